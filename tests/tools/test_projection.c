/*
 * Unit tests of the projections' batch inverse (common/projection.h):
 * mapproj_inverse_points against a naive reference, mapproj_inverse point
 * by point followed by the header's rule for points a rounding step past
 * the antimeridian or a pole, bit for bit. The equirectangular batch has a
 * path of its own (blocks of points, two coordinates to an instruction),
 * so the plans are eqc ones with and without a false origin and a central
 * meridian, and a transverse Mercator one for the general loop; the
 * arrays' lengths fall on both sides of the blocks' size, and a point that
 * does not come back (infinite or NaN) stops the batch where the reference
 * stops, with every point after it untouched.
 * mapproj_inverse_lattice (the scaling of lattice points to user
 * coordinates and the inverse in one pass) against the scaling as
 * hpfc_user_points does it followed by the reference, bit for bit, on
 * eqc plans, lattices of 10^-7 to 10^2 and points across the world's
 * edges; it declines (MAPPROJ_NOT_HANDLED) another plan, an exponent
 * past 22 and a value from 2^51.
 */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "projection.h"

/* pi, as <math.h> gives it only beyond C11 */
#define PI_DOUBLE 3.14159265358979323846

/* The header's rule: a longitude past +-180 by at most 1e-6 goes on the
 * antimeridian, one further comes round by 360; latitudes are clamped. */
static void reference_back_on_globe(double *lon, double *lat)
{
    if (*lon > 180.0)
        *lon = *lon <= 180.0 + 1e-6 ? 180.0 : *lon - 360.0;
    else if (*lon < -180.0)
        *lon = *lon >= -180.0 - 1e-6 ? -180.0 : *lon + 360.0;
    if (*lat > 90.0)
        *lat = 90.0;
    else if (*lat < -90.0)
        *lat = -90.0;
}

/* The reference over n points of xy in place: the index of the first
 * point that does not come back, or n. */
static size_t reference_inverse(const mapproj_plan *p, double *xy, size_t n)
{
    for (size_t k = 0; k < n; k++) {
        double lon, lat;
        if (mapproj_inverse(p, xy[2 * k], xy[2 * k + 1], &lon, &lat) != 0)
            return k;
        reference_back_on_globe(&lon, &lat);
        xy[2 * k] = lon, xy[2 * k + 1] = lat;
    }
    return n;
}

static uint64_t next_random(uint64_t *r)
{
    *r ^= *r << 13, *r ^= *r >> 7, *r ^= *r << 17;
    return *r;
}

/* A plane point within (scale) metres of the origin, on a lattice of
 * 10^-7 steps as user coordinates are, or (with `edges`, one in four) on
 * the edge of the world: x at +-(half the equator) plus a few lattice
 * steps, to go past the antimeridian, or y past a pole; without, one in
 * sixty-four has a coordinate -0. */
static void random_point(uint64_t *r, double scale, int edges, double *x, double *y)
{
    uint64_t v = next_random(r);
    *x = ((double)(int64_t)(v >> 11) / 9007199254740992.0 - 0.5) * 2 * scale;
    *y = ((double)(int64_t)(next_random(r) >> 11) / 9007199254740992.0 - 0.5) * scale;
    *x = round(*x * 1e7) / 1e7, *y = round(*y * 1e7) / 1e7;
    double half = 6378137.0 * PI_DOUBLE, quarter = half / 2; /* eqc on WGS 84's a */
    if (!edges && (v & 63) == 5) /* signed zeros: each lane's exact steps */
        *(v & 64 ? x : y) = -0.0;
    switch (edges ? v & 7 : 7) {
    case 0:
        *x = (v & 8 ? half : -half) + (double)((v >> 4) & 15) * 0.05;
        break;
    case 1:
        *y = (v & 8 ? quarter : -quarter) + (double)((v >> 4) & 15) * 0.05;
        break;
    default:
        break;
    }
}

static void check_plan(const char *text, double scale, uint64_t seed)
{
    char why[200];
    mapproj_plan *p = mapproj_from_text(text, strlen(text), why, sizeof why);
    CHECK(p != NULL);
    if (!p)
        return;
    static const size_t sizes[] = {0, 1, 2, 63, 64, 65, 127, 128, 129, 1000};
    uint64_t r = seed;
    for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++) {
        size_t n = sizes[s];
        double *a = malloc((2 * n + 2) * sizeof *a), *b = malloc((2 * n + 2) * sizeof *b);
        CHECK(a && b);
        if (!a || !b) {
            free(a);
            free(b);
            continue;
        }
        /* whole arrays inside the world and across its edges, then one
         * point made infinite or NaN at a few places */
        for (int bad = -2; bad < 4; bad++) {
            for (size_t k = 0; k < n; k++)
                random_point(&r, scale, bad != -2, &a[2 * k], &a[2 * k + 1]);
            size_t at = n;
            if (bad >= 0 && n) {
                at = bad == 0 ? 0 : bad == 1 ? n - 1 : bad == 2 ? n / 2 : (size_t)(next_random(&r) % n);
                a[2 * at + (bad & 1)] = bad == 3 ? NAN : (bad & 1 ? -INFINITY : INFINITY);
            }
            memcpy(b, a, 2 * n * sizeof *a);
            size_t got = mapproj_inverse_points(p, a, n);
            size_t want = reference_inverse(p, b, n);
            CHECK_EQ_INT((long long)got, (long long)want);
            CHECK_EQ_INT((long long)got, (long long)at);
            /* converted before the stop, untouched from it: both the same */
            CHECK(memcmp(a, b, 2 * n * sizeof *a) == 0);
        }
        free(a);
        free(b);
    }
    mapproj_free(p);
}

