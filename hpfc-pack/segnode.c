/*
 * segnode.c: see segnode.h.
 */
#include "segnode.h"

#include <math.h>
#include <pthread.h>
#include <stdlib.h>

__extension__ typedef __int128 i128;

/* A segment covering more grid cells than this is marked dirty untested:
 * long segments are rare in real layers, and GEOS nodes them. */
enum { MAX_CELLS_PER_SEGMENT = 4096 };

/* Sign of the turn a -> b -> c. */
static int orient(int64_t ax, int64_t ay, int64_t bx, int64_t by, int64_t cx, int64_t cy)
{
    i128 d = (i128)(bx - ax) * (cy - ay) - (i128)(by - ay) * (cx - ax);
    return (d > 0) - (d < 0);
}

static int lex_less(int64_t x1, int64_t y1, int64_t x2, int64_t y2)
{
    return x1 < x2 || (x1 == x2 && y1 < y2);
}

static int64_t min64(int64_t a, int64_t b)
{
    return a < b ? a : b;
}

static int64_t max64(int64_t a, int64_t b)
{
    return a > b ? a : b;
}

int segnode_interact(const segnode_seg *a, const segnode_seg *b)
{
    if (a->bx < b->ax || b->bx < a->ax || max64(a->ay, a->by) < min64(b->ay, b->by) ||
        max64(b->ay, b->by) < min64(a->ay, a->by))
        return 0;
    int o1 = orient(a->ax, a->ay, a->bx, a->by, b->ax, b->ay);
    int o2 = orient(a->ax, a->ay, a->bx, a->by, b->bx, b->by);
    int o3 = orient(b->ax, b->ay, b->bx, b->by, a->ax, a->ay);
    int o4 = orient(b->ax, b->ay, b->bx, b->by, a->bx, a->by);
    if ((o1 && o1 == o2) || (o3 && o3 == o4))
        return 0; /* one lies wholly on one side of the other's line */
    if (o1 == 0 && o2 == 0) {
        /* collinear: ends are sorted along the line, so they overlap when the
         * later start comes before the earlier end */
        int a_starts_later = lex_less(b->ax, b->ay, a->ax, a->ay);
        int64_t sx = a_starts_later ? a->ax : b->ax, sy = a_starts_later ? a->ay : b->ay;
        int b_ends_first = lex_less(b->bx, b->by, a->bx, a->by);
        int64_t ex = b_ends_first ? b->bx : a->bx, ey = b_ends_first ? b->by : a->by;
        return lex_less(sx, sy, ex, ey);
    }
    /* one common point: fine only if it is an end of both */
    int shared = (a->ax == b->ax && a->ay == b->ay) || (a->ax == b->bx && a->ay == b->by) ||
                 (a->bx == b->ax && a->by == b->ay) || (a->bx == b->bx && a->by == b->by);
    return !shared;
}

/* The uniform grid: cell (i, j) covers x0 + [i, i+1) * size, y0 + ... */
typedef struct grid {
    int64_t x0, y0, size;
    size_t cols, rows;
} grid;

static void cell_range(const grid *g, const segnode_seg *s, size_t *i0, size_t *i1, size_t *j0,
                       size_t *j1)
{
    *i0 = (size_t)((s->ax - g->x0) / g->size);
    *i1 = (size_t)((s->bx - g->x0) / g->size);
    *j0 = (size_t)((min64(s->ay, s->by) - g->y0) / g->size);
    *j1 = (size_t)((max64(s->ay, s->by) - g->y0) / g->size);
}

/* Cells of about twice the mean segment extent, but no more cells than
 * segments (plus a row and a column), and at most 2^20 a side. */
static grid make_grid(const segnode_seg *s, size_t n)
{
    int64_t x0 = s[0].ax, x1 = s[0].bx, y0 = min64(s[0].ay, s[0].by), y1 = max64(s[0].ay, s[0].by);
    double len = 0;
    for (size_t i = 0; i < n; i++) {
        x0 = min64(x0, s[i].ax);
        x1 = max64(x1, s[i].bx);
        y0 = min64(y0, min64(s[i].ay, s[i].by));
        y1 = max64(y1, max64(s[i].ay, s[i].by));
        int64_t dy = s[i].by - s[i].ay;
        len += (double)max64(s[i].bx - s[i].ax, dy < 0 ? -dy : dy);
    }
    double w = (double)(x1 - x0) + 1, h = (double)(y1 - y0) + 1;
    double size = fmax(2 * len / (double)n, sqrt(w * h / (double)n));
    size = fmax(fmax(size, fmax(w, h) / 1048576.0), 1.0);
    grid g = {x0, y0, (int64_t)ceil(size), 0, 0};
    g.cols = (size_t)((x1 - x0) / g.size) + 1;
    g.rows = (size_t)((y1 - y0) / g.size) + 1;
    return g;
}

