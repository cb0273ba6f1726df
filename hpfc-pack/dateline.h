/*
 * dateline.h: cutting geographic lines and polygons at the antimeridian, for
 * hpfc-pack's GIS input (gis_input.c).
 *
 * In longitude/latitude data a segment whose ends are more than 180 degrees
 * of longitude apart is taken to cross the antimeridian, the short way round
 * (the GeoJSON convention). Projected as it stands it would run the long way
 * across the whole map, so such geometry is cut at +-180:
 *
 *   - a line is split into pieces that end on the meridian;
 *   - a polygon becomes a multipolygon: the pieces of its rings are closed
 *     along the meridian, on both sides, over the latitude intervals that lie
 *     inside it (found by parity along the meridian), and rings that cross
 *     nothing keep their place as holes or shells;
 *   - a ring that crosses an odd number of times winds around a pole; it
 *     encloses the pole of the hemisphere that holds all its points, and is
 *     closed through that pole (along latitude +-90, a line in the
 *     equirectangular projection). A winding ring with points in both
 *     hemispheres, or a polygon with rings winding around both poles, is
 *     ambiguous and refused.
 *
 * The crossing latitude is interpolated linearly in (lon, lat) from the
 * segment's east end, so that a border two features store bit-identically
 * (in either direction) is cut at bit-identical points.
 */
#ifndef HPFC_PACK_DATELINE_H
#define HPFC_PACK_DATELINE_H

#include <stddef.h>

#include <ogr_api.h>

/* Does the segment (lon1, lat1)-(lon2, lat2) cross the antimeridian? True
 * when the longitudes (each within [-180, 180]) are more than 180 degrees
 * apart, unless an end is a pole (|lat| = 90): a segment along a pole line,
 * e.g. (180, -90)-(-180, -90) closing Natural Earth's Antarctica, is a line of
 * the map, not a crossing. */
int dateline_segment_wraps(double lon1, double lat1, double lon2, double lat2);

/* Cuts `g` (coordinates stored (lat, lon) when swap_xy) at the antimeridian
 * into a new geometry *out of the same coordinate order (destroy it with
 * OGR_G_DestroyGeometry). Lines and polygons that do not cross are copied.
 * Returns 0, or 1 with one line in `err`. Every coordinate must already be a
 * finite longitude/latitude. */
int dateline_cut(OGRGeometryH g, int swap_xy, OGRGeometryH *out, char *err, size_t err_len);

#endif
