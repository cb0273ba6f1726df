/*
 * The FEAT section (hpfc_file_get_features, hpfc_file_get_feature, hpfc_layer_name,
 * hpfc_face_feature_*; spec/hpfc-format.md): a feature table written with a
 * map reads back field for field; every byte of the section damaged gives
 * a refusal at open or accesses that stay in bounds; the writer refuses
 * inconsistent tables.
 */
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "file_helpers.h"
#include "gen.h"
#include "hpfc.h"

/* ---- the FEAT section ---------------------------------------------------------------------- */

static bool same_string(const char *s, size_t len, const char *want)
{
    return want ? s && len == strlen(want) && memcmp(s, want, len) == 0 : s == NULL;
}

/* Everything the reader gives back equals the table that was written. */
static void check_features_read_back(const hpfc_file *f, const feat_fixture *x)
{
    hpfc_features_info fi;
    CHECK_EQ_INT(hpfc_file_get_features(f, &fi), HPFC_OK);
    CHECK(fi.features == 7 && fi.layers == 2 && fi.faces == x->t.face_count &&
          fi.links == x->start[x->t.face_count]);
    CHECK(same_string(fi.key_field, fi.key_field_len, "NAME"));
    for (uint32_t k = 0; k < 7; k++) {
        hpfc_feature ft;
        CHECK_EQ_INT(hpfc_file_get_feature(f, k, &ft), HPFC_OK);
        CHECK(ft.fid == x->fid[k] && ft.layer == x->layer[k]);
        CHECK(same_string(ft.key, ft.key_len, x->key[k]));
    }
    for (uint32_t l = 0; l < 2; l++) {
        const char *name;
        size_t len;
        CHECK_EQ_INT(hpfc_layer_name(f, l, &name, &len), HPFC_OK);
        CHECK(same_string(name, len, x->layer_name[l]));
    }
    for (uint32_t face = 0; face < x->t.face_count; face++) {
        uint32_t count = 99;
        hpfc_id feature = 99;
        CHECK_EQ_INT(hpfc_face_feature_count(f, face, &count), HPFC_OK);
        CHECK_EQ_INT(count, face == 0 ? 0 : 1 + face % 2);
        for (uint32_t k = 0; k < count; k++) {
            CHECK_EQ_INT(hpfc_face_feature_id(f, face, k, &feature), HPFC_OK);
            CHECK_EQ_INT(feature, k == 0 ? face % 5 : 5 + face % 2);
        }
        CHECK_EQ_INT(hpfc_face_feature_id(f, face, count, &feature), HPFC_E_ARG);
    }
    hpfc_feature ft;
    uint32_t count;
    const char *name;
    size_t len;
    CHECK_EQ_INT(hpfc_file_get_feature(f, 7, &ft), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_layer_name(f, 2, &name, &len), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_face_feature_count(f, x->t.face_count, &count), HPFC_E_ARG);
}

/* Every accessor on a file whose FEAT bytes were changed: a status, never
 * a read outside the section (AddressSanitizer watches the exact buffer). */
static void probe_features(const hpfc_file *f)
{
    hpfc_features_info fi;
    if (hpfc_file_get_features(f, &fi) != HPFC_OK)
        return;
    for (uint32_t k = 0; k <= fi.features && k < 64; k++) {
        hpfc_feature ft;
        int st = hpfc_file_get_feature(f, k, &ft);
        CHECK(st == HPFC_OK || st == HPFC_E_ARG || st == HPFC_E_CORRUPT);
        if (st == HPFC_OK && ft.key)
            (void)memchr(ft.key, 0, ft.key_len);
    }
    for (uint32_t l = 0; l <= fi.layers && l < 8; l++) {
        const char *name;
        size_t len;
        int st = hpfc_layer_name(f, l, &name, &len);
        CHECK(st == HPFC_OK || st == HPFC_E_ARG || st == HPFC_E_CORRUPT);
        if (st == HPFC_OK)
            (void)memchr(name, 0, len);
    }
    for (uint32_t face = 0; face <= fi.faces && face < 64; face++) {
        uint32_t count = 0;
        hpfc_id feature;
        int st = hpfc_face_feature_count(f, face, &count);
        CHECK(st == HPFC_OK || st == HPFC_E_ARG || st == HPFC_E_CORRUPT);
        for (uint32_t k = 0; st == HPFC_OK && k < count && k < 16; k++) {
            int s2 = hpfc_face_feature_id(f, face, k, &feature);
            CHECK(s2 == HPFC_OK || s2 == HPFC_E_CORRUPT);
            CHECK(s2 != HPFC_OK || feature < fi.features);
        }
    }
}

