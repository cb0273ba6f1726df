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
 * Each column is cut into blocks of the size that makes it smallest. The
 * section is made in two passes over its values and never held: the plan
 * (geometry_plan) measures every column at every block size in one pass,
 * and the emission (geometry_emit) streams each column's directory and
 * payload to the file as its blocks fill (stream.h). The tree's columns
 * are read off a walk of the tree in each pass rather than kept: they
 * have a value per leaf and per crossing, 8 bytes each when kept, several
 * times what the section stores for them.
 */
#include <stdlib.h>
#include <string.h>

#include "geometry.h"
#include "geometry_write.h"
#include "graph.h"
#include "road.h"

static uint32_t bits_for(uint64_t max_value)
{
    return max_value ? (uint32_t)(64 - __builtin_clzll(max_value)) : 0;
}

/* ---- a column measured at every block size, in one pass ---------------------- */

enum { PLAN_SHIFTS = 13 }; /* blocks of 2^0 .. 2^12 values */

/* Per block size 2^s: the open block (s >= 1: the closed blocks of 2^(s-1)
 * values merged into it), and the sums over the closed ones. */
typedef struct column_stats {
    uint64_t lo[PLAN_SHIFTS], hi[PLAN_SHIFTS], fill[PLAN_SHIFTS];
    uint64_t payload[PLAN_SHIFTS], last_start[PLAN_SHIFTS], max_base[PLAN_SHIFTS];
    uint64_t blocks[PLAN_SHIFTS];
} column_stats;

/* A block of n values in [lo, hi] closed at size 2^s: counted, then merged
 * into the open block of twice its size, which closes in turn when full.
 * Each value closes O(1) blocks on average, so the pass costs little more
 * than one block size did. */
static void stats_close(column_stats *cs, uint32_t s, uint64_t lo, uint64_t hi, uint64_t n)
{
    for (;;) {
        cs->max_base[s] = lo > cs->max_base[s] ? lo : cs->max_base[s];
        cs->last_start[s] = cs->payload[s];
        cs->payload[s] += n * bits_for(hi - lo);
        cs->blocks[s]++;
        if (++s == PLAN_SHIFTS)
            return;
        if (cs->fill[s] == 0) {
            cs->lo[s] = lo, cs->hi[s] = hi;
        } else {
            cs->lo[s] = lo < cs->lo[s] ? lo : cs->lo[s];
            cs->hi[s] = hi > cs->hi[s] ? hi : cs->hi[s];
        }
        cs->fill[s] += n;
        if (cs->fill[s] < (UINT64_C(1) << s))
            return;
        lo = cs->lo[s], hi = cs->hi[s], n = cs->fill[s];
        cs->fill[s] = 0;
    }
}

static void stats_push(column_stats *cs, uint64_t v)
{
    stats_close(cs, 0, v, v, 1);
}

/* The column's end: at each size its last block, shorter than the others
 * (the smaller sizes' first, since each joins the next size's). */
static void stats_end(column_stats *cs)
{
    for (uint32_t s = 1; s < PLAN_SHIFTS; s++)
        if (cs->fill[s]) {
            uint64_t n = cs->fill[s];
            cs->fill[s] = 0;
            stats_close(cs, s, cs->lo[s], cs->hi[s], n);
        }
}

/* The encoding chosen for one column. */
typedef struct column_plan {
    uint64_t n;
    uint32_t shift, offset_bits, base_bits;
    uint64_t payload_bits;
} column_plan;

/* The block size that makes the column smallest (the smallest of equals):
 * a directory entry per block (the payload offset of its first value, its
 * base, its width) and the values less their block's base. */
static void choose_shift(const column_stats *cs, uint64_t n, column_plan *cp)
{
    uint64_t best = UINT64_MAX;
    cp->n = n;
    for (uint32_t s = 0; s < PLAN_SHIFTS; s++) {
        uint32_t ob = bits_for(cs->last_start[s]), bb = bits_for(cs->max_base[s]);
        uint64_t size = cs->blocks[s] * (ob + bb + GEOM_WIDTH_BITS) + cs->payload[s];
        if (size < best) {
            best = size;
            cp->shift = s, cp->offset_bits = ob, cp->base_bits = bb;
            cp->payload_bits = cs->payload[s];
        }
    }
}

