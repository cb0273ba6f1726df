#include "tree_oracle.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "road.h"

void oracle_for_each_pixel(const hpfc_tree *t, pixel_fn fn, void *ctx)
{
    hpfc_tree_info info;
    hpfc_tree_get_info(t, &info);
    for (uint32_t l = 0; l < info.levels; l++) {
        uint32_t cols = l ? info.cols : info.root_cols, rows = l ? info.rows : info.root_rows;
        for (size_t im = 0; im < hpfc_tree_image_count(t, l); im++)
            for (uint32_t j = 0; j < rows; j++)
                for (uint32_t i = 0; i < cols; i++) {
                    hpfc_tree_pixel px;
                    if (hpfc_tree_get_pixel(t, l, im, i, j, &px) == HPFC_OK)
                        fn(t, l, im, i, j, &px, ctx);
                }
    }
}

bool oracle_word_is_valid(const char *w, size_t len)
{
    char stack[4096];
    size_t depth = 0, plus = 0;
    for (size_t k = 0; k < len; k++) {
        char c = w[k];
        if (plus == 4)
            return false; /* symbols after the fourth '+' */
        switch (c) {
        case '+': plus++; break;
        case '=': break;
        case '[':
        case '(':
            if (depth == sizeof stack)
                return false;
            stack[depth++] = c;
            break;
        case 'Y':
            if (!depth || stack[depth - 1] != '(')
                return false;
            break;
        case ']':
            if (!depth || stack[--depth] != '[')
                return false;
            break;
        case ')':
            if (!depth || stack[--depth] != '(')
                return false;
            break;
        default:
            return false;
        }
    }
    return plus == 4 && depth == 0;
}

void oracle_road_counts(const char *w, size_t len, size_t counts[4])
{
    size_t road = 0;
    memset(counts, 0, 4 * sizeof *counts);
    for (size_t k = 0; k < len && road < 4; k++) {
        if (w[k] == '+')
            road++;
        else
            counts[road]++;
    }
}

/* ---- per-pixel checks against the graph --------------------------------- */

typedef struct check_ctx {
    const hpfc_graph *g;
    hpfc_tree_info info;
    uint32_t max_leaf_points;
    int failures;
    uint32_t *vertex_hits;   /* word pixels holding each vertex */
    size_t *degree;
} check_ctx;

static void fail(check_ctx *c, uint32_t level, size_t image, uint32_t i, uint32_t j, const char *what)
{
    c->failures++;
    if (c->failures <= 20)
        fprintf(stderr, "pixel L%u image %zu (%u,%u): %s\n", level, image, i, j, what);
}

static lpoint rel_point(const check_ctx *c, const hpfc_graph *g, size_t e, size_t k)
{
    const int64_t *pts;
    size_t n;
    uint32_t u, v;
    hpfc_graph_edge(g, e, &u, &v, &pts, &n);
    int64_t x, y;
    if (k == 0)
        hpfc_graph_vertex(g, u, &x, &y);
    else if (k == n + 1)
        hpfc_graph_vertex(g, v, &x, &y);
    else
        x = pts[2 * (k - 1)], y = pts[2 * (k - 1) + 1];
    return (lpoint){x - c->info.x0, y - c->info.y0};
}

static size_t edge_points(const hpfc_graph *g, size_t e)
{
    const int64_t *pts;
    size_t n;
    uint32_t u, v;
    hpfc_graph_edge(g, e, &u, &v, &pts, &n);
    return n + 2;
}

/* Does edge e lie entirely inside the pixel (all its points in it)? */
static bool edge_inside(const check_ctx *c, size_t e, const int64_t cell[4])
{
    for (size_t k = 0; k < edge_points(c->g, e); k++)
        if (!point_in_cell(rel_point(c, c->g, e, k), cell[0], cell[1], cell[2], cell[3]))
            return false;
    return true;
}

/* Interior points of every edge that lie in the pixel (naive: all edges). */
static size_t shape_points_inside(const check_ctx *c, const int64_t cell[4])
{
    size_t n = 0;
    for (size_t e = 0; e < hpfc_graph_edge_count(c->g); e++)
        for (size_t k = 1; k + 1 < edge_points(c->g, e); k++)
            n += point_in_cell(rel_point(c, c->g, e, k), cell[0], cell[1], cell[2], cell[3]);
    return n;
}

