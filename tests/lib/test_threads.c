/* Many readers at once (hpfc.h, "Thread safety, handle by handle"): 8
 * threads share one mapped hpfc_file and one hpfc_faces, each with its own
 * walker and shapes object, and run the same random queries (point and
 * exact location, batches, face traversals, face, feature and window
 * shapes, feature reads) in their own orders. The oracle is the answers
 * of the same queries run first by one thread alone: every thread must
 * give each query the same digest. Built with ThreadSanitizer by
 * tools/run-tests.sh (any report fails the run); in the other builds it
 * checks the answers only.
 *
 * Usage: test_threads [THREADS [QUERIES]] */
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "gen.h"
#include "hpfc.h"
#include "hpfc_batch.h"

#define FEATURES 5
#define BATCH 200

typedef struct shared {
    const hpfc_file *f;
    const hpfc_faces *faces;
    hpfc_file_info info;
    uint64_t face_count;
    size_t queries;
    const uint64_t *want; /* the lone thread's digests; NULL while they are made */
} shared;

typedef struct worker {
    const shared *s;
    unsigned id;
    uint64_t *got;
    size_t mismatches, done;
    int setup;
} worker;

typedef struct digest {
    uint64_t h;
} digest;

static void mix(digest *d, uint64_t v)
{
    d->h = (d->h ^ v) * 1099511628211u;
    d->h ^= d->h >> 29;
}

static uint64_t splitmix(uint64_t *z)
{
    uint64_t r = (*z += 0x9e3779b97f4a7c15u);
    r = (r ^ (r >> 30)) * 0xbf58476d1ce4e5b9u;
    r = (r ^ (r >> 27)) * 0x94d049bb133111ebu;
    return r ^ (r >> 31);
}

/* A point of the domain, or now and then just outside it. */
static void point(const shared *s, uint64_t *z, int64_t *x, int64_t *y)
{
    const hpfc_file_info *in = &s->info;
    *x = in->x0 - in->width / 50 + (int64_t)(splitmix(z) % (uint64_t)(in->width + in->width / 25));
    *y = in->y0 - in->height / 50 +
         (int64_t)(splitmix(z) % (uint64_t)(in->height + in->height / 25));
}

static void mix_polygons(digest *d, int st, const hpfc_polygons *p)
{
    mix(d, (uint64_t)st);
    if (st)
        return;
    mix(d, p->polygon_count), mix(d, p->ring_count), mix(d, p->point_count);
    for (size_t k = 0; k < 2 * p->point_count; k++)
        mix(d, (uint64_t)p->xy[k]);
    for (size_t r = 0; r <= p->ring_count; r++)
        mix(d, p->ring_point[r]);
}

/* Query q's answer, as a digest. Everything it reads is q's own: the
 * random numbers come from q, the scratch from the caller's walker and
 * shapes. */
