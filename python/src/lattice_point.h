/*
 * lattice_point.h: user coordinates and (lon, lat) to lattice points for
 * the Python module, decided as hpfc-inspect's --locate decides them.
 */
#ifndef HPFC_PY_LATTICE_POINT_H
#define HPFC_PY_LATTICE_POINT_H

#include <stddef.h>
#include <stdint.h>

#include "projection.h"

/* The lattice point floor(d / 10^unit_exp10) of a decimal d of v, as the
 * CLI reads a coordinate: shortest = 1 takes the shortest decimal that
 * reads back as v (what a user typed: Python's repr), shortest = 0 the
 * "%.17g" one (how the CLI prints a projected double). 0 on success, -1
 * when v is not finite or the point lies beyond any int64 lattice (then
 * outside every domain). */
int lattice_floor(double v, int32_t unit_exp10, int shortest, int64_t *out);

/* Projects n (lon, lat) degrees with `plan` and floors them to the lattice
 * (17 digits); with plan NULL, floors user coordinates (shortest); valid[k] is 0
 * where lon/lat is out of range, the projection fails or the point lies
 * beyond the lattice. */
void lattice_points(const mapproj_plan *plan, int32_t unit_exp10, size_t n, const double *lon,
                    const double *lat, int64_t *x, int64_t *y, uint8_t *valid);

#endif
