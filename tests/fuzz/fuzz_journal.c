/* libFuzzer target for the journals behind `sweep --resume` and `montecarlo --resume`
 * (src/study/journal.c): a journal file of any bytes read by vs_journal_read, then reopened by
 * vs_journal_open and appended to, as a resumed study does. Run it with tests/fuzz/run.sh
 * [SECONDS] journal.
 *
 * The input's first byte chooses the rows' size (a sweep's row, a Monte Carlo sample, or 1 to
 * 32 bytes, so that a short input holds many rows), whether the file starts with the journal's
 * header line, and (small rows) which rows the reader refuses; the other bytes are the rest of
 * the file, where a stored row is the row's bytes followed by their FNV-1a 64 checksum (8 bytes,
 * little endian). A sweep's rows and Monte Carlo samples go through the studies' own checks of
 * every field (vs_sweep_row_check, vs_mc_sample_check), fed any bytes. Checks besides crashes and
 * sanitizer reports:
 *  - vs_journal_read refuses (VS_JOURNAL_FOREIGN) exactly a file that does not begin as the
 *    header does (a header cut short by a kill is an empty journal), and then changes nothing;
 *  - it passes to the reader exactly the whole stored rows whose checksum holds (computed here
 *    again), in file order, byte for byte; a torn last row is not passed;
 *  - the rows the reader took now lead the journal, each with its checksum, in their order;
 *  - vs_journal_open then vs_journal_append leave the header, those rows and the new row (with
 *    its checksum), nothing else. */
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
#include "sweep_rows.h"
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

/* FNV-1a 64 of n bytes, written here again, little endian into out[8]. */
static void sum8(const uint8_t *p, size_t n, uint8_t out[8]) {
  uint64_t h = 0xcbf29ce484222325u;
  for (size_t i = 0; i < n; i++) h = (h ^ p[i]) * 0x100000001b3u;
  for (int i = 0; i < 8; i++) out[i] = (uint8_t)(h >> (8 * i));
}

/* The reader: each row it is given must be the next stored row whose checksum holds; it takes
 * or refuses it (kind 0, 1: the study's checks; else every row whose first byte has the bit
 * `refuse` set is refused), and keeps what it took, in order. */
typedef struct {
  const uint8_t *file;
  size_t at, end, size; /* the next stored row's offset; the whole rows' end; the rows' size */
  unsigned kind, refuse;
  uint8_t *kept; /* the rows taken, each with its checksum */
  long taken;
} reader;

/* The next stored row from r->at whose checksum holds (r->at moves to it), or NULL. */
static const uint8_t *next_sound(reader *r) {
  uint8_t sum[8];
  for (; r->at + r->size + 8 <= r->end; r->at += r->size + 8) {
    sum8(r->file + r->at, r->size, sum);
    if (memcmp(sum, r->file + r->at + r->size, 8) == 0) return r->file + r->at;
  }
  return NULL;
}

static int take(void *user, const void *row, char *why, size_t why_size) {
  reader *r = user;
  const uint8_t *want = next_sound(r);
  CHECK(want != NULL && memcmp(row, want, r->size) == 0);
  int ok;
  if (r->kind == 0) ok = vs_sweep_row_check(row, 12, 2, why, why_size);
  else if (r->kind == 1) ok = vs_mc_sample_check(row, 40, 0, 1, 56, why, why_size);
  else ok = (((const uint8_t *)row)[0] & r->refuse) == 0;
  if (!ok && r->kind > 1) snprintf(why, why_size, "refused by the fuzz target");
  CHECK(ok || why[0] != '\0'); /* a refusal says why */
  if (ok) memcpy(r->kept + (size_t)r->taken++ * (r->size + 8), want, r->size + 8);
  r->at += r->size + 8;
  return ok;
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
  snprintf(head, sizeof head, "voussoir fuzz journal 2 row %zu bytes\n", row_size + 8);
  const size_t hl = strlen(head);

  /* the file: the header (unless headless), then the input's other bytes */
  const size_t n = (headless ? 0 : hl) + size - 1;
  uint8_t *file = malloc(n > 0 ? n : 1);
  CHECK(file != NULL);
  if (!headless) memcpy(file, head, hl);
  memcpy(file + (headless ? 0 : hl), data + 1, size - 1);
  FILE *f = fopen(g_path, "wb");
  CHECK(f != NULL && (n == 0 || fwrite(file, 1, n, f) == n) && fclose(f) == 0);

  const size_t stored = row_size + 8;
  const size_t whole = n >= hl ? hl + (n - hl) / stored * stored : hl;
  reader r = {file, hl, whole, row_size, kind, 1u << (data[0] >> 5 & 7u), NULL, 0};
  r.kept = malloc((n / stored + 1) * stored);
  CHECK(r.kept != NULL);
  long rows = -1;
  const int rc = vs_journal_read(g_path, head, row_size, "fuzz", take, &r, &rows);
  const size_t got = n < hl ? n : hl;
  const int foreign = memcmp(file, head, got) != 0;
  size_t m;
  uint8_t *after = slurp(&m);
  if (foreign) {
    CHECK(rc == VS_JOURNAL_FOREIGN);
    CHECK(m == n && memcmp(after, file, n) == 0); /* nothing changed */
  } else {
    CHECK(rc == 0 && rows == r.taken);
    CHECK(next_sound(&r) == NULL); /* every sound row was passed */
    const size_t keep = (size_t)rows * stored;
    if (n >= hl) CHECK(m >= hl + keep && memcmp(after, head, hl) == 0 &&
                       memcmp(after + hl, r.kept, keep) == 0);
  }
  free(after);

  if (rc == 0) { /* resumed: appended to after the rows taken */
    uint8_t *row = malloc(row_size), sum[8];
    CHECK(row != NULL);
    for (size_t i = 0; i < row_size; i++) row[i] = (uint8_t)(0xa5 ^ i);
    sum8(row, row_size, sum);
    vs_error err;
    FILE *j = vs_journal_open(g_path, head, row_size, rows, &err);
    CHECK(j != NULL && vs_journal_append(j, row, row_size) == 0 && fclose(j) == 0);
    const size_t keep = hl + (size_t)rows * stored; /* rows 0: a fresh header */
    after = slurp(&m);
    CHECK(m == keep + stored && memcmp(after, head, hl) == 0 &&
          memcmp(after + hl, r.kept, keep - hl) == 0 && memcmp(after + keep, row, row_size) == 0 &&
          memcmp(after + keep + row_size, sum, 8) == 0);
    free(after);
    free(row);
  }
  free(r.kept);
  free(file);
  return 0;
}
