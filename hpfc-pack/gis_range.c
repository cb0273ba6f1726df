/*
 * gis_range.c: see gis_range.h.
 */
#include "gis_range.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "grow.h"

static const uint8_t MAGIC[8] = GIS_RANGE_MAGIC;
enum { HEAD_BYTES = 24 };

/* ---- writing ----------------------------------------------------------------- */

void gis_range_init(gis_range *g, uint64_t tag, uint32_t layer, uint32_t fields, int64_t begin)
{
    memset(g, 0, sizeof *g);
    g->tag = tag, g->layer = layer, g->fields = fields, g->begin = begin;
}

void gis_range_free(gis_range *g)
{
    free(g->features);
    free(g->parts);
    free(g->values);
    free(g->xy);
    free(g->text);
    memset(g, 0, sizeof *g);
}

/* Keeps n bytes of s and a NUL; their offset, or GIS_RANGE_NONE. */
static size_t keep_text(gis_range *g, const char *s, size_t n)
{
    if (n >= SIZE_MAX / 2 || !array_grow((void **)&g->text, &g->cap_text, g->text_len + n + 1, 1))
        return GIS_RANGE_NONE;
    size_t at = g->text_len;
    memcpy(g->text + at, s, n);
    g->text[at + n] = 0;
    g->text_len += n + 1;
    return at;
}

int gis_range_add_feature(gis_range *g, int64_t position, int64_t fid, const char *key)
{
    if (!array_grow((void **)&g->features, &g->cap_features, g->n_features + 1, sizeof *g->features))
        return -1;
    size_t k = GIS_RANGE_NONE;
    if (key && (k = keep_text(g, key, strlen(key))) == GIS_RANGE_NONE)
        return -1;
    g->features[g->n_features++] = (gis_range_feature){position, fid, k, g->n_values, 0};
    return 0;
}

static gis_range_value *add_value(gis_range *g, uint32_t field, uint8_t kind)
{
    if (!g->n_features ||
        !array_grow((void **)&g->values, &g->cap_values, g->n_values + 1, sizeof *g->values))
        return NULL;
    gis_range_value *v = &g->values[g->n_values++];
    *v = (gis_range_value){.field = field, .kind = kind, .s = GIS_RANGE_NONE};
    g->features[g->n_features - 1].values++;
    return v;
}

int gis_range_add_integer(gis_range *g, uint32_t field, int64_t i)
{
    gis_range_value *v = add_value(g, field, GIS_RANGE_INTEGER);
    if (v)
        v->i = i;
    return v ? 0 : -1;
}

int gis_range_add_real(gis_range *g, uint32_t field, double r)
{
    gis_range_value *v = add_value(g, field, GIS_RANGE_REAL);
    if (v)
        v->r = r;
    return v ? 0 : -1;
}

int gis_range_add_string(gis_range *g, uint32_t field, const char *s)
{
    size_t at = keep_text(g, s, strlen(s));
    gis_range_value *v = at == GIS_RANGE_NONE ? NULL : add_value(g, field, GIS_RANGE_STRING);
    if (v)
        v->s = at;
    return v ? 0 : -1;
}

int gis_range_add_part(gis_range *g, uint32_t feature, const double *xy, size_t n, int ring)
{
    uint32_t last = g->n_parts ? g->parts[g->n_parts - 1].feature : 0;
    if (feature >= g->n_features || feature < last || n == 0 || n >= SIZE_MAX / 4 - g->n_points ||
        !array_grow((void **)&g->parts, &g->cap_parts, g->n_parts + 1, sizeof *g->parts) ||
        !array_grow((void **)&g->xy, &g->cap_points, 2 * (g->n_points + n), sizeof *g->xy))
        return -1;
    memcpy(g->xy + 2 * g->n_points, xy, 2 * n * sizeof *xy);
    g->parts[g->n_parts++] =
        (gis_range_part){g->n_points, n, feature, ring != 0};
    g->n_points += n;
    return 0;
}

