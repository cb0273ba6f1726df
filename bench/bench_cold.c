/*
 * bench_cold: one answer from a cold handle: hpfc_open, one
 * point location, the point's faces and their source features, then
 * hpfc_close, timed as a whole, once per fresh open.
 *
 *   bench_cold FILE.hpfc [OPENS [SEED]]
 *
 * Each of OPENS (default 100) opens maps the file anew and answers a
 * different random point of the domain, drawn beforehand (untimed) among
 * the points whose faces have a source feature when the file has FEAT
 * sections and such points are found (else any point). With a LABL section the faces
 * come from the leaf's record (hpfc_label_leaf_faces); without one the
 * answer numbers the map's faces first (hpfc_faces_build), as a 1.1
 * reader must. The page cache is warm (the file was read before): the
 * figure is the library's work, not the disk's. Prints the median, the
 * 10th and 90th percentiles and the best time in microseconds.
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#include "hpfc.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static uint64_t rng_next(uint64_t *s)
{
    *s ^= *s << 13, *s ^= *s >> 7, *s ^= *s << 17;
    return *s;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The faces of the leaf at (x, y): from LABL, or by numbering them. */
static int point_faces(const hpfc_file *f, const hpfc_pixel *px, uint64_t *faces, size_t cap,
                       size_t *n)
{
    hpfc_labels_info li;
    if (hpfc_file_get_labels(f, &li) == HPFC_OK)
        return hpfc_label_leaf_faces(f, px, faces, cap, n);
    hpfc_faces *fc = NULL;
    int is_private = 0, st = hpfc_faces_build(f, &fc);
    if (!st)
        st = hpfc_pixel_is_private(f, px, &is_private);
    if (!st && is_private) {
        *n = 1;
        st = hpfc_faces_pixel_face(fc, px, &faces[0]);
    } else if (!st) {
        size_t len = 0;
        st = hpfc_pixel_word(f, px, NULL, 0, &len);
        *n = 0;
        for (uint32_t k = 0; !st && k + 4 < len && k < cap; k++) {
            hpfc_dart d = {.pixel = *px, .crossing = k};
            st = hpfc_faces_dart_face(fc, &d, &faces[(*n)++]);
        }
    }
    hpfc_faces_free(fc);
    return st;
}

/* One answer: open, locate, faces, features, close. *features: how many. */
static int answer(const char *path, int64_t x, int64_t y, size_t *features)
{
    hpfc_file *f = NULL;
    hpfc_pixel px;
    uint64_t faces[256];
    size_t n = 0;
    int st = hpfc_open(path, 0, &f);
    if (!st)
        st = hpfc_locate(f, x, y, &px);
    if (!st)
        st = point_faces(f, &px, faces, 256, &n);
    *features = 0;
    hpfc_features_info fi;
    if (!st && hpfc_file_get_features(f, &fi) == HPFC_OK) {
        for (size_t k = 0; k < n && !st; k++) {
            uint32_t count = 0;
            hpfc_id feature;
            st = hpfc_face_feature_count(f, faces[k], &count);
            for (uint32_t i = 0; i < count && !st; i++) {
                hpfc_feature ft;
                if (!(st = hpfc_face_feature_id(f, faces[k], i, &feature)))
                    st = hpfc_file_get_feature(f, feature, &ft);
                *features += !st;
            }
        }
    }
    hpfc_close(f);
    return st;
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: bench_cold FILE.hpfc [OPENS [SEED]]\n");
        return 2;
    }
    const char *path = argv[1];
    int opens = argc > 2 ? atoi(argv[2]) : 100;
    uint64_t seed = argc > 3 ? strtoull(argv[3], NULL, 10) : 1;
    if (opens < 1)
        opens = 1;
    hpfc_file *f = NULL;
    int st = hpfc_open(path, 0, &f);
    if (st) {
        fprintf(stderr, "bench_cold: %s: %s\n", path, hpfc_strerror(st));
        return 1;
    }
    hpfc_file_info info;
    hpfc_labels_info li;
    hpfc_file_get_info(f, &info);
    int labels = hpfc_file_get_labels(f, &li) == HPFC_OK;
    hpfc_close(f);
    struct stat sb;
    double mb = stat(path, &sb) == 0 ? (double)sb.st_size / 1e6 : 0;
    double *t = malloc((size_t)opens * sizeof *t);
    int64_t *pts = malloc((size_t)opens * 2 * sizeof *pts);
    size_t found = 0;
    uint64_t s = seed * 0x9E3779B97F4A7C15ull | 1;
    for (int k = 0, tries = 0; k < opens; tries++) {
        int64_t x = info.x0 + (int64_t)(rng_next(&s) % (uint64_t)info.width);
        int64_t y = info.y0 + (int64_t)(rng_next(&s) % (uint64_t)info.height);
        size_t features = 0;
        if (labels && tries < 200 * opens && (answer(path, x, y, &features) || features == 0))
            continue; /* only points with a feature, while they can be found fast */
        pts[2 * k] = x, pts[2 * k + 1] = y;
        k++;
    }
    for (int k = 0; k < opens; k++) {
        size_t features;
        double t0 = now();
        st = answer(path, pts[2 * k], pts[2 * k + 1], &features);
        t[k] = (now() - t0) * 1e6;
        if (st) {
            fprintf(stderr, "bench_cold: %s: %s\n", path, hpfc_strerror(st));
            return 1;
        }
        found += features;
    }
    qsort(t, (size_t)opens, sizeof *t, cmp_double);
    printf("%-40s %9.1f MB  labels %-3s  opens %4d  median %10.1f us  p10 %10.1f  p90 %10.1f  "
           "best %10.1f  features/answer %.2f\n",
           path, mb, labels ? "yes" : "no", opens, t[opens / 2], t[opens / 10],
           t[opens * 9 / 10], t[0], (double)found / opens);
    free(t);
    free(pts);
    return 0;
}
