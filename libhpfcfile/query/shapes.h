/*
 * shapes.h: the index behind geometry back from a file and the spatial
 * queries over it (struct hpfc_shapes: each edge's ends and faces, each
 * face's edges, each feature's faces and edges, and the scratch its calls
 * share): shapes.c builds it and assembles rings (of faces, features,
 * sets of features) and lines (a feature's, a mesh's borders); window.c
 * answers windows through it; neighbours.c the features that touch and
 * each feature's border; nearest.c the edges near a point. Internal to
 * the library.
 */
#ifndef HPFC_SHAPES_H
#define HPFC_SHAPES_H

#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "arrays.h"
#include "feature_links.h"
#include "file.h"
#include "hpfc.h"
#include "shix.h"

__extension__ typedef __int128 s128;

/* A dart of a region's boundary: edge << 1 | reversed, with what the
 * assembly needs of it. */
typedef struct bdart {
    uint64_t code;
    size_t pts;       /* its edge's points, u -> v, from s->ept[2 * pts] */
    uint32_t face;    /* the region's face on its left */
    uint32_t origin, target;
    int64_t out[2];   /* direction leaving the origin */
    int64_t back[2];  /* direction from the target back along the last segment */
    uint32_t next;    /* the dart continuing it */
    uint8_t has_prev, used;
} bdart;

/* A ring being assembled: points [start, end) of the scratch points. */
typedef struct tring {
    size_t start, end;
    uint32_t part;    /* the region's part it bounds (see own_by_part) */
    s128 area2;       /* twice the signed area */
    int64_t box[4];   /* xmin, ymin, xmax, ymax */
    size_t owner;     /* holes: the outer ring's index, SIZE_MAX: none */
} tring;

/* The index's three inverse tables. */
enum shapes_table { FACE_EDGES, FEATURE_FACES, FEATURE_EDGES, SHAPES_TABLES };

/* One of them: built in memory at create (start: rows + 1 offsets, and
 * item), or read in place from the file's SHIX section (spec §6.8; mapped
 * .bits.base non-NULL), each row checked as it is read (shix_row).
 * Neither: the file has not the section the table inverts. */
typedef struct shapes_rows {
    uint64_t *start;
    uint32_t *item;
    shix_table mapped;
} shapes_rows;

/* Edges and vertices are read a chunk at a time, on first use
 * (shapes_edges.c): a query pays for the edges it meets. */
enum { SHAPES_CHUNK_SHIFT = 6, SHAPES_CHUNK = 1 << SHAPES_CHUNK_SHIFT };

/* An edge as the queries use it: its ends, the faces on its sides, its
 * shape points [first, end) of GEOM's. One record rather than an array a
 * field: a chunk of edges read is then 2.5 KB in one or two pages, where
 * six arrays took six, each a page fault on its first write (a 1 % window
 * of US counties from a fresh handle: 70 faults in all, 63 with records). */
typedef struct shapes_edge {
    uint64_t left, right;
    uint64_t first, end;
    uint32_t u, v;
} shapes_edge;

