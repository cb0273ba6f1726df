/*
 * part_dir.c: part_dir.h, a split build's shared directory.
 */
#include "part_dir.h"

#include <errno.h>
#include <fcntl.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

static int diag_say(hpfc_diag *d, int status, const char *what, const char *why)
{
    snprintf(d->message, sizeof d->message, "%.200s: %.100s", what, why);
    d->status = status;
    return status;
}

hpfc_build_params part_plan_params(const part_plan *plan)
{
    hpfc_build_params p;
    hpfc_build_params_default(&p);
    p.root_cols = plan->root_cols, p.root_rows = plan->root_rows;
    p.cols = plan->cols, p.rows = plan->rows;
    p.max_leaf_points = plan->leaf_points;
    return p;
}

void part_dir_range(const part_plan *plan, uint32_t k, uint64_t *first, uint64_t *end)
{
    uint64_t roots = (uint64_t)plan->root_cols * plan->root_rows;
    *first = roots * k / plan->parts;
    *end = roots * ((uint64_t)k + 1) / plan->parts;
}

static void part_path(char *path, size_t size, const char *dir, uint32_t k, const char *ext)
{
    snprintf(path, size, "%s/part-%u.%s", dir, k, ext);
}

/* The graph as .pfc text of lattice integers (unit exponent 0: the reader
 * gets back the same integers, and the plan carries the unit). 0 or errno. */
static int write_pfc(const hpfc_graph *g, const char *path)
{
    FILE *f = fopen(path, "w");
    if (!f)
        return errno ? errno : EIO;
    fputs("pfc 1\n", f);
    for (size_t v = 0; v < hpfc_graph_vertex_count(g); v++) {
        int64_t x, y;
        hpfc_graph_vertex(g, v, &x, &y);
        fprintf(f, "v %lld %lld\n", (long long)x, (long long)y);
    }
    for (size_t e = 0; e < hpfc_graph_edge_count(g); e++) {
        uint32_t u, v;
        const int64_t *xy;
        size_t n;
        hpfc_graph_edge(g, e, &u, &v, &xy, &n);
        fprintf(f, "e %u %u", u, v);
        for (size_t k = 0; k < 2 * n; k++)
            fprintf(f, " %lld", (long long)xy[k]);
        fputc('\n', f);
    }
    int err = ferror(f) ? EIO : 0;
    if (fclose(f) && !err)
        err = errno ? errno : EIO;
    return err;
}

static int write_ids(const uint32_t *ids, size_t n, const char *path)
{
    FILE *f = fopen(path, "wb");
    if (!f)
        return errno ? errno : EIO;
    size_t done = n ? fwrite(ids, sizeof *ids, n, f) : 0;
    int err = done != n || ferror(f) ? EIO : 0;
    if (fclose(f) && !err)
        err = errno ? errno : EIO;
    return err;
}

/* One part's graph and ids into dir. */
static int cut_one(const hpfc_cut *cut, uint32_t k, const char *dir, hpfc_diag *d)
{
    hpfc_graph *sub = NULL;
    uint32_t *ids = NULL;
    int st = hpfc_cut_part_graph(cut, k, &sub, &ids, d);
    char path[4096];
    int err = 0;
    if (!st) {
        part_path(path, sizeof path, dir, k, "pfc");
        err = write_pfc(sub, path);
        if (!err) {
            part_path(path, sizeof path, dir, k, "ids");
            err = write_ids(ids, hpfc_graph_edge_count(sub), path);
        }
    }
    if (err)
        st = diag_say(d, HPFC_E_IO, path, strerror(err));
    hpfc_graph_free(sub);
    hpfc_free(ids);
    return st;
}

