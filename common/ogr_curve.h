/*
 * ogr_curve.h: an OGR line string or linear ring made with room for its
 * points, which the caller writes in place (ogr_shapes.c): OGR keeps a
 * curve's points as (x, y) pairs, the layout in which ogr_shapes_points
 * converts lattice points, so a ring's points go from the lattice straight
 * into OGR's own array, without a copy through x and y arrays.
 */
#ifndef HPFC_OGR_CURVE_H
#define HPFC_OGR_CURVE_H

#include <stddef.h>

#include <ogr_api.h>

#ifdef __cplusplus
extern "C" {
#endif

/* A new curve of type t (wkbLineString or wkbLinearRing) with n points,
 * their coordinates unset; *points: its pairs (x0, y0, x1, y1, ...), 2n
 * doubles, to fill before any other use of the curve. NULL when t is
 * another type, n exceeds OGR's int or memory runs out. */
OGRGeometryH ogr_curve_create(OGRwkbGeometryType t, size_t n, double **points);

#ifdef __cplusplus
}
#endif

#endif
