/*
 * Darts through the walker's cache (topo.h, topo_cache.c): crossing
 * identification recorded as links between cached words, and walks that
 * follow them.
 *
 * Crossing identification as topo_cross_road does it, for all crossings of
 * one road of a cached word at once (they share the neighbour, the leaves
 * walked and the sums), from that word's side only: each link is exactly
 * what topo_cross_road would answer for its crossing, a failure included. A
 * walk then follows links. An instruction (the cache emptied, or a word too
 * big for it: topo_flow) abandons the work without recording anything.
 */
#include <string.h>

#include "topo.h"

/* One road of a cached word P being identified. */
typedef struct road_job {
    uint32_t pref;           /* P's entry */
    int road, opposite;
    uint32_t first, count;   /* P's crossings on the road */
    road_box pb;             /* P's box */
} road_job;

static cached_word *entry_of(const hpfc_walker *w, uint32_t ref)
{
    return cache_entry(&w->cache, ref);
}

/* Crossing first + count - 1 - rank of P: the rank-th crossing of the road
 * counted from its end, i.e. with rank crossings after it. */
static cached_crossing *ranked(const hpfc_walker *w, const road_job *j, uint64_t rank)
{
    return &word_crossings(entry_of(w, j->pref))[j->first + j->count - 1 - (uint32_t)rank];
}

static void set_link(cached_crossing *x, uint32_t ref, uint32_t m)
{
    x->link_state = LINK_FOUND;
    x->link.ref = ref;
    x->link_m = m;
}

static void set_failed(cached_crossing *x, int status)
{
    x->link_state = LINK_FAILED;
    x->link.status = status;
    x->link_m = TOPO_NONE;
}

/* The crossings of ranks [from, count) failed with r's status, if it is a
 * failure; an instruction (the cache is gone) is passed on untouched. */
static topo_result fail_ranks(const hpfc_walker *w, const road_job *j, uint64_t from, topo_result r)
{
    if (r.flow != TOPO_DONE || r.status == HPFC_OK)
        return r;
    for (uint64_t rank = from; rank < j->count; rank++)
        set_failed(ranked(w, j, rank), r.status);
    return topo_done(HPFC_OK);
}

/* Crossings on road `road` of the word in entry ref. */
static uint32_t road_crossings(const hpfc_walker *w, uint32_t ref, int road)
{
    const cached_word *e = entry_of(w, ref);
    return e->road_off[road + 1] - e->road_off[road];
}

/* topo_road_counter from the cache: the leaf's word parsed once. */
static topo_result cached_road_count(hpfc_walker *w, const hpfc_pixel *px, int road,
                                     uint32_t *count)
{
    uint32_t ref;
    topo_result r = topo_cache_load(w, px, false, &ref);
    if (!topo_stops(r))
        *count = road_crossings(w, ref, road);
    return r;
}

/* The parsed entry of a neighbour: its grammar must hold. */
static topo_result load_neighbour(hpfc_walker *w, const hpfc_pixel *q, uint32_t *ref)
{
    topo_result r = topo_cache_load(w, q, false, ref);
    return topo_stops(r) ? r : topo_done(entry_of(w, *ref)->parse_status);
}

/* ---- links back ----
 *
 * Identifying P's road from P's side also answers, for a neighbour Q that
 * P spans, what topo_cross_road(Q, m) would compute for Q's crossings on
 * the opposite road, provided Q's own computation takes the same steps:
 * Algorithm 1 from Q leads back to P itself (the same path), Q's side lies
 * inside P's and on P's road line (so Q locates the same points P's walk
 * located), and P's walk covered the whole side without an error (so the
 * leaves after Q and their counts are known). Q's answers are then
 * recorded too, and Q never identifies that road itself: each road between
 * two leaves is identified once, from the larger (or either equal) side.
 * When any condition fails, Q identifies the road itself later. */

/* Q's side (road_box qb) lies inside P's on P's road line. */
static bool on_side(const road_job *j, const road_box *qb)
{
    int64_t lo, hi, qlo, qhi;
    road_extent(&j->pb, j->road, &lo, &hi);
    road_extent(qb, j->road, &qlo, &qhi);
    return qlo >= lo && qhi <= hi && road_line(qb, j->opposite) == road_line(&j->pb, j->road);
}

/* Does Algorithm 1 from Q across the opposite road lead to P's path? */
static bool moves_back(hpfc_walker *w, const road_job *j, uint32_t qref)
{
    hpfc_pixel qpx, r;
    cached_word *pe = entry_of(w, j->pref);
    topo_entry_pixel(entry_of(w, qref), &qpx);
    return hpfc_pixel_move(w->file, &qpx, j->opposite, &r) == HPFC_OK && r.depth == pe->depth &&
           memcmp(r.path, word_path(pe), ((size_t)r.depth + 1) * sizeof(path_step)) == 0;
}

/* Q's crossings on the opposite road, `after` crossings of leaves after Q
 * on P's side: topo_cross_road's case (a) seen from Q, rank by rank. */
