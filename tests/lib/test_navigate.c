/*
 * The reader's navigation (hpfc_pixel_*, hpfc_locate; spec/hpfc-format.md):
 * generated graphs are built, serialised, reopened and walked pixel by pixel
 * against the in-memory tree and against naive geometric oracles; the
 * paper's Fig. 4 tree with its pool sizes and the moves of Sect. 3.3;
 * arguments and forged pixels refused; every pool bit of a small file
 * flipped under a bounded walk.
 */
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "file_helpers.h"
#include "format.h"
#include "gen.h"
#include "hpfc.h"
#include "reader.h"
#include "tree.h"
#include "tree_oracle.h"

/* the layout under test (check_use_test_layout) */
static int test_layout_compact;

/* What the round trips covered, reported at the end (a sweep that silently
 * shrank would show here). */
static struct {
    long trees, one_level_trees, pixels, moves, brute_moves, locates;
    uint32_t max_levels;
} covered;

/* ---- navigation helpers --------------------------------------------------- */

typedef struct box {
    int64_t x0, y0, x1, y1;
} box;

static box pixel_box(const hpfc_file *f, const hpfc_pixel *px)
{
    box b = {0, 0, 0, 0};
    CHECK_EQ_INT(hpfc_pixel_bounds(f, px, &b.x0, &b.y0, &b.x1, &b.y1), HPFC_OK);
    return b;
}

static bool same_box(box a, int64_t x0, int64_t y0, int64_t x1, int64_t y1)
{
    return a.x0 == x0 && a.y0 == y0 && a.x1 == x1 && a.y1 == y1;
}

/* The leaf of the tree containing (x, y), by direct index arithmetic on the
 * tree's own pixel bounds (independent of the reader). */
static bool tree_leaf_at(const hpfc_tree *t, int64_t x, int64_t y, hpfc_tree_pixel *out)
{
    hpfc_tree_info in;
    hpfc_tree_get_info(t, &in);
    if (x < in.x0 || y < in.y0 || x >= in.x0 + in.width || y >= in.y0 + in.height)
        return false;
    int64_t cw = in.width / in.root_cols, ch = in.height / in.root_rows;
    uint32_t i = (uint32_t)((x - in.x0) / cw), j = in.root_rows - 1 - (uint32_t)((y - in.y0) / ch);
    hpfc_tree_get_pixel(t, 0, 0, i, j, out);
    for (uint32_t l = 1; out->type == HPFC_PIXEL_REFINED; l++) {
        cw = (out->x1 - out->x0) / in.cols, ch = (out->y1 - out->y0) / in.rows;
        i = (uint32_t)((x - out->x0) / cw);
        j = in.rows - 1 - (uint32_t)((y - out->y0) / ch);
        hpfc_tree_get_pixel(t, l, out->child, i, j, out);
    }
    return true;
}

/* ---- Fig. 7 --------------------------------------------------------------------------- */

/* Builds the shape of the paper's Fig. 4 directly in the builder's structure
 * (tree.h), as far as the text pins it down (Sect. 3.3's examples): root
 * 4x3 whose pixels (0,0), (2,1), (3,1), (1,2) are refined (images I1..I4),
 * 2x2 images; at level 1, I1's (1,0) and (0,1), I2's (1,1), I3's (0,0), I4's
 * (0,1) and (1,1) are refined (images I5..I10 of level 2, all words).
 * Longest words: 8 symbols (20 bits) at levels 0 and 1, 7 (16 bits) at 2. */
static void fig4_level(hpfc_tree *t, uint32_t l, uint32_t cols, uint32_t rows, size_t images, int64_t cell)
{
    tlevel *lv = &t->levels[l];
    lv->cols = cols, lv->rows = rows, lv->cell_w = lv->cell_h = cell;
    lv->nimages = lv->cap = images;
    lv->img_gx = calloc(images, sizeof *lv->img_gx);
    lv->img_gy = calloc(images, sizeof *lv->img_gy);
    lv->pix = calloc(images * cols * rows, sizeof *lv->pix);
}

static void fig4_refine(hpfc_tree *t, uint32_t l, size_t image, uint32_t i, uint32_t j, uint32_t child)
{
    tlevel *lv = &t->levels[l], *next = &t->levels[l + 1];
    lv->pix[image * lv->cols * lv->rows + j * lv->cols + i] = (tpixel){child, TPIXEL_REFINED};
    next->img_gx[child] = (lv->img_gx[image] + i) * next->cols;
    next->img_gy[child] = (lv->img_gy[image] + lv->rows - 1 - j) * next->rows;
}

