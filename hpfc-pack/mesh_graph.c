/*
 * Triangle mesh to planar graph (mesh_graph.h). Every decision after the
 * lattice mapping is made on lattice integers; the only doubles compared are
 * the input coordinates themselves (for the bounding box).
 */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_graph.h"

__extension__ typedef __int128 i128;
__extension__ typedef unsigned __int128 u128;

#define NONE UINT32_MAX

static int fail(hpfc_diag *diag, int status, const char *fmt, ...)
{
    if (diag) {
        memset(diag, 0, sizeof *diag);
        diag->status = status;
        diag->edge[0] = diag->edge[1] = -1;
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(diag->message, sizeof diag->message, fmt, ap);
        va_end(ap);
    }
    return status;
}

/* ---- exact lattice mapping ------------------------------------------------- */

static const uint64_t POW5[28] = {
    1ull, 5ull, 25ull, 125ull, 625ull, 3125ull, 15625ull, 78125ull, 390625ull,
    1953125ull, 9765625ull, 48828125ull, 244140625ull, 1220703125ull, 6103515625ull,
    30517578125ull, 152587890625ull, 762939453125ull, 3814697265625ull,
    19073486328125ull, 95367431640625ull, 476837158203125ull, 2384185791015625ull,
    11920928955078125ull, 59604644775390625ull, 298023223876953125ull,
    1490116119384765625ull, 7450580596923828125ull,
};

static int bit_length(u128 v)
{
    int n = 0;
    while (v) {
        v >>= 1;
        n++;
    }
    return n;
}

/* A finite v as sign, odd magnitude and binary exponent: |v| = mag * 2^k
 * (mag = 0, k = 0 for a zero). frexp and the scaling by 2^53 are exact. */
static void decompose(double v, int *neg, uint64_t *mag, int *k)
{
    int ex;
    double f = frexp(fabs(v), &ex);
    uint64_t m = (uint64_t)ldexp(f, 53);
    *neg = v < 0;
    if (m == 0) {
        *mag = 0, *k = 0;
        return;
    }
    int tz = __builtin_ctzll(m);
    *mag = m >> tz;
    *k = ex - 53 + tz;
}

int mesh_decimal_digits(double v)
{
    int neg, k;
    uint64_t mag;
    decompose(v, &neg, &mag, &k);
    return mag && k < 0 ? -k : 0;
}

int mesh_lattice_coord(double v, int32_t exp10, int64_t *out)
{
    if (exp10 < MESH_UNIT_EXP10_MIN || exp10 > MESH_UNIT_EXP10_MAX)
        return HPFC_E_ARG;
    if (!isfinite(v))
        return HPFC_E_EXTENT;
    int neg, k;
    uint64_t mag;
    decompose(v, &neg, &mag, &k);
    u128 q = 0;
    if (mag && exp10 <= 0) {
        /* |v| / 10^e = mag * 5^-e * 2^(k - e) */
        u128 p = (u128)mag * POW5[-exp10]; /* < 2^53 * 2^63 */
        int s = k - exp10;
        if (s >= 0) {
            if (bit_length(p) + s > 41) /* at least 2^41 */
                return HPFC_E_EXTENT;
            q = p << s;
        } else if (-s < 120) {
            q = (p + ((u128)1 << (-s - 1))) >> -s;
        } /* else below 2^116 / 2^120: rounds to 0 */
    } else if (mag) {
        /* |v| / 10^e = mag * 2^(k - e) / 5^e, rounded as floor(n / d + 1/2) */
        u128 d = POW5[exp10];
        int t = k - exp10;
        if (t >= 0) {
            if (bit_length(mag) + t > 106) /* at least 2^105 / 2^63 */
                return HPFC_E_EXTENT;
            u128 n = (u128)mag << t;
            q = (2 * n + d) / (2 * d);
        } else if (bit_length(d) - t <= 126) {
            d <<= -t;
            q = (2 * (u128)mag + d) / (2 * d);
        } /* else d > 2^125 > 2 * mag: rounds to 0 */
    }
    if (q > (u128)HPFC_COORD_MAX)
        return HPFC_E_EXTENT;
    *out = neg ? -(int64_t)q : (int64_t)q;
    return HPFC_OK;
}

