/*
 * The topology questions (hpfc_shapes_feature_neighbours, _adjacency,
 * _nearest_edge, _edges_within, _features_polygons, _mesh) against oracles
 * that read geometry, not the side labels, over generated maps with random
 * features: a partition of the bounded faces into six polygon features
 * (multipolygons, holes, enclaves, parts touching at one vertex), two that
 * overlap them, and two line features (EDGF only).
 *   - neighbours: two features touch when their borders (the rings of
 *     hpfc_shapes_feature_polygons, a line feature's polylines) share a
 *     point, and share an edge when they share a segment; the length is
 *     the sum of the shared segments;
 *   - nearest: every segment of the map, the squared distances compared
 *     exactly in 128 bits (the generated coordinates are small), ties to
 *     the lowest edge and segment; "within d" the same test for each edge;
 *   - dissolve: the rings' segments are exactly those of the edges with
 *     one side's face in the set (the test's own face-to-feature table),
 *     and the area is the sum of the set's faces' areas;
 *   - mesh: the lines' segments are exactly those of the edges the
 *     sides' groups select, by the same table.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "gen.h"
#include "hpfc.h"

__extension__ typedef __int128 s128;

enum { NPOLY = 6, NFEAT = 10, FIRST_LINE = 8 };

typedef struct seg {
    int64_t c[4]; /* the lower end first */
} seg;

static int cmp_seg(const void *pa, const void *pb)
{
    const seg *a = pa, *b = pb;
    for (int k = 0; k < 4; k++)
        if (a->c[k] != b->c[k])
            return a->c[k] < b->c[k] ? -1 : 1;
    return 0;
}

typedef struct segs {
    seg *s;
    size_t n, cap;
} segs;

static void segs_add(segs *v, const int64_t *a, const int64_t *b)
{
    if (v->n == v->cap) {
        v->cap = v->cap ? 2 * v->cap : 64;
        v->s = realloc(v->s, v->cap * sizeof *v->s);
    }
    int swap = a[0] > b[0] || (a[0] == b[0] && a[1] > b[1]);
    const int64_t *p = swap ? b : a, *q = swap ? a : b;
    v->s[v->n++] = (seg){{p[0], p[1], q[0], q[1]}};
}

static void segs_sort(segs *v)
{
    if (v->n)
        qsort(v->s, v->n, sizeof *v->s, cmp_seg);
}

static int segs_equal(const segs *a, const segs *b)
{
    return a->n == b->n && (a->n == 0 || !memcmp(a->s, b->s, a->n * sizeof *a->s));
}

static void answer_segs(const hpfc_polygons *p, segs *v)
{
    for (size_t r = 0; r < p->ring_count; r++)
        for (size_t k = p->ring_point[r]; k + 1 < p->ring_point[r + 1]; k++)
            segs_add(v, p->xy + 2 * k, p->xy + 2 * k + 2);
}

typedef struct world {
    hpfc_file *f;
    hpfc_shapes *s;
    uint64_t faces, edges;
    uint32_t *fstart, *flinks, *estart, *elinks;
    uint64_t *left, *right, *npoints;
    int64_t domain[4];
    segs border[NFEAT];      /* each feature's border segments, sorted */
    segs points[NFEAT];      /* its border points, as (p, p) */
} world;

static void edge_point(const world *w, uint64_t e, uint64_t k, int64_t p[2])
{
    CHECK_EQ_INT(hpfc_geometry_edge_point(w->f, e, k, &p[0], &p[1]), HPFC_OK);
}

static void edge_segs(const world *w, uint64_t e, segs *v)
{
    int64_t a[2], b[2];
    edge_point(w, e, 0, a);
    for (uint64_t k = 1; k < w->npoints[e]; k++) {
        edge_point(w, e, k, b);
        segs_add(v, a, b);
        a[0] = b[0], a[1] = b[1];
    }
}

static int face_has(const world *w, uint64_t face, uint32_t g)
{
    for (uint32_t k = w->fstart[face]; k < w->fstart[face + 1]; k++)
        if (w->flinks[k] == g)
            return 1;
    return 0;
}

/* ---- neighbours ------------------------------------------------------------------ */

