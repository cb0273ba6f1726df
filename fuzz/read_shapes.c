/*
 * read_shapes: geometry back from a file (hpfc_shapes_*, hpfc_geometry_dart_*)
 * on an opened file, driven by the input.
 *
 * The input is an .hpfc file followed by command bytes (input.h), opened
 * with HPFC_OPEN_SKIP_CHECKSUM so mutated GEOM, LABL, FEAT and EDGF
 * sections reach the ring assembly. Without commands: the index, every
 * face and every feature (at most 256 each, polygons and lines), the darts
 * of the first 64 leaves and windows (hpfc_shapes_window: the domain, its
 * centre quarter and centre point, one beside it, an empty one). With
 * commands: faces and features by input-chosen ids (any value), darts
 * naming any crossing, windows with input-chosen corners within two domain
 * sizes of the domain.
 *
 * Oracle: known statuses only; an index that builds answers in range ids
 * and refuses ids past the end with HPFC_E_ARG; every answer is well
 * formed: offsets non-decreasing and in range, every ring closed and at
 * least four points, outer rings counter-clockwise and holes clockwise
 * (exact signed area), lines at least two points; a dart's polyline has
 * the count the count query gives; a window's lists are ascending ids in
 * range, flagged 0 or 1, the unbounded face never inside, and an empty
 * rectangle is HPFC_E_ARG; each layer's kinds (hpfc_shapes_layer_kinds)
 * are those of its features' records and face counts read one by one
 * where these all read.
 *
 * The SHIX section (format 1.3, the stored inverse tables the shapes read
 * instead of inverting LABL, FEAT and EDGF): hpfc_index_verify gives OK,
 * CORRUPT with a message, or NO_SECTION; when it accepts the section, the
 * same file with the section hidden (its tag renamed: the shapes then
 * invert the sections themselves) gives the same statuses and the same
 * points for the first faces and features.
 *
 * The Python package's ragged arrays (python/src/ragged.c) are built from
 * the same answers, one array per run: every face, feature, feature's
 * lines, edge and dart key probed is appended to it, and the arrays must
 * hold exactly the library's points and offsets (ragged_check).
 */
#include "input.h"
#include "ragged.h"

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
    hpfc_walker *w;
    uint64_t faces, edges;
    uint32_t features;
    int have_features;
    ragged polys, lines; /* the package's arrays: faces and features; lines */
    size_t poly_items, line_items;
} shp;

static int ragged_offsets_ok(const ragged_i64s *a, int64_t last)
{
    if (a->n == 0 || a->v[0] != 0 || a->v[a->n - 1] != last)
        return 0;
    for (size_t k = 1; k < a->n; k++)
        if (a->v[k] < a->v[k - 1])
            return 0;
    return 1;
}

/* The arrays' structure: each level's offsets start at 0, never decrease
 * and end at the next level's size; one part per item, one hole flag per
 * polygon. */
static void ragged_check(const ragged *r, int polygons, size_t items)
{
    FUZZ_CHECK(r->xy.n % 2 == 0);
    FUZZ_CHECK(ragged_offsets_ok(&r->ring, (int64_t)(r->xy.n / 2)));
    FUZZ_CHECK(r->part.n == items + 1);
    if (polygons) {
        FUZZ_CHECK(ragged_offsets_ok(&r->polygon, (int64_t)r->ring.n - 1));
        FUZZ_CHECK(ragged_offsets_ok(&r->part, (int64_t)r->polygon.n - 1));
        FUZZ_CHECK(r->hole_only.n == r->polygon.n - 1);
    } else {
        FUZZ_CHECK(ragged_offsets_ok(&r->part, (int64_t)r->ring.n - 1));
    }
}

/* Item `id` appended to the arrays with status `expect`; its points, read
 * back from the tail, must be `points` points xy (a copy of the library's
 * answer: the call inside ragged_add reuses its buffers), unless xy is
 * NULL. */
