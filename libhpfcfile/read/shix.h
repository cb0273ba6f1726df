/*
 * shix.h: the SHIX section (spec/hpfc-format.md §6.8, format 1.3), the
 * shape index: each face's edges, each feature's faces and each feature's
 * edges, the three inverse tables hpfc_shapes needs, stored so that a
 * file's shapes open without a pass over the map. Each table is an index
 * of rows + 1 offsets, then its links (ids), both bit-packed MSB-first at
 * the widths their counts give. shix.c checks the section at open, reads
 * and checks a row, and builds the section for the writer; query/shapes.c
 * reads it. Internal to the library.
 */
#ifndef HPFC_SHIX_H
#define HPFC_SHIX_H

#include <stdbool.h>
#include <stdint.h>

#include "diag.h"
#include "feature_links.h"
#include "format.h"
#include "hpfc.h"
#include "labels.h"

/* One table as open found it (§6.8.1): `rows` rows, `links` ids each
 * below `bound`; offsets of offset_bits bits from bit 0 of `bits`, the ids
 * of id_bits bits from bit links_at. */
typedef struct shix_table {
    format_bits bits;
    uint32_t rows, links, bound;
    unsigned offset_bits, id_bits;
    uint64_t links_at;
} shix_table;

/* A SHIX section as open found it. A table the section does not hold has
 * rows == 0 and bits.base NULL. */
typedef struct shix_view {
    bool present;
    uint32_t faces, edges, features, tables;
    shix_table face_edges, feature_faces, feature_edges;
} shix_view;

/* Checks a SHIX section's header and exact length (spec §8.1 S45) and
 * fills v: HPFC_E_SECTION for a section that does not hold what its
 * header says. The counts are compared with LABL, FEAT and EDGF where the
 * tables are used (hpfc_shapes_create), not here. */
int shix_open(shix_view *v, const uint8_t *section, uint64_t length);

/* Id j of a table (j < links, the caller's check). */
static inline uint32_t shix_id(const shix_table *t, uint64_t j)
{
    return (uint32_t)format_get(&t->bits, t->links_at + j * t->id_bits, t->id_bits);
}

/* Offset `row` of a table's index (row <= rows, the caller's check),
 * unchecked: shix_row checks a row's two before it is read. */
static inline uint64_t shix_offset(const shix_table *t, uint64_t row)
{
    return format_get(&t->bits, row * t->offset_bits, t->offset_bits);
}

/* What a row of a table inverts, to check each of its ids against:
 * LABL's sides (labels; the face table), or FEAT's or EDGF's links
 * (links; the feature tables). */
typedef struct shix_inverse {
    const labels_view *labels;
    const feature_links *links;
} shix_inverse;

/* Row `row` (< t->rows, the caller's check) of a table as ids [*a, *b)
 * (spec §8.5 S46): HPFC_E_CORRUPT unless its offsets do not decrease and
 * lie in the links and its ids ascend strictly, each below the bound and
 * each the inverse of a link of `of`. O(the row and the links it checks). */
int shix_row(const shix_table *t, uint64_t row, const shix_inverse *of, uint64_t *a,
             uint64_t *b);

/* The SHIX section the writer stores (spec §6.8.3) for a map with LABL
 * view `labels` (its sides give each face's edges), FEAT table
 * `features` and EDGF table `edges` (either NULL), measured before it is
 * made, so that a writer can place it, then made in place. */
typedef struct shix_plan {
    uint8_t header[SHIX_HEADER_SIZE];
    uint64_t length; /* the section's bytes */
} shix_plan;

/* The section's header and length into *plan, from one pass over LABL's
 * sides: HPFC_E_LIMIT (diag set) for a table of 2^32 links or more,
 * which the section cannot hold; HPFC_E_ARG for a LABL whose counts its
 * bytes do not pay for or whose sides name a face past its count. */
int shix_measure(const labels_view *labels, const hpfc_feature_table *features,
                 const hpfc_edge_feature_table *edges, shix_plan *plan, hpfc_diag *diag);

/* The section measured in *plan, made in `out` (plan->length zeroed
 * bytes) from the same tables, with no memory beside it: each table is
 * inverted by a counting sort kept in its own offsets. */
void shix_emit(const shix_plan *plan, const labels_view *labels,
               const hpfc_feature_table *features, const hpfc_edge_feature_table *edges,
               uint8_t *out);

/* Whether a map of `edges` edges with these FEAT and EDGF tables (either
 * NULL) has a SHIX section whatever its LABL: each table under 2^32
 * links (an edge is in two faces' rows at most), so that a writer can
 * count the section in the directory before LABL is made. */
bool shix_fits(uint64_t edges, const hpfc_feature_table *features,
               const hpfc_edge_feature_table *edges_table);

/* shix_measure, then shix_emit into *out (*length bytes, free()). */
int shix_build(const labels_view *labels, const hpfc_feature_table *features,
               const hpfc_edge_feature_table *edges, uint8_t **out, uint64_t *length,
               hpfc_diag *diag);

#endif
