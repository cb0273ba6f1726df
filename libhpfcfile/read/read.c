/*
 * read.c: navigating the pixels of an open file (hpfc.h, "Pixels"): pixel
 * access in either pool layout, the moves of the paper's Algorithm 1,
 * point location, words, and the pool-layout views the traversal, faces
 * and labels code needs (reader.h).
 *
 * Navigation trusts only what open (file.c) checked: every pixel access
 * re-checks that the pixel's whole image lies inside its level's pool (its
 * size follows from its mask), so a corrupt pool gives HPFC_E_CORRUPT,
 * never a read outside the buffer. A descent gains one level per step and a
 * refined pixel at the last level is corrupt, so no walk can loop.
 *
 * Nothing here allocates or writes to the handle: any number of threads may
 * share one.
 */
#include <string.h>

#include "file.h"
#include "reader.h"
#include "words.h"

/* ---- pixels ---------------------------------------------------------------------------- */

/* Where pixel p (scanline index) of a refined image starts, after checking
 * the image: its mask and every slot the mask implies lie inside the pool,
 * and no pixel of the last level is refined. */
static inline int refined_image_pixel(const file_level *lv, uint64_t image, uint64_t p, int *type,
                               uint64_t *slot)
{
    uint64_t per = lv->image_pixels, bits = lv->pool.bits;
    if (image > bits || per > bits - image)
        return HPFC_E_CORRUPT;
    uint64_t before, total;
    if (per <= 57) { /* the common small image: one load holds the mask */
        uint64_t mask = format_peek(&lv->pool, image, (unsigned)per);
        total = format_ones(mask);
        before = format_ones(mask & ~(UINT64_MAX >> p));
        *type = (int)(mask >> (63 - p) & 1);
    } else {
        before = format_popcount(&lv->pool, image, p);
        *type = (int)format_get(&lv->pool, image + p, 1);
        total = before + (uint64_t)*type + format_popcount(&lv->pool, image + p + 1, per - p - 1);
    }
    if (total && lv->last)
        return HPFC_E_CORRUPT;
    /* at most 2^20 * (2^22 + 64) bits: no overflow */
    uint64_t slots = total * lv->address_bits + (per - total) * lv->word_bits;
    if (slots > bits - image - per)
        return HPFC_E_CORRUPT;
    *slot = image + per + before * lv->address_bits + (p - before) * lv->word_bits;
    return HPFC_OK;
}

/* A pixel as an access finds it, in either layout. */
typedef struct pixel_at {
    int type;       /* HPFC_PIXEL_WORD or HPFC_PIXEL_REFINED */
    uint64_t slot;  /* paper: pool bit of its address or word slot (root: after the
                       type bit); compact: its pixel index g in the level */
    uint64_t word;  /* compact word pixel: 0 stabbed, NO_WORD private (the
                       ranks are counted only when asked: pool_rank) */
} pixel_at;

#define NO_WORD UINT64_MAX

/* Pixel p of compact image `image` (its index in the level). */
static inline int compact_image_pixel(const file_level *lv, uint32_t level, uint64_t image,
                                      uint64_t p, pixel_at *at)
{
    if (image >= lv->info.images)
        return level ? HPFC_E_CORRUPT : HPFC_E_ARG; /* as a paper image past its pool */
    uint64_t g = image * lv->image_pixels + p; /* < P: open checked images * n * m */
    int kind;
    int st = pool_read_type(&lv->pool, &lv->compact, g, &kind);
    if (st)
        return st;
    if (kind == POOL_REFINED && lv->last)
        return HPFC_E_CORRUPT;
    at->type = kind == POOL_REFINED ? HPFC_PIXEL_REFINED : HPFC_PIXEL_WORD;
    at->slot = g;
    at->word = kind == POOL_PRIVATE ? NO_WORD : 0;
    return HPFC_OK;
}

/* Pixel (i, j) of the image `image` of `level` (paper: its bit offset;
 * compact: its index). */
