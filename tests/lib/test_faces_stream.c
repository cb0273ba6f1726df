/* The faces numbered one root pixel at a time (faces_stream_*, faces.h)
 * against hpfc_faces_build over the whole file:
 *   - the same face count, and for every root pixel, every leaf's faces
 *     (each crossing's out-dart, each private leaf) the same ids;
 *   - a root's numbering answers for its own leaves only;
 *   - LABL written a root at a time (labels_build_stream) is the section
 *     the writer stores, byte for byte, and so is a file written with
 *     hpfc_write_options.faces_by_root (also with faces_out, which it
 *     leaves to the whole numbering);
 *   - the plan made on one thread and on several (roots in blocks), the
 *     roots then numbered ahead on a thread of their own, and asked for
 *     out of order too;
 *   - over maps of the generators and the special cases, both layouts, root
 *     grids from 1 x 1 to 16 x 16 and refined images of 2 x 2 and 3 x 2;
 *   - mutants of those files (pools changed, opened without the checksum)
 *     are numbered or refused, and never read out of bounds (ASan).
 * With file names as arguments it checks those files instead. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "faces.h"
#include "file.h"
#include "labels.h"
#include "gen.h"
#include "hpfc.h"

static size_t roots_checked, leaves_checked, mutants_checked, mutants_numbered;

/* Leaf px's faces from a and from b agree (b: the root's own numbering). */
static void same_leaf_faces(const hpfc_file *f, const hpfc_faces *a, const hpfc_faces *b,
                            const hpfc_pixel *px)
{
    int is_private = 0;
    uint64_t fa = 0, fb = 0;
    CHECK_EQ_INT(hpfc_pixel_is_private(f, px, &is_private), HPFC_OK);
    if (is_private) {
        CHECK_EQ_INT(hpfc_faces_pixel_face(a, px, &fa), HPFC_OK);
        CHECK_EQ_INT(hpfc_faces_pixel_face(b, px, &fb), HPFC_OK);
        CHECK(fa == fb);
        return;
    }
    hpfc_dart d = {.pixel = *px};
    for (d.crossing = 0;; d.crossing++) {
        int sa = hpfc_faces_dart_face(a, &d, &fa), sb = hpfc_faces_dart_face(b, &d, &fb);
        CHECK_EQ_INT(sb, sa);
        if (sa != HPFC_OK)
            break; /* past the leaf's crossings */
        if (fa != fb)
            fprintf(stderr, "leaf at depth %u crossing %u: face %llu, streamed %llu\n", px->depth,
                    d.crossing, (unsigned long long)fa, (unsigned long long)fb);
        CHECK(fa == fb);
    }
}

/* Root r's numbering (row-major) against the whole file's at its leaves. */
static void check_root(const hpfc_file *f, faces_stream *s, const hpfc_faces *whole, uint32_t cols,
                       uint32_t r)
{
    hpfc_faces *root = NULL;
    CHECK_EQ_INT(faces_stream_root(s, r % cols, r / cols, &root), HPFC_OK);
    hpfc_pixel px;
    int st;
    for (st = hpfc_leaf_first(f, &px); root && !st; st = hpfc_leaf_next(f, &px))
        if (px.path[0].j * cols + px.path[0].i == r)
            same_leaf_faces(f, whole, root, &px);
    roots_checked++;
    hpfc_faces_free(root);
}

/* With the roots numbered ahead (a plan on two threads), roots asked for
 * out of order: 0, 2, 1, 0, then the rest in order, each as the whole
 * file's. */
static void check_out_of_order(const hpfc_file *f)
{
    hpfc_file_info info;
    hpfc_file_get_info(f, &info);
    uint32_t roots = info.root_cols * info.root_rows;
    hpfc_faces *whole = NULL;
    faces_stream *s = NULL;
    CHECK_EQ_INT(hpfc_faces_build(f, &whole), HPFC_OK);
    CHECK_EQ_INT(faces_stream_plan(f, 2, &s), HPFC_OK);
    if (whole && s && roots >= 3) {
        static const uint32_t order[] = {0, 2, 1, 0};
        for (size_t k = 0; k < sizeof order / sizeof *order; k++)
            check_root(f, s, whole, info.root_cols, order[k]);
        for (uint32_t r = 1; r < roots; r++)
            check_root(f, s, whole, info.root_cols, r);
    }
    faces_stream_free(s);
    hpfc_faces_free(whole);
}

/* Every root's numbering, the plan made on `threads` threads, against the
 * whole file's. */
