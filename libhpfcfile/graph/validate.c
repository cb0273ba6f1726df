/*
 * Exact validation of a graph as a planar embedding (hpfc_graph_validate):
 * each edge on its own (loops, zero-length segments), then the whole-graph
 * checks the .pfc reader runs too (graph_check.c), then planarity.
 *
 * Planarity is checked by bucketing segments into a grid of about one cell
 * per segment (with the same exact segment/cell test the builder uses, so
 * a contact point always lies in a cell both segments meet) and testing
 * the pairs inside each cell with exact orientation predicates. The grid's
 * columns and rows are cut at quantiles of a sample of the segments, not
 * evenly over the box: a city's streets and one stray edge far away (a
 * feature at null island) would otherwise share a single cell. A dense
 * cell is swept, and a vertex of high degree in it (which no grid splits)
 * is checked by sorting its segments around it.
 * The cells can be searched on several threads (tasks.h); the conflict
 * named is the first in cell order either way.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "arrays.h"
#include "graph.h"
#include "road.h"
#include "tasks.h"

/* Describes edge e for a message: "edge 3 (line 12)" or "edge 3". */
static void describe_edge(const hpfc_graph *g, size_t e, char *buf, size_t size)
{
    if (graph_edge_line(g, e))
        snprintf(buf, size, "edge %zu (line %u)", e, graph_edge_line(g, e));
    else
        snprintf(buf, size, "edge %zu", e);
}

static void diag_edges(hpfc_diag *diag, const hpfc_graph *g, int64_t e0, int64_t e1)
{
    if (diag) {
        diag->edge[0] = e0;
        diag->edge[1] = e1;
        diag->line = e0 >= 0 ? graph_edge_line(g, e0) : 0;
    }
}

static int check_edges_locally(const hpfc_graph *g, hpfc_diag *diag)
{
    char what[64];
    for (size_t e = 0; e < g->ne; e++) {
        size_t np = graph_edge_point_count(g, e);
        if (g->eu[e] == g->ev[e] && np < 4) {
            describe_edge(g, e, what, sizeof what);
            diag_edges(diag, g, (int64_t)e, -1);
            return diag_set(diag, HPFC_E_LOOP_INTERIOR,
                            "%s is a loop with fewer than two interior points", what);
        }
        for (size_t k = 0; k + 1 < np; k++) {
            int64_t ax, ay, bx, by;
            graph_edge_point(g, e, k, &ax, &ay);
            graph_edge_point(g, e, k + 1, &bx, &by);
            if (ax == bx && ay == by) {
                describe_edge(g, e, what, sizeof what);
                diag_edges(diag, g, (int64_t)e, -1);
                diag_point(diag, (double)ax, (double)ay, g->unit_exp10);
                return diag_set(diag, HPFC_E_ZERO_LENGTH,
                                "%s has a zero-length segment at (%.17g, %.17g)",
                                what, diag ? diag->x : 0.0, diag ? diag->y : 0.0);
            }
        }
    }
    return HPFC_OK;
}

/* ---- planarity ---------------------------------------------------------- */

/* Segment k of edge `edge` (from its point k to point k + 1). The grid
 * holds these, 8 bytes an incidence, and reads the points from the graph:
 * a copy of every segment's ends took 40 bytes a segment more (8 GB at
 * 2*10^8 shape points). */
typedef struct seg_ref {
    uint32_t edge, k;
} seg_ref;

static bool on_segment(lpoint a, lpoint b, lpoint p)
{
    /* p is collinear with ab: is it within ab's bounding box? */
    return p.x >= (a.x < b.x ? a.x : b.x) && p.x <= (a.x > b.x ? a.x : b.x) &&
           p.y >= (a.y < b.y ? a.y : b.y) && p.y <= (a.y > b.y ? a.y : b.y);
}

static bool same_point(lpoint a, lpoint b)
{
    return a.x == b.x && a.y == b.y;
}

/* Do segments ab and cd meet anywhere other than at one shared end point
 * (where they may only meet without overlapping)? On conflict *at is a
 * contact point (approximate for a proper crossing, in lattice units). */