static inline int image_pixel(const hpfc_file *f, uint32_t level, uint64_t image, uint32_t i, uint32_t j,
                              pixel_at *at)
{
    const file_level *lv = &f->lv[level];
    if (i >= lv->cols || j >= lv->rows)
        return HPFC_E_ARG;
    uint64_t p = (uint64_t)j * lv->cols + i;
    if (f->compact)
        return compact_image_pixel(lv, level, image, p, at);
    at->word = NO_WORD; /* unused in this layout */
    if (level > 0)
        return refined_image_pixel(lv, image, p, &at->type, &at->slot);
    if (image != 0)
        return HPFC_E_ARG;
    uint64_t record = p * lv->record_bits; /* fixed records: inside s^0 by construction */
    at->type = (int)format_get(&lv->pool, record, 1);
    at->slot = record + 1;
    return at->type == HPFC_PIXEL_REFINED && lv->last ? HPFC_E_CORRUPT : HPFC_OK;
}

static int top_pixel(const hpfc_file *f, const hpfc_pixel *px, pixel_at *at)
{
    if (!f || !px || px->depth >= f->info.levels)
        return HPFC_E_ARG;
    uint32_t d = px->depth;
    return image_pixel(f, d, px->path[d].image, px->path[d].i, px->path[d].j, at);
}

/* The child image of a refined pixel: its address, or (compact) the rank
 * of its refined bit, checked against the level's count (the next level's
 * images) by pool_rank. */
static inline int child_address(const hpfc_file *f, uint32_t level, const pixel_at *at,
                                uint64_t *child)
{
    const file_level *lv = &f->lv[level];
    if (f->compact)
        return pool_rank(&lv->pool, &lv->compact, at->slot, POOL_REFINED, child);
    *child = format_get(&lv->pool, at->slot, lv->address_bits);
    return HPFC_OK;
}

static void copy_path(hpfc_pixel *out, const hpfc_pixel *px, uint32_t depth)
{
    if (out != px)
        memcpy(out->path, px->path, (depth + 1) * sizeof px->path[0]);
}

int hpfc_pixel_root(const hpfc_file *f, uint32_t i, uint32_t j, hpfc_pixel *out)
{
    if (!f || !out || i >= f->info.root_cols || j >= f->info.root_rows)
        return HPFC_E_ARG;
    out->depth = 0;
    out->path[0].image = 0;
    out->path[0].i = i;
    out->path[0].j = j;
    return HPFC_OK;
}

int hpfc_pixel_type(const hpfc_file *f, const hpfc_pixel *px, int *type)
{
    pixel_at at;
    int st = type ? top_pixel(f, px, &at) : HPFC_E_ARG;
    if (!st)
        *type = at.type;
    return st;
}

int hpfc_pixel_child(const hpfc_file *f, const hpfc_pixel *px, uint32_t i, uint32_t j, hpfc_pixel *out)
{
    uint64_t image;
    int type;
    int st = out ? reader_child_image(f, px, &image) : HPFC_E_ARG;
    return st ? st : reader_child(f, px, image, i, j, out, &type);
}

int reader_child_image(const hpfc_file *f, const hpfc_pixel *px, uint64_t *image)
{
    pixel_at at;
    int st = image ? top_pixel(f, px, &at) : HPFC_E_ARG;
    if (st)
        return st;
    if (at.type != HPFC_PIXEL_REFINED)
        return HPFC_E_NO_PIXEL;
    return child_address(f, px->depth, &at, image);
}

int reader_child(const hpfc_file *f, const hpfc_pixel *px, uint64_t image, uint32_t i, uint32_t j,
                 hpfc_pixel *out, int *type)
{
    uint32_t d = px->depth; /* < levels - 1: reader_child_image found a refined pixel */
    pixel_at at;
    int st = image_pixel(f, d + 1, image, i, j, &at);
    if (st)
        return st;
    copy_path(out, px, d);
    out->depth = d + 1;
    out->path[d + 1].image = image;
    out->path[d + 1].i = i;
    out->path[d + 1].j = j;
    *type = at.type;
    return HPFC_OK;
}

int reader_children_begin(const hpfc_file *f, const hpfc_pixel *px, reader_children *c)
{
    *c = (reader_children){.parent = px};
    int st = reader_child_image(f, px, &c->image);
    if (st)
        return st;
    const file_level *lv = &f->lv[px->depth + 1]; /* a refined pixel is above the last level */
    /* compact, the image's type bits in one load (2 bits a pixel, up to 56
     * at an even bit), and an image of the level: a walk by counts */
    if (!f->compact || lv->image_pixels > 28 || c->image >= lv->info.images)
        return HPFC_OK;
    uint64_t g0 = c->image * lv->image_pixels;
    pool_pixel base;
    if ((st = pool_read_pixel(&lv->pool, &lv->compact, g0, &base)))
        return st;
    c->counted = true;
    c->g0 = g0;
    c->refined = base.refined;
    c->stabbed = base.stabbed;
    c->pairs = format_peek(&lv->pool, 2 * g0, 2 * (unsigned)lv->image_pixels);
    return HPFC_OK;
}

