/*
 * locate_batch: hpfc_locate_batch (hpfc_batch.h), the call behind the Python
 * package's array queries, on an opened file.
 *
 * The input is an .hpfc file followed by command bytes (input.h), opened
 * with HPFC_OPEN_SKIP_CHECKSUM so mutated pools and FEAT sections reach the
 * faces and the links. Without commands the points are a 9 x 9 grid over
 * the domain and a margin around it, the domain's corners and points far
 * outside; with commands, each 17 bytes give a point (domain-relative or any
 * 64-bit pair) and whether it is skipped. At most FUZZ_POINTS points.
 *
 * Oracle: known statuses only; on success every answer agrees with the
 * single-point calls it strings together: outside (hpfc_locate says
 * NO_PIXEL) or skipped means face -1, feature -1, counts 0, flags 0;
 * inside: INSIDE set, PRIVATE as hpfc_pixel_is_private, depth the leaf's,
 * SINGLE exactly when one face meets the leaf, the face then below the face
 * count (a private leaf: hpfc_faces_pixel_face's) and -1 otherwise;
 * a feature only with a FEAT section, below its feature count and counted
 * in feature_count; a FEAT section that does not read fails the whole
 * batch with its status. The call keeps no state: each half of the points
 * answered alone, and each point alone, gives the same arrays (a batch of
 * 64 or more points is answered in Morton order with the last leaf
 * reused, a smaller one in input order), and a failure at point k fails
 * the batch of point k alone with the same status.
 *
 * A file with GEOM and LABL is answered exactly (hpfc_locate_point's
 * code): then every answer is hpfc_locate_point's (status, face count, the
 * face when one, BOUNDARY, depth), EXACT is set, and every face it names
 * is the face of one of the leaf's stretches (hpfc_label_stretch_face);
 * a vertex or edge it names is below GEOM's counts. A point whose exact
 * location fails fails the batch at that point with the same status.
 */
#include "hpfc_batch.h"
#include "input.h"

#define FUZZ_POINTS 160

typedef struct answers {
    int64_t face[FUZZ_POINTS], feature[FUZZ_POINTS];
    uint32_t face_count[FUZZ_POINTS], feature_count[FUZZ_POINTS];
    uint8_t flags[FUZZ_POINTS], depth[FUZZ_POINTS];
} answers;

static hpfc_locate_out out_of(answers *a, size_t offset)
{
    hpfc_locate_out o = {a->face + offset, a->face_count + offset, a->feature + offset,
                         a->feature_count + offset, a->flags + offset, a->depth + offset};
    return o;
}

static size_t default_points(const hpfc_file_info *info, int64_t *x, int64_t *y, uint8_t *valid)
{
    size_t n = 0;
    for (int i = 0; i < 9; i++)
        for (int j = 0; j < 9; j++) {
            /* from -1/8 to 9/8 of the domain in each direction */
            x[n] = info->x0 + (info->width / 8) * (i - 1) + i;
            y[n] = info->y0 + (info->height / 8) * (j - 1) + j;
            valid[n++] = 1;
        }
    const int64_t corner_x[] = {info->x0, info->x0 + info->width - 1, info->x0 + info->width,
                                INT64_MIN, INT64_MAX};
    const int64_t corner_y[] = {info->y0, info->y0 + info->height - 1, info->y0 + info->height,
                                INT64_MAX, INT64_MIN};
    for (int k = 0; k < 5; k++) {
        x[n] = corner_x[k];
        y[n] = corner_y[k];
        valid[n++] = 1;
    }
    return n;
}

static size_t command_points(const hpfc_file_info *info, fuzz_bytes *cmds, int64_t *x, int64_t *y,
                             uint8_t *valid)
{
    size_t n = 0;
    while (!fuzz_empty(cmds) && n < FUZZ_POINTS) {
        uint8_t mode = fuzz_u8(cmds);
        uint64_t u = fuzz_u64(cmds), v = fuzz_u64(cmds);
        if (mode & 1) { /* inside or next to the domain */
            uint64_t w = (uint64_t)info->width + 2, h = (uint64_t)info->height + 2;
            x[n] = info->x0 - 1 + (int64_t)(w ? u % w : 0);
            y[n] = info->y0 - 1 + (int64_t)(h ? v % h : 0);
        } else {
            x[n] = (int64_t)u;
            y[n] = (int64_t)v;
        }
        valid[n++] = (mode & 2) == 0;
    }
    return n;
}

/* Is `face` the face of some stretch of leaf px? */
static bool stretch_face_of(const hpfc_file *f, const hpfc_pixel *px, uint64_t face)
{
    size_t len;
    if (hpfc_pixel_word(f, px, NULL, 0, &len) != HPFC_OK || len < 4)
        return false;
    uint32_t stretches = len > 4 ? (uint32_t)(len - 4) : 1;
    for (uint32_t t = 0; t < stretches; t++) {
        uint64_t g;
        if (hpfc_label_stretch_face(f, px, t, &g) == HPFC_OK && g == face)
            return true;
    }
    return false;
}

