/*
 * Unit tests of hpfc-pack's mesh-to-graph conversion (hpfc-pack/mesh_graph.h):
 * the exact lattice mapping against an independent rational oracle, the unit
 * choice, merges, dropped and split triangles, folds and crossings, and, as
 * the topology oracle, generated Delaunay triangulations whose graph must
 * read back from an .hpfc exactly like the triangulation's own edge graph.
 * No Draco here: tests/cli/draco.sh covers the decoder.
 */
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_graph.h"
#include "check.h"
#include "export.h"
#include "gen.h"
#include "hpfc.h"

__extension__ typedef __int128 i128;

/* ---- lattice mapping --------------------------------------------------------- */

/* the layout under test (check_use_test_layout) */
static int test_layout_compact;

static int64_t lattice(double v, int32_t e)
{
    int64_t q = INT64_MIN;
    CHECK_EQ_INT(mesh_lattice_coord(v, e, &q), HPFC_OK);
    return q;
}

/* round(num / den) half away from zero, den > 0 */
static int64_t round_rational(i128 num, i128 den)
{
    i128 mag = num < 0 ? -num : num;
    i128 q = (2 * mag + den) / (2 * den);
    return (int64_t)(num < 0 ? -q : q);
}

static void test_lattice_exact(void)
{
    /* halves round away from zero */
    CHECK_EQ_INT(lattice(0.5, 0), 1);
    CHECK_EQ_INT(lattice(-0.5, 0), -1);
    CHECK_EQ_INT(lattice(2.5, 0), 3);
    CHECK_EQ_INT(lattice(-2.5, 0), -3);
    CHECK_EQ_INT(lattice(0.49999999999999994, 0), 0);
    CHECK_EQ_INT(lattice(-0.0, 0), 0);
    /* the double's exact value decides, not a product in floating point:
     * 0.0045 is 0.004499999999999999659..., although 0.0045 * 1000 == 4.5 */
    CHECK(0.0045 * 1000 == 4.5);
    CHECK_EQ_INT(lattice(0.0045, -3), 4);
    CHECK_EQ_INT(lattice(0.0015, -3), 2); /* 0.00150000000000000003... */
    CHECK_EQ_INT(lattice(2.675, -2), 267); /* 2.67499999999999982... */
    CHECK_EQ_INT(lattice(0.1, -1), 1);
    CHECK_EQ_INT(lattice(0.1f, -9), 100000001); /* 0.100000001490116... */
    /* coarser units */
    CHECK_EQ_INT(lattice(1500, 3), 2);
    CHECK_EQ_INT(lattice(-1500, 3), -2);
    CHECK_EQ_INT(lattice(1499.9999, 3), 1);
    CHECK_EQ_INT(lattice(1234567, 3), 1235);
    CHECK_EQ_INT(lattice(5e26, 27), 1);
    CHECK_EQ_INT(lattice(4.9e26, 27), 0);
    CHECK_EQ_INT(lattice(3e38, 27), 300000000000);
    /* tiny values round to zero */
    CHECK_EQ_INT(lattice(1e-300, -27), 0);
    CHECK_EQ_INT(lattice(4.9e-324, -27), 0);
    CHECK_EQ_INT(lattice(5e-28, -27), 1);
    /* bounds */
    CHECK_EQ_INT(lattice(ldexp(1, 40), 0), HPFC_COORD_MAX);
    CHECK_EQ_INT(lattice(-ldexp(1, 40), 0), -HPFC_COORD_MAX);
    CHECK_EQ_INT(lattice(ldexp(1, 40) + 0.25, 0), HPFC_COORD_MAX);
    int64_t q;
    CHECK_EQ_INT(mesh_lattice_coord(ldexp(1, 40) + 0.5, 0, &q), HPFC_E_EXTENT);
    CHECK_EQ_INT(mesh_lattice_coord(ldexp(1, 40) + 1, 0, &q), HPFC_E_EXTENT);
    CHECK_EQ_INT(mesh_lattice_coord(1e300, 27, &q), HPFC_E_EXTENT);
    CHECK_EQ_INT(mesh_lattice_coord(1, -13, &q), HPFC_E_EXTENT);
    CHECK_EQ_INT(mesh_lattice_coord(NAN, 0, &q), HPFC_E_EXTENT);
    CHECK_EQ_INT(mesh_lattice_coord(-INFINITY, 0, &q), HPFC_E_EXTENT);
    CHECK_EQ_INT(mesh_lattice_coord(1, 28, &q), HPFC_E_ARG);
    CHECK_EQ_INT(mesh_lattice_coord(1, -28, &q), HPFC_E_ARG);

    CHECK_EQ_INT(mesh_decimal_digits(0), 0);
    CHECK_EQ_INT(mesh_decimal_digits(3), 0);
    CHECK_EQ_INT(mesh_decimal_digits(1e20), 0);
    CHECK_EQ_INT(mesh_decimal_digits(0.5), 1);
    CHECK_EQ_INT(mesh_decimal_digits(-0.125), 3);
    CHECK_EQ_INT(mesh_decimal_digits(0.1), 55);
    CHECK_EQ_INT(mesh_decimal_digits(0.1f), 27);
}

