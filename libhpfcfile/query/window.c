/*
 * window.c: what of the map meets a closed lattice rectangle (hpfc.h,
 * hpfc_shapes_window), by a descent of the tree to the leaves that meet it.
 *
 * A leaf whose closed box lies in the window gives its faces (LABL) and the
 * edges of its crossings, with no geometry. A leaf the window's border cuts
 * is decided exactly on R, the part of its box in the window (a lattice
 * rectangle): an edge meets R when one of its segments inside the leaf does
 * (exact segment-rectangle test; the leaf holds few shape points, so the
 * walk from each crossing's segment is short), and then both its faces do;
 * a face that meets R along no such segment covers all of R (R is
 * connected), so the face at R's south-west corner (as hpfc_locate_point)
 * completes the set. Every leaf whose closed box meets the window is
 * visited, so a contact on a leaf's border is seen from the leaf that holds
 * the segment.
 *
 * Inside or crossing: an edge lies inside when its box does; a bounded face
 * when all the edges around it do (its boundary inside a convex window
 * holds it); a feature when all its faces and edges do. Only what meets
 * the window's border needs that test: a face or edge that reaches
 * outside meets the border (it is connected) at some point p, and every
 * leaf whose closed box holds p meets the border too; the one where it
 * passes p (its interior near p, or its segment through p) finds it there.
 * So what the descent finds in border leaves alone (a closed box not
 * within the window's interior) is tested; the rest lies inside.
 */
#include <stdlib.h>
#include <string.h>

#include "arrays.h"
#include "file.h"
#include "geometry.h"
#include "labels.h"
#include "locate_point.h"
#include "reader.h"
#include "shapes.h"

/* The window's answer and the marks that keep each id once. */
struct shapes_window {
    uint32_t *face_mark, *edge_mark, *feature_mark, gen;
    uint32_t *face_border, *edge_border; /* == gen: found in a border leaf */
    uint8_t *face_in, *edge_in; /* valid where *_mark is current: it lies inside */
    hpfc_id *face, *edge, *feature;
    size_t nface, cap_face, nedge, cap_edge, nfeature, cap_feature;
    uint8_t *face_inside, *edge_inside, *feature_inside;
    size_t cap_face_inside, cap_edge_inside, cap_feature_inside;
    char *word;
    size_t cap_word;
    labels_leaf leaf;       /* a cut leaf's labels, loaded once */
    uint64_t *seg;
    size_t cap_seg;
    locx_scratch loc;       /* the corner's location, its arrays kept across calls */
    uint64_t *sort_tmp;     /* id_sort's scratch */
    size_t cap_sort_tmp;
};

void shapes_window_free(const hpfc_shapes *s, shapes_window *w)
{
    if (!w)
        return;
    size_t F = (size_t)s->faces + 1, E = (size_t)s->edges + 1;
    shapes_zeroed_free(w->face_mark, F, sizeof *w->face_mark);
    shapes_zeroed_free(w->edge_mark, E, sizeof *w->edge_mark);
    shapes_zeroed_free(w->feature_mark, (size_t)s->features + 1, sizeof *w->feature_mark);
    shapes_zeroed_free(w->face_border, F, sizeof *w->face_border);
    shapes_zeroed_free(w->edge_border, E, sizeof *w->edge_border);
    shapes_zeroed_free(w->face_in, F, 1);
    shapes_zeroed_free(w->edge_in, E, 1);
    free(w->face);
    free(w->edge);
    free(w->feature);
    free(w->face_inside);
    free(w->edge_inside);
    free(w->feature_inside);
    free(w->word);
    labels_leaf_free(&w->leaf);
    free(w->seg);
    locx_scratch_free(&w->loc);
    free(w->sort_tmp);
    free(w);
}

/* The window's marks, made whole or not at all: a query after a failed
 * one finds either none or every array. */
