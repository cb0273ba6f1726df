/*
 * pack_cut.c: see pack_cut.h.
 */
#include "pack_cut.h"

#include <stdio.h>

#ifdef __GLIBC__
#include <malloc.h>
#endif

/* The memory model's bytes a point and a pixel of the tree, fitted to a
 * generated street network (0.2 pixels a point) and to countries-land-1m's
 * graph (0.94) and rounded up by a tenth (bench/README.md, "A memory
 * budget"): a whole build's working arrays and tree (its validation
 * included); the cut's lists of every part's edges; a part's builder
 * arrays, tree and graph; the join of the part files and the write
 * (LABL's face numbering, the edges' union-find). */
enum {
    WHOLE_BYTES_A_POINT = 44,
    WHOLE_BYTES_A_PIXEL = 24,
    CUT_BYTES_A_POINT = 2,
    PART_BYTES_A_POINT = 56,
    PART_BYTES_A_PIXEL = 60,
    JOIN_BYTES_A_POINT = 2,
    JOIN_BYTES_A_PIXEL = 25,
};

/* products of points and parts, or of points and pixels, may pass 64 bits */
__extension__ typedef unsigned __int128 u128;

static uint64_t root_of(const hpfc_domain *d, uint64_t cell_w, uint64_t cell_h, uint32_t cols,
                        uint32_t rows, int64_t x, int64_t y)
{
    /* the domain holds every point of the map it was chosen for; the clamps
     * only keep a stray index inside the array */
    uint64_t i = x > d->x0 ? (uint64_t)(x - d->x0) / cell_w : 0;
    uint64_t j = y > d->y0 ? (uint64_t)(y - d->y0) / cell_h : 0;
    i = i < cols ? i : cols - 1u;
    j = j < rows ? j : rows - 1u;
    return (rows - 1u - j) * (uint64_t)cols + i; /* row 0 is the northern one */
}

void pack_cut_weigh(const hpfc_graph *g, const hpfc_build_params *p, const hpfc_domain *d,
                    uint64_t *weight)
{
    uint32_t cols = p->root_cols, rows = p->root_rows;
    uint64_t cell_w = (uint64_t)d->width / cols, cell_h = (uint64_t)d->height / rows;
    for (uint64_t r = 0; r < (uint64_t)cols * rows; r++)
        weight[r] = 0;
    for (size_t v = 0; v < hpfc_graph_vertex_count(g); v++) {
        int64_t x, y;
        hpfc_graph_vertex(g, v, &x, &y);
        weight[root_of(d, cell_w, cell_h, cols, rows, x, y)]++;
    }
    for (size_t e = 0; e < hpfc_graph_edge_count(g); e++) {
        uint32_t u, v;
        const int64_t *xy;
        size_t n;
        hpfc_graph_edge(g, e, &u, &v, &xy, &n);
        for (size_t k = 0; k < n; k++)
            weight[root_of(d, cell_w, cell_h, cols, rows, xy[2 * k], xy[2 * k + 1])]++;
    }
}

uint32_t pack_cut_even(const uint64_t *weight, uint64_t roots, uint32_t parts, uint64_t *start)
{
    u128 total = 0, before = 0;
    for (uint64_t r = 0; r < roots; r++)
        total += weight[r];
    uint32_t runs = 1;
    start[0] = 0;
    if (total == 0)
        parts = 1; /* nothing to share out */
    /* a run starts at the first pixel whose points before it reach the
     * next share of the total */
    for (uint64_t r = 0; r < roots; r++) {
        if (r > start[runs - 1] && runs < parts && before * parts >= total * runs)
            start[runs++] = r;
        before += weight[r];
    }
    start[runs] = roots;
    return runs;
}

uint32_t pack_cut_limit(const uint64_t *weight, uint64_t roots, uint64_t limit, uint32_t most,
                        uint64_t *start)
{
    uint32_t runs = 1;
    uint64_t in_run = 0;
    start[0] = 0;
    for (uint64_t r = 0; r < roots; r++) {
        if (r > start[runs - 1] && in_run + weight[r] > limit) {
            if (runs == most)
                return pack_cut_even(weight, roots, most, start);
            start[runs++] = r;
            in_run = 0;
        }
        in_run += weight[r];
    }
    start[runs] = roots;
    return runs;
}