static void borders(world *w)
{
    for (uint32_t g = 0; g < NFEAT; g++) {
        hpfc_polygons p;
        int st = g < FIRST_LINE ? hpfc_shapes_feature_polygons(w->s, g, &p)
                                : hpfc_shapes_feature_polylines(w->s, g, &p);
        CHECK_EQ_INT(st, HPFC_OK);
        w->border[g].n = w->points[g].n = 0;
        if (st)
            continue;
        answer_segs(&p, &w->border[g]);
        for (size_t k = 0; k < p.point_count; k++)
            segs_add(&w->points[g], p.xy + 2 * k, p.xy + 2 * k);
        segs_sort(&w->border[g]);
        segs_sort(&w->points[g]);
    }
}

/* Common elements of two sorted lists: how many, and their total length. */
static size_t common(const segs *a, const segs *b, double *len)
{
    size_t i = 0, j = 0, n = 0;
    *len = 0;
    while (i < a->n && j < b->n) {
        int c = cmp_seg(&a->s[i], &b->s[j]);
        if (c == 0) {
            const int64_t *q = a->s[i].c;
            *len += hypot((double)(q[2] - q[0]), (double)(q[3] - q[1]));
            n++;
            int64_t *last = a->s[i].c;
            /* a ring may pass a point twice: count the pair once */
            while (i < a->n && !cmp_seg(&a->s[i], (const seg *)last))
                i++;
            while (j < b->n && !cmp_seg(&b->s[j], (const seg *)last))
                j++;
        } else if (c < 0) {
            i++;
        } else {
            j++;
        }
    }
    return n;
}

/* The oracle's touch of f and g: 0, HPFC_TOUCH_VERTEX or _EDGE. */
static int oracle_touch(const world *w, uint32_t f, uint32_t g, double *len)
{
    double l;
    if (common(&w->border[f], &w->border[g], len))
        return HPFC_TOUCH_EDGE;
    return common(&w->points[f], &w->points[g], &l) ? HPFC_TOUCH_VERTEX : 0;
}

static long pairs_checked, neighbour_bad;

static void check_neighbours(world *w)
{
    borders(w);
    hpfc_adjacency adj;
    int st = hpfc_shapes_adjacency(w->s, HPFC_TOUCH_EDGE | HPFC_TOUCH_VERTEX, &adj);
    CHECK_EQ_INT(st, HPFC_OK);
    size_t ka = 0;
    hpfc_adjacency rook;
    CHECK_EQ_INT(hpfc_shapes_adjacency(w->s, HPFC_TOUCH_EDGE, &rook), HPFC_OK);
    size_t rook_count = rook.count, rook_want = 0;
    for (uint32_t f = 0; f < NFEAT; f++) {
        hpfc_neighbours nb;
        CHECK_EQ_INT(hpfc_shapes_feature_neighbours(w->s, f, &nb), HPFC_OK);
        size_t k = 0;
        for (uint32_t g = 0; g < NFEAT; g++) {
            if (g == f)
                continue;
            double len;
            int t = oracle_touch(w, f, g, &len);
            pairs_checked++;
            int ok = 1;
            if (t) {
                ok = k < nb.count && nb.feature[k] == g && nb.touch[k] == t &&
                     fabs(nb.length[k] - len) <= 1e-9 * (len + 1);
                /* the shared edges' segments are the common segments */
                if (ok && t == HPFC_TOUCH_EDGE) {
                    segs v = {0};
                    for (size_t j = nb.edge_start[k]; j < nb.edge_start[k + 1]; j++)
                        edge_segs(w, nb.edge[j], &v);
                    double l2;
                    segs_sort(&v);
                    ok = common(&v, &w->border[f], &l2) == v.n &&
                         common(&v, &w->border[g], &l2) == v.n && fabs(l2 - len) < 1e-9 * (len + 1);
                    free(v.s);
                }
                k++;
            } else {
                ok = k >= nb.count || nb.feature[k] != g;
            }
            if (g > f && t) {
                ok &= ka < adj.count && adj.a[ka] == f && adj.b[ka] == g && adj.touch[ka] == t &&
                      fabs(adj.length[ka] - len) <= 1e-9 * (len + 1);
                ka++;
                rook_want += t == HPFC_TOUCH_EDGE;
            }
            CHECK(ok);
            if (!ok && neighbour_bad++ < 5)
                fprintf(stderr, "  features %u and %u: oracle touch %d length %g\n", f, g, t, len);
        }
        CHECK(k == nb.count);
    }
    CHECK(ka == adj.count);
    CHECK(rook_count == rook_want);
}

