/*
 * The .hpfc writer (spec/hpfc-format.md): lays an in-memory tree out as
 * header, level table, section directory, then the POOL section (every
 * level's pool, level 0 first) and the optional sections: CRS, FEAT,
 * ATTR, EDGF, LABL, GEOM, and SHIX, which the writer derives from LABL,
 * FEAT and EDGF.
 *
 * The tree is read through the public hpfc_tree_* accessors only, in three
 * passes: count (n_w, n_@, k_w and each image's refined pixels), size (k_@
 * and s bottom-up, then each image's bit offset), and emit.
 *
 * A tree with LABL written to a descriptor that maps is made in the file's
 * own pages (write_in_place): the pools first, read back for their faces,
 * then LABL and SHIX each placed from a first pass and made in place. The
 * serialize calls, and a descriptor that does not map, make LABL and SHIX
 * in memory first (make_labels, make_index), then place every section.
 */
#include <errno.h>
#include <fcntl.h>
#include <sys/mman.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "attrs.h"
#include "faces.h"
#include "feat.h"
#include "file.h"
#include "format.h"
#include "geometry.h"
#include "geometry_write.h"
#include "graph.h"
#include "labels.h"
#include "part_file.h"
#include "pool.h"
#include "shix.h"
#include "sized.h"
#include "tree.h"
#include "words.h"

typedef struct layout {
    const hpfc_write_options *opts; /* the caller's, over the defaults */
    const hpfc_tree *tree;   /* the map to lay out, or */
    const hpfc_file *source; /* an open file whose pools are copied */
    hpfc_tree_info info;
    format_level lv[HPFC_MAX_LEVELS];
    /* Per level >= 1 in the paper layout: first the refined pixels of
     * each image, then (after sizing) the bit offset of each image in the
     * level's pool. */
    uint64_t *image_off[HPFC_MAX_LEVELS];
    uint64_t pool_offset[HPFC_MAX_LEVELS]; /* byte offset in the file */
    uint32_t section_count;
    uint64_t meta_size, pool_section, pool_length, crs_offset, crs_length, file_size;
    uint64_t feat_offset, feat_length;
    const uint8_t *labl;     /* the LABL section's bytes, NULL for none */
    uint64_t labl_offset, labl_length;
    const uint8_t *geom;     /* the GEOM section's bytes (an open file's), or */
    geom_writer *geom_plan;  /* the plan it is streamed from (a tree's), NULL for none */
    uint64_t geom_offset, geom_length;
    const char *crs;
    const hpfc_feature_table *features;
    /* ATTR and EDGF (§6.3, §6.4), after FEAT */
    const hpfc_attr_table *attributes;
    const hpfc_edge_feature_table *edge_features;
    uint64_t attr_offset, attr_length, edgf_offset, edgf_length;
    /* where make_labels hands out the faces it numbered (faces_out), or NULL */
    hpfc_faces **faces_out;
    unsigned threads; /* hpfc_write_options.threads: for numbering the faces */
    bool faces_by_root; /* hpfc_write_options.faces_by_root */
    /* SHIX (§6.8), made from LABL, FEAT and EDGF when there is a LABL */
    uint8_t *shix;
    uint64_t shix_offset, shix_length;
    /* made in the file's own pages (write_in_place): the pools, LABL and
     * SHIX are in the file already, with these CRCs */
    bool in_place;
    uint32_t pool_crc, labl_crc, shix_crc;
    /* the compact layout (pool.h): per level, its stabbed words, their
     * stream's bits and longest code, and the geometry from them */
    bool compact;
    uint64_t stabbed[HPFC_MAX_LEVELS], stream_bits[HPFC_MAX_LEVELS];
    uint32_t longest[HPFC_MAX_LEVELS];
    pool_level pool[HPFC_MAX_LEVELS];
} layout;

static uint32_t image_cols(const layout *L, uint32_t level)
{
    return level ? L->info.cols : L->info.root_cols;
}

static uint32_t image_rows(const layout *L, uint32_t level)
{
    return level ? L->info.rows : L->info.root_rows;
}

static bool has_geom(const layout *L)
{
    return L->geom || L->geom_plan;
}

/* In place (write_in_place), LABL and SHIX are made after the pools. */
static bool has_labl(const layout *L)
{
    return L->labl || L->in_place;
}

static bool has_shix(const layout *L)
{
    return L->shix || L->in_place;
}

static void layout_free(layout *L)
{
    for (uint32_t l = 0; l < HPFC_MAX_LEVELS; l++)
        free(L->image_off[l]);
    free(L->shix);
}

/* ---- pass 1: counts ------------------------------------------------------ */

static int count_pixel(layout *L, uint32_t level, size_t image, const hpfc_tree_pixel *px,
                       hpfc_diag *diag)
{
    format_level *lv = &L->lv[level];
    if (px->type == HPFC_PIXEL_REFINED) {
        if (level + 1 >= L->info.levels || px->child >= hpfc_tree_image_count(L->tree, level + 1))
            return diag_set(diag, HPFC_E_ARG, "tree: a refined pixel of level %u has no child image",
                            level);
        lv->refined_pixels++;
        if (L->image_off[level])
            L->image_off[level][image]++;
        return HPFC_OK;
    }
    uint64_t bits = word_code_bits(px->word, px->word_len);
    if (bits == 0)
        return diag_set(diag, HPFC_E_ARG, "tree: malformed word at level %u", level);
    if (bits > FORMAT_MAX_WORD_BITS)
        return diag_set(diag, HPFC_E_LIMIT, "a word of %llu bits exceeds the format's 2^22-bit slots (2^20 - 1 crossings)",
                        (unsigned long long)bits);
    lv->word_pixels++;
    if (bits > lv->word_bits)
        lv->word_bits = (uint32_t)bits;
    uint64_t code = pool_word_bits(px->word, px->word_len);
    if (code == UINT64_MAX)
        return diag_set(diag, HPFC_E_ARG, "tree: malformed word at level %u", level);
    if (code > POOL_MAX_WORD_BITS)
        return diag_set(diag, HPFC_E_LIMIT, "a word of %llu compact bits exceeds the layout's 2^20 - 1",
                        (unsigned long long)code);
    if (code) {
        L->stabbed[level]++;
        L->stream_bits[level] += code;
        if (code > L->longest[level])
            L->longest[level] = (uint32_t)code;
    }
    return HPFC_OK;
}

static int count_level(layout *L, uint32_t level, hpfc_diag *diag)
{
    size_t images = hpfc_tree_image_count(L->tree, level);
    L->lv[level].images = images;
    if (level > 0 && !L->compact) { /* the paper layout's child addresses: the compact has none */
        L->image_off[level] = calloc(images ? images : 1, sizeof(uint64_t));
        if (!L->image_off[level])
            return diag_set(diag, HPFC_E_NOMEM, "out of memory");
    }
    for (size_t im = 0; im < images; im++)
        for (uint32_t j = 0; j < image_rows(L, level); j++)
            for (uint32_t i = 0; i < image_cols(L, level); i++) {
                hpfc_tree_pixel px;
                int st = hpfc_tree_get_pixel(L->tree, level, im, i, j, &px);
                if (st)
                    return diag_set(diag, st, "tree: cannot read a pixel of level %u", level);
                if ((st = count_pixel(L, level, im, &px, diag)))
                    return st;
            }
    return HPFC_OK;
}

/* ---- pass 2: sizes and placement ------------------------------------------ */

/* Turns each image's refined-pixel count into its bit offset in the pool. */
static void place_images(layout *L, uint32_t level)
{
    const format_level *lv = &L->lv[level];
    uint64_t ppi = (uint64_t)L->info.cols * L->info.rows, off = 0;
    for (size_t im = 0; im < lv->images; im++) {
        uint64_t refined = L->image_off[level][im];
        L->image_off[level][im] = off;
        off += ppi + refined * lv->address_bits + (ppi - refined) * lv->word_bits;
    }
}

