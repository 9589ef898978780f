/* SPDX-License-Identifier: MIT */
/* list.h - --list: the parts and channels of the first frame's file and what ddof would use. */
#ifndef DDOF_CLI_LIST_H
#define DDOF_CLI_LIST_H

#include "options.h"

/* Prints the list on stdout. Returns the exit status. */
int list_run(const cli_options *o);

#endif

