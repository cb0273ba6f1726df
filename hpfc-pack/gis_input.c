/*
 * gis_input.c: see gis_input.h. The pipeline:
 *
 *   1. read every selected layer's lines and polygon rings into flat
 *      arrays, checking coordinates (finite; in range when geographic),
 *      cutting geographic features that cross the antimeridian
 *      (dateline.h), and checking polygon validity (GEOS, on a second
 *      thread while GDAL reads on: polygon_checks.h);
 *   2. choose the projection from the geographic extent, project;
 *   3. choose the lattice unit from the projected extent, snap by rounding;
 *   4. collect the distinct snapped segments, find exactly those that need
 *      noding (segnode.h) and node them (or, failing that, all the
 *      linework) with GEOS's snap-rounding unary union on a unit grid: the
 *      output's coordinates are lattice integers, crossings are nodes,
 *      duplicate borders are dissolved;
 *   5. build the graph from the distinct segments in the chosen vertex
 *      model.
 */
#include "gis_input.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef HPFC_HAVE_GIS

#include <errno.h>
#include <math.h>
#include <time.h>
#include <unistd.h>

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_vsi.h>
#include <gdal.h>
#include <ogr_api.h>
#include <ogr_srs_api.h>
#include <geos_c.h>

#include "clock.h"
#include "dateline.h"
#include "grow.h"
#include "lattice.h"
#include "noded_paths.h"
#include "polygon_checks.h"
#include "progress.h"
#include "projection.h"
#include "segment_graph.h"
#include "segnode.h"
#include "sort.h"

/* ---- state ---------------------------------------------------------------------- */

typedef struct part_ref {
    uint32_t layer;
    int64_t fid;
    uint32_t feature; /* the part's feature (gis_features.h) */
    int ring;         /* a ring of a polygon */
} part_ref;

typedef struct reader {
    const gis_options *opt;
    GDALDatasetH given;  /* the caller's open dataset (gis_read_graph_dataset), else NULL */
    gis_info *info;
    char *err;
    size_t err_len;
    progress bar;

    GEOSContextHandle_t geos;
    char geos_msg[256];
    polygon_checks *checks; /* the polygons' validity, in feature order */

    /* the current layer and feature, for messages */
    const char *layer_name;
    uint32_t layer_index;
    int64_t fid;      /* the feature's FID in the source */
    int64_t position; /* the feature's position in its layer, from 0 */
    int *key_index;   /* the --key fields of the current layer */
    size_t n_key;
    struct field_map {    /* the --fields of the current layer */
        int index;        /* in the layer */
        uint32_t column;  /* attribute column */
        int kind;         /* OGRFieldType */
    } *fields;
    size_t n_fields, cap_fields;
    uint32_t feature; /* the index the current feature gets if it has parts */
    int polygon;      /* the current feature has a polygon: its closed parts are rings */
    int key_found;    /* some layer read has the --key fields */
    char key_missing[300]; /* why the first layer without them has none */
    OGRFeatureH cur;  /* the current feature, for its --key value in messages */

    OGRSpatialReferenceH given_srs;   /* -a_srs or -s_srs, NULL if none */
    OGRSpatialReferenceH assumed_srs; /* WGS 84, for layers without SRS in lon/lat range */

    int geographic;   /* coordinates are (lon, lat) degrees */
    int saw_wrap;     /* the current feature has a segment crossing the antimeridian */
    int swap_xy;      /* the data store (lat, lon) */
    double a, f;      /* ellipsoid of a geographic SRS */

    double *xy;       /* every point, x then y */
    size_t n_points, cap_points;
    size_t *start;    /* part k: points start[k] .. start[k+1]-1 */
    part_ref *refs;
    size_t n_parts, cap_parts, cap_start;
    double xmin, ymin, xmax, ymax;
    segnode_pt *line_ends; /* where each line part starts and ends in the map */
    size_t n_line_ends, cap_line_ends;

    /* A read in feature ranges (gis_range.h). gis_read_range: the one
     * range read here, and what it keeps (features, attributes and noded
     * polygons' names go there instead of info). gis_read_graph with
     * opt->ranges: the ranges other processes read, loaded by read_layer
     * instead of reading the features (NULL: read here). */
    const gis_range_plan *only;
    gis_range *kept;
    gis_range_plan *plan;
    size_t n_plan;
    uint64_t tag;
} reader;

static int fail(reader *r, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(r->err, r->err_len, fmt, ap);
    va_end(ap);
    return 1;
}

/* The current feature's first --key field's value, for messages; NULL
 * when there is none. */
static const char *message_key(const reader *r)
{
    if (!r->cur || !r->n_key || !OGR_F_IsFieldSetAndNotNull(r->cur, r->key_index[0]))
        return NULL;
    return OGR_F_GetFieldAsString(r->cur, r->key_index[0]);
}

/* "layer 'NAME' feature FID", and "(KEY 'VALUE')" with --key, for
 * messages: a user knows "Oregon" better than "feature 38". */
static const char *where(const reader *r, char *buf, size_t n)
{
    const char *key = message_key(r);
    if (key)
        snprintf(buf, n, "layer '%s' feature %lld (%s '%.60s')", r->layer_name, (long long)r->fid,
                 r->opt->key_field, key);
    else
        snprintf(buf, n, "layer '%s' feature %lld", r->layer_name, (long long)r->fid);
    return buf;
}

/* A polygon's name in the report's short list of those noded: its --key
 * value, else its layer and FID. */
static void repaired_item(const reader *r, char *buf, size_t n)
{
    const char *key = message_key(r);
    if (key)
        snprintf(buf, n, "'%.40s'", key);
    else
        snprintf(buf, n, "layer '%.40s' feature %lld", r->layer_name, (long long)r->fid);
}

/* Adds a noded polygon to the report's short list (the first few); a
 * range keeps the names for the list of the whole read. */
static int note_repaired(reader *r, const char *item)
{
    if (r->kept && gis_range_add_repaired(r->kept, item) != 0)
        return fail(r, "out of memory");
    char *list = r->info->repaired;
    size_t len = strlen(list), cap = sizeof r->info->repaired;
    if (r->info->invalid_noded > 4 || len + 8 >= cap)
        return 0;
    snprintf(list + len, cap - len, "%s%s", len ? ", " : "", item);
    return 0;
}

/* The index the next feature with parts gets. */
static uint32_t features_so_far(const reader *r)
{
    return r->kept ? (uint32_t)r->kept->n_features : gis_features_count(r->info->polygons);
}

static void geos_message(const char *msg, void *user)
{
    reader *r = user;
    snprintf(r->geos_msg, sizeof r->geos_msg, "%s", msg);
}

static void geos_notice(const char *msg, void *user)
{
    (void)msg;
    (void)user;
}

/* ---- step 1: reading -------------------------------------------------------------- */

/* Appends one line string or ring of `g`. */
static int add_part(reader *r, OGRGeometryH g, int closed)
{
    int n = OGR_G_GetPointCount(g);
    if (n <= 0)
        return 0;
    if (!array_grow((void **)&r->xy, &r->cap_points, r->n_points + (size_t)n + 1,
                    2 * sizeof(double)) ||
        !array_grow((void **)&r->start, &r->cap_start, r->n_parts + 2, sizeof(size_t)) ||
        !array_grow((void **)&r->refs, &r->cap_parts, r->n_parts + 1, sizeof(part_ref)))
        return fail(r, "out of memory");
    double *x = r->xy + 2 * r->n_points;
    OGR_G_GetPoints(g, x, 2 * sizeof(double), x + 1, 2 * sizeof(double), NULL, 0);
    char wb[200];
    for (int i = 0; i < n; i++) {
        double px = x[2 * i], py = x[2 * i + 1];
        if (!isfinite(px) || !isfinite(py))
            return fail(r, "%s: invalid geometry: coordinate (%g, %g) is not finite",
                        where(r, wb, sizeof wb), px, py);
        if (r->swap_xy) {
            x[2 * i] = py;
            x[2 * i + 1] = px;
            px = x[2 * i];
            py = x[2 * i + 1];
        }
        if (r->geographic) {
            if (px < -180.0 || px > 180.0 || py < -90.0 || py > 90.0)
                return fail(r, "%s: point (%.9g, %.9g) is outside the longitude/latitude range "
                               "of its geographic SRS",
                            where(r, wb, sizeof wb), px, py);
            if (i > 0 && dateline_segment_wraps(x[2 * i - 2], x[2 * i - 1], px, py)) {
                if (r->opt->dateline == GIS_DATELINE_REJECT)
                    return fail(r, "%s: a line or ring crosses the antimeridian (a segment "
                                   "from longitude %.9g to %.9g); --wrap-dateline yes cuts "
                                   "it at +-180 degrees",
                                where(r, wb, sizeof wb), x[2 * i - 2], px);
                r->saw_wrap = 1; /* read_feature cuts the feature and reads it again */
            }
        }
        if (px < r->xmin) r->xmin = px;
        if (px > r->xmax) r->xmax = px;
        if (py < r->ymin) r->ymin = py;
        if (py > r->ymax) r->ymax = py;
    }
    size_t end = r->n_points + (size_t)n;
    if (closed && n > 1 && (x[0] != x[2 * n - 2] || x[1] != x[2 * n - 1])) {
        x[2 * n] = x[0];
        x[2 * n + 1] = x[1];
        end++;
    }
    r->start[r->n_parts] = r->n_points;
    r->refs[r->n_parts].layer = r->layer_index;
    r->refs[r->n_parts].fid = r->fid;
    r->refs[r->n_parts].feature = r->feature;
    r->refs[r->n_parts].ring = closed && r->polygon;
    r->n_parts++;
    r->n_points = end;
    r->start[r->n_parts] = end;
    return 0;
}

/* GEOS's verdict on a polygon, in feature order (polygon_checks.h):
 * counted and named when invalid polygons are noded, else the failure. */
static int take_verdict(void *user, const polygon_verdict *v)
{
    reader *r = user;
    if (v->kind == POLYGON_UNREADABLE)
        return fail(r, "%s: invalid geometry (%s)", v->where,
                    v->why[0] ? v->why : "GEOS cannot read it");
    if (v->kind == POLYGON_VALID)
        return 0;
    if (r->opt->invalid_mode == GIS_INVALID_NODE) {
        r->info->invalid_noded++;
        return note_repaired(r, v->item);
    }
    return fail(r, "%s: invalid polygon: %s (--invalid node, the default, packs its rings as "
                   "noded linework)",
                v->where, v->why[0] ? v->why : "rejected by GEOS");
}

