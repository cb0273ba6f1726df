/*
 * neighbours.c: which features touch which (hpfc.h, "Topology questions"),
 * from the stored edges and the features on their sides alone.
 *
 * An edge is on the border of the features that cover exactly one of its
 * two faces (FEAT), and of the line features EDGF links to it; call that
 * set B(e). Two features share an edge when both are in some B(e), and a
 * vertex when both are in the union of B over the edges at that vertex:
 * every border passes through a vertex as the end of one of its edges, and
 * a planar map has no other contact (an edge touching another away from a
 * shared end is refused when the map is built). So rook and queen
 * contiguity are sets of pairs read off the edges and the vertices, with
 * no coordinate compared; only the shared length reads the points.
 */
#include <stdlib.h>
#include <string.h>

#include "arrays.h"
#include "shapes.h"

/* One contact found: feature b touches a (or the asked feature) by an
 * edge (edge < edges) or at a vertex (edge == UINT32_MAX). */
typedef struct contact {
    uint32_t a, b;
    uint32_t edge;
} contact;

#define VERTEX_ONLY UINT32_MAX

struct shapes_topo {
    uint64_t *vstart;       /* vertices + 1: the edges at vertex v are */
    uint32_t *vedge;        /* vedge[vstart[v] .. vstart[v + 1]) */
    double *length;         /* per edge, -1 until computed */
    uint32_t *vmark, vgen;  /* vertices seen by one query */
    uint32_t *fset;         /* B(e), B(v) being gathered */
    size_t nfset, cap_fset;
    uint32_t *fmark, fgen;  /* features in fset */
    contact *c;
    size_t nc, cap_c;
    uint32_t *border;
    size_t nborder, cap_border;
    /* the answers */
    hpfc_id *feature, *edge, *b;
    uint8_t *touch;
    double *len;
    size_t *edge_start;
    size_t cap_feature, cap_edge, cap_b, cap_touch, cap_len, cap_edge_start;
};

void shapes_topo_free(shapes_topo *t)
{
    if (!t)
        return;
    free(t->vstart);
    free(t->vedge);
    free(t->length);
    free(t->vmark);
    free(t->fset);
    free(t->fmark);
    free(t->c);
    free(t->border);
    free(t->feature);
    free(t->edge);
    free(t->b);
    free(t->touch);
    free(t->len);
    free(t->edge_start);
    free(t);
}

/* The edges at each vertex (a loop twice at its vertex), once per object. */
static int topo_begin(hpfc_shapes *s)
{
    if (s->topo)
        return HPFC_OK;
    int st = shapes_read_all(s); /* every vertex's edges */
    if (st)
        return st;
    /* made whole or not at all: a query after a failed one finds either
     * none or the whole vertex index */
    shapes_topo *t = calloc(1, sizeof *t);
    if (!t)
        return HPFC_E_NOMEM;
    uint64_t V = s->vertices, E = s->edges;
    t->vstart = calloc(V + 2, sizeof *t->vstart);
    t->vedge = malloc((2 * E + 1) * sizeof *t->vedge);
    t->length = malloc((E + 1) * sizeof *t->length);
    t->vmark = calloc(V + 1, sizeof *t->vmark);
    t->fmark = calloc((size_t)s->features + 1, sizeof *t->fmark);
    uint64_t *fill = malloc((V + 1) * sizeof *fill);
    if (!t->vstart || !t->vedge || !t->length || !t->vmark || !t->fmark || !fill) {
        free(fill);
        shapes_topo_free(t);
        return HPFC_E_NOMEM;
    }
    for (uint64_t e = 0; e < E; e++) {
        t->vstart[s->edge[e].u + 1]++;
        t->vstart[s->edge[e].v + 1]++;
        t->length[e] = -1;
    }
    for (uint64_t v = 0; v < V; v++)
        t->vstart[v + 1] += t->vstart[v];
    memcpy(fill, t->vstart, V * sizeof *fill);
    for (uint64_t e = 0; e < E; e++) {
        t->vedge[fill[s->edge[e].u]++] = (uint32_t)e;
        t->vedge[fill[s->edge[e].v]++] = (uint32_t)e;
    }
    free(fill);
    s->topo = t;
    return HPFC_OK;
}

/* A new feature-set stamp, the set emptied. */
static void fset_clear(shapes_topo *t, uint32_t features)
{
    if (++t->fgen == 0) {
        memset(t->fmark, 0, ((size_t)features + 1) * sizeof *t->fmark);
        t->fgen = 1;
    }
    t->nfset = 0;
}

