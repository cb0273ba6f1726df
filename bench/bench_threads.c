/*
 * bench_threads: point location from 1, 2, 4 and 8 threads sharing one
 * mapped file, beside GEOS queried from as many threads.
 *
 *   hpfc single  hpfc_locate_point, one call a point (its face, exactly)
 *   hpfc batch   hpfc_locate_batch over each thread's share of the points
 *                (stored labels; exact with GEOM)
 *   GEOS         every bounded face as a polygon in one GEOSSTRtree (built
 *                before the threads start, then read-only), a point's
 *                candidates tested with GEOSPreparedContains; each thread
 *                has its GEOS context and its own prepared geometries
 *                (GEOS prepares lazily, which is not thread-safe)
 *
 * The same N random lattice points (all inside the domain) are split into
 * equal shares. Each line: wall time, speed-up over one thread, wall time
 * per point and CPU time per point (the threads' CPU clocks summed, over
 * N: what a point costs, whatever else the machine runs; a rise with the
 * thread count is contention between the threads). The answers are
 * checked against each other: hpfc's single and batch faces must agree
 * everywhere, GEOS's wherever it finds exactly one face (a point on a
 * shared edge is in none for GEOS's contains).
 *
 * Usage: bench_threads FILE.hpfc [N [REPEATS]]
 */
#include <geos_c.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "hpfc.h"
#include "hpfc_batch.h"

typedef struct bench {
    const hpfc_file *f;
    size_t n;
    const int64_t *x, *y;
    int64_t *face_single, *face_batch, *face_geos;
    GEOSSTRtree *tree;
    GEOSGeometry **poly; /* by face id; NULL for the unbounded face */
    uint64_t faces;
} bench;

typedef struct job {
    bench *b;
    int kind; /* 0 single, 1 batch, 2 GEOS */
    size_t lo, hi;
    int status;
    double cpu; /* the thread's CPU seconds */
} job;

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

typedef struct geos_hit {
    GEOSContextHandle_t ctx;
    const GEOSPreparedGeometry **prep;
    GEOSGeometry **poly;
    const GEOSGeometry *pt;
    int64_t face;
    int hits;
} geos_hit;

static void visit(void *item, void *user)
{
    geos_hit *h = user;
    size_t k = (size_t)(uintptr_t)item;
    if (!h->prep[k])
        h->prep[k] = GEOSPrepare_r(h->ctx, h->poly[k]);
    if (GEOSPreparedContains_r(h->ctx, h->prep[k], h->pt) == 1) {
        h->face = (int64_t)k;
        h->hits++;
    }
}

