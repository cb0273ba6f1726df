/*
 * export_gis.c: hpfc-inspect --export / --export-faces through GDAL/OGR
 * (interfaces §5). The geometry is the library's exact rings
 * (hpfc_shapes_*), turned into user coordinates (lattice * 10^unit_exp10)
 * and, for a map that hpfc-pack projected from longitude and latitude,
 * projected back with the inverse of the projection the CRS section
 * records, so the output lies in the source SRS and opens on top of the
 * original. Each feature keeps its fid (the OGR FID, and a "fid" field
 * where the driver has no FID column of that name), its key and its stored
 * attributes.
 */
#include "export_gis.h"

#include <dirent.h>
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
#include <gdal.h>
#include <ogr_api.h>
#include <ogr_srs_api.h>

#include "clock.h"
#include "hpfc.h"
#include "jsonw.h"
#include "ogr_shapes.h"

typedef struct exporter {
    const gis_export_options *o;
    hpfc_file *f;
    hpfc_file_info fi;
    hpfc_shapes *shapes;
    ogr_shapes g;               /* the geometry, fields and SRS (ogr_shapes.h) */
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

/* The layer's fields as ogr_shapes_fields lists them, from OGR field
 * *first on (GPKG's FID column is named "fid": no field of that name). */
static int make_fields(exporter *x, OGRLayerH layer, ogr_shapes_field **fields, size_t *count,
                       int *first)
{
    if (ogr_shapes_fields(&x->g, !x->fid_column, fields, count))
        return fail(x, "%s", x->g.why);
    *first = OGR_FD_GetFieldCount(OGR_L_GetLayerDefn(layer));
    for (size_t c = 0; c < *count; c++) {
        int index;
        if (add_field(x, layer, (*fields)[c].name, (*fields)[c].type, &index))
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

static int write_feature(exporter *x, OGRLayerH layer, const ogr_shapes_field *fields,
                         size_t count, int first, uint32_t k, const hpfc_feature *feat)
{
    OGRGeometryH g;
    if (ogr_shapes_feature_geometry(&x->g, k, &g))
        return fail(x, "%s", x->g.why);
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
    int r = ogr_shapes_fill(&x->g, ft, first, fields, count, k, feat)
                ? fail(x, "%s", x->g.why)
                : 0;
    if (!r && OGR_L_CreateFeature(layer, ft) != OGRERR_NONE)
        r = fail(x, "feature %u (fid %lld): %s", k, (long long)feat->fid,
                 gdal_reason("the driver refused it"));
    OGR_F_Destroy(ft);
    x->written += !r;
    return r;
}

/* Every feature, layer by layer (FEAT's layers, with their names). */
static int write_features(exporter *x)
{
    hpfc_features_info fi;
    int st = hpfc_file_get_features(x->f, &fi);
    if (st == HPFC_E_NO_SECTION)
        return fail(x, "the file has no features (FEAT section); --export-faces writes its "
                       "faces");
    if (st)
        return fail(x, "features: %s", hpfc_strerror(st));
    for (uint32_t l = 0; l < fi.layers; l++) {
        const char *name;
        size_t len;
        if ((st = hpfc_layer_name(x->f, l, &name, &len)))
            return fail(x, "layer %u: %s", l, hpfc_strerror(st));
        char *lname = malloc(len + 1);
        if (!lname)
            return fail(x, "out of memory");
        memcpy(lname, name, len);
        lname[len] = '\0';
        OGRLayerH layer = create_layer(x, lname[0] ? lname : "features",
                                       ogr_shapes_layer_type(&x->g, l));
        free(lname);
        ogr_shapes_field *fields = NULL;
        size_t count = 0;
        int first = 0;
        int r = !layer || make_fields(x, layer, &fields, &count, &first);
        /* one transaction a layer (GeoPackage: a commit per feature otherwise);
         * drivers without transactions write as they go */
        int tx = layer && !r && OGR_L_StartTransaction(layer) == OGRERR_NONE;
        for (uint32_t k = 0; k < fi.features && !r; k++) {
            hpfc_feature feat;
            if ((st = hpfc_file_get_feature(x->f, k, &feat)))
                r = fail(x, "feature %u: %s", k, hpfc_strerror(st));
            else if (feat.layer == l)
                r = write_feature(x, layer, fields, count, first, k, &feat);
        }
        if (tx && !r && OGR_L_CommitTransaction(layer) != OGRERR_NONE)
            r = fail(x, "cannot commit layer %u: %s", l, gdal_reason("refused"));
        ogr_shapes_fields_free(fields, count);
        if (r)
            return 1;
    }
    return 0;
}

/* ---- faces ------------------------------------------------------------------------- */

/* Every bounded face as its polygon (the unbounded face has no outer ring),
 * with its id and its features' fids and keys. */
static int write_faces(exporter *x)
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
            return fail(x, "%s", x->g.why);
        OGRFeatureH ft = OGR_F_Create(OGR_L_GetLayerDefn(layer));
        if (!ft) {
            OGR_G_DestroyGeometry(g);
            return fail(x, "out of memory");
        }
        OGR_F_SetFID(ft, (GIntBig)face);
        OGR_F_SetGeometryDirectly(ft, g);
        if (face_field >= 0)
            OGR_F_SetFieldInteger64(ft, face_field, (GIntBig)face);
        int r = 0;
        if (have_features &&
            ogr_shapes_face_features(&x->g, ft, face, count_field, fids_field, keys_field))
            r = fail(x, "%s", x->g.why);
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

/* ---- atomic output ------------------------------------------------------------------- */

/* OUT's directory ("." when none) and last name. */
static char *dir_of(const char *path, const char **base)
{
    const char *slash = strrchr(path, '/');
    size_t dlen = slash ? (size_t)(slash - path) : 1;
    if (slash && dlen == 0)
        dlen = 1;
    char *dir = malloc(dlen + 1);
    if (dir) {
        memcpy(dir, slash ? path : ".", dlen);
        dir[dlen] = '\0';
    }
    *base = slash ? slash + 1 : path;
    return dir;
}

static char *join(const char *a, const char *b)
{
    size_t n = strlen(a) + strlen(b) + 2;
    char *p = malloc(n);
    if (p)
        snprintf(p, n, "%s/%s", a, b);
    return p;
}

/* Removes the temporary directory and what is left in it. */
static void remove_temp(const char *tmp)
{
    DIR *d = opendir(tmp);
    if (d) {
        struct dirent *e;
        while ((e = readdir(d)))
            if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) {
                char *p = join(tmp, e->d_name);
                if (p)
                    unlink(p);
                free(p);
            }
        closedir(d);
    }
    rmdir(tmp);
}

/* Moves every file the driver wrote into OUT's directory (each rename is
 * atomic; a multi-file format such as a Shapefile is moved file by file). */
static int move_into_place(exporter *x, const char *tmp, const char *dir)
{
    DIR *d = opendir(tmp);
    if (!d)
        return fail(x, "%s: %s", tmp, strerror(errno));
    struct dirent *e;
    int r = 0;
    while (!r && (e = readdir(d))) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, ".."))
            continue;
        char *from = join(tmp, e->d_name), *to = join(dir, e->d_name);
        if (!from || !to)
            r = fail(x, "out of memory");
        else if (rename(from, to) != 0)
            r = fail(x, "%s: cannot replace: %s", to, strerror(errno));
        free(from);
        free(to);
    }
    closedir(d);
    return r;
}

