/*
 * s2_peer.h: Google's S2 as a peer of exact point location:
 * polygons in lon/lat, as S2LaxPolygonShapes in an S2ShapeIndex, encoded
 * and queried through EncodedS2ShapeIndex with lazy decoding and
 * S2ContainsPointQuery, S2's way of answering containment straight from an
 * encoded buffer. A C interface for bench_locate_exact.c.
 */
#ifndef HPFC_BENCH_S2_PEER_H
#define HPFC_BENCH_S2_PEER_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct s2_peer s2_peer;

s2_peer *s2_peer_create(void);
void s2_peer_free(s2_peer *p);
/* Starts polygon `id` (a multipolygon's parts are added one ring after
 * another; `shell` marks each part's outer ring, the holes follow it). */
void s2_peer_begin(s2_peer *p, int64_t id);
/* One ring of the current polygon, n points (lon, lat) in degrees; a
 * closing point equal to the first is dropped. */
void s2_peer_ring(s2_peer *p, const double *lon, const double *lat, size_t n, int shell);
/* Indexes the polygons, encodes shapes and index into one buffer and opens
 * it as an EncodedS2ShapeIndex; *bytes is the buffer's size. 0 on success. */
int s2_peer_build(s2_peer *p, size_t *bytes);
/* A point as S2's unit vector (x, y, z), converted before timing. */
void s2_peer_point(double lon, double lat, double xyz[3]);
/* The id of the first polygon containing the point (semi-open model), or -1. */
int64_t s2_peer_locate(s2_peer *p, const double xyz[3]);

#ifdef __cplusplus
}
#endif

#endif
