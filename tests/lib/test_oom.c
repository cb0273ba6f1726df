/*
 * test_oom: every allocation of opening a file and of the shapes queries
 * made to fail in turn.
 *
 * This program is linked with -Wl,--wrap=malloc,--wrap=calloc,
 * --wrap=realloc (tests/meson.build), so that every allocation of the
 * library's archive passes through the wrappers below. While a countdown
 * runs, the n-th allocation returns NULL, once. For each query and each n,
 * until the query makes fewer than n allocations:
 *   - the call answers HPFC_OK (a fallback took over) or HPFC_E_NOMEM, and
 *     never crashes or leaks (ASan in CI);
 *   - the same object then answers the query, and every other, exactly as
 *     an object that never saw a failure does: no half-built state stays
 *     behind in the object's lazily made parts (the window's marks, the
 *     topology's vertex index, the nearest-edge search, the edges read on
 *     first use).
 * Besides the shapes queries: the walker's darts and its cache, numbering
 * the faces, verifying LABL, SHIX and GEOM, point location and writing
 * the file again; and parsing, building and writing a .pfc, and a build
 * in two parts joined (the same bytes as the whole build).
 * The oracle is the same query on an object that never failed, compared
 * through a hash of every byte of the answer (ids, flags, points,
 * lengths) and its status.
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "gen.h"
#include "hpfc.h"
#include "hpfc_batch.h"

/* ---- the allocation wrappers ------------------------------------------------------ */

void *__real_malloc(size_t n);
void *__real_calloc(size_t count, size_t size);
void *__real_realloc(void *p, size_t n);

static long countdown = -1; /* allocations before the failing one; -1: none fails */
static int fired;           /* the countdown's failure happened */

static int allocation_fails(void)
{
    if (countdown < 0)
        return 0;
    if (countdown-- > 0)
        return 0;
    fired = 1;
    return 1;
}

void *__wrap_malloc(size_t n)
{
    return allocation_fails() ? NULL : __real_malloc(n);
}

void *__wrap_calloc(size_t count, size_t size)
{
    return allocation_fails() ? NULL : __real_calloc(count, size);
}

void *__wrap_realloc(void *p, size_t n)
{
    return allocation_fails() ? NULL : __real_realloc(p, n);
}

static void fail_at(long n)
{
    countdown = n;
    fired = 0;
}

static void fail_none(void)
{
    countdown = -1;
}

/* ---- answers as hashes ------------------------------------------------------------ */

static uint64_t mix(uint64_t h, const void *p, size_t n)
{
    const unsigned char *b = p;
    for (size_t k = 0; k < n; k++)
        h = (h ^ b[k]) * UINT64_C(0x100000001b3);
    return h;
}

static uint64_t mix_u64(uint64_t h, uint64_t v)
{
    return mix(h, &v, sizeof v);
}

static uint64_t mix_polygons(uint64_t h, const hpfc_polygons *p)
{
    h = mix_u64(h, p->polygon_count);
    h = mix_u64(h, p->ring_count);
    h = mix_u64(h, p->point_count);
    if (p->polygon_count)
        h = mix(h, p->polygon_ring, (p->polygon_count + 1) * sizeof *p->polygon_ring);
    if (p->ring_count)
        h = mix(h, p->ring_point, (p->ring_count + 1) * sizeof *p->ring_point);
    return p->point_count ? mix(h, p->xy, 2 * p->point_count * sizeof *p->xy) : h;
}

/* ---- the queries ------------------------------------------------------------------ */

typedef struct map {
    const char *name;
    uint8_t *bytes;
    size_t size;
    hpfc_file *f;
    uint64_t faces;
    uint32_t features, layers;
    int64_t box[4]; /* the domain: x0, y0, x1, y1 */
} map;

/* What a query works with, made afresh for each allocation failed and
 * kept for the queries after it: a shapes object and a walker (with its
 * cache of words). */
typedef struct ctx {
    hpfc_shapes *s;
    hpfc_walker *w;
} ctx;

/* A query: its answers folded into *h, the first failing status
 * returned (the query goes on after a status that is not HPFC_E_NOMEM,
 * which the hash records). */
