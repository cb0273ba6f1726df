/*
 * file_helpers.h: helpers shared by the tests of the .hpfc file (test_open,
 * test_navigate, test_write, test_features): a generated graph built into a
 * tree and serialised, a bounded walk over a possibly corrupt file that
 * collects the statuses it meets, and a FEAT table to write and read back.
 * Header-only and static like check.h, so that every check counts in the
 * test program that runs it.
 */
#ifndef HPFC_TEST_FILE_HELPERS_H
#define HPFC_TEST_FILE_HELPERS_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "gen.h"
#include "hpfc.h"

#define BIT(code) ((uint64_t)1 << (code))
#define OKB BIT(HPFC_OK)

/* ---- a tree, its file ------------------------------------------------------ */

typedef struct shape {
    uint32_t n0, m0, n, m;
    int flat;
} shape;

static inline hpfc_tree *build(const hpfc_graph *g, const shape *sh)
{
    hpfc_build_params p;
    hpfc_build_params_default(&p);
    p.root_cols = sh->n0, p.root_rows = sh->m0, p.cols = sh->n, p.rows = sh->m, p.flat = sh->flat;
    p.max_flat_pixels = 1 << 16;
    hpfc_tree *t = NULL;
    hpfc_diag d;
    int st = hpfc_build(g, &p, &t, &d);
    if (st && st != HPFC_E_TOO_MANY_PIXELS)
        fprintf(stderr, "build failed: %s: %s\n", hpfc_strerror(st), d.message);
    CHECK(st == HPFC_OK || (sh->flat && st == HPFC_E_TOO_MANY_PIXELS));
    return t;
}

static inline uint8_t *serialize(const hpfc_tree *t, const char *crs, size_t *size)
{
    hpfc_write_options opts = {.crs = crs};
    uint8_t *buf = NULL;
    hpfc_diag d;
    int st = check_tree_serialize(t, &opts, &buf, size, &d);
    if (st)
        fprintf(stderr, "serialize failed: %s: %s\n", hpfc_strerror(st), d.message);
    CHECK_EQ_INT(st, HPFC_OK);
    return buf;
}

static inline bool same_pixel(const hpfc_pixel *a, const hpfc_pixel *b)
{
    if (a->depth != b->depth)
        return false;
    for (uint32_t l = 0; l <= a->depth; l++)
        if (a->path[l].image != b->path[l].image || a->path[l].i != b->path[l].i ||
            a->path[l].j != b->path[l].j)
            return false;
    return true;
}

static inline hpfc_tree *special_tree(int which, uint32_t n0)
{
    hpfc_graph *g = NULL;
    CHECK_EQ_INT(gen_special(which, &g), HPFC_OK);
    const shape sh = {n0, n0, 2, 2, 0};
    hpfc_tree *t = g ? build(g, &sh) : NULL;
    hpfc_graph_free(g);
    return t;
}

/* ---- bounded walk over a possibly corrupt file ------------------------------------- */

typedef struct probe {
    const hpfc_file *f;
    hpfc_file_info info;
    long budget;
    uint64_t codes; /* BIT(status) of every status seen */
} probe;

static inline void note(probe *p, int st)
{
    p->codes |= BIT(st);
}

/* A word pixel's word; HPFC_E_ARG only when the buffer is too small. */
static inline void probe_word(probe *p, const hpfc_pixel *px)
{
    char buf[64];
    size_t len = 0;
    int st = hpfc_pixel_word(p->f, px, buf, sizeof buf, &len);
    note(p, st == HPFC_E_ARG && len > sizeof buf ? HPFC_OK : st);
}

static inline void probe_pixel(probe *p, const hpfc_pixel *px)
{
    if (p->budget-- <= 0)
        return;
    int type = -1, priv;
    int st = hpfc_pixel_type(p->f, px, &type);
    note(p, st);
    if (st)
        return;
    int64_t x0, y0, x1, y1;
    note(p, hpfc_pixel_bounds(p->f, px, &x0, &y0, &x1, &y1));
    note(p, hpfc_pixel_is_private(p->f, px, &priv));
    for (int dir = HPFC_WEST; dir <= HPFC_SOUTH; dir++) {
        hpfc_pixel q;
        st = hpfc_pixel_move(p->f, px, dir, &q);
        note(p, st);
        if (!st) /* a move ends on a word pixel */
            probe_word(p, &q);
    }
    if (type == HPFC_PIXEL_WORD) {
        probe_word(p, px);
        return;
    }
    for (uint32_t j = 0; j < p->info.rows; j++)
        for (uint32_t i = 0; i < p->info.cols; i++) {
            hpfc_pixel child;
            st = hpfc_pixel_child(p->f, px, i, j, &child);
            note(p, st);
            if (!st)
                probe_pixel(p, &child);
        }
}

/* Walks the whole file (within a budget) and locates points; returns the
 * set of statuses seen. */
static inline uint64_t probe_file(const hpfc_file *f, long budget)
{
    probe p = {.f = f, .budget = budget};
    hpfc_file_get_info(f, &p.info);
    for (uint32_t j = 0; j < p.info.root_rows && p.budget > 0; j++)
        for (uint32_t i = 0; i < p.info.root_cols && p.budget > 0; i++) {
            hpfc_pixel px;
            note(&p, hpfc_pixel_root(f, i, j, &px));
            probe_pixel(&p, &px);
        }
    for (int k = 0; k < 64; k++) {
        hpfc_pixel px;
        int64_t x = p.info.x0 + (p.info.width * k) / 64, y = p.info.y0 + (p.info.height * (k * 37 % 64)) / 64;
        int st = hpfc_locate(f, x, y, &px);
        note(&p, st);
        if (!st)
            probe_pixel(&p, &px);
    }
    return p.codes;
}

/* ---- the FEAT section ---------------------------------------------------------------------- */

/* A feature table for `faces` faces, derived from the face number so that
 * reading it back can be checked against this same rule: face 0 has no
 * feature, face f the features f % 5 and, for odd f, also 5 + f % 2. */
typedef struct feat_fixture {
    int64_t fid[7];
    uint32_t layer[7];
    const char *key[7];
    const char *layer_name[2];
    uint32_t *start, *link;
    hpfc_feature_table t;
} feat_fixture;

static inline void feat_fixture_make(feat_fixture *x, uint32_t faces)
{
    static const char *keys[7] = {"Travis", NULL, "Z\xc3\xbcrich", "", "a \"quoted\" key", "7", NULL};
    memset(x, 0, sizeof *x);
    for (uint32_t k = 0; k < 7; k++) {
        x->fid[k] = k == 3 ? INT64_MIN : (int64_t)k * 1000003 - 2;
        x->layer[k] = k >= 5;
        x->key[k] = keys[k];
    }
    x->layer_name[0] = "counties";
    x->layer_name[1] = "lakes";
    x->start = calloc(faces + 1, sizeof *x->start);
    x->link = calloc(2 * (size_t)faces + 1, sizeof *x->link);
    uint32_t n = 0;
    for (uint32_t f = 0; f < faces; f++) {
        x->start[f] = n;
        if (f > 0) {
            x->link[n++] = f % 5;
            if (f % 2)
                x->link[n++] = 5 + f % 2;
        }
    }
    x->start[faces] = n;
    x->t = (hpfc_feature_table){.feature_count = 7, .fid = x->fid, .layer = x->layer,
                                .key_field = "NAME", .key = x->key, .layer_count = 2,
                                .layer_name = x->layer_name, .face_count = faces,
                                .face_start = x->start, .face_feature = x->link};
}

#endif
