/* SPDX-License-Identifier: MIT */
/* test_cli_files.c - where the `ddof` command writes and what it leaves: an output that would
 * replace its input, unwritable and non-regular outputs, a closed standard output, an
 * interrupted run.
 *
 *   test_cli_files DDOF_BINARY CASE SCRATCH_DIR
 * CASE: refuse_same unwritable outputs pipe interrupt */
#include "cli_test.h"

#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

static int case_refuse_same(void)
{
    static scene s;
    const char *in = test_path(dir, "in.exr");
    char spelled[4][4096];
    size_t size0 = 0, size1 = 0;
    char *before, *after;
    int k;

    make_scene(&s, 0);
    write_scene(in, &s, 0);
    mkdir(test_path(dir, "sub"), 0777);
    CHECK(symlink("in.exr", test_path(dir, "link.exr")) == 0);
    CHECK(link(in, test_path(dir, "hard.exr")) == 0);
    snprintf(spelled[0], 4096, "%s", in);
    snprintf(spelled[1], 4096, "%s/./in.exr", dir);
    snprintf(spelled[2], 4096, "%s/sub/../in.exr", dir);
    snprintf(spelled[3], 4096, "%s", test_path(dir, "link.exr"));
    before = test_read_file(in, &size0);
    for (k = 0; k < 4; k++) {
        CHECK_MSG(ddof(in, "-o", spelled[k], "--focal-length", "50", "--fstop", "2", "--focus",
                       "3", NULL) == 1, "%s", spelled[k]);
        CHECK(err_contains("refusing") && err_contains("never overwrites its input"));
    }
    /* A hard link is the same file under another name. */
    CHECK(ddof(test_path(dir, "hard.exr"), "-o", in, "--focal-length", "50", "--fstop", "2",
               "--focus", "3", NULL) == 1);
    CHECK(err_contains("refusing"));
    CHECK(ddof(in, "-o", test_path(dir, "ok.exr"), "--preview", in, "--focal-length", "50",
               "--fstop", "2", "--focus", "3", NULL) == 1);
    CHECK(err_contains("refusing to write preview"));
    after = test_read_file(in, &size1);
    CHECK(before && after && size0 == size1 && memcmp(before, after, size0) == 0);
    CHECK(!test_file_exists(test_path(dir, "ok.exr")));
    free(before);
    free(after);

    /* Sequences: the same pattern for input and output. */
    write_scene(test_path(dir, "f_0001.exr"), &s, 0);
    write_scene(test_path(dir, "f_0002.exr"), &s, 0);
    before = test_read_file(test_path(dir, "f_0002.exr"), &size0);
    CHECK(ddof(test_path(dir, "f_####.exr"), "-o", test_path(dir, "f_####.exr"), "--frames",
               "1-2", "--focal-length", "50", "--fstop", "2", "--focus", "3", NULL) == 1);
    CHECK(err_contains("refusing to write output") && err_contains("f_0001.exr"));
    after = test_read_file(test_path(dir, "f_0002.exr"), &size1);
    CHECK(before && after && size0 == size1 && memcmp(before, after, size0) == 0);
    free(before);
    free(after);

    /* Every input of every frame is protected from every output, the camera sidecar and the
     * --stats file included: frame 5's output must not replace frame 1005's input. */
    {
        const char *json = test_path(dir, "camera.json");
        const char *camera =
            "{\"focal_length_mm\": 50, \"sensor_width_mm\": 36, \"sensor_fit\": \"AUTO\","
            " \"fstop\": 2.0, \"focus_distance_m\": 3.0, \"resolution\": [48, 32],"
            " \"pixel_aspect\": 1.0}";
        test_write_file(json, camera, strlen(camera));
        before = test_read_file(json, &size0);
        CHECK(ddof(in, "-o", json, "--camera", json, NULL) == 1);
        CHECK(err_contains("refusing") && err_contains("never overwrites its input"));
        CHECK(ddof(in, "-o", test_path(dir, "s.exr"), "--camera", json, "--stats", json,
                   NULL) == 1);
        CHECK(err_contains("refusing"));
        CHECK(ddof(in, "-o", test_path(dir, "s.exr"), "--camera", json, "--stats", in,
                   NULL) == 1);
        CHECK(ddof(in, "-o", test_path(dir, "s.exr"), "--camera", json, "--stats",
                   test_path(dir, "s.exr"), NULL) == 1);
        CHECK(err_contains("--stats") && err_contains("also an output"));
        after = test_read_file(json, &size1);
        CHECK(before && after && size0 == size1 && memcmp(before, after, size0) == 0);
        free(before);
        free(after);

        write_scene(test_path(dir, "g_0005.exr"), &s, 0);
        write_scene(test_path(dir, "g_1005.exr"), &s, 0);
        before = test_read_file(test_path(dir, "g_1005.exr"), &size0);
        CHECK(ddof(test_path(dir, "g_####.exr"), "-o", test_path(dir, "g_1###.exr"), "--frames",
                   "5,1005", "--camera", json, NULL) == 1);
        CHECK(err_contains("refusing") && err_contains("g_1005.exr"));
        after = test_read_file(test_path(dir, "g_1005.exr"), &size1);
        CHECK(before && after && size0 == size1 && memcmp(before, after, size0) == 0);
        CHECK(!test_file_exists(test_path(dir, "s.exr")));
        free(before);
        free(after);
    }
    CHECK(test_count_suffix(dir, ".tmp") == 0);
    return test_finish("test_cli refuse_same");
}

