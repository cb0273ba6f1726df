/*
 * Batch point location (hpfc_batch.h): the public calls of one point
 * location, strung together over an array so that a binding crosses into C
 * once per array. A file with exact geometry goes through the code of
 * hpfc_locate_point (locate_point.c) with one scratch for the whole array,
 * in space-filling-curve order so that the locator's last leaf answers
 * most points; no format knowledge lives here.
 */
#include <stdlib.h>
#include <string.h>

#include "file.h"
#include "hpfc_batch.h"
#include "locate_point.h"
#include "arrays.h"
#include "sized.h"

/* Growable scratch for one point's candidate faces and features. */
typedef struct batch_scratch {
    hpfc_id *faces;
    size_t face_cap;
    hpfc_id *features;
    size_t feature_cap;
    int exact;              /* the file has GEOM and LABL: locx answers */
    locx_scratch locx;
    /* features[0 .. feature_m) answer the one face feature_face (valid
     * when have_face_features): the next point in that face reuses them */
    int have_face_features, feature_sure;
    uint64_t feature_face;
    size_t feature_m;
} batch_scratch;

/* The faces meeting leaf px, each once, into s->faces; their number in *n. */
static int leaf_faces(const hpfc_file *f, const hpfc_faces *fc, const hpfc_pixel *px,
                      int *is_private, batch_scratch *s, size_t *n)
{
    int st = hpfc_pixel_is_private(f, px, is_private);
    if (st)
        return st;
    if (!fc) { /* the stored labels: the faces of the leaf's regions */
        size_t count;
        if ((st = hpfc_label_leaf_faces(f, px, NULL, 0, &count)) ||
            (st = array_grow((void **)&s->faces, &s->face_cap, count ? count : 1,
                               sizeof *s->faces)) ||
            (st = hpfc_label_leaf_faces(f, px, s->faces, s->face_cap, &count)))
            return st;
        *n = scratch_sort_unique(s->faces, count);
        return HPFC_OK;
    }
    if (*is_private) {
        if ((st = array_grow((void **)&s->faces, &s->face_cap, 1, sizeof *s->faces)))
            return st;
        *n = 1;
        return hpfc_faces_pixel_face(fc, px, &s->faces[0]);
    }
    size_t len;
    if ((st = hpfc_pixel_word(f, px, NULL, 0, &len)))
        return st;
    if (len < 4)
        return HPFC_E_CORRUPT;
    size_t crossings = len - 4; /* a word of c crossings has c + 4 symbols */
    if ((st = array_grow((void **)&s->faces, &s->face_cap, crossings ? crossings : 1,
                   sizeof *s->faces)))
        return st;
    for (size_t k = 0; k < crossings; k++) {
        hpfc_dart d = {.pixel = *px, .crossing = (uint32_t)k};
        if ((st = hpfc_faces_dart_face(fc, &d, &s->faces[k])))
            return st;
    }
    *n = scratch_sort_unique(s->faces, crossings);
    return HPFC_OK;
}

/* The distinct features of faces[0..n), into s->features; count in *m.
 * *sure: every face links exactly one feature, the same one, so the point
 * lies in it whichever candidate face holds it. */
static int leaf_features(const hpfc_file *f, batch_scratch *s, size_t n, size_t *m, int *sure)
{
    if (n == 1 && s->have_face_features && s->feature_face == s->faces[0]) {
        *m = s->feature_m;
        *sure = s->feature_sure;
        return HPFC_OK;
    }
    s->have_face_features = 0;
    size_t total = 0;
    *sure = n > 0;
    for (size_t k = 0; k < n; k++) {
        uint32_t count;
        int st = hpfc_face_feature_count(f, s->faces[k], &count);
        if (!st)
            st = array_grow((void **)&s->features, &s->feature_cap, total + count,
                              sizeof *s->features);
        for (uint32_t i = 0; i < count && !st; i++)
            st = hpfc_face_feature_id(f, s->faces[k], i, &s->features[total++]);
        if (st)
            return st;
        if (count != 1 || s->features[total - 1] != s->features[0])
            *sure = 0;
    }
    *m = scratch_sort_unique(s->features, total);
    if (n == 1) {
        s->have_face_features = 1;
        s->feature_face = s->faces[0];
        s->feature_m = *m;
        s->feature_sure = *sure;
    }
    return HPFC_OK;
}

