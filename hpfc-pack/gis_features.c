/*
 * Source features of a GIS pack and the faces they cover (gis_features.h).
 */
#include "gis_features.h"

#include <pthread.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "clock.h"
#include "face_check.h"
#include "face_link.h"
#include "grow.h"

struct gis_features {
    char *key_field;
    char **layer_name;
    uint32_t layers;
    /* features */
    int64_t *fid, *source_fid;
    uint32_t *layer;
    char **key;
    uint32_t n, cap;
    /* parts: part r is code[ring_start[r] .. ring_start[r + 1]) (ring code),
       a ring of its feature's area when ring_closed[r] */
    uint32_t *ring_feature;
    uint8_t *ring_closed;
    size_t *ring_start;
    size_t rings, cap_rings, cap_ring_start, cap_closed;
    uint8_t *code;
    size_t code_len, cap_code;
};

static char *dup_or_null(const char *s)
{
    return s ? strdup(s) : NULL;
}

gis_features *gis_features_create(const char *key_field)
{
    gis_features *fs = calloc(1, sizeof *fs);
    if (fs && key_field && !(fs->key_field = strdup(key_field))) {
        free(fs);
        return NULL;
    }
    if (fs && !(fs->ring_start = calloc(1, sizeof *fs->ring_start))) {
        free(fs->key_field);
        free(fs);
        return NULL;
    }
    if (fs)
        fs->cap_ring_start = 1; /* ring_start holds rings + 1 entries */
    return fs;
}

void gis_features_free(gis_features *fs)
{
    if (!fs)
        return;
    for (uint32_t l = 0; l < fs->layers; l++)
        free(fs->layer_name[l]);
    for (uint32_t k = 0; k < fs->n; k++)
        free(fs->key[k]);
    free(fs->layer_name);
    free(fs->key_field);
    free(fs->fid);
    free(fs->source_fid);
    free(fs->layer);
    free(fs->ring_closed);
    free(fs->key);
    free(fs->ring_feature);
    free(fs->ring_start);
    free(fs->code);
    free(fs);
}

int gis_features_set_layer(gis_features *fs, uint32_t index, const char *name)
{
    if (index >= fs->layers) {
        char **p = realloc(fs->layer_name, ((size_t)index + 1) * sizeof *p);
        if (!p)
            return -1;
        for (uint32_t l = fs->layers; l <= index; l++)
            p[l] = NULL;
        fs->layer_name = p;
        fs->layers = index + 1;
    }
    free(fs->layer_name[index]);
    fs->layer_name[index] = strdup(name ? name : "");
    return fs->layer_name[index] ? 0 : -1;
}

int gis_features_add(gis_features *fs, int64_t fid, int64_t source_fid, uint32_t layer,
                     const char *key)
{
    if (fs->n >= UINT32_MAX / 2)
        return -1;
    if (fs->n == fs->cap) {
        uint32_t c = fs->cap ? 2 * fs->cap : 64;
        int64_t *f = realloc(fs->fid, c * sizeof *f);
        if (f)
            fs->fid = f;
        int64_t *sf = realloc(fs->source_fid, c * sizeof *sf);
        if (sf)
            fs->source_fid = sf;
        uint32_t *l = realloc(fs->layer, c * sizeof *l);
        if (l)
            fs->layer = l;
        char **k = realloc(fs->key, c * sizeof *k);
        if (k)
            fs->key = k;
        if (!f || !sf || !l || !k)
            return -1;
        fs->cap = c;
    }
    char *copy = dup_or_null(key);
    if (key && !copy)
        return -1;
    fs->fid[fs->n] = fid;
    fs->source_fid[fs->n] = source_fid;
    fs->layer[fs->n] = layer;
    fs->key[fs->n] = copy;
    fs->n++;
    return 0;
}

uint32_t gis_features_count(const gis_features *fs)
{
    return fs ? fs->n : 0;
}

int64_t gis_features_source_fid(const gis_features *fs, uint32_t k)
{
    return fs->source_fid[k];
}