static int fset_add(shapes_topo *t, hpfc_id g)
{
    if (t->fmark[g] == t->fgen)
        return HPFC_OK;
    if (array_grow((void **)&t->fset, &t->cap_fset, t->nfset + 1, sizeof *t->fset))
        return HPFC_E_NOMEM;
    t->fmark[g] = t->fgen;
    t->fset[t->nfset++] = (uint32_t)g;
    return HPFC_OK;
}

/* Whether feature g is linked to face `face` (FEAT's list of the face). */
static int face_has(const hpfc_shapes *s, uint64_t face, hpfc_id g, int *has)
{
    uint32_t n;
    hpfc_id x;
    *has = 0;
    int st = hpfc_face_feature_count(s->f, face, &n);
    for (uint32_t k = 0; k < n && !st && !*has; k++)
        if (!(st = hpfc_face_feature_id(s->f, face, k, &x)))
            *has = x == g;
    return st;
}

/* Whether feature g has faces into *has: HPFC_E_CORRUPT for a damaged
 * row of SHIX. */
static int has_faces(hpfc_shapes *s, hpfc_id g, int *has)
{
    uint64_t a = 0, b = 0;
    int st = shapes_has_rows(s, FEATURE_FACES) ? shapes_row(s, FEATURE_FACES, g, &a, &b) : HPFC_OK;
    *has = b > a;
    return st;
}

/* Adds B(e) to the set: the features of exactly one of e's faces, the
 * line features of e. */
static int add_edge_border(hpfc_shapes *s, uint64_t e)
{
    shapes_topo *t = s->topo;
    int st = shapes_need_edge(s, e);
    if (!st && s->face_features && s->edge[e].left != s->edge[e].right) {
        for (int side = 0; side < 2 && !st; side++) {
            const shapes_edge *r = &s->edge[e];
            uint64_t face = side ? r->right : r->left, other = side ? r->left : r->right;
            uint32_t n;
            hpfc_id g;
            if ((st = hpfc_face_feature_count(s->f, face, &n)))
                break;
            for (uint32_t k = 0; k < n && !st; k++) {
                int both;
                if ((st = hpfc_face_feature_id(s->f, face, k, &g)))
                    break;
                if (g >= s->features)
                    return HPFC_E_CORRUPT;
                if (!(st = face_has(s, other, g, &both)) && !both)
                    st = fset_add(t, g);
            }
        }
    }
    if (s->have_edge_features && !st) {
        uint32_t n = 0;
        hpfc_id g;
        st = hpfc_edge_feature_count(s->f, e, &n);
        for (uint32_t j = 0; j < n && !st; j++) {
            if ((st = hpfc_edge_feature_id(s->f, e, j, &g)))
                return st;
            int faced;
            if (g >= s->features)
                return HPFC_E_CORRUPT;
            if (!(st = has_faces(s, g, &faced)) && !faced)
                st = fset_add(t, g);
        }
    }
    return st;
}

static int push_contact(shapes_topo *t, uint32_t a, uint32_t b, uint32_t edge)
{
    if (array_grow((void **)&t->c, &t->cap_c, t->nc + 1, sizeof *t->c))
        return HPFC_E_NOMEM;
    t->c[t->nc++] = (contact){a, b, edge};
    return HPFC_OK;
}

static int cmp_contact(const void *pa, const void *pb)
{
    const contact *a = pa, *b = pb;
    if (a->a != b->a)
        return a->a < b->a ? -1 : 1;
    if (a->b != b->b)
        return a->b < b->b ? -1 : 1;
    return (a->edge > b->edge) - (a->edge < b->edge);
}

static int cmp_u32(const void *pa, const void *pb)
{
    uint32_t a = *(const uint32_t *)pa, b = *(const uint32_t *)pb;
    return (a > b) - (a < b);
}

/* Edge e's length in lattice units, segment by segment. */
static int edge_length(hpfc_shapes *s, uint64_t e, double *len)
{
    shapes_topo *t = s->topo;
    int st = shapes_need_edge(s, e);
    if (st)
        return st;
    if (t->length[e] < 0) {
        double sum = 0;
        int64_t px = 0, py = 0, x, y;
        for (uint64_t k = 0; k < shapes_edge_points(s, e); k++) {
            st = hpfc_geometry_edge_point(s->f, e, k, &x, &y);
            if (st)
                return st;
            if (k)
                {
                    double dx = (double)x - (double)px, dy = (double)y - (double)py;
                    sum += shapes_sqrt(dx * dx + dy * dy);
                }
            px = x, py = y;
        }
        t->length[e] = sum;
    }
    *len = t->length[e];
    return HPFC_OK;
}

