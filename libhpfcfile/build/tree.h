/* The in-memory hPFC tree made by the builder (build.c) and read by the
 * writer and the tests through hpfc_tree_get_pixel(). */
#ifndef HPFC_TREE_H
#define HPFC_TREE_H

#include <stdbool.h>

#include "graph.h"

/* One pixel, in 16 bytes since a continental map has millions. A word
 * pixel with n crossings has its word at tree->syms[off] (n + 4 symbols)
 * and its crossings at tree->cross_edge / cross_seg [cross >>
 * TPIXEL_COUNT_BITS], n in the low bits of cross; a refined pixel has cross
 * == TPIXEL_REFINED and its child image in off. */
typedef struct tpixel {
    uint64_t off;
    uint64_t cross;
} tpixel;

#define TPIXEL_COUNT_BITS 24
#define TPIXEL_COUNT_MAX ((UINT64_C(1) << TPIXEL_COUNT_BITS) - 2)
#define TPIXEL_CROSS_OFF_MAX ((UINT64_C(1) << (64 - TPIXEL_COUNT_BITS)) - 1)
#define TPIXEL_REFINED UINT64_MAX
/* A root pixel that a part's build (hpfc_build_part) leaves to another part. */
#define TPIXEL_ABSENT (UINT64_MAX - 1)

typedef struct tlevel {
    uint32_t cols, rows;      /* pixels per image at this level */
    int64_t cell_w, cell_h;   /* pixel size (lattice units) */
    size_t nimages, cap;
    int64_t *img_gx, *img_gy; /* level-wide cell coords of each image's SW pixel */
    tpixel *pix;              /* nimages * cols * rows, scanline order per image */
} tlevel;

struct hpfc_tree {
    hpfc_tree_info info;
    tlevel *levels;
    uint32_t levels_cap;      /* entries allocated in levels */
    char *syms;
    size_t nsyms, cap_syms;
    uint32_t *cross_edge;
    /* Segment of each crossing, NULL while every crossing lies on its edge's
     * first segment (straight edges: half the crossings' memory); then
     * zero_seg, max_word_symbols zeros, stands for any word's. */
    uint32_t *cross_seg, *zero_seg;
    size_t ncross, cap_cross;
    /* A part of a split build: some root pixels are TPIXEL_ABSENT, the info's
     * faces and components are unknown (0) and its vertices are those its
     * words hold. Only hpfc_tree_merge takes it; the writer refuses it. */
    bool part;
};

#endif
