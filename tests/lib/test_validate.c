/*
 * hpfc_graph_validate on dense graphs, against a naive oracle: every pair
 * of segments and every pair of points compared directly.
 *
 * The graphs put a few hundred segments into a small cluster and one edge
 * far away, so the validator's uniform grid (about one cell a segment over
 * the whole box) gathers the cluster into a cell or four: dense cells are
 * searched by a sweep, sparse ones pair by pair, and point repeats are
 * found by a hash before a sort names the culprit. The oracle shares none
 * of that: its verdict, and for a crossing the pair of edges named, must be
 * the validator's.
 */
#include <math.h>
#include <stdbool.h>
#include <string.h>

#include "check.h"
#include "gen.h"
#include "hpfc.h"

typedef struct pt {
    int64_t x, y;
} pt;

typedef struct segment {
    pt a, b;
    uint32_t edge;
} segment;

/* Exact in 64 bits: the graphs here stay below 2^26 in x and y. */
static int orientation(pt a, pt b, pt c)
{
    int64_t v = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    return (v > 0) - (v < 0);
}

static bool within(int64_t lo, int64_t hi, int64_t v)
{
    return (lo < hi ? lo : hi) <= v && v <= (lo > hi ? lo : hi);
}

static bool on_closed_segment(pt a, pt b, pt p)
{
    return orientation(a, b, p) == 0 && within(a.x, b.x, p.x) && within(a.y, b.y, p.y);
}

static bool same(pt a, pt b)
{
    return a.x == b.x && a.y == b.y;
}

/* The closed segments' intersection is empty, one point or a segment; the
 * graph allows only one point that is an end of both. */
static bool naive_conflict(pt a, pt b, pt c, pt d)
{
    int o1 = orientation(a, b, c), o2 = orientation(a, b, d);
    int o3 = orientation(c, d, a), o4 = orientation(c, d, b);
    bool meet = (o1 * o2 < 0 && o3 * o4 < 0) || on_closed_segment(a, b, c) ||
                on_closed_segment(a, b, d) || on_closed_segment(c, d, a) || on_closed_segment(c, d, b);
    if (!meet)
        return false;
    bool share = same(a, c) || same(a, d) || same(b, c) || same(b, d);
    if (o1 || o2) /* not on one line: they meet in one point */
        return !share;
    /* on one line: the overlap of their extents along it */
    bool by_x = a.x != b.x || c.x != d.x;
    int64_t a0 = by_x ? a.x : a.y, a1 = by_x ? b.x : b.y, c0 = by_x ? c.x : c.y, c1 = by_x ? d.x : d.y;
    int64_t lo = (a0 < a1 ? a0 : a1) > (c0 < c1 ? c0 : c1) ? (a0 < a1 ? a0 : a1) : (c0 < c1 ? c0 : c1);
    int64_t hi = (a0 > a1 ? a0 : a1) < (c0 > c1 ? c0 : c1) ? (a0 > a1 ? a0 : a1) : (c0 > c1 ? c0 : c1);
    return hi > lo || !share;
}

typedef struct graph_copy {
    segment *seg;
    size_t nseg;
    pt *point;
    size_t npoint;
} graph_copy;

static void copy_graph(const hpfc_graph *g, graph_copy *c)
{
    size_t ne = hpfc_graph_edge_count(g), nv = hpfc_graph_vertex_count(g), interior = 0;
    for (size_t e = 0; e < ne; e++) {
        uint32_t u, v;
        const int64_t *xy;
        size_t n;
        hpfc_graph_edge(g, e, &u, &v, &xy, &n);
        interior += n;
    }
    c->point = malloc((nv + interior) * sizeof *c->point);
    c->seg = malloc((ne + interior) * sizeof *c->seg); /* an edge of n interior points has n + 1 */
    c->npoint = c->nseg = 0;
    for (size_t v = 0; v < nv; v++) {
        pt *p = &c->point[c->npoint++];
        hpfc_graph_vertex(g, v, &p->x, &p->y);
    }
    for (size_t e = 0; e < ne; e++) {
        uint32_t u, v;
        const int64_t *xy;
        size_t n;
        hpfc_graph_edge(g, e, &u, &v, &xy, &n);
        pt prev = c->point[u];
        for (size_t k = 0; k <= n; k++) {
            pt next = k < n ? (pt){xy[2 * k], xy[2 * k + 1]} : c->point[v];
            if (k < n)
                c->point[c->npoint++] = next;
            c->seg[c->nseg++] = (segment){prev, next, (uint32_t)e};
            prev = next;
        }
    }
}

