/*
 * nearest.c: the edges near a lattice point (hpfc.h, "Topology questions"),
 * by a branch-and-bound descent of the tree.
 *
 * Pixels are visited nearest box first, and one farther than the best edge
 * so far is skipped with all below it; the root image is split in halves as
 * a virtual tree over its pixels, so a query reads O(log) root boxes, not
 * all of them. A leaf's crossings give its edges and the segment each
 * crossing is on; the segments met walking from there both ways, while
 * they meet the leaf's closed box, are the edge's pieces in the leaf (as
 * the window's cut leaves read them). The closest point of the map lies
 * in some leaf's closed box, on a segment met from that leaf, so the
 * descent finds it before its bound passes it.
 *
 * Distances are compared exactly: a squared distance is the rational
 * cross^2 / len2 (or an integer at a segment's end), its numerator below
 * 2^176 and denominator below 2^89 for coordinates within 2^42, and two
 * are compared by cross-multiplying in 64-bit limbs.
 */
#include <stdlib.h>
#include <string.h>

#include "arrays.h"
#include "shapes.h"

__extension__ typedef unsigned __int128 u128;

/* A squared distance n / d, n in three limbs (little-endian), d > 0. */
typedef struct qdist {
    uint64_t n[3];
    u128 d;
} qdist;

/* r = a * b, na + nb limbs. */
static void mp_mul(const uint64_t *a, int na, const uint64_t *b, int nb, uint64_t *r)
{
    memset(r, 0, (size_t)(na + nb) * sizeof *r);
    for (int i = 0; i < na; i++) {
        u128 carry = 0;
        for (int j = 0; j < nb; j++) {
            u128 t = (u128)a[i] * b[j] + r[i + j] + carry;
            r[i + j] = (uint64_t)t;
            carry = t >> 64;
        }
        r[i + nb] = (uint64_t)carry;
    }
}

static int mp_cmp(const uint64_t *a, const uint64_t *b, int n)
{
    for (int k = n - 1; k >= 0; k--)
        if (a[k] != b[k])
            return a[k] < b[k] ? -1 : 1;
    return 0;
}

static int qcmp(const qdist *a, const qdist *b)
{
    uint64_t ad[2] = {(uint64_t)a->d, (uint64_t)(a->d >> 64)};
    uint64_t bd[2] = {(uint64_t)b->d, (uint64_t)(b->d >> 64)};
    uint64_t l[5], r[5];
    mp_mul(a->n, 3, bd, 2, l);
    mp_mul(b->n, 3, ad, 2, r);
    return mp_cmp(l, r, 5);
}

/* To double without the compiler's 128-bit conversions, which libc lacks
 * (the reader links libc alone): two exact halves, one rounding each. */
static double u128_double(u128 v)
{
    return (double)(uint64_t)(v >> 64) * 18446744073709551616.0 + (double)(uint64_t)v;
}

static double s128_double(s128 v)
{
    return v < 0 ? -u128_double((u128)-v) : u128_double((u128)v);
}

static qdist q_int(u128 v)
{
    return (qdist){{(uint64_t)v, (uint64_t)(v >> 64), 0}, 1};
}

/* n / d to within a few units in the last place. */
static double q_square(const qdist *q)
{
    const double two64 = 18446744073709551616.0;
    double n = ((double)q->n[2] * two64 + (double)q->n[1]) * two64 + (double)q->n[0];
    return n / u128_double(q->d);
}

static double q_value(const qdist *q)
{
    return shapes_sqrt(q_square(q));
}

/* a <=> b, exactly: their doubles decide when they differ by more than
 * their rounding (a relative 1e-9 is thousands of times that), else the
 * rationals are cross-multiplied. */
static int qcmp_fast(const qdist *a, double a2, const qdist *b, double b2)
{
    if (a2 > b2 * (1 + 1e-9))
        return 1;
    if (a2 < b2 * (1 - 1e-9))
        return -1;
    return qcmp(a, b);
}

