/*
 * shapes.c: geometry back from a file (hpfc.h, "Geometry back from the
 * file"): a dart's polyline, and the rings of a face or of a feature's
 * faces, assembled from the GEOM section's coordinates and each edge's
 * left and right faces. Exact throughout: directions are compared by the
 * sign of integer cross products, orientations by exact signed areas, and
 * containment by an exact crossing count, all in 128-bit integers
 * (absolute lattice coordinates stay within 2^41, HPFC_LATTICE_MAX).
 */
#include <stdlib.h>
#include <string.h>

#include "arrays.h"
#include "attrs.h"
#include "feat.h"
#include "file.h"
#include "inverse.h"
#include "ring_index.h"
#include "sized.h"
#include "shapes.h"


/* Coordinates past this come from a corrupt file (a graph's lie within
 * HPFC_LATTICE_MAX): refusing them keeps every difference, cross product
 * and area sum below inside 128 bits. */
#define COORD_LIMIT (2 * HPFC_LATTICE_MAX)

static int coord_ok(int64_t x, int64_t y)
{
    return x >= -COORD_LIMIT && x <= COORD_LIMIT && y >= -COORD_LIMIT && y <= COORD_LIMIT;
}

/* ---- darts ----------------------------------------------------------------------- */

/* Whether lattice point (x, y) lies in the half-open box [x0, x1) x [y0, y1)
 * (the perturbation rule's cells, spec §3.5). */
static int in_box(int64_t x, int64_t y, const int64_t b[4])
{
    return x >= b[0] && x < b[2] && y >= b[1] && y < b[3];
}

/* Reverses the order of n points (x, y pairs). */
static void reverse_points(int64_t *xy, uint64_t n)
{
    for (uint64_t a = 0, b = n ? n - 1 : 0; a < b; a++, b--)
        for (int c = 0; c < 2; c++) {
            int64_t t = xy[2 * a + c];
            xy[2 * a + c] = xy[2 * b + c];
            xy[2 * b + c] = t;
        }
}

int hpfc_geometry_dart_edge(const hpfc_file *f, const hpfc_dart *d, uint64_t *edge,
                            int *reversed)
{
    if (!f || !d || !edge || !reversed)
        return HPFC_E_ARG;
    uint64_t e, u, v, n;
    int64_t box[4], ux, uy, vx, vy;
    int st = hpfc_label_dart_edge(f, d, &e);
    if (!st)
        st = hpfc_geometry_edge(f, e, &u, &v, &n);
    if (!st)
        st = hpfc_pixel_bounds(f, &d->pixel, &box[0], &box[1], &box[2], &box[3]);
    if (!st)
        st = hpfc_geometry_vertex(f, u, &ux, &uy);
    if (!st)
        st = hpfc_geometry_vertex(f, v, &vx, &vy);
    if (st)
        return st;
    int has_u = in_box(ux, uy, box), has_v = in_box(vx, vy, box);
    if (has_u != has_v) {
        *edge = e;
        *reversed = has_v;
        return HPFC_OK;
    }
    if (!has_u || n < 3)
        return HPFC_E_CORRUPT; /* a straight edge cannot leave a box and come back */
    /* Both ends in the pixel: the edge leaves it first on the first segment
     * with an end outside (seen from u), and last comes back on the last
     * such segment; the box being convex, these differ. */
    uint64_t seg, first = n, last = n;
    for (uint64_t k = 1; k + 1 < n; k++) {
        int64_t x, y;
        if ((st = hpfc_geometry_edge_point(f, e, k, &x, &y)))
            return st;
        if (!in_box(x, y, box)) {
            if (first == n)
                first = k - 1;
            last = k;
        }
    }
    if (first == n || (st = hpfc_geometry_crossing_segment(f, &d->pixel, d->crossing, &seg)))
        return st ? st : HPFC_E_CORRUPT;
    if (seg != first && seg != last)
        return HPFC_E_CORRUPT;
    *edge = e;
    *reversed = seg == last;
    return HPFC_OK;
}

int hpfc_geometry_dart_points(const hpfc_file *f, const hpfc_dart *d, int64_t *xy, size_t cap,
                              size_t *count)
{
    if (!count)
        return HPFC_E_ARG;
    uint64_t e, u, v, n;
    int rev, st = hpfc_geometry_dart_edge(f, d, &e, &rev);
    if (!st)
        st = hpfc_geometry_edge(f, e, &u, &v, &n);
    if (st)
        return st;
    if (n > SIZE_MAX / 2)
        return HPFC_E_LIMIT;
    *count = (size_t)n;
    if (!xy)
        return HPFC_OK;
    if (cap < n)
        return HPFC_E_BUFFER_SMALL;
    if (!(st = geom_edge_points(f, e, xy)) && rev)
        reverse_points(xy, n);
    return st;
}

/* ---- user coordinates ------------------------------------------------------------ */

/* v * 10^e, correctly rounded: powers of ten up to 10^22 are exact doubles,
 * so one multiplication or division rounds once. */
