/*
 * Builder tests: hand-made pixels for every symbol and for every tie of the
 * perturbation rule, invalid graphs, and generated graphs checked pixel by
 * pixel against the naive oracle of tree_oracle.c.
 */
#include <string.h>

#include "check.h"
#include "gen.h"
#include "hpfc.h"
#include "tree_oracle.h"

enum { RW = 0, RN = 1, RE = 2, RS = 3 }; /* roads in word order */

static hpfc_graph *graph_from(const int64_t *xy, size_t nv, const uint32_t *uv, size_t ne)
{
    hpfc_graph *g;
    if (hpfc_graph_create(&g))
        return NULL;
    for (size_t v = 0; v < nv; v++)
        hpfc_graph_add_vertex(g, xy[2 * v], xy[2 * v + 1], NULL);
    for (size_t e = 0; e < ne; e++)
        hpfc_graph_add_edge(g, uv[2 * e], uv[2 * e + 1], NULL, 0, NULL);
    return g;
}

static hpfc_tree *build_bounded(const hpfc_graph *g, uint32_t n0, uint32_t m0, uint32_t n, uint32_t m,
                                int flat, uint32_t max_leaf_points)
{
    hpfc_build_params p;
    hpfc_build_params_default(&p);
    p.root_cols = n0, p.root_rows = m0, p.cols = n, p.rows = m, p.flat = flat;
    p.max_leaf_points = max_leaf_points;
    hpfc_tree *t = NULL;
    hpfc_diag d;
    int st = hpfc_build(g, &p, &t, &d);
    if (st)
        fprintf(stderr, "build failed: %s: %s\n", hpfc_strerror(st), d.message);
    return t;
}

static hpfc_tree *build(const hpfc_graph *g, uint32_t n0, uint32_t m0, uint32_t n, uint32_t m, int flat)
{
    return build_bounded(g, n0, m0, n, m, flat, HPFC_DEFAULT_MAX_LEAF_POINTS);
}

static bool word_is(const hpfc_tree_pixel *px, const char *w)
{
    return px->type == HPFC_PIXEL_WORD && px->word_len == strlen(w) && !memcmp(px->word, w, px->word_len);
}

/* A triangle with a dead end, on a 2 x 2 root: every symbol appears. The
 * words were derived by hand from the geometry (domain [-3,13) x [-4,12)). */
static void test_every_symbol(void)
{
    const int64_t xy[] = {0, 0, 10, 0, 5, 8, 5, 3};
    const uint32_t uv[] = {0, 1, 1, 2, 2, 0, 0, 3};
    hpfc_graph *g = graph_from(xy, 4, uv, 4);
    hpfc_tree *t = build(g, 2, 2, 2, 2, 0);
    CHECK(t != NULL);
    if (!t)
        return;
    hpfc_tree_info info;
    hpfc_tree_get_info(t, &info);
    CHECK_EQ_INT(info.levels, 1);
    CHECK_EQ_INT(info.x0, -3);
    CHECK_EQ_INT(info.y0, -4);
    CHECK_EQ_INT(info.faces, 2);
    hpfc_tree_pixel px;
    hpfc_tree_get_pixel(t, 0, 0, 0, 0, &px);
    CHECK(word_is(&px, "++[+]+"));     /* c->a cuts the NW pixel E to S */
    hpfc_tree_get_pixel(t, 0, 0, 1, 0, &px);
    CHECK(word_is(&px, "(+++)+"));     /* c on the W road of NE: x = 5 belongs east */
    hpfc_tree_get_pixel(t, 0, 0, 0, 1, &px);
    CHECK(word_is(&px, "+(+Y)++"));    /* a with three branches */
    hpfc_tree_get_pixel(t, 0, 0, 1, 1, &px);
    CHECK(word_is(&px, "(=+)+++"));    /* b and the dead end d */
    CHECK_EQ_INT(oracle_check_tree(g, t, HPFC_DEFAULT_MAX_LEAF_POINTS), 0);
    hpfc_tree_free(t);
    hpfc_graph_free(g);
}

