/*
 * open_buffer: the whole input is an .hpfc file, opened from memory
 * (hpfc_open_memory) twice: with the header checksum verified, then with
 * HPFC_OPEN_SKIP_CHECKSUM so mutated metadata gets past the checksum to the
 * header, level table and section directory checks. An opened file is then
 * queried through every metadata accessor, its FEAT section (when it has
 * one) through every feature accessor, its ATTR and EDGF sections through
 * every attribute and edge-feature accessor, each level's pool layout
 * checked (hpfc_file_check_pool_layout) and its checksums verified.
 *
 * Oracle: open fails only with a file code (MAGIC .. SECTION, or NOMEM) and
 * never with CORRUPT (open decodes no pool); opening with the checksum
 * verified succeeds only if opening without it does, with the same info;
 * the info a handle reports is inside the ranges open promises to check;
 * feature accessors give OK, ARG (out of range, exactly) or CORRUPT, and
 * every link they give names a feature; a failed layout or checksum check
 * explains itself (a checksum names the header or a section); status names
 * are the header's; hpfc_file_serialize of an opened
 * file, with no section or a CRS, opens with its checksums verified and
 * holds the same levels and the same pool bytes.
 */
#include "input.h"

static int feature_status_ok(int st)
{
    return st == HPFC_OK || st == HPFC_E_CORRUPT;
}

/* The FEAT accessors over the first entries of each table (a file may
 * declare 2^32 of them). */
static void probe_features(const hpfc_file *f)
{
    hpfc_features_info fi;
    int st = hpfc_file_get_features(f, &fi);
    FUZZ_CHECK(st == HPFC_OK || st == HPFC_E_NO_SECTION);
    if (st)
        return;
    FUZZ_CHECK(fi.key_field == NULL || fi.key_field_len < UINT32_MAX);
    hpfc_feature ft;
    const char *name;
    size_t len;
    uint32_t count;
    hpfc_id feature;
    for (uint32_t k = 0; k < fi.features && k < 256; k++) {
        FUZZ_CHECK(feature_status_ok(hpfc_file_get_feature(f, k, &ft)));
    }
    FUZZ_CHECK(hpfc_file_get_feature(f, fi.features, &ft) == HPFC_E_ARG);
    for (uint32_t l = 0; l < fi.layers && l < 256; l++)
        FUZZ_CHECK(feature_status_ok(hpfc_layer_name(f, l, &name, &len)));
    FUZZ_CHECK(hpfc_layer_name(f, fi.layers, &name, &len) == HPFC_E_ARG);
    for (uint32_t face = 0; face < fi.faces && face < 256; face++) {
        st = hpfc_face_feature_count(f, face, &count);
        FUZZ_CHECK(feature_status_ok(st));
        for (uint32_t k = 0; st == HPFC_OK && k < count && k < 64; k++) {
            int s2 = hpfc_face_feature_id(f, face, k, &feature);
            FUZZ_CHECK(feature_status_ok(s2));
            FUZZ_CHECK(s2 != HPFC_OK || feature < fi.features);
        }
        if (st == HPFC_OK)
            FUZZ_CHECK(hpfc_face_feature_id(f, face, count, &feature) == HPFC_E_ARG);
    }
    FUZZ_CHECK(hpfc_face_feature_count(f, fi.faces, &count) == HPFC_E_ARG);
}

/* The ATTR and EDGF accessors (1.2) over the first rows, columns and
 * edges: OK, ARG exactly out of range, or CORRUPT; strings and names lie
 * in the buffer [base, base + size). */