static uint64_t query(const shared *s, size_t q, hpfc_walker *w, hpfc_shapes *sh)
{
    uint64_t z = 0x5eed0000u + q;
    digest d = {1469598103934665603u};
    int64_t x, y;
    point(s, &z, &x, &y);
    switch (q % 7) {
    case 0: { /* the leaf of a point */
        hpfc_pixel px;
        int st = hpfc_locate(s->f, x, y, &px);
        mix(&d, (uint64_t)st);
        if (!st) {
            mix(&d, px.depth);
            for (uint32_t l = 0; l <= px.depth; l++)
                mix(&d, px.path[l].image), mix(&d, px.path[l].i), mix(&d, px.path[l].j);
        }
        break;
    }
    case 1: { /* exact location */
        hpfc_point_location loc;
        hpfc_id faces[64];
        size_t n = 0;
        int st = hpfc_locate_point(s->f, x, y, &loc, faces, 64, &n);
        mix(&d, (uint64_t)st), mix(&d, n);
        for (size_t k = 0; k < n && k < 64; k++)
            mix(&d, faces[k]);
        if (!st)
            mix(&d, loc.vertex), mix(&d, loc.edge);
        break;
    }
    case 2: { /* a batch, through the shared numbering or the stored labels */
        int64_t bx[BATCH], by[BATCH], face[BATCH], feature[BATCH];
        uint32_t fc[BATCH], nfeat[BATCH];
        uint8_t flags[BATCH], depth[BATCH];
        size_t n = 1 + (size_t)(splitmix(&z) % BATCH);
        for (size_t k = 0; k < n; k++)
            point(s, &z, &bx[k], &by[k]);
        hpfc_locate_out out = {face, fc, feature, nfeat, flags, depth};
        size_t failed = 0;
        int st = hpfc_locate_batch(s->f, q % 2 ? s->faces : NULL, n, bx, by, NULL, &out, &failed);
        mix(&d, (uint64_t)st);
        for (size_t k = 0; k < n; k++)
            mix(&d, (uint64_t)face[k]), mix(&d, fc[k]), mix(&d, (uint64_t)feature[k]),
                mix(&d, nfeat[k]), mix(&d, flags[k]), mix(&d, depth[k]);
        break;
    }
    case 3: { /* around the faces of a leaf's darts */
        hpfc_pixel px;
        int st = hpfc_locate(s->f, x, y, &px);
        mix(&d, (uint64_t)st);
        for (uint32_t c = 0; !st && c < 4; c++) {
            uint64_t start, k;
            int ds = hpfc_pixel_dart_key(w, &px, c, &start);
            mix(&d, (uint64_t)ds);
            if (ds)
                continue;
            k = start;
            size_t steps = 0;
            do {
                ds = hpfc_key_next(w, k, &k);
                mix(&d, k);
            } while (!ds && k != start && ++steps < 100000);
            uint64_t face = 0;
            mix(&d, (uint64_t)ds), mix(&d, steps);
            mix(&d, (uint64_t)hpfc_faces_key_face(s->faces, w, start, &face)), mix(&d, face);
        }
        break;
    }
    case 4: { /* a face's shape */
        hpfc_polygons p;
        hpfc_id face = splitmix(&z) % (s->face_count + 1); /* one past: HPFC_E_ARG */
        mix_polygons(&d, hpfc_shapes_face_polygons(sh, face, &p), &p);
        break;
    }
    case 5: { /* a feature's shape, or the features in a window */
        if (q % 2) {
            hpfc_polygons p;
            mix_polygons(&d, hpfc_shapes_feature_polygons(sh, splitmix(&z) % FEATURES, &p), &p);
        } else {
            int64_t x1, y1;
            point(s, &z, &x1, &y1);
            hpfc_window_hits hits;
            int st = hpfc_shapes_window(sh, x < x1 ? x : x1, y < y1 ? y : y1, x < x1 ? x1 : x,
                                        y < y1 ? y1 : y, HPFC_WINDOW_FACES | HPFC_WINDOW_FEATURES,
                                        &hits);
            mix(&d, (uint64_t)st);
            if (!st) {
                mix(&d, hits.face_count), mix(&d, hits.feature_count);
                for (size_t k = 0; k < hits.face_count; k++)
                    mix(&d, hits.face[k]), mix(&d, hits.face_inside[k]);
                for (size_t k = 0; k < hits.feature_count; k++)
                    mix(&d, hits.feature[k]);
            }
        }
        break;
    }
    default: { /* feature reads */
        hpfc_id face = splitmix(&z) % s->face_count, id = 0;
        uint32_t n = 0;
        int st = hpfc_face_feature_count(s->f, face, &n);
        mix(&d, (uint64_t)st), mix(&d, n);
        for (uint32_t k = 0; !st && k < n; k++)
            mix(&d, (uint64_t)hpfc_face_feature_id(s->f, face, k, &id)), mix(&d, id);
        hpfc_feature ft;
        st = hpfc_file_get_feature(s->f, splitmix(&z) % (FEATURES + 1), &ft);
        mix(&d, (uint64_t)st);
        if (!st) {
            mix(&d, (uint64_t)ft.fid), mix(&d, ft.layer), mix(&d, ft.key_len);
            for (size_t k = 0; ft.key && k < ft.key_len; k++)
                mix(&d, (unsigned char)ft.key[k]);
        }
        break;
    }
    }
    return d.h;
}

static void *run(void *arg)
{
    worker *wk = arg;
    const shared *s = wk->s;
    hpfc_walker *w = NULL;
    hpfc_shapes *sh = NULL;
    if (hpfc_walker_create(s->f, &w) || hpfc_shapes_create(s->f, &sh)) {
        wk->setup = 1;
        hpfc_walker_free(w);
        return NULL;
    }
    /* every query once, in this thread's own order */
    size_t *order = malloc(s->queries * sizeof *order);
    uint64_t z = wk->id * 7919u + 1;
    for (size_t k = 0; order && k < s->queries; k++) {
        size_t j = (size_t)(splitmix(&z) % (k + 1));
        order[k] = order[j];
        order[j] = k;
    }
    for (size_t k = 0; order && k < s->queries; k++) {
        size_t q = order[k];
        uint64_t h = query(s, q, w, sh);
        if (s->want && h != s->want[q])
            wk->mismatches++;
        if (wk->got)
            wk->got[q] = h;
        wk->done++;
    }
    wk->setup |= !order;
    free(order);
    hpfc_shapes_free(sh);
    hpfc_walker_free(w);
    return NULL;
}

/* A map with exact geometry, labels and features, written to a file that
 * the threads share mapped (as a program opens one). */
