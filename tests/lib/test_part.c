/*
 * A build split into parts (hpfc_build_part, hpfc_tree_merge) against the
 * single build of the same map: for random sets of root pixels, parts built
 * from the whole graph or from the edges that meet their pixels alone (with
 * the vertices renumbered), the joined tree has the single tree's info and
 * writes the same bytes in both pool layouts, with and without LABL and
 * GEOM. Then every refusal the header lists.
 */
#include <stdbool.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "gen.h"
#include "format.h"
#include "hpfc.h"

typedef struct shape {
    uint32_t n0, m0, n, m, leaf_points;
} shape;

static const shape SHAPES[] = {
    {1, 1, 2, 2, 16}, {4, 3, 2, 2, 16}, {3, 5, 3, 2, 0}, {16, 16, 2, 2, 16}, {7, 7, 4, 4, 1}, {2, 1, 2, 3, 3},
    {40, 30, 2, 2, 16}, /* a root of over 1,024 pixels: parts of no segment at all */
};

static hpfc_build_params params_of(const shape *sh)
{
    hpfc_build_params p;
    hpfc_build_params_default(&p);
    p.root_cols = sh->n0, p.root_rows = sh->m0, p.cols = sh->n, p.rows = sh->m;
    p.max_leaf_points = sh->leaf_points;
    return p;
}

/* ---- a part's graph: the edges whose segments' boxes meet its pixels ---- */

typedef struct subgraph {
    hpfc_graph *g;
    uint32_t *edge_ids;
} subgraph;

/* Does the closed box of segment (a, b) meet root pixel p's closed cell? A
 * box test keeps more edges than meet the pixel, which a part allows. */
static bool segment_near_pixel(const int64_t a[2], const int64_t b[2], const hpfc_domain *d,
                               const hpfc_build_params *p, uint32_t pixel)
{
    int64_t cw = d->width / p->root_cols, ch = d->height / p->root_rows;
    int64_t i = pixel % p->root_cols, j = pixel / p->root_cols, gy = p->root_rows - 1 - j;
    int64_t x0 = d->x0 + i * cw, y0 = d->y0 + gy * ch;
    int64_t bx0 = a[0] < b[0] ? a[0] : b[0], bx1 = a[0] < b[0] ? b[0] : a[0];
    int64_t by0 = a[1] < b[1] ? a[1] : b[1], by1 = a[1] < b[1] ? b[1] : a[1];
    return bx1 >= x0 && bx0 <= x0 + cw && by1 >= y0 && by0 <= y0 + ch;
}

static bool edge_near_part(const hpfc_graph *g, size_t e, const hpfc_domain *d, const hpfc_build_params *p,
                           const uint32_t *pixels, size_t npixels)
{
    uint32_t u, v;
    const int64_t *xy;
    size_t n;
    hpfc_graph_edge(g, e, &u, &v, &xy, &n);
    int64_t prev[2], cur[2];
    hpfc_graph_vertex(g, u, &prev[0], &prev[1]);
    for (size_t k = 0; k <= n; k++) {
        if (k < n)
            cur[0] = xy[2 * k], cur[1] = xy[2 * k + 1];
        else
            hpfc_graph_vertex(g, v, &cur[0], &cur[1]);
        for (size_t q = 0; q < npixels; q++)
            if (segment_near_pixel(prev, cur, d, p, pixels[q]))
                return true;
        prev[0] = cur[0], prev[1] = cur[1];
    }
    return false;
}

/* The part's edges in the whole map's order; their vertices numbered in
 * reverse order of the whole map's, which a part must not depend on. */
static int make_subgraph(const hpfc_graph *g, const hpfc_domain *d, const hpfc_build_params *p,
                         const uint32_t *pixels, size_t npixels, uint32_t skip_edge, subgraph *out)
{
    size_t nv = hpfc_graph_vertex_count(g), ne = hpfc_graph_edge_count(g);
    uint32_t *vmap = malloc(nv * sizeof *vmap);
    out->edge_ids = malloc((ne ? ne : 1) * sizeof *out->edge_ids);
    out->g = NULL;
    if (!vmap || !out->edge_ids || hpfc_graph_create(&out->g))
        return HPFC_E_NOMEM;
    hpfc_graph_set_unit_exp10(out->g, hpfc_graph_unit_exp10(g));
    uint8_t *keep = calloc(ne ? ne : 1, 1), *used = calloc(nv ? nv : 1, 1);
    for (size_t e = 0; e < ne; e++) {
        uint32_t u, v;
        const int64_t *xy;
        size_t n;
        hpfc_graph_edge(g, e, &u, &v, &xy, &n);
        keep[e] = e != skip_edge && edge_near_part(g, e, d, p, pixels, npixels);
        if (keep[e])
            used[u] = used[v] = 1;
    }
    uint32_t next = 0;
    for (size_t k = nv; k-- > 0;)
        if (used[k]) {
            int64_t x, y;
            hpfc_graph_vertex(g, k, &x, &y);
            hpfc_graph_add_vertex(out->g, x, y, NULL);
            vmap[k] = next++;
        }
    size_t kept = 0;
    for (size_t e = 0; e < ne; e++)
        if (keep[e]) {
            uint32_t u, v;
            const int64_t *xy;
            size_t n;
            hpfc_graph_edge(g, e, &u, &v, &xy, &n);
            hpfc_graph_add_edge(out->g, vmap[u], vmap[v], xy, n, NULL);
            out->edge_ids[kept++] = (uint32_t)e;
        }
    free(keep);
    free(used);
    free(vmap);
    return HPFC_OK;
}

/* ---- comparing the joined tree with the single one ---------------------- */

