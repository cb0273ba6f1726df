/*
 * Faces with holes (spec/hpfc-format.md, "Faces").
 *
 * The fragments of spec §3.11 are every crossing's local darts in_k and
 * out_k and every private pixel. Rule 2 always joins out_{k-1} and in_k (the
 * boundary stretch between consecutive crossings), so the union-find keeps
 * one node per such pair: node k of a word pixel with n crossings holds in_k
 * and out_{k-1} (cyclically), a private pixel has one node. Node k's
 * smallest fragment is fragment 2k - 1 (node 0's is fragment 0), so the
 * order of nodes is the order of §3.11's smallest fragments, and numbering
 * faces by their smallest node numbers them as the spec does. The unions:
 *   - next(in_k) = out_pred[k]: one sidewalk inside the pixel;
 *   - out_a and in_b for consecutive crossings a, b of the pixel: the
 *     stretch of the pixel's boundary between them is one region;
 *   - out_k of P and in_m of Q where the same crossing is seen from both
 *     sides of a road: one sidewalk across the road;
 *   - a road stretch without crossings between two leaves: the regions on
 *     both sides. Every such stretch is the whole side of the smaller leaf,
 *     so each leaf only looks at the neighbour that spans its side.
 * The classes are the faces.
 */
#include <pthread.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "arrays.h"
#include "faces.h"
#include "file.h"
#include "labels.h"
#include "reader.h"
#include "tasks.h"
#include "topo.h"

/* A leaf's entry: its first node and its crossing count (0 when private)
 * in one word, the count in the low ENTRY_COUNT_BITS bits. */
#define ENTRY_COUNT_BITS 24
#define ENTRY_COUNT_MAX ((UINT64_C(1) << ENTRY_COUNT_BITS) - 1)
#define ENTRY_BASE_MAX (UINT64_MAX >> ENTRY_COUNT_BITS)
#define ENTRY_EMPTY UINT64_MAX /* no leaf there (never a leaf's: base < ENTRY_BASE_MAX) */

static uint64_t entry_base(uint64_t e)
{
    return e >> ENTRY_COUNT_BITS;
}

static uint64_t entry_crossings(uint64_t e)
{
    return e & ENTRY_COUNT_MAX;
}

/* The node of in_k, and of out_k, in a word pixel of n crossings. */
static uint64_t in_node(uint64_t base, uint64_t k)
{
    return base + k;
}

static uint64_t out_node(uint64_t base, uint64_t n, uint64_t k)
{
    return base + (k + 1) % n;
}

/* The union-find, then node -> face id, takes one word per node: 32 bits
 * while the nodes number below 2^31 (the top bit tags numbered roots in
 * number_faces), else 64. A continental map has millions of nodes. */
typedef struct node_array {
    uint32_t *narrow;
    uint64_t *wide;
} node_array;

static uint64_t node_get(const node_array *a, uint64_t x)
{
    return a->narrow ? a->narrow[x] : a->wide[x];
}

static void node_set(node_array *a, uint64_t x, uint64_t v)
{
    if (a->narrow)
        a->narrow[x] = (uint32_t)v;
    else
        a->wide[x] = v;
}

static uint64_t node_tag(const node_array *a)
{
    return a->narrow ? UINT64_C(1) << 31 : UINT64_C(1) << 63;
}

static int node_array_init(node_array *a, uint64_t nodes, uint64_t narrow_below)
{
    size_t n = (size_t)nodes + 1;
    if (nodes < narrow_below)
        a->narrow = malloc(n * sizeof *a->narrow);
    else
        a->wide = malloc(n * sizeof *a->wide);
    if (!a->narrow && !a->wide)
        return HPFC_E_NOMEM;
    for (uint64_t x = 0; x < nodes; x++)
        node_set(a, x, x);
    return HPFC_OK;
}

/* The leaves' entries by position in the pools, 8 bytes a slot of k_w bits
 * (about 9 bytes a leaf on a continental map): the word slot at pool bit b
 * of level l >= 1 has entry first[l] + b / k_w (word slots are k_w bits
 * long and disjoint, so two never share an entry), the root record r
 * entry first[0] + r. Why not a hash table of slots (16 bytes a leaf, a
 * third empty): leaves come in pool order level by level and their
 * neighbours lie close by in the pools, so the passes below read this
 * table almost in order, where a hash sent every lookup to a random
 * place (a cache miss each: most of the time of number_leaves). */
typedef struct leaf_table {
    uint64_t *entry;                     /* ENTRY_EMPTY where no leaf is */
    uint64_t first[HPFC_MAX_LEVELS + 1]; /* level l's entries: [first[l], first[l + 1]) */
    uint64_t pool_bit[HPFC_MAX_LEVELS];  /* absolute bit of the level's pool */
    uint64_t unit[HPFC_MAX_LEVELS];      /* bits per entry: a root record, k_w below */
    /* the pool bit of the level's first entry: 0, but for one root pixel's
     * table (faces_stream) the start of its run */
    uint64_t lo[HPFC_MAX_LEVELS];
} leaf_table;

/* What a file's pools must be for faces numbered on another copy to hold
 * on it: every level's counts, widths and pool size, and its pool's bytes
 * (by their CRC-32C). The grid and the layout follow from these. */
typedef struct pools_print {
    uint32_t levels;
    bool compact;
    hpfc_level_info level[HPFC_MAX_LEVELS]; /* pool_offset left 0 */
    uint32_t crc[HPFC_MAX_LEVELS];
} pools_print;

struct hpfc_faces {
    const hpfc_file *file; /* NULL while detached (faces_detach) */
    leaf_table leaves;
    node_array parent;
    uint64_t nodes, count;
    pools_print print; /* set while detached */
    bool shared;       /* the union-find is shared by threads (numbering only) */
    /* one root pixel's leaves only (faces_stream): roads on its boundary
     * are left to the plan's gaps; cols x rows pixels an image below it */
    bool scoped;
    uint32_t cols, rows;
};

/* Sizes the table from the level table, for a file of `leaves` leaves. A
 * valid file needs fewer than 8 entries a leaf below the root (a level's
 * pool holds its masks, at most a quarter entry a pixel; its word slots, one
 * entry each; its refined slots, at most 16 entries each, and a refined
 * pixel has at least 4 pixels below it): more is a corrupt level table,
 * whose pools could ask for far more memory than the file has leaves. */
static int leaf_table_init(leaf_table *t, const hpfc_file *f, uint64_t leaves)
{
    hpfc_file_info info;
    hpfc_level_info lv;
    hpfc_file_get_info(f, &info);
    uint64_t total = 0;
    for (uint32_t l = 0; l < info.levels; l++) {
        hpfc_file_get_level(f, l, &lv);
        uint64_t n;
        t->first[l] = total;
        t->pool_bit[l] = lv.pool_offset * 8;
        reader_slot_grid(f, l, &t->unit[l], &n);
        if (n > UINT64_MAX / 8 - total)
            return HPFC_E_CORRUPT;
        total += n;
    }
    t->first[info.levels] = total;
    if (leaves < UINT64_MAX / 16 && total - t->first[1] > 8 * leaves + 64)
        return HPFC_E_CORRUPT;
    if (total > SIZE_MAX / sizeof *t->entry || !(t->entry = malloc(total ? total * 8 : 1)))
        return HPFC_E_NOMEM;
    memset(t->entry, 0xFF, total * 8); /* ENTRY_EMPTY */
    return HPFC_OK;
}

/* The entry of leaf px: NULL when px is no word pixel of the file's (a
 * caller's refined pixel: *st = HPFC_E_ARG) or has no entry. */
static uint64_t *leaf_entry(const hpfc_faces *fc, const hpfc_pixel *px, int *st)
{
    uint64_t slot;
    if (!fc->file) { /* detached: no file to read the pixel in */
        *st = HPFC_E_ARG;
        return NULL;
    }
    if ((*st = reader_leaf_slot_bit(fc->file, px, &slot)))
        return NULL;
    const leaf_table *t = &fc->leaves;
    uint32_t l = px->depth; /* below the file's levels: the slot exists */
    uint64_t off = slot - t->pool_bit[l];
    if (off < t->lo[l])
        return NULL; /* before one root pixel's run */
    uint64_t at = t->first[l] + (off - t->lo[l]) / t->unit[l];
    return at < t->first[l + 1] ? &t->entry[at] : NULL;
}

static int node_base(const hpfc_faces *fc, const hpfc_pixel *px, uint64_t *base)
{
    int st;
    const uint64_t *e = leaf_entry(fc, px, &st);
    if (st)
        return st;
    if (!e || *e == ENTRY_EMPTY)
        return HPFC_E_CORRUPT;
    *base = entry_base(*e);
    return HPFC_OK;
}

static uint64_t find(node_array *parent, uint64_t x)
{
    for (uint64_t p; (p = node_get(parent, x)) != x; x = p) {
        p = node_get(parent, p); /* path halving */
        node_set(parent, x, p);
    }
    return x;
}

/* The union-find shared by the numbering's threads (hpfc_faces_build_threads):
 * every parent is smaller than its child (a root links under the smaller
 * root), so a parent once read is an ancestor still, whatever the other
 * threads do after; path halving stores an ancestor, and a root is only
 * ever linked by a compare-and-swap that finds it still a root. The classes,
 * and so the faces' numbers, do not depend on the order of the unions. */
static uint64_t node_load(const node_array *a, uint64_t x)
{
    return a->narrow ? __atomic_load_n(&a->narrow[x], __ATOMIC_RELAXED)
                     : __atomic_load_n(&a->wide[x], __ATOMIC_RELAXED);
}

static void node_store(node_array *a, uint64_t x, uint64_t v)
{
    if (a->narrow)
        __atomic_store_n(&a->narrow[x], (uint32_t)v, __ATOMIC_RELAXED);
    else
        __atomic_store_n(&a->wide[x], v, __ATOMIC_RELAXED);
}

