/*
 * The GEOM section on the write side (spec/hpfc-format.md §6.6), from the
 * graph the tree was built from and the tree itself:
 *
 *   - the graph gives the coordinates, the end vertices and the shape
 *     points, in the graph's own order (vertex and edge ids are indices);
 *   - the tree gives, for a map with shape points, every crossing's
 *     segment (hpfc_tree_pixel.cross_segment) in global leaf order, and,
 *     for every edge, its first crossing in that order: the crossing whose
 *     out-dart's right face LABL's reference writer calls side 0 (§6.5.2).
 *     Whether u -> v leaves the pixel there (exact predicate of geom.h on
 *     the crossing's road) says which side lies on the right of u -> v.
 *
 * Each column is cut into blocks of the size that makes it smallest.
 */
#include <stdlib.h>
#include <string.h>

#include "road.h"
#include "geometry.h"
#include "graph.h"

static uint32_t bits_for(uint64_t max_value)
{
    return max_value ? (uint32_t)(64 - __builtin_clzll(max_value)) : 0;
}

/* A growable array of values. */
typedef struct u64vec {
    uint64_t *v;
    size_t n, cap;
} u64vec;

static bool vec_push(u64vec *a, uint64_t x)
{
    if (a->n == a->cap) {
        size_t cap = a->cap ? 2 * a->cap : 1024;
        uint64_t *v = realloc(a->v, cap * sizeof *v);
        if (!v)
            return false;
        a->v = v;
        a->cap = cap;
    }
    a->v[a->n++] = x;
    return true;
}

/* The encoding chosen for one column. */
typedef struct column_plan {
    uint64_t n;
    uint32_t shift, offset_bits, base_bits;
    uint64_t payload_bits;
} column_plan;

typedef struct geom_plan geom_plan;
static uint64_t column_value(const geom_plan *p, int c, uint64_t i);

/* The smallest and largest values of block [b, end) of column c. */
static void block_range(const geom_plan *p, int c, uint64_t b, uint64_t end, uint64_t *lo,
                        uint64_t *hi)
{
    *lo = UINT64_MAX, *hi = 0;
    for (uint64_t i = b; i < end; i++) {
        uint64_t v = column_value(p, c, i);
        *lo = v < *lo ? v : *lo;
        *hi = v > *hi ? v : *hi;
    }
}

/* Bits of column c with blocks of 2^shift values; fills the widths. */
static uint64_t column_size(const geom_plan *p, int c, uint64_t n, uint32_t shift,
                            uint32_t *offset_bits, uint32_t *base_bits, uint64_t *payload_bits)
{
    uint64_t B = UINT64_C(1) << shift, payload = 0, max_base = 0, max_off = 0, blocks = 0;
    for (uint64_t b = 0; b < n; b += B, blocks++) {
        uint64_t end = n - b < B ? n : b + B, lo, hi;
        block_range(p, c, b, end, &lo, &hi);
        max_base = lo > max_base ? lo : max_base;
        max_off = payload;
        payload += (end - b) * (uint64_t)bits_for(hi - lo);
    }
    *offset_bits = bits_for(max_off);
    *base_bits = bits_for(max_base);
    *payload_bits = payload;
    return blocks * (*offset_bits + *base_bits + GEOM_WIDTH_BITS) + payload;
}

static void plan_column(const geom_plan *p, int c, column_plan *cp)
{
    uint64_t best = UINT64_MAX;
    for (uint32_t s = 0; s <= 12; s++) {
        uint32_t ob, bb;
        uint64_t pb, size = column_size(p, c, cp->n, s, &ob, &bb, &pb);
        if (size < best) {
            best = size;
            cp->shift = s, cp->offset_bits = ob, cp->base_bits = bb, cp->payload_bits = pb;
        }
    }
}

static void emit_column(const geom_plan *p, int c, const column_plan *cp, uint8_t *dir,
                        uint8_t *payload)
{
    uint64_t B = UINT64_C(1) << cp->shift, at = 0;
    uint64_t entry = cp->offset_bits + cp->base_bits + GEOM_WIDTH_BITS;
    for (uint64_t b = 0, k = 0; b < cp->n; b += B, k++) {
        uint64_t end = cp->n - b < B ? cp->n : b + B, lo, hi;
        block_range(p, c, b, end, &lo, &hi);
        uint32_t w = bits_for(hi - lo);
        format_put(dir, k * entry, cp->offset_bits, at);
        format_put(dir, k * entry + cp->offset_bits, cp->base_bits, lo);
        format_put(dir, k * entry + cp->offset_bits + cp->base_bits, GEOM_WIDTH_BITS, w);
        for (uint64_t i = b; i < end; i++, at += w)
            format_put(payload, at, w, column_value(p, c, i) - lo);
    }
}

