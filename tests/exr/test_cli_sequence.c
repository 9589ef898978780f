/* SPDX-License-Identifier: MIT */
/* test_cli_sequence.c - frame sequences through the `ddof` command: the frames of a pattern
 * against the library, and a batch resumed after a stop.
 *
 *   test_cli_sequence DDOF_BINARY CASE SCRATCH_DIR
 * CASE: sequence resume */
#include "cli_test.h"

#include <cJSON.h>

#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

static int case_sequence(void)
{
    static scene s[6];
    static float ref[N * 4];
    char name[64];
    char *text;
    int f, bad;
    reference r;

    memset(&r, 0, sizeof r);
    r.kind = REF_CAMERA;
    r.substeps = 2;
    camera_50mm(&r.camera, 2.0, 3.0);
    for (f = 1; f <= 5; f++) {
        snprintf(name, sizeof name, "in_%04d.exr", f);
        make_scene(&s[f], f);
        write_scene(test_path(dir, name), &s[f], 0);
    }
    /* Frame 3 is cut short, as a render killed while writing would leave it. */
    {
        size_t size = 0;
        char *bytes = test_read_file(test_path(dir, "in_0003.exr"), &size);
        test_write_file(test_path(dir, "in_0003.exr"), bytes, size / 2);
        free(bytes);
    }
    CHECK(ddof(test_path(dir, "in_####.exr"), "-o", test_path(dir, "out/dof_####.exr"),
               "--frames", "1-5", "--focal-length", "50", "--fstop", "2", "--focus", "3",
               "--substeps", "2", "--pixel-type", "float", "--stats",
               test_path(dir, "out/stats.json"), NULL) == 1);
    CHECK(err_contains("frame 3: FAILED") && err_contains("truncated"));
    CHECK(err_contains("1 of 5 frames failed") && err_contains("failed frame: 3\n"));
    CHECK(out_contains("frame 1: ") && out_contains("frame 5: "));
    {
        char *e = err_text();
        CHECK_MSG(strchr(e, '\r') == NULL, "a progress bar was drawn into a pipe");
        free(e);
    }
    for (f = 1; f <= 5; f++) {
        snprintf(name, sizeof name, "out/dof_%04d.exr", f);
        if (f == 3) {
            CHECK(!test_file_exists(test_path(dir, name)));
            continue;
        }
        library_result(&s[f], &r, ref, NULL);
        bad = compare_output(test_path(dir, name), ref, 1, 0.0, 0);
        CHECK_MSG(bad == 0, "frame %d: %d values differ", f, bad);
    }
    CHECK(test_count_suffix(test_path(dir, "out"), ".tmp") == 0);
    text = test_read_file(test_path(dir, "out/stats.json"), NULL);
    CHECK(text != NULL);
    if (text) {
        cJSON *root = cJSON_Parse(text);
        const cJSON *frames = cJSON_GetObjectItem(root, "frames");
        CHECK(cJSON_GetArraySize(frames) == 5);
        for (f = 0; f < 5; f++) {
            const cJSON *fr = cJSON_GetArrayItem(frames, f);
            CHECK(cJSON_GetObjectItem(fr, "frame")->valuedouble == f + 1);
            CHECK(strcmp(cJSON_GetObjectItem(fr, "status")->valuestring,
                         f == 2 ? "failed" : "ok") == 0);
        }
        CHECK(cJSON_GetObjectItem(cJSON_GetObjectItem(root, "summary"), "failed")->valuedouble ==
              1.0);
        cJSON_Delete(root);
        free(text);
    }

    /* The good frames alone, one at a time, with the bar forced on. */
    CHECK(ddof(test_path(dir, "in_####.exr"), "-o", test_path(dir, "out2/dof_####.exr"),
               "--frames", "1-2,4-5", "--focal-length", "50", "--fstop", "2", "--focus", "3",
               "--jobs", "1", "--progress", "always", NULL) == 0);
    CHECK(out_contains("4 frames written") && out_contains("1 at a time"));
    CHECK(err_contains("\r") && err_contains("4/4 frames"));
    CHECK(test_file_exists(test_path(dir, "out2/dof_0005.exr")));
    return test_finish("test_cli sequence");
}

/* Issue 14: a batch killed with SIGKILL leaves a temporary file; the next run removes it (its
 * process is gone) and, with --skip-existing, redoes only the frames that are missing or
 * older than their inputs. */