typedef int (*query)(const map *m, ctx *c, uint64_t *h);

/* The status folded in; HPFC_E_NOMEM stops the query. */
static int took(uint64_t *h, int st)
{
    *h = mix_u64(*h, (uint64_t)(int64_t)st);
    return st == HPFC_E_NOMEM ? st : HPFC_OK;
}

static int q_faces(const map *m, ctx *c, uint64_t *h)
{
    hpfc_shapes *s = c->s;
    for (uint64_t f = 0; f < m->faces; f++) {
        hpfc_polygons p;
        int st = hpfc_shapes_face_polygons(s, f, &p);
        if (took(h, st))
            return st;
        if (!st)
            *h = mix_polygons(*h, &p);
    }
    return HPFC_OK;
}

static int q_features(const map *m, ctx *c, uint64_t *h)
{
    hpfc_shapes *s = c->s;
    uint8_t kinds[16];
    uint64_t counts[16];
    int st = hpfc_shapes_layer_kinds(s, kinds, counts, m->layers);
    if (took(h, st))
        return st;
    if (!st)
        *h = mix(mix(*h, kinds, m->layers), counts, m->layers * sizeof *counts);
    for (uint32_t k = 0; k < m->features; k++) {
        hpfc_polygons p;
        hpfc_id faces[256];
        size_t n = 0;
        if (took(h, st = hpfc_shapes_feature_polygons(s, k, &p)))
            return st;
        if (!st)
            *h = mix_polygons(*h, &p);
        if (took(h, st = hpfc_shapes_feature_polylines(s, k, &p)))
            return st;
        if (!st)
            *h = mix_polygons(*h, &p);
        if (took(h, st = hpfc_shapes_feature_faces(s, k, faces, 256, &n)))
            return st;
        if (!st)
            *h = mix(*h, faces, n * sizeof *faces);
    }
    return HPFC_OK;
}

static int q_windows(const map *m, ctx *c, uint64_t *h)
{
    hpfc_shapes *s = c->s;
    int64_t w = m->box[2] - m->box[0], t = m->box[3] - m->box[1];
    const int64_t windows[3][4] = {
        {m->box[0], m->box[1], m->box[2], m->box[3]},
        {m->box[0] + w / 4, m->box[1] + t / 4, m->box[0] + w / 2, m->box[1] + t / 2},
        {m->box[0] + w / 3, m->box[1] + t / 3, m->box[0] + w / 3, m->box[1] + t / 3},
    };
    unsigned what = HPFC_WINDOW_FACES | HPFC_WINDOW_EDGES;
    if (m->features)
        what |= HPFC_WINDOW_FEATURES;
    for (int k = 0; k < 3; k++) {
        hpfc_window_hits r;
        const int64_t *b = windows[k];
        int st = hpfc_shapes_window(s, b[0], b[1], b[2], b[3], what, &r);
        if (took(h, st))
            return st;
        if (st)
            continue;
        *h = mix_u64(mix_u64(mix_u64(*h, r.face_count), r.edge_count), r.feature_count);
        *h = mix(*h, r.face, r.face_count * sizeof *r.face);
        *h = mix(*h, r.face_inside, r.face_count);
        *h = mix(*h, r.edge, r.edge_count * sizeof *r.edge);
        *h = mix(*h, r.edge_inside, r.edge_count);
        *h = mix(*h, r.feature, r.feature_count * sizeof *r.feature);
        *h = mix(*h, r.feature_inside, r.feature_count);
    }
    return HPFC_OK;
}

