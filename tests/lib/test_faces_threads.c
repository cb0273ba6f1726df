/* Faces numbered on several threads (hpfc_faces_build_threads) against
 * the input graph and against one thread:
 *   - the face count is Euler's, E - V + C + 1, from the input graph (its
 *     connected components counted here by a union-find over the edges);
 *   - every crossing's face and every private leaf's face is the one the
 *     calling thread alone gives, for 1 to 8 threads and runs of 3 to 17
 *     leaves, with the union-find's 32- and 64-bit words;
 *   - a file written with hpfc_write_options.threads (its GEOM planned
 *     on a thread beside the labels) is the same bytes as one written on
 *     one thread;
 *   - mutants of those files (bytes of the pools changed, opened without
 *     the checksum) give, on 3 threads, the status one thread gives, from
 *     the same leaf's failure, and the same faces when they number at all.
 * Built with ThreadSanitizer too (tools/run-tests.sh), where any report
 * fails the run. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "faces.h"
#include "gen.h"
#include "hpfc.h"

/* A map's faces as one list: the face of every crossing's out-dart of every
 * leaf, then of every private leaf, in leaf order (statuses mixed in). */
typedef struct face_list {
    uint64_t *face;
    size_t count, cap;
} face_list;

static void push(face_list *l, uint64_t v)
{
    if (l->count == l->cap) {
        size_t cap = l->cap ? 2 * l->cap : 256;
        uint64_t *p = realloc(l->face, cap * sizeof *p);
        if (!p)
            return;
        l->face = p, l->cap = cap;
    }
    l->face[l->count++] = v;
}

static void list_faces(const hpfc_file *f, const hpfc_faces *fc, face_list *out)
{
    hpfc_walker *w = NULL;
    out->count = 0;
    if (hpfc_walker_create(f, &w))
        return;
    hpfc_pixel px;
    int st;
    for (st = hpfc_leaf_first(f, &px); !st; st = hpfc_leaf_next(f, &px)) {
        uint64_t face = 0;
        int is_private = 0;
        if (hpfc_pixel_is_private(f, &px, &is_private) == HPFC_OK && is_private) {
            push(out, (uint64_t)hpfc_faces_pixel_face(fc, &px, &face));
            push(out, face);
            continue;
        }
        hpfc_dart d = {.pixel = px};
        for (d.crossing = 0;; d.crossing++) {
            int s = hpfc_faces_dart_face(fc, &d, &face);
            if (s == HPFC_E_ARG)
                break; /* past the leaf's crossings */
            push(out, (uint64_t)s);
            push(out, face);
        }
    }
    push(out, (uint64_t)st);
    hpfc_walker_free(w);
}

static uint64_t find(uint32_t *parent, uint64_t x)
{
    while (parent[x] != x)
        x = parent[x] = parent[parent[x]];
    return x;
}

/* E - V + C + 1: the faces of a planar map, the unbounded one among them. */
static uint64_t euler_faces(const hpfc_graph *g)
{
    size_t nv = hpfc_graph_vertex_count(g), ne = hpfc_graph_edge_count(g), c = nv;
    uint32_t *parent = malloc((nv ? nv : 1) * sizeof *parent);
    if (!parent)
        return 0;
    for (size_t v = 0; v < nv; v++)
        parent[v] = (uint32_t)v;
    for (size_t e = 0; e < ne; e++) {
        uint32_t u, v;
        const int64_t *xy;
        size_t n;
        hpfc_graph_edge(g, e, &u, &v, &xy, &n);
        uint64_t a = find(parent, u), b = find(parent, v);
        if (a != b)
            parent[a] = (uint32_t)b, c--;
    }
    free(parent);
    return ne - nv + c + 1;
}

static size_t maps_checked, mutants_checked, mutants_numbered, mutants_failed;

/* One mutant: statuses and faces on 1 and on 3 threads, runs of 4 leaves. */
static void check_mutant(const uint8_t *bytes, size_t size)
{
    hpfc_file *f = NULL;
    if (hpfc_open_memory(bytes, size, HPFC_OPEN_SKIP_CHECKSUM, &f))
        return;
    hpfc_faces *one = NULL, *many = NULL;
    uint64_t fail1 = 0, fail3 = 0;
    int st1 = faces_build_width(f, FACES_NARROW_NODES, 1, 4, &fail1, &one);
    int st3 = faces_build_width(f, FACES_NARROW_NODES, 3, 4, &fail3, &many);
    CHECK_EQ_INT(st3, st1);
    CHECK(fail3 == fail1); /* the same leaf's failure, whichever thread met it */
    mutants_checked++;
    mutants_failed += fail1 != UINT64_MAX;
    if (!st1 && !st3) {
        face_list a = {0}, b = {0};
        list_faces(f, one, &a);
        list_faces(f, many, &b);
        CHECK(hpfc_faces_face_count(one) == hpfc_faces_face_count(many));
        CHECK(a.count == b.count && memcmp(a.face, b.face, a.count * sizeof *a.face) == 0);
        free(a.face);
        free(b.face);
        mutants_numbered++;
    }
    hpfc_faces_free(one);
    hpfc_faces_free(many);
    hpfc_close(f);
}

