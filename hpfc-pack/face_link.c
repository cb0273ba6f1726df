/*
 * Features of faces and edges from the topology (face_link.h).
 */
#include "face_link.h"

#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "grow.h"
#include "sort.h"

#define NO_FACE UINT32_MAX

/* ---- the map's segments ------------------------------------------------------ */

/* A segment of an edge of the map, ends in lexicographic (x, y) order:
 * segment `pos` of edge `edge` joins its points pos and pos + 1 (point 0
 * is u). Segment 0 is the edge's representative, where the rings' toggles
 * are counted: the parity is the same on every segment of an edge (at a
 * point of degree 2 a path's ends on its two segments add up to an even
 * number), so one segment stands for the edge. */
typedef struct map_seg {
    int64_t ax, ay, bx, by;
    uint32_t edge, pos;
} map_seg;

static int cmp_ends(int64_t ax, int64_t ay, int64_t bx, int64_t by, const map_seg *s)
{
    if (ax != s->ax)
        return ax < s->ax ? -1 : 1;
    if (ay != s->ay)
        return ay < s->ay ? -1 : 1;
    if (bx != s->bx)
        return bx < s->bx ? -1 : 1;
    return (by > s->by) - (by < s->by);
}

static int cmp_map_seg(const void *a, const void *b)
{
    const map_seg *p = a;
    return cmp_ends(p->ax, p->ay, p->bx, p->by, b);
}

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

/* Puts (px, py)-(qx, qy) in lexicographic order; 0 when the points are one. */
static int order_ends(int64_t *px, int64_t *py, int64_t *qx, int64_t *qy)
{
    if (*px == *qx && *py == *qy)
        return 0;
    if (*px > *qx || (*px == *qx && *py > *qy)) {
        int64_t tx = *px, ty = *py;
        *px = *qx, *py = *qy, *qx = tx, *qy = ty;
    }
    return 1;
}

/* Every segment of every edge of g, sorted; *n of them. */
static map_seg *map_segments(const hpfc_graph *g, size_t *n)
{
    size_t edges = hpfc_graph_edge_count(g), total = 0;
    for (size_t e = 0; e < edges; e++) {
        uint32_t u, v;
        const int64_t *xy;
        size_t k;
        hpfc_graph_edge(g, e, &u, &v, &xy, &k);
        total += k + 1;
    }
    map_seg *s = malloc((total ? total : 1) * sizeof *s);
    if (!s)
        return NULL;
    size_t m = 0;
    for (size_t e = 0; e < edges; e++) {
        uint32_t u, v;
        const int64_t *xy;
        size_t k;
        hpfc_graph_edge(g, e, &u, &v, &xy, &k);
        int64_t px, py, qx, qy;
        hpfc_graph_vertex(g, u, &px, &py);
        for (size_t i = 0; i <= k; i++) {
            if (i < k)
                qx = xy[2 * i], qy = xy[2 * i + 1];
            else
                hpfc_graph_vertex(g, v, &qx, &qy);
            int64_t ax = px, ay = py, bx = qx, by = qy;
            if (order_ends(&ax, &ay, &bx, &by))
                s[m++] = (map_seg){ax, ay, bx, by, (uint32_t)e, (uint32_t)i};
            px = qx, py = qy;
        }
    }
    sort_in_place(s, m, sizeof *s, cmp_map_seg);
    *n = m;
    return s;
}

static const map_seg *find_seg(const map_seg *s, size_t n, int64_t ax, int64_t ay, int64_t bx,
                               int64_t by)
{
    size_t lo = 0, hi = n;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        int c = cmp_ends(ax, ay, bx, by, &s[mid]);
        if (c == 0)
            return &s[mid];
        if (c < 0)
            hi = mid;
        else
            lo = mid + 1;
    }
    return NULL;
}

/* ---- parts against segments ----------------------------------------------------- */

typedef struct u64_list {
    uint64_t *v;
    size_t n, cap;
} u64_list;

static int push_u64(u64_list *l, uint64_t x)
{
    if (!array_grow((void **)&l->v, &l->cap, l->n + 1, sizeof *l->v))
        return HPFC_E_NOMEM;
    l->v[l->n++] = x;
    return HPFC_OK;
}

/* Where a part runs along an edge: point `at` of edge `edge` (0 .. k + 1),
 * going toward higher points (dir 1) or lower (-1); edge UINT32_MAX: none. */
typedef struct edge_walk {
    const hpfc_graph *g;
    uint32_t edge, at;
    int dir;
    uint32_t u, v;
    const int64_t *xy;
    size_t k;
} edge_walk;

static void walk_point(const edge_walk *w, size_t j, int64_t *x, int64_t *y)
{
    if (j == 0)
        hpfc_graph_vertex(w->g, w->u, x, y);
    else if (j == w->k + 1)
        hpfc_graph_vertex(w->g, w->v, x, y);
    else
        *x = w->xy[2 * (j - 1)], *y = w->xy[2 * (j - 1) + 1];
}

