/*
 * Witness points of faces (face_witness.h).
 *
 * The tree says, for every crossing of every word leaf, which segment of
 * which input edge makes it (kept in a leaf_crossings once the tree is
 * gone); the file says which faces lie before and after the crossing along
 * the leaf's boundary. Between them, the faces on both sides of the
 * crossing's segment get a place each.
 */
#include "face_witness.h"

#include <stdlib.h>
#include <string.h>


__extension__ typedef __int128 i128;

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

/* A word leaf of the file: its bounds, its word, and where its crossings
 * start in a leaf_crossings. */
typedef struct leaf_view {
    hpfc_pixel px;
    int64_t x0, y0, x1, y1;
    char *word;
    size_t word_len, word_cap;
    uint64_t first;
} leaf_view;

/* The direction in which a leaf's boundary runs clockwise along each road
 * (W northward, N eastward, E southward, S westward), roads in word order. */
static const int road_dir[4][2] = {{0, 1}, {1, 0}, {0, -1}, {-1, 0}};

/* Witness for the face on one side of segment p -> q: its midpoint, moved
 * towards the side where the turn p -> q -> (moved point) has sign `side`. */
static face_witness segment_witness(const int64_t p[2], const int64_t q[2], int side)
{
    int64_t dx = q[0] - p[0], dy = q[1] - p[1];
    /* (-dy, dx) points to the left of p -> q */
    return (face_witness){p[0] + q[0], p[1] + q[1], side > 0 ? -dy : dy, side > 0 ? dx : -dx,
                          FACE_WITNESS_SEGMENT};
}

static int offer(face_witness *w, uint64_t face, uint64_t faces, face_witness c)
{
    if (face >= faces)
        return HPFC_E_CORRUPT;
    if (w[face].kind < c.kind)
        w[face] = c;
    return HPFC_OK;
}

/* The witnesses a word leaf offers; *used: its crossings. After crossing
 * k, clockwise, the leaf's boundary runs in the face of dart k; it leaves
 * the crossing on the side of the segment that the road's direction points
 * to, and the face before the crossing lies on the other side. */
static int leaf_witnesses(const hpfc_graph *g, const leaf_crossings *lc, const leaf_view *v,
                          const hpfc_faces *faces, face_witness *w, uint32_t *used)
{
    uint64_t nf = hpfc_faces_face_count(faces), face;
    uint32_t n = 0;
    for (size_t s = 0; s < v->word_len; s++)
        n += v->word[s] != '+';
    *used = n;
    if (n == 0) {
        int st = hpfc_faces_pixel_face(faces, &v->px, &face);
        return st ? st
                  : offer(w, face, nf,
                          (face_witness){v->x0 + v->x1, v->y0 + v->y1, 0, 0, FACE_WITNESS_LEAF});
    }
    if (v->first + n > lc->count)
        return HPFC_E_CORRUPT;
    int road = 0;
    for (size_t s = 0, k = 0; s < v->word_len; s++) {
        if (v->word[s] == '+') {
            road++;
            continue;
        }
        if (road > 3)
            return HPFC_E_CORRUPT;
        uint64_t c = v->first + k;
        int64_t p[2], q[2];
        segment_points(g, lc->pairs[2 * c], lc->pairs[2 * c + 1], p, q);
        i128 turn = (i128)(q[0] - p[0]) * road_dir[road][1] - (i128)(q[1] - p[1]) * road_dir[road][0];
        if (turn == 0)
            return HPFC_E_CORRUPT; /* a segment along the road does not cross it */
        int side = turn > 0 ? 1 : -1;
        uint64_t before, after;
        hpfc_dart d_after = {v->px, (uint32_t)k}, d_before = {v->px, (uint32_t)((k + n - 1) % n)};
        int st = hpfc_faces_dart_face(faces, &d_after, &after);
        if (!st)
            st = hpfc_faces_dart_face(faces, &d_before, &before);
        if (!st)
            st = offer(w, after, nf, segment_witness(p, q, side));
        if (!st)
            st = offer(w, before, nf, segment_witness(p, q, -side));
        if (st)
            return st;
        k++;
    }
    return HPFC_OK;
}

