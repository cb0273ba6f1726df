/*
 * The ATTR and EDGF sections (spec/hpfc-format.md §6.3, §6.4): written
 * with a small map, read back value by value against the tables that were
 * written (the oracle), refused by the writer when inconsistent, and
 * damaged byte by byte: every byte of both sections set to 0x00, 0xFF and
 * each of its bits flipped, every accessor called on every column, feature
 * and edge of the damaged copy. Each copy lives in a buffer of exactly its
 * size, so AddressSanitizer sees any read outside it; every status must be
 * a named one, and a value read must lie inside the file.
 */
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "hpfc.h"

enum { FEATURES = 5, COLUMNS = 4 };

typedef struct fixture {
    const char *names[COLUMNS];
    uint8_t types[COLUMNS];
    hpfc_attr_value cells[FEATURES * COLUMNS];
    int64_t fid[FEATURES];
    uint32_t layer[FEATURES];
    const char *layer_name[1];
    uint32_t *face_start, *face_feature;
    uint32_t edge_start[8], edge_feature[16];
    hpfc_feature_table ft;
    hpfc_attr_table at;
    hpfc_edge_feature_table et;
} fixture;

static const char *const words[FEATURES] = {"Travis", "", "Bexar \xc3\xa9t\xc3\xa9", "x", "Harris"};

static void fixture_make(fixture *x, uint32_t faces, uint32_t edges)
{
    memset(x, 0, sizeof *x);
    const char *names[COLUMNS] = {"source_fid", "area", "name", "date"};
    const uint8_t types[COLUMNS] = {HPFC_ATTR_INTEGER, HPFC_ATTR_REAL, HPFC_ATTR_STRING,
                                    HPFC_ATTR_STRING};
    memcpy(x->names, names, sizeof names);
    memcpy(x->types, types, sizeof types);
    for (uint32_t k = 0; k < FEATURES; k++) {
        hpfc_attr_value *row = x->cells + k * COLUMNS;
        row[0] = (hpfc_attr_value){.type = HPFC_ATTR_INTEGER, .i = (int64_t)k * 1000 - 2};
        row[1] = (hpfc_attr_value){.type = k == 2 ? HPFC_ATTR_NULL : HPFC_ATTR_REAL,
                                   .r = 0.5 + k * 1e10};
        row[2] = (hpfc_attr_value){.type = HPFC_ATTR_STRING, .s = words[k], .len = strlen(words[k])};
        row[3] = (hpfc_attr_value){.type = k % 2 ? HPFC_ATTR_STRING : HPFC_ATTR_NULL,
                                   .s = "2026-12-01", .len = 10};
        x->fid[k] = k;
        x->layer[k] = 0;
    }
    x->layer_name[0] = "counties";
    x->face_start = calloc(faces + 1, sizeof *x->face_start);
    x->face_feature = calloc(faces + 1, sizeof *x->face_feature);
    for (uint32_t f = 1; f < faces; f++) {
        x->face_feature[x->face_start[f]] = f % FEATURES;
        x->face_start[f + 1] = x->face_start[f] + 1;
    }
    if (faces > 1)
        x->face_start[faces] = faces - 1;
    x->ft = (hpfc_feature_table){.feature_count = FEATURES, .fid = x->fid, .layer = x->layer,
                                 .layer_count = 1, .layer_name = x->layer_name,
                                 .face_count = faces, .face_start = x->face_start,
                                 .face_feature = x->face_feature};
    x->at = (hpfc_attr_table){.feature_count = FEATURES, .column_count = COLUMNS,
                              .name = x->names, .type = x->types, .cells = x->cells};
    /* edge e: features e % 5 and, for odd e, also 4 */
    uint32_t m = 0;
    for (uint32_t e = 0; e < edges; e++) {
        x->edge_start[e] = m;
        x->edge_feature[m++] = e % FEATURES == 4 ? 3 : e % FEATURES;
        if (e % 2)
            x->edge_feature[m++] = 4;
    }
    x->edge_start[edges] = m;
    x->et = (hpfc_edge_feature_table){.edge_count = edges, .feature_count = FEATURES,
                                      .edge_start = x->edge_start, .edge_feature = x->edge_feature};
}

