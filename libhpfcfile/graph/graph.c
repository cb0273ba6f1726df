/*
 * graph.c: the planar graph a caller builds (hpfc.h, "Graph"): vertices on
 * the integer lattice, edges with their shape points, the source lines the
 * .pfc reader records, and the accessors. It grows arrays and checks
 * coordinates; whether the graph is a planar embedding is
 * graph_check.c's and validate.c's question.
 */
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

#include "graph.h"

int hpfc_graph_create(hpfc_graph **out)
{
    if (!out)
        return HPFC_E_ARG;
    *out = calloc(1, sizeof **out);
    if (!*out)
        return HPFC_E_NOMEM;
    (*out)->eoff = calloc(1, sizeof(size_t));
    if (!(*out)->eoff) {
        free(*out);
        *out = NULL;
        return HPFC_E_NOMEM;
    }
    return HPFC_OK;
}

/* Frees the graph's arrays, then the graph.
 * (hpfc_graph_free, hpfc_tree_free and hpfc_shapes_free look alike, a free()
 * a member, but each lists the arrays of its own struct.) */
void hpfc_graph_free(hpfc_graph *g)
{
    if (!g)
        return;
    if (g->map) /* the arrays are a graph file's pages */
        munmap(g->map, g->map_len);
    if (g->map || g->map_len) {
        free(g);
        return;
    }
    free(g->vxy);
    free(g->vline);
    free(g->eu);
    free(g->ev);
    free(g->eoff);
    free(g->eline);
    free(g->pts);
    free(g);
}

int hpfc_graph_set_unit_exp10(hpfc_graph *g, int32_t exp10)
{
    if (!g || exp10 < -30 || exp10 > 30)
        return HPFC_E_ARG;
    g->unit_exp10 = exp10;
    return HPFC_OK;
}

int32_t hpfc_graph_unit_exp10(const hpfc_graph *g)
{
    return g ? g->unit_exp10 : 0;
}

/* Capacity after growing `cap` to hold at least `need` elements, or 0 on
 * overflow of `elem`-byte arrays. Not arrays.h's array_reserve: a vertex's
 * coordinates and its source line (an edge's too) are parallel arrays that
 * share one capacity, computed once and applied to each. */
static size_t grown_capacity(size_t cap, size_t need, size_t elem)
{
    size_t ncap = cap ? cap : 16;
    while (ncap < need) {
        if (ncap > SIZE_MAX / 4 / elem)
            return 0;
        ncap *= 2;
    }
    return ncap;
}

/* Reallocates *p to n elements of size elem. */
static int resize(void **p, size_t n, size_t elem)
{
    void *np = realloc(*p, n * elem);
    if (!np)
        return HPFC_E_NOMEM;
    *p = np;
    return HPFC_OK;
}

/* Source lines are kept only once one is set: a graph read from a GIS
 * layer has none, and two zeroed arrays would cost it 8 bytes per vertex
 * and edge. *lines, when there, grows from cap to ncap zero-filled. */
static int resize_lines(uint32_t **lines, size_t cap, size_t ncap)
{
    if (!*lines)
        return HPFC_OK;
    if (resize((void **)lines, ncap, sizeof **lines))
        return HPFC_E_NOMEM;
    memset(*lines + cap, 0, (ncap - cap) * sizeof **lines);
    return HPFC_OK;
}

/* Sets entry i of a line array of cap entries, made on first use. */
static void set_line(uint32_t **lines, size_t cap, size_t i, uint32_t line)
{
    if (!*lines && line)
        *lines = calloc(cap, sizeof **lines);
    if (*lines) /* out of memory: the line is only lost from messages */
        (*lines)[i] = line;
}

/* A graph over a graph file's bytes cannot grow: its arrays are not its own. */
static bool graph_is_file(const hpfc_graph *g)
{
    return g->map || g->map_len;
}

static bool coord_ok(int64_t v)
{
    return v >= -HPFC_COORD_MAX && v <= HPFC_COORD_MAX;
}

