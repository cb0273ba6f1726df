/*
 * test_api.c: the conventions of the public header itself, checked against
 * independent sources: every status code against the spec's table (§7.4)
 * and every `HPFC_E_NAME (number)` the specs cite, and its name as
 * hpfc_status_name gives it; the structs that grow (a caller compiled
 * against an older or a newer hpfc.h, simulated by the size it passes);
 * the format version a written file carries. The deprecated names have
 * their own test (test_deprecated.c).
 */
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "hpfc.h"
#include "hpfc_batch.h"

/* Every code of hpfc.h, by the header's own names and values. */
#define CODE(c) {c, #c}
static const struct {
    int code;
    const char *name;
} all_codes[] = {
    CODE(HPFC_OK), CODE(HPFC_E_NOMEM), CODE(HPFC_E_ARG), CODE(HPFC_E_IO),
    CODE(HPFC_E_BUFFER_SMALL), CODE(HPFC_E_PFC_SYNTAX), CODE(HPFC_E_PFC_VERSION),
    CODE(HPFC_E_VERTEX_INDEX), CODE(HPFC_E_DUPLICATE_POINT), CODE(HPFC_E_ZERO_LENGTH),
    CODE(HPFC_E_LOOP_INTERIOR), CODE(HPFC_E_ISOLATED_VERTEX), CODE(HPFC_E_NONPLANAR),
    CODE(HPFC_E_EXTENT), CODE(HPFC_E_EMPTY), CODE(HPFC_E_TOO_MANY_PIXELS), CODE(HPFC_E_LIMIT),
    CODE(HPFC_E_MAGIC), CODE(HPFC_E_VERSION), CODE(HPFC_E_INCOMPATIBLE), CODE(HPFC_E_TRUNCATED),
    CODE(HPFC_E_CHECKSUM), CODE(HPFC_E_HEADER), CODE(HPFC_E_LEVEL_TABLE), CODE(HPFC_E_SECTION),
    CODE(HPFC_E_CORRUPT), CODE(HPFC_E_NO_PIXEL), CODE(HPFC_E_NO_SECTION),
    CODE(HPFC_E_OVER_LIMIT),
};
#define CODE_COUNT (sizeof all_codes / sizeof all_codes[0])

static char *read_text(const char *dir, const char *name)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *fp = fopen(path, "rb");
    if (!fp) {
        fprintf(stderr, "cannot open %s\n", path);
        exit(EXIT_FAILURE);
    }
    fseek(fp, 0, SEEK_END);
    long n = ftell(fp);
    rewind(fp);
    char *s = malloc((size_t)n + 1);
    if (!s || fread(s, 1, (size_t)n, fp) != (size_t)n)
        exit(EXIT_FAILURE);
    s[n] = '\0';
    fclose(fp);
    return s;
}

static int code_of_name(const char *name, size_t len)
{
    for (size_t k = 0; k < CODE_COUNT; k++)
        if (strlen(all_codes[k].name) == len && memcmp(all_codes[k].name, name, len) == 0)
            return all_codes[k].code;
    return -1;
}

/* The spec's §7.4 rows "| number | `NAME` | meaning |": each names a code
 * of the header with its number, and each code has its row. */
static void check_spec_table(const char *spec)
{
    const char *at = strstr(spec, "### 7.4 Status codes");
    CHECK(at != NULL);
    if (!at)
        return;
    const char *end = strstr(at, "\n## ");
    int seen[CODE_COUNT] = {0};
    size_t rows = 0;
    for (const char *line = at; line && line < end; line = strchr(line + 1, '\n')) {
        int number;
        char name[64];
        if (sscanf(line, "\n| %d | `%63[A-Z_]` |", &number, name) != 2)
            continue;
        rows++;
        int code = code_of_name(name, strlen(name));
        if (code != number)
            fprintf(stderr, "spec row %s (%d): header says %d\n", name, number, code);
        CHECK_EQ_INT(code, number);
        for (size_t k = 0; k < CODE_COUNT; k++)
            seen[k] += all_codes[k].code == number;
    }
    CHECK_EQ_INT(rows, CODE_COUNT);
    for (size_t k = 0; k < CODE_COUNT; k++)
        if (seen[k] != 1)
            fprintf(stderr, "%s: %d rows in the spec's table\n", all_codes[k].name, seen[k]);
    for (size_t k = 0; k < CODE_COUNT; k++)
        CHECK_EQ_INT(seen[k], 1);
}

