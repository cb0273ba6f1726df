/*
 * read_gis: hpfc-pack's GIS input (hpfc-pack/gis_input.h) on a dataset held
 * in memory, then, for small maps, the rest of a pack: the build, the
 * features of the faces (face_witness.h, gis_features.h) and the file that
 * records them.
 *
 * The input is written to a GDAL in-memory file (/vsimem/) and read with
 * gis_read_graph, so any driver that recognises the bytes by their content
 * takes part (GeoJSON, TopoJSON, ESRI JSON, CSV with WKT, GML, KML,
 * FlatGeobuf, GeoPackage, ...). An input that starts with the byte 0x01,
 * which starts no dataset, carries an options byte after it; the dataset
 * follows. Without it the options are hpfc-pack's defaults:
 *
 *   bit 0  --vertices junctions (else all)
 *   bit 1  --invalid node (else reject)
 *   bit 2  --wrap-dateline no (refuse wrapping rings; else cut them)
 *   bit 3  --projection none (else auto)
 *   bit 4  --key name
 *   bit 5  the in-memory file is named *.csv (GDAL's CSV driver goes by the
 *          name; the others by content)
 *   bit 6  --fields all
 *
 * Oracle: gis_read_graph returns 0 with a graph or 1 with a one-line
 * message and no graph; the graph passes hpfc_graph_validate (the promise
 * of gis_input.h: the builder always receives a planar graph) and the shape
 * checks of input.h, at the unit gis_info reports. Reading again with
 * GEOS's polygon checks on a second thread (polygon_checks.h) gives the
 * same outcome: the same message on failure (GDAL's refusal to open it
 * excepted, whose detail depends on the process's past), else the same
 * graph, count of invalid polygons and list of them. When the map has at most
 * PACK_MAX_EDGES edges it is built, serialised, reopened with checksums,
 * and its faces are linked to the polygon features as hpfc-pack links them
 * (leaf_crossings_collect, the tree freed, gis_features_link): as many faces
 * as the builder counted, every face's features exist, and the file
 * rewritten with them (hpfc_file_serialize) records exactly that table, the
 * attributes (ATTR) and the edges' features (EDGF). The walk over the
 * faces and every face's exact witness agree (no conflict, noded or not:
 * the parts are recorded as they lie in the map), every face has a
 * witness, and the witness method alone gives the very same table.
 */
#include <cpl_vsi.h>

#include "gis_features.h"
#include "gis_input.h"
#include "input.h"

enum { PACK_MAX_EDGES = 200, OPTIONS_MARK = 0x01 };

static const char *const fuzz_paths[2] = {"/vsimem/read_gis_input", "/vsimem/read_gis_input.csv"};

static void options_from_byte(uint8_t b, gis_options *o, const char **path)
{
    memset(o, 0, sizeof *o);
    *path = fuzz_paths[b >> 5 & 1];
    o->vertex_model = b & 1 ? GIS_VERTICES_JUNCTIONS : GIS_VERTICES_ALL;
    o->invalid_mode = b & 2 ? GIS_INVALID_NODE : GIS_INVALID_REJECT;
    o->dateline = b & 4 ? GIS_DATELINE_REJECT : GIS_DATELINE_CUT;
    o->projection = b & 8 ? "none" : "auto";
    o->key_field = b & 16 ? "name" : NULL;
    o->fields = b & 64 ? "all" : NULL;
}

/* GDAL's open failures carry GDAL's last error, which depends on what the
 * process did before: a driver may say why only the first time (the
 * GPSBabel driver's "posix_spawnp() failed", then nothing). Two reads of
 * one input fail alike when the messages are the same, or both are GDAL's
 * refusal to open it. */
static bool same_failure(const char *a, const char *b)
{
    static const char *const refused[] = {"not a vector dataset GDAL can read",
                                          "unknown format: not a vector dataset GDAL can read"};
    bool a_refused = false, b_refused = false;
    for (size_t k = 0; k < 2; k++) {
        a_refused |= strncmp(a, refused[k], strlen(refused[k])) == 0;
        b_refused |= strncmp(b, refused[k], strlen(refused[k])) == 0;
    }
    return strcmp(a, b) == 0 || (a_refused && b_refused);
}

/* Reads the in-memory dataset; 0 with *g, or 1 (checked message in err,
 * no graph). */
static int read_graph(const char *path, const gis_options *o, hpfc_graph **g, gis_info *info,
                      char err[512])
{
    memset(err, 'x', 512);
    *g = NULL;
    int st = gis_read_graph(path, o, g, info, err, 512);
    FUZZ_CHECK(st == 0 || st == 1);
    FUZZ_CHECK((st == 0) == (*g != NULL));
    FUZZ_CHECK(memchr(err, '\0', 512) != NULL);
    if (st) {
        FUZZ_CHECK(err[0] != '\0');
        FUZZ_CHECK(strpbrk(err, "\r\n") == NULL);
    }
    return st;
}

