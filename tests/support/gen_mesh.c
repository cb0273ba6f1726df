/*
 * gen-mesh: writes a generated triangle mesh as OBJ or PLY, and optionally
 * the planar graph of its triangle edges as .pfc (the "same triangulation
 * given as .pfc" the Draco tests compare with). Makes tests/data/mesh/ (see
 * tests/data/mesh/regen.sh).
 *
 *   gen-mesh KIND SEED N OUT.obj|OUT.ply [OUT.pfc]
 *
 *   delaunay  Delaunay triangulation of N random points (gen.h; the points
 *             lie in [1, C-1]^2 as gen-pfc chooses C), z random in [0, 100)
 *   tin       terrain: an N x N cell grid, spacing 100, every vertex jittered
 *             by up to 24 (so no triangle can flip), a random diagonal per
 *             cell, z a smooth integer surface plus noise
 *   holes     the tin grid (N >= 12) without: a 2 x 3 block of cells (an
 *             inner hole), a 5 x 5 block but its centre cell (a hole with an
 *             island: a face with a hole), one corner cell (a notch in the
 *             outer boundary, its corner vertex left unused)
 *   cluster   (N ignored) a square 0..8188 whose centre vertex is ringed by
 *             8 points 1 unit away, all triangulated: lossless, 13 points
 *             and 20 triangles; quantized to 11 bits (a step of 4 units) the
 *             ring lands on the centre, leaving the square fanned to it
 *   fold      a strip of N triangles whose last triangle folds back over the
 *             first ones (not planar in x, y)
 *   flat      N triangles whose corners are all collinear (nothing left)
 *
 * Every coordinate is an integer, so a lossless encoding (-qp 0) keeps them
 * exactly and the .pfc has the very same points.
 */
#include <errno.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gen.h"

typedef struct mesh {
    size_t np, nt;
    int64_t *p;    /* x, y, z per point */
    uint32_t *t;   /* 3 per triangle */
} mesh;

static int mesh_alloc(mesh *m, size_t np, size_t nt)
{
    m->np = np, m->nt = 0;
    m->p = calloc(3 * (np ? np : 1), sizeof *m->p);
    m->t = calloc(3 * (nt ? nt : 1), sizeof *m->t);
    return m->p && m->t ? HPFC_OK : HPFC_E_NOMEM;
}

static void add_tri(mesh *m, uint32_t a, uint32_t b, uint32_t c)
{
    m->t[3 * m->nt] = a, m->t[3 * m->nt + 1] = b, m->t[3 * m->nt + 2] = c;
    m->nt++;
}

static int64_t coord_max_for(uint64_t n)
{
    int64_t c = 64;
    while (c < GEN_COORD_MAX_DELAUNAY && (uint64_t)c * (uint64_t)c < 256 * n)
        c *= 2;
    return c;
}

static int make_delaunay(uint64_t seed, size_t n, mesh *m)
{
    gen_triangulation t;
    int st = gen_delaunay_triangulation(seed, n, coord_max_for(n), &t);
    if (st)
        return st;
    gen_rng rng;
    gen_rng_seed(&rng, seed ^ 0x7a);
    st = mesh_alloc(m, t.npoints, t.ntriangles);
    for (size_t i = 0; i < t.npoints && !st; i++) {
        m->p[3 * i] = t.xy[2 * i], m->p[3 * i + 1] = t.xy[2 * i + 1];
        m->p[3 * i + 2] = (int64_t)gen_rng_below(&rng, 100);
    }
    for (size_t k = 0; k < t.ntriangles && !st; k++)
        add_tri(m, t.tri[3 * k], t.tri[3 * k + 1], t.tri[3 * k + 2]);
    gen_triangulation_free(&t);
    return st;
}

/* The jittered terrain grid; keep(i, j) says which cells stay. */
static int make_grid(uint64_t seed, size_t n, int (*keep)(size_t, size_t, size_t), mesh *m)
{
    gen_rng rng;
    gen_rng_seed(&rng, seed);
    size_t side = n + 1;
    int st = mesh_alloc(m, side * side, 2 * n * n);
    for (size_t j = 0; j < side && !st; j++)
        for (size_t i = 0; i < side; i++) {
            int64_t *p = &m->p[3 * (j * side + i)];
            p[0] = (int64_t)(i * 100) + (int64_t)gen_rng_below(&rng, 49) - 24;
            p[1] = (int64_t)(j * 100) + (int64_t)gen_rng_below(&rng, 49) - 24;
            int64_t di = (int64_t)i - (int64_t)n / 3, dj = (int64_t)j - (int64_t)n / 2;
            p[2] = 1000 - 3 * (di * di + dj * dj) + (int64_t)gen_rng_below(&rng, 20);
        }
    for (size_t j = 0; j < n && !st; j++)
        for (size_t i = 0; i < n; i++) {
            int diag = (int)gen_rng_below(&rng, 2);
            if (keep && !keep(i, j, n))
                continue;
            uint32_t a = (uint32_t)(j * side + i), b = a + 1, c = a + (uint32_t)side, d = c + 1;
            if (diag)
                add_tri(m, a, b, d), add_tri(m, a, d, c);
            else
                add_tri(m, a, b, c), add_tri(m, b, d, c);
        }
    return st;
}