/* Queues the feature's polygon for GEOS's verdict (take_verdict). */
static int check_polygon(reader *r, OGRGeometryH g)
{
    size_t size = (size_t)OGR_G_WkbSize(g);
    unsigned char *wkb = malloc(size ? size : 1);
    if (!wkb)
        return fail(r, "out of memory");
    if (OGR_G_ExportToWkb(g, wkbNDR, wkb) != OGRERR_NONE) {
        free(wkb); /* GEOS cannot read it */
        wkb = NULL, size = 0;
    }
    char wb[200], item[120];
    where(r, wb, sizeof wb);
    repaired_item(r, item, sizeof item);
    int st = polygon_checks_add(r->checks, wkb, size, wb, item);
    return st < 0 ? fail(r, "out of memory") : st;
}

/* Adds every line and ring of g; *lines counts what was added. */
static int add_geometry(reader *r, OGRGeometryH g, uint64_t *lines)
{
    if (OGR_G_IsEmpty(g))
        return 0;
    OGRwkbGeometryType t = wkbFlatten(OGR_G_GetGeometryType(g));
    switch (t) {
    case wkbPoint:
    case wkbMultiPoint:
        r->info->skipped_points++;
        return 0;
    case wkbLineString:
    case wkbLinearRing:
        ++*lines;
        return add_part(r, g, t == wkbLinearRing);
    case wkbPolygon:
    case wkbTriangle:
        for (int i = 0; i < OGR_G_GetGeometryCount(g); i++) {
            int st = add_part(r, OGR_G_GetGeometryRef(g, i), 1);
            if (st)
                return st;
            ++*lines;
        }
        return 0;
    default:
        for (int i = 0; i < OGR_G_GetGeometryCount(g); i++) {
            int st = add_geometry(r, OGR_G_GetGeometryRef(g, i), lines);
            if (st)
                return st;
        }
        return 0;
    }
}

static int has_polygon(OGRGeometryH g)
{
    OGRwkbGeometryType t = wkbFlatten(OGR_G_GetGeometryType(g));
    if (t == wkbPolygon || t == wkbTriangle)
        return 1;
    for (int i = 0; t != wkbLineString && t != wkbLinearRing && t != wkbPoint &&
                    i < OGR_G_GetGeometryCount(g);
         i++)
        if (has_polygon(OGR_G_GetGeometryRef(g, i)))
            return 1;
    return 0;
}

/* A date, time or date-time field as ISO 8601 text. */
static void iso_date(OGRFeatureH f, int i, OGRFieldType t, char *buf, size_t n)
{
    int y, mo, d, h, mi, tz;
    float sec;
    OGR_F_GetFieldAsDateTimeEx(f, i, &y, &mo, &d, &h, &mi, &sec, &tz);
    char time[32] = "", zone[16] = "";
    int whole = (int)sec;
    if ((float)whole == sec)
        snprintf(time, sizeof time, "%02d:%02d:%02d", h, mi, whole);
    else
        snprintf(time, sizeof time, "%02d:%02d:%06.3f", h, mi, (double)sec);
    if (tz == 100)
        snprintf(zone, sizeof zone, "Z");
    else if (tz > 1) {
        int off = (tz - 100) * 15;
        snprintf(zone, sizeof zone, "%c%02d:%02d", off < 0 ? '-' : '+', abs(off) / 60, abs(off) % 60);
    }
    if (t == OFTDate)
        snprintf(buf, n, "%04d-%02d-%02d", y, mo, d);
    else if (t == OFTTime)
        snprintf(buf, n, "%s%s", time, zone);
    else
        snprintf(buf, n, "%04d-%02d-%02dT%s%s", y, mo, d, time, zone);
}

/* Value k of the layer's --fields: to the attribute row, or to the
 * range's feature (its field index, for the reader that loads it). */
static int set_integer(reader *r, size_t k, int64_t v)
{
    return r->kept ? gis_range_add_integer(r->kept, (uint32_t)k, v)
                   : gis_attrs_set_integer(r->info->attrs, r->fields[k].column, v);
}

static int set_real(reader *r, size_t k, double v)
{
    return r->kept ? gis_range_add_real(r->kept, (uint32_t)k, v)
                   : gis_attrs_set_real(r->info->attrs, r->fields[k].column, v);
}

static int set_string(reader *r, size_t k, const char *v)
{
    return r->kept ? gis_range_add_string(r->kept, (uint32_t)k, v)
                   : gis_attrs_set_string(r->info->attrs, r->fields[k].column, v);
}

/* Starts the feature's attribute row with its source FID (a range's
 * reader adds it when it loads the feature). */
static int start_row(reader *r)
{
    gis_attrs *a = r->info->attrs;
    if (!r->kept && (gis_attrs_row(a) != 0 || gis_attrs_set_integer(a, 0, r->fid) != 0))
        return fail(r, "out of memory");
    return 0;
}

/* The --fields values of feature f as the next attribute row, after its
 * source FID. */
static int add_attributes(reader *r, OGRFeatureH f)
{
    if (start_row(r))
        return 1;
    for (size_t k = 0; k < r->n_fields; k++) {
        int i = r->fields[k].index, st;
        if (!OGR_F_IsFieldSetAndNotNull(f, i))
            continue;
        OGRFieldType t = (OGRFieldType)r->fields[k].kind;
        if (t == OFTInteger || t == OFTInteger64)
            st = set_integer(r, k, OGR_F_GetFieldAsInteger64(f, i));
        else if (t == OFTReal)
            st = set_real(r, k, OGR_F_GetFieldAsDouble(f, i));
        else if (t == OFTDate || t == OFTTime || t == OFTDateTime) {
            char buf[64];
            iso_date(f, i, t, buf, sizeof buf);
            st = set_string(r, k, buf);
        } else
            st = set_string(r, k, OGR_F_GetFieldAsString(f, i));
        if (st)
            return fail(r, "out of memory");
    }
    return 0;
}

/* The --key value: the key fields' values joined by commas (a null one
 * empty); NULL when all are null. malloc'ed. */
static char *key_value(reader *r, OGRFeatureH f, int *failed)
{
    size_t len = 0, set = 0;
    for (size_t k = 0; k < r->n_key; k++)
        if (OGR_F_IsFieldSetAndNotNull(f, r->key_index[k])) {
            len += strlen(OGR_F_GetFieldAsString(f, r->key_index[k]));
            set++;
        }
    if (!set)
        return NULL;
    char *key = malloc(len + r->n_key + 1);
    if (!key) {
        *failed = 1;
        return NULL;
    }
    key[0] = 0;
    for (size_t k = 0, at = 0; k < r->n_key; k++) {
        const char *v = OGR_F_IsFieldSetAndNotNull(f, r->key_index[k])
                            ? OGR_F_GetFieldAsString(f, r->key_index[k])
                            : "";
        at += (size_t)sprintf(key + at, "%s%s", k ? "," : "", v);
    }
    return key;
}

/* Records a feature with parts: its position, source FID, layer, --key
 * value and attributes. */
static int add_feature(reader *r, OGRFeatureH f)
{
    int failed = 0;
    char *key = key_value(r, f, &failed);
    if (failed || (r->kept ? gis_range_add_feature(r->kept, r->position, r->fid, key)
                           : gis_features_add(r->info->polygons, r->position, r->fid,
                                              r->layer_index, key)) != 0) {
        free(key);
        return fail(r, "out of memory");
    }
    free(key);
    return add_attributes(r, f);
}

/* Adds the lines and rings of g; a geographic feature that crosses the
 * antimeridian is taken back and its cut added instead, which then replaces
 * *owned (the geometry the caller frees). */
static int read_geometry(reader *r, OGRGeometryH g, uint64_t *lines, OGRGeometryH *owned)
{
    size_t parts = r->n_parts, points = r->n_points;
    r->saw_wrap = 0;
    int st = add_geometry(r, g, lines);
    if (st || !r->saw_wrap)
        return st;
    r->n_parts = parts;
    r->n_points = points;
    char wb[200], why[512];
    OGRGeometryH cut = NULL;
    if (dateline_cut(g, r->swap_xy, &cut, why, sizeof why) != 0)
        return fail(r, "%s: %s", where(r, wb, sizeof wb), why);
    if (*owned)
        OGR_G_DestroyGeometry(*owned);
    *owned = cut;
    r->info->dateline_cut++;
    r->saw_wrap = 0;
    st = add_geometry(r, cut, lines);
    if (!st && r->saw_wrap)
        st = fail(r, "%s: internal error: still crosses the antimeridian after the cut",
                  where(r, wb, sizeof wb));
    return st;
}

static int read_feature(reader *r, OGRFeatureH f, uint64_t *lines)
{
    OGRGeometryH g = OGR_F_GetGeometryRef(f);
    r->fid = OGR_F_GetFID(f);
    if (!g || OGR_G_IsEmpty(g)) {
        r->info->skipped_empty++;
        return 0;
    }
    OGRGeometryH lin = NULL;
    if (OGR_G_HasCurveGeometry(g, TRUE)) {
        lin = OGR_G_GetLinearGeometry(g, 0, NULL);
        if (!lin) {
            char wb[200];
            return fail(r, "%s: cannot linearise a curved geometry", where(r, wb, sizeof wb));
        }
        g = lin;
    }
    size_t parts_before = r->n_parts;
    int st = 0;
    r->feature = features_so_far(r);
    r->polygon = has_polygon(g);
    st = read_geometry(r, g, lines, &lin);
    if (!st && r->n_parts > parts_before)
        st = add_feature(r, f);
    if (lin)
        g = lin; /* the linearised geometry, or the cut */
    /* after add_part's checks, so that GEOS never sees NaN */
    if (!st && r->n_parts > parts_before && has_polygon(g))
        st = check_polygon(r, g);
    if (lin)
        OGR_G_DestroyGeometry(lin);
    return st;
}

/* Decides how coordinates are read from the SRS of the first layer. */
static int setup_srs(reader *r, OGRSpatialReferenceH srs)
{
    r->geographic = 0;
    r->swap_xy = 0;
    r->a = 6378137.0;
    r->f = 1.0 / 298.257223563;
    if (!srs)
        return 0;
    if (OSRIsGeographic(srs)) {
        r->geographic = 1;
        OGRErr e1 = OGRERR_NONE, e2 = OGRERR_NONE;
        double a = OSRGetSemiMajor(srs, &e1), rf = OSRGetInvFlattening(srs, &e2);
        if (e1 == OGRERR_NONE && e2 == OGRERR_NONE && a > 0) {
            r->a = a;
            r->f = rf > 0 ? 1.0 / rf : 0.0;
        }
        int count = 0;
        const int *map = OSRGetDataAxisToSRSAxisMapping(srs, &count);
        if (map && count >= 2) {
            OGRAxisOrientation o = OAO_Other;
            int axis = abs(map[0]) - 1;
            OSRGetAxis(srs, "GEOGCS", axis, &o);
            r->swap_xy = o == OAO_North || o == OAO_South;
        }
    }
    return 0;
}

