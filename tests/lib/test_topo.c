/*
 * Traversal tests: the map read back from a file with the library's
 * operators must be the input graph's combinatorial map. The oracle builds
 * that map from the graph alone (exact angular order of darts around each
 * vertex) and looks for an isomorphism that keeps every vertex inside the
 * box the file gives it.
 */
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "export.h"
#include "gen.h"
#include "hpfc.h"
#include "key_ops.h"
#include "faces.h"
#include "reader.h"

__extension__ typedef __int128 i128;

/* ---- the input graph's combinatorial map --------------------------------- */

typedef struct graph_map {
    size_t nv, nd;
    int64_t *xy;                 /* vertex positions */
    uint32_t *origin, *twin, *next;
    int64_t *dir;                /* 2 per dart: direction of its first segment */
} graph_map;

/* Counter-clockwise angular order of two directions, from the +x axis. */
/* the layout under test (check_use_test_layout) */
static int test_layout_compact;

static int ccw_cmp(const int64_t *a, const int64_t *b)
{
    int ha = a[1] < 0 || (a[1] == 0 && a[0] < 0), hb = b[1] < 0 || (b[1] == 0 && b[0] < 0);
    if (ha != hb)
        return ha - hb;
    i128 cross = (i128)a[0] * b[1] - (i128)a[1] * b[0];
    return cross > 0 ? -1 : cross < 0;
}

static const graph_map *sort_map;
static int cmp_darts_ccw(const void *pa, const void *pb)
{
    uint32_t a = *(const uint32_t *)pa, b = *(const uint32_t *)pb;
    if (sort_map->origin[a] != sort_map->origin[b])
        return sort_map->origin[a] < sort_map->origin[b] ? -1 : 1;
    return ccw_cmp(sort_map->dir + 2 * a, sort_map->dir + 2 * b);
}

static void graph_map_build(const hpfc_graph *g, graph_map *m)
{
    m->nv = hpfc_graph_vertex_count(g);
    m->nd = 2 * hpfc_graph_edge_count(g);
    m->xy = malloc(2 * m->nv * sizeof *m->xy);
    m->origin = malloc(m->nd * sizeof *m->origin);
    m->twin = malloc(m->nd * sizeof *m->twin);
    m->next = malloc(m->nd * sizeof *m->next);
    m->dir = malloc(2 * m->nd * sizeof *m->dir);
    for (size_t v = 0; v < m->nv; v++)
        hpfc_graph_vertex(g, v, &m->xy[2 * v], &m->xy[2 * v + 1]);
    for (size_t e = 0; e < m->nd / 2; e++) {
        uint32_t u, v;
        const int64_t *pts;
        size_t n;
        hpfc_graph_edge(g, e, &u, &v, &pts, &n);
        int64_t first[2], last[2];
        first[0] = n ? pts[0] : m->xy[2 * v], first[1] = n ? pts[1] : m->xy[2 * v + 1];
        last[0] = n ? pts[2 * n - 2] : m->xy[2 * u], last[1] = n ? pts[2 * n - 1] : m->xy[2 * u + 1];
        m->origin[2 * e] = u, m->origin[2 * e + 1] = v;
        m->twin[2 * e] = (uint32_t)(2 * e + 1), m->twin[2 * e + 1] = (uint32_t)(2 * e);
        m->dir[4 * e] = first[0] - m->xy[2 * u], m->dir[4 * e + 1] = first[1] - m->xy[2 * u + 1];
        m->dir[4 * e + 2] = last[0] - m->xy[2 * v], m->dir[4 * e + 3] = last[1] - m->xy[2 * v + 1];
    }
    /* next(d) = the dart after twin(d) counter-clockwise around d's target */
    uint32_t *order = malloc(m->nd * sizeof *order);
    for (size_t d = 0; d < m->nd; d++)
        order[d] = (uint32_t)d;
    sort_map = m;
    qsort(order, m->nd, sizeof *order, cmp_darts_ccw);
    uint32_t *ccw_next = malloc(m->nd * sizeof *ccw_next);
    for (size_t s = 0; s < m->nd;) {
        size_t e = s;
        while (e < m->nd && m->origin[order[e]] == m->origin[order[s]])
            e++;
        for (size_t k = s; k < e; k++)
            ccw_next[order[k]] = order[k + 1 < e ? k + 1 : s];
        s = e;
    }
    for (size_t d = 0; d < m->nd; d++)
        m->next[d] = ccw_next[m->twin[d]];
    free(order);
    free(ccw_next);
}

static void graph_map_free(graph_map *m)
{
    free(m->xy), free(m->origin), free(m->twin), free(m->next), free(m->dir);
}

/* ---- isomorphism under the box constraint -------------------------------- */

static bool inside(const int64_t *box, const int64_t *p)
{
    return p[0] >= box[0] && p[0] < box[2] && p[1] >= box[1] && p[1] < box[3];
}

/* Tries to extend f (file dart -> graph dart) from seed -> cand over the
 * seed's connected component. On failure undoes what it set. */
static bool try_map(const exported_map *fm, const graph_map *gm, uint32_t seed, uint32_t cand,
                    uint32_t *f, uint32_t *finv, uint32_t *queue)
{
    size_t head = 0, tail = 0, set = 0;
    bool ok = true;
    f[seed] = cand, finv[cand] = seed, queue[tail++] = seed;
    while (head < tail && ok) {
        uint32_t d = queue[head++], g = f[d];
        if (!inside(fm->box + 4 * fm->origin[d], gm->xy + 2 * gm->origin[g])) {
            ok = false;
            break;
        }
        uint32_t pairs[2][2] = {{fm->twin[d], gm->twin[g]}, {fm->next[d], gm->next[g]}};
        for (int k = 0; k < 2 && ok; k++) {
            uint32_t fd = pairs[k][0], gd = pairs[k][1];
            if (f[fd] == UINT32_MAX && finv[gd] == UINT32_MAX) {
                f[fd] = gd, finv[gd] = fd, queue[tail++] = fd;
            } else if (f[fd] != gd || finv[gd] != fd) {
                ok = false;
            }
        }
    }
    set = tail;
    if (!ok)
        for (size_t k = 0; k < set; k++) {
            finv[f[queue[k]]] = UINT32_MAX;
            f[queue[k]] = UINT32_MAX;
        }
    return ok;
}