static void test_features(void)
{
    hpfc_tree *t = special_tree(GEN_SPECIAL_HOLE, 3);
    if (!t)
        return;
    size_t plain_size, size;
    uint8_t *plain = serialize(t, "EPSG:4326", &plain_size);
    hpfc_file *f = NULL;
    hpfc_faces *fc = NULL;
    CHECK_EQ_INT(hpfc_open_memory(plain, plain_size, 0, &f), HPFC_OK);
    CHECK_EQ_INT(hpfc_faces_build(f, &fc), HPFC_OK);
    uint32_t faces = (uint32_t)hpfc_faces_face_count(fc);
    hpfc_features_info fi;
    CHECK_EQ_INT(hpfc_file_get_features(f, &fi), HPFC_E_NO_SECTION);
    hpfc_faces_free(fc);
    hpfc_close(f);
    CHECK(faces >= 3);

    feat_fixture x;
    feat_fixture_make(&x, faces);
    hpfc_write_options opts = {.crs = "EPSG:4326", .features = &x.t};
    uint8_t *buf = NULL;
    hpfc_diag d;
    CHECK_EQ_INT(check_tree_serialize(t, &opts, &buf, &size, &d), HPFC_OK);
    /* the same pools, so the same faces; FEAT only adds a section */
    CHECK(buf && size > plain_size);
    f = NULL;
    CHECK_EQ_INT(hpfc_open_memory(buf, size, 0, &f), HPFC_OK);
    if (f) {
        CHECK_EQ_INT(hpfc_file_check_checksums(f, NULL), HPFC_OK);
        CHECK_EQ_INT(hpfc_faces_build(f, &fc), HPFC_OK);
        CHECK_EQ_INT(hpfc_faces_face_count(fc), faces);
        hpfc_faces_free(fc);
        check_features_read_back(f, &x);
        hpfc_close(f);
    }

    /* every byte of the section set to 0x00, 0xFF and bit-flipped: open
     * refuses the file with a named code or every access stays in bounds */
    hpfc_section_info si = {0};
    CHECK_EQ_INT(hpfc_open_memory(buf, size, 0, &f), HPFC_OK);
    for (uint32_t k = 0; f && k < 3; k++)
        if (hpfc_file_get_section(f, k, &si) == HPFC_OK && memcmp(si.tag, "FEAT", 4) == 0)
            break;
    hpfc_close(f);
    CHECK(memcmp(si.tag, "FEAT", 4) == 0 && si.offset + si.length == size);
    for (uint64_t at = si.offset; at < si.offset + si.length; at++)
        for (int how = 0; how < 10; how++) {
            uint8_t *m = malloc(size);
            memcpy(m, buf, size);
            m[at] = how == 0 ? 0x00 : how == 1 ? 0xff : (uint8_t)(m[at] ^ (1u << (how - 2)));
            f = NULL;
            int st = hpfc_open_memory(m, size, HPFC_OPEN_SKIP_CHECKSUM, &f);
            CHECK(st == HPFC_OK || st == HPFC_E_SECTION);
            if (f) {
                CHECK_EQ_INT(hpfc_file_check_checksums(f, NULL),
                             m[at] == buf[at] ? HPFC_OK : HPFC_E_CHECKSUM);
                probe_features(f);
                hpfc_close(f);
            }
            free(m);
        }

    /* inconsistent tables are refused by the writer */
    hpfc_free(buf);
    uint32_t saved = x.link[0];
    x.link[0] = 7; /* no such feature */
    CHECK_EQ_INT(check_tree_serialize(t, &opts, &buf, &size, &d), HPFC_E_ARG);
    x.link[0] = saved;
    x.layer[2] = 2; /* no such layer */
    CHECK_EQ_INT(check_tree_serialize(t, &opts, &buf, &size, &d), HPFC_E_ARG);
    x.layer[2] = 0;
    x.start[1] = 3, x.start[2] = 2; /* decreasing offsets */
    CHECK_EQ_INT(check_tree_serialize(t, &opts, &buf, &size, &d), HPFC_E_ARG);
    CHECK(buf == NULL);
    free(x.start);
    free(x.link);
    hpfc_free(plain);
    hpfc_tree_free(t);
}

int main(void)
{
    check_use_test_layout();
    test_features();
    return check_report("test_features");
}
