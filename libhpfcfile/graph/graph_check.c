/*
 * graph_check.c: the checks of a whole graph that need no geometry beyond
 * point equality: no isolated vertex, no two points at one place. The .pfc
 * reader (spec/pfc-format.md §5, rules 5 and 6) and hpfc_graph_validate
 * both run them, so a map gets the same verdict, the same culprit and the
 * same words from either.
 *
 * Culprits are a function of the graph alone, never of the sort: the
 * points of the graph are ordered vertices first (by index), then interior
 * points (by edge, then position), and the pair named is the one whose
 * later point comes first in that order, with the earliest point at its
 * place (for a .pfc file: the repeat defined first in the file).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "graph.h"

/* A point of the graph: a vertex (edge < 0) or interior point `index` of
 * `edge`. */
typedef struct point_ref {
    int64_t x, y;
    int64_t edge;   /* -1 for a vertex */
    size_t index;   /* vertex index, or interior point index */
} point_ref;

static int cmp3(int64_t a, int64_t b)
{
    return (a > b) - (a < b);
}

/* The culprit order: vertices by index, then interior points by edge and
 * position. */
static int cmp_ref_order(const point_ref *a, const point_ref *b)
{
    int c = cmp3(a->edge, b->edge);
    return c ? c : (a->index > b->index) - (a->index < b->index);
}

/* By place, then in culprit order: a total order, as no two refs are one. */
static int cmp_point_ref(const void *pa, const void *pb)
{
    const point_ref *a = pa, *b = pb;
    int c = cmp3(a->x, b->x);
    if (!c)
        c = cmp3(a->y, b->y);
    return c ? c : cmp_ref_order(a, b);
}

static bool same_place(const point_ref *a, const point_ref *b)
{
    return a->x == b->x && a->y == b->y;
}

static uint32_t ref_line(const hpfc_graph *g, const point_ref *p)
{
    return p->edge < 0 ? graph_vertex_line(g, p->index) : graph_edge_line(g, (size_t)p->edge);
}

/* "vertex 3", "interior point 2 of edge 5" (1-based, as in the file). */
static void describe(const point_ref *p, char *buf, size_t size)
{
    if (p->edge < 0)
        snprintf(buf, size, "vertex %zu", p->index);
    else
        snprintf(buf, size, "interior point %zu of edge %lld", p->index + 1, (long long)p->edge);
}

/* "line N: " when the graph knows the culprit's line (a .pfc file's), else
 * nothing: the one-line shape of spec/pfc-format.md §5. */
static void line_prefix(uint32_t line, char buf[24])
{
    if (line)
        snprintf(buf, 24, "line %u: ", (unsigned)line);
    else
        buf[0] = '\0';
}

/* Point k of the graph in the culprit order: vertices, then the edges'
 * interior points, which g->pts holds in that order. */
static const int64_t *point_at(const hpfc_graph *g, size_t k)
{
    return k < g->nv ? g->vxy + 2 * k : g->pts + 2 * (k - g->nv);
}

static uint64_t place_hash(const int64_t *p)
{
    uint64_t h = (uint64_t)p[0] * UINT64_C(0x9E3779B97F4A7C15) ^ (uint64_t)p[1];
    h ^= h >> 29;
    h *= UINT64_C(0xBF58476D1CE4E5B9);
    return h ^ h >> 32;
}

/* Whether some two of the first n points share a place: 1 yes, 0 no, -1
 * not known (out of memory, too many points for the table's 32-bit slots,
 * or too many probes). An open-addressing table of point numbers, at most
 * half full: a probe or two a point, where sorting the points took a
 * comparison sort of 32-byte records (2.5 s for 7 M points, and four times
 * the table's memory). Only a repeat's culprit needs the sort, and so does
 * a graph whose points were chosen to collide in the table (the hash is
 * fixed and the input may be hostile): past 8 probes a point on average,
 * the sort's n log n decides instead. */
