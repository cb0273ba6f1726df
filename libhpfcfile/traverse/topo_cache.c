/*
 * The walker's cache of parsed words (topo.h).
 *
 * Why: one traversal operator needs the words of several pixels (the
 * dart's, the neighbours that identify each crossing on the way, the
 * target's), and a full traversal asks for every pixel's word many times.
 * Kept parsed, with the crossing across each road recorded once it is
 * identified, a word is decoded about once per traversal and an operator on
 * a dart seen before only follows links.
 *
 * Bounds: the arena (entries from its start, the key blocks of keyed
 * entries from its end, topo.h) and its two indexes (by path; by slot, for
 * the entries key operators found by their slot's own path, topo_keys.c)
 * together take at most the configured bytes (never more than caching
 * every word of the file would take). When the arena or the indexes are
 * full, everything is dropped at once, so a link never outlives the entry
 * it names; a word too big for the arena is never cached.
 *
 * Safety: an entry holds exactly what a fresh decode and parse of its word
 * give (the same checks, the same statuses), and it is found only by an
 * identical path, whose checks it passed when it was built, or by its slot
 * once that path was found to be the slot's own.
 */
#include <stdlib.h>
#include <string.h>

#include "file.h"
#include "format.h"
#include "reader.h"
#include "topo.h"

_Static_assert(sizeof(path_step) == sizeof(((hpfc_pixel *)0)->path[0]),
               "a path_step mirrors an hpfc_pixel path entry");
_Static_assert(sizeof(cached_word) % 8 == 0 && sizeof(cached_crossing) % 8 == 0 &&
                   sizeof(cached_vertex) % 8 == 0,
               "paths follow the header, crossings and vertices 8-byte aligned");

enum {
    INDEX_SHARE = 4, /* the two indexes take about 1/4 of the cache */
    MIN_BUCKETS = 8,
};

/* Bytes per bucket of the two indexes (by path, by slot) together. */
#define BUCKET_BYTES (2 * sizeof(cache_bucket))

/* References are 32-bit offsets in 8-byte units. */
#define MAX_ARENA_BYTES ((size_t)8 * (UINT32_MAX - 1))

static size_t entry_bytes(uint32_t depth, uint32_t n, uint32_t nvert)
{
    size_t b = sizeof(cached_word) + ((size_t)depth + 1) * sizeof(path_step) +
               (size_t)n * sizeof(cached_crossing) + (size_t)nvert * sizeof(cached_vertex);
    return (b + 7) & ~(size_t)7;
}

static size_t block_bytes(uint32_t n)
{
    return sizeof(key_block) + (size_t)n * sizeof(key_answer);
}

static uint64_t saturating_mul_add(uint64_t acc, uint64_t a, uint64_t b)
{
    if (b && a > UINT64_MAX / b)
        return UINT64_MAX;
    return acc > UINT64_MAX - a * b ? UINT64_MAX : acc + a * b;
}

/* What caching every word of the file could take at most, from the level
 * table: arena bytes (entries and their key blocks) and entries (a corrupt
 * file can reach one word by several paths; it then just empties the cache
 * more often). */
static void file_needs(const hpfc_file *f, uint64_t *bytes, uint64_t *entries)
{
    hpfc_level_info lv;
    *bytes = *entries = 0;
    for (uint32_t l = 0; hpfc_file_get_level(f, l, &lv) == HPFC_OK; l++) {
        uint32_t c = file_level_max_crossings(f, l);
        *bytes = saturating_mul_add(*bytes, lv.word_pixels, entry_bytes(l, c, c) + block_bytes(c));
        *entries = saturating_mul_add(*entries, lv.word_pixels, 1);
    }
}

static void cache_release(word_cache *c)
{
    free(c->arena);
    free(c->index);
    free(c->slots);
    memset(c, 0, sizeof *c);
}

/* Splits `limit` bytes between the indexes and the arena, sized down to
 * what the file can use, and allocates them. */
