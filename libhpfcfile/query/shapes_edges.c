/*
 * The shapes' edge and vertex records, read on first use (shapes.h,
 * "edges and vertices read 64 at a time"): a query reads the chunks of
 * the edges it meets and of their vertices, so that an index whose tables
 * are in the file (SHIX) opens in O(1) and a window costs what it
 * returns. The arrays are allocated at create and filled a chunk at a
 * time; a chunk that does not read (a damaged GEOM or LABL) stays unread
 * and every query that needs it answers the same error.
 */
#define _DEFAULT_SOURCE /* MAP_ANONYMOUS, beside the build's _POSIX_C_SOURCE */
#include <stdlib.h>
#include <sys/mman.h>

#include "file.h"
#include "shapes.h"

/* From a page on, zeroed arrays are fresh anonymous pages: calloc may
 * take a large block from the heap (glibc does once a free has raised
 * its mmap threshold, as in any GDAL process) and clear it, O(size). A
 * dozen arrays a shapes object, so the system calls stay few. */
enum { ZEROED_PAGES = 1 << 12 };

/* Under AddressSanitizer every array stays a heap block, with its
 * redzones: the tests and fuzzers see an overrun of a large map too. */
#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SHAPES_UNDER_ASAN 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)
#define SHAPES_UNDER_ASAN 1
#endif

#if defined(MAP_ANONYMOUS) && !defined(SHAPES_UNDER_ASAN)
#define SHAPES_MAP_ANON MAP_ANONYMOUS
#elif defined(MAP_ANON) && !defined(SHAPES_UNDER_ASAN)
#define SHAPES_MAP_ANON MAP_ANON
#endif

void *shapes_zeroed(size_t count, size_t size)
{
    if (size && count > SIZE_MAX / size)
        return NULL;
#ifdef SHAPES_MAP_ANON
    if (count * size >= ZEROED_PAGES) {
        void *p = mmap(NULL, count * size, PROT_READ | PROT_WRITE, MAP_PRIVATE | SHAPES_MAP_ANON,
                       -1, 0);
        return p == MAP_FAILED ? NULL : p;
    }
#endif
    return calloc(count, size);
}

void shapes_zeroed_free(void *p, size_t count, size_t size)
{
    (void)count, (void)size; /* without anonymous pages, every array is calloc's */
    if (!p)
        return;
#ifdef SHAPES_MAP_ANON
    if (count * size >= ZEROED_PAGES) {
        munmap(p, count * size);
        return;
    }
#endif
    free(p);
}

int shapes_read_vertices(hpfc_shapes *s, uint64_t chunk)
{
    uint64_t v0 = chunk << SHAPES_CHUNK_SHIFT, m = s->vertices - v0;
    if (v0 >= s->vertices)
        return HPFC_E_CORRUPT;
    if (m > SHAPES_CHUNK)
        m = SHAPES_CHUNK;
    int st = geom_points(s->f, GEOM_VX, v0, m, s->vxy + 2 * v0);
    if (!st)
        s->vertex_read[chunk] = 1;
    return st;
}

/* Each edge's ends, shape points and faces: GEOM's orientation bit picks
 * which of LABL's two sides is the right one (as hpfc_geometry_edge_faces
 * reads them, without its checks per call: hpfc_shapes_create checked
 * that the counts agree); then the ends' vertices. */
int shapes_read_edges(hpfc_shapes *s, uint64_t chunk)
{
    const hpfc_file *f = s->f;
    const labels_view *lv = &f->labels;
    const unsigned fb = lv->face_bits;
    uint64_t e0 = chunk << SHAPES_CHUNK_SHIFT, m = s->edges - e0;
    if (e0 >= s->edges)
        return HPFC_E_CORRUPT;
    if (m > SHAPES_CHUNK)
        m = SHAPES_CHUNK;
    geom_edge rec[SHAPES_CHUNK];
    int st = geom_edges(f, e0, m, rec);
    for (uint64_t k = 0; k < m && !st; k++) {
        uint64_t e = e0 + k;
        unsigned rgt = (unsigned)format_get(&f->geom.orient, e, 1);
        uint64_t r = format_get(&lv->sides, (2 * e + rgt) * fb, fb);
        uint64_t l = format_get(&lv->sides, (2 * e + !rgt) * fb, fb);
        if (l >= s->faces || r >= s->faces)
            return HPFC_E_CORRUPT;
        for (int end = 0; end < 2 && !st; end++) {
            uint64_t vc = (end ? rec[k].v : rec[k].u) >> SHAPES_CHUNK_SHIFT;
            if (!s->vertex_read[vc])
                st = shapes_read_vertices(s, vc);
        }
        s->edge[e].u = (uint32_t)rec[k].u, s->edge[e].v = (uint32_t)rec[k].v;
        s->edge[e].first = rec[k].first, s->edge[e].end = rec[k].first + rec[k].n;
        s->edge[e].left = l, s->edge[e].right = r;
    }
    if (!st)
        s->edge_read[chunk] = 1;
    return st;
}

int shapes_read_all(hpfc_shapes *s)
{
    int st = HPFC_OK;
    for (uint64_t c = 0; !s->all_read && c << SHAPES_CHUNK_SHIFT < s->edges && !st; c++)
        if (!s->edge_read[c])
            st = shapes_read_edges(s, c);
    s->all_read = !st;
    return st;
}
