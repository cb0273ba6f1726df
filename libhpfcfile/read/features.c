/*
 * Source features: the FEAT section (spec/hpfc-format.md §6.2).
 *
 * Layout, after a 32-byte header: the layer table (8 bytes a layer), the
 * feature table (24 bytes a feature), the face index (face_count + 1
 * 32-bit offsets into the links), the links (32-bit feature indices) and
 * the strings (UTF-8, not NUL-terminated). Open checks only that these
 * parts add up to the section's length (O(1)); every access checks the
 * entries it reads, so a corrupt table gives HPFC_E_CORRUPT, never a read
 * outside the section.
 */
#include <stdlib.h>
#include <string.h>

#include "feat.h"
#include "feature_links.h"
#include "file.h"
#include "format.h"
#include "sized.h"

/* ---- layout ----------------------------------------------------------------- */

typedef struct feat_parts {
    uint64_t layers, features, face_index, links, strings, end;
} feat_parts;

/* Offsets of the parts for the given counts (all below 2^32: no overflow
 * in 64 bits). */
static feat_parts feat_layout(uint64_t layers, uint64_t features, uint64_t faces, uint64_t links,
                              uint64_t string_bytes)
{
    feat_parts p;
    p.layers = FEAT_HEADER_SIZE;
    p.features = p.layers + FEAT_LAYER_SIZE * layers;
    p.face_index = p.features + FEAT_FEATURE_SIZE * features;
    p.links = p.face_index + 4 * (faces + 1);
    p.strings = p.links + 4 * links;
    p.end = p.strings + string_bytes;
    return p;
}

/* ---- writer ------------------------------------------------------------------- */

static uint64_t key_bytes(const hpfc_feature_table *t, uint32_t k)
{
    return t->key && t->key[k] ? strlen(t->key[k]) : 0;
}

int feat_section_length(const hpfc_feature_table *t, uint64_t *length, hpfc_diag *diag)
{
    if ((t->feature_count && (!t->fid || !t->layer)) || (t->layer_count && !t->layer_name) ||
        !t->face_start || (t->key && !t->key_field))
        return diag_set(diag, HPFC_E_ARG, "feature table: a NULL array");
    if (t->face_count == UINT32_MAX || t->face_start[0] != 0)
        return diag_set(diag, HPFC_E_ARG, "feature table: bad face count or first offset");
    uint64_t strings = t->key_field ? strlen(t->key_field) : 0;
    for (uint32_t l = 0; l < t->layer_count; l++)
        strings += t->layer_name[l] ? strlen(t->layer_name[l]) : 0;
    for (uint32_t k = 0; k < t->feature_count; k++) {
        if (t->layer[k] >= t->layer_count)
            return diag_set(diag, HPFC_E_ARG, "feature table: feature %u names layer %u of %u", k,
                            t->layer[k], t->layer_count);
        strings += key_bytes(t, k);
    }
    bool decreases = false;
    uint32_t f = feature_links_first_bad(t->face_start, t->face_feature, t->face_count,
                                         t->feature_count, &decreases);
    if (f < t->face_count && decreases)
        return diag_set(diag, HPFC_E_ARG, "feature table: face offsets decrease at face %u", f);
    if (f < t->face_count)
        return diag_set(diag, HPFC_E_ARG,
                        "feature table: face %u's features not ascending feature indices", f);
    if (strings >= FEAT_NONE)
        return diag_set(diag, HPFC_E_LIMIT, "feature table: over 4 GiB of names and keys");
    *length = feat_layout(t->layer_count, t->feature_count, t->face_count, t->face_start[t->face_count],
                          strings)
                  .end;
    return HPFC_OK;
}

/* Appends s (NULL: nothing) to the strings; its offset and length, or
 * (0, FEAT_NONE) for NULL. */
static void put_string(uint8_t *strings, uint32_t *used, const char *s, uint32_t *off, uint32_t *len)
{
    if (!s) {
        *off = 0;
        *len = FEAT_NONE;
        return;
    }
    size_t n = strlen(s);
    memcpy(strings + *used, s, n);
    *off = *used;
    *len = (uint32_t)n;
    *used += (uint32_t)n;
}