/* "EPSG:4326" or the SRS's name. */
static void srs_label(OGRSpatialReferenceH srs, char *buf, size_t n)
{
    const char *auth = OSRGetAuthorityName(srs, NULL), *code = OSRGetAuthorityCode(srs, NULL);
    const char *name = OSRGetName(srs);
    if (auth && code)
        snprintf(buf, n, "%s:%s%s%s%s", auth, code, name ? " (" : "", name ? name : "",
                 name ? ")" : "");
    else
        snprintf(buf, n, "%s", name ? name : "unnamed SRS");
}

/* The index of field `name` (n bytes) in the layer, or a failure naming
 * the fields; `option` names the option for the message. */
static int find_field(reader *r, OGRLayerH layer, const char *option, const char *name, size_t n,
                      int *index)
{
    OGRFeatureDefnH defn = OGR_L_GetLayerDefn(layer);
    for (int i = 0; i < OGR_FD_GetFieldCount(defn); i++) {
        const char *fn = OGR_Fld_GetNameRef(OGR_FD_GetFieldDefn(defn, i));
        if (strlen(fn) == n && strncmp(fn, name, n) == 0) {
            *index = i;
            return 0;
        }
    }
    char names[200] = "";
    for (int i = 0; i < OGR_FD_GetFieldCount(defn); i++) {
        size_t len = strlen(names);
        snprintf(names + len, sizeof names - len, "%s'%s'", i ? ", " : "",
                 OGR_Fld_GetNameRef(OGR_FD_GetFieldDefn(defn, i)));
    }
    return fail(r, "%s %.*s: layer '%s' has no such field (fields: %s)", option, (int)n, name,
                OGR_L_GetName(layer), names[0] ? names : "none");
}

/* Calls add(r, layer, name, n) for each comma-separated name of list. */
static int each_name(reader *r, OGRLayerH layer, const char *list,
                     int (*add)(reader *, OGRLayerH, const char *, size_t))
{
    for (const char *p = list;;) {
        const char *comma = strchr(p, ',');
        size_t n = comma ? (size_t)(comma - p) : strlen(p);
        int st = add(r, layer, p, n);
        if (st || !comma)
            return st;
        p = comma + 1;
    }
}

static int add_key_field(reader *r, OGRLayerH layer, const char *name, size_t n)
{
    int i;
    if (find_field(r, layer, "--key", name, n, &i))
        return 1;
    int *k = realloc(r->key_index, (r->n_key + 1) * sizeof *k);
    if (!k)
        return fail(r, "out of memory");
    r->key_index = k;
    r->key_index[r->n_key++] = i;
    return 0;
}

/* The --key fields' indices in the layer. A layer without one of them is
 * a failure naming the fields when the layers were chosen with --layer;
 * else its features have no key (us-atlas's 'nation' layer beside
 * 'states'), and read_dataset fails only when no layer has the fields. */
static int find_key_field(reader *r, OGRLayerH layer)
{
    r->n_key = 0;
    if (!r->opt->key_field)
        return 0;
    if (each_name(r, layer, r->opt->key_field, add_key_field) == 0) {
        r->key_found = 1;
        return 0;
    }
    r->n_key = 0;
    if (!r->key_missing[0])
        snprintf(r->key_missing, sizeof r->key_missing, "%s", r->err);
    return r->opt->n_layers ? 1 : 0;
}

/* The attribute type of an OGR field: numbers stay numbers, the rest text. */
static int attr_type_of(OGRFieldType t)
{
    if (t == OFTInteger || t == OFTInteger64)
        return HPFC_ATTR_INTEGER;
    return t == OFTReal ? HPFC_ATTR_REAL : HPFC_ATTR_STRING;
}

static int add_field_index(reader *r, OGRLayerH layer, int i)
{
    OGRFieldDefnH fd = OGR_FD_GetFieldDefn(OGR_L_GetLayerDefn(layer), i);
    OGRFieldType t = OGR_Fld_GetType(fd);
    long c = gis_attrs_column(r->info->attrs, OGR_Fld_GetNameRef(fd), attr_type_of(t));
    if (c < 0 || !array_grow((void **)&r->fields, &r->cap_fields, r->n_fields + 1, sizeof *r->fields))
        return fail(r, "out of memory");
    r->fields[r->n_fields++] = (struct field_map){i, (uint32_t)c, (int)t};
    return 0;
}

static int add_named_field(reader *r, OGRLayerH layer, const char *name, size_t n)
{
    int i;
    return find_field(r, layer, "--fields", name, n, &i) ? 1 : add_field_index(r, layer, i);
}

/* The --fields of the layer, as attribute columns. */
static int find_fields(reader *r, OGRLayerH layer)
{
    r->n_fields = 0;
    if (!r->opt->fields)
        return 0;
    if (strcmp(r->opt->fields, "all") != 0)
        return each_name(r, layer, r->opt->fields, add_named_field);
    for (int i = 0; i < OGR_FD_GetFieldCount(OGR_L_GetLayerDefn(layer)); i++)
        if (add_field_index(r, layer, i))
            return 1;
    return 0;
}

/* Reads the layer's features (gis_read_range: its range's alone);
 * *features counts them, *lines their lines and rings. */
static int read_features(reader *r, OGRLayerH layer, uint64_t *features, uint64_t *lines)
{
    GIntBig total = r->bar.on ? OGR_L_GetFeatureCount(layer, TRUE) : -1;
    uint64_t done = 0;
    int64_t end = r->only ? r->only->end : -1;
    OGR_L_ResetReading(layer);
    CPLErrorReset();
    r->position = 0;
    /* GDAL's contract: the feature the begin-th GetNextFeature gives. The
     * one before it is read too: its FID, the previous range's last,
     * tells the reading whether the driver kept the contract. */
    if (r->only && r->only->begin > 0) {
        OGRFeatureH before = NULL;
        if (OGR_L_SetNextByIndex(layer, r->only->begin - 1) != OGRERR_NONE ||
            !(before = OGR_L_GetNextFeature(layer)))
            return fail(r, "layer '%s': cannot start reading at feature %lld", r->layer_name,
                        (long long)r->only->begin);
        r->kept->has_before = r->kept->has_last = 1;
        r->kept->fid_before = r->kept->fid_last = OGR_F_GetFID(before);
        OGR_F_Destroy(before);
        r->position = r->only->begin;
    }
    OGRFeatureH f;
    while ((end < 0 || r->position < end) && (f = OGR_L_GetNextFeature(layer)) != NULL) {
        ++*features;
        if (r->kept)
            r->kept->has_last = 1, r->kept->fid_last = OGR_F_GetFID(f);
        r->cur = f;
        int st = read_feature(r, f, lines);
        r->position++;
        r->cur = NULL;
        OGR_F_Destroy(f);
        if (st)
            return st; /* read_dataset puts an earlier polygon's failure first */
        if (++done % 256 == 0)
            progress_show(&r->bar, "reading", (double)done, (double)total, 0);
    }
    if (CPLGetLastErrorType() >= CE_Failure)
        return fail(r, "layer '%s': %s", r->layer_name, CPLGetLastErrorMsg());
    return 0;
}

/* The attribute type of a range's value kind. */
static int attr_type_of_kind(uint8_t kind)
{
    return kind == GIS_RANGE_INTEGER ? HPFC_ATTR_INTEGER
           : kind == GIS_RANGE_REAL  ? HPFC_ATTR_REAL
                                     : HPFC_ATTR_STRING;
}

/* A range's feature and its attribute row, as add_feature records them. */
static int take_feature(reader *r, const gis_range *g, const gis_range_feature *ft,
                        const char *name)
{
    r->fid = ft->fid;
    const char *key = ft->key == GIS_RANGE_NONE ? NULL : g->text + ft->key;
    if (gis_features_add(r->info->polygons, ft->position, ft->fid, r->layer_index, key) != 0 ||
        start_row(r) != 0)
        return fail(r, "out of memory");
    for (size_t v = 0; v < ft->values; v++) {
        const gis_range_value *val = &g->values[ft->first_value + v];
        if (attr_type_of_kind(val->kind) != attr_type_of((OGRFieldType)r->fields[val->field].kind))
            return fail(r, "%s: damaged range file: a value of field %u is not of its type", name,
                        val->field);
        int st = val->kind == GIS_RANGE_INTEGER ? set_integer(r, val->field, val->i)
                 : val->kind == GIS_RANGE_REAL  ? set_real(r, val->field, val->r)
                                                : set_string(r, val->field, g->text + val->s);
        if (st)
            return fail(r, "out of memory");
    }
    return 0;
}

/* A range's part, with add_part's checks of a geographic layer's points
 * (those of any layer, finite, the range's decoder made). */
static int take_part(reader *r, const gis_range *g, const gis_range_part *pt, uint32_t base,
                     const char *name)
{
    size_t n = pt->points;
    if (!array_grow((void **)&r->xy, &r->cap_points, r->n_points + n, 2 * sizeof(double)) ||
        !array_grow((void **)&r->start, &r->cap_start, r->n_parts + 2, sizeof(size_t)) ||
        !array_grow((void **)&r->refs, &r->cap_parts, r->n_parts + 1, sizeof(part_ref)))
        return fail(r, "out of memory");
    const double *x = g->xy + 2 * pt->first_point;
    for (size_t i = 0; i < n; i++) {
        double px = x[2 * i], py = x[2 * i + 1];
        if (r->geographic &&
            (px < -180.0 || px > 180.0 || py < -90.0 || py > 90.0 ||
             (i > 0 && dateline_segment_wraps(x[2 * i - 2], x[2 * i - 1], px, py))))
            return fail(r, "%s: damaged range file: a point outside the longitude/latitude "
                           "range, or a segment across the antimeridian",
                        name);
        r->xmin = fmin(r->xmin, px), r->xmax = fmax(r->xmax, px);
        r->ymin = fmin(r->ymin, py), r->ymax = fmax(r->ymax, py);
    }
    memcpy(r->xy + 2 * r->n_points, x, 2 * n * sizeof *x);
    const gis_range_feature *ft = &g->features[pt->feature];
    r->start[r->n_parts] = r->n_points;
    r->refs[r->n_parts] = (part_ref){r->layer_index, ft->fid, base + pt->feature, pt->ring};
    r->n_parts++;
    r->n_points += n;
    r->start[r->n_parts] = r->n_points;
    return 0;
}