static bool naive_repeat(const graph_copy *c)
{
    for (size_t i = 0; i < c->npoint; i++)
        for (size_t j = i + 1; j < c->npoint; j++)
            if (same(c->point[i], c->point[j]))
                return true;
    return false;
}

static bool edges_conflict(const graph_copy *c, int64_t e1, int64_t e2)
{
    for (size_t i = 0; i < c->nseg; i++)
        for (size_t j = i + 1; j < c->nseg; j++)
            if (((c->seg[i].edge == e1 && c->seg[j].edge == e2) ||
                 (c->seg[i].edge == e2 && c->seg[j].edge == e1)) &&
                naive_conflict(c->seg[i].a, c->seg[i].b, c->seg[j].a, c->seg[j].b))
                return true;
    return false;
}

static bool naive_crossing(const graph_copy *c)
{
    for (size_t i = 0; i < c->nseg; i++)
        for (size_t j = i + 1; j < c->nseg; j++)
            if (naive_conflict(c->seg[i].a, c->seg[i].b, c->seg[j].a, c->seg[j].b))
                return true;
    return false;
}

/* Polylines in horizontal strips of a small square, x rising along each
 * (so none crosses itself or another strip), a far edge that stretches the
 * box, then the flaws a round asks for: edges with random ends across the
 * strips, a vertex dropped on a polyline's point, a polyline's point moved
 * onto another's, or, right of the strips, an edge ending on a vertical one
 * (or one unit short of it), where the two boxes' only common x is an end
 * of both: the sweep's bound, tested exactly. */
typedef struct dense_case {
    uint32_t strips, points, stray_edges;
    bool repeat, touch, t_junction, t_apart;
    bool split; /* every other strip moved far up and right: two clusters on a diagonal */
} dense_case;

static hpfc_graph *dense_graph(gen_rng *rng, const dense_case *dc)
{
    hpfc_graph *g;
    hpfc_graph_create(&g);
    const int64_t side = 4096, strip = side / dc->strips;
    int64_t *xy = malloc(2 * dc->points * sizeof *xy);
    for (uint32_t s = 0; s < dc->strips; s++) {
        int64_t shift = dc->split && s % 2 ? 1 << 20 : 0;
        int64_t y0 = s * strip + shift, x = (int64_t)gen_rng_below(rng, 16) + shift;
        uint32_t u, v;
        hpfc_graph_add_vertex(g, x, y0 + (int64_t)gen_rng_below(rng, (uint64_t)strip - 1), &u);
        for (uint32_t k = 0; k < dc->points; k++) {
            x += 1 + (int64_t)gen_rng_below(rng, 2 * side / dc->points);
            xy[2 * k] = x;
            xy[2 * k + 1] = y0 + (int64_t)gen_rng_below(rng, (uint64_t)strip - 1);
        }
        x += 1 + (int64_t)gen_rng_below(rng, 8);
        hpfc_graph_add_vertex(g, x, y0 + (int64_t)gen_rng_below(rng, (uint64_t)strip - 1), &v);
        hpfc_graph_add_edge(g, u, v, xy, dc->points, NULL);
    }
    uint32_t u, v;
    hpfc_graph_add_vertex(g, 40000000, 30000000, &u);
    hpfc_graph_add_vertex(g, 40000005, 30000009, &v);
    hpfc_graph_add_edge(g, u, v, NULL, 0, NULL);
    for (uint32_t k = 0; k < dc->stray_edges; k++) {
        int64_t x0 = (int64_t)gen_rng_below(rng, 3 * side), y0 = (int64_t)gen_rng_below(rng, side);
        hpfc_graph_add_vertex(g, x0, y0, &u);
        hpfc_graph_add_vertex(g, x0 + 1 + (int64_t)gen_rng_below(rng, 64), y0 + (int64_t)gen_rng_below(rng, 64), &v);
        hpfc_graph_add_edge(g, u, v, NULL, 0, NULL);
    }
    if (dc->touch || dc->repeat) { /* a vertex on, or a point of, a strip's point */
        uint32_t s = (uint32_t)gen_rng_below(rng, dc->strips);
        const int64_t *pts;
        size_t n;
        hpfc_graph_edge(g, s, &u, &v, &pts, &n);
        size_t k = (size_t)gen_rng_below(rng, n);
        int64_t px = pts[2 * k], py = pts[2 * k + 1];
        if (dc->repeat) {
            hpfc_graph_add_vertex(g, px, py, &u);
            hpfc_graph_add_vertex(g, px + 3, py + side, &v);
        } else { /* the middle of the segment after point k: on it only if the lattice allows */
            const int64_t *q = k + 1 < n ? pts + 2 * k + 2 : NULL;
            int64_t qx = q ? q[0] : px + 2, qy = q ? q[1] : py;
            hpfc_graph_add_vertex(g, (px + qx) / 2, (py + qy) / 2, &u);
            hpfc_graph_add_vertex(g, (px + qx) / 2 + 1, py + side, &v);
        }
        hpfc_graph_add_edge(g, u, v, NULL, 0, NULL);
    }
    if (dc->t_junction) {
        int64_t x = 3 * side + 500, y = (int64_t)gen_rng_below(rng, side);
        hpfc_graph_add_vertex(g, x, y, &u);
        hpfc_graph_add_vertex(g, x, y + 40, &v);
        hpfc_graph_add_edge(g, u, v, NULL, 0, NULL);
        hpfc_graph_add_vertex(g, x - (dc->t_apart ? 1 : 0), y + 20, &u);
        hpfc_graph_add_vertex(g, x - 9, y + 27, &v);
        hpfc_graph_add_edge(g, u, v, NULL, 0, NULL);
    }
    free(xy);
    return g;
}