static int write_dataset(exporter *x, const char *path)
{
    CPLErrorReset();
    x->ds = GDALCreate(x->driver, path, 0, 0, 0, GDT_Unknown, NULL);
    if (!x->ds)
        return fail(x, "%s: cannot create: %s", x->o->output, gdal_reason("refused"));
    x->fid_column = strcmp(GDALGetDriverShortName(x->driver), "GPKG") == 0;
    int r = x->o->faces ? write_faces(x) : write_features(x);
    CPLErrorReset();
    GDALClose(x->ds);
    x->ds = NULL;
    if (!r && CPLGetLastErrorType() >= CE_Failure)
        r = fail(x, "%s: %s", x->o->output, gdal_reason("cannot write"));
    return r;
}

/* The dataset in a fresh directory beside OUT, then moved into place. */
static int write_atomically(exporter *x)
{
    const char *base;
    char *dir = dir_of(x->o->output, &base);
    if (!dir)
        return fail(x, "out of memory");
    if (!*base) {
        free(dir);
        return fail(x, "%s: not a file name", x->o->output);
    }
    size_t n = strlen(dir) + strlen(base) + 16;
    char *tmp = malloc(n);
    int r = 0;
    if (!tmp) {
        r = fail(x, "out of memory");
    } else {
        snprintf(tmp, n, "%s/.%s.XXXXXX", dir, base);
        if (!mkdtemp(tmp)) {
            r = fail(x, "%s: cannot create a temporary directory: %s", x->o->output,
                     strerror(errno));
            free(tmp);
            tmp = NULL;
        }
    }
    if (tmp) {
        char *path = join(tmp, base);
        r = path ? write_dataset(x, path) : fail(x, "out of memory");
        free(path);
        if (!r)
            r = move_into_place(x, tmp, dir);
        remove_temp(tmp);
        free(tmp);
    }
    free(dir);
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
        jsonw_string(&w, "what", x->o->faces ? "faces" : "features");
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
                x->o->output, (unsigned long long)x->written, x->o->faces ? "faces" : "features",
                (unsigned long long)x->g.polygons, (unsigned long long)x->g.rings,
                (unsigned long long)x->g.lines, (unsigned long long)x->g.points, drv, x->g.srs_name,
                x->g.plan ? " (projected back)" : "");
    }
}

static int run(exporter *x)
{
    int st = hpfc_open(x->o->file, 0, &x->f);
    if (st)
        return fail(x, "%s: %s", x->o->file,
                    st == HPFC_E_IO && errno ? strerror(errno) : hpfc_strerror(st));
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
    hpfc_features_info fi;
    if (!x->o->faces && (st = hpfc_file_get_features(x->f, &fi)) == HPFC_E_NO_SECTION)
        return fail(x, "%s: the file has no features (FEAT section); --export-faces writes its "
                       "faces",
                    x->o->file);
    if (ogr_shapes_init(&x->g, x->f, x->shapes))
        return fail(x, "%s", x->g.why);
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
    ogr_shapes_release(&x.g);
    hpfc_shapes_free(x.shapes);
    hpfc_close(x.f);
    return r;
}