/* Links root x under y if x is a root still. */
static bool node_link(node_array *a, uint64_t x, uint64_t y)
{
    if (a->narrow) {
        uint32_t was = (uint32_t)x;
        return __atomic_compare_exchange_n(&a->narrow[x], &was, (uint32_t)y, false, __ATOMIC_RELAXED,
                                           __ATOMIC_RELAXED);
    }
    uint64_t was = x;
    return __atomic_compare_exchange_n(&a->wide[x], &was, y, false, __ATOMIC_RELAXED, __ATOMIC_RELAXED);
}

static uint64_t find_shared(node_array *parent, uint64_t x)
{
    for (uint64_t p; (p = node_load(parent, x)) != x; x = p) {
        p = node_load(parent, p);
        node_store(parent, x, p);
    }
    return x;
}

/* The smaller root wins: face 0 stays outer, and a class's root is its
 * smallest node. */
static void unite(node_array *parent, bool shared, uint64_t a, uint64_t b)
{
    if (!shared) {
        a = find(parent, a), b = find(parent, b);
        if (a != b)
            node_set(parent, a > b ? a : b, a < b ? a : b);
        return;
    }
    for (;;) {
        a = find_shared(parent, a), b = find_shared(parent, b);
        if (a == b || node_link(parent, a > b ? a : b, a < b ? a : b))
            return;
    }
}

/* Node of the boundary region of a parsed pixel that holds the stretch of
 * road `road` after its first `t` crossings (in the pixel's clockwise
 * order): the out-dart of the crossing just before, cyclically. */
static uint64_t gap_node(const word_parts *lw, uint64_t base, int road, uint64_t t)
{
    if (lw->n == 0)
        return base;
    uint64_t k = lw->road_off[road] + t; /* the crossing after the stretch */
    return out_node(base, lw->n, k == 0 ? lw->n - 1 : k - 1);
}

/* ---- the leaves in runs, for several threads ----------------------------------- */

/* Leaves are reached only one after another (hpfc_leaf_next), so the count
 * keeps every RUN_LEAVES-th (772 bytes each) and each thread takes whole
 * runs: a run's leaves are parsed, given their first node, then united.
 * Fuzzing builds make runs of a few leaves, so that the small files a
 * fuzzer makes are numbered in many runs too. */
#ifdef FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION
enum { RUN_LEAVES = 3 };
#else
enum { RUN_LEAVES = 4096 };
#endif

/* Where in a leaf's checks a failure came, in the order one thread makes
 * them: a failure's key is its leaf's number << FAIL_ORDER_BITS | order. */
enum { FAIL_READ = 0, FAIL_OUTSIDE = 1, FAIL_TWICE = 2, FAIL_LIMIT = 3, FAIL_ORDER_BITS = 2 };

typedef struct numbering numbering;
typedef void (*run_step)(numbering *nb, hpfc_walker *w, size_t run);

/* One numbering's runs and their threads. The failure kept is the first
 * by key, whichever thread meets it; a run that starts after it is not
 * taken, and runs are taken in order, so every run before it is done:
 * any number of threads gives the status one thread does. */
struct numbering {
    hpfc_faces *fc;
    hpfc_pixel *run_first; /* each run's first leaf */
    uint64_t *run_nodes;   /* each run's node count */
    size_t runs;
    uint64_t run_size; /* leaves a run */
    uint64_t leaves;
    run_step step;
    size_t next_run;     /* the next run to take (atomic) */
    uint64_t fail_key;   /* UINT64_MAX while none (atomic, written under lock) */
    int fail_status;
    pthread_mutex_t lock;
    bool locked;         /* lock made: more than one thread */
};

static void note_failure(numbering *nb, uint64_t leaf, int order, int st)
{
    uint64_t key = leaf << FAIL_ORDER_BITS | (uint64_t)order;
    if (nb->locked)
        pthread_mutex_lock(&nb->lock);
    if (key < __atomic_load_n(&nb->fail_key, __ATOMIC_RELAXED)) {
        __atomic_store_n(&nb->fail_key, key, __ATOMIC_RELAXED);
        nb->fail_status = st;
    }
    if (nb->locked)
        pthread_mutex_unlock(&nb->lock);
}

/* Leaf `leaf` of a run whose first is `first`, px holding the one before:
 * the count met every one of them, so the end of the leaves here is a
 * file that changed under us. */
static int run_next(const hpfc_file *f, uint64_t first, uint64_t leaf, hpfc_pixel *px)
{
    int st = leaf > first ? hpfc_leaf_next(f, px) : HPFC_OK;
    return st == HPFC_E_NO_PIXEL ? HPFC_E_CORRUPT : st;
}

static uint64_t run_leaves(const numbering *nb, size_t run)
{
    uint64_t first = (uint64_t)run * nb->run_size;
    return nb->leaves - first < nb->run_size ? nb->leaves - first : nb->run_size;
}

/* Pass 1: the leaves counted (a tree has exactly as many as the level table
 * declares word pixels; addresses that alias one child image make the tree
 * a DAG whose leaf paths can number n^L in a small file: counting stops
 * there), each run's first kept, the table of entries made. */
static int count_leaves(numbering *nb)
{
    hpfc_faces *fc = nb->fc;
    hpfc_pixel px;
    uint64_t most = file_total_leaves(fc->file);
    size_t cap = 0;
    int st = hpfc_leaf_first(fc->file, &px);
    for (; !st; st = hpfc_leaf_next(fc->file, &px)) {
        if (nb->leaves >= most)
            return HPFC_E_CORRUPT;
        if (nb->leaves % nb->run_size == 0) {
            if (nb->runs == cap) {
                size_t grown = cap ? 2 * cap : 16;
                hpfc_pixel *p = realloc(nb->run_first, grown * sizeof *p);
                if (!p)
                    return HPFC_E_NOMEM;
                nb->run_first = p, cap = grown;
            }
            nb->run_first[nb->runs++] = px;
        }
        nb->leaves++;
    }
    if (st != HPFC_E_NO_PIXEL)
        return st;
    if (!(nb->run_nodes = calloc(nb->runs ? nb->runs : 1, sizeof *nb->run_nodes)))
        return HPFC_E_NOMEM;
    return leaf_table_init(&fc->leaves, fc->file, nb->leaves);
}

/* Pass 2, a run: each leaf's crossing count in its entry, beside its
 * number (entry_base) while the first nodes are not known; the run's node
 * count. An entry found taken is a second path to its leaf: the failure is
 * the later of the two paths'. */
static void parse_run(numbering *nb, hpfc_walker *w, size_t run)
{
    hpfc_faces *fc = nb->fc;
    hpfc_pixel px = nb->run_first[run];
    uint64_t first = (uint64_t)run * nb->run_size, end = first + run_leaves(nb, run), nodes = 0;
    for (uint64_t leaf = first; leaf < end; leaf++) {
        int st = run_next(fc->file, first, leaf, &px);
        uint64_t *e = st ? NULL : leaf_entry(fc, &px, &st);
        if (st || (st = topo_parse_pixel(w, &w->p_word, &px))) {
            note_failure(nb, leaf, FAIL_READ, st);
            return;
        }
        if (!e) { /* outside its level's entries */
            note_failure(nb, leaf, FAIL_OUTSIDE, HPFC_E_CORRUPT);
            return;
        }
        uint64_t n = w->p_word.n, was = ENTRY_EMPTY;
        uint64_t mine = leaf << ENTRY_COUNT_BITS | (n > ENTRY_COUNT_MAX ? ENTRY_COUNT_MAX : n);
        if (!__atomic_compare_exchange_n(e, &was, mine, false, __ATOMIC_RELAXED, __ATOMIC_RELAXED)) {
            uint64_t other = entry_base(was);
            note_failure(nb, other > leaf ? other : leaf, FAIL_TWICE, HPFC_E_CORRUPT);
            return;
        }
        if (n > ENTRY_COUNT_MAX) { /* 2^24 crossings in one leaf */
            note_failure(nb, leaf, FAIL_LIMIT, HPFC_E_LIMIT);
            return;
        }
        nodes += n ? n : 1;
    }
    nb->run_nodes[run] = nodes;
}

/* Between passes 2 and 3: the node count, which must fit an entry's
 * base; past it, the failure is the first run's that crosses the limit. */
static int sum_runs(numbering *nb)
{
    uint64_t total = 0;
    for (size_t r = 0; r < nb->runs; r++) {
        uint64_t n = nb->run_nodes[r];
        if (total > ENTRY_BASE_MAX - n) { /* 2^40 nodes in all */
            note_failure(nb, (uint64_t)r * nb->run_size, FAIL_LIMIT, HPFC_E_LIMIT);
            return HPFC_E_LIMIT;
        }
        total += n;
    }
    nb->fc->nodes = total;
    return HPFC_OK;
}

/* Pass 3: each leaf's first node in its entry. Pass 2 left every leaf's
 * number in its entry, so the bases are the prefix sums of the leaves'
 * node counts by leaf number: two sweeps of the table and one of the
 * counts, where a walk of the leaves in their order would decode the tree
 * again. The counts take 4 bytes a leaf (8 past 2^32 nodes), freed before
 * the union-find takes as many a node. */
static int bases_from_entries(numbering *nb)
{
    hpfc_faces *fc = nb->fc;
    leaf_table *t = &fc->leaves;
    hpfc_file_info info;
    hpfc_file_get_info(fc->file, &info);
    uint64_t slots = t->first[info.levels];
    bool narrow = fc->nodes <= UINT32_MAX;
    size_t unit = narrow ? sizeof(uint32_t) : sizeof(uint64_t);
    if (nb->leaves > SIZE_MAX / unit)
        return HPFC_E_NOMEM;
    void *sums = malloc(nb->leaves ? (size_t)nb->leaves * unit : 1);
    if (!sums)
        return HPFC_E_NOMEM;
    uint32_t *sum32 = sums;
    uint64_t *sum64 = sums;
    for (uint64_t x = 0; x < slots; x++) {
        uint64_t e = t->entry[x];
        if (e == ENTRY_EMPTY)
            continue;
        uint64_t n = entry_crossings(e), nodes = n ? n : 1;
        if (narrow)
            sum32[entry_base(e)] = (uint32_t)nodes;
        else
            sum64[entry_base(e)] = nodes;
    }
    uint64_t total = 0;
    for (uint64_t leaf = 0; leaf < nb->leaves; leaf++) {
        uint64_t nodes = narrow ? sum32[leaf] : sum64[leaf];
        if (narrow)
            sum32[leaf] = (uint32_t)total;
        else
            sum64[leaf] = total;
        total += nodes;
    }
    for (uint64_t x = 0; x < slots; x++) {
        uint64_t e = t->entry[x];
        if (e == ENTRY_EMPTY)
            continue;
        uint64_t leaf = entry_base(e);
        t->entry[x] = (narrow ? sum32[leaf] : sum64[leaf]) << ENTRY_COUNT_BITS | entry_crossings(e);
    }
    free(sums);
    return total == fc->nodes ? HPFC_OK : HPFC_E_CORRUPT;
}