static int q_topology(const map *m, ctx *c, uint64_t *h)
{
    hpfc_shapes *s = c->s;
    int st;
    for (uint32_t k = 0; k < m->features; k++) {
        hpfc_neighbours nb;
        if (took(h, st = hpfc_shapes_feature_neighbours(s, k, &nb)))
            return st;
        if (st)
            continue;
        *h = mix_u64(*h, nb.count);
        *h = mix(*h, nb.feature, nb.count * sizeof *nb.feature);
        *h = mix(*h, nb.touch, nb.count);
        *h = mix(*h, nb.length, nb.count * sizeof *nb.length);
        *h = mix(*h, nb.edge_start, (nb.count + 1) * sizeof *nb.edge_start);
        *h = mix(*h, nb.edge, nb.edge_start[nb.count] * sizeof *nb.edge);
    }
    hpfc_adjacency adj;
    if (took(h, st = hpfc_shapes_adjacency(s, HPFC_TOUCH_EDGE | HPFC_TOUCH_VERTEX, &adj)))
        return st;
    if (!st) {
        *h = mix_u64(*h, adj.count);
        *h = mix(*h, adj.a, adj.count * sizeof *adj.a);
        *h = mix(*h, adj.b, adj.count * sizeof *adj.b);
        *h = mix(*h, adj.touch, adj.count);
        *h = mix(*h, adj.length, adj.count * sizeof *adj.length);
    }
    hpfc_id all[64];
    uint32_t n = m->features < 64 ? m->features : 64;
    for (uint32_t k = 0; k < n; k++)
        all[k] = k;
    hpfc_polygons p;
    if (took(h, st = hpfc_shapes_features_polygons(s, all, n, &p)))
        return st;
    if (!st)
        *h = mix_polygons(*h, &p);
    if (took(h, st = hpfc_shapes_mesh(s, NULL, m->features,
                                      HPFC_MESH_INTERIOR | HPFC_MESH_EXTERIOR, &p)))
        return st;
    if (!st)
        *h = mix_polygons(*h, &p);
    return HPFC_OK;
}

static int q_nearest(const map *m, ctx *c, uint64_t *h)
{
    hpfc_shapes *s = c->s;
    int64_t cx = m->box[0] + (m->box[2] - m->box[0]) / 3;
    int64_t cy = m->box[1] + (m->box[3] - m->box[1]) / 2;
    int st;
    for (uint64_t k = 0; k <= m->features && k < 8; k++) {
        hpfc_nearest r;
        hpfc_id feature = k == 0 ? HPFC_ID_NONE : k - 1;
        if (took(h, st = hpfc_shapes_nearest_edge(s, cx, cy, feature, &r)))
            return st;
        if (!st) {
            *h = mix_u64(mix_u64(*h, r.edge), r.segment);
            *h = mix(*h, &r.distance, sizeof r.distance);
        }
    }
    hpfc_edge_hits e;
    if (took(h, st = hpfc_shapes_edges_within(s, cx, cy, (m->box[2] - m->box[0]) / 4 + 1, &e)))
        return st;
    if (!st) {
        *h = mix_u64(*h, e.count);
        *h = mix(*h, e.edge, e.count * sizeof *e.edge);
        *h = mix(*h, e.distance, e.count * sizeof *e.distance);
    }
    return HPFC_OK;
}

/* The map's darts through the walker: each leaf's vertices and its
 * crossings' darts, with each dart's next, twin and origin. */
static int q_walker(const map *m, ctx *c, uint64_t *h)
{
    (void)m;
    hpfc_pixel px;
    int st = hpfc_leaf_first(m->f, &px);
    for (int leaves = 0; !st && leaves < 64; leaves++) {
        uint32_t nv = 0;
        if (took(h, st = hpfc_pixel_vertex_count(c->w, &px, &nv)))
            return st;
        for (uint32_t v = 0; !st && v < nv; v++) {
            uint64_t key;
            if (took(h, st = hpfc_pixel_vertex_key(c->w, &px, v, &key)))
                return st;
            *h = mix_u64(*h, key);
        }
        size_t len = 0;
        hpfc_pixel_word(m->f, &px, NULL, 0, &len);
        for (uint32_t k = 0; k < len && k < 8; k++) {
            uint64_t d, next, twin, origin;
            if (took(h, st = hpfc_pixel_dart_key(c->w, &px, k, &d)))
                return st;
            if (st)
                break;
            if (took(h, st = hpfc_key_next(c->w, d, &next)) ||
                took(h, st = hpfc_key_twin(c->w, d, &twin)) ||
                took(h, st = hpfc_key_origin(c->w, d, &origin)))
                return st;
            *h = mix_u64(mix_u64(mix_u64(mix_u64(*h, d), next), twin), origin);
        }
        st = hpfc_leaf_next(m->f, &px);
    }
    return HPFC_OK;
}

