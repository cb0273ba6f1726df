/*
 * ogr_shapes.c: ogr_shapes.h over GDAL's C API and projection.h.
 */
#include "ogr_shapes.h"

#include "ogr_curve.h"

#include <ctype.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cpl_error.h>

static int fail(ogr_shapes *o, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

static int fail(ogr_shapes *o, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(o->why, sizeof o->why, fmt, ap);
    va_end(ap);
    return 1;
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

/* Whether the CRS text of a hostile file is safe to hand to PROJ: a PROJ
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

static int setup_srs(ogr_shapes *o)
{
    snprintf(o->srs_name, sizeof o->srs_name, "none");
    hpfc_file_info fi;
    hpfc_file_get_info(o->f, &fi);
    if (!fi.crs)
        return 0;
    crs_parts p;
    split_crs(fi.crs, fi.crs_len, &p);
    OGRSpatialReferenceH source = p.code[0] ? srs_from(p.code, 0) : NULL;
    /* The description's SRS only stands in for a missing source SRS: with
     * one, parsing it (a PROJ object, some 0.3 ms) would be wasted. */
    OGRSpatialReferenceH desc = !source && p.desc[0] ? srs_from(p.desc, 1) : NULL;
    int back = made_by_pack(p.desc) && (!source || OSRIsGeographic(source));
    if (back) {
        char reason[200];
        o->plan = mapproj_from_text(p.desc, strlen(p.desc), reason, sizeof reason);
        if (!o->plan) {
            if (source)
                OSRDestroySpatialReference(source);
            if (desc)
                OSRDestroySpatialReference(desc);
            return fail(o, "cannot project back to the source SRS: %s", reason);
        }
        if (!source && desc) { /* the geographic SRS on the projection's ellipsoid */
            source = OSRCloneGeogCS(desc);
            if (source)
                OSRSetAxisMappingStrategy(source, OAMS_TRADITIONAL_GIS_ORDER);
        }
        o->srs = source;
        if (desc)
            OSRDestroySpatialReference(desc);
    } else {
        o->srs = source ? source : desc;
    }
    if (o->srs) {
        const char *auth = OSRGetAuthorityName(o->srs, NULL);
        const char *code = OSRGetAuthorityCode(o->srs, NULL);
        const char *name = OSRGetName(o->srs);
        if (auth && code)
            snprintf(o->srs_name, sizeof o->srs_name, "%s:%s", auth, code);
        else
            snprintf(o->srs_name, sizeof o->srs_name, "%s", name ? name : "unnamed");
    }
    return 0;
}

int ogr_shapes_init(ogr_shapes *o, const hpfc_file *f, hpfc_shapes *shapes)
{
    memset(o, 0, sizeof *o);
    o->f = f;
    o->shapes = shapes;
    hpfc_file_info info;
    hpfc_file_get_info(f, &info);
    o->unit_exp10 = info.unit_exp10;
    return setup_srs(o);
}

void ogr_shapes_release(ogr_shapes *o)
{
    mapproj_free(o->plan);
    if (o->srs) /* a reference: the GDAL driver's layers may hold more */
        OSRRelease(o->srs);
    o->plan = NULL, o->srs = NULL;
}

/* ---- geometry ---------------------------------------------------------------------- */

int ogr_shapes_points(ogr_shapes *o, const int64_t *xy, size_t n, double *out)
{
    /* both steps in one pass where the projection can (the world layers'
     * equirectangular plan), else one pass each: the same doubles */
    size_t done = o->plan ? mapproj_inverse_lattice(o->plan, xy, n, o->unit_exp10, out)
                          : MAPPROJ_NOT_HANDLED;
    if (done == MAPPROJ_NOT_HANDLED) {
        hpfc_user_points(o->f, xy, n, out);
        done = o->plan ? mapproj_inverse_points(o->plan, out, n) : n;
    }
    if (done < n) /* out[2 * done] is still the user point: the projection stopped there */
        return fail(o, "point (%.17g, %.17g) cannot be projected back", out[2 * done],
                    out[2 * done + 1]);
    return 0;
}

int ogr_shapes_point(ogr_shapes *o, int64_t x, int64_t y, double *ox, double *oy)
{
    const int64_t xy[2] = {x, y};
    double out[2];
    if (ogr_shapes_points(o, xy, 1, out))
        return 1;
    *ox = out[0], *oy = out[1];
    return 0;
}

/* n lattice points (pairs) into out (pairs), in output coordinates, a chunk
 * at a time: the scaling's and the projection's passes over a chunk find
 * it in the cache where a pass over a whole large ring would not. */
enum { CHUNK_POINTS = 1024 };

static int convert_points(ogr_shapes *o, const int64_t *xy, size_t n, double *out)
{
    for (size_t at = 0; at < n; at += CHUNK_POINTS) {
        size_t m = n - at < CHUNK_POINTS ? n - at : CHUNK_POINTS;
        if (ogr_shapes_points(o, xy + 2 * at, m, out + 2 * at))
            return 1;
    }
    return 0;
}

/* A new curve of type t for n points, converted by the caller into *out,
 * OGR's own array (ogr_curve.h); NULL with o->why set. */
static OGRGeometryH new_curve(ogr_shapes *o, OGRwkbGeometryType t, size_t n, double **out)
{
    OGRGeometryH g = ogr_curve_create(t, n, out);
    if (!g)
        fail(o, "%zu points: out of memory", n);
    return g;
}

/* The points [a, b) of an answer as a new curve of type t. */
static OGRGeometryH curve(ogr_shapes *o, const hpfc_polygons *p, size_t r, OGRwkbGeometryType t)
{
    size_t a = p->ring_point[r], b = p->ring_point[r + 1];
    double *out;
    OGRGeometryH g = new_curve(o, t, b - a, &out);
    if (g && convert_points(o, p->xy + 2 * a, b - a, out)) {
        OGR_G_DestroyGeometry(g);
        return NULL;
    }
    o->points += g ? b - a : 0;
    return g;
}

OGRGeometryH ogr_shapes_polygon(ogr_shapes *o, const hpfc_polygons *p, size_t k)
{
    OGRGeometryH poly = OGR_G_CreateGeometry(wkbPolygon);
    for (size_t r = p->polygon_ring[k]; poly && r < p->polygon_ring[k + 1]; r++) {
        OGRGeometryH ring = curve(o, p, r, wkbLinearRing);
        if (!ring) {
            OGR_G_DestroyGeometry(poly);
            return NULL;
        }
        OGR_G_AddGeometryDirectly(poly, ring);
        o->rings++;
    }
    if (!poly)
        fail(o, "out of memory");
    o->polygons++;
    return poly;
}

OGRGeometryH ogr_shapes_multipolygon(ogr_shapes *o, const hpfc_polygons *p)
{
    OGRGeometryH mp = OGR_G_CreateGeometry(wkbMultiPolygon);
    for (size_t k = 0; mp && k < p->polygon_count; k++) {
        OGRGeometryH poly = ogr_shapes_polygon(o, p, k);
        if (!poly) {
            OGR_G_DestroyGeometry(mp);
            return NULL;
        }
        OGR_G_AddGeometryDirectly(mp, poly);
    }
    if (!mp)
        fail(o, "out of memory");
    o->skipped_holes += p->ring_count - p->polygon_ring[p->polygon_count];
    return mp;
}

OGRGeometryH ogr_shapes_multiline(ogr_shapes *o, const hpfc_polygons *p)
{
    OGRGeometryH ml = OGR_G_CreateGeometry(wkbMultiLineString);
    for (size_t r = 0; ml && r < p->ring_count; r++) {
        OGRGeometryH line = curve(o, p, r, wkbLineString);
        if (!line) {
            OGR_G_DestroyGeometry(ml);
            return NULL;
        }
        OGR_G_AddGeometryDirectly(ml, line);
        o->lines++;
    }
    if (!ml)
        fail(o, "out of memory");
    return ml;
}

int ogr_shapes_feature_geometry(ogr_shapes *o, hpfc_id k, OGRGeometryH *g)
{
    *g = NULL;
    size_t faces;
    hpfc_polygons p;
    int st = hpfc_shapes_feature_faces(o->shapes, k, NULL, 0, &faces);
    if (!st && faces) {
        if ((st = hpfc_shapes_feature_polygons(o->shapes, k, &p)))
            return fail(o, "feature %llu: %s", (unsigned long long)k, hpfc_strerror(st));
        return !(*g = ogr_shapes_multipolygon(o, &p));
    }
    if (st)
        return fail(o, "feature %llu: %s", (unsigned long long)k, hpfc_strerror(st));
    st = hpfc_shapes_feature_polylines(o->shapes, k, &p);
    if (st == HPFC_E_NO_SECTION || (!st && p.ring_count == 0))
        return 0;
    if (st)
        return fail(o, "feature %llu: %s", (unsigned long long)k, hpfc_strerror(st));
    return !(*g = ogr_shapes_multiline(o, &p));
}

OGRGeometryH ogr_shapes_face_geometry(ogr_shapes *o, hpfc_id face)
{
    hpfc_polygons p;
    int st = hpfc_shapes_face_polygons(o->shapes, face, &p);
    if (st) {
        fail(o, "face %llu: %s", (unsigned long long)face, hpfc_strerror(st));
        return NULL;
    }
    if (p.polygon_count != 1) {
        fail(o, "face %llu: %zu outer rings, where a bounded face has one%s",
             (unsigned long long)face, p.polygon_count, face ? " (corrupt file)" : "");
        return NULL;
    }
    return ogr_shapes_polygon(o, &p, 0);
}

OGRGeometryH ogr_shapes_edge_geometry(ogr_shapes *o, hpfc_id edge)
{
    hpfc_id u, v;
    uint64_t n;
    int st = hpfc_geometry_edge(o->f, edge, &u, &v, &n);
    if (!st && n > SIZE_MAX / 2)
        st = HPFC_E_CORRUPT;
    if (st) {
        fail(o, "edge %llu: %s", (unsigned long long)edge, hpfc_strerror(st));
        return NULL;
    }
    double *out;
    OGRGeometryH g = new_curve(o, wkbLineString, (size_t)n, &out);
    for (uint64_t k = 0; g && k < n; k++) {
        int64_t x, y;
        if ((st = hpfc_geometry_edge_point(o->f, edge, k, &x, &y)))
            fail(o, "edge %llu: %s", (unsigned long long)edge, hpfc_strerror(st));
        if (st || ogr_shapes_point(o, x, y, &out[2 * k], &out[2 * k + 1])) {
            OGR_G_DestroyGeometry(g);
            return NULL;
        }
    }
    if (g) {
        o->points += n;
        o->lines++;
    }
    return g;
}

int ogr_shapes_layer_types(ogr_shapes *o, OGRwkbGeometryType *types, uint64_t *counts,
                           uint32_t layers)
{
    uint8_t *kinds = malloc(layers ? layers : 1);
    if (!kinds)
        return fail(o, "out of memory");
    int st = hpfc_shapes_layer_kinds(o->shapes, kinds, counts, layers);
    for (uint32_t l = 0; !st && l < layers; l++)
        types[l] = kinds[l] == (HPFC_KIND_POLYGONS | HPFC_KIND_LINES) ? wkbUnknown
                   : kinds[l] == HPFC_KIND_POLYGONS                  ? wkbMultiPolygon
                                                                      : wkbMultiLineString;
    free(kinds);
    return st ? fail(o, "feature layers: %s", hpfc_strerror(st)) : 0;
}

/* ---- fields ------------------------------------------------------------------------ */

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

/* Whether an ATTR column is named `name`. */
static int attr_has(const hpfc_file *f, const char *name)
{
    uint32_t c;
    return hpfc_attr_find(f, name, strlen(name), &c) == HPFC_OK;
}

void ogr_shapes_fields_free(ogr_shapes_field *fields, size_t count)
{
    for (size_t k = 0; fields && k < count; k++)
        free(fields[k].name);
    free(fields);
}

int ogr_shapes_fields(ogr_shapes *o, int with_fid, ogr_shapes_field **out, size_t *count)
{
    *out = NULL, *count = 0;
    hpfc_attrs_info ai;
    int st = hpfc_file_get_attrs(o->f, &ai);
    if (st && st != HPFC_E_NO_SECTION)
        return fail(o, "attributes: %s", hpfc_strerror(st));
    uint64_t columns = st ? 0 : ai.columns;
    if (columns > ai.section_bytes) /* each column takes bytes of the section */
        return fail(o, "attributes: %s", hpfc_strerror(HPFC_E_CORRUPT));
    ogr_shapes_field *f = calloc(columns + 2, sizeof *f);
    if (!f)
        return fail(o, "out of memory");
    size_t n = 0;
    int r = 0;
    if (with_fid && !attr_has(o->f, "fid")) {
        f[n] = (ogr_shapes_field){dup_n("fid", 3), OFTInteger64, OGR_SHAPES_FID};
        r = !f[n++].name;
    }
    hpfc_features_info fi;
    if (!r && hpfc_file_get_features(o->f, &fi) == HPFC_OK && fi.key_field) {
        char *key = dup_n(fi.key_field, fi.key_field_len);
        r = !key;
        if (key && attr_has(o->f, key))
            free(key);
        else if (key)
            f[n++] = (ogr_shapes_field){key, OFTString, OGR_SHAPES_KEY};
    }
    for (uint32_t c = 0; !r && c < columns; c++) {
        const char *name;
        size_t len;
        int type;
        if ((st = hpfc_attr_column(o->f, c, &name, &len, &type))) {
            ogr_shapes_fields_free(f, n);
            return fail(o, "attribute column %u: %s", c, hpfc_strerror(st));
        }
        OGRFieldType t = type == HPFC_ATTR_INTEGER ? OFTInteger64
                         : type == HPFC_ATTR_REAL  ? OFTReal
                                                   : OFTString;
        f[n] = (ogr_shapes_field){dup_n(name, len), t, c};
        r = !f[n++].name;
    }
    if (r) {
        ogr_shapes_fields_free(f, n);
        return fail(o, "out of memory");
    }
    *out = f, *count = n;
    return 0;
}

static int set_string(ogr_shapes *o, OGRFeatureH ft, int field, const char *s, size_t n)
{
    char *v = dup_n(s, n);
    if (!v)
        return fail(o, "out of memory");
    OGR_F_SetFieldString(ft, field, v);
    free(v);
    return 0;
}

int ogr_shapes_fill(ogr_shapes *o, OGRFeatureH ft, int first, const ogr_shapes_field *fields,
                    size_t count, hpfc_id k, const hpfc_feature *feat)
{
    for (size_t c = 0; c < count; c++) {
        int field = first + (int)c;
        if (fields[c].source == OGR_SHAPES_FID) {
            OGR_F_SetFieldInteger64(ft, field, feat->fid);
            continue;
        }
        hpfc_attr_value v = {.type = HPFC_ATTR_NULL};
        if (fields[c].source == OGR_SHAPES_KEY) {
            if (feat->key)
                v = (hpfc_attr_value){.type = HPFC_ATTR_STRING, .s = feat->key,
                                      .len = feat->key_len};
        } else {
            int st = hpfc_file_get_attr_value(o->f, k, (uint32_t)fields[c].source, &v);
            if (st)
                return fail(o, "feature %llu, attribute %lld: %s", (unsigned long long)k,
                            (long long)fields[c].source, hpfc_strerror(st));
        }
        if (v.type == HPFC_ATTR_INTEGER)
            OGR_F_SetFieldInteger64(ft, field, v.i);
        else if (v.type == HPFC_ATTR_REAL)
            OGR_F_SetFieldDouble(ft, field, v.r);
        else if (v.type == HPFC_ATTR_STRING) {
            if (set_string(o, ft, field, v.s, v.len))
                return 1;
        } else
            OGR_F_SetFieldNull(ft, field);
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

int ogr_shapes_face_features(ogr_shapes *o, OGRFeatureH ft, hpfc_id face, int count_field,
                             int fids_field, int keys_field)
{
    uint32_t n = 0;
    if (hpfc_face_feature_count(o->f, face, &n) != HPFC_OK) {
        if (count_field >= 0)
            OGR_F_SetFieldInteger(ft, count_field, 0);
        return 0;
    }
    text fids = {0}, keys = {0};
    int r = 0;
    for (uint32_t k = 0; k < n && !r; k++) {
        hpfc_id index;
        hpfc_feature feat;
        char buf[32];
        int st = hpfc_face_feature_id(o->f, face, k, &index);
        if (!st)
            st = hpfc_file_get_feature(o->f, index, &feat);
        if (st) {
            r = fail(o, "face %llu: %s", (unsigned long long)face, hpfc_strerror(st));
            break;
        }
        snprintf(buf, sizeof buf, "%lld", (long long)feat.fid);
        if (text_add(&fids, " ", buf, strlen(buf)) ||
            (keys_field >= 0 && text_add(&keys, "|", feat.key ? feat.key : "",
                                         feat.key ? feat.key_len : 0)))
            r = fail(o, "out of memory");
    }
    if (!r) {
        if (count_field >= 0)
            OGR_F_SetFieldInteger(ft, count_field, (int)n);
        OGR_F_SetFieldString(ft, fids_field, fids.s ? fids.s : "");
        if (keys_field >= 0)
            OGR_F_SetFieldString(ft, keys_field, keys.s ? keys.s : "");
    }
    free(fids.s);
    free(keys.s);
    return r;
}