static bool same_info(const hpfc_tree *a, const hpfc_tree *b)
{
    hpfc_tree_info x, y;
    hpfc_tree_get_info(a, &x);
    hpfc_tree_get_info(b, &y);
    return x.root_cols == y.root_cols && x.root_rows == y.root_rows && x.cols == y.cols && x.rows == y.rows &&
           x.levels == y.levels && x.x0 == y.x0 && x.y0 == y.y0 && x.width == y.width &&
           x.height == y.height && x.unit_exp10 == y.unit_exp10 && x.vertices == y.vertices &&
           x.edges == y.edges && x.faces == y.faces && x.components == y.components &&
           x.word_pixels == y.word_pixels && x.refined_pixels == y.refined_pixels &&
           x.private_pixels == y.private_pixels && x.max_word_symbols == y.max_word_symbols;
}

static int comparisons;

/* Both trees written alike, in each layout, with and without LABL and
 * GEOM: the same bytes. */
static void check_same_bytes(const hpfc_tree *single, const hpfc_tree *joined, const hpfc_graph *g)
{
    for (int layout = HPFC_LAYOUT_PAPER; layout <= HPFC_LAYOUT_COMPACT; layout++)
        for (int extras = 0; extras < 2; extras++) {
            hpfc_write_options o = {.layout = layout, .face_labels = extras, .geometry = extras ? g : NULL};
            uint8_t *a = NULL, *b = NULL;
            size_t na = 0, nb = 0;
            hpfc_diag d;
            int sa = hpfc_tree_serialize(single, &o, &a, &na, &d);
            int sb = hpfc_tree_serialize(joined, &o, &b, &nb, &d);
            CHECK_EQ_INT(sa, HPFC_OK);
            CHECK_EQ_INT(sb, HPFC_OK);
            CHECK(na == nb && a && b && memcmp(a, b, na) == 0);
            comparisons++;
            hpfc_free(a);
            hpfc_free(b);
        }
}

/* Deals the root pixels to k parts at random (a part may get none), or in
 * runs of scanline order when `runs`. */
static void deal_pixels(gen_rng *rng, uint32_t roots, size_t k, bool runs, uint32_t *owner)
{
    for (uint32_t p = 0; p < roots; p++)
        owner[p] = runs ? (uint32_t)((uint64_t)p * k / roots) : (uint32_t)gen_rng_below(rng, k);
}

static char part_path[64];

/* The part written to a part file and read back, in place of itself. */
static void through_file(hpfc_tree **part)
{
    hpfc_diag d;
    hpfc_tree *back = NULL;
    CHECK_EQ_INT(hpfc_tree_write_part(*part, part_path, &d), HPFC_OK);
    int st = hpfc_tree_read_part(part_path, &back, &d);
    if (st)
        fprintf(stderr, "part file read back: %s: %s\n", hpfc_strerror(st), d.message);
    CHECK_EQ_INT(st, HPFC_OK);
    if (back) {
        hpfc_tree_free(*part);
        *part = back;
    }
}

/* Part q's own file, for the joins from files. */
static void part_file_path(char *path, size_t size, size_t q)
{
    if (snprintf(path, size, "%s.%zu", part_path, q) >= (int)size)
        path[0] = '\0'; /* never: part_path is short */
}

/* The parts written to files, freed, and joined from the files in a
 * random order (hpfc_tree_merge_files). The files are removed before the
 * joined tree is returned: its mappings keep them. */
static hpfc_tree *join_files(hpfc_tree **parts, size_t k, gen_rng *rng)
{
    char (*paths)[80] = calloc(k, sizeof *paths);
    const char **order = calloc(k, sizeof *order);
    hpfc_tree *joined = NULL;
    hpfc_diag diag;
    for (size_t q = 0; paths && order && q < k; q++) {
        part_file_path(paths[q], sizeof paths[q], q);
        CHECK_EQ_INT(hpfc_tree_write_part(parts[q], paths[q], &diag), HPFC_OK);
        hpfc_tree_free(parts[q]);
        parts[q] = NULL;
        order[q] = paths[q];
    }
    for (size_t q = k; paths && order && q > 1; q--) {
        size_t r = (size_t)gen_rng_below(rng, q);
        const char *t = order[q - 1];
        order[q - 1] = order[r], order[r] = t;
    }
    if (paths && order) {
        int st = hpfc_tree_merge_files(order, k, &joined, &diag);
        if (st)
            fprintf(stderr, "merge of %zu part files: %s: %s\n", k, hpfc_strerror(st), diag.message);
        CHECK_EQ_INT(st, HPFC_OK);
        for (size_t q = 0; q < k; q++)
            remove(paths[q]);
    }
    free(paths);
    free(order);
    return joined;
}

/* How build_in_parts joins its parts. */
enum join_way { JOIN_TREES, JOIN_READ_BACK, JOIN_FILES };

/* Builds k parts of g (from subgraphs when `sub`: the test's own when the
 * parts go through files, else hpfc_part_graph's), joins them in a random
 * order (`way`: their trees, their trees read back from part files, or
 * the part files themselves) and returns the joined tree (NULL on
 * failure, checked). */