/* Returns the number of file darts left without an image. */
static size_t isomorphism_failures(const exported_map *fm, const graph_map *gm)
{
    if (fm->nd != gm->nd || fm->nv != gm->nv)
        return fm->nd + 1;
    uint32_t *f = malloc(fm->nd * sizeof *f), *finv = malloc(gm->nd * sizeof *finv);
    uint32_t *queue = malloc(fm->nd * sizeof *queue);
    memset(f, 0xff, fm->nd * sizeof *f);
    memset(finv, 0xff, gm->nd * sizeof *finv);
    size_t failures = 0;
    for (uint32_t s = 0; s < fm->nd; s++) {
        if (f[s] != UINT32_MAX)
            continue;
        bool found = false;
        for (uint32_t c = 0; c < gm->nd && !found; c++)
            if (finv[c] == UINT32_MAX && inside(fm->box + 4 * fm->origin[s], gm->xy + 2 * gm->origin[c]))
                found = try_map(fm, gm, s, c, f, finv, queue);
        failures += !found;
    }
    free(f), free(finv), free(queue);
    return failures;
}

/* ---- per-graph checks ---------------------------------------------------- */

static hpfc_file *pack_with(const hpfc_graph *g, const hpfc_build_params *p, uint8_t **buf)
{
    hpfc_tree *t = NULL;
    hpfc_file *f = NULL;
    size_t size;
    *buf = NULL;
    if (hpfc_build(g, p, &t, NULL) == HPFC_OK && check_tree_serialize(t, NULL, buf, &size, NULL) == HPFC_OK)
        CHECK_EQ_INT(hpfc_open_memory(*buf, size, 0, &f), HPFC_OK);
    hpfc_tree_free(t);
    return f;
}

static hpfc_file *pack(const hpfc_graph *g, uint32_t n0, uint32_t n, int flat, uint8_t **buf)
{
    hpfc_build_params p;
    hpfc_build_params_default(&p);
    p.root_cols = p.root_rows = n0;
    p.cols = p.rows = n;
    p.flat = flat;
    return pack_with(g, &p, buf);
}

/* opposite(opposite(d)) == d and next(prev(d)) == prev(next(d)) == d on
 * every dart; origin(next(d)) == target(d). */
static void check_involutions(const hpfc_file *f)
{
    hpfc_walker *w;
    CHECK_EQ_INT(hpfc_walker_create(f, &w), HPFC_OK);
    hpfc_pixel px;
    int st = hpfc_leaf_first(f, &px);
    size_t bad = 0, darts = 0;
    while (!st) {
        uint32_t nv = 0;
        hpfc_pixel_vertex_count(w, &px, &nv);
        for (uint32_t v = 0; v < nv; v++) {
            hpfc_vertex vx;
            uint32_t deg = 0;
            hpfc_pixel_vertex(w, &px, v, &vx);
            hpfc_vertex_degree(w, &vx, &deg);
            for (uint32_t k = 0; k < deg; k++) {
                hpfc_dart d, a, b, c;
                hpfc_vertex tv, ov;
                hpfc_vertex_dart(w, &vx, k, &d);
                uint64_t key = hpfc_dart_key(f, &d);
                darts++;
                bad += hpfc_dart_twin(w, &d, &a) || hpfc_dart_twin(w, &a, &b) || hpfc_dart_key(f, &b) != key;
                bad += hpfc_dart_prev(w, &d, &a) || hpfc_dart_next(w, &a, &c) || hpfc_dart_key(f, &c) != key;
                bad += hpfc_dart_next(w, &d, &a) || hpfc_dart_prev(w, &a, &c) || hpfc_dart_key(f, &c) != key;
                bad += hpfc_dart_target(w, &d, &tv) || hpfc_dart_origin(w, &a, &ov) ||
                       hpfc_vertex_key(f, &tv) != hpfc_vertex_key(f, &ov);
            }
        }
        st = hpfc_leaf_next(f, &px);
    }
    CHECK_EQ_INT(st, HPFC_E_NO_PIXEL);
    CHECK(darts > 0);
    CHECK_EQ_INT(bad, 0);
    hpfc_walker_free(w);
}

static size_t collect_darts(const hpfc_file *f, hpfc_walker *w, hpfc_dart *darts, size_t max);

/* The face of every dart, in hpfc_vertex_dart order (nd darts): the
 * number of darts whose face is not a face id below `count`. */
static size_t faces_of_darts(const hpfc_file *f, hpfc_walker *w, const hpfc_faces *faces,
                             uint64_t count, uint64_t *face_of, size_t nd)
{
    hpfc_dart *darts = malloc((nd ? nd : 1) * sizeof *darts);
    size_t n = collect_darts(f, w, darts, nd), bad = 0;
    CHECK_EQ_INT(n, nd);
    for (size_t d = 0; d < n; d++)
        bad += hpfc_faces_dart_face(faces, &darts[d], &face_of[d]) != HPFC_OK ||
               face_of[d] >= count;
    for (size_t d = 0; d < n; d++) { /* a dart's pixel cut to a refined ancestor names no leaf */
        hpfc_dart up = darts[d];
        uint64_t face;
        if (up.pixel.depth == 0)
            continue;
        up.pixel.depth--;
        bad += hpfc_faces_dart_face(faces, &up, &face) != HPFC_E_ARG;
        break;
    }
    free(darts);
    return bad;
}

/* The 64-bit union-find of continental maps numbers the faces as the
 * 32-bit one does: the face of every dart. */
static void check_wide_faces(const hpfc_file *f, hpfc_walker *w, uint64_t count,
                             const uint64_t *face_of, size_t nd)
{
    hpfc_faces *wide;
    CHECK_EQ_INT(faces_build_width(f, 0, 1, 0, NULL, &wide), HPFC_OK);
    if (!wide)
        return;
    CHECK_EQ_INT(hpfc_faces_face_count(wide), count);
    uint64_t *wide_of = malloc(nd * sizeof *wide_of);
    CHECK_EQ_INT(faces_of_darts(f, w, wide, count, wide_of, nd), 0);
    CHECK(memcmp(wide_of, face_of, nd * sizeof *face_of) == 0);
    free(wide_of);
    hpfc_faces_free(wide);
}

/* Faces with holes: the count obeys Euler (V - E + F = 1 + C), there are
 * F + C - 1 boundary loops, every loop has one face and every face a loop. */
