/*
 * ring_index.c: see ring_index.h.
 */
#include "ring_index.h"

#include <stdlib.h>
#include <string.h>

#include "arrays.h"
#include "hpfc.h"

__extension__ typedef __int128 s128;

enum { FANOUT = 8 };

/* ---- boxes -------------------------------------------------------------------------- */

typedef struct packing {
    int64_t cx, cy; /* the box's centre, doubled */
    uint32_t id;
} packing;

static int cmp_cx(const void *a, const void *b)
{
    const packing *p = a, *q = b;
    if (p->cx != q->cx)
        return p->cx < q->cx ? -1 : 1;
    return (p->id > q->id) - (p->id < q->id);
}

static int cmp_cy(const void *a, const void *b)
{
    const packing *p = a, *q = b;
    if (p->cy != q->cy)
        return p->cy < q->cy ? -1 : 1;
    return (p->id > q->id) - (p->id < q->id);
}

void box_tree_free(box_tree *t)
{
    for (int l = 0; l < t->levels; l++)
        free(t->level[l]);
    free(t->level);
    free(t->count);
    free(t->item);
    memset(t, 0, sizeof *t);
}

/* The number of levels a packed tree over n entries has. */
static int levels_for(size_t n)
{
    int levels = 1;
    for (size_t m = n; m > 1; m = (m + FANOUT - 1) / FANOUT)
        levels++;
    return levels;
}

int box_tree_build(box_tree *t, const int64_t (*b)[4], size_t n)
{
    memset(t, 0, sizeof *t);
    if (n == 0)
        return HPFC_OK;
    int max_levels = levels_for(n);
    packing *p = malloc(n * sizeof *p);
    t->level = calloc((size_t)max_levels, sizeof *t->level);
    t->count = calloc((size_t)max_levels, sizeof *t->count);
    t->item = malloc(n * sizeof *t->item);
    int64_t(*sorted)[4] = malloc(n * sizeof *sorted);
    if (!p || !t->level || !t->count || !t->item || !sorted || n > UINT32_MAX) {
        free(p), free(sorted);
        box_tree_free(t);
        return HPFC_E_NOMEM;
    }
    /* sort-tile-recursive: slabs by x, runs of FANOUT by y within a slab */
    for (size_t i = 0; i < n; i++)
        p[i] = (packing){b[i][0] + b[i][2], b[i][1] + b[i][3], (uint32_t)i};
    qsort(p, n, sizeof *p, cmp_cx);
    size_t nodes = (n + FANOUT - 1) / FANOUT, slabs = 1;
    while (slabs * slabs < nodes)
        slabs++;
    size_t per_slab = slabs * FANOUT;
    for (size_t s = 0; s < n; s += per_slab)
        qsort(p + s, n - s < per_slab ? n - s : per_slab, sizeof *p, cmp_cy);
    for (size_t i = 0; i < n; i++) {
        memcpy(sorted[i], b[p[i].id], sizeof sorted[i]);
        t->item[i] = p[i].id;
    }
    free(p);
    t->level[0] = sorted;
    t->count[0] = n;
    t->levels = 1;
    while (t->count[t->levels - 1] > 1) {
        size_t below = t->count[t->levels - 1], m = (below + FANOUT - 1) / FANOUT;
        int64_t(*up)[4] = malloc(m * sizeof *up);
        if (!up) {
            box_tree_free(t);
            return HPFC_E_NOMEM;
        }
        int64_t(*child)[4] = t->level[t->levels - 1];
        for (size_t k = 0; k < m; k++) {
            size_t first = k * FANOUT, end = first + FANOUT < below ? first + FANOUT : below;
            memcpy(up[k], child[first], sizeof up[k]);
            for (size_t i = first + 1; i < end; i++) {
                up[k][0] = child[i][0] < up[k][0] ? child[i][0] : up[k][0];
                up[k][1] = child[i][1] < up[k][1] ? child[i][1] : up[k][1];
                up[k][2] = child[i][2] > up[k][2] ? child[i][2] : up[k][2];
                up[k][3] = child[i][3] > up[k][3] ? child[i][3] : up[k][3];
            }
        }
        t->level[t->levels] = up;
        t->count[t->levels] = m;
        t->levels++;
    }
    return HPFC_OK;
}

static int box_contains(const int64_t b[4], const int64_t q[4])
{
    return b[0] <= q[0] && b[1] <= q[1] && b[2] >= q[2] && b[3] >= q[3];
}

static int collect(const box_tree *t, int l, size_t k, const int64_t q[4], uint32_t **out,
                   size_t *n, size_t *cap)
{
    /* a child's box lies in its parent's: a parent that misses q prunes */
    if (!box_contains(t->level[l][k], q))
        return HPFC_OK;
    if (l == 0) {
        if (array_grow((void **)out, cap, *n + 1, sizeof **out))
            return HPFC_E_NOMEM;
        (*out)[(*n)++] = t->item[k];
        return HPFC_OK;
    }
    size_t first = k * FANOUT, end = first + FANOUT;
    end = end < t->count[l - 1] ? end : t->count[l - 1];
    for (size_t i = first; i < end; i++) {
        int st = collect(t, l - 1, i, q, out, n, cap);
        if (st)
            return st;
    }
    return HPFC_OK;
}

int box_tree_containing(const box_tree *t, const int64_t q[4], uint32_t **out, size_t *n,
                        size_t *cap)
{
    return t->levels ? collect(t, t->levels - 1, 0, q, out, n, cap) : HPFC_OK;
}

/* ---- one ring --------------------------------------------------------------------------- */

/* How segment a -> b (lattice) meets the eastward ray from p (doubled):
 * 1 it crosses it (half-open in y), 0 not, -1 p lies on the segment. */
