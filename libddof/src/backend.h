/* backend.h - the seam between the core and a diffusion backend (the GL plugin).
 *
 * The planner and the layers decide *what* to simulate and issue ADI requests (adi.h); a
 * backend decides *how* to run one. The CPU backend is adi.c and reference_f64.c. The GL
 * backends live in the plugin library libddof_gl, which the core loads with
 * dlopen(RTLD_LOCAL) and asks for one table through the symbol DDOF_BACKEND_ENTRY_SYMBOL.
 * The plugin is built from this tree, but the two libraries can still be mixed up on disk, so
 * the table carries an ABI number and its size, checked before use.
 *
 * This header is shared by libddof and plugin/gl only; it is not installed.
 */
#ifndef DDOF_BACKEND_H
#define DDOF_BACKEND_H

#include "adi.h"

/* Bump when adi_request, adi_report or this table change layout or meaning. */
#define DDOF_BACKEND_ABI 2
#define DDOF_BACKEND_ENTRY_SYMBOL "ddof_gl_backend_table"

typedef struct ddof_device ddof_device; /* a backend's opened state, opaque to the core */

/* Where the device stands: what it is and what the last run took. */
typedef struct ddof_device_info {
    uint32_t hardware;      /* 1: a GPU; 0: a software renderer              */
    char renderer[128];     /* GL_RENDERER + GL_VERSION                      */
} ddof_device_info;

typedef struct ddof_backend_table {
    uint32_t abi;           /* DDOF_BACKEND_ABI                               */
    uint32_t table_size;    /* sizeof(ddof_backend_table)                     */

    /* Opens a device of `kind` (EGL, OSMESA or HOST_GL; never CPU or AUTO). `require_hardware`
     * (EGL only): fail unless a GPU is found, so AUTO does not pick software GL. On failure
     * returns NULL and writes a sentence into message. Must not leave any GL context current
     * (except HOST_GL, which never changes what is current). */
    ddof_device *(*open)(ddof_backend_kind kind, int require_hardware, char *message,
                         size_t message_size);
    void (*close)(ddof_device *device);
    void (*describe)(const ddof_device *device, ddof_device_info *info);

    /* Whether run() supports this solver/precision pair (REFERENCE_F64 never: the core runs
     * it itself). */
    int (*supports)(const ddof_device *device, ddof_solver solver, ddof_precision precision);

    /* One diffusion with the same contract as ddof_adi_run (the request is validated; out may
     * equal color; progress may cancel). Makes its context current for the call and releases
     * it afterwards. On failure: a status (DDOF_ERROR_BACKEND_FAILED, _OUT_OF_MEMORY,
     * _CANCELLED), a sentence in message, and out untouched unless cancelled.
     * report->device_bytes: peak GPU memory of the call. */
    ddof_status (*run)(ddof_device *device, const adi_request *request, adi_report *report,
                       char *message, size_t message_size);

    /* Appended within ABI 2; a table whose table_size ends before a field lacks it.
     * Whether run() takes requests with `disc` set (DDOF_SOLVER_THOMAS, float). */
    int (*supports_disc)(const ddof_device *device);
} ddof_backend_table;

/* The smallest table of ABI 2: the fields up to run(). */
#define DDOF_BACKEND_TABLE_MIN_SIZE offsetof(ddof_backend_table, supports_disc)

/* The plugin's one exported function. */
typedef const ddof_backend_table *(*ddof_backend_entry_fn)(void);

/* ---- the core's side (backend.c) ---------------------------------------------------------- */

/* Runs one diffusion on the context's backend: the double reference and the CPU solvers here,
 * everything else on the loaded device. */
ddof_status ddof_run_adi(ddof_context *context, const adi_request *request, adi_report *report);

/* Whether the disc kernel runs with this solver on the context's backend: on the CPU with
 * Thomas (lens_adi.c), on a device whose table says so with Thomas, and with REFERENCE_F64
 * everywhere (the core runs the reference itself). */
int ddof_backend_runs_disc(const ddof_context *context, ddof_solver solver);

/* DDOF_OK when the context's backend can run this solver/precision, else a failure recorded
 * in the context (before any output is written). */
ddof_status ddof_check_backend_supports(ddof_context *context, ddof_solver solver,
                                        ddof_precision precision);

/* Releases the loaded plugin and device (context teardown). */
void ddof_backend_release(ddof_context *context);

#endif