/* The compact sizes (pool.h): no addresses, k_w the longest compact code. */
static int size_compact_levels(layout *L, hpfc_diag *diag)
{
    uint64_t root = (uint64_t)L->info.root_cols * L->info.root_rows;
    uint64_t ppi = (uint64_t)L->info.cols * L->info.rows;
    for (uint32_t l = 0; l < L->info.levels; l++) {
        format_level *lv = &L->lv[l];
        uint64_t pixels;
        if (!format_mul(lv->images, l ? ppi : root, &pixels) ||
            !pool_level_sizes(&L->pool[l], pixels, lv->refined_pixels, L->stabbed[l],
                              L->stream_bits[l]))
            return diag_set(diag, HPFC_E_LIMIT, "the pools exceed 2^64 bits");
        lv->word_bits = L->longest[l];
        lv->address_bits = 0;
        lv->pool_bits = L->pool[l].pool_bits;
    }
    return HPFC_OK;
}

static int size_levels(layout *L, hpfc_diag *diag)
{
    if (L->compact)
        return size_compact_levels(L, diag);
    uint64_t root = (uint64_t)L->info.root_cols * L->info.root_rows;
    uint64_t ppi = (uint64_t)L->info.cols * L->info.rows;
    if (!format_level_sizes(L->lv, L->info.levels, root, ppi))
        return diag_set(diag, HPFC_E_LIMIT, "the pools exceed 2^64 bits");
    for (uint32_t l = 1; l < L->info.levels; l++)
        place_images(L, l);
    return HPFC_OK;
}

/* The lengths of the FEAT, ATTR and EDGF sections to write. */
static int measure_tables(layout *L, hpfc_diag *diag)
{
    int st = HPFC_OK;
    if (L->features)
        st = feat_section_length(L->features, &L->feat_length, diag);
    if (!st && L->attributes)
        st = attr_section_length(L->attributes, &L->attr_length, diag);
    if (!st && L->edge_features)
        st = edgf_section_length(L->edge_features, &L->edgf_length, diag);
    return st;
}

/* LABL's view as a reader opens it: the source file's, or the section
 * just made for the tree, read against the levels laid out. */
static int labels_of(const layout *L, labels_view *v)
{
    if (L->source) {
        *v = L->source->labels;
        return HPFC_OK;
    }
    labels_levels lv = {.levels = L->info.levels};
    for (uint32_t l = 0; l < L->info.levels; l++) {
        lv.word_pixels[l] = L->lv[l].word_pixels;
        lv.units[l] = l ? L->lv[l].images : (uint64_t)L->info.root_cols * L->info.root_rows;
    }
    return labels_open(v, L->labl, L->labl_length, &lv);
}

/* The SHIX section of a layout with LABL (§6.8.3), after FEAT and EDGF
 * were checked (measure_tables). A table of 2^32 links or more cannot be
 * stored: the file is then written without the section, which readers
 * rebuild in memory, as for a file of 1.2. So is a file copied from one
 * whose LABL names a face past its count (hpfc_file_serialize copies what
 * it was given; its readers meet the same damage as the source's). */
static int make_index(layout *L, hpfc_diag *diag)
{
    labels_view v;
    if (labels_of(L, &v))
        return diag_set(diag, HPFC_E_ARG, "shape index: the labels do not read back");
    int st = shix_build(&v, L->features, L->edge_features, &L->shix, &L->shix_length, diag);
    if (st == HPFC_E_LIMIT || (st == HPFC_E_ARG && L->source)) {
        diag_clear(diag);
        return HPFC_OK;
    }
    return st;
}

/* A section of `length` bytes placed after the file so far, at the next
 * 8-byte boundary: returns its offset; *file_size becomes its end. */
static uint64_t append_section(uint64_t *file_size, uint64_t length)
{
    uint64_t offset = format_align8(*file_size);
    *file_size = offset + length;
    return offset;
}

static int check_file_size(const layout *L, hpfc_diag *diag)
{
    if (L->file_size > FORMAT_MAX_FILE_SIZE)
        return diag_set(diag, HPFC_E_LIMIT, "the file would exceed the format's 2^41 bytes");
#if SIZE_MAX < UINT64_MAX
    if (L->file_size > SIZE_MAX)
        return diag_set(diag, HPFC_E_NOMEM, "the file does not fit in memory");
#endif
    return HPFC_OK;
}

/* Header, level table and directory, then the POOL section (pools on 8-byte
 * boundaries, the section ending with the last pool's last byte), then CRS,
 * FEAT, ATTR, EDGF, LABL, GEOM and SHIX, each present one on an 8-byte
 * boundary: place_pools, then place_tail. */
static int place_pools(layout *L, hpfc_diag *diag)
{
    int st = measure_tables(L, diag);
    if (!st && L->labl && !L->shix && !L->in_place)
        st = make_index(L, diag);
    if (st)
        return st;
    /* in place, LABL, GEOM and SHIX are placed once made, but counted now:
     * the directory's size places the pools (shix_fits) */
    bool geom = has_geom(L) || (L->in_place && L->opts->geometry);
    L->section_count = 1 + (L->crs != NULL) + (L->features != NULL) + (L->attributes != NULL) +
                       (L->edge_features != NULL) + has_labl(L) + geom + has_shix(L);
    L->meta_size = FORMAT_HEADER_SIZE + (uint64_t)FORMAT_LEVEL_ENTRY_SIZE * L->info.levels +
                   (uint64_t)FORMAT_SECTION_ENTRY_SIZE * L->section_count;
    L->pool_section = format_align8(L->meta_size);
    uint64_t at = L->pool_section, end = at;
    for (uint32_t l = 0; l < L->info.levels; l++) {
        uint64_t bytes = format_pool_bytes(L->lv[l].pool_bits);
        L->pool_offset[l] = at;
        if (!format_add(at, bytes, &end) || end > (uint64_t)1 << 62)
            return diag_set(diag, HPFC_E_LIMIT, "the file would exceed 2^62 bytes");
        at = format_align8(end);
    }
    L->pool_length = end - L->pool_section;
    L->file_size = end;
    return HPFC_OK;
}

/* The sections after the pools, from their lengths; in place, SHIX is
 * placed once LABL is made (index_in_place). */
static int place_tail(layout *L, hpfc_diag *diag)
{
    if (L->crs) {
        L->crs_length = strlen(L->crs);
        L->crs_offset = append_section(&L->file_size, L->crs_length);
    }
    if (L->features)
        L->feat_offset = append_section(&L->file_size, L->feat_length);
    if (L->attributes)
        L->attr_offset = append_section(&L->file_size, L->attr_length);
    if (L->edge_features)
        L->edgf_offset = append_section(&L->file_size, L->edgf_length);
    if (has_labl(L))
        L->labl_offset = append_section(&L->file_size, L->labl_length);
    if (has_geom(L))
        L->geom_offset = append_section(&L->file_size, L->geom_length);
    if (L->shix)
        L->shix_offset = append_section(&L->file_size, L->shix_length);
    return check_file_size(L, diag);
}

static int place_sections(layout *L, hpfc_diag *diag)
{
    int st = place_pools(L, diag);
    return st ? st : place_tail(L, diag);
}

/* ---- pass 3: emit ---------------------------------------------------------- */

static uint64_t child_address(const layout *L, uint32_t level, const hpfc_tree_pixel *px)
{
    return L->image_off[level + 1][px->child];
}

/* Level 0: fixed records of 1 + max(k_@, k_w) bits in scanline order. */
static void emit_root(const layout *L, uint8_t *pool)
{
    const format_level *lv = &L->lv[0];
    uint64_t record = 1 + (uint64_t)(lv->address_bits > lv->word_bits ? lv->address_bits : lv->word_bits);
    for (uint32_t j = 0; j < L->info.root_rows; j++)
        for (uint32_t i = 0; i < L->info.root_cols; i++) {
            hpfc_tree_pixel px;
            hpfc_tree_get_pixel(L->tree, 0, 0, i, j, &px);
            uint64_t off = ((uint64_t)j * L->info.root_cols + i) * record;
            if (px.type == HPFC_PIXEL_REFINED) {
                format_put(pool, off, 1, 1);
                format_put(pool, off + 1, lv->address_bits, child_address(L, 0, &px));
            } else {
                word_encode_code(pool, off + 1, px.word, px.word_len);
            }
        }
}

