/*
 * projection.h: a small C interface over GeographicLib's map projections
 * (projection.cc), for hpfc-pack's GIS input and for the (lon, lat) points
 * of hpfc-inspect and the Python package. Geographic (lon, lat) degrees
 * go to plane metres; the PROJ-style description of the projection is what
 * the .hpfc file's CRS section records, so that a reader can map (lon, lat)
 * back to user coordinates with any PROJ-compatible library.
 */
#ifndef HPFC_PROJECTION_H
#define HPFC_PROJECTION_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum mapproj_kind {
    MAPPROJ_AUTO = 0, /* chosen from the data's extent, see mapproj_create() */
    MAPPROJ_NONE,     /* keep the coordinates as they are */
    MAPPROJ_TM,       /* transverse Mercator centred on the data */
    MAPPROJ_LCC,      /* Lambert conformal conic, two standard parallels */
    MAPPROJ_AEA,      /* Albers equal-area conic, two standard parallels */
    MAPPROJ_EQC       /* equirectangular (plate carree), for world extents */
} mapproj_kind;

/* Parses "auto", "none", "tm", "lcc", "aea" or "eqc"; 0 if unknown. */
int mapproj_parse_kind(const char *name, mapproj_kind *out);
const char *mapproj_kind_name(mapproj_kind kind);

typedef struct mapproj_plan mapproj_plan;

/* A projection for geographic data with the given extent (degrees) on the
 * ellipsoid (a, f). MAPPROJ_AUTO picks transverse Mercator when the longitude
 * span is at most 12 degrees, a Lambert conformal conic when the data stay
 * within 84 degrees of the equator and span at most 150 degrees of
 * longitude, and the equirectangular projection otherwise. MAPPROJ_NONE is not
 * a projection: the caller keeps the coordinates. Returns NULL when
 * memory runs out. */
mapproj_plan *mapproj_create(mapproj_kind kind, double lon_min, double lat_min, double lon_max,
                       double lat_max, double a, double f);
/* The same with the central meridian at lon0 (e.g. the data's median
 * longitude) for tm, lcc and aea; eqc and a NaN lon0 take the extent's
 * middle (eqc keeps its seam opposite, in the data's gap). */
mapproj_plan *mapproj_create_at(mapproj_kind kind, double lon_min, double lat_min,
                                double lon_max, double lat_max, double lon0, double a, double f);
void mapproj_free(mapproj_plan *plan);

/* The kind actually used (never MAPPROJ_AUTO). */
mapproj_kind mapproj_plan_kind(const mapproj_plan *plan);

/* Projects (lon, lat) to (x, y) metres; 0 on success, -1 when the result is
 * not finite (for example a point on the far side of a conic's apex). */
int mapproj_forward(const mapproj_plan *plan, double lon, double lat, double *x, double *y);

/* The inverse: (x, y) metres back to (lon, lat) degrees; 0 on success,
 * -1 when the result is not finite. */
int mapproj_inverse(const mapproj_plan *plan, double x, double y, double *lon, double *lat);

/* n points (x, y), interleaved in xy, back to (lon, lat) degrees in
 * place, as every reader writes them out: a point that comes back a
 * rounding step past the antimeridian or a pole (half a lattice unit:
 * under 1e-6 degrees for any lattice hpfc-pack chooses) is put back on it,
 * not on the map's far side. Returns n, or the index of the first point
 * that does not project back (those before it are converted). */
size_t mapproj_inverse_points(const mapproj_plan *plan, double *xy, size_t n);

/* mapproj_inverse_points on n lattice points (integer pairs in xy) scaled
 * to user coordinates by 10^exp10, as hpfc_user_points scales them, into
 * out: the same doubles as the two passes, in one, where it can (the
 * equirectangular plan, |exp10| <= 22, every value below 2^51, SSE2).
 * Returns n, the index of the first point that does not project back (out
 * holds its user coordinates; those before it are converted), or
 * MAPPROJ_NOT_HANDLED, leaving the two passes to the caller. */
#define MAPPROJ_NOT_HANDLED ((size_t)-1)
size_t mapproj_inverse_lattice(const mapproj_plan *plan, const int64_t *xy, size_t n,
                               int32_t exp10, double *out);

/* "+proj=tmerc +lat_0=... +lon_0=... +k=1 +x_0=0 +y_0=0 +ellps=WGS84
 * +units=m +no_defs", owned by the plan. */
const char *mapproj_describe(const mapproj_plan *plan);

/* A plan from a description such as mapproj_describe() makes, or a PROJ
 * string of a longlat, tmerc, utm, lcc, aea or eqc projection on WGS 84,
 * GRS 80 or an explicit ellipsoid, in metres (read up to the first ';', as
 * the CRS section records "DESCRIPTION; source ..."). NULL with a reason in
 * `why` otherwise. */
mapproj_plan *mapproj_from_text(const char *text, size_t len, char *why, size_t why_len);

#ifdef __cplusplus
}
#endif

#endif
