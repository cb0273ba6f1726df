/*
 * hpfc_shapes_window against an oracle that never looks at the tree: for
 * random windows (points, lines, slivers, pixel-aligned and larger than the
 * domain) over generated maps with random features (FEAT) and edge
 * features (EDGF), packed under several root images:
 *   - an edge meets the window when one of its segments does (exact
 *     Liang-Barsky clipping in rationals, written here), and lies inside
 *     when all its points do;
 *   - a face meets it when one of the edges beside it does, or when the
 *     window's south-west corner lies in the face (a ray test on the face's
 *     rings, hpfc_shapes_face_polygons, written here; the unbounded face's rings
 *     bound the map, and it holds what they do not hold strictly); a bounded
 *     face lies inside when every edge beside it does;
 *   - a feature meets it through its faces and edges, and lies inside when
 *     all of them do.
 * The lists must be exactly the oracle's, in increasing order, with the
 * oracle's flags. Then every byte of POOL and LABL damaged (check_damage):
 * known statuses and well-formed lists only.
 */
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "gen.h"
#include "hpfc.h"

__extension__ typedef __int128 s128;

/* ---- the oracle's geometry ---------------------------------------------------------- */

/* Does segment a-b meet the closed rectangle w? Liang-Barsky: the
 * parameter interval [lo, hi] of the points inside each slab, as
 * fractions with positive denominators. */
static int clip_meets(const int64_t a[2], const int64_t b[2], const int64_t w[4])
{
    s128 lo_n = 0, lo_d = 1, hi_n = 1, hi_d = 1;
    for (int k = 0; k < 2; k++) {
        s128 d = (s128)b[k] - a[k];
        s128 e0 = (s128)w[k] - a[k], e1 = (s128)w[k + 2] - a[k]; /* e0 <= t d <= e1 */
        if (d == 0) {
            if (e0 > 0 || e1 < 0)
                return 0;
            continue;
        }
        s128 t0 = e0, t1 = e1, den = d;
        if (den < 0)
            t0 = -e1, t1 = -e0, den = -den;
        if (t0 * lo_d > lo_n * den)
            lo_n = t0, lo_d = den;
        if (t1 * hi_d < hi_n * den)
            hi_n = t1, hi_d = den;
    }
    return lo_n * hi_d <= hi_n * lo_d;
}

/* Point p in ring xy[0 .. n) (closed): 1 strictly inside, 0 outside, -1 on. */
static int ring_where(const int64_t *xy, size_t n, const int64_t p[2])
{
    int in = 0;
    for (size_t k = 0; k + 1 < n; k++) {
        const int64_t *a = xy + 2 * k, *b = xy + 2 * k + 2;
        s128 c = ((s128)b[0] - a[0]) * ((s128)p[1] - a[1]) - ((s128)b[1] - a[1]) * ((s128)p[0] - a[0]);
        int64_t xlo = a[0] < b[0] ? a[0] : b[0], xhi = a[0] < b[0] ? b[0] : a[0];
        int64_t ylo = a[1] < b[1] ? a[1] : b[1], yhi = a[1] < b[1] ? b[1] : a[1];
        if (c == 0 && p[0] >= xlo && p[0] <= xhi && p[1] >= ylo && p[1] <= yhi)
            return -1;
        if ((a[1] > p[1]) != (b[1] > p[1]) && ((c > 0) == (b[1] > a[1])))
            in = !in;
    }
    return in;
}

/* Point p in face f's rings: even-odd over them; -1 on one. */
static int face_where(hpfc_shapes *s, uint64_t f, const int64_t p[2])
{
    hpfc_polygons poly;
    if (hpfc_shapes_face_polygons(s, f, &poly) != HPFC_OK)
        return 0;
    int in = 0;
    for (size_t r = 0; r < poly.ring_count; r++) {
        size_t a = poly.ring_point[r], b = poly.ring_point[r + 1];
        int w = ring_where(poly.xy + 2 * a, b - a, p);
        if (w < 0)
            return -1;
        in ^= w;
    }
    return in;
}

/* ---- one file ------------------------------------------------------------------------ */

typedef struct world {
    hpfc_file *f;
    hpfc_shapes *s;
    uint64_t faces, edges;
    uint32_t features;
    const uint32_t *face_start, *face_feature, *edge_start, *edge_feature;
    uint64_t *left, *right, *npoints;
    int64_t domain[4];
    /* the oracle's answer */
    uint8_t *face_meets, *face_in, *edge_meets, *edge_in, *feat_meets, *feat_in;
} world;

