/* SPDX-License-Identifier: MIT */
/* output_file.c - temporary file + rename, the clean-up thread for signals, an output path's
 * type, stale temporary files. */
#include "output_file.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <pthread.h>
#include <signal.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

/* ---- registry of live temporary files --------------------------------------------------- */

typedef struct registry_entry {
    char *path;
    struct registry_entry *next;
} registry_entry;

static pthread_mutex_t registry_lock = PTHREAD_MUTEX_INITIALIZER;
static registry_entry *registry;
static unsigned long temp_counter;
static pthread_t signal_thread;
static int signal_thread_running;

/* Called with registry_lock held. */
static int registry_add(const char *path)
{
    registry_entry *e = malloc(sizeof *e);
    if (!e)
        return -1;
    e->path = strdup(path);
    if (!e->path) {
        free(e);
        return -1;
    }
    e->next = registry;
    registry = e;
    return 0;
}

/* Called with registry_lock held. */
static void registry_remove(const char *path)
{
    registry_entry **p;
    for (p = &registry; *p; p = &(*p)->next) {
        if (strcmp((*p)->path, path) == 0) {
            registry_entry *dead = *p;
            *p = dead->next;
            free(dead->path);
            free(dead);
            return;
        }
    }
}

static const char *signal_name(int sig)
{
    switch (sig) {
    case SIGINT: return "SIGINT";
    case SIGTERM: return "SIGTERM";
    case SIGHUP: return "SIGHUP";
    default: return "SIGPIPE";
    }
}

/* Removes every registered temporary file, says why on stderr (the signal, or the closed
 * `stream`) and exits with 128 + sig. The lock is kept until _exit: no worker can create or
 * rename a temporary file now. The caller must not hold registry_lock. */
static void clean_up_and_exit(int sig, const char *stream)
{
    registry_entry *e;
    char message[256];
    int removed = 0;
    int n;

    pthread_mutex_lock(&registry_lock);
    for (e = registry; e; e = e->next)
        if (unlink(e->path) == 0)
            removed++;
    if (stream)
        n = snprintf(message, sizeof message, "\nddof: %s is closed (broken pipe), stopping: "
                     "removed %d temporary file%s; no output was half-written\n", stream,
                     removed, removed == 1 ? "" : "s");
    else
        n = snprintf(message, sizeof message, "\nddof: interrupted by %s: removed %d temporary "
                     "file%s; no output was half-written\n", signal_name(sig), removed,
                     removed == 1 ? "" : "s");
    if (n > 0 && write(STDERR_FILENO, message, (size_t)n) < 0) {
        /* nothing more to say */
    }
    _exit(128 + sig);
}

/* What the clean-up thread waits for, and where sigwait puts the signal. Not on that thread's
 * stack: the thread is cancelled inside sigwait at a normal exit, and AddressSanitizer's
 * thread teardown then trips over the poisoned redzones of an address-taken local. */
typedef struct signal_wait {
    sigset_t set;
    int sig;
} signal_wait;

static void *signal_main(void *arg)
{
    signal_wait *w = arg;
    while (sigwait(&w->set, &w->sig) != 0)
        ;
    clean_up_and_exit(w->sig, NULL);
    return NULL;
}

void output_broken_pipe(const char *stream)
{
    clean_up_and_exit(SIGPIPE, stream);
}

int output_signals_install(void)
{
    static signal_wait waiting;
    sigset_t *set = &waiting.set;
    sigemptyset(set);
    sigaddset(set, SIGINT);
    sigaddset(set, SIGTERM);
    sigaddset(set, SIGHUP);
    /* A write to a closed pipe raises SIGPIPE in the writing thread, which sigwait in another
     * thread never sees: blocked, it turns into EPIPE, and progress_print stops the run through
     * output_broken_pipe. A SIGPIPE sent to the process is taken like SIGTERM. */
    sigaddset(set, SIGPIPE);
    if (pthread_sigmask(SIG_BLOCK, set, NULL) != 0)
        return -1;
    if (pthread_create(&signal_thread, NULL, signal_main, &waiting) != 0)
        return -1;
    signal_thread_running = 1;
    return 0;
}

void output_signals_shutdown(void)
{
    if (signal_thread_running) {
        /* sigwait is a cancellation point. */
        pthread_cancel(signal_thread);
        pthread_join(signal_thread, NULL);
        signal_thread_running = 0;
    }
}

/* ---- paths ------------------------------------------------------------------------------ */

/* Directory part of `path` ("." when it has none), newly allocated. */
static char *directory_of(const char *path)
{
    const char *slash = strrchr(path, '/');
    char *dir;
    if (!slash)
        return strdup(".");
    if (slash == path)
        return strdup("/");
    dir = malloc((size_t)(slash - path) + 1);
    if (dir) {
        memcpy(dir, path, (size_t)(slash - path));
        dir[slash - path] = '\0';
    }
    return dir;
}

