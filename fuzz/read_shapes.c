/*
 * read_shapes: geometry back from a file (hpfc_shapes_*, hpfc_geometry_dart_*)
 * on an opened file, driven by the input.
 *
 * The input is an .hpfc file followed by command bytes (input.h), opened
 * with HPFC_OPEN_SKIP_CHECKSUM so mutated GEOM, LABL, FEAT and EDGF
 * sections reach the ring assembly. Without commands: the index, every
 * face and every feature (at most 256 each, polygons and lines) and the
 * darts of the first 64 leaves. With commands: faces and features by
 * input-chosen ids (any value), darts naming any crossing.
 *
 * Oracle: known statuses only; an index that builds answers in range ids
 * and refuses ids past the end with HPFC_E_ARG; every answer is well
 * formed: offsets non-decreasing and in range, every ring closed and at
 * least four points, outer rings counter-clockwise and holes clockwise
 * (exact signed area), lines at least two points; a dart's polyline has
 * the count the count query gives.
 */
#include "input.h"

#define FUZZ_ITEMS 256
#define FUZZ_LEAVES 64

__extension__ typedef __int128 s128;

/* The operators' statuses, and a missing section (FEAT, EDGF, GEOM). */
static void check_status(int st)
{
    FUZZ_CHECK(fuzz_known_status(st) || st == HPFC_E_NO_SECTION);
}

static s128 ring_area2(const hpfc_polygons *p, size_t r)
{
    s128 a = 0;
    for (size_t k = p->ring_point[r]; k + 1 < p->ring_point[r + 1]; k++)
        a += (s128)p->xy[2 * k] * p->xy[2 * k + 3] - (s128)p->xy[2 * k + 2] * p->xy[2 * k + 1];
    return a;
}

/* An answer's structure; lines: open polylines, no polygon. */
static void check_answer(const hpfc_polygons *p, int lines)
{
    FUZZ_CHECK(p->ring_point[0] == 0 && p->ring_point[p->ring_count] == p->point_count);
    FUZZ_CHECK(p->polygon_ring[0] == (lines ? p->ring_count : 0) || p->polygon_count > 0);
    FUZZ_CHECK(p->polygon_ring[p->polygon_count] <= p->ring_count);
    if (lines)
        FUZZ_CHECK(p->polygon_count == 0 && p->polygon_ring[0] == p->ring_count);
    for (size_t q = 0; q < p->polygon_count; q++)
        FUZZ_CHECK(p->polygon_ring[q] < p->polygon_ring[q + 1]);
    for (size_t r = 0; r < p->ring_count; r++) {
        size_t a = p->ring_point[r], b = p->ring_point[r + 1];
        FUZZ_CHECK(a <= b && b <= p->point_count);
        if (lines) {
            FUZZ_CHECK(b - a >= 2);
            continue;
        }
        FUZZ_CHECK(b - a >= 4);
        FUZZ_CHECK(p->xy[2 * a] == p->xy[2 * (b - 1)] &&
                   p->xy[2 * a + 1] == p->xy[2 * (b - 1) + 1]);
        int outer = 0;
        for (size_t q = 0; q < p->polygon_count; q++)
            outer |= p->polygon_ring[q] == r;
        s128 area = ring_area2(p, r);
        FUZZ_CHECK(outer ? area > 0 : area < 0);
    }
}

typedef struct shp {
    const hpfc_file *f;
    hpfc_shapes *s;
    uint64_t faces;
    uint32_t features;
    int have_features;
} shp;

static void probe_face(shp *z, uint64_t face)
{
    hpfc_polygons p;
    int st = hpfc_shapes_face(z->s, face, &p);
    check_status(st);
    if (face >= z->faces)
        FUZZ_CHECK(st == HPFC_E_ARG);
    if (!st)
        check_answer(&p, 0);
}

