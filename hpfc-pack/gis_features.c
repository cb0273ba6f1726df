/*
 * Source features of a GIS pack and the faces they cover (gis_features.h).
 */
#include "gis_features.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <time.h>

#ifdef HPFC_HAVE_GIS
#include <geos_c.h>
#endif

/* Seconds since *t, which moves on to now. */
static double lap_seconds(struct timespec *t)
{
    struct timespec now;
    clock_gettime(CLOCK_MONOTONIC, &now);
    double d = (double)(now.tv_sec - t->tv_sec) + (double)(now.tv_nsec - t->tv_nsec) * 1e-9;
    *t = now;
    return d;
}

#include "face_link.h"
#include "grow.h"

struct gis_features {
    char *key_field;
    char **layer_name;
    uint32_t layers;
    /* features */
    int64_t *fid, *source_fid;
    uint32_t *layer;
    char **key;
    uint32_t n, cap;
    /* parts: part r is code[ring_start[r] .. ring_start[r + 1]) (ring code),
       a ring of its feature's area when ring_closed[r] */
    uint32_t *ring_feature;
    uint8_t *ring_closed;
    size_t *ring_start;
    size_t rings, cap_rings, cap_ring_start, cap_closed;
    uint8_t *code;
    size_t code_len, cap_code;
    /* segments GEOS re-noded (x0, y0, x1, y1 quads, sorted), or all of them */
    int64_t *noded;
    size_t n_noded;
    int noded_all;
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
    free(fs->source_fid);
    free(fs->layer);
    free(fs->ring_closed);
    free(fs->noded);
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

int gis_features_add(gis_features *fs, int64_t fid, int64_t source_fid, uint32_t layer,
                     const char *key)
{
    if (fs->n >= UINT32_MAX / 2)
        return -1;
    if (fs->n == fs->cap) {
        uint32_t c = fs->cap ? 2 * fs->cap : 64;
        int64_t *f = realloc(fs->fid, c * sizeof *f);
        if (f)
            fs->fid = f;
        int64_t *sf = realloc(fs->source_fid, c * sizeof *sf);
        if (sf)
            fs->source_fid = sf;
        uint32_t *l = realloc(fs->layer, c * sizeof *l);
        if (l)
            fs->layer = l;
        char **k = realloc(fs->key, c * sizeof *k);
        if (k)
            fs->key = k;
        if (!f || !sf || !l || !k)
            return -1;
        fs->cap = c;
    }
    char *copy = dup_or_null(key);
    if (key && !copy)
        return -1;
    fs->fid[fs->n] = fid;
    fs->source_fid[fs->n] = source_fid;
    fs->layer[fs->n] = layer;
    fs->key[fs->n] = copy;
    fs->n++;
    return 0;
}

uint32_t gis_features_count(const gis_features *fs)
{
    return fs ? fs->n : 0;
}

int64_t gis_features_source_fid(const gis_features *fs, uint32_t k)
{
    return fs->source_fid[k];
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

typedef gis_part_cursor ring_cursor;

static ring_cursor ring_open(const gis_features *fs, size_t r)
{
    uint64_t n;
    ring_cursor c = {get_varint(fs->code + fs->ring_start[r], &n), 0, 0, 0};
    c.left = (size_t)n;
    return c;
}

size_t gis_features_part_count(const gis_features *fs)
{
    return fs->rings;
}

gis_part_cursor gis_features_part_open(const gis_features *fs, size_t r, uint32_t *feature,
                                       int *ring)
{
    *feature = fs->ring_feature[r];
    *ring = fs->ring_closed[r];
    return ring_open(fs, r);
}

#define ring_next gis_part_next

void gis_part_next(ring_cursor *c, int64_t *x, int64_t *y)
{
    uint64_t dx, dy;
    c->p = get_varint(get_varint(c->p, &dx), &dy);
    c->x += unzigzag(dx), c->y += unzigzag(dy);
    c->left--;
    *x = (int64_t)c->x, *y = (int64_t)c->y;
}

int gis_features_add_part(gis_features *fs, uint32_t feature, int ring, const int64_t *xy,
                          size_t n)
{
    if (n < (ring ? 3u : 2u))
        return 0; /* no area, no segment */
    if (n > (SIZE_MAX - fs->code_len) / (2 * VARINT_MAX_BYTES) - 1 ||
        !array_grow((void **)&fs->ring_feature, &fs->cap_rings, fs->rings + 1,
                    sizeof *fs->ring_feature) ||
        !array_grow((void **)&fs->ring_closed, &fs->cap_closed, fs->rings + 1,
                    sizeof *fs->ring_closed) ||
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
    fs->ring_closed[fs->rings] = ring != 0;
    fs->ring_start[++fs->rings] = fs->code_len;
    return 0;
}

int gis_features_set_noded(gis_features *fs, const int64_t *segs, size_t n, int all)
{
    free(fs->noded);
    fs->noded = NULL;
    fs->n_noded = 0;
    fs->noded_all = all;
    if (all || n == 0)
        return 0;
    if (n > SIZE_MAX / (4 * sizeof *segs) || !(fs->noded = malloc(n * 4 * sizeof *segs)))
        return -1;
    memcpy(fs->noded, segs, n * 4 * sizeof *segs);
    fs->n_noded = n;
    return 0;
}

static int cmp_quad(const int64_t *a, const int64_t *b)
{
    for (int k = 0; k < 4; k++)
        if (a[k] != b[k])
            return a[k] < b[k] ? -1 : 1;
    return 0;
}

int gis_features_segment_noded(const gis_features *fs, int64_t ax, int64_t ay, int64_t bx,
                               int64_t by)
{
    if (fs->noded_all)
        return 1;
    const int64_t key[4] = {ax, ay, bx, by};
    size_t lo = 0, hi = fs->n_noded;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        int c = cmp_quad(key, fs->noded + 4 * mid);
        if (c == 0)
            return 1;
        if (c < 0)
            hi = mid;
        else
            lo = mid + 1;
    }
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

/* The box of part r: x0, y0, x1, y1. */
static void part_box(const gis_features *fs, size_t r, int64_t box[4])
{
    ring_cursor cur = ring_open(fs, r);
    int64_t px, py;
    ring_next(&cur, &px, &py);
    box[0] = box[2] = px, box[1] = box[3] = py;
    while (cur.left) {
        ring_next(&cur, &px, &py);
        box[0] = px < box[0] ? px : box[0], box[2] = px > box[2] ? px : box[2];
        box[1] = py < box[1] ? py : box[1], box[3] = py > box[3] ? py : box[3];
    }
}

/* A growable list of links. */
typedef struct link_list {
    uint32_t *v;
    size_t n, cap;
} link_list;

/* Appends to links the features whose rings, among candidates ring[0..n)
 * (ascending), hold witness w an odd number of times, in ascending order. */
static int odd_features(const gis_features *fs, const size_t *ring, size_t n, const face_witness *w,
                        link_list *links)
{
    if (!array_grow((void **)&links->v, &links->cap, links->n + n + 1, sizeof *links->v))
        return -1;
    for (size_t i = 0; i < n;) {
        uint32_t feature = fs->ring_feature[ring[i]];
        int odd = 0;
        for (; i < n && fs->ring_feature[ring[i]] == feature; i++)
            odd ^= ring_holds(fs, ring[i], w->x, w->y);
        if (odd)
            links->v[links->n++] = feature;
    }
    return 0;
}

/* Finds the rings around witness points: by a scan of the rings' boxes for
 * a few anchors, by a GEOS STRtree for many. */
typedef struct ring_finder {
    const gis_features *fs;
    int64_t *box; /* 4 per part; lines get an empty box */
    size_t *ring;
    size_t n, cap;
    int failed;
#ifdef HPFC_HAVE_GIS
    GEOSContextHandle_t ctx;
    GEOSSTRtree *tree;
    GEOSGeometry **boxes;
#endif
} ring_finder;


static int scan_boxes(ring_finder *rf, const face_witness *w)
{
    const gis_features *fs = rf->fs;
    if (!rf->box) {
        if (!(rf->box = malloc((fs->rings ? fs->rings : 1) * 4 * sizeof *rf->box)))
            return -1;
        for (size_t r = 0; r < fs->rings; r++)
            if (fs->ring_closed[r])
                part_box(fs, r, rf->box + 4 * r);
            else
                rf->box[4 * r] = 1, rf->box[4 * r + 2] = 0; /* empty */
    }
    rf->n = 0;
    for (size_t r = 0; r < fs->rings; r++) {
        const int64_t *b = rf->box + 4 * r;
        /* one unit of margin: the witness lies within a unit of the lattice */
        if (w->x >= (long double)b[0] - 1 && w->x <= (long double)b[2] + 1 &&
            w->y >= (long double)b[1] - 1 && w->y <= (long double)b[3] + 1) {
            if (!array_grow((void **)&rf->ring, &rf->cap, rf->n + 1, sizeof *rf->ring))
                return -1;
            rf->ring[rf->n++] = r;
        }
    }
    return 0;
}

#ifdef HPFC_HAVE_GIS

static void collect(void *item, void *user)
{
    ring_finder *c = user;
    if (!array_grow((void **)&c->ring, &c->cap, c->n + 1, sizeof *c->ring)) {
        c->failed = 1;
        return;
    }
    c->ring[c->n++] = (size_t)(uintptr_t)item - 1;
}

/* The rings' boxes in an STRtree; their geometries in rf->boxes (the tree
 * keeps pointers to their envelopes). */
static int ring_index(ring_finder *rf)
{
    const gis_features *fs = rf->fs;
    if (!(rf->ctx = GEOS_init_r()) || !(rf->tree = GEOSSTRtree_create_r(rf->ctx, 10)) ||
        !(rf->boxes = calloc(fs->rings ? fs->rings : 1, sizeof *rf->boxes)))
        return -1;
    for (size_t r = 0; r < fs->rings; r++) {
        if (!fs->ring_closed[r])
            continue;
        int64_t b[4];
        part_box(fs, r, b);
        /* one unit of margin: the witness is a long double, the query a double */
        rf->boxes[r] = GEOSGeom_createRectangle_r(rf->ctx, (double)b[0] - 1, (double)b[1] - 1,
                                                  (double)b[2] + 1, (double)b[3] + 1);
        if (!rf->boxes[r])
            return -1;
        GEOSSTRtree_insert_r(rf->ctx, rf->tree, rf->boxes[r], (void *)(uintptr_t)(r + 1));
    }
    return 0;
}

static int cmp_size(const void *a, const void *b)
{
    size_t x = *(const size_t *)a, y = *(const size_t *)b;
    return (x > y) - (x < y);
}

static int query_tree(ring_finder *rf, const face_witness *w)
{
    if (!rf->tree && ring_index(rf) != 0)
        return -1;
    rf->n = 0;
    GEOSGeometry *pt = GEOSGeom_createPointFromXY_r(rf->ctx, (double)w->x, (double)w->y);
    if (!pt)
        return -1;
    GEOSSTRtree_query_r(rf->ctx, rf->tree, pt, collect, rf);
    GEOSGeom_destroy_r(rf->ctx, pt);
    if (rf->n > 1)
        qsort(rf->ring, rf->n, sizeof *rf->ring, cmp_size); /* rings, hence features, in order */
    return rf->failed ? -1 : 0;
}

#endif

/* Appends the features whose rings hold witness w an odd number of times. */
static int witness_features(ring_finder *rf, int many, const face_witness *w, link_list *links)
{
#ifdef HPFC_HAVE_GIS
    int st = many ? query_tree(rf, w) : scan_boxes(rf, w);
#else
    (void)many;
    int st = scan_boxes(rf, w);
#endif
    return st ? st : odd_features(rf->fs, rf->ring, rf->n, w, links);
}

static void ring_finder_free(ring_finder *rf)
{
#ifdef HPFC_HAVE_GIS
    if (rf->tree)
        GEOSSTRtree_destroy_r(rf->ctx, rf->tree);
    for (size_t r = 0; rf->boxes && r < rf->fs->rings; r++)
        if (rf->boxes[r])
            GEOSGeom_destroy_r(rf->ctx, rf->boxes[r]);
    free(rf->boxes);
    if (rf->ctx)
        GEOS_finish_r(rf->ctx);
#endif
    free(rf->box);
    free(rf->ring);
}

void gis_feature_table_free(gis_feature_table *t)
{
    free(t->face_start);
    free(t->face_feature);
    free(t->edge_start);
    free(t->edge_feature);
    memset(t, 0, sizeof *t);
}

/* Anchors every face no walk reached that has a witness point, by the
 * rings around the point; with `all`, every face (the witness method). */
static int anchor_faces(const gis_features *fs, const face_witness *w, face_link *fl, int all,
                        gis_feature_table *out)
{
    uint64_t pending = 0;
    for (uint64_t f = 0; f < fl->faces; f++)
        pending += (all || !fl->reached[f]) && w[f].reach > 0;
    /* a scan of the boxes costs one pass over the rings a point */
    int many = pending > 256;
    ring_finder rf = {.fs = fs};
    link_list set = {0};
    int st = 0;
    for (uint64_t f = 0; f < fl->faces && !st; f++) {
        if (all && w[f].reach <= 0)
            fl->reached[f] = 0; /* as before 1.2: no witness, no features */
        if (!(all || !fl->reached[f]) || w[f].reach <= 0)
            continue;
        set.n = 0;
        if (witness_features(&rf, many, &w[f], &set) != 0)
            st = HPFC_E_NOMEM;
        else if (all) { /* replace the walk's answer */
            fl->reached[f] = 0;
            fl->reached[f] = 0;
            st = face_link_anchor(fl, f, set.v, set.n);
        } else if (!fl->reached[f])
            st = face_link_anchor(fl, f, set.v, set.n);
        out->anchors++;
    }
    free(set.v);
    ring_finder_free(&rf);
    return st;
}

/* The table's face index from the walk's sets, and the edges' features. */
static int make_table(const gis_features *fs, face_link *fl, gis_feature_table *out)
{
    out->face_start = calloc(fl->faces + 1, sizeof *out->face_start);
    uint64_t total = 0;
    for (uint64_t f = 0; f < fl->faces; f++)
        total += fl->reached[f] ? fl->set_len[f] : 0;
    if (total >= UINT32_MAX)
        return HPFC_E_LIMIT;
    out->face_feature = malloc((total ? total : 1) * sizeof *out->face_feature);
    if (!out->face_start || !out->face_feature)
        return HPFC_E_NOMEM;
    uint32_t m = 0;
    for (uint64_t f = 0; f < fl->faces; f++) {
        out->face_start[f] = m;
        if (!fl->reached[f])
            continue;
        memcpy(out->face_feature + m, fl->pool + fl->set_off[f], fl->set_len[f] * sizeof(uint32_t));
        m += fl->set_len[f];
    }
    out->face_start[fl->faces] = m;
    uint32_t last = UINT32_MAX; /* parts come in feature order */
    for (size_t r = 0; r < fs->rings; r++)
        if (fs->ring_closed[r] && fs->ring_feature[r] != last) {
            out->polygon_features++;
            last = fs->ring_feature[r];
        }
    out->edge_count = fl->edges;
    out->edge_start = fl->edge_start, fl->edge_start = NULL;
    out->edge_feature = fl->edge_feature, fl->edge_feature = NULL;
    out->table = (hpfc_feature_table){
        .feature_count = fs->n, .fid = fs->fid, .layer = fs->layer, .key_field = fs->key_field,
        .key = fs->key_field ? (const char *const *)fs->key : NULL, .layer_count = fs->layers,
        .layer_name = (const char *const *)fs->layer_name, .face_count = (uint32_t)fl->faces,
        .face_start = out->face_start, .face_feature = out->face_feature};
    return HPFC_OK;
}

int gis_features_link(const gis_features *fs, const hpfc_graph *graph, const leaf_crossings *lc,
                      const hpfc_file *file, gis_feature_table *out, char *err, size_t err_len)
{
    const char *method = getenv("HPFC_PACK_LINK");
    return gis_features_link_method(fs, graph, lc, file, method && strcmp(method, "witness") == 0,
                                    out, err, err_len);
}

int gis_features_link_method(const gis_features *fs, const hpfc_graph *graph,
                             const leaf_crossings *lc, const hpfc_file *file, int witness,
                             gis_feature_table *out, char *err, size_t err_len)
{
    memset(out, 0, sizeof *out);
    out->method_witness = witness != 0;
    hpfc_faces *faces = NULL;
    face_witness *w = NULL;
    face_link fl = {0};
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    int st = hpfc_faces_build(file, &faces);
    out->faces_s = lap_seconds(&t);
    uint64_t n = faces ? hpfc_faces_count(faces) : 0;
    if (!st && n >= UINT32_MAX)
        st = HPFC_E_LIMIT;
    if (!st && !(w = malloc((n ? n : 1) * sizeof *w)))
        st = HPFC_E_NOMEM;
    if (!st)
        st = face_witnesses(graph, lc, file, faces, w);
    out->witness_s = lap_seconds(&t);
    if (!st)
        st = face_link_run(&fl, fs, graph, lc, file, faces);
    hpfc_faces_free(faces); /* the walk needs the faces' ids only */
    out->topology_s = lap_seconds(&t);
    if (!st)
        st = anchor_faces(fs, w, &fl, out->method_witness, out);
    out->anchor_s = lap_seconds(&t);
    if (!st) {
        out->faces_propagated = fl.propagated - out->anchors - 1;
        out->conflicts = out->method_witness ? 0 : face_link_conflicts(&fl);
        for (uint64_t f = 0; f < n; f++)
            out->faces_without_witness += w[f].reach <= 0;
        st = make_table(fs, &fl, out);
    }
    free(w);
    face_link_free(&fl);
    if (st) {
        gis_feature_table_free(out);
        snprintf(err, err_len, "cannot link the faces to their features (%s)", hpfc_strerror(st));
        return 1;
    }
    return 0;
}