static shapes_window *window_new(const hpfc_shapes *s)
{
    shapes_window *w = calloc(1, sizeof *w);
    if (!w)
        return NULL;
    /* pages touched as the windows meet faces and edges */
    w->face_mark = shapes_zeroed(s->faces + 1, sizeof *w->face_mark);
    w->edge_mark = shapes_zeroed(s->edges + 1, sizeof *w->edge_mark);
    w->feature_mark = shapes_zeroed((size_t)s->features + 1, sizeof *w->feature_mark);
    w->face_border = shapes_zeroed(s->faces + 1, sizeof *w->face_border);
    w->edge_border = shapes_zeroed(s->edges + 1, sizeof *w->edge_border);
    w->face_in = shapes_zeroed(s->faces + 1, 1);
    w->edge_in = shapes_zeroed(s->edges + 1, 1);
    if (!w->face_mark || !w->edge_mark || !w->feature_mark || !w->face_border ||
        !w->edge_border || !w->face_in || !w->edge_in) {
        shapes_window_free(s, w);
        return NULL;
    }
    return w;
}

/* The marks, once per shapes object; a new generation per query. */
static int window_begin(hpfc_shapes *s)
{
    shapes_window *w = s->window;
    if (!w && !(w = s->window = window_new(s)))
        return HPFC_E_NOMEM;
    if (++w->gen == 0) { /* the stamps wrapped: forget them all */
        memset(w->face_mark, 0, (s->faces + 1) * sizeof *w->face_mark);
        memset(w->edge_mark, 0, (s->edges + 1) * sizeof *w->edge_mark);
        memset(w->face_border, 0, (s->faces + 1) * sizeof *w->face_border);
        memset(w->edge_border, 0, (s->edges + 1) * sizeof *w->edge_border);
        memset(w->feature_mark, 0, ((size_t)s->features + 1) * sizeof *w->feature_mark);
        w->gen = 1;
    }
    w->nface = w->nedge = w->nfeature = 0;
    return HPFC_OK;
}

/* Face `face` met; `border`: in a border leaf. */
static int add_face(hpfc_shapes *s, uint64_t face, int border)
{
    shapes_window *w = s->window;
    if (face >= s->faces)
        return HPFC_E_CORRUPT;
    if (border)
        w->face_border[face] = w->gen;
    if (w->face_mark[face] == w->gen)
        return HPFC_OK;
    w->face_mark[face] = w->gen;
    if (w->nface + w->nedge + w->nfeature >= s->max_items)
        return HPFC_E_OVER_LIMIT;
    if (array_grow((void **)&w->face, &w->cap_face, w->nface + 1, sizeof *w->face))
        return HPFC_E_NOMEM;
    w->face[w->nface++] = face;
    return HPFC_OK;
}

/* Edge `edge` met, and its sides with it: they were added with the edge
 * before, unless the edge is new or newly found in a border leaf. */
static int add_edge_sides(hpfc_shapes *s, uint64_t edge, int border)
{
    shapes_window *w = s->window;
    if (edge >= s->edges)
        return HPFC_E_CORRUPT;
    if (w->edge_mark[edge] == w->gen && (!border || w->edge_border[edge] == w->gen))
        return HPFC_OK;
    int st = shapes_need_edge(s, edge);
    if (st)
        return st;
    if (border)
        w->edge_border[edge] = w->gen;
    st = add_face(s, s->edge[edge].left, border);
    if (!st && s->edge[edge].right != s->edge[edge].left)
        st = add_face(s, s->edge[edge].right, border);
    if (st || w->edge_mark[edge] == w->gen)
        return st;
    w->edge_mark[edge] = w->gen;
    if (w->nface + w->nedge + w->nfeature >= s->max_items)
        return HPFC_E_OVER_LIMIT;
    if (array_grow((void **)&w->edge, &w->cap_edge, w->nedge + 1, sizeof *w->edge))
        return HPFC_E_NOMEM;
    w->edge[w->nedge++] = edge;
    return HPFC_OK;
}

/* ---- exact tests ------------------------------------------------------------------ */

typedef struct rect {
    int64_t x0, y0, x1, y1; /* closed */
} rect;

static int rect_within(const rect *a, const rect *b)
{
    return a->x0 >= b->x0 && a->y0 >= b->y0 && a->x1 <= b->x1 && a->y1 <= b->y1;
}