static void check_faces(const hpfc_file *f, const exported_map *fm, const hpfc_graph *g)
{
    hpfc_faces *faces;
    CHECK_EQ_INT(hpfc_faces_build(f, &faces), HPFC_OK);
    if (!faces)
        return;
    size_t nv = hpfc_graph_vertex_count(g), ne = hpfc_graph_edge_count(g);
    /* components, from the input graph */
    uint32_t *root = malloc(nv * sizeof *root);
    for (size_t v = 0; v < nv; v++)
        root[v] = (uint32_t)v;
    size_t comps = nv;
    for (size_t e = 0; e < ne; e++) {
        uint32_t u, v;
        const int64_t *pts;
        size_t n;
        hpfc_graph_edge(g, e, &u, &v, &pts, &n);
        while (root[u] != u) u = root[u];
        while (root[v] != v) v = root[v];
        if (u != v)
            root[u] = v, comps--;
    }
    free(root);
    uint64_t F = hpfc_faces_face_count(faces);
    CHECK_EQ_INT(F, ne + 1 + comps - nv);
    /* loops = orbits of next; each must carry a single face id */
    hpfc_walker *w;
    hpfc_walker_create(f, &w);
    uint64_t *face_of = malloc(fm->nd * sizeof *face_of);
    CHECK_EQ_INT(faces_of_darts(f, w, faces, F, face_of, fm->nd), 0);
    check_wide_faces(f, w, F, face_of, fm->nd);
    uint8_t *seen = calloc(fm->nd, 1), *face_seen = calloc(F + 1, 1);
    size_t loops = 0, bad = 0;
    for (size_t s = 0; s < fm->nd; s++) {
        if (seen[s])
            continue;
        loops++;
        for (size_t x = s; !seen[x]; x = fm->next[x]) {
            seen[x] = 1;
            bad += face_of[x] != face_of[s];
            face_seen[face_of[x] < F ? face_of[x] : F] = 1;
        }
    }
    CHECK_EQ_INT(bad, 0);
    CHECK_EQ_INT(loops, F + comps - 1);
    size_t faces_with_loops = 0;
    for (uint64_t x = 0; x < F; x++)
        faces_with_loops += face_seen[x];
    CHECK_EQ_INT(faces_with_loops, F);
    free(seen), free(face_seen), free(face_of);
    hpfc_walker_free(w);
    hpfc_faces_free(faces);
}

static void check_keys(const hpfc_file *f, size_t nd);

static void check_graph(const hpfc_graph *g, const char *what)
{
    static const uint32_t shapes[][3] = {{1, 2, 0}, {4, 2, 0}, {16, 2, 0}, {5, 3, 0}, {4, 2, 1}};
    graph_map gm;
    graph_map_build(g, &gm);
    for (size_t s = 0; s < sizeof shapes / sizeof *shapes; s++) {
        uint8_t *buf;
        hpfc_file *f = pack(g, shapes[s][0], shapes[s][1], (int)shapes[s][2], &buf);
        if (!f) {
            hpfc_free(buf);
            CHECK(shapes[s][2] == 1); /* only a flat grid may exceed its limit */
            continue;
        }
        exported_map fm;
        int st = export_map(f, &fm);
        CHECK_EQ_INT(st, HPFC_OK);
        if (!st) {
            CHECK_EQ_INT(fm.nv, gm.nv);
            CHECK_EQ_INT(fm.nd, gm.nd);
            size_t fails = isomorphism_failures(&fm, &gm);
            if (fails)
                fprintf(stderr, "%s, root %u refine %u%s: %zu darts unmatched\n", what, shapes[s][0],
                        shapes[s][1], shapes[s][2] ? " flat" : "", fails);
            CHECK_EQ_INT(fails, 0);
            check_faces(f, &fm, g);
            exported_map_free(&fm);
        }
        check_involutions(f);
        check_keys(f, gm.nd);
        hpfc_close(f);
        hpfc_free(buf);
    }
    graph_map_free(&gm);
}

static void test_generated(void)
{
    CHECK_EQ_INT(gen_sweep(3, 80, 150, check_graph), HPFC_OK);
}

/* A 3 x 6 root refined 2 x 8: cells thousands of times taller than wide,
 * refined nine levels deep around two short edges, so that a road borders
 * more leaves (private ones) than the whole file has crossings. Walks along
 * a road were bounded by the crossings and hpfc_faces_build answered
 * CORRUPT on this valid file (found by the roundtrip_graph fuzzer). */
static void test_road_with_many_leaves(void)
{
    static const int64_t xy[4][2] = {{8320, 896}, {0, 128}, {0, -128}, {6528, 6272}};
    hpfc_graph *g = NULL;
    CHECK_EQ_INT(hpfc_graph_create(&g), HPFC_OK);
    uint32_t v[4];
    for (int k = 0; k < 4; k++)
        CHECK_EQ_INT(hpfc_graph_add_vertex(g, xy[k][0], xy[k][1], &v[k]), HPFC_OK);
    CHECK_EQ_INT(hpfc_graph_add_edge(g, v[1], v[2], NULL, 0, NULL), HPFC_OK);
    CHECK_EQ_INT(hpfc_graph_add_edge(g, v[3], v[0], NULL, 0, NULL), HPFC_OK);
    hpfc_build_params p;
    hpfc_build_params_default(&p);
    p.root_cols = 3, p.root_rows = 6, p.cols = 2, p.rows = 8;
    uint8_t *buf;
    hpfc_file *f = pack_with(g, &p, &buf);
    CHECK(f != NULL);
    if (f) {
        hpfc_file_info info;
        hpfc_file_get_info(f, &info);
        CHECK(info.levels >= 8); /* the deep refinement this case needs */
        graph_map gm;
        graph_map_build(g, &gm);
        exported_map fm;
        CHECK_EQ_INT(export_map(f, &fm), HPFC_OK);
        CHECK_EQ_INT(isomorphism_failures(&fm, &gm), 0);
        check_faces(f, &fm, g);
        check_involutions(f);
        check_keys(f, gm.nd); /* nine levels of parents */
        exported_map_free(&fm);
        graph_map_free(&gm);
    }
    hpfc_close(f);
    hpfc_free(buf);
    hpfc_graph_free(g);
}

/* ---- the walker's cache -------------------------------------------------- */

/* Cache sizes that must all give the same answers: off, so small that
 * almost every operator empties it (or runs without it), small, default. */
static const size_t cache_sizes[] = {0, 700, 2048, 16384, HPFC_WALKER_DEFAULT_CACHE};
#define CACHE_SIZES (sizeof cache_sizes / sizeof *cache_sizes)

static uint64_t mix(uint64_t h, uint64_t v)
{
    h ^= v + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
    return h * 0xBF58476D1CE4E5B9ull;
}

/* Everything an operator returns: status, and the full pixel path (not only
 * the key) and crossing or local vertex. */
static uint64_t pixel_digest(uint64_t h, const hpfc_pixel *px)
{
    h = mix(h, px->depth);
    for (uint32_t l = 0; l <= px->depth && l < HPFC_MAX_LEVELS; l++)
        h = mix(mix(mix(h, px->path[l].image), px->path[l].i), px->path[l].j);
    return h;
}

static uint64_t dart_result(uint64_t h, int st, const hpfc_dart *d)
{
    h = mix(h, (uint64_t)st);
    return st ? h : mix(pixel_digest(h, &d->pixel), d->crossing);
}

static uint64_t vertex_result(uint64_t h, int st, const hpfc_vertex *v)
{
    h = mix(h, (uint64_t)st);
    return st ? h : mix(pixel_digest(h, &v->pixel), v->local);
}

