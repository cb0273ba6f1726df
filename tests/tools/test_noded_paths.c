/*
 * Unit tests of the paths noding gave the parts' segments
 * (hpfc-pack/noded_paths.h):
 *  - noded_square_meets() against an independent oracle, exact clipping of
 *    the segment to the square with rational parameters;
 *  - noded_path() against a naive snap rounding written here: hot pixels at
 *    every end and every rounded crossing of random segments on a small
 *    grid (many near-misses and shared pixels), each segment routed through
 *    the centre of every hot pixel whose square it meets, in GEOS's order
 *    along the segment. Given only the routed pieces, the walk must find
 *    each segment's route exactly, and nothing for a segment that has none.
 */
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "noded_paths.h"

__extension__ typedef __int128 i128;

/* ---- the square test against clipping ------------------------------------------- */

/* Does a -> b meet the closed square [2qx - 1, 2qx + 1] x [2qy - 1, 2qy + 1]
 * (doubled coordinates)? Liang-Barsky: the parameter interval [lo, hi]
 * of the segment inside each slab, kept as fractions num/den with den > 0. */
static int clip_oracle(int64_t qx, int64_t qy, int64_t ax, int64_t ay, int64_t bx, int64_t by)
{
    i128 lo_n = 0, lo_d = 1, hi_n = 1, hi_d = 1;
    i128 p[2] = {2 * (i128)ax, 2 * (i128)ay}, d[2] = {2 * (i128)(bx - ax), 2 * (i128)(by - ay)};
    i128 c[2] = {2 * (i128)qx, 2 * (i128)qy};
    for (int k = 0; k < 2; k++) {
        i128 e0 = c[k] - 1 - p[k], e1 = c[k] + 1 - p[k]; /* want e0 <= t d <= e1 */
        if (d[k] == 0) {
            if (e0 > 0 || e1 < 0)
                return 0;
            continue;
        }
        i128 t0n = e0, t1n = e1, den = d[k];
        if (den < 0) {
            t0n = -e1, t1n = -e0, den = -den;
        }
        /* lo = max(lo, t0n/den), hi = min(hi, t1n/den) */
        if (t0n * lo_d > lo_n * den)
            lo_n = t0n, lo_d = den;
        if (t1n * hi_d < hi_n * den)
            hi_n = t1n, hi_d = den;
    }
    return lo_n * hi_d <= hi_n * lo_d;
}

static void test_square(void)
{
    srand(7);
    long met = 0;
    for (int i = 0; i < 200000; i++) {
        int64_t ax = rand() % 13 - 6, ay = rand() % 13 - 6, bx = rand() % 13 - 6, by = rand() % 13 - 6;
        int64_t qx = rand() % 9 - 4, qy = rand() % 9 - 4;
        if (ax == bx && ay == by)
            continue;
        int want = clip_oracle(qx, qy, ax, ay, bx, by);
        met += want;
        CHECK_EQ_INT(noded_square_meets(qx, qy, ax, ay, bx, by), want);
    }
    CHECK(met > 10000);
    /* touching the square's corner only, and near the lattice bound */
    CHECK_EQ_INT(noded_square_meets(0, 0, 1, 0, 0, 1), 1);  /* through (0.5, 0.5) */
    CHECK_EQ_INT(noded_square_meets(0, 0, 2, 0, 0, 2), 0);  /* passes (1, 1) */
    CHECK_EQ_INT(noded_square_meets(0, 0, 3, -1, -1, 3), 0);
    int64_t big = (int64_t)1 << 40;
    CHECK_EQ_INT(noded_square_meets(0, 0, -big, -big, big, big), 1);
    CHECK_EQ_INT(noded_square_meets(0, 1, -big, -big + 1, big, big + 1), 1);
    CHECK_EQ_INT(noded_square_meets(1, 0, -big, -big + 1, big, big + 1), 0);
    CHECK_EQ_INT(noded_square_meets(2, 0, -big, -big, big, big), 0);
}

