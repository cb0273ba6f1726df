/*
 * segment_graph.h: the last step of the GIS input: the noded lattice
 * segments of a layer made into the planar graph the builder takes. Pure
 * integer work, no GDAL or GEOS, so that it is tested on its own
 * (tests/tools/test_segment_graph.c).
 */
#ifndef HPFC_PACK_SEGMENT_GRAPH_H
#define HPFC_PACK_SEGMENT_GRAPH_H

#include <stddef.h>
#include <stdint.h>

#include "hpfc.h"
#include "segnode.h"

/* Makes the graph of `n` distinct non-degenerate segments (ends in order,
 * as segnode_seg says), sorted by first end then second, that meet only at
 * shared ends. With `all_vertices`
 * every segment end is a vertex and every segment an edge; otherwise a
 * chain of segments through points of degree 2 is one edge between the
 * junctions at its ends (degree 1 or 3 and more, or one of the n_ends
 * points `ends`, in any order: where the input's lines end; an end that is
 * no segment's end is ignored), and a closed chain with
 * no junction gets one vertex, at its least point (lowest x, then y).
 * Vertices are added in point order, so equal inputs give equal graphs.
 * The points are sorted on up to `threads` threads (0 or 1: this one),
 * the same graph whatever the count.
 * HPFC_OK, or a status with a one-line reason in err. */
int segment_graph_make(const segnode_seg *segs, size_t n, const segnode_pt *ends, size_t n_ends,
                       int all_vertices, int32_t unit_exp10, unsigned threads, hpfc_graph **out,
                       char *err, size_t err_len);

#endif