/* Every dart of the file, from leaf order (darts[] holds up to max). */
static size_t collect_darts(const hpfc_file *f, hpfc_walker *w, hpfc_dart *darts, size_t max)
{
    hpfc_pixel px;
    size_t n = 0;
    for (int st = hpfc_leaf_first(f, &px); !st; st = hpfc_leaf_next(f, &px)) {
        uint32_t nv = 0;
        hpfc_pixel_vertex_count(w, &px, &nv);
        for (uint32_t v = 0; v < nv; v++) {
            hpfc_vertex vx;
            uint32_t deg = 0;
            hpfc_pixel_vertex(w, &px, v, &vx);
            hpfc_vertex_degree(w, &vx, &deg);
            for (uint32_t k = 0; k < deg && n < max; k++)
                CHECK_EQ_INT(hpfc_vertex_dart(w, &vx, k, &darts[n++]), HPFC_OK);
        }
    }
    return n;
}

/* Digests of every operator on every dart, in order, with a cache of
 * `bytes`; *decodes gets the words decoded. */
static void operator_digests(const hpfc_file *f, size_t bytes, const hpfc_dart *darts, size_t n,
                             uint64_t *digest, uint64_t *decodes)
{
    hpfc_walker *w;
    CHECK_EQ_INT(hpfc_walker_create(f, &w), HPFC_OK);
    CHECK_EQ_INT(hpfc_walker_set_cache_size(w, bytes), HPFC_OK);
    uint64_t before = hpfc_walker_pixels_visited(w);
    for (size_t k = 0; k < n; k++) {
        hpfc_dart d;
        hpfc_vertex v;
        uint64_t h = 0;
        h = dart_result(h, hpfc_dart_twin(w, &darts[k], &d), &d);
        h = dart_result(h, hpfc_dart_next(w, &darts[k], &d), &d);
        h = dart_result(h, hpfc_dart_prev(w, &darts[k], &d), &d);
        h = vertex_result(h, hpfc_dart_origin(w, &darts[k], &v), &v);
        h = vertex_result(h, hpfc_dart_target(w, &darts[k], &v), &v);
        digest[k] = h;
    }
    *decodes = hpfc_walker_pixels_visited(w) - before;
    hpfc_walker_free(w);
}

/* Every cache size gives every operator's answer unchanged; the default
 * cache decodes each word about once in the whole pass. */
static void check_cache_sizes(const hpfc_file *f, size_t nd)
{
    hpfc_walker *w;
    CHECK_EQ_INT(hpfc_walker_create(f, &w), HPFC_OK);
    hpfc_dart *darts = malloc((nd + 1) * sizeof *darts);
    size_t n = collect_darts(f, w, darts, nd);
    hpfc_walker_free(w);
    CHECK_EQ_INT(n, nd);
    uint64_t *digest[CACHE_SIZES], decodes[CACHE_SIZES];
    for (size_t s = 0; s < CACHE_SIZES; s++) {
        digest[s] = malloc((n + 1) * sizeof(uint64_t));
        operator_digests(f, cache_sizes[s], darts, n, digest[s], &decodes[s]);
    }
    size_t differ = 0;
    for (size_t s = 1; s < CACHE_SIZES; s++)
        for (size_t k = 0; k < n; k++)
            differ += digest[s][k] != digest[0][k];
    CHECK_EQ_INT(differ, 0);
    hpfc_file_info info;
    hpfc_file_get_info(f, &info);
    uint64_t leaves = 0;
    hpfc_level_info lv;
    for (uint32_t l = 0; hpfc_file_get_level(f, l, &lv) == HPFC_OK; l++)
        leaves += lv.word_pixels;
    CHECK(decodes[CACHE_SIZES - 1] <= leaves);       /* each word at most once */
    CHECK(decodes[CACHE_SIZES - 1] <= decodes[0]);   /* and never more than without */
    for (size_t s = 0; s < CACHE_SIZES; s++)
        free(digest[s]);
    free(darts);
}

/* Two breadth-first traversals (one by next and twin, one by prev and twin)
 * advanced in turn on one walker give, step by step, what a walker without
 * cache gives. */
static void check_interleaved(const hpfc_file *f, size_t nd, size_t bytes)
{
    hpfc_walker *w, *plain;
    CHECK_EQ_INT(hpfc_walker_create(f, &w), HPFC_OK);
    CHECK_EQ_INT(hpfc_walker_create(f, &plain), HPFC_OK);
    CHECK_EQ_INT(hpfc_walker_set_cache_size(w, bytes), HPFC_OK);
    CHECK_EQ_INT(hpfc_walker_set_cache_size(plain, 0), HPFC_OK);
    hpfc_dart *darts = malloc((nd + 1) * sizeof *darts);
    size_t n = collect_darts(f, plain, darts, nd);
    hpfc_dart *queue[2] = {malloc((2 * n + 2) * sizeof(hpfc_dart)), malloc((2 * n + 2) * sizeof(hpfc_dart))};
    size_t head[2] = {0, 0}, tail[2] = {0, 0}, differ = 0, steps = 0;
    if (n) {
        queue[0][tail[0]++] = darts[0];
        queue[1][tail[1]++] = darts[n - 1];
    }
    /* each queue visits darts again (no visited set) until 2n entries */
    while (head[0] < tail[0] || head[1] < tail[1]) {
        for (int t = 0; t < 2; t++) {
            if (head[t] == tail[t])
                continue;
            const hpfc_dart *d = &queue[t][head[t]++];
            hpfc_dart a, b;
            int sa = t ? hpfc_dart_prev(w, d, &a) : hpfc_dart_next(w, d, &a);
            int sb = t ? hpfc_dart_prev(plain, d, &b) : hpfc_dart_next(plain, d, &b);
            differ += dart_result(0, sa, &a) != dart_result(0, sb, &b);
            if (!sa && tail[t] < 2 * n)
                queue[t][tail[t]++] = a;
            sa = hpfc_dart_twin(w, d, &a);
            sb = hpfc_dart_twin(plain, d, &b);
            differ += dart_result(0, sa, &a) != dart_result(0, sb, &b);
            if (!sa && tail[t] < 2 * n && head[t] % 3 == 0)
                queue[t][tail[t]++] = a;
            steps++;
        }
    }
    CHECK(steps > 0);
    CHECK_EQ_INT(differ, 0);
    free(queue[0]), free(queue[1]), free(darts);
    hpfc_walker_free(w);
    hpfc_walker_free(plain);
}

/* A caller's dart whose path says another image at some level above its
 * pixel (the pixel itself and its bounds unchanged): the operators follow
 * that path, so the answers differ from the true dart's; they must not
 * differ between walkers with and without the cache, whatever order real
 * and altered darts come in. */