/* What another process read of the layer, appended as read_features would
 * have appended it. */
static int take_range(reader *r, const gis_range *g, const char *name)
{
    if (g->fields != r->n_fields)
        return fail(r, "%s: a range file of another reading (%u fields; the layer has %zu)", name,
                    g->fields, r->n_fields);
    uint32_t base = gis_features_count(r->info->polygons);
    if (g->n_features > UINT32_MAX - base)
        return fail(r, "%s: more features than a file holds", name);
    for (size_t f = 0; f < g->n_features; f++)
        if (take_feature(r, g, &g->features[f], name))
            return 1;
    for (size_t p = 0; p < g->n_parts; p++)
        if (take_part(r, g, &g->parts[p], base, name))
            return 1;
    gis_info *info = r->info;
    info->skipped_empty += g->counts.skipped_empty;
    info->skipped_points += g->counts.skipped_points;
    info->dateline_cut += g->counts.dateline_cut;
    if (g->counts.invalid_noded && r->opt->invalid_mode != GIS_INVALID_NODE)
        return fail(r, "%s: a range file of another reading (invalid polygons noded)", name);
    for (uint64_t k = 0; k < g->counts.invalid_noded; k++) {
        info->invalid_noded++;
        if (k < g->n_repaired && note_repaired(r, g->text + g->repaired[k]))
            return 1;
    }
    return 0;
}

/* Range file K's bytes (malloc'ed), the whole file or its first `most`,
 * or a failure. */
static int read_range_file(reader *r, size_t k, size_t most, uint8_t **bytes, size_t *len,
                           char *name, size_t name_len)
{
    snprintf(name, name_len, "%s/range-%zu", r->opt->ranges->dir, k);
    errno = 0;
    FILE *f = fopen(name, "rb");
    long size = -1;
    if (f && fseek(f, 0, SEEK_END) == 0)
        size = ftell(f);
    size_t want = size >= 0 && (unsigned long)size < most ? (size_t)size : most;
    *bytes = size >= 0 && fseek(f, 0, SEEK_SET) == 0 ? malloc(want ? want : 1) : NULL;
    int ok = *bytes && fread(*bytes, 1, want, f) == want;
    int err = ok ? 0 : errno;
    if (f)
        fclose(f);
    if (!ok) {
        free(*bytes);
        return fail(r, "%s: cannot read: %s", name, err ? strerror(err) : "short read");
    }
    *len = want;
    return 0;
}

/* The layer's ranges, read by other processes, taken in order;
 * *features and *lines as read_features counts them. */
static int load_layer(reader *r, uint64_t *features, uint64_t *lines)
{
    int64_t fid_last = 0;
    int has_last = 0;
    for (size_t k = 0; k < r->n_plan; k++) {
        const gis_range_plan *p = &r->plan[k];
        if (p->layer != r->layer_index)
            continue;
        char name[1200], why[256];
        uint8_t *bytes = NULL;
        size_t len = 0;
        if (read_range_file(r, k, SIZE_MAX, &bytes, &len, name, sizeof name))
            return 1;
        gis_range g;
        int st = gis_range_decode(bytes, len, r->tag, p->layer, p->begin, &g, why, sizeof why);
        free(bytes);
        if (st)
            return fail(r, "%s: %s", name, why);
        if (p->end >= 0 && (int64_t)g.counts.read != p->end - p->begin)
            st = fail(r, "layer '%s': %llu features read from feature %lld where %lld were "
                         "counted: the layer changed while it was read",
                      r->layer_name, (unsigned long long)g.counts.read, (long long)p->begin,
                      (long long)(p->end - p->begin));
        /* ranges_chained checked the heads; a file replaced since then
         * must chain too */
        if (!st && has_last && g.fid_before != fid_last)
            st = fail(r, "%s: a range file of another reading (it does not follow the range "
                         "before it)",
                      name);
        has_last = g.has_last, fid_last = g.fid_last;
        if (!st)
            st = take_range(r, &g, name);
        *features += g.counts.read;
        *lines += g.counts.lines;
        gis_range_free(&g);
        if (st)
            return st;
    }
    return 0;
}

static int read_layer(reader *r, OGRLayerH layer, int chosen)
{
    r->layer_name = OGR_L_GetName(layer);
    if (find_key_field(r, layer) != 0 || find_fields(r, layer) != 0 ||
        (!r->kept &&
         gis_features_set_layer(r->info->polygons, r->layer_index, r->layer_name) != 0))
        return r->err[0] ? 1 : fail(r, "out of memory");
    uint64_t features = 0, lines = 0;
    int st = r->plan ? load_layer(r, &features, &lines) : read_features(r, layer, &features, &lines);
    if (st)
        return st;
    r->info->features += features;
    if (r->kept) { /* a range: the layer's totals are for the whole read */
        r->kept->counts.read = features;
        r->kept->counts.lines = lines;
        return 0;
    }
    if (features == 0)
        return fail(r, "layer '%s' is empty (no features)", r->layer_name);
    if (lines == 0)
        return fail(r, "layer '%s' has no line or polygon geometry%s", r->layer_name,
                    chosen ? "" : " (choose layers with --layer)");
    return 0;
}

/* The SRS of -a_srs or -s_srs, with longitude first as GIS data stores it
 * (ogr2ogr does the same); NULL with a failure when GDAL does not know it. */
static OGRSpatialReferenceH user_srs(reader *r)
{
    const char *opt = r->opt->assign_srs ? "-a_srs" : "-s_srs";
    const char *text = r->opt->assign_srs ? r->opt->assign_srs : r->opt->source_srs;
    OGRSpatialReferenceH s = OSRNewSpatialReference(NULL);
    if (!s || OSRSetFromUserInput(s, text) != OGRERR_NONE) {
        if (s)
            OSRDestroySpatialReference(s);
        fail(r, "%s %s: not a spatial reference system GDAL knows (e.g. EPSG:4326, a PROJ "
                "string or WKT)",
             opt, text);
        return NULL;
    }
    OSRSetAxisMappingStrategy(s, OAMS_TRADITIONAL_GIS_ORDER);
    return s;
}

/* Does the layer's extent lie in the longitude/latitude range? */
static int extent_is_lonlat(OGRLayerH layer)
{
    OGREnvelope e;
    if (OGR_L_GetExtent(layer, &e, TRUE) != OGRERR_NONE)
        return 0;
    return e.MinX >= -180.0 && e.MaxX <= 180.0 && e.MinY >= -90.0 && e.MaxY <= 90.0;
}

/* The SRS a layer is read in (borrowed): the one the user gave, else the
 * layer's own; a layer without one whose every coordinate could be a
 * longitude/latitude (TopoJSON, a shapefile without .prj) is taken as WGS 84
 * unless --projection none keeps coordinates as they are. */
static OGRSpatialReferenceH layer_srs(reader *r, OGRLayerH layer)
{
    if (r->given_srs)
        return r->given_srs;
    OGRSpatialReferenceH srs = OGR_L_GetSpatialRef(layer);
    const char *p = r->opt->projection;
    if (srs || (p && strcmp(p, "none") == 0) || !extent_is_lonlat(layer))
        return srs;
    if (!r->assumed_srs) {
        r->assumed_srs = OSRNewSpatialReference(NULL);
        if (!r->assumed_srs || OSRImportFromEPSG(r->assumed_srs, 4326) != OGRERR_NONE)
            return NULL; /* then the layer has no SRS, as before */
        OSRSetAxisMappingStrategy(r->assumed_srs, OAMS_TRADITIONAL_GIS_ORDER);
    }
    if (!r->info->srs_assumed[0])
        snprintf(r->info->srs_assumed, sizeof r->info->srs_assumed, "%s", OGR_L_GetName(layer));
    return r->assumed_srs;
}

/* Opens the dataset (or takes the caller's): NULL with a failure. */
static GDALDatasetH open_dataset(reader *r, const char *path)
{
    /* Reading never writes: GDAL's GML driver would otherwise leave a .gfs
     * schema beside the input, and read it back the next time, so that the
     * same file could pack differently twice. */
    static const char *const open_options[] = {"WRITE_GFS=NO", NULL};
    GDALDatasetH ds = r->given ? r->given
                               : GDALOpenEx(path, GDAL_OF_VECTOR | GDAL_OF_READONLY, NULL,
                                            open_options, NULL);
    if (!ds) {
        /* through GDAL's file layer, so /vsimem/ and /vsizip/ paths are
         * judged as GDAL sees them */
        errno = 0;
        VSILFILE *probe = VSIFOpenL(path, "rb");
        if (!probe)
            return fail(r, "cannot read: %s", errno ? strerror(errno) : "no such file"), NULL;
        VSIFCloseL(probe);
        const char *msg = CPLGetLastErrorMsg();
        if (msg && msg[0])
            return fail(r, "not a vector dataset GDAL can read: %s", msg), NULL;
        return fail(r, "unknown format: not a vector dataset GDAL can read"), NULL;
    }
    GDALDriverH drv = GDALGetDatasetDriver(ds);
    snprintf(r->info->driver, sizeof r->info->driver, "%s",
             drv ? GDALGetDriverShortName(drv) : "GDAL");
    return ds;
}

/* Layer k of those read: the k-th named with --layer, else the dataset's
 * k-th. 0 with *out; -1 to pass over it (a table without geometry, when
 * the layers are not named); 1, a failure, when a named layer is not
 * there. */
static int select_layer(reader *r, GDALDatasetH ds, size_t k, OGRLayerH *out)
{
    int n = GDALDatasetGetLayerCount(ds);
    if (!r->opt->n_layers) {
        *out = GDALDatasetGetLayer(ds, (int)k);
        return OGR_L_GetGeomType(*out) == wkbNone ? -1 : 0;
    }
    if ((*out = GDALDatasetGetLayerByName(ds, r->opt->layers[k])) != NULL)
        return 0;
    char names[200] = "";
    for (int i = 0; i < n; i++) {
        size_t len = strlen(names);
        snprintf(names + len, sizeof names - len, "%s'%s'", i ? ", " : "",
                 OGR_L_GetName(GDALDatasetGetLayer(ds, i)));
    }
    return fail(r, "no layer '%s' (layers: %s)", r->opt->layers[k], names);
}

/* A tag that tells this reading's range files from any other's. */
static uint64_t reading_tag(void)
{
    uint64_t tag = 0;
    FILE *f = fopen("/dev/urandom", "rb");
    if (!f || fread(&tag, sizeof tag, 1, f) != 1)
        tag = (uint64_t)time(NULL) * UINT64_C(0x9e3779b97f4a7c15) ^ (uint64_t)getpid();
    if (f)
        fclose(f);
    return tag;
}

