/*
 * hpfc_geometry_verify: the GEOM section against itself and the map
 * (spec/hpfc-format.md §6.6.6), for hpfc-inspect --verify:
 *
 *   0. the padding between and after the parts is zero;
 *   1. every vertex, edge and shape point reads (ids and ranges in bounds,
 *      coordinates inside the domain);
 *   2. the coordinates make a valid planar graph (hpfc_graph_validate on a
 *      copy): no crossing or touching edges, no duplicate point;
 *   3. every leaf holds as many vertices (located by their coordinates) as
 *      its word has junctions;
 *   4. with LABL: every crossing's segment (of the edge LABL names) crosses
 *      the crossing's road, the crossings of each road lie in the word's
 *      order along it (perturbation rule G2-G5), and the face on the right
 *      of each crossing's out-dart is the side hpfc_geometry_edge_faces
 *      gives for the way u -> v runs there.
 *
 * The first disagreement is reported, never trusted. O(file), plus the
 * planarity check's O(n log n).
 */
#include <stdlib.h>
#include <string.h>

#include "road.h"
#include "geometry.h"
#include "graph.h"
#include "file.h"
#include "labels.h"
#include "verify_report.h"

/* The first disagreement, into the report: HPFC_E_CORRUPT. */
#define problem(r, ...) verify_message((r)->message, sizeof (r)->message, __VA_ARGS__)

/* The section as a graph (step 1 on the way), then step 2. */
static int check_graph(const hpfc_file *f, const geom_view *g, hpfc_geometry_report *r)
{
    hpfc_graph *gr = NULL;
    int st = hpfc_graph_create(&gr);
    hpfc_file_info fi;
    hpfc_file_get_info(f, &fi);
    hpfc_graph_set_unit_exp10(gr, fi.unit_exp10);
    for (uint64_t v = 0; !st && v < g->vertices; v++) {
        int64_t x, y;
        if ((st = hpfc_geometry_vertex(f, v, &x, &y)))
            st = problem(r, "vertex %llu: %s", (unsigned long long)v, hpfc_strerror(st));
        else if ((st = hpfc_graph_add_vertex(gr, x, y, NULL)))
            st = problem(r, "vertex %llu lies beyond the lattice's range", (unsigned long long)v);
    }
    int64_t *xy = NULL;
    size_t cap = 0;
    for (uint64_t e = 0; !st && e < g->edges; e++) {
        uint64_t u, v, n;
        if ((st = hpfc_geometry_edge(f, e, &u, &v, &n))) {
            st = problem(r, "edge %llu: %s", (unsigned long long)e, hpfc_strerror(st));
            break;
        }
        if (n > cap) {
            cap = n;
            int64_t *grown = cap <= SIZE_MAX / 16 ? realloc(xy, cap * 16) : NULL;
            if (!grown) {
                st = HPFC_E_NOMEM;
                break;
            }
            xy = grown;
        }
        if ((st = geom_edge_points(f, e, xy)))
            st = problem(r, "edge %llu's points: %s", (unsigned long long)e, hpfc_strerror(st));
        /* the shape points between u and v */
        if (!st && (st = hpfc_graph_add_edge(gr, (uint32_t)u, (uint32_t)v, xy + 2,
                                             (size_t)(n - 2), NULL)))
            st = problem(r, "edge %llu: %s", (unsigned long long)e, hpfc_strerror(st));
    }
    free(xy);
    hpfc_diag diag;
    if (!st && (st = hpfc_graph_validate(gr, &diag)))
        st = st == HPFC_E_NOMEM ? st : problem(r, "the geometry is not a planar map: %s", diag.message);
    hpfc_graph_free(gr);
    return st;
}

/* A leaf's word, grown as needed. */
typedef struct word_buf {
    char *sym;
    size_t len, cap;
} word_buf;

