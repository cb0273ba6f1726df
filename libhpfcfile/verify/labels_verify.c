/*
 * hpfc_labels_verify: the stored LABL section against the map
 * (spec/hpfc-format.md §6.5.6). hpfc_faces_build stays the reference for
 * faces; the rank samples are recounted from the pools; the directory must
 * give each record right after the previous one; a crossing seen from both
 * sides of its road must carry one edge id. O(file).
 */
#include <stdlib.h>
#include <string.h>

#include "file.h"
#include "labels.h"
#include "reader.h"
#include "topo.h"
#include "verify_report.h"

/* The first disagreement, into the report: HPFC_E_CORRUPT. */
#define problem(r, ...) verify_message((r)->message, sizeof (r)->message, __VA_ARGS__)

/* Every rank sample against a count over the pools (images back to back). */
static int check_samples(const hpfc_file *f, const labels_view *v, hpfc_labels_report *r)
{
    hpfc_file_info fi;
    hpfc_file_get_info(f, &fi);
    uint64_t step = UINT64_C(1) << v->sample_shift;
    for (uint32_t l = 0; l < fi.levels; l++) {
        hpfc_level_info li;
        hpfc_file_get_level(f, l, &li);
        const format_bits *pool = &f->lv[l].pool;
        uint64_t units = l ? li.images : (uint64_t)fi.root_cols * fi.root_rows;
        uint64_t words = 0, off = 0, nm = (uint64_t)fi.cols * fi.rows;
        uint64_t record = 1 + (uint64_t)(li.address_bits > li.word_bits ? li.address_bits : li.word_bits);
        for (uint64_t u = 0; u < units; u++) {
            if ((u & (step - 1)) == 0 && f->compact) {
                int st = reader_compact_words_before(f, l, u, &words);
                if (st)
                    return problem(r, "level %u unit %llu: %s", l, (unsigned long long)u,
                                   hpfc_strerror(st));
            }
            if ((u & (step - 1)) == 0) {
                uint64_t k = u >> v->sample_shift;
                uint64_t got = format_get(&v->rank, v->rank_start[l] + k * v->rank_bits[l],
                                          v->rank_bits[l]);
                if (got != words)
                    return problem(r, "level %u rank sample %llu is %llu, the pools say %llu", l,
                                   (unsigned long long)k, (unsigned long long)got,
                                   (unsigned long long)words);
            }
            if (f->compact)
                continue; /* counted at the samples, by rank */
            if (l == 0) {
                words += !format_get(pool, u * record, 1);
                continue;
            }
            uint64_t bits, refined;
            int st = reader_image_bits(f, l, off, &bits, &refined);
            if (st)
                return problem(r, "level %u image %llu: %s", l, (unsigned long long)u,
                               hpfc_strerror(st));
            words += nm - refined;
            off += bits;
        }
    }
    return HPFC_OK;
}

typedef struct verifier {
    const hpfc_file *f;
    const labels_view *v;
    const hpfc_faces *fc;
    hpfc_walker *w;
    uint64_t *length; /* per global leaf: its record's bits, UINT64_MAX before it is seen */
    hpfc_labels_report *r;
} verifier;