int shapes_feature_border(hpfc_shapes *s, hpfc_id feature, uint32_t **edges, size_t *n,
                          size_t *cap)
{
    *n = 0;
    int faced, st = has_faces(s, feature, &faced);
    if (st)
        return st;
    if (faced) {
        uint32_t m = shapes_next_mark(s);
        uint64_t a, b;
        shapes_row(s, FEATURE_FACES, feature, &a, &b); /* read by has_faces */
        for (uint64_t k = a; k < b; k++)
            s->face_mark[shapes_item(s, FEATURE_FACES, k)] = m;
        for (uint64_t k = a; k < b; k++) {
            uint32_t face = shapes_item(s, FEATURE_FACES, k);
            uint64_t fa, fb;
            if ((st = shapes_row(s, FACE_EDGES, face, &fa, &fb)))
                return st;
            for (uint64_t j = fa; j < fb; j++) {
                uint32_t e = shapes_item(s, FACE_EDGES, j);
                int in_left = s->face_mark[s->edge[e].left] == m;
                /* once per edge: from its side inside the feature */
                if (shapes_on_border(s, s->face_mark, m, e) &&
                    (in_left ? s->edge[e].left : s->edge[e].right) == face) {
                    if (array_grow((void **)edges, cap, *n + 1, sizeof **edges))
                        return HPFC_E_NOMEM;
                    (*edges)[(*n)++] = e;
                }
            }
        }
        if (*n)
            qsort(*edges, *n, sizeof **edges, cmp_u32);
    } else if (s->have_edge_features) {
        uint64_t a, b;
        if ((st = shapes_row(s, FEATURE_EDGES, feature, &a, &b)))
            return st;
        if (array_grow((void **)edges, cap, (size_t)(b - a) + 1, sizeof **edges))
            return HPFC_E_NOMEM;
        for (uint64_t k = a; k < b; k++)
            (*edges)[(*n)++] = shapes_item(s, FEATURE_EDGES, k);
    }
    return HPFC_OK;
}

/* The contacts of the features of the set with `self` (a = self), or,
 * self UINT32_MAX, of every pair of the set (a < b); by edge e or at a
 * vertex. */
static int set_contacts(shapes_topo *t, uint32_t self, uint32_t edge)
{
    int st = HPFC_OK;
    if (self != UINT32_MAX) {
        for (size_t k = 0; k < t->nfset && !st; k++)
            if (t->fset[k] != self)
                st = push_contact(t, self, t->fset[k], edge);
        return st;
    }
    for (size_t i = 0; i < t->nfset && !st; i++)
        for (size_t j = 0; j < t->nfset && !st; j++)
            if (t->fset[i] < t->fset[j])
                st = push_contact(t, t->fset[i], t->fset[j], edge);
    return st;
}

/* Contacts at vertex v: the union of B over its edges. */
static int vertex_contacts(hpfc_shapes *s, uint64_t v, uint32_t self)
{
    shapes_topo *t = s->topo;
    fset_clear(t, s->features);
    int st = HPFC_OK;
    for (uint64_t k = t->vstart[v]; k < t->vstart[v + 1] && !st; k++)
        st = add_edge_border(s, t->vedge[k]);
    if (!st && (self == UINT32_MAX || t->fmark[self] == t->fgen))
        st = set_contacts(t, self, VERTEX_ONLY);
    return st;
}

/* A new vertex stamp (the stamps cleared when they wrap). */
static void new_vertex_gen(hpfc_shapes *s)
{
    shapes_topo *t = s->topo;
    if (++t->vgen == 0) {
        memset(t->vmark, 0, (s->vertices + 1) * sizeof *t->vmark);
        t->vgen = 1;
    }
}

/* The sorted contacts, merged: one answer per pair, by edge when any
 * contact of the pair is, its edges listed once each. */
