/* The blocks command: a case's arch written as a blocks file (geometry.h:
 * vs_geometry_blocks_json), for a user to start from a shape and edit it. */
#define _GNU_SOURCE /* getopt_long */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "outpath.h"
#include "voussoir/run.h"

static const char *const BLOCKS_USAGE =
    "usage: voussoir blocks CASE [--set SECTION.KEY=VALUE]... [-o FILE]\n"
    "Writes the case's arch (any shape, its imperfections drawn) as a blocks file, JSON\n"
    "(docs/blocks-file.md): each voussoir a polygon in mm, a pier under each springing face (the\n"
    "supports), the ring from the left pier to the right one (with [piers], the piers' courses\n"
    "as blocks on their foundations, the ring through them). Edit it, and run it with\n"
    "arch.shape = file and arch.blocks_file = FILE.\n"
    "  --set SECTION.KEY=VALUE  override a case key (repeatable, applied in order)\n"
    "  -o FILE                  the file to write (default: standard output); created anew, never\n"
    "                           written through a link, not the case or its blocks file\n"
    "exit status: 0 written, 1 the file could not be written, 2 bad input (the case, an arch\n"
    "that cannot be built, an output that is not a regular file)\n";

enum { OPT_SET = 256 };

static const struct option BLOCKS_OPTIONS[] = {{"set", required_argument, NULL, OPT_SET},
                                               {0, 0, 0, 0}};
static const cli_command BLOCKS = {"voussoir blocks", BLOCKS_USAGE, "o:", BLOCKS_OPTIONS};

typedef struct {
  const char *case_path, *out;
  const char *sets[VS_CLI_MAX_SETS];
  int nsets;
} blocks_args;

static int blocks_option(void *user, int code, const char *value) {
  blocks_args *a = user;
  if (code == 'o') a->out = value;
  else if (code == OPT_SET) return cli_add_set(BLOCKS.name, value, a->sets, &a->nsets);
  else if (a->case_path == NULL) a->case_path = value; /* 1: the case */
  else {
    fprintf(stderr, "voussoir blocks: unexpected argument %s\n%s", vs_q(value).s, BLOCKS_USAGE);
    return VS_EXIT_BAD_INPUT;
  }
  return 0;
}

/* The text into path, through path.part renamed into place; 0 or an exit status. */
static int write_file(const char *path, const char *text) {
  char part[VS_ARCH_PATH_MAX + 8];
  vs_error err;
  vs_error_clear(&err);
  snprintf(part, sizeof part, "%s.part", path);
  FILE *f = NULL;
  vs_status st = vs_outpath_fopen(part, &f, &err);
  if (st == VS_OK) {
    const int bad = fputs(text, f) < 0 || fputc('\n', f) == EOF;
    if ((fclose(f) != 0 || bad))
      st = vs_error_set(&err, VS_ERR_IO, "%s: cannot write: %s", part, strerror(errno));
  }
  if (st == VS_OK) st = vs_outpath_publish(part, path, &err);
  if (st == VS_OK) return VS_EXIT_OK;
  vs_outpath_discard(part);
  fprintf(stderr, "voussoir blocks: %s\n", err.msg);
  return st == VS_ERR_INVALID ? VS_EXIT_BAD_INPUT : VS_EXIT_FAILED;
}

int vs_cli_blocks(int argc, char **argv) {
  blocks_args a = {0};
  int rc = cli_parse(&BLOCKS, argc, argv, blocks_option, &a);
  if (rc != 0) return rc < 0 ? VS_EXIT_OK : rc;
  if (a.case_path == NULL) {
    fprintf(stderr, "voussoir blocks: needs a CASE file\n%s", BLOCKS_USAGE);
    return VS_EXIT_BAD_INPUT;
  }
  vs_case c;
  vs_error err;
  vs_error_clear(&err);
  vs_case_defaults(&c);
  vs_status st = vs_case_read(&c, a.case_path, NULL, &err);
  for (int i = 0; st == VS_OK && i < a.nsets; i++) st = vs_case_set(&c, a.sets[i], &err);
  if (st == VS_OK) st = vs_case_validate(&c, &err);
  const vs_outpath_other others[2] = {{a.case_path, "the case file"},
                                      {c.blocks_file, "the case's blocks file"}};
  if (st == VS_OK && a.out != NULL)
    st = vs_outpath_check(a.out, others, c.blocks_file[0] != '\0' ? 2 : 1, &err);
  vs_run *run = NULL;
  char *text = NULL;
  if (st == VS_OK) st = vs_run_create(&c, &run, &err);
  if (st == VS_OK) st = vs_geometry_blocks_json(vs_run_geometry(run), &text, &err);
  vs_run_destroy(&run);
  if (st != VS_OK) {
    fprintf(stderr, "voussoir blocks: %s\n", err.msg);
    return st == VS_ERR_NOMEM ? VS_EXIT_FAILED : VS_EXIT_BAD_INPUT;
  }
  vs_outlock *lock = NULL;
  if (a.out == NULL) {
    rc = puts(text) < 0 || fflush(stdout) != 0 ? VS_EXIT_FAILED : VS_EXIT_OK;
  } else if (vs_outlock_acquire(a.out, &lock, &err) != VS_OK) {
    fprintf(stderr, "voussoir blocks: %s\n", err.msg);
    rc = VS_EXIT_BAD_INPUT;
  } else {
    rc = write_file(a.out, text);
  }
  vs_outlock_release(&lock);
  free(text);
  return rc;
}