/* The graph's columns are read from the graph itself; only the tree's
 * (each leaf's first crossing, each crossing's segment) are collected. */
struct geom_plan {
    const hpfc_graph *g;
    hpfc_tree_info ti;
    column_plan col[GEOM_COLUMNS];
    u64vec lcross, cseg;
    uint8_t *orient;        /* E bits, as the section stores them */
    uint8_t *seen;          /* per edge: its first crossing was met */
    uint64_t leaves, crossings;
};

static uint64_t column_value(const geom_plan *p, int c, uint64_t i)
{
    const hpfc_graph *g = p->g;
    switch (c) {
    case GEOM_VX: return (uint64_t)(g->vxy[2 * i] - p->ti.x0);
    case GEOM_VY: return (uint64_t)(g->vxy[2 * i + 1] - p->ti.y0);
    case GEOM_EU: return g->eu[i];
    case GEOM_EV: return g->ev[i];
    case GEOM_EPOINT: return g->eoff[i];
    case GEOM_PX: return (uint64_t)(g->pts[2 * i] - p->ti.x0);
    case GEOM_PY: return (uint64_t)(g->pts[2 * i + 1] - p->ti.y0);
    case GEOM_LCROSS: return p->lcross.v[i];
    default: return p->cseg.v[i];
    }
}

static void plan_free(geom_plan *p)
{
    free(p->lcross.v);
    free(p->cseg.v);
    free(p->orient);
    free(p->seen);
}

/* Every vertex and shape point inside the tree's domain (the columns
 * store them relative to its corner, below W and H). */
static int check_graph_domain(const geom_plan *p, hpfc_diag *diag)
{
    const hpfc_graph *g = p->g;
    uint64_t W = (uint64_t)p->ti.width, H = (uint64_t)p->ti.height;
    for (size_t k = 0; k < g->nv; k++)
        if (column_value(p, GEOM_VX, k) >= W || column_value(p, GEOM_VY, k) >= H)
            return diag_set(diag, HPFC_E_ARG, "geometry: vertex %zu lies outside the tree's domain", k);
    for (size_t k = 0; k < g->npts; k++)
        if (column_value(p, GEOM_PX, k) >= W || column_value(p, GEOM_PY, k) >= H)
            return diag_set(diag, HPFC_E_ARG,
                            "geometry: shape point %zu lies outside the tree's domain", k);
    return HPFC_OK;
}

/* Does edge e, run from u to v, enter the pixel at its crossing on road
 * `road` along segment `seg`? (false: it leaves there) */
static int edge_enters(const geom_plan *p, uint64_t e, uint64_t seg, int road,
                       const hpfc_tree_pixel *px, bool *entering)
{
    int64_t ax, ay, bx, by;
    graph_edge_point(p->g, e, seg, &ax, &ay);
    graph_edge_point(p->g, e, seg + 1, &bx, &by);
    int64_t x0 = p->ti.x0, y0 = p->ti.y0;
    lpoint a = {ax - x0, ay - y0}, b = {bx - x0, by - y0};
    line_pos pos;
    return cross_road(a, b, road, px->x0 - x0, px->y0 - y0, px->x1 - x0, px->y1 - y0, &pos,
                      entering)
               ? HPFC_OK
               : HPFC_E_ARG;
}

/* One leaf: its crossings' segments, and the orientation of every edge
 * whose first crossing it holds. */
static int plan_leaf(geom_plan *p, const hpfc_tree_pixel *px, hpfc_diag *diag)
{
    bool shaped = p->g->npts > 0;
    if (shaped && !vec_push(&p->lcross, p->crossings))
        return diag_set(diag, HPFC_E_NOMEM, "geometry: out of memory");
    p->leaves++;
    int road = 0;
    for (uint32_t s = 0, c = 0; s < px->word_len; s++) {
        if (px->word[s] == '+') {
            road++;
            continue;
        }
        uint64_t e = px->cross_edge[c], seg = px->cross_segment[c];
        c++;
        p->crossings++;
        if (e >= p->g->ne || seg + 1 >= graph_edge_point_count(p->g, e) || road > 3)
            return diag_set(diag, HPFC_E_ARG, "geometry: a crossing of the tree names no segment of the graph");
        if (shaped && !vec_push(&p->cseg, seg))
            return diag_set(diag, HPFC_E_NOMEM, "geometry: out of memory");
        if (p->seen[e >> 3] & (1u << (e & 7)))
            continue;
        p->seen[e >> 3] |= (uint8_t)(1u << (e & 7));
        bool entering;
        if (edge_enters(p, e, seg, road, px, &entering))
            return diag_set(diag, HPFC_E_ARG,
                            "geometry: edge %llu does not cross its leaf where the tree says",
                            (unsigned long long)e);
        /* LABL's side 0 is right of the out-dart here: if u -> v enters, the
         * out-dart runs v -> u and u -> v has side 1 on its right */
        if (entering)
            format_put(p->orient, e, 1, 1);
    }
    return HPFC_OK;
}

