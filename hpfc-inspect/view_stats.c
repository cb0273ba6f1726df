/*
 * view_stats.c: --stats, histograms of word length, leaf depth, crossings
 * per pixel and stabbings per edge, over every leaf of the file.
 */
#include "views.h"

#include <ctype.h>
#include <errno.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "jsonw.h"
#include "roads.h"
#include "word.h"

/* ---- --stats ------------------------------------------------------------------- */

/* Counts per value 0, 1, 2, ... */
typedef struct histogram {
    const char *name, *unit;
    uint64_t *count;
    size_t cap;
    uint64_t n, sum, max;
} histogram;

static int hist_add(histogram *h, uint64_t value)
{
    if (value >= h->cap) {
        size_t cap = h->cap ? h->cap : 16;
        while (cap <= value)
            cap *= 2;
        uint64_t *c = realloc(h->count, cap * sizeof *c);
        if (!c)
            return HPFC_E_NOMEM;
        memset(c + h->cap, 0, (cap - h->cap) * sizeof *c);
        h->count = c;
        h->cap = cap;
    }
    h->count[value]++;
    h->n++;
    h->sum += value;
    if (value > h->max)
        h->max = value;
    return HPFC_OK;
}

enum { H_WORD_LENGTH, H_DEPTH, H_CROSSINGS, H_STABBINGS, H_COUNT };

typedef struct stats {
    histogram h[H_COUNT];
    uint64_t leaves, private_leaves, vertices, edges, stabbings, faces;
    int faces_status;
} stats;

/* Every dart leaving a vertex of the leaf: walk it to its target, counting
 * the stabbings on the way; each edge is counted once, from the dart whose
 * key is the smaller of the two. */
static int leaf_edges(roads *r, const hpfc_pixel *px, const word_info *wi, stats *s)
{
    for (uint32_t k = 0; k < wi->n; k++) {
        if (wi->comp_vertex[wi->comp[k]] == WORD_NONE)
            continue;
        hpfc_dart d = {.pixel = *px, .crossing = k}, twin;
        uint64_t stabbings;
        int st = roads_walk(r, &d, &stabbings, &twin);
        if (st)
            return st;
        if (hpfc_dart_key(r->file, &d) < hpfc_dart_key(r->file, &twin)) {
            s->edges++;
            s->stabbings += stabbings;
            if ((st = hist_add(&s->h[H_STABBINGS], stabbings)))
                return st;
        }
    }
    return HPFC_OK;
}

static int collect_stats(const hpfc_file *f, stats *s)
{
    roads r;
    word_info wi;
    memset(&wi, 0, sizeof wi);
    hpfc_pixel px;
    int st = roads_init(&r, f);
    for (st = st ? st : hpfc_leaf_first(f, &px); !st; st = hpfc_leaf_next(f, &px)) {
        if ((st = roads_parse(&r, &px, &wi)))
            break;
        s->leaves++;
        s->private_leaves += wi.n == 0;
        s->vertices += wi.nvert;
        if ((st = hist_add(&s->h[H_WORD_LENGTH], wi.n + 4)) ||
            (st = hist_add(&s->h[H_DEPTH], px.depth)) ||
            (st = hist_add(&s->h[H_CROSSINGS], wi.n)) || (st = leaf_edges(&r, &px, &wi, s)))
            break;
    }
    roads_free(&r);
    word_info_free(&wi);
    if (st != HPFC_E_NO_PIXEL)
        return st;
    hpfc_faces *fc;
    s->faces_status = hpfc_faces_build(f, &fc);
    if (!s->faces_status)
        s->faces = hpfc_faces_face_count(fc);
    hpfc_faces_free(fc);
    return HPFC_OK;
}