/* Random dyadic values n * 2^-j against exact rational rounding (every
 * product below stays under 2^110). */
static void test_lattice_oracle(void)
{
    gen_rng rng;
    gen_rng_seed(&rng, 6);
    long mismatches = 0;
    for (int it = 0; it < 200000; it++) {
        int64_t n = (int64_t)gen_rng_below(&rng, (uint64_t)1 << 24) - ((int64_t)1 << 23);
        int j = (int)gen_rng_below(&rng, 60) - 20;
        int32_t e = (int32_t)gen_rng_below(&rng, 41) - 20;
        double v = ldexp((double)n, -j);
        i128 num = j < 0 ? (i128)n * ((i128)1 << -j) : n, den = j < 0 ? 1 : (i128)1 << j;
        for (int k = 0; k < (e < 0 ? -e : e); k++)
            *(e < 0 ? &num : &den) *= 10;
        int64_t want = round_rational(num, den), got = 0;
        int st = mesh_lattice_coord(v, e, &got);
        if (want > HPFC_COORD_MAX || want < -HPFC_COORD_MAX) {
            mismatches += st != HPFC_E_EXTENT;
            continue;
        }
        if (st != HPFC_OK || got != want) {
            if (mismatches++ < 5)
                fprintf(stderr, "lattice(%.17g, %d): got %lld, want %lld\n", v, (int)e,
                        (long long)got, (long long)want);
        }
    }
    CHECK_EQ_INT(mismatches, 0);
}

/* ---- small meshes -------------------------------------------------------------- */

typedef struct built {
    int status;
    hpfc_graph *g;
    mesh_graph_stats stats;
    hpfc_diag diag;
} built;

static built build(const double *xy, size_t dims, size_t np, const uint32_t *tri, size_t nt,
                   const mesh_graph_options *opts)
{
    built b;
    memset(&b, 0, sizeof b);
    b.status = mesh_graph_build(xy, dims, np, tri, nt, opts, &b.g, &b.stats, &b.diag);
    CHECK((b.status == HPFC_OK) == (b.g != NULL));
    if (b.status)
        CHECK(b.diag.message[0] != '\0' && !strchr(b.diag.message, '\n'));
    return b;
}

/* Does the graph have a straight edge between the vertices at (x0, y0) and
 * (x1, y1)? */
static int has_edge(const hpfc_graph *g, int64_t x0, int64_t y0, int64_t x1, int64_t y1)
{
    for (size_t e = 0; e < hpfc_graph_edge_count(g); e++) {
        uint32_t u, v;
        const int64_t *pts;
        size_t n;
        int64_t ux, uy, vx, vy;
        hpfc_graph_edge(g, e, &u, &v, &pts, &n);
        hpfc_graph_vertex(g, u, &ux, &uy);
        hpfc_graph_vertex(g, v, &vx, &vy);
        if (n == 0 && ((ux == x0 && uy == y0 && vx == x1 && vy == y1) ||
                       (ux == x1 && uy == y1 && vx == x0 && vy == y0)))
            return 1;
    }
    return 0;
}