static int keep_holes(size_t i, size_t j, size_t n)
{
    size_t c = n / 2 + 1; /* centre of the ring block */
    int ring = i + 2 >= c && i <= c + 2 && j + 2 >= c && j <= c + 2 && !(i == c && j == c);
    int hole = i >= 1 && i <= 2 && j >= 1 && j <= 3;
    int notch = i == n - 1 && j == 0;
    return !ring && !hole && !notch;
}

static int make_cluster(mesh *m)
{
    /* 0-3 square corners (counter-clockwise from the origin), 4 centre,
     * 5-12 the ring, counter-clockwise from the east */
    static const int64_t corner[4][2] = {{0, 0}, {8188, 0}, {8188, 8188}, {0, 8188}};
    static const int64_t ring[8][2] = {{1, 0}, {1, 1}, {0, 1}, {-1, 1},
                                       {-1, 0}, {-1, -1}, {0, -1}, {1, -1}};
    int st = mesh_alloc(m, 13, 20);
    if (st)
        return st;
    for (int k = 0; k < 4; k++)
        m->p[3 * k] = corner[k][0], m->p[3 * k + 1] = corner[k][1];
    m->p[12] = m->p[13] = 4096;
    for (int k = 0; k < 8; k++)
        m->p[3 * (5 + k)] = 4096 + ring[k][0], m->p[3 * (5 + k) + 1] = 4096 + ring[k][1];
    for (uint32_t k = 0; k < 8; k++) {
        uint32_t a = 5 + k, b = 5 + (k + 1) % 8;
        /* ring edge k faces the corner nearest its middle; where that corner
         * changes, one triangle joins the ring point to the square's side */
        uint32_t ca = (k / 2 + 2) % 4, cb = ((k + 1) % 8 / 2 + 2) % 4;
        add_tri(m, 4, a, b);
        add_tri(m, b, a, ca);
        if (cb != ca)
            add_tri(m, b, ca, cb);
    }
    return HPFC_OK;
}

static int make_fold(size_t n, mesh *m)
{
    /* a strip along x: bottom points 2k, top points 2k+1; the last triangle
     * reaches back over the first cells at another height */
    int st = mesh_alloc(m, 2 * (n + 1) + 1, 2 * n + 1);
    for (size_t k = 0; k <= n && !st; k++) {
        m->p[3 * (2 * k)] = (int64_t)(10 * k), m->p[3 * (2 * k) + 1] = 0;
        m->p[3 * (2 * k + 1)] = (int64_t)(10 * k), m->p[3 * (2 * k + 1) + 1] = 10;
        m->p[3 * (2 * k) + 2] = m->p[3 * (2 * k + 1) + 2] = 0;
    }
    for (size_t k = 0; k < n && !st; k++) {
        uint32_t a = (uint32_t)(2 * k);
        add_tri(m, a, a + 2, a + 3);
        add_tri(m, a, a + 3, a + 1);
    }
    uint32_t back = (uint32_t)(2 * (n + 1));
    m->p[3 * back] = 5, m->p[3 * back + 1] = 5, m->p[3 * back + 2] = 50;
    add_tri(m, (uint32_t)(2 * n), (uint32_t)(2 * n + 1), back);
    return st;
}

static int make_flat(size_t n, mesh *m)
{
    int st = mesh_alloc(m, n + 2, n);
    for (size_t k = 0; k < n + 2 && !st; k++)
        m->p[3 * k] = (int64_t)(3 * k), m->p[3 * k + 1] = (int64_t)(2 * k);
    for (size_t k = 0; k < n && !st; k++)
        add_tri(m, (uint32_t)k, (uint32_t)(k + 1), (uint32_t)(k + 2));
    return st;
}

static int write_obj(const mesh *m, FILE *f)
{
    fprintf(f, "# gen-mesh: %zu points, %zu triangles\n", m->np, m->nt);
    for (size_t i = 0; i < m->np; i++)
        fprintf(f, "v %" PRId64 " %" PRId64 " %" PRId64 "\n", m->p[3 * i], m->p[3 * i + 1],
                m->p[3 * i + 2]);
    for (size_t k = 0; k < m->nt; k++)
        fprintf(f, "f %u %u %u\n", m->t[3 * k] + 1, m->t[3 * k + 1] + 1, m->t[3 * k + 2] + 1);
    return ferror(f) ? HPFC_E_IO : HPFC_OK;
}