static int rounds_with_verdict[3];

/* The verdict against the pairwise oracle's, and the edges a crossing
 * names; counts the oracle's verdict into verdicts[valid, crossing,
 * repeating]. */
static void check_against_oracle(const hpfc_graph *g, int verdicts[3])
{
    graph_copy c;
    copy_graph(g, &c);
    hpfc_diag d;
    int st = hpfc_graph_validate(g, &d);
    int expected = naive_repeat(&c) ? HPFC_E_DUPLICATE_POINT
                   : naive_crossing(&c) ? HPFC_E_NONPLANAR
                                        : HPFC_OK;
    CHECK_EQ_INT(st, expected);
    if (st == HPFC_E_NONPLANAR && expected == st) /* the edges named do conflict */
        CHECK(d.edge[0] >= 0 && d.edge[1] >= 0 && edges_conflict(&c, d.edge[0], d.edge[1]));
    verdicts[expected == HPFC_OK ? 0 : expected == HPFC_E_NONPLANAR ? 1 : 2]++;
    free(c.seg);
    free(c.point);
}

static void test_dense_clusters(void)
{
    gen_rng rng;
    gen_rng_seed(&rng, 20261205);
    for (int round = 0; round < 300; round++) {
        dense_case dc = {.strips = 4 + (uint32_t)gen_rng_below(&rng, 28),
                         .points = 8 + (uint32_t)gen_rng_below(&rng, 40),
                         .stray_edges = round % 5 == 0 ? 1 + (uint32_t)gen_rng_below(&rng, 3) : 0,
                         .repeat = round % 5 == 1,
                         .touch = round % 5 == 2,
                         .t_junction = round % 5 == 3,
                         .t_apart = round % 10 == 8,
                         .split = round % 3 == 0};
        hpfc_graph *g = dense_graph(&rng, &dc);
        check_against_oracle(g, rounds_with_verdict);
        hpfc_graph_free(g);
    }
    /* each verdict reached often enough to mean something */
    CHECK(rounds_with_verdict[0] >= 40 && rounds_with_verdict[1] >= 40 && rounds_with_verdict[2] >= 40);
    fprintf(stderr, "dense clusters: %d valid, %d crossing, %d repeating\n", rounds_with_verdict[0],
            rounds_with_verdict[1], rounds_with_verdict[2]);
}

/* A hub: one vertex with 40 to 300 spokes (some of them bent, some
 * starting at their far end), which no grid splits, then the flaw a round
 * asks for: a short spoke along another's first units, a short edge
 * across spokes near the hub, an edge through the hub, a second hub close
 * by, a ring of short edges beyond the spokes (valid), or two edges that
 * cross each other beside the spokes. The first two and the last conflict
 * only in the hub's own cell. */
