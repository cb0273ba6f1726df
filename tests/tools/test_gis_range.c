/*
 * Unit tests of the range files of a GIS read in feature ranges
 * (hpfc-pack/gis_range.h): random ranges written and read back against the
 * test's own record of what was put in (features, keys, typed values,
 * parts, points, names); a file of another reading (tag, layer, first
 * feature) refused; every truncation and every flipped byte of a file
 * refused; and ranges whose bytes are whole (rehashed) but whose data
 * break a rule the reader relies on (positions out of order or outside the
 * range, a feature without parts, a part of no feature, a value of a field
 * the layer does not have or given twice, a coordinate not finite, counts
 * that disagree) refused.
 */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "gis_range.h"

static uint64_t rng_state = 0x2545f4914f6cdd1du;

static uint64_t rnd(uint64_t n)
{
    rng_state ^= rng_state << 13, rng_state ^= rng_state >> 7, rng_state ^= rng_state << 17;
    return n ? rng_state % n : 0;
}

/* The test's own record of a range: what it put in, in plain arrays. */
enum { MAX_F = 40, MAX_V = 6, MAX_P = 3, MAX_PTS = 9 };
typedef struct model_value {
    uint32_t field;
    uint8_t kind;
    int64_t i;
    double r;
    char s[24];
} model_value;
typedef struct model {
    uint64_t tag;
    uint32_t layer, fields;
    int64_t begin;
    size_t n;
    int64_t position[MAX_F], fid[MAX_F];
    char key[MAX_F][24];
    int has_key[MAX_F];
    size_t n_values[MAX_F], n_parts[MAX_F], points[MAX_F][MAX_P];
    model_value value[MAX_F][MAX_V];
    int ring[MAX_F][MAX_P];
    double xy[MAX_F][MAX_P][2 * MAX_PTS];
    size_t n_repaired;
    char repaired[GIS_RANGE_REPAIRED][32];
    gis_range_counts counts;
    int has_before, has_last;
    int64_t fid_before, fid_last;
} model;

static void random_text(char *s, size_t cap)
{
    size_t n = rnd(cap - 1);
    for (size_t k = 0; k < n; k++)
        s[k] = (char)(k % 5 == 4 ? ',' : 'a' + rnd(26)) | (rnd(8) == 0 ? (char)0x80 : 0);
    s[n] = 0;
}

static void random_model(model *m)
{
    memset(m, 0, sizeof *m);
    m->tag = rnd(UINT64_MAX), m->layer = (uint32_t)rnd(4), m->fields = (uint32_t)rnd(MAX_V + 1);
    m->begin = (int64_t)rnd(1000);
    m->n = rnd(MAX_F + 1);
    int64_t at = m->begin;
    for (size_t f = 0; f < m->n; f++) {
        at += (int64_t)rnd(3); /* features without parts between */
        m->position[f] = at++;
        m->fid[f] = (int64_t)rnd(1u << 30) - (1 << 29);
        m->has_key[f] = rnd(3) != 0;
        random_text(m->key[f], sizeof m->key[f]);
        for (uint32_t field = 0; field < m->fields; field++) {
            if (rnd(3) == 0)
                continue; /* a null */
            model_value *v = &m->value[f][m->n_values[f]++];
            v->field = field, v->kind = (uint8_t)(1 + rnd(3));
            v->i = (int64_t)rnd(UINT64_MAX), v->r = (double)rnd(1u << 20) / 7.0 - 1000.0;
            random_text(v->s, sizeof v->s);
        }
        m->n_parts[f] = 1 + rnd(MAX_P);
        for (size_t p = 0; p < m->n_parts[f]; p++) {
            m->points[f][p] = 1 + rnd(MAX_PTS);
            m->ring[f][p] = (int)rnd(2);
            for (size_t k = 0; k < 2 * m->points[f][p]; k++)
                m->xy[f][p][k] = (double)rnd(1u << 30) / 1024.0 - 180.0;
            m->counts.lines++;
        }
    }
    m->counts.read = (uint64_t)(at - m->begin) + rnd(3);
    m->counts.lines += rnd(2);
    m->counts.skipped_empty = m->counts.read - m->n;
    m->counts.dateline_cut = rnd(m->n + 1);
    m->counts.invalid_noded = rnd(m->n + 1);
    m->n_repaired = m->counts.invalid_noded < GIS_RANGE_REPAIRED ? m->counts.invalid_noded
                                                                 : GIS_RANGE_REPAIRED;
    for (size_t k = 0; k < m->n_repaired; k++)
        random_text(m->repaired[k], sizeof m->repaired[k]);
    /* the chain: the FID before the range, and its last (else that one) */
    m->has_before = m->begin > 0;
    m->fid_before = m->has_before ? (int64_t)rnd(1u << 20) - 9 : 0;
    m->has_last = m->has_before || m->counts.read > 0;
    m->fid_last = m->counts.read ? (int64_t)rnd(1u << 20) : m->fid_before;
}