int gis_range_add_repaired(gis_range *g, const char *item)
{
    if (g->n_repaired == GIS_RANGE_REPAIRED)
        return 0;
    size_t at = keep_text(g, item, strlen(item));
    if (at == GIS_RANGE_NONE)
        return -1;
    g->repaired[g->n_repaired++] = at;
    return 0;
}

typedef struct sink {
    uint8_t *p;
    size_t len, cap;
    int failed;
} sink;

static void put(sink *s, const void *bytes, size_t n)
{
    if (s->failed || !array_grow((void **)&s->p, &s->cap, s->len + n, 1)) {
        s->failed = 1;
        return;
    }
    memcpy(s->p + s->len, bytes, n);
    s->len += n;
}

static void put_u64(sink *s, uint64_t v)
{
    uint8_t b[8];
    for (int k = 0; k < 8; k++)
        b[k] = (uint8_t)(v >> (8 * k));
    put(s, b, 8);
}

static void put_u32(sink *s, uint32_t v)
{
    uint8_t b[4];
    for (int k = 0; k < 4; k++)
        b[k] = (uint8_t)(v >> (8 * k));
    put(s, b, 4);
}

static void put_f64(sink *s, double d)
{
    uint64_t v;
    memcpy(&v, &d, 8);
    put_u64(s, v);
}

/* A string of the text at offset `at`, or none. */
static void put_text(sink *s, const gis_range *g, size_t at)
{
    if (at == GIS_RANGE_NONE) {
        put_u32(s, 0);
        return;
    }
    size_t n = strlen(g->text + at);
    if (n >= UINT32_MAX) {
        s->failed = 1;
        return;
    }
    put_u32(s, (uint32_t)n + 1);
    put(s, g->text + at, n);
}

uint64_t gis_range_hash(const uint8_t *p, size_t n)
{
    uint64_t h = UINT64_C(0xcbf29ce484222325);
    for (size_t k = 0; k < n; k++)
        h = (h ^ p[k]) * UINT64_C(0x100000001b3);
    return h;
}

static void put_value(sink *s, const gis_range *g, const gis_range_value *v)
{
    put_u32(s, v->field);
    put(s, &v->kind, 1);
    if (v->kind == GIS_RANGE_INTEGER)
        put_u64(s, (uint64_t)v->i);
    else if (v->kind == GIS_RANGE_REAL)
        put_f64(s, v->r);
    else
        put_text(s, g, v->s);
}

int gis_range_encode(const gis_range *g, uint8_t **out, size_t *len)
{
    sink s = {0};
    put(&s, MAGIC, 8);
    put_u64(&s, 0); /* the payload's length and hash, set below */
    put_u64(&s, 0);
    put_u64(&s, g->tag);
    put_u32(&s, g->layer);
    put_u32(&s, g->fields);
    put_u64(&s, (uint64_t)g->begin);
    put_u64(&s, (uint64_t)(g->has_before != 0) | (uint64_t)(g->has_last != 0) << 1);
    put_u64(&s, (uint64_t)g->fid_before);
    put_u64(&s, (uint64_t)g->fid_last);
    const gis_range_counts *c = &g->counts;
    uint64_t counts[] = {c->read, c->lines, c->skipped_empty, c->skipped_points, c->dateline_cut,
                         c->invalid_noded, g->n_features, g->n_parts, g->n_points};
    for (size_t k = 0; k < sizeof counts / sizeof counts[0]; k++)
        put_u64(&s, counts[k]);
    put_u32(&s, (uint32_t)g->n_repaired);
    for (size_t f = 0; f < g->n_features; f++) {
        const gis_range_feature *ft = &g->features[f];
        put_u64(&s, (uint64_t)ft->position);
        put_u64(&s, (uint64_t)ft->fid);
        put_text(&s, g, ft->key);
        put_u32(&s, (uint32_t)ft->values);
        for (size_t v = 0; v < ft->values; v++)
            put_value(&s, g, &g->values[ft->first_value + v]);
    }
    for (size_t p = 0; p < g->n_parts; p++) {
        put_u64(&s, g->parts[p].points);
        put_u32(&s, g->parts[p].feature);
        uint8_t ring = (uint8_t)g->parts[p].ring;
        put(&s, &ring, 1);
    }
    for (size_t k = 0; k < 2 * g->n_points; k++)
        put_f64(&s, g->xy[k]);
    for (size_t k = 0; k < g->n_repaired; k++)
        put_text(&s, g, g->repaired[k]);
    if (s.failed) {
        free(s.p);
        return -1;
    }
    uint64_t n = s.len - HEAD_BYTES, h = gis_range_hash(s.p + HEAD_BYTES, n);
    for (int k = 0; k < 8; k++) {
        s.p[8 + k] = (uint8_t)(n >> (8 * k));
        s.p[16 + k] = (uint8_t)(h >> (8 * k));
    }
    *out = s.p;
    *len = s.len;
    return 0;
}

