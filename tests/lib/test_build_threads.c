/* The build on several threads (hpfc_build_params.threads) against the
 * build on one:
 *   - valid maps of every generator, at three image shapes and two leaf
 *     point bounds, give on 2, 3 and 8 threads the same tree, array for
 *     array (every level's images and pixels, refined pixels' children
 *     among them, which the file does not store, the words' symbols and
 *     crossings, every counter of its info), and so the same file, byte
 *     for byte;
 *   - the same maps with one random straight edge added (which mostly
 *     crosses or touches another: validation's search on threads), or
 *     one vertex moved onto another's place, give on 3 threads the status
 *     and the very message one thread gives; those that still build give
 *     the same bytes.
 * Built with ThreadSanitizer too (tools/run-tests.sh), where any report
 * fails the run. */
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "gen.h"
#include "hpfc.h"
#include "tree.h"

static size_t maps_built, mutants_checked, mutants_refused;

static bool same_array(const void *a, const void *b, size_t bytes)
{
    return bytes == 0 || (a && b && memcmp(a, b, bytes) == 0);
}

/* The two trees, array for array. */
static bool same_tree(const hpfc_tree *a, const hpfc_tree *b)
{
    if (memcmp(&a->info, &b->info, sizeof a->info) != 0 || a->nsyms != b->nsyms ||
        a->ncross != b->ncross || !same_array(a->syms, b->syms, a->nsyms) ||
        !same_array(a->cross_edge, b->cross_edge, a->ncross * sizeof *a->cross_edge) ||
        (a->cross_seg != NULL) != (b->cross_seg != NULL) ||
        (a->cross_seg && !same_array(a->cross_seg, b->cross_seg, a->ncross * sizeof *a->cross_seg)))
        return false;
    for (uint32_t l = 0; l < a->info.levels; l++) {
        const tlevel *x = &a->levels[l], *y = &b->levels[l];
        size_t n = x->nimages, per = (size_t)x->cols * x->rows;
        if (n != y->nimages || x->cols != y->cols || x->rows != y->rows || x->cell_w != y->cell_w ||
            x->cell_h != y->cell_h || !same_array(x->img_gx, y->img_gx, n * sizeof *x->img_gx) ||
            !same_array(x->img_gy, y->img_gy, n * sizeof *x->img_gy) ||
            !same_array(x->pix, y->pix, n * per * sizeof *x->pix))
            return false;
    }
    return true;
}

/* g built on `threads` threads, and its file (NULL when the build fails:
 * its status in *status and message in diag). */
static uint8_t *build_bytes(const hpfc_graph *g, const hpfc_build_params *base, unsigned threads,
                            hpfc_tree **tree, size_t *size, int *status, hpfc_diag *diag)
{
    hpfc_build_params p = *base;
    p.threads = threads;
    uint8_t *bytes = NULL;
    memset(diag, 0, sizeof *diag);
    *tree = NULL;
    *status = hpfc_build(g, &p, tree, diag);
    if (*status)
        return NULL;
    hpfc_write_options o = {.face_labels = 1};
    CHECK_EQ_INT(hpfc_tree_serialize(*tree, &o, &bytes, size, NULL), HPFC_OK);
    return bytes;
}

/* Builds on 1 and on `threads` threads must agree: status, message, bytes. */
static int compare_builds(const hpfc_graph *g, const hpfc_build_params *p, unsigned threads,
                          const char *what)
{
    size_t size1 = 0, size_n = 0;
    int st1, st_n;
    hpfc_diag d1, dn;
    hpfc_tree *t1, *tn;
    uint8_t *one = build_bytes(g, p, 1, &t1, &size1, &st1, &d1);
    uint8_t *many = build_bytes(g, p, threads, &tn, &size_n, &st_n, &dn);
    CHECK_EQ_INT(st_n, st1);
    if (st1 || st_n) {
        if (strcmp(d1.message, dn.message) != 0)
            fprintf(stderr, "%s, %u threads: '%s' against one thread's '%s'\n", what, threads, dn.message,
                    d1.message);
        CHECK(strcmp(d1.message, dn.message) == 0);
    } else {
        bool same = t1 && tn && same_tree(t1, tn);
        if (!same || size1 != size_n || memcmp(one, many, size1) != 0)
            fprintf(stderr, "%s, %u threads: the %s differ from one thread's\n", what, threads,
                    same ? "bytes" : "trees");
        CHECK(same);
        CHECK(one && many && size1 == size_n && memcmp(one, many, size1) == 0);
    }
    hpfc_tree_free(t1);
    hpfc_tree_free(tn);
    hpfc_free(one);
    hpfc_free(many);
    return st1;
}