/* The ATTR and EDGF sections read back are the tables written. */
static void check_recorded_attributes(const hpfc_file *f, const hpfc_attr_table *at,
                                      const gis_feature_table *ft)
{
    hpfc_attrs_info ai;
    FUZZ_CHECK(hpfc_file_get_attrs(f, &ai) == HPFC_OK);
    FUZZ_CHECK(ai.features == at->feature_count && ai.columns == at->column_count);
    for (uint32_t k = 0; k < at->feature_count; k++)
        for (uint32_t c = 0; c < at->column_count; c++) {
            hpfc_attr_value v;
            const hpfc_attr_value *w = &at->cells[(size_t)k * at->column_count + c];
            FUZZ_CHECK(hpfc_file_get_attr_value(f, k, c, &v) == HPFC_OK && v.type == w->type);
            FUZZ_CHECK(v.type != HPFC_ATTR_INTEGER || v.i == w->i);
            FUZZ_CHECK(v.type != HPFC_ATTR_REAL || memcmp(&v.r, &w->r, sizeof v.r) == 0);
            FUZZ_CHECK(v.type != HPFC_ATTR_STRING ||
                       (v.len == w->len && memcmp(v.s, w->s, v.len) == 0));
        }
    hpfc_edge_links_info ei;
    FUZZ_CHECK(hpfc_file_get_edge_links(f, &ei) == HPFC_OK);
    FUZZ_CHECK(ei.edges == ft->edge_count && ei.links == ft->edge_start[ft->edge_count] &&
               ei.features == ft->table.feature_count);
    for (uint32_t e = 0; e < ft->edge_count; e++) {
        uint32_t n;
        hpfc_id feature;
        FUZZ_CHECK(hpfc_edge_feature_count(f, e, &n) == HPFC_OK);
        FUZZ_CHECK(n == ft->edge_start[e + 1] - ft->edge_start[e]);
        for (uint32_t k = 0; k < n; k++) {
            FUZZ_CHECK(hpfc_edge_feature_id(f, e, k, &feature) == HPFC_OK);
            FUZZ_CHECK(feature == ft->edge_feature[ft->edge_start[e] + k]);
        }
    }
}

/* The FEAT section read back is the table that was written. */
static void check_recorded_features(const hpfc_file *f, const gis_feature_table *ft)
{
    hpfc_features_info fi;
    FUZZ_CHECK(hpfc_file_get_features(f, &fi) == HPFC_OK);
    FUZZ_CHECK(fi.features == ft->table.feature_count && fi.faces == ft->table.face_count);
    for (uint32_t face = 0; face < fi.faces; face++) {
        uint32_t n;
        FUZZ_CHECK(hpfc_face_feature_count(f, face, &n) == HPFC_OK);
        FUZZ_CHECK(n == ft->face_start[face + 1] - ft->face_start[face]);
        for (uint32_t k = 0; k < n; k++) {
            hpfc_id feature;
            FUZZ_CHECK(hpfc_face_feature_id(f, face, k, &feature) == HPFC_OK);
            FUZZ_CHECK(feature == ft->face_feature[ft->face_start[face] + k]);
        }
    }
}

/* Links the faces of the serialised map f to the features as hpfc-pack
 * does (freeing the tree first), writes the map again with them and reads
 * them back. */
