/*
 * Tests of the .hpfc writer and reader (spec/hpfc-format.md): generated
 * graphs are built, serialised, reopened and walked through the reader's
 * navigation, pixel by pixel against the in-memory tree and against naive
 * geometric oracles; every metadata byte is mutated, every metadata prefix
 * truncated, pool bits flipped under a bounded walk; the atomic file writer
 * is made to fail; and the fixtures of $HPFC_TEST_DATA/{valid,invalid} are
 * opened.
 */
#include <dirent.h>
#include <errno.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include "check.h"
#include "fixtures.h"
#include "format.h"
#include "pool.h"
#include "gen.h"
#include "hpfc.h"
#include "reader.h"
#include "tree.h"
#include "tree_oracle.h"

#define BIT(code) ((uint64_t)1 << (code))

/* What the round trips covered, reported at the end (a sweep that silently
 * shrank would show here). */
/* the layout under test (check_use_test_layout) */
static int test_layout_compact;

static struct {
    long trees, one_level_trees, pixels, moves, brute_moves, locates;
    uint32_t max_levels;
} covered;

/* ---- helpers --------------------------------------------------------------- */

typedef struct shape {
    uint32_t n0, m0, n, m;
    int flat;
} shape;

static hpfc_tree *build(const hpfc_graph *g, const shape *sh)
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

static uint8_t *serialize(const hpfc_tree *t, const char *crs, size_t *size)
{
    hpfc_write_options opts = {.crs = crs};
    uint8_t *buf = NULL;
    hpfc_diag d;
    int st = hpfc_tree_serialize(t, &opts, &buf, size, &d);
    if (st)
        fprintf(stderr, "serialize failed: %s: %s\n", hpfc_strerror(st), d.message);
    CHECK_EQ_INT(st, HPFC_OK);
    return buf;
}

static int open_buf(const uint8_t *buf, size_t size, unsigned flags)
{
    hpfc_file *f = NULL;
    int st = hpfc_open_memory(buf, size, flags, &f);
    CHECK((st == HPFC_OK) == (f != NULL));
    hpfc_close(f);
    return st;
}

static bool same_pixel(const hpfc_pixel *a, const hpfc_pixel *b)
{
    if (a->depth != b->depth)
        return false;
    for (uint32_t l = 0; l <= a->depth; l++)
        if (a->path[l].image != b->path[l].image || a->path[l].i != b->path[l].i ||
            a->path[l].j != b->path[l].j)
            return false;
    return true;
}

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

/* ---- CRC-32C and bit streams ---------------------------------------------------- */

static void test_crc32c(void)
{
    CHECK_EQ_INT(crc32c_update(0, "123456789", 9), 0xE3069283u);
    CHECK_EQ_INT(crc32c_update(0, "", 0), 0);
    uint8_t buf[1000];
    for (size_t k = 0; k < sizeof buf; k++)
        buf[k] = (uint8_t)(k * 131 + 7);
    uint32_t whole = crc32c_update(0, buf, sizeof buf);
    for (size_t cut = 0; cut <= sizeof buf; cut += 37) /* chaining, every alignment */
        CHECK_EQ_INT(crc32c_update(crc32c_update(0, buf, cut), buf + cut, sizeof buf - cut), whole);
    uint32_t bytewise = 0;
    for (size_t k = 0; k < sizeof buf; k++)
        bytewise = crc32c_update(bytewise, buf + k, 1);
    CHECK_EQ_INT(bytewise, whole);
}

static void test_bit_streams(void)
{
    gen_rng rng;
    gen_rng_seed(&rng, 7);
    enum { BYTES = 256, FIELDS = 40 };
    uint8_t pool[BYTES];
    for (int round = 0; round < 200; round++) {
        memset(pool, 0, sizeof pool);
        uint64_t off[FIELDS], val[FIELDS], at = gen_rng_below(&rng, 8);
        unsigned k[FIELDS];
        for (int f = 0; f < FIELDS; f++) {
            k[f] = (unsigned)gen_rng_below(&rng, 65);
            val[f] = k[f] == 64 ? gen_rng_next(&rng) : gen_rng_next(&rng) & (((uint64_t)1 << k[f]) - 1);
            off[f] = at;
            format_put(pool, at, k[f], val[f]);
            at += k[f];
        }
        /* avail is cut at the last byte used, so reads near the end take
         * the byte-by-byte path */
        format_bits b = {pool, at, format_pool_bytes(at)};
        uint64_t ones = 0;
        for (int f = 0; f < FIELDS; f++) {
            CHECK(format_get(&b, off[f], k[f]) == val[f]);
            ones += (uint64_t)__builtin_popcountll(val[f]);
        }
        CHECK_EQ_INT(format_popcount(&b, 0, at), ones);
    }
    /* the first bit of a pool is the most significant bit of its first byte */
    memset(pool, 0, sizeof pool);
    format_put(pool, 0, 1, 1);
    format_put(pool, 9, 3, 5);
    CHECK_EQ_INT(pool[0], 0x80);
    CHECK_EQ_INT(pool[1], 0x50);
    /* the word code table round-trips */
    for (unsigned c = 8; c < FORMAT_CODE_RESERVED_MIN; c++)
        CHECK_EQ_INT(format_symbol_code(format_code_symbol(c)), (int)c);
    CHECK_EQ_INT(format_symbol_code('+'), -1);
}

/* ---- Fig. 7 --------------------------------------------------------------------------- */

