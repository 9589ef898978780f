/* SPDX-License-Identifier: MIT */
/* cli_clock.c - the monotonic clock the command times its stages with (cli_clock.h). */
#include "cli_clock.h"

#include <time.h>

double cli_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}