static double scaled(int64_t v, int32_t e)
{
    static const double pow10[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                     1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                     1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
    int32_t m = e < 0 ? -e : e;
    double p = pow10[m < 22 ? m : 22];
    double r = e < 0 ? (double)v / p : (double)v * p;
    for (int32_t k = 22; k < m; k++)
        r = e < 0 ? r / 10.0 : r * 10.0;
    return r;
}

/* Called for every point an export writes: the unit read in place, the
 * power of ten from a table. */
void hpfc_user_point(const hpfc_file *f, int64_t x, int64_t y, double *ux, double *uy)
{
    *ux = scaled(x, f->info.unit_exp10);
    *uy = scaled(y, f->info.unit_exp10);
}

/* (double)v for |v| < 2^51 without the conversion instruction, which x86-64
 * has only for one value at a time: v added to the bits of 2^52 + 2^51
 * gives the double 2^52 + 2^51 + v (ulp 1 in that binade), and subtracting
 * 2^52 + 2^51 leaves v exactly. The adds and subtractions go two or more
 * to an instruction (as wide as the target's vectors), and so do the
 * divisions after them. */
#define SMALL_BIAS_BITS UINT64_C(0x4338000000000000)
#define SMALL_BIAS 6755399441055744.0

static double small_to_double(int64_t v)
{
    uint64_t bits = (uint64_t)v + SMALL_BIAS_BITS;
    double d;
    memcpy(&d, &bits, sizeof d);
    return d - SMALL_BIAS;
}

/* Whether every value is in (-2^51, 2^51): small_to_double's range. A
 * pass of its own, branch-free, so that both loops vectorise. */
static int all_small(const int64_t *v, size_t count)
{
    uint64_t out = 0;
    for (size_t k = 0; k < count; k++)
        out |= ((uint64_t)v[k] + (UINT64_C(1) << 51)) >> 52;
    return out == 0;
}

/* An export converts every shape point: the common exponents (|e| <= 22,
 * one exact power of ten) take one division or multiplication per
 * coordinate, several to an instruction when every coordinate is below
 * 2^51 (lattice points are); the others go through scaled(), whose result
 * this equals in every case: each path converts v exactly (or as the
 * conversion instruction rounds it, past 2^53) and rounds once. */
void hpfc_user_points(const hpfc_file *f, const int64_t *xy, size_t n, double *uv)
{
    int32_t e = f->info.unit_exp10;
    size_t count = 2 * n;
    if (e < -22 || e > 22) {
        for (size_t k = 0; k < count; k++)
            uv[k] = scaled(xy[k], e);
        return;
    }
    double p = scaled(1, e < 0 ? -e : e);
    if (all_small(xy, count)) {
        if (e < 0)
            for (size_t k = 0; k < count; k++)
                uv[k] = small_to_double(xy[k]) / p;
        else
            for (size_t k = 0; k < count; k++)
                uv[k] = small_to_double(xy[k]) * p;
    } else if (e < 0) {
        for (size_t k = 0; k < count; k++)
            uv[k] = (double)xy[k] / p;
    } else {
        for (size_t k = 0; k < count; k++)
            uv[k] = (double)xy[k] * p;
    }
}

/* ---- the index ------------------------------------------------------------------- */

/* Frees the hpfc_shapes object's arrays, then the object.
 * (hpfc_graph_free, hpfc_tree_free and hpfc_shapes_free look alike, a free()
 * a member, but each lists the arrays of its own struct.) */
void hpfc_shapes_free(hpfc_shapes *s)
{
    if (!s)
        return;
    size_t E = (size_t)s->edges + 1, V = (size_t)s->vertices + 1, F = (size_t)s->faces + 1;
    shapes_zeroed_free(s->edge, E, sizeof *s->edge);
    shapes_zeroed_free(s->vxy, 2 * V, sizeof *s->vxy);
    shapes_zeroed_free(s->edge_read, (E >> SHAPES_CHUNK_SHIFT) + 1, 1);
    shapes_zeroed_free(s->vertex_read, (V >> SHAPES_CHUNK_SHIFT) + 1, 1);
    shapes_zeroed_free(s->face_mark, F, sizeof *s->face_mark);
    shapes_zeroed_free(s->face_local, F, sizeof *s->face_local);
    shapes_zeroed_free(s->vmark, V, sizeof *s->vmark);
    shapes_zeroed_free(s->vpos, V, sizeof *s->vpos);
    for (int t = 0; t < SHAPES_TABLES; t++) {
        free(s->rows[t].start);
        free(s->rows[t].item);
    }
    free(s->row_copy);
    free(s->darts);
    free(s->dsorted);
    free(s->dkeys);
    free(s->ept);
    free(s->part);
    free(s->part_outer);
    free(s->cycle);
    free(s->txy);
    free(s->rings);
    free(s->ring_point);
    free(s->polygon_ring);
    shapes_zeroed_free(s->edge_box, (size_t)s->edges + 1, sizeof *s->edge_box);
    shapes_window_free(s, s->window);
    shapes_topo_free(s->topo);
    shapes_near_free(s->near);
    free(s);
}

uint64_t hpfc_shapes_face_count(const hpfc_shapes *s)
{
    return s ? s->faces : 0;
}

/* Each face's edges, in memory: a file without SHIX's (an edge with one
 * face on both sides bounds nothing and is left out). */
static int build_face_edges(hpfc_shapes *s)
{
    int st = shapes_read_all(s);
    inverse_table t = {0};
    if (!st)
        st = inverse_begin(&t, s->faces);
    for (int pass = 0; pass < 2 && !st; pass++) {
        for (uint64_t e = 0; e < s->edges; e++) {
            if (s->edge[e].left == s->edge[e].right)
                continue;
            if (pass == 0) {
                inverse_count(&t, s->edge[e].left);
                inverse_count(&t, s->edge[e].right);
            } else {
                inverse_put(&t, s->edge[e].left, (uint32_t)e);
                inverse_put(&t, s->edge[e].right, (uint32_t)e);
            }
        }
        if (pass == 0)
            st = inverse_room(&t, UINT64_MAX);
    }
    if (st) {
        inverse_free(&t);
        return st;
    }
    inverse_done(&t);
    s->rows[FACE_EDGES].start = t.start;
    s->rows[FACE_EDGES].item = t.item;
    return HPFC_OK;
}

/* Room for each edge's record and each vertex's coordinates, read a
 * chunk at a time on first use (shapes_edges.c); untouched until then, so
 * a query pays a page fault for each page of them it writes first. */
static int index_edges(hpfc_shapes *s)
{
    size_t E = (size_t)s->edges + 1, V = (size_t)s->vertices + 1;
    s->edge = shapes_zeroed(E, sizeof *s->edge);
    s->vxy = shapes_zeroed(2 * V, sizeof *s->vxy);
    s->edge_read = shapes_zeroed((E >> SHAPES_CHUNK_SHIFT) + 1, 1);
    s->vertex_read = shapes_zeroed((V >> SHAPES_CHUNK_SHIFT) + 1, 1);
    if (!s->edge || !s->vxy ||
        !s->edge_read || !s->vertex_read)
        return HPFC_E_NOMEM;
    return HPFC_OK;
}

/* The links of rows [0, rows) (faces or edges) inverted: for each feature,
 * the rows that link it, in increasing order. */
static int invert_links(const feature_links *t, uint64_t rows, uint32_t features,
                        shapes_rows *out)
{
    inverse_table inv;
    int st = inverse_begin(&inv, features);
    /* the links read straight from the section: a row's run at a time */
    const uint8_t *link = t->index + 4 * ((size_t)t->rows + 1);
    for (int pass = 0; pass < 2 && !st; pass++) {
        for (uint64_t o = 0; o < rows && !st; o++) {
            uint32_t first, end;
            st = feature_links_row(t, o, &first, &end);
            for (uint32_t i = first; i < end && !st; i++) {
                uint32_t ft = (uint32_t)le_load(link + 4 * (size_t)i, 4);
                if (ft >= features || ft >= t->features)
                    st = HPFC_E_CORRUPT;
                else if (pass == 0)
                    inverse_count(&inv, ft);
                else
                    inverse_put(&inv, ft, (uint32_t)o);
            }
        }
        if (!st && pass == 0)
            st = inverse_room(&inv, UINT64_MAX);
    }
    if (st) {
        inverse_free(&inv);
        return st;
    }
    inverse_done(&inv);
    out->start = inv.start;
    out->item = inv.item;
    return HPFC_OK;
}

/* Table t read in place from SHIX when the section holds it (bit
 * `table`, 0 for the faces' edges, which it always holds): *mapped true.
 * A SHIX whose counts are not the map's is HPFC_E_CORRUPT: a writer
 * derives it from the same LABL, FEAT and EDGF (spec §6.8.3). */
static int map_table(hpfc_shapes *s, enum shapes_table t, uint32_t table, bool *mapped)
{
    const shix_view *x = &s->f->shix;
    *mapped = false;
    if (!x->present || (table && !(x->tables & table)))
        return HPFC_OK;
    if (x->faces != s->faces || x->edges != s->edges || (table && x->features != s->features))
        return HPFC_E_CORRUPT;
    const shix_table *src = t == FACE_EDGES      ? &x->face_edges
                               : t == FEATURE_FACES ? &x->feature_faces
                                                    : &x->feature_edges;
    s->rows[t].mapped = *src;
    *mapped = true;
    return HPFC_OK;
}

/* FEAT's faces of each feature and EDGF's edges, where the file has them:
 * from SHIX, or FEAT and EDGF inverted. */
static int index_features(hpfc_shapes *s)
{
    hpfc_features_info fi;
    feature_links links;
    bool mapped;
    int st = hpfc_file_get_features(s->f, &fi);
    if (st == HPFC_E_NO_SECTION)
        return HPFC_OK;
    if (!st)
        st = features_face_links(s->f, true, &links);
    if (st)
        return st;
    s->have_features = 1;
    s->features = fi.features;
    s->face_links = links;
    /* a FEAT table numbered against other faces is not to be used (§6.2.2) */
    uint64_t faces = fi.faces == s->faces ? s->faces : 0;
    s->face_features = faces != 0;
    st = faces ? map_table(s, FEATURE_FACES, SHIX_FEATURE_FACES, &mapped) : HPFC_OK;
    if (!st && (!faces || !mapped))
        st = invert_links(&links, faces, fi.features, &s->rows[FEATURE_FACES]);
    if (st)
        return st;
    st = attrs_edge_links(s->f, true, &links);
    if (st == HPFC_E_NO_SECTION)
        return HPFC_OK;
    if (st)
        return st;
    if (links.rows != s->edges)
        return HPFC_E_CORRUPT;
    s->have_edge_features = 1;
    s->edge_links = links;
    if ((st = map_table(s, FEATURE_EDGES, SHIX_FEATURE_EDGES, &mapped)) || mapped)
        return st;
    return invert_links(&links, links.rows, fi.features, &s->rows[FEATURE_EDGES]);
}

/* Row `row` of table t as an array (a mapped row copied out). */
static int row_array(hpfc_shapes *s, enum shapes_table t, uint64_t row, const uint32_t **items,
                     size_t *n)
{
    uint64_t a, b;
    int st = shapes_row(s, t, row, &a, &b);
    if (st)
        return st;
    *n = (size_t)(b - a);
    if (!s->rows[t].mapped.bits.base) {
        *items = s->rows[t].item + a;
        return HPFC_OK;
    }
    if ((st = array_grow((void **)&s->row_copy, &s->cap_row_copy, *n + 1, sizeof *s->row_copy)))
        return st;
    for (size_t k = 0; k < *n; k++)
        s->row_copy[k] = shapes_item(s, t, a + k);
    *items = s->row_copy;
    return HPFC_OK;
}

/* The scratch arrays that hold a feature's points (its edges' points, then
 * its rings'), reserved once for as many points as the file has, up to
 * SCRATCH_POINTS. Grown from 16 by doubling, they were reallocated a dozen
 * times on a large feature, each time into pages the process had not
 * touched, and those page faults were most of what reading the large
 * features of a world layer through the GDAL driver cost (bench/README.md,
 * "Fewer pages touched"). Reserved memory is only address space until
 * written. */
enum { SCRATCH_POINTS = 1 << 18 };

static int reserve_point_scratch(hpfc_shapes *s)
{
    uint64_t all = s->points + s->vertices;
    size_t n = all < SCRATCH_POINTS ? (size_t)all + 1 : SCRATCH_POINTS;
    if (array_grow((void **)&s->ept, &s->cap_ept, 2 * n, sizeof *s->ept) ||
        array_grow((void **)&s->txy, &s->cap_txy, 2 * n, sizeof *s->txy))
        return HPFC_E_NOMEM;
    return HPFC_OK;
}

int hpfc_shapes_create(const hpfc_file *f, hpfc_shapes **out)
{
    if (!f || !out)
        return HPFC_E_ARG;
    *out = NULL;
    if (!file_has_exact_geometry(f))
        return HPFC_E_NO_SECTION;
    const geom_view *gi = &f->geom;
    const labels_view *li = &f->labels;
    if (gi->edges != li->edges)
        return HPFC_E_CORRUPT;
    /* Counts a corrupt file may invent, bounded by what a valid one pays
     * for, before anything is allocated or walked: LABL's edges and faces
     * (labels_counts_paid; GEOM's edges are LABL's); no vertex is isolated
     * (V <= 2E); and GEOM spends at least a bit on each shape point
     * (consecutive points differ). */
    if (!labels_counts_paid(li) || gi->vertices > 2 * gi->edges ||
        gi->points / 8 > gi->section_length)
        return HPFC_E_CORRUPT;
    if (gi->vertices >= UINT32_MAX || gi->edges >= UINT32_MAX || li->faces >= UINT32_MAX ||
        gi->vertices > SIZE_MAX / 16 || gi->edges > SIZE_MAX / 64)
        return HPFC_E_LIMIT;
    int st;
    hpfc_shapes *s = calloc(1, sizeof *s);
    if (!s)
        return HPFC_E_NOMEM;
    s->f = f;
    s->max_points = HPFC_LIMIT_POINTS_DEFAULT;
    s->max_items = HPFC_LIMIT_ITEMS_DEFAULT;
    s->vertices = gi->vertices, s->edges = gi->edges, s->faces = li->faces, s->points = gi->points;
    const hpfc_file_info *fi = &f->info;
    s->domain_in_limit = fi->x0 >= -COORD_LIMIT && fi->x0 <= COORD_LIMIT &&
                         fi->y0 >= -COORD_LIMIT && fi->y0 <= COORD_LIMIT && fi->width >= 0 &&
                         fi->height >= 0 && fi->width <= COORD_LIMIT - fi->x0 &&
                         fi->height <= COORD_LIMIT - fi->y0;
    bool mapped = false;
    st = index_edges(s);
    if (!st)
        st = map_table(s, FACE_EDGES, 0, &mapped);
    if (!st && !mapped)
        st = build_face_edges(s);
    if (!st)
        st = index_features(s);
    if (!st) {
        s->face_mark = shapes_zeroed(s->faces + 1, sizeof *s->face_mark);
        s->face_local = shapes_zeroed(s->faces + 1, sizeof *s->face_local);
        s->vmark = shapes_zeroed(s->vertices + 1, sizeof *s->vmark);
        s->vpos = shapes_zeroed(s->vertices + 1, sizeof *s->vpos);
        if (!s->face_mark || !s->face_local || !s->vmark || !s->vpos)
            st = HPFC_E_NOMEM;
    }
    if (!st)
        st = reserve_point_scratch(s);
    if (st) {
        hpfc_shapes_free(s);
        return st;
    }
    *out = s;
    return HPFC_OK;
}

/* What every per-feature call checks first: s and its output given, the
 * section it reads present, `feature` one of the map's. */
static int check_feature_call(const hpfc_shapes *s, const void *out, enum shapes_table need,
                              hpfc_id feature)
{
    if (!s || !out)
        return HPFC_E_ARG;
    if (!(need == FEATURE_EDGES ? s->have_edge_features : s->have_features))
        return HPFC_E_NO_SECTION;
    return feature < s->features ? HPFC_OK : HPFC_E_ARG;
}

int hpfc_shapes_feature_faces(const hpfc_shapes *s, hpfc_id feature, hpfc_id *faces, size_t cap,
                              size_t *count)
{
    int st = check_feature_call(s, count, FEATURE_FACES, feature);
    if (st)
        return st;
    uint64_t a, b;
    /* a faces row reads no edge: the object stays as it was */
    if ((st = shapes_row((hpfc_shapes *)s, FEATURE_FACES, feature, &a, &b)))
        return st;
    *count = (size_t)(b - a);
    if (!faces)
        return HPFC_OK;
    if (cap < b - a)
        return HPFC_E_BUFFER_SMALL;
    for (uint64_t k = a; k < b; k++)
        faces[k - a] = shapes_item(s, FEATURE_FACES, k);
    return HPFC_OK;
}

/* Whether feature `row`'s row of the faces table is not empty, from its
 * offsets alone (shapes_row checks the row when it is read). */
static int covers_faces(const hpfc_shapes *s, uint64_t row)
{
    const shapes_rows *r = &s->rows[FEATURE_FACES];
    if (r->mapped.bits.base)
        return shix_offset(&r->mapped, row + 1) > shix_offset(&r->mapped, row);
    return r->start[row + 1] > r->start[row];
}

int hpfc_shapes_layer_kinds(const hpfc_shapes *s, uint8_t *kinds, uint64_t *counts,
                            size_t layer_count)
{
    if (!s || !kinds)
        return HPFC_E_ARG;
    if (!s->have_features)
        return HPFC_E_NO_SECTION;
    hpfc_features_info fi;
    int st = hpfc_file_get_features(s->f, &fi);
    if (st)
        return st;
    if (layer_count != fi.layers)
        return HPFC_E_ARG;
    memset(kinds, 0, layer_count);
    if (counts)
        memset(counts, 0, layer_count * sizeof *counts);
    /* the layers a chunk at a time: one layer needs none read (S8 holds
     * every feature's below 1, checked when a feature is read); none
     * makes every feature's a layer past them */
    enum { CHUNK = 256 };
    uint32_t layer[CHUNK] = {0};
    for (uint32_t k = 0; k < s->features; k += CHUNK) {
        uint32_t n = s->features - k < CHUNK ? s->features - k : CHUNK;
        if (fi.layers != 1 && (st = features_layers(s->f, k, n, layer)))
            return st;
        for (uint32_t j = 0; j < n; j++) {
            kinds[layer[j]] |= covers_faces(s, k + j) ? HPFC_KIND_POLYGONS : HPFC_KIND_LINES;
            if (counts)
                counts[layer[j]]++;
        }
    }
    return HPFC_OK;
}

/* ---- exact predicates -------------------------------------------------------------- */

/* 0 for directions in [0, pi), 1 in [pi, 2 pi), counter-clockwise from +x. */
static int half_of(const int64_t d[2])
{
    return d[1] < 0 || (d[1] == 0 && d[0] < 0);
}

/* The order of two non-zero directions by angle counter-clockwise from +x. */
static int cmp_angle(const int64_t a[2], const int64_t b[2])
{
    int ha = half_of(a), hb = half_of(b);
    if (ha != hb)
        return ha - hb;
    s128 c = (s128)a[0] * b[1] - (s128)a[1] * b[0];
    return c > 0 ? -1 : c < 0;
}

static int cmp_dart(const void *pa, const void *pb)
{
    const bdart *a = pa, *b = pb;
    if (a->origin != b->origin)
        return a->origin < b->origin ? -1 : 1;
    return cmp_angle(a->out, b->out);
}

/* ---- the region's parts ----------------------------------------------------------- */

/* The region's faces (face_local numbers them) fall into parts, joined
 * across the edges that have the region on both sides. A hole's part
 * surrounds it and lies within the part's outer boundary, so a part with
 * one outer ring owns all its holes (own_by_part): no geometry needed. */
static int parts_init(hpfc_shapes *s, size_t n)
{
    if (array_grow((void **)&s->part, &s->cap_part, n + 1, sizeof *s->part))
        return HPFC_E_NOMEM;
    for (size_t k = 0; k < n; k++)
        s->part[k] = (uint32_t)k;
    s->nparts = n;
    return HPFC_OK;
}

static uint32_t part_of(hpfc_shapes *s, uint64_t face)
{
    uint32_t x = s->face_local[face];
    while (s->part[x] != x)
        x = s->part[x] = s->part[s->part[x]]; /* path halving */
    return x;
}

static void parts_join(hpfc_shapes *s, uint64_t f, uint64_t g)
{
    uint32_t a = part_of(s, f), b = part_of(s, g);
    s->part[a > b ? a : b] = a < b ? a : b;
}

/* ---- assembling rings -------------------------------------------------------------- */

/* Decodes edge e's points (u to v) onto the end of s->ept; *at: the
 * first. */
static int load_edge(hpfc_shapes *s, uint64_t e, size_t *at)
{
    int st = shapes_need_edge(s, e);
    if (st)
        return st;
    uint64_t n = shapes_edge_points(s, e);
    if (array_grow((void **)&s->ept, &s->cap_ept, 2 * (s->nept + n), sizeof *s->ept))
        return HPFC_E_NOMEM;
    int64_t *p = s->ept + 2 * s->nept;
    memcpy(p, s->vxy + 2 * (size_t)s->edge[e].u, 2 * sizeof *p);
    memcpy(p + 2 * (n - 1), s->vxy + 2 * (size_t)s->edge[e].v, 2 * sizeof *p);
    st = geom_points(s->f, GEOM_PX, s->edge[e].first, n - 2, p + 2);
    /* GEOM's points lie in the domain (geom_points checks): within the
     * limit when the domain is */
    for (uint64_t k = 0; k < n && !st && !s->domain_in_limit; k++)
        if (!coord_ok(p[2 * k], p[2 * k + 1]))
            st = HPFC_E_CORRUPT;
    if (!st) {
        *at = s->nept;
        s->nept += n;
    }
    return st;
}

/* The dart of edge e with the region's face `face` on its left (v to u
 * when reversed); its points are counted now and read by load_darts. */
static int add_dart(hpfc_shapes *s, uint64_t e, int reversed, uint64_t face)
{
    int st = shapes_need_edge(s, e);
    if (st)
        return st;
    if (shapes_take_points(s, shapes_edge_points(s, e)))
        return HPFC_E_OVER_LIMIT;
    if (array_grow((void **)&s->darts, &s->cap_darts, s->ndarts + 1, sizeof *s->darts))
        return HPFC_E_NOMEM;
    bdart *d = &s->darts[s->ndarts++];
    memset(d, 0, sizeof *d);
    d->code = e << 1 | (uint64_t)reversed;
    d->face = (uint32_t)face;
    d->origin = reversed ? s->edge[e].v : s->edge[e].u;
    d->target = reversed ? s->edge[e].u : s->edge[e].v;
    return HPFC_OK;
}

/* Room in *p (pairs) for as many points as this call has counted
 * (call_points), which bounds both the darts' edge points and the rings'. */
static int reserve_call_points(const hpfc_shapes *s, int64_t **p, size_t *cap)
{
    if (s->call_points > SIZE_MAX / 4)
        return HPFC_E_NOMEM;
    return array_grow((void **)p, cap, 2 * ((size_t)s->call_points + 1), sizeof **p);
}

/* Every dart's points, decoded once for the ring that takes it, into an
 * array sized once from the points counted (call_points): grown an edge
 * at a time, a large feature's points were copied a dozen times into
 * pages not touched before. Then each dart's first and last directions. */
static int load_darts(hpfc_shapes *s)
{
    if (reserve_call_points(s, &s->ept, &s->cap_ept))
        return HPFC_E_NOMEM;
    for (size_t k = 0; k < s->ndarts; k++) {
        bdart *d = &s->darts[k];
        uint64_t e = d->code >> 1;
        int st = load_edge(s, e, &d->pts);
        if (st)
            return st;
        uint64_t n = shapes_edge_points(s, e);
        /* first two and last two points, u -> v */
        const int64_t *p0 = s->ept + 2 * d->pts, *p1 = p0 + 2, *q0 = p0 + 2 * (n - 2),
                      *q1 = p0 + 2 * (n - 1);
        int64_t fwd[2] = {p1[0] - p0[0], p1[1] - p0[1]}, bwd[2] = {q0[0] - q1[0], q0[1] - q1[1]};
        if ((!fwd[0] && !fwd[1]) || (!bwd[0] && !bwd[1]))
            return HPFC_E_CORRUPT; /* a zero-length segment */
        int reversed = (int)(d->code & 1);
        memcpy(d->out, reversed ? bwd : fwd, sizeof d->out);
        memcpy(d->back, reversed ? fwd : bwd, sizeof d->back);
    }
    return HPFC_OK;
}

/* A new stamp for vmark (the stamps cleared when they wrap). */
static void next_vgen(hpfc_shapes *s)
{
    if (++s->vgen == 0) {
        memset(s->vmark, 0, (s->vertices + 1) * sizeof *s->vmark);
        s->vgen = 1;
    }
}

/* Sorts the darts by origin, then by angle (cmp_dart): by origin with
 * key_sort, then each vertex's few darts by angle. */
static int sort_darts(hpfc_shapes *s)
{
    size_t n = s->ndarts;
    if (array_grow((void **)&s->dkeys, &s->cap_dkeys, 2 * n, sizeof *s->dkeys) ||
        array_grow((void **)&s->dsorted, &s->cap_dsorted, n, sizeof *s->dsorted))
        return HPFC_E_NOMEM;
    for (size_t k = 0; k < n; k++)
        s->dkeys[k] = (key_item){s->darts[k].origin, (uint32_t)k};
    key_sort(s->dkeys, s->dkeys + n, n);
    for (size_t k = 0; k < n; k++)
        s->dsorted[k] = s->darts[s->dkeys[k].index];
    bdart *t = s->darts;
    s->darts = s->dsorted, s->dsorted = t;
    size_t c = s->cap_darts;
    s->cap_darts = s->cap_dsorted, s->cap_dsorted = c;
    /* each vertex's darts: from vpos[v] on, where vmark[v] holds the stamp */
    next_vgen(s);
    for (size_t a = 0, b; a < n; a = b) {
        uint32_t v = s->darts[a].origin;
        for (b = a + 1; b < n && s->darts[b].origin == v; b++)
            ;
        if (b - a > 1)
            qsort(s->darts + a, b - a, sizeof *s->darts, cmp_dart);
        s->vmark[v] = s->vgen;
        s->vpos[v] = (uint32_t)a;
    }
    return HPFC_OK;
}

/* Links each dart to the one continuing it: at its target, the first dart
 * leaving clockwise from the way it came (the region's corner). A file
 * whose boundary does not pair up is corrupt. */
static int link_darts(hpfc_shapes *s)
{
    size_t n = s->ndarts;
    if (n == 0)
        return HPFC_OK; /* a face all of whose edges are bridges: no ring */
    int st = sort_darts(s);
    if (st)
        return st;
    bdart *D = s->darts;
    for (size_t k = 0; k < n; k++) {
        uint32_t t = D[k].target;
        if (s->vmark[t] != s->vgen)
            return HPFC_E_CORRUPT; /* the boundary ends at t */
        /* the darts leaving t: [first, end); end found by bisection, since
         * a scan would cost a vertex of degree d its d darts d times */
        size_t first = s->vpos[t], lo = first + 1, hi = n;
        while (lo < hi) {
            size_t mid = lo + (hi - lo) / 2;
            if (D[mid].origin == t)
                lo = mid + 1;
            else
                hi = mid;
        }
        size_t end = lo;
        /* the first of them at an angle not below the way back */
        lo = first, hi = end;
        while (lo < hi) {
            size_t mid = lo + (hi - lo) / 2;
            if (cmp_angle(D[mid].out, D[k].back) < 0)
                lo = mid + 1;
            else
                hi = mid;
        }
        size_t next = lo > first ? lo - 1 : end - 1;
        if (D[next].has_prev)
            return HPFC_E_CORRUPT;
        D[next].has_prev = 1;
        D[k].next = (uint32_t)next;
    }
    return HPFC_OK;
}

/* Appends points [from, to) of the n points s->ept[2 * at ..] (an edge's,
 * u to v), taken from v to u when rev. */
static int add_points(hpfc_shapes *s, size_t at, uint64_t n, int rev, uint64_t from, uint64_t to)
{
    if (array_grow((void **)&s->txy, &s->cap_txy, 2 * (s->ntxy + to - from), sizeof *s->txy))
        return HPFC_E_NOMEM;
    const int64_t *src = s->ept + 2 * at;
    int64_t *dst = s->txy + 2 * s->ntxy;
    if (!rev) {
        memcpy(dst, src + 2 * from, 2 * (to - from) * sizeof *dst);
    } else {
        for (uint64_t j = from; j < to; j++, dst += 2) {
            uint64_t k = n - 1 - j;
            dst[0] = src[2 * k];
            dst[1] = src[2 * k + 1];
        }
    }
    s->ntxy += to - from;
    return HPFC_OK;
}

static int add_point(hpfc_shapes *s, int64_t x, int64_t y)
{
    if (!coord_ok(x, y))
        return HPFC_E_CORRUPT;
    if (array_grow((void **)&s->txy, &s->cap_txy, 2 * (s->ntxy + 1), sizeof *s->txy))
        return HPFC_E_NOMEM;
    s->txy[2 * s->ntxy] = x;
    s->txy[2 * s->ntxy + 1] = y;
    s->ntxy++;
    return HPFC_OK;
}

/* Ring from darts cycle[a .. b): each dart's points but its last, then the
 * first point again; its area and box. */
static int emit_ring(hpfc_shapes *s, size_t a, size_t b)
{
    if (array_grow((void **)&s->rings, &s->cap_rings, s->nrings + 1, sizeof *s->rings))
        return HPFC_E_NOMEM;
    tring *r = &s->rings[s->nrings];
    r->start = s->ntxy;
    r->owner = SIZE_MAX;
    r->part = part_of(s, s->darts[s->cycle[a]].face);
    int st = HPFC_OK;
    for (size_t k = a; k < b && !st; k++) {
        const bdart *d = &s->darts[s->cycle[k]];
        uint64_t n = shapes_edge_points(s, d->code >> 1);
        st = add_points(s, d->pts, n, (int)(d->code & 1), 0, n - 1);
    }
    if (st)
        return st;
    if (s->ntxy - r->start < 2)
        return HPFC_E_CORRUPT;
    if ((st = add_point(s, s->txy[2 * r->start], s->txy[2 * r->start + 1])))
        return st;
    r->end = s->ntxy;
    s128 area = 0;
    const int64_t *p = s->txy + 2 * r->start;
    r->box[0] = r->box[2] = p[0];
    r->box[1] = r->box[3] = p[1];
    for (size_t k = 0; k + 1 < r->end - r->start; k++) {
        area += (s128)p[2 * k] * p[2 * k + 3] - (s128)p[2 * k + 2] * p[2 * k + 1];
        int64_t x = p[2 * k + 2], y = p[2 * k + 3];
        r->box[0] = x < r->box[0] ? x : r->box[0];
        r->box[1] = y < r->box[1] ? y : r->box[1];
        r->box[2] = x > r->box[2] ? x : r->box[2];
        r->box[3] = y > r->box[3] ? y : r->box[3];
    }
    if (area == 0)
        return HPFC_E_CORRUPT; /* a simple ring of distinct edges encloses something */
    r->area2 = area;
    s->nrings++;
    return HPFC_OK;
}

/* Follows the links from every unused dart; each closed walk is cut into
 * simple rings wherever it comes back to a vertex it has passed. */
static int trace_rings(hpfc_shapes *s)
{
    size_t n = s->ndarts;
    if (array_grow((void **)&s->cycle, &s->cap_cycle, n + 1, sizeof *s->cycle))
        return HPFC_E_NOMEM;
    for (size_t start = 0; start < n; start++) {
        if (s->darts[start].used)
            continue;
        next_vgen(s);
        size_t top = 0; /* the walk so far, cut loops removed: cycle[0 .. top) */
        size_t d = start;
        for (size_t steps = 0; !s->darts[d].used; steps++) {
            if (steps > n)
                return HPFC_E_CORRUPT;
            bdart *D = &s->darts[d];
            D->used = 1;
            uint32_t o = D->origin;
            if (s->vmark[o] == s->vgen) { /* back at o: the darts since form a ring */
                size_t at = s->vpos[o];
                int st = emit_ring(s, at, top);
                if (st)
                    return st;
                for (size_t k = at; k < top; k++)
                    s->vmark[s->darts[s->cycle[k]].origin] = 0;
                top = at;
            }
            s->vmark[o] = s->vgen;
            s->vpos[o] = (uint32_t)top;
            s->cycle[top++] = (uint32_t)d;
            d = D->next;
        }
        if (d != start)
            return HPFC_E_CORRUPT; /* the links do not close this walk */
        if (top) {
            int st = emit_ring(s, 0, top);
            if (st)
                return st;
        }
    }
    return HPFC_OK;
}

/* Where point p (doubled) lies against ring o: through its index when it
 * has one. */
static int locate_in(const hpfc_shapes *s, const tring *o, const ring_index *oi, const int64_t p[2])
{
    return oi && oi->levels ? ring_index_locate(oi, p)
                            : ring_locate(s->txy + 2 * o->start, o->end - o->start, p);
}

/* Whether ring h lies inside ring o (oi: o's index, or NULL): the first
 * point of h (or middle of its segments) that is not on o decides; rings
 * never cross. */
static int ring_inside(const hpfc_shapes *s, const tring *h, const tring *o, const ring_index *oi)
{
    if (h->box[0] < o->box[0] || h->box[1] < o->box[1] || h->box[2] > o->box[2] ||
        h->box[3] > o->box[3])
        return 0;
    const int64_t *hp = s->txy + 2 * h->start;
    size_t hn = h->end - h->start;
    for (size_t k = 0; k + 1 < hn; k++) {
        int64_t p[2] = {2 * hp[2 * k], 2 * hp[2 * k + 1]};
        int w = locate_in(s, o, oi, p);
        if (w >= 0)
            return w;
    }
    for (size_t k = 0; k + 1 < hn; k++) {
        int64_t p[2] = {hp[2 * k] + hp[2 * k + 2], hp[2 * k + 1] + hp[2 * k + 3]};
        int w = locate_in(s, o, oi, p);
        if (w >= 0)
            return w;
    }
    return 0;
}

/* An outer ring with at least this many points is indexed (ring_index.h)
 * when a hole is tested against it: below, a pass over it is as cheap. */
enum { INDEX_MIN_POINTS = 64 };

/* What finding the holes' owners keeps: the outer rings (their ring
 * numbers, boxes, a tree over the boxes, each one's index once built), the
 * candidates of one hole. */
typedef struct owners {
    size_t *outer;       /* ring number of outer k */
    int64_t (*box)[4];
    box_tree tree;
    ring_index *index;   /* per outer, levels 0 until built */
    uint32_t *cand;
    size_t ncand, cap_cand;
} owners;

static void owners_free(owners *w, size_t outers)
{
    for (size_t k = 0; w->index && k < outers; k++)
        ring_index_free(&w->index[k]);
    free(w->index);
    free(w->outer);
    free(w->box);
    free(w->cand);
    box_tree_free(&w->tree);
}

/* A candidate owner of a hole, in the order owners are chosen in:
 * smallest area first, then the earlier ring (the first of equal smallest
 * wins). */
typedef struct candidate {
    s128 area2;
    size_t ring;
    uint32_t outer;
} candidate;

static int cmp_candidate(const void *pa, const void *pb)
{
    const candidate *a = pa, *b = pb;
    if (a->area2 != b->area2)
        return a->area2 < b->area2 ? -1 : 1;
    return (a->ring > b->ring) - (a->ring < b->ring);
}

/* The outer rings, a tree over their boxes, room for their indexes. */
static int owners_init(hpfc_shapes *s, owners *w, size_t outers)
{
    memset(w, 0, sizeof *w);
    w->outer = malloc((outers + 1) * sizeof *w->outer);
    w->box = malloc((outers + 1) * sizeof *w->box);
    w->index = calloc(outers + 1, sizeof *w->index);
    if (!w->outer || !w->box || !w->index)
        return HPFC_E_NOMEM;
    size_t k = 0;
    for (size_t r = 0; r < s->nrings; r++)
        if (s->rings[r].area2 > 0) {
            w->outer[k] = r;
            memcpy(w->box[k], s->rings[r].box, sizeof w->box[k]);
            k++;
        }
    return box_tree_build(&w->tree, (const int64_t(*)[4])w->box, outers);
}

/* Hole h's owner: the smallest outer ring containing it, of those with a
 * larger area (owner stays SIZE_MAX when none). The tree gives the outers
 * whose box holds h's; they are tried smallest first, each long one
 * through its index. */
static int find_owner(hpfc_shapes *s, owners *w, size_t h, candidate **cand, size_t *cap)
{
    tring *H = &s->rings[h];
    w->ncand = 0;
    int st = box_tree_containing(&w->tree, H->box, &w->cand, &w->ncand, &w->cap_cand);
    if (st)
        return st;
    if (array_grow((void **)cand, cap, w->ncand + 1, sizeof **cand))
        return HPFC_E_NOMEM;
    size_t n = 0;
    for (size_t k = 0; k < w->ncand; k++) {
        size_t r = w->outer[w->cand[k]];
        if (s->rings[r].area2 > -H->area2)
            (*cand)[n++] = (candidate){s->rings[r].area2, r, w->cand[k]};
    }
    qsort(*cand, n, sizeof **cand, cmp_candidate);
    for (size_t k = 0; k < n; k++) {
        const tring *O = &s->rings[(*cand)[k].ring];
        ring_index *oi = &w->index[(*cand)[k].outer];
        if (!oi->levels && O->end - O->start >= INDEX_MIN_POINTS &&
            (st = ring_index_build(oi, s->txy + 2 * O->start, O->end - O->start)))
            return st;
        if (ring_inside(s, H, O, oi)) {
            H->owner = (*cand)[k].ring;
            break;
        }
    }
    return HPFC_OK;
}

/* Gives each hole the outer ring of its part where the part has exactly
 * one, as a part joined across edges has; *rest: the holes left (a part
 * with no outer ring or several), for find_owner's search by geometry. */
static int own_by_part(hpfc_shapes *s, size_t *rest)
{
    const size_t none = SIZE_MAX, several = SIZE_MAX - 1;
    if (array_grow((void **)&s->part_outer, &s->cap_part_outer, s->nparts + 1,
                   sizeof *s->part_outer))
        return HPFC_E_NOMEM;
    for (size_t c = 0; c < s->nparts; c++)
        s->part_outer[c] = none;
    for (size_t r = 0; r < s->nrings; r++)
        if (s->rings[r].area2 > 0) {
            size_t *o = &s->part_outer[s->rings[r].part];
            *o = *o == none ? r : several;
        }
    *rest = 0;
    for (size_t h = 0; h < s->nrings; h++) {
        tring *H = &s->rings[h];
        if (H->area2 < 0 && s->part_outer[H->part] < several)
            H->owner = s->part_outer[H->part];
        else if (H->area2 < 0)
            (*rest)++;
    }
    return HPFC_OK;
}

/* Ring r as the answer's next ring: copied to s->ept, whose darts' points
 * are no longer needed once the rings are traced (an array of the
 * answer's own was a third as large as the feature, its pages touched for
 * this copy alone), or, where the answer is the traced points as they lie
 * (in_place), only numbered. */
static void put_ring(hpfc_shapes *s, size_t r, int in_place, size_t *rings, size_t *points)
{
    const tring *R = &s->rings[r];
    size_t n = R->end - R->start;
    if (!in_place)
        memcpy(s->ept + 2 * *points, s->txy + 2 * R->start, 2 * n * sizeof *s->ept);
    s->ring_point[(*rings)++] = *points;
    *points += n;
}

/* Whether the answer's ring order (outer rings in ring order, each with
 * its holes, then the holes of none) leaves every ring where tracing put
 * it in s->txy: one polygon, or islands with no holes, the usual feature.
 * Then the answer points into s->txy and its points are not copied: a
 * second array as large as the feature, touched for nothing. */
static int answer_in_place(const hpfc_shapes *s, const size_t *first, const size_t *hole)
{
    size_t nr = s->nrings, at = 0;
    for (size_t o = 0; o <= nr; o++) {
        if (o < nr) {
            if (s->rings[o].area2 <= 0)
                continue;
            if (s->rings[o].start != at)
                return 0;
            at = s->rings[o].end;
        }
        for (size_t k = first[o]; k < first[o + 1]; k++) {
            if (s->rings[hole[k]].start != at)
                return 0;
            at = s->rings[hole[k]].end;
        }
    }
    return 1;
}

/* Each hole to the smallest outer ring containing it; then the answer:
 * polygons (outer, its holes), in ring order, the holes of none last.
 * O((rings + candidates) log + the points tested), where the old pairwise
 * search cost holes x outer rings x their points. */
static int arrange(hpfc_shapes *s, hpfc_polygons *out)
{
    size_t nr = s->nrings, outers = 0, holes = 0;
    for (size_t r = 0; r < nr; r++)
        s->rings[r].area2 > 0 ? outers++ : holes++;
    size_t rest = 0;
    int st = holes && outers ? own_by_part(s, &rest) : HPFC_OK;
    if (!st && rest) {
        owners w;
        candidate *cand = NULL;
        size_t cap = 0;
        st = owners_init(s, &w, outers);
        for (size_t h = 0; h < nr && !st; h++)
            if (s->rings[h].area2 < 0 && s->rings[h].owner == SIZE_MAX)
                st = find_owner(s, &w, h, &cand, &cap);
        free(cand);
        owners_free(&w, outers);
        if (st)
            return st;
    }
    /* the holes of each ring (the holes of none under nr), in ring order:
     * counts, starts, then each hole placed */
    size_t *first = calloc(nr + 2, sizeof *first), *fill = malloc((nr + 2) * sizeof *fill);
    size_t *hole = malloc((holes + 1) * sizeof *hole);
    if (!first || !fill || !hole) {
        free(first), free(fill), free(hole);
        return HPFC_E_NOMEM;
    }
    for (size_t h = 0; h < nr; h++)
        if (s->rings[h].area2 < 0)
            first[(s->rings[h].owner == SIZE_MAX ? nr : s->rings[h].owner) + 1]++;
    for (size_t r = 0; r <= nr; r++)
        first[r + 1] += first[r];
    memcpy(fill, first, (nr + 2) * sizeof *fill);
    for (size_t h = 0; h < nr; h++)
        if (s->rings[h].area2 < 0)
            hole[fill[s->rings[h].owner == SIZE_MAX ? nr : s->rings[h].owner]++] = h;
    free(fill);
    int in_place = answer_in_place(s, first, hole);
    if ((!in_place && array_grow((void **)&s->ept, &s->cap_ept, 2 * s->ntxy + 2, sizeof *s->ept)) ||
        array_grow((void **)&s->ring_point, &s->cap_ring_point, nr + 1, sizeof *s->ring_point) ||
        array_grow((void **)&s->polygon_ring, &s->cap_polygon_ring, outers + 1,
                   sizeof *s->polygon_ring)) {
        free(first), free(hole);
        return HPFC_E_NOMEM;
    }
    size_t rings = 0, points = 0, polygons = 0;
    for (size_t o = 0; o < nr; o++) {
        if (s->rings[o].area2 <= 0)
            continue;
        s->polygon_ring[polygons++] = rings;
        put_ring(s, o, in_place, &rings, &points);
        for (size_t k = first[o]; k < first[o + 1]; k++)
            put_ring(s, hole[k], in_place, &rings, &points);
    }
    s->polygon_ring[polygons] = rings;
    for (size_t k = first[nr]; k < first[nr + 1]; k++)
        put_ring(s, hole[k], in_place, &rings, &points);
    free(first), free(hole);
    s->ring_point[rings] = points;
    *out = (hpfc_polygons){.polygon_count = polygons,
                           .ring_count = rings,
                           .point_count = points,
                           .polygon_ring = s->polygon_ring,
                           .ring_point = s->ring_point,
                           .xy = in_place ? s->txy : s->ept};
    return HPFC_OK;
}

static void reset(hpfc_shapes *s)
{
    s->ndarts = s->nept = s->ntxy = s->nrings = 0;
    s->call_points = 0;
}

/* The region's boundary darts are collected; then linked, traced and
 * arranged. */
static int assemble(hpfc_shapes *s, hpfc_polygons *out)
{
    int st = load_darts(s);
    if (!st)
        st = link_darts(s);
    /* the rings' points at once: each dart's edge but one point, and a
     * closing point a ring, fewer than the darts' call_points; grown a
     * ring at a time, the array was copied a dozen times on a large
     * feature, each copy into pages the process had not touched yet */
    if (!st && reserve_call_points(s, &s->txy, &s->cap_txy))
        st = HPFC_E_NOMEM;
    if (!st)
        st = trace_rings(s);
    if (!st)
        st = arrange(s, out);
    return st;
}

int hpfc_shapes_face_polygons(hpfc_shapes *s, hpfc_id face, hpfc_polygons *out)
{
    if (!s || !out || face >= s->faces)
        return HPFC_E_ARG;
    reset(s);
    s->face_local[face] = 0;
    uint64_t a = 0, b = 0;
    int st = parts_init(s, 1);
    if (!st)
        st = shapes_row(s, FACE_EDGES, face, &a, &b);
    for (uint64_t k = a; !st && k < b; k++) {
        uint32_t e = shapes_item(s, FACE_EDGES, k);
        /* the face on the left: u -> v when it is the left face */
        st = add_dart(s, e, s->edge[e].left != face, face);
    }
    return st ? st : assemble(s, out);
}


/* The polygons of a region given as its faces (distinct ids): the faces'
 * parts joined across the edges inside the region, so that each hole is
 * owned by the part around it, and a dart for every edge on its border. */
static int region_polygons(hpfc_shapes *s, const uint32_t *faces, size_t n, hpfc_polygons *out)
{
    reset(s);
    uint32_t m = shapes_next_mark(s);
    for (size_t k = 0; k < n; k++) {
        s->face_mark[faces[k]] = m;
        s->face_local[faces[k]] = (uint32_t)k;
    }
    int st = parts_init(s, n);
    for (size_t k = 0; k < n && !st; k++) {
        uint32_t face = faces[k];
        uint64_t a, b;
        st = shapes_row(s, FACE_EDGES, face, &a, &b);
        for (uint64_t j = a; !st && j < b; j++) {
            uint32_t e = shapes_item(s, FACE_EDGES, j);
            int in_left = s->face_mark[s->edge[e].left] == m,
                in_right = s->face_mark[s->edge[e].right] == m;
            if (in_left && in_right)
                parts_join(s, s->edge[e].left, s->edge[e].right);
            /* once per edge: from the face on its side inside the region */
            else if (in_left != in_right && (in_left ? s->edge[e].left : s->edge[e].right) == face)
                st = add_dart(s, e, in_right, face);
        }
    }
    return st ? st : assemble(s, out);
}

int hpfc_shapes_feature_polygons(hpfc_shapes *s, hpfc_id feature, hpfc_polygons *out)
{
    int st = check_feature_call(s, out, FEATURE_FACES, feature);
    if (st)
        return st;
    const uint32_t *faces;
    size_t n;
    if ((st = row_array(s, FEATURE_FACES, feature, &faces, &n)))
        return st;
    return region_polygons(s, faces, n, out);
}

/* ---- lines --------------------------------------------------------------------------- */

/* One end of one of the feature's edges, at vertex `vertex`. */
typedef struct line_end {
    uint32_t vertex;
    uint32_t k;    /* index into the feature's edges */
    uint32_t end;  /* 0: the edge's u, 1: its v */
} line_end;

/* Line ends by vertex, then by edge and end.
 * (Every qsort comparator of the library has this field-by-field shape;
 * each orders its own record, so they share no code.) */
static int cmp_line_end(const void *pa, const void *pb)
{
    const line_end *a = pa, *b = pb;
    if (a->vertex != b->vertex)
        return a->vertex < b->vertex ? -1 : 1;
    if (a->k != b->k)
        return a->k < b->k ? -1 : 1;
    return (a->end > b->end) - (a->end < b->end);
}

typedef struct line_walk {
    hpfc_shapes *s;
    const uint32_t *edges;
    size_t n;
    line_end *ends;   /* 2n, by vertex */
    uint8_t *used;
} line_walk;

/* The other end at vertex v when exactly two ends meet there (the chain
 * goes on), else NULL. `at` is the end the walk arrived by. */
static const line_end *continuation(const line_walk *w, uint32_t v, const line_end *at)
{
    size_t lo = 0, hi = 2 * w->n;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (w->ends[mid].vertex < v)
            lo = mid + 1;
        else
            hi = mid;
    }
    if (lo + 1 >= 2 * w->n || w->ends[lo + 1].vertex != v ||
        (lo + 2 < 2 * w->n && w->ends[lo + 2].vertex == v))
        return NULL;
    const line_end *a = &w->ends[lo], *b = &w->ends[lo + 1];
    return a->k == at->k && a->end == at->end ? b : a;
}

