/* SPDX-License-Identifier: MIT */
/* backend_cpu.h - the CPU as a backend (backend_cpu.c): the seam's table, every entry filled
 * by the core's own code. A context holds it from its creation (context->cpu), and the
 * dispatch (backends/backend.c) reaches it only through there. */
#ifndef DDOF_BACKEND_CPU_H
#define DDOF_BACKEND_CPU_H

#include "ddof_backend_seam.h"

extern const ddof_backend_table ddof_cpu_backend;

#endif