/* The file's own answers, made afresh by each call: faces numbered and
 * checked against LABL, the index and geometry verified, points located,
 * the file written again. */
static int q_file(const map *m, ctx *c, uint64_t *h)
{
    (void)c;
    hpfc_faces *faces = NULL;
    int st = hpfc_faces_build(m->f, &faces);
    if (took(h, st))
        return st;
    if (!st) {
        hpfc_labels_report lr;
        *h = mix_u64(*h, hpfc_faces_face_count(faces));
        st = hpfc_labels_verify(m->f, faces, &lr);
        hpfc_faces_free(faces);
        if (took(h, st))
            return st;
        *h = mix_u64(mix_u64(*h, lr.leaves_checked), lr.labels_checked);
    }
    hpfc_index_report ir;
    if (took(h, st = hpfc_index_verify(m->f, &ir)))
        return st;
    *h = mix_u64(*h, ir.rows_checked);
    hpfc_geometry_report gr;
    if (took(h, st = hpfc_geometry_verify(m->f, &gr)))
        return st;
    *h = mix_u64(mix_u64(*h, gr.vertices_checked), gr.crossings_checked);
    for (int i = 0; i < 5; i++)
        for (int j = 0; j < 5; j++) {
            int64_t x = m->box[0] + (m->box[2] - m->box[0]) * i / 4;
            int64_t y = m->box[1] + (m->box[3] - m->box[1]) * j / 4;
            hpfc_point_location loc;
            hpfc_id found[16];
            size_t n = 0;
            if (took(h, st = hpfc_locate_point(m->f, x, y, &loc, found, 16, &n)))
                return st;
            if (!st)
                *h = mix(mix_u64(*h, (uint64_t)loc.on_boundary), found, n * sizeof *found);
        }
    /* enough points for the batch's Morton order (and its fallback) */
    enum { NB = 100 };
    int64_t bx[NB], by[NB], face[NB], feature[NB];
    uint32_t face_count[NB], feature_count[NB];
    uint8_t flags[NB], depth[NB];
    for (int k = 0; k < NB; k++) {
        bx[k] = m->box[0] + (m->box[2] - m->box[0]) * ((k * 37) % NB) / NB;
        by[k] = m->box[1] + (m->box[3] - m->box[1]) * ((k * 61) % NB) / NB;
    }
    hpfc_locate_out lo = {.face = face, .face_count = face_count, .feature = feature,
                          .feature_count = feature_count, .flags = flags, .depth = depth};
    if (took(h, st = hpfc_locate_batch(m->f, NULL, NB, bx, by, NULL, &lo, NULL)))
        return st;
    if (!st) {
        *h = mix(mix(*h, face, sizeof face), feature, sizeof feature);
        *h = mix(mix(*h, face_count, sizeof face_count), feature_count, sizeof feature_count);
        *h = mix(mix(*h, flags, sizeof flags), depth, sizeof depth);
    }
    uint8_t *out = NULL;
    size_t size = 0;
    if (took(h, st = hpfc_file_serialize(m->f, NULL, &out, &size, NULL)))
        return st;
    if (!st)
        *h = mix(*h, out, size);
    hpfc_free(out);
    return HPFC_OK;
}

static int q_all(const map *m, ctx *c, uint64_t *h)
{
    static const query each[] = {q_windows, q_faces,  q_features, q_topology,
                                 q_nearest, q_walker, q_file};
    for (size_t k = 0; k < sizeof each / sizeof *each; k++) {
        int st = each[k](m, c, h);
        if (st)
            return st;
    }
    return HPFC_OK;
}

/* ---- the campaigns ---------------------------------------------------------------- */

static int ctx_make(const map *m, ctx *c)
{
    c->s = NULL, c->w = NULL;
    int st = hpfc_shapes_create(m->f, &c->s);
    if (!st)
        st = hpfc_walker_create(m->f, &c->w);
    return st;
}