/* Does road `road` of leaf p lie on its root pixel's boundary? The pixels
 * of its path below the root all touch that side. */
static bool on_root_side(uint32_t cols, uint32_t rows, const hpfc_pixel *p, int road)
{
    for (uint32_t d = 1; d <= p->depth; d++) {
        uint32_t i = p->path[d].i, j = p->path[d].j;
        if ((road == HPFC_WEST && i != 0) || (road == HPFC_EAST && i + 1 != cols) ||
            (road == HPFC_NORTH && j != 0) || (road == HPFC_SOUTH && j + 1 != rows))
            return false;
    }
    return true;
}

/* A numbering of one root pixel's leaves leaves its boundary roads out:
 * what lies across them is another root's (faces_stream's gaps join it). */
static bool road_left_out(const hpfc_faces *fc, const hpfc_pixel *p, int road)
{
    return fc->scoped && on_root_side(fc->cols, fc->rows, p, road);
}

/* The unions that stay inside one pixel. */
static void unite_inside(hpfc_faces *fc, const word_parts *lw, uint64_t base)
{
    for (uint32_t k = 0; k < lw->n; k++) /* rule 2 holds by construction */
        unite(&fc->parent, fc->shared, in_node(base, k), out_node(base, lw->n, lw->pred[k]));
}

/* A crossing seen from both sides of its road is one pair of sidewalks
 * across it: P's out_k with Q's in_m, and Q's out_m with P's in_k. The leaf
 * whose road is W or N identifies the pair (Algorithm 1, topo_cross_road)
 * and makes both unions; its neighbour, whose road is E or S, skips it.
 * When one leaf Q spans P's side (most roads of a continental map), the
 * road's later crossings are Q's previous ones, without locating Q again
 * or counting the leaves along its side: the same answers. */
static int unite_across(hpfc_faces *fc, hpfc_walker *w, const hpfc_pixel *p, uint64_t base)
{
    const word_parts *lw = &w->p_word;
    for (int road = HPFC_WEST; road <= HPFC_NORTH; road++) {
        if (road_left_out(fc, p, road))
            continue;
        hpfc_pixel q;
        uint32_t mk = 0;
        uint64_t qbase = 0;
        bool spans = false;
        for (uint32_t k = lw->road_off[road]; k < lw->road_off[road + 1]; k++) {
            if (spans) {
                mk--; /* rank one less: at least the leaves' sum, never below Q's road */
            } else {
                int st = topo_cross_road_spans(w, p, true, lw, k, &q, &w->q_word, &mk, &spans);
                if (!st)
                    st = node_base(fc, &q, &qbase);
                if (st)
                    return st;
            }
            unite(&fc->parent, fc->shared, out_node(base, lw->n, k), in_node(qbase, mk));
            unite(&fc->parent, fc->shared, out_node(qbase, w->q_word.n, mk), in_node(base, k));
        }
    }
    return HPFC_OK;
}

/* Crossing-free road stretches: for each road of P without crossings whose
 * neighbour Q spans P's whole side, join P's region there with Q's.
 *
 * Q is found by hpfc_pixel_move, which stops at the first leaf across: a
 * leaf no deeper than P spans P's side (pixels of one level are aligned),
 * a deeper one is one of several smaller leaves, each of which handles its
 * own side. When Q is as large as P, P is the only leaf along Q's side, so
 * no crossing comes after P there, and the road seen from Q is empty too:
 * Q makes the same union from its road W or N, and P leaves its roads E
 * and S to Q. Most empty roads lie between leaves of one size (private
 * pixels in open country), so most take one move and no parse. */
static int unite_empty_roads(hpfc_faces *fc, hpfc_walker *w, const hpfc_pixel *p, uint64_t base)
{
    road_box pb;
    bool have_pb = false;
    int st = HPFC_OK;
    for (int road = 0; road < 4 && !st; road++) {
        if (w->p_word.road_off[road + 1] != w->p_word.road_off[road] || road_left_out(fc, p, road))
            continue; /* crossings link both sides through the sidewalks */
        hpfc_pixel q;
        st = hpfc_pixel_move(fc->file, p, road, &q);
        if (st == HPFC_E_NO_PIXEL) { /* the domain's border: nothing across */
            st = HPFC_OK;
            continue;
        }
        if (st)
            break;
        if (q.depth > p->depth || (q.depth == p->depth && (road == HPFC_EAST || road == HPFC_SOUTH)))
            continue; /* smaller leaves across, or Q makes this union */
        int opposite = (road + 2) % 4;
        uint64_t before = 0, qbase, qn;
        const uint64_t *e = leaf_entry(fc, &q, &st);
        if (!st && (!e || *e == ENTRY_EMPTY))
            st = HPFC_E_CORRUPT;
        if (st)
            break;
        qbase = entry_base(*e), qn = entry_crossings(*e);
        uint64_t on_road = 0; /* Q's crossings on the road */
        if (qn) {             /* a private Q is one node: no word to read */
            if ((st = topo_parse_pixel(w, &w->q_word, &q)))
                break;
            on_road = w->q_word.road_off[opposite + 1] - w->q_word.road_off[opposite];
        }
        /* A larger Q whose road has crossings: those of the leaves along its
         * side after P. A road with none has none after P in a valid file;
         * in a damaged one whose smaller leaves along it have some, the
         * union is still with a node of Q's (the walk did not find every
         * such contradiction before either: not those before P). */
        if (q.depth < p->depth && on_road) {
            road_box qb;
            int64_t qlo, qhi;
            if (!have_pb && (st = topo_leaf_box(fc->file, p, &pb)))
                break;
            have_pb = true;
            if ((st = topo_leaf_box(fc->file, &q, &qb)))
                break;
            road_extent(&qb, road, &qlo, &qhi);
            /* the plain counter's flow is always TOPO_DONE: the status is all;
             * its counts decode other leaves' symbols, not Q's parsed word */
            if ((st = topo_crossings_after(w, p, &pb, road, qlo, qhi, topo_road_count, &before).status))
                break;
            if (before > on_road) {
                st = HPFC_E_CORRUPT; /* more crossings on P's side than on Q's road */
                break;
            }
        }
        uint64_t qnode = qn ? gap_node(&w->q_word, qbase, opposite, before) : qbase;
        unite(&fc->parent, fc->shared, gap_node(&w->p_word, base, road, 0), qnode);
    }
    return st;
}

/* Pass 4, a run: all unions its leaves make. */
static void unite_run(numbering *nb, hpfc_walker *w, size_t run)
{
    hpfc_faces *fc = nb->fc;
    hpfc_pixel px = nb->run_first[run];
    uint64_t first = (uint64_t)run * nb->run_size, end = first + run_leaves(nb, run);
    for (uint64_t leaf = first; leaf < end; leaf++) {
        uint64_t base;
        int st = run_next(fc->file, first, leaf, &px);
        if (!st && !(st = node_base(fc, &px, &base)) && !(st = topo_parse_pixel(w, &w->p_word, &px))) {
            unite_inside(fc, &w->p_word, base);
            if (!(st = unite_across(fc, w, &px, base)))
                st = unite_empty_roads(fc, w, &px, base);
        }
        if (st) {
            note_failure(nb, leaf, FAIL_READ, st);
            return;
        }
    }
}

/* Takes runs in order until none is left or one starts after the first
 * failure known. */
static void take_runs(numbering *nb, hpfc_walker *w)
{
    for (;;) {
        size_t run = __atomic_fetch_add(&nb->next_run, 1, __ATOMIC_RELAXED);
        uint64_t fail_leaf = __atomic_load_n(&nb->fail_key, __ATOMIC_RELAXED) >> FAIL_ORDER_BITS;
        if (run >= nb->runs || (uint64_t)run * nb->run_size > fail_leaf)
            return;
        nb->step(nb, w, run);
    }
}

/* The threads besides the caller, started once for the three passes: each
 * waits for a pass, takes runs until none is left, says it is done, and
 * waits for the next pass or the end. */
typedef struct crew crew;
typedef struct crew_seat {
    crew *c;
    hpfc_walker *w;
} crew_seat;

struct crew {
    numbering *nb;
    unsigned started; /* threads running besides the caller */
    pthread_t id[FACES_MAX_THREADS];
    crew_seat seat[FACES_MAX_THREADS];
    pthread_mutex_t lock; /* guards what follows */
    pthread_cond_t start, done;
    unsigned pass;    /* passes begun */
    unsigned finished; /* threads done with the current pass */
    bool quit;
};

static void *crew_main(void *arg)
{
    crew_seat *seat = arg;
    crew *c = seat->c;
    for (unsigned seen = 0;;) {
        pthread_mutex_lock(&c->lock);
        while (c->pass == seen && !c->quit)
            pthread_cond_wait(&c->start, &c->lock);
        bool quit = c->quit;
        seen = c->pass;
        pthread_mutex_unlock(&c->lock);
        if (quit)
            return NULL;
        take_runs(c->nb, seat->w);
        pthread_mutex_lock(&c->lock);
        if (++c->finished == c->started)
            pthread_cond_signal(&c->done);
        pthread_mutex_unlock(&c->lock);
    }
}

/* Starts up to `threads` - 1 threads, one a walker after the first: false
 * when none could be (the caller then works alone). */