static void pack_features(const hpfc_graph *g, hpfc_tree *t, const hpfc_file *f,
                          const gis_info *info)
{
    hpfc_tree_info ti; /* the builder's count: F = E - V + 1 + C */
    hpfc_tree_get_info(t, &ti);
    leaf_crossings lc;
    FUZZ_CHECK(leaf_crossings_collect(t, f, &lc) == HPFC_OK);
    hpfc_tree_free(t);
    gis_feature_table ft = {0}, fw = {0};
    char err[256];
    FUZZ_CHECK(gis_features_link_method(info->polygons, g, &lc, f, NULL, 0, 1, &ft, err, sizeof err) == 0);
    FUZZ_CHECK(ft.conflicts == 0);
    FUZZ_CHECK(ft.faces_without_witness == 0);
    /* the witness alone gives the very same table, checked on 3 threads */
    FUZZ_CHECK(gis_features_link_method(info->polygons, g, &lc, f, NULL, 1, 3, &fw, err, sizeof err) == 0);
    FUZZ_CHECK(fw.table.face_count == ft.table.face_count);
    FUZZ_CHECK(memcmp(fw.face_start, ft.face_start,
                      (ft.table.face_count + 1) * sizeof *ft.face_start) == 0);
    FUZZ_CHECK(memcmp(fw.face_feature, ft.face_feature,
                      ft.face_start[ft.table.face_count] * sizeof *ft.face_feature) == 0);
    gis_feature_table_free(&fw);
    leaf_crossings_free(&lc);
    uint32_t features = gis_features_count(info->polygons);
    FUZZ_CHECK(ft.table.feature_count == features && ft.table.face_count == ti.faces);
    for (uint32_t face = 0; face < ft.table.face_count; face++)
        for (uint32_t k = ft.face_start[face]; k < ft.face_start[face + 1]; k++)
            FUZZ_CHECK(ft.face_feature[k] < features);

    hpfc_attr_table at;
    FUZZ_CHECK(gis_attrs_table(info->attrs, &at) == 0 && at.feature_count == features);
    hpfc_edge_feature_table et = {.edge_count = ft.edge_count, .feature_count = features,
                                  .edge_start = ft.edge_start, .edge_feature = ft.edge_feature};
    hpfc_write_options wopts = {.crs = info->crs, .features = &ft.table, .attributes = &at,
                                .edge_features = &et};
    uint8_t *with_feat = NULL;
    size_t with_size = 0;
    FUZZ_CHECK(hpfc_file_serialize(f, &wopts, &with_feat, &with_size, NULL) == HPFC_OK);
    hpfc_file *f2 = NULL;
    FUZZ_CHECK(hpfc_open_memory(with_feat, with_size, 0, &f2) == HPFC_OK);
    check_recorded_features(f2, &ft);
    check_recorded_attributes(f2, &at, &ft);
    hpfc_close(f2);
    hpfc_free(with_feat);
    gis_feature_table_free(&ft);
}

/* Builds and serialises the map with a small root image, as a pack does. */
static void pack(const hpfc_graph *g, const gis_info *info)
{
    hpfc_build_params params;
    hpfc_build_params_default(&params);
    params.root_cols = params.root_rows = 4;
    hpfc_tree *t = NULL;
    int st = hpfc_build(g, &params, &t, NULL);
    /* a valid graph builds, unless it needs more pixels or levels than allowed */
    FUZZ_CHECK(st == HPFC_OK || st == HPFC_E_LIMIT || st == HPFC_E_TOO_MANY_PIXELS ||
               st == HPFC_E_NOMEM);
    if (st)
        return;
    uint8_t *bytes = NULL;
    size_t size = 0;
    hpfc_file *f = NULL;
    hpfc_write_options wopts = {.crs = info->crs};
    FUZZ_CHECK(hpfc_tree_serialize(t, &wopts, &bytes, &size, NULL) == HPFC_OK);
    FUZZ_CHECK(hpfc_open_memory(bytes, size, 0, &f) == HPFC_OK);
    if (gis_features_count(info->polygons) > 0)
        pack_features(g, t, f, info); /* frees t */
    else
        hpfc_tree_free(t);
    hpfc_close(f);
    hpfc_free(bytes);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    gis_options o;
    const char *path;
    bool has_options = size >= 2 && data[0] == OPTIONS_MARK;
    options_from_byte(has_options ? data[1] : 0, &o, &path);
    if (has_options) {
        data += 2;
        size -= 2;
    }
    /* GDAL reads the bytes in place (no copy, not freed by GDAL) */
    VSILFILE *mem = VSIFileFromMemBuffer(path, (GByte *)data, (vsi_l_offset)size, FALSE);
    FUZZ_CHECK(mem != NULL);
    VSIFCloseL(mem);

    hpfc_graph *g = NULL, *again = NULL;
    gis_info info, info2;
    char err[512], err2[512];
    /* read again with GEOS's polygon checks on a second thread: the same
     * outcome, message or graph and report */
    gis_options threaded = o;
    threaded.threads = 2;
    int st = read_graph(path, &o, &g, &info, err);
    FUZZ_CHECK(read_graph(path, &threaded, &again, &info2, err2) == st);
    if (st)
        FUZZ_CHECK(same_failure(err, err2));
    if (st == 0) {
        fuzz_check_graph(g);
        FUZZ_CHECK(hpfc_graph_validate(g, NULL) == HPFC_OK);
        FUZZ_CHECK(hpfc_graph_unit_exp10(g) == info.unit_exp10);
        FUZZ_CHECK(fuzz_same_graph(g, again));
        FUZZ_CHECK(info.invalid_noded == info2.invalid_noded);
        FUZZ_CHECK(strcmp(info.repaired, info2.repaired) == 0);
        hpfc_graph_free(again);
        gis_info_free(&info2);
        if (hpfc_graph_edge_count(g) <= PACK_MAX_EDGES)
            pack(g, &info);
        hpfc_graph_free(g);
        gis_info_free(&info);
    }
    VSIUnlink(path);
    return 0;
}