/* A square with a diagonal: 4 vertices, 5 edges, 3 faces. */
static hpfc_graph *square_graph(void)
{
    hpfc_graph *g = NULL;
    CHECK_EQ_INT(hpfc_graph_create(&g), HPFC_OK);
    const int64_t xy[8] = {0, 0, 10, 0, 10, 10, 0, 10};
    for (int k = 0; k < 4; k++)
        hpfc_graph_add_vertex(g, xy[2 * k], xy[2 * k + 1], NULL);
    const uint32_t ends[10] = {0, 1, 1, 2, 2, 3, 3, 0, 0, 2};
    for (int k = 0; k < 5; k++)
        hpfc_graph_add_edge(g, ends[2 * k], ends[2 * k + 1], NULL, 0, NULL);
    return g;
}

static bool same(const char *s, size_t len, const char *want)
{
    return len == strlen(want) && memcmp(s, want, len) == 0;
}

/* The directory's entry of the section `tag` (all zero: none). */
static hpfc_section_info section_named(const hpfc_file *f, const char *tag)
{
    hpfc_file_info info;
    hpfc_section_info s;
    hpfc_file_get_info(f, &info);
    for (uint32_t k = 0; k < info.section_count; k++)
        if (hpfc_file_get_section(f, k, &s) == HPFC_OK && strcmp(s.tag, tag) == 0)
            return s;
    memset(&s, 0, sizeof s);
    return s;
}

static void check_read_back(const hpfc_file *f, const fixture *x)
{
    hpfc_attrs_info ai;
    CHECK_EQ_INT(hpfc_file_get_attrs(f, &ai), HPFC_OK);
    CHECK(ai.features == FEATURES && ai.columns == COLUMNS);
    uint64_t strings = 0; /* the column names, then every string value */
    for (uint32_t c = 0; c < COLUMNS; c++)
        strings += strlen(x->names[c]);
    for (uint32_t k = 0; k < FEATURES * COLUMNS; k++)
        strings += x->cells[k].type == HPFC_ATTR_STRING ? x->cells[k].len : 0;
    CHECK_EQ_INT(ai.string_bytes, strings);
    CHECK_EQ_INT(ai.section_bytes, section_named(f, "ATTR").length);
    for (uint32_t c = 0; c < COLUMNS; c++) {
        const char *name;
        size_t len;
        int type;
        uint32_t found = 99;
        CHECK_EQ_INT(hpfc_attr_column(f, c, &name, &len, &type), HPFC_OK);
        CHECK(same(name, len, x->names[c]) && type == x->types[c]);
        CHECK_EQ_INT(hpfc_attr_find(f, x->names[c], strlen(x->names[c]), &found), HPFC_OK);
        CHECK_EQ_INT(found, c);
    }
    for (uint32_t k = 0; k < FEATURES; k++)
        for (uint32_t c = 0; c < COLUMNS; c++) {
            const hpfc_attr_value *want = &x->cells[k * COLUMNS + c];
            hpfc_attr_value v;
            CHECK_EQ_INT(hpfc_file_get_attr_value(f, k, c, &v), HPFC_OK);
            CHECK_EQ_INT(v.type, want->type);
            if (want->type == HPFC_ATTR_INTEGER)
                CHECK(v.i == want->i);
            if (want->type == HPFC_ATTR_REAL)
                CHECK(v.r == want->r);
            if (want->type == HPFC_ATTR_STRING)
                CHECK(v.len == want->len && memcmp(v.s, want->s, v.len) == 0);
        }
    hpfc_attr_value v;
    uint32_t col;
    CHECK_EQ_INT(hpfc_file_get_attr_value(f, FEATURES, 0, &v), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_file_get_attr_value(f, 0, COLUMNS, &v), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_attr_find(f, "nosuch", 6, &col), HPFC_E_ARG);
    hpfc_edge_links_info ei;
    CHECK_EQ_INT(hpfc_file_get_edge_links(f, &ei), HPFC_OK);
    const uint32_t edges = x->et.edge_count;
    CHECK(ei.edges == edges && ei.links == x->edge_start[edges] && ei.features == FEATURES);
    CHECK_EQ_INT(ei.section_bytes, section_named(f, "EDGF").length);
    for (uint32_t e = 0; e < edges; e++) {
        uint32_t n = 99;
        hpfc_id feature = 99;
        CHECK_EQ_INT(hpfc_edge_feature_count(f, e, &n), HPFC_OK);
        CHECK_EQ_INT(n, x->edge_start[e + 1] - x->edge_start[e]);
        for (uint32_t k = 0; k < n; k++) {
            CHECK_EQ_INT(hpfc_edge_feature_id(f, e, k, &feature), HPFC_OK);
            CHECK_EQ_INT(feature, x->edge_feature[x->edge_start[e] + k]);
        }
        CHECK_EQ_INT(hpfc_edge_feature_id(f, e, n, &feature), HPFC_E_ARG);
    }
    uint32_t n;
    CHECK_EQ_INT(hpfc_edge_feature_count(f, edges, &n), HPFC_E_ARG);
}