/* dirty[] is shared by the threads that test cells: a segment in cells of
 * two threads may be marked by both. Marks only ever go from 0 to 1, and a
 * mark read only spares a test whose answer would change nothing, so the
 * set marked is the same in any order. */
static unsigned char dirty_get(const unsigned char *dirty, uint32_t i)
{
    return __atomic_load_n(&dirty[i], __ATOMIC_RELAXED);
}

static void dirty_set(unsigned char *dirty, uint32_t i)
{
    __atomic_store_n(&dirty[i], 1, __ATOMIC_RELAXED);
}

/* Tests every pair of segments sharing cell c. */
static void test_cell(const segnode_seg *s, const uint32_t *ids, size_t k, unsigned char *dirty)
{
    for (size_t p = 0; p < k; p++)
        for (size_t q = p + 1; q < k; q++) {
            uint32_t a = ids[p], b = ids[q];
            if ((!dirty_get(dirty, a) || !dirty_get(dirty, b)) && segnode_interact(&s[a], &s[b])) {
                dirty_set(dirty, a);
                dirty_set(dirty, b);
            }
        }
}

/* Cells [first, end) of the grid's buckets, tested by one thread. */
typedef struct cell_run {
    const segnode_seg *s;
    const uint32_t *ids;
    const size_t *start;
    size_t first, end;
    unsigned char *dirty;
} cell_run;

static void *test_cells(void *arg)
{
    const cell_run *r = arg;
    for (size_t c = r->first; c < r->end; c++)
        test_cell(r->s, r->ids + r->start[c], r->start[c + 1] - r->start[c], r->dirty);
    return NULL;
}

/* The cells' tests, on up to `threads` threads with about as many bucket
 * entries each (a run whose thread cannot start is tested here). */
static void test_all_cells(const segnode_seg *s, const uint32_t *ids, const size_t *start,
                           size_t cells, unsigned char *dirty, unsigned threads)
{
    enum { MAX_RUNS = 16, MIN_ENTRIES_PER_RUN = 1 << 15 };
    size_t entries = start[cells], runs = threads < 1 ? 1 : threads > MAX_RUNS ? MAX_RUNS : threads;
    if (entries / MIN_ENTRIES_PER_RUN < runs)
        runs = entries / MIN_ENTRIES_PER_RUN ? entries / MIN_ENTRIES_PER_RUN : 1;
    cell_run run[MAX_RUNS];
    pthread_t thread[MAX_RUNS];
    int started[MAX_RUNS] = {0};
    size_t c = 0;
    for (size_t k = 0; k < runs; k++) {
        size_t goal = entries / runs * (k + 1);
        run[k] = (cell_run){s, ids, start, c, c, dirty};
        while (c < cells && (k + 1 == runs || start[c + 1] <= goal))
            c++;
        run[k].end = c;
    }
    for (size_t k = 1; k < runs; k++)
        started[k] = pthread_create(&thread[k], NULL, test_cells, &run[k]) == 0;
    test_cells(&run[0]);
    for (size_t k = 1; k < runs; k++) {
        if (started[k])
            pthread_join(thread[k], NULL);
        else
            test_cells(&run[k]);
    }
}

static int same_seg(const segnode_seg *a, const segnode_seg *b)
{
    return a->ax == b->ax && a->ay == b->ay && a->bx == b->bx && a->by == b->by;
}

/* The cells of the grid that segment s's box covers, clipped to the grid:
 * 0 when it lies outside it. */
static int clipped_range(const grid *g, const segnode_seg *s, size_t *i0, size_t *i1,
                         size_t *j0, size_t *j1)
{
    int64_t x1 = g->x0 + (int64_t)g->cols * g->size - 1, y1 = g->y0 + (int64_t)g->rows * g->size - 1;
    int64_t sy0 = min64(s->ay, s->by), sy1 = max64(s->ay, s->by);
    if (s->bx < g->x0 || s->ax > x1 || sy1 < g->y0 || sy0 > y1)
        return 0;
    segnode_seg c = {max64(s->ax, g->x0), max64(sy0, g->y0), min64(s->bx, x1), min64(sy1, y1)};
    cell_range(g, &c, i0, i1, j0, j1);
    return 1;
}

