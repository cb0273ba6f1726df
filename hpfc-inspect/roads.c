#include "roads.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int roads_init(roads *r, const hpfc_file *file)
{
    memset(r, 0, sizeof *r);
    r->file = file;
    hpfc_file_info info;
    hpfc_file_get_info(file, &info);
    /* A valid walk passes each stabbing once; a corrupt file must not make
     * it loop, so it stops after as many steps as the file has crossings. */
    uint64_t steps = 1;
    for (uint32_t l = 0; l < info.levels; l++) {
        hpfc_level_info lv;
        if (hpfc_file_get_level(file, l, &lv))
            return HPFC_E_ARG;
        /* crossings a word can hold: k_w / 4, or k_w in the compact layout */
        uint64_t per_word = info.incompat_flags & 0x1 ? lv.word_bits : lv.word_bits / 4;
        if (per_word && lv.word_pixels > (UINT64_MAX - steps) / per_word)
            steps = UINT64_MAX;
        else
            steps += lv.word_pixels * per_word;
    }
    r->max_steps = steps;
    return HPFC_OK;
}

void roads_free(roads *r)
{
    free(r->buf);
    word_info_free(&r->a);
    word_info_free(&r->b);
    memset(r, 0, sizeof *r);
}

int roads_word(roads *r, const hpfc_pixel *px, size_t *len)
{
    int st = hpfc_pixel_word(r->file, px, NULL, 0, len);
    if (st)
        return st;
    if (*len + 1 > r->cap) {
        size_t cap = r->cap ? r->cap : 64;
        while (cap < *len + 1)
            cap *= 2;
        char *buf = realloc(r->buf, cap);
        if (!buf)
            return HPFC_E_NOMEM;
        r->buf = buf;
        r->cap = cap;
    }
    st = hpfc_pixel_word(r->file, px, r->buf, r->cap, len);
    if (!st)
        r->buf[*len] = '\0';
    return st;
}

int roads_parse(roads *r, const hpfc_pixel *px, word_info *wi)
{
    size_t len;
    int st = roads_word(r, px, &len);
    if (st)
        return st;
    int p = word_parse(wi, r->buf, len);
    return p == 0 ? HPFC_OK : p == -2 ? HPFC_E_NOMEM : HPFC_E_CORRUPT;
}

int roads_count(roads *r, const hpfc_pixel *px, int road, uint32_t *count)
{
    size_t len;
    uint32_t counts[4];
    int st = roads_word(r, px, &len);
    if (st)
        return st;
    word_road_counts(r->buf, len, counts);
    *count = counts[road];
    return HPFC_OK;
}

int roads_box(const hpfc_file *file, const hpfc_pixel *px, lbox *b)
{
    return hpfc_pixel_bounds(file, px, &b->x0, &b->y0, &b->x1, &b->y1);
}

int roads_leaf(const hpfc_file *file, const lbox *b, int road, int64_t t, bool across,
              hpfc_pixel *out, lbox *out_box)
{
    /* Cells are half-open with integer bounds of size >= 1, so the lattice
     * point one unit outside (or just inside) the road names the leaf. */
    int64_t x, y;
    road_point(b, road, t, !across, &x, &y);
    int st = hpfc_locate(file, x, y, out);
    if (!st && out_box)
        st = roads_box(file, out, out_box);
    return st;
}

static void spread(int64_t lo, int64_t hi, uint32_t c, double *pos)
{
    for (uint32_t a = 0; a < c; a++)
        pos[a] = (double)lo + (double)(hi - lo) * (a + 1) / (c + 1);
}

/* Ascending positions of the crossings along b's road when the leaves
 * across are smaller: each leaf's stretch holds its own crossings. */
static int spread_across(roads *r, const lbox *b, int road, uint32_t c, double *pos)
{
    int64_t lo, hi;
    road_extent(b, road, &lo, &hi);
    uint32_t done = 0;
    for (int64_t t = lo; t < hi;) {
        hpfc_pixel q;
        lbox qb;
        int64_t qlo, qhi;
        uint32_t cq;
        int st = roads_leaf(r->file, b, road, t, true, &q, &qb);
        if (!st)
            st = roads_count(r, &q, road_opposite(road), &cq);
        if (st)
            return st;
        road_extent(&qb, road, &qlo, &qhi);
        if (cq > c - done)
            return HPFC_E_CORRUPT;
        spread(qlo, qhi, cq, pos + done);
        done += cq;
        t = qhi;
    }
    return done == c ? HPFC_OK : HPFC_E_CORRUPT;
}

int roads_positions(roads *r, const lbox *b, int road, uint32_t c, double *pos)
{
    if (c == 0)
        return HPFC_OK;
    int64_t lo, hi, qlo, qhi;
    road_extent(b, road, &lo, &hi);
    hpfc_pixel q;
    lbox qb;
    int st = roads_leaf(r->file, b, road, lo, true, &q, &qb);
    if (st && st != HPFC_E_NO_PIXEL)
        return st;
    int spans = 1;
    if (!st) {
        road_extent(&qb, road, &qlo, &qhi);
        spans = qlo <= lo && qhi >= hi;
    }
    /* A corrupt count across still gets a picture: fall back to an even
     * spread along this leaf's own road. */
    if (spans || spread_across(r, b, road, c, pos) != HPFC_OK)
        spread(lo, hi, c, pos);
    if (!road_ascends(road))
        for (uint32_t a = 0; a < c / 2; a++) {
            double t = pos[a];
            pos[a] = pos[c - 1 - a];
            pos[c - 1 - a] = t;
        }
    return HPFC_OK;
}

