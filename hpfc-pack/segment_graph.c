/*
 * segment_graph.c: noded lattice segments to a planar graph
 * (segment_graph.h): points sorted and numbered, each point's segments in
 * a compressed adjacency, then the chains between junctions walked once.
 */
#include "segment_graph.h"

#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "grow.h"
#include "sort.h"

/* The reason into err; the status a failure of the graph's making gives. */
static int fail_status(char *err, size_t err_len, int st, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err, err_len, fmt, ap);
    va_end(ap);
    return st;
}

static size_t find_pt(const segnode_pt *pts, size_t n, int64_t x, int64_t y)
{
    segnode_pt key = {x, y};
    const segnode_pt *p = bsearch(&key, pts, n, sizeof *pts, segnode_pt_cmp);
    return (size_t)(p - pts);
}

typedef struct graph_builder {
    char *err;
    size_t err_len;
    hpfc_graph *g;
    const segnode_seg *segs;
    size_t n_segs;
    segnode_pt *pts;
    size_t n_pts;
    uint32_t *seg_a, *seg_b;    /* point index of each segment's ends */
    size_t *adj_start, *adj;    /* incident segments of each point (CSR) */
    uint32_t *vertex;           /* point -> graph vertex, UINT32_MAX if none */
    unsigned char *line_end;    /* point: a line of the input ends there */
    unsigned char *used;
    int64_t *interior;
    size_t cap_interior;
} graph_builder;

#define fail_nomem(b) fail_status((b)->err, (b)->err_len, HPFC_E_NOMEM, "out of memory")
#define fail_graph(b, st) fail_status((b)->err, (b)->err_len, (st), "graph: %s", hpfc_strerror(st))

static int gb_vertex(graph_builder *b, size_t p, uint32_t *out)
{
    if (b->vertex[p] == UINT32_MAX) {
        int st = hpfc_graph_add_vertex(b->g, b->pts[p].x, b->pts[p].y, &b->vertex[p]);
        if (st)
            return fail_graph(b, st);
    }
    *out = b->vertex[p];
    return 0;
}

static size_t degree(const graph_builder *b, size_t p)
{
    return b->adj_start[p + 1] - b->adj_start[p];
}

/* A chain stops at a junction: a point of degree other than 2, or where a
 * line ends. */
static int is_junction(const graph_builder *b, size_t p)
{
    return degree(b, p) != 2 || b->line_end[p];
}

/* Follows the chain from point p along segment s through degree-2 points,
 * up to a junction (or back to p), and adds it as one edge. */
static int gb_chain(graph_builder *b, size_t p, size_t s)
{
    size_t n_int = 0, cur = p;
    for (;;) {
        b->used[s] = 1;
        size_t q = b->seg_a[s] == cur ? b->seg_b[s] : b->seg_a[s];
        if (q == p || is_junction(b, q)) {
            uint32_t u = 0, v = 0; /* set when st == 0; -O3 cannot tell */
            int st = gb_vertex(b, p, &u);
            if (!st)
                st = gb_vertex(b, q, &v);
            if (!st && (st = hpfc_graph_add_edge(b->g, u, v, b->interior, n_int, NULL)) != 0)
                return fail_graph(b, st);
            return st;
        }
        if (!array_grow((void **)&b->interior, &b->cap_interior, 2 * n_int + 2, sizeof(int64_t)))
            return fail_nomem(b);
        b->interior[2 * n_int] = b->pts[q].x;
        b->interior[2 * n_int + 1] = b->pts[q].y;
        n_int++;
        size_t s0 = b->adj[b->adj_start[q]], s1 = b->adj[b->adj_start[q] + 1];
        s = s0 == s ? s1 : s0;
        cur = q;
    }
}

/* Segments [first, end)'s second ends numbered, by binary search. */
typedef struct b_ends {
    graph_builder *b;
    size_t first, end;
} b_ends;

static void *number_b_ends(void *arg)
{
    const b_ends *r = arg;
    const graph_builder *b = r->b;
    for (size_t i = r->first; i < r->end; i++)
        b->seg_b[i] = (uint32_t)find_pt(b->pts, b->n_pts, b->segs[i].bx, b->segs[i].by);
    return NULL;
}

/* Each segment's ends as point numbers. The first ends come in the points'
 * order when the segments are sorted, as the readers give them, so each is
 * the point the last one was, or the next (a search otherwise); the second
 * ends are searched for, their halves on two threads when there are. */
static void number_ends(graph_builder *b, unsigned threads)
{
    size_t at = 0;
    for (size_t i = 0; i < b->n_segs; i++) {
        segnode_pt a = {b->segs[i].ax, b->segs[i].ay};
        if (segnode_pt_cmp(&b->pts[at], &a) != 0)
            at = at + 1 < b->n_pts && segnode_pt_cmp(&b->pts[at + 1], &a) == 0
                     ? at + 1
                     : find_pt(b->pts, b->n_pts, a.x, a.y);
        b->seg_a[i] = (uint32_t)at;
    }
    b_ends half[2] = {{b, 0, b->n_segs / 2}, {b, b->n_segs / 2, b->n_segs}};
    pthread_t thread;
    if (threads > 1 && b->n_segs >= SORT_SPLIT_MIN &&
        pthread_create(&thread, NULL, number_b_ends, &half[1]) == 0) {
        number_b_ends(&half[0]);
        pthread_join(thread, NULL);
    } else {
        half[0].end = b->n_segs;
        number_b_ends(&half[0]);
    }
}