int reader_children_get(const hpfc_file *f, const reader_children *c, uint32_t i, uint32_t j,
                        hpfc_pixel *out, int *type, reader_leaf_at *at)
{
    *at = (reader_leaf_at){.rank = UINT64_MAX};
    if (!c->counted)
        return reader_child(f, c->parent, c->image, i, j, out, type);
    uint32_t d = c->parent->depth + 1;
    const file_level *lv = &f->lv[d];
    if (i >= lv->cols || j >= lv->rows)
        return HPFC_E_ARG;
    unsigned p = j * lv->cols + i;
    uint64_t before = p ? c->pairs & ~(UINT64_MAX >> (2 * p)) : 0;
    unsigned pair = (unsigned)(c->pairs << (2 * p) >> 62);
    if (pair == 3)
        return HPFC_E_CORRUPT; /* refined and stabbed */
    if (pair == 2 && lv->last)
        return HPFC_E_CORRUPT;
    uint64_t refined = c->refined + format_ones(before & 0xAAAAAAAAAAAAAAAAull);
    uint64_t stabbed = c->stabbed + format_ones(before & 0x5555555555555555ull);
    copy_path(out, c->parent, d - 1);
    out->depth = d;
    out->path[d].image = c->image;
    out->path[d].i = i;
    out->path[d].j = j;
    *type = pair == 2 ? HPFC_PIXEL_REFINED : HPFC_PIXEL_WORD;
    if (pair != 2) {
        uint64_t g = c->g0 + p;
        if (g - refined >= lv->info.word_pixels || (pair == 1 && stabbed >= lv->compact.stabbed))
            return HPFC_E_CORRUPT; /* damaged block counts */
        at->rank = g - refined;
        at->word = pair == 1 ? stabbed : NO_WORD;
    }
    return HPFC_OK;
}

/* Starts the scan's run at images [first, last) of `level` (first < last):
 * the refined pixels before it from the block counts. */
static int scan_run(const hpfc_file *f, reader_scan *sc, uint32_t level, uint64_t first,
                    uint64_t last)
{
    const file_level *lv = &f->lv[level];
    if (last > lv->info.images)
        return HPFC_E_CORRUPT; /* more refined pixels above than images here */
    pool_pixel px;
    int st = pool_read_pixel(&lv->pool, &lv->compact, first * lv->image_pixels, &px);
    if (st)
        return st;
    sc->level = level;
    sc->g = first * lv->image_pixels;
    sc->end = last * lv->image_pixels; /* <= the level's pixels: open checked them */
    sc->refined = sc->first_refined = px.refined;
    return HPFC_OK;
}

int reader_scan_begin(const hpfc_file *f, const hpfc_pixel *px, reader_scan *sc)
{
    uint64_t image;
    int st = f->compact ? reader_child_image(f, px, &image) : HPFC_E_ARG;
    if (st)
        return st == HPFC_E_NO_PIXEL ? HPFC_E_ARG : st;
    return scan_run(f, sc, px->depth + 1, image, image + 1);
}

int reader_scan_next(const hpfc_file *f, reader_scan *sc, uint32_t *level, uint64_t *rank,
                     bool *is_private)
{
    for (;;) {
        if (sc->g == sc->end) { /* the run's refined pixels' children, a level down */
            if (sc->refined == sc->first_refined)
                return HPFC_E_NO_PIXEL;
            int st = scan_run(f, sc, sc->level + 1, sc->first_refined, sc->refined);
            if (st)
                return st;
        }
        const file_level *lv = &f->lv[sc->level];
        uint64_t g = sc->g++;
        unsigned pair = (unsigned)(format_window(&lv->pool, 8 * (g / 32)) << (2 * (g % 32)) >> 62);
        if (pair == 3 || (pair == 2 && lv->last))
            return HPFC_E_CORRUPT;
        if (pair == 2) {
            if (++sc->refined > lv->compact.refined)
                return HPFC_E_CORRUPT;
            continue;
        }
        if (g - sc->refined >= lv->info.word_pixels)
            return HPFC_E_CORRUPT; /* damaged block counts */
        *level = sc->level;
        *rank = g - sc->refined;
        *is_private = pair == 0;
        return HPFC_OK;
    }
}