int face_witness_ray_crosses(const face_witness *w, int64_t ux, int64_t uy, int64_t vx,
                             int64_t vy)
{
    /* the witness is (x2 + e nx, y2 + e ny) / 2 for an infinitesimal e > 0;
     * a point is above it when its y is greater */
    i128 x2 = w->x2, y2 = w->y2, Ux = 2 * (i128)ux, Uy = 2 * (i128)uy, Vx = 2 * (i128)vx,
         Vy = 2 * (i128)vy;
    int u_above = Uy > y2 || (Uy == y2 && w->ny < 0);
    int v_above = Vy > y2 || (Vy == y2 && w->ny < 0);
    if (u_above == v_above)
        return 0;
    if (u_above) { /* U below, V above */
        i128 t = Ux;
        Ux = Vx, Vx = t;
        t = Uy;
        Uy = Vy, Vy = t;
    }
    /* the ray crosses when the witness lies left of the upward U -> V */
    i128 o0 = (Vx - Ux) * (y2 - Uy) - (Vy - Uy) * (x2 - Ux);
    i128 o1 = (Vx - Ux) * w->ny - (Vy - Uy) * w->nx;
    i128 o = o0 ? o0 : o1;
    return o == 0 ? -1 : o > 0;
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

/* The tree's images along the last leaf's path, so that the next leaf,
 * which shares the start of its path (leaves come depth first), is found
 * from where the two paths part instead of from the root. */
typedef struct tree_path {
    uint32_t valid; /* image[0 .. valid) are known for the path in i[], j[] */
    size_t image[HPFC_MAX_LEVELS];
    uint32_t i[HPFC_MAX_LEVELS], j[HPFC_MAX_LEVELS];
} tree_path;

/* The tree's pixel at the file pixel's path: the child images of the
 * refined pixels along it, level by level. */
static int tree_pixel_of(const hpfc_tree *tree, const hpfc_pixel *px, tree_path *tp_cache,
                         hpfc_tree_pixel *tp)
{
    if (px->depth >= HPFC_MAX_LEVELS)
        return HPFC_E_CORRUPT;
    /* image[l] depends on the path above level l only */
    uint32_t l = 0;
    while (l < tp_cache->valid && l <= px->depth &&
           (l == 0 || (tp_cache->i[l - 1] == px->path[l - 1].i &&
                       tp_cache->j[l - 1] == px->path[l - 1].j)))
        l++;
    l = l ? l - 1 : 0;
    size_t image = l ? tp_cache->image[l] : 0;
    for (;; l++) {
        tp_cache->image[l] = image;
        tp_cache->i[l] = px->path[l].i, tp_cache->j[l] = px->path[l].j;
        tp_cache->valid = l + 1;
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
    tree_path path = {0};
    int st = reserve_crossings(tree, out);
    if (!st)
        st = hpfc_leaf_first(file, &v.px);
    for (; !st; st = hpfc_leaf_next(file, &v.px)) {
        hpfc_tree_pixel tp;
        if ((st = view_leaf(file, &v)) || (st = tree_pixel_of(tree, &v.px, &path, &tp)))
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
    for (uint64_t f = 0; f < hpfc_faces_face_count(faces); f++)
        w[f] = (face_witness){0, 0, 0, 0, FACE_WITNESS_NONE};
    leaf_view v = {0};
    int st = hpfc_leaf_first(file, &v.px);
    for (; !st; st = hpfc_leaf_next(file, &v.px)) {
        if ((st = view_leaf(file, &v)))
            break;
        uint32_t used = 0;
        if ((st = leaf_witnesses(graph, lc, &v, faces, w, &used)))
            break;
        v.first += used;
    }
    free(v.word);
    if (st == HPFC_E_NO_PIXEL)
        st = v.first == lc->count ? HPFC_OK : HPFC_E_CORRUPT;
    return st;
}
