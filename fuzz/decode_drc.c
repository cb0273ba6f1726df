/*
 * decode_drc: hpfc-pack's mesh input (hpfc-pack/draco_input.h,
 * hpfc-pack/mesh_graph.h).
 *
 * An input that starts with "DRACO" goes whole through Draco's decoder and
 * mesh_graph_build (draco_graph_from_memory), as hpfc-pack reads a .drc
 * file. Any other input is a raw mesh recipe handed straight to
 * mesh_graph_build, so the lattice choice, point merging, dropped and split
 * triangles and fold detection see meshes Draco's own checks would never let
 * through (NaN, infinities, indices out of range, any unit):
 *
 *   u8 flags       bit 0: fixed unit, then an i8 exponent follows (any
 *                  value, so out-of-range units are tried too)
 *   u8 npoints     at most 64
 *   u8 ntri        at most 64
 *   points         per point a u8 kind, then x and y: kind & 3 = 0: i16
 *                  scaled by 2^-(kind >> 2); 1: i32 scaled the same; 2: the
 *                  raw bits of a double (NaN, infinities, subnormals);
 *                  3: a small integer (i8), to make merges and collinear
 *                  triples likely
 *   triangles      3 x u8 indices, taken modulo npoints + 2 (so some are
 *                  out of range)
 *
 * Oracle: the status is one the headers document (never NOT_BUILT in a
 * Draco build, ARG only for a fixed unit); a graph comes back exactly on
 * success, and the diagnostic is filled otherwise; the graph passes
 * hpfc_graph_validate and the shape checks of input.h, its counts match
 * the stats; in the raw path every
 * vertex is the lattice image (mesh_lattice_coord, at the reported unit) of
 * an input point some triangle uses, the stats count no more used points
 * than the mesh has and at most three edges per triangle plus one per split;
 * decoding twice gives the same graph.
 */
#include <math.h>

#include "draco_input.h"
#include "input.h"
#include "mesh_graph.h"

enum { RAW_MAX_POINTS = 64, RAW_MAX_TRIANGLES = 64 };

static bool status_ok(int st, bool raw)
{
    switch (st) {
    case HPFC_OK:
    case HPFC_E_NOMEM:
    case HPFC_E_VERTEX_INDEX:
    case HPFC_E_EXTENT:
    case HPFC_E_EMPTY:
    case HPFC_E_NONPLANAR:
    case HPFC_E_LIMIT:
        return true;
    case HPFC_E_ARG: /* a fixed unit out of range: only the raw path sets one */
        return raw;
    case DRACO_E_DECODE:
    case DRACO_E_NOT_MESH:
        return !raw;
    case DRACO_E_NOT_BUILT:
        return !raw && !draco_input_available();
    default:
        return false;
    }
}

static double raw_coordinate(fuzz_bytes *in, uint8_t kind)
{
    double scale = ldexp(1.0, -(int)(kind >> 2));
    switch (kind & 3) {
    case 0:
        return (int16_t)fuzz_u16(in) * scale;
    case 1:
        return (int32_t)fuzz_u32(in) * scale;
    case 2: {
        uint64_t bits = fuzz_u64(in);
        double v;
        memcpy(&v, &bits, sizeof v);
        return v;
    }
    default:
        return (int8_t)fuzz_u8(in);
    }
}

typedef struct raw_mesh {
    mesh_graph_options opts;
    size_t npoints, ntri;
    double pos[2 * RAW_MAX_POINTS];
    uint32_t tri[3 * RAW_MAX_TRIANGLES];
} raw_mesh;