/* Whether each range of a layer starts where the one before it ended, by
 * the FIDs its reader saw (gis_range.h): a driver whose SetNextByIndex
 * does not follow its GetNextFeature (a shapefile with deleted records)
 * would have the ranges overlap or leave features out. When one does not,
 * the features are read here, and the report says why. A file that does
 * not decode is left for load_layer, which refuses it. */
static int ranges_chained(reader *r, GDALDatasetH ds)
{
    gis_range prev = {0}, cur;
    for (size_t k = 0; k < r->n_plan; k++) {
        const gis_range_plan *p = &r->plan[k];
        char name[1200], why[256];
        uint8_t *bytes = NULL;
        size_t len = 0;
        if (read_range_file(r, k, GIS_RANGE_HEAD, &bytes, &len, name, sizeof name)) {
            r->err[0] = 0;
            return 1;
        }
        int st = gis_range_decode_head(bytes, len, r->tag, p->layer, p->begin, &cur, why,
                                       sizeof why);
        free(bytes);
        if (st)
            return 1;
        if (k && p->layer == prev.layer && prev.has_last && cur.fid_before != prev.fid_last) {
            OGRLayerH layer = NULL;
            select_layer(r, ds, p->layer, &layer);
            snprintf(r->info->ranges_declined, sizeof r->info->ranges_declined,
                     "layer '%.60s': its driver's SetNextByIndex does not follow its feature "
                     "order (feature %lld)",
                     layer ? OGR_L_GetName(layer) : "?", (long long)p->begin);
            gis_range_free(&cur);
            gis_range_free(&prev);
            return 0;
        }
        gis_range_free(&prev);
        prev = cur;
    }
    gis_range_free(&prev);
    return 1;
}

/* c * i / pieces without overflow (a driver may count any number). */
static uint64_t share(uint64_t c, uint64_t i, uint64_t pieces)
{
    return c / pieces * i + c % pieces * i / pieces;
}

/* Cuts the `want` layers to read into about opt->ranges->count ranges of
 * equal feature counts and has other processes read them: r->plan is set
 * when they were. A layer GDAL cannot count, or a reader that failed,
 * leaves the features to be read here (which words any failure). */
static int plan_ranges(reader *r, GDALDatasetH ds, size_t want)
{
    const gis_ranges *rg = r->opt->ranges;
    int64_t *count = calloc(want ? want : 1, sizeof *count);
    gis_range_plan *plan = NULL;
    size_t n = 0, cap = 0;
    uint64_t total = 0;
    if (!count)
        return fail(r, "out of memory");
    for (size_t k = 0; k < want; k++) {
        OGRLayerH layer;
        int st = select_layer(r, ds, k, &layer);
        count[k] = st < 0 ? 0 : st > 0 ? -1 : (int64_t)OGR_L_GetFeatureCount(layer, TRUE);
        if (count[k] < 0) {
            r->err[0] = 0; /* the read here says it again, in its place */
            goto here;
        }
        total += (uint64_t)count[k];
    }
    uint64_t size = total / (rg->count ? rg->count : 1) + 1;
    for (size_t k = 0; k < want; k++) {
        uint64_t c = (uint64_t)count[k], pieces = (c + size - 1) / size;
        for (uint64_t i = 0; i < pieces; i++) {
            if (!array_grow((void **)&plan, &cap, n + 1, sizeof *plan)) {
                free(plan);
                free(count);
                return fail(r, "out of memory");
            }
            plan[n++] = (gis_range_plan){(uint32_t)k, (int64_t)share(c, i, pieces),
                                         i + 1 == pieces ? -1 : (int64_t)share(c, i + 1, pieces)};
        }
    }
    r->tag = reading_tag();
    if (n && rg->read(rg->user, plan, n, r->tag) == 0) {
        r->plan = plan, r->n_plan = n;
        if (ranges_chained(r, ds)) {
            free(count);
            return 0;
        }
        r->plan = NULL, r->n_plan = 0;
    }
here:
    free(plan);
    free(count);
    CPLErrorReset();
    return 0;
}

/* gis_read_range: the range's layer alone, in the SRS of the layers a
 * whole read checks are all the same. */
static int read_range_layer(reader *r, GDALDatasetH ds, OGRSpatialReferenceH *srs_out)
{
    size_t want = r->opt->n_layers ? r->opt->n_layers : (size_t)GDALDatasetGetLayerCount(ds);
    OGRLayerH layer;
    int st = r->only->layer < want ? select_layer(r, ds, r->only->layer, &layer) : -1;
    if (st)
        return st > 0 ? 1 : fail(r, "no layer %u with geometry to read", r->only->layer);
    OGRSpatialReferenceH srs = layer_srs(r, layer);
    *srs_out = srs ? OSRClone(srs) : NULL;
    setup_srs(r, *srs_out);
    r->layer_index = r->only->layer;
    st = read_layer(r, layer, r->opt->n_layers != 0);
    r->kept->fields = (uint32_t)r->n_fields;
    return st;
}

/* Opens the dataset and reads the selected layers. */
static int read_dataset(reader *r, const char *path, char **srs_text, OGRSpatialReferenceH *srs_out)
{
    if ((r->opt->assign_srs || r->opt->source_srs) && !(r->given_srs = user_srs(r)))
        return 1;
    GDALDatasetH ds = open_dataset(r, path);
    if (!ds)
        return 1;
    size_t want = r->opt->n_layers ? r->opt->n_layers : (size_t)GDALDatasetGetLayerCount(ds);
    OGRSpatialReferenceH srs0 = NULL;
    const char *name0 = NULL;
    int st = 0;
    if (r->only) {
        st = read_range_layer(r, ds, &srs0);
        name0 = "";
        goto finish;
    }
    if (want == 0)
        st = fail(r, "the dataset has no layer");
    else if (r->opt->ranges && r->opt->ranges->count && !r->given)
        st = plan_ranges(r, ds, want);
    for (size_t k = 0; k < want && !st; k++) {
        OGRLayerH layer;
        int sel = select_layer(r, ds, k, &layer);
        if (sel < 0)
            continue; /* a table without geometry */
        if ((st = sel) != 0)
            break;
        OGRSpatialReferenceH srs = layer_srs(r, layer);
        if (!name0) {
            name0 = OGR_L_GetName(layer);
            srs0 = srs ? OSRClone(srs) : NULL;
            setup_srs(r, srs0);
        } else if ((srs0 == NULL) != (srs == NULL) || (srs && !OSRIsSame(srs0, srs))) {
            st = fail(r, "layers '%s' and '%s' have different spatial reference systems; "
                         "reproject them to one first",
                      name0, OGR_L_GetName(layer));
            break;
        }
        r->layer_index = (uint32_t)k;
        st = read_layer(r, layer, r->opt->n_layers != 0);
        r->info->layers++;
    }
finish:
    /* every polygon's verdict before any failure after them; a failure of
     * the verdicts is the earlier and replaces the message */
    if (polygon_checks_finish(r->checks))
        st = 1;
    if (!st && !name0)
        st = fail(r, "the dataset has no layer with geometry");
    if (!st && !r->only && r->opt->key_field && !r->key_found)
        st = fail(r, "%s", r->key_missing);
    if (!st && srs0 && !r->only) {
        char *p4 = NULL;
        if (OSRExportToProj4(srs0, &p4) == OGRERR_NONE && p4) {
            *srs_text = strdup(p4);
        }
        CPLFree(p4);
    }
    if (!r->given)
        GDALClose(ds);
    *srs_out = srs0;
    return st;
}

/* ---- steps 2-3: projection and lattice ------------------------------------------------ */

/* Data without an SRS taken as longitude/latitude: every point must be one,
 * and since the features were read without cutting, none may cross the
 * antimeridian. */
static int check_assumed_lonlat(reader *r, const char *pname)
{
    for (size_t k = 0; k < r->n_parts; k++)
        for (size_t i = r->start[k]; i < r->start[k + 1]; i++) {
            double px = r->xy[2 * i], py = r->xy[2 * i + 1];
            if (px < -180.0 || px > 180.0 || py < -90.0 || py > 90.0)
                return fail(r, "--projection %s: the input has no SRS and point (%g, %g) is "
                               "not a longitude/latitude",
                            pname, px, py);
            if (i > r->start[k] &&
                dateline_segment_wraps(r->xy[2 * i - 2], r->xy[2 * i - 1], px, py))
                return fail(r, "--projection %s: the input has no SRS and a segment from "
                               "longitude %.9g to %.9g crosses the antimeridian; give the "
                               "input a geographic SRS (ogr2ogr -a_srs EPSG:4326) so that "
                               "it is cut",
                            pname, r->xy[2 * i - 2], px);
        }
    return 0;
}

/* The longitudes the data cover, as the shortest arc [*lo, *hi] (*hi may
 * pass 180) when it is at most a half-turn, so that a projection centres on
 * data that cross the antimeridian (US states with the Aleutians and Guam:
 * the plain extent -180..180 would centre them on Greenwich); wider data
 * keep their plain extent. *mid is the median longitude of the points, where
 * a conic or transverse Mercator puts its central meridian (north up where
 * most of the data are, not in the Pacific between Guam and Puerto Rico).
 * Longitudes are binned by 0.1 degree: the arc and the median are the data's
 * within a bin. Only for an explicit tm, lcc or aea: auto and eqc keep
 * the plain extent, so that data split at the antimeridian (by this reader
 * or in the source) have it as the seam at the map's two ends. */
static void longitude_arc(const reader *r, double *lo, double *hi, double *mid)
{
    enum { BINS = 3600 };
    const double step = 360.0 / BINS;
    size_t *count = calloc(BINS, sizeof *count);
    *lo = r->xmin, *hi = r->xmax, *mid = NAN;
    if (!count || r->n_points == 0) {
        free(count);
        return;
    }
    for (size_t i = 0; i < r->n_points; i++) {
        int b = (int)floor((r->xy[2 * i] + 180.0) / step);
        count[b < 0 ? 0 : b >= BINS ? BINS - 1 : b]++;
    }
    /* the longest circular run of empty bins: the data are the rest */
    int best_len = 0, best_end = -1, run = 0;
    for (int k = 0; k < 2 * BINS; k++) {
        run = count[k % BINS] ? 0 : run + 1;
        if (run > best_len && run < BINS)
            best_len = run, best_end = k % BINS;
    }
    int first = (best_end + 1) % BINS; /* the arc's first bin (0 without a gap) */
    double width = (BINS - best_len) * step, start = first * step - 180.0;
    if (width <= 180.0 && width < (r->xmax - r->xmin) - 1e-9)
        *lo = start, *hi = start + width;
    else
        first = (int)floor((r->xmin + 180.0) / step), start = first * step - 180.0;
    size_t seen = 0;
    for (int k = 0; k < BINS; k++) {
        seen += count[(first + k) % BINS];
        if (2 * seen >= r->n_points) {
            double m = start + (k + 0.5) * step;
            *mid = m > 180.0 ? m - 360.0 : m;
            break;
        }
    }
    free(count);
}

