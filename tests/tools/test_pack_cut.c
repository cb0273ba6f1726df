/*
 * Unit tests of the cut of a build in parts (hpfc-pack/pack_cut.h) against
 * naive references: the root pixels' weights against a count of each
 * point's pixel from first principles; the even cut's runs against their
 * definition (a cover of the pixels in order, none empty, at most the parts
 * asked, each within a share plus one pixel); the cut under a limit against
 * a dynamic program's fewest runs; the budget's cut against the model
 * evaluated on it and on every cut the fewest runs can take, with and
 * without a sample of pixels a point.
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "pack_cut.h"

static uint64_t rng_state = 0x9e3779b97f4a7c15u;

static uint64_t rnd(uint64_t n)
{
    rng_state ^= rng_state << 13, rng_state ^= rng_state >> 7, rng_state ^= rng_state << 17;
    return n ? rng_state % n : 0;
}

/* Weights with empty stretches and a few heavy pixels, as a map's are. */
static void random_weights(uint64_t *w, uint64_t roots)
{
    for (uint64_t r = 0; r < roots; r++) {
        uint64_t kind = rnd(10);
        w[r] = kind < 4 ? 0 : kind < 9 ? rnd(100) : rnd(5000);
    }
}

static uint64_t run_weight(const uint64_t *w, const uint64_t *start, uint32_t q)
{
    uint64_t s = 0;
    for (uint64_t r = start[q]; r < start[q + 1]; r++)
        s += w[r];
    return s;
}

/* A cover of [0, roots) by `runs` non-empty runs in order. */
static void check_cover(const uint64_t *start, uint32_t runs, uint64_t roots)
{
    CHECK(runs >= 1);
    CHECK_EQ_INT(start[0], 0);
    CHECK_EQ_INT(start[runs], roots);
    for (uint32_t q = 0; q < runs; q++)
        CHECK(start[q] < start[q + 1]);
}

static void test_even(void)
{
    for (int round = 0; round < 300; round++) {
        uint64_t roots = 1 + rnd(300), w[300], start[301], total = 0, heaviest = 0;
        random_weights(w, roots);
        for (uint64_t r = 0; r < roots; r++)
            total += w[r], heaviest = w[r] > heaviest ? w[r] : heaviest;
        uint32_t parts = 1 + (uint32_t)rnd(roots + 5);
        uint32_t runs = pack_cut_even(w, roots, parts, start);
        check_cover(start, runs, roots);
        CHECK(runs <= parts);
        for (uint32_t q = 0; q < runs; q++)
            CHECK(run_weight(w, start, q) * parts <= total + heaviest * parts);
        /* no weight at all: one run, as many parts as asked gain nothing */
        memset(w, 0, sizeof w);
        CHECK_EQ_INT(pack_cut_even(w, roots, parts, start), 1);
        /* equal weights: exactly the parts asked, where there are pixels enough */
        for (uint64_t r = 0; r < roots; r++)
            w[r] = 7;
        runs = pack_cut_even(w, roots, parts, start);
        CHECK_EQ_INT(runs, parts < roots ? parts : roots);
        check_cover(start, runs, roots);
    }
}

/* The fewest runs of weight <= limit (a heavier pixel alone), by dynamic
 * programming over every run's end. */
static uint32_t fewest_runs(const uint64_t *w, uint64_t roots, uint64_t limit)
{
    uint32_t best[301];
    best[0] = 0;
    for (uint64_t end = 1; end <= roots; end++) {
        best[end] = UINT32_MAX;
        uint64_t s = 0;
        for (uint64_t first = end; first-- > 0;) {
            s += w[first];
            if (s > limit && first + 1 < end)
                break;
            if (best[first] + 1 < best[end])
                best[end] = best[first] + 1;
        }
    }
    return best[roots];
}