/* The tie tests share a frame that fixes the domain: the extent is [0,14]^2,
 * so with a 4 x 4 root and 2 x 2 refinement the domain is [-1,15)^2 and the
 * root grid lines are x, y in {3, 7, 11}. */
static hpfc_graph *frame_plus(const int64_t *xy, size_t nv, const uint32_t *uv, size_t ne)
{
    int64_t all[64];
    uint32_t edges[64];
    const int64_t frame[] = {0, 0, 0, 14, 14, 14};
    memcpy(all, frame, sizeof frame);
    memcpy(all + 6, xy, 2 * nv * sizeof *xy);
    edges[0] = 0, edges[1] = 1, edges[2] = 1, edges[3] = 2;
    for (size_t k = 0; k < 2 * ne; k++)
        edges[4 + k] = uv[k] + 3;
    return graph_from(all, nv + 3, edges, ne + 2);
}

/* Does the leaf containing lattice point (x, y) have a crossing of `edge`
 * on road `road` (0..3 = W, N, E, S)? */
static bool leaf_has(const hpfc_tree *t, int64_t x, int64_t y, int road, uint32_t edge)
{
    hpfc_tree_pixel px;
    uint32_t level;
    if (!oracle_locate(t, x, y, &px, &level))
        return false;
    size_t counts[4], first = 0;
    oracle_road_counts(px.word, px.word_len, counts);
    for (int r = 0; r < road; r++)
        first += counts[r];
    for (size_t q = 0; q < counts[road]; q++)
        if (px.cross_edge[first + q] == edge)
            return true;
    return false;
}

static bool leaf_touches(const hpfc_tree *t, int64_t x, int64_t y, uint32_t edge)
{
    for (int r = 0; r < 4; r++)
        if (leaf_has(t, x, y, r, edge))
            return true;
    return false;
}

static void test_vertex_on_road(void)
{
    /* vertex (7,5) on the vertical line x = 7, vertex (12,11) on y = 11 */
    const int64_t xy[] = {7, 5, 12, 2, 12, 11, 2, 9};
    const uint32_t uv[] = {0, 1, 2, 3};
    hpfc_graph *g = frame_plus(xy, 4, uv, 2);
    hpfc_tree *t = build(g, 4, 4, 2, 2, 0);
    CHECK(t != NULL);
    if (!t)
        return;
    hpfc_tree_pixel px;
    uint32_t level;
    CHECK(oracle_locate(t, 7, 5, &px, &level));
    CHECK_EQ_INT(px.x0, 7);           /* a vertex on a road goes east ... */
    CHECK(oracle_locate(t, 12, 11, &px, &level));
    CHECK_EQ_INT(px.y0, 11);          /* ... or north */
    CHECK_EQ_INT(oracle_check_tree(g, t, HPFC_DEFAULT_MAX_LEAF_POINTS), 0);
    hpfc_tree_free(t);
    hpfc_graph_free(g);
}

static void test_vertex_on_crossroad(void)
{
    const int64_t xy[] = {11, 7, 4, 1, 2, 12, 13, 10};
    const uint32_t uv[] = {0, 1, 0, 2, 0, 3};
    hpfc_graph *g = frame_plus(xy, 4, uv, 3);
    hpfc_tree *t = build(g, 4, 4, 2, 2, 0);
    CHECK(t != NULL);
    if (!t)
        return;
    hpfc_tree_pixel px;
    uint32_t level;
    CHECK(oracle_locate(t, 11, 7, &px, &level));
    CHECK_EQ_INT(px.x0, 11);          /* the NE pixel of the crossroad */
    CHECK_EQ_INT(px.y0, 7);
    /* the edge to (4,1) leaves the crossroad going SW: under the rule it
     * first crosses into the SE pixel, then its W road into the SW one */
    CHECK(leaf_has(t, 11, 6, RN, 2));
    CHECK(leaf_has(t, 11, 6, RW, 2));
    CHECK(!leaf_touches(t, 10, 7, 2));  /* the NW pixel never sees it */
    CHECK_EQ_INT(oracle_check_tree(g, t, HPFC_DEFAULT_MAX_LEAF_POINTS), 0);
    hpfc_tree_free(t);
    hpfc_graph_free(g);
}

