/* A study's manifest, journal and lock (sweep, montecarlo). The manifest says what the study is
 * (its case and its own settings), so that --resume continues only the same study. The journal:
 * a header line naming what it holds and the layout of its rows (their size), then whole rows of
 * that size, each appended and flushed as a run ends, so that a study killed at any moment can
 * be resumed from it (--resume). Each row is the row's bytes followed by their checksum, so that
 * a damaged row is told from a sound one, and a reader checks every field of a row before it
 * counts the row's run as done: a row that fails is not done (the run runs again). A kill may
 * cut the last row short; a reader ignores it, and a resumed study truncates it away before
 * appending, so that the rows after it stay aligned. The lock keeps a second study out of the
 * directory while one (or any worker it forked) is at work there. In the program
 * (src/study/journal.c). */
#ifndef VS_JOURNAL_H
#define VS_JOURNAL_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "sweep_private.h"
#include "voussoir/case.h"
#include "voussoir/montecarlo.h"
#include "outpath.h"

/* The case's every key as "section.key=value" lines (%.17g): the part of a manifest that says
 * which case the study runs, with extra bytes to spare at the end for the study's own lines.
 * malloc'd; NULL when out of memory. */
char *vs_manifest_case(const vs_case *c, size_t extra);

/* Whether the manifest at path holds text: 1 the same, 0 another, -1 none (missing or
 * unreadable). */
int vs_manifest_same(const char *path, const char *text);

/* The bytes of a row's checksum, stored after the row: FNV-1a 64 of the row's bytes, little
 * endian. A journal row of a size-byte row takes size + VS_JOURNAL_SUM bytes in the file (the
 * header names that size). */
enum { VS_JOURNAL_SUM = 8 };

/* FNV-1a 64 of n bytes at p. */
uint64_t vs_journal_sum(const void *p, size_t n);

/* What vs_journal_read returns besides 0. */
enum { VS_JOURNAL_FOREIGN = -1, VS_JOURNAL_IO = -2 };

/* A reader's verdict on a row whose checksum holds (size bytes at row, aligned for any type):
 * 1 taken (its run is done), or 0 refused with the reason in why (a field out of its range,
 * e.g. "status is not NUL-terminated in its 32 bytes"). */
typedef int (*vs_journal_take_fn)(void *user, const void *row, char *why, size_t why_size);

/* Read the journal at path for a --resume: its rows of size bytes (each followed by its
 * checksum) after the header line head. Each row whose checksum holds goes to take(); every row
 * refused, by its checksum or by take, is reported on stderr once ("WHO: --resume: PATH: row K:
 * WHY: not counted as done, so it runs again") and removed from the journal: the rows taken are
 * moved up over it in place (each stays whole somewhere in the file at every moment, so that a
 * kill meanwhile loses none). *rows receives the rows taken, which now lead the journal
 * (vs_journal_open appends after them). A missing journal, or one whose header a kill cut
 * short: 0 rows. 0; VS_JOURNAL_FOREIGN when the journal's first line is not head (another
 * build's or another kind's journal; nothing changed); VS_JOURNAL_IO (errno set) when it cannot
 * be read or rewritten. */
int vs_journal_read(const char *path, const char *head, size_t size, const char *who,
                    vs_journal_take_fn take, void *user, long *rows);

/* Open the journal at path to append rows of size bytes: rows <= 0, a fresh one (created anew,
 * head written: vs_outpath_create); otherwise the one read with that many rows taken, cut after
 * them (opened without following a link, and only if it is a regular file). NULL on failure,
 * with the reason in err ("PATH: ..."). */
FILE *vs_journal_open(const char *path, const char *head, size_t size, long rows,
                      vs_error *err);

/* Append one row of size bytes and its checksum, flushed. 0, or -1 (errno set). */
int vs_journal_append(FILE *f, const void *row, size_t size);

/* Field by field, whether a sweep's journal row can be a finished run of a sweep of total runs
 * on nax axes (the checksum is vs_journal_read's): run in 1..total; code VS_SWEEP_OK or
 * VS_SWEEP_FAILED (nothing else is journalled); every text NUL-terminated in its array; status
 * one of a finished run's words and "failed" exactly when the code says so; mode "", I, II or
 * III; hinges made of labels, joint numbers, sides, ':', '-' and spaces; no error for a run that
 * worked; the axes' values finite (the unused ones 0); the displacements >= 0 or NaN (none), the
 * components NaN exactly when the collapse displacement is; wall_s >= 0 or NaN; snaps in
 * 0..VS_RUN_MAX_LIMITS. 1 sound; 0 with the first fault in why. No I/O: a fuzzer may call it
 * with any bytes copied into a row. */
int vs_sweep_row_check(const vs_sweep_row *row, int total, int nax, char *why, size_t why_size);

/* The same for a montecarlo journal's row of the study of samples 0..samples-1 whose shard
 * K/M runs (the samples i with i mod M = K - 1), on an arch of `joints` joints: sample one of
 * the shard's; status VS_MC_*; pattern NUL-terminated and made of I, E and '-'; error
 * NUL-terminated, empty unless the sample failed; first_limit_mm >= 0 or NaN; a collapse's
 * delta_u_mm >= 0 and its components finite, NaN for any other status; mode 0..3; each hinge's
 * joint 0 (none) or 1..joints, with a side 'I' or 'E' exactly when it has a joint; no mode,
 * hinge or pattern without a collapse. 1 sound; 0 with the first fault in why. No I/O. */
int vs_mc_sample_check(const vs_mc_sample *r, int samples, int shard_k, int shard_m, int joints,
                       char *why, size_t why_size);

/* The lock of a study's directory, DIR/study.lock (vs_outlock on DIR/study), one for every
 * study command, so that two studies (sweep or montecarlo) never share a directory. Taken
 * before anything in DIR is written and held until the study's end; its workers, forked from
 * the study, share it (flock: the lock goes with the open file), so that it is free only once
 * the study and every worker it started have ended. */
#define VS_STUDY_LOCK "study"

/* Most seconds a study waits for the workers of a study that was killed (its pid, in the lock
 * file, no longer runs) to let go of the directory's lock: they end with it (parent-death
 * signal), within milliseconds. */
enum { VS_STUDY_LOCK_WAIT_S = 30 };

/* Take the lock of directory dir (which must exist) for the study command who ("voussoir
 * sweep"). Held by a running process: refused at once, err says "-o DIR: another study is under
 * way in this directory (pid N, lock DIR/study.lock)". Held with its pid no longer running: the
 * killed study's workers have not ended yet; waits for them (saying so on stderr once) up to
 * VS_STUDY_LOCK_WAIT_S. Errors as vs_outlock_acquire's (VS_ERR_INVALID: held, or the lock file
 * is not a regular file). */
vs_status vs_study_lock(const char *dir, const char *who, vs_outlock **out, vs_error *err);

#endif
