/*
 * Exact point location (spec/hpfc-format.md §6.7): the face holding a
 * lattice point, or the faces around it when it lies on an edge or a
 * vertex, from the located leaf alone.
 *
 * The leaf's word, its LABL record (an edge id per crossing, a face per
 * stretch of its boundary) and GEOM (each crossing's segment, the edges'
 * points) give the pieces of edges inside the leaf as segments. A point on
 * one of them is on the boundary. Otherwise a ray leaves the point towards
 * the east at the height y + delta (delta > 0 infinitesimal, below every
 * eps term of §3.5): the first segment it meets says the face by the side
 * the point is on; if it meets none, it leaves the leaf through road E,
 * between two crossings, on a stretch whose face LABL stores. Every
 * decision is an integer comparison (geom.h), so ties fall as the
 * perturbation rule orders them.
 */
#include "locate_point.h"

#include <stdlib.h>
#include <string.h>

#include "file.h"
#include "geometry.h"
#include "reader.h"
#include "arrays.h"

void locx_scratch_free(locx_scratch *s)
{
    free(s->sym);
    labels_leaf_free(&s->labels);
    free(s->cr);
    free(s->around);
    free(s->segs);
    memset(s, 0, sizeof *s);
}

/* Room for n crossings in every per-crossing array: both grow from the
 * one capacity they share, so to the same one. */
static int reserve_crossings(locx_scratch *s, size_t n)
{
    size_t cr_cap = s->crossing_cap, around_cap = s->crossing_cap;
    int st = array_grow((void **)&s->cr, &cr_cap, n, sizeof *s->cr);
    if (!st)
        st = array_grow((void **)&s->around, &around_cap, n, sizeof *s->around);
    if (!st)
        s->crossing_cap = cr_cap;
    return st;
}

/* ---- the leaf ---------------------------------------------------------------------- */

/* What one location knows of its file and leaf. */
typedef struct leaf_ctx {
    const hpfc_file *f;
    const hpfc_pixel *leaf;
    int64_t dx0, dy0;          /* the domain's south-west corner (absolute) */
    int64_t x0, y0, x1, y1;    /* the leaf, relative to it */
    lpoint p;                  /* the point, relative */
    uint32_t n;                /* crossings */
    locx_scratch *s;
} leaf_ctx;

/* A point GEOM gave as (x, y) with status st, relative to the domain.
 * An id the leaf names but GEOM does not have (HPFC_E_ARG) is corrupt, and
 * so is a point outside [0, 2^41]^2 (the predicates' products must fit
 * 128 bits). */
static int relative_point(const leaf_ctx *c, int st, int64_t x, int64_t y, lpoint *out)
{
    if (st)
        return st == HPFC_E_ARG ? HPFC_E_CORRUPT : st;
    if (x < c->dx0 || y < c->dy0 || x - c->dx0 > HPFC_LATTICE_MAX || y - c->dy0 > HPFC_LATTICE_MAX)
        return HPFC_E_CORRUPT;
    *out = (lpoint){x - c->dx0, y - c->dy0};
    return HPFC_OK;
}

/* Point k of an edge, relative to the domain. */
static int edge_point(const leaf_ctx *c, uint64_t edge, uint64_t k, lpoint *out)
{
    int64_t x = 0, y = 0;
    int st = hpfc_geometry_edge_point(c->f, edge, k, &x, &y);
    return relative_point(c, st, x, y, out);
}

/* Vertex `vertex`, relative; the crossings before k (the last 32) that
 * read it already give it without a GEOM read: a junction's edges share
 * their vertex, and a straight edge's segment ends are its vertices. */
static int vertex_point(const leaf_ctx *c, uint64_t vertex, uint32_t k, lpoint *out)
{
    const locx_crossing *cr = c->s->cr;
    for (uint32_t j = k > 32 ? k - 32 : 0; j < k; j++) {
        if (cr[j].u == vertex && cr[j].segment == 0) {
            *out = cr[j].a;
            return HPFC_OK;
        }
        if (cr[j].v == vertex && cr[j].segment + 2 == cr[j].count) {
            *out = cr[j].b;
            return HPFC_OK;
        }
    }
    int64_t x = 0, y = 0;
    int st = hpfc_geometry_vertex(c->f, vertex, &x, &y);
    return relative_point(c, st, x, y, out);
}

/* Point i of crossing k's edge: a vertex through vertex_point, a shape
 * point from GEOM. */