/* An exact decimal rendering of lattice value v * 10^e ("-12.5", "3000"). */
static void format_lattice(int64_t v, int32_t e, char *buf, size_t size)
{
    char digits[24];
    int n = snprintf(digits, sizeof digits, "%llu",
                     (unsigned long long)(v < 0 ? -(uint64_t)v : (uint64_t)v));
    const char *sign = v < 0 ? "-" : "";
    if (e >= 0 || v == 0) {
        snprintf(buf, size, "%s%s%.*s", sign, digits, v ? (int)e : 0,
                 "000000000000000000000000000000");
        return;
    }
    int frac = -e;
    while (frac > 0 && n > 1 && digits[n - 1] == '0') /* drop trailing zeros */
        digits[--n] = '\0', frac--;
    if (frac == 0)
        snprintf(buf, size, "%s%s", sign, digits);
    else if (n > frac)
        snprintf(buf, size, "%s%.*s.%s", sign, n - frac, digits, digits + n - frac);
    else
        snprintf(buf, size, "%s0.%.*s%s", sign, frac - n, "000000000000000000000000000000",
                 digits);
}

/* ---- unit choice ------------------------------------------------------------ */

typedef struct bbox {
    double x0, y0, x1, y1;
} bbox;

/* The lattice box of b in unit 10^e, or nonzero when a corner does not fit.
 * The mapping is monotone, so the corners bound every used point. */
static int lattice_box(const bbox *b, int32_t e, int64_t box[4])
{
    return mesh_lattice_coord(b->x0, e, &box[0]) || mesh_lattice_coord(b->y0, e, &box[1]) ||
           mesh_lattice_coord(b->x1, e, &box[2]) || mesh_lattice_coord(b->y1, e, &box[3]);
}

static int choose_unit(const bbox *b, int digits, int32_t *e, int *exact)
{
    int64_t box[4];
    if (digits <= -MESH_UNIT_EXP10_MIN && !lattice_box(b, -digits, box)) {
        *e = -digits;
        *exact = 1;
        return HPFC_OK;
    }
    const int64_t span = (int64_t)1 << MESH_EXTENT_BITS;
    for (int32_t u = MESH_UNIT_EXP10_MIN; u <= MESH_UNIT_EXP10_MAX; u++) {
        if (!lattice_box(b, u, box) && box[2] - box[0] <= span && box[3] - box[1] <= span) {
            *e = u;
            *exact = 0;
            return HPFC_OK;
        }
    }
    return HPFC_E_EXTENT;
}

/* ---- sorting helpers ---------------------------------------------------------- */

typedef struct point_key {
    int64_t x, y;
    uint32_t index;
} point_key;

static int cmp_point_key(const void *pa, const void *pb)
{
    const point_key *a = pa, *b = pb;
    if (a->x != b->x)
        return a->x < b->x ? -1 : 1;
    if (a->y != b->y)
        return a->y < b->y ? -1 : 1;
    return a->index < b->index ? -1 : a->index > b->index;
}

/* Three vertices (sorted) and the triangle's index; a split (lo, hi, mid); a
 * side record (u < v, third vertex w); an edge (u < v): all sorted as
 * uint32 tuples. */
typedef struct quad {
    uint32_t a, b, c, d;
} quad;

static int cmp_quad(const void *pa, const void *pb)
{
    const quad *p = pa, *q = pb;
    if (p->a != q->a)
        return p->a < q->a ? -1 : 1;
    if (p->b != q->b)
        return p->b < q->b ? -1 : 1;
    if (p->c != q->c)
        return p->c < q->c ? -1 : 1;
    return p->d < q->d ? -1 : p->d > q->d;
}

/* Sorts quads whose first field is a vertex below nv: a counting sort on
 * that field, then each bucket (a vertex's few incident records) by qsort.
 * Falls back to qsort alone when the scratch memory is not there. */
