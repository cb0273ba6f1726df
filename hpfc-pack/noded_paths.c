/*
 * noded_paths.c: see noded_paths.h.
 */
#include "noded_paths.h"

#include <stdlib.h>

#include "grow.h"
#include "sort.h"

__extension__ typedef __int128 i128;

/* A walk that has not reached b after this many steps (forward or back)
 * gives up: a real path has a handful of points, and a dead end costs one
 * step back. */
enum { MAX_STEPS = 1 << 16 };

/* A segment's second end, for finding the segments that end at a point. */
typedef struct second_end {
    int64_t x, y;
    uint32_t seg;
} second_end;

struct noded_index {
    const segnode_seg *s;
    size_t n;
    second_end *by_b; /* sorted by point */
};

int point_list_push(point_list *l, int64_t x, int64_t y)
{
    if (!array_grow((void **)&l->xy, &l->cap, 2 * l->n + 2, sizeof *l->xy))
        return -1;
    l->xy[2 * l->n] = x;
    l->xy[2 * l->n + 1] = y;
    l->n++;
    return 0;
}

static int cmp_point(int64_t ax, int64_t ay, int64_t bx, int64_t by)
{
    if (ax != bx)
        return ax < bx ? -1 : 1;
    return (ay > by) - (ay < by);
}

static int cmp_second_end(const void *a, const void *b)
{
    const second_end *p = a, *q = b;
    return cmp_point(p->x, p->y, q->x, q->y);
}

int noded_index_create(const segnode_seg *segs, size_t n, noded_index **out)
{
    *out = NULL;
    noded_index *ix = malloc(sizeof *ix);
    if (!ix || n > UINT32_MAX || !(ix->by_b = malloc((n ? n : 1) * sizeof *ix->by_b))) {
        free(ix);
        return -1;
    }
    ix->s = segs;
    ix->n = n;
    for (size_t i = 0; i < n; i++)
        ix->by_b[i] = (second_end){segs[i].bx, segs[i].by, (uint32_t)i};
    sort_in_place(ix->by_b, n, sizeof *ix->by_b, cmp_second_end);
    *out = ix;
    return 0;
}

void noded_index_free(noded_index *ix)
{
    if (ix) {
        free(ix->by_b);
        free(ix);
    }
}