static int project_and_snap(reader *r, OGRSpatialReferenceH srs, const char *srs_p4,
                            int64_t *lat)
{
    mapproj_kind kind = MAPPROJ_AUTO;
    const char *pname = r->opt->projection ? r->opt->projection : "auto";
    if (!mapproj_parse_kind(pname, &kind))
        return fail(r, "unknown projection '%s'", pname);
    char label[256] = "";
    if (srs)
        srs_label(srs, label, sizeof label);
    mapproj_plan *plan = NULL;
    const char *ellps_note = r->info->srs_assumed[0] ? " (assumed: the input has no SRS)" : "";
    if (!srs && kind != MAPPROJ_AUTO && kind != MAPPROJ_NONE) {
        /* no SRS but a projection asked for: take the data as WGS 84 lon/lat */
        r->geographic = 1;
        ellps_note = " (assumed: the input has no SRS)";
        snprintf(label, sizeof label, "EPSG:4326 (WGS 84)");
        if (check_assumed_lonlat(r, pname))
            return 1;
    }
    if (!r->geographic && kind != MAPPROJ_AUTO && kind != MAPPROJ_NONE)
        return fail(r, "--projection %s: the input is already projected (%s); use auto or none",
                    pname, label);
    if (!r->geographic || kind == MAPPROJ_NONE) {
        snprintf(r->info->projection, sizeof r->info->projection, "none");
        if (srs_p4 || label[0]) {
            size_t n = strlen(srs_p4 ? srs_p4 : "") + strlen(label) + 32;
            r->info->crs = malloc(n);
            if (!r->info->crs)
                return fail(r, "out of memory");
            snprintf(r->info->crs, n, "%s; source %s", srs_p4 ? srs_p4 : "", label);
        }
    } else {
        double lon_lo = r->xmin, lon_hi = r->xmax, lon_mid = NAN;
        if (kind == MAPPROJ_TM || kind == MAPPROJ_LCC || kind == MAPPROJ_AEA)
            longitude_arc(r, &lon_lo, &lon_hi, &lon_mid);
        plan = mapproj_create_at(kind, lon_lo, r->ymin, lon_hi, r->ymax, lon_mid, r->a, r->f);
        if (!plan)
            return fail(r, "cannot set up the projection '%s'", pname);
        snprintf(r->info->projection, sizeof r->info->projection, "%s",
                 mapproj_kind_name(mapproj_plan_kind(plan)));
        const char *d = mapproj_describe(plan);
        size_t n = strlen(d) + strlen(label) + strlen(ellps_note) + 32;
        r->info->crs = malloc(n);
        if (!r->info->crs) {
            mapproj_free(plan);
            return fail(r, "out of memory");
        }
        snprintf(r->info->crs, n, "%s; source %s%s", d, label, ellps_note);
        double xmin = INFINITY, ymin = INFINITY, xmax = -INFINITY, ymax = -INFINITY;
        size_t part = 0;
        for (size_t i = 0; i < r->n_points; i++) {
            while (r->start[part + 1] <= i)
                part++;
            double x, y, lon = r->xy[2 * i], la = r->xy[2 * i + 1];
            if (mapproj_forward(plan, lon, la, &x, &y) != 0) {
                mapproj_free(plan);
                return fail(r, "layer %u feature %lld: point (%.9g, %.9g) cannot be projected "
                               "with %s; try another --projection",
                            r->refs[part].layer, (long long)r->refs[part].fid, lon, la,
                            r->info->projection);
            }
            r->xy[2 * i] = x;
            r->xy[2 * i + 1] = y;
            xmin = fmin(xmin, x), xmax = fmax(xmax, x);
            ymin = fmin(ymin, y), ymax = fmax(ymax, y);
            if (i % 65536 == 0)
                progress_show(&r->bar, "projecting", (double)i, (double)r->n_points, 0);
        }
        mapproj_free(plan);
        r->xmin = xmin, r->xmax = xmax, r->ymin = ymin, r->ymax = ymax;
    }
    char why[256];
    if (lattice_choose(r->xmin, r->ymin, r->xmax, r->ymax, &r->info->unit_exp10, why,
                       sizeof why) != 0)
        return fail(r, "%s", why);
    for (size_t i = 0; i < 2 * r->n_points; i++)
        lat[i] = lattice_snap(r->xy[i], r->info->unit_exp10);
    return 0;
}

/* ---- step 4: noding ---------------------------------------------------------------- */

typedef segnode_seg seg;

typedef segnode_pt pt;

static int cmp_i64(int64_t a, int64_t b)
{
    return (a > b) - (a < b);
}

/* By first end, then second end (fields compared one by one: a segment's
 * ends are not pt objects, and reading them as such breaks aliasing). */
static int cmp_seg(const void *a, const void *b)
{
    const seg *p = a, *q = b;
    int c = cmp_i64(p->ax, q->ax);
    c = c ? c : cmp_i64(p->ay, q->ay);
    c = c ? c : cmp_i64(p->bx, q->bx);
    return c ? c : cmp_i64(p->by, q->by);
}

/* Appends segment p-q (p != q) with its ends in order. */
static int push_seg(reader *r, seg **segs, size_t *n, size_t *cap, pt a, pt b)
{
    if (!array_grow((void **)segs, cap, *n + 1, sizeof **segs))
        return fail(r, "out of memory");
    int c = segnode_pt_cmp(&a, &b);
    (*segs)[*n] = (seg){c < 0 ? a.x : b.x, c < 0 ? a.y : b.y, c < 0 ? b.x : a.x,
                        c < 0 ? b.y : a.y};
    ++*n;
    return 0;
}

/* Sorts and deduplicates segs on up to `threads` threads; returns the
 * array, shrunk to *n. */
static seg *sort_unique(seg *segs, size_t *n, unsigned threads)
{
    sort_in_place_threads(segs, *n, sizeof *segs, cmp_seg, threads); /* qsort would double the array */
    size_t u = 0;
    for (size_t i = 0; i < *n; i++)
        if (u == 0 || cmp_seg(&segs[u - 1], &segs[i]) != 0)
            segs[u++] = segs[i];
    *n = u;
    /* a polygon coverage stores each shared border twice: deduplication
     * halves the array, held through the graph's making, the read's peak */
    return array_shrink(segs, u, sizeof *segs);
}

/* The distinct non-degenerate segments of the snapped parts, sorted. */
static int collect_segments(reader *r, const int64_t *lat, seg **out, size_t *n_out)
{
    /* at most one segment a point: one allocation, no doubling */
    size_t n = 0, cap = r->n_points ? r->n_points : 1;
    seg *segs = malloc(cap * sizeof *segs);
    if (!segs)
        return fail(r, "out of memory");
    for (size_t k = 0; k < r->n_parts; k++)
        for (size_t i = r->start[k] + 1; i < r->start[k + 1]; i++) {
            pt a = {lat[2 * i - 2], lat[2 * i - 1]}, b = {lat[2 * i], lat[2 * i + 1]};
            if (segnode_pt_cmp(&a, &b) != 0 && push_seg(r, &segs, &n, &cap, a, b)) {
                free(segs);
                return 1;
            }
        }
    segs = sort_unique(segs, &n, r->opt->threads);
    *out = segs;
    *n_out = n;
    return n ? 0 : fail(r, "nothing left after snapping to the lattice (every line collapsed "
                           "to a point)");
}

/* A GEOS line string of m points (x, y doubles), appended to lines[]. */
static int geos_line(reader *r, const double *xy, unsigned m, GEOSGeometry **lines, size_t *n)
{
    GEOSCoordSequence *cs = GEOSCoordSeq_copyFromBuffer_r(r->geos, xy, m, 0, 0);
    GEOSGeometry *ls = cs ? GEOSGeom_createLineString_r(r->geos, cs) : NULL;
    if (!ls)
        return fail(r, "GEOS: %s", r->geos_msg[0] ? r->geos_msg : "cannot make a line");
    lines[(*n)++] = ls;
    return 0;
}

/* The parts as GEOS line strings (lines[] holds r->n_parts). */
static int lines_of_parts(reader *r, const int64_t *lat, GEOSGeometry **lines, size_t *n_lines)
{
    double *buf = malloc((r->n_points ? r->n_points : 1) * 2 * sizeof(double));
    if (!buf)
        return fail(r, "out of memory");
    int st = 0;
    for (size_t k = 0; k < r->n_parts && !st; k++) {
        size_t m = 0;
        for (size_t i = r->start[k]; i < r->start[k + 1]; i++) {
            double x = (double)lat[2 * i], y = (double)lat[2 * i + 1];
            if (m && buf[2 * m - 2] == x && buf[2 * m - 1] == y)
                continue; /* a zero-length piece */
            buf[2 * m] = x;
            buf[2 * m + 1] = y;
            m++;
        }
        if (m >= 2)
            st = geos_line(r, buf, (unsigned)m, lines, n_lines);
    }
    free(buf);
    return st;
}

/* The segments marked in pick[] as two-point GEOS line strings. */
static int lines_of_segments(reader *r, const seg *segs, size_t n, const unsigned char *pick,
                             GEOSGeometry **lines, size_t *n_lines)
{
    int st = 0;
    for (size_t i = 0; i < n && !st; i++)
        if (pick[i]) {
            double xy[4] = {(double)segs[i].ax, (double)segs[i].ay, (double)segs[i].bx,
                            (double)segs[i].by};
            st = geos_line(r, xy, 2, lines, n_lines);
        }
    return st;
}

/* Appends the segments of GEOS's noded result to *segs; every point must be
 * a lattice point. */
static int collect_noded(reader *r, const GEOSGeometry *noded, seg **segs, size_t *n,
                         size_t *cap)
{
    int ng = GEOSGetNumGeometries_r(r->geos, noded);
    for (int gi = 0; gi < ng; gi++) {
        const GEOSGeometry *g = GEOSGetGeometryN_r(r->geos, noded, gi);
        if (GEOSGeomTypeId_r(r->geos, g) != GEOS_LINESTRING)
            continue;
        const GEOSCoordSequence *cs = GEOSGeom_getCoordSeq_r(r->geos, g);
        unsigned m = 0;
        if (!cs || !GEOSCoordSeq_getSize_r(r->geos, cs, &m))
            continue;
        pt prev = {0, 0};
        for (unsigned i = 0; i < m; i++) {
            double x, y;
            GEOSCoordSeq_getXY_r(r->geos, cs, i, &x, &y);
            pt p = {(int64_t)llround(x), (int64_t)llround(y)};
            if ((double)p.x != x || (double)p.y != y)
                return fail(r, "internal error: GEOS left a point off the lattice (%.17g, %.17g)",
                            x, y);
            if (i > 0 && segnode_pt_cmp(&prev, &p) != 0 && push_seg(r, segs, n, cap, prev, p))
                return 1;
            prev = p;
        }
    }
    return 0;
}