static void edge_point(const world *w, uint64_t e, uint64_t k, int64_t p[2])
{
    CHECK_EQ_INT(hpfc_geometry_edge_point(w->f, e, k, &p[0], &p[1]), HPFC_OK);
}

static void oracle(world *w, const int64_t win[4])
{
    for (uint64_t e = 0; e < w->edges; e++) {
        int meets = 0, inside = 1;
        int64_t a[2], b[2];
        edge_point(w, e, 0, a);
        for (uint64_t k = 0; k < w->npoints[e]; k++) {
            edge_point(w, e, k, b);
            inside &= b[0] >= win[0] && b[1] >= win[1] && b[0] <= win[2] && b[1] <= win[3];
            if (k && clip_meets(a, b, win))
                meets = 1;
            a[0] = b[0], a[1] = b[1];
        }
        w->edge_meets[e] = (uint8_t)meets;
        w->edge_in[e] = (uint8_t)(meets && inside);
    }
    int64_t corner[2] = {win[0], win[1]};
    for (uint64_t f = 0; f < w->faces; f++) {
        w->face_meets[f] = 0;
        w->face_in[f] = f != 0;
    }
    for (uint64_t e = 0; e < w->edges; e++) {
        uint64_t side[2] = {w->left[e], w->right[e]};
        for (int k = 0; k < 2; k++) {
            w->face_meets[side[k]] |= w->edge_meets[e];
            if (!w->edge_in[e] && w->left[e] != w->right[e])
                w->face_in[side[k]] = 0;
        }
    }
    for (uint64_t f = 0; f < w->faces; f++)
        if (!w->face_meets[f])
            w->face_meets[f] = f ? face_where(w->s, f, corner) != 0
                                 : face_where(w->s, 0, corner) != 1;
    for (uint64_t f = 0; f < w->faces; f++)
        w->face_in[f] = w->face_in[f] && w->face_meets[f];
    for (uint32_t t = 0; t < w->features; t++)
        w->feat_meets[t] = 0, w->feat_in[t] = 1;
    for (uint64_t f = 0; f < w->faces; f++)
        for (uint32_t k = w->face_start[f]; k < w->face_start[f + 1]; k++) {
            uint32_t t = w->face_feature[k];
            w->feat_meets[t] |= w->face_meets[f];
            w->feat_in[t] &= w->face_in[f];
        }
    for (uint64_t e = 0; e < w->edges; e++)
        for (uint32_t k = w->edge_start[e]; k < w->edge_start[e + 1]; k++) {
            uint32_t t = w->edge_feature[k];
            w->feat_meets[t] |= w->edge_meets[e];
            w->feat_in[t] &= w->edge_in[e];
        }
}

/* The library's list against the oracle's marks: the same ids, ascending,
 * the same flags. */
static int same_list(const uint8_t *meets, const uint8_t *in, uint64_t n, size_t count,
                     const hpfc_id *ids, const uint8_t *inside)
{
    size_t k = 0;
    for (uint64_t id = 0; id < n; id++) {
        if (!meets[id])
            continue;
        hpfc_id got = k < count ? ids[k] : HPFC_ID_NONE;
        if (got != id || inside[k] != in[id])
            return 0;
        k++;
    }
    return k == count;
}

static long windows_checked, windows_bad;

static void check_window(world *w, const int64_t win[4])
{
    hpfc_window_hits h;
    int st = hpfc_shapes_window(w->s, win[0], win[1], win[2], win[3],
                                HPFC_WINDOW_FACES | HPFC_WINDOW_EDGES | HPFC_WINDOW_FEATURES, &h);
    CHECK_EQ_INT(st, HPFC_OK);
    if (st)
        return;
    oracle(w, win);
    int faces_ok = same_list(w->face_meets, w->face_in, w->faces, h.face_count, h.face,
                             h.face_inside);
    int edges_ok = same_list(w->edge_meets, w->edge_in, w->edges, h.edge_count, h.edge,
                             h.edge_inside);
    int feats_ok = same_list(w->feat_meets, w->feat_in, w->features, h.feature_count,
                             h.feature, h.feature_inside);
    CHECK(faces_ok);
    CHECK(edges_ok);
    CHECK(feats_ok);
    windows_checked++;
    if (!faces_ok || !edges_ok || !feats_ok) {
        windows_bad++;
        if (windows_bad < 5)
            fprintf(stderr, "  window %lld,%lld %lld,%lld: faces %d edges %d features %d "
                            "(%zu faces, %zu edges, %zu features)\n",
                    (long long)win[0], (long long)win[1], (long long)win[2], (long long)win[3],
                    faces_ok, edges_ok, feats_ok, h.face_count, h.edge_count, h.feature_count);
        if (windows_bad < 5) {
            fprintf(stderr, "    got faces:");
            for (size_t k = 0; k < h.face_count; k++)
                fprintf(stderr, " %llu%s", (unsigned long long)h.face[k], h.face_inside[k] ? "i" : "");
            fprintf(stderr, "; want:");
            for (uint64_t f = 0; f < w->faces; f++)
                if (w->face_meets[f])
                    fprintf(stderr, " %llu%s", (unsigned long long)f, w->face_in[f] ? "i" : "");
            fprintf(stderr, "\n");
        }
    }
}

