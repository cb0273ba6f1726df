/*
 * topo.h: traversal internals, shared by the traversal's files and by
 * faces.c and labels_verify.c. The files are layers; each calls only the
 * ones below it:
 *
 *   topo.c, topo_keys.c   the public operators on darts and on keys
 *   topo_walk.c           the walker: a dart followed to its target, the
 *                         cache in front of the plain walk
 *   topo_links.c          the walk through the cache: links between entries
 *   topo_cache.c          the cache of parsed words and their key blocks
 *   topo_cross.c          words decoded and parsed for a walker; crossing
 *                         identification across roads
 *   topo_index.c          keys and pixels: the parent index
 *   reader, words.h, road.h
 *
 * Three answer sources, one answer. A dart operator's answer comes from the
 * plain walk (topo_walk.c, topo_cross.c), from the cached follow
 * (topo_links.c) or, for a key operator, from its key block (topo_keys.c);
 * all three give the same answer and the same status for every dart, on
 * every file, whatever the cache's size and history. By construction: the
 * cached follow records only what topo_cross_road answers (topo_links.c);
 * a key block is only ever a copy of its entry (topo_cache.c); and
 * topo_walk.c's arrive, the one place dart and key operators walk, puts
 * the cache in front of the plain walk. tests/lib/test_topo.c
 * (check_three_sources) runs every operator on every dart of generated
 * graphs without the cache, with caches of several sizes and through keys,
 * and compares.
 */
#ifndef HPFC_TOPO_H
#define HPFC_TOPO_H

#include <stdbool.h>
#include <string.h>

#include "hpfc.h"
#include "road.h"
#include "words.h"

/* No index: a stabbing's vertex, a link not found, no dart (as words.h). */
#define TOPO_NONE WORD_NONE

/* A dart or vertex key (spec/hpfc-format.md §3.10): the word pixel's slot
 * position, then TOPO_KEY_SHIFT bits of crossing or local vertex id. */
#define TOPO_KEY_SHIFT 20
#define TOPO_KEY_LOW ((1u << TOPO_KEY_SHIFT) - 1)

static inline uint64_t topo_key(uint64_t slot, uint32_t id)
{
    return slot << TOPO_KEY_SHIFT | (id & TOPO_KEY_LOW);
}

/* ---- the walker's cache (topo_cache.c) ------------------------------------
 *
 * A word pixel's parsed word, stored once per walker and reused by every
 * operator that needs it, with the crossings across its roads filled in as
 * they are identified. Entries live in one arena of bounded size and are
 * found by the pixel's full path (the path, not only its slot, decides
 * where Algorithm 1 and point location lead, so an entry reached by another
 * path on a corrupt file is another entry). When the arena or its index is
 * full, everything is dropped at once: links between entries then never
 * point at a dropped entry. */

/* A status and an instruction are different things: the cached layers
 * return both, each in its own field, and the layer above acts on the
 * instruction and passes on only the status. So a public function, which
 * returns an int status, can never hand a caller an instruction. */
typedef enum topo_flow {
    TOPO_DONE = 0,  /* finished: the status is the answer */
    TOPO_RETRY,     /* the cache was emptied under the operation: start again */
    TOPO_UNCACHED,  /* a word too big for the cache: go without it */
} topo_flow;

/* The callers of a cached layer all run it the same way: at most twice
 * (TOPO_RETRY: once more, in the emptied cache, where an entry that fits
 * the arena fits), then, after TOPO_UNCACHED or a second RETRY, the plain
 * path without the cache. That loop is written out where it runs
 * (topo_arrive, key_op, key_parsed_word) rather than shared: the attempts
 * differ in arguments and outputs, and a callback would cost the hot
 * operators an indirect call. */
typedef struct topo_result {
    int status;      /* HPFC_OK or an HPFC_E_* code; HPFC_OK unless flow is TOPO_DONE */
    topo_flow flow;
} topo_result;

static inline topo_result topo_done(int status)
{
    return (topo_result){status, TOPO_DONE};
}

static inline topo_result topo_redo(topo_flow flow)
{
    return (topo_result){HPFC_OK, flow};
}

/* Whether the operation stops here: a failure, or an instruction. */
static inline bool topo_stops(topo_result r)
{
    return r.status != HPFC_OK || r.flow != TOPO_DONE;
}

/* One level of a pixel's path, laid out as hpfc_pixel's path entries. */
typedef struct path_step {
    uint64_t image;
    uint32_t i, j;
} path_step;

/* What a crossing's link holds (its tag). */
enum { LINK_UNKNOWN = 0, LINK_FOUND, LINK_FAILED };