static double thread_cpu(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void *work(void *arg)
{
    job *j = arg;
    bench *b = j->b;
    double c0 = thread_cpu();
    if (j->kind == 0) {
        for (size_t k = j->lo; k < j->hi; k++) {
            hpfc_point_location loc;
            hpfc_id faces[16];
            size_t n = 0;
            int st = hpfc_locate_point(b->f, b->x[k], b->y[k], &loc, faces, 16, &n);
            b->face_single[k] = st == HPFC_OK && n == 1 ? (int64_t)faces[0] : -1;
        }
    } else if (j->kind == 1) {
        size_t n = j->hi - j->lo;
        uint32_t *fc = malloc(n * sizeof *fc);
        hpfc_locate_out out = {.face = b->face_batch + j->lo, .face_count = fc};
        j->status = fc ? hpfc_locate_batch(b->f, NULL, n, b->x + j->lo, b->y + j->lo, NULL, &out,
                                           NULL)
                       : HPFC_E_NOMEM;
        for (size_t k = 0; fc && k < n; k++)
            if (fc[k] != 1)
                b->face_batch[j->lo + k] = -1;
        free(fc);
    } else {
        GEOSContextHandle_t ctx = GEOS_init_r();
        const GEOSPreparedGeometry **prep = calloc(b->faces, sizeof *prep);
        for (size_t k = j->lo; prep && k < j->hi; k++) {
            GEOSGeometry *pt = GEOSGeom_createPointFromXY_r(ctx, (double)b->x[k], (double)b->y[k]);
            geos_hit h = {ctx, prep, b->poly, pt, -1, 0};
            GEOSSTRtree_query_r(ctx, b->tree, pt, visit, &h);
            b->face_geos[k] = h.hits == 1 ? h.face : -1;
            GEOSGeom_destroy_r(ctx, pt);
        }
        for (uint64_t k = 0; prep && k < b->faces; k++)
            if (prep[k])
                GEOSPreparedGeom_destroy_r(ctx, prep[k]);
        j->status = !prep;
        free(prep);
        GEOS_finish_r(ctx);
    }
    j->cpu = thread_cpu() - c0;
    return NULL;
}

static double run(bench *b, int kind, unsigned threads, double *cpu)
{
    pthread_t t[8];
    job j[8];
    double t0 = now();
    for (unsigned k = 0; k < threads; k++) {
        j[k] = (job){b, kind, b->n * k / threads, b->n * (k + 1) / threads, 0, 0};
        pthread_create(&t[k], NULL, work, &j[k]);
    }
    *cpu = 0;
    for (unsigned k = 0; k < threads; k++) {
        pthread_join(t[k], NULL);
        *cpu += j[k].cpu;
    }
    for (unsigned k = 0; k < threads; k++)
        if (j[k].status) {
            fprintf(stderr, "bench_threads: kind %d failed: %s\n", kind,
                    hpfc_strerror(j[k].status));
            exit(1);
        }
    return now() - t0;
}

/* Every bounded face as a GEOS (multi)polygon of its exact rings. */
static int load_geos(bench *b, GEOSContextHandle_t ctx)
{
    hpfc_shapes *sh;
    if (hpfc_shapes_create(b->f, &sh))
        return 1;
    b->faces = hpfc_shapes_face_count(sh);
    b->poly = calloc(b->faces, sizeof *b->poly);
    b->tree = GEOSSTRtree_create_r(ctx, 10);
    for (uint64_t face = 1; b->poly && face < b->faces; face++) {
        hpfc_polygons p;
        if (hpfc_shapes_face_polygons(sh, face, &p) || p.polygon_count == 0)
            continue;
        GEOSGeometry **polys = malloc(p.polygon_count * sizeof *polys);
        for (size_t q = 0; q < p.polygon_count; q++) {
            size_t r0 = p.polygon_ring[q], r1 = p.polygon_ring[q + 1];
            GEOSGeometry **rings = malloc((r1 - r0) * sizeof *rings);
            for (size_t r = r0; r < r1; r++) {
                size_t a = p.ring_point[r], e = p.ring_point[r + 1];
                GEOSCoordSequence *cs = GEOSCoordSeq_create_r(ctx, (unsigned)(e - a), 2);
                for (size_t i = a; i < e; i++)
                    GEOSCoordSeq_setXY_r(ctx, cs, (unsigned)(i - a), (double)p.xy[2 * i],
                                         (double)p.xy[2 * i + 1]);
                rings[r - r0] = GEOSGeom_createLinearRing_r(ctx, cs);
            }
            polys[q] = GEOSGeom_createPolygon_r(ctx, rings[0], rings + 1, (unsigned)(r1 - r0 - 1));
            free(rings);
        }
        b->poly[face] = p.polygon_count == 1
                            ? polys[0]
                            : GEOSGeom_createCollection_r(ctx, GEOS_MULTIPOLYGON, polys,
                                                          (unsigned)p.polygon_count);
        free(polys);
        GEOSSTRtree_insert_r(ctx, b->tree, b->poly[face], (void *)(uintptr_t)face);
    }
    hpfc_shapes_free(sh);
    /* one query builds the tree, before the threads share it */
    GEOSGeometry *pt = GEOSGeom_createPointFromXY_r(ctx, 0, 0);
    geos_hit h = {ctx, NULL, b->poly, pt, -1, 0};
    const GEOSPreparedGeometry **none = calloc(b->faces, sizeof *none);
    h.prep = none;
    GEOSSTRtree_query_r(ctx, b->tree, pt, visit, &h);
    for (uint64_t k = 0; k < b->faces; k++)
        if (none[k])
            GEOSPreparedGeom_destroy_r(ctx, none[k]);
    free(none);
    GEOSGeom_destroy_r(ctx, pt);
    return !b->poly;
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: bench_threads FILE.hpfc [N [REPEATS]]\n");
        return 2;
    }
    size_t n = argc > 2 ? (size_t)atol(argv[2]) : 1000000;
    int repeats = argc > 3 ? atoi(argv[3]) : 3;
    hpfc_file *f;
    if (hpfc_open(argv[1], 0, &f)) {
        fprintf(stderr, "bench_threads: %s: cannot open\n", argv[1]);
        return 1;
    }
    hpfc_file_info in;
    hpfc_file_get_info(f, &in);
    bench b = {.f = f, .n = n};
    int64_t *x = malloc(n * sizeof *x), *y = malloc(n * sizeof *y);
    b.face_single = malloc(n * sizeof(int64_t));
    b.face_batch = malloc(n * sizeof(int64_t));
    b.face_geos = malloc(n * sizeof(int64_t));
    uint64_t z = 12345;
    for (size_t k = 0; k < n; k++) {
        z = z * 6364136223846793005u + 1442695040888963407u;
        x[k] = in.x0 + (int64_t)((z >> 11) % (uint64_t)in.width);
        z = z * 6364136223846793005u + 1442695040888963407u;
        y[k] = in.y0 + (int64_t)((z >> 11) % (uint64_t)in.height);
    }
    b.x = x, b.y = y;
    GEOSContextHandle_t ctx = GEOS_init_r();
    if (load_geos(&b, ctx)) {
        fprintf(stderr, "bench_threads: %s: no exact geometry (GEOM, LABL)\n", argv[1]);
        return 1;
    }
    printf("%s: %llu faces, %zu points, best of %d, %s\n", argv[1],
           (unsigned long long)b.faces, n, repeats, GEOSversion());
    printf("%-12s %7s %9s %8s %12s %12s\n", "method", "threads", "wall s", "speedup",
           "wall ns/pt", "cpu ns/pt");
    static const char *names[3] = {"hpfc single", "hpfc batch", "GEOS STRtree"};
    for (int kind = 0; kind < 3; kind++) {
        double base = 0;
        for (unsigned threads = 1; threads <= 8; threads *= 2) {
            double best = 1e300, best_cpu = 1e300;
            for (int r = 0; r < repeats; r++) {
                double cpu, s = run(&b, kind, threads, &cpu);
                best = s < best ? s : best;
                best_cpu = cpu < best_cpu ? cpu : best_cpu;
            }
            if (threads == 1)
                base = best;
            printf("%-12s %7u %9.3f %8.2f %12.1f %12.1f\n", names[kind], threads, best,
                   base / best, best * 1e9 / (double)n, best_cpu * 1e9 / (double)n);
            fflush(stdout);
        }
    }
    size_t agree_batch = 0, geos_one = 0, agree_geos = 0;
    for (size_t k = 0; k < n; k++) {
        agree_batch += b.face_single[k] == b.face_batch[k];
        if (b.face_geos[k] >= 0) {
            geos_one++;
            agree_geos += b.face_geos[k] == b.face_single[k];
        }
    }
    printf("agreement: single = batch at %zu of %zu points; GEOS found one face at %zu, "
           "hpfc the same at %zu\n",
           agree_batch, n, geos_one, agree_geos);
    for (uint64_t k = 0; k < b.faces; k++)
        if (b.poly[k])
            GEOSGeom_destroy_r(ctx, b.poly[k]);
    GEOSSTRtree_destroy_r(ctx, b.tree);
    GEOS_finish_r(ctx);
    free(b.poly);
    free(x), free(y), free(b.face_single), free(b.face_batch), free(b.face_geos);
    hpfc_close(f);
    return agree_batch == n && agree_geos == geos_one ? 0 : 1;
}