int hpfc_pixel_parent(const hpfc_pixel *px, hpfc_pixel *out)
{
    if (!px || !out || px->depth >= HPFC_MAX_LEVELS)
        return HPFC_E_ARG;
    if (px->depth == 0)
        return HPFC_E_NO_PIXEL;
    uint32_t d = px->depth - 1;
    copy_path(out, px, d);
    out->depth = d;
    return HPFC_OK;
}

/* ---- moves (paper Algorithm 1 and its mirrors) ------------------------------------------ */

/* Is the pixel at path entry k on the image border that dir leaves by? */
static bool on_border(const file_level *lv, uint32_t i, uint32_t j, int dir)
{
    switch (dir) {
    case HPFC_WEST: return i == 0;
    case HPFC_EAST: return i + 1 >= lv->cols;
    case HPFC_NORTH: return j == 0;
    default: return j + 1 >= lv->rows;
    }
}

/* Entry (i, j) of the image entered at `level` while descending: the column
 * (W/E) or row (N/S) next to the road crossed; along the road, P's own row
 * or column while level <= P's depth, else the neighbour's first pixel in its
 * clockwise order (W: north end, E: south end, N: east end, S: west end). */
static void entry_pixel(const file_level *lv, const hpfc_pixel *p, uint32_t level, int dir, uint32_t *i,
                        uint32_t *j)
{
    bool keep = level <= p->depth;
    switch (dir) {
    case HPFC_WEST:
        *i = lv->cols - 1;
        *j = keep ? p->path[level].j : 0;
        break;
    case HPFC_EAST:
        *i = 0;
        *j = keep ? p->path[level].j : lv->rows - 1;
        break;
    case HPFC_NORTH:
        *j = lv->rows - 1;
        *i = keep ? p->path[level].i : lv->cols - 1;
        break;
    default:
        *j = 0;
        *i = keep ? p->path[level].i : 0;
        break;
    }
}

/* One step down a pixel path: records pixel (i, j) of `image` at `level` in
 * out. A word pixel ends the path there (*word, out->depth = level); a
 * refined one replaces *image by its child image. */
static inline int descend(const hpfc_file *f, uint32_t level, uint64_t *image, uint32_t i, uint32_t j,
                          hpfc_pixel *out, bool *word)
{
    pixel_at at;
    int st = image_pixel(f, level, *image, i, j, &at);
    if (st)
        return st;
    out->path[level].image = *image;
    out->path[level].i = i;
    out->path[level].j = j;
    *word = at.type == HPFC_PIXEL_WORD;
    if (*word)
        out->depth = level;
    else
        return child_address(f, level, &at, image);
    return HPFC_OK;
}

int hpfc_pixel_move(const hpfc_file *f, const hpfc_pixel *px, int dir, hpfc_pixel *out)
{
    if (!f || !px || !out || px->depth >= f->info.levels || dir < HPFC_WEST || dir > HPFC_SOUTH)
        return HPFC_E_ARG;
    /* Up: the deepest ancestor that has a neighbour in its own image. */
    uint32_t k = px->depth;
    while (on_border(&f->lv[k], px->path[k].i, px->path[k].j, dir)) {
        if (k == 0)
            return HPFC_E_NO_PIXEL; /* the domain's border */
        k--;
    }
    uint32_t i = px->path[k].i - (dir == HPFC_WEST) + (dir == HPFC_EAST);
    uint32_t j = px->path[k].j - (dir == HPFC_NORTH) + (dir == HPFC_SOUTH);
    uint64_t image = px->path[k].image;
    copy_path(out, px, k);
    for (uint32_t level = k;; level++) {
        bool word;
        int st = descend(f, level, &image, i, j, out, &word);
        if (st || word)
            return st;
        /* px->path[level + 1] is read before out->path[level + 1] is written */
        entry_pixel(&f->lv[level + 1], px, level + 1, dir, &i, &j);
    }
}

