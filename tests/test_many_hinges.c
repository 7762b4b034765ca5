/* Many hinges, none dropped: a long deformable arch can open far more hinges than a handful.
 * The reference arch with 160 voussoirs, its joints 2, 4, .., 140 open one in two on alternating
 * sides (a constructed state of the run's hinge tracker): 70 separate hinges form at once. Taken
 * as the mechanism of a collapse, every one of them is in the collapse record (left to right),
 * among the run's hinges, in the side pattern, the JSON report, the record's tables and the
 * pictures' labels; a list of their names too long for its field ends with "+K more", the K it
 * leaves out; a side pattern too long for its field ends with '-'. */
#define _POSIX_C_SOURCE 200809L /* mkdtemp, open_memstream */

#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <hdf5.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "plot_cmd.h"     /* the pictures' labels (vs_plotrec_hinges_at) */
#include "run_internal.h" /* the run's tracker, and its collapse from it */
#include "voussoir/output.h"
#include "voussoir/report.h"
#include "voussoir/run.h"

enum { NB = 160, NJ = NB + 1, NH = 70 };

/* Hinge i (0-based, left to right) of the constructed state: joint 2 (i + 1), intrados side for
 * even i (its extrados opened), extrados for odd i. */
static int joint_of(int i) { return 2 * (i + 1); }
static char side_of(int i) { return i % 2 == 0 ? 'I' : 'E'; }

typedef struct {
  vs_run *r;
  char pattern[2 * NH]; /* the sides, "I-E-I-...", written here */
} fixture;

static int setup(void **ts) {
  fixture *f = calloc(1, sizeof *f);
  vs_case c;
  vs_case_defaults(&c);
  c.voussoirs = NB;
  vs_error err;
  vs_error_clear(&err);
  if (f == NULL || vs_run_create(&c, &f->r, &err) != VS_OK) return -1;
  vs_joint_state st[NJ];
  memset(st, 0, sizeof st);
  for (int k = 0; k < NJ; k++) st[k].gap_i = st[k].gap_e = -1e-6; /* closed */
  for (int i = 0; i < NH; i++) {
    vs_joint_state *s = &st[joint_of(i) - 1];
    *(side_of(i) == 'I' ? &s->gap_e : &s->gap_i) = 4.0 * c.open_mm * 1e-3; /* the other edge */
    f->pattern[2 * i] = side_of(i);
    f->pattern[2 * i + 1] = i + 1 < NH ? '-' : '\0';
  }
  if (vs_hinges_update(f->r->h, 1e-3, st) != NH) return -1;
  /* the motion that follows collapses: its mechanism is the tracker's hinges now */
  vs_dyn_result d;
  memset(&d, 0, sizeof d);
  d.t_collapse = 1e-3 / (c.rate_mm_s * 1e-3);
  if (vs_run_record_collapse(f->r, &d) != 0) return -1;
  vs_run_classify(f->r);
  *ts = f;
  return 0;
}

static int teardown(void **ts) {
  fixture *f = *ts;
  vs_run_destroy(&f->r);
  free(f);
  return 0;
}

static void test_collapse_record_and_run(void **ts) {
  fixture *f = *ts;
  const vs_collapse_record *col = vs_run_collapse(f->r);
  assert_true(col->found);
  assert_int_equal(col->n_hinges, NH);
  assert_int_equal(vs_run_hinge_count(f->r), NH);
  for (int i = 0; i < NH; i++) {
    const vs_hinge *c = &col->hinges[i], *h = vs_run_hinge(f->r, i);
    if (c->first != joint_of(i) || c->last != joint_of(i) || c->side != side_of(i) || !c->open)
      fail_msg("collapse hinge %d: joints %d-%d side %c, expected %d-%c", i, c->first, c->last,
               c->side, joint_of(i), side_of(i));
    if (h->first != joint_of(i) || h->side != side_of(i))
      fail_msg("run hinge %d: joint %d side %c, expected %d-%c", i, h->first, h->side,
               joint_of(i), side_of(i));
  }
  /* the first three are A, B, C from the left */
  assert_true(col->hinges[0].label == 'A' && col->hinges[1].label == 'B' &&
              col->hinges[2].label == 'C');
  assert_string_equal(vs_run_pattern_collapse(f->r), f->pattern);
}

