/*
 * handles.c: the key forms of the per-dart calls of the faces, LABL and
 * GEOM modules (hpfc_faces_key_face, hpfc_label_key_face, ...); the
 * traversal's own key calls are topo_keys.c's and topo.c's.
 *
 * Why a file of its own: each entry point is the path-form call it mirrors
 * with the key converted on the way in (hpfc_dart_from_key), nothing
 * more. So its answer, status included, is the path form's by
 * construction, and the modules below keep one implementation of each
 * question. It sits above topo*.c, faces.c, labels.c and shapes.c and none
 * of them calls it.
 */
#include "topo.h"

/* The five calls are the same three lines on purpose: check the
 * arguments, resolve the key, ask the path form. Their path-form calls
 * differ in module, arguments and outputs, so a shared function would
 * only hide the one call each makes. */

int hpfc_faces_key_face(const hpfc_faces *faces, hpfc_walker *w, uint64_t dart_key,
                        uint64_t *face)
{
    if (!faces || !w || !face)
        return HPFC_E_ARG;
    hpfc_dart d;
    int st = hpfc_dart_from_key(w, dart_key, &d);
    return st ? st : hpfc_faces_dart_face(faces, &d, face);
}

int hpfc_label_key_face(hpfc_walker *w, uint64_t dart_key, uint64_t *face)
{
    if (!w || !face)
        return HPFC_E_ARG;
    hpfc_dart d;
    int st = hpfc_dart_from_key(w, dart_key, &d);
    return st ? st : hpfc_label_dart_face(w->file, &d, face);
}

int hpfc_label_key_edge(hpfc_walker *w, uint64_t dart_key, uint64_t *edge)
{
    if (!w || !edge)
        return HPFC_E_ARG;
    hpfc_dart d;
    int st = hpfc_dart_from_key(w, dart_key, &d);
    return st ? st : hpfc_label_dart_edge(w->file, &d, edge);
}

int hpfc_geometry_key_edge(hpfc_walker *w, uint64_t dart_key, uint64_t *edge, int *reversed)
{
    if (!w || !edge || !reversed)
        return HPFC_E_ARG;
    hpfc_dart d;
    int st = hpfc_dart_from_key(w, dart_key, &d);
    return st ? st : hpfc_geometry_dart_edge(w->file, &d, edge, reversed);
}

int hpfc_geometry_key_points(hpfc_walker *w, uint64_t dart_key, int64_t *xy, size_t cap,
                             size_t *count)
{
    if (!w || !count)
        return HPFC_E_ARG;
    hpfc_dart d;
    int st = hpfc_dart_from_key(w, dart_key, &d);
    return st ? st : hpfc_geometry_dart_points(w->file, &d, xy, cap, count);
}