typedef struct naive_crossing {
    line_pos pos;
    uint32_t edge, seg;
} naive_crossing;

static int cmp_naive(const void *pa, const void *pb)
{
    const naive_crossing *a = pa, *b = pb;
    return cmp_line_pos(&a->pos, &b->pos);
}

/* All crossings of one road of the pixel, over every segment of the graph,
 * in the road's clockwise direction. Returns the count. */
static size_t naive_road(const check_ctx *c, int road, const int64_t cell[4], naive_crossing **out)
{
    size_t n = 0, cap = 16;
    naive_crossing *list = malloc(cap * sizeof *list);
    for (size_t e = 0; e < hpfc_graph_edge_count(c->g); e++)
        for (size_t k = 0; k + 1 < edge_points(c->g, e); k++) {
            naive_crossing nc;
            bool entering;
            if (!cross_road(rel_point(c, c->g, e, k), rel_point(c, c->g, e, k + 1), road, cell[0], cell[1],
                            cell[2], cell[3], &nc.pos, &entering))
                continue;
            if (n == cap)
                list = realloc(list, (cap *= 2) * sizeof *list);
            nc.edge = (uint32_t)e, nc.seg = (uint32_t)k;
            list[n++] = nc;
        }
    qsort(list, n, sizeof *list, cmp_naive);
    if (road == HPFC_EAST || road == HPFC_SOUTH) /* clockwise runs south / west there */
        for (size_t a = 0, b = n ? n - 1 : 0; a < b; a++, b--) {
            naive_crossing t = list[a];
            list[a] = list[b], list[b] = t;
        }
    *out = list;
    return n;
}

static int cmp_size(const void *pa, const void *pb)
{
    size_t a = *(const size_t *)pa, b = *(const size_t *)pb;
    return (a > b) - (a < b);
}

/* Junction components of the word (sizes, sorted) against the vertices the
 * graph puts in the pixel (degrees, sorted). */
static void check_junctions(check_ctx *c, const hpfc_tree_pixel *px, const int64_t cell[4],
                            uint32_t level, size_t image, uint32_t i, uint32_t j)
{
    size_t comp_sizes[512], ncomp = 0, stack[512], depth = 0, deg[512], ndeg = 0;
    size_t open_size[512];
    for (size_t k = 0; k < px->word_len; k++) {
        char s = px->word[k];
        if (s == '=' && ncomp < 512)
            comp_sizes[ncomp++] = 1;
        else if (s == '(' && depth < 512)
            stack[depth] = 1, open_size[depth] = 1, depth++;
        else if (s == '[' && depth < 512)
            stack[depth] = 0, open_size[depth] = 1, depth++;
        else if (s == 'Y' && depth)
            open_size[depth - 1]++;
        else if ((s == ')' || s == ']') && depth) {
            depth--;
            if (stack[depth] && ncomp < 512)
                comp_sizes[ncomp++] = open_size[depth] + 1;
        }
    }
    for (size_t v = 0; v < hpfc_graph_vertex_count(c->g); v++) {
        int64_t x, y;
        hpfc_graph_vertex(c->g, v, &x, &y);
        lpoint p = {x - c->info.x0, y - c->info.y0};
        if (point_in_cell(p, cell[0], cell[1], cell[2], cell[3])) {
            c->vertex_hits[v]++;
            if (ndeg < 512)
                deg[ndeg++] = c->degree[v];
        }
    }
    qsort(comp_sizes, ncomp, sizeof *comp_sizes, cmp_size);
    qsort(deg, ndeg, sizeof *deg, cmp_size);
    if (ncomp != ndeg || memcmp(comp_sizes, deg, ncomp * sizeof *deg))
        fail(c, level, image, i, j, "junction components differ from the vertices in the pixel");
}