static hpfc_tree *fig4_tree(void)
{
    static const char syms[] = "++++(+Y+)+=+(+Y+)++";
    hpfc_tree *t = calloc(1, sizeof *t);
    t->info = (hpfc_tree_info){.root_cols = 4, .root_rows = 3, .cols = 2, .rows = 2, .levels = 3,
                               .width = 16, .height = 12, .x0 = -5, .y0 = 7};
    t->levels = calloc(3, sizeof *t->levels);
    t->levels_cap = 3;
    t->syms = malloc(sizeof syms);
    memcpy(t->syms, syms, sizeof syms);
    t->nsyms = t->cap_syms = sizeof syms - 1;
    t->cross_edge = calloc(8, sizeof *t->cross_edge);
    t->cross_seg = calloc(8, sizeof *t->cross_seg);
    t->ncross = t->cap_cross = 8;
    fig4_level(t, 0, 4, 3, 1, 4);
    fig4_level(t, 1, 2, 2, 4, 2);
    fig4_level(t, 2, 2, 2, 6, 1);
    for (uint32_t l = 0; l < 3; l++) /* every pixel "++++" unless refined below */
        for (size_t p = 0; p < t->levels[l].nimages * t->levels[l].cols * t->levels[l].rows; p++)
            t->levels[l].pix[p] = (tpixel){0, 0};
    fig4_refine(t, 0, 0, 0, 0, 0); /* I1 */
    fig4_refine(t, 0, 0, 2, 1, 1); /* I2 */
    fig4_refine(t, 0, 0, 3, 1, 2); /* I3 */
    fig4_refine(t, 0, 0, 1, 2, 3); /* I4 */
    fig4_refine(t, 1, 0, 1, 0, 0); /* I5 */
    fig4_refine(t, 1, 0, 0, 1, 1);
    fig4_refine(t, 1, 1, 1, 1, 2);
    fig4_refine(t, 1, 2, 0, 0, 3);
    fig4_refine(t, 1, 3, 0, 1, 4); /* I9 */
    fig4_refine(t, 1, 3, 1, 1, 5); /* I10 */
    t->levels[0].pix[2 * 4 + 3] = (tpixel){4, 4};  /* root (3,2): "(+Y+)+=+" */
    t->levels[1].pix[1 * 4 + 0] = (tpixel){4, 4};  /* I2 (0,0) */
    t->levels[2].pix[5 * 4 + 3] = (tpixel){12, 3}; /* I10 (1,1): "(+Y+)++" */
    t->info.word_pixels = 8 + 10 + 24;
    t->info.refined_pixels = 10;
    return t;
}

/* ---- round trip: the file's tree against the in-memory tree -------------------- */

typedef struct walk {
    const hpfc_tree *t;
    const hpfc_file *f;
    hpfc_tree_info info;
    box *leaves; /* every word pixel of the tree, for the naive neighbour search */
    size_t nleaves, cap_leaves;
    size_t pixels, move_every, brute_every;
} walk;

static void collect_leaf(const hpfc_tree *t, uint32_t level, size_t image, uint32_t i, uint32_t j,
                         const hpfc_tree_pixel *px, void *ctx)
{
    (void)t, (void)level, (void)image, (void)i, (void)j;
    walk *w = ctx;
    if (px->type != HPFC_PIXEL_WORD)
        return;
    if (w->nleaves == w->cap_leaves) {
        w->cap_leaves = w->cap_leaves ? 2 * w->cap_leaves : 1024;
        w->leaves = realloc(w->leaves, w->cap_leaves * sizeof *w->leaves);
    }
    w->leaves[w->nleaves++] = (box){px->x0, px->y0, px->x1, px->y1};
}

static bool overlap(int64_t a0, int64_t a1, int64_t b0, int64_t b1)
{
    return a0 < b1 && b0 < a1;
}

/* The first leaf across P's road in direction dir, by scanning every leaf:
 * among the leaves that share a stretch of the road, the northernmost (W),
 * southernmost (E), easternmost (N) or westernmost (S). */
static bool brute_neighbour(const walk *w, box p, int dir, box *out)
{
    bool found = false;
    for (size_t k = 0; k < w->nleaves; k++) {
        box q = w->leaves[k];
        bool adjacent, better;
        switch (dir) {
        case HPFC_WEST:
            adjacent = q.x1 == p.x0 && overlap(q.y0, q.y1, p.y0, p.y1);
            better = !found || q.y1 > out->y1;
            break;
        case HPFC_EAST:
            adjacent = q.x0 == p.x1 && overlap(q.y0, q.y1, p.y0, p.y1);
            better = !found || q.y0 < out->y0;
            break;
        case HPFC_NORTH:
            adjacent = q.y0 == p.y1 && overlap(q.x0, q.x1, p.x0, p.x1);
            better = !found || q.x1 > out->x1;
            break;
        default:
            adjacent = q.y1 == p.y0 && overlap(q.x0, q.x1, p.x0, p.x1);
            better = !found || q.x0 < out->x0;
            break;
        }
        if (adjacent && better) {
            *out = q;
            found = true;
        }
    }
    return found;
}