static hpfc_tree *build_in_parts(const hpfc_graph *g, const hpfc_build_params *p, const hpfc_domain *d,
                                 const uint32_t *owner, size_t k, bool sub, enum join_way way,
                                 gen_rng *rng)
{
    bool files = way != JOIN_TREES;
    uint32_t roots = p->root_cols * p->root_rows;
    hpfc_tree **parts = calloc(k, sizeof *parts);
    uint32_t *pixels = malloc(roots * sizeof *pixels);
    hpfc_tree *joined = NULL;
    hpfc_diag diag;
    bool ok = parts && pixels;
    for (size_t q = 0; ok && q < k; q++) {
        size_t n = 0;
        for (uint32_t px = 0; px < roots; px++)
            if (owner[px] == q)
                pixels[n++] = px;
        hpfc_part part = {.domain = *d, .root_pixels = pixels, .root_pixel_count = n};
        subgraph s = {0};
        if (sub && files) { /* the test's own, its vertices reversed */
            CHECK_EQ_INT(make_subgraph(g, d, p, pixels, n, UINT32_MAX, &s), HPFC_OK);
        } else if (sub) {
            CHECK_EQ_INT(hpfc_part_graph(g, p, &part, &s.g, &s.edge_ids, &diag), HPFC_OK);
        }
        if (sub) {
            part.edge_ids = s.edge_ids;
            part.edge_count = hpfc_graph_edge_count(g);
        }
        /* a part of no edges still builds its (private) pixels */
        int st = hpfc_build_part(sub ? s.g : g, p, &part, &parts[q], &diag);
        if (st)
            fprintf(stderr, "part %zu of %zu: %s: %s\n", q, k, hpfc_strerror(st), diag.message);
        CHECK_EQ_INT(st, HPFC_OK);
        ok = st == HPFC_OK;
        if (ok && way == JOIN_READ_BACK)
            through_file(&parts[q]);
        hpfc_graph_free(s.g);
        free(s.edge_ids);
    }
    for (size_t q = k; ok && q > 1; q--) { /* the order of the parts must not matter */
        size_t r = (size_t)gen_rng_below(rng, q);
        hpfc_tree *t = parts[q - 1];
        parts[q - 1] = parts[r], parts[r] = t;
    }
    if (ok && way == JOIN_FILES) {
        joined = join_files(parts, k, rng);
    } else if (ok) {
        int st = hpfc_tree_merge(parts, k, &joined, &diag);
        if (st)
            fprintf(stderr, "merge of %zu parts: %s: %s\n", k, hpfc_strerror(st), diag.message);
        CHECK_EQ_INT(st, HPFC_OK);
    }
    for (size_t q = 0; parts && q < k; q++)
        hpfc_tree_free(parts[q]);
    free(parts);
    free(pixels);
    return joined;
}

/* Part q's graph from the cut against the oracle: the edges edge_near_part
 * keeps for q's pixels, in the map's order, with their vertices in the
 * map's order. */
static void check_cut_part(const hpfc_graph *g, const hpfc_domain *d, const hpfc_build_params *p,
                           const uint32_t *owner, uint32_t q, const hpfc_cut *cut)
{
    uint32_t roots = p->root_cols * p->root_rows, *pixels = malloc(roots * sizeof *pixels);
    size_t npx = 0, ne = hpfc_graph_edge_count(g), nv = hpfc_graph_vertex_count(g);
    for (uint32_t px = 0; pixels && px < roots; px++)
        if (owner[px] == q)
            pixels[npx++] = px;
    hpfc_graph *sub = NULL;
    uint32_t *ids = NULL;
    CHECK_EQ_INT(hpfc_cut_part_graph(cut, q, &sub, &ids, NULL), HPFC_OK);
    uint8_t *used = calloc(nv ? nv : 1, 1);
    size_t kept = 0, sub_ne = sub ? hpfc_graph_edge_count(sub) : 0;
    bool same = pixels && used && sub;
    for (size_t e = 0; same && e < ne; e++) {
        if (!edge_near_part(g, e, d, p, pixels, npx))
            continue;
        uint32_t u, v, su, sv;
        const int64_t *xy, *sxy;
        size_t n, sn;
        hpfc_graph_edge(g, e, &u, &v, &xy, &n);
        used[u] = used[v] = 1;
        same = kept < sub_ne && ids[kept] == e;
        if (same) {
            hpfc_graph_edge(sub, kept, &su, &sv, &sxy, &sn);
            same = sn == n && (n == 0 || memcmp(sxy, xy, 2 * n * sizeof *xy) == 0);
        }
        kept++;
    }
    same = same && kept == sub_ne;
    size_t sv = 0; /* the vertices: the used ones, in the map's order */
    for (size_t v = 0; same && v < nv; v++)
        if (used[v]) {
            int64_t x, y, sx, sy;
            hpfc_graph_vertex(g, v, &x, &y);
            same = sv < hpfc_graph_vertex_count(sub);
            if (same) {
                hpfc_graph_vertex(sub, sv, &sx, &sy);
                same = sx == x && sy == y;
            }
            sv++;
        }
    same = same && sv == hpfc_graph_vertex_count(sub);
    if (!same)
        fprintf(stderr, "the cut's part %u differs from the oracle's\n", q);
    CHECK(same);
    hpfc_graph_free(sub);
    hpfc_free(ids);
    free(used);
    free(pixels);
}

/* The cut of k parts (and with a tenth of the pixels owned by none)
 * against the oracle, part by part. */
static void check_cut(const hpfc_graph *g, const hpfc_domain *d, const hpfc_build_params *p, const uint32_t *owner,
                      size_t k, gen_rng *rng)
{
    uint32_t roots = p->root_cols * p->root_rows, *some = malloc(roots * sizeof *some);
    for (int holes = 0; some && holes < 2; holes++) {
        for (uint32_t px = 0; px < roots; px++)
            some[px] = holes && gen_rng_below(rng, 10) == 0 ? UINT32_MAX : owner[px];
        hpfc_cut *cut = NULL;
        CHECK_EQ_INT(hpfc_cut_create(g, p, d, some, (uint32_t)k, &cut, NULL), HPFC_OK);
        for (uint32_t q = 0; cut && q < k; q++)
            check_cut_part(g, d, p, some, q, cut);
        hpfc_cut_free(cut);
    }
    free(some);
}

