/*
 * A feature's attributes and an edge's features as JSON (attrs_json.h).
 */
#include "attrs_json.h"

#include <stdlib.h>
#include <string.h>

void json_feature_attributes(jsonw *w, const hpfc_file *f, hpfc_id feature)
{
    hpfc_attrs_info ai;
    if (hpfc_file_get_attrs(f, &ai) != HPFC_OK || feature >= ai.features)
        return;
    jsonw_object_begin(w, "attributes");
    char *key = NULL;
    for (uint32_t c = 0; c < ai.columns; c++) {
        const char *name;
        size_t len;
        int type;
        hpfc_attr_value v;
        if (hpfc_attr_column(f, c, &name, &len, &type) != HPFC_OK ||
            hpfc_file_get_attr_value(f, feature, c, &v) != HPFC_OK) {
            jsonw_string(w, "error", "corrupt");
            break;
        }
        char *k = realloc(key, len + 1);
        if (!k)
            break;
        key = k;
        memcpy(key, name, len);
        key[len] = 0;
        if (v.type == HPFC_ATTR_INTEGER)
            jsonw_i64(w, key, v.i);
        else if (v.type == HPFC_ATTR_REAL)
            jsonw_real(w, key, v.r);
        else if (v.type == HPFC_ATTR_STRING)
            jsonw_string_n(w, key, v.s, v.len);
        else
            jsonw_null(w, key);
    }
    free(key);
    jsonw_object_end(w);
}

void json_edge_features(jsonw *w, const hpfc_file *f, hpfc_id edge)
{
    uint32_t n;
    if (hpfc_edge_feature_count(f, edge, &n) != HPFC_OK)
        return;
    jsonw_array_begin(w, "edge_features");
    for (uint32_t k = 0; k < n; k++) {
        hpfc_id feature;
        if (hpfc_edge_feature_id(f, edge, k, &feature) == HPFC_OK)
            jsonw_u64(w, NULL, feature);
    }
    jsonw_array_end(w);
}
