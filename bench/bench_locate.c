/*
 * bench_locate: point-in-feature queries on a packed GIS layer, hpfc
 * against GEOS.
 *
 *   bench_locate DATASET FILE.hpfc N [SEED]
 *
 * DATASET is the polygon layer FILE.hpfc was packed from (with hpfc-pack's
 * default projection). Both sides answer the same N random points of the
 * layer's projected extent:
 *   - hpfc: hpfc_locate on the mapped file, then the face of a private leaf
 *     or the candidate faces of a stabbed one, then their features (the
 *     FEAT section); the faces are numbered once beforehand (timed apart);
 *   - GEOS: every feature's polygon, projected with the same projection
 *     (parsed from the file's CRS section), prepared, in an STRtree; a point
 *     queries the tree and tests each candidate with GEOSPreparedContains.
 * It prints the set-up and per-point times, and how often the answers agree
 * (private leaves: the same features; stabbed: GEOS's among the candidates).
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

#include "hpfc.h"
#include "projection.h"

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

/* ---- GEOS side ------------------------------------------------------------------ */

typedef struct geos_side {
    GEOSContextHandle_t ctx;
    GEOSSTRtree *tree;
    GEOSGeometry **poly;
    const GEOSPreparedGeometry **prep;
    int64_t *fid;
    size_t n;
    double x0, y0, x1, y1; /* projected extent */
} geos_side;