static void probe_attributes(const hpfc_file *f, const uint8_t *base, size_t size)
{
    hpfc_attrs_info ai = {0};
    uint32_t col;
    int st = hpfc_file_get_attrs(f, &ai);
    FUZZ_CHECK(st == HPFC_OK || st == HPFC_E_NO_SECTION);
    FUZZ_CHECK(st || (ai.section_bytes <= size && ai.string_bytes < ai.section_bytes));
    uint64_t features = ai.features, columns = ai.columns;
    for (uint32_t c = 0; st == HPFC_OK && c <= columns && c < 64; c++) {
        const char *name;
        size_t len;
        int type;
        int s1 = hpfc_attr_column(f, c, &name, &len, &type);
        FUZZ_CHECK(c == columns ? s1 == HPFC_E_ARG : feature_status_ok(s1));
        if (s1 == HPFC_OK) {
            FUZZ_CHECK(type >= HPFC_ATTR_INTEGER && type <= HPFC_ATTR_STRING);
            FUZZ_CHECK((const uint8_t *)name >= base && (const uint8_t *)name + len <= base + size);
            int s3 = hpfc_attr_find(f, name, len, &col);
            FUZZ_CHECK(feature_status_ok(s3) && (s3 != HPFC_OK || col <= c));
        }
        for (uint32_t k = 0; k <= features && k < 64; k++) {
            hpfc_attr_value v;
            int s2 = hpfc_file_get_attr_value(f, k, c, &v);
            if (k == features || c == columns) /* a damaged column may be found first */
                FUZZ_CHECK(s2 == HPFC_E_ARG || (c < columns && s2 == HPFC_E_CORRUPT));
            else
                FUZZ_CHECK(feature_status_ok(s2));
            if (s2 == HPFC_OK && v.type == HPFC_ATTR_STRING)
                FUZZ_CHECK((const uint8_t *)v.s >= base && (const uint8_t *)v.s + v.len <= base + size);
        }
    }
    hpfc_edge_links_info ei = {0};
    uint32_t count;
    hpfc_id feature;
    st = hpfc_file_get_edge_links(f, &ei);
    FUZZ_CHECK(st == HPFC_OK || st == HPFC_E_NO_SECTION);
    FUZZ_CHECK(st || ei.section_bytes <= size);
    for (uint32_t e = 0; st == HPFC_OK && e < ei.edges && e < 256; e++) {
        int s1 = hpfc_edge_feature_count(f, e, &count);
        FUZZ_CHECK(feature_status_ok(s1));
        for (uint32_t k = 0; s1 == HPFC_OK && k < count && k < 64; k++) {
            int s2 = hpfc_edge_feature_id(f, e, k, &feature);
            FUZZ_CHECK(feature_status_ok(s2));
            FUZZ_CHECK(s2 != HPFC_OK || feature < ei.features);
        }
        if (s1 == HPFC_OK)
            FUZZ_CHECK(hpfc_edge_feature_id(f, e, count, &feature) == HPFC_E_ARG);
    }
    if (st == HPFC_OK)
        FUZZ_CHECK(hpfc_edge_feature_count(f, ei.edges, &count) == HPFC_E_ARG);
}

static int open_status_ok(int st)
{
    return st == HPFC_OK || st == HPFC_E_NOMEM || (st >= HPFC_E_MAGIC && st <= HPFC_E_SECTION);
}

static void query(const hpfc_file *f)
{
    hpfc_file_info info;
    hpfc_file_get_info(f, &info);
    FUZZ_CHECK(info.format_major == 1);
    FUZZ_CHECK(info.levels >= 1 && info.levels <= HPFC_MAX_LEVELS);
    FUZZ_CHECK(info.root_cols >= 1 && info.root_rows >= 1 && info.cols >= 2 && info.rows >= 2);
    FUZZ_CHECK(info.width >= 1 && info.height >= 1);
    FUZZ_CHECK(info.section_count >= 1);
    if (info.crs) {
        /* the text lies in the buffer and holds no NUL (R15) */
        FUZZ_CHECK(memchr(info.crs, '\0', info.crs_len) == NULL);
    }
    int64_t cell_w = info.width, cell_h = info.height;
    for (uint32_t l = 0; l < info.levels; l++) {
        hpfc_level_info lv;
        FUZZ_CHECK(hpfc_file_get_level(f, l, &lv) == HPFC_OK);
        FUZZ_CHECK(lv.cell_w >= 1 && lv.cell_h >= 1 && lv.cell_w <= cell_w && lv.cell_h <= cell_h);
        FUZZ_CHECK(lv.pool_offset + (lv.pool_bits + 7) / 8 <= info.file_size);
        FUZZ_CHECK(lv.images >= 1 && lv.address_bits <= 64);
        FUZZ_CHECK(l + 1 < info.levels || lv.refined_pixels == 0);
        cell_w = lv.cell_w, cell_h = lv.cell_h;
    }
    hpfc_level_info lv;
    FUZZ_CHECK(hpfc_file_get_level(f, info.levels, &lv) == HPFC_E_ARG);
    for (uint32_t l = 0; l <= info.levels; l++) { /* the compact layout's own structure */
        hpfc_diag d;
        int s = hpfc_file_check_pool_layout(f, l, &d);
        FUZZ_CHECK(l == info.levels ? s == HPFC_E_ARG : s == HPFC_OK || s == HPFC_E_CORRUPT);
        FUZZ_CHECK(s == HPFC_OK || (d.status == s && d.message[0] != '\0'));
    }
    for (uint32_t k = 0; k < info.section_count; k++) {
        hpfc_section_info s;
        FUZZ_CHECK(hpfc_file_get_section(f, k, &s) == HPFC_OK);
        FUZZ_CHECK(s.tag[4] == '\0' && s.offset + s.length <= info.file_size);
    }
    hpfc_section_info s;
    FUZZ_CHECK(hpfc_file_get_section(f, info.section_count, &s) == HPFC_E_ARG);
    probe_features(f);
    hpfc_diag diag;
    int st = hpfc_file_check_checksums(f, &diag);
    FUZZ_CHECK(st == HPFC_OK || st == HPFC_E_CHECKSUM);
    FUZZ_CHECK(diag.status == st && memchr(diag.message, '\0', sizeof diag.message));
    /* a failure names the header or a section of the directory */
    FUZZ_CHECK(st == HPFC_OK ? diag.message[0] == '\0'
                             : strncmp(diag.message, "the header's ", 13) == 0 ||
                                   strncmp(diag.message, "section ", 8) == 0);
}

