/*
 * Geometry back from the file (hpfc_geometry_dart_*, hpfc_shapes_*) against
 * an independent oracle built from the input graph alone: its faces traced
 * by the textbook rule (at each vertex the darts sorted by exact angle, a
 * face's next dart the one after the twin counter-clockwise), each face's
 * exact doubled area, its directed segments, and which edges are bridges
 * (both darts in one face walk). Checked, for every face and for random
 * features (unions of faces):
 *   - the rings' directed segments are exactly the oracle's (the region on
 *     the left; bridges and dead ends inside the region absent);
 *   - the rings' signed areas add up to the region's area (holes count
 *     negative), the outer rings counter-clockwise and holes clockwise;
 *   - every ring simple (no point twice but the closing one), rings that
 *     meet at a point not crossing there (their arms nest), each polygon's
 *     interior connected (its rings touch without a cycle), one outer
 *     ring per bounded face, none for the unbounded face, every hole inside
 *     its polygon's outer ring;
 * a feature's lines (random edge sets) are its edges' segments in as many
 * polylines as the set has chains, and every dart's polyline is its input
 * edge, forward or backward, from
 * the end in the dart's pixel, its twin's the reverse. On the .pfc
 * fixtures, hand-made pinches (two triangles meeting at a vertex, a hole
 * touching its face's outer ring), the special graphs and random Delaunay
 * graphs with edges removed (bridges, dead ends, islands) and polylines,
 * deep and flat, in both pool layouts (HPFC_TEST_LAYOUT).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "format.h"
#include "gen.h"
#include "hpfc.h"
#include "shix.h"

__extension__ typedef __int128 s128;

/* ---- the oracle ----------------------------------------------------------------- */

typedef struct oracle {
    size_t nv, ne, nd;
    int64_t *dir;          /* per dart: direction leaving its origin */
    uint32_t *origin;      /* per dart */
    uint32_t *next;        /* per dart: next dart, face on the right */
    uint32_t *walk;        /* per dart: its face walk */
    size_t nwalks;
    s128 *walk_area2;      /* per walk: twice its signed area */
} oracle;

static const hpfc_graph *G;

static int half(const int64_t *d)
{
    return d[1] < 0 || (d[1] == 0 && d[0] < 0);
}

static int cmp_dir(const int64_t *a, const int64_t *b)
{
    if (half(a) != half(b))
        return half(a) - half(b);
    s128 c = (s128)a[0] * b[1] - (s128)a[1] * b[0];
    return c > 0 ? -1 : c < 0;
}

static const oracle *O_sort;
static int cmp_dart_at(const void *pa, const void *pb)
{
    uint32_t a = *(const uint32_t *)pa, b = *(const uint32_t *)pb;
    if (O_sort->origin[a] != O_sort->origin[b])
        return O_sort->origin[a] < O_sort->origin[b] ? -1 : 1;
    return cmp_dir(O_sort->dir + 2 * a, O_sort->dir + 2 * b);
}

/* Point k of dart d (d = 2e: u -> v, 2e + 1: v -> u). */
static void dart_point(uint32_t d, size_t k, int64_t *x, int64_t *y)
{
    size_t e = d / 2;
    const int64_t *in;
    size_t n_in;
    uint32_t u, v;
    hpfc_graph_edge(G, e, &u, &v, &in, &n_in);
    size_t n = n_in + 2, j = d & 1 ? n - 1 - k : k;
    if (j == 0)
        hpfc_graph_vertex(G, u, x, y);
    else if (j == n - 1)
        hpfc_graph_vertex(G, v, x, y);
    else
        *x = in[2 * (j - 1)], *y = in[2 * (j - 1) + 1];
}

static size_t dart_npoints(uint32_t d)
{
    const int64_t *in;
    size_t n_in;
    uint32_t u, v;
    hpfc_graph_edge(G, d / 2, &u, &v, &in, &n_in);
    return n_in + 2;
}

static void oracle_build(oracle *o)
{
    memset(o, 0, sizeof *o);
    o->nv = hpfc_graph_vertex_count(G), o->ne = hpfc_graph_edge_count(G), o->nd = 2 * o->ne;
    o->dir = malloc(2 * o->nd * sizeof *o->dir);
    o->origin = malloc(o->nd * sizeof *o->origin);
    o->next = malloc(o->nd * sizeof *o->next);
    o->walk = malloc(o->nd * sizeof *o->walk);
    o->walk_area2 = calloc(o->nd + 1, sizeof *o->walk_area2);
    uint32_t *order = malloc(o->nd * sizeof *order), *pos = malloc(o->nd * sizeof *pos);
    for (uint32_t d = 0; d < o->nd; d++) {
        int64_t x0, y0, x1, y1;
        dart_point(d, 0, &x0, &y0);
        dart_point(d, 1, &x1, &y1);
        o->dir[2 * d] = x1 - x0, o->dir[2 * d + 1] = y1 - y0;
        uint32_t u, v;
        const int64_t *in;
        size_t n_in;
        hpfc_graph_edge(G, d / 2, &u, &v, &in, &n_in);
        o->origin[d] = d & 1 ? v : u;
        order[d] = d;
    }
    O_sort = o;
    qsort(order, o->nd, sizeof *order, cmp_dart_at);
    for (uint32_t k = 0; k < o->nd; k++)
        pos[order[k]] = k;
    /* next (face on the right): after the twin, counter-clockwise */
    for (uint32_t d = 0; d < o->nd; d++) {
        uint32_t t = d ^ 1, k = pos[t] + 1;
        if (k == o->nd || o->origin[order[k]] != o->origin[t]) {
            k = pos[t];
            while (k > 0 && o->origin[order[k - 1]] == o->origin[t])
                k--;
        }
        o->next[d] = order[k];
    }
    for (uint32_t d = 0; d < o->nd; d++)
        o->walk[d] = UINT32_MAX;
    for (uint32_t d = 0; d < o->nd; d++) {
        if (o->walk[d] != UINT32_MAX)
            continue;
        uint32_t w = (uint32_t)o->nwalks++;
        for (uint32_t c = d; o->walk[c] == UINT32_MAX; c = o->next[c]) {
            o->walk[c] = w;
            for (size_t k = 0; k + 1 < dart_npoints(c); k++) {
                int64_t ax, ay, bx, by;
                dart_point(c, k, &ax, &ay);
                dart_point(c, k + 1, &bx, &by);
                o->walk_area2[w] += (s128)ax * by - (s128)bx * ay;
            }
        }
    }
    free(order);
    free(pos);
}

static void oracle_free(oracle *o)
{
    free(o->dir);
    free(o->origin);
    free(o->next);
    free(o->walk);
    free(o->walk_area2);
}

/* ---- segments ------------------------------------------------------------------- */

typedef struct seg {
    int64_t v[4];
} seg;