static void check_file(const hpfc_file *f, const char *what, unsigned threads)
{
    hpfc_faces *whole = NULL;
    faces_stream *s = NULL;
    CHECK_EQ_INT(hpfc_faces_build(f, &whole), HPFC_OK);
    CHECK_EQ_INT(faces_stream_plan(f, threads, &s), HPFC_OK);
    if (!whole || !s) {
        hpfc_faces_free(whole);
        faces_stream_free(s);
        return;
    }
    if (faces_stream_face_count(s) != hpfc_faces_face_count(whole))
        fprintf(stderr, "%s: %llu faces streamed, %llu whole\n", what,
                (unsigned long long)faces_stream_face_count(s),
                (unsigned long long)hpfc_faces_face_count(whole));
    CHECK(faces_stream_face_count(s) == hpfc_faces_face_count(whole));
    hpfc_file_info info;
    hpfc_file_get_info(f, &info);
    hpfc_faces *root = NULL;
    uint32_t ri = UINT32_MAX, rj = UINT32_MAX;
    hpfc_pixel px;
    int st;
    for (st = hpfc_leaf_first(f, &px); !st; st = hpfc_leaf_next(f, &px)) {
        if (px.path[0].i != ri || px.path[0].j != rj) {
            hpfc_faces_free(root);
            root = NULL;
            ri = px.path[0].i, rj = px.path[0].j;
            CHECK_EQ_INT(faces_stream_root(s, ri, rj, &root), HPFC_OK);
            roots_checked++;
            if (root && info.root_cols * info.root_rows > 1) { /* another root's leaf: not its own */
                hpfc_pixel other;
                uint64_t face;
                uint32_t oi = (ri + 1) % info.root_cols, oj = oi ? rj : (rj + 1) % info.root_rows;
                CHECK_EQ_INT(hpfc_pixel_root(f, oi, oj, &other), HPFC_OK);
                int type = HPFC_PIXEL_REFINED;
                hpfc_pixel_type(f, &other, &type);
                if (type == HPFC_PIXEL_WORD)
                    CHECK(hpfc_faces_pixel_face(root, &other, &face) != HPFC_OK ||
                          hpfc_faces_dart_face(root, &(hpfc_dart){.pixel = other}, &face) !=
                              HPFC_OK);
            }
        }
        if (root)
            same_leaf_faces(f, whole, root, &px);
        leaves_checked++;
    }
    CHECK_EQ_INT(st, HPFC_E_NO_PIXEL);
    CHECK_EQ_INT(faces_stream_root(s, info.root_cols, 0, &root), HPFC_E_ARG);
    hpfc_faces_free(root);
    hpfc_faces_free(whole);
    faces_stream_free(s);
}

/* A mutant is numbered or refused; when both numberings succeed, the
 * streamed plan still has a face count (its ids are not compared: a
 * damaged file's classes depend on which unions each method makes). The
 * plan made on three threads is refused or made as on one, with the same
 * face count. */
static void check_mutant(const uint8_t *bytes, size_t size)
{
    hpfc_file *f = NULL;
    if (hpfc_open_memory(bytes, size, HPFC_OPEN_SKIP_CHECKSUM, &f))
        return;
    faces_stream *s = NULL, *three = NULL;
    mutants_checked++;
    int st = faces_stream_plan(f, 1, &s), st3 = faces_stream_plan(f, 3, &three);
    CHECK((st == HPFC_OK) == (st3 == HPFC_OK));
    if (!st && !st3)
        CHECK(faces_stream_face_count(s) == faces_stream_face_count(three));
    faces_stream_free(three);
    if (st == HPFC_OK) {
        hpfc_file_info info;
        hpfc_file_get_info(f, &info);
        for (uint32_t j = 0; j < info.root_rows; j++)
            for (uint32_t i = 0; i < info.root_cols; i++) {
                hpfc_faces *root = NULL;
                if (faces_stream_root(s, i, j, &root) == HPFC_OK)
                    CHECK(hpfc_faces_face_count(root) == faces_stream_face_count(s));
                hpfc_faces_free(root);
            }
        mutants_numbered++;
    }
    faces_stream_free(s);
    hpfc_close(f);
}