static bool crew_start(crew *c, numbering *nb, hpfc_walker **walkers, unsigned threads)
{
    c->nb = nb;
    if (pthread_mutex_init(&c->lock, NULL) != 0)
        return false;
    if (pthread_cond_init(&c->start, NULL) != 0) {
        pthread_mutex_destroy(&c->lock);
        return false;
    }
    if (pthread_cond_init(&c->done, NULL) != 0) {
        pthread_cond_destroy(&c->start);
        pthread_mutex_destroy(&c->lock);
        return false;
    }
    for (unsigned k = 1; k < threads; k++) {
        c->seat[c->started] = (crew_seat){c, walkers[k]};
        if (pthread_create(&c->id[c->started], NULL, crew_main, &c->seat[c->started]) != 0)
            break;
        c->started++;
    }
    if (c->started)
        return true;
    pthread_cond_destroy(&c->done);
    pthread_cond_destroy(&c->start);
    pthread_mutex_destroy(&c->lock);
    return false;
}

static void crew_stop(crew *c)
{
    pthread_mutex_lock(&c->lock);
    c->quit = true;
    pthread_cond_broadcast(&c->start);
    pthread_mutex_unlock(&c->lock);
    for (unsigned k = 0; k < c->started; k++)
        pthread_join(c->id[k], NULL);
    pthread_cond_destroy(&c->done);
    pthread_cond_destroy(&c->start);
    pthread_mutex_destroy(&c->lock);
}

/* One pass over every run, by the calling thread (with `w`) and the crew
 * (NULL: alone). The first failure's status, or HPFC_OK. */
static int run_pass(numbering *nb, run_step step, hpfc_walker *w, crew *c)
{
    nb->step = step;
    nb->next_run = 0;
    if (c) {
        pthread_mutex_lock(&c->lock);
        c->finished = 0;
        c->pass++;
        pthread_cond_broadcast(&c->start);
        pthread_mutex_unlock(&c->lock);
    }
    take_runs(nb, w);
    if (c) {
        pthread_mutex_lock(&c->lock);
        while (c->finished < c->started)
            pthread_cond_wait(&c->done, &c->lock);
        pthread_mutex_unlock(&c->lock);
    }
    return nb->fail_key == UINT64_MAX ? HPFC_OK : nb->fail_status;
}

/* A node of the unbounded face (§3.11): the one at the north-west
 * crossroad of the leaf at the domain's north-west corner, *corner. */
static int outer_node(const hpfc_faces *fc, hpfc_walker *w, hpfc_pixel *corner, uint64_t *node)
{
    hpfc_file_info info;
    hpfc_file_get_info(fc->file, &info);
    uint64_t base;
    int st = hpfc_locate(fc->file, info.x0, info.y0 + info.height - 1, corner);
    if (!st)
        st = node_base(fc, corner, &base);
    if (!st)
        st = topo_parse_pixel(w, &w->p_word, corner);
    if (!st)
        *node = gap_node(&w->p_word, base, HPFC_NORTH, 0);
    return st;
}

/* Numbers the classes densely, the unbounded face first. */
static int number_faces(hpfc_faces *fc, hpfc_walker *w)
{
    hpfc_pixel corner;
    uint64_t node;
    int st = outer_node(fc, w, &corner, &node);
    if (st)
        return st;
    node_array *parent = &fc->parent;
    uint64_t outer = find(parent, node);
    for (uint64_t x = 0; x < fc->nodes; x++) /* every node now points at its root */
        node_set(parent, x, find(parent, x));
    /* Face ids in place, in order of each face's smallest node, the outer
     * face 0: a root, once numbered, holds FACE_TAG | id (node numbers stay
     * below the tag bit, node_array's choice of width); a node takes its
     * root's id. Nodes before x are numbered already, and only roots are
     * read. */
    const uint64_t FACE_TAG = node_tag(parent);
    node_set(parent, outer, FACE_TAG | 0);
    fc->count = 1;
    for (uint64_t x = 0; x < fc->nodes; x++) {
        uint64_t r = node_get(parent, x);
        if (r & FACE_TAG)
            continue; /* a root numbered before */
        if (!(node_get(parent, r) & FACE_TAG))
            node_set(parent, r, FACE_TAG | fc->count++);
        node_set(parent, x, node_get(parent, r));
    }
    for (uint64_t x = 0; x < fc->nodes; x++)
        node_set(parent, x, node_get(parent, x) & ~FACE_TAG);
    return HPFC_OK;
}

int hpfc_faces_build(const hpfc_file *file, hpfc_faces **out)
{
    return faces_build_width(file, FACES_NARROW_NODES, 1, 0, NULL, out);
}

int hpfc_faces_build_threads(const hpfc_file *file, unsigned threads, hpfc_faces **out)
{
    return faces_build_width(file, FACES_NARROW_NODES, threads, 0, NULL, out);
}

/* The walkers of the threads after the first, one each, as many as can be
 * made up to `threads` (a walker that cannot be made leaves its runs to
 * the others): how many walkers there are in all. */
static unsigned more_walkers(const hpfc_file *file, hpfc_walker **w, unsigned threads)
{
    unsigned n = 1;
    while (n < threads && !topo_walker_create(file, 0, &w[n]))
        n++;
    return n;
}

/* Passes 1 to 4 and the numbering, with walkers[0] and up to `threads`. */
static int number_all(numbering *nb, hpfc_walker **walkers, unsigned threads, uint64_t narrow_below,
                      unsigned *made)
{
    hpfc_faces *fc = nb->fc;
    int st = count_leaves(nb);
    if (st)
        return st;
    if (threads > nb->runs)
        threads = nb->runs ? (unsigned)nb->runs : 1;
    crew team = {0}, *c = NULL;
    if (threads > 1 && (*made = more_walkers(fc->file, walkers, threads)) > 1 &&
        pthread_mutex_init(&nb->lock, NULL) == 0) {
        nb->locked = true;
        if (crew_start(&team, nb, walkers, *made))
            c = &team, fc->shared = true;
    }
    if (!(st = run_pass(nb, parse_run, walkers[0], c)) && !(st = sum_runs(nb)) &&
        !(st = bases_from_entries(nb)) &&
        !(st = node_array_init(&fc->parent, fc->nodes, narrow_below)) &&
        !(st = run_pass(nb, unite_run, walkers[0], c)))
        st = number_faces(fc, walkers[0]);
    if (c)
        crew_stop(c);
    fc->shared = false;
    return st;
}

int faces_build_width(const hpfc_file *file, uint64_t narrow_below, unsigned threads, uint64_t run_size,
                      uint64_t *failure, hpfc_faces **out)
{
    if (!file || !out)
        return HPFC_E_ARG;
    *out = NULL;
    hpfc_faces *fc = calloc(1, sizeof *fc);
    hpfc_walker *walkers[FACES_MAX_THREADS] = {0};
    unsigned made = 1;
    if (!fc)
        return HPFC_E_NOMEM;
    fc->file = file;
    numbering nb = {.fc = fc, .fail_key = UINT64_MAX, .run_size = run_size ? run_size : RUN_LEAVES};
    /* the flood fill parses each leaf into the walker's scratch words: no cache */
    int st = topo_walker_create(file, 0, &walkers[0]);
    if (!st)
        st = number_all(&nb, walkers, threads < FACES_MAX_THREADS ? threads : FACES_MAX_THREADS,
                        narrow_below, &made);
    for (unsigned k = 0; k < made; k++)
        hpfc_walker_free(walkers[k]);
    if (nb.locked)
        pthread_mutex_destroy(&nb.lock);
    free(nb.run_first);
    free(nb.run_nodes);
    if (failure)
        *failure = nb.fail_key;
    if (st) {
        hpfc_faces_free(fc);
        return st;
    }
    *out = fc;
    return HPFC_OK;
}

void hpfc_faces_free(hpfc_faces *fc)
{
    if (!fc)
        return;
    free(fc->leaves.entry);
    free(fc->parent.narrow);
    free(fc->parent.wide);
    free(fc);
}

uint64_t hpfc_faces_face_count(const hpfc_faces *fc)
{
    return fc ? fc->count : 0;
}

int hpfc_faces_dart_face(const hpfc_faces *fc, const hpfc_dart *d, uint64_t *face)
{
    if (!fc || !d || !face)
        return HPFC_E_ARG;
    int st;
    const uint64_t *e = leaf_entry(fc, &d->pixel, &st);
    if (st)
        return st;
    if (!e || *e == ENTRY_EMPTY)
        return HPFC_E_CORRUPT;
    uint64_t n = entry_crossings(*e);
    if (d->crossing >= n)
        return HPFC_E_ARG; /* no such crossing in the dart's pixel */
    *face = node_get(&fc->parent, out_node(entry_base(*e), n, d->crossing));
    return HPFC_OK;
}

int hpfc_faces_pixel_face(const hpfc_faces *fc, const hpfc_pixel *px, uint64_t *face)
{
    int is_private = 0;
    uint64_t base;
    if (!fc || !fc->file || !px || !face)
        return HPFC_E_ARG;
    int st = hpfc_pixel_is_private(fc->file, px, &is_private);
    if (!st && !is_private)
        st = HPFC_E_ARG;
    if (!st)
        st = node_base(fc, px, &base);
    if (!st)
        *face = node_get(&fc->parent, base);
    return st;
}

/* ---- handed out by a write, bound to the file written ---------------------------- */

/* The print of f's pools; false when a pool lies outside the file (a
 * corrupt level table that open let through cannot, but the CRC must not
 * read past the bytes). */
static bool print_pools(const hpfc_file *f, pools_print *p)
{
    memset(p, 0, sizeof *p);
    hpfc_file_info info;
    hpfc_file_get_info(f, &info);
    p->levels = info.levels;
    p->compact = f->compact;
    for (uint32_t l = 0; l < info.levels; l++) {
        hpfc_level_info lv = {0};
        hpfc_file_get_level(f, l, &lv);
        uint64_t bytes = format_pool_bytes(lv.pool_bits);
        if (lv.pool_offset > f->size || bytes > f->size - lv.pool_offset)
            return false;
        p->crc[l] = crc32c_update(0, f->data + lv.pool_offset, (size_t)bytes);
        p->level[l] = lv;
        p->level[l].pool_offset = 0; /* where the pool lies may differ */
    }
    return true;
}

