/*
 * dateline.c: see dateline.h. GDAL has a WRAPDATELINE option of its own
 * (OGR_GeomTransformer_Create), but in GDAL 3.6 it leaves Natural Earth's
 * Fiji, Russia and Antarctica (as world-atlas stores them) uncut without a
 * word, and it cuts with a GEOS intersection whose crossing points need not
 * be bit-identical for two neighbours sharing a border. This cut is
 * deterministic, exact in its topology, and refuses what it cannot decide.
 */
#include "dateline.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "grow.h"

typedef struct ll {
    double lon, lat;
} ll;

/* A path of the cut polygon in the strip [-180, 180] x [-90, 90]: a piece of
 * a ring between two crossings, or a closing interval along the meridian or
 * a pole line. */
typedef struct chain {
    ll *p;
    size_t n;
    int used;
} chain;

typedef struct cutter {
    int swap;
    char *err;
    size_t err_len;
    chain *chains;
    size_t n_chains, cap_chains;
    double *cross; /* crossing latitudes of the polygon being cut */
    size_t n_cross, cap_cross;
} cutter;

static int fail(cutter *c, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(c->err, c->err_len, fmt, ap);
    va_end(ap);
    return 1;
}

int dateline_segment_wraps(double lon1, double lat1, double lon2, double lat2)
{
    double d = lon1 - lon2;
    return (d > 180.0 || d < -180.0) && lat1 != 90.0 && lat1 != -90.0 && lat2 != 90.0 &&
           lat2 != -90.0;
}

static int wraps(ll a, ll b)
{
    return dateline_segment_wraps(a.lon, a.lat, b.lon, b.lat);
}

static int same(ll a, ll b)
{
    return a.lon == b.lon && a.lat == b.lat;
}

/* The meridian on a point's side: +180 east of Greenwich, -180 west. */
static double side(double lon)
{
    return lon > 0 ? 180.0 : -180.0;
}

/* Where a wrapping segment meets the antimeridian, interpolated from its
 * east end whatever its direction, so that both copies of a shared border
 * give the same bits; an end on the meridian is the crossing itself. */
static double crossing_lat(ll a, ll b)
{
    ll e = a.lon > 0 ? a : b, w = a.lon > 0 ? b : a;
    double de = 180.0 - e.lon, dw = w.lon + 180.0;
    if (de == 0)
        return e.lat;
    if (dw == 0)
        return w.lat;
    return e.lat + (w.lat - e.lat) * (de / (de + dw));
}

/* The points of a line or ring as (lon, lat); malloc'ed, NULL when empty or
 * out of memory (*n says which). */
static ll *load(const cutter *c, OGRGeometryH g, size_t *n)
{
    int count = OGR_G_GetPointCount(g);
    *n = count > 0 ? (size_t)count : 0;
    if (*n == 0)
        return NULL;
    ll *p = malloc(*n * sizeof *p);
    if (!p)
        return NULL;
    OGR_G_GetPoints(g, &p[0].lon, sizeof *p, &p[0].lat, sizeof *p, NULL, 0);
    if (c->swap)
        for (size_t i = 0; i < *n; i++) {
            double t = p[i].lon;
            p[i].lon = p[i].lat;
            p[i].lat = t;
        }
    return p;
}

/* A LineString or LinearRing of the points, in the input's axis order. */
static OGRGeometryH make_curve(const cutter *c, OGRwkbGeometryType type, const ll *p, size_t n)
{
    OGRGeometryH g = OGR_G_CreateGeometry(type);
    if (g)
        OGR_G_SetPoints(g, (int)n, c->swap ? &p[0].lat : &p[0].lon, sizeof *p,
                        c->swap ? &p[0].lon : &p[0].lat, sizeof *p, NULL, 0);
    return g;
}

static void push(ll *buf, size_t *m, ll q)
{
    if (*m == 0 || !same(buf[*m - 1], q))
        buf[(*m)++] = q;
}

/* ---- lines --------------------------------------------------------------------- */