struct hpfc_shapes {
    const hpfc_file *f;
    uint64_t vertices, edges, faces, points;
    int domain_in_limit;        /* every lattice point of the domain passes coord_ok */
    /* each edge's record, each vertex's coordinates (pairs): valid for
     * the edges and vertices of a chunk read (edge_read, vertex_read;
     * shapes_need_edge) */
    shapes_edge *edge;
    int64_t *vxy;
    uint8_t *edge_read, *vertex_read;
    int all_read;               /* every edge's chunk read (shapes_read_all) */
    /* each face's edges (an edge with one face on both sides bounds
     * nothing and is in no row), each feature's faces (FEAT) and edges
     * (EDGF): shapes_row and shapes_item read them */
    shapes_rows rows[SHAPES_TABLES];
    feature_links face_links, edge_links; /* FEAT's and EDGF's, for the mapped rows' checks */
    uint32_t *row_copy;         /* a mapped row copied out, for callers that take an array */
    size_t cap_row_copy;
    int have_features, have_edge_features;
    int face_features;          /* FEAT numbers this map's faces: face -> features reads */
    uint32_t features;
    uint32_t *face_mark, mark;  /* face_mark[f] == mark: f is in the region */
    uint32_t *face_local;       /* f's index among the region's faces */
    uint32_t *vmark, *vpos, vgen;
    /* scratch, reused by every call */
    bdart *darts, *dsorted;
    size_t ndarts, cap_darts, cap_dsorted;
    key_item *dkeys;            /* the darts by origin, and scratch */
    size_t cap_dkeys;
    int64_t *ept;               /* the darts' edges' points (pairs); once the rings
                                 * are traced, the answer's points when they
                                 * are not where tracing put them */
    size_t nept, cap_ept;
    uint32_t *part;             /* union-find over the region's faces */
    size_t nparts, cap_part;
    size_t *part_outer, cap_part_outer;
    uint32_t *cycle;
    size_t cap_cycle;
    int64_t *txy;
    size_t ntxy, cap_txy;       /* points (pairs) */
    tring *rings;
    size_t nrings, cap_rings;
    /* the answer */
    size_t *ring_point, cap_ring_point;
    size_t *polygon_ring, cap_polygon_ring;
    /* hpfc_limits, 0 fields resolved to the defaults; the points the
     * current call has gathered so far */
    uint64_t max_points, max_items, call_points;
    /* the spatial queries' state, made on first use */
    int64_t (*edge_box)[4];     /* per edge; all zero until computed */
    struct shapes_window *window;
    struct shapes_topo *topo;       /* neighbours.c */
    struct shapes_near *near;       /* nearest.c */
};

typedef struct shapes_window shapes_window;
void shapes_window_free(const hpfc_shapes *s, shapes_window *w);
typedef struct shapes_topo shapes_topo;
void shapes_topo_free(shapes_topo *t);
typedef struct shapes_near shapes_near;
void shapes_near_free(shapes_near *n);

/* The square root of v >= 0 (0 for anything else) to within an ulp: the
 * reader links no libm. Newton's iteration from the exponent halved. */
static inline double shapes_sqrt(double v)
{
    if (!(v > 0) || v > 1e300)
        return v > 1e300 ? v : 0;
    uint64_t b;
    memcpy(&b, &v, sizeof b);
    b = (b >> 1) + (UINT64_C(0x3ff0000000000000) >> 1);
    double r;
    memcpy(&r, &b, sizeof r);
    for (int k = 0; k < 6; k++)
        r = 0.5 * (r + v / r);
    return r;
}

/* A new stamp for face_mark (the stamps cleared when they wrap). Inline:
 * neighbours.c needs it and shapes.c frees neighbours.c's state, and the
 * files of a group may not call each other both ways. */
static inline uint32_t shapes_next_mark(hpfc_shapes *s)
{
    if (++s->mark == 0) {
        memset(s->face_mark, 0, (s->faces + 1) * sizeof *s->face_mark);
        s->mark = 1;
    }
    return s->mark;
}

/* count zeroed elements of `size` bytes that cost nothing until touched
 * (large ones are fresh pages), and their release with the same count and
 * size: the per-edge, per-vertex and per-face arrays, so that creating the
 * object is O(1) however large the map. shapes_edges.c. */
void *shapes_zeroed(size_t count, size_t size);
void shapes_zeroed_free(void *p, size_t count, size_t size);

/* Reads chunk `chunk` of the edges (with their vertices' chunks) or of
 * the vertices; every edge's chunk. HPFC_E_CORRUPT as GEOM's and LABL's
 * reads; the chunk then stays unread. shapes_edges.c. */
int shapes_read_edges(hpfc_shapes *s, uint64_t chunk);
int shapes_read_vertices(hpfc_shapes *s, uint64_t chunk);
int shapes_read_all(hpfc_shapes *s);

/* Edge e's record and its vertices' coordinates read (e below the
 * edges: the caller's check). Every path that takes an edge id from the
 * file or the caller passes here (or through shapes_row) before it reads
 * eu, ev, left, right, first, end or vxy. */
