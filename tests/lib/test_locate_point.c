/*
 * hpfc_locate_point (spec §6.7) against a naive exact locator that shares
 * no code with it: every segment of every input edge, a ray from the point
 * eastwards to infinity, the face on the side of the nearest edge hit (face
 * 0, the unbounded face, when none is hit), and on_boundary for a point on
 * a segment. The two sides of each edge come from the traversal and
 * hpfc_faces_build (the flood fill of §3.11), not from LABL or GEOM: the
 * out-dart leaving the edge's first vertex, found through the builder's
 * own record of which crossing lies on which segment.
 *
 * Points: random ones over the domain and beyond it, and adversarial ones:
 * every vertex and shape point, lattice points on segments, their
 * neighbours, points on the grid lines of the leaves, and points next to
 * where segments cross those lines.
 */
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "gen.h"
#include "hpfc.h"
#include "hpfc_batch.h"
#include "tree_oracle.h"

__extension__ typedef __int128 wide;

typedef struct packed {
    hpfc_tree *tree;
    uint8_t *bytes;
    hpfc_file *f;
    hpfc_faces *faces;
    hpfc_walker *w;
    uint64_t *left, *right; /* per edge: faces on the left, right of u -> v */
} packed;

/* ---- the naive oracle --------------------------------------------------------------- */

typedef struct pt {
    int64_t x, y;
} pt;

static pt graph_point(const hpfc_graph *g, size_t e, size_t k, size_t *count)
{
    uint32_t u, v;
    const int64_t *in;
    size_t n;
    hpfc_graph_edge(g, e, &u, &v, &in, &n);
    *count = n + 2;
    pt p;
    if (k == 0)
        hpfc_graph_vertex(g, u, &p.x, &p.y);
    else if (k == n + 1)
        hpfc_graph_vertex(g, v, &p.x, &p.y);
    else
        p = (pt){in[2 * (k - 1)], in[2 * (k - 1) + 1]};
    return p;
}

static int turn(pt a, pt b, pt c)
{
    wide d = (wide)(b.x - a.x) * (c.y - a.y) - (wide)(b.y - a.y) * (c.x - a.x);
    return (d > 0) - (d < 0);
}

static bool between(int64_t a, int64_t b, int64_t v)
{
    return a < b ? a <= v && v <= b : b <= v && v <= a;
}

/* The sides of every edge, from the traversal and the flood fill. */
static int edge_sides(const hpfc_graph *g, packed *p)
{
    size_t ne = hpfc_graph_edge_count(g);
    p->left = calloc(ne, sizeof *p->left);
    p->right = calloc(ne, sizeof *p->right);
    if (!p->left || !p->right)
        return HPFC_E_NOMEM;
    for (size_t e = 0; e < ne; e++) {
        size_t count;
        pt u = graph_point(g, e, 0, &count);
        hpfc_tree_pixel tp;
        uint32_t level;
        hpfc_pixel px;
        if (!oracle_locate(p->tree, u.x, u.y, &tp, &level) || hpfc_locate(p->f, u.x, u.y, &px))
            return HPFC_E_CORRUPT;
        /* the first crossing of edge e leaving u: the smallest segment */
        uint32_t best = UINT32_MAX, k = 0, bestk = 0;
        for (uint32_t s = 0; s < tp.word_len; s++) {
            if (tp.word[s] == '+')
                continue;
            if (tp.cross_edge[k] == e && tp.cross_segment[k] < best)
                best = tp.cross_segment[k], bestk = k;
            k++;
        }
        if (best == UINT32_MAX)
            return HPFC_E_CORRUPT;
        hpfc_dart d = {.pixel = px, .crossing = bestk}, t;
        int st = hpfc_faces_dart_face(p->faces, &d, &p->right[e]);
        if (!st)
            st = hpfc_dart_twin(p->w, &d, &t);
        if (!st)
            st = hpfc_faces_dart_face(p->faces, &t, &p->left[e]);
        if (st)
            return st;
    }
    return HPFC_OK;
}

