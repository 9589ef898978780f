/* SPDX-License-Identifier: MIT */
/* path_safety.c - the outputs' paths judged before they are written (path_safety.h). */
#include "path_safety.h"

#include "exr_whole.h"
#include "output_file.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* 1 when `a` and `b` name the same existing file (same device and inode: this sees through
 * "./x", "../dir/x", symbolic and hard links), 0 otherwise. */
static int same_file(const char *a, const char *b)
{
    struct stat sa, sb;
    if (stat(a, &sa) != 0 || stat(b, &sb) != 0)
        return 0;
    return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

int frame_check_paths(const frame_paths *paths, char *error, size_t error_size)
{
    const char *inputs[4];
    const char *input_kind[4] = {"input", "depth file", "ground truth", "foreground element"};
    const char *outputs[4];
    const char *output_kind[4] = {"output", "preview", "input preview", "focus map"};
    int i, o;
    inputs[0] = paths->input;
    inputs[1] = paths->depth_file;
    inputs[2] = paths->compare;
    inputs[3] = paths->foreground;
    outputs[0] = paths->output;
    outputs[1] = paths->preview;
    outputs[2] = paths->preview_input;
    outputs[3] = paths->focus_map;
    for (o = 0; o < 4; o++) {
        if (!outputs[o][0])
            continue;
        for (i = 0; i < 4; i++) {
            if (!inputs[i][0])
                continue;
            /* Same spelling, or the same file under another spelling or link. */
            if (strcmp(outputs[o], inputs[i]) == 0 || same_file(outputs[o], inputs[i])) {
                snprintf(error, error_size, "refusing to write %s %s: it is the %s (%s); ddof "
                         "never overwrites its input", output_kind[o], outputs[o],
                         input_kind[i], inputs[i]);
                return -1;
            }
        }
    }
    for (o = 1; o < 4; o++) { /* every pair of outputs, the focus map included */
        int p;
        for (p = 0; p < o; p++) {
            if (outputs[o][0] && (strcmp(outputs[o], outputs[p]) == 0 ||
                                  same_file(outputs[o], outputs[p]))) {
                snprintf(error, error_size, "the %s and the %s are the same file (%s)",
                         output_kind[o], output_kind[p], outputs[o]);
                return -1;
            }
        }
    }
    return 0;
}

/* The identity of an existing file: the same under any spelling, symbolic or hard link. */
typedef struct file_id {
    dev_t dev;
    ino_t ino;
    const char *path; /* one spelling of it, for messages */
} file_id;

static int compare_file_ids(const void *pa, const void *pb)
{
    const file_id *a = pa, *b = pb;
    if (a->dev != b->dev)
        return a->dev < b->dev ? -1 : 1;
    return a->ino < b->ino ? -1 : a->ino > b->ino;
}

/* Adds path to ids if it names an existing file (a missing one is nothing to protect). */
static void add_file_id(file_id *ids, size_t *n, const char *path)
{
    struct stat st;
    if (path && path[0] && stat(path, &st) == 0)
        ids[(*n)++] = (file_id){st.st_dev, st.st_ino, path};
}

/* The existing input that path is, or NULL. */
static const file_id *find_file_id(const file_id *ids, size_t n, const char *path)
{
    struct stat st;
    file_id key;
    if (!path || !path[0] || stat(path, &st) != 0)
        return NULL;
    key = (file_id){st.st_dev, st.st_ino, NULL};
    return bsearch(&key, ids, n, sizeof *ids, compare_file_ids);
}

/* No output of any frame, no preview and no stats file may be an input of any frame or the
 * camera sidecar: with sequences, frame 5's output may be frame 1005's input. Inputs exist,
 * so their (device, inode) identify them; each output is looked up once. */
static int check_no_input_overwritten(const cli_options *o, const frame_paths *paths, int count)
{
    /* Four inputs a frame and the sidecar (count is at least 1; a guard for the allocator's
     * size, which the compiler cannot see bounded). */
    file_id *ids = malloc(((size_t)(count > 0 ? count : 0) * 4 + 1) * sizeof *ids);
    size_t n = 0;
    int i, refused = 0;
    if (!ids) {
        fprintf(stderr, "ddof: out of memory\n");
        return -1;
    }
    for (i = 0; i < count; i++) {
        add_file_id(ids, &n, paths[i].input);
        add_file_id(ids, &n, paths[i].depth_file);
        add_file_id(ids, &n, paths[i].compare);
        add_file_id(ids, &n, paths[i].foreground);
    }
    add_file_id(ids, &n, o->camera_json);
    qsort(ids, n, sizeof *ids, compare_file_ids);
    for (i = 0; i <= count && !refused; i++) {
        /* Every frame's outputs, then (i == count) the stats file. */
        const char *outputs[4] = {i < count ? paths[i].output : o->stats_path,
                                  i < count ? paths[i].preview : NULL,
                                  i < count ? paths[i].preview_input : NULL,
                                  i < count ? paths[i].focus_map : NULL};
        int k;
        for (k = 0; k < 4 && !refused; k++) {
            const file_id *hit = find_file_id(ids, n, outputs[k]);
            if (hit) {
                fprintf(stderr, "ddof: refusing to write %s: it is an input (%s); ddof never "
                                "overwrites its input\n",
                        outputs[k], hit->path);
                refused = 1;
            }
        }
    }
    free(ids);
    return refused ? -1 : 0;
}

/* Where an output will be, whether or not it exists yet: its directory's identity and its
 * name in it (output_check_target refuses a link at an output path, so the name is the file). */
typedef struct output_slot {
    dev_t dev;
    ino_t ino;
    const char *name;
    const char *path;
    int frame, kind;
} output_slot;

static int compare_slots(const void *pa, const void *pb)
{
    const output_slot *a = pa, *b = pb;
    if (a->dev != b->dev)
        return a->dev < b->dev ? -1 : 1;
    if (a->ino != b->ino)
        return a->ino < b->ino ? -1 : 1;
    return strcmp(a->name, b->name);
}

/* The slot of `path`: 0, or -1 when its directory does not exist (output_check_directory
 * says so later). */
static int output_slot_of(const char *path, output_slot *slot)
{
    char folder[PATH_MAX];
    const char *slash = strrchr(path, '/');
    struct stat st;
    if (!slash)
        snprintf(folder, sizeof folder, ".");
    else
        snprintf(folder, sizeof folder, "%.*s", slash == path ? 1 : (int)(slash - path), path);
    if (stat(folder, &st) != 0)
        return -1;
    slot->dev = st.st_dev;
    slot->ino = st.st_ino;
    slot->name = slash ? slash + 1 : path;
    slot->path = path;
    return 0;
}

/* No two frames write one file: with patterns, frame 0's --preview q_1#.exr is frame 10's
 * output q_10.exr. The outputs do not exist yet, so each is known by its directory's identity
 * and its name. */
static int check_outputs_distinct(const frame_paths *paths, int count)
{
    static const char *const kind[4] = {"output", "preview", "input preview", "focus map"};
    output_slot *slots;
    size_t n = 0, i;
    int refused = 0;
    if (count < 2)
        return 0; /* one frame: frame_check_paths */
    slots = malloc((size_t)count * 4 * sizeof *slots);
    if (!slots) {
        fprintf(stderr, "ddof: out of memory\n");
        return -1;
    }
    for (int f = 0; f < count; f++) {
        const char *outputs[4] = {paths[f].output, paths[f].preview, paths[f].preview_input,
                                  paths[f].focus_map};
        for (int k = 0; k < 4; k++)
            if (outputs[k][0] && output_slot_of(outputs[k], &slots[n]) == 0) {
                slots[n].frame = paths[f].frame;
                slots[n].kind = k;
                n++;
            }
    }
    qsort(slots, n, sizeof *slots, compare_slots);
    for (i = 1; i < n && !refused; i++) {
        const output_slot *a = &slots[i - 1], *b = &slots[i];
        if (compare_slots(a, b) == 0) {
            fprintf(stderr, "ddof: frame %d's %s %s is also frame %d's %s (%s): one would "
                    "overwrite the other\n", a->frame, kind[a->kind], a->path, b->frame,
                    kind[b->kind], b->path);
            refused = 1;
        }
    }
    free(slots);
    return refused ? -1 : 0;
}

int path_safety_check_outputs(const cli_options *o, const frame_paths *paths, int count)
{
    char error[2048];
    int i;
    for (i = 0; i < count; i++) { /* the common case, with the clearest message */
        if (frame_check_paths(&paths[i], error, sizeof error) != 0) {
            fprintf(stderr, "ddof: %s\n", error);
            return -1;
        }
    }
    /* A device, FIFO, socket, directory or link at any frame's output path: one lstat each,
     * before the first frame, not a failure after frame 239. */
    for (i = 0; i <= count; i++) {
        const char *outputs[4] = {i < count ? paths[i].output : o->stats_path,
                                  i < count ? paths[i].preview : NULL,
                                  i < count ? paths[i].preview_input : NULL,
                                  i < count ? paths[i].focus_map : NULL};
        int k;
        for (k = 0; k < 4; k++)
            if (outputs[k] && outputs[k][0] &&
                output_check_target(outputs[k], error, sizeof error) != 0) {
                fprintf(stderr, "ddof: %s%s\n", k == 0 && i == count ? "--stats: " : "", error);
                return -1;
            }
    }
    if (check_no_input_overwritten(o, paths, count) != 0 ||
        check_outputs_distinct(paths, count) != 0)
        return -1;
    for (i = 0; o->stats_path && i < count; i++) { /* nor may --stats be one of the outputs */
        const char *outputs[4] = {paths[i].output, paths[i].preview, paths[i].preview_input,
                                  paths[i].focus_map};
        int k;
        for (k = 0; k < 4; k++)
            if (outputs[k][0] && (strcmp(outputs[k], o->stats_path) == 0 ||
                                  same_file(outputs[k], o->stats_path))) {
                if (paths[i].frame < 0)
                    fprintf(stderr, "ddof: --stats %s is also an output\n", o->stats_path);
                else
                    fprintf(stderr, "ddof: --stats %s is also an output of frame %d\n",
                            o->stats_path, paths[i].frame);
                return -1;
            }
    }
    /* Patterns keep the directory the same for every frame, so the first frame tells. */
    if (output_check_directory(paths[0].output, error, sizeof error) != 0 ||
        (paths[0].preview[0] &&
         output_check_directory(paths[0].preview, error, sizeof error) != 0) ||
        (paths[0].preview_input[0] &&
         output_check_directory(paths[0].preview_input, error, sizeof error) != 0) ||
        (paths[0].focus_map[0] &&
         output_check_directory(paths[0].focus_map, error, sizeof error) != 0)) {
        fprintf(stderr, "ddof: %s\n", error);
        return -1;
    }
    if (o->stats_path && output_check_directory(o->stats_path, error, sizeof error) != 0) {
        fprintf(stderr, "ddof: --stats: %s\n", error);
        return -1;
    }
    return 0;
}

/* What a killed run (SIGKILL, a power cut) left in the output directories. Patterns keep the
 * directory the same for every frame, so the first frame's paths name them all. */
void path_safety_remove_stale_temps(const cli_options *o, const frame_paths *first)
{
    const char *outputs[5] = {first->output, first->preview, first->preview_input,
                              first->focus_map, o->stats_path};
    int k;
    for (k = 0; k < 5; k++) {
        char note[PATH_MAX + 64];
        int removed;
        if (!outputs[k] || !outputs[k][0])
            continue;
        removed = output_remove_stale_temps(outputs[k], note, sizeof note);
        if (removed > 0)
            fprintf(stderr, "ddof: note: removed %d temporary file%s left by an earlier run "
                    "that was killed (%s%s)\n", removed, removed == 1 ? "" : "s", note,
                    removed > 1 ? ", ..." : "");
    }
}

/* 1 when `output` was modified no earlier than `input` (both exist). */
static int newer_than(const struct stat *output, const char *input)
{
    struct stat in;
    if (!input || !input[0])
        return 1;
    if (stat(input, &in) != 0)
        return 0; /* a missing input: let the frame run and say so */
    if (output->st_mtim.tv_sec != in.st_mtim.tv_sec)
        return output->st_mtim.tv_sec > in.st_mtim.tv_sec;
    return output->st_mtim.tv_nsec >= in.st_mtim.tv_nsec;
}

int frame_outputs_complete(const cli_options *options, const frame_paths *paths)
{
    const char *outputs[4] = {paths->output, paths->preview, paths->preview_input,
                              paths->focus_map};
    const char *inputs[5] = {paths->input, paths->depth_file, paths->foreground,
                             options->camera_json, options->compare ? paths->compare : NULL};
    int o, i;
    for (o = 0; o < 4; o++) {
        struct stat st;
        if (!outputs[o][0])
            continue;
        if (lstat(outputs[o], &st) != 0 || !S_ISREG(st.st_mode))
            return 0;
        for (i = 0; i < 5; i++)
            if (!newer_than(&st, inputs[i]))
                return 0;
    }
    /* Outputs appear only by renaming a complete temporary file, but a copy or a full disk
     * elsewhere can cut one after its header: the EXR must open and hold every chunk. */
    return exr_file_whole(paths->output);
}