/* Levels >= 1: per image, the type mask, then the slots in scanline order. */
static void emit_level(const layout *L, uint32_t level, uint8_t *pool)
{
    const format_level *lv = &L->lv[level];
    uint32_t cols = L->info.cols, rows = L->info.rows;
    for (size_t im = 0; im < lv->images; im++) {
        uint64_t mask = L->image_off[level][im], slot = mask + (uint64_t)cols * rows;
        for (uint32_t j = 0; j < rows; j++)
            for (uint32_t i = 0; i < cols; i++, mask++) {
                hpfc_tree_pixel px;
                hpfc_tree_get_pixel(L->tree, level, im, i, j, &px);
                if (px.type == HPFC_PIXEL_REFINED) {
                    format_put(pool, mask, 1, 1);
                    format_put(pool, slot, lv->address_bits, child_address(L, level, &px));
                    slot += lv->address_bits;
                } else {
                    word_encode_code(pool, slot, px.word, px.word_len);
                    slot += lv->word_bits;
                }
            }
    }
}

/* A compact level: every pixel of every image in pool order. */
static void emit_compact_level(const layout *L, uint32_t level, uint8_t *pool)
{
    pool_writer pw = {.pool = pool, .pl = &L->pool[level]};
    for (size_t im = 0; im < L->lv[level].images; im++)
        for (uint32_t j = 0; j < image_rows(L, level); j++)
            for (uint32_t i = 0; i < image_cols(L, level); i++) {
                hpfc_tree_pixel px;
                hpfc_tree_get_pixel(L->tree, level, im, i, j, &px);
                int kind = px.type == HPFC_PIXEL_REFINED  ? POOL_REFINED
                           : pool_word_bits(px.word, px.word_len) ? POOL_STABBED
                                                                   : POOL_PRIVATE;
                pool_writer_pixel(&pw, kind, px.word, px.word_len);
            }
    pool_writer_finish(&pw);
}

static void emit_header(const layout *L, uint8_t *h)
{
    const hpfc_tree_info *t = &L->info;
    memcpy(h + hdr_OFF_magic, FORMAT_MAGIC, FORMAT_MAGIC_SIZE);
    hdr_set_format_major(h, FORMAT_MAJOR);
    hdr_set_format_minor(h, FORMAT_MINOR);
    hdr_set_header_size(h, FORMAT_HEADER_SIZE);
    hdr_set_compat_flags(h, 0);
    hdr_set_incompat_flags(h, L->compact ? FORMAT_INCOMPAT_COMPACT_POOL : 0);
    hdr_set_root_cols(h, t->root_cols);
    hdr_set_root_rows(h, t->root_rows);
    hdr_set_cols(h, t->cols);
    hdr_set_rows(h, t->rows);
    hdr_set_levels(h, t->levels);
    hdr_set_section_count(h, L->section_count);
    hdr_set_x0(h, t->x0);
    hdr_set_y0(h, t->y0);
    hdr_set_width(h, t->width);
    hdr_set_height(h, t->height);
    hdr_set_unit_exp10(h, t->unit_exp10);
    hdr_set_file_size(h, L->file_size);
    hdr_set_meta_size(h, L->meta_size);
}

static void emit_level_table(const layout *L, uint8_t *file)
{
    for (uint32_t l = 0; l < L->info.levels; l++) {
        uint8_t *e = file + FORMAT_HEADER_SIZE + (size_t)l * FORMAT_LEVEL_ENTRY_SIZE;
        const format_level *lv = &L->lv[l];
        lvl_set_word_pixels(e, lv->word_pixels);
        lvl_set_refined_pixels(e, lv->refined_pixels);
        lvl_set_images(e, lv->images);
        lvl_set_word_bits(e, lv->word_bits);
        lvl_set_address_bits(e, lv->address_bits);
        lvl_set_pool_offset(e, L->pool_offset[l]);
        lvl_set_pool_bits(e, lv->pool_bits);
        if (L->compact) {
            lvl_set_stabbed_pixels(e, L->stabbed[l]);
            lvl_set_stream_bits(e, L->stream_bits[l]);
        }
    }
}

/* Directory entry `index` of the metadata `meta` (the file's first
 * meta_size bytes). */
static void emit_section(uint8_t *meta, uint32_t index, const char *tag, uint32_t flags, uint64_t offset,
                         uint64_t length, uint32_t crc, uint32_t levels)
{
    uint8_t *e = meta + FORMAT_HEADER_SIZE + (size_t)levels * FORMAT_LEVEL_ENTRY_SIZE +
                 (size_t)index * FORMAT_SECTION_ENTRY_SIZE;
    memcpy(e + sec_OFF_tag, tag, sec_SIZE_tag);
    sec_set_flags(e, flags);
    sec_set_offset(e, offset);
    sec_set_length(e, length);
    sec_set_crc32c(e, crc);
}

/* ---- where the bytes go ------------------------------------------------------ */

/* The file being written: a memory image of all of it (the serialize
 * calls), or a file descriptor written section by section at known
 * offsets (the write calls), so that a writer to disk holds one section
 * at a time, never the file. When the descriptor can be mapped, a
 * section is made in a mapping of the file's own pages (`mapped`): the
 * kernel writes them back and may drop them, so the writer's memory is
 * what the sections' making needs beside them. */
typedef struct sink {
    uint8_t *file;  /* the memory image (zeroed), or NULL */
    int fd;         /* else: a regular file, already file_size bytes of zeros
                       (mapped: grown to each section's end before it) */
    bool mapped;    /* fd: rooms are mappings of the file */
    int err;        /* the first write error (an errno) */
} sink;

/* The start of the page that holds byte `offset` of the file: where a
 * mapping of it starts. */
static uint64_t page_start(uint64_t offset)
{
    uint64_t page = (uint64_t)sysconf(_SC_PAGESIZE);
    return offset - offset % page;
}

/* Bytes [offset, offset + length) of the mapped sink's file, shared: NULL
 * with k->err set when they cannot be mapped. */
static uint8_t *sink_map(sink *k, uint64_t offset, uint64_t length, int prot)
{
    uint64_t start = page_start(offset), span = offset - start + length;
    void *p = mmap(NULL, span ? (size_t)span : 1, prot, MAP_SHARED, k->fd, (off_t)start);
    if (p == MAP_FAILED) {
        if (!k->err)
            k->err = errno;
        return NULL;
    }
    return (uint8_t *)p + (offset - start);
}

static void sink_unmap(const uint8_t *bytes, uint64_t offset, uint64_t length)
{
    uint64_t start = page_start(offset), span = offset - start + length;
    munmap((void *)(bytes - (offset - start)), span ? (size_t)span : 1);
}

/* Whether fd can be mapped for writing (opened for reading and writing,
 * on a file system that maps). */
static bool can_map(int fd)
{
    void *p = mmap(NULL, 1, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
    if (p == MAP_FAILED)
        return false;
    munmap(p, 1);
    return true;
}

/* The mapped sink's file grown to `size` bytes of zeros, its blocks
 * reserved, so that no store into a mapping meets a full disk (which
 * would raise SIGBUS rather than return an error). */
static void sink_grow(sink *k, uint64_t from, uint64_t size)
{
    if (k->err)
        return;
    if (ftruncate(k->fd, (off_t)size) != 0)
        k->err = errno;
    else if (size > from)
        k->err = posix_fallocate(k->fd, (off_t)from, (off_t)(size - from));
}

/* Room for `length` bytes at `offset`, zeroed: in the image, in the
 * file's pages, or a buffer of their own (NULL when out of memory:
 * *nomem set; or, mapped, when they cannot be mapped: k->err set). */
static uint8_t *sink_room(sink *k, uint64_t offset, uint64_t length, int *nomem)
{
    if (k->file)
        return k->file + offset;
    if (k->mapped)
        return sink_map(k, offset, length, PROT_READ | PROT_WRITE);
    uint8_t *b = calloc(1, length ? (size_t)length : 1);
    *nomem |= b == NULL;
    return b;
}

static void sink_pwrite(sink *k, uint64_t offset, const uint8_t *bytes, uint64_t length)
{
    while (length > 0 && !k->err) {
        size_t n = length > ((size_t)1 << 30) ? ((size_t)1 << 30) : (size_t)length;
        ssize_t w = pwrite(k->fd, bytes, n, (off_t)offset);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0) {
            k->err = w < 0 ? errno : EIO;
            return;
        }
        bytes += w, offset += (uint64_t)w, length -= (uint64_t)w;
    }
}