static void sort_quads(quad *q, size_t n, size_t nv)
{
    size_t *start = n > 1 ? calloc(nv + 1, sizeof *start) : NULL;
    quad *tmp = start ? malloc(n * sizeof *tmp) : NULL;
    if (!tmp) {
        free(start);
        if (n > 1)
            qsort(q, n, sizeof *q, cmp_quad);
        return;
    }
    for (size_t i = 0; i < n; i++)
        start[q[i].a + 1]++;
    for (size_t v = 0; v < nv; v++)
        start[v + 1] += start[v];
    for (size_t i = 0; i < n; i++)
        tmp[start[q[i].a]++] = q[i];
    /* start[v] is now the end of bucket v */
    for (size_t v = 0, b = 0; v < nv; b = start[v++])
        if (start[v] - b > 1)
            qsort(tmp + b, start[v] - b, sizeof *tmp, cmp_quad);
    memcpy(q, tmp, n * sizeof *q);
    free(tmp);
    free(start);
}

static void sort3(uint32_t v[3])
{
    uint32_t t;
    if (v[0] > v[1])
        t = v[0], v[0] = v[1], v[1] = t;
    if (v[1] > v[2])
        t = v[1], v[1] = v[2], v[2] = t;
    if (v[0] > v[1])
        t = v[0], v[0] = v[1], v[1] = t;
}

/* ---- the conversion ----------------------------------------------------------- */

typedef struct mesh_state {
    int32_t e;
    size_t nv;           /* merged vertices */
    int64_t *vx, *vy;    /* their lattice points */
    uint32_t *vrep;      /* their lowest point index */
    quad *edges;         /* (u, v, 0, 0), u < v, growing list */
    size_t ne, cap;
} mesh_state;

static int orient_sign(const mesh_state *s, uint32_t a, uint32_t b, uint32_t c)
{
    i128 d = (i128)(s->vx[b] - s->vx[a]) * (s->vy[c] - s->vy[a]) -
             (i128)(s->vy[b] - s->vy[a]) * (s->vx[c] - s->vx[a]);
    return d > 0 ? 1 : d < 0 ? -1 : 0;
}

/* Lexicographic (x, y) order of vertices: along a line, the order of the
 * points on it. */
static int vertex_before(const mesh_state *s, uint32_t a, uint32_t b)
{
    return s->vx[a] != s->vx[b] ? s->vx[a] < s->vx[b] : s->vy[a] < s->vy[b];
}

static int push_edge(mesh_state *s, uint32_t u, uint32_t v)
{
    if (s->ne == s->cap) {
        size_t cap = s->cap ? 2 * s->cap : 64;
        quad *n = cap > SIZE_MAX / sizeof *n ? NULL : realloc(s->edges, cap * sizeof *n);
        if (!n)
            return HPFC_E_NOMEM;
        s->edges = n;
        s->cap = cap;
    }
    s->edges[s->ne++] = (quad){u < v ? u : v, u < v ? v : u, 0, 0};
    return HPFC_OK;
}

static void point_text(const mesh_state *s, uint32_t v, char *buf, size_t size)
{
    char x[64], y[64];
    format_lattice(s->vx[v], s->e, x, sizeof x);
    format_lattice(s->vy[v], s->e, y, sizeof y);
    snprintf(buf, size, "(%s, %s)", x, y);
}

/* Folds: along an edge, at most one triangle on each side. recs are side
 * records (u, v, w, triangle) sorted by (u, v); fills s->edges with one
 * entry per (u, v). */
static int check_sides(mesh_state *s, const quad *recs, size_t nrec, hpfc_diag *diag)
{
    for (size_t i = 0; i < nrec;) {
        size_t j = i;
        uint32_t seen[2] = {NONE, NONE}; /* third vertex seen left, right */
        for (; j < nrec && recs[j].a == recs[i].a && recs[j].b == recs[i].b; j++) {
            int side = orient_sign(s, recs[j].a, recs[j].b, recs[j].c) > 0;
            if (seen[side] == NONE) {
                seen[side] = recs[j].c;
                continue;
            }
            uint32_t p = s->vrep[recs[i].a], q = s->vrep[recs[i].b];
            uint32_t r1 = s->vrep[seen[side]], r2 = s->vrep[recs[j].c];
            char at1[144], at2[144];
            point_text(s, seen[side], at1, sizeof at1);
            point_text(s, recs[j].c, at2, sizeof at2);
            int st = fail(diag, HPFC_E_NONPLANAR,
                          "the mesh folds over itself in x, y: triangles %u-%u-%u and %u-%u-%u "
                          "lie on the same side of their shared edge %u-%u, at points %u %s "
                          "and %u %s (mesh point indices; hpfc-pack does not node meshes)",
                          p, q, r1, p, q, r2, p, q, r1, at1, r2, at2);
            if (diag) {
                diag->has_point = 1;
                diag->x = (double)s->vx[recs[j].c] * pow(10.0, s->e);
                diag->y = (double)s->vy[recs[j].c] * pow(10.0, s->e);
            }
            return st;
        }
        int st = push_edge(s, recs[i].a, recs[i].b);
        if (st)
            return st;
        i = j;
    }
    return HPFC_OK;
}