static int make_file(const char *path)
{
    hpfc_graph *g = NULL;
    hpfc_tree *t = NULL;
    hpfc_file *f = NULL;
    hpfc_faces *faces = NULL;
    uint8_t *bytes = NULL;
    size_t size = 0;
    if (gen_delaunay(33, 1500, 200000, 0.3, &g))
        return 1;
    hpfc_build_params p;
    hpfc_build_params_default(&p);
    hpfc_write_options o = {.face_labels = 1, .geometry = g};
    int st = hpfc_build(g, &p, &t, NULL);
    if (!st)
        st = hpfc_tree_serialize(t, &o, &bytes, &size, NULL);
    if (!st)
        st = hpfc_open_memory(bytes, size, 0, &f);
    if (!st)
        st = hpfc_faces_build(f, &faces);
    if (!st) { /* face k > 0 is feature k % FEATURES's, face 0 (outside) none */
        uint32_t n = (uint32_t)hpfc_faces_face_count(faces);
        uint32_t *start = calloc((size_t)n + 1, sizeof *start);
        uint32_t *link = calloc((size_t)n + 1, sizeof *link);
        static const int64_t fid[FEATURES] = {10, 11, 12, 13, 14};
        static const uint32_t layer[FEATURES] = {0, 0, 0, 1, 1};
        static const char *const key[FEATURES] = {"a", "b", NULL, "d", "\xc3\xa9"};
        static const char *const layers[2] = {"one", "two"};
        for (uint32_t k = 0; start && link && k < n; k++) {
            start[k + 1] = start[k] + (k > 0);
            if (k > 0)
                link[start[k]] = k % FEATURES;
        }
        hpfc_feature_table ft = {.feature_count = FEATURES, .fid = fid, .layer = layer,
                                 .key_field = "name", .key = key, .layer_count = 2,
                                 .layer_name = layers, .face_count = n, .face_start = start,
                                 .face_feature = link};
        hpfc_write_options o2 = {.face_labels = 1, .geometry = g, .features = &ft};
        st = start && link ? hpfc_file_write_file(f, &o2, path, NULL) : HPFC_E_NOMEM;
        free(start);
        free(link);
    }
    hpfc_faces_free(faces);
    hpfc_close(f);
    hpfc_free(bytes);
    hpfc_tree_free(t);
    hpfc_graph_free(g);
    return st;
}

int main(int argc, char **argv)
{
    unsigned threads = argc > 1 ? (unsigned)atoi(argv[1]) : 8;
    size_t queries = argc > 2 ? (size_t)atol(argv[2]) : 700;
    if (threads < 1 || threads > 64 || queries < 1)
        return 2;
    char path[] = "/tmp/hpfc-threads.XXXXXX";
    int fd = mkstemp(path);
    CHECK(fd >= 0);
    if (fd < 0)
        return check_report("threads");
    close(fd);
    CHECK_EQ_INT(make_file(path), HPFC_OK);
    hpfc_file *f = NULL;
    hpfc_faces *faces = NULL;
    CHECK_EQ_INT(hpfc_open(path, 0, &f), HPFC_OK);
    unlink(path); /* the mapping keeps the bytes */
    if (!f)
        return check_report("threads");
    CHECK_EQ_INT(hpfc_faces_build(f, &faces), HPFC_OK);
    shared s = {.f = f, .faces = faces, .queries = queries};
    hpfc_file_get_info(f, &s.info);
    s.face_count = hpfc_faces_face_count(faces);

    /* the oracle: one thread alone */
    uint64_t *want = malloc(queries * sizeof *want);
    worker lone = {.s = &s, .id = 0, .got = want};
    CHECK(want != NULL);
    if (!want)
        return check_report("threads");
    run(&lone);
    CHECK(!lone.setup && lone.done == queries);
    s.want = want;

    pthread_t tid[64];
    worker wk[64];
    for (unsigned k = 0; k < threads; k++) {
        wk[k] = (worker){.s = &s, .id = k + 1};
        CHECK_EQ_INT(pthread_create(&tid[k], NULL, run, &wk[k]), 0);
    }
    size_t mismatches = 0;
    for (unsigned k = 0; k < threads; k++) {
        pthread_join(tid[k], NULL);
        CHECK(!wk[k].setup);
        CHECK(wk[k].done == queries);
        mismatches += wk[k].mismatches;
    }
    CHECK_EQ_INT(mismatches, 0);
    printf("%u threads x %zu queries on one file (%llu faces): %zu answers differ from one "
           "thread's\n",
           threads, queries, (unsigned long long)s.face_count, mismatches);
    free(want);
    hpfc_faces_free(faces);
    hpfc_close(f);
    return check_report("threads");
}