static int read_word(const hpfc_file *f, const hpfc_pixel *px, word_buf *w)
{
    int st = hpfc_pixel_word(f, px, NULL, 0, &w->len);
    if (st)
        return st;
    if (w->len > w->cap) {
        char *grown = realloc(w->sym, w->len);
        if (!grown)
            return HPFC_E_NOMEM;
        w->sym = grown;
        w->cap = w->len;
    }
    return hpfc_pixel_word(f, px, w->sym, w->cap, &w->len);
}

/* Step 3: vertices per leaf, by their global leaf number. */
static int count_vertices(const hpfc_file *f, const geom_view *g, uint32_t *per_leaf,
                          uint64_t leaves, hpfc_geometry_report *r)
{
    for (uint64_t v = 0; v < g->vertices; v++) {
        int64_t x, y;
        hpfc_pixel px;
        uint64_t rank;
        int st = hpfc_geometry_vertex(f, v, &x, &y);
        if (!st)
            st = hpfc_locate(f, x, y, &px);
        if (!st)
            st = labels_leaf_rank(f, &px, &rank);
        if (st)
            return st == HPFC_E_NOMEM ? st
                                      : problem(r, "vertex %llu: no leaf holds it (%s)",
                                                (unsigned long long)v, hpfc_strerror(st));
        uint64_t at = g->first_leaf[px.depth] + rank;
        if (at >= leaves)
            return problem(r, "vertex %llu: its leaf's number is out of range", (unsigned long long)v);
        if (per_leaf[at]++ == UINT32_MAX - 1)
            return problem(r, "too many vertices in one leaf");
    }
    return HPFC_OK;
}

/* Step 4 on one crossing: its segment crosses road `road` of the cell at
 * *pos, and its out-dart has the right face. */
static int check_crossing(const hpfc_file *f, const geom_view *g, const hpfc_pixel *px,
                          uint32_t k, int road, const int64_t cell[4], line_pos *pos,
                          hpfc_geometry_report *r)
{
    hpfc_file_info fi;
    hpfc_file_get_info(f, &fi);
    uint64_t edge, seg, left, right, face;
    int64_t ax, ay, bx, by;
    int st = hpfc_label_crossing_edge(f, px, k, &edge);
    if (!st)
        st = hpfc_geometry_crossing_segment(f, px, k, &seg);
    if (!st)
        st = hpfc_geometry_edge_point(f, edge, seg, &ax, &ay);
    if (!st)
        st = hpfc_geometry_edge_point(f, edge, seg + 1, &bx, &by);
    if (!st)
        st = hpfc_geometry_edge_faces(f, edge, &left, &right);
    hpfc_dart d = {.pixel = *px, .crossing = k};
    if (!st)
        st = hpfc_label_dart_face(f, &d, &face);
    if (st)
        return st == HPFC_E_NOMEM ? st
                                  : problem(r, "leaf at depth %u, crossing %u: %s", px->depth, k,
                                            hpfc_strerror(st));
    (void)g;
    lpoint a = {ax - fi.x0, ay - fi.y0}, b = {bx - fi.x0, by - fi.y0};
    bool entering;
    if (!cross_road(a, b, road, cell[0] - fi.x0, cell[1] - fi.y0, cell[2] - fi.x0,
                    cell[3] - fi.y0, pos, &entering))
        return problem(r, "crossing %u of the leaf at (%lld, %lld): segment %llu of edge %llu "
                          "does not cross its road",
                       k, (long long)cell[0], (long long)cell[1], (unsigned long long)seg,
                       (unsigned long long)edge);
    /* the out-dart runs u -> v where u -> v leaves the cell */
    if (face != (entering ? left : right))
        return problem(r, "edge %llu: the face on its %s is %llu, the labels say %llu",
                       (unsigned long long)edge, entering ? "left" : "right",
                       (unsigned long long)(entering ? left : right), (unsigned long long)face);
    return HPFC_OK;
}

