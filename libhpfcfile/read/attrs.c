/*
 * Attributes and the features of edges: the ATTR and EDGF sections
 * (spec/hpfc-format.md §6.3, §6.4).
 *
 * ATTR, after a 32-byte header: the column table (16 bytes a column), the
 * cells (8 bytes each, feature-major: feature k's value of column c is cell
 * k * column_count + c), one null bit per cell (padded with zero bits to a
 * multiple of 8 bytes) and the strings (UTF-8, not NUL-terminated). EDGF,
 * after a 16-byte header: edge_count + 1 offsets into the links, then the
 * links (feature indices), 4 bytes each. Open checks only that the parts
 * add up to each section's length (O(1)); every access checks what it
 * reads, so a corrupt section gives HPFC_E_CORRUPT, never a read outside
 * it.
 */
#include <string.h>

#include "attrs.h"
#include "feature_links.h"
#include "file.h"
#include "format.h"
#include "sized.h"

/* Cells at most 2^37: the cells then take at most 2^40 bytes, below the
 * format's file size limit, and no size below overflows 64 bits. */
#define ATTR_MAX_CELLS ((uint64_t)1 << 37)

/* ---- ATTR layout ------------------------------------------------------------- */

typedef struct attr_parts {
    uint64_t columns, cells, nulls, strings, end;
} attr_parts;

static attr_parts attr_layout(uint64_t features, uint64_t columns, uint64_t string_bytes)
{
    uint64_t n = features * columns; /* the caller checked n <= ATTR_MAX_CELLS */
    attr_parts p;
    p.columns = ATTR_HEADER_SIZE;
    p.cells = p.columns + ATTR_COLUMN_SIZE * columns;
    p.nulls = p.cells + ATTR_CELL_SIZE * n;
    p.strings = p.nulls + format_align8((n + 7) / 8);
    p.end = p.strings + string_bytes;
    return p;
}

static bool attr_sizes_ok(uint64_t features, uint64_t columns, uint64_t string_bytes)
{
    return features * columns <= ATTR_MAX_CELLS && string_bytes <= FORMAT_MAX_FILE_SIZE;
}

/* ---- ATTR writer ----------------------------------------------------------------- */

static bool type_valid(int type)
{
    return type == HPFC_ATTR_INTEGER || type == HPFC_ATTR_REAL || type == HPFC_ATTR_STRING;
}

int attr_section_length(const hpfc_attr_table *t, uint64_t *length, hpfc_diag *diag)
{
    if (t->column_count && (!t->name || !t->type))
        return diag_set(diag, HPFC_E_ARG, "attribute table: a NULL array");
    if ((uint64_t)t->feature_count * t->column_count > ATTR_MAX_CELLS)
        return diag_set(diag, HPFC_E_LIMIT, "attribute table: over 2^37 values");
    if (t->feature_count && t->column_count && !t->cells)
        return diag_set(diag, HPFC_E_ARG, "attribute table: no cells");
    uint64_t strings = 0;
    for (uint32_t c = 0; c < t->column_count; c++) {
        if (!type_valid(t->type[c]))
            return diag_set(diag, HPFC_E_ARG, "attribute table: column %u has type %d", c,
                            t->type[c]);
        strings += t->name[c] ? strlen(t->name[c]) : 0;
    }
    uint64_t n = (uint64_t)t->feature_count * t->column_count;
    for (uint64_t k = 0; k < n; k++) {
        const hpfc_attr_value *v = &t->cells[k];
        if (v->type != HPFC_ATTR_NULL && v->type != t->type[k % t->column_count])
            return diag_set(diag, HPFC_E_ARG,
                            "attribute table: feature %llu column %llu: type %d, not the column's",
                            (unsigned long long)(k / t->column_count),
                            (unsigned long long)(k % t->column_count), v->type);
        if (v->type == HPFC_ATTR_STRING) {
            if (!v->s && v->len)
                return diag_set(diag, HPFC_E_ARG, "attribute table: a NULL string");
            strings += v->len;
        }
    }
    if (strings >= UINT32_MAX)
        return diag_set(diag, HPFC_E_LIMIT, "attribute table: over 4 GiB of strings");
    *length = attr_layout(t->feature_count, t->column_count, strings).end;
    return HPFC_OK;
}

