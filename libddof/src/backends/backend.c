/* SPDX-License-Identifier: MIT */
/* backend.c - choosing where the diffusion runs: the CPU's table (the context's), or a GL
 * device from the plugin library, loaded at run time so that libddof itself never links GL.
 * Both are whole tables (ddof_backend_seam.h); the context's backend is always one of them
 * with its device (the CPU's: the context), and what it does not take runs on the CPU's. */
#define _GNU_SOURCE /* dladdr */
#include "backend.h"
#include "ddof_output_struct.h"

#include "disc/disc_kernel.h"

#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PLUGIN_FILE "libddof_gl.so"

const char *ddof_backend_name(ddof_backend_kind kind)
{
    switch (kind) {
    case DDOF_BACKEND_CPU: return "cpu";
    case DDOF_BACKEND_AUTO: return "auto";
    case DDOF_BACKEND_EGL: return "egl";
    case DDOF_BACKEND_OSMESA: return "osmesa";
    case DDOF_BACKEND_HOST_GL: return "host";
    case DDOF_BACKEND_COUNT_:
    case DDOF_BACKEND_FORCE_32BIT_: break;
    }
    return NULL;
}

/* The directory libddof was loaded from (so the plugin installed beside it is found first),
 * written into dir with a trailing '/'; "" when unknown. */
static void own_directory(char *dir, size_t size)
{
    dir[0] = '\0';
    static const char anchor = 0; /* any object of libddof's tells dladdr which file it is */
    Dl_info info;
    if (!dladdr(&anchor, &info) || !info.dli_fname)
        return;
    const char *slash = strrchr(info.dli_fname, '/');
    if (!slash || (size_t)(slash - info.dli_fname) + 2 > size)
        return;
    size_t n = (size_t)(slash - info.dli_fname) + 1;
    memcpy(dir, info.dli_fname, n);
    dir[n] = '\0';
}

int ddof_backend_table_whole(const ddof_backend_table *t)
{
    return t->open && t->close && t->describe && t->supports && t->run && t->supports_disc &&
           t->run_layers && t->supports_cards && t->render_cards && t->split_near;
}

/* dlopen()s the plugin and returns its table, or NULL with a sentence in message. */
static void *load_plugin(const char *plugin_path, const ddof_backend_table **table,
                         char *message, size_t size)
{
    char beside[4096], tried[1024] = "";
    /* A path the caller names (argument, else the environment) is the only one tried: asking
     * for a file and silently getting another would hide the mistake. */
    const char *env = getenv("DDOF_GL_PLUGIN");
    const char *named = plugin_path ? plugin_path : env && env[0] ? env : NULL;
    own_directory(beside, sizeof beside - sizeof PLUGIN_FILE);
    if (beside[0])
        strcat(beside, PLUGIN_FILE);
    const char *candidates[] = {named, named ? NULL : beside, named ? NULL : PLUGIN_FILE};
    void *handle = NULL;
    for (size_t i = 0; i < sizeof candidates / sizeof *candidates && !handle; i++) {
        if (!candidates[i] || !candidates[i][0])
            continue;
        handle = dlopen(candidates[i], RTLD_NOW | RTLD_LOCAL);
        if (!handle && !tried[0]) {
            const char *why = dlerror();
            snprintf(tried, sizeof tried, "%s", why ? why : candidates[i]);
        }
    }
    if (!handle) {
        snprintf(message, size, "the GL plugin %s could not be loaded (%s)", PLUGIN_FILE,
                 tried[0] ? tried : "not found");
        return NULL;
    }
    ddof_backend_entry_fn entry;
    void *symbol = dlsym(handle, DDOF_BACKEND_ENTRY_SYMBOL);
    memcpy(&entry, &symbol, sizeof entry); /* ISO C has no object-to-function cast */
    const ddof_backend_table *t = symbol ? entry() : NULL;
    if (!t || t->abi != DDOF_BACKEND_ABI || t->table_size != sizeof *t ||
        !ddof_backend_table_whole(t)) {
        snprintf(message, size,
                 "the GL plugin found is not built for this libddof (backend ABI %u, wanted %u)",
                 t ? t->abi : 0u, DDOF_BACKEND_ABI);
        dlclose(handle);
        return NULL;
    }
    *table = t;
    return handle;
}

