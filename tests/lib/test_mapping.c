/* A file that changes while a program has it open (hpfc.h, "A mapped file
 * must not change under its mapping"): replaced by rename, a mapped handle
 * keeps answering from the old bytes; under HPFC_OPEN_READ a handle owns
 * its copy, so even a file rewritten or truncated in place does not reach
 * it, and pipes open; truncation under a plain mapping faults (checked in
 * a child, as the header says it does). The oracle for "the same answers"
 * is the handle's own answers before the change, and a handle opened on
 * the old bytes kept in memory. */
#include <errno.h>
#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "check.h"
#include "hpfc.h"

static uint8_t *slurp(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    uint8_t *b = malloc(n > 0 ? (size_t)n : 1);
    if (b && fread(b, 1, (size_t)n, f) != (size_t)n) {
        free(b);
        b = NULL;
    }
    fclose(f);
    *size = (size_t)n;
    return b;
}

static int put(const char *path, const uint8_t *b, size_t n)
{
    FILE *f = fopen(path, "wb");
    if (!f)
        return -1;
    int bad = fwrite(b, 1, n, f) != n;
    return fclose(f) || bad ? -1 : 0;
}

/* A digest of what the handle answers: its info and the leaf of every
 * point of a 41 x 41 grid over the domain (and a ring outside it). */
static uint64_t answers(const hpfc_file *f)
{
    hpfc_file_info in;
    hpfc_file_get_info(f, &in);
    uint64_t h = 1469598103934665603u;
#define MIX(v) (h = (h ^ (uint64_t)(v)) * 1099511628211u)
    MIX(in.cols), MIX(in.rows), MIX(in.levels), MIX(in.file_size), MIX(in.section_count);
    MIX(hpfc_file_check_checksums(f, NULL)); /* reads every byte */
    for (int a = -1; a <= 41; a++)
        for (int b = -1; b <= 41; b++) {
            int64_t x = in.x0 + in.width * a / 40, y = in.y0 + in.height * b / 40;
            hpfc_pixel px;
            int st = hpfc_locate(f, x, y, &px);
            MIX(st);
            if (!st)
                MIX(px.depth), MIX(px.path[px.depth].image), MIX(px.path[px.depth].i),
                    MIX(px.path[px.depth].j);
        }
#undef MIX
    return h;
}

typedef struct feeder {
    int fd;
    const uint8_t *b;
    size_t n;
} feeder;

static void *feed(void *arg)
{
    feeder *fe = arg;
    size_t done = 0;
    while (done < fe->n) { /* small writes: the reader meets short reads */
        size_t chunk = fe->n - done < 777 ? fe->n - done : 777;
        ssize_t w = write(fe->fd, fe->b + done, chunk);
        if (w <= 0)
            break;
        done += (size_t)w;
    }
    close(fe->fd);
    return NULL;
}