/* Appends one polyline: from end `from` (its edge walked away from it) on
 * through vertices of degree 2, until an end, a branch or a used edge. */
static int walk_line(line_walk *w, line_end from)
{
    hpfc_shapes *s = w->s;
    int st = HPFC_OK, first = 1;
    for (size_t steps = 0; steps < w->n && !w->used[from.k] && !st; steps++) {
        uint32_t e = w->edges[from.k];
        uint64_t n = shapes_edge_points(s, e);
        w->used[from.k] = 1;
        if ((st = shapes_take_points(s, n)))
            break;
        size_t at;
        s->nept = 0;
        st = load_edge(s, e, &at);
        if (!st)
            st = add_points(s, at, n, from.end, first ? 0 : 1, n);
        first = 0;
        line_end arrived = {from.end ? s->edge[e].u : s->edge[e].v, from.k, 1 - from.end};
        const line_end *next = continuation(w, arrived.vertex, &arrived);
        if (!next)
            break;
        from = *next;
    }
    return st;
}

/* Where the polyline through edge k starts: walked back from k's u through
 * vertices of degree 2; k's own u end when the chain closes. */
static line_end line_start(const line_walk *w, uint32_t k)
{
    const hpfc_shapes *s = w->s;
    line_end at = {s->edge[w->edges[k]].u, k, 0};
    for (size_t steps = 0; steps < w->n; steps++) {
        const line_end *o = continuation(w, at.vertex, &at);
        if (!o || o->k == k || w->used[o->k])
            break;
        uint32_t e = w->edges[o->k];
        at = (line_end){o->end ? s->edge[e].u : s->edge[e].v, o->k, 1 - o->end};
    }
    return at; /* the walk goes forward from here, along at.k */
}

