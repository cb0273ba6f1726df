/*
 * Reading a part file (spec/part-format.md) back into a part's tree.
 *
 * A part file comes from another process, maybe another machine: every
 * byte may be damaged or hostile. The reader accepts only what
 * hpfc_build_part can make, checked as it copies: the header against the
 * build's rules (image sizes, a domain of root_cols * cols^depth), the
 * sizes against the file's, and the pixels in the order the builder
 * emits them (each refined pixel's child the next image of the next level
 * at its place, each word the next symbols and crossings, a word of the
 * grammar with the crossings it claims, edges below the map's count), so
 * that hpfc_tree_merge and the writer can take the tree as one the builder
 * made. HPFC_E_CORRUPT (with the reason in diag) for anything else.
 *
 * The tree is read in place: its arrays point into the file's bytes (a
 * read-only mapping of the file, or the reader's one copy of a caller's
 * buffer), whose version 2 layout puts every array on its alignment. A
 * part costs its file's size once, never a second copy, and a merge of
 * mapped parts (hpfc_tree_merge_files) reads them from the page cache.
 */
#include <errno.h>
#include <fcntl.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include "part_file.h"
#include "tree.h"
#include "words.h"

typedef struct part_reader {
    uint8_t *data;                /* the tree's backing: aligned to 8 */
    size_t size;
    hpfc_tree *t;
    uint32_t level_count;
    bool segments;                /* the file holds each crossing's segment */
    uint64_t nimages[HPFC_MAX_LEVELS];
    uint64_t syms_at, cross_at;   /* the next word's symbols and crossings */
    uint64_t vertices, words, privates, refined;
    uint32_t longest;
    word_parts wp;
    hpfc_diag *diag;
} part_reader;

static int corrupt(part_reader *r, const char *what)
{
    return diag_set(r->diag, HPFC_E_CORRUPT, "part file: %s", what);
}

/* ---- the header --------------------------------------------------------- */

/* a * b^k, or -1 past the lattice */
static int64_t scaled(int64_t a, int64_t b, uint32_t k)
{
    for (uint32_t i = 0; i < k; i++) {
        if (a > HPFC_LATTICE_MAX / b)
            return -1;
        a *= b;
    }
    return a;
}

static int check_shape(part_reader *r, const uint8_t *h)
{
    uint32_t n0 = part_get_root_cols(h), m0 = part_get_root_rows(h), n = part_get_cols(h),
             m = part_get_rows(h);
    r->level_count = part_get_level_count(h);
    uint32_t levels = part_get_levels(h);
    if (n0 < 1 || m0 < 1 || (uint64_t)n0 * m0 > ((uint64_t)1 << 31) || n < 2 || m < 2 ||
        (uint64_t)n * m > ((uint64_t)1 << 20))
        return corrupt(r, "image sizes outside a build's range");
    if (r->level_count < 1 || r->level_count > HPFC_MAX_LEVELS || levels < 1 || levels > r->level_count)
        return corrupt(r, "level counts outside a build's range");
    int64_t x0 = part_get_x0(h), y0 = part_get_y0(h);
    if (part_get_width(h) != scaled(n0, n, r->level_count - 1) ||
        part_get_height(h) != scaled(m0, m, r->level_count - 1) || x0 < -HPFC_LATTICE_MAX ||
        x0 > HPFC_LATTICE_MAX || y0 < -HPFC_LATTICE_MAX || y0 > HPFC_LATTICE_MAX)
        return corrupt(r, "a domain no build gives");
    int32_t unit = part_get_unit_exp10(h);
    if (unit < FORMAT_MIN_UNIT_EXP10 || unit > FORMAT_MAX_UNIT_EXP10)
        return corrupt(r, "a unit outside the format's range");
    if (part_get_edges(h) > (uint64_t)UINT32_MAX + 1 || part_get_has_segments(h) > 1 ||
        part_get_flags(h) || part_get_reserved(h))
        return corrupt(r, "an edge count, flag or reserved field out of range");
    return HPFC_OK;
}

