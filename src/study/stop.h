/* The program's stop signals (SIGINT, SIGTERM): how each command hears them. The studies install
 * their own handlers (vs_on_stop_signals); `run` watches one flag (vs_stop_*). A signal handler
 * can only reach a global: these are the program's one piece of process state. */
#ifndef VS_STOP_H
#define VS_STOP_H

#include <signal.h>

/* Install fn for SIGINT and SIGTERM (no SA_RESTART: a blocking wait returns with EINTR). */
void vs_on_stop_signals(void (*fn)(int));

/* Catch SIGINT and SIGTERM into the stop flag: the solve under way stops at its next residual
 * evaluation and the outputs are closed with the status "failed: interrupted". */
void vs_stop_catch(void);

/* The flag vs_stop_catch sets (read-only; never NULL). */
const volatile sig_atomic_t *vs_stop_flag(void);

/* For the commands that do not watch the flag: the default disposition back, and a signal that
 * came meanwhile delivered again (it then ends the process as it would have). */
void vs_stop_release(void);

#endif