static void ragged_probe(shp *z, int kind, uint64_t id, int expect, const int64_t *xy,
                         size_t points)
{
    int polygons = kind == RAGGED_FACE || kind == RAGGED_FEATURE;
    ragged *r = polygons ? &z->polys : &z->lines;
    size_t *items = polygons ? &z->poly_items : &z->line_items;
    size_t xy_before = r->xy.n;
    const ragged_source src = {.file = z->f, .shapes = z->s, .walker = z->w};
    int st = ragged_add(r, &src, kind, id);
    if (st == HPFC_E_NOMEM) /* a partial tail: the package drops the arrays */
        return;
    FUZZ_CHECK(st == expect);
    if (st) { /* the package raises and drops the arrays; here, start anew */
        ragged_free(r);
        FUZZ_CHECK(ragged_start(r, polygons) == HPFC_OK);
        *items = 0;
        return;
    }
    ++*items;
    ragged_check(r, polygons, *items);
    if (xy) {
        FUZZ_CHECK(r->xy.n - xy_before == 2 * points);
        FUZZ_CHECK(points == 0 || memcmp(r->xy.v + xy_before, xy, 2 * points * sizeof *xy) == 0);
    }
}

static void probe_face(shp *z, uint64_t face)
{
    hpfc_polygons p;
    int st = hpfc_shapes_face_polygons(z->s, face, &p);
    check_status(st);
    if (face >= z->faces)
        FUZZ_CHECK(st == HPFC_E_ARG);
    int64_t *xy = NULL;
    size_t points = 0;
    if (!st) {
        check_answer(&p, 0);
        points = p.point_count;
        xy = malloc((2 * points + 1) * sizeof *xy);
        if (!xy)
            return;
        memcpy(xy, p.xy, 2 * points * sizeof *xy);
    }
    ragged_probe(z, RAGGED_FACE, face, st, xy, points);
    free(xy);
}

static void probe_feature(shp *z, hpfc_id k)
{
    hpfc_polygons p;
    size_t n = 0;
    int st = hpfc_shapes_feature_faces(z->s, k, NULL, 0, &n);
    check_status(st);
    if (!z->have_features)
        FUZZ_CHECK(st == HPFC_E_NO_SECTION);
    else if (k >= z->features)
        FUZZ_CHECK(st == HPFC_E_ARG);
    if (!st && n > 0 && n <= FUZZ_ITEMS) { /* the listing: its count, face ids in order */
        hpfc_id faces[FUZZ_ITEMS];
        size_t m = 0;
        FUZZ_CHECK(hpfc_shapes_feature_faces(z->s, k, faces, n - 1, &m) == HPFC_E_BUFFER_SMALL &&
                   m == n);
        FUZZ_CHECK(hpfc_shapes_feature_faces(z->s, k, faces, n, &m) == HPFC_OK && m == n);
        for (size_t j = 0; j < n; j++)
            FUZZ_CHECK(faces[j] < z->faces && (j == 0 || faces[j - 1] <= faces[j]));
    }
    st = hpfc_shapes_feature_polygons(z->s, k, &p);
    check_status(st);
    if (!st)
        check_answer(&p, 0);
    ragged_probe(z, RAGGED_FEATURE, k, st, NULL, 0);
    st = hpfc_shapes_feature_polylines(z->s, k, &p);
    check_status(st);
    if (!st)
        check_answer(&p, 1);
    ragged_probe(z, RAGGED_FEATURE_LINES, k, st, NULL, 0);
}

/* An input edge's polyline in the package's arrays, point by point the
 * library's. */
