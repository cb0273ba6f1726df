// projection.cc: projection.h over GeographicLib. The parameters are printed
// first and parsed back, so the recorded description is exactly what
// projects the data.
#include "projection.h"

#include <GeographicLib/AlbersEqualArea.hpp>
#include <GeographicLib/LambertConformalConic.hpp>
#include <GeographicLib/TransverseMercator.hpp>

#ifdef __SSE2__
#include <emmintrin.h>
#endif

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <new>
#include <stdexcept>
#include <string>

struct mapproj_plan {
    mapproj_kind kind;
    double lon0, lat0;   // central meridian, latitude of the origin
    double y0;           // northing of (lon0, lat0) in the library's frame
    double a, f;
    double x_0, y_0;     // false easting and northing (parsed plans only)
    GeographicLib::TransverseMercator *tm;
    GeographicLib::LambertConformalConic *lcc;
    GeographicLib::AlbersEqualArea *aea;
    std::string text;
};

static const char *const kind_names[] = {"auto", "none", "tm", "lcc", "aea", "eqc"};

extern "C" int mapproj_parse_kind(const char *name, mapproj_kind *out)
{
    for (int k = 0; k < 6; k++)
        if (std::strcmp(name, kind_names[k]) == 0) {
            *out = (mapproj_kind)k;
            return 1;
        }
    return 0;
}

extern "C" const char *mapproj_kind_name(mapproj_kind kind)
{
    return (unsigned)kind < 6 ? kind_names[kind] : "?";
}

// A parameter as it will be printed: nine significant digits are plenty to
// centre a projection, and keep the description short.
static double rounded(double v)
{
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return std::strtod(buf, nullptr);
}

static std::string fmt(const char *key, double v)
{
    char buf[64];
    std::snprintf(buf, sizeof buf, " +%s=%.9g", key, v);
    return buf;
}

static std::string ellipsoid(double a, double f)
{
    if (a == 6378137.0 && std::fabs(1.0 / f - 298.257223563) < 1e-9)
        return " +ellps=WGS84";
    if (a == 6378137.0 && std::fabs(1.0 / f - 298.257222101) < 1e-9)
        return " +ellps=GRS80";
    char buf[96];
    if (f == 0.0)
        std::snprintf(buf, sizeof buf, " +R=%.17g", a);
    else
        std::snprintf(buf, sizeof buf, " +a=%.17g +rf=%.17g", a, 1.0 / f);
    return buf;
}

static mapproj_kind choose(double lon_min, double lat_min, double lon_max, double lat_max)
{
    double dlon = lon_max - lon_min;
    if (dlon <= 12.0 && lat_min >= -84.0 && lat_max <= 84.0)
        return MAPPROJ_TM;
    if (dlon <= 150.0 && lat_min >= -84.0 && lat_max <= 84.0)
        return MAPPROJ_LCC;
    return MAPPROJ_EQC;
}

static void build(mapproj_plan *p, double lat_min, double lat_max)
{
    double span = lat_max - lat_min;
    double s1 = rounded(lat_min + span / 6), s2 = rounded(lat_max - span / 6);
    std::string head;
    switch (p->kind) {
    case MAPPROJ_TM:
        p->tm = new GeographicLib::TransverseMercator(p->a, p->f, 1.0);
        head = "+proj=tmerc" + fmt("lat_0", p->lat0) + fmt("lon_0", p->lon0) + " +k=1";
        break;
    case MAPPROJ_LCC:
        p->lcc = s1 == s2 ? new GeographicLib::LambertConformalConic(p->a, p->f, s1, 1.0)
                          : new GeographicLib::LambertConformalConic(p->a, p->f, s1, s2, 1.0);
        head = "+proj=lcc" + fmt("lat_0", p->lat0) + fmt("lon_0", p->lon0) + fmt("lat_1", s1) +
               fmt("lat_2", s2);
        break;
    case MAPPROJ_AEA:
        p->aea = s1 == s2 ? new GeographicLib::AlbersEqualArea(p->a, p->f, s1, 1.0)
                          : new GeographicLib::AlbersEqualArea(p->a, p->f, s1, s2, 1.0);
        head = "+proj=aea" + fmt("lat_0", p->lat0) + fmt("lon_0", p->lon0) + fmt("lat_1", s1) +
               fmt("lat_2", s2);
        break;
    default: // MAPPROJ_EQC, on the sphere of radius a as PROJ's eqc does
        p->lat0 = 0.0;
        head = "+proj=eqc +lat_ts=0 +lat_0=0" + fmt("lon_0", p->lon0);
        break;
    }
    p->y0 = 0.0;
    double x, y;
    if (p->kind != MAPPROJ_EQC && mapproj_forward(p, p->lon0, p->lat0, &x, &y) == 0)
        p->y0 = y;
    p->text = head + " +x_0=0 +y_0=0" + ellipsoid(p->a, p->f) + " +units=m +no_defs";
}