typedef struct oracle_answer {
    int on_boundary, on_vertex;
    uint64_t vertex, edge;
    uint64_t faces[256];
    size_t count;
} oracle_answer;

static void add_face(oracle_answer *a, uint64_t face)
{
    for (size_t k = 0; k < a->count; k++)
        if (a->faces[k] == face)
            return;
    if (a->count < 256)
        a->faces[a->count++] = face;
}

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

/* Is q on the boundary: a vertex (then every edge at it), else a segment. */
static bool oracle_boundary(const hpfc_graph *g, const packed *p, pt q, oracle_answer *a)
{
    size_t nv = hpfc_graph_vertex_count(g), ne = hpfc_graph_edge_count(g);
    for (size_t v = 0; v < nv; v++) {
        pt c;
        hpfc_graph_vertex(g, v, &c.x, &c.y);
        if (c.x != q.x || c.y != q.y)
            continue;
        a->on_boundary = a->on_vertex = 1;
        a->vertex = v;
        for (size_t e = 0; e < ne; e++) {
            uint32_t eu, ev;
            const int64_t *in;
            size_t n;
            hpfc_graph_edge(g, e, &eu, &ev, &in, &n);
            if (eu == v || ev == v) {
                add_face(a, p->left[e]);
                add_face(a, p->right[e]);
            }
        }
        return true;
    }
    for (size_t e = 0; e < ne; e++) {
        size_t count;
        graph_point(g, e, 0, &count);
        for (size_t k = 0; k + 1 < count; k++) {
            pt s = graph_point(g, e, k, &count), t = graph_point(g, e, k + 1, &count);
            if (turn(s, t, q) == 0 && between(s.x, t.x, q.x) && between(s.y, t.y, q.y)) {
                a->on_boundary = 1;
                a->edge = e;
                add_face(a, p->left[e]);
                add_face(a, p->right[e]);
                return true;
            }
        }
    }
    return false;
}

/* The face of a point off the graph: the ray y = q.y + delta eastwards. */
static uint64_t oracle_ray(const hpfc_graph *g, const packed *p, pt q)
{
    size_t ne = hpfc_graph_edge_count(g);
    bool found = false;
    wide bn = 0;
    int64_t bd = 1, bdx = 0;
    uint64_t face = 0;
    for (size_t e = 0; e < ne; e++) {
        size_t count;
        graph_point(g, e, 0, &count);
        for (size_t k = 0; k + 1 < count; k++) {
            pt s = graph_point(g, e, k, &count), t = graph_point(g, e, k + 1, &count);
            /* an end at q.y lies below the ray */
            if ((s.y > q.y) == (t.y > q.y))
                continue;
            pt lo = s.y > q.y ? t : s, hi = s.y > q.y ? s : t;
            int64_t dy = hi.y - lo.y, dx = hi.x - lo.x;
            wide num = (wide)lo.x * dy + (wide)dx * (q.y - lo.y);
            if (num <= (wide)q.x * dy)
                continue; /* west of q (q on it was answered before) */
            bool first = !found;
            if (!first) {
                wide l = num * bd, r = bn * dy;
                first = l < r || (l == r && (wide)dx * bd < (wide)bdx * dy);
            }
            if (first) {
                found = true;
                bn = num, bd = dy, bdx = dx;
                face = turn(s, t, q) > 0 ? p->left[e] : p->right[e];
            }
        }
    }
    return face;
}

static void oracle(const hpfc_graph *g, const packed *p, pt q, oracle_answer *a)
{
    memset(a, 0, sizeof *a);
    a->vertex = a->edge = UINT64_MAX;
    if (!oracle_boundary(g, p, q, a)) {
        a->count = 1;
        a->faces[0] = oracle_ray(g, p, q);
    }
    qsort(a->faces, a->count, sizeof *a->faces, cmp_u64);
}