/* Nodes lines[0..n_lines-1] (taken over) with GEOS's snap-rounding union
 * on the unit grid and appends the result's segments to *segs. */
static int geos_node(reader *r, GEOSGeometry **lines, size_t n_lines, seg **segs, size_t *n,
                     size_t *cap)
{
    progress_show(&r->bar, "noding", 0, 0, 1);
    GEOSGeometry *all =
        GEOSGeom_createCollection_r(r->geos, GEOS_MULTILINESTRING, lines, (unsigned)n_lines);
    if (!all) {
        for (size_t k = 0; k < n_lines; k++)
            GEOSGeom_destroy_r(r->geos, lines[k]);
        return fail(r, "GEOS: %s", r->geos_msg[0] ? r->geos_msg : "cannot collect the lines");
    }
    GEOSGeometry *noded = GEOSUnaryUnionPrec_r(r->geos, all, 1.0);
    GEOSGeom_destroy_r(r->geos, all);
    if (!noded)
        return fail(r, "GEOS could not node the linework: %s",
                    r->geos_msg[0] ? r->geos_msg : "unknown error");
    int st = collect_noded(r, noded, segs, n, cap);
    GEOSGeom_destroy_r(r->geos, noded);
    return st;
}

/* The segments a[i] not marked skip[i] and b[0 .. nb), both sorted lists
 * of distinct segments, merged in order, each once: a malloc'ed array of
 * *n_out (no copy of a's kept ones first: a may be most of the map). */
static seg *merge_unique(const seg *a, size_t na, const unsigned char *skip, size_t kept,
                         const seg *b, size_t nb, size_t *n_out)
{
    seg *out = malloc((kept + nb ? kept + nb : 1) * sizeof *out);
    size_t i = 0, j = 0, n = 0;
    while (out && (i < na || j < nb)) {
        if (i < na && skip[i]) {
            i++;
            continue;
        }
        int c = i == na ? 1 : j == nb ? -1 : cmp_seg(&a[i], &b[j]);
        out[n++] = c <= 0 ? a[i] : b[j];
        i += c <= 0, j += c >= 0;
    }
    *n_out = n;
    return out;
}

/* GEOS nodes the segments marked dirty; the clean ones are kept as they
 * are. Fills *out when the result is a planar graph (checked exactly: the
 * clean ones met nothing, so only what meets GEOS's segments can break it),
 * and *geos_out with GEOS's own segments (sorted), else leaves them NULL. */
static int node_partly(reader *r, const seg *segs, size_t n, const unsigned char *dirty,
                       size_t n_dirty, seg **out, size_t *n_out, seg **geos_out,
                       size_t *n_geos_out)
{
    GEOSGeometry **lines = malloc(n_dirty * sizeof *lines);
    seg *merged = NULL;
    size_t n_lines = 0, m = 0, cap = 0;
    int st = lines ? lines_of_segments(r, segs, n, dirty, lines, &n_lines)
                   : fail(r, "out of memory");
    if (st) {
        for (size_t k = 0; k < n_lines; k++)
            GEOSGeom_destroy_r(r->geos, lines[k]);
    } else
        st = geos_node(r, lines, n_lines, &merged, &m, &cap);
    free(lines);
    seg *from_geos = NULL; /* GEOS's segments: the paths of the dirty ones run along them */
    size_t n_geos = m;
    if (!st) {
        from_geos = sort_unique(merged, &n_geos, r->opt->threads);
        merged = NULL;
    }
    /* the clean segments, in segs' sorted order, and GEOS's */
    if (!st && !(merged = merge_unique(segs, n, dirty, n - n_dirty, from_geos, n_geos, &m)))
        st = fail(r, "out of memory");
    if (!st) {
        int near = segnode_any_near(from_geos, n_geos, merged, m);
        if (near < 0)
            st = fail(r, "out of memory");
        else if (near == 0) {
            *out = merged;
            *n_out = m;
            merged = NULL;
            *geos_out = from_geos;
            *n_geos_out = n_geos;
            from_geos = NULL;
        }
    }
    free(from_geos);
    free(merged);
    return st;
}

/* The segments marked dirty, in segs' order (sorted): *out malloc'ed. */
static int keep_dirty(reader *r, const seg *segs, size_t n, const unsigned char *dirty,
                      size_t n_dirty, seg **out, size_t *n_out)
{
    if (!(*out = malloc((n_dirty ? n_dirty : 1) * sizeof **out)))
        return fail(r, "out of memory");
    *n_out = 0;
    for (size_t i = 0; i < n; i++)
        if (dirty[i])
            (*out)[(*n_out)++] = segs[i];
    return 0;
}

/* Nodes the snapped parts; fills *segs with the distinct segments, each
 * with a < b, and *geos with those GEOS made (NULL when it was not called;
 * *segs itself when it noded everything); when GEOS noded a few segments
 * only, *dirty with those (sorted), else NULL. Most segments of a topologically
 * built layer need no noding (segnode.h): when none does, GEOS is not
 * called; when a few do, GEOS nodes those; when that leaves the graph
 * non-planar, or when many do, GEOS nodes all the linework, as it always
 * did. */
static int node(reader *r, const int64_t *lat, seg **segs_out, size_t *n_out, seg **geos,
                size_t *n_geos, seg **dirty_out, size_t *n_dirty_out)
{
    seg *segs = NULL;
    size_t n = 0;
    *dirty_out = NULL;
    *n_dirty_out = 0;
    int st = collect_segments(r, lat, &segs, &n);
    unsigned char *dirty = st ? NULL : calloc(n, 1);
    if (!st && !dirty)
        st = fail(r, "out of memory");
    long long n_dirty = st ? 0 : segnode_find_dirty(segs, n, dirty, r->opt->threads);
    if (n_dirty < 0)
        st = fail(r, "out of memory");
    *segs_out = *geos = NULL;
    *n_geos = 0;
    if (!st && n_dirty == 0) {
        snprintf(r->info->noding, sizeof r->info->noding, "none");
        *segs_out = segs;
        *n_out = n;
        segs = NULL;
    } else if (!st && (size_t)n_dirty <= n / 4) {
        st = node_partly(r, segs, n, dirty, (size_t)n_dirty, segs_out, n_out, geos, n_geos);
        snprintf(r->info->noding, sizeof r->info->noding, "partial");
        r->info->noded_segments = (uint64_t)n_dirty;
        if (!st && *segs_out)
            st = keep_dirty(r, segs, n, dirty, (size_t)n_dirty, dirty_out, n_dirty_out);
    }
    free(dirty);
    free(segs);
    segs = NULL;
    if (st || *segs_out)
        return st;
    /* all the linework, part by part */
    GEOSGeometry **lines = malloc((r->n_parts ? r->n_parts : 1) * sizeof *lines);
    size_t n_lines = 0, cap = 0;
    n = 0;
    if (!lines)
        return fail(r, "out of memory");
    st = lines_of_parts(r, lat, lines, &n_lines);
    if (st) {
        for (size_t k = 0; k < n_lines; k++)
            GEOSGeom_destroy_r(r->geos, lines[k]);
    } else
        st = geos_node(r, lines, n_lines, &segs, &n, &cap);
    free(lines);
    if (st) {
        free(segs);
        return st;
    }
    segs = sort_unique(segs, &n, r->opt->threads);
    snprintf(r->info->noding, sizeof r->info->noding, "all");
    r->info->noded_segments = n;
    *segs_out = *geos = segs;
    *n_out = *n_geos = n;
    return 0;
}

/* ---- step 4b: the parts as they lie in the map ---------------------------------- */

static int has_segment(const seg *segs, size_t n, pt a, pt b)
{
    int c = segnode_pt_cmp(&a, &b);
    seg key = {c < 0 ? a.x : b.x, c < 0 ? a.y : b.y, c < 0 ? b.x : a.x, c < 0 ? b.y : a.y};
    return bsearch(&key, segs, n, sizeof *segs, cmp_seg) != NULL;
}

/* Which segments of the snapped parts are segments of the map: every one
 * when nothing was noded; when GEOS noded a few, those it did not node and
 * those it gave back unchanged; when it noded everything, those it gave
 * back. The short lists are searched where there are some: a search per
 * point in all the map's segments was the stage's largest cost at 10^7
 * points (a cache miss a step), and it grew faster than the map. */
typedef struct map_segments {
    const seg *all, *dirty, *geos; /* geos NULL: nothing noded; geos == all: all noded */
    size_t n_all, n_dirty, n_geos;
} map_segments;

static int in_map(const map_segments *m, pt a, pt b)
{
    if (!m->geos)
        return 1;
    if (m->geos == m->all || !m->dirty)
        return has_segment(m->all, m->n_all, a, b);
    return !has_segment(m->dirty, m->n_dirty, a, b) || has_segment(m->geos, m->n_geos, a, b);
}

/* Appends part k's path through the map to *out: each segment as it is
 * where noding left it alone, else the path GEOS's noding gave it
 * (noded_paths.h; paths: an index over GEOS's segments, NULL when GEOS was
 * not called). */
static int part_in_map(reader *r, const int64_t *lat, size_t k, const map_segments *map,
                       const noded_index *paths, point_list *out)
{
    size_t i0 = r->start[k];
    out->n = 0;
    if (point_list_push(out, lat[2 * i0], lat[2 * i0 + 1]))
        return fail(r, "out of memory");
    for (size_t i = i0 + 1; i < r->start[k + 1]; i++) {
        pt a = {lat[2 * i - 2], lat[2 * i - 1]}, b = {lat[2 * i], lat[2 * i + 1]};
        if (segnode_pt_cmp(&a, &b) == 0)
            continue;
        int st = 1;
        if (in_map(map, a, b))
            st = point_list_push(out, b.x, b.y);
        else if (paths)
            st = noded_path(paths, a.x, a.y, b.x, b.y, out);
        if (st < 0)
            return fail(r, "out of memory");
        if (st > 0)
            return fail(r, "internal error: noding left no path in the map for the segment "
                           "(%lld, %lld)-(%lld, %lld) of layer %u feature %lld",
                        (long long)a.x, (long long)a.y, (long long)b.x, (long long)b.y,
                        r->refs[k].layer, (long long)r->refs[k].fid);
    }
    return 0;
}