/* Replaces each edge that is the long side of a collinear triangle by the
 * chain through the middle corners on it, repeatedly (a piece may be a long
 * side too). An edge split once is dropped when it comes back: its chain is
 * already in. splits are (lo, hi, mid, 0) sorted. */
static int split_long_sides(mesh_state *s, const quad *splits, size_t nsplit,
                            mesh_graph_stats *stats)
{
    if (nsplit == 0)
        return HPFC_OK;
    unsigned char *done = calloc(nsplit, 1);
    uint32_t *chain = malloc((nsplit + 2) * sizeof *chain);
    int st = done && chain ? HPFC_OK : HPFC_E_NOMEM;
    /* s->edges grows while we walk it: new pieces are examined in turn */
    for (size_t i = 0; i < s->ne && !st; i++) {
        quad key = {s->edges[i].a, s->edges[i].b, 0, 0};
        size_t lo = 0, hi = nsplit;
        while (lo < hi) {
            size_t mid = lo + (hi - lo) / 2;
            if (cmp_quad(&splits[mid], &key) < 0)
                lo = mid + 1;
            else
                hi = mid;
        }
        if (lo == nsplit || splits[lo].a != key.a || splits[lo].b != key.b)
            continue;
        s->edges[i].c = 1; /* drop this edge */
        if (done[lo])
            continue;
        size_t n = 0;
        chain[n++] = key.a;
        chain[n++] = key.b;
        for (size_t k = lo; k < nsplit && splits[k].a == key.a && splits[k].b == key.b; k++) {
            done[k] = 1;
            if (splits[k].c != chain[n - 1])
                chain[n++] = splits[k].c;
        }
        /* insertion sort along the line; the ends sort to the ends */
        for (size_t k = 1; k < n; k++) {
            uint32_t v = chain[k];
            size_t m = k;
            for (; m > 0 && vertex_before(s, v, chain[m - 1]); m--)
                chain[m] = chain[m - 1];
            chain[m] = v;
        }
        for (size_t k = 0; k + 1 < n && !st; k++)
            if (chain[k] != chain[k + 1])
                st = push_edge(s, chain[k], chain[k + 1]);
        if (stats)
            stats->split_edges++;
    }
    free(done);
    free(chain);
    return st;
}

/* Sorts and dedupes the kept edges (c == 0). */
static void finish_edges(mesh_state *s)
{
    size_t n = 0;
    for (size_t i = 0; i < s->ne; i++)
        if (s->edges[i].c == 0)
            s->edges[n++] = s->edges[i];
    sort_quads(s->edges, n, s->nv);
    size_t m = 0;
    for (size_t i = 0; i < n; i++)
        if (m == 0 || s->edges[m - 1].a != s->edges[i].a || s->edges[m - 1].b != s->edges[i].b)
            s->edges[m++] = s->edges[i];
    s->ne = m;
}

/* The graph of the kept edges: vertices without an edge left out, the others
 * in the order of their lowest point index. */