/* |v|, as u128 (v within 2^120). */
static u128 uabs(s128 v)
{
    return v < 0 ? (u128)-v : (u128)v;
}

/* Point p's squared distance to segment a-b, and the closest point. */
static qdist seg_dist(const int64_t p[2], const int64_t a[2], const int64_t b[2], double *cx,
                      double *cy)
{
    s128 dx = (s128)b[0] - a[0], dy = (s128)b[1] - a[1];
    s128 wx = (s128)p[0] - a[0], wy = (s128)p[1] - a[1];
    s128 dot = wx * dx + wy * dy, len2 = dx * dx + dy * dy;
    if (dot <= 0 || len2 == 0) {
        *cx = (double)a[0], *cy = (double)a[1];
        return q_int((u128)(wx * wx + wy * wy));
    }
    if (dot >= len2) {
        s128 ux = (s128)p[0] - b[0], uy = (s128)p[1] - b[1];
        *cx = (double)b[0], *cy = (double)b[1];
        return q_int((u128)(ux * ux + uy * uy));
    }
    double t = s128_double(dot) / s128_double(len2);
    *cx = (double)a[0] + t * s128_double(dx);
    *cy = (double)a[1] + t * s128_double(dy);
    u128 c = uabs(wx * dy - wy * dx);
    uint64_t cl[2] = {(uint64_t)c, (uint64_t)(c >> 64)}, sq[4];
    mp_mul(cl, 2, cl, 2, sq);
    return (qdist){{sq[0], sq[1], sq[2]}, (u128)len2};
}

/* The squared distance from p to the closed box b (x0, y0, x1, y1). */
static u128 box_dist(const int64_t p[2], const int64_t b[4])
{
    s128 dx = p[0] < b[0] ? (s128)b[0] - p[0] : p[0] > b[2] ? (s128)p[0] - b[2] : 0;
    s128 dy = p[1] < b[1] ? (s128)b[1] - p[1] : p[1] > b[3] ? (s128)p[1] - b[3] : 0;
    return (u128)(dx * dx + dy * dy);
}

/* Refinement images of at most this many pixels have their children
 * sorted nearest first (a list per level: 48 levels of 256 at most). */
enum { SORTED_CHILDREN = 256 };

/* One child of a refined pixel, or one half of a block of root pixels. */
typedef struct cand {
    u128 d;
    uint32_t i, j;
    uint32_t c0, c1, r0, r1; /* a block of root pixels */
} cand;

struct shapes_near {
    const int64_t *p;
    int within;             /* edges_within: every edge within bound */
    qdist bound;            /* the best so far (nearest), or d^2 */
    double bound2;          /* its value, rounded: a filter before qcmp */
    int found;
    hpfc_nearest best;
    qdist best_d;
    uint32_t cols, rows;
    int64_t root_x0, root_top, cell_w, cell_h, x_end, y_end;
    char *word;
    size_t cap_word;
    cand *stack;            /* per depth, cols * rows */
    size_t cap_stack;
    /* edges_within */
    uint32_t *mark, gen;
    qdist *edist;
    hpfc_id *edge;
    double *dist;
    size_t nedge, cap_edge, cap_dist;
    uint32_t *border;
    size_t nborder, cap_border;
};

void shapes_near_free(shapes_near *n)
{
    if (!n)
        return;
    free(n->word);
    free(n->stack);
    free(n->mark);
    free(n->edist);
    free(n->edge);
    free(n->dist);
    free(n->border);
    free(n);
}

/* Whether a box at squared distance d may hold an answer. */
static int worth(const shapes_near *n, u128 d)
{
    if (!n->within && !n->found)
        return 1;
    qdist q = q_int(d);
    return qcmp_fast(&q, u128_double(d), &n->bound, n->bound2) <= 0;
}