/* faces and components of the graph, from a build */
static void faces_of(const hpfc_graph *g, uint64_t *faces, uint64_t *components)
{
    hpfc_build_params p;
    hpfc_build_params_default(&p);
    hpfc_tree *t = NULL;
    *faces = *components = 0;
    CHECK_EQ_INT(hpfc_build(g, &p, &t, NULL), HPFC_OK);
    if (!t)
        return;
    hpfc_tree_info info;
    hpfc_tree_get_info(t, &info);
    *faces = info.faces;
    *components = info.components;
    hpfc_tree_free(t);
}

static void test_units(void)
{
    /* integers: unit 1, exact; z ignored */
    const double tri3[] = {0, 0, 7, 10, 0, -3, 0, 10, 99};
    const uint32_t t1[] = {0, 1, 2};
    built b = build(tri3, 3, 3, t1, 1, NULL);
    CHECK_EQ_INT(b.status, HPFC_OK);
    CHECK_EQ_INT(hpfc_graph_unit_exp10(b.g), 0);
    CHECK(b.stats.exact);
    CHECK_EQ_INT(hpfc_graph_vertex_count(b.g), 3);
    CHECK_EQ_INT(hpfc_graph_edge_count(b.g), 3);
    CHECK(has_edge(b.g, 0, 0, 10, 0) && has_edge(b.g, 10, 0, 0, 10) && has_edge(b.g, 0, 0, 0, 10));
    hpfc_graph_free(b.g);

    /* binary fractions with few decimals: the coarsest exact unit */
    const double quarter[] = {0.25, 0, 1.5, 0, 0, 2.75};
    b = build(quarter, 2, 3, t1, 1, NULL);
    CHECK_EQ_INT(hpfc_graph_unit_exp10(b.g), -2);
    CHECK(b.stats.exact);
    CHECK(has_edge(b.g, 25, 0, 150, 0) && has_edge(b.g, 0, 275, 150, 0));
    hpfc_graph_free(b.g);

    /* large integers keep unit 1 as long as they fit */
    const double big[] = {1e12, 0, 1e12 + 1, 0, 1e12, 1};
    b = build(big, 2, 3, t1, 1, NULL);
    CHECK_EQ_INT(hpfc_graph_unit_exp10(b.g), 0);
    hpfc_graph_free(b.g);

    /* floats in [0, 1]: no exact unit fits, the box spans at most 2^34 units:
     * 1 / 10^-10 = 1e10 <= 2^34 < 1e11 */
    const double unit[] = {0.1f, 0.2f, 1, 0, 0, 1};
    b = build(unit, 2, 3, t1, 1, NULL);
    CHECK_EQ_INT(hpfc_graph_unit_exp10(b.g), -10);
    CHECK(!b.stats.exact);
    hpfc_graph_free(b.g);

    /* far from the origin: the magnitude bound 2^40 decides; here the floats'
     * own resolution (1/32 at 5e5) is exact at unit 1e-5 */
    const double utm[] = {500000.03125f, 4649776.5f, 500010.f, 4649776.5f, 500000.03125f,
                          4649786.75f};
    b = build(utm, 2, 3, t1, 1, NULL);
    CHECK_EQ_INT(hpfc_graph_unit_exp10(b.g), -5);
    CHECK(b.stats.exact);
    hpfc_graph_free(b.g);
    const double utm2[] = {500000.1, 4649776.1, 500010.2, 4649776.3, 500000.4, 4649786.7};
    b = build(utm2, 2, 3, t1, 1, NULL);
    CHECK_EQ_INT(hpfc_graph_unit_exp10(b.g), -5); /* 4.6e6 / 1e-5 < 2^40 < 4.6e6 / 1e-6 */
    CHECK(!b.stats.exact);
    hpfc_graph_free(b.g);

    /* a fixed unit */
    mesh_graph_options fixed = {1, 1};
    const double tens[] = {0, 0, 100, 0, 0, 100};
    b = build(tens, 2, 3, t1, 1, &fixed);
    CHECK_EQ_INT(hpfc_graph_unit_exp10(b.g), 1);
    CHECK(has_edge(b.g, 0, 0, 10, 0));
    hpfc_graph_free(b.g);
    fixed.unit_exp10 = 40;
    b = build(tens, 2, 3, t1, 1, &fixed);
    CHECK_EQ_INT(b.status, HPFC_E_ARG);

    /* too large for any unit */
    const double huge[] = {-1e300, 0, 1e300, 0, 0, 1};
    b = build(huge, 2, 3, t1, 1, NULL);
    CHECK_EQ_INT(b.status, HPFC_E_EXTENT);
}