static void probe_feature(shp *z, uint32_t k)
{
    hpfc_polygons p;
    uint64_t n = 0;
    int st = hpfc_shapes_feature_face_count(z->s, k, &n);
    check_status(st);
    if (!z->have_features)
        FUZZ_CHECK(st == HPFC_E_NO_SECTION);
    else if (k >= z->features)
        FUZZ_CHECK(st == HPFC_E_ARG);
    st = hpfc_shapes_feature(z->s, k, &p);
    check_status(st);
    if (!st)
        check_answer(&p, 0);
    st = hpfc_shapes_feature_lines(z->s, k, &p);
    check_status(st);
    if (!st)
        check_answer(&p, 1);
}

static void probe_dart(shp *z, const hpfc_pixel *px, uint32_t crossing)
{
    hpfc_dart d = {.pixel = *px, .crossing = crossing};
    uint64_t e;
    int rev = -1;
    size_t n = 0, n2 = 0;
    int st = hpfc_geometry_dart_edge(z->f, &d, &e, &rev);
    check_status(st);
    if (!st)
        FUZZ_CHECK(rev == 0 || rev == 1);
    st = hpfc_geometry_dart_points(z->f, &d, NULL, 0, &n);
    check_status(st);
    if (st || n > 4096)
        return;
    int64_t *xy = malloc((2 * n + 2) * sizeof *xy);
    if (!xy)
        return;
    st = hpfc_geometry_dart_points(z->f, &d, xy, n, &n2);
    check_status(st);
    if (!st)
        FUZZ_CHECK(n2 == n && n >= 2);
    free(xy);
}

static void explore(shp *z)
{
    for (uint64_t face = 0; face < z->faces && face < FUZZ_ITEMS; face++)
        probe_face(z, face);
    probe_face(z, z->faces);
    for (uint32_t k = 0; k < z->features && k < FUZZ_ITEMS; k++)
        probe_feature(z, k);
    probe_feature(z, z->features);
    hpfc_pixel px;
    int st = hpfc_leaf_first(z->f, &px);
    for (int leaves = 0; !st && leaves < FUZZ_LEAVES; leaves++) {
        size_t len = 0;
        if (hpfc_pixel_word(z->f, &px, NULL, 0, &len) == HPFC_OK)
            for (uint32_t c = 0; c < 8 && c <= len; c++)
                probe_dart(z, &px, c);
        st = hpfc_leaf_next(z->f, &px);
    }
}

static void run_commands(shp *z, fuzz_bytes *in)
{
    hpfc_pixel px;
    int have_leaf = hpfc_leaf_first(z->f, &px) == HPFC_OK;
    for (int steps = 0; steps < 64 && !fuzz_empty(in); steps++) {
        switch (fuzz_u8(in) % 4) {
        case 0:
            probe_face(z, fuzz_u8(in) & 1 ? fuzz_u64(in) : fuzz_u16(in) % (z->faces + 1));
            break;
        case 1:
            probe_feature(z, fuzz_u8(in) & 1 ? fuzz_u32(in) : fuzz_u16(in) % (z->features + 1));
            break;
        case 2:
            if (have_leaf)
                have_leaf = hpfc_leaf_next(z->f, &px) == HPFC_OK;
            break;
        default:
            if (have_leaf)
                probe_dart(z, &px, fuzz_u8(in));
            break;
        }
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    uint8_t *file;
    size_t file_size;
    fuzz_bytes cmds;
    if (!fuzz_split_file(data, size, &file, &file_size, &cmds))
        return 0;
    hpfc_file *f = NULL;
    if (hpfc_open_memory(file, file_size, HPFC_OPEN_SKIP_CHECKSUM, &f) == HPFC_OK) {
        shp z = {.f = f};
        int st = hpfc_shapes_create(f, &z.s);
        check_status(st);
        if (st == HPFC_OK) {
            z.faces = hpfc_shapes_face_count(z.s);
            hpfc_features_info fi;
            z.have_features = hpfc_file_features(f, &fi) == HPFC_OK;
            z.features = z.have_features ? fi.features : 0;
            if (fuzz_empty(&cmds))
                explore(&z);
            else
                run_commands(&z, &cmds);
            hpfc_shapes_free(z.s);
        }
        hpfc_close(f);
    }
    free(file);
    return 0;
}