static int cmp_cand(const void *pa, const void *pb)
{
    const cand *a = pa, *b = pb;
    return (a->d > b->d) - (a->d < b->d);
}

/* A segment's distance, kept when it is the nearest (ties: lowest edge,
 * then segment) or, for edges_within, within the bound. */
static int consider(hpfc_shapes *s, uint64_t e, uint64_t k, const int64_t a[2],
                    const int64_t b[2])
{
    shapes_near *n = s->near;
    double cx, cy;
    qdist q = seg_dist(n->p, a, b, &cx, &cy);
    double q2 = q_square(&q);
    if (n->within) {
        if (qcmp_fast(&q, q2, &n->bound, n->bound2) > 0)
            return HPFC_OK;
        if (n->mark[e] != n->gen) {
            if (array_grow((void **)&n->edge, &n->cap_edge, n->nedge + 1, sizeof *n->edge))
                return HPFC_E_NOMEM;
            n->mark[e] = n->gen;
            n->edist[e] = q;
            n->edge[n->nedge++] = e;
        } else if (qcmp(&q, &n->edist[e]) < 0) {
            n->edist[e] = q;
        }
        return HPFC_OK;
    }
    int c = n->found ? qcmp_fast(&q, q2, &n->best_d, n->bound2) : -1;
    if (c < 0 || (c == 0 && (e < n->best.edge || (e == n->best.edge && k < n->best.segment)))) {
        n->found = 1;
        n->best_d = n->bound = q;
        n->bound2 = q2;
        n->best = (hpfc_nearest){.edge = e, .segment = k, .x = cx, .y = cy};
    }
    return HPFC_OK;
}

/* Point k of edge e, refused past twice the lattice's range (a damaged
 * file): that keeps every product above within its limbs. */
static int read_point(hpfc_shapes *s, uint64_t e, uint64_t k, int64_t p[2])
{
    int st = hpfc_geometry_edge_point(s->f, e, k, &p[0], &p[1]);
    if (!st && (p[0] < -2 * HPFC_LATTICE_MAX || p[0] > 2 * HPFC_LATTICE_MAX ||
                p[1] < -2 * HPFC_LATTICE_MAX || p[1] > 2 * HPFC_LATTICE_MAX))
        st = HPFC_E_CORRUPT;
    return st;
}

/* The segments of crossing k's edge inside the leaf's closed box, walked
 * both ways from the crossing's segment, each point read once. */
static int leaf_crossing(hpfc_shapes *s, const hpfc_pixel *leaf, uint32_t k, const int64_t box[4])
{
    uint64_t e, seg;
    int st = hpfc_label_crossing_edge(s->f, leaf, k, &e);
    if (!st)
        st = hpfc_geometry_crossing_segment(s->f, leaf, k, &seg);
    if (st)
        return st;
    if (e >= s->edges)
        return HPFC_E_CORRUPT;
    if ((st = shapes_need_edge(s, e)))
        return st;
    if (seg + 1 >= shapes_edge_points(s, e))
        return HPFC_E_CORRUPT;
    int64_t a[2], b[2], first[2];
    if ((st = read_point(s, e, seg, a)))
        return st;
    first[0] = a[0], first[1] = a[1];
    for (uint64_t j = seg; j + 1 < shapes_edge_points(s, e) && !st; j++) {
        if ((st = read_point(s, e, j + 1, b)))
            return st;
        /* the crossing's own segment too: in a damaged file it may lie
         * elsewhere, and what one leaf answers must lie in its box for the
         * bound to hold */
        if (!shapes_segment_meets(a, b, box))
            break;
        st = consider(s, e, j, a, b);
        a[0] = b[0], a[1] = b[1];
    }
    b[0] = first[0], b[1] = first[1];
    for (uint64_t j = seg; j-- > 0 && !st;) {
        if ((st = read_point(s, e, j, a)))
            return st;
        if (!shapes_segment_meets(a, b, box))
            break;
        st = consider(s, e, j, a, b);
        b[0] = a[0], b[1] = a[1];
    }
    return st;
}