static void link_back(hpfc_walker *w, const road_job *j, uint32_t qref, uint64_t after)
{
    cached_word *qe = entry_of(w, qref);
    uint32_t qfirst = qe->road_off[j->opposite], qcount = road_crossings(w, qref, j->opposite);
    uint32_t pfirst = entry_of(w, j->pref)->road_off[j->road];
    if (!qcount || word_crossings(qe)[qfirst].link_state != LINK_UNKNOWN)
        return; /* nothing to link, or linked already (to the same answers) */
    if (!moves_back(w, j, qref))
        return;
    for (uint32_t x = 0; x < qcount; x++) {
        uint64_t rank = (uint64_t)(qcount - 1 - x) + after;
        cached_crossing *c = &word_crossings(qe)[qfirst + x];
        if (rank < j->count)
            set_link(c, j->pref, pfirst + (uint32_t)rank);
        else
            set_failed(c, HPFC_E_CORRUPT);
    }
}

/* Case (a): Q spans P's side. */
static topo_result link_to_spanning(hpfc_walker *w, const road_job *j, const hpfc_pixel *q,
                                    const road_box *qb)
{
    int64_t lo, hi, qlo, qhi;
    road_extent(&j->pb, j->road, &lo, &hi);
    road_extent(qb, j->road, &qlo, &qhi);
    uint64_t sum;
    uint32_t qref;
    /* from the root: q has P's path above its level, a caller's (topo_cross_road) */
    topo_result r = topo_crossings_after(w, NULL, &j->pb, j->road, qlo, qhi, cached_road_count, &sum);
    if (!topo_stops(r))
        r = load_neighbour(w, q, &qref);
    if (topo_stops(r))
        return fail_ranks(w, j, 0, r);
    uint32_t qfirst = entry_of(w, qref)->road_off[j->opposite];
    uint32_t qcount = road_crossings(w, qref, j->opposite);
    for (uint64_t rank = 0; rank < j->count; rank++) {
        if (rank + sum < qcount)
            set_link(ranked(w, j, rank), qref, qfirst + (uint32_t)(rank + sum));
        else
            set_failed(ranked(w, j, rank), HPFC_E_CORRUPT);
    }
    if (qlo == lo && qhi == hi) /* equal sides: no leaf after Q, no point located */
        link_back(w, j, qref, 0);
    return topo_done(HPFC_OK);
}

/* The leaves of P's side in case (b), as far as links back need them. */
enum { SIDE_LEAVES = 32 };

typedef struct side_leaf {
    uint32_t ref, count;     /* its entry and its crossings on the opposite road */
    bool on_side;
} side_leaf;

/* Case (b): smaller leaves across, walked in their own clockwise order;
 * each takes the next ranks of P's crossings. The walk goes on to the end
 * of the side (while the leaves fit in SIDE_LEAVES) to link back; what it
 * meets after P's last crossing never changes P's links. */
static topo_result link_along(hpfc_walker *w, const road_job *j, hpfc_pixel *q, road_box *qb)
{
    int64_t lo, hi;
    road_extent(&j->pb, j->road, &lo, &hi);
    bool up = road_ascends(j->opposite);
    int64_t t = up ? lo : hi - 1;
    uint64_t base = 0; /* ranks taken by the leaves before */
    topo_result r = topo_done(HPFC_E_CORRUPT); /* the side ends before the last crossing */
    side_leaf leaves[SIDE_LEAVES];
    size_t n = 0;
    bool whole = true; /* every leaf so far is in leaves[] */
    for (uint64_t steps = 0; (base < j->count || whole) && (up ? t < hi : t >= lo); steps++) {
        uint32_t qref;
        if (steps > w->leaf_budget) {
            r = topo_done(HPFC_E_CORRUPT);
            whole = false;
            break;
        }
        const hpfc_pixel *near = steps > 1 ? q : NULL; /* as topo_cross_road's */
        int st = steps ? topo_locate_on_road(w->file, near, &j->pb, j->road, t, false, q, qb)
                       : HPFC_OK;
        r = st ? topo_done(st) : load_neighbour(w, q, &qref);
        if (topo_stops(r)) {
            whole = false;
            break;
        }
        uint32_t qfirst = entry_of(w, qref)->road_off[j->opposite];
        uint32_t qcount = road_crossings(w, qref, j->opposite);
        for (uint64_t rank = base; rank < base + qcount && rank < j->count; rank++)
            set_link(ranked(w, j, rank), qref, qfirst + (uint32_t)(rank - base));
        base += qcount;
        if (n < SIDE_LEAVES)
            leaves[n++] = (side_leaf){qref, qcount, on_side(j, qb)};
        else
            whole = false;
        int64_t qlo, qhi;
        road_extent(qb, j->road, &qlo, &qhi);
        t = up ? qhi : qlo - 1;
        r = topo_done(HPFC_E_CORRUPT);
    }
    if (r.flow != TOPO_DONE) /* the cache is gone, even if P's crossings were all placed */
        return r;
    if (base < j->count)
        return fail_ranks(w, j, base, r);
    uint64_t after = 0;
    for (size_t i = n; whole && i-- > 0; after += leaves[i].count)
        if (leaves[i].on_side)
            link_back(w, j, leaves[i].ref, after);
    return topo_done(HPFC_OK);
}

