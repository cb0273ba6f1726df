/*
 * face_check.c: see face_check.h.
 */
#include "face_check.h"

#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "grow.h"
#include "sort.h"

/* Entries a node of either packed tree holds. */
enum { FANOUT = 8 };

/* A ring with fewer segments than this is read from its code every time;
 * one with more gets its interval tree when asked about a second time. */
enum { INDEX_MIN_SEGMENTS = 48 };

/* ---- a packed R-tree over the rings' boxes ---------------------------------------- */

typedef struct box {
    int64_t x0, y0, x1, y1;
} box;

/* An entry being packed: its box's doubled centre and what it stands for. */
typedef struct packing {
    int64_t cx, cy;
    uint32_t id;
} packing;

static int cmp_cx(const void *a, const void *b)
{
    const packing *p = a, *q = b;
    return (p->cx > q->cx) - (p->cx < q->cx);
}

static int cmp_cy(const void *a, const void *b)
{
    const packing *p = a, *q = b;
    return (p->cy > q->cy) - (p->cy < q->cy);
}

/* Levels of boxes: level 0 the rings' boxes in packed order (item[k] the
 * ring of entry k), each entry k of level l + 1 the box of entries
 * [FANOUT k, FANOUT k + FANOUT) of level l. */
typedef struct box_tree {
    box **level;
    size_t *count;
    int levels;
    uint32_t *item;
} box_tree;

static box merge_boxes(const box *b, size_t n)
{
    box m = b[0];
    for (size_t i = 1; i < n; i++) {
        m.x0 = b[i].x0 < m.x0 ? b[i].x0 : m.x0, m.y0 = b[i].y0 < m.y0 ? b[i].y0 : m.y0;
        m.x1 = b[i].x1 > m.x1 ? b[i].x1 : m.x1, m.y1 = b[i].y1 > m.y1 ? b[i].y1 : m.y1;
    }
    return m;
}

/* Sort-tile-recursive order of boxes b[0 .. n): slabs by x, runs by y. */
static void str_order(const box *b, size_t n, packing *p)
{
    for (size_t i = 0; i < n; i++)
        p[i] = (packing){b[i].x0 + b[i].x1, b[i].y0 + b[i].y1, (uint32_t)i};
    sort_in_place(p, n, sizeof *p, cmp_cx);
    size_t nodes = (n + FANOUT - 1) / FANOUT, slabs = 1;
    while (slabs * slabs < nodes)
        slabs++;
    size_t per_slab = slabs * FANOUT;
    for (size_t s = 0; s < n; s += per_slab)
        sort_in_place(p + s, n - s < per_slab ? n - s : per_slab, sizeof *p, cmp_cy);
}

static void box_tree_free(box_tree *t)
{
    for (int l = 0; l < t->levels; l++)
        free(t->level[l]);
    free(t->level);
    free(t->count);
    free(t->item);
    memset(t, 0, sizeof *t);
}

/* Packs boxes b[0 .. n) (taken over: it becomes level 0, reordered); no
 * levels when there is no box (a layer of lines). */
static int box_tree_build(box_tree *t, box *b, size_t n)
{
    memset(t, 0, sizeof *t);
    if (n == 0) {
        free(b);
        return HPFC_OK;
    }
    int max_levels = 2;
    for (size_t m = n; m > 1; m = (m + FANOUT - 1) / FANOUT)
        max_levels++;
    packing *p = malloc((n ? n : 1) * sizeof *p);
    t->level = calloc((size_t)max_levels, sizeof *t->level);
    t->count = calloc((size_t)max_levels, sizeof *t->count);
    t->item = malloc((n ? n : 1) * sizeof *t->item);
    box *sorted = malloc((n ? n : 1) * sizeof *sorted);
    if (!p || !t->level || !t->count || !t->item || !sorted) {
        free(p), free(sorted), free(b);
        box_tree_free(t);
        return HPFC_E_NOMEM;
    }
    str_order(b, n, p);
    for (size_t i = 0; i < n; i++) {
        sorted[i] = b[p[i].id];
        t->item[i] = p[i].id;
    }
    free(b);
    free(p);
    t->level[0] = sorted;
    t->count[0] = n;
    t->levels = 1;
    while (t->count[t->levels - 1] > 1) {
        size_t below = t->count[t->levels - 1], m = (below + FANOUT - 1) / FANOUT;
        box *up = malloc(m * sizeof *up);
        if (!up) {
            box_tree_free(t);
            return HPFC_E_NOMEM;
        }
        for (size_t k = 0; k < m; k++) {
            size_t first = k * FANOUT, end = first + FANOUT < below ? first + FANOUT : below;
            up[k] = merge_boxes(t->level[t->levels - 1] + first, end - first);
        }
        t->level[t->levels] = up;
        t->count[t->levels] = m;
        t->levels++;
    }
    return HPFC_OK;
}