/* An exact answer against hpfc_locate_point's. */
static void check_exact(const hpfc_file *f, const hpfc_geometry_info *gi, const answers *a,
                        size_t k, int64_t x, int64_t y, uint8_t valid)
{
    hpfc_point_location loc;
    uint64_t faces[64];
    size_t count = 0;
    int st = valid ? hpfc_locate_point(f, x, y, &loc, faces, 64, &count) : HPFC_E_NO_PIXEL;
    if (st == HPFC_E_NO_PIXEL) {
        FUZZ_CHECK(a->face[k] == -1 && a->face_count[k] == 0 && a->flags[k] == 0 &&
                   a->depth[k] == 0);
        return;
    }
    FUZZ_CHECK(st == HPFC_OK || (st == HPFC_E_BUFFER_SMALL && count > 64));
    FUZZ_CHECK(a->flags[k] & HPFC_LOC_INSIDE && a->flags[k] & HPFC_LOC_EXACT);
    FUZZ_CHECK(!(a->flags[k] & HPFC_LOC_BOUNDARY) == !loc.on_boundary);
    FUZZ_CHECK(a->face_count[k] == count && count >= 1);
    FUZZ_CHECK(a->depth[k] == loc.leaf.depth);
    FUZZ_CHECK(loc.on_boundary || count == 1);
    if (st)
        return;
    FUZZ_CHECK(a->face[k] == (count == 1 ? (int64_t)faces[0] : -1));
    for (size_t i = 0; i < count; i++) {
        FUZZ_CHECK(i == 0 || faces[i - 1] < faces[i]);
        FUZZ_CHECK(stretch_face_of(f, &loc.leaf, faces[i]));
    }
    if (loc.on_vertex) {
        FUZZ_CHECK(loc.on_boundary && loc.vertex < gi->vertices);
    } else if (loc.on_boundary) {
        FUZZ_CHECK(loc.edge < gi->edges);
    }
}

static void check_answer(const hpfc_file *f, const hpfc_faces *fc, int features,
                         const hpfc_features_info *fi, const answers *a, size_t k, int64_t x,
                         int64_t y, uint8_t valid)
{
    hpfc_pixel px;
    int st = valid ? hpfc_locate(f, x, y, &px) : HPFC_E_NO_PIXEL;
    if (st == HPFC_E_NO_PIXEL) {
        FUZZ_CHECK(a->face[k] == -1 && a->feature[k] == -1 && a->face_count[k] == 0 &&
                   a->feature_count[k] == 0 && a->flags[k] == 0 && a->depth[k] == 0);
        return;
    }
    FUZZ_CHECK(st == HPFC_OK); /* the batch answered this very call */
    int is_private = 0;
    FUZZ_CHECK(hpfc_pixel_is_private(f, &px, &is_private) == HPFC_OK);
    FUZZ_CHECK(a->flags[k] & HPFC_LOC_INSIDE);
    FUZZ_CHECK(!(a->flags[k] & HPFC_LOC_PRIVATE) == !is_private);
    FUZZ_CHECK(a->depth[k] == px.depth);
    int single = (a->flags[k] & HPFC_LOC_SINGLE) != 0;
    FUZZ_CHECK(single == (a->face_count[k] == 1));
    if (single) {
        FUZZ_CHECK(a->face[k] >= 0 && (uint64_t)a->face[k] < hpfc_faces_face_count(fc));
    } else {
        FUZZ_CHECK(a->face[k] == -1);
    }
    if (is_private) {
        uint64_t face;
        FUZZ_CHECK(hpfc_faces_pixel_face(fc, &px, &face) == HPFC_OK);
        FUZZ_CHECK(single && (uint64_t)a->face[k] == face);
    }
    if (!features) {
        FUZZ_CHECK(a->feature[k] == -1 && a->feature_count[k] == 0);
    } else if (a->feature[k] >= 0) {
        FUZZ_CHECK((uint64_t)a->feature[k] < fi->features && a->feature_count[k] == 1);
    }
}