/* A lattice point for check_lattice: the user point random_point makes,
 * at 10^exp10 a lattice step (rounded to the lattice). */
static void random_lattice_point(uint64_t *r, double scale, int edges, int32_t exp10, int64_t *v)
{
    double x, y;
    random_point(r, scale, edges, &x, &y);
    double step = pow(10.0, exp10);
    v[0] = (int64_t)llround(x / step);
    v[1] = (int64_t)llround(y / step);
}

static void check_lattice(const char *text, double scale, uint64_t seed)
{
    char why[200];
    mapproj_plan *p = mapproj_from_text(text, strlen(text), why, sizeof why);
    CHECK(p != NULL);
    if (!p)
        return;
    static const int32_t exps[] = {-7, -3, -1, 0, 2};
    static const size_t sizes[] = {0, 1, 63, 64, 65, 129, 1000};
    uint64_t r = seed;
    for (size_t e = 0; e < sizeof exps / sizeof exps[0]; e++)
        for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++) {
            size_t n = sizes[s];
            int64_t *v = malloc((2 * n + 2) * sizeof *v);
            double *got = malloc((2 * n + 2) * sizeof *got), *want = malloc((2 * n + 2) * sizeof *want);
            CHECK(v && got && want);
            if (!v || !got || !want) {
                free(v), free(got), free(want);
                continue;
            }
            for (int edges = 0; edges < 2; edges++) {
                for (size_t k = 0; k < n; k++)
                    random_lattice_point(&r, scale, edges, exps[e], v + 2 * k);
                double unit = pow(10.0, exps[e] < 0 ? -exps[e] : exps[e]); /* exact to 10^22 */
                for (size_t k = 0; k < 2 * n; k++)
                    want[k] = exps[e] < 0 ? (double)v[k] / unit : (double)v[k] * unit;
                size_t stop = reference_inverse(p, want, n);
                size_t done = mapproj_inverse_lattice(p, v, n, exps[e], got);
                CHECK_EQ_INT((long long)done, (long long)stop);
                CHECK(memcmp(got, want, 2 * (done < n ? done + 1 : n) * sizeof *got) == 0);
                if (n) { /* a value from 2^51, an exponent past 22: declined */
                    int64_t keep = v[n];
                    v[n] = INT64_C(1) << 51;
                    CHECK(mapproj_inverse_lattice(p, v, n, exps[e], got) == MAPPROJ_NOT_HANDLED);
                    v[n] = keep;
                    CHECK(mapproj_inverse_lattice(p, v, n, 23, got) == MAPPROJ_NOT_HANDLED);
                }
            }
            free(v), free(got), free(want);
        }
    mapproj_free(p);
}

int main(void)
{
    double world = 6378137.0 * PI_DOUBLE;
    check_plan("+proj=eqc +lat_ts=0 +lat_0=0 +lon_0=0 +x_0=0 +y_0=0 +ellps=WGS84 +units=m +no_defs",
               world, 1);
    check_plan("+proj=eqc +lat_ts=0 +lat_0=0 +lon_0=-151.25 +x_0=0 +y_0=0 +ellps=WGS84 +units=m "
               "+no_defs",
               world, 2);
    check_plan("+proj=eqc +lat_ts=0 +lat_0=12.5 +lon_0=33 +x_0=500000 +y_0=-2500.5 +ellps=WGS84 "
               "+units=m +no_defs",
               world / 2, 3); /* inside the globe, off the false origin: whole blocks pass */
    check_plan("+proj=tmerc +lat_0=40 +lon_0=-100 +k=1 +x_0=0 +y_0=0 +ellps=WGS84 +units=m +no_defs",
               600000.0, 4);
    check_lattice("+proj=eqc +lat_ts=0 +lat_0=0 +lon_0=0 +x_0=0 +y_0=0 +ellps=WGS84 +units=m +no_defs",
                  world, 5);
    check_lattice("+proj=eqc +lat_ts=0 +lat_0=12.5 +lon_0=33 +x_0=500000 +y_0=-2500.5 +ellps=WGS84 "
                  "+units=m +no_defs",
                  world, 6);
    /* another plan: the caller's two passes */
    const char *tm = "+proj=tmerc +lat_0=40 +lon_0=-100 +k=1 +x_0=0 +y_0=0 +ellps=WGS84 +units=m +no_defs";
    char why[200];
    mapproj_plan *p = mapproj_from_text(tm, strlen(tm), why, sizeof why);
    int64_t v[2] = {1, 2};
    double out[2];
    CHECK(p && mapproj_inverse_lattice(p, v, 1, -1, out) == MAPPROJ_NOT_HANDLED);
    mapproj_free(p);
    return check_report("projection");
}