static void probe_edge(shp *z, uint64_t e)
{
    uint64_t u, v, n = 0;
    int st = hpfc_geometry_edge(z->f, e, &u, &v, &n);
    check_status(st);
    size_t before = z->lines.xy.n;
    const ragged_source src = {.file = z->f, .shapes = z->s, .walker = z->w};
    int got = ragged_add(&z->lines, &src, RAGGED_EDGE, e);
    check_status(got);
    if (st || got) { /* the package raises: start anew */
        ragged_free(&z->lines);
        FUZZ_CHECK(ragged_start(&z->lines, 0) == HPFC_OK);
        z->line_items = 0;
        return;
    }
    ragged_check(&z->lines, 0, ++z->line_items);
    FUZZ_CHECK(z->lines.xy.n - before == 2 * n);
    for (uint64_t k = 0; k < n && k < 64; k++) {
        int64_t x, y;
        FUZZ_CHECK(hpfc_geometry_edge_point(z->f, e, k, &x, &y) == HPFC_OK);
        FUZZ_CHECK(z->lines.xy.v[before + 2 * k] == x && z->lines.xy.v[before + 2 * k + 1] == y);
    }
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
    if (z->w) { /* the package names darts by key */
        size_t before = z->lines.xy.n;
        const ragged_source src = {.file = z->f, .shapes = z->s, .walker = z->w};
        st = ragged_add(&z->lines, &src, RAGGED_DART, hpfc_dart_key(z->f, &d));
        check_status(st);
        if (st) {
            ragged_free(&z->lines);
            FUZZ_CHECK(ragged_start(&z->lines, 0) == HPFC_OK);
            z->line_items = 0;
            return;
        }
        ragged_check(&z->lines, 0, ++z->line_items);
        FUZZ_CHECK(z->lines.xy.n - before >= 4);
    }
}

/* ids[0 .. n): ascending, below `end`, each flag 0 or 1. */
static void check_hits(const hpfc_id *ids, const uint8_t *inside, size_t n, uint64_t end)
{
    for (size_t k = 0; k < n; k++)
        FUZZ_CHECK(ids[k] < end && (k == 0 || ids[k - 1] < ids[k]) && inside[k] <= 1);
}

static void probe_window(shp *z, int64_t x0, int64_t y0, int64_t x1, int64_t y1)
{
    hpfc_window_hits h;
    unsigned what = HPFC_WINDOW_FACES | HPFC_WINDOW_EDGES |
                    (z->have_features ? HPFC_WINDOW_FEATURES : 0u);
    int st = hpfc_shapes_window(z->s, x0, y0, x1, y1, what, &h);
    check_status(st);
    if (x0 > x1 || y0 > y1)
        FUZZ_CHECK(st == HPFC_E_ARG);
    if (st)
        return;
    check_hits(h.face, h.face_inside, h.face_count, z->faces);
    check_hits(h.edge, h.edge_inside, h.edge_count, z->edges);
    check_hits(h.feature, h.feature_inside, h.feature_count, z->features);
    FUZZ_CHECK(h.face_count == 0 || h.face[0] != 0 || h.face_inside[0] == 0);
}

/* A corner coordinate from the input: within two domain sizes of the
 * domain, either side. */
static int64_t window_coord(fuzz_bytes *in, int64_t origin, int64_t size)
{
    return origin - 2 * size + (int64_t)(fuzz_u32(in) % (uint64_t)(5 * size + 1));
}

static void explore_windows(shp *z)
{
    hpfc_file_info fi;
    hpfc_file_get_info(z->f, &fi);
    int64_t x0 = fi.x0, y0 = fi.y0, x1 = fi.x0 + fi.width - 1, y1 = fi.y0 + fi.height - 1;
    int64_t cx = fi.x0 + fi.width / 2, cy = fi.y0 + fi.height / 2;
    probe_window(z, x0, y0, x1, y1);
    probe_window(z, cx - fi.width / 4, cy - fi.height / 4, cx + fi.width / 4, cy + fi.height / 4);
    probe_window(z, cx, cy, cx, cy);
    probe_window(z, x1 + 1, y0, x1 + 1 + fi.width / 2, y1);
    probe_window(z, cx, cy, cx - 1, cy);
}

/* hpfc_shapes_layer_kinds against each feature's record and faces read
 * one by one: the same kinds where those all read, and CORRUPT only where
 * a feature's record does not. */
