/* The exit statuses of every command of the program. Here, in its lowest layer, because the
 * plugin loader, the studies and the command line all return them. */
#ifndef VS_EXIT_STATUS_H
#define VS_EXIT_STATUS_H

enum { VS_EXIT_OK = 0, VS_EXIT_FAILED = 1, VS_EXIT_BAD_INPUT = 2, VS_EXIT_INTERRUPTED = 130 };

#endif