/* Changes a few bytes past the header, where the pools and sections lie. */
static int mutants_a_map = 16;

static void check_mutants(const uint8_t *bytes, size_t size, uint64_t seed)
{
    uint8_t *copy = malloc(size);
    gen_rng rng;
    gen_rng_seed(&rng, seed);
    for (int m = 0; copy && m < mutants_a_map && size > 128; m++) {
        memcpy(copy, bytes, size);
        int changes = 1 + (int)gen_rng_below(&rng, 4);
        for (int k = 0; k < changes; k++) {
            size_t at = 64 + (size_t)gen_rng_below(&rng, size - 64);
            copy[at] ^= (uint8_t)(1u << gen_rng_below(&rng, 8));
        }
        check_mutant(copy, size);
    }
    free(copy);
}

/* GEOM from a graph the tree was not built from (one vertex, no edge):
 * the same status and words on three threads, where the plan fails beside
 * the labels, as on one, with a diagnostic and without. */
static void check_wrong_geometry(const hpfc_tree *t, int layout)
{
    hpfc_graph *other = NULL;
    if (hpfc_graph_create(&other) != HPFC_OK || hpfc_graph_add_vertex(other, 0, 0, NULL) != HPFC_OK) {
        CHECK(0);
        hpfc_graph_free(other);
        return;
    }
    hpfc_write_options o = {.face_labels = 1, .layout = layout, .geometry = other};
    hpfc_write_options o3 = {.face_labels = 1, .layout = layout, .geometry = other, .threads = 3};
    hpfc_diag d1, d3;
    uint8_t *bytes = NULL;
    size_t size = 0;
    CHECK_EQ_INT(hpfc_tree_serialize(t, &o, &bytes, &size, &d1), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_tree_serialize(t, &o3, &bytes, &size, &d3), HPFC_E_ARG);
    CHECK(!bytes && d1.status == d3.status && strcmp(d1.message, d3.message) == 0 &&
          d1.edge[0] == d3.edge[0] && d1.edge[1] == d3.edge[1] && strstr(d3.message, "geometry"));
    CHECK(d3.edge[0] == -1 && d3.edge[1] == -1 && !d3.has_point); /* no edge or point named */
    CHECK_EQ_INT(hpfc_tree_serialize(t, &o3, &bytes, &size, NULL), HPFC_E_ARG);
    hpfc_graph_free(other);
}