/* Ring code: the point count, then each point's x and y as the difference
 * from the point before (the first from 0), zigzag LEB128 varints. Shape
 * points of a ring lie close together, so a point takes 2 to 6 bytes
 * instead of 16: the rings of a continental layer are held from reading
 * until the faces are linked, across the build's peak. Differences wrap
 * modulo 2^64, so every int64 ring decodes exactly. */
enum { VARINT_MAX_BYTES = 10 };

static uint8_t *put_varint(uint8_t *p, uint64_t v)
{
    for (; v >= 0x80; v >>= 7)
        *p++ = (uint8_t)(v | 0x80);
    *p++ = (uint8_t)v;
    return p;
}

static const uint8_t *get_varint(const uint8_t *p, uint64_t *v)
{
    uint64_t x = 0;
    for (int shift = 0;; shift += 7) {
        uint8_t b = *p++;
        x |= (uint64_t)(b & 0x7f) << shift;
        if (!(b & 0x80))
            break;
    }
    *v = x;
    return p;
}

static uint64_t zigzag(uint64_t delta)
{
    return delta << 1 ^ (uint64_t) - (int64_t)(delta >> 63);
}

static uint64_t unzigzag(uint64_t z)
{
    return z >> 1 ^ (uint64_t) - (int64_t)(z & 1);
}

typedef gis_part_cursor ring_cursor;

static ring_cursor ring_open(const gis_features *fs, size_t r)
{
    uint64_t n;
    ring_cursor c = {get_varint(fs->code + fs->ring_start[r], &n), 0, 0, 0};
    c.left = (size_t)n;
    return c;
}

size_t gis_features_part_count(const gis_features *fs)
{
    return fs->rings;
}

gis_part_cursor gis_features_part_open(const gis_features *fs, size_t r, uint32_t *feature,
                                       int *ring)
{
    *feature = fs->ring_feature[r];
    *ring = fs->ring_closed[r];
    return ring_open(fs, r);
}

#define ring_next gis_part_next

void gis_part_next(ring_cursor *c, int64_t *x, int64_t *y)
{
    uint64_t dx, dy;
    c->p = get_varint(get_varint(c->p, &dx), &dy);
    c->x += unzigzag(dx), c->y += unzigzag(dy);
    c->left--;
    *x = (int64_t)c->x, *y = (int64_t)c->y;
}

int gis_features_add_part(gis_features *fs, uint32_t feature, int ring, const int64_t *xy,
                          size_t n)
{
    if (n < (ring ? 3u : 2u))
        return 0; /* no area, no segment */
    if (n > (SIZE_MAX - fs->code_len) / (2 * VARINT_MAX_BYTES) - 1 ||
        !array_grow((void **)&fs->ring_feature, &fs->cap_rings, fs->rings + 1,
                    sizeof *fs->ring_feature) ||
        !array_grow((void **)&fs->ring_closed, &fs->cap_closed, fs->rings + 1,
                    sizeof *fs->ring_closed) ||
        !array_grow((void **)&fs->ring_start, &fs->cap_ring_start, fs->rings + 2,
                    sizeof *fs->ring_start) ||
        !array_grow((void **)&fs->code, &fs->cap_code,
                    fs->code_len + (n + 1) * 2 * VARINT_MAX_BYTES, 1))
        return -1;
    uint8_t *p = put_varint(fs->code + fs->code_len, n);
    uint64_t px = 0, py = 0;
    for (size_t i = 0; i < n; i++) {
        uint64_t x = (uint64_t)xy[2 * i], y = (uint64_t)xy[2 * i + 1];
        p = put_varint(put_varint(p, zigzag(x - px)), zigzag(y - py));
        px = x, py = y;
    }
    fs->code_len = (size_t)(p - fs->code);
    fs->ring_feature[fs->rings] = feature;
    fs->ring_closed[fs->rings] = ring != 0;
    fs->ring_start[++fs->rings] = fs->code_len;
    return 0;
}

size_t gis_features_part_points(const gis_features *fs, size_t r)
{
    return ring_open(fs, r).left;
}