static int crossing_point(const leaf_ctx *c, uint32_t k, uint64_t i, lpoint *out)
{
    const locx_crossing *x = &c->s->cr[k];
    if (i == 0)
        return vertex_point(c, x->u, k, out);
    if (i + 1 == x->count)
        return vertex_point(c, x->v, k, out);
    return edge_point(c, c->s->labels.edge[k], i, out);
}

static bool in_leaf(const leaf_ctx *c, lpoint q)
{
    return point_in_cell(q, c->x0, c->y0, c->x1, c->y1);
}

/* Every crossing's segment at once (hpfc_geometry_crossing_segment's
 * answer, without finding the leaf's rank and word once per crossing):
 * GEOM's per-leaf crossing count and per-crossing segment columns, or
 * segment 0 throughout when no edge has shape points. */
static int leaf_segments(const leaf_ctx *c)
{
    const geom_view *g = &c->f->geom;
    if (!g->points) {
        for (uint32_t k = 0; k < c->n; k++)
            c->s->cr[k].segment = 0;
        return HPFC_OK;
    }
    uint64_t rank, start, end = g->crossings;
    int st = labels_leaf_rank(c->f, c->leaf, &rank);
    uint64_t gl = st ? 0 : g->first_leaf[c->leaf->depth] + rank;
    if (!st && gl >= g->leaves)
        st = HPFC_E_CORRUPT;
    if (!st)
        st = geom_column_get(&g->col[GEOM_LCROSS], gl, &start);
    if (!st && gl + 1 < g->leaves)
        st = geom_column_get(&g->col[GEOM_LCROSS], gl + 1, &end);
    /* the leaf's crossings are exactly its word's */
    if (!st && (start > end || end > g->crossings || end - start != c->n))
        st = HPFC_E_CORRUPT;
    for (uint32_t k = 0; k < c->n && !st; k++)
        st = geom_column_get(&g->col[GEOM_CSEG], start + k, &c->s->cr[k].segment);
    return st;
}

/* Per crossing: its symbol, road, segment and whether that segment, run
 * from u to v, leaves the leaf there (GEOM must agree with the word). */
static int load_crossings(leaf_ctx *c, const char *sym, size_t len)
{
    locx_scratch *s = c->s;
    uint32_t k = 0, road = 0;
    for (size_t i = 0; i < len; i++) {
        if (sym[i] == '+') {
            road++;
            continue;
        }
        if (k >= c->n || road > HPFC_SOUTH)
            return HPFC_E_CORRUPT;
        s->cr[k].kind = sym[i];
        s->cr[k++].road = road;
    }
    int st = leaf_segments(c);
    if (st)
        return st;
    for (k = 0; k < c->n; k++) {
        locx_crossing *x = &s->cr[k];
        uint64_t edge = s->labels.edge[k];
        st = hpfc_geometry_edge(c->f, edge, &x->u, &x->v, &x->count);
        if (st)
            return st == HPFC_E_ARG ? HPFC_E_CORRUPT : st;
        if (x->count < 2 || x->segment > x->count - 2)
            return HPFC_E_CORRUPT;
        bool entering;
        if ((st = crossing_point(c, k, x->segment, &x->a)) ||
            (st = crossing_point(c, k, x->segment + 1, &x->b)))
            return st;
        if (!cross_road(x->a, x->b, (int)x->road, c->x0, c->y0, c->x1, c->y1, &x->pos,
                        &entering))
            return HPFC_E_CORRUPT; /* the segment does not cross that road */
        x->leaving = !entering;
    }
    return HPFC_OK;
}

/* ---- the pieces as segments ------------------------------------------------------------- */

/* Point i of `edge`, taken from the segments of crossings x and y (the
 * piece's) when it is an end of one, else read from GEOM. */
static int run_point(const leaf_ctx *c, uint64_t edge, uint64_t i, const locx_crossing *x,
                     const locx_crossing *y, lpoint *out)
{
    for (int k = 0; k < 2; k++, x = y) {
        if (i == x->segment) {
            *out = x->a;
            return HPFC_OK;
        }
        if (i == x->segment + 1) {
            *out = x->b;
            return HPFC_OK;
        }
    }
    return edge_point(c, edge, i, out);
}

/* Appends segments first .. last of `edge` (points first .. last + 1),
 * tagged with crossing k of their piece (and its partner crossing j, k
 * itself for a junction's). Their inner points lie in the leaf; so does
 * point `vertex_point` (a vertex of the piece, or UINT64_MAX for none),
 * which is vertex `vertex`. */
