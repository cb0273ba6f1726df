/*
 * The tree's accessors (hpfc_tree_get_pixel and its kin) and its release,
 * for every kind of tree: one the builder made, a part read in place from
 * its file (part_read.c), or a view joined over such parts (merge.c).
 * They sit apart from the builder, the reader and the merge, which all
 * call them, so that none of those calls another back.
 */
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

#include "sized.h"
#include "tree.h"

void part_backing_release(void *backing, size_t size, bool mapped)
{
    if (backing && mapped)
        munmap(backing, size);
    else
        free(backing);
}

void tree_view_locate(const tree_view *v, uint32_t level, size_t image, size_t p,
                      const hpfc_tree **src, size_t *src_image, int64_t *child_delta)
{
    if (level == 0) {
        *src = v->parts[v->owner[p]];
        *src_image = 0;
        *child_delta = v->root_delta[p];
        return;
    }
    const view_run *r = v->runs[level];
    size_t lo = 0, hi = v->nruns[level];
    while (hi - lo > 1) {
        size_t mid = lo + (hi - lo) / 2;
        if (r[mid].first <= image)
            lo = mid;
        else
            hi = mid;
    }
    *src = v->parts[r[lo].part];
    *src_image = (size_t)(r[lo].part_first + (image - r[lo].first));
    *child_delta = r[lo].child_delta;
}

void tree_view_free(tree_view *v)
{
    if (!v)
        return;
    for (size_t k = 0; k < v->nparts; k++)
        hpfc_tree_free(v->parts[k]);
    for (uint32_t l = 0; l < HPFC_MAX_LEVELS; l++)
        free(v->runs[l]);
    free(v->parts);
    free(v->owner);
    free(v->root_delta);
    free(v);
}

/* Frees every level's arrays, the tree's own, then the tree.
 * (hpfc_graph_free, hpfc_tree_free and hpfc_shapes_free look alike, a free()
 * a member, but each lists the arrays of its own struct.) */
void hpfc_tree_free(hpfc_tree *t)
{
    if (!t)
        return;
    tree_view_free(t->view);
    for (uint32_t l = 0; l < t->levels_cap && !t->backing; l++) {
        free(t->levels[l].img_gx);
        free(t->levels[l].img_gy);
        free(t->levels[l].pix);
    }
    free(t->levels);
    if (!t->backing) {
        free(t->syms);
        free(t->cross_edge);
        free(t->cross_seg);
    }
    free(t->zero_seg);
    part_backing_release(t->backing, t->backing_size, t->backing_mapped);
    free(t);
}

void hpfc_tree_get_info_sized(const hpfc_tree *t, hpfc_tree_info *info, size_t size)
{
    if (t && info)
        sized_out(info, size, &t->info, sizeof t->info);
}

size_t hpfc_tree_image_count(const hpfc_tree *t, uint32_t level)
{
    return level < t->info.levels ? t->levels[level].nimages : 0;
}

int hpfc_tree_get_pixel(const hpfc_tree *t, uint32_t level, size_t image, uint32_t i,
                        uint32_t j, hpfc_tree_pixel *out)
{
    if (!t || !out || level >= t->info.levels)
        return HPFC_E_ARG;
    const tlevel *lv = &t->levels[level];
    if (image >= lv->nimages || i >= lv->cols || j >= lv->rows)
        return HPFC_E_ARG;
    const hpfc_tree *src = t; /* the tree whose arrays hold the pixel: t, or a part of its view */
    size_t p = (size_t)j * lv->cols + i;
    int64_t child_delta = 0;
    if (t->view)
        tree_view_locate(t->view, level, image, p, &src, &image, &child_delta);
    const tlevel *slv = &src->levels[level];
    const tpixel *px = &slv->pix[image * lv->cols * lv->rows + p];
    if (px->cross == TPIXEL_ABSENT)
        return HPFC_E_ARG; /* a part's tree: another part's root pixel */
    int64_t gx = slv->img_gx[image] + i, gy = slv->img_gy[image] + (lv->rows - 1 - j);
    memset(out, 0, sizeof *out);
    out->x0 = t->info.x0 + gx * lv->cell_w;
    out->y0 = t->info.y0 + gy * lv->cell_h;
    out->x1 = out->x0 + lv->cell_w;
    out->y1 = out->y0 + lv->cell_h;
    if (px->cross == TPIXEL_REFINED) {
        out->type = HPFC_PIXEL_REFINED;
        out->child = (uint32_t)((int64_t)px->off + child_delta);
        return HPFC_OK;
    }
    uint64_t cross_off = px->cross >> TPIXEL_COUNT_BITS;
    out->type = HPFC_PIXEL_WORD;
    out->word = src->syms + px->off;
    out->word_len = (uint32_t)(px->cross & ((UINT64_C(1) << TPIXEL_COUNT_BITS) - 1)) + 4;
    out->cross_edge = src->cross_edge + cross_off;
    /* a joined view's zero_seg is as long as the longest word of all parts */
    out->cross_segment = src->cross_seg ? src->cross_seg + cross_off : t->zero_seg;
    return HPFC_OK;
}