/* The part's segment p-q as the next one along the edge being walked: its
 * position, else -1. */
static int64_t walk_next(const edge_walk *w, int64_t qx, int64_t qy)
{
    if (w->edge == UINT32_MAX || (w->dir < 0 && w->at == 0) || (w->dir > 0 && w->at > w->k))
        return -1;
    int64_t x, y;
    size_t next = w->dir > 0 ? w->at + 1 : w->at - 1;
    walk_point(w, next, &x, &y);
    if (x != qx || y != qy)
        return -1;
    return (int64_t)(w->dir > 0 ? w->at : next);
}

/* Starts walking edge m->edge from p (an end of segment m) toward q. */
static void walk_start(edge_walk *w, const map_seg *m, int64_t px, int64_t py)
{
    size_t k;
    w->edge = m->edge;
    hpfc_graph_edge(w->g, m->edge, &w->u, &w->v, &w->xy, &k);
    w->k = k;
    int64_t x, y;
    walk_point(w, m->pos, &x, &y);
    w->dir = x == px && y == py ? 1 : -1;
    w->at = w->dir > 0 ? m->pos : m->pos + 1;
}

/* One segment p-q of a part, which is a segment of the map (the parts were
 * recorded as they lie in the map, gis_features.h): the edge's feature (once
 * per run along one edge) and, on the edge's representative segment, a
 * toggle of a ring. The segment is first sought as the next one of the
 * edge the part was running along (one comparison), and only at the edge's
 * end among all the map's (a binary search a segment cost a cache miss a
 * step, most of the stage on large maps). */
static int match_segment(const map_seg *s, size_t n, edge_walk *w, int64_t px, int64_t py,
                         int64_t qx, int64_t qy, uint32_t feature, int ring, u64_list *uses,
                         u64_list *toggles)
{
    int64_t ax = px, ay = py, bx = qx, by = qy;
    if (!order_ends(&ax, &ay, &bx, &by))
        return HPFC_OK;
    uint32_t edge;
    int64_t pos = walk_next(w, qx, qy);
    if (pos >= 0) {
        edge = w->edge;
        w->at = (uint32_t)(w->at + w->dir);
    } else {
        const map_seg *m = find_seg(s, n, ax, ay, bx, by);
        if (!m)
            return HPFC_E_CORRUPT; /* a part leaves the map */
        walk_start(w, m, px, py);
        w->at = (uint32_t)(w->at + w->dir);
        edge = m->edge, pos = m->pos;
    }
    uint64_t key = (uint64_t)edge << 32 | feature;
    if ((uses->n == 0 || uses->v[uses->n - 1] != key) && push_u64(uses, key))
        return HPFC_E_NOMEM;
    if (ring && pos == 0)
        return push_u64(toggles, key);
    return HPFC_OK;
}

static int match_parts(const gis_features *fs, const hpfc_graph *g, const map_seg *s, size_t n,
                       u64_list *uses, u64_list *toggles)
{
    size_t parts = gis_features_part_count(fs);
    for (size_t r = 0; r < parts; r++) {
        uint32_t feature;
        int ring;
        gis_part_cursor c = gis_features_part_open(fs, r, &feature, &ring);
        int64_t x0, y0, px, py, qx, qy;
        if (!c.left)
            continue;
        gis_part_next(&c, &x0, &y0);
        px = x0, py = y0;
        int st = HPFC_OK;
        edge_walk w = {.g = g, .edge = UINT32_MAX};
        while (c.left && !st) {
            gis_part_next(&c, &qx, &qy);
            st = match_segment(s, n, &w, px, py, qx, qy, feature, ring, uses, toggles);
            px = qx, py = qy;
        }
        if (!st && ring) /* the closing segment */
            st = match_segment(s, n, &w, px, py, x0, y0, feature, ring, uses, toggles);
        if (st)
            return st;
    }
    return HPFC_OK;
}

/* Sorted (edge << 32 | feature) keys as CSR per edge: distinct keys, or
 * with `parity` the keys present an odd number of times. */
static int edge_csr(u64_list *l, uint32_t edges, int parity, uint32_t **start, uint32_t **feat)
{
    sort_in_place(l->v, l->n, sizeof *l->v, cmp_u64);
    *start = calloc((size_t)edges + 1, sizeof **start);
    *feat = malloc((l->n ? l->n : 1) * sizeof **feat);
    if (!*start || !*feat)
        return HPFC_E_NOMEM;
    size_t m = 0;
    for (size_t i = 0; i < l->n;) {
        size_t j = i;
        while (j < l->n && l->v[j] == l->v[i])
            j++;
        if (!parity || (j - i) % 2) {
            (*feat)[m++] = (uint32_t)l->v[i];
            (*start)[(l->v[i] >> 32) + 1]++;
        }
        i = j;
    }
    for (uint32_t e = 0; e < edges; e++)
        (*start)[e + 1] += (*start)[e];
    return HPFC_OK;
}

