/*
 * The GEOM section (spec/hpfc-format.md §6.6) against the input graph:
 *   - every vertex's coordinates, every edge's end vertices and every
 *     point of every edge read back equal the graph's;
 *   - every crossing of every leaf: a naive reference lists, road by road,
 *     every segment of every edge of the graph that crosses the road, in
 *     the order of the perturbation rule (G2-G5); the crossing's segment
 *     (hpfc_geometry_crossing_segment) and edge (LABL) must be the k-th;
 *   - the faces left and right of every edge: at each of its crossings,
 *     the flood fill's face of the out-dart (hpfc_faces_build) is the face
 *     on the right of u -> v when u -> v leaves the leaf there, on its left
 *     when it enters;
 *   - hpfc_geometry_verify accepts every map written;
 *   - ids out of range, a file without the section, and the section kept
 *     by hpfc_file_serialize;
 *   - a section larger than the writer's stream buffers: written to a file
 *     (streamed) and to memory, the same bytes, and each of the graph's
 *     columns cut into the blocks a naive search over every block size
 *     finds smallest.
 * On generated straight and polyline graphs and the special graphs, under
 * several image sizes, flat and deep, on both pool layouts.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "gen.h"
#include "road.h"
#include "geometry.h"
#include "hpfc.h"

typedef struct packed {
    uint8_t *with, *without;
    hpfc_file *f, *f0;
} packed;

static int pack(const hpfc_graph *g, uint32_t n0, uint32_t n, int flat, packed *p)
{
    memset(p, 0, sizeof *p);
    hpfc_build_params bp;
    hpfc_build_params_default(&bp);
    bp.root_cols = bp.root_rows = n0;
    bp.cols = bp.rows = n;
    bp.flat = flat;
    size_t s1, s0;
    hpfc_tree *tree = NULL;
    hpfc_write_options o = {.face_labels = 1, .geometry = g};
    hpfc_write_options o0 = {.face_labels = 1};
    int st = hpfc_build(g, &bp, &tree, NULL);
    if (!st)
        st = check_tree_serialize(tree, &o, &p->with, &s1, NULL);
    if (!st)
        st = check_tree_serialize(tree, &o0, &p->without, &s0, NULL);
    if (!st)
        st = hpfc_open_memory(p->with, s1, 0, &p->f);
    if (!st)
        st = hpfc_open_memory(p->without, s0, 0, &p->f0);
    hpfc_tree_free(tree);
    return st;
}

static void unpack(packed *p)
{
    hpfc_close(p->f);
    hpfc_close(p->f0);
    hpfc_free(p->with);
    hpfc_free(p->without);
}

/* Coordinates and edges against the graph. */
static void check_points(const hpfc_file *f, const hpfc_graph *g)
{
    hpfc_geometry_info gi;
    CHECK_EQ_INT(hpfc_file_get_geometry(f, &gi), HPFC_OK);
    size_t nv = hpfc_graph_vertex_count(g), ne = hpfc_graph_edge_count(g), npts = 0;
    CHECK_EQ_INT(gi.vertices, nv);
    CHECK_EQ_INT(gi.edges, ne);
    for (size_t v = 0; v < nv; v++) {
        int64_t x = 0, y = 0, gx, gy;
        hpfc_graph_vertex(g, v, &gx, &gy);
        CHECK_EQ_INT(hpfc_geometry_vertex(f, v, &x, &y), HPFC_OK);
        if (x != gx || y != gy) {
            CHECK_EQ_INT(x, gx);
            CHECK_EQ_INT(y, gy);
            break;
        }
    }
    int64_t x, y;
    CHECK_EQ_INT(hpfc_geometry_vertex(f, nv, &x, &y), HPFC_E_ARG);
    int bad = 0;
    for (size_t e = 0; e < ne && bad < 3; e++) {
        uint32_t gu, gv;
        const int64_t *xy;
        size_t ni;
        hpfc_graph_edge(g, e, &gu, &gv, &xy, &ni);
        npts += ni;
        uint64_t u = 0, v = 0, count = 0;
        CHECK_EQ_INT(hpfc_geometry_edge(f, e, &u, &v, &count), HPFC_OK);
        bad += u != gu || v != gv || count != ni + 2;
        CHECK_EQ_INT(u, gu);
        CHECK_EQ_INT(v, gv);
        CHECK_EQ_INT(count, ni + 2);
        for (uint64_t k = 0; k < count && count == ni + 2; k++) {
            int64_t wx, wy;
            if (k == 0 || k == count - 1)
                hpfc_graph_vertex(g, k ? gv : gu, &wx, &wy);
            else
                wx = xy[2 * (k - 1)], wy = xy[2 * (k - 1) + 1];
            CHECK_EQ_INT(hpfc_geometry_edge_point(f, e, k, &x, &y), HPFC_OK);
            if (x != wx || y != wy) {
                CHECK_EQ_INT(x, wx);
                CHECK_EQ_INT(y, wy);
                bad++;
                break;
            }
        }
        CHECK_EQ_INT(hpfc_geometry_edge_point(f, e, ni + 2, &x, &y), HPFC_E_ARG);
    }
    CHECK_EQ_INT(gi.points, npts);
    /* the box of every vertex and shape point, against the graph's */
    int64_t want[4] = {INT64_MAX, INT64_MAX, INT64_MIN, INT64_MIN}, box[4] = {0, 0, 0, 0};
    for (size_t k = 0; k < nv; k++) {
        int64_t gx, gy;
        hpfc_graph_vertex(g, k, &gx, &gy);
        want[0] = gx < want[0] ? gx : want[0], want[1] = gy < want[1] ? gy : want[1];
        want[2] = gx > want[2] ? gx : want[2], want[3] = gy > want[3] ? gy : want[3];
    }
    for (size_t e = 0; e < ne; e++) {
        uint32_t gu, gv;
        const int64_t *xy;
        size_t ni;
        hpfc_graph_edge(g, e, &gu, &gv, &xy, &ni);
        for (size_t k = 0; k < ni; k++) {
            want[0] = xy[2 * k] < want[0] ? xy[2 * k] : want[0];
            want[1] = xy[2 * k + 1] < want[1] ? xy[2 * k + 1] : want[1];
            want[2] = xy[2 * k] > want[2] ? xy[2 * k] : want[2];
            want[3] = xy[2 * k + 1] > want[3] ? xy[2 * k + 1] : want[3];
        }
    }
    CHECK_EQ_INT(hpfc_geometry_bounds(f, box), HPFC_OK);
    for (int k = 0; k < 4; k++)
        CHECK_EQ_INT(box[k], want[k]);
    CHECK_EQ_INT(hpfc_geometry_bounds(f, NULL), HPFC_E_ARG);
    uint64_t u, v, c;
    CHECK_EQ_INT(hpfc_geometry_edge(f, ne, &u, &v, &c), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_geometry_edge_point(f, ne, 0, &x, &y), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_geometry_edge_faces(f, ne, &u, &v), HPFC_E_ARG);
}

