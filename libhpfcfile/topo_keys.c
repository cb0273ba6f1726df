/*
 * Keys as dart and vertex handles (hpfc.h, "Keys").
 *
 * Why: an hpfc_dart carries a whole pixel path (776 bytes), which a
 * traversal copies, hashes and compares at every step. A key is the word
 * pixel's slot position and a crossing (spec/hpfc-format.md §3.10); the
 * walker answers key operators from its cache entries, which record their
 * own slot, without building a path; warm twin, next and prev from the
 * entries' compact key blocks (topo.h).
 *
 * A key names its pixel by position only, and the file has no parent
 * pointers: the path of a key the cache does not hold comes from a parent
 * index built once per walker by one pass over the pools, which also checks
 * the layout that makes the path unique (§9: images back to back in parent
 * order, every address the start of the next image). Then the entry the
 * path leads to is the one dart operators use for that pixel: key
 * operators give exactly the dart operators' answers. Only entries reached
 * by that path are found by slot, so a caller's dart with a made-up path
 * never answers for a key.
 */
#include <stdlib.h>
#include <string.h>

#include "file.h"
#include "reader.h"
#include "topo.h"

void topo_keys_free(hpfc_walker *w)
{
    free(w->keys.images);
    memset(&w->keys, 0, sizeof w->keys);
}

/* ---- the parent index ------------------------------------------------------ */

/* Level l + 1's images from level l's refined pixels, in pool order: each
 * address must be where the previous image ends, and the images must fill
 * the pool exactly. Anything else is corruption (aliased or out-of-order
 * addresses, masks that contradict the level table). */
static int index_level(hpfc_walker *w, uint32_t l, const hpfc_level_info *lv)
{
    key_index *x = &w->keys;
    key_image *next = x->images + x->first[l + 1];
    uint64_t parents = l ? lv[l].images : 1, count = lv[l + 1].images, c = 0, at = 0;
    for (uint64_t img = 0; img < parents; img++) {
        uint64_t start = l ? x->images[x->first[l] + img].start : 0, address, bits, refined;
        reader_refined it = {0, 0};
        uint32_t pixel;
        int st;
        while ((st = reader_next_refined(w->file, l, start, &it, &pixel, &address)) == HPFC_OK) {
            if (c == count || address != at)
                return HPFC_E_CORRUPT;
            if ((st = reader_image_bits(w->file, l + 1, at, &bits, &refined)))
                return st;
            next[c++] = (key_image){at, (uint32_t)img, pixel};
            at += bits;
        }
    }
    return c == count && at == reader_image_end(w->file, l + 1) ? HPFC_OK : HPFC_E_CORRUPT;
}

static int build_index(hpfc_walker *w)
{
    key_index *x = &w->keys;
    hpfc_level_info lv[HPFC_MAX_LEVELS];
    hpfc_file_info info;
    hpfc_file_get_info(w->file, &info);
    x->root_cols = info.root_cols;
    x->cols = info.cols;
    x->image_pixels = (uint64_t)info.cols * info.rows;
    uint64_t total = 0, pixels = 0;
    for (uint32_t l = 0; l < w->levels; l++) {
        hpfc_file_get_level(w->file, l, &lv[l]);
        x->pool_bit[l] = lv[l].pool_offset * 8;
        x->pool_bits[l] = lv[l].pool_bits;
        x->first[l] = total;
        x->pixel_first[l] = pixels;
        if (l > 0) {
            /* open checked images * pixels <= s^l, so the totals fit */
            if (lv[l].images > UINT32_MAX)
                return HPFC_E_LIMIT;
            total += lv[l].images;
            pixels += lv[l].images * x->image_pixels;
        } else {
            pixels += (uint64_t)info.root_cols * info.root_rows;
        }
    }
    x->first[w->levels] = total;
    x->pixel_first[w->levels] = pixels;
    /* a file of huge words and many pixels: its indices would not fit, but
     * its keys still work */
    x->bound_status = w->cap && pixels > UINT64_MAX / w->cap ? HPFC_E_LIMIT : HPFC_OK;
    x->bound = x->bound_status ? 0 : pixels * w->cap;
    if (!(x->images = malloc(total ? total * sizeof *x->images : 1)))
        return HPFC_E_NOMEM;
    int st = HPFC_OK;
    for (uint32_t l = 0; l + 1 < w->levels && !st; l++)
        st = index_level(w, l, lv);
    return st;
}

