/*
 * The traversal's public face (hpfc.h, "Traversal"): the walker's life,
 * the dart operators on hpfc_dart values, a pixel's vertices, and leaf
 * iteration. Everything below is the walker's (topo_walk.c); this file
 * only checks arguments and shapes answers. Layers, each calling only
 * those below it: topo.c and topo_keys.c; topo_walk.c; topo_links.c;
 * topo_cache.c; topo_cross.c and topo_index.c; the reader, words.h, road.h.
 */
#include <stdlib.h>
#include <string.h>

#include "file.h"
#include "reader.h"

#include "topo.h"

int hpfc_walker_create(const hpfc_file *file, hpfc_walker **out)
{
    return topo_walker_create(file, HPFC_WALKER_DEFAULT_CACHE, out);
}

int topo_walker_create(const hpfc_file *file, size_t cache_limit, hpfc_walker **out)
{
    if (!file || !out)
        return HPFC_E_ARG;
    *out = NULL;
    hpfc_walker *w = calloc(1, sizeof *w);
    if (!w)
        return HPFC_E_NOMEM;
    w->file = file;
    w->cap = file_max_crossings(file);
    w->budget = file_total_crossings(file) + 1;
    /* a road can border more leaves than the file has crossings (private
     * leaves around a deep refinement), never more than it has leaves */
    w->leaf_budget = file_total_leaves(file) + 1;
    int st = word_parts_alloc(&w->p_word, w->cap);
    if (!st)
        st = word_parts_alloc(&w->q_word, w->cap);
    if (!st && !(w->symbols = malloc((size_t)w->cap + 4)))
        st = HPFC_E_NOMEM;
    if (!st)
        st = topo_cache_init(w, cache_limit);
    if (st == HPFC_E_NOMEM && w->uncached)
        st = HPFC_OK; /* no room for the default cache: walk without it */
    if (st) {
        hpfc_walker_free(w);
        return st;
    }
    *out = w;
    return HPFC_OK;
}

uint64_t hpfc_walker_pixels_visited(const hpfc_walker *w)
{
    return w ? w->visited : 0;
}

void hpfc_walker_free(hpfc_walker *w)
{
    if (!w)
        return;
    word_parts_free(&w->p_word);
    word_parts_free(&w->q_word);
    free(w->symbols);
    topo_cache_free(w);
    topo_index_free(w);
    free(w);
}

int hpfc_dart_twin(hpfc_walker *w, const hpfc_dart *d, hpfc_dart *out)
{
    return out ? topo_dart_op(w, d, TOPO_TWIN, out, NULL) : HPFC_E_ARG;
}

int hpfc_dart_next(hpfc_walker *w, const hpfc_dart *d, hpfc_dart *out)
{
    return out ? topo_dart_op(w, d, TOPO_NEXT, out, NULL) : HPFC_E_ARG;
}

int hpfc_dart_prev(hpfc_walker *w, const hpfc_dart *d, hpfc_dart *out)
{
    return out ? topo_dart_op(w, d, TOPO_PREV, out, NULL) : HPFC_E_ARG;
}

int hpfc_dart_origin(hpfc_walker *w, const hpfc_dart *d, hpfc_vertex *out)
{
    return out ? topo_dart_op(w, d, TOPO_ORIGIN, NULL, out) : HPFC_E_ARG;
}

int hpfc_dart_target(hpfc_walker *w, const hpfc_dart *d, hpfc_vertex *out)
{
    return out ? topo_dart_op(w, d, TOPO_TARGET, NULL, out) : HPFC_E_ARG;
}

/* ---- vertices of a pixel ----------------------------------------------------- */

int hpfc_pixel_vertex_count(hpfc_walker *w, const hpfc_pixel *px, uint32_t *count)
{
    if (!w || !px || !count)
        return HPFC_E_ARG;
    cached_word *e;
    int st = topo_parsed_word(w, px, &e);
    if (!st)
        *count = e->nvert;
    return st;
}

int hpfc_pixel_vertex(hpfc_walker *w, const hpfc_pixel *px, uint32_t index, hpfc_vertex *out)
{
    uint32_t count;
    int st = hpfc_pixel_vertex_count(w, px, &count);
    if (st)
        return st;
    if (index >= count || !out)
        return HPFC_E_ARG;
    out->local = index;
    return topo_copy_pixel(&out->pixel, px);
}

