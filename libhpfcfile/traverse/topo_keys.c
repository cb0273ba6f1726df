/*
 * The key operators (hpfc.h, "Keys"): twin, next, prev, origin and target
 * on 64-bit keys, dense indices, and keys back to values.
 *
 * Why: an hpfc_dart carries a whole pixel path, which a traversal copies,
 * hashes and compares at every step. A key is the word pixel's slot
 * position and a crossing (spec/hpfc-format.md §3.10); the walker answers
 * key operators from its cache entries, which record their own slot,
 * without building a path; warm twin, next and prev from the entries'
 * compact key blocks (topo.h). A key the cache does not hold is resolved
 * to its pixel's path by the parent index (topo_index.c), the path dart
 * operators use: key operators give exactly the dart operators' answers.
 * Only entries reached by that path are found by slot, so a caller's dart
 * with a made-up path never answers for a key.
 */
#include "topo.h"

/* The dense id of a cache entry's pixel, recorded in it (found by
 * topo_pixel_id the first time). */
static int entry_pixel_id(hpfc_walker *w, cached_word *e, uint64_t *id)
{
    if (e->pixel_id != PIXEL_ID_UNKNOWN) {
        *id = e->pixel_id;
        return HPFC_OK;
    }
    int st = topo_pixel_id(w, e->depth, &word_path(e)[e->depth], e->slot, id);
    if (!st)
        e->pixel_id = *id;
    return st;
}

/* ---- operators through the cache -------------------------------------------- */

/* The cache entry of the key's pixel when the slot index does not have it:
 * by the path the parent index gives (and keyed then). */
static topo_result key_entry(hpfc_walker *w, uint64_t key, uint32_t *ref)
{
    if (!w->cache.arena)
        return topo_redo(TOPO_UNCACHED);
    hpfc_pixel px;
    uint64_t id;
    int st = topo_key_pixel(w, key, &px, &id);
    if (st)
        return topo_done(st);
    topo_result r = topo_cache_load(w, &px, true, ref);
    if (r.flow == TOPO_RETRY) /* emptied: an entry that fits the arena fits now */
        r = topo_cache_load(w, &px, true, ref);
    if (topo_stops(r))
        return r;
    cache_entry(&w->cache, *ref)->pixel_id = id; /* the path is the slot's own */
    return topo_cache_key(w, *ref);
}

/* The parsed cache entry of the key's pixel: found by slot, else resolved
 * and keyed (key_entry); its word's parse status. */
static topo_result keyed_word(hpfc_walker *w, uint64_t key, uint32_t *ref, cached_word **e)
{
    const key_block *b = topo_cache_find_slot(&w->cache, key >> TOPO_KEY_SHIFT);
    if (b) {
        *ref = b->ref;
    } else {
        topo_result r = key_entry(w, key, ref);
        if (topo_stops(r))
            return r;
    }
    *e = cache_entry(&w->cache, *ref);
    return topo_done((*e)->parse_status);
}

/* The key's pixel, its dense id and its parsed word. */
static int key_word(hpfc_walker *w, uint64_t key, hpfc_pixel *px, uint64_t *id, cached_word **e)
{
    int st = topo_key_pixel(w, key, px, id);
    if (!st)
        st = topo_word_view(w, px, e);
    return st ? st : (*e)->parse_status;
}

/* Whether `local` names a dart (a vertex) of the parsed word e. */
static bool names_one(cached_word *e, uint32_t local, bool vertex)
{
    if (vertex)
        return local < e->nvert;
    return local < e->n && word_crossings(e)[local].vertex != TOPO_NONE;
}

/* The parsed word of the key's pixel, for the calls that only read it (a
 * vertex's degree and darts, indices, values): the cache entry found by
 * slot, else resolved and keyed; else, when the cache cannot hold it, the
 * word of the path the parent index gives (key_word). Its parse status.
 * Keying can empty the cache under the call, hence key_op's one retry
 * (topo.h, topo_result). */
