/*
 * Witness points of faces (face_witness.h).
 *
 * The tree says, for every crossing of every word leaf, which segment of
 * which input edge makes it; the file says which face lies on the right of
 * the crossing's out-dart. Between them, every stretch of a leaf's boundary
 * between two consecutive crossings gets both a face and a place.
 */
#include "face_witness.h"

#include <stdlib.h>

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

/* The witnesses a word leaf of the tree offers; fp is the same leaf in
 * the file. */
static int leaf_witnesses(const hpfc_graph *g, const hpfc_tree_pixel *tp, const hpfc_faces *faces,
                          const hpfc_pixel *fp, face_witness *w, long double *pos)
{
    leaf_geometry L = {tp->x0, tp->y0, tp->x1, tp->y1, 0, 0, 0};
    L.w = (long double)(L.x1 - L.x0), L.h = (long double)(L.y1 - L.y0);
    L.perimeter = 2 * (L.w + L.h);
    uint32_t n = 0;
    int road = 0;
    for (uint32_t s = 0; s < tp->word_len; s++) {
        if (tp->word[s] == '+') {
            road++;
            continue;
        }
        int64_t p[2], q[2];
        segment_points(g, tp->cross_edge[n], tp->cross_segment[n], p, q);
        pos[n++] = boundary_position(&L, road, p, q);
    }
    uint64_t face;
    if (n == 0) {
        int st = hpfc_faces_of_private_pixel(faces, fp, &face);
        if (!st)
            offer(w, face, (long double)L.x0 + L.w / 2, (long double)L.y0 + L.h / 2,
                  (L.w < L.h ? L.w : L.h) / 2);
        return st;
    }
    for (uint32_t k = 0; k < n; k++) {
        long double gap = (k + 1 < n ? pos[k + 1] : pos[0] + L.perimeter) - pos[k];
        if (!(gap > 0))
            continue; /* crossings at one point: a vertex on the road */
        hpfc_dart d = {*fp, k};
        int st = hpfc_faces_of_dart(faces, &d, &face);
        if (st)
            return st;
        long double x, y;
        boundary_point(&L, pos[k] + gap / 2, &x, &y);
        offer(w, face, x, y, gap / 4);
    }
    return HPFC_OK;
}

/* The file's leaf with the tree pixel's bounds. */
static int file_leaf(const hpfc_file *file, const hpfc_tree_pixel *tp, hpfc_pixel *fp)
{
    int64_t x0, y0, x1, y1;
    int st = hpfc_locate(file, tp->x0, tp->y0, fp);
    if (!st)
        st = hpfc_pixel_bounds(file, fp, &x0, &y0, &x1, &y1);
    if (!st && (x0 != tp->x0 || y0 != tp->y0 || x1 != tp->x1 || y1 != tp->y1))
        st = HPFC_E_CORRUPT;
    return st;
}

int face_witnesses(const hpfc_graph *graph, const hpfc_tree *tree, const hpfc_file *file,
                   const hpfc_faces *faces, face_witness *w)
{
    hpfc_tree_info info;
    hpfc_tree_get_info(tree, &info);
    for (uint64_t f = 0; f < hpfc_faces_count(faces); f++)
        w[f] = (face_witness){0, 0, 0};
    long double *pos = malloc(((size_t)info.max_word_symbols + 1) * sizeof *pos);
    if (!pos)
        return HPFC_E_NOMEM;
    int st = HPFC_OK;
    for (uint32_t l = 0; l < info.levels && !st; l++) {
        uint32_t cols = l ? info.cols : info.root_cols, rows = l ? info.rows : info.root_rows;
        size_t images = hpfc_tree_image_count(tree, l);
        for (size_t im = 0; im < images && !st; im++)
            for (uint32_t j = 0; j < rows && !st; j++)
                for (uint32_t i = 0; i < cols && !st; i++) {
                    hpfc_tree_pixel tp;
                    hpfc_pixel fp;
                    st = hpfc_tree_get_pixel(tree, l, im, i, j, &tp);
                    if (st || tp.type != HPFC_PIXEL_WORD)
                        continue;
                    st = file_leaf(file, &tp, &fp);
                    if (!st)
                        st = leaf_witnesses(graph, &tp, faces, &fp, w, pos);
                }
    }
    free(pos);
    return st;
}
