/*
 * test_deprecated.c: every deprecated name at the end of hpfc.h still
 * compiles (this file alone is built with -Wno-deprecated-declarations) and
 * answers what the call it names answers, status included, on a file with
 * every section (FEAT, ATTR, EDGF, LABL, GEOM), on a damaged copy and on
 * arguments out of range.
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "hpfc.h"

/* A square cut by its diagonal (faces 0, 1, 2), a dangling polyline edge
 * inside one triangle: 6 vertices, 6 edges. */
static hpfc_graph *map(void)
{
    hpfc_graph *g = NULL;
    CHECK_EQ_INT(hpfc_graph_create(&g), HPFC_OK);
    const int64_t xy[12] = {0, 0, 100, 0, 100, 100, 0, 100, 60, 20, 80, 30};
    for (int k = 0; k < 6; k++)
        hpfc_graph_add_vertex(g, xy[2 * k], xy[2 * k + 1], NULL);
    const uint32_t ends[10] = {0, 1, 1, 2, 2, 3, 3, 0, 0, 2};
    for (int k = 0; k < 5; k++)
        hpfc_graph_add_edge(g, ends[2 * k], ends[2 * k + 1], NULL, 0, NULL);
    const int64_t bend[2] = {75, 15};
    hpfc_graph_add_edge(g, 4, 5, bend, 1, NULL);
    return g;
}

/* Two features over the two triangles, the second also along edges 4 and
 * 5, one attribute column: the FEAT, ATTR and EDGF sections. */
static uint8_t *pack(size_t *size)
{
    hpfc_graph *g = map();
    hpfc_build_params p;
    hpfc_build_params_default(&p);
    p.root_cols = p.root_rows = 4;
    hpfc_tree *t = NULL;
    uint8_t *bare = NULL, *out = NULL;
    size_t bare_size = 0;
    hpfc_file *f = NULL;
    const hpfc_write_options plain = {.face_labels = 1, .geometry = g};
    CHECK_EQ_INT(hpfc_build(g, &p, &t, NULL), HPFC_OK);
    CHECK_EQ_INT(hpfc_tree_serialize(t, &plain, &bare, &bare_size, NULL), HPFC_OK);
    CHECK_EQ_INT(hpfc_open_memory(bare, bare_size, 0, &f), HPFC_OK);
    static const int64_t fid[2] = {10, 11};
    static const uint32_t layer[2] = {0, 0}, face_start[4] = {0, 0, 1, 2},
                          face_feature[2] = {0, 1}, edge_start[7] = {0, 0, 0, 0, 0, 1, 2},
                          edge_feature[2] = {1, 1};
    static const char *const layer_name[1] = {"triangles"}, *const key[2] = {"a", "b"},
                             *const column[1] = {"n"};
    static const uint8_t type[1] = {HPFC_ATTR_INTEGER};
    static const hpfc_attr_value cells[2] = {{.type = HPFC_ATTR_INTEGER, .i = 7},
                                             {.type = HPFC_ATTR_NULL}};
    const hpfc_feature_table ft = {.feature_count = 2, .fid = fid, .layer = layer,
                                   .key_field = "name", .key = key, .layer_count = 1,
                                   .layer_name = layer_name, .face_count = 3,
                                   .face_start = face_start, .face_feature = face_feature};
    const hpfc_attr_table at = {.feature_count = 2, .column_count = 1, .name = column,
                                .type = type, .cells = cells};
    const hpfc_edge_feature_table et = {.edge_count = 6, .feature_count = 2,
                                        .edge_start = edge_start, .edge_feature = edge_feature};
    const hpfc_write_options gis = {.features = &ft, .attributes = &at, .edge_features = &et};
    if (f)
        CHECK_EQ_INT(hpfc_file_serialize(f, &gis, &out, size, NULL), HPFC_OK);
    hpfc_close(f);
    hpfc_free(bare);
    hpfc_tree_free(t);
    hpfc_graph_free(g);
    return out;
}