static bool same_level(const hpfc_level_info *a, const hpfc_level_info *b)
{
    return a->word_pixels == b->word_pixels && a->refined_pixels == b->refined_pixels &&
           a->images == b->images && a->word_bits == b->word_bits &&
           a->address_bits == b->address_bits && a->pool_bits == b->pool_bits &&
           a->cell_w == b->cell_w && a->cell_h == b->cell_h;
}

static bool same_pools(const pools_print *a, const pools_print *b)
{
    if (a->levels != b->levels || a->compact != b->compact)
        return false;
    for (uint32_t l = 0; l < a->levels; l++)
        if (!same_level(&a->level[l], &b->level[l]) || a->crc[l] != b->crc[l])
            return false;
    return true;
}

int faces_detach(hpfc_faces *fc)
{
    if (!print_pools(fc->file, &fc->print))
        return HPFC_E_CORRUPT;
    fc->file = NULL;
    return HPFC_OK;
}

int hpfc_faces_attach(hpfc_faces *fc, const hpfc_file *file)
{
    if (!fc || !file || fc->file)
        return HPFC_E_ARG;
    pools_print p;
    if (!print_pools(file, &p) || !same_pools(&p, &fc->print))
        return HPFC_E_ARG;
    /* the leaves' entries are relative to their level's pool: only where
     * the pools start moves */
    for (uint32_t l = 0; l < p.levels; l++) {
        hpfc_level_info lv;
        hpfc_file_get_level(file, l, &lv);
        fc->leaves.pool_bit[l] = lv.pool_offset * 8;
    }
    fc->file = file;
    return HPFC_OK;
}

/* ---- for the LABL writer (labels.h) ---------------------------------------------- */

int faces_leaf_nodes(const hpfc_faces *fc, uint32_t level, uint64_t bit, uint64_t *base,
                     uint64_t *crossings)
{
    const leaf_table *t = &fc->leaves;
    if (level >= HPFC_MAX_LEVELS || !t->unit[level] || bit < t->lo[level])
        return HPFC_E_ARG;
    uint64_t at = t->first[level] + (bit - t->lo[level]) / t->unit[level];
    if (at >= t->first[level + 1] || t->entry[at] == ENTRY_EMPTY)
        return HPFC_E_ARG;
    *base = entry_base(t->entry[at]);
    *crossings = entry_crossings(t->entry[at]);
    return HPFC_OK;
}

uint64_t faces_node_face(const hpfc_faces *fc, uint64_t node)
{
    return node_get(&fc->parent, node);
}

/* ---- the faces one root pixel at a time (faces.h) ------------------------------- */

/*
 * A root pixel's leaves are numbered alone, as hpfc_faces_build numbers
 * the whole file, but for the roads on the root's boundary. Along each
 * side of a root the crossings on that line cut it into gaps, the same
 * gaps seen from the roots on both sides (both see the line's crossings
 * in the same order), and the region at one gap is one face on both sides
 * (no edge passes there). So each root keeps, per side, the class of
 * each gap, and the plan unites the classes across every side two roots
 * share: a union-find of the roots' border classes only. A root's other
 * classes (closed ones) lie inside it. A class's rank among all classes,
 * by smallest node as §3.11 numbers them, then follows from counts: each
 * root's closed classes, which border classes have their smallest node in
 * it, and how many closed classes come before each of those.
 *
 * Nodes are numbered as hpfc_faces_build numbers them, leaf order being
 * depth-first: a root's nodes are one run, and node x of a root is node
 * node_base[root] + x of the file. Depth-first order also meets the leaves
 * along each side of a root from north to south or from west to east,
 * which is the order of a side's gaps here.
 */

typedef struct gap_list {
    uint64_t *at;
    size_t n, cap;
} gap_list;

/* One root pixel's numbering: its scoped faces and its sides' gaps. */
typedef struct root_pass {
    hpfc_faces fc;
    gap_list side[4]; /* HPFC_WEST .. HPFC_SOUTH: a local node a gap */
    uint32_t i, j;
    hpfc_pixel first;
    uint64_t leaves;
} root_pass;

/* A root numbered ahead of the caller (faces_stream_root). */
typedef struct ahead_slot {
    hpfc_faces *fc;
    int status;
    bool ready;
} ahead_slot;

enum { AHEAD_SLOTS = 8, AHEAD_MAX_THREADS = 4 };

/* The roots numbered in row-major order by threads of their own, each
 * claiming the next root in turn, at most AHEAD_SLOTS ahead of the
 * caller, who writes a root's labels meanwhile: root r waits in slot
 * r % AHEAD_SLOTS. */
typedef struct roots_ahead {
    unsigned wanted, running; /* threads */
    bool stop;
    pthread_t thread[AHEAD_MAX_THREADS];
    pthread_mutex_t lock;
    pthread_cond_t filled, taken;
    uint64_t claimed; /* the roots claimed by the threads so far */
    uint64_t next;    /* the root the caller takes next */
    ahead_slot slot[AHEAD_SLOTS];
} roots_ahead;

struct faces_stream {
    const hpfc_file *file;
    hpfc_walker *w;
    roots_ahead ahead;
    uint32_t cols, rows, sub_cols, sub_rows; /* the root grid; an image's pixels below */
    uint64_t roots;
    uint64_t *node_base;  /* per root, its first node in the file (roots + 1) */
    uint64_t *closed;     /* per root, its closed classes */
    uint64_t *face_base;  /* per root, the rank of its first class (roots + 1) */
    uint64_t *border_at;  /* per root, its first border class (roots + 1) */
    uint64_t *side_at;    /* per root and side, its first gap (4 roots + 1) */
    /* the border classes, each root's in order of their smallest node */
    uint64_t *bx;         /* its smallest node, in its root */
    uint64_t *below;      /* its root's closed classes before bx */
    uint64_t *parent;     /* the union-find across the roots' sides */
    uint64_t *gmin;       /* per united class (at its root): its smallest node in the file */
    uint64_t *grank;      /* per united class: its rank among all classes */
    uint64_t *gaps;       /* per gap, its border class */
    /* once ranked (settle_plan), all the numbering of a root needs per
     * border class: its class's rank, and whether its smallest node is the
     * class's (a bit each); below, parent, gmin, grank, gaps and side_at
     * are freed then */
    uint64_t *krank;
    uint8_t *first;
    uint64_t borders, gap_count;
    size_t border_cap, gap_cap;
    uint64_t outer_x, outer_closed_below; /* the unbounded face's node in root 0 */
    bool outer_border;
    uint64_t outer_rank, count;
};

static int gap_push(gap_list *g, uint64_t node)
{
    int st = array_reserve((void **)&g->at, &g->cap, g->n + 1, sizeof *g->at, 64);
    if (!st)
        g->at[g->n++] = node;
    return st;
}

static void root_pass_free(root_pass *rp)
{
    free(rp->fc.leaves.entry);
    free(rp->fc.parent.narrow);
    free(rp->fc.parent.wide);
    for (int s = 0; s < 4; s++)
        free(rp->side[s].at);
    memset(rp, 0, sizeof *rp);
}

static bool in_root(const hpfc_pixel *px, uint32_t i, uint32_t j)
{
    return px->path[0].i == i && px->path[0].j == j;
}

/* The leaf after px, *more false past the root's last. */
static int next_in_root(const hpfc_file *f, hpfc_pixel *px, uint32_t i, uint32_t j, bool *more)
{
    int st = hpfc_leaf_next(f, px);
    *more = false;
    if (st == HPFC_E_NO_PIXEL)
        return HPFC_OK;
    if (!st)
        *more = in_root(px, i, j);
    return st;
}

/* Pass 1 of a root: its first leaf, its leaves counted (within what the
 * level table leaves), the run of slots they take at each level, and a
 * leaf table over those runs. */
static int root_count(faces_stream *s, root_pass *rp, uint64_t most)
{
    const hpfc_file *f = s->file;
    hpfc_file_info info;
    hpfc_file_get_info(f, &info);
    uint64_t lo[HPFC_MAX_LEVELS], hi[HPFC_MAX_LEVELS];
    for (uint32_t l = 0; l < HPFC_MAX_LEVELS; l++)
        lo[l] = UINT64_MAX, hi[l] = 0;
    hpfc_pixel px;
    int st = hpfc_pixel_root(f, rp->i, rp->j, &px);
    if (!st)
        st = topo_first_leaf_below(f, &px);
    rp->first = px;
    leaf_table *t = &rp->fc.leaves;
    for (bool more = true; !st && more; st = next_in_root(f, &px, rp->i, rp->j, &more)) {
        uint64_t slot;
        if (rp->leaves >= most)
            return HPFC_E_CORRUPT; /* more paths to leaves than leaves */
        if ((st = reader_leaf_slot_bit(f, &px, &slot)))
            return st;
        uint32_t l = px.depth;
        slot -= (uint64_t)f->lv[l].info.pool_offset * 8;
        lo[l] = slot < lo[l] ? slot : lo[l];
        hi[l] = slot > hi[l] ? slot : hi[l];
        rp->leaves++;
    }
    if (st)
        return st;
    uint64_t total = 0;
    for (uint32_t l = 0; l < info.levels; l++) {
        uint64_t entries;
        reader_slot_grid(f, l, &t->unit[l], &entries);
        t->first[l] = total;
        t->pool_bit[l] = (uint64_t)f->lv[l].info.pool_offset * 8;
        if (hi[l] < lo[l])
            continue; /* no leaf of the root at this level */
        t->lo[l] = lo[l];
        uint64_t n = (hi[l] - lo[l]) / t->unit[l] + 1, most = 16 * rp->leaves + 64;
        if (n > most || total + n > most) /* a valid run: fewer than 8 entries a leaf */
            return HPFC_E_CORRUPT;
        total += n;
    }
    t->first[info.levels] = total;
    if (!(t->entry = malloc(total ? (size_t)total * 8 : 1)))
        return HPFC_E_NOMEM;
    memset(t->entry, 0xFF, (size_t)total * 8); /* ENTRY_EMPTY */
    return HPFC_OK;
}