/* The pixels of `points` points, by the sample's proportion. */
static uint64_t pixels_of(const pack_memory *m, uint64_t points)
{
    if (m->sample_points == 0)
        return points;
    return (uint64_t)((u128)points * m->sample_pixels / m->sample_points);
}

uint64_t pack_memory_need(const pack_memory *m)
{
    uint64_t n = m->points, px = pixels_of(m, n), h = m->heaviest;
    if (m->parts <= 1)
        return m->held + WHOLE_BYTES_A_POINT * n + WHOLE_BYTES_A_PIXEL * px;
    uint64_t build = CUT_BYTES_A_POINT * n +
                     (uint64_t)m->jobs * (PART_BYTES_A_POINT * h + PART_BYTES_A_PIXEL * pixels_of(m, h));
    uint64_t join = JOIN_BYTES_A_POINT * n + JOIN_BYTES_A_PIXEL * px;
    return m->held + (build > join ? build : join);
}

static uint64_t heaviest_run(const uint64_t *weight, const uint64_t *start, uint32_t runs)
{
    uint64_t most = 0;
    for (uint32_t q = 0; q < runs; q++) {
        uint64_t w = 0;
        for (uint64_t r = start[q]; r < start[q + 1]; r++)
            w += weight[r];
        most = w > most ? w : most;
    }
    return most;
}

/* The heaviest run whose part keeps the build within `budget` (0 when
 * none does): a binary search, as the need grows with the run's points. */
static uint64_t part_limit(pack_memory m, uint64_t budget)
{
    uint64_t lo = 0, hi = m.points;
    m.parts = 2;
    while (lo < hi) {
        uint64_t mid = lo + (hi - lo + 1) / 2;
        m.heaviest = mid;
        uint64_t build = pack_memory_need(&m);
        m.heaviest = 0;
        /* the part's own share, beside the join's floor */
        if (build <= budget || build <= pack_memory_need(&m))
            lo = mid;
        else
            hi = mid - 1;
    }
    return lo;
}

uint32_t pack_cut_budget(const uint64_t *weight, uint64_t roots, pack_memory *m, uint64_t budget,
                         uint32_t most, uint64_t *start, uint64_t *need)
{
    uint64_t pixel_most = 0;
    m->jobs = m->jobs ? m->jobs : 1;
    m->points = 0;
    for (uint64_t r = 0; r < roots; r++) {
        m->points += weight[r];
        pixel_most = weight[r] > pixel_most ? weight[r] : pixel_most;
    }
    m->parts = 1;
    m->heaviest = m->points;
    uint64_t need_whole = pack_memory_need(m);
    start[0] = 0, start[1] = roots;
    *need = need_whole;
    if (need_whole <= budget || most <= 1)
        return 1;
    /* the heaviest part the budget leaves room for, a part at a time on
     * each job. Two floors: no part is lighter than the heaviest root
     * pixel, and parts whose build needs less than the join gain nothing,
     * since the join comes after them (part_limit stops at neither) */
    uint64_t limit = part_limit(*m, budget);
    limit = limit > pixel_most ? limit : pixel_most;
    m->parts = pack_cut_limit(weight, roots, limit, most, start);
    m->heaviest = heaviest_run(weight, start, m->parts);
    *need = pack_memory_need(m);
    if (*need > budget && need_whole <= *need) {
        /* nothing fits, and the whole build needs no more than parts */
        m->parts = 1, m->heaviest = m->points;
        start[1] = roots;
        *need = need_whole;
        return 1;
    }
    return m->parts;
}

/* RssAnon of /proc/self/status, in bytes; 0 where there is none. */
static uint64_t resident_anonymous(void)
{
    FILE *f = fopen("/proc/self/status", "r");
    char line[256];
    unsigned long long kb = 0;
    while (f && fgets(line, sizeof line, f))
        if (sscanf(line, "RssAnon: %llu kB", &kb) == 1)
            break;
    if (f)
        fclose(f);
    return (uint64_t)kb << 10;
}

uint64_t pack_own_bytes(void)
{
    uint64_t resident = resident_anonymous();
    if (resident)
        return resident;
#if defined(__GLIBC__) && (__GLIBC__ > 2 || __GLIBC_MINOR__ >= 33)
    struct mallinfo2 mi = mallinfo2();
    return (uint64_t)mi.uordblks + (uint64_t)mi.hblkhd;
#else
    return 0;
#endif
}
