/*
 * The SHIX section (spec/hpfc-format.md §6.8): its layout, its checks at
 * open and at each row read, and the writer's build of it. See shix.h.
 */
#include <stdlib.h>
#include <string.h>

#include "inverse.h"
#include "shix.h"

/* Bits to write x: 0 for 0. */
static unsigned bit_length(uint64_t x)
{
    return x ? 64 - (unsigned)__builtin_clzll(x) : 0;
}

/* A table's widths and size from its counts (§6.8.1): offsets of
 * bit_length(links) bits, ids of bit_length(bound - 1), the table padded
 * to a multiple of 8 bytes. */
static void table_shape(shix_table *t, uint32_t rows, uint32_t links, uint32_t bound)
{
    t->rows = rows, t->links = links, t->bound = bound;
    t->offset_bits = bit_length(links);
    t->id_bits = bit_length(bound ? bound - 1 : 0);
    t->links_at = ((uint64_t)rows + 1) * t->offset_bits;
    t->bits.bits = t->links_at + (uint64_t)links * t->id_bits;
}

static uint64_t table_bytes(const shix_table *t)
{
    return (t->bits.bits + 63) / 64 * 8;
}

/* The section's three tables from its header into v (not placed); returns
 * the section's exact length (below 2^41: every count is a u32). */
static uint64_t layout(const uint8_t *s, shix_view *v)
{
    uint32_t faces = shix_get_face_count(s), edges = shix_get_edge_count(s);
    uint32_t features = shix_get_feature_count(s), tables = shix_get_tables(s);
    *v = (shix_view){.faces = faces, .edges = edges, .features = features, .tables = tables};
    table_shape(&v->face_edges, faces, shix_get_face_links(s), edges);
    uint64_t end = SHIX_HEADER_SIZE + table_bytes(&v->face_edges);
    if (tables & SHIX_FEATURE_FACES) {
        table_shape(&v->feature_faces, features, shix_get_feature_face_links(s), faces);
        end += table_bytes(&v->feature_faces);
    }
    if (tables & SHIX_FEATURE_EDGES) {
        table_shape(&v->feature_edges, features, shix_get_feature_edge_links(s), edges);
        end += table_bytes(&v->feature_edges);
    }
    return end;
}

/* Places table t at *at in a section ending at `end`; *at moves past it. */
static void place(shix_table *t, const uint8_t **at, const uint8_t *end)
{
    t->bits.base = *at;
    t->bits.avail = (uint64_t)(end - *at);
    *at += table_bytes(t);
}

int shix_open(shix_view *v, const uint8_t *s, uint64_t length)
{
    *v = (shix_view){0};
    if (length < SHIX_HEADER_SIZE)
        return HPFC_E_SECTION;
    uint32_t tables = shix_get_tables(s);
    if (shix_get_reserved(s) != 0 || tables & ~(uint32_t)(SHIX_FEATURE_FACES | SHIX_FEATURE_EDGES) ||
        shix_get_face_count(s) == UINT32_MAX || shix_get_edge_count(s) == UINT32_MAX ||
        shix_get_feature_count(s) == UINT32_MAX ||
        (!(tables & SHIX_FEATURE_FACES) && shix_get_feature_face_links(s)) ||
        (!(tables & SHIX_FEATURE_EDGES) && shix_get_feature_edge_links(s)))
        return HPFC_E_SECTION;
    shix_view w;
    if (layout(s, &w) != length)
        return HPFC_E_SECTION;
    const uint8_t *at = s + SHIX_HEADER_SIZE, *end = s + length;
    place(&w.face_edges, &at, end);
    if (tables & SHIX_FEATURE_FACES)
        place(&w.feature_faces, &at, end);
    if (tables & SHIX_FEATURE_EDGES)
        place(&w.feature_edges, &at, end);
    w.present = true;
    *v = w;
    return HPFC_OK;
}