static void probe_layer_kinds(shp *z)
{
    hpfc_features_info fi;
    if (!z->have_features || z->features > FUZZ_ITEMS ||
        hpfc_file_get_features(z->f, &fi) != HPFC_OK || fi.layers > 64)
        return;
    uint8_t want[64] = {0}, got[64];
    uint64_t want_count[64] = {0}, count[64];
    int records_ok = 1, rows_ok = 1;
    for (uint32_t k = 0; k < z->features; k++) {
        hpfc_feature ft;
        size_t n = 0;
        if (hpfc_file_get_feature(z->f, k, &ft) != HPFC_OK) {
            records_ok = 0;
            continue;
        }
        if (hpfc_shapes_feature_faces(z->s, k, NULL, 0, &n) != HPFC_OK)
            rows_ok = 0;
        want[ft.layer] |= n ? HPFC_KIND_POLYGONS : HPFC_KIND_LINES;
        want_count[ft.layer]++;
    }
    int st = hpfc_shapes_layer_kinds(z->s, got, count, fi.layers);
    check_status(st);
    FUZZ_CHECK(st == HPFC_OK || st == HPFC_E_CORRUPT);
    FUZZ_CHECK(st == HPFC_OK || !records_ok);
    if (st == HPFC_OK && records_ok && rows_ok)
        FUZZ_CHECK(memcmp(got, want, fi.layers) == 0);
    if (st == HPFC_OK && records_ok)
        FUZZ_CHECK(memcmp(count, want_count, fi.layers * sizeof *count) == 0);
}

static void explore(shp *z)
{
    probe_layer_kinds(z);
    for (uint64_t face = 0; face < z->faces && face < FUZZ_ITEMS; face++)
        probe_face(z, face);
    probe_face(z, z->faces);
    for (uint32_t k = 0; k < z->features && k < FUZZ_ITEMS; k++)
        probe_feature(z, k);
    probe_feature(z, z->features);
    hpfc_geometry_info gi;
    if (hpfc_file_get_geometry(z->f, &gi) == HPFC_OK) {
        for (uint64_t e = 0; e < gi.edges && e < FUZZ_ITEMS; e++)
            probe_edge(z, e);
        probe_edge(z, gi.edges);
    }
    explore_windows(z);
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
        switch (fuzz_u8(in) % 6) {
        case 0:
            probe_face(z, fuzz_u8(in) & 1 ? fuzz_u64(in) : fuzz_u16(in) % (z->faces + 1));
            break;
        case 1:
            probe_feature(z, fuzz_u8(in) & 1 ? fuzz_u64(in) : fuzz_u16(in) % (z->features + 1));
            break;
        case 2:
            if (have_leaf)
                have_leaf = hpfc_leaf_next(z->f, &px) == HPFC_OK;
            break;
        case 3:
            if (have_leaf)
                probe_dart(z, &px, fuzz_u8(in));
            break;
        case 4:
            probe_edge(z, fuzz_u8(in) & 1 ? fuzz_u64(in) : fuzz_u16(in));
            break;
        default: {
            hpfc_file_info fi;
            hpfc_file_get_info(z->f, &fi);
            int64_t x0 = window_coord(in, fi.x0, fi.width), y0 = window_coord(in, fi.y0, fi.height);
            int64_t x1 = window_coord(in, fi.x0, fi.width), y1 = window_coord(in, fi.y0, fi.height);
            probe_window(z, x0, y0, x1, y1);
            break;
        }
        }
    }
}

/* A copy of `file` whose SHIX directory entry is renamed to an unknown
 * unflagged tag (readers ignore it), the metadata checksum left stale
 * (opened with HPFC_OPEN_SKIP_CHECKSUM); NULL without SHIX. */
static uint8_t *hide_index(const hpfc_file *f, const uint8_t *file, size_t size)
{
    hpfc_section_info si;
    uint32_t header = (uint32_t)file[12] | (uint32_t)file[13] << 8 | (uint32_t)file[14] << 16 |
                      (uint32_t)file[15] << 24;
    uint32_t levels = (uint32_t)file[40] | (uint32_t)file[41] << 8;
    for (uint32_t k = 0; hpfc_file_get_section(f, k, &si) == HPFC_OK; k++)
        if (memcmp(si.tag, "SHIX", 4) == 0) {
            uint8_t *copy = malloc(size);
            if (!copy)
                return NULL;
            memcpy(copy, file, size);
            memcpy(copy + header + 64 * (size_t)levels + 32 * (size_t)k, "shix", 4);
            return copy;
        }
    return NULL;
}

