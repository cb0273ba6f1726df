/*
 * projection_stub.c: projection.h for hpfc-inspect and the Python package
 * built without GeographicLib. Points in (lon, lat) cannot be placed;
 * everything else works.
 */
#include <stdio.h>

#include "projection.h"

mapproj_plan *mapproj_from_text(const char *text, size_t len, char *why, size_t why_len)
{
    (void)text;
    (void)len;
    snprintf(why, why_len, "projections need GeographicLib, not built in");
    return NULL;
}

int mapproj_forward(const mapproj_plan *plan, double lon, double lat, double *x, double *y)
{
    (void)plan;
    (void)lon;
    (void)lat;
    *x = *y = 0;
    return -1;
}

int mapproj_inverse(const mapproj_plan *plan, double x, double y, double *lon, double *lat)
{
    (void)plan;
    (void)x;
    (void)y;
    *lon = *lat = 0;
    return -1;
}

size_t mapproj_inverse_points(const mapproj_plan *plan, double *xy, size_t n)
{
    (void)plan;
    (void)xy;
    (void)n;
    return 0; /* not one point projects back */
}

size_t mapproj_inverse_lattice(const mapproj_plan *plan, const int64_t *xy, size_t n,
                               int32_t exp10, double *out)
{
    (void)plan;
    (void)xy;
    (void)n;
    (void)exp10;
    (void)out;
    return MAPPROJ_NOT_HANDLED; /* the caller's two passes answer */
}

void mapproj_free(mapproj_plan *plan)
{
    (void)plan;
}