/* ---- point location and geometry ---------------------------------------------------------- */

int hpfc_locate(const hpfc_file *f, int64_t x, int64_t y, hpfc_pixel *out)
{
    return f && out ? reader_locate_near(f, NULL, x, y, out) : HPFC_E_ARG;
}

int reader_locate_near(const hpfc_file *f, const hpfc_pixel *near, int64_t x, int64_t y,
                       hpfc_pixel *out)
{
    const hpfc_file_info *in = &f->info;
    if (x < in->x0 || y < in->y0)
        return HPFC_E_NO_PIXEL;
    /* offsets inside the domain (|x0| <= 2^62, so the differences fit) */
    uint64_t rx = (uint64_t)x - (uint64_t)in->x0, ry = (uint64_t)y - (uint64_t)in->y0;
    if (rx >= (uint64_t)in->width || ry >= (uint64_t)in->height)
        return HPFC_E_NO_PIXEL;
    /* levels above near's own whose refined pixel may also hold the point */
    uint32_t shared = near && near->depth < in->levels ? near->depth : 0;
    /* 2^a x 2^b images: the point's cell at the deepest level, whose bits
     * are every level's cell index (divisions are most of a descent's
     * arithmetic); cell_w(0) = cell_w(deepest) << (a * deepest) < 2^63
     * bounds the shifts */
    uint32_t deepest = in->levels - 1, sx = f->shift_x, sy = f->shift_y;
    bool radix = sx && sy;
    uint64_t qx = radix ? rx / (uint64_t)f->lv[deepest].cell_w : 0;
    uint64_t qy = radix ? ry / (uint64_t)f->lv[deepest].cell_h : 0;
    uint64_t image = 0;
    for (uint32_t level = 0;; level++) {
        const file_level *lv = &f->lv[level];
        uint64_t gx, gy; /* < cols, rows: the point lies in the parent cell */
        if (radix) {
            gx = qx >> (sx * (deepest - level));
            gy = qy >> (sy * (deepest - level));
            if (level > 0)
                gx &= lv->cols - 1, gy &= lv->rows - 1;
        } else {
            uint64_t cw = (uint64_t)lv->cell_w, ch = (uint64_t)lv->cell_h;
            gx = rx / cw, gy = ry / ch;
            rx -= gx * cw;
            ry -= gy * ch;
        }
        uint32_t i = (uint32_t)gx, j = lv->rows - 1 - (uint32_t)gy; /* j = 0 is the northern row */
        if (level < shared && near->path[level].image == image && near->path[level].i == i &&
            near->path[level].j == j) {
            /* near's ancestor: the descent through it is near's path (out may be near) */
            out->path[level] = near->path[level];
            image = near->path[level + 1].image;
            continue;
        }
        shared = 0;
        bool word;
        int st = descend(f, level, &image, i, j, out, &word);
        if (st || word)
            return st;
    }
}

int hpfc_pixel_bounds(const hpfc_file *f, const hpfc_pixel *px, int64_t *x0, int64_t *y0, int64_t *x1,
                      int64_t *y1)
{
    if (!f || !px || !x0 || !y0 || !x1 || !y1 || px->depth >= f->info.levels)
        return HPFC_E_ARG;
    int64_t gx = 0, gy = 0; /* south-west corner relative to the domain's */
    for (uint32_t l = 0; l <= px->depth; l++) {
        const file_level *lv = &f->lv[l];
        if (px->path[l].i >= lv->cols || px->path[l].j >= lv->rows)
            return HPFC_E_ARG;
        gx += (int64_t)px->path[l].i * lv->cell_w;
        gy += (int64_t)(lv->rows - 1 - px->path[l].j) * lv->cell_h;
    }
    const file_level *lv = &f->lv[px->depth];
    *x0 = f->info.x0 + gx;
    *y0 = f->info.y0 + gy;
    *x1 = *x0 + lv->cell_w;
    *y1 = *y0 + lv->cell_h;
    return HPFC_OK;
}

/* ---- words ------------------------------------------------------------------------------ */