static void test_rejections(void)
{
    const double xy[] = {0, 0, 10, 0, 0, 10, NAN, 0};
    const uint32_t ok[] = {0, 1, 2};
    const uint32_t out_of_range[] = {0, 1, 4};
    const uint32_t nan[] = {0, 1, 3};
    built b = build(xy, 2, 4, ok, 1, NULL); /* the unused NaN point is ignored */
    CHECK_EQ_INT(b.status, HPFC_OK);
    hpfc_graph_free(b.g);
    CHECK_EQ_INT(build(xy, 2, 4, out_of_range, 1, NULL).status, HPFC_E_VERTEX_INDEX);
    b = build(xy, 2, 4, nan, 1, NULL);
    CHECK_EQ_INT(b.status, HPFC_E_EXTENT);
    CHECK(strstr(b.diag.message, "point 3") != NULL);
    CHECK_EQ_INT(build(xy, 2, 4, ok, 0, NULL).status, HPFC_E_EMPTY);
    CHECK_EQ_INT(build(xy, 1, 4, ok, 1, NULL).status, HPFC_E_ARG);
    CHECK_EQ_INT(mesh_graph_build(xy, 2, 4, ok, 1, NULL, NULL, NULL, NULL), HPFC_E_ARG);
    /* every triangle degenerate: nothing left */
    const uint32_t flat[] = {0, 0, 1, 1, 2, 2};
    b = build(xy, 2, 4, flat, 2, NULL);
    CHECK_EQ_INT(b.status, HPFC_E_EMPTY);
    CHECK_EQ_INT(b.stats.degenerate_triangles, 2);
    const double line[] = {0, 0, 1, 1, 2, 2};
    b = build(line, 2, 3, ok, 1, NULL);
    CHECK_EQ_INT(b.status, HPFC_E_EMPTY);
    CHECK_EQ_INT(b.stats.collinear_triangles, 1);
}

static void test_merges(void)
{
    /* a square split in two, plus a point 0.3 from a corner fanned into the
     * corner's triangles; at unit 1 it merges into the corner */
    const double xy[] = {0, 0, 10, 0, 10, 10, 0, 10, 0.3, 0.2};
    const uint32_t tri[] = {0, 1, 2, 0, 2, 3, 4, 1, 2, 0, 4, 1};
    mesh_graph_options unit1 = {1, 0};
    built b = build(xy, 2, 5, tri, 4, &unit1);
    CHECK_EQ_INT(b.status, HPFC_OK);
    CHECK_EQ_INT(b.stats.merged_points, 1);
    CHECK_EQ_INT(b.stats.degenerate_triangles, 1);  /* 0 4 1 */
    CHECK_EQ_INT(b.stats.duplicate_triangles, 1);   /* 4 1 2 is 0 1 2 */
    CHECK_EQ_INT(hpfc_graph_vertex_count(b.g), 4);
    CHECK_EQ_INT(hpfc_graph_edge_count(b.g), 5);
    uint64_t faces, comps;
    faces_of(b.g, &faces, &comps);
    CHECK_EQ_INT(faces, 3);
    hpfc_graph_free(b.g);
    /* automatic unit: nothing merges, the extra point is a vertex... whose
     * triangle 0 4 1 lies inside 0 1 2 on the same side of edge 0-1: a fold */
    b = build(xy, 2, 5, tri, 4, NULL);
    CHECK_EQ_INT(b.status, HPFC_E_NONPLANAR);
    CHECK(strstr(b.diag.message, "folds") != NULL);

    /* a repeat with the other winding is dropped, not a fold */
    const uint32_t twice[] = {0, 1, 2, 2, 1, 0};
    b = build(xy, 2, 5, twice, 2, NULL);
    CHECK_EQ_INT(b.status, HPFC_OK);
    CHECK_EQ_INT(b.stats.duplicate_triangles, 1);
    CHECK_EQ_INT(hpfc_graph_edge_count(b.g), 3);
    hpfc_graph_free(b.g);

    /* points that merge keep the lowest index's place: the graph's vertex
     * order follows the lowest point index on each lattice point */
    const double dup[] = {8, 8, 0, 0, 10, 0, 0, 10, 0, 0};
    const uint32_t dt[] = {4, 2, 3, 2, 3, 0, 1, 3, 2};
    b = build(dup, 2, 5, dt, 3, NULL);
    CHECK_EQ_INT(b.status, HPFC_OK);
    CHECK_EQ_INT(b.stats.merged_points, 1);
    CHECK_EQ_INT(b.stats.points_used, 5);
    int64_t x, y;
    hpfc_graph_vertex(b.g, 0, &x, &y);
    CHECK(x == 8 && y == 8);
    hpfc_graph_vertex(b.g, 1, &x, &y);
    CHECK(x == 0 && y == 0);
    hpfc_graph_free(b.g);
}