/* Link i of FEAT's or EDGF's links. */
static uint32_t link_at(const feature_links *t, uint64_t i)
{
    return (uint32_t)le_load(t->index + 4 * ((size_t)t->rows + 1 + (size_t)i), 4);
}

/* Whether row `row` of FEAT's or EDGF's links holds `feature`. */
static bool links_hold(const feature_links *t, uint64_t row, uint32_t feature)
{
    uint32_t first, end;
    if (feature_links_row(t, row, &first, &end))
        return false;
    for (uint32_t i = first; i < end; i++)
        if (link_at(t, i) == feature)
            return true;
    return false;
}

/* Whether id v of row `row` is the inverse of a link of `of`. */
static bool is_inverse(const shix_inverse *of, uint64_t row, uint32_t v)
{
    if (of->links)
        return links_hold(of->links, v, (uint32_t)row);
    /* LABL's two sides of edge v: which is which does not matter here */
    const labels_view *lv = of->labels;
    if (v >= lv->edges)
        return false;
    uint64_t l = format_get(&lv->sides, 2 * (uint64_t)v * lv->face_bits, lv->face_bits);
    uint64_t r = format_get(&lv->sides, (2 * (uint64_t)v + 1) * lv->face_bits, lv->face_bits);
    return l != r && (l == row || r == row);
}

int shix_row(const shix_table *t, uint64_t row, const shix_inverse *of, uint64_t *a,
             uint64_t *b)
{
    uint64_t first = shix_offset(t, row), end = shix_offset(t, row + 1);
    if (first > end || end > t->links)
        return HPFC_E_CORRUPT;
    uint32_t prev = 0;
    for (uint64_t i = first; i < end; i++) {
        uint32_t v = shix_id(t, i);
        if (v >= t->bound || (i > first && v <= prev) || !is_inverse(of, row, v))
            return HPFC_E_CORRUPT;
        prev = v;
    }
    *a = first, *b = end;
    return HPFC_OK;
}

/* ---- the writer's build ------------------------------------------------------------ */

/* The writer's tables hold fewer than 2^32 links: the header's u32 fields
 * say how many. */
#define SHIX_MOST_LINKS (UINT32_MAX - 1)

/* The rows of (start, item), `rows` of them, inverted: for each of
 * `targets` targets, the rows that link it, ascending (rows are visited
 * in order). The links were checked below `targets` by the writer's
 * check of FEAT and EDGF. */
static int invert(uint32_t rows, const uint32_t *start, const uint32_t *item, uint32_t targets,
                  inverse_table *out)
{
    int st = inverse_begin(out, targets);
    if (st)
        return st;
    for (uint32_t i = 0; i < start[rows]; i++)
        inverse_count(out, item[i]);
    if ((st = inverse_room(out, SHIX_MOST_LINKS)))
        return st;
    for (uint32_t r = 0; r < rows; r++)
        for (uint32_t i = start[r]; i < start[r + 1]; i++)
            inverse_put(out, item[i], r);
    inverse_done(out);
    return HPFC_OK;
}

/* Each face's edges from LABL's sides: an edge with two different faces
 * is in both faces' rows, one with the same face on both sides in none
 * (it bounds nothing). HPFC_E_ARG for a side past the faces. */
static int face_edges(const labels_view *lv, inverse_table *out)
{
    uint64_t faces = lv->faces;
    unsigned fb = lv->face_bits;
    int st = inverse_begin(out, faces);
    for (int pass = 0; pass < 2 && !st; pass++) {
        for (uint64_t e = 0; e < lv->edges; e++) {
            uint64_t a = format_get(&lv->sides, 2 * e * fb, fb);
            uint64_t b = format_get(&lv->sides, (2 * e + 1) * fb, fb);
            if (a >= faces || b >= faces)
                return HPFC_E_ARG;
            if (a == b)
                continue;
            if (pass == 0) {
                inverse_count(out, a);
                inverse_count(out, b);
            } else {
                inverse_put(out, a, (uint32_t)e);
                inverse_put(out, b, (uint32_t)e);
            }
        }
        if (pass == 0)
            st = inverse_room(out, SHIX_MOST_LINKS);
    }
    inverse_done(out);
    return st;
}