static bool segments_conflict(lpoint a, lpoint b, lpoint c, lpoint d, double at[2])
{
    int shared = same_point(a, c) + same_point(a, d) + same_point(b, c) + same_point(b, d);
    if (shared >= 2) {            /* the same segment twice */
        at[0] = (double)a.x, at[1] = (double)a.y;
        return true;
    }
    if (shared == 1) {
        lpoint p = same_point(a, c) || same_point(a, d) ? a : b;
        lpoint u = same_point(p, a) ? b : a;
        lpoint v = same_point(p, c) ? d : c;
        i128 dot = (i128)(u.x - p.x) * (v.x - p.x) + (i128)(u.y - p.y) * (v.y - p.y);
        if (orient(p, u, v) == 0 && dot > 0) {
            lpoint nearer = (i128)(u.x - p.x) * (u.x - p.x) + (i128)(u.y - p.y) * (u.y - p.y) <
                                    (i128)(v.x - p.x) * (v.x - p.x) + (i128)(v.y - p.y) * (v.y - p.y)
                                ? u
                                : v;
            at[0] = (double)nearer.x, at[1] = (double)nearer.y;
            return true;
        }
        return false;
    }
    int o1 = orient(a, b, c), o2 = orient(a, b, d);
    int o3 = orient(c, d, a), o4 = orient(c, d, b);
    if (o1 * o2 < 0 && o3 * o4 < 0) {
        /* proper crossing: the point is for the message only */
        double den = (double)(b.x - a.x) * (double)(d.y - c.y) - (double)(b.y - a.y) * (double)(d.x - c.x);
        double t = ((double)(c.x - a.x) * (double)(d.y - c.y) - (double)(c.y - a.y) * (double)(d.x - c.x)) / den;
        at[0] = (double)a.x + t * (double)(b.x - a.x);
        at[1] = (double)a.y + t * (double)(b.y - a.y);
        return true;
    }
    const lpoint *cand[4] = {&c, &d, &a, &b};
    int ors[4] = {o1, o2, o3, o4};
    for (int i = 0; i < 4; i++) {
        const lpoint *s0 = i < 2 ? &a : &c, *s1 = i < 2 ? &b : &d;
        if (ors[i] == 0 && on_segment(*s0, *s1, *cand[i])) {
            at[0] = (double)cand[i]->x, at[1] = (double)cand[i]->y;
            return true;
        }
    }
    return false;
}

typedef struct bucket_grid {
    const hpfc_graph *g;
    int64_t ox, oy;
    /* cell (c, r) is [xs[c], xs[c + 1]) x [ys[r], ys[r + 1]) relative to
     * (ox, oy): cols + 1 and rows + 1 increasing bounds, the first 0 and
     * the last past the box */
    int64_t *xs, *ys;
    size_t cols, rows;
    size_t *start;     /* cols*rows + 1 offsets into items */
    seg_ref *items;    /* each cell's segments, cell after cell */
} bucket_grid;

/* An end of a segment, relative to the grid's origin. */
static lpoint seg_point(const bucket_grid *bg, seg_ref s, int end)
{
    int64_t x, y;
    graph_edge_point(bg->g, s.edge, (size_t)s.k + (size_t)end, &x, &y);
    return (lpoint){x - bg->ox, y - bg->oy};
}

/* The band (column or row) holding coordinate v among bands lo .. hi - 1,
 * given bounds[lo] <= v < bounds[hi]: the last whose lower bound is at
 * most v. */
