/*
 * The GEOM section on the read side (spec/hpfc-format.md §6.6): the header
 * and layout checked at open in O(1), then every value read in O(1) from
 * its column and checked against what it must name (a coordinate inside
 * the domain, a vertex id below V, a point range inside P, a segment of
 * its own edge), so that a damaged section gives HPFC_E_CORRUPT, never a
 * read outside the section or a point outside the map.
 */
#include <stdlib.h>
#include <string.h>

#include "file.h"
#include "geometry.h"
#include "diag.h"
#include "labels.h"
#include "sized.h"

/* ---- layout --------------------------------------------------------------------- */

bool geom_column_counts(uint64_t vertices, uint64_t edges, uint64_t points, uint64_t leaves,
                        uint64_t crossings, uint64_t counts[GEOM_COLUMNS])
{
    bool shaped = points > 0;
    counts[GEOM_VX] = counts[GEOM_VY] = vertices;
    counts[GEOM_EU] = counts[GEOM_EV] = edges;
    counts[GEOM_EPOINT] = shaped ? edges : 0;
    counts[GEOM_PX] = counts[GEOM_PY] = points;
    counts[GEOM_LCROSS] = shaped ? leaves : 0;
    counts[GEOM_CSEG] = shaped ? crossings : 0;
    /* without shape points nothing is stored per leaf or crossing */
    return shaped || (leaves == 0 && crossings == 0);
}

static uint64_t block_count(uint64_t n, uint32_t shift)
{
    return (n >> shift) + ((n & ((UINT64_C(1) << shift) - 1)) != 0);
}

bool geom_compute_layout(const uint64_t counts[GEOM_COLUMNS], uint64_t edges,
                         const uint32_t shift[GEOM_COLUMNS], const uint32_t offset_bits[GEOM_COLUMNS],
                         const uint32_t base_bits[GEOM_COLUMNS],
                         const uint64_t payload_bits[GEOM_COLUMNS], geom_layout *out)
{
    memset(out, 0, sizeof *out);
    out->orient_at = GEOM_META_SIZE;
    uint64_t end = out->orient_at + format_pool_bytes(edges);
    if (edges > UINT64_MAX - 8)
        return false;
    for (int c = 0; c < GEOM_COLUMNS; c++) {
        if (shift[c] > GEOM_MAX_SHIFT || offset_bits[c] > 64 || base_bits[c] > 64)
            return false;
        uint64_t entry = offset_bits[c] + base_bits[c] + GEOM_WIDTH_BITS;
        if (end > UINT64_MAX - 8 ||
            !format_mul(block_count(counts[c], shift[c]), entry, &out->dir_bits[c]))
            return false;
        out->dir_at[c] = format_align8(end);
        if (!format_add(out->dir_at[c], format_pool_bytes(out->dir_bits[c]), &end) ||
            end > UINT64_MAX - 8)
            return false;
        out->payload_at[c] = format_align8(end);
        if (!format_add(out->payload_at[c], format_pool_bytes(payload_bits[c]), &end))
            return false;
    }
    out->length = end;
    return true;
}

static format_bits stream(const uint8_t *sec, uint64_t length, uint64_t at, uint64_t bits)
{
    return (format_bits){.base = sec + at, .bits = bits, .avail = length - at};
}

