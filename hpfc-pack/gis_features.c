/*
 * Source features of a GIS pack and the faces they cover (gis_features.h).
 */
#include "gis_features.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "grow.h"

struct gis_features {
    char *key_field;
    char **layer_name;
    uint32_t layers;
    /* features */
    int64_t *fid;
    uint32_t *layer;
    char **key;
    uint32_t n, cap;
    /* rings: ring r is code[ring_start[r] .. ring_start[r + 1]) (ring_code) */
    uint32_t *ring_feature;
    size_t *ring_start;
    size_t rings, cap_rings, cap_ring_start;
    uint8_t *code;
    size_t code_len, cap_code;
};

static char *dup_or_null(const char *s)
{
    return s ? strdup(s) : NULL;
}

gis_features *gis_features_create(const char *key_field)
{
    gis_features *fs = calloc(1, sizeof *fs);
    if (fs && key_field && !(fs->key_field = strdup(key_field))) {
        free(fs);
        return NULL;
    }
    if (fs && !(fs->ring_start = calloc(1, sizeof *fs->ring_start))) {
        free(fs->key_field);
        free(fs);
        return NULL;
    }
    if (fs)
        fs->cap_ring_start = 1; /* ring_start holds rings + 1 entries */
    return fs;
}

void gis_features_free(gis_features *fs)
{
    if (!fs)
        return;
    for (uint32_t l = 0; l < fs->layers; l++)
        free(fs->layer_name[l]);
    for (uint32_t k = 0; k < fs->n; k++)
        free(fs->key[k]);
    free(fs->layer_name);
    free(fs->key_field);
    free(fs->fid);
    free(fs->layer);
    free(fs->key);
    free(fs->ring_feature);
    free(fs->ring_start);
    free(fs->code);
    free(fs);
}

int gis_features_set_layer(gis_features *fs, uint32_t index, const char *name)
{
    if (index >= fs->layers) {
        char **p = realloc(fs->layer_name, ((size_t)index + 1) * sizeof *p);
        if (!p)
            return -1;
        for (uint32_t l = fs->layers; l <= index; l++)
            p[l] = NULL;
        fs->layer_name = p;
        fs->layers = index + 1;
    }
    free(fs->layer_name[index]);
    fs->layer_name[index] = strdup(name ? name : "");
    return fs->layer_name[index] ? 0 : -1;
}

int gis_features_add(gis_features *fs, int64_t fid, uint32_t layer, const char *key)
{
    if (fs->n == UINT32_MAX - 1)
        return -1;
    if (fs->n == fs->cap) {
        uint32_t c = fs->cap ? 2 * fs->cap : 64;
        int64_t *f = realloc(fs->fid, c * sizeof *f);
        if (f)
            fs->fid = f;
        uint32_t *l = realloc(fs->layer, c * sizeof *l);
        if (l)
            fs->layer = l;
        char **k = realloc(fs->key, c * sizeof *k);
        if (k)
            fs->key = k;
        if (!f || !l || !k)
            return -1;
        fs->cap = c;
    }
    char *copy = dup_or_null(key);
    if (key && !copy)
        return -1;
    fs->fid[fs->n] = fid;
    fs->layer[fs->n] = layer;
    fs->key[fs->n] = copy;
    fs->n++;
    return 0;
}

uint32_t gis_features_count(const gis_features *fs)
{
    return fs ? fs->n : 0;
}

/* Ring code: the point count, then each point's x and y as the difference
 * from the point before (the first from 0), zigzag LEB128 varints. Shape
 * points of a ring lie close together, so a point takes 2 to 6 bytes
 * instead of 16: the rings of a continental layer are held from reading
 * until the faces are linked, across the build's peak. Differences wrap
 * modulo 2^64, so every int64 ring decodes exactly. */
enum { VARINT_MAX_BYTES = 10 };