/* ---- reading ----------------------------------------------------------------- */

typedef struct source {
    const uint8_t *p;
    size_t left;
    char *why;
    size_t why_len;
    int failed;
} source;

static int refuse(source *s, const char *fmt, ...)
{
    if (!s->failed) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(s->why, s->why_len, fmt, ap);
        va_end(ap);
    }
    s->failed = 1;
    return -1;
}

static const uint8_t *take(source *s, size_t n)
{
    if (s->failed || n > s->left) {
        refuse(s, "damaged range file: it ends inside its data");
        return NULL;
    }
    const uint8_t *p = s->p;
    s->p += n, s->left -= n;
    return p;
}

static uint64_t get_u64(source *s)
{
    const uint8_t *b = take(s, 8);
    uint64_t v = 0;
    for (int k = 0; b && k < 8; k++)
        v |= (uint64_t)b[k] << (8 * k);
    return v;
}

static uint32_t get_u32(source *s)
{
    const uint8_t *b = take(s, 4);
    uint32_t v = 0;
    for (int k = 0; b && k < 4; k++)
        v |= (uint32_t)b[k] << (8 * k);
    return v;
}

static double get_f64(source *s)
{
    uint64_t v = get_u64(s);
    double d;
    memcpy(&d, &v, 8);
    return d;
}

/* A string into g's text: its offset, or GIS_RANGE_NONE (none, or a
 * failure, which s records). */
static size_t get_text(source *s, gis_range *g)
{
    uint32_t n = get_u32(s);
    if (n == 0 || s->failed)
        return GIS_RANGE_NONE;
    const uint8_t *b = take(s, n - 1);
    if (!b)
        return GIS_RANGE_NONE;
    if (memchr(b, 0, n - 1)) {
        refuse(s, "damaged range file: a string holds a NUL");
        return GIS_RANGE_NONE;
    }
    size_t at = keep_text(g, (const char *)b, n - 1);
    if (at == GIS_RANGE_NONE)
        refuse(s, "out of memory");
    return at;
}

/* An array of n items of `size` bytes; get_head has checked n against the
 * bytes the file holds. */
static void *get_array(source *s, size_t n, size_t size)
{
    void *p = malloc(n ? n * size : 1);
    if (!p)
        refuse(s, "out of memory");
    return p;
}

static int get_value(source *s, gis_range *g, uint32_t fields, uint32_t last, gis_range_value *v)
{
    v->field = get_u32(s);
    const uint8_t *kind = take(s, 1);
    if (!kind)
        return -1;
    v->kind = *kind;
    v->s = GIS_RANGE_NONE;
    if (v->field >= fields || (last != UINT32_MAX && v->field <= last))
        return refuse(s, "damaged range file: a value of field %u (the layer has %u, each once "
                         "and in order)",
                      v->field, fields);
    if (v->kind == GIS_RANGE_INTEGER)
        v->i = (int64_t)get_u64(s);
    else if (v->kind == GIS_RANGE_REAL)
        v->r = get_f64(s);
    else if (v->kind == GIS_RANGE_STRING) {
        if ((v->s = get_text(s, g)) == GIS_RANGE_NONE)
            return refuse(s, "damaged range file: a string value without a string");
    } else
        return refuse(s, "damaged range file: a value of unknown kind %u", v->kind);
    return s->failed ? -1 : 0;
}