extern "C" mapproj_plan *mapproj_create(mapproj_kind kind, double lon_min, double lat_min,
                                  double lon_max, double lat_max, double a, double f)
{
    return mapproj_create_at(kind, lon_min, lat_min, lon_max, lat_max, NAN, a, f);
}

extern "C" mapproj_plan *mapproj_create_at(mapproj_kind kind, double lon_min, double lat_min,
                                           double lon_max, double lat_max, double lon0, double a,
                                           double f)
{
    mapproj_plan *p = new (std::nothrow) mapproj_plan();
    if (!p)
        return nullptr;
    p->kind = kind == MAPPROJ_AUTO ? choose(lon_min, lat_min, lon_max, lat_max) : kind;
    double mid = (lon_min + lon_max) / 2; // lon_max may pass 180 (an arc across the antimeridian)
    if (p->kind != MAPPROJ_EQC && std::isfinite(lon0))
        mid = lon0;
    p->lon0 = rounded(mid > 180.0 ? mid - 360.0 : mid);
    p->lat0 = rounded((lat_min + lat_max) / 2);
    p->a = a;
    p->f = f;
    try {
        if (p->kind != MAPPROJ_NONE)
            build(p, lat_min, lat_max);
    } catch (const std::exception &) {
        mapproj_free(p);
        return nullptr;
    }
    return p;
}

extern "C" void mapproj_free(mapproj_plan *p)
{
    if (!p)
        return;
    delete p->tm;
    delete p->lcc;
    delete p->aea;
    delete p;
}

extern "C" mapproj_kind mapproj_plan_kind(const mapproj_plan *p)
{
    return p->kind;
}

extern "C" int mapproj_forward(const mapproj_plan *p, double lon, double lat, double *x, double *y)
{
    const double deg = M_PI / 180.0;
    switch (p->kind) {
    case MAPPROJ_NONE:
        *x = lon;
        *y = lat;
        break;
    case MAPPROJ_TM:
        p->tm->Forward(p->lon0, lat, lon, *x, *y);
        break;
    case MAPPROJ_LCC:
        p->lcc->Forward(p->lon0, lat, lon, *x, *y);
        break;
    case MAPPROJ_AEA:
        p->aea->Forward(p->lon0, lat, lon, *x, *y);
        break;
    default: {
        *x = p->a * (lon - p->lon0) * deg;
        *y = p->a * lat * deg;
        break;
    }
    }
    *y -= p->y0;
    *x += p->x_0;
    *y += p->y_0;
    return std::isfinite(*x) && std::isfinite(*y) ? 0 : -1;
}

// The equirectangular inverse of (x, y) already moved to the projection's
// origin: mapproj_inverse's and mapproj_inverse_points' one formula.
static void eqc_back(const mapproj_plan *p, double x, double y, double *lon, double *lat)
{
    const double unit = p->a * (M_PI / 180.0);
    *lon = x / unit + p->lon0;
    *lat = y / unit;
}