static void raw_mesh_read(fuzz_bytes *in, raw_mesh *m)
{
    memset(m, 0, sizeof *m);
    uint8_t flags = fuzz_u8(in);
    if (flags & 1) {
        m->opts.fixed_unit = 1;
        m->opts.unit_exp10 = (int8_t)fuzz_u8(in);
    }
    m->npoints = fuzz_u8(in) % (RAW_MAX_POINTS + 1);
    m->ntri = fuzz_u8(in) % (RAW_MAX_TRIANGLES + 1);
    for (size_t p = 0; p < m->npoints; p++) {
        uint8_t kind = fuzz_u8(in);
        m->pos[2 * p] = raw_coordinate(in, kind);
        m->pos[2 * p + 1] = raw_coordinate(in, kind);
    }
    for (size_t k = 0; k < 3 * m->ntri; k++)
        m->tri[k] = fuzz_u8(in) % (uint32_t)(m->npoints + 2);
}

/* Is (x, y) the lattice image of a point some triangle uses? */
static bool is_image_of_used_point(const raw_mesh *m, int32_t unit, int64_t x, int64_t y)
{
    for (size_t k = 0; k < 3 * m->ntri; k++) {
        uint32_t p = m->tri[k];
        int64_t px, py;
        if (p < m->npoints && mesh_lattice_coord(m->pos[2 * p], unit, &px) == HPFC_OK &&
            mesh_lattice_coord(m->pos[2 * p + 1], unit, &py) == HPFC_OK && px == x && py == y)
            return true;
    }
    return false;
}

static void check_raw_graph(const raw_mesh *m, const hpfc_graph *g, const mesh_graph_stats *s)
{
    FUZZ_CHECK(s->points_used <= m->npoints);
    FUZZ_CHECK(s->edges <= 3 * m->ntri + s->split_edges);
    FUZZ_CHECK(s->unit_exp10 == hpfc_graph_unit_exp10(g));
    FUZZ_CHECK(!m->opts.fixed_unit || s->unit_exp10 == m->opts.unit_exp10);
    for (size_t v = 0; v < hpfc_graph_vertex_count(g); v++) {
        int64_t x, y;
        hpfc_graph_vertex(g, v, &x, &y);
        FUZZ_CHECK(is_image_of_used_point(m, s->unit_exp10, x, y));
    }
}

static int decode(const uint8_t *data, size_t size, const raw_mesh *m, hpfc_graph **g,
                  mesh_graph_stats *stats, hpfc_diag *diag)
{
    if (!m) {
        draco_options opts = {.stats = stats};
        return draco_graph_from_memory(data, size, &opts, g, diag);
    }
    return mesh_graph_build(m->pos, 2, m->npoints, m->tri, m->ntri, &m->opts, g, stats, diag);
}

/* Checks a decoded graph, then frees it. */
static void check_graph(const uint8_t *data, size_t size, const raw_mesh *m, hpfc_graph *g,
                        const mesh_graph_stats *stats)
{
    fuzz_check_graph(g);
    FUZZ_CHECK(hpfc_graph_validate(g, NULL) == HPFC_OK);
    FUZZ_CHECK(stats->vertices == hpfc_graph_vertex_count(g));
    FUZZ_CHECK(stats->edges == hpfc_graph_edge_count(g));
    if (m)
        check_raw_graph(m, g, stats);
    hpfc_graph *again = NULL;
    FUZZ_CHECK(decode(data, size, m, &again, NULL, NULL) == HPFC_OK);
    FUZZ_CHECK(fuzz_same_graph(g, again));
    hpfc_graph_free(again);
    hpfc_graph_free(g);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    raw_mesh *m = NULL;
    if (!draco_has_magic(data, size)) {
        m = malloc(sizeof *m);
        if (!m)
            return 0;
        fuzz_bytes in = {data, size};
        raw_mesh_read(&in, m);
    }
    hpfc_graph *g = NULL;
    hpfc_diag diag;
    mesh_graph_stats stats;
    memset(&stats, 0, sizeof stats);
    int st = decode(data, size, m, &g, &stats, &diag);
    FUZZ_CHECK(status_ok(st, m != NULL));
    FUZZ_CHECK((st == HPFC_OK) == (g != NULL));
    if (st != HPFC_OK)
        fuzz_check_diag(&diag, st);
    else
        check_graph(data, size, m, g, &stats);
    free(m);
    return 0;
}
