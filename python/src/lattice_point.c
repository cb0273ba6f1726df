/*
 * Coordinates to lattice points (lattice_point.h).
 *
 * hpfc-inspect reads a coordinate as a decimal and floors it exactly at the
 * lattice unit; a projected double becomes the decimal "%.17g" prints. Doing
 * that through text costs about a microsecond a point, so the common case
 * is decided in long double: the scaled value t = v * 10^-e and its floor c
 * are exact enough unless t lies within a hair of an integer, where the
 * decimal and the double may sit on either side of it. Only then is the
 * decimal made and floored digit by digit, as the CLI does.
 */
#include "lattice_point.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define LATTICE_LIMIT 9.0e18L /* below INT64_MAX, far above any domain */

/* The slow path: v as a decimal of 17 significant digits (shortest = 0:
 * "%.17g", as the CLI prints a projected double) or of the fewest digits
 * that read back as v (shortest = 1: what a user typed, as Python's repr),
 * floored exactly. */
static int floor_by_digits(double v, int32_t e, int shortest, int64_t *out)
{
    char text[40];
    for (int prec = shortest ? 1 : 17; prec <= 17; prec++) {
        snprintf(text, sizeof text, "%.*e", prec - 1, v);
        if (prec == 17 || strtod(text, NULL) == v)
            break;
    }
    int neg = text[0] == '-';
    const char *p = text + neg;
    char digits[18];
    size_t nd = 0;
    for (; *p && *p != 'e'; p++)
        if (*p >= '0' && *p <= '9' && nd < 17)
            digits[nd++] = *p;
    if (*p != 'e' || nd == 0)
        return -1;
    long exp10 = strtol(p + 1, NULL, 10) - (long)(nd - 1); /* value = digits * 10^exp10 */
    long shift = exp10 - e; /* lattice value = digits * 10^shift */
    long int_digits = (long)nd + shift;
    if (int_digits > 19) /* the CLI's bounds: |lattice value| <= INT64_MAX */
        return -1;
    uint64_t mag = 0;
    int frac = 0;
    for (long i = 0; i < int_digits; i++) {
        uint64_t digit = i < (long)nd ? (uint64_t)(digits[i] - '0') : 0;
        if (mag > (UINT64_MAX - digit) / 10)
            return -1;
        mag = mag * 10 + digit;
    }
    for (long i = int_digits > 0 ? int_digits : 0; i < (long)nd; i++)
        frac |= digits[i] != '0';
    if (neg && frac)
        mag++;
    if (mag > (uint64_t)INT64_MAX)
        return -1;
    *out = neg ? -(int64_t)mag : (int64_t)mag;
    return 0;
}

/* 10^-e as a long double, and whether to multiply (e <= 0) or divide by
 * 10^e: both are exact in the 64-bit mantissa up to 10^27. */
typedef struct lattice_scale {
    int32_t e;
    int shortest;
    int digits_only;
    int multiply;
    long double factor;
} lattice_scale;

static lattice_scale scale_for(int32_t e, int shortest)
{
    lattice_scale s = {e, shortest, e < -27 || e > 27, e <= 0, 1.0L};
    for (int32_t k = 0; !s.digits_only && k < (e < 0 ? -e : e); k++)
        s.factor *= 10.0L;
    return s;
}

static int floor_scaled(double v, const lattice_scale *s, int64_t *out)
{
    if (!isfinite(v))
        return -1;
    if (s->digits_only)
        return floor_by_digits(v, s->e, s->shortest, out);
    long double t = s->multiply ? (long double)v * s->factor : (long double)v / s->factor;
    if (!(fabsl(t) < LATTICE_LIMIT)) /* near or past INT64_MAX: as the CLI decides */
        return floor_by_digits(v, s->e, s->shortest, out);
    long double c = floorl(t);
    long double frac = t - c;
    /* v's decimals (17 digits or shortest) are within 1.2e-16 |v| of v, and
     * t's rounding adds a few 2^-64 |t|: a margin of 1e-15 |t| (plus subnormal slack) keeps
     * both on the same side of every integer. */
    long double margin = fabsl(t) * 1e-15L + 1e-30L;
    if (frac > margin && 1.0L - frac > margin) {
        *out = (int64_t)c;
        return 0;
    }
    return floor_by_digits(v, s->e, s->shortest, out);
}

int lattice_floor(double v, int32_t e, int shortest, int64_t *out)
{
    lattice_scale s = scale_for(e, shortest);
    return floor_scaled(v, &s, out);
}

void lattice_points(const mapproj_plan *plan, int32_t e, size_t n, const double *lon,
                    const double *lat, int64_t *x, int64_t *y, uint8_t *valid)
{
    lattice_scale s = scale_for(e, plan == NULL);
    for (size_t k = 0; k < n; k++) {
        double u = lon[k], w = lat[k];
        int ok = 1;
        if (plan) {
            ok = u >= -180 && u <= 180 && w >= -90 && w <= 90 &&
                 mapproj_forward(plan, lon[k], lat[k], &u, &w) == 0;
        }
        ok = ok && floor_scaled(u, &s, &x[k]) == 0 && floor_scaled(w, &s, &y[k]) == 0;
        if (!ok)
            x[k] = y[k] = 0;
        valid[k] = (uint8_t)ok;
    }
}