static void check_roads(check_ctx *c, const hpfc_tree_pixel *px, const int64_t cell[4], uint32_t level,
                        size_t image, uint32_t i, uint32_t j)
{
    size_t counts[4], k = 0;
    oracle_road_counts(px->word, px->word_len, counts);
    for (int road = 0; road < 4; road++) {
        naive_crossing *list;
        size_t n = naive_road(c, road, cell, &list);
        if (n != counts[road]) {
            fail(c, level, image, i, j, "crossing count differs from the naive count");
        } else {
            for (size_t q = 0; q < n; q++, k++)
                if (list[q].edge != px->cross_edge[k] || list[q].seg != px->cross_segment[k]) {
                    fail(c, level, image, i, j, "crossing order differs from the naive order");
                    break;
                }
        }
        k = 0; /* the next road's crossings start after this one's */
        for (int r = 0; r <= road; r++)
            k += counts[r];
        free(list);
    }
}

static void check_pixel(const hpfc_tree *t, uint32_t level, size_t image, uint32_t i, uint32_t j,
                        const hpfc_tree_pixel *px, void *ctx)
{
    (void)t;
    check_ctx *c = ctx;
    int64_t cell[4] = {px->x0 - c->info.x0, px->y0 - c->info.y0, px->x1 - c->info.x0, px->y1 - c->info.y0};
    bool holds = false;
    for (size_t e = 0; e < hpfc_graph_edge_count(c->g) && !holds; e++)
        holds = edge_inside(c, e, cell);
    bool unit = cell[2] - cell[0] == 1 && cell[3] - cell[1] == 1;
    bool crowded = c->max_leaf_points && !unit && shape_points_inside(c, cell) > c->max_leaf_points;
    if (px->type == HPFC_PIXEL_REFINED) {
        if (!holds && !crowded)
            fail(c, level, image, i, j, "refined pixel holds no whole edge and few shape points");
        return;
    }
    if (holds)
        fail(c, level, image, i, j, "word pixel holds a whole edge");
    if (crowded)
        fail(c, level, image, i, j, "word pixel holds more shape points than the bound");
    if (!oracle_word_is_valid(px->word, px->word_len))
        fail(c, level, image, i, j, "word is not well nested");
    check_junctions(c, px, cell, level, image, i, j);
    check_roads(c, px, cell, level, image, i, j);
}

int oracle_check_tree(const hpfc_graph *g, const hpfc_tree *t, uint32_t max_leaf_points)
{
    check_ctx c = {.g = g, .max_leaf_points = max_leaf_points};
    hpfc_tree_get_info(t, &c.info);
    size_t nv = hpfc_graph_vertex_count(g);
    c.vertex_hits = calloc(nv + 1, sizeof *c.vertex_hits);
    c.degree = calloc(nv + 1, sizeof *c.degree);
    for (size_t e = 0; e < hpfc_graph_edge_count(g); e++) {
        const int64_t *pts;
        size_t n;
        uint32_t u, v;
        hpfc_graph_edge(g, e, &u, &v, &pts, &n);
        c.degree[u]++;
        c.degree[v]++;
    }
    oracle_for_each_pixel(t, check_pixel, &c);
    for (size_t v = 0; v < nv; v++)
        if (c.vertex_hits[v] != 1) {
            c.failures++;
            fprintf(stderr, "vertex %zu lies in %u word pixels\n", v, c.vertex_hits[v]);
        }
    /* the pixels of every image tile its parent exactly: checked through the
     * counts (every level's pixels cover the domain once) */
    free(c.vertex_hits);
    free(c.degree);
    return c.failures;
}

/* ---- point location (naive: descend by bounds) --------------------------- */

bool oracle_locate(const hpfc_tree *t, int64_t x, int64_t y, hpfc_tree_pixel *out, uint32_t *level)
{
    hpfc_tree_info info;
    hpfc_tree_get_info(t, &info);
    uint32_t l = 0;
    size_t image = 0;
    for (;;) {
        uint32_t cols = l ? info.cols : info.root_cols, rows = l ? info.rows : info.root_rows;
        bool found = false;
        for (uint32_t j = 0; j < rows && !found; j++)
            for (uint32_t i = 0; i < cols && !found; i++) {
                hpfc_tree_pixel px;
                hpfc_tree_get_pixel(t, l, image, i, j, &px);
                if (x >= px.x0 && x < px.x1 && y >= px.y0 && y < px.y1) {
                    found = true;
                    if (px.type == HPFC_PIXEL_WORD) {
                        *out = px;
                        *level = l;
                        return true;
                    }
                    image = px.child;
                }
            }
        if (!found)
            return false;
        l++;
    }
}