/* The word pixel whose slot starts at absolute bit `pos`, with its path
 * from the root and its dense id: HPFC_E_ARG when no word slot starts
 * there. */
static int slot_pixel(hpfc_walker *w, uint64_t pos, hpfc_pixel *px, uint64_t *id)
{
    const key_index *x = &w->keys;
    uint32_t l = 0;
    while (l < w->levels && (pos < x->pool_bit[l] || pos - x->pool_bit[l] >= x->pool_bits[l]))
        l++;
    if (l == w->levels)
        return HPFC_E_ARG;
    uint64_t rel = pos - x->pool_bit[l], index = 0, start = 0;
    if (l > 0 && w->file->compact) { /* images are numbered: the type bits say which */
        int st = reader_slot_image(w->file, l, rel, &index);
        if (st)
            return st;
        start = index;
    } else if (l > 0) { /* the last image starting at or before rel (image 0 starts at 0) */
        uint64_t lo = x->first[l], hi = x->first[l + 1];
        while (hi - lo > 1) {
            uint64_t mid = lo + (hi - lo) / 2;
            if (x->images[mid].start <= rel)
                lo = mid;
            else
                hi = mid;
        }
        index = lo - x->first[l];
        start = x->images[lo].start;
    }
    uint32_t pixel;
    int st = reader_word_at(w->file, l, start, rel, &pixel);
    if (st)
        return st;
    *id = x->pixel_first[l] + index * x->image_pixels + pixel;
    px->depth = l;
    for (;;) {
        uint32_t cols = l ? x->cols : x->root_cols;
        px->path[l].image = start;
        px->path[l].i = pixel % cols;
        px->path[l].j = pixel / cols;
        if (l == 0)
            return HPFC_OK;
        const key_image *k = &x->images[x->first[l] + index];
        l--;
        index = k->parent;
        pixel = k->pixel;
        start = l ? x->images[x->first[l] + index].start : 0;
    }
}

/* The parent index, built on first use: its status. */
static int ensure_index(hpfc_walker *w)
{
    if (!w->keys.built) {
        int st = build_index(w);
        if (st)
            topo_keys_free(w);
        if (st == HPFC_E_NOMEM)
            return st; /* not built: the next key tries again */
        w->keys.status = st;
        w->keys.built = true;
    }
    return w->keys.status;
}

/* The path and dense id of the key's word pixel. */
static int key_pixel(hpfc_walker *w, uint64_t key, hpfc_pixel *px, uint64_t *id)
{
    int st = ensure_index(w);
    return st ? st : slot_pixel(w, key >> TOPO_KEY_SHIFT, px, id);
}

/* The dense id of a cache entry's pixel, recorded in it. An entry built by
 * a pixel path does not know it: its path's last image is found among its
 * level's images (on a file whose parent index built, every checked path
 * is the slot's own, so that image is one of them and the id is the slot's;
 * the slot is searched anyway should it not be). */
static int entry_pixel_id(hpfc_walker *w, cached_word *e, uint64_t *id)
{
    if (e->pixel_id != PIXEL_ID_UNKNOWN) {
        *id = e->pixel_id;
        return HPFC_OK;
    }
    int st = ensure_index(w);
    if (st)
        return st;
    const key_index *x = &w->keys;
    uint32_t l = e->depth;
    const path_step *p = &word_path(e)[l];
    uint64_t lo = x->first[l], hi = x->first[l + 1], index = 0;
    bool found = l == 0 && p->image == 0;
    if (l > 0) { /* the image starting exactly at p->image */
        while (hi > lo) {
            uint64_t mid = lo + (hi - lo) / 2;
            if (x->images[mid].start < p->image)
                lo = mid + 1;
            else
                hi = mid;
        }
        found = lo < x->first[l + 1] && x->images[lo].start == p->image;
        index = lo - x->first[l];
    }
    uint32_t cols = l ? x->cols : x->root_cols;
    if (found) {
        *id = x->pixel_first[l] + index * x->image_pixels + (uint64_t)p->j * cols + p->i;
    } else {
        hpfc_pixel px;
        if ((st = slot_pixel(w, e->slot, &px, id)))
            return st;
    }
    e->pixel_id = *id;
    return HPFC_OK;
}