/* Sum of road-`road` crossings of the leaves on b's side from t up to end. */
static int count_inside(roads *r, const lbox *b, int road, int64_t t, int64_t end,
                        uint64_t *sum)
{
    *sum = 0;
    while (t < end) {
        hpfc_pixel p;
        lbox pb;
        int64_t plo, phi;
        uint32_t c;
        int st = roads_leaf(r->file, b, road, t, false, &p, &pb);
        if (!st)
            st = roads_count(r, &p, road, &c);
        if (st)
            return st;
        road_extent(&pb, road, &plo, &phi);
        *sum += c;
        t = phi;
    }
    return HPFC_OK;
}

/* The leaf across b's road that holds the crossing with ascending index a
 * among b's crossings on that road, and that crossing's ascending index on
 * the facing road (§3.10 crossing identification, cases (a) and (b)). */
static int find_across(roads *r, const lbox *b, int road, uint64_t a, hpfc_pixel *q,
                       uint64_t *m_asc)
{
    int64_t lo, hi, qlo, qhi;
    road_extent(b, road, &lo, &hi);
    lbox qb;
    int st = roads_leaf(r->file, b, road, lo, true, q, &qb);
    if (st)
        return st == HPFC_E_NO_PIXEL ? HPFC_E_CORRUPT : st; /* a crossing on the domain's rim */
    road_extent(&qb, road, &qlo, &qhi);
    if (qlo <= lo && qhi >= hi) {
        /* (a): the facing road also lists the crossings of the leaves on
         * b's side that come before b along it */
        uint64_t before;
        if ((st = count_inside(r, b, road, qlo, lo, &before)))
            return st;
        *m_asc = before + a;
        return HPFC_OK;
    }
    /* (b): b's road is cut into the roads of smaller leaves across */
    for (int64_t t = lo; t < hi;) {
        uint32_t cq;
        if ((st = roads_leaf(r->file, b, road, t, true, q, &qb)) ||
            (st = roads_count(r, q, road_opposite(road), &cq)))
            return st;
        if (a < cq) {
            *m_asc = a;
            return HPFC_OK;
        }
        a -= cq;
        road_extent(&qb, road, &qlo, &qhi);
        t = qhi;
    }
    return HPFC_E_CORRUPT;
}

int roads_cross(roads *r, const hpfc_pixel *px, const word_info *wi, uint32_t k,
               hpfc_pixel *q, uint32_t *m)
{
    if (k >= wi->n)
        return HPFC_E_ARG;
    int road = word_road_of(wi, k), opp = road_opposite(road);
    uint32_t c = wi->road_off[road + 1] - wi->road_off[road], i = k - wi->road_off[road];
    lbox b;
    uint64_t m_asc;
    size_t len;
    uint32_t counts[4];
    int st = roads_box(r->file, px, &b);
    if (!st)
        st = find_across(r, &b, road, road_ascends(road) ? i : c - 1 - i, q, &m_asc);
    if (!st)
        st = roads_word(r, q, &len);
    if (st)
        return st;
    word_road_counts(r->buf, len, counts);
    if (m_asc >= counts[opp])
        return HPFC_E_CORRUPT;
    uint32_t off = 0;
    for (int d = 0; d < opp; d++)
        off += counts[d];
    *m = off + (uint32_t)(road_ascends(opp) ? m_asc : counts[opp] - 1 - m_asc);
    return HPFC_OK;
}

int roads_walk(roads *r, const hpfc_dart *d, uint64_t *stabbings, hpfc_dart *end)
{
    hpfc_pixel p = d->pixel, q;
    uint32_t k = d->crossing, m;
    word_info *here = &r->a, *there = &r->b;
    int st = roads_parse(r, &p, here);
    if (st)
        return st;
    *stabbings = 0;
    for (uint64_t step = 0; step < r->max_steps; step++) {
        if ((st = roads_cross(r, &p, here, k, &q, &m)) || (st = roads_parse(r, &q, there)))
            return st;
        if (m >= there->n)
            return HPFC_E_CORRUPT;
        uint32_t c = there->comp[m];
        if (there->comp_vertex[c] != WORD_NONE) {
            if (end) {
                end->pixel = q;
                end->crossing = m;
            }
            return HPFC_OK;
        }
        /* a stabbing: the dart leaves at the stabbing's other crossing */
        ++*stabbings;
        k = m == there->comp_first[c] ? there->comp_last[c] : there->comp_first[c];
        p = q;
        word_info *t = here;
        here = there;
        there = t;
    }
    return HPFC_E_CORRUPT;
}

void pixel_path_text(const hpfc_pixel *px, char *buf, size_t cap)
{
    size_t used = 0;
    if (cap)
        buf[0] = '\0';
    for (uint32_t l = 0; l <= px->depth && l < HPFC_MAX_LEVELS; l++) {
        int n = snprintf(buf + used, cap - used, "%s%u,%u", l ? "/" : "", px->path[l].i,
                         px->path[l].j);
        if (n < 0 || (size_t)n >= cap - used)
            return;
        used += (size_t)n;
    }
}