static void print_hist_text(FILE *out, const histogram *h)
{
    fprintf(out, "\n%s (%llu %s", h->name, (unsigned long long)h->n, h->unit);
    if (h->n)
        fprintf(out, ", mean %.3f, max %llu", (double)h->sum / (double)h->n,
                (unsigned long long)h->max);
    fprintf(out, ")\n");
    uint64_t top = 0;
    for (size_t v = 0; v < h->cap; v++)
        if (h->count[v] > top)
            top = h->count[v];
    for (size_t v = 0; v < h->cap; v++) {
        if (!h->count[v])
            continue;
        int bar = (int)((h->count[v] * 50 + top - 1) / (top ? top : 1));
        fprintf(out, "%8zu %12llu  %.*s\n", v, (unsigned long long)h->count[v], bar,
                "##################################################");
    }
}

static void print_stats_text(FILE *out, const stats *s)
{
    fprintf(out, "leaves      %llu (%llu private, %llu stabbed)\n",
            (unsigned long long)s->leaves, (unsigned long long)s->private_leaves,
            (unsigned long long)(s->leaves - s->private_leaves));
    fprintf(out, "graph       %llu vertices, %llu edges, ", (unsigned long long)s->vertices,
            (unsigned long long)s->edges);
    if (s->faces_status)
        fprintf(out, "faces: %s\n", hpfc_strerror(s->faces_status));
    else
        fprintf(out, "%llu faces\n", (unsigned long long)s->faces);
    fprintf(out, "stabbings   %llu along all edges\n", (unsigned long long)s->stabbings);
    for (int k = 0; k < H_COUNT; k++)
        print_hist_text(out, &s->h[k]);
}

static void print_hist_json(jsonw *w, const histogram *h, const char *key)
{
    jsonw_object_begin(w, key);
    jsonw_u64(w, "count", h->n);
    jsonw_u64(w, "sum", h->sum);
    jsonw_u64(w, "max", h->max);
    jsonw_double(w, "mean", h->n ? (double)h->sum / (double)h->n : 0.0, 4);
    jsonw_array_begin(w, "bins"); /* [value, count] for every value that occurs */
    for (size_t v = 0; v < h->cap; v++) {
        if (!h->count[v])
            continue;
        jsonw_array_begin(w, NULL);
        jsonw_u64(w, NULL, v);
        jsonw_u64(w, NULL, h->count[v]);
        jsonw_array_end(w);
    }
    jsonw_array_end(w);
    jsonw_object_end(w);
}

static void print_stats_json(FILE *out, const stats *s)
{
    static const char *const keys[H_COUNT] = {"word_length", "depth", "crossings_per_pixel",
                                              "stabbings_per_edge"};
    jsonw w;
    jsonw_init(&w, out);
    jsonw_object_begin(&w, NULL);
    jsonw_u64(&w, "leaves", s->leaves);
    jsonw_u64(&w, "private_leaves", s->private_leaves);
    jsonw_u64(&w, "vertices", s->vertices);
    jsonw_u64(&w, "edges", s->edges);
    if (s->faces_status)
        jsonw_null(&w, "faces");
    else
        jsonw_u64(&w, "faces", s->faces);
    jsonw_u64(&w, "stabbings", s->stabbings);
    for (int k = 0; k < H_COUNT; k++)
        print_hist_json(&w, &s->h[k], keys[k]);
    jsonw_object_end(&w);
    jsonw_finish(&w);
}

int view_stats(const hpfc_file *f, FILE *out, int json, char *why)
{
    stats s;
    memset(&s, 0, sizeof s);
    s.h[H_WORD_LENGTH] = (histogram){.name = "word length, symbols", .unit = "word pixels"};
    s.h[H_DEPTH] = (histogram){.name = "depth of leaves", .unit = "word pixels"};
    s.h[H_CROSSINGS] = (histogram){.name = "crossings per pixel", .unit = "word pixels"};
    s.h[H_STABBINGS] = (histogram){.name = "stabbings per edge", .unit = "edges"};
    int st = collect_stats(f, &s);
    if (!st) {
        if (json)
            print_stats_json(out, &s);
        else
            print_stats_text(out, &s);
    }
    for (int k = 0; k < H_COUNT; k++)
        free(s.h[k].count);
    return st ? view_fail_status(why, "stats", st) : VIEW_OK;
}