static int visit_leaf(hpfc_shapes *s, const hpfc_pixel *leaf, const int64_t box[4])
{
    shapes_near *n = s->near;
    size_t len;
    if (!n->word && array_grow((void **)&n->word, &n->cap_word, 64, 1))
        return HPFC_E_NOMEM;
    /* one decode when the buffer holds the word (a short one: the usual) */
    int st = hpfc_pixel_word(s->f, leaf, n->word, n->cap_word, &len);
    if (st == HPFC_E_BUFFER_SMALL) {
        if (array_grow((void **)&n->word, &n->cap_word, len + 1, 1))
            return HPFC_E_NOMEM;
        st = hpfc_pixel_word(s->f, leaf, n->word, n->cap_word, &len);
    }
    uint32_t crossings = 0;
    for (size_t k = 0; k < len && !st; k++)
        crossings += n->word[k] != '+';
    for (uint32_t k = 0; k < crossings && !st; k++)
        st = leaf_crossing(s, leaf, k, box);
    return st;
}

static int pixel_box(hpfc_shapes *s, const hpfc_pixel *px, int64_t b[4])
{
    return hpfc_pixel_bounds(s->f, px, &b[0], &b[1], &b[2], &b[3]);
}

/* A pixel and all below it, children nearest first, pruned by the bound. */
static int descend(hpfc_shapes *s, const hpfc_pixel *px, const int64_t box[4])
{
    shapes_near *n = s->near;
    int type, st = hpfc_pixel_type(s->f, px, &type);
    if (st)
        return st;
    if (type == HPFC_PIXEL_WORD)
        return visit_leaf(s, px, box);
    if (px->depth + 1 >= HPFC_MAX_LEVELS)
        return HPFC_E_CORRUPT;
    size_t per = (size_t)n->cols * n->rows;
    /* the children's boxes from the parent's: the grid is uniform, so
     * only the children worth a visit are decoded */
    int64_t cw = (box[2] - box[0]) / n->cols, ch = (box[3] - box[1]) / n->rows;
    if (cw <= 0 || ch <= 0)
        return HPFC_E_CORRUPT;
    if (per > SORTED_CHILDREN) {
        /* images this large (the format allows 2^20 pixels) are visited in
         * place, unsorted: the bound still prunes, and no level keeps a
         * list of them */
        for (uint32_t j = 0; j < n->rows && !st; j++)
            for (uint32_t i = 0; i < n->cols && !st; i++) {
                int64_t b[4] = {box[0] + (int64_t)i * cw, box[3] - (int64_t)(j + 1) * ch,
                                box[0] + (int64_t)(i + 1) * cw, box[3] - (int64_t)j * ch};
                hpfc_pixel child;
                if (!worth(n, box_dist(n->p, b)))
                    continue;
                st = hpfc_pixel_child(s->f, px, i, j, &child);
                if (!st)
                    st = pixel_box(s, &child, b);
                if (!st)
                    st = descend(s, &child, b);
            }
        return st;
    }
    cand *c = n->stack + per * (px->depth + 1);
    size_t m = 0;
    for (uint32_t j = 0; j < n->rows; j++)
        for (uint32_t i = 0; i < n->cols; i++) {
            int64_t b[4] = {box[0] + (int64_t)i * cw, box[3] - (int64_t)(j + 1) * ch,
                            box[0] + (int64_t)(i + 1) * cw, box[3] - (int64_t)j * ch};
            c[m++] = (cand){.d = box_dist(n->p, b), .i = i, .j = j};
        }
    qsort(c, m, sizeof *c, cmp_cand);
    for (size_t k = 0; k < m && !st; k++) {
        if (!worth(n, c[k].d))
            break;
        hpfc_pixel child;
        int64_t b[4];
        st = hpfc_pixel_child(s->f, px, c[k].i, c[k].j, &child);
        if (!st)
            st = pixel_box(s, &child, b);
        if (!st)
            st = descend(s, &child, b);
    }
    return st;
}