static void test_edge_along_road(void)
{
    /* a horizontal edge on y = 7 and a vertical one on x = 7: each lies on
     * the north / east side of its line */
    const int64_t xy[] = {2, 7, 13, 7, 7, 1, 7, 5};
    const uint32_t uv[] = {0, 1, 2, 3};
    hpfc_graph *g = frame_plus(xy, 4, uv, 2);
    hpfc_tree *t = build(g, 4, 4, 2, 2, 0);
    CHECK(t != NULL);
    if (!t)
        return;
    CHECK(leaf_has(t, 11, 7, RW, 2));     /* crosses x = 11 in the northern row */
    CHECK(!leaf_touches(t, 11, 6, 2));
    CHECK(leaf_has(t, 7, 3, RS, 3) || leaf_has(t, 7, 2, RN, 3)); /* crosses y = 3 east of x = 7 */
    CHECK(!leaf_touches(t, 6, 2, 3));
    CHECK(!leaf_touches(t, 6, 3, 3));
    CHECK_EQ_INT(oracle_check_tree(g, t, HPFC_DEFAULT_MAX_LEAF_POINTS), 0);
    hpfc_tree_free(t);
    hpfc_graph_free(g);
}

static void test_edge_through_crossroad(void)
{
    /* slope +1 through the crossroad (7,3): a small stabbing W -> N in its
     * SE pixel; slope -1 through (7,11): a stabbing W -> S in its NE pixel */
    const int64_t xy[] = {5, 1, 13, 9, 5, 13, 9, 9};
    const uint32_t uv[] = {0, 1, 2, 3};
    hpfc_graph *g = frame_plus(xy, 4, uv, 2);
    hpfc_tree *t = build(g, 4, 4, 2, 2, 0);
    CHECK(t != NULL);
    if (!t)
        return;
    CHECK(leaf_has(t, 7, 2, RW, 2));
    CHECK(leaf_has(t, 7, 2, RN, 2));
    CHECK(!leaf_touches(t, 6, 3, 2));     /* NW of the crossroad: untouched */
    CHECK(leaf_has(t, 7, 11, RW, 3));
    CHECK(leaf_has(t, 7, 11, RS, 3));
    CHECK(!leaf_touches(t, 6, 10, 3));    /* SW of the crossroad: untouched */
    CHECK_EQ_INT(oracle_check_tree(g, t, HPFC_DEFAULT_MAX_LEAF_POINTS), 0);
    hpfc_tree_free(t);
    hpfc_graph_free(g);
}

/* ---- invalid graphs ------------------------------------------------------ */

static int build_status(const hpfc_graph *g, hpfc_diag *d)
{
    hpfc_build_params p;
    hpfc_build_params_default(&p);
    hpfc_tree *t = NULL;
    int st = hpfc_build(g, &p, &t, d);
    hpfc_tree_free(t);
    return st;
}

