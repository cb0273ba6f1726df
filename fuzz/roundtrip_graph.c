/*
 * roundtrip_graph: a small graph packed, written, reopened and read back,
 * compared with what went in.
 *
 * The input describes the graph and the packing:
 *   byte 0      mode: a generator of tests/support/gen.h (a special graph but the
 *               comb, Delaunay, polyline, jittered grid, from a seed and
 *               sizes in the next bytes) or a graph decoded from the bytes:
 *               up to 16 points
 *               (a coordinate byte times an input-chosen power of two) and
 *               up to 24 candidate edges with up to 3 interior points, each
 *               kept only if hpfc_graph_validate still accepts the graph;
 *   then        the build parameters: root 1..6 x 1..6, refinement 2..8 x
 *               2..8, sometimes a flat grid; the unit exponent; a CRS or not;
 *               the pool layout; LABL or not.
 *
 * Oracle (any failure aborts): a graph the validator accepts builds (or hits
 * a documented limit: LIMIT, TOO_MANY_PIXELS, or EXTENT when the domain
 * the image sizes need exceeds HPFC_LATTICE_MAX); the tree reports the graph's
 * V, E, C and F = E - V + 1 + C; the serialized file opens with its
 * checksums verified and keeps the unit and the CRS; every pixel of the file
 * has the tree's type, bounds and word (a joint walk of both); the map the
 * library's operators export (hpfc-inspect's export_map) has V vertices and
 * 2E darts, twin is an involution without fixed point, next a permutation
 * with origin(next(d)) = origin(twin(d)), prev inverts next; each input
 * vertex is located in a leaf, and every leaf holds as many vertices, of the
 * same degrees, as the input puts there; the face builder finds F faces and
 * gives every dart of a boundary loop the same face; with LABL, the faces
 * the write hands out (faces_out) bind to the file read back and give
 * every dart and private leaf the face builder's face.
 */
#include "export.h"
#include "gen.h"
#include "input.h"

#define MAX_POINTS 16
#define MAX_CANDIDATES 24
#define MAX_INTERIOR 3

typedef struct cand_edge {
    uint32_t u, v;
    size_t n;
    int64_t xy[2 * MAX_INTERIOR];
} cand_edge;

/* The graph of the points used by edges[0..ne), vertices in point order. */
static hpfc_graph *make_graph(const int64_t *pts, size_t np, const cand_edge *edges, size_t ne)
{
    uint32_t index[MAX_POINTS];
    bool used[MAX_POINTS] = {false};
    for (size_t e = 0; e < ne; e++)
        used[edges[e].u] = used[edges[e].v] = true;
    hpfc_graph *g;
    if (hpfc_graph_create(&g))
        return NULL;
    for (size_t p = 0; p < np; p++)
        if (used[p] && hpfc_graph_add_vertex(g, pts[2 * p], pts[2 * p + 1], &index[p]))
            goto fail;
    for (size_t e = 0; e < ne; e++)
        if (hpfc_graph_add_edge(g, index[edges[e].u], index[edges[e].v], edges[e].xy, edges[e].n, NULL))
            goto fail;
    return g;
fail:
    hpfc_graph_free(g);
    return NULL;
}

static int64_t coord(fuzz_bytes *in, unsigned shift)
{
    return (int64_t)(int8_t)fuzz_u8(in) * ((int64_t)1 << shift);
}

