/* A study's manifest and journal (sweep, montecarlo). The manifest says what the study is (its
 * case and its own settings), so that --resume continues only the same study. The journal: a
 * header line naming what it holds and the layout of its rows (their size), then whole rows of
 * that size, each appended and flushed as a run ends, so that a study killed at any moment can
 * be resumed from it (--resume). A kill may cut the last row short; a reader ignores it, and a
 * resumed study truncates it away before appending, so that the rows after it stay aligned. In
 * the program (src/study/journal.c). */
#ifndef VS_JOURNAL_H
#define VS_JOURNAL_H

#include <stddef.h>
#include <stdio.h>

#include "voussoir/case.h"

/* The case's every key as "section.key=value" lines (%.17g): the part of a manifest that says
 * which case the study runs, with extra bytes to spare at the end for the study's own lines.
 * malloc'd; NULL when out of memory. */
char *vs_manifest_case(const vs_case *c, size_t extra);

/* Whether the manifest at path holds text: 1 the same, 0 another, -1 none (missing or
 * unreadable). */
int vs_manifest_same(const char *path, const char *text);

/* The rows of the journal at path, each passed to take(user, row) in file order; *rows receives
 * their count (a missing journal, or one whose header a kill cut short: 0 rows). 0, or -1 when
 * the journal's first line is not head (another build's or another kind's journal). */
int vs_journal_read(const char *path, const char *head, size_t size,
                    void (*take)(void *user, const void *row), void *user, long *rows);

/* Open the journal at path to append rows: rows <= 0, a fresh one (created anew, head written:
 * vs_outpath_create); otherwise the one read with that many whole rows, cut after them (opened
 * without following a link, and only if it is a regular file). NULL on failure, with the reason
 * in err ("PATH: ..."). */
FILE *vs_journal_open(const char *path, const char *head, size_t size, long rows,
                      vs_error *err);

/* Append one row, flushed. 0, or -1 (errno set). */
int vs_journal_append(FILE *f, const void *row, size_t size);

#endif