static void check_graph(const hpfc_graph *g, const char *what, gen_rng *rng)
{
    static const size_t PART_COUNTS[] = {1, 2, 3, 5};
    for (size_t s = 0; s < sizeof SHAPES / sizeof *SHAPES; s++) {
        hpfc_build_params p = params_of(&SHAPES[s]);
        hpfc_tree *single = NULL;
        hpfc_diag diag;
        CHECK_EQ_INT(hpfc_build(g, &p, &single, &diag), HPFC_OK);
        int64_t box[4];
        CHECK_EQ_INT(hpfc_graph_bounds(g, box), HPFC_OK);
        hpfc_domain d;
        CHECK_EQ_INT(hpfc_build_domain(box, &p, &d, &diag), HPFC_OK);
        uint32_t roots = p.root_cols * p.root_rows;
        uint32_t *owner = malloc(roots * sizeof *owner);
        for (size_t c = 0; single && owner && c < sizeof PART_COUNTS / sizeof *PART_COUNTS; c++)
            for (int mode = 0; mode < 4; mode++) {
                /* 0: whole graph, trees; 1: own subgraphs, read back; 2:
                 * runs of pixels, cut subgraphs; 3: own subgraphs, files */
                size_t k = PART_COUNTS[c];
                deal_pixels(rng, roots, k, mode == 2, owner);
                if (mode == 0 || mode == 2)
                    check_cut(g, &d, &p, owner, k, rng);
                enum join_way way = mode == 1 ? JOIN_READ_BACK : mode == 3 ? JOIN_FILES : JOIN_TREES;
                hpfc_tree *joined = build_in_parts(g, &p, &d, owner, k, mode != 0, way, rng);
                bool same = joined && same_info(single, joined);
                if (!same)
                    fprintf(stderr, "%s, shape %zu, %zu parts, mode %d: the joined tree differs\n", what, s,
                            k, mode);
                CHECK(same);
                if (joined)
                    check_same_bytes(single, joined, g);
                hpfc_tree_free(joined);
            }
        free(owner);
        hpfc_tree_free(single);
    }
}

static void test_generated(void)
{
    gen_rng rng;
    gen_rng_seed(&rng, 32);
    for (uint64_t seed = 1; seed <= 3; seed++) {
        hpfc_graph *g = NULL;
        CHECK_EQ_INT(gen_delaunay(seed, 60 + 40 * seed, 1 << 12, 0.2, &g), HPFC_OK);
        if (g)
            check_graph(g, "delaunay", &rng);
        hpfc_graph_free(g);
        g = NULL;
        CHECK_EQ_INT(gen_polyline(seed, 150, 1 << 12, 0.5, &g), HPFC_OK);
        if (g)
            check_graph(g, "polyline", &rng);
        hpfc_graph_free(g);
    }
    for (int which = 0; which < GEN_SPECIAL_COUNT; which++) {
        hpfc_graph *g = NULL;
        CHECK_EQ_INT(gen_special(which, &g), HPFC_OK);
        if (g)
            check_graph(g, gen_special_name(which), &rng);
        hpfc_graph_free(g);
    }
    CHECK(comparisons >= 1000); /* the byte comparisons must not be skipped */
}

/* ---- refusals ----------------------------------------------------------- */

typedef struct fixture {
    hpfc_graph *g;
    hpfc_build_params p;
    hpfc_domain d;
    uint32_t all[16], half[2][8]; /* 4 x 4 root pixels: all, west and east halves */
} fixture;

static bool fixture_init(fixture *f)
{
    CHECK_EQ_INT(gen_delaunay(7, 120, 1 << 12, 0.2, &f->g), HPFC_OK);
    shape sh = {4, 4, 2, 2, 16};
    f->p = params_of(&sh);
    int64_t box[4];
    CHECK_EQ_INT(hpfc_graph_bounds(f->g, box), HPFC_OK);
    CHECK_EQ_INT(hpfc_build_domain(box, &f->p, &f->d, NULL), HPFC_OK);
    size_t n[2] = {0, 0};
    for (uint32_t px = 0; px < 16; px++) {
        f->all[px] = px;
        int east = px % 4 >= 2;
        f->half[east][n[east]++] = px;
    }
    return f->g != NULL;
}

static int part_status(const fixture *f, const hpfc_graph *g, const hpfc_build_params *p, const hpfc_part *part,
                       hpfc_tree **out)
{
    hpfc_diag d;
    hpfc_tree *t = NULL;
    int st = hpfc_build_part(g, p, part, &t, &d);
    (void)f;
    if (out)
        *out = t;
    else
        hpfc_tree_free(t);
    return st;
}

/* The whole-graph calls a split build needs: the box, and the checks no
 * part can make. */
static void test_whole_graph_calls(void)
{
    hpfc_graph *g = NULL;
    int64_t box[4];
    CHECK_EQ_INT(hpfc_graph_create(&g), HPFC_OK);
    CHECK_EQ_INT(hpfc_graph_bounds(g, box), HPFC_E_EMPTY);
    CHECK_EQ_INT(hpfc_graph_bounds(NULL, box), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_graph_check_whole(g, NULL), HPFC_E_EMPTY);
    hpfc_graph_add_vertex(g, 0, 0, NULL);
    hpfc_graph_add_vertex(g, 10, 5, NULL);
    hpfc_graph_add_vertex(g, 4, 4, NULL);
    hpfc_graph_add_vertex(g, 4, -2, NULL);
    const int64_t bend[2] = {-3, 7};
    hpfc_graph_add_edge(g, 0, 1, bend, 1, NULL);
    CHECK_EQ_INT(hpfc_graph_bounds(g, box), HPFC_OK);
    CHECK(box[0] == -3 && box[1] == -2 && box[2] == 10 && box[3] == 7);
    hpfc_diag d;
    CHECK_EQ_INT(hpfc_graph_check_whole(g, &d), HPFC_E_ISOLATED_VERTEX); /* vertices 2 and 3 */
    CHECK_EQ_INT(hpfc_graph_validate(g, NULL), HPFC_E_ISOLATED_VERTEX);
    /* a crossing is a part's to find, not the whole graph's check */
    hpfc_graph_add_edge(g, 2, 3, NULL, 0, NULL);
    hpfc_graph_add_vertex(g, 0, 2, NULL);
    hpfc_graph_add_vertex(g, 8, 2, NULL);
    hpfc_graph_add_edge(g, 4, 5, NULL, 0, NULL); /* crosses 2-3 at (4, 2) */
    CHECK_EQ_INT(hpfc_graph_check_whole(g, NULL), HPFC_OK);
    CHECK_EQ_INT(hpfc_graph_validate(g, NULL), HPFC_E_NONPLANAR);
    hpfc_graph_free(g);
}

