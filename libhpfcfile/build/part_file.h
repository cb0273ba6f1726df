/*
 * part_file.h: the part file (spec/part-format.md), a part's tree
 * (hpfc_build_part) on disk for a merge in another process: the header's
 * field table, shared by its writer (write/part_write.c) and its reader
 * (build/part_read.c).
 */
#ifndef HPFC_PART_FILE_H
#define HPFC_PART_FILE_H

#include "diag.h"
#include "format.h"

#define PART_MAGIC "hpfcPART"
#define PART_VERSION 2
#define PART_HEADER_SIZE 144
#define PART_LEVEL_ENTRY_SIZE 8   /* a level's image count */
#define PART_PIXEL_SIZE 16        /* two u64: off, cross (tree.h's tpixel) */
#define PART_CRC_SIZE 4
/* The symbols are followed by zeros up to a multiple of 8 bytes (version 2),
 * so that every array of a part file lies aligned in a mapping of it and a
 * reader can point into it (part_read.c) instead of copying. */
#define PART_SYMBOLS_ALIGN 8
static inline uint64_t part_symbols_padding(uint64_t symbols)
{
    return (PART_SYMBOLS_ALIGN - symbols % PART_SYMBOLS_ALIGN) % PART_SYMBOLS_ALIGN;
}

enum { part_OFF_magic = 0, part_SIZE_magic = 8 };
FORMAT_FIELD(part, version, 8, 4, uint32_t)
FORMAT_FIELD(part, flags, 12, 4, uint32_t)
FORMAT_FIELD(part, root_cols, 16, 4, uint32_t)
FORMAT_FIELD(part, root_rows, 20, 4, uint32_t)
FORMAT_FIELD(part, cols, 24, 4, uint32_t)
FORMAT_FIELD(part, rows, 28, 4, uint32_t)
FORMAT_FIELD(part, levels, 32, 4, uint32_t)
FORMAT_FIELD(part, level_count, 36, 4, uint32_t)
FORMAT_FIELD(part, x0, 40, 8, int64_t)
FORMAT_FIELD(part, y0, 48, 8, int64_t)
FORMAT_FIELD(part, width, 56, 8, int64_t)
FORMAT_FIELD(part, height, 64, 8, int64_t)
FORMAT_FIELD(part, unit_exp10, 72, 4, int32_t)
FORMAT_FIELD(part, max_word_symbols, 76, 4, uint32_t)
FORMAT_FIELD(part, vertices, 80, 8, uint64_t)
FORMAT_FIELD(part, edges, 88, 8, uint64_t)
FORMAT_FIELD(part, word_pixels, 96, 8, uint64_t)
FORMAT_FIELD(part, refined_pixels, 104, 8, uint64_t)
FORMAT_FIELD(part, private_pixels, 112, 8, uint64_t)
FORMAT_FIELD(part, symbols, 120, 8, uint64_t)
FORMAT_FIELD(part, crossings, 128, 8, uint64_t)
FORMAT_FIELD(part, has_segments, 136, 4, uint32_t)
FORMAT_FIELD(part, reserved, 140, 4, uint32_t)

/* The part file of a part's tree, in a new buffer (write/part_write.c). */
struct hpfc_tree;
int part_serialize(const struct hpfc_tree *tree, uint8_t **out, size_t *out_size, hpfc_diag *diag);

#endif
