/*
 * pack_write.c: pack_write.h, the steps hpfc-pack ran after reading its
 * input, moved here unchanged so that the GDAL driver runs the very same.
 */
#include "pack_write.h"

#include <errno.h>
#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#ifdef __GLIBC__
#include <malloc.h>
#endif

#include "atomic_output.h"
#include "clock.h"
#include "face_witness.h"
#include "gis_features.h"
#include "pack_cut.h"
#include "progress.h"

/* Links the faces of the serialised file to the GIS features that
 * cover it, for the FEAT section, with the faces the writer numbered for
 * LABL (NULL without LABL: numbered here). The witnesses need the
 * crossings' segments from the tree, taken first; then the tree is freed
 * before the linking's own arrays (and, without LABL, the faces' flood
 * fill) are made. 0, or 1 with a message in err. */
static int link_features(const hpfc_graph *g, hpfc_tree **t, const hpfc_file *f,
                         const hpfc_faces *faces, const gis_info *gis, int witness, unsigned threads,
                         pack_write_stats *r, gis_feature_table *ft, char *err, size_t err_len)
{
    stage_time t0 = stage_now();
    leaf_crossings lc;
    int st = leaf_crossings_collect(*t, f, &lc);
    hpfc_tree_free(*t);
    *t = NULL;
    if (st) {
        snprintf(err, err_len, "internal error: the file does not match its tree (%s)",
                 hpfc_strerror(st));
        return 1;
    }
    st = gis_features_link_method(gis->polygons, g, &lc, f, faces, witness, threads, ft, err, err_len);
    leaf_crossings_free(&lc);
    if (!st) {
        r->features = ft->polygon_features;
        r->all_features = ft->table.feature_count;
        r->faces_without_witness = ft->faces_without_witness;
        r->faces_walked = ft->faces_propagated;
        r->faces_anchored = ft->anchors;
        r->link_conflicts = ft->conflicts;
        r->faces_checked = ft->table.face_count - ft->faces_without_witness;
        r->link_witness = ft->method_witness;
        r->link_t[0] = ft->faces_t, r->link_t[1] = ft->witness_t;
        r->link_t[2] = ft->topology_t, r->link_t[3] = ft->check_t;
        for (uint32_t e = 0; e < ft->edge_count; e++)
            r->edges_with_features += ft->edge_start[e + 1] > ft->edge_start[e];
        for (uint32_t k = 0; k < ft->table.face_count; k++)
            r->faces_with_features += ft->face_start[k + 1] > ft->face_start[k];
    }
    r->features_t = stage_lap(&t0);
    return st;
}

/* Gives the heap's free pages back to the system. The builder frees
 * about a hundred megabytes of working arrays on a continental map, in
 * pieces glibc keeps, while the serialised file and the crossings that
 * follow are large enough to be mapped afresh: without this, both would
 * count at the pack's peak. */
static void release_free_memory(void)
{
#ifdef __GLIBC__
    malloc_trim(0);
#endif
}

/* hpfc_build's progress, as a bar per level. */
static void show_build_progress(void *user, uint32_t level, uint64_t done, uint64_t total)
{
    char stage[24];
    snprintf(stage, sizeof stage, "level %u", level);
    progress_show(user, stage, (double)done, (double)total, done == total);
}

/* atomic_output's why[] ("OUTPUT: reason") as diag's message, without the
 * name the caller prints itself. */
static int output_failed(const char *output, const char *why, hpfc_diag *diag)
{
    size_t n = strlen(output);
    const char *reason = strncmp(why, output, n) == 0 && why[n] == ':' ? why + n + 2 : why;
    snprintf(diag->message, sizeof diag->message, "%.300s", reason);
    return HPFC_E_IO;
}

/* The final bytes (with the FEAT section) on standard output (output
 * NULL: serialised, then written) or to OUTPUT through
 * common/atomic_output.h, written a section at a time from the mapping
 * (hpfc_file_write_fd), so the pack never holds the file twice. */