/* a within b's interior: it does not touch b's border */
static int rect_within_interior(const rect *a, const rect *b)
{
    return a->x0 > b->x0 && a->y0 > b->y0 && a->x1 < b->x1 && a->y1 < b->y1;
}

/* How many of r's corners lie strictly left of the line a-b (*pos) and
 * strictly right (*neg): exact, on 128-bit products. */
static void corner_sides(const int64_t a[2], const int64_t b[2], const rect *r, int *pos, int *neg)
{
    s128 dx = (s128)b[0] - a[0], dy = (s128)b[1] - a[1];
    int64_t cx[4] = {r->x0, r->x1, r->x1, r->x0}, cy[4] = {r->y0, r->y0, r->y1, r->y1};
    *pos = *neg = 0;
    for (int k = 0; k < 4; k++) {
        int o = sign128(dx * ((s128)cy[k] - a[1]) - dy * ((s128)cx[k] - a[0]));
        *pos += o > 0, *neg += o < 0;
    }
}

/* Does segment a-b meet the closed rectangle r? Separating axes: x, y and
 * the segment's normal (the rectangle's corners all strictly on one side). */
static int segment_meets(const int64_t a[2], const int64_t b[2], const rect *r)
{
    if ((a[0] < r->x0 && b[0] < r->x0) || (a[0] > r->x1 && b[0] > r->x1) ||
        (a[1] < r->y0 && b[1] < r->y0) || (a[1] > r->y1 && b[1] > r->y1))
        return 0;
    int pos, neg;
    corner_sides(a, b, r, &pos, &neg);
    return !(pos == 4 || neg == 4);
}

/* Does segment a-b meet the open interior of r (x0 < x1, y0 < y1)? The
 * same axes, the separation now weak: the open box lies strictly on one
 * side of the segment's line when its four corners lie on one closed side. */
static int segment_meets_interior(const int64_t a[2], const int64_t b[2], const rect *r)
{
    if ((a[0] <= r->x0 && b[0] <= r->x0) || (a[0] >= r->x1 && b[0] >= r->x1) ||
        (a[1] <= r->y0 && b[1] <= r->y0) || (a[1] >= r->y1 && b[1] >= r->y1))
        return 0;
    int pos, neg;
    corner_sides(a, b, r, &pos, &neg);
    return pos > 0 && neg > 0;
}

int shapes_segment_meets(const int64_t a[2], const int64_t b[2], const int64_t box[4])
{
    rect r = {box[0], box[1], box[2], box[3]};
    return segment_meets(a, b, &r);
}

int shapes_edge_point_run(const hpfc_shapes *s, uint64_t e, uint64_t from, uint64_t n,
                          int64_t *xy)
{
    /* reading the edge's record on first use changes no answer */
    int st = shapes_need_edge((hpfc_shapes *)s, e);
    if (st)
        return st;
    uint64_t last = shapes_edge_points(s, e) - 1, end = from + n;
    if (n == 0)
        return HPFC_OK;
    if (from > last || n > last - from + 1)
        return HPFC_E_ARG;
    uint64_t k = from;
    if (k == 0) {
        xy[0] = s->vxy[2 * (size_t)s->edge[e].u], xy[1] = s->vxy[2 * (size_t)s->edge[e].u + 1];
        xy += 2, k++;
    }
    uint64_t inner = end < last ? end : last; /* shape points: 1 .. last - 1 */
    if (k < inner) {
        st = geom_points(s->f, GEOM_PX, s->edge[e].first + k - 1, inner - k, xy);
        if (st)
            return st;
        xy += 2 * (inner - k), k = inner;
    }
    if (k < end) /* k == last */
        xy[0] = s->vxy[2 * (size_t)s->edge[e].v], xy[1] = s->vxy[2 * (size_t)s->edge[e].v + 1];
    return HPFC_OK;
}