/* ---- a column streamed out, a block at a time --------------------------------- */

typedef struct column_out {
    const column_plan *cp;
    bitout *dir, *payload;
    uint64_t fill, at; /* values in block; payload bits before it */
    uint64_t block[UINT64_C(1) << (PLAN_SHIFTS - 1)];
} column_out;

static void out_block(column_out *o)
{
    uint64_t lo = UINT64_MAX, hi = 0;
    for (uint64_t i = 0; i < o->fill; i++) {
        lo = o->block[i] < lo ? o->block[i] : lo;
        hi = o->block[i] > hi ? o->block[i] : hi;
    }
    uint32_t w = bits_for(hi - lo);
    bitout_put(o->dir, o->cp->offset_bits, o->at);
    bitout_put(o->dir, o->cp->base_bits, lo);
    bitout_put(o->dir, GEOM_WIDTH_BITS, w);
    for (uint64_t i = 0; i < o->fill; i++)
        bitout_put(o->payload, w, o->block[i] - lo);
    o->at += o->fill * w;
    o->fill = 0;
}

static void out_push(column_out *o, uint64_t v)
{
    o->block[o->fill++] = v;
    if (o->fill == UINT64_C(1) << o->cp->shift)
        out_block(o);
}

/* ---- the plan ----------------------------------------------------------------- */

struct geom_writer {
    const hpfc_graph *g;
    const hpfc_tree *tree;
    hpfc_tree_info ti;
    uint64_t counts[GEOM_COLUMNS];
    column_plan col[GEOM_COLUMNS];
    geom_layout lay;
    uint8_t *head;        /* the section's first bytes: header, column entries, orientation bits */
    uint64_t head_length;
};

void geometry_writer_free(geom_writer *w)
{
    if (w) {
        free(w->head);
        free(w);
    }
}

/* Value i of one of the graph's columns (those before GEOM_LCROSS). */
static uint64_t graph_value(const geom_writer *w, int c, uint64_t i)
{
    const hpfc_graph *g = w->g;
    switch (c) {
    case GEOM_VX: return (uint64_t)(g->vxy[2 * i] - w->ti.x0);
    case GEOM_VY: return (uint64_t)(g->vxy[2 * i + 1] - w->ti.y0);
    case GEOM_EU: return g->eu[i];
    case GEOM_EV: return g->ev[i];
    case GEOM_EPOINT: return g->eoff[i];
    case GEOM_PX: return (uint64_t)(g->pts[2 * i] - w->ti.x0);
    default: return (uint64_t)(g->pts[2 * i + 1] - w->ti.y0);
    }
}

/* Every vertex and shape point inside the tree's domain (the columns
 * store them relative to its corner, below W and H). */
static int check_graph_domain(const geom_writer *w, hpfc_diag *diag)
{
    const hpfc_graph *g = w->g;
    uint64_t W = (uint64_t)w->ti.width, H = (uint64_t)w->ti.height;
    for (size_t k = 0; k < g->nv; k++)
        if (graph_value(w, GEOM_VX, k) >= W || graph_value(w, GEOM_VY, k) >= H)
            return diag_set(diag, HPFC_E_ARG, "geometry: vertex %zu lies outside the tree's domain", k);
    for (size_t k = 0; k < g->npts; k++)
        if (graph_value(w, GEOM_PX, k) >= W || graph_value(w, GEOM_PY, k) >= H)
            return diag_set(diag, HPFC_E_ARG,
                            "geometry: shape point %zu lies outside the tree's domain", k);
    return HPFC_OK;
}

/* A walk of the tree's leaves for its two columns: measured (the plan,
 * which also checks the crossings and finds each edge's orientation), or
 * streamed out (the emission). */
typedef struct tree_walk {
    const geom_writer *w;
    column_stats *stats; /* GEOM_LCROSS's and GEOM_CSEG's, or */
    column_out *out[2];
    uint8_t *seen;       /* plan: per edge, its first crossing was met */
    uint8_t *orient;     /* plan: E bits, as the section stores them */
    uint64_t leaves, crossings;
} tree_walk;