/* The naive reference: every (edge, segment) of the graph crossing road
 * `road` of the cell, in the word's order along it. */
typedef struct ref_cross {
    uint64_t edge, seg;
    line_pos pos;
    int road;
} ref_cross;

static int cmp_ref(const void *a, const void *b)
{
    const ref_cross *x = a, *y = b;
    int c = cmp_line_pos(&x->pos, &y->pos);
    /* W and N run with the line (north, east), E and S against it */
    return x->road == HPFC_WEST || x->road == HPFC_NORTH ? c : -c;
}

static size_t reference_crossings(const hpfc_graph *g, int64_t ox, int64_t oy, int64_t x0,
                                  int64_t y0, int64_t x1, int64_t y1, ref_cross *out, size_t cap)
{
    size_t n = 0;
    for (int road = 0; road < 4; road++) {
        size_t first = n;
        for (size_t e = 0; e < hpfc_graph_edge_count(g); e++) {
            uint32_t u, v;
            const int64_t *xy;
            size_t ni;
            hpfc_graph_edge(g, e, &u, &v, &xy, &ni);
            for (size_t s = 0; s <= ni; s++) {
                int64_t ax, ay, bx, by;
                if (s == 0)
                    hpfc_graph_vertex(g, u, &ax, &ay);
                else
                    ax = xy[2 * (s - 1)], ay = xy[2 * (s - 1) + 1];
                if (s == ni)
                    hpfc_graph_vertex(g, v, &bx, &by);
                else
                    bx = xy[2 * s], by = xy[2 * s + 1];
                lpoint a = {ax - ox, ay - oy}, b = {bx - ox, by - oy};
                line_pos pos;
                bool entering;
                if (cross_road(a, b, road, x0 - ox, y0 - oy, x1 - ox, y1 - oy, &pos, &entering) &&
                    n < cap)
                    out[n++] = (ref_cross){e, s, pos, road};
            }
        }
        qsort(out + first, n - first, sizeof *out, cmp_ref);
    }
    return n;
}