/* ---- operators through the cache -------------------------------------------- */

/* The cache entry of the key's pixel when the slot index does not have it:
 * by the path the parent index gives (and keyed then). */
static int key_entry(hpfc_walker *w, uint64_t key, uint32_t *ref)
{
    if (!w->cache.arena)
        return TOPO_UNCACHED;
    hpfc_pixel px;
    uint64_t id;
    int st = key_pixel(w, key, &px, &id);
    if (!st)
        st = topo_cache_load(w, &px, true, ref);
    if (st == TOPO_RETRY) /* emptied: an entry that fits the arena fits now */
        st = topo_cache_load(w, &px, true, ref);
    if (!st) {
        cache_entry(&w->cache, *ref)->pixel_id = id; /* the path is the slot's own */
        st = topo_cache_key(w, *ref);
    }
    return st;
}

/* The parsed cache entry of the key's pixel: found by slot, else resolved
 * and keyed (key_entry); its word's parse status. */
static int keyed_word(hpfc_walker *w, uint64_t key, uint32_t *ref, cached_word **e)
{
    const key_block *b = topo_cache_find_slot(&w->cache, key >> TOPO_KEY_SHIFT);
    int st = HPFC_OK;
    if (b)
        *ref = b->ref;
    else if ((st = key_entry(w, key, ref)))
        return st;
    *e = cache_entry(&w->cache, *ref);
    return (*e)->parse_status;
}

enum { OP_TWIN, OP_NEXT, OP_PREV, OP_ORIGIN, OP_TARGET };

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
static int cached_op(hpfc_walker *w, uint64_t key, int op, uint64_t *out, uint64_t *index)
{
    uint32_t ref, end, m, k = key & TOPO_KEY_LOW;
    cached_word *e;
    int st = keyed_word(w, key, &ref, &e);
    if (st)
        return st;
    cached_crossing *x = word_crossings(e);
    if (k >= e->n || x[k].vertex == TOPO_NONE)
        return HPFC_E_ARG;
    if (op == OP_ORIGIN) {
        *out = e->slot << TOPO_KEY_SHIFT | x[k].vertex;
        return HPFC_OK;
    }
    /* twin(d) = out_m where d arrives, next(d) = out_pred(m), prev(d) =
     * twin(out_succ(k)) */
    uint32_t from = op == OP_PREV ? x[k].succ : k;
    if ((st = topo_cached_follow(w, ref, from, &end, &m)))
        return st;
    cached_word *t = cache_entry(&w->cache, end);
    const cached_crossing *y = &word_crossings(t)[m];
    uint32_t r = op == OP_NEXT ? y->pred : op == OP_TARGET ? y->vertex : m;
    if (index) {
        if ((st = entry_dart_index(w, end, r, index)))
            return st;
        topo_block_arrival(w, ref, from); /* with the pixel id now known */
    }
    *out = t->slot << TOPO_KEY_SHIFT | r;
    return HPFC_OK;
}

/* A warm twin, next or prev from the key's block alone, when it has the
 * answer: true then. Anything else (a key no block holds, a crossing not
 * walked yet, no dart, an index not known or not allowed) goes the long
 * way, which gives the same answer or the error. */