static int add_run(leaf_ctx *c, uint64_t edge, uint64_t first, uint64_t last, uint32_t k,
                   uint32_t j, uint64_t vertex_point, uint64_t vertex)
{
    locx_scratch *s = c->s;
    const locx_crossing *x = &s->cr[k], *y = &s->cr[j];
    lpoint a, b;
    int st = run_point(c, edge, first, x, y, &a);
    if (!st && vertex_point == first && !in_leaf(c, a))
        st = HPFC_E_CORRUPT;
    for (uint64_t i = first; !st && i <= last; i++) {
        if ((st = run_point(c, edge, i + 1, x, y, &b)))
            break;
        if ((i < last || vertex_point == i + 1) && !in_leaf(c, b))
            return HPFC_E_CORRUPT; /* GEOM leaves the leaf where the word does not */
        /* Pieces are disjoint, so a leaf has at most one segment per
         * crossing plus one per shape point: a damaged file whose pieces
         * claim the same long run again and again stops here, not after
         * crossings x points steps. */
        if (s->seg_count > s->points + c->n)
            return HPFC_E_CORRUPT;
        if ((st = array_grow((void **)&s->segs, &s->seg_cap, s->seg_count + 1, sizeof *s->segs)))
            break;
        s->segs[s->seg_count++] = (locx_segment){
            .a = a,
            .b = b,
            .edge = edge,
            .index = i,
            .crossing = k,
            .vertex = vertex,
            .vertex_end = vertex_point == i ? 0 : vertex_point == i + 1 ? 1 : -1};
        a = b;
    }
    return st;
}

/* A junction's piece (vertex to crossing k) or a stabbing's (crossing k,
 * a '[', to its ']'), as the run of segments of its edge. */
static int add_piece(leaf_ctx *c, uint32_t k)
{
    locx_scratch *s = c->s;
    const locx_crossing *x = &s->cr[k];
    uint64_t edge = s->labels.edge[k], seg = x->segment;
    if (x->kind == '[') {
        uint32_t b = s->labels.rec.word.parts.pred[k];
        if (b >= c->n || s->cr[b].kind != ']' || s->labels.edge[b] != edge ||
            s->cr[b].leaving == x->leaving)
            return HPFC_E_CORRUPT;
        /* run u -> v, the piece enters at its first crossing */
        uint64_t first = x->leaving ? s->cr[b].segment : seg;
        uint64_t last = x->leaving ? seg : s->cr[b].segment;
        if (first > last)
            return HPFC_E_CORRUPT;
        return add_run(c, edge, first, last, k, b, UINT64_MAX, UINT64_MAX);
    }
    /* a junction crossing: the vertex is u if the edge leaves here going
     * u -> v, else v */
    if (x->leaving)
        return add_run(c, edge, 0, seg, k, k, 0, x->u);
    return add_run(c, edge, seg, x->count - 2, k, k, x->count - 1, x->v);
}

static int collect_segments(leaf_ctx *c)
{
    c->s->seg_count = 0;
    int st = HPFC_OK;
    for (uint32_t k = 0; k < c->n && !st; k++)
        if (c->s->cr[k].kind != ']')
            st = add_piece(c, k);
    return st;
}

/* ---- answers ----------------------------------------------------------------------------- */

/* The faces on the left and on the right of a piece run u -> v: those of
 * the stretches before and after its crossing k, the right one after k
 * when the edge leaves the leaf there (§6.5.1: the face on the right of
 * out_k is stretch k + 1's). */
static int stretch_face(const leaf_ctx *c, uint32_t t, uint64_t *face)
{
    return labels_leaf_face(c->f, &c->s->labels, t, face);
}

static int piece_sides(const leaf_ctx *c, uint32_t k, uint64_t *left, uint64_t *right)
{
    uint64_t before, after;
    int st = stretch_face(c, k, &before);
    if (!st)
        st = stretch_face(c, (k + 1) % c->n, &after);
    if (st)
        return st;
    *left = c->s->cr[k].leaving ? before : after;
    *right = c->s->cr[k].leaving ? after : before;
    return HPFC_OK;
}

static bool on_segment(lpoint a, lpoint b, lpoint p)
{
    if (orient(a, b, p))
        return false;
    int64_t lx = a.x < b.x ? a.x : b.x, hx = a.x < b.x ? b.x : a.x;
    int64_t ly = a.y < b.y ? a.y : b.y, hy = a.y < b.y ? b.y : a.y;
    return lx <= p.x && p.x <= hx && ly <= p.y && p.y <= hy;
}

/* The faces around a boundary point on segment sg: around its vertex,
 * those after each crossing of the vertex's component (the sectors
 * between its edges); on an edge, its two sides. */