static int make_graph(const mesh_state *s, hpfc_graph **out, hpfc_diag *diag)
{
    if (s->ne == 0)
        return fail(diag, HPFC_E_EMPTY, "no triangle is left: every one is degenerate on the "
                                        "lattice of unit 10^%d", (int)s->e);
    if (s->ne > UINT32_MAX)
        return fail(diag, HPFC_E_LIMIT, "the mesh has more than 2^32 - 1 edges");
    uint32_t *id = malloc((s->nv ? s->nv : 1) * sizeof *id);
    hpfc_graph *g = NULL;
    int st = id ? hpfc_graph_create(&g) : HPFC_E_NOMEM;
    if (!st)
        st = hpfc_graph_set_unit_exp10(g, s->e);
    if (!st) {
        for (size_t v = 0; v < s->nv; v++)
            id[v] = NONE;
        for (size_t i = 0; i < s->ne; i++)
            id[s->edges[i].a] = id[s->edges[i].b] = 0;
        uint32_t next = 0;
        for (size_t v = 0; v < s->nv && !st; v++)
            if (id[v] == 0) {
                id[v] = next++;
                st = hpfc_graph_add_vertex(g, s->vx[v], s->vy[v], NULL);
            }
    }
    for (size_t i = 0; i < s->ne && !st; i++)
        st = hpfc_graph_add_edge(g, id[s->edges[i].a], id[s->edges[i].b], NULL, 0, NULL);
    free(id);
    if (st) {
        hpfc_graph_free(g);
        return fail(diag, st, "%s", hpfc_strerror(st));
    }
    *out = g;
    return HPFC_OK;
}

/* hpfc_graph_validate, its edges named by mesh points. Graph edge i is
 * s->edges[i]. */
static int validate(const mesh_state *s, const hpfc_graph *g, hpfc_diag *diag)
{
    hpfc_diag d;
    int st = hpfc_graph_validate(g, &d);
    if (st == HPFC_OK)
        return st;
    if (st != HPFC_E_NONPLANAR || d.edge[0] < 0 || d.edge[1] < 0)
        return fail(diag, st, "%s", d.message);
    const quad *e0 = &s->edges[d.edge[0]], *e1 = &s->edges[d.edge[1]];
    st = fail(diag, st,
              "the mesh is not planar in x, y: its edges %u-%u and %u-%u cross or touch at "
              "(%.10g, %.10g) (mesh point indices; hpfc-pack does not node meshes)",
              s->vrep[e0->a], s->vrep[e0->b], s->vrep[e1->a], s->vrep[e1->b], d.x, d.y);
    if (diag) {
        diag->edge[0] = d.edge[0], diag->edge[1] = d.edge[1];
        diag->has_point = d.has_point, diag->x = d.x, diag->y = d.y;
    }
    return st;
}

/* Marks the used points and checks the indices; finds their bounding box and
 * the most decimal digits any of their coordinates needs. */
static int scan_points(const double *pos, size_t dims, size_t npoints, const uint32_t *tri,
                       size_t ntri, unsigned char *used, size_t *nused, bbox *b, int *digits,
                       hpfc_diag *diag)
{
    *nused = 0;
    *digits = 0;
    for (size_t t = 0; t < ntri; t++)
        for (int k = 0; k < 3; k++) {
            uint32_t p = tri[3 * t + k];
            if (p >= npoints)
                return fail(diag, HPFC_E_VERTEX_INDEX,
                            "triangle %zu refers to point %u, but the mesh has %zu points", t, p,
                            npoints);
            if (used[p])
                continue;
            used[p] = 1;
            double x = pos[dims * p], y = pos[dims * p + 1];
            if (!isfinite(x) || !isfinite(y))
                return fail(diag, HPFC_E_EXTENT, "mesh point %u has a coordinate that is not "
                                                 "a finite number", p);
            if (*nused == 0)
                b->x0 = b->x1 = x, b->y0 = b->y1 = y;
            b->x0 = fmin(b->x0, x), b->x1 = fmax(b->x1, x);
            b->y0 = fmin(b->y0, y), b->y1 = fmax(b->y1, y);
            int dx = mesh_decimal_digits(x), dy = mesh_decimal_digits(y);
            *digits = dx > *digits ? dx : *digits;
            *digits = dy > *digits ? dy : *digits;
            ++*nused;
        }
    return HPFC_OK;
}

/* Merges the used points by lattice point: fills s->vx, vy, vrep and the
 * vertex of every used point (pvert), vertices in the order of their lowest
 * point index. */