/* Does box b, doubled, hold the doubled point (x2, y2)? */
static int box_holds(const box *b, int64_t x2, int64_t y2)
{
    return 2 * b->x0 <= x2 && x2 <= 2 * b->x1 && 2 * b->y0 <= y2 && y2 <= 2 * b->y1;
}

/* ---- a packed interval tree over one ring's segments ---------------------------------- */

/* Ring r's points p[0 .. n) (closed: p[n - 1] == p[0] unless it had no
 * closing point, then the closing segment is added), its segments
 * seg[k] = p[seg[k]] -> p[seg[k] + 1] in the order of their y midpoints, and
 * levels of y intervals as the box tree's. */
typedef struct ring_index {
    int64_t *p;
    size_t n;
    uint32_t *seg;
    int64_t **lo, **hi; /* per level */
    size_t *count;
    int levels;
} ring_index;

typedef struct span {
    int64_t mid2; /* y0 + y1 */
    uint32_t seg;
} span;

static int cmp_span(const void *a, const void *b)
{
    const span *p = a, *q = b;
    return (p->mid2 > q->mid2) - (p->mid2 < q->mid2);
}

static void ring_index_free(ring_index *ri)
{
    if (!ri)
        return;
    for (int l = 0; l < ri->levels; l++) {
        free(ri->lo[l]);
        free(ri->hi[l]);
    }
    free(ri->lo);
    free(ri->hi);
    free(ri->count);
    free(ri->seg);
    free(ri->p);
    free(ri);
}

/* Decodes part r's points, closed, into *p (2 per point); their count. */
static size_t ring_points(const gis_features *fs, size_t r, int64_t **p, size_t *cap)
{
    uint32_t feature;
    int ring;
    gis_part_cursor c = gis_features_part_open(fs, r, &feature, &ring);
    size_t n = 0;
    if (!array_grow((void **)p, cap, 2 * (c.left + 1), sizeof **p))
        return SIZE_MAX;
    while (c.left) {
        gis_part_next(&c, &(*p)[2 * n], &(*p)[2 * n + 1]);
        n++;
    }
    if (n && ((*p)[0] != (*p)[2 * n - 2] || (*p)[1] != (*p)[2 * n - 1])) {
        (*p)[2 * n] = (*p)[0];
        (*p)[2 * n + 1] = (*p)[1];
        n++;
    }
    return n;
}