static void same_section_calls(const hpfc_file *f)
{
    hpfc_features_info fa, fb;
    hpfc_labels_info la, lb;
    hpfc_geometry_info ga, gb;
    CHECK_EQ_INT(hpfc_file_features(f, &fa), hpfc_file_get_features(f, &fb));
    CHECK(memcmp(&fa, &fb, sizeof fa) == 0);
    CHECK_EQ_INT(hpfc_file_labels(f, &la), hpfc_file_get_labels(f, &lb));
    CHECK(memcmp(&la, &lb, sizeof la) == 0);
    CHECK_EQ_INT(hpfc_file_geometry(f, &ga), hpfc_file_get_geometry(f, &gb));
    CHECK(memcmp(&ga, &gb, sizeof ga) == 0);
    for (uint32_t level = 0; level < 3; level++)
        CHECK_EQ_INT(hpfc_check_pool_layout(f, level, NULL),
                     hpfc_file_check_pool_layout(f, level, NULL));

    uint32_t a = 99, b = 99;
    hpfc_attrs_info ai;
    CHECK_EQ_INT(hpfc_attr_info(f, &a, &b), hpfc_file_get_attrs(f, &ai));
    CHECK(a == ai.features && b == ai.columns && a == 2 && b == 1);
    CHECK_EQ_INT(hpfc_attr_info(f, NULL, &b), HPFC_E_ARG);
    hpfc_edge_links_info ei;
    CHECK_EQ_INT(hpfc_edge_features_info(f, &a, &b), hpfc_file_get_edge_links(f, &ei));
    CHECK(a == ei.edges && b == ei.links && a == 6 && b == 2);
    CHECK_EQ_INT(hpfc_edge_features_info(f, &a, NULL), HPFC_E_ARG);

    for (uint32_t k = 0; k <= 2; k++) {
        hpfc_feature x, y;
        memset(&x, 0, sizeof x), memset(&y, 0, sizeof y);
        CHECK_EQ_INT(hpfc_feature_get(f, k, &x), hpfc_file_get_feature(f, k, &y));
        CHECK(memcmp(&x, &y, sizeof x) == 0);
        hpfc_attr_value v, w, u;
        memset(&v, 0, sizeof v), memset(&w, 0, sizeof w), memset(&u, 0, sizeof u);
        CHECK_EQ_INT(hpfc_attr_get(f, k, 0, &v), hpfc_file_get_attr_value(f, k, 0, &w));
        CHECK_EQ_INT(hpfc_file_get_attr(f, k, 0, &u), hpfc_file_get_attr_value(f, k, 0, &w));
        CHECK(memcmp(&v, &w, sizeof v) == 0 && memcmp(&u, &w, sizeof u) == 0);
    }
    for (hpfc_id face = 0; face <= 3; face++)
        for (uint32_t k = 0; k <= 1; k++) {
            uint32_t old = 99;
            hpfc_id id = 99;
            CHECK_EQ_INT(hpfc_face_feature(f, face, k, &old),
                         hpfc_face_feature_id(f, face, k, &id));
            CHECK_EQ_INT(old, id);
        }
    for (hpfc_id edge = 0; edge <= 6; edge++)
        for (uint32_t k = 0; k <= 1; k++) {
            uint32_t old = 99;
            hpfc_id id = 99;
            CHECK_EQ_INT(hpfc_edge_feature(f, edge, k, &old),
                         hpfc_edge_feature_id(f, edge, k, &id));
            CHECK_EQ_INT(old, id);
        }
}

/* The per-dart calls and the faces' numbering, on every dart of every leaf
 * and one key that names nothing. */