/* Occurrences of needle in text. */
static int count(const char *text, const char *needle) {
  int n = 0;
  for (const char *p = strstr(text, needle); p != NULL; p = strstr(p + 1, needle)) n++;
  return n;
}

static void test_json(void **ts) {
  fixture *f = *ts;
  char *buf = NULL;
  size_t size = 0;
  FILE *out = open_memstream(&buf, &size);
  assert_non_null(out);
  vs_report_json(out, f->r, VS_OK, NULL, "many.ini");
  assert_int_equal(fclose(out), 0);
  /* the run's hinges (with their onset joints), then the collapse's (without) */
  assert_int_equal(count(buf, "\"joints_onset\""), NH);
  assert_int_equal(count(buf, "\"label\""), 2 * NH);
  char last[64];
  snprintf(last, sizeof last, "\"joints\":[%d]", joint_of(NH - 1));
  assert_int_equal(count(buf, last), 2);
  assert_non_null(strstr(buf, "\"hinges_in_fall\":0"));
  char want[2 * NH + 40];
  snprintf(want, sizeof want, "\"hinge_sides_collapse\":\"%s\"", f->pattern);
  assert_non_null(strstr(buf, want));
  free(buf);
}

/* A list of the hinges' names in size bytes (vs_hinges_list): the first ones in order, "A:2-I
 * B:4-E ...", then "+K more" with K the ones left out; all of them when cut is 0. */
static void expect_list(const vs_run *r, const char *list, size_t size, int cut) {
  if (strlen(list) >= size) fail_msg("\"%s\": longer than its %zu bytes", list, size);
  const char *p = list;
  int listed = 0;
  while (*p != '\0' && strncmp(p, listed ? " +" : "+", listed ? 2 : 1) != 0) {
    char want[32];
    const int n = snprintf(want, sizeof want, "%s%c:%d-%c", listed ? " " : "",
                           vs_run_hinge(r, listed)->label, joint_of(listed), side_of(listed));
    if (listed == NH || strncmp(p, want, (size_t)n) != 0)
      fail_msg("\"%s\": entry %d is not \"%s\"", list, listed + 1, want);
    p += n;
    listed++;
  }
  int more = 0;
  char junk[8] = "";
  if (*p != '\0' && sscanf(p, " +%d more%7s", &more, junk) != 1)
    fail_msg("\"%s\": its end \"%s\" is not \"+K more\"", list, p);
  if (listed + more != NH || (more > 0) != cut)
    fail_msg("\"%s\": %d listed and %d more, expected %d in all%s", list, listed, more, NH,
             cut ? ", some left out" : "");
}

static void test_lists_say_what_they_leave_out(void **ts) {
  fixture *f = *ts;
  char small[160], row[512], big[4096], tiny[9];
  vs_run_open_hinges(f->r, small, sizeof small);
  expect_list(f->r, small, sizeof small, 1);
  vs_run_open_hinges(f->r, big, sizeof big);
  expect_list(f->r, big, sizeof big, 0);
  vs_run_open_hinges(f->r, tiny, sizeof tiny);
  assert_string_equal(tiny, "+70 more");
  /* a limit point's hinges (its 160 bytes); a sweep's row of the collapse's (512: they fit) */
  assert_int_equal(vs_run_add_limit(f->r, 2e-3), 0);
  expect_list(f->r, vs_run_limit(f->r, 0)->hinges_before, sizeof small, 1);
  const vs_collapse_record *col = vs_run_collapse(f->r);
  vs_hinges_list(col->hinges, col->n_hinges, 0, row, sizeof row);
  expect_list(f->r, row, sizeof row, 0);
  vs_hinges_list(col->hinges, col->n_hinges, 0, row, 300);
  expect_list(f->r, row, 300, 1);
  /* the sides in a field of 16 bytes (a Monte Carlo sample's): cut after a '-' */
  char sides[16];
  vs_hinges_side_pattern(col->hinges, col->n_hinges, sides, sizeof sides);
  assert_string_equal(sides, "I-E-I-E-I-E-I-");
}