static void check_mutants(const uint8_t *bytes, size_t size, uint64_t seed)
{
    uint8_t *copy = malloc(size);
    gen_rng rng;
    gen_rng_seed(&rng, seed);
    for (int m = 0; copy && m < 12 && size > 128; m++) {
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

static size_t sections_checked;

/* LABL written a root at a time against the section the writer stored. */
static void check_labels(const hpfc_tree *t, const hpfc_file *f)
{
    faces_stream *s = NULL;
    uint8_t *labl = NULL;
    uint64_t length = 0;
    hpfc_diag d;
    CHECK_EQ_INT(faces_stream_plan(f, 2, &s), HPFC_OK);
    if (!s)
        return;
    int st = labels_build_stream(t, f, s, &labl, &length, &d);
    if (st)
        fprintf(stderr, "labels_build_stream: %s\n", d.message);
    CHECK_EQ_INT(st, HPFC_OK);
    CHECK(f->labels.present && labl && length == f->labels.section_length &&
          memcmp(labl, f->labels.section, (size_t)length) == 0);
    sections_checked++;
    free(labl);
    faces_stream_free(s);
}

/* The writer's option (hpfc_write_options.faces_by_root): the same bytes;
 * with faces_out too, the faces handed out as without it. */
static void check_by_root(const hpfc_tree *t, const hpfc_write_options *o, const uint8_t *bytes,
                          size_t size)
{
    hpfc_write_options by_root = *o;
    by_root.faces_by_root = 1;
    uint8_t *again = NULL;
    size_t again_size = 0;
    CHECK_EQ_INT(hpfc_tree_serialize(t, &by_root, &again, &again_size, NULL), HPFC_OK);
    CHECK(again && again_size == size && memcmp(again, bytes, size) == 0);
    hpfc_free(again);
    hpfc_faces *fc = NULL;
    by_root.faces_out = &fc;
    again = NULL;
    CHECK_EQ_INT(hpfc_tree_serialize(t, &by_root, &again, &again_size, NULL), HPFC_OK);
    CHECK(again && again_size == size && memcmp(again, bytes, size) == 0 && fc);
    hpfc_faces_free(fc);
    hpfc_free(again);
}

static void check_map(const hpfc_graph *g, const char *what, uint64_t seed)
{
    static const struct {
        uint32_t root_cols, root_rows, cols, rows;
    } grids[] = {{1, 1, 2, 2}, {4, 4, 2, 2}, {16, 16, 2, 2}, {5, 3, 3, 2}};
    for (size_t k = 0; k < sizeof grids / sizeof *grids; k++)
        for (int layout = 0; layout < 2; layout++) {
            hpfc_build_params p;
            hpfc_build_params_default(&p);
            p.root_cols = grids[k].root_cols, p.root_rows = grids[k].root_rows;
            p.cols = grids[k].cols, p.rows = grids[k].rows;
            hpfc_tree *t = NULL;
            if (hpfc_build(g, &p, &t, NULL) != HPFC_OK)
                continue; /* a build's failure is test_build's */
            hpfc_write_options o = {.layout = layout ? HPFC_LAYOUT_COMPACT : HPFC_LAYOUT_PAPER,
                                    .face_labels = 1};
            uint8_t *bytes = NULL;
            size_t size = 0;
            CHECK_EQ_INT(hpfc_tree_serialize(t, &o, &bytes, &size, NULL), HPFC_OK);
            check_by_root(t, &o, bytes, size);
            hpfc_file *f = NULL;
            if (bytes && hpfc_open_memory(bytes, size, 0, &f) == HPFC_OK) {
                check_file(f, what, 1);
                check_file(f, what, 3);
                if (k == 1)
                    check_out_of_order(f);
                check_labels(t, f);
                hpfc_close(f);
                if (k == 1 || k == 3)
                    check_mutants(bytes, size, seed * 7 + k * 2 + (uint64_t)layout);
            } else {
                CHECK(0);
            }
            hpfc_free(bytes);
            hpfc_tree_free(t);
        }
}

int main(int argc, char **argv)
{
    if (argc > 1) { /* the files named, whole (real layers, by hand) */
        for (int a = 1; a < argc; a++) {
            hpfc_file *f = NULL;
            CHECK_EQ_INT(hpfc_open(argv[a], 0, &f), HPFC_OK);
            if (f)
                check_file(f, argv[a], 2);
            hpfc_close(f);
        }
        printf("faces_stream: %zu roots, %zu leaves checked\n", roots_checked, leaves_checked);
        return check_report("faces_stream");
    }
    for (int k = 0; gen_special_name(k); k++) {
        hpfc_graph *g = NULL;
        if (gen_special(k, &g) == HPFC_OK)
            check_map(g, gen_special_name(k), 100 + (uint64_t)k);
        hpfc_graph_free(g);
    }
    for (uint64_t seed = 1; seed <= 4; seed++) {
        hpfc_graph *g = NULL;
        if (gen_delaunay(seed, 30 * seed * seed, 100000, 0.3, &g) == HPFC_OK)
            check_map(g, "delaunay", seed);
        hpfc_graph_free(g);
        g = NULL;
        if (gen_polyline(seed, 40 * seed * seed, 100000, 0.5, &g) == HPFC_OK)
            check_map(g, "polyline", seed + 10);
        hpfc_graph_free(g);
        g = NULL;
        if (gen_grid_mesh(seed, 3 + 3 * seed, 2 + 2 * seed, 40, &g) == HPFC_OK)
            check_map(g, "grid", seed + 20);
        hpfc_graph_free(g);
    }
    printf("faces_stream: %zu roots, %zu leaves, %zu LABL sections checked; %zu mutants, %zu numbered\n",
           roots_checked, leaves_checked, sections_checked, mutants_checked, mutants_numbered);
    CHECK(roots_checked > 1000 && leaves_checked > 10000 && sections_checked > 100 && mutants_checked > 50);
    return check_report("faces_stream");
}
