/*
 * Traversal benchmark (paper Sect. 5.1, Fig. 11): a breadth-first walk over
 * all darts of random Delaunay triangulations (4000 points, 20% of the edges
 * removed), following next and twin, on the hPFC file, on the flat rPFC file
 * of the same graph, and on an explicit half-edge array holding the same
 * map. Reports pixels visited per edge and nanoseconds per operation.
 *
 * Each file is walked by one walker in three ways: without its cache (every
 * operator decodes the words it needs: the paper's "pixels visited"), with
 * an empty cache (cold: the words are decoded and the crossings identified
 * during the walk) and again with the cache a cold walk filled (warm); each
 * way three times, reporting the median. The hPFC file is also walked on
 * keys (hpfc_key_next / hpfc_key_twin; a queue of 64-bit keys, the visited
 * set on keys), by another walker, cold and warm; its parent index, built
 * by the first key it cannot find in its cache, is timed apart (one build,
 * before the walks). A third walker walks keys with the visited set a
 * bitmap of hpfc_key_index_bound bits, by the dart index the _indexed
 * operators return with each result, cold and warm, and warm once more
 * with the queue push behind an if as in the other walks.
 * The memory the walks write (queue, visited set, the cache's arena) is
 * touched before the clock starts, as the half-edge array is.
 */
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "export.h"
#include "gen.h"
#include "hpfc.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* A set of 64-bit keys (open addressing). */
typedef struct key_set {
    uint64_t *keys;
    size_t mask;
} key_set;

static bool set_insert(key_set *s, uint64_t key)
{
    size_t h = (size_t)((key + 1) * 0x9E3779B97F4A7C15ull >> 17) & s->mask;
    while (s->keys[h]) {
        if (s->keys[h] == key + 1)
            return false;
        h = (h + 1) & s->mask;
    }
    s->keys[h] = key + 1;
    return true;
}

static void set_clear(key_set *s)
{
    memset(s->keys, 0, (s->mask + 1) * sizeof *s->keys);
}

/* One timed walk: ns per operator call and words decoded per edge. */
typedef struct timing {
    double ns_per_op, decodes_per_edge;
} timing;

typedef struct file_result {
    timing plain, cold, warm, key_cold, key_warm, bit_cold, bit_warm, bit_if;
    double half;      /* words decoded per edge, each half-edge followed once, no cache */
    double key_alone; /* ns per warm key operator without the walk around it */
    double index_ms;  /* the key walker's parent index, built once */
} file_result;

/* The walk's state: every dart of the file, a queue and a visited set. */
typedef struct bfs {
    const hpfc_file *f;
    hpfc_walker *w;
    hpfc_dart *all, *queue; /* queue: one spare entry for the next result */
    size_t n, nd;
    key_set seen;
    bool on_keys; /* walk keys[] with the key operators */
    bool on_bits; /* ... with the _indexed ones, the visited set a bitmap */
    bool branchy; /* ... the bitmap tested with an if, as the other walks */
    uint64_t *keys, *kqueue, *kindex; /* kindex: keys[]' dart indices */
    uint8_t *bits;
    uint64_t bound; /* of the dart indices: bits of the bitmap */
} bfs;

/* A walk's figures: ns per operator call over `seconds`, and words decoded
 * per edge since the walker had decoded `visited0`. */
static timing walk_timing(const bfs *b, double seconds, size_t ops, uint64_t visited0)
{
    timing r;
    r.ns_per_op = 1e9 * seconds / (double)ops;
    r.decodes_per_edge =
        (double)(hpfc_walker_pixels_visited(b->w) - visited0) / (double)(b->nd / 2);
    return r;
}

/* Breadth-first over darts from every dart in turn, by next and twin. The
 * results are written straight into the queue, which is read in place:
 * an hpfc_dart is large, and copying it is no part of the operators. */
static timing run_bfs(bfs *b)
{
    size_t ops = 0;
    set_clear(&b->seen);
    uint64_t visited0 = hpfc_walker_pixels_visited(b->w);
    double t0 = now();
    for (size_t s = 0; s < b->n; s++) {
        if (!set_insert(&b->seen, hpfc_dart_key(b->f, &b->all[s])))
            continue;
        size_t head = 0, tail = 0;
        b->queue[tail++] = b->all[s];
        while (head < tail) {
            const hpfc_dart *d = &b->queue[head++];
            if (!hpfc_dart_next(b->w, d, &b->queue[tail]) && set_insert(&b->seen, hpfc_dart_key(b->f, &b->queue[tail])))
                tail++;
            if (!hpfc_dart_twin(b->w, d, &b->queue[tail]) && set_insert(&b->seen, hpfc_dart_key(b->f, &b->queue[tail])))
                tail++;
            ops += 2;
        }
    }
    return walk_timing(b, now() - t0, ops, visited0);
}