static int get_features(source *s, gis_range *g)
{
    int64_t last = 0, end = g->begin + (int64_t)g->counts.read;
    for (size_t f = 0; f < g->n_features; f++) {
        gis_range_feature *ft = &g->features[f];
        ft->position = (int64_t)get_u64(s);
        ft->fid = (int64_t)get_u64(s);
        ft->key = get_text(s, g);
        uint32_t values = get_u32(s);
        if (s->failed)
            return -1;
        if (ft->position < g->begin || ft->position >= end || (f && ft->position <= last))
            return refuse(s, "damaged range file: feature position %lld is not after the last "
                             "within the range",
                          (long long)ft->position);
        last = ft->position;
        ft->first_value = g->n_values;
        ft->values = values;
        if (values > g->fields || values > s->left / 5)
            return refuse(s, "damaged range file: a feature with %u values", values);
        if (!array_grow((void **)&g->values, &g->cap_values, g->n_values + values,
                        sizeof *g->values))
            return refuse(s, "out of memory");
        uint32_t field = UINT32_MAX;
        for (uint32_t v = 0; v < values; v++) {
            if (get_value(s, g, g->fields, field, &g->values[g->n_values]))
                return -1;
            field = g->values[g->n_values++].field;
        }
    }
    return 0;
}

/* Every feature has parts, the parts come in feature order, and their
 * points add up to the points stored. */
static int get_parts(source *s, gis_range *g)
{
    size_t point = 0;
    for (size_t p = 0; p < g->n_parts; p++) {
        gis_range_part *pt = &g->parts[p];
        uint64_t n = get_u64(s);
        pt->feature = get_u32(s);
        const uint8_t *ring = take(s, 1);
        if (!ring)
            return -1;
        pt->ring = *ring != 0;
        uint32_t expect = p ? g->parts[p - 1].feature : 0;
        if (*ring > 1 || n == 0 || n > g->n_points - point ||
            (pt->feature != expect && (!p || pt->feature != expect + 1)))
            return refuse(s, "damaged range file: part %zu does not follow the features and points",
                          p);
        pt->first_point = point, pt->points = (size_t)n;
        point += (size_t)n;
    }
    if (point != g->n_points || (g->n_parts ? g->parts[g->n_parts - 1].feature + 1 : 0) != g->n_features)
        return refuse(s, "damaged range file: its parts do not cover its features and points");
    return 0;
}

static int get_points(source *s, gis_range *g)
{
    for (size_t k = 0; k < 2 * g->n_points; k++) {
        g->xy[k] = get_f64(s);
        if (!isfinite(g->xy[k]))
            return refuse(s, "damaged range file: a coordinate is not finite");
    }
    return s->failed ? -1 : 0;
}

/* The head; `whole` says the bytes are the whole file, whose length and
 * hash are then checked, else they may be its first GIS_RANGE_HEAD bytes
 * and the counts are checked against the payload length the file states.
 * The counts are left in g->n_*; nothing is allocated. */