static int read_header(part_reader *r)
{
    const uint8_t *h = r->data;
    if (r->size < PART_HEADER_SIZE + PART_CRC_SIZE || memcmp(h, PART_MAGIC, part_SIZE_magic))
        return diag_set(r->diag, HPFC_E_MAGIC, "not a part file (its magic is not \"%s\")", PART_MAGIC);
    if (part_get_version(h) != PART_VERSION)
        return diag_set(r->diag, HPFC_E_VERSION, "part file version %u (this library reads %d)",
                        part_get_version(h), PART_VERSION);
    uint32_t stored = (uint32_t)le_load(r->data + r->size - PART_CRC_SIZE, 4);
    if (crc32c_update(0, r->data, r->size - PART_CRC_SIZE) != stored)
        return diag_set(r->diag, HPFC_E_CHECKSUM, "part file: its CRC-32C does not match its bytes");
    return check_shape(r, h);
}

/* ---- sizes -------------------------------------------------------------- */

static size_t pixels_per_image(const hpfc_tree_info *i, uint32_t l)
{
    return l ? (size_t)i->cols * i->rows : (size_t)i->root_cols * i->root_rows;
}

/* The level table (one image at the root, some on every level below up
 * to `levels`, none after) and the file's size from it, exactly. */
static int check_sizes(part_reader *r)
{
    const hpfc_tree_info *i = &r->t->info;
    uint64_t table = (uint64_t)PART_LEVEL_ENTRY_SIZE * r->level_count;
    if (r->size - PART_CRC_SIZE - PART_HEADER_SIZE < table)
        return corrupt(r, "shorter than its level table");
    uint64_t room = r->size - PART_CRC_SIZE - PART_HEADER_SIZE - table;
    for (uint32_t l = 0; l < r->level_count; l++) {
        uint64_t n = le_load(r->data + PART_HEADER_SIZE + (size_t)l * PART_LEVEL_ENTRY_SIZE, 8);
        if ((l == 0 && n != 1) || (l > 0 && l < i->levels && n == 0) || (l >= i->levels && n != 0))
            return corrupt(r, "a level table no build gives");
        uint64_t each = 16 + (uint64_t)PART_PIXEL_SIZE * pixels_per_image(i, l);
        if (n > room / each)
            return corrupt(r, "shorter than its levels");
        room -= n * each;
        r->nimages[l] = n;
    }
    uint64_t nsyms = r->t->nsyms, ncross = r->t->ncross, per_cross = r->segments ? 8 : 4;
    uint64_t pad = part_symbols_padding(nsyms);
    if (nsyms < 4 || nsyms > room || pad > room - nsyms ||
        ncross > (room - nsyms - pad) / per_cross || room - nsyms - pad != ncross * per_cross ||
        ncross > TPIXEL_CROSS_OFF_MAX)
        return corrupt(r, "its symbols and crossings do not fill it");
    const uint8_t *zeros = r->data + (r->size - PART_CRC_SIZE) - ncross * per_cross - pad;
    for (uint64_t k = 0; k < pad; k++)
        if (zeros[k])
            return corrupt(r, "padding after its symbols that is not zeros");
    return HPFC_OK;
}

/* ---- the tree's arrays, in the file ------------------------------------- */

/* The levels' sizes; their arrays are pointed at by point_level. */
static int shape_levels(part_reader *r)
{
    hpfc_tree *t = r->t;
    if (!(t->levels = calloc(r->level_count, sizeof *t->levels)))
        return HPFC_E_NOMEM;
    t->levels_cap = r->level_count;
    for (uint32_t l = 0; l < r->level_count; l++) {
        tlevel *lv = &t->levels[l];
        lv->cols = l ? t->info.cols : t->info.root_cols;
        lv->rows = l ? t->info.rows : t->info.root_rows;
        lv->cell_w = l ? t->levels[l - 1].cell_w / t->info.cols : t->info.width / t->info.root_cols;
        lv->cell_h = l ? t->levels[l - 1].cell_h / t->info.rows : t->info.height / t->info.root_rows;
    }
    return HPFC_OK;
}