static int case_unwritable(void)
{
    static scene s;
    const char *in = test_path(dir, "in.exr");
    const char *ro = test_path(dir, "readonly");
    char target[4096], probe[4096];
    FILE *f;

    make_scene(&s, 0);
    write_scene(in, &s, 0);
    mkdir(ro, 0777);
    chmod(ro, 0555);
    /* root writes into a 0555 directory anyway; then use a directory no one can write. */
    snprintf(probe, sizeof probe, "%s/probe", ro);
    f = fopen(probe, "w");
    if (f) {
        fclose(f);
        unlink(probe);
        snprintf(target, sizeof target, "/sys/kernel/ddof-test-out.exr");
        f = fopen(target, "w");
        if (f) {
            fclose(f);
            unlink(target);
            printf("test_cli unwritable: no unwritable directory available here; part skipped\n");
            target[0] = '\0';
        }
    } else {
        snprintf(target, sizeof target, "%s/out.exr", ro);
    }
    if (target[0]) {
        CHECK(ddof(in, "-o", target, "--focal-length", "50", "--fstop", "2", "--focus", "3",
                   NULL) == 1);
        CHECK(err_contains("is not writable"));
        CHECK(!test_file_exists(target));
    }
    chmod(ro, 0777);

    /* Missing directories are created; a directory is not a file name. */
    CHECK(ddof(in, "-o", test_path(dir, "new/deeper/out.exr"), "--focal-length", "50", "--fstop",
               "2", "--focus", "3", NULL) == 0);
    CHECK(test_file_exists(test_path(dir, "new/deeper/out.exr")));
    CHECK(ddof(in, "-o", test_path(dir, "new/"), "--focal-length", "50", "--fstop", "2",
               "--focus", "3", NULL) == 1);
    CHECK(err_contains("names a directory"));
    return test_finish("test_cli unwritable");
}

/* Issue 14: an output path that is not a regular file is refused before the first frame, and
 * never replaced: a FIFO, a symbolic link (not followed), a directory, a device (when the test
 * may make one); for -o, --stats and --preview alike. A failed --stats write is not blamed on
 * the frames. */