/* Edges[0 .. n) joined into polylines, the answer. */
static int join_lines(hpfc_shapes *s, const uint32_t *edges, size_t n, hpfc_polygons *out)
{
    int st;
    reset(s);
    line_walk w = {.s = s, .edges = edges, .n = n};
    w.used = calloc(w.n + 1, 1);
    w.ends = malloc((2 * w.n + 1) * sizeof *w.ends);
    st = w.used && w.ends ? HPFC_OK : HPFC_E_NOMEM;
    /* the answer's xy is s->txy, never NULL */
    if (!st && array_grow((void **)&s->txy, &s->cap_txy, 2, sizeof *s->txy))
        st = HPFC_E_NOMEM;
    for (size_t k = 0; k < w.n && !st; k++) {
        uint32_t e = w.edges[k];
        w.ends[2 * k] = (line_end){s->edge[e].u, (uint32_t)k, 0};
        w.ends[2 * k + 1] = (line_end){s->edge[e].v, (uint32_t)k, 1};
    }
    if (!st && w.n)
        qsort(w.ends, 2 * w.n, sizeof *w.ends, cmp_line_end);
    size_t lines = 0;
    for (size_t k = 0; k < w.n && !st; k++) {
        if (w.used[k])
            continue;
        if (array_grow((void **)&s->ring_point, &s->cap_ring_point, lines + 2,
                 sizeof *s->ring_point)) {
            st = HPFC_E_NOMEM;
            break;
        }
        s->ring_point[lines++] = s->ntxy;
        st = walk_line(&w, line_start(&w, (uint32_t)k));
    }
    free(w.used);
    free(w.ends);
    if (!st && (array_grow((void **)&s->polygon_ring, &s->cap_polygon_ring, 1,
                     sizeof *s->polygon_ring) ||
                array_grow((void **)&s->ring_point, &s->cap_ring_point, lines + 1,
                     sizeof *s->ring_point)))
        st = HPFC_E_NOMEM;
    if (st)
        return st;
    s->ring_point[lines] = s->ntxy;
    s->polygon_ring[0] = lines; /* no polygon; the lines are not holes */
    *out = (hpfc_polygons){.polygon_count = 0,
                           .ring_count = lines,
                           .point_count = s->ntxy,
                           .polygon_ring = s->polygon_ring,
                           .ring_point = s->ring_point,
                           .xy = s->txy}; /* the lines as walked */
    return HPFC_OK;
}