static int write_output(const char *output, const hpfc_file *f, const hpfc_write_options *wopts,
                        pack_write_stats *r, hpfc_diag *diag)
{
    char why[ATOMIC_WHY];
    if (!output) {
        uint8_t *bytes = NULL;
        size_t size = 0;
        int st = hpfc_file_serialize(f, wopts, &bytes, &size, diag);
        if (!st && (fwrite(bytes, 1, size, stdout) != size || fflush(stdout) != 0)) {
            snprintf(diag->message, sizeof diag->message, "cannot write to standard output: %s",
                     strerror(errno));
            st = HPFC_E_IO;
        }
        if (!st)
            r->file_bytes = size;
        hpfc_free(bytes);
        return st;
    }
    atomic_output o;
    if (atomic_output_open(&o, output, why))
        return output_failed(output, why, diag);
    int st = hpfc_file_write_fd(f, wopts, o.fd, diag);
    struct stat sb;
    if (!st && fstat(o.fd, &sb) == 0)
        r->file_bytes = (uint64_t)sb.st_size;
    if (st) { /* "cannot write: reason", after the OUTPUT the caller prints */
        atomic_output_discard(&o);
        return st;
    }
    return atomic_output_commit(&o, why) ? output_failed(output, why, diag) : HPFC_OK;
}

/* The tree written straight to OUTPUT's temporary file, a section at a
 * time (hpfc_tree_write_fd: GEOM streamed, pools one at a time), then
 * opened from there for the read-back check and the report (`hook`), and
 * renamed to OUTPUT. For a file OUTPUT when nothing is added after the
 * tree (no features to link): the file is never held in memory, where
 * the path through hpfc_tree_serialize holds all of it while it writes. */
static int write_tree_direct(const hpfc_tree *t, const hpfc_write_options *wopts,
                             const char *output, pack_write_hook hook, void *user,
                             pack_write_stats *r, hpfc_diag *diag)
{
    char why[ATOMIC_WHY];
    atomic_output o;
    if (atomic_output_open(&o, output, why))
        return output_failed(output, why, diag);
    hpfc_file *f = NULL;
    struct stat sb;
    char proc_path[40];
    const char *written = atomic_output_read_path(&o, proc_path, sizeof proc_path);
    int st = hpfc_tree_write_fd(t, wopts, o.fd, diag);
    if (!st && fstat(o.fd, &sb) == 0)
        r->file_bytes = (uint64_t)sb.st_size;
    if (!st && ((st = hpfc_open(written, 0, &f)) != HPFC_OK || (hook && (st = hook(user, t, f)) != HPFC_OK)))
        snprintf(diag->message, sizeof diag->message,
                 "internal error: the file written does not read back (%s)", hpfc_strerror(st));
    hpfc_close(f);
    if (st) { /* "cannot write: reason", after the OUTPUT the caller prints */
        atomic_output_discard(&o);
        return st;
    }
    return atomic_output_commit(&o, why) ? output_failed(output, why, diag) : HPFC_OK;
}

static int diag_set_message(hpfc_diag *diag, int status, const char *message)
{
    snprintf(diag->message, sizeof diag->message, "%s", message);
    return status;
}

/* The tree written to a scratch file beside OUTPUT (`OUT.tree-XXXXXX`, or
 * under $TMPDIR for standard output) and opened (mapped) from there: the
 * mapping keeps the bytes, in the page cache rather than in the process,
 * until hpfc_close. The features are linked on it, and the final file
 * (with FEAT) is copied from it. The name is removed as soon as the file
 * is created when /proc/self/fd can reopen it (so that a killed run
 * leaves nothing), else once it is open; a file size limit fails the
 * write (EFBIG), as atomic_output arranges, rather than killing the
 * process. */
static int tree_to_scratch(const hpfc_tree *t, const hpfc_write_options *wopts,
                           const char *output, hpfc_file **f, hpfc_diag *diag)
{
    char path[4200], proc_path[40];
    const char *tmp = getenv("TMPDIR");
    int n = output ? snprintf(path, sizeof path, "%s.tree-XXXXXX", output)
                   : snprintf(path, sizeof path, "%s/hpfc-tree-XXXXXX", tmp && *tmp ? tmp : "/tmp");
    if (n < 0 || (size_t)n >= sizeof path)
        return diag_set_message(diag, HPFC_E_IO, "the output's name is too long for a scratch file");
    signal(SIGXFSZ, SIG_IGN);
    int fd = mkstemp(path);
    if (fd < 0) {
        char why[sizeof diag->message];
        snprintf(why, sizeof why, "cannot make a scratch file beside the output (%.200s): %s", path,
                 strerror(errno));
        return diag_set_message(diag, HPFC_E_IO, why);
    }
    const char *reopen = path;
    if (access("/proc/self/fd", X_OK) == 0) {
        snprintf(proc_path, sizeof proc_path, "/proc/self/fd/%d", fd);
        unlink(path);
        reopen = proc_path;
    }
    int st = hpfc_tree_write_fd(t, wopts, fd, diag);
    if (!st && (st = hpfc_open(reopen, 0, f)) != HPFC_OK)
        snprintf(diag->message, sizeof diag->message,
                 "internal error: the file written does not read back (%s)", hpfc_strerror(st));
    if (reopen == path)
        unlink(path);
    close(fd);
    return st;
}

