/*
 * bench_locate_exact: exact point -> feature, hpfc against GEOS prepared
 * polygons in an STRtree, on the same points in the same run.
 *
 *   bench_locate_exact LAYER FILE.hpfc N [SEED [XMIN YMIN XMAX YMAX]]
 *
 * LAYER is the polygon layer FILE.hpfc was packed from (GDAL-readable),
 * FILE.hpfc packed with its exact geometry (GEOM, LABL) and features
 * (FEAT). N random lattice points of the layer's extent, or of the box
 * given (in degrees when the file records a projection, projected
 * corner by corner: meant for cylindrical ones), seed SEED (default 1),
 * are answered
 *   - by hpfc_locate_batch on the mapped file (the code of
 *     hpfc_locate_point: one face, or the faces around a point on a
 *     border), giving the point's feature when its face links one;
 *   - by GEOS: every polygon (projected with the file's CRS when it records
 *     one) prepared and in an STRtree; a point (the lattice point's user
 *     coordinates) queries the tree and tests the candidates with
 *     GEOSPreparedContains, the first that contains it answers.
 * GEOS gets the polygons cut at the antimeridian as hpfc-pack cuts them.
 * Both sides get the same points, as the lattice point's user coordinates,
 * so they differ only where the pack moved a border (to the lattice, half
 * a unit at most, and by noding): every disagreement is measured against
 * the borders of the two polygons involved, and counted as within one
 * lattice unit of a border or not. Prints one JSON line.
 */
#include <gdal.h>
#include <geos_c.h>
#include <math.h>
#include <ogr_api.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "dateline.h"
#include "hpfc.h"
#include "hpfc_batch.h"
#include "projection.h"
#ifdef HPFC_BENCH_S2
#include "s2_peer.h"
#endif

struct s2_peer; /* the S2 peer, when built with it (HPFC_BENCH_S2) */

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static uint64_t rng_next(uint64_t *s)
{
    *s ^= *s << 13, *s ^= *s >> 7, *s ^= *s << 17;
    return *s;
}

/* ---- GEOS side ------------------------------------------------------------------ */

typedef struct geos_side {
    GEOSContextHandle_t ctx;
    GEOSSTRtree *tree;
    GEOSGeometry **poly;
    const GEOSPreparedGeometry **prep;
    int64_t *position; /* the feature's position in its layer (FEAT's fid) */
    size_t n;
    double x0, y0, x1, y1;
} geos_side;

/* An OGR geometry as GEOS, projected when plan is set: then (lon, lat)
 * first cut at the antimeridian as hpfc-pack cuts it (dateline.c), or a
 * polygon that crosses it (world-atlas's Russia, Fiji, Antarctica) would
 * run the long way round and cover half the map. */
static GEOSGeometry *to_geos(GEOSContextHandle_t ctx, OGRGeometryH g, const mapproj_plan *plan)
{
    OGRGeometryH c = NULL;
    char err[200];
    if (!plan || dateline_cut(g, 0, &c, err, sizeof err) != 0)
        c = OGR_G_Clone(g);
    int n = OGR_G_GetGeometryCount(c);
    for (int i = 0; plan && i < n; i++) {
        OGRGeometryH part = OGR_G_GetGeometryRef(c, i);
        int rings = OGR_G_GetGeometryCount(part);
        for (int r = 0; r < (rings ? rings : 1); r++) {
            OGRGeometryH ring = rings ? OGR_G_GetGeometryRef(part, r) : part;
            for (int k = 0; k < OGR_G_GetPointCount(ring); k++) {
                double x, y;
                mapproj_forward(plan, OGR_G_GetX(ring, k), OGR_G_GetY(ring, k), &x, &y);
                OGR_G_SetPoint_2D(ring, k, x, y);
            }
        }
    }
    size_t size = (size_t)OGR_G_WkbSize(c);
    unsigned char *wkb = malloc(size);
    OGR_G_ExportToWkb(c, wkbNDR, wkb);
    GEOSGeometry *out = GEOSGeomFromWKB_buf_r(ctx, wkb, size);
    free(wkb);
    OGR_G_DestroyGeometry(c);
    return out;
}

