/*
 * Unit tests of hpfc-pack's last GIS step (hpfc-pack/segment_graph.h),
 * without GDAL or GEOS: random sets of lattice segments that meet only at
 * shared ends (edges of a jittered grid, some removed, plus loose squares
 * and lone segments), made into graphs, checked against the segments
 * themselves: every edge expands back into input segments, each used once;
 * vertices sit exactly where the input's degree is not 2 or a line ends,
 * plus one on each closed chain without a junction, at its least point;
 * interior points
 * have degree 2 and no line ends there. With all_vertices, one vertex a
 * point and one edge a segment. On several threads, the one thread's
 * graph; from segments in no order, a graph as correct.
 */
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "segment_graph.h"
#include "segnode.h"

static uint64_t rng_state;

static uint32_t rnd(uint32_t n)
{
    rng_state = rng_state * 6364136223846793005u + 1442695040888963407u;
    return (uint32_t)(rng_state >> 33) % n;
}

static segnode_seg make_seg(int64_t x1, int64_t y1, int64_t x2, int64_t y2)
{
    int swap = x2 < x1 || (x2 == x1 && y2 < y1);
    return swap ? (segnode_seg){x2, y2, x1, y1} : (segnode_seg){x1, y1, x2, y2};
}

static int cmp_seg(const void *a, const void *b)
{
    const segnode_seg *p = a, *q = b;
    const int64_t u[4] = {p->ax, p->ay, p->bx, p->by}, v[4] = {q->ax, q->ay, q->bx, q->by};
    for (int k = 0; k < 4; k++)
        if (u[k] != v[k])
            return u[k] < v[k] ? -1 : 1;
    return 0;
}

/* Grid points (i, j) at jittered lattice positions: kept apart so that
 * edges between grid neighbours never meet but at their ends. */
static void grid_point(int i, int j, const int64_t *jx, const int64_t *jy, int w, int64_t *x,
                       int64_t *y)
{
    *x = 100 * i + jx[j * w + i];
    *y = 100 * j + jy[j * w + i];
}

static size_t make_segments(segnode_seg *s, int w, int h, int keep_percent)
{
    int64_t *jx = malloc(sizeof *jx * (size_t)(w * h)), *jy = malloc(sizeof *jy * (size_t)(w * h));
    for (int k = 0; k < w * h; k++) {
        jx[k] = (int64_t)rnd(41) - 20;
        jy[k] = (int64_t)rnd(41) - 20;
    }
    size_t n = 0;
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) {
            int64_t x0, y0, x1, y1;
            grid_point(i, j, jx, jy, w, &x0, &y0);
            if (i + 1 < w && (int)rnd(100) < keep_percent) {
                grid_point(i + 1, j, jx, jy, w, &x1, &y1);
                s[n++] = make_seg(x0, y0, x1, y1);
            }
            if (j + 1 < h && (int)rnd(100) < keep_percent) {
                grid_point(i, j + 1, jx, jy, w, &x1, &y1);
                s[n++] = make_seg(x0, y0, x1, y1);
            }
        }
    /* closed chains without a junction and lone segments, off the grid */
    for (int k = 0; k < 3; k++) {
        int64_t x = 100 * (w + 2) + 50 * k, y = 30 * k;
        s[n++] = make_seg(x, y, x + 10, y);
        s[n++] = make_seg(x + 10, y, x + 10, y + 10);
        s[n++] = make_seg(x + 10, y + 10, x, y + 10);
        s[n++] = make_seg(x, y + 10, x, y);
    }
    s[n++] = make_seg(-500, -500, -490, -480);
    free(jx);
    free(jy);
    qsort(s, n, sizeof *s, cmp_seg);
    return n;
}

typedef struct point_degree {
    segnode_pt p;
    int degree;
} point_degree;

static int cmp_pd(const void *a, const void *b)
{
    return segnode_pt_cmp(&((const point_degree *)a)->p, &((const point_degree *)b)->p);
}

/* Every end with the number of segments at it, sorted by point. */
static size_t degrees(const segnode_seg *s, size_t n, point_degree *pd)
{
    size_t m = 0;
    for (size_t i = 0; i < n; i++) {
        pd[m++] = (point_degree){{s[i].ax, s[i].ay}, 1};
        pd[m++] = (point_degree){{s[i].bx, s[i].by}, 1};
    }
    qsort(pd, m, sizeof *pd, cmp_pd);
    size_t u = 0;
    for (size_t i = 0; i < m; i++)
        if (u && cmp_pd(&pd[u - 1], &pd[i]) == 0)
            pd[u - 1].degree++;
        else
            pd[u++] = pd[i];
    return u;
}

static int degree_at(const point_degree *pd, size_t n, int64_t x, int64_t y)
{
    point_degree key = {{x, y}, 0};
    const point_degree *f = bsearch(&key, pd, n, sizeof *pd, cmp_pd);
    return f ? f->degree : 0;
}