uint32_t gis_features_part_feature(const gis_features *fs, size_t r)
{
    return fs->ring_feature[r];
}

void gis_feature_table_free(gis_feature_table *t)
{
    free(t->face_start);
    free(t->face_feature);
    free(t->edge_start);
    free(t->edge_feature);
    memset(t, 0, sizeof *t);
}

/* Every face's features, the exact answer of face_check.h at its witness,
 * into the table's face index; each compared with the walk's where the
 * walk reached the face (without `walked`, no face is compared).
 *
 * The faces are checked in runs, 16 a thread and of at least CHECK_RUN_MIN
 * faces, taken in order by up to `threads` threads that share the check
 * (each with its own scratch):
 * a run's sets and counts go to arrays of its own, joined in run order
 * afterwards, so the table, the counts and a failure are the one thread's. */
#ifdef FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION
#define CHECK_RUN_MIN 3 /* fuzzed maps are small: many runs even so */
#else
#define CHECK_RUN_MIN 64
#endif
enum { CHECK_MAX_THREADS = 64 };

typedef struct check_run {
    uint32_t *feature;  /* the run's faces' sets, one after the other */
    size_t n, cap;
    uint32_t *len;      /* per face of the run, its set's length (up to a failure) */
    uint64_t faces_done, without_witness, anchors, conflicts;
    int status;
} check_run;

typedef struct face_checking {
    const face_witness *w;
    const face_link *fl;
    int walked;
    face_check *fc;
    check_run *run;
    size_t nruns, run_faces;
    size_t next_run;     /* the next run to take (atomic) */
    size_t first_failed; /* the first run known to have failed: later ones stop (atomic) */
} face_checking;

/* Face f's features into *set, counted in the run. */
static int check_face(face_checking *c, uint64_t f, face_check_scratch *s, feature_list *set,
                      check_run *r)
{
    const face_link *fl = c->fl;
    const uint32_t *walk = fl->pool + fl->set_off[f];
    int reached = c->walked && fl->reached[f];
    if (c->w[f].kind == FACE_WITNESS_NONE) {
        /* no place of the file lies in this face: the walk's answer stands */
        r->without_witness++;
        set->n = 0;
        if (reached && !array_grow((void **)&set->v, &set->cap, fl->set_len[f] + 1, sizeof *set->v))
            return HPFC_E_NOMEM;
        if (reached) {
            memcpy(set->v, walk, fl->set_len[f] * sizeof *walk);
            set->n = fl->set_len[f];
        }
        return HPFC_OK;
    }
    int st = face_check_features(c->fc, s, &c->w[f], set);
    if (!st && !reached)
        r->anchors++;
    else if (!st && (set->n != fl->set_len[f] || memcmp(set->v, walk, set->n * sizeof *walk) != 0))
        r->conflicts++;
    return st;
}

static int check_run_faces(face_checking *c, size_t k, face_check_scratch *s, feature_list *set)
{
    check_run *r = &c->run[k];
    uint64_t first = (uint64_t)k * c->run_faces, end = first + c->run_faces;
    end = end < c->fl->faces ? end : c->fl->faces;
    if (!(r->len = malloc((size_t)(end - first) * sizeof *r->len)))
        return HPFC_E_NOMEM;
    for (uint64_t f = first; f < end; f++) {
        int st = check_face(c, f, s, set, r);
        if (st)
            return st;
        if (!array_grow((void **)&r->feature, &r->cap, r->n + set->n + 1, sizeof *r->feature))
            return HPFC_E_NOMEM;
        memcpy(r->feature + r->n, set->v, set->n * sizeof *set->v);
        r->n += set->n;
        r->len[f - first] = (uint32_t)set->n;
        r->faces_done++;
    }
    return HPFC_OK;
}

