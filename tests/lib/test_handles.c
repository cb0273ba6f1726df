/*
 * test_handles.c: the key entry points of handles.c against their path
 * forms. For every leaf, vertex, crossing and dart of generated graphs
 * (with and without the LABL and GEOM sections, under several cache sizes),
 * each key call must give the path-form call's answer converted to a key,
 * and its status: the path form is the oracle. Keys that name nothing and
 * NULL arguments give the documented HPFC_E_ARG.
 */
#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "gen.h"
#include "hpfc.h"

#define KEY_LOW 0xFFFFFu /* the crossing or local id bits of a key (§3.10) */

/* Cache sizes the answers must not depend on: off, tiny, default. */
static const size_t cache_sizes[] = {0, 700, HPFC_WALKER_DEFAULT_CACHE};

typedef struct tally {
    size_t vertices, darts, no_darts, differ;
} tally;

/* ---- the per-dart calls of other modules ------------------------------------------- */

/* Each key form on key against its path form on d (the dart the key names,
 * or NULL when it names none: then HPFC_E_ARG). */
static void compare_dart_calls(hpfc_walker *w, const hpfc_file *f, const hpfc_faces *fc,
                               uint64_t key, const hpfc_dart *d, tally *t)
{
    uint64_t a = 0, b = 0, ea = 0, eb = 0;
    int ra = 0, rb = 0;
    int want, got;
    if (fc) {
        want = d ? hpfc_faces_dart_face(fc, d, &a) : HPFC_E_ARG;
        got = hpfc_faces_key_face(fc, w, key, &b);
        t->differ += want != got || (!got && a != b);
    }
    want = d ? hpfc_label_dart_face(f, d, &a) : HPFC_E_ARG;
    got = hpfc_label_key_face(w, key, &b);
    t->differ += want != got || (!got && a != b);
    want = d ? hpfc_label_dart_edge(f, d, &a) : HPFC_E_ARG;
    got = hpfc_label_key_edge(w, key, &b);
    t->differ += want != got || (!got && a != b);
    want = d ? hpfc_geometry_dart_edge(f, d, &ea, &ra) : HPFC_E_ARG;
    got = hpfc_geometry_key_edge(w, key, &eb, &rb);
    t->differ += want != got || (!got && (ea != eb || ra != rb));
    size_t na = 0, nb = 0;
    want = d ? hpfc_geometry_dart_points(f, d, NULL, 0, &na) : HPFC_E_ARG;
    got = hpfc_geometry_key_points(w, key, NULL, 0, &nb);
    t->differ += want != got || (!got && na != nb);
    if (!want && !got && na > 0) {
        int64_t *pa = malloc(2 * na * sizeof *pa), *pb = malloc(2 * na * sizeof *pb);
        CHECK(pa && pb);
        t->differ += hpfc_geometry_dart_points(f, d, pa, na, &na) != HPFC_OK ||
                     hpfc_geometry_key_points(w, key, pb, nb, &nb) != HPFC_OK ||
                     memcmp(pa, pb, 2 * na * sizeof *pa) != 0;
        /* a cap too small: HPFC_E_BUFFER_SMALL, the count still set */
        nb = 0;
        t->differ += hpfc_geometry_key_points(w, key, pb, na - 1, &nb) != HPFC_E_BUFFER_SMALL || nb != na;
        free(pa), free(pb);
    }
}

/* ---- vertices ----------------------------------------------------------------------- */

/* Vertex key vk (of path-form vertex v) : its degree and every dart, and
 * one past the last, against the path form. */