/* A pixel's vertex and dart as keys: its entry records its slot, so no
 * second slot lookup (and the same checks as hpfc_pixel_vertex and
 * hpfc_dart_origin). */
int hpfc_pixel_vertex_key(hpfc_walker *w, const hpfc_pixel *px, uint32_t index,
                          uint64_t *vertex_key)
{
    if (!w || !px || !vertex_key)
        return HPFC_E_ARG;
    cached_word *e;
    int st = topo_parsed_word(w, px, &e);
    if (!st && index >= e->nvert)
        st = HPFC_E_ARG;
    if (!st)
        *vertex_key = topo_key(e->slot, index);
    return st;
}

int hpfc_pixel_dart_key(hpfc_walker *w, const hpfc_pixel *px, uint32_t crossing,
                        uint64_t *dart_key)
{
    if (!w || !px || !dart_key)
        return HPFC_E_ARG;
    cached_word *e;
    int st = topo_parsed_word(w, px, &e);
    if (!st && (crossing >= e->n || word_crossings(e)[crossing].vertex == TOPO_NONE))
        st = HPFC_E_ARG;
    if (!st)
        *dart_key = topo_key(e->slot, crossing);
    return st;
}

/* The parsed word of a vertex's pixel, and the vertex in it. */
static int load_vertex(hpfc_walker *w, const hpfc_vertex *v, cached_word **e, cached_vertex *out)
{
    int st = topo_parsed_word(w, &v->pixel, e);
    if (!st && v->local >= (*e)->nvert)
        st = HPFC_E_ARG;
    if (!st)
        *out = word_vertices(*e)[v->local];
    return st;
}

/* A vertex's degree and darts; topo_keys.c's hpfc_key_degree and
 * hpfc_key_vertex_dart(s) are the same reads reached by the key's slot. */
int hpfc_vertex_degree(hpfc_walker *w, const hpfc_vertex *v, uint32_t *degree)
{
    if (!w || !v || !degree)
        return HPFC_E_ARG;
    cached_word *e;
    cached_vertex cv;
    int st = load_vertex(w, v, &e, &cv);
    if (!st)
        *degree = cv.degree;
    return st;
}

int hpfc_vertex_dart(hpfc_walker *w, const hpfc_vertex *v, uint32_t index, hpfc_dart *out)
{
    if (!w || !v || !out)
        return HPFC_E_ARG;
    cached_word *e;
    cached_vertex cv;
    int st = load_vertex(w, v, &e, &cv);
    if (st)
        return st;
    if (index >= cv.degree)
        return HPFC_E_ARG;
    out->crossing = vertex_dart_crossing(e, cv, index);
    return topo_copy_pixel(&out->pixel, &v->pixel);
}

/* ---- leaf iteration ------------------------------------------------------ */

int topo_first_leaf_below(const hpfc_file *f, hpfc_pixel *px)
{
    for (;;) {
        int type, st = hpfc_pixel_type(f, px, &type);
        if (st || type == HPFC_PIXEL_WORD)
            return st;
        if ((st = hpfc_pixel_child(f, px, 0, 0, px)))
            return st;
    }
}

int hpfc_leaf_first(const hpfc_file *f, hpfc_pixel *px)
{
    if (!f || !px)
        return HPFC_E_ARG;
    int st = hpfc_pixel_root(f, 0, 0, px);
    return st ? st : topo_first_leaf_below(f, px);
}

int hpfc_leaf_next(const hpfc_file *f, hpfc_pixel *px)
{
    if (!f || !px || px->depth >= HPFC_MAX_LEVELS)
        return HPFC_E_ARG;
    hpfc_file_info info;
    hpfc_file_get_info(f, &info);
    for (;;) {
        uint32_t d = px->depth;
        uint32_t cols = d ? info.cols : info.root_cols, rows = d ? info.rows : info.root_rows;
        uint32_t i = px->path[d].i, j = px->path[d].j;
        if (i + 1 < cols || j + 1 < rows) {
            i = i + 1 < cols ? i + 1 : 0;
            j = i == 0 ? j + 1 : j;
            int st;
            if (d == 0) {
                st = hpfc_pixel_root(f, i, j, px);
            } else {
                hpfc_pixel parent;
                st = hpfc_pixel_parent(px, &parent);
                if (!st)
                    st = hpfc_pixel_child(f, &parent, i, j, px);
            }
            return st ? st : topo_first_leaf_below(f, px);
        }
        if (d == 0)
            return HPFC_E_NO_PIXEL;
        px->depth--;
    }
}