static int segment_ray(const int64_t *a, const int64_t *b, const int64_t p[2])
{
    int64_t ax = 2 * a[0], ay = 2 * a[1], bx = 2 * b[0], by = 2 * b[1];
    s128 c = (s128)(bx - ax) * (p[1] - ay) - (s128)(by - ay) * (p[0] - ax);
    if (c == 0 && p[0] >= (ax < bx ? ax : bx) && p[0] <= (ax < bx ? bx : ax) &&
        p[1] >= (ay < by ? ay : by) && p[1] <= (ay < by ? by : ay))
        return -1;
    return (ay > p[1]) != (by > p[1]) && (c > 0) == (by > ay);
}

int ring_locate(const int64_t *xy, size_t n, const int64_t p[2])
{
    int inside = 0;
    for (size_t k = 0; k + 1 < n; k++) {
        int c = segment_ray(xy + 2 * k, xy + 2 * k + 2, p);
        if (c < 0)
            return -1;
        inside ^= c;
    }
    return inside;
}

typedef struct span {
    int64_t mid2; /* y0 + y1 */
    uint32_t seg;
} span;

static int cmp_span(const void *a, const void *b)
{
    const span *p = a, *q = b;
    if (p->mid2 != q->mid2)
        return p->mid2 < q->mid2 ? -1 : 1;
    return (p->seg > q->seg) - (p->seg < q->seg);
}

void ring_index_free(ring_index *ri)
{
    for (int l = 0; l < ri->levels; l++) {
        free(ri->lo[l]);
        free(ri->hi[l]);
    }
    free(ri->lo);
    free(ri->hi);
    free(ri->count);
    free(ri->seg);
    memset(ri, 0, sizeof *ri);
}

int ring_index_build(ring_index *ri, const int64_t *xy, size_t n)
{
    memset(ri, 0, sizeof *ri);
    if (n < 2 || n - 1 > UINT32_MAX)
        return HPFC_E_NOMEM;
    size_t m = n - 1;
    int max_levels = levels_for(m);
    ri->xy = xy, ri->n = n;
    span *sp = malloc(m * sizeof *sp);
    ri->seg = malloc(m * sizeof *ri->seg);
    ri->lo = calloc((size_t)max_levels, sizeof *ri->lo);
    ri->hi = calloc((size_t)max_levels, sizeof *ri->hi);
    ri->count = calloc((size_t)max_levels, sizeof *ri->count);
    int64_t *lo = malloc(m * sizeof *lo), *hi = malloc(m * sizeof *hi);
    if (!sp || !ri->seg || !ri->lo || !ri->hi || !ri->count || !lo || !hi) {
        free(sp), free(lo), free(hi);
        ring_index_free(ri);
        return HPFC_E_NOMEM;
    }
    for (size_t k = 0; k < m; k++)
        sp[k] = (span){xy[2 * k + 1] + xy[2 * k + 3], (uint32_t)k};
    qsort(sp, m, sizeof *sp, cmp_span);
    for (size_t k = 0; k < m; k++) {
        int64_t y0 = xy[2 * sp[k].seg + 1], y1 = xy[2 * sp[k].seg + 3];
        ri->seg[k] = sp[k].seg;
        lo[k] = y0 < y1 ? y0 : y1;
        hi[k] = y0 < y1 ? y1 : y0;
    }
    free(sp);
    ri->lo[0] = lo, ri->hi[0] = hi, ri->count[0] = m, ri->levels = 1;
    while (ri->count[ri->levels - 1] > 1) {
        int l = ri->levels;
        size_t below = ri->count[l - 1], up = (below + FANOUT - 1) / FANOUT;
        ri->levels++; /* so that a failure below frees what this level got */
        if (!(ri->lo[l] = malloc(up * sizeof **ri->lo)) ||
            !(ri->hi[l] = malloc(up * sizeof **ri->hi))) {
            ring_index_free(ri);
            return HPFC_E_NOMEM;
        }
        for (size_t k = 0; k < up; k++) {
            size_t first = k * FANOUT, end = first + FANOUT < below ? first + FANOUT : below;
            int64_t a = ri->lo[l - 1][first], b = ri->hi[l - 1][first];
            for (size_t i = first + 1; i < end; i++) {
                a = ri->lo[l - 1][i] < a ? ri->lo[l - 1][i] : a;
                b = ri->hi[l - 1][i] > b ? ri->hi[l - 1][i] : b;
            }
            ri->lo[l][k] = a, ri->hi[l][k] = b;
        }
        ri->count[l] = up;
    }
    return HPFC_OK;
}

/* Parity of the crossings of the segments under entry k of level l whose
 * y extent holds p's; -1 when p lies on one of them. */
static int locate_under(const ring_index *ri, int l, size_t k, const int64_t p[2])
{
    if (!(2 * ri->lo[l][k] <= p[1] && p[1] <= 2 * ri->hi[l][k]))
        return 0;
    if (l == 0) {
        const int64_t *a = ri->xy + 2 * (size_t)ri->seg[k];
        return segment_ray(a, a + 2, p);
    }
    int odd = 0;
    size_t first = k * FANOUT, end = first + FANOUT;
    end = end < ri->count[l - 1] ? end : ri->count[l - 1];
    for (size_t i = first; i < end; i++) {
        int c = locate_under(ri, l - 1, i, p);
        if (c < 0)
            return -1;
        odd ^= c;
    }
    return odd;
}

int ring_index_locate(const ring_index *ri, const int64_t p[2])
{
    return ri->levels ? locate_under(ri, ri->levels - 1, 0, p) : 0;
}