static int check_leaf(verifier *z, const hpfc_pixel *px)
{
    uint64_t rank, g, want, got;
    int st = labels_leaf_rank(z->f, px, &rank);
    if (st)
        return problem(z->r, "a leaf at depth %u has no number: %s", px->depth, hpfc_strerror(st));
    g = z->v->first_leaf[px->depth] + rank;
    if (z->length[g] != UINT64_MAX)
        return problem(z->r, "two leaves have number %llu", (unsigned long long)g);
    if ((st = topo_parse_pixel(z->w, &z->w->p_word, px)))
        return problem(z->r, "leaf %llu: %s", (unsigned long long)g, hpfc_strerror(st));
    const word_parts *lw = &z->w->p_word;
    uint32_t stabbings = 0;
    for (uint32_t c = 0; c < lw->ncomp; c++)
        stabbings += lw->comp_vertex[c] == TOPO_NONE;
    z->length[g] = lw->n ? (uint64_t)(lw->n - stabbings) * (z->v->edge_bits + 1) : z->v->face_bits;
    for (uint32_t t = 0; t < (lw->n ? lw->n : 1); t++) {
        if (lw->n) {
            hpfc_dart d = {.pixel = *px, .crossing = t ? t - 1 : lw->n - 1};
            st = hpfc_faces_dart_face(z->fc, &d, &want);
        } else {
            st = hpfc_faces_pixel_face(z->fc, px, &want);
        }
        if (!st)
            st = hpfc_label_stretch_face(z->f, px, t, &got);
        if (st)
            return problem(z->r, "leaf %llu stretch %u: %s", (unsigned long long)g, t,
                           hpfc_strerror(st));
        if (got != want)
            return problem(z->r, "leaf %llu stretch %u: stored face %llu, the map's is %llu",
                           (unsigned long long)g, t, (unsigned long long)got,
                           (unsigned long long)want);
        z->r->labels_checked++;
    }
    for (uint32_t k = 0; k < lw->n; k++) {
        if ((st = hpfc_label_crossing_edge(z->f, px, k, &got)))
            return problem(z->r, "leaf %llu crossing %u: %s", (unsigned long long)g, k,
                           hpfc_strerror(st));
        z->r->labels_checked++;
        if (k >= z->w->p_word.road_off[HPFC_EAST])
            continue; /* E and S roads: checked from the leaf across */
        hpfc_pixel q;
        uint32_t m;
        if ((st = topo_cross_road(z->w, px, true, &z->w->p_word, k, &q, &z->w->q_word, &m)) ||
            (st = hpfc_label_crossing_edge(z->f, &q, m, &want)))
            return problem(z->r, "leaf %llu crossing %u across its road: %s",
                           (unsigned long long)g, k, hpfc_strerror(st));
        if (got != want)
            return problem(z->r,
                           "leaf %llu crossing %u: edge id %llu, the same crossing across "
                           "the road has %llu",
                           (unsigned long long)g, k, (unsigned long long)got,
                           (unsigned long long)want);
    }
    z->r->leaves_checked++;
    return HPFC_OK;
}

/* Records back to back in leaf order, filling the label stream. */
static int check_directory(verifier *z)
{
    const labels_view *v = z->v;
    uint64_t at = 0;
    for (uint64_t g = 0; g < v->leaves; g++) {
        if (z->length[g] == UINT64_MAX)
            return problem(z->r, "no leaf has number %llu", (unsigned long long)g);
        uint64_t block = g >> v->block_shift, k = g & ((UINT64_C(1) << v->block_shift) - 1);
        uint64_t base = block * v->block_record_bits;
        uint64_t off = format_get(&v->dir, base, v->block_bits);
        if (k)
            off += format_get(&v->dir, base + v->block_bits + (k - 1) * v->offset_bits,
                              v->offset_bits);
        if (off != at)
            return problem(z->r, "leaf %llu's record starts at bit %llu, after the one before: %llu",
                           (unsigned long long)g, (unsigned long long)off,
                           (unsigned long long)at);
        at += z->length[g];
    }
    if (at != v->label_bits)
        return problem(z->r, "the records end at bit %llu of %llu", (unsigned long long)at,
                       (unsigned long long)v->label_bits);
    return HPFC_OK;
}

int hpfc_labels_verify(const hpfc_file *f, const hpfc_faces *fc, hpfc_labels_report *r)
{
    if (!f || !fc || !r)
        return HPFC_E_ARG;
    memset(r, 0, sizeof *r);
    const labels_view *v = &f->labels;
    if (!v->present)
        return HPFC_E_NO_SECTION;
    if (v->faces != hpfc_faces_face_count(fc))
        return problem(r, "the section counts %llu faces, the map has %llu",
                       (unsigned long long)v->faces, (unsigned long long)hpfc_faces_face_count(fc));
    int st = check_samples(f, v, r);
    if (st)
        return st;
    verifier z = {.f = f, .v = v, .fc = fc, .r = r};
    if (v->leaves > SIZE_MAX / sizeof *z.length || !(z.length = malloc((v->leaves ? v->leaves : 1) * sizeof *z.length)))
        return HPFC_E_NOMEM;
    memset(z.length, 0xFF, (v->leaves ? v->leaves : 1) * sizeof *z.length);
    if ((st = hpfc_walker_create(f, &z.w)) == HPFC_OK)
        st = hpfc_walker_set_cache_size(z.w, 0);
    hpfc_pixel px;
    uint64_t seen = 0;
    if (!st) {
        for (st = hpfc_leaf_first(f, &px); !st; st = hpfc_leaf_next(f, &px)) {
            if (++seen > v->leaves) {
                st = problem(r, "more leaves than the level table declares");
                break;
            }
            if ((st = check_leaf(&z, &px)))
                break;
        }
        if (st == HPFC_E_NO_PIXEL)
            st = check_directory(&z);
        else if (st != HPFC_E_CORRUPT || !r->message[0])
            st = problem(r, "leaf iteration: %s", hpfc_strerror(st));
    }
    hpfc_walker_free(z.w);
    free(z.length);
    return st;
}