int part_dir_plan(const hpfc_graph *g, const hpfc_build_params *p, uint32_t parts, const int64_t *box,
                  part_plan *plan, hpfc_diag *d)
{
    memset(d, 0, sizeof *d);
    uint64_t roots = (uint64_t)p->root_cols * p->root_rows;
    if (parts < 1 || roots == 0 || roots > UINT32_MAX)
        return diag_say(d, HPFC_E_ARG, "partitions", "at least 1, on at most 2^32 root pixels");
    int st = hpfc_graph_check_whole(g, d);
    int64_t bounds[4];
    memset(plan, 0, sizeof *plan);
    if (!st && !box)
        st = hpfc_graph_bounds(g, bounds);
    if (!st)
        st = hpfc_build_domain(box ? box : bounds, p, &plan->domain, d);
    if (st)
        return st;
    plan->unit_exp10 = hpfc_graph_unit_exp10(g);
    plan->edges = hpfc_graph_edge_count(g);
    plan->parts = parts < roots ? parts : (uint32_t)roots;
    plan->root_cols = p->root_cols, plan->root_rows = p->root_rows;
    plan->cols = p->cols, plan->rows = p->rows, plan->leaf_points = p->max_leaf_points;
    return HPFC_OK;
}

/* Each root pixel's part (malloc'd), NULL when out of memory. */
static uint32_t *plan_owners(const part_plan *plan)
{
    uint64_t roots = (uint64_t)plan->root_cols * plan->root_rows;
    uint32_t *owner = malloc((size_t)(roots ? roots : 1) * sizeof *owner);
    for (uint32_t k = 0; owner && k < plan->parts; k++) {
        uint64_t first, end;
        part_dir_range(plan, k, &first, &end);
        for (uint64_t px = first; px < end; px++)
            owner[px] = k;
    }
    return owner;
}

int part_dir_cut(const hpfc_graph *g, const hpfc_build_params *p, uint32_t parts, const char *dir,
                 part_plan *plan, hpfc_diag *d)
{
    int st = part_dir_plan(g, p, parts, NULL, plan, d);
    if (st)
        return st;
    uint32_t *owner = plan_owners(plan);
    if (!owner)
        return diag_say(d, HPFC_E_NOMEM, "cutting the parts", "out of memory");
    hpfc_cut *cut = NULL;
    st = hpfc_cut_create(g, p, &plan->domain, owner, plan->parts, &cut, d);
    free(owner);
    for (uint32_t k = 0; !st && k < plan->parts; k++)
        st = cut_one(cut, k, dir, d);
    hpfc_cut_free(cut);
    return st;
}

/* The ids file: u32 each, as many as the part's edges (hpfc_build_part
 * checks their order and range). */
static int read_ids(const char *path, size_t count, uint32_t **out, hpfc_diag *d)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return diag_say(d, HPFC_E_IO, path, strerror(errno));
    uint32_t *ids = malloc((count ? count : 1) * sizeof *ids);
    int st = ids ? HPFC_OK : diag_say(d, HPFC_E_NOMEM, path, "out of memory");
    if (!st && (fread(ids, sizeof *ids, count, f) != count || fgetc(f) != EOF))
        st = diag_say(d, HPFC_E_CORRUPT, path, "not one id for each of the part's edges");
    fclose(f);
    if (st)
        free(ids);
    else
        *out = ids;
    return st;
}

/* A part's graph file, with the plan's unit: a part that no edge comes near
 * is an empty file (its pixels are private). */
static int read_part_graph(const char *path, int32_t unit, hpfc_graph **g, hpfc_diag *d)
{
    int st = hpfc_pfc_read_file(path, g, d);
    if (st == HPFC_E_EMPTY)
        st = hpfc_graph_create(g);
    else if (st) {
        char why[sizeof d->message];
        memcpy(why, d->message, sizeof why);
        return diag_say(d, st, path, why[0] ? why : hpfc_strerror(st));
    }
    if (!st && hpfc_graph_unit_exp10(*g) != 0)
        return diag_say(d, HPFC_E_CORRUPT, path, "a part's graph has fractions");
    if (!st)
        st = hpfc_graph_set_unit_exp10(*g, unit);
    return st;
}

/* Is part k one of the plan's, on a root the builder takes? */
static int check_part(const part_plan *plan, uint32_t k, hpfc_diag *d)
{
    uint64_t roots = (uint64_t)plan->root_cols * plan->root_rows;
    if (plan->parts < 1 || k >= plan->parts || plan->parts > roots)
        return diag_say(d, HPFC_E_ARG, "part", "no such part in the plan");
    if (roots > ((uint64_t)1 << 31)) /* the builder's bound, before the pixels are listed */
        return diag_say(d, HPFC_E_ARG, "plan", "more root pixels than a build takes");
    return HPFC_OK;
}