void attr_section_emit(const hpfc_attr_table *t, uint8_t *out)
{
    attr_parts p = attr_layout(t->feature_count, t->column_count, 0);
    uint8_t *strings = out + p.strings;
    uint64_t used = 0;
    memset(out, 0, ATTR_HEADER_SIZE);
    attr_set_feature_count(out, t->feature_count);
    attr_set_column_count(out, t->column_count);
    for (uint32_t c = 0; c < t->column_count; c++) {
        uint8_t *e = out + p.columns + (size_t)c * ATTR_COLUMN_SIZE;
        size_t len = t->name[c] ? strlen(t->name[c]) : 0;
        memset(e, 0, ATTR_COLUMN_SIZE);
        memcpy(strings + used, t->name[c] ? t->name[c] : "", len);
        attrc_set_name_offset(e, (uint32_t)used);
        attrc_set_name_length(e, (uint32_t)len);
        attrc_set_type(e, t->type[c]);
        used += len;
    }
    uint64_t n = (uint64_t)t->feature_count * t->column_count;
    memset(out + p.nulls, 0, (size_t)(p.strings - p.nulls));
    for (uint64_t k = 0; k < n; k++) {
        const hpfc_attr_value *v = &t->cells[k];
        uint8_t *cell = out + p.cells + (size_t)k * ATTR_CELL_SIZE;
        uint64_t bits = 0;
        switch (v->type) {
        case HPFC_ATTR_INTEGER:
            le_store(cell, 8, (uint64_t)v->i);
            break;
        case HPFC_ATTR_REAL:
            memcpy(&bits, &v->r, sizeof bits);
            le_store(cell, 8, bits);
            break;
        case HPFC_ATTR_STRING:
            if (v->len)
                memcpy(strings + used, v->s, v->len);
            attrs_set_offset(cell, (uint32_t)used);
            attrs_set_length(cell, (uint32_t)v->len);
            used += v->len;
            break;
        default:
            le_store(cell, 8, 0);
            out[p.nulls + k / 8] |= (uint8_t)(1u << (k % 8));
        }
    }
    attr_set_string_bytes(out, used);
}

/* ---- ATTR reader ------------------------------------------------------------------ */

static attr_parts attr_parts_of(const uint8_t *s)
{
    return attr_layout(attr_get_feature_count(s), attr_get_column_count(s),
                       attr_get_string_bytes(s));
}

int attr_section_check(const uint8_t *s, uint64_t length)
{
    if (length < ATTR_HEADER_SIZE || !format_all_zero(s + attr_OFF_reserved, attr_SIZE_reserved))
        return HPFC_E_SECTION;
    if (!attr_sizes_ok(attr_get_feature_count(s), attr_get_column_count(s),
                       attr_get_string_bytes(s)))
        return HPFC_E_SECTION;
    return attr_parts_of(s).end == length ? HPFC_OK : HPFC_E_SECTION;
}

/* The two sections this file reads. */
typedef enum attrs_section { SECTION_ATTR, SECTION_EDGF } attrs_section;

/* ATTR or EDGF for an accessor: HPFC_E_ARG without a file or without the
 * accessor's outputs (out_ok false), HPFC_E_NO_SECTION when the file has
 * none. The same checks as features.c's for FEAT: each file reads its own
 * sections' pointers in hpfc_file. */
static int section_of(const hpfc_file *file, attrs_section which, bool out_ok, const uint8_t **s)
{
    if (!file || !out_ok)
        return HPFC_E_ARG;
    *s = which == SECTION_ATTR ? file->attr : file->edgf;
    return *s ? HPFC_OK : HPFC_E_NO_SECTION;
}

/* Does (off, len) lie in the strings? */
static bool attr_string_fits(const uint8_t *s, uint64_t off, uint64_t len)
{
    return off + len <= attr_get_string_bytes(s);
}