static void check_altered_paths(const hpfc_file *f, size_t nd)
{
    hpfc_walker *w, *plain;
    CHECK_EQ_INT(hpfc_walker_create(f, &w), HPFC_OK);
    CHECK_EQ_INT(hpfc_walker_create(f, &plain), HPFC_OK);
    CHECK_EQ_INT(hpfc_walker_set_cache_size(plain, 0), HPFC_OK);
    hpfc_dart *darts = malloc((nd + 1) * sizeof *darts);
    size_t n = collect_darts(f, plain, darts, nd), altered = 0, differ = 0;
    for (size_t k = 0; k < n; k++) {
        hpfc_dart d = darts[k];
        const hpfc_dart *other = &darts[(k * 7 + 3) % n];
        if (k % 2) { /* another image at a level above */
            for (uint32_t l = 1; l < d.pixel.depth && l <= other->pixel.depth; l++)
                if (other->pixel.path[l].image != d.pixel.path[l].image) {
                    d.pixel.path[l].image = other->pixel.path[l].image;
                    altered++;
                    break;
                }
        } else if (d.pixel.depth > 0) { /* another column or row: moved bounds */
            uint32_t l = (uint32_t)(k / 2 % d.pixel.depth);
            if (k % 4)
                d.pixel.path[l].i ^= 1;
            else
                d.pixel.path[l].j ^= 1;
            altered++;
        }
        const hpfc_dart *both[2] = {&darts[k], &d};
        for (int b = 0; b < 2; b++) {
            uint64_t h[2] = {0, 0};
            hpfc_walker *ws[2] = {w, plain};
            for (int s = 0; s < 2; s++) {
                hpfc_dart o;
                hpfc_vertex v;
                h[s] = dart_result(h[s], hpfc_dart_twin(ws[s], both[b], &o), &o);
                h[s] = dart_result(h[s], hpfc_dart_next(ws[s], both[b], &o), &o);
                h[s] = dart_result(h[s], hpfc_dart_prev(ws[s], both[b], &o), &o);
                h[s] = vertex_result(h[s], hpfc_dart_origin(ws[s], both[b], &v), &v);
                h[s] = vertex_result(h[s], hpfc_dart_target(ws[s], both[b], &v), &v);
            }
            differ += h[0] != h[1];
        }
    }
    CHECK_EQ_INT(differ, 0);
    CHECK(altered > n / 4);
    free(darts);
    hpfc_walker_free(w);
    hpfc_walker_free(plain);
}

/* ---- keys as handles ------------------------------------------------------ */

enum { KEY_OPS = 5 }; /* the operators of key_ops.h */

/* Keys that name no dart: past the word's crossings, a crossing of a
 * stabbing, a position off the slot, in a mask, on a refined root record,
 * past the file. */
static size_t check_bad_keys(const hpfc_file *f, hpfc_walker *w, const uint64_t *keys, size_t n)
{
    size_t bad = 0, tried = 0;
    hpfc_pixel px;
    for (int st = hpfc_leaf_first(f, &px); !st; st = hpfc_leaf_next(f, &px)) {
        char sym[4096];
        size_t len = 0;
        uint32_t crossings = 0;
        if (hpfc_pixel_word(f, &px, sym, sizeof sym, &len) != HPFC_OK)
            continue;
        for (size_t s = 0; s < len; s++)
            crossings += sym[s] != '+';
        hpfc_dart d = {px, 0};
        uint64_t pos = hpfc_dart_key(f, &d) >> 20;
        for (uint32_t k = 0; k < crossings + 2; k++) {
            uint64_t key = pos << 20 | k, out;
            bool is_dart = false;
            for (size_t x = 0; x < n && !is_dart; x++)
                is_dart = keys[x] == key;
            hpfc_dart back;
            int want = is_dart ? HPFC_OK : HPFC_E_ARG;
            for (int op = 0; op < KEY_OPS; op++) /* warm: twin, next and prev answer from blocks */
                bad += key_op_call(w, op, key, &out) != want;
            bad += hpfc_dart_from_key(w, key, &back) != want;
            tried++;
        }
        uint64_t out;
        bad += hpfc_key_twin(w, (pos + 1) << 20, &out) != HPFC_E_ARG; /* inside the slot */
        bad += hpfc_key_twin(w, pos << 20 | 0xFFFFF, &out) != HPFC_E_ARG;
        tried += 2;
    }
    hpfc_file_info info;
    hpfc_level_info lv0, lv1;
    hpfc_file_get_info(f, &info);
    hpfc_file_get_level(f, 0, &lv0);
    uint64_t out;
    hpfc_dart d;
    hpfc_vertex v;
    uint64_t beyond[] = {(info.file_size * 8) << 20, UINT64_MAX, 0,
                         (lv0.pool_offset * 8 - 1) << 20};
    for (size_t k = 0; k < sizeof beyond / sizeof *beyond; k++) {
        bad += hpfc_key_next(w, beyond[k], &out) != HPFC_E_ARG;
        bad += hpfc_dart_from_key(w, beyond[k], &d) != HPFC_E_ARG;
        bad += hpfc_vertex_from_key(w, beyond[k], &v) != HPFC_E_ARG;
        tried++;
    }
    if (hpfc_file_get_level(f, 1, &lv1) == HPFC_OK) { /* a mask bit, and a refined root record */
        /* paper: bit 0 is a mask bit; compact: pixel 0's type bits start
         * there, bit 1 is the second of them */
        uint64_t mask_bit = lv1.pool_offset * 8 + (info.incompat_flags & 1);
        bad += hpfc_key_prev(w, mask_bit << 20, &out) != HPFC_E_ARG;
        for (uint32_t r = 0; r < info.root_cols * info.root_rows; r++) {
            hpfc_pixel root;
            int type;
            uint64_t at; /* its record (paper) or type bits (compact) */
            hpfc_pixel_root(f, r % info.root_cols, r / info.root_cols, &root);
            if (hpfc_pixel_type(f, &root, &type) == HPFC_OK && type == HPFC_PIXEL_REFINED &&
                reader_pixel_slot_bit(f, &root, &at) == HPFC_OK) {
                bad += hpfc_key_twin(w, at << 20, &out) != HPFC_E_ARG;
                tried++;
                break;
            }
        }
        tried++;
    }
    CHECK(tried > n);
    CHECK(hpfc_key_next(NULL, keys[0], &out) == HPFC_E_ARG);
    CHECK(hpfc_key_next(w, keys[0], NULL) == HPFC_E_ARG);
    CHECK(hpfc_dart_from_key(w, keys[0], NULL) == HPFC_E_ARG);
    return bad;
}

/* Every key operator on every dart equals the dart operator's answer as a
 * key, for each cache size (`bytes`), keys taken in leaf order, then in a
 * breadth-first order by next and twin on keys, with dart operators on the
 * same walker in between (their cache entries are reached by other means);
 * hpfc_dart_from_key and hpfc_vertex_from_key give back the very dart and
 * vertex (whole path) a key came from. */