/* Does u -> v along segment seg of edge e leave the cell at its crossing
 * on `road`? */
static bool leaves_cell(const hpfc_graph *g, const ref_cross *r, int64_t ox, int64_t oy,
                        int64_t x0, int64_t y0, int64_t x1, int64_t y1)
{
    uint32_t u, v;
    const int64_t *xy;
    size_t ni;
    hpfc_graph_edge(g, r->edge, &u, &v, &xy, &ni);
    int64_t ax, ay, bx, by;
    if (r->seg == 0)
        hpfc_graph_vertex(g, u, &ax, &ay);
    else
        ax = xy[2 * (r->seg - 1)], ay = xy[2 * (r->seg - 1) + 1];
    if (r->seg == ni)
        hpfc_graph_vertex(g, v, &bx, &by);
    else
        bx = xy[2 * r->seg], by = xy[2 * r->seg + 1];
    lpoint a = {ax - ox, ay - oy}, b = {bx - ox, by - oy};
    line_pos pos;
    bool entering = true;
    cross_road(a, b, r->road, x0 - ox, y0 - oy, x1 - ox, y1 - oy, &pos, &entering);
    return !entering;
}

static void check_crossings(const packed *p, const hpfc_graph *g)
{
    hpfc_file_info fi;
    hpfc_file_get_info(p->f, &fi);
    hpfc_faces *fc = NULL;
    CHECK_EQ_INT(hpfc_faces_build(p->f, &fc), HPFC_OK);
    size_t ne = hpfc_graph_edge_count(g);
    uint64_t *left = malloc(ne * sizeof *left), *right = malloc(ne * sizeof *right);
    for (size_t e = 0; e < ne; e++) {
        CHECK_EQ_INT(hpfc_geometry_edge_faces(p->f, e, &left[e], &right[e]), HPFC_OK);
        uint64_t a, b;
        CHECK_EQ_INT(hpfc_geometry_edge_faces(p->f0, e, &a, &b), HPFC_E_NO_SECTION);
    }
    size_t cap = 4096, bad = 0;
    ref_cross *ref = malloc(cap * sizeof *ref);
    hpfc_pixel px;
    int st;
    for (st = hpfc_leaf_first(p->f, &px); !st && bad < 5; st = hpfc_leaf_next(p->f, &px)) {
        int64_t x0, y0, x1, y1;
        CHECK_EQ_INT(hpfc_pixel_bounds(p->f, &px, &x0, &y0, &x1, &y1), HPFC_OK);
        size_t n = reference_crossings(g, fi.x0, fi.y0, x0, y0, x1, y1, ref, cap), len = 0;
        CHECK_EQ_INT(hpfc_pixel_word(p->f, &px, NULL, 0, &len), HPFC_OK);
        CHECK_EQ_INT(len, n + 4);
        uint64_t seg;
        CHECK_EQ_INT(hpfc_geometry_crossing_segment(p->f, &px, (uint32_t)n, &seg), HPFC_E_ARG);
        CHECK_EQ_INT(hpfc_geometry_crossing_segment(p->f0, &px, 0, &seg), HPFC_E_NO_SECTION);
        for (size_t k = 0; k < n && len == n + 4; k++) {
            uint64_t edge = UINT64_MAX, face = UINT64_MAX;
            seg = UINT64_MAX;
            CHECK_EQ_INT(hpfc_geometry_crossing_segment(p->f, &px, (uint32_t)k, &seg), HPFC_OK);
            CHECK_EQ_INT(hpfc_label_crossing_edge(p->f, &px, (uint32_t)k, &edge), HPFC_OK);
            if (seg != ref[k].seg || edge != ref[k].edge) {
                CHECK_EQ_INT(seg, ref[k].seg);
                CHECK_EQ_INT(edge, ref[k].edge);
                bad++;
                break;
            }
            hpfc_dart d = {.pixel = px, .crossing = (uint32_t)k};
            CHECK_EQ_INT(hpfc_faces_dart_face(fc, &d, &face), HPFC_OK);
            /* the out-dart at k runs u -> v iff u -> v leaves the cell there */
            uint64_t want = leaves_cell(g, &ref[k], fi.x0, fi.y0, x0, y0, x1, y1) ? right[edge]
                                                                                  : left[edge];
            if (face != want) {
                CHECK_EQ_INT(face, want);
                bad++;
            }
        }
    }
    CHECK(st == HPFC_E_NO_PIXEL || bad);
    free(ref);
    free(left);
    free(right);
    hpfc_faces_free(fc);
}

