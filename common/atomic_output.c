/*
 * atomic_output.c: the tools' one way of writing an output file
 * (atomic_output.h says the policy and why).
 */
#define _GNU_SOURCE /* O_TMPFILE, where the C library has it */
#include "atomic_output.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#define SUFFIX ".tmp"

/* Fills why[]; leaves errno = err for atomic_output_check. */
static int say(char *why, const char *path, const char *what, int err)
{
    if (err)
        snprintf(why, ATOMIC_WHY, "%.240s: %.180s: %.80s", path, what, strerror(err));
    else
        snprintf(why, ATOMIC_WHY, "%.240s: %.180s", path, what);
    errno = err;
    return 1;
}

static uint64_t mix64(uint64_t z)
{
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9u;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebu;
    return z ^ (z >> 31);
}

/* A name no other process picks at the same time: the pid keeps
 * concurrent writers apart and lets a later run tell a dead one's leftover
 * (sweep); the random part keeps one process's attempts apart. */
static void temp_name(const atomic_output *o, const char *suffix, char *buf, size_t cap,
                      int attempt)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    uint64_t r = mix64((uint64_t)ts.tv_nsec ^ (uint64_t)ts.tv_sec << 30 ^
                       (uint64_t)(uintptr_t)o ^ (uint64_t)attempt << 48);
    snprintf(buf, cap, "%s/.%s.%ld.%012llx%s", o->dir, o->base, (long)getpid(),
             (unsigned long long)(r & 0xffffffffffffu), suffix);
}

/* Whether `name` is ".<base>.<pid>.<hex>.tmp" of a process that no
 * longer exists. A pid reused since is only a leftover kept. */
static int stale(const char *name, const char *base)
{
    size_t bl = strlen(base);
    if (name[0] != '.' || strncmp(name + 1, base, bl) != 0 || name[1 + bl] != '.')
        return 0;
    const char *p = name + 2 + bl, *q = p;
    while (*q >= '0' && *q <= '9')
        q++;
    if (q == p || q - p > 10 || *q != '.')
        return 0;
    long pid = strtol(p, NULL, 10);
    const char *h = ++q;
    while ((*q >= '0' && *q <= '9') || (*q >= 'a' && *q <= 'f'))
        q++;
    if (q - h != 12 || strcmp(q, SUFFIX) != 0)
        return 0;
    if (pid <= 0 || pid == (long)getpid())
        return 0;
    return kill((pid_t)pid, 0) != 0 && errno == ESRCH;
}

/* Removes the leftovers of earlier writers of OUT that were killed. */
static void sweep(const atomic_output *o)
{
    DIR *d = opendir(o->dir);
    if (!d)
        return;
    struct dirent *e;
    while ((e = readdir(d))) {
        if (!stale(e->d_name, o->base))
            continue;
        size_t n = strlen(o->dir) + strlen(e->d_name) + 2;
        char *p = malloc(n);
        if (p) {
            snprintf(p, n, "%s/%s", o->dir, e->d_name);
            unlink(p);
        }
        free(p);
    }
    closedir(d);
}

/* The common start: OUT split into directory and name, old leftovers
 * swept, SIGXFSZ ignored. */
static int start(atomic_output *o, const char *path, char *why)
{
    memset(o, 0, sizeof *o);
    o->fd = -1;
    const char *slash = strrchr(path, '/');
    size_t dlen = slash ? (size_t)(slash - path) : 1;
    if (slash && dlen == 0)
        dlen = 1; /* "/name": the root directory */
    o->path = strdup(path);
    o->dir = malloc(dlen + 1);
    if (!o->path || !o->dir) {
        atomic_output_discard(o);
        return say(why, path, "cannot write", ENOMEM);
    }
    memcpy(o->dir, slash ? path : ".", dlen);
    o->dir[dlen] = '\0';
    o->base = o->path + (slash ? (size_t)(slash - path) + 1 : 0);
    if (*o->base == '\0' || !strcmp(o->base, ".") || !strcmp(o->base, "..")) {
        atomic_output_discard(o);
        return say(why, path, "not a file name", 0);
    }
    signal(SIGXFSZ, SIG_IGN);
    sweep(o);
    return 0;
}