int geometry_open(geom_view *v, const uint8_t *sec, uint64_t length, const geom_levels *lv)
{
    memset(v, 0, sizeof *v);
    if (length < GEOM_META_SIZE || geom_get_reserved(sec))
        return HPFC_E_SECTION;
    v->vertices = geom_get_vertex_count(sec);
    v->edges = geom_get_edge_count(sec);
    v->points = geom_get_point_count(sec);
    v->leaves = geom_get_leaf_count(sec);
    v->crossings = geom_get_crossing_count(sec);
    if (!labels_first_leaves(lv->levels, lv->word_pixels, v->first_leaf))
        return HPFC_E_SECTION;
    uint64_t counts[GEOM_COLUMNS], leaves = v->first_leaf[lv->levels];
    if (v->vertices == 0 || v->edges == 0 || (v->points && v->leaves != leaves) ||
        !geom_column_counts(v->vertices, v->edges, v->points, v->leaves, v->crossings, counts) ||
        (lv->has_labels && lv->label_edges != v->edges))
        return HPFC_E_SECTION;
    /* No two points of a valid map coincide, so two of them never share a
     * block of width 0 in both columns: each costs a bit at least (§6.6.2).
     * This bounds every loop over the points by the section's size. */
    uint64_t most = length > (UINT64_MAX - 1) / 8 ? UINT64_MAX : 8 * length + 1;
    if (v->vertices > most || v->points > most || v->vertices > UINT32_MAX)
        return HPFC_E_SECTION;
    uint32_t shift[GEOM_COLUMNS], ob[GEOM_COLUMNS], bb[GEOM_COLUMNS];
    uint64_t payload[GEOM_COLUMNS];
    for (int c = 0; c < GEOM_COLUMNS; c++) {
        const uint8_t *d = sec + GEOM_HEADER_SIZE + (size_t)c * GEOM_COLUMN_SIZE;
        if (!format_all_zero(d + geomc_OFF_reserved, geomc_SIZE_reserved))
            return HPFC_E_SECTION;
        shift[c] = geomc_get_block_shift(d);
        ob[c] = geomc_get_offset_bits(d);
        bb[c] = geomc_get_base_bits(d);
        payload[c] = geomc_get_payload_bits(d);
    }
    geom_layout lay;
    if (!geom_compute_layout(counts, v->edges, shift, ob, bb, payload, &lay) || lay.length != length)
        return HPFC_E_SECTION;
    v->orient = stream(sec, length, lay.orient_at, v->edges);
    for (int c = 0; c < GEOM_COLUMNS; c++) {
        geom_column *col = &v->col[c];
        col->count = counts[c];
        col->shift = shift[c];
        col->offset_bits = ob[c];
        col->base_bits = bb[c];
        col->entry_bits = ob[c] + bb[c] + GEOM_WIDTH_BITS;
        col->dir = stream(sec, length, lay.dir_at[c], lay.dir_bits[c]);
        col->payload = stream(sec, length, lay.payload_at[c], payload[c]);
    }
    v->width = (uint64_t)lv->width;
    v->height = (uint64_t)lv->height;
    v->layout = lay;
    v->section = sec;
    v->section_length = length;
    v->present = true;
    return HPFC_OK;
}

/* The stream of `bits` bits at byte `at` ends with zero bits, and the
 * bytes from its end to `next` are zero. */
static bool tail_zero(const uint8_t *sec, uint64_t at, uint64_t bits, uint64_t next, uint64_t *bad)
{
    uint64_t end = at + bits / 8;
    if (bits % 8 && (sec[end] & (0xFF >> (bits % 8)))) {
        *bad = end;
        return false;
    }
    for (uint64_t k = at + format_pool_bytes(bits); k < next; k++)
        if (sec[k]) {
            *bad = k;
            return false;
        }
    return true;
}

bool geom_padding_zero(const geom_view *v, uint64_t *at)
{
    const geom_layout *l = &v->layout;
    if (!tail_zero(v->section, l->orient_at, v->edges, l->dir_at[0], at))
        return false;
    for (int c = 0; c < GEOM_COLUMNS; c++) {
        uint64_t next = c + 1 < GEOM_COLUMNS ? l->dir_at[c + 1] : v->section_length;
        if (!tail_zero(v->section, l->dir_at[c], l->dir_bits[c], l->payload_at[c], at) ||
            !tail_zero(v->section, l->payload_at[c], v->col[c].payload.bits, next, at))
            return false;
    }
    return true;
}

/* The directory entry of a column's block: where its values start in the
 * payload, their base and their width. */
typedef struct column_block {
    uint64_t off, base;
    uint32_t width;
} column_block;

static column_block block_entry(const geom_column *c, uint64_t block)
{
    uint64_t at = block * c->entry_bits; /* < dir bits: checked at open */
    column_block b;
    if (c->entry_bits <= 57) {
        /* the usual case: the block's entry in one read, then split */
        uint64_t e = format_get(&c->dir, at, c->entry_bits);
        b.width = (uint32_t)(e & ((1u << GEOM_WIDTH_BITS) - 1));
        e >>= GEOM_WIDTH_BITS;
        b.base = e & ((UINT64_C(1) << c->base_bits) - 1); /* base_bits <= 50 here */
        b.off = e >> c->base_bits;
    } else {
        b.off = format_get(&c->dir, at, c->offset_bits);
        b.base = format_get(&c->dir, at + c->offset_bits, c->base_bits);
        b.width = (uint32_t)format_get(&c->dir, at + c->offset_bits + c->base_bits,
                                       GEOM_WIDTH_BITS);
    }
    return b;
}

