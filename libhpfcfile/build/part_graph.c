/*
 * The graph of one part of a split build (hpfc_part_graph): the edges of
 * the whole map that come near the part's root pixels.
 *
 * A root pixel's subtree depends only on the segments that meet it, so a
 * part needs those edges whole (a word's crossings are ordered along
 * their edges, and a junction is found from its edge's ends). An edge is
 * kept when one of its segments' closed box meets a selected root pixel's
 * closed cell: a cheap test that keeps every edge that meets the pixels and
 * a few that only pass near, which a part allows.
 *
 * The cut (hpfc_cut_create) makes that test for every part at once, in one
 * pass over the segments: each segment's box names the root pixels it
 * meets, their owners the parts. A part's graph is then copied from its
 * list of edges alone, so k parts cost one pass, not k.
 */
#include <stdlib.h>
#include <string.h>

#include "arrays.h"
#include "graph.h"
#include "sized.h"

#define NO_PART UINT32_MAX

struct hpfc_cut {
    const hpfc_graph *g;
    uint32_t parts;
    uint32_t *start;   /* parts + 1: part k's edges are edge[start[k] .. start[k + 1]) */
    uint32_t *edge;    /* ascending within a part */
};

/* The root grid and who owns each root pixel. */
typedef struct owners {
    const uint32_t *owner;        /* per root pixel: its part, or NO_PART */
    int64_t x0, y0, cw, ch;       /* the domain's corner, a root pixel's size */
    int64_t cols, rows;
} owners;

static int64_t clamp(int64_t v, int64_t lo, int64_t hi)
{
    return v < lo ? lo : v > hi ? hi : v;
}

/* The (part, edge) pairs, grown as edges are met. */
typedef struct pair {
    uint32_t part, edge;
} pair;

typedef struct pairs {
    pair *v;
    size_t n, cap;
} pairs;

static int pairs_add(pairs *ps, uint32_t part, uint32_t e)
{
    if (array_reserve((void **)&ps->v, &ps->cap, ps->n + 1, sizeof *ps->v, 1024))
        return HPFC_E_NOMEM;
    ps->v[ps->n++] = (pair){part, e};
    return HPFC_OK;
}

/* Adds edge e to every part owning a root pixel whose closed cell meets the
 * closed box [ax, bx] x [ay, by] (a point on a grid line meets the cells on
 * both sides); seen[part] == e + 1 marks a part e was already added to. */
static int box_parts(const owners *o, int64_t ax, int64_t ay, int64_t bx, int64_t by, uint32_t e,
                     uint32_t *seen, pairs *ps)
{
    int64_t i0 = clamp((ax - o->x0 - 1) / o->cw, 0, o->cols - 1), i1 = clamp((bx - o->x0) / o->cw, 0, o->cols - 1);
    int64_t g0 = clamp((ay - o->y0 - 1) / o->ch, 0, o->rows - 1), g1 = clamp((by - o->y0) / o->ch, 0, o->rows - 1);
    for (int64_t gy = g0; gy <= g1; gy++)
        for (int64_t i = i0; i <= i1; i++) {
            uint32_t q = o->owner[(o->rows - 1 - gy) * o->cols + i];
            if (q == NO_PART || seen[q] == e + 1)
                continue;
            seen[q] = e + 1;
            if (pairs_add(ps, q, e))
                return HPFC_E_NOMEM;
        }
    return HPFC_OK;
}

/* Every part whose pixels one of e's segments' closed box meets. */
static int edge_parts(const owners *o, const hpfc_graph *g, uint32_t e, uint32_t *seen, pairs *ps)
{
    int64_t px, py;
    graph_edge_point(g, e, 0, &px, &py);
    int st = HPFC_OK;
    for (size_t k = 1; !st && k < graph_edge_point_count(g, e); k++) {
        int64_t qx, qy;
        graph_edge_point(g, e, k, &qx, &qy);
        st = box_parts(o, px < qx ? px : qx, py < qy ? py : qy, px < qx ? qx : px, py < qy ? qy : py, e, seen,
                       ps);
        px = qx, py = qy;
    }
    return st;
}

/* The pairs, grouped by part (a counting sort: edges stay ascending). */
static int group_pairs(const pairs *ps, hpfc_cut *c)
{
    c->start = calloc((size_t)c->parts + 1, sizeof *c->start);
    c->edge = malloc((ps->n ? ps->n : 1) * sizeof *c->edge);
    if (!c->start || !c->edge)
        return HPFC_E_NOMEM;
    for (size_t k = 0; k < ps->n; k++)
        c->start[ps->v[k].part + 1]++;
    for (uint32_t q = 0; q < c->parts; q++)
        c->start[q + 1] += c->start[q];
    uint32_t *next = malloc(((size_t)c->parts ? c->parts : 1) * sizeof *next);
    if (!next)
        return HPFC_E_NOMEM;
    memcpy(next, c->start, (size_t)c->parts * sizeof *next);
    for (size_t k = 0; k < ps->n; k++)
        c->edge[next[ps->v[k].part]++] = ps->v[k].edge;
    free(next);
    return HPFC_OK;
}

