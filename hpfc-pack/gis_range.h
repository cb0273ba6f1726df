/*
 * gis_range.h: a run of one GIS layer's features read by another process,
 * as a range file (docs/interfaces.md section 8, "GIS layers read in
 * feature ranges").
 *
 * hpfc-pack --read-range reads features [begin, end) of one layer exactly
 * as a whole read would (GDAL's parse, the coordinate checks, the
 * antimeridian cut, GEOS's polygon checks, the attributes) and writes what
 * the read kept; hpfc-pack --read-ranges takes the ranges back in order,
 * so that the rest of the pack (projection, lattice, noding, build) sees
 * the very arrays a whole read gives. Nothing here needs GDAL: the file's
 * bytes are parsed and checked by libc alone, and are untrusted (another
 * host may have written them, a disk may have damaged them).
 *
 * A range file, all integers little-endian:
 *   magic "HPFCRNG" and the version byte 2;
 *   u64 payload length, u64 FNV-1a hash of the payload;
 *   payload: u64 tag (the reading's, so a file of another run is refused),
 *   u32 layer, u32 fields (the layer's --fields count), i64 begin,
 *   u64 chain (bit 0: fid_before is set, bit 1: fid_last is), i64
 *   fid_before (the source FID of the feature before the range, read to
 *   check that GDAL started where a whole read would be), i64 fid_last
 *   (of the range's last feature, else fid_before), u64 read (features read, empty ones too: positions begin ..
 *   begin + read - 1), u64 lines, skipped_empty, skipped_points,
 *   dateline_cut, invalid_noded, u64 features, parts, points, u32
 *   repaired; then each feature (i64 position, i64 source FID, its key
 *   as a string, u32 values, each value u32 field, u8 kind and an i64,
 *   f64 or string), each part (u64 points, u32 feature, u8 ring), the
 *   points (f64 x, y, already swapped and cut as a whole read keeps
 *   them) and the names of the first noded invalid polygons. A string is
 *   u32 length + 1 (0 for none) and its bytes, without a NUL.
 */
#ifndef HPFC_PACK_GIS_RANGE_H
#define HPFC_PACK_GIS_RANGE_H

#include <stddef.h>
#include <stdint.h>

/* A range file's first 8 bytes: "HPFCRNG" and the version */
#define GIS_RANGE_MAGIC "HPFCRNG\2"

enum { GIS_RANGE_INTEGER = 1, GIS_RANGE_REAL = 2, GIS_RANGE_STRING = 3 };
/* the names of the first noded invalid polygons a report lists */
enum { GIS_RANGE_REPAIRED = 5 };
#define GIS_RANGE_NONE SIZE_MAX

typedef struct gis_range_value {
    uint32_t field; /* in the layer's --fields, from 0 */
    uint8_t kind;   /* GIS_RANGE_* */
    int64_t i;
    double r;
    size_t s; /* a string's offset in the range's text */
} gis_range_value;

typedef struct gis_range_feature {
    int64_t position, fid;
    size_t key;            /* its offset in the range's text, GIS_RANGE_NONE for none */
    size_t first_value, values;
} gis_range_feature;

typedef struct gis_range_part {
    size_t first_point, points;
    uint32_t feature; /* in the range, from 0 */
    int ring;
} gis_range_part;

typedef struct gis_range_counts {
    uint64_t read, lines, skipped_empty, skipped_points, dateline_cut, invalid_noded;
} gis_range_counts;

/* What a reader of a range keeps, and what a parse gives back. */
typedef struct gis_range {
    uint64_t tag;
    uint32_t layer, fields;
    int64_t begin;
    /* The FIDs that chain the ranges of a layer: range k's fid_before is
     * range k - 1's fid_last when GDAL's SetNextByIndex follows the order
     * of its GetNextFeature (a shapefile with deleted records does not). */
    int has_before, has_last;
    int64_t fid_before, fid_last;
    gis_range_counts counts;
    gis_range_feature *features;
    gis_range_part *parts;
    gis_range_value *values;
    double *xy;
    size_t repaired[GIS_RANGE_REPAIRED]; /* offsets in text */
    size_t n_features, n_parts, n_values, n_points, n_repaired;
    /* owned storage; the strings, each ended by a NUL */
    char *text;
    size_t text_len, cap_text, cap_features, cap_parts, cap_values, cap_points;
} gis_range;

/* ---- writing (hpfc-pack --read-range) ---- */

/* An empty range of `layer` from `begin`; gis_range_free releases it. */
void gis_range_init(gis_range *g, uint64_t tag, uint32_t layer, uint32_t fields, int64_t begin);
void gis_range_free(gis_range *g);
/* The next feature, then its values; -1 when memory runs out. */
int gis_range_add_feature(gis_range *g, int64_t position, int64_t fid, const char *key);
int gis_range_add_integer(gis_range *g, uint32_t field, int64_t v);
int gis_range_add_real(gis_range *g, uint32_t field, double v);
int gis_range_add_string(gis_range *g, uint32_t field, const char *s);
/* A part of feature `feature` (parts in feature order): n points (x, y). */
int gis_range_add_part(gis_range *g, uint32_t feature, const double *xy, size_t n, int ring);
/* A noded invalid polygon's name (only the first few are kept). */
int gis_range_add_repaired(gis_range *g, const char *item);
/* The file's bytes (malloc'ed) in *out; -1 when memory runs out. */
int gis_range_encode(const gis_range *g, uint8_t **out, size_t *len);

/* The payload's hash a range file stores (FNV-1a, 64 bits): it tells a
 * damaged file from a whole one, not a forged one from a true one. */
uint64_t gis_range_hash(const uint8_t *payload, size_t n);

/* ---- reading (hpfc-pack --read-ranges) ---- */

/* Parses and checks a range file's bytes: the magic, the hash, the tag,
 * layer and begin the reading expects, the counts against the bytes, and
 * the data's own consistency (positions rising within the range, every
 * feature with parts in order, finite points, fields below the layer's
 * count). 0, or -1 with why[] (a line without the file's name) filled
 * and *g left empty. */
int gis_range_decode(const uint8_t *bytes, size_t len, uint64_t tag, uint32_t layer,
                     int64_t begin, gis_range *g, char *why, size_t why_len);
/* A range file's head, its first GIS_RANGE_HEAD bytes (or more, or the
 * whole file): the magic, the reading, the counts against the payload
 * length it states. Its hash and data are left for gis_range_decode, so
 * a reader can check a chain of ranges before it reads any of them. Only
 * tag, layer, fields, begin, the chain and the counts are kept. */
#define GIS_RANGE_HEAD 148
int gis_range_decode_head(const uint8_t *bytes, size_t len, uint64_t tag, uint32_t layer,
                          int64_t begin, gis_range *g, char *why, size_t why_len);

#endif