static void *check_runs(void *arg)
{
    face_checking *c = arg;
    face_check_scratch s = {0};
    feature_list set = {0};
    for (;;) {
        size_t k = __atomic_fetch_add(&c->next_run, 1, __ATOMIC_RELAXED);
        if (k >= c->nruns || __atomic_load_n(&c->first_failed, __ATOMIC_RELAXED) < k)
            break; /* runs are taken in order: all later ones stop too */
        if ((c->run[k].status = check_run_faces(c, k, &s, &set)) != HPFC_OK) {
            size_t seen = __atomic_load_n(&c->first_failed, __ATOMIC_RELAXED);
            while (k < seen && !__atomic_compare_exchange_n(&c->first_failed, &seen, k, false,
                                                            __ATOMIC_RELAXED, __ATOMIC_RELAXED))
                ;
        }
    }
    free(set.v);
    face_check_scratch_free(&s);
    return NULL;
}

/* The runs' sets and counts, in run order, into the table. */
static int join_runs(const face_checking *c, gis_feature_table *out)
{
    size_t total = 0;
    for (size_t k = 0; k < c->nruns; k++) {
        const check_run *r = &c->run[k];
        if (total + r->n >= UINT32_MAX)
            return HPFC_E_LIMIT; /* at a face before any failure of the run */
        if (r->status)
            return r->status;
        total += r->n;
    }
    if (!(out->face_feature = malloc((total ? total : 1) * sizeof *out->face_feature)))
        return HPFC_E_NOMEM;
    size_t at = 0;
    for (size_t k = 0; k < c->nruns; k++) {
        const check_run *r = &c->run[k];
        uint64_t first = (uint64_t)k * c->run_faces;
        for (uint64_t i = 0; i < r->faces_done; i++) {
            out->face_start[first + i] = (uint32_t)at;
            at += r->len[i];
        }
        if (r->n)
            memcpy(out->face_feature + out->face_start[first], r->feature, r->n * sizeof *r->feature);
        out->faces_without_witness += r->without_witness;
        out->anchors += r->anchors;
        out->conflicts += r->conflicts;
    }
    out->face_start[c->fl->faces] = (uint32_t)at;
    return HPFC_OK;
}

static int check_faces(const gis_features *fs, const face_witness *w, const face_link *fl,
                       int walked, unsigned threads, gis_feature_table *out)
{
    face_checking c = {.w = w, .fl = fl, .walked = walked};
    threads = threads < 1 ? 1 : threads > CHECK_MAX_THREADS ? CHECK_MAX_THREADS : threads;
    c.run_faces = (size_t)((fl->faces + 16 * threads - 1) / (16 * threads));
    c.run_faces = c.run_faces < CHECK_RUN_MIN ? CHECK_RUN_MIN : c.run_faces;
    c.nruns = (size_t)((fl->faces + c.run_faces - 1) / c.run_faces);
    out->face_start = calloc(fl->faces + 1, sizeof *out->face_start);
    c.run = calloc(c.nruns ? c.nruns : 1, sizeof *c.run);
    int st = out->face_start && c.run ? face_check_create(fs, &c.fc) : HPFC_E_NOMEM;
    if (!st) {
        c.first_failed = SIZE_MAX;
        pthread_t id[CHECK_MAX_THREADS];
        unsigned started = 0;
        while (started + 1 < threads && started + 1 < c.nruns &&
               pthread_create(&id[started], NULL, check_runs, &c) == 0)
            started++;
        check_runs(&c);
        for (unsigned k = 0; k < started; k++)
            pthread_join(id[k], NULL);
        st = join_runs(&c, out);
    }
    for (size_t k = 0; c.run && k < c.nruns; k++) {
        free(c.run[k].feature);
        free(c.run[k].len);
    }
    free(c.run);
    face_check_free(c.fc);
    return st;
}