static void test_invalid_graphs(void)
{
    hpfc_diag d;
    {   /* two edges crossing at (5,5) */
        const int64_t xy[] = {0, 0, 10, 10, 0, 10, 10, 0};
        const uint32_t uv[] = {0, 1, 2, 3};
        hpfc_graph *g = graph_from(xy, 4, uv, 2);
        CHECK_EQ_INT(build_status(g, &d), HPFC_E_NONPLANAR);
        CHECK(d.has_point && d.x == 5.0 && d.y == 5.0);
        CHECK(d.edge[0] == 0 && d.edge[1] == 1);
        hpfc_graph_free(g);
    }
    {   /* a vertex on another edge (T junction without a shared vertex) */
        const int64_t xy[] = {0, 0, 10, 0, 5, 0, 5, 7};
        const uint32_t uv[] = {0, 1, 2, 3};
        hpfc_graph *g = graph_from(xy, 4, uv, 2);
        CHECK_EQ_INT(build_status(g, &d), HPFC_E_NONPLANAR);
        CHECK(d.has_point && d.x == 5.0 && d.y == 0.0);
        hpfc_graph_free(g);
    }
    {   /* two edges from one vertex overlapping along a line */
        const int64_t xy[] = {0, 0, 10, 0, 4, 0};
        const uint32_t uv[] = {0, 1, 0, 2};
        hpfc_graph *g = graph_from(xy, 3, uv, 2);
        CHECK_EQ_INT(build_status(g, &d), HPFC_E_NONPLANAR);
        hpfc_graph_free(g);
    }
    {   /* two straight edges between the same vertices coincide */
        const int64_t xy[] = {0, 0, 10, 3};
        const uint32_t uv[] = {0, 1, 0, 1};
        hpfc_graph *g = graph_from(xy, 2, uv, 2);
        CHECK_EQ_INT(build_status(g, &d), HPFC_E_NONPLANAR);
        hpfc_graph_free(g);
    }
    {   /* duplicate vertices */
        const int64_t xy[] = {0, 0, 10, 3, 0, 0, 5, 9};
        const uint32_t uv[] = {0, 1, 2, 3};
        hpfc_graph *g = graph_from(xy, 4, uv, 2);
        CHECK_EQ_INT(build_status(g, &d), HPFC_E_DUPLICATE_POINT);
        hpfc_graph_free(g);
    }
    {   /* the culprit is a function of the graph, not of the sort: the pair
         * whose later point comes first (vertices by index, then interior
         * points by edge), even where another pair lies first by place */
        hpfc_graph *g;
        hpfc_graph_create(&g);
        hpfc_graph_set_unit_exp10(g, -1);
        const int64_t xy[] = {0, 0, 20, 0, 0, 20, 20, 20};
        for (size_t v = 0; v < 4; v++)
            hpfc_graph_add_vertex(g, xy[2 * v], xy[2 * v + 1], NULL);
        const int64_t mid[] = {7, 7}, corner[] = {0, 20};
        hpfc_graph_add_edge(g, 0, 1, mid, 1, NULL);
        hpfc_graph_add_edge(g, 2, 3, mid, 1, NULL);
        hpfc_graph_add_edge(g, 1, 3, corner, 1, NULL); /* on vertex 2, at a smaller x */
        CHECK_EQ_INT(hpfc_graph_validate(g, &d), HPFC_E_DUPLICATE_POINT);
        CHECK(strcmp(d.message, "interior point 1 of edge 1 is at the same point (0.7, 0.7) as "
                                "interior point 1 of edge 0") == 0);
        CHECK(d.edge[0] == 0 && d.edge[1] == 1 && d.line == 0);
        CHECK(d.has_point && d.x == 7 * 0.1 && d.y == 7 * 0.1);
        hpfc_graph_add_vertex(g, 0, 0, NULL); /* vertex 4 on vertex 0: a vertex pair first */
        hpfc_graph_add_edge(g, 4, 3, NULL, 0, NULL);
        CHECK_EQ_INT(hpfc_graph_validate(g, &d), HPFC_E_DUPLICATE_POINT);
        CHECK(strcmp(d.message, "vertex 4 is at the same point (0, 0) as vertex 0") == 0);
        CHECK(d.edge[0] == -1 && d.edge[1] == -1);
        hpfc_graph_free(g);
    }
    {   /* a polyline that crosses itself */
        hpfc_graph *g;
        hpfc_graph_create(&g);
        hpfc_graph_add_vertex(g, 0, 0, NULL);
        hpfc_graph_add_vertex(g, 0, 6, NULL);
        const int64_t pts[] = {6, 6, 6, 0}; /* its 1st and 3rd segments cross at (3,3) */
        hpfc_graph_add_edge(g, 0, 1, pts, 2, NULL);
        CHECK_EQ_INT(build_status(g, &d), HPFC_E_NONPLANAR);
        CHECK(d.edge[0] == 0 && d.edge[1] == 0);
        hpfc_graph_free(g);
    }
    {   /* a polyline that folds back on itself */
        hpfc_graph *g;
        hpfc_graph_create(&g);
        hpfc_graph_add_vertex(g, 0, 0, NULL);
        hpfc_graph_add_vertex(g, 10, 5, NULL);
        const int64_t pts[] = {6, 0, 3, 0};
        hpfc_graph_add_edge(g, 0, 1, pts, 2, NULL);
        CHECK_EQ_INT(build_status(g, &d), HPFC_E_NONPLANAR);
        hpfc_graph_free(g);
    }
    {   /* loop edges need two interior points; zero-length segments */
        hpfc_graph *g;
        hpfc_graph_create(&g);
        hpfc_graph_add_vertex(g, 0, 0, NULL);
        hpfc_graph_add_vertex(g, 10, 5, NULL);
        const int64_t pts[] = {6, 0};
        hpfc_graph_add_edge(g, 0, 0, pts, 1, NULL);
        CHECK_EQ_INT(build_status(g, &d), HPFC_E_LOOP_INTERIOR);
        hpfc_graph_free(g);
        hpfc_graph_create(&g);
        hpfc_graph_add_vertex(g, 0, 0, NULL);
        hpfc_graph_add_vertex(g, 10, 5, NULL);
        const int64_t pts2[] = {6, 0, 6, 0};
        hpfc_graph_add_edge(g, 0, 1, pts2, 2, NULL);
        CHECK_EQ_INT(build_status(g, &d), HPFC_E_ZERO_LENGTH);
        hpfc_graph_free(g);
    }
    {   /* isolated vertex; empty graph */
        const int64_t xy[] = {0, 0, 10, 3, 4, 4};
        const uint32_t uv[] = {0, 1};
        hpfc_graph *g = graph_from(xy, 3, uv, 1);
        CHECK_EQ_INT(build_status(g, &d), HPFC_E_ISOLATED_VERTEX);
        CHECK(strcmp(d.message, "vertex 2 has no edge (isolated vertex)") == 0);
        CHECK(d.has_point && d.x == 4 && d.y == 4);
        hpfc_graph_free(g);
        g = graph_from(xy, 0, uv, 0);
        CHECK_EQ_INT(build_status(g, &d), HPFC_E_EMPTY);
        hpfc_graph_free(g);
    }
    {   /* extent beyond the lattice */
        const int64_t xy[] = {-HPFC_COORD_MAX, 0, HPFC_COORD_MAX, 1};
        const uint32_t uv[] = {0, 1};
        hpfc_graph *g = graph_from(xy, 2, uv, 1);
        CHECK_EQ_INT(build_status(g, &d), HPFC_E_EXTENT);
        hpfc_graph_free(g);
    }
    {   /* bad parameters, and a flat grid above its limit: the short edge
         * lies inside pixels of 4 x 4 lattice units, 2^18 to a side */
        const int64_t xy[] = {0, 0, 1000000, 0, 500, 5, 501, 7};
        const uint32_t uv[] = {0, 1, 2, 3};
        hpfc_graph *g = graph_from(xy, 4, uv, 2);
        hpfc_build_params p;
        hpfc_tree *t = NULL;
        hpfc_build_params_default(&p);
        p.cols = 1;
        CHECK_EQ_INT(hpfc_build(g, &p, &t, &d), HPFC_E_ARG);
        hpfc_build_params_default(&p);
        p.flat = 1;
        p.max_flat_pixels = 1 << 20;
        CHECK_EQ_INT(hpfc_build(g, &p, &t, &d), HPFC_E_TOO_MANY_PIXELS);
        CHECK(t == NULL);
        hpfc_graph_free(g);
    }
}