static void test_part_refusals(const fixture *f)
{
    hpfc_part part = {.domain = f->d, .root_pixels = f->all, .root_pixel_count = 16};
    hpfc_build_params flat = f->p;
    flat.flat = 1;
    CHECK_EQ_INT(part_status(f, f->g, &flat, &part, NULL), HPFC_E_ARG);
    hpfc_part wrong = part;
    wrong.domain.width *= 2; /* not root_cols * cols^max_depth */
    CHECK_EQ_INT(part_status(f, f->g, &f->p, &wrong, NULL), HPFC_E_ARG);
    wrong = part;
    wrong.domain.x0 += wrong.domain.width / 2; /* the map's west half outside */
    CHECK_EQ_INT(part_status(f, f->g, &f->p, &wrong, NULL), HPFC_E_ARG);
    uint32_t unordered[2] = {5, 3}, beyond[1] = {16};
    wrong = part;
    wrong.root_pixels = unordered, wrong.root_pixel_count = 2;
    CHECK_EQ_INT(part_status(f, f->g, &f->p, &wrong, NULL), HPFC_E_ARG);
    wrong.root_pixels = beyond, wrong.root_pixel_count = 1;
    CHECK_EQ_INT(part_status(f, f->g, &f->p, &wrong, NULL), HPFC_E_ARG);
    size_t ne = hpfc_graph_edge_count(f->g);
    uint32_t *ids = malloc(ne * sizeof *ids);
    for (size_t e = 0; e < ne; e++)
        ids[e] = (uint32_t)e;
    wrong = part;
    wrong.edge_ids = ids, wrong.edge_count = ne - 1; /* the last id not below the count */
    CHECK_EQ_INT(part_status(f, f->g, &f->p, &wrong, NULL), HPFC_E_ARG);
    ids[1] = ids[0]; /* not ascending */
    wrong.edge_count = ne;
    CHECK_EQ_INT(part_status(f, f->g, &f->p, &wrong, NULL), HPFC_E_ARG);
    free(ids);
    wrong = part;
    wrong.edge_count = ne + 1; /* without ids, the graph's count or 0 */
    CHECK_EQ_INT(part_status(f, f->g, &f->p, &wrong, NULL), HPFC_E_ARG);
    hpfc_graph *pg = NULL;
    uint32_t *pids = NULL;
    wrong = part;
    wrong.root_pixels = beyond, wrong.root_pixel_count = 1;
    CHECK_EQ_INT(hpfc_part_graph(f->g, &f->p, &wrong, &pg, &pids, NULL), HPFC_E_ARG);
    CHECK(pg == NULL && pids == NULL);
    CHECK_EQ_INT(hpfc_part_graph(f->g, &f->p, &part, &pg, NULL, NULL), HPFC_E_ARG);
    /* all root pixels: the whole graph */
    CHECK_EQ_INT(hpfc_part_graph(f->g, &f->p, &part, &pg, &pids, NULL), HPFC_OK);
    CHECK(pg && hpfc_graph_edge_count(pg) == ne && hpfc_graph_vertex_count(pg) == hpfc_graph_vertex_count(f->g));
    CHECK(pids && pids[ne - 1] == ne - 1);
    hpfc_graph_free(pg);
    hpfc_free(pids);
    CHECK_EQ_INT(part_status(f, NULL, &f->p, &part, NULL), HPFC_E_ARG);
    CHECK_EQ_INT(part_status(f, f->g, &f->p, NULL, NULL), HPFC_E_ARG);
    /* the cut: owners beyond the parts, NULLs, a part beyond */
    uint32_t owner[16] = {0};
    hpfc_cut *cut = (hpfc_cut *)&owner; /* must be set to NULL on failure */
    owner[5] = 2;
    CHECK_EQ_INT(hpfc_cut_create(f->g, &f->p, &f->d, owner, 2, &cut, NULL), HPFC_E_ARG);
    CHECK(cut == NULL);
    CHECK_EQ_INT(hpfc_cut_create(NULL, &f->p, &f->d, owner, 3, &cut, NULL), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_cut_create(f->g, &f->p, NULL, owner, 3, &cut, NULL), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_cut_create(f->g, &f->p, &f->d, NULL, 3, &cut, NULL), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_cut_create(f->g, &f->p, &f->d, owner, 3, NULL, NULL), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_cut_create(f->g, &f->p, &f->d, owner, 3, &cut, NULL), HPFC_OK);
    CHECK_EQ_INT(hpfc_cut_part_graph(cut, 3, &pg, &pids, NULL), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_cut_part_graph(cut, 1, &pg, &pids, NULL), HPFC_OK); /* a part of no pixel: no edge */
    CHECK(pg && hpfc_graph_edge_count(pg) == 0 && hpfc_graph_vertex_count(pg) == 0);
    hpfc_graph_free(pg);
    hpfc_free(pids);
    CHECK_EQ_INT(hpfc_cut_part_graph(NULL, 0, &pg, &pids, NULL), HPFC_E_ARG);
    hpfc_cut_free(cut);
    hpfc_cut_free(NULL);
    /* a part's tree is not a file */
    hpfc_tree *t = NULL;
    CHECK_EQ_INT(part_status(f, f->g, &f->p, &part, &t), HPFC_OK);
    uint8_t *bytes = NULL;
    size_t size = 0;
    CHECK_EQ_INT(hpfc_tree_serialize(t, NULL, &bytes, &size, NULL), HPFC_E_ARG);
    CHECK(bytes == NULL);
    hpfc_tree_free(t);
    /* another part's root pixel has no pixel here */
    hpfc_part west = {.domain = f->d, .root_pixels = f->half[0], .root_pixel_count = 8};
    CHECK_EQ_INT(part_status(f, f->g, &f->p, &west, &t), HPFC_OK);
    hpfc_tree_pixel px;
    CHECK_EQ_INT(hpfc_tree_get_pixel(t, 0, 0, 3, 0, &px), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_tree_get_pixel(t, 0, 0, 0, 0, &px), HPFC_OK);
    hpfc_tree_free(t);
}

