/* The in-memory hPFC tree made by the builder (build.c) and read by the
 * writer and the tests through hpfc_tree_get_pixel(). */
#ifndef HPFC_TREE_H
#define HPFC_TREE_H

#include "internal.h"

/* One pixel. A word pixel has word_len >= 4 (its word is at
 * tree->syms[word_off]); a refined pixel has word_len == 0 and child set. */
typedef struct tpixel {
    uint64_t word_off;
    uint64_t cross_off;   /* its crossings in tree->cross_edge / cross_seg */
    uint32_t word_len;
    uint32_t child;
} tpixel;

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
    uint32_t *cross_edge, *cross_seg;
    size_t ncross, cap_cross;
};

#endif