static void test_collinear(void)
{
    /* a(0,0) b(5,0) c(10,0) d(5,5) e(5,-5): triangle a c d above, a b e and
     * b c e below; a-c passes through b (a T-junction) */
    const double xy[] = {0, 0, 5, 0, 10, 0, 5, 5, 5, -5};
    const uint32_t tjunction[] = {0, 2, 3, 0, 1, 4, 1, 2, 4};
    built b = build(xy, 2, 5, tjunction, 3, NULL);
    CHECK_EQ_INT(b.status, HPFC_E_NONPLANAR);
    CHECK(strstr(b.diag.message, "cross or touch") != NULL);
    CHECK(strstr(b.diag.message, "0-2") != NULL);
    CHECK(b.diag.has_point && b.diag.x == 5 && b.diag.y == 0);
    /* with the zero-area triangle a b c, as meshes carry them, a-c splits at b */
    const uint32_t sliver[] = {0, 2, 3, 0, 1, 4, 1, 2, 4, 0, 1, 2};
    b = build(xy, 2, 5, sliver, 4, NULL);
    CHECK_EQ_INT(b.status, HPFC_OK);
    CHECK_EQ_INT(b.stats.collinear_triangles, 1);
    CHECK_EQ_INT(b.stats.split_edges, 1);
    CHECK_EQ_INT(hpfc_graph_vertex_count(b.g), 5);
    CHECK_EQ_INT(hpfc_graph_edge_count(b.g), 7);
    CHECK(has_edge(b.g, 0, 0, 5, 0) && has_edge(b.g, 5, 0, 10, 0) && !has_edge(b.g, 0, 0, 10, 0));
    uint64_t faces, comps;
    faces_of(b.g, &faces, &comps);
    CHECK_EQ_INT(faces, 4);
    hpfc_graph_free(b.g);

    /* nested: a(0,0) m(2,0) n(6,0) c(8,0); slivers a n c and a m n; above
     * a c d, below a m e, m n e, n c e: a-c -> a-n, n-c -> a-m, m-n, n-c */
    const double xy2[] = {0, 0, 2, 0, 6, 0, 8, 0, 4, 4, 4, -4};
    const uint32_t nested[] = {0, 2, 3, 0, 1, 2, 0, 3, 4, 0, 1, 5, 1, 2, 5, 2, 3, 5};
    b = build(xy2, 2, 6, nested, 6, NULL);
    CHECK_EQ_INT(b.status, HPFC_OK);
    CHECK_EQ_INT(b.stats.split_edges, 2);
    CHECK(has_edge(b.g, 0, 0, 2, 0) && has_edge(b.g, 2, 0, 6, 0) && has_edge(b.g, 6, 0, 8, 0));
    CHECK_EQ_INT(hpfc_graph_edge_count(b.g), 9);
    hpfc_graph_free(b.g);
    /* two middles on one long side, listed in either order */
    const uint32_t two[] = {0, 3, 2, 0, 1, 3, 0, 3, 4, 0, 1, 5, 1, 2, 5, 2, 3, 5};
    b = build(xy2, 2, 6, two, 6, NULL);
    CHECK_EQ_INT(b.status, HPFC_OK);
    CHECK_EQ_INT(b.stats.split_edges, 1);
    CHECK_EQ_INT(hpfc_graph_edge_count(b.g), 9);
    hpfc_graph_free(b.g);
}