/* One point's answer: a row of hpfc_locate_out. */
typedef struct point_answer {
    int64_t face, feature;
    uint32_t face_count, feature_count;
    uint8_t flags, depth;
} point_answer;

/* A point outside the domain, or skipped by `valid` (hpfc_batch.h). */
static const point_answer answer_outside = {.face = -1, .feature = -1};

/* Row k of the outputs the caller wants: one line per optional output of
 * hpfc_locate_out, all of one shape (they differ in their column only). */
static void put_answer(const hpfc_locate_out *o, size_t k, const point_answer *a)
{
    if (o->face)
        o->face[k] = a->face;
    if (o->face_count)
        o->face_count[k] = a->face_count;
    if (o->feature)
        o->feature[k] = a->feature;
    if (o->feature_count)
        o->feature_count[k] = a->feature_count;
    if (o->flags)
        o->flags[k] = a->flags;
    if (o->depth)
        o->depth[k] = a->depth;
}

/* The exact answer: the point's face, or the faces around it on the
 * boundary, into s->faces. */
static int exact_faces(const hpfc_file *f, int64_t x, int64_t y, uint32_t *depth,
                       int *is_private, int *on_boundary, batch_scratch *s, size_t *n)
{
    locx_answer a;
    int st = locx_locate(f, x, y, &s->locx, &a, n);
    if (!st)
        st = array_grow((void **)&s->faces, &s->face_cap, *n ? *n : 1, sizeof *s->faces);
    if (st)
        return st;
    memcpy(s->faces, s->locx.around, *n * sizeof *s->faces); /* where locx keeps them */
    *depth = s->locx.leaf.depth;
    *is_private = s->locx.labels.rec.word.n == 0;
    *on_boundary = a.on_boundary;
    return HPFC_OK;
}

static int answer_point(const hpfc_file *f, const hpfc_faces *fc, int features, int64_t x,
                        int64_t y, const hpfc_locate_out *o, size_t k, batch_scratch *s)
{
    hpfc_pixel px; /* without exact geometry */
    uint32_t depth = 0;
    int is_private = 0, sure = 0, on_boundary = 0;
    size_t n = 0, m = 0;
    int st = s->exact ? exact_faces(f, x, y, &depth, &is_private, &on_boundary, s, &n)
                      : hpfc_locate(f, x, y, &px);
    if (st == HPFC_E_NO_PIXEL) {
        put_answer(o, k, &answer_outside);
        return HPFC_OK;
    }
    if (!st && !s->exact) {
        depth = px.depth;
        st = leaf_faces(f, fc, &px, &is_private, s, &n);
    }
    if (!st && features && (o->feature || o->feature_count))
        st = leaf_features(f, s, n, &m, &sure);
    if (st)
        return st;
    point_answer a = {
        .face = n == 1 ? (int64_t)s->faces[0] : -1,
        .face_count = (uint32_t)n,
        .feature = sure ? (int64_t)s->features[0] : -1,
        .feature_count = (uint32_t)m,
        .flags = (uint8_t)(HPFC_LOC_INSIDE | (is_private ? HPFC_LOC_PRIVATE : 0) |
                           (n == 1 ? HPFC_LOC_SINGLE : 0) | (s->exact ? HPFC_LOC_EXACT : 0) |
                           (on_boundary ? HPFC_LOC_BOUNDARY : 0)),
        .depth = (uint8_t)depth};
    put_answer(o, k, &a);
    return HPFC_OK;
}