static void ctx_free(ctx *c)
{
    hpfc_shapes_free(c->s);
    hpfc_walker_free(c->w);
}

static uint64_t answer(const map *m, query q, ctx *c)
{
    uint64_t h = UINT64_C(0xcbf29ce484222325);
    int st = q(m, c, &h);
    CHECK_EQ_INT(st, HPFC_OK); /* nothing fails: HPFC_E_NOMEM would stop it */
    return h;
}

/* The query with its n-th allocation failing, for every n, each with a
 * fresh shapes object and walker, then again with none failing: the
 * answer of objects that never failed; and then every query, in case the
 * failure left another's state half made. */
static void campaign(const map *m, const char *what, query q)
{
    ctx c;
    CHECK_EQ_INT(ctx_make(m, &c), HPFC_OK);
    uint64_t want = answer(m, q, &c), want_all = answer(m, q_all, &c);
    ctx_free(&c);
    long n;
    for (n = 0; n < 100000; n++) {
        if (ctx_make(m, &c) != HPFC_OK) {
            CHECK(0);
            ctx_free(&c);
            return;
        }
        uint64_t h = 0;
        fail_at(n);
        int st = q(m, &c, &h);
        fail_none();
        int done = !fired;
        if (st != HPFC_OK && st != HPFC_E_NOMEM) {
            CHECK(0);
            fprintf(stderr, "%s %s: allocation %ld failing gives %s\n", m->name, what, n,
                    hpfc_strerror(st));
        }
        uint64_t again = answer(m, q, &c), all = answer(m, q_all, &c);
        if (again != want || all != want_all) {
            CHECK(0);
            fprintf(stderr, "%s %s: after allocation %ld failed the answers differ (%s)\n",
                    m->name, what, n, again != want ? "the same query" : "the other queries");
        }
        ctx_free(&c);
        if (done)
            break;
    }
    CHECK(n < 100000);
    printf("%s %s: %ld allocations failed in turn\n", m->name, what, n);
}

/* hpfc_open_memory, hpfc_shapes_create and hpfc_walker_create with their
 * n-th allocation failing: HPFC_E_NOMEM and nothing kept (ASan's leak
 * check), or objects that answer as they should. */
static void campaign_open(const map *m)
{
    ctx c;
    CHECK_EQ_INT(ctx_make(m, &c), HPFC_OK);
    uint64_t want = answer(m, q_all, &c);
    ctx_free(&c);
    long n;
    for (n = 0; n < 100000; n++) {
        hpfc_file *f = NULL;
        c.s = NULL, c.w = NULL;
        fail_at(n);
        int st = hpfc_open_memory(m->bytes, m->size, 0, &f);
        if (!st) {
            map fm = *m;
            fm.f = f;
            st = ctx_make(&fm, &c);
        }
        fail_none();
        int done = !fired;
        CHECK(st == HPFC_OK || st == HPFC_E_NOMEM);
        if (!st) {
            map fm = *m;
            fm.f = f;
            if (answer(&fm, q_all, &c) != want) {
                CHECK(0);
                fprintf(stderr, "%s open: allocation %ld failing changes the answers\n", m->name,
                        n);
            }
        }
        ctx_free(&c);
        hpfc_close(f);
        if (done)
            break;
    }
    printf("%s open and create: %ld allocations failed in turn\n", m->name, n);
}

/* Tree t, built from g, written with its labels and geometry: the bytes
 * hashed, or 0 with the status in *st. */
static uint64_t tree_hash(const hpfc_tree *t, const hpfc_graph *g, int layout, int *st)
{
    uint8_t *out = NULL;
    size_t size = 0;
    hpfc_write_options o = {.face_labels = 1, .geometry = g, .layout = layout};
    *st = hpfc_tree_serialize(t, &o, &out, &size, NULL);
    uint64_t h = *st ? 0 : mix(UINT64_C(0xcbf29ce484222325), out, size);
    hpfc_free(out);
    return h;
}