static inline int shapes_need_edge(hpfc_shapes *s, uint64_t e)
{
    return s->edge_read[e >> SHAPES_CHUNK_SHIFT] ? HPFC_OK
                                                 : shapes_read_edges(s, e >> SHAPES_CHUNK_SHIFT);
}

/* Whether table t is there to read (its section is in the file). */
static inline int shapes_has_rows(const hpfc_shapes *s, enum shapes_table t)
{
    return s->rows[t].start || s->rows[t].mapped.bits.base;
}

/* Item j of table t, j in a row shapes_row gave. */
static inline uint32_t shapes_item(const hpfc_shapes *s, enum shapes_table t, uint64_t j)
{
    const shapes_rows *r = &s->rows[t];
    return r->mapped.bits.base ? shix_id(&r->mapped, j) : r->item[j];
}

/* Row `row` of table t as items [*a, *b) (shapes_item), row below the
 * table's rows, the edges of an edge table read (shapes_need_edge):
 * HPFC_OK, or HPFC_E_CORRUPT for a damaged mapped row or edge. */
static inline int shapes_row(hpfc_shapes *s, enum shapes_table t, uint64_t row, uint64_t *a,
                             uint64_t *b)
{
    const shapes_rows *r = &s->rows[t];
    int st = HPFC_OK;
    if (r->mapped.bits.base) {
        /* the face table's ids against LABL's sides, not the edges'
         * records, which may not be read yet */
        shix_inverse of = {.labels = &s->f->labels};
        if (t != FACE_EDGES)
            of = (shix_inverse){.links = t == FEATURE_FACES ? &s->face_links : &s->edge_links};
        st = shix_row(&r->mapped, row, &of, a, b);
    } else {
        *a = r->start[row], *b = r->start[row + 1];
    }
    for (uint64_t j = *a; t != FEATURE_FACES && j < *b && !st; j++)
        st = shapes_need_edge(s, shapes_item(s, t, j));
    return st;
}

/* Whether a feature covers exactly one side of edge e (it is on the
 * feature's border): mark[] stamps the feature's faces with m. */
static inline int shapes_on_border(const hpfc_shapes *s, const uint32_t *mark, uint32_t m,
                                   uint64_t e)
{
    return (mark[s->edge[e].left] == m) != (mark[s->edge[e].right] == m);
}

/* Feature `feature`'s border edges, ascending (hpfc.h, "Topology
 * questions"), into *edges (*n of *cap, grown). neighbours.c. */
int shapes_feature_border(hpfc_shapes *s, hpfc_id feature, uint32_t **edges, size_t *n,
                          size_t *cap);

/* Whether segment a-b meets the closed box (x0, y0, x1, y1), exactly.
 * window.c. */
int shapes_segment_meets(const int64_t a[2], const int64_t b[2], const int64_t box[4]);

/* Edge e's points: u, its shape points, v. */
static inline uint64_t shapes_edge_points(const hpfc_shapes *s, uint64_t e)
{
    return s->edge[e].end - s->edge[e].first + 2;
}

/* Points [from, from + n) of edge e (point 0 is u, the last v) into xy
 * (x, y a point): the vertices from the index, the shape points in one
 * run of GEOM's column, a fraction of their cost point by point.
 * HPFC_E_ARG past the edge's points, HPFC_E_CORRUPT as GEOM's reads.
 * window.c (shapes.c calls window.c, not the other way round). */
int shapes_edge_point_run(const hpfc_shapes *s, uint64_t e, uint64_t from, uint64_t n,
                          int64_t *xy);

/* Each edge's box (x0, y0, x1, y1) over all its points, computed on first
 * use; HPFC_E_CORRUPT on a point that does not read. */
int shapes_edge_box(hpfc_shapes *s, uint64_t edge, const int64_t **box);

/* Counts n more points against the call's max_points: HPFC_OK, or
 * HPFC_E_OVER_LIMIT before the points are read. */
static inline int shapes_take_points(hpfc_shapes *s, uint64_t n)
{
    if (n > s->max_points - s->call_points)
        return HPFC_E_OVER_LIMIT;
    s->call_points += n;
    return HPFC_OK;
}

#endif
