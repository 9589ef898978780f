/* SPDX-License-Identifier: MIT */
/* configs.c - the configurations of the study and their ids.
 *
 * The full list is not the blind cross product of every knob (too slow): a base configuration,
 * one-factor-at-a-time sweeps of each knob around it, and the cross product of the knobs that
 * interact most (sub-steps x beta calibration k x layers) on the CPU Thomas solver. Every
 * configuration has an id that names all its settings and parses back ("cpu/thomas/f32/n4/
 * k0.03125/auto"; a disc kernel, which has no sub-steps or k, "cpu/thomas/f32/disc-2x2/auto"),
 * so report.py can ask ddof-study for the image of any configuration. */
#include "study.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* After the layers' name: the far field's gather on (ddof_params.far_field AUTO), its depth
 * slices where blurred surfaces meet (ddof_params.blurred_edges AUTO), then the silhouettes'
 * split (ddof_params.silhouettes AUTO), then the scene's object matte for it. */
#define FAR_FIELD_SUFFIX "+ff"
#define BLURRED_EDGES_SUFFIX "+be"
#define SILHOUETTES_SUFFIX "+sil"
#define MATTE_SUFFIX "+matte"

/* Strips `suffix` off the end of `token`; whether it was there. */
static int strip_suffix(char *token, const char *suffix)
{
    const size_t length = strlen(token), suffix_length = strlen(suffix);
    if (length <= suffix_length || strcmp(token + length - suffix_length, suffix))
        return 0;
    token[length - suffix_length] = '\0';
    return 1;
}

static const char *const layer_names[LAYERS_COUNT_] = {"single", "bg",    "bg2",
                                                       "bgnear", "auto",  "auto2",
                                                       "fg",     "fgpin", "autospread"};

int study_config_uses_fg(const study_config *cfg, int fg_element)
{
    return fg_element && cfg->kind == STUDY_DIFFUSION &&
           (cfg->layers == LAYERS_FG || cfg->layers == LAYERS_FGPIN);
}

const char *study_layers_name(study_layers layers)
{
    return (unsigned)layers < LAYERS_COUNT_ ? layer_names[layers] : "?";
}

static const char *precision_token(const study_config *cfg)
{
    if (cfg->solver == DDOF_SOLVER_REFERENCE_F64)
        return "f64";
    return cfg->precision == DDOF_PRECISION_PACKED_HALF ? "f16p" : "f32";
}

void study_config_make_id(study_config *cfg)
{
    switch (cfg->kind) {
    case STUDY_COD4: snprintf(cfg->id, sizeof cfg->id, "cod4"); return;
    case STUDY_GATHER: snprintf(cfg->id, sizeof cfg->id, "gather"); return;
    case STUDY_PINHOLE: snprintf(cfg->id, sizeof cfg->id, "pinhole"); return;
    case STUDY_DEFOCUS:
        snprintf(cfg->id, sizeof cfg->id, "%s", study_node_names[cfg->node]);
        return;
    case STUDY_DIFFUSION: break;
    }
    char solver[32];
    if (cfg->solver == DDOF_SOLVER_JACOBI)
        snprintf(solver, sizeof solver, "jacobi%u", cfg->jacobi_iterations);
    else
        snprintf(solver, sizeof solver, "%s", ddof_solver_name(cfg->solver));
    char ff[32];
    snprintf(ff, sizeof ff, "%s%s%s%s", cfg->far_field ? FAR_FIELD_SUFFIX : "",
             cfg->blurred_edges ? BLURRED_EDGES_SUFFIX : "",
             cfg->silhouettes ? SILHOUETTES_SUFFIX : "", cfg->matte ? MATTE_SUFFIX : "");
    if (cfg->kernel != DDOF_KERNEL_HEAT) { /* a disc has no sub-steps or k */
        snprintf(cfg->id, sizeof cfg->id, "%s/%s/%s/%s/%s%s", ddof_backend_name(cfg->backend),
                 solver, precision_token(cfg), ddof_kernel_name(cfg->kernel),
                 study_layers_name(cfg->layers), ff);
        return;
    }
    snprintf(cfg->id, sizeof cfg->id, "%s/%s/%s/n%u/k%.6g/%s%s", ddof_backend_name(cfg->backend),
             solver, precision_token(cfg), cfg->substeps, (double)cfg->beta_scale,
             study_layers_name(cfg->layers), ff);
}