static int cmp_seg(const void *pa, const void *pb)
{
    const seg *a = pa, *b = pb;
    for (int k = 0; k < 4; k++)
        if (a->v[k] != b->v[k])
            return a->v[k] < b->v[k] ? -1 : 1;
    return 0;
}

typedef struct segs {
    seg *s;
    size_t n, cap;
} segs;

static void segs_add(segs *l, int64_t ax, int64_t ay, int64_t bx, int64_t by)
{
    if (l->n == l->cap) {
        l->cap = l->cap ? 2 * l->cap : 256;
        l->s = realloc(l->s, l->cap * sizeof *l->s);
    }
    l->s[l->n++] = (seg){{ax, ay, bx, by}};
}

/* Dart d's segments, face on its LEFT: the dart itself run forward. */
static void segs_of_dart(segs *l, uint32_t d)
{
    for (size_t k = 0; k + 1 < dart_npoints(d); k++) {
        int64_t ax, ay, bx, by;
        dart_point(d, k, &ax, &ay);
        dart_point(d, k + 1, &bx, &by);
        segs_add(l, ax, ay, bx, by);
    }
}

static int segs_equal(segs *a, segs *b)
{
    if (a->n != b->n)
        return 0;
    if (a->n == 0)
        return 1; /* both empty (and their arrays NULL) */
    qsort(a->s, a->n, sizeof *a->s, cmp_seg);
    qsort(b->s, b->n, sizeof *b->s, cmp_seg);
    return memcmp(a->s, b->s, a->n * sizeof *a->s) == 0;
}

/* ---- rings that touch must not cross ---------------------------------------------- */

/* A ring passing through a point: the directions to its previous and next
 * points. */
typedef struct passage {
    int64_t x, y;
    int64_t dir[2][2];
} passage;

static int cmp_passage(const void *pa, const void *pb)
{
    const passage *a = pa, *b = pb;
    if (a->x != b->x)
        return a->x < b->x ? -1 : 1;
    return (a->y > b->y) - (a->y < b->y);
}

typedef struct arm {
    const int64_t *dir;
    size_t owner;
} arm;

static int cmp_arm(const void *pa, const void *pb)
{
    return cmp_dir(((const arm *)pa)->dir, ((const arm *)pb)->dir);
}

/* Where rings (or one ring's passages) share a point, each passage's two
 * arms must be adjacent in the angular order once the nested passages
 * between them are taken out: a non-crossing matching, checked with a
 * stack. 1 when no two passages cross. */
static int passages_nested(const hpfc_polygons *p)
{
    size_t n = p->ring_point[p->ring_count] - p->ring_count, m = 0;
    passage *ps = malloc((n + 1) * sizeof *ps);
    for (size_t r = 0; r < p->ring_count; r++) {
        size_t a = p->ring_point[r], len = p->ring_point[r + 1] - a - 1; /* without the closing point */
        for (size_t k = 0; k < len; k++) {
            const int64_t *c = p->xy + 2 * (a + k), *pr = p->xy + 2 * (a + (k + len - 1) % len),
                          *nx = p->xy + 2 * (a + (k + 1) % len);
            ps[m] = (passage){c[0], c[1], {{pr[0] - c[0], pr[1] - c[1]}, {nx[0] - c[0], nx[1] - c[1]}}};
            m++;
        }
    }
    qsort(ps, m, sizeof *ps, cmp_passage);
    int ok = 1;
    for (size_t i = 0; i < m && ok;) {
        size_t j = i;
        while (j < m && !cmp_passage(&ps[i], &ps[j]))
            j++;
        if (j - i >= 2) {
            size_t na = 2 * (j - i), top = 0;
            arm *arms = malloc(na * sizeof *arms);
            size_t *stack = malloc(na * sizeof *stack);
            for (size_t k = i; k < j; k++)
                for (int e = 0; e < 2; e++)
                    arms[2 * (k - i) + (size_t)e] = (arm){ps[k].dir[e], k};
            qsort(arms, na, sizeof *arms, cmp_arm);
            for (size_t k = 0; k < na; k++) {
                if (top && stack[top - 1] == arms[k].owner)
                    top--;
                else
                    stack[top++] = arms[k].owner;
            }
            ok = top == 0;
            free(arms);
            free(stack);
        }
        i = j;
    }
    free(ps);
    return ok;
}

/* A polygon's interior is connected (OGC) when the graph whose nodes are its
 * rings and whose edges are the points where two of them touch has no
 * cycle: two touches between the same rings, or a chain of touches around,
 * would cut the interior in two. Union-find over the touching points. */
static size_t uf_find(size_t *parent, size_t a)
{
    while (parent[a] != a)
        a = parent[a] = parent[parent[a]];
    return a;
}

static int interior_connected(const hpfc_polygons *p, size_t q)
{
    size_t r0 = p->polygon_ring[q], r1 = p->polygon_ring[q + 1], m = 0;
    size_t n = p->ring_point[r1] - p->ring_point[r0];
    seg *pts = malloc((n + 1) * sizeof *pts); /* x, y, ring, 0 */
    size_t *parent = malloc((r1 - r0 + 1) * sizeof *parent);
    for (size_t r = r0; r < r1; r++) {
        parent[r - r0] = r - r0;
        for (size_t k = p->ring_point[r]; k + 1 < p->ring_point[r + 1]; k++)
            pts[m++] = (seg){{p->xy[2 * k], p->xy[2 * k + 1], (int64_t)(r - r0), 0}};
    }
    qsort(pts, m, sizeof *pts, cmp_seg);
    int ok = 1;
    for (size_t i = 1; i < m && ok; i++) {
        if (pts[i].v[0] != pts[i - 1].v[0] || pts[i].v[1] != pts[i - 1].v[1])
            continue;
        size_t a = uf_find(parent, (size_t)pts[i - 1].v[2]), b = uf_find(parent, (size_t)pts[i].v[2]);
        if (a == b)
            ok = 0;
        else
            parent[a] = b;
    }
    free(pts);
    free(parent);
    return ok;
}

/* ---- checking an answer --------------------------------------------------------- */

/* Twice the signed area of ring r. */
static s128 ring_area2(const hpfc_polygons *p, size_t r)
{
    s128 a = 0;
    for (size_t k = p->ring_point[r]; k + 1 < p->ring_point[r + 1]; k++)
        a += (s128)p->xy[2 * k] * p->xy[2 * k + 3] - (s128)p->xy[2 * k + 2] * p->xy[2 * k + 1];
    return a;
}

/* A naive even-odd test of point (px, py) (doubled) against ring r: 1 in,
 * 0 out, -1 on. */
