/*
 * Graph traversal on an open file (spec/hpfc-format.md, "Traversal"):
 * vertices and darts of the input graph, read straight from the pools.
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
#include <stdlib.h>
#include <string.h>

#include "file.h"
#include "internal.h"
#include "reader.h"

#include "topo.h"

static void local_free(local_word *lw)
{
    free(lw->comp), free(lw->pred), free(lw->succ), free(lw->comp_vertex);
    free(lw->comp_first), free(lw->comp_last), free(lw->comp_size);
    free(lw->vertex_comp), free(lw->stack), free(lw->sym);
}

static int local_alloc(local_word *lw, uint32_t cap)
{
    size_t n = (size_t)cap + 1;
    lw->comp = malloc(n * sizeof(uint32_t));
    lw->pred = malloc(n * sizeof(uint32_t));
    lw->succ = malloc(n * sizeof(uint32_t));
    lw->comp_vertex = malloc(n * sizeof(uint32_t));
    lw->comp_first = malloc(n * sizeof(uint32_t));
    lw->comp_last = malloc(n * sizeof(uint32_t));
    lw->comp_size = malloc(n * sizeof(uint32_t));
    lw->vertex_comp = malloc(n * sizeof(uint32_t));
    lw->stack = malloc(n * sizeof(uint32_t));
    lw->sym = malloc(n + 4);
    if (!lw->comp || !lw->pred || !lw->succ || !lw->comp_vertex || !lw->comp_first ||
        !lw->comp_last || !lw->comp_size || !lw->vertex_comp || !lw->stack || !lw->sym)
        return HPFC_E_NOMEM;
    return HPFC_OK;
}

int hpfc_walker_create(const hpfc_file *file, hpfc_walker **out)
{
    if (!file || !out)
        return HPFC_E_ARG;
    *out = NULL;
    hpfc_walker *w = calloc(1, sizeof *w);
    if (!w)
        return HPFC_E_NOMEM;
    w->file = file;
    w->cap = file_max_crossings(file);
    w->budget = file_total_crossings(file) + 1;
    /* a road can border more leaves than the file has crossings (private
     * leaves around a deep refinement), never more than it has leaves */
    w->leaf_budget = file_total_leaves(file) + 1;
    int st = local_alloc(&w->p_word, w->cap);
    if (!st)
        st = local_alloc(&w->q_word, w->cap);
    if (!st && !(w->scratch = malloc((size_t)w->cap + 4)))
        st = HPFC_E_NOMEM;
    if (!st)
        st = topo_cache_init(w, HPFC_WALKER_DEFAULT_CACHE);
    if (st == HPFC_E_NOMEM && w->uncached)
        st = HPFC_OK; /* no room for the default cache: walk without it */
    if (st) {
        hpfc_walker_free(w);
        return st;
    }
    *out = w;
    return HPFC_OK;
}

uint64_t hpfc_walker_pixels_visited(const hpfc_walker *w)
{
    return w ? w->visited : 0;
}

void hpfc_walker_free(hpfc_walker *w)
{
    if (!w)
        return;
    local_free(&w->p_word);
    local_free(&w->q_word);
    free(w->scratch);
    topo_cache_free(w);
    topo_keys_free(w);
    free(w);
}

/* ---- parsing a word ----------------------------------------------------- */

static void add_crossing(local_word *lw, uint32_t k, uint32_t c)
{
    lw->comp[k] = c;
    if (lw->comp_last[c] == TOPO_NONE) {
        lw->comp_first[c] = k;
    } else {
        lw->succ[lw->comp_last[c]] = k;
        lw->pred[k] = lw->comp_last[c];
    }
    lw->comp_last[c] = k;
    lw->comp_size[c]++;
}

static uint32_t new_component(local_word *lw, bool junction)
{
    uint32_t c = lw->ncomp++;
    lw->comp_last[c] = TOPO_NONE;
    lw->comp_size[c] = 0;
    lw->comp_vertex[c] = TOPO_NONE;
    if (junction) {
        lw->vertex_comp[lw->nvert] = c;
        lw->comp_vertex[c] = lw->nvert++;
    }
    return c;
}

/* Parses the grammar of rpfc-operators §2 with a stack; any violation is
 * corruption of the file. */
