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
 */
#include <stdlib.h>
#include <string.h>

#include "graph.h"
#include "sized.h"

typedef struct selection {
    const uint8_t *bits;          /* one per root pixel */
    int64_t x0, y0, cw, ch;       /* the domain's corner, a root pixel's size */
    int64_t cols, rows;
} selection;

static int64_t clamp(int64_t v, int64_t lo, int64_t hi)
{
    return v < lo ? lo : v > hi ? hi : v;
}

/* Does the closed box [ax, bx] x [ay, by] meet a selected root pixel? A
 * point on a grid line meets the cells on both sides. */
static bool box_selected(const selection *s, int64_t ax, int64_t ay, int64_t bx, int64_t by)
{
    int64_t i0 = clamp((ax - s->x0 - 1) / s->cw, 0, s->cols - 1), i1 = clamp((bx - s->x0) / s->cw, 0, s->cols - 1);
    int64_t g0 = clamp((ay - s->y0 - 1) / s->ch, 0, s->rows - 1), g1 = clamp((by - s->y0) / s->ch, 0, s->rows - 1);
    for (int64_t gy = g0; gy <= g1; gy++)
        for (int64_t i = i0; i <= i1; i++) {
            int64_t p = (s->rows - 1 - gy) * s->cols + i;
            if (s->bits[p >> 3] >> (p & 7) & 1)
                return true;
        }
    return false;
}

static bool edge_selected(const selection *s, const hpfc_graph *g, size_t e)
{
    int64_t px, py;
    graph_edge_point(g, e, 0, &px, &py);
    for (size_t k = 1; k < graph_edge_point_count(g, e); k++) {
        int64_t qx, qy;
        graph_edge_point(g, e, k, &qx, &qy);
        if (box_selected(s, px < qx ? px : qx, py < qy ? py : qy, px < qx ? qx : px, py < qy ? qy : py))
            return true;
        px = qx, py = qy;
    }
    return false;
}

/* The kept edges (edge_ids) and their vertices, renumbered in order. */
static int copy_selected(const hpfc_graph *g, const uint8_t *keep, uint32_t *edge_ids, hpfc_graph *out)
{
    uint32_t *vmap = malloc((g->nv ? g->nv : 1) * sizeof *vmap);
    if (!vmap)
        return HPFC_E_NOMEM;
    for (size_t v = 0; v < g->nv; v++)
        vmap[v] = UINT32_MAX;
    for (size_t e = 0; e < g->ne; e++)
        if (keep[e])
            vmap[g->eu[e]] = vmap[g->ev[e]] = 0;
    int st = hpfc_graph_set_unit_exp10(out, g->unit_exp10);
    uint32_t next = 0;
    for (size_t v = 0; v < g->nv && !st; v++)
        if (vmap[v] == 0 && !(st = hpfc_graph_add_vertex(out, g->vxy[2 * v], g->vxy[2 * v + 1], NULL)))
            vmap[v] = next++;
    size_t kept = 0;
    for (size_t e = 0; e < g->ne && !st; e++)
        if (keep[e]) {
            size_t n = g->eoff[e + 1] - g->eoff[e];
            st = hpfc_graph_add_edge(out, vmap[g->eu[e]], vmap[g->ev[e]], g->pts + 2 * g->eoff[e], n, NULL);
            edge_ids[kept++] = (uint32_t)e;
        }
    free(vmap);
    return st;
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
    uint8_t *bits = calloc((size_t)(roots + 7) / 8, 1), *keep = calloc(g->ne ? g->ne : 1, 1);
    *edge_ids = malloc((g->ne ? g->ne : 1) * sizeof **edge_ids);
    int st = bits && keep && *edge_ids ? hpfc_graph_create(out) : HPFC_E_NOMEM;
    for (size_t k = 0; !st && k < part->root_pixel_count; k++) {
        if (part->root_pixels[k] >= roots)
            st = diag_set(diag, HPFC_E_ARG, "hpfc_part_graph: root pixel %u beyond the root", part->root_pixels[k]);
        else
            bits[part->root_pixels[k] >> 3] |= (uint8_t)(1u << (part->root_pixels[k] & 7));
    }
    selection s = {.bits = bits, .x0 = part->domain.x0, .y0 = part->domain.y0,
                   .cw = part->domain.width / p.root_cols, .ch = part->domain.height / p.root_rows,
                   .cols = p.root_cols, .rows = p.root_rows};
    for (size_t e = 0; !st && e < g->ne; e++)
        keep[e] = edge_selected(&s, g, e);
    if (!st)
        st = copy_selected(g, keep, *edge_ids, *out);
    free(bits);
    free(keep);
    if (st) {
        if (st == HPFC_E_NOMEM)
            diag_set(diag, st, "out of memory");
        hpfc_graph_free(*out);
        free(*edge_ids);
        *out = NULL;
        *edge_ids = NULL;
    }
    return st;
}