static int merge_points(const double *pos, size_t dims, size_t npoints,
                        const unsigned char *used, size_t nused, mesh_state *s,
                        uint32_t *pvert, hpfc_diag *diag)
{
    point_key *keys = malloc(nused * sizeof *keys);
    if (!keys)
        return fail(diag, HPFC_E_NOMEM, "out of memory");
    size_t n = 0;
    for (size_t p = 0; p < npoints; p++) {
        if (!used[p])
            continue;
        point_key *k = &keys[n++];
        k->index = (uint32_t)p;
        int st = mesh_lattice_coord(pos[dims * p], s->e, &k->x);
        if (!st)
            st = mesh_lattice_coord(pos[dims * p + 1], s->e, &k->y);
        if (st) {
            free(keys);
            return fail(diag, st, "mesh point %zu (%.17g, %.17g) does not fit the lattice of "
                                  "unit 10^%d", p, pos[dims * p], pos[dims * p + 1], (int)s->e);
        }
    }
    qsort(keys, nused, sizeof *keys, cmp_point_key);
    /* group by lattice point; the group's first key has the lowest index */
    for (size_t i = 0; i < nused; i++) {
        int first = i == 0 || keys[i].x != keys[i - 1].x || keys[i].y != keys[i - 1].y;
        pvert[keys[i].index] = first ? keys[i].index : pvert[keys[i - 1].index];
    }
    free(keys);
    /* pvert holds each point's group leader; number the leaders in order */
    s->vx = malloc(nused * sizeof *s->vx);
    s->vy = malloc(nused * sizeof *s->vy);
    s->vrep = malloc(nused * sizeof *s->vrep);
    if (!s->vx || !s->vy || !s->vrep)
        return fail(diag, HPFC_E_NOMEM, "out of memory");
    s->nv = 0;
    for (size_t p = 0; p < npoints; p++) {
        if (!used[p])
            continue;
        if (pvert[p] == p) {
            (void)mesh_lattice_coord(pos[dims * p], s->e, &s->vx[s->nv]);
            (void)mesh_lattice_coord(pos[dims * p + 1], s->e, &s->vy[s->nv]);
            s->vrep[s->nv] = (uint32_t)p;
            pvert[p] = (uint32_t)s->nv++;
        } else {
            pvert[p] = pvert[pvert[p]]; /* the leader is lower, so already numbered */
        }
    }
    return HPFC_OK;
}