/* ---- generated graphs ---------------------------------------------------- */

static int flat_compared; /* flat grids small enough to compare */

typedef struct shape {
    uint32_t n0, m0, n, m;
} shape;

static const shape SHAPES[] = {
    {1, 1, 2, 2}, {4, 3, 2, 2}, {3, 5, 3, 2}, {16, 16, 2, 2}, {7, 7, 4, 4}, {2, 1, 2, 3},
};

/* Builds the flat rPFC of the same graph (when its grid is small enough for
 * the naive oracle) and compares its crossings with the hPFC's. */
static void compare_with_flat(const hpfc_graph *g, const hpfc_tree *t, const shape *sh)
{
    hpfc_build_params p;
    hpfc_build_params_default(&p);
    p.root_cols = sh->n0, p.root_rows = sh->m0, p.cols = sh->n, p.rows = sh->m, p.flat = 1;
    p.max_flat_pixels = 1 << 18;
    hpfc_tree *flat = NULL;
    hpfc_diag d;
    int st = hpfc_build(g, &p, &flat, &d);
    CHECK(st == HPFC_OK || st == HPFC_E_TOO_MANY_PIXELS);
    if (st)
        return;
    flat_compared++;
    hpfc_tree_info info;
    hpfc_tree_get_info(flat, &info);
    CHECK_EQ_INT(info.levels, 1);
    if ((uint64_t)info.root_cols * info.root_rows <= (1 << 14))
        CHECK_EQ_INT(oracle_check_tree(g, flat, 0), 0);
    CHECK_EQ_INT(oracle_compare_flat(flat, t), 0);
    hpfc_tree_free(flat);
}