/* The box of root columns [c0, c1) and rows [r0, r1) (row 0 north),
 * clamped to the domain: no smaller than the pixels it holds. */
static void block_box(const shapes_near *n, const cand *c, int64_t b[4])
{
    b[0] = n->root_x0 + (int64_t)c->c0 * n->cell_w;
    b[2] = n->root_x0 + (int64_t)c->c1 * n->cell_w;
    b[3] = n->root_top - (int64_t)c->r0 * n->cell_h;
    b[1] = n->root_top - (int64_t)c->r1 * n->cell_h;
    if (b[2] > n->x_end)
        b[2] = n->x_end;
    if (b[1] < n->y_end)
        b[1] = n->y_end;
}

/* A block of root pixels: one pixel is descended, a larger block split in
 * two across its longer side, the nearer half first. */
static int descend_block(hpfc_shapes *s, const cand *blk)
{
    shapes_near *n = s->near;
    if (blk->c1 - blk->c0 == 1 && blk->r1 - blk->r0 == 1) {
        hpfc_pixel root;
        int64_t b[4];
        int st = hpfc_pixel_root(s->f, blk->c0, blk->r0, &root);
        if (!st)
            st = pixel_box(s, &root, b);
        if (!st && worth(n, box_dist(n->p, b)))
            st = descend(s, &root, b);
        return st;
    }
    cand h[2] = {*blk, *blk};
    if (blk->c1 - blk->c0 >= blk->r1 - blk->r0)
        h[0].c1 = h[1].c0 = blk->c0 + (blk->c1 - blk->c0) / 2;
    else
        h[0].r1 = h[1].r0 = blk->r0 + (blk->r1 - blk->r0) / 2;
    for (int k = 0; k < 2; k++) {
        int64_t b[4];
        block_box(n, &h[k], b);
        h[k].d = box_dist(n->p, b);
    }
    int first = h[1].d < h[0].d;
    int st = HPFC_OK;
    for (int k = 0; k < 2 && !st; k++) {
        const cand *c = &h[k ? 1 - first : first];
        if (worth(n, c->d))
            st = descend_block(s, c);
    }
    return st;
}

static int near_begin(hpfc_shapes *s, const int64_t p[2])
{
    shapes_near *n = s->near;
    if (!n) {
        /* made whole or not at all: a search after a failed one finds
         * either none or both arrays */
        if (!(n = calloc(1, sizeof *n)))
            return HPFC_E_NOMEM;
        n->mark = calloc(s->edges + 1, sizeof *n->mark);
        n->edist = malloc((s->edges + 1) * sizeof *n->edist);
        if (!n->mark || !n->edist) {
            shapes_near_free(n);
            return HPFC_E_NOMEM;
        }
        s->near = n;
    }
    hpfc_file_info fi;
    hpfc_level_info lv;
    hpfc_file_get_info(s->f, &fi);
    int st = hpfc_file_get_level(s->f, 0, &lv);
    if (st)
        return st;
    if (lv.cell_w <= 0 || lv.cell_h <= 0)
        return HPFC_E_CORRUPT;
    n->p = p;
    n->found = 0;
    n->within = 0;
    n->nedge = 0;
    n->cols = fi.cols, n->rows = fi.rows;
    n->root_x0 = fi.x0, n->root_top = fi.y0 + fi.height;
    n->x_end = fi.x0 + fi.width, n->y_end = fi.y0;
    n->cell_w = lv.cell_w, n->cell_h = lv.cell_h;
    size_t per = (size_t)fi.cols * fi.rows;
    if (per <= SORTED_CHILDREN &&
        array_grow((void **)&n->stack, &n->cap_stack, per * HPFC_MAX_LEVELS, sizeof *n->stack))
        return HPFC_E_NOMEM;
    return HPFC_OK;
}

