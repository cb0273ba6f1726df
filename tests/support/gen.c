/*
 * gen.c: deterministic generators of valid planar test graphs (see gen.h).
 *
 * Determinism across machines rests on three rules: the only randomness is
 * our own xoshiro256** stream; every geometric decision is an exact integer
 * predicate; and every ordering is fully specified (qsort only ever sees
 * distinct keys, hash tables are only used for membership).
 */
#include <inttypes.h>
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "gen.h"

__extension__ typedef __int128 i128;
__extension__ typedef unsigned __int128 u128;

#define NONE UINT32_MAX

/* Largest point count the Delaunay generators accept: triangle and point
 * indices are uint32_t, and the triangle pool holds about 2n entries. */
#define GEN_MAX_POINTS ((size_t)1 << 28)

/* ------------------------------------------------------------------------
 * PRNG
 * ------------------------------------------------------------------------ */

static uint64_t splitmix64(uint64_t *x)
{
    uint64_t z = (*x += UINT64_C(0x9e3779b97f4a7c15));
    z = (z ^ (z >> 30)) * UINT64_C(0xbf58476d1ce4e5b9);
    z = (z ^ (z >> 27)) * UINT64_C(0x94d049bb133111eb);
    return z ^ (z >> 31);
}

void gen_rng_seed(gen_rng *rng, uint64_t seed)
{
    /* splitmix64 spreads any seed (even 0) over the whole xoshiro state,
     * which must not be all zero. */
    for (int i = 0; i < 4; i++)
        rng->s[i] = splitmix64(&seed);
}

static inline uint64_t rotl64(uint64_t x, int k)
{
    return (x << k) | (x >> (64 - k));
}

uint64_t gen_rng_next(gen_rng *rng)
{
    uint64_t *s = rng->s;
    uint64_t result = rotl64(s[1] * 5, 7) * 9;
    uint64_t t = s[1] << 17;
    s[2] ^= s[0];
    s[3] ^= s[1];
    s[1] ^= s[2];
    s[0] ^= s[3];
    s[2] ^= t;
    s[3] = rotl64(s[3], 45);
    return result;
}

uint64_t gen_rng_below(gen_rng *rng, uint64_t bound)
{
    /* Reject the incomplete top block so every residue is equally likely;
     * `limit` is the largest multiple of bound that fits. */
    uint64_t limit = UINT64_MAX - UINT64_MAX % bound;
    uint64_t x;
    do
        x = gen_rng_next(rng);
    while (x >= limit);
    return x % bound;
}

/* The removal stream is derived from the seed, separate from the point
 * stream, so that gen_delaunay_triangulation(seed) sees the same points as
 * gen_delaunay(seed). */
static uint64_t removal_seed(uint64_t seed)
{
    return seed ^ UINT64_C(0x6a09e667f3bcc909);
}

/* ------------------------------------------------------------------------
 * Exact predicates. With coordinates in [0, 2^21) differences are below 2^21
 * in magnitude: orient2d is below 2^44 (int64 suffices) and incircle below
 * 3 * 2^43 * 2^44 < 2^89 (needs __int128).
 * ------------------------------------------------------------------------ */

