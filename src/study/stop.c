/* The program's stop signals (stop.h). */
#define _POSIX_C_SOURCE 200809L
#include "stop.h"

#include <string.h>

static volatile sig_atomic_t g_interrupted = 0;
static volatile sig_atomic_t g_signal = 0;

void vs_on_stop_signals(void (*fn)(int)) {
  struct sigaction sa;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = fn;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, NULL);
  sigaction(SIGTERM, &sa, NULL);
}

static void on_signal(int sig) {
  g_signal = sig;
  g_interrupted = 1;
}

void vs_stop_catch(void) { vs_on_stop_signals(on_signal); }

const volatile sig_atomic_t *vs_stop_flag(void) { return &g_interrupted; }

void vs_stop_release(void) {
  signal(SIGINT, SIG_DFL);
  signal(SIGTERM, SIG_DFL);
  if (g_interrupted) raise(g_signal != 0 ? (int)g_signal : SIGINT);
}
