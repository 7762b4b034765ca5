/* Private to the model: the blocks file's reader (blocks.c; docs/blocks-file.md), which
 * vs_geometry_create_arch calls for arch.shape = file. Not installed. */
#ifndef VOUSSOIR_BLOCKS_H
#define VOUSSOIR_BLOCKS_H

#include <stddef.h>

#include "voussoir/def.h"
#include "voussoir/geometry.h"
#include "voussoir/status.h"

/* Largest blocks file read, bytes (64 MiB), and most blocks and vertices of one polygon. */
#define VS_BLOCKS_MAX_BYTES (64 << 20)
enum { VS_BLOCKS_MAX = 20000, VS_BLOCKS_MAX_VERTICES = 256 };

/* The geometry of the blocks file a->blocks_file (a regular file of at most
 * VS_BLOCKS_MAX_BYTES; a FIFO or a device is refused without blocking); a gives the depth, the
 * default density and the gravity. VS_ERR_IO when it cannot be read; otherwise as
 * vs_blocks_parse. */
vs_status vs_blocks_read(const vs_arch_def *a, vs_geometry **out, vs_error *err);

/* The geometry of the blocks file's text (len bytes; name stands for the file in messages).
 * VS_ERR_PARSE for text that is not JSON ("NAME:LINE:COLUMN: reason"); VS_ERR_INVALID naming
 * the field, the block and what is allowed, for JSON that is not a blocks file (an unknown
 * field, a polygon that crosses itself, edges that overlap only partly, a block that touches
 * nothing, a ring that is not a chain from the left support to the right one); VS_ERR_NOMEM. */
vs_status vs_blocks_parse(const char *name, const char *text, size_t len, const vs_arch_def *a,
                          vs_geometry **out, vs_error *err);

#endif