#ifdef HPFC_BENCH_S2
/* One OGR (multi)polygon to S2 in its source coordinates (lon/lat): each
 * part's first ring its shell, the others its holes. */
static void s2_add(s2_peer *s2, OGRGeometryH g, int64_t id)
{
    s2_peer_begin(s2, id);
    int multi = wkbFlatten(OGR_G_GetGeometryType(g)) == wkbMultiPolygon;
    int parts = multi ? OGR_G_GetGeometryCount(g) : 1;
    for (int i = 0; i < parts; i++) {
        OGRGeometryH part = multi ? OGR_G_GetGeometryRef(g, i) : g;
        for (int r = 0; r < OGR_G_GetGeometryCount(part); r++) {
            OGRGeometryH ring = OGR_G_GetGeometryRef(part, r);
            size_t np = (size_t)OGR_G_GetPointCount(ring);
            double *lon = malloc((np + 1) * sizeof *lon), *lat = malloc((np + 1) * sizeof *lat);
            for (size_t k = 0; lon && lat && k < np; k++)
                lon[k] = OGR_G_GetX(ring, (int)k), lat[k] = OGR_G_GetY(ring, (int)k);
            if (lon && lat)
                s2_peer_ring(s2, lon, lat, np, r == 0);
            free(lon), free(lat);
        }
    }
}
#endif

/* The layer's polygons into G (and S2 when s2 is set: a lon/lat layer). */
static int geos_load(geos_side *G, const char *path, const mapproj_plan *plan, struct s2_peer *s2)
{
    GDALAllRegister();
    GDALDatasetH ds = GDALOpenEx(path, GDAL_OF_VECTOR, NULL, NULL, NULL);
    if (!ds)
        return -1;
    OGRLayerH layer = GDALDatasetGetLayer(ds, 0);
    size_t cap = (size_t)OGR_L_GetFeatureCount(layer, 1) + 1;
    G->poly = calloc(cap, sizeof *G->poly);
    G->prep = calloc(cap, sizeof *G->prep);
    G->position = calloc(cap, sizeof *G->position);
    G->tree = GEOSSTRtree_create_r(G->ctx, 10);
    G->x0 = G->y0 = 1e300, G->x1 = G->y1 = -1e300;
    OGRFeatureH f;
    int64_t position = 0;
    for (; (f = OGR_L_GetNextFeature(layer)) && G->n < cap; position++) {
        OGRGeometryH g = OGR_F_GetGeometryRef(f);
        OGRwkbGeometryType t = g ? wkbFlatten(OGR_G_GetGeometryType(g)) : wkbNone;
        GEOSGeometry *p = t == wkbPolygon || t == wkbMultiPolygon ? to_geos(G->ctx, g, plan) : NULL;
        double a, b, c, d;
        if (p && GEOSGeom_getXMin_r(G->ctx, p, &a) && GEOSGeom_getYMin_r(G->ctx, p, &b) &&
            GEOSGeom_getXMax_r(G->ctx, p, &c) && GEOSGeom_getYMax_r(G->ctx, p, &d)) {
            G->x0 = a < G->x0 ? a : G->x0, G->y0 = b < G->y0 ? b : G->y0;
            G->x1 = c > G->x1 ? c : G->x1, G->y1 = d > G->y1 ? d : G->y1;
#ifdef HPFC_BENCH_S2
            /* S2 too gets the polygons cut at the antimeridian: a part of
             * Russia that crosses it otherwise covers the globe */
            OGRGeometryH cut = NULL;
            char why[200];
            if (s2 && dateline_cut(g, 0, &cut, why, sizeof why) == 0 && cut) {
                s2_add(s2, cut, (int64_t)G->n);
                OGR_G_DestroyGeometry(cut);
            } else if (s2) {
                s2_add(s2, g, (int64_t)G->n);
            }
#else
            (void)s2;
#endif
            G->poly[G->n] = p;
            G->position[G->n++] = position;
        }
        OGR_F_Destroy(f);
    }
    GDALClose(ds);
    return 0;
}