static void check_keys_with(const hpfc_file *f, const hpfc_dart *darts, const uint64_t *want,
                            size_t n, size_t bytes)
{
    hpfc_walker *w;
    CHECK_EQ_INT(hpfc_walker_create(f, &w), HPFC_OK);
    CHECK_EQ_INT(hpfc_walker_set_cache_size(w, bytes), HPFC_OK);
    uint64_t *keys = malloc((n + 1) * sizeof *keys);
    size_t differ = 0, back = 0;
    for (size_t k = 0; k < n; k++)
        keys[k] = hpfc_dart_key(f, &darts[k]);
    for (int pass = 0; pass < 2; pass++) /* the second pass finds the cache warm */
        for (size_t k = 0; k < n; k++) {
            size_t x = pass ? n - 1 - k : k;
            for (int op = 0; op < KEY_OPS; op++) {
                uint64_t got = 0;
                int st = key_op_call(w, op, keys[x], &got);
                differ += st != HPFC_OK || got != want[KEY_OPS * x + op];
            }
            if (k % 3 == 0) { /* a dart operator in between */
                hpfc_dart r;
                hpfc_dart_next(w, &darts[(x * 7) % n], &r);
            }
            hpfc_dart d;
            hpfc_vertex v;
            uint64_t vkey = want[KEY_OPS * x + 3];
            back += hpfc_dart_from_key(w, keys[x], &d) != HPFC_OK ||
                    dart_result(0, 0, &d) != dart_result(0, 0, &darts[x]);
            back += hpfc_vertex_from_key(w, vkey, &v) != HPFC_OK ||
                    hpfc_vertex_key(f, &v) != vkey ||
                    pixel_digest(0, &v.pixel) != pixel_digest(0, &darts[x].pixel);
            back += hpfc_vertex_from_key(w, vkey | 0xFFFFF, &v) != HPFC_E_ARG;
        }
    /* breadth-first on keys alone; every key reached is a dart's */
    uint64_t *queue = malloc((n + 1) * sizeof *queue);
    uint8_t *seen = calloc(n + 1, 1);
    size_t head = 0, tail = 0, reached = 0;
    for (size_t s = 0; s < n; s++) {
        if (seen[s])
            continue;
        seen[s] = 1, queue[tail++] = keys[s];
        while (head < tail) {
            uint64_t key = queue[head++], out;
            size_t x = 0;
            while (x < n && keys[x] != key)
                x++;
            CHECK(x < n);
            if (x == n)
                break;
            reached++;
            for (int op = 0; op < 2; op++) {
                int st = key_op_call(w, op, key, &out);
                differ += st != HPFC_OK || out != want[KEY_OPS * x + op];
                size_t y = 0;
                while (!st && y < n && keys[y] != out)
                    y++;
                if (!st && y < n && !seen[y])
                    seen[y] = 1, queue[tail++] = out;
            }
        }
    }
    CHECK_EQ_INT(reached, n);
    CHECK_EQ_INT(differ, 0);
    CHECK_EQ_INT(back, 0);
    CHECK_EQ_INT(check_bad_keys(f, w, keys, n), 0);
    free(queue), free(seen), free(keys);
    hpfc_walker_free(w);
}

/* ---- dense indices -------------------------------------------------------- */

/* The documented numbering, computed from the public level info and the
 * images the leaves' paths go through: per level, the sorted addresses of
 * its images (their pool order). */
typedef struct index_oracle {
    uint64_t *images[HPFC_MAX_LEVELS];
    uint64_t count[HPFC_MAX_LEVELS];
    uint64_t first[HPFC_MAX_LEVELS + 1]; /* first pixel id of each level */
    uint64_t k;                          /* most crossings of a word */
    uint32_t root_cols, cols, levels;
    uint64_t image_pixels;
} index_oracle;

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

static void oracle_build(const hpfc_file *f, index_oracle *o)
{
    memset(o, 0, sizeof *o);
    hpfc_file_info info;
    hpfc_file_get_info(f, &info);
    o->levels = info.levels, o->root_cols = info.root_cols, o->cols = info.cols;
    o->image_pixels = (uint64_t)info.cols * info.rows;
    uint64_t pixels = 0;
    for (uint32_t l = 0; l < info.levels; l++) {
        hpfc_level_info lv;
        CHECK_EQ_INT(hpfc_file_get_level(f, l, &lv), HPFC_OK);
        /* crossings a slot holds; compact layout: a crossing costs >= 1 bit */
        uint64_t k = info.incompat_flags & 1 ? lv.word_bits
                     : lv.word_bits >= 4      ? (lv.word_bits - 4) / 4
                                              : 0;
        o->k = k > o->k ? k : o->k;
        o->first[l] = pixels;
        pixels += l ? lv.images * o->image_pixels : (uint64_t)info.root_cols * info.root_rows;
        o->images[l] = malloc((lv.images + 1) * sizeof(uint64_t));
    }
    o->first[info.levels] = pixels;
    hpfc_pixel px;
    for (int st = hpfc_leaf_first(f, &px); !st; st = hpfc_leaf_next(f, &px))
        for (uint32_t l = 1; l <= px.depth; l++) { /* an image's first leaf: its pixel (0, 0) */
            bool first = px.path[l].i == 0 && px.path[l].j == 0;
            for (uint32_t d = l + 1; d <= px.depth; d++)
                first = first && px.path[d].i == 0 && px.path[d].j == 0;
            if (first)
                o->images[l][o->count[l]++] = px.path[l].image;
        }
    for (uint32_t l = 1; l < info.levels; l++) {
        hpfc_level_info lv;
        hpfc_file_get_level(f, l, &lv);
        CHECK_EQ_INT(o->count[l], lv.images);
        qsort(o->images[l], o->count[l], sizeof(uint64_t), cmp_u64);
    }
}

static void oracle_free(index_oracle *o)
{
    for (uint32_t l = 0; l < o->levels; l++)
        free(o->images[l]);
}

/* pixel id * K + local, as hpfc.h defines it. */
static uint64_t oracle_index(const index_oracle *o, const hpfc_pixel *px, uint32_t local)
{
    uint32_t l = px->depth;
    uint64_t rank = 0;
    if (l > 0) {
        const uint64_t *at =
            bsearch(&px->path[l].image, o->images[l], o->count[l], sizeof(uint64_t), cmp_u64);
        CHECK(at != NULL);
        rank = at ? (uint64_t)(at - o->images[l]) : 0;
    }
    uint64_t pixel = o->first[l] + rank * o->image_pixels +
                     (uint64_t)px->path[l].j * (l ? o->cols : o->root_cols) + px->path[l].i;
    return pixel * o->k + local;
}

static int cmp_pair(const void *a, const void *b)
{
    const uint64_t *x = a, *y = b;
    return x[0] != y[0] ? (x[0] > y[0]) - (x[0] < y[0]) : (x[1] > y[1]) - (x[1] < y[1]);
}