const char *const study_node_names[STUDY_NODE_COUNT] = {"defocus", "defocus-4.2",
                                                         "defocus-5.3"};

int study_config_parse(const char *id, study_config *out)
{
    memset(out, 0, sizeof *out);
    out->jacobi_iterations = 50;
    for (int n = 0; n < STUDY_NODE_COUNT; n++)
        if (!strcmp(id, study_node_names[n])) {
            out->kind = STUDY_DEFOCUS;
            out->node = n;
            out->substeps = 1;
            out->beta_scale = DDOF_MOMENT_BETA_SCALE;
            study_config_make_id(out);
            return 0;
        }
    static const struct {
        const char *name;
        study_kind kind;
    } baselines[] = {{"cod4", STUDY_COD4}, {"gather", STUDY_GATHER},
                     {"pinhole", STUDY_PINHOLE}};
    for (size_t i = 0; i < sizeof baselines / sizeof *baselines; i++)
        if (!strcmp(id, baselines[i].name)) {
            out->kind = baselines[i].kind;
            out->substeps = 1;
            out->beta_scale = DDOF_MOMENT_BETA_SCALE;
            study_config_make_id(out);
            return 0;
        }
    char copy[128];
    if (strlen(id) >= sizeof copy)
        return -1;
    strcpy(copy, id);
    char *parts[7];
    int n = 0;
    for (char *s = copy, *slash; n < 7; s = slash + 1) {
        parts[n++] = s;
        slash = strchr(s, '/');
        if (!slash)
            break;
        *slash = '\0';
    }
    if (n == 5) { /* a disc kernel in place of "n../k..": parts 0-2, kernel, layers */
        for (int k = 1; k < DDOF_KERNEL_COUNT_; k++)
            if (!strcmp(parts[3], ddof_kernel_name((ddof_kernel)k)))
                out->kernel = (ddof_kernel)k;
        if (out->kernel == DDOF_KERNEL_HEAT)
            return -1;
        parts[5] = parts[4];
        parts[4] = "k0.03125";
        parts[3] = "n1";
        n = 6;
    }
    if (n != 6)
        return -1;
    out->kind = STUDY_DIFFUSION;
    int found = 0;
    for (int b = 0; b < DDOF_BACKEND_COUNT_; b++)
        if (!strcmp(parts[0], ddof_backend_name((ddof_backend_kind)b))) {
            out->backend = (ddof_backend_kind)b;
            found = 1;
        }
    if (!found)
        return -1;
    found = 0;
    if (!strncmp(parts[1], "jacobi", 6) && parts[1][6]) {
        char *end;
        unsigned long it = strtoul(parts[1] + 6, &end, 10);
        if (*end || it == 0 || it > 100000)
            return -1;
        out->solver = DDOF_SOLVER_JACOBI;
        out->jacobi_iterations = (uint32_t)it;
        found = 1;
    } else {
        for (int s = 0; s < DDOF_SOLVER_COUNT_; s++)
            if (s != DDOF_SOLVER_JACOBI && !strcmp(parts[1], ddof_solver_name((ddof_solver)s))) {
                out->solver = (ddof_solver)s;
                found = 1;
            }
    }
    if (!found)
        return -1;
    if (!strcmp(parts[2], "f32"))
        out->precision = DDOF_PRECISION_FLOAT;
    else if (!strcmp(parts[2], "f16p"))
        out->precision = DDOF_PRECISION_PACKED_HALF;
    else if (!strcmp(parts[2], "f64") && out->solver == DDOF_SOLVER_REFERENCE_F64)
        out->precision = DDOF_PRECISION_FLOAT;
    else
        return -1;
    if ((out->solver == DDOF_SOLVER_REFERENCE_F64) != !strcmp(parts[2], "f64"))
        return -1;
    char *end;
    if (parts[3][0] != 'n')
        return -1;
    unsigned long substeps = strtoul(parts[3] + 1, &end, 10);
    if (*end || substeps == 0 || substeps > 4096)
        return -1;
    out->substeps = (uint32_t)substeps;
    if (parts[4][0] != 'k')
        return -1;
    float k = strtof(parts[4] + 1, &end);
    if (*end || !(k > 0.0f) || !isfinite(k))
        return -1;
    out->beta_scale = k;
    found = 0;
    out->matte = strip_suffix(parts[5], MATTE_SUFFIX);
    out->silhouettes = strip_suffix(parts[5], SILHOUETTES_SUFFIX);
    if (out->matte && !out->silhouettes)
        return -1; /* the matte serves the split only */
    out->blurred_edges = strip_suffix(parts[5], BLURRED_EDGES_SUFFIX);
    out->far_field = strip_suffix(parts[5], FAR_FIELD_SUFFIX);
    if (out->blurred_edges && !out->far_field)
        return -1; /* the slices are the far field's */
    for (int l = 0; l < LAYERS_COUNT_; l++)
        if (!strcmp(parts[5], layer_names[l])) {
            out->layers = (study_layers)l;
            found = 1;
        }
    if (!found)
        return -1;
    study_config_make_id(out);
    return 0;
}