/* The bytes of a section (or a pool) placed at `offset`: written out and
 * released when they had a room of their own (`own`, from sink_room);
 * returns their CRC-32C, continued from `crc`. */
static uint32_t sink_put(sink *k, uint64_t offset, const uint8_t *bytes, uint64_t length, int own,
                         uint32_t crc)
{
    crc = crc32c_update(crc, bytes, (size_t)length);
    if (k->file) {
        if (!own)
            memcpy(k->file + offset, bytes, (size_t)length);
    } else if (k->mapped && own) {
        sink_unmap(bytes, offset, length); /* already in the file */
        return crc;
    } else {
        sink_pwrite(k, offset, bytes, length);
    }
    if (own && !k->file)
        free((void *)bytes);
    return crc;
}

/* The sink as a stream's target (stream.h): sections streamed out a
 * buffer at a time. */
static void sink_stream_put(void *ctx, uint64_t offset, const uint8_t *bytes, uint64_t length)
{
    sink *k = ctx;
    if (k->file)
        memcpy(k->file + offset, bytes, (size_t)length);
    else
        sink_pwrite(k, offset, bytes, length);
}

/* The CRC-32C of `n` zero bytes after `crc`: the padding between pools. */
static uint32_t crc_zeros(uint32_t crc, uint64_t n)
{
    static const uint8_t zeros[8];
    return crc32c_update(crc, zeros, (size_t)n);
}

/* Level l's pool: copied bit for bit from an open file (same counts and
 * widths give the same sizes: its level table was checked at open), or
 * laid out from the tree into a zeroed room. */
static uint32_t emit_pool(const layout *L, uint32_t l, sink *k, uint32_t crc, int *nomem)
{
    uint64_t bytes = format_pool_bytes(L->lv[l].pool_bits);
    if (L->source) {
        hpfc_level_info li;
        hpfc_file_get_level(L->source, l, &li);
        return sink_put(k, L->pool_offset[l], L->source->data + li.pool_offset, bytes, 0, crc);
    }
    uint8_t *pool = sink_room(k, L->pool_offset[l], bytes, nomem);
    if (!pool)
        return crc;
    if (L->compact)
        emit_compact_level(L, l, pool);
    else if (l == 0)
        emit_root(L, pool);
    else
        emit_level(L, l, pool);
    return sink_put(k, L->pool_offset[l], pool, bytes, 1, crc);
}

/* A table section (FEAT, ATTR, EDGF) emitted into its room. */
typedef void (*table_emit)(const void *table, uint8_t *out);

static uint32_t emit_table(sink *k, uint64_t offset, uint64_t length, table_emit fn, const void *t,
                           int *nomem)
{
    uint8_t *room = sink_room(k, offset, length, nomem);
    if (!room)
        return 0;
    fn(t, room);
    return sink_put(k, offset, room, length, 1, 0);
}

static void feat_emit(const void *t, uint8_t *out)
{
    feat_section_emit(t, out);
}

static void attr_emit(const void *t, uint8_t *out)
{
    attr_section_emit(t, out);
}

static void edgf_emit(const void *t, uint8_t *out)
{
    edgf_section_emit(t, out);
}

/* Every pool in level order into k: the POOL section's CRC-32C. */
static uint32_t emit_pools(const layout *L, sink *k, int *nomem)
{
    uint32_t crc = 0;
    for (uint32_t l = 0; l < L->info.levels; l++) {
        crc = emit_pool(L, l, k, crc, nomem);
        if (l + 1 < L->info.levels) /* the zeros up to the next pool, inside the section */
            crc = crc_zeros(crc, L->pool_offset[l + 1] - L->pool_offset[l] -
                                     format_pool_bytes(L->lv[l].pool_bits));
    }
    return crc;
}

/* Each section's CRC-32C, for the directory. */
typedef struct section_crcs {
    uint32_t pool, crs, feat, attr, edgf, labl, geom, shix;
} section_crcs;

/* The metadata (header, level table, directory) of L's sections, with
 * their CRCs, into k. */
static int emit_meta(const layout *L, sink *k, const section_crcs *c, hpfc_diag *diag)
{
    int nomem = 0;
    uint8_t *meta = sink_room(k, 0, L->meta_size, &nomem);
    if (!meta)
        return k->err ? HPFC_OK : diag_set(diag, HPFC_E_NOMEM, "out of memory");
    memset(meta, 0, (size_t)L->meta_size); /* in place: over the provisional header */
    emit_header(L, meta);
    emit_level_table(L, meta);
    uint32_t levels = L->info.levels, next = 1;
    emit_section(meta, 0, FORMAT_TAG_POOL, FORMAT_SECTION_REQUIRED, L->pool_section, L->pool_length,
                 c->pool, levels);
    if (L->crs)
        emit_section(meta, next++, FORMAT_TAG_CRS, 0, L->crs_offset, L->crs_length, c->crs, levels);
    if (L->features)
        emit_section(meta, next++, FORMAT_TAG_FEAT, 0, L->feat_offset, L->feat_length, c->feat,
                     levels);
    if (L->attributes)
        emit_section(meta, next++, FORMAT_TAG_ATTR, 0, L->attr_offset, L->attr_length, c->attr,
                     levels);
    if (L->edge_features)
        emit_section(meta, next++, FORMAT_TAG_EDGF, 0, L->edgf_offset, L->edgf_length, c->edgf,
                     levels);
    if (has_labl(L))
        emit_section(meta, next++, FORMAT_TAG_LABL, 0, L->labl_offset, L->labl_length, c->labl,
                     levels);
    if (has_geom(L))
        emit_section(meta, next++, FORMAT_TAG_GEOM, 0, L->geom_offset, L->geom_length, c->geom,
                     levels);
    if (has_shix(L))
        emit_section(meta, next, FORMAT_TAG_SHIX, 0, L->shix_offset, L->shix_length, c->shix,
                     levels);
    hdr_set_meta_crc32c(meta, format_meta_crc(meta, L->meta_size));
    sink_put(k, 0, meta, L->meta_size, 1, 0);
    return HPFC_OK;
}

/* Every section in file order (GEOM streamed from its plan; in place, the
 * pools, LABL and SHIX are there already), then the metadata, into k.
 * HPFC_E_NOMEM when a section's room or a stream's buffer could not be
 * had, with diag set; a write error stays in k->err. */
