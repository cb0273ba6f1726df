/*
 * file.h: an open .hpfc file (struct hpfc_file) as hpfc_open_memory checked
 * it: the header, the level table with what navigation derives from each
 * level, and the sections' views. file.c owns it: only open fills these
 * fields, and nothing writes them after (a handle is shared by threads).
 * Every other module of the library reads the fields directly; the
 * functions below are the ones that compute something from them.
 * Internal to the library (and its tests and fuzzers).
 *
 * What open checked, so that readers need not check it again: the header's
 * ranges and extent split (spec/hpfc-format.md, "Safe reading"), every
 * level's counts and pool place (each pool lies inside the buffer), the
 * section directory (no overlap, no repeated tag, known required tags) and
 * the O(1) header checks of FEAT, LABL, ATTR, EDGF and GEOM. Not the pools'
 * bits: navigation (read.c) checks each image it touches.
 */
#ifndef HPFC_FILE_H
#define HPFC_FILE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "format.h"
#include "geometry.h"
#include "hpfc.h"
#include "labels.h"
#include "shix.h"
#include "pool.h"

/* One level as navigation needs it, derived at open. */
typedef struct file_level {
    format_bits pool;       /* s^l bits; reads may look ahead to the buffer's end */
    uint32_t word_bits;     /* k_w */
    uint32_t address_bits;  /* k_@ */
    uint32_t cols, rows;    /* pixels per image */
    uint64_t image_pixels;  /* cols * rows */
    uint64_t record_bits;   /* level 0: 1 + max(k_@, k_w) */
    int64_t cell_w, cell_h;
    bool last;
    hpfc_level_info info;
    pool_level compact;     /* the compact layout's geometry (pool.h) */
} file_level;

struct hpfc_file {
    const uint8_t *data;    /* the whole file, size bytes (the writer copies sections from it) */
    size_t size;
    void *map; /* hpfc_open's mapping; NULL for a caller's buffer */
    size_t map_size;
    void *owned; /* hpfc_open's copy under HPFC_OPEN_READ; NULL otherwise */
    const uint8_t *directory;
    uint64_t meta_size;
    hpfc_file_info info;
    file_level lv[HPFC_MAX_LEVELS];
    /* log2 of cols and rows when both are powers of two, else 0: point
     * location then reads every level's cell index off one quotient */
    uint32_t shift_x, shift_y;
    bool compact;           /* incompat flag: the compact pool layout */
    /* FEAT, ATTR and EDGF, NULL when absent: checked at open against their
     * lengths, so their accessors need only the start */
    const uint8_t *feat;
    labels_view labels;     /* the LABL section (labels.present: the file has one) */
    const uint8_t *attr, *edgf;
    geom_view geom;         /* the GEOM section (geom.present: the file has one) */
    shix_view shix;         /* the SHIX section (shix.present: the file has one) */
};

/* The file has exact geometry: GEOM and LABL (open checked that their edge
 * counts agree), what point location, the shapes and the exact batch need.
 * Their callers answer HPFC_E_NO_SECTION when it has not. */
static inline bool file_has_exact_geometry(const hpfc_file *f)
{
    return f->geom.present && f->labels.present;
}

/* Most crossings a word of this file can hold (from the level table). */
uint32_t file_max_crossings(const hpfc_file *f);
/* Most crossings a word of level `level` can hold. */
uint32_t file_level_max_crossings(const hpfc_file *f, uint32_t level);
/* An upper bound on all crossings of the file, to bound walks. */
uint64_t file_total_crossings(const hpfc_file *f);
/* Word pixels (leaves) in all levels, as the level table declares them. */
uint64_t file_total_leaves(const hpfc_file *f);

#endif
