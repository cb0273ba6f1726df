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

/* Starts walking edge e from its end u (at_v 0) or v (1). */
static void walk_from_end(edge_walk *w, uint32_t e, int at_v)
{
    size_t k;
    w->edge = e;
    hpfc_graph_edge(w->g, e, &w->u, &w->v, &w->xy, &k);
    w->k = k;
    w->dir = at_v ? -1 : 1;
    w->at = at_v ? (uint32_t)(k + 1) : 0;
}

/* ---- the map's vertices by their point ------------------------------------------ */

/* The vertices in a hash table of their points, and the edge ends at each
 * vertex, so that a part is matched to the map from one of its points that
 * is a vertex: along an edge the part can only go on or turn back, and at
 * a vertex it takes the edge end whose first segment it runs along. */
typedef struct vertex_index {
    const hpfc_graph *g;
    uint32_t *slot; /* vertex + 1, 0 for none */
    size_t mask;
    uint64_t *end_start; /* vertex v's edge ends: end[end_start[v] .. end_start[v + 1]) */
    uint64_t *end;       /* edge << 1 | (1 at the edge's v end) */
} vertex_index;

/* A point's slot: lattice points share their low bits (a grid's step, a
 * snapping), so every bit of both coordinates is mixed in (splitmix64's
 * finaliser). */
static size_t point_hash(int64_t x, int64_t y)
{
    uint64_t z = (uint64_t)x * 0x9e3779b97f4a7c15u ^ (uint64_t)y;
    z = (z ^ z >> 30) * 0xbf58476d1ce4e5b9u;
    z = (z ^ z >> 27) * 0x94d049bb133111ebu;
    return (size_t)(z ^ z >> 31);
}

static uint32_t vertex_find(const vertex_index *vi, int64_t x, int64_t y)
{
    for (size_t i = point_hash(x, y) & vi->mask;; i = (i + 1) & vi->mask) {
        uint32_t s = vi->slot[i];
        if (s == 0)
            return UINT32_MAX;
        int64_t vx, vy;
        hpfc_graph_vertex(vi->g, s - 1, &vx, &vy);
        if (vx == x && vy == y)
            return s - 1;
    }
}

static int vertex_index_make(vertex_index *vi, const hpfc_graph *g)
{
    memset(vi, 0, sizeof *vi);
    vi->g = g;
    size_t nv = hpfc_graph_vertex_count(g), ne = hpfc_graph_edge_count(g), slots = 16;
    if (nv >= UINT32_MAX)
        return HPFC_E_LIMIT;
    while (slots < 2 * nv)
        slots *= 2;
    vi->mask = slots - 1;
    vi->slot = calloc(slots, sizeof *vi->slot);
    vi->end_start = calloc(nv + 1, sizeof *vi->end_start);
    vi->end = malloc((ne ? 2 * ne : 1) * sizeof *vi->end);
    if (!vi->slot || !vi->end_start || !vi->end)
        return HPFC_E_NOMEM;
    for (size_t v = 0; v < nv; v++) {
        int64_t x, y;
        hpfc_graph_vertex(g, v, &x, &y);
        size_t i = point_hash(x, y) & vi->mask;
        while (vi->slot[i])
            i = (i + 1) & vi->mask;
        vi->slot[i] = (uint32_t)v + 1;
    }
    for (size_t e = 0; e < ne; e++) {
        uint32_t u, v;
        const int64_t *xy;
        size_t k;
        hpfc_graph_edge(g, e, &u, &v, &xy, &k);
        vi->end_start[u + 1]++;
        vi->end_start[v + 1]++;
    }
    for (size_t v = 0; v < nv; v++)
        vi->end_start[v + 1] += vi->end_start[v];
    for (size_t e = 0; e < ne; e++) { /* end_start[v] runs ahead, then is put back */
        uint32_t u, v;
        const int64_t *xy;
        size_t k;
        hpfc_graph_edge(g, e, &u, &v, &xy, &k);
        vi->end[vi->end_start[u]++] = (uint64_t)e << 1;
        vi->end[vi->end_start[v]++] = (uint64_t)e << 1 | 1;
    }
    for (size_t v = nv; v > 0; v--)
        vi->end_start[v] = vi->end_start[v - 1];
    vi->end_start[0] = 0;
    return HPFC_OK;
}