static int key_parsed_word(hpfc_walker *w, uint64_t key, cached_word **e)
{
    uint32_t ref;
    for (int tries = 0; tries < 2; tries++) {
        topo_result r = keyed_word(w, key, &ref, e);
        if (r.flow == TOPO_DONE)
            return r.status;
        if (r.flow == TOPO_UNCACHED)
            break;
    }
    hpfc_pixel px;
    uint64_t id;
    return key_word(w, key, &px, &id, e);
}

/* The dense index of the dart (vertex) a key names. */
static int dense_index(hpfc_walker *w, uint64_t key, bool vertex, uint64_t *index)
{
    cached_word *e;
    uint32_t local = key & TOPO_KEY_LOW;
    int st = key_parsed_word(w, key, &e);
    if (!st && !names_one(e, local, vertex))
        st = HPFC_E_ARG;
    uint64_t id;
    if (!st && !(st = entry_pixel_id(w, e, &id)))
        *index = id * w->cap + local;
    return st;
}

/* Dart index `index` of crossing m of entry ref. */
static int entry_dart_index(hpfc_walker *w, uint32_t ref, uint32_t m, uint64_t *index)
{
    uint64_t id;
    int st = entry_pixel_id(w, cache_entry(&w->cache, ref), &id);
    if (!st)
        *index = id * w->cap + m;
    return st;
}

/* `index`, when not NULL, gets the dart index of a dart result, read from
 * the entry the answer comes from (a twin, next or prev). */
static topo_result cached_op(hpfc_walker *w, uint64_t key, topo_op op, uint64_t *out,
                             uint64_t *index)
{
    uint32_t ref, end, m, k = key & TOPO_KEY_LOW;
    cached_word *e;
    topo_result r = keyed_word(w, key, &ref, &e);
    if (topo_stops(r))
        return r;
    cached_crossing *x = word_crossings(e);
    if (k >= e->n || x[k].vertex == TOPO_NONE)
        return topo_done(HPFC_E_ARG);
    if (op == TOPO_ORIGIN) {
        *out = e->slot << TOPO_KEY_SHIFT | x[k].vertex;
        return topo_done(HPFC_OK);
    }
    /* twin(d) = out_m where d arrives, next(d) = out_pred(m), prev(d) =
     * twin(out_succ(k)) */
    uint32_t from = op == TOPO_PREV ? x[k].succ : k;
    r = topo_cached_follow(w, ref, from, &end, &m);
    if (topo_stops(r))
        return r;
    cached_word *t = cache_entry(&w->cache, end);
    const cached_crossing *y = &word_crossings(t)[m];
    uint32_t answer = op == TOPO_NEXT ? y->pred : op == TOPO_TARGET ? y->vertex : m;
    if (index) {
        int st = entry_dart_index(w, end, answer, index);
        if (st)
            return topo_done(st);
        topo_block_arrival(w, ref, from); /* with the pixel id now known */
    }
    *out = t->slot << TOPO_KEY_SHIFT | answer;
    return topo_done(HPFC_OK);
}

/* A warm twin, next or prev from the key's block alone, when it has the
 * answer: true then. Anything else (a key no block holds, a crossing not
 * walked yet, no dart, an index not known or not allowed) goes the long
 * way, which gives the same answer or the error. */
static inline bool block_op(hpfc_walker *w, uint64_t key, topo_op op, uint64_t *out, uint64_t *index)
{
    key_block *b = topo_cache_find_slot(&w->cache, key >> TOPO_KEY_SHIFT);
    uint32_t k = key & TOPO_KEY_LOW;
    if (!b || k >= b->n)
        return false;
    const key_answer *a = block_answers(b);
    if (op == TOPO_PREV && (k = a[k].succ) == TOPO_NONE)
        return false;
    if (!a[k].slot) /* not walked yet, or no dart: the entry says which */
        return false;
    uint32_t m = op == TOPO_NEXT ? a[k].pred : a[k].m;
    if (index) {
        if (a[k].pixel == KEY_PIXEL_UNKNOWN || w->keys.bound_status)
            return false;
        *index = (uint64_t)a[k].pixel * w->cap + m;
    }
    *out = a[k].slot << TOPO_KEY_SHIFT | m;
    return true;
}

