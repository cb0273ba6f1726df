/*
 * draco_input.h: Draco meshes (.drc) as hpfc graphs, for hpfc-pack.
 *
 * A small C interface over Draco's C++ decoder (draco_input.cc). Builds
 * without Draco compile draco_stub.c instead, whose functions fail with
 * DRACO_E_NOT_BUILT. No C++ exception ever crosses into C.
 *
 * The decoder dequantizes positions as Draco defines them; the triangles and
 * the x, y of those positions then go through mesh_graph_build()
 * (mesh_graph.h), which chooses the lattice and makes the planar graph.
 * Safe on untrusted input: a corrupt, truncated or unsupported file gives a
 * status and a one-line reason (Draco's own message where it has one).
 */
#ifndef HPFC_PACK_DRACO_INPUT_H
#define HPFC_PACK_DRACO_INPUT_H

#include <stddef.h>
#include <string.h>

#include "hpfc.h"
#include "mesh_graph.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Statuses beyond the HPFC_E_* codes these functions also return (those of
 * mesh_graph_build, and HPFC_E_IO when the file cannot be read). */
enum {
    DRACO_E_NOT_BUILT = 200, /* this build has no Draco decoder */
    DRACO_E_DECODE = 201,    /* Draco refused the bytes: not Draco, corrupt, truncated,
                                an unsupported version or feature */
    DRACO_E_NOT_MESH = 202   /* a point cloud, or a mesh without 2-D or 3-D positions */
};

typedef struct draco_options {
    mesh_graph_options mesh;  /* lattice unit; zero: chosen from the data */
    mesh_graph_stats *stats;  /* when non-NULL, receives what the conversion did */
} draco_options;

/* Whether this build can decode Draco (1) or not (0). */
int draco_input_available(void);

/* Decodes the Draco mesh in data[0..size) into a new graph (*out, free with
 * hpfc_graph_free) that passed hpfc_graph_validate. opts may be NULL. On
 * failure *out is NULL and diag (when non-NULL) holds the reason. */
int draco_graph_from_memory(const void *data, size_t size, const draco_options *opts,
                            hpfc_graph **out, hpfc_diag *diag);

/* The same for the file at path. */
int draco_read_graph(const char *path, const draco_options *opts, hpfc_graph **out,
                     hpfc_diag *diag);

/* Does the buffer start with Draco's magic "DRACO"? (Either build.) */
static inline int draco_has_magic(const void *data, size_t size)
{
    return size >= 5 && memcmp(data, "DRACO", 5) == 0;
}

#ifdef __cplusplus
}
#endif

#endif