/* > 0 when a, b, c turn counter-clockwise, 0 when collinear. */
static inline int64_t orient(const int64_t *a, const int64_t *b, const int64_t *c)
{
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

/* > 0 when d is strictly inside the circle through the counter-clockwise
 * triangle a, b, c; 0 when on it. */
static inline i128 incircle(const int64_t *a, const int64_t *b, const int64_t *c,
                            const int64_t *d)
{
    int64_t adx = a[0] - d[0], ady = a[1] - d[1];
    int64_t bdx = b[0] - d[0], bdy = b[1] - d[1];
    int64_t cdx = c[0] - d[0], cdy = c[1] - d[1];
    i128 alift = (i128)(adx * adx + ady * ady);
    i128 blift = (i128)(bdx * bdx + bdy * bdy);
    i128 clift = (i128)(cdx * cdx + cdy * cdy);
    return alift * (bdx * cdy - cdx * bdy) + blift * (cdx * ady - adx * cdy) +
           clift * (adx * bdy - bdx * ady);
}

/* Whether p lies strictly between a and b, given that the three are
 * collinear. */
static inline bool strictly_between(const int64_t *a, const int64_t *b, const int64_t *p)
{
    return (p[0] - a[0]) * (b[0] - a[0]) + (p[1] - a[1]) * (b[1] - a[1]) > 0 &&
           (p[0] - b[0]) * (a[0] - b[0]) + (p[1] - b[1]) * (a[1] - b[1]) > 0;
}

/* ------------------------------------------------------------------------
 * Random distinct points
 * ------------------------------------------------------------------------ */

/* Draws n distinct points of [1, coord_max-1]^2 into xy. A point already
 * drawn is redrawn; an open-addressing set of packed (x, y) keys detects
 * that. The set only answers membership, so its layout never shows. */
static int random_points(gen_rng *rng, size_t n, int64_t coord_max, int64_t *xy)
{
    size_t cap = 16;
    while (cap < 2 * n)
        cap *= 2;
    int bits = 0;
    while (((size_t)1 << bits) < cap)
        bits++;
    uint64_t *set = calloc(cap, sizeof *set);
    if (!set)
        return HPFC_E_NOMEM;
    for (size_t i = 0; i < n;) {
        int64_t x = 1 + (int64_t)gen_rng_below(rng, (uint64_t)coord_max - 1);
        int64_t y = 1 + (int64_t)gen_rng_below(rng, (uint64_t)coord_max - 1);
        uint64_t key = (((uint64_t)x << 21) | (uint64_t)y) + 1; /* never 0 */
        size_t h = (size_t)((key * UINT64_C(0x9e3779b97f4a7c15)) >> (64 - bits));
        while (set[h] && set[h] != key)
            h = (h + 1) & (cap - 1);
        if (set[h])
            continue; /* duplicate: draw again */
        set[h] = key;
        xy[2 * i] = x;
        xy[2 * i + 1] = y;
        i++;
    }
    free(set);
    return HPFC_OK;
}

/* ------------------------------------------------------------------------
 * Hilbert order: inserting points along a space-filling curve keeps each
 * point next to the previous one, so the walk from the last triangle is
 * O(1) steps and the whole triangulation runs in about O(n log n).
 * ------------------------------------------------------------------------ */

/* Position of (x, y), both in [0, 2^21), along the Hilbert curve of order 21.
 * A bijection, so distinct points get distinct keys. */
static uint64_t hilbert_key(uint64_t x, uint64_t y)
{
    const uint64_t n = (uint64_t)1 << 21;
    uint64_t d = 0;
    for (uint64_t s = n / 2; s > 0; s /= 2) {
        uint64_t rx = (x & s) != 0, ry = (y & s) != 0;
        d += s * s * ((3 * rx) ^ ry);
        if (ry == 0) {
            if (rx == 1) {
                x = n - 1 - x;
                y = n - 1 - y;
            }
            uint64_t t = x;
            x = y;
            y = t;
        }
    }
    return d;
}

typedef struct keyed {
    uint64_t key;
    uint32_t index;
} keyed;

static int cmp_keyed(const void *pa, const void *pb)
{
    const keyed *a = pa, *b = pb;
    return (a->key > b->key) - (a->key < b->key);
}

/* The point indices 0..n-1 sorted along the Hilbert curve. */
static uint32_t *hilbert_order(const int64_t *xy, size_t n)
{
    keyed *k = malloc((n ? n : 1) * sizeof *k);
    uint32_t *order = malloc((n ? n : 1) * sizeof *order);
    if (!k || !order) {
        free(k);
        free(order);
        return NULL;
    }
    for (size_t i = 0; i < n; i++) {
        k[i].key = hilbert_key((uint64_t)xy[2 * i], (uint64_t)xy[2 * i + 1]);
        k[i].index = (uint32_t)i;
    }
    qsort(k, n, sizeof *k, cmp_keyed); /* keys are distinct: order is fixed */
    for (size_t i = 0; i < n; i++)
        order[i] = k[i].index;
    free(k);
    return order;
}

/* ------------------------------------------------------------------------
 * Bowyer-Watson with ghost triangles.
 *
 * A ghost vertex G (index npoints) closes the triangulation over the convex
 * hull: each hull edge a -> b (exterior on its left) carries a ghost triangle
 * (a, b, G), stored with G last. Vertices are counter-clockwise; n[i] is the
 * neighbour across the edge opposite v[i]. Following Shewchuk, the
 * "circumcircle" of a ghost triangle is the open half-plane left of a -> b
 * plus the open segment ab. With that convention the triangles in conflict
 * with a new point (whose open circumdisk contains it) form a region
 * star-shaped from the point, and the point lies in its interior, even for
 * collinear or cocircular input: re-triangulating the region's boundary
 * towards the point keeps a Delaunay triangulation of all the points.
 * ------------------------------------------------------------------------ */

typedef struct dt_tri {
    uint32_t v[3];
    uint32_t n[3];
} dt_tri;

typedef struct dt_edge {
    uint32_t a, b;    /* boundary edge of the cavity, counter-clockwise */
    uint32_t out;     /* the triangle outside the cavity across it */
    uint32_t slot;    /* index of this edge in `out` */
    uint32_t id;      /* the new triangle (a, b, p) */
} dt_edge;

typedef struct dt {
    const int64_t *xy;
    uint32_t ghost;        /* index of G: npoints */
    dt_tri *t;
    uint32_t *mark;        /* stamp of the last insertion that tested t */
    uint8_t *conf;         /* that test's result */
    size_t nt, cap;
    uint32_t free_head;    /* dead triangles, chained through n[0] */
    uint32_t stamp;
    uint32_t last;         /* a live real triangle: where walks start */
    uint64_t walk_state;   /* xorshift for the walk's edge order */
    uint32_t *cav;
    size_t ncav, cap_cav;
    dt_edge *bnd;
    size_t nbnd, cap_bnd;
    uint32_t *start_of;    /* per vertex: new triangle whose edge starts there */
    uint32_t *end_of;      /* per vertex: new triangle whose edge ends there */
} dt;

static inline const int64_t *dt_pt(const dt *d, uint32_t i)
{
    return d->xy + 2 * (size_t)i;
}

static inline bool dt_is_ghost(const dt *d, uint32_t t)
{
    return d->t[t].v[2] == d->ghost;
}

/* Grows *p (of *cap elements of size elem) to hold at least need. */
static int grow(void **p, size_t *cap, size_t need, size_t elem)
{
    if (need <= *cap)
        return HPFC_OK;
    size_t ncap = *cap ? *cap : 16;
    while (ncap < need)
        ncap *= 2;
    void *np = realloc(*p, ncap * elem);
    if (!np)
        return HPFC_E_NOMEM;
    *p = np;
    *cap = ncap;
    return HPFC_OK;
}

/* A triangle slot: a dead one if any, else a fresh one. */
static int dt_alloc(dt *d, uint32_t *out)
{
    if (d->free_head != NONE) {
        *out = d->free_head;
        d->free_head = d->t[*out].n[0];
        return HPFC_OK;
    }
    if (d->nt == d->cap) {
        size_t ncap = d->cap * 2;
        dt_tri *nt = realloc(d->t, ncap * sizeof *nt);
        if (!nt)
            return HPFC_E_NOMEM;
        d->t = nt;
        uint32_t *nm = realloc(d->mark, ncap * sizeof *nm);
        if (!nm)
            return HPFC_E_NOMEM;
        d->mark = nm;
        uint8_t *nc = realloc(d->conf, ncap * sizeof *nc);
        if (!nc)
            return HPFC_E_NOMEM;
        d->conf = nc;
        memset(d->mark + d->cap, 0, (ncap - d->cap) * sizeof *nm);
        d->cap = ncap;
    }
    *out = (uint32_t)d->nt++;
    return HPFC_OK;
}

static void dt_release(dt *d, uint32_t t)
{
    d->t[t].v[0] = d->t[t].v[1] = d->t[t].v[2] = NONE;
    d->t[t].n[0] = d->free_head;
    d->free_head = t;
}

/* Whether p lies in the (open) circumcircle of triangle t. */
static bool dt_conflict(const dt *d, uint32_t t, const int64_t *p)
{
    const dt_tri *T = &d->t[t];
    const int64_t *a = dt_pt(d, T->v[0]), *b = dt_pt(d, T->v[1]);
    if (T->v[2] == d->ghost) {
        int64_t o = orient(a, b, p);
        if (o != 0)
            return o > 0;
        return strictly_between(a, b, p);
    }
    return incircle(a, b, dt_pt(d, T->v[2]), p) > 0;
}

/* A triangle in conflict with p: a visibility walk from the last triangle
 * crosses any edge that has p strictly on its far side. It ends in the real
 * triangle containing p (p inside or on its boundary, hence strictly inside
 * its circumdisk) or, leaving the hull, in a ghost triangle whose open
 * half-plane holds p. Edges are tried in a pseudo-random order from a fixed
 * xorshift so that even degenerate configurations cannot cycle. */
static uint32_t dt_locate(dt *d, const int64_t *p)
{
    uint32_t t = d->last;
    for (;;) {
        const dt_tri *T = &d->t[t];
        d->walk_state ^= d->walk_state << 13;
        d->walk_state ^= d->walk_state >> 7;
        d->walk_state ^= d->walk_state << 17;
        unsigned r = (unsigned)(d->walk_state % 3);
        uint32_t next = NONE;
        for (unsigned k = 0; k < 3; k++) {
            unsigned i = (r + k) % 3;
            if (orient(dt_pt(d, T->v[(i + 1) % 3]), dt_pt(d, T->v[(i + 2) % 3]), p) < 0) {
                next = T->n[i];
                break;
            }
        }
        if (next == NONE || dt_is_ghost(d, next))
            return next == NONE ? t : next;
        t = next;
    }
}

/* Collects the conflict region of p, starting at its conflict triangle t0,
 * into d->cav and its boundary edges into d->bnd. Each triangle's conflict
 * status is computed once per insertion (mark/conf). */
static int dt_cavity(dt *d, uint32_t t0, const int64_t *p)
{
    d->stamp++;
    d->ncav = d->nbnd = 0;
    d->mark[t0] = d->stamp;
    d->conf[t0] = 1;
    d->cav[d->ncav++] = t0;
    for (size_t k = 0; k < d->ncav; k++) {
        uint32_t t = d->cav[k];
        for (unsigned i = 0; i < 3; i++) {
            uint32_t nb = d->t[t].n[i];
            if (d->mark[nb] != d->stamp) {
                d->mark[nb] = d->stamp;
                d->conf[nb] = dt_conflict(d, nb, p);
                if (d->conf[nb]) {
                    if (grow((void **)&d->cav, &d->cap_cav, d->ncav + 1, sizeof *d->cav))
                        return HPFC_E_NOMEM;
                    d->cav[d->ncav++] = nb;
                }
            }
            if (d->conf[nb])
                continue;
            if (grow((void **)&d->bnd, &d->cap_bnd, d->nbnd + 1, sizeof *d->bnd))
                return HPFC_E_NOMEM;
            dt_edge *e = &d->bnd[d->nbnd++];
            e->a = d->t[t].v[(i + 1) % 3];
            e->b = d->t[t].v[(i + 2) % 3];
            e->out = nb;
            e->slot = d->t[nb].n[0] == t ? 0 : d->t[nb].n[1] == t ? 1 : 2;
        }
    }
    return HPFC_OK;
}

/* Rotates triangle t so that the ghost vertex, if any, comes last. */
static void dt_normalize(dt *d, uint32_t t)
{
    dt_tri *T = &d->t[t];
    int shift = T->v[0] == d->ghost ? 1 : T->v[1] == d->ghost ? 2 : 0;
    if (!shift)
        return;
    dt_tri old = *T;
    for (int i = 0; i < 3; i++) {
        T->v[i] = old.v[(i + shift) % 3];
        T->n[i] = old.n[(i + shift) % 3];
    }
}

/* Replaces the cavity by the fan of triangles (a, b, p) over its boundary.
 * The boundary is one cycle around p, so each vertex starts exactly one
 * boundary edge and ends exactly one: start_of / end_of find the fan
 * neighbours in O(1). */
static int dt_fill(dt *d, uint32_t p)
{
    for (size_t k = 0; k < d->ncav; k++)
        dt_release(d, d->cav[k]);
    for (size_t k = 0; k < d->nbnd; k++) {
        dt_edge *e = &d->bnd[k];
        if (dt_alloc(d, &e->id))
            return HPFC_E_NOMEM;
        dt_tri *T = &d->t[e->id];
        T->v[0] = e->a;
        T->v[1] = e->b;
        T->v[2] = p;
        T->n[2] = e->out;
        d->t[e->out].n[e->slot] = e->id;
        d->start_of[e->a] = e->id;
        d->end_of[e->b] = e->id;
    }
    for (size_t k = 0; k < d->nbnd; k++) {
        dt_edge *e = &d->bnd[k];
        dt_tri *T = &d->t[e->id];
        T->n[0] = d->start_of[e->b]; /* across b -> p */
        T->n[1] = d->end_of[e->a];   /* across p -> a */
    }
    for (size_t k = 0; k < d->nbnd; k++) {
        dt_normalize(d, d->bnd[k].id);
        if (!dt_is_ghost(d, d->bnd[k].id))
            d->last = d->bnd[k].id;
    }
    return HPFC_OK;
}

static int dt_insert(dt *d, uint32_t p)
{
    const int64_t *pp = dt_pt(d, p);
    int st = dt_cavity(d, dt_locate(d, pp), pp);
    return st ? st : dt_fill(d, p);
}

/* The first triangle a, b, c (counter-clockwise, not degenerate) and a
 * ghost triangle on each of its edges. */
static void dt_start(dt *d, uint32_t a, uint32_t b, uint32_t c)
{
    uint32_t v[3] = {a, b, c};
    if (orient(dt_pt(d, a), dt_pt(d, b), dt_pt(d, c)) < 0) {
        v[1] = c;
        v[2] = b;
    }
    d->nt = 4;
    for (int i = 0; i < 3; i++) {
        d->t[0].v[i] = v[i];
        d->t[0].n[i] = (uint32_t)(1 + i);
        /* ghost 1+i lies across the real edge v[i+1] -> v[i+2] */
        dt_tri *g = &d->t[1 + i];
        g->v[0] = v[(i + 2) % 3];
        g->v[1] = v[(i + 1) % 3];
        g->v[2] = d->ghost;
        g->n[0] = (uint32_t)(1 + (i + 2) % 3); /* ghost starting at v[i+1] */
        g->n[1] = (uint32_t)(1 + (i + 1) % 3); /* ghost ending at v[i+2] */
        g->n[2] = 0;
    }
    d->last = 0;
}

static void dt_free(dt *d)
{
    free(d->t);
    free(d->mark);
    free(d->conf);
    free(d->cav);
    free(d->bnd);
    free(d->start_of);
    free(d->end_of);
}

static int dt_init(dt *d, const int64_t *xy, size_t n)
{
    memset(d, 0, sizeof *d);
    d->xy = xy;
    d->ghost = (uint32_t)n;
    d->free_head = NONE;
    d->walk_state = UINT64_C(0x2545f4914f6cdd1d);
    d->cap = 2 * n + 16; /* a sphere triangulation of n+1 vertices has 2n-2 */
    d->t = malloc(d->cap * sizeof *d->t);
    d->mark = calloc(d->cap, sizeof *d->mark);
    d->conf = malloc(d->cap * sizeof *d->conf);
    d->start_of = malloc((n + 1) * sizeof *d->start_of);
    d->end_of = malloc((n + 1) * sizeof *d->end_of);
    if (!d->t || !d->mark || !d->conf || !d->start_of || !d->end_of ||
        grow((void **)&d->cav, &d->cap_cav, 64, sizeof *d->cav) ||
        grow((void **)&d->bnd, &d->cap_bnd, 64, sizeof *d->bnd)) {
        dt_free(d);
        return HPFC_E_NOMEM;
    }
    return HPFC_OK;
}

/* Copies the live real triangles, their edges and the hull size out of d,
 * with d's point i renamed to to_out[i]. */
static int dt_extract(const dt *d, const uint32_t *to_out, gen_triangulation *out)
{
    size_t nreal = 0, nghost = 0;
    for (size_t t = 0; t < d->nt; t++) {
        if (d->t[t].v[0] == NONE)
            continue;
        if (dt_is_ghost(d, (uint32_t)t))
            nghost++;
        else
            nreal++;
    }
    /* each real triangle emits at most 3 edges */
    size_t ne = 3 * nreal;
    out->tri = malloc((nreal ? nreal : 1) * 3 * sizeof *out->tri);
    out->edge = malloc((ne ? ne : 1) * 2 * sizeof *out->edge);
    if (!out->tri || !out->edge)
        return HPFC_E_NOMEM;
    size_t it = 0, ie = 0;
    for (size_t t = 0; t < d->nt; t++) {
        const dt_tri *T = &d->t[t];
        if (T->v[0] == NONE || T->v[2] == d->ghost)
            continue;
        for (int i = 0; i < 3; i++) {
            out->tri[3 * it + (size_t)i] = to_out[T->v[i]];
            uint32_t nb = T->n[i];
            /* an interior edge is emitted by its lower-numbered triangle */
            if (dt_is_ghost(d, nb) || t < nb) {
                uint32_t a = to_out[T->v[(i + 1) % 3]], b = to_out[T->v[(i + 2) % 3]];
                out->edge[2 * ie] = a < b ? a : b;
                out->edge[2 * ie + 1] = a < b ? b : a;
                ie++;
            }
        }
        it++;
    }
    out->ntriangles = nreal;
    out->nedges = ie;
    out->nhull = nghost;
    return HPFC_OK;
}

/* No triangle exists (fewer than 3 points, or all collinear): the edges
 * join consecutive points along the line, which is lexicographic order. */
static int collinear_path(gen_triangulation *out)
{
    size_t n = out->npoints;
    keyed *idx = malloc((n ? n : 1) * sizeof *idx);
    out->tri = malloc(3 * sizeof *out->tri);
    out->edge = malloc((n ? n : 1) * 2 * sizeof *out->edge);
    if (!idx || !out->tri || !out->edge) {
        free(idx);
        return HPFC_E_NOMEM;
    }
    /* coordinates are below 2^21, so x * 2^21 + y orders lexicographically */
    for (size_t i = 0; i < n; i++) {
        idx[i].key = ((uint64_t)out->xy[2 * i] << 21) | (uint64_t)out->xy[2 * i + 1];
        idx[i].index = (uint32_t)i;
    }
    qsort(idx, n, sizeof *idx, cmp_keyed); /* points are distinct */
    for (size_t i = 0; i + 1 < n; i++) {
        uint32_t a = idx[i].index, b = idx[i + 1].index;
        out->edge[2 * i] = a < b ? a : b;
        out->edge[2 * i + 1] = a < b ? b : a;
    }
    out->nedges = n ? n - 1 : 0;
    out->ntriangles = 0;
    out->nhull = n;
    free(idx);
    return HPFC_OK;
}

/* Inserts the points in Hilbert order, the first non-degenerate triple
 * first. The triangulation works on a copy of the points stored in that
 * order, so that neighbouring triangles touch neighbouring memory; `order`
 * maps the copy's indices back to the caller's. */
static int triangulate(gen_triangulation *out, uint32_t *order)
{
    size_t n = out->npoints;
    const int64_t *xy = out->xy;
    size_t k = 2;
    while (k < n && orient(xy + 2 * (size_t)order[0], xy + 2 * (size_t)order[1],
                           xy + 2 * (size_t)order[k]) == 0)
        k++;
    if (k >= n)
        return collinear_path(out);
    uint32_t tmp = order[2];
    order[2] = order[k];
    order[k] = tmp;
    int64_t *sxy = malloc(2 * n * sizeof *sxy);
    if (!sxy)
        return HPFC_E_NOMEM;
    for (size_t i = 0; i < n; i++) {
        sxy[2 * i] = xy[2 * (size_t)order[i]];
        sxy[2 * i + 1] = xy[2 * (size_t)order[i] + 1];
    }
    dt d;
    int st = dt_init(&d, sxy, n);
    if (!st) {
        dt_start(&d, 0, 1, 2);
        for (size_t i = 3; i < n && !st; i++)
            st = dt_insert(&d, (uint32_t)i);
        if (!st)
            st = dt_extract(&d, order, out);
        dt_free(&d);
    }
    free(sxy);
    return st;
}

void gen_triangulation_free(gen_triangulation *t)
{
    if (!t)
        return;
    free(t->xy);
    free(t->tri);
    free(t->edge);
    memset(t, 0, sizeof *t);
}

int gen_delaunay_triangulation(uint64_t seed, size_t npoints, int64_t coord_max,
                               gen_triangulation *out)
{
    if (!out)
        return HPFC_E_ARG;
    memset(out, 0, sizeof *out);
    if (coord_max < 2 || coord_max > GEN_COORD_MAX_DELAUNAY || npoints > GEN_MAX_POINTS ||
        (uint64_t)npoints > (uint64_t)(coord_max - 1) * (uint64_t)(coord_max - 1))
        return HPFC_E_ARG;
    gen_rng rng;
    gen_rng_seed(&rng, seed);
    out->npoints = npoints;
    out->xy = malloc((npoints ? npoints : 1) * 2 * sizeof *out->xy);
    if (!out->xy)
        return HPFC_E_NOMEM;
    int st = random_points(&rng, npoints, coord_max, out->xy);
    uint32_t *order = st ? NULL : hilbert_order(out->xy, npoints);
    if (!st && !order)
        st = HPFC_E_NOMEM;
    if (!st)
        st = triangulate(out, order);
    free(order);
    if (st)
        gen_triangulation_free(out);
    return st;
}

/* ------------------------------------------------------------------------
 * Edge removal and graph assembly
 * ------------------------------------------------------------------------ */

/* round(fraction * ne), computed in fixed point: scaling by 2^32 (ldexp) and
 * truncating are both exact, so no rounding of the platform can show. */
static size_t removal_count(double fraction, size_t ne)
{
    uint64_t q = (uint64_t)ldexp(fraction, 32);
    return (size_t)(((u128)ne * q + ((u128)1 << 31)) >> 32);
}

/* keep[e] = 0 for round(fraction * ne) edges chosen uniformly (a partial
 * Fisher-Yates shuffle), 1 for the others. */
static int choose_kept(uint64_t seed, double fraction, size_t ne, uint8_t *keep)
{
    size_t k = removal_count(fraction, ne);
    uint32_t *perm = malloc((ne ? ne : 1) * sizeof *perm);
    if (!perm)
        return HPFC_E_NOMEM;
    gen_rng rng;
    gen_rng_seed(&rng, removal_seed(seed));
    for (size_t i = 0; i < ne; i++) {
        perm[i] = (uint32_t)i;
        keep[i] = 1;
    }
    for (size_t i = 0; i < k; i++) {
        size_t j = i + (size_t)gen_rng_below(&rng, ne - i);
        uint32_t t = perm[i];
        perm[i] = perm[j];
        perm[j] = t;
        keep[perm[i]] = 0;
    }
    free(perm);
    return HPFC_OK;
}

/* Degree of every point counting kept edges only. */
static uint32_t *kept_degrees(const gen_triangulation *t, const uint8_t *keep)
{
    uint32_t *deg = calloc(t->npoints ? t->npoints : 1, sizeof *deg);
    if (!deg)
        return NULL;
    for (size_t e = 0; e < t->nedges; e++)
        if (keep[e]) {
            deg[t->edge[2 * e]]++;
            deg[t->edge[2 * e + 1]]++;
        }
    return deg;
}

/* The graph of the kept edges; points of degree 0 are dropped, the others
 * renumbered in their original order. */
static int graph_from_kept(const gen_triangulation *t, const uint8_t *keep,
                           hpfc_graph **out)
{
    uint32_t *deg = kept_degrees(t, keep);
    uint32_t *id = malloc((t->npoints ? t->npoints : 1) * sizeof *id);
    int st = deg && id ? hpfc_graph_create(out) : HPFC_E_NOMEM;
    for (size_t i = 0; i < t->npoints && !st; i++)
        if (deg[i])
            st = hpfc_graph_add_vertex(*out, t->xy[2 * i], t->xy[2 * i + 1], &id[i]);
    for (size_t e = 0; e < t->nedges && !st; e++)
        if (keep[e])
            st = hpfc_graph_add_edge(*out, id[t->edge[2 * e]], id[t->edge[2 * e + 1]],
                                     NULL, 0, NULL);
    free(deg);
    free(id);
    return st;
}

static bool fraction_ok(double f)
{
    return f >= 0.0 && f <= 1.0; /* false for NaN */
}

/* The triangulation of (seed, npoints, coord_max) and which of its edges
 * survive the removal. */
static int triangulate_and_remove(uint64_t seed, size_t npoints, int64_t coord_max,
                                  double remove_fraction, gen_triangulation *t,
                                  uint8_t **keep)
{
    *keep = NULL;
    if (!fraction_ok(remove_fraction))
        return HPFC_E_ARG;
    int st = gen_delaunay_triangulation(seed, npoints, coord_max, t);
    if (st)
        return st;
    *keep = malloc(t->nedges ? t->nedges : 1);
    st = *keep ? choose_kept(seed, remove_fraction, t->nedges, *keep) : HPFC_E_NOMEM;
    if (st) {
        free(*keep);
        *keep = NULL;
        gen_triangulation_free(t);
    }
    return st;
}

int gen_delaunay(uint64_t seed, size_t npoints, int64_t coord_max,
                 double remove_fraction, hpfc_graph **out)
{
    if (!out)
        return HPFC_E_ARG;
    *out = NULL;
    gen_triangulation t;
    uint8_t *keep;
    int st = triangulate_and_remove(seed, npoints, coord_max, remove_fraction, &t, &keep);
    if (st)
        return st;
    st = graph_from_kept(&t, keep, out);
    free(keep);
    gen_triangulation_free(&t);
    if (st) {
        hpfc_graph_free(*out);
        *out = NULL;
    }
    return st;
}

/* ------------------------------------------------------------------------
 * Chain contraction (gen_polyline)
 * ------------------------------------------------------------------------ */

typedef struct chains {
    const gen_triangulation *t;
    const uint8_t *keep;
    uint32_t *deg;
    size_t *off;        /* incident kept edges of v: inc[off[v] .. off[v+1]) */
    uint32_t *inc;
    uint8_t *used;      /* edge already part of an output edge */
    uint32_t *id;       /* graph vertex of a point, NONE for interior points */
    int64_t *buf;       /* interior points of the edge being built */
} chains;

static void chains_free(chains *c)
{
    free(c->deg);
    free(c->off);
    free(c->inc);
    free(c->used);
    free(c->id);
    free(c->buf);
}

/* Degrees, adjacency lists (CSR) of the kept edges, and scratch space. */
static int chains_init(chains *c, const gen_triangulation *t, const uint8_t *keep)
{
    size_t n = t->npoints, m = t->nedges;
    memset(c, 0, sizeof *c);
    c->t = t;
    c->keep = keep;
    c->deg = kept_degrees(t, keep);
    c->off = calloc(n + 1, sizeof *c->off);
    c->inc = malloc((m ? 2 * m : 1) * sizeof *c->inc);
    c->used = calloc(m ? m : 1, 1);
    c->id = malloc((n ? n : 1) * sizeof *c->id);
    c->buf = malloc((n ? n : 1) * 2 * sizeof *c->buf);
    if (!c->deg || !c->off || !c->inc || !c->used || !c->id || !c->buf)
        return HPFC_E_NOMEM;
    for (size_t v = 0; v < n; v++)
        c->off[v + 1] = c->off[v] + c->deg[v];
    size_t *fill = malloc((n ? n : 1) * sizeof *fill);
    if (!fill)
        return HPFC_E_NOMEM;
    memcpy(fill, c->off, n * sizeof *fill);
    for (size_t e = 0; e < m; e++)
        if (keep[e]) {
            c->inc[fill[t->edge[2 * e]]++] = (uint32_t)e;
            c->inc[fill[t->edge[2 * e + 1]]++] = (uint32_t)e;
        }
    free(fill);
    return HPFC_OK;
}

static inline uint32_t other_end(const chains *c, uint32_t e, uint32_t v)
{
    const uint32_t *ab = c->t->edge + 2 * (size_t)e;
    return ab[0] == v ? ab[1] : ab[0];
}

/* Follows the chain leaving `start` through edge e across degree-2 points,
 * collecting them in c->buf, up to the first point of another degree (or
 * back to start, for a ring). Returns the end point and the count. */
static uint32_t follow_chain(chains *c, uint32_t start, uint32_t e, size_t *ninterior)
{
    size_t k = 0;
    c->used[e] = 1;
    uint32_t cur = other_end(c, e, start);
    while (c->deg[cur] == 2 && cur != start) {
        c->buf[2 * k] = c->t->xy[2 * (size_t)cur];
        c->buf[2 * k + 1] = c->t->xy[2 * (size_t)cur + 1];
        k++;
        const uint32_t *two = c->inc + c->off[cur];
        e = two[0] == e ? two[1] : two[0]; /* no multi-edges: ids differ */
        c->used[e] = 1;
        cur = other_end(c, e, cur);
    }
    *ninterior = k;
    return cur;
}

/* Chains between junctions (degree not 2), then rings of degree-2 points. */
static int contract(chains *c, hpfc_graph *g)
{
    size_t n = c->t->npoints;
    int st = HPFC_OK;
    for (size_t v = 0; v < n && !st; v++) {
        c->id[v] = NONE;
        if (c->deg[v] && c->deg[v] != 2)
            st = hpfc_graph_add_vertex(g, c->t->xy[2 * v], c->t->xy[2 * v + 1], &c->id[v]);
    }
    for (size_t v = 0; v < n && !st; v++) {
        if (c->id[v] == NONE)
            continue;
        for (size_t k = c->off[v]; k < c->off[v + 1] && !st; k++) {
            uint32_t e = c->inc[k];
            if (c->used[e])
                continue;
            size_t ni;
            uint32_t w = follow_chain(c, (uint32_t)v, e, &ni);
            st = hpfc_graph_add_edge(g, c->id[v], c->id[w], c->buf, ni, NULL);
        }
    }
    for (size_t v = 0; v < n && !st; v++) {
        if (c->deg[v] != 2 || c->used[c->inc[c->off[v]]])
            continue;
        size_t ni;
        follow_chain(c, (uint32_t)v, c->inc[c->off[v]], &ni);
        st = hpfc_graph_add_vertex(g, c->t->xy[2 * v], c->t->xy[2 * v + 1], &c->id[v]);
        if (!st)
            st = hpfc_graph_add_edge(g, c->id[v], c->id[v], c->buf, ni, NULL);
    }
    return st;
}

int gen_polyline(uint64_t seed, size_t npoints, int64_t coord_max,
                 double remove_fraction, hpfc_graph **out)
{
    if (!out)
        return HPFC_E_ARG;
    *out = NULL;
    gen_triangulation t;
    uint8_t *keep;
    int st = triangulate_and_remove(seed, npoints, coord_max, remove_fraction, &t, &keep);
    if (st)
        return st;
    chains c;
    st = chains_init(&c, &t, keep);
    if (!st)
        st = hpfc_graph_create(out);
    if (!st)
        st = contract(&c, *out);
    chains_free(&c);
    free(keep);
    gen_triangulation_free(&t);
    if (st) {
        hpfc_graph_free(*out);
        *out = NULL;
    }
    return st;
}

/* ------------------------------------------------------------------------
 * Jittered grid mesh
 * ------------------------------------------------------------------------ */

static int grid_vertices(gen_rng *rng, hpfc_graph *g, size_t cols, size_t rows,
                         int64_t spacing)
{
    int64_t jit = (spacing - 1) / 4; /* < spacing / 4: see gen.h */
    uint64_t span = 2 * (uint64_t)jit + 1;
    int st = HPFC_OK;
    for (size_t j = 0; j <= rows && !st; j++)
        for (size_t i = 0; i <= cols && !st; i++) {
            int64_t x = (int64_t)(i + 1) * spacing;
            int64_t y = (int64_t)(j + 1) * spacing;
            if (jit) {
                x += (int64_t)gen_rng_below(rng, span) - jit;
                y += (int64_t)gen_rng_below(rng, span) - jit;
            }
            st = hpfc_graph_add_vertex(g, x, y, NULL);
        }
    return st;
}

/* Horizontal and vertical edges, then one diagonal per cell. */
static int grid_edges(gen_rng *rng, hpfc_graph *g, size_t cols, size_t rows)
{
    size_t w = cols + 1;
    int st = HPFC_OK;
    for (size_t j = 0; j <= rows && !st; j++)
        for (size_t i = 0; i <= cols && !st; i++) {
            uint32_t v = (uint32_t)(j * w + i);
            if (i < cols)
                st = hpfc_graph_add_edge(g, v, v + 1, NULL, 0, NULL);
            if (j < rows && !st)
                st = hpfc_graph_add_edge(g, v, v + (uint32_t)w, NULL, 0, NULL);
        }
    for (size_t j = 0; j < rows && !st; j++)
        for (size_t i = 0; i < cols && !st; i++) {
            uint32_t v = (uint32_t)(j * w + i);
            if (gen_rng_next(rng) >> 63)
                st = hpfc_graph_add_edge(g, v, v + (uint32_t)w + 1, NULL, 0, NULL);
            else
                st = hpfc_graph_add_edge(g, v + 1, v + (uint32_t)w, NULL, 0, NULL);
        }
    return st;
}

int gen_grid_mesh(uint64_t seed, size_t cols, size_t rows, int64_t spacing,
                  hpfc_graph **out)
{
    if (!out)
        return HPFC_E_ARG;
    *out = NULL;
    if (cols < 1 || rows < 1 || spacing < 1 || cols > (1u << 20) || rows > (1u << 20) ||
        (uint64_t)(cols + 1) * (rows + 1) >= UINT32_MAX / 4 ||
        (int64_t)(cols > rows ? cols : rows) + 2 > HPFC_COORD_MAX / spacing)
        return HPFC_E_ARG;
    gen_rng rng;
    gen_rng_seed(&rng, seed);
    int st = hpfc_graph_create(out);
    if (!st)
        st = grid_vertices(&rng, *out, cols, rows, spacing);
    if (!st)
        st = grid_edges(&rng, *out, cols, rows);
    if (st) {
        hpfc_graph_free(*out);
        *out = NULL;
    }
    return st;
}

/* ------------------------------------------------------------------------
 * Special graphs
 * ------------------------------------------------------------------------ */

/* Adds the closed polygon through k vertices (x, y pairs), as k edges. */
static int add_polygon(hpfc_graph *g, const int64_t *xy, size_t k)
{
    uint32_t first = (uint32_t)hpfc_graph_vertex_count(g);
    int st = HPFC_OK;
    for (size_t i = 0; i < k && !st; i++)
        st = hpfc_graph_add_vertex(g, xy[2 * i], xy[2 * i + 1], NULL);
    for (size_t i = 0; i < k && !st; i++)
        st = hpfc_graph_add_edge(g, first + (uint32_t)i, first + (uint32_t)((i + 1) % k),
                                 NULL, 0, NULL);
    return st;
}

/* Adds vertex (x, y) and returns its index through *v. */
static int add_v(hpfc_graph *g, int64_t x, int64_t y, uint32_t *v)
{
    return hpfc_graph_add_vertex(g, x, y, v);
}

static int special_edge(hpfc_graph *g)
{
    uint32_t a, b;
    int st = add_v(g, 0, 0, &a);
    if (!st)
        st = add_v(g, 7, 3, &b);
    return st ? st : hpfc_graph_add_edge(g, a, b, NULL, 0, NULL);
}

static int special_triangle(hpfc_graph *g)
{
    static const int64_t tri[] = {0, 0, 12, 0, 4, 9};
    return add_polygon(g, tri, 3);
}

static int special_crack(hpfc_graph *g)
{
    static const int64_t sq[] = {0, 0, 40, 0, 40, 40, 0, 40};
    uint32_t tip;
    int st = add_polygon(g, sq, 4);
    if (!st)
        st = add_v(g, 23, 17, &tip);
    return st ? st : hpfc_graph_add_edge(g, 0, tip, NULL, 0, NULL);
}

static int special_loop(hpfc_graph *g)
{
    /* loop a -> (8,-4) -> (12,4) -> (6,10) -> a: a convex quadrilateral */
    static const int64_t loop[] = {8, -4, 12, 4, 6, 10};
    uint32_t a, b;
    int st = add_v(g, 0, 0, &a);
    if (!st)
        st = add_v(g, -9, 2, &b);
    if (!st)
        st = hpfc_graph_add_edge(g, a, a, loop, 3, NULL);
    return st ? st : hpfc_graph_add_edge(g, a, b, NULL, 0, NULL);
}

static int special_multi(hpfc_graph *g)
{
    static const int64_t north[] = {10, 6}, south[] = {10, -6};
    uint32_t a, b;
    int st = add_v(g, 0, 0, &a);
    if (!st)
        st = add_v(g, 20, 0, &b);
    if (!st)
        st = hpfc_graph_add_edge(g, a, b, NULL, 0, NULL);
    if (!st)
        st = hpfc_graph_add_edge(g, a, b, north, 1, NULL);
    return st ? st : hpfc_graph_add_edge(g, b, a, south, 1, NULL);
}

static int special_hole(hpfc_graph *g)
{
    static const int64_t outer[] = {0, 0, 60, 0, 60, 60, 0, 60};
    static const int64_t inner[] = {20, 20, 40, 20, 40, 40, 20, 40};
    static const int64_t island[] = {26, 26, 34, 27, 29, 34};
    int st = add_polygon(g, outer, 4);
    if (!st)
        st = add_polygon(g, inner, 4);
    return st ? st : add_polygon(g, island, 3);
}

/* Every other lattice point of the square ring |x|,|y| <= 16, max = 16: 64
 * distinct directions from the centre, so the radial segments only meet
 * there. */
static int special_star(hpfc_graph *g)
{
    const int64_t r = 16;
    uint32_t c;
    int st = add_v(g, 0, 0, &c);
    int64_t x = -r, y = -r;
    static const int dir[4][2] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
    for (int side = 0; side < 4 && !st; side++)
        for (int64_t k = 0; k < 2 * r && !st; k++) {
            if (k % 2 == 0) {
                uint32_t v;
                st = add_v(g, x, y, &v);
                if (!st)
                    st = hpfc_graph_add_edge(g, c, v, NULL, 0, NULL);
            }
            x += dir[side][0];
            y += dir[side][1];
        }
    return st;
}

static int special_comb(hpfc_graph *g)
{
    const uint32_t teeth = 100;
    int st = HPFC_OK;
    for (uint32_t i = 0; i < teeth && !st; i++) {
        uint32_t base, tip;
        st = add_v(g, 2 * (int64_t)i, 0, &base);
        if (!st)
            st = add_v(g, 2 * (int64_t)i, 1000, &tip);
        if (!st)
            st = hpfc_graph_add_edge(g, base, tip, NULL, 0, NULL);
        if (!st && i > 0)
            st = hpfc_graph_add_edge(g, base - 2, base, NULL, 0, NULL);
    }
    return st;
}

static const struct {
    const char *name;
    int (*build)(hpfc_graph *g);
} specials[GEN_SPECIAL_COUNT] = {
    [GEN_SPECIAL_EDGE] = {"edge", special_edge},
    [GEN_SPECIAL_TRIANGLE] = {"triangle", special_triangle},
    [GEN_SPECIAL_CRACK] = {"crack", special_crack},
    [GEN_SPECIAL_LOOP] = {"loop", special_loop},
    [GEN_SPECIAL_MULTI] = {"multi", special_multi},
    [GEN_SPECIAL_HOLE] = {"hole", special_hole},
    [GEN_SPECIAL_STAR] = {"star", special_star},
    [GEN_SPECIAL_COMB] = {"comb", special_comb},
};

const char *gen_special_name(int which)
{
    return which >= 0 && which < GEN_SPECIAL_COUNT ? specials[which].name : NULL;
}

int gen_special(int which, hpfc_graph **out)
{
    if (!out)
        return HPFC_E_ARG;
    *out = NULL;
    if (which < 0 || which >= GEN_SPECIAL_COUNT)
        return HPFC_E_ARG;
    int st = hpfc_graph_create(out);
    if (!st)
        st = specials[which].build(*out);
    if (st) {
        hpfc_graph_free(*out);
        *out = NULL;
    }
    return st;
}

/* ------------------------------------------------------------------------
 * .pfc output
 * ------------------------------------------------------------------------ */

int gen_write_pfc(const hpfc_graph *g, FILE *f)
{
    if (!g || !f || hpfc_graph_unit_exp10(g) != 0)
        return HPFC_E_ARG;
    fprintf(f, "pfc 1\n");
    for (size_t i = 0; i < hpfc_graph_vertex_count(g); i++) {
        int64_t x, y;
        hpfc_graph_vertex(g, i, &x, &y);
        fprintf(f, "v %" PRId64 " %" PRId64 "\n", x, y);
    }
    for (size_t e = 0; e < hpfc_graph_edge_count(g); e++) {
        uint32_t u, v;
        const int64_t *p;
        size_t k;
        hpfc_graph_edge(g, e, &u, &v, &p, &k);
        fprintf(f, "e %" PRIu32 " %" PRIu32, u, v);
        for (size_t i = 0; i < 2 * k; i++)
            fprintf(f, " %" PRId64, p[i]);
        fputc('\n', f);
    }
    return ferror(f) ? HPFC_E_IO : HPFC_OK;
}

/* One generated graph through fn (st: its generator's status, checked
 * after the generator ran, which set g); that status back. */
static int sweep_one(int st, hpfc_graph *g, const char *what,
                     void (*fn)(const hpfc_graph *g, const char *what))
{
    if (!st)
        fn(g, what);
    hpfc_graph_free(g);
    return st;
}

int gen_sweep(uint64_t seeds, size_t delaunay_step, size_t polyline_points,
              void (*fn)(const hpfc_graph *g, const char *what))
{
    int first = HPFC_OK;
    for (int which = 0; which < GEN_SPECIAL_COUNT; which++) {
        hpfc_graph *g = NULL;
        int st = gen_special(which, &g);
        st = sweep_one(st, g, gen_special_name(which), fn);
        first = first ? first : st;
    }
    for (uint64_t seed = 1; seed <= seeds; seed++) {
        hpfc_graph *g = NULL;
        int st = gen_delaunay(seed, delaunay_step * seed, 1 << 16, 0.2, &g);
        st = sweep_one(st, g, "delaunay", fn);
        first = first ? first : st;
        g = NULL;
        st = gen_polyline(seed, polyline_points, 1 << 16, 0.5, &g);
        st = sweep_one(st, g, "polyline", fn);
        first = first ? first : st;
    }
    return first;
}