int hpfc_file_get_attrs_sized(const hpfc_file *file, hpfc_attrs_info *out, size_t size)
{
    const uint8_t *s;
    int st = section_of(file, SECTION_ATTR, out != NULL, &s);
    if (st)
        return st;
    const hpfc_attrs_info full = {.features = attr_get_feature_count(s),
                                  .columns = attr_get_column_count(s),
                                  .string_bytes = attr_get_string_bytes(s),
                                  .section_bytes = attr_parts_of(s).end};
    sized_out(out, size, &full, sizeof full);
    return HPFC_OK;
}

/* Column c's entry, checked: a known type, zero reserved bytes, a name in
 * the strings. */
static int column_entry(const uint8_t *s, uint32_t c, const uint8_t **entry)
{
    if (c >= attr_get_column_count(s))
        return HPFC_E_ARG;
    const uint8_t *e = s + attr_parts_of(s).columns + (size_t)c * ATTR_COLUMN_SIZE;
    if (!type_valid(attrc_get_type(e)) ||
        !format_all_zero(e + attrc_OFF_reserved, attrc_SIZE_reserved) ||
        !attr_string_fits(s, attrc_get_name_offset(e), attrc_get_name_length(e)))
        return HPFC_E_CORRUPT;
    *entry = e;
    return HPFC_OK;
}

int hpfc_attr_column(const hpfc_file *file, uint32_t column, const char **name,
                     size_t *name_len, int *type)
{
    const uint8_t *s, *e;
    int st = section_of(file, SECTION_ATTR, name && name_len && type, &s);
    if (!st)
        st = column_entry(s, column, &e);
    if (st)
        return st;
    *name = (const char *)(s + attr_parts_of(s).strings + attrc_get_name_offset(e));
    *name_len = attrc_get_name_length(e);
    *type = attrc_get_type(e);
    return HPFC_OK;
}

int hpfc_attr_find(const hpfc_file *file, const char *name, size_t len, uint32_t *column)
{
    const uint8_t *s;
    int st = section_of(file, SECTION_ATTR, name && column, &s);
    if (st)
        return st;
    for (uint32_t c = 0; c < attr_get_column_count(s); c++) {
        const char *n;
        size_t nl;
        int type;
        if ((st = hpfc_attr_column(file, c, &n, &nl, &type)))
            return st;
        if (nl == len && memcmp(n, name, len) == 0) {
            *column = c;
            return HPFC_OK;
        }
    }
    return HPFC_E_ARG;
}

int hpfc_file_get_attr_value(const hpfc_file *file, hpfc_id feature, uint32_t column,
                             hpfc_attr_value *out)
{
    const uint8_t *s, *e;
    int st = section_of(file, SECTION_ATTR, out != NULL, &s);
    if (!st)
        st = column_entry(s, column, &e);
    if (st)
        return st;
    if (feature >= attr_get_feature_count(s))
        return HPFC_E_ARG;
    attr_parts p = attr_parts_of(s);
    uint64_t k = feature * attr_get_column_count(s) + column;
    const uint8_t *cell = s + p.cells + k * ATTR_CELL_SIZE;
    memset(out, 0, sizeof *out);
    if (s[p.nulls + k / 8] >> (k % 8) & 1)
        return HPFC_OK; /* HPFC_ATTR_NULL */
    out->type = attrc_get_type(e);
    uint64_t bits = le_load(cell, 8);
    switch (out->type) {
    case HPFC_ATTR_INTEGER:
        out->i = (int64_t)bits;
        break;
    case HPFC_ATTR_REAL:
        memcpy(&out->r, &bits, sizeof out->r);
        break;
    default: {
        uint32_t off = attrs_get_offset(cell), len = attrs_get_length(cell);
        if (!attr_string_fits(s, off, len)) {
            memset(out, 0, sizeof *out);
            return HPFC_E_CORRUPT;
        }
        out->s = (const char *)(s + p.strings + off);
        out->len = len;
    }
    }
    return HPFC_OK;
}

/* ---- EDGF ----------------------------------------------------------------------------- */