static void test_nonplanar(void)
{
    /* a fold: two triangles on the same side of their shared edge */
    const double xy[] = {0, 0, 10, 0, 0, 10, 2, 2, 20, 20, 30, 0, 25, 30};
    const uint32_t fold[] = {0, 1, 2, 1, 2, 3};
    built b = build(xy, 2, 7, fold, 2, NULL);
    CHECK_EQ_INT(b.status, HPFC_E_NONPLANAR);
    CHECK(strstr(b.diag.message, "folds over itself") != NULL);
    CHECK(strstr(b.diag.message, "1-2") != NULL && strstr(b.diag.message, "(2, 2)") != NULL);
    CHECK(b.diag.has_point && b.diag.x == 2 && b.diag.y == 2);
    /* three triangles on one edge */
    const double fan[] = {0, 0, 10, 0, 5, 5, 5, -5, 5, -9};
    const uint32_t three[] = {0, 1, 2, 0, 1, 3, 0, 1, 4};
    CHECK_EQ_INT(build(fan, 2, 5, three, 3, NULL).status, HPFC_E_NONPLANAR);
    /* two separate triangles: apart, touching, crossing */
    const uint32_t apart[] = {0, 1, 2, 4, 5, 6};
    b = build(xy, 2, 7, apart, 2, NULL);
    CHECK_EQ_INT(b.status, HPFC_OK);
    hpfc_graph_free(b.g);
    const uint32_t cross[] = {0, 1, 2, 3, 4, 5};
    b = build(xy, 2, 7, cross, 2, NULL);
    /* the second triangle leaves the first twice, across its edge 1-2:
     * edge 3-4 at (5, 5), edge 3-5 at (110/13, 20/13); the planarity
     * search names whichever it meets first, with its own point */
    CHECK_EQ_INT(b.status, HPFC_E_NONPLANAR);
    bool at_34 = b.diag.has_point && b.diag.x == 5 && b.diag.y == 5 &&
                 strstr(b.diag.message, "edges 1-2 and 3-4 ") != NULL;
    bool at_35 = b.diag.has_point && fabs(b.diag.x - 110.0 / 13) < 1e-9 &&
                 fabs(b.diag.y - 20.0 / 13) < 1e-9 &&
                 strstr(b.diag.message, "edges 1-2 and 3-5 ") != NULL;
    CHECK(at_34 || at_35);
    const double xy2[] = {0, 0, 10, 0, 0, 10, 5, 5, 20, 5, 5, 20};
    b = build(xy2, 2, 6, cross, 2, NULL);
    CHECK_EQ_INT(b.status, HPFC_E_NONPLANAR);
    CHECK(strstr(b.diag.message, "not planar in x, y") != NULL);
    CHECK(strstr(b.diag.message, "cross or touch at (") != NULL);
    /* a triangle inside another is planar: a hole in the outer one's face */
    const double nest[] = {0, 0, 100, 0, 0, 100, 10, 10, 20, 10, 10, 20};
    b = build(nest, 2, 6, cross, 2, NULL);
    CHECK_EQ_INT(b.status, HPFC_OK);
    uint64_t faces, comps;
    faces_of(b.g, &faces, &comps);
    CHECK_EQ_INT(faces, 3);
    CHECK_EQ_INT(comps, 2);
    hpfc_graph_free(b.g);
}

/* ---- generated meshes ---------------------------------------------------------- */