/* The lattice point whose leaf is the first neighbour: just across the road,
 * at the end of P's side where the neighbour's clockwise order starts. */
static void first_neighbour_point(box p, int dir, int64_t *x, int64_t *y)
{
    switch (dir) {
    case HPFC_WEST: *x = p.x0 - 1, *y = p.y1 - 1; break;
    case HPFC_EAST: *x = p.x1, *y = p.y0; break;
    case HPFC_NORTH: *x = p.x1 - 1, *y = p.y1; break;
    default: *x = p.x0, *y = p.y0 - 1; break;
    }
}

static void check_moves(walk *w, const hpfc_pixel *px, bool brute)
{
    box p = pixel_box(w->f, px);
    for (int dir = HPFC_WEST; dir <= HPFC_SOUTH; dir++) {
        hpfc_pixel q;
        int st = hpfc_pixel_move(w->f, px, dir, &q);
        int64_t x, y;
        first_neighbour_point(p, dir, &x, &y);
        hpfc_tree_pixel want;
        bool inside = tree_leaf_at(w->t, x, y, &want);
        CHECK_EQ_INT(st, inside ? HPFC_OK : HPFC_E_NO_PIXEL);
        if (st || !inside)
            continue;
        int type = -1;
        CHECK_EQ_INT(hpfc_pixel_type(w->f, &q, &type), HPFC_OK);
        CHECK_EQ_INT(type, HPFC_PIXEL_WORD);
        box got = pixel_box(w->f, &q);
        CHECK(same_box(got, want.x0, want.y0, want.x1, want.y1));
        covered.moves++;
        covered.brute_moves += brute;
        if (brute) {
            box b = {0, 0, 0, 0};
            CHECK(brute_neighbour(w, p, dir, &b));
            CHECK(same_box(got, b.x0, b.y0, b.x1, b.y1));
        }
        /* the move may write over its input */
        hpfc_pixel same = *px;
        CHECK_EQ_INT(hpfc_pixel_move(w->f, &same, dir, &same), HPFC_OK);
        CHECK(same_pixel(&same, &q));
    }
}

static void check_word(const walk *w, const hpfc_pixel *px, const hpfc_tree_pixel *tp)
{
    char buf[4096];
    size_t len = 0;
    CHECK_EQ_INT(hpfc_pixel_word(w->f, px, buf, sizeof buf, &len), HPFC_OK);
    CHECK(len == tp->word_len && memcmp(buf, tp->word, len) == 0);
    size_t len2 = 0;
    CHECK_EQ_INT(hpfc_pixel_word(w->f, px, NULL, 0, &len2), HPFC_OK);
    CHECK_EQ_INT(len2, len);
    if (len > 4) { /* a too small buffer: the length needed, HPFC_E_BUFFER_SMALL */
        len2 = 0;
        CHECK_EQ_INT(hpfc_pixel_word(w->f, px, buf, 4, &len2), HPFC_E_BUFFER_SMALL);
        CHECK_EQ_INT(len2, len);
    }
    int priv = -1;
    CHECK_EQ_INT(hpfc_pixel_is_private(w->f, px, &priv), HPFC_OK);
    CHECK_EQ_INT(priv, tp->word_len == 4);
}

/* Compares the file's pixel px (level `level`) with the tree's pixel tp,
 * then recurses into its children. */
static void walk_pixel(walk *w, const hpfc_pixel *px, const hpfc_tree_pixel *tp, uint32_t level)
{
    int type = -1;
    w->pixels++;
    CHECK_EQ_INT(px->depth, level);
    CHECK_EQ_INT(hpfc_pixel_type(w->f, px, &type), HPFC_OK);
    CHECK_EQ_INT(type, tp->type);
    CHECK(same_box(pixel_box(w->f, px), tp->x0, tp->y0, tp->x1, tp->y1));
    if (w->pixels % w->move_every == 0)
        check_moves(w, px, w->pixels % w->brute_every == 0);
    hpfc_pixel child;
    if (type == HPFC_PIXEL_WORD) {
        check_word(w, px, tp);
        CHECK_EQ_INT(hpfc_pixel_child(w->f, px, 0, 0, &child), HPFC_E_NO_PIXEL);
        return;
    }
    int priv = -1;
    CHECK_EQ_INT(hpfc_pixel_is_private(w->f, px, &priv), HPFC_OK);
    CHECK_EQ_INT(priv, 0);
    size_t len;
    CHECK_EQ_INT(hpfc_pixel_word(w->f, px, NULL, 0, &len), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_pixel_child(w->f, px, w->info.cols, 0, &child), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_pixel_child(w->f, px, 0, w->info.rows, &child), HPFC_E_ARG);
    for (uint32_t j = 0; j < w->info.rows; j++)
        for (uint32_t i = 0; i < w->info.cols; i++) {
            hpfc_tree_pixel tc;
            CHECK_EQ_INT(hpfc_tree_get_pixel(w->t, level + 1, tp->child, i, j, &tc), HPFC_OK);
            CHECK_EQ_INT(hpfc_pixel_child(w->f, px, i, j, &child), HPFC_OK);
            hpfc_pixel up, again;
            CHECK_EQ_INT(hpfc_pixel_parent(&child, &up), HPFC_OK);
            CHECK(same_pixel(&up, px));
            CHECK_EQ_INT(hpfc_pixel_child(w->f, &up, i, j, &again), HPFC_OK);
            CHECK(same_pixel(&again, &child));
            walk_pixel(w, &child, &tc, level + 1);
        }
}