static uint64_t edgf_layout_end(uint64_t edges, uint64_t links)
{
    return EDGF_HEADER_SIZE + 4 * (edges + 1) + 4 * links;
}

int edgf_section_length(const hpfc_edge_feature_table *t, uint64_t *length, hpfc_diag *diag)
{
    if (!t->edge_start || (t->edge_start[t->edge_count] && !t->edge_feature))
        return diag_set(diag, HPFC_E_ARG, "edge feature table: a NULL array");
    if (t->edge_count == UINT32_MAX || t->edge_start[0] != 0)
        return diag_set(diag, HPFC_E_ARG, "edge feature table: bad edge count or first offset");
    bool decreases = false;
    uint32_t e = feature_links_first_bad(t->edge_start, t->edge_feature, t->edge_count,
                                         t->feature_count, &decreases);
    if (e < t->edge_count && decreases)
        return diag_set(diag, HPFC_E_ARG, "edge feature table: offsets decrease at edge %u", e);
    if (e < t->edge_count)
        return diag_set(diag, HPFC_E_ARG,
                        "edge feature table: edge %u's features not ascending indices", e);
    *length = edgf_layout_end(t->edge_count, t->edge_start[t->edge_count]);
    return HPFC_OK;
}

void edgf_section_emit(const hpfc_edge_feature_table *t, uint8_t *out)
{
    uint32_t links = t->edge_start[t->edge_count];
    memset(out, 0, EDGF_HEADER_SIZE);
    edgf_set_edge_count(out, t->edge_count);
    edgf_set_link_count(out, links);
    edgf_set_feature_count(out, t->feature_count);
    feature_links_emit(out + EDGF_HEADER_SIZE, t->edge_start, t->edge_feature, t->edge_count);
}

int edgf_section_check(const uint8_t *s, uint64_t length)
{
    if (length < EDGF_HEADER_SIZE || edgf_get_reserved(s) != 0 ||
        edgf_get_edge_count(s) == UINT32_MAX)
        return HPFC_E_SECTION;
    return edgf_layout_end(edgf_get_edge_count(s), edgf_get_link_count(s)) == length
               ? HPFC_OK
               : HPFC_E_SECTION;
}

int hpfc_file_get_edge_links_sized(const hpfc_file *file, hpfc_edge_links_info *out,
                                   size_t size)
{
    const uint8_t *s;
    int st = section_of(file, SECTION_EDGF, out != NULL, &s);
    if (st)
        return st;
    const hpfc_edge_links_info full = {
        .edges = edgf_get_edge_count(s),
        .features = edgf_get_feature_count(s),
        .links = edgf_get_link_count(s),
        .section_bytes = edgf_layout_end(edgf_get_edge_count(s), edgf_get_link_count(s))};
    sized_out(out, size, &full, sizeof full);
    return HPFC_OK;
}

/* EDGF's edge index and links, for an accessor: as section_of answers.
 * feature_links.h reads them for edges here and for faces in features.c;
 * what stays twice (this, features.c's features_face_links and their two
 * accessors) is each section's own part: finding its links in its own
 * layout. */
int attrs_edge_links(const hpfc_file *file, bool out_ok, feature_links *links)
{
    const uint8_t *s;
    int st = section_of(file, SECTION_EDGF, out_ok, &s);
    if (!st)
        *links = (feature_links){.index = s + EDGF_HEADER_SIZE,
                                 .rows = edgf_get_edge_count(s),
                                 .links = edgf_get_link_count(s),
                                 .features = edgf_get_feature_count(s)};
    return st;
}

int hpfc_edge_feature_count(const hpfc_file *file, hpfc_id edge, uint32_t *count)
{
    feature_links links;
    int st = attrs_edge_links(file, count != NULL, &links);
    return st ? st : feature_links_count(&links, edge, count);
}

int hpfc_edge_feature_id(const hpfc_file *file, hpfc_id edge, uint32_t k, hpfc_id *feature)
{
    feature_links links;
    int st = attrs_edge_links(file, feature != NULL, &links);
    return st ? st : feature_links_get(&links, edge, k, feature);
}
