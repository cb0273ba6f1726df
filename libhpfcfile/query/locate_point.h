/*
 * locate_point.h: exact point location (spec/hpfc-format.md §6.7), the
 * code behind hpfc_locate_point, shared with the batch call so that both
 * give the same answer. Internal to the library.
 */
#ifndef HPFC_LOCATE_POINT_H
#define HPFC_LOCATE_POINT_H

#include <stddef.h>
#include <stdint.h>

#include "road.h"
#include "hpfc.h"
#include "labels.h"

/* One segment of an edge piece inside the located leaf, u -> v direction
 * (a runs from point i to point i + 1 of its edge). */
typedef struct locx_segment {
    lpoint a, b;          /* relative to the domain's south-west corner */
    uint64_t edge, index; /* edge id, segment index */
    uint32_t crossing;    /* a crossing of its piece: its faces by §6.5 */
    uint64_t vertex;      /* the vertex id of its vertex end, if it has one */
    int8_t vertex_end;    /* -1: neither end is a vertex; 0: a is one; 1: b is */
} locx_segment;

/* What one location knows of a crossing of its leaf. */
typedef struct locx_crossing {
    uint64_t segment;     /* the segment of its edge it lies on */
    uint64_t u, v, count; /* its edge's ends and point count */
    lpoint a, b;          /* that segment's ends, relative */
    line_pos pos;         /* where it lies on its road's line */
    uint32_t road;        /* HPFC_WEST .. HPFC_SOUTH */
    char kind;            /* its symbol */
    int8_t leaving;       /* 1 when its segment, run u -> v, leaves the leaf */
} locx_crossing;

/* What one location needs between calls (the batch reuses it); zero it
 * before the first call, locx_scratch_free after the last. */
typedef struct locx_scratch {
    const hpfc_file *file;   /* the file the fields below were read from */
    int64_t dx0, dy0;        /* its domain's south-west corner */
    uint64_t points;         /* its GEOM shape points (bounds a leaf's segments) */
    char *sym;
    size_t sym_cap;
    labels_leaf labels;
    locx_crossing *cr;       /* per crossing */
    uint64_t *around;        /* the faces of the answer */
    size_t crossing_cap;
    locx_segment *segs;
    size_t seg_count, seg_cap;
    /* The leaf of the last answer, loaded (word, labels, crossings,
     * segments) and kept for the next point: a point in it skips the
     * descent and every read but its answer's. A batch in space-filling-
     * curve order finds most points in the leaf before. have_leaf is
     * false after any failure. */
    int have_leaf;
    hpfc_pixel leaf;
    int64_t leaf_x0, leaf_y0, leaf_x1, leaf_y1; /* its bounds, absolute, half-open */
} locx_scratch;

void locx_scratch_free(locx_scratch *s);

/* What a location says besides its faces and leaf. */
typedef struct locx_answer {
    int on_boundary, on_vertex;
    uint64_t vertex, edge; /* UINT64_MAX when not on one */
} locx_answer;

/* hpfc_locate_point's answer with caller-kept scratch: the faces in
 * s->around[0 .. *count), the leaf in s->leaf (both valid until the next
 * call), the rest in *out. */
int locx_locate(const hpfc_file *file, int64_t x, int64_t y, locx_scratch *s, locx_answer *out,
                size_t *count);

#endif