/* Appends the pieces of line `g` between its crossings to `multi`. */
static int cut_line_into(cutter *c, OGRGeometryH g, OGRGeometryH multi)
{
    size_t n;
    ll *p = load(c, g, &n);
    if (!p)
        return n ? fail(c, "out of memory") : 0;
    ll *buf = malloc((n + 2) * sizeof *buf);
    if (!buf) {
        free(p);
        return fail(c, "out of memory");
    }
    size_t m = 0;
    int st = 0;
    buf[m++] = p[0];
    for (size_t i = 0; i + 1 < n && !st; i++) {
        if (wraps(p[i], p[i + 1])) {
            double lat = crossing_lat(p[i], p[i + 1]);
            push(buf, &m, (ll){side(p[i].lon), lat});
            if (m >= 2 && OGR_G_AddGeometryDirectly(multi, make_curve(c, wkbLineString, buf, m)))
                st = fail(c, "cannot store a cut line");
            m = 0;
            push(buf, &m, (ll){side(p[i + 1].lon), lat});
        }
        push(buf, &m, p[i + 1]);
    }
    if (!st && m >= 2 && OGR_G_AddGeometryDirectly(multi, make_curve(c, wkbLineString, buf, m)))
        st = fail(c, "cannot store a cut line");
    free(buf);
    free(p);
    return st;
}

/* ---- polygons ------------------------------------------------------------------ */

static int add_chain(cutter *c, ll *p, size_t n)
{
    if (!array_grow((void **)&c->chains, &c->cap_chains, c->n_chains + 1, sizeof *c->chains)) {
        free(p);
        return fail(c, "out of memory");
    }
    c->chains[c->n_chains++] = (chain){p, n, 0};
    return 0;
}

static int add_segment_chain(cutter *c, ll a, ll b)
{
    ll *p = malloc(2 * sizeof *p);
    if (!p)
        return fail(c, "out of memory");
    p[0] = a;
    p[1] = b;
    return add_chain(c, p, 2);
}

/* Which pole a ring that winds around the globe encloses: -1 south, +1
 * north, 0 when it has points on both sides of the equator (ambiguous). */
static int enclosed_pole(const ll *q, size_t m)
{
    double lo = 90, hi = -90;
    for (size_t i = 0; i < m; i++) {
        lo = q[i].lat < lo ? q[i].lat : lo;
        hi = q[i].lat > hi ? q[i].lat : hi;
    }
    return hi <= 0 && lo < 0 ? -1 : lo >= 0 && hi > 0 ? 1 : 0;
}

/* Splits the closed ring q[0..m-1] (q[m] = q[0] implied) at its k crossings
 * (segments wrap[0..k-1]) into chains from crossing to crossing, and records
 * the crossing latitudes. */