/* The range the writer makes of the model. */
static void write_model(const model *m, gis_range *g)
{
    gis_range_init(g, m->tag, m->layer, m->fields, m->begin);
    g->counts = m->counts;
    g->has_before = m->has_before, g->has_last = m->has_last;
    g->fid_before = m->fid_before, g->fid_last = m->fid_last;
    for (size_t f = 0; f < m->n; f++) {
        CHECK(gis_range_add_feature(g, m->position[f], m->fid[f], m->has_key[f] ? m->key[f] : NULL) == 0);
        for (size_t v = 0; v < m->n_values[f]; v++) {
            const model_value *mv = &m->value[f][v];
            int st = mv->kind == GIS_RANGE_INTEGER ? gis_range_add_integer(g, mv->field, mv->i)
                     : mv->kind == GIS_RANGE_REAL  ? gis_range_add_real(g, mv->field, mv->r)
                                                   : gis_range_add_string(g, mv->field, mv->s);
            CHECK(st == 0);
        }
    }
    for (size_t f = 0; f < m->n; f++)
        for (size_t p = 0; p < m->n_parts[f]; p++)
            CHECK(gis_range_add_part(g, (uint32_t)f, m->xy[f][p], m->points[f][p], m->ring[f][p]) == 0);
    for (size_t k = 0; k < m->n_repaired; k++)
        CHECK(gis_range_add_repaired(g, m->repaired[k]) == 0);
}

static int same_value(const gis_range *g, const gis_range_value *v, const model_value *mv)
{
    if (v->field != mv->field || v->kind != mv->kind)
        return 0;
    if (mv->kind == GIS_RANGE_INTEGER)
        return v->i == mv->i;
    if (mv->kind == GIS_RANGE_REAL)
        return v->r == mv->r;
    return strcmp(g->text + v->s, mv->s) == 0;
}

/* The decoded range holds exactly the model. */
static void check_same(const gis_range *g, const model *m)
{
    CHECK_EQ_INT(g->n_features, m->n);
    CHECK(memcmp(&g->counts, &m->counts, sizeof g->counts) == 0);
    CHECK_EQ_INT(g->fields, m->fields);
    CHECK_EQ_INT(g->n_repaired, m->n_repaired);
    CHECK(g->has_before == m->has_before && g->has_last == m->has_last);
    CHECK(g->fid_before == m->fid_before && g->fid_last == m->fid_last);
    if (g->n_features != m->n)
        return;
    size_t part = 0;
    for (size_t f = 0; f < m->n; f++) {
        const gis_range_feature *ft = &g->features[f];
        CHECK(ft->position == m->position[f] && ft->fid == m->fid[f]);
        CHECK(m->has_key[f] ? ft->key != GIS_RANGE_NONE && strcmp(g->text + ft->key, m->key[f]) == 0
                            : ft->key == GIS_RANGE_NONE);
        CHECK_EQ_INT(ft->values, m->n_values[f]);
        for (size_t v = 0; v < m->n_values[f] && v < ft->values; v++)
            CHECK(same_value(g, &g->values[ft->first_value + v], &m->value[f][v]));
        for (size_t p = 0; p < m->n_parts[f]; p++, part++) {
            if (part >= g->n_parts) {
                CHECK(part < g->n_parts);
                return;
            }
            const gis_range_part *pt = &g->parts[part];
            CHECK(pt->feature == f && pt->ring == m->ring[f][p] && pt->points == m->points[f][p]);
            if (pt->points == m->points[f][p])
                CHECK(memcmp(g->xy + 2 * pt->first_point, m->xy[f][p],
                             2 * pt->points * sizeof(double)) == 0);
        }
    }
    CHECK_EQ_INT(g->n_parts, part);
    for (size_t k = 0; k < m->n_repaired; k++)
        CHECK(strcmp(g->text + g->repaired[k], m->repaired[k]) == 0);
}

static int decode(const uint8_t *b, size_t n, const model *m, gis_range *g, char *why)
{
    return gis_range_decode(b, n, m->tag, m->layer, m->begin, g, why, 256);
}

/* Writes the model, reads it back; another reading's tag, layer or first
 * feature, every truncation and every flipped byte are refused. */