/* A line ends there: a junction whatever its degree. */
static int is_end(const segnode_pt *ends, size_t n_ends, int64_t x, int64_t y)
{
    for (size_t k = 0; k < n_ends; k++)
        if (ends[k].x == x && ends[k].y == y)
            return 1;
    return 0;
}

static void check_graph(const segnode_seg *s, size_t n, const segnode_pt *ends, size_t n_ends,
                        const hpfc_graph *g, int all_vertices)
{
    point_degree *pd = malloc(2 * n * sizeof *pd + 1);
    size_t npts = degrees(s, n, pd);
    segnode_seg *back = malloc(n * sizeof *back + 1);
    size_t nback = 0, nv = hpfc_graph_vertex_count(g), ne = hpfc_graph_edge_count(g);
    int ok = 1;
    for (size_t e = 0; e < ne && ok; e++) {
        uint32_t u, v;
        const int64_t *in;
        size_t m;
        hpfc_graph_edge(g, e, &u, &v, &in, &m);
        int64_t px, py, qx, qy;
        hpfc_graph_vertex(g, u, &px, &py);
        for (size_t k = 0; k <= m && ok; k++) {
            if (k < m) {
                qx = in[2 * k], qy = in[2 * k + 1];
                CHECK_EQ_INT(degree_at(pd, npts, qx, qy), 2); /* interior: degree 2 */
                CHECK(all_vertices || !is_end(ends, n_ends, qx, qy)); /* no line ends inside */
            } else {
                hpfc_graph_vertex(g, v, &qx, &qy);
            }
            if (nback == n) {
                ok = 0; /* more segments than the input has */
                break;
            }
            back[nback++] = make_seg(px, py, qx, qy);
            px = qx, py = qy;
        }
    }
    CHECK(ok);
    CHECK_EQ_INT(nback, n);
    qsort(back, nback, sizeof *back, cmp_seg);
    for (size_t i = 0; i < nback && i < n; i++)
        CHECK_EQ_INT(cmp_seg(&back[i], &s[i]), 0); /* the same set, each segment once */
    if (all_vertices) {
        CHECK_EQ_INT(nv, npts);
        CHECK_EQ_INT(ne, n);
    } else {
        size_t junctions = 0;
        for (size_t k = 0; k < npts; k++)
            junctions += pd[k].degree != 2 || is_end(ends, n_ends, pd[k].p.x, pd[k].p.y);
        size_t loops = 0;
        for (size_t k = 0; k < nv; k++) {
            int64_t x, y;
            hpfc_graph_vertex(g, k, &x, &y);
            loops += degree_at(pd, npts, x, y) == 2 && !is_end(ends, n_ends, x, y);
        }
        CHECK(n_ends > 1 || loops >= 3); /* the loose squares, when no line ends on them */
        CHECK_EQ_INT(nv, junctions + loops);
        /* a degree-2 vertex closes a chain: its one edge is a loop */
        for (size_t e = 0; e < ne; e++) {
            uint32_t u, v;
            const int64_t *in;
            size_t m;
            hpfc_graph_edge(g, e, &u, &v, &in, &m);
            int64_t x, y;
            hpfc_graph_vertex(g, u, &x, &y);
            if (degree_at(pd, npts, x, y) == 2 && !is_end(ends, n_ends, x, y)) {
                CHECK_EQ_INT(u, v);
                for (size_t k = 0; k < m; k++) /* at the chain's least point */
                    CHECK(in[2 * k] > x || (in[2 * k] == x && in[2 * k + 1] > y));
            }
        }
    }
    free(pd);
    free(back);
}

static void test_random(void)
{
    for (int round = 0; round < 60; round++) {
        rng_state = 0x5e9u + (uint64_t)round;
        int w = 2 + (int)rnd(12), h = 2 + (int)rnd(12);
        segnode_seg *s = malloc(sizeof *s * (size_t)(2 * w * h + 20));
        size_t n = make_segments(s, w, h, 40 + (int)rnd(60));
        /* line ends: segment ends picked at random (degree 2 ones among
         * them), and points no segment ends at, which change nothing */
        segnode_pt ends[24];
        size_t n_ends = round % 3 == 0 ? 0 : 1 + rnd(20);
        for (size_t k = 0; k < n_ends; k++) {
            const segnode_seg *t = &s[rnd((uint32_t)n)];
            ends[k] = rnd(2) ? (segnode_pt){t->ax, t->ay} : (segnode_pt){t->bx, t->by};
        }
        ends[n_ends++] = (segnode_pt){-7777, 12345};
        for (int all = 0; all < 2; all++) {
            hpfc_graph *g = NULL;
            char why[256] = "";
            CHECK_EQ_INT(segment_graph_make(s, n, ends, n_ends, all, -3, 1, &g, why, sizeof why),
                         HPFC_OK);
            if (g) {
                CHECK_EQ_INT(hpfc_graph_unit_exp10(g), -3);
                CHECK_EQ_INT(hpfc_graph_validate(g, NULL), HPFC_OK);
                check_graph(s, n, ends, n_ends, g, all);
            }
            hpfc_graph_free(g);
        }
        free(s);
    }
}