void hpfc_cut_free(hpfc_cut *c)
{
    if (!c)
        return;
    free(c->start);
    free(c->edge);
    free(c);
}

int hpfc_cut_create_sized(const hpfc_graph *g, const hpfc_build_params *params_arg, size_t params_size,
                          const hpfc_domain *domain, const uint32_t *owner, uint32_t part_count, hpfc_cut **out,
                          hpfc_diag *diag)
{
    return hpfc_cut_create_range(g, params_arg, params_size, domain, owner, part_count, 0, g ? g->ne : 0,
                                 out, diag);
}

int hpfc_cut_create_range(const hpfc_graph *g, const hpfc_build_params *params_arg, size_t params_size,
                          const hpfc_domain *domain, const uint32_t *owner, uint32_t part_count,
                          size_t first_edge, size_t end_edge, hpfc_cut **out, hpfc_diag *diag)
{
    hpfc_build_params p;
    hpfc_build_params_default(&p);
    diag_clear(diag);
    if (!out)
        return diag_set(diag, HPFC_E_ARG, "hpfc_cut_create: NULL or unknown argument");
    *out = NULL;
    if (!g || !params_arg || !domain || !owner || sized_in(&p, sizeof p, params_arg, params_size) ||
        first_edge > end_edge || end_edge > g->ne)
        return diag_set(diag, HPFC_E_ARG, "hpfc_cut_create: NULL or unknown argument");
    uint64_t roots = (uint64_t)p.root_cols * p.root_rows;
    if (p.root_cols < 1 || p.root_rows < 1 || roots > ((uint64_t)1 << 31) || domain->width < (int64_t)p.root_cols ||
        domain->height < (int64_t)p.root_rows)
        return diag_set(diag, HPFC_E_ARG, "hpfc_cut_create: root image and domain do not agree");
    if (part_count == NO_PART)
        return diag_set(diag, HPFC_E_ARG, "hpfc_cut_create: too many parts");
    for (uint64_t px = 0; px < roots; px++)
        if (owner[px] != NO_PART && owner[px] >= part_count)
            return diag_set(diag, HPFC_E_ARG, "hpfc_cut_create: root pixel %llu in part %u of %u",
                            (unsigned long long)px, owner[px], part_count);
    hpfc_cut *c = calloc(1, sizeof *c);
    uint32_t *seen = calloc(part_count ? part_count : 1, sizeof *seen);
    pairs ps = {0};
    int st = c && seen ? HPFC_OK : HPFC_E_NOMEM;
    owners o = {.owner = owner, .x0 = domain->x0, .y0 = domain->y0, .cw = domain->width / p.root_cols,
                .ch = domain->height / p.root_rows, .cols = p.root_cols, .rows = p.root_rows};
    for (size_t e = first_edge; !st && e < end_edge; e++)
        st = edge_parts(&o, g, (uint32_t)e, seen, &ps);
    if (!st) {
        c->g = g, c->parts = part_count;
        st = group_pairs(&ps, c);
    }
    free(seen);
    free(ps.v);
    if (st) {
        hpfc_cut_free(c);
        return diag_set(diag, st, "out of memory");
    }
    *out = c;
    return HPFC_OK;
}

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

/* The position of v in the ascending verts[0 .. n). */
static uint32_t vertex_rank(const uint32_t *verts, size_t n, uint32_t v)
{
    size_t lo = 0, hi = n;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (verts[mid] < v)
            lo = mid + 1;
        else
            hi = mid;
    }
    return (uint32_t)lo;
}

/* The listed edges (ascending) and their vertices, renumbered in the whole
 * map's order: O(n log n), whatever the whole map's size. */
static int copy_edges(const hpfc_graph *g, const uint32_t *list, size_t n, hpfc_graph *out)
{
    uint32_t *verts = malloc((n ? 2 * n : 1) * sizeof *verts);
    if (!verts)
        return HPFC_E_NOMEM;
    for (size_t k = 0; k < n; k++)
        verts[2 * k] = g->eu[list[k]], verts[2 * k + 1] = g->ev[list[k]];
    qsort(verts, 2 * n, sizeof *verts, cmp_u32);
    size_t nv = 0;
    for (size_t k = 0; k < 2 * n; k++)
        if (nv == 0 || verts[nv - 1] != verts[k])
            verts[nv++] = verts[k];
    int st = hpfc_graph_set_unit_exp10(out, g->unit_exp10);
    for (size_t k = 0; k < nv && !st; k++)
        st = hpfc_graph_add_vertex(out, g->vxy[2 * (size_t)verts[k]], g->vxy[2 * (size_t)verts[k] + 1], NULL);
    for (size_t k = 0; k < n && !st; k++) {
        uint32_t u, v;
        const int64_t *interior; /* through the accessor: a graph of straight edges has no pts */
        size_t n_interior;
        hpfc_graph_edge(g, list[k], &u, &v, &interior, &n_interior);
        st = hpfc_graph_add_edge(out, vertex_rank(verts, nv, u), vertex_rank(verts, nv, v), interior,
                                 n_interior, NULL);
    }
    free(verts);
    return st;
}