/* ---- nearest --------------------------------------------------------------------- */

/* The squared distance from p to segment a-b as n / d, exact (small
 * coordinates). */
static void sq_dist(const int64_t p[2], const int64_t a[2], const int64_t b[2], s128 *n, s128 *d)
{
    s128 dx = b[0] - a[0], dy = b[1] - a[1], wx = p[0] - a[0], wy = p[1] - a[1];
    s128 dot = wx * dx + wy * dy, len2 = dx * dx + dy * dy;
    if (dot <= 0) {
        *n = wx * wx + wy * wy, *d = 1;
    } else if (dot >= len2) {
        s128 ux = p[0] - b[0], uy = p[1] - b[1];
        *n = ux * ux + uy * uy, *d = 1;
    } else {
        s128 c = wx * dy - wy * dx;
        *n = c * c, *d = len2;
    }
}

static long points_checked, nearest_bad;

static void check_point(world *w, const int64_t p[2], int64_t dmax)
{
    s128 bn = -1, bd = 1;
    uint64_t be = 0, bk = 0;
    s128 *en = malloc((w->edges + 1) * sizeof *en), *ed = malloc((w->edges + 1) * sizeof *ed);
    for (uint64_t e = 0; e < w->edges; e++) {
        int64_t a[2], b[2];
        en[e] = -1;
        edge_point(w, e, 0, a);
        for (uint64_t k = 0; k + 1 < w->npoints[e]; k++) {
            edge_point(w, e, k + 1, b);
            s128 n, d;
            sq_dist(p, a, b, &n, &d);
            if (en[e] < 0 || n * ed[e] < en[e] * d)
                en[e] = n, ed[e] = d;
            if (bn < 0 || n * bd < bn * d)
                bn = n, bd = d, be = e, bk = k;
            a[0] = b[0], a[1] = b[1];
        }
    }
    hpfc_nearest r;
    int st = hpfc_shapes_nearest_edge(w->s, p[0], p[1], HPFC_ID_NONE, &r);
    CHECK_EQ_INT(st, HPFC_OK);
    double want = sqrt((double)bn / (double)bd);
    int ok = !st && r.edge == be && r.segment == bk && fabs(r.distance - want) <= 1e-9 * (want + 1) &&
             fabs(hypot(r.x - (double)p[0], r.y - (double)p[1]) - want) <= 1e-6 * (want + 1);
    CHECK(ok);
    points_checked++;
    if (!ok && nearest_bad++ < 5)
        fprintf(stderr, "  point %lld,%lld: got edge %llu seg %llu d %.9g, want %llu seg %llu d %.9g\n",
                (long long)p[0], (long long)p[1], (unsigned long long)r.edge,
                (unsigned long long)r.segment, r.distance, (unsigned long long)be,
                (unsigned long long)bk, want);
    /* within d: every edge whose squared distance is at most d^2 */
    int64_t d = (int64_t)(want + 0.5) + (dmax ? (int64_t)(p[0] % dmax + dmax) % dmax : 0);
    hpfc_edge_hits h;
    CHECK_EQ_INT(hpfc_shapes_edges_within(w->s, p[0], p[1], d, &h), HPFC_OK);
    size_t k = 0;
    ok = 1;
    for (uint64_t e = 0; e < w->edges; e++) {
        if (en[e] > (s128)d * d * ed[e])
            continue;
        double de = sqrt((double)en[e] / (double)ed[e]);
        ok &= k < h.count && h.edge[k] == e && fabs(h.distance[k] - de) <= 1e-9 * (de + 1);
        k++;
    }
    ok &= k == h.count;
    CHECK(ok);
    if (!ok && nearest_bad++ < 5)
        fprintf(stderr, "  point %lld,%lld within %lld: %zu edges, want %zu\n", (long long)p[0],
                (long long)p[1], (long long)d, h.count, k);
    /* a feature's border: its nearest by the same test, over its edges */
    uint32_t g = (uint32_t)((uint64_t)(p[0] ^ p[1]) % NFEAT);
    st = hpfc_shapes_nearest_edge(w->s, p[0], p[1], g, &r);
    if (w->border[g].n == 0) {
        CHECK_EQ_INT(st, HPFC_E_ARG);
    } else {
        CHECK_EQ_INT(st, HPFC_OK);
        /* against the border's segments (the rings' points are the edges') */
        s128 fn = -1, fd = 1;
        for (size_t j = 0; j < w->border[g].n; j++) {
            s128 n, dd;
            const int64_t *c = w->border[g].s[j].c;
            sq_dist(p, c, c + 2, &n, &dd);
            if (fn < 0 || n * fd < fn * dd)
                fn = n, fd = dd;
        }
        double fw = sqrt((double)fn / (double)fd);
        ok = !st && fabs(r.distance - fw) <= 1e-9 * (fw + 1);
        CHECK(ok);
        if (!ok && nearest_bad++ < 5)
            fprintf(stderr, "  point %lld,%lld feature %u: %.9g, want %.9g\n", (long long)p[0],
                    (long long)p[1], g, r.distance, fw);
    }
    free(en);
    free(ed);
}

