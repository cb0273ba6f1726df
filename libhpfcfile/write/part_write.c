/*
 * The part file (spec/part-format.md): a part's tree, array by array, as
 * build/part_read.c reads it back.
 */
#include <stdlib.h>
#include <string.h>

#include "part_file.h"
#include "tree.h"

/* Level l's pixels per image: the root's, or a refined image's. */
static size_t pixels_per_image(const hpfc_tree *t, uint32_t l)
{
    return l ? (size_t)t->info.cols * t->info.rows : (size_t)t->info.root_cols * t->info.root_rows;
}

static uint64_t part_size(const hpfc_tree *t)
{
    uint64_t size = PART_HEADER_SIZE + (uint64_t)PART_LEVEL_ENTRY_SIZE * t->levels_cap;
    for (uint32_t l = 0; l < t->info.levels; l++)
        size += (uint64_t)t->levels[l].nimages * (16 + PART_PIXEL_SIZE * pixels_per_image(t, l));
    size += t->nsyms + part_symbols_padding(t->nsyms) + (uint64_t)t->ncross * (t->cross_seg ? 8 : 4);
    return size + PART_CRC_SIZE;
}

static void put_header(const hpfc_tree *t, uint8_t *h)
{
    const hpfc_tree_info *i = &t->info;
    memcpy(h + part_OFF_magic, PART_MAGIC, part_SIZE_magic);
    part_set_version(h, PART_VERSION);
    part_set_root_cols(h, i->root_cols);
    part_set_root_rows(h, i->root_rows);
    part_set_cols(h, i->cols);
    part_set_rows(h, i->rows);
    part_set_levels(h, i->levels);
    part_set_level_count(h, t->levels_cap);
    part_set_x0(h, i->x0);
    part_set_y0(h, i->y0);
    part_set_width(h, i->width);
    part_set_height(h, i->height);
    part_set_unit_exp10(h, i->unit_exp10);
    part_set_max_word_symbols(h, i->max_word_symbols);
    part_set_vertices(h, i->vertices);
    part_set_edges(h, i->edges);
    part_set_word_pixels(h, i->word_pixels);
    part_set_refined_pixels(h, i->refined_pixels);
    part_set_private_pixels(h, i->private_pixels);
    part_set_symbols(h, t->nsyms);
    part_set_crossings(h, t->ncross);
    part_set_has_segments(h, t->cross_seg != NULL);
}

static uint8_t *put_u32s(uint8_t *at, const uint32_t *v, size_t n)
{
    for (size_t k = 0; k < n; k++, at += 4)
        le_store(at, 4, v[k]);
    return at;
}

static uint8_t *put_level(const hpfc_tree *t, uint32_t l, uint8_t *at)
{
    const tlevel *lv = &t->levels[l];
    size_t pixels = lv->nimages * pixels_per_image(t, l);
    for (size_t k = 0; k < lv->nimages; k++, at += 8)
        le_store(at, 8, (uint64_t)lv->img_gx[k]);
    for (size_t k = 0; k < lv->nimages; k++, at += 8)
        le_store(at, 8, (uint64_t)lv->img_gy[k]);
    for (size_t k = 0; k < pixels; k++, at += PART_PIXEL_SIZE) {
        le_store(at, 8, lv->pix[k].off);
        le_store(at + 8, 8, lv->pix[k].cross);
    }
    return at;
}

int part_serialize(const hpfc_tree *t, uint8_t **out, size_t *out_size, hpfc_diag *diag)
{
    if (!t->part)
        return diag_set(diag, HPFC_E_ARG, "hpfc_tree_write_part: not a part's tree (hpfc_build_part)");
    uint64_t size = part_size(t);
    uint8_t *bytes = size <= SIZE_MAX ? calloc(1, (size_t)size) : NULL;
    if (!bytes)
        return diag_set(diag, HPFC_E_NOMEM, "out of memory for a %llu-byte part file",
                        (unsigned long long)size);
    put_header(t, bytes);
    uint8_t *at = bytes + PART_HEADER_SIZE;
    for (uint32_t l = 0; l < t->levels_cap; l++, at += PART_LEVEL_ENTRY_SIZE)
        le_store(at, 8, l < t->info.levels ? t->levels[l].nimages : 0);
    for (uint32_t l = 0; l < t->info.levels; l++)
        at = put_level(t, l, at);
    memcpy(at, t->syms, t->nsyms);
    at = put_u32s(at + t->nsyms + part_symbols_padding(t->nsyms), t->cross_edge, t->ncross); /* calloc'd: the padding is zeros */
    if (t->cross_seg)
        at = put_u32s(at, t->cross_seg, t->ncross);
    le_store(at, 4, crc32c_update(0, bytes, (size_t)(at - bytes)));
    *out = bytes;
    *out_size = (size_t)size;
    return HPFC_OK;
}