static inline bool block_op(hpfc_walker *w, uint64_t key, int op, uint64_t *out, uint64_t *index)
{
    key_block *b = topo_cache_find_slot(&w->cache, key >> TOPO_KEY_SHIFT);
    uint32_t k = key & TOPO_KEY_LOW;
    if (!b || k >= b->n)
        return false;
    const key_answer *a = block_answers(b);
    if (op == OP_PREV && (k = a[k].succ) == TOPO_NONE)
        return false;
    if (!a[k].slot) /* not walked yet, or no dart: the entry says which */
        return false;
    uint32_t m = op == OP_NEXT ? a[k].pred : a[k].m;
    if (index) {
        if (a[k].pixel == KEY_PIXEL_UNKNOWN || w->keys.bound_status)
            return false;
        *index = (uint64_t)a[k].pixel * w->cap + m;
    }
    *out = a[k].slot << TOPO_KEY_SHIFT | m;
    return true;
}

/* Without the cache: the dart operators on the key's dart. */
static int plain_op(hpfc_walker *w, uint64_t key, int op, uint64_t *out)
{
    hpfc_dart d, r;
    hpfc_vertex v;
    int st = hpfc_dart_from_key(w, key, &d);
    if (st)
        return st;
    switch (op) {
    case OP_TWIN:
        st = hpfc_dart_twin(w, &d, &r);
        break;
    case OP_NEXT:
        st = hpfc_dart_next(w, &d, &r);
        break;
    case OP_PREV:
        st = hpfc_dart_prev(w, &d, &r);
        break;
    case OP_ORIGIN:
        st = hpfc_dart_origin(w, &d, &v);
        break;
    default:
        st = hpfc_dart_target(w, &d, &v);
        break;
    }
    if (!st)
        *out = op >= OP_ORIGIN ? hpfc_vertex_key(w->file, &v) : hpfc_dart_key(w->file, &r);
    return st;
}

static int plain_index(hpfc_walker *w, uint64_t key, bool vertex, uint64_t *index);

/* What any index call checks first: the parent index and the bound. */
static int index_ready(hpfc_walker *w)
{
    int st = ensure_index(w);
    return st ? st : w->keys.bound_status;
}

/* As the dart operators do: a walk that empties the cache starts again
 * once, in the emptied cache; then, or for a word the cache cannot hold,
 * without it. */
static int key_op(hpfc_walker *w, uint64_t key, int op, uint64_t *out, uint64_t *index)
{
    int st;
    if (index && (st = index_ready(w)))
        return st;
    for (int tries = 0; tries < 2; tries++) {
        st = cached_op(w, key, op, out, index);
        if (st >= 0)
            return st;
        if (st == TOPO_UNCACHED)
            break;
    }
    uint64_t r, i = 0;
    if (!(st = plain_op(w, key, op, &r)) && index)
        st = plain_index(w, r, false, &i);
    if (!st) {
        *out = r;
        if (index)
            *index = i;
    }
    return st;
}

/* A twin, next or prev: from the key's block when it answers, else key_op. */
static inline int moving_op(hpfc_walker *w, uint64_t key, int op, uint64_t *out, uint64_t *index)
{
    return block_op(w, key, op, out, index) ? HPFC_OK : key_op(w, key, op, out, index);
}

int hpfc_key_twin(hpfc_walker *w, uint64_t dart_key, uint64_t *out)
{
    return w && out ? moving_op(w, dart_key, OP_TWIN, out, NULL) : HPFC_E_ARG;
}

int hpfc_key_next(hpfc_walker *w, uint64_t dart_key, uint64_t *out)
{
    return w && out ? moving_op(w, dart_key, OP_NEXT, out, NULL) : HPFC_E_ARG;
}

int hpfc_key_prev(hpfc_walker *w, uint64_t dart_key, uint64_t *out)
{
    return w && out ? moving_op(w, dart_key, OP_PREV, out, NULL) : HPFC_E_ARG;
}

int hpfc_key_origin(hpfc_walker *w, uint64_t dart_key, uint64_t *vertex_key)
{
    return w && vertex_key ? key_op(w, dart_key, OP_ORIGIN, vertex_key, NULL) : HPFC_E_ARG;
}

