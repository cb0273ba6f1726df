/*
 * export_gis.c: hpfc-inspect --export / --export-faces through GDAL/OGR
 * (interfaces §5). The geometry is the library's exact rings
 * (hpfc_shapes_*), turned into user coordinates (lattice * 10^unit_exp10)
 * and, for a map that hpfc-pack projected from longitude and latitude,
 * projected back with the inverse of the projection the CRS section
 * records, so the output lies in the source SRS and opens on top of the
 * original. Each feature keeps its fid (the OGR FID, and a "fid" field
 * where the driver has no FID column of that name), its key and its stored
 * attributes. The shapes, fields and SRS are common/ogr_shapes.c's, which
 * the GDAL driver reads with: an export and a driver read agree.
 */
#include "export_gis.h"

#include <errno.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_string.h>
#include <cpl_vsi.h>
#include <gdal.h>
#include <ogr_api.h>
#include <ogr_srs_api.h>

#include "atomic_output.h"
#include "clock.h"
#include "hpfc.h"
#include "jsonw.h"
#include "ogr_shapes.h"
#include "open_input.h"

typedef struct exporter {
    const gis_export_options *o;
    const hpfc_file *f;         /* o->open, or owned */
    hpfc_file *owned;           /* opened here */
    hpfc_file_info fi;
    hpfc_shapes *shapes;
    ogr_shapes g;               /* the SRS, the plan back to lon/lat, the shapes made */
    int g_ready;
    GDALDriverH driver;
    GDALDatasetH ds;
    int fid_column;             /* the driver's FID column is named "fid" */
    uint64_t written, empty;
    char why[600];
} exporter;