/* One crossing of a cached word (32 bytes). */
typedef struct cached_crossing {
    /* the crossing seen from across its road, once identified: link_state
     * says which member of `link` holds */
    uint32_t link_state;
    union {
        uint32_t ref;   /* LINK_FOUND: the entry across (a cache reference) */
        int32_t status; /* LINK_FAILED: why identification failed */
    } link;
    uint32_t link_m; /* LINK_FOUND: the crossing across */
    /* for a junction's crossing: where its out-dart's edge arrives (entry,
     * crossing), once a walk has followed it; arrival == 0: not yet */
    uint32_t arrival, arrival_m;
    uint32_t pred, succ;     /* cyclic within its component */
    uint32_t vertex;         /* local vertex of its component, TOPO_NONE for a stabbing */
} cached_crossing;

typedef struct cached_vertex {
    uint32_t first;          /* first crossing of its component (word order) */
    uint32_t degree;         /* crossings of its component */
} cached_vertex;

/* Header of an entry; cached_crossing[n], cached_vertex[nvert] and
 * path_step[depth + 1] follow. A word whose grammar is broken is kept for
 * its road counts (the part that does not depend on the grammar): its
 * parse_status says why any other use must fail. */
typedef struct cached_word {
    uint32_t depth;
    uint32_t n, nvert;
    int32_t parse_status;
    uint32_t road_off[5];    /* as in word_parts */
    /* its key block (a reference as cache_block's), once the path was
     * found to be the slot's own (topo_keys.c); 0: not keyed */
    uint32_t block;
    uint64_t slot;           /* absolute bit position of the word's slot (its key) */
    /* the pixel's dense id (topo_keys.c), PIXEL_ID_UNKNOWN until a key call
     * needs it: kept here so that a warm index call reads it, not searches */
    uint64_t pixel_id;
} cached_word;

#define PIXEL_ID_UNKNOWN UINT64_MAX

static inline cached_crossing *word_crossings(cached_word *e)
{
    return (cached_crossing *)(void *)(e + 1);
}

static inline cached_vertex *word_vertices(cached_word *e)
{
    return (cached_vertex *)(word_crossings(e) + e->n);
}

/* The crossing of dart `index` (< v's degree) of vertex v of e: word order
 * is clockwise around a vertex, from its first crossing. */
static inline uint32_t vertex_dart_crossing(cached_word *e, cached_vertex v, uint32_t index)
{
    uint32_t k = v.first;
    for (uint32_t s = 0; s < index; s++)
        k = word_crossings(e)[k].succ;
    return k;
}

static inline path_step *word_path(cached_word *e)
{
    return (path_step *)(void *)(word_vertices(e) + e->nvert);
}

/* ---- key blocks -----------------------------------------------------------
 *
 * What a warm key operator reads of a keyed entry (one whose path is its
 * slot's own): its slot and, per crossing, the answers of twin and next
 * once a walk has found them. Why apart from the entry: blocks sit
 * together at the arena's end, so a warm walk on keys reads a bucket and
 * one block line per step from about a third of the memory the entries
 * take, most of it then in the core's L2 cache instead of farther away
 * (bench/README.md, "Notes", has the warm walk before and after).
 * A block is written only from its entry (the arrival recorded there, the
 * arrival entry's slot, pred and dense id): a copy, never another answer,
 * and it goes when the entries go. */
typedef struct key_block {
    uint64_t slot; /* the entry's slot (its key) */
    uint32_t n;    /* crossings */
    uint32_t ref;  /* its cache entry */
} key_block;

/* One crossing of a key block, key_answer[n] after its key_block. */
typedef struct key_answer {
    /* where the crossing's out-dart arrives: that entry's slot (0: not known
     * yet, or the crossing is no dart), crossing `m` there (twin) and pred(m)
     * (next) */
    uint64_t slot;
    uint32_t m, pred;
    uint32_t pixel; /* that entry's dense pixel id, KEY_PIXEL_UNKNOWN if not known */
    uint32_t succ;  /* succ of the crossing in its component; TOPO_NONE: no dart */
} key_answer;

#define KEY_PIXEL_UNKNOWN UINT32_MAX

static inline key_answer *block_answers(key_block *b)
{
    return (key_answer *)(void *)(b + 1);
}

typedef struct cache_bucket {
    uint32_t ref;            /* entry reference, 0 = empty */
    uint32_t check;          /* high bits of the path's hash */
} cache_bucket;