static size_t band_within(const int64_t *bounds, size_t lo, size_t hi, int64_t v)
{
    while (hi - lo > 1) {
        size_t mid = lo + (hi - lo) / 2;
        if (bounds[mid] <= v)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

/* The band of the n (bounds[0] = 0 <= v < bounds[n]) holding v, searched
 * outward from band `near` in growing steps: a polyline's next point is
 * almost always in the band of the last or the next one, where this costs
 * a comparison or two and a search from scratch a dozen. */
static size_t band_near(const int64_t *bounds, size_t n, int64_t v, size_t near)
{
    size_t lo = near, hi, step = 1;
    if (bounds[near] <= v) {
        for (hi = near + 1; hi < n && bounds[hi] <= v; step *= 2)
            lo = hi, hi = n - hi > step ? hi + step : n;
        return band_within(bounds, lo, hi, v);
    }
    hi = near;
    for (lo = near - 1; lo > 0 && bounds[lo] > v; step *= 2)
        hi = lo, lo = lo > step ? lo - step : 0;
    return band_within(bounds, lo, hi, v);
}

/* A segment's cells: the columns c0 .. c1 and rows r0 .. r1 of its box. */
typedef struct seg_cells {
    size_t c0, c1, r0, r1;
} seg_cells;

/* Calls fn(cell, segment) for every cell of span b the segment meets. */
static void for_each_cell(bucket_grid *bg, seg_ref s, lpoint p, lpoint q, seg_cells b,
                          void (*fn)(bucket_grid *, size_t, seg_ref))
{
    for (size_t r = b.r0; r <= b.r1; r++)
        for (size_t c = b.c0; c <= b.c1; c++)
            if ((b.c0 == b.c1 && b.r0 == b.r1) ||
                segment_meets_cell(p, q, bg->xs[c], bg->ys[r], bg->xs[c + 1], bg->ys[r + 1]))
                fn(bg, r * bg->cols + c, s);
}

static void count_incidence(bucket_grid *bg, size_t cell, seg_ref s)
{
    (void)s;
    bg->start[cell + 1]++;
}

static void place_incidence(bucket_grid *bg, size_t cell, seg_ref s)
{
    bg->items[bg->start[cell]++] = s;
}

/* Every segment of the graph, in edge order, each point's column and row
 * found from its predecessor's. */
static void for_each_segment(bucket_grid *bg, void (*fn)(bucket_grid *, size_t, seg_ref))
{
    size_t col = 0, row = 0;
    for (size_t e = 0; e < bg->g->ne; e++) {
        seg_ref s = {(uint32_t)e, 0};
        lpoint p = seg_point(bg, s, 0);
        col = band_near(bg->xs, bg->cols, p.x, col);
        row = band_near(bg->ys, bg->rows, p.y, row);
        for (size_t k = 0; k + 1 < graph_edge_point_count(bg->g, e); k++) {
            s.k = (uint32_t)k;
            lpoint q = seg_point(bg, s, 1);
            size_t qcol = band_near(bg->xs, bg->cols, q.x, col);
            size_t qrow = band_near(bg->ys, bg->rows, q.y, row);
            seg_cells b = {col < qcol ? col : qcol, col > qcol ? col : qcol,
                           row < qrow ? row : qrow, row > qrow ? row : qrow};
            for_each_cell(bg, s, p, q, b, fn);
            p = q, col = qcol, row = qrow;
        }
    }
}

/* floor(sqrt(n)), in integers (the reader, which validates a GEOM section's
 * graph, links no libm): Newton's iteration from above. */
static size_t integer_sqrt(size_t n)
{
    if (n < 2)
        return n;
    size_t x = n, y = (x + 1) / 2;
    while (y < x) {
        x = y;
        y = (x + n / x) / 2;
    }
    return x;
}

/* At most this many segments are sampled to place the grid's bounds:
 * 2 MB, and at 2*10^8 segments still about nine a column. */
#ifdef FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION
#define BOUNDS_SAMPLE_MAX 64 /* fuzzed graphs are small: sampled even so */
#else
#define BOUNDS_SAMPLE_MAX (1u << 17)
#endif

static int cmp_int64(const void *pa, const void *pb)
{
    int64_t a = *(const int64_t *)pa, b = *(const int64_t *)pb;
    return (a > b) - (a < b);
}

/* Up to `side` bands over [0, extent) cut at quantiles of the m sorted
 * sample coordinates (relative to the origin), equal cuts merged: the
 * bounds into out (at most side + 1 of them); returns the band count. */
static size_t bands_from_sample(const int64_t *sample, size_t m, size_t side, int64_t extent,
                                int64_t *out)
{
    size_t n = 0;
    out[0] = 0;
    for (size_t i = 1; i < side; i++) {
        int64_t cut = sample[(size_t)((uint64_t)i * m / side)];
        if (cut > out[n] && cut < extent)
            out[++n] = cut;
    }
    out[++n] = extent;
    return n;
}

/* The grid's bounds: each segment's first point sampled (every stride-th
 * segment, in edge order), then the columns and rows cut where the sample
 * puts about the same number of segments in each. */
static int place_bounds(bucket_grid *bg, size_t segments, size_t side, const int64_t box[4])
{
    size_t stride = segments / BOUNDS_SAMPLE_MAX + 1, m = 0, i = 0, most = segments / stride + 1;
    int64_t *sx = malloc(most * sizeof *sx);
    int64_t *sy = malloc(most * sizeof *sy);
    /* bounds: at most one a distinct sample value, and side + 1 */
    most = (side > most ? side : most) + 2;
    bg->xs = malloc(most * sizeof *bg->xs);
    bg->ys = malloc(most * sizeof *bg->ys);
    int st = sx && sy && bg->xs && bg->ys ? HPFC_OK : HPFC_E_NOMEM;
    for (size_t e = 0; !st && e < bg->g->ne; e++)
        for (size_t k = 0; k + 1 < graph_edge_point_count(bg->g, e); k++, i++)
            if (i % stride == 0) {
                lpoint p = seg_point(bg, (seg_ref){(uint32_t)e, (uint32_t)k}, 0);
                sx[m] = p.x, sy[m++] = p.y;
            }
    if (!st) {
        qsort(sx, m, sizeof *sx, cmp_int64);
        qsort(sy, m, sizeof *sy, cmp_int64);
        int64_t width = box[2] - box[0] + 1, height = box[3] - box[1] + 1;
        bg->cols = bands_from_sample(sx, m, side, width, bg->xs);
        bg->rows = bands_from_sample(sy, m, side, height, bg->ys);
        /* a map whose points share few x (or y) values: the other axis
         * takes the cells this one could not use */
        if (bg->cols < side)
            bg->rows = bands_from_sample(sy, m, segments / bg->cols + 1, height, bg->ys);
        else if (bg->rows < side)
            bg->cols = bands_from_sample(sx, m, segments / bg->rows + 1, width, bg->xs);
    }
    free(sx);
    free(sy);
    return st;
}

static int build_buckets(const hpfc_graph *g, size_t segments, bucket_grid *bg)
{
    int64_t box[4];
    hpfc_graph_bounds(g, box); /* a graph with an edge has a vertex */
    bg->g = g;
    bg->ox = box[0], bg->oy = box[1];
    int st = place_bounds(bg, segments, integer_sqrt(segments) + 1, box);
    if (st)
        return st;
    size_t cells = bg->cols * bg->rows;
    bg->start = calloc(cells + 2, sizeof *bg->start);
    if (!bg->start)
        return HPFC_E_NOMEM;
    for_each_segment(bg, count_incidence);
    for (size_t c = 0; c < cells; c++)
        bg->start[c + 1] += bg->start[c];
    size_t incidences = bg->start[cells];
    bg->items = incidences <= SIZE_MAX / sizeof *bg->items
                    ? malloc((incidences ? incidences : 1) * sizeof *bg->items)
                    : NULL;
    if (!bg->items)
        return HPFC_E_NOMEM;
    for_each_segment(bg, place_incidence);
    /* place_incidence advanced each start to the next cell's start */
    memmove(bg->start + 1, bg->start, cells * sizeof *bg->start);
    bg->start[0] = 0;
    return HPFC_OK;
}

static int report_conflict(const bucket_grid *bg, seg_ref s1, seg_ref s2, const double at[2],
                           hpfc_diag *diag)
{
    char a[64], b[64];
    uint32_t e1 = s1.edge, e2 = s2.edge;
    if (e1 > e2) {
        uint32_t tmp = e1;
        e1 = e2, e2 = tmp;
    }
    describe_edge(bg->g, e1, a, sizeof a);
    describe_edge(bg->g, e2, b, sizeof b);
    diag_edges(diag, bg->g, e1, e2);
    diag_point(diag, at[0] + (double)bg->ox, at[1] + (double)bg->oy, bg->g->unit_exp10);
    if (e1 == e2)
        return diag_set(diag, HPFC_E_NONPLANAR, "%s intersects itself at (%.17g, %.17g)", a,
                        diag ? diag->x : 0.0, diag ? diag->y : 0.0);
    return diag_set(diag, HPFC_E_NONPLANAR, "%s and %s cross or touch at (%.17g, %.17g)", a, b,
                    diag ? diag->x : 0.0, diag ? diag->y : 0.0);
}

/* The pairs of one cell. Two segments that conflict share a point, so
 * their closed boxes meet: the box test, a few comparisons, spares the
 * orientation predicates of most pairs. Exact either way. */
static bool boxes_meet(lpoint a, lpoint b, lpoint c, lpoint d)
{
    return (a.x < b.x ? a.x : b.x) <= (c.x > d.x ? c.x : d.x) &&
           (c.x < d.x ? c.x : d.x) <= (a.x > b.x ? a.x : b.x) &&
           (a.y < b.y ? a.y : b.y) <= (c.y > d.y ? c.y : d.y) &&
           (c.y < d.y ? c.y : d.y) <= (a.y > b.y ? a.y : b.y);
}

static bool pair_conflicts(const bucket_grid *bg, seg_ref s1, seg_ref s2, double at[2])
{
    lpoint a = seg_point(bg, s1, 0), b = seg_point(bg, s1, 1);
    lpoint c = seg_point(bg, s2, 0), d = seg_point(bg, s2, 1);
    return boxes_meet(a, b, c, d) && segments_conflict(a, b, c, d, at);
}

/* A conflicting pair found in a cell, and where they meet. */
typedef struct conflict {
    seg_ref a, b;
    double at[2];
} conflict;

static bool test_pair(const bucket_grid *bg, seg_ref s1, seg_ref s2, conflict *out)
{
    if (!pair_conflicts(bg, s1, s2, out->at))
        return false;
    out->a = s1, out->b = s2;
    return true;
}

/* The first pair of a small cell that conflicts, in the cell's order. */
static bool first_conflict(const bucket_grid *bg, const seg_ref *items, size_t k, conflict *out)
{
    for (size_t i = 0; i < k; i++)
        for (size_t j = i + 1; j < k; j++)
            if (test_pair(bg, items[i], items[j], out))
                return true;
    return false;
}

/* A dense cell (a coastline's detail finer than the sample saw, or the
 * segments around a vertex of high degree) is swept instead: its segments
 * sorted by their boxes' west side, each tested only against those that
 * start before it ends. Where that would still test many pairs and one
 * point ends many of the cell's segments (a hub: a vertex of high degree,
 * which no grid splits), the hub's spokes are tested against each other
 * by sorting them around it (two spokes conflict only when they leave the
 * hub in the same direction), and each other segment against them. */
typedef struct swept_seg {
    int64_t x0, x1;
    seg_ref s;
} swept_seg;

/* A hub's spoke: its direction from the hub. */
typedef struct spoke {
    int64_t dx, dy;
    seg_ref s;
} spoke;

typedef struct cell_scratch {
    swept_seg *sweep, *rest;
    lpoint *ends;
    spoke *spokes;
    size_t cap_sweep, cap_rest, cap_ends, cap_spokes;
} cell_scratch;

#ifdef FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION
#define SWEEP_FROM 2     /* fuzzed graphs are small: sweep almost every cell */
#define HUB_MIN 3        /* and look for hubs in them */
#define HUB_PAIRS_PER 0
#else
#define SWEEP_FROM 32
#define HUB_MIN 32       /* spokes that make a hub */
#define HUB_PAIRS_PER 8  /* a hub is looked for past this many pairs a segment */
#endif

static int cmp_swept(const void *pa, const void *pb)
{
    const swept_seg *a = pa, *b = pb;
    return (a->x0 > b->x0) - (a->x0 < b->x0);
}

static int cmp_lpoint(const void *pa, const void *pb)
{
    const lpoint *a = pa, *b = pb;
    if (a->x != b->x)
        return a->x < b->x ? -1 : 1;
    return (a->y > b->y) - (a->y < b->y);
}

/* Directions around a point: the upper half-plane (y > 0, or y = 0 and
 * x > 0) first, then by orientation; equal for the same direction. */
static int cmp_spoke(const void *pa, const void *pb)
{
    const spoke *a = pa, *b = pb;
    int ha = a->dy < 0 || (a->dy == 0 && a->dx < 0), hb = b->dy < 0 || (b->dy == 0 && b->dx < 0);
    if (ha != hb)
        return ha - hb;
    i128 cross = (i128)a->dx * b->dy - (i128)a->dy * b->dx;
    return cross > 0 ? -1 : cross < 0;
}

/* The pairs whose x ranges overlap, sweep sorted by x0: a count that stops
 * past `most`. */
static size_t overlapping_pairs(const swept_seg *sweep, size_t k, size_t most)
{
    size_t pairs = 0;
    for (size_t i = 0; i < k && pairs <= most; i++) {
        size_t lo = i + 1, hi = k; /* the first after i starting past its end */
        while (lo < hi) {
            size_t mid = lo + (hi - lo) / 2;
            if (sweep[mid].x0 <= sweep[i].x1)
                lo = mid + 1;
            else
                hi = mid;
        }
        pairs += lo - i - 1;
    }
    return pairs;
}

/* The point that ends the most of the k segments, and how many it ends. */
static size_t find_hub(const bucket_grid *bg, const swept_seg *sweep, size_t k, lpoint *ends,
                       lpoint *hub)
{
    for (size_t i = 0; i < k; i++)
        ends[2 * i] = seg_point(bg, sweep[i].s, 0), ends[2 * i + 1] = seg_point(bg, sweep[i].s, 1);
    qsort(ends, 2 * k, sizeof *ends, cmp_lpoint);
    size_t best = 0;
    for (size_t i = 0, j; i < 2 * k; i = j) {
        for (j = i + 1; j < 2 * k && cmp_lpoint(&ends[i], &ends[j]) == 0; j++)
            ;
        if (j - i > best)
            best = j - i, *hub = ends[i];
    }
    return best;
}

/* The pairs of `sweep` (sorted by x0) whose x ranges overlap. */
static bool sweep_pairs(const bucket_grid *bg, const swept_seg *sweep, size_t k, conflict *out)
{
    for (size_t i = 0; i < k; i++)
        for (size_t j = i + 1; j < k && sweep[j].x0 <= sweep[i].x1; j++)
            if (test_pair(bg, sweep[i].s, sweep[j].s, out))
                return true;
    return false;
}

/* The hub's spokes against each other (sorted around it, neighbours in
 * the same direction: two segments from one point meet elsewhere only
 * along one line), then every other segment against the spokes and the
 * others whose x ranges overlap its own. cs->sweep holds the cell's k
 * segments by x0; the spokes are moved to its front in place (each
 * written at an index no later than the one read), still by x0, and the
 * others into cs->rest. */
static bool hub_pairs(const bucket_grid *bg, size_t k, lpoint hub, cell_scratch *cs, conflict *out)
{
    swept_seg *sweep = cs->sweep;
    size_t nspokes = 0, nrest = 0;
    for (size_t i = 0; i < k; i++) {
        lpoint a = seg_point(bg, sweep[i].s, 0), b = seg_point(bg, sweep[i].s, 1);
        if (same_point(a, hub) || same_point(b, hub)) {
            lpoint far = same_point(a, hub) ? b : a;
            cs->spokes[nspokes] = (spoke){far.x - hub.x, far.y - hub.y, sweep[i].s};
            sweep[nspokes++] = sweep[i];
        } else {
            cs->rest[nrest++] = sweep[i];
        }
    }
    qsort(cs->spokes, nspokes, sizeof *cs->spokes, cmp_spoke);
    for (size_t i = 0; i + 1 < nspokes; i++)
        if (cmp_spoke(&cs->spokes[i], &cs->spokes[i + 1]) == 0 &&
            test_pair(bg, cs->spokes[i].s, cs->spokes[i + 1].s, out))
            return true;
    if (sweep_pairs(bg, cs->rest, nrest, out))
        return true;
    for (size_t r = 0; r < nrest; r++)
        for (size_t i = 0; i < nspokes && sweep[i].x0 <= cs->rest[r].x1; i++)
            if (sweep[i].x1 >= cs->rest[r].x0 && test_pair(bg, sweep[i].s, cs->rest[r].s, out))
                return true;
    return false;
}

static bool cell_conflicts_swept(const bucket_grid *bg, const seg_ref *items, size_t k,
                                 cell_scratch *cs, bool *no_room, conflict *out)
{
    if (array_reserve((void **)&cs->sweep, &cs->cap_sweep, k, sizeof *cs->sweep, 64)) {
        *no_room = true;
        return true;
    }
    swept_seg *sweep = cs->sweep;
    for (size_t i = 0; i < k; i++) {
        lpoint a = seg_point(bg, items[i], 0), b = seg_point(bg, items[i], 1);
        sweep[i] = (swept_seg){a.x < b.x ? a.x : b.x, a.x > b.x ? a.x : b.x, items[i]};
    }
    qsort(sweep, k, sizeof *sweep, cmp_swept);
    size_t most = HUB_PAIRS_PER * k;
    if (k < HUB_MIN || overlapping_pairs(sweep, k, most) <= most)
        return sweep_pairs(bg, sweep, k, out);
    if (array_reserve((void **)&cs->ends, &cs->cap_ends, 2 * k, sizeof *cs->ends, 64) ||
        array_reserve((void **)&cs->rest, &cs->cap_rest, k, sizeof *cs->rest, 64) ||
        array_reserve((void **)&cs->spokes, &cs->cap_spokes, k, sizeof *cs->spokes, 64)) {
        *no_room = true;
        return true;
    }
    lpoint hub;
    if (find_hub(bg, sweep, k, cs->ends, &hub) < HUB_MIN)
        return sweep_pairs(bg, sweep, k, out);
    return hub_pairs(bg, k, hub, cs, out);
}

static bool cell_conflicts(const bucket_grid *bg, size_t c, cell_scratch *cs, bool *no_room,
                           conflict *out)
{
    const seg_ref *items = bg->items + bg->start[c];
    size_t k = bg->start[c + 1] - bg->start[c];
    if (k <= SWEEP_FROM)
        return first_conflict(bg, items, k, out);
    return cell_conflicts_swept(bg, items, k, cs, no_room, out);
}

/* The cells are searched in runs, 16 a thread (so that a thread that meets
 * dense cells does not hold the others up) of at least RUN_CELLS_MIN
 * cells, shared by the threads: each run finds its first cell holding a
 * conflict, and the first such run's names the conflict, as one thread
 * going through the cells in order would. */
#ifdef FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION
#define RUN_CELLS_MIN 2 /* fuzzed graphs are small: many runs even so */
#else
#define RUN_CELLS_MIN 16
#endif

typedef struct cell_search {
    const bucket_grid *bg;
    size_t cells, run_cells;
    size_t *found;           /* per run: its first cell with a conflict, or SIZE_MAX */
    conflict *pair;          /* per run: the pair that cell's search found */
    unsigned char *no_room;  /* per run: that cell's sweep found no memory */
    tasks_failure first_run; /* the first run known to have found one: later runs stop */
} cell_search;

static void search_run(void *arg, size_t run)
{
    cell_search *cs = arg;
    cell_scratch scratch = {0};
    size_t end = (run + 1) * cs->run_cells;
    bool no_room = false;
    for (size_t c = run * cs->run_cells; c < end && c < cs->cells; c++) {
        if (tasks_failed_before(&cs->first_run, run))
            break; /* an earlier run names the conflict */
        if (cell_conflicts(cs->bg, c, &scratch, &no_room, &cs->pair[run])) {
            cs->found[run] = c;
            cs->no_room[run] = no_room;
            tasks_failure_note(&cs->first_run, run);
            break;
        }
    }
    free(scratch.sweep);
    free(scratch.rest);
    free(scratch.ends);
    free(scratch.spokes);
}

static int check_planarity(const hpfc_graph *g, unsigned threads, hpfc_diag *diag)
{
    size_t segments = 0;
    for (size_t e = 0; e < g->ne; e++)
        segments += graph_edge_point_count(g, e) - 1;
    if (segments > UINT32_MAX)
        return diag_set(diag, HPFC_E_LIMIT, "too many segments");
    bucket_grid bg = {0};
    cell_search cs = {.bg = &bg};
    int st = build_buckets(g, segments, &bg);
    cs.cells = bg.cols * bg.rows;
    size_t per_thread = (size_t)(threads > 1 ? threads : 1) * 16;
    cs.run_cells = (cs.cells + per_thread - 1) / per_thread;
    if (cs.run_cells < RUN_CELLS_MIN)
        cs.run_cells = RUN_CELLS_MIN;
    size_t runs = (cs.cells + cs.run_cells - 1) / cs.run_cells;
    if (!st && (!(cs.found = malloc(runs * sizeof *cs.found)) || !(cs.no_room = calloc(runs, 1)) ||
                !(cs.pair = malloc(runs * sizeof *cs.pair))))
        st = HPFC_E_NOMEM;
    if (!st) {
        for (size_t r = 0; r < runs; r++)
            cs.found[r] = SIZE_MAX;
        tasks_failure_init(&cs.first_run);
        tasks_run(threads, runs, search_run, &cs);
        size_t first = tasks_first_failure(&cs.first_run);
        if (first < runs && cs.no_room[first])
            st = HPFC_E_NOMEM;
        else if (first < runs)
            st = report_conflict(&bg, cs.pair[first].a, cs.pair[first].b, cs.pair[first].at, diag);
    }
    if (st == HPFC_E_NOMEM)
        diag_set(diag, st, "out of memory");
    free(bg.start);
    free(bg.items);
    free(bg.xs);
    free(bg.ys);
    free(cs.found);
    free(cs.pair);
    free(cs.no_room);
    return st;
}

int graph_validate_threads(const hpfc_graph *g, unsigned threads, hpfc_diag *diag)
{
    diag_clear(diag);
    if (!g)
        return diag_set(diag, HPFC_E_ARG, "no graph");
    if (g->ne == 0)
        return diag_set(diag, HPFC_E_EMPTY, "the graph has no edge");
    int st = check_edges_locally(g, diag);
    if (!st)
        st = graph_check_isolated(g, diag);
    if (!st)
        st = graph_check_duplicates(g, true, diag);
    if (!st)
        st = check_planarity(g, threads, diag);
    return st;
}

int hpfc_graph_validate(const hpfc_graph *g, hpfc_diag *diag)
{
    return graph_validate_threads(g, 1, diag);
}

int hpfc_graph_check_whole(const hpfc_graph *g, hpfc_diag *diag)
{
    diag_clear(diag);
    if (!g)
        return diag_set(diag, HPFC_E_ARG, "no graph");
    if (g->ne == 0 || graph_check_isolated(g, NULL))
        return hpfc_graph_validate(g, diag);
    return HPFC_OK;
}

int hpfc_graph_bounds(const hpfc_graph *g, int64_t box[4])
{
    if (!g || !box)
        return HPFC_E_ARG;
    if (g->nv == 0)
        return HPFC_E_EMPTY;
    box[0] = box[1] = INT64_MAX, box[2] = box[3] = INT64_MIN;
    for (size_t k = 0; k < g->nv + g->npts; k++) {
        const int64_t *p = k < g->nv ? g->vxy + 2 * k : g->pts + 2 * (k - g->nv);
        box[0] = p[0] < box[0] ? p[0] : box[0], box[2] = p[0] > box[2] ? p[0] : box[2];
        box[1] = p[1] < box[1] ? p[1] : box[1], box[3] = p[1] > box[3] ? p[1] : box[3];
    }
    return HPFC_OK;
}