/* ---- space-filling-curve order ------------------------------------------------------ */

/* Points are answered chunk by chunk in Morton order of their position in
 * the domain, so that consecutive points mostly share their leaf (the
 * exact locator then reuses it whole) or most of their descent. The order
 * changes no answer: each point's is computed on its own. */
enum { ORDER_CHUNK = 1u << 18, ORDER_MIN = 64 };

/* Interleaves the low 16 bits of x (even bits) and y (odd bits). */
static uint32_t morton16(uint32_t x, uint32_t y)
{
    uint64_t v = (uint64_t)(x & 0xFFFF) | (uint64_t)(y & 0xFFFF) << 32;
    v = (v | v << 8) & 0x00FF00FF00FF00FFull;
    v = (v | v << 4) & 0x0F0F0F0F0F0F0F0Full;
    v = (v | v << 2) & 0x3333333333333333ull;
    v = (v | v << 1) & 0x5555555555555555ull;
    return (uint32_t)(v | v >> 31);
}

/* A point's key: its cell on a 65536 x 65536 grid over the domain;
 * points outside it clamp to the grid's edge (they answer at once). */
static uint32_t order_key(const hpfc_file_info *fi, unsigned shift, int64_t x, int64_t y)
{
    uint64_t rx = x < fi->x0 ? 0 : (uint64_t)x - (uint64_t)fi->x0;
    uint64_t ry = y < fi->y0 ? 0 : (uint64_t)y - (uint64_t)fi->y0;
    rx >>= shift, ry >>= shift;
    return morton16((uint32_t)(rx > 0xFFFF ? 0xFFFF : rx), (uint32_t)(ry > 0xFFFF ? 0xFFFF : ry));
}

/* The shift that maps the domain's larger side below 2^16. */
static unsigned order_shift(const hpfc_file_info *fi)
{
    uint64_t side = (uint64_t)(fi->width > fi->height ? fi->width : fi->height);
    unsigned shift = 0;
    while (shift < 63 && (side - 1) >> shift > 0xFFFF)
        shift++;
    return shift;
}

/* Answers points [first, first + n) in input order. */
static int answer_in_order(const hpfc_file *file, const hpfc_faces *faces, int features,
                           size_t first, size_t n, const int64_t *x, const int64_t *y,
                           const uint8_t *valid, const hpfc_locate_out *out, size_t *failed,
                           batch_scratch *s)
{
    int st = HPFC_OK;
    for (size_t k = first; k < first + n && !st; k++) {
        if (valid && !valid[k])
            put_answer(out, k, &answer_outside);
        else if ((st = answer_point(file, faces, features, x[k], y[k], out, k, s)) && failed)
            *failed = k;
    }
    return st;
}

/* A chunk's buffers in Morton order: the points gathered, their answers
 * (scattered back to the caller's arrays afterwards). Gathering and
 * scattering in passes of their own keeps the answering loop on
 * sequential memory; the CPU overlaps the passes' cache misses. */
typedef struct order_buf {
    key_item *items, *tmp; /* key: Morton code of 16-bit cell coordinates; index in the chunk */
    int64_t *x, *y, *face, *feature;
    uint32_t *face_count, *feature_count;
    uint8_t *valid, *flags, *depth;
} order_buf;

static void order_free(order_buf *b)
{
    free(b->items), free(b->tmp), free(b->x), free(b->y), free(b->face), free(b->feature);
    free(b->face_count), free(b->feature_count), free(b->valid), free(b->flags), free(b->depth);
}