/* The CPU as the context's backend: its table, the context its device. */
static ddof_backend_state cpu_state(ddof_context *context)
{
    return (ddof_backend_state){.kind = DDOF_BACKEND_CPU, .table = context->cpu,
                                .device = (ddof_device *)context};
}

void ddof_backend_start(ddof_context *context)
{
    context->backend = cpu_state(context);
}

static void drop_device(ddof_backend_state *b)
{
    if (b->device)
        b->table->close(b->device);
    if (b->plugin)
        dlclose(b->plugin);
    b->device = NULL;
    b->plugin = NULL;
    b->table = NULL;
}

void ddof_backend_release(ddof_context *context)
{
    drop_device(&context->backend);
}

static ddof_status set_backend(ddof_context *context, ddof_backend_kind kind,
                               const char *plugin_path)
{
    if ((unsigned)kind >= DDOF_BACKEND_COUNT_)
        return ddof_fail(context, DDOF_ERROR_BAD_PARAMETER, "unknown backend %d", (int)kind);

    ddof_backend_state next = cpu_state(context);
    if (kind != DDOF_BACKEND_CPU) {
        char why[512] = "";
        next = (ddof_backend_state){.kind = DDOF_BACKEND_CPU};
        next.plugin = load_plugin(plugin_path, &next.table, why, sizeof why);
        if (next.plugin) {
            const ddof_backend_kind open_kind = kind == DDOF_BACKEND_AUTO ? DDOF_BACKEND_EGL : kind;
            next.device = next.table->open(open_kind, kind == DDOF_BACKEND_AUTO, why, sizeof why);
            if (next.device)
                next.kind = open_kind;
            else
                drop_device(&next);
        }
        if (!next.device) {
            if (kind != DDOF_BACKEND_AUTO)
                return ddof_fail(context, DDOF_ERROR_BACKEND_UNAVAILABLE, "backend %s: %s",
                                 ddof_backend_name(kind), why);
            next = cpu_state(context);
            snprintf(next.note, sizeof next.note, "auto: the CPU, because %.200s", why);
        } else if (kind == DDOF_BACKEND_AUTO) {
            snprintf(next.note, sizeof next.note, "auto: a GPU was found through EGL");
        }
    }
    drop_device(&context->backend);
    context->backend = next;
    return DDOF_OK;
}

ddof_status ddof_context_set_backend(ddof_context *context, ddof_backend_kind kind,
                                     const char *plugin_path)
{
    DDOF_EXCLUSIVE_CALL(context, set_backend(context, kind, plugin_path));
}

/* The backend a request runs on, and its device: the context's backend where it takes the
 * request, else the CPU (whose device is the context), which also runs the double reference
 * on every backend and a disc kernel a device does not run. */
static const ddof_backend_table *runner(const ddof_context *context, ddof_solver solver,
                                        int disc, ddof_device **device)
{
    const ddof_backend_state *b = &context->backend;
    if (solver != DDOF_SOLVER_REFERENCE_F64 && (!disc || b->table->supports_disc(b->device))) {
        *device = b->device;
        return b->table;
    }
    *device = (ddof_device *)context; /* the CPU's device: the context itself */
    return context->cpu;
}

/* A backend's failure, recorded once: where the core already said why (the CPU's steps, a
 * card the core prepared), that stands; else the backend's sentence, named by the context's
 * backend. */
static ddof_status failed(ddof_context *context, ddof_status status, const char *why)
{
    if (context->last_error[0])
        return status;
    return ddof_fail(context, status, "%s backend: %s", ddof_backend_name(context->backend.kind),
                     why[0] ? why : ddof_status_string(status));
}

/* The disc kernel runs on the CPU with Thomas (lens_adi.c), on a device whose table says so
 * with Thomas, and with REFERENCE_F64 everywhere (the CPU runs the reference). */
static int runs_disc(const ddof_context *context, ddof_solver solver)
{
    if (solver == DDOF_SOLVER_REFERENCE_F64)
        return 1;
    ddof_device *device;
    const ddof_backend_table *t = runner(context, solver, 0, &device);
    return solver == DDOF_SOLVER_THOMAS && t->supports_disc(device);
}