static void check_map(const hpfc_graph *g, uint32_t n0, uint32_t n, int flat)
{
    packed p;
    int st = pack(g, n0, n, flat, &p);
    CHECK_EQ_INT(st, HPFC_OK);
    if (!st) {
        hpfc_geometry_info gi;
        int64_t x, y;
        CHECK_EQ_INT(hpfc_file_get_geometry(p.f0, &gi), HPFC_E_NO_SECTION);
        CHECK_EQ_INT(hpfc_geometry_vertex(p.f0, 0, &x, &y), HPFC_E_NO_SECTION);
        int64_t box[4];
        CHECK_EQ_INT(hpfc_geometry_bounds(p.f0, box), HPFC_E_NO_SECTION);
        check_points(p.f, g);
        check_crossings(&p, g);
        hpfc_geometry_report rep;
        CHECK_EQ_INT(hpfc_geometry_verify(p.f, &rep), HPFC_OK);
        if (rep.message[0])
            fprintf(stderr, "verify: %s\n", rep.message);
        CHECK_EQ_INT(rep.vertices_checked, hpfc_graph_vertex_count(g));
        CHECK_EQ_INT(hpfc_geometry_verify(p.f0, &rep), HPFC_E_NO_SECTION);
        /* hpfc_file_serialize keeps the section */
        uint8_t *again = NULL;
        size_t size = 0;
        hpfc_file *f2 = NULL;
        CHECK_EQ_INT(hpfc_file_serialize(p.f, NULL, &again, &size, NULL), HPFC_OK);
        CHECK_EQ_INT(hpfc_open_memory(again, size, 0, &f2), HPFC_OK);
        if (f2)
            check_points(f2, g);
        hpfc_close(f2);
        hpfc_free(again);
    }
    unpack(&p);
}

static void check_graph(const hpfc_graph *g)
{
    check_map(g, 1, 2, 0);
    check_map(g, 3, 3, 0);
    check_map(g, 16, 4, 0);
    check_map(g, 64, 2, 0);
    check_map(g, 8, 2, 1);
}

/* A graph that is not the tree's is refused. */
static void check_wrong_graph(void)
{
    hpfc_graph *a = NULL, *b = NULL;
    hpfc_tree *t = NULL;
    CHECK_EQ_INT(gen_special(GEN_SPECIAL_TRIANGLE, &a), HPFC_OK);
    CHECK_EQ_INT(gen_special(GEN_SPECIAL_CRACK, &b), HPFC_OK);
    hpfc_build_params bp;
    hpfc_build_params_default(&bp);
    CHECK_EQ_INT(hpfc_build(a, &bp, &t, NULL), HPFC_OK);
    hpfc_write_options o = {.geometry = b};
    uint8_t *bytes = NULL;
    size_t size = 0;
    CHECK_EQ_INT(check_tree_serialize(t, &o, &bytes, &size, NULL), HPFC_E_ARG);
    CHECK(bytes == NULL);
    hpfc_tree_free(t);
    hpfc_graph_free(a);
    hpfc_graph_free(b);
}

/* spec/hpfc-format.md §6.6.7: the triangle of §9 with edge 2 bent through
 * (1, 6), root 2 x 2, refined 2 x 2: its GEOM section's 322 bytes as
 * printed there, and its LABL section unchanged from §6.5.7. */