static void test_limit(void)
{
    for (int round = 0; round < 300; round++) {
        uint64_t roots = 1 + rnd(300), w[300], start[302];
        random_weights(w, roots);
        uint64_t limit = rnd(20000);
        uint32_t want = fewest_runs(w, roots, limit);
        uint32_t runs = pack_cut_limit(w, roots, limit, UINT32_MAX, start);
        CHECK_EQ_INT(runs, want);
        check_cover(start, runs, roots);
        for (uint32_t q = 0; q < runs; q++)
            CHECK(run_weight(w, start, q) <= limit || start[q + 1] == start[q] + 1);
        /* too many runs for `most`: cut evenly into `most` instead */
        if (want > 1) {
            uint32_t most = 1 + (uint32_t)rnd(want - 1);
            uint64_t even[302];
            runs = pack_cut_limit(w, roots, limit, most, start);
            CHECK_EQ_INT(runs, pack_cut_even(w, roots, most, even));
            CHECK(memcmp(start, even, (runs + 1) * sizeof *start) == 0);
        }
    }
}

/* The model on a cut. */
static uint64_t need_of(const uint64_t *w, const uint64_t *start, uint32_t runs, const pack_memory *base)
{
    pack_memory m = *base;
    m.parts = runs, m.points = 0, m.heaviest = 0;
    for (uint32_t q = 0; q < runs; q++) {
        uint64_t s = run_weight(w, start, q);
        m.points += s;
        m.heaviest = s > m.heaviest ? s : m.heaviest;
    }
    return pack_memory_need(&m);
}

/* The fewest runs whose need is at most `target`, over every cut: the
 * model depends on a cut's heaviest run only, and for each bound on it
 * the fewest runs are pack_cut_limit's (checked against the dynamic
 * program above), so every bound a run's weight can take is tried, and
 * the whole build. */
static uint32_t fewest_fitting(const uint64_t *w, uint64_t roots, const pack_memory *m,
                               uint64_t target)
{
    uint64_t whole[2] = {0, roots}, start[62];
    if (need_of(w, whole, 1, m) <= target)
        return 1;
    uint32_t best = UINT32_MAX;
    for (uint64_t first = 0; first < roots; first++) {
        uint64_t bound = 0;
        for (uint64_t end = first; end < roots; end++) {
            bound += w[end];
            uint32_t runs = pack_cut_limit(w, roots, bound, UINT32_MAX, start);
            if (runs > 1 && runs < best && need_of(w, start, runs, m) <= target)
                best = runs;
        }
    }
    return best;
}

static void test_budget(void)
{
    for (int round = 0; round < 400; round++) {
        uint64_t roots = 1 + rnd(60), w[60], start[61], finest[61];
        random_weights(w, roots);
        if (round % 4 == 0)
            w[rnd(roots)] = 20000 + rnd(100000); /* a dense city in one root pixel */
        /* a sample of none (a pixel a point), or of 0.1 to 2 pixels a point */
        pack_memory m = {.held = rnd(1u << 24), .jobs = 1 + (uint32_t)rnd(3)};
        if (round % 3) {
            m.sample_points = 1000 + rnd(100000);
            m.sample_pixels = m.sample_points / 10 + rnd(2 * m.sample_points);
        }
        for (uint64_t r = 0; r <= roots; r++)
            finest[r] = r;
        uint64_t whole[2] = {0, roots};
        uint64_t need_whole = need_of(w, whole, 1, &m);
        uint64_t least = need_of(w, finest, (uint32_t)roots, &m);
        least = roots > 1 && least < need_whole ? least : need_whole;
        uint64_t budget = m.held + rnd(need_whole - m.held + 2), need = 0;
        pack_memory given = m;
        uint32_t runs = pack_cut_budget(w, roots, &m, budget, (uint32_t)roots, start, &need);
        check_cover(start, runs, roots);
        CHECK_EQ_INT(need, need_of(w, start, runs, &given));
        CHECK_EQ_INT(need, pack_memory_need(&m)); /* m describes the cut taken */
        CHECK_EQ_INT(m.parts, runs);
        /* within the budget when any cut is, else the least any cut needs */
        uint64_t target = least <= budget ? budget : least;
        CHECK(need <= target);
        /* and in the fewest parts that do so */
        CHECK_EQ_INT(runs, fewest_fitting(w, roots, &given, target));
    }
}

