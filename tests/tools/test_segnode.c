/*
 * Unit tests of hpfc-pack's exact "needs noding" test (hpfc-pack/segnode.h):
 * segnode_interact() against hand-made cases and an independent parametric
 * oracle on small integer segments (many degeneracies: shared ends, touches,
 * collinear overlaps), segnode_find_dirty()'s grid against all pairs,
 * segnode_any_near() against all pairs with a fresh segment,
 * with long segments and coordinates near the lattice bound.
 */
#include <stdlib.h>
#include <string.h>

#include "segnode.h"
#include "check.h"

__extension__ typedef __int128 i128;

static segnode_seg seg(int64_t x1, int64_t y1, int64_t x2, int64_t y2)
{
    int swap = x2 < x1 || (x2 == x1 && y2 < y1);
    return swap ? (segnode_seg){x2, y2, x1, y1} : (segnode_seg){x1, y1, x2, y2};
}

static int meet(segnode_seg a, segnode_seg b)
{
    int r = segnode_interact(&a, &b);
    CHECK_EQ_INT(segnode_interact(&b, &a), r);
    return r;
}

static void test_cases(void)
{
    CHECK_EQ_INT(meet(seg(0, 0, 2, 2), seg(0, 2, 2, 0)), 1);  /* crossing */
    CHECK_EQ_INT(meet(seg(0, 0, 2, 0), seg(1, 0, 1, 3)), 1);  /* T: end on interior */
    CHECK_EQ_INT(meet(seg(0, 0, 2, 0), seg(2, 0, 3, 5)), 0);  /* shared end */
    CHECK_EQ_INT(meet(seg(0, 0, 2, 0), seg(2, 0, 4, 0)), 0);  /* collinear, end to end */
    CHECK_EQ_INT(meet(seg(0, 0, 2, 0), seg(1, 0, 4, 0)), 1);  /* collinear overlap */
    CHECK_EQ_INT(meet(seg(0, 0, 4, 0), seg(1, 0, 2, 0)), 1);  /* one inside the other */
    CHECK_EQ_INT(meet(seg(0, 0, 2, 0), seg(3, 0, 4, 0)), 0);  /* collinear apart */
    CHECK_EQ_INT(meet(seg(0, 0, 0, 2), seg(0, 1, 0, 5)), 1);  /* vertical overlap */
    CHECK_EQ_INT(meet(seg(0, 0, 1, 1), seg(2, 2, 3, 3)), 0);  /* diagonal apart */
    CHECK_EQ_INT(meet(seg(0, 0, 2, 2), seg(1, 1, 3, 3)), 1);  /* diagonal overlap */
    CHECK_EQ_INT(meet(seg(0, 0, 2, 2), seg(2, 2, 2, 0)), 0);  /* corner */
    CHECK_EQ_INT(meet(seg(0, 0, 4, 1), seg(1, 1, 3, 2)), 0);  /* parallel */
    /* near the lattice bound, where 64-bit products overflow */
    int64_t big = (int64_t)1 << 40;
    CHECK_EQ_INT(meet(seg(-big, -big, big, big), seg(-big, big, big, -big)), 1);
    CHECK_EQ_INT(meet(seg(-big, -big, big, big - 1), seg(-big, -big + 1, big, big)), 0);
    CHECK_EQ_INT(meet(seg(-big, -big, big, big - 1), seg(-big + 2, -big + 1, big, big)), 1);
    CHECK_EQ_INT(meet(seg(-big, -big, big, big), seg(0, 0, big, -big)), 1);
}

/* ---- the parametric oracle ------------------------------------------------------ */

static i128 cross(i128 ax, i128 ay, i128 bx, i128 by)
{
    return ax * by - ay * bx;
}

/* num/den in [0, 1], den != 0 */
static int in01(i128 num, i128 den)
{
    return den > 0 ? num >= 0 && num <= den : num <= 0 && num >= den;
}

static int at_end(i128 num, i128 den)
{
    return num == 0 || num == den;
}