static int64_t between(gen_rng *r, int64_t lo, int64_t hi)
{
    return lo + (int64_t)gen_rng_below(r, (uint64_t)(hi - lo + 1));
}

static void check_nearest(world *w, gen_rng *r, int count)
{
    int64_t span = w->domain[2] - w->domain[0] + 1;
    for (int k = 0; k < count; k++) {
        int64_t p[2] = {between(r, w->domain[0] - span / 4, w->domain[2] + span / 4),
                        between(r, w->domain[1] - span / 4, w->domain[3] + span / 4)};
        check_point(w, p, k % 3 ? span / 8 + 1 : 0);
    }
    /* on the map: each edge's first shape point and its middle */
    for (uint64_t e = 0; e < w->edges && e < 40; e++) {
        int64_t a[2], b[2];
        edge_point(w, e, 0, a);
        edge_point(w, e, 1, b);
        check_point(w, a, 0);
        int64_t m[2] = {(a[0] + b[0]) / 2, (a[1] + b[1]) / 2};
        check_point(w, m, 3);
    }
}

/* ---- dissolve and mesh ---------------------------------------------------------- */

static s128 answer_area2(const hpfc_polygons *p)
{
    s128 a = 0;
    for (size_t r = 0; r < p->ring_count; r++)
        for (size_t k = p->ring_point[r]; k + 1 < p->ring_point[r + 1]; k++)
            a += (s128)p->xy[2 * k] * p->xy[2 * k + 3] - (s128)p->xy[2 * k + 2] * p->xy[2 * k + 1];
    return a;
}

static long sets_checked, sets_bad;

/* The union of features set[0 .. n): its segments and area. */
static void check_union(world *w, const hpfc_id *set, size_t n)
{
    uint8_t *in = calloc(w->faces + 1, 1);
    for (uint64_t f = 0; f < w->faces; f++)
        for (size_t k = 0; k < n; k++)
            in[f] |= face_has(w, f, (uint32_t)set[k]);
    segs want = {0}, got = {0};
    for (uint64_t e = 0; e < w->edges; e++)
        if (in[w->left[e]] != in[w->right[e]])
            edge_segs(w, e, &want);
    s128 area = 0;
    for (uint64_t f = 1; f < w->faces; f++) {
        hpfc_polygons p;
        if (in[f] && hpfc_shapes_face_polygons(w->s, f, &p) == HPFC_OK)
            area += answer_area2(&p);
    }
    hpfc_polygons p;
    int st = hpfc_shapes_features_polygons(w->s, set, n, &p);
    CHECK_EQ_INT(st, HPFC_OK);
    int ok = 0;
    if (!st) {
        answer_segs(&p, &got);
        segs_sort(&want);
        segs_sort(&got);
        ok = segs_equal(&want, &got) && answer_area2(&p) == area;
        for (size_t q = 0; q < p.polygon_count; q++) /* outer rings first, counter-clockwise */
            ok &= p.polygon_ring[q] < p.polygon_ring[q + 1];
    }
    CHECK(ok);
    sets_checked++;
    if (!ok && sets_bad++ < 5)
        fprintf(stderr, "  union of %zu features: %zu segments, want %zu\n", n, got.n, want.n);
    free(want.s), free(got.s), free(in);
}

