/*
 * hpfc_batch.h: point location for many points in one call.
 *
 * Bindings (the Python package in python/) hand a whole array of lattice
 * points to one C call instead of crossing into C once per point. The
 * answers are exactly those of the public calls it strings together:
 * hpfc_locate, then the faces of the leaf's regions from the stored
 * labels (hpfc_label_leaf_faces, LABL) or, given numbered faces,
 * hpfc_faces_pixel_face (a private leaf) or the face after each crossing
 * of a stabbed leaf (hpfc_faces_dart_face, experimental), then the FEAT
 * links of those faces (hpfc_face_feature_id). A file with exact geometry
 * (GEOM and LABL) is answered by hpfc_locate_point's code instead: the one
 * face holding the point, or the faces around it when it lies on an edge
 * or a vertex (HPFC_LOC_BOUNDARY). Without it a stabbed leaf names its
 * candidate faces, not the one face holding the point; the batch reports
 * how many there are and a face only when there is one.
 */
#ifndef HPFC_BATCH_H
#define HPFC_BATCH_H

#include "hpfc.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Flags of one answer. */
enum {
    HPFC_LOC_INSIDE = 1u,   /* the point lies in the file's domain */
    HPFC_LOC_PRIVATE = 2u,  /* its leaf is private: the face is the point's */
    HPFC_LOC_SINGLE = 4u,   /* one face answers: `face` is set (without
                               exact geometry: the leaf meets one face only) */
    HPFC_LOC_EXACT = 8u,    /* exact geometry decided the answer */
    HPFC_LOC_BOUNDARY = 16u /* exact: the point lies on an edge or a vertex;
                               the faces counted are those around it */
};

/* Per-point outputs; any pointer may be NULL when not wanted. Each array
 * has n entries. Face and feature ids are int64_t columns, as numpy and
 * data frames hold them, -1 for none (HPFC_ID_NONE's bits; no id reaches
 * 2^63). A point outside the domain, or skipped by `valid`, gets face -1,
 * feature -1, counts 0 and flags 0. */
typedef struct hpfc_locate_out {
    int64_t *face;           /* the face when one answers (the point's with
                                exact geometry, off the boundary), else -1 */
    uint32_t *face_count;    /* exact: 1, or the faces around a boundary
                                point; else the faces meeting the leaf */
    int64_t *feature;        /* the point's feature when every candidate face
                                links exactly that one feature, else -1 (also
                                without a FEAT section) */
    uint32_t *feature_count; /* distinct features of the candidate faces */
    uint8_t *flags;          /* HPFC_LOC_* */
    uint8_t *depth;          /* level of the leaf, 0 outside */
} hpfc_locate_out;

/* Answers lattice points (x[k], y[k]), k < n, skipping those whose
 * valid[k] is 0 (valid NULL: none skipped). `faces` comes from
 * hpfc_faces_build on the same file, or is NULL to read the file's stored
 * labels instead (no per-process numbering; HPFC_E_NO_SECTION when the
 * file has no LABL section). Stops at the first failure with its
 * status (HPFC_E_CORRUPT, HPFC_E_NOMEM, ...) and the failing index in
 * *failed (when non-NULL); outputs before it are filled. Keeps no state:
 * threads may answer parts of one array at once.
 *
 * With exact geometry, 64 points or more are answered in chunks of 2^18
 * in Morton order of their position (about 60 bytes of scratch a point,
 * 16 MB at most), so that consecutive points share their leaf, which is
 * then read once; the answers are those of input order, and without the
 * memory for the order the call answers in input order. */
HPFC_API int hpfc_locate_batch_sized(const hpfc_file *file, const hpfc_faces *faces, size_t n,
                                     const int64_t *x, const int64_t *y, const uint8_t *valid,
                                     const hpfc_locate_out *out, size_t out_size,
                                     size_t *failed);
/* hpfc_locate_out can grow (hpfc.h, "Structs that grow"): outputs past
 * out_size are not written. */
#define hpfc_locate_batch(file, faces, n, x, y, valid, out, failed) \
    hpfc_locate_batch_sized((file), (faces), (n), (x), (y), (valid), (out), \
                            sizeof(hpfc_locate_out), (failed))

#ifdef __cplusplus
}
#endif
#endif /* HPFC_BATCH_H */