int shapes_edge_box(hpfc_shapes *s, uint64_t edge, const int64_t **box)
{
    if (!s->edge_box && !(s->edge_box = shapes_zeroed(s->edges + 1, sizeof *s->edge_box)))
        return HPFC_E_NOMEM;
    int64_t *b = s->edge_box[edge];
    int st = shapes_need_edge(s, edge);
    if (st)
        return st;
    /* all zero: not computed (an edge's points are not all one point) */
    if (!b[0] && !b[1] && !b[2] && !b[3]) { /* read a run of points at a time */
        enum { RUN = 128 };
        int64_t xy[2 * RUN], lo[2] = {INT64_MAX, INT64_MAX}, hi[2] = {INT64_MIN, INT64_MIN};
        for (uint64_t k0 = 0, n = shapes_edge_points(s, edge), m; k0 < n; k0 += m) {
            m = n - k0 < RUN ? n - k0 : RUN;
            if ((st = shapes_edge_point_run(s, edge, k0, m, xy)))
                return st;
            for (uint64_t k = 0; k < 2 * m; k++) {
                lo[k & 1] = xy[k] < lo[k & 1] ? xy[k] : lo[k & 1];
                hi[k & 1] = xy[k] > hi[k & 1] ? xy[k] : hi[k & 1];
            }
        }
        b[0] = lo[0], b[1] = lo[1], b[2] = hi[0], b[3] = hi[1];
    }
    *box = b;
    return HPFC_OK;
}

static int edge_inside(hpfc_shapes *s, uint64_t edge, const rect *win, int *inside)
{
    const int64_t *b;
    int st = shapes_edge_box(s, edge, &b);
    if (!st)
        *inside = b[0] >= win->x0 && b[1] >= win->y0 && b[2] <= win->x1 && b[3] <= win->y1;
    return st;
}

/* ---- the descent ------------------------------------------------------------------- */

/* The segments of edge e after `seg` (forward: seg, seg + 1, ...) or
 * before it (seg - 1, seg - 2, ...), while they meet the leaf's closed
 * box: *hit 1 when one of them meets r, 2 when it meets r's interior
 * (r not flat). The points come a run at a time. */
static int walk_segments(hpfc_shapes *s, uint64_t e, uint64_t seg, int forward, const rect *box,
                         const rect *r, int *hit)
{
    enum { RUN = 16 };
    int64_t xy[2 * (RUN + 1)];
    uint64_t segments = shapes_edge_points(s, e) - 1, j = seg;
    while (forward ? j < segments : j > 0) {
        uint64_t m = forward ? segments - j : j;
        m = m < RUN ? m : RUN;
        uint64_t from = forward ? j : j - m;
        int st = shapes_edge_point_run(s, e, from, m + 1, xy);
        if (st)
            return st;
        for (uint64_t i = 0; i < m; i++) {
            uint64_t k = forward ? i : m - 1 - i; /* segment from + k: points k, k + 1 */
            if (!segment_meets(&xy[2 * k], &xy[2 * k + 2], box))
                return HPFC_OK;
            if (segment_meets(&xy[2 * k], &xy[2 * k + 2], r)) {
                *hit = r->x0 < r->x1 && r->y0 < r->y1 &&
                               segment_meets_interior(&xy[2 * k], &xy[2 * k + 2], r)
                           ? 2
                           : 1;
                return HPFC_OK;
            }
        }
        j = forward ? j + m : j - m;
    }
    return HPFC_OK;
}

/* The edge of a crossing of a cut leaf (its edge e, its segment seg), if
 * its piece inside the leaf meets r: the segments from the crossing's on,
 * both ways, while they meet the leaf's closed box. *through: set when
 * the piece crosses r's interior. */
static int cut_crossing(hpfc_shapes *s, uint64_t e, uint64_t seg, const rect *box, const rect *r,
                        int *through)
{
    if (e >= s->edges)
        return HPFC_E_CORRUPT;
    int hit = 0, st = shapes_need_edge(s, e);
    if (st)
        return st;
    if (seg + 1 >= shapes_edge_points(s, e))
        return HPFC_E_CORRUPT;
    st = walk_segments(s, e, seg, 1, box, r, &hit);
    if (!st && !hit)
        st = walk_segments(s, e, seg, 0, box, r, &hit);
    if (st || !hit)
        return st;
    *through |= hit == 2;
    return add_edge_sides(s, e, 1);
}

