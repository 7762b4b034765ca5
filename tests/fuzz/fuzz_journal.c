/* libFuzzer target for the journals behind `sweep --resume` and `montecarlo --resume`
 * (src/journal.c): a journal file of any bytes read by vs_journal_read, then reopened by
 * vs_journal_open and appended to, as a resumed study does. Run it with tests/fuzz/run.sh
 * [SECONDS] journal.
 *
 * The input's first byte chooses the rows' size (a sweep's row, a Monte Carlo sample, or 1 to
 * 32 bytes, so that a short input holds many rows) and whether the file starts with the
 * journal's header line; the other bytes are the rest of the file. What the journal holds is
 * framing: a header naming the layout, then whole rows, the last one perhaps torn by a kill.
 * The rows' fields are the studies' to check (sweep.c, montecarlo_cmd.c), not this target's.
 * Checks besides crashes and sanitizer reports:
 *  - vs_journal_read refuses (-1) exactly a file that does not begin as the header does (a
 *    header cut short by a kill is an empty journal);
 *  - it passes exactly the whole rows after the header, in file order, byte for byte, and
 *    counts them: a torn last row is not passed; it changes nothing in the file;
 *  - vs_journal_open then vs_journal_append leave the header, the rows read and the new row,
 *    nothing else: the torn tail is cut, and a journal with no whole row is started afresh. */
#define _POSIX_C_SOURCE 200809L
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define FUZZ_NAME "fuzz_journal"
#include "fuzz.h"

#include "journal.h"
#include "sweep_private.h"
#include "voussoir/montecarlo.h"

static char g_root[4096], g_path[4200];

static void remove_root(void) {
  unlink(g_path);
  rmdir(g_root);
}

int LLVMFuzzerInitialize(int *argc, char ***argv) {
  (void)argc, (void)argv;
  fuzz_report_open();
  fuzz_scratch(g_root, sizeof g_root);
  snprintf(g_path, sizeof g_path, "%s/study.journal", g_root);
  atexit(remove_root);
  return 0;
}

/* The rows vs_journal_read passes, compared with the file's bytes as they come. */
typedef struct {
  const uint8_t *file; /* the journal's bytes */
  size_t at, size;     /* where the next row starts; the rows' size */
  long taken;
} reader;

static void take(void *user, const void *row) {
  reader *r = user;
  CHECK(memcmp(row, r->file + r->at, r->size) == 0);
  r->at += r->size;
  r->taken++;
}

static uint8_t *slurp(size_t *n) {
  uint8_t *b = (uint8_t *)fuzz_slurp(g_path, n);
  CHECK(b != NULL);
  return b;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  if (size == 0) return 0;
  const unsigned kind = data[0] & 3u, headless = data[0] & 4u;
  const size_t row_size = kind == 0   ? sizeof(vs_sweep_row)
                          : kind == 1 ? sizeof(vs_mc_sample)
                                      : 1 + (size_t)(data[0] >> 3) % 32;
  char head[96];
  snprintf(head, sizeof head, "voussoir fuzz journal 1 row %zu bytes\n", row_size);
  const size_t hl = strlen(head);

  /* the file: the header (unless headless), then the input's other bytes */
  const size_t n = (headless ? 0 : hl) + size - 1;
  uint8_t *file = malloc(n > 0 ? n : 1);
  CHECK(file != NULL);
  if (!headless) memcpy(file, head, hl);
  memcpy(file + (headless ? 0 : hl), data + 1, size - 1);
  FILE *f = fopen(g_path, "wb");
  CHECK(f != NULL && (n == 0 || fwrite(file, 1, n, f) == n) && fclose(f) == 0);

  reader r = {file, hl, row_size, 0};
  long rows = -1;
  const int rc = vs_journal_read(g_path, head, row_size, take, &r, &rows);
  const size_t got = n < hl ? n : hl;
  const int foreign = memcmp(file, head, got) != 0;
  CHECK(rc == (foreign ? -1 : 0));
  const long whole = !foreign && n >= hl ? (long)((n - hl) / row_size) : 0;
  CHECK(rows == r.taken && rows == whole);
  size_t m;
  uint8_t *after = slurp(&m);
  CHECK(m == n && memcmp(after, file, n) == 0); /* reading changed nothing */
  free(after);

  if (rc == 0) { /* resumed: appended to after the rows read */
    uint8_t *row = malloc(row_size);
    CHECK(row != NULL);
    for (size_t i = 0; i < row_size; i++) row[i] = (uint8_t)(0xa5 ^ i);
    FILE *j = vs_journal_open(g_path, head, row_size, rows);
    CHECK(j != NULL && vs_journal_append(j, row, row_size) == 0 && fclose(j) == 0);
    const size_t keep = hl + (size_t)rows * row_size; /* rows 0: a fresh header */
    after = slurp(&m);
    const uint8_t *kept = rows > 0 ? file : (const uint8_t *)head;
    CHECK(m == keep + row_size && memcmp(after, kept, keep) == 0 &&
          memcmp(after + keep, row, row_size) == 0);
    free(after);
    free(row);
  }
  free(file);
  return 0;
}