int hpfc_key_target(hpfc_walker *w, uint64_t dart_key, uint64_t *vertex_key)
{
    return w && vertex_key ? key_op(w, dart_key, OP_TARGET, vertex_key, NULL) : HPFC_E_ARG;
}

int hpfc_key_twin_indexed(hpfc_walker *w, uint64_t dart_key, uint64_t *out, uint64_t *index)
{
    return w && out && index ? moving_op(w, dart_key, OP_TWIN, out, index) : HPFC_E_ARG;
}

int hpfc_key_next_indexed(hpfc_walker *w, uint64_t dart_key, uint64_t *out, uint64_t *index)
{
    return w && out && index ? moving_op(w, dart_key, OP_NEXT, out, index) : HPFC_E_ARG;
}

int hpfc_key_prev_indexed(hpfc_walker *w, uint64_t dart_key, uint64_t *out, uint64_t *index)
{
    return w && out && index ? moving_op(w, dart_key, OP_PREV, out, index) : HPFC_E_ARG;
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

/* Whether `local` names a dart (a vertex) of the parsed word e. */
static bool names_one(cached_word *e, uint32_t local, bool vertex)
{
    if (vertex)
        return local < e->nvert;
    return local < e->n && word_crossings(e)[local].vertex != TOPO_NONE;
}

static int cached_index(hpfc_walker *w, uint64_t key, bool vertex, uint64_t *index)
{
    uint32_t ref, local = key & TOPO_KEY_LOW;
    cached_word *e;
    int st = keyed_word(w, key, &ref, &e);
    if (st)
        return st;
    if (!names_one(e, local, vertex))
        return HPFC_E_ARG;
    uint64_t id;
    if ((st = entry_pixel_id(w, e, &id)))
        return st;
    *index = id * w->cap + local;
    return HPFC_OK;
}

static int index_call(hpfc_walker *w, uint64_t key, bool vertex, uint64_t *index)
{
    if (!w || !index)
        return HPFC_E_ARG;
    int st = index_ready(w);
    if (st)
        return st;
    for (int tries = 0; tries < 2; tries++) {
        st = cached_index(w, key, vertex, index);
        if (st >= 0)
            return st;
        if (st == TOPO_UNCACHED)
            break;
    }
    return plain_index(w, key, vertex, index);
}

int hpfc_dart_index(hpfc_walker *w, uint64_t dart_key, uint64_t *index)
{
    return index_call(w, dart_key, false, index);
}

int hpfc_vertex_index(hpfc_walker *w, uint64_t vertex_key, uint64_t *index)
{
    return index_call(w, vertex_key, true, index);
}

/* ---- back to values ----------------------------------------------------------- */

/* The key's pixel, its dense id and its parsed word. */
static int key_word(hpfc_walker *w, uint64_t key, hpfc_pixel *px, uint64_t *id, cached_word **e)
{
    int st = key_pixel(w, key, px, id);
    if (!st)
        st = topo_word_view(w, px, e);
    return st ? st : (*e)->parse_status;
}

/* The path of the key's word pixel into *out, when the key names a dart
 * (vertex) of it; *out untouched otherwise. */
static int key_path(hpfc_walker *w, uint64_t key, bool vertex, hpfc_pixel *out)
{
    cached_word *e;
    hpfc_pixel px;
    uint64_t id;
    int st = w ? key_word(w, key, &px, &id, &e) : HPFC_E_ARG;
    if (!st && !names_one(e, key & TOPO_KEY_LOW, vertex))
        st = HPFC_E_ARG;
    if (!st)
        topo_entry_pixel(e, out); /* the path just resolved */
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

/* Without the cache: the key's pixel and word, as hpfc_dart_from_key. */
static int plain_index(hpfc_walker *w, uint64_t key, bool vertex, uint64_t *index)
{
    cached_word *e;
    hpfc_pixel px;
    uint64_t id;
    uint32_t local = key & TOPO_KEY_LOW;
    int st = key_word(w, key, &px, &id, &e);
    if (!st && !names_one(e, local, vertex))
        st = HPFC_E_ARG;
    if (!st)
        *index = id * w->cap + local;
    return st;
}