int hpfc_cut_part_edges(const hpfc_cut *c, uint32_t part, const uint32_t **edge_ids, size_t *count)
{
    if (!c || !edge_ids || !count || part >= c->parts)
        return HPFC_E_ARG;
    *edge_ids = c->edge + c->start[part];
    *count = c->start[part + 1] - c->start[part];
    return HPFC_OK;
}

int hpfc_graph_copy_edges(const hpfc_graph *g, const uint32_t *edge_ids, size_t count, hpfc_graph **out,
                          hpfc_diag *diag)
{
    diag_clear(diag);
    if (!g || !out || (count && !edge_ids))
        return diag_set(diag, HPFC_E_ARG, "hpfc_graph_copy_edges: NULL argument");
    *out = NULL;
    for (size_t k = 0; k < count; k++)
        if (edge_ids[k] >= g->ne || (k && edge_ids[k] <= edge_ids[k - 1]))
            return diag_set(diag, HPFC_E_ARG, "hpfc_graph_copy_edges: edge ids not ascending within the graph");
    int st = hpfc_graph_create(out);
    if (!st)
        st = copy_edges(g, edge_ids, count, *out);
    if (st) {
        hpfc_graph_free(*out);
        *out = NULL;
        return diag_set(diag, st, "out of memory");
    }
    return HPFC_OK;
}

int hpfc_cut_part_graph(const hpfc_cut *c, uint32_t part, hpfc_graph **out, uint32_t **edge_ids, hpfc_diag *diag)
{
    diag_clear(diag);
    if (!c || !out || !edge_ids || part >= c->parts)
        return diag_set(diag, HPFC_E_ARG, "hpfc_cut_part_graph: NULL argument or no such part");
    *out = NULL;
    size_t n = c->start[part + 1] - c->start[part];
    *edge_ids = malloc((n ? n : 1) * sizeof **edge_ids);
    int st = *edge_ids ? hpfc_graph_create(out) : HPFC_E_NOMEM;
    if (!st) {
        memcpy(*edge_ids, c->edge + c->start[part], n * sizeof **edge_ids);
        st = copy_edges(c->g, *edge_ids, n, *out);
    }
    if (st) {
        hpfc_graph_free(*out);
        free(*edge_ids);
        *out = NULL;
        *edge_ids = NULL;
        return diag_set(diag, st, "out of memory");
    }
    return HPFC_OK;
}

int hpfc_part_graph_sized(const hpfc_graph *g, const hpfc_build_params *params_arg, size_t params_size,
                          const hpfc_part *part, hpfc_graph **out, uint32_t **edge_ids, hpfc_diag *diag)
{
    hpfc_build_params p;
    hpfc_build_params_default(&p);
    diag_clear(diag);
    if (!g || !params_arg || !part || !out || !edge_ids || sized_in(&p, sizeof p, params_arg, params_size) ||
        (part->root_pixel_count && !part->root_pixels))
        return diag_set(diag, HPFC_E_ARG, "hpfc_part_graph: NULL or unknown argument");
    *out = NULL;
    *edge_ids = NULL;
    uint64_t roots = (uint64_t)p.root_cols * p.root_rows;
    if (p.root_cols < 1 || p.root_rows < 1 || roots > ((uint64_t)1 << 31) || part->domain.width < (int64_t)p.root_cols ||
        part->domain.height < (int64_t)p.root_rows)
        return diag_set(diag, HPFC_E_ARG, "hpfc_part_graph: root image and domain do not agree");
    /* one part: the cut's owners are 0 for the part's pixels */
    uint32_t *owner = malloc((size_t)roots * sizeof *owner);
    if (!owner)
        return diag_set(diag, HPFC_E_NOMEM, "out of memory");
    for (uint64_t px = 0; px < roots; px++)
        owner[px] = NO_PART;
    int st = HPFC_OK;
    for (size_t k = 0; !st && k < part->root_pixel_count; k++) {
        if (part->root_pixels[k] >= roots)
            st = diag_set(diag, HPFC_E_ARG, "hpfc_part_graph: root pixel %u beyond the root", part->root_pixels[k]);
        else
            owner[part->root_pixels[k]] = 0;
    }
    hpfc_cut *c = NULL;
    if (!st)
        st = hpfc_cut_create_sized(g, params_arg, params_size, &part->domain, owner, 1, &c, diag);
    if (!st)
        st = hpfc_cut_part_graph(c, 0, out, edge_ids, diag);
    hpfc_cut_free(c);
    free(owner);
    return st;
}
