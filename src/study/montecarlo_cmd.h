/* What the montecarlo and merge commands share (src/study/montecarlo_cmd.c, src/study/montecarlo_merge.c);
 * not part of the installed API. */
#ifndef VS_MONTECARLO_CMD_H
#define VS_MONTECARLO_CMD_H

#include "outpath.h"

/* Check that dir may receive the summary's files (VS_MC_OUTPUTS) and, with state, the study's
 * own (its manifest, journal and lock file): dir absent or a directory, each file there absent
 * or a regular file and none of the others (the case file, an input shard's table). 0, or
 * VS_EXIT_BAD_INPUT after printing why ("voussoir CMD: -o PATH: reason"). */
int vs_mc_check_outputs(const char *cmd, const char *dir, const vs_outpath_other *others,
                        int n_others, int state);

#endif
