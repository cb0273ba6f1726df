/* Reader internals shared with the traversal code (topo.c). */
#ifndef HPFC_READER_H
#define HPFC_READER_H

#include "hpfc.h"

/* hpfc_faces_build's union-find takes 32-bit words below this many nodes
 * (2^31: the top bit tags numbered roots), else 64-bit ones. A variable
 * only so that the tests can run the 64-bit path on small maps. */
extern uint64_t faces_narrow_nodes;

/* Most crossings a word of this file can hold (from the level table). */
uint32_t reader_max_crossings(const hpfc_file *file);
/* An upper bound on all crossings of the file, to bound walks. */
uint64_t reader_total_crossings(const hpfc_file *file);
/* Word pixels (leaves) in all levels, as the level table declares them. */
uint64_t reader_total_leaves(const hpfc_file *file);
/* Absolute bit position in the file of a word pixel's record or slot: a
 * unique, stable number per pixel. */
int reader_pixel_slot_bit(const hpfc_file *file, const hpfc_pixel *px, uint64_t *bit);
/* The file's bytes (its whole size, as opened). */
const uint8_t *reader_bytes(const hpfc_file *file);
/* The FEAT section (checked at open), NULL when the file has none. */
const uint8_t *reader_feat_section(const hpfc_file *file, uint64_t *length);

#endif