static hpfc_graph *graph_from_bytes(fuzz_bytes *in)
{
    int64_t pts[2 * MAX_POINTS];
    size_t np = 0, want = 2 + fuzz_u8(in) % (MAX_POINTS - 1);
    unsigned shift = fuzz_u8(in) % 24;
    for (size_t k = 0; k < want; k++) {
        int64_t x = coord(in, shift), y = coord(in, shift);
        bool dup = false;
        for (size_t p = 0; p < np && !dup; p++)
            dup = pts[2 * p] == x && pts[2 * p + 1] == y;
        if (!dup)
            pts[2 * np] = x, pts[2 * np + 1] = y, np++;
    }
    cand_edge edges[MAX_CANDIDATES];
    size_t ne = 0, tries = 1 + fuzz_u8(in) % MAX_CANDIDATES;
    for (size_t k = 0; k < tries && !fuzz_empty(in); k++) {
        cand_edge *c = &edges[ne];
        c->u = fuzz_u8(in) % np;
        c->v = fuzz_u8(in) % np;
        c->n = fuzz_u8(in) % (MAX_INTERIOR + 1);
        if (c->u == c->v && c->n < 2)
            c->n = 2;
        for (size_t p = 0; p < 2 * c->n; p++)
            c->xy[p] = coord(in, shift);
        hpfc_graph *g = make_graph(pts, np, edges, ne + 1);
        if (g && hpfc_graph_validate(g, NULL) == HPFC_OK)
            ne++;
        hpfc_graph_free(g);
    }
    return ne ? make_graph(pts, np, edges, ne) : NULL;
}

static hpfc_graph *graph_from_generator(fuzz_bytes *in, uint8_t mode)
{
    hpfc_graph *g = NULL;
    uint64_t seed = fuzz_u64(in);
    int st;
    switch (mode % 4) {
    case 0:
        /* all but the comb (200 vertices, 100 ms an input; test_topo has it) */
        st = gen_special(fuzz_u8(in) % GEN_SPECIAL_COMB, &g);
        break;
    case 1: {
        size_t n = 2 + fuzz_u8(in) % 40;
        int64_t coord_max = (int64_t)1 << (3 + fuzz_u8(in) % 16);
        st = gen_delaunay(seed, n, coord_max, (fuzz_u8(in) % 101) / 100.0, &g);
        break;
    }
    case 2: {
        size_t n = 3 + fuzz_u8(in) % 50;
        int64_t coord_max = (int64_t)1 << (4 + fuzz_u8(in) % 15);
        st = gen_polyline(seed, n, coord_max, 0.3 + (fuzz_u8(in) % 61) / 100.0, &g);
        break;
    }
    default: {
        size_t cols = 1 + fuzz_u8(in) % 4, rows = 1 + fuzz_u8(in) % 4;
        st = gen_grid_mesh(seed, cols, rows, 1 + fuzz_u8(in) % 24, &g);
        break;
    }
    }
    if (st) {
        hpfc_graph_free(g);
        return NULL;
    }
    return g;
}

/* ---- the input's own counts ------------------------------------------------ */

typedef struct graph_facts {
    size_t nv, ne, components;
    uint32_t *degree;
} graph_facts;

static uint32_t root_of(uint32_t *parent, uint32_t x)
{
    while (parent[x] != x)
        x = parent[x] = parent[parent[x]];
    return x;
}

static void facts_of(const hpfc_graph *g, graph_facts *gf)
{
    gf->nv = hpfc_graph_vertex_count(g);
    gf->ne = hpfc_graph_edge_count(g);
    gf->degree = calloc(gf->nv + 1, sizeof *gf->degree);
    uint32_t *parent = malloc((gf->nv + 1) * sizeof *parent);
    FUZZ_CHECK(gf->degree && parent);
    for (size_t v = 0; v < gf->nv; v++)
        parent[v] = (uint32_t)v;
    gf->components = gf->nv;
    for (size_t e = 0; e < gf->ne; e++) {
        uint32_t u, v;
        const int64_t *pts;
        size_t n;
        hpfc_graph_edge(g, e, &u, &v, &pts, &n);
        gf->degree[u]++, gf->degree[v]++;
        u = root_of(parent, u), v = root_of(parent, v);
        if (u != v)
            parent[u] = v, gf->components--;
    }
    free(parent);
}

/* ---- tree against file: every pixel ------------------------------------------ */

typedef struct walk_ctx {
    const hpfc_tree *t;
    const hpfc_file *f;
    hpfc_tree_info info;
    char *word;
    size_t cap;
} walk_ctx;

