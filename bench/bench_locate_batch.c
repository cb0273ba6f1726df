/*
 * bench_locate_batch: the C batch path the Python package is measured
 * against (bench/python_bench.py).
 *
 *   bench_locate_batch locate FILE.hpfc POINTS.f64 lonlat|xy [REPEATS]
 *   bench_locate_batch open FILE.hpfc [REPEATS]
 *
 * locate: POINTS.f64 holds n longitudes then n latitudes (or x then y, user
 * coordinates), native doubles. The points go to the lattice as the Python
 * package takes them (python/src/lattice_point.c, through the file's CRS
 * for lonlat), then through hpfc_locate_batch; the faces are numbered once
 * beforehand, timed apart. Prints the best wall and CPU times of REPEATS
 * (default 3) and checksums of the answers, as JSON.
 * open: hpfc_open + hpfc_close of FILE, REPEATS times (default 100): the
 * median and best time.
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "hpfc.h"
#include "hpfc_batch.h"
#include "lattice_point.h"
#include "projection.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* CPU time of this thread: steadier than the wall clock on a shared machine. */
static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static int bench_open(const char *path, int repeats)
{
    double *t = calloc((size_t)repeats, sizeof *t);
    if (!t)
        return 1;
    for (int r = 0; r < repeats; r++) {
        hpfc_file *f;
        double t0 = now();
        int st = hpfc_open(path, 0, &f);
        t[r] = now() - t0;
        if (st) {
            fprintf(stderr, "bench_locate_batch: %s: %s\n", path, hpfc_strerror(st));
            free(t);
            return 1;
        }
        hpfc_close(f);
    }
    qsort(t, (size_t)repeats, sizeof *t, cmp_double);
    printf("{\"open_median_s\":%.9f,\"open_best_s\":%.9f,\"repeats\":%d}\n", t[repeats / 2], t[0],
           repeats);
    free(t);
    return 0;
}

static double *read_points(const char *path, size_t *n)
{
    FILE *in = fopen(path, "rb");
    if (!in)
        return NULL;
    fseek(in, 0, SEEK_END);
    long bytes = ftell(in);
    fseek(in, 0, SEEK_SET);
    double *p = bytes > 0 ? malloc((size_t)bytes) : NULL;
    if (p && fread(p, 1, (size_t)bytes, in) != (size_t)bytes) {
        free(p);
        p = NULL;
    }
    fclose(in);
    *n = (size_t)bytes / 16;
    return p;
}

static int bench_locate(const char *path, const char *points, int lonlat, int repeats)
{
    hpfc_file *f;
    int st = hpfc_open(path, 0, &f);
    if (st) {
        fprintf(stderr, "bench_locate_batch: %s: %s\n", path, hpfc_strerror(st));
        return 1;
    }
    hpfc_file_info info;
    hpfc_file_get_info(f, &info);
    mapproj_plan *plan = NULL;
    if (lonlat) {
        char why[200];
        plan = info.crs ? mapproj_from_text(info.crs, info.crs_len, why, sizeof why) : NULL;
        if (!plan) {
            fprintf(stderr, "bench_locate_batch: no usable CRS for lon/lat\n");
            return 1;
        }
    }
    size_t n;
    double *uv = read_points(points, &n);
    int64_t *x = malloc(n * sizeof *x), *y = malloc(n * sizeof *y), *face = malloc(n * 8),
            *feature = malloc(n * 8);
    uint32_t *face_count = malloc(n * 4), *feature_count = malloc(n * 4);
    uint8_t *valid = malloc(n), *flags = malloc(n), *depth = malloc(n);
    if (!uv || !x || !y || !face || !feature || !face_count || !feature_count || !valid ||
        !flags || !depth) {
        fprintf(stderr, "bench_locate_batch: cannot read %s or out of memory\n", points);
        return 1;
    }
    hpfc_faces *faces;
    double t0 = now();
    if ((st = hpfc_faces_build(f, &faces))) {
        fprintf(stderr, "bench_locate_batch: faces: %s\n", hpfc_strerror(st));
        return 1;
    }
    double faces_s = now() - t0, best = 1e300, best_cpu = 1e300;
    hpfc_locate_out out = {face, face_count, feature, feature_count, flags, depth};
    for (int r = 0; r < repeats; r++) {
        t0 = now();
        double c0 = cpu_now();
        lattice_points(plan, info.unit_exp10, n, uv, uv + n, x, y, valid);
        st = hpfc_locate_batch(f, faces, n, x, y, valid, &out, NULL);
        double t = now() - t0, c = cpu_now() - c0;
        best_cpu = c < best_cpu ? c : best_cpu;
        if (st) {
            fprintf(stderr, "bench_locate_batch: locate: %s\n", hpfc_strerror(st));
            return 1;
        }
        best = t < best ? t : best;
    }
    uint64_t sum_face = 0, sum_feature = 0, single = 0;
    for (size_t k = 0; k < n; k++) {
        sum_face += (uint64_t)(face[k] + 1);
        sum_feature += (uint64_t)(feature[k] + 1);
        single += (flags[k] & HPFC_LOC_SINGLE) != 0;
    }
    printf("{\"points\":%zu,\"faces_s\":%.6f,\"locate_best_s\":%.6f,\"locate_best_cpu_s\":%.6f,"
           "\"ns_per_point\":%.1f,"
           "\"sum_face\":%llu,\"sum_feature\":%llu,\"single\":%llu}\n",
           n, faces_s, best, best_cpu, best * 1e9 / (double)n, (unsigned long long)sum_face,
           (unsigned long long)sum_feature, (unsigned long long)single);
    hpfc_faces_free(faces);
    if (plan)
        mapproj_free(plan);
    hpfc_close(f);
    free(uv), free(x), free(y), free(face), free(feature), free(face_count);
    free(feature_count), free(valid), free(flags), free(depth);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc >= 3 && strcmp(argv[1], "open") == 0)
        return bench_open(argv[2], argc > 3 ? atoi(argv[3]) > 0 ? atoi(argv[3]) : 100 : 100);
    if (argc >= 5 && strcmp(argv[1], "locate") == 0)
        return bench_locate(argv[2], argv[3], strcmp(argv[4], "lonlat") == 0,
                            argc > 5 && atoi(argv[5]) > 0 ? atoi(argv[5]) : 3);
    fprintf(stderr, "usage: bench_locate_batch locate FILE.hpfc POINTS.f64 lonlat|xy [REPEATS]\n"
                    "       bench_locate_batch open FILE.hpfc [REPEATS]\n");
    return 2;
}