/* Part k built from its graph g and g's edge ids, into DIR/part-K.part. */
static int build_and_write(const char *dir, const part_plan *plan, uint32_t k, const hpfc_graph *g,
                           const uint32_t *ids, hpfc_diag *d)
{
    uint64_t first, end;
    part_dir_range(plan, k, &first, &end);
    hpfc_build_params p = part_plan_params(plan);
    hpfc_tree *t = NULL;
    uint32_t *pixels = malloc((size_t)(end - first + 1) * sizeof *pixels);
    int st = pixels ? HPFC_OK : diag_say(d, HPFC_E_NOMEM, "part", "out of memory");
    for (uint64_t q = first; !st && q < end; q++)
        pixels[q - first] = (uint32_t)q;
    if (!st) {
        hpfc_part part = {.domain = plan->domain, .root_pixels = pixels,
                          .root_pixel_count = (size_t)(end - first), .edge_ids = ids,
                          .edge_count = plan->edges};
        st = hpfc_build_part(g, &p, &part, &t, d);
    }
    char path[4096];
    part_path(path, sizeof path, dir, k, "part");
    if (!st)
        st = hpfc_tree_write_part(t, path, d);
    hpfc_tree_free(t);
    free(pixels);
    return st;
}

int part_dir_build(const char *dir, const part_plan *plan, uint32_t k, hpfc_diag *d)
{
    memset(d, 0, sizeof *d);
    int st = check_part(plan, k, d);
    if (st)
        return st;
    hpfc_graph *g = NULL;
    uint32_t *ids = NULL;
    char path[4096];
    part_path(path, sizeof path, dir, k, "pfc");
    if (!st)
        st = read_part_graph(path, plan->unit_exp10, &g, d);
    part_path(path, sizeof path, dir, k, "ids");
    if (!st)
        st = read_ids(path, hpfc_graph_edge_count(g), &ids, d);
    if (!st)
        st = build_and_write(dir, plan, k, g, ids, d);
    hpfc_graph_free(g);
    free(ids);
    return st;
}

int part_dir_merge(const char *dir, const char *const *paths, uint32_t count,
                   bool count_components, hpfc_tree **out, hpfc_diag *d)
{
    memset(d, 0, sizeof *d);
    /* dir's names, each as long as it needs ("DIR/part-K.part") */
    size_t each = paths ? 0 : strlen(dir) + 32;
    char *named = paths ? NULL : malloc((count ? count : 1) * each);
    const char **list = paths ? NULL : calloc(count ? count : 1, sizeof *list);
    if (!paths && (!named || !list)) {
        free(named);
        free(list);
        return diag_say(d, HPFC_E_NOMEM, "joining the parts", "out of memory");
    }
    for (uint32_t k = 0; !paths && k < count; k++) {
        part_path(named + k * each, each, dir, k, "part");
        list[k] = named + k * each;
    }
    /* the library's message already names the file at fault */
    const char *const *files = paths ? paths : list;
    int st = count_components ? hpfc_tree_merge_files(files, count, out, d)
                              : hpfc_tree_merge_files_uncounted(files, count, out, d);
    free(named);
    free(list);
    return st;
}

/* ---- the .pfc read by the workers, into DIR/graph --------------------------- */

int part_dir_map_text(const char *path, const char **text, size_t *length, hpfc_diag *d)
{
    memset(d, 0, sizeof *d);
    *text = NULL, *length = 0;
    int fd = open(path, O_RDONLY | O_CLOEXEC);
    struct stat sb;
    if (fd < 0)
        return diag_say(d, HPFC_E_IO, path, strerror(errno));
    if (fstat(fd, &sb) != 0 || !S_ISREG(sb.st_mode) || (uintmax_t)sb.st_size > SIZE_MAX) {
        close(fd);
        return diag_say(d, HPFC_E_IO, path, "not a regular file");
    }
    if (sb.st_size > 0) {
        void *map = mmap(NULL, (size_t)sb.st_size, PROT_READ, MAP_PRIVATE, fd, 0);
        if (map == MAP_FAILED) {
            int err = errno;
            close(fd);
            return diag_say(d, HPFC_E_IO, path, strerror(err));
        }
        *text = map, *length = (size_t)sb.st_size;
    }
    close(fd);
    return HPFC_OK;
}