static int write_ply(const mesh *m, FILE *f)
{
    fprintf(f, "ply\nformat ascii 1.0\ncomment gen-mesh\nelement vertex %zu\n"
               "property float x\nproperty float y\nproperty float z\n"
               "element face %zu\nproperty list uchar int vertex_indices\nend_header\n",
            m->np, m->nt);
    for (size_t i = 0; i < m->np; i++)
        fprintf(f, "%" PRId64 " %" PRId64 " %" PRId64 "\n", m->p[3 * i], m->p[3 * i + 1],
                m->p[3 * i + 2]);
    for (size_t k = 0; k < m->nt; k++)
        fprintf(f, "3 %u %u %u\n", m->t[3 * k], m->t[3 * k + 1], m->t[3 * k + 2]);
    return ferror(f) ? HPFC_E_IO : HPFC_OK;
}

static int cmp_pair(const void *a, const void *b)
{
    const uint32_t *p = a, *q = b;
    return p[0] != q[0] ? (p[0] < q[0] ? -1 : 1) : (p[1] < q[1] ? -1 : p[1] > q[1]);
}

/* The graph of the triangle edges, each once; unused points left out. */
static int edge_graph(const mesh *m, hpfc_graph **out)
{
    uint32_t *e = malloc(6 * (m->nt ? m->nt : 1) * sizeof *e);
    uint32_t *id = malloc((m->np ? m->np : 1) * sizeof *id);
    hpfc_graph *g = NULL;
    int st = e && id ? hpfc_graph_create(&g) : HPFC_E_NOMEM;
    size_t ne = 0;
    for (size_t k = 0; k < m->nt && !st; k++)
        for (int c = 0; c < 3; c++) {
            uint32_t u = m->t[3 * k + c], v = m->t[3 * k + (c + 1) % 3];
            e[2 * ne] = u < v ? u : v, e[2 * ne + 1] = u < v ? v : u;
            ne++;
        }
    if (!st) {
        qsort(e, ne, 2 * sizeof *e, cmp_pair);
        for (size_t i = 0; i < m->np; i++)
            id[i] = UINT32_MAX;
        for (size_t i = 0; i < ne; i++)
            id[e[2 * i]] = id[e[2 * i + 1]] = 0;
        uint32_t next = 0;
        for (size_t i = 0; i < m->np && !st; i++)
            if (id[i] == 0) {
                id[i] = next++;
                st = hpfc_graph_add_vertex(g, m->p[3 * i], m->p[3 * i + 1], NULL);
            }
    }
    for (size_t i = 0; i < ne && !st; i++)
        if (i == 0 || cmp_pair(&e[2 * i], &e[2 * i - 2]) != 0)
            st = hpfc_graph_add_edge(g, id[e[2 * i]], id[e[2 * i + 1]], NULL, 0, NULL);
    free(e);
    free(id);
    if (st)
        hpfc_graph_free(g);
    else
        *out = g;
    return st;
}

static int write_file(const char *path, const mesh *m, int pfc)
{
    FILE *f = fopen(path, "w");
    if (!f) {
        fprintf(stderr, "gen-mesh: %s: %s\n", path, strerror(errno));
        return HPFC_E_IO;
    }
    int st;
    if (pfc) {
        hpfc_graph *g = NULL;
        st = edge_graph(m, &g);
        if (!st)
            st = gen_write_pfc(g, f);
        hpfc_graph_free(g);
    } else {
        size_t n = strlen(path);
        st = n > 4 && strcmp(path + n - 4, ".ply") == 0 ? write_ply(m, f) : write_obj(m, f);
    }
    if (fclose(f) != 0 && !st)
        st = HPFC_E_IO;
    if (st)
        fprintf(stderr, "gen-mesh: %s: %s\n", path, hpfc_strerror(st));
    return st;
}

int main(int argc, char **argv)
{
    char *end;
    if (argc != 5 && argc != 6) {
        fprintf(stderr, "usage: gen-mesh delaunay|tin|holes|cluster|fold|flat SEED N "
                        "OUT.obj|OUT.ply [OUT.pfc]\n");
        return 2;
    }
    uint64_t seed = strtoull(argv[2], &end, 0);
    size_t n = (size_t)strtoull(argv[3], &end, 0);
    mesh m = {0};
    const char *kind = argv[1];
    int st = HPFC_E_ARG;
    if (n == 0 || n > 100000)
        st = HPFC_E_ARG;
    else if (strcmp(kind, "delaunay") == 0)
        st = make_delaunay(seed, n, &m);
    else if (strcmp(kind, "tin") == 0)
        st = make_grid(seed, n, NULL, &m);
    else if (strcmp(kind, "holes") == 0)
        st = n >= 12 ? make_grid(seed, n, keep_holes, &m) : HPFC_E_ARG;
    else if (strcmp(kind, "cluster") == 0)
        st = make_cluster(&m);
    else if (strcmp(kind, "fold") == 0)
        st = make_fold(n, &m);
    else if (strcmp(kind, "flat") == 0)
        st = make_flat(n, &m);
    if (st)
        fprintf(stderr, "gen-mesh: %s\n", hpfc_strerror(st));
    if (!st)
        st = write_file(argv[4], &m, 0);
    if (!st && argc == 6)
        st = write_file(argv[5], &m, 1);
    free(m.p);
    free(m.t);
    return st ? 1 : 0;
}