/* The same walk on keys: 8-byte queue entries, no path anywhere. */
static timing run_key_bfs(bfs *b)
{
    size_t ops = 0;
    set_clear(&b->seen);
    uint64_t visited0 = hpfc_walker_pixels_visited(b->w);
    double t0 = now();
    size_t head = 0, tail = 0; /* one queue for all: it ends holding every dart */
    for (size_t s = 0; s < b->n; s++) {
        if (!set_insert(&b->seen, b->keys[s]))
            continue;
        b->kqueue[tail++] = b->keys[s];
        while (head < tail) {
            uint64_t d = b->kqueue[head++], r;
            if (!hpfc_key_next(b->w, d, &r) && set_insert(&b->seen, r))
                b->kqueue[tail++] = r;
            if (!hpfc_key_twin(b->w, d, &r) && set_insert(&b->seen, r))
                b->kqueue[tail++] = r;
            ops += 2;
        }
    }
    return walk_timing(b, now() - t0, ops, visited0);
}

/* The same walk on keys, visited darts in a bitmap indexed by dart index
 * (hpfc_key_next_indexed / hpfc_key_twin_indexed give it with the result).
 * Without `branchy` each result is written to the queue's tail and the tail
 * moves when its bit was clear: no branch waits on the operator's answer,
 * so a mispredicted one does not throw away the next operators' cache
 * misses in flight (the same change leaves the array walk as fast). */
static timing run_bit_bfs(bfs *b)
{
    size_t ops = 0;
    memset(b->bits, 0, (size_t)(b->bound + 7) / 8);
    uint64_t visited0 = hpfc_walker_pixels_visited(b->w);
    double t0 = now();
    size_t head = 0, tail = 0;
    for (size_t s = 0; s < b->n; s++) {
        uint64_t i = b->kindex[s];
        if (b->bits[i >> 3] >> (i & 7) & 1)
            continue;
        b->bits[i >> 3] |= (uint8_t)(1u << (i & 7));
        b->kqueue[tail++] = b->keys[s];
        while (head < tail) {
            uint64_t d = b->kqueue[head++], r;
            for (int op = 0; op < 2; op++) {
                int st = op ? hpfc_key_twin_indexed(b->w, d, &r, &i)
                            : hpfc_key_next_indexed(b->w, d, &r, &i);
                if (st)
                    continue; /* not on this map's darts */
                unsigned fresh = !(b->bits[i >> 3] >> (i & 7) & 1);
                if (b->branchy) {
                    if (fresh) {
                        b->bits[i >> 3] |= (uint8_t)(1u << (i & 7));
                        b->kqueue[tail++] = r;
                    }
                } else { /* kqueue has a spare entry */
                    b->bits[i >> 3] |= (uint8_t)(1u << (i & 7));
                    b->kqueue[tail] = r;
                    tail += fresh;
                }
            }
            ops += 2;
        }
    }
    return walk_timing(b, now() - t0, ops, visited0);
}

static volatile uint64_t key_sink;

/* The warm key operators alone: the walk's next and twin calls in the
 * walk's order (kqueue holds every dart once, as the last walk left it),
 * without its queue and visited set. Best of RUNS. */
static double key_ops_alone(bfs *b)
{
    double best = 0;
    uint64_t sum = 0;
    for (int r = 0; r < 3; r++) {
        double t0 = now();
        for (size_t k = 0; k < b->nd; k++) {
            uint64_t x = 0, y = 0;
            hpfc_key_next(b->w, b->kqueue[k], &x);
            hpfc_key_twin(b->w, b->kqueue[k], &y);
            sum += x ^ y;
        }
        double ns = 1e9 * (now() - t0) / (double)(2 * b->nd);
        best = r == 0 || ns < best ? ns : best;
    }
    key_sink = sum; /* keeps the calls */
    return best;
}

/* The paper's count (Sect. 5.1: "we traverse all its half-edges"): words
 * decoded per edge when each half-edge is followed once, from its origin to
 * its target, without the cache. The BFS follows each edge four times (next
 * and twin of both darts each walk the edge), so its count is about twice
 * this one. */
static double half_edge_decodes(bfs *b)
{
    hpfc_walker_set_cache_size(b->w, 0);
    uint64_t visited0 = hpfc_walker_pixels_visited(b->w);
    hpfc_dart r;
    for (size_t k = 0; k < b->n; k++)
        hpfc_dart_twin(b->w, &b->all[k], &r);
    return (double)(hpfc_walker_pixels_visited(b->w) - visited0) / (double)(b->nd / 2);
}