/* Part q: a run of root pixels in scanline order (bands of rows), its
 * graph from the cut. */
static int build_one_part(const hpfc_cut *cut, const hpfc_build_params *p, const hpfc_domain *d,
                          uint32_t q, const uint32_t *pixels, size_t n, uint64_t edges, hpfc_tree **out,
                          hpfc_diag *diag)
{
    hpfc_part part = {.domain = *d, .root_pixels = pixels, .root_pixel_count = n};
    hpfc_graph *sub = NULL;
    uint32_t *ids = NULL;
    int st = hpfc_cut_part_graph(cut, q, &sub, &ids, diag);
    part.edge_ids = ids;
    part.edge_count = edges;
    if (!st)
        st = hpfc_build_part(sub, p, &part, out, diag);
    hpfc_graph_free(sub);
    hpfc_free(ids);
    return st;
}

/* After the parts failed: hpfc_build's words for a flaw of the graph, or
 * the parts' own failure (out of memory, a file). */
static int word_part_failure(const hpfc_graph *g, int st, hpfc_diag *diag)
{
    if (st == HPFC_E_NOMEM)
        return st;
    hpfc_diag whole;
    int flaw = hpfc_graph_validate(g, &whole);
    if (flaw)
        *diag = whole;
    return flaw ? flaw : st;
}

/* The parts built by others (pack_parts.await_parts), read back and joined. */
static int build_parts_elsewhere(const hpfc_graph *g, const hpfc_build_params *p,
                                 const pack_parts *parts, hpfc_tree **out, hpfc_diag *diag)
{
    part_plan plan;
    int st = part_dir_cut(g, p, parts->count, parts->dir, &plan, diag);
    if (!st && (st = parts->await_parts(parts->user, &plan, diag)) != HPFC_OK)
        return word_part_failure(g, st, diag);
    if (!st && (st = part_dir_merge(parts->dir, NULL, plan.parts, true, out, diag)) == HPFC_E_ARG)
        st = HPFC_E_CORRUPT; /* parts that do not belong together: their files' fault */
    return st;
}

/* The folder of a build's part files: beside the output, whose file
 * system takes what is written there (where /tmp may be memory), or under
 * $TMPDIR for the standard output. */
typedef struct part_folder {
    char dir[4096];
    char **paths;
    size_t count;
} part_folder;

static int part_folder_open(part_folder *pf, const char *output, size_t count, hpfc_diag *diag)
{
    memset(pf, 0, sizeof *pf);
    const char *tmp = getenv("TMPDIR");
    int n = output ? snprintf(pf->dir, sizeof pf->dir, "%s.parts-XXXXXX", output)
                   : snprintf(pf->dir, sizeof pf->dir, "%s/hpfc-parts-XXXXXX", tmp && *tmp ? tmp : "/tmp");
    if (n < 0 || (size_t)n >= sizeof pf->dir)
        return diag_set_message(diag, HPFC_E_IO, "the output's name is too long for its parts' folder");
    if (!mkdtemp(pf->dir)) {
        char why[sizeof diag->message];
        snprintf(why, sizeof why, "cannot make a folder for the parts beside the output (%s): %s",
                 pf->dir, strerror(errno));
        pf->dir[0] = '\0';
        return diag_set_message(diag, HPFC_E_IO, why);
    }
    if (!(pf->paths = calloc(count, sizeof *pf->paths)))
        return diag_set_message(diag, HPFC_E_NOMEM, "out of memory");
    for (size_t q = 0; q < count; q++) {
        size_t len = strlen(pf->dir) + 32;
        if (!(pf->paths[q] = malloc(len)))
            return diag_set_message(diag, HPFC_E_NOMEM, "out of memory");
        snprintf(pf->paths[q], len, "%s/part-%zu.part", pf->dir, q);
        pf->count = q + 1;
    }
    return HPFC_OK;
}