static void tree_value(tree_walk *t, int c, uint64_t v)
{
    if (t->stats)
        stats_push(&t->stats[c - GEOM_LCROSS], v);
    else
        out_push(t->out[c - GEOM_LCROSS], v);
}

/* Does edge e, run from u to v, enter the pixel at its crossing on road
 * `road` along segment `seg`? (false: it leaves there) */
static int edge_enters(const geom_writer *w, uint64_t e, uint64_t seg, int road,
                       const hpfc_tree_pixel *px, bool *entering)
{
    int64_t ax, ay, bx, by;
    graph_edge_point(w->g, e, seg, &ax, &ay);
    graph_edge_point(w->g, e, seg + 1, &bx, &by);
    int64_t x0 = w->ti.x0, y0 = w->ti.y0;
    lpoint a = {ax - x0, ay - y0}, b = {bx - x0, by - y0};
    line_pos pos;
    return cross_road(a, b, road, px->x0 - x0, px->y0 - y0, px->x1 - x0, px->y1 - y0, &pos,
                      entering)
               ? HPFC_OK
               : HPFC_E_ARG;
}

/* The plan's check of one crossing, and the orientation of its edge when
 * this is the edge's first. */
static int plan_crossing(tree_walk *t, const hpfc_tree_pixel *px, uint64_t e, uint64_t seg,
                         int road, hpfc_diag *diag)
{
    const hpfc_graph *g = t->w->g;
    if (e >= g->ne || seg + 1 >= graph_edge_point_count(g, e) || road > 3)
        return diag_set(diag, HPFC_E_ARG, "geometry: a crossing of the tree names no segment of the graph");
    if (t->seen[e >> 3] & (1u << (e & 7)))
        return HPFC_OK;
    t->seen[e >> 3] |= (uint8_t)(1u << (e & 7));
    bool entering;
    if (edge_enters(t->w, e, seg, road, px, &entering))
        return diag_set(diag, HPFC_E_ARG, "geometry: edge %llu does not cross its leaf where the tree says",
                        (unsigned long long)e);
    /* LABL's side 0 is right of the out-dart here: if u -> v enters, the
     * out-dart runs v -> u and u -> v has side 1 on its right */
    if (entering)
        format_put(t->orient, e, 1, 1);
    return HPFC_OK;
}

/* One leaf: its first crossing's number and its crossings' segments. */
static int walk_leaf(tree_walk *t, const hpfc_tree_pixel *px, hpfc_diag *diag)
{
    bool shaped = t->w->g->npts > 0;
    if (shaped)
        tree_value(t, GEOM_LCROSS, t->crossings);
    t->leaves++;
    int road = 0;
    for (uint32_t s = 0, c = 0; s < px->word_len; s++) {
        if (px->word[s] == '+') {
            road++;
            continue;
        }
        uint64_t e = px->cross_edge[c], seg = px->cross_segment[c];
        c++;
        t->crossings++;
        int st = t->seen ? plan_crossing(t, px, e, seg, road, diag) : HPFC_OK;
        if (st)
            return st;
        if (shaped)
            tree_value(t, GEOM_CSEG, seg);
    }
    return HPFC_OK;
}

/* Every leaf in global order: levels in turn, images in pool order, each
 * in scanline order (the order of the pools, and LABL's). */
static int walk_tree(tree_walk *t, hpfc_diag *diag)
{
    const hpfc_tree_info *ti = &t->w->ti;
    for (uint32_t l = 0; l < ti->levels; l++) {
        uint32_t cols = l ? ti->cols : ti->root_cols, rows = l ? ti->rows : ti->root_rows;
        size_t images = hpfc_tree_image_count(t->w->tree, l);
        for (size_t im = 0; im < images; im++)
            for (uint32_t j = 0; j < rows; j++)
                for (uint32_t i = 0; i < cols; i++) {
                    hpfc_tree_pixel px;
                    int st = hpfc_tree_get_pixel(t->w->tree, l, im, i, j, &px);
                    if (st)
                        return diag_set(diag, st, "geometry: no pixel (%u, %u)", i, j);
                    if (px.type == HPFC_PIXEL_WORD && (st = walk_leaf(t, &px, diag)))
                        return st;
                }
    }
    return HPFC_OK;
}