static int search(hpfc_shapes *s)
{
    hpfc_file_info fi;
    hpfc_file_get_info(s->f, &fi);
    cand all = {.c0 = 0, .c1 = fi.root_cols, .r0 = 0, .r1 = fi.root_rows};
    return descend_block(s, &all);
}

static int point_ok(int64_t x, int64_t y)
{
    return x >= -HPFC_LATTICE_MAX && x <= HPFC_LATTICE_MAX && y >= -HPFC_LATTICE_MAX &&
           y <= HPFC_LATTICE_MAX;
}

/* The nearest of a feature's border, segment by segment. */
static int feature_nearest(hpfc_shapes *s, hpfc_id feature)
{
    shapes_near *n = s->near;
    int st = shapes_feature_border(s, feature, &n->border, &n->nborder, &n->cap_border);
    int64_t a[2], b[2];
    for (size_t k = 0; k < n->nborder && !st; k++) {
        uint32_t e = n->border[k];
        st = read_point(s, e, 0, a);
        for (uint64_t j = 0; j + 1 < shapes_edge_points(s, e) && !st; j++) {
            if (!(st = read_point(s, e, j + 1, b)))
                st = consider(s, e, j, a, b);
            a[0] = b[0], a[1] = b[1];
        }
    }
    return st;
}

int hpfc_shapes_nearest_edge(hpfc_shapes *s, int64_t x, int64_t y, hpfc_id feature,
                             hpfc_nearest *out)
{
    if (!s || !out || !point_ok(x, y))
        return HPFC_E_ARG;
    if (feature != HPFC_ID_NONE) {
        if (!s->have_features && !s->have_edge_features)
            return HPFC_E_NO_SECTION;
        if (feature >= s->features)
            return HPFC_E_ARG;
    }
    int64_t p[2] = {x, y};
    int st = near_begin(s, p);
    if (!st)
        st = feature == HPFC_ID_NONE ? search(s) : feature_nearest(s, feature);
    shapes_near *n = s->near;
    if (!st && !n->found)
        st = feature == HPFC_ID_NONE ? HPFC_E_CORRUPT : HPFC_E_ARG; /* a map has edges */
    if (st)
        return st;
    *out = n->best;
    out->distance = q_value(&n->best_d);
    return HPFC_OK;
}

static int cmp_id(const void *a, const void *b)
{
    hpfc_id x = *(const hpfc_id *)a, y = *(const hpfc_id *)b;
    return (x > y) - (x < y);
}

int hpfc_shapes_edges_within(hpfc_shapes *s, int64_t x, int64_t y, int64_t d,
                             hpfc_edge_hits *out)
{
    if (!s || !out || !point_ok(x, y) || d < 0 || d > 2 * HPFC_LATTICE_MAX)
        return HPFC_E_ARG;
    int64_t p[2] = {x, y};
    int st = near_begin(s, p);
    if (st)
        return st;
    shapes_near *n = s->near;
    if (++n->gen == 0) {
        memset(n->mark, 0, (s->edges + 1) * sizeof *n->mark);
        n->gen = 1;
    }
    n->within = 1;
    n->bound = q_int((u128)d * (u128)d);
    n->bound2 = q_square(&n->bound);
    st = search(s);
    if (!st && array_grow((void **)&n->dist, &n->cap_dist, n->nedge + 1, sizeof *n->dist))
        st = HPFC_E_NOMEM;
    if (st)
        return st;
    if (n->nedge)
        qsort(n->edge, n->nedge, sizeof *n->edge, cmp_id);
    for (size_t k = 0; k < n->nedge; k++)
        n->dist[k] = q_value(&n->edist[n->edge[k]]);
    *out = (hpfc_edge_hits){.count = n->nedge, .edge = n->edge, .distance = n->dist};
    return HPFC_OK;
}