static void test_round_trip(void)
{
    for (int round = 0; round < 300; round++) {
        model m;
        random_model(&m);
        gis_range w, g;
        write_model(&m, &w);
        uint8_t *b = NULL;
        size_t n = 0;
        CHECK(gis_range_encode(&w, &b, &n) == 0);
        gis_range_free(&w);
        char why[256] = "";
        int st = decode(b, n, &m, &g, why);
        CHECK(st == 0);
        if (st == 0)
            check_same(&g, &m);
        else if (round < 3)
            fprintf(stderr, "round %d: %s\n", round, why);
        gis_range_free(&g);
        /* the head alone, from the whole file or its first bytes: the
         * same head, no data */
        size_t lens[] = {GIS_RANGE_HEAD, n};
        for (int k = 0; k < 2; k++) {
            size_t len = lens[k];
            CHECK(gis_range_decode_head(b, len, m.tag, m.layer, m.begin, &g, why, sizeof why) ==
                  0);
            CHECK(g.n_features == 0 && g.features == NULL && g.xy == NULL);
            CHECK(g.fid_before == m.fid_before && g.fid_last == m.fid_last &&
                  memcmp(&g.counts, &m.counts, sizeof g.counts) == 0);
            gis_range_free(&g);
        }
        CHECK(gis_range_decode_head(b, GIS_RANGE_HEAD - 1, m.tag, m.layer, m.begin, &g, why,
                                    sizeof why) != 0);
        CHECK(gis_range_decode_head(b, n, m.tag ^ 1, m.layer, m.begin, &g, why, sizeof why) != 0);
        CHECK(gis_range_decode(b, n, m.tag ^ 1, m.layer, m.begin, &g, why, sizeof why) != 0);
        CHECK(strstr(why, "another reading") != NULL);
        CHECK(gis_range_decode(b, n, m.tag, m.layer + 1, m.begin, &g, why, sizeof why) != 0);
        CHECK(gis_range_decode(b, n, m.tag, m.layer, m.begin + 1, &g, why, sizeof why) != 0);
        for (size_t cut = 0; cut < n; cut += 1 + rnd(7))
            CHECK(decode(b, cut, &m, &g, why) != 0);
        for (size_t at = 0; at < n; at += 1 + rnd(5)) {
            uint8_t keep = b[at];
            b[at] ^= (uint8_t)(1u << rnd(8));
            CHECK(decode(b, n, &m, &g, why) != 0);
            b[at] = keep;
        }
        free(b);
    }
}

/* The model, spoiled by `spoil`, written and rehashed: the decoder must
 * find the rule broken, not the bytes. */
static void expect_refused(void (*spoil)(model *m), const char *what)
{
    int refused = 0, tried = 0;
    for (int round = 0; round < 200; round++) {
        model m;
        random_model(&m);
        if (m.n < 2 || m.fields == 0)
            continue;
        spoil(&m);
        gis_range w, g;
        write_model(&m, &w);
        uint8_t *b = NULL;
        size_t n = 0;
        if (gis_range_encode(&w, &b, &n) == 0) {
            char why[256] = "";
            tried++;
            if (decode(b, n, &m, &g, why) != 0 && strstr(why, "damaged") != NULL)
                refused++;
            else
                fprintf(stderr, "%s: decoded (%s)\n", what, why);
            gis_range_free(&g);
        }
        gis_range_free(&w);
        free(b);
    }
    CHECK(tried > 20);
    CHECK_EQ_INT(refused, tried);
}

static void positions_backwards(model *m) { m->position[1] = m->position[0]; }
static void position_before_range(model *m) { m->position[0] = m->begin - 1; }
static void position_past_read(model *m) { m->counts.read = (uint64_t)(m->position[m->n - 1] - m->begin); }
static void field_missing(model *m)
{
    m->value[0][0] = (model_value){.field = m->fields, .kind = GIS_RANGE_INTEGER};
    m->n_values[0] = m->n_values[0] ? m->n_values[0] : 1;
}
static void field_twice(model *m)
{
    m->value[0][0] = (model_value){.field = 0, .kind = GIS_RANGE_INTEGER};
    m->value[0][1] = (model_value){.field = 0, .kind = GIS_RANGE_REAL};
    m->n_values[0] = 2;
}
static void not_finite(model *m) { m->xy[1][0][1] = NAN; }
static void fewer_read(model *m) { m->counts.read = m->n - 1; }
/* a range after the first without the FID before it (or the first with one) */
static void chain_without_before(model *m) { m->has_before = !m->has_before, m->fid_before = 0; }
static void chain_before_at_zero(model *m) { m->begin = 0, m->has_before = 1, m->position[0] = 0; }
static void chain_last_moved(model *m)
{
    m->counts.read = 0, m->n = 0, m->counts.skipped_empty = 0, m->counts.dateline_cut = 0;
    m->counts.invalid_noded = 0, m->n_repaired = 0, m->has_last = m->has_before;
    m->fid_last = m->fid_before + 1;
}
static void more_repaired(model *m) { m->counts.invalid_noded = m->n_repaired ? m->n_repaired - 1 : 0, m->n_repaired = m->n_repaired ? m->n_repaired : 1; }

/* A feature without parts (its parts given to the next), written by hand:
 * the writer refuses parts out of order. */
