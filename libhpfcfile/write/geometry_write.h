/* geometry_write.h: the GEOM section made from the graph and the tree
 * (geometry_write.c), planned first, then streamed to the file. Internal
 * to the writer. */
#ifndef HPFC_GEOMETRY_WRITE_H
#define HPFC_GEOMETRY_WRITE_H

#include <stdint.h>

#include "diag.h"
#include "hpfc.h"
#include "stream.h"

typedef struct geom_writer geom_writer;

/* Measures the section of `tree` and the graph it was built from: *length
 * its bytes, *out what geometry_emit needs (the tree and the graph are
 * read again there, and must outlive it). HPFC_E_ARG when the graph is
 * not the tree's. */
int geometry_plan(const hpfc_tree *tree, const hpfc_graph *graph, geom_writer **out,
                  uint64_t *length, hpfc_diag *diag);

/* Puts the section's bytes at file offset `at` of `to`, a bounded buffer
 * at a time, in no particular order; *crc: the section's CRC-32C. */
int geometry_emit(const geom_writer *w, stream_target to, uint64_t at, uint32_t *crc,
                  hpfc_diag *diag);

void geometry_writer_free(geom_writer *w);

#endif