/* A built table's bits at *at (zeroed), its ids below `bound`; *at moves
 * past it. */
static void put_table(uint8_t **at, const inverse_table *b, uint32_t bound)
{
    shix_table t;
    table_shape(&t, (uint32_t)b->rows, (uint32_t)b->start[b->rows], bound);
    for (uint64_t r = 0; r <= b->rows; r++)
        format_put(*at, r * t.offset_bits, t.offset_bits, b->start[r]);
    for (uint64_t i = 0; i < t.links; i++)
        format_put(*at, t.links_at + i * t.id_bits, t.id_bits, b->item[i]);
    *at += table_bytes(&t);
}

int shix_build(const labels_view *labels, const hpfc_feature_table *features,
               const hpfc_edge_feature_table *edges, uint8_t **out, uint64_t *length,
               hpfc_diag *diag)
{
    *out = NULL;
    *length = 0;
    if (labels->faces >= UINT32_MAX || labels->edges >= UINT32_MAX)
        return diag_set(diag, HPFC_E_LIMIT, "shape index: over 2^32 - 2 faces or edges");
    /* a LABL copied from a damaged file may claim counts its bytes do not
     * pay for: held to the bounds hpfc_shapes_create holds them to, before
     * anything is allocated */
    if (!labels_counts_paid(labels))
        return diag_set(diag, HPFC_E_ARG, "shape index: LABL's counts are not its bytes'");
    inverse_table fe = {0}, ff = {0}, fx = {0};
    uint32_t tables = 0, nfeat = features ? features->feature_count : 0;
    uint32_t nedges = (uint32_t)labels->edges;
    int st = face_edges(labels, &fe);
    if (!st && features && features->face_count == labels->faces) {
        tables |= SHIX_FEATURE_FACES;
        st = invert(features->face_count, features->face_start, features->face_feature, nfeat, &ff);
    }
    if (!st && features && edges && edges->edge_count == labels->edges &&
        edges->feature_count == nfeat) {
        tables |= SHIX_FEATURE_EDGES;
        st = invert(edges->edge_count, edges->edge_start, edges->edge_feature, nfeat, &fx);
    }
    uint8_t header[SHIX_HEADER_SIZE] = {0}, *s = NULL;
    uint64_t n = 0;
    if (!st) {
        shix_set_face_count(header, (uint32_t)fe.rows);
        shix_set_edge_count(header, nedges);
        shix_set_feature_count(header, nfeat);
        shix_set_tables(header, tables);
        shix_set_face_links(header, (uint32_t)fe.start[fe.rows]);
        shix_set_feature_face_links(header, ff.start ? (uint32_t)ff.start[nfeat] : 0);
        shix_set_feature_edge_links(header, fx.start ? (uint32_t)fx.start[nfeat] : 0);
        shix_view v;
        n = layout(header, &v);
        if (!(s = calloc(1, (size_t)n)))
            st = HPFC_E_NOMEM;
    }
    if (!st) {
        memcpy(s, header, sizeof header);
        uint8_t *at = s + SHIX_HEADER_SIZE;
        put_table(&at, &fe, nedges);
        if (ff.start)
            put_table(&at, &ff, (uint32_t)fe.rows);
        if (fx.start)
            put_table(&at, &fx, nedges);
        *out = s;
        *length = n;
    }
    inverse_free(&fe);
    inverse_free(&ff);
    inverse_free(&fx);
    if (st == HPFC_E_LIMIT)
        return diag_set(diag, st, "shape index: a table of 2^32 links or more");
    if (st == HPFC_E_ARG)
        return diag_set(diag, st, "shape index: LABL names a face past its count");
    return st ? diag_set(diag, st, "out of memory") : HPFC_OK;
}