/* ---- the faces on both sides of each edge --------------------------------------- */

/* Crossing k of a leaf with n separates the stretches k - 1 and k of its
 * boundary (face_witness.h): the faces on the two sides of its edge. */
static int leaf_sides(face_link *fl, const leaf_crossings *lc, const hpfc_faces *faces,
                      const hpfc_pixel *px, uint64_t first, uint32_t n)
{
    for (uint32_t k = 0; k < n; k++) {
        if (first + k >= lc->count)
            return HPFC_E_CORRUPT;
        uint32_t e = lc->pairs[2 * (first + k)];
        if (e >= fl->edges)
            return HPFC_E_CORRUPT;
        if (fl->side_a[e] != NO_FACE)
            continue;
        hpfc_dart before = {*px, (k + n - 1) % n}, after = {*px, k};
        uint64_t fa, fb;
        int st = hpfc_faces_dart_face(faces, &before, &fa);
        if (!st)
            st = hpfc_faces_dart_face(faces, &after, &fb);
        if (st)
            return st;
        if (fa >= fl->faces || fb >= fl->faces)
            return HPFC_E_CORRUPT;
        fl->side_a[e] = (uint32_t)fa, fl->side_b[e] = (uint32_t)fb;
    }
    return HPFC_OK;
}

static int find_sides(face_link *fl, const leaf_crossings *lc, const hpfc_file *file,
                      const hpfc_faces *faces)
{
    hpfc_pixel px;
    char *word = NULL;
    size_t cap = 0, len;
    uint64_t first = 0;
    int st = hpfc_leaf_first(file, &px);
    for (; !st; st = hpfc_leaf_next(file, &px)) {
        if ((st = hpfc_pixel_word(file, &px, NULL, 0, &len)))
            break;
        if (!array_grow((void **)&word, &cap, len + 1, 1)) {
            st = HPFC_E_NOMEM;
            break;
        }
        if ((st = hpfc_pixel_word(file, &px, word, cap, &len)))
            break;
        uint32_t n = 0;
        for (size_t i = 0; i < len; i++)
            n += word[i] != '+';
        if (n && (st = leaf_sides(fl, lc, faces, &px, first, n)))
            break;
        first += n;
    }
    free(word);
    if (st == HPFC_E_NO_PIXEL)
        st = first == lc->count ? HPFC_OK : HPFC_E_CORRUPT;
    return st;
}

/* Adjacency over the edges that separate two faces. */
static int build_adjacency(face_link *fl)
{
    fl->adj_start = calloc(fl->faces + 1, sizeof *fl->adj_start);
    if (!fl->adj_start)
        return HPFC_E_NOMEM;
    for (uint32_t e = 0; e < fl->edges; e++)
        if (fl->side_a[e] != NO_FACE && fl->side_a[e] != fl->side_b[e]) {
            fl->adj_start[fl->side_a[e] + 1]++;
            fl->adj_start[fl->side_b[e] + 1]++;
        }
    for (uint64_t f = 0; f < fl->faces; f++)
        fl->adj_start[f + 1] += fl->adj_start[f];
    uint64_t total = fl->adj_start[fl->faces];
    uint64_t *fill = malloc((fl->faces + 1) * sizeof *fill);
    fl->adj = malloc((total ? total : 1) * sizeof *fl->adj);
    if (!fill || !fl->adj) {
        free(fill);
        return HPFC_E_NOMEM;
    }
    memcpy(fill, fl->adj_start, (fl->faces + 1) * sizeof *fill);
    for (uint32_t e = 0; e < fl->edges; e++)
        if (fl->side_a[e] != NO_FACE && fl->side_a[e] != fl->side_b[e]) {
            fl->adj[fill[fl->side_a[e]]++] = e;
            fl->adj[fill[fl->side_b[e]]++] = e;
        }
    free(fill);
    return HPFC_OK;
}

/* ---- the walk ------------------------------------------------------------------- */

/* Appends the symmetric difference of the sorted sets a[0..na) and
 * b[0..nb) to out (which has room); its length. */
static size_t sym_diff(const uint32_t *a, size_t na, const uint32_t *b, size_t nb, uint32_t *out)
{
    size_t i = 0, j = 0, m = 0;
    while (i < na || j < nb) {
        if (j == nb || (i < na && a[i] < b[j]))
            out[m++] = a[i++];
        else if (i == na || b[j] < a[i])
            out[m++] = b[j++];
        else
            i++, j++;
    }
    return m;
}

