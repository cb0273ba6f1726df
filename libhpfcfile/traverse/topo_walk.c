/*
 * The walker: a dart followed through the stabbings of its edge to its
 * target, and the one word of a dart's or vertex's pixel, for the dart
 * operators of topo.c and the key operators of topo_keys.c alike. The
 * cache (topo_cache.c, topo_links.c) sits in front of the plain walk
 * here; both give the same answers (topo.h, "Three answer sources").
 */
#include <string.h>

#include "reader.h"
#include "topo.h"

/* ---- darts without the cache ---------------------------------------------- */

/* Parses px into w->p_word unless it is already there: operators on one dart
 * or vertex in a row parse its pixel once. */
static int parse_p_word(hpfc_walker *w, const hpfc_pixel *px)
{
    uint64_t slot;
    int st = reader_pixel_slot_bit(w->file, px, &slot);
    if (st)
        return st;
    if (w->p_word_valid && w->p_word_slot == slot)
        return HPFC_OK;
    w->p_word_valid = false;
    if ((st = topo_parse_pixel(w, &w->p_word, px)))
        return st;
    w->p_word_valid = true;
    w->p_word_slot = slot;
    return HPFC_OK;
}

/* Parses the dart's pixel into w->p_word and checks the dart names a
 * crossing of a junction there. */
static int load_dart(hpfc_walker *w, const hpfc_dart *d)
{
    int st = parse_p_word(w, &d->pixel);
    if (st)
        return st;
    if (d->crossing >= w->p_word.n || w->p_word.comp_vertex[w->p_word.comp[d->crossing]] == TOPO_NONE)
        return HPFC_E_ARG;
    return HPFC_OK;
}

/* Follows dart d (parsed in w->p_word) through its stabbings to the pixel of
 * its target vertex: on return w->q_word holds that pixel, *end the pixel
 * and *m the crossing where the edge enters it (in_m). */
static int walk(hpfc_walker *w, const hpfc_dart *d, hpfc_pixel *end, uint32_t *m)
{
    hpfc_pixel cur;
    int st = topo_copy_pixel(&cur, &d->pixel);
    uint32_t k = d->crossing;
    word_parts *at = &w->p_word, *next = &w->q_word;
    for (uint64_t steps = 0; !st; steps++) {
        if (steps > w->budget)
            return HPFC_E_CORRUPT;
        uint32_t mm;
        if ((st = topo_cross_road(w, &cur, false, at, k, end, next, &mm)))
            break;
        if (next->comp_vertex[next->comp[mm]] != TOPO_NONE) {
            if (next != &w->q_word) { /* keep the answer in w->q_word */
                word_parts t = w->q_word;
                w->q_word = w->p_word;
                w->p_word = t;
            }
            w->p_word_valid = false;
            *m = mm;
            return HPFC_OK;
        }
        /* a stabbing: leave through its other crossing */
        k = next->succ[mm];
        st = topo_copy_pixel(&cur, end);
        word_parts *t = at;
        at = next;
        next = t;
    }
    w->p_word_valid = false;
    return st;
}

/* Dart d, or with from_succ the dart out_succ(k) of its origin (prev(d) is
 * that dart's twin), followed to its target without the cache: *end gets
 * the target's pixel, written only on success. */
static int plain_arrive(hpfc_walker *w, const hpfc_dart *d, bool from_succ, hpfc_pixel *end,
                        topo_arrival *a)
{
    int st = load_dart(w, d);
    if (st)
        return st;
    hpfc_dart from;
    hpfc_pixel there;
    uint32_t m;
    from.crossing = from_succ ? w->p_word.succ[d->crossing] : d->crossing;
    if ((st = topo_copy_pixel(&from.pixel, &d->pixel)) || (st = walk(w, &from, &there, &m)))
        return st;
    a->m = m;
    a->pred = w->q_word.pred[m];
    a->vertex = w->q_word.comp_vertex[w->q_word.comp[m]];
    return topo_copy_pixel(end, &there);
}

/* ---- the one entry: the cache in front of the walk ------------------------- */

/* Through the cache when it can hold what the walk needs: a walk that
 * empties it starts again once, in the emptied cache; then, or for a word
 * the cache cannot hold, without it (topo.h, topo_result). The answers
 * are the same (topo.h, "Three answer sources"). */
int topo_arrive(hpfc_walker *w, const hpfc_dart *d, bool from_succ, hpfc_pixel *end,
                topo_arrival *a)
{
    for (int tries = 0; tries < 2; tries++) {
        topo_result r = topo_cached_arrive(w, d, from_succ, end, a);
        if (r.flow == TOPO_DONE)
            return r.status;
        if (r.flow == TOPO_UNCACHED)
            break;
    }
    return plain_arrive(w, d, from_succ, end, a);
}

int topo_parsed_word(hpfc_walker *w, const hpfc_pixel *px, cached_word **e)
{
    int st = topo_word_view(w, px, e);
    return st ? st : (*e)->parse_status;
}

int topo_dart_origin(hpfc_walker *w, const hpfc_dart *d, hpfc_vertex *out)
{
    cached_word *e;
    int st = topo_parsed_word(w, &d->pixel, &e);
    if (st)
        return st;
    if (d->crossing >= e->n || word_crossings(e)[d->crossing].vertex == TOPO_NONE)
        return HPFC_E_ARG;
    out->local = word_crossings(e)[d->crossing].vertex;
    return topo_copy_pixel(&out->pixel, &d->pixel);
}
