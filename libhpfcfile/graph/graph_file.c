/*
 * graph_file.c: a graph's arrays in a file (hpfc.h, "A graph file"), the
 * form in which a .pfc read in chunks by many processes meets again: each
 * chunk writes its own stretch of each array, and the graph is mapped back
 * whole, its arrays the file's pages. A map too large for the memory of the
 * process that cuts it into parts then sits in the page cache.
 *
 * The layout is the struct's (int64 vxy, uint32 eu and ev, uint64 eoff,
 * int64 pts) in the machine's byte order, each array 8-byte aligned after a
 * 64-byte header:
 *
 *   0  "HPFCGRF1"        8  byte-order mark 0x0A0B0C0D (uint32)
 *   12 unit_exp10 (int32) 16 vertices  24 edges  32 points (uint64)
 *   40 zeros to 64
 *
 * It is a file between the processes of one build (docs/interfaces.md §8),
 * not an exchange format, but its bytes are checked as hostile all the same:
 * every value a graph's accessors and checks rely on is one
 * hpfc_graph_add_* would have accepted.
 */
#define _DEFAULT_SOURCE /* madvise's MADV_DONTNEED, beside the build's _POSIX_C_SOURCE */
#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include "graph.h"

#define GRAPH_FILE_MAGIC "HPFCGRF1"
#define GRAPH_FILE_ORDER 0x0A0B0C0Du
#define GRAPH_FILE_HEADER 64
/* what hpfc_graph_add_* take: fewer than 2^32 - 2 vertices or edges, and
 * points far past any file (2^58 of 16 bytes is 2^62 bytes) */
#define GRAPH_FILE_MAX_ITEMS ((uint64_t)UINT32_MAX - 2)
#define GRAPH_FILE_MAX_POINTS ((uint64_t)1 << 58)

static uint64_t align8(uint64_t n)
{
    return (n + 7) & ~(uint64_t)7;
}

static void put_u32(uint8_t *p, uint32_t v)
{
    memcpy(p, &v, sizeof v);
}

static void put_u64(uint8_t *p, uint64_t v)
{
    memcpy(p, &v, sizeof v);
}

static uint64_t get_u64(const uint8_t *p)
{
    uint64_t v;
    memcpy(&v, p, sizeof v);
    return v;
}

int hpfc_graph_file_layout_of(uint64_t vertices, uint64_t edges, uint64_t points,
                              int32_t unit_exp10, hpfc_graph_file_layout *out)
{
    if (!out || unit_exp10 < -30 || unit_exp10 > 30)
        return HPFC_E_ARG;
    if (vertices > GRAPH_FILE_MAX_ITEMS || edges > GRAPH_FILE_MAX_ITEMS ||
        points > GRAPH_FILE_MAX_POINTS)
        return HPFC_E_LIMIT;
    memset(out, 0, sizeof *out);
    memcpy(out->header, GRAPH_FILE_MAGIC, 8);
    put_u32(out->header + 8, GRAPH_FILE_ORDER);
    put_u32(out->header + 12, (uint32_t)unit_exp10);
    put_u64(out->header + 16, vertices);
    put_u64(out->header + 24, edges);
    put_u64(out->header + 32, points);
    out->vxy = GRAPH_FILE_HEADER;
    out->eu = out->vxy + 16 * vertices;
    out->ev = out->eu + align8(4 * edges);
    out->eoff = out->ev + align8(4 * edges);
    out->pts = out->eoff + 8 * (edges + 1);
    out->size = out->pts + 16 * points;
    return HPFC_OK;
}

/* The check reads the mapped file a stretch at a time and hands each
 * stretch's pages back to the page cache once read: a process that maps
 * the file to use a small part of it (a part's builder, a chunk's router)
 * must not hold every page of it resident for the check's sake. */
enum { CHECK_STRETCH = 1 << 20 }; /* values */

/* The whole pages of [from, to) dropped from this process's mapping (the
 * file's pages stay in the page cache); nothing when the bytes are no
 * mapping (a copy: dropping would zero it). */
static void release(const hpfc_graph *g, const void *from, const void *to)
{
    if (!g->map)
        return;
    uintptr_t page = (uintptr_t)sysconf(_SC_PAGESIZE);
    uintptr_t a = ((uintptr_t)from + page - 1) & ~(page - 1), b = (uintptr_t)to & ~(page - 1);
    if (b > a)
        madvise((void *)a, b - a, MADV_DONTNEED);
}

static bool coords_ok(const hpfc_graph *g, const int64_t *xy, uint64_t n)
{
    for (uint64_t at = 0; at < n; at += CHECK_STRETCH) {
        uint64_t end = n - at < CHECK_STRETCH ? n : at + CHECK_STRETCH;
        for (uint64_t k = at; k < end; k++)
            if (xy[k] < -HPFC_COORD_MAX || xy[k] > HPFC_COORD_MAX)
                return false;
        release(g, xy + at, xy + end);
    }
    return true;
}