/* Values q .. q + n - 1 of block b into out[0], out[stride], ...:
 * HPFC_E_CORRUPT when the last lies outside the payload or a value
 * overflows. */
static int block_values(const geom_column *c, const column_block *b, uint64_t q, uint64_t n,
                        uint64_t *out, size_t stride)
{
    uint64_t pos, end;
    if (b->width > 64 || !format_mul(q + n, b->width, &end) || !format_add(b->off, end, &end) ||
        end > c->payload.bits)
        return HPFC_E_CORRUPT;
    pos = b->off + q * b->width;
    uint64_t most = b->width == 64 ? UINT64_MAX : (UINT64_C(1) << b->width) - 1;
    if (b->width && b->width <= 57 && b->base <= UINT64_MAX - most) {
        /* the usual block: no value can overflow, each one read */
        const format_bits *pl = &c->payload;
        if (n && ((pos + (n - 1) * b->width) >> 3) + 8 <= pl->avail) {
            /* and every value's 8-byte window inside the payload: read
             * straight (a shape's points are runs like this) */
            unsigned w = b->width;
            for (uint64_t k = 0; k < n; k++, pos += w)
                out[k * stride] = b->base + ((format_be64(pl->base + (pos >> 3)) << (pos & 7)) >>
                                             (64 - w));
            return HPFC_OK;
        }
        for (uint64_t k = 0; k < n; k++, pos += b->width)
            out[k * stride] =
                b->base + (format_peek(&c->payload, pos, b->width) >> (64 - b->width));
        return HPFC_OK;
    }
    for (uint64_t k = 0; k < n; k++, pos += b->width) {
        uint64_t delta = format_get(&c->payload, pos, b->width);
        if (delta > UINT64_MAX - b->base)
            return HPFC_E_CORRUPT;
        out[k * stride] = b->base + delta;
    }
    return HPFC_OK;
}

int geom_column_get(const geom_column *c, uint64_t i, uint64_t *value)
{
    if (i >= c->count)
        return HPFC_E_CORRUPT;
    column_block b = block_entry(c, i >> c->shift);
    return block_values(c, &b, i & ((UINT64_C(1) << c->shift) - 1), 1, value, 1);
}

/* Where geom_coordinate_run's values go: each below `limit`, plus
 * `origin` (block_coordinates). */
typedef struct coordinate_to {
    uint64_t limit;
    int64_t origin;
} coordinate_to;

static int block_coordinates(const geom_column *c, const column_block *b, uint64_t q,
                             uint64_t n, uint64_t limit, int64_t origin, int64_t *out);

/* Values i .. i + n - 1 of column c a block at a time: as they are into
 * out[0], out[stride], ..., or, with `to`, as coordinates (stride 2). */
static int column_run(const geom_column *c, uint64_t i, uint64_t n, const coordinate_to *to,
                      uint64_t *out, size_t stride)
{
    if (i > c->count || n > c->count - i)
        return HPFC_E_CORRUPT;
    uint64_t size = UINT64_C(1) << c->shift;
    int st = HPFC_OK;
    while (n && !st) {
        uint64_t q = i & (size - 1), take = size - q < n ? size - q : n;
        column_block b = block_entry(c, i >> c->shift);
        st = to ? block_coordinates(c, &b, q, take, to->limit, to->origin, (int64_t *)out)
                : block_values(c, &b, q, take, out, stride);
        i += take, n -= take, out += take * stride;
    }
    return st;
}

int geom_column_run(const geom_column *c, uint64_t i, uint64_t n, uint64_t *out, size_t stride)
{
    return column_run(c, i, n, NULL, out, stride);
}

/* ---- accessors ---------------------------------------------------------------- */

/* GEOM for an accessor: HPFC_E_ARG without a file or without the
 * accessor's arguments (args_ok false), then HPFC_E_NO_SECTION without
 * GEOM. */
static int geometry_of(const hpfc_file *file, bool args_ok, const geom_view **v)
{
    if (!file || !args_ok)
        return HPFC_E_ARG;
    *v = &file->geom;
    return (*v)->present ? HPFC_OK : HPFC_E_NO_SECTION;
}