/* Every accessor on a damaged copy: named statuses, values inside the file. */
static void probe(const hpfc_file *f, const uint8_t *m, size_t size)
{
    hpfc_attrs_info ai;
    if (hpfc_file_get_attrs(f, &ai) == HPFC_OK) {
        CHECK(ai.section_bytes <= size);
        for (uint32_t c = 0; c <= ai.columns && c < 8; c++) {
            const char *name;
            size_t len;
            int type;
            int st = hpfc_attr_column(f, c, &name, &len, &type);
            CHECK(st == HPFC_OK || st == HPFC_E_ARG || st == HPFC_E_CORRUPT);
            if (st == HPFC_OK)
                CHECK((const uint8_t *)name >= m && (const uint8_t *)name + len <= m + size);
            for (uint32_t k = 0; k <= ai.features && k < 8; k++) {
                hpfc_attr_value v;
                st = hpfc_file_get_attr_value(f, k, c, &v);
                CHECK(st == HPFC_OK || st == HPFC_E_ARG || st == HPFC_E_CORRUPT);
                if (st == HPFC_OK && v.type == HPFC_ATTR_STRING)
                    CHECK((const uint8_t *)v.s >= m && (const uint8_t *)v.s + v.len <= m + size);
            }
        }
        uint32_t col;
        int st = hpfc_attr_find(f, "name", 4, &col);
        CHECK(st == HPFC_OK || st == HPFC_E_ARG || st == HPFC_E_CORRUPT);
    }
    hpfc_edge_links_info ei;
    if (hpfc_file_get_edge_links(f, &ei) == HPFC_OK)
        for (uint32_t e = 0; e <= ei.edges && e < 16; e++) {
            uint32_t n = 0;
            hpfc_id feature;
            int st = hpfc_edge_feature_count(f, e, &n);
            CHECK(st == HPFC_OK || st == HPFC_E_ARG || st == HPFC_E_CORRUPT);
            for (uint32_t k = 0; st == HPFC_OK && k <= n && k < 16; k++) {
                int s2 = hpfc_edge_feature_id(f, e, k, &feature);
                CHECK(s2 == HPFC_OK || s2 == HPFC_E_ARG || s2 == HPFC_E_CORRUPT);
            }
        }
}

static long damaged, opened;

static void damage_section(const uint8_t *buf, size_t size, const char *tag)
{
    hpfc_file *f = NULL;
    CHECK_EQ_INT(hpfc_open_memory(buf, size, 0, &f), HPFC_OK);
    const hpfc_section_info si = section_named(f, tag);
    hpfc_close(f);
    CHECK(si.length > 0);
    for (uint64_t at = si.offset; at < si.offset + si.length; at++)
        for (int how = 0; how < 10; how++) {
            uint8_t *m = malloc(size);
            memcpy(m, buf, size);
            m[at] = how == 0 ? 0x00 : how == 1 ? 0xff : (uint8_t)(m[at] ^ (1u << (how - 2)));
            f = NULL;
            int st = hpfc_open_memory(m, size, HPFC_OPEN_SKIP_CHECKSUM, &f);
            CHECK(st == HPFC_OK || st == HPFC_E_SECTION);
            damaged++;
            if (f) {
                opened++;
                CHECK_EQ_INT(hpfc_file_check_checksums(f, NULL),
                             m[at] == buf[at] ? HPFC_OK : HPFC_E_CHECKSUM);
                probe(f, m, size);
                hpfc_close(f);
            }
            free(m);
        }
}