/* Every "`HPFC_E_NAME` (number)" in a spec's text gives the header's number. */
static void check_citations(const char *text, const char *file)
{
    size_t cited = 0;
    for (const char *p = strstr(text, "`HPFC_"); p; p = strstr(p + 1, "`HPFC_")) {
        const char *close = strchr(p + 1, '`');
        int number;
        if (!close || sscanf(close + 1, " (%d)", &number) != 1)
            continue;
        cited++;
        int code = code_of_name(p + 1, (size_t)(close - p - 1));
        if (code != number)
            fprintf(stderr, "%s: %.*s (%d): header says %d\n", file, (int)(close - p - 1), p + 1,
                    number, code);
        CHECK_EQ_INT(code, number);
    }
    CHECK(cited > 10);
}

/* hpfc_strerror names every code, each differently, and no other. */
static void check_strerror(void)
{
    const char *unknown = hpfc_strerror(9999);
    CHECK(unknown != NULL);
    for (size_t k = 0; k < CODE_COUNT; k++) {
        const char *s = hpfc_strerror(all_codes[k].code);
        CHECK(s != NULL && strcmp(s, unknown) != 0);
        for (size_t j = 0; j < k; j++)
            CHECK(strcmp(s, hpfc_strerror(all_codes[j].code)) != 0);
    }
    CHECK(strcmp(hpfc_strerror(-1), unknown) == 0);
    CHECK(strcmp(hpfc_strerror(5), unknown) == 0);
}

/* hpfc_status_name spells every code as the header does, and no other. */
static void check_status_names(void)
{
    for (size_t k = 0; k < CODE_COUNT; k++) {
        const char *name = hpfc_status_name(all_codes[k].code);
        if (strcmp(name, all_codes[k].name) != 0)
            fprintf(stderr, "hpfc_status_name(%d) is %s\n", all_codes[k].code, name);
        CHECK(strcmp(name, all_codes[k].name) == 0);
    }
    for (int code = -1; code < 100; code++)
        if (code_of_name(hpfc_status_name(code), strlen(hpfc_status_name(code))) != code)
            CHECK(strcmp(hpfc_status_name(code), "HPFC_E_UNKNOWN") == 0);
    CHECK_EQ_INT(code_of_name("HPFC_E_UNKNOWN", 14), -1);
}

/* ---- structs that grow ------------------------------------------------------ */

#define CANARY 0xA5
#define EXTRA 32

/* A struct of the library's with room past it, every byte a canary. */
typedef union grown {
    hpfc_tree_info tree;
    hpfc_file_info file;
    hpfc_level_info level;
    hpfc_section_info section;
    hpfc_labels_info labels;
    hpfc_geometry_info geometry;
    hpfc_feature feature;
    hpfc_attrs_info attrs;
    hpfc_edge_links_info edge_links;
    hpfc_build_params params;
    unsigned char bytes[sizeof(hpfc_file_info) + sizeof(hpfc_tree_info) + EXTRA];
} grown;

static void fill_canary(grown *g)
{
    memset(g, CANARY, sizeof *g);
}

/* An older caller (size bytes) gets the first size bytes of the full
 * answer and nothing past them; a newer one (full + EXTRA) gets the full
 * answer and zeros past it. */
static void check_out(const char *what, const void *full, size_t full_size, const grown *older,
                      size_t size, const grown *newer)
{
    size_t bad = 0;
    for (size_t k = 0; k < sizeof older->bytes; k++)
        bad += k < size ? older->bytes[k] != ((const unsigned char *)full)[k]
                        : older->bytes[k] != CANARY;
    for (size_t k = 0; k < full_size + EXTRA; k++)
        bad += k < full_size ? newer->bytes[k] != ((const unsigned char *)full)[k]
                             : newer->bytes[k] != 0;
    for (size_t k = full_size + EXTRA; k < sizeof newer->bytes; k++)
        bad += newer->bytes[k] != CANARY;
    if (bad)
        fprintf(stderr, "%s: %zu bytes wrong\n", what, bad);
    CHECK_EQ_INT(bad, 0);
}

/* A map whose polyline edge holds 200 shape points in a small area: the
 * leaf bound (max_leaf_points) changes its tree. */
