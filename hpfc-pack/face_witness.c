/*
 * Witness points of faces (face_witness.h).
 *
 * The tree says, for every crossing of every word leaf, which segment of
 * which input edge makes it (kept in a leaf_crossings once the tree is
 * gone); the file says which face lies on the right of the crossing's
 * out-dart. Between them, every stretch of a leaf's boundary between two
 * consecutive crossings gets both a face and a place.
 */
#include "face_witness.h"

#include <stdlib.h>
#include <string.h>

#include "grow.h"

/* Nudge across a road, in lattice units: far below any distance between a
 * lattice point and a segment that misses it (at least 2^-42 for coordinates
 * below 2^41, when it is not zero), far above long double's resolution there
 * (2^-22). Witnesses only feed point-in-ring tests, so what matters is that
 * the side is right. */
#define NUDGE 0x1p-16L

typedef struct leaf_geometry {
    int64_t x0, y0, x1, y1;
    long double w, h, perimeter;
} leaf_geometry;

/* Points of segment s of edge e. */
static void segment_points(const hpfc_graph *g, uint32_t e, uint32_t s, int64_t p[2], int64_t q[2])
{
    uint32_t u, v;
    const int64_t *xy;
    size_t n;
    hpfc_graph_edge(g, e, &u, &v, &xy, &n);
    if (s == 0)
        hpfc_graph_vertex(g, u, &p[0], &p[1]);
    else
        p[0] = xy[2 * (s - 1)], p[1] = xy[2 * (s - 1) + 1];
    if (s == n)
        hpfc_graph_vertex(g, v, &q[0], &q[1]);
    else
        q[0] = xy[2 * s], q[1] = xy[2 * s + 1];
}

/* Where segment pq meets the vertical line x = X (or, with `horizontal`,
 * the line y = X), as the other coordinate. The caller knows it crosses. */
static long double cross_at(const int64_t p[2], const int64_t q[2], int64_t X, int horizontal)
{
    int a = horizontal ? 1 : 0, b = 1 - a;
    long double d = (long double)(q[a] - p[a]);
    return (long double)p[b] + (long double)(q[b] - p[b]) * ((long double)(X - p[a]) / d);
}

/* Position of a crossing along the leaf's boundary, clockwise from the SW
 * corner: road W northward, N eastward, E southward, S westward. */
static long double boundary_position(const leaf_geometry *L, int road, const int64_t p[2],
                                     const int64_t q[2])
{
    switch (road) {
    case HPFC_WEST:
        return cross_at(p, q, L->x0, 0) - (long double)L->y0;
    case HPFC_NORTH:
        return L->h + cross_at(p, q, L->y1, 1) - (long double)L->x0;
    case HPFC_EAST:
        return L->h + L->w + (long double)L->y1 - cross_at(p, q, L->x1, 0);
    default:
        return 2 * L->h + L->w + (long double)L->x1 - cross_at(p, q, L->y0, 1);
    }
}

/* The boundary point at clockwise position t, nudged the way §3.5 moves
 * its road: west of vertical lines, south of horizontal ones. */
static void boundary_point(const leaf_geometry *L, long double t, long double *x, long double *y)
{
    while (t >= L->perimeter)
        t -= L->perimeter;
    if (t < L->h) {
        *x = (long double)L->x0 - NUDGE, *y = (long double)L->y0 + t;
    } else if (t < L->h + L->w) {
        *x = (long double)L->x0 + (t - L->h), *y = (long double)L->y1 - NUDGE;
    } else if (t < 2 * L->h + L->w) {
        *x = (long double)L->x1 - NUDGE, *y = (long double)L->y1 - (t - L->h - L->w);
    } else {
        *x = (long double)L->x1 - (t - 2 * L->h - L->w), *y = (long double)L->y0 - NUDGE;
    }
}

static void offer(face_witness *w, uint64_t face, long double x, long double y, long double reach)
{
    if (reach > w[face].reach)
        w[face] = (face_witness){x, y, reach};
}

/* A word leaf of the file: its bounds, its word, and where its crossings
 * start in a leaf_crossings. */