/* Without the cache: the dart operators' walk on the key's dart. */
static int plain_op(hpfc_walker *w, uint64_t key, topo_op op, uint64_t *out)
{
    hpfc_dart d, r;
    hpfc_vertex v;
    int st = hpfc_dart_from_key(w, key, &d);
    if (!st)
        st = topo_dart_op(w, &d, op, &r, &v);
    if (!st)
        *out = op >= TOPO_ORIGIN ? hpfc_vertex_key(w->file, &v) : hpfc_dart_key(w->file, &r);
    return st;
}

/* What any index call checks first: the parent index and the bound. */
static int index_ready(hpfc_walker *w)
{
    int st = topo_index_ready(w);
    return st ? st : w->keys.bound_status;
}

/* As the dart operators do (topo_arrive): a walk that empties the cache
 * starts again once, in the emptied cache; then, or for a word the cache
 * cannot hold, without it (topo.h, topo_result). */
static int key_op(hpfc_walker *w, uint64_t key, topo_op op, uint64_t *out, uint64_t *index)
{
    int st;
    if (index && (st = index_ready(w)))
        return st;
    for (int tries = 0; tries < 2; tries++) {
        topo_result r = cached_op(w, key, op, out, index);
        if (r.flow == TOPO_DONE)
            return r.status;
        if (r.flow == TOPO_UNCACHED)
            break;
    }
    uint64_t r, i = 0;
    if (!(st = plain_op(w, key, op, &r)) && index)
        st = dense_index(w, r, false, &i);
    if (!st) {
        *out = r;
        if (index)
            *index = i;
    }
    return st;
}

/* A twin, next or prev: from the key's block when it answers, else key_op. */
static inline int moving_op(hpfc_walker *w, uint64_t key, topo_op op, uint64_t *out, uint64_t *index)
{
    return block_op(w, key, op, out, index) ? HPFC_OK : key_op(w, key, op, out, index);
}

int hpfc_key_twin(hpfc_walker *w, uint64_t dart_key, uint64_t *out)
{
    return w && out ? moving_op(w, dart_key, TOPO_TWIN, out, NULL) : HPFC_E_ARG;
}

int hpfc_key_next(hpfc_walker *w, uint64_t dart_key, uint64_t *out)
{
    return w && out ? moving_op(w, dart_key, TOPO_NEXT, out, NULL) : HPFC_E_ARG;
}

int hpfc_key_prev(hpfc_walker *w, uint64_t dart_key, uint64_t *out)
{
    return w && out ? moving_op(w, dart_key, TOPO_PREV, out, NULL) : HPFC_E_ARG;
}

int hpfc_key_origin(hpfc_walker *w, uint64_t dart_key, uint64_t *vertex_key)
{
    return w && vertex_key ? key_op(w, dart_key, TOPO_ORIGIN, vertex_key, NULL) : HPFC_E_ARG;
}

int hpfc_key_target(hpfc_walker *w, uint64_t dart_key, uint64_t *vertex_key)
{
    return w && vertex_key ? key_op(w, dart_key, TOPO_TARGET, vertex_key, NULL) : HPFC_E_ARG;
}

int hpfc_key_twin_indexed(hpfc_walker *w, uint64_t dart_key, uint64_t *out, uint64_t *index)
{
    return w && out && index ? moving_op(w, dart_key, TOPO_TWIN, out, index) : HPFC_E_ARG;
}

int hpfc_key_next_indexed(hpfc_walker *w, uint64_t dart_key, uint64_t *out, uint64_t *index)
{
    return w && out && index ? moving_op(w, dart_key, TOPO_NEXT, out, index) : HPFC_E_ARG;
}

int hpfc_key_prev_indexed(hpfc_walker *w, uint64_t dart_key, uint64_t *out, uint64_t *index)
{
    return w && out && index ? moving_op(w, dart_key, TOPO_PREV, out, index) : HPFC_E_ARG;
}

/* ---- dense indices ------------------------------------------------------------- */

int hpfc_key_index_bound(hpfc_walker *w, uint64_t *darts, uint64_t *vertices)
{
    if (!w || !darts || !vertices)
        return HPFC_E_ARG;
    int st = index_ready(w);
    if (!st)
        *darts = *vertices = w->keys.bound; /* a word has at most cap vertices */
    return st;
}