/* ---- flat rPFC against hPFC ---------------------------------------------- */

typedef struct flat_ctx {
    const hpfc_tree *flat;
    hpfc_tree_info finfo;
    int failures;
} flat_ctx;

/* Appends the crossings of road `road` of flat pixel (gx, gy) (level-wide
 * cell coordinates, gy from the south) to (edges, segs). */
static size_t flat_road(const flat_ctx *c, int64_t gx, int64_t gy, int road, uint32_t *edges, uint32_t *segs,
                        size_t at, size_t cap)
{
    uint32_t i = (uint32_t)gx, j = (uint32_t)(c->finfo.root_rows - 1 - gy);
    hpfc_tree_pixel px;
    hpfc_tree_get_pixel(c->flat, 0, 0, i, j, &px);
    size_t counts[4], first = 0;
    oracle_road_counts(px.word, px.word_len, counts);
    for (int r = 0; r < road; r++)
        first += counts[r];
    for (size_t q = 0; q < counts[road] && at < cap; q++) {
        edges[at] = px.cross_edge[first + q];
        segs[at] = px.cross_segment[first + q];
        at++;
    }
    return at;
}

static void compare_leaf(const hpfc_tree *t, uint32_t level, size_t image, uint32_t i, uint32_t j,
                         const hpfc_tree_pixel *px, void *ctx)
{
    (void)t;
    flat_ctx *c = ctx;
    if (px->type != HPFC_PIXEL_WORD)
        return;
    int64_t fw = c->finfo.width / c->finfo.root_cols, fh = c->finfo.height / c->finfo.root_rows;
    int64_t gx0 = (px->x0 - c->finfo.x0) / fw, gx1 = (px->x1 - c->finfo.x0) / fw;
    int64_t gy0 = (px->y0 - c->finfo.y0) / fh, gy1 = (px->y1 - c->finfo.y0) / fh;
    size_t counts[4], k = 0;
    oracle_road_counts(px->word, px->word_len, counts);
    size_t cap = px->word_len + 16; /* more than the road can hold if both agree */
    uint32_t *edges = malloc(cap * sizeof *edges), *segs = malloc(cap * sizeof *segs);
    for (int road = 0; road < 4; road++) {
        size_t n = 0;
        /* the fine road pieces along this road, in its clockwise direction */
        int64_t len = road == HPFC_WEST || road == HPFC_EAST ? gy1 - gy0 : gx1 - gx0;
        for (int64_t s = 0; s < len; s++) {
            switch (road) {
            case HPFC_WEST: n = flat_road(c, gx0, gy0 + s, road, edges, segs, n, cap); break;
            case HPFC_NORTH: n = flat_road(c, gx0 + s, gy1 - 1, road, edges, segs, n, cap); break;
            case HPFC_EAST: n = flat_road(c, gx1 - 1, gy1 - 1 - s, road, edges, segs, n, cap); break;
            default: n = flat_road(c, gx1 - 1 - s, gy0, road, edges, segs, n, cap); break;
            }
        }
        bool same = n == counts[road];
        for (size_t q = 0; same && q < n; q++)
            same = edges[q] == px->cross_edge[k + q] && segs[q] == px->cross_segment[k + q];
        if (!same) {
            c->failures++;
            if (c->failures <= 20)
                fprintf(stderr, "L%u image %zu (%u,%u) road %d: hPFC and flat crossings differ\n", level, image,
                        i, j, road);
        }
        k += counts[road];
    }
    free(edges);
    free(segs);
}

int oracle_compare_flat(const hpfc_tree *flat, const hpfc_tree *tree)
{
    flat_ctx c = {.flat = flat};
    hpfc_tree_get_info(flat, &c.finfo);
    if (c.finfo.levels != 1)
        return 1;
    oracle_for_each_pixel(tree, compare_leaf, &c);
    return c.failures;
}