/* Face v gets face u's set changed by edge e's toggles. */
static int derive_set(face_link *fl, uint32_t u, uint32_t v, uint32_t e)
{
    size_t nt = fl->toggle_start[e + 1] - fl->toggle_start[e];
    if (!array_grow((void **)&fl->pool, &fl->pool_cap, fl->pool_n + fl->set_len[u] + nt,
                    sizeof *fl->pool))
        return HPFC_E_NOMEM;
    size_t m = sym_diff(fl->pool + fl->set_off[u], fl->set_len[u], fl->toggle + fl->toggle_start[e],
                        nt, fl->pool + fl->pool_n);
    fl->set_off[v] = fl->pool_n;
    fl->set_len[v] = (uint32_t)m;
    fl->pool_n += m;
    return HPFC_OK;
}

/* Breadth-first from the reached face `start` over the edges. */
static int walk_from(face_link *fl, uint32_t start)
{
    size_t head = 0, tail = 0;
    fl->queue[tail++] = start;
    fl->propagated++;
    while (head < tail) {
        uint32_t u = fl->queue[head++];
        for (uint64_t k = fl->adj_start[u]; k < fl->adj_start[u + 1]; k++) {
            uint32_t e = fl->adj[k];
            uint32_t v = fl->side_a[e] == u ? fl->side_b[e] : fl->side_a[e];
            if (fl->reached[v])
                continue;
            int st = derive_set(fl, u, v, e);
            if (st)
                return st;
            fl->reached[v] = 1;
            fl->propagated++;
            fl->queue[tail++] = v;
        }
    }
    return HPFC_OK;
}

/* ---- entry points ----------------------------------------------------------------- */

static int allocate(face_link *fl, uint64_t faces, uint32_t edges)
{
    fl->faces = faces;
    fl->edges = edges;
    size_t nf = faces ? (size_t)faces : 1, ne = edges ? edges : 1;
    fl->set_off = malloc(nf * sizeof *fl->set_off);
    fl->set_len = calloc(nf, sizeof *fl->set_len);
    fl->reached = calloc(nf, 1);
    fl->queue = malloc(nf * sizeof *fl->queue);
    fl->side_a = malloc(ne * sizeof *fl->side_a);
    fl->side_b = malloc(ne * sizeof *fl->side_b);
    fl->pool_cap = 64;
    fl->pool = malloc(fl->pool_cap * sizeof *fl->pool);
    if (!fl->pool || !fl->set_off || !fl->set_len || !fl->reached || !fl->queue ||
        !fl->side_a || !fl->side_b)
        return HPFC_E_NOMEM;
    for (uint32_t e = 0; e < edges; e++)
        fl->side_a[e] = fl->side_b[e] = NO_FACE;
    return HPFC_OK;
}

int face_link_run(face_link *fl, const gis_features *fs, const hpfc_graph *graph,
                  const leaf_crossings *lc, const hpfc_file *file, const hpfc_faces *faces)
{
    memset(fl, 0, sizeof *fl);
    uint64_t nf = hpfc_faces_face_count(faces);
    size_t ne = hpfc_graph_edge_count(graph);
    if (nf == 0 || nf >= UINT32_MAX || ne >= UINT32_MAX)
        return HPFC_E_CORRUPT;
    int st = allocate(fl, nf, (uint32_t)ne);
    size_t n_seg = 0;
    map_seg *segs = st ? NULL : map_segments(graph, &n_seg);
    u64_list uses = {0}, toggles = {0};
    if (!st && !segs)
        st = HPFC_E_NOMEM;
    if (!st)
        st = match_parts(fs, graph, segs, n_seg, &uses, &toggles);
    free(segs);
    if (!st)
        st = edge_csr(&uses, fl->edges, 0, &fl->edge_start, &fl->edge_feature);
    free(uses.v);
    if (!st)
        st = edge_csr(&toggles, fl->edges, 1, &fl->toggle_start, &fl->toggle);
    free(toggles.v);
    if (!st)
        st = find_sides(fl, lc, file, faces);
    if (!st)
        st = build_adjacency(fl);
    if (!st) { /* the unbounded face lies inside no ring */
        fl->set_off[0] = 0;
        fl->set_len[0] = 0;
        fl->reached[0] = 1;
        st = walk_from(fl, 0);
    }
    return st;
}

void face_link_free(face_link *fl)
{
    free(fl->set_off);
    free(fl->set_len);
    free(fl->reached);
    free(fl->pool);
    free(fl->toggle_start);
    free(fl->toggle);
    free(fl->side_a);
    free(fl->side_b);
    free(fl->adj_start);
    free(fl->adj);
    free(fl->edge_start);
    free(fl->edge_feature);
    free(fl->queue);
    memset(fl, 0, sizeof *fl);
}