/* The level table against the tree's own counts. */
static void check_file_info(const walk *w, const uint8_t *buf, size_t size, const char *crs)
{
    hpfc_file_info fi;
    hpfc_file_get_info(w->f, &fi);
    const hpfc_tree_info *ti = &w->info;
    CHECK_EQ_INT(fi.format_major, 1);
    CHECK_EQ_INT(fi.format_minor, HPFC_FORMAT_MINOR);
    CHECK(fi.root_cols == ti->root_cols && fi.root_rows == ti->root_rows && fi.cols == ti->cols &&
          fi.rows == ti->rows && fi.levels == ti->levels);
    CHECK(fi.x0 == ti->x0 && fi.y0 == ti->y0 && fi.width == ti->width && fi.height == ti->height);
    CHECK_EQ_INT(fi.unit_exp10, ti->unit_exp10);
    CHECK_EQ_INT(fi.file_size, size);
    CHECK_EQ_INT(fi.section_count, crs ? 2 : 1);
    CHECK(crs ? fi.crs_len == strlen(crs) && memcmp(fi.crs, crs, fi.crs_len) == 0 : fi.crs == NULL);
    uint64_t words = 0, refined = 0, pools_end = 0;
    for (uint32_t l = 0; l < fi.levels; l++) {
        hpfc_level_info li;
        CHECK_EQ_INT(hpfc_file_get_level(w->f, l, &li), HPFC_OK);
        CHECK_EQ_INT(li.images, hpfc_tree_image_count(w->t, l));
        CHECK_EQ_INT(li.pool_offset % 8, 0);
        CHECK(li.pool_offset >= pools_end);
        pools_end = li.pool_offset + (li.pool_bits + 7) / 8;
        words += li.word_pixels;
        refined += li.refined_pixels;
    }
    CHECK_EQ_INT(words, ti->word_pixels);
    CHECK_EQ_INT(refined, ti->refined_pixels);
    hpfc_level_info li;
    CHECK_EQ_INT(hpfc_file_get_level(w->f, fi.levels, &li), HPFC_E_ARG);
    hpfc_section_info si;
    CHECK_EQ_INT(hpfc_file_get_section(w->f, 0, &si), HPFC_OK);
    CHECK(strcmp(si.tag, "POOL") == 0 && si.flags == 1);
    CHECK_EQ_INT(si.crc32c, crc32c_update(0, buf + si.offset, (size_t)si.length));
    CHECK_EQ_INT(hpfc_file_get_section(w->f, fi.section_count, &si), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_file_check_checksums(w->f, NULL), HPFC_OK);
}

/* reader_locate_near from `near` (and in place, out = near) gives
 * hpfc_locate's status and pixel, whole path included. */
static void check_locate_near(const hpfc_file *f, const hpfc_pixel *near, int64_t x, int64_t y,
                              int want_st, const hpfc_pixel *want)
{
    hpfc_pixel got, in_place = *near;
    int st = reader_locate_near(f, near, x, y, &got);
    CHECK_EQ_INT(st, want_st);
    CHECK(st || same_pixel(&got, want));
    st = reader_locate_near(f, &in_place, x, y, &in_place);
    CHECK_EQ_INT(st, want_st);
    CHECK(st || same_pixel(&in_place, want));
}

/* hpfc_locate at random lattice points (some outside) against the naive
 * tree descent of tree_oracle.c; reader_locate_near against hpfc_locate,
 * from the pixel located before and from the point's neighbours. */