/* "1/32" when k is the reciprocal of an integer, else "0.0208". */
static void k_text(float k, char *out, size_t size)
{
    const double inv = 1.0 / (double)k;
    if (fabs(inv - floor(inv + 0.5)) < 1e-3 * inv)
        snprintf(out, size, "1/%.0f", inv);
    else
        snprintf(out, size, "%.4g", (double)k);
}

void study_config_label(const study_config *cfg, char *out, size_t size)
{
    if (cfg->kind != STUDY_DIFFUSION) {
        static const char *const names[] = {"", "CoD4 preview", "gather blur", "pinhole",
                                            "Defocus node"};
        if (cfg->kind == STUDY_DEFOCUS)
            snprintf(out, size, "Defocus node (%s)", study_node_names[cfg->node]);
        else
            snprintf(out, size, "%s", names[cfg->kind]);
        return;
    }
    char solver[32], k[32];
    if (cfg->solver == DDOF_SOLVER_JACOBI)
        snprintf(solver, sizeof solver, "jacobi%u", cfg->jacobi_iterations);
    else
        snprintf(solver, sizeof solver, "%s", ddof_solver_name(cfg->solver));
    k_text(cfg->beta_scale, k, sizeof k);
    char ff[96];
    snprintf(ff, sizeof ff, "%s%s%s%s", cfg->far_field ? " + far field" : "",
             cfg->blurred_edges ? " + blurred edges" : "",
             cfg->silhouettes ? " + silhouettes" : "", cfg->matte ? " + object matte" : "");
    if (cfg->kernel != DDOF_KERNEL_HEAT) {
        snprintf(out, size, "%s %s %s %s%s", ddof_backend_name(cfg->backend), solver,
                 ddof_kernel_name(cfg->kernel), study_layers_name(cfg->layers), ff);
        return;
    }
    snprintf(out, size, "%s %s%s n=%u k=%s %s%s", ddof_backend_name(cfg->backend), solver,
             cfg->precision == DDOF_PRECISION_PACKED_HALF ? " half" : "", cfg->substeps, k,
             study_layers_name(cfg->layers), ff);
}

int study_config_add(study_config_list *list, const study_config *cfg, const char *sweep)
{
    study_config c = *cfg;
    study_config_make_id(&c);
    /* The id is canonical: parse it back so that k is exactly what the id says. */
    study_config parsed;
    if (study_config_parse(c.id, &parsed) != 0)
        return -1;
    for (size_t i = 0; i < list->count; i++) {
        study_config *old = &list->items[i];
        if (strcmp(old->id, parsed.id))
            continue;
        if (sweep && sweep[0] && !strstr(old->sweeps, sweep)) {
            size_t used = strlen(old->sweeps);
            snprintf(old->sweeps + used, sizeof old->sweeps - used, "%s%s", used ? "," : "",
                     sweep);
        }
        return 0;
    }
    if (list->count == list->capacity) {
        size_t cap = list->capacity ? list->capacity * 2 : 64;
        study_config *items = realloc(list->items, cap * sizeof *items);
        if (!items)
            return -1;
        list->items = items;
        list->capacity = cap;
    }
    snprintf(parsed.sweeps, sizeof parsed.sweeps, "%s", sweep ? sweep : "");
    list->items[list->count++] = parsed;
    return 0;
}

