/*
 * replay.c: a main() for the harnesses when they are built without libFuzzer
 * (gcc, the ordinary test build). Runs the harness's LLVMFuzzerTestOneInput
 * once per file named on the command line; a directory stands for every
 * regular file in it (not recursive, in name order, so runs are
 * reproducible). Each input is handed over in a malloc'ed buffer of exactly
 * its size, as libFuzzer does, so AddressSanitizer sees any read past it.
 *
 *   replay_open_buffer fuzz/corpus/open_buffer tests/data/valid crash-1234
 *
 * Exit status: 0 when every input ran (a harness reports a finding by
 * crashing or aborting, never by a return value); 1 when an argument cannot
 * be read or no input was found at all, so an empty or misspelt corpus
 * fails the test instead of passing vacuously.
 */
#include <dirent.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static int read_file(const char *path, uint8_t **out, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return -1;
    size_t cap = 4096, n = 0;
    uint8_t *buf = malloc(cap);
    for (size_t got; buf && (got = fread(buf + n, 1, cap - n, f)) > 0;) {
        n += got;
        if (n == cap) {
            uint8_t *bigger = realloc(buf, cap *= 2);
            if (!bigger)
                free(buf);
            buf = bigger;
        }
    }
    int err = ferror(f) || !buf;
    fclose(f);
    if (err) {
        free(buf);
        return -1;
    }
    /* an exact-size copy: no slack after the last byte */
    *out = malloc(n ? n : 1);
    if (!*out) {
        free(buf);
        return -1;
    }
    memcpy(*out, buf, n);
    free(buf);
    *size = n;
    return 0;
}

static int run_file(const char *path, long *count)
{
    uint8_t *data;
    size_t size;
    if (read_file(path, &data, &size)) {
        fprintf(stderr, "replay: cannot read %s\n", path);
        return -1;
    }
    LLVMFuzzerTestOneInput(data, size);
    free(data);
    (*count)++;
    return 0;
}

static int cmp_names(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

static int run_dir(const char *dir, long *count)
{
    DIR *d = opendir(dir);
    if (!d) {
        fprintf(stderr, "replay: cannot open %s\n", dir);
        return -1;
    }
    size_t n = 0, cap = 64;
    char **names = malloc(cap * sizeof *names);
    int st = names ? 0 : -1;
    for (struct dirent *de; !st && (de = readdir(d));) {
        if (de->d_name[0] == '.')
            continue;
        size_t len = strlen(dir) + strlen(de->d_name) + 2;
        char *path = malloc(len);
        struct stat sb;
        if (!path) {
            st = -1;
            break;
        }
        snprintf(path, len, "%s/%s", dir, de->d_name);
        if (stat(path, &sb) || !S_ISREG(sb.st_mode)) {
            free(path);
            continue;
        }
        if (n == cap) {
            char **bigger = realloc(names, (cap *= 2) * sizeof *names);
            if (!bigger) {
                free(path);
                st = -1;
                break;
            }
            names = bigger;
        }
        names[n++] = path;
    }
    closedir(d);
    if (!st)
        qsort(names, n, sizeof *names, cmp_names);
    for (size_t k = 0; k < n; k++) {
        if (!st)
            st = run_file(names[k], count);
        free(names[k]);
    }
    free(names);
    return st;
}

int main(int argc, char **argv)
{
    long count = 0;
    int st = 0;
    for (int a = 1; a < argc && !st; a++) {
        struct stat sb;
        if (stat(argv[a], &sb)) {
            fprintf(stderr, "replay: no such file or directory: %s\n", argv[a]);
            st = -1;
        } else if (S_ISDIR(sb.st_mode)) {
            st = run_dir(argv[a], &count);
        } else {
            st = run_file(argv[a], &count);
        }
    }
    if (!st && count == 0) {
        fprintf(stderr, "replay: no input files\n");
        st = -1;
    }
    printf("replay: %ld inputs\n", count);
    return st ? EXIT_FAILURE : EXIT_SUCCESS;
}