extern "C" int mapproj_inverse(const mapproj_plan *p, double x, double y, double *lon,
                               double *lat)
{
    x -= p->x_0;
    y -= p->y_0;
    y += p->y0;
    switch (p->kind) {
    case MAPPROJ_NONE:
        *lon = x;
        *lat = y;
        break;
    case MAPPROJ_TM:
        p->tm->Reverse(p->lon0, x, y, *lat, *lon);
        break;
    case MAPPROJ_LCC:
        p->lcc->Reverse(p->lon0, x, y, *lat, *lon);
        break;
    case MAPPROJ_AEA:
        p->aea->Reverse(p->lon0, x, y, *lat, *lon);
        break;
    default:
        eqc_back(p, x, y, lon, lat);
        break;
    }
    return std::isfinite(*lon) && std::isfinite(*lat) ? 0 : -1;
}

static void put_back_on_the_globe(double *lon, double *lat)
{
    if (*lon > 180.0)
        *lon = *lon <= 180.0 + 1e-6 ? 180.0 : *lon - 360.0;
    else if (*lon < -180.0)
        *lon = *lon >= -180.0 - 1e-6 ? -180.0 : *lon + 360.0;
    *lat = *lat > 90.0 ? 90.0 : *lat < -90.0 ? -90.0 : *lat;
}

// One point of mapproj_inverse's equirectangular case; false when it is not
// finite (xy[2k] and xy[2k + 1] then left as they were).
static bool eqc_inverse_point(const mapproj_plan *p, double *xy)
{
    double lon, lat;
    eqc_back(p, xy[0] - p->x_0, xy[1] - p->y_0 + p->y0, &lon, &lat);
    if (!std::isfinite(lon) || !std::isfinite(lat))
        return false;
    put_back_on_the_globe(&lon, &lat);
    xy[0] = lon, xy[1] = lat;
    return true;
}

#ifdef __SSE2__
// eqc_back on one point as a pair of lanes, x low and y high, each lane
// with exactly its scalar operations (an addition of zero would turn -0
// into +0): x - x_0, y - y_0 + y0, both / unit, lon0 added to x alone.
static __m128d eqc_back_pair(__m128d v, __m128d origin, __m128d y0, __m128d unit, __m128d lon0)
{
    v = _mm_sub_pd(v, origin);
    v = _mm_move_sd(_mm_add_pd(v, y0), v);  // y0 added to the high lane only
    v = _mm_div_pd(v, unit);
    return _mm_move_sd(v, _mm_add_pd(v, lon0));  // lon0 added to the low lane only
}
#endif

// mapproj_inverse's equirectangular case in a loop of its own, without a
// call and a switch a point: the world layers' projection, whose inverse
// an export or the GDAL driver runs on every point. Blocks of points are
// computed two coordinates to an instruction into a buffer and stored as
// they are when every result is finite and on the globe (|lon| <= 180,
// |lat| <= 90), as nearly all are; a block with any other goes point by
// point, put back on the globe or stopped at its first non-finite point
// as the scalar loop did. The results are the scalar loop's bit for bit:
// the same operations, each correctly rounded, lane by lane.
static size_t eqc_inverse_points(const mapproj_plan *p, double *xy, size_t n)
{
    size_t k = 0;
#ifdef __SSE2__
    enum { BLOCK = 64 };
    const double unit = p->a * (M_PI / 180.0);
    const __m128d origin = _mm_set_pd(p->y_0, p->x_0), y0 = _mm_set_pd(p->y0, 0.0),
                  units = _mm_set1_pd(unit), lon0 = _mm_set_pd(0.0, p->lon0),
                  globe = _mm_set_pd(90.0, 180.0), sign = _mm_set1_pd(-0.0);
    double out[2 * BLOCK];
    for (; k + BLOCK <= n; k += BLOCK) {
        double *in = xy + 2 * k;
        __m128d off = _mm_setzero_pd();
        for (size_t j = 0; j < BLOCK; j++) {
            __m128d r = eqc_back_pair(_mm_loadu_pd(in + 2 * j), origin, y0, units, lon0);
            // !(|r| <= bound): past the globe, infinite or NaN
            off = _mm_or_pd(off, _mm_cmpnle_pd(_mm_andnot_pd(sign, r), globe));
            _mm_storeu_pd(out + 2 * j, r);
        }
        if (!_mm_movemask_pd(off)) {
            std::memcpy(in, out, sizeof out);
            continue;
        }
        for (size_t j = 0; j < BLOCK; j++)
            if (!eqc_inverse_point(p, in + 2 * j))
                return k + j;
    }
#endif
    for (; k < n; k++)
        if (!eqc_inverse_point(p, xy + 2 * k))
            return k;
    return n;
}