static int any_repeat(const hpfc_graph *g, size_t n)
{
    if (n >= UINT32_MAX / 2)
        return -1;
    size_t budget = 8 * n + 1024;
    size_t size = 16;
    while (size < 2 * n)
        size *= 2;
    uint32_t *slot = malloc(size * sizeof *slot);
    if (!slot)
        return -1;
    memset(slot, 0xff, size * sizeof *slot); /* UINT32_MAX: empty */
    int repeat = 0;
    for (size_t k = 0; k < n && !repeat; k++) {
        const int64_t *p = point_at(g, k);
        for (size_t at = (size_t)place_hash(p) & (size - 1);; at = (at + 1) & (size - 1)) {
            if (budget-- == 0) {
                repeat = -1;
                break;
            }
            if (slot[at] == UINT32_MAX) {
                slot[at] = (uint32_t)k;
                break;
            }
            const int64_t *q = point_at(g, slot[at]);
            if (q[0] == p[0] && q[1] == p[1]) {
                repeat = 1;
                break;
            }
        }
    }
    free(slot);
    return repeat;
}

int graph_check_duplicates(const hpfc_graph *g, bool interior, hpfc_diag *diag)
{
    size_t n = g->nv + (interior ? g->npts : 0);
    if (any_repeat(g, n) == 0)
        return HPFC_OK;
    point_ref *refs = malloc((n ? n : 1) * sizeof *refs);
    if (!refs)
        return diag_set(diag, HPFC_E_NOMEM, "out of memory");
    size_t k = 0;
    for (size_t v = 0; v < g->nv; v++)
        refs[k++] = (point_ref){g->vxy[2 * v], g->vxy[2 * v + 1], -1, v};
    for (size_t e = 0; interior && e < g->ne; e++)
        for (size_t p = g->eoff[e]; p < g->eoff[e + 1]; p++)
            refs[k++] = (point_ref){g->pts[2 * p], g->pts[2 * p + 1], (int64_t)e, p - g->eoff[e]};
    qsort(refs, n, sizeof *refs, cmp_point_ref);
    /* each place's points start with its earliest, then its first repeat */
    size_t culprit = 0;
    for (size_t i = 1; i < n; i++)
        if (same_place(&refs[i - 1], &refs[i]) && (i == 1 || !same_place(&refs[i - 2], &refs[i - 1])) &&
            (!culprit || cmp_ref_order(&refs[i], &refs[culprit]) < 0))
            culprit = i;
    if (!culprit) {
        free(refs);
        return HPFC_OK;
    }
    point_ref later = refs[culprit], first = refs[culprit - 1];
    free(refs);
    if (!diag)
        return HPFC_E_DUPLICATE_POINT;
    char at[24], a[96], b[96], xs[64], ys[64], on[24] = "";
    uint32_t first_line = ref_line(g, &first);
    line_prefix(ref_line(g, &later), at);
    describe(&later, a, sizeof a);
    describe(&first, b, sizeof b);
    if (first_line)
        snprintf(on, sizeof on, " on line %u", (unsigned)first_line);
    diag->line = ref_line(g, &later);
    diag->edge[0] = first.edge;
    diag->edge[1] = later.edge;
    diag_point(diag, (double)later.x, (double)later.y, g->unit_exp10);
    return diag_set(diag, HPFC_E_DUPLICATE_POINT, "%s%s is at the same point (%s, %s) as %s%s", at, a,
                    lattice_to_text(later.x, -(int64_t)g->unit_exp10, xs),
                    lattice_to_text(later.y, -(int64_t)g->unit_exp10, ys), b, on);
}

int graph_check_isolated(const hpfc_graph *g, hpfc_diag *diag)
{
    uint8_t *used = calloc(g->nv ? g->nv : 1, 1);
    if (!used)
        return diag_set(diag, HPFC_E_NOMEM, "out of memory");
    for (size_t e = 0; e < g->ne; e++)
        used[g->eu[e]] = used[g->ev[e]] = 1;
    size_t lonely = 0;
    while (lonely < g->nv && used[lonely])
        lonely++;
    free(used);
    if (lonely == g->nv)
        return HPFC_OK;
    if (!diag)
        return HPFC_E_ISOLATED_VERTEX;
    char at[24];
    line_prefix(graph_vertex_line(g, lonely), at);
    diag->line = graph_vertex_line(g, lonely);
    diag_point(diag, (double)g->vxy[2 * lonely], (double)g->vxy[2 * lonely + 1], g->unit_exp10);
    return diag_set(diag, HPFC_E_ISOLATED_VERTEX, "%svertex %zu has no edge (isolated vertex)", at,
                    lonely);
}
