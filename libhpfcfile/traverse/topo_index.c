/*
 * Keys and pixels (spec/hpfc-format.md §3.10): the key of a dart or
 * vertex from its pixel, and back, the word pixel of a key's slot with its
 * path from the root and its dense id, through a parent index built once
 * per walker by one pass over the pools. The index also checks the layout
 * that makes the path unique (§5.2.2: images back to back in parent order,
 * every address the start of the next image), so the path it gives is the
 * one dart operators use for that pixel. Calls only the reader.
 */
#include <stdlib.h>
#include <string.h>

#include "file.h"
#include "reader.h"
#include "topo.h"

/* The key of local id `id` of word pixel px: HPFC_KEY_INVALID when px
 * names no pixel of the file (its slot cannot be found). */
static uint64_t pixel_key(const hpfc_file *f, const hpfc_pixel *px, uint32_t id)
{
    uint64_t slot;
    if (!f || reader_pixel_slot_bit(f, px, &slot) != HPFC_OK)
        return HPFC_KEY_INVALID;
    return topo_key(slot, id);
}

uint64_t hpfc_vertex_key(const hpfc_file *f, const hpfc_vertex *v)
{
    return v ? pixel_key(f, &v->pixel, v->local) : HPFC_KEY_INVALID;
}

uint64_t hpfc_dart_key(const hpfc_file *f, const hpfc_dart *d)
{
    return d ? pixel_key(f, &d->pixel, d->crossing) : HPFC_KEY_INVALID;
}

void topo_index_free(hpfc_walker *w)
{
    free(w->keys.images);
    memset(&w->keys, 0, sizeof w->keys);
}

/* ---- the parent index ------------------------------------------------------ */

/* Level l + 1's images from level l's refined pixels, in pool order: each
 * address must be where the previous image ends, and the images must fill
 * the pool exactly. Anything else is corruption (aliased or out-of-order
 * addresses, masks that contradict the level table). */
static int index_level(hpfc_walker *w, uint32_t l, const hpfc_level_info *lv)
{
    key_index *x = &w->keys;
    key_image *next = x->images + x->first[l + 1];
    uint64_t parents = l ? lv[l].images : 1, count = lv[l + 1].images, c = 0, at = 0;
    for (uint64_t img = 0; img < parents; img++) {
        uint64_t start = l ? x->images[x->first[l] + img].start : 0, address, bits, refined;
        reader_refined it = {0, 0};
        uint32_t pixel;
        int st;
        while ((st = reader_next_refined(w->file, l, start, &it, &pixel, &address)) == HPFC_OK) {
            if (c == count || address != at)
                return HPFC_E_CORRUPT;
            if ((st = reader_image_bits(w->file, l + 1, at, &bits, &refined)))
                return st;
            next[c++] = (key_image){at, (uint32_t)img, pixel};
            at += bits;
        }
    }
    return c == count && at == reader_image_end(w->file, l + 1) ? HPFC_OK : HPFC_E_CORRUPT;
}

static int build_index(hpfc_walker *w)
{
    key_index *x = &w->keys;
    hpfc_level_info lv[HPFC_MAX_LEVELS];
    hpfc_file_info info;
    hpfc_file_get_info(w->file, &info);
    x->root_cols = info.root_cols;
    x->cols = info.cols;
    x->image_pixels = (uint64_t)info.cols * info.rows;
    uint64_t total = 0, pixels = 0;
    for (uint32_t l = 0; l < w->levels; l++) {
        hpfc_file_get_level(w->file, l, &lv[l]);
        x->pool_bit[l] = lv[l].pool_offset * 8;
        x->pool_bits[l] = lv[l].pool_bits;
        x->first[l] = total;
        x->pixel_first[l] = pixels;
        if (l > 0) {
            /* open checked images * pixels <= s^l, so the totals fit */
            if (lv[l].images > UINT32_MAX)
                return HPFC_E_LIMIT;
            total += lv[l].images;
            pixels += lv[l].images * x->image_pixels;
        } else {
            pixels += (uint64_t)info.root_cols * info.root_rows;
        }
    }
    x->first[w->levels] = total;
    x->pixel_first[w->levels] = pixels;
    /* a file of huge words and many pixels: its indices would not fit, but
     * its keys still work */
    x->bound_status = w->cap && pixels > UINT64_MAX / w->cap ? HPFC_E_LIMIT : HPFC_OK;
    x->bound = x->bound_status ? 0 : pixels * w->cap;
    if (!(x->images = malloc(total ? total * sizeof *x->images : 1)))
        return HPFC_E_NOMEM;
    int st = HPFC_OK;
    for (uint32_t l = 0; l + 1 < w->levels && !st; l++)
        st = index_level(w, l, lv);
    return st;
}