/* mkdir -p */
static int make_directories(const char *dir)
{
    char *copy = strdup(dir);
    char *p;
    int rc = 0;
    if (!copy)
        return -1;
    for (p = copy + 1; *p; p++) {
        if (*p == '/' && p[-1] != '/') {
            *p = '\0';
            if (mkdir(copy, 0777) != 0 && errno != EEXIST)
                rc = -1;
            *p = '/';
        }
    }
    if (mkdir(copy, 0777) != 0 && errno != EEXIST)
        rc = -1;
    free(copy);
    return rc;
}

static void describe_create_error(int e, const char *dir, char *error, size_t error_size)
{
    if (e == EACCES || e == EPERM || e == EROFS)
        snprintf(error, error_size, "output directory '%s' is not writable: %s", dir,
                 strerror(e));
    else if (e == ENOENT || e == ENOTDIR)
        snprintf(error, error_size, "output directory '%s' does not exist and cannot be "
                 "created: %s", dir, strerror(e));
    else
        snprintf(error, error_size, "cannot create a file in output directory '%s': %s", dir,
                 strerror(e));
}

int output_file_begin(output_file *file, const char *path, char *error, size_t error_size)
{
    const char *base = strrchr(path, '/');
    char *dir;
    size_t size;
    int fd, e;

    memset(file, 0, sizeof *file);
    file->fd = -1;
    base = base ? base + 1 : path;
    if (!*base) {
        snprintf(error, error_size, "output path '%s' names a directory, not a file", path);
        return -1;
    }
    if (output_check_target(path, error, error_size) != 0)
        return -1;
    dir = directory_of(path);
    if (!dir) {
        snprintf(error, error_size, "out of memory");
        return -1;
    }
    (void)make_directories(dir); /* failures show up as the create error below */
    size = strlen(path) + 64;
    file->final_path = strdup(path);
    file->temp_path = malloc(size);
    if (!file->final_path || !file->temp_path) {
        snprintf(error, error_size, "out of memory");
        free(dir);
        output_file_abort(file);
        return -1;
    }

    pthread_mutex_lock(&registry_lock);
    snprintf(file->temp_path, size, "%.*s.%s.ddof-%ld-%lu.tmp", (int)(base - path), path, base,
             (long)getpid(), ++temp_counter);
    fd = open(file->temp_path, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    e = errno;
    if (fd >= 0 && registry_add(file->temp_path) != 0) {
        close(fd);
        unlink(file->temp_path);
        fd = -1;
        e = ENOMEM;
    }
    pthread_mutex_unlock(&registry_lock);

    if (fd < 0) {
        describe_create_error(e, dir, error, error_size);
        free(dir);
        free(file->temp_path);
        file->temp_path = NULL; /* nothing to remove */
        output_file_abort(file);
        return -1;
    }
    free(dir);
    file->fd = fd;
    return 0;
}

FILE *output_file_stream(output_file *file)
{
    if (!file->stream && file->fd >= 0)
        file->stream = fdopen(file->fd, "wb");
    return file->stream;
}

/* Test hook: DDOF_TEST_HOLD_TEMP_MS=N makes every commit wait N ms with its temporary file
 * complete but not yet renamed, so that a test can deliver SIGINT at exactly that moment and
 * check that the file is removed. Unset (always, outside tests) it costs one getenv. */
static void test_hold(void)
{
    const char *hold = getenv("DDOF_TEST_HOLD_TEMP_MS");
    long ms = hold ? strtol(hold, NULL, 10) : 0;
    if (ms > 0 && ms < 60000) {
        struct timespec ts;
        ts.tv_sec = ms / 1000;
        ts.tv_nsec = (ms % 1000) * 1000000L;
        while (nanosleep(&ts, &ts) != 0 && errno == EINTR)
            ;
    }
}

/* The file is done with (renamed or removed): its paths freed, the struct back to empty. */
static void forget(output_file *file)
{
    free(file->temp_path);
    free(file->final_path);
    memset(file, 0, sizeof *file);
    file->fd = -1;
}

int output_file_commit(output_file *file, char *error, size_t error_size)
{
    int ok = 1;
    int e = 0;
    if (file->stream) {
        if (fflush(file->stream) != 0 || fsync(fileno(file->stream)) != 0) {
            ok = 0;
            e = errno;
        }
        if (fclose(file->stream) != 0 && ok) {
            ok = 0;
            e = errno;
        }
        file->stream = NULL;
        file->fd = -1;
    } else if (file->fd >= 0) {
        if (fsync(file->fd) != 0) {
            ok = 0;
            e = errno;
        }
        if (close(file->fd) != 0 && ok) {
            ok = 0;
            e = errno;
        }
        file->fd = -1;
    }
    if (!ok) {
        snprintf(error, error_size, "cannot write %s: %s", file->final_path, strerror(e));
        output_file_abort(file);
        return -1;
    }
    test_hold();
    pthread_mutex_lock(&registry_lock);
    if (rename(file->temp_path, file->final_path) != 0) {
        e = errno;
        pthread_mutex_unlock(&registry_lock);
        snprintf(error, error_size, "cannot rename %s to %s: %s", file->temp_path,
                 file->final_path, strerror(e));
        output_file_abort(file);
        return -1;
    }
    registry_remove(file->temp_path);
    pthread_mutex_unlock(&registry_lock);
    forget(file);
    return 0;
}

void output_file_abort(output_file *file)
{
    if (file->stream)
        fclose(file->stream);
    else if (file->fd >= 0)
        close(file->fd);
    if (file->temp_path) {
        pthread_mutex_lock(&registry_lock);
        unlink(file->temp_path);
        registry_remove(file->temp_path);
        pthread_mutex_unlock(&registry_lock);
    }
    forget(file);
}

int output_check_directory(const char *path, char *error, size_t error_size)
{
    output_file probe;
    if (output_file_begin(&probe, path, error, error_size) != 0)
        return -1;
    output_file_abort(&probe);
    return 0;
}

int output_check_target(const char *path, char *error, size_t error_size)
{
    struct stat st;
    const char *what;
    if (lstat(path, &st) != 0)
        return 0; /* a new path (or one begin reports a clearer error for) */
    if (S_ISREG(st.st_mode))
        return 0;
    if (S_ISLNK(st.st_mode)) {
        snprintf(error, error_size, "refusing to write %s: it is a symbolic link, and ddof does "
                 "not follow links (the rename would replace the link, not write its target); "
                 "give the target's path", path);
        return -1;
    }
    if (S_ISDIR(st.st_mode)) {
        snprintf(error, error_size, "output path '%s' names a directory, not a file", path);
        return -1;
    }
    what = S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode) ? "a device"
           : S_ISFIFO(st.st_mode)                      ? "a FIFO"
           : S_ISSOCK(st.st_mode)                      ? "a socket"
                                                       : "not a regular file";
    snprintf(error, error_size, "refusing to write %s: it is %s; ddof writes only regular files "
             "(the rename would replace it)", path, what);
    return -1;
}