static void compare_vertex(hpfc_walker *w, const hpfc_file *f, const hpfc_vertex *v,
                           uint64_t vk, tally *t)
{
    uint32_t da = 0, db = 0, dc = 0;
    int want = hpfc_vertex_degree(w, v, &da), got = hpfc_key_degree(w, vk, &db);
    t->differ += want != got || da != db;
    uint64_t all[64] = {0};
    got = hpfc_key_vertex_darts(w, vk, all, 64, &dc);
    t->differ += want != got || da != dc;
    if (dc > 0) /* one short: HPFC_E_BUFFER_SMALL, the degree still given */
        t->differ += hpfc_key_vertex_darts(w, vk, all, dc - 1, &db) != HPFC_E_BUFFER_SMALL || db != dc;
    t->differ += hpfc_key_vertex_darts(w, vk, NULL, 0, &db) != want || db != da;
    for (uint32_t e = 0; e <= da; e++) {
        hpfc_dart d;
        uint64_t dk = 0;
        want = hpfc_vertex_dart(w, v, e, &d);
        got = hpfc_key_vertex_dart(w, vk, e, &dk);
        t->differ += want != got || (!got && dk != hpfc_dart_key(f, &d));
        t->differ += !got && e < 64 && all[e] != dk;
        t->differ += e == da && got != HPFC_E_ARG; /* past the degree */
    }
    t->vertices++;
}

/* The vertices of leaf px: hpfc_pixel_vertex_key against hpfc_pixel_vertex
 * for each index and one past the last. */
static void compare_vertices(hpfc_walker *w, const hpfc_file *f, const hpfc_pixel *px, tally *t)
{
    uint32_t count = 0;
    CHECK_EQ_INT(hpfc_pixel_vertex_count(w, px, &count), HPFC_OK);
    for (uint32_t k = 0; k <= count; k++) {
        hpfc_vertex v;
        uint64_t vk = 0;
        int want = hpfc_pixel_vertex(w, px, k, &v), got = hpfc_pixel_vertex_key(w, px, k, &vk);
        t->differ += want != got || (k == count) != (got == HPFC_E_ARG);
        if (!want && !got) {
            t->differ += vk != hpfc_vertex_key(f, &v);
            compare_vertex(w, f, &v, vk, t);
        }
    }
}

/* ---- darts -------------------------------------------------------------------------- */

static uint32_t word_crossings(const hpfc_file *f, const hpfc_pixel *px)
{
    size_t len = 0;
    CHECK_EQ_INT(hpfc_pixel_word(f, px, NULL, 0, &len), HPFC_OK);
    return len >= 4 ? (uint32_t)(len - 4) : 0;
}

/* Every crossing of leaf px and two past them: hpfc_pixel_dart_key against
 * the path form's {px, k} (a dart when hpfc_dart_origin accepts it), and
 * the per-dart calls on its key; a crossing with no dart gives HPFC_E_ARG
 * both as a pixel crossing and as a key made of the leaf's slot. */
static void compare_darts(hpfc_walker *w, const hpfc_file *f, const hpfc_faces *fc,
                          const hpfc_pixel *px, tally *t)
{
    uint32_t n = word_crossings(f, px);
    hpfc_dart first = {.pixel = *px, .crossing = 0};
    uint64_t slot_key = hpfc_dart_key(f, &first) & ~(uint64_t)KEY_LOW;
    for (uint32_t k = 0; k < n + 2; k++) {
        hpfc_dart d = {.pixel = *px, .crossing = k};
        hpfc_vertex o;
        uint64_t dk = 0;
        int want = hpfc_dart_origin(w, &d, &o), got = hpfc_pixel_dart_key(w, px, k, &dk);
        t->differ += want != got;
        if (!want && !got) {
            t->differ += dk != hpfc_dart_key(f, &d) || dk != (slot_key | k);
            compare_dart_calls(w, f, fc, dk, &d, t);
            t->darts++;
        } else {
            t->differ += got != HPFC_E_ARG;
            compare_dart_calls(w, f, fc, slot_key | k, NULL, t);
            t->no_darts++;
        }
    }
}

/* ---- keys that name nothing, NULL arguments ------------------------------------------- */

