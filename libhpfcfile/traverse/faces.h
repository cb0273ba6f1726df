/* faces.h: the faces' internals (faces.c) beyond the public hpfc_faces_*
 * calls: the union-find's width, and the nodes the LABL writer
 * (write/labels_write.c) reads the faces of. Internal to the library (and
 * its tests). */
#ifndef HPFC_FACES_H
#define HPFC_FACES_H

#include <stdint.h>

#include "hpfc.h"

/* hpfc_faces_build's union-find takes 32-bit words below this many nodes
 * (2^31: the top bit tags numbered roots), else 64-bit ones. */
#define FACES_NARROW_NODES (UINT64_C(1) << 31)

/* The most threads one numbering uses (hpfc_faces_build_threads). */
#define FACES_MAX_THREADS 64u

/* hpfc_faces_build_threads with 32-bit words below `narrow_below` nodes
 * and runs of `run_size` leaves a thread takes at a time (0: the
 * library's): the tests pass 0 and small runs to reach the 64-bit path and
 * many runs on small maps. *failure (when not NULL) receives which of the
 * runs' failures was kept: its leaf's number << 2 | the check's place
 * among that leaf's, UINT64_MAX for none (a failure before the runs, in
 * the count, is not one of them). */
int faces_build_width(const hpfc_file *file, uint64_t narrow_below, unsigned threads, uint64_t run_size,
                      uint64_t *failure, hpfc_faces **out);

/* The nodes of the leaf whose record (level 0) or slot starts at bit `bit`
 * of level `level`'s pool: node base + t is stretch t (one node for a
 * private leaf). */
int faces_leaf_nodes(const hpfc_faces *fc, uint32_t level, uint64_t bit, uint64_t *base,
                     uint64_t *crossings);
uint64_t faces_node_face(const hpfc_faces *fc, uint64_t node);

/* Unbinds fc from its file, keeping a print of the file's pools for
 * hpfc_faces_attach: the writer hands out the faces it numbered LABL with
 * on a copy of the pools it then frees. HPFC_E_CORRUPT for a pool outside
 * the file. */
int faces_detach(hpfc_faces *fc);

/* The faces one root pixel at a time, for a writer whose memory must
 * follow the roots' borders, not the map (issue 32's merge). The plan
 * numbers each root's leaves alone and keeps only what lies on the roots'
 * sides: the classes of the gaps between crossings along them, united
 * across each side two roots share, and counts. faces_stream_root then
 * numbers one root again, with the ids hpfc_faces_build gives: an
 * hpfc_faces whose faces_leaf_nodes and faces_node_face answer for that
 * root's leaves only (hpfc_faces_free it). The plan numbers its roots
 * on up to `threads` threads (0 or 1: the calling one), the same plan
 * whatever the count. With more than one, faces_stream_root, called
 * from root 0 in row-major order (as the writer goes), finds each root
 * numbered ahead by a thread of the plan's while the caller used the one
 * before; a call out of that order stops the thread and numbers alone.
 * faces_stream_root on one caller thread at a time. */
typedef struct faces_stream faces_stream;
int faces_stream_plan(const hpfc_file *file, unsigned threads, faces_stream **out);
uint64_t faces_stream_face_count(const faces_stream *s);
/* Bytes the plan holds (its arrays' capacity), and a numbering's leaf
 * table and union-find: for tests and benches. */
uint64_t faces_bytes(const hpfc_faces *fc);
uint64_t faces_stream_plan_bytes(const faces_stream *s);
int faces_stream_root(faces_stream *s, uint32_t i, uint32_t j, hpfc_faces **out);
void faces_stream_free(faces_stream *s);

#endif