int hpfc_file_get_geometry_sized(const hpfc_file *file, hpfc_geometry_info *out, size_t size)
{
    const geom_view *v;
    int st = geometry_of(file, out != NULL, &v);
    if (st)
        return st;
    const hpfc_geometry_info full = {.vertices = v->vertices,
                                     .edges = v->edges,
                                     .points = v->points,
                                     .section_bytes = v->section_length};
    sized_out(out, size, &full, sizeof full);
    return HPFC_OK;
}

/* An absolute coordinate from a column: inside the domain, else corrupt. */
static int point_at(const hpfc_file *file, const geom_view *v, int cx, uint64_t i, int64_t *x,
                    int64_t *y)
{
    uint64_t dx, dy;
    int st = geom_column_get(&v->col[cx], i, &dx);
    if (!st)
        st = geom_column_get(&v->col[cx + 1], i, &dy);
    if (!st && (dx >= v->width || dy >= v->height))
        st = HPFC_E_CORRUPT;
    if (st)
        return st;
    *x = file->info.x0 + (int64_t)dx;
    *y = file->info.y0 + (int64_t)dy;
    return HPFC_OK;
}

int hpfc_geometry_vertex(const hpfc_file *file, uint64_t vertex, int64_t *x, int64_t *y)
{
    const geom_view *v;
    int st = geometry_of(file, x && y, &v);
    if (st)
        return st;
    if (vertex >= v->vertices)
        return HPFC_E_ARG;
    return point_at(file, v, GEOM_VX, vertex, x, y);
}

/* ---- bounds ------------------------------------------------------------------- */

/* (geom_column_span) A block's values lie in [base, base + 2^width - 1],
 * so a block is read only when that range could still move the answer. The
 * block with the lowest floor is read first (and the one with the highest
 * ceiling), which for a writer whose bases are the blocks' minima settles
 * the minimum at once. */
typedef struct column_span {
    const geom_column *c;
    uint64_t blocks, size;
    uint64_t *scratch;
} column_span;

static uint64_t block_ceiling(const column_block *b)
{
    if (b->width >= 64)
        return UINT64_MAX;
    uint64_t most = (UINT64_C(1) << b->width) - 1;
    return b->base > UINT64_MAX - most ? UINT64_MAX : b->base + most;
}

/* Reads block k's values and widens [*lo, *hi] by them. */
static int span_read_block(const column_span *s, uint64_t k, uint64_t *lo, uint64_t *hi)
{
    uint64_t first = k * s->size, n = s->c->count - first < s->size ? s->c->count - first : s->size;
    int st = geom_column_run(s->c, first, n, s->scratch, 1);
    for (uint64_t i = 0; i < n && !st; i++) {
        *lo = s->scratch[i] < *lo ? s->scratch[i] : *lo;
        *hi = s->scratch[i] > *hi ? s->scratch[i] : *hi;
    }
    return st;
}

int geom_column_span(const geom_column *c, uint64_t *lo, uint64_t *hi)
{
    *lo = UINT64_MAX, *hi = 0;
    if (c->count == 0)
        return HPFC_OK;
    column_span s = {.c = c, .size = UINT64_C(1) << c->shift}; /* shift checked at open */
    s.blocks = (c->count - 1) / s.size + 1;
    uint64_t most = s.size < c->count ? s.size : c->count; /* values a block read gives */
    if (most > SIZE_MAX / sizeof *s.scratch ||
        !(s.scratch = malloc((size_t)most * sizeof *s.scratch)))
        return HPFC_E_NOMEM;
    /* the lowest floor and the highest ceiling: read those blocks first */
    uint64_t k_lo = 0, k_hi = 0, floor_min = UINT64_MAX, ceil_max = 0;
    for (uint64_t k = 0; k < s.blocks; k++) {
        column_block b = block_entry(c, k);
        uint64_t ceil = block_ceiling(&b);
        if (b.base < floor_min)
            floor_min = b.base, k_lo = k;
        if (ceil > ceil_max || k == 0)
            ceil_max = ceil, k_hi = k;
    }
    int st = span_read_block(&s, k_lo, lo, hi);
    if (!st && k_hi != k_lo)
        st = span_read_block(&s, k_hi, lo, hi);
    /* then any block that could still hold a smaller or a larger value */
    for (uint64_t k = 0; k < s.blocks && !st; k++) {
        column_block b = block_entry(c, k);
        if (k != k_lo && k != k_hi && (b.base < *lo || block_ceiling(&b) > *hi))
            st = span_read_block(&s, k, lo, hi);
    }
    free(s.scratch);
    return st;
}