void feat_section_emit(const hpfc_feature_table *t, uint8_t *out)
{
    uint32_t links = t->face_start[t->face_count];
    feat_parts p = feat_layout(t->layer_count, t->feature_count, t->face_count, links, 0);
    uint8_t *strings = out + p.strings;
    uint32_t used = 0, off, len;
    memset(out, 0, FEAT_HEADER_SIZE);
    feat_set_feature_count(out, t->feature_count);
    feat_set_face_count(out, t->face_count);
    feat_set_link_count(out, links);
    feat_set_layer_count(out, t->layer_count);
    put_string(strings, &used, t->key_field, &off, &len);
    feat_set_key_field_offset(out, off);
    feat_set_key_field_length(out, len);
    for (uint32_t l = 0; l < t->layer_count; l++) {
        uint8_t *e = out + p.layers + (size_t)l * FEAT_LAYER_SIZE;
        put_string(strings, &used, t->layer_name[l] ? t->layer_name[l] : "", &off, &len);
        featl_set_name_offset(e, off);
        featl_set_name_length(e, len);
    }
    for (uint32_t k = 0; k < t->feature_count; k++) {
        uint8_t *e = out + p.features + (size_t)k * FEAT_FEATURE_SIZE;
        featf_set_fid(e, t->fid[k]);
        featf_set_layer(e, t->layer[k]);
        put_string(strings, &used, t->key ? t->key[k] : NULL, &off, &len);
        featf_set_key_offset(e, off);
        featf_set_key_length(e, len);
        featf_set_reserved(e, 0);
    }
    feature_links_emit(out + p.face_index, t->face_start, t->face_feature, t->face_count);
    feat_set_string_bytes(out, used);
}

/* ---- reader -------------------------------------------------------------------- */

static feat_parts section_parts(const uint8_t *s)
{
    return feat_layout(feat_get_layer_count(s), feat_get_feature_count(s), feat_get_face_count(s),
                       feat_get_link_count(s), feat_get_string_bytes(s));
}

/* Does the string (off, len) lie in the strings part? FEAT_NONE is "no
 * value" and always fine. */
static bool string_fits(const uint8_t *s, uint32_t off, uint32_t len)
{
    return len == FEAT_NONE || (uint64_t)off + len <= feat_get_string_bytes(s);
}

int feat_section_check(const uint8_t *s, uint64_t length)
{
    if (length < FEAT_HEADER_SIZE || feat_get_reserved(s) != 0 || feat_get_face_count(s) == UINT32_MAX)
        return HPFC_E_SECTION;
    if (section_parts(s).end != length)
        return HPFC_E_SECTION;
    if (!string_fits(s, feat_get_key_field_offset(s), feat_get_key_field_length(s)))
        return HPFC_E_SECTION;
    return HPFC_OK;
}

/* FEAT for an accessor: HPFC_E_ARG without a file or without the
 * accessor's outputs (out_ok false), HPFC_E_NO_SECTION when the file has
 * none. The same checks as attrs.c's for ATTR and EDGF: each file reads its own
 * sections' pointers in hpfc_file. */
static int section_of(const hpfc_file *file, bool out_ok, const uint8_t **s)
{
    if (!file || !out_ok)
        return HPFC_E_ARG;
    *s = file->feat;
    return *s ? HPFC_OK : HPFC_E_NO_SECTION;
}

static const char *string_at(const uint8_t *s, uint32_t off)
{
    return (const char *)(s + section_parts(s).strings + off);
}

int hpfc_file_get_features_sized(const hpfc_file *file, hpfc_features_info *out, size_t size)
{
    const uint8_t *s;
    int st = section_of(file, out != NULL, &s);
    if (st)
        return st;
    hpfc_features_info full = {.features = feat_get_feature_count(s),
                               .faces = feat_get_face_count(s),
                               .layers = feat_get_layer_count(s),
                               .links = feat_get_link_count(s)};
    uint32_t len = feat_get_key_field_length(s);
    if (len != FEAT_NONE) {
        full.key_field = string_at(s, feat_get_key_field_offset(s));
        full.key_field_len = len;
    }
    sized_out(out, size, &full, sizeof full);
    return HPFC_OK;
}