/* The same graph whatever the threads: enough segments for the segments'
 * ends to be numbered on two threads, against one thread's graph, vertex
 * for vertex and edge for edge, and against the segments themselves. */
static int same_graph(const hpfc_graph *a, const hpfc_graph *b)
{
    if (hpfc_graph_vertex_count(a) != hpfc_graph_vertex_count(b) ||
        hpfc_graph_edge_count(a) != hpfc_graph_edge_count(b))
        return 0;
    for (size_t v = 0; v < hpfc_graph_vertex_count(a); v++) {
        int64_t ax, ay, bx, by;
        hpfc_graph_vertex(a, v, &ax, &ay);
        hpfc_graph_vertex(b, v, &bx, &by);
        if (ax != bx || ay != by)
            return 0;
    }
    for (size_t e = 0; e < hpfc_graph_edge_count(a); e++) {
        uint32_t au, av, bu, bv;
        const int64_t *axy, *bxy;
        size_t ak, bk;
        hpfc_graph_edge(a, e, &au, &av, &axy, &ak);
        hpfc_graph_edge(b, e, &bu, &bv, &bxy, &bk);
        if (au != bu || av != bv || ak != bk || (ak && memcmp(axy, bxy, 2 * ak * sizeof *axy)))
            return 0;
    }
    return 1;
}

static void test_threads(void)
{
    rng_state = 0x7a11u;
    int w = 150, h = 150;
    segnode_seg *s = malloc(sizeof *s * (size_t)(2 * w * h + 20));
    size_t n = make_segments(s, w, h, 90);
    CHECK(n > 40000); /* above the size split on threads */
    segnode_pt ends[1] = {{s[n / 2].ax, s[n / 2].ay}};
    hpfc_graph *one = NULL, *many = NULL;
    char why[256] = "";
    CHECK_EQ_INT(segment_graph_make(s, n, ends, 1, 0, 0, 1, &one, why, sizeof why), HPFC_OK);
    for (unsigned threads = 2; threads <= 3 && one; threads++) {
        CHECK_EQ_INT(segment_graph_make(s, n, ends, 1, 0, 0, threads, &many, why, sizeof why),
                     HPFC_OK);
        if (many) {
            CHECK(same_graph(one, many));
            check_graph(s, n, ends, 1, many, 0);
        }
        hpfc_graph_free(many);
        many = NULL;
    }
    hpfc_graph_free(one);
    free(s);
}

/* Segments in no order (the readers sort theirs; the graph must not need
 * it): the same checks against the segments. */
static void test_unsorted(void)
{
    for (int round = 0; round < 10; round++) {
        rng_state = 0x50f7u + (uint64_t)round;
        int w = 2 + (int)rnd(12), h = 2 + (int)rnd(12);
        segnode_seg *s = malloc(sizeof *s * (size_t)(2 * w * h + 20));
        size_t n = make_segments(s, w, h, 60 + (int)rnd(40));
        segnode_seg *shuffled = malloc(sizeof *s * n);
        memcpy(shuffled, s, sizeof *s * n);
        for (size_t i = n; i > 1; i--) {
            size_t j = rnd((uint32_t)i);
            segnode_seg t = shuffled[i - 1];
            shuffled[i - 1] = shuffled[j], shuffled[j] = t;
        }
        hpfc_graph *g = NULL;
        char why[256] = "";
        CHECK_EQ_INT(segment_graph_make(shuffled, n, NULL, 0, 0, 0, 2, &g, why, sizeof why),
                     HPFC_OK);
        if (g) /* against the segments in order, as check_graph takes them */
            check_graph(s, n, NULL, 0, g, 0);
        hpfc_graph_free(g);
        free(shuffled);
        free(s);
    }
}

static void test_empty(void)
{
    hpfc_graph *g = NULL;
    char why[64];
    CHECK_EQ_INT(segment_graph_make(NULL, 0, NULL, 0, 0, 0, 2, &g, why, sizeof why), HPFC_OK);
    CHECK(g != NULL);
    CHECK_EQ_INT(hpfc_graph_vertex_count(g), 0);
    CHECK_EQ_INT(hpfc_graph_edge_count(g), 0);
    hpfc_graph_free(g);
}

int main(void)
{
    test_random();
    test_threads();
    test_unsorted();
    test_empty();
    return check_report("test_segment_graph");
}