int hpfc_geometry_bounds(const hpfc_file *file, int64_t box[4])
{
    const geom_view *v;
    int st = geometry_of(file, box != NULL, &v);
    if (st)
        return st;
    uint64_t lo[4], hi[4]; /* VX, VY, PX, PY */
    static const int column[4] = {GEOM_VX, GEOM_VY, GEOM_PX, GEOM_PY};
    for (int k = 0; k < 4 && !st; k++)
        st = geom_column_span(&v->col[column[k]], &lo[k], &hi[k]);
    if (st)
        return st;
    if (v->vertices == 0 || lo[0] > hi[0] || lo[1] > hi[1])
        return HPFC_E_CORRUPT; /* a map has vertices (the builder refuses an edgeless graph) */
    uint64_t x0 = lo[0], y0 = lo[1], x1 = hi[0], y1 = hi[1];
    if (lo[2] <= hi[2]) {
        x0 = lo[2] < x0 ? lo[2] : x0, x1 = hi[2] > x1 ? hi[2] : x1;
        y0 = lo[3] < y0 ? lo[3] : y0, y1 = hi[3] > y1 ? hi[3] : y1;
    }
    if (x1 >= v->width || y1 >= v->height)
        return HPFC_E_CORRUPT; /* as every point read: inside the domain */
    box[0] = file->info.x0 + (int64_t)x0, box[1] = file->info.y0 + (int64_t)y0;
    box[2] = file->info.x0 + (int64_t)x1, box[3] = file->info.y0 + (int64_t)y1;
    return HPFC_OK;
}

/* Checks an edge's record read from the columns, its shape points ending
 * where the next edge's (`next`) start, and sets r->n. */
static int edge_check(const geom_view *v, geom_edge *r, uint64_t next)
{
    if (r->u >= v->vertices || r->v >= v->vertices || r->first > next || next > v->points)
        return HPFC_E_CORRUPT;
    r->n = next - r->first;
    /* a loop needs two shape points (spec §3.9 rule 1) */
    return r->u == r->v && r->n < 2 ? HPFC_E_CORRUPT : HPFC_OK;
}

static int edge_record(const geom_view *v, uint64_t e, geom_edge *r)
{
    uint64_t next = v->points;
    r->first = r->n = 0;
    int st = geom_column_get(&v->col[GEOM_EU], e, &r->u);
    if (!st)
        st = geom_column_get(&v->col[GEOM_EV], e, &r->v);
    if (!st && v->points)
        st = geom_column_get(&v->col[GEOM_EPOINT], e, &r->first);
    if (!st && v->points && e + 1 < v->edges)
        st = geom_column_get(&v->col[GEOM_EPOINT], e + 1, &next);
    return st ? st : edge_check(v, r, next);
}

int geom_edges(const hpfc_file *file, uint64_t first, uint64_t n, geom_edge *out)
{
    const geom_view *v = &file->geom;
    if (first > v->edges || n > v->edges - first)
        return HPFC_E_ARG;
    const size_t stride = sizeof *out / sizeof(uint64_t);
    uint64_t next = v->points;
    int st = geom_column_run(&v->col[GEOM_EU], first, n, &out->u, stride);
    if (!st)
        st = geom_column_run(&v->col[GEOM_EV], first, n, &out->v, stride);
    for (uint64_t k = 0; k < n && !v->points; k++)
        out[k].first = 0;
    if (!st && v->points)
        st = geom_column_run(&v->col[GEOM_EPOINT], first, n, &out->first, stride);
    if (!st && v->points && first + n < v->edges)
        st = geom_column_get(&v->col[GEOM_EPOINT], first + n, &next);
    for (uint64_t k = 0; k < n && !st; k++)
        st = edge_check(v, &out[k], k + 1 < n ? out[k + 1].first : next);
    return st;
}

/* Edge `edge`'s record for an accessor: as geometry_of answers, then
 * HPFC_E_ARG past the edges, then as edge_record. */
