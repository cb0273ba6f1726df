/*
 * bench_shapes: the whole-file calls of the public API that the scaling
 * benchmark (bench/run-scaling.sh) times, one call a run, so that each
 * process's peak memory is that call's.
 *
 *   bench_shapes faces FILE.hpfc            hpfc_faces_build
 *   bench_shapes all FILE.hpfc              hpfc_shapes_create, then
 *                                           hpfc_shapes_feature_polygons of every feature
 *   bench_shapes feature FILE.hpfc K [REPEATS]
 *                                           hpfc_shapes_create, then feature K
 *                                           REPEATS times (default 1), the best
 *
 * Prints one JSON object: the wall and CPU seconds (CLOCK_MONOTONIC,
 * CLOCK_PROCESS_CPUTIME_ID) of the call, of hpfc_shapes_create apart, and
 * what came back (and a checksum of it, to compare builds); `all` names the
 * feature with the most points ("largest"), which `feature` then times
 * alone.
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "hpfc.h"

typedef struct times {
    double wall, cpu;
} times;

static times now(void)
{
    struct timespec w, c;
    clock_gettime(CLOCK_MONOTONIC, &w);
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &c);
    return (times){(double)w.tv_sec + (double)w.tv_nsec * 1e-9,
                   (double)c.tv_sec + (double)c.tv_nsec * 1e-9};
}

static times since(times t0)
{
    times t = now();
    return (times){t.wall - t0.wall, t.cpu - t0.cpu};
}

/* FNV-1a over n 64-bit words, a word a step. */
static uint64_t hash_words(uint64_t h, const void *p, size_t n)
{
    for (size_t k = 0; k < n; k++) {
        uint64_t w;
        memcpy(&w, (const char *)p + 8 * k, 8);
        h = (h ^ w) * UINT64_C(0x100000001b3);
    }
    return h;
}

static uint64_t hash_polygons(uint64_t h, const hpfc_polygons *p)
{
    uint64_t counts[2] = {p->polygon_count, p->ring_count};
    h = hash_words(h, counts, 2);
    h = hash_words(h, p->polygon_ring, p->polygon_count + 1);
    h = hash_words(h, p->ring_point, p->ring_count + 1);
    return hash_words(h, p->xy, 2 * p->point_count);
}

static int fail(const char *what, int st)
{
    fprintf(stderr, "bench_shapes: %s: %s\n", what, hpfc_strerror(st));
    return 1;
}

static int bench_faces(const hpfc_file *f)
{
    hpfc_faces *faces;
    times t0 = now();
    int st = hpfc_faces_build(f, &faces);
    times t = since(t0);
    if (st)
        return fail("hpfc_faces_build", st);
    printf("{\"call\":\"faces\",\"wall_s\":%.6f,\"cpu_s\":%.6f,\"faces\":%llu}\n", t.wall, t.cpu,
           (unsigned long long)hpfc_faces_face_count(faces));
    hpfc_faces_free(faces);
    return 0;
}

/* Every feature (k < 0) or feature k, `repeats` times, the best. */
static int bench_features(const hpfc_file *f, long k, int repeats)
{
    hpfc_features_info info;
    int st = hpfc_file_get_features(f, &info);
    if (st)
        return fail("hpfc_file_get_features", st);
    if (k >= (long)info.features) {
        fprintf(stderr, "bench_shapes: feature %ld: the file has %u\n", k, info.features);
        return 2;
    }
    hpfc_shapes *s;
    times t0 = now();
    if ((st = hpfc_shapes_create(f, &s)))
        return fail("hpfc_shapes_create", st);
    times create = since(t0), best = {1e300, 1e300};
    uint32_t first = k < 0 ? 0 : (uint32_t)k, end = k < 0 ? info.features : first + 1;
    uint32_t largest = first;
    size_t points = 0, rings = 0, largest_points = 0, largest_rings = 0;
    uint64_t sum = UINT64_C(0xcbf29ce484222325);
    for (int r = 0; r < repeats && !st; r++) {
        points = rings = 0;
        times t = {0, 0};
        for (uint32_t q = first; q < end && !st; q++) {
            hpfc_polygons poly;
            t0 = now();
            st = hpfc_shapes_feature_polygons(s, q, &poly);
            times call = since(t0);
            t.wall += call.wall, t.cpu += call.cpu;
            if (st)
                break;
            if (r == 0)
                sum = hash_polygons(sum, &poly);
            points += poly.point_count;
            rings += poly.ring_count;
            if (poly.point_count > largest_points || q == first) {
                largest = q;
                largest_points = poly.point_count;
                largest_rings = poly.ring_count;
            }
        }
        best.wall = t.wall < best.wall ? t.wall : best.wall;
        best.cpu = t.cpu < best.cpu ? t.cpu : best.cpu;
    }
    hpfc_shapes_free(s);
    if (st)
        return fail("hpfc_shapes_feature_polygons", st);
    printf("{\"call\":\"%s\",\"wall_s\":%.6f,\"cpu_s\":%.6f,\"create_wall_s\":%.6f,"
           "\"create_cpu_s\":%.6f,\"features\":%u,\"points\":%zu,\"rings\":%zu,"
           "\"largest\":%u,\"largest_points\":%zu,\"largest_rings\":%zu,"
           "\"checksum\":\"%016llx\"}\n",
           k < 0 ? "all" : "feature", best.wall, best.cpu, create.wall, create.cpu, end - first,
           points, rings, largest, largest_points, largest_rings, (unsigned long long)sum);
    return 0;
}

int main(int argc, char **argv)
{
    int feature = argc >= 4 && strcmp(argv[1], "feature") == 0;
    if (!(argc == 3 && (strcmp(argv[1], "faces") == 0 || strcmp(argv[1], "all") == 0)) &&
        !(feature && argc <= 5)) {
        fprintf(stderr, "usage: bench_shapes faces|all FILE.hpfc\n"
                        "       bench_shapes feature FILE.hpfc K [REPEATS]\n");
        return 2;
    }
    hpfc_file *f;
    int st = hpfc_open(argv[2], 0, &f);
    if (st)
        return fail(argv[2], st);
    if (strcmp(argv[1], "faces") == 0)
        st = bench_faces(f);
    else if (feature)
        st = bench_features(f, atol(argv[3]), argc > 4 && atoi(argv[4]) > 0 ? atoi(argv[4]) : 1);
    else
        st = bench_features(f, -1, 1);
    hpfc_close(f);
    return st;
}