static void check_locate(const walk *w, uint64_t seed, int count)
{
    gen_rng rng;
    gen_rng_seed(&rng, seed);
    const hpfc_tree_info *ti = &w->info;
    hpfc_pixel before;
    bool have_before = false;
    for (int k = 0; k < count; k++) {
        int64_t x, y;
        if (k < 8) { /* the domain's corners and just outside them */
            x = k & 1 ? ti->x0 + ti->width - 1 : ti->x0;
            y = k & 2 ? ti->y0 + ti->height - 1 : ti->y0;
            if (k & 4)
                x += k & 1 ? 1 : -1;
        } else {
            x = ti->x0 - ti->width / 8 + (int64_t)gen_rng_below(&rng, (uint64_t)(ti->width + ti->width / 4 + 1));
            y = ti->y0 - ti->height / 8 + (int64_t)gen_rng_below(&rng, (uint64_t)(ti->height + ti->height / 4 + 1));
        }
        hpfc_tree_pixel want;
        uint32_t level = 0;
        bool inside = oracle_locate(w->t, x, y, &want, &level);
        hpfc_pixel got;
        int st = hpfc_locate(w->f, x, y, &got);
        CHECK_EQ_INT(st, inside ? HPFC_OK : HPFC_E_NO_PIXEL);
        if (have_before)
            check_locate_near(w->f, &before, x, y, st, &got);
        if (st || !inside)
            continue;
        for (int dir = HPFC_WEST; dir <= HPFC_SOUTH; dir++) { /* the leaf next door as near */
            hpfc_pixel next_door;
            if (hpfc_pixel_move(w->f, &got, dir, &next_door) == HPFC_OK)
                check_locate_near(w->f, &next_door, x, y, st, &got);
        }
        before = got, have_before = true;
        CHECK_EQ_INT(got.depth, level);
        covered.locates++;
        CHECK(same_box(pixel_box(w->f, &got), want.x0, want.y0, want.x1, want.y1));
        char buf[4096];
        size_t len = 0;
        CHECK_EQ_INT(hpfc_pixel_word(w->f, &got, buf, sizeof buf, &len), HPFC_OK);
        CHECK(len == want.word_len && memcmp(buf, want.word, len) == 0);
    }
    hpfc_pixel px;
    CHECK_EQ_INT(hpfc_locate(w->f, INT64_MIN, INT64_MAX, &px), HPFC_E_NO_PIXEL);
    CHECK_EQ_INT(hpfc_locate(w->f, INT64_MAX, INT64_MIN, &px), HPFC_E_NO_PIXEL);
}

/* Build, serialise, reopen; compare everything. Returns the number of
 * pixels walked. */
static size_t round_trip(const hpfc_tree *t, const char *crs, uint64_t seed)
{
    size_t size = 0;
    uint8_t *buf = serialize(t, crs, &size);
    if (!buf)
        return 0;
    walk w = {.t = t};
    hpfc_tree_get_info(t, &w.info);
    hpfc_file *f = NULL;
    CHECK_EQ_INT(hpfc_open_memory(buf, size, 0, &f), HPFC_OK);
    if (!f) {
        hpfc_free(buf);
        return 0;
    }
    w.f = f;
    check_file_info(&w, buf, size, crs);
    oracle_for_each_pixel(t, collect_leaf, &w);
    uint64_t total = w.info.word_pixels + w.info.refined_pixels;
    w.move_every = total > 20000 ? 7 : 1;
    w.brute_every = w.nleaves * total > 4000000 ? 1 + w.nleaves * total / 4000000 : 1;
    for (uint32_t j = 0; j < w.info.root_rows; j++)
        for (uint32_t i = 0; i < w.info.root_cols; i++) {
            hpfc_pixel px;
            hpfc_tree_pixel tp;
            CHECK_EQ_INT(hpfc_pixel_root(f, i, j, &px), HPFC_OK);
            CHECK_EQ_INT(hpfc_tree_get_pixel(t, 0, 0, i, j, &tp), HPFC_OK);
            CHECK_EQ_INT(hpfc_pixel_parent(&px, &px), HPFC_E_NO_PIXEL);
            walk_pixel(&w, &px, &tp, 0);
        }
    CHECK_EQ_INT(w.pixels, total);
    check_locate(&w, seed, 400);
    covered.trees++;
    covered.one_level_trees += w.info.levels == 1;
    covered.pixels += (long)w.pixels;
    covered.max_levels = w.info.levels > covered.max_levels ? w.info.levels : covered.max_levels;
    hpfc_close(f);
    free(w.leaves);
    hpfc_free(buf);
    return w.pixels;
}

/* A pixel from its (i, j) path, following the file's addresses. */
static bool path_pixel(const hpfc_file *f, const uint32_t *ij, uint32_t depth, hpfc_pixel *px)
{
    bool ok = hpfc_pixel_root(f, ij[0], ij[1], px) == HPFC_OK;
    for (uint32_t l = 1; l <= depth && ok; l++)
        ok = hpfc_pixel_child(f, px, ij[2 * l], ij[2 * l + 1], px) == HPFC_OK;
    return ok;
}