static int emit_to(const layout *L, sink *k, hpfc_diag *diag)
{
    int nomem = 0;
    section_crcs c = {.labl = L->labl_crc, .shix = L->shix_crc};
    c.pool = L->in_place ? L->pool_crc : emit_pools(L, k, &nomem);
    if (L->crs)
        c.crs = sink_put(k, L->crs_offset, (const uint8_t *)L->crs, L->crs_length, 0, 0);
    if (L->features)
        c.feat = emit_table(k, L->feat_offset, L->feat_length, feat_emit, L->features, &nomem);
    if (L->attributes)
        c.attr = emit_table(k, L->attr_offset, L->attr_length, attr_emit, L->attributes, &nomem);
    if (L->edge_features)
        c.edgf = emit_table(k, L->edgf_offset, L->edgf_length, edgf_emit, L->edge_features, &nomem);
    if (L->labl && !L->in_place)
        c.labl = sink_put(k, L->labl_offset, L->labl, L->labl_length, 0, 0);
    if (L->geom)
        c.geom = sink_put(k, L->geom_offset, L->geom, L->geom_length, 0, 0);
    int st = HPFC_OK;
    if (L->geom_plan)
        st = geometry_emit(L->geom_plan, (stream_target){sink_stream_put, k}, L->geom_offset,
                           &c.geom, diag);
    if (L->shix && !L->in_place)
        c.shix = sink_put(k, L->shix_offset, L->shix, L->shix_length, 0, 0);
    if (!st && nomem)
        st = diag_set(diag, HPFC_E_NOMEM, "out of memory");
    return st || k->err ? st : emit_meta(L, k, &c, diag);
}

/* ---- entry points ------------------------------------------------------------ */

static int check_tree_info(const hpfc_tree_info *t, hpfc_diag *diag)
{
    if (t->levels < 1 || t->levels > HPFC_MAX_LEVELS)
        return diag_set(diag, HPFC_E_LIMIT, "a tree of %u levels (the format allows 1 to %d)", t->levels,
                        HPFC_MAX_LEVELS);
    if (t->root_cols < 1 || t->root_rows < 1 || t->cols < 2 || t->rows < 2 ||
        (uint64_t)t->root_cols * t->root_rows > FORMAT_MAX_ROOT_PIXELS ||
        (uint64_t)t->cols * t->rows > FORMAT_MAX_IMAGE_PIXELS)
        return diag_set(diag, HPFC_E_LIMIT, "image sizes outside the format's range");
    if (t->width < 1 || t->height < 1 || t->width > FORMAT_MAX_EXTENT || t->height > FORMAT_MAX_EXTENT ||
        t->x0 < -FORMAT_MAX_ORIGIN || t->x0 > FORMAT_MAX_ORIGIN || t->y0 < -FORMAT_MAX_ORIGIN ||
        t->y0 > FORMAT_MAX_ORIGIN || t->unit_exp10 < FORMAT_MIN_UNIT_EXP10 ||
        t->unit_exp10 > FORMAT_MAX_UNIT_EXP10)
        return diag_set(diag, HPFC_E_LIMIT, "domain or unit outside the format's range");
    return HPFC_OK;
}

/* Places the sections and emits the file laid out in L (its pools sized). */
static int serialize_layout(layout *L, uint8_t **out, size_t *out_size, hpfc_diag *diag)
{
    int st = place_sections(L, diag);
    uint8_t *file = NULL;
    if (!st && !(file = calloc(1, (size_t)L->file_size)))
        st = diag_set(diag, HPFC_E_NOMEM, "out of memory for a %llu-byte file",
                      (unsigned long long)L->file_size);
    sink k = {.file = file, .fd = -1};
    if (!st)
        st = emit_to(L, &k, diag);
    if (!st) {
        *out = file;
        *out_size = (size_t)L->file_size;
    } else {
        free(file);
    }
    return st;
}

static int write_error(hpfc_diag *diag, const char *name, int err)
{
    if (name)
        return diag_set(diag, HPFC_E_IO, "cannot write %s: %s", name, strerror(err));
    return diag_set(diag, HPFC_E_IO, "cannot write: %s", strerror(err));
}

/* ---- LABL and GEOM --------------------------------------------------------- */

/* The faces of f (the tree's pools, serialised) numbered, whole on L's
 * threads or a root pixel at a time (faces.h, hpfc_write_options.
 * faces_by_root: a merge's writer then holds what the roots' borders need
 * rather than a union-find over the whole map), and LABL's first pass:
 * *w, the section's *length. */
static int begin_labels(layout *L, const hpfc_file *f, hpfc_faces **fc, faces_stream **fs,
                        labels_writer **w, uint64_t *length, hpfc_diag *diag)
{
    int st = L->faces_by_root && !L->faces_out ? faces_stream_plan(f, L->threads, fs)
                                                 : hpfc_faces_build_threads(f, L->threads, fc);
    if (st)
        return diag_set(diag, st, "labels: numbering the faces failed");
    return labels_writer_begin(L->tree, f, *fc, *fs, w, length, diag);
}

/* LABL made in `sec` (its zeroed bytes), and the faces handed to the
 * caller who asked for them (faces_out). */
static int finish_labels(layout *L, labels_writer *w, uint8_t *sec, hpfc_faces **fc,
                         hpfc_diag *diag)
{
    int st = labels_writer_emit(w, sec, diag);
    /* the faces answer for every copy of these pools: the caller may have
     * them, bound to the file it opens (hpfc_faces_attach) */
    if (!st && L->faces_out) {
        if ((st = faces_detach(*fc)))
            diag_set(diag, st, "labels: the serialised pools lie outside their file");
        else
            *L->faces_out = *fc, *fc = NULL;
    }
    return st;
}

/* The LABL section of the tree laid out in L, in memory: its faces are
 * numbered on the file serialised without it (face ids depend on the
 * pools only). */
static int make_labels(layout *L, void *unused, hpfc_diag *diag)
{
    (void)unused;
    uint8_t *bytes = NULL, *labl = NULL;
    size_t size = 0;
    hpfc_file *f = NULL;
    hpfc_faces *fc = NULL;
    faces_stream *fs = NULL;
    labels_writer *w = NULL;
    uint64_t length = 0;
    int st = serialize_layout(L, &bytes, &size, diag);
    if (!st && (st = hpfc_open_memory(bytes, size, 0, &f)))
        diag_set(diag, st, "labels: the serialised file does not read back");
    if (!st)
        st = begin_labels(L, f, &fc, &fs, &w, &length, diag);
    if (!st && !(labl = calloc(1, (size_t)length)))
        st = diag_set(diag, HPFC_E_NOMEM, "labels: out of memory");
    if (!st)
        st = finish_labels(L, w, labl, &fc, diag);
    labels_writer_free(w);
    faces_stream_free(fs);
    hpfc_faces_free(fc);
    hpfc_close(f);
    free(bytes);
    if (st) {
        free(labl);
        return st;
    }
    L->labl = labl;
    L->labl_length = length;
    return HPFC_OK;
}

/* The GEOM section of the tree laid out in L, from the graph it was built
 * from (spec §6.6): planned here, streamed out with the other sections.
 * The plan needs the tree and the graph alone: with threads to spare it
 * is made on a thread of its own beside the labels (a fifth of the
 * labels' time on a continental map), into the job rather than L, whose
 * sections the labels' step may lay out without GEOM. */
typedef struct geometry_job {
    const hpfc_tree *tree;
    const hpfc_graph *graph;
    geom_writer *plan;
    uint64_t length;
    int status;
    hpfc_diag diag;
} geometry_job;

static void *plan_geometry(void *arg)
{
    geometry_job *job = arg;
    job->status = geometry_plan(job->tree, job->graph, &job->plan, &job->length, &job->diag);
    return NULL;
}

/* A step that makes or begins LABL (make_labels, or in place
 * pools_and_labels) on `ctx`. */
typedef int (*labels_step)(layout *L, void *ctx, hpfc_diag *diag);

/* The labels' step when opts asks for LABL, then GEOM's plan into L, the
 * plan beside the step on two threads or more; the first failure of the
 * two in that order. */
static int labels_and_geometry(layout *L, const hpfc_write_options *opts, labels_step step,
                               void *ctx, hpfc_diag *diag)
{
    geometry_job job = {.tree = L->tree, .graph = opts->geometry};
    diag_clear(&job.diag);
    pthread_t thread;
    bool beside = opts->geometry && opts->face_labels && L->threads > 1 &&
                  pthread_create(&thread, NULL, plan_geometry, &job) == 0;
    int st = opts->face_labels ? step(L, ctx, diag) : HPFC_OK;
    if (beside)
        pthread_join(thread, NULL);
    else if (!st && opts->geometry)
        plan_geometry(&job);
    if (!st && job.status) {
        if (diag) /* the caller may want no message */
            *diag = job.diag;
        st = job.status;
    }
    if (!st) {
        L->geom_plan = job.plan;
        L->geom_length = job.length;
    } else {
        geometry_writer_free(job.plan);
    }
    return st;
}