/* ---- packing ------------------------------------------------------------------------- */

static void unpack(packed *p)
{
    hpfc_walker_free(p->w);
    hpfc_faces_free(p->faces);
    hpfc_close(p->f);
    hpfc_free(p->bytes);
    hpfc_tree_free(p->tree);
    free(p->left);
    free(p->right);
    memset(p, 0, sizeof *p);
}

static int pack(const hpfc_graph *g, uint32_t n0, uint32_t n, packed *p)
{
    memset(p, 0, sizeof *p);
    hpfc_build_params bp;
    hpfc_build_params_default(&bp);
    bp.root_cols = bp.root_rows = n0;
    bp.cols = bp.rows = n;
    size_t size = 0;
    hpfc_write_options o = {.face_labels = 1, .geometry = g};
    int st = hpfc_build(g, &bp, &p->tree, NULL);
    if (!st)
        st = check_tree_serialize(p->tree, &o, &p->bytes, &size, NULL);
    if (!st)
        st = hpfc_open_memory(p->bytes, size, 0, &p->f);
    if (!st)
        st = hpfc_faces_build(p->f, &p->faces);
    if (!st)
        st = hpfc_walker_create(p->f, &p->w);
    if (!st)
        st = edge_sides(g, p);
    return st;
}

/* ---- checks ------------------------------------------------------------------------ */

static long points_checked, boundary_points, vertex_points;

/* Every point asked of a map, for the batch call afterwards. */
static int64_t *asked_x, *asked_y;
static size_t asked, asked_cap;

static void remember(pt q)
{
    if (asked == asked_cap) {
        size_t cap = asked_cap ? 2 * asked_cap : 4096;
        int64_t *nx = realloc(asked_x, cap * sizeof *nx), *ny;
        if (nx)
            asked_x = nx;
        if (!nx || !(ny = realloc(asked_y, cap * sizeof *ny)))
            return;
        asked_y = ny;
        asked_cap = cap;
    }
    asked_x[asked] = q.x;
    asked_y[asked++] = q.y;
}

/* hpfc_locate_batch gives each point hpfc_locate_point's answer. */
static void check_batch(const packed *p)
{
    size_t n = asked;
    int64_t *face = malloc((n + 1) * sizeof *face), *feature = malloc((n + 1) * sizeof *feature);
    uint32_t *count = malloc((n + 1) * sizeof *count), *fcount = malloc((n + 1) * sizeof *fcount);
    uint8_t *flags = malloc(n + 1), *depth = malloc(n + 1);
    CHECK(face && feature && count && fcount && flags && depth);
    if (face && feature && count && fcount && flags && depth) {
        hpfc_locate_out out = {face, count, feature, fcount, flags, depth};
        size_t failed = 0;
        CHECK_EQ_INT(hpfc_locate_batch(p->f, NULL, n, asked_x, asked_y, NULL, &out, &failed),
                     HPFC_OK);
        long bad = 0;
        for (size_t k = 0; k < n; k++) {
            hpfc_point_location loc;
            uint64_t faces[256];
            size_t c = 0;
            int st = hpfc_locate_point(p->f, asked_x[k], asked_y[k], &loc, faces, 256, &c);
            int want = st == HPFC_E_NO_PIXEL
                           ? 0
                           : HPFC_LOC_INSIDE | HPFC_LOC_EXACT | (c == 1 ? HPFC_LOC_SINGLE : 0) |
                                 (loc.on_boundary ? HPFC_LOC_BOUNDARY : 0) |
                                 (loc.on_boundary ? 0 : flags[k] & HPFC_LOC_PRIVATE);
            bad += (flags[k] & ~HPFC_LOC_PRIVATE) != (want & ~HPFC_LOC_PRIVATE) ||
                   count[k] != c || face[k] != (c == 1 ? (int64_t)faces[0] : -1) ||
                   depth[k] != (st ? 0 : loc.leaf.depth);
        }
        CHECK_EQ_INT(bad, 0);
    }
    free(face), free(feature), free(count), free(fcount), free(flags), free(depth);
    asked = 0;
}