static int ring_pieces(cutter *c, const ll *q, size_t m, const size_t *wrap, size_t k)
{
    for (size_t j = 0; j < k; j++) {
        size_t w = wrap[j], w2 = wrap[(j + 1) % k];
        size_t last = w2 > w ? w2 : w2 + m; /* the vertex before the next crossing */
        ll *buf = malloc((last - w + 2) * sizeof *buf);
        if (!buf)
            return fail(c, "out of memory");
        size_t n = 0;
        double lat = crossing_lat(q[w], q[(w + 1) % m]);
        double lat2 = crossing_lat(q[w2], q[(w2 + 1) % m]);
        push(buf, &n, (ll){side(q[(w + 1) % m].lon), lat});
        for (size_t t = w + 1; t <= last; t++)
            push(buf, &n, q[t % m]);
        push(buf, &n, (ll){side(q[w2].lon), lat2});
        if (add_chain(c, buf, n))
            return 1;
        if (!array_grow((void **)&c->cross, &c->cap_cross, c->n_cross + 1, sizeof *c->cross))
            return fail(c, "out of memory");
        c->cross[c->n_cross++] = lat;
    }
    return 0;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The closing chains: along both meridians over the latitude intervals
 * inside the polygon (parity: crossings toggle, starting inside at -90 when
 * the polygon holds the south pole), and along a pole line the polygon
 * holds. */
static int closing_chains(cutter *c, int south)
{
    qsort(c->cross, c->n_cross, sizeof *c->cross, cmp_double);
    int in = south;
    double prev = -90.0;
    if (south && add_segment_chain(c, (ll){180, -90}, (ll){-180, -90}))
        return 1;
    for (size_t i = 0; i <= c->n_cross; i++) {
        double lat = i < c->n_cross ? c->cross[i] : 90.0;
        if (in && lat > prev &&
            (add_segment_chain(c, (ll){180, prev}, (ll){180, lat}) ||
             add_segment_chain(c, (ll){-180, prev}, (ll){-180, lat})))
            return 1;
        if (i == c->n_cross && in && add_segment_chain(c, (ll){180, 90}, (ll){-180, 90}))
            return 1;
        in = !in;
        prev = lat;
    }
    return 0;
}

/* Joins the chains end to end into closed rings, appended to `rings` (a
 * geometry collection of LinearRings). */
static int assemble(cutter *c, OGRGeometryH rings)
{
    size_t total = 0;
    for (size_t i = 0; i < c->n_chains; i++)
        total += c->chains[i].n;
    ll *buf = malloc((total + 1) * sizeof *buf);
    if (!buf)
        return fail(c, "out of memory");
    int st = 0;
    for (size_t i = 0; i < c->n_chains && !st; i++) {
        if (c->chains[i].used)
            continue;
        size_t m = 0;
        c->chains[i].used = 1;
        for (size_t t = 0; t < c->chains[i].n; t++)
            push(buf, &m, c->chains[i].p[t]);
        while (!st && (m < 2 || !same(buf[m - 1], buf[0]))) {
            size_t j = 0;
            int rev = 0;
            for (; j < c->n_chains; j++) {
                const chain *h = &c->chains[j];
                if (h->used)
                    continue;
                if (same(h->p[0], buf[m - 1]))
                    break;
                if (same(h->p[h->n - 1], buf[m - 1])) {
                    rev = 1;
                    break;
                }
            }
            if (j == c->n_chains) {
                st = fail(c, "cannot close its rings after cutting them at the antimeridian "
                             "(near longitude %.9g, latitude %.9g)",
                          buf[m - 1].lon, buf[m - 1].lat);
                break;
            }
            chain *h = &c->chains[j];
            h->used = 1;
            for (size_t t = 1; t < h->n; t++)
                push(buf, &m, h->p[rev ? h->n - 1 - t : t]);
        }
        if (!st && OGR_G_AddGeometryDirectly(rings, make_curve(c, wkbLinearRing, buf, m)))
            st = fail(c, "cannot store a cut ring");
    }
    free(buf);
    return st;
}

/* Even-odd point in ring. */
static int inside(ll pt, const ll *q, size_t n)
{
    int in = 0;
    for (size_t i = 0, j = n - 1; i < n; j = i++)
        if ((q[i].lat > pt.lat) != (q[j].lat > pt.lat) &&
            pt.lon < (q[j].lon - q[i].lon) * (pt.lat - q[i].lat) / (q[j].lat - q[i].lat) +
                         q[i].lon)
            in = !in;
    return in;
}

/* Makes polygons of the new shells (the assembled rings) and of the rings
 * that crossed nothing: the original shell, if whole, is a shell; each whole
 * hole goes into the first shell holding it (or stands alone, which GEOS's
 * validity check then judges). Appends them to `multi`. */
static int build_polygons(cutter *c, OGRGeometryH shells, OGRGeometryH whole, int shell_whole,
                          OGRGeometryH multi)
{
    int n_shells = OGR_G_GetGeometryCount(shells), n_whole = OGR_G_GetGeometryCount(whole);
    OGRGeometryH *polys = calloc((size_t)(n_shells + n_whole) + 1, sizeof *polys);
    if (!polys)
        return fail(c, "out of memory");
    int n_polys = 0, st = 0;
    for (int i = 0; i < n_shells; i++) {
        polys[n_polys] = OGR_G_CreateGeometry(wkbPolygon);
        OGR_G_AddGeometry(polys[n_polys++], OGR_G_GetGeometryRef(shells, i));
    }
    for (int h = 0; h < n_whole && !st; h++) {
        OGRGeometryH ring = OGR_G_GetGeometryRef(whole, h);
        if (h == 0 && shell_whole) {
            polys[n_polys] = OGR_G_CreateGeometry(wkbPolygon);
            OGR_G_AddGeometry(polys[n_polys++], ring);
            continue;
        }
        size_t n;
        ll *q = load(c, ring, &n);
        if (!q) {
            st = n ? fail(c, "out of memory") : 0;
            continue;
        }
        ll probe = n > 1 ? (ll){(q[0].lon + q[1].lon) / 2, (q[0].lat + q[1].lat) / 2} : q[0];
        free(q);
        int home = -1;
        for (int s = 0; s < n_shells && home < 0; s++) {
            size_t ns;
            ll *sq = load(c, OGR_G_GetGeometryRef(shells, s), &ns);
            if (!sq) {
                st = fail(c, "out of memory");
                break;
            }
            if (inside(probe, sq, ns))
                home = s;
            free(sq);
        }
        if (home < 0) {
            home = n_polys;
            polys[n_polys++] = OGR_G_CreateGeometry(wkbPolygon);
        }
        OGR_G_AddGeometry(polys[home], ring);
    }
    for (int i = 0; i < n_polys; i++)
        if (!st && OGR_G_AddGeometryDirectly(multi, polys[i]) != OGRERR_NONE)
            st = fail(c, "cannot store a cut polygon");
        else if (st)
            OGR_G_DestroyGeometry(polys[i]);
    free(polys);
    return st;
}

static void clear_chains(cutter *c)
{
    for (size_t i = 0; i < c->n_chains; i++)
        free(c->chains[i].p);
    c->n_chains = 0;
    c->n_cross = 0;
}

/* A ring crossing the antimeridian k (odd) times winds around a pole: the
 * pole of the hemisphere holding its points. All such rings of a polygon must
 * wind around the same pole (a band between two parallels of one hemisphere
 * is fine; across the equator, which side is inside is a guess). *pole is 0
 * until the first; *south toggles for each ring around the south pole. */
static int winding_ring(cutter *c, const ll *q, size_t m, size_t k, int *pole, int *south)
{
    int p = enclosed_pole(q, m);
    if (p == 0)
        return fail(c, "a polygon ring winds around a pole (it crosses the antimeridian %s) "
                       "and has points on both sides of the equator: which pole it encloses "
                       "is ambiguous",
                    k == 1 ? "once" : "an odd number of times");
    if (*pole && p != *pole)
        return fail(c, "a polygon has rings winding around the north pole and around the "
                       "south pole: which pole it encloses is ambiguous");
    *pole = p;
    *south ^= p < 0;
    return 0;
}

/* Splits the rings of `poly` into chains (pieces) or whole rings; *south
 * tells whether the polygon holds the south pole. */
static int split_rings(cutter *c, OGRGeometryH poly, OGRGeometryH whole, int *shell_whole,
                       int *south)
{
    int pole = 0, st = 0;
    *south = 0;
    *shell_whole = 0;
    for (int r = 0; r < OGR_G_GetGeometryCount(poly) && !st; r++) {
        OGRGeometryH ring = OGR_G_GetGeometryRef(poly, r);
        size_t n;
        ll *q = load(c, ring, &n);
        if (!q) {
            st = n ? fail(c, "out of memory") : 0;
            continue;
        }
        size_t m = n > 1 && same(q[0], q[n - 1]) ? n - 1 : n; /* distinct points */
        size_t *wrap = malloc((m + 1) * sizeof *wrap), k = 0;
        if (!wrap) {
            free(q);
            return fail(c, "out of memory");
        }
        for (size_t i = 0; i < m; i++)
            if (wraps(q[i], q[(i + 1) % m]))
                wrap[k++] = i;
        if (k == 0) {
            *shell_whole |= r == 0;
            if (OGR_G_AddGeometry(whole, ring) != OGRERR_NONE)
                st = fail(c, "cannot store a ring");
        } else {
            if (k % 2 == 1)
                st = winding_ring(c, q, m, k, &pole, south);
            if (!st)
                st = ring_pieces(c, q, m, wrap, k);
        }
        free(wrap);
        free(q);
    }
    return st;
}

/* Appends the cut of polygon `poly` (or a copy, if it crosses nothing) to
 * the MultiPolygon `multi`. */
static int cut_polygon_into(cutter *c, OGRGeometryH poly, OGRGeometryH multi)
{
    OGRGeometryH whole = OGR_G_CreateGeometry(wkbGeometryCollection);
    OGRGeometryH shells = OGR_G_CreateGeometry(wkbGeometryCollection);
    int shell_whole = 0, south = 0;
    int st = whole && shells ? split_rings(c, poly, whole, &shell_whole, &south)
                             : fail(c, "out of memory");
    if (!st && c->n_chains == 0) {
        OGRGeometryH copy = OGR_G_Clone(poly);
        if (wkbFlatten(OGR_G_GetGeometryType(copy)) != wkbPolygon)
            copy = OGR_G_ForceToPolygon(copy); /* a triangle */
        if (OGR_G_AddGeometryDirectly(multi, copy) != OGRERR_NONE)
            st = fail(c, "cannot store a polygon");
    } else if (!st)
        st = closing_chains(c, south) || assemble(c, shells) ||
             build_polygons(c, shells, whole, shell_whole, multi);
    clear_chains(c);
    if (whole)
        OGR_G_DestroyGeometry(whole);
    if (shells)
        OGR_G_DestroyGeometry(shells);
    return st;
}

/* ---- any geometry ---------------------------------------------------------------- */

static int cut_any(cutter *c, OGRGeometryH g, OGRGeometryH *out)
{
    OGRwkbGeometryType t = wkbFlatten(OGR_G_GetGeometryType(g));
    int st = 0, n = OGR_G_GetGeometryCount(g);
    *out = NULL;
    switch (t) {
    case wkbPolygon:
    case wkbTriangle:
    case wkbMultiPolygon:
        *out = OGR_G_CreateGeometry(wkbMultiPolygon);
        if (t != wkbMultiPolygon)
            return cut_polygon_into(c, g, *out);
        for (int i = 0; i < n && !st; i++)
            st = cut_polygon_into(c, OGR_G_GetGeometryRef(g, i), *out);
        return st;
    case wkbLineString:
    case wkbLinearRing:
    case wkbMultiLineString:
        *out = OGR_G_CreateGeometry(wkbMultiLineString);
        if (t != wkbMultiLineString)
            return cut_line_into(c, g, *out);
        for (int i = 0; i < n && !st; i++)
            st = cut_line_into(c, OGR_G_GetGeometryRef(g, i), *out);
        return st;
    default:
        if (n == 0) {
            *out = OGR_G_Clone(g); /* points */
            return *out ? 0 : fail(c, "out of memory");
        }
        *out = OGR_G_CreateGeometry(wkbGeometryCollection);
        for (int i = 0; i < n && !st; i++) {
            OGRGeometryH part = NULL;
            st = cut_any(c, OGR_G_GetGeometryRef(g, i), &part);
            if (part && OGR_G_AddGeometryDirectly(*out, part) != OGRERR_NONE) {
                OGR_G_DestroyGeometry(part);
                st = st ? st : fail(c, "cannot store a cut geometry");
            }
        }
        return st;
    }
}

int dateline_cut(OGRGeometryH g, int swap_xy, OGRGeometryH *out, char *err, size_t err_len)
{
    cutter c = {.swap = swap_xy, .err = err, .err_len = err_len};
    int st = cut_any(&c, g, out);
    if (st && *out) {
        OGR_G_DestroyGeometry(*out);
        *out = NULL;
    }
    if (!st && !*out)
        st = fail(&c, "out of memory");
    clear_chains(&c);
    free(c.chains);
    free(c.cross);
    return st;
}