static hpfc_file *pack(const hpfc_graph *g, uint8_t **buf)
{
    hpfc_build_params p;
    hpfc_build_params_default(&p);
    p.root_cols = p.root_rows = 8;
    hpfc_tree *t = NULL;
    hpfc_file *f = NULL;
    size_t size;
    *buf = NULL;
    if (hpfc_build(g, &p, &t, NULL) == HPFC_OK &&
        check_tree_serialize(t, NULL, buf, &size, NULL) == HPFC_OK)
        CHECK_EQ_INT(hpfc_open_memory(*buf, size, 0, &f), HPFC_OK);
    hpfc_tree_free(t);
    return f;
}

/* The two graphs read back from their files as the same map. */
static int same_export(const hpfc_graph *a, const hpfc_graph *b)
{
    uint8_t *ba, *bb;
    hpfc_file *fa = pack(a, &ba), *fb = pack(b, &bb);
    exported_map ma = {0}, mb = {0};
    int same = fa && fb && export_map(fa, &ma) == HPFC_OK && export_map(fb, &mb) == HPFC_OK &&
               ma.nv == mb.nv && ma.nd == mb.nd &&
               memcmp(ma.box, mb.box, 4 * ma.nv * sizeof *ma.box) == 0 &&
               memcmp(ma.origin, mb.origin, ma.nd * sizeof *ma.origin) == 0 &&
               memcmp(ma.twin, mb.twin, ma.nd * sizeof *ma.twin) == 0 &&
               memcmp(ma.next, mb.next, ma.nd * sizeof *ma.next) == 0;
    exported_map_free(&ma);
    exported_map_free(&mb);
    hpfc_close(fa);
    hpfc_close(fb);
    free(ba);
    free(bb);
    return same;
}

/* The triangulation's own edges as a graph (unit 1). */
static hpfc_graph *edge_graph(const gen_triangulation *t)
{
    hpfc_graph *g;
    CHECK_EQ_INT(hpfc_graph_create(&g), HPFC_OK);
    for (size_t p = 0; p < t->npoints; p++)
        hpfc_graph_add_vertex(g, t->xy[2 * p], t->xy[2 * p + 1], NULL);
    for (size_t e = 0; e < t->nedges; e++)
        hpfc_graph_add_edge(g, t->edge[2 * e], t->edge[2 * e + 1], NULL, 0, NULL);
    return g;
}

/* Delaunay triangulations: with integer positions the mesh route gives the
 * triangulation's graph exactly, whatever the order of points, corners and
 * triangles; scaled by 1/4 (exact binary fractions) it keeps its counts. */
static void test_delaunay(void)
{
    for (uint64_t seed = 1; seed <= 40; seed++) {
        gen_triangulation t;
        size_t n = 3 + (size_t)(seed * 37 % 400);
        int64_t cmax = seed % 3 == 0 ? 64 : seed % 3 == 1 ? 5000 : GEN_COORD_MAX_DELAUNAY;
        if ((uint64_t)n > (uint64_t)((cmax - 1) * (cmax - 1)))
            n = 100;
        CHECK_EQ_INT(gen_delaunay_triangulation(seed, n, cmax, &t), HPFC_OK);
        if (t.ntriangles == 0) {
            gen_triangulation_free(&t);
            continue;
        }
        /* points permuted, corners rotated, triangles reversed, z added */
        gen_rng rng;
        gen_rng_seed(&rng, seed);
        uint32_t *perm = malloc(t.npoints * sizeof *perm);
        for (size_t p = 0; p < t.npoints; p++)
            perm[p] = (uint32_t)p;
        for (size_t p = t.npoints; p > 1; p--) {
            size_t q = (size_t)gen_rng_below(&rng, p);
            uint32_t tmp = perm[p - 1];
            perm[p - 1] = perm[q], perm[q] = tmp;
        }
        double *pos = malloc(3 * t.npoints * sizeof *pos);
        for (size_t p = 0; p < t.npoints; p++) {
            pos[3 * perm[p]] = (double)t.xy[2 * p];
            pos[3 * perm[p] + 1] = (double)t.xy[2 * p + 1];
            pos[3 * perm[p] + 2] = (double)gen_rng_below(&rng, 1000);
        }
        uint32_t *tri = malloc(3 * t.ntriangles * sizeof *tri);
        for (size_t k = 0; k < t.ntriangles; k++) {
            size_t r = (size_t)gen_rng_below(&rng, 3), dst = t.ntriangles - 1 - k;
            for (int c = 0; c < 3; c++)
                tri[3 * dst + c] = perm[t.tri[3 * k + (c + r) % 3]];
        }
        hpfc_graph *direct = edge_graph(&t);
        built b = build(pos, 3, t.npoints, tri, t.ntriangles, NULL);
        CHECK_EQ_INT(b.status, HPFC_OK);
        if (b.g) {
            CHECK_EQ_INT(hpfc_graph_unit_exp10(b.g), 0);
            CHECK_EQ_INT(hpfc_graph_vertex_count(b.g), t.npoints);
            CHECK_EQ_INT(hpfc_graph_edge_count(b.g), t.nedges);
            CHECK(same_export(direct, b.g));
            uint64_t faces, comps;
            faces_of(b.g, &faces, &comps);
            CHECK_EQ_INT(faces, t.ntriangles + 1);
            CHECK_EQ_INT(comps, 1);
        }
        hpfc_graph_free(b.g);
        for (size_t p = 0; p < 3 * t.npoints; p++)
            pos[p] *= 0.25;
        b = build(pos, 3, t.npoints, tri, t.ntriangles, NULL);
        CHECK_EQ_INT(b.status, HPFC_OK);
        if (b.g) {
            CHECK(b.stats.exact);
            CHECK_EQ_INT(hpfc_graph_edge_count(b.g), t.nedges);
        }
        hpfc_graph_free(b.g);
        hpfc_graph_free(direct);
        free(perm);
        free(pos);
        free(tri);
        gen_triangulation_free(&t);
    }
}