static hpfc_graph *hub_graph(gen_rng *rng, int flaw)
{
    hpfc_graph *g;
    hpfc_graph_create(&g);
    uint32_t hub, u, v;
    const int64_t cx = 5000, cy = -3000;
    hpfc_graph_add_vertex(g, cx, cy, &hub);
    uint32_t spokes = 40 + (uint32_t)gen_rng_below(rng, 261);
    int64_t first_far[2] = {0, 0};
    for (uint32_t k = 0; k < spokes; k++) {
        /* all around the hub; for flaw 6, from 100 to 260 degrees only */
        double turn = ((double)k + 0.5 * (double)gen_rng_below(rng, 100) / 100.0) / spokes;
        double angle = flaw == 6 ? 1.7453292519943295 + 2.792526803190927 * turn
                                 : 6.283185307179586 * turn;
        double r = 2000.0 + (double)gen_rng_below(rng, 3000);
        int64_t fx = cx + (int64_t)(r * cos(angle)), fy = cy + (int64_t)(r * sin(angle));
        if (k == 0 && flaw != 6) /* along (3, 1), which flaw 1 follows for a few units only */
            fx = cx + 3000, fy = cy + 1000, first_far[0] = 3, first_far[1] = 1;
        hpfc_graph_add_vertex(g, fx, fy, &v);
        bool bent = gen_rng_below(rng, 4) == 0, reversed = gen_rng_below(rng, 3) == 0;
        int64_t mid[2] = {cx + (fx - cx) / 2 + (int64_t)gen_rng_below(rng, 3) - 1,
                          cy + (fy - cy) / 2 + (int64_t)gen_rng_below(rng, 3) - 1};
        if (reversed)
            hpfc_graph_add_edge(g, v, hub, bent ? mid : NULL, bent ? 1 : 0, NULL);
        else
            hpfc_graph_add_edge(g, hub, v, bent ? mid : NULL, bent ? 1 : 0, NULL);
    }
    if (flaw == 1) { /* along spoke 0's first units, seen in the hub's cell only */
        hpfc_graph_add_vertex(g, cx + first_far[0], cy + first_far[1], &v);
        hpfc_graph_add_edge(g, v, hub, NULL, 0, NULL);
    } else if (flaw == 2) { /* across the spokes near the hub */
        hpfc_graph_add_vertex(g, cx - 30, cy + 17, &u);
        hpfc_graph_add_vertex(g, cx + 25, cy + 41, &v);
        hpfc_graph_add_edge(g, u, v, NULL, 0, NULL);
    } else if (flaw == 3) { /* through the hub, between two spokes' directions */
        hpfc_graph_add_vertex(g, cx - 7000, cy - 1, &u);
        hpfc_graph_add_vertex(g, cx + 7000, cy + 1, &v);
        hpfc_graph_add_edge(g, u, v, NULL, 0, NULL);
    } else if (flaw == 4) { /* a second hub, its spokes among the first's */
        uint32_t hub2;
        hpfc_graph_add_vertex(g, cx + 1500, cy + 700, &hub2);
        for (uint32_t k = 0; k < 40; k++) {
            hpfc_graph_add_vertex(g, cx + 1500 + (int64_t)gen_rng_below(rng, 900) - 450,
                                  cy + 700 + (int64_t)gen_rng_below(rng, 900) - 450, &v);
            hpfc_graph_add_edge(g, hub2, v, NULL, 0, NULL);
        }
    } else if (flaw == 6) { /* right of the spokes, two edges crossing at (cx + 20, cy): their
                               * first points on the hub's x, so that the grid's cuts, at
                               * sampled first points, leave the crossing in the hub's cell */
        hpfc_graph_add_vertex(g, cx, cy + 30, &u);
        hpfc_graph_add_vertex(g, cx + 40, cy - 30, &v);
        hpfc_graph_add_edge(g, u, v, NULL, 0, NULL);
        hpfc_graph_add_vertex(g, cx, cy - 30, &u);
        hpfc_graph_add_vertex(g, cx + 40, cy + 30, &v);
        hpfc_graph_add_edge(g, u, v, NULL, 0, NULL);
    } else if (flaw == 5) { /* a ring of short edges beyond every spoke */
        for (uint32_t k = 0; k < 64; k++) {
            double a0 = 6.283185307179586 * k / 64, a1 = 6.283185307179586 * (k + 0.8) / 64;
            hpfc_graph_add_vertex(g, cx + (int64_t)(5200 * cos(a0)),
                                  cy + (int64_t)(5200 * sin(a0)), &u);
            hpfc_graph_add_vertex(g, cx + (int64_t)(5200 * cos(a1)),
                                  cy + (int64_t)(5200 * sin(a1)), &v);
            hpfc_graph_add_edge(g, u, v, NULL, 0, NULL);
        }
    }
    return g;
}