typedef struct word_cache {
    size_t limit;            /* bytes allowed (arena + indexes), 0 = no cache */
    uint8_t *arena;          /* entries and key blocks, 8-byte aligned */
    size_t arena_bytes, used;
    cache_bucket *index; /* by path; open addressing, at most half full */
    cache_bucket *slots; /* the key blocks by slot, as many buckets */
    size_t mask, entries, max_entries;
    /* key blocks fill the arena down from its end, entries up from its
     * start: blocks from here on */
    size_t blocks_low;
} word_cache;

/* The walker's parent index (topo_index.c): per level l >= 1, its images in
 * pool order, each with the refined pixel of level l - 1 pointing at it. */
typedef struct key_image {
    uint64_t start;  /* bit offset in the level's pool */
    uint32_t parent; /* index of the parent image in level l - 1 */
    uint32_t pixel;  /* scanline index of the refined pixel in it */
} key_image;

typedef struct key_index {
    int status; /* HPFC_OK once built, a file's status if it cannot be */
    bool built;
    key_image *images; /* all levels, level l from first[l] */
    uint64_t first[HPFC_MAX_LEVELS + 1];
    uint64_t pool_bit[HPFC_MAX_LEVELS], pool_bits[HPFC_MAX_LEVELS];
    /* dense pixel ids (hpfc_dart_index): level l's pixels from
     * pixel_first[l], image by image in pool order, each in scanline order;
     * pixel_first[levels] is all pixels */
    uint64_t pixel_first[HPFC_MAX_LEVELS + 1];
    uint64_t image_pixels; /* cols * rows */
    uint32_t root_cols, cols;
    uint64_t bound;   /* pixels * the walker's cap: the indices' bound */
    int bound_status; /* HPFC_E_LIMIT when that overflows 64 bits */
} key_index;

struct hpfc_walker {
    const hpfc_file *file;
    uint32_t levels;
    uint32_t cap;            /* most crossings of any word in the file */
    uint64_t budget;         /* most stabbings a walk may follow */
    uint64_t leaf_budget;    /* most leaves a walk along one road may meet */
    word_parts p_word, q_word; /* a pixel P's parsed word, and Q's across its road */
    char *symbols;           /* the word last decoded (cap + 4 symbols), parsed or
                              * counted at once */
    uint64_t visited;        /* words decoded */
    bool p_word_valid;       /* p_word holds the pixel at bit p_word_slot */
    uint64_t p_word_slot;
    word_cache cache;
    cached_word *uncached;   /* one word built outside the cache */
    bool uncached_valid;
    key_index keys; /* built on the first key that is not cached */
};

/* Reference of a cache entry: its offset in the arena in 8-byte units, + 1. */
static inline cached_word *cache_entry(const word_cache *c, uint32_t ref)
{
    return (cached_word *)(void *)(c->arena + (size_t)(ref - 1) * 8);
}

/* Key block of a reference (as cache_entry's). */
static inline key_block *cache_block(const word_cache *c, uint32_t ref)
{
    return (key_block *)(void *)(c->arena + (size_t)(ref - 1) * 8);
}

/* Allocates the cache (limit bytes, 0 = none) and the uncached entry. */
int topo_cache_init(hpfc_walker *w, size_t limit);
void topo_cache_free(hpfc_walker *w);
/* The entry of word pixel px (full path), decoded into the cache if it is
 * not there: HPFC_OK, a decoding status (as topo_parse_pixel's; the entry
 * of a word with a broken grammar is returned with its parse_status set),
 * or TOPO_RETRY / TOPO_UNCACHED. `own`: px comes from the caller, so a bad
 * path is an argument error (as reader_pixel_slot_bit says), not
 * corruption. */
topo_result topo_cache_load(hpfc_walker *w, const hpfc_pixel *px, bool own, uint32_t *ref);
static inline uint64_t topo_slot_hash(uint64_t slot)
{
    uint64_t h = slot * 0x9E3779B97F4A7C15ull;
    return h ^ h >> 29;
}

/* The key block of slot `slot`, NULL when there is none (one entry per
 * slot at most is keyed, so the first match is the one). Inline: it is
 * most of a key operator on a warm cache. */
static inline key_block *topo_cache_find_slot(const word_cache *c, uint64_t slot)
{
    if (!c->arena)
        return NULL;
    uint64_t h = topo_slot_hash(slot);
    uint32_t check = (uint32_t)(h >> 32);
    for (size_t b = (size_t)h & c->mask;; b = (b + 1) & c->mask) { /* at most half full */
        const cache_bucket *k = &c->slots[b];
        if (!k->ref)
            return NULL;
        if (k->check == check && cache_block(c, k->ref)->slot == slot)
            return cache_block(c, k->ref);
    }
}
/* Marks entry ref, whose path is its slot's own, as keyed: found by slot,
 * through a new key block (filled with the arrivals the entry holds).
 * HPFC_OK, or TOPO_RETRY / TOPO_UNCACHED as topo_cache_load. */