/* First segment whose first end is >= (x, y). */
static size_t lower_first(const noded_index *ix, int64_t x, int64_t y)
{
    size_t lo = 0, hi = ix->n;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (cmp_point(ix->s[mid].ax, ix->s[mid].ay, x, y) < 0)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

/* First position in by_b at or after (x, y): lower_first's search over the
 * other array, whose records hold the point itself. */
static size_t lower_second(const noded_index *ix, int64_t x, int64_t y)
{
    size_t lo = 0, hi = ix->n;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (cmp_point(ix->by_b[mid].x, ix->by_b[mid].y, x, y) < 0)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

int noded_index_has(const noded_index *ix, int64_t ax, int64_t ay, int64_t bx, int64_t by)
{
    if (cmp_point(ax, ay, bx, by) > 0) {
        int64_t tx = ax, ty = ay;
        ax = bx, ay = by, bx = tx, by = ty;
    }
    for (size_t k = lower_first(ix, ax, ay);
         k < ix->n && ix->s[k].ax == ax && ix->s[k].ay == ay; k++)
        if (ix->s[k].bx == bx && ix->s[k].by == by)
            return 1;
    return 0;
}

/* Sign of the turn a -> b -> c, all doubled coordinates. */
static int orient2(i128 ax, i128 ay, i128 bx, i128 by, i128 cx, i128 cy)
{
    i128 d = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
    return (d > 0) - (d < 0);
}

int noded_square_meets(int64_t qx, int64_t qy, int64_t ax, int64_t ay, int64_t bx, int64_t by)
{
    /* doubled, so that the square's corners are integers; separating axes:
     * x, y and the segment's normal */
    i128 x0 = 2 * (i128)qx - 1, x1 = 2 * (i128)qx + 1, y0 = 2 * (i128)qy - 1,
         y1 = 2 * (i128)qy + 1;
    i128 sax = 2 * (i128)ax, say = 2 * (i128)ay, sbx = 2 * (i128)bx, sby = 2 * (i128)by;
    if ((sax < x0 && sbx < x0) || (sax > x1 && sbx > x1) || (say < y0 && sby < y0) ||
        (say > y1 && sby > y1))
        return 0;
    int o1 = orient2(sax, say, sbx, sby, x0, y0), o2 = orient2(sax, say, sbx, sby, x1, y0);
    int o3 = orient2(sax, say, sbx, sby, x1, y1), o4 = orient2(sax, say, sbx, sby, x0, y1);
    return !((o1 > 0 && o2 > 0 && o3 > 0 && o4 > 0) || (o1 < 0 && o2 < 0 && o3 < 0 && o4 < 0));
}

/* GEOS's order of nodes along a segment (SegmentPointComparator): by the
 * octant of its direction, the major coordinate first. */
static int octant(int64_t dx, int64_t dy)
{
    int64_t adx = dx < 0 ? -dx : dx, ady = dy < 0 ? -dy : dy;
    if (dx >= 0)
        return dy >= 0 ? (adx >= ady ? 0 : 1) : (adx >= ady ? 7 : 6);
    return dy >= 0 ? (adx >= ady ? 3 : 2) : (adx >= ady ? 4 : 5);
}

static int first_nonzero(int a, int b)
{
    return a ? a : b;
}

/* < 0 when p comes before q along a segment of octant oct. */
static int along_cmp(int oct, int64_t px, int64_t py, int64_t qx, int64_t qy)
{
    int xs = (px > qx) - (px < qx), ys = (py > qy) - (py < qy);
    switch (oct) {
    case 0: return first_nonzero(xs, ys);
    case 1: return first_nonzero(ys, xs);
    case 2: return first_nonzero(ys, -xs);
    case 3: return first_nonzero(-xs, ys);
    case 4: return first_nonzero(-xs, -ys);
    case 5: return first_nonzero(-ys, -xs);
    case 6: return first_nonzero(-ys, xs);
    default: return first_nonzero(xs, -ys);
    }
}

/* One point of the walk: where it is, and its next steps
 * cand[first .. end) (points), tried in order from `next`. */
typedef struct frame {
    int64_t x, y;
    size_t first, end, next;
} frame;

typedef struct walk {
    const noded_index *ix;
    int64_t ax, ay, bx, by;
    int oct;
    frame *stack;
    size_t depth, cap_stack;
    int64_t *cand; /* x, y pairs */
    size_t n_cand, cap_cand;
} walk;

static int walk_offer(walk *w, int64_t cx, int64_t cy, int64_t qx, int64_t qy)
{
    if (along_cmp(w->oct, cx, cy, qx, qy) >= 0 || along_cmp(w->oct, qx, qy, w->bx, w->by) > 0 ||
        !noded_square_meets(qx, qy, w->ax, w->ay, w->bx, w->by))
        return 0;
    if (!array_grow((void **)&w->cand, &w->cap_cand, 2 * w->n_cand + 2, sizeof *w->cand))
        return -1;
    size_t k = w->n_cand;
    w->cand[2 * k] = qx;
    w->cand[2 * k + 1] = qy;
    w->n_cand++;
    return 0;
}

/* Sorts cand[first ..] in order along the segment, by insertion: a point
 * has a few neighbours. */
static void sort_tail(walk *w, size_t first)
{
    for (size_t i = first + 1; i < w->n_cand; i++) {
        int64_t x = w->cand[2 * i], y = w->cand[2 * i + 1];
        size_t j = i;
        while (j > first && along_cmp(w->oct, x, y, w->cand[2 * j - 2], w->cand[2 * j - 1]) < 0) {
            w->cand[2 * j] = w->cand[2 * j - 2];
            w->cand[2 * j + 1] = w->cand[2 * j - 1];
            j--;
        }
        w->cand[2 * j] = x;
        w->cand[2 * j + 1] = y;
    }
}

/* Pushes point (x, y) with its next steps. */
static int walk_push(walk *w, int64_t x, int64_t y)
{
    if (!array_grow((void **)&w->stack, &w->cap_stack, w->depth + 1, sizeof *w->stack))
        return -1;
    size_t first = w->n_cand;
    const noded_index *ix = w->ix;
    for (size_t k = lower_first(ix, x, y); k < ix->n && ix->s[k].ax == x && ix->s[k].ay == y; k++)
        if (walk_offer(w, x, y, ix->s[k].bx, ix->s[k].by))
            return -1;
    for (size_t k = lower_second(ix, x, y);
         k < ix->n && ix->by_b[k].x == x && ix->by_b[k].y == y; k++)
        if (walk_offer(w, x, y, ix->s[ix->by_b[k].seg].ax, ix->s[ix->by_b[k].seg].ay))
            return -1;
    sort_tail(w, first);
    w->stack[w->depth++] = (frame){x, y, first, w->n_cand, first};
    return 0;
}

int noded_path(const noded_index *ix, int64_t ax, int64_t ay, int64_t bx, int64_t by,
               point_list *out)
{
    walk w = {ix, ax, ay, bx, by, octant(bx - ax, by - ay), NULL, 0, 0, NULL, 0, 0};
    int st = walk_push(&w, ax, ay) ? -1 : 1;
    for (long steps = 0; st == 1 && w.depth && steps < MAX_STEPS; steps++) {
        frame *f = &w.stack[w.depth - 1];
        if (f->x == bx && f->y == by) {
            st = 0;
            break;
        }
        if (f->next == f->end) { /* a dead end: back one point */
            w.n_cand = f->first;
            w.depth--;
            continue;
        }
        size_t k = f->next++;
        if (walk_push(&w, w.cand[2 * k], w.cand[2 * k + 1]))
            st = -1;
    }
    size_t had = out->n;
    for (size_t d = 1; st == 0 && d < w.depth; d++)
        if (point_list_push(out, w.stack[d].x, w.stack[d].y)) {
            out->n = had;
            st = -1;
        }
    free(w.stack);
    free(w.cand);
    return st;
}