static void check_bad_arguments(hpfc_walker *w, const hpfc_file *f, const hpfc_faces *fc)
{
    hpfc_pixel px;
    CHECK_EQ_INT(hpfc_leaf_first(f, &px), HPFC_OK);
    hpfc_dart d0 = {.pixel = px, .crossing = 0};
    uint64_t slot_key = hpfc_dart_key(f, &d0) & ~(uint64_t)KEY_LOW, u = 0;
    hpfc_file_info info;
    hpfc_file_get_info(f, &info);
    /* past the file, a local id past any word, one bit inside the slot */
    const uint64_t nothing[] = {(info.file_size * 8) << 20, UINT64_MAX, slot_key | KEY_LOW,
                                slot_key + ((uint64_t)1 << 20)};
    for (size_t x = 0; x < sizeof nothing / sizeof *nothing; x++) {
        uint64_t key = nothing[x];
        uint32_t deg;
        int64_t xy[2];
        size_t count;
        int reversed;
        CHECK_EQ_INT(hpfc_key_degree(w, key, &deg), HPFC_E_ARG);
        CHECK_EQ_INT(hpfc_key_vertex_dart(w, key, 0, &u), HPFC_E_ARG);
        CHECK_EQ_INT(hpfc_key_vertex_darts(w, key, &u, 1, &deg), HPFC_E_ARG);
        if (fc)
            CHECK_EQ_INT(hpfc_faces_key_face(fc, w, key, &u), HPFC_E_ARG);
        CHECK_EQ_INT(hpfc_label_key_face(w, key, &u), HPFC_E_ARG);
        CHECK_EQ_INT(hpfc_label_key_edge(w, key, &u), HPFC_E_ARG);
        CHECK_EQ_INT(hpfc_geometry_key_edge(w, key, &u, &reversed), HPFC_E_ARG);
        CHECK_EQ_INT(hpfc_geometry_key_points(w, key, xy, 1, &count), HPFC_E_ARG);
    }
    uint32_t deg;
    int reversed;
    size_t count;
    CHECK_EQ_INT(hpfc_pixel_vertex_key(NULL, &px, 0, &u), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_pixel_vertex_key(w, NULL, 0, &u), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_pixel_vertex_key(w, &px, 0, NULL), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_pixel_dart_key(NULL, &px, 0, &u), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_pixel_dart_key(w, NULL, 0, &u), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_pixel_dart_key(w, &px, 0, NULL), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_key_degree(NULL, slot_key, &deg), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_key_degree(w, slot_key, NULL), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_key_vertex_dart(NULL, slot_key, 0, &u), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_key_vertex_dart(w, slot_key, 0, NULL), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_key_vertex_darts(NULL, slot_key, &u, 1, &deg), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_key_vertex_darts(w, slot_key, &u, 1, NULL), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_faces_key_face(NULL, w, slot_key, &u), HPFC_E_ARG);
    if (fc) {
        CHECK_EQ_INT(hpfc_faces_key_face(fc, NULL, slot_key, &u), HPFC_E_ARG);
        CHECK_EQ_INT(hpfc_faces_key_face(fc, w, slot_key, NULL), HPFC_E_ARG);
    }
    CHECK_EQ_INT(hpfc_label_key_face(NULL, slot_key, &u), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_label_key_face(w, slot_key, NULL), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_label_key_edge(NULL, slot_key, &u), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_label_key_edge(w, slot_key, NULL), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_geometry_key_edge(NULL, slot_key, &u, &reversed), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_geometry_key_edge(w, slot_key, NULL, &reversed), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_geometry_key_edge(w, slot_key, &u, NULL), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_geometry_key_points(NULL, slot_key, NULL, 0, &count), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_geometry_key_points(w, slot_key, NULL, 0, NULL), HPFC_E_ARG);
}

/* A refined pixel: the path forms' verdict for the pixel calls, HPFC_E_CORRUPT
 * (its slot is read as a word that is not there). */