static int cache_allocate(word_cache *c, const hpfc_file *f, size_t limit)
{
    uint64_t need_bytes, need_entries;
    file_needs(f, &need_bytes, &need_entries);
    size_t buckets = MIN_BUCKETS;
    while (buckets < SIZE_MAX / 4 / BUCKET_BYTES &&
           2 * buckets * BUCKET_BYTES <= limit / INDEX_SHARE && buckets / 2 < need_entries)
        buckets *= 2;
    size_t index_bytes = buckets * BUCKET_BYTES;
    if (limit <= index_bytes)
        return HPFC_OK; /* too small to hold anything: no cache */
    size_t arena = limit - index_bytes;
    if (arena > need_bytes)
        arena = (size_t)need_bytes;
    if (arena > MAX_ARENA_BYTES)
        arena = MAX_ARENA_BYTES;
    arena &= ~(size_t)7;
    c->limit = limit;
    c->index = calloc(buckets, sizeof(cache_bucket));
    c->slots = calloc(buckets, sizeof(cache_bucket));
    c->arena = arena ? malloc(arena) : NULL;
    if (!c->index || !c->slots || !c->arena) {
        cache_release(c);
        return arena ? HPFC_E_NOMEM : HPFC_OK;
    }
    c->arena_bytes = c->blocks_low = arena;
    c->mask = buckets - 1;
    c->max_entries = buckets / 2;
    return HPFC_OK;
}

static void cache_flush(word_cache *c)
{
    memset(c->index, 0, (c->mask + 1) * sizeof(cache_bucket));
    memset(c->slots, 0, (c->mask + 1) * sizeof(cache_bucket));
    c->used = 0;
    c->blocks_low = c->arena_bytes;
    c->entries = 0;
}

int topo_cache_init(hpfc_walker *w, size_t limit)
{
    hpfc_file_info info;
    hpfc_file_get_info(w->file, &info);
    w->levels = info.levels;
    if (!w->uncached) {
        w->uncached = malloc(entry_bytes(w->levels - 1, w->cap, w->cap));
        if (!w->uncached)
            return HPFC_E_NOMEM;
    }
    w->uncached_valid = false;
    if (limit && limit == w->cache.limit) { /* keep the memory, drop the words */
        cache_flush(&w->cache);
        return HPFC_OK;
    }
    cache_release(&w->cache);
    return limit ? cache_allocate(&w->cache, w->file, limit) : HPFC_OK;
}

void topo_cache_free(hpfc_walker *w)
{
    cache_release(&w->cache);
    free(w->uncached);
    w->uncached = NULL;
}

int hpfc_walker_set_cache_size(hpfc_walker *w, size_t bytes)
{
    return w ? topo_cache_init(w, bytes) : HPFC_E_ARG;
}

/* ---- finding entries ------------------------------------------------------ */

/* The last level of a path decides the slot; the levels above only matter on
 * corrupt files, where they are compared in full. */
static uint64_t path_hash(const hpfc_pixel *px)
{
    uint32_t d = px->depth;
    uint64_t h = px->path[d].image * 0x9E3779B97F4A7C15ull;
    h ^= ((uint64_t)px->path[d].i << 32 | px->path[d].j) * 0xC2B2AE3D27D4EB4Full;
    h ^= (uint64_t)d * 0x165667B19E3779F9ull;
    h ^= h >> 31;
    h *= 0xBF58476D1CE4E5B9ull;
    return h ^ h >> 29;
}

/* Compared from the pixel's own level up: a different pixel differs there
 * at once, and paths are short (a loop beats a call to memcmp). */
static bool same_path(cached_word *e, const hpfc_pixel *px)
{
    if (e->depth != px->depth)
        return false;
    const path_step *p = word_path(e);
    for (uint32_t l = px->depth + 1; l-- > 0;)
        if (p[l].image != px->path[l].image || p[l].i != px->path[l].i || p[l].j != px->path[l].j)
            return false;
    return true;
}

static uint32_t cache_find(const word_cache *c, const hpfc_pixel *px, uint64_t h)
{
    uint32_t check = (uint32_t)(h >> 32);
    for (size_t b = (size_t)h & c->mask;; b = (b + 1) & c->mask) { /* at most half full */
        const cache_bucket *k = &c->index[b];
        if (!k->ref)
            return 0;
        if (k->check == check && same_path(cache_entry(c, k->ref), px))
            return k->ref;
    }
}