/* The table from the checked face index, and the edges' features. */
static void make_table(const gis_features *fs, face_link *fl, gis_feature_table *out)
{
    uint32_t last = UINT32_MAX; /* parts come in feature order */
    for (size_t r = 0; r < fs->rings; r++)
        if (fs->ring_closed[r] && fs->ring_feature[r] != last) {
            out->polygon_features++;
            last = fs->ring_feature[r];
        }
    out->edge_count = fl->edges;
    out->edge_start = fl->edge_start, fl->edge_start = NULL;
    out->edge_feature = fl->edge_feature, fl->edge_feature = NULL;
    out->table = (hpfc_feature_table){
        .feature_count = fs->n, .fid = fs->fid, .layer = fs->layer, .key_field = fs->key_field,
        .key = fs->key_field ? (const char *const *)fs->key : NULL, .layer_count = fs->layers,
        .layer_name = (const char *const *)fs->layer_name, .face_count = (uint32_t)fl->faces,
        .face_start = out->face_start, .face_feature = out->face_feature};
}

/* The faces' witnesses (face_witness.h), found on a thread of their own:
 * they and the topology walk (face_link.h) only read the graph, the file
 * and the faces, and each writes its own array, so on two cores the two
 * walks, the linking's two largest steps, take the time of the longer. */
typedef struct witness_job {
    const hpfc_graph *graph;
    const leaf_crossings *lc;
    const hpfc_file *file;
    const hpfc_faces *faces;
    face_witness *w;
    int status;
    stage_time t; /* wall and the thread's own CPU time */
} witness_job;

static stage_time thread_now(void)
{
    stage_time t;
    t.wall = clock_seconds();
    t.cpu = clock_read(CLOCK_THREAD_CPUTIME_ID);
    return t;
}

/* The wall and this thread's CPU time since t0. */
static stage_time thread_since(stage_time t0)
{
    stage_time t = thread_now();
    t.wall -= t0.wall;
    t.cpu -= t0.cpu;
    return t;
}

static void *find_witnesses(void *arg)
{
    witness_job *job = arg;
    stage_time t0 = thread_now();
    job->status = face_witnesses(job->graph, job->lc, job->file, job->faces, job->w);
    job->t = thread_since(t0);
    return NULL;
}

int gis_features_link_method(const gis_features *fs, const hpfc_graph *graph,
                             const leaf_crossings *lc, const hpfc_file *file,
                             const hpfc_faces *given, int witness, unsigned threads,
                             gis_feature_table *out, char *err, size_t err_len)
{
    memset(out, 0, sizeof *out);
    out->method_witness = witness != 0;
    hpfc_faces *built = NULL;
    face_witness *w = NULL;
    face_link fl = {0};
    stage_time t = stage_now();
    int st = given ? HPFC_OK : hpfc_faces_build_threads(file, threads, &built);
    const hpfc_faces *faces = given ? given : built;
    out->faces_t = stage_lap(&t);
    uint64_t n = faces ? hpfc_faces_face_count(faces) : 0;
    if (!st && n >= UINT32_MAX)
        st = HPFC_E_LIMIT;
    if (!st && !(w = malloc((n ? n : 1) * sizeof *w)))
        st = HPFC_E_NOMEM;
    if (!st) {
        witness_job job = {graph, lc, file, faces, w, HPFC_OK, {0, 0}};
        pthread_t thread;
        int threaded = pthread_create(&thread, NULL, find_witnesses, &job) == 0;
        if (!threaded) /* no thread to be had: one walk after the other */
            find_witnesses(&job);
        stage_time t0 = thread_now();
        int walked = face_link_run(&fl, fs, graph, lc, file, faces);
        out->topology_t = thread_since(t0);
        if (threaded)
            pthread_join(thread, NULL);
        out->witness_t = job.t;
        st = job.status ? job.status : walked; /* as when the witnesses came first */
    }
    hpfc_faces_free(built); /* the walk needs the faces' ids only */
    stage_lap(&t);
    if (!st)
        st = check_faces(fs, w, &fl, !out->method_witness, threads, out);
    out->check_t = stage_lap(&t);
    if (!st) {
        out->faces_propagated = out->method_witness ? 0 : fl.propagated - 1;
        make_table(fs, &fl, out);
    }
    free(w);
    face_link_free(&fl);
    if (st) {
        gis_feature_table_free(out);
        snprintf(err, err_len, "cannot link the faces to their features (%s)", hpfc_strerror(st));
        return 1;
    }
    return 0;
}
