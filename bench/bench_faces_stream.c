/*
 * bench_faces_stream: a file's faces numbered one root pixel at a time
 * (faces_stream_*, the merge's numbering) against the whole file at once
 * (hpfc_faces_build_threads), in alternated rounds, each on THREADS
 * threads (the plan's roots; the roots' second numbering, as the writer
 * makes it, is on one). Prints each method's best and median wall time
 * (the plan's part apart) and the memory each holds: the whole
 * numbering's leaf table and union-find, the plan's arrays and the largest
 * root's numbering. The face counts must agree (the run fails otherwise).
 *
 * Usage: bench_faces_stream FILE.hpfc [ROUNDS [THREADS]]
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "faces.h"
#include "hpfc.h"

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

/* The plan (its time in *plan_s), then every root numbered again: the
 * largest root's bytes. */
static int stream_all(const hpfc_file *f, unsigned threads, double *plan_s, uint64_t *faces,
                      uint64_t *plan_bytes, uint64_t *root_bytes)
{
    faces_stream *s = NULL;
    hpfc_file_info info;
    hpfc_file_get_info(f, &info);
    double t0 = now();
    int st = faces_stream_plan(f, threads, &s);
    *plan_s = now() - t0;
    if (st)
        return st;
    *faces = faces_stream_face_count(s);
    *plan_bytes = faces_stream_plan_bytes(s);
    *root_bytes = 0;
    for (uint32_t j = 0; j < info.root_rows && !st; j++)
        for (uint32_t i = 0; i < info.root_cols && !st; i++) {
            hpfc_faces *fc = NULL;
            if (!(st = faces_stream_root(s, i, j, &fc)) && faces_bytes(fc) > *root_bytes)
                *root_bytes = faces_bytes(fc);
            hpfc_faces_free(fc);
        }
    faces_stream_free(s);
    return st;
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: bench_faces_stream FILE.hpfc [ROUNDS [THREADS]]\n");
        return 2;
    }
    int rounds = argc > 2 ? atoi(argv[2]) : 3, threads = argc > 3 ? atoi(argv[3]) : 1;
    if (rounds < 1 || rounds > 100 || threads < 1 || threads > 64)
        return 2;
    hpfc_file *f = NULL;
    int st = hpfc_open(argv[1], 0, &f);
    if (st) {
        fprintf(stderr, "bench_faces_stream: %s: %s\n", argv[1], hpfc_strerror(st));
        return 1;
    }
    double whole_t[100], stream_t[100], plan_t[100];
    uint64_t whole_faces = 0, stream_faces = 0, whole_bytes = 0, plan_bytes = 0, root_bytes = 0;
    for (int r = 0; r < rounds && !st; r++) {
        hpfc_faces *fc = NULL;
        double t0 = now();
        if ((st = hpfc_faces_build_threads(f, (unsigned)threads, &fc)))
            break;
        whole_t[r] = now() - t0;
        whole_faces = hpfc_faces_face_count(fc);
        whole_bytes = faces_bytes(fc);
        hpfc_faces_free(fc);
        t0 = now();
        st = stream_all(f, (unsigned)threads, &plan_t[r], &stream_faces, &plan_bytes, &root_bytes);
        stream_t[r] = now() - t0;
    }
    if (st || whole_faces != stream_faces) {
        fprintf(stderr, "bench_faces_stream: %s\n", st ? hpfc_strerror(st) : "the face counts differ");
        return 1;
    }
    qsort(whole_t, (size_t)rounds, sizeof(double), by_value);
    qsort(stream_t, (size_t)rounds, sizeof(double), by_value);
    qsort(plan_t, (size_t)rounds, sizeof(double), by_value);
    printf("%-26s %9s %9s %14s\n", "numbering", "best_s", "median_s", "bytes");
    printf("%-26s %9.3f %9.3f %14llu\n", "whole file", whole_t[0], whole_t[rounds / 2],
           (unsigned long long)whole_bytes);
    printf("%-26s %9.3f %9.3f %14llu\n", "root by root: plan + roots", stream_t[0],
           stream_t[rounds / 2], (unsigned long long)plan_bytes);
    printf("%-26s %9.3f %9.3f\n", "  the plan alone", plan_t[0], plan_t[rounds / 2]);
    printf("%-26s %9s %9s %14llu\n", "  largest root", "", "", (unsigned long long)root_bytes);
    printf("faces %llu, threads %d\n", (unsigned long long)whole_faces, threads);
    hpfc_close(f);
    return 0;
}
