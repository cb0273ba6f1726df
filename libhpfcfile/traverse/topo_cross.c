/*
 * The bottom of traversal (spec/hpfc-format.md, "Traversal"): a word
 * pixel's word decoded and parsed for a walker, and crossing
 * identification, which crossing of which leaf a crossing is seen from
 * across its road. Calls only the reader, words.h and road.h.
 *
 * A word pixel's crossings are numbered k = 0..n-1 in word order. Each
 * crossing carries an in-dart (entering the pixel) and an out-dart; inside a
 * pixel next(in_k) = out_pred[k], where pred is the cyclic predecessor of k
 * among its component's crossings (rpfc-operators §4).
 *
 * Crossing identification (paper Sect. 3.4) is done by one rule for its
 * three cases: the crossings of the two sides of a shared road segment, read
 * in opposite directions, are the same list. The leaves along a side are
 * found by exact point location on the lattice, which is what the half-open
 * pixels of the perturbation rule make possible.
 */
#include "file.h"
#include "reader.h"
#include "topo.h"

/* ---- parsing a word ----------------------------------------------------- */

int topo_decode_word(hpfc_walker *w, const hpfc_pixel *px, size_t *len)
{
    w->visited++;
    int st = hpfc_pixel_word(w->file, px, w->symbols, (size_t)w->cap + 4, len);
    return st == HPFC_E_ARG || st == HPFC_E_BUFFER_SMALL ? HPFC_E_CORRUPT : st;
}

int topo_parse_decoded(hpfc_walker *w, word_parts *lw, size_t len)
{
    if (lw == &w->p_word)
        w->p_word_valid = false; /* parse_p_word revalidates it */
    return word_parse_symbols(lw, w->symbols, len);
}

int topo_parse_pixel(hpfc_walker *w, word_parts *lw, const hpfc_pixel *px)
{
    size_t len;
    int st = topo_decode_word(w, px, &len);
    return st ? st : topo_parse_decoded(w, lw, len);
}

/* Crossings on one road of a word pixel, from its symbols. */
topo_result topo_road_count(hpfc_walker *w, const hpfc_pixel *px, int road, uint32_t *count)
{
    size_t len;
    int st = topo_decode_word(w, px, &len);
    if (!st)
        *count = word_road_count(w->symbols, len, road);
    return topo_done(st);
}

/* ---- crossing identification -------------------------------------------- */

int topo_leaf_box(const hpfc_file *f, const hpfc_pixel *px, road_box *b)
{
    return hpfc_pixel_bounds(f, px, &b->x0, &b->y0, &b->x1, &b->y1);
}

int topo_locate_on_road(const hpfc_file *f, const hpfc_pixel *near, const road_box *b, int road,
                        int64_t t, bool inside, hpfc_pixel *out, road_box *out_box)
{
    int64_t x, y;
    road_point(b, road, t, inside, &x, &y);
    int st = reader_locate_near(f, near, x, y, out);
    if (!st)
        st = topo_leaf_box(f, out, out_box);
    return st == HPFC_E_NO_PIXEL ? HPFC_E_CORRUPT : st;
}

topo_result topo_crossings_after(hpfc_walker *w, const hpfc_pixel *near, const road_box *b,
                                 int road, int64_t qlo, int64_t qhi, topo_road_counter count_of,
                                 uint64_t *sum)
{
    int64_t lo, hi;
    road_extent(b, road, &lo, &hi);
    bool up = road_ascends(road);
    int64_t t = up ? hi : lo - 1;
    *sum = 0;
    for (uint64_t steps = 0; up ? t < qhi : t >= qlo; steps++) {
        hpfc_pixel l;
        road_box lb;
        uint32_t count;
        int st = steps > w->leaf_budget
                     ? HPFC_E_CORRUPT
                     : topo_locate_on_road(w->file, steps ? &l : near, b, road, t, true, &l, &lb);
        topo_result r = st ? topo_done(st) : count_of(w, &l, road, &count);
        if (topo_stops(r))
            return r;
        *sum += count;
        int64_t llo, lhi;
        road_extent(&lb, road, &llo, &lhi);
        t = up ? lhi : llo - 1;
    }
    return topo_done(HPFC_OK);
}

