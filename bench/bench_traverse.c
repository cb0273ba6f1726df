/*
 * Traversal benchmark (paper Sect. 5.1, Fig. 11): a breadth-first walk over
 * all darts of random Delaunay triangulations (4000 points, 20% of the edges
 * removed), following next and twin, on the hPFC file, on the flat rPFC file
 * of the same graph, and on an explicit half-edge array holding the same
 * map. Reports pixels visited per edge and nanoseconds per operation.
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

typedef struct result {
    double ns_per_op, pixels_per_edge;
    size_t ops;
} result;

/* Breadth-first over darts from every dart in turn, by next and twin. */
static result walk_file(const hpfc_file *f, size_t nd)
{
    result r = {0};
    hpfc_walker *w;
    if (hpfc_walker_create(f, &w))
        return r;
    hpfc_dart *all = malloc(nd * sizeof *all), *queue = malloc(nd * sizeof *queue);
    key_set seen = {calloc(4 * nd + 16, sizeof(uint64_t)), 0};
    size_t cap = 16;
    while (cap < 4 * nd + 16)
        cap *= 2;
    seen.keys = realloc(seen.keys, cap * sizeof(uint64_t));
    memset(seen.keys, 0, cap * sizeof(uint64_t));
    seen.mask = cap - 1;
    /* the darts themselves, to start from each component */
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
    uint64_t visited0 = hpfc_walker_pixels_visited(w);
    double t0 = now();
    for (size_t s = 0; s < n; s++) {
        if (!set_insert(&seen, hpfc_dart_key(f, &all[s])))
            continue;
        size_t head = 0, tail = 0;
        queue[tail++] = all[s];
        while (head < tail) {
            hpfc_dart d = queue[head++], x;
            if (!hpfc_dart_next(w, &d, &x) && set_insert(&seen, hpfc_dart_key(f, &x)))
                queue[tail++] = x;
            if (!hpfc_dart_twin(w, &d, &x) && set_insert(&seen, hpfc_dart_key(f, &x)))
                queue[tail++] = x;
            r.ops += 2;
        }
    }
    double t1 = now();
    r.ns_per_op = 1e9 * (t1 - t0) / (double)r.ops;
    r.pixels_per_edge = (double)(hpfc_walker_pixels_visited(w) - visited0) / (double)(nd / 2);
    free(all), free(queue), free(seen.keys);
    hpfc_walker_free(w);
    return r;
}

/* The same walk on plain arrays next[] and twin[]. */
static result walk_array(const exported_map *m)
{
    result r = {0};
    uint8_t *seen = calloc(m->nd, 1);
    uint32_t *queue = malloc(m->nd * sizeof *queue);
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
                r.ops += 2;
            }
        }
    }
    double t1 = now();
    r.ns_per_op = 1e9 * (t1 - t0) / (double)r.ops;
    free(seen), free(queue);
    return r;
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
    printf("%-5s %7s | %10s %9s | %10s %9s | %9s | %s\n", "seed", "edges", "hPFC px/e", "ns/op",
           "rPFC px/e", "ns/op", "array ns", "hPFC/array");
    for (int seed = 1; seed <= seeds; seed++) {
        hpfc_graph *g = NULL;
        if (gen_delaunay((uint64_t)seed, 4000, 1 << 20, 0.2, &g))
            return 1;
        uint8_t *hbuf, *fbuf = NULL;
        hpfc_file *h = pack(g, 0, &hbuf);
        exported_map m;
        if (!h || export_map(h, &m))
            return 1;
        result rh = walk_file(h, m.nd), ra = walk_array(&m), rf = {0};
        hpfc_file *flat = with_flat ? pack(g, 1, &fbuf) : NULL;
        if (flat)
            rf = walk_file(flat, m.nd);
        printf("%-5d %7zu | %10.2f %9.1f | %10.2f %9.1f | %9.2f | %.0fx\n", seed, m.nd / 2, rh.pixels_per_edge,
               rh.ns_per_op, rf.pixels_per_edge, rf.ns_per_op, ra.ns_per_op, rh.ns_per_op / ra.ns_per_op);
        exported_map_free(&m);
        hpfc_close(h);
        hpfc_close(flat);
        free(hbuf), free(fbuf);
        hpfc_graph_free(g);
    }
    return 0;
}