static int case_outputs(void)
{
    static scene s;
    const char *in = test_path(dir, "in.exr");
    const char *fifo = test_path(dir, "fifo");
    const char *link = test_path(dir, "link.exr");
    const char *target = test_path(dir, "target.exr");
    const char *folder = test_path(dir, "folder.exr");
    const char *device = test_path(dir, "null");
    struct stat st;
    int k, have_device;
#define CAMERA "--focal-length", "50", "--fstop", "2", "--focus", "3"
    make_scene(&s, 0);
    write_scene(in, &s, 0);
    CHECK(mkfifo(fifo, 0666) == 0);
    CHECK(symlink("target.exr", link) == 0);
    CHECK(mkdir(folder, 0777) == 0);
    /* A character device like /dev/null (1, 3) in the scratch folder, never the real one. */
    have_device = mknod(device, S_IFCHR | 0666, makedev(1, 3)) == 0;
    if (!have_device)
        printf("test_cli outputs: cannot make a device node here (%s); that part skipped\n",
               strerror(errno));

    for (k = 0; k < 3; k++) {
        /* -o, then --stats, then --preview at each non-file. */
        const char *paths[4] = {fifo, link, folder, device};
        const char *kinds[4] = {"it is a FIFO", "it is a symbolic link", "names a directory",
                                "it is a device"};
        int t;
        for (t = 0; t < 4; t++) {
            const char *o = k == 0 ? paths[t] : test_path(dir, "o.exr");
            int rc;
            if (t == 3 && !have_device)
                continue;
            unlink(test_path(dir, "o.exr"));
            if (k == 0)
                rc = ddof(in, "-o", o, CAMERA, NULL);
            else if (k == 1)
                rc = ddof(in, "-o", o, "--stats", paths[t], CAMERA, NULL);
            else
                rc = ddof(in, "-o", o, "--preview", paths[t], CAMERA, NULL);
            CHECK_MSG(rc == 1, "option %d, path %s: exit %d", k, paths[t], rc);
            CHECK_MSG(err_contains(kinds[t]), "option %d, path %s", k, paths[t]);
            /* Before the first frame: nothing was computed or written. */
            CHECK_MSG(!test_file_exists(test_path(dir, "o.exr")), "option %d, path %s", k,
                      paths[t]);
        }
    }
    CHECK(lstat(fifo, &st) == 0 && S_ISFIFO(st.st_mode));
    CHECK(lstat(link, &st) == 0 && S_ISLNK(st.st_mode));
    CHECK(!test_file_exists(target));
    CHECK(lstat(folder, &st) == 0 && S_ISDIR(st.st_mode));
    if (have_device)
        CHECK(lstat(device, &st) == 0 && S_ISCHR(st.st_mode));
    CHECK(test_count_suffix(dir, ".tmp") == 0);

    /* Every frame's outputs are checked up front, not only the first one's. */
    {
        char name[64];
        int f;
        for (f = 1; f <= 3; f++) {
            snprintf(name, sizeof name, "seq_%04d.exr", f);
            write_scene(test_path(dir, name), &s, 0);
        }
        mkdir(test_path(dir, "seqout"), 0777);
        CHECK(mkfifo(test_path(dir, "seqout/o_0003.exr"), 0666) == 0);
        CHECK(ddof(test_path(dir, "seq_####.exr"), "-o", test_path(dir, "seqout/o_####.exr"),
                   "--frames", "1-3", CAMERA, NULL) == 1);
        CHECK(err_contains("o_0003.exr: it is a FIFO"));
        CHECK(!test_file_exists(test_path(dir, "seqout/o_0001.exr")));
    }

    /* A --stats write that fails after the frames: its own message, exit 1, no frame blamed.
     * The directory appears while the frames run (DDOF_TEST_HOLD_TEMP_MS holds the commit). */
    {
        pid_t pid;
        int status = 0;
        const char *late = test_path(dir, "late.json");
        unlink(test_path(dir, "o.exr"));
        fflush(stdout);
        pid = fork();
        if (pid == 0) {
            char *argv[] = {(char *)ddof_bin, (char *)in, "-o", (char *)test_path(dir, "o.exr"),
                            "--stats", (char *)late, CAMERA, NULL};
            FILE *err = freopen(test_path(dir, "run.err"), "w", stderr);
            (void)err;
            setenv("DDOF_TEST_HOLD_TEMP_MS", "1500", 1);
            execv(argv[0], argv);
            _exit(127);
        }
        wait_for_temp(dir);
        CHECK(mkdir(late, 0777) == 0);
        waitpid(pid, &status, 0);
        CHECK_MSG(WIFEXITED(status) && WEXITSTATUS(status) == 1, "status %d", status);
        CHECK(err_contains("--stats: ") && err_contains("names a directory"));
        {
            char *e = err_text();
            CHECK_MSG(strstr(e, "frames failed") == NULL && strstr(e, "failed frame") == NULL,
                      "the frames were blamed: %s", e);
            free(e);
        }
        CHECK(test_file_exists(test_path(dir, "o.exr")));
    }
#undef CAMERA
    return test_finish("test_cli outputs");
}

/* Runs ddof with stdout a pipe whose reading end is already closed (`ddof ... | true`);
 * stderr goes to run.err. Returns the raw wait status. */
static int run_into_closed_pipe(char *const *argv)
{
    int fds[2], status = 0;
    pid_t pid;
    if (pipe(fds) != 0)
        return -1;
    close(fds[0]);
    fflush(stdout);
    pid = fork();
    if (pid == 0) {
        FILE *err = freopen(test_path(dir, "run.err"), "w", stderr);
        (void)err;
        dup2(fds[1], STDOUT_FILENO);
        close(fds[1]);
        execv(argv[0], argv);
        _exit(127);
    }
    close(fds[1]);
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR)
        ;
    return status;
}

/* Issue 14: a closed stdout ends the batch like SIGTERM: a message, the temporary files
 * removed, exit 141, not a silent death by SIGPIPE. */