static bool moves_to(const hpfc_file *f, const uint32_t *from, uint32_t from_depth, int dir,
                     const uint32_t *to, uint32_t to_depth)
{
    hpfc_pixel p, q, want;
    return path_pixel(f, from, from_depth, &p) && path_pixel(f, to, to_depth, &want) &&
           hpfc_pixel_move(f, &p, dir, &q) == HPFC_OK && same_pixel(&q, &want);
}

/* The moves west of Sect. 3.3, on the Fig. 4 shape (paths as (i, j) per
 * level). The text's f = ((I0,1,2), (I4,1,1), (I9,1,1)) is a misprint for
 * (I4,0,1): I9 is the child of I4's pixel (0,1). */
static void check_paper_moves(const hpfc_file *f)
{
    const uint32_t a[] = {1, 0}, b[] = {0, 0, 1, 0, 1, 0};
    const uint32_t c[] = {1, 2, 0, 1, 0, 1}, d[] = {0, 2};
    const uint32_t e[] = {1, 2, 1, 1, 0, 1}, f_[] = {1, 2, 0, 1, 1, 1};
    CHECK(moves_to(f, a, 0, HPFC_WEST, b, 2));
    CHECK(moves_to(f, c, 2, HPFC_WEST, d, 0));
    CHECK(moves_to(f, e, 2, HPFC_WEST, f_, 2));
    /* and back east: from b the first pixel east is a; from d, the
     * southernmost pixel of I4's west column, I9's (0,1) = c */
    CHECK(moves_to(f, b, 2, HPFC_EAST, a, 0));
    CHECK(moves_to(f, d, 0, HPFC_EAST, c, 2));
}

static void test_fig7_file(void)
{
    hpfc_tree *t = fig4_tree();
    size_t size = 0;
    uint8_t *buf = serialize(t, NULL, &size);
    hpfc_file *f = NULL;
    CHECK_EQ_INT(hpfc_open_memory(buf, size, 0, &f), HPFC_OK);
    static const uint64_t paper_bits[3] = {252, 270, 408}, compact_bits[3] = {56, 64, 69};
    static const uint32_t paper_kw[3] = {20, 20, 16}, paper_ka[3] = {9, 9, 0};
    static const uint32_t compact_kw[3] = {16, 16, 10}, compact_ka[3] = {0, 0, 0};
    /* spec §4.3 (paper) and §5.4 (compact): the sizes worked by hand */
    const uint64_t *bits = test_layout_compact ? compact_bits : paper_bits;
    const uint32_t *kw = test_layout_compact ? compact_kw : paper_kw;
    const uint32_t *ka = test_layout_compact ? compact_ka : paper_ka;
    for (uint32_t l = 0; f && l < 3; l++) {
        hpfc_level_info li;
        CHECK_EQ_INT(hpfc_file_get_level(f, l, &li), HPFC_OK);
        CHECK_EQ_INT(li.pool_bits, bits[l]);
        CHECK_EQ_INT(li.word_bits, kw[l]);
        CHECK_EQ_INT(li.address_bits, ka[l]);
    }
    if (f)
        check_paper_moves(f);
    hpfc_close(f);
    hpfc_free(buf);
    CHECK_EQ_INT(round_trip(t, NULL, 1), 12 + 16 + 24);
    hpfc_tree_free(t);
}

/* ---- generated graphs -------------------------------------------------------------- */

static const shape SHAPES[] = {
    {1, 1, 2, 2, 0}, {4, 3, 2, 2, 0}, {3, 5, 3, 2, 0}, {64, 64, 2, 2, 0}, {2, 1, 2, 3, 0}, {4, 4, 2, 2, 1},
};

static void round_trip_all_shapes(const hpfc_graph *g, uint64_t seed, bool big_shapes)
{
    for (size_t s = 0; s < sizeof SHAPES / sizeof *SHAPES; s++) {
        if (!big_shapes && SHAPES[s].n0 == 64)
            continue;
        hpfc_tree *t = build(g, &SHAPES[s]);
        if (!t)
            continue;
        round_trip(t, s % 2 ? "EPSG:32631" : NULL, seed * 100 + s);
        hpfc_tree_free(t);
    }
}

