/* libFuzzer target for the blocks file reader (arch.shape = file; src/model/blocks.c), run by
 * tests/fuzz/run.sh. Besides crashes and sanitizer reports it checks meaning:
 *  - text that is refused says why (a message, a status);
 *  - text that is accepted gives a geometry of finite, positive blocks (area, mass, inertia),
 *    joints of unit normal and positive length between two different bodies, the ring's
 *    joints first, from the left support to the right one;
 *  - that geometry written back as a blocks file is read again with the same blocks (areas to
 *    1e-9) and the same ring, or refused with a message. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define FUZZ_NAME "fuzz_blocks"
#include "fuzz.h"

#include "blocks.h"

static void check_geometry(const vs_geometry *g) {
  CHECK(g->n_blocks >= 1 && g->n_joints >= 1);
  CHECK(g->ring >= 2 && g->ring <= g->n_joints);
  CHECK(g->joints[0].a == VS_SUPPORT_LEFT && g->joints[g->ring - 1].b == VS_SUPPORT_RIGHT);
  for (int i = 0; i < g->n_blocks; i++) {
    const vs_block *b = &g->blocks[i];
    CHECK(isfinite(b->area) && b->area > 0.0 && isfinite(b->mass) && b->mass > 0.0);
    CHECK(isfinite(b->inertia) && b->inertia > 0.0 && isfinite(b->cx) && isfinite(b->cz));
    CHECK(b->n_edges >= 3);
  }
  for (int k = 0; k < g->n_joints; k++) {
    const vs_joint_geom *j = &g->joints[k];
    CHECK(j->a != j->b && j->a >= VS_SUPPORT_RIGHT && j->a < g->n_blocks);
    CHECK(j->b >= VS_SUPPORT_RIGHT && j->b < g->n_blocks);
    CHECK(isfinite(j->length) && j->length > 0.0);
    CHECK(fabs(hypot(j->nx, j->nz) - 1.0) < 1e-12);
  }
}

int LLVMFuzzerInitialize(int *argc, char ***argv) {
  (void)argc, (void)argv;
  fuzz_report_open();
  return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  vs_run_def d;
  vs_run_def_default(&d);
  vs_geometry *g = NULL, *h = NULL;
  vs_error err;
  vs_error_clear(&err);
  if (vs_blocks_parse("fuzz.json", (const char *)data, size, &d.arch, &g, &err) != VS_OK) {
    CHECK(g == NULL && err.status != VS_OK && err.msg[0] != '\0');
    return 0;
  }
  check_geometry(g);
  char *text = NULL;
  if (vs_geometry_blocks_json(g, &text, &err) == VS_OK) {
    if (vs_blocks_parse("again.json", text, strlen(text), &d.arch, &h, &err) == VS_OK) {
      CHECK(h->n_blocks == g->n_blocks && h->ring == g->ring);
      for (int i = 0; i < g->n_blocks; i++)
        CHECK(fabs(h->blocks[i].area - g->blocks[i].area) <= 1e-9 * g->blocks[i].area);
    } else {
      CHECK(h == NULL && err.msg[0] != '\0');
    }
  } else {
    CHECK(text == NULL && err.msg[0] != '\0');
  }
  free(text);
  vs_geometry_destroy(&h);
  vs_geometry_destroy(&g);
  return 0;
}
