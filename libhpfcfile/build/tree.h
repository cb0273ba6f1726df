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


typedef struct tree_view tree_view;

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
    /* A part read in place (part_read.c): its arrays point into `backing`,
     * a mapping of its part file (backing_mapped) or a buffer of its own,
     * and are freed with it, not one by one. */
    void *backing;
    size_t backing_size;
    bool backing_mapped;
    /* A tree joined from parts read in place (hpfc_tree_merge_files): no
     * arrays of its own but its levels' sizes; its pixels are its parts',
     * found through the view. NULL for every other tree. */
    tree_view *view;
};

/* A tree joined from parts read in place (hpfc_tree_merge_files, merge.c):
 * its levels' images come in runs, each a stretch of one part's images. */
typedef struct view_run {
    uint64_t first;      /* the run's first image on the joined level */
    uint64_t part_first; /* the same image on its part's level */
    uint64_t count;
    int64_t child_delta; /* a refined pixel's joined child: its part's + this */
    uint32_t part;
} view_run;

struct tree_view {
    hpfc_tree **parts;   /* read in place; the view frees them */
    size_t nparts;
    uint32_t *owner;     /* the part of each root pixel */
    int64_t *root_delta; /* each refined root pixel's child delta */
    view_run *runs[HPFC_MAX_LEVELS]; /* levels >= 1, in joined order */
    size_t nruns[HPFC_MAX_LEVELS], cap[HPFC_MAX_LEVELS];
};

/* Where pixel p of image `image` of level `level` of a joined view lies:
 * *src the part, *src_image its image there, *child_delta what to add to a
 * refined pixel's child (tree.c). The arguments are in range. */
void tree_view_locate(const tree_view *v, uint32_t level, size_t image, size_t p,
                      const hpfc_tree **src, size_t *src_image, int64_t *child_delta);
void tree_view_free(tree_view *v);
/* Releases a part's backing: unmapped, or freed (tree.c). */
void part_backing_release(void *backing, size_t size, bool mapped);

#endif