static void check_worked_example(void)
{
    static const uint8_t want[322] = {
        0x04, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x04, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x04, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x0a, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x02, 0x00, 0x02, 0x00, 0x00, 0x00, 0x00, 0x00, 0x10, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x01, 0x00, 0x03, 0x00, 0x00, 0x00, 0x00, 0x00, 0x06, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x02, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x08, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x02, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x08, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x02, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x04, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x00, 0x00, 0x03, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x00, 0x00, 0x04, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x02, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x0c, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x04, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x0a, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x60, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xc2, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x0a, 0x55, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x80, 0x38, 0x30, 0x00, 0x00, 0x00, 0x00, 0x00,
        0xa0, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x04, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x18, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x04, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x63, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x02, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x10, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x80, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
        0xa0, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x06, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x0a, 0x70, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x02, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x48, 0x00};
    static const uint8_t labl_head[8] = {0x02, 0, 0, 0, 0, 0, 0, 0};
    static const uint8_t labl_tail[4] = {0x95, 0x4c, 0x0e, 0x60};
    static const int64_t xy[4][2] = {{0, 0}, {10, 0}, {5, 8}, {5, 3}};
    static const uint32_t uv[4][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}};
    static const int64_t bend[2] = {1, 6};
    hpfc_graph *g = NULL;
    CHECK_EQ_INT(hpfc_graph_create(&g), HPFC_OK);
    for (int k = 0; k < 4; k++)
        CHECK_EQ_INT(hpfc_graph_add_vertex(g, xy[k][0], xy[k][1], NULL), HPFC_OK);
    for (int k = 0; k < 4; k++)
        CHECK_EQ_INT(hpfc_graph_add_edge(g, uv[k][0], uv[k][1], k == 2 ? bend : NULL, k == 2, NULL),
                     HPFC_OK);
    packed p;
    CHECK_EQ_INT(pack(g, 2, 2, 0, &p), HPFC_OK);
    hpfc_section_info si;
    int found = 0;
    for (uint32_t k = 0; p.f && hpfc_file_get_section(p.f, k, &si) == HPFC_OK; k++) {
        if (memcmp(si.tag, "GEOM", 4) == 0) {
            found++;
            CHECK_EQ_INT(si.length, sizeof want);
            CHECK(si.length == sizeof want && memcmp(p.with + si.offset, want, sizeof want) == 0);
        }
        if (memcmp(si.tag, "LABL", 4) == 0) {
            found++;
            CHECK_EQ_INT(si.length, 84);
            CHECK(si.length == 84 && memcmp(p.with + si.offset, labl_head, 8) == 0 &&
                  memcmp(p.with + si.offset + 80, labl_tail, 4) == 0);
        }
    }
    CHECK_EQ_INT(found, 2);
    uint64_t left = 9, right = 9;
    static const uint64_t want_right[4] = {0, 0, 0, 1}, want_left[4] = {1, 1, 1, 1};
    for (uint64_t e = 0; p.f && e < 4; e++) {
        CHECK_EQ_INT(hpfc_geometry_edge_faces(p.f, e, &left, &right), HPFC_OK);
        CHECK_EQ_INT(left, want_left[e]);
        CHECK_EQ_INT(right, want_right[e]);
    }
    unpack(&p);
    hpfc_graph_free(g);
}

/* geom_column_get reads a block's directory entry (offset, base, width)
 * in one read when it fits 57 bits and field by field otherwise: both
 * must give back the values written, in every block. */
static void check_column_entries(void)
{
    for (int wide = 0; wide < 2; wide++) {
        const uint32_t ob = wide ? 30 : 12, bb = wide ? 40 : 20, entry = ob + bb + GEOM_WIDTH_BITS;
        const unsigned width = 5, shift = 2, count = 11; /* 3 blocks of 4, the last short */
        const uint64_t base[3] = {wide ? (UINT64_C(1) << 39) + 5 : 1000, wide ? 77 : 3,
                                  wide ? (UINT64_C(1) << 40) - 40 : (UINT64_C(1) << 20) - 40};
        uint8_t dir[32] = {0}, payload[16] = {0};
        for (uint64_t b = 0; b < 3; b++) {
            format_put(dir, b * entry, ob, b * 4 * width + (wide ? 3 : 1));
            format_put(dir, b * entry + ob, bb, base[b]);
            format_put(dir, b * entry + ob + bb, GEOM_WIDTH_BITS, width);
        }
        const uint64_t lead = wide ? 3 : 1; /* payload bits before block 0's values */
        for (uint64_t i = 0; i < count; i++)
            format_put(payload, lead + i * width, width, (i * 7) % 32);
        geom_column c = {.count = count, .shift = shift, .offset_bits = ob, .base_bits = bb,
                         .entry_bits = entry,
                         .dir = {dir, 3 * entry, sizeof dir},
                         .payload = {payload, lead + count * width, sizeof payload}};
        for (uint64_t i = 0; i < count; i++) {
            uint64_t v = 0;
            CHECK_EQ_INT(geom_column_get(&c, i, &v), HPFC_OK);
            CHECK(v == base[i >> shift] + (i * 7) % 32);
        }
        uint64_t v;
        CHECK_EQ_INT(geom_column_get(&c, count, &v), HPFC_E_CORRUPT);
    }
}

/* geom_coordinate_run (geom_points' reading of a coordinate) against
 * geom_column_get value by value, on check_column_entries' narrow column
 * (blocks of 4 values of width 5, bases 1000, 3 and 2^20 - 40): every run,
 * under a limit no block can reach (each block added to as it is
 * unpacked), and under one the last block's ceiling passes, where the
 * values are tested one by one: a run holding a value at or past the limit
 * is corrupt, the rest read. The odd slots stay untouched. */