static uint8_t *put_varint(uint8_t *p, uint64_t v)
{
    for (; v >= 0x80; v >>= 7)
        *p++ = (uint8_t)(v | 0x80);
    *p++ = (uint8_t)v;
    return p;
}

static const uint8_t *get_varint(const uint8_t *p, uint64_t *v)
{
    uint64_t x = 0;
    for (int shift = 0;; shift += 7) {
        uint8_t b = *p++;
        x |= (uint64_t)(b & 0x7f) << shift;
        if (!(b & 0x80))
            break;
    }
    *v = x;
    return p;
}

static uint64_t zigzag(uint64_t delta)
{
    return delta << 1 ^ (uint64_t) - (int64_t)(delta >> 63);
}

static uint64_t unzigzag(uint64_t z)
{
    return z >> 1 ^ (uint64_t) - (int64_t)(z & 1);
}

/* Reads a ring's points in order. */
typedef struct ring_cursor {
    const uint8_t *p;
    uint64_t x, y;
    size_t left;
} ring_cursor;

static ring_cursor ring_open(const gis_features *fs, size_t r)
{
    uint64_t n;
    ring_cursor c = {get_varint(fs->code + fs->ring_start[r], &n), 0, 0, 0};
    c.left = (size_t)n;
    return c;
}

static void ring_next(ring_cursor *c, int64_t *x, int64_t *y)
{
    uint64_t dx, dy;
    c->p = get_varint(get_varint(c->p, &dx), &dy);
    c->x += unzigzag(dx), c->y += unzigzag(dy);
    c->left--;
    *x = (int64_t)c->x, *y = (int64_t)c->y;
}

int gis_features_add_ring(gis_features *fs, uint32_t feature, const int64_t *xy, size_t n)
{
    if (n < 3)
        return 0; /* no area */
    if (n > (SIZE_MAX - fs->code_len) / (2 * VARINT_MAX_BYTES) - 1 ||
        !array_grow((void **)&fs->ring_feature, &fs->cap_rings, fs->rings + 1,
                    sizeof *fs->ring_feature) ||
        !array_grow((void **)&fs->ring_start, &fs->cap_ring_start, fs->rings + 2,
                    sizeof *fs->ring_start) ||
        !array_grow((void **)&fs->code, &fs->cap_code,
                    fs->code_len + (n + 1) * 2 * VARINT_MAX_BYTES, 1))
        return -1;
    uint8_t *p = put_varint(fs->code + fs->code_len, n);
    uint64_t px = 0, py = 0;
    for (size_t i = 0; i < n; i++) {
        uint64_t x = (uint64_t)xy[2 * i], y = (uint64_t)xy[2 * i + 1];
        p = put_varint(put_varint(p, zigzag(x - px)), zigzag(y - py));
        px = x, py = y;
    }
    fs->code_len = (size_t)(p - fs->code);
    fs->ring_feature[fs->rings] = feature;
    fs->ring_start[++fs->rings] = fs->code_len;
    return 0;
}

/* Does edge (xi, yi) - (xj, yj) cross the horizontal ray from (x, y)
 * eastward? Half-open in y, so a vertex on the ray counts once. */
static int ray_crosses(int64_t xi_, int64_t yi_, int64_t xj_, int64_t yj_, long double x,
                       long double y)
{
    long double xi = (long double)xi_, yi = (long double)yi_;
    long double xj = (long double)xj_, yj = (long double)yj_;
    return (yi > y) != (yj > y) && x < xi + (xj - xi) * ((y - yi) / (yj - yi));
}

/* Does the ray from (x, y) cross ring r an odd number of times? */
static int ring_holds(const gis_features *fs, size_t r, long double x, long double y)
{
    ring_cursor c = ring_open(fs, r);
    int64_t x0, y0, xp, yp, xq, yq;
    ring_next(&c, &x0, &y0);
    xp = x0, yp = y0;
    int inside = 0;
    while (c.left) {
        ring_next(&c, &xq, &yq);
        inside ^= ray_crosses(xq, yq, xp, yp, x, y);
        xp = xq, yp = yq;
    }
    return inside ^ ray_crosses(x0, y0, xp, yp, x, y); /* the closing edge */
}