static void index_put(cache_bucket *index, size_t mask, uint64_t h, uint32_t ref)
{
    size_t b = (size_t)h & mask;
    while (index[b].ref)
        b = (b + 1) & mask;
    index[b] = (cache_bucket){ref, (uint32_t)(h >> 32)};
}

/* Crossing k's answers in a key block, from its entry e. */
static key_answer entry_answer(const word_cache *c, cached_word *e, uint32_t k)
{
    const cached_crossing *x = &word_crossings(e)[k];
    key_answer a = {.slot = 0,
                    .m = TOPO_NONE,
                    .pred = TOPO_NONE,
                    .pixel = KEY_PIXEL_UNKNOWN,
                    .succ = x->vertex == TOPO_NONE ? TOPO_NONE : x->succ};
    if (x->arrival) {
        cached_word *t = cache_entry(c, x->arrival);
        a.slot = t->slot;
        a.m = x->arrival_m;
        a.pred = word_crossings(t)[x->arrival_m].pred;
        if (t->pixel_id < KEY_PIXEL_UNKNOWN)
            a.pixel = (uint32_t)t->pixel_id;
    }
    return a;
}

topo_result topo_cache_key(hpfc_walker *w, uint32_t ref)
{
    word_cache *c = &w->cache;
    cached_word *e = cache_entry(c, ref);
    if (e->block)
        return topo_done(HPFC_OK);
    size_t bytes = block_bytes(e->n);
    if (bytes > c->arena_bytes)
        return topo_redo(TOPO_UNCACHED);
    if (bytes > c->blocks_low - c->used) {
        cache_flush(c);
        return topo_redo(TOPO_RETRY);
    }
    c->blocks_low -= bytes;
    e->block = (uint32_t)(c->blocks_low / 8 + 1);
    key_block *b = cache_block(c, e->block);
    *b = (key_block){e->slot, e->n, ref};
    key_answer *a = block_answers(b);
    for (uint32_t k = 0; k < e->n; k++)
        a[k] = entry_answer(c, e, k);
    index_put(c->slots, c->mask, topo_slot_hash(e->slot), e->block);
    return topo_done(HPFC_OK);
}

void topo_block_arrival(hpfc_walker *w, uint32_t ref, uint32_t k)
{
    cached_word *e = cache_entry(&w->cache, ref);
    if (e->block)
        block_answers(cache_block(&w->cache, e->block))[k] = entry_answer(&w->cache, e, k);
}

/* Room for an entry of `bytes`; when the arena or the index is full, empties
 * the cache and says so (the caller's references are gone). */
static topo_result cache_reserve(word_cache *c, size_t bytes, uint32_t *ref)
{
    if (bytes > c->arena_bytes)
        return topo_redo(TOPO_UNCACHED);
    if (bytes > c->blocks_low - c->used || c->entries >= c->max_entries) {
        cache_flush(c);
        return topo_redo(TOPO_RETRY);
    }
    *ref = (uint32_t)(c->used / 8 + 1);
    c->used += bytes;
    c->entries++;
    return topo_done(HPFC_OK);
}

/* ---- building entries ----------------------------------------------------- */

/* Decodes px's word into w->p_word and parses it: *parse_status is the
 * grammar's verdict; the road counts in w->p_word hold either way. `own`: the
 * caller's pixel, whose slot is checked first (as every operator always
 * did, so a bad path stays an argument error). */
static int decode_and_parse(hpfc_walker *w, const hpfc_pixel *px, bool own, int *parse_status,
                            uint64_t *slot)
{
    size_t len;
    int st = own ? reader_pixel_slot_bit(w->file, px, slot) : HPFC_OK;
    if (!st)
        st = topo_decode_word(w, px, &len);
    if (!st && !own) /* the word decoded: its slot is there */
        st = reader_pixel_slot_bit(w->file, px, slot);
    if (st)
        return st;
    *parse_status = topo_parse_decoded(w, &w->p_word, len);
    return HPFC_OK;
}