static int pwrite_all(int fd, const void *buf, size_t n, uint64_t at)
{
    const char *p = buf;
    while (n > 0) {
        ssize_t w = pwrite(fd, p, n, (off_t)at);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0)
            return errno ? errno : EIO;
        p += w, n -= (size_t)w, at += (uint64_t)w;
    }
    return 0;
}

int part_dir_graph_create(const char *path, uint64_t vertices, uint64_t edges, uint64_t points,
                          int32_t unit_exp10, hpfc_diag *d)
{
    memset(d, 0, sizeof *d);
    hpfc_graph_file_layout l;
    int st = hpfc_graph_file_layout_of(vertices, edges, points, unit_exp10, &l);
    if (st)
        return diag_say(d, st, "the graph", "too large for a graph file");
    int fd = open(path, O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0)
        return diag_say(d, HPFC_E_IO, path, strerror(errno));
    int err = ftruncate(fd, (off_t)l.size) ? errno : 0;
    if (!err)
        err = pwrite_all(fd, l.header, sizeof l.header, 0);
    if (!err)
        err = pwrite_all(fd, &points, sizeof points, l.eoff + 8 * edges);
    if (close(fd) && !err)
        err = errno ? errno : EIO;
    return err ? diag_say(d, HPFC_E_IO, path, strerror(err)) : HPFC_OK;
}

/* One array's stretch of the chunk: n items of `size` bytes from item
 * `first` of the array at byte `at`. */
static int put_stretch(int fd, const void *items, uint64_t n, size_t size, uint64_t at, uint64_t first)
{
    return n ? pwrite_all(fd, items, (size_t)n * size, at + first * size) : 0;
}

/* Do items [first, first + n) lie within [0, total)? */
static bool fits(uint64_t first, uint64_t n, uint64_t total)
{
    return first <= total && n <= total - first;
}

int part_dir_fill_chunk(const char *pfc_path, size_t begin, size_t end, const struct hpfc_pfc_chunk *scan,
                        const char *graph_path, const part_dir_chunk_place *place, int64_t box[4],
                        hpfc_diag *d)
{
    hpfc_graph_file_layout l;
    if (hpfc_graph_file_layout_of(place->vertices, place->edges, place->points, -place->digits, &l) ||
        !fits(place->first_vertex, scan->vertices, place->vertices) ||
        !fits(place->first_edge, scan->edges, place->edges) ||
        !fits(place->first_point, scan->points, place->points))
        return diag_say(d, HPFC_E_ARG, "chunk", "not a chunk of the graph file's counts");
    const char *text;
    size_t length;
    int st = part_dir_map_text(pfc_path, &text, &length, d);
    if (st)
        return st;
    hpfc_pfc_fill f = {.digits = place->digits, .first_vertex = place->first_vertex,
                       .first_point = place->first_point};
    /* the chunk's share of each array, in the process's memory until written */
    f.vxy = malloc(16 * (size_t)scan->vertices + 16);
    f.eu = malloc(4 * (size_t)scan->edges + 4);
    f.ev = malloc(4 * (size_t)scan->edges + 4);
    f.eoff = malloc(8 * (size_t)scan->edges + 8);
    f.pts = malloc(16 * (size_t)scan->points + 16);
    if (!f.vxy || !f.eu || !f.ev || !f.eoff || !f.pts)
        st = diag_say(d, HPFC_E_NOMEM, "chunk", "out of memory");
    if (!st)
        st = hpfc_pfc_chunk_fill(text, length, begin, end, scan, &f, d);
    if (text)
        munmap((void *)(uintptr_t)text, length);
    int fd = st ? -1 : open(graph_path, O_WRONLY | O_CLOEXEC);
    int err = !st && fd < 0 ? errno : 0;
    if (!st && !err)
        err = put_stretch(fd, f.vxy, scan->vertices, 16, l.vxy, place->first_vertex);
    if (!st && !err)
        err = put_stretch(fd, f.eu, scan->edges, 4, l.eu, place->first_edge);
    if (!st && !err)
        err = put_stretch(fd, f.ev, scan->edges, 4, l.ev, place->first_edge);
    if (!st && !err)
        err = put_stretch(fd, f.eoff, scan->edges, 8, l.eoff, place->first_edge);
    if (!st && !err)
        err = put_stretch(fd, f.pts, scan->points, 16, l.pts, place->first_point);
    if (fd >= 0 && close(fd) && !err)
        err = errno ? errno : EIO;
    if (err)
        st = diag_say(d, HPFC_E_IO, graph_path, strerror(err));
    if (!st)
        memcpy(box, f.box, sizeof f.box);
    free(f.vxy), free(f.eu), free(f.ev), free(f.eoff), free(f.pts);
    return st;
}

