/*
 * FILE read once, mapped or into memory (open_input.h).
 */
#include "open_input.h"

#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

const char *input_path(const char *file)
{
    return strcmp(file, "-") == 0 ? "/dev/stdin" : file;
}

/* Only a regular file can be mapped; a directory is refused as such. */
static int must_read(const struct stat *sb)
{
    return !S_ISREG(sb->st_mode) && !S_ISDIR(sb->st_mode);
}

int open_input(const char *file, hpfc_file **f)
{
    struct stat sb;
    const char *p = input_path(file);
    int read = stat(p, &sb) == 0 && must_read(&sb);
    return hpfc_open(p, read ? HPFC_OPEN_READ : 0, f);
}

/* fd to its end into b->owned (a pipe's size is not known before). */
static int read_all(int fd, input_bytes *b, int *err)
{
    size_t cap = 65536;
    for (;;) {
        if (!b->owned || b->size == cap) {
            size_t grown = !b->owned ? cap : cap > SIZE_MAX / 2 ? SIZE_MAX : cap * 2;
            uint8_t *p = grown > b->size ? realloc(b->owned, grown) : NULL;
            if (!p) {
                *err = ENOMEM;
                return HPFC_E_NOMEM;
            }
            b->owned = p, cap = grown;
        }
        ssize_t n = read(fd, b->owned + b->size, cap - b->size);
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0) {
            *err = errno;
            return HPFC_E_IO;
        }
        if (n == 0)
            break;
        b->size += (size_t)n;
    }
    b->data = b->owned;
    return HPFC_OK;
}

/* A regular file's bytes through a private read-only mapping. */
static int map_all(int fd, const struct stat *sb, input_bytes *b, int *err)
{
    static const uint8_t empty[1];
    if ((uint64_t)sb->st_size > SIZE_MAX) {
        *err = EFBIG;
        return HPFC_E_IO;
    }
    b->size = (size_t)sb->st_size;
    b->data = empty; /* mmap refuses an empty mapping; the verdict is the same */
    if (!b->size)
        return HPFC_OK;
    void *m = mmap(NULL, b->size, PROT_READ, MAP_PRIVATE, fd, 0);
    if (m == MAP_FAILED) {
        *err = errno;
        b->size = 0;
        return *err == ENOMEM ? HPFC_E_NOMEM : HPFC_E_IO;
    }
    b->map = m;
    b->data = m;
    return HPFC_OK;
}

int input_load(const char *file, input_bytes *b, int *err)
{
    memset(b, 0, sizeof *b);
    *err = 0;
    int fd = open(input_path(file), O_RDONLY | O_CLOEXEC);
    if (fd < 0) {
        *err = errno;
        return errno == ENOMEM ? HPFC_E_NOMEM : HPFC_E_IO;
    }
    struct stat sb;
    int st;
    if (fstat(fd, &sb) != 0) {
        *err = errno;
        st = HPFC_E_IO;
    } else if (S_ISDIR(sb.st_mode)) {
        *err = EISDIR;
        st = HPFC_E_IO;
    } else {
        st = must_read(&sb) ? read_all(fd, b, err) : map_all(fd, &sb, b, err);
    }
    close(fd);
    return st;
}

void input_unload(input_bytes *b)
{
    if (b->map)
        munmap(b->map, b->size);
    free(b->owned);
    memset(b, 0, sizeof *b);
}