int segment_graph_make(const segnode_seg *segs, size_t n_segs, const segnode_pt *ends,
                       size_t n_ends, int all_vertices, int32_t unit_exp10, unsigned threads,
                       hpfc_graph **out, char *err, size_t err_len)
{
    graph_builder b = {.err = err, .err_len = err_len, .segs = segs, .n_segs = n_segs};
    int st = 0;
    if (n_segs >= UINT32_MAX / 2)
        return fail_status(err, err_len, HPFC_E_LIMIT, "too many segments (%zu) for one graph",
                           n_segs);
    b.pts = malloc(2 * n_segs * sizeof *b.pts);
    b.seg_a = malloc(n_segs * sizeof *b.seg_a);
    b.seg_b = malloc(n_segs * sizeof *b.seg_b);
    b.used = calloc(n_segs ? n_segs : 1, 1);
    if (!b.pts || !b.seg_a || !b.seg_b || !b.used) {
        st = fail_nomem(&b);
        goto done;
    }
    for (size_t i = 0; i < n_segs; i++) {
        b.pts[2 * i] = (segnode_pt){segs[i].ax, segs[i].ay};
        b.pts[2 * i + 1] = (segnode_pt){segs[i].bx, segs[i].by};
    }
    sort_in_place_threads(b.pts, 2 * n_segs, sizeof *b.pts, segnode_pt_cmp, threads);
    for (size_t i = 0; i < 2 * n_segs; i++)
        if (b.n_pts == 0 || segnode_pt_cmp(&b.pts[b.n_pts - 1], &b.pts[i]) != 0)
            b.pts[b.n_pts++] = b.pts[i];
    b.pts = array_shrink(b.pts, b.n_pts, sizeof *b.pts);
    b.adj_start = calloc(b.n_pts + 1, sizeof *b.adj_start);
    b.adj = malloc(2 * n_segs * sizeof *b.adj);
    b.vertex = malloc(b.n_pts * sizeof *b.vertex);
    b.line_end = calloc(b.n_pts ? b.n_pts : 1, 1);
    if (!b.adj_start || !b.adj || !b.vertex || !b.line_end) {
        st = fail_nomem(&b);
        goto done;
    }
    number_ends(&b, threads);
    for (size_t i = 0; i < n_segs; i++) {
        b.adj_start[b.seg_a[i] + 1]++;
        b.adj_start[b.seg_b[i] + 1]++;
    }
    for (size_t p = 0; p < b.n_pts; p++) {
        b.adj_start[p + 1] += b.adj_start[p];
        b.vertex[p] = UINT32_MAX;
    }
    for (size_t k = 0; k < n_ends; k++) {
        const segnode_pt *at = bsearch(&ends[k], b.pts, b.n_pts, sizeof *b.pts, segnode_pt_cmp);
        if (at)
            b.line_end[at - b.pts] = 1;
    }
    {
        size_t *fill = malloc((b.n_pts + 1) * sizeof *fill);
        if (!fill) {
            st = fail_nomem(&b);
            goto done;
        }
        memcpy(fill, b.adj_start, (b.n_pts + 1) * sizeof *fill);
        for (size_t i = 0; i < n_segs; i++) {
            b.adj[fill[b.seg_a[i]]++] = i;
            b.adj[fill[b.seg_b[i]]++] = i;
        }
        free(fill);
    }
    if ((st = hpfc_graph_create(&b.g)) != 0 ||
        (st = hpfc_graph_set_unit_exp10(b.g, unit_exp10)) != 0) {
        st = fail_graph(&b, st);
        goto done;
    }
    if (all_vertices) {
        for (size_t p = 0; p < b.n_pts && !st; p++) {
            uint32_t v;
            st = gb_vertex(&b, p, &v);
        }
        for (size_t i = 0; i < n_segs && !st; i++)
            if ((st = hpfc_graph_add_edge(b.g, b.seg_a[i], b.seg_b[i], NULL, 0, NULL)) != 0)
                st = fail_graph(&b, st);
    } else {
        /* chains between junctions, then the closed chains with none */
        for (size_t p = 0; p < b.n_pts && !st; p++)
            if (is_junction(&b, p))
                for (size_t k = b.adj_start[p]; k < b.adj_start[p + 1] && !st; k++)
                    if (!b.used[b.adj[k]])
                        st = gb_chain(&b, p, b.adj[k]);
        for (size_t p = 0; p < b.n_pts && !st; p++)
            if (!is_junction(&b, p) && !b.used[b.adj[b.adj_start[p]]])
                st = gb_chain(&b, p, b.adj[b.adj_start[p]]);
    }
done:
    if (!st)
        *out = b.g;
    else
        hpfc_graph_free(b.g);
    free(b.pts);
    free(b.seg_a);
    free(b.seg_b);
    free(b.used);
    free(b.adj_start);
    free(b.adj);
    free(b.vertex);
    free(b.line_end);
    free(b.interior);
    return st;
}