static void test_merge_refusals(const fixture *f)
{
    hpfc_part west = {.domain = f->d, .root_pixels = f->half[0], .root_pixel_count = 8};
    hpfc_part east = {.domain = f->d, .root_pixels = f->half[1], .root_pixel_count = 8};
    hpfc_tree *w = NULL, *e = NULL, *single = NULL, *joined = NULL;
    CHECK_EQ_INT(part_status(f, f->g, &f->p, &west, &w), HPFC_OK);
    CHECK_EQ_INT(part_status(f, f->g, &f->p, &east, &e), HPFC_OK);
    CHECK_EQ_INT(hpfc_build(f->g, &f->p, &single, NULL), HPFC_OK);
    hpfc_diag d;
    hpfc_tree *both[2] = {w, e}, *twice[3] = {w, e, w}, *alone[1] = {w}, *whole[2] = {w, single};
    CHECK_EQ_INT(hpfc_tree_merge(both, 2, &joined, &d), HPFC_OK);
    CHECK(joined && same_info(joined, single));
    hpfc_tree_free(joined);
    CHECK_EQ_INT(hpfc_tree_merge(both, 0, &joined, &d), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_tree_merge(alone, 1, &joined, &d), HPFC_E_ARG); /* the east half in no part */
    CHECK(joined == NULL);
    CHECK_EQ_INT(hpfc_tree_merge(twice, 3, &joined, &d), HPFC_E_ARG); /* the west half twice */
    CHECK_EQ_INT(hpfc_tree_merge(whole, 2, &joined, &d), HPFC_E_ARG); /* not a part */
    CHECK_EQ_INT(hpfc_tree_merge(both, 2, NULL, &d), HPFC_E_ARG);
    /* a part of another build: the same pixels under other image sizes */
    shape other = {4, 4, 3, 3, 16};
    hpfc_build_params q = params_of(&other);
    hpfc_domain d3;
    int64_t box[4];
    CHECK_EQ_INT(hpfc_graph_bounds(f->g, box), HPFC_OK);
    CHECK_EQ_INT(hpfc_build_domain(box, &q, &d3, NULL), HPFC_OK);
    hpfc_part east3 = {.domain = d3, .root_pixels = f->half[1], .root_pixel_count = 8};
    hpfc_tree *e3 = NULL;
    CHECK_EQ_INT(part_status(f, f->g, &q, &east3, &e3), HPFC_OK);
    hpfc_tree *mixed[2] = {w, e3};
    CHECK_EQ_INT(hpfc_tree_merge(mixed, 2, &joined, &d), HPFC_E_ARG);
    hpfc_tree_free(e3);
    /* a map of more edges than its parts' crossings: refused before the
     * union-find over its edges is sized */
    size_t ne = hpfc_graph_edge_count(f->g);
    uint32_t *ids = malloc(ne * sizeof *ids);
    for (size_t k = 0; k < ne; k++)
        ids[k] = (uint32_t)k;
    hpfc_part huge = {.domain = f->d, .root_pixels = f->all, .root_pixel_count = 16, .edge_ids = ids,
                      .edge_count = (uint64_t)UINT32_MAX + 1};
    hpfc_tree *h = NULL;
    CHECK_EQ_INT(part_status(f, f->g, &f->p, &huge, &h), HPFC_OK);
    CHECK_EQ_INT(hpfc_tree_merge(&h, 1, &joined, &d), HPFC_E_ARG);
    CHECK(strstr(d.message, "crossings") != NULL);
    hpfc_tree_free(h);
    free(ids);
    /* an edge left out of every part's graph is in no part's words */
    subgraph sw, se;
    CHECK_EQ_INT(make_subgraph(f->g, &f->d, &f->p, f->half[0], 8, 0, &sw), HPFC_OK);
    CHECK_EQ_INT(make_subgraph(f->g, &f->d, &f->p, f->half[1], 8, 0, &se), HPFC_OK);
    hpfc_tree *pw = NULL, *pe = NULL;
    west.edge_ids = sw.edge_ids, east.edge_ids = se.edge_ids;
    west.edge_count = east.edge_count = hpfc_graph_edge_count(f->g);
    CHECK_EQ_INT(part_status(f, sw.g, &f->p, &west, &pw), HPFC_OK);
    CHECK_EQ_INT(part_status(f, se.g, &f->p, &east, &pe), HPFC_OK);
    hpfc_tree *gap[2] = {pw, pe};
    CHECK_EQ_INT(hpfc_tree_merge(gap, 2, &joined, &d), HPFC_E_ARG);
    CHECK(strstr(d.message, "edge 0") != NULL);
    /* and from their files, the components counted or not (a bit an edge
     * then says which were met) */
    char gap_path[2][80];
    for (int q = 0; q < 2; q++) {
        part_file_path(gap_path[q], sizeof gap_path[q], (size_t)(5 + q));
        CHECK_EQ_INT(hpfc_tree_write_part(gap[q], gap_path[q], &d), HPFC_OK);
    }
    const char *gap_files[2] = {gap_path[0], gap_path[1]};
    for (int counted = 0; counted < 2; counted++) {
        int st = counted ? hpfc_tree_merge_files(gap_files, 2, &joined, &d)
                         : hpfc_tree_merge_files_uncounted(gap_files, 2, &joined, &d);
        CHECK_EQ_INT(st, HPFC_E_ARG);
        CHECK(joined == NULL && strstr(d.message, "edge 0") != NULL);
    }
    remove(gap_path[0]);
    remove(gap_path[1]);
    hpfc_tree_free(pw);
    hpfc_tree_free(pe);
    hpfc_graph_free(sw.g);
    hpfc_graph_free(se.g);
    free(sw.edge_ids);
    free(se.edge_ids);
    hpfc_tree_free(w);
    hpfc_tree_free(e);
    hpfc_tree_free(single);
}

