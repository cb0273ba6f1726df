/*
 * Exact predicates on the integer lattice, and the project's one symbolic
 * perturbation (spec/hpfc-format.md, "Perturbation rule").
 *
 * Every vertical grid line x = X is treated as x = X - eps and every
 * horizontal grid line y = Y as y = Y - eps^2, with 0 < eps^2 << eps
 * infinitesimal. Consequences used below:
 *   - a point lies in the half-open cell [x0, x1) x [y0, y1);
 *   - no point lies on a perturbed line, no segment passes through a
 *     perturbed crossroad, so every crossing is on exactly one road;
 *   - crossings at the same exact point of a line (only possible where a
 *     vertex or shape point lies on the line) are ordered by the segments'
 *     slopes, the same way at every level and on both sides of a road.
 *
 * Lattice coordinates given to these functions are relative to the domain's
 * south-west corner, in [0, 2^41], so every product below fits in __int128.
 */
#ifndef HPFC_GEOM_H
#define HPFC_GEOM_H

#include <stdbool.h>
#include <stdint.h>

__extension__ typedef __int128 i128;

typedef struct lpoint {
    int64_t x, y;
} lpoint;

/* Where a segment meets a grid line: the exact position num/den along the
 * line (den > 0) and the segment's tilt (dy for a vertical line, dx for a
 * horizontal one, over the same den) that breaks ties. */
typedef struct line_pos {
    i128 num;
    int64_t den;
    int64_t tilt;
} line_pos;

static inline int sign128(i128 v)
{
    return (v > 0) - (v < 0);
}

static inline int cmp128(i128 a, i128 b)
{
    return (a > b) - (a < b);
}

/* Sign of the cross product (b - a) x (c - a): > 0 when a, b, c turn left. */
static inline int orient(lpoint a, lpoint b, lpoint c)
{
    i128 d = (i128)(b.x - a.x) * (c.y - a.y) - (i128)(b.y - a.y) * (c.x - a.x);
    return sign128(d);
}

static inline bool point_in_cell(lpoint p, int64_t x0, int64_t y0,
                                 int64_t x1, int64_t y1)
{
    return p.x >= x0 && p.x < x1 && p.y >= y0 && p.y < y1;
}

/* The same point with x and y exchanged: a horizontal line seen as a
 * vertical one. */
static inline lpoint swap_xy(lpoint p)
{
    return (lpoint){p.y, p.x};
}

/* Does segment pq cross the perturbed vertical line x = X - eps? If so,
 * *pos receives the crossing's y as num/den and tilt = dy. A point on the
 * line is east of it, so the test is x >= X. */
static inline bool cross_vertical(lpoint p, lpoint q, int64_t X, line_pos *pos)
{
    if ((p.x >= X) == (q.x >= X))
        return false;
    if (p.x > q.x) {
        lpoint t = p;
        p = q;
        q = t;
    }
    int64_t den = q.x - p.x, dy = q.y - p.y;
    pos->num = (i128)p.y * den + (i128)dy * (X - p.x);
    pos->den = den;
    pos->tilt = dy;
    return true;
}

/* Same for the perturbed horizontal line y = Y - eps^2; num/den is x and
 * tilt dx. A point on the line is north of it (y >= Y), so with x and y
 * exchanged this is cross_vertical: the two perturbations differ only in
 * how crossings of one line are ordered (vpos_north_of, hpos_east_of). */
static inline bool cross_horizontal(lpoint p, lpoint q, int64_t Y, line_pos *pos)
{
    return cross_vertical(swap_xy(p), swap_xy(q), Y, pos);
}

/* A crossing of a vertical line sits at y* - eps * dy/dx. It is north of the
 * perturbed horizontal line Y - eps^2 iff y* > Y, or y* == Y and dy <= 0. */
static inline bool vpos_north_of(const line_pos *a, int64_t Y)
{
    int c = cmp128(a->num, (i128)Y * a->den);
    return c > 0 || (c == 0 && a->tilt <= 0);
}

/* A crossing of a horizontal line sits at x* - eps^2 * dx/dy, which is east
 * of the perturbed vertical line X - eps iff x* >= X. */
static inline bool hpos_east_of(const line_pos *a, int64_t X)
{
    return cmp128(a->num, (i128)X * a->den) >= 0;
}

/* Order of two crossings of one line: -1 if a comes first going north (for
 * a vertical line) or east (for a horizontal one). At equal exact position,
 * the larger tilt/den comes first, as the perturbation implies. */
static inline int cmp_line_pos(const line_pos *a, const line_pos *b)
{
    int c = cmp128(a->num * b->den, b->num * a->den);
    if (c)
        return c;
    return cmp128((i128)b->tilt * a->den, (i128)a->tilt * b->den);
}

#endif