/* A compact word pixel's word: "++++" for a private one, else its code. */
static int compact_word(const file_level *lv, const pixel_at *at, char *buf, size_t cap, size_t *len)
{
    if (at->word == NO_WORD) {
        for (size_t k = 0; buf && k < cap && k < 4; k++)
            buf[k] = '+';
        *len = 4;
        return buf && cap < 4 ? HPFC_E_BUFFER_SMALL : HPFC_OK;
    }
    uint64_t start, end, word;
    int st = pool_rank(&lv->pool, &lv->compact, at->slot, POOL_STABBED, &word);
    if (!st)
        st = pool_word_span(&lv->pool, &lv->compact, lv->word_bits, word, &start, &end);
    return st ? st : pool_decode_word(&lv->pool, start, end, buf, cap, len);
}

int hpfc_pixel_word(const hpfc_file *f, const hpfc_pixel *px, char *buf, size_t cap, size_t *len)
{
    pixel_at at;
    int st = len ? top_pixel(f, px, &at) : HPFC_E_ARG;
    if (st)
        return st;
    if (at.type != HPFC_PIXEL_WORD)
        return HPFC_E_ARG;
    const file_level *lv = &f->lv[px->depth];
    if (f->compact)
        return compact_word(lv, &at, buf, cap, len);
    return word_decode_code(&lv->pool, at.slot, lv->word_bits, buf, cap, len);
}

/* A compact word pixel's word from its index in the level's word stream
 * (NO_WORD: a private pixel, "++++"). */
static int indexed_word(const file_level *lv, uint64_t word, char *buf, size_t cap, size_t *len)
{
    if (word == NO_WORD) {
        pixel_at at = {.type = HPFC_PIXEL_WORD, .word = NO_WORD};
        return compact_word(lv, &at, buf, cap, len);
    }
    uint64_t start, end;
    int st = pool_word_span(&lv->pool, &lv->compact, lv->word_bits, word, &start, &end);
    return st ? st : pool_decode_word(&lv->pool, start, end, buf, cap, len);
}

int reader_leaf_word(const hpfc_file *f, const hpfc_pixel *leaf, const reader_leaf_at *known,
                     char *buf, size_t cap, size_t *len, uint64_t *rank)
{
    if (!f || !leaf || !len || !rank || leaf->depth >= f->info.levels)
        return HPFC_E_ARG;
    *rank = UINT64_MAX;
    if (known && known->rank != UINT64_MAX) { /* reader_children_get counted it */
        int st = indexed_word(&f->lv[leaf->depth], known->word, buf, cap, len);
        if (!st)
            *rank = known->rank;
        return st;
    }
    if (!f->compact)
        return hpfc_pixel_word(f, leaf, buf, cap, len);
    uint32_t d = leaf->depth;
    const file_level *lv = &f->lv[d];
    uint64_t image = leaf->path[d].image;
    if (leaf->path[d].i >= lv->cols || leaf->path[d].j >= lv->rows)
        return HPFC_E_ARG;
    if (image >= lv->info.images)
        return d ? HPFC_E_CORRUPT : HPFC_E_ARG; /* as compact_image_pixel says */
    /* one read of the type bits' counts gives both ranks */
    uint64_t g = image * lv->image_pixels + (uint64_t)leaf->path[d].j * lv->cols + leaf->path[d].i;
    pool_pixel px;
    int st = pool_read_pixel(&lv->pool, &lv->compact, g, &px);
    if (st)
        return st;
    if (px.kind == POOL_REFINED)
        return lv->last ? HPFC_E_CORRUPT : HPFC_E_ARG;
    if (g - px.refined >= lv->info.word_pixels)
        return HPFC_E_CORRUPT; /* damaged block counts */
    st = indexed_word(lv, px.kind == POOL_PRIVATE ? NO_WORD : px.stabbed, buf, cap, len);
    if (!st)
        *rank = g - px.refined;
    return st;
}

int hpfc_pixel_is_private(const hpfc_file *f, const hpfc_pixel *px, int *is_private)
{
    pixel_at at;
    int st = is_private ? top_pixel(f, px, &at) : HPFC_E_ARG;
    if (st)
        return st;
    const file_level *lv = &f->lv[px->depth];
    if (at.type == HPFC_PIXEL_REFINED) {
        *is_private = 0;
        return HPFC_OK;
    }
    if (f->compact) {
        *is_private = at.word == NO_WORD;
        return HPFC_OK;
    }
    if (lv->word_bits < FORMAT_MIN_WORD_BITS)
        return HPFC_E_CORRUPT;
    /* "++++" is the only word whose code starts with four 0 bits */
    *is_private = format_peek(&lv->pool, at.slot, 4) == 0;
    return HPFC_OK;
}