/* Rows of the table at path of the record file f. */
static long rows_of(hid_t f, const char *path) {
  hid_t d = H5Dopen2(f, path, H5P_DEFAULT);
  if (d < 0) fail_msg("%s: no such table", path);
  hid_t sp = H5Dget_space(d);
  hsize_t n = 0;
  H5Sget_simple_extent_dims(sp, &n, NULL);
  H5Sclose(sp);
  H5Dclose(d);
  return (long)n;
}

static void test_record(void **ts) {
  fixture *f = *ts;
  char dir[] = "/tmp/vs_many_XXXXXX", path[64], xmf[64];
  assert_non_null(mkdtemp(dir));
  snprintf(path, sizeof path, "%s/many.h5", dir);
  snprintf(xmf, sizeof xmf, "%s/many.xmf", dir);
  vs_output_opts oo;
  vs_output_opts_default(&oo);
  vs_output *o = NULL;
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(vs_output_create(path, f->r, NULL, &oo, &o, &err), VS_OK);
  if (vs_output_finish(o, f->r, VS_OK, NULL, &err) != VS_OK) fail_msg("%s", err.msg);
  vs_output_destroy(&o);
  hid_t h5 = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(h5 >= 0);
  assert_int_equal(rows_of(h5, "/summary/collapse/hinges"), NH);
  assert_int_equal(rows_of(h5, "/summary/hinges"), NH);
  H5Fclose(h5);
  assert_int_equal(unlink(path), 0);
  unlink(xmf);
  assert_int_equal(rmdir(dir), 0);
}

/* The pictures of `voussoir plot`: a state whose open joints are the NH groups, each paired with
 * the recorded hinge at its joints, and the picture of the collapse: every hinge labelled. */
static void test_picture_labels(void **ts) {
  (void)ts;
  rec_hinge h[NH];
  signed char row[NJ];
  memset(row, 0, sizeof row);
  for (int i = 0; i < NH; i++) {
    const int j = joint_of(i);
    h[i] = (rec_hinge){.label = vs_hinges_label(i), .side = side_of(i), .first = j, .last = j,
                       .onset_first = j, .onset_last = j, .order = i + 1, .open = 1};
    row[j - 1] = side_of(i) == 'I' ? 1 : 2;
  }
  vs_plotrec r = {.nj = NJ, .nh = NH, .h = h, .hinge = row, .rows = 1};
  vs_hinge out[NH];
  const pic_kind kinds[2] = {PIC_ROW, PIC_COLLAPSE};
  for (int k = 0; k < 2; k++) {
    const int n = vs_plotrec_hinges_at(&r, 0, 1.0, kinds[k], -1, out);
    if (n != NH) fail_msg("picture %d: %d hinges labelled, expected %d", k, n, NH);
    for (int i = 0; i < NH; i++) { /* each at its own joint (rows: left to right) */
      int found = 0;
      for (int m = 0; m < n; m++)
        found |= out[m].label == h[i].label && out[m].first == joint_of(i);
      if (!found) fail_msg("picture %d: hinge %c at joint %d not labelled", k, h[i].label, joint_of(i));
    }
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test_setup_teardown(test_collapse_record_and_run, setup, teardown),
      cmocka_unit_test_setup_teardown(test_json, setup, teardown),
      cmocka_unit_test_setup_teardown(test_lists_say_what_they_leave_out, setup, teardown),
      cmocka_unit_test_setup_teardown(test_record, setup, teardown),
      cmocka_unit_test(test_picture_labels),
  };
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  return cmocka_run_group_tests(tests, NULL, NULL);
}