/* The model grows with the sample's pixels a point: a map of many pixels
 * a point needs more, and with no sample it takes one a point. */
static void test_model(void)
{
    pack_memory few = {.points = 1000000, .heaviest = 1000000, .parts = 1, .jobs = 1,
                       .sample_points = 1000, .sample_pixels = 200};
    pack_memory many = few, none = few;
    many.sample_pixels = 900;
    none.sample_points = 0;
    CHECK(pack_memory_need(&few) < pack_memory_need(&many));
    pack_memory one = few;
    one.sample_pixels = 1000;
    CHECK_EQ_INT(pack_memory_need(&none), pack_memory_need(&one));
    few.parts = many.parts = 8, few.heaviest = many.heaviest = 200000;
    CHECK(pack_memory_need(&few) < pack_memory_need(&many));
}

/* A run is closed only by a pixel that would take it past the limit: a
 * run may weigh the limit exactly. */
static void test_limit_exact(void)
{
    uint64_t w[9] = {5, 5, 5, 5, 5, 5, 5, 5, 5}, start[10];
    CHECK_EQ_INT(pack_cut_limit(w, 9, 10, UINT32_MAX, start), 5);
    CHECK_EQ_INT(start[1], 2);
    CHECK_EQ_INT(pack_cut_limit(w, 9, 9, UINT32_MAX, start), 9);
    CHECK_EQ_INT(pack_cut_limit(w, 9, 45, UINT32_MAX, start), 1);
}

/* Weights from a graph: each point's root pixel counted from first
 * principles (cells of width / cols, row 0 the northern one). */
static void test_weigh(void)
{
    hpfc_graph *g = NULL;
    CHECK_EQ_INT(hpfc_graph_create(&g), HPFC_OK);
    int64_t xy[2 * 40];
    uint64_t want[16] = {0};
    hpfc_domain d = {.x0 = -8, .y0 = -4, .width = 32, .height = 16};
    hpfc_build_params p;
    hpfc_build_params_default(&p);
    p.root_cols = 4, p.root_rows = 4; /* cells 8 wide, 4 high */
    for (int e = 0; e < 30; e++) {
        uint32_t u, v;
        int64_t ux = -8 + (int64_t)rnd(32), uy = -4 + (int64_t)rnd(16);
        int64_t vx = -8 + (int64_t)rnd(32), vy = -4 + (int64_t)rnd(16);
        CHECK_EQ_INT(hpfc_graph_add_vertex(g, ux, uy, &u), HPFC_OK);
        CHECK_EQ_INT(hpfc_graph_add_vertex(g, vx, vy, &v), HPFC_OK);
        size_t n = (size_t)rnd(40);
        for (size_t k = 0; k < n; k++)
            xy[2 * k] = -8 + (int64_t)rnd(32), xy[2 * k + 1] = -4 + (int64_t)rnd(16);
        CHECK_EQ_INT(hpfc_graph_add_edge(g, u, v, xy, n, NULL), HPFC_OK);
        int64_t pts[2 * 42];
        pts[0] = ux, pts[1] = uy, pts[2] = vx, pts[3] = vy;
        memcpy(pts + 4, xy, 2 * n * sizeof *xy);
        for (size_t k = 0; k < n + 2; k++) {
            int64_t col = (pts[2 * k] + 8) / 8, row_up = (pts[2 * k + 1] + 4) / 4;
            want[(3 - row_up) * 4 + col]++;
        }
    }
    uint64_t got[16];
    pack_cut_weigh(g, &p, &d, got);
    for (int r = 0; r < 16; r++)
        CHECK_EQ_INT(got[r], want[r]);
    hpfc_graph_free(g);
}

int main(void)
{
    test_even();
    test_limit();
    test_limit_exact();
    test_budget();
    test_model();
    test_weigh();
    return check_report("pack_cut");
}