/* ---- slot positions, the pixels' stable numbers (reader.h) -------------------------------- */

/* The absolute bit of px's record or slot; a refined pixel's too unless
 * leaf_only (HPFC_E_ARG then). */
static int slot_bit(const hpfc_file *f, const hpfc_pixel *px, bool leaf_only, uint64_t *bit)
{
    pixel_at at;
    int st = bit ? top_pixel(f, px, &at) : HPFC_E_ARG;
    if (!st && leaf_only && at.type != HPFC_PIXEL_WORD)
        st = HPFC_E_ARG;
    if (st)
        return st;
    uint64_t slot = at.slot;
    if (f->compact)
        slot = pool_type_bit(&f->lv[px->depth].compact, slot);
    else if (px->depth == 0)
        slot -= 1; /* the root record starts at its type bit */
    *bit = f->lv[px->depth].info.pool_offset * 8 + slot;
    return HPFC_OK;
}

int reader_pixel_slot_bit(const hpfc_file *f, const hpfc_pixel *px, uint64_t *bit)
{
    return slot_bit(f, px, false, bit);
}

int reader_leaf_slot_bit(const hpfc_file *f, const hpfc_pixel *px, uint64_t *bit)
{
    return slot_bit(f, px, true, bit);
}

/* ---- pool layout, for the walker's key index (reader.h) ------------------------------------ */

/* A compact image is one unit of its level's image numbering; its refined
 * pixels are counted by reading each. */
static int compact_image_bits(const hpfc_file *f, uint32_t level, uint64_t image, uint64_t *bits,
                              uint64_t *refined)
{
    const file_level *lv = &f->lv[level];
    if (image >= lv->info.images)
        return level ? HPFC_E_CORRUPT : HPFC_E_ARG;
    uint64_t total = 0;
    for (uint64_t p = 0; p < lv->image_pixels; p++) {
        pixel_at at;
        int st = compact_image_pixel(lv, level, image, p, &at);
        if (st)
            return st;
        total += at.type == HPFC_PIXEL_REFINED;
    }
    *bits = 1;
    *refined = total;
    return HPFC_OK;
}

int reader_image_bits(const hpfc_file *f, uint32_t level, uint64_t image, uint64_t *bits,
                      uint64_t *refined)
{
    if (level >= f->info.levels)
        return HPFC_E_ARG;
    const file_level *lv = &f->lv[level];
    uint64_t per = lv->image_pixels, pool = lv->pool.bits, total = 0;
    if (f->compact)
        return compact_image_bits(f, level, image, bits, refined);
    if (level == 0) {
        if (image != 0)
            return HPFC_E_ARG;
        for (uint64_t p = 0; p < per; p++) /* s^0 holds every record (the recurrence) */
            total += format_get(&lv->pool, p * lv->record_bits, 1);
        *bits = per * lv->record_bits;
    } else {
        if (image > pool || per > pool - image)
            return HPFC_E_CORRUPT;
        total = format_popcount(&lv->pool, image, per);
        uint64_t slots = total * lv->address_bits + (per - total) * lv->word_bits;
        if (slots > pool - image - per)
            return HPFC_E_CORRUPT;
        *bits = per + slots;
    }
    if (total && lv->last)
        return HPFC_E_CORRUPT;
    *refined = total;
    return HPFC_OK;
}