int main(void)
{
    const char *data = getenv("HPFC_TEST_DATA");
    if (!data)
        data = "tests/data";
    char pa[1024], pb[1024], dir[] = "/tmp/hpfc-mapping.XXXXXX";
    snprintf(pa, sizeof pa, "%s/valid/borders_features.hpfc", data);
    snprintf(pb, sizeof pb, "%s/valid/square_diagonal.hpfc", data);
    size_t na, nb;
    uint8_t *a = slurp(pa, &na), *b = slurp(pb, &nb);
    CHECK(a && b && mkdtemp(dir));
    if (!a || !b)
        return check_report("mapping");
    char path[1100], next[1100];
    snprintf(path, sizeof path, "%s/map.hpfc", dir);
    snprintf(next, sizeof next, "%s/next.hpfc", dir);

    /* the oracles: handles over the bytes kept in memory */
    hpfc_file *ma = NULL, *mb = NULL;
    CHECK_EQ_INT(hpfc_open_memory(a, na, 0, &ma), HPFC_OK);
    CHECK_EQ_INT(hpfc_open_memory(b, nb, 0, &mb), HPFC_OK);
    uint64_t want_a = answers(ma), want_b = answers(mb);
    CHECK(want_a != want_b);

    /* 1. replaced by rename while mapped: the old handle answers A */
    CHECK_EQ_INT(put(path, a, na), 0);
    hpfc_file *mapped = NULL, *copied = NULL;
    CHECK_EQ_INT(hpfc_open(path, 0, &mapped), HPFC_OK);
    CHECK_EQ_INT(hpfc_open(path, HPFC_OPEN_READ, &copied), HPFC_OK);
    CHECK(mapped && copied);
    if (!mapped || !copied)
        return check_report("mapping");
    CHECK(answers(mapped) == want_a);
    CHECK_EQ_INT(put(next, b, nb), 0);
    CHECK_EQ_INT(rename(next, path), 0);
    CHECK(answers(mapped) == want_a);
    CHECK(answers(copied) == want_a);
    hpfc_file *fresh = NULL;
    CHECK_EQ_INT(hpfc_open(path, 0, &fresh), HPFC_OK);
    CHECK(fresh && answers(fresh) == want_b);
    hpfc_close(fresh);
    hpfc_close(mapped);

    /* 2. rewritten and truncated in place: a HPFC_OPEN_READ handle owns
     * its bytes */
    CHECK_EQ_INT(put(path, b, nb / 2), 0);
    CHECK(answers(copied) == want_a);
    CHECK_EQ_INT(truncate(path, 0), 0);
    CHECK(answers(copied) == want_a);
    hpfc_close(copied);
    hpfc_file *none = NULL;
    CHECK_EQ_INT(hpfc_open(path, HPFC_OPEN_READ, &none), HPFC_E_TRUNCATED);
    CHECK(none == NULL);

    /* 3. a pipe: refused mapped (it cannot be), read whole under the flag */
    for (int flags = 0; flags <= (int)HPFC_OPEN_READ; flags += HPFC_OPEN_READ) {
        int p[2];
        CHECK_EQ_INT(pipe(p), 0);
        feeder fe = {p[1], a, na};
        pthread_t t;
        pthread_create(&t, NULL, feed, &fe);
        char fdpath[64];
        snprintf(fdpath, sizeof fdpath, "/dev/fd/%d", p[0]);
        hpfc_file *piped = NULL;
        int st = hpfc_open(fdpath, (unsigned)flags, &piped);
        if (flags) {
            CHECK_EQ_INT(st, HPFC_OK);
            CHECK(piped && answers(piped) == want_a);
        } else {
            CHECK_EQ_INT(st, HPFC_E_IO);
            CHECK(piped == NULL);
            char sink[4096]; /* let the feeder finish */
            while (read(p[0], sink, sizeof sink) > 0)
                ;
        }
        hpfc_close(piped);
        pthread_join(t, NULL);
        close(p[0]);
    }
    /* a directory, under either mode */
    CHECK_EQ_INT(hpfc_open(dir, 0, &none), HPFC_E_IO);
    CHECK_EQ_INT(hpfc_open(dir, HPFC_OPEN_READ, &none), HPFC_E_IO);

    /* 4. truncated in place under a mapping: the read past the new end
     * faults, as the header warns (in a child; ASan turns SIGBUS into an
     * error exit, which counts the same) */
    CHECK_EQ_INT(put(path, a, na), 0);
    fflush(NULL);
    pid_t pid = fork();
    if (pid == 0) {
        hpfc_file *f = NULL;
        if (hpfc_open(path, 0, &f) != HPFC_OK || truncate(path, 0) != 0)
            _exit(3);
        hpfc_file_check_checksums(f, NULL); /* reads every page */
        _exit(0);
    }
    int status = 0;
    CHECK(pid > 0 && waitpid(pid, &status, 0) == pid);
    CHECK(!(WIFEXITED(status) && (WEXITSTATUS(status) == 0 || WEXITSTATUS(status) == 3)));
    printf("truncated under a mapping: %s %d\n", WIFSIGNALED(status) ? "signal" : "exit",
           WIFSIGNALED(status) ? WTERMSIG(status) : WEXITSTATUS(status));

    hpfc_close(ma);
    hpfc_close(mb);
    unlink(path);
    rmdir(dir);
    free(a);
    free(b);
    return check_report("mapping");
}