/* The sorted groups of face f's features into g; their count. */
static size_t groups_of(const world *w, uint64_t f, const uint32_t *group, uint32_t *g)
{
    size_t n = 0;
    for (uint32_t k = w->fstart[f]; k < w->fstart[f + 1]; k++) {
        uint32_t v = group ? group[w->flinks[k]] : w->flinks[k];
        if (v == HPFC_GROUP_NONE)
            continue;
        size_t j = 0;
        while (j < n && g[j] < v)
            j++;
        if (j < n && g[j] == v)
            continue;
        memmove(g + j + 1, g + j, (n - j) * sizeof *g);
        g[j] = v, n++;
    }
    return n;
}

static void check_mesh(world *w, const uint32_t *group, unsigned sides)
{
    segs want = {0}, got = {0};
    for (uint64_t e = 0; e < w->edges; e++) {
        uint32_t gl[NFEAT], gr[NFEAT];
        if (w->left[e] == w->right[e])
            continue;
        size_t nl = groups_of(w, w->left[e], group, gl), nr = groups_of(w, w->right[e], group, gr);
        int keep = (sides & HPFC_MESH_EXTERIOR) && (nl == 0) != (nr == 0);
        if ((sides & HPFC_MESH_INTERIOR) && nl && nr)
            keep |= nl != nr || memcmp(gl, gr, nl * sizeof *gl);
        if (keep)
            edge_segs(w, e, &want);
    }
    hpfc_polygons p;
    int st = hpfc_shapes_mesh(w->s, group, NFEAT, sides, &p);
    CHECK_EQ_INT(st, HPFC_OK);
    int ok = 0;
    if (!st) {
        answer_segs(&p, &got);
        segs_sort(&want);
        segs_sort(&got);
        ok = segs_equal(&want, &got) && p.polygon_count == 0;
    }
    CHECK(ok);
    sets_checked++;
    if (!ok && sets_bad++ < 5)
        fprintf(stderr, "  mesh %u: %zu segments, want %zu\n", sides, got.n, want.n);
    free(want.s), free(got.s);
}

static void check_sets(world *w, gen_rng *r)
{
    /* by a field: the polygon features in three groups */
    for (uint32_t v = 0; v < 3; v++) {
        hpfc_id set[NPOLY];
        size_t n = 0;
        for (uint32_t g = 0; g < NPOLY; g++)
            if (g % 3 == v)
                set[n++] = g;
        check_union(w, set, n);
    }
    for (int k = 0; k < 8; k++) {
        hpfc_id set[6];
        size_t n = (size_t)gen_rng_below(r, 6);
        for (size_t j = 0; j < n; j++)
            set[j] = gen_rng_below(r, FIRST_LINE);
        check_union(w, set, n);
    }
    uint32_t field[NFEAT];
    for (uint32_t g = 0; g < NFEAT; g++)
        field[g] = g < NPOLY ? g % 3 : HPFC_GROUP_NONE;
    unsigned kinds[3] = {HPFC_MESH_INTERIOR, HPFC_MESH_EXTERIOR,
                         HPFC_MESH_INTERIOR | HPFC_MESH_EXTERIOR};
    for (int k = 0; k < 3; k++) {
        check_mesh(w, NULL, kinds[k]);
        check_mesh(w, field, kinds[k]);
    }
}

/* ---- one file ---------------------------------------------------------------------- */