int topo_parse_symbols(local_word *lw, const char *sym, size_t len)
{
    uint32_t depth = 0, plus = 0;
    lw->n = lw->ncomp = lw->nvert = 0;
    lw->road_off[0] = 0;
    for (size_t s = 0; s < len; s++) {
        char c = sym[s];
        if (c == '+') {
            lw->road_off[++plus] = lw->n;
            continue;
        }
        uint32_t k = lw->n++, top = depth ? lw->stack[depth - 1] : TOPO_NONE;
        switch (c) {
        case '=': add_crossing(lw, k, new_component(lw, true)); break;
        case '(':
        case '[': {
            uint32_t comp = new_component(lw, c == '(');
            lw->stack[depth++] = comp;
            add_crossing(lw, k, comp);
            break;
        }
        case 'Y':
            if (top == TOPO_NONE || lw->comp_vertex[top] == TOPO_NONE)
                return HPFC_E_CORRUPT;
            add_crossing(lw, k, top);
            break;
        default: /* ')' or ']' */
            if (top == TOPO_NONE || (lw->comp_vertex[top] == TOPO_NONE) != (c == ']'))
                return HPFC_E_CORRUPT;
            depth--;
            add_crossing(lw, k, top);
        }
    }
    if (plus != 4 || depth != 0)
        return HPFC_E_CORRUPT;
    for (uint32_t comp = 0; comp < lw->ncomp; comp++) {
        lw->pred[lw->comp_first[comp]] = lw->comp_last[comp];
        lw->succ[lw->comp_last[comp]] = lw->comp_first[comp];
    }
    return HPFC_OK;
}

/* What the grammar does not decide: the crossings of each road. */
void topo_count_roads(local_word *lw, const char *sym, size_t len)
{
    uint32_t plus = 0;
    lw->n = 0;
    lw->road_off[0] = 0;
    for (size_t s = 0; s < len && plus < 4; s++) {
        if (sym[s] == '+')
            lw->road_off[++plus] = lw->n;
        else
            lw->n++;
    }
    while (plus < 4) /* not reached: a decoded word has four '+' */
        lw->road_off[++plus] = lw->n;
}

int topo_decode_word(hpfc_walker *w, local_word *lw, const hpfc_pixel *px, size_t *len)
{
    w->visited++;
    if (lw == &w->p_word)
        w->p_word_valid = false; /* parse_p_word revalidates it */
    int st = hpfc_pixel_word(w->file, px, lw->sym, (size_t)w->cap + 4, len);
    return st == HPFC_E_ARG || st == HPFC_E_BUFFER_SMALL ? HPFC_E_CORRUPT : st;
}

int topo_parse_pixel(hpfc_walker *w, local_word *lw, const hpfc_pixel *px)
{
    size_t len;
    int st = topo_decode_word(w, lw, px, &len);
    return st ? st : topo_parse_symbols(lw, lw->sym, len);
}

/* Crossings on one road of a word pixel, from its symbols. */
int topo_road_count(hpfc_walker *w, const hpfc_pixel *px, int road, uint32_t *count)
{
    size_t len;
    w->visited++;
    int st = hpfc_pixel_word(w->file, px, w->scratch, (size_t)w->cap + 4, &len);
    if (st)
        return st == HPFC_E_ARG || st == HPFC_E_BUFFER_SMALL ? HPFC_E_CORRUPT : st;
    int r = 0;
    *count = 0;
    for (size_t s = 0; s < len && r <= road; s++) {
        if (w->scratch[s] == '+')
            r++;
        else if (r == road)
            (*count)++;
    }
    return HPFC_OK;
}

/* ---- crossing identification -------------------------------------------- */

int topo_leaf_box(const hpfc_file *f, const hpfc_pixel *px, topo_box *b)
{
    return hpfc_pixel_bounds(f, px, &b->x0, &b->y0, &b->x1, &b->y1);
}

/* The lattice point at position t along road `road` of topo_box b, on b's side
 * (inside = true) or just across the road. */
static void road_point(const topo_box *b, int road, int64_t t, bool inside, int64_t *x, int64_t *y)
{
    switch (road) {
    case HPFC_WEST: *x = inside ? b->x0 : b->x0 - 1, *y = t; break;
    case HPFC_EAST: *x = inside ? b->x1 - 1 : b->x1, *y = t; break;
    case HPFC_NORTH: *x = t, *y = inside ? b->y1 - 1 : b->y1; break;
    default: *x = t, *y = inside ? b->y0 : b->y0 - 1; break;
    }
}

/* Extent of topo_box b along the line of `road`: [lo, hi). */
void topo_road_extent(const topo_box *b, int road, int64_t *lo, int64_t *hi)
{
    bool vertical = road == HPFC_WEST || road == HPFC_EAST;
    *lo = vertical ? b->y0 : b->x0;
    *hi = vertical ? b->y1 : b->x1;
}