int hpfc_shapes_set_limits_sized(hpfc_shapes *s, const hpfc_limits *limits, size_t limits_size)
{
    if (!s)
        return HPFC_E_ARG;
    hpfc_limits l = {0};
    if (limits && sized_in(&l, sizeof l, limits, limits_size))
        return HPFC_E_ARG;
    s->max_points = l.max_points ? l.max_points : HPFC_LIMIT_POINTS_DEFAULT;
    s->max_items = l.max_items ? l.max_items : HPFC_LIMIT_ITEMS_DEFAULT;
    return HPFC_OK;
}

int hpfc_shapes_feature_polylines(hpfc_shapes *s, hpfc_id feature, hpfc_polygons *out)
{
    int st = check_feature_call(s, out, FEATURE_EDGES, feature);
    if (st)
        return st;
    const uint32_t *edges;
    size_t n;
    if ((st = row_array(s, FEATURE_EDGES, feature, &edges, &n)))
        return st;
    return join_lines(s, edges, n, out);
}

/* ---- sets of features ------------------------------------------------------------- */

static int cmp_u32(const void *pa, const void *pb)
{
    uint32_t a = *(const uint32_t *)pa, b = *(const uint32_t *)pb;
    return (a > b) - (a < b);
}

int hpfc_shapes_features_polygons(hpfc_shapes *s, const hpfc_id *features, size_t n,
                                  hpfc_polygons *out)
{
    if (!s || !out || (n && !features))
        return HPFC_E_ARG;
    if (!s->have_features)
        return HPFC_E_NO_SECTION;
    size_t nf = 0;
    for (size_t k = 0; k < n; k++) /* the caller's ids first, then the file's rows */
        if (features[k] >= s->features)
            return HPFC_E_ARG;
    for (size_t k = 0; k < n; k++) {
        uint64_t a, b;
        int st = shapes_row(s, FEATURE_FACES, features[k], &a, &b);
        if (st)
            return st;
        nf += (size_t)(b - a);
    }
    /* the set's faces, each once (features may share faces, ids repeat) */
    uint32_t *faces = malloc((nf + 1) * sizeof *faces);
    if (!faces)
        return HPFC_E_NOMEM;
    nf = 0;
    for (size_t k = 0; k < n; k++) {
        uint64_t a, b;
        shapes_row(s, FEATURE_FACES, features[k], &a, &b); /* read above */
        for (uint64_t j = a; j < b; j++)
            faces[nf++] = shapes_item(s, FEATURE_FACES, j);
    }
    if (nf)
        qsort(faces, nf, sizeof *faces, cmp_u32);
    size_t u = 0;
    for (size_t k = 0; k < nf; k++)
        if (!u || faces[k] != faces[u - 1])
            faces[u++] = faces[k];
    /* as one feature's faces */
    int st = region_polygons(s, faces, u, out);
    free(faces);
    return st;
}