/* A line's ends must be vertices of the map: where one line stops and the
 * next goes on through a point of degree 2, an edge running through it
 * would belong to both lines, and each line's geometry would take in the
 * other's. A ring's first point is arbitrary and stays a shape point. */
static int add_line_ends(reader *r, const point_list *part)
{
    if (!array_grow((void **)&r->line_ends, &r->cap_line_ends, r->n_line_ends + 2,
                    sizeof *r->line_ends))
        return fail(r, "out of memory");
    r->line_ends[r->n_line_ends++] = (segnode_pt){part->xy[0], part->xy[1]};
    r->line_ends[r->n_line_ends++] =
        (segnode_pt){part->xy[2 * part->n - 2], part->xy[2 * part->n - 1]};
    return 0;
}

/* Records the features' parts as they lie in the map, for the faces' and
 * edges' features: a ring's area is what its path through the map encloses
 * (face_link.h), so every part segment must be a segment of the map. */
static int keep_parts(reader *r, const int64_t *lat, const map_segments *map)
{
    noded_index *paths = NULL;
    if (map->geos && noded_index_create(map->geos, map->n_geos, &paths))
        return fail(r, "out of memory");
    point_list part = {0};
    int st = 0;
    for (size_t k = 0; k < r->n_parts && !st; k++) {
        st = part_in_map(r, lat, k, map, paths, &part);
        if (!st && !r->refs[k].ring && part.n > 0)
            st = add_line_ends(r, &part);
        if (!st && gis_features_add_part(r->info->polygons, r->refs[k].feature, r->refs[k].ring,
                                         part.xy, part.n) != 0)
            st = fail(r, "out of memory");
    }
    free(part.xy);
    noded_index_free(paths);
    return st;
}

/* ---- step 5: the graph (segment_graph.c) ------------------------------------------ */

static int make_graph(reader *r, const seg *segs, size_t n_segs, hpfc_graph **out)
{
    progress_show(&r->bar, "graph", 0, 0, 1);
    char why[256];
    int st = segment_graph_make(segs, n_segs, r->line_ends, r->n_line_ends,
                                r->opt->vertex_model == GIS_VERTICES_ALL, r->info->unit_exp10,
                                r->opt->threads, out, why, sizeof why);
    return st ? fail(r, "%s", why) : 0;
}

/* ---- entry point ----------------------------------------------------------------- */

int gis_available(void)
{
    return 1;
}

int gis_projection_valid(const char *name)
{
    mapproj_kind k;
    return mapproj_parse_kind(name, &k);
}

/* GDAL and GEOS set up for a read, and the polygons' checks started. */
static void reader_start(reader *r, char *err)
{
    r->bar.on = r->opt->progress;
    r->xmin = r->ymin = INFINITY;
    r->xmax = r->ymax = -INFINITY;
    err[0] = 0;
    /* GDAL speaks through our one-line messages only; GeoJSON objects of
     * any size are read. */
    CPLPushErrorHandler(CPLQuietErrorHandler);
    CPLSetConfigOption("OGR_GEOJSON_MAX_OBJ_SIZE", "0");
    GDALAllRegister();
    r->geos = GEOS_init_r();
    GEOSContext_setErrorMessageHandler_r(r->geos, geos_message, r);
    GEOSContext_setNoticeMessageHandler_r(r->geos, geos_notice, r);
    r->checks = polygon_checks_create(r->opt->threads > 1,
                                      r->opt->invalid_mode != GIS_INVALID_NODE, take_verdict, r);
}

/* What reader_start and the read made, released; err made one line. */
static void reader_end(reader *r, char *srs_p4, OGRSpatialReferenceH srs)
{
    progress_end(&r->bar);
    free(r->xy);
    free(r->start);
    free(r->refs);
    free(r->line_ends);
    free(r->key_index);
    free(r->fields);
    free(r->plan);
    free(srs_p4);
    if (srs)
        OSRDestroySpatialReference(srs);
    if (r->given_srs)
        OSRDestroySpatialReference(r->given_srs);
    if (r->assumed_srs)
        OSRDestroySpatialReference(r->assumed_srs);
    GEOS_finish_r(r->geos);
    CPLPopErrorHandler();
    for (char *c = r->err; *c; c++)
        if (*c == '\n' || *c == '\r')
            *c = ' ';
}

static int read_graph(const char *path, GDALDatasetH given, const gis_options *opt,
                      hpfc_graph **out, gis_info *info, char *err, size_t err_len)
{
    memset(info, 0, sizeof *info);
    reader r = {.opt = opt, .given = given, .info = info, .err = err, .err_len = err_len};
    if (!(info->polygons = gis_features_create(opt->key_field)) ||
        !(info->attrs = gis_attrs_create()) ||
        gis_attrs_column(info->attrs, "source_fid", HPFC_ATTR_INTEGER) != 0) {
        gis_info_free(info);
        snprintf(err, err_len, "out of memory");
        return 1;
    }
    reader_start(&r, err);

    char *srs_p4 = NULL;
    OGRSpatialReferenceH srs = NULL;
    int64_t *lat = NULL;
    seg *segs = NULL;
    size_t n_segs = 0;
    stage_time t = stage_now();
    int st = r.checks ? read_dataset(&r, path, &srs_p4, &srs) : fail(&r, "out of memory");
    polygon_checks_free(r.checks);
    info->points_read = r.n_points;
    info->read_t = stage_lap(&t);
    if (!st) {
        lat = malloc((r.n_points ? r.n_points : 1) * 2 * sizeof *lat);
        st = lat ? project_and_snap(&r, srs, srs_p4, lat) : fail(&r, "out of memory");
    }
    free(r.xy);
    r.xy = NULL;
    free(r.plan);
    r.plan = NULL;
    info->project_t = stage_lap(&t);
    seg *geos = NULL, *dirty = NULL;
    size_t n_geos = 0, n_dirty = 0;
    if (!st)
        st = node(&r, lat, &segs, &n_segs, &geos, &n_geos, &dirty, &n_dirty);
    map_segments map = {segs, dirty, geos, n_segs, n_dirty, n_geos};
    if (!st)
        st = keep_parts(&r, lat, &map);
    if (geos != segs)
        free(geos);
    free(dirty);
    free(lat);
    info->node_t = stage_lap(&t);
    if (!st)
        st = make_graph(&r, segs, n_segs, out);
    info->graph_t = stage_lap(&t);
    free(segs);
    reader_end(&r, srs_p4, srs);
    if (st) {
        gis_info_free(info);
        return 1;
    }
    return 0;
}

/* The parts read, as the range's parts. */
static int keep_parts_read(reader *r)
{
    for (size_t k = 0; k < r->n_parts; k++) {
        size_t n = r->start[k + 1] - r->start[k];
        if (gis_range_add_part(r->kept, r->refs[k].feature, r->xy + 2 * r->start[k], n,
                               r->refs[k].ring) != 0)
            return fail(r, "out of memory");
    }
    return 0;
}

int gis_read_range(const char *path, const gis_options *opt, const gis_range_plan *range,
                   uint64_t tag, uint8_t **bytes, size_t *len, char *err, size_t err_len)
{
    gis_info info;
    memset(&info, 0, sizeof info);
    gis_range kept;
    gis_range_init(&kept, tag, range->layer, 0, range->begin);
    reader r = {.opt = opt, .info = &info, .err = err, .err_len = err_len, .only = range,
                .kept = &kept};
    /* the fields' columns, as a whole read numbers them (the values go to
     * the range) */
    if (!(info.attrs = gis_attrs_create())) {
        snprintf(err, err_len, "out of memory");
        return 1;
    }
    reader_start(&r, err);
    char *srs_p4 = NULL;
    OGRSpatialReferenceH srs = NULL;
    int st = r.checks ? read_dataset(&r, path, &srs_p4, &srs) : fail(&r, "out of memory");
    polygon_checks_free(r.checks);
    if (!st) {
        gis_range_counts *c = &kept.counts;
        c->skipped_empty = info.skipped_empty, c->skipped_points = info.skipped_points;
        c->dateline_cut = info.dateline_cut, c->invalid_noded = info.invalid_noded;
        st = keep_parts_read(&r);
    }
    if (!st && gis_range_encode(&kept, bytes, len) != 0)
        st = fail(&r, "out of memory");
    gis_range_free(&kept);
    reader_end(&r, srs_p4, srs);
    gis_info_free(&info);
    return st;
}

int gis_read_graph(const char *path, const gis_options *opt, hpfc_graph **out, gis_info *info,
                   char *err, size_t err_len)
{
    return read_graph(path, NULL, opt, out, info, err, err_len);
}

int gis_read_graph_dataset(void *dataset, const gis_options *opt, hpfc_graph **out,
                           gis_info *info, char *err, size_t err_len)
{
    return read_graph("dataset", (GDALDatasetH)dataset, opt, out, info, err, err_len);
}

#else /* !HPFC_HAVE_GIS */

int gis_read_graph_dataset(void *dataset, const gis_options *opt, hpfc_graph **out,
                           gis_info *info, char *err, size_t err_len)
{
    (void)dataset;
    return gis_read_graph(NULL, opt, out, info, err, err_len);
}

int gis_available(void)
{
    return 0;
}

int gis_projection_valid(const char *name)
{
    static const char *const names[] = {"auto", "none", "tm", "lcc", "aea", "eqc"};
    for (size_t k = 0; k < sizeof names / sizeof names[0]; k++)
        if (strcmp(name, names[k]) == 0)
            return 1;
    return 0;
}

int gis_read_graph(const char *path, const gis_options *opt, hpfc_graph **out, gis_info *info,
                   char *err, size_t err_len)
{
    (void)path;
    (void)opt;
    (void)out;
    memset(info, 0, sizeof *info);
    snprintf(err, err_len, "GIS input needs GDAL, not built in");
    return 2;
}

int gis_read_range(const char *path, const gis_options *opt, const gis_range_plan *range,
                   uint64_t tag, uint8_t **bytes, size_t *len, char *err, size_t err_len)
{
    (void)path, (void)opt, (void)range, (void)tag, (void)bytes, (void)len;
    snprintf(err, err_len, "GIS input needs GDAL, not built in");
    return 2;
}

#endif

void gis_info_free(gis_info *info)
{
    if (info) {
        free(info->crs);
        info->crs = NULL;
        gis_features_free(info->polygons);
        info->polygons = NULL;
        gis_attrs_free(info->attrs);
        info->attrs = NULL;
    }
}