int hpfc_graph_add_vertex(hpfc_graph *g, int64_t x, int64_t y, uint32_t *out_index)
{
    if (!g || graph_is_file(g))
        return HPFC_E_ARG;
    if (!coord_ok(x) || !coord_ok(y))
        return HPFC_E_EXTENT;
    if (g->nv >= UINT32_MAX - 1)
        return HPFC_E_LIMIT;
    if (g->nv == g->cap_v) {
        size_t cap = grown_capacity(g->cap_v, g->nv + 1, 2 * sizeof(int64_t));
        if (!cap || resize((void **)&g->vxy, cap, 2 * sizeof(int64_t)) ||
            resize_lines(&g->vline, g->cap_v, cap))
            return HPFC_E_NOMEM;
        g->cap_v = cap;
    }
    g->vxy[2 * g->nv] = x;
    g->vxy[2 * g->nv + 1] = y;
    if (out_index)
        *out_index = (uint32_t)g->nv;
    g->nv++;
    return HPFC_OK;
}

int hpfc_graph_add_edge(hpfc_graph *g, uint32_t u, uint32_t v,
                        const int64_t *interior_xy, size_t n_interior,
                        uint32_t *out_index)
{
    if (!g || graph_is_file(g) || (n_interior && !interior_xy))
        return HPFC_E_ARG;
    if (u >= g->nv || v >= g->nv)
        return HPFC_E_VERTEX_INDEX;
    if (g->ne >= UINT32_MAX - 1 || n_interior > (SIZE_MAX / 64) - g->npts)
        return HPFC_E_LIMIT;
    for (size_t k = 0; k < 2 * n_interior; k++)
        if (!coord_ok(interior_xy[k]))
            return HPFC_E_EXTENT;
    if (g->ne == g->cap_e) {
        size_t cap = grown_capacity(g->cap_e, g->ne + 1, sizeof(size_t));
        if (!cap || resize((void **)&g->eu, cap, sizeof(uint32_t)) ||
            resize((void **)&g->ev, cap, sizeof(uint32_t)) ||
            resize_lines(&g->eline, g->cap_e, cap) ||
            resize((void **)&g->eoff, cap + 1, sizeof(size_t)))
            return HPFC_E_NOMEM;
        g->cap_e = cap;
    }
    if (g->npts + n_interior > g->cap_pts) {
        size_t cap = grown_capacity(g->cap_pts, g->npts + n_interior, 2 * sizeof(int64_t));
        if (!cap || resize((void **)&g->pts, cap, 2 * sizeof(int64_t)))
            return HPFC_E_NOMEM;
        g->cap_pts = cap;
    }
    if (n_interior)
        memcpy(g->pts + 2 * g->npts, interior_xy, 2 * n_interior * sizeof(int64_t));
    g->npts += n_interior;
    g->eu[g->ne] = u;
    g->ev[g->ne] = v;
    g->eoff[g->ne + 1] = g->npts;
    if (out_index)
        *out_index = (uint32_t)g->ne;
    g->ne++;
    return HPFC_OK;
}

void graph_set_last_vertex_line(hpfc_graph *g, uint32_t line)
{
    if (g && g->nv)
        set_line(&g->vline, g->cap_v, g->nv - 1, line);
}

void graph_set_last_edge_line(hpfc_graph *g, uint32_t line)
{
    if (g && g->ne)
        set_line(&g->eline, g->cap_e, g->ne - 1, line);
}

size_t hpfc_graph_vertex_count(const hpfc_graph *g) { return g ? g->nv : 0; }
size_t hpfc_graph_edge_count(const hpfc_graph *g) { return g ? g->ne : 0; }

void hpfc_graph_vertex(const hpfc_graph *g, size_t i, int64_t *x, int64_t *y)
{
    *x = g->vxy[2 * i];
    *y = g->vxy[2 * i + 1];
}

void hpfc_graph_edge(const hpfc_graph *g, size_t i, uint32_t *u, uint32_t *v,
                     const int64_t **interior_xy, size_t *n_interior)
{
    *u = g->eu[i];
    *v = g->ev[i];
    *n_interior = g->eoff[i + 1] - g->eoff[i];
    /* a graph without interior points has no pts array: no NULL + 0 */
    static const int64_t none[2] = {0, 0};
    *interior_xy = g->pts ? g->pts + 2 * g->eoff[i] : none;
}

uint32_t hpfc_graph_vertex_line(const hpfc_graph *g, size_t i)
{
    return graph_vertex_line(g, i);
}
uint32_t hpfc_graph_edge_line(const hpfc_graph *g, size_t i)
{
    return graph_edge_line(g, i);
}