static void bad_arguments(world *w)
{
    hpfc_neighbours nb;
    hpfc_adjacency adj;
    hpfc_nearest r;
    hpfc_edge_hits h;
    hpfc_polygons p;
    hpfc_id past = NFEAT;
    uint32_t group[NFEAT] = {0};
    CHECK_EQ_INT(hpfc_shapes_feature_neighbours(w->s, NFEAT, &nb), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_shapes_feature_neighbours(w->s, 0, NULL), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_shapes_adjacency(w->s, 0, &adj), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_shapes_adjacency(w->s, HPFC_TOUCH_VERTEX, &adj), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_shapes_adjacency(w->s, 8 | HPFC_TOUCH_EDGE, &adj), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_shapes_nearest_edge(w->s, HPFC_LATTICE_MAX + 1, 0, HPFC_ID_NONE, &r),
                 HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_shapes_nearest_edge(w->s, 0, -HPFC_LATTICE_MAX - 1, HPFC_ID_NONE, &r),
                 HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_shapes_nearest_edge(w->s, 0, 0, NFEAT, &r), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_shapes_edges_within(w->s, 0, 0, -1, &h), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_shapes_edges_within(w->s, 0, 0, 2 * HPFC_LATTICE_MAX + 1, &h), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_shapes_features_polygons(w->s, &past, 1, &p), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_shapes_features_polygons(w->s, NULL, 1, &p), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_shapes_mesh(w->s, group, NFEAT - 1, HPFC_MESH_INTERIOR, &p), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_shapes_mesh(w->s, group, NFEAT, 0, &p), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_shapes_mesh(w->s, group, NFEAT, 4, &p), HPFC_E_ARG);
    /* the empty set is no polygon */
    CHECK_EQ_INT(hpfc_shapes_features_polygons(w->s, NULL, 0, &p), HPFC_OK);
    CHECK(p.ring_count == 0);
}

/* refine: the refined images' side (2: the default; above 16, images of
 * more than 256 pixels, which the nearest-edge search visits unsorted) */