static void same_dart_calls(const hpfc_file *f)
{
    hpfc_walker *w = NULL;
    hpfc_faces *fc = NULL;
    CHECK_EQ_INT(hpfc_walker_create(f, &w), HPFC_OK);
    CHECK_EQ_INT(hpfc_faces_build(f, &fc), HPFC_OK);
    if (!w || !fc)
        goto done;
    CHECK_EQ_INT(hpfc_faces_count(fc), hpfc_faces_face_count(fc));
    CHECK_EQ_INT(hpfc_faces_face_count(fc), 3);
    hpfc_pixel px;
    size_t darts = 0;
    for (int st = hpfc_leaf_first(f, &px); st == HPFC_OK; st = hpfc_leaf_next(f, &px)) {
        hpfc_id a = 99, b = 99;
        CHECK_EQ_INT(hpfc_faces_of_private_pixel(fc, &px, &a), hpfc_faces_pixel_face(fc, &px, &b));
        CHECK_EQ_INT(a, b);
        size_t len = 0;
        CHECK_EQ_INT(hpfc_pixel_word(f, &px, NULL, 0, &len), HPFC_OK);
        for (uint32_t k = 0; k + 4 <= len; k++) { /* every crossing and one past */
            uint64_t key = HPFC_KEY_INVALID;
            if (k + 4 == len || hpfc_pixel_dart_key(w, &px, k, &key) != HPFC_OK)
                key = HPFC_KEY_INVALID;
            darts += key != HPFC_KEY_INVALID;
            hpfc_dart d = {.pixel = px, .crossing = k};
            a = b = 99;
            CHECK_EQ_INT(hpfc_faces_of_dart(fc, &d, &a), hpfc_faces_dart_face(fc, &d, &b));
            CHECK_EQ_INT(a, b);
            a = b = 99;
            CHECK_EQ_INT(hpfc_faces_of_key(fc, w, key, &a), hpfc_faces_key_face(fc, w, key, &b));
            CHECK_EQ_INT(a, b);
            a = b = 99;
            CHECK_EQ_INT(hpfc_key_label_face(w, key, &a), hpfc_label_key_face(w, key, &b));
            CHECK_EQ_INT(a, b);
            a = b = 99;
            CHECK_EQ_INT(hpfc_key_label_edge(w, key, &a), hpfc_label_key_edge(w, key, &b));
            CHECK_EQ_INT(a, b);
            int ra = 9, rb = 9;
            a = b = 99;
            CHECK_EQ_INT(hpfc_key_geometry_edge(w, key, &a, &ra),
                         hpfc_geometry_key_edge(w, key, &b, &rb));
            CHECK(a == b && ra == rb);
            int64_t xa[16], xb[16];
            size_t na = 99, nb = 99;
            CHECK_EQ_INT(hpfc_key_geometry_points(w, key, xa, 8, &na),
                         hpfc_geometry_key_points(w, key, xb, 8, &nb));
            CHECK(na == nb &&
                  (key == HPFC_KEY_INVALID || memcmp(xa, xb, 2 * na * sizeof *xa) == 0));
        }
    }
    CHECK_EQ_INT(darts, 2 * 6);
done:
    hpfc_faces_free(fc);
    hpfc_walker_free(w);
}

/* Rings and lines back, every face and feature and one past. */
static void same_shapes_calls(const hpfc_file *f)
{
    hpfc_shapes *s = NULL;
    CHECK_EQ_INT(hpfc_shapes_create(f, &s), HPFC_OK);
    if (!s)
        return;
    for (hpfc_id face = 0; face <= 3; face++) {
        hpfc_polygons a, b;
        int sa = hpfc_shapes_face(s, face, &a);
        size_t na = sa ? 0 : a.point_count;
        CHECK_EQ_INT(sa, hpfc_shapes_face_polygons(s, face, &b));
        CHECK(sa || (na == b.point_count && b.ring_count > 0));
    }
    for (uint32_t k = 0; k <= 2; k++) {
        hpfc_polygons a, b;
        int sa = hpfc_shapes_feature(s, k, &a);
        size_t na = sa ? 0 : a.point_count;
        CHECK_EQ_INT(sa, hpfc_shapes_feature_polygons(s, k, &b));
        CHECK(sa || na == b.point_count);
        sa = hpfc_shapes_feature_lines(s, k, &a);
        na = sa ? 0 : a.point_count;
        CHECK_EQ_INT(sa, hpfc_shapes_feature_polylines(s, k, &b));
        CHECK(sa || na == b.point_count);
        uint64_t old = 99;
        size_t n = 99;
        CHECK_EQ_INT(hpfc_shapes_feature_face_count(s, k, &old),
                     hpfc_shapes_feature_faces(s, k, NULL, 0, &n));
        CHECK(k == 2 || (old == n && n == 1));
    }
    hpfc_shapes_free(s);
}

int main(void)
{
    size_t size = 0;
    uint8_t *buf = pack(&size);
    hpfc_file *f = NULL;
    if (buf)
        CHECK_EQ_INT(hpfc_open_memory(buf, size, 0, &f), HPFC_OK);
    if (f) {
        same_section_calls(f);
        same_dart_calls(f);
        same_shapes_calls(f);
        CHECK_EQ_INT(hpfc_file_verify_checksums(f), HPFC_OK);
        CHECK_EQ_INT(hpfc_verify_checksums(f), HPFC_OK);
        hpfc_close(f);
        /* a damaged last byte: the section checksums fail alike */
        buf[size - 1] ^= 1;
        CHECK_EQ_INT(hpfc_open_memory(buf, size, 0, &f), HPFC_OK);
        CHECK_EQ_INT(hpfc_file_verify_checksums(f), HPFC_E_CHECKSUM);
        CHECK_EQ_INT(hpfc_verify_checksums(f), hpfc_file_check_checksums(f, NULL));
        hpfc_close(f);
    }
    CHECK_EQ_INT(hpfc_file_verify_checksums(NULL), HPFC_E_ARG);
    hpfc_free(buf);
    return check_report("deprecated");
}