static void check_point(const hpfc_graph *g, const packed *p, pt q)
{
    hpfc_file_info fi;
    hpfc_file_get_info(p->f, &fi);
    hpfc_point_location loc;
    uint64_t faces[256];
    size_t count = 99;
    int st = hpfc_locate_point(p->f, q.x, q.y, &loc, faces, 256, &count);
    remember(q);
    bool inside = q.x >= fi.x0 && q.y >= fi.y0 && q.x - fi.x0 < fi.width && q.y - fi.y0 < fi.height;
    if (!inside) {
        CHECK_EQ_INT(st, HPFC_E_NO_PIXEL);
        CHECK_EQ_INT(count, 0);
        return;
    }
    points_checked++;
    oracle_answer a;
    oracle(g, p, q, &a);
    boundary_points += a.on_boundary;
    vertex_points += a.on_vertex;
    CHECK_EQ_INT(st, HPFC_OK);
    bool same = st == HPFC_OK && loc.on_boundary == a.on_boundary && count == a.count &&
                loc.on_vertex == a.on_vertex && memcmp(faces, a.faces, count * sizeof *faces) == 0 &&
                (!a.on_vertex || loc.vertex == a.vertex) &&
                (!a.on_boundary || a.on_vertex || loc.edge == a.edge);
    CHECK(same);
    if (!same && check_failures < 20) {
        fprintf(stderr, "  point (%lld, %lld): got %zu faces [%llu ...] boundary %d vertex %d (%llu) "
                        "edge %llu; oracle %zu faces [%llu ...] boundary %d vertex %d (%llu) edge %llu\n",
                (long long)q.x, (long long)q.y, count, (unsigned long long)faces[0],
                loc.on_boundary, loc.on_vertex, (unsigned long long)loc.vertex,
                (unsigned long long)loc.edge, a.count, (unsigned long long)a.faces[0],
                a.on_boundary, a.on_vertex, (unsigned long long)a.vertex,
                (unsigned long long)a.edge);
    }
}

/* The adversarial points of segment s -> t: its ends, its lattice points
 * (a few), and their eight neighbours. */
static void check_segment_points(const hpfc_graph *g, const packed *p, pt s, pt t)
{
    int64_t dx = t.x - s.x, dy = t.y - s.y, a = dx < 0 ? -dx : dx, b = dy < 0 ? -dy : dy;
    while (b) {
        int64_t r = a % b;
        a = b, b = r;
    }
    int64_t steps = a; /* lattice points on the segment: steps + 1 */
    int64_t stride = steps > 6 ? steps / 6 : 1;
    for (int64_t k = 0; k <= steps; k += stride) {
        pt c = {s.x + dx / steps * k, s.y + dy / steps * k};
        for (int ox = -1; ox <= 1; ox++)
            for (int oy = -1; oy <= 1; oy++)
                check_point(g, p, (pt){c.x + ox, c.y + oy});
    }
}

/* Points on a leaf's grid lines and next to where segments cross them:
 * the corners of the leaf holding q and the lattice points beside it. */
static void check_leaf_lines(const hpfc_graph *g, const packed *p, pt q)
{
    hpfc_pixel px;
    int64_t x0, y0, x1, y1;
    if (hpfc_locate(p->f, q.x, q.y, &px) || hpfc_pixel_bounds(p->f, &px, &x0, &y0, &x1, &y1))
        return;
    pt list[] = {{x0, q.y}, {x1, q.y}, {q.x, y0}, {q.x, y1}, {x0, y0}, {x1, y1}, {x0, y1},
                 {x1, y0}, {x1 - 1, q.y}, {q.x, y1 - 1}, {x1 - 1, y1 - 1}};
    for (size_t k = 0; k < sizeof list / sizeof list[0]; k++)
        check_point(g, p, list[k]);
}