static void test_feature_without_parts(void)
{
    model m;
    do
        random_model(&m);
    while (m.n < 3);
    gis_range w, g;
    gis_range_init(&w, m.tag, m.layer, 0, m.begin);
    w.counts = m.counts;
    w.counts.invalid_noded = 0;
    for (size_t f = 0; f < m.n; f++)
        CHECK(gis_range_add_feature(&w, m.position[f], m.fid[f], NULL) == 0);
    for (size_t f = 0; f < m.n; f++)
        if (f != 1)
            CHECK(gis_range_add_part(&w, (uint32_t)f, m.xy[f][0], m.points[f][0], 0) == 0);
    /* the writer keeps parts in feature order */
    CHECK(gis_range_add_part(&w, 1, m.xy[1][0], m.points[1][0], 0) != 0);
    CHECK(gis_range_add_part(&w, (uint32_t)m.n, m.xy[1][0], 1, 0) != 0);
    uint8_t *b = NULL;
    size_t n = 0;
    char why[256] = "";
    CHECK(gis_range_encode(&w, &b, &n) == 0);
    CHECK(gis_range_decode(b, n, m.tag, m.layer, m.begin, &g, why, sizeof why) != 0);
    CHECK(strstr(why, "damaged") != NULL);
    free(b);
    gis_range_free(&w);
}

static void put_le64(uint8_t *b, uint64_t v)
{
    for (int k = 0; k < 8; k++)
        b[k] = (uint8_t)(v >> (8 * k));
}

/* The tightest range the format allows (features with no key or value,
 * each one part of one point) decodes, head and whole: the head's bound
 * on the counts is not tighter than the data. A head that counts more
 * points, features or parts than its bytes could hold is refused by both
 * decoders, before anything is allocated. */
static void test_counts_against_bytes(void)
{
    gis_range w, g;
    enum { N = 9 };
    gis_range_init(&w, 7, 0, 0, 0);
    for (uint32_t f = 0; f < N; f++) {
        double xy[2] = {f, -1.0 * f};
        CHECK(gis_range_add_feature(&w, f, 100 + f, NULL) == 0);
        CHECK(gis_range_add_part(&w, f, xy, 1, 0) == 0);
    }
    w.counts.read = N, w.counts.lines = N;
    w.has_last = 1, w.fid_last = 100 + N - 1;
    uint8_t *b = NULL;
    size_t n = 0;
    char why[256] = "";
    CHECK(gis_range_encode(&w, &b, &n) == 0);
    gis_range_free(&w);
    CHECK_EQ_INT((long long)n, GIS_RANGE_HEAD + N * (24 + 13 + 16));
    CHECK(gis_range_decode(b, n, 7, 0, 0, &g, why, sizeof why) == 0);
    CHECK(g.n_features == N && g.n_points == N);
    gis_range_free(&g);
    /* features, parts and points counts, each pushed past the bytes */
    const size_t at[] = {120, 128, 136};
    for (size_t k = 0; k < 3; k++) {
        uint8_t keep[8];
        memcpy(keep, b + at[k], 8);
        uint64_t huge[] = {N + (n - GIS_RANGE_HEAD) / 8, UINT64_MAX / 2, UINT64_MAX};
        for (size_t h = 0; h < 3; h++) {
            put_le64(b + at[k], huge[h]);
            put_le64(b + 16, gis_range_hash(b + 24, n - 24));
            CHECK(gis_range_decode(b, n, 7, 0, 0, &g, why, sizeof why) != 0);
            CHECK(strstr(why, "more than it holds") || strstr(why, "counts disagree"));
            CHECK(gis_range_decode_head(b, GIS_RANGE_HEAD, 7, 0, 0, &g, why, sizeof why) != 0);
        }
        memcpy(b + at[k], keep, 8);
    }
    /* a head whose stated length is shorter than the bytes given */
    put_le64(b + 8, GIS_RANGE_HEAD - 25);
    CHECK(gis_range_decode_head(b, GIS_RANGE_HEAD, 7, 0, 0, &g, why, sizeof why) != 0);
    free(b);
}

int main(void)
{
    test_round_trip();
    expect_refused(positions_backwards, "positions backwards");
    expect_refused(position_before_range, "a position before the range");
    expect_refused(position_past_read, "a position past the features read");
    expect_refused(field_missing, "a field the layer does not have");
    expect_refused(field_twice, "a field given twice");
    expect_refused(not_finite, "a coordinate not finite");
    expect_refused(fewer_read, "fewer features read than kept");
    expect_refused(more_repaired, "more names than polygons noded");
    expect_refused(chain_without_before, "the FID before the range where there is none, or none");
    expect_refused(chain_before_at_zero, "a FID before the first feature");
    expect_refused(chain_last_moved, "a range of no feature whose last FID moved");
    test_feature_without_parts();
    test_counts_against_bytes();
    return check_report("gis_range");
}