/* A jittered grid with holes: cells removed in blocks (inner holes, one with
 * an island of kept cells inside) and at the border. Faces = kept triangles
 * + 1 outer face + 1 per inner hole; the island makes a second component. */
static void test_holes(void)
{
    enum { N = 12 };
    double pos[(N + 1) * (N + 1) * 2];
    uint32_t tri[N * N * 2 * 3];
    gen_rng rng;
    gen_rng_seed(&rng, 99);
    for (int j = 0; j <= N; j++)
        for (int i = 0; i <= N; i++) {
            pos[2 * (j * (N + 1) + i)] = i * 100 + (double)gen_rng_below(&rng, 41) - 20;
            pos[2 * (j * (N + 1) + i) + 1] = j * 100 + (double)gen_rng_below(&rng, 41) - 20;
        }
    size_t nt = 0, kept_cells = 0;
    for (int j = 0; j < N; j++)
        for (int i = 0; i < N; i++) {
            int ring = i >= 5 && i <= 9 && j >= 5 && j <= 9 && !(i == 7 && j == 7);
            int hole = i >= 1 && i <= 2 && j >= 1 && j <= 3;
            int notch = i == N - 1 && j == 0;
            if (ring || hole || notch)
                continue;
            uint32_t a = (uint32_t)(j * (N + 1) + i), b = a + 1, c = a + N + 1, d = c + 1;
            const uint32_t cell[6] = {a, b, d, a, d, c};
            memcpy(tri + 3 * nt, cell, sizeof cell);
            nt += 2;
            kept_cells++;
        }
    built b = build(pos, 2, (N + 1) * (N + 1), tri, nt, NULL);
    CHECK_EQ_INT(b.status, HPFC_OK);
    if (!b.g)
        return;
    uint64_t faces, comps;
    faces_of(b.g, &faces, &comps);
    CHECK_EQ_INT(comps, 2);
    CHECK_EQ_INT(faces, 2 * kept_cells + 1 + 2);
    CHECK_EQ_INT(faces, hpfc_graph_edge_count(b.g) - hpfc_graph_vertex_count(b.g) + 1 + comps);
    hpfc_graph_free(b.g);
}

int main(void)
{
    test_layout_compact = check_use_test_layout();
    test_lattice_exact();
    test_lattice_oracle();
    test_units();
    test_rejections();
    test_merges();
    test_collinear();
    test_nonplanar();
    test_delaunay();
    test_holes();
    return check_report("test_mesh");
}