int mesh_graph_build(const double *pos, size_t dims, size_t npoints, const uint32_t *tri,
                     size_t ntri, const mesh_graph_options *opts, hpfc_graph **out,
                     mesh_graph_stats *stats, hpfc_diag *diag)
{
    if (!out)
        return fail(diag, HPFC_E_ARG, "no output graph");
    *out = NULL;
    if (stats)
        memset(stats, 0, sizeof *stats);
    if (dims < 2 || (npoints && !pos) || (ntri && !tri))
        return fail(diag, HPFC_E_ARG, "positions need at least x and y");
    if (opts && opts->fixed_unit &&
        (opts->unit_exp10 < MESH_UNIT_EXP10_MIN || opts->unit_exp10 > MESH_UNIT_EXP10_MAX))
        return fail(diag, HPFC_E_ARG, "lattice unit 10^%d is outside 10^%d .. 10^%d",
                    (int)opts->unit_exp10, MESH_UNIT_EXP10_MIN, MESH_UNIT_EXP10_MAX);
    if (ntri == 0)
        return fail(diag, HPFC_E_EMPTY, "the mesh has no triangle");
    if (npoints > UINT32_MAX || ntri > SIZE_MAX / (3 * sizeof(quad)))
        return fail(diag, HPFC_E_LIMIT, "the mesh has too many points or triangles");

    mesh_state s = {0};
    unsigned char *used = calloc(npoints, 1);
    uint32_t *pvert = malloc(npoints * sizeof *pvert);
    quad *recs = NULL, *splits = NULL;
    hpfc_graph *g = NULL;
    size_t nused, nrec = 0, nsplit = 0;
    bbox b = {0};
    int digits, exact = 1, st;
    if (!used || !pvert) {
        st = fail(diag, HPFC_E_NOMEM, "out of memory");
        goto done;
    }
    st = scan_points(pos, dims, npoints, tri, ntri, used, &nused, &b, &digits, diag);
    if (st)
        goto done;
    if (opts && opts->fixed_unit) {
        s.e = opts->unit_exp10;
        exact = digits <= -s.e;
    } else if ((st = choose_unit(&b, digits, &s.e, &exact)) != HPFC_OK) {
        st = fail(diag, st, "the mesh's coordinates (x %.9g .. %.9g, y %.9g .. %.9g) are too "
                            "large for the lattice", b.x0, b.x1, b.y0, b.y1);
        goto done;
    }
    st = merge_points(pos, dims, npoints, used, nused, &s, pvert, diag);
    if (st)
        goto done;

    /* triangles: drop the degenerate ones and repeats */
    recs = malloc(3 * ntri * sizeof *recs);
    if (!recs) {
        st = fail(diag, HPFC_E_NOMEM, "out of memory");
        goto done;
    }
    size_t nt = 0, ndegenerate = 0;
    for (size_t t = 0; t < ntri; t++) {
        uint32_t v[3] = {pvert[tri[3 * t]], pvert[tri[3 * t + 1]], pvert[tri[3 * t + 2]]};
        sort3(v);
        if (v[0] == v[1] || v[1] == v[2])
            ndegenerate++;
        else
            recs[nt++] = (quad){v[0], v[1], v[2], (uint32_t)t};
    }
    sort_quads(recs, nt, s.nv);
    size_t nunique = 0;
    for (size_t i = 0; i < nt; i++)
        if (nunique == 0 || recs[i].a != recs[nunique - 1].a || recs[i].b != recs[nunique - 1].b ||
            recs[i].c != recs[nunique - 1].c)
            recs[nunique++] = recs[i];
    /* collinear triangles become splits; the others give three side records.
     * The triangles move to the last third of recs: the records, written
     * from the start, never overtake a triangle not yet read. */
    splits = malloc((nunique ? nunique : 1) * sizeof *splits);
    if (!splits) {
        st = fail(diag, HPFC_E_NOMEM, "out of memory");
        goto done;
    }
    quad *tris = recs + 2 * ntri;
    memmove(tris, recs, nunique * sizeof *recs);
    for (size_t i = 0; i < nunique; i++) {
        uint32_t a = tris[i].a, bb = tris[i].b, c = tris[i].c;
        if (orient_sign(&s, a, bb, c) == 0) {
            /* the middle one lies between the others in (x, y) order */
            uint32_t lo = a, mid = bb, hi = c, t;
            if (vertex_before(&s, mid, lo))
                t = lo, lo = mid, mid = t;
            if (vertex_before(&s, hi, mid))
                t = mid, mid = hi, hi = t;
            if (vertex_before(&s, mid, lo))
                t = lo, lo = mid, mid = t;
            splits[nsplit++] = (quad){lo < hi ? lo : hi, lo < hi ? hi : lo, mid, 0};
            continue;
        }
        recs[nrec++] = (quad){a, bb, c, 0};
        recs[nrec++] = (quad){a, c, bb, 0};
        recs[nrec++] = (quad){bb, c, a, 0};
    }
    sort_quads(recs, nrec, s.nv);
    sort_quads(splits, nsplit, s.nv);
    if (stats) {
        stats->unit_exp10 = s.e;
        stats->exact = exact;
        stats->points_used = nused;
        stats->merged_points = nused - s.nv;
        stats->degenerate_triangles = ndegenerate;
        stats->duplicate_triangles = nt - nunique;
        stats->collinear_triangles = nsplit;
    }
    st = check_sides(&s, recs, nrec, diag);
    if (!st)
        st = split_long_sides(&s, splits, nsplit, stats);
    if (st) {
        if (st == HPFC_E_NOMEM)
            fail(diag, st, "out of memory");
        goto done;
    }
    finish_edges(&s);
    st = make_graph(&s, &g, diag);
    if (!st)
        st = validate(&s, g, diag);
    if (!st) {
        if (stats) {
            stats->vertices = hpfc_graph_vertex_count(g);
            stats->edges = hpfc_graph_edge_count(g);
        }
        *out = g;
        g = NULL;
    }
done:
    hpfc_graph_free(g);
    free(used);
    free(pvert);
    free(recs);
    free(splits);
    free(s.vx);
    free(s.vy);
    free(s.vrep);
    free(s.edges);
    return st;
}
