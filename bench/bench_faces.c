/*
 * bench_faces: the faces of a file numbered on 1, 2, 4 and 8 threads
 * (hpfc_faces_build_threads), in alternated rounds. Each line: the thread
 * count, the best and median wall time over the rounds, the speed-up of
 * the medians over one thread, and the face count (which must be the same
 * on every line; the run fails otherwise).
 *
 * Usage: bench_faces FILE.hpfc [ROUNDS [MOST_THREADS]]
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "hpfc.h"

enum { COUNTS = 4 };

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int by_value(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: bench_faces FILE.hpfc [ROUNDS [MOST_THREADS]]\n");
        return 2;
    }
    int rounds = argc > 2 ? atoi(argv[2]) : 3;
    unsigned most = argc > 3 ? (unsigned)atoi(argv[3]) : 8;
    static const unsigned counts[COUNTS] = {1, 2, 4, 8};
    if (rounds < 1 || rounds > 100)
        return 2;
    hpfc_file *f = NULL;
    int st = hpfc_open(argv[1], 0, &f);
    if (st) {
        fprintf(stderr, "bench_faces: %s: %s\n", argv[1], hpfc_strerror(st));
        return 1;
    }
    double times[COUNTS][100];
    uint64_t faces[COUNTS] = {0};
    for (int r = 0; r < rounds; r++)
        for (int c = 0; c < COUNTS && counts[c] <= most; c++) {
            hpfc_faces *fc = NULL;
            double t0 = now();
            st = hpfc_faces_build_threads(f, counts[c], &fc);
            times[c][r] = now() - t0;
            if (st) {
                fprintf(stderr, "bench_faces: %s\n", hpfc_strerror(st));
                return 1;
            }
            faces[c] = hpfc_faces_face_count(fc);
            hpfc_faces_free(fc);
        }
    double base = 0;
    printf("%-8s %9s %9s %8s %10s\n", "threads", "best_s", "median_s", "speedup", "faces");
    for (int c = 0; c < COUNTS && counts[c] <= most; c++) {
        qsort(times[c], (size_t)rounds, sizeof(double), by_value);
        double median = times[c][rounds / 2];
        if (c == 0)
            base = median;
        printf("%-8u %9.3f %9.3f %7.2fx %10llu\n", counts[c], times[c][0], median, base / median,
               (unsigned long long)faces[c]);
        if (faces[c] != faces[0]) {
            fprintf(stderr, "bench_faces: %u threads give another face count\n", counts[c]);
            return 1;
        }
    }
    hpfc_close(f);
    return 0;
}