static int boundary_faces(const leaf_ctx *c, const locx_segment *sg, lpoint p, int *on_vertex,
                          size_t *count)
{
    locx_scratch *s = c->s;
    lpoint end = sg->vertex_end == 0 ? sg->a : sg->b;
    *on_vertex = sg->vertex_end >= 0 && end.x == p.x && end.y == p.y;
    size_t m = 0;
    int st = HPFC_OK;
    if (*on_vertex) {
        const uint32_t *pred = s->labels.rec.word.parts.pred;
        uint32_t j = sg->crossing;
        do {
            st = stretch_face(c, (j + 1) % c->n, &s->around[m++]);
            j = pred[j];
        } while (!st && j != sg->crossing && m < c->n);
    } else {
        st = piece_sides(c, sg->crossing, &s->around[0], &s->around[1]);
        m = 2;
    }
    *count = scratch_sort_unique(s->around, m);
    return st;
}

/* Where the ray y = p.y + delta meets segment sg east of p and west of the
 * leaf's east road (x < x1): x = num/den + delta * dx/den. */
typedef struct ray_hit {
    i128 num;
    int64_t den, dx;
} ray_hit;

static bool ray_meets(const locx_segment *sg, lpoint p, int64_t x1, ray_hit *h)
{
    bool a_above = sg->a.y > p.y, b_above = sg->b.y > p.y;
    if (a_above == b_above)
        return false;
    lpoint lo = a_above ? sg->b : sg->a, hi = a_above ? sg->a : sg->b;
    int64_t dy = hi.y - lo.y, dx = hi.x - lo.x;
    i128 num = (i128)lo.x * dy + (i128)dx * (p.y - lo.y);
    /* num/dy == p.x would put p on the segment: answered before */
    if (num <= (i128)p.x * dy || num >= (i128)x1 * dy)
        return false;
    *h = (ray_hit){num, dy, dx};
    return true;
}

/* Does hit a come before hit b going east? At one x (a shared end point on
 * the ray's line) the smaller dx/dy is met first, delta above the line. */
static bool hit_before(const ray_hit *a, const ray_hit *b)
{
    int c = cmp128(a->num * b->den, b->num * a->den);
    if (c)
        return c < 0;
    return (i128)a->dx * b->den < (i128)b->dx * a->den;
}

/* The stretch through which the ray leaves the leaf: road E's crossings
 * come north to south in word order; those above y + delta come first. */
static uint32_t exit_stretch(const leaf_ctx *c)
{
    const locx_scratch *s = c->s;
    uint32_t k = 0;
    while (k < c->n && s->cr[k].road < HPFC_EAST)
        k++;
    for (; k < c->n && s->cr[k].road == HPFC_EAST; k++) {
        const line_pos *pos = &s->cr[k].pos;
        int cmp = cmp128(pos->num, (i128)c->p.y * pos->den);
        bool above = cmp > 0 || (cmp == 0 && pos->tilt < 0);
        if (!above)
            break;
    }
    return k % c->n;
}

/* The point's faces in the stabbed leaf, into s->around; *count of them. */
static int locate_in_leaf(leaf_ctx *c, locx_answer *out, size_t *count)
{
    locx_scratch *s = c->s;
    int st;
    for (size_t i = 0; i < s->seg_count; i++) {
        const locx_segment *sg = &s->segs[i];
        if (!on_segment(sg->a, sg->b, c->p))
            continue;
        out->on_boundary = 1;
        st = boundary_faces(c, sg, c->p, &out->on_vertex, count);
        if (out->on_vertex)
            out->vertex = sg->vertex;
        else
            out->edge = sg->edge;
        return st;
    }
    const locx_segment *best = NULL;
    ray_hit hit, h;
    for (size_t i = 0; i < s->seg_count; i++)
        if (ray_meets(&s->segs[i], c->p, c->x1, &h) && (!best || hit_before(&h, &hit))) {
            best = &s->segs[i];
            hit = h;
        }
    *count = 1;
    if (!best) {
        return stretch_face(c, exit_stretch(c), &s->around[0]);
    }
    uint64_t left, right;
    if ((st = piece_sides(c, best->crossing, &left, &right)))
        return st;
    s->around[0] = orient(best->a, best->b, c->p) > 0 ? left : right;
    return HPFC_OK;
}

/* ---- entry points -------------------------------------------------------------------------- */

/* The point's leaf loaded into c and s: its bounds, word, LABL record,
 * crossings and (stabbed) segments. The descent starts below the levels
 * it shares with the last leaf when that one is whole. */