/* Where segment s -> t meets the vertical grid lines of the leaf holding
 * its start: the lattice points at the crossing's floor and ceiling. */
static void check_near_crossings(const hpfc_graph *g, const packed *p, pt s, pt t)
{
    hpfc_pixel px;
    int64_t x0, y0, x1, y1;
    if (hpfc_locate(p->f, s.x, s.y, &px) || hpfc_pixel_bounds(p->f, &px, &x0, &y0, &x1, &y1))
        return;
    int64_t lines[2] = {x0, x1};
    for (int k = 0; k < 2; k++) {
        int64_t X = lines[k];
        if (!between(s.x, t.x, X) || s.x == t.x)
            continue;
        /* y at X: s.y + (t.y - s.y) * (X - s.x) / (t.x - s.x), floored */
        wide num = (wide)(t.y - s.y) * (X - s.x);
        int64_t den = t.x - s.x;
        if (den < 0)
            num = -num, den = -den;
        int64_t fy = (int64_t)(num / den) - (num % den < 0);
        for (int64_t d = -1; d <= 2; d++)
            for (int64_t ox = -1; ox <= 0; ox++)
                check_point(g, p, (pt){X + ox, s.y + fy + d});
    }
    int64_t rows[2] = {y0, y1};
    for (int k = 0; k < 2; k++) {
        int64_t Y = rows[k];
        if (!between(s.y, t.y, Y) || s.y == t.y)
            continue;
        wide num = (wide)(t.x - s.x) * (Y - s.y);
        int64_t den = t.y - s.y;
        if (den < 0)
            num = -num, den = -den;
        int64_t fx = (int64_t)(num / den) - (num % den < 0);
        for (int64_t d = -1; d <= 2; d++)
            for (int64_t oy = -1; oy <= 0; oy++)
                check_point(g, p, (pt){s.x + fx + d, Y + oy});
    }
}

static void check_map(const hpfc_graph *g, uint32_t n0, uint32_t n, uint64_t seed, int randoms)
{
    packed p;
    int st = pack(g, n0, n, &p);
    CHECK_EQ_INT(st, HPFC_OK);
    if (st) {
        unpack(&p);
        return;
    }
    size_t ne = hpfc_graph_edge_count(g);
    for (size_t e = 0; e < ne; e++) {
        size_t count;
        graph_point(g, e, 0, &count);
        for (size_t k = 0; k + 1 < count; k++) {
            pt s = graph_point(g, e, k, &count), t = graph_point(g, e, k + 1, &count);
            check_segment_points(g, &p, s, t);
            check_near_crossings(g, &p, s, t);
            check_near_crossings(g, &p, t, s);
            check_leaf_lines(g, &p, s);
        }
    }
    hpfc_file_info fi;
    hpfc_file_get_info(p.f, &fi);
    gen_rng rng;
    gen_rng_seed(&rng, seed);
    for (int k = 0; k < randoms; k++) {
        /* over the domain and a margin of a tenth around it */
        int64_t mx = fi.width / 10 + 1, my = fi.height / 10 + 1;
        pt q = {fi.x0 - mx + (int64_t)gen_rng_below(&rng, (uint64_t)(fi.width + 2 * mx)),
                fi.y0 - my + (int64_t)gen_rng_below(&rng, (uint64_t)(fi.height + 2 * my))};
        check_point(g, &p, q);
        if (k % 16 == 0)
            check_leaf_lines(g, &p, q);
    }
    check_batch(&p);
    unpack(&p);
}