int reader_next_refined(const hpfc_file *f, uint32_t level, uint64_t image, reader_refined *it,
                        uint32_t *pixel, uint64_t *address)
{
    const file_level *lv = &f->lv[level];
    uint64_t per = lv->image_pixels;
    if (f->compact) {
        for (; it->p < per; it->p++) {
            pixel_at at;
            int st = compact_image_pixel(lv, level, image, it->p, &at);
            if (st)
                return st;
            if (at.type == HPFC_PIXEL_REFINED) {
                *pixel = (uint32_t)it->p++;
                return child_address(f, level, &at, address);
            }
        }
        return HPFC_E_NO_PIXEL;
    }
    if (level == 0) {
        for (; it->p < per; it->p++)
            if (format_get(&lv->pool, it->p * lv->record_bits, 1)) {
                *pixel = (uint32_t)it->p;
                *address = format_get(&lv->pool, it->p * lv->record_bits + 1, lv->address_bits);
                it->p++;
                return HPFC_OK;
            }
        return HPFC_E_NO_PIXEL;
    }
    while (it->p < per) {
        unsigned k = per - it->p < 56 ? (unsigned)(per - it->p) : 56;
        uint64_t mask = format_peek(&lv->pool, image + it->p, k);
        if (!mask) {
            it->p += k;
            continue;
        }
        it->p += (uint64_t)__builtin_clzll(mask);
        uint64_t slot =
            image + per + it->before * lv->address_bits + (it->p - it->before) * lv->word_bits;
        *pixel = (uint32_t)it->p;
        *address = format_get(&lv->pool, slot, lv->address_bits);
        it->p++;
        it->before++;
        return HPFC_OK;
    }
    return HPFC_E_NO_PIXEL;
}

int reader_word_at(const hpfc_file *f, uint32_t level, uint64_t image, uint64_t bit,
                   uint32_t *pixel)
{
    const file_level *lv = &f->lv[level];
    uint64_t per = lv->image_pixels;
    if (f->compact) {
        uint64_t g;
        pixel_at at;
        if (!pool_pixel_at_bit(&lv->compact, bit, &g) || g / per != image ||
            compact_image_pixel(lv, level, image, g % per, &at) || at.type != HPFC_PIXEL_WORD)
            return HPFC_E_ARG;
        *pixel = (uint32_t)(g % per);
        return HPFC_OK;
    }
    if (level == 0) {
        uint64_t p = bit / lv->record_bits;
        if (bit % lv->record_bits || p >= per || format_get(&lv->pool, bit, 1))
            return HPFC_E_ARG;
        *pixel = (uint32_t)p;
        return HPFC_OK;
    }
    if (bit < image + per)
        return HPFC_E_ARG; /* in the mask, or before the image */
    uint64_t want = bit - image - per, at = 0;
    for (uint64_t p = 0; p < per && at <= want; p++) {
        int refined = (int)format_get(&lv->pool, image + p, 1);
        if (at == want && !refined) {
            *pixel = (uint32_t)p;
            return HPFC_OK;
        }
        at += refined ? lv->address_bits : lv->word_bits;
    }
    return HPFC_E_ARG;
}

/* ---- layout-neutral views for the traversal and faces code (reader.h) ----------------------- */

uint64_t reader_image_end(const hpfc_file *f, uint32_t level)
{
    const file_level *lv = &f->lv[level];
    return f->compact ? lv->info.images : lv->info.pool_bits;
}

int reader_slot_image(const hpfc_file *f, uint32_t level, uint64_t bit, uint64_t *image)
{
    const file_level *lv = &f->lv[level];
    uint64_t g;
    if (!f->compact || !pool_pixel_at_bit(&lv->compact, bit, &g))
        return HPFC_E_ARG;
    *image = g / lv->image_pixels;
    return HPFC_OK;
}

void reader_slot_grid(const hpfc_file *f, uint32_t level, uint64_t *unit, uint64_t *entries)
{
    const file_level *lv = &f->lv[level];
    if (f->compact) { /* type bits, two a pixel, in the pool's first type_bits */
        *unit = 2;
        *entries = lv->compact.type_bits / 2 + 1;
    } else if (level == 0) {
        *unit = lv->record_bits;
        *entries = lv->image_pixels;
    } else {
        *unit = lv->word_bits ? lv->word_bits : 1; /* no word slots: no entries needed */
        *entries = lv->info.word_pixels ? lv->info.pool_bits / *unit + 1 : 0;
    }
}

/* The compact layout's word pixels of a level before unit u (an image,
 * or a root pixel): what the LABL rank samples count (spec §6.5.2). */
int reader_compact_words_before(const hpfc_file *f, uint32_t level, uint64_t unit, uint64_t *words)
{
    const file_level *lv = &f->lv[level];
    uint64_t g = level ? unit * lv->image_pixels : unit;
    pool_pixel px;
    int st = pool_read_pixel(&lv->pool, &lv->compact, g, &px);
    if (!st)
        *words = g - px.refined;
    return st;
}