static int fail(exporter *x, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

static int fail(exporter *x, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(x->why, sizeof x->why, fmt, ap);
    va_end(ap);
    return 1;
}

/* GDAL's last message, or `fallback`. */
static const char *gdal_reason(const char *fallback)
{
    const char *m = CPLGetLastErrorMsg();
    return m && *m ? m : fallback;
}

/* ---- driver ---------------------------------------------------------------------- */

static int can_write_vectors(GDALDriverH d)
{
    return GDALGetMetadataItem(d, GDAL_DCAP_VECTOR, NULL) &&
           GDALGetMetadataItem(d, GDAL_DCAP_CREATE, NULL);
}

/* Whether `ext` is one of the driver's extensions (a space-separated list). */
static int has_extension(GDALDriverH d, const char *ext)
{
    const char *list = GDALGetMetadataItem(d, GDAL_DMD_EXTENSIONS, NULL);
    if (!list)
        list = GDALGetMetadataItem(d, GDAL_DMD_EXTENSION, NULL);
    if (!list)
        return 0;
    size_t n = strlen(ext);
    for (const char *p = list; *p;) {
        while (*p == ' ')
            p++;
        size_t len = strcspn(p, " ");
        if (len == n && strncasecmp(p, ext, n) == 0)
            return 1;
        p += len;
    }
    return 0;
}

/* -f NAME, or the first writable vector driver that claims OUT's
 * extension (GeoJSON for .json, as ogr2ogr). */
static int choose_driver(exporter *x)
{
    const char *name = x->o->driver;
    if (name) {
        x->driver = GDALGetDriverByName(name);
        if (!x->driver)
            return fail(x, "-f %s: no such GDAL driver", name);
        if (!can_write_vectors(x->driver))
            return fail(x, "-f %s: the driver cannot create vector datasets", name);
        return 0;
    }
    const char *base = strrchr(x->o->output, '/');
    base = base ? base + 1 : x->o->output;
    const char *dot = strrchr(base, '.');
    if (!dot || !dot[1])
        return fail(x, "%s: no extension to choose a driver by; name one with -f (GPKG, "
                       "GeoJSON, FlatGeobuf, \"ESRI Shapefile\", ...)",
                    x->o->output);
    const char *ext = dot + 1;
    if (strcasecmp(ext, "json") == 0 || strcasecmp(ext, "geojson") == 0)
        x->driver = GDALGetDriverByName("GeoJSON");
    for (int k = 0; !x->driver && k < GDALGetDriverCount(); k++) {
        GDALDriverH d = GDALGetDriver(k);
        if (can_write_vectors(d) && has_extension(d, ext))
            x->driver = d;
    }
    if (!x->driver)
        return fail(x, "%s: no GDAL vector driver writes .%s files; name one with -f",
                    x->o->output, ext);
    return 0;
}

/* ---- features ---------------------------------------------------------------------- */

/* A NUL-terminated copy of n bytes (names and strings of the file). */
static char *dup_n(const char *s, size_t n)
{
    char *d = malloc(n + 1);
    if (d) {
        memcpy(d, s, n);
        d[n] = '\0';
    }
    return d;
}

/* Fails with ogr_shapes' reason. */
static int shapes_failed(exporter *x)
{
    return fail(x, "%s", x->g.why);
}

static int add_field(exporter *x, OGRLayerH layer, const char *name, OGRFieldType t, int *index)
{
    OGRFieldDefnH fd = OGR_Fld_Create(name, t);
    OGRErr e = fd ? OGR_L_CreateField(layer, fd, TRUE) : OGRERR_NOT_ENOUGH_MEMORY;
    if (fd)
        OGR_Fld_Destroy(fd);
    if (e != OGRERR_NONE)
        return fail(x, "cannot create field '%s': %s", name, gdal_reason("refused"));
    *index = OGR_FD_GetFieldCount(OGR_L_GetLayerDefn(layer)) - 1;
    return 0;
}

/* A source layer's fields (ogr_shapes_fields: fid unless the driver's FID
 * column has that name, the key, every stored attribute), created in
 * order from the layer's first field. */
typedef struct columns {
    ogr_shapes_field *fields;
    size_t count;
    int first;
} columns;

static int make_fields(exporter *x, OGRLayerH layer, columns *c)
{
    memset(c, 0, sizeof *c);
    if (ogr_shapes_fields(&x->g, !x->fid_column, &c->fields, &c->count))
        return shapes_failed(x);
    c->first = OGR_FD_GetFieldCount(OGR_L_GetLayerDefn(layer));
    for (size_t k = 0; k < c->count; k++) {
        int index;
        if (add_field(x, layer, c->fields[k].name, c->fields[k].type, &index))
            return 1;
    }
    return 0;
}

static OGRLayerH create_layer(exporter *x, const char *name, OGRwkbGeometryType t)
{
    OGRLayerH layer = GDALDatasetCreateLayer(x->ds, name, x->g.srs, t, NULL);
    if (!layer)
        fail(x, "cannot create layer '%s': %s", name, gdal_reason("refused"));
    return layer;
}

static int write_feature(exporter *x, OGRLayerH layer, const columns *c, uint32_t k,
                         const hpfc_feature *feat)
{
    OGRGeometryH g;
    if (ogr_shapes_feature_geometry(&x->g, k, &g))
        return shapes_failed(x);
    OGRFeatureH ft = OGR_F_Create(OGR_L_GetLayerDefn(layer));
    if (!ft) {
        OGR_G_DestroyGeometry(g);
        return fail(x, "out of memory");
    }
    OGR_F_SetFID(ft, feat->fid);
    if (g)
        OGR_F_SetGeometryDirectly(ft, g);
    else
        x->empty++;
    int r = ogr_shapes_fill(&x->g, ft, c->first, c->fields, c->count, k, feat) ? shapes_failed(x)
                                                                                : 0;
    if (!r && OGR_L_CreateFeature(layer, ft) != OGRERR_NONE)
        r = fail(x, "feature %u (fid %lld): %s", k, (long long)feat->fid,
                 gdal_reason("the driver refused it"));
    OGR_F_Destroy(ft);
    x->written += !r;
    return r;
}

/* Layer l's features (FEAT's layer l, with its name) as an output layer
 * of geometry type `type`: 0, or 1 after fail(). */
static int write_layer(exporter *x, const hpfc_features_info *fi, uint32_t l,
                       OGRwkbGeometryType type)
{
    const char *name;
    size_t len;
    int st = hpfc_layer_name(x->f, l, &name, &len);
    if (st)
        return fail(x, "layer %u: %s", l, hpfc_strerror(st));
    char *lname = dup_n(name, len);
    if (!lname)
        return fail(x, "out of memory");
    OGRLayerH layer = create_layer(x, lname[0] ? lname : "features", type);
    free(lname);
    columns c;
    int r = !layer || make_fields(x, layer, &c);
    /* one transaction a layer (GeoPackage: a commit per feature otherwise);
     * drivers without transactions write as they go */
    int tx = layer && !r && OGR_L_StartTransaction(layer) == OGRERR_NONE;
    for (uint32_t k = 0; k < fi->features && !r; k++) {
        hpfc_feature feat;
        if ((st = hpfc_file_get_feature(x->f, k, &feat)))
            r = fail(x, "feature %u: %s", k, hpfc_strerror(st));
        else if (feat.layer == l)
            r = write_feature(x, layer, &c, k, &feat);
    }
    if (tx && !r && OGR_L_CommitTransaction(layer) != OGRERR_NONE)
        r = fail(x, "cannot commit layer %u: %s", l, gdal_reason("refused"));
    if (layer)
        ogr_shapes_fields_free(c.fields, c.count);
    return r ? 1 : 0;
}

/* Every feature, layer by layer, each layer typed from its features' row
 * lengths (one pass for all layers).
 * write_features and write_faces stay out of line: each is a stage that
 * bench/scaling.py's smoke counts by its calls in a profile. */
__attribute__((noinline)) static int write_features(exporter *x)
{
    hpfc_features_info fi;
    int st = hpfc_file_get_features(x->f, &fi);
    if (st == HPFC_E_NO_SECTION)
        return fail(x, "the file has no features (FEAT section); --export-faces writes its "
                       "faces");
    if (st)
        return fail(x, "features: %s", hpfc_strerror(st));
    OGRwkbGeometryType *types = malloc((fi.layers ? fi.layers : 1) * sizeof *types);
    if (!types)
        return fail(x, "out of memory");
    int r = ogr_shapes_layer_types(&x->g, types, NULL, fi.layers) ? fail(x, "%s", x->g.why) : 0;
    for (uint32_t l = 0; l < fi.layers && !r; l++)
        r = write_layer(x, &fi, l, types[l]);
    free(types);
    return r;
}

/* ---- faces ------------------------------------------------------------------------- */

/* Every bounded face as its polygon (the unbounded face has no outer ring),
 * with its id and its features' fids and keys. */
__attribute__((noinline)) static int write_faces(exporter *x)
{
    OGRLayerH layer = create_layer(x, "faces", wkbPolygon);
    if (!layer)
        return 1;
    int face_field = -1, count_field = -1, fids_field = -1, keys_field = -1;
    hpfc_features_info fi;
    int have_features = hpfc_file_get_features(x->f, &fi) == HPFC_OK;
    if ((!x->fid_column && add_field(x, layer, "face", OFTInteger64, &face_field)) ||
        (have_features && (add_field(x, layer, "features", OFTInteger, &count_field) ||
                           add_field(x, layer, "fids", OFTString, &fids_field))) ||
        (have_features && fi.key_field && add_field(x, layer, "keys", OFTString, &keys_field)))
        return 1;
    int tx = OGR_L_StartTransaction(layer) == OGRERR_NONE;
    uint64_t faces = hpfc_shapes_face_count(x->shapes);
    for (uint64_t face = 1; face < faces; face++) {
        OGRGeometryH g = ogr_shapes_face_geometry(&x->g, face);
        if (!g)
            return shapes_failed(x);
        OGRFeatureH ft = OGR_F_Create(OGR_L_GetLayerDefn(layer));
        if (!ft) {
            OGR_G_DestroyGeometry(g);
            return fail(x, "out of memory");
        }
        OGR_F_SetFID(ft, (GIntBig)face);
        OGR_F_SetGeometryDirectly(ft, g);
        if (face_field >= 0)
            OGR_F_SetFieldInteger64(ft, face_field, (GIntBig)face);
        int r = have_features && ogr_shapes_face_features(&x->g, ft, face, count_field,
                                                          fids_field, keys_field)
                    ? shapes_failed(x)
                    : 0;
        if (!r && OGR_L_CreateFeature(layer, ft) != OGRERR_NONE)
            r = fail(x, "face %llu: %s", (unsigned long long)face,
                     gdal_reason("the driver refused it"));
        OGR_F_Destroy(ft);
        if (r)
            return 1;
        x->written++;
    }
    if (tx && OGR_L_CommitTransaction(layer) != OGRERR_NONE)
        return fail(x, "cannot commit the faces: %s", gdal_reason("refused"));
    return 0;
}

/* ---- computed layers ---------------------------------------------------------------- */

/* A gis_custom_layer: one feature an item, its value in the one field. */
static int write_custom(exporter *x)
{
    const gis_custom_layer *c = x->o->custom;
    OGRLayerH layer = create_layer(x, c->name, c->lines ? wkbMultiLineString : wkbMultiPolygon);
    int field = -1;
    if (!layer || (c->field && add_field(x, layer, c->field, OFTString, &field)))
        return 1;
    int tx = OGR_L_StartTransaction(layer) == OGRERR_NONE;
    for (size_t k = 0; k < c->count; k++) {
        hpfc_polygons p;
        const char *value = NULL;
        size_t len = 0;
        int st = c->item(c->ctx, x->shapes, k, &p, &value, &len);
        if (st)
            return fail(x, "%s %zu: %s", c->name, k, hpfc_strerror(st));
        OGRGeometryH g = c->lines ? ogr_shapes_multiline(&x->g, &p)
                                  : ogr_shapes_multipolygon(&x->g, &p);
        OGRFeatureH ft = g ? OGR_F_Create(OGR_L_GetLayerDefn(layer)) : NULL;
        if (!ft) {
            OGR_G_DestroyGeometry(g);
            return g ? fail(x, "out of memory") : shapes_failed(x);
        }
        OGR_F_SetGeometryDirectly(ft, g);
        int r = 0;
        if (field >= 0 && value) {
            char *v = dup_n(value, len);
            if (v)
                OGR_F_SetFieldString(ft, field, v);
            else
                r = fail(x, "out of memory");
            free(v);
        }
        if (!r && OGR_L_CreateFeature(layer, ft) != OGRERR_NONE)
            r = fail(x, "%s %zu: %s", c->name, k, gdal_reason("the driver refused it"));
        OGR_F_Destroy(ft);
        if (r)
            return 1;
        x->written++;
    }
    if (tx && OGR_L_CommitTransaction(layer) != OGRERR_NONE)
        return fail(x, "cannot commit %s: %s", c->name, gdal_reason("refused"));
    return 0;
}

/* ---- atomic output ------------------------------------------------------------------- */

static int write_dataset(exporter *x, const char *path)
{
    CPLErrorReset();
    x->ds = GDALCreate(x->driver, path, 0, 0, 0, GDT_Unknown, NULL);
    if (!x->ds)
        return fail(x, "%s: cannot create: %s", x->o->output, gdal_reason("refused"));
    x->fid_column = strcmp(GDALGetDriverShortName(x->driver), "GPKG") == 0;
    int r = x->o->custom ? write_custom(x) : x->o->faces ? write_faces(x) : write_features(x);
    CPLErrorReset();
    GDALClose(x->ds);
    x->ds = NULL;
    if (!r && CPLGetLastErrorType() >= CE_Failure)
        r = fail(x, "%s: %s", x->o->output, gdal_reason("cannot write"));
    return r;
}

/* Copies every file the driver made in `mem` beside OUT, each through
 * common/atomic_output.h (a Shapefile's .shp, .shx, .dbf and .prj are
 * replaced one by one, each whole). */
static int copy_out(exporter *x, const char *mem)
{
    const char *out = x->o->output, *slash = strrchr(out, '/');
    size_t dlen = slash ? (size_t)(slash - out) + 1 : 0;
    char **names = VSIReadDir(mem);
    int r = 0, copied = 0;
    for (int i = 0; names && names[i] && !r; i++) {
        if (!strcmp(names[i], ".") || !strcmp(names[i], ".."))
            continue;
        char *from = CPLStrdup(CPLFormFilename(mem, names[i], NULL));
        size_t n = dlen + strlen(names[i]) + 1;
        char *to = malloc(n), why[ATOMIC_WHY];
        vsi_l_offset len = 0;
        GByte *bytes;
        if (!to) {
            r = fail(x, "out of memory");
        } else if (snprintf(to, n, "%.*s%s", (int)dlen, out, names[i]) < 0 ||
                   !(bytes = VSIGetMemFileBuffer(from, &len, FALSE))) { /* not a file */
            r = fail(x, "%s: the driver made a directory, %s (name OUT with the driver's "
                        "extension)", out, names[i]);
        } else if (atomic_output_write(to, bytes, (size_t)len, why)) {
            r = fail(x, "%s", why);
        } else {
            copied++;
        }
        free(to);
        CPLFree(from);
    }
    CSLDestroy(names);
    if (!r && !copied)
        r = fail(x, "%s: the driver wrote no file", out);
    return r;
}

/* The driver writes into memory (/vsimem), and the files it made are then
 * written out by common/atomic_output.h. Writing through the driver to
 * disk would trust it with write errors, and some drivers ignore them:
 * GeoJSON and FlatGeobuf, at a full disk, close a truncated file and
 * report success. The cost is the output's size in memory. */
static int write_atomically(exporter *x)
{
    char why[ATOMIC_WHY], mem[96];
    /* a read-only directory fails before the work */
    if (atomic_output_check(x->o->output, why))
        return fail(x, "%s", why);
    const char *base = strrchr(x->o->output, '/');
    base = base ? base + 1 : x->o->output;
    snprintf(mem, sizeof mem, "/vsimem/hpfc-export-%ld-%p", (long)getpid(), (void *)x);
    VSIMkdir(mem, 0700);
    char *path = CPLStrdup(CPLFormFilename(mem, base, NULL));
    int r = write_dataset(x, path);
    if (!r)
        r = copy_out(x, mem);
    CPLFree(path);
    VSIRmdirRecursive(mem);
    return r;
}

/* ---- the run ------------------------------------------------------------------------- */

static void print_report(const exporter *x, FILE *out, double seconds)
{
    const char *drv = GDALGetDriverShortName(x->driver);
    if (x->o->json) {
        jsonw w;
        jsonw_init(&w, out);
        jsonw_object_begin(&w, NULL);
        jsonw_string(&w, "file", x->o->file);
        jsonw_string(&w, "output", x->o->output);
        jsonw_string(&w, "driver", drv);
        jsonw_string(&w, "what", x->o->custom ? x->o->custom->name : x->o->faces ? "faces" : "features");
        jsonw_string(&w, "srs", x->g.srs_name);
        jsonw_bool(&w, "projected_back", x->g.plan != NULL);
        jsonw_u64(&w, "written", x->written);
        jsonw_u64(&w, "polygons", x->g.polygons);
        jsonw_u64(&w, "rings", x->g.rings);
        jsonw_u64(&w, "lines", x->g.lines);
        jsonw_u64(&w, "points", x->g.points);
        jsonw_u64(&w, "without_geometry", x->empty);
        jsonw_double(&w, "seconds", seconds, 3);
        jsonw_object_end(&w);
        jsonw_finish(&w);
    } else {
        fprintf(out,
                "%s: %llu %s (%llu polygons, %llu rings, %llu lines, %llu points), %s, SRS %s%s\n",
                x->o->output, (unsigned long long)x->written,
                x->o->custom ? x->o->custom->name : x->o->faces ? "faces" : "features",
                (unsigned long long)x->g.polygons, (unsigned long long)x->g.rings,
                (unsigned long long)x->g.lines, (unsigned long long)x->g.points, drv,
                x->g.srs_name, x->g.plan ? " (projected back)" : "");
    }
}

static int run(exporter *x)
{
    int st = HPFC_OK;
    errno = 0;
    if (x->o->open)
        x->f = x->o->open;
    else if ((st = open_input(x->o->file, &x->owned)))
        return fail(x, "%s: %s", x->o->file,
                    st == HPFC_E_IO && errno ? strerror(errno) : hpfc_strerror(st));
    else
        x->f = x->owned;
    hpfc_file_get_info(x->f, &x->fi);
    /* a damaged file must not give a plausible but wrong map */
    if ((st = hpfc_file_check_checksums(x->f, NULL)))
        return fail(x, "%s: %s", x->o->file, hpfc_strerror(st));
    if (choose_driver(x))
        return 1;
    if ((st = hpfc_shapes_create(x->f, &x->shapes))) {
        if (st == HPFC_E_NO_SECTION)
            return fail(x, "%s: no exact geometry (GEOM and LABL sections); pack it again "
                           "with hpfc-pack 1.2",
                        x->o->file);
        return fail(x, "%s: geometry: %s", x->o->file, hpfc_strerror(st));
    }
    /* The export asks for every feature whole, however large: the caps
     * that protect an interactive query would refuse a legitimate one.
     * Each answer stays bounded by the checksummed file. */
    hpfc_limits unlimited = {HPFC_LIMIT_NONE, HPFC_LIMIT_NONE};
    hpfc_shapes_set_limits(x->shapes, &unlimited);
    hpfc_features_info fi;
    if (!x->o->faces && (st = hpfc_file_get_features(x->f, &fi)) == HPFC_E_NO_SECTION)
        return fail(x, "%s: the file has no features (FEAT section); --export-faces writes its "
                       "faces",
                    x->o->file);
    x->g_ready = 1; /* released even when it fails */
    if (ogr_shapes_init(&x->g, x->f, x->shapes))
        return shapes_failed(x);
    return write_atomically(x);
}

int export_gis(const gis_export_options *o, FILE *report)
{
    exporter x = {.o = o};
    double t0 = clock_seconds();
    CPLPushErrorHandler(CPLQuietErrorHandler);
    GDALAllRegister();
    int r = run(&x);
    if (!r)
        print_report(&x, report, clock_seconds() - t0);
    else
        fprintf(stderr, "hpfc-inspect: %s\n", x.why);
    CPLPopErrorHandler();
    if (x.g_ready)
        ogr_shapes_release(&x.g);
    hpfc_shapes_free(x.shapes);
    hpfc_close(x.owned);
    return r;
}
