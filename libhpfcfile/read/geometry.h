/*
 * geometry.h: the GEOM section (spec/hpfc-format.md §6.6): the input
 * graph's exact lattice coordinates, its edges' end vertices and shape
 * points, the segment of every crossing of a polyline map, and which of
 * LABL's two sides lies on the right of each edge run from u to v.
 * Internal to the library (and its tests and fuzzers).
 *
 * Every table of the section is a *column*: n unsigned integers cut into
 * blocks of 2^shift, each block stored as a base and the offsets from it
 * in the bits the block needs (frame of reference). Value i is then one
 * fixed-width directory entry and one field away: O(1), and a block of
 * neighbouring vertices (or points of one polyline) costs the bits of its
 * own extent, not of the map's.
 */
#ifndef HPFC_GEOMETRY_H
#define HPFC_GEOMETRY_H

#include <stdbool.h>
#include <stdint.h>

#include "format.h"
#include "hpfc.h"

#define FORMAT_TAG_GEOM "GEOM"

/* The columns, in the order the section stores them. */
enum {
    GEOM_VX = 0,     /* per vertex: x - x0 */
    GEOM_VY,         /* per vertex: y - y0 */
    GEOM_EU,         /* per edge: vertex u */
    GEOM_EV,         /* per edge: vertex v */
    GEOM_EPOINT,     /* per edge (only with shape points): shape points before it */
    GEOM_PX,         /* per shape point: x - x0 */
    GEOM_PY,         /* per shape point: y - y0 */
    GEOM_LCROSS,     /* per leaf (only with shape points): crossings before it */
    GEOM_CSEG,       /* per crossing (only with shape points): its segment */
    GEOM_COLUMNS
};

enum {
    GEOM_HEADER_SIZE = 48,
    GEOM_COLUMN_SIZE = 16,
    GEOM_META_SIZE = GEOM_HEADER_SIZE + GEOM_COLUMNS * GEOM_COLUMN_SIZE, /* 192 */
    GEOM_MAX_SHIFT = 16,
    GEOM_WIDTH_BITS = 7, /* a block's width field: 0 .. 64 */
};

/* Header (48 bytes): a field table, one FORMAT_FIELD line a row of spec
 * §6.6.2's table; its likeness to the other sections' tables is the macro's
 * (format.h, FORMAT_FIELD). */
FORMAT_FIELD(geom, vertex_count, 0, 8, uint64_t)
FORMAT_FIELD(geom, edge_count, 8, 8, uint64_t)
FORMAT_FIELD(geom, point_count, 16, 8, uint64_t)
FORMAT_FIELD(geom, leaf_count, 24, 8, uint64_t)
FORMAT_FIELD(geom, crossing_count, 32, 8, uint64_t)
FORMAT_FIELD(geom, reserved, 40, 8, uint64_t)
/* Column descriptor (16 bytes each, from offset 48). */
FORMAT_FIELD(geomc, block_shift, 0, 1, uint8_t)
FORMAT_FIELD(geomc, offset_bits, 1, 1, uint8_t)
FORMAT_FIELD(geomc, base_bits, 2, 1, uint8_t)
enum { geomc_OFF_reserved = 3, geomc_SIZE_reserved = 5 };
FORMAT_FIELD(geomc, payload_bits, 8, 8, uint64_t)

/* The byte offsets of the parts: the orientation bits, then per column
 * its directory and its payload, each on an 8-byte boundary; *length the
 * exact section length. false on overflow or a field out of range. */
typedef struct geom_layout {
    uint64_t orient_at, dir_at[GEOM_COLUMNS], dir_bits[GEOM_COLUMNS], payload_at[GEOM_COLUMNS];
    uint64_t length;
} geom_layout;
/* A column as the reader sees it. */
typedef struct geom_column {
    uint64_t count;
    uint32_t shift, offset_bits, base_bits, entry_bits;
    format_bits dir, payload;
} geom_column;

typedef struct geom_view {
    bool present;
    uint64_t vertices, edges, points, leaves, crossings;
    uint64_t width, height;   /* the domain: coordinates below these */
    format_bits orient;       /* E bits: the LABL side on the right of u -> v */
    geom_column col[GEOM_COLUMNS];
    uint64_t first_leaf[HPFC_MAX_LEVELS + 1]; /* global number of level l's leaf 0 */
    geom_layout layout;       /* where its parts lie */
    const uint8_t *section;   /* its bytes */
    uint64_t section_length;
} geom_view;