/* The darts of every vertex, in leaf order, as keys, and in the path form
 * the path-form walks take (converted by hpfc_dart_from_key); by a walker
 * of its own, so the timed walkers start as they always did. */
static size_t collect(const hpfc_file *f, uint64_t *keys, hpfc_dart *all, size_t nd)
{
    hpfc_walker *w;
    if (hpfc_walker_create(f, &w))
        return 0;
    size_t n = 0;
    hpfc_pixel px;
    for (int st = hpfc_leaf_first(f, &px); !st && n < nd; st = hpfc_leaf_next(f, &px)) {
        uint32_t nv = 0;
        hpfc_pixel_vertex_count(w, &px, &nv);
        for (uint32_t v = 0; v < nv; v++) {
            uint64_t vertex = 0;
            uint32_t deg = 0;
            hpfc_pixel_vertex_key(w, &px, v, &vertex);
            hpfc_key_degree(w, vertex, &deg);
            for (uint32_t k = 0; k < deg && n < nd; k++)
                if (!hpfc_key_vertex_dart(w, vertex, k, &keys[n]) &&
                    !hpfc_dart_from_key(w, keys[n], &all[n]))
                    n++;
        }
    }
    hpfc_walker_free(w);
    return n;
}

/* The median of RUNS walks (the machine's speed drifts): with a cache of
 * `cache` bytes emptied before each when `empty`, else with the cache the
 * walks before left. */
enum { RUNS = 3 };

static int by_time(const void *a, const void *b)
{
    double x = ((const timing *)a)->ns_per_op, y = ((const timing *)b)->ns_per_op;
    return (x > y) - (x < y);
}

static timing median_bfs(bfs *b, size_t cache, bool empty)
{
    timing t[RUNS];
    for (int r = 0; r < RUNS; r++) {
        if (empty)
            hpfc_walker_set_cache_size(b->w, cache);
        t[r] = b->on_bits ? run_bit_bfs(b) : b->on_keys ? run_key_bfs(b) : run_bfs(b);
    }
    qsort(t, RUNS, sizeof *t, by_time);
    return t[RUNS / 2];
}

static file_result walk_file(const hpfc_file *f, size_t nd, bool with_keys)
{
    file_result r = {.index_ms = 0};
    bfs b = {.f = f, .nd = nd};
    if (hpfc_walker_create(f, &b.w))
        return r;
    size_t cap = 16;
    while (cap < 4 * nd + 16)
        cap *= 2;
    b.all = malloc(nd * sizeof *b.all);
    b.queue = malloc((nd + 1) * sizeof *b.queue);
    b.seen = (key_set){malloc(cap * sizeof(uint64_t)), cap - 1};
    b.keys = malloc((nd + 1) * sizeof *b.keys);
    memset(b.queue, 0, (nd + 1) * sizeof *b.queue);
    b.n = collect(f, b.keys, b.all, nd);
    /* a warm-up walk maps the cache's pages; emptying keeps them */
    run_bfs(&b);
    r.cold = median_bfs(&b, HPFC_WALKER_DEFAULT_CACHE, true);
    r.warm = median_bfs(&b, HPFC_WALKER_DEFAULT_CACHE, false);
    r.plain = median_bfs(&b, 0, true);
    r.half = half_edge_decodes(&b);
    hpfc_walker_free(b.w);
    if (with_keys && !hpfc_walker_create(f, &b.w)) {
        b.kqueue = malloc((nd + 1) * sizeof *b.kqueue);
        memset(b.kqueue, 0, (nd + 1) * sizeof *b.kqueue);
        uint64_t out;
        double t0 = now();
        hpfc_key_next(b.w, b.keys[0], &out); /* builds the parent index */
        r.index_ms = 1e3 * (now() - t0);
        b.on_keys = true;
        run_key_bfs(&b);
        r.key_cold = median_bfs(&b, HPFC_WALKER_DEFAULT_CACHE, true);
        r.key_warm = median_bfs(&b, HPFC_WALKER_DEFAULT_CACHE, false);
        r.key_alone = key_ops_alone(&b);
        hpfc_walker_free(b.w);
    }
    /* the bitmap walk: another walker, its index built apart as above */
    uint64_t vbound;
    if (with_keys && !hpfc_walker_create(f, &b.w) &&
        !hpfc_key_index_bound(b.w, &b.bound, &vbound)) {
        b.kindex = malloc((b.n + 1) * sizeof *b.kindex);
        b.bits = malloc((size_t)(b.bound + 7) / 8 + 1);
        for (size_t k = 0; k < b.n; k++)
            hpfc_dart_index(b.w, b.keys[k], &b.kindex[k]);
        b.on_bits = true;
        run_bit_bfs(&b);
        r.bit_cold = median_bfs(&b, HPFC_WALKER_DEFAULT_CACHE, true);
        r.bit_warm = median_bfs(&b, HPFC_WALKER_DEFAULT_CACHE, false);
        b.branchy = true;
        r.bit_if = median_bfs(&b, HPFC_WALKER_DEFAULT_CACHE, false);
        b.on_bits = b.branchy = false;
        free(b.kindex), free(b.bits);
        hpfc_walker_free(b.w);
    }
    free(b.keys), free(b.kqueue);
    free(b.all), free(b.queue), free(b.seen.keys);
    return r;
}