/* ---- the edges routed to the parts by the workers (DIR/route-C) -------------
 * One file a chunk: "HPFCRTE1", the part count (u32) and a zero (u32), the
 * chunk's edge range (u64 first, u64 end), each part's count of edges (u64
 * each), then the edges' ids (u32), part by part, ascending within a part.
 * The machine's byte order, as the graph file's. */

#define ROUTE_MAGIC "HPFCRTE1"
#define ROUTE_HEADER 32
/* more ids than any route file holds (16 TiB of them), which keeps the
 * length the counts imply within 64 bits */
#define ROUTE_MAX_IDS ((uint64_t)1 << 42)

static void route_path(char *path, size_t size, const char *dir, uint32_t chunk)
{
    snprintf(path, size, "%s/route-%u", dir, chunk);
}

int part_dir_route(const char *dir, const hpfc_graph *g, const part_plan *plan, uint32_t chunk,
                   uint64_t first_edge, uint64_t end_edge, hpfc_diag *d)
{
    memset(d, 0, sizeof *d);
    int st = check_part(plan, 0, d);
    if (st)
        return st;
    hpfc_build_params p = part_plan_params(plan);
    uint32_t *owner = plan_owners(plan);
    if (!owner)
        return diag_say(d, HPFC_E_NOMEM, "routing the edges", "out of memory");
    hpfc_cut *cut = NULL;
    st = first_edge <= end_edge && end_edge <= hpfc_graph_edge_count(g)
                 ? hpfc_cut_create_range(g, &p, sizeof p, &plan->domain, owner, plan->parts,
                                         (size_t)first_edge, (size_t)end_edge, &cut, d)
                 : diag_say(d, HPFC_E_ARG, "chunk", "an edge range past the graph's");
    free(owner);
    char path[4096];
    route_path(path, sizeof path, dir, chunk);
    FILE *f = st ? NULL : fopen(path, "wb");
    if (!st && !f)
        st = diag_say(d, HPFC_E_IO, path, strerror(errno));
    if (!st) {
        uint32_t head[2] = {plan->parts, 0};
        uint64_t range[2] = {first_edge, end_edge};
        fwrite(ROUTE_MAGIC, 1, 8, f);
        fwrite(head, sizeof head, 1, f);
        fwrite(range, sizeof range, 1, f);
        for (uint32_t k = 0; k < plan->parts; k++) {
            const uint32_t *ids;
            size_t n;
            hpfc_cut_part_edges(cut, k, &ids, &n);
            uint64_t count = n;
            fwrite(&count, sizeof count, 1, f);
        }
        for (uint32_t k = 0; k < plan->parts; k++) {
            const uint32_t *ids;
            size_t n;
            hpfc_cut_part_edges(cut, k, &ids, &n);
            if (n)
                fwrite(ids, sizeof *ids, n, f);
        }
        int err = ferror(f) ? EIO : 0;
        if (fclose(f) && !err)
            err = errno ? errno : EIO;
        if (err)
            st = diag_say(d, HPFC_E_IO, path, strerror(err));
    }
    hpfc_cut_free(cut);
    return st;
}

/* Part k's ids in chunk c's route file, appended to *ids (grown: *n held,
 * *cap room): refused unless the file is one of this plan's, for the edge
 * range that follows the last chunk's (*next_edge), whole. */