/* ---- a naive snap rounding -------------------------------------------------------- */

typedef struct pt {
    int64_t x, y;
} pt;

static int pt_cmp(const void *a, const void *b)
{
    const pt *p = a, *q = b;
    if (p->x != q->x)
        return p->x < q->x ? -1 : 1;
    return (p->y > q->y) - (p->y < q->y);
}

/* Nearest integer to num/den (den > 0), halves up, as GEOS's rounding. */
static int64_t round_div(i128 num, i128 den)
{
    i128 f = num >= 0 ? num / den : -((-num + den - 1) / den); /* floor */
    i128 rem = num - f * den;                                  /* 0 <= rem < den */
    return (int64_t)(2 * rem >= den ? f + 1 : f);
}

/* Appends the rounded crossing of segments a and b, if they cross. */
static void add_crossing(const pt *a, const pt *b, pt *hot, size_t *n)
{
    i128 rx = a[1].x - a[0].x, ry = a[1].y - a[0].y, sx = b[1].x - b[0].x, sy = b[1].y - b[0].y;
    i128 den = rx * sy - ry * sx;
    if (den == 0)
        return; /* parallel: their ends are hot already */
    i128 qx = b[0].x - a[0].x, qy = b[0].y - a[0].y;
    i128 tn = qx * sy - qy * sx, un = qx * ry - qy * rx;
    if (den < 0)
        den = -den, tn = -tn, un = -un;
    if (tn < 0 || tn > den || un < 0 || un > den)
        return;
    hot[(*n)++] = (pt){round_div((i128)a[0].x * den + tn * rx, den),
                       round_div((i128)a[0].y * den + tn * ry, den)};
}

/* GEOS's order along a segment of direction (dx, dy) (SegmentPointComparator
 * by octant, read as a rule): the major axis first, in the direction's
 * sense, then the minor axis, in its sense (+ when the minor part is 0). */
static int along(int64_t dx, int64_t dy, pt p, pt q)
{
    int xs = (p.x > q.x) - (p.x < q.x), ys = (p.y > q.y) - (p.y < q.y);
    int major_x = (dx < 0 ? -dx : dx) >= (dy < 0 ? -dy : dy);
    int sx = dx >= 0 ? 1 : -1, sy = dy >= 0 ? 1 : -1;
    int first = major_x ? sx * xs : sy * ys, second = major_x ? sy * ys : sx * xs;
    return first ? first : second;
}

typedef struct route {
    pt *p;
    size_t n;
} route;

static const pt *sort_seg;
static int sort_along(const void *a, const void *b)
{
    return along(sort_seg[1].x - sort_seg[0].x, sort_seg[1].y - sort_seg[0].y, *(const pt *)a,
                 *(const pt *)b);
}

/* The route of segment s through the hot pixels hot[0 .. n). */
static route route_of(const pt *s, const pt *hot, size_t n)
{
    route r = {malloc((n + 2) * sizeof *r.p), 0};
    for (size_t k = 0; k < n; k++)
        if (noded_square_meets(hot[k].x, hot[k].y, s[0].x, s[0].y, s[1].x, s[1].y))
            r.p[r.n++] = hot[k];
    sort_seg = s;
    qsort(r.p, r.n, sizeof *r.p, sort_along);
    return r;
}

static int seg_cmp(const void *a, const void *b)
{
    const segnode_seg *p = a, *q = b;
    int64_t x[4] = {p->ax, p->ay, p->bx, p->by}, y[4] = {q->ax, q->ay, q->bx, q->by};
    for (int k = 0; k < 4; k++)
        if (x[k] != y[k])
            return x[k] < y[k] ? -1 : 1;
    return 0;
}

static segnode_seg ordered(pt a, pt b)
{
    return pt_cmp(&a, &b) < 0 ? (segnode_seg){a.x, a.y, b.x, b.y}
                              : (segnode_seg){b.x, b.y, a.x, a.y};
}