static int64_t between(gen_rng *r, int64_t lo, int64_t hi)
{
    return lo + (int64_t)gen_rng_below(r, (uint64_t)(hi - lo + 1));
}

static void random_windows(world *w, gen_rng *r, int count)
{
    int64_t x0 = w->domain[0], y0 = w->domain[1], x1 = w->domain[2], y1 = w->domain[3];
    int64_t span = (x1 - x0 > y1 - y0 ? x1 - x0 : y1 - y0) + 1;
    for (int k = 0; k < count; k++) {
        int64_t a = between(r, x0 - span / 8, x1 + span / 8);
        int64_t b = between(r, y0 - span / 8, y1 + span / 8);
        int64_t size = (int64_t)1 << gen_rng_below(r, 12);
        int kind = (int)gen_rng_below(r, 6);
        int64_t win[4] = {a, b, a + between(r, 0, size), b + between(r, 0, size)};
        if (kind == 0)
            win[2] = win[0]; /* a vertical line */
        if (kind == 1)
            win[2] = win[0], win[3] = win[1]; /* a point */
        if (kind == 2) /* around the whole domain */
            win[0] = x0 - 1, win[1] = y0 - 1, win[2] = x1 + 1, win[3] = y1 + 1;
        check_window(w, win);
    }
    /* a window on every leaf of the first few: pixel-aligned borders */
    hpfc_pixel px;
    int n = 0;
    for (int st = hpfc_leaf_first(w->f, &px); !st && n < 64; st = hpfc_leaf_next(w->f, &px), n++) {
        int64_t b[4];
        if (hpfc_pixel_bounds(w->f, &px, &b[0], &b[1], &b[2], &b[3]) == HPFC_OK)
            check_window(w, b);
    }
}