/* A .pfc text parsed, built and written with its labels and geometry
 * (the builder and the writer): the file's bytes hashed, or 0 with the
 * status in *status. */
static uint64_t build_once(const char *text, size_t len, int layout, int *status)
{
    hpfc_graph *g = NULL;
    hpfc_tree *t = NULL;
    uint64_t h = 0;
    hpfc_build_params bp;
    hpfc_build_params_default(&bp);
    int st = hpfc_pfc_parse(text, len, &g, NULL);
    if (!st)
        st = hpfc_build(g, &bp, &t, NULL);
    if (!st)
        h = tree_hash(t, g, layout, &st);
    hpfc_tree_free(t);
    hpfc_graph_free(g);
    *status = st;
    return h;
}

/* Building and writing with their n-th allocation failing:
 * HPFC_E_NOMEM and nothing kept, or the same bytes. */
static void campaign_build(const char *name, int layout)
{
    const char *root = getenv("HPFC_TEST_DATA");
    char path[1024];
    snprintf(path, sizeof path, "%s/valid/%s", root ? root : "tests/data", name);
    FILE *fp = fopen(path, "rb");
    CHECK(fp != NULL);
    if (!fp)
        return;
    char text[65536];
    size_t len = fread(text, 1, sizeof text, fp);
    fclose(fp);
    int st;
    uint64_t want = build_once(text, len, layout, &st);
    CHECK_EQ_INT(st, HPFC_OK);
    long n;
    for (n = 0; n < 100000; n++) {
        fail_at(n);
        uint64_t h = build_once(text, len, layout, &st);
        fail_none();
        CHECK(st == HPFC_OK || st == HPFC_E_NOMEM);
        if (!st && h != want) {
            CHECK(0);
            fprintf(stderr, "%s build: allocation %ld failing changes the bytes\n", name, n);
        }
        if (!fired)
            break;
    }
    printf("%s build and write (layout %d): %ld allocations failed in turn\n", name, layout, n);
}

/* A generated map built in two parts (the west and east halves of a 4 x
 * 4 root) from one cut, joined and written: the bytes hashed, or 0 with
 * the status in *status. */
static uint64_t build_parts_once(const hpfc_graph *g, const hpfc_build_params *p, int *status)
{
    int64_t box[4];
    hpfc_domain d;
    uint32_t owner[16], pixels[2][8], n[2] = {0, 0};
    for (uint32_t px = 0; px < 16; px++) {
        owner[px] = px % 4 >= 2;
        pixels[owner[px]][n[owner[px]]++] = px;
    }
    hpfc_cut *cut = NULL;
    hpfc_tree *parts[2] = {NULL, NULL}, *joined = NULL;
    uint64_t h = 0;
    int st = hpfc_graph_bounds(g, box);
    if (!st)
        st = hpfc_build_domain(box, p, &d, NULL);
    if (!st)
        st = hpfc_cut_create(g, p, &d, owner, 2, &cut, NULL);
    for (uint32_t k = 0; k < 2 && !st; k++) {
        hpfc_graph *pg = NULL;
        uint32_t *ids = NULL;
        st = hpfc_cut_part_graph(cut, k, &pg, &ids, NULL);
        hpfc_part part = {.domain = d, .root_pixels = pixels[k], .root_pixel_count = n[k],
                          .edge_ids = ids, .edge_count = hpfc_graph_edge_count(g)};
        if (!st)
            st = hpfc_build_part(pg, p, &part, &parts[k], NULL);
        hpfc_graph_free(pg);
        hpfc_free(ids);
    }
    if (!st)
        st = hpfc_tree_merge(parts, 2, &joined, NULL);
    if (!st)
        h = tree_hash(joined, g, HPFC_LAYOUT_COMPACT, &st);
    hpfc_tree_free(joined);
    hpfc_tree_free(parts[0]);
    hpfc_tree_free(parts[1]);
    hpfc_cut_free(cut);
    *status = st;
    return h;
}

/* The build in parts with its n-th allocation failing: HPFC_E_NOMEM and
 * nothing kept, or the bytes of the whole build. */