/* Entry `index` of the layer table (layers true) or of the feature table,
 * for an accessor: HPFC_E_ARG past the table's end, else as section_of. */
static int table_entry(const hpfc_file *file, bool out_ok, bool layers, uint64_t index,
                       const uint8_t **s, const uint8_t **entry)
{
    int st = section_of(file, out_ok, s);
    if (st)
        return st;
    feat_parts p = section_parts(*s);
    if (index >= (layers ? feat_get_layer_count(*s) : feat_get_feature_count(*s)))
        return HPFC_E_ARG;
    *entry = *s + (layers ? p.layers + (size_t)index * FEAT_LAYER_SIZE
                          : p.features + (size_t)index * FEAT_FEATURE_SIZE);
    return HPFC_OK;
}

int hpfc_file_get_feature_sized(const hpfc_file *file, hpfc_id feature, hpfc_feature *out,
                                size_t size)
{
    const uint8_t *s, *e;
    int st = table_entry(file, out != NULL, false, feature, &s, &e);
    if (st)
        return st;
    uint32_t off = featf_get_key_offset(e), len = featf_get_key_length(e);
    if (featf_get_layer(e) >= feat_get_layer_count(s) || featf_get_reserved(e) != 0 ||
        !string_fits(s, off, len))
        return HPFC_E_CORRUPT;
    hpfc_feature full;
    memset(&full, 0, sizeof full); /* padding too: a caller may compare bytes */
    full.fid = featf_get_fid(e);
    full.layer = featf_get_layer(e);
    if (len != FEAT_NONE) {
        full.key = string_at(s, off);
        full.key_len = len;
    }
    sized_out(out, size, &full, sizeof full);
    return HPFC_OK;
}

int hpfc_layer_name(const hpfc_file *file, uint32_t layer, const char **name, size_t *len)
{
    const uint8_t *s, *e;
    int st = table_entry(file, name && len, true, layer, &s, &e);
    if (st)
        return st;
    uint32_t off = featl_get_name_offset(e), n = featl_get_name_length(e);
    if (n == FEAT_NONE || !string_fits(s, off, n))
        return HPFC_E_CORRUPT;
    *name = string_at(s, off);
    *len = n;
    return HPFC_OK;
}

int features_layers(const hpfc_file *file, uint32_t first, uint32_t count, uint32_t *layer)
{
    const uint8_t *s;
    int st = section_of(file, layer != NULL || count == 0, &s);
    if (st)
        return st;
    if ((uint64_t)first + count > feat_get_feature_count(s))
        return HPFC_E_ARG;
    const uint8_t *e = s + section_parts(s).features + (size_t)first * FEAT_FEATURE_SIZE;
    uint32_t layers = feat_get_layer_count(s);
    for (uint32_t k = 0; k < count; k++, e += FEAT_FEATURE_SIZE) {
        layer[k] = featf_get_layer(e);
        if (layer[k] >= layers)
            return HPFC_E_CORRUPT;
    }
    return HPFC_OK;
}

/* FEAT's face index and links, for an accessor: as section_of answers.
 * feature_links.h reads them for faces here and for edges in attrs.c;
 * what stays twice (this, attrs.c's attrs_edge_links and their two accessors)
 * is each section's own part: finding its links in its own layout. */
int features_face_links(const hpfc_file *file, bool out_ok, feature_links *links)
{
    const uint8_t *s;
    int st = section_of(file, out_ok, &s);
    if (!st)
        *links = (feature_links){.index = s + section_parts(s).face_index,
                                 .rows = feat_get_face_count(s),
                                 .links = feat_get_link_count(s),
                                 .features = feat_get_feature_count(s)};
    return st;
}

int hpfc_face_feature_count(const hpfc_file *file, hpfc_id face, uint32_t *count)
{
    feature_links links;
    int st = features_face_links(file, count != NULL, &links);
    return st ? st : feature_links_count(&links, face, count);
}

int hpfc_face_feature_id(const hpfc_file *file, hpfc_id face, uint32_t k, hpfc_id *feature)
{
    feature_links links;
    int st = features_face_links(file, feature != NULL, &links);
    return st ? st : feature_links_get(&links, face, k, feature);
}