static void test_routes(int seed, int n_seg, int size)
{
    srand((unsigned)seed);
    pt *s = malloc(2 * (size_t)n_seg * sizeof *s);
    for (int i = 0; i < n_seg; i++) {
        do {
            s[2 * i] = (pt){rand() % size, rand() % size};
            s[2 * i + 1] = (pt){rand() % size, rand() % size};
        } while (s[2 * i].x == s[2 * i + 1].x && s[2 * i].y == s[2 * i + 1].y);
    }
    size_t n_hot = 0;
    pt *hot = malloc((2 * (size_t)n_seg + (size_t)n_seg * n_seg) * sizeof *hot);
    for (int i = 0; i < 2 * n_seg; i++)
        hot[n_hot++] = s[i];
    for (int i = 0; i < n_seg; i++)
        for (int j = i + 1; j < n_seg; j++)
            add_crossing(s + 2 * i, s + 2 * j, hot, &n_hot);
    qsort(hot, n_hot, sizeof *hot, pt_cmp);
    size_t u = 0;
    for (size_t k = 0; k < n_hot; k++)
        if (!u || pt_cmp(&hot[u - 1], &hot[k]))
            hot[u++] = hot[k];
    n_hot = u;
    route *routes = malloc((size_t)n_seg * sizeof *routes);
    size_t n_out = 0, cap_out = 0;
    segnode_seg *out = NULL;
    for (int i = 0; i < n_seg; i++) {
        routes[i] = route_of(s + 2 * i, hot, n_hot);
        cap_out += routes[i].n;
    }
    out = malloc(cap_out * sizeof *out);
    for (int i = 0; i < n_seg; i++)
        for (size_t k = 0; k + 1 < routes[i].n; k++)
            out[n_out++] = ordered(routes[i].p[k], routes[i].p[k + 1]);
    qsort(out, n_out, sizeof *out, seg_cmp);
    u = 0;
    for (size_t k = 0; k < n_out; k++)
        if (!u || seg_cmp(&out[u - 1], &out[k]))
            out[u++] = out[k];
    n_out = u;

    noded_index *ix = NULL;
    CHECK(noded_index_create(out, n_out, &ix) == 0);
    point_list got = {0};
    for (int i = 0; i < n_seg && ix; i++) {
        route *r = &routes[i];
        /* both directions: a ring may run either way along a segment */
        for (int dir = 0; dir < 2; dir++) {
            pt a = s[2 * i + dir], b = s[2 * i + 1 - dir];
            got.n = 0;
            int st = noded_path(ix, a.x, a.y, b.x, b.y, &got);
            CHECK_EQ_INT(st, 0);
            if (st)
                continue;
            CHECK_EQ_INT(got.n, r->n - 1);
            for (size_t k = 0; k < got.n && got.n == r->n - 1; k++) {
                pt want = r->p[dir ? r->n - 2 - k : k + 1];
                CHECK(got.xy[2 * k] == want.x && got.xy[2 * k + 1] == want.y);
            }
            CHECK(noded_index_has(ix, a.x, a.y, got.xy[0], got.xy[1]));
        }
    }
    /* a segment between two hot pixels that no route joins has no path */
    if (ix) {
        got.n = 0;
        CHECK_EQ_INT(noded_path(ix, -100, -100, -90, -100, &got), 1);
        CHECK_EQ_INT(got.n, 0);
    }
    noded_index_free(ix);
    free(got.xy);
    for (int i = 0; i < n_seg; i++)
        free(routes[i].p);
    free(routes);
    free(out);
    free(hot);
    free(s);
}

int main(void)
{
    test_square();
    for (int seed = 1; seed <= 40; seed++)
        test_routes(seed, 6 + seed % 20, seed % 2 ? 12 : 40);
    test_routes(99, 60, 25); /* dense: many shared hot pixels */
    return check_report("noded_paths");
}