static ring_index *ring_index_build(const gis_features *fs, size_t r)
{
    ring_index *ri = calloc(1, sizeof *ri);
    size_t cap = 0;
    if (!ri || (ri->n = ring_points(fs, r, &ri->p, &cap)) == SIZE_MAX || ri->n < 2) {
        ring_index_free(ri);
        return NULL;
    }
    size_t m = ri->n - 1;
    int max_levels = 2;
    for (size_t k = m; k > 1; k = (k + FANOUT - 1) / FANOUT)
        max_levels++;
    span *sp = malloc(m * sizeof *sp);
    ri->seg = malloc(m * sizeof *ri->seg);
    ri->lo = calloc((size_t)max_levels, sizeof *ri->lo);
    ri->hi = calloc((size_t)max_levels, sizeof *ri->hi);
    ri->count = calloc((size_t)max_levels, sizeof *ri->count);
    if (!sp || !ri->seg || !ri->lo || !ri->hi || !ri->count) {
        free(sp);
        ring_index_free(ri);
        return NULL;
    }
    for (size_t k = 0; k < m; k++)
        sp[k] = (span){ri->p[2 * k + 1] + ri->p[2 * k + 3], (uint32_t)k};
    sort_in_place(sp, m, sizeof *sp, cmp_span);
    int64_t *lo = malloc(m * sizeof *lo), *hi = malloc(m * sizeof *hi);
    if (!lo || !hi) {
        free(lo), free(hi), free(sp);
        ring_index_free(ri);
        return NULL;
    }
    for (size_t k = 0; k < m; k++) {
        int64_t y0 = ri->p[2 * sp[k].seg + 1], y1 = ri->p[2 * sp[k].seg + 3];
        ri->seg[k] = sp[k].seg;
        lo[k] = y0 < y1 ? y0 : y1;
        hi[k] = y0 < y1 ? y1 : y0;
    }
    free(sp);
    ri->lo[0] = lo, ri->hi[0] = hi, ri->count[0] = m, ri->levels = 1;
    while (ri->count[ri->levels - 1] > 1) {
        int l = ri->levels;
        size_t below = ri->count[l - 1], up = (below + FANOUT - 1) / FANOUT;
        if (!(ri->lo[l] = malloc(up * sizeof **ri->lo)) ||
            !(ri->hi[l] = malloc(up * sizeof **ri->hi))) {
            ri->levels++;
            ring_index_free(ri);
            return NULL;
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
        ri->levels++;
    }
    return ri;
}

/* Parity of the ray's crossings with the segments of entry k of level l
 * whose y extent holds the witness's; -1 when the witness lies on one. */
static int ring_index_parity(const ring_index *ri, int l, size_t k, const face_witness *w)
{
    if (!(2 * ri->lo[l][k] <= w->y2 && w->y2 <= 2 * ri->hi[l][k]))
        return 0;
    if (l == 0) {
        const int64_t *a = ri->p + 2 * ri->seg[k];
        return face_witness_ray_crosses(w, a[0], a[1], a[2], a[3]);
    }
    int odd = 0;
    size_t first = k * FANOUT, end = first + FANOUT;
    end = end < ri->count[l - 1] ? end : ri->count[l - 1];
    for (size_t i = first; i < end; i++) {
        int c = ring_index_parity(ri, l - 1, i, w);
        if (c < 0)
            return -1;
        odd ^= c;
    }
    return odd;
}

/* ---- the check ------------------------------------------------------------------- */

/* Shared by the threads that ask (each with its own face_check_scratch):
 * the tree is read only; asked and index change by atomic operations. */
struct face_check {
    const gis_features *fs;
    size_t rings;       /* parts */
    box_tree tree;      /* over the closed parts */
    uint32_t *asked;    /* per part: how often its parity was asked for */
    ring_index **index; /* per part, once built (published by compare-and-swap) */
};

void face_check_scratch_free(face_check_scratch *s)
{
    free(s->pts);
    free(s->hits);
    memset(s, 0, sizeof *s);
}

void face_check_free(face_check *fc)
{
    if (!fc)
        return;
    for (size_t r = 0; fc->index && r < fc->rings; r++)
        ring_index_free(fc->index[r]);
    free(fc->index);
    free(fc->asked);
    box_tree_free(&fc->tree);
    free(fc);
}

int face_check_create(const gis_features *fs, face_check **out)
{
    *out = NULL;
    face_check *fc = calloc(1, sizeof *fc);
    if (!fc)
        return HPFC_E_NOMEM;
    fc->fs = fs;
    fc->rings = gis_features_part_count(fs);
    size_t n = 0;
    box *b = malloc((fc->rings ? fc->rings : 1) * sizeof *b);
    uint32_t *id = malloc((fc->rings ? fc->rings : 1) * sizeof *id);
    fc->asked = calloc(fc->rings ? fc->rings : 1, sizeof *fc->asked);
    fc->index = calloc(fc->rings ? fc->rings : 1, sizeof *fc->index);
    if (!b || !id || !fc->asked || !fc->index || fc->rings > UINT32_MAX) {
        free(b), free(id);
        face_check_free(fc);
        return HPFC_E_NOMEM;
    }
    for (size_t r = 0; r < fc->rings; r++) {
        uint32_t feature;
        int ring;
        gis_part_cursor c = gis_features_part_open(fs, r, &feature, &ring);
        if (!ring || !c.left)
            continue;
        int64_t x, y;
        gis_part_next(&c, &x, &y);
        box bx = {x, y, x, y};
        while (c.left) {
            gis_part_next(&c, &x, &y);
            bx.x0 = x < bx.x0 ? x : bx.x0, bx.x1 = x > bx.x1 ? x : bx.x1;
            bx.y0 = y < bx.y0 ? y : bx.y0, bx.y1 = y > bx.y1 ? y : bx.y1;
        }
        b[n] = bx;
        id[n++] = (uint32_t)r;
    }
    int st = box_tree_build(&fc->tree, b, n);
    if (!st) /* the tree's items are positions in b: make them parts */
        for (size_t k = 0; k < n; k++)
            fc->tree.item[k] = id[fc->tree.item[k]];
    free(id);
    if (st) {
        face_check_free(fc);
        return st;
    }
    *out = fc;
    return HPFC_OK;
}

static int collect_hits(const face_check *fc, face_check_scratch *s, int l, size_t k,
                        const face_witness *w)
{
    const box_tree *t = &fc->tree;
    if (!box_holds(&t->level[l][k], w->x2, w->y2))
        return HPFC_OK;
    if (l == 0) {
        if (!array_grow((void **)&s->hits, &s->cap_hits, s->n_hits + 1, sizeof *s->hits))
            return HPFC_E_NOMEM;
        s->hits[s->n_hits++] = t->item[k];
        return HPFC_OK;
    }
    size_t first = k * FANOUT, end = first + FANOUT;
    end = end < t->count[l - 1] ? end : t->count[l - 1];
    for (size_t i = first; i < end; i++) {
        int st = collect_hits(fc, s, l - 1, i, w);
        if (st)
            return st;
    }
    return HPFC_OK;
}

/* Ring r's index, built at its second question when it is long enough
 * (NULL otherwise; *failed when there was no memory for it). Two threads
 * may build it at once: the first to publish it wins, the other frees
 * its copy. Either way the parity is exact, so when a ring gets its index
 * changes only the time. */
static const ring_index *ring_index_get(face_check *fc, size_t r, bool *failed)
{
    ring_index *ri = __atomic_load_n(&fc->index[r], __ATOMIC_ACQUIRE);
    if (ri || __atomic_add_fetch(&fc->asked[r], 1, __ATOMIC_RELAXED) < 2 ||
        gis_features_part_points(fc->fs, r) < INDEX_MIN_SEGMENTS)
        return ri;
    if (!(ri = ring_index_build(fc->fs, r))) {
        *failed = true;
        return NULL;
    }
    ring_index *none = NULL;
    if (!__atomic_compare_exchange_n(&fc->index[r], &none, ri, false, __ATOMIC_ACQ_REL, __ATOMIC_ACQUIRE)) {
        ring_index_free(ri);
        ri = none;
    }
    return ri;
}

/* Parity of ring r at w: 1, 0, -1 (w on the ring) or -2 (no memory). */
static int ring_parity(face_check *fc, face_check_scratch *s, size_t r, const face_witness *w)
{
    bool failed = false;
    const ring_index *ri = ring_index_get(fc, r, &failed);
    if (failed)
        return -2;
    if (ri)
        return ring_index_parity(ri, ri->levels - 1, 0, w);
    size_t n = ring_points(fc->fs, r, &s->pts, &s->cap_pts);
    if (n == SIZE_MAX)
        return -2;
    int odd = 0;
    for (size_t k = 0; k + 1 < n; k++) {
        int c = face_witness_ray_crosses(w, s->pts[2 * k], s->pts[2 * k + 1],
                                         s->pts[2 * k + 2], s->pts[2 * k + 3]);
        if (c < 0)
            return -1;
        odd ^= c;
    }
    return odd;
}

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

int face_check_features(face_check *fc, face_check_scratch *s, const face_witness *w,
                        feature_list *out)
{
    out->n = 0;
    s->n_hits = 0;
    int st = fc->tree.levels ? collect_hits(fc, s, fc->tree.levels - 1, 0, w) : HPFC_OK;
    if (st)
        return st;
    /* parts in order, so a feature's rings come together */
    sort_in_place(s->hits, s->n_hits, sizeof *s->hits, cmp_u32);
    if (!array_grow((void **)&out->v, &out->cap, s->n_hits + 1, sizeof *out->v))
        return HPFC_E_NOMEM;
    for (size_t i = 0; i < s->n_hits;) {
        uint32_t feature = gis_features_part_feature(fc->fs, s->hits[i]);
        int odd = 0;
        for (; i < s->n_hits && gis_features_part_feature(fc->fs, s->hits[i]) == feature; i++) {
            int p = ring_parity(fc, s, s->hits[i], w);
            if (p < 0)
                return p == -1 ? HPFC_E_CORRUPT : HPFC_E_NOMEM;
            odd ^= p;
        }
        if (odd)
            out->v[out->n++] = feature;
    }
    return HPFC_OK;
}