static int load_leaf(leaf_ctx *c, int64_t x, int64_t y)
{
    locx_scratch *s = c->s;
    hpfc_pixel *leaf = &s->leaf;
    int st = reader_locate_near(c->f, s->have_leaf ? leaf : NULL, x, y, leaf);
    s->have_leaf = 0;
    size_t len = 0;
    int64_t bx0, by0, bx1, by1;
    if (!st)
        st = hpfc_pixel_bounds(c->f, leaf, &bx0, &by0, &bx1, &by1);
    if (!st && !s->sym)
        st = array_grow((void **)&s->sym, &s->sym_cap, 64, 1);
    if (!st) /* most words fit the buffer: one decode */
        st = hpfc_pixel_word(c->f, leaf, s->sym, s->sym_cap, &len);
    if (st == HPFC_E_BUFFER_SMALL) {
        st = array_grow((void **)&s->sym, &s->sym_cap, len, 1);
        if (!st)
            st = hpfc_pixel_word(c->f, leaf, s->sym, s->sym_cap, &len);
    }
    if (!st)
        st = labels_leaf_load(c->f, leaf, s->sym, len, &s->labels);
    if (st)
        return st;
    c->leaf = leaf;
    c->x0 = bx0 - c->dx0, c->y0 = by0 - c->dy0, c->x1 = bx1 - c->dx0, c->y1 = by1 - c->dy0;
    c->n = s->labels.rec.word.n;
    if ((st = reserve_crossings(s, c->n ? c->n : 1)))
        return st;
    s->seg_count = 0;
    if (c->n && ((st = load_crossings(c, s->sym, len)) || (st = collect_segments(c))))
        return st;
    s->leaf_x0 = bx0, s->leaf_y0 = by0, s->leaf_x1 = bx1, s->leaf_y1 = by1;
    s->have_leaf = 1;
    return HPFC_OK;
}

/* The leaf of the last answer holds (x, y): c takes it as it is. */
static bool reuse_leaf(leaf_ctx *c, int64_t x, int64_t y)
{
    const locx_scratch *s = c->s;
    if (!s->have_leaf || x < s->leaf_x0 || x >= s->leaf_x1 || y < s->leaf_y0 || y >= s->leaf_y1)
        return false;
    c->leaf = &s->leaf;
    c->x0 = s->leaf_x0 - c->dx0, c->y0 = s->leaf_y0 - c->dy0;
    c->x1 = s->leaf_x1 - c->dx0, c->y1 = s->leaf_y1 - c->dy0;
    c->n = s->labels.rec.word.n;
    return true;
}

int locx_locate(const hpfc_file *f, int64_t x, int64_t y, locx_scratch *s, locx_answer *out,
                size_t *count)
{
    if (!f || !s || !out || !count)
        return HPFC_E_ARG;
    *count = 0;
    if (s->file != f) { /* once per file and scratch */
        s->have_leaf = 0;
        if (!file_has_exact_geometry(f))
            return HPFC_E_NO_SECTION;
        hpfc_file_info info;
        hpfc_file_get_info(f, &info);
        s->file = f, s->dx0 = info.x0, s->dy0 = info.y0, s->points = f->geom.points;
    }
    int st;
    leaf_ctx c = {.f = f, .dx0 = s->dx0, .dy0 = s->dy0, .s = s};
    locx_answer a = {.vertex = UINT64_MAX, .edge = UINT64_MAX};
    size_t n = 1;
    if (!reuse_leaf(&c, x, y) && (st = load_leaf(&c, x, y)))
        return st;
    c.p = (lpoint){x - c.dx0, y - c.dy0};
    if (c.n == 0)
        st = stretch_face(&c, 0, &s->around[0]); /* a private leaf lies in one face */
    else
        st = locate_in_leaf(&c, &a, &n);
    if (st) {
        s->have_leaf = 0;
        return st;
    }
    *out = a;
    *count = n;
    return HPFC_OK;
}

int hpfc_locate_point(const hpfc_file *file, int64_t x, int64_t y, hpfc_point_location *out,
                      uint64_t *faces, size_t cap, size_t *count)
{
    if (!out || !count)
        return HPFC_E_ARG;
    locx_scratch s = {0};
    locx_answer a;
    int st = locx_locate(file, x, y, &s, &a, count);
    if (!st) {
        out->leaf = s.leaf;
        out->on_boundary = a.on_boundary, out->on_vertex = a.on_vertex;
        out->vertex = a.vertex, out->edge = a.edge;
        if (faces && cap < *count)
            st = HPFC_E_BUFFER_SMALL;
        else if (faces)
            memcpy(faces, s.around, *count * sizeof *faces);
    }
    locx_scratch_free(&s);
    return st;
}