/* ---- damaged part files ------------------------------------------------- */

static uint8_t *read_all(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    uint8_t *data = NULL;
    *size = 0;
    if (f && !fseek(f, 0, SEEK_END)) {
        long n = ftell(f);
        rewind(f);
        data = n > 0 ? malloc((size_t)n) : NULL;
        if (data && fread(data, 1, (size_t)n, f) == (size_t)n)
            *size = (size_t)n;
    }
    if (f)
        fclose(f);
    return data;
}

static void set_crc(uint8_t *data, size_t size)
{
    uint32_t crc = crc32c_update(0, data, size - 4);
    for (int k = 0; k < 4; k++)
        data[size - 4 + k] = (uint8_t)(crc >> (8 * k));
}

/* A damaged part file read, and when it reads, joined and written: an
 * error code, never a crash (the sanitizers watch). Returns 1 when the
 * reader refused it. */
static int try_damaged(const uint8_t *data, size_t size, hpfc_tree *other)
{
    hpfc_tree *t = NULL, *joined = NULL;
    hpfc_diag d;
    int st = hpfc_tree_read_part_memory(data, size, &t, &d);
    if (st) {
        CHECK(t == NULL && d.message[0] != '\0');
        return 1;
    }
    hpfc_tree *both[2] = {t, other};
    if (hpfc_tree_merge(both, 2, &joined, &d) == HPFC_OK) {
        uint8_t *bytes = NULL;
        size_t n = 0;
        hpfc_write_options o = {.face_labels = 1};
        if (hpfc_tree_serialize(joined, &o, &bytes, &n, &d) == HPFC_OK)
            hpfc_free(bytes);
    }
    hpfc_tree_free(joined);
    hpfc_tree_free(t);
    return 0;
}

static void test_damaged_part_files(const fixture *f)
{
    hpfc_part west = {.domain = f->d, .root_pixels = f->half[0], .root_pixel_count = 8};
    hpfc_part east = {.domain = f->d, .root_pixels = f->half[1], .root_pixel_count = 8};
    hpfc_tree *w = NULL, *e = NULL;
    CHECK_EQ_INT(part_status(f, f->g, &f->p, &west, &w), HPFC_OK);
    CHECK_EQ_INT(part_status(f, f->g, &f->p, &east, &e), HPFC_OK);
    hpfc_diag d;
    CHECK_EQ_INT(hpfc_tree_write_part(w, part_path, &d), HPFC_OK);
    size_t size = 0;
    uint8_t *good = read_all(part_path, &size), *bad = malloc(size ? size : 1);
    CHECK(good && size > 200);
    if (!good || !bad || !e) {
        free(good), free(bad), hpfc_tree_free(w), hpfc_tree_free(e);
        return;
    }
    CHECK_EQ_INT(try_damaged(good, size, e), 0);
    /* every shorter file, and one longer, is refused */
    int refused = 0;
    for (size_t n = 0; n < size; n++)
        refused += try_damaged(good, n, e);
    CHECK_EQ_INT(refused, (long long)size);
    /* a byte flipped anywhere: caught by the CRC; with the CRC set anew,
     * by the structure where it can tell */
    refused = 0;
    int structural = 0;
    for (size_t k = 0; k < size; k++) {
        memcpy(bad, good, size);
        bad[k] ^= (uint8_t)(1u << (k % 8));
        refused += try_damaged(bad, size, e);
        if (k < size - 4) {
            set_crc(bad, size);
            structural += try_damaged(bad, size, e);
        }
    }
    CHECK_EQ_INT(refused, (long long)size);
    fprintf(stderr, "damaged part files: %d of %zu flips refused with a valid CRC\n", structural, size - 4);
    CHECK(structural > (int)(size / 2)); /* the pixels' fields are all checked */
    /* a tree that is not a part has no part file */
    hpfc_tree *single = NULL;
    CHECK_EQ_INT(hpfc_build(f->g, &f->p, &single, NULL), HPFC_OK);
    CHECK_EQ_INT(hpfc_tree_write_part(single, part_path, &d), HPFC_E_ARG);
    hpfc_tree_free(single);
    CHECK_EQ_INT(hpfc_tree_read_part("/nonexistent/part", &single, &d), HPFC_E_IO);
    CHECK(single == NULL);
    free(good);
    free(bad);
    hpfc_tree_free(w);
    hpfc_tree_free(e);
}

/* The status of joining the files at paths[0 .. n), and whether its
 * message names `named` (NULL: not asked). */
static int merge_files_status(const char *const *paths, size_t n, const char *named, bool *names)
{
    hpfc_tree *joined = NULL;
    hpfc_diag d;
    int st = hpfc_tree_merge_files(paths, n, &joined, &d);
    CHECK((st == HPFC_OK) == (joined != NULL));
    if (names)
        *names = named && strstr(d.message, named) != NULL;
    hpfc_tree_free(joined);
    return st;
}

/* A join without the components' count (hpfc_tree_merge_files_uncounted)
 * against the counted `joined`: the same counts but F and C, those 0, and
 * the same bytes, also with LABL's faces numbered a root pixel at a time
 * as the Dask client writes them, whose face count is joined's F. */