static bool same_answers(const answers *a, const answers *b, size_t from, size_t to)
{
    for (size_t k = from; k < to; k++)
        if (a->face[k] != b->face[k] || a->feature[k] != b->feature[k] ||
            a->face_count[k] != b->face_count[k] || a->feature_count[k] != b->feature_count[k] ||
            a->flags[k] != b->flags[k] || a->depth[k] != b->depth[k])
            return false;
    return true;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    uint8_t *file;
    size_t file_size;
    fuzz_bytes cmds;
    if (!fuzz_split_file(data, size, &file, &file_size, &cmds))
        return 0;
    hpfc_file *f = NULL;
    hpfc_faces *fc = NULL;
    static answers a, b;
    int64_t x[FUZZ_POINTS], y[FUZZ_POINTS];
    uint8_t valid[FUZZ_POINTS];
    if (hpfc_open_memory(file, file_size, HPFC_OPEN_SKIP_CHECKSUM, &f) != HPFC_OK)
        goto done;
    int st = hpfc_faces_build(f, &fc);
    FUZZ_CHECK(fuzz_known_status(st));
    if (st)
        goto done;
    hpfc_file_info info;
    hpfc_file_get_info(f, &info);
    hpfc_features_info fi;
    int feature_status = hpfc_file_get_features(f, &fi);
    int features = feature_status == HPFC_OK;
    size_t n = fuzz_empty(&cmds) ? default_points(&info, x, y, valid)
                                 : command_points(&info, &cmds, x, y, valid);
    hpfc_locate_out out = out_of(&a, 0);
    size_t failed = SIZE_MAX;
    st = hpfc_locate_batch(f, fc, n, x, y, valid, &out, &failed);
    if (!features && feature_status != HPFC_E_NO_SECTION) {
        /* a FEAT section that does not read refuses the whole batch up front */
        FUZZ_CHECK(st == feature_status && failed == SIZE_MAX);
        goto done;
    }
    FUZZ_CHECK(fuzz_known_status(st));
    hpfc_geometry_info gi;
    hpfc_labels_info li;
    bool exact =
        hpfc_file_get_geometry(f, &gi) == HPFC_OK && hpfc_file_get_labels(f, &li) == HPFC_OK;
    if (st) {
        FUZZ_CHECK(failed < n);
        hpfc_locate_out one = out_of(&b, failed);
        FUZZ_CHECK(hpfc_locate_batch(f, fc, 1, x + failed, y + failed, valid + failed, &one,
                                     NULL) == st);
        if (exact) { /* the exact location of that point fails the same way */
            hpfc_point_location loc;
            size_t count;
            FUZZ_CHECK(hpfc_locate_point(f, x[failed], y[failed], &loc, NULL, 0, &count) == st ||
                       st == HPFC_E_NOMEM);
        }
        goto done;
    }
    for (size_t k = 0; k < n; k++) {
        if (exact)
            check_exact(f, &gi, &a, k, x[k], y[k], valid[k]);
        else
            check_answer(f, fc, features, &fi, &a, k, x[k], y[k], valid[k]);
    }
    size_t half = n / 2;
    hpfc_locate_out first = out_of(&b, 0), second = out_of(&b, half);
    FUZZ_CHECK(hpfc_locate_batch(f, fc, half, x, y, valid, &first, NULL) == HPFC_OK);
    FUZZ_CHECK(hpfc_locate_batch(f, fc, n - half, x + half, y + half, valid + half, &second,
                                 NULL) == HPFC_OK);
    FUZZ_CHECK(same_answers(&a, &b, 0, n));
    /* A batch of 64 points or more is answered in Morton order, reusing the
     * last point's leaf and feature answer: each point asked alone (no
     * order, no reuse) answers the same. */
    for (size_t k = 0; k < n && n >= 64; k++) {
        hpfc_locate_out one = out_of(&b, k);
        FUZZ_CHECK(hpfc_locate_batch(f, fc, 1, x + k, y + k, valid + k, &one, NULL) == HPFC_OK);
    }
    FUZZ_CHECK(same_answers(&a, &b, 0, n));
    /* NULL outputs are allowed and change nothing else */
    hpfc_locate_out faces_only = {b.face, NULL, NULL, NULL, NULL, NULL};
    FUZZ_CHECK(hpfc_locate_batch(f, fc, n, x, y, valid, &faces_only, NULL) == HPFC_OK);
    FUZZ_CHECK(same_answers(&a, &b, 0, n));
    /* Stored labels that agree with the numbered faces give the very
     * answers of the numbered faces; any other LABL a known status. */
    hpfc_labels_report report;
    int labels = hpfc_labels_verify(f, fc, &report);
    hpfc_locate_out stored = out_of(&b, 0);
    st = hpfc_locate_batch(f, NULL, n, x, y, valid, &stored, NULL);
    if (labels == HPFC_OK) {
        FUZZ_CHECK(st == HPFC_OK);
        FUZZ_CHECK(same_answers(&a, &b, 0, n));
    } else {
        /* no LABL: refused at the first point inside the domain, if any */
        FUZZ_CHECK(labels == HPFC_E_NO_SECTION ? st == HPFC_E_NO_SECTION || st == HPFC_OK
                                               : fuzz_known_status(st));
    }
done:
    hpfc_faces_free(fc);
    hpfc_close(f);
    free(file);
    return 0;
}