static int get_head(source *s, gis_range *g, uint64_t tag, uint32_t layer, int64_t begin,
                    int whole)
{
    const uint8_t *m = take(s, 8);
    if (!m || memcmp(m, MAGIC, 8) != 0)
        return refuse(s, "not a range file of this version (hpfc-pack --read-range writes them)");
    uint64_t n = get_u64(s), h = get_u64(s);
    if (s->failed || (whole ? n != s->left || h != gis_range_hash(s->p, s->left) : n < s->left))
        return refuse(s, "damaged range file: its length or hash does not match its bytes");
    g->tag = get_u64(s);
    g->layer = get_u32(s);
    g->fields = get_u32(s);
    g->begin = (int64_t)get_u64(s);
    uint64_t chain = get_u64(s);
    g->fid_before = (int64_t)get_u64(s);
    g->fid_last = (int64_t)get_u64(s);
    g->has_before = (int)(chain & 1), g->has_last = (int)(chain >> 1 & 1);
    if (!s->failed && chain > 3)
        return refuse(s, "damaged range file: an unknown chain flag");
    if (!s->failed && (g->tag != tag || g->layer != layer || g->begin != begin))
        return refuse(s, "a range file of another reading (layer %u from feature %lld, expected "
                         "layer %u from %lld)",
                      g->layer, (long long)g->begin, layer, (long long)begin);
    gis_range_counts *c = &g->counts;
    uint64_t *counts[] = {&c->read, &c->lines, &c->skipped_empty, &c->skipped_points,
                          &c->dateline_cut, &c->invalid_noded};
    for (size_t k = 0; k < sizeof counts / sizeof counts[0]; k++)
        *counts[k] = get_u64(s);
    uint64_t features = get_u64(s), parts = get_u64(s), points = get_u64(s);
    uint32_t repaired = get_u32(s);
    if (s->failed)
        return -1;
    if (begin < 0 || c->read > (uint64_t)INT64_MAX - (uint64_t)begin || features > c->read ||
        c->skipped_empty > c->read || c->dateline_cut > c->read || c->invalid_noded > features ||
        parts < features || c->lines < parts || repaired > GIS_RANGE_REPAIRED ||
        repaired > c->invalid_noded || g->has_before != (begin > 0) ||
        g->has_last != (g->has_before || c->read > 0) ||
        (!g->has_before && g->fid_before) || (!g->has_last && g->fid_last) ||
        (!c->read && g->fid_last != g->fid_before))
        return refuse(s, "damaged range file: its counts disagree");
    /* The data after the head: a feature takes at least 24 bytes, a part
     * 13, a point 16 (each step below subtracts what fits). */
    uint64_t data = n - (GIS_RANGE_HEAD - 24);
    if (points > data / 16 || features > (data -= points * 16) / 24 ||
        parts > (data - features * 24) / 13)
        return refuse(s, "damaged range file: it counts more than it holds");
    g->n_features = (size_t)features, g->n_parts = (size_t)parts, g->n_points = (size_t)points;
    g->n_repaired = repaired;
    return 0;
}

static int get_arrays(source *s, gis_range *g)
{
    if (!(g->features = get_array(s, g->n_features, sizeof *g->features)) ||
        !(g->parts = get_array(s, g->n_parts, sizeof *g->parts)) ||
        !(g->xy = get_array(s, g->n_points, 2 * sizeof *g->xy)))
        return -1;
    return 0;
}

int gis_range_decode_head(const uint8_t *bytes, size_t len, uint64_t tag, uint32_t layer,
                          int64_t begin, gis_range *g, char *why, size_t why_len)
{
    memset(g, 0, sizeof *g);
    source s = {bytes, len, why, why_len, 0};
    int st = get_head(&s, g, tag, layer, begin, 0);
    g->n_features = g->n_parts = g->n_points = g->n_repaired = 0;
    return st ? -1 : 0;
}

int gis_range_decode(const uint8_t *bytes, size_t len, uint64_t tag, uint32_t layer,
                     int64_t begin, gis_range *g, char *why, size_t why_len)
{
    memset(g, 0, sizeof *g);
    source s = {bytes, len, why, why_len, 0};
    if (get_head(&s, g, tag, layer, begin, 1) || get_arrays(&s, g) || get_features(&s, g) ||
        get_parts(&s, g) || get_points(&s, g))
        goto failed;
    for (size_t k = 0; k < g->n_repaired; k++)
        if ((g->repaired[k] = get_text(&s, g)) == GIS_RANGE_NONE) {
            refuse(&s, "damaged range file: a repaired polygon without a name");
            goto failed;
        }
    if (s.left) {
        refuse(&s, "damaged range file: bytes after its data");
        goto failed;
    }
    return 0;
failed:
    gis_range_free(g);
    return -1;
}