/* Crossing k of word pixel P (parsed in lw), seen from the other side of its
 * road: the word pixel Q (parsed into qlw) and Q's crossing *m; *spans: Q
 * spans P's whole side (case (a) of Algorithm 1). */
int topo_cross_road_spans(hpfc_walker *w, const hpfc_pixel *p, bool p_located,
                          const word_parts *lw, uint32_t k, hpfc_pixel *q, word_parts *qlw,
                          uint32_t *m, bool *spans)
{
    *spans = false;
    const hpfc_file *f = w->file;
    int road = word_road_of_crossing(lw->road_off, k);
    int opposite = road_opposite(road);
    uint32_t c = lw->road_off[road + 1] - lw->road_off[road];
    uint32_t after = c - 1 - (k - lw->road_off[road]); /* crossings after k on P's road */
    road_box pb, qb;
    int st = topo_leaf_box(f, p, &pb);
    int64_t lo, hi, qlo, qhi;
    road_extent(&pb, road, &lo, &hi);
    /* Algorithm 1's first neighbour: the leaf across that spans P's side,
     * or the first of the smaller ones in their clockwise order */
    if (!st && (st = hpfc_pixel_move(f, p, road, q)) == HPFC_E_NO_PIXEL)
        st = HPFC_E_CORRUPT; /* a crossing on the domain's border */
    if (!st)
        st = topo_leaf_box(f, q, &qb);
    if (st)
        return st;
    road_extent(&qb, road, &qlo, &qhi);
    uint64_t rank = after;
    if (qlo <= lo && qhi >= hi) {
        /* Q spans P's whole side: add the crossings of the leaves on P's
         * side that follow P along Q's side, in P's clockwise order */
        uint64_t sum;
        /* the plain counter's flow is always TOPO_DONE: the status is all */
        if ((st = topo_crossings_after(w, p_located ? q : NULL, &pb, road, qlo, qhi,
                                       topo_road_count, &sum).status) ||
            (st = topo_parse_pixel(w, qlw, q)))
            return st;
        rank += sum;
        if (rank >= qlw->road_off[opposite + 1] - qlw->road_off[opposite])
            return HPFC_E_CORRUPT;
        *m = qlw->road_off[opposite] + (uint32_t)rank;
        *spans = true;
        return HPFC_OK;
    }
    /* Smaller leaves across: walk them in their own clockwise order along
     * P's side until the crossing's rank falls inside one of them. */
    bool up = road_ascends(opposite);
    int64_t t = up ? lo : hi - 1;
    for (uint64_t steps = 0; up ? t < hi : t >= lo; steps++) {
        if (steps > w->leaf_budget)
            return HPFC_E_CORRUPT;
        /* q came from p's path, then from a descent (reader_locate_near) */
        const hpfc_pixel *near = p_located || steps > 1 ? q : NULL;
        if (steps && (st = topo_locate_on_road(f, near, &pb, road, t, false, q, &qb)))
            return st;
        if ((st = topo_parse_pixel(w, qlw, q)))
            return st;
        uint32_t count = qlw->road_off[opposite + 1] - qlw->road_off[opposite];
        if (rank < count) {
            *m = qlw->road_off[opposite] + (uint32_t)rank;
            return HPFC_OK;
        }
        rank -= count;
        road_extent(&qb, road, &qlo, &qhi);
        t = up ? qhi : qlo - 1;
    }
    return HPFC_E_CORRUPT;
}

int topo_cross_road(hpfc_walker *w, const hpfc_pixel *p, bool p_located, const word_parts *lw,
                    uint32_t k, hpfc_pixel *q, word_parts *qlw, uint32_t *m)
{
    bool spans;
    return topo_cross_road_spans(w, p, p_located, lw, k, q, qlw, m, &spans);
}
