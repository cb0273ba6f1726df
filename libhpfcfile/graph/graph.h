/* graph.h: the graph as the library holds it (struct hpfc_graph, its
 * accessors, the source lines the .pfc reader records) and the checks every
 * graph input shares. Internal to the library (and its tests and
 * fuzzers). */
#ifndef HPFC_GRAPH_H
#define HPFC_GRAPH_H

#include <stdbool.h>

#include "diag.h"
#include "hpfc.h"

struct hpfc_graph {
    int32_t unit_exp10;
    size_t nv, cap_v;
    int64_t *vxy;          /* 2 per vertex */
    uint32_t *vline;       /* source line per vertex, NULL until one is set */
    size_t ne, cap_e;
    uint32_t *eu, *ev;     /* end vertices */
    size_t *eoff;          /* interior points of edge e: pts[eoff[e] .. eoff[e+1]) */
    uint32_t *eline;       /* source line per edge, NULL until one is set */
    size_t npts, cap_pts;
    int64_t *pts;          /* 2 per interior point */
    /* a graph file's mapping (graph_file.c), which the arrays point into;
     * NULL for a graph that owns its arrays */
    void *map;
    size_t map_len;
};

/* Source line of vertex v / edge e, 0 if unknown (the arrays exist only
 * once a line was set). */
static inline uint32_t graph_vertex_line(const hpfc_graph *g, size_t v)
{
    return g->vline ? g->vline[v] : 0;
}

static inline uint32_t graph_edge_line(const hpfc_graph *g, size_t e)
{
    return g->eline ? g->eline[e] : 0;
}

/* Number of points of edge e, ends included. */
static inline size_t graph_edge_point_count(const hpfc_graph *g, size_t e)
{
    return g->eoff[e + 1] - g->eoff[e] + 2;
}

/* Point k (0 = u, last = v) of edge e. */
static inline void graph_edge_point(const hpfc_graph *g, size_t e, size_t k,
                                    int64_t *x, int64_t *y)
{
    size_t last = graph_edge_point_count(g, e) - 1;
    const int64_t *p;
    if (k == 0)
        p = g->vxy + 2 * (size_t)g->eu[e];
    else if (k == last)
        p = g->vxy + 2 * (size_t)g->ev[e];
    else
        p = g->pts + 2 * (g->eoff[e] + k - 1);
    *x = p[0];
    *y = p[1];
}

/* Records the 1-based source line of the last vertex / edge added (the
 * .pfc reader's), so that diagnostics can name it. */
void graph_set_last_vertex_line(hpfc_graph *g, uint32_t line);
void graph_set_last_edge_line(hpfc_graph *g, uint32_t line);

/* A graph over a graph file's bytes (hpfc_graph_map_file's checks), its
 * arrays pointing into them: the caller keeps the bytes until the graph is
 * freed (which frees neither), and sets map to have them unmapped. */
int graph_from_file_bytes(const void *bytes, size_t length, hpfc_graph **out, hpfc_diag *diag);

/* The whole-graph checks both the .pfc reader and hpfc_graph_validate run
 * (graph_check.c): two points at one place (vertices only, or interior
 * points too) is HPFC_E_DUPLICATE_POINT, a vertex no edge uses
 * HPFC_E_ISOLATED_VERTEX; diag names the culprit (its line, its point) and
 * the message starts with "line N: " when the graph knows N. */
int graph_check_duplicates(const hpfc_graph *g, bool interior, hpfc_diag *diag);
int graph_check_isolated(const hpfc_graph *g, hpfc_diag *diag);

/* hpfc_graph_validate with planarity's cells searched on up to `threads`
 * threads (0 or 1: the caller's alone): the same status and message. */
int graph_validate_threads(const hpfc_graph *g, unsigned threads, hpfc_diag *diag);

#endif