/* hpfc_build_domain on the box of g's edges' points (read through the
 * public graph calls) gives tree t's domain, and that domain is what its
 * definition says: root_cols * cols^K wide (rows likewise), a lattice unit
 * of margin on every side, K the smallest such, the tree no deeper. */
static void check_domain(const hpfc_graph *g, const hpfc_tree *t, const shape *sh)
{
    int64_t box[4] = {INT64_MAX, INT64_MAX, INT64_MIN, INT64_MIN};
    for (size_t e = 0; e < hpfc_graph_edge_count(g); e++) {
        uint32_t uv[2];
        const int64_t *xy;
        size_t n;
        hpfc_graph_edge(g, e, &uv[0], &uv[1], &xy, &n);
        for (size_t k = 0; k < n + 2; k++) {
            int64_t x, y;
            if (k < 2)
                hpfc_graph_vertex(g, uv[k], &x, &y);
            else
                x = xy[2 * (k - 2)], y = xy[2 * (k - 2) + 1];
            box[0] = x < box[0] ? x : box[0], box[2] = x > box[2] ? x : box[2];
            box[1] = y < box[1] ? y : box[1], box[3] = y > box[3] ? y : box[3];
        }
    }
    hpfc_build_params p;
    hpfc_build_params_default(&p);
    p.root_cols = sh->n0, p.root_rows = sh->m0, p.cols = sh->n, p.rows = sh->m;
    hpfc_domain d;
    hpfc_diag diag;
    CHECK_EQ_INT(hpfc_build_domain(box, &p, &d, &diag), HPFC_OK);
    hpfc_tree_info info;
    hpfc_tree_get_info(t, &info);
    CHECK(d.x0 == info.x0 && d.y0 == info.y0 && d.width == info.width && d.height == info.height);
    CHECK(info.levels <= d.max_depth + 1);
    int64_t w = sh->n0, h = sh->m0;
    for (uint32_t k = 0; k < d.max_depth; k++)
        w *= sh->n, h *= sh->m;
    CHECK(d.width == w && d.height == h);
    CHECK(d.x0 < box[0] && d.y0 < box[1] && box[2] < d.x0 + w && box[3] < d.y0 + h);
    CHECK(d.max_depth == 0 || w / sh->n < box[2] - box[0] + 2 || h / sh->m < box[3] - box[1] + 2);
}