static int order_alloc(order_buf *b, size_t n)
{
    *b = (order_buf){0};
    b->items = malloc(n * sizeof *b->items), b->tmp = malloc(n * sizeof *b->tmp);
    b->x = malloc(n * sizeof *b->x), b->y = malloc(n * sizeof *b->y);
    b->face = malloc(n * sizeof *b->face), b->feature = malloc(n * sizeof *b->feature);
    b->face_count = malloc(n * sizeof *b->face_count);
    b->feature_count = malloc(n * sizeof *b->feature_count);
    b->valid = malloc(n), b->flags = malloc(n), b->depth = malloc(n);
    if (b->items && b->tmp && b->x && b->y && b->face && b->feature && b->face_count &&
        b->feature_count && b->valid && b->flags && b->depth)
        return 0;
    order_free(b);
    return -1;
}

/* Answers a chunk in Morton order; 1 on a failure, and then the caller
 * answers the chunk again in input order, which names the first failing
 * point and fills the answers before it, as the contract says. */
static int answer_sorted(const hpfc_file *file, const hpfc_faces *faces, int features,
                         size_t first, size_t n, const int64_t *x, const int64_t *y,
                         const uint8_t *valid, const hpfc_locate_out *out, order_buf *b,
                         batch_scratch *s)
{
    hpfc_file_info fi;
    hpfc_file_get_info(file, &fi);
    unsigned shift = order_shift(&fi);
    for (size_t k = 0; k < n; k++)
        b->items[k] = (key_item){order_key(&fi, shift, x[first + k], y[first + k]), (uint32_t)k};
    key_sort(b->items, b->tmp, n);
    for (size_t i = 0; i < n; i++) {
        size_t k = first + b->items[i].index;
        b->x[i] = x[k], b->y[i] = y[k], b->valid[i] = valid ? valid[k] != 0 : 1;
    }
    const hpfc_locate_out sorted = {b->face, b->face_count, b->feature, b->feature_count,
                                    b->flags, b->depth};
    for (size_t i = 0; i < n; i++) {
        if (!b->valid[i])
            put_answer(&sorted, i, &answer_outside);
        else if (answer_point(file, faces, features, b->x[i], b->y[i], &sorted, i, s))
            return 1;
    }
    for (size_t i = 0; i < n; i++) {
        point_answer a = {.face = b->face[i],
                          .face_count = b->face_count[i],
                          .feature = b->feature[i],
                          .feature_count = b->feature_count[i],
                          .flags = b->flags[i],
                          .depth = b->depth[i]};
        put_answer(out, first + b->items[i].index, &a);
    }
    return 0;
}

int hpfc_locate_batch_sized(const hpfc_file *file, const hpfc_faces *faces, size_t n,
                            const int64_t *x, const int64_t *y, const uint8_t *valid,
                            const hpfc_locate_out *out_arg, size_t out_size, size_t *failed)
{
    hpfc_locate_out full = {0}; /* outputs an older caller does not have: not wanted */
    const hpfc_locate_out *out = &full;
    if (!file || !out_arg || (n && (!x || !y)) ||
        sized_in(&full, sizeof full, out_arg, out_size))
        return HPFC_E_ARG;
    hpfc_features_info fi;
    int st = hpfc_file_get_features(file, &fi);
    int features = st == HPFC_OK;
    if (st && st != HPFC_E_NO_SECTION)
        return st;
    batch_scratch s = {0};
    s.exact = file_has_exact_geometry(file);
    /* the exact locator reuses leaves: worth an order when points are many
     * (without memory for it, input order gives the same answers) */
    size_t chunk = n < ORDER_CHUNK ? n : ORDER_CHUNK;
    order_buf b = {0};
    int sorted = s.exact && n >= ORDER_MIN && order_alloc(&b, chunk) == 0;
    st = HPFC_OK;
    for (size_t first = 0; first < n && !st; first += chunk) {
        size_t m = n - first < chunk ? n - first : chunk;
        if (!sorted || answer_sorted(file, faces, features, first, m, x, y, valid, out, &b, &s))
            st = answer_in_order(file, faces, features, first, m, x, y, valid, out, failed, &s);
    }
    if (sorted)
        order_free(&b);
    free(s.faces);
    free(s.features);
    locx_scratch_free(&s.locx);
    return st;
}