/* The arrays' values, as hpfc_graph_add_* would have checked them. */
static int check_arrays(const hpfc_graph *g, hpfc_diag *diag)
{
    if (!coords_ok(g, g->vxy, 2 * (uint64_t)g->nv) || !coords_ok(g, g->pts, 2 * (uint64_t)g->npts))
        return diag_set(diag, HPFC_E_EXTENT, "graph file: a coordinate past 2^40");
    if (g->eoff[0] != 0 || g->eoff[g->ne] != g->npts)
        return diag_set(diag, HPFC_E_CORRUPT, "graph file: the edges' points do not span the points");
    for (size_t e = 0; e < g->ne; e++) {
        if (e % CHECK_STRETCH == 0 && e) {
            release(g, g->eu + e - CHECK_STRETCH, g->eu + e);
            release(g, g->ev + e - CHECK_STRETCH, g->ev + e);
            release(g, g->eoff + e - CHECK_STRETCH, g->eoff + e);
        }
        if (g->eu[e] >= g->nv || g->ev[e] >= g->nv)
            return diag_set(diag, HPFC_E_VERTEX_INDEX, "graph file: edge %zu names no vertex", e);
        if (g->eoff[e + 1] < g->eoff[e])
            return diag_set(diag, HPFC_E_CORRUPT, "graph file: edge %zu's points out of order", e);
        if (g->eu[e] == g->ev[e] && g->eoff[e + 1] - g->eoff[e] < 2) /* as every graph input refuses */
            return diag_set(diag, HPFC_E_LOOP_INTERIOR, "graph file: loop edge %zu has fewer than 2 interior points", e);
    }
    return HPFC_OK;
}

/* bytes the file's mapping (`mapped`: the graph then owns it, and its
 * pages may be dropped once checked) or a copy. */
static int graph_from_bytes(const void *bytes, size_t length, bool mapped, hpfc_graph **out,
                            hpfc_diag *diag)
{
    diag_clear(diag);
    if (out)
        *out = NULL;
    if (!out || (!bytes && length))
        return diag_set(diag, HPFC_E_ARG, "graph file: NULL argument");
    const uint8_t *b = bytes;
    uint32_t order;
    int32_t unit;
    if (length < GRAPH_FILE_HEADER || memcmp(b, GRAPH_FILE_MAGIC, 8) != 0)
        return diag_set(diag, HPFC_E_MAGIC, "not a graph file");
    memcpy(&order, b + 8, 4);
    if (order != GRAPH_FILE_ORDER)
        return diag_set(diag, HPFC_E_MAGIC, "graph file of another byte order");
    if (sizeof(size_t) != 8) /* eoff is the struct's size_t */
        return diag_set(diag, HPFC_E_LIMIT, "graph file: a 64-bit machine's");
    memcpy(&unit, b + 12, 4);
    for (size_t k = 40; k < GRAPH_FILE_HEADER; k++)
        if (b[k])
            return diag_set(diag, HPFC_E_HEADER, "graph file: reserved header bytes not zero");
    hpfc_graph_file_layout l;
    int st = hpfc_graph_file_layout_of(get_u64(b + 16), get_u64(b + 24), get_u64(b + 32), unit, &l);
    if (st)
        return diag_set(diag, HPFC_E_HEADER, "graph file: counts or unit out of range");
    if (l.size != length)
        return diag_set(diag, HPFC_E_TRUNCATED, "graph file: %zu bytes where its header says %llu",
                        length, (unsigned long long)l.size);
    hpfc_graph *g = calloc(1, sizeof *g);
    if (!g)
        return diag_set(diag, HPFC_E_NOMEM, "out of memory");
    /* the arrays are 8-byte aligned in the file, and the caller's bytes are
     * a mapping (page-aligned) or a malloc'd copy */
    g->unit_exp10 = unit;
    g->nv = (size_t)get_u64(b + 16), g->ne = (size_t)get_u64(b + 24), g->npts = (size_t)get_u64(b + 32);
    g->vxy = (int64_t *)(uintptr_t)(b + l.vxy);
    g->eu = (uint32_t *)(uintptr_t)(b + l.eu);
    g->ev = (uint32_t *)(uintptr_t)(b + l.ev);
    g->eoff = (size_t *)(uintptr_t)(b + l.eoff);
    g->pts = g->npts ? (int64_t *)(uintptr_t)(b + l.pts) : NULL;
    g->map_len = length;
    g->map = mapped ? (void *)(uintptr_t)bytes : NULL;
    if ((st = check_arrays(g, diag))) {
        free(g); /* not hpfc_graph_free: the caller unmaps */
        return st;
    }
    release(g, bytes, b + length); /* the check's last stretches */
    *out = g;
    return HPFC_OK;
}

int graph_from_file_bytes(const void *bytes, size_t length, hpfc_graph **out, hpfc_diag *diag)
{
    return graph_from_bytes(bytes, length, false, out, diag);
}

int hpfc_graph_map_file(const char *path, hpfc_graph **out, hpfc_diag *diag)
{
    diag_clear(diag);
    if (out)
        *out = NULL;
    if (!path || !out)
        return diag_set(diag, HPFC_E_ARG, "hpfc_graph_map_file: NULL argument");
    int fd = open(path, O_RDONLY | O_CLOEXEC);
    if (fd < 0)
        return diag_set(diag, HPFC_E_IO, "cannot open %s: %s", path, strerror(errno));
    struct stat sb;
    if (fstat(fd, &sb) != 0 || !S_ISREG(sb.st_mode)) {
        close(fd);
        return diag_set(diag, HPFC_E_IO, "%s: not a regular file", path);
    }
    if ((uintmax_t)sb.st_size < GRAPH_FILE_HEADER || (uintmax_t)sb.st_size > SIZE_MAX) {
        close(fd);
        return diag_set(diag, HPFC_E_MAGIC, "%s: not a graph file", path);
    }
    size_t len = (size_t)sb.st_size;
    void *map = mmap(NULL, len, PROT_READ, MAP_SHARED, fd, 0);
    close(fd);
    if (map == MAP_FAILED)
        return diag_set(diag, HPFC_E_IO, "cannot map %s: %s", path, strerror(errno));
    int st = graph_from_bytes(map, len, true, out, diag);
    if (st)
        munmap(map, len);
    return st;
}