static void test_hubs(void)
{
    gen_rng rng;
    gen_rng_seed(&rng, 20261207);
    int verdicts[3] = {0, 0, 0};
    for (int round = 0; round < 140; round++) {
        hpfc_graph *g = hub_graph(&rng, round % 7);
        check_against_oracle(g, verdicts);
        hpfc_graph_free(g);
    }
    CHECK(verdicts[0] >= 30 && verdicts[1] >= 50);
    fprintf(stderr, "hubs: %d valid, %d crossing, %d repeating\n", verdicts[0], verdicts[1],
            verdicts[2]);
}

/* Vertical polylines on three x values only, stacked in y (the grid's
 * columns cannot split them, so its rows take the cells), then in some
 * rounds a short edge across one of them, or up to one of them. */
static void test_few_columns(void)
{
    gen_rng rng;
    gen_rng_seed(&rng, 20261206);
    int verdicts[2] = {0, 0};
    for (int round = 0; round < 40; round++) {
        hpfc_graph *g;
        hpfc_graph_create(&g);
        int64_t y = 0;
        for (int k = 0; k < 600; k++) {
            uint32_t u, v;
            int64_t x = 1000 * (k % 3), len = 1 + (int64_t)gen_rng_below(&rng, 50);
            if (k % 3 == 0) /* past the last three, the longest 50 */
                y += 51 + (int64_t)gen_rng_below(&rng, 4);
            hpfc_graph_add_vertex(g, x, y, &u);
            hpfc_graph_add_vertex(g, x, y + len, &v);
            hpfc_graph_add_edge(g, u, v, NULL, 0, NULL);
        }
        if (round % 2) {
            uint32_t u, v;
            int64_t x = 1000 * (int64_t)gen_rng_below(&rng, 3);
            int64_t at = (int64_t)gen_rng_below(&rng, (uint64_t)y);
            int64_t reach = round % 4 == 1 ? 1 : -1; /* across the line, or ending one unit short */
            hpfc_graph_add_vertex(g, x - 7, at, &u);
            hpfc_graph_add_vertex(g, x + reach, at + 1, &v);
            hpfc_graph_add_edge(g, u, v, NULL, 0, NULL);
        }
        graph_copy c;
        copy_graph(g, &c);
        hpfc_diag d;
        int st = hpfc_graph_validate(g, &d);
        bool crossing = naive_crossing(&c);
        CHECK_EQ_INT(st, crossing ? HPFC_E_NONPLANAR : HPFC_OK);
        verdicts[crossing]++;
        free(c.seg);
        free(c.point);
        hpfc_graph_free(g);
    }
    CHECK(verdicts[0] >= 10 && verdicts[1] >= 5);
    fprintf(stderr, "few columns: %d valid, %d crossing\n", verdicts[0], verdicts[1]);
}

/* The hash sees every point: a repeat between the first vertex and the
 * last interior point of a long graph, and none at all. */
static void test_repeat_far_apart(void)
{
    for (int with_repeat = 0; with_repeat < 2; with_repeat++) {
        hpfc_graph *g;
        hpfc_graph_create(&g);
        uint32_t u, v;
        hpfc_graph_add_vertex(g, 0, 0, &u);
        hpfc_graph_add_vertex(g, 100000, 7, &v);
        static int64_t xy[2 * 50000]; /* 800 KB: not on the stack */
        for (int k = 0; k < 50000; k++)
            xy[2 * k] = 2 * (k + 1), xy[2 * k + 1] = 1 + (k % 5);
        if (with_repeat)
            xy[2 * 49999] = 0, xy[2 * 49999 + 1] = 0;
        hpfc_graph_add_edge(g, u, v, xy, 50000, NULL);
        hpfc_diag d;
        int st = hpfc_graph_validate(g, &d);
        CHECK_EQ_INT(st, with_repeat ? HPFC_E_DUPLICATE_POINT : HPFC_OK);
        if (with_repeat)
            CHECK(strcmp(d.message, "interior point 50000 of edge 0 is at the same point (0, 0) as vertex 0") == 0);
        hpfc_graph_free(g);
    }
}

int main(void)
{
    test_dense_clusters();
    test_few_columns();
    test_hubs();
    test_repeat_far_apart();
    return check_report("validate");
}