static void run_map(const char *name, const hpfc_graph *g, uint32_t n0, uint32_t refine,
                    uint64_t seed)
{
    hpfc_build_params bp;
    hpfc_build_params_default(&bp);
    bp.root_cols = bp.root_rows = n0;
    bp.cols = bp.rows = refine;
    uint8_t *buf = NULL, *buf2 = NULL;
    size_t size, size2;
    hpfc_file *f = NULL;
    int st = check_labelled_file(g, &bp, &buf, &size, &f);
    CHECK_EQ_INT(st, HPFC_OK);
    if (st)
        return;
    hpfc_faces *fc;
    CHECK_EQ_INT(hpfc_faces_build(f, &fc), HPFC_OK);
    uint64_t nf = hpfc_faces_face_count(fc);
    hpfc_faces_free(fc);
    size_t ne = hpfc_graph_edge_count(g);
    gen_rng r;
    gen_rng_seed(&r, seed);
    world w = {.faces = nf, .edges = ne};
    w.fstart = calloc(nf + 1, sizeof *w.fstart), w.flinks = malloc(3 * nf * 4 + 4);
    w.estart = calloc(ne + 1, sizeof *w.estart), w.elinks = malloc(2 * ne * 4 + 4);
    uint32_t nl = 0;
    for (uint64_t face = 0; face < nf; face++) {
        w.fstart[face] = nl;
        if (!face)
            continue;
        w.flinks[nl++] = (uint32_t)gen_rng_below(&r, NPOLY); /* a partition */
        for (uint32_t k = NPOLY; k < FIRST_LINE; k++) /* two that overlap it */
            if (gen_rng_below(&r, 5) == 0)
                w.flinks[nl++] = k;
    }
    w.fstart[nf] = nl;
    nl = 0;
    for (size_t e = 0; e < ne; e++) {
        w.estart[e] = nl;
        if (gen_rng_below(&r, 6) == 0)
            w.elinks[nl++] = FIRST_LINE + (uint32_t)gen_rng_below(&r, NFEAT - FIRST_LINE);
    }
    w.estart[ne] = nl;
    int64_t fid[NFEAT];
    uint32_t layer[NFEAT] = {0};
    for (int k = 0; k < NFEAT; k++)
        fid[k] = k;
    const char *lname[1] = {"random"};
    hpfc_feature_table ft = {.feature_count = NFEAT, .fid = fid, .layer = layer, .layer_count = 1,
                             .layer_name = lname, .face_count = (uint32_t)nf,
                             .face_start = w.fstart, .face_feature = w.flinks};
    hpfc_edge_feature_table eft = {.edge_count = (uint32_t)ne, .feature_count = NFEAT,
                                   .edge_start = w.estart, .edge_feature = w.elinks};
    hpfc_write_options o2 = {.features = &ft, .edge_features = &eft};
    st = hpfc_file_serialize(f, &o2, &buf2, &size2, NULL);
    if (!st)
        st = hpfc_open_memory(buf2, size2, 0, &w.f);
    if (!st)
        st = hpfc_shapes_create(w.f, &w.s);
    CHECK_EQ_INT(st, HPFC_OK);
    if (!st) {
        hpfc_file_info fi;
        hpfc_file_get_info(w.f, &fi);
        w.domain[0] = fi.x0, w.domain[1] = fi.y0;
        w.domain[2] = fi.x0 + fi.width - 1, w.domain[3] = fi.y0 + fi.height - 1;
        w.left = malloc(ne * 8 + 8), w.right = malloc(ne * 8 + 8), w.npoints = malloc(ne * 8 + 8);
        for (size_t e = 0; e < ne; e++) {
            uint64_t u, v;
            CHECK_EQ_INT(hpfc_geometry_edge(w.f, e, &u, &v, &w.npoints[e]), HPFC_OK);
            CHECK_EQ_INT(hpfc_geometry_edge_faces(w.f, e, &w.left[e], &w.right[e]), HPFC_OK);
        }
        long before = neighbour_bad + nearest_bad + sets_bad;
        check_neighbours(&w);
        check_nearest(&w, &r, 60);
        check_sets(&w, &r);
        bad_arguments(&w);
        if (neighbour_bad + nearest_bad + sets_bad > before)
            fprintf(stderr, "  in %s, root %ux%u\n", name, n0, n0);
        hpfc_shapes_free(w.s);
        free(w.left), free(w.right), free(w.npoints);
        for (int k = 0; k < NFEAT; k++)
            free(w.border[k].s), free(w.points[k].s);
    }
    /* without features: the nearest edge still, the rest need FEAT */
    hpfc_shapes *s0;
    if (hpfc_shapes_create(f, &s0) == HPFC_OK) {
        hpfc_neighbours nb;
        hpfc_nearest nr;
        hpfc_polygons p;
        CHECK_EQ_INT(hpfc_shapes_feature_neighbours(s0, 0, &nb), HPFC_E_NO_SECTION);
        CHECK_EQ_INT(hpfc_shapes_nearest_edge(s0, 0, 0, 0, &nr), HPFC_E_NO_SECTION);
        CHECK_EQ_INT(hpfc_shapes_nearest_edge(s0, 0, 0, HPFC_ID_NONE, &nr), HPFC_OK);
        CHECK_EQ_INT(hpfc_shapes_mesh(s0, NULL, 0, HPFC_MESH_INTERIOR, &p), HPFC_E_NO_SECTION);
        hpfc_shapes_free(s0);
    }
    hpfc_close(w.f);
    hpfc_close(f);
    hpfc_free(buf2);
    hpfc_free(buf);
    free(w.fstart), free(w.flinks), free(w.estart), free(w.elinks);
}

int main(void)
{
    check_use_test_layout();
    for (int k = 0; k < GEN_SPECIAL_COUNT; k++) {
        hpfc_graph *g;
        if (gen_special(k, &g))
            continue;
        run_map(gen_special_name(k), g, 4, 2, (uint64_t)k + 1);
        hpfc_graph_free(g);
    }
    for (uint64_t seed = 1; seed <= 5; seed++) {
        hpfc_graph *g;
        if (!gen_delaunay(seed, 120 + 40 * seed, 2000, 0.3, &g)) {
            run_map("delaunay", g, seed % 2 ? 4 : 16, 2, seed);
            run_map("delaunay 1x1", g, 1, seed == 1 ? 17 : 2, seed + 100);
            hpfc_graph_free(g);
        }
        if (!gen_polyline(seed, 200, 3000, 0.5, &g)) {
            run_map("polyline", g, 8, seed == 2 ? 20 : 3, seed + 200);
            hpfc_graph_free(g);
        }
    }
    printf("%ld feature pairs, %ld wrong; %ld points, %ld wrong; %ld unions and meshes, %ld wrong\n",
           pairs_checked, neighbour_bad, points_checked, nearest_bad, sets_checked, sets_bad);
    return check_report("queries");
}