static void check_uncounted(const hpfc_tree *joined, const hpfc_tree *view, const hpfc_graph *g)
{
    hpfc_tree_info a, b;
    hpfc_tree_get_info(joined, &a);
    hpfc_tree_get_info(view, &b);
    CHECK(a.faces > 1 && a.components > 0);
    CHECK(b.faces == 0 && b.components == 0);
    CHECK(a.vertices == b.vertices && a.edges == b.edges && a.levels == b.levels &&
          a.word_pixels == b.word_pixels && a.refined_pixels == b.refined_pixels &&
          a.max_word_symbols == b.max_word_symbols);
    check_same_bytes(joined, view, g);
    hpfc_write_options o = {.layout = HPFC_LAYOUT_COMPACT, .face_labels = 1, .geometry = g,
                            .faces_by_root = 1, .threads = 2};
    uint8_t *x = NULL, *y = NULL;
    size_t nx = 0, ny = 0;
    hpfc_diag d;
    CHECK_EQ_INT(hpfc_tree_serialize(joined, &o, &x, &nx, &d), HPFC_OK);
    CHECK_EQ_INT(hpfc_tree_serialize(view, &o, &y, &ny, &d), HPFC_OK);
    CHECK(nx == ny && x && y && memcmp(x, y, nx) == 0);
    hpfc_file *file = NULL;
    hpfc_labels_info li;
    CHECK_EQ_INT(y ? hpfc_open_memory(y, ny, 0, &file) : HPFC_E_ARG, HPFC_OK);
    CHECK_EQ_INT(file ? hpfc_file_get_labels(file, &li) : HPFC_E_ARG, HPFC_OK);
    CHECK(file && li.faces == a.faces);
    hpfc_close(file);
    comparisons++;
    hpfc_free(x);
    hpfc_free(y);
}

/* hpfc_tree_merge_files: the halves' files joined give hpfc_tree_merge's
 * bytes, counted or not (check_uncounted); a part twice, a part missing, a
 * damaged or absent file and no file are refused, a file's refusal naming
 * it. */
static void test_merge_files(const fixture *f)
{
    hpfc_part west = {.domain = f->d, .root_pixels = f->half[0], .root_pixel_count = 8};
    hpfc_part east = {.domain = f->d, .root_pixels = f->half[1], .root_pixel_count = 8};
    hpfc_tree *halves[2] = {NULL, NULL}, *joined = NULL, *view = NULL;
    CHECK_EQ_INT(part_status(f, f->g, &f->p, &west, &halves[0]), HPFC_OK);
    CHECK_EQ_INT(part_status(f, f->g, &f->p, &east, &halves[1]), HPFC_OK);
    char wpath[80], epath[80], bad_path[80];
    part_file_path(wpath, sizeof wpath, 0);
    part_file_path(epath, sizeof epath, 1);
    part_file_path(bad_path, sizeof bad_path, 2);
    hpfc_diag d;
    CHECK_EQ_INT(hpfc_tree_write_part(halves[0], wpath, &d), HPFC_OK);
    CHECK_EQ_INT(hpfc_tree_write_part(halves[1], epath, &d), HPFC_OK);
    CHECK_EQ_INT(hpfc_tree_merge(halves, 2, &joined, &d), HPFC_OK);
    const char *both[2] = {epath, wpath};
    CHECK_EQ_INT(hpfc_tree_merge_files(both, 2, &view, &d), HPFC_OK);
    if (joined && view)
        check_same_bytes(joined, view, f->g);
    hpfc_tree_free(view);
    view = NULL;
    CHECK_EQ_INT(hpfc_tree_merge_files_uncounted(both, 2, &view, &d), HPFC_OK);
    if (joined && view)
        check_uncounted(joined, view, f->g);
    hpfc_tree_free(view);
    /* refusals */
    bool names = false;
    const char *alone[1] = {wpath}, *twice[3] = {wpath, epath, wpath};
    CHECK_EQ_INT(merge_files_status(alone, 1, NULL, NULL), HPFC_E_ARG);
    CHECK_EQ_INT(merge_files_status(twice, 3, NULL, NULL), HPFC_E_ARG);
    CHECK_EQ_INT(merge_files_status(both, 0, NULL, NULL), HPFC_E_ARG);
    CHECK_EQ_INT(merge_files_status(NULL, 2, NULL, NULL), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_tree_merge_files(both, 2, NULL, &d), HPFC_E_ARG);
    const char *absent[2] = {wpath, "/nonexistent/east.part"};
    CHECK_EQ_INT(merge_files_status(absent, 2, "/nonexistent/east.part", &names), HPFC_E_IO);
    CHECK(names);
    size_t size = 0;
    uint8_t *bytes = read_all(epath, &size);
    const char *damaged[2] = {wpath, bad_path};
    for (int how = 0; bytes && size > 200 && how < 3; how++) {
        FILE *out = fopen(bad_path, "wb");
        CHECK(out != NULL);
        if (!out)
            break;
        uint8_t saved = bytes[size / 2];
        if (how == 1)
            bytes[size / 2] ^= 0x10; /* a pixel's byte, the CRC left: refused by the CRC */
        size_t n = how == 2 ? 10 : size; /* a stub that is no part file */
        CHECK(fwrite(bytes, 1, n, out) == n);
        fclose(out);
        bytes[size / 2] = saved;
        int want = how == 0 ? HPFC_OK : how == 1 ? HPFC_E_CHECKSUM : HPFC_E_MAGIC;
        CHECK_EQ_INT(merge_files_status(damaged, 2, bad_path, &names), want);
        CHECK(how == 0 || names);
    }
    free(bytes);
    remove(wpath);
    remove(epath);
    remove(bad_path);
    hpfc_tree_free(joined);
    hpfc_tree_free(halves[0]);
    hpfc_tree_free(halves[1]);
}

int main(void)
{
    snprintf(part_path, sizeof part_path, "/tmp/test_part_%ld.part", (long)getpid());
    test_generated();
    test_whole_graph_calls();
    fixture f = {0};
    if (fixture_init(&f)) {
        test_part_refusals(&f);
        test_merge_refusals(&f);
        test_damaged_part_files(&f);
        test_merge_files(&f);
    }
    remove(part_path);
    hpfc_graph_free(f.g);
    return check_report("test_part");
}