static void compare_pixel(walk_ctx *c, uint32_t level, size_t image, uint32_t i, uint32_t j,
                          const hpfc_pixel *px)
{
    hpfc_tree_pixel tp;
    int type;
    int64_t x0, y0, x1, y1;
    FUZZ_CHECK(hpfc_tree_get_pixel(c->t, level, image, i, j, &tp) == HPFC_OK);
    FUZZ_CHECK(hpfc_pixel_type(c->f, px, &type) == HPFC_OK && type == tp.type);
    FUZZ_CHECK(hpfc_pixel_bounds(c->f, px, &x0, &y0, &x1, &y1) == HPFC_OK);
    FUZZ_CHECK(x0 == tp.x0 && y0 == tp.y0 && x1 == tp.x1 && y1 == tp.y1);
    if (type == HPFC_PIXEL_WORD) {
        size_t len;
        FUZZ_CHECK(hpfc_pixel_word(c->f, px, c->word, c->cap, &len) == HPFC_OK);
        FUZZ_CHECK(len == tp.word_len && memcmp(c->word, tp.word, len) == 0);
        return;
    }
    FUZZ_CHECK(level + 1 < c->info.levels && tp.child < hpfc_tree_image_count(c->t, level + 1));
    for (uint32_t cj = 0; cj < c->info.rows; cj++)
        for (uint32_t ci = 0; ci < c->info.cols; ci++) {
            hpfc_pixel child;
            FUZZ_CHECK(hpfc_pixel_child(c->f, px, ci, cj, &child) == HPFC_OK);
            compare_pixel(c, level + 1, tp.child, ci, cj, &child);
        }
}

static void compare_tree(const hpfc_tree *t, const hpfc_file *f)
{
    walk_ctx c = {.t = t, .f = f};
    hpfc_tree_get_info(t, &c.info);
    c.cap = (size_t)c.info.max_word_symbols + 1;
    c.word = malloc(c.cap);
    FUZZ_CHECK(c.word != NULL);
    FUZZ_CHECK(hpfc_tree_image_count(t, 0) == 1);
    for (uint32_t j = 0; j < c.info.root_rows; j++)
        for (uint32_t i = 0; i < c.info.root_cols; i++) {
            hpfc_pixel px;
            FUZZ_CHECK(hpfc_pixel_root(f, i, j, &px) == HPFC_OK);
            compare_pixel(&c, 0, 0, i, j, &px);
        }
    free(c.word);
}

/* ---- the exported map and the operators ------------------------------------ */

typedef struct placed {
    uint64_t slot;   /* leaf identity: vertex key without its local id */
    uint32_t degree;
} placed;

static int cmp_placed(const void *a, const void *b)
{
    const placed *x = a, *y = b;
    if (x->slot != y->slot)
        return x->slot < y->slot ? -1 : 1;
    return (x->degree > y->degree) - (x->degree < y->degree);
}

/* handed: the faces the write handed out (faces_out), bound to f, or NULL;
 * each of their answers must be hpfc_faces_build's. */