static void test_generated(void)
{
    for (uint64_t seed = 1; seed <= 3; seed++) {
        hpfc_graph *g = NULL;
        CHECK_EQ_INT(gen_delaunay(seed, 30 + 25 * seed, 1 << 12, 0.2, &g), HPFC_OK);
        if (g)
            round_trip_all_shapes(g, seed, seed == 1);
        hpfc_graph_free(g);
        g = NULL;
        CHECK_EQ_INT(gen_polyline(seed, 100, 1 << 12, 0.5, &g), HPFC_OK);
        if (g)
            round_trip_all_shapes(g, seed + 10, seed == 2);
        hpfc_graph_free(g);
    }
    for (int which = 0; which < GEN_SPECIAL_COUNT; which++) {
        hpfc_graph *g = NULL;
        CHECK_EQ_INT(gen_special(which, &g), HPFC_OK);
        if (g)
            round_trip_all_shapes(g, 50 + (uint64_t)which, true);
        hpfc_graph_free(g);
    }
}

/* ---- corrupt pools ------------------------------------------------------------------ */

/* "section K (TAG) at offset", how hpfc_file_check_checksums names the
 * section that holds byte `at` (the directory's sections do not overlap). */
static const char *section_holding(const hpfc_file *f, uint64_t at)
{
    static char name[64];
    hpfc_file_info info;
    hpfc_file_get_info(f, &info);
    snprintf(name, sizeof name, "no section holds byte %llu", (unsigned long long)at);
    for (uint32_t k = 0; k < info.section_count; k++) {
        hpfc_section_info s;
        if (hpfc_file_get_section(f, k, &s) == HPFC_OK && at >= s.offset &&
            at < s.offset + s.length)
            snprintf(name, sizeof name, "section %u (%s) at offset %llu", k, s.tag,
                     (unsigned long long)s.offset);
    }
    return name;
}

/* Every pool bit of a small file flipped in turn: navigation stays inside
 * the buffer and answers with a status (run under ASan/UBSan in CI). */
static void test_pool_corruption(void)
{
    hpfc_graph *g = NULL; /* 4 levels, about 1500 pool bits */
    CHECK_EQ_INT(gen_delaunay(5, 20, 1 << 8, 0.2, &g), HPFC_OK);
    const shape sh = {2, 2, 2, 2, 0};
    hpfc_tree *t = g ? build(g, &sh) : NULL;
    size_t size = 0;
    uint8_t *buf = t ? serialize(t, NULL, &size) : NULL;
    hpfc_tree_free(t);
    hpfc_graph_free(g);
    if (!buf)
        return;
    hpfc_file *f = NULL;
    CHECK_EQ_INT(hpfc_open_memory(buf, size, 0, &f), HPFC_OK);
    hpfc_level_info first;
    CHECK_EQ_INT(hpfc_file_get_level(f, 0, &first), HPFC_OK);
    CHECK_EQ_INT(probe_file(f, 1 << 20), BIT(HPFC_OK) | BIT(HPFC_E_NO_PIXEL));
    hpfc_close(f);
    uint64_t allowed = BIT(HPFC_OK) | BIT(HPFC_E_NO_PIXEL) | BIT(HPFC_E_CORRUPT);
    /* a private copy sized exactly, so ASan sees any read past the end */
    uint8_t *copy = malloc(size);
    size_t flips = 0, corrupt = 0;
    for (uint64_t bit = first.pool_offset * 8; bit < (uint64_t)size * 8; bit++) {
        memcpy(copy, buf, size);
        copy[bit >> 3] ^= (uint8_t)(0x80 >> (bit & 7));
        f = NULL;
        CHECK_EQ_INT(hpfc_open_memory(copy, size, HPFC_OPEN_SKIP_CHECKSUM, &f), HPFC_OK);
        if (!f)
            continue;
        uint64_t codes = probe_file(f, 4000);
        CHECK((codes & ~allowed) == 0);
        corrupt += (codes & BIT(HPFC_E_CORRUPT)) != 0;
        hpfc_diag diag;
        CHECK_EQ_INT(hpfc_file_check_checksums(f, &diag), HPFC_E_CHECKSUM);
        CHECK(diag.status == HPFC_E_CHECKSUM &&
              strstr(diag.message, section_holding(f, bit >> 3)) == diag.message);
        hpfc_close(f);
        flips++;
    }
    /* the compact pools of this map are about a third of the paper's */
    CHECK(flips > (test_layout_compact ? 300u : 1000u));
    CHECK(corrupt > (test_layout_compact ? 30u : 100u)); /* some flips must be detected while navigating */
    printf("pool corruption: %zu flips, %zu detected while navigating\n", flips, corrupt);
    free(copy);
    hpfc_free(buf);
}

/* ---- arguments and small cases -------------------------------------------------------- */