/* The same answer twice: statuses, then counts and points. */
static void same_answer(int sa, const hpfc_polygons *a, int sb, const hpfc_polygons *b)
{
    FUZZ_CHECK(sa == sb);
    if (sa != HPFC_OK)
        return;
    FUZZ_CHECK(a->point_count == b->point_count && a->ring_count == b->ring_count &&
               a->polygon_count == b->polygon_count);
    FUZZ_CHECK(memcmp(a->xy, b->xy, 2 * a->point_count * sizeof *a->xy) == 0);
}

/* hpfc_index_verify's verdict, and a verified SHIX against the tables
 * the shapes compute without it. */
static void check_index(const hpfc_file *f, hpfc_shapes *s, const uint8_t *file, size_t size)
{
    hpfc_index_report rep;
    int st = hpfc_index_verify(f, &rep);
    FUZZ_CHECK(st == HPFC_OK || st == HPFC_E_NO_SECTION || st == HPFC_E_NOMEM ||
               (st == HPFC_E_CORRUPT && rep.message[0]));
    uint8_t *hidden = st == HPFC_OK ? hide_index(f, file, size) : NULL;
    hpfc_file *g = NULL;
    hpfc_shapes *t = NULL;
    if (hidden && hpfc_open_memory(hidden, size, HPFC_OPEN_SKIP_CHECKSUM, &g) == HPFC_OK &&
        hpfc_shapes_create(g, &t) == HPFC_OK) {
        hpfc_features_info fi;
        uint32_t features = hpfc_file_get_features(f, &fi) == HPFC_OK ? fi.features : 0;
        for (uint64_t face = 0; face < hpfc_shapes_face_count(s) && face < 64; face++) {
            hpfc_polygons a, b;
            int sa = hpfc_shapes_face_polygons(s, face, &a);
            hpfc_polygons keep = a;
            size_t n = sa == HPFC_OK ? 2 * a.point_count : 0;
            int64_t *xy = n ? malloc(n * sizeof *xy) : NULL;
            if (n && !xy)
                continue;
            if (n)
                memcpy(xy, a.xy, n * sizeof *xy);
            keep.xy = xy;
            same_answer(sa, &keep, hpfc_shapes_face_polygons(t, face, &b), &b);
            free(xy);
        }
        for (uint32_t k = 0; k < features && k < 64; k++) {
            size_t na = 0, nb = 0;
            int sa = hpfc_shapes_feature_faces(s, k, NULL, 0, &na);
            int sb = hpfc_shapes_feature_faces(t, k, NULL, 0, &nb);
            FUZZ_CHECK(sa == sb && (sa || na == nb));
        }
    }
    hpfc_shapes_free(t);
    hpfc_close(g);
    free(hidden);
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
        if (st == HPFC_OK && ragged_start(&z.polys, 1) == HPFC_OK &&
            ragged_start(&z.lines, 0) == HPFC_OK) {
            if (hpfc_walker_create(f, &z.w) != HPFC_OK)
                z.w = NULL;
            z.faces = hpfc_shapes_face_count(z.s);
            hpfc_geometry_info gi;
            z.edges = hpfc_file_get_geometry(f, &gi) == HPFC_OK ? gi.edges : 0;
            hpfc_features_info fi;
            z.have_features = hpfc_file_get_features(f, &fi) == HPFC_OK;
            z.features = z.have_features ? fi.features : 0;
            if (fuzz_empty(&cmds)) {
                check_index(f, z.s, file, file_size);
                explore(&z);
            }
            else
                run_commands(&z, &cmds);
        }
        ragged_free(&z.polys);
        ragged_free(&z.lines);
        hpfc_walker_free(z.w);
        hpfc_shapes_free(z.s);
        hpfc_close(f);
    }
    free(file);
    return 0;
}