static int naive_inside(const hpfc_polygons *p, size_t r, int64_t px, int64_t py)
{
    int in = 0;
    for (size_t k = p->ring_point[r]; k + 1 < p->ring_point[r + 1]; k++) {
        int64_t ax = 2 * p->xy[2 * k], ay = 2 * p->xy[2 * k + 1];
        int64_t bx = 2 * p->xy[2 * k + 2], by = 2 * p->xy[2 * k + 3];
        s128 c = (s128)(bx - ax) * (py - ay) - (s128)(by - ay) * (px - ax);
        int64_t lox = ax < bx ? ax : bx, hix = ax < bx ? bx : ax;
        int64_t loy = ay < by ? ay : by, hiy = ay < by ? by : ay;
        if (c == 0 && px >= lox && px <= hix && py >= loy && py <= hiy)
            return -1;
        if ((ay > py) != (by > py)) {
            /* x of the crossing > px ? */
            s128 lhs = (s128)(px - ax) * (by - ay), rhs = (s128)(bx - ax) * (py - ay);
            if (by > ay ? rhs > lhs : rhs < lhs)
                in = !in;
        }
    }
    return in;
}

/* Whether ring h lies inside ring o, decided by the first of h's points,
 * then of its segments' middles, that is not on o (rings never cross): 1,
 * 0, or -1 when all of h lies on o. */
static int hole_inside(const hpfc_polygons *p, size_t h, size_t o)
{
    int verdict = -1;
    for (size_t k = p->ring_point[h]; verdict < 0 && k + 1 < p->ring_point[h + 1]; k++)
        verdict = naive_inside(p, o, 2 * p->xy[2 * k], 2 * p->xy[2 * k + 1]);
    for (size_t k = p->ring_point[h]; verdict < 0 && k + 1 < p->ring_point[h + 1]; k++)
        verdict = naive_inside(p, o, p->xy[2 * k] + p->xy[2 * k + 2],
                               p->xy[2 * k + 1] + p->xy[2 * k + 3]);
    return verdict;
}

/* Rings simple and closed, outer rings positive, holes negative and inside
 * their outer ring; the directed segments and the area sum as expected. */
static void check_answer(const char *what, const hpfc_polygons *p, segs *want, s128 want_area2,
                         int bounded_face)
{
    segs got = {0};
    s128 area = 0;
    int ok_simple = 1, ok_orient = 1, ok_inside = 1;
    for (size_t r = 0; r < p->ring_count; r++) {
        size_t a = p->ring_point[r], b = p->ring_point[r + 1];
        CHECK(b >= a + 4);
        if (b < a + 2)
            continue;
        CHECK(p->xy[2 * a] == p->xy[2 * (b - 1)] && p->xy[2 * a + 1] == p->xy[2 * (b - 1) + 1]);
        segs pts = {0};
        for (size_t k = a; k + 1 < b; k++) {
            segs_add(&got, p->xy[2 * k], p->xy[2 * k + 1], p->xy[2 * k + 2], p->xy[2 * k + 3]);
            segs_add(&pts, p->xy[2 * k], p->xy[2 * k + 1], 0, 0);
        }
        qsort(pts.s, pts.n, sizeof *pts.s, cmp_seg);
        for (size_t k = 1; k < pts.n; k++)
            if (!cmp_seg(&pts.s[k - 1], &pts.s[k]))
                ok_simple = 0;
        free(pts.s);
        s128 ar = ring_area2(p, r);
        area += ar;
        int is_outer = 0;
        for (size_t q = 0; q < p->polygon_count; q++)
            is_outer |= p->polygon_ring[q] == r;
        if (is_outer ? ar <= 0 : ar >= 0)
            ok_orient = 0;
    }
    /* each hole: inside its outer ring (some point of it strictly inside),
     * and that ring the smallest outer ring around it, the first of equal
     * ones; the holes after the last polygon inside none */
    for (size_t q = 0; q <= p->polygon_count; q++) {
        size_t outer = q < p->polygon_count ? p->polygon_ring[q] : SIZE_MAX;
        size_t h0 = q < p->polygon_count ? outer + 1 : p->polygon_ring[q];
        size_t h1 = q < p->polygon_count ? p->polygon_ring[q + 1] : p->ring_count;
        for (size_t h = h0; h < h1; h++) {
            size_t smallest = SIZE_MAX;
            for (size_t o = 0; o < p->polygon_count; o++) {
                size_t r = p->polygon_ring[o];
                if (-ring_area2(p, h) < ring_area2(p, r) && hole_inside(p, h, r) == 1 &&
                    (smallest == SIZE_MAX || ring_area2(p, r) < ring_area2(p, smallest)))
                    smallest = r;
            }
            if (smallest != outer)
                ok_inside = 0;
        }
    }
    int segs_ok = segs_equal(&got, want), nested = passages_nested(p);
    for (size_t q = 0; q < p->polygon_count; q++)
        nested &= interior_connected(p, q);
    CHECK(segs_ok);
    CHECK(nested);
    CHECK(area == want_area2);
    CHECK(ok_simple);
    CHECK(ok_orient);
    CHECK(ok_inside);
    if (bounded_face == 1)
        CHECK_EQ_INT(p->polygon_count, 1);
    if (bounded_face == 0)
        CHECK_EQ_INT(p->polygon_count, 0);
    if (!segs_ok || area != want_area2 || !ok_simple || !ok_orient || !ok_inside || !nested)
        fprintf(stderr, "  in %s: %zu polygons, %zu rings, %zu segments (want %zu)\n", what,
                p->polygon_count, p->ring_count, got.n, want->n);
    free(got.s);
}

/* ---- lines ---------------------------------------------------------------------- */

static size_t uf_root(size_t *parent, size_t a)
{
    while (parent[a] != a)
        a = parent[a] = parent[parent[a]];
    return a;
}

/* A feature's lines against its edges: the same undirected segments, and
 * as many polylines as the edge set has chains (an open chain for every two
 * ends at vertices where other than two of its edges meet, a closed one for
 * every component whose vertices all have two). */