/* Steps 3 and 4 on one leaf. */
static int check_leaf(const hpfc_file *f, const geom_view *g, const hpfc_pixel *px,
                      const uint32_t *per_leaf, uint64_t leaves, word_buf *w, bool labels,
                      hpfc_geometry_report *r)
{
    uint64_t rank;
    int64_t cell[4];
    int st = labels_leaf_rank(f, px, &rank);
    if (!st)
        st = read_word(f, px, w);
    if (!st)
        st = hpfc_pixel_bounds(f, px, &cell[0], &cell[1], &cell[2], &cell[3]);
    if (st)
        return st == HPFC_E_NOMEM ? st : problem(r, "a leaf: %s", hpfc_strerror(st));
    uint32_t junctions = 0;
    for (size_t s = 0; s < w->len; s++)
        junctions += w->sym[s] == '(' || w->sym[s] == '=';
    if (g->first_leaf[px->depth] + rank >= leaves)
        return problem(r, "a leaf's number is out of range");
    uint32_t held = per_leaf[g->first_leaf[px->depth] + rank];
    if (held != junctions)
        return problem(r, "the leaf at (%lld, %lld), depth %u, holds %u vertices, its word %u "
                          "junctions",
                       (long long)cell[0], (long long)cell[1], px->depth, held, junctions);
    if (!labels)
        return HPFC_OK;
    int road = 0;
    line_pos prev = {0, 1, 0};
    bool has_prev = false;
    for (size_t s = 0, k = 0; s < w->len; s++) {
        if (w->sym[s] == '+') {
            road++;
            has_prev = false;
            continue;
        }
        line_pos pos = {0, 1, 0};
        if (road > 3)
            return problem(r, "a word with a crossing after its fourth '+'");
        if ((st = check_crossing(f, g, px, (uint32_t)k, road, cell, &pos, r)))
            return st;
        /* W and N list their crossings going north and east, E and S back */
        int order = cmp_line_pos(&prev, &pos);
        if (has_prev && (road == HPFC_WEST || road == HPFC_NORTH ? order >= 0 : order <= 0))
            return problem(r, "crossings %zu and %zu of the leaf at (%lld, %lld) are out of "
                              "order along their road",
                           k - 1, k, (long long)cell[0], (long long)cell[1]);
        prev = pos;
        has_prev = true;
        k++;
        r->crossings_checked++;
    }
    return HPFC_OK;
}

int hpfc_geometry_verify(const hpfc_file *f, hpfc_geometry_report *r)
{
    if (!f || !r)
        return HPFC_E_ARG;
    memset(r, 0, sizeof *r);
    const geom_view *g = &f->geom;
    if (!g->present)
        return HPFC_E_NO_SECTION;
    uint64_t at;
    if (!geom_padding_zero(g, &at))
        return problem(r, "byte %llu of the section is padding but not zero", (unsigned long long)at);
    int st = check_graph(f, g, r);
    if (st)
        return st;
    uint64_t leaves = file_total_leaves(f);
    uint32_t *per_leaf = calloc(leaves ? leaves : 1, sizeof *per_leaf);
    if (!per_leaf)
        return HPFC_E_NOMEM;
    st = count_vertices(f, g, per_leaf, leaves, r);
    r->vertices_checked = st ? 0 : g->vertices;
    bool labels = f->labels.present;
    word_buf w = {0};
    hpfc_pixel px;
    uint64_t seen = 0;
    int it;
    for (it = hpfc_leaf_first(f, &px); !st && !it; it = hpfc_leaf_next(f, &px)) {
        if (++seen > leaves)
            st = problem(r, "more leaves than the level table declares");
        else
            st = check_leaf(f, g, &px, per_leaf, leaves, &w, labels, r);
    }
    if (!st && it != HPFC_E_NO_PIXEL)
        st = it == HPFC_E_NOMEM ? it : problem(r, "the leaves: %s", hpfc_strerror(it));
    free(w.sym);
    free(per_leaf);
    return st;
}
