/*
 * Batch point location (hpfc_batch.h): the public calls of one point
 * location, strung together over an array so that a binding crosses into C
 * once per array. A file with exact geometry goes through the code of
 * hpfc_locate_point (locate_point.c) with one scratch for the whole array;
 * no format knowledge lives here.
 */
#include <stdlib.h>
#include <string.h>

#include "hpfc_batch.h"
#include "locate_point.h"

/* Growable scratch for one point's candidate faces and features. */
typedef struct batch_scratch {
    uint64_t *faces;
    size_t face_cap;
    uint32_t *features;
    size_t feature_cap;
    int exact;              /* the file has GEOM and LABL: locx answers */
    locx_scratch locx;
} batch_scratch;

static int grow(void **p, size_t *cap, size_t n, size_t size)
{
    if (n <= *cap)
        return HPFC_OK;
    size_t want = *cap ? *cap : 16;
    while (want < n)
        want *= 2;
    void *q = realloc(*p, want * size);
    if (!q)
        return HPFC_E_NOMEM;
    *p = q;
    *cap = want;
    return HPFC_OK;
}

/* Sorts a short list in place and drops repeats; returns the new length.
 * Candidate lists are a leaf's crossings: a handful, so insertion sort. */
static size_t unique_u64(uint64_t *v, size_t n)
{
    for (size_t i = 1; i < n; i++) {
        uint64_t t = v[i];
        size_t j = i;
        for (; j > 0 && v[j - 1] > t; j--)
            v[j] = v[j - 1];
        v[j] = t;
    }
    size_t u = 0;
    for (size_t i = 0; i < n; i++)
        if (u == 0 || v[u - 1] != v[i])
            v[u++] = v[i];
    return u;
}

static size_t unique_u32(uint32_t *v, size_t n)
{
    for (size_t i = 1; i < n; i++) {
        uint32_t t = v[i];
        size_t j = i;
        for (; j > 0 && v[j - 1] > t; j--)
            v[j] = v[j - 1];
        v[j] = t;
    }
    size_t u = 0;
    for (size_t i = 0; i < n; i++)
        if (u == 0 || v[u - 1] != v[i])
            v[u++] = v[i];
    return u;
}

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
            (st = grow((void **)&s->faces, &s->face_cap, count ? count : 1, sizeof *s->faces)) ||
            (st = hpfc_label_leaf_faces(f, px, s->faces, s->face_cap, &count)))
            return st;
        *n = unique_u64(s->faces, count);
        return HPFC_OK;
    }
    if (*is_private) {
        if ((st = grow((void **)&s->faces, &s->face_cap, 1, sizeof *s->faces)))
            return st;
        *n = 1;
        return hpfc_faces_of_private_pixel(fc, px, &s->faces[0]);
    }
    size_t len;
    if ((st = hpfc_pixel_word(f, px, NULL, 0, &len)))
        return st;
    if (len < 4)
        return HPFC_E_CORRUPT;
    size_t crossings = len - 4; /* a word of c crossings has c + 4 symbols */
    if ((st = grow((void **)&s->faces, &s->face_cap, crossings ? crossings : 1,
                   sizeof *s->faces)))
        return st;
    for (size_t k = 0; k < crossings; k++) {
        hpfc_dart d = {.pixel = *px, .crossing = (uint32_t)k};
        if ((st = hpfc_faces_of_dart(fc, &d, &s->faces[k])))
            return st;
    }
    *n = unique_u64(s->faces, crossings);
    return HPFC_OK;
}

/* The distinct features of faces[0..n), into s->features; count in *m.
 * *sure: every face links exactly one feature, the same one, so the point
 * lies in it whichever candidate face holds it. */
static int leaf_features(const hpfc_file *f, batch_scratch *s, size_t n, size_t *m, int *sure)
{
    size_t total = 0;
    *sure = n > 0;
    for (size_t k = 0; k < n; k++) {
        uint32_t count;
        int st = hpfc_face_feature_count(f, s->faces[k], &count);
        if (!st)
            st = grow((void **)&s->features, &s->feature_cap, total + count, sizeof *s->features);
        for (uint32_t i = 0; i < count && !st; i++)
            st = hpfc_face_feature(f, s->faces[k], i, &s->features[total++]);
        if (st)
            return st;
        if (count != 1 || s->features[total - 1] != s->features[0])
            *sure = 0;
    }
    *m = unique_u32(s->features, total);
    return HPFC_OK;
}

