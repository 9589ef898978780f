/* SPDX-License-Identifier: MIT */
/* cli_clock.h - the command's one clock for stage times and the progress bar. */
#ifndef DDOF_CLI_CLOCK_H
#define DDOF_CLI_CLOCK_H

/* Seconds on the monotonic clock (only differences mean anything). */
double cli_now(void);

#endif