static void run_map(const char *name, const hpfc_graph *g, uint32_t n0, uint64_t seed)
{
    hpfc_build_params bp;
    hpfc_build_params_default(&bp);
    bp.root_cols = bp.root_rows = n0;
    uint8_t *buf = NULL, *buf2 = NULL;
    size_t size, size2;
    hpfc_file *f = NULL;
    int st = check_labelled_file(g, &bp, &buf, &size, &f);
    CHECK_EQ_INT(st, HPFC_OK);
    if (st)
        return;
    /* random features: faces (FEAT) and edges (EDGF) */
    hpfc_faces *fc;
    CHECK_EQ_INT(hpfc_faces_build(f, &fc), HPFC_OK);
    uint64_t nf = hpfc_faces_face_count(fc);
    hpfc_faces_free(fc);
    size_t ne = hpfc_graph_edge_count(g);
    enum { NFEAT = 4 };
    gen_rng r;
    gen_rng_seed(&r, seed);
    uint32_t *fstart = calloc(nf + 1, sizeof *fstart), *flinks = malloc(NFEAT * nf * 4 + 4);
    uint32_t *estart = calloc(ne + 1, sizeof *estart), *elinks = malloc(NFEAT * ne * 4 + 4);
    uint32_t nl = 0;
    for (uint64_t face = 0; face < nf; face++) {
        fstart[face] = nl;
        for (uint32_t k = 0; k < NFEAT && face; k++)
            if (gen_rng_below(&r, 3) == 0)
                flinks[nl++] = k;
    }
    fstart[nf] = nl;
    nl = 0;
    for (size_t e = 0; e < ne; e++) {
        estart[e] = nl;
        if (gen_rng_below(&r, 4) == 0)
            elinks[nl++] = (uint32_t)gen_rng_below(&r, NFEAT);
    }
    estart[ne] = nl;
    int64_t fid[NFEAT] = {0, 1, 2, 3};
    uint32_t layer[NFEAT] = {0};
    const char *lname[1] = {"random"};
    hpfc_feature_table ft = {.feature_count = NFEAT, .fid = fid, .layer = layer, .layer_count = 1,
                             .layer_name = lname, .face_count = (uint32_t)nf,
                             .face_start = fstart, .face_feature = flinks};
    hpfc_edge_feature_table eft = {.edge_count = (uint32_t)ne, .feature_count = NFEAT,
                                   .edge_start = estart, .edge_feature = elinks};
    hpfc_write_options o2 = {.features = &ft, .edge_features = &eft};
    hpfc_file *f2 = NULL;
    st = hpfc_file_serialize(f, &o2, &buf2, &size2, NULL);
    if (!st)
        st = hpfc_open_memory(buf2, size2, 0, &f2);
    CHECK_EQ_INT(st, HPFC_OK);
    world w = {.f = f2, .faces = nf, .edges = ne, .features = NFEAT, .face_start = fstart,
               .face_feature = flinks, .edge_start = estart, .edge_feature = elinks};
    if (!st)
        st = hpfc_shapes_create(f2, &w.s);
    CHECK_EQ_INT(st, HPFC_OK);
    if (!st) {
        hpfc_file_info fi;
        hpfc_file_get_info(f2, &fi);
        w.domain[0] = fi.x0, w.domain[1] = fi.y0;
        w.domain[2] = fi.x0 + fi.width - 1, w.domain[3] = fi.y0 + fi.height - 1;
        w.left = malloc(ne * 8 + 8), w.right = malloc(ne * 8 + 8), w.npoints = malloc(ne * 8 + 8);
        for (size_t e = 0; e < ne; e++) {
            uint64_t u, v;
            CHECK_EQ_INT(hpfc_geometry_edge(f2, e, &u, &v, &w.npoints[e]), HPFC_OK);
            CHECK_EQ_INT(hpfc_geometry_edge_faces(f2, e, &w.left[e], &w.right[e]), HPFC_OK);
        }
        w.face_meets = malloc(nf + 1), w.face_in = malloc(nf + 1);
        w.edge_meets = malloc(ne + 1), w.edge_in = malloc(ne + 1);
        w.feat_meets = malloc(NFEAT), w.feat_in = malloc(NFEAT);
        long before = windows_bad;
        random_windows(&w, &r, 120);
        if (windows_bad > before)
            fprintf(stderr, "  in %s, root %ux%u\n", name, n0, n0);
        /* bad arguments */
        hpfc_window_hits h;
        CHECK_EQ_INT(hpfc_shapes_window(w.s, 5, 0, 4, 0, HPFC_WINDOW_FACES, &h), HPFC_E_ARG);
        CHECK_EQ_INT(hpfc_shapes_window(w.s, 0, 0, 1, 1, 8, &h), HPFC_E_ARG);
        CHECK_EQ_INT(hpfc_shapes_window(w.s, 0, 0, 1, 1, HPFC_WINDOW_FACES, NULL), HPFC_E_ARG);
        hpfc_shapes_free(w.s);
        free(w.left), free(w.right), free(w.npoints);
        free(w.face_meets), free(w.face_in), free(w.edge_meets), free(w.edge_in);
        free(w.feat_meets), free(w.feat_in);
    }
    /* without features: faces and edges only */
    hpfc_shapes *s0;
    if (hpfc_shapes_create(f, &s0) == HPFC_OK) {
        hpfc_window_hits h;
        CHECK_EQ_INT(hpfc_shapes_window(s0, 0, 0, 10, 10, HPFC_WINDOW_FEATURES, &h),
                     HPFC_E_NO_SECTION);
        hpfc_shapes_free(s0);
    }
    hpfc_close(f2);
    hpfc_close(f);
    hpfc_free(buf2);
    hpfc_free(buf);
    free(fstart), free(flinks), free(estart), free(elinks);
}

/* Damaged POOL and LABL sections (the type bits and block counts a scan
 * of an inside subtree reads, the records and directory an inside leaf's
 * pieces come from): every byte of both set to 0x00, 0xFF and flipped,
 * opened without the checksum; the domain with a margin (every refined
 * root inside), its centre quarter and a line through it give a known
 * status and, on success, ascending lists in range, flags 0 or 1, face 0
 * never inside (ASan and UBSan watch the reads). */
static int known_status(int st)
{
    return st == HPFC_OK || st == HPFC_E_CORRUPT || st == HPFC_E_NO_SECTION ||
           st == HPFC_E_NOMEM || st == HPFC_E_LIMIT || st == HPFC_E_OVER_LIMIT;
}

static int well_formed(const hpfc_id *ids, const uint8_t *inside, size_t n, uint64_t bound)
{
    for (size_t k = 0; k < n; k++)
        if (ids[k] >= bound || (k && ids[k - 1] >= ids[k]) || inside[k] > 1)
            return 0;
    return 1;
}