static void geos_index(geos_side *G)
{
    for (size_t k = 0; k < G->n; k++) {
        G->prep[k] = GEOSPrepare_r(G->ctx, G->poly[k]);
        GEOSSTRtree_insert_r(G->ctx, G->tree, G->poly[k], (void *)(uintptr_t)k);
    }
}

typedef struct hit {
    const geos_side *G;
    const GEOSGeometry *pt;
    int64_t k; /* the first polygon containing the point, -1 for none */
} hit;

static void geos_visit(void *item, void *user)
{
    hit *h = user;
    size_t k = (size_t)(uintptr_t)item;
    if (h->k < 0 && GEOSPreparedContains_r(h->G->ctx, h->G->prep[k], h->pt) == 1)
        h->k = (int64_t)k;
}

/* Distance from (x, y) to polygon k's boundary. */
static double border_distance(const geos_side *G, size_t k, double x, double y)
{
    GEOSGeometry *pt = GEOSGeom_createPointFromXY_r(G->ctx, x, y);
    GEOSGeometry *b = GEOSBoundary_r(G->ctx, G->poly[k]);
    double d = INFINITY;
    if (pt && b)
        GEOSDistance_r(G->ctx, pt, b, &d);
    GEOSGeom_destroy_r(G->ctx, pt);
    GEOSGeom_destroy_r(G->ctx, b);
    return d;
}

/* ---- driver ------------------------------------------------------------------------ */

/* The STRtree's first polygon that contains the point, or -1. */
static int64_t geos_query(geos_side *G, double ux, double uy)
{
    GEOSGeometry *pt = GEOSGeom_createPointFromXY_r(G->ctx, ux, uy);
    hit h = {.G = G, .pt = pt, .k = -1};
    GEOSSTRtree_query_r(G->ctx, G->tree, pt, geos_visit, &h);
    GEOSGeom_destroy_r(G->ctx, pt);
    return h.k;
}

#ifdef HPFC_BENCH_S2
/* S2 on the same points: built and encoded (timed), queried through the
 * encoded index in input order and in Morton order, compared with GEOS's
 * answers (S2's edges are geodesics, GEOS's straight lines of the
 * projection: they differ near borders; the first 1,000 disagreements are
 * measured against the borders). Writes a JSON object to out. */
static void s2_bench(s2_peer *s2, const geos_side *G, const mapproj_plan *plan, const double *ux,
                     const double *uy, size_t n, const size_t *order, const int64_t *geos_k,
                     double unit, double hpfc_cpu, char *out, size_t cap)
{
    size_t bytes = 0;
    double t0 = now();
    if (s2_peer_build(s2, &bytes)) {
        snprintf(out, cap, "{\"error\": \"S2 did not build its index\"}");
        return;
    }
    double build = now() - t0;
    double *xyz = malloc(3 * n * sizeof *xyz);
    int64_t *s2_k = malloc(n * sizeof *s2_k);
    for (size_t k = 0; k < n; k++) {
        double lon = ux[k], lat = uy[k];
        if (plan)
            mapproj_inverse(plan, ux[k], uy[k], &lon, &lat);
        s2_peer_point(lon, lat, xyz + 3 * k);
    }
    double cpu = INFINITY, sorted_cpu = INFINITY;
    for (int r = 0; r < 3; r++) {
        double c = cpu_now();
        for (size_t k = 0; k < n; k++)
            s2_k[k] = s2_peer_locate(s2, xyz + 3 * k);
        c = cpu_now() - c;
        cpu = c < cpu ? c : cpu;
        c = cpu_now();
        int64_t sum = 0;
        for (size_t i = 0; i < n; i++)
            sum += s2_peer_locate(s2, xyz + 3 * order[i]);
        c = cpu_now() - c;
        sorted_cpu = c < sorted_cpu ? c : sorted_cpu;
        if (sum == INT64_MIN) /* keeps the loop */
            fprintf(stderr, "?\n");
    }
    size_t agree = 0, near = 0, far = 0, measured = 0;
    double worst = 0;
    for (size_t k = 0; k < n; k++) {
        int64_t a = s2_k[k] >= 0 ? G->position[s2_k[k]] : -1;
        int64_t b = geos_k[k] >= 0 ? G->position[geos_k[k]] : -1;
        if (a == b) {
            agree++;
            continue;
        }
        if (measured == 1000) /* a border distance to a 10^5-point polygon is slow */
            continue;
        measured++;
        double d = INFINITY;
        if (s2_k[k] >= 0)
            d = border_distance(G, (size_t)s2_k[k], ux[k], uy[k]);
        if (geos_k[k] >= 0) {
            double e = border_distance(G, (size_t)geos_k[k], ux[k], uy[k]);
            d = e < d ? e : d;
        }
        if (d <= unit)
            near++;
        else
            far++, worst = d > worst ? d : worst;
    }
    snprintf(out, cap,
             "{\"index_bytes\": %zu, \"build_ms\": %.1f, \"cpu_ns\": %.1f, \"sorted_cpu_ns\": %.1f, "
             "\"hpfc_speedup_cpu\": %.2f, \"hpfc_speedup_cpu_vs_sorted\": %.2f, "
             "\"agree_with_geos\": %zu, \"disagreements_measured\": %zu, "
             "\"disagree_within_1_unit\": %zu, \"disagree_farther\": %zu, "
             "\"farthest_units\": %.1f}",
             bytes, build * 1e3, cpu / (double)n * 1e9, sorted_cpu / (double)n * 1e9,
             cpu / hpfc_cpu, sorted_cpu / hpfc_cpu, agree, measured, near, far, worst / unit);
    free(xyz), free(s2_k);
}
#endif