const disc_kernel *ddof_backend_disc_kernel(const ddof_context *context, ddof_solver solver,
                                            ddof_kernel kernel)
{
    return runs_disc(context, solver) ? ddof_disc_kernel(kernel) : NULL;
}

ddof_status ddof_check_backend_supports(ddof_context *context, ddof_solver solver,
                                        ddof_precision precision)
{
    ddof_device *device;
    const ddof_backend_table *t = runner(context, solver, 0, &device);
    if (t->supports(device, solver, precision))
        return DDOF_OK;
    return ddof_fail(context, DDOF_ERROR_UNSUPPORTED,
                     "the %s backend cannot run solver %s with %s precision",
                     ddof_backend_name(context->backend.kind), ddof_solver_name(solver),
                     precision == DDOF_PRECISION_PACKED_HALF ? "packed half" : "float");
}

ddof_status ddof_context_backend_info(const ddof_context *context, ddof_backend_info *info)
{
    if (!context || !info)
        return DDOF_ERROR_NULL_POINTER;
    if (info->struct_size < DDOF_BACKEND_INFO_SIZE_0_3)
        return DDOF_ERROR_BAD_PARAMETER;
    const ddof_backend_state *b = &context->backend;
    ddof_backend_info full = {.struct_size = sizeof full, .kind = b->kind};
    snprintf(full.note, sizeof full.note, "%s", b->note);
    ddof_device_info d = {0};
    b->table->describe(b->device, &d);
    full.hardware = d.hardware;
    snprintf(full.renderer, sizeof full.renderer, "%s", d.renderer);
    ddof_write_output_struct(info, &full, sizeof full);
    return DDOF_OK;
}

ddof_status ddof_run_adi(ddof_context *context, const adi_request *request, adi_report *report)
{
    ddof_device *device;
    const ddof_backend_table *t = runner(context, request->solver, request->disc != NULL, &device);
    char why[512] = "";
    *report = (adi_report){0};
    const ddof_status status = t->run(device, request, report, why, sizeof why);
    return status == DDOF_OK ? DDOF_OK : failed(context, status, why);
}

int ddof_backend_runs_layers(const ddof_context *context, const adi_request *r)
{
    ddof_device *device;
    return r->coc && runner(context, r->solver, r->disc != NULL, &device) == context->backend.table;
}

ddof_status ddof_backend_run_layers(ddof_context *context, int on_backend,
                                    const adi_layers_request *request,
                                    adi_layers_report *report)
{
    const ddof_backend_state *b = &context->backend;
    const ddof_backend_table *t = on_backend ? b->table : context->cpu;
    ddof_device *device = on_backend ? b->device : (ddof_device *)context;
    char why[512] = "";
    memset(report, 0, sizeof *report);
    const ddof_status status = t->run_layers(device, request, report, why, sizeof why);
    return status == DDOF_OK ? DDOF_OK : failed(context, status, why);
}

ddof_status ddof_backend_split_near(ddof_context *context, const adi_near_request *request,
                                    adi_near_split *split, adi_report *report)
{
    const ddof_backend_state *b = &context->backend;
    char why[512] = "";
    memset(report, 0, sizeof *report);
    if (b->table != context->cpu && ddof_backend_runs_layers(context, &request->base)) {
        const ddof_status status =
            b->table->split_near(b->device, request, split, report, why, sizeof why);
        if (status != DDOF_ERROR_UNSUPPORTED)
            return status == DDOF_OK ? DDOF_OK : failed(context, status, why);
    }
    adi_report cpu = {0};
    const ddof_status status = context->cpu->split_near((ddof_device *)context, request, split,
                                                        &cpu, why, sizeof why);
    return status == DDOF_OK ? DDOF_OK : failed(context, status, why);
}

ddof_status ddof_backend_render_cards(ddof_context *context, const adi_cards_request *request)
{
    const ddof_backend_state *b = &context->backend;
    const int here = b->table->supports_cards(b->device);
    const ddof_backend_table *t = here ? b->table : context->cpu;
    ddof_device *device = here ? b->device : (ddof_device *)context;
    char why[512] = "";
    const ddof_status status = t->render_cards(device, request, why, sizeof why);
    return status == DDOF_OK ? DDOF_OK : failed(context, status, why);
}