int atomic_output_open(atomic_output *o, const char *path, char *why)
{
    if (start(o, path, why))
        return 1;
    size_t cap = strlen(o->dir) + strlen(o->base) + 48;
    if (!(o->tmp = malloc(cap))) {
        atomic_output_discard(o);
        return say(why, path, "cannot write", ENOMEM);
    }
    /* opened for reading too: the library's writer maps the file to make
     * its sections in place (hpfc_tree_write_fd) */
#ifdef O_TMPFILE
    /* Unnamed until complete: a kill leaves nothing. Linking it later goes
     * through /proc (linkat's AT_EMPTY_PATH needs a privilege). */
    if (access("/proc/self/fd", X_OK) == 0) {
        o->fd = open(o->dir, O_TMPFILE | O_RDWR | O_CLOEXEC, 0666);
        if (o->fd >= 0) {
            free(o->tmp);
            o->tmp = NULL;
            return 0;
        }
    }
#endif
    /* mode 0666 so that the umask gives OUT its usual permissions, which
     * mkstemp's 0600 would not */
    for (int attempt = 0; attempt < 64 && o->fd < 0; attempt++) {
        temp_name(o, SUFFIX, o->tmp, cap, attempt);
        o->fd = open(o->tmp, O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (o->fd < 0 && errno != EEXIST)
            break;
    }
    if (o->fd < 0) {
        int err = errno;
        char where[180];
        snprintf(where, sizeof where, "cannot create a temporary file in %.120s", o->dir);
        free(o->tmp);
        o->tmp = NULL;
        atomic_output_discard(o);
        return say(why, path, where, err);
    }
    return 0;
}

const char *atomic_output_read_path(const atomic_output *o, char *buf, size_t cap)
{
    if (o->tmp)
        return o->tmp;
    snprintf(buf, cap, "/proc/self/fd/%d", o->fd);
    return buf;
}

FILE *atomic_output_stream(atomic_output *o)
{
    if (!o->fp && o->fd >= 0)
        o->fp = fdopen(o->fd, "wb");
    return o->fp;
}

void atomic_output_discard(atomic_output *o)
{
    if (o->fp)
        fclose(o->fp);
    else if (o->fd >= 0)
        close(o->fd);
    if (o->tmp)
        unlink(o->tmp);
    free(o->tmp);
    free(o->dir);
    free(o->path);
    memset(o, 0, sizeof *o);
    o->fd = -1;
}

/* fsync of a directory makes a rename in it durable. Some file systems
 * refuse it (EINVAL); the rename has happened by then, so only real errors
 * count. */
static int sync_dir(const char *dir)
{
    int fd = open(dir, O_RDONLY | O_CLOEXEC);
    if (fd < 0)
        return errno;
    int err = fsync(fd) ? errno : 0;
    close(fd);
    return err == EINVAL || err == ENOTSUP ? 0 : err;
}

/* Gives the unnamed temporary file its hidden name, now that it is
 * complete. */
static int name_temp(atomic_output *o)
{
    size_t cap = strlen(o->dir) + strlen(o->base) + 48;
    if (!(o->tmp = malloc(cap)))
        return ENOMEM;
    char proc[64];
    snprintf(proc, sizeof proc, "/proc/self/fd/%d", o->fd);
    for (int attempt = 0; attempt < 64; attempt++) {
        temp_name(o, SUFFIX, o->tmp, cap, attempt);
        if (linkat(AT_FDCWD, proc, AT_FDCWD, o->tmp, AT_SYMLINK_FOLLOW) == 0)
            return 0;
        if (errno != EEXIST)
            break;
    }
    int err = errno;
    free(o->tmp);
    o->tmp = NULL;
    return err;
}

static int commit_file(atomic_output *o, char *why)
{
    int err = 0;
    const char *what = "cannot write";
    errno = 0;
    if (o->fp && (fflush(o->fp) != 0 || ferror(o->fp)))
        err = errno ? errno : EIO;
    if (!err && fsync(o->fd) != 0)
        err = errno;
    if (!err && !o->tmp && (err = name_temp(o)) != 0)
        what = "cannot name the temporary file";
    /* close before the rename: NFS reports some write errors only here */
    int closed = o->fp ? fclose(o->fp) : close(o->fd);
    if (closed != 0 && !err)
        err = errno ? errno : EIO;
    o->fp = NULL;
    o->fd = -1;
    if (!err && rename(o->tmp, o->path) != 0)
        what = "cannot replace", err = errno;
    if (err)
        return say(why, o->path, what, err);
    free(o->tmp);
    o->tmp = NULL; /* renamed: nothing to remove any more */
    if ((err = sync_dir(o->dir)))
        return say(why, o->path, "cannot sync its directory", err);
    return 0;
}

int atomic_output_commit(atomic_output *o, char *why)
{
    int r = commit_file(o, why);
    atomic_output_discard(o);
    return r;
}

static int write_all(int fd, const unsigned char *p, size_t size)
{
    while (size > 0) {
        ssize_t n = write(fd, p, size);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            return n < 0 ? errno : EIO;
        p += n;
        size -= (size_t)n;
    }
    return 0;
}

int atomic_output_write(const char *path, const void *data, size_t size, char *why)
{
    atomic_output o;
    if (atomic_output_open(&o, path, why))
        return 1;
    int err = write_all(o.fd, data, size);
    if (err) {
        atomic_output_discard(&o);
        return say(why, path, "cannot write", err);
    }
    return atomic_output_commit(&o, why);
}

int atomic_output_check(const char *path, char *why)
{
    atomic_output o;
    if (atomic_output_open(&o, path, why)) {
        int err = errno;
        return err ? say(why, path, "cannot create", err) : 1;
    }
    atomic_output_discard(&o);
    return 0;
}