/* Distinct keys with one index: pairs (index, key) sorted. */
static size_t shared_indices(uint64_t *pairs, size_t n)
{
    size_t shared = 0;
    qsort(pairs, n, 2 * sizeof(uint64_t), cmp_pair);
    for (size_t x = 1; x < n; x++)
        shared += pairs[2 * x] == pairs[2 * x - 2] && pairs[2 * x + 1] != pairs[2 * x - 1];
    return shared;
}

static int indexed_op(hpfc_walker *w, uint64_t key, int op, uint64_t *out, uint64_t *index)
{
    switch (op) {
    case 0:
        return hpfc_key_twin_indexed(w, key, out, index);
    case 1:
        return hpfc_key_next_indexed(w, key, out, index);
    default:
        return hpfc_key_prev_indexed(w, key, out, index);
    }
}

/* hpfc_dart_index / hpfc_vertex_index of every dart and origin vertex, on
 * walkers with the cache off, tiny (emptied mid-walk) and default, cold then
 * warm, with dart operators in between (entries reached by pixel paths):
 * below the bound, equal to the documented formula on the paths
 * hpfc_dart_from_key / hpfc_vertex_from_key give, distinct for distinct
 * keys; the _indexed operators give the key operators' answers and their
 * results' indices; keys naming nothing give HPFC_E_ARG. */
static void check_indices(const hpfc_file *f, const hpfc_dart *darts, const uint64_t *want,
                          size_t n)
{
    static const size_t sizes[] = {0, 700, HPFC_WALKER_DEFAULT_CACHE};
    index_oracle o;
    oracle_build(f, &o);
    hpfc_walker *ref;
    CHECK_EQ_INT(hpfc_walker_create(f, &ref), HPFC_OK);
    uint64_t *expect = malloc((2 * n + 1) * sizeof *expect); /* dart, then origin vertex */
    uint64_t *pairs = malloc((4 * n + 2) * sizeof *pairs);
    size_t wrong = 0, differ = 0, over = 0;
    for (size_t x = 0; x < n; x++) {
        uint64_t key = hpfc_dart_key(f, &darts[x]);
        hpfc_dart d;
        hpfc_vertex v;
        wrong += hpfc_dart_from_key(ref, key, &d) != HPFC_OK;
        wrong += hpfc_vertex_from_key(ref, want[KEY_OPS * x + 3], &v) != HPFC_OK;
        expect[2 * x] = oracle_index(&o, &d.pixel, d.crossing);
        expect[2 * x + 1] = oracle_index(&o, &v.pixel, v.local);
    }
    uint64_t dbound = 0, vbound = 0;
    CHECK_EQ_INT(hpfc_key_index_bound(ref, &dbound, &vbound), HPFC_OK);
    CHECK_EQ_INT(dbound, o.first[o.levels] * o.k);
    CHECK_EQ_INT(vbound, dbound);
    for (size_t s = 0; s < sizeof sizes / sizeof *sizes; s++) {
        hpfc_walker *w;
        CHECK_EQ_INT(hpfc_walker_create(f, &w), HPFC_OK);
        CHECK_EQ_INT(hpfc_walker_set_cache_size(w, sizes[s]), HPFC_OK);
        for (int pass = 0; pass < 2; pass++) /* cold, then warm */
            for (size_t k = 0; k < n; k++) {
                size_t x = pass ? n - 1 - k : k;
                uint64_t key = hpfc_dart_key(f, &darts[x]), vkey = want[KEY_OPS * x + 3];
                uint64_t di = UINT64_MAX, vi = UINT64_MAX;
                /* the _indexed operators first: on a cold cache their
                 * results' entries come from links, not from keys */
                for (int op = 0; op < 3; op++) {
                    uint64_t out = 0, oi = UINT64_MAX, ri = UINT64_MAX;
                    int st = indexed_op(w, key, op, &out, &oi);
                    differ += st != HPFC_OK || out != want[KEY_OPS * x + op];
                    differ += hpfc_dart_index(ref, out, &ri) != HPFC_OK || oi != ri;
                }
                if (k % 3 == 0) { /* a dart operator in between */
                    hpfc_dart r;
                    hpfc_dart_next(w, &darts[(x * 7) % n], &r);
                }
                differ += hpfc_dart_index(w, key, &di) != HPFC_OK || di != expect[2 * x];
                differ += hpfc_vertex_index(w, vkey, &vi) != HPFC_OK || vi != expect[2 * x + 1];
                over += di >= dbound || vi >= vbound;
                pairs[2 * x] = di, pairs[2 * x + 1] = key;
                pairs[2 * (n + x)] = vi + (UINT64_MAX / 2), pairs[2 * (n + x) + 1] = vkey;
                /* nothing there: a crossing or vertex past the word's */
                uint64_t bad = 0;
                differ += hpfc_dart_index(w, key | 0xFFFFF, &bad) != HPFC_E_ARG;
                differ += hpfc_vertex_index(w, vkey | 0xFFFFF, &bad) != HPFC_E_ARG;
                differ += hpfc_key_next_indexed(w, key | 0xFFFFF, &bad, &bad) != HPFC_E_ARG;
            }
        CHECK_EQ_INT(shared_indices(pairs, 2 * n), 0); /* vertices shifted apart from darts */
        uint64_t out, idx;
        hpfc_file_info info;
        hpfc_file_get_info(f, &info);
        CHECK_EQ_INT(hpfc_dart_index(w, (info.file_size * 8) << 20, &idx), HPFC_E_ARG);
        CHECK_EQ_INT(hpfc_vertex_index(w, UINT64_MAX, &idx), HPFC_E_ARG);
        CHECK_EQ_INT(hpfc_dart_index(w, 0, &idx), HPFC_E_ARG);
        CHECK_EQ_INT(hpfc_dart_index(NULL, want[1], &idx), HPFC_E_ARG);
        CHECK_EQ_INT(hpfc_dart_index(w, want[1], NULL), HPFC_E_ARG);
        CHECK_EQ_INT(hpfc_key_twin_indexed(w, want[1], &out, NULL), HPFC_E_ARG);
        CHECK_EQ_INT(hpfc_key_prev_indexed(w, want[1], NULL, &idx), HPFC_E_ARG);
        CHECK_EQ_INT(hpfc_key_index_bound(w, NULL, &idx), HPFC_E_ARG);
        hpfc_walker_free(w);
    }
    CHECK_EQ_INT(wrong, 0);
    CHECK_EQ_INT(differ, 0);
    CHECK_EQ_INT(over, 0);
    free(expect), free(pairs);
    hpfc_walker_free(ref);
    oracle_free(&o);
}

/* Cache sizes for keys: off, tiny (emptied again and again mid-walk),
 * small, default. */