typedef struct keyed {
    uint64_t key;
    size_t index;
} keyed;

static int cmp_keyed(const void *a, const void *b)
{
    const keyed *p = a, *q = b;
    return p->key < q->key ? -1 : p->key > q->key;
}

/* order[] = the points sorted by the Morton code of their cell on a
 * 65536 x 65536 grid over the box (as hpfc_locate_batch orders them). */
static void morton_order(const int64_t *x, const int64_t *y, size_t n, int64_t x0, int64_t y0,
                         int64_t x1, int64_t y1, size_t *order)
{
    keyed *kv = malloc(n * sizeof *kv);
    double sx = 65535.0 / (double)(x1 - x0 + 1), sy = 65535.0 / (double)(y1 - y0 + 1);
    for (size_t k = 0; k < n; k++) {
        uint64_t cx = (uint64_t)((double)(x[k] - x0) * sx), cy = (uint64_t)((double)(y[k] - y0) * sy);
        uint64_t key = 0;
        for (int b = 0; b < 16; b++)
            key |= (cx >> b & 1) << (2 * b) | (cy >> b & 1) << (2 * b + 1);
        kv[k] = (keyed){key, k};
    }
    qsort(kv, n, sizeof *kv, cmp_keyed);
    for (size_t k = 0; k < n; k++)
        order[k] = kv[k].index;
    free(kv);
}