static void check_coordinate_runs(void)
{
    const uint32_t ob = 12, bb = 20, entry = ob + bb + GEOM_WIDTH_BITS;
    const unsigned width = 5, shift = 2, count = 11;
    const uint64_t base[3] = {1000, 3, (UINT64_C(1) << 20) - 40};
    uint8_t dir[32] = {0}, payload[16] = {0};
    for (uint64_t b = 0; b < 3; b++) {
        format_put(dir, b * entry, ob, b * 4 * width + 1);
        format_put(dir, b * entry + ob, bb, base[b]);
        format_put(dir, b * entry + ob + bb, GEOM_WIDTH_BITS, width);
    }
    for (uint64_t i = 0; i < count; i++)
        format_put(payload, 1 + i * width, width, (i * 7) % 32);
    geom_column c = {.count = count, .shift = shift, .offset_bits = ob, .base_bits = bb,
                     .entry_bits = entry,
                     .dir = {dir, 3 * entry, sizeof dir},
                     .payload = {payload, 1 + count * width, sizeof payload}};
    const uint64_t limits[2] = {UINT64_C(1) << 21, (UINT64_C(1) << 20) - 40 + 20};
    const int64_t origins[3] = {0, -5000, INT64_C(1) << 40};
    int slow_ok = 0, slow_corrupt = 0;
    for (int l = 0; l < 2; l++)
        for (int o = 0; o < 3; o++)
            for (uint64_t i = 0; i <= count; i++)
                for (uint64_t n = 0; i + n <= count; n++) {
                    int64_t out[2 * 12];
                    for (int k = 0; k < 24; k++)
                        out[k] = -1;
                    int want = HPFC_OK;
                    for (uint64_t k = 0; k < n; k++) {
                        uint64_t v = 0;
                        CHECK_EQ_INT(geom_column_get(&c, i + k, &v), HPFC_OK);
                        if (v >= limits[l])
                            want = HPFC_E_CORRUPT;
                    }
                    int st = geom_coordinate_run(&c, i, n, limits[l], origins[o], out);
                    CHECK_EQ_INT(st, want);
                    if (l == 1 && i + n > 8)
                        st == HPFC_OK ? slow_ok++ : slow_corrupt++;
                    for (uint64_t k = 0; k < n && st == HPFC_OK; k++) {
                        uint64_t v = 0;
                        geom_column_get(&c, i + k, &v);
                        CHECK(out[2 * k] == origins[o] + (int64_t)v);
                    }
                    for (int k = 1; k < 24; k += 2)
                        CHECK(out[k] == -1);
                }
    /* both outcomes of the value-by-value test were met */
    CHECK(slow_ok > 0 && slow_corrupt > 0);
    int64_t out[2];
    CHECK_EQ_INT(geom_coordinate_run(&c, count, 1, limits[0], 0, out), HPFC_E_CORRUPT);
}

/* geom_column_span against every value read, on columns whose bases are
 * not their blocks' minima (hpfc's writer makes them minima; another
 * writer, or damage, need not): random bases, widths and values, so that
 * the smallest and largest values sit in blocks other than those with the
 * lowest floor and the highest ceiling. */
static void check_column_span(void)
{
    uint64_t r = 0x2545f4914f6cdd1du;
    for (int trial = 0; trial < 200; trial++) {
        enum { BLOCKS = 40, SHIFT = 2, OB = 16, BB = 16, ENTRY = OB + BB + GEOM_WIDTH_BITS };
        const uint32_t ob = OB, bb = BB, entry = ENTRY;
        uint8_t dir[(BLOCKS * ENTRY + 7) / 8 + 8] = {0}, payload[BLOCKS * 4 * 2 + 8] = {0};
        uint64_t count = (uint64_t)(BLOCKS - 1) * 4 + 1 + trial % 4, off = 0, lo = UINT64_MAX, hi = 0;
        for (uint64_t b = 0; b * 4 < count; b++) {
            r ^= r << 13, r ^= r >> 7, r ^= r << 17;
            unsigned width = (unsigned)(r % 9);
            uint64_t base = (r >> 8) % 1000;
            format_put(dir, b * entry, ob, off);
            format_put(dir, b * entry + ob, bb, base);
            format_put(dir, b * entry + ob + bb, GEOM_WIDTH_BITS, width);
            for (uint64_t i = b * 4; i < count && i < b * 4 + 4; i++) {
                r ^= r << 13, r ^= r >> 7, r ^= r << 17;
                uint64_t delta = width ? (r >> 11) & ((UINT64_C(1) << width) - 1) : 0;
                format_put(payload, off, width, delta);
                off += width;
                lo = base + delta < lo ? base + delta : lo;
                hi = base + delta > hi ? base + delta : hi;
            }
        }
        geom_column c = {.count = count, .shift = SHIFT, .offset_bits = ob, .base_bits = bb,
                         .entry_bits = entry,
                         .dir = {dir, (uint64_t)BLOCKS * entry, sizeof dir},
                         .payload = {payload, off, sizeof payload}};
        uint64_t got_lo = 0, got_hi = 0;
        CHECK_EQ_INT(geom_column_span(&c, &got_lo, &got_hi), HPFC_OK);
        CHECK_EQ_INT(got_lo, lo);
        CHECK_EQ_INT(got_hi, hi);
    }
    geom_column empty = {.count = 0, .shift = 2};
    uint64_t lo, hi;
    CHECK_EQ_INT(geom_column_span(&empty, &lo, &hi), HPFC_OK);
    CHECK(lo > hi);
}