/* Do a and b share a point that is not an end of both? */
static int oracle(segnode_seg a, segnode_seg b)
{
    i128 dx1 = a.bx - a.ax, dy1 = a.by - a.ay, dx2 = b.bx - b.ax, dy2 = b.by - b.ay;
    i128 ex = b.ax - a.ax, ey = b.ay - a.ay;
    i128 den = cross(dx1, dy1, dx2, dy2);
    if (den != 0) {
        i128 t = cross(ex, ey, dx2, dy2), u = cross(ex, ey, dx1, dy1);
        if (!in01(t, den) || !in01(u, den))
            return 0;
        return !(at_end(t, den) && at_end(u, den));
    }
    if (cross(ex, ey, dx1, dy1) != 0)
        return 0; /* parallel lines */
    /* collinear: b's ends as parameters along a, over len = |d1|^2 */
    i128 len = dx1 * dx1 + dy1 * dy1;
    i128 tc = ex * dx1 + ey * dy1, td = (b.bx - a.ax) * dx1 + (b.by - a.ay) * dy1;
    i128 lo = tc < td ? tc : td, hi = tc < td ? td : tc;
    if (lo < 0)
        lo = 0;
    if (hi > len)
        hi = len;
    return lo < hi;
}

static uint64_t rng_state = 0x9E3779B97F4A7C15u;

static int64_t rnd(int64_t n)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (int64_t)(rng_state % (uint64_t)n);
}

static void test_oracle(void)
{
    for (int k = 0; k < 200000; k++) {
        segnode_seg a, b;
        do
            a = seg(rnd(6), rnd(6), rnd(6), rnd(6));
        while (a.ax == a.bx && a.ay == a.by);
        do
            b = seg(rnd(6), rnd(6), rnd(6), rnd(6));
        while ((b.ax == b.bx && b.ay == b.by) || memcmp(&a, &b, sizeof a) == 0);
        if (segnode_interact(&a, &b) != oracle(a, b)) {
            CHECK(0);
            return;
        }
    }
}

/* ---- the grid against all pairs ---------------------------------------------------- */

static int cmp(const void *p, const void *q)
{
    return memcmp(p, q, sizeof(segnode_seg));
}

/* Sorts s[0 .. n) and keeps each segment once: the count kept. */
static size_t sort_unique(segnode_seg *s, size_t n)
{
    qsort(s, n, sizeof *s, cmp);
    size_t u = 0;
    for (size_t i = 0; i < n; i++)
        if (u == 0 || cmp(&s[u - 1], &s[i]) != 0)
            s[u++] = s[i];
    return u;
}

static void grid_case(int64_t span, int64_t offset, int n_long)
{
    enum { N = 1500 };
    segnode_seg s[N];
    size_t n = 0;
    while (n < N) {
        int64_t x = rnd(span), y = rnd(span);
        int64_t r = (int)n < n_long ? span : span / 40 + 1;
        segnode_seg t = seg(offset + x, offset + y, offset + x + rnd(2 * r + 1) - r,
                            offset + y + rnd(2 * r + 1) - r);
        if (t.ax != t.bx || t.ay != t.by)
            s[n++] = t;
    }
    size_t u = sort_unique(s, n);
    unsigned char got[N] = {0}, want[N] = {0};
    long long marked = segnode_find_dirty(s, u, got, 1);
    long long expect = 0;
    for (size_t i = 0; i < u; i++)
        for (size_t j = i + 1; j < u; j++)
            if (segnode_interact(&s[i], &s[j]))
                want[i] = want[j] = 1;
    for (size_t i = 0; i < u; i++) {
        expect += want[i];
        /* a long segment may be marked untested; a clean one never wrongly
         * left out */
        if (want[i] && !got[i]) {
            CHECK(0);
            return;
        }
    }
    CHECK(marked >= expect);
    if (n_long == 0)
        CHECK_EQ_INT(marked, expect);
}

