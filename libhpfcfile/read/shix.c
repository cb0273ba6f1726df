/*
 * The SHIX section (spec/hpfc-format.md §6.8): its layout, its checks at
 * open and at each row read, and the writer's build of it. See shix.h.
 */
#include <stdlib.h>
#include <string.h>

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

/* Side k (0 or 1) of edge e in LABL's sides. */
static uint64_t side_of(const labels_view *lv, uint64_t e, int k)
{
    return format_get(&lv->sides, (2 * e + (uint64_t)k) * lv->face_bits, lv->face_bits);
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
    uint64_t l = side_of(lv, v, 0), r = side_of(lv, v, 1);
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

/* The rows a table inverts: LABL's edges (`labels` set: an edge's two
 * faces when they differ, none when they are the same) or FEAT's or
 * EDGF's rows (start, item). */
typedef struct source_rows {
    const labels_view *labels;
    const uint32_t *start, *item;
    uint64_t rows;
} source_rows;

/* Row r's links as *links, their count returned; pair is room for an
 * edge's two faces (below the face count, which count_face_links
 * checked: they fit 32 bits). */
static uint32_t row_links(const source_rows *s, uint64_t r, uint32_t pair[2], const uint32_t **links)
{
    if (!s->labels) {
        *links = s->item + s->start[r];
        return s->start[r + 1] - s->start[r];
    }
    pair[0] = (uint32_t)side_of(s->labels, r, 0);
    pair[1] = (uint32_t)side_of(s->labels, r, 1);
    *links = pair;
    return pair[0] != pair[1] ? 2 : 0;
}

/* The face table's links: two for each edge between two faces.
 * HPFC_E_ARG for a side past the faces, HPFC_E_LIMIT past the u32
 * count. */
static int count_face_links(const labels_view *lv, uint64_t *links)
{
    uint64_t n = 0;
    for (uint64_t e = 0; e < lv->edges; e++) {
        uint64_t a = side_of(lv, e, 0), b = side_of(lv, e, 1);
        if (a >= lv->faces || b >= lv->faces)
            return HPFC_E_ARG;
        n += a != b ? 2 : 0;
    }
    *links = n;
    return n > SHIX_MOST_LINKS ? HPFC_E_LIMIT : HPFC_OK;
}

/* Table t (shaped, its `rows` the targets) filled in its own zeroed
 * bytes `b` with the inverse of the source's rows, by counting sort with
 * no memory beside the table: target x's count is kept in offset x + 2,
 * the counts become each row's start in offset x + 1, and placing a link
 * moves that start on to the row's end, which is the next row's start.
 * Each row's ids ascend, as the source rows are visited in order. */
static void invert_into(const shix_table *t, uint8_t *b, const source_rows *s)
{
    unsigned ob = t->offset_bits;
    uint64_t rows = t->rows;
    if (t->links == 0)
        return; /* every offset 0 */
    format_bits view = {b, t->bits.bits, format_pool_bytes(t->bits.bits)};
    for (uint64_t r = 0; r < s->rows; r++) {
        uint32_t pair[2];
        const uint32_t *links;
        for (uint32_t i = 0, n = row_links(s, r, pair, &links); i < n; i++)
            if ((uint64_t)links[i] + 2 <= rows) {
                uint64_t at = ((uint64_t)links[i] + 2) * ob;
                format_set(b, at, ob, format_get(&view, at, ob) + 1);
            }
    }
    uint64_t sum = 0;
    for (uint64_t k = 1; k <= rows; k++) {
        sum += format_get(&view, k * ob, ob);
        format_set(b, k * ob, ob, sum);
    }
    for (uint64_t r = 0; r < s->rows; r++) {
        uint32_t pair[2];
        const uint32_t *links;
        for (uint32_t i = 0, n = row_links(s, r, pair, &links); i < n; i++) {
            uint64_t at = ((uint64_t)links[i] + 1) * ob, pos = format_get(&view, at, ob);
            format_put(b, t->links_at + pos * t->id_bits, t->id_bits, r);
            format_set(b, at, ob, pos + 1);
        }
    }
}

bool shix_fits(uint64_t edges, const hpfc_feature_table *features,
               const hpfc_edge_feature_table *edges_table)
{
    return edges < UINT32_MAX / 2 && 2 * edges <= SHIX_MOST_LINKS &&
           (!features || features->face_start[features->face_count] <= SHIX_MOST_LINKS) &&
           (!edges_table || edges_table->edge_start[edges_table->edge_count] <= SHIX_MOST_LINKS);
}

int shix_measure(const labels_view *labels, const hpfc_feature_table *features,
                 const hpfc_edge_feature_table *edges, shix_plan *plan, hpfc_diag *diag)
{
    *plan = (shix_plan){0};
    if (labels->faces >= UINT32_MAX || labels->edges >= UINT32_MAX)
        return diag_set(diag, HPFC_E_LIMIT, "shape index: over 2^32 - 2 faces or edges");
    /* a LABL copied from a damaged file may claim counts its bytes do not
     * pay for: held to the bounds hpfc_shapes_create holds them to, before
     * anything is read */
    if (!labels_counts_paid(labels))
        return diag_set(diag, HPFC_E_ARG, "shape index: LABL's counts are not its bytes'");
    uint64_t face_links = 0, feature_faces = 0, feature_edges = 0;
    uint32_t tables = 0, nfeat = features ? features->feature_count : 0;
    int st = count_face_links(labels, &face_links);
    if (st == HPFC_E_ARG)
        return diag_set(diag, st, "shape index: LABL names a face past its count");
    if (!st && features && features->face_count == labels->faces) {
        tables |= SHIX_FEATURE_FACES;
        feature_faces = features->face_start[features->face_count];
    }
    if (!st && features && edges && edges->edge_count == labels->edges &&
        edges->feature_count == nfeat) {
        tables |= SHIX_FEATURE_EDGES;
        feature_edges = edges->edge_start[edges->edge_count];
    }
    if (st || feature_faces > SHIX_MOST_LINKS || feature_edges > SHIX_MOST_LINKS)
        return diag_set(diag, HPFC_E_LIMIT, "shape index: a table of 2^32 links or more");
    uint8_t *h = plan->header;
    shix_set_face_count(h, (uint32_t)labels->faces);
    shix_set_edge_count(h, (uint32_t)labels->edges);
    shix_set_feature_count(h, nfeat);
    shix_set_tables(h, tables);
    shix_set_face_links(h, (uint32_t)face_links);
    shix_set_feature_face_links(h, (uint32_t)feature_faces);
    shix_set_feature_edge_links(h, (uint32_t)feature_edges);
    shix_view v;
    plan->length = layout(h, &v);
    return HPFC_OK;
}

void shix_emit(const shix_plan *plan, const labels_view *labels,
               const hpfc_feature_table *features, const hpfc_edge_feature_table *edges,
               uint8_t *out)
{
    memcpy(out, plan->header, SHIX_HEADER_SIZE);
    shix_view v;
    layout(plan->header, &v);
    uint8_t *at = out + SHIX_HEADER_SIZE;
    invert_into(&v.face_edges, at, &(source_rows){.labels = labels, .rows = labels->edges});
    at += table_bytes(&v.face_edges);
    if (v.tables & SHIX_FEATURE_FACES) {
        invert_into(&v.feature_faces, at,
                    &(source_rows){.start = features->face_start, .item = features->face_feature,
                                   .rows = features->face_count});
        at += table_bytes(&v.feature_faces);
    }
    if (v.tables & SHIX_FEATURE_EDGES)
        invert_into(&v.feature_edges, at,
                    &(source_rows){.start = edges->edge_start, .item = edges->edge_feature,
                                   .rows = edges->edge_count});
}

int shix_build(const labels_view *labels, const hpfc_feature_table *features,
               const hpfc_edge_feature_table *edges, uint8_t **out, uint64_t *length,
               hpfc_diag *diag)
{
    *out = NULL;
    *length = 0;
    shix_plan plan;
    int st = shix_measure(labels, features, edges, &plan, diag);
    if (st)
        return st;
    uint8_t *s = calloc(1, (size_t)plan.length);
    if (!s)
        return diag_set(diag, HPFC_E_NOMEM, "out of memory");
    shix_emit(&plan, labels, features, edges, s);
    *out = s;
    *length = plan.length;
    return HPFC_OK;
}