void study_config_list_free(study_config_list *list)
{
    free(list->items);
    memset(list, 0, sizeof *list);
}

static study_config base_config(void)
{
    study_config c;
    memset(&c, 0, sizeof c);
    c.kind = STUDY_DIFFUSION;
    c.backend = DDOF_BACKEND_CPU;
    c.solver = DDOF_SOLVER_THOMAS;
    c.jacobi_iterations = 50;
    c.precision = DDOF_PRECISION_FLOAT;
    c.substeps = 4;
    c.beta_scale = DDOF_MOMENT_BETA_SCALE;
    c.layers = LAYERS_AUTO;
    return c;
}

static int add_baseline(study_config_list *list, const char *name)
{
    study_config c;
    return study_config_parse(name, &c) == 0 ? study_config_add(list, &c, "baseline") : -1;
}

/* Every Blender's Defocus node (a scene without a node's files reports it not available). */
static int add_nodes(study_config_list *list)
{
    int rc = 0;
    for (int n = 0; n < STUDY_NODE_COUNT; n++)
        rc |= add_baseline(list, study_node_names[n]);
    return rc;
}

/* The far field's gather, alone and with the silhouettes' split, over the configurations a
 * preset could be: the disc kernels and the heat kernel's best k per sub-step count, with the
 * layers on AUTO (and the near spread). With the AUTO layers and the split, also with the depth
 * slices where blurred surfaces meet. */
static int add_far_field(study_config_list *list)
{
    int rc = 0;
    study_config c = base_config();
    c.far_field = 1;
    static const study_layers layers[] = {LAYERS_AUTO, LAYERS_AUTOSPREAD, LAYERS_BGNEAR};
    for (int k = 0; k < DDOF_KERNEL_COUNT_; k++)
        for (size_t l = 0; l < sizeof layers / sizeof *layers; l++) {
            c.kernel = (ddof_kernel)k;
            c.layers = layers[l];
            static const uint32_t substeps[] = {1, 2, 4};
            static const float k_heat[] = {16, 24};
            /* 0: no split, 1: the colours' split, 2: the split by the scene's object matte
             * (the AUTO layers only: what the presets can be). */
            for (int split = 0; split < 3; split++)
                for (int slices = 0; slices < 2; slices++) {
                    if ((split == 2 || slices) && layers[l] != LAYERS_AUTO)
                        continue;
                    if (slices && !split)
                        continue;
                    c.silhouettes = split > 0;
                    c.matte = split == 2;
                    c.blurred_edges = slices;
                    static const char *const sweeps[2][3] = {
                        {"far field", "far field,silhouettes", "far field,silhouettes,matte"},
                        {"far field,blurred edges", "far field,blurred edges,silhouettes",
                         "far field,blurred edges,silhouettes,matte"}};
                    const char *sweep = sweeps[slices][split];
                    if (k != DDOF_KERNEL_HEAT) {
                        c.substeps = 1;
                        c.beta_scale = DDOF_MOMENT_BETA_SCALE;
                        rc |= study_config_add(list, &c, sweep);
                        continue;
                    }
                    for (size_t n = 0; n < sizeof substeps / sizeof *substeps; n++)
                        for (size_t b = 0; b < sizeof k_heat / sizeof *k_heat; b++) {
                            c.substeps = substeps[n];
                            c.beta_scale = 1.0f / k_heat[b];
                            rc |= study_config_add(list, &c, sweep);
                        }
                }
        }
    return rc;
}