static void test_grid(void)
{
    grid_case(1000, 0, 0);           /* sparse: few meet */
    grid_case(60, 0, 0);             /* dense: many meet, many degeneracies */
    grid_case(100000, -(1LL << 39), 0);
    grid_case(1000, 0, 30);          /* long segments across everything */
    grid_case((int64_t)1 << 38, (int64_t)1 << 38, 0);
}

/* Enough segments for the cells to be tested on several threads (the
 * small cases above, checked against all pairs, run on one): a random
 * network of short segments with a few crossings among them, marked alike
 * on 1, 2 and 3 threads, and the crossings found. */
static void test_grid_threads(void)
{
    enum { N = 120000 };
    segnode_seg *s = malloc(N * sizeof *s);
    unsigned char *one = calloc(N, 1), *many = calloc(N, 1);
    if (!s || !one || !many) {
        CHECK(0);
        free(s), free(one), free(many);
        return;
    }
    size_t n = 0;
    while (n < N) {
        int64_t x = rnd(1000000), y = rnd(1000000);
        segnode_seg t = seg(x, y, x + rnd(801) - 400, y + rnd(801) - 400);
        if (t.ax != t.bx || t.ay != t.by)
            s[n++] = t;
    }
    size_t u = sort_unique(s, n);
    long long marked = segnode_find_dirty(s, u, one, 1);
    CHECK(marked > 100 && (size_t)marked < u / 4); /* some cross, most do not */
    for (unsigned threads = 2; threads <= 3; threads++) {
        memset(many, 0, N);
        CHECK_EQ_INT(segnode_find_dirty(s, u, many, threads), marked);
        CHECK(memcmp(one, many, u) == 0);
    }
    free(s);
    free(one);
    free(many);
}

/* ---- segnode_any_near against all pairs with a fresh segment ------------------- */

/* all: n random segments (distinct); fresh: m of them (every k-th, so each
 * is also in all) or, with `apart`, m new ones. Brute force: does any pair
 * (fresh, all) other than a segment with itself meet? */
static int near_case(int64_t span, int64_t len, size_t m, int apart)
{
    enum { N = 1200 };
    segnode_seg all[N], fresh[N];
    size_t n = 0;
    while (n < N) {
        int64_t x = rnd(span), y = rnd(span);
        segnode_seg t = seg(x, y, x + rnd(2 * len + 1) - len, y + rnd(2 * len + 1) - len);
        if (t.ax != t.bx || t.ay != t.by)
            all[n++] = t;
    }
    size_t u = sort_unique(all, n);
    for (size_t k = 0; k < m; k++) {
        if (!apart) {
            fresh[k] = all[(k * 7919) % u];
            continue;
        }
        int64_t x = rnd(span), y = rnd(span);
        fresh[k] = seg(x, y, x + len, y + 1 + rnd(len));
    }
    int want = 0;
    for (size_t k = 0; k < m && !want; k++)
        for (size_t i = 0; i < u && !want; i++)
            want = memcmp(&fresh[k], &all[i], sizeof all[i]) != 0 &&
                   segnode_interact(&fresh[k], &all[i]);
    CHECK_EQ_INT(segnode_any_near(fresh, m, all, u), want);
    return want;
}

static void test_near(void)
{
    int seen[2] = {0, 0};
    for (int round = 0; round < 300 && !check_failures; round++) {
        /* from sparse maps, where a few fresh segments often meet nothing,
         * to dense ones, where most do */
        int64_t span = round % 3 == 0 ? 100000 : round % 3 == 1 ? 5000 : 400;
        size_t m = 1 + (size_t)rnd(round % 2 ? 3 : 40);
        seen[near_case(span, 1 + rnd(20), m, round % 4 == 3)]++;
    }
    CHECK(seen[0] > 10 && seen[1] > 10); /* both answers were asked for */
    CHECK_EQ_INT(segnode_any_near(NULL, 0, NULL, 0), 0);
}

int main(void)
{
    test_cases();
    test_oracle();
    test_grid();
    test_near();
    test_grid_threads();
    return check_report("test_segnode");
}