/* The projected copy of an OGR geometry, as GEOS. */
static GEOSGeometry *project(GEOSContextHandle_t ctx, OGRGeometryH g, const mapproj_plan *plan)
{
    OGRGeometryH c = OGR_G_Clone(g);
    int n = OGR_G_GetGeometryCount(c);
    for (int i = 0; i < n; i++) {
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

static int geos_load(geos_side *G, const char *path, const mapproj_plan *plan)
{
    GDALAllRegister();
    GDALDatasetH ds = GDALOpenEx(path, GDAL_OF_VECTOR, NULL, NULL, NULL);
    if (!ds)
        return -1;
    OGRLayerH layer = GDALDatasetGetLayer(ds, 0);
    size_t cap = (size_t)OGR_L_GetFeatureCount(layer, 1) + 1;
    G->poly = calloc(cap, sizeof *G->poly);
    G->prep = calloc(cap, sizeof *G->prep);
    G->fid = calloc(cap, sizeof *G->fid);
    G->tree = GEOSSTRtree_create_r(G->ctx, 10);
    G->x0 = G->y0 = 1e300, G->x1 = G->y1 = -1e300;
    OGRFeatureH f;
    while ((f = OGR_L_GetNextFeature(layer)) && G->n < cap) {
        OGRGeometryH g = OGR_F_GetGeometryRef(f);
        OGRwkbGeometryType t = g ? wkbFlatten(OGR_G_GetGeometryType(g)) : wkbNone;
        if (t == wkbPolygon || t == wkbMultiPolygon) {
            GEOSGeometry *p = project(G->ctx, g, plan);
            double a, b, c, d;
            if (p && GEOSGeom_getXMin_r(G->ctx, p, &a) && GEOSGeom_getYMin_r(G->ctx, p, &b) &&
                GEOSGeom_getXMax_r(G->ctx, p, &c) && GEOSGeom_getYMax_r(G->ctx, p, &d)) {
                G->x0 = a < G->x0 ? a : G->x0, G->y0 = b < G->y0 ? b : G->y0;
                G->x1 = c > G->x1 ? c : G->x1, G->y1 = d > G->y1 ? d : G->y1;
                G->poly[G->n] = p;
                G->fid[G->n] = OGR_F_GetFID(f);
                G->n++;
            }
        }
        OGR_F_Destroy(f);
    }
    GDALClose(ds);
    return 0;
}

/* Prepares the polygons and fills the tree (timed as GEOS's set-up). */
static void geos_index(geos_side *G)
{
    for (size_t k = 0; k < G->n; k++) {
        G->prep[k] = GEOSPrepare_r(G->ctx, G->poly[k]);
        GEOSSTRtree_insert_r(G->ctx, G->tree, G->poly[k], (void *)(uintptr_t)k);
    }
}

typedef struct hits {
    const geos_side *G;
    const GEOSGeometry *pt;
    int64_t fid[16];
    int n;
} hits;

static void geos_visit(void *item, void *user)
{
    hits *h = user;
    size_t k = (size_t)(uintptr_t)item;
    if (h->n < 16 && GEOSPreparedContains_r(h->G->ctx, h->G->prep[k], h->pt) == 1)
        h->fid[h->n++] = h->G->fid[k];
}

/* ---- hpfc side ------------------------------------------------------------------- */

typedef struct answer {
    int is_private, n;
    int64_t fid[64];
} answer;

static void add_face(const hpfc_file *f, uint64_t face, answer *a)
{
    uint32_t count;
    hpfc_id feature;
    hpfc_feature ft;
    if (hpfc_face_feature_count(f, face, &count))
        return;
    for (uint32_t k = 0; k < count; k++)
        if (!hpfc_face_feature_id(f, face, k, &feature) &&
            !hpfc_file_get_feature(f, feature, &ft)) {
            int seen = 0;
            for (int i = 0; i < a->n; i++)
                seen |= a->fid[i] == ft.fid;
            if (!seen && a->n < 64)
                a->fid[a->n++] = ft.fid;
        }
}

static void hpfc_answer(const hpfc_file *f, const hpfc_faces *faces, int64_t x, int64_t y,
                        answer *a)
{
    hpfc_pixel px;
    a->n = 0;
    a->is_private = 0;
    if (hpfc_locate(f, x, y, &px) || hpfc_pixel_is_private(f, &px, &a->is_private))
        return;
    uint64_t face;
    if (a->is_private) {
        if (!hpfc_faces_pixel_face(faces, &px, &face))
            add_face(f, face, a);
        return;
    }
    size_t len;
    if (hpfc_pixel_word(f, &px, NULL, 0, &len) || len < 4)
        return;
    for (uint32_t k = 0; k + 4 < len; k++) {
        hpfc_dart d = {px, k};
        if (!hpfc_faces_dart_face(faces, &d, &face))
            add_face(f, face, a);
    }
}

/* ---- driver ------------------------------------------------------------------------ */

static int contains(const int64_t *set, int n, int64_t v)
{
    for (int i = 0; i < n; i++)
        if (set[i] == v)
            return 1;
    return 0;
}

int main(int argc, char **argv)
{
    if (argc < 4) {
        fprintf(stderr, "usage: bench_locate DATASET FILE.hpfc N [SEED]\n");
        return 2;
    }
    size_t n = strtoul(argv[3], NULL, 10);
    uint64_t seed = argc > 4 ? strtoull(argv[4], NULL, 10) : 1;
    hpfc_file *f = NULL;
    hpfc_faces *faces = NULL;
    hpfc_file_info info;
    char why[200];
    if (hpfc_open(argv[2], 0, &f)) {
        fprintf(stderr, "bench_locate: cannot open %s\n", argv[2]);
        return 1;
    }
    hpfc_file_get_info(f, &info);
    mapproj_plan *plan = info.crs ? mapproj_from_text(info.crs, info.crs_len, why, sizeof why) : NULL;
    if (!plan) {
        fprintf(stderr, "bench_locate: %s: no usable CRS\n", argv[2]);
        return 1;
    }
    geos_side G = {.ctx = GEOS_init_r()};
    if (geos_load(&G, argv[1], plan) || G.n == 0) {
        fprintf(stderr, "bench_locate: cannot read polygons from %s\n", argv[1]);
        return 1;
    }
    double t0 = now();
    hpfc_faces_build(f, &faces);
    double hpfc_setup = now() - t0;
    t0 = now();
    geos_index(&G);
    double geos_setup = now() - t0;

    double *px = malloc(2 * n * sizeof *px), unit = 1;
    for (int e = info.unit_exp10; e > 0; e--)
        unit *= 10;
    for (int e = info.unit_exp10; e < 0; e++)
        unit /= 10;
    for (size_t k = 0; k < n; k++) {
        px[2 * k] = G.x0 + (G.x1 - G.x0) * (double)(rng_next(&seed) >> 11) * 0x1p-53;
        px[2 * k + 1] = G.y0 + (G.y1 - G.y0) * (double)(rng_next(&seed) >> 11) * 0x1p-53;
    }
    answer *ans = malloc(n * sizeof *ans);
    t0 = now();
    for (size_t k = 0; k < n; k++)
        hpfc_answer(f, faces, (int64_t)floor(px[2 * k] / unit), (int64_t)floor(px[2 * k + 1] / unit),
                    &ans[k]);
    double hpfc_s = now() - t0;

    size_t agree = 0, priv = 0;
    t0 = now();
    hits *h = malloc(n * sizeof *h);
    for (size_t k = 0; k < n; k++) {
        GEOSGeometry *pt = GEOSGeom_createPointFromXY_r(G.ctx, px[2 * k], px[2 * k + 1]);
        h[k] = (hits){.G = &G, .pt = pt};
        GEOSSTRtree_query_r(G.ctx, G.tree, pt, geos_visit, &h[k]);
        GEOSGeom_destroy_r(G.ctx, pt);
    }
    double geos_s = now() - t0;
    for (size_t k = 0; k < n; k++) {
        int ok = 1;
        for (int i = 0; i < h[k].n; i++)
            ok &= contains(ans[k].fid, ans[k].n, h[k].fid[i]);
        if (ans[k].is_private)
            ok &= ans[k].n == h[k].n, priv++;
        agree += ok;
    }
    printf("%-28s %8zu %9zu | %9.3f %9.1f | %9.3f %9.1f | %6.1f%% %6.1f%%\n", argv[1], G.n, n,
           hpfc_setup * 1e3, hpfc_s / (double)n * 1e9, geos_setup * 1e3, geos_s / (double)n * 1e9,
           100.0 * (double)priv / (double)n, 100.0 * (double)agree / (double)n);
    free(h);
    free(ans);
    free(px);
    hpfc_faces_free(faces);
    hpfc_close(f);
    return 0;
}