/* Bits of column values[0..n) cut into blocks of 2^s (spec §6.6.3): a
 * directory entry per block, the values less their block's minimum at the
 * block's width. The writer's own choice is made in one pass over all
 * sizes; this measures each size apart. */
static uint64_t naive_column_bits(const uint64_t *values, uint64_t n, uint32_t s, uint32_t *ob,
                                  uint32_t *bb, uint64_t *payload)
{
    uint64_t B = UINT64_C(1) << s, blocks = 0, last_start = 0, max_base = 0;
    *payload = 0;
    for (uint64_t b = 0; b < n; b += B, blocks++) {
        uint64_t lo = UINT64_MAX, hi = 0;
        for (uint64_t i = b; i < n && i < b + B; i++) {
            lo = values[i] < lo ? values[i] : lo;
            hi = values[i] > hi ? values[i] : hi;
        }
        max_base = lo > max_base ? lo : max_base;
        last_start = *payload;
        uint64_t span = hi - lo;
        uint32_t w = span ? (uint32_t)(64 - __builtin_clzll(span)) : 0;
        *payload += (n - b < B ? n - b : B) * w;
    }
    *ob = last_start ? (uint32_t)(64 - __builtin_clzll(last_start)) : 0;
    *bb = max_base ? (uint32_t)(64 - __builtin_clzll(max_base)) : 0;
    return blocks * (*ob + *bb + GEOM_WIDTH_BITS) + *payload;
}

/* Column c of the graph's GEOM columns (VX .. PY), from the graph. */
static uint64_t *graph_column(const hpfc_graph *g, const hpfc_file_info *fi, int c, uint64_t *n)
{
    size_t nv = hpfc_graph_vertex_count(g), ne = hpfc_graph_edge_count(g), np = 0;
    for (size_t e = 0; e < ne; e++) {
        uint32_t u, w;
        const int64_t *xy;
        size_t ni;
        hpfc_graph_edge(g, e, &u, &w, &xy, &ni);
        np += ni;
    }
    *n = c <= GEOM_VY ? nv : c <= GEOM_EPOINT ? ne : np;
    uint64_t *v = malloc((*n ? *n : 1) * sizeof *v), k = 0;
    for (size_t i = 0; v && c <= GEOM_VY && i < nv; i++) {
        int64_t x, y;
        hpfc_graph_vertex(g, i, &x, &y);
        v[k++] = (uint64_t)(c == GEOM_VX ? x - fi->x0 : y - fi->y0);
    }
    for (size_t e = 0, before = 0; v && c > GEOM_VY && e < ne; e++) {
        uint32_t u, w;
        const int64_t *xy;
        size_t ni;
        hpfc_graph_edge(g, e, &u, &w, &xy, &ni);
        if (c == GEOM_EU || c == GEOM_EV || c == GEOM_EPOINT)
            v[k++] = c == GEOM_EU ? u : c == GEOM_EV ? w : before;
        for (size_t q = 0; c >= GEOM_PX && q < ni; q++)
            v[k++] = (uint64_t)(c == GEOM_PX ? xy[2 * q] - fi->x0 : xy[2 * q + 1] - fi->y0);
        before += ni;
    }
    return v;
}

/* A map whose GEOM outgrows the writer's stream buffers (64 KiB): written
 * to a file, where the section is streamed, and serialised, the same
 * bytes; read back equal to the graph; its graph columns blocked as the
 * naive search says. */