/* ---- the file made in its own pages ------------------------------------------ */

/* A file written in place (write_in_place) holds, between its steps, the
 * pools mapped back under a provisional header, their faces and LABL's
 * writer. */
typedef struct in_place {
    sink *k;
    const uint8_t *view;
    uint64_t view_size;
    hpfc_file *f;
    hpfc_faces *fc;
    faces_stream *fs;
    labels_writer *w;
} in_place;

static void in_place_free(in_place *ip)
{
    labels_writer_free(ip->w);
    faces_stream_free(ip->fs);
    hpfc_faces_free(ip->fc);
    hpfc_close(ip->f);
    if (ip->view)
        sink_unmap(ip->view, 0, ip->view_size);
}

/* L's pools under a header that names them alone: a file that opens with
 * the pools at their final offsets, the bytes between its smaller
 * metadata and the pools zero (padding, spec §4). The final metadata,
 * written last, covers it. */
static layout provisional(const layout *L)
{
    layout P = *L;
    P.crs = NULL, P.features = NULL, P.attributes = NULL, P.edge_features = NULL;
    P.labl = NULL, P.geom = NULL, P.geom_plan = NULL, P.shix = NULL, P.in_place = false;
    P.section_count = 1;
    P.meta_size = FORMAT_HEADER_SIZE + (uint64_t)FORMAT_LEVEL_ENTRY_SIZE * L->info.levels +
                  FORMAT_SECTION_ENTRY_SIZE;
    P.file_size = L->pool_section + L->pool_length;
    return P;
}

/* The labels' step in place: the pools written into the file, read back
 * under a provisional header, their faces numbered and LABL's first pass.
 * A write error stays in the sink. */
static int pools_and_labels(layout *L, void *ctx, hpfc_diag *diag)
{
    in_place *ip = ctx;
    sink *k = ip->k;
    int nomem = 0;
    sink_grow(k, 0, L->file_size);
    if (!k->err)
        L->pool_crc = emit_pools(L, k, &nomem);
    layout P = provisional(L);
    int st = k->err ? HPFC_OK : emit_meta(&P, k, &(section_crcs){.pool = L->pool_crc}, diag);
    if (st || k->err || !(ip->view = sink_map(k, 0, P.file_size, PROT_READ)))
        return st;
    ip->view_size = P.file_size;
    if ((st = hpfc_open_memory(ip->view, (size_t)ip->view_size, 0, &ip->f)))
        return diag_set(diag, st, "labels: the pools written do not read back");
    return begin_labels(L, ip->f, &ip->fc, &ip->fs, &ip->w, &L->labl_length, diag);
}

/* SHIX measured from the LABL just made (L->labl, in the file's pages),
 * placed last and made in its own pages. */
static int index_in_place(layout *L, sink *k, hpfc_diag *diag)
{
    labels_view v;
    shix_plan plan;
    if (labels_of(L, &v))
        return diag_set(diag, HPFC_E_ARG, "shape index: the labels do not read back");
    int st = shix_measure(&v, L->features, L->edge_features, &plan, diag);
    uint64_t from = L->file_size;
    if (!st) {
        L->shix_length = plan.length;
        L->shix_offset = append_section(&L->file_size, plan.length);
        st = check_file_size(L, diag);
    }
    if (st)
        return st;
    sink_grow(k, from, L->file_size);
    uint8_t *room = k->err ? NULL : sink_map(k, L->shix_offset, plan.length, PROT_READ | PROT_WRITE);
    if (room) {
        shix_emit(&plan, &v, L->features, L->edge_features, room);
        L->shix_crc = sink_put(k, L->shix_offset, room, plan.length, 1, 0);
    }
    return HPFC_OK;
}

/* LABL made in its pages (placed: place_tail), then SHIX from it. */
static int labels_in_place(layout *L, in_place *ip, hpfc_diag *diag)
{
    sink *k = ip->k;
    sink_grow(k, L->pool_section + L->pool_length, L->file_size);
    uint8_t *labl =
        k->err ? NULL : sink_map(k, L->labl_offset, L->labl_length, PROT_READ | PROT_WRITE);
    if (!labl)
        return HPFC_OK;
    int st = finish_labels(L, ip->w, labl, &ip->fc, diag);
    if (!st) {
        L->labl = labl; /* for labels_of, while it is mapped */
        st = index_in_place(L, k, diag);
        L->labl = NULL;
    }
    L->labl_crc = sink_put(k, L->labl_offset, labl, L->labl_length, 1, 0);
    return st;
}

/* The tree laid out in L (its pools sized, LABL and GEOM not yet made)
 * written to fd, mapped, in its own pages: the pools, then read back for
 * their faces, LABL placed and made, SHIX from it, the other sections,
 * then the metadata. The writer holds no section; what it holds is the
 * faces' numbering, LABL's pass-1 plan and GEOM's plan. */
static int write_in_place(layout *L, const hpfc_write_options *opts, sink *k, hpfc_diag *diag)
{
    in_place ip = {.k = k};
    L->in_place = true;
    int st = place_pools(L, diag);
    if (!st)
        st = labels_and_geometry(L, opts, pools_and_labels, &ip, diag);
    if (!st && !k->err)
        st = place_tail(L, diag);
    if (!st && !k->err)
        st = labels_in_place(L, &ip, diag);
    in_place_free(&ip);
    if (!st && !k->err)
        st = emit_to(L, k, diag);
    return st;
}

/* Whether the tree laid out in L is written in place to fd: LABL asked
 * for, fd mapped, and SHIX storable whatever the faces (it is counted
 * before LABL is made). */
static bool writes_in_place(const layout *L, const hpfc_write_options *opts, int fd)
{
    return L->tree && opts->face_labels &&
           shix_fits(L->info.edges, L->features, L->edge_features) && can_map(fd);
}

/* Writes the file laid out in L (a tree's: its LABL and GEOM not yet
 * made, as opts asks) to fd, a regular file, from its start, a section
 * at a time; `name` for the messages (NULL: the caller's descriptor,
 * which the caller names). */
static int write_layout(layout *L, int fd, const char *name, hpfc_diag *diag)
{
    const hpfc_write_options *opts = L->opts;
    if (ftruncate(fd, 0) != 0) /* emptied: the padding between sections reads as zeros */
        return write_error(diag, name, errno);
    sink k = {.fd = fd};
    int st;
    if (writes_in_place(L, opts, fd)) {
        k.mapped = true;
        st = write_in_place(L, opts, &k, diag);
    } else {
        st = L->tree ? labels_and_geometry(L, opts, make_labels, NULL, diag) : HPFC_OK;
        if (!st)
            st = place_sections(L, diag);
        if (!st && ftruncate(fd, (off_t)L->file_size) != 0)
            return write_error(diag, name, errno);
        if (!st)
            st = emit_to(L, &k, diag);
    }
    if (st)
        return st;
    return k.err ? write_error(diag, name, k.err) : HPFC_OK;
}

/* The caller's options of `size` bytes over the defaults (all zero), into
 * *full; NULL is the defaults. */
static int read_options(const hpfc_write_options *opts, size_t size, hpfc_write_options *full,
                        const char *who, hpfc_diag *diag)
{
    *full = (hpfc_write_options){0};
    if (opts && sized_in(full, sizeof *full, opts, size))
        return diag_set(diag, HPFC_E_ARG, "%s: options unknown to this library are set", who);
    return HPFC_OK;
}

/* What every serialize and write call (`who`) does first: the diagnostic
 * cleared, the source (the tree or the file) checked, the caller's options
 * read over the defaults into *opts, and L started with the sections opts
 * gives. */
