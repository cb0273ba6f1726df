/*
 * lattice.h: from floating-point map coordinates to hpfc's integer lattice.
 *
 * The lattice unit is a power of ten of the coordinate unit (metres after a
 * projection, the input's own unit otherwise), so that a lattice point
 * (X, Y) stands exactly for the user coordinates (X * 10^e, Y * 10^e) the
 * file records (hpfc_graph_set_unit_exp10). After snapping, every decision
 * (merging points, dropping zero-length pieces) is made on integers.
 */
#ifndef HPFC_PACK_LATTICE_H
#define HPFC_PACK_LATTICE_H

#include <stddef.h>
#include <stdint.h>

/* At most this many lattice units across the data's extent. */
#define LATTICE_SPAN_MAX ((double)(1 << 30))
/* At most this |coordinate|, in lattice units (half of HPFC_COORD_MAX). */
#define LATTICE_ABS_MAX ((double)((int64_t)1 << 39))
/* Below this many units across the extent the lattice would be too coarse. */
#define LATTICE_SPAN_MIN ((double)(1 << 20))

/* Chooses the finest exponent e such that the extent spans at most
 * LATTICE_SPAN_MAX units and no coordinate exceeds LATTICE_ABS_MAX units.
 * Returns 0, or -1 with a one-line reason in `why` when the bounds are not
 * finite or lie so far from the origin, relative to their span, that fewer
 * than LATTICE_SPAN_MIN units would remain across the data. */
int lattice_choose(double xmin, double ymin, double xmax, double ymax, int32_t *exp10,
                   char *why, size_t why_len);

/* v / 10^e rounded to the nearest integer (halves away from zero), for a v
 * the chosen exponent covers. */
int64_t lattice_snap(double v, int32_t exp10);

#endif