static void check_lines(const char *what, const hpfc_polygons *p, const uint8_t *in_set)
{
    size_t ne = hpfc_graph_edge_count(G), nv = hpfc_graph_vertex_count(G);
    segs want = {0}, got = {0};
    uint32_t *deg = calloc(nv + 1, sizeof *deg);
    size_t *parent = malloc((nv + 1) * sizeof *parent);
    for (size_t v = 0; v < nv; v++)
        parent[v] = v;
    for (size_t e = 0; e < ne; e++) {
        if (!in_set[e])
            continue;
        uint32_t u, v;
        const int64_t *in;
        size_t n_in;
        hpfc_graph_edge(G, e, &u, &v, &in, &n_in);
        deg[u]++, deg[v]++;
        parent[uf_root(parent, u)] = uf_root(parent, v);
        for (size_t k = 0; k + 1 < n_in + 2; k++) {
            int64_t ax, ay, bx, by;
            dart_point((uint32_t)(2 * e), k, &ax, &ay);
            dart_point((uint32_t)(2 * e), k + 1, &bx, &by);
            if (ax > bx || (ax == bx && ay > by))
                segs_add(&want, bx, by, ax, ay);
            else
                segs_add(&want, ax, ay, bx, by);
        }
    }
    size_t chains = 0;
    uint8_t *open = calloc(nv + 1, 1);
    for (size_t v = 0; v < nv; v++)
        if (deg[v] && deg[v] != 2) {
            chains += deg[v];
            open[uf_root(parent, v)] = 1;
        }
    chains /= 2;
    for (size_t v = 0; v < nv; v++)
        if (deg[v] && uf_root(parent, v) == v && !open[v])
            chains++;
    for (size_t r = 0; r < p->ring_count; r++)
        for (size_t k = p->ring_point[r]; k + 1 < p->ring_point[r + 1]; k++) {
            int64_t ax = p->xy[2 * k], ay = p->xy[2 * k + 1], bx = p->xy[2 * k + 2],
                    by = p->xy[2 * k + 3];
            if (ax > bx || (ax == bx && ay > by))
                segs_add(&got, bx, by, ax, ay);
            else
                segs_add(&got, ax, ay, bx, by);
        }
    int ok = segs_equal(&got, &want);
    CHECK(ok);
    CHECK_EQ_INT(p->ring_count, chains);
    CHECK_EQ_INT(p->polygon_count, 0);
    if (!ok || p->ring_count != chains)
        fprintf(stderr, "  in %s: %zu lines (want %zu), %zu segments (want %zu)\n", what,
                p->ring_count, chains, got.n, want.n);
    free(want.s);
    free(got.s);
    free(deg);
    free(parent);
    free(open);
}

/* ---- one file ------------------------------------------------------------------- */

/* A copy of the file (size bytes) whose SHIX section a reader no longer
 * knows: its tag renamed to an unknown unflagged one, which readers
 * ignore, so the shapes invert LABL, FEAT and EDGF themselves as for a
 * file of 1.2. NULL when the file has no SHIX. */
static uint8_t *without_index(const uint8_t *buf, size_t size)
{
    uint8_t *copy = malloc(size);
    memcpy(copy, buf, size);
    uint64_t dir = hdr_get_header_size(copy) + (uint64_t)FORMAT_LEVEL_ENTRY_SIZE * hdr_get_levels(copy);
    for (uint32_t k = 0; k < hdr_get_section_count(copy); k++) {
        uint8_t *e = copy + dir + (uint64_t)FORMAT_SECTION_ENTRY_SIZE * k;
        if (memcmp(e, FORMAT_TAG_SHIX, 4) == 0) {
            memcpy(e, "shix", 4);
            hdr_set_meta_crc32c(copy, format_meta_crc(copy, hdr_get_meta_size(copy)));
            return copy;
        }
    }
    free(copy);
    return NULL;
}

/* Writes the low k bits of v at bit offset off, MSB first, over what was
 * there. */
static void put_bits(uint8_t *p, uint64_t off, unsigned k, uint64_t v)
{
    for (unsigned i = 0; i < k; i++, off++) {
        uint8_t bit = (uint8_t)(0x80u >> (off & 7));
        if (v >> (k - 1 - i) & 1)
            p[off >> 3] |= bit;
        else
            p[off >> 3] &= (uint8_t)~bit;
    }
}

/* A place in the face table (link *at) and an edge id (*id) to put there
 * that keeps the row ascending but does not bound the row's face: a
 * damage only the inverse check (S46) sees. */
static int wrong_edge(const uint8_t *buf, size_t size, const shix_table *t, uint64_t *at,
                      uint64_t *id)
{
    hpfc_file *f = NULL;
    int found = 0;
    if (hpfc_open_memory(buf, size, 0, &f))
        return 0;
    for (uint64_t row = 0, j = 0; row < t->rows && !found; row++) {
        uint64_t end = format_get(&t->bits, (row + 1) * t->offset_bits, t->offset_bits);
        for (j = format_get(&t->bits, row * t->offset_bits, t->offset_bits); j + 1 < end; j++) {
            uint64_t c = (uint64_t)shix_id(t, j) + 1, l, r;
            if (c < shix_id(t, j + 1) && !hpfc_geometry_edge_faces(f, c, &l, &r) &&
                (l == r || (l != row && r != row))) {
                *at = j + 1, *id = c, found = 1;
                break;
            }
        }
    }
    hpfc_close(f);
    return found;
}

/* The file's SHIX against its sections (hpfc_index_verify), then damaged:
 * an edge of a face's row swapped for one that does not bound the face
 * (the access check refuses it), and a face row emptied into its
 * neighbour (rows that still read but miss links: only verification sees
 * it). The shapes' answers on the damaged copies: known statuses only. */
static void check_index(const uint8_t *buf, size_t size)
{
    hpfc_file *f = NULL;
    hpfc_index_report rep;
    CHECK_EQ_INT(hpfc_open_memory(buf, size, 0, &f), HPFC_OK);
    CHECK_EQ_INT(hpfc_index_verify(f, &rep), HPFC_OK);
    hpfc_section_info si = {0};
    int found = 0;
    for (uint32_t k = 0; f && hpfc_file_get_section(f, k, &si) == HPFC_OK && !found; k++)
        found = memcmp(si.tag, FORMAT_TAG_SHIX, 4) == 0;
    CHECK(found);
    hpfc_close(f);
    if (!found)
        return;
    shix_view v;
    CHECK_EQ_INT(shix_open(&v, buf + si.offset, si.length), HPFC_OK);
    const shix_table *t = &v.face_edges;
    for (int damage = 0; damage < 2 && t->links > 0 && v.faces > 1; damage++) {
        uint8_t *copy = malloc(size);
        memcpy(copy, buf, size);
        uint8_t *table = copy + (t->bits.base - buf);
        if (damage == 0) { /* an edge of a face's row: one that does not bound it */
            uint64_t at = 0, id = 0;
            if (!wrong_edge(buf, size, t, &at, &id)) {
                free(copy);
                continue;
            }
            put_bits(table, t->links_at + at * t->id_bits, t->id_bits, id);
        } else { /* face 0's row given to face 1: face 0 has no edges */
            put_bits(table, t->offset_bits, t->offset_bits, 0);
        }
        CHECK_EQ_INT(hpfc_open_memory(copy, size, HPFC_OPEN_SKIP_CHECKSUM, &f), HPFC_OK);
        int st = f ? hpfc_index_verify(f, &rep) : HPFC_E_ARG;
        CHECK_EQ_INT(st, HPFC_E_CORRUPT);
        hpfc_shapes *s = NULL;
        if (f && hpfc_shapes_create(f, &s) == HPFC_OK) {
            for (uint64_t face = 0; face < v.faces; face++) {
                hpfc_polygons poly;
                st = hpfc_shapes_face_polygons(s, face, &poly);
                CHECK(st == HPFC_OK || st == HPFC_E_CORRUPT);
            }
            hpfc_shapes_free(s);
        }
        hpfc_close(f);
        free(copy);
    }
}