/* The map serialised again (pools copied) reads back as the same map. */
static void reserialize(const hpfc_file *f, const uint8_t *data, const char *crs)
{
    hpfc_write_options opts = {.crs = crs};
    uint8_t *out = NULL;
    size_t size = 0;
    hpfc_diag d;
    int st = hpfc_file_serialize(f, &opts, &out, &size, &d);
    FUZZ_CHECK(st == HPFC_OK || st == HPFC_E_NOMEM);
    hpfc_file *g = NULL;
    if (!st) {
        FUZZ_CHECK(hpfc_open_memory(out, size, 0, &g) == HPFC_OK);
        FUZZ_CHECK(hpfc_file_check_checksums(g, NULL) == HPFC_OK);
    }
    hpfc_file_info a, b;
    hpfc_file_get_info(f, &a);
    if (g) {
        hpfc_file_get_info(g, &b);
        FUZZ_CHECK(a.levels == b.levels && a.root_cols == b.root_cols && a.cols == b.cols &&
                   a.x0 == b.x0 && a.width == b.width && a.unit_exp10 == b.unit_exp10);
        FUZZ_CHECK(b.crs_len == (crs ? strlen(crs) : 0));
    }
    for (uint32_t l = 0; g && l < a.levels; l++) {
        hpfc_level_info x, y;
        FUZZ_CHECK(hpfc_file_get_level(f, l, &x) == HPFC_OK &&
                   hpfc_file_get_level(g, l, &y) == HPFC_OK);
        FUZZ_CHECK(x.word_pixels == y.word_pixels && x.refined_pixels == y.refined_pixels &&
                   x.images == y.images && x.word_bits == y.word_bits &&
                   x.address_bits == y.address_bits && x.pool_bits == y.pool_bits);
        FUZZ_CHECK(memcmp(data + x.pool_offset, out + y.pool_offset, (x.pool_bits + 7) / 8) == 0);
    }
    hpfc_close(g);
    hpfc_free(out);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    hpfc_file *checked = NULL, *skipped = NULL;
    int st_checked = hpfc_open_memory(data, size, 0, &checked);
    int st_skipped = hpfc_open_memory(data, size, HPFC_OPEN_SKIP_CHECKSUM, &skipped);
    FUZZ_CHECK(open_status_ok(st_checked) && open_status_ok(st_skipped));
    FUZZ_CHECK(hpfc_strerror(st_checked) != NULL && hpfc_strerror(st_skipped) != NULL);
    FUZZ_CHECK(strncmp(hpfc_status_name(st_checked), "HPFC_", 5) == 0 &&
               strcmp(hpfc_status_name(st_checked), "HPFC_E_UNKNOWN") != 0);
    FUZZ_CHECK(strcmp(hpfc_version_string(), HPFC_VERSION_STRING) == 0 &&
               hpfc_version_number() == HPFC_VERSION_NUMBER);
    FUZZ_CHECK((st_checked == HPFC_OK) == (checked != NULL));
    FUZZ_CHECK((st_skipped == HPFC_OK) == (skipped != NULL));
    /* the checksum is the only check the flag skips */
    FUZZ_CHECK(st_checked != HPFC_OK || st_skipped == HPFC_OK);
    FUZZ_CHECK(st_skipped == HPFC_OK || st_checked == st_skipped ||
               st_checked == HPFC_E_CHECKSUM);
    if (skipped) {
        query(skipped);
        probe_attributes(skipped, data, size);
        reserialize(skipped, data, NULL);
        reserialize(skipped, data, "EPSG:4326");
    }
    if (checked) {
        query(checked);
        hpfc_file_info a, b;
        hpfc_file_get_info(checked, &a);
        hpfc_file_get_info(skipped, &b);
        FUZZ_CHECK(memcmp(&a, &b, sizeof a) == 0);
    }
    hpfc_close(checked);
    hpfc_close(skipped);
    return 0;
}
