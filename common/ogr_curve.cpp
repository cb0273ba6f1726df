/*
 * ogr_curve.cpp: ogr_curve.h over GDAL's C++ geometry classes.
 */
#include "ogr_curve.h"

#include <climits>
#include <new>

#include <ogr_geometry.h>

namespace {

// OGRSimpleCurve keeps its points in the protected array paoPoints; these
// classes add nothing but the access to it, so that their objects are the
// line strings and rings OGR makes (a clone is a plain OGRLineString or
// OGRLinearRing, and every virtual member is OGR's own).
struct FilledLine : OGRLineString {
    OGRRawPoint *points() { return paoPoints; }
};

struct FilledRing : OGRLinearRing {
    OGRRawPoint *points() { return paoPoints; }
};

template <class Curve> OGRGeometryH create(size_t n, double **points)
{
    Curve *c = new (std::nothrow) Curve;
    if (!c)
        return nullptr;
    // without zeroing: the caller writes every point
    c->setNumPoints(static_cast<int>(n), FALSE);
    if (c->getNumPoints() != static_cast<int>(n)) { // OGR's allocation failed
        delete c;
        return nullptr;
    }
    static_assert(sizeof(OGRRawPoint) == 2 * sizeof(double), "OGR's points are (x, y) pairs");
    *points = n ? &c->points()[0].x : nullptr;
    return OGRGeometry::ToHandle(c);
}

} // namespace

extern "C" OGRGeometryH ogr_curve_create(OGRwkbGeometryType t, size_t n, double **points)
{
    *points = nullptr;
    if (n > static_cast<size_t>(INT_MAX))
        return nullptr;
    if (t == wkbLinearRing)
        return create<FilledRing>(n, points);
    if (t == wkbLineString)
        return create<FilledLine>(n, points);
    return nullptr;
}