static int begin_layout(const char *who, const void *source, const hpfc_write_options *opts_arg,
                        size_t opts_size, hpfc_write_options *opts, layout *L, hpfc_diag *diag)
{
    diag_clear(diag);
    *L = (layout){0};
    if (!source)
        return diag_set(diag, HPFC_E_ARG, "%s: NULL argument", who);
    int st = read_options(opts_arg, opts_size, opts, who, diag);
    if (st)
        return st;
    *L = (layout){.opts = opts,
                  .crs = opts->crs,
                  .features = opts->features,
                  .attributes = opts->attributes,
                  .edge_features = opts->edge_features,
                  .faces_out = opts->faces_out,
                  .threads = opts->threads,
                  .faces_by_root = opts->faces_by_root != 0};
    if (opts->faces_out)
        *opts->faces_out = NULL;
    return HPFC_OK;
}

/* The serialize calls' start: begin_layout, and the outputs emptied. */
static int begin_serialize(const char *who, const void *source, const hpfc_write_options *opts_arg,
                           size_t opts_size, uint8_t **out, size_t *out_size,
                           hpfc_write_options *opts, layout *L, hpfc_diag *diag)
{
    int st = begin_layout(who, source, opts_arg, opts_size, opts, L, diag);
    if (!st && (!out || !out_size))
        st = diag_set(diag, HPFC_E_ARG, "%s: NULL argument", who);
    if (st)
        return st;
    *out = NULL;
    *out_size = 0;
    return HPFC_OK;
}

/* The tree's layout: counted and sized; its LABL and GEOM are made as
 * opts asks by the serialize call (labels_and_geometry) or as the write
 * calls place them (write_layout). layout_release after, whatever it
 * returns. */
static int lay_out_tree(const hpfc_tree *tree, const hpfc_write_options *opts, layout *L,
                        hpfc_diag *diag)
{
    int kind = opts->layout;
    if (kind < HPFC_LAYOUT_DEFAULT || kind > HPFC_LAYOUT_COMPACT)
        return diag_set(diag, HPFC_E_ARG, "unknown layout %d", kind);
    if (tree->part)
        return diag_set(diag, HPFC_E_ARG, "a part of a split build: hpfc_tree_merge the parts first");
    L->tree = tree;
    L->compact = kind != HPFC_LAYOUT_PAPER; /* HPFC_LAYOUT_DEFAULT is the compact layout */
    hpfc_tree_get_info(tree, &L->info);
    int st = check_tree_info(&L->info, diag);
    for (uint32_t l = 0; l < L->info.levels && !st; l++)
        st = count_level(L, l, diag);
    if (!st)
        st = size_levels(L, diag);
    return st;
}

/* What lay_out_tree made (an open file's layout only points into it),
 * and the faces handed out when the call that made them fails after. */
static void layout_release(layout *L, int status)
{
    if (status && L->faces_out) {
        hpfc_faces_free(*L->faces_out);
        *L->faces_out = NULL;
    }
    if (L->tree) {
        free((void *)L->labl);
        geometry_writer_free(L->geom_plan);
    }
    layout_free(L);
}

/* An open file's layout: its pools, LABL and GEOM as they are. */
static void lay_out_file(const hpfc_file *file, layout *L)
{
    L->source = file;
    const labels_view *labels = &file->labels;
    if (labels->present) { /* the pools are copied bit for bit: the labels stay true */
        L->labl = labels->section;
        L->labl_length = labels->section_length;
    }
    const geom_view *geometry = &file->geom;
    if (geometry->present) { /* ids and coordinates do not depend on the sections replaced */
        L->geom = geometry->section;
        L->geom_length = geometry->section_length;
    }
    hpfc_file_info fi;
    hpfc_file_get_info(file, &fi);
    L->info = (hpfc_tree_info){.root_cols = fi.root_cols,
                               .root_rows = fi.root_rows,
                               .cols = fi.cols,
                               .rows = fi.rows,
                               .levels = fi.levels,
                               .x0 = fi.x0,
                               .y0 = fi.y0,
                               .width = fi.width,
                               .height = fi.height,
                               .unit_exp10 = fi.unit_exp10};
    /* the pools are copied as they are, in their layout */
    L->compact = file->compact;
    const uint8_t *bytes = file->data;
    for (uint32_t l = 0; l < fi.levels; l++) {
        hpfc_level_info li;
        hpfc_file_get_level(file, l, &li);
        L->lv[l] = (format_level){li.word_pixels, li.refined_pixels, li.images,
                                  li.word_bits,   li.address_bits,   li.pool_bits};
        const uint8_t *e = bytes + hdr_get_header_size(bytes) + (size_t)l * FORMAT_LEVEL_ENTRY_SIZE;
        L->stabbed[l] = L->compact ? lvl_get_stabbed_pixels(e) : 0;
        L->stream_bits[l] = L->compact ? lvl_get_stream_bits(e) : 0;
    }
}

/* hpfc_tree_serialize and hpfc_file_serialize below share their signature
 * (hpfc.h) and their start (begin_serialize); what stays twice is only that
 * call. They part where the pools come from: laid out from the tree here,
 * copied from the file there. */
int hpfc_tree_serialize_sized(const hpfc_tree *tree, const hpfc_write_options *opts_arg,
                              size_t opts_size, uint8_t **out, size_t *out_size, hpfc_diag *diag)
{
    hpfc_write_options opts;
    layout L;
    int st = begin_serialize("hpfc_tree_serialize", tree, opts_arg, opts_size, out, out_size,
                             &opts, &L, diag);
    if (st)
        return st;
    st = lay_out_tree(tree, &opts, &L, diag);
    if (!st)
        st = labels_and_geometry(&L, &opts, make_labels, NULL, diag);
    if (!st)
        st = serialize_layout(&L, out, out_size, diag);
    layout_release(&L, st);
    return st;
}

/* Starts as hpfc_tree_serialize does (see there); the pools are copied. */
int hpfc_file_serialize_sized(const hpfc_file *file, const hpfc_write_options *opts_arg,
                              size_t opts_size, uint8_t **out, size_t *out_size, hpfc_diag *diag)
{
    hpfc_write_options opts;
    layout L;
    int st = begin_serialize("hpfc_file_serialize", file, opts_arg, opts_size, out, out_size,
                             &opts, &L, diag);
    if (st)
        return st;
    lay_out_file(file, &L);
    st = serialize_layout(&L, out, out_size, diag);
    layout_release(&L, st);
    return st;
}

/* The write_fd calls' start (they mirror the serialize pair): begin_layout,
 * and the descriptor checked. */
static int begin_write_fd(const char *who, const void *source, const hpfc_write_options *opts_arg,
                          size_t opts_size, int fd, hpfc_write_options *opts, layout *L,
                          hpfc_diag *diag)
{
    int st = begin_layout(who, source, opts_arg, opts_size, opts, L, diag);
    if (!st && fd < 0)
        st = diag_set(diag, HPFC_E_ARG, "%s: no file descriptor", who);
    return st;
}

int hpfc_tree_write_fd_sized(const hpfc_tree *tree, const hpfc_write_options *opts_arg,
                             size_t opts_size, int fd, hpfc_diag *diag)
{
    hpfc_write_options opts;
    layout L;
    int st = begin_write_fd("hpfc_tree_write_fd", tree, opts_arg, opts_size, fd, &opts, &L, diag);
    if (st)
        return st;
    st = lay_out_tree(tree, &opts, &L, diag);
    if (!st)
        st = write_layout(&L, fd, NULL, diag);
    layout_release(&L, st);
    return st;
}

/* Starts as hpfc_tree_write_fd does (see there); the pools are copied. */
int hpfc_file_write_fd_sized(const hpfc_file *file, const hpfc_write_options *opts_arg,
                             size_t opts_size, int fd, hpfc_diag *diag)
{
    hpfc_write_options opts;
    layout L;
    int st = begin_write_fd("hpfc_file_write_fd", file, opts_arg, opts_size, fd, &opts, &L, diag);
    if (st)
        return st;
    lay_out_file(file, &L);
    st = write_layout(&L, fd, NULL, diag);
    layout_release(&L, st);
    return st;
}