static hpfc_graph *zigzag_map(void)
{
    hpfc_graph *g = NULL;
    uint32_t v[6];
    const int64_t corner[4][2] = {{0, 0}, {100000, 0}, {100000, 100000}, {0, 100000}};
    hpfc_graph_create(&g);
    for (int k = 0; k < 4; k++)
        hpfc_graph_add_vertex(g, corner[k][0], corner[k][1], &v[k]);
    for (int k = 0; k < 4; k++)
        hpfc_graph_add_edge(g, v[k], v[(k + 1) % 4], NULL, 0, NULL);
    int64_t xy[400];
    for (int k = 0; k < 200; k++) {
        xy[2 * k] = 10000 + 10 * (k + 1);
        xy[2 * k + 1] = 10005 + 5 * (k % 2);
    }
    hpfc_graph_add_vertex(g, 10000, 10000, &v[4]);
    hpfc_graph_add_vertex(g, 10000 + 10 * 201, 10000, &v[5]);
    hpfc_graph_add_edge(g, v[4], v[5], xy, 200, NULL);
    return g;
}

static int progress_calls;
static void count_progress(void *user, uint32_t level, uint64_t done, uint64_t total)
{
    (void)user, (void)level, (void)done, (void)total;
    progress_calls++;
}

static int same_tree(const hpfc_tree *a, const hpfc_tree *b)
{
    hpfc_tree_info ia, ib;
    hpfc_tree_get_info(a, &ia);
    hpfc_tree_get_info(b, &ib);
    return memcmp(&ia, &ib, sizeof ia) == 0;
}

/* Build parameters of an older caller: the fields past its size (here
 * max_leaf_points and the progress callback) take their defaults, whatever
 * the bytes there hold; a newer caller's unknown fields must be zero. */
static void check_build_params(const hpfc_graph *g, hpfc_tree **with_default)
{
    const size_t older = offsetof(hpfc_build_params, max_leaf_points);
    grown p;
    fill_canary(&p);
    hpfc_build_params_init(&p.params, older);
    hpfc_build_params full;
    hpfc_build_params_default(&full);
    CHECK(memcmp(&p.params, &full, older) == 0);
    CHECK_EQ_INT(p.bytes[older], CANARY);
    CHECK_EQ_INT(full.max_leaf_points, HPFC_DEFAULT_MAX_LEAF_POINTS);
    CHECK(full.progress == NULL);

    hpfc_tree *t_default = NULL, *t_short = NULL, *t_unbounded = NULL, *t = NULL;
    CHECK_EQ_INT(hpfc_build(g, &full, &t_default, NULL), HPFC_OK);
    p.params.max_leaf_points = 0; /* past the older caller's size: not read */
    p.params.progress = count_progress;
    progress_calls = 0;
    CHECK_EQ_INT(hpfc_build_sized(g, &p.params, older, &t_short, NULL), HPFC_OK);
    CHECK_EQ_INT(progress_calls, 0);
    hpfc_build_params unbounded = full;
    unbounded.max_leaf_points = 0;
    unbounded.progress = count_progress;
    CHECK_EQ_INT(hpfc_build(g, &unbounded, &t_unbounded, NULL), HPFC_OK);
    CHECK(progress_calls > 0);
    if (t_default && t_short && t_unbounded) {
        CHECK(same_tree(t_short, t_default));
        CHECK(!same_tree(t_unbounded, t_default)); /* the bound matters on this map */
    }
    /* a newer caller: its extra fields at 0 are fine, set ones refused */
    grown newer;
    memset(&newer, 0, sizeof newer);
    newer.params = full;
    CHECK_EQ_INT(hpfc_build_sized(g, &newer.params, sizeof full + 8, &t, NULL), HPFC_OK);
    if (t && t_default)
        CHECK(same_tree(t, t_default));
    hpfc_tree_free(t);
    t = NULL;
    newer.bytes[sizeof full + 3] = 1;
    CHECK_EQ_INT(hpfc_build_sized(g, &newer.params, sizeof full + 8, &t, NULL), HPFC_E_ARG);
    CHECK(t == NULL);
    hpfc_tree_free(t_short);
    hpfc_tree_free(t_unbounded);
    *with_default = t_default;
}

/* Write options of an older caller: fields past its size (layout,
 * geometry) are not read, even invalid ones. */