/* Does the road run toward increasing coordinates in its own clockwise
 * order? W runs north, N east, E south, S west. */
bool topo_road_ascends(int road)
{
    return road == HPFC_WEST || road == HPFC_NORTH;
}

int topo_locate_on_road(const hpfc_file *f, const hpfc_pixel *near, const topo_box *b, int road,
                        int64_t t, bool inside, hpfc_pixel *out, topo_box *out_box)
{
    int64_t x, y;
    road_point(b, road, t, inside, &x, &y);
    int st = reader_locate_near(f, near, x, y, out);
    if (!st)
        st = topo_leaf_box(f, out, out_box);
    return st == HPFC_E_NO_PIXEL ? HPFC_E_CORRUPT : st;
}

int topo_crossings_after(hpfc_walker *w, const hpfc_pixel *near, const topo_box *b, int road,
                         int64_t qlo, int64_t qhi, topo_road_counter count_of, uint64_t *sum)
{
    int64_t lo, hi;
    topo_road_extent(b, road, &lo, &hi);
    bool up = topo_road_ascends(road);
    int64_t t = up ? hi : lo - 1;
    *sum = 0;
    for (uint64_t steps = 0; up ? t < qhi : t >= qlo; steps++) {
        hpfc_pixel l;
        topo_box lb;
        uint32_t count;
        int st = steps > w->leaf_budget
                     ? HPFC_E_CORRUPT
                     : topo_locate_on_road(w->file, steps ? &l : near, b, road, t, true, &l, &lb);
        if (!st)
            st = count_of(w, &l, road, &count);
        if (st)
            return st;
        *sum += count;
        int64_t llo, lhi;
        topo_road_extent(&lb, road, &llo, &lhi);
        t = up ? lhi : llo - 1;
    }
    return HPFC_OK;
}

/* Crossing k of word pixel P (parsed in lw), seen from the other side of its
 * road: the word pixel Q (parsed into qlw) and Q's crossing *m. */
int topo_cross_road(hpfc_walker *w, const hpfc_pixel *p, bool p_located, const local_word *lw,
                    uint32_t k, hpfc_pixel *q, local_word *qlw, uint32_t *m)
{
    const hpfc_file *f = w->file;
    int road = 0;
    while (road < 3 && k >= lw->road_off[road + 1])
        road++;
    int opposite = (road + 2) % 4;
    uint32_t c = lw->road_off[road + 1] - lw->road_off[road];
    uint32_t after = c - 1 - (k - lw->road_off[road]); /* crossings after k on P's road */
    topo_box pb, qb;
    int st = topo_leaf_box(f, p, &pb);
    int64_t lo, hi, qlo, qhi;
    topo_road_extent(&pb, road, &lo, &hi);
    /* Algorithm 1's first neighbour: the leaf across that spans P's side,
     * or the first of the smaller ones in their clockwise order */
    if (!st && (st = hpfc_pixel_move(f, p, road, q)) == HPFC_E_NO_PIXEL)
        st = HPFC_E_CORRUPT; /* a crossing on the domain's border */
    if (!st)
        st = topo_leaf_box(f, q, &qb);
    if (st)
        return st;
    topo_road_extent(&qb, road, &qlo, &qhi);
    uint64_t rank = after;
    if (qlo <= lo && qhi >= hi) {
        /* Q spans P's whole side: add the crossings of the leaves on P's
         * side that follow P along Q's side, in P's clockwise order */
        uint64_t sum;
        if ((st = topo_crossings_after(w, p_located ? q : NULL, &pb, road, qlo, qhi,
                                       topo_road_count, &sum)) ||
            (st = topo_parse_pixel(w, qlw, q)))
            return st;
        rank += sum;
        if (rank >= qlw->road_off[opposite + 1] - qlw->road_off[opposite])
            return HPFC_E_CORRUPT;
        *m = qlw->road_off[opposite] + (uint32_t)rank;
        return HPFC_OK;
    }
    /* Smaller leaves across: walk them in their own clockwise order along
     * P's side until the crossing's rank falls inside one of them. */
    bool up = topo_road_ascends(opposite);
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
        topo_road_extent(&qb, road, &qlo, &qhi);
        t = up ? qhi : qlo - 1;
    }
    return HPFC_E_CORRUPT;
}

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

