/*
 * queries.c: the topology queries of hpfc-inspect (contracts §6), each one
 * call of the library's hpfc_shapes index, printed as text or one JSON
 * object, or (--dissolve, --mesh with --export) written through GDAL as
 * --export writes features.
 *
 * Coordinates are the file's user coordinates (lattice * 10^unit_exp10),
 * floored onto the lattice; the lon/lat forms go through the projection
 * the CRS section records. Lengths and distances are in metres when the
 * file's CRS says what its unit is: along the WGS 84 ellipsoid for a map
 * hpfc-pack projected from lon/lat (each segment cut into pieces of at
 * most 1 km of the plane, inverse-projected, measured with the
 * ellipsoid's local radii), or the plane's metres for a CRS with
 * +units=m; otherwise in user units ("length", "distance").
 */
#include "queries.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "attrs_json.h"
#include "export_gis.h"
#include "hpfc.h"
#include "jsonw.h"
#include "open_input.h"
#include "projection.h"
#include "views.h"

/* ---- options ------------------------------------------------------------------------ */

static int usage(const char *opt, const char *what)
{
    fprintf(stderr, "hpfc-inspect: %s%s%s (see --help)\n", opt ? opt : "", opt ? ": " : "", what);
    return VIEW_USAGE;
}

int topo_option(int argc, char **argv, int *i, topo_args *t)
{
    struct {
        const char *name;
        const char **slot;
    } opts[] = {{"--neighbours", &t->neighbours}, {"--neighbors", &t->neighbours},
                {"--nearest-lonlat", &t->nearest_lonlat}, {"--nearest", &t->nearest},
                {"--within", &t->within}, {"--dissolve-features", &t->dissolve_features},
                {"--dissolve", &t->dissolve}, {"--mesh", &t->mesh}};
    for (size_t k = 0; k < sizeof opts / sizeof opts[0]; k++) {
        int missing = 0;
        /* --mesh alone is the interior borders: its value is optional when
         * the next word is another option or the last one (FILE) */
        if (strcmp(argv[*i], "--mesh") == 0 && strcmp(opts[k].name, "--mesh") == 0 &&
            (*i + 2 >= argc || argv[*i + 1][0] == '-')) {
            if (t->mesh)
                return usage("--mesh", "given twice");
            t->mesh = "interior";
            return 0;
        }
        const char *v = option_numeric_value(argc, argv, i, opts[k].name, &missing);
        if (!v && !missing)
            continue;
        if (missing)
            return usage(opts[k].name, "missing its value");
        if (*opts[k].slot)
            return usage(opts[k].name, "given twice");
        if (!*v)
            return usage(opts[k].name, "empty value");
        *opts[k].slot = v;
        return 0;
    }
    return -1;
}

int topo_count(const topo_args *t)
{
    return !!(t->window || t->window_lonlat) + !!t->neighbours +
           !!(t->nearest || t->nearest_lonlat) + !!(t->dissolve || t->dissolve_features) +
           !!t->mesh;
}

/* n comma-separated finite decimals. */
static int numbers(const char *text, decimal *d, int n)
{
    if (decimal_list_parse(text, d, n))
        return -1;
    for (int k = 0; k < n; k++)
        if (!isfinite(d[k].value))
            return -1;
    return 0;
}

int topo_check(const topo_args *t)
{
    decimal d[4];
    if (topo_count(t) > 1 || (t->dissolve && t->dissolve_features))
        return usage(NULL, "use one of --window, --neighbours, --nearest, --dissolve, "
                           "--dissolve-features and --mesh");
    if (t->window && t->window_lonlat)
        return usage(NULL, "use one of --window and --window-lonlat");
    if (t->nearest && t->nearest_lonlat)
        return usage(NULL, "use one of --nearest and --nearest-lonlat");
    if (t->window && (numbers(t->window, d, 4) || d[0].value > d[2].value ||
                      d[1].value > d[3].value))
        return usage("--window", "expected X0,Y0,X1,Y1 with X0 <= X1 and Y0 <= Y1");
    if (t->window_lonlat &&
        (numbers(t->window_lonlat, d, 4) || d[0].value > d[2].value || d[1].value > d[3].value ||
         d[0].value < -180 || d[2].value > 180 || d[1].value < -90 || d[3].value > 90))
        return usage("--window-lonlat", "expected W,S,E,N in degrees with W <= E and S <= N");
    if (t->nearest && numbers(t->nearest, d, 2))
        return usage("--nearest", "expected X,Y: two decimal numbers");
    if (t->nearest_lonlat && (numbers(t->nearest_lonlat, d, 2) || fabs(d[0].value) > 180 ||
                              fabs(d[1].value) > 90))
        return usage("--nearest-lonlat", "expected LON,LAT in degrees");
    if (t->within && !(t->nearest || t->nearest_lonlat))
        return usage("--within", "only with --nearest or --nearest-lonlat");
    if (t->within && (numbers(t->within, d, 1) || d[0].value < 0))
        return usage("--within", "expected a distance >= 0 in user units");
    if (t->export_out && !t->dissolve && !t->dissolve_features && !t->mesh)
        return usage("--export",
                     "with a topology query only with --dissolve, --dissolve-features or --mesh");
    return -1;
}