// mapproj_inverse_lattice's scaling: 10^|e|, exact for |e| <= 22.
static double power_of_ten(int32_t m)
{
    static const double pow10[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                     1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                     1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
    return pow10[m];
}

// Whether every value is in (-2^51, 2^51), where the bias below converts
// exactly: a pass of its own, branch-free.
static bool all_small(const int64_t *v, size_t count)
{
    uint64_t out = 0;
    for (size_t k = 0; k < count; k++)
        out |= ((uint64_t)v[k] + (UINT64_C(1) << 51)) >> 52;
    return out == 0;
}

// One lattice point scaled to user coordinates, as hpfc_user_points
// scales a value below 2^51: converted exactly, then one division or
// multiplication.
static void scale_point(const int64_t *v, double p, bool divide, double *out)
{
    for (int c = 0; c < 2; c++)
        out[c] = divide ? (double)v[c] / p : (double)v[c] * p;
}

extern "C" size_t mapproj_inverse_lattice(const mapproj_plan *p, const int64_t *xy, size_t n,
                                          int32_t exp10, double *out)
{
#ifdef __SSE2__
    if (p->kind != MAPPROJ_EQC || exp10 < -22 || exp10 > 22 || !all_small(xy, 2 * n))
        return MAPPROJ_NOT_HANDLED;
    const bool divide = exp10 < 0;
    const double scale = power_of_ten(divide ? -exp10 : exp10);
    enum { BLOCK = 64 };
    const double unit = p->a * (M_PI / 180.0);
    const __m128d origin = _mm_set_pd(p->y_0, p->x_0), y0 = _mm_set_pd(p->y0, 0.0),
                  units = _mm_set1_pd(unit), lon0 = _mm_set_pd(0.0, p->lon0),
                  globe = _mm_set_pd(90.0, 180.0), sign = _mm_set1_pd(-0.0),
                  scales = _mm_set1_pd(scale),
                  bias = _mm_castsi128_pd(_mm_set1_epi64x((long long)0x4338000000000000));
    // (double)v for |v| < 2^51 two lanes at a time: v added to the bits of
    // 2^52 + 2^51 is the double 2^52 + 2^51 + v, less 2^52 + 2^51 is v
    const __m128i bias_bits = _mm_castpd_si128(bias);
    size_t k = 0;
    for (; k < n; k += BLOCK) {
        size_t m = n - k < (size_t)BLOCK ? n - k : (size_t)BLOCK;
        __m128d off = _mm_setzero_pd();
        for (size_t j = 0; j < m; j++) {
            __m128i v = _mm_loadu_si128((const __m128i *)(xy + 2 * (k + j)));
            __m128d d = _mm_sub_pd(_mm_castsi128_pd(_mm_add_epi64(v, bias_bits)), bias);
            d = divide ? _mm_div_pd(d, scales) : _mm_mul_pd(d, scales);
            __m128d r = eqc_back_pair(d, origin, y0, units, lon0);
            off = _mm_or_pd(off, _mm_cmpnle_pd(_mm_andnot_pd(sign, r), globe));
            _mm_storeu_pd(out + 2 * (k + j), r);
        }
        if (!_mm_movemask_pd(off))
            continue;
        // a point off the globe or not finite: the block again, a point at
        // a time, as the two passes would go
        for (size_t j = 0; j < m; j++) {
            scale_point(xy + 2 * (k + j), scale, divide, out + 2 * (k + j));
            if (!eqc_inverse_point(p, out + 2 * (k + j)))
                return k + j;
        }
    }
    return n;
#else
    (void)p, (void)xy, (void)n, (void)exp10, (void)out;
    return MAPPROJ_NOT_HANDLED;
#endif
}

extern "C" size_t mapproj_inverse_points(const mapproj_plan *p, double *xy, size_t n)
{
    if (p->kind == MAPPROJ_EQC)
        return eqc_inverse_points(p, xy, n);
    for (size_t k = 0; k < n; k++) {
        double lon, lat;
        if (mapproj_inverse(p, xy[2 * k], xy[2 * k + 1], &lon, &lat) != 0)
            return k;
        put_back_on_the_globe(&lon, &lat);
        xy[2 * k] = lon, xy[2 * k + 1] = lat;
    }
    return n;
}

extern "C" const char *mapproj_describe(const mapproj_plan *p)
{
    return p->text.c_str();
}

// ---- reading a description back ------------------------------------------------

namespace {

// The +key=value parameters of a PROJ-style string, up to its first ';'.
struct proj_params {
    std::string proj, ellps, datum, units;
    double lat_0 = 0, lon_0 = 0, lat_1 = NAN, lat_2 = NAN, k = 1, x_0 = 0, y_0 = 0;
    double a = NAN, rf = NAN, R = NAN;
    int zone = 0;
    bool south = false;
};

bool parse_number(const std::string &v, double *out)
{
    char *end = nullptr;
    *out = std::strtod(v.c_str(), &end);
    return !v.empty() && end && *end == '\0' && std::isfinite(*out);
}

// One "+key=value" (or "+key"); false on a number that does not parse.
bool take(proj_params *p, const std::string &key, const std::string &v)
{
    struct { const char *name; double *slot; } numbers[] = {
        {"lat_0", &p->lat_0}, {"lon_0", &p->lon_0}, {"lat_1", &p->lat_1}, {"lat_2", &p->lat_2},
        {"k", &p->k},         {"k_0", &p->k},       {"x_0", &p->x_0},     {"y_0", &p->y_0},
        {"a", &p->a},         {"rf", &p->rf},       {"R", &p->R},         {"lat_ts", nullptr}};
    for (auto &n : numbers)
        if (key == n.name) {
            double d;
            if (!parse_number(v, &d))
                return false;
            if (n.slot)
                *n.slot = d;
            return true;
        }
    if (key == "proj") p->proj = v;
    else if (key == "ellps") p->ellps = v;
    else if (key == "datum") p->datum = v;
    else if (key == "units") p->units = v;
    else if (key == "south") p->south = true;
    else if (key == "zone") {
        double d;
        if (!parse_number(v, &d) || d < 1 || d > 60 || d != std::floor(d))
            return false;
        p->zone = (int)d;
    }
    return true; // +no_defs, +towgs84, +wktext ...: no bearing on the plane
}

bool parse_params(const char *text, size_t len, proj_params *p)
{
    std::string s(text, len);
    s = s.substr(0, s.find(';'));
    size_t at = 0;
    while ((at = s.find('+', at)) != std::string::npos) {
        size_t end = s.find(' ', at);
        std::string tok = s.substr(at + 1, end == std::string::npos ? std::string::npos : end - at - 1);
        size_t eq = tok.find('=');
        if (!take(p, tok.substr(0, eq), eq == std::string::npos ? "" : tok.substr(eq + 1)))
            return false;
        at = end == std::string::npos ? s.size() : end;
    }
    return !p->proj.empty();
}

// The ellipsoid of the parameters, WGS 84 unless they say otherwise.
bool ellipsoid_of(const proj_params &p, double *a, double *f)
{
    *a = 6378137.0;
    *f = 1.0 / 298.257223563;
    if (p.ellps == "GRS80")
        *f = 1.0 / 298.257222101;
    else if (!p.ellps.empty() && p.ellps != "WGS84")
        return false;
    if (!p.datum.empty() && p.datum != "WGS84")
        return false;
    if (std::isfinite(p.R)) {
        *a = p.R;
        *f = 0.0;
    } else if (std::isfinite(p.a)) {
        *a = p.a;
        *f = std::isfinite(p.rf) && p.rf > 0 ? 1.0 / p.rf : 0.0;
    }
    return *a > 0;
}

} // namespace

extern "C" mapproj_plan *mapproj_from_text(const char *text, size_t len, char *why, size_t why_len)
{
    proj_params pp;
    auto refuse = [&](const char *reason) -> mapproj_plan * {
        std::snprintf(why, why_len, "%s", reason);
        return nullptr;
    };
    if (!parse_params(text, len, &pp))
        return refuse("the CRS is not a PROJ-style description (+proj=...)");
    if (!pp.units.empty() && pp.units != "m" && pp.proj != "longlat")
        return refuse("the CRS's unit is not the metre");
    double a, f;
    if (!ellipsoid_of(pp, &a, &f))
        return refuse("the CRS's ellipsoid or datum is not WGS 84, GRS 80 or given by +a/+R");
    mapproj_plan *p = new (std::nothrow) mapproj_plan();
    if (!p)
        return refuse("out of memory");
    p->a = a, p->f = f, p->lat0 = pp.lat_0, p->lon0 = pp.lon_0, p->x_0 = pp.x_0, p->y_0 = pp.y_0;
    p->text.assign(text, len);
    try {
        if (pp.proj == "longlat" || pp.proj == "latlong") {
            p->kind = MAPPROJ_NONE;
        } else if (pp.proj == "tmerc" || pp.proj == "utm") {
            if (pp.proj == "utm") {
                if (!pp.zone)
                    throw std::invalid_argument("utm without +zone");
                p->lon0 = pp.zone * 6.0 - 183.0, p->lat0 = 0, pp.k = 0.9996;
                p->x_0 = 500000.0, p->y_0 = pp.south ? 10000000.0 : 0.0;
            }
            p->kind = MAPPROJ_TM;
            p->tm = new GeographicLib::TransverseMercator(a, f, pp.k);
        } else if (pp.proj == "lcc" || pp.proj == "aea") {
            double s1 = std::isfinite(pp.lat_1) ? pp.lat_1 : pp.lat_0;
            double s2 = std::isfinite(pp.lat_2) ? pp.lat_2 : s1;
            if (pp.proj == "lcc") {
                p->kind = MAPPROJ_LCC;
                p->lcc = s1 == s2 ? new GeographicLib::LambertConformalConic(a, f, s1, pp.k)
                                  : new GeographicLib::LambertConformalConic(a, f, s1, s2, pp.k);
            } else {
                p->kind = MAPPROJ_AEA;
                p->aea = s1 == s2 ? new GeographicLib::AlbersEqualArea(a, f, s1, pp.k)
                                  : new GeographicLib::AlbersEqualArea(a, f, s1, s2, pp.k);
            }
        } else if (pp.proj == "eqc") {
            p->kind = MAPPROJ_EQC;
        } else {
            mapproj_free(p);
            return refuse("the CRS's projection is not one of longlat, tmerc, utm, lcc, aea, eqc");
        }
    } catch (const std::exception &) {
        mapproj_free(p);
        return refuse("the CRS's parameters are out of range");
    }
    // the origin's northing, as build() computes it for the plans it makes
    double x, y, x_0 = p->x_0, y_0 = p->y_0;
    p->x_0 = p->y_0 = 0;
    if (p->kind != MAPPROJ_EQC && p->kind != MAPPROJ_NONE && mapproj_forward(p, p->lon0, p->lat0, &x, &y) == 0)
        p->y0 = y;
    p->x_0 = x_0, p->y_0 = y_0;
    return p;
}