typedef struct leaf_view {
    hpfc_pixel px;
    int64_t x0, y0, x1, y1;
    char *word;
    size_t word_len, word_cap;
    uint64_t first;
} leaf_view;

/* The witnesses a word leaf offers; *used: its crossings. */
static int leaf_witnesses(const hpfc_graph *g, const leaf_crossings *lc, const leaf_view *v,
                          const hpfc_faces *faces, face_witness *w, long double *pos,
                          uint32_t *used)
{
    leaf_geometry L = {v->x0, v->y0, v->x1, v->y1, 0, 0, 0};
    L.w = (long double)(L.x1 - L.x0), L.h = (long double)(L.y1 - L.y0);
    L.perimeter = 2 * (L.w + L.h);
    uint32_t n = 0;
    int road = 0;
    for (size_t s = 0; s < v->word_len; s++) {
        if (v->word[s] == '+') {
            road++;
            continue;
        }
        int64_t p[2], q[2];
        uint64_t c = v->first + n;
        if (c >= lc->count)
            return HPFC_E_CORRUPT;
        segment_points(g, lc->pairs[2 * c], lc->pairs[2 * c + 1], p, q);
        pos[n++] = boundary_position(&L, road, p, q);
    }
    *used = n;
    uint64_t face;
    if (n == 0) {
        int st = hpfc_faces_of_private_pixel(faces, &v->px, &face);
        if (!st)
            offer(w, face, (long double)L.x0 + L.w / 2, (long double)L.y0 + L.h / 2,
                  (L.w < L.h ? L.w : L.h) / 2);
        return st;
    }
    for (uint32_t k = 0; k < n; k++) {
        long double gap = (k + 1 < n ? pos[k + 1] : pos[0] + L.perimeter) - pos[k];
        if (!(gap > 0))
            continue; /* crossings at one point: a vertex on the road */
        hpfc_dart d = {v->px, k};
        int st = hpfc_faces_of_dart(faces, &d, &face);
        if (st)
            return st;
        long double x, y;
        boundary_point(&L, pos[k] + gap / 2, &x, &y);
        offer(w, face, x, y, gap / 4);
    }
    return HPFC_OK;
}

/* Decodes the word of the file's leaf v->px into v (growing its buffer)
 * with its bounds. */
static int view_leaf(const hpfc_file *file, leaf_view *v)
{
    int st = hpfc_pixel_word(file, &v->px, NULL, 0, &v->word_len);
    if (!st && v->word_len + 1 > v->word_cap) {
        char *nw = realloc(v->word, v->word_len + 1);
        if (!nw)
            return HPFC_E_NOMEM;
        v->word = nw, v->word_cap = v->word_len + 1;
    }
    if (!st)
        st = hpfc_pixel_word(file, &v->px, v->word, v->word_cap, &v->word_len);
    if (!st)
        st = hpfc_pixel_bounds(file, &v->px, &v->x0, &v->y0, &v->x1, &v->y1);
    return st;
}

/* The tree's pixel at the file pixel's path: the child images of the
 * refined pixels along it, level by level. */
static int tree_pixel_of(const hpfc_tree *tree, const hpfc_pixel *px, hpfc_tree_pixel *tp)
{
    size_t image = 0;
    for (uint32_t l = 0;; l++) {
        int st = hpfc_tree_get_pixel(tree, l, image, px->path[l].i, px->path[l].j, tp);
        if (st || l == px->depth)
            return st ? HPFC_E_CORRUPT : HPFC_OK;
        if (tp->type != HPFC_PIXEL_REFINED)
            return HPFC_E_CORRUPT;
        image = tp->child;
    }
}

static uint32_t word_crossings(const hpfc_tree_pixel *tp)
{
    uint32_t n = 0;
    for (uint32_t s = 0; s < tp->word_len; s++)
        n += tp->word[s] != '+';
    return n;
}

/* Allocates lc for all the tree's crossings at once: grown by doubling,
 * the array would leave its earlier copies in the heap, and it is
 * allocated at a pack's peak. */