static void answer_outside(const hpfc_locate_out *o, size_t k)
{
    if (o->face)
        o->face[k] = -1;
    if (o->face_count)
        o->face_count[k] = 0;
    if (o->feature)
        o->feature[k] = -1;
    if (o->feature_count)
        o->feature_count[k] = 0;
    if (o->flags)
        o->flags[k] = 0;
    if (o->depth)
        o->depth[k] = 0;
}

/* The exact answer: the point's face, or the faces around it on the
 * boundary, into s->faces. */
static int exact_faces(const hpfc_file *f, int64_t x, int64_t y, hpfc_pixel *px,
                       int *is_private, int *on_boundary, batch_scratch *s, size_t *n)
{
    hpfc_point_location loc;
    int st = locx_locate(f, x, y, &s->locx, &loc, NULL, 0, n);
    if (!st)
        st = grow((void **)&s->faces, &s->face_cap, *n ? *n : 1, sizeof *s->faces);
    if (st)
        return st;
    memcpy(s->faces, s->locx.around, *n * sizeof *s->faces); /* where locx keeps them */
    *px = loc.leaf;
    *is_private = s->locx.labels.rec.word.n == 0;
    *on_boundary = loc.on_boundary;
    return HPFC_OK;
}

static int answer_point(const hpfc_file *f, const hpfc_faces *fc, int features, int64_t x,
                        int64_t y, const hpfc_locate_out *o, size_t k, batch_scratch *s)
{
    hpfc_pixel px;
    int is_private = 0, sure = 0, on_boundary = 0;
    size_t n = 0, m = 0;
    int st = s->exact ? exact_faces(f, x, y, &px, &is_private, &on_boundary, s, &n)
                      : hpfc_locate(f, x, y, &px);
    if (st == HPFC_E_NO_PIXEL) {
        answer_outside(o, k);
        return HPFC_OK;
    }
    if (!st && !s->exact)
        st = leaf_faces(f, fc, &px, &is_private, s, &n);
    if (!st && features && (o->feature || o->feature_count))
        st = leaf_features(f, s, n, &m, &sure);
    if (st)
        return st;
    if (o->face)
        o->face[k] = n == 1 ? (int64_t)s->faces[0] : -1;
    if (o->face_count)
        o->face_count[k] = (uint32_t)n;
    if (o->feature)
        o->feature[k] = sure ? (int64_t)s->features[0] : -1;
    if (o->feature_count)
        o->feature_count[k] = (uint32_t)m;
    if (o->flags)
        o->flags[k] = (uint8_t)(HPFC_LOC_INSIDE | (is_private ? HPFC_LOC_PRIVATE : 0) |
                                (n == 1 ? HPFC_LOC_SINGLE : 0) |
                                (s->exact ? HPFC_LOC_EXACT : 0) |
                                (on_boundary ? HPFC_LOC_BOUNDARY : 0));
    if (o->depth)
        o->depth[k] = (uint8_t)px.depth;
    return HPFC_OK;
}

int hpfc_locate_batch(const hpfc_file *file, const hpfc_faces *faces, size_t n, const int64_t *x,
                      const int64_t *y, const uint8_t *valid, const hpfc_locate_out *out,
                      size_t *failed)
{
    if (!file || !out || (n && (!x || !y)))
        return HPFC_E_ARG;
    hpfc_features_info fi;
    int st = hpfc_file_features(file, &fi);
    int features = st == HPFC_OK;
    if (st && st != HPFC_E_NO_SECTION)
        return st;
    batch_scratch s = {0};
    hpfc_geometry_info gi;
    hpfc_labels_info li;
    s.exact = hpfc_file_geometry(file, &gi) == HPFC_OK && hpfc_file_labels(file, &li) == HPFC_OK;
    st = HPFC_OK;
    for (size_t k = 0; k < n && !st; k++) {
        if (valid && !valid[k])
            answer_outside(out, k);
        else if ((st = answer_point(file, faces, features, x[k], y[k], out, k, &s)) && failed)
            *failed = k;
    }
    free(s.faces);
    free(s.features);
    locx_scratch_free(&s.locx);
    return st;
}
