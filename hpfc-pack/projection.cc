// projection.cc: projection.h over GeographicLib. The parameters are printed
// first and parsed back, so the recorded description is exactly what
// projects the data.
#include "projection.h"

#include <GeographicLib/AlbersEqualArea.hpp>
#include <GeographicLib/LambertConformalConic.hpp>
#include <GeographicLib/TransverseMercator.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <new>
#include <string>

struct mapproj_plan {
    mapproj_kind kind;
    double lon0, lat0;   // central meridian, latitude of the origin
    double y0;           // northing of (lon0, lat0) in the library's frame
    double a, f;
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
    mapproj_plan *p = new (std::nothrow) mapproj_plan();
    if (!p)
        return nullptr;
    p->kind = kind == MAPPROJ_AUTO ? choose(lon_min, lat_min, lon_max, lat_max) : kind;
    p->lon0 = rounded((lon_min + lon_max) / 2);
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
    return std::isfinite(*x) && std::isfinite(*y) ? 0 : -1;
}

extern "C" const char *mapproj_describe(const mapproj_plan *p)
{
    return p->text.c_str();
}
