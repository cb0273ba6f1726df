/*
 * bench_build_threads: a .pfc map built (hpfc_build: validation, then the
 * levels) on 1, 2, 4 and 8 threads (hpfc_build_params.threads), in
 * alternated rounds. Each line: the thread count, the best and median
 * wall time over the rounds, the median CPU time of the process over the
 * build, the speed-up of the medians over one thread, and the tree's
 * pixel count (which must be the same on every line; the run fails
 * otherwise; tests/lib/test_build_threads.c checks the trees array for
 * array).
 *
 * Usage: bench_build_threads FILE.pfc [ROUNDS [MOST_THREADS]]
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "hpfc.h"

enum { COUNTS = 4, MOST_ROUNDS = 100 };

static double clock_seconds(clockid_t which)
{
    struct timespec t;
    clock_gettime(which, &t);
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
        fprintf(stderr, "usage: bench_build_threads FILE.pfc [ROUNDS [MOST_THREADS]]\n");
        return 2;
    }
    int rounds = argc > 2 ? atoi(argv[2]) : 3;
    unsigned most = argc > 3 ? (unsigned)atoi(argv[3]) : 8;
    static const unsigned counts[COUNTS] = {1, 2, 4, 8};
    if (rounds < 1 || rounds > MOST_ROUNDS)
        return 2;
    hpfc_graph *g = NULL;
    hpfc_diag diag;
    if (hpfc_pfc_read_file(argv[1], &g, &diag)) {
        fprintf(stderr, "bench_build_threads: %s: %s\n", argv[1], diag.message);
        return 1;
    }
    static double wall[COUNTS][MOST_ROUNDS], cpu[COUNTS][MOST_ROUNDS];
    uint64_t pixels[COUNTS] = {0};
    for (int r = 0; r < rounds; r++)
        for (int c = 0; c < COUNTS && counts[c] <= most; c++) {
            hpfc_build_params p;
            hpfc_build_params_default(&p);
            p.threads = counts[c];
            hpfc_tree *t = NULL;
            double t0 = clock_seconds(CLOCK_MONOTONIC), c0 = clock_seconds(CLOCK_PROCESS_CPUTIME_ID);
            int st = hpfc_build(g, &p, &t, &diag);
            wall[c][r] = clock_seconds(CLOCK_MONOTONIC) - t0;
            cpu[c][r] = clock_seconds(CLOCK_PROCESS_CPUTIME_ID) - c0;
            if (st) {
                fprintf(stderr, "bench_build_threads: %s\n", diag.message);
                return 1;
            }
            hpfc_tree_info info;
            hpfc_tree_get_info(t, &info);
            pixels[c] = info.word_pixels + info.refined_pixels;
            hpfc_tree_free(t);
        }
    double base = 0;
    printf("%-8s %9s %9s %9s %8s %10s\n", "threads", "best_s", "median_s", "cpu_s", "speedup", "pixels");
    for (int c = 0; c < COUNTS && counts[c] <= most; c++) {
        qsort(wall[c], (size_t)rounds, sizeof(double), by_value);
        qsort(cpu[c], (size_t)rounds, sizeof(double), by_value);
        double median = wall[c][rounds / 2];
        if (c == 0)
            base = median;
        printf("%-8u %9.3f %9.3f %9.3f %7.2fx %10llu\n", counts[c], wall[c][0], median, cpu[c][rounds / 2],
               base / median, (unsigned long long)pixels[c]);
        if (pixels[c] != pixels[0]) {
            fprintf(stderr, "bench_build_threads: %u threads give another tree\n", counts[c]);
            return 1;
        }
    }
    hpfc_graph_free(g);
    return 0;
}