static void vertex_index_free(vertex_index *vi)
{
    free(vi->slot);
    free(vi->end_start);
    free(vi->end);
    memset(vi, 0, sizeof *vi);
}

/* ---- parts against edges ------------------------------------------------------- */

/* A part's run over the map: the edge it runs along, its last point, and
 * that point's vertex when the run starts there (UINT32_MAX otherwise). */
typedef struct part_run {
    const vertex_index *vi;
    const map_seg *segs; /* the map's segments, for a part through no vertex; else NULL */
    size_t n_segs;
    edge_walk w;
    int64_t px, py;
    uint32_t vertex;
    uint32_t feature;
    int ring;
    u64_list *uses, *toggles;
} part_run;

static void run_start(part_run *pr, int64_t x, int64_t y, uint32_t vertex)
{
    pr->w.edge = UINT32_MAX;
    pr->px = x, pr->py = y;
    pr->vertex = vertex;
}

/* The first segment from vertex `vertex` toward q: the walk set on its
 * edge and its position, else -1. */
static int64_t branch_at(part_run *pr, uint32_t vertex, int64_t qx, int64_t qy)
{
    const vertex_index *vi = pr->vi;
    for (uint64_t i = vi->end_start[vertex]; i < vi->end_start[vertex + 1]; i++) {
        walk_from_end(&pr->w, (uint32_t)(vi->end[i] >> 1), (int)(vi->end[i] & 1));
        int64_t pos = walk_next(&pr->w, qx, qy);
        if (pos >= 0)
            return pos;
    }
    return -1;
}

/* Where p-q lies when it is not the next segment of the edge being walked:
 * back along the edge from a point inside it (a point of degree 2 lies on
 * no other edge), or another edge from a vertex; -1 when p-q is not a
 * segment of the map. */
static int64_t turn(part_run *pr, int64_t qx, int64_t qy)
{
    edge_walk *w = &pr->w;
    if (w->edge != UINT32_MAX) {
        if (w->at > 0 && w->at <= w->k) {
            w->dir = -w->dir;
            return walk_next(w, qx, qy);
        }
        return branch_at(pr, w->at == 0 ? w->u : w->v, qx, qy);
    }
    if (pr->vertex != UINT32_MAX)
        return branch_at(pr, pr->vertex, qx, qy);
    if (!pr->segs)
        return -1;
    int64_t ax = pr->px, ay = pr->py, bx = qx, by = qy;
    order_ends(&ax, &ay, &bx, &by);
    const map_seg *m = find_seg(pr->segs, pr->n_segs, ax, ay, bx, by);
    if (!m)
        return -1;
    walk_start(w, m, pr->px, pr->py);
    return m->pos;
}

/* The part's next point q: the segment from the last point to q gives the
 * part's feature to its edge (once per run along one edge) and, on the
 * edge's representative segment, toggles a ring. */
static int run_to(part_run *pr, int64_t qx, int64_t qy)
{
    if (qx == pr->px && qy == pr->py)
        return HPFC_OK;
    int64_t pos = walk_next(&pr->w, qx, qy);
    if (pos < 0 && (pos = turn(pr, qx, qy)) < 0)
        return HPFC_E_CORRUPT; /* a part leaves the map */
    pr->w.at = (uint32_t)(pr->w.at + pr->w.dir);
    pr->px = qx, pr->py = qy;
    uint64_t key = (uint64_t)pr->w.edge << 32 | pr->feature;
    if ((pr->uses->n == 0 || pr->uses->v[pr->uses->n - 1] != key) && push_u64(pr->uses, key))
        return HPFC_E_NOMEM;
    if (pr->ring && pos == 0)
        return push_u64(pr->toggles, key);
    return HPFC_OK;
}