/* Pass 2 of a root: each leaf's entry, its first node (the leaves come in
 * order) and crossing count; the root's node count. */
static int root_parse(faces_stream *s, hpfc_walker *w, root_pass *rp)
{
    hpfc_pixel px = rp->first;
    uint64_t nodes = 0;
    int st = HPFC_OK;
    for (bool more = true; !st && more; st = next_in_root(s->file, &px, rp->i, rp->j, &more)) {
        uint64_t *e = leaf_entry(&rp->fc, &px, &st);
        if (st || (st = topo_parse_pixel(w, &w->p_word, &px)))
            return st;
        uint64_t n = w->p_word.n;
        if (!e || *e != ENTRY_EMPTY)
            return HPFC_E_CORRUPT; /* outside the runs counted, or a second path to a leaf */
        if (n > ENTRY_COUNT_MAX || nodes > ENTRY_BASE_MAX - n - 1)
            return HPFC_E_LIMIT;
        *e = nodes << ENTRY_COUNT_BITS | n;
        nodes += n ? n : 1;
    }
    rp->fc.nodes = nodes;
    return st;
}

/* Leaf p's gaps on the sides of its root it lies on, in the side's order:
 * north to south, west to east; clockwise, roads W and S run the other
 * way. A leaf's first gap on a side is its neighbour's last there (the
 * crossroad between them carries no edge): one gap, its nodes united. */
static int collect_gaps(root_pass *rp, const word_parts *lw, const hpfc_pixel *p, uint64_t base)
{
    for (int road = 0; road < 4; road++) {
        if (!on_root_side(rp->fc.cols, rp->fc.rows, p, road))
            continue;
        gap_list *g = &rp->side[road];
        uint64_t c = lw->n ? lw->road_off[road + 1] - lw->road_off[road] : 0;
        bool reversed = road == HPFC_WEST || road == HPFC_SOUTH;
        for (uint64_t u = 0; u <= c; u++) {
            uint64_t node = gap_node(lw, base, road, reversed ? c - u : u);
            if (u == 0 && g->n) {
                unite(&rp->fc.parent, false, g->at[g->n - 1], node);
                continue;
            }
            int st = gap_push(g, node);
            if (st)
                return st;
        }
    }
    return HPFC_OK;
}

/* Pass 3 of a root: its unions, then every node pointing at its class's
 * smallest node. */
static int root_unite(faces_stream *s, hpfc_walker *w, root_pass *rp)
{
    hpfc_pixel px = rp->first;
    /* narrow words only while the face ids, which pass 2 puts in them, fit too */
    uint64_t narrow_below = s->count < FACES_NARROW_NODES ? FACES_NARROW_NODES : 0;
    int st = node_array_init(&rp->fc.parent, rp->fc.nodes, narrow_below);
    for (bool more = true; !st && more; st = next_in_root(s->file, &px, rp->i, rp->j, &more)) {
        uint64_t base;
        if ((st = node_base(&rp->fc, &px, &base)) || (st = topo_parse_pixel(w, &w->p_word, &px)))
            return st;
        unite_inside(&rp->fc, &w->p_word, base);
        if ((st = unite_across(&rp->fc, w, &px, base)) ||
            (st = unite_empty_roads(&rp->fc, w, &px, base)) ||
            (st = collect_gaps(rp, &w->p_word, &px, base)))
            return st;
    }
    if (st)
        return st;
    node_array *parent = &rp->fc.parent;
    for (uint64_t x = 0; x < rp->fc.nodes; x++)
        node_set(parent, x, find(parent, x));
    for (int road = 0; road < 4; road++)
        for (size_t k = 0; k < rp->side[road].n; k++)
            rp->side[road].at[k] = node_get(parent, rp->side[road].at[k]);
    return HPFC_OK;
}

/* Root (i, j) numbered alone with walker w, within `most` leaves: its
 * classes, each node at its smallest. */
static int root_number(faces_stream *s, hpfc_walker *w, uint32_t i, uint32_t j, uint64_t most,
                       root_pass *rp)
{
    memset(rp, 0, sizeof *rp);
    rp->i = i, rp->j = j;
    rp->fc.file = s->file;
    rp->fc.scoped = true;
    rp->fc.cols = s->sub_cols, rp->fc.rows = s->sub_rows;
    int st = root_count(s, rp, most);
    if (!st)
        st = root_parse(s, w, rp);
    if (!st)
        st = root_unite(s, w, rp);
    return st;
}

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

/* What the plan keeps of a block of roots [r0, r1), made by one task
 * (plan_roots): the border classes and the gaps of its roots in root
 * order, with each root's first class and first gap counted from the
 * block's start; joined into the plan in block order. Each root's node
 * and closed class counts go straight to the plan's slots. */
typedef struct plan_block {
    uint64_t r0, r1;
    uint64_t *bx, *below, *gaps;
    uint64_t borders, gap_count;
    size_t border_cap, gap_cap;
    uint64_t *border_at; /* r1 - r0 + 1 */
    uint64_t *side_at;   /* 4 (r1 - r0) + 1 */
    uint64_t outer_x, outer_closed_below; /* the block of root 0 */
    int status;
} plan_block;

/* The blocks' tasks: the plan, the blocks, and the leaves left to count
 * (every root's walk is bounded by what the roots before it left, as one
 * thread going in root order would bound it). */
typedef struct plan_tasks {
    faces_stream *s;
    plan_block *blocks;
    _Atomic uint64_t leaves_left;
    tasks_failure failure;
} plan_tasks;

/* The border classes of root r: the classes of its sides' gaps, in order
 * of their smallest node, at the end of the block's list. */
static int add_borders(plan_block *b, root_pass *rp, uint64_t r)
{
    size_t n = 0;
    for (int road = 0; road < 4; road++)
        n += rp->side[road].n;
    uint64_t have = b->borders;
    size_t cap = b->border_cap;
    int st = array_reserve((void **)&b->bx, &cap, have + n, sizeof *b->bx, 256); /* bx and below grow alike */
    if (!st && (cap = b->border_cap,
                st = array_reserve((void **)&b->below, &cap, have + n, sizeof *b->below, 256)) == HPFC_OK)
        b->border_cap = cap;
    if (st)
        return st;
    uint64_t *x = b->bx + have;
    n = 0;
    for (int road = 0; road < 4; road++)
        for (size_t k = 0; k < rp->side[road].n; k++)
            x[n++] = rp->side[road].at[k];
    qsort(x, n, sizeof *x, cmp_u64);
    size_t u = 0;
    for (size_t k = 0; k < n; k++)
        if (u == 0 || x[k] != x[u - 1])
            x[u++] = x[k];
    b->borders = have + u;
    b->border_at[r - b->r0 + 1] = b->borders;
    return HPFC_OK;
}