/* The groups of the features of a face, sorted and each once, into g
 * (*n of *cap, grown); HPFC_GROUP_NONE left out. */
static int face_groups(hpfc_shapes *s, uint64_t face, const uint32_t *group, uint32_t **g,
                       size_t *n, size_t *cap)
{
    uint32_t count;
    hpfc_id ft;
    *n = 0;
    int st = hpfc_face_feature_count(s->f, face, &count);
    for (uint32_t k = 0; k < count && !st; k++) {
        if ((st = hpfc_face_feature_id(s->f, face, k, &ft)))
            break;
        if (ft >= s->features)
            return HPFC_E_CORRUPT;
        uint32_t v = group ? group[ft] : (uint32_t)ft;
        if (v == HPFC_GROUP_NONE)
            continue;
        if (array_grow((void **)g, cap, *n + 1, sizeof **g))
            return HPFC_E_NOMEM;
        (*g)[(*n)++] = v;
    }
    if (st || *n < 2)
        return st;
    qsort(*g, *n, sizeof **g, cmp_u32);
    size_t u = 1;
    for (size_t k = 1; k < *n; k++)
        if ((*g)[k] != (*g)[u - 1])
            (*g)[u++] = (*g)[k];
    *n = u;
    return HPFC_OK;
}

int hpfc_shapes_mesh(hpfc_shapes *s, const uint32_t *group, size_t n, unsigned sides,
                     hpfc_polygons *out)
{
    if (!s || !out || !sides || (sides & ~(unsigned)(HPFC_MESH_INTERIOR | HPFC_MESH_EXTERIOR)))
        return HPFC_E_ARG;
    if (!s->have_features)
        return HPFC_E_NO_SECTION;
    if (group && n != s->features)
        return HPFC_E_ARG;
    uint32_t *gl = NULL, *gr = NULL, *kept = NULL;
    size_t nl = 0, nr = 0, cap_l = 0, cap_r = 0, nk = 0, cap_k = 0;
    int st = shapes_read_all(s); /* every edge's faces */
    for (uint64_t e = 0; e < s->edges && s->face_features && !st; e++) {
        if (s->edge[e].left == s->edge[e].right)
            continue;
        st = face_groups(s, s->edge[e].left, group, &gl, &nl, &cap_l);
        if (!st)
            st = face_groups(s, s->edge[e].right, group, &gr, &nr, &cap_r);
        if (st)
            break;
        int keep = (sides & HPFC_MESH_EXTERIOR) && ((nl == 0) != (nr == 0));
        if ((sides & HPFC_MESH_INTERIOR) && nl && nr)
            keep |= nl != nr || memcmp(gl, gr, nl * sizeof *gl) != 0;
        if (!keep)
            continue;
        if (array_grow((void **)&kept, &cap_k, nk + 1, sizeof *kept))
            st = HPFC_E_NOMEM;
        else
            kept[nk++] = (uint32_t)e;
    }
    free(gl);
    free(gr);
    if (!st)
        st = join_lines(s, kept, nk, out);
    free(kept);
    return st;
}