typedef struct packed {
    hpfc_tree *tree;
    uint8_t *buf, *buf2;
    size_t size;
    hpfc_file *f;
} packed;

static int pack(const hpfc_graph *g, uint32_t n0, uint32_t n, int flat, packed *p)
{
    memset(p, 0, sizeof *p);
    hpfc_build_params bp;
    hpfc_build_params_default(&bp);
    bp.root_cols = bp.root_rows = n0;
    bp.cols = bp.rows = n;
    bp.flat = flat;
    hpfc_write_options o = {.face_labels = 1, .geometry = g};
    int st = hpfc_build(g, &bp, &p->tree, NULL);
    if (!st)
        st = check_tree_serialize(p->tree, &o, &p->buf, &p->size, NULL);
    if (!st)
        st = hpfc_open_memory(p->buf, p->size, 0, &p->f);
    return st;
}

static void unpack(packed *p)
{
    hpfc_close(p->f);
    hpfc_free(p->buf);
    free(p->buf2);
    hpfc_tree_free(p->tree);
}

/* Every dart of the file, by key (tests/lib/test_handles.c holds the path form to
 * the key form): its polyline is its edge's, run from the end in
 * its pixel; its twin's is the reverse. */
static void check_darts(const hpfc_file *f)
{
    hpfc_walker *w;
    CHECK_EQ_INT(hpfc_walker_create(f, &w), HPFC_OK);
    hpfc_pixel px;
    int st = hpfc_leaf_first(f, &px), bad = 0;
    size_t darts = 0, cap = 0;
    int64_t *xy = NULL, *txy = NULL;
    while (!st) {
        uint32_t nv = 0;
        hpfc_pixel_vertex_count(w, &px, &nv);
        for (uint32_t k = 0; k < nv; k++) {
            uint64_t v = HPFC_KEY_INVALID;
            uint32_t deg = 0;
            hpfc_pixel_vertex_key(w, &px, k, &v);
            hpfc_key_degree(w, v, &deg);
            for (uint32_t j = 0; j < deg; j++) {
                uint64_t d = HPFC_KEY_INVALID, t = HPFC_KEY_INVALID, e, te;
                int rev, trev;
                size_t n, tn;
                hpfc_key_vertex_dart(w, v, j, &d);
                hpfc_key_twin(w, d, &t);
                if (hpfc_geometry_key_edge(w, d, &e, &rev) ||
                    hpfc_geometry_key_edge(w, t, &te, &trev) || e != te || rev == trev ||
                    hpfc_geometry_key_points(w, d, NULL, 0, &n) ||
                    hpfc_geometry_key_points(w, t, NULL, 0, &tn) || n != tn ||
                    n != dart_npoints((uint32_t)(2 * e))) {
                    bad++;
                    continue;
                }
                if (n > cap) {
                    cap = 2 * n;
                    xy = realloc(xy, 2 * cap * sizeof *xy);
                    txy = realloc(txy, 2 * cap * sizeof *txy);
                }
                size_t short_n = 0; /* one point short: the count needed */
                if (hpfc_geometry_key_points(w, d, xy, n - 1, &short_n) !=
                        HPFC_E_BUFFER_SMALL || short_n != n)
                    bad++;
                hpfc_geometry_key_points(w, d, xy, cap, &n);
                hpfc_geometry_key_points(w, t, txy, cap, &tn);
                int64_t b[4]; /* a vertex's darts start in its leaf */
                hpfc_pixel_bounds(f, &px, &b[0], &b[1], &b[2], &b[3]);
                if (xy[0] < b[0] || xy[0] >= b[2] || xy[1] < b[1] || xy[1] >= b[3])
                    bad++;
                for (size_t q = 0; q < n; q++) {
                    int64_t x, y;
                    dart_point((uint32_t)(2 * e + (uint64_t)rev), q, &x, &y);
                    if (xy[2 * q] != x || xy[2 * q + 1] != y ||
                        txy[2 * (n - 1 - q)] != x || txy[2 * (n - 1 - q) + 1] != y)
                        bad++;
                }
                darts++;
            }
        }
        st = hpfc_leaf_next(f, &px);
    }
    CHECK_EQ_INT(st, HPFC_E_NO_PIXEL);
    CHECK_EQ_INT(bad, 0);
    CHECK_EQ_INT(darts, 2 * hpfc_graph_edge_count(G));
    free(xy);
    free(txy);
    hpfc_walker_free(w);
}

/* The library's face of each oracle walk (through the left/right faces of
 * one of its darts: the walk's face is on the dart's right), all darts of a
 * walk agreeing. */
static uint64_t *walk_faces(const hpfc_file *f, const oracle *o)
{
    uint64_t *wf = malloc((o->nwalks + 1) * sizeof *wf);
    for (size_t w = 0; w < o->nwalks; w++)
        wf[w] = UINT64_MAX;
    int bad = 0;
    for (uint32_t d = 0; d < o->nd; d++) {
        uint64_t l, r;
        if (hpfc_geometry_edge_faces(f, d / 2, &l, &r)) {
            bad++;
            continue;
        }
        uint64_t face = d & 1 ? l : r;
        if (wf[o->walk[d]] == UINT64_MAX)
            wf[o->walk[d]] = face;
        else if (wf[o->walk[d]] != face)
            bad++;
    }
    CHECK_EQ_INT(bad, 0);
    return wf;
}

/* Every face against the oracle; then random features. */
/* Each face's polygons against the oracle's walks. */
static void check_faces(const char *name, hpfc_shapes *s, const oracle *o, const uint64_t *wf,
                        const s128 *face_area)
{
    uint64_t nf = hpfc_shapes_face_count(s);
    /* per face: its darts with it on the left, bridges left out */
    for (uint64_t face = 0; face < nf; face++) {
        segs want = {0};
        for (uint32_t d = 0; d < o->nd; d++)
            if (wf[o->walk[d ^ 1]] == face && o->walk[d] != o->walk[d ^ 1] &&
                wf[o->walk[d]] != face)
                segs_of_dart(&want, d); /* face on the right of the twin: on d's left */
        hpfc_polygons poly;
        char what[160];
        snprintf(what, sizeof what, "%s face %llu", name, (unsigned long long)face);
        int st = hpfc_shapes_face_polygons(s, face, &poly);
        CHECK_EQ_INT(st, HPFC_OK);
        if (!st)
            check_answer(what, &poly, &want, face_area[face], face == 0 ? 0 : want.n ? 1 : -1);
        free(want.s);
    }
    CHECK_EQ_INT(hpfc_shapes_face_polygons(s, nf, &(hpfc_polygons){0}), HPFC_E_ARG);
}