static int edge_of(const hpfc_file *file, bool args_ok, uint64_t edge, const geom_view **g,
                   geom_edge *r)
{
    int st = geometry_of(file, args_ok, g);
    if (st)
        return st;
    if (edge >= (*g)->edges)
        return HPFC_E_ARG;
    return edge_record(*g, edge, r);
}

int hpfc_geometry_edge(const hpfc_file *file, uint64_t edge, uint64_t *u, uint64_t *v,
                       uint64_t *point_count)
{
    const geom_view *g;
    geom_edge r;
    int st = edge_of(file, u && v && point_count, edge, &g, &r);
    if (st)
        return st;
    *u = r.u;
    *v = r.v;
    *point_count = r.n + 2;
    return HPFC_OK;
}

int hpfc_geometry_edge_point(const hpfc_file *file, uint64_t edge, uint64_t k, int64_t *x,
                             int64_t *y)
{
    const geom_view *g;
    geom_edge r;
    int st = edge_of(file, x && y, edge, &g, &r);
    if (st)
        return st;
    if (k > r.n + 1)
        return HPFC_E_ARG;
    if (k == 0)
        return point_at(file, g, GEOM_VX, r.u, x, y);
    if (k == r.n + 1)
        return point_at(file, g, GEOM_VX, r.v, x, y);
    return point_at(file, g, GEOM_PX, r.first + k - 1, x, y);
}

/* Values q .. q + n - 1 of block b as coordinates: each below `limit`,
 * plus `origin`, into out[0], out[2], ... A block none of whose values can
 * reach the limit (base + 2^width - 1 below it: a writer's usual block,
 * its base the block's least value) gets base and origin added in the
 * unpacking loop, one pass and no test a value; any other is unpacked,
 * then tested value by value. HPFC_E_CORRUPT as block_values, or for a
 * value past the limit. */
static int block_coordinates(const geom_column *c, const column_block *b, uint64_t q,
                             uint64_t n, uint64_t limit, int64_t origin, int64_t *out)
{
    const format_bits *pl = &c->payload;
    unsigned w = b->width;
    uint64_t pos, end;
    if (w > 64 || !format_mul(q + n, w, &end) || !format_add(b->off, end, &end) ||
        end > pl->bits)
        return HPFC_E_CORRUPT;
    pos = b->off + q * w;
    if (n && w && w <= 57 && b->base < limit && (UINT64_C(1) << w) - 1 < limit - b->base &&
        ((pos + (n - 1) * w) >> 3) + 8 <= pl->avail) {
        /* origin + base + value lies in the domain, which the header's
         * checks keep within int64_t: the sum taken modulo 2^64 is it */
        uint64_t add = b->base + (uint64_t)origin;
        for (uint64_t k = 0; k < n; k++, pos += w)
            out[2 * k] = format_as_int64(
                add + ((format_be64(pl->base + (pos >> 3)) << (pos & 7)) >> (64 - w)));
        return HPFC_OK;
    }
    uint64_t *v = (uint64_t *)out;
    int st = block_values(c, b, q, n, v, 2);
    for (uint64_t k = 0; k < n && !st; k++) {
        if (v[2 * k] >= limit)
            return HPFC_E_CORRUPT;
        out[2 * k] = origin + (int64_t)v[2 * k];
    }
    return st;
}

int geom_coordinate_run(const geom_column *c, uint64_t i, uint64_t n, uint64_t limit,
                        int64_t origin, int64_t *out)
{
    const coordinate_to to = {limit, origin};
    return column_run(c, i, n, &to, (uint64_t *)out, 2);
}

int geom_points(const hpfc_file *file, int column, uint64_t first, uint64_t n, int64_t *xy)
{
    const geom_view *g = &file->geom;
    int st = geom_coordinate_run(&g->col[column], first, n, g->width, file->info.x0, xy);
    if (!st)
        st = geom_coordinate_run(&g->col[column + 1], first, n, g->height, file->info.y0, xy + 1);
    return st;
}

int geom_edge_points(const hpfc_file *file, uint64_t edge, int64_t *xy)
{
    const geom_view *g;
    geom_edge r;
    int st = edge_of(file, xy != NULL, edge, &g, &r);
    if (!st)
        st = point_at(file, g, GEOM_VX, r.u, &xy[0], &xy[1]);
    if (!st)
        st = point_at(file, g, GEOM_VX, r.v, &xy[2 * r.n + 2], &xy[2 * r.n + 3]);
    return st ? st : geom_points(file, GEOM_PX, r.first, r.n, xy + 2);
}