/* ---- atomic file output ------------------------------------------------------ */

static int io_error(hpfc_diag *diag, const char *what, const char *path, int err)
{
    return diag_set(diag, HPFC_E_IO, "cannot %s %s: %s", what, path, strerror(err));
}

/* Splits path into its directory (".", "/" or "dir") and its last name. */
static int split_path(const char *path, char **dir, const char **base)
{
    const char *slash = strrchr(path, '/');
    size_t dlen = slash ? (size_t)(slash - path) : 1;
    if (slash && dlen == 0)
        dlen = 1; /* "/name": the root directory */
    *dir = malloc(dlen + 1);
    if (!*dir)
        return HPFC_E_NOMEM;
    memcpy(*dir, slash ? path : ".", dlen);
    (*dir)[dlen] = '\0';
    *base = slash ? slash + 1 : path;
    return HPFC_OK;
}

static uint64_t mix64(uint64_t z)
{
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9u;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebu;
    return z ^ (z >> 31);
}

/* Creates "<dir>/.<base>.XXXXXXXXXXXX.tmp" exclusively, like mkstemp, but
 * with mode 0666 so the umask gives the file its usual permissions. */
static int create_temp(const char *dir, const char *base, char **tmp, int *fd)
{
    size_t cap = strlen(dir) + strlen(base) + 32;
    *tmp = malloc(cap);
    if (!*tmp)
        return HPFC_E_NOMEM;
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    uint64_t seed = (uint64_t)ts.tv_nsec ^ (uint64_t)ts.tv_sec << 30 ^ (uint64_t)getpid() << 16 ^
                    (uint64_t)(uintptr_t)&ts;
    for (int attempt = 0; attempt < 64; attempt++) {
        seed = mix64(seed + (uint64_t)attempt);
        snprintf(*tmp, cap, "%s/.%s.%012llx.tmp", dir, base,
                 (unsigned long long)(seed & 0xffffffffffffu));
        /* read and write: the writer maps it (write_in_place) */
        *fd = open(*tmp, O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (*fd >= 0 || errno != EEXIST)
            return HPFC_OK;
    }
    return HPFC_OK; /* *fd < 0 with errno == EEXIST */
}

/* Makes the rename durable. Some file systems refuse fsync on a directory
 * (EINVAL); the rename has happened by then, so only real errors count. */
static int sync_dir(const char *dir)
{
    int fd = open(dir, O_RDONLY | O_CLOEXEC);
    if (fd < 0)
        return errno;
    int err = fsync(fd) ? errno : 0;
    close(fd);
    return err == EINVAL || err == ENOTSUP ? 0 : err;
}

/* What fills a new file: a layout (write_layout) or bytes in memory. */
typedef int (*file_filler)(int fd, const char *name, const void *source, hpfc_diag *diag);

static int fill_layout(int fd, const char *name, const void *source, hpfc_diag *diag)
{
    return write_layout((layout *)source, fd, name, diag);
}

typedef struct byte_span {
    const uint8_t *bytes;
    size_t size;
} byte_span;

static int fill_bytes(int fd, const char *name, const void *source, hpfc_diag *diag)
{
    const byte_span *b = source;
    for (size_t done = 0; done < b->size;) {
        ssize_t n = write(fd, b->bytes + done, b->size - done);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            return write_error(diag, name, n < 0 ? errno : EIO);
        done += (size_t)n;
    }
    return HPFC_OK;
}

/* Fills the temporary file, syncs and closes it (fd is closed in any
 * case). */
static int fill_temp(int fd, const char *tmp, file_filler fill, const void *source, hpfc_diag *diag)
{
    int st = fill(fd, tmp, source, diag), err = 0;
    if (!st && fsync(fd))
        err = errno;
    if (close(fd) && !st && !err)
        err = errno;
    return st ? st : err ? io_error(diag, "write", tmp, err) : HPFC_OK;
}

/* The source written to path by `fill` through a temporary file beside
 * it, renamed over path once complete and synced. */
static int write_atomic(const char *path, file_filler fill, const void *source, hpfc_diag *diag)
{
    char *dir = NULL, *tmp = NULL;
    const char *base;
    if (split_path(path, &dir, &base))
        return diag_set(diag, HPFC_E_NOMEM, "out of memory");
    int fd = -1, st, err;
    if (*base == '\0') {
        st = diag_set(diag, HPFC_E_ARG, "%s: not a file name", path);
    } else if (create_temp(dir, base, &tmp, &fd)) {
        st = diag_set(diag, HPFC_E_NOMEM, "out of memory");
    } else if (fd < 0) {
        st = io_error(diag, "create a temporary file in", dir, errno);
    } else {
        st = fill_temp(fd, tmp, fill, source, diag);
        if (!st && rename(tmp, path))
            st = io_error(diag, "replace", path, errno);
        if (st)
            unlink(tmp); /* ours: created with O_EXCL, and not renamed */
        else if ((err = sync_dir(dir)))
            st = io_error(diag, "sync the directory of", path, err);
    }
    free(dir);
    free(tmp);
    return st;
}

/* The write calls stream the file to disk a section at a time
 * (write_layout): the serialised file is never held whole. The two share
 * their start and their end (begin_layout, write_atomic) and part, as the
 * serialize pair does, where the layout comes from: the tree or the file. */
int hpfc_tree_write_file_sized(const hpfc_tree *tree, const hpfc_write_options *opts_arg,
                               size_t opts_size, const char *path, hpfc_diag *diag)
{
    hpfc_write_options opts;
    layout L;
    int st = begin_layout("hpfc_tree_write_file", tree, opts_arg, opts_size, &opts, &L, diag);
    if (!st && !path)
        st = diag_set(diag, HPFC_E_ARG, "hpfc_tree_write_file: NULL path");
    if (st)
        return st;
    st = lay_out_tree(tree, &opts, &L, diag);
    if (!st)
        st = write_atomic(path, fill_layout, &L, diag);
    layout_release(&L, st);
    return st;
}

int hpfc_file_write_file_sized(const hpfc_file *file, const hpfc_write_options *opts_arg,
                               size_t opts_size, const char *path, hpfc_diag *diag)
{
    hpfc_write_options opts;
    layout L;
    int st = begin_layout("hpfc_file_write_file", file, opts_arg, opts_size, &opts, &L, diag);
    if (!st && !path)
        st = diag_set(diag, HPFC_E_ARG, "hpfc_file_write_file: NULL path");
    if (st)
        return st;
    lay_out_file(file, &L);
    st = write_atomic(path, fill_layout, &L, diag);
    layout_release(&L, st);
    return st;
}

int hpfc_tree_write_part_fd(const hpfc_tree *part, int fd, hpfc_diag *diag)
{
    diag_clear(diag);
    if (!part || fd < 0)
        return diag_set(diag, HPFC_E_ARG, "hpfc_tree_write_part_fd: NULL argument or no file descriptor");
    byte_span span = {0};
    uint8_t *bytes = NULL;
    int st = part_serialize(part, &bytes, &span.size, diag);
    span.bytes = bytes;
    if (!st && (lseek(fd, 0, SEEK_SET) < 0 || ftruncate(fd, 0) != 0))
        st = write_error(diag, NULL, errno);
    if (!st)
        st = fill_bytes(fd, NULL, &span, diag);
    free(bytes);
    return st;
}

int hpfc_tree_write_part(const hpfc_tree *part, const char *path, hpfc_diag *diag)
{
    diag_clear(diag);
    if (!part || !path)
        return diag_set(diag, HPFC_E_ARG, "hpfc_tree_write_part: NULL argument");
    byte_span span = {0};
    uint8_t *bytes = NULL;
    int st = part_serialize(part, &bytes, &span.size, diag);
    span.bytes = bytes;
    if (!st)
        st = write_atomic(path, fill_bytes, &span, diag);
    free(bytes);
    return st;
}