/* What hpfc_build_domain refuses. */
static void test_domain_refusals(void)
{
    hpfc_build_params p;
    hpfc_build_params_default(&p);
    hpfc_domain d;
    hpfc_diag diag;
    const int64_t box[4] = {0, 0, 10, 10}, empty[4] = {5, 0, 4, 10},
                  far[4] = {-HPFC_COORD_MAX - 1, 0, 0, 1},
                  wide[4] = {-HPFC_COORD_MAX, 0, HPFC_COORD_MAX, 1};
    CHECK_EQ_INT(hpfc_build_domain(NULL, &p, &d, &diag), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_build_domain(box, NULL, &d, &diag), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_build_domain(box, &p, NULL, &diag), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_build_domain(empty, &p, &d, &diag), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_build_domain(far, &p, &d, &diag), HPFC_E_EXTENT);
    CHECK_EQ_INT(hpfc_build_domain(wide, &p, &d, &diag), HPFC_E_EXTENT);
    p.cols = 1;
    CHECK_EQ_INT(hpfc_build_domain(box, &p, &d, &diag), HPFC_E_ARG);
    hpfc_build_params_default(&p);
    CHECK_EQ_INT(hpfc_build_domain(box, &p, &d, &diag), HPFC_OK);
    CHECK(d.width == 64 && d.height == 64 && d.max_depth == 0 && d.x0 == -27 && d.y0 == -27);
}

/* Bounds on shape points per leaf: none, the tightest, a small one and the
 * default. */
static const uint32_t LEAF_BOUNDS[] = {0, 1, 3, HPFC_DEFAULT_MAX_LEAF_POINTS};

/* Builds g with every image shape and leaf bound and checks each tree with
 * the oracle. Returns the refined pixels of the tightest bound's trees
 * beyond the unbounded ones', so a caller can tell the bound was exercised. */
static uint64_t check_graph_all_shapes(const hpfc_graph *g, const char *what, bool compare_flat)
{
    uint64_t extra_refined = 0;
    for (size_t s = 0; s < sizeof SHAPES / sizeof *SHAPES; s++) {
        const shape *sh = &SHAPES[s];
        uint64_t refined[sizeof LEAF_BOUNDS / sizeof *LEAF_BOUNDS] = {0};
        for (size_t b = 0; b < sizeof LEAF_BOUNDS / sizeof *LEAF_BOUNDS; b++) {
            hpfc_tree *t = build_bounded(g, sh->n0, sh->m0, sh->n, sh->m, 0, LEAF_BOUNDS[b]);
            CHECK(t != NULL);
            if (!t)
                continue;
            int fails = oracle_check_tree(g, t, LEAF_BOUNDS[b]);
            if (fails)
                fprintf(stderr, "%s with %ux%u/%ux%u, leaf bound %u: %d oracle failures\n", what, sh->n0,
                        sh->m0, sh->n, sh->m, LEAF_BOUNDS[b], fails);
            CHECK_EQ_INT(fails, 0);
            check_domain(g, t, sh);
            hpfc_tree_info info;
            hpfc_tree_get_info(t, &info);
            refined[b] = info.refined_pixels;
            /* the flat grid is the unbounded tree's finest leaves */
            if (compare_flat && LEAF_BOUNDS[b] == 0)
                compare_with_flat(g, t, sh);
            hpfc_tree_free(t);
        }
        CHECK(refined[1] >= refined[2] && refined[2] >= refined[0]);
        extra_refined += refined[1] - refined[0];
    }
    return extra_refined;
}

/* For n0 = m0 = 1 and n = m = 2, every refined pixel splits into its four
 * quadrants. */
static void check_quadtree(const hpfc_graph *g)
{
    hpfc_tree *t = build(g, 1, 1, 2, 2, 0);
    CHECK(t != NULL);
    if (!t)
        return;
    hpfc_tree_info info;
    hpfc_tree_get_info(t, &info);
    CHECK_EQ_INT(hpfc_tree_image_count(t, 0), 1);
    for (uint32_t l = 0; l + 1 < info.levels; l++) {
        uint32_t cols = l ? 2 : 1;
        for (size_t im = 0; im < hpfc_tree_image_count(t, l); im++)
            for (uint32_t j = 0; j < cols; j++)
                for (uint32_t i = 0; i < cols; i++) {
                    hpfc_tree_pixel px, q;
                    hpfc_tree_get_pixel(t, l, im, i, j, &px);
                    if (px.type != HPFC_PIXEL_REFINED)
                        continue;
                    int64_t hx = (px.x1 - px.x0) / 2, hy = (px.y1 - px.y0) / 2;
                    hpfc_tree_get_pixel(t, l + 1, px.child, 0, 0, &q); /* NW quadrant */
                    CHECK(q.x0 == px.x0 && q.x1 == px.x0 + hx && q.y0 == px.y0 + hy && q.y1 == px.y1);
                    hpfc_tree_get_pixel(t, l + 1, px.child, 1, 1, &q); /* SE quadrant */
                    CHECK(q.x0 == px.x0 + hx && q.x1 == px.x1 && q.y0 == px.y0 && q.y1 == px.y0 + hy);
                }
    }
    hpfc_tree_free(t);
}