typedef struct point_list {
    int64_t *xy;
    size_t n, cap;
} point_list;

/* The cursor's next point, kept at the end of pts; NULL when out of memory. */
static const int64_t *keep_next(point_list *pts, gis_part_cursor *c)
{
    if (!array_grow((void **)&pts->xy, &pts->cap, 2 * (pts->n + 1), sizeof *pts->xy))
        return NULL;
    int64_t *p = pts->xy + 2 * pts->n++;
    gis_part_next(c, &p[0], &p[1]);
    return p;
}

/* A part in pts through no vertex of the map (a ring lying inside one edge,
 * along another feature's border; or a line not starting at one, which the
 * reader never records): its first segment sought among all the map's
 * segments, which are sorted the first time. */
static int run_without_vertex(part_run *pr, const point_list *pts, map_seg **segs, size_t *n_segs)
{
    if (!*segs && !(*segs = map_segments(pr->vi->g, n_segs)))
        return HPFC_E_NOMEM;
    pr->segs = *segs, pr->n_segs = *n_segs;
    run_start(pr, pts->xy[0], pts->xy[1], UINT32_MAX);
    int st = HPFC_OK;
    for (size_t j = 1; j < pts->n && !st; j++)
        st = run_to(pr, pts->xy[2 * j], pts->xy[2 * j + 1]);
    if (!st && pr->ring)
        st = run_to(pr, pts->xy[0], pts->xy[1]);
    pr->segs = NULL;
    return st;
}

/* Part r, started at a point that is a vertex: a line's first (its ends
 * are vertices of the map, gis_input.c), a ring's first such point, whose
 * points before it are kept in `pts` and run over last, so each of the
 * ring's segments is run over once. */
static int match_part(part_run *pr, const gis_features *fs, size_t r, point_list *pts,
                      map_seg **segs, size_t *n_segs)
{
    gis_part_cursor c = gis_features_part_open(fs, r, &pr->feature, &pr->ring);
    uint32_t vertex = UINT32_MAX;
    pts->n = 0;
    while (c.left && vertex == UINT32_MAX && (pr->ring || pts->n == 0)) {
        const int64_t *p = keep_next(pts, &c);
        if (!p)
            return HPFC_E_NOMEM;
        vertex = vertex_find(pr->vi, p[0], p[1]);
    }
    if (pts->n == 0)
        return HPFC_OK;
    if (vertex == UINT32_MAX) {
        while (c.left) /* the rest of a line */
            if (!keep_next(pts, &c))
                return HPFC_E_NOMEM;
        return run_without_vertex(pr, pts, segs, n_segs);
    }
    size_t i = pts->n - 1;
    run_start(pr, pts->xy[2 * i], pts->xy[2 * i + 1], vertex);
    int st = HPFC_OK;
    while (c.left && !st) {
        int64_t x, y;
        gis_part_next(&c, &x, &y);
        st = run_to(pr, x, y);
    }
    /* a ring's closing segment, then its points before the vertex */
    for (size_t j = 0; pr->ring && j <= i && !st; j++)
        st = run_to(pr, pts->xy[2 * j], pts->xy[2 * j + 1]);
    return st;
}

static int match_parts(const gis_features *fs, const hpfc_graph *g, u64_list *uses,
                       u64_list *toggles)
{
    vertex_index vi;
    int st = vertex_index_make(&vi, g);
    part_run pr = {.vi = &vi, .w = {.g = g, .edge = UINT32_MAX}, .uses = uses, .toggles = toggles};
    point_list pts = {0};
    map_seg *segs = NULL;
    size_t n_segs = 0, parts = gis_features_part_count(fs);
    for (size_t r = 0; r < parts && !st; r++)
        st = match_part(&pr, fs, r, &pts, &segs, &n_segs);
    free(pts.xy);
    free(segs);
    vertex_index_free(&vi);
    return st;
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
    u64_list uses = {0}, toggles = {0};
    if (!st)
        st = match_parts(fs, graph, &uses, &toggles);
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