topo_result topo_cache_key(hpfc_walker *w, uint32_t ref);
/* Records in entry ref's key block, if it has one, crossing k's arrival
 * (as its cached crossing holds it). */
void topo_block_arrival(hpfc_walker *w, uint32_t ref, uint32_t k);
/* px's entry from the cache, or else built in the walker's uncached entry (valid
 * until the next call): for operators that look at one word. */
int topo_word_view(hpfc_walker *w, const hpfc_pixel *px, cached_word **out);
/* The pixel of an entry. */
void topo_entry_pixel(cached_word *e, hpfc_pixel *px);

/* Where an edge arrives: crossing m of its target's pixel (twin = out_m),
 * pred(m) (next = out_pred(m)) and the target vertex. */
typedef struct topo_arrival {
    uint32_t m, pred, vertex;
} topo_arrival;

/* Dart d, or with from_succ the dart out_succ(k) of its origin (prev(d) is
 * that dart's twin), followed to its target through the cache
 * (topo_links.c): *end gets the target's pixel, written only on success.
 * The same answers as without the cache, or TOPO_RETRY / TOPO_UNCACHED. */
topo_result topo_cached_arrive(hpfc_walker *w, const hpfc_dart *d, bool from_succ,
                               hpfc_pixel *end, topo_arrival *a);
/* The walk of topo_cached_arrive from crossing k (a junction's) of entry
 * ref: the entry and crossing where it arrives. */
topo_result topo_cached_follow(hpfc_walker *w, uint32_t ref, uint32_t k, uint32_t *end_ref,
                               uint32_t *end_m);
/* ---- the walker (topo_walk.c) --------------------------------------------- */

/* The operators on one dart. */
typedef enum topo_op { TOPO_TWIN, TOPO_NEXT, TOPO_PREV, TOPO_ORIGIN, TOPO_TARGET } topo_op;

/* Dart d, or with from_succ the dart out_succ(k) of its origin (prev(d) is
 * that dart's twin), followed to its target: through the cache when it can
 * hold what the walk needs, else (or when it was emptied twice under the
 * walk) without it. *end gets the target's pixel, written only on
 * success. */
int topo_arrive(hpfc_walker *w, const hpfc_dart *d, bool from_succ, hpfc_pixel *end,
                topo_arrival *a);
/* origin(d): the vertex of d's crossing, in d's own word. */
int topo_dart_origin(hpfc_walker *w, const hpfc_dart *d, hpfc_vertex *out);
/* The parsed word of a caller's pixel (from the cache, or built alone):
 * its decoding status, else its grammar's. */
int topo_parsed_word(hpfc_walker *w, const hpfc_pixel *px, cached_word **e);

/* Operator op on dart d: a dart into *dart (twin, next, prev) or a vertex
 * into *vertex (origin, target); the other may be NULL. The dart
 * operators' answers and statuses, cache or not. Inline: with op a
 * constant, each public operator is its one call. */
static inline int topo_dart_op(hpfc_walker *w, const hpfc_dart *d, topo_op op, hpfc_dart *dart,
                               hpfc_vertex *vertex)
{
    if (!w || !d)
        return HPFC_E_ARG;
    if (op == TOPO_ORIGIN)
        return topo_dart_origin(w, d, vertex);
    topo_arrival a;
    /* prev(out_k) = twin(out_succ[k]) */
    int st = topo_arrive(w, d, op == TOPO_PREV, op == TOPO_TARGET ? &vertex->pixel : &dart->pixel,
                         &a);
    if (st)
        return st;
    switch (op) {
    case TOPO_NEXT: dart->crossing = a.pred; break; /* next(in_m) = out_pred[m] */
    case TOPO_TARGET: vertex->local = a.vertex; break;
    default: dart->crossing = a.m; /* twin(d) = out_m where d arrives */
    }
    return HPFC_OK;
}

static inline int topo_copy_pixel(hpfc_pixel *dst, const hpfc_pixel *src)
{
    if (src->depth >= HPFC_MAX_LEVELS)
        return HPFC_E_ARG;
    dst->depth = src->depth;
    memcpy(dst->path, src->path, (src->depth + 1) * sizeof src->path[0]);
    return HPFC_OK;
}

/* ---- keys and pixels (topo_index.c) ---------------------------------------- */