static int copy_pixel(hpfc_pixel *dst, const hpfc_pixel *src)
{
    if (src->depth >= HPFC_MAX_LEVELS)
        return HPFC_E_ARG;
    dst->depth = src->depth;
    memcpy(dst->path, src->path, (src->depth + 1) * sizeof src->path[0]);
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
    int st = copy_pixel(&cur, &d->pixel);
    uint32_t k = d->crossing;
    local_word *at = &w->p_word, *next = &w->q_word;
    for (uint64_t steps = 0; !st; steps++) {
        if (steps > w->budget)
            return HPFC_E_CORRUPT;
        uint32_t mm;
        if ((st = topo_cross_road(w, &cur, false, at, k, end, next, &mm)))
            break;
        if (next->comp_vertex[next->comp[mm]] != TOPO_NONE) {
            if (next != &w->q_word) { /* keep the answer in w->q_word */
                local_word t = w->q_word;
                w->q_word = w->p_word;
                w->p_word = t;
            }
            w->p_word_valid = false;
            *m = mm;
            return HPFC_OK;
        }
        /* a stabbing: leave through its other crossing */
        k = next->succ[mm];
        st = copy_pixel(&cur, end);
        local_word *t = at;
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
    if ((st = copy_pixel(&from.pixel, &d->pixel)) || (st = walk(w, &from, &there, &m)))
        return st;
    a->m = m;
    a->pred = w->q_word.pred[m];
    a->vertex = w->q_word.comp_vertex[w->q_word.comp[m]];
    return copy_pixel(end, &there);
}

/* Through the cache when it can hold what the walk needs: a walk that
 * empties it starts again once, in the emptied cache; then, or for a word
 * the cache cannot hold, without it. The answers are the same. */
static int arrive(hpfc_walker *w, const hpfc_dart *d, bool from_succ, hpfc_pixel *end, topo_arrival *a)
{
    if (!w || !d)
        return HPFC_E_ARG;
    for (int tries = 0; tries < 2; tries++) {
        int st = topo_cached_arrive(w, d, from_succ, end, a);
        if (st >= 0)
            return st;
        if (st == TOPO_UNCACHED)
            break;
    }
    return plain_arrive(w, d, from_succ, end, a);
}

int hpfc_dart_twin(hpfc_walker *w, const hpfc_dart *d, hpfc_dart *out)
{
    topo_arrival a;
    int st = out ? arrive(w, d, false, &out->pixel, &a) : HPFC_E_ARG;
    if (!st)
        out->crossing = a.m; /* twin(d) = out_m where d arrives */
    return st;
}

int hpfc_dart_next(hpfc_walker *w, const hpfc_dart *d, hpfc_dart *out)
{
    topo_arrival a;
    int st = out ? arrive(w, d, false, &out->pixel, &a) : HPFC_E_ARG;
    if (!st)
        out->crossing = a.pred; /* next(in_m) = out_pred[m] */
    return st;
}

int hpfc_dart_prev(hpfc_walker *w, const hpfc_dart *d, hpfc_dart *out)
{
    topo_arrival a; /* prev(out_k) = twin(out_succ[k]) */
    int st = out ? arrive(w, d, true, &out->pixel, &a) : HPFC_E_ARG;
    if (!st)
        out->crossing = a.m;
    return st;
}

int hpfc_dart_target(hpfc_walker *w, const hpfc_dart *d, hpfc_vertex *out)
{
    topo_arrival a;
    int st = out ? arrive(w, d, false, &out->pixel, &a) : HPFC_E_ARG;
    if (!st)
        out->local = a.vertex;
    return st;
}

/* ---- one word at a time: origins and vertices ------------------------------- */

/* The parsed word of a caller's pixel (from the cache, or built alone). */
static int parsed_word(hpfc_walker *w, const hpfc_pixel *px, cached_word **e)
{
    int st = topo_word_view(w, px, e);
    return st ? st : (*e)->parse_status;
}

int hpfc_dart_origin(hpfc_walker *w, const hpfc_dart *d, hpfc_vertex *out)
{
    if (!w || !d || !out)
        return HPFC_E_ARG;
    cached_word *e;
    int st = parsed_word(w, &d->pixel, &e);
    if (st)
        return st;
    if (d->crossing >= e->n || word_crossings(e)[d->crossing].vertex == TOPO_NONE)
        return HPFC_E_ARG;
    out->local = word_crossings(e)[d->crossing].vertex;
    return copy_pixel(&out->pixel, &d->pixel);
}

int hpfc_pixel_vertex_count(hpfc_walker *w, const hpfc_pixel *px, uint32_t *count)
{
    if (!w || !px || !count)
        return HPFC_E_ARG;
    cached_word *e;
    int st = parsed_word(w, px, &e);
    if (!st)
        *count = e->nvert;
    return st;
}

int hpfc_pixel_vertex(hpfc_walker *w, const hpfc_pixel *px, uint32_t index, hpfc_vertex *out)
{
    uint32_t count;
    int st = hpfc_pixel_vertex_count(w, px, &count);
    if (st)
        return st;
    if (index >= count || !out)
        return HPFC_E_ARG;
    out->local = index;
    return copy_pixel(&out->pixel, px);
}

/* The parsed word of a vertex's pixel, and the vertex in it. */
static int load_vertex(hpfc_walker *w, const hpfc_vertex *v, cached_word **e, cached_vertex *out)
{
    int st = parsed_word(w, &v->pixel, e);
    if (!st && v->local >= (*e)->nvert)
        st = HPFC_E_ARG;
    if (!st)
        *out = word_vertices(*e)[v->local];
    return st;
}

int hpfc_vertex_degree(hpfc_walker *w, const hpfc_vertex *v, uint32_t *degree)
{
    if (!w || !v || !degree)
        return HPFC_E_ARG;
    cached_word *e;
    cached_vertex cv;
    int st = load_vertex(w, v, &e, &cv);
    if (!st)
        *degree = cv.degree;
    return st;
}

int hpfc_vertex_dart(hpfc_walker *w, const hpfc_vertex *v, uint32_t index, hpfc_dart *out)
{
    if (!w || !v || !out)
        return HPFC_E_ARG;
    cached_word *e;
    cached_vertex cv;
    int st = load_vertex(w, v, &e, &cv);
    if (st)
        return st;
    if (index >= cv.degree)
        return HPFC_E_ARG;
    uint32_t k = cv.first;
    for (uint32_t s = 0; s < index; s++)  /* word order is clockwise around the vertex */
        k = word_crossings(e)[k].succ;
    out->crossing = k;
    return copy_pixel(&out->pixel, &v->pixel);
}

/* ---- identifiers and iteration ------------------------------------------ */

uint64_t hpfc_vertex_key(const hpfc_file *f, const hpfc_vertex *v)
{
    uint64_t slot = 0;
    reader_pixel_slot_bit(f, &v->pixel, &slot);
    return topo_key(slot, v->local);
}

uint64_t hpfc_dart_key(const hpfc_file *f, const hpfc_dart *d)
{
    uint64_t slot = 0;
    reader_pixel_slot_bit(f, &d->pixel, &slot);
    return topo_key(slot, d->crossing);
}

/* Descends from px to the first leaf below it (pixel (0,0) of each image). */
static int first_leaf_below(const hpfc_file *f, hpfc_pixel *px)
{
    for (;;) {
        int type, st = hpfc_pixel_type(f, px, &type);
        if (st || type == HPFC_PIXEL_WORD)
            return st;
        if ((st = hpfc_pixel_child(f, px, 0, 0, px)))
            return st;
    }
}

int hpfc_leaf_first(const hpfc_file *f, hpfc_pixel *px)
{
    if (!f || !px)
        return HPFC_E_ARG;
    int st = hpfc_pixel_root(f, 0, 0, px);
    return st ? st : first_leaf_below(f, px);
}

int hpfc_leaf_next(const hpfc_file *f, hpfc_pixel *px)
{
    if (!f || !px || px->depth >= HPFC_MAX_LEVELS)
        return HPFC_E_ARG;
    hpfc_file_info info;
    hpfc_file_get_info(f, &info);
    for (;;) {
        uint32_t d = px->depth;
        uint32_t cols = d ? info.cols : info.root_cols, rows = d ? info.rows : info.root_rows;
        uint32_t i = px->path[d].i, j = px->path[d].j;
        if (i + 1 < cols || j + 1 < rows) {
            i = i + 1 < cols ? i + 1 : 0;
            j = i == 0 ? j + 1 : j;
            int st;
            if (d == 0) {
                st = hpfc_pixel_root(f, i, j, px);
            } else {
                hpfc_pixel parent;
                st = hpfc_pixel_parent(px, &parent);
                if (!st)
                    st = hpfc_pixel_child(f, &parent, i, j, px);
            }
            return st ? st : first_leaf_below(f, px);
        }
        if (d == 0)
            return HPFC_E_NO_PIXEL;
        px->depth--;
    }
}