/* The features' polygons and lines against the oracle, k's faces those
 * with member[k * nf + face], its lines the edges with on_edge[k * ne + e]. */
static void check_features(const char *name, hpfc_shapes *s, const oracle *o, const uint64_t *wf,
                           const s128 *face_area, const uint8_t *member, const uint8_t *on_edge,
                           uint32_t nfeat, size_t ne)
{
    uint64_t nf = hpfc_shapes_face_count(s);
    for (uint32_t k = 0; k < nfeat; k++) {
        segs want = {0};
        s128 area = 0;
        for (uint64_t face = 0; face < nf; face++)
            if (member[k * nf + face])
                area += face_area[face];
        for (uint32_t d = 0; d < o->nd; d++) {
            uint64_t left = wf[o->walk[d ^ 1]], right = wf[o->walk[d]];
            if (member[k * nf + left] && !member[k * nf + right])
                segs_of_dart(&want, d);
        }
        hpfc_polygons poly;
        char what[160];
        snprintf(what, sizeof what, "%s feature %u", name, k);
        int st = hpfc_shapes_feature_polygons(s, k, &poly);
        CHECK_EQ_INT(st, HPFC_OK);
        if (!st)
            check_answer(what, &poly, &want, area, -1);
        free(want.s);
        snprintf(what, sizeof what, "%s lines of feature %u", name, k);
        st = hpfc_shapes_feature_polylines(s, k, &poly);
        CHECK_EQ_INT(st, HPFC_OK);
        if (!st)
            check_lines(what, &poly, on_edge + k * ne);
    }
}

/* The shapes of the file at buf (size bytes) as `check` reads them, with
 * its SHIX section and with the section hidden (the tables inverted in
 * memory, as for a 1.2 file). */
typedef void (*shapes_check)(const char *name, hpfc_shapes *s, const void *ctx);

static void both_ways(const char *name, const uint8_t *buf, size_t size, shapes_check check,
                      const void *ctx)
{
    uint8_t *hidden = without_index(buf, size);
    CHECK(hidden != NULL);
    for (int way = 0; way < 2; way++) {
        const uint8_t *bytes = way ? hidden : buf;
        hpfc_file *f = NULL;
        hpfc_shapes *s = NULL;
        if (!bytes)
            continue;
        int st = hpfc_open_memory(bytes, size, 0, &f);
        if (!st)
            st = hpfc_shapes_create(f, &s);
        CHECK_EQ_INT(st, HPFC_OK);
        char what[128];
        snprintf(what, sizeof what, "%s%s", name, way ? " (no SHIX)" : "");
        if (!st)
            check(what, s, ctx);
        hpfc_shapes_free(s);
        hpfc_close(f);
    }
    free(hidden);
}

typedef struct shapes_ctx {
    const oracle *o;
    const uint64_t *wf;
    const s128 *face_area;
    const uint8_t *member, *on_edge;
    uint32_t nfeat;
    size_t ne;
    const uint32_t *layer; /* each feature's */
    uint32_t nlayer;
} shapes_ctx;

static void faces_way(const char *name, hpfc_shapes *s, const void *ctx)
{
    const shapes_ctx *c = ctx;
    check_faces(name, s, c->o, c->wf, c->face_area);
}

/* hpfc_shapes_layer_kinds against the features' faces in the input. */
static void check_layer_kinds(const char *name, hpfc_shapes *s, const shapes_ctx *c)
{
    uint64_t nf = hpfc_shapes_face_count(s);
    uint8_t want[8] = {0}, got[8];
    uint64_t want_count[8] = {0}, count[8];
    for (uint32_t k = 0; k < c->nfeat; k++) {
        int polygon = 0;
        for (uint64_t face = 0; face < nf; face++)
            polygon |= c->member[k * nf + face];
        want[c->layer[k]] |= polygon ? HPFC_KIND_POLYGONS : HPFC_KIND_LINES;
        want_count[c->layer[k]]++;
    }
    memset(got, 0xee, sizeof got);
    memset(count, 0xee, sizeof count);
    CHECK_EQ_INT(hpfc_shapes_layer_kinds(s, got, count, c->nlayer), HPFC_OK);
    for (uint32_t l = 0; l < c->nlayer; l++)
        if (got[l] != want[l] || count[l] != want_count[l]) {
            CHECK(0);
            fprintf(stderr, "%s: layer %u holds kinds %d of %llu features, want %d of %llu\n",
                    name, l, got[l], (unsigned long long)count[l], want[l],
                    (unsigned long long)want_count[l]);
        }
    memset(got, 0xee, sizeof got);
    CHECK_EQ_INT(hpfc_shapes_layer_kinds(s, got, NULL, c->nlayer), HPFC_OK);
    CHECK(memcmp(got, want, c->nlayer) == 0);
    CHECK_EQ_INT(hpfc_shapes_layer_kinds(s, got, count, c->nlayer + 1), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_shapes_layer_kinds(s, NULL, count, c->nlayer), HPFC_E_ARG);
}

static void features_way(const char *name, hpfc_shapes *s, const void *ctx)
{
    const shapes_ctx *c = ctx;
    check_features(name, s, c->o, c->wf, c->face_area, c->member, c->on_edge, c->nfeat, c->ne);
    check_layer_kinds(name, s, c);
}

