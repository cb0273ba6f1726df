/*
 * ragged.c: see ragged.h. Nothing here computes geometry: it copies the
 * library's answers and offsets them into the arrays of many items.
 */
#include "ragged.h"

#include <stdlib.h>
#include <string.h>

/* Room for `more` values past the end, capacity doubled; -1 when the size
 * would overflow or realloc fails. */
static int reserve(ragged_i64s *a, size_t more)
{
    if (more > SIZE_MAX / sizeof *a->v - a->n)
        return -1;
    size_t need = a->n + more;
    if (need <= a->cap)
        return 0;
    size_t c = a->cap ? a->cap : 256;
    while (c < need)
        c = c > SIZE_MAX / sizeof *a->v / 2 ? need : 2 * c;
    int64_t *p = realloc(a->v, c * sizeof *p);
    if (!p)
        return -1;
    a->v = p, a->cap = c;
    return 0;
}

static int put(ragged_i64s *a, int64_t x)
{
    if (reserve(a, 1))
        return -1;
    a->v[a->n++] = x;
    return 0;
}

static int put_points(ragged_i64s *xy, const int64_t *src, size_t points)
{
    if (points > SIZE_MAX / 2 || reserve(xy, 2 * points))
        return -1;
    if (points)
        memcpy(xy->v + xy->n, src, 2 * points * sizeof *src);
    xy->n += 2 * points;
    return 0;
}

int ragged_start(ragged *r, int polygons)
{
    memset(r, 0, sizeof *r);
    return put(&r->part, 0) || (polygons && put(&r->polygon, 0)) || put(&r->ring, 0)
               ? HPFC_E_NOMEM
               : HPFC_OK;
}

void ragged_free(ragged *r)
{
    free(r->part.v);
    free(r->polygon.v);
    free(r->ring.v);
    free(r->xy.v);
    free(r->hole_only.v);
    memset(r, 0, sizeof *r);
}

/* The library answer's rings, offset past the points already stored. */
static int add_rings(ragged *r, const hpfc_polygons *p)
{
    int64_t base = (int64_t)(r->xy.n / 2);
    if (put_points(&r->xy, p->xy, p->point_count))
        return -1;
    for (size_t k = 0; k < p->ring_count; k++)
        if (put(&r->ring, base + (int64_t)p->ring_point[k + 1]))
            return -1;
    return 0;
}

/* One answer: its polygons (outer ring, holes), then each unplaced hole as
 * a polygon of its own. */
static int add_polygons(ragged *r, const hpfc_polygons *p)
{
    int64_t rbase = (int64_t)r->ring.n - 1;
    if (add_rings(r, p))
        return -1;
    for (size_t k = 0; k < p->polygon_count; k++)
        if (put(&r->polygon, rbase + (int64_t)p->polygon_ring[k + 1]) || put(&r->hole_only, 0))
            return -1;
    for (size_t k = p->polygon_ring[p->polygon_count]; k < p->ring_count; k++)
        if (put(&r->polygon, rbase + (int64_t)k + 1) || put(&r->hole_only, 1))
            return -1;
    return put(&r->part, (int64_t)r->polygon.n - 1);
}

/* Lines (hpfc_shapes_feature_polylines): rings as polylines. */
static int add_lines(ragged *r, const hpfc_polygons *p)
{
    return add_rings(r, p) || put(&r->part, (int64_t)r->ring.n - 1);
}

/* Ends the polyline whose points were just stored. */
static int close_line(ragged *r)
{
    return put(&r->ring, (int64_t)(r->xy.n / 2)) || put(&r->part, (int64_t)r->ring.n - 1);
}

static int add_edge(ragged *r, const hpfc_file *f, uint64_t e)
{
    uint64_t u, v, n;
    int st = hpfc_geometry_edge(f, e, &u, &v, &n);
    if (st)
        return st;
    if (n > SIZE_MAX / 2 || reserve(&r->xy, 2 * (size_t)n))
        return HPFC_E_NOMEM;
    for (uint64_t k = 0; k < n; k++) {
        int64_t *xy = r->xy.v + r->xy.n;
        if ((st = hpfc_geometry_edge_point(f, e, k, &xy[0], &xy[1])))
            return st;
        r->xy.n += 2;
    }
    return close_line(r) ? HPFC_E_NOMEM : HPFC_OK;
}

static int add_dart(ragged *r, hpfc_walker *w, uint64_t key)
{
    size_t n = 0, got = 0;
    if (!w)
        return HPFC_E_ARG;
    int st = hpfc_geometry_key_points(w, key, NULL, 0, &n);
    if (st)
        return st;
    if (n > SIZE_MAX / 2 || reserve(&r->xy, 2 * n))
        return HPFC_E_NOMEM;
    if ((st = hpfc_geometry_key_points(w, key, r->xy.v + r->xy.n, n, &got)))
        return st;
    if (got != n)
        return HPFC_E_CORRUPT;
    r->xy.n += 2 * n;
    return close_line(r) ? HPFC_E_NOMEM : HPFC_OK;
}

int ragged_add(ragged *r, const ragged_source *src, int kind, uint64_t id)
{
    hpfc_polygons p;
    int st;
    switch (kind) {
    case RAGGED_FACE:
        if (!src->shapes)
            return HPFC_E_ARG;
        if ((st = hpfc_shapes_face_polygons(src->shapes, id, &p)))
            return st;
        return add_polygons(r, &p) ? HPFC_E_NOMEM : HPFC_OK;
    case RAGGED_FEATURE:
    case RAGGED_FEATURE_LINES:
        if (!src->shapes)
            return HPFC_E_ARG;
        st = kind == RAGGED_FEATURE ? hpfc_shapes_feature_polygons(src->shapes, id, &p)
                                    : hpfc_shapes_feature_polylines(src->shapes, id, &p);
        if (st)
            return st;
        return (kind == RAGGED_FEATURE ? add_polygons(r, &p) : add_lines(r, &p)) ? HPFC_E_NOMEM
                                                                                  : HPFC_OK;
    case RAGGED_EDGE:
        return add_edge(r, src->file, id);
    case RAGGED_DART:
        return add_dart(r, src->walker, id);
    default:
        return HPFC_E_ARG;
    }
}