static void check_streamed(void)
{
    hpfc_graph *g = NULL;
    CHECK_EQ_INT(gen_polyline(11, 120000, 2000, 0.5, &g), HPFC_OK);
    hpfc_build_params bp;
    hpfc_build_params_default(&bp);
    hpfc_tree *tree = NULL;
    CHECK_EQ_INT(hpfc_build(g, &bp, &tree, NULL), HPFC_OK);
    hpfc_write_options o = {.face_labels = 1, .geometry = g};
    uint8_t *mem = NULL, *disk = NULL;
    size_t size = 0, disk_size = 0;
    char path[] = "/tmp/hpfc-geom-XXXXXX";
    int fd = mkstemp(path);
    CHECK(fd >= 0);
    if (fd >= 0)
        close(fd);
    CHECK_EQ_INT(check_tree_serialize(tree, &o, &mem, &size, NULL), HPFC_OK);
    o.layout = check_layout;
    CHECK_EQ_INT(hpfc_tree_write_file(tree, &o, path, NULL), HPFC_OK);
    FILE *in = fopen(path, "rb");
    CHECK(in != NULL);
    if (in && (disk = malloc(size + 1)))
        disk_size = fread(disk, 1, size + 1, in);
    if (in)
        fclose(in);
    unlink(path);
    CHECK_EQ_INT(disk_size, size);
    CHECK(mem && disk && disk_size == size && memcmp(mem, disk, size) == 0);
    hpfc_file *f = NULL;
    CHECK_EQ_INT(hpfc_open_memory(disk, disk_size, 0, &f), HPFC_OK);
    hpfc_section_info si = {0};
    uint32_t k = 0;
    while (f && hpfc_file_get_section(f, k, &si) == HPFC_OK && memcmp(si.tag, "GEOM", 4) != 0)
        k++;
    CHECK(f && memcmp(si.tag, "GEOM", 4) == 0);
    if (f && memcmp(si.tag, "GEOM", 4) == 0) {
        CHECK(si.length > 4 * 65536); /* several buffers a column */
        check_points(f, g);
        hpfc_file_info fi;
        hpfc_file_get_info(f, &fi);
        for (int c = GEOM_VX; c <= GEOM_PY; c++) {
            uint64_t n = 0, best = UINT64_MAX, payload = 0, best_payload = 0;
            uint64_t *v = graph_column(g, &fi, c, &n);
            uint32_t best_s = 0, ob = 0, bb = 0, best_ob = 0, best_bb = 0;
            CHECK(v != NULL);
            for (uint32_t s = 0; v && s <= 12; s++) {
                uint64_t bits = naive_column_bits(v, n, s, &ob, &bb, &payload);
                if (bits < best)
                    best = bits, best_s = s, best_ob = ob, best_bb = bb, best_payload = payload;
            }
            const uint8_t *d = disk + si.offset + GEOM_HEADER_SIZE + (size_t)c * GEOM_COLUMN_SIZE;
            CHECK_EQ_INT(geomc_get_block_shift(d), best_s);
            CHECK_EQ_INT(geomc_get_offset_bits(d), best_ob);
            CHECK_EQ_INT(geomc_get_base_bits(d), best_bb);
            CHECK_EQ_INT(geomc_get_payload_bits(d), best_payload);
            free(v);
        }
    }
    hpfc_close(f);
    free(disk);
    hpfc_free(mem);
    hpfc_tree_free(tree);
    hpfc_graph_free(g);
}

int main(void)
{
    check_streamed();
    check_use_test_layout();
    check_column_entries();
    check_coordinate_runs();
    check_column_span();
    check_wrong_graph();
    check_worked_example();
    for (int which = 0; which < GEN_SPECIAL_COUNT; which++) {
        hpfc_graph *g = NULL;
        CHECK_EQ_INT(gen_special(which, &g), HPFC_OK);
        if (g)
            check_graph(g);
        hpfc_graph_free(g);
    }
    for (uint64_t seed = 1; seed <= 3; seed++) {
        hpfc_graph *g = NULL;
        CHECK_EQ_INT(gen_delaunay(seed, 120, 1000, 0.2, &g), HPFC_OK);
        if (g)
            check_graph(g);
        hpfc_graph_free(g);
        g = NULL;
        CHECK_EQ_INT(gen_polyline(seed, 200, 600, 0.5, &g), HPFC_OK);
        if (g)
            check_graph(g);
        hpfc_graph_free(g);
    }
    return check_report("geometry");
}