/* The contract's edges: NULL faces, a short cap, outside the domain. */
static void check_api(void)
{
    hpfc_graph *g;
    CHECK_EQ_INT(gen_special(GEN_SPECIAL_CRACK, &g), HPFC_OK);
    packed p;
    CHECK_EQ_INT(pack(g, 2, 2, &p), HPFC_OK);
    hpfc_file_info fi;
    hpfc_file_get_info(p.f, &fi);
    hpfc_point_location loc;
    size_t count = 7;
    uint64_t face;
    /* a vertex: several faces, so cap 1 is short */
    int64_t vx, vy;
    hpfc_graph_vertex(g, 0, &vx, &vy);
    CHECK_EQ_INT(hpfc_locate_point(p.f, vx, vy, &loc, NULL, 0, &count), HPFC_OK);
    CHECK(count >= 1);
    CHECK_EQ_INT(loc.on_vertex, 1);
    CHECK_EQ_INT(loc.vertex, 0);
    size_t need = count;
    if (need > 1)
        CHECK_EQ_INT(hpfc_locate_point(p.f, vx, vy, &loc, &face, 1, &count),
                     HPFC_E_BUFFER_SMALL);
    CHECK_EQ_INT(count, need);
    CHECK_EQ_INT(hpfc_locate_point(p.f, fi.x0 - 1, fi.y0, &loc, &face, 1, &count),
                 HPFC_E_NO_PIXEL);
    CHECK_EQ_INT(count, 0);
    CHECK_EQ_INT(hpfc_locate_point(NULL, 0, 0, &loc, &face, 1, &count), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_locate_point(p.f, vx, vy, NULL, &face, 1, &count), HPFC_E_ARG);
    unpack(&p);
    /* a file without GEOM says so */
    hpfc_tree *t;
    uint8_t *bytes;
    size_t size;
    hpfc_file *f;
    hpfc_write_options o = {.face_labels = 1};
    hpfc_build_params bp;
    hpfc_build_params_default(&bp);
    CHECK_EQ_INT(hpfc_build(g, &bp, &t, NULL), HPFC_OK);
    CHECK_EQ_INT(check_tree_serialize(t, &o, &bytes, &size, NULL), HPFC_OK);
    CHECK_EQ_INT(hpfc_open_memory(bytes, size, 0, &f), HPFC_OK);
    CHECK_EQ_INT(hpfc_locate_point(f, vx, vy, &loc, &face, 1, &count), HPFC_E_NO_SECTION);
    hpfc_close(f);
    hpfc_free(bytes);
    hpfc_tree_free(t);
    hpfc_graph_free(g);
}

/* Damaged GEOM and LABL sections: every byte of both, set to 0x00, 0xFF
 * and flipped, opened without the checksum; exact location at the map's
 * vertices, edge midpoints and a grid of points gives a known status and,
 * on success, faces below the face count, ascending (ASan watches the
 * reads). */
static int known(int st)
{
    return st == HPFC_OK || st == HPFC_E_CORRUPT || st == HPFC_E_NO_PIXEL ||
           st == HPFC_E_NO_SECTION || st == HPFC_E_NOMEM || st == HPFC_E_LIMIT;
}