static void test_generated(void)
{
    for (uint64_t seed = 1; seed <= 4; seed++) {
        hpfc_graph *g = NULL;
        CHECK_EQ_INT(gen_delaunay(seed, 40 + 30 * seed, 1 << 12, 0.2, &g), HPFC_OK);
        if (g) {
            check_graph_all_shapes(g, "delaunay", seed <= 2);
            check_quadtree(g);
        }
        hpfc_graph_free(g);
        g = NULL;
        CHECK_EQ_INT(gen_polyline(seed, 120, 1 << 12, 0.5, &g), HPFC_OK);
        if (g) {
            /* polylines put several shape points in a leaf: the bound must bite */
            CHECK(check_graph_all_shapes(g, "polyline", seed <= 2) > 0);
            check_quadtree(g);
        }
        hpfc_graph_free(g);
    }
    for (int which = 0; which < GEN_SPECIAL_COUNT; which++) {
        hpfc_graph *g = NULL;
        CHECK_EQ_INT(gen_special(which, &g), HPFC_OK);
        if (g)
            check_graph_all_shapes(g, "special", true);
        hpfc_graph_free(g);
    }
    CHECK(flat_compared >= 20); /* the comparison must not be skipped wholesale */
}

/* The progress callback: per level, images done rising to the level's
 * image count (the tree's), the levels in order, the last one reported. */
typedef struct progress_log {
    uint32_t level;
    uint64_t done, total, calls, levels_ended;
    bool ordered;
} progress_log;

static void log_progress(void *user, uint32_t level, uint64_t done, uint64_t total)
{
    progress_log *log = user;
    bool same = level == log->level && done > log->done && total == log->total;
    bool next = level == log->level + 1 && log->done == log->total && done >= 1;
    if (log->calls == 0)
        next = level == 0 && done >= 1;
    log->ordered &= (same || next) && done <= total;
    log->levels_ended += done == total;
    log->level = level, log->done = done, log->total = total;
    log->calls++;
}

static void test_progress(void)
{
    hpfc_graph *g = NULL;
    CHECK_EQ_INT(gen_grid_mesh(5, 200, 200, 20, &g), HPFC_OK);
    hpfc_build_params p;
    hpfc_build_params_default(&p);
    CHECK(p.progress == NULL && p.progress_user == NULL);
    progress_log log = {.ordered = true};
    p.root_cols = p.root_rows = 4;
    p.progress = log_progress;
    p.progress_user = &log;
    hpfc_tree *t = NULL;
    hpfc_diag d;
    CHECK_EQ_INT(hpfc_build(g, &p, &t, &d), HPFC_OK);
    if (t) {
        hpfc_tree_info info;
        hpfc_tree_get_info(t, &info);
        CHECK(log.ordered);
        CHECK_EQ_INT(log.levels_ended, info.levels);
        CHECK_EQ_INT(log.level, info.levels - 1);
        CHECK_EQ_INT(log.total, hpfc_tree_image_count(t, info.levels - 1));
        CHECK(log.calls > info.levels); /* some level has over 4096 images */
    }
    hpfc_tree_free(t);
    hpfc_graph_free(g);
}

int main(void)
{
    test_every_symbol();
    test_domain_refusals();
    test_vertex_on_road();
    test_vertex_on_crossroad();
    test_edge_along_road();
    test_edge_through_crossroad();
    test_invalid_graphs();
    test_generated();
    test_progress();
    return check_report("build");
}