/* A leaf's word and labels, read once into w->leaf (w->leaf.rec.word.n
 * crossings, w->leaf.edge their edges). */
static int load_leaf(hpfc_shapes *s, const hpfc_pixel *leaf, const reader_leaf_at *at)
{
    shapes_window *w = s->window;
    return labels_leaf_load_word(s->f, leaf, at, &w->word, &w->cap_word, &w->leaf);
}

/* A leaf's faces and edges from its record's pieces: with crossings, the
 * faces are their edges' sides: every region of the leaf borders an edge
 * piece (the pieces cut the leaf into its regions), and each piece has a
 * region on either side. */
static int add_pieces(hpfc_shapes *s, const labels_pieces *lp, int border)
{
    if (lp->is_private)
        return add_face(s, lp->face, border);
    int st = HPFC_OK;
    for (uint64_t q = 0; !st && q < lp->count; q++) {
        uint64_t e;
        st = labels_piece_edge(s->f, lp, q, &e);
        if (!st)
            st = add_edge_sides(s, e, border);
    }
    return st;
}

/* A leaf whose closed box lies in the window: its faces and its crossings'
 * edges, from its record alone (labels_leaf_pieces: its word is not read,
 * which crossing is on which edge does not matter here). */
static int inside_leaf(hpfc_shapes *s, const hpfc_pixel *leaf, const reader_leaf_at *at,
                       int border)
{
    labels_pieces lp;
    int st = labels_leaf_pieces(s->f, leaf, at, &lp);
    return st ? st : add_pieces(s, &lp, border);
}

/* Every leaf below a refined pixel whose closed box lies in the window's
 * interior (compact layout): none is a border leaf, so none needs its
 * box or its path. A scan of the subtree's type bits (reader_scan) gives
 * them level by level in rank order, so the records of a level's run
 * follow each other: a private leaf's extent is known, a stabbed one's is
 * one directory entry. */
static int inside_subtree(hpfc_shapes *s, const hpfc_pixel *px)
{
    reader_scan sc;
    uint32_t level, prev_level = UINT32_MAX;
    uint64_t rank, prev_rank = 0, next = UINT64_MAX;
    bool is_private;
    int st = reader_scan_begin(s->f, px, &sc);
    while (!st && !(st = reader_scan_next(s->f, &sc, &level, &rank, &is_private))) {
        if (level != prev_level || rank != prev_rank + 1)
            next = UINT64_MAX; /* a new run: its first record from the directory */
        labels_pieces lp;
        st = labels_leaf_pieces_ranked(s->f, level, rank, is_private, &next, &lp);
        if (!st)
            st = add_pieces(s, &lp, 0);
        prev_level = level, prev_rank = rank;
    }
    return st == HPFC_E_NO_PIXEL ? HPFC_OK : st;
}

/* A leaf the window's border cuts: exactly, on r = its box in the window. */
static int cut_leaf(hpfc_shapes *s, const hpfc_pixel *leaf, const reader_leaf_at *at,
                    const rect *box, const rect *r)
{
    shapes_window *w = s->window;
    int st = load_leaf(s, leaf, at);
    if (st)
        return st;
    uint32_t n = w->leaf.rec.word.n;
    if (array_grow((void **)&w->seg, &w->cap_seg, (size_t)n + 1, sizeof *w->seg))
        return HPFC_E_NOMEM;
    st = geom_leaf_segments(s->f, leaf, n, w->seg);
    int through = 0;
    for (uint32_t k = 0; k < n && !st; k++)
        st = cut_crossing(s, w->leaf.edge[k], w->seg[k], box, r, &through);
    /* A face meeting r along no segment covers r: the one at its corner.
     * None does when an edge crosses r's interior (it would hold that
     * edge's points, and be one of its sides). */
    if (st || through)
        return st;
    /* hpfc_locate_point's answer, its scratch kept across leaves */
    locx_answer ans;
    size_t count = 0;
    st = locx_locate(s->f, r->x0, r->y0, &w->loc, &ans, &count);
    if (st == HPFC_E_NO_PIXEL) /* r's corner on the domain's far border: outside it */
        return add_face(s, 0, 1);
    for (size_t k = 0; k < count && !st; k++)
        st = add_face(s, w->loc.around[k], 1);
    return st;
}