static void check_write_options(const hpfc_tree *t, const hpfc_graph *g)
{
    const size_t older = offsetof(hpfc_write_options, layout);
    hpfc_write_options short_opts = {.face_labels = 1, .layout = 99, .geometry = g};
    const hpfc_write_options same = {.face_labels = 1};
    uint8_t *a = NULL, *b = NULL;
    size_t na = 0, nb = 0;
    CHECK_EQ_INT(hpfc_tree_serialize_sized(t, &short_opts, older, &a, &na, NULL), HPFC_OK);
    CHECK_EQ_INT(hpfc_tree_serialize(t, &same, &b, &nb, NULL), HPFC_OK);
    CHECK(a && b && na == nb && memcmp(a, b, na) == 0);
    hpfc_free(a);
    hpfc_free(b);
    /* read in full, the invalid layout is refused */
    CHECK_EQ_INT(hpfc_tree_serialize(t, &short_opts, &a, &na, NULL), HPFC_E_ARG);
    CHECK(a == NULL);
    /* a newer caller's unknown option set: refused, not ignored */
    grown newer;
    memset(&newer, 0, sizeof newer);
    memcpy(&newer, &same, sizeof same);
    newer.bytes[sizeof same] = 1;
    CHECK_EQ_INT(hpfc_tree_serialize_sized(t, (const hpfc_write_options *)&newer,
                                           sizeof same + 8, &a, &na, NULL),
                 HPFC_E_ARG);
}

/* One feature along edge 0 (and over no face), with one attribute: the
 * FEAT, ATTR and EDGF sections of the structs' check, on a map of at most
 * 7 faces and 7 edges. */
typedef struct gis_sections {
    uint32_t face_start[8], edge_start[8], edge_feature[1], layer[1];
    int64_t fid[1];
    const char *layer_name[1], *key[1], *column[1];
    uint8_t type[1];
    hpfc_attr_value cell[1];
    hpfc_feature_table ft;
    hpfc_attr_table at;
    hpfc_edge_feature_table et;
} gis_sections;

static void gis_sections_make(gis_sections *s, uint32_t faces, uint32_t edges)
{
    memset(s, 0, sizeof *s);
    CHECK(faces < 8 && edges > 0 && edges < 8);
    for (uint32_t e = 1; e <= edges; e++)
        s->edge_start[e] = 1; /* edge 0: feature 0 */
    s->layer_name[0] = "layer";
    s->key[0] = "k";
    s->column[0] = "n";
    s->type[0] = HPFC_ATTR_INTEGER;
    s->cell[0] = (hpfc_attr_value){.type = HPFC_ATTR_INTEGER, .i = 42};
    s->fid[0] = 7;
    s->ft = (hpfc_feature_table){.feature_count = 1, .fid = s->fid, .layer = s->layer,
                                 .key_field = "name", .key = s->key, .layer_count = 1,
                                 .layer_name = s->layer_name, .face_count = faces,
                                 .face_start = s->face_start};
    s->at = (hpfc_attr_table){.feature_count = 1, .column_count = 1, .name = s->column,
                              .type = s->type, .cells = s->cell};
    s->et = (hpfc_edge_feature_table){.edge_count = edges, .feature_count = 1,
                                      .edge_start = s->edge_start,
                                      .edge_feature = s->edge_feature};
}