#ifdef HPFC_HAVE_GIS

#include <geos_c.h>

typedef struct candidates {
    size_t *ring;
    size_t n, cap;
    int failed;
} candidates;

static void collect(void *item, void *user)
{
    candidates *c = user;
    if (!array_grow((void **)&c->ring, &c->cap, c->n + 1, sizeof *c->ring)) {
        c->failed = 1;
        return;
    }
    c->ring[c->n++] = (size_t)(uintptr_t)item - 1;
}

static int cmp_size(const void *a, const void *b)
{
    size_t x = *(const size_t *)a, y = *(const size_t *)b;
    return (x > y) - (x < y);
}

/* The rings' boxes in an STRtree; their geometries in *boxes (the tree
 * keeps pointers to their envelopes). */
static GEOSSTRtree *ring_index(GEOSContextHandle_t ctx, const gis_features *fs, GEOSGeometry ***boxes)
{
    GEOSSTRtree *tree = GEOSSTRtree_create_r(ctx, 10);
    *boxes = calloc(fs->rings ? fs->rings : 1, sizeof **boxes);
    if (!tree || !*boxes)
        return tree;
    for (size_t r = 0; r < fs->rings; r++) {
        ring_cursor cur = ring_open(fs, r);
        int64_t px, py;
        ring_next(&cur, &px, &py);
        double x0 = (double)px, x1 = x0, y0 = (double)py, y1 = y0;
        while (cur.left) {
            ring_next(&cur, &px, &py);
            double x = (double)px, y = (double)py;
            x0 = x < x0 ? x : x0, x1 = x > x1 ? x : x1;
            y0 = y < y0 ? y : y0, y1 = y > y1 ? y : y1;
        }
        /* one unit of margin: the witness is a long double, the query a double */
        (*boxes)[r] = GEOSGeom_createRectangle_r(ctx, x0 - 1, y0 - 1, x1 + 1, y1 + 1);
        if (!(*boxes)[r])
            return tree;
        GEOSSTRtree_insert_r(ctx, tree, (*boxes)[r], (void *)(uintptr_t)(r + 1));
    }
    return tree;
}

/* A growable list of links. */
typedef struct link_list {
    uint32_t *v;
    size_t n, cap;
} link_list;

/* Appends the features whose rings hold witness w an odd number of times,
 * in ascending order. */
static int face_features(GEOSContextHandle_t ctx, GEOSSTRtree *tree, const gis_features *fs,
                         const face_witness *w, candidates *c, link_list *links)
{
    c->n = 0;
    GEOSGeometry *pt = GEOSGeom_createPointFromXY_r(ctx, (double)w->x, (double)w->y);
    if (!pt)
        return -1;
    GEOSSTRtree_query_r(ctx, tree, pt, collect, c);
    GEOSGeom_destroy_r(ctx, pt);
    if (c->failed ||
        !array_grow((void **)&links->v, &links->cap, links->n + c->n, sizeof *links->v))
        return -1;
    if (c->n > 1)
        qsort(c->ring, c->n, sizeof *c->ring, cmp_size); /* rings, hence features, in order */
    for (size_t i = 0; i < c->n;) {
        uint32_t feature = fs->ring_feature[c->ring[i]];
        int odd = 0;
        for (; i < c->n && fs->ring_feature[c->ring[i]] == feature; i++)
            odd ^= ring_holds(fs, c->ring[i], w->x, w->y);
        if (odd)
            links->v[links->n++] = feature;
    }
    return 0;
}