/* What the descent keeps fixed: the window, and each level's cell size. */
typedef struct descent {
    rect win;
    int64_t cell_w[HPFC_MAX_LEVELS], cell_h[HPFC_MAX_LEVELS];
    uint32_t cols, rows;
} descent;

static int rect_meets(const rect *a, const rect *b)
{
    return a->x0 <= b->x1 && a->x1 >= b->x0 && a->y0 <= b->y1 && a->y1 >= b->y0;
}

/* Every leaf under px (of `type`, its closed box `box` meeting the window;
 * `at` what its parent's walk learnt of it, NULL: nothing) whose closed box
 * meets the window. A child's box is its parent's corner plus its cell, as
 * hpfc_pixel_bounds adds them, so only the children that meet the window
 * are read, from their image's type bits read once (reader_children). A
 * refined pixel within the window's interior (compact layout) has only
 * inside, non-border leaves below it: they are scanned, not descended. */
static int descend(hpfc_shapes *s, const descent *d, const hpfc_pixel *px, int type,
                   const reader_leaf_at *at, const rect *box)
{
    const rect *win = &d->win;
    if (type == HPFC_PIXEL_WORD) {
        if (rect_within(box, win))
            return inside_leaf(s, px, at, !rect_within_interior(box, win));
        rect r = {box->x0 > win->x0 ? box->x0 : win->x0, box->y0 > win->y0 ? box->y0 : win->y0,
                  box->x1 < win->x1 ? box->x1 : win->x1, box->y1 < win->y1 ? box->y1 : win->y1};
        return cut_leaf(s, px, at, box, &r);
    }
    if (s->f->compact && rect_within_interior(box, win))
        return inside_subtree(s, px);
    reader_children children;
    int st = reader_children_begin(s->f, px, &children);
    uint32_t level = px->depth + 1; /* a refined pixel is above the last level */
    int64_t cw = d->cell_w[level], ch = d->cell_h[level];
    for (uint32_t j = 0; j < d->rows && !st; j++)
        for (uint32_t i = 0; i < d->cols && !st; i++) {
            rect cb;
            cb.x0 = box->x0 + (int64_t)i * cw;
            cb.y0 = box->y0 + (int64_t)(d->rows - 1 - j) * ch;
            cb.x1 = cb.x0 + cw;
            cb.y1 = cb.y0 + ch;
            if (!rect_meets(&cb, win))
                continue;
            hpfc_pixel child;
            reader_leaf_at child_at;
            int child_type;
            st = reader_children_get(s->f, &children, i, j, &child, &child_type, &child_at);
            if (!st)
                st = descend(s, d, &child, child_type, &child_at, &cb);
        }
    return st;
}

/* The root pixels whose closed box can meet the window: columns and rows
 * of the root image from the window's extent, one more each side. */