#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
#define PART_HOST_BIG_ENDIAN 1
/* The file is little-endian: on a big-endian host its integers are turned
 * in place (the backing is the reader's own copy there, never a mapping). */
static void swap_in_place(uint8_t *at, size_t count, size_t width)
{
    for (size_t k = 0; k < count; k++, at += width) {
        uint64_t v = le_load(at, (unsigned)width);
        uint32_t w = (uint32_t)v;
        if (width == 8)
            memcpy(at, &v, 8);
        else
            memcpy(at, &w, 4);
    }
}
#else
#define PART_HOST_BIG_ENDIAN 0
static void swap_in_place(uint8_t *at, size_t count, size_t width)
{
    (void)at, (void)count, (void)width;
}
#endif

/* Level l's images and pixels are the file's bytes at `at` (8-aligned, in
 * the host's order); returns the bytes after. The tree never writes them. */
static uint8_t *point_level(part_reader *r, uint32_t l, uint8_t *at)
{
    tlevel *lv = &r->t->levels[l];
    size_t n = (size_t)r->nimages[l], pixels = n * pixels_per_image(&r->t->info, l);
    swap_in_place(at, 2 * n + 2 * pixels, 8);
    lv->img_gx = (int64_t *)(void *)at;
    lv->img_gy = (int64_t *)(void *)(at + 8 * n);
    lv->pix = (tpixel *)(void *)(at + 16 * n);
    lv->nimages = lv->cap = n;
    return at + 16 * n + PART_PIXEL_SIZE * pixels;
}

/* The symbols and crossings after the levels (the crossings 8-aligned
 * after the symbols' padding). */
static void point_words(part_reader *r, uint8_t *at)
{
    hpfc_tree *t = r->t;
    t->syms = (char *)at;
    at += t->nsyms + part_symbols_padding(t->nsyms);
    swap_in_place(at, (size_t)t->ncross * (r->segments ? 2 : 1), 4);
    t->cross_edge = (uint32_t *)(void *)at;
    if (r->segments)
        t->cross_seg = (uint32_t *)(void *)(at + 4 * t->ncross);
    t->cap_syms = (size_t)t->nsyms;
    t->cap_cross = (size_t)t->ncross;
}

/* ---- the pixels, in the builder's order --------------------------------- */

static int check_word(part_reader *r, const tpixel *px)
{
    hpfc_tree *t = r->t;
    uint64_t n = px->cross & ((UINT64_C(1) << TPIXEL_COUNT_BITS) - 1), at = px->cross >> TPIXEL_COUNT_BITS;
    r->words++;
    if (n == 0) {
        r->privates++;
        if (px->off != 0 || at != r->cross_at)
            return corrupt(r, "a private pixel out of place");
        return HPFC_OK;
    }
    if (n > TPIXEL_COUNT_MAX || px->off != r->syms_at || at != r->cross_at || n + 4 > t->nsyms - r->syms_at ||
        n > t->ncross - r->cross_at || n + 4 > t->info.max_word_symbols)
        return corrupt(r, "a word out of place or longer than its file says");
    const char *sym = t->syms + r->syms_at;
    if (word_parse_symbols(&r->wp, sym, (size_t)n + 4) || r->wp.n != n || sym[n + 3] != '+')
        return corrupt(r, "a word that is not one of the grammar, or not of its crossings");
    for (uint64_t k = 0; k < n; k++)
        if (t->cross_edge[r->cross_at + k] >= t->info.edges)
            return corrupt(r, "a crossing on an edge beyond the map's");
    r->vertices += r->wp.nvert;
    r->syms_at += n + 4;
    r->cross_at += n;
    if (n + 4 > r->longest)
        r->longest = (uint32_t)(n + 4);
    return HPFC_OK;
}

/* A refined pixel at (gx, gy) of level l: its child is the next image of
 * level l + 1, whose south-west pixel lies at (gx * cols, gy * rows). */