static int read_route(const char *dir, const part_plan *plan, uint32_t c, uint32_t k, uint64_t *next_edge,
                      uint32_t **ids, size_t *n, size_t *cap, hpfc_diag *d)
{
    char path[4096];
    route_path(path, sizeof path, dir, c);
    FILE *f = fopen(path, "rb");
    if (!f)
        return diag_say(d, HPFC_E_IO, path, strerror(errno));
    char magic[8];
    uint32_t head[2];
    uint64_t range[2], before = 0, count = 0, total = 0;
    int st = fread(magic, 8, 1, f) == 1 && fread(head, sizeof head, 1, f) == 1 &&
                     fread(range, sizeof range, 1, f) == 1 && memcmp(magic, ROUTE_MAGIC, 8) == 0 &&
                     head[0] == plan->parts && head[1] == 0 && range[0] == *next_edge &&
                     range[0] <= range[1] && range[1] <= plan->edges
                 ? HPFC_OK
                 : diag_say(d, HPFC_E_CORRUPT, path, "not a route file of this plan's chunks");
    for (uint32_t q = 0; !st && q < plan->parts; q++) {
        uint64_t m;
        if (fread(&m, sizeof m, 1, f) != 1 || m > range[1] - range[0] || total + m > ROUTE_MAX_IDS)
            st = diag_say(d, HPFC_E_CORRUPT, path, "a part's count past the chunk's edges");
        before += q < k ? m : 0, count = q == k ? m : count, total += m;
    }
    struct stat sb;
    if (!st && (fstat(fileno(f), &sb) != 0 ||
                (uint64_t)sb.st_size != ROUTE_HEADER + 8 * (uint64_t)plan->parts + 4 * total))
        st = diag_say(d, HPFC_E_CORRUPT, path, "not as long as its counts say");
    if (!st && *n + count > *cap) {
        size_t want = (size_t)(*n + count) * 2 + 16;
        uint32_t *more = realloc(*ids, want * sizeof *more);
        if (!more)
            st = diag_say(d, HPFC_E_NOMEM, "part", "out of memory");
        else
            *ids = more, *cap = want;
    }
    if (!st && count &&
        (fseeko(f, (off_t)(ROUTE_HEADER + 8 * (uint64_t)plan->parts + 4 * before), SEEK_SET) != 0 ||
         fread(*ids + *n, sizeof **ids, (size_t)count, f) != count))
        st = diag_say(d, HPFC_E_IO, path, "cannot read its ids");
    for (size_t q = *n; !st && q < *n + count; q++) /* ascending within the chunk's range */
        if ((*ids)[q] < range[0] || (*ids)[q] >= range[1] || (q > *n && (*ids)[q] <= (*ids)[q - 1]))
            st = diag_say(d, HPFC_E_CORRUPT, path, "ids out of the chunk's range or order");
    fclose(f);
    if (!st)
        *n += (size_t)count, *next_edge = range[1];
    return st;
}

int part_dir_build_routed(const char *dir, const part_plan *plan, uint32_t k, uint32_t chunks, hpfc_diag *d)
{
    memset(d, 0, sizeof *d);
    int st = check_part(plan, k, d);
    if (st)
        return st;
    uint32_t *ids = NULL;
    size_t n = 0, cap = 0;
    uint64_t next_edge = 0;
    for (uint32_t c = 0; !st && c < chunks; c++)
        st = read_route(dir, plan, c, k, &next_edge, &ids, &n, &cap, d);
    if (!st && next_edge != plan->edges)
        st = diag_say(d, HPFC_E_CORRUPT, dir, "the route files do not cover the graph's edges");
    if (!st && !ids && !(ids = malloc(sizeof *ids))) /* a part no edge comes near: ids, none of them */
        st = diag_say(d, HPFC_E_NOMEM, "part", "out of memory");
    char path[4096];
    snprintf(path, sizeof path, "%s/graph", dir);
    hpfc_graph *whole = NULL, *g = NULL;
    if (!st)
        st = hpfc_graph_map_file(path, &whole, d);
    if (!st && (hpfc_graph_edge_count(whole) != plan->edges || hpfc_graph_unit_exp10(whole) != plan->unit_exp10))
        st = diag_say(d, HPFC_E_CORRUPT, path, "not the plan's graph");
    if (!st)
        st = hpfc_graph_copy_edges(whole, ids, n, &g, d);
    hpfc_graph_free(whole);
    if (!st)
        st = build_and_write(dir, plan, k, g, ids, d);
    hpfc_graph_free(g);
    free(ids);
    return st;
}