static int descend_roots(hpfc_shapes *s, const rect *win)
{
    hpfc_file_info fi;
    hpfc_file_get_info(s->f, &fi);
    descent d = {.win = *win, .cols = fi.cols, .rows = fi.rows};
    for (uint32_t l = 0; l < fi.levels; l++) {
        hpfc_level_info lv;
        int st = hpfc_file_get_level(s->f, l, &lv);
        if (st)
            return st;
        if (lv.cell_w <= 0 || lv.cell_h <= 0)
            return HPFC_E_CORRUPT;
        d.cell_w[l] = lv.cell_w, d.cell_h[l] = lv.cell_h;
    }
    /* the window relative to the domain, clamped, in root cells (row 0 north) */
    int64_t c0 = win->x0 <= fi.x0 ? 0 : (win->x0 - fi.x0) / d.cell_w[0];
    int64_t c1 = win->x1 <= fi.x0 ? 0 : (win->x1 - fi.x0) / d.cell_w[0];
    int64_t r0 = win->y1 >= fi.y0 + fi.height ? 0 : (fi.y0 + fi.height - win->y1) / d.cell_h[0];
    int64_t r1 = win->y0 >= fi.y0 + fi.height ? 0 : (fi.y0 + fi.height - win->y0) / d.cell_h[0];
    int st = HPFC_OK;
    for (int64_t j = r0 > 0 ? r0 - 1 : 0; j <= r1 && j < fi.root_rows && !st; j++)
        for (int64_t i = c0 > 0 ? c0 - 1 : 0; i <= c1 && i < fi.root_cols && !st; i++) {
            hpfc_pixel root;
            rect box;
            int type;
            st = hpfc_pixel_root(s->f, (uint32_t)i, (uint32_t)j, &root);
            if (!st)
                st = hpfc_pixel_bounds(s->f, &root, &box.x0, &box.y0, &box.x1, &box.y1);
            if (!st)
                st = hpfc_pixel_type(s->f, &root, &type);
            if (!st && rect_meets(&box, win))
                st = descend(s, &d, &root, type, NULL, &box);
        }
    return st;
}

/* ---- the answer -------------------------------------------------------------------- */

/* ids[0 .. n) (each below bound) ascending. */
static int sort_ids(shapes_window *w, uint64_t *ids, size_t n, uint64_t bound)
{
    if (array_grow((void **)&w->sort_tmp, &w->cap_sort_tmp, n + 1, sizeof *w->sort_tmp))
        return HPFC_E_NOMEM;
    id_sort(ids, w->sort_tmp, n, bound);
    return HPFC_OK;
}

/* Edges' and faces' flags (faces after edges: a face is inside when all
 * the edges around it are). */
static int flag_edges_faces(hpfc_shapes *s, const rect *win)
{
    shapes_window *w = s->window;
    if (array_grow((void **)&w->edge_inside, &w->cap_edge_inside, w->nedge + 1, 1) ||
        array_grow((void **)&w->face_inside, &w->cap_face_inside, w->nface + 1, 1))
        return HPFC_E_NOMEM;
    int st = HPFC_OK, inside = 1;
    for (size_t k = 0; k < w->nedge && !st; k++) {
        uint64_t e = w->edge[k];
        if (w->edge_border[e] == w->gen)
            st = edge_inside(s, e, win, &inside);
        else
            inside = 1;
        w->edge_inside[k] = w->edge_in[e] = (uint8_t)inside;
    }
    for (size_t k = 0; k < w->nface && !st; k++) {
        uint64_t f = w->face[k], a = 0, b = 0;
        inside = f != 0;
        if (w->face_border[f] == w->gen && inside)
            st = shapes_row(s, FACE_EDGES, f, &a, &b);
        for (uint64_t j = a; j < b && inside && !st; j++)
            st = edge_inside(s, shapes_item(s, FACE_EDGES, j), win, &inside);
        w->face_inside[k] = w->face_in[f] = (uint8_t)inside;
    }
    return st;
}

static int add_feature(hpfc_shapes *s, hpfc_id feature)
{
    shapes_window *w = s->window;
    if (feature >= s->features)
        return HPFC_E_CORRUPT;
    if (w->feature_mark[feature] == w->gen)
        return HPFC_OK;
    w->feature_mark[feature] = w->gen;
    if (w->nface + w->nedge + w->nfeature >= s->max_items)
        return HPFC_E_OVER_LIMIT;
    if (array_grow((void **)&w->feature, &w->cap_feature, w->nfeature + 1, sizeof *w->feature))
        return HPFC_E_NOMEM;
    w->feature[w->nfeature++] = feature;
    return HPFC_OK;
}

/* The features of the faces and edges found; inside when all their faces
 * and edges are. */