static void check_file(const char *name, const packed *p, uint64_t seed)
{
    oracle o;
    oracle_build(&o);
    check_darts(p->f);
    hpfc_shapes *s;
    int st = hpfc_shapes_create(p->f, &s);
    CHECK_EQ_INT(st, HPFC_OK);
    if (st) {
        oracle_free(&o);
        return;
    }
    uint64_t nf = hpfc_shapes_face_count(s);
    hpfc_shapes_free(s);
    uint64_t *wf = walk_faces(p->f, &o);
    s128 *face_area = calloc(nf + 1, sizeof *face_area);
    for (size_t w = 0; w < o.nwalks; w++)
        if (wf[w] < nf)
            face_area[wf[w]] -= o.walk_area2[w]; /* walks have the face on the right */
    shapes_ctx ctx = {.o = &o, .wf = wf, .face_area = face_area};
    both_ways(name, p->buf, p->size, faces_way, &ctx);
    check_index(p->buf, p->size);

    /* features: three, each a random set of bounded faces, and a fourth
     * with lines only, in three layers */
    enum { NFEAT = 4, NLAYER = 3 };
    uint32_t *start = calloc(nf + 1, sizeof *start), *links = malloc(NFEAT * nf * sizeof *links);
    uint8_t *member = calloc(NFEAT * nf + 1, 1);
    gen_rng rng;
    gen_rng_seed(&rng, seed);
    uint32_t nl = 0;
    for (uint64_t face = 0; face < nf; face++) {
        start[face] = nl;
        for (uint32_t k = 0; k < NFEAT - 1 && face > 0; k++)
            if (gen_rng_below(&rng, 3) == 0 || (k == 0 && face % 2)) {
                links[nl++] = k;
                member[k * nf + face] = 1;
            }
    }
    start[nf] = nl;
    int64_t fid[NFEAT] = {0, 1, 2, 3};
    uint32_t layer[NFEAT] = {0, 1, 1, 2};
    const char *lname[NLAYER] = {"random", "more", "lines"};
    hpfc_feature_table ft = {.feature_count = NFEAT, .fid = fid, .layer = layer,
                             .layer_count = NLAYER, .layer_name = lname, .face_count = (uint32_t)nf,
                             .face_start = start, .face_feature = links};
    /* and each feature's lines: a random set of edges (EDGF) */
    size_t ne = hpfc_graph_edge_count(G);
    uint32_t *estart = calloc(ne + 1, sizeof *estart), *elinks = malloc(NFEAT * ne * sizeof *elinks);
    uint8_t *on_edge = calloc(NFEAT * ne + 1, 1);
    uint32_t nel = 0;
    for (size_t e = 0; e < ne; e++) {
        estart[e] = nel;
        for (uint32_t k = 0; k < NFEAT; k++)
            if (gen_rng_below(&rng, k + 2) == 0) {
                elinks[nel++] = k;
                on_edge[k * ne + e] = 1;
            }
    }
    estart[ne] = nel;
    hpfc_edge_feature_table eft = {.edge_count = (uint32_t)ne, .feature_count = NFEAT,
                                   .edge_start = estart, .edge_feature = elinks};
    hpfc_write_options wo = {.features = &ft, .face_labels = 1, .edge_features = &eft};
    uint8_t *buf = NULL;
    size_t size;
    st = hpfc_file_serialize(p->f, &wo, &buf, &size, NULL);
    CHECK_EQ_INT(st, HPFC_OK);
    if (!st) {
        ctx.member = member, ctx.on_edge = on_edge, ctx.nfeat = NFEAT, ctx.ne = ne;
        ctx.layer = layer, ctx.nlayer = NLAYER;
        both_ways(name, buf, size, features_way, &ctx);
        check_index(buf, size);
    }
    hpfc_free(buf);
    free(start);
    free(links);
    free(member);
    free(estart);
    free(elinks);
    free(on_edge);
    free(face_area);
    free(wf);
    oracle_free(&o);
}

static void run_graph(const char *name, const hpfc_graph *g, uint32_t n0, uint32_t n, int flat,
                      uint64_t seed)
{
    packed p;
    G = g;
    int st = pack(g, n0, n, flat, &p);
    CHECK_EQ_INT(st, HPFC_OK);
    if (!st)
        check_file(name, &p, seed);
    unpack(&p);
}

/* ---- hand-made pinches ---------------------------------------------------------- */

static hpfc_graph *graph_of(const int64_t *v, size_t nv, const uint32_t *e, size_t ne)
{
    hpfc_graph *g;
    hpfc_graph_create(&g);
    for (size_t k = 0; k < nv; k++)
        hpfc_graph_add_vertex(g, v[2 * k], v[2 * k + 1], NULL);
    for (size_t k = 0; k < ne; k++)
        hpfc_graph_add_edge(g, e[2 * k], e[2 * k + 1], NULL, 0, NULL);
    return g;
}

static void run_pinches(void)
{
    /* a square around a bow tie: two triangles meeting at vertex 4 */
    static const int64_t bow_v[] = {0, 0, 100, 0, 100, 100, 0, 100, 50, 50,
                                    20, 40, 20, 60, 80, 40, 80, 60};
    static const uint32_t bow_e[] = {0, 1, 1, 2, 2, 3, 3, 0, 4, 5, 5, 6, 6, 4, 4, 7, 7, 8, 8, 4};
    /* a square whose bottom side has a vertex (4) that a triangle inside
     * touches: a hole touching its face's outer ring */
    static const int64_t touch_v[] = {0, 0, 100, 0, 100, 100, 0, 100, 50, 0, 30, 40, 70, 40};
    static const uint32_t touch_e[] = {0, 4, 4, 1, 1, 2, 2, 3, 3, 0, 4, 5, 5, 6, 6, 4};
    /* three triangles around vertex 4: six arms at one point */
    static const int64_t fan_v[] = {0, 0, 100, 0, 100, 100, 0, 100, 50, 50,
                                    80, 45, 80, 55, 35, 80, 25, 75, 25, 25, 35, 20};
    static const uint32_t fan_e[] = {0, 1, 1, 2, 2, 3, 3, 0, 4, 5, 5, 6, 6, 4,
                                     4, 7, 7, 8, 8, 4, 4, 9, 9, 10, 10, 4};
    /* four triangles touching corner to corner around a middle face: their
     * union is four polygons, not one with a hole touching it four times */
    static const int64_t ring_v[] = {0, 0, 200, 0, 200, 200, 0, 200,
                                     100, 60, 140, 100, 100, 140, 60, 100,
                                     120, 40, 160, 120, 80, 160, 40, 80};
    static const uint32_t ring_e[] = {0, 1, 1, 2, 2, 3, 3, 0,
                                      4, 8, 8, 5, 5, 4, 5, 9, 9, 6, 6, 5,
                                      6, 10, 10, 7, 7, 6, 7, 11, 11, 4, 4, 7};
    /* five nested squares: a feature of every other annulus is islands in
     * lakes in islands, each hole inside several outer rings, owned by the
     * smallest */
    int64_t nest_v[40];
    uint32_t nest_e[40];
    for (int k = 0; k < 5; k++) {
        int64_t lo = 40 * k, hi = 400 - 40 * k;
        int64_t sq[8] = {lo, lo, hi, lo, hi, hi, lo, hi};
        memcpy(nest_v + 8 * k, sq, sizeof sq);
        for (int j = 0; j < 4; j++) {
            nest_e[8 * k + 2 * j] = (uint32_t)(4 * k + j);
            nest_e[8 * k + 2 * j + 1] = (uint32_t)(4 * k + (j + 1) % 4);
        }
    }
    hpfc_graph *g = graph_of(nest_v, 20, nest_e, 20);
    for (uint64_t seed = 0; seed < 40; seed++)
        run_graph("nested squares", g, 4, 2, 0, seed);
    hpfc_graph_free(g);
    g = graph_of(ring_v, 12, ring_e, 16);
    for (uint64_t seed = 0; seed < 40; seed++)
        run_graph("corner ring", g, 4, 2, 0, seed);
    hpfc_graph_free(g);
    g = graph_of(fan_v, 11, fan_e, 13);
    for (uint64_t seed = 0; seed < 8; seed++)
        run_graph("fan", g, 4, 2, 0, seed);
    hpfc_graph_free(g);
    g = graph_of(bow_v, 9, bow_e, 10);
    run_graph("bow tie", g, 4, 2, 0, 1);
    run_graph("bow tie flat", g, 1, 2, 1, 2);
    hpfc_graph_free(g);
    g = graph_of(touch_v, 7, touch_e, 8);
    run_graph("touching hole", g, 4, 2, 0, 3);
    run_graph("touching hole 1x1", g, 1, 2, 0, 4);
    hpfc_graph_free(g);
}