/* The columns measured (the tree's in a walk that also orients the edges),
 * their block sizes chosen, the section laid out. */
static int plan_columns(geom_writer *w, uint8_t *seen, hpfc_diag *diag)
{
    column_stats *cs = calloc(GEOM_COLUMNS, sizeof *cs);
    if (!cs)
        return diag_set(diag, HPFC_E_NOMEM, "geometry: out of memory");
    tree_walk t = {.w = w, .stats = cs + GEOM_LCROSS, .seen = seen, .orient = w->head + GEOM_META_SIZE};
    int st = walk_tree(&t, diag);
    const hpfc_graph *g = w->g;
    uint64_t points = g->npts;
    if (!st && !geom_column_counts(g->nv, g->ne, points, points ? t.leaves : 0,
                                   points ? t.crossings : 0, w->counts))
        st = diag_set(diag, HPFC_E_ARG, "geometry: the tree's crossings do not add up");
    uint32_t shift[GEOM_COLUMNS], ob[GEOM_COLUMNS], bb[GEOM_COLUMNS];
    uint64_t payload[GEOM_COLUMNS];
    for (int c = 0; c < GEOM_COLUMNS && !st; c++) {
        for (uint64_t i = 0; c < GEOM_LCROSS && i < w->counts[c]; i++)
            stats_push(&cs[c], graph_value(w, c, i));
        stats_end(&cs[c]);
        choose_shift(&cs[c], w->counts[c], &w->col[c]);
        shift[c] = w->col[c].shift, ob[c] = w->col[c].offset_bits, bb[c] = w->col[c].base_bits;
        payload[c] = w->col[c].payload_bits;
    }
    free(cs);
    if (!st && (!geom_compute_layout(w->counts, g->ne, shift, ob, bb, payload, &w->lay) ||
                w->lay.orient_at != GEOM_META_SIZE))
        st = diag_set(diag, HPFC_E_LIMIT, "geometry: the section would be too large");
    return st;
}

static void put_head(geom_writer *w)
{
    uint8_t *sec = w->head;
    geom_set_vertex_count(sec, w->g->nv);
    geom_set_edge_count(sec, w->g->ne);
    geom_set_point_count(sec, w->g->npts);
    geom_set_leaf_count(sec, w->counts[GEOM_LCROSS]);
    geom_set_crossing_count(sec, w->counts[GEOM_CSEG]);
    for (int c = 0; c < GEOM_COLUMNS; c++) {
        uint8_t *d = sec + GEOM_HEADER_SIZE + (size_t)c * GEOM_COLUMN_SIZE;
        geomc_set_block_shift(d, (uint8_t)w->col[c].shift);
        geomc_set_offset_bits(d, (uint8_t)w->col[c].offset_bits);
        geomc_set_base_bits(d, (uint8_t)w->col[c].base_bits);
        geomc_set_payload_bits(d, w->col[c].payload_bits);
    }
}

int geometry_plan(const hpfc_tree *tree, const hpfc_graph *graph, geom_writer **out,
                  uint64_t *length, hpfc_diag *diag)
{
    *out = NULL;
    *length = 0;
    geom_writer *w = calloc(1, sizeof *w);
    if (!w)
        return diag_set(diag, HPFC_E_NOMEM, "geometry: out of memory");
    w->g = graph;
    w->tree = tree;
    hpfc_tree_get_info(tree, &w->ti);
    int st = HPFC_OK;
    if (graph->nv != w->ti.vertices || graph->ne != w->ti.edges || graph->ne == 0)
        st = diag_set(diag, HPFC_E_ARG, "geometry: the graph is not the one the tree was built from");
    uint64_t edge_bytes = format_pool_bytes(graph->ne);
    uint8_t *seen = NULL;
    w->head_length = GEOM_META_SIZE + edge_bytes;
    if (!st && (edge_bytes > SIZE_MAX - GEOM_META_SIZE || !(w->head = calloc(1, (size_t)w->head_length)) ||
                !(seen = calloc(1, (size_t)edge_bytes))))
        st = diag_set(diag, HPFC_E_NOMEM, "geometry: out of memory");
    if (!st)
        st = check_graph_domain(w, diag);
    if (!st)
        st = plan_columns(w, seen, diag);
    free(seen);
    if (st) {
        geometry_writer_free(w);
        return st;
    }
    put_head(w);
    *out = w;
    *length = w->lay.length;
    return HPFC_OK;
}

