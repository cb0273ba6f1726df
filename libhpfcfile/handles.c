/*
 * handles.c: the key entry points that complete the key API (hpfc.h,
 * "Graph traversal on an open file"): a leaf's vertices and crossings as
 * keys, a vertex key's degree and darts, and the key forms of the per-dart
 * calls of the faces, LABL and GEOM modules.
 *
 * Why a file of its own: each entry point is the path-form call it mirrors
 * with the key converted on the way in (hpfc_dart_from_key,
 * hpfc_vertex_from_key) and the answer converted on the way out
 * (hpfc_dart_key, hpfc_vertex_key), nothing more. So its answer, status
 * included, is the path form's by construction, and the traversal modules
 * below (topo*.c) keep one implementation of each operator. It sits above
 * topo*.c, faces.c, labels.c and shapes.c and none of them calls it.
 */
#include "topo.h"

/* The key of the dart (vertex) a path-form value names. The value comes
 * from a call that succeeded on it, so its pixel's slot lookup succeeds:
 * the one place here that turns a path into a key. */
static uint64_t dart_key_of(hpfc_walker *w, const hpfc_dart *d)
{
    return hpfc_dart_key(w->file, d);
}

static uint64_t vertex_key_of(hpfc_walker *w, const hpfc_vertex *v)
{
    return hpfc_vertex_key(w->file, v);
}

/* ---- a leaf's vertices and darts as keys ------------------------------------------ */

int hpfc_pixel_vertex_key(hpfc_walker *w, const hpfc_pixel *px, uint32_t index,
                          uint64_t *vertex_key)
{
    if (!w || !vertex_key)
        return HPFC_E_ARG;
    hpfc_vertex v;
    int st = hpfc_pixel_vertex(w, px, index, &v);
    if (!st)
        *vertex_key = vertex_key_of(w, &v);
    return st;
}

int hpfc_pixel_dart_key(hpfc_walker *w, const hpfc_pixel *px, uint32_t crossing,
                        uint64_t *dart_key)
{
    if (!w || !px || !dart_key)
        return HPFC_E_ARG;
    hpfc_dart d = {.pixel = *px, .crossing = crossing};
    hpfc_vertex origin; /* hpfc_dart_origin checks that the crossing is a dart's */
    int st = hpfc_dart_origin(w, &d, &origin);
    if (!st)
        *dart_key = dart_key_of(w, &d);
    return st;
}

/* ---- vertex keys ----------------------------------------------------------------- */

int hpfc_key_degree(hpfc_walker *w, uint64_t vertex_key, uint32_t *degree)
{
    if (!w || !degree)
        return HPFC_E_ARG;
    hpfc_vertex v;
    int st = hpfc_vertex_from_key(w, vertex_key, &v);
    return st ? st : hpfc_vertex_degree(w, &v, degree);
}

/* A dart leaving vertex v has v's pixel, so its key is v's slot with the
 * dart's crossing (spec §3.10): no second slot lookup. */
static uint64_t dart_key_at(uint64_t vertex_key, const hpfc_dart *d)
{
    return (vertex_key & ~(uint64_t)TOPO_KEY_LOW) | d->crossing;
}

int hpfc_key_vertex_dart(hpfc_walker *w, uint64_t vertex_key, uint32_t index, uint64_t *dart_key)
{
    if (!w || !dart_key)
        return HPFC_E_ARG;
    hpfc_vertex v;
    hpfc_dart d;
    int st = hpfc_vertex_from_key(w, vertex_key, &v);
    if (!st)
        st = hpfc_vertex_dart(w, &v, index, &d);
    if (!st)
        *dart_key = dart_key_at(vertex_key, &d);
    return st;
}

int hpfc_key_vertex_darts(hpfc_walker *w, uint64_t vertex_key, uint64_t *darts, size_t cap,
                          uint32_t *degree)
{
    if (!w || !degree)
        return HPFC_E_ARG;
    hpfc_vertex v;
    uint32_t n;
    int st = hpfc_vertex_from_key(w, vertex_key, &v);
    if (!st)
        st = hpfc_vertex_degree(w, &v, &n);
    if (st)
        return st;
    *degree = n;
    if (!darts)
        return HPFC_OK;
    if (cap < n)
        return HPFC_E_BUFFER_SMALL;
    for (uint32_t k = 0; k < n && !st; k++) {
        hpfc_dart d;
        if (!(st = hpfc_vertex_dart(w, &v, k, &d)))
            darts[k] = dart_key_at(vertex_key, &d);
    }
    return st;
}

/* ---- per-dart questions of the other modules -------------------------------------- */

/* The five calls below are the same three lines on purpose: check the
 * arguments, resolve the key, ask the path form. Their path-form calls
 * differ in module, arguments and outputs, so a shared function would
 * only hide the one call each makes. */

int hpfc_faces_of_key(const hpfc_faces *faces, hpfc_walker *w, uint64_t dart_key,
                      uint64_t *face)
{
    if (!faces || !w || !face)
        return HPFC_E_ARG;
    hpfc_dart d;
    int st = hpfc_dart_from_key(w, dart_key, &d);
    return st ? st : hpfc_faces_of_dart(faces, &d, face);
}

int hpfc_key_label_face(hpfc_walker *w, uint64_t dart_key, uint64_t *face)
{
    if (!w || !face)
        return HPFC_E_ARG;
    hpfc_dart d;
    int st = hpfc_dart_from_key(w, dart_key, &d);
    return st ? st : hpfc_label_dart_face(w->file, &d, face);
}

int hpfc_key_label_edge(hpfc_walker *w, uint64_t dart_key, uint64_t *edge)
{
    if (!w || !edge)
        return HPFC_E_ARG;
    hpfc_dart d;
    int st = hpfc_dart_from_key(w, dart_key, &d);
    return st ? st : hpfc_label_dart_edge(w->file, &d, edge);
}

int hpfc_key_geometry_edge(hpfc_walker *w, uint64_t dart_key, uint64_t *edge, int *reversed)
{
    if (!w || !edge || !reversed)
        return HPFC_E_ARG;
    hpfc_dart d;
    int st = hpfc_dart_from_key(w, dart_key, &d);
    return st ? st : hpfc_geometry_dart_edge(w->file, &d, edge, reversed);
}

int hpfc_key_geometry_points(hpfc_walker *w, uint64_t dart_key, int64_t *xy, size_t cap,
                             size_t *count)
{
    if (!w || !count)
        return HPFC_E_ARG;
    hpfc_dart d;
    int st = hpfc_dart_from_key(w, dart_key, &d);
    return st ? st : hpfc_geometry_dart_points(w->file, &d, xy, cap, count);
}