int hpfc_geometry_edge_faces(const hpfc_file *file, uint64_t edge, uint64_t *left,
                             uint64_t *right)
{
    const geom_view *g;
    int st = geometry_of(file, left && right, &g);
    if (st)
        return st;
    const labels_view *lv = &file->labels;
    if (!lv->present)
        return HPFC_E_NO_SECTION;
    if (edge >= g->edges)
        return HPFC_E_ARG;
    /* LABL's edge count equals GEOM's (checked at open) */
    uint32_t r = (uint32_t)format_get(&g->orient, edge, 1);
    uint64_t fr = format_get(&lv->sides, (2 * edge + r) * lv->face_bits, lv->face_bits);
    uint64_t fl = format_get(&lv->sides, (2 * edge + !r) * lv->face_bits, lv->face_bits);
    if (fr >= lv->faces || fl >= lv->faces)
        return HPFC_E_CORRUPT;
    *left = fl;
    *right = fr;
    return HPFC_OK;
}

/* The crossings of a word pixel: its word's symbols but the four '+'. */
static int leaf_crossings(const hpfc_file *file, const hpfc_pixel *leaf, uint64_t *n)
{
    size_t len = 0;
    int st = hpfc_pixel_word(file, leaf, NULL, 0, &len);
    if (st)
        return st;
    if (len < 4)
        return HPFC_E_CORRUPT;
    *n = len - 4;
    return HPFC_OK;
}

int geom_leaf_segments(const hpfc_file *file, const hpfc_pixel *leaf, uint32_t n,
                       uint64_t *segment)
{
    const geom_view *g;
    int st = geometry_of(file, leaf && segment, &g);
    if (st)
        return st;
    if (!g->points) { /* every edge is one segment */
        memset(segment, 0, (size_t)n * sizeof *segment);
        return HPFC_OK;
    }
    uint64_t rank, start, end = g->crossings;
    if ((st = labels_leaf_rank(file, leaf, &rank)))
        return st;
    uint64_t gl = g->first_leaf[leaf->depth] + rank;
    st = geom_column_get(&g->col[GEOM_LCROSS], gl, &start);
    if (!st && gl + 1 < g->leaves)
        st = geom_column_get(&g->col[GEOM_LCROSS], gl + 1, &end);
    if (!st && (start > end || end > g->crossings || end - start != n))
        st = HPFC_E_CORRUPT;
    if (!st && n)
        st = geom_column_run(&g->col[GEOM_CSEG], start, n, segment, 1);
    return st;
}

int hpfc_geometry_crossing_segment(const hpfc_file *file, const hpfc_pixel *leaf,
                                   uint32_t crossing, uint64_t *segment)
{
    const geom_view *g;
    int st = geometry_of(file, leaf && segment, &g);
    if (st)
        return st;
    uint64_t rank, n;
    st = labels_leaf_rank(file, leaf, &rank);
    if (!st)
        st = leaf_crossings(file, leaf, &n);
    if (st)
        return st;
    if (crossing >= n)
        return HPFC_E_ARG;
    if (!g->points) { /* every edge is one segment */
        *segment = 0;
        return HPFC_OK;
    }
    uint64_t gl = g->first_leaf[leaf->depth] + rank, start, end = g->crossings, seg;
    st = geom_column_get(&g->col[GEOM_LCROSS], gl, &start);
    if (!st && gl + 1 < g->leaves)
        st = geom_column_get(&g->col[GEOM_LCROSS], gl + 1, &end);
    /* the leaf's crossings are exactly its word's */
    if (!st && (start > end || end > g->crossings || end - start != n))
        st = HPFC_E_CORRUPT;
    if (!st)
        st = geom_column_get(&g->col[GEOM_CSEG], start + crossing, &seg);
    if (st)
        return st;
    /* a segment of the crossing's own edge, when LABL names it */
    uint64_t edge;
    if (file->labels.present) {
        geom_edge r;
        st = hpfc_label_crossing_edge(file, leaf, crossing, &edge);
        if (!st && edge >= g->edges)
            st = HPFC_E_CORRUPT;
        if (!st)
            st = edge_record(g, edge, &r);
        if (!st && seg > r.n)
            st = HPFC_E_CORRUPT;
        if (st)
            return st;
    }
    *segment = seg;
    return HPFC_OK;
}