typedef struct array_result {
    double walk_ns, alone_ns;
} array_result;

static volatile uint32_t array_sink;

/* The array's next and twin lookups alone, in the walk's order (queue
 * holds every dart once), as key_ops_alone times the key operators. Best
 * of 3 sets of 100 passes (one pass is too short to time). */
static double array_ops_alone(const exported_map *m, const uint32_t *queue)
{
    double best = 0;
    uint32_t sum = 0;
    for (int r = 0; r < 3; r++) {
        double t0 = now();
        for (int rep = 0; rep < 100; rep++)
            for (size_t k = 0; k < m->nd; k++)
                sum += m->next[queue[k]] ^ m->twin[queue[k]];
        double ns = 1e9 * (now() - t0) / (200.0 * (double)m->nd);
        best = r == 0 || ns < best ? ns : best;
    }
    array_sink = sum;
    return best;
}

/* The same walk on plain arrays next[] and twin[]. */
static array_result walk_array(const exported_map *m)
{
    size_t ops = 0;
    uint8_t *seen = calloc(m->nd, 1);
    uint32_t *queue = calloc(m->nd, sizeof *queue);
    double t0 = now();
    for (int rep = 0; rep < 100; rep++) { /* repeat: one pass is too short to time */
        memset(seen, 0, m->nd);
        for (uint32_t s = 0; s < m->nd; s++) {
            if (seen[s])
                continue;
            seen[s] = 1;
            size_t head = 0, tail = 0;
            queue[tail++] = s;
            while (head < tail) {
                uint32_t d = queue[head++];
                uint32_t a = m->next[d], b = m->twin[d];
                if (!seen[a])
                    seen[a] = 1, queue[tail++] = a;
                if (!seen[b])
                    seen[b] = 1, queue[tail++] = b;
                ops += 2;
            }
        }
    }
    double t1 = now();
    array_result r = {1e9 * (t1 - t0) / (double)ops, 0};
    /* one queue per start: rebuild the whole order for the replay */
    memset(seen, 0, m->nd);
    size_t tail = 0;
    for (uint32_t s = 0; s < m->nd; s++) {
        if (seen[s])
            continue;
        seen[s] = 1;
        size_t head = tail;
        queue[tail++] = s;
        while (head < tail) {
            uint32_t d = queue[head++], a = m->next[d], b = m->twin[d];
            if (!seen[a])
                seen[a] = 1, queue[tail++] = a;
            if (!seen[b])
                seen[b] = 1, queue[tail++] = b;
        }
    }
    r.alone_ns = array_ops_alone(m, queue);
    free(seen), free(queue);
    return r;
}

/* The hPFC files' pool layout: argv[3], paper (default) or compact (A/B). */
static int hpfc_layout = HPFC_LAYOUT_PAPER;

static hpfc_file *pack(const hpfc_graph *g, int flat, uint8_t **buf)
{
    hpfc_build_params p;
    hpfc_build_params_default(&p);
    p.flat = flat;
    p.max_flat_pixels = (uint64_t)1 << 31;
    hpfc_tree *t = NULL;
    hpfc_file *f = NULL;
    size_t size;
    *buf = NULL;
    hpfc_write_options o = {.layout = flat ? HPFC_LAYOUT_PAPER : hpfc_layout};
    if (hpfc_build(g, &p, &t, NULL) || hpfc_tree_serialize(t, &o, buf, &size, NULL) ||
        hpfc_open_memory(*buf, size, 0, &f))
        f = NULL;
    hpfc_tree_free(t);
    return f;
}