/* The PID of a temporary file name ".NAME.ddof-PID-N.tmp", or 0 when it is not one. */
static long temp_file_pid(const char *name)
{
    const char *tag = NULL, *p;
    char *end;
    long pid;
    size_t n = strlen(name);
    if (name[0] != '.' || n < 12 || strcmp(name + n - 4, ".tmp") != 0)
        return 0;
    for (p = strstr(name, ".ddof-"); p; p = strstr(p + 1, ".ddof-"))
        tag = p;
    if (!tag || tag == name)
        return 0;
    p = tag + 6;
    if (*p < '0' || *p > '9')
        return 0;
    pid = strtol(p, &end, 10);
    if (*end != '-' || end[1] < '0' || end[1] > '9')
        return 0;
    (void)strtoul(end + 1, &end, 10);
    return strcmp(end, ".tmp") == 0 && pid > 0 ? pid : 0;
}

int output_remove_stale_temps(const char *path, char *note, size_t note_size)
{
    char *dir = directory_of(path);
    DIR *d;
    struct dirent *entry;
    const long self = (long)getpid();
    int removed = 0;
    note[0] = '\0';
    if (!dir)
        return 0;
    d = opendir(dir);
    if (!d) {
        free(dir);
        return 0; /* a directory still to be made holds nothing stale */
    }
    while ((entry = readdir(d)) != NULL) {
        const long pid = temp_file_pid(entry->d_name);
        size_t size;
        char *full;
        /* Only a process that no longer exists: a live one (another ddof writing into the same
         * directory) still owns its file. */
        if (pid == 0 || pid == self || (pid_t)pid != pid || kill((pid_t)pid, 0) == 0 ||
            errno != ESRCH)
            continue;
        size = strlen(dir) + strlen(entry->d_name) + 2;
        full = malloc(size);
        if (!full)
            break;
        snprintf(full, size, "%s/%s", dir, entry->d_name);
        if (unlink(full) == 0) {
            if (removed == 0)
                snprintf(note, note_size, "%s", full);
            removed++;
        }
        free(full);
    }
    closedir(d);
    free(dir);
    return removed;
}