/* Identifies every crossing of P's road `road` (P parsed in entry pref). */
static topo_result link_road(hpfc_walker *w, uint32_t pref, int road)
{
    cached_word *pe = entry_of(w, pref);
    road_job j = {pref, road, road_opposite(road), pe->road_off[road], road_crossings(w, pref, road), {0}};
    hpfc_pixel p, q;
    road_box qb;
    topo_entry_pixel(pe, &p);
    int st = topo_leaf_box(w->file, &p, &j.pb);
    /* Algorithm 1's first neighbour: the leaf across that spans P's side,
     * or the first of the smaller ones in their clockwise order */
    if (!st && (st = hpfc_pixel_move(w->file, &p, road, &q)) == HPFC_E_NO_PIXEL)
        st = HPFC_E_CORRUPT; /* a crossing on the domain's border */
    if (!st)
        st = topo_leaf_box(w->file, &q, &qb);
    if (st)
        return fail_ranks(w, &j, 0, topo_done(st));
    int64_t lo, hi, qlo, qhi;
    road_extent(&j.pb, road, &lo, &hi);
    road_extent(&qb, road, &qlo, &qhi);
    if (qlo <= lo && qhi >= hi)
        return link_to_spanning(w, &j, &q, &qb);
    return link_along(w, &j, &q, &qb);
}

/* The cached word of a dart's pixel, checked as load_dart checks it. */
static topo_result cached_dart(hpfc_walker *w, const hpfc_dart *d, uint32_t *ref)
{
    topo_result r = topo_cache_load(w, &d->pixel, true, ref);
    if (topo_stops(r))
        return r;
    cached_word *e = entry_of(w, *ref);
    if (e->parse_status)
        return topo_done(e->parse_status);
    if (d->crossing >= e->n || word_crossings(e)[d->crossing].vertex == TOPO_NONE)
        return topo_done(HPFC_E_ARG);
    return topo_done(HPFC_OK);
}

/* The answer of an arrival recorded in entry ref, crossing m. */
static void arrived(hpfc_walker *w, uint32_t ref, uint32_t m, hpfc_pixel *end, topo_arrival *a)
{
    cached_word *e = entry_of(w, ref);
    const cached_crossing *y = &word_crossings(e)[m];
    *a = (topo_arrival){m, y->pred, y->vertex};
    topo_entry_pixel(e, end);
}

/* The plain walk through the cache: links across roads, identified on first
 * use; through a stabbing, on by its other crossing. The end of the walk is
 * recorded at the crossing it started from (failures are not: a failed
 * walk stops at the first failed link anyway). */
topo_result topo_cached_follow(hpfc_walker *w, uint32_t ref, uint32_t k, uint32_t *end_ref,
                               uint32_t *end_m)
{
    cached_word *e = entry_of(w, ref);
    cached_crossing *start = &word_crossings(e)[k];
    uint32_t start_ref = ref, start_k = k;
    if (start->arrival) {
        *end_ref = start->arrival;
        *end_m = start->arrival_m;
        return topo_done(HPFC_OK);
    }
    for (uint64_t steps = 0;; steps++) {
        if (steps > w->budget)
            return topo_done(HPFC_E_CORRUPT);
        cached_crossing *x = &word_crossings(e)[k];
        if (x->link_state == LINK_UNKNOWN) {
            topo_result r = link_road(w, ref, word_road_of_crossing(e->road_off, k));
            if (topo_stops(r))
                return r;
        }
        if (x->link_state == LINK_UNKNOWN) /* link_road leaves no crossing of the road unanswered */
            return topo_done(HPFC_E_CORRUPT);
        if (x->link_state == LINK_FAILED)
            return topo_done(x->link.status);
        ref = x->link.ref;
        e = entry_of(w, ref);
        const cached_crossing *y = &word_crossings(e)[x->link_m];
        if (y->vertex != TOPO_NONE) {
            start->arrival = *end_ref = ref;
            start->arrival_m = *end_m = x->link_m;
            topo_block_arrival(w, start_ref, start_k);
            return topo_done(HPFC_OK);
        }
        k = y->succ; /* a stabbing: leave through its other crossing */
    }
}

topo_result topo_cached_arrive(hpfc_walker *w, const hpfc_dart *d, bool from_succ,
                               hpfc_pixel *end, topo_arrival *a)
{
    uint32_t ref, end_ref, m;
    topo_result r = cached_dart(w, d, &ref);
    if (topo_stops(r))
        return r;
    uint32_t k = from_succ ? word_crossings(entry_of(w, ref))[d->crossing].succ : d->crossing;
    r = topo_cached_follow(w, ref, k, &end_ref, &m);
    if (topo_stops(r))
        return r;
    arrived(w, end_ref, m, end, a);
    return topo_done(HPFC_OK);
}
