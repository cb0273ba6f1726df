/* lattice.c: see lattice.h. */
#include "lattice.h"

#include <math.h>
#include <stdio.h>

/* 10^k for |k| <= 22 is exact in a double; beyond, pow() is close enough
 * for choosing (snapping never needs it: see lattice_snap). */
static double pow10i(int32_t k)
{
    double p = 1.0;
    for (int32_t i = 0; i < (k < 0 ? -k : k); i++)
        p *= 10.0;
    return k < 0 ? 1.0 / p : p;
}

int lattice_choose(double xmin, double ymin, double xmax, double ymax, int32_t *exp10,
                   char *why, size_t why_len)
{
    if (!isfinite(xmin) || !isfinite(ymin) || !isfinite(xmax) || !isfinite(ymax)) {
        snprintf(why, why_len, "coordinates are not finite");
        return -1;
    }
    double span = fmax(xmax - xmin, ymax - ymin);
    double amax = fmax(fmax(fabs(xmin), fabs(xmax)), fmax(fabs(ymin), fabs(ymax)));
    if (amax > 1e300) {
        snprintf(why, why_len, "extent too large for the lattice (coordinates up to %g)", amax);
        return -1;
    }
    /* The finest exponent that satisfies both bounds; -22 keeps every 10^-e
     * exact. A single point (span 0) gets that finest unit. */
    int32_t e = -22;
    while (e < 300 && (span / pow10i(e) > LATTICE_SPAN_MAX || amax / pow10i(e) > LATTICE_ABS_MAX))
        e++;
    if (span > 0 && span / pow10i(e) < LATTICE_SPAN_MIN) {
        snprintf(why, why_len,
                 "extent too large for the lattice: coordinates up to %g need a unit of 1e%d, "
                 "which leaves only %.0f units across the data (span %g)",
                 amax, (int)e, span / pow10i(e), span);
        return -1;
    }
    *exp10 = e;
    return 0;
}

int64_t lattice_snap(double v, int32_t exp10)
{
    /* One correctly rounded multiplication (10^-e is exact for e >= -22) or
     * division, then rounding to an integer. */
    double s = exp10 <= 0 ? v * pow10i(-exp10) : v / pow10i(exp10);
    return (int64_t)llround(s);
}