static int add_full(study_config_list *list)
{
    int rc = 0;
    const study_config base = base_config();
    study_config c;
    rc |= study_config_add(list, &base, "base");

    /* Solvers, on the CPU (and double = the reference solver). */
    static const uint32_t jacobi[] = {10, 50, 200, 1000};
    static const ddof_solver exact[] = {DDOF_SOLVER_CYCLIC_REDUCTION, DDOF_SOLVER_PCR};
    for (size_t i = 0; i < sizeof exact / sizeof *exact; i++) {
        c = base;
        c.solver = exact[i];
        rc |= study_config_add(list, &c, "solver");
    }
    for (size_t i = 0; i < sizeof jacobi / sizeof *jacobi; i++) {
        c = base;
        c.solver = DDOF_SOLVER_JACOBI;
        c.jacobi_iterations = jacobi[i];
        rc |= study_config_add(list, &c, "solver");
    }
    c = base;
    c.solver = DDOF_SOLVER_REFERENCE_F64;
    rc |= study_config_add(list, &c, "solver,precision");

    /* Sub-steps, k and layers, one at a time. */
    static const uint32_t substeps[] = {1, 2, 4, 8};
    for (size_t i = 0; i < sizeof substeps / sizeof *substeps; i++) {
        c = base;
        c.substeps = substeps[i];
        rc |= study_config_add(list, &c, "substeps");
    }
    static const float k_sweep[] = {128, 64, 48, 40, 32, 28, 24, 20, 16, 12};
    for (size_t i = 0; i < sizeof k_sweep / sizeof *k_sweep; i++) {
        c = base;
        c.beta_scale = 1.0f / k_sweep[i];
        rc |= study_config_add(list, &c, "k");
    }
    for (int l = 0; l < LAYERS_COUNT_; l++) {
        c = base;
        c.layers = (study_layers)l;
        rc |= study_config_add(list, &c, "layers");
    }

    /* Backends: the GL solvers, float and packed half. Measured when the backend opens. */
    static const ddof_backend_kind gl[] = {DDOF_BACKEND_OSMESA, DDOF_BACKEND_EGL};
    static const ddof_solver gl_solvers[] = {DDOF_SOLVER_GRUEN, DDOF_SOLVER_THOMAS,
                                             DDOF_SOLVER_CYCLIC_REDUCTION, DDOF_SOLVER_PCR,
                                             DDOF_SOLVER_JACOBI};
    for (size_t b = 0; b < sizeof gl / sizeof *gl; b++) {
        for (size_t s = 0; s < sizeof gl_solvers / sizeof *gl_solvers; s++) {
            c = base;
            c.backend = gl[b];
            c.solver = gl_solvers[s];
            rc |= study_config_add(list, &c, "backend");
            if (gl_solvers[s] == DDOF_SOLVER_GRUEN) {
                c.precision = DDOF_PRECISION_PACKED_HALF;
                rc |= study_config_add(list, &c, "backend,precision");
            }
        }
    }

    /* The knobs that interact: sub-steps x k x layers on CPU Thomas. */
    static const float k_cross[] = {64, 48, 40, 32, 24, 16};
    static const study_layers l_cross[] = {LAYERS_SINGLE, LAYERS_BG, LAYERS_BGNEAR, LAYERS_AUTO,
                                           LAYERS_FG};
    for (size_t l = 0; l < sizeof l_cross / sizeof *l_cross; l++)
        for (size_t n = 0; n < sizeof substeps / sizeof *substeps; n++)
            for (size_t k = 0; k < sizeof k_cross / sizeof *k_cross; k++) {
                c = base;
                c.layers = l_cross[l];
                c.substeps = substeps[n];
                c.beta_scale = 1.0f / k_cross[k];
                rc |= study_config_add(list, &c, "cross");
            }

    /* The disc kernels (CPU Thomas), with each layer setting. */
    static const study_layers l_disc[] = {LAYERS_SINGLE, LAYERS_BG,  LAYERS_BGNEAR,
                                          LAYERS_AUTO,   LAYERS_FG, LAYERS_AUTOSPREAD};
    for (int k = 1; k < DDOF_KERNEL_COUNT_; k++)
        for (size_t l = 0; l < sizeof l_disc / sizeof *l_disc; l++) {
            c = base;
            c.kernel = (ddof_kernel)k;
            c.substeps = 1;
            c.layers = l_disc[l];
            rc |= study_config_add(list, &c, "kernel");
        }

    rc |= add_far_field(list);
    rc |= add_baseline(list, "pinhole");
    rc |= add_baseline(list, "cod4");
    rc |= add_baseline(list, "gather");
    rc |= add_nodes(list);
    return rc ? -1 : 0;
}