/* The paper's Fig. 4 tree as level statistics (Sect. 4.5). */
static void test_fig7_arithmetic(void)
{
    format_level lv[3] = {
        {8, 4, 1, 20, 0, 0},   /* root 4x3: 4 refined + 8 word pixels, k_w = 20 */
        {10, 6, 4, 20, 0, 0},  /* 4 images: 6 refined + 10 word, k_w = 20 */
        {24, 0, 6, 16, 0, 0},  /* 6 images of 4 word pixels, k_w = 16 */
    };
    CHECK(format_level_sizes(lv, 3, 4 * 3, 2 * 2));
    CHECK_EQ_INT(lv[2].pool_bits, 408);
    CHECK_EQ_INT(lv[2].address_bits, 0);
    CHECK_EQ_INT(lv[1].address_bits, 9);
    CHECK_EQ_INT(lv[1].pool_bits, 270);
    CHECK_EQ_INT(lv[0].address_bits, 9);
    CHECK_EQ_INT(lv[0].pool_bits, 252);
    /* address bits: just enough for every bit offset of the next pool */
    CHECK_EQ_INT(format_address_bits(0), 0);
    CHECK_EQ_INT(format_address_bits(1), 0);
    CHECK_EQ_INT(format_address_bits(2), 1);
    CHECK_EQ_INT(format_address_bits(512), 9);
    CHECK_EQ_INT(format_address_bits(513), 10);
    CHECK_EQ_INT(format_address_bits(UINT64_MAX), 64);
    format_level big[2] = {{0, 1, 1, 0, 0, 0}, {UINT64_MAX / 2, 0, 1, 16, 0, 0}};
    CHECK(!format_level_sizes(big, 2, 1, 4)); /* overflow is refused */
}

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
    if (len > 4) /* a too small buffer: the length, HPFC_E_ARG */
        CHECK_EQ_INT(hpfc_pixel_word(w->f, px, buf, 4, &len2), HPFC_E_ARG);
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
    CHECK_EQ_INT(fi.format_minor, 2);
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
    CHECK_EQ_INT(hpfc_verify_checksums(w->f), HPFC_OK);
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
        free(buf);
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
    free(buf);
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
    /* spec §6 (paper) and §16.7 (compact): the sizes worked by hand */
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
    free(buf);
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

/* A graph whose tree is several levels deep, written with a CRS: the
 * subject of the mutation tests. */
static uint8_t *sample_file(size_t *size, uint32_t *levels)
{
    hpfc_graph *g = NULL;
    CHECK_EQ_INT(gen_delaunay(11, 40, 1 << 10, 0.2, &g), HPFC_OK);
    const shape sh = {4, 3, 2, 2, 0};
    hpfc_tree *t = g ? build(g, &sh) : NULL;
    uint8_t *buf = t ? serialize(t, "EPSG:32631", size) : NULL;
    hpfc_tree_info info = {0};
    if (t)
        hpfc_tree_get_info(t, &info);
    *levels = info.levels;
    CHECK(info.levels >= 3);
    hpfc_tree_free(t);
    hpfc_graph_free(g);
    return buf;
}

/* ---- bounded walk over a possibly corrupt file ------------------------------------- */

typedef struct probe {
    const hpfc_file *f;
    hpfc_file_info info;
    long budget;
    uint64_t codes; /* BIT(status) of every status seen */
} probe;

static void note(probe *p, int st)
{
    p->codes |= BIT(st);
}

/* A word pixel's word; HPFC_E_ARG only when the buffer is too small. */
static void probe_word(probe *p, const hpfc_pixel *px)
{
    char buf[64];
    size_t len = 0;
    int st = hpfc_pixel_word(p->f, px, buf, sizeof buf, &len);
    note(p, st == HPFC_E_ARG && len > sizeof buf ? HPFC_OK : st);
}

static void probe_pixel(probe *p, const hpfc_pixel *px)
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
static uint64_t probe_file(const hpfc_file *f, long budget)
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
        CHECK_EQ_INT(hpfc_verify_checksums(f), HPFC_E_CHECKSUM);
        hpfc_close(f);
        flips++;
    }
    /* the compact pools of this map are about a third of the paper's */
    CHECK(flips > (test_layout_compact ? 300u : 1000u));
    CHECK(corrupt > (test_layout_compact ? 30u : 100u)); /* some flips must be detected while navigating */
    printf("pool corruption: %zu flips, %zu detected while navigating\n", flips, corrupt);
    free(copy);
    free(buf);
}

/* ---- metadata mutations ------------------------------------------------------------ */

typedef struct field {
    char name[40];
    size_t off, size;
    uint64_t fixed;  /* statuses allowed once the meta checksum is recomputed */
    uint64_t raw;    /* ... and without recomputing it */
    uint64_t verify; /* hpfc_verify_checksums after an accepted mutation */
} field;

typedef struct field_list {
    field f[512];
    size_t n;
} field_list;

static void add_field(field_list *L, const char *name, size_t off, size_t size, uint64_t fixed, uint64_t raw,
                      uint64_t verify)
{
    if (L->n == sizeof L->f / sizeof L->f[0])
        return;
    field *f = &L->f[L->n++];
    snprintf(f->name, sizeof f->name, "%s", name);
    f->off = off, f->size = size, f->fixed = fixed, f->raw = raw, f->verify = verify;
}

#define OKB BIT(HPFC_OK)
#define CSUM BIT(HPFC_E_CHECKSUM)
#define HDR(name, fixed) add_field(L, "header." #name, hdr_OFF_##name, hdr_SIZE_##name, fixed, CSUM, OKB)

static void header_fields(field_list *L)
{
    const uint64_t H = BIT(HPFC_E_HEADER), LT = BIT(HPFC_E_LEVEL_TABLE);
    add_field(L, "header.magic", hdr_OFF_magic, hdr_SIZE_magic, BIT(HPFC_E_MAGIC), BIT(HPFC_E_MAGIC), 0);
    add_field(L, "header.format_major", hdr_OFF_format_major, hdr_SIZE_format_major, BIT(HPFC_E_VERSION),
              BIT(HPFC_E_VERSION), 0);
    HDR(format_minor, OKB); /* a higher minor is compatible */
    add_field(L, "header.header_size", hdr_OFF_header_size, hdr_SIZE_header_size, H, H | CSUM, 0);
    HDR(compat_flags, OKB);
    /* unknown bits are refused; bit 0 (compact pool) reads the level table
     * in the other layout, whose sizes then disagree */
    HDR(incompat_flags, BIT(HPFC_E_INCOMPATIBLE) | BIT(HPFC_E_LEVEL_TABLE));
    HDR(root_cols, H | LT);
    HDR(root_rows, H | LT);
    HDR(cols, H | LT);
    HDR(rows, H | LT);
    HDR(levels, H);
    HDR(section_count, H);
    HDR(x0, OKB | H);
    HDR(y0, OKB | H);
    HDR(width, OKB | H); /* another multiple of n0 * n^(levels-1) is valid */
    HDR(height, OKB | H);
    HDR(unit_exp10, OKB | H);
    HDR(reserved0, H);
    HDR(file_size, H | BIT(HPFC_E_TRUNCATED));
    add_field(L, "header.meta_size", hdr_OFF_meta_size, hdr_SIZE_meta_size, H | BIT(HPFC_E_TRUNCATED),
              H | BIT(HPFC_E_TRUNCATED) | CSUM, 0);
    HDR(reserved1, H);
    HDR(reserved2, H);
    add_field(L, "header.meta_crc32c", hdr_OFF_meta_crc32c, hdr_SIZE_meta_crc32c, 0, CSUM, 0);
}