static int reserve_crossings(const hpfc_tree *tree, leaf_crossings *lc)
{
    hpfc_tree_info info;
    hpfc_tree_get_info(tree, &info);
    uint64_t total = 0;
    for (uint32_t l = 0; l < info.levels; l++) {
        uint32_t cols = l ? info.cols : info.root_cols, rows = l ? info.rows : info.root_rows;
        size_t images = hpfc_tree_image_count(tree, l);
        for (size_t im = 0; im < images; im++)
            for (uint32_t j = 0; j < rows; j++)
                for (uint32_t i = 0; i < cols; i++) {
                    hpfc_tree_pixel tp;
                    if (!hpfc_tree_get_pixel(tree, l, im, i, j, &tp) && tp.type == HPFC_PIXEL_WORD)
                        total += word_crossings(&tp);
                }
    }
    if (total > SIZE_MAX / 2 / sizeof *lc->pairs ||
        !(lc->pairs = malloc(total ? 2 * (size_t)total * sizeof *lc->pairs : 1)))
        return HPFC_E_NOMEM;
    lc->cap = 2 * (size_t)total;
    return HPFC_OK;
}

static int append_crossings(leaf_crossings *lc, const hpfc_tree_pixel *tp)
{
    uint32_t n = word_crossings(tp);
    if (2 * (lc->count + n) > lc->cap)
        return HPFC_E_CORRUPT; /* more crossings on the file's leaves than in the tree */
    for (uint32_t k = 0; k < n; k++) {
        lc->pairs[2 * lc->count] = tp->cross_edge[k];
        lc->pairs[2 * lc->count + 1] = tp->cross_segment[k];
        lc->count++;
    }
    return HPFC_OK;
}

int leaf_crossings_collect(const hpfc_tree *tree, const hpfc_file *file, leaf_crossings *out)
{
    memset(out, 0, sizeof *out);
    leaf_view v = {0};
    int st = reserve_crossings(tree, out);
    if (!st)
        st = hpfc_leaf_first(file, &v.px);
    for (; !st; st = hpfc_leaf_next(file, &v.px)) {
        hpfc_tree_pixel tp;
        if ((st = view_leaf(file, &v)) || (st = tree_pixel_of(tree, &v.px, &tp)))
            break;
        if (tp.type != HPFC_PIXEL_WORD || tp.word_len != v.word_len ||
            memcmp(tp.word, v.word, v.word_len) != 0 || tp.x0 != v.x0 || tp.y0 != v.y0 ||
            tp.x1 != v.x1 || tp.y1 != v.y1) {
            st = HPFC_E_CORRUPT; /* the file is not the tree's */
            break;
        }
        if ((st = append_crossings(out, &tp)))
            break;
    }
    free(v.word);
    if (st == HPFC_E_NO_PIXEL) /* every crossing of the tree found on a leaf of the file */
        st = 2 * out->count == out->cap ? HPFC_OK : HPFC_E_CORRUPT;
    if (st)
        leaf_crossings_free(out);
    return st;
}

void leaf_crossings_free(leaf_crossings *lc)
{
    free(lc->pairs);
    memset(lc, 0, sizeof *lc);
}

int face_witnesses(const hpfc_graph *graph, const leaf_crossings *lc, const hpfc_file *file,
                   const hpfc_faces *faces, face_witness *w)
{
    for (uint64_t f = 0; f < hpfc_faces_count(faces); f++)
        w[f] = (face_witness){0, 0, 0};
    leaf_view v = {0};
    long double *pos = NULL;
    size_t pos_cap = 0;
    int st = hpfc_leaf_first(file, &v.px);
    for (; !st; st = hpfc_leaf_next(file, &v.px)) {
        if ((st = view_leaf(file, &v)))
            break;
        if (!array_grow((void **)&pos, &pos_cap, v.word_len + 1, sizeof *pos)) {
            st = HPFC_E_NOMEM;
            break;
        }
        uint32_t used = 0;
        if ((st = leaf_witnesses(graph, lc, &v, faces, w, pos, &used)))
            break;
        v.first += used;
    }
    free(v.word);
    free(pos);
    if (st == HPFC_E_NO_PIXEL)
        st = v.first == lc->count ? HPFC_OK : HPFC_E_CORRUPT;
    return st;
}