static void campaign_parts(void)
{
    hpfc_graph *g = NULL;
    CHECK_EQ_INT(gen_delaunay(7, 60, 1 << 12, 0.2, &g), HPFC_OK);
    if (!g)
        return;
    hpfc_build_params p;
    hpfc_build_params_default(&p);
    p.root_cols = p.root_rows = 4, p.cols = p.rows = 2, p.max_leaf_points = 16;
    hpfc_tree *whole = NULL;
    int st;
    CHECK_EQ_INT(hpfc_build(g, &p, &whole, NULL), HPFC_OK);
    uint64_t want = tree_hash(whole, g, HPFC_LAYOUT_COMPACT, &st);
    CHECK_EQ_INT(st, HPFC_OK);
    hpfc_tree_free(whole);
    CHECK(build_parts_once(g, &p, &st) == want);
    long n;
    for (n = 0; n < 1000000; n++) {
        fail_at(n);
        uint64_t h = build_parts_once(g, &p, &st);
        fail_none();
        CHECK(st == HPFC_OK || st == HPFC_E_NOMEM);
        if (!st && h != want) {
            CHECK(0);
            fprintf(stderr, "parts: allocation %ld failing changes the bytes\n", n);
        }
        if (!fired)
            break;
    }
    printf("generated map in two parts: %ld allocations failed in turn\n", n);
    hpfc_graph_free(g);
}

static int load(map *m, const char *name)
{
    const char *root = getenv("HPFC_TEST_DATA");
    char path[1024];
    memset(m, 0, sizeof *m);
    m->name = name;
    snprintf(path, sizeof path, "%s/valid/%s", root ? root : "tests/data", name);
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return -1;
    fseek(fp, 0, SEEK_END);
    long len = ftell(fp);
    fseek(fp, 0, SEEK_SET);
    m->bytes = malloc(len > 0 ? (size_t)len : 1);
    m->size = len > 0 && m->bytes && fread(m->bytes, 1, (size_t)len, fp) == (size_t)len
                  ? (size_t)len
                  : 0;
    fclose(fp);
    if (!m->size || hpfc_open_memory(m->bytes, m->size, 0, &m->f) != HPFC_OK)
        return -1;
    hpfc_shapes *s;
    if (hpfc_shapes_create(m->f, &s) != HPFC_OK)
        return -1;
    m->faces = hpfc_shapes_face_count(s);
    hpfc_shapes_free(s);
    hpfc_features_info fi;
    if (hpfc_file_get_features(m->f, &fi) == HPFC_OK && fi.layers <= 16)
        m->features = fi.features, m->layers = fi.layers;
    hpfc_file_info info;
    hpfc_file_get_info(m->f, &info);
    m->box[0] = info.x0, m->box[1] = info.y0;
    m->box[2] = info.x0 + info.width - 1, m->box[3] = info.y0 + info.height - 1;
    return 0;
}

int main(void)
{
    /* with SHIX (1.3), without (1.2: the inverse tables built in memory),
     * and a map with no features */
    const char *files[] = {"borders_1_3.hpfc", "borders_1_2.hpfc", "two_components_hole_1_3.hpfc"};
    for (size_t k = 0; k < sizeof files / sizeof *files; k++) {
        map m;
        int st = load(&m, files[k]);
        CHECK_EQ_INT(st, 0);
        if (!st) {
            CHECK(m.faces > 1);
            campaign_open(&m);
            campaign(&m, "windows", q_windows);
            campaign(&m, "faces", q_faces);
            campaign(&m, "features", q_features);
            campaign(&m, "topology", q_topology);
            campaign(&m, "nearest", q_nearest);
            campaign(&m, "walker", q_walker);
            campaign(&m, "file", q_file);
        }
        hpfc_close(m.f);
        free(m.bytes);
    }
    campaign_build("two_components_hole.pfc", HPFC_LAYOUT_PAPER);
    campaign_build("two_components_hole.pfc", HPFC_LAYOUT_COMPACT);
    campaign_build("polyline_decimals.pfc", HPFC_LAYOUT_COMPACT);
    campaign_parts();
    return check_report("oom");
}