/* Every info call, older and newer callers against the full answer. */
static void check_infos(const hpfc_tree *t, const hpfc_graph *g)
{
    grown older, newer;
    hpfc_tree_info ti;
    hpfc_tree_get_info(t, &ti);
    size_t size = offsetof(hpfc_tree_info, vertices);
    fill_canary(&older), fill_canary(&newer);
    hpfc_tree_get_info_sized(t, &older.tree, size);
    hpfc_tree_get_info_sized(t, &newer.tree, sizeof ti + EXTRA);
    check_out("tree_info", &ti, sizeof ti, &older, size, &newer);

    gis_sections gs;
    gis_sections_make(&gs, (uint32_t)ti.faces, (uint32_t)ti.edges);
    const hpfc_write_options o = {.face_labels = 1, .geometry = g, .features = &gs.ft,
                                  .attributes = &gs.at, .edge_features = &gs.et};
    uint8_t *buf = NULL;
    size_t n = 0;
    hpfc_file *f = NULL;
    CHECK_EQ_INT(hpfc_tree_serialize(t, &o, &buf, &n, NULL), HPFC_OK);
    CHECK_EQ_INT(hpfc_open_memory(buf, n, 0, &f), HPFC_OK);
    if (!f) {
        hpfc_free(buf);
        return;
    }
    hpfc_file_info fi;
    hpfc_file_get_info(f, &fi);
    CHECK_EQ_INT(fi.format_major, HPFC_FORMAT_MAJOR); /* what the library writes */
    CHECK_EQ_INT(fi.format_minor, HPFC_FORMAT_MINOR);
    size = offsetof(hpfc_file_info, section_count);
    fill_canary(&older), fill_canary(&newer);
    hpfc_file_get_info_sized(f, &older.file, size);
    hpfc_file_get_info_sized(f, &newer.file, sizeof fi + EXTRA);
    check_out("file_info", &fi, sizeof fi, &older, size, &newer);

    hpfc_level_info li;
    CHECK_EQ_INT(hpfc_file_get_level(f, 0, &li), HPFC_OK);
    size = offsetof(hpfc_level_info, pool_offset);
    fill_canary(&older), fill_canary(&newer);
    CHECK_EQ_INT(hpfc_file_get_level_sized(f, 0, &older.level, size), HPFC_OK);
    CHECK_EQ_INT(hpfc_file_get_level_sized(f, 0, &newer.level, sizeof li + EXTRA), HPFC_OK);
    check_out("level_info", &li, sizeof li, &older, size, &newer);

    hpfc_section_info si;
    CHECK_EQ_INT(hpfc_file_get_section(f, 0, &si), HPFC_OK);
    size = offsetof(hpfc_section_info, length);
    fill_canary(&older), fill_canary(&newer);
    CHECK_EQ_INT(hpfc_file_get_section_sized(f, 0, &older.section, size), HPFC_OK);
    CHECK_EQ_INT(hpfc_file_get_section_sized(f, 0, &newer.section, sizeof si + EXTRA), HPFC_OK);
    check_out("section_info", &si, sizeof si, &older, size, &newer);

    hpfc_labels_info lb;
    CHECK_EQ_INT(hpfc_file_get_labels(f, &lb), HPFC_OK);
    size = offsetof(hpfc_labels_info, section_bytes);
    fill_canary(&older), fill_canary(&newer);
    CHECK_EQ_INT(hpfc_file_get_labels_sized(f, &older.labels, size), HPFC_OK);
    CHECK_EQ_INT(hpfc_file_get_labels_sized(f, &newer.labels, sizeof lb + EXTRA), HPFC_OK);
    check_out("labels_info", &lb, sizeof lb, &older, size, &newer);

    hpfc_geometry_info gi;
    CHECK_EQ_INT(hpfc_file_get_geometry(f, &gi), HPFC_OK);
    CHECK_EQ_INT(gi.points, 200);
    size = offsetof(hpfc_geometry_info, points);
    fill_canary(&older), fill_canary(&newer);
    CHECK_EQ_INT(hpfc_file_get_geometry_sized(f, &older.geometry, size), HPFC_OK);
    CHECK_EQ_INT(hpfc_file_get_geometry_sized(f, &newer.geometry, sizeof gi + EXTRA), HPFC_OK);
    check_out("geometry_info", &gi, sizeof gi, &older, size, &newer);

    hpfc_feature fe;
    CHECK_EQ_INT(hpfc_file_get_feature(f, 0, &fe), HPFC_OK);
    CHECK(fe.fid == 7 && fe.key_len == 1);
    size = offsetof(hpfc_feature, key);
    fill_canary(&older), fill_canary(&newer);
    CHECK_EQ_INT(hpfc_file_get_feature_sized(f, 0, &older.feature, size), HPFC_OK);
    CHECK_EQ_INT(hpfc_file_get_feature_sized(f, 0, &newer.feature, sizeof fe + EXTRA), HPFC_OK);
    check_out("feature", &fe, sizeof fe, &older, size, &newer);

    hpfc_attrs_info ai;
    CHECK_EQ_INT(hpfc_file_get_attrs(f, &ai), HPFC_OK);
    CHECK(ai.features == 1 && ai.columns == 1 && ai.string_bytes == 1);
    size = offsetof(hpfc_attrs_info, string_bytes);
    fill_canary(&older), fill_canary(&newer);
    CHECK_EQ_INT(hpfc_file_get_attrs_sized(f, &older.attrs, size), HPFC_OK);
    CHECK_EQ_INT(hpfc_file_get_attrs_sized(f, &newer.attrs, sizeof ai + EXTRA), HPFC_OK);
    check_out("attrs_info", &ai, sizeof ai, &older, size, &newer);

    hpfc_edge_links_info ei;
    CHECK_EQ_INT(hpfc_file_get_edge_links(f, &ei), HPFC_OK);
    CHECK(ei.edges == ti.edges && ei.features == 1 && ei.links == 1);
    size = offsetof(hpfc_edge_links_info, links);
    fill_canary(&older), fill_canary(&newer);
    CHECK_EQ_INT(hpfc_file_get_edge_links_sized(f, &older.edge_links, size), HPFC_OK);
    CHECK_EQ_INT(hpfc_file_get_edge_links_sized(f, &newer.edge_links, sizeof ei + EXTRA),
                 HPFC_OK);
    check_out("edge_links_info", &ei, sizeof ei, &older, size, &newer);

    /* hpfc_locate_out, an input struct of output arrays: an older caller's
     * struct ends before `feature`, so neither it nor `flags` is written */
    const int64_t x[1] = {50000}, y[1] = {50000};
    int64_t face[1] = {-7}, feature[1] = {-7};
    uint8_t flags[1] = {CANARY};
    const hpfc_locate_out lo = {.face = face, .feature = feature, .flags = flags};
    CHECK_EQ_INT(hpfc_locate_batch_sized(f, NULL, 1, x, y, NULL, &lo,
                                         offsetof(hpfc_locate_out, feature), NULL),
                 HPFC_OK);
    CHECK(face[0] > 0); /* the square's inside, not the unbounded face */
    CHECK(feature[0] == -7 && flags[0] == CANARY);
    CHECK_EQ_INT(hpfc_locate_batch(f, NULL, 1, x, y, NULL, &lo, NULL), HPFC_OK);
    CHECK(feature[0] == -1 && flags[0] != CANARY);
    hpfc_close(f);
    hpfc_free(buf);
}