static int index_call(hpfc_walker *w, uint64_t key, bool vertex, uint64_t *index)
{
    if (!w || !index)
        return HPFC_E_ARG;
    int st = index_ready(w);
    return st ? st : dense_index(w, key, vertex, index);
}

int hpfc_dart_index(hpfc_walker *w, uint64_t dart_key, uint64_t *index)
{
    return index_call(w, dart_key, false, index);
}

int hpfc_vertex_index(hpfc_walker *w, uint64_t vertex_key, uint64_t *index)
{
    return index_call(w, vertex_key, true, index);
}

/* ---- vertex keys -------------------------------------------------------------- */

/* The key forms of hpfc_vertex_degree and hpfc_vertex_dart (topo.c): the
 * same reads of the same entry, reached by slot instead of by path. */

/* The vertex a key names in its parsed word. */
static int key_vertex(hpfc_walker *w, uint64_t vertex_key, cached_word **e, cached_vertex *v)
{
    int st = key_parsed_word(w, vertex_key, e);
    if (!st && !names_one(*e, vertex_key & TOPO_KEY_LOW, true))
        st = HPFC_E_ARG;
    if (!st)
        *v = word_vertices(*e)[vertex_key & TOPO_KEY_LOW];
    return st;
}

int hpfc_key_degree(hpfc_walker *w, uint64_t vertex_key, uint32_t *degree)
{
    if (!w || !degree)
        return HPFC_E_ARG;
    cached_word *e;
    cached_vertex v;
    int st = key_vertex(w, vertex_key, &e, &v);
    if (!st)
        *degree = v.degree;
    return st;
}

int hpfc_key_vertex_dart(hpfc_walker *w, uint64_t vertex_key, uint32_t index, uint64_t *dart_key)
{
    if (!w || !dart_key)
        return HPFC_E_ARG;
    cached_word *e;
    cached_vertex v;
    int st = key_vertex(w, vertex_key, &e, &v);
    if (!st && index >= v.degree)
        st = HPFC_E_ARG;
    if (!st)
        *dart_key = topo_key(e->slot, vertex_dart_crossing(e, v, index));
    return st;
}

int hpfc_key_vertex_darts(hpfc_walker *w, uint64_t vertex_key, uint64_t *darts, size_t cap,
                          uint32_t *degree)
{
    if (!w || !degree)
        return HPFC_E_ARG;
    cached_word *e;
    cached_vertex v;
    int st = key_vertex(w, vertex_key, &e, &v);
    if (st)
        return st;
    *degree = v.degree;
    if (!darts)
        return HPFC_OK;
    if (cap < v.degree)
        return HPFC_E_BUFFER_SMALL;
    uint32_t k = v.first;
    for (uint32_t s = 0; s < v.degree; s++, k = word_crossings(e)[k].succ)
        darts[s] = topo_key(e->slot, k);
    return HPFC_OK;
}

/* ---- back to values ----------------------------------------------------------- */

/* The path of the key's word pixel into *out, when the key names a dart
 * (vertex) of it; *out untouched otherwise. A keyed entry's path is the
 * one the parent index gives (key_entry), so the cache changes no answer. */
static int key_path(hpfc_walker *w, uint64_t key, bool vertex, hpfc_pixel *out)
{
    cached_word *e;
    int st = w ? key_parsed_word(w, key, &e) : HPFC_E_ARG;
    if (!st && !names_one(e, key & TOPO_KEY_LOW, vertex))
        st = HPFC_E_ARG;
    if (!st)
        topo_entry_pixel(e, out);
    return st;
}

int hpfc_dart_from_key(hpfc_walker *w, uint64_t key, hpfc_dart *out)
{
    int st = out ? key_path(w, key, false, &out->pixel) : HPFC_E_ARG;
    if (!st)
        out->crossing = key & TOPO_KEY_LOW;
    return st;
}

int hpfc_vertex_from_key(hpfc_walker *w, uint64_t key, hpfc_vertex *out)
{
    int st = out ? key_path(w, key, true, &out->pixel) : HPFC_E_ARG;
    if (!st)
        out->local = key & TOPO_KEY_LOW;
    return st;
}