/* A part's file in the parts' folder: created, written, closed; not synced
 * (it lives as long as the build). */
static int write_part(const hpfc_tree *part, const char *path, hpfc_diag *diag)
{
    int fd = open(path, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
    if (fd < 0) {
        char why[sizeof diag->message];
        snprintf(why, sizeof why, "cannot create %s: %s", path, strerror(errno));
        return diag_set_message(diag, HPFC_E_IO, why);
    }
    int st = hpfc_tree_write_part_fd(part, fd, diag);
    if (close(fd) != 0 && !st) {
        char why[sizeof diag->message];
        snprintf(why, sizeof why, "cannot write %s: %s", path, strerror(errno));
        st = diag_set_message(diag, HPFC_E_IO, why);
    }
    return st;
}

/* Removes the part files and their folder. A tree joined from them keeps
 * reading them through its mappings: their room on disk goes when it is
 * freed. */
static void part_folder_close(part_folder *pf)
{
    for (size_t q = 0; q < pf->count; q++) {
        remove(pf->paths[q]);
        free(pf->paths[q]);
    }
    free(pf->paths);
    if (pf->dir[0])
        rmdir(pf->dir);
    memset(pf, 0, sizeof *pf);
}

/* The parts of one build, handed out to `jobs` threads (pack_parts.jobs):
 * each takes the next part, builds it, writes its file and frees it. The
 * failure kept is the one of the lowest part, so that a run reports what
 * a run one part after another would have (the builder's own flaws are
 * worded again from the whole graph after: word_part_failure). */
typedef struct part_queue {
    const hpfc_cut *cut;
    const hpfc_build_params *params; /* without a progress callback */
    const hpfc_domain *domain;
    const uint32_t *pixels; /* every root pixel in scanline order */
    const uint64_t *start;  /* part q is pixels [start[q], start[q + 1]) */
    uint64_t edges;
    size_t parts;
    const part_folder *files;
    progress *bar;
    /* one thread: the heap given back after each part, as the parts go
     * one after another. Several: once, after the last (pack_write);
     * malloc_trim walks and locks every thread's heap, and under
     * AddressSanitizer two threads trimming at once crashed in glibc */
    bool trim_each;
    pthread_mutex_t lock; /* guards what follows */
    size_t next, done;
    size_t failed_part; /* parts when none failed */
    int status;
    hpfc_diag diag;
} part_queue;

static int build_and_write_part(part_queue *pq, size_t q, hpfc_diag *diag)
{
    size_t first = (size_t)pq->start[q], end = (size_t)pq->start[q + 1];
    hpfc_tree *part = NULL;
    int st = build_one_part(pq->cut, pq->params, pq->domain, (uint32_t)q, pq->pixels + first,
                            end - first, pq->edges, &part, diag);
    if (!st)
        st = write_part(part, pq->files->paths[q], diag); /* HPFC_E_IO: the disk's fault */
    hpfc_tree_free(part);
    if (pq->trim_each)
        release_free_memory();
    return st;
}

static void *part_worker(void *arg)
{
    part_queue *pq = arg;
    for (;;) {
        pthread_mutex_lock(&pq->lock);
        /* parts go out in order, so after a failure no later part starts; the
         * earlier ones, already running, finish (one may fail first) */
        bool stop = pq->next >= pq->parts || pq->next > pq->failed_part;
        size_t q = stop ? 0 : pq->next++;
        pthread_mutex_unlock(&pq->lock);
        if (stop)
            return NULL;
        hpfc_diag diag = {0};
        int st = build_and_write_part(pq, q, &diag);
        pthread_mutex_lock(&pq->lock);
        if (st && q < pq->failed_part)
            pq->failed_part = q, pq->status = st, pq->diag = diag;
        pq->done++;
        progress_show(pq->bar, "parts", (double)pq->done, (double)pq->parts, 1);
        pthread_mutex_unlock(&pq->lock);
    }
}

/* Runs the queue on `jobs` threads, the calling one among them; a thread
 * that cannot be started leaves its share to the others. */
static int run_part_queue(part_queue *pq, uint32_t jobs, hpfc_diag *diag)
{
    pq->failed_part = pq->parts;
    if (pthread_mutex_init(&pq->lock, NULL) != 0)
        return diag_set_message(diag, HPFC_E_NOMEM, "cannot make a lock for the parts' threads");
    size_t extra = jobs > pq->parts ? pq->parts - 1 : jobs - 1, started = 0;
    pthread_t *threads = extra ? calloc(extra, sizeof *threads) : NULL;
    for (size_t j = 0; threads && j < extra; j++, started++)
        if (pthread_create(&threads[j], NULL, part_worker, pq) != 0)
            break;
    part_worker(pq);
    for (size_t j = 0; j < started; j++)
        pthread_join(threads[j], NULL);
    free(threads);
    pthread_mutex_destroy(&pq->lock);
    if (pq->status)
        *diag = pq->diag;
    return pq->status;
}

/* The memory model's sample (pack_cut.h): PILOTS small runs of root
 * pixels spread over the map (each about 1/PILOT_SHARE of its points,
 * from a pixel of no more than four times that), built as parts and
 * thrown away, give the tree's pixels a point. A few percent of the
 * build's time; a pilot that fails (a flaw of the graph, which the build
 * proper reports) counts for nothing. */
enum { PILOTS = 4, PILOT_SHARE = 128 };

static void sample_pixels(const hpfc_graph *g, const hpfc_build_params *p, const hpfc_domain *d,
                          const uint64_t *weight, uint64_t roots, pack_memory *m)
{
    uint64_t total = 0, before = 0, target;
    for (uint64_t r = 0; r < roots; r++)
        total += weight[r];
    target = total / PILOT_SHARE + 1;
    uint32_t *owner = malloc((size_t)roots * sizeof *owner);
    uint32_t *pixels = malloc((size_t)roots * sizeof *pixels);
    uint64_t first[PILOTS], count[PILOTS] = {0}, points[PILOTS] = {0};
    uint32_t pilots = 0;
    if (!owner || !pixels)
        goto done;
    for (uint64_t r = 0; r < roots; r++)
        owner[r] = UINT32_MAX, pixels[r] = (uint32_t)r; /* in no pilot: left out of the cut */
    for (uint64_t r = 0; r < roots && pilots < PILOTS; before += weight[r], r++) {
        bool dense = weight[r] > 4 * target;
        if (count[pilots] == 0) {
            /* pilot k starts at the (2k + 1)/(2 PILOTS) quantile of the points */
            bool reached = before * 2 * PILOTS >= total * (2 * pilots + 1);
            if (!reached || weight[r] == 0 || dense)
                continue;
            first[pilots] = r;
        } else if (dense) {
            pilots++; /* closed before a dense pixel */
            continue;
        }
        owner[r] = pilots;
        count[pilots]++;
        points[pilots] += weight[r];
        if (points[pilots] >= target)
            pilots++;
    }
    pilots += pilots < PILOTS && count[pilots] > 0;
    hpfc_cut *cut = NULL;
    hpfc_diag quiet;
    hpfc_build_params one = *p;
    one.progress = NULL;
    one.threads = 1;
    if (pilots == 0 || hpfc_cut_create(g, p, d, owner, pilots, &cut, &quiet))
        goto done;
    for (uint32_t k = 0; k < pilots; k++) {
        hpfc_tree *t = NULL;
        hpfc_tree_info info;
        if (build_one_part(cut, &one, d, k, pixels + first[k], count[k], hpfc_graph_edge_count(g), &t,
                           &quiet) == HPFC_OK) {
            hpfc_tree_get_info(t, &info);
            m->sample_pixels += info.word_pixels + info.refined_pixels;
            m->sample_points += points[k];
        }
        hpfc_tree_free(t);
    }
    hpfc_cut_free(cut);
done:
    free(owner);
    free(pixels);
}

/* How the parts cut the root pixels (pack_cut.h): into runs of about
 * equal points, or for the budget of parts->memory. *k is the number of
 * runs, in start[0 .. *k]; 1 builds whole. */
static int choose_runs(const hpfc_graph *g, const hpfc_build_params *p, const hpfc_domain *d,
                       const pack_parts *parts, uint64_t *start, uint32_t *k, pack_write_stats *r,
                       hpfc_diag *diag)
{
    uint64_t roots = (uint64_t)p->root_cols * p->root_rows;
    uint32_t most = roots < UINT32_MAX ? (uint32_t)roots : UINT32_MAX;
    uint64_t *weight = malloc((size_t)roots * sizeof *weight);
    if (!weight)
        return diag_set_message(diag, HPFC_E_NOMEM, "out of memory");
    pack_cut_weigh(g, p, d, weight);
    if (!parts->memory) {
        *k = pack_cut_even(weight, roots, parts->count < most ? parts->count : most, start);
        free(weight);
        return HPFC_OK;
    }
    /* what the process holds, without the free heap the build would reuse
     * (hpfc-pack keeps it while GDAL reads) */
    release_free_memory();
    pack_memory m = {.held = pack_own_bytes(), .jobs = parts->jobs};
    sample_pixels(g, p, d, weight, roots, &m);
    release_free_memory();
    *k = pack_cut_budget(weight, roots, &m, parts->memory, most, start, &r->memory_need);
    r->memory_held = m.held;
    r->memory_sample_pixels = m.sample_pixels, r->memory_sample_points = m.sample_points;
    free(weight);
    if (r->memory_need > parts->memory && parts->notice) {
        char text[200];
        snprintf(text, sizeof text,
                 "--memory %llu MiB: this map needs about %llu MiB however it is cut; "
                 "building it in %u part%s",
                 (unsigned long long)(parts->memory >> 20),
                 (unsigned long long)((r->memory_need + (1u << 20) - 1) >> 20), *k,
                 *k == 1 ? " (whole)" : "s");
        parts->notice(text);
    }
    return HPFC_OK;
}

/* The tree, built whole, or in parts (pack_parts), each from the edges near
 * its root pixels, written to a part file and freed, then joined where the
 * files lie (hpfc_build_part, hpfc_tree_merge_files): the same tree, with
 * the builder's working arrays and tree for `jobs` parts at a time, and
 * the joined tree's pixels in the files (the page cache) rather than in
 * the process.
 *
 * Validation too goes part by part: every flaw hpfc_graph_validate looks
 * for but an isolated vertex (two points at one place, a zero-length
 * segment, a short loop, edges that cross or touch) lies at a point of
 * some root pixel, whose part holds every edge through it and validates
 * its graph (hpfc_graph_check_whole makes the rest). So the whole graph's
 * check (64 bytes a point, the one-process pack's peak on large maps) runs
 * only when a part finds a flaw, to report it in hpfc_build's very words. */
static int build_tree(const hpfc_graph *g, const hpfc_build_params *p, const pack_parts *parts,
                      const char *output, progress *bar, hpfc_tree **out, pack_write_stats *r,
                      hpfc_diag *diag)
{
    uint64_t roots = (uint64_t)p->root_cols * p->root_rows;
    if (parts->dir) {
        r->parts = parts->count < roots ? parts->count : (uint32_t)roots; /* part_dir_cut's */
        return build_parts_elsewhere(g, p, parts, out, diag);
    }
    r->parts = 1;
    if ((parts->count <= 1 && !parts->memory) || p->flat || hpfc_graph_check_whole(g, NULL))
        return hpfc_build(g, p, out, diag); /* which words the flaw */
    int64_t box[4];
    hpfc_domain d;
    int st = hpfc_graph_bounds(g, box);
    if (!st)
        st = hpfc_build_domain(box, p, &d, diag);
    uint64_t *start = st ? NULL : malloc(((size_t)roots + 1) * sizeof *start);
    uint32_t k = 1;
    if (!st && parts->memory)
        progress_show(bar, "sampling", 0, 0, 1); /* the model's small parts */
    if (!st)
        st = start ? choose_runs(g, p, &d, parts, start, &k, r, diag)
                   : diag_set_message(diag, HPFC_E_NOMEM, "out of memory");
    if (!st && k <= 1) {
        free(start);
        return hpfc_build(g, p, out, diag);
    }
    uint32_t *pixels = st ? NULL : malloc((size_t)roots * sizeof *pixels);
    uint32_t *owner = st ? NULL : malloc((size_t)roots * sizeof *owner);
    hpfc_cut *cut = NULL;
    part_folder pf = {0};
    if (!st && (!pixels || !owner))
        st = diag_set_message(diag, HPFC_E_NOMEM, "out of memory");
    if (!st)
        st = part_folder_open(&pf, output, k, diag);
    for (uint32_t q = 0; !st && q < k; q++)
        for (uint64_t px = start[q]; px < start[q + 1]; px++)
            pixels[px] = (uint32_t)px, owner[px] = q;
    if (!st)
        st = hpfc_cut_create(g, p, &d, owner, k, &cut, diag);
    free(owner);
    r->parts = k;
    /* one bar for the parts, not one a level of each */
    hpfc_build_params quiet = *p;
    quiet.progress = NULL;
    quiet.threads = 1; /* the parts themselves share the threads */
    part_queue pq = {.cut = cut, .params = &quiet, .domain = &d, .pixels = pixels, .start = start,
                     .edges = hpfc_graph_edge_count(g), .parts = k, .files = &pf, .bar = bar};
    uint32_t jobs = parts->jobs ? parts->jobs : 1;
    pq.trim_each = jobs == 1;
    if (!st) {
        progress_show(bar, "parts", 0, (double)k, 1);
        st = run_part_queue(&pq, jobs, diag);
    }
    hpfc_cut_free(cut);
    if (st && st != HPFC_E_IO)
        st = word_part_failure(g, st, diag);
    if (!st) {
        progress_show(bar, "joining", 0, 0, 1);
        st = hpfc_tree_merge_files((const char *const *)pf.paths, k, out, diag);
    }
    part_folder_close(&pf);
    free(pixels);
    free(start);
    return st;
}

int pack_write(const hpfc_graph *g, const hpfc_build_params *p, const pack_parts *parts,
               const hpfc_write_options *base, const gis_info *gis, int link_witness,
               const char *output, int progress_on, pack_write_hook hook, void *user, pack_write_stats *r,
               hpfc_diag *diag)
{
    memset(r, 0, sizeof *r);
    memset(diag, 0, sizeof *diag);
    progress bar = {.on = progress_on};
    hpfc_build_params params = *p;
    params.progress = show_build_progress;
    params.progress_user = &bar;
    hpfc_write_options wopts = *base;
    gis_feature_table ft = {0};
    hpfc_tree *t = NULL;
    stage_time t0 = stage_now();
    progress_show(&bar, "building", 0, 0, 1);
    pack_parts whole = {0};
    int st = build_tree(g, &params, parts ? parts : &whole, output, &bar, &t, r, diag);
    progress_end(&bar);
    release_free_memory();
    r->build_t = stage_lap(&t0);
    if (st) {
        r->build_failed = 1;
        return st;
    }
    int linking = gis && gis_features_count(gis->polygons) > 0;
    if (output && !linking) {
        st = write_tree_direct(t, &wopts, output, hook, user, r, diag);
        hpfc_tree_free(t);
        r->write_t = stage_lap(&t0);
        return st;
    }
    hpfc_file *f = NULL;
    /* the faces LABL is numbered with, kept for the linking, which would
     * otherwise number them again on the file (seconds on a large layer) */
    hpfc_faces *faces = NULL;
    wopts.faces_out = linking && wopts.face_labels ? &faces : NULL;
    if ((st = tree_to_scratch(t, &wopts, output, &f, diag)) == HPFC_OK &&
        ((faces && (st = hpfc_faces_attach(faces, f)) != HPFC_OK) ||
         (hook && (st = hook(user, t, f)) != HPFC_OK)))
        snprintf(diag->message, sizeof diag->message,
                 "internal error: the file written does not read back (%s)", hpfc_strerror(st));
    wopts.faces_out = NULL; /* the final write copies the file: no faces to hand out */
    hpfc_attr_table attrs;
    hpfc_edge_feature_table edge_features;
    if (!st && linking) {
        st = link_features(g, &t, f, faces, gis, link_witness, wopts.threads, r, &ft, diag->message,
                           sizeof diag->message);
        wopts.features = &ft.table;
        /* the features' attributes (ATTR) and the edges' features (EDGF) */
        if (!st && gis_attrs_table(gis->attrs, &attrs) != 0)
            st = HPFC_E_NOMEM;
        if (!st && attrs.feature_count == ft.table.feature_count)
            wopts.attributes = &attrs;
        edge_features = (hpfc_edge_feature_table){.edge_count = ft.edge_count,
                                                  .feature_count = ft.table.feature_count,
                                                  .edge_start = ft.edge_start,
                                                  .edge_feature = ft.edge_feature};
        if (!st && ft.edge_start)
            wopts.edge_features = &edge_features;
    }
    hpfc_faces_free(faces);
    hpfc_tree_free(t);
    if (!st) /* the pools as serialised, with the FEAT section when there is one */
        st = write_output(output, f, &wopts, r, diag);
    r->write_t = stage_lap(&t0);
    hpfc_close(f);
    gis_feature_table_free(&ft);
    return st;
}