/* ---- the emission ------------------------------------------------------------- */

static void column_free(column_out *o)
{
    if (o) {
        bitout_free(o->dir);
        bitout_free(o->payload);
        free(o);
    }
}

/* Column c's stream over its directory and payload regions. */
static column_out *column_open(const geom_writer *w, int c, stream_target to, uint64_t at)
{
    column_out *o = calloc(1, sizeof *o);
    if (!o)
        return NULL;
    o->cp = &w->col[c];
    o->dir = bitout_new(to, at + w->lay.dir_at[c], format_pool_bytes(w->lay.dir_bits[c]));
    o->payload = bitout_new(to, at + w->lay.payload_at[c], format_pool_bytes(w->col[c].payload_bits));
    if (!o->dir || !o->payload) {
        column_free(o);
        return NULL;
    }
    return o;
}

/* The column's last block out, its two regions' CRCs; false when they do
 * not come out at the sizes planned. Frees o. */
static bool column_close(column_out *o, uint32_t crc[2])
{
    if (o->fill)
        out_block(o);
    bool exact = o->at == o->cp->payload_bits;
    exact &= bitout_finish(o->dir, &crc[0]);
    exact &= bitout_finish(o->payload, &crc[1]);
    free(o);
    return exact;
}

/* The section's CRC from its regions' (in file order, zeros between). */
static int section_crc(const geom_writer *w, uint32_t region[GEOM_COLUMNS][2], uint32_t *crc)
{
    static const uint8_t zeros[8];
    uint32_t sum = crc32c_update(0, w->head, (size_t)w->head_length);
    uint64_t end = w->head_length;
    for (int c = 0; c < GEOM_COLUMNS; c++) {
        uint64_t at[2] = {w->lay.dir_at[c], w->lay.payload_at[c]};
        uint64_t bytes[2] = {format_pool_bytes(w->lay.dir_bits[c]),
                             format_pool_bytes(w->col[c].payload_bits)};
        for (int r = 0; r < 2; r++) {
            if (at[r] < end || at[r] - end > sizeof zeros)
                return HPFC_E_ARG;
            sum = crc32c_update(sum, zeros, (size_t)(at[r] - end));
            sum = crc32c_combine(sum, region[c][r], bytes[r]);
            end = at[r] + bytes[r];
        }
    }
    *crc = sum;
    return end == w->lay.length ? HPFC_OK : HPFC_E_ARG;
}

int geometry_emit(const geom_writer *w, stream_target to, uint64_t at, uint32_t *crc,
                  hpfc_diag *diag)
{
    uint32_t region[GEOM_COLUMNS][2];
    bool exact = true;
    to.put(to.ctx, at, w->head, w->head_length);
    for (int c = 0; c < GEOM_LCROSS; c++) {
        column_out *o = column_open(w, c, to, at);
        if (!o)
            return diag_set(diag, HPFC_E_NOMEM, "geometry: out of memory");
        for (uint64_t i = 0; i < w->counts[c]; i++)
            out_push(o, graph_value(w, c, i));
        exact &= column_close(o, region[c]);
    }
    tree_walk t = {.w = w};
    t.out[0] = column_open(w, GEOM_LCROSS, to, at);
    t.out[1] = column_open(w, GEOM_CSEG, to, at);
    if (!t.out[0] || !t.out[1]) {
        column_free(t.out[0]);
        column_free(t.out[1]);
        return diag_set(diag, HPFC_E_NOMEM, "geometry: out of memory");
    }
    /* without shape points the tree gives no value: its walk is the plan's */
    int st = w->g->npts ? walk_tree(&t, diag) : HPFC_OK;
    exact &= column_close(t.out[0], region[GEOM_LCROSS]);
    exact &= column_close(t.out[1], region[GEOM_CSEG]);
    if (st)
        return st;
    if (!exact || section_crc(w, region, crc))
        return diag_set(diag, HPFC_E_ARG, "geometry: the tree or the graph changed since the plan");
    return HPFC_OK;
}