/* Frees the parent index. */
void topo_index_free(hpfc_walker *w);
/* The parent index, built on first use: HPFC_OK, or the file's status
 * (HPFC_E_NOMEM: not built, the next call tries again). */
int topo_index_ready(hpfc_walker *w);
/* The path and dense id of the word pixel of a key's slot (HPFC_E_ARG when
 * no word slot starts there). */
int topo_key_pixel(hpfc_walker *w, uint64_t key, hpfc_pixel *px, uint64_t *id);
/* The dense id of the word pixel at depth `depth` whose path ends in
 * `last`, with slot `slot`. */
int topo_pixel_id(hpfc_walker *w, uint32_t depth, const path_step *last, uint64_t slot,
                  uint64_t *id);

/* ---- parsing and crossing identification (topo_cross.c) ------------------- */

/* Decodes px's word into w->symbols, *len symbols (HPFC_E_CORRUPT if the
 * slot holds no word that fits the walker). */
int topo_decode_word(hpfc_walker *w, const hpfc_pixel *px, size_t *len);
/* Parses the word just decoded into lw (word_parse_symbols' status; on
 * HPFC_E_CORRUPT lw holds its road counts). */
int topo_parse_decoded(hpfc_walker *w, word_parts *lw, size_t len);
/* Decodes and parses px's word into lw (HPFC_E_CORRUPT if malformed). */
int topo_parse_pixel(hpfc_walker *w, word_parts *lw, const hpfc_pixel *px);
/* hpfc_walker_create with a cache of `cache_limit` bytes (0: none, as
 * hpfc_walker_set_cache_size(w, 0) leaves it, without making the default
 * cache first). */
int topo_walker_create(const hpfc_file *file, size_t cache_limit, hpfc_walker **out);
/* Crossings on road `road` of a word pixel, decoded (a topo_road_counter;
 * its flow is always TOPO_DONE). */
topo_result topo_road_count(hpfc_walker *w, const hpfc_pixel *px, int road, uint32_t *count);
int topo_leaf_box(const hpfc_file *f, const hpfc_pixel *px, road_box *b);
/* The leaf at position t along b's road, on b's side (inside) or across;
 * located from `near`, a pixel next to it (reader_locate_near; NULL: from
 * the root). out may be near. */
int topo_locate_on_road(const hpfc_file *f, const hpfc_pixel *near, const road_box *b, int road,
                        int64_t t, bool inside, hpfc_pixel *out, road_box *out_box);
/* Crossing k of P (parsed in lw) seen from across its road: pixel Q (parsed
 * into qlw, which must differ from lw) and the crossing's index *m in Q.
 * p_located: P's path is a descent the reader made (leaf iteration, point
 * location), so the leaves next to P are located from it
 * (reader_locate_near); otherwise (a caller's pixel, whose path above its
 * own level is not checked) from the root, as for a path that names the
 * pixel by mistake the answers must not depend on how it was found. */
int topo_cross_road(hpfc_walker *w, const hpfc_pixel *p, bool p_located, const word_parts *lw,
                    uint32_t k, hpfc_pixel *q, word_parts *qlw, uint32_t *m);
/* topo_cross_road, and *spans: Q spans P's whole side (Algorithm 1's first
 * case). Then every crossing of P's road meets that same Q, and the
 * crossing after k on the road is Q's crossing *m - 1: a caller going
 * through a road's crossings in order needs this call for its first only
 * (the faces' flood fill does). */
/* Descends from px to the first leaf below it (pixel (0,0) of each image):
 * the leaves' depth-first order starts there (hpfc_leaf_first, and one
 * root pixel's leaves for faces_stream). */
int topo_first_leaf_below(const hpfc_file *f, hpfc_pixel *px);
int topo_cross_road_spans(hpfc_walker *w, const hpfc_pixel *p, bool p_located,
                          const word_parts *lw, uint32_t k, hpfc_pixel *q, word_parts *qlw,
                          uint32_t *m, bool *spans);
/* How many crossings a word pixel has on a road: topo_road_count, or the
 * walker cache's answer (topo_links.c). */
typedef topo_result (*topo_road_counter)(hpfc_walker *w, const hpfc_pixel *px, int road,
                                         uint32_t *count);
/* Sum of road-`road` crossings of the leaves on b's side that follow b, in
 * b's clockwise order, up to the end of the extent [qlo, qhi), each leaf's
 * count taken from `count`; the first located from `near`, each next from
 * the one before. */
topo_result topo_crossings_after(hpfc_walker *w, const hpfc_pixel *near, const road_box *b,
                                 int road, int64_t qlo, int64_t qhi, topo_road_counter count,
                                 uint64_t *sum);

#endif