static void test_sections(void)
{
    hpfc_graph *g = square_graph();
    hpfc_build_params params;
    hpfc_build_params_default(&params);
    params.root_cols = params.root_rows = 4;
    hpfc_tree *t = NULL;
    CHECK_EQ_INT(hpfc_build(g, &params, &t, NULL), HPFC_OK);
    if (!t)
        return;
    hpfc_tree_info ti;
    hpfc_tree_get_info(t, &ti);
    fixture x;
    fixture_make(&x, (uint32_t)ti.faces, (uint32_t)hpfc_graph_edge_count(g));
    hpfc_write_options opts = {.features = &x.ft, .attributes = &x.at, .edge_features = &x.et};
    uint8_t *buf = NULL;
    size_t size = 0;
    hpfc_diag d;
    CHECK_EQ_INT(hpfc_tree_serialize(t, &opts, &buf, &size, &d), HPFC_OK);
    hpfc_file *f = NULL;
    CHECK_EQ_INT(hpfc_open_memory(buf, size, 0, &f), HPFC_OK);
    if (f) {
        hpfc_file_info fi;
        hpfc_file_get_info(f, &fi);
        CHECK_EQ_INT(fi.format_minor, HPFC_FORMAT_MINOR);
        CHECK_EQ_INT(hpfc_file_check_checksums(f, NULL), HPFC_OK);
        check_read_back(f, &x);
        /* a copy through hpfc_file_serialize keeps them */
        uint8_t *again = NULL;
        size_t again_size = 0;
        CHECK_EQ_INT(hpfc_file_serialize(f, &opts, &again, &again_size, &d), HPFC_OK);
        CHECK(again_size == size && memcmp(again, buf, size) == 0);
        hpfc_free(again);
        hpfc_close(f);
    }
    /* without the sections: NO_SECTION */
    uint8_t *plain = NULL;
    size_t plain_size = 0;
    CHECK_EQ_INT(hpfc_tree_serialize(t, NULL, &plain, &plain_size, &d), HPFC_OK);
    CHECK_EQ_INT(hpfc_open_memory(plain, plain_size, 0, &f), HPFC_OK);
    uint32_t a;
    hpfc_attr_value v;
    hpfc_attrs_info ai;
    hpfc_edge_links_info ei;
    CHECK_EQ_INT(hpfc_file_get_attrs(f, &ai), HPFC_E_NO_SECTION);
    CHECK_EQ_INT(hpfc_file_get_edge_links(f, &ei), HPFC_E_NO_SECTION);
    CHECK_EQ_INT(hpfc_file_get_attr_value(f, 0, 0, &v), HPFC_E_NO_SECTION);
    CHECK_EQ_INT(hpfc_edge_feature_count(f, 0, &a), HPFC_E_NO_SECTION);
    hpfc_close(f);
    hpfc_free(plain);

    damage_section(buf, size, "ATTR");
    damage_section(buf, size, "EDGF");

    /* inconsistent tables are refused by the writer */
    uint8_t *bad = NULL;
    size_t bad_size;
    x.cells[3].type = HPFC_ATTR_INTEGER; /* an integer in a string column */
    CHECK_EQ_INT(hpfc_tree_serialize(t, &opts, &bad, &bad_size, &d), HPFC_E_ARG);
    x.cells[3].type = HPFC_ATTR_NULL;
    x.types[1] = 9;
    CHECK_EQ_INT(hpfc_tree_serialize(t, &opts, &bad, &bad_size, &d), HPFC_E_ARG);
    x.types[1] = HPFC_ATTR_REAL;
    x.edge_feature[0] = FEATURES; /* no such feature */
    CHECK_EQ_INT(hpfc_tree_serialize(t, &opts, &bad, &bad_size, &d), HPFC_E_ARG);
    x.edge_feature[0] = 0;
    x.edge_start[2] = 0; /* offsets decrease */
    CHECK_EQ_INT(hpfc_tree_serialize(t, &opts, &bad, &bad_size, &d), HPFC_E_ARG);
    hpfc_free(buf);
    free(x.face_start);
    free(x.face_feature);
    hpfc_tree_free(t);
    hpfc_graph_free(g);
}

int main(void)
{
    test_sections();
    printf("attributes: %ld damaged copies, %ld opened\n", damaged, opened);
    return check_report("test_attrs");
}