static int check_refined(part_reader *r, uint32_t l, const tpixel *px, int64_t gx, int64_t gy,
                         uint64_t *next_child)
{
    const hpfc_tree *t = r->t;
    r->refined++;
    if (l + 1 >= t->info.levels || px->off != *next_child || *next_child >= r->nimages[l + 1])
        return corrupt(r, "a refined pixel whose child is out of place");
    const tlevel *child = &t->levels[l + 1];
    if (child->img_gx[px->off] != gx * t->info.cols || child->img_gy[px->off] != gy * t->info.rows)
        return corrupt(r, "a child image that is not under its pixel");
    (*next_child)++;
    return HPFC_OK;
}

static int check_pixel(part_reader *r, uint32_t l, size_t image, size_t p, uint64_t *next_child)
{
    const tlevel *lv = &r->t->levels[l];
    const tpixel *px = &lv->pix[image * lv->cols * lv->rows + p];
    if (px->cross == TPIXEL_ABSENT)
        return l == 0 ? HPFC_OK : corrupt(r, "another part's pixel below the root");
    if (px->cross != TPIXEL_REFINED)
        return check_word(r, px);
    int64_t gx = lv->img_gx[image] + (int64_t)(p % lv->cols);
    int64_t gy = lv->img_gy[image] + (int64_t)(lv->rows - 1 - p / lv->cols);
    return check_refined(r, l, px, gx, gy, next_child);
}

static int check_levels(part_reader *r)
{
    const hpfc_tree *t = r->t;
    if (t->levels[0].img_gx[0] != 0 || t->levels[0].img_gy[0] != 0)
        return corrupt(r, "a root image away from the origin");
    for (uint32_t l = 0; l < t->info.levels; l++) {
        const tlevel *lv = &t->levels[l];
        size_t per = (size_t)lv->cols * lv->rows;
        uint64_t next_child = 0;
        for (size_t im = 0; im < lv->nimages; im++)
            for (size_t p = 0; p < per; p++) {
                int st = check_pixel(r, l, im, p, &next_child);
                if (st)
                    return st;
            }
        if (l + 1 < t->info.levels && next_child != r->nimages[l + 1])
            return corrupt(r, "images that no pixel refines");
    }
    const hpfc_tree_info *i = &t->info;
    if (r->syms_at != t->nsyms || r->cross_at != t->ncross || r->vertices != i->vertices ||
        r->words != i->word_pixels || r->privates != i->private_pixels || r->refined != i->refined_pixels ||
        r->longest != i->max_word_symbols)
        return corrupt(r, "counts that its pixels do not give");
    if (memcmp(t->syms, "++++", 4))
        return corrupt(r, "no private word at its symbols' start");
    return HPFC_OK;
}

/* ---- entry points ------------------------------------------------------- */

static void take_info(part_reader *r)
{
    const uint8_t *h = r->data;
    hpfc_tree *t = r->t;
    t->part = true;
    t->info = (hpfc_tree_info){
        .root_cols = part_get_root_cols(h), .root_rows = part_get_root_rows(h),
        .cols = part_get_cols(h), .rows = part_get_rows(h), .levels = part_get_levels(h),
        .x0 = part_get_x0(h), .y0 = part_get_y0(h), .width = part_get_width(h),
        .height = part_get_height(h), .unit_exp10 = part_get_unit_exp10(h),
        .vertices = part_get_vertices(h), .edges = part_get_edges(h),
        .word_pixels = part_get_word_pixels(h), .refined_pixels = part_get_refined_pixels(h),
        .private_pixels = part_get_private_pixels(h), .max_word_symbols = part_get_max_word_symbols(h)};
    t->nsyms = part_get_symbols(h);
    t->ncross = part_get_crossings(h);
}

/* Reads the part in r->data (r->size bytes, the backing the tree will own:
 * hpfc_tree_free releases it, whatever this returns). */