int main(int argc, char **argv)
{
    int seeds = argc > 1 ? atoi(argv[1]) : 5;
    int with_flat = argc > 2 ? atoi(argv[2]) : 1;
    if (argc > 3 && strcmp(argv[3], "compact") == 0)
        hpfc_layout = HPFC_LAYOUT_COMPACT;
    printf("pool layout of the hPFC files: %s\n", hpfc_layout == HPFC_LAYOUT_COMPACT ? "compact" : "paper");
    printf("Traversal of all darts (BFS by next and twin), Delaunay 4000 points, 20%% edges removed, (n0, n) = (64, 2)\n");
    printf("px/e: words decoded per edge; half = each half-edge followed once without cache\n"
           "  (the paper's traversal of all half-edges), none = the BFS without cache,\n"
           "  cold = empty cache\n");
    printf("ns/op: per next or twin; warm = the cache the cold walk filled; key = the walk on "
           "64-bit keys\n");
    printf("x = hPFC / array; alone = the warm key operators without the walk's queue and visited "
           "set,\n  against the array's lookups alone (arr1), in the same order\n");
    printf("bit = the walk on keys with a visited bitmap by dart index (the _indexed "
           "operators),\n  its queue push without a branch; if = the same warm with an if, as "
           "the other walks\n");
    printf("idx = the key walker's parent index, built once (ms)\n");
    printf("%-4s %5s | %6s %6s %6s | %7s %7s %7s | %7s %7s %7s | %7s %7s %6s | %7s %7s %6s | "
           "%8s %8s | %6s %6s | %6s %6s %6s %6s %6s %6s %6s %6s | %5s\n",
           "seed", "edges", "hPFC", "", "", "rPFC", "", "", "hPFC", "dart", "", "hPFC", "key", "",
           "hPFC", "bit", "", "rPFC", "", "array", "", "hPFC", "", "", "", "", "", "", "", "idx");
    printf("%-4s %5s | %6s %6s %6s | %7s %7s %7s | %7s %7s %7s | %7s %7s %6s | %7s %7s %6s | "
           "%8s %8s | %6s %6s | %6s %6s %6s %6s %6s %6s %6s %6s | %5s\n",
           "", "", "half", "none", "cold", "half", "none", "cold", "none", "cold", "warm", "cold",
           "warm", "alone", "cold", "warm", "if", "none", "cold", "ns/op", "arr1", "cold", "warm",
           "kcold", "kwarm", "bcold", "bwarm", "bif", "kalone", "ms");
    for (int seed = 1; seed <= seeds; seed++) {
        hpfc_graph *g = NULL;
        if (gen_delaunay((uint64_t)seed, 4000, 1 << 20, 0.2, &g))
            return 1;
        uint8_t *hbuf, *fbuf = NULL;
        hpfc_file *h = pack(g, 0, &hbuf);
        exported_map m;
        if (!h || export_map(h, &m))
            return 1;
        file_result rh = walk_file(h, m.nd, true), rf = {.index_ms = 0};
        array_result ar = walk_array(&m);
        double array_ns = ar.walk_ns;
        hpfc_file *flat = with_flat ? pack(g, 1, &fbuf) : NULL;
        if (flat)
            rf = walk_file(flat, m.nd, false);
        printf("%-4d %5zu | %6.2f %6.2f %6.2f | %7.2f %7.2f %7.2f | %7.1f %7.1f %7.1f | %7.1f "
               "%7.1f %6.1f | "
               "%7.1f %7.1f %6.1f | %8.1f %8.1f | "
               "%6.2f %6.2f | %5.0fx %5.0fx %5.0fx %5.1fx %5.0fx %5.1fx %5.1fx %5.1fx | %5.2f\n",
               seed, m.nd / 2, rh.half, rh.plain.decodes_per_edge, rh.cold.decodes_per_edge,
               rf.half, rf.plain.decodes_per_edge, rf.cold.decodes_per_edge, rh.plain.ns_per_op,
               rh.cold.ns_per_op, rh.warm.ns_per_op, rh.key_cold.ns_per_op, rh.key_warm.ns_per_op,
               rh.key_alone, rh.bit_cold.ns_per_op, rh.bit_warm.ns_per_op, rh.bit_if.ns_per_op,
               rf.plain.ns_per_op, rf.cold.ns_per_op, array_ns, ar.alone_ns,
               rh.cold.ns_per_op / array_ns, rh.warm.ns_per_op / array_ns,
               rh.key_cold.ns_per_op / array_ns, rh.key_warm.ns_per_op / array_ns,
               rh.bit_cold.ns_per_op / array_ns, rh.bit_warm.ns_per_op / array_ns,
               rh.bit_if.ns_per_op / array_ns, rh.key_alone / ar.alone_ns, rh.index_ms);
        exported_map_free(&m);
        hpfc_close(h);
        hpfc_close(flat);
        free(hbuf), free(fbuf);
        hpfc_graph_free(g);
    }
    return 0;
}