#define LVL(name, fixed)                                                                     \
    do {                                                                                     \
        snprintf(name_buf, sizeof name_buf, "level%u." #name, l);                            \
        add_field(L, name_buf, base + lvl_OFF_##name, lvl_SIZE_##name, fixed, CSUM, OKB);    \
    } while (0)

static void level_fields(field_list *L, const uint8_t *buf)
{
    uint32_t levels = hdr_get_levels(buf);
    const uint64_t LT = BIT(HPFC_E_LEVEL_TABLE);
    char name_buf[40];
    for (uint32_t l = 0; l < levels; l++) {
        size_t base = FORMAT_HEADER_SIZE + (size_t)l * FORMAT_LEVEL_ENTRY_SIZE;
        const uint8_t *e = buf + base;
        LVL(word_pixels, LT);
        LVL(refined_pixels, LT);
        LVL(images, LT);
        /* k_w leaves the sizes alone when no word uses it, or at the root
         * while k_@ is the wider payload */
        bool loose = lvl_get_word_pixels(e) == 0 || (l == 0 && lvl_get_word_bits(e) < lvl_get_address_bits(e));
        /* compact: k_w bounds the words, the sizes do not depend on it */
        loose = loose || (hdr_get_incompat_flags(buf) & FORMAT_INCOMPAT_COMPACT_POOL);
        LVL(word_bits, LT | (loose ? OKB : 0));
        LVL(address_bits, LT);
        LVL(pool_offset, LT);
        LVL(pool_bits, LT);
        LVL(reserved, LT);
    }
}

#define SEC(name, fixed, verify)                                                             \
    do {                                                                                     \
        snprintf(name_buf, sizeof name_buf, "section%u." #name, k);                          \
        add_field(L, name_buf, base + sec_OFF_##name, sec_SIZE_##name, fixed, CSUM, verify); \
    } while (0)

static void section_fields(field_list *L, const uint8_t *buf)
{
    uint32_t levels = hdr_get_levels(buf), count = hdr_get_section_count(buf);
    const uint64_t S = BIT(HPFC_E_SECTION), LT = BIT(HPFC_E_LEVEL_TABLE);
    char name_buf[40];
    for (uint32_t k = 0; k < count; k++) {
        size_t base = FORMAT_HEADER_SIZE + (size_t)levels * FORMAT_LEVEL_ENTRY_SIZE +
                      (size_t)k * FORMAT_SECTION_ENTRY_SIZE;
        bool pool = memcmp(buf + base, "POOL", 4) == 0;
        if (pool) {
            SEC(tag, BIT(HPFC_E_INCOMPATIBLE) | S, OKB);
            SEC(flags, OKB | S, OKB); /* REQUIRED may be dropped from a known tag */
            SEC(offset, S | LT, OKB);
            SEC(length, OKB | S | LT, OKB | CSUM); /* growing into the padding is fine */
        } else { /* CRS, the last section */
            SEC(tag, OKB | S, OKB); /* an unknown optional section is ignored */
            SEC(flags, OKB | S, OKB);
            SEC(offset, S, OKB);
            SEC(length, OKB | S, OKB | CSUM);
        }
        SEC(crc32c, OKB, CSUM);
        SEC(reserved, S, OKB);
    }
}

/* The field's bytes replaced by each test value in turn: every bit flipped,
 * every byte 0x00 and 0xFF, and the whole field 0, 1, all ones, its value
 * plus and minus one, and its top bit set. */
static size_t mutations(const field *fd, const uint8_t *orig, uint8_t out[][16])
{
    size_t n = 0;
    for (size_t b = 0; b < fd->size; b++) {
        for (int bit = 0; bit < 8; bit++, n++) {
            memcpy(out[n], orig, fd->size);
            out[n][b] ^= (uint8_t)(1u << bit);
        }
        memcpy(out[n], orig, fd->size), out[n++][b] = 0x00;
        memcpy(out[n], orig, fd->size), out[n++][b] = 0xFF;
    }
    unsigned sz = (unsigned)fd->size <= 8 ? (unsigned)fd->size : 8;
    uint64_t v = le_load(orig, sz);
    const uint64_t values[] = {0, 1, UINT64_MAX, v + 1, v - 1, (uint64_t)1 << (8 * sz - 1), v ^ ((uint64_t)1 << (8 * sz - 1))};
    for (size_t k = 0; k < sizeof values / sizeof *values && fd->size <= 8; k++) {
        le_store(out[n++], sz, values[k]);
    }
    return n;
}

static void mutate_field(const field *fd, const uint8_t *buf, size_t size, uint8_t *copy, long *tried)
{
    static uint8_t values[16 * 10 + 8][16];
    size_t nv = mutations(fd, buf + fd->off, values);
    for (size_t v = 0; v < nv; v++) {
        if (memcmp(values[v], buf + fd->off, fd->size) == 0)
            continue;
        (*tried)++;
        memcpy(copy, buf, size);
        memcpy(copy + fd->off, values[v], fd->size);
        int raw = open_buf(copy, size, 0);
        int skip = open_buf(copy, size, HPFC_OPEN_SKIP_CHECKSUM);
        if (!(BIT(raw) & fd->raw))
            fprintf(stderr, "%s mutation %zu: %s without a new checksum\n", fd->name, v, hpfc_strerror(raw));
        CHECK(BIT(raw) & fd->raw);
        uint64_t meta = hdr_get_meta_size(copy);
        if (!fd->fixed || meta < FORMAT_HEADER_SIZE || meta > size)
            continue;
        hdr_set_meta_crc32c(copy, format_meta_crc(copy, meta));
        hpfc_file *f = NULL;
        int st = hpfc_open_memory(copy, size, 0, &f);
        if (!(BIT(st) & fd->fixed))
            fprintf(stderr, "%s mutation %zu: %s\n", fd->name, v, hpfc_strerror(st));
        CHECK(BIT(st) & fd->fixed);
        CHECK_EQ_INT(skip, st); /* skipping the checksum reaches the same field check */
        if (!f)
            continue;
        CHECK(BIT(hpfc_verify_checksums(f)) & fd->verify);
        uint64_t codes = probe_file(f, 2000);
        CHECK((codes & ~(OKB | BIT(HPFC_E_NO_PIXEL) | BIT(HPFC_E_CORRUPT))) == 0);
        hpfc_close(f);
    }
}

static void test_metadata_mutations(void)
{
    size_t size = 0;
    uint32_t levels = 0;
    uint8_t *buf = sample_file(&size, &levels);
    if (!buf)
        return;
    static field_list L;
    L.n = 0;
    header_fields(&L);
    level_fields(&L, buf);
    section_fields(&L, buf);
    CHECK_EQ_INT(L.n, 23 + 8 * levels + 2 * 6);
    /* the table covers every metadata byte exactly once */
    uint64_t meta = hdr_get_meta_size(buf);
    uint8_t *cover = calloc(1, (size_t)meta);
    for (size_t k = 0; k < L.n; k++)
        for (size_t b = 0; b < L.f[k].size; b++)
            cover[L.f[k].off + b]++;
    for (uint64_t b = 0; b < meta; b++)
        CHECK_EQ_INT(cover[b], 1);
    free(cover);
    uint8_t *copy = malloc(size);
    long tried = 0;
    for (size_t k = 0; k < L.n; k++)
        mutate_field(&L.f[k], buf, size, copy, &tried);
    CHECK(tried > 5000);
    free(copy);
    free(buf);
}

/* A later minor version may grow the header: the level table then starts at
 * header_size, and a 1.0 reader skips the bytes it does not know. */
static void test_header_extension(void)
{
    size_t size = 0;
    uint32_t levels = 0;
    uint8_t *buf = sample_file(&size, &levels);
    if (!buf)
        return;
    enum { EXTRA = 16 };
    uint8_t *big = calloc(1, size + EXTRA);
    memcpy(big, buf, FORMAT_HEADER_SIZE);
    memset(big + FORMAT_HEADER_SIZE, 0xA5, EXTRA); /* unknown header bytes */
    memcpy(big + FORMAT_HEADER_SIZE + EXTRA, buf + FORMAT_HEADER_SIZE, size - FORMAT_HEADER_SIZE);
    hdr_set_header_size(big, FORMAT_HEADER_SIZE + EXTRA);
    hdr_set_meta_size(big, hdr_get_meta_size(buf) + EXTRA);
    hdr_set_file_size(big, size + EXTRA);
    hdr_set_format_minor(big, 7);
    for (uint32_t l = 0; l < levels; l++) {
        uint8_t *e = big + FORMAT_HEADER_SIZE + EXTRA + (size_t)l * FORMAT_LEVEL_ENTRY_SIZE;
        lvl_set_pool_offset(e, lvl_get_pool_offset(e) + EXTRA);
    }
    for (uint32_t k = 0; k < hdr_get_section_count(big); k++) {
        uint8_t *e = big + FORMAT_HEADER_SIZE + EXTRA + (size_t)levels * FORMAT_LEVEL_ENTRY_SIZE +
                     (size_t)k * FORMAT_SECTION_ENTRY_SIZE;
        sec_set_offset(e, sec_get_offset(e) + EXTRA);
    }
    hdr_set_meta_crc32c(big, format_meta_crc(big, hdr_get_meta_size(big)));
    hpfc_file *a = NULL, *b = NULL;
    CHECK_EQ_INT(hpfc_open_memory(buf, size, 0, &a), HPFC_OK);
    CHECK_EQ_INT(hpfc_open_memory(big, size + EXTRA, 0, &b), HPFC_OK);
    if (a && b) {
        CHECK_EQ_INT(hpfc_verify_checksums(b), HPFC_OK);
        hpfc_file_info fa, fb;
        hpfc_file_get_info(a, &fa);
        hpfc_file_get_info(b, &fb);
        CHECK_EQ_INT(fb.format_minor, 7);
        CHECK(fb.crs_len == fa.crs_len && memcmp(fb.crs, fa.crs, fa.crs_len) == 0);
        gen_rng rng;
        gen_rng_seed(&rng, 3);
        for (int k = 0; k < 2000; k++) { /* the same leaves and words */
            int64_t x = fa.x0 + (int64_t)gen_rng_below(&rng, (uint64_t)fa.width);
            int64_t y = fa.y0 + (int64_t)gen_rng_below(&rng, (uint64_t)fa.height);
            hpfc_pixel pa, pb;
            char wa[512], wb[512];
            size_t la = 0, lb = 0;
            CHECK_EQ_INT(hpfc_locate(a, x, y, &pa), HPFC_OK);
            CHECK_EQ_INT(hpfc_locate(b, x, y, &pb), HPFC_OK);
            CHECK(same_pixel(&pa, &pb));
            CHECK_EQ_INT(hpfc_pixel_word(a, &pa, wa, sizeof wa, &la), HPFC_OK);
            CHECK_EQ_INT(hpfc_pixel_word(b, &pb, wb, sizeof wb, &lb), HPFC_OK);
            CHECK(la == lb && memcmp(wa, wb, la) == 0);
        }
    }
    hpfc_close(a);
    hpfc_close(b);
    free(big);
    free(buf);
}

/* Sections at one offset must both be empty; an empty section may sit at
 * the end of another. */
static void test_section_overlaps(void)
{
    size_t size = 0;
    uint32_t levels = 0;
    uint8_t *buf = sample_file(&size, &levels);
    if (!buf)
        return;
    uint8_t *pool = buf + FORMAT_HEADER_SIZE + (size_t)levels * FORMAT_LEVEL_ENTRY_SIZE;
    uint8_t *crs = pool + FORMAT_SECTION_ENTRY_SIZE;
    CHECK(memcmp(crs, "CRS ", 4) == 0);
    uint64_t pool_end = sec_get_offset(pool) + sec_get_length(pool);
    const struct {
        uint64_t offset, length;
        int want;
    } cases[] = {
        {sec_get_offset(pool), 0, HPFC_E_SECTION},     /* at POOL's start */
        {sec_get_offset(pool) + 8, 0, HPFC_E_SECTION}, /* inside POOL */
        {sec_get_offset(crs), 0, HPFC_OK},             /* after POOL, empty */
        {format_align8(pool_end) - 8, 8, HPFC_E_SECTION},
        {sec_get_offset(crs) + 1, 1, HPFC_E_SECTION},  /* misaligned */
    };
    for (size_t k = 0; k < sizeof cases / sizeof *cases; k++) {
        uint8_t *copy = malloc(size);
        memcpy(copy, buf, size);
        uint8_t *e = copy + (crs - buf);
        sec_set_offset(e, cases[k].offset);
        sec_set_length(e, cases[k].length);
        sec_set_crc32c(e, crc32c_update(0, copy + cases[k].offset, (size_t)cases[k].length));
        hdr_set_meta_crc32c(copy, format_meta_crc(copy, hdr_get_meta_size(copy)));
        CHECK_EQ_INT(open_buf(copy, size, 0), cases[k].want);
        free(copy);
    }
    /* the same two sections in the other directory order */
    uint8_t *copy = malloc(size);
    memcpy(copy, buf, size);
    uint8_t *e0 = copy + (pool - buf), *e1 = copy + (crs - buf), tmp[FORMAT_SECTION_ENTRY_SIZE];
    memcpy(tmp, e0, sizeof tmp);
    memcpy(e0, e1, sizeof tmp);
    memcpy(e1, tmp, sizeof tmp);
    hdr_set_meta_crc32c(copy, format_meta_crc(copy, hdr_get_meta_size(copy)));
    CHECK_EQ_INT(open_buf(copy, size, 0), HPFC_OK);
    sec_set_offset(e0, sec_get_offset(e1)); /* CRS at POOL's offset */
    sec_set_length(e0, 0);
    hdr_set_meta_crc32c(copy, format_meta_crc(copy, hdr_get_meta_size(copy)));
    CHECK_EQ_INT(open_buf(copy, size, 0), HPFC_E_SECTION);
    free(copy);
    free(buf);
}

/* Every prefix of the metadata, and some of the pools, is TRUNCATED: the
 * header states the file size. A longer buffer is a HEADER error. */
static void test_truncation(void)
{
    size_t size = 0;
    uint32_t levels = 0;
    uint8_t *buf = sample_file(&size, &levels);
    if (!buf)
        return;
    uint64_t meta = hdr_get_meta_size(buf);
    size_t cuts[] = {(size_t)meta + 1, (size_t)meta + 8, size / 2, size - 8, size - 1};
    for (size_t cut = 0; cut <= size; cut++) {
        bool in_meta = cut <= meta;
        bool listed = false;
        for (size_t k = 0; k < sizeof cuts / sizeof *cuts; k++)
            listed |= cuts[k] == cut;
        if (!in_meta && !listed)
            continue;
        uint8_t *part = malloc(cut ? cut : 1); /* exact size: ASan sees over-reads */
        memcpy(part, buf, cut);
        int st = open_buf(part, cut, 0);
        if (st != HPFC_E_TRUNCATED)
            fprintf(stderr, "cut at %zu of %zu: %s\n", cut, size, hpfc_strerror(st));
        CHECK_EQ_INT(st, HPFC_E_TRUNCATED);
        free(part);
    }
    uint8_t *longer = malloc(size + 1);
    memcpy(longer, buf, size);
    longer[size] = 0;
    CHECK_EQ_INT(open_buf(longer, size + 1, 0), HPFC_E_HEADER);
    /* a prefix that is not the magic's is not an hpfc file, however short */
    longer[0] = 'P';
    CHECK_EQ_INT(open_buf(longer, 1, 0), HPFC_E_MAGIC);
    CHECK_EQ_INT(open_buf(longer, 100, 0), HPFC_E_MAGIC);
    free(longer);
    free(buf);
}

/* ---- files: atomic writes, hpfc_open -------------------------------------------------- */

static uint8_t *read_all(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    size_t cap = 1 << 16, n = 0;
    uint8_t *buf = malloc(cap);
    for (size_t got; (got = fread(buf + n, 1, cap - n, f)) > 0;) {
        n += got;
        if (n == cap)
            buf = realloc(buf, cap *= 2);
    }
    fclose(f);
    *size = n;
    return buf;
}

static bool file_equals(const char *path, const uint8_t *want, size_t size)
{
    size_t n = 0;
    uint8_t *got = read_all(path, &n);
    bool same = got && n == size && memcmp(got, want, size) == 0;
    free(got);
    return same;
}

/* Number of entries in dir, "." and ".." excluded. */
static int dir_entries(const char *dir)
{
    DIR *d = opendir(dir);
    int n = 0;
    if (!d)
        return -1;
    for (struct dirent *de; (de = readdir(d));)
        n += strcmp(de->d_name, ".") && strcmp(de->d_name, "..");
    closedir(d);
    return n;
}

static hpfc_tree *special_tree(int which, uint32_t n0)
{
    hpfc_graph *g = NULL;
    CHECK_EQ_INT(gen_special(which, &g), HPFC_OK);
    const shape sh = {n0, n0, 2, 2, 0};
    hpfc_tree *t = g ? build(g, &sh) : NULL;
    hpfc_graph_free(g);
    return t;
}

static void test_write_file(void)
{
    char dir[] = "/tmp/hpfc-test-format-XXXXXX";
    CHECK(mkdtemp(dir) != NULL);
    char path[256], sub[256], bad[256];
    snprintf(path, sizeof path, "%s/map.hpfc", dir);
    snprintf(sub, sizeof sub, "%s/sub", dir);
    snprintf(bad, sizeof bad, "%s/no/such/dir/map.hpfc", dir);
    hpfc_tree *a = special_tree(GEN_SPECIAL_TRIANGLE, 4), *b = special_tree(GEN_SPECIAL_HOLE, 3);
    if (!a || !b)
        return;
    size_t size_a, size_b;
    uint8_t *buf_a = serialize(a, NULL, &size_a), *buf_b = serialize(b, "EPSG:4326", &size_b);
    hpfc_diag d;

    /* a missing directory: a clean failure, nothing created */
    CHECK_EQ_INT(hpfc_tree_write_file(a, NULL, bad, &d), HPFC_E_IO);
    CHECK_EQ_INT(d.status, HPFC_E_IO);
    CHECK_EQ_INT(dir_entries(dir), 0);

    /* a new file, then a replacement */
    CHECK_EQ_INT(hpfc_tree_write_file(a, NULL, path, &d), HPFC_OK);
    CHECK(file_equals(path, buf_a, size_a));
    CHECK_EQ_INT(dir_entries(dir), 1);
    hpfc_write_options opts = {.crs = "EPSG:4326"};
    CHECK_EQ_INT(hpfc_tree_write_file(b, &opts, path, &d), HPFC_OK);
    CHECK(file_equals(path, buf_b, size_b));
    CHECK_EQ_INT(dir_entries(dir), 1);

    /* hpfc_open maps it */
    hpfc_file *f = NULL;
    CHECK_EQ_INT(hpfc_open(path, 0, &f), HPFC_OK);
    if (f) {
        hpfc_file_info fi;
        hpfc_file_get_info(f, &fi);
        CHECK(fi.crs_len == 9 && memcmp(fi.crs, "EPSG:4326", 9) == 0);
        CHECK_EQ_INT(hpfc_verify_checksums(f), HPFC_OK);
        CHECK_EQ_INT(probe_file(f, 1 << 20) & ~(OKB | BIT(HPFC_E_NO_PIXEL)), 0);
    }
    hpfc_close(f);

    /* a write that fails half-way (file size limit): the old file stays
     * byte-identical and no temporary is left */
    struct rlimit old_limit, small;
    if (getrlimit(RLIMIT_FSIZE, &old_limit) == 0) {
        void (*old_handler)(int) = signal(SIGXFSZ, SIG_IGN);
        small = old_limit;
        small.rlim_cur = 64;
        CHECK_EQ_INT(setrlimit(RLIMIT_FSIZE, &small), 0);
        CHECK_EQ_INT(hpfc_tree_write_file(a, NULL, path, &d), HPFC_E_IO);
        CHECK_EQ_INT(setrlimit(RLIMIT_FSIZE, &old_limit), 0);
        signal(SIGXFSZ, old_handler);
        CHECK(file_equals(path, buf_b, size_b));
        CHECK_EQ_INT(dir_entries(dir), 1);
    }

    /* the target is a directory: the rename fails, nothing changes */
    CHECK_EQ_INT(mkdir(sub, 0755), 0);
    CHECK_EQ_INT(hpfc_tree_write_file(a, NULL, sub, &d), HPFC_E_IO);
    CHECK_EQ_INT(dir_entries(dir), 2);
    CHECK_EQ_INT(dir_entries(sub), 0);

    /* a directory we may not write to (meaningless for root) */
    if (geteuid() != 0) {
        CHECK_EQ_INT(chmod(dir, 0555), 0);
        CHECK_EQ_INT(hpfc_tree_write_file(a, NULL, path, &d), HPFC_E_IO);
        CHECK_EQ_INT(chmod(dir, 0755), 0);
        CHECK(file_equals(path, buf_b, size_b));
        CHECK_EQ_INT(dir_entries(dir), 2);
    }

    /* hpfc_open's failures */
    CHECK_EQ_INT(hpfc_open(bad, 0, &f), HPFC_E_IO);
    CHECK(f == NULL);
    CHECK_EQ_INT(hpfc_open(sub, 0, &f), HPFC_E_IO);
    char empty[256];
    snprintf(empty, sizeof empty, "%s/empty.hpfc", dir);
    FILE *e = fopen(empty, "wb");
    CHECK(e != NULL);
    if (e)
        fclose(e);
    CHECK_EQ_INT(hpfc_open(empty, 0, &f), HPFC_E_TRUNCATED);
    CHECK_EQ_INT(hpfc_open(NULL, 0, &f), HPFC_E_ARG);

    CHECK_EQ_INT(hpfc_tree_write_file(a, NULL, NULL, &d), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_tree_write_file(NULL, NULL, path, &d), HPFC_E_ARG);
    remove(empty);
    remove(path);
    rmdir(sub);
    CHECK_EQ_INT(rmdir(dir), 0); /* empty: nothing stray was left */
    free(buf_a);
    free(buf_b);
    hpfc_tree_free(a);
    hpfc_tree_free(b);
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
    CHECK_EQ_INT(hpfc_verify_checksums(NULL), HPFC_E_ARG);
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

static void feat_fixture_make(feat_fixture *x, uint32_t faces)
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

static bool same_string(const char *s, size_t len, const char *want)
{
    return want ? s && len == strlen(want) && memcmp(s, want, len) == 0 : s == NULL;
}

/* Everything the reader gives back equals the table that was written. */
static void check_features_read_back(const hpfc_file *f, const feat_fixture *x)
{
    hpfc_features_info fi;
    CHECK_EQ_INT(hpfc_file_features(f, &fi), HPFC_OK);
    CHECK(fi.features == 7 && fi.layers == 2 && fi.faces == x->t.face_count &&
          fi.links == x->start[x->t.face_count]);
    CHECK(same_string(fi.key_field, fi.key_field_len, "NAME"));
    for (uint32_t k = 0; k < 7; k++) {
        hpfc_feature ft;
        CHECK_EQ_INT(hpfc_feature_get(f, k, &ft), HPFC_OK);
        CHECK(ft.fid == x->fid[k] && ft.layer == x->layer[k]);
        CHECK(same_string(ft.key, ft.key_len, x->key[k]));
    }
    for (uint32_t l = 0; l < 2; l++) {
        const char *name;
        size_t len;
        CHECK_EQ_INT(hpfc_layer_name(f, l, &name, &len), HPFC_OK);
        CHECK(same_string(name, len, x->layer_name[l]));
    }
    for (uint32_t face = 0; face < x->t.face_count; face++) {
        uint32_t count = 99, feature = 99;
        CHECK_EQ_INT(hpfc_face_feature_count(f, face, &count), HPFC_OK);
        CHECK_EQ_INT(count, face == 0 ? 0 : 1 + face % 2);
        for (uint32_t k = 0; k < count; k++) {
            CHECK_EQ_INT(hpfc_face_feature(f, face, k, &feature), HPFC_OK);
            CHECK_EQ_INT(feature, k == 0 ? face % 5 : 5 + face % 2);
        }
        CHECK_EQ_INT(hpfc_face_feature(f, face, count, &feature), HPFC_E_ARG);
    }
    hpfc_feature ft;
    uint32_t count;
    const char *name;
    size_t len;
    CHECK_EQ_INT(hpfc_feature_get(f, 7, &ft), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_layer_name(f, 2, &name, &len), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_face_feature_count(f, x->t.face_count, &count), HPFC_E_ARG);
}

/* Every accessor on a file whose FEAT bytes were changed: a status, never
 * a read outside the section (AddressSanitizer watches the exact buffer). */
static void probe_features(const hpfc_file *f)
{
    hpfc_features_info fi;
    if (hpfc_file_features(f, &fi) != HPFC_OK)
        return;
    for (uint32_t k = 0; k <= fi.features && k < 64; k++) {
        hpfc_feature ft;
        int st = hpfc_feature_get(f, k, &ft);
        CHECK(st == HPFC_OK || st == HPFC_E_ARG || st == HPFC_E_CORRUPT);
        if (st == HPFC_OK && ft.key)
            (void)memchr(ft.key, 0, ft.key_len);
    }
    for (uint32_t l = 0; l <= fi.layers && l < 8; l++) {
        const char *name;
        size_t len;
        int st = hpfc_layer_name(f, l, &name, &len);
        CHECK(st == HPFC_OK || st == HPFC_E_ARG || st == HPFC_E_CORRUPT);
        if (st == HPFC_OK)
            (void)memchr(name, 0, len);
    }
    for (uint32_t face = 0; face <= fi.faces && face < 64; face++) {
        uint32_t count = 0, feature;
        int st = hpfc_face_feature_count(f, face, &count);
        CHECK(st == HPFC_OK || st == HPFC_E_ARG || st == HPFC_E_CORRUPT);
        for (uint32_t k = 0; st == HPFC_OK && k < count && k < 16; k++) {
            int s2 = hpfc_face_feature(f, face, k, &feature);
            CHECK(s2 == HPFC_OK || s2 == HPFC_E_CORRUPT);
            CHECK(s2 != HPFC_OK || feature < fi.features);
        }
    }
}

static void test_features(void)
{
    hpfc_tree *t = special_tree(GEN_SPECIAL_HOLE, 3);
    if (!t)
        return;
    size_t plain_size, size;
    uint8_t *plain = serialize(t, "EPSG:4326", &plain_size);
    hpfc_file *f = NULL;
    hpfc_faces *fc = NULL;
    CHECK_EQ_INT(hpfc_open_memory(plain, plain_size, 0, &f), HPFC_OK);
    CHECK_EQ_INT(hpfc_faces_build(f, &fc), HPFC_OK);
    uint32_t faces = (uint32_t)hpfc_faces_count(fc);
    hpfc_features_info fi;
    CHECK_EQ_INT(hpfc_file_features(f, &fi), HPFC_E_NO_SECTION);
    hpfc_faces_free(fc);
    hpfc_close(f);
    CHECK(faces >= 3);

    feat_fixture x;
    feat_fixture_make(&x, faces);
    hpfc_write_options opts = {.crs = "EPSG:4326", .features = &x.t};
    uint8_t *buf = NULL;
    hpfc_diag d;
    CHECK_EQ_INT(hpfc_tree_serialize(t, &opts, &buf, &size, &d), HPFC_OK);
    /* the same pools, so the same faces; FEAT only adds a section */
    CHECK(buf && size > plain_size);
    f = NULL;
    CHECK_EQ_INT(hpfc_open_memory(buf, size, 0, &f), HPFC_OK);
    if (f) {
        CHECK_EQ_INT(hpfc_verify_checksums(f), HPFC_OK);
        CHECK_EQ_INT(hpfc_faces_build(f, &fc), HPFC_OK);
        CHECK_EQ_INT(hpfc_faces_count(fc), faces);
        hpfc_faces_free(fc);
        check_features_read_back(f, &x);
        hpfc_close(f);
    }

    /* every byte of the section set to 0x00, 0xFF and bit-flipped: open
     * refuses the file with a named code or every access stays in bounds */
    hpfc_section_info si = {0};
    CHECK_EQ_INT(hpfc_open_memory(buf, size, 0, &f), HPFC_OK);
    for (uint32_t k = 0; f && k < 3; k++)
        if (hpfc_file_get_section(f, k, &si) == HPFC_OK && memcmp(si.tag, "FEAT", 4) == 0)
            break;
    hpfc_close(f);
    CHECK(memcmp(si.tag, "FEAT", 4) == 0 && si.offset + si.length == size);
    for (uint64_t at = si.offset; at < si.offset + si.length; at++)
        for (int how = 0; how < 10; how++) {
            uint8_t *m = malloc(size);
            memcpy(m, buf, size);
            m[at] = how == 0 ? 0x00 : how == 1 ? 0xff : (uint8_t)(m[at] ^ (1u << (how - 2)));
            f = NULL;
            int st = hpfc_open_memory(m, size, HPFC_OPEN_SKIP_CHECKSUM, &f);
            CHECK(st == HPFC_OK || st == HPFC_E_SECTION);
            if (f) {
                CHECK_EQ_INT(hpfc_verify_checksums(f), m[at] == buf[at] ? HPFC_OK : HPFC_E_CHECKSUM);
                probe_features(f);
                hpfc_close(f);
            }
            free(m);
        }

    /* inconsistent tables are refused by the writer */
    free(buf);
    uint32_t saved = x.link[0];
    x.link[0] = 7; /* no such feature */
    CHECK_EQ_INT(hpfc_tree_serialize(t, &opts, &buf, &size, &d), HPFC_E_ARG);
    x.link[0] = saved;
    x.layer[2] = 2; /* no such layer */
    CHECK_EQ_INT(hpfc_tree_serialize(t, &opts, &buf, &size, &d), HPFC_E_ARG);
    x.layer[2] = 0;
    x.start[1] = 3, x.start[2] = 2; /* decreasing offsets */
    CHECK_EQ_INT(hpfc_tree_serialize(t, &opts, &buf, &size, &d), HPFC_E_ARG);
    CHECK(buf == NULL);
    free(x.start);
    free(x.link);
    free(plain);
    hpfc_tree_free(t);
}

/* ---- fixtures ------------------------------------------------------------------------------ */

/* Opens and verifies a fixture: the first failing status. */
static int open_and_verify(const char *path)
{
    hpfc_file *f = NULL;
    int st = hpfc_open(path, 0, &f);
    if (!st)
        st = hpfc_verify_checksums(f);
    if (!st) {
        uint64_t codes = probe_file(f, 1 << 20);
        st = codes & BIT(HPFC_E_CORRUPT) ? HPFC_E_CORRUPT : HPFC_OK;
        CHECK((codes & ~(OKB | BIT(HPFC_E_NO_PIXEL) | BIT(HPFC_E_CORRUPT))) == 0);
    }
    hpfc_close(f);
    return st;
}

static int check_hpfc_fixture(const char *path, char *detail, size_t n)
{
    (void)detail;
    (void)n;
    return open_and_verify(path);
}

/* hpfc_file_serialize of a file serialised from tree t with `from` equals
 * hpfc_tree_serialize of t with `to`, byte for byte: the pools are copied
 * and the sections laid out as the tree writer lays them. */
static void check_reserialized(const hpfc_tree *t, const hpfc_write_options *from,
                               const hpfc_write_options *to, const char *path)
{
    uint8_t *src = NULL, *want = NULL, *got = NULL;
    size_t src_size = 0, want_size = 0, got_size = 0;
    hpfc_diag d;
    hpfc_file *f = NULL;
    CHECK_EQ_INT(hpfc_tree_serialize(t, from, &src, &src_size, &d), HPFC_OK);
    CHECK_EQ_INT(hpfc_tree_serialize(t, to, &want, &want_size, &d), HPFC_OK);
    CHECK_EQ_INT(hpfc_open_memory(src, src_size, 0, &f), HPFC_OK);
    if (f) {
        CHECK_EQ_INT(hpfc_file_serialize(f, to, &got, &got_size, &d), HPFC_OK);
        CHECK(got && got_size == want_size && memcmp(got, want, want_size) == 0);
        CHECK_EQ_INT(hpfc_file_write_file(f, to, path, &d), HPFC_OK);
        CHECK(file_equals(path, want, want_size));
    }
    hpfc_close(f);
    free(src), free(want), free(got);
}

static void test_file_serialize(void)
{
    char dir[] = "/tmp/hpfc-test-format-XXXXXX";
    CHECK(mkdtemp(dir) != NULL);
    char path[256];
    snprintf(path, sizeof path, "%s/map.hpfc", dir);
    hpfc_tree *t = special_tree(GEN_SPECIAL_HOLE, 3);
    if (!t)
        return;
    size_t size;
    uint8_t *plain = serialize(t, NULL, &size);
    hpfc_file *f = NULL;
    hpfc_faces *fc = NULL;
    CHECK_EQ_INT(hpfc_open_memory(plain, size, 0, &f), HPFC_OK);
    CHECK_EQ_INT(hpfc_faces_build(f, &fc), HPFC_OK);
    feat_fixture x;
    feat_fixture_make(&x, (uint32_t)hpfc_faces_count(fc));
    hpfc_faces_free(fc);
    const hpfc_write_options opts[4] = {
        {.crs = NULL},
        {.crs = "EPSG:4326"},
        {.features = &x.t},
        {.crs = "+proj=lcc +lat_1=33", .features = &x.t}};
    for (int a = 0; a < 4; a++)
        for (int b = 0; b < 4; b++)
            check_reserialized(t, &opts[a], &opts[b], path);
    /* opts NULL: no optional section */
    uint8_t *got = NULL;
    size_t got_size = 0;
    hpfc_diag d;
    CHECK_EQ_INT(hpfc_file_serialize(f, NULL, &got, &got_size, &d), HPFC_OK);
    CHECK(got && got_size == size && memcmp(got, plain, size) == 0);
    free(got);
    CHECK_EQ_INT(hpfc_file_serialize(NULL, NULL, &got, &got_size, &d), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_file_serialize(f, NULL, NULL, &got_size, &d), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_file_write_file(f, NULL, NULL, &d), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_file_write_file(NULL, NULL, path, &d), HPFC_E_ARG);
    hpfc_close(f);
    free(plain);
    free(x.start), free(x.link);
    hpfc_tree_free(t);
    remove(path);
    rmdir(dir);
}

static void test_valid_fixtures(const char *root)
{
    check_valid_fixtures(root, ".hpfc", check_hpfc_fixture, 2);
}

static void test_invalid_fixtures(const char *root)
{
    check_invalid_fixtures(root, ".hpfc", check_hpfc_fixture, 5);
}

int main(void)
{
    test_layout_compact = check_use_test_layout();
    test_crc32c();
    test_bit_streams();
    test_fig7_arithmetic();
    test_fig7_file();
    test_arguments();
    test_small_shapes();
    test_generated();
    test_metadata_mutations();
    test_header_extension();
    test_section_overlaps();
    test_truncation();
    test_pool_corruption();
    test_write_file();
    test_features();
    test_file_serialize();
    const char *root = getenv("HPFC_TEST_DATA");
    CHECK(root != NULL);
    if (root) {
        test_valid_fixtures(root);
        test_invalid_fixtures(root);
    }
    printf("round trips: %ld trees (%ld of one level, up to %u levels), %ld pixels, %ld moves "
           "(%ld by full search), %ld located points\n",
           covered.trees, covered.one_level_trees, covered.max_levels, covered.pixels, covered.moves,
           covered.brute_moves, covered.locates);
    return check_report("test_format");
}