static void test_arguments(void)
{
    hpfc_file *f = (hpfc_file *)1;
    CHECK_EQ_INT(hpfc_open_memory(NULL, 10, 0, &f), HPFC_E_ARG);
    CHECK(f == NULL);
    CHECK_EQ_INT(hpfc_open_memory("x", 1, 0, NULL), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_open_memory("", 0, 0, &f), HPFC_E_TRUNCATED);
    CHECK_EQ_INT(hpfc_open_memory(FORMAT_MAGIC, 8, 0, &f), HPFC_E_TRUNCATED);
    hpfc_close(NULL);
    CHECK_EQ_INT(hpfc_file_check_checksums(NULL, NULL), HPFC_E_ARG);
    uint8_t *out = NULL;
    size_t size = 0;
    CHECK_EQ_INT(hpfc_tree_serialize(NULL, NULL, &out, &size, NULL), HPFC_E_ARG);

    hpfc_tree *t = special_tree(GEN_SPECIAL_EDGE, 2);
    if (!t)
        return;
    CHECK_EQ_INT(hpfc_tree_serialize(t, NULL, NULL, &size, NULL), HPFC_E_ARG);
    uint8_t *buf = serialize(t, NULL, &size);
    hpfc_tree_free(t);
    CHECK_EQ_INT(hpfc_open_memory(buf, size, 0, &f), HPFC_OK);
    if (!f)
        return;
    hpfc_pixel px, q;
    int type;
    size_t len;
    CHECK_EQ_INT(hpfc_pixel_root(f, 2, 0, &px), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_pixel_root(f, 0, 2, &px), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_pixel_root(f, 0, 0, &px), HPFC_OK);
    CHECK_EQ_INT(hpfc_pixel_move(f, &px, 4, &q), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_pixel_move(f, &px, HPFC_WEST, &q), HPFC_E_NO_PIXEL);
    CHECK_EQ_INT(hpfc_pixel_move(f, &px, HPFC_NORTH, &q), HPFC_E_NO_PIXEL);
    CHECK_EQ_INT(hpfc_pixel_type(f, &px, NULL), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_pixel_word(f, &px, NULL, 0, NULL), HPFC_E_ARG);
    /* forged pixels are refused, not followed */
    q = px;
    q.depth = HPFC_MAX_LEVELS;
    CHECK_EQ_INT(hpfc_pixel_type(f, &q, &type), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_pixel_parent(&q, &q), HPFC_E_ARG);
    q = px;
    q.path[0].image = 5;
    CHECK_EQ_INT(hpfc_pixel_type(f, &q, &type), HPFC_E_ARG);
    q = px;
    q.path[0].i = 7;
    CHECK_EQ_INT(hpfc_pixel_word(f, &q, NULL, 0, &len), HPFC_E_ARG);
    int64_t x0, y0, x1, y1;
    CHECK_EQ_INT(hpfc_pixel_bounds(f, &q, &x0, &y0, &x1, &y1), HPFC_E_ARG);
    hpfc_level_info li;
    CHECK_EQ_INT(hpfc_file_get_level(f, 0, &li), HPFC_OK);
    if (li.refined_pixels) {
        hpfc_pixel child;
        for (uint32_t j = 0; j < 2; j++)
            for (uint32_t i = 0; i < 2; i++) {
                CHECK_EQ_INT(hpfc_pixel_root(f, i, j, &px), HPFC_OK);
                hpfc_pixel_type(f, &px, &type);
                if (type != HPFC_PIXEL_REFINED)
                    continue;
                CHECK_EQ_INT(hpfc_pixel_child(f, &px, 0, 0, &child), HPFC_OK);
                q = child;
                q.path[1].image = li.pool_bits * 1000; /* beyond its pool */
                CHECK_EQ_INT(hpfc_pixel_type(f, &q, &type), HPFC_E_CORRUPT);
                /* child may alias its input */
                q = px;
                CHECK_EQ_INT(hpfc_pixel_child(f, &q, 1, 1, &q), HPFC_OK);
                CHECK_EQ_INT(q.depth, 1);
            }
    }
    hpfc_close(f);
    free(buf);
}

/* Graphs whose root is a single pixel or whose tree is flat. */
static void test_small_shapes(void)
{
    for (int which = 0; which < GEN_SPECIAL_COUNT; which++) {
        hpfc_tree *t = special_tree(which, 1);
        if (!t)
            continue;
        hpfc_tree_info info;
        hpfc_tree_get_info(t, &info);
        CHECK(info.levels >= 2);
        round_trip(t, NULL, 900 + (uint64_t)which);
        hpfc_tree_free(t);
    }
}

int main(void)
{
    test_layout_compact = check_use_test_layout();
    test_fig7_file();
    test_arguments();
    test_small_shapes();
    test_generated();
    test_pool_corruption();
    printf("round trips: %ld trees (%ld of one level, up to %u levels), %ld pixels, %ld moves "
           "(%ld by full search), %ld located points\n",
           covered.trees, covered.one_level_trees, covered.max_levels, covered.pixels, covered.moves,
           covered.brute_moves, covered.locates);
    return check_report("test_navigate");
}