/* The first of bx[lo, hi) (ascending) at least x. */
static uint64_t border_search(const uint64_t *bx, uint64_t lo, uint64_t hi, uint64_t x)
{
    while (lo < hi) {
        uint64_t mid = lo + (hi - lo) / 2;
        if (bx[mid] < x)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

/* Root r's border class of local node x (one of its gaps' classes). */
static uint64_t border_of(const faces_stream *s, uint64_t r, uint64_t x)
{
    return border_search(s->bx, s->border_at[r], s->border_at[r + 1], x);
}

/* Root r's closed classes, and before each border class how many. */
static void count_closed(faces_stream *s, plan_block *b, root_pass *rp, uint64_t r)
{
    uint64_t k = b->border_at[r - b->r0], end = b->border_at[r - b->r0 + 1], closed = 0;
    for (uint64_t x = 0; x < rp->fc.nodes; x++) {
        if (r == 0 && x == b->outer_x)
            b->outer_closed_below = closed;
        if (k < end && b->bx[k] == x) {
            b->below[k++] = closed;
            continue;
        }
        if (node_get(&rp->fc.parent, x) == x)
            closed++;
    }
    s->closed[r] = closed;
}

/* Root r's gaps as the block's border classes, side by side. */
static int add_gaps(plan_block *b, root_pass *rp, uint64_t r)
{
    uint64_t lo = b->border_at[r - b->r0], hi = b->border_at[r - b->r0 + 1];
    for (int road = 0; road < 4; road++) {
        const gap_list *g = &rp->side[road];
        int st = array_reserve((void **)&b->gaps, &b->gap_cap, b->gap_count + g->n, sizeof *b->gaps, 256);
        if (st)
            return st;
        for (size_t k = 0; k < g->n; k++)
            b->gaps[b->gap_count++] = border_search(b->bx, lo, hi, g->at[k]);
        b->side_at[4 * (r - b->r0) + (uint64_t)road + 1] = b->gap_count;
    }
    return HPFC_OK;
}

/* The unbounded face's class in root 0 (its numbering flattened). */
static int find_outer(hpfc_walker *w, plan_block *b, root_pass *rp)
{
    hpfc_pixel corner;
    uint64_t node;
    int st = outer_node(&rp->fc, w, &corner, &node);
    if (!st && !in_root(&corner, 0, 0))
        st = HPFC_E_CORRUPT;
    if (!st)
        b->outer_x = node_get(&rp->fc.parent, node);
    return st;
}

/* Takes `leaves` from what is left to count: HPFC_E_CORRUPT past it (more
 * paths to leaves than leaves). */
static int take_leaves(plan_tasks *pt, uint64_t leaves)
{
    uint64_t left = atomic_load(&pt->leaves_left);
    do {
        if (leaves > left)
            return HPFC_E_CORRUPT;
    } while (!atomic_compare_exchange_weak(&pt->leaves_left, &left, left - leaves));
    return HPFC_OK;
}

/* One root of block b with walker w: numbered alone, what the plan keeps
 * of it added to the block. */
static int plan_root(plan_tasks *pt, hpfc_walker *w, plan_block *b, uint64_t r)
{
    faces_stream *s = pt->s;
    root_pass rp;
    int st = root_number(s, w, (uint32_t)(r % s->cols), (uint32_t)(r / s->cols),
                         atomic_load(&pt->leaves_left), &rp);
    if (!st && r == 0)
        st = find_outer(w, b, &rp);
    if (!st)
        st = take_leaves(pt, rp.leaves);
    if (!st) {
        s->node_base[r + 1] = rp.fc.nodes; /* summed once every block is done */
        st = add_borders(b, &rp, r);
    }
    if (!st) {
        count_closed(s, b, &rp, r);
        st = add_gaps(b, &rp, r);
    }
    root_pass_free(&rp);
    return st;
}

/* Task k: block k's roots in order, with a walker of its own. */
static void plan_block_task(void *ctx, size_t k)
{
    plan_tasks *pt = ctx;
    plan_block *b = &pt->blocks[k];
    hpfc_walker *w = NULL;
    size_t n = (size_t)(b->r1 - b->r0);
    b->border_at = calloc(n + 1, sizeof *b->border_at);
    b->side_at = calloc(4 * n + 1, sizeof *b->side_at);
    int st = b->border_at && b->side_at ? topo_walker_create(pt->s->file, 0, &w) : HPFC_E_NOMEM;
    for (uint64_t r = b->r0; r < b->r1 && !st && !tasks_failed_before(&pt->failure, k); r++)
        st = plan_root(pt, w, b, r);
    hpfc_walker_free(w);
    if ((b->status = st))
        tasks_failure_note(&pt->failure, k);
}

static void plan_block_free(plan_block *b)
{
    free(b->bx), free(b->below), free(b->gaps), free(b->border_at), free(b->side_at);
    memset(b, 0, sizeof *b);
}

/* Block b appended to the plan's lists: its classes and gaps, its roots'
 * first class and first gap counted from the plan's start. */
static int join_block(faces_stream *s, plan_block *b)
{
    size_t cap = s->border_cap;
    int st = array_reserve((void **)&s->bx, &cap, s->borders + b->borders, sizeof *s->bx, 256);
    if (!st && (cap = s->border_cap, st = array_reserve((void **)&s->below, &cap, s->borders + b->borders,
                                                        sizeof *s->below, 256)) == HPFC_OK)
        s->border_cap = cap;
    if (!st)
        st = array_reserve((void **)&s->gaps, &s->gap_cap, s->gap_count + b->gap_count, sizeof *s->gaps, 256);
    if (st)
        return st;
    memcpy(s->bx + s->borders, b->bx, (size_t)b->borders * sizeof *s->bx);
    memcpy(s->below + s->borders, b->below, (size_t)b->borders * sizeof *s->below);
    for (uint64_t g = 0; g < b->gap_count; g++)
        s->gaps[s->gap_count + g] = s->borders + b->gaps[g];
    for (uint64_t r = b->r0; r < b->r1; r++) {
        s->border_at[r + 1] = s->borders + b->border_at[r - b->r0 + 1];
        for (uint64_t road = 1; road <= 4; road++)
            s->side_at[4 * r + road] = s->gap_count + b->side_at[4 * (r - b->r0) + road];
    }
    if (b->r0 == 0)
        s->outer_x = b->outer_x, s->outer_closed_below = b->outer_closed_below;
    s->borders += b->borders;
    s->gap_count += b->gap_count;
    return HPFC_OK;
}

/* Pass 1 over every root, in blocks of roots on up to `threads` threads:
 * what the plan keeps of each, in root order, as one thread would. */
static int plan_roots(faces_stream *s, unsigned threads)
{
    size_t nblocks = threads > 1 ? 8 * (size_t)threads : 1;
    if (nblocks > s->roots)
        nblocks = (size_t)s->roots;
    plan_tasks pt = {.s = s, .blocks = calloc(nblocks, sizeof *pt.blocks)};
    if (!pt.blocks)
        return HPFC_E_NOMEM;
    atomic_init(&pt.leaves_left, file_total_leaves(s->file));
    tasks_failure_init(&pt.failure);
    for (size_t k = 0; k < nblocks; k++) {
        pt.blocks[k].r0 = s->roots * k / nblocks;
        pt.blocks[k].r1 = s->roots * (k + 1) / nblocks;
    }
    tasks_run(threads, nblocks, plan_block_task, &pt);
    size_t failed = tasks_first_failure(&pt.failure);
    int st = failed < nblocks ? pt.blocks[failed].status : HPFC_OK;
    for (size_t k = 0; k < nblocks; k++) {
        if (!st)
            st = join_block(s, &pt.blocks[k]);
        plan_block_free(&pt.blocks[k]);
    }
    free(pt.blocks);
    for (uint64_t r = 0; r < s->roots && !st; r++) {
        if (s->node_base[r + 1] > ENTRY_BASE_MAX - s->node_base[r])
            st = HPFC_E_LIMIT;
        s->node_base[r + 1] += s->node_base[r];
    }
    return st;
}

static uint64_t plan_find(uint64_t *parent, uint64_t x)
{
    for (uint64_t p; (p = parent[x]) != x; x = p)
        parent[x] = parent[p];
    return x;
}

/* Side `a` of root r and side `b` of root q are one line: gap k of one is
 * gap k of the other. */
static int unite_side(faces_stream *s, uint64_t r, int a, uint64_t q, int b)
{
    uint64_t ra = s->side_at[4 * r + (uint64_t)a], na = s->side_at[4 * r + (uint64_t)a + 1] - ra;
    uint64_t qb = s->side_at[4 * q + (uint64_t)b], nb = s->side_at[4 * q + (uint64_t)b + 1] - qb;
    if (na != nb)
        return HPFC_E_CORRUPT; /* the line's crossings differ seen from its two sides */
    for (uint64_t k = 0; k < na; k++) {
        uint64_t x = plan_find(s->parent, s->gaps[ra + k]), y = plan_find(s->parent, s->gaps[qb + k]);
        if (x != y)
            s->parent[x > y ? x : y] = x < y ? x : y;
    }
    return HPFC_OK;
}

static int unite_roots(faces_stream *s)
{
    for (uint64_t x = 0; x < s->borders; x++)
        s->parent[x] = x;
    for (uint64_t r = 0; r < s->roots; r++) {
        uint64_t i = r % s->cols, j = r / s->cols;
        int st = HPFC_OK;
        if (i + 1 < s->cols)
            st = unite_side(s, r, HPFC_EAST, r + 1, HPFC_WEST);
        if (!st && j + 1 < s->rows)
            st = unite_side(s, r, HPFC_SOUTH, r + s->cols, HPFC_NORTH);
        if (st)
            return st;
    }
    return HPFC_OK;
}

/* Is border class k (of root r) the smallest node of its united class? */
static bool first_of_class(const faces_stream *s, uint64_t r, uint64_t k)
{
    return s->node_base[r] + s->bx[k] == s->gmin[plan_find(s->parent, k)];
}

/* The ranks: each united class's smallest node, each root's first rank,
 * each united class's rank, the unbounded face's. */
static void rank_classes(faces_stream *s)
{
    for (uint64_t k = 0; k < s->borders; k++)
        s->gmin[k] = UINT64_MAX;
    for (uint64_t r = 0; r < s->roots; r++)
        for (uint64_t k = s->border_at[r]; k < s->border_at[r + 1]; k++) {
            uint64_t g = plan_find(s->parent, k), at = s->node_base[r] + s->bx[k];
            s->gmin[g] = at < s->gmin[g] ? at : s->gmin[g];
        }
    s->face_base[0] = 0;
    for (uint64_t r = 0; r < s->roots; r++) {
        uint64_t firsts = 0;
        for (uint64_t k = s->border_at[r]; k < s->border_at[r + 1]; k++)
            if (first_of_class(s, r, k))
                s->grank[plan_find(s->parent, k)] = s->face_base[r] + s->below[k] + firsts++;
        s->face_base[r + 1] = s->face_base[r] + s->closed[r] + firsts;
    }
    s->count = s->face_base[s->roots];
    uint64_t k = border_of(s, 0, s->outer_x);
    s->outer_border = k < s->border_at[1] && s->bx[k] == s->outer_x;
    if (s->outer_border) {
        s->outer_rank = s->grank[plan_find(s->parent, k)];
        return;
    }
    uint64_t firsts = 0; /* united classes first in root 0 before the outer node */
    for (k = 0; k < s->border_at[1] && s->bx[k] < s->outer_x; k++)
        firsts += first_of_class(s, 0, k);
    s->outer_rank = s->outer_closed_below + firsts;
}

/* Face id of rank k: the unbounded face 0, the others 1, 2, ... in order. */
static uint64_t face_of_rank(const faces_stream *s, uint64_t k)
{
    return k == s->outer_rank ? 0 : k < s->outer_rank ? k + 1 : k;
}

static int plan_alloc(faces_stream *s)
{
    uint64_t r = s->roots;
    if (r > SIZE_MAX / 64)
        return HPFC_E_NOMEM;
    s->node_base = calloc((size_t)r + 1, sizeof *s->node_base);
    s->closed = calloc((size_t)r, sizeof *s->closed);
    s->face_base = calloc((size_t)r + 1, sizeof *s->face_base);
    s->border_at = calloc((size_t)r + 1, sizeof *s->border_at);
    s->side_at = calloc(4 * (size_t)r + 1, sizeof *s->side_at);
    if (!s->node_base || !s->closed || !s->face_base || !s->border_at || !s->side_at)
        return HPFC_E_NOMEM;
    return HPFC_OK;
}

static void stop_ahead(faces_stream *s);

void faces_stream_free(faces_stream *s)
{
    if (!s)
        return;
    stop_ahead(s);
    hpfc_walker_free(s->w);
    free(s->node_base);
    free(s->closed);
    free(s->face_base);
    free(s->border_at);
    free(s->side_at);
    free(s->bx);
    free(s->below);
    free(s->parent);
    free(s->gmin);
    free(s->grank);
    free(s->gaps);
    free(s->krank);
    free(s->first);
    free(s);
}

/* What the roots' numberings need of the ranked plan, the rest freed:
 * the plan held while the file is written is two words and a bit a border
 * class and a few words a root. */
static int settle_plan(faces_stream *s)
{
    size_t n = s->borders ? (size_t)s->borders : 1;
    if (!(s->krank = malloc(n * sizeof *s->krank)) || !(s->first = calloc((n + 7) / 8, 1)))
        return HPFC_E_NOMEM;
    for (uint64_t r = 0; r < s->roots; r++)
        for (uint64_t k = s->border_at[r]; k < s->border_at[r + 1]; k++) {
            s->krank[k] = s->grank[plan_find(s->parent, k)];
            if (first_of_class(s, r, k))
                s->first[k >> 3] |= (uint8_t)(1u << (k & 7));
        }
    uint64_t *bx = realloc(s->bx, n * sizeof *bx);
    if (bx)
        s->bx = bx;
    free(s->below), free(s->parent), free(s->gmin), free(s->grank), free(s->gaps), free(s->side_at);
    s->below = s->parent = s->gmin = s->grank = s->gaps = s->side_at = NULL;
    s->border_cap = s->borders, s->gap_cap = 0;
    return HPFC_OK;
}

int faces_stream_plan(const hpfc_file *file, unsigned threads, faces_stream **out)
{
    if (!file || !out)
        return HPFC_E_ARG;
    *out = NULL;
    faces_stream *s = calloc(1, sizeof *s);
    if (!s)
        return HPFC_E_NOMEM;
    hpfc_file_info info;
    hpfc_file_get_info(file, &info);
    s->file = file;
    s->cols = info.root_cols, s->rows = info.root_rows;
    s->sub_cols = info.cols, s->sub_rows = info.rows;
    s->roots = (uint64_t)s->cols * s->rows;
    int st = topo_walker_create(file, 0, &s->w);
    if (!st)
        st = plan_alloc(s);
    if (!st)
        st = plan_roots(s, threads ? threads : 1);
    /* the writer's own thread writes LABL meanwhile, which costs less */
    s->ahead.wanted = threads < 2 ? 0 : threads < AHEAD_MAX_THREADS ? threads : AHEAD_MAX_THREADS;
    if (!st && s->node_base[s->roots] > ENTRY_BASE_MAX)
        st = HPFC_E_LIMIT;
    if (!st) {
        size_t n = s->borders ? (size_t)s->borders : 1;
        s->parent = malloc(n * sizeof *s->parent);
        s->gmin = malloc(n * sizeof *s->gmin);
        s->grank = malloc(n * sizeof *s->grank);
        if (!s->parent || !s->gmin || !s->grank)
            st = HPFC_E_NOMEM;
    }
    if (!st)
        st = unite_roots(s);
    if (st) {
        faces_stream_free(s);
        return st;
    }
    rank_classes(s);
    if ((st = settle_plan(s))) {
        faces_stream_free(s);
        return st;
    }
    *out = s;
    return HPFC_OK;
}

uint64_t faces_stream_face_count(const faces_stream *s)
{
    return s ? s->count : 0;
}

uint64_t faces_bytes(const hpfc_faces *fc)
{
    uint64_t entries = 0; /* the last level's end, the largest */
    for (uint32_t l = 0; l <= HPFC_MAX_LEVELS; l++)
        entries = fc->leaves.first[l] > entries ? fc->leaves.first[l] : entries;
    return 8 * entries + (fc->parent.narrow ? 4 : 8) * (fc->nodes + 1);
}

uint64_t faces_stream_plan_bytes(const faces_stream *s)
{
    return 8 * (s->roots * 4 + s->borders * 2) + (s->borders + 7) / 8;
}

/* Pass 2 of root r: its nodes' face ids, in place of their classes. */
static int number_root(const faces_stream *s, root_pass *rp, uint64_t r)
{
    node_array *parent = &rp->fc.parent;
    const uint64_t TAG = node_tag(parent);
    uint64_t k = s->border_at[r], end = s->border_at[r + 1], next = s->face_base[r];
    for (uint64_t x = 0; x < rp->fc.nodes; x++) {
        uint64_t c = node_get(parent, x);
        if (c != x) { /* its class's smallest node, numbered before */
            node_set(parent, x, node_get(parent, c));
            continue;
        }
        uint64_t rank;
        if (k < end && s->bx[k] == x) {
            rank = s->krank[k];
            next += (s->first[k >> 3] >> (k & 7)) & 1;
            k++;
        } else {
            rank = next++;
        }
        node_set(parent, x, TAG | face_of_rank(s, rank));
    }
    if (next != s->face_base[r + 1] || k != end)
        return HPFC_E_CORRUPT; /* not the root the plan saw */
    for (uint64_t x = 0; x < rp->fc.nodes; x++)
        node_set(parent, x, node_get(parent, x) & ~TAG);
    return HPFC_OK;
}

/* Root r numbered again with walker w, into *out. */
static int number_one(faces_stream *s, hpfc_walker *w, uint64_t r, hpfc_faces **out)
{
    root_pass rp;
    int st = root_number(s, w, (uint32_t)(r % s->cols), (uint32_t)(r / s->cols),
                         file_total_leaves(s->file), &rp);
    if (!st && rp.fc.nodes != s->node_base[r + 1] - s->node_base[r])
        st = HPFC_E_CORRUPT;
    if (!st)
        st = number_root(s, &rp, r);
    hpfc_faces *fc = st ? NULL : malloc(sizeof *fc);
    if (!st && !fc)
        st = HPFC_E_NOMEM;
    if (st) {
        root_pass_free(&rp);
        return st;
    }
    *fc = rp.fc;
    fc->count = s->count;
    for (int road = 0; road < 4; road++)
        free(rp.side[road].at);
    *out = fc;
    return HPFC_OK;
}

/* A thread numbering roots ahead, with a walker of its own: the next
 * root not claimed, once its slot is free, until the last or the caller's
 * stop. */
static void *number_ahead(void *arg)
{
    faces_stream *s = arg;
    roots_ahead *a = &s->ahead;
    hpfc_walker *w = NULL;
    int walker_st = topo_walker_create(s->file, 0, &w);
    for (;;) {
        pthread_mutex_lock(&a->lock);
        while (!a->stop && a->claimed < s->roots && a->claimed - a->next >= AHEAD_SLOTS)
            pthread_cond_wait(&a->taken, &a->lock);
        if (a->stop || a->claimed == s->roots) {
            pthread_mutex_unlock(&a->lock);
            break;
        }
        uint64_t r = a->claimed++;
        pthread_mutex_unlock(&a->lock);
        hpfc_faces *fc = NULL;
        int st = walker_st ? walker_st : number_one(s, w, r, &fc);
        pthread_mutex_lock(&a->lock);
        a->slot[r % AHEAD_SLOTS] = (ahead_slot){fc, st, true};
        pthread_cond_broadcast(&a->filled);
        pthread_mutex_unlock(&a->lock);
    }
    hpfc_walker_free(w);
    return NULL;
}

/* The threads started for root 0 (none when none can be: the caller
 * numbers alone). */
static void start_ahead(faces_stream *s)
{
    roots_ahead *a = &s->ahead;
    unsigned want = a->wanted;
    a->wanted = 0; /* once */
    if (pthread_mutex_init(&a->lock, NULL))
        return;
    if (pthread_cond_init(&a->filled, NULL)) {
        pthread_mutex_destroy(&a->lock);
        return;
    }
    if (pthread_cond_init(&a->taken, NULL)) {
        pthread_cond_destroy(&a->filled);
        pthread_mutex_destroy(&a->lock);
        return;
    }
    while (a->running < want && pthread_create(&a->thread[a->running], NULL, number_ahead, s) == 0)
        a->running++;
    if (!a->running) {
        pthread_cond_destroy(&a->taken);
        pthread_cond_destroy(&a->filled);
        pthread_mutex_destroy(&a->lock);
    }
}

/* The threads stopped and joined, the roots they numbered and nobody
 * took freed. */
static void stop_ahead(faces_stream *s)
{
    roots_ahead *a = &s->ahead;
    if (!a->running)
        return;
    pthread_mutex_lock(&a->lock);
    a->stop = true;
    pthread_cond_broadcast(&a->taken);
    pthread_mutex_unlock(&a->lock);
    for (unsigned k = 0; k < a->running; k++)
        pthread_join(a->thread[k], NULL);
    for (int k = 0; k < AHEAD_SLOTS; k++)
        if (a->slot[k].ready)
            hpfc_faces_free(a->slot[k].fc);
    pthread_cond_destroy(&a->filled);
    pthread_cond_destroy(&a->taken);
    pthread_mutex_destroy(&a->lock);
    a->running = 0;
}

/* Root r (the caller's next) from the threads: its numbering or failure
 * in *out and the status returned. */
static int take_ahead(faces_stream *s, uint64_t r, hpfc_faces **out)
{
    roots_ahead *a = &s->ahead;
    ahead_slot *slot = &a->slot[r % AHEAD_SLOTS];
    pthread_mutex_lock(&a->lock);
    while (!slot->ready) /* claimed (the caller's next is within reach), so coming */
        pthread_cond_wait(&a->filled, &a->lock);
    *out = slot->fc;
    int st = slot->status;
    *slot = (ahead_slot){0};
    a->next = r + 1;
    pthread_cond_broadcast(&a->taken);
    pthread_mutex_unlock(&a->lock);
    return st;
}

int faces_stream_root(faces_stream *s, uint32_t i, uint32_t j, hpfc_faces **out)
{
    if (!s || !out || i >= s->cols || j >= s->rows)
        return HPFC_E_ARG;
    *out = NULL;
    uint64_t r = (uint64_t)j * s->cols + i;
    if (r == 0 && s->ahead.wanted)
        start_ahead(s);
    if (s->ahead.running && r == s->ahead.next)
        return take_ahead(s, r, out);
    stop_ahead(s); /* out of their order: alone from here */
    return number_one(s, s->w, r, out);
}