int segnode_any_near(const segnode_seg *fresh, size_t m, const segnode_seg *all, size_t n)
{
    if (m == 0)
        return 0;
    if (m >= UINT32_MAX)
        return 1;
    grid g = make_grid(fresh, m);
    size_t cells = g.cols * g.rows, entries = 0, i0, i1, j0, j1;
    size_t *start = calloc(cells + 1, sizeof *start);
    if (!start)
        return -1;
    int found = 0;
    for (size_t f = 0; f < m && !found; f++) {
        cell_range(&g, &fresh[f], &i0, &i1, &j0, &j1);
        found = (i1 - i0 + 1) * (j1 - j0 + 1) > MAX_CELLS_PER_SEGMENT;
        for (size_t j = j0; j <= j1 && !found; j++)
            for (size_t c = i0; c <= i1; c++)
                start[j * g.cols + c + 1]++, entries++;
    }
    for (size_t c = 0; c < cells; c++)
        start[c + 1] += start[c];
    uint32_t *ids = found ? NULL : malloc((entries ? entries : 1) * sizeof *ids);
    size_t *fill = found ? NULL : malloc((cells + 1) * sizeof *fill);
    if (!found && (!ids || !fill))
        found = -1;
    for (size_t c = 0; c <= cells && !found; c++)
        fill[c] = start[c];
    for (size_t f = 0; f < m && !found; f++) {
        cell_range(&g, &fresh[f], &i0, &i1, &j0, &j1);
        for (size_t j = j0; j <= j1; j++)
            for (size_t c = i0; c <= i1; c++)
                ids[fill[j * g.cols + c]++] = (uint32_t)f;
    }
    /* every segment against the fresh ones of the cells its box covers */
    for (size_t i = 0; i < n && !found; i++) {
        if (!clipped_range(&g, &all[i], &i0, &i1, &j0, &j1))
            continue;
        if ((i1 - i0 + 1) * (j1 - j0 + 1) > MAX_CELLS_PER_SEGMENT) {
            found = 1;
            break;
        }
        for (size_t j = j0; j <= j1 && !found; j++)
            for (size_t c = i0; c <= i1 && !found; c++)
                for (size_t k = start[j * g.cols + c]; k < start[j * g.cols + c + 1]; k++) {
                    const segnode_seg *f = &fresh[ids[k]];
                    if (!same_seg(f, &all[i]) && segnode_interact(f, &all[i])) {
                        found = 1;
                        break;
                    }
                }
    }
    free(ids);
    free(fill);
    free(start);
    return found;
}

long long segnode_find_dirty(const segnode_seg *s, size_t n, unsigned char *dirty,
                             unsigned threads)
{
    long long marked = 0;
    if (n >= UINT32_MAX) /* beyond 32-bit ids: let GEOS node them all */
        for (size_t i = 0; i < n; i++)
            dirty[i] = 1;
    if (n >= 2 && n < UINT32_MAX) {
        grid g = make_grid(s, n);
        size_t cells = g.cols * g.rows, entries = 0;
        size_t *start = calloc(cells + 1, sizeof *start);
        if (!start)
            return -1;
        /* count, then place: a counting sort of (cell, segment) */
        for (size_t i = 0; i < n; i++) {
            size_t i0, i1, j0, j1;
            cell_range(&g, &s[i], &i0, &i1, &j0, &j1);
            if ((i1 - i0 + 1) * (j1 - j0 + 1) > MAX_CELLS_PER_SEGMENT) {
                dirty[i] = 1;
                continue;
            }
            for (size_t j = j0; j <= j1; j++)
                for (size_t c = i0; c <= i1; c++)
                    start[j * g.cols + c + 1]++, entries++;
        }
        for (size_t c = 0; c < cells; c++)
            start[c + 1] += start[c];
        uint32_t *ids = malloc((entries ? entries : 1) * sizeof *ids);
        size_t *fill = malloc((cells + 1) * sizeof *fill);
        if (!ids || !fill) {
            free(start);
            free(ids);
            free(fill);
            return -1;
        }
        for (size_t c = 0; c <= cells; c++)
            fill[c] = start[c];
        for (size_t i = 0; i < n; i++) {
            size_t i0, i1, j0, j1;
            cell_range(&g, &s[i], &i0, &i1, &j0, &j1);
            if ((i1 - i0 + 1) * (j1 - j0 + 1) > MAX_CELLS_PER_SEGMENT)
                continue;
            for (size_t j = j0; j <= j1; j++)
                for (size_t c = i0; c <= i1; c++)
                    ids[fill[j * g.cols + c]++] = (uint32_t)i;
        }
        free(fill);
        test_all_cells(s, ids, start, cells, dirty, threads);
        free(ids);
        free(start);
    }
    for (size_t i = 0; i < n; i++)
        marked += dirty[i] != 0;
    return marked;
}