/* The column counts a header implies (and whether they are consistent). */
bool geom_column_counts(uint64_t vertices, uint64_t edges, uint64_t points, uint64_t leaves,
                        uint64_t crossings, uint64_t counts[GEOM_COLUMNS]);

bool geom_compute_layout(const uint64_t counts[GEOM_COLUMNS], uint64_t edges,
                         const uint32_t shift[GEOM_COLUMNS], const uint32_t offset_bits[GEOM_COLUMNS],
                         const uint32_t base_bits[GEOM_COLUMNS],
                         const uint64_t payload_bits[GEOM_COLUMNS], geom_layout *out);

/* What the open check needs of the file: its domain and leaves per level. */
typedef struct geom_levels {
    uint32_t levels;
    uint64_t word_pixels[HPFC_MAX_LEVELS];
    int64_t width, height;
    bool has_labels;
    uint64_t label_edges;     /* LABL's edge count when has_labels */
} geom_levels;

/* Checks a GEOM section's header and layout (O(1)); HPFC_E_SECTION when
 * it fails. */
int geometry_open(geom_view *v, const uint8_t *sec, uint64_t length, const geom_levels *lv);

/* Every byte between the parts and every bit after a stream's last bit
 * up to its last byte is zero (§6.6.2): false at the first that is not,
 * with the byte's offset in *at. O(section). */
bool geom_padding_zero(const geom_view *v, uint64_t *at);

/* Value i of a column (i < count): HPFC_E_CORRUPT when its block's
 * directory entry or field lies outside the column. */
int geom_column_get(const geom_column *c, uint64_t i, uint64_t *value);
/* Values [i, i + n) of a column into out[0], out[stride], ...: a block's
 * directory entry read once for all its values. HPFC_E_CORRUPT as
 * geom_column_get, or when the run passes the column's end. */
int geom_column_run(const geom_column *c, uint64_t i, uint64_t n, uint64_t *out, size_t stride);

/* The smallest and largest value of a column, exact, reading only the
 * blocks whose stored bounds could still change them (*lo > *hi for an
 * empty column). HPFC_E_CORRUPT as geom_column_run; HPFC_E_NOMEM. */
int geom_column_span(const geom_column *c, uint64_t *lo, uint64_t *hi);

/* An edge's end vertices and its shape points [first, first + n). */
typedef struct geom_edge {
    uint64_t u, v, first, n;
} geom_edge;

/* Edges [first, first + n)'s records into out, read a column run at a
 * time, each checked as hpfc_geometry_edge checks it (HPFC_E_CORRUPT);
 * HPFC_E_ARG past the edges. The GEOM section is present. */
int geom_edges(const hpfc_file *file, uint64_t first, uint64_t n, geom_edge *out);

/* Values [i, i + n) of column c as one coordinate of n points: origin +
 * value into out[0], out[2], ..., each value below `limit` (the domain's
 * width or height) or HPFC_E_CORRUPT, as for a run past the column. The
 * odd slots are not written. */
int geom_coordinate_run(const geom_column *c, uint64_t i, uint64_t n, uint64_t limit,
                        int64_t origin, int64_t *out);

/* Points [first, first + n) of a point column, GEOM_VX (the vertices) or
 * GEOM_PX (the shape points), as lattice coordinates into xy (x, y a
 * point), read a column run at a time. HPFC_E_CORRUPT for a run past the
 * column or a point outside the domain. */
int geom_points(const hpfc_file *file, int column, uint64_t first, uint64_t n, int64_t *xy);

/* Every point of edge `edge`, u first, v last (hpfc_geometry_edge's
 * point_count of them), into xy: x, y a point. Statuses as
 * hpfc_geometry_edge_point's; the points of a whole edge at once cost
 * about a third of its calls point by point. */
int geom_edge_points(const hpfc_file *file, uint64_t edge, int64_t *xy);

/* The segments of a leaf's n crossings (its word's symbols other than
 * '+'), from GEOM's crossing column in one run: what
 * hpfc_geometry_crossing_segment answers one crossing at a time, without
 * checking each against its edge (the caller, who knows the edges, does).
 * HPFC_E_CORRUPT when the column does not give the leaf n crossings. */
int geom_leaf_segments(const hpfc_file *file, const hpfc_pixel *leaf, uint32_t n,
                       uint64_t *segment);

#endif