static int merge_contacts(hpfc_shapes *s, size_t *pairs, size_t *edges)
{
    shapes_topo *t = s->topo;
    if (t->nc)
        qsort(t->c, t->nc, sizeof *t->c, cmp_contact);
    size_t np = 0, ne = 0;
    for (size_t k = 0; k < t->nc; k++) {
        if (k && t->c[k].a == t->c[k - 1].a && t->c[k].b == t->c[k - 1].b) {
            if (t->c[k].edge != VERTEX_ONLY && t->c[k].edge != t->c[k - 1].edge)
                ne++;
            continue;
        }
        np++;
        ne += t->c[k].edge != VERTEX_ONLY;
    }
    if (array_grow((void **)&t->feature, &t->cap_feature, np + 1, sizeof *t->feature) ||
        array_grow((void **)&t->b, &t->cap_b, np + 1, sizeof *t->b) ||
        array_grow((void **)&t->touch, &t->cap_touch, np + 1, sizeof *t->touch) ||
        array_grow((void **)&t->len, &t->cap_len, np + 1, sizeof *t->len) ||
        array_grow((void **)&t->edge_start, &t->cap_edge_start, np + 1, sizeof *t->edge_start) ||
        array_grow((void **)&t->edge, &t->cap_edge, ne + 1, sizeof *t->edge))
        return HPFC_E_NOMEM;
    np = ne = 0;
    for (size_t k = 0; k < t->nc; k++) {
        const contact *c = &t->c[k];
        int same = k && c->a == t->c[k - 1].a && c->b == t->c[k - 1].b;
        if (!same) {
            t->feature[np] = c->a;
            t->b[np] = c->b;
            t->touch[np] = HPFC_TOUCH_VERTEX;
            t->len[np] = 0;
            t->edge_start[np] = ne;
            np++;
        }
        if (c->edge == VERTEX_ONLY || (same && c->edge == t->c[k - 1].edge))
            continue;
        double len;
        int st = edge_length(s, c->edge, &len);
        if (st)
            return st;
        t->touch[np - 1] = HPFC_TOUCH_EDGE;
        t->len[np - 1] += len;
        t->edge[ne++] = c->edge;
    }
    t->edge_start[np] = ne;
    *pairs = np;
    *edges = ne;
    return HPFC_OK;
}

int hpfc_shapes_feature_neighbours(hpfc_shapes *s, hpfc_id feature, hpfc_neighbours *out)
{
    if (!s || !out)
        return HPFC_E_ARG;
    if (!s->have_features && !s->have_edge_features)
        return HPFC_E_NO_SECTION;
    if (feature >= s->features)
        return HPFC_E_ARG;
    memset(out, 0, sizeof *out);
    int st = topo_begin(s);
    if (st)
        return st;
    shapes_topo *t = s->topo;
    t->nc = 0;
    uint32_t self = (uint32_t)feature;
    if ((st = shapes_feature_border(s, feature, &t->border, &t->nborder, &t->cap_border)))
        return st;
    new_vertex_gen(s);
    for (size_t k = 0; k < t->nborder && !st; k++) {
        uint32_t e = t->border[k];
        fset_clear(t, s->features);
        st = add_edge_border(s, e);
        if (!st)
            st = set_contacts(t, self, e);
        uint32_t ends[2] = {s->edge[e].u, s->edge[e].v};
        for (int j = 0; j < 2 && !st; j++) {
            if (t->vmark[ends[j]] == t->vgen)
                continue;
            t->vmark[ends[j]] = t->vgen;
            st = vertex_contacts(s, ends[j], self);
        }
    }
    size_t np, ne;
    if (!st)
        st = merge_contacts(s, &np, &ne);
    if (st)
        return st;
    *out = (hpfc_neighbours){.count = np,
                             .feature = t->b,
                             .touch = t->touch,
                             .length = t->len,
                             .edge_start = t->edge_start,
                             .edge = t->edge};
    return HPFC_OK;
}

int hpfc_shapes_adjacency(hpfc_shapes *s, unsigned touch, hpfc_adjacency *out)
{
    if (!s || !out || !(touch & HPFC_TOUCH_EDGE) ||
        (touch & ~(unsigned)(HPFC_TOUCH_EDGE | HPFC_TOUCH_VERTEX)))
        return HPFC_E_ARG;
    if (!s->have_features && !s->have_edge_features)
        return HPFC_E_NO_SECTION;
    memset(out, 0, sizeof *out);
    int st = topo_begin(s);
    if (st)
        return st;
    shapes_topo *t = s->topo;
    t->nc = 0;
    for (uint64_t e = 0; e < s->edges && !st; e++) {
        fset_clear(t, s->features);
        st = add_edge_border(s, e);
        if (!st)
            st = set_contacts(t, UINT32_MAX, (uint32_t)e);
    }
    for (uint64_t v = 0; (touch & HPFC_TOUCH_VERTEX) && v < s->vertices && !st; v++)
        st = vertex_contacts(s, v, UINT32_MAX);
    size_t np, ne;
    if (!st)
        st = merge_contacts(s, &np, &ne);
    if (st)
        return st;
    *out = (hpfc_adjacency){
        .count = np, .a = t->feature, .b = t->b, .touch = t->touch, .length = t->len};
    return HPFC_OK;
}