int study_config_named(study_config_list *list, const char *name)
{
    if (!strcmp(name, "full"))
        return add_full(list);
    if (!strcmp(name, "smoke")) {
        const study_config base = base_config();
        study_config disc = base;
        disc.kernel = DDOF_KERNEL_DISC_2X2;
        disc.substeps = 1;
        study_config far = disc;
        far.far_field = 1;
        far.silhouettes = 1;
        study_config matte = far;
        matte.matte = 1;
        study_config edges = far;
        edges.blurred_edges = 1;
        return study_config_add(list, &base, "base") | study_config_add(list, &disc, "kernel") |
               study_config_add(list, &far, "far field") |
               study_config_add(list, &edges, "far field,blurred edges,silhouettes") |
               study_config_add(list, &matte, "far field,silhouettes,matte") |
               add_baseline(list, "pinhole");
    }
    if (!strcmp(name, "baselines"))
        return add_baseline(list, "pinhole") | add_baseline(list, "cod4") |
               add_baseline(list, "gather") | add_nodes(list);
    return -1;
}

int study_config_from_spec(study_config_list *list, const char *spec, char *error, size_t size)
{
    char *copy = malloc(strlen(spec) + 1);
    if (!copy) {
        snprintf(error, size, "out of memory");
        return -1;
    }
    strcpy(copy, spec);
    int rc = 0;
    for (char *save = NULL, *tok = strtok_r(copy, ",", &save); tok && !rc;
         tok = strtok_r(NULL, ",", &save)) {
        study_config c;
        if (study_config_named(list, tok) == 0)
            continue;
        if (study_config_parse(tok, &c) != 0 || study_config_add(list, &c, "listed") != 0) {
            snprintf(error, size, "'%s' is not a configuration id or list name (full, smoke, "
                     "baselines); ids look like cpu/thomas/f32/n4/k0.03125/auto, cod4, gather, "
                     "pinhole, defocus, defocus-4.2, defocus-5.3", tok);
            rc = -1;
        }
    }
    free(copy);
    return rc;
}

void study_config_params(const study_config *cfg, int fg_element, ddof_params *p)
{
    ddof_params_init(p); /* thresholds and ramp: the library's base values */
    p->method = cfg->kind == STUDY_COD4 ? DDOF_METHOD_COD4_PREVIEW : DDOF_METHOD_DIFFUSION;
    p->solver = cfg->solver;
    p->substeps = cfg->substeps;
    p->beta_scale = cfg->beta_scale;
    p->jacobi_iterations = cfg->jacobi_iterations;
    p->precision = cfg->precision;
    p->kernel = cfg->kernel;
    p->coc_signed = 1;
    p->pixel_aspect = 1.0f;
    p->background_levels = 1;
    p->near_layer = DDOF_LAYER_OFF; /* AUTO in the AUTO settings only */
    p->far_field = cfg->far_field ? DDOF_LAYER_AUTO : DDOF_LAYER_OFF;
    p->blurred_edges = cfg->blurred_edges ? DDOF_LAYER_AUTO : DDOF_LAYER_OFF;
    p->silhouettes = cfg->silhouettes ? DDOF_LAYER_AUTO : DDOF_LAYER_OFF;
    switch (cfg->layers) {
    case LAYERS_SINGLE:
        p->background = DDOF_LAYER_OFF;
        p->near_spread = DDOF_LAYER_OFF;
        break;
    case LAYERS_BG2:
        p->background_levels = 2;
        /* fall through */
    case LAYERS_BG:
        p->background = DDOF_LAYER_ON;
        p->near_spread = DDOF_LAYER_OFF;
        break;
    case LAYERS_BGNEAR:
        p->background = DDOF_LAYER_ON;
        p->near_spread = DDOF_LAYER_ON;
        break;
    case LAYERS_AUTO2:
        p->background_levels = 2;
        /* fall through */
    case LAYERS_AUTO:
    case LAYERS_COUNT_:
        p->background = DDOF_LAYER_AUTO;
        p->near_spread = DDOF_LAYER_AUTO;
        p->near_layer = DDOF_LAYER_AUTO;
        break;
    case LAYERS_AUTOSPREAD:
        p->background = DDOF_LAYER_AUTO;
        p->near_spread = DDOF_LAYER_AUTO;
        break;
    case LAYERS_FG:
    case LAYERS_FGPIN:
        p->background = DDOF_LAYER_ON;
        p->near_spread = fg_element ? DDOF_LAYER_OFF : DDOF_LAYER_ON;
        break;
    }
}