static int read_part(part_reader *r, bool mapped)
{
    if (!(r->t = calloc(1, sizeof *r->t))) {
        part_backing_release(r->data, r->size, mapped);
        return HPFC_E_NOMEM;
    }
    r->t->backing = r->data;
    r->t->backing_size = r->size;
    r->t->backing_mapped = mapped;
    int st = read_header(r);
    if (st)
        return st;
    take_info(r);
    r->segments = part_get_has_segments(r->data) == 1;
    if ((st = check_sizes(r)))
        return st;
    uint32_t longest = r->t->info.max_word_symbols;
    if (longest > r->t->nsyms)
        return corrupt(r, "a longest word longer than its symbols");
    if ((st = shape_levels(r)) || (st = word_parts_alloc(&r->wp, longest > 4 ? longest - 4 : 1)))
        return st;
    uint8_t *at = r->data + PART_HEADER_SIZE + (size_t)PART_LEVEL_ENTRY_SIZE * r->level_count;
    for (uint32_t l = 0; l < r->t->info.levels; l++)
        at = point_level(r, l, at);
    point_words(r, at);
    if ((st = check_levels(r)))
        return st;
    if (!r->t->cross_seg &&
        !(r->t->zero_seg = calloc((size_t)r->t->info.max_word_symbols + 1, sizeof *r->t->zero_seg)))
        return HPFC_E_NOMEM;
    return HPFC_OK;
}

/* Reads the part whose bytes are r->data (see read_part) into *out. */
static int read_into(part_reader *r, bool mapped, hpfc_tree **out, hpfc_diag *diag)
{
    int st = read_part(r, mapped);
    word_parts_free(&r->wp);
    if (st == HPFC_E_NOMEM)
        diag_set(diag, st, "out of memory");
    if (st) {
        hpfc_tree_free(r->t);
        return st;
    }
    *out = r->t;
    return HPFC_OK;
}

int hpfc_tree_read_part_memory(const void *data, size_t size, hpfc_tree **out, hpfc_diag *diag)
{
    diag_clear(diag);
    if (!data || !out)
        return diag_set(diag, HPFC_E_ARG, "hpfc_tree_read_part_memory: NULL argument");
    *out = NULL;
    /* the tree's one copy, aligned as malloc aligns, which it points into */
    uint8_t *copy = malloc(size ? size : 1);
    if (!copy)
        return diag_set(diag, HPFC_E_NOMEM, "out of memory");
    memcpy(copy, data, size);
    part_reader r = {.data = copy, .size = size, .syms_at = 4, .diag = diag}; /* after the "++++" */
    return read_into(&r, false, out, diag);
}

/* The whole of the open file fd (`size` bytes) into a buffer of its own. */
static uint8_t *read_whole(int fd, size_t size)
{
    uint8_t *data = malloc(size ? size : 1);
    size_t got = 0;
    while (data && got < size) {
        ssize_t n = read(fd, data + got, size - got);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0) {
            free(data);
            return NULL;
        }
        got += (size_t)n;
    }
    return data;
}

int hpfc_tree_read_part(const char *path, hpfc_tree **out, hpfc_diag *diag)
{
    diag_clear(diag);
    if (!path || !out)
        return diag_set(diag, HPFC_E_ARG, "hpfc_tree_read_part: NULL argument");
    *out = NULL;
    int fd = open(path, O_RDONLY | O_CLOEXEC);
    if (fd < 0)
        return diag_set(diag, HPFC_E_IO, "cannot open %s: %s", path, strerror(errno));
    struct stat sb;
    if (fstat(fd, &sb) != 0 || !S_ISREG(sb.st_mode) || (uint64_t)sb.st_size > SIZE_MAX) {
        close(fd);
        return diag_set(diag, HPFC_E_IO, "cannot read %s: not a regular file", path);
    }
    size_t size = (size_t)sb.st_size;
    uint8_t *data = NULL;
    bool mapped = !PART_HOST_BIG_ENDIAN && size > 0;
    if (mapped) { /* read-only: the tree never writes its arrays */
        void *map = mmap(NULL, size, PROT_READ, MAP_PRIVATE, fd, 0);
        data = map == MAP_FAILED ? NULL : map;
    } else {
        data = read_whole(fd, size);
    }
    int err = errno;
    close(fd);
    if (!data)
        return diag_set(diag, HPFC_E_IO, "cannot read %s: %s", path, strerror(err));
    part_reader r = {.data = data, .size = size, .syms_at = 4, .diag = diag};
    return read_into(&r, mapped, out, diag);
}