static void check_damage(int kind)
{
    hpfc_graph *g;
    CHECK_EQ_INT(gen_special(kind, &g), HPFC_OK);
    packed p;
    CHECK_EQ_INT(pack(g, 2, 2, &p), HPFC_OK);
    hpfc_file_info fi;
    hpfc_file_get_info(p.f, &fi);
    size_t size = fi.file_size;
    pt q[96];
    size_t nq = 0;
    for (size_t v = 0; v < hpfc_graph_vertex_count(g) && nq < 32; v++)
        hpfc_graph_vertex(g, v, &q[nq].x, &q[nq].y), nq++;
    for (size_t e = 0; e < hpfc_graph_edge_count(g) && nq < 64; e++) {
        size_t count;
        pt a = graph_point(g, e, 0, &count), b = graph_point(g, e, 1, &count);
        q[nq++] = (pt){(a.x + b.x) / 2, (a.y + b.y) / 2};
    }
    for (int i = 0; i < 6; i++)
        for (int j = 0; j < 5 && nq < 96; j++)
            q[nq++] = (pt){fi.x0 + fi.width * i / 6, fi.y0 + fi.height * j / 5};
    uint8_t *copy = malloc(size);
    long opened = 0, answered = 0;
    for (uint32_t k = 0; k < fi.section_count; k++) {
        hpfc_section_info si;
        CHECK_EQ_INT(hpfc_file_get_section(p.f, k, &si), HPFC_OK);
        if (strcmp(si.tag, "GEOM") != 0 && strcmp(si.tag, "LABL") != 0)
            continue;
        for (uint64_t at = si.offset; at < si.offset + si.length; at++)
            for (int how = 0; how < 3; how++) {
                memcpy(copy, p.bytes, size);
                copy[at] = how == 0 ? 0x00 : how == 1 ? 0xFF : (uint8_t)~copy[at];
                hpfc_file *f;
                if (hpfc_open_memory(copy, size, HPFC_OPEN_SKIP_CHECKSUM, &f) != HPFC_OK)
                    continue;
                opened++;
                hpfc_labels_info li;
                uint64_t faces_max = hpfc_file_get_labels(f, &li) == HPFC_OK ? li.faces : 0;
                for (size_t i = 0; i < nq; i++) {
                    hpfc_point_location loc;
                    uint64_t faces[64];
                    size_t count = 0;
                    int st = hpfc_locate_point(f, q[i].x, q[i].y, &loc, faces, 64, &count);
                    CHECK(known(st) || (st == HPFC_E_ARG && count > 64));
                    if (st)
                        continue;
                    answered++;
                    bool ok = count >= 1 && (loc.on_boundary || count == 1);
                    for (size_t c = 0; c < count; c++)
                        ok = ok && faces[c] < faces_max && (c == 0 || faces[c - 1] < faces[c]);
                    CHECK(ok);
                }
                hpfc_close(f);
            }
    }
    CHECK(opened > 0 && answered > 0);
    free(copy);
    unpack(&p);
    hpfc_graph_free(g);
}

int main(void)
{
    int compact = check_use_test_layout();
    check_api();
    check_damage(GEN_SPECIAL_LOOP);
    check_damage(GEN_SPECIAL_MULTI);
    for (int kind = 0; kind < GEN_SPECIAL_COUNT; kind++) {
        hpfc_graph *g;
        CHECK_EQ_INT(gen_special(kind, &g), HPFC_OK);
        check_map(g, 2, 2, 100 + (uint64_t)kind, 400);
        check_map(g, 3, 2, 200 + (uint64_t)kind, 400);
        check_map(g, 1, 3, 300 + (uint64_t)kind, 200);
        hpfc_graph_free(g);
    }
    for (uint64_t seed = 1; seed <= 3; seed++) {
        hpfc_graph *g;
        CHECK_EQ_INT(gen_delaunay(seed, 150, 600, 0.2, &g), HPFC_OK);
        check_map(g, 4, 2, seed, 2000);
        hpfc_graph_free(g);
        CHECK_EQ_INT(gen_polyline(seed, 200, 800, 0.5, &g), HPFC_OK);
        check_map(g, compact ? 2 : 8, 2, seed + 10, 2000);
        hpfc_graph_free(g);
        CHECK_EQ_INT(gen_grid_mesh(seed, 6, 5, 12, &g), HPFC_OK);
        check_map(g, 2, 3, seed + 20, 1000);
        hpfc_graph_free(g);
    }
    printf("points %ld (on the boundary %ld, on a vertex %ld)\n", points_checked, boundary_points,
           vertex_points);
    CHECK(boundary_points > 1000 && vertex_points > 100);
    free(asked_x);
    free(asked_y);
    return check_report("test_locate_point");
}