/* The word pixel whose slot starts at absolute bit `pos`, with its path
 * from the root and its dense id: HPFC_E_ARG when no word slot starts
 * there. */
static int slot_pixel(hpfc_walker *w, uint64_t pos, hpfc_pixel *px, uint64_t *id)
{
    const key_index *x = &w->keys;
    uint32_t l = 0;
    while (l < w->levels && (pos < x->pool_bit[l] || pos - x->pool_bit[l] >= x->pool_bits[l]))
        l++;
    if (l == w->levels)
        return HPFC_E_ARG;
    uint64_t rel = pos - x->pool_bit[l], index = 0, start = 0;
    if (l > 0 && w->file->compact) { /* images are numbered: the type bits say which */
        int st = reader_slot_image(w->file, l, rel, &index);
        if (st)
            return st;
        start = index;
    } else if (l > 0) { /* the last image starting at or before rel (image 0 starts at 0) */
        uint64_t lo = x->first[l], hi = x->first[l + 1];
        while (hi - lo > 1) {
            uint64_t mid = lo + (hi - lo) / 2;
            if (x->images[mid].start <= rel)
                lo = mid;
            else
                hi = mid;
        }
        index = lo - x->first[l];
        start = x->images[lo].start;
    }
    uint32_t pixel;
    int st = reader_word_at(w->file, l, start, rel, &pixel);
    if (st)
        return st;
    *id = x->pixel_first[l] + index * x->image_pixels + pixel;
    px->depth = l;
    for (;;) {
        uint32_t cols = l ? x->cols : x->root_cols;
        px->path[l].image = start;
        px->path[l].i = pixel % cols;
        px->path[l].j = pixel / cols;
        if (l == 0)
            return HPFC_OK;
        const key_image *k = &x->images[x->first[l] + index];
        l--;
        index = k->parent;
        pixel = k->pixel;
        start = l ? x->images[x->first[l] + index].start : 0;
    }
}

/* The parent index, built on first use: its status. */
int topo_index_ready(hpfc_walker *w)
{
    if (!w->keys.built) {
        int st = build_index(w);
        if (st)
            topo_index_free(w);
        if (st == HPFC_E_NOMEM)
            return st; /* not built: the next key tries again */
        w->keys.status = st;
        w->keys.built = true;
    }
    return w->keys.status;
}

/* The path and dense id of the key's word pixel. */
int topo_key_pixel(hpfc_walker *w, uint64_t key, hpfc_pixel *px, uint64_t *id)
{
    int st = topo_index_ready(w);
    return st ? st : slot_pixel(w, key >> TOPO_KEY_SHIFT, px, id);
}

/* The path's last image is found among its level's images (on a file
 * whose parent index built, every checked path is the slot's own, so that
 * image is one of them and the id is the slot's; the slot is searched
 * anyway should it not be). */
int topo_pixel_id(hpfc_walker *w, uint32_t depth, const path_step *last, uint64_t slot,
                  uint64_t *id)
{
    int st = topo_index_ready(w);
    if (st)
        return st;
    const key_index *x = &w->keys;
    uint32_t l = depth;
    const path_step *p = last;
    uint64_t lo = x->first[l], hi = x->first[l + 1], index = 0;
    bool found = l == 0 && p->image == 0;
    if (l > 0) { /* the image starting exactly at p->image */
        while (hi > lo) {
            uint64_t mid = lo + (hi - lo) / 2;
            if (x->images[mid].start < p->image)
                lo = mid + 1;
            else
                hi = mid;
        }
        found = lo < x->first[l + 1] && x->images[lo].start == p->image;
        index = lo - x->first[l];
    }
    uint32_t cols = l ? x->cols : x->root_cols;
    if (found) {
        *id = x->pixel_first[l] + index * x->image_pixels + (uint64_t)p->j * cols + p->i;
    } else {
        hpfc_pixel px;
        if ((st = slot_pixel(w, slot, &px, id)))
            return st;
    }
    return HPFC_OK;
}