static void fill_entry(cached_word *e, const hpfc_pixel *px, const word_parts *lw, int parse_status,
                       uint64_t slot)
{
    bool ok = parse_status == HPFC_OK;
    e->depth = px->depth;
    e->n = lw->n;
    e->nvert = ok ? lw->nvert : 0;
    e->parse_status = parse_status;
    memcpy(e->road_off, lw->road_off, sizeof e->road_off);
    e->block = 0;
    e->slot = slot;
    e->pixel_id = PIXEL_ID_UNKNOWN;
    memcpy(word_path(e), px->path, ((size_t)px->depth + 1) * sizeof(path_step));
    cached_crossing *x = word_crossings(e);
    for (uint32_t k = 0; k < e->n; k++)
        x[k] = (cached_crossing){.link_state = LINK_UNKNOWN,
                                 .link = {.ref = 0},
                                 .link_m = TOPO_NONE,
                                 .arrival = 0,
                                 .arrival_m = TOPO_NONE,
                                 .pred = ok ? lw->pred[k] : k,
                                 .succ = ok ? lw->succ[k] : k,
                                 .vertex = ok ? lw->comp_vertex[lw->comp[k]] : TOPO_NONE};
    cached_vertex *v = word_vertices(e);
    for (uint32_t u = 0; u < e->nvert; u++) {
        uint32_t comp = lw->vertex_comp[u];
        v[u] = (cached_vertex){lw->comp_first[comp], lw->comp_size[comp]};
    }
}

topo_result topo_cache_load(hpfc_walker *w, const hpfc_pixel *px, bool own, uint32_t *ref)
{
    word_cache *c = &w->cache;
    if (px->depth >= w->levels)
        return topo_done(own ? HPFC_E_ARG : HPFC_E_CORRUPT);
    if (!c->arena)
        return topo_redo(TOPO_UNCACHED);
    uint64_t h = path_hash(px);
    if ((*ref = cache_find(c, px, h)))
        return topo_done(HPFC_OK);
    uint64_t slot;
    int parse_status, st = decode_and_parse(w, px, own, &parse_status, &slot);
    if (st)
        return topo_done(st);
    size_t bytes = entry_bytes(px->depth, w->p_word.n, parse_status ? 0 : w->p_word.nvert);
    topo_result r = cache_reserve(c, bytes, ref);
    if (topo_stops(r))
        return r;
    fill_entry(cache_entry(c, *ref), px, &w->p_word, parse_status, slot);
    index_put(c->index, c->mask, h, *ref);
    return topo_done(HPFC_OK);
}

/* The uncached entry: a one-word cache for when the cache is off or too small. */
static int uncached_view(hpfc_walker *w, const hpfc_pixel *px, cached_word **out)
{
    if (px->depth >= w->levels)
        return HPFC_E_ARG;
    if (!w->uncached_valid || !same_path(w->uncached, px)) {
        uint64_t slot;
        int parse_status, st = decode_and_parse(w, px, true, &parse_status, &slot);
        w->uncached_valid = false;
        if (st)
            return st;
        fill_entry(w->uncached, px, &w->p_word, parse_status, slot);
        w->uncached_valid = true;
    }
    *out = w->uncached;
    return HPFC_OK;
}

int topo_word_view(hpfc_walker *w, const hpfc_pixel *px, cached_word **out)
{
    uint32_t ref;
    topo_result r = topo_cache_load(w, px, true, &ref);
    if (r.flow == TOPO_RETRY) /* emptied: an entry that fits the arena fits now */
        r = topo_cache_load(w, px, true, &ref);
    if (r.flow != TOPO_DONE)
        return uncached_view(w, px, out);
    if (r.status == HPFC_OK)
        *out = cache_entry(&w->cache, ref);
    return r.status;
}

void topo_entry_pixel(cached_word *e, hpfc_pixel *px)
{
    px->depth = e->depth;
    memcpy(px->path, word_path(e), ((size_t)e->depth + 1) * sizeof(path_step));
}