/* n points of xy through hpfc_user_points, each against hpfc_user_point
 * bit for bit; the first `oracle` values also against libc's correctly
 * rounded reading of "vEe". Returns the number of disagreements. */
static size_t user_points_bad(const hpfc_file *f, const int64_t *xy, size_t n, double *uv,
                              size_t oracle, int32_t e)
{
    hpfc_user_points(f, xy, n, uv);
    size_t bad = 0;
    for (size_t k = 0; k < 2 * n; k += 2) {
        double ux, uy;
        hpfc_user_point(f, xy[k], xy[k + 1], &ux, &uy);
        bad += memcmp(&ux, &uv[k], sizeof ux) || memcmp(&uy, &uv[k + 1], sizeof uy);
        if (k < oracle && e >= -22 && e <= 22) {
            char text[64];
            snprintf(text, sizeof text, "%lldE%d", (long long)xy[k], (int)e);
            double want = strtod(text, NULL);
            bad += memcmp(&want, &uv[k], sizeof want) != 0;
        }
    }
    return bad;
}

/* hpfc_user_points against hpfc_user_point, bit for bit, over the whole
 * exponent range (the batch has its own paths for |e| <= 22: one for
 * coordinates all in (-2^51, 2^51), as lattice points are, one for any),
 * and against libc's correctly rounded decimal reading of "vEe" where one
 * rounding is all there is (|v| < 2^53, |e| <= 22). */
static void run_user_points(void)
{
    static const int32_t exps[] = {-30, -23, -22, -21, -7, -1, 0, 1, 5, 21, 22, 23, 30};
    static const int64_t tri[] = {0, 0, 1000, 0, 0, 1000};
    static const uint32_t tri_e[] = {0, 1, 1, 2, 2, 0};
    enum { N = 4096 };
    /* values: [0, N) below 2^50 with the edges of the short path's range,
     * [N, 3N/2) below 2^53 beginning with the first values past, then
     * up to 2^62 */
    static const int64_t edges[] = {-4, -1, 0, 1, 3, INT64_C(2251799813685247),
                                    -INT64_C(2251799813685248), -INT64_C(2251799813685247)};
    int64_t *xy = malloc(2 * N * sizeof *xy);
    double *uv = malloc(2 * N * sizeof *uv);
    CHECK(xy && uv);
    uint64_t r = 0x9e3779b97f4a7c15u;
    for (size_t k = 0; xy && k < 2 * N; k++) {
        r ^= r << 13, r ^= r >> 7, r ^= r << 17;
        int bits = k < N ? 50 : k < 3 * N / 2 ? 53 : 62;
        int64_t v = (int64_t)(r >> (64 - bits)) - (INT64_C(1) << (bits - 1));
        xy[k] = k < 8 ? edges[k] : v;
    }
    if (xy) {
        xy[N] = INT64_C(2251799813685249); /* 2^51 + 1, 2^51: the first two past */
        xy[N + 1] = INT64_C(2251799813685248);
        xy[N + 2] = -INT64_C(2251799813685249);
        xy[N + 3] = 0;
    }
    for (size_t q = 0; xy && uv && q < sizeof exps / sizeof *exps; q++) {
        hpfc_graph *g = graph_of(tri, 3, tri_e, 3);
        CHECK_EQ_INT(hpfc_graph_set_unit_exp10(g, exps[q]), HPFC_OK);
        packed p;
        int st = pack(g, 4, 2, 0, &p);
        CHECK_EQ_INT(st, HPFC_OK);
        if (!st) {
            /* the short path (every value below 2^51), then the whole array */
            CHECK_EQ_INT(user_points_bad(p.f, xy, N / 2, uv, N, exps[q]), 0);
            CHECK_EQ_INT(user_points_bad(p.f, xy + N, 1, uv, 2, exps[q]), 0);
            CHECK_EQ_INT(user_points_bad(p.f, xy + N + 2, 1, uv, 2, exps[q]), 0);
            CHECK_EQ_INT(user_points_bad(p.f, xy + N, N / 2, uv, N / 2, exps[q]), 0);
            CHECK_EQ_INT(user_points_bad(p.f, xy, N, uv, 3 * N / 2, exps[q]), 0);
        }
        unpack(&p);
        hpfc_graph_free(g);
    }
    free(xy);
    free(uv);
}

int main(void)
{
    check_use_test_layout();
    run_user_points();
    run_pinches();
    for (int k = 0; k < GEN_SPECIAL_COUNT; k++) {
        hpfc_graph *g;
        if (gen_special(k, &g))
            continue;
        run_graph(gen_special_name(k), g, 4, 2, 0, (uint64_t)k);
        run_graph(gen_special_name(k), g, 1, 3, 0, (uint64_t)k + 100);
        hpfc_graph_free(g);
    }
    const char *root = getenv("HPFC_TEST_DATA");
    static const char *const fixtures[] = {"crack_dead_end.pfc", "loop.pfc", "multi_edges.pfc",
                                           "polyline_decimals.pfc", "square_diagonal.pfc",
                                           "two_components_hole.pfc", "crlf_tabs.pfc"};
    for (size_t k = 0; root && k < sizeof fixtures / sizeof *fixtures; k++) {
        char path[1024];
        snprintf(path, sizeof path, "%s/valid/%s", root, fixtures[k]);
        hpfc_graph *g;
        int st = hpfc_pfc_read_file(path, &g, NULL);
        CHECK_EQ_INT(st, HPFC_OK);
        if (st)
            continue;
        run_graph(fixtures[k], g, 4, 2, 0, k);
        hpfc_graph_free(g);
    }
    for (uint64_t seed = 1; seed <= 12; seed++) {
        hpfc_graph *g;
        char name[64];
        snprintf(name, sizeof name, "delaunay seed %llu", (unsigned long long)seed);
        if (gen_delaunay(seed, 60 + 20 * seed, 1 << 12, 0.1 * (double)(seed % 6), &g) == 0) {
            run_graph(name, g, 4 + (uint32_t)(seed % 3) * 4, 2 + (uint32_t)(seed % 2), 0, seed);
            hpfc_graph_free(g);
        }
        snprintf(name, sizeof name, "polyline seed %llu", (unsigned long long)seed);
        if (gen_polyline(seed, 80 + 10 * seed, 1 << 12, 0.5, &g) == 0) {
            run_graph(name, g, 8, 2, seed % 4 == 0, seed + 50);
            hpfc_graph_free(g);
        }
    }
    return check_report("shapes");
}