/* ---- the open file --------------------------------------------------------------- */

typedef struct ctx {
    const char *file;
    hpfc_file *f;
    hpfc_file_info info;
    hpfc_shapes *s;
    hpfc_features_info fi;
    int features;
    mapproj_plan *plan;      /* the CRS's projection, when it records one */
    double plane_metres;     /* metres a user unit of the plane, 0: unknown */
    char why[VIEW_WHY];
} ctx;

static int fail(ctx *c, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

static int fail(ctx *c, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(c->why, sizeof c->why, fmt, ap);
    va_end(ap);
    return VIEW_FAIL;
}

static int lib_fail(ctx *c, const char *what, int st)
{
    if (st == HPFC_E_NO_SECTION)
        return fail(c, "%s: the file has no %s", what,
                    c->s ? "features (FEAT section)"
                         : "exact geometry (GEOM and LABL sections); pack it with hpfc-pack 1.2");
    return fail(c, "%s: %s", what, hpfc_strerror(st));
}

static int open_ctx(ctx *c, int lonlat)
{
    errno = 0;
    int st = open_input(c->file, &c->f);
    if (st)
        return fail(c, "%s", st == HPFC_E_IO && errno ? strerror(errno) : hpfc_strerror(st));
    hpfc_file_get_info(c->f, &c->info);
    if ((st = hpfc_shapes_create(c->f, &c->s)))
        return lib_fail(c, "geometry", st);
    c->features = hpfc_file_get_features(c->f, &c->fi) == HPFC_OK;
    if (c->info.crs) {
        char reason[200];
        c->plan = mapproj_from_text(c->info.crs, c->info.crs_len, reason, sizeof reason);
        if (!c->plan && lonlat)
            return fail(c, "cannot place (lon, lat) points: %s", reason);
        if (!c->plan && (strstr(c->info.crs, "+units=m ") || strstr(c->info.crs, "+units=m;")))
            c->plane_metres = 1;
        size_t n = c->info.crs_len;
        if (!c->plan && n >= 8 && memcmp(c->info.crs + n - 8, "+units=m", 8) == 0)
            c->plane_metres = 1;
    } else if (lonlat) {
        return fail(c, "the file records no CRS, so no (lon, lat) can be placed in it");
    }
    return VIEW_OK;
}

static void close_ctx(ctx *c)
{
    hpfc_shapes_free(c->s);
    if (c->plan)
        mapproj_free(c->plan);
    hpfc_close(c->f);
}

static int metric(const ctx *c)
{
    return c->plan || c->plane_metres > 0;
}

/* ---- lengths ------------------------------------------------------------------------- */

/* The length of a straight piece between lon/lat points on WGS 84, from
 * the ellipsoid's radii of curvature at its middle latitude: exact to
 * well under a millimetre for the kilometre pieces measured here. */
static double piece_metres(double lon0, double lat0, double lon1, double lat1)
{
    const double a = 6378137.0, f = 1 / 298.257223563, e2 = f * (2 - f);
    const double rad = 3.14159265358979323846 / 180.0;
    double phi = 0.5 * (lat0 + lat1) * rad, s = sin(phi), w = 1 - e2 * s * s;
    double m = a * (1 - e2) / (w * sqrt(w)), n = a / sqrt(w);
    double dlon = lon1 - lon0;
    if (dlon > 180)
        dlon -= 360;
    else if (dlon < -180)
        dlon += 360;
    double dy = (lat1 - lat0) * rad * m, dx = dlon * rad * n * cos(phi);
    return sqrt(dx * dx + dy * dy);
}

/* The length of the segment between two user points: metres when the
 * file's CRS gives them, else user units. */
static double seg_length(const ctx *c, double x0, double y0, double x1, double y1)
{
    double plane = hypot(x1 - x0, y1 - y0);
    if (!c->plan)
        return c->plane_metres > 0 ? plane * c->plane_metres : plane;
    int pieces = (int)ceil(plane / 1000.0);
    pieces = pieces < 1 ? 1 : pieces > 100000 ? 100000 : pieces;
    double sum = 0, plon = 0, plat = 0;
    for (int k = 0; k <= pieces; k++) {
        double t = (double)k / pieces, lon, lat;
        if (mapproj_inverse(c->plan, x0 + t * (x1 - x0), y0 + t * (y1 - y0), &lon, &lat) != 0)
            return plane; /* off the projection's domain: the plane's */
        if (k)
            sum += piece_metres(plon, plat, lon, lat);
        plon = lon, plat = lat;
    }
    return sum;
}

static double edge_metres(const ctx *c, hpfc_id e)
{
    uint64_t u, v, n;
    double sum = 0, px = 0, py = 0;
    if (hpfc_geometry_edge(c->f, e, &u, &v, &n))
        return 0;
    for (uint64_t k = 0; k < n; k++) {
        int64_t x, y;
        double ux, uy;
        if (hpfc_geometry_edge_point(c->f, e, k, &x, &y))
            return sum;
        hpfc_user_point(c->f, x, y, &ux, &uy);
        if (k)
            sum += seg_length(c, px, py, ux, uy);
        px = ux, py = uy;
    }
    return sum;
}

/* The length a lattice length is in user units. */
static double user_scale(const ctx *c)
{
    double ux, uy;
    hpfc_user_point(c->f, 1, 0, &ux, &uy);
    return ux;
}

/* ---- features ------------------------------------------------------------------------ */

static void json_feature_body(jsonw *w, const ctx *c, hpfc_id k)
{
    hpfc_feature ft;
    const char *layer;
    size_t len;
    if (hpfc_file_get_feature(c->f, k, &ft) != HPFC_OK)
        return;
    jsonw_i64(w, "fid", ft.fid);
    if (c->fi.key_field && ft.key)
        jsonw_string_n(w, "key", ft.key, ft.key_len);
    else if (c->fi.key_field)
        jsonw_null(w, "key");
    if (hpfc_layer_name(c->f, ft.layer, &layer, &len) == HPFC_OK)
        jsonw_string_n(w, "layer", layer, len);
    json_feature_attributes(w, c->f, k);
}

static void text_feature(FILE *out, const ctx *c, hpfc_id k)
{
    hpfc_feature ft;
    if (hpfc_file_get_feature(c->f, k, &ft) != HPFC_OK)
        return;
    fprintf(out, "fid %lld", (long long)ft.fid);
    if (c->fi.key_field && ft.key)
        fprintf(out, " '%.*s'", (int)ft.key_len, ft.key);
}

/* The feature KEY names (its --key value), else the one whose fid is FID:
 * text[0 .. n). */
static int find_feature(ctx *c, const char *opt, const char *text, size_t n, hpfc_id *out)
{
    if (!c->features)
        return fail(c, "%s: the file has no features (FEAT section)", opt);
    char *end;
    errno = 0;
    long long fid = strtoll(text, &end, 10);
    int numeric = end != text && end == text + n && !errno;
    hpfc_id by_fid = HPFC_ID_NONE;
    for (uint32_t k = 0; k < c->fi.features; k++) {
        hpfc_feature ft;
        if (hpfc_file_get_feature(c->f, k, &ft) != HPFC_OK)
            continue;
        if (ft.key && ft.key_len == n && memcmp(ft.key, text, n) == 0) {
            *out = k;
            return VIEW_OK;
        }
        if (numeric && ft.fid == fid && by_fid == HPFC_ID_NONE)
            by_fid = k;
    }
    if (by_fid == HPFC_ID_NONE)
        return fail(c, "%s: '%.*s' names no feature (neither a key nor a fid)", opt, (int)n,
                    text);
    *out = by_fid;
    return VIEW_OK;
}

/* ---- user points ------------------------------------------------------------------- */

static int to_lattice(ctx *c, const decimal *d, int64_t *v, const char *opt)
{
    if (decimal_floor_lattice(d, c->info.unit_exp10, v) || *v < -HPFC_LATTICE_MAX ||
        *v > HPFC_LATTICE_MAX)
        return fail(c, "%s: %.17g is beyond the lattice's range", opt, d->value);
    return VIEW_OK;
}

static int project(ctx *c, double lon, double lat, decimal *xy, const char *opt)
{
    double x, y;
    char t[2][40];
    if (mapproj_forward(c->plan, lon, lat, &x, &y) != 0)
        return fail(c, "%s: (%g, %g) cannot be projected with the file's CRS", opt, lon, lat);
    snprintf(t[0], sizeof t[0], "%.17g", x);
    snprintf(t[1], sizeof t[1], "%.17g", y);
    if (decimal_parse(t[0], strlen(t[0]), &xy[0]) || decimal_parse(t[1], strlen(t[1]), &xy[1]))
        return fail(c, "%s: (%g, %g) projects to no finite point", opt, lon, lat);
    return VIEW_OK;
}

/* ---- --window ------------------------------------------------------------------------ */

static int run_window(ctx *c, const topo_args *t, FILE *out)
{
    decimal d[4];
    int64_t w[4];
    if (t->window) {
        numbers(t->window, d, 4);
    } else {
        /* the box around the projected outline, 32 points a side */
        decimal ll[4];
        numbers(t->window_lonlat, ll, 4);
        double box[4] = {INFINITY, INFINITY, -INFINITY, -INFINITY};
        for (int k = 0; k < 4 * 32; k++) {
            double s = (k % 32) / 32.0, lon, lat;
            int side = k / 32;
            lon = side == 0 ? ll[0].value + s * (ll[2].value - ll[0].value)
                : side == 1 ? ll[2].value
                : side == 2 ? ll[2].value - s * (ll[2].value - ll[0].value)
                            : ll[0].value;
            lat = side == 0 ? ll[1].value
                : side == 1 ? ll[1].value + s * (ll[3].value - ll[1].value)
                : side == 2 ? ll[3].value
                            : ll[3].value - s * (ll[3].value - ll[1].value);
            decimal xy[2];
            if (project(c, lon, lat, xy, "--window-lonlat"))
                return VIEW_FAIL;
            box[0] = fmin(box[0], xy[0].value), box[1] = fmin(box[1], xy[1].value);
            box[2] = fmax(box[2], xy[0].value), box[3] = fmax(box[3], xy[1].value);
        }
        for (int k = 0; k < 4; k++) {
            char text[40];
            snprintf(text, sizeof text, "%.17g", box[k]);
            decimal_parse(text, strlen(text), &d[k]);
        }
    }
    for (int k = 0; k < 4; k++)
        if (to_lattice(c, &d[k], &w[k], t->window ? "--window" : "--window-lonlat"))
            return VIEW_FAIL;
    unsigned what = HPFC_WINDOW_FACES | HPFC_WINDOW_EDGES;
    hpfc_edge_links_info ei;
    if (c->features || hpfc_file_get_edge_links(c->f, &ei) == HPFC_OK)
        what |= HPFC_WINDOW_FEATURES;
    hpfc_window_hits h;
    int st = hpfc_shapes_window(c->s, w[0], w[1], w[2], w[3], what, &h);
    if (st)
        return lib_fail(c, "--window", st);
    double u[4];
    hpfc_user_point(c->f, w[0], w[1], &u[0], &u[1]);
    hpfc_user_point(c->f, w[2], w[3], &u[2], &u[3]);
    size_t fin = 0;
    for (size_t k = 0; k < h.feature_count; k++)
        fin += h.feature_inside[k];
    if (!t->json) {
        fprintf(out, "window %.17g,%.17g %.17g,%.17g: %zu features (%zu inside), %zu faces, "
                     "%zu edges\n",
                u[0], u[1], u[2], u[3], h.feature_count, fin, h.face_count, h.edge_count);
        for (size_t k = 0; k < h.feature_count; k++) {
            fprintf(out, "  ");
            text_feature(out, c, h.feature[k]);
            fprintf(out, " %s\n", h.feature_inside[k] ? "inside" : "crossing");
        }
        return VIEW_OK;
    }
    jsonw j;
    jsonw_init(&j, out);
    jsonw_object_begin(&j, NULL);
    jsonw_string(&j, "file", c->file);
    jsonw_object_begin(&j, "window");
    jsonw_real(&j, "x0", u[0]);
    jsonw_real(&j, "y0", u[1]);
    jsonw_real(&j, "x1", u[2]);
    jsonw_real(&j, "y1", u[3]);
    jsonw_object_end(&j);
    jsonw_array_begin(&j, "features");
    for (size_t k = 0; k < h.feature_count; k++) {
        jsonw_object_begin(&j, NULL);
        json_feature_body(&j, c, h.feature[k]);
        jsonw_bool(&j, "inside", h.feature_inside[k]);
        jsonw_object_end(&j);
    }
    jsonw_array_end(&j);
    jsonw_array_begin(&j, "faces");
    for (size_t k = 0; k < h.face_count; k++) {
        jsonw_object_begin(&j, NULL);
        jsonw_u64(&j, "face", h.face[k]);
        jsonw_bool(&j, "inside", h.face_inside[k]);
        jsonw_object_end(&j);
    }
    jsonw_array_end(&j);
    jsonw_array_begin(&j, "edges");
    for (size_t k = 0; k < h.edge_count; k++) {
        jsonw_object_begin(&j, NULL);
        jsonw_u64(&j, "edge", h.edge[k]);
        jsonw_bool(&j, "inside", h.edge_inside[k]);
        jsonw_object_end(&j);
    }
    jsonw_array_end(&j);
    jsonw_object_end(&j);
    jsonw_finish(&j);
    return VIEW_OK;
}

/* ---- --neighbours ------------------------------------------------------------------- */

static int run_neighbours(ctx *c, const topo_args *t, FILE *out)
{
    hpfc_id self = HPFC_ID_NONE;
    if (find_feature(c, "--neighbours", t->neighbours, strlen(t->neighbours), &self))
        return VIEW_FAIL;
    hpfc_neighbours nb;
    int st = hpfc_shapes_feature_neighbours(c->s, self, &nb);
    if (st)
        return lib_fail(c, "--neighbours", st);
    double *len = malloc((nb.count + 1) * sizeof *len), scale = user_scale(c);
    if (!len)
        return fail(c, "out of memory");
    for (size_t k = 0; k < nb.count; k++) {
        len[k] = 0;
        if (!metric(c))
            len[k] = nb.length[k] * scale;
        else
            for (size_t j = nb.edge_start[k]; j < nb.edge_start[k + 1]; j++)
                len[k] += edge_metres(c, nb.edge[j]);
    }
    const char *unit = metric(c) ? "length_m" : "length";
    if (!t->json) {
        text_feature(out, c, self);
        fprintf(out, ": %zu neighbours\n", nb.count);
        for (size_t k = 0; k < nb.count; k++) {
            fprintf(out, "  ");
            text_feature(out, c, nb.feature[k]);
            if (nb.touch[k] == HPFC_TOUCH_EDGE)
                fprintf(out, " edge, %s %.10g\n", unit, len[k]);
            else
                fprintf(out, " vertex\n");
        }
    } else {
        jsonw j;
        jsonw_init(&j, out);
        jsonw_object_begin(&j, NULL);
        jsonw_string(&j, "file", c->file);
        jsonw_object_begin(&j, "feature");
        json_feature_body(&j, c, self);
        jsonw_object_end(&j);
        jsonw_array_begin(&j, "neighbours");
        for (size_t k = 0; k < nb.count; k++) {
            jsonw_object_begin(&j, NULL);
            json_feature_body(&j, c, nb.feature[k]);
            jsonw_string(&j, "touch", nb.touch[k] == HPFC_TOUCH_EDGE ? "edge" : "vertex");
            jsonw_real(&j, unit, len[k]);
            jsonw_u64(&j, "shared_edges", nb.edge_start[k + 1] - nb.edge_start[k]);
            jsonw_object_end(&j);
        }
        jsonw_array_end(&j);
        jsonw_object_end(&j);
        jsonw_finish(&j);
    }
    free(len);
    return VIEW_OK;
}

/* ---- --nearest ---------------------------------------------------------------------- */

static void json_side(jsonw *j, const ctx *c, uint64_t face, const char *side)
{
    uint32_t n = 0;
    hpfc_id ft;
    if (!c->features || hpfc_face_feature_count(c->f, face, &n))
        return;
    for (uint32_t k = 0; k < n; k++)
        if (hpfc_face_feature_id(c->f, face, k, &ft) == HPFC_OK) {
            jsonw_object_begin(j, NULL);
            json_feature_body(j, c, ft);
            jsonw_string(j, "side", side);
            jsonw_object_end(j);
        }
}

static int run_nearest(ctx *c, const topo_args *t, FILE *out)
{
    decimal d[2], ll[2];
    int lonlat = t->nearest_lonlat != NULL;
    const char *opt = lonlat ? "--nearest-lonlat" : "--nearest";
    if (lonlat) {
        numbers(t->nearest_lonlat, ll, 2);
        if (project(c, ll[0].value, ll[1].value, d, opt))
            return VIEW_FAIL;
    } else {
        numbers(t->nearest, d, 2);
    }
    int64_t x, y;
    if (to_lattice(c, &d[0], &x, opt) || to_lattice(c, &d[1], &y, opt))
        return VIEW_FAIL;
    hpfc_nearest r;
    int st = hpfc_shapes_nearest_edge(c->s, x, y, HPFC_ID_NONE, &r);
    if (st)
        return lib_fail(c, opt, st);
    double scale = user_scale(c), px, py, qx = r.x * scale, qy = r.y * scale;
    hpfc_user_point(c->f, x, y, &px, &py);
    double dist = metric(c) ? seg_length(c, px, py, qx, qy) : r.distance * scale;
    const char *unit = metric(c) ? "distance_m" : "distance";
    hpfc_edge_hits h = {0};
    if (t->within) {
        decimal dw;
        numbers(t->within, &dw, 1);
        double lim = dw.value / scale;
        if (!(lim <= 2.0 * (double)HPFC_LATTICE_MAX))
            return fail(c, "--within: %s is beyond the lattice's range", t->within);
        if ((st = hpfc_shapes_edges_within(c->s, x, y, (int64_t)floor(lim), &h)))
            return lib_fail(c, "--within", st);
    }
    uint64_t left, right;
    if ((st = hpfc_geometry_edge_faces(c->f, r.edge, &left, &right)))
        return lib_fail(c, opt, st);
    double plon = 0, plat = 0;
    if (c->plan && mapproj_inverse(c->plan, qx, qy, &plon, &plat) != 0)
        plon = plat = NAN;
    if (!t->json) {
        fprintf(out, "nearest edge %llu (segment %llu) at %s %.10g, closest point %.17g,%.17g",
                (unsigned long long)r.edge, (unsigned long long)r.segment, unit, dist, qx, qy);
        if (c->plan)
            fprintf(out, " (lon %.9f, lat %.9f)", plon, plat);
        fprintf(out, "\n");
        if (t->within)
            fprintf(out, "%zu edges within %s\n", h.count, t->within);
        return VIEW_OK;
    }
    jsonw j;
    jsonw_init(&j, out);
    jsonw_object_begin(&j, NULL);
    jsonw_string(&j, "file", c->file);
    jsonw_object_begin(&j, "query");
    jsonw_real(&j, "x", px);
    jsonw_real(&j, "y", py);
    if (lonlat) {
        jsonw_real(&j, "lon", ll[0].value);
        jsonw_real(&j, "lat", ll[1].value);
    }
    jsonw_object_end(&j);
    jsonw_u64(&j, "edge", r.edge);
    jsonw_u64(&j, "segment", r.segment);
    jsonw_real(&j, unit, dist);
    jsonw_object_begin(&j, "point");
    jsonw_real(&j, "x", qx);
    jsonw_real(&j, "y", qy);
    if (c->plan) {
        jsonw_real(&j, "lon", plon);
        jsonw_real(&j, "lat", plat);
    }
    jsonw_object_end(&j);
    jsonw_array_begin(&j, "features");
    json_side(&j, c, left, "left");
    json_side(&j, c, right, "right");
    uint32_t n = 0;
    size_t faces;
    hpfc_id ft;
    if (c->features && hpfc_edge_feature_count(c->f, r.edge, &n) == HPFC_OK)
        for (uint32_t k = 0; k < n; k++)
            if (hpfc_edge_feature_id(c->f, r.edge, k, &ft) == HPFC_OK &&
                hpfc_shapes_feature_faces(c->s, ft, NULL, 0, &faces) == HPFC_OK && !faces) {
                /* lines along the edge (a polygon's are its sides above) */
                jsonw_object_begin(&j, NULL);
                json_feature_body(&j, c, ft);
                jsonw_string(&j, "side", "along");
                jsonw_object_end(&j);
            }
    jsonw_array_end(&j);
    if (t->within) {
        jsonw_array_begin(&j, "within");
        for (size_t k = 0; k < h.count; k++) {
            jsonw_object_begin(&j, NULL);
            jsonw_u64(&j, "edge", h.edge[k]);
            jsonw_real(&j, "distance", h.distance[k] * scale);
            jsonw_object_end(&j);
        }
        jsonw_array_end(&j);
    }
    jsonw_object_end(&j);
    jsonw_finish(&j);
    return VIEW_OK;
}

/* ---- groups by a field -------------------------------------------------------------- */

typedef struct groups {
    uint32_t count;      /* groups */
    uint32_t *of;        /* per feature: its group, HPFC_GROUP_NONE for a null value */
    char **value;        /* per group: its value as text */
    hpfc_id *members;    /* features by group */
    size_t *start;       /* count + 1 */
} groups;

static void groups_free(groups *g)
{
    for (uint32_t k = 0; g->value && k < g->count; k++)
        free(g->value[k]);
    free(g->value);
    free(g->of);
    free(g->members);
    free(g->start);
}

typedef struct keyed {
    char *text;
    uint32_t feature;
} keyed;

static int cmp_keyed(const void *pa, const void *pb)
{
    const keyed *a = pa, *b = pb;
    int c = strcmp(a->text, b->text);
    return c ? c : (a->feature > b->feature) - (a->feature < b->feature);
}

/* The features grouped by the value of column FIELD (null values in no
 * group), groups in the order of their values' text. */
static int group_by(ctx *c, const char *field, const char *opt, groups *g)
{
    memset(g, 0, sizeof *g);
    if (!c->features)
        return fail(c, "%s: the file has no features (FEAT section)", opt);
    uint32_t col;
    int type;
    const char *name;
    size_t nlen;
    if (hpfc_attr_find(c->f, field, strlen(field), &col) != HPFC_OK) {
        char list[160] = "";
        size_t used = 0;
        for (uint32_t k = 0; hpfc_attr_column(c->f, k, &name, &nlen, &type) == HPFC_OK; k++)
            used += (size_t)snprintf(list + used, used < sizeof list ? sizeof list - used : 0,
                                     "%s%.*s", k ? ", " : "", (int)nlen, name);
        return fail(c, "%s: no attribute '%s' (the file has: %s)", opt, field,
                    list[0] ? list : "none");
    }
    uint32_t n = c->fi.features;
    keyed *kv = calloc((size_t)n + 1, sizeof *kv);
    g->of = malloc(((size_t)n + 1) * sizeof *g->of);
    if (!kv || !g->of) {
        free(kv);
        return fail(c, "out of memory");
    }
    size_t m = 0;
    int r = VIEW_OK;
    for (uint32_t k = 0; k < n && !r; k++) {
        hpfc_attr_value v;
        g->of[k] = HPFC_GROUP_NONE;
        int st = hpfc_file_get_attr_value(c->f, k, col, &v);
        if (st) {
            r = lib_fail(c, opt, st);
            break;
        }
        char buf[64];
        const char *s = buf;
        size_t len;
        if (v.type == HPFC_ATTR_NULL)
            continue;
        if (v.type == HPFC_ATTR_STRING)
            s = v.s, len = v.len;
        else if (v.type == HPFC_ATTR_INTEGER)
            len = (size_t)snprintf(buf, sizeof buf, "%lld", (long long)v.i);
        else
            len = (size_t)snprintf(buf, sizeof buf, "%.17g", v.r);
        kv[m].text = malloc(len + 1);
        if (!kv[m].text) {
            r = fail(c, "out of memory");
            break;
        }
        memcpy(kv[m].text, s, len);
        kv[m].text[len] = '\0';
        kv[m++].feature = k;
    }
    if (!r && m)
        qsort(kv, m, sizeof *kv, cmp_keyed);
    g->value = calloc(m + 1, sizeof *g->value);
    g->members = malloc((m + 1) * sizeof *g->members);
    g->start = malloc((m + 2) * sizeof *g->start);
    if (!r && (!g->value || !g->members || !g->start))
        r = fail(c, "out of memory");
    for (size_t k = 0; k < m && !r; k++) {
        if (k == 0 || strcmp(kv[k].text, g->value[g->count - 1])) {
            g->start[g->count] = k;
            g->value[g->count++] = kv[k].text;
            kv[k].text = NULL;
        }
        g->members[k] = kv[k].feature;
        g->of[kv[k].feature] = g->count - 1;
    }
    if (g->start)
        g->start[g->count] = m;
    for (size_t k = 0; k < m; k++)
        free(kv[k].text);
    free(kv);
    return r;
}

static int cmp_id(const void *pa, const void *pb)
{
    hpfc_id a = *(const hpfc_id *)pa, b = *(const hpfc_id *)pb;
    return (a > b) - (a < b);
}

/* One group: the features LIST names (comma-separated KEY|FID, each as
 * --neighbours takes it; one named twice counts once), its value the list. */
static int group_list(ctx *c, const char *list, const char *opt, groups *g)
{
    memset(g, 0, sizeof *g);
    size_t items = 1;
    for (const char *p = list; *p; p++)
        items += *p == ',';
    size_t len = strlen(list);
    g->value = calloc(2, sizeof *g->value);
    g->members = malloc(items * sizeof *g->members);
    g->start = malloc(2 * sizeof *g->start);
    if (!g->value || !g->members || !g->start || !(g->value[0] = malloc(len + 1)))
        return fail(c, "out of memory");
    memcpy(g->value[0], list, len + 1);
    g->count = 1;
    size_t m = 0;
    for (const char *p = list;; p++) {
        const char *comma = strchr(p, ',');
        size_t n = comma ? (size_t)(comma - p) : strlen(p);
        if (n == 0)
            return fail(c, "%s: an empty item in '%s'", opt, list);
        if (find_feature(c, opt, p, n, &g->members[m++]))
            return VIEW_FAIL;
        if (!comma)
            break;
        p = comma;
    }
    qsort(g->members, m, sizeof *g->members, cmp_id);
    size_t u = 0;
    for (size_t k = 0; k < m; k++)
        if (u == 0 || g->members[k] != g->members[u - 1])
            g->members[u++] = g->members[k];
    g->start[0] = 0, g->start[1] = u;
    return VIEW_OK;
}

/* ---- --dissolve and --mesh ------------------------------------------------------------ */

/* Twice the signed area of an answer's rings, in lattice units squared
 * (double: a report, not a predicate). */
static double area2(const hpfc_polygons *p)
{
    double a = 0;
    for (size_t r = 0; r < p->ring_count; r++)
        for (size_t k = p->ring_point[r]; k + 1 < p->ring_point[r + 1]; k++)
            a += (double)p->xy[2 * k] * (double)p->xy[2 * k + 3] -
                 (double)p->xy[2 * k + 2] * (double)p->xy[2 * k + 1];
    return a;
}

typedef struct layer_ctx {
    groups *g;             /* --dissolve */
    hpfc_polygons mesh;    /* --mesh */
} layer_ctx;

static int dissolve_item(void *vc, hpfc_shapes *s, size_t k, hpfc_polygons *p,
                         const char **value, size_t *len)
{
    layer_ctx *l = vc;
    *value = l->g->value[k];
    *len = strlen(*value);
    return hpfc_shapes_features_polygons(s, l->g->members + l->g->start[k],
                                         l->g->start[k + 1] - l->g->start[k], p);
}

/* The mesh, one line a feature of the layer: a view of line k of the
 * answer of our own index (its offsets index the answer's points), which
 * stays valid while the exporter runs. */
static int mesh_item(void *vc, hpfc_shapes *s, size_t k, hpfc_polygons *p, const char **value,
                     size_t *len)
{
    const layer_ctx *l = vc;
    static const size_t none = 0;
    (void)s;
    *value = NULL, *len = 0;
    *p = (hpfc_polygons){.polygon_count = 0,
                         .ring_count = 1,
                         .point_count = l->mesh.point_count,
                         .polygon_ring = &none,
                         .ring_point = l->mesh.ring_point + k,
                         .xy = l->mesh.xy};
    return HPFC_OK;
}

static int export_layer(ctx *c, const topo_args *t, gis_custom_layer *layer, FILE *out)
{
    gis_export_options o = {.file = c->file, .open = c->f, .output = t->export_out,
                            .driver = t->driver, .json = t->json, .custom = layer};
    if (export_gis(&o, out))
        return fail(c, "--export failed (the reason is above)");
    return VIEW_OK;
}

/* --dissolve FIELD (a group per value) or --dissolve-features LIST (one). */
static int run_dissolve(ctx *c, const topo_args *t, FILE *out)
{
    groups g;
    const char *opt = t->dissolve ? "--dissolve" : "--dissolve-features";
    const char *field = t->dissolve ? t->dissolve : "features";
    int r = t->dissolve ? group_by(c, t->dissolve, opt, &g)
                        : group_list(c, t->dissolve_features, opt, &g);
    if (!r && t->export_out) {
        layer_ctx l = {.g = &g};
        gis_custom_layer layer = {.name = "dissolved", .field = field, .count = g.count,
                                  .item = dissolve_item, .ctx = &l};
        r = export_layer(c, t, &layer, out);
        groups_free(&g);
        return r;
    }
    jsonw j;
    if (!r && t->json) {
        jsonw_init(&j, out);
        jsonw_object_begin(&j, NULL);
        jsonw_string(&j, "file", c->file);
        jsonw_string(&j, t->dissolve ? "field" : "features", t->dissolve ? field : t->dissolve_features);
        jsonw_array_begin(&j, "groups");
    }
    double scale = user_scale(c);
    for (uint32_t k = 0; k < g.count && !r; k++) {
        hpfc_polygons p;
        size_t n = g.start[k + 1] - g.start[k];
        int st = hpfc_shapes_features_polygons(c->s, g.members + g.start[k], n, &p);
        if (st) {
            r = lib_fail(c, opt, st);
            break;
        }
        double area = area2(&p) / 2 * scale * scale;
        size_t holes = p.ring_count - p.polygon_count;
        if (t->json) {
            jsonw_object_begin(&j, NULL);
            jsonw_string(&j, "value", g.value[k]);
            jsonw_u64(&j, "features", n);
            jsonw_u64(&j, "polygons", p.polygon_count);
            jsonw_u64(&j, "holes", holes);
            jsonw_u64(&j, "points", p.point_count);
            jsonw_real(&j, "area", area);
            jsonw_object_end(&j);
        } else {
            fprintf(out, "%s: %zu features, %zu polygons, %zu holes, %zu points, area %.10g\n",
                    g.value[k], n, p.polygon_count, holes, p.point_count, area);
        }
    }
    if (!r && t->json) {
        jsonw_array_end(&j);
        jsonw_object_end(&j);
        jsonw_finish(&j);
    }
    groups_free(&g);
    return r;
}

static int run_mesh(ctx *c, const topo_args *t, FILE *out)
{
    groups g = {0};
    unsigned sides = HPFC_MESH_INTERIOR;
    int by_field = 0;
    if (strcmp(t->mesh, "exterior") == 0)
        sides = HPFC_MESH_EXTERIOR;
    else if (strcmp(t->mesh, "all") == 0)
        sides = HPFC_MESH_INTERIOR | HPFC_MESH_EXTERIOR;
    else if (strcmp(t->mesh, "interior") != 0)
        by_field = 1;
    if (!c->features)
        return fail(c, "--mesh: the file has no features (FEAT section)");
    if (by_field && group_by(c, t->mesh, "--mesh", &g))
        return VIEW_FAIL;
    hpfc_polygons p;
    int st = hpfc_shapes_mesh(c->s, by_field ? g.of : NULL, c->fi.features, sides, &p);
    if (st) {
        groups_free(&g);
        return lib_fail(c, "--mesh", st);
    }
    int r = VIEW_OK;
    if (t->export_out) {
        layer_ctx l = {.mesh = p};
        gis_custom_layer layer = {.name = "mesh", .lines = 1, .count = p.ring_count,
                                  .item = mesh_item, .ctx = &l};
        r = export_layer(c, t, &layer, out);
        groups_free(&g);
        return r;
    }
    double length = 0, scale = user_scale(c);
    for (size_t q = 0; q < p.ring_count; q++)
        for (size_t k = p.ring_point[q]; k + 1 < p.ring_point[q + 1]; k++)
            length += seg_length(c, (double)p.xy[2 * k] * scale, (double)p.xy[2 * k + 1] * scale,
                                 (double)p.xy[2 * k + 2] * scale, (double)p.xy[2 * k + 3] * scale);
    const char *unit = metric(c) ? "length_m" : "length";
    if (t->json) {
        jsonw j;
        jsonw_init(&j, out);
        jsonw_object_begin(&j, NULL);
        jsonw_string(&j, "file", c->file);
        jsonw_string(&j, "mesh", t->mesh);
        jsonw_u64(&j, "lines", p.ring_count);
        jsonw_u64(&j, "points", p.point_count);
        jsonw_real(&j, unit, length);
        jsonw_object_end(&j);
        jsonw_finish(&j);
    } else {
        fprintf(out, "mesh %s: %zu lines, %zu points, %s %.10g\n", t->mesh, p.ring_count,
                p.point_count, unit, length);
    }
    groups_free(&g);
    return r;
}

int topo_run(const char *file, const topo_args *t, FILE *out)
{
    ctx c = {.file = file};
    int r = open_ctx(&c, t->window_lonlat || t->nearest_lonlat);
    if (!r) {
        if (t->window || t->window_lonlat)
            r = run_window(&c, t, out);
        else if (t->neighbours)
            r = run_neighbours(&c, t, out);
        else if (t->nearest || t->nearest_lonlat)
            r = run_nearest(&c, t, out);
        else if (t->dissolve || t->dissolve_features)
            r = run_dissolve(&c, t, out);
        else
            r = run_mesh(&c, t, out);
    }
    if (r)
        fprintf(stderr, "hpfc-inspect: %s: %s\n", file, c.why);
    close_ctx(&c);
    return r ? 1 : 0;
}