static int find_features(hpfc_shapes *s)
{
    shapes_window *w = s->window;
    int st = HPFC_OK;
    uint32_t n;
    hpfc_id ft;
    for (size_t k = 0; k < w->nface && s->have_features && !st; k++) {
        if ((st = hpfc_face_feature_count(s->f, w->face[k], &n)))
            break;
        for (uint32_t j = 0; j < n && !st; j++)
            if (!(st = hpfc_face_feature_id(s->f, w->face[k], j, &ft)))
                st = add_feature(s, ft);
    }
    for (size_t k = 0; k < w->nedge && s->have_edge_features && !st; k++) {
        if ((st = hpfc_edge_feature_count(s->f, w->edge[k], &n)))
            break;
        for (uint32_t j = 0; j < n && !st; j++)
            if (!(st = hpfc_edge_feature_id(s->f, w->edge[k], j, &ft)))
                st = add_feature(s, ft);
    }
    if (st)
        return st;
    if ((st = sort_ids(w, w->feature, w->nfeature, s->features)))
        return st;
    if (array_grow((void **)&w->feature_inside, &w->cap_feature_inside, w->nfeature + 1, 1))
        return HPFC_E_NOMEM;
    for (size_t k = 0; k < w->nfeature && !st; k++) {
        hpfc_id ftr = w->feature[k];
        int inside = 1;
        uint64_t a = 0, b = 0;
        if (shapes_has_rows(s, FEATURE_FACES))
            st = shapes_row(s, FEATURE_FACES, ftr, &a, &b);
        for (uint64_t j = a; j < b && inside && !st; j++) {
            uint32_t f = shapes_item(s, FEATURE_FACES, j);
            inside = w->face_mark[f] == w->gen && w->face_in[f];
        }
        a = b = 0;
        if (shapes_has_rows(s, FEATURE_EDGES) && inside && !st)
            st = shapes_row(s, FEATURE_EDGES, ftr, &a, &b);
        for (uint64_t j = a; j < b && inside && !st; j++) {
            uint32_t e = shapes_item(s, FEATURE_EDGES, j);
            inside = w->edge_mark[e] == w->gen && w->edge_in[e];
        }
        w->feature_inside[k] = (uint8_t)inside;
    }
    return st;
}

int hpfc_shapes_window(hpfc_shapes *s, int64_t x0, int64_t y0, int64_t x1, int64_t y1,
                       unsigned what, hpfc_window_hits *out)
{
    if (!s || !out || x0 > x1 || y0 > y1 ||
        (what & ~(unsigned)(HPFC_WINDOW_FACES | HPFC_WINDOW_EDGES | HPFC_WINDOW_FEATURES)))
        return HPFC_E_ARG;
    if ((what & HPFC_WINDOW_FEATURES) && !s->have_features && !s->have_edge_features)
        return HPFC_E_NO_SECTION;
    memset(out, 0, sizeof *out);
    rect win = {x0, y0, x1, y1};
    int st = window_begin(s);
    if (!st)
        st = descend_roots(s, &win);
    /* the unbounded face holds everything outside the domain */
    hpfc_file_info fi;
    hpfc_file_get_info(s->f, &fi);
    if (!st && (x0 < fi.x0 || y0 < fi.y0 || x1 >= fi.x0 + fi.width || y1 >= fi.y0 + fi.height))
        st = add_face(s, 0, 1);
    shapes_window *w = s->window;
    if (!st)
        st = sort_ids(w, w->face, w->nface, s->faces);
    if (!st)
        st = sort_ids(w, w->edge, w->nedge, s->edges);
    if (!st)
        st = flag_edges_faces(s, &win);
    if (!st && (what & HPFC_WINDOW_FEATURES))
        st = find_features(s);
    if (st)
        return st;
    if (what & HPFC_WINDOW_FACES)
        out->face_count = w->nface, out->face = w->face, out->face_inside = w->face_inside;
    if (what & HPFC_WINDOW_EDGES)
        out->edge_count = w->nedge, out->edge = w->edge, out->edge_inside = w->edge_inside;
    if (what & HPFC_WINDOW_FEATURES)
        out->feature_count = w->nfeature, out->feature = w->feature,
        out->feature_inside = w->feature_inside;
    return HPFC_OK;
}