static int case_resume(void)
{
    static scene s;
    char name[64];
    const char *out = test_path(dir, "out");
    struct stat before, after;
    int f;
    pid_t pid;
    int status = 0;
#define SEQ test_path(dir, "in_####.exr"), "-o", test_path(dir, "out/o_####.exr"), "--frames", \
            "1-4", "--focal-length", "50", "--fstop", "2", "--focus", "3", "--jobs", "1"
    for (f = 1; f <= 4; f++) {
        snprintf(name, sizeof name, "in_%04d.exr", f);
        make_scene(&s, f);
        write_scene(test_path(dir, name), &s, 0);
    }
    mkdir(out, 0777);
    /* Frames 1 and 2 done, then SIGKILL while frame 3's file waits for its rename. */
    CHECK(ddof(test_path(dir, "in_####.exr"), "-o", test_path(dir, "out/o_####.exr"),
               "--frames", "1-2", "--focal-length", "50", "--fstop", "2", "--focus", "3",
               NULL) == 0);
    fflush(stdout);
    pid = fork();
    if (pid == 0) {
        char *argv[] = {(char *)ddof_bin, (char *)test_path(dir, "in_0003.exr"), "-o",
                        (char *)test_path(dir, "out/o_0003.exr"), "--focal-length", "50",
                        "--fstop", "2", "--focus", "3", NULL};
        FILE *err = freopen(test_path(dir, "run.err"), "w", stderr);
        (void)err;
        setenv("DDOF_TEST_HOLD_TEMP_MS", "30000", 1);
        execv(argv[0], argv);
        _exit(127);
    }
    wait_for_temp(out);
    kill(pid, SIGKILL);
    waitpid(pid, &status, 0);
    CHECK(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);
    CHECK_MSG(test_count_suffix(out, ".tmp") == 1, "SIGKILL should leave the temporary file");
    CHECK(!test_file_exists(test_path(dir, "out/o_0003.exr")));

    /* Frame 2's input changes after its output was written: redone; frame 1: skipped. */
    CHECK(stat(test_path(dir, "out/o_0001.exr"), &before) == 0);
    {
        struct timespec ts = {0, 20 * 1000000L};
        nanosleep(&ts, NULL);
        make_scene(&s, 7);
        write_scene(test_path(dir, "in_0002.exr"), &s, 0);
    }
    CHECK(ddof(SEQ, "--skip-existing", "--stats", test_path(dir, "stats.json"), NULL) == 0);
    CHECK(err_contains("removed 1 temporary file left by an earlier run"));
    CHECK(test_count_suffix(out, ".tmp") == 0);
    CHECK(out_contains("frame 1: ") && out_contains("skipped: complete and newer"));
    CHECK(out_contains("3 frames written, 1 skipped"));
    CHECK(stat(test_path(dir, "out/o_0001.exr"), &after) == 0);
    CHECK_MSG(before.st_mtim.tv_sec == after.st_mtim.tv_sec &&
                  before.st_mtim.tv_nsec == after.st_mtim.tv_nsec && before.st_ino == after.st_ino,
              "frame 1 was rewritten");
    for (f = 2; f <= 4; f++) {
        snprintf(name, sizeof name, "out/o_%04d.exr", f);
        CHECK_MSG(test_file_exists(test_path(dir, name)), "%s", name);
    }
    {
        char *status_text = NULL;
        char *text = test_read_file(test_path(dir, "stats.json"), NULL);
        cJSON *root = text ? cJSON_Parse(text) : NULL;
        const cJSON *frames = cJSON_GetObjectItem(root, "frames");
        status_text = cJSON_GetStringValue(cJSON_GetObjectItem(cJSON_GetArrayItem(frames, 0),
                                                               "status"));
        CHECK(status_text && !strcmp(status_text, "skipped"));
        status_text = cJSON_GetStringValue(cJSON_GetObjectItem(cJSON_GetArrayItem(frames, 1),
                                                               "status"));
        CHECK(status_text && !strcmp(status_text, "ok"));
        cJSON_Delete(root);
        free(text);
    }
    /* A not-EXR at an output path is not "complete": redone. */
    test_write_file(test_path(dir, "out/o_0004.exr"), "junk", 4);
    CHECK(ddof(SEQ, "--skip-existing", NULL) == 0);
    CHECK(out_contains("1 frame written, 3 skipped"));
    /* A live process's temporary file is left alone (PID 1 always exists). */
    test_write_file(test_path(dir, "out/.o_0001.exr.ddof-1-1.tmp"), "", 0);
    CHECK(ddof(SEQ, "--skip-existing", NULL) == 0);
    CHECK(test_file_exists(test_path(dir, "out/.o_0001.exr.ddof-1-1.tmp")));
    unlink(test_path(dir, "out/.o_0001.exr.ddof-1-1.tmp"));
#undef SEQ
    return test_finish("test_cli resume");
}

int main(int argc, char **argv)
{
    static const cli_case cases[] = {
        {"sequence", case_sequence},
        {"resume", case_resume},
    };
    return cli_test_main(argc, argv, "test_cli_sequence", cases, sizeof cases / sizeof cases[0]);
}