static int case_pipe(void)
{
    static scene s;
    char name[64];
    int f, status, jobs;
    for (f = 1; f <= 6; f++) {
        snprintf(name, sizeof name, "r_%04d.exr", f);
        make_scene(&s, f);
        write_scene(test_path(dir, name), &s, 0);
    }
    for (jobs = 1; jobs <= 2; jobs++) {
        char *argv[] = {(char *)ddof_bin, (char *)test_path(dir, "r_####.exr"), "-o",
                        (char *)test_path(dir, "o/o_####.exr"), "--frames", "1-6",
                        "--focal-length", "50", "--fstop", "2", "--focus", "3", "--jobs",
                        jobs == 1 ? "1" : "2", NULL};
        status = run_into_closed_pipe(argv);
        CHECK_MSG(WIFEXITED(status) && WEXITSTATUS(status) == 141,
                  "--jobs %d: %s %d", jobs, WIFSIGNALED(status) ? "killed by signal" : "exit",
                  WIFSIGNALED(status) ? WTERMSIG(status) : WEXITSTATUS(status));
        CHECK(err_contains("standard output is closed"));
        CHECK(test_count_suffix(test_path(dir, "o"), ".tmp") == 0);
    }
    /* A SIGPIPE sent to the process is SIGTERM's twin. */
    {
        pid_t pid;
        mkdir(test_path(dir, "out"), 0777);
        fflush(stdout);
        pid = fork();
        if (pid == 0) {
            char *argv[] = {(char *)ddof_bin, (char *)test_path(dir, "r_0001.exr"), "-o",
                            (char *)test_path(dir, "out/out.exr"), "--focal-length", "50",
                            "--fstop", "2", "--focus", "3", NULL};
            FILE *err = freopen(test_path(dir, "run.err"), "w", stderr);
            (void)err;
            setenv("DDOF_TEST_HOLD_TEMP_MS", "30000", 1);
            execv(argv[0], argv);
            _exit(127);
        }
        wait_for_temp(test_path(dir, "out"));
        kill(pid, SIGPIPE);
        waitpid(pid, &status, 0);
        CHECK_MSG(WIFEXITED(status) && WEXITSTATUS(status) == 141, "status %d", status);
        CHECK(err_contains("interrupted by SIGPIPE") && err_contains("removed 1 temporary file"));
        CHECK(test_count_suffix(test_path(dir, "out"), ".tmp") == 0);
    }
    return test_finish("test_cli pipe");
}

/* SIGINT and SIGTERM while a finished temporary file waits for its rename (held there by the
 * DDOF_TEST_HOLD_TEMP_MS hook): the file is removed and the exit status says so. */
static int case_interrupt(void)
{
    static scene s;
    const int sigs[2] = {SIGINT, SIGTERM};
    int k;
    make_scene(&s, 0);
    write_scene(test_path(dir, "in.exr"), &s, 0);
    mkdir(test_path(dir, "out"), 0777);
    for (k = 0; k < 2; k++) {
        pid_t pid;
        int status = 0;
        fflush(stdout);
        pid = fork();
        if (pid == 0) {
            char *argv[] = {(char *)ddof_bin, (char *)test_path(dir, "in.exr"), "-o",
                            (char *)test_path(dir, "out/out.exr"), "--focal-length", "50",
                            "--fstop", "2", "--focus", "3", NULL};
            FILE *err = freopen(test_path(dir, "run.err"), "w", stderr);
            (void)err;
            setenv("DDOF_TEST_HOLD_TEMP_MS", "30000", 1);
            execv(argv[0], argv);
            _exit(127);
        }
        wait_for_temp(test_path(dir, "out"));
        CHECK_MSG(test_count_suffix(test_path(dir, "out"), ".tmp") == 1,
                  "no temporary file appeared");
        kill(pid, sigs[k]);
        waitpid(pid, &status, 0);
        CHECK_MSG(WIFEXITED(status) && WEXITSTATUS(status) == 128 + sigs[k], "status %d",
                  status);
        CHECK(test_count_suffix(test_path(dir, "out"), ".tmp") == 0);
        CHECK(!test_file_exists(test_path(dir, "out/out.exr")));
        CHECK(err_contains("interrupted") && err_contains("removed 1 temporary file"));
    }
    return test_finish("test_cli interrupt");
}

int main(int argc, char **argv)
{
    static const cli_case cases[] = {
        {"refuse_same", case_refuse_same},
        {"unwritable", case_unwritable},
        {"outputs", case_outputs},
        {"pipe", case_pipe},
        {"interrupt", case_interrupt},
    };
    return cli_test_main(argc, argv, "test_cli_files", cases, sizeof cases / sizeof cases[0]);
}
