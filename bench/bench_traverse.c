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
 * way three times, reporting the median.
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
    timing plain, cold, warm;
} file_result;

/* The walk's state: every dart of the file, a queue and a visited set. */
typedef struct bfs {
    const hpfc_file *f;
    hpfc_walker *w;
    hpfc_dart *all, *queue; /* queue: one spare entry for the next result */
    size_t n, nd;
    key_set seen;
} bfs;

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
    double t1 = now();
    timing r;
    r.ns_per_op = 1e9 * (t1 - t0) / (double)ops;
    r.decodes_per_edge = (double)(hpfc_walker_pixels_visited(b->w) - visited0) / (double)(b->nd / 2);
    return r;
}

/* The darts of every vertex, in leaf order. */
static size_t collect(const hpfc_file *f, hpfc_walker *w, hpfc_dart *all, size_t nd)
{
    size_t n = 0;
    hpfc_pixel px;
    for (int st = hpfc_leaf_first(f, &px); !st && n < nd; st = hpfc_leaf_next(f, &px)) {
        uint32_t nv = 0;
        hpfc_pixel_vertex_count(w, &px, &nv);
        for (uint32_t v = 0; v < nv; v++) {
            hpfc_vertex vx;
            uint32_t deg = 0;
            hpfc_pixel_vertex(w, &px, v, &vx);
            hpfc_vertex_degree(w, &vx, &deg);
            for (uint32_t k = 0; k < deg && n < nd; k++)
                hpfc_vertex_dart(w, &vx, k, &all[n++]);
        }
    }
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
        t[r] = run_bfs(b);
    }
    qsort(t, RUNS, sizeof *t, by_time);
    return t[RUNS / 2];
}

static file_result walk_file(const hpfc_file *f, size_t nd)
{
    file_result r = {{0, 0}, {0, 0}, {0, 0}};
    bfs b = {.f = f, .nd = nd};
    if (hpfc_walker_create(f, &b.w))
        return r;
    size_t cap = 16;
    while (cap < 4 * nd + 16)
        cap *= 2;
    b.all = malloc(nd * sizeof *b.all);
    b.queue = malloc((nd + 1) * sizeof *b.queue);
    b.seen = (key_set){malloc(cap * sizeof(uint64_t)), cap - 1};
    memset(b.queue, 0, (nd + 1) * sizeof *b.queue);
    b.n = collect(f, b.w, b.all, nd);
    /* a warm-up walk maps the cache's pages; emptying keeps them */
    run_bfs(&b);
    r.cold = median_bfs(&b, HPFC_WALKER_DEFAULT_CACHE, true);
    r.warm = median_bfs(&b, HPFC_WALKER_DEFAULT_CACHE, false);
    r.plain = median_bfs(&b, 0, true);
    free(b.all), free(b.queue), free(b.seen.keys);
    hpfc_walker_free(b.w);
    return r;
}

/* The same walk on plain arrays next[] and twin[]. */
static double walk_array(const exported_map *m)
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
    free(seen), free(queue);
    return 1e9 * (t1 - t0) / (double)ops;
}

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
    if (hpfc_build(g, &p, &t, NULL) || hpfc_tree_serialize(t, NULL, buf, &size, NULL) ||
        hpfc_open_memory(*buf, size, 0, &f))
        f = NULL;
    hpfc_tree_free(t);
    return f;
}

int main(int argc, char **argv)
{
    int seeds = argc > 1 ? atoi(argv[1]) : 5;
    int with_flat = argc > 2 ? atoi(argv[2]) : 1;
    printf("Traversal of all darts (BFS by next and twin), Delaunay 4000 points, 20%% edges removed, (n0, n) = (64, 2)\n");
    printf("px/e: words decoded per edge; none = no cache (the paper's pixels visited), cold = empty cache\n");
    printf("ns/op: per next or twin; warm = the cache the cold walk filled; x = hPFC / array\n");
    printf("%-4s %5s | %6s %6s | %7s %7s | %7s %7s %7s | %8s %8s | %6s | %6s %6s\n", "seed", "edges", "hPFC",
           "", "rPFC", "", "hPFC", "", "", "rPFC", "", "array", "hPFC", "");
    printf("%-4s %5s | %6s %6s | %7s %7s | %7s %7s %7s | %8s %8s | %6s | %6s %6s\n", "", "", "none", "cold",
           "none", "cold", "none", "cold", "warm", "none", "cold", "ns/op", "cold", "warm");
    for (int seed = 1; seed <= seeds; seed++) {
        hpfc_graph *g = NULL;
        if (gen_delaunay((uint64_t)seed, 4000, 1 << 20, 0.2, &g))
            return 1;
        uint8_t *hbuf, *fbuf = NULL;
        hpfc_file *h = pack(g, 0, &hbuf);
        exported_map m;
        if (!h || export_map(h, &m))
            return 1;
        file_result rh = walk_file(h, m.nd), rf = {{0, 0}, {0, 0}, {0, 0}};
        double array_ns = walk_array(&m);
        hpfc_file *flat = with_flat ? pack(g, 1, &fbuf) : NULL;
        if (flat)
            rf = walk_file(flat, m.nd);
        printf("%-4d %5zu | %6.2f %6.2f | %7.2f %7.2f | %7.1f %7.1f %7.1f | %8.1f %8.1f | %6.2f | %5.0fx %5.0fx\n",
               seed, m.nd / 2, rh.plain.decodes_per_edge, rh.cold.decodes_per_edge, rf.plain.decodes_per_edge,
               rf.cold.decodes_per_edge, rh.plain.ns_per_op, rh.cold.ns_per_op, rh.warm.ns_per_op,
               rf.plain.ns_per_op, rf.cold.ns_per_op, array_ns, rh.cold.ns_per_op / array_ns,
               rh.warm.ns_per_op / array_ns);
        exported_map_free(&m);
        hpfc_close(h);
        hpfc_close(flat);
        free(hbuf), free(fbuf);
        hpfc_graph_free(g);
    }
    return 0;
}