static void check_map(const hpfc_file *f, const hpfc_graph *g, const graph_facts *gf,
                      uint64_t faces_expected, const hpfc_faces *handed)
{
    exported_map m;
    FUZZ_CHECK(export_map(f, &m) == HPFC_OK);
    FUZZ_CHECK(m.nv == gf->nv && m.nd == 2 * gf->ne);
    uint8_t *hit = calloc(m.nd + 1, 1);
    FUZZ_CHECK(hit != NULL);
    for (size_t d = 0; d < m.nd; d++) {
        FUZZ_CHECK(m.twin[d] < m.nd && m.next[d] < m.nd && m.origin[d] < m.nv);
        FUZZ_CHECK(m.twin[m.twin[d]] == d && m.twin[d] != d);
        FUZZ_CHECK(m.origin[m.next[d]] == m.origin[m.twin[d]]);
        FUZZ_CHECK(!hit[m.next[d]]);
        hit[m.next[d]] = 1;
    }
    free(hit);

    /* every leaf: the input's vertices there and their degrees; darts in
     * export order (leaf, local vertex, clockwise), prev and faces */
    hpfc_walker *w;
    hpfc_faces *faces;
    FUZZ_CHECK(hpfc_walker_create(f, &w) == HPFC_OK);
    FUZZ_CHECK(hpfc_faces_build(f, &faces) == HPFC_OK);
    FUZZ_CHECK(hpfc_faces_face_count(faces) == faces_expected);
    placed *in_file = malloc((m.nv + 1) * sizeof *in_file);
    placed *in_graph = malloc((m.nv + 1) * sizeof *in_graph);
    uint64_t *face = malloc((m.nd + 1) * sizeof *face);
    FUZZ_CHECK(in_file && in_graph && face);
    size_t nv = 0, nd = 0;
    hpfc_pixel px;
    int st;
    for (st = hpfc_leaf_first(f, &px); !st; st = hpfc_leaf_next(f, &px)) {
        uint32_t count;
        FUZZ_CHECK(hpfc_pixel_vertex_count(w, &px, &count) == HPFC_OK);
        for (uint32_t k = 0; k < count; k++) {
            hpfc_vertex v;
            uint32_t degree;
            FUZZ_CHECK(hpfc_pixel_vertex(w, &px, k, &v) == HPFC_OK);
            FUZZ_CHECK(hpfc_vertex_degree(w, &v, &degree) == HPFC_OK);
            FUZZ_CHECK(nv < m.nv);
            in_file[nv++] = (placed){hpfc_vertex_key(f, &v) >> 20, degree};
            for (uint32_t e = 0; e < degree; e++, nd++) {
                hpfc_dart d, n, back;
                hpfc_vertex o;
                FUZZ_CHECK(nd < m.nd && m.origin[nd] == nv - 1);
                FUZZ_CHECK(hpfc_vertex_dart(w, &v, e, &d) == HPFC_OK);
                FUZZ_CHECK(hpfc_dart_origin(w, &d, &o) == HPFC_OK &&
                           hpfc_vertex_key(f, &o) == hpfc_vertex_key(f, &v));
                FUZZ_CHECK(hpfc_dart_next(w, &d, &n) == HPFC_OK);
                FUZZ_CHECK(hpfc_dart_prev(w, &n, &back) == HPFC_OK &&
                           hpfc_dart_key(f, &back) == hpfc_dart_key(f, &d));
                FUZZ_CHECK(hpfc_faces_dart_face(faces, &d, &face[nd]) == HPFC_OK);
                FUZZ_CHECK(face[nd] < faces_expected);
                uint64_t same;
                FUZZ_CHECK(!handed || (hpfc_faces_dart_face(handed, &d, &same) == HPFC_OK &&
                                       same == face[nd]));
            }
        }
        int is_private;
        FUZZ_CHECK(hpfc_pixel_is_private(f, &px, &is_private) == HPFC_OK);
        if (is_private) {
            uint64_t pf;
            FUZZ_CHECK(count == 0);
            FUZZ_CHECK(hpfc_faces_pixel_face(faces, &px, &pf) == HPFC_OK && pf < faces_expected);
            uint64_t same;
            FUZZ_CHECK(!handed ||
                       (hpfc_faces_pixel_face(handed, &px, &same) == HPFC_OK && same == pf));
        }
    }
    FUZZ_CHECK(st == HPFC_E_NO_PIXEL && nv == m.nv && nd == m.nd);
    for (size_t d = 0; d < m.nd; d++)
        FUZZ_CHECK(face[m.next[d]] == face[d]);
    for (size_t v = 0; v < gf->nv; v++) {
        int64_t x, y;
        hpfc_graph_vertex(g, v, &x, &y);
        hpfc_vertex at = {.local = 0};
        FUZZ_CHECK(hpfc_locate(f, x, y, &at.pixel) == HPFC_OK);
        in_graph[v] = (placed){hpfc_vertex_key(f, &at) >> 20, gf->degree[v]};
    }
    qsort(in_file, nv, sizeof *in_file, cmp_placed);
    qsort(in_graph, gf->nv, sizeof *in_graph, cmp_placed);
    for (size_t k = 0; k < nv; k++) /* field by field: the struct has padding */
        FUZZ_CHECK(in_file[k].slot == in_graph[k].slot && in_file[k].degree == in_graph[k].degree);
    free(in_file), free(in_graph), free(face);
    hpfc_faces_free(faces);
    hpfc_walker_free(w);
    exported_map_free(&m);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_bytes in = {data, size};
    uint8_t mode = fuzz_u8(&in);
    hpfc_graph *g = mode % 8 < 4 ? graph_from_generator(&in, mode) : graph_from_bytes(&in);
    if (!g)
        return 0;
    hpfc_build_params p;
    hpfc_build_params_default(&p);
    p.root_cols = 1 + fuzz_u8(&in) % 6;
    p.root_rows = 1 + fuzz_u8(&in) % 6;
    p.cols = 2 + fuzz_u8(&in) % 7; /* up to 8 x 8: images over 57 pixels */
    p.rows = 2 + fuzz_u8(&in) % 7; /* take the reader's long-mask path */
    uint8_t flags = fuzz_u8(&in);
    p.flat = (flags & 7) == 7;
    p.max_flat_pixels = (uint64_t)1 << 12; /* keeps an input under ~10 ms */
    int32_t unit = (int32_t)(fuzz_u8(&in) % 11) - 5;
    FUZZ_CHECK(hpfc_graph_set_unit_exp10(g, unit) == HPFC_OK);
    hpfc_tree *t = NULL;
    int vst = hpfc_graph_validate(g, NULL);
    int st = vst ? vst : hpfc_build(g, &p, &t, NULL);
    if (vst || st == HPFC_E_LIMIT || st == HPFC_E_TOO_MANY_PIXELS || st == HPFC_E_EXTENT) {
        FUZZ_CHECK(t == NULL);
        hpfc_graph_free(g);
        return 0;
    }
    FUZZ_CHECK(st == HPFC_OK && t != NULL);

    graph_facts gf;
    facts_of(g, &gf);
    uint64_t faces_expected = gf.ne + 1 + gf.components - gf.nv;
    hpfc_tree_info ti;
    hpfc_tree_get_info(t, &ti);
    FUZZ_CHECK(ti.vertices == gf.nv && ti.edges == gf.ne);
    FUZZ_CHECK(ti.components == gf.components && ti.faces == faces_expected);
    FUZZ_CHECK(ti.unit_exp10 == unit);

    const char *crs = flags & 8 ? "EPSG:32631" : NULL;
    /* flags bit 4: the compact pool layout (spec §5.3), whose reader the
     * same oracle then checks against the tree */
    /* flags bit 5: LABL, its faces handed out and bound to the file read
     * back (hpfc-pack's linking takes them so) */
    hpfc_faces *handed = NULL;
    hpfc_write_options opts = {.crs = crs,
                               .layout = flags & 16 ? HPFC_LAYOUT_COMPACT : HPFC_LAYOUT_PAPER,
                               .face_labels = (flags & 32) != 0,
                               .faces_out = &handed};
    uint8_t *buf = NULL;
    size_t len = 0;
    FUZZ_CHECK(hpfc_tree_serialize(t, &opts, &buf, &len, NULL) == HPFC_OK);
    FUZZ_CHECK((handed != NULL) == ((flags & 32) != 0));
    hpfc_file *f = NULL;
    FUZZ_CHECK(hpfc_open_memory(buf, len, 0, &f) == HPFC_OK);
    FUZZ_CHECK(!handed || hpfc_faces_attach(handed, f) == HPFC_OK);
    FUZZ_CHECK(hpfc_file_check_checksums(f, NULL) == HPFC_OK);
    hpfc_file_info fi;
    hpfc_file_get_info(f, &fi);
    FUZZ_CHECK(fi.unit_exp10 == unit && fi.levels == ti.levels && fi.file_size == len);
    FUZZ_CHECK(crs ? fi.crs && fi.crs_len == strlen(crs) && memcmp(fi.crs, crs, fi.crs_len) == 0
                   : fi.crs == NULL);
    compare_tree(t, f);
    check_map(f, g, &gf, faces_expected, handed);
    hpfc_faces_free(handed);

    hpfc_close(f);
    hpfc_free(buf);
    free(gf.degree);
    hpfc_tree_free(t);
    hpfc_graph_free(g);
    return 0;
}