static void check_refined_pixel(hpfc_walker *w, const hpfc_file *f)
{
    hpfc_file_info info;
    hpfc_file_get_info(f, &info);
    for (uint32_t r = 0; r < info.root_cols * info.root_rows; r++) {
        hpfc_pixel px;
        int type;
        CHECK_EQ_INT(hpfc_pixel_root(f, r % info.root_cols, r / info.root_cols, &px), HPFC_OK);
        if (hpfc_pixel_type(f, &px, &type) != HPFC_OK || type != HPFC_PIXEL_REFINED)
            continue;
        hpfc_vertex v;
        hpfc_vertex o;
        hpfc_dart d = {.pixel = px, .crossing = 0};
        uint64_t u;
        CHECK_EQ_INT(hpfc_pixel_vertex_key(w, &px, 0, &u), hpfc_pixel_vertex(w, &px, 0, &v));
        CHECK_EQ_INT(hpfc_pixel_dart_key(w, &px, 0, &u), hpfc_dart_origin(w, &d, &o));
        CHECK_EQ_INT(hpfc_pixel_dart_key(w, &px, 0, &u), HPFC_E_CORRUPT);
        CHECK_EQ_INT(hpfc_pixel_vertex_key(w, &px, 0, &u), HPFC_E_CORRUPT);
        return;
    }
}

/* ---- driver --------------------------------------------------------------------------- */

/* Every leaf of f on a walker with each cache size. */
static void check_file(const hpfc_file *f, const char *what)
{
    hpfc_faces *fc = NULL;
    CHECK_EQ_INT(hpfc_faces_build(f, &fc), HPFC_OK);
    for (size_t c = 0; c < sizeof cache_sizes / sizeof *cache_sizes; c++) {
        hpfc_walker *w;
        CHECK_EQ_INT(hpfc_walker_create(f, &w), HPFC_OK);
        CHECK_EQ_INT(hpfc_walker_set_cache_size(w, cache_sizes[c]), HPFC_OK);
        tally t = {0};
        hpfc_pixel px;
        int st;
        for (st = hpfc_leaf_first(f, &px); !st; st = hpfc_leaf_next(f, &px)) {
            compare_vertices(w, f, &px, &t);
            compare_darts(w, f, fc, &px, &t);
        }
        CHECK_EQ_INT(st, HPFC_E_NO_PIXEL);
        if (t.differ)
            fprintf(stderr, "%s, cache %zu: %zu answers differ\n", what, cache_sizes[c], t.differ);
        CHECK_EQ_INT(t.differ, 0);
        CHECK(t.vertices > 0 && t.darts > 0 && t.no_darts > 0);
        check_bad_arguments(w, f, fc);
        check_refined_pixel(w, f);
        hpfc_walker_free(w);
    }
    hpfc_faces_free(fc);
}

/* g packed with root n0 x n0 refined 2 x 2, with LABL and GEOM or without. */
static hpfc_file *pack(const hpfc_graph *g, uint32_t n0, bool sections, uint8_t **buf)
{
    hpfc_build_params p;
    hpfc_build_params_default(&p);
    p.root_cols = p.root_rows = n0;
    hpfc_tree *t = NULL;
    hpfc_file *f = NULL;
    hpfc_write_options opts = {.face_labels = sections, .geometry = sections ? g : NULL};
    size_t size;
    *buf = NULL;
    CHECK_EQ_INT(hpfc_build(g, &p, &t, NULL), HPFC_OK);
    if (t && check_tree_serialize(t, &opts, buf, &size, NULL) == HPFC_OK)
        CHECK_EQ_INT(hpfc_open_memory(*buf, size, 0, &f), HPFC_OK);
    hpfc_tree_free(t);
    return f;
}

static void check_graph(const hpfc_graph *g, const char *what)
{
    static const uint32_t roots[] = {1, 4, 16};
    for (size_t r = 0; r < sizeof roots / sizeof *roots; r++)
        for (int sections = 1; sections >= 0; sections--) {
            if (!sections && r > 0)
                continue; /* one file without sections is enough */
            uint8_t *buf;
            hpfc_file *f = pack(g, roots[r], sections, &buf);
            CHECK(f != NULL);
            if (f)
                check_file(f, what);
            hpfc_close(f);
            free(buf);
        }
}

int main(void)
{
    check_use_test_layout();
    CHECK_EQ_INT(gen_sweep(2, 60, 100, check_graph), HPFC_OK);
    return check_report("handles");
}