static void check_damage(const hpfc_graph *g, uint32_t n0, long *answered)
{
    hpfc_build_params bp;
    hpfc_build_params_default(&bp);
    bp.root_cols = bp.root_rows = n0;
    uint8_t *buf = NULL;
    size_t size = 0;
    hpfc_file *f = NULL;
    int st = check_labelled_file(g, &bp, &buf, &size, &f);
    CHECK_EQ_INT(st, HPFC_OK);
    hpfc_file_info fi;
    if (!st)
        hpfc_file_get_info(f, &fi);
    uint8_t *copy = malloc(size + 1);
    for (uint32_t k = 0; !st && k < fi.section_count; k++) {
        hpfc_section_info si;
        CHECK_EQ_INT(hpfc_file_get_section(f, k, &si), HPFC_OK);
        if (strcmp(si.tag, "POOL") != 0 && strcmp(si.tag, "LABL") != 0)
            continue;
        for (uint64_t at = si.offset; at < si.offset + si.length; at++)
            for (int how = 0; how < 3; how++) {
                memcpy(copy, buf, size);
                copy[at] = how == 0 ? 0x00 : how == 1 ? 0xFF : (uint8_t)~copy[at];
                hpfc_file *d;
                hpfc_shapes *s;
                if (hpfc_open_memory(copy, size, HPFC_OPEN_SKIP_CHECKSUM, &d) != HPFC_OK)
                    continue;
                int cs = hpfc_shapes_create(d, &s);
                CHECK(known_status(cs));
                int64_t cx = fi.x0 + fi.width / 2, cy = fi.y0 + fi.height / 2;
                int64_t win[3][4] = {
                    {fi.x0 - 1, fi.y0 - 1, fi.x0 + fi.width + 1, fi.y0 + fi.height + 1},
                    {cx - fi.width / 4, cy - fi.height / 4, cx + fi.width / 4, cy + fi.height / 4},
                    {fi.x0, cy, fi.x0 + fi.width, cy}};
                for (int w = 0; w < 3 && cs == HPFC_OK; w++) {
                    hpfc_window_hits h;
                    int ws = hpfc_shapes_window(s, win[w][0], win[w][1], win[w][2], win[w][3],
                                                HPFC_WINDOW_FACES | HPFC_WINDOW_EDGES, &h);
                    CHECK(known_status(ws));
                    if (ws)
                        continue;
                    (*answered)++;
                    uint64_t nf = hpfc_shapes_face_count(s);
                    CHECK(well_formed(h.face, h.face_inside, h.face_count, nf));
                    CHECK(well_formed(h.edge, h.edge_inside, h.edge_count, UINT64_MAX));
                    CHECK(h.face_count == 0 || h.face[0] != 0 || !h.face_inside[0]);
                }
                if (cs == HPFC_OK)
                    hpfc_shapes_free(s);
                hpfc_close(d);
            }
    }
    free(copy);
    hpfc_close(f);
    hpfc_free(buf);
}

int main(void)
{
    check_use_test_layout();
    for (int k = 0; k < GEN_SPECIAL_COUNT; k++) {
        hpfc_graph *g;
        if (gen_special(k, &g))
            continue;
        run_map(gen_special_name(k), g, 4, (uint64_t)k + 1);
        hpfc_graph_free(g);
    }
    for (uint64_t seed = 1; seed <= 6; seed++) {
        hpfc_graph *g;
        if (!gen_delaunay(seed, 150 + 40 * seed, 2000, 0.3, &g)) {
            run_map("delaunay", g, seed % 2 ? 4 : 16, seed);
            run_map("delaunay 1x1", g, 1, seed + 100);
            hpfc_graph_free(g);
        }
        if (!gen_polyline(seed, 200, 3000, 0.5, &g)) {
            run_map("polyline", g, 8, seed + 200);
            hpfc_graph_free(g);
        }
    }
    long answered = 0;
    hpfc_graph *damaged[3] = {NULL, NULL, NULL};
    CHECK_EQ_INT(gen_special(GEN_SPECIAL_LOOP, &damaged[0]), HPFC_OK);
    CHECK_EQ_INT(gen_special(GEN_SPECIAL_MULTI, &damaged[1]), HPFC_OK);
    CHECK_EQ_INT(gen_delaunay(7, 30, 2000, 0.3, &damaged[2]), HPFC_OK);
    for (int k = 0; k < 3; k++)
        if (damaged[k]) {
            check_damage(damaged[k], 2, &answered);
            hpfc_graph_free(damaged[k]);
        }
    CHECK(answered > 0); /* damage the window reads through, not only refused opens */
    printf("%ld windows, %ld wrong; %ld answers on damaged files\n", windows_checked, windows_bad,
           answered);
    return check_report("window");
}
