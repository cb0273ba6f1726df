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
#include "open_input.h"
#include "projection.h"

typedef struct exporter {
    const gis_export_options *o;
    const hpfc_file *f;         /* o->open, or owned */
    hpfc_file *owned;           /* opened here */
    hpfc_file_info fi;
    hpfc_shapes *shapes;
    mapproj_plan *plan;         /* back to lon/lat; NULL: user coordinates */
    OGRSpatialReferenceH srs;   /* the output's, NULL: none */
    char srs_name[160];
    GDALDriverH driver;
    GDALDatasetH ds;
    int fid_column;             /* the driver's FID column is named "fid" */
    unsigned char *wkb;         /* the geometry being built, as WKB */
    size_t wkb_len, wkb_cap;
    uint64_t written, polygons, rings, points, lines, empty, skipped_holes;
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

/* ---- SRS --------------------------------------------------------------------------- */

/* The CRS section as hpfc-pack writes it: "DESCRIPTION; source LABEL",
 * LABEL "AUTH:CODE (name)" or a name. */
typedef struct crs_parts {
    char desc[1024];
    char code[128]; /* AUTH:CODE of the source, "" if none */
} crs_parts;

static void split_crs(const char *crs, size_t len, crs_parts *p)
{
    memset(p, 0, sizeof *p);
    size_t semi = 0;
    while (semi < len && crs[semi] != ';')
        semi++;
    size_t n = semi < sizeof p->desc - 1 ? semi : sizeof p->desc - 1;
    memcpy(p->desc, crs, n);
    while (n && p->desc[n - 1] == ' ')
        p->desc[--n] = '\0';
    const char *src = " source ";
    size_t sl = strlen(src);
    if (semi + 1 + sl <= len && memcmp(crs + semi + 1, src, sl) == 0) {
        const char *t = crs + semi + 1 + sl;
        size_t tl = 0, rest = len - (semi + 1 + sl);
        while (tl < rest && tl < sizeof p->code - 1 && t[tl] != ' ' && t[tl] != '\0')
            tl++;
        if (memchr(t, ':', tl)) {
            memcpy(p->code, t, tl);
            p->code[tl] = '\0';
        }
    }
}

/* (as common/ogr_shapes.c, which the GDAL driver reads with) Whether the CRS text of a hostile file is safe to hand to PROJ: a PROJ
 * string of "+key" and "+key=value" tokens, or an AUTH:CODE. PROJ takes
 * any other text for a name and searches its database for it, which can
 * take seconds on a crafted string. */
static int plain_crs_text(const char *text, int proj4)
{
    if (proj4) {
        if (strncmp(text, "+proj=", 6) != 0)
            return 0;
        for (const char *p = text; *p; p++)
            if (!(isalnum((unsigned char)*p) || strchr("+=_.,-/@ ", *p)) ||
                (*p == ' ' && p[1] != '+' && p[1] != '\0'))
                return 0;
        return 1;
    }
    const char *colon = strchr(text, ':');
    if (!colon || colon == text || !colon[1])
        return 0;
    for (const char *p = text; *p; p++)
        if (!(isalnum((unsigned char)*p) || *p == '_' || *p == '.' || p == colon))
            return 0;
    return 1;
}

static OGRSpatialReferenceH srs_from(const char *text, int proj4)
{
    if (!plain_crs_text(text, proj4))
        return NULL;
    OGRSpatialReferenceH s = OSRNewSpatialReference(NULL);
    if (!s)
        return NULL;
    OGRErr e = proj4 ? OSRImportFromProj4(s, text) : OSRSetFromUserInput(s, text);
    if (e != OGRERR_NONE) {
        OSRDestroySpatialReference(s);
        return NULL;
    }
    OSRSetAxisMappingStrategy(s, OAMS_TRADITIONAL_GIS_ORDER);
    return s;
}

/* Whether a description is one hpfc-pack's projection made
 * (common/projection.cc: tmerc, lcc, aea or eqc, no false origin, metres). */
static int made_by_pack(const char *desc)
{
    size_t n = strlen(desc);
    const char *tail = "+units=m +no_defs";
    size_t tl = strlen(tail);
    return (strncmp(desc, "+proj=tmerc ", 12) == 0 || strncmp(desc, "+proj=lcc ", 10) == 0 ||
            strncmp(desc, "+proj=aea ", 10) == 0 || strncmp(desc, "+proj=eqc ", 10) == 0) &&
           strstr(desc, " +x_0=0 +y_0=0 ") && n >= tl && strcmp(desc + n - tl, tail) == 0;
}

/* The output's SRS, and whether coordinates go back to lon/lat: yes when
 * hpfc-pack projected a geographic source (the description is one of its
 * projections and the source, where named by an authority, geographic);
 * otherwise the user coordinates are the source's own. */
static int setup_srs(exporter *x)
{
    snprintf(x->srs_name, sizeof x->srs_name, "none");
    if (!x->fi.crs)
        return 0;
    crs_parts p;
    split_crs(x->fi.crs, x->fi.crs_len, &p);
    OGRSpatialReferenceH source = p.code[0] ? srs_from(p.code, 0) : NULL;
    OGRSpatialReferenceH desc = p.desc[0] ? srs_from(p.desc, 1) : NULL;
    int back = made_by_pack(p.desc) && (!source || OSRIsGeographic(source));
    if (back) {
        char reason[200];
        x->plan = mapproj_from_text(p.desc, strlen(p.desc), reason, sizeof reason);
        if (!x->plan) {
            if (source)
                OSRDestroySpatialReference(source);
            if (desc)
                OSRDestroySpatialReference(desc);
            return fail(x, "cannot project back to the source SRS: %s", reason);
        }
        if (!source && desc) { /* the geographic SRS on the projection's ellipsoid */
            source = OSRCloneGeogCS(desc);
            if (source)
                OSRSetAxisMappingStrategy(source, OAMS_TRADITIONAL_GIS_ORDER);
        }
        x->srs = source;
        if (desc)
            OSRDestroySpatialReference(desc);
    } else {
        x->srs = source ? source : desc;
        if (source && desc)
            OSRDestroySpatialReference(desc);
    }
    if (x->srs) {
        const char *auth = OSRGetAuthorityName(x->srs, NULL);
        const char *code = OSRGetAuthorityCode(x->srs, NULL);
        const char *name = OSRGetName(x->srs);
        if (auth && code)
            snprintf(x->srs_name, sizeof x->srs_name, "%s:%s", auth, code);
        else
            snprintf(x->srs_name, sizeof x->srs_name, "%s", name ? name : "unnamed");
    }
    return 0;
}

/* ---- geometry ---------------------------------------------------------------------- */

/* A geometry is written as WKB (in this machine's byte order) and read by
 * GDAL in one call, which allocates each polygon's rings at once: adding
 * them one by one, GDAL grew its ring array and checked each ring, more
 * than the rest of the export cost on a layer with 10^5 holes. */

/* Room for n more bytes. */
static int wkb_room(exporter *x, size_t n)
{
    if (x->wkb_len + n <= x->wkb_cap)
        return 0;
    size_t c = x->wkb_cap ? x->wkb_cap : 4096;
    while (c < x->wkb_len + n)
        c *= 2;
    unsigned char *w = realloc(x->wkb, c);
    if (!w)
        return fail(x, "out of memory");
    x->wkb = w, x->wkb_cap = c;
    return 0;
}

static int wkb_put(exporter *x, const void *v, size_t n)
{
    if (wkb_room(x, n))
        return 1;
    memcpy(x->wkb + x->wkb_len, v, n);
    x->wkb_len += n;
    return 0;
}

/* A geometry's header: byte order, type, and its count (points of a line,
 * rings of a polygon, parts of a collection). */
static int wkb_head(exporter *x, uint32_t type, size_t count)
{
    const uint16_t one = 1;
    unsigned char order; /* 1: little-endian (wkbNDR), 0: big-endian */
    memcpy(&order, &one, 1);
    uint32_t n = (uint32_t)count;
    if (count > UINT32_MAX)
        return fail(x, "a geometry of %zu parts or points is too large for WKB", count);
    return wkb_put(x, &order, 1) || wkb_put(x, &type, 4) || wkb_put(x, &n, 4);
}

/* The points of ring (or line) r of an answer in output coordinates. */
static int wkb_points(exporter *x, const hpfc_polygons *p, size_t r)
{
    size_t a = p->ring_point[r], n = p->ring_point[r + 1] - a;
    if (wkb_room(x, 16 * n))
        return 1;
    /* WKB's points are (x, y) doubles in the machine's order (wkb_head
     * wrote it), at no particular alignment: converted a run at a time */
    enum { RUN = 256 };
    double uv[2 * RUN];
    for (size_t k = 0; k < n; k += RUN) {
        size_t m = n - k < RUN ? n - k : RUN;
        hpfc_user_points(x->f, p->xy + 2 * (a + k), m, uv);
        size_t done = x->plan ? mapproj_inverse_points(x->plan, uv, m) : m;
        if (done < m)
            return fail(x, "point (%.17g, %.17g) cannot be projected back", uv[2 * done],
                        uv[2 * done + 1]);
        memcpy(x->wkb + x->wkb_len + 16 * k, uv, 16 * m);
    }
    x->wkb_len += 16 * n;
    x->points += n;
    return 0;
}

/* Polygon k of an answer, its outer ring then its holes, appended. */
static int wkb_polygon(exporter *x, const hpfc_polygons *p, size_t k)
{
    size_t a = p->polygon_ring[k], b = p->polygon_ring[k + 1];
    if (wkb_head(x, wkbPolygon, b - a))
        return 1;
    for (size_t r = a; r < b; r++) {
        uint32_t n = (uint32_t)(p->ring_point[r + 1] - p->ring_point[r]);
        if (wkb_put(x, &n, 4) || wkb_points(x, p, r))
            return 1;
        x->rings++;
    }
    x->polygons++;
    return 0;
}

/* The WKB built, as a GDAL geometry (NULL after fail()). */
static OGRGeometryH from_wkb(exporter *x, int st)
{
    OGRGeometryH g = NULL;
    if (!st && OGR_G_CreateFromWkbEx(x->wkb, NULL, &g, x->wkb_len) != OGRERR_NONE)
        fail(x, "%s", gdal_reason("GDAL cannot read the geometry built"));
    return g;
}

/* Polygon k of an answer alone (a face). */
static OGRGeometryH polygon(exporter *x, const hpfc_polygons *p, size_t k)
{
    x->wkb_len = 0;
    return from_wkb(x, wkb_polygon(x, p, k));
}

static OGRGeometryH multipolygon(exporter *x, const hpfc_polygons *p)
{
    x->wkb_len = 0;
    int st = wkb_head(x, wkbMultiPolygon, p->polygon_count);
    for (size_t k = 0; k < p->polygon_count && !st; k++)
        st = wkb_polygon(x, p, k);
    x->skipped_holes += p->ring_count - p->polygon_ring[p->polygon_count];
    return from_wkb(x, st);
}

static OGRGeometryH multiline(exporter *x, const hpfc_polygons *p)
{
    x->wkb_len = 0;
    int st = wkb_head(x, wkbMultiLineString, p->ring_count);
    for (size_t r = 0; r < p->ring_count && !st; r++) {
        st = wkb_head(x, wkbLineString, p->ring_point[r + 1] - p->ring_point[r]) ||
             wkb_points(x, p, r);
        x->lines++;
    }
    return from_wkb(x, st);
}

/* A feature's geometry: its faces' union, else its lines, else none
 * (*g NULL). 0 or 1 after fail(). */
static int feature_geometry(exporter *x, uint32_t k, OGRGeometryH *g)
{
    *g = NULL;
    size_t faces;
    hpfc_polygons p;
    int st = hpfc_shapes_feature_faces(x->shapes, k, NULL, 0, &faces);
    if (!st && faces) {
        if ((st = hpfc_shapes_feature_polygons(x->shapes, k, &p)))
            return fail(x, "feature %u: %s", k, hpfc_strerror(st));
        return !(*g = multipolygon(x, &p));
    }
    if (st)
        return fail(x, "feature %u: %s", k, hpfc_strerror(st));
    st = hpfc_shapes_feature_polylines(x->shapes, k, &p);
    if (st == HPFC_E_NO_SECTION || (!st && p.ring_count == 0))
        return 0;
    if (st)
        return fail(x, "feature %u: %s", k, hpfc_strerror(st));
    return !(*g = multiline(x, &p));
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

typedef struct columns {
    uint32_t count;
    int key_field;          /* OGR field index of the key, -1 none */
    int fid_field;          /* OGR field index of "fid", -1 none */
    int *attr_field;        /* per ATTR column: OGR field index */
    int *type;
} columns;

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

/* Whether an ATTR column is named `name`. */
static int attr_has(const hpfc_file *f, const char *name)
{
    uint32_t c;
    return hpfc_attr_find(f, name, strlen(name), &c) == HPFC_OK;
}

/* fid (unless the driver's FID column has that name), the key (unless an
 * attribute has its name), then every stored attribute. */
static int make_fields(exporter *x, OGRLayerH layer, columns *c)
{
    memset(c, 0, sizeof *c);
    c->key_field = c->fid_field = -1;
    hpfc_attrs_info ai;
    int st = hpfc_file_get_attrs(x->f, &ai);
    c->count = st ? 0 : (uint32_t)ai.columns; /* ATTR counts its columns in 32 bits */
    if (st && st != HPFC_E_NO_SECTION)
        return fail(x, "attributes: %s", hpfc_strerror(st));
    if (!x->fid_column && !attr_has(x->f, "fid") &&
        add_field(x, layer, "fid", OFTInteger64, &c->fid_field))
        return 1;
    hpfc_features_info fi;
    if (hpfc_file_get_features(x->f, &fi) == HPFC_OK && fi.key_field) {
        char *key = dup_n(fi.key_field, fi.key_field_len);
        if (!key)
            return fail(x, "out of memory");
        int r = attr_has(x->f, key) ? 0 : add_field(x, layer, key, OFTString, &c->key_field);
        free(key);
        if (r)
            return 1;
    }
    c->attr_field = calloc(c->count + 1, sizeof *c->attr_field);
    c->type = calloc(c->count + 1, sizeof *c->type);
    if (!c->attr_field || !c->type)
        return fail(x, "out of memory");
    for (uint32_t k = 0; k < c->count; k++) {
        const char *name;
        size_t len;
        if ((st = hpfc_attr_column(x->f, k, &name, &len, &c->type[k])))
            return fail(x, "attribute column %u: %s", k, hpfc_strerror(st));
        char *n = dup_n(name, len);
        OGRFieldType t = c->type[k] == HPFC_ATTR_INTEGER ? OFTInteger64
                         : c->type[k] == HPFC_ATTR_REAL  ? OFTReal
                                                         : OFTString;
        int r = n ? add_field(x, layer, n, t, &c->attr_field[k]) : fail(x, "out of memory");
        free(n);
        if (r)
            return 1;
    }
    return 0;
}

static int set_string(exporter *x, OGRFeatureH ft, int field, const char *s, size_t n)
{
    char *v = dup_n(s, n);
    if (!v)
        return fail(x, "out of memory");
    OGR_F_SetFieldString(ft, field, v);
    free(v);
    return 0;
}

static int fill_fields(exporter *x, OGRFeatureH ft, const columns *c, uint32_t k,
                       const hpfc_feature *feat)
{
    if (c->fid_field >= 0)
        OGR_F_SetFieldInteger64(ft, c->fid_field, feat->fid);
    if (c->key_field >= 0) {
        if (feat->key && set_string(x, ft, c->key_field, feat->key, feat->key_len))
            return 1;
        if (!feat->key)
            OGR_F_SetFieldNull(ft, c->key_field);
    }
    for (uint32_t col = 0; col < c->count; col++) {
        hpfc_attr_value v;
        int st = hpfc_file_get_attr_value(x->f, k, col, &v), field = c->attr_field[col];
        if (st)
            return fail(x, "feature %u, attribute %u: %s", k, col, hpfc_strerror(st));
        if (v.type == HPFC_ATTR_INTEGER)
            OGR_F_SetFieldInteger64(ft, field, v.i);
        else if (v.type == HPFC_ATTR_REAL)
            OGR_F_SetFieldDouble(ft, field, v.r);
        else if (v.type == HPFC_ATTR_STRING && set_string(x, ft, field, v.s, v.len))
            return 1;
        else if (v.type == HPFC_ATTR_NULL)
            OGR_F_SetFieldNull(ft, field);
    }
    return 0;
}

/* The geometry type of a layer: multipolygons when all its features with
 * a geometry cover faces, multilines when none does, else any. */
static OGRwkbGeometryType layer_type(exporter *x, uint32_t layer, uint32_t features)
{
    int polys = 0, others = 0;
    for (uint32_t k = 0; k < features; k++) {
        hpfc_feature ft;
        size_t faces = 0;
        if (hpfc_file_get_feature(x->f, k, &ft) || ft.layer != layer)
            continue;
        hpfc_shapes_feature_faces(x->shapes, k, NULL, 0, &faces);
        if (faces)
            polys = 1;
        else
            others = 1;
    }
    return polys && others ? wkbUnknown : polys ? wkbMultiPolygon : wkbMultiLineString;
}

static OGRLayerH create_layer(exporter *x, const char *name, OGRwkbGeometryType t)
{
    OGRLayerH layer = GDALDatasetCreateLayer(x->ds, name, x->srs, t, NULL);
    if (!layer)
        fail(x, "cannot create layer '%s': %s", name, gdal_reason("refused"));
    return layer;
}

static int write_feature(exporter *x, OGRLayerH layer, const columns *c, uint32_t k,
                         const hpfc_feature *feat)
{
    OGRGeometryH g;
    if (feature_geometry(x, k, &g))
        return 1;
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
    int r = fill_fields(x, ft, c, k, feat);
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
        char *lname = dup_n(name, len);
        if (!lname)
            return fail(x, "out of memory");
        OGRLayerH layer = create_layer(x, lname[0] ? lname : "features",
                                       layer_type(x, l, fi.features));
        free(lname);
        columns c;
        int r = !layer || make_fields(x, layer, &c);
        /* one transaction a layer (GeoPackage: a commit per feature otherwise);
         * drivers without transactions write as they go */
        int tx = layer && !r && OGR_L_StartTransaction(layer) == OGRERR_NONE;
        for (uint32_t k = 0; k < fi.features && !r; k++) {
            hpfc_feature feat;
            if ((st = hpfc_file_get_feature(x->f, k, &feat)))
                r = fail(x, "feature %u: %s", k, hpfc_strerror(st));
            else if (feat.layer == l)
                r = write_feature(x, layer, &c, k, &feat);
        }
        if (tx && !r && OGR_L_CommitTransaction(layer) != OGRERR_NONE)
            r = fail(x, "cannot commit layer %u: %s", l, gdal_reason("refused"));
        if (layer) {
            free(c.attr_field);
            free(c.type);
        }
        if (r)
            return 1;
    }
    return 0;
}

/* ---- faces ------------------------------------------------------------------------- */

typedef struct text {
    char *s;
    size_t len, cap;
} text;

static int text_add(text *t, const char *sep, const char *s, size_t n)
{
    size_t sl = t->len ? strlen(sep) : 0;
    if (t->len + sl + n + 1 > t->cap) {
        size_t c = 2 * (t->len + sl + n + 1);
        char *p = realloc(t->s, c);
        if (!p)
            return -1;
        t->s = p, t->cap = c;
    }
    memcpy(t->s + t->len, sep, sl);
    memcpy(t->s + t->len + sl, s, n);
    t->len += sl + n;
    t->s[t->len] = '\0';
    return 0;
}

/* "fids" (space-separated) and "keys" ('|'-separated) of a face's features. */
static int face_fields(exporter *x, OGRFeatureH ft, uint64_t face, int fids_field, int keys_field)
{
    uint32_t n = 0;
    if (hpfc_face_feature_count(x->f, face, &n) != HPFC_OK)
        return 0;
    text fids = {0}, keys = {0};
    int r = 0;
    for (uint32_t k = 0; k < n && !r; k++) {
        hpfc_id index;
        hpfc_feature feat;
        char buf[32];
        int st = hpfc_face_feature_id(x->f, face, k, &index);
        if (!st)
            st = hpfc_file_get_feature(x->f, index, &feat);
        if (st) {
            r = fail(x, "face %llu: %s", (unsigned long long)face, hpfc_strerror(st));
            break;
        }
        snprintf(buf, sizeof buf, "%lld", (long long)feat.fid);
        if (text_add(&fids, " ", buf, strlen(buf)) ||
            (keys_field >= 0 && text_add(&keys, "|", feat.key ? feat.key : "",
                                         feat.key ? feat.key_len : 0)))
            r = fail(x, "out of memory");
    }
    if (!r) {
        OGR_F_SetFieldString(ft, fids_field, fids.s ? fids.s : "");
        if (keys_field >= 0)
            OGR_F_SetFieldString(ft, keys_field, keys.s ? keys.s : "");
    }
    free(fids.s);
    free(keys.s);
    return r;
}

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
        hpfc_polygons p;
        int st = hpfc_shapes_face_polygons(x->shapes, face, &p);
        if (st)
            return fail(x, "face %llu: %s", (unsigned long long)face, hpfc_strerror(st));
        if (p.polygon_count != 1)
            return fail(x, "face %llu: %zu outer rings, where a bounded face has one (corrupt "
                           "file)",
                        (unsigned long long)face, p.polygon_count);
        OGRGeometryH g = polygon(x, &p, 0);
        OGRFeatureH ft = g ? OGR_F_Create(OGR_L_GetLayerDefn(layer)) : NULL;
        if (!ft) {
            OGR_G_DestroyGeometry(g);
            return g ? fail(x, "out of memory") : 1;
        }
        OGR_F_SetFID(ft, (GIntBig)face);
        OGR_F_SetGeometryDirectly(ft, g);
        if (face_field >= 0)
            OGR_F_SetFieldInteger64(ft, face_field, (GIntBig)face);
        uint32_t n = 0;
        int r = 0;
        if (have_features) {
            hpfc_face_feature_count(x->f, face, &n);
            OGR_F_SetFieldInteger(ft, count_field, (int)n);
            r = face_fields(x, ft, face, fids_field, keys_field);
        }
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
        OGRGeometryH g = c->lines ? multiline(x, &p) : multipolygon(x, &p);
        OGRFeatureH ft = g ? OGR_F_Create(OGR_L_GetLayerDefn(layer)) : NULL;
        if (!ft) {
            OGR_G_DestroyGeometry(g);
            return g ? fail(x, "out of memory") : 1;
        }
        OGR_F_SetGeometryDirectly(ft, g);
        int r = 0;
        if (field >= 0 && value)
            r = set_string(x, ft, field, value, len);
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
        jsonw_string(&w, "srs", x->srs_name);
        jsonw_bool(&w, "projected_back", x->plan != NULL);
        jsonw_u64(&w, "written", x->written);
        jsonw_u64(&w, "polygons", x->polygons);
        jsonw_u64(&w, "rings", x->rings);
        jsonw_u64(&w, "lines", x->lines);
        jsonw_u64(&w, "points", x->points);
        jsonw_u64(&w, "without_geometry", x->empty);
        jsonw_double(&w, "seconds", seconds, 3);
        jsonw_object_end(&w);
        jsonw_finish(&w);
    } else {
        fprintf(out,
                "%s: %llu %s (%llu polygons, %llu rings, %llu lines, %llu points), %s, SRS %s%s\n",
                x->o->output, (unsigned long long)x->written,
                x->o->custom ? x->o->custom->name : x->o->faces ? "faces" : "features",
                (unsigned long long)x->polygons, (unsigned long long)x->rings,
                (unsigned long long)x->lines, (unsigned long long)x->points, drv, x->srs_name,
                x->plan ? " (projected back)" : "");
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
    if (setup_srs(x))
        return 1;
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
    hpfc_shapes_free(x.shapes);
    mapproj_free(x.plan);
    if (x.srs)
        OSRDestroySpatialReference(x.srs);
    hpfc_close(x.owned);
    free(x.wkb);
    return r;
}