static void check_map(const hpfc_graph *g, const char *what, int layout, uint64_t seed)
{
    hpfc_build_params p;
    hpfc_build_params_default(&p);
    hpfc_tree *t = NULL;
    uint8_t *bytes = NULL, *bytes3 = NULL;
    size_t size = 0, size3 = 0;
    hpfc_write_options o = {.face_labels = 1, .layout = layout, .geometry = g};
    hpfc_write_options o3 = {.face_labels = 1, .layout = layout, .geometry = g, .threads = 3};
    if (hpfc_build(g, &p, &t, NULL) != HPFC_OK)
        return; /* the generators' graphs all build; a failure is build's test */
    CHECK_EQ_INT(hpfc_tree_serialize(t, &o, &bytes, &size, NULL), HPFC_OK);
    CHECK_EQ_INT(hpfc_tree_serialize(t, &o3, &bytes3, &size3, NULL), HPFC_OK);
    CHECK(bytes && bytes3 && size == size3 && memcmp(bytes, bytes3, size) == 0);
    static unsigned wrong_geometry_maps;
    if (wrong_geometry_maps++ < 4) /* the failure's path, not the maps', is under test */
        check_wrong_geometry(t, layout);
    hpfc_tree_free(t);
    hpfc_file *f = NULL;
    if (!bytes || hpfc_open_memory(bytes, size, 0, &f)) {
        CHECK(0);
        hpfc_free(bytes);
        hpfc_free(bytes3);
        return;
    }
    hpfc_faces *alone = NULL;
    face_list want = {0};
    CHECK_EQ_INT(faces_build_width(f, FACES_NARROW_NODES, 1, 0, NULL, &alone), HPFC_OK);
    if (alone) {
        uint64_t euler = euler_faces(g);
        if (hpfc_faces_face_count(alone) != euler)
            fprintf(stderr, "%s: %llu faces, Euler %llu\n", what,
                    (unsigned long long)hpfc_faces_face_count(alone), (unsigned long long)euler);
        CHECK(hpfc_faces_face_count(alone) == euler);
        list_faces(f, alone, &want);
    }
    /* threads, leaves a run, 64-bit words */
    static const struct {
        unsigned threads;
        uint64_t run;
        int wide;
    } ways[] = {{1, 3, 0}, {2, 3, 1}, {2, 17, 0}, {3, 5, 0}, {8, 4, 0}};
    for (size_t a = 0; alone && a < sizeof ways / sizeof *ways; a++) {
        hpfc_faces *fc = NULL;
        face_list got = {0};
        CHECK_EQ_INT(faces_build_width(f, ways[a].wide ? 0 : FACES_NARROW_NODES, ways[a].threads,
                                       ways[a].run, NULL, &fc),
                     HPFC_OK);
        if (!fc)
            continue;
        list_faces(f, fc, &got);
        CHECK(hpfc_faces_face_count(fc) == hpfc_faces_face_count(alone));
        CHECK(got.count == want.count && memcmp(got.face, want.face, got.count * sizeof *got.face) == 0);
        free(got.face);
        hpfc_faces_free(fc);
    }
    /* the public call, as a program makes it */
    hpfc_faces *pub = NULL;
    face_list got = {0};
    CHECK_EQ_INT(hpfc_faces_build_threads(f, 2, &pub), HPFC_OK);
    if (pub && alone) {
        list_faces(f, pub, &got);
        CHECK(got.count == want.count && memcmp(got.face, want.face, got.count * sizeof *got.face) == 0);
    }
    free(got.face);
    free(want.face);
    hpfc_faces_free(pub);
    hpfc_faces_free(alone);
    hpfc_close(f);
    check_mutants(bytes, size, seed);
    hpfc_free(bytes);
    hpfc_free(bytes3);
    maps_checked++;
}

/* Usage: test_faces_threads [SEEDS [MUTANTS]]: the generators' seeds 1 ..
 * SEEDS (default 4) and MUTANTS a map (default 16); the ThreadSanitizer run
 * (tools/run-tests.sh) takes fewer. */
int main(int argc, char **argv)
{
    uint64_t seeds = argc > 1 ? strtoull(argv[1], NULL, 10) : 4;
    if (argc > 2)
        mutants_a_map = atoi(argv[2]);
    size_t want_maps = (size_t)(2 * (GEN_SPECIAL_COUNT + 3 * seeds));
    for (int layout = HPFC_LAYOUT_PAPER; layout <= HPFC_LAYOUT_COMPACT; layout++) {
        for (int k = 0; k < GEN_SPECIAL_COUNT; k++) {
            hpfc_graph *g = NULL;
            if (gen_special(k, &g) == HPFC_OK)
                check_map(g, gen_special_name(k), layout, 100 + (uint64_t)k);
            hpfc_graph_free(g);
        }
        for (uint64_t seed = 1; seed <= seeds; seed++) {
            hpfc_graph *g = NULL;
            if (gen_delaunay(seed, 30 * seed * seed, 100000, 0.3, &g) == HPFC_OK)
                check_map(g, "delaunay", layout, seed);
            hpfc_graph_free(g);
            g = NULL;
            if (gen_polyline(seed, 40 * seed * seed, 100000, 0.5, &g) == HPFC_OK)
                check_map(g, "polyline", layout, 1000 + seed);
            hpfc_graph_free(g);
            g = NULL;
            if (gen_grid_mesh(seed, 3 + 3 * seed, 2 + 2 * seed, 40, &g) == HPFC_OK)
                check_map(g, "grid", layout, 2000 + seed);
            hpfc_graph_free(g);
        }
    }
    printf("faces_threads: %zu maps, %zu mutants (%zu numbered, %zu failed in the runs)\n", maps_checked,
           mutants_checked, mutants_numbered, mutants_failed);
    CHECK(maps_checked == want_maps);
    CHECK(mutants_checked >= maps_checked && mutants_numbered > 0 && mutants_failed > 0);
    return check_report("faces_threads");
}