static void free_index(GEOSContextHandle_t ctx, GEOSSTRtree *tree, GEOSGeometry **boxes, size_t n)
{
    if (tree)
        GEOSSTRtree_destroy_r(ctx, tree);
    for (size_t r = 0; boxes && r < n; r++)
        if (boxes[r])
            GEOSGeom_destroy_r(ctx, boxes[r]);
    free(boxes);
}

int gis_feature_table_make(const gis_features *fs, const face_witness *w, uint64_t faces,
                           gis_feature_table *out, char *err, size_t err_len)
{
    memset(out, 0, sizeof *out);
    if (faces >= UINT32_MAX) {
        snprintf(err, err_len, "too many faces (%llu) for a feature table",
                 (unsigned long long)faces);
        return 1;
    }
    GEOSContextHandle_t ctx = GEOS_init_r();
    GEOSGeometry **boxes = NULL;
    GEOSSTRtree *tree = ctx ? ring_index(ctx, fs, &boxes) : NULL;
    candidates c = {0};
    link_list links = {0};
    int st = tree && boxes && (fs->rings == 0 || boxes[fs->rings - 1]) ? 0 : -1;
    out->face_start = calloc(faces + 1, sizeof *out->face_start);
    if (!out->face_start)
        st = -1;
    for (uint64_t f = 0; f < faces && !st; f++) {
        if (links.n >= UINT32_MAX - fs->n) {
            st = -1;
            break;
        }
        out->face_start[f] = (uint32_t)links.n;
        if (w[f].reach <= 0)
            out->faces_without_witness++;
        else
            st = face_features(ctx, tree, fs, &w[f], &c, &links);
    }
    out->face_feature = links.v;
    if (!st)
        out->face_start[faces] = (uint32_t)links.n;
    free(c.ring);
    free_index(ctx, tree, boxes, fs->rings);
    if (ctx)
        GEOS_finish_r(ctx);
    if (st) {
        gis_feature_table_free(out);
        snprintf(err, err_len, "out of memory linking faces to features");
        return 1;
    }
    out->table = (hpfc_feature_table){
        .feature_count = fs->n, .fid = fs->fid, .layer = fs->layer, .key_field = fs->key_field,
        .key = fs->key_field ? (const char *const *)fs->key : NULL, .layer_count = fs->layers,
        .layer_name = (const char *const *)fs->layer_name, .face_count = (uint32_t)faces,
        .face_start = out->face_start, .face_feature = out->face_feature};
    return 0;
}

#else /* !HPFC_HAVE_GIS */

int gis_feature_table_make(const gis_features *fs, const face_witness *w, uint64_t faces,
                           gis_feature_table *out, char *err, size_t err_len)
{
    (void)fs;
    (void)w;
    (void)faces;
    (void)ring_holds;
    memset(out, 0, sizeof *out);
    snprintf(err, err_len, "GIS features need GEOS, not built in");
    return 1;
}

#endif

void gis_feature_table_free(gis_feature_table *t)
{
    free(t->face_start);
    free(t->face_feature);
    memset(t, 0, sizeof *t);
}

int gis_features_link(const gis_features *fs, const hpfc_graph *graph, const leaf_crossings *lc,
                      const hpfc_file *file, gis_feature_table *out, char *err, size_t err_len)
{
    hpfc_faces *faces = NULL;
    face_witness *w = NULL;
    int st = hpfc_faces_build(file, &faces);
    uint64_t n = faces ? hpfc_faces_count(faces) : 0;
    if (!st && !(w = malloc((n ? n : 1) * sizeof *w)))
        st = HPFC_E_NOMEM;
    if (!st)
        st = face_witnesses(graph, lc, file, faces, w);
    if (st)
        snprintf(err, err_len, "internal error: cannot find the faces' features (%s)",
                 hpfc_strerror(st));
    else if (gis_feature_table_make(fs, w, n, out, err, err_len) != 0)
        st = 1;
    free(w);
    hpfc_faces_free(faces);
    return st ? 1 : 0;
}