/* ---- version --------------------------------------------------------------- */

/* The running library's number is the header's, and both agree with the
 * string "MAJOR.MINOR.PATCH". */
static void check_version(void)
{
    unsigned major = 0, minor = 0, patch = 0;
    int fields = sscanf(hpfc_version_string(), "%u.%u.%u", &major, &minor, &patch);
    CHECK_EQ_INT(fields, 3);
    CHECK(strcmp(hpfc_version_string(), HPFC_VERSION_STRING) == 0);
    CHECK_EQ_INT(hpfc_version_number(), HPFC_VERSION_NUMBER);
    CHECK_EQ_INT(hpfc_version_number(), major * 10000 + minor * 100 + patch);
    CHECK_EQ_INT(major, HPFC_VERSION_MAJOR);
    CHECK_EQ_INT(minor, HPFC_VERSION_MINOR);
    CHECK_EQ_INT(patch, HPFC_VERSION_PATCH);
    hpfc_free(NULL); /* accepts NULL, as free() */
}

static void check_sized_structs(void)
{
    hpfc_graph *g = zigzag_map();
    hpfc_tree *t = NULL;
    CHECK_EQ_INT(hpfc_graph_validate(g, NULL), HPFC_OK);
    check_build_params(g, &t);
    if (t) {
        check_write_options(t, g);
        check_infos(t, g);
    }
    hpfc_tree_free(t);
    hpfc_graph_free(g);
}

int main(void)
{
    const char *dir = getenv("HPFC_SPEC_DIR");
    if (!dir) {
        fprintf(stderr, "HPFC_SPEC_DIR is not set\n");
        return EXIT_FAILURE;
    }
    char *spec = read_text(dir, "hpfc-format.md");
    char *pfc = read_text(dir, "pfc-format.md");
    check_spec_table(spec);
    check_citations(spec, "hpfc-format.md");
    check_citations(pfc, "pfc-format.md");
    check_strerror();
    check_status_names();
    check_sized_structs();
    check_version();
    free(spec);
    free(pfc);
    return check_report("api");
}