static void check_keys(const hpfc_file *f, size_t nd)
{
    static const size_t sizes[] = {0, 700, 2048, HPFC_WALKER_DEFAULT_CACHE};
    hpfc_walker *plain;
    CHECK_EQ_INT(hpfc_walker_create(f, &plain), HPFC_OK);
    CHECK_EQ_INT(hpfc_walker_set_cache_size(plain, 0), HPFC_OK);
    hpfc_dart *darts = malloc((nd + 1) * sizeof *darts);
    size_t n = collect_darts(f, plain, darts, nd);
    CHECK_EQ_INT(n, nd);
    uint64_t *want = malloc((KEY_OPS * n + 1) * sizeof *want);
    size_t failed = 0;
    for (size_t k = 0; k < n; k++)
        for (int op = 0; op < KEY_OPS; op++)
            failed += dart_op_key(plain, f, &darts[k], op, &want[KEY_OPS * k + op]) != HPFC_OK;
    CHECK_EQ_INT(failed, 0);
    for (size_t s = 0; n && s < sizeof sizes / sizeof *sizes; s++)
        check_keys_with(f, darts, want, n, sizes[s]);
    if (n)
        check_indices(f, darts, want, n);
    free(want), free(darts);
    hpfc_walker_free(plain);
}

/* The three answer sources agree (libhpfcfile/topo.h, "Three answer
 * sources"): every operator on every dart gives the same answer and status
 * without the cache, through caches of every size (also emptied under the
 * walk, also reached by altered paths and interleaved with another walker)
 * and through keys, cold and warm (warm: from the key blocks). */
static void check_three_sources(const hpfc_file *f, size_t nd)
{
    check_cache_sizes(f, nd);
    check_interleaved(f, nd, 2048);
    check_interleaved(f, nd, HPFC_WALKER_DEFAULT_CACHE);
    check_altered_paths(f, nd);
    check_keys(f, nd);
}

static void test_three_sources(void)
{
    CHECK_EQ_INT(hpfc_walker_set_cache_size(NULL, 1024), HPFC_E_ARG);
    for (uint64_t seed = 1; seed <= 2; seed++) {
        hpfc_graph *g = NULL;
        CHECK_EQ_INT(seed == 1 ? gen_delaunay(seed, 300, 1 << 16, 0.2, &g)
                               : gen_polyline(seed, 300, 1 << 16, 0.5, &g), HPFC_OK);
        static const uint32_t shapes[][2] = {{1, 2}, {4, 2}, {5, 3}};
        for (size_t s = 0; g && s < sizeof shapes / sizeof *shapes; s++) {
            uint8_t *buf;
            hpfc_file *f = pack(g, shapes[s][0], shapes[s][1], 0, &buf);
            size_t nd = 2 * hpfc_graph_edge_count(g);
            if (f)
                check_three_sources(f, nd);
            hpfc_close(f);
            hpfc_free(buf);
        }
        hpfc_graph_free(g);
    }
}

/* A dart or vertex whose pixel path names no pixel of the file has no key:
 * HPFC_KEY_INVALID, never the key of slot 0 (or of any slot); the key
 * operators refuse that key. */
static void test_invalid_keys(void)
{
    hpfc_graph *g = NULL;
    CHECK_EQ_INT(gen_delaunay(3, 40, 1 << 16, 0.2, &g), HPFC_OK);
    uint8_t *buf;
    hpfc_file *f = pack(g, 4, 2, 0, &buf);
    CHECK(f != NULL);
    hpfc_walker *w;
    CHECK_EQ_INT(hpfc_walker_create(f, &w), HPFC_OK);
    hpfc_dart darts[1];
    CHECK_EQ_INT(collect_darts(f, w, darts, 1), 1);
    hpfc_dart d = darts[0];
    hpfc_vertex v = {d.pixel, 0};
    CHECK(hpfc_dart_key(f, &d) != HPFC_KEY_INVALID);
    hpfc_file_info info;
    hpfc_file_get_info(f, &info);
    hpfc_dart off_grid = d, too_deep = d;
    off_grid.pixel.path[off_grid.pixel.depth].i = d.pixel.depth ? info.cols : info.root_cols;
    too_deep.pixel.depth = HPFC_MAX_LEVELS; /* a path longer than any file's */
    hpfc_vertex off_grid_v = {off_grid.pixel, 0};
    CHECK(hpfc_dart_key(f, &off_grid) == HPFC_KEY_INVALID);
    CHECK(hpfc_dart_key(f, &too_deep) == HPFC_KEY_INVALID);
    CHECK(hpfc_vertex_key(f, &off_grid_v) == HPFC_KEY_INVALID);
    CHECK(hpfc_vertex_key(f, &v) != HPFC_KEY_INVALID);
    CHECK(hpfc_dart_key(f, NULL) == HPFC_KEY_INVALID);
    CHECK(hpfc_dart_key(NULL, &d) == HPFC_KEY_INVALID);
    CHECK(hpfc_vertex_key(NULL, &v) == HPFC_KEY_INVALID);
    /* the operators on the same values fail as they always did */
    hpfc_dart out;
    CHECK_EQ_INT(hpfc_dart_twin(w, &off_grid, &out), HPFC_E_ARG);
    uint64_t k;
    hpfc_dart back;
    CHECK_EQ_INT(hpfc_key_twin(w, HPFC_KEY_INVALID, &k), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_key_origin(w, HPFC_KEY_INVALID, &k), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_dart_from_key(w, HPFC_KEY_INVALID, &back), HPFC_E_ARG);
    hpfc_walker_free(w);
    hpfc_close(f);
    free(buf);
    hpfc_graph_free(g);
}

/* The oracle itself must reject a map that differs from the graph. */
static void test_oracle_detects_difference(void)
{
    hpfc_graph *g = NULL;
    CHECK_EQ_INT(gen_delaunay(5, 60, 1 << 16, 0.2, &g), HPFC_OK);
    graph_map gm;
    graph_map_build(g, &gm);
    uint8_t *buf;
    hpfc_file *f = pack(g, 4, 2, 0, &buf);
    exported_map fm;
    int st = export_map(f, &fm);
    CHECK_EQ_INT(st, HPFC_OK);
    if (st)
        return;
    uint32_t t = fm.next[0];  /* swap two next links: a different map */
    fm.next[0] = fm.next[1];
    fm.next[1] = t;
    CHECK(isomorphism_failures(&fm, &gm) > 0);
    exported_map_free(&fm);
    hpfc_close(f);
    hpfc_free(buf);
    graph_map_free(&gm);
    hpfc_graph_free(g);
}

int main(void)
{
    test_layout_compact = check_use_test_layout();
    test_oracle_detects_difference();
    test_generated();
    test_road_with_many_leaves();
    test_three_sources();
    test_invalid_keys();
    return check_report("topo");
}