int main(int argc, char **argv)
{
    if (argc < 4) {
        fprintf(stderr, "usage: bench_locate_exact LAYER FILE.hpfc N [SEED [XMIN YMIN XMAX YMAX]]\n");
        return 2;
    }
    size_t n = strtoul(argv[3], NULL, 10);
    uint64_t seed = argc > 4 ? strtoull(argv[4], NULL, 10) : 1;
    hpfc_file *f = NULL;
    hpfc_file_info info;
    char why[200];
    if (hpfc_open(argv[2], 0, &f)) {
        fprintf(stderr, "bench_locate_exact: cannot open %s\n", argv[2]);
        return 1;
    }
    hpfc_file_get_info(f, &info);
    hpfc_geometry_info gi;
    hpfc_features_info fi;
    if (hpfc_file_get_geometry(f, &gi) || hpfc_file_get_features(f, &fi)) {
        fprintf(stderr, "bench_locate_exact: %s has no GEOM or no FEAT section\n", argv[2]);
        return 1;
    }
    mapproj_plan *plan = NULL;
    if (info.crs && !(plan = mapproj_from_text(info.crs, info.crs_len, why, sizeof why))) {
        fprintf(stderr, "bench_locate_exact: %s: %s\n", argv[2], why);
        return 1;
    }
    geos_side G = {.ctx = GEOS_init_r()};
    struct s2_peer *s2 = NULL;
#ifdef HPFC_BENCH_S2
    s2 = s2_peer_create();
#endif
    if (geos_load(&G, argv[1], plan, s2) || G.n == 0) {
        fprintf(stderr, "bench_locate_exact: cannot read polygons from %s\n", argv[1]);
        return 1;
    }
    double t0 = now();
    geos_index(&G);
    double geos_setup = now() - t0;

    /* the same points for both: random lattice points of the extent */
    double unit = pow(10.0, info.unit_exp10);
    if (argc > 8) { /* the box, in degrees when the file projects them */
        G.x0 = atof(argv[5]), G.y0 = atof(argv[6]), G.x1 = atof(argv[7]), G.y1 = atof(argv[8]);
        if (plan && (mapproj_forward(plan, G.x0, G.y0, &G.x0, &G.y0) ||
                     mapproj_forward(plan, G.x1, G.y1, &G.x1, &G.y1))) {
            fprintf(stderr, "bench_locate_exact: the box does not project\n");
            return 1;
        }
    }
    int64_t lx0 = (int64_t)floor(G.x0 / unit), ly0 = (int64_t)floor(G.y0 / unit);
    int64_t lx1 = (int64_t)ceil(G.x1 / unit), ly1 = (int64_t)ceil(G.y1 / unit);
    int64_t *x = malloc(n * sizeof *x), *y = malloc(n * sizeof *y), *face = malloc(n * sizeof *face);
    int64_t *feature = malloc(n * sizeof *feature);
    uint8_t *flags = malloc(n);
    double *ux = malloc(n * sizeof *ux), *uy = malloc(n * sizeof *uy);
    for (size_t k = 0; k < n; k++) {
        x[k] = lx0 + (int64_t)(rng_next(&seed) % (uint64_t)(lx1 - lx0 + 1));
        y[k] = ly0 + (int64_t)(rng_next(&seed) % (uint64_t)(ly1 - ly0 + 1));
        /* the lattice point in user units, correctly rounded */
        ux[k] = info.unit_exp10 < 0 ? (double)x[k] / pow(10.0, -info.unit_exp10) : (double)x[k] * unit;
        uy[k] = info.unit_exp10 < 0 ? (double)y[k] / pow(10.0, -info.unit_exp10) : (double)y[k] * unit;
    }

    hpfc_locate_out out = {.face = face, .feature = feature, .flags = flags};
    double best_wall = INFINITY, best_cpu = INFINITY;
    for (int r = 0; r < 3; r++) {
        double w = now(), c = cpu_now();
        size_t failed = 0;
        int st = hpfc_locate_batch(f, NULL, n, x, y, NULL, &out, &failed);
        c = cpu_now() - c, w = now() - w;
        if (st) {
            fprintf(stderr, "bench_locate_exact: point %zu: %s\n", failed, hpfc_strerror(st));
            return 1;
        }
        best_wall = w < best_wall ? w : best_wall, best_cpu = c < best_cpu ? c : best_cpu;
    }

    int64_t *geos_k = malloc(n * sizeof *geos_k);
    double geos_wall = INFINITY, geos_cpu = INFINITY;
    for (int r = 0; r < 3; r++) {
        double w = now(), c = cpu_now();
        for (size_t k = 0; k < n; k++)
            geos_k[k] = geos_query(&G, ux[k], uy[k]);
        c = cpu_now() - c, w = now() - w;
        geos_wall = w < geos_wall ? w : geos_wall, geos_cpu = c < geos_cpu ? c : geos_cpu;
    }
    /* GEOS given the order hpfc_locate_batch answers in (Morton order of
     * the points' cells), which makes its tree walks and polygons cache
     * better too: the sorting not timed, the fairer peer */
    size_t *order = malloc(n * sizeof *order);
    morton_order(x, y, n, lx0, ly0, lx1, ly1, order);
    double geos_sorted_wall = INFINITY, geos_sorted_cpu = INFINITY;
    for (int r = 0; r < 3; r++) {
        double w = now(), c = cpu_now();
        for (size_t i = 0; i < n; i++) {
            size_t k = order[i];
            if (geos_query(&G, ux[k], uy[k]) != geos_k[k])
                fprintf(stderr, "bench_locate_exact: GEOS answered point %zu two ways\n", k);
        }
        c = cpu_now() - c, w = now() - w;
        geos_sorted_wall = w < geos_sorted_wall ? w : geos_sorted_wall;
        geos_sorted_cpu = c < geos_sorted_cpu ? c : geos_sorted_cpu;
    }
    char s2_json[600] = "null";
#ifdef HPFC_BENCH_S2
    s2_bench(s2, &G, plan, ux, uy, n, order, geos_k, unit, best_cpu, s2_json, sizeof s2_json);
    s2_peer_free(s2);
#endif
    free(order);

    /* agreement: hpfc's feature position (FEAT fid) against GEOS's */
    size_t agree = 0, near_border = 0, far = 0, boundary = 0, inside_hpfc = 0, inside_geos = 0;
    for (size_t k = 0; k < n; k++) {
        int64_t mine = -1, theirs = geos_k[k] >= 0 ? G.position[geos_k[k]] : -1;
        hpfc_feature ft;
        if (feature[k] >= 0 && !hpfc_file_get_feature(f, (uint32_t)feature[k], &ft))
            mine = ft.fid;
        boundary += (flags[k] & HPFC_LOC_BOUNDARY) != 0;
        inside_hpfc += mine >= 0, inside_geos += theirs >= 0;
        if (mine == theirs) {
            agree++;
            continue;
        }
        double d = INFINITY;
        if (geos_k[k] >= 0)
            d = border_distance(&G, (size_t)geos_k[k], ux[k], uy[k]);
        for (size_t j = 0; mine >= 0 && j < G.n; j++)
            if (G.position[j] == mine) {
                double e = border_distance(&G, j, ux[k], uy[k]);
                d = e < d ? e : d;
            }
        if (d <= unit)
            near_border++;
        else {
            far++;
            if (far <= 5)
                fprintf(stderr, "far disagreement: lattice (%lld, %lld) hpfc fid %lld, GEOS %lld, "
                                "%.3g units from a border\n",
                        (long long)x[k], (long long)y[k], (long long)mine, (long long)theirs,
                        d / unit);
        }
    }
    printf("{\"layer\": \"%s\", \"polygons\": %zu, \"points\": %zu, \"hpfc_ns\": %.1f, "
           "\"hpfc_cpu_ns\": %.1f, \"geos_setup_ms\": %.2f, \"geos_ns\": %.1f, "
           "\"geos_cpu_ns\": %.1f, \"geos_sorted_ns\": %.1f, \"geos_sorted_cpu_ns\": %.1f, "
           "\"speedup_cpu\": %.2f, \"speedup_cpu_vs_sorted\": %.2f, \"in_a_feature_hpfc\": %zu, "
           "\"in_a_feature_geos\": %zu, \"on_boundary\": %zu, \"agree\": %zu, "
           "\"disagree_within_1_unit\": %zu, \"disagree_farther\": %zu, \"s2\": %s}\n",
           argv[1], G.n, n, best_wall / (double)n * 1e9, best_cpu / (double)n * 1e9,
           geos_setup * 1e3, geos_wall / (double)n * 1e9, geos_cpu / (double)n * 1e9,
           geos_sorted_wall / (double)n * 1e9, geos_sorted_cpu / (double)n * 1e9,
           geos_cpu / best_cpu, geos_sorted_cpu / best_cpu, inside_hpfc, inside_geos, boundary,
           agree, near_border, far, s2_json);
    free(x), free(y), free(face), free(feature), free(flags), free(ux), free(uy), free(geos_k);
    hpfc_close(f);
    return far ? 3 : 0;
}