/* Every leaf in global order: levels in turn, images in pool order, each
 * in scanline order (the order of the pools, and LABL's). */
static int plan_tree(geom_plan *p, const hpfc_tree *tree, hpfc_diag *diag)
{
    for (uint32_t l = 0; l < p->ti.levels; l++) {
        uint32_t cols = l ? p->ti.cols : p->ti.root_cols, rows = l ? p->ti.rows : p->ti.root_rows;
        size_t images = hpfc_tree_image_count(tree, l);
        for (size_t im = 0; im < images; im++)
            for (uint32_t j = 0; j < rows; j++)
                for (uint32_t i = 0; i < cols; i++) {
                    hpfc_tree_pixel px;
                    int st = hpfc_tree_get_pixel(tree, l, im, i, j, &px);
                    if (st)
                        return diag_set(diag, st, "geometry: no pixel (%u, %u)", i, j);
                    if (px.type == HPFC_PIXEL_WORD && (st = plan_leaf(p, &px, diag)))
                        return st;
                }
    }
    return HPFC_OK;
}

int geometry_build(const hpfc_tree *tree, const hpfc_graph *graph, uint8_t **out,
                   uint64_t *length, hpfc_diag *diag)
{
    *out = NULL;
    *length = 0;
    geom_plan p = {.g = graph};
    hpfc_tree_get_info(tree, &p.ti);
    if (graph->nv != p.ti.vertices || graph->ne != p.ti.edges || graph->ne == 0)
        return diag_set(diag, HPFC_E_ARG, "geometry: the graph is not the one the tree was built from");
    int st = HPFC_OK;
    size_t bytes = (graph->ne + 7) / 8;
    if (!(p.orient = calloc(1, bytes)) || !(p.seen = calloc(1, bytes)))
        st = diag_set(diag, HPFC_E_NOMEM, "geometry: out of memory");
    if (!st)
        st = check_graph_domain(&p, diag);
    if (!st)
        st = plan_tree(&p, tree, diag);
    uint64_t counts[GEOM_COLUMNS], payload[GEOM_COLUMNS];
    uint32_t shift[GEOM_COLUMNS], ob[GEOM_COLUMNS], bb[GEOM_COLUMNS];
    geom_layout lay;
    uint64_t points = graph->npts;
    if (!st) {
        geom_column_counts(graph->nv, graph->ne, points, points ? p.leaves : 0,
                           points ? p.crossings : 0, counts);
        for (int c = 0; c < GEOM_COLUMNS; c++) {
            p.col[c].n = counts[c];
            plan_column(&p, c, &p.col[c]);
            shift[c] = p.col[c].shift, ob[c] = p.col[c].offset_bits, bb[c] = p.col[c].base_bits;
            payload[c] = p.col[c].payload_bits;
        }
        if (p.lcross.n != counts[GEOM_LCROSS] || p.cseg.n != counts[GEOM_CSEG])
            st = diag_set(diag, HPFC_E_ARG, "geometry: the tree's crossings do not add up");
    }
    if (!st && (!geom_compute_layout(counts, graph->ne, shift, ob, bb, payload, &lay) ||
                lay.length > SIZE_MAX))
        st = diag_set(diag, HPFC_E_LIMIT, "geometry: the section would be too large");
    uint8_t *sec = NULL;
    if (!st && !(sec = calloc(1, (size_t)lay.length)))
        st = diag_set(diag, HPFC_E_NOMEM, "geometry: out of memory");
    if (!st) {
        geom_set_vertex_count(sec, graph->nv);
        geom_set_edge_count(sec, graph->ne);
        geom_set_point_count(sec, points);
        geom_set_leaf_count(sec, counts[GEOM_LCROSS]);
        geom_set_crossing_count(sec, counts[GEOM_CSEG]);
        memcpy(sec + lay.orient_at, p.orient, bytes);
        for (int c = 0; c < GEOM_COLUMNS; c++) {
            uint8_t *d = sec + GEOM_HEADER_SIZE + (size_t)c * GEOM_COLUMN_SIZE;
            geomc_set_block_shift(d, (uint8_t)shift[c]);
            geomc_set_offset_bits(d, (uint8_t)ob[c]);
            geomc_set_base_bits(d, (uint8_t)bb[c]);
            geomc_set_payload_bits(d, payload[c]);
            emit_column(&p, c, &p.col[c], sec + lay.dir_at[c], sec + lay.payload_at[c]);
        }
        *out = sec;
        *length = lay.length;
    }
    plan_free(&p);
    return st;
}