/* A copy of g (NULL on failure). */
static hpfc_graph *copy_graph(const hpfc_graph *g)
{
    hpfc_graph *c = NULL;
    if (hpfc_graph_create(&c))
        return NULL;
    hpfc_graph_set_unit_exp10(c, hpfc_graph_unit_exp10(g));
    for (size_t v = 0; v < hpfc_graph_vertex_count(g); v++) {
        int64_t x, y;
        hpfc_graph_vertex(g, v, &x, &y);
        hpfc_graph_add_vertex(c, x, y, NULL);
    }
    for (size_t e = 0; e < hpfc_graph_edge_count(g); e++) {
        uint32_t u, v;
        const int64_t *xy;
        size_t n;
        hpfc_graph_edge(g, e, &u, &v, &xy, &n);
        hpfc_graph_add_edge(c, u, v, xy, n, NULL);
    }
    return c;
}

/* g with a straight edge between two random vertices, or with a vertex
 * of degree 0 at another vertex's place (a duplicate point). */
static hpfc_graph *mutant(const hpfc_graph *g, gen_rng *rng)
{
    size_t nv = hpfc_graph_vertex_count(g);
    hpfc_graph *m = nv >= 2 ? copy_graph(g) : NULL;
    if (!m)
        return NULL;
    uint32_t a = (uint32_t)gen_rng_below(rng, nv), b = (uint32_t)gen_rng_below(rng, nv);
    if (gen_rng_below(rng, 4) == 0) {
        int64_t x, y;
        uint32_t added;
        hpfc_graph_vertex(g, a, &x, &y);
        hpfc_graph_add_vertex(m, x, y, &added);
        hpfc_graph_add_edge(m, added, b, NULL, 0, NULL);
    } else if (a != b)
        hpfc_graph_add_edge(m, a, b, NULL, 0, NULL);
    return m;
}

static void check_map(const hpfc_graph *g, const char *what, uint64_t seed, int mutants)
{
    static const struct {
        uint32_t root, cols, leaf_points;
    } shapes[] = {{64, 2, 16}, {4, 2, 0}, {3, 3, 4}};
    for (size_t s = 0; s < sizeof shapes / sizeof *shapes; s++) {
        hpfc_build_params p;
        hpfc_build_params_default(&p);
        p.root_cols = p.root_rows = shapes[s].root;
        p.cols = p.rows = shapes[s].cols;
        p.max_leaf_points = shapes[s].leaf_points;
        static const unsigned threads[] = {2, 3, 8};
        for (size_t k = 0; k < sizeof threads / sizeof *threads; k++)
            CHECK_EQ_INT(compare_builds(g, &p, threads[k], what), HPFC_OK);
    }
    maps_built++;
    gen_rng rng;
    gen_rng_seed(&rng, seed);
    hpfc_build_params p;
    hpfc_build_params_default(&p);
    p.root_cols = p.root_rows = 4;
    for (int k = 0; k < mutants; k++) {
        hpfc_graph *m = mutant(g, &rng);
        if (!m)
            continue;
        mutants_refused += compare_builds(m, &p, 3, what) != HPFC_OK;
        mutants_checked++;
        hpfc_graph_free(m);
    }
}

/* Usage: test_build_threads [SEEDS [MUTANTS]]: the generators' seeds 1 ..
 * SEEDS (default 4), MUTANTS a map (default 12); the ThreadSanitizer run
 * (tools/run-tests.sh) takes fewer. */
int main(int argc, char **argv)
{
    uint64_t seeds = argc > 1 ? strtoull(argv[1], NULL, 10) : 4;
    int mutants = argc > 2 ? atoi(argv[2]) : 12;
    size_t want_maps = (size_t)GEN_SPECIAL_COUNT + 3 * seeds;
    for (int k = 0; k < GEN_SPECIAL_COUNT; k++) {
        hpfc_graph *g = NULL;
        if (gen_special(k, &g) == HPFC_OK)
            check_map(g, gen_special_name(k), 100 + (uint64_t)k, mutants);
        hpfc_graph_free(g);
    }
    for (uint64_t seed = 1; seed <= seeds; seed++) {
        hpfc_graph *g = NULL;
        if (gen_delaunay(seed, 60 * seed * seed, 100000, 0.3, &g) == HPFC_OK)
            check_map(g, "delaunay", seed, mutants);
        hpfc_graph_free(g);
        g = NULL;
        if (gen_polyline(seed, 80 * seed * seed, 100000, 0.5, &g) == HPFC_OK)
            check_map(g, "polyline", 1000 + seed, mutants);
        hpfc_graph_free(g);
        g = NULL;
        if (gen_grid_mesh(seed, 3 + 4 * seed, 2 + 3 * seed, 40, &g) == HPFC_OK)
            check_map(g, "grid", 2000 + seed, mutants);
        hpfc_graph_free(g);
    }
    printf("build_threads: %zu maps, %zu mutants (%zu refused)\n", maps_built, mutants_checked,
           mutants_refused);
    CHECK(maps_built == want_maps);
    CHECK(mutants_checked >= maps_built && mutants_refused > 0 && mutants_refused < mutants_checked);
    return check_report("build_threads");
}
