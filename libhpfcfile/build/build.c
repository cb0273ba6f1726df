/*
 * The builder: planar graph to hPFC tree (paper Sect. 3.2; spec/hpfc-format.md
 * "Construction").
 *
 * Domain. The graph's lattice is translated so that the domain is
 * [0, W) x [0, H) with W = n0 * n^K and H = m0 * m^K for the smallest K that
 * leaves at least one lattice unit of margin on every side. Every grid line
 * of every level down to K is then an integer, and a pixel of depth K
 * (1 x 1) can hold no edge, so refinement stops by depth K at the latest.
 *
 * Refinement. An edge lies inside a pixel iff all its points lie in it, so
 * the deepest pixel containing an edge follows from its bounding box alone.
 * A pixel is refined iff it contains some edge, or (below depth K) more
 * than max_leaf_points shape points: a long polyline held whole by no
 * pixel would otherwise leave leaves of hundreds of segments, and a
 * query's cost in a leaf grows with its segments.
 *
 * Words. The tree is built level by level. Each image carries the segments
 * that meet it; they are handed down to the pixels they meet, and a word
 * pixel's crossings come from intersecting those segments with its four
 * roads under the perturbation of geom.h, so both sides of every road see
 * the same crossings in the same order.
 */
#include <stdlib.h>
#include <string.h>

#include "arrays.h"
#include "road.h"
#include "sized.h"
#include "tasks.h"
#include "tree.h"
#include "words.h"

/* Segment k of an edge (0 = the one leaving u). Its end points are read
 * from the graph (seg_points), not kept: a continental map has millions of
 * segments, and 32 bytes each of copies made the build's largest array. */
typedef struct seg {
    uint32_t edge, k;
} seg;

typedef struct builder {
    const hpfc_graph *g;
    hpfc_build_params p;
    hpfc_tree *t;
    int64_t ox, oy;           /* domain origin in graph coordinates */
    seg *segs;
    size_t nsegs;
    int32_t *edge_level;      /* deepest level with a pixel holding the edge, -1 if none */
    uint8_t *vertex_seen;     /* each vertex must land in exactly one word pixel */
    /* per-level segment lists: image i's segments are list[start[i]..start[i+1]) */
    uint32_t *cur_list, *next_list;
    size_t *cur_start, *next_start;
    size_t next_len, next_cap, next_images_cap;
    uint32_t max_depth;       /* K: pixels of this depth are 1 x 1 */
    /* A part's build (hpfc_build_part): the root pixels it builds, one bit
     * each (NULL: all of them), and the whole map's id of each of its
     * graph's edges (NULL: the graph's own index). */
    uint8_t *root_selected;
    const uint32_t *edge_ids;
    uint64_t edge_count;      /* the whole map's, with edge_ids */
    hpfc_diag *diag;
} builder;

/* ---- small growable arrays ---------------------------------------------- */

/* The builder's arrays start at 64 elements (arrays.h). */
static int reserve(void **p, size_t *cap, size_t need, size_t elem)
{
    return array_reserve(p, cap, need, elem, 64);
}

/* ---- domain and per-edge refinement depth -------------------------------- */

/* The domain of a map whose points span box (xmin, ymin, xmax, ymax,
 * closed): the smallest K with a lattice unit of margin on every side, the
 * map centred in it. */
static int domain_of_box(const int64_t box[4], const hpfc_build_params *p, hpfc_domain *d,
                         hpfc_diag *diag)
{
    int64_t ex = box[2] - box[0], ey = box[3] - box[1];
    int64_t W = p->root_cols, H = p->root_rows;
    uint32_t K = 0;
    while (W < ex + 2 || H < ey + 2) {
        if (W > HPFC_LATTICE_MAX / p->cols || H > HPFC_LATTICE_MAX / p->rows)
            return diag_set(diag, HPFC_E_EXTENT,
                            "the graph's extent (%lld x %lld lattice units) needs a domain larger than 2^41",
                            (long long)ex, (long long)ey);
        W *= p->cols;
        H *= p->rows;
        K++;
    }
    if (W > HPFC_LATTICE_MAX || H > HPFC_LATTICE_MAX)
        return diag_set(diag, HPFC_E_EXTENT, "root image too large for the lattice");
    *d = (hpfc_domain){.x0 = box[0] - (W - ex) / 2,
                       .y0 = box[1] - (H - ey) / 2,
                       .width = W,
                       .height = H,
                       .max_depth = K};
    return HPFC_OK;
}

static void set_domain(builder *b, const hpfc_domain *d)
{
    b->ox = d->x0;
    b->oy = d->y0;
    hpfc_tree_info *info = &b->t->info;
    info->x0 = d->x0;
    info->y0 = d->y0;
    info->width = d->width;
    info->height = d->height;
    info->unit_exp10 = b->g->unit_exp10;
    b->max_depth = d->max_depth;
}

static int choose_domain(builder *b)
{
    const hpfc_graph *g = b->g;
    int64_t box[4] = {INT64_MAX, INT64_MAX, INT64_MIN, INT64_MIN};
    for (size_t e = 0; e < g->ne; e++)
        for (size_t k = 0; k < graph_edge_point_count(g, e); k++) {
            int64_t x, y;
            graph_edge_point(g, e, k, &x, &y);
            box[0] = x < box[0] ? x : box[0], box[2] = x > box[2] ? x : box[2];
            box[1] = y < box[1] ? y : box[1], box[3] = y > box[3] ? y : box[3];
        }
    hpfc_domain d = {0};
    int st = domain_of_box(box, &b->p, &d, b->diag);
    if (st)
        return st;
    set_domain(b, &d);
    return HPFC_OK;
}

/* Point k of edge e, domain-relative. */
static lpoint edge_point(const builder *b, size_t e, size_t k)
{
    int64_t x, y;
    graph_edge_point(b->g, e, k, &x, &y);
    return (lpoint){x - b->ox, y - b->oy};
}

static void seg_points(const builder *b, const seg *s, lpoint *p, lpoint *q)
{
    *p = edge_point(b, s->edge, s->k);
    *q = edge_point(b, s->edge, (size_t)s->k + 1);
}

static void compute_edge_levels(builder *b)
{
    const hpfc_graph *g = b->g;
    const hpfc_tree_info *info = &b->t->info;
    for (size_t e = 0; e < g->ne; e++) {
        int64_t xmin = INT64_MAX, ymin = INT64_MAX, xmax = INT64_MIN, ymax = INT64_MIN;
        for (size_t k = 0; k < graph_edge_point_count(g, e); k++) {
            int64_t x, y;
            graph_edge_point(g, e, k, &x, &y);
            x -= b->ox, y -= b->oy;
            xmin = x < xmin ? x : xmin, xmax = x > xmax ? x : xmax;
            ymin = y < ymin ? y : ymin, ymax = y > ymax ? y : ymax;
        }
        int32_t level = -1;
        int64_t cw = info->width / b->p.root_cols, ch = info->height / b->p.root_rows;
        while (xmin / cw == xmax / cw && ymin / ch == ymax / ch) {
            level++;
            if (cw % b->p.cols || ch % b->p.rows)
                break; /* 1 x 1 pixels are reached: no deeper level exists */
            cw /= b->p.cols;
            ch /= b->p.rows;
        }
        b->edge_level[e] = level;
    }
}

static int make_segments(builder *b)
{
    const hpfc_graph *g = b->g;
    size_t n = 0;
    for (size_t e = 0; e < g->ne; e++)
        n += graph_edge_point_count(g, e) - 1;
    if (n > UINT32_MAX - 1)
        return diag_set(b->diag, HPFC_E_LIMIT, "more than 2^32 - 2 segments");
    b->segs = malloc((n ? n : 1) * sizeof *b->segs);
    if (!b->segs)
        return HPFC_E_NOMEM;
    b->nsegs = n;
    size_t s = 0;
    for (size_t e = 0; e < g->ne; e++)
        for (size_t k = 1; k < graph_edge_point_count(g, e); k++, s++)
            b->segs[s] = (seg){(uint32_t)e, (uint32_t)(k - 1)};
    return HPFC_OK;
}

/* ---- tree storage ------------------------------------------------------- */

static const char PRIVATE_WORD[4] = {'+', '+', '+', '+'};

static int tree_init(builder *b, uint32_t max_levels)
{
    hpfc_tree *t = b->t;
    t->levels = calloc(max_levels, sizeof *t->levels);
    if (!t->levels)
        return HPFC_E_NOMEM;
    t->levels_cap = max_levels;
    int st = reserve((void **)&t->syms, &t->cap_syms, 4, 1);
    if (st)
        return st;
    memcpy(t->syms, PRIVATE_WORD, 4); /* every private pixel shares offset 0 */
    t->nsyms = 4;
    return HPFC_OK;
}

static int level_add_image(tlevel *lv, int64_t gx, int64_t gy, size_t *index)
{
    size_t per = (size_t)lv->cols * lv->rows;
    if (lv->nimages == lv->cap) {
        /* a large image (the root, or a flat grid) is allocated alone: the
         * default 64x64 root once took room for 16, 1 MB that every part of
         * a split build held until the join */
        size_t ncap = lv->cap ? 2 * lv->cap : per >= 256 ? 1 : 16;
        int64_t *ngx = realloc(lv->img_gx, ncap * sizeof *ngx);
        if (!ngx)
            return HPFC_E_NOMEM;
        lv->img_gx = ngx;
        int64_t *ngy = realloc(lv->img_gy, ncap * sizeof *ngy);
        if (!ngy)
            return HPFC_E_NOMEM;
        lv->img_gy = ngy;
        if (ncap > SIZE_MAX / per / sizeof(tpixel))
            return HPFC_E_NOMEM;
        tpixel *np = realloc(lv->pix, ncap * per * sizeof *np);
        if (!np)
            return HPFC_E_NOMEM;
        lv->pix = np;
        lv->cap = ncap;
    }
    lv->img_gx[lv->nimages] = gx;
    lv->img_gy[lv->nimages] = gy;
    *index = lv->nimages++;
    return HPFC_OK;
}

/* ---- words -------------------------------------------------------------- */

typedef struct crossing {
    line_pos pos;
    uint32_t seg;       /* index into b->segs */
    uint32_t edge, k;   /* the segment's edge and index within it */
    uint8_t road;
    uint8_t entering;
    uint32_t comp;      /* component within the pixel */
} crossing;

typedef struct component {
    int64_t vertex;     /* junction vertex, or -1 for a stabbing */
    uint32_t size, seen;
} component;

typedef struct word_scratch {
    crossing *cr;
    size_t ncr, cap_cr;
    component *comp;
    size_t ncomp, cap_comp;
} word_scratch;

/* Crossings by edge, then by segment along it.
 * (Every qsort comparator of the library has this field-by-field shape;
 * each orders its own record, so they share no code.) */
static int cmp_along_edge(const void *pa, const void *pb)
{
    const crossing *a = pa, *b = pb;
    if (a->edge != b->edge)
        return a->edge < b->edge ? -1 : 1;
    if (a->k != b->k)
        return a->k < b->k ? -1 : 1;
    /* within one segment the entry (if any) precedes the exit */
    return (int)b->entering - (int)a->entering;
}

/* Clockwise order around the pixel from its SW corner: W going north,
 * N going east, E going south, S going west. */
static int cmp_clockwise(const void *pa, const void *pb)
{
    const crossing *a = pa, *b = pb;
    if (a->road != b->road)
        return a->road < b->road ? -1 : 1;
    int c = cmp_line_pos(&a->pos, &b->pos);
    return a->road == HPFC_WEST || a->road == HPFC_NORTH ? c : -c;
}

/* Sorts a pixel's crossings: most pixels have a handful, where insertion
 * sort beats qsort's overhead. */
static void sort_crossings(crossing *cr, size_t n, int (*cmp)(const void *, const void *))
{
    if (n > 16) {
        qsort(cr, n, sizeof *cr, cmp);
        return;
    }
    for (size_t i = 1; i < n; i++) {
        crossing c = cr[i];
        size_t j = i;
        for (; j > 0 && cmp(&cr[j - 1], &c) > 0; j--)
            cr[j] = cr[j - 1];
        cr[j] = c;
    }
}

static int add_component(word_scratch *w, int64_t vertex, uint32_t *id)
{
    if (vertex >= 0)
        for (size_t c = 0; c < w->ncomp; c++)
            if (w->comp[c].vertex == vertex) {
                *id = (uint32_t)c;
                return HPFC_OK;
            }
    int st = reserve((void **)&w->comp, &w->cap_comp, w->ncomp + 1, sizeof *w->comp);
    if (st)
        return st;
    w->comp[w->ncomp] = (component){vertex, 0, 0};
    *id = (uint32_t)w->ncomp++;
    return HPFC_OK;
}

static int join(word_scratch *w, crossing *c, int64_t vertex)
{
    int st = add_component(w, vertex, &c->comp);
    if (!st)
        w->comp[c->comp].size++;
    return st;
}

static int internal_error(builder *b, const char *what, uint32_t edge)
{
    if (b->diag)
        b->diag->edge[0] = edge;
    return diag_set(b->diag, HPFC_E_LIMIT, "internal inconsistency (%s) at edge %u", what, edge);
}

/* Splits the crossings of each edge into pieces inside the pixel: a piece
 * that reaches a vertex in the pixel joins that junction's component, a
 * piece between two crossings is a stabbing. */
static int assign_components(builder *b, word_scratch *w, const int64_t cell[4])
{
    sort_crossings(w->cr, w->ncr, cmp_along_edge);
    const hpfc_graph *g = b->g;
    size_t i = 0;
    while (i < w->ncr) {
        uint32_t e = w->cr[i].edge;
        lpoint u = edge_point(b, e, 0), v = edge_point(b, e, graph_edge_point_count(g, e) - 1);
        bool u_in = point_in_cell(u, cell[0], cell[1], cell[2], cell[3]);
        bool v_in = point_in_cell(v, cell[0], cell[1], cell[2], cell[3]);
        bool inside = u_in, from_vertex = u_in;
        crossing *open = NULL;
        int st;
        for (; i < w->ncr && w->cr[i].edge == e; i++) {
            crossing *c = &w->cr[i];
            if (c->entering == inside)
                return internal_error(b, "crossing parity", e);
            if (c->entering) {
                open = c;
                from_vertex = false;
            } else if (from_vertex) {
                if ((st = join(w, c, g->eu[e])))
                    return st;
            } else {
                if ((st = join(w, open, -1)))
                    return st;
                c->comp = open->comp;
                w->comp[c->comp].size++;
            }
            inside = c->entering;
        }
        if (inside != v_in || (inside && from_vertex))
            return internal_error(b, "edge inside a word pixel", e);
        if (inside && (st = join(w, open, g->ev[e])))
            return st;
    }
    return HPFC_OK;
}

/* Does a crossing of the word lie past its edge's first segment? */
static bool beyond_first_segment(const word_scratch *w)
{
    for (size_t k = 0; k < w->ncr; k++)
        if (w->cr[k].k)
            return true;
    return false;
}

/* Room for `more` crossings after the tree's, cross_seg (when there is
 * one) following cross_edge's capacity. */
static int reserve_crossings(hpfc_tree *t, size_t more)
{
    size_t old_cap = t->cap_cross;
    int st = reserve((void **)&t->cross_edge, &t->cap_cross, t->ncross + more, sizeof(uint32_t));
    if (!st && t->cross_seg && t->cap_cross != old_cap) {
        uint32_t *ns = realloc(t->cross_seg, t->cap_cross * sizeof *ns);
        if (!ns)
            return HPFC_E_NOMEM;
        t->cross_seg = ns;
    }
    return st;
}

/* The tree's first crossing past an edge's first segment: cross_seg made,
 * the crossings so far all on first segments. */
static int start_cross_seg(hpfc_tree *t)
{
    if (!t->cross_seg && !(t->cross_seg = calloc(t->cap_cross ? t->cap_cross : 1, sizeof *t->cross_seg)))
        return HPFC_E_NOMEM;
    return HPFC_OK;
}

static int append_word(builder *b, word_scratch *w, tpixel *px)
{
    hpfc_tree *t = b->t;
    sort_crossings(w->cr, w->ncr, cmp_clockwise);
    size_t len = w->ncr + 4;
    int st = reserve((void **)&t->syms, &t->cap_syms, t->nsyms + len, 1);
    if (!st)
        st = reserve_crossings(t, w->ncr);
    if (!st && beyond_first_segment(w))
        st = start_cross_seg(t);
    if (st)
        return st;
    if (w->ncr > TPIXEL_COUNT_MAX || t->ncross > TPIXEL_CROSS_OFF_MAX - w->ncr)
        return diag_set(b->diag, HPFC_E_LIMIT,
                        "more than 2^24 - 2 crossings in a pixel, or "
                        "2^40 in all");
    px->off = t->nsyms;
    px->cross = (uint64_t)t->ncross << TPIXEL_COUNT_BITS | w->ncr;
    char *out = t->syms + t->nsyms;
    size_t k = 0;
    for (int road = 0; road < 4; road++) {
        for (; k < w->ncr && w->cr[k].road == road; k++) {
            component *c = &w->comp[w->cr[k].comp];
            c->seen++;
            *out++ = word_crossing_symbol(c->vertex >= 0, c->seen, c->size);
            t->cross_edge[t->ncross] = b->edge_ids ? b->edge_ids[w->cr[k].edge] : w->cr[k].edge;
            if (t->cross_seg)
                t->cross_seg[t->ncross] = w->cr[k].k;
            t->ncross++;
        }
        *out++ = '+';
    }
    t->nsyms += len;
    if (len > t->info.max_word_symbols)
        t->info.max_word_symbols = (uint32_t)len;
    return HPFC_OK;
}

static int make_word(builder *b, word_scratch *w, const uint32_t *list, size_t n,
                     const int64_t cell[4], tpixel *px)
{
    w->ncr = 0;
    w->ncomp = 0;
    for (size_t i = 0; i < n; i++) {
        const seg *s = &b->segs[list[i]];
        lpoint sa, sb;
        seg_points(b, s, &sa, &sb);
        for (int road = 0; road < 4; road++) {
            crossing c;
            bool entering;
            if (!cross_road(sa, sb, road, cell[0], cell[1], cell[2], cell[3], &c.pos, &entering))
                continue;
            int st = reserve((void **)&w->cr, &w->cap_cr, w->ncr + 1, sizeof *w->cr);
            if (st)
                return st;
            c.seg = list[i];
            c.edge = s->edge;
            c.k = s->k;
            c.road = (uint8_t)road;
            c.entering = entering;
            c.comp = 0;
            w->cr[w->ncr++] = c;
        }
    }
    if (w->ncr == 0) {
        /* the shared "++++" at offset 0 */
        *px = (tpixel){0, (uint64_t)b->t->ncross << TPIXEL_COUNT_BITS};
        b->t->info.private_pixels++;
        return HPFC_OK;
    }
    int st = assign_components(b, w, cell);
    if (st)
        return st;
    for (size_t c = 0; c < w->ncomp; c++) {
        int64_t v = w->comp[c].vertex;
        if (v >= 0) {
            /* one byte a vertex, shared by a level's threads */
            if (__atomic_exchange_n(&b->vertex_seen[v], 1, __ATOMIC_RELAXED))
                return internal_error(b, "vertex in two pixels", b->segs[list[0]].edge);
        }
    }
    return append_word(b, w, px);
}

/* ---- distributing segments to the pixels of an image -------------------- */

typedef struct incidence {
    uint32_t pixel; /* scanline index within the image */
    uint32_t seg;
} incidence;

/* Incidences by pixel, then by segment.
 * (Every qsort comparator of the library has this field-by-field shape;
 * each orders its own record, so they share no code.) */
static int cmp_incidence(const void *pa, const void *pb)
{
    const incidence *a = pa, *b = pb;
    if (a->pixel != b->pixel)
        return a->pixel < b->pixel ? -1 : 1;
    return (a->seg > b->seg) - (a->seg < b->seg);
}

typedef struct image_scratch {
    incidence *inc, *sorted;
    size_t ninc, cap_inc, cap_sorted;
    uint32_t *sub;            /* one pixel's segments */
    size_t cap_sub;
    size_t *count;
    size_t cap_count;
} image_scratch;

/* Orders the incidences by pixel, keeping each pixel's segments in list
 * order: a counting sort when the image is not much larger than the
 * incidences, qsort (by pixel, then segment) for sparse large images. */
static int group_by_pixel(image_scratch *is, size_t pixels)
{
    if (pixels > 4 * is->ninc + 1024) {
        if (is->ninc) /* a part's image may hold none, and inc be NULL */
            qsort(is->inc, is->ninc, sizeof *is->inc, cmp_incidence);
        return HPFC_OK;
    }
    if (reserve((void **)&is->count, &is->cap_count, pixels + 1, sizeof *is->count) ||
        reserve((void **)&is->sorted, &is->cap_sorted, is->ninc + 1, sizeof *is->sorted))
        return HPFC_E_NOMEM;
    memset(is->count, 0, (pixels + 1) * sizeof *is->count);
    for (size_t k = 0; k < is->ninc; k++)
        is->count[is->inc[k].pixel + 1]++;
    for (size_t p = 0; p < pixels; p++)
        is->count[p + 1] += is->count[p];
    for (size_t k = 0; k < is->ninc; k++)
        is->sorted[is->count[is->inc[k].pixel]++] = is->inc[k];
    incidence *t = is->inc;  /* swap buffers: the sorted one becomes inc */
    size_t tc = is->cap_inc;
    is->inc = is->sorted, is->cap_inc = is->cap_sorted;
    is->sorted = t, is->cap_sorted = tc;
    return HPFC_OK;
}

static int64_t floor_div(int64_t a, int64_t b)
{
    return a / b - (a % b != 0 && (a < 0) != (b < 0));
}

/* Collects (pixel, segment) for every pixel of the image each segment
 * meets, sorted by pixel. */
static int distribute(builder *b, const tlevel *lv, int64_t gx0, int64_t gy0,
                      const uint32_t *list, size_t n, image_scratch *is)
{
    is->ninc = 0;
    int64_t cols = lv->cols, rows = lv->rows;
    for (size_t i = 0; i < n; i++) {
        lpoint sa, sb;
        seg_points(b, &b->segs[list[i]], &sa, &sb);
        int64_t c0 = floor_div(sa.x < sb.x ? sa.x : sb.x, lv->cell_w) - gx0;
        int64_t c1 = floor_div(sa.x > sb.x ? sa.x : sb.x, lv->cell_w) - gx0;
        int64_t r0 = floor_div(sa.y < sb.y ? sa.y : sb.y, lv->cell_h) - gy0;
        int64_t r1 = floor_div(sa.y > sb.y ? sa.y : sb.y, lv->cell_h) - gy0;
        bool single = c0 == c1 && r0 == r1;
        c0 = c0 < 0 ? 0 : c0, r0 = r0 < 0 ? 0 : r0;
        c1 = c1 >= cols ? cols - 1 : c1, r1 = r1 >= rows ? rows - 1 : r1;
        for (int64_t r = r0; r <= r1; r++)
            for (int64_t c = c0; c <= c1; c++) {
                int64_t x0 = (gx0 + c) * lv->cell_w, y0 = (gy0 + r) * lv->cell_h;
                if (!single &&
                    !segment_meets_cell(sa, sb, x0, y0, x0 + lv->cell_w, y0 + lv->cell_h))
                    continue;
                int st = reserve((void **)&is->inc, &is->cap_inc, is->ninc + 1, sizeof *is->inc);
                if (st)
                    return st;
                /* scanline index: row j = 0 is the northern row */
                int64_t j = rows - 1 - r;
                is->inc[is->ninc++] = (incidence){(uint32_t)(j * cols + c), list[i]};
            }
    }
    return group_by_pixel(is, (size_t)cols * (size_t)rows);
}

/* Is the pixel at level-wide cell (gx, gy) of `level` holding a whole edge? */
static bool holds_edge(const builder *b, const tlevel *lv, uint32_t level, int64_t gx, int64_t gy,
                       const uint32_t *list, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        uint32_t e = b->segs[list[i]].edge;
        if (b->edge_level[e] < (int32_t)level)
            continue;
        /* the whole edge lies in one pixel of this level: its first point's */
        lpoint u = edge_point(b, e, 0);
        if (u.x / lv->cell_w == gx && u.y / lv->cell_h == gy)
            return true;
    }
    return false;
}

/* Does the pixel hold more shape points (interior points of edges) than the
 * bound? Point k >= 1 of an edge starts its segment k, so each point is
 * counted once, from the one segment of the list it starts. */
static bool holds_too_many_points(const builder *b, const int64_t cell[4], const uint32_t *list,
                                  size_t n)
{
    uint32_t bound = b->p.max_leaf_points, held = 0;
    if (bound == 0 || n <= bound)
        return false;
    for (size_t i = 0; i < n; i++) {
        const seg *s = &b->segs[list[i]];
        if (s->k == 0)
            continue;
        if (point_in_cell(edge_point(b, s->edge, s->k), cell[0], cell[1], cell[2], cell[3]) &&
            ++held > bound)
            return true;
    }
    return false;
}

static int push_child(builder *b, tlevel *next, int64_t gx, int64_t gy, const uint32_t *list,
                      size_t n, uint32_t *child)
{
    size_t index;
    int st = level_add_image(next, gx * next->cols, gy * next->rows, &index);
    if (st)
        return st;
    if (index > UINT32_MAX)
        return diag_set(b->diag, HPFC_E_LIMIT, "too many images in one level");
    *child = (uint32_t)index;
    st = reserve((void **)&b->next_list, &b->next_cap, b->next_len + n, sizeof *b->next_list);
    if (!st)
        st = reserve((void **)&b->next_start, &b->next_images_cap, index + 2, sizeof *b->next_start);
    if (st)
        return st;
    memcpy(b->next_list + b->next_len, list, n * sizeof *list);
    b->next_len += n;
    b->next_start[index] = b->next_len - n;
    b->next_start[index + 1] = b->next_len;
    return HPFC_OK;
}

static bool root_selected(const builder *b, size_t pixel)
{
    return !b->root_selected || (b->root_selected[pixel >> 3] >> (pixel & 7) & 1);
}

static int build_image(builder *b, uint32_t level, size_t image, image_scratch *is,
                       word_scratch *w)
{
    tlevel *lv = &b->t->levels[level];
    int64_t gx0 = lv->img_gx[image], gy0 = lv->img_gy[image];
    const uint32_t *list = b->cur_list + b->cur_start[image];
    size_t n = b->cur_start[image + 1] - b->cur_start[image];
    int st = distribute(b, lv, gx0, gy0, list, n, is);
    if (st)
        return st;
    size_t per = (size_t)lv->cols * lv->rows, k = 0;
    if (reserve((void **)&is->sub, &is->cap_sub, is->ninc + 1, sizeof *is->sub))
        return HPFC_E_NOMEM;
    uint32_t *sub = is->sub;
    for (size_t p = 0; p < per && !st; p++) {
        size_t first = k;
        while (k < is->ninc && is->inc[k].pixel == p)
            k++;
        for (size_t q = first; q < k; q++)
            sub[q - first] = is->inc[q].seg;
        size_t ns = k - first;
        int64_t i = (int64_t)(p % lv->cols), j = (int64_t)(p / lv->cols);
        int64_t gx = gx0 + i, gy = gy0 + (lv->rows - 1 - j);
        tpixel *px = &lv->pix[image * per + p];
        if (level == 0 && !root_selected(b, p)) {
            *px = (tpixel){0, TPIXEL_ABSENT}; /* another part's */
            continue;
        }
        int64_t cell[4] = {gx * lv->cell_w, gy * lv->cell_h, (gx + 1) * lv->cell_w, (gy + 1) * lv->cell_h};
        if (!b->p.flat && (holds_edge(b, lv, level, gx, gy, sub, ns) ||
                           (level < b->max_depth && holds_too_many_points(b, cell, sub, ns)))) {
            uint32_t child = 0;
            b->t->info.refined_pixels++;
            st = push_child(b, &b->t->levels[level + 1], gx, gy, sub, ns, &child);
            *px = (tpixel){child, TPIXEL_REFINED};
        } else {
            b->t->info.word_pixels++;
            st = make_word(b, w, sub, ns, cell, px);
        }
    }
    return st;
}

/* ---- driver ------------------------------------------------------------- */

static int check_params(const hpfc_build_params *p, hpfc_diag *diag)
{
    if (p->root_cols < 1 || p->root_rows < 1 || p->cols < 2 || p->rows < 2)
        return diag_set(diag, HPFC_E_ARG, "image sizes must be root >= 1x1 and refined >= 2x2");
    if ((uint64_t)p->root_cols * p->root_rows > ((uint64_t)1 << 31) ||
        (uint64_t)p->cols * p->rows > ((uint64_t)1 << 20))
        return diag_set(diag, HPFC_E_ARG, "image sizes too large (root <= 2^31 pixels, refined <= 2^20)");
    return HPFC_OK;
}

/* The flat rPFC: the root is the hierarchical grid of the first depth at
 * which no pixel holds an edge, so its pixels equal the finest hPFC leaves. */
static int flatten_root(builder *b)
{
    int32_t deepest = -1;
    for (size_t e = 0; e < b->g->ne; e++)
        deepest = b->edge_level[e] > deepest ? b->edge_level[e] : deepest;
    uint64_t cols = b->p.root_cols, rows = b->p.root_rows;
    uint64_t limit = b->p.max_flat_pixels < ((uint64_t)1 << 31) ? b->p.max_flat_pixels : (uint64_t)1 << 31;
    for (int32_t l = 0; l <= deepest; l++) {
        cols *= b->p.cols;
        rows *= b->p.rows;
        if (cols * rows > limit)
            break;
    }
    if (cols * rows > limit)
        return diag_set(b->diag, HPFC_E_TOO_MANY_PIXELS,
                        "the flat grid needs at least %llu x %llu pixels, above the limit of %llu",
                        (unsigned long long)cols, (unsigned long long)rows,
                        (unsigned long long)limit);
    b->p.root_cols = (uint32_t)cols;
    b->p.root_rows = (uint32_t)rows;
    b->max_depth = 0;
    return HPFC_OK;
}

static size_t find_root(uint32_t *parent, size_t v)
{
    while (parent[v] != v) {
        parent[v] = parent[parent[v]];
        v = parent[v];
    }
    return v;
}

static int count_components(builder *b)
{
    const hpfc_graph *g = b->g;
    uint32_t *parent = malloc(g->nv * sizeof *parent);
    if (!parent)
        return HPFC_E_NOMEM;
    for (size_t v = 0; v < g->nv; v++)
        parent[v] = (uint32_t)v;
    uint64_t comps = g->nv;
    for (size_t e = 0; e < g->ne; e++) {
        size_t a = find_root(parent, g->eu[e]), c = find_root(parent, g->ev[e]);
        if (a != c) {
            parent[a] = (uint32_t)c;
            comps--;
        }
    }
    free(parent);
    hpfc_tree_info *info = &b->t->info;
    info->vertices = g->nv;
    info->edges = g->ne;
    info->components = comps;
    info->faces = info->edges + 1 + comps - info->vertices; /* Euler: V - E + F = 1 + C */
    return HPFC_OK;
}

static int setup_root(builder *b)
{
    hpfc_tree *t = b->t;
    tlevel *root = &t->levels[0];
    root->cols = b->p.root_cols;
    root->rows = b->p.root_rows;
    root->cell_w = t->info.width / root->cols;
    root->cell_h = t->info.height / root->rows;
    size_t index;
    int st = level_add_image(root, 0, 0, &index);
    if (st)
        return st;
    b->cur_list = malloc((b->nsegs ? b->nsegs : 1) * sizeof *b->cur_list);
    b->cur_start = malloc(2 * sizeof *b->cur_start);
    if (!b->cur_list || !b->cur_start)
        return HPFC_E_NOMEM;
    for (size_t s = 0; s < b->nsegs; s++)
        b->cur_list[s] = (uint32_t)s;
    b->cur_start[0] = 0;
    b->cur_start[1] = b->nsegs;
    return HPFC_OK;
}

static void free_scratch(image_scratch *is, word_scratch *w)
{
    free(is->inc);
    free(is->sorted);
    free(is->count);
    free(is->sub);
    free(w->cr);
    free(w->comp);
}

/* Images [first, end) of `level`, in order, by the builder b. */
static int build_images(builder *b, uint32_t level, size_t first, size_t end)
{
    image_scratch is = {0};
    word_scratch w = {0};
    size_t total = b->t->levels[level].nimages;
    int st = HPFC_OK;
    for (size_t im = first; im < end && !st; im++) {
        st = build_image(b, level, im, &is, &w);
        if (b->p.progress && ((im + 1) % 4096 == 0 || im + 1 == total))
            b->p.progress(b->p.progress_user, level, im + 1, total);
    }
    free_scratch(&is, &w);
    return st;
}

/* ---- a level's images on several threads ---------------------------------
 *
 * The level's images are cut into runs of about equal segment counts. A
 * run is built by one thread, in order, as build_images would build it,
 * into a tree and next-level lists of its own (its pixels into the level's
 * own array, which runs share image by image). The runs are then spliced
 * onto the tree in order: their symbols, crossings, child images and
 * segment lists appended, and their pixels' offsets moved by what the runs
 * before them appended. So the tree is byte for byte the one thread's, and
 * a failure is the first run's that failed, which is the one thread's
 * first (but for "vertex in two pixels", an internal inconsistency, which
 * either of the two pixels' runs may report). */

typedef struct image_run {
    size_t first, end;
    builder b;              /* b.t is `t`, b.diag is `diag` */
    hpfc_tree t;            /* symbols from 4 ("++++" at 0, as the tree's), crossings, counts */
    hpfc_diag diag;
    int status;
} image_run;

typedef struct level_runs {
    builder *b;
    uint32_t level;
    image_run *run;
    size_t nruns;
    tasks_failure first_failed; /* the first run known to have failed: later ones stop */
} level_runs;

/* Cuts the level's images into at most `most` runs of about equal numbers
 * of segments (each image's list length, and one for the image). */
static size_t cut_runs(const builder *b, size_t nimages, size_t most, image_run *run)
{
    uint64_t total = b->cur_start[nimages] - b->cur_start[0] + nimages, done = 0;
    size_t n = 0, first = 0;
    for (size_t im = 0; im < nimages; im++) {
        done += b->cur_start[im + 1] - b->cur_start[im] + 1;
        if (done * most >= total * (n + 1) || im + 1 == nimages) {
            run[n++] = (image_run){.first = first, .end = im + 1};
            first = im + 1;
        }
    }
    return n;
}

static void free_run(image_run *r, uint32_t level)
{
    free(r->t.syms);
    free(r->t.cross_edge);
    free(r->t.cross_seg);
    if (r->t.levels && level + 1 < r->t.levels_cap) {
        free(r->t.levels[level + 1].img_gx);
        free(r->t.levels[level + 1].img_gy);
        free(r->t.levels[level + 1].pix);
    }
    free(r->t.levels);
    free(r->b.next_list);
    free(r->b.next_start);
}

static int start_run(const level_runs *lr, image_run *r)
{
    const hpfc_tree *t = lr->b->t;
    r->b = *lr->b;
    r->b.t = &r->t;
    r->b.diag = &r->diag;
    r->b.p.progress = NULL;
    r->b.next_list = NULL, r->b.next_start = NULL;
    r->b.next_len = r->b.next_cap = r->b.next_images_cap = 0;
    r->t.info = t->info;
    r->t.info.word_pixels = r->t.info.refined_pixels = r->t.info.private_pixels = 0;
    r->t.info.max_word_symbols = 0;
    if (!(r->t.levels = calloc(t->levels_cap, sizeof *r->t.levels)))
        return HPFC_E_NOMEM;
    r->t.levels_cap = t->levels_cap;
    r->t.levels[lr->level] = t->levels[lr->level]; /* its pixels are the tree's */
    if (lr->level + 1 < t->levels_cap) {
        const tlevel *next = &t->levels[lr->level + 1];
        r->t.levels[lr->level + 1] = (tlevel){.cols = next->cols, .rows = next->rows,
                                              .cell_w = next->cell_w, .cell_h = next->cell_h};
    }
    if (reserve((void **)&r->t.syms, &r->t.cap_syms, 4, 1))
        return HPFC_E_NOMEM;
    memcpy(r->t.syms, PRIVATE_WORD, 4);
    r->t.nsyms = 4;
    return HPFC_OK;
}

static void build_run(void *arg, size_t k)
{
    level_runs *lr = arg;
    image_run *r = &lr->run[k];
    if (tasks_failed_before(&lr->first_failed, k))
        return; /* an earlier run failed: this one is not spliced */
    diag_clear(&r->diag);
    r->status = start_run(lr, r);
    if (!r->status)
        r->status = build_images(&r->b, lr->level, r->first, r->end);
    if (r->status)
        tasks_failure_note(&lr->first_failed, k);
}

/* The run's pixels, which name its own symbols, crossings and children,
 * moved past the tree's. */
static void move_run_pixels(const tlevel *lv, const image_run *r, size_t sym_base, uint64_t cross_base,
                            size_t child_base)
{
    size_t per = (size_t)lv->cols * lv->rows;
    for (tpixel *px = lv->pix + r->first * per; px < lv->pix + r->end * per; px++) {
        if (px->cross == TPIXEL_REFINED)
            px->off += child_base;
        else if (px->cross != TPIXEL_ABSENT) {
            if (px->cross & ((UINT64_C(1) << TPIXEL_COUNT_BITS) - 1))
                px->off += sym_base; /* a private pixel keeps the shared "++++" at 0 */
            px->cross += cross_base << TPIXEL_COUNT_BITS;
        }
    }
}

/* The run's symbols and crossings after the tree's. */
static int append_run_words(builder *b, const image_run *r)
{
    hpfc_tree *t = b->t;
    const hpfc_tree *rt = &r->t;
    if (rt->ncross > TPIXEL_CROSS_OFF_MAX - t->ncross)
        return diag_set(b->diag, HPFC_E_LIMIT, "more than 2^24 - 2 crossings in a pixel, or 2^40 in all");
    int st = reserve((void **)&t->syms, &t->cap_syms, t->nsyms + rt->nsyms - 4, 1);
    if (!st)
        st = reserve_crossings(t, rt->ncross);
    if (!st && rt->cross_seg)
        st = start_cross_seg(t);
    if (st)
        return st;
    memcpy(t->syms + t->nsyms, rt->syms + 4, rt->nsyms - 4);
    t->nsyms += rt->nsyms - 4;
    if (rt->ncross) { /* else the arrays may be NULL */
        memcpy(t->cross_edge + t->ncross, rt->cross_edge, rt->ncross * sizeof *t->cross_edge);
        if (rt->cross_seg)
            memcpy(t->cross_seg + t->ncross, rt->cross_seg, rt->ncross * sizeof *t->cross_seg);
        else if (t->cross_seg)
            memset(t->cross_seg + t->ncross, 0, rt->ncross * sizeof *t->cross_seg);
        t->ncross += rt->ncross;
    }
    t->info.word_pixels += rt->info.word_pixels;
    t->info.refined_pixels += rt->info.refined_pixels;
    t->info.private_pixels += rt->info.private_pixels;
    if (rt->info.max_word_symbols > t->info.max_word_symbols)
        t->info.max_word_symbols = rt->info.max_word_symbols;
    return HPFC_OK;
}

/* The run's child images and their segment lists after the tree's. */
static int append_run_children(builder *b, uint32_t level, const image_run *r)
{
    if (level + 1 >= b->t->levels_cap)
        return HPFC_OK;
    tlevel *next = &b->t->levels[level + 1];
    const tlevel *rn = &r->t.levels[level + 1];
    size_t child_base = next->nimages, list_base = b->next_len;
    if (rn->nimages == 0)
        return HPFC_OK;
    if (child_base + rn->nimages - 1 > UINT32_MAX)
        return diag_set(b->diag, HPFC_E_LIMIT, "too many images in one level");
    if (reserve((void **)&b->next_list, &b->next_cap, b->next_len + r->b.next_len, sizeof *b->next_list) ||
        reserve((void **)&b->next_start, &b->next_images_cap, child_base + rn->nimages + 2,
                sizeof *b->next_start))
        return HPFC_E_NOMEM;
    for (size_t i = 0; i < rn->nimages; i++) {
        size_t index;
        if (level_add_image(next, rn->img_gx[i], rn->img_gy[i], &index))
            return HPFC_E_NOMEM;
        b->next_start[index] = list_base + r->b.next_start[i];
    }
    b->next_start[next->nimages] = list_base + r->b.next_len;
    if (r->b.next_len)
        memcpy(b->next_list + list_base, r->b.next_list, r->b.next_len * sizeof *b->next_list);
    b->next_len += r->b.next_len;
    return HPFC_OK;
}

static int splice_run(builder *b, uint32_t level, const image_run *r)
{
    tlevel *lv = &b->t->levels[level];
    size_t child_base = level + 1 < b->t->levels_cap ? b->t->levels[level + 1].nimages : 0;
    move_run_pixels(lv, r, b->t->nsyms - 4, b->t->ncross, child_base);
    int st = append_run_words(b, r);
    if (!st)
        st = append_run_children(b, level, r);
    if (!st && b->p.progress)
        b->p.progress(b->p.progress_user, level, r->end, lv->nimages);
    return st;
}

static int build_level_threads(builder *b, uint32_t level, unsigned threads)
{
    size_t nimages = b->t->levels[level].nimages, most = (size_t)threads * 8;
    level_runs lr = {.b = b, .level = level};
    tasks_failure_init(&lr.first_failed);
    if (!(lr.run = calloc(most < nimages ? most : nimages, sizeof *lr.run)))
        return HPFC_E_NOMEM;
    lr.nruns = cut_runs(b, nimages, most < nimages ? most : nimages, lr.run);
    tasks_run(threads, lr.nruns, build_run, &lr);
    int st = HPFC_OK;
    for (size_t k = 0; k < lr.nruns && !st; k++) {
        if ((st = lr.run[k].status) != HPFC_OK) {
            if (b->diag && st != HPFC_E_NOMEM)
                *b->diag = lr.run[k].diag;
        } else
            st = splice_run(b, level, &lr.run[k]);
    }
    for (size_t k = 0; k < lr.nruns; k++)
        free_run(&lr.run[k], level);
    free(lr.run);
    return st;
}

static int build_levels(builder *b)
{
    hpfc_tree *t = b->t;
    int st = HPFC_OK;
    uint32_t level = 0;
    for (;; level++) {
        tlevel *lv = &t->levels[level];
        if (level < b->max_depth) {
            tlevel *next = &t->levels[level + 1];
            next->cols = b->p.cols;
            next->rows = b->p.rows;
            next->cell_w = lv->cell_w / b->p.cols;
            next->cell_h = lv->cell_h / b->p.rows;
        }
        b->next_len = 0;
        if (b->p.threads > 1 && lv->nimages > 1)
            st = build_level_threads(b, level, b->p.threads);
        else
            st = build_images(b, level, 0, lv->nimages);
        if (st || level >= b->max_depth || t->levels[level + 1].nimages == 0)
            break;
        /* the next level's segment lists become the current ones */
        free(b->cur_list);
        free(b->cur_start);
        b->cur_list = b->next_list, b->cur_start = b->next_start;
        b->next_list = NULL, b->next_start = NULL;
        b->next_cap = b->next_images_cap = 0;
    }
    t->info.levels = level + 1;
    return st;
}

static void free_builder(builder *b)
{
    free(b->segs);
    free(b->edge_level);
    free(b->vertex_seen);
    free(b->cur_list);
    free(b->next_list);
    free(b->cur_start);
    free(b->next_start);
}

int hpfc_build_domain_sized(const int64_t box[4], const hpfc_build_params *params_arg,
                            size_t params_size, hpfc_domain *out, hpfc_diag *diag)
{
    hpfc_build_params full;
    hpfc_build_params_default(&full);
    diag_clear(diag);
    if (!box || !params_arg || !out || sized_in(&full, sizeof full, params_arg, params_size))
        return diag_set(diag, HPFC_E_ARG, "hpfc_build_domain: NULL or unknown argument");
    int st = check_params(&full, diag);
    if (st)
        return st;
    if (box[0] > box[2] || box[1] > box[3])
        return diag_set(diag, HPFC_E_ARG, "hpfc_build_domain: an empty box");
    for (int k = 0; k < 4; k++)
        if (box[k] < -HPFC_COORD_MAX || box[k] > HPFC_COORD_MAX)
            return diag_set(diag, HPFC_E_EXTENT, "a coordinate beyond 2^40 lattice units");
    return domain_of_box(box, &full, out, diag);
}

/* The root pixel holding domain-relative point (x, y), scanline index. */
static size_t root_pixel_of(const builder *b, int64_t x, int64_t y)
{
    const tlevel *root = &b->t->levels[0];
    int64_t i = x / root->cell_w, j = root->rows - 1 - y / root->cell_h;
    return (size_t)j * root->cols + (size_t)i;
}

/* A part holds the vertices that lie in its root pixels: each must be in
 * one of its words, as hpfc_build checks of every vertex. */
static int count_part_vertices(builder *b)
{
    uint64_t held = 0;
    for (size_t v = 0; v < b->g->nv; v++) {
        int64_t x = b->g->vxy[2 * v] - b->ox, y = b->g->vxy[2 * v + 1] - b->oy;
        if (!root_selected(b, root_pixel_of(b, x, y)))
            continue;
        if (!b->vertex_seen[v])
            return internal_error(b, "vertex in no word pixel", 0);
        held++;
    }
    b->t->info.vertices = held;
    b->t->info.edges = b->edge_ids ? b->edge_count : b->g->ne;
    b->t->part = true;
    return HPFC_OK;
}

static int check_vertices_seen(builder *b)
{
    for (size_t v = 0; v < b->g->nv; v++)
        if (!b->vertex_seen[v])
            return internal_error(b, "vertex in no word pixel", 0);
    return HPFC_OK;
}

/* The build proper, once the builder holds its graph, params and diag:
 * the domain (the part's, or chosen from the graph), the levels, the
 * checks and counts at the end. Frees the builder's arrays; on failure the
 * tree too. */
static int run_build(builder *b, const hpfc_domain *domain, hpfc_tree **out)
{
    const hpfc_graph *g = b->g;
    int st = HPFC_OK;
    b->t = calloc(1, sizeof *b->t);
    b->edge_level = malloc((g->ne ? g->ne : 1) * sizeof *b->edge_level);
    b->vertex_seen = calloc(g->nv ? g->nv : 1, 1);
    if (!b->t || !b->edge_level || !b->vertex_seen)
        st = HPFC_E_NOMEM;
    if (!st && domain)
        set_domain(b, domain);
    else if (!st)
        st = choose_domain(b);
    if (!st)
        st = make_segments(b);
    if (!st) {
        compute_edge_levels(b);
        if (b->p.flat)
            st = flatten_root(b);
    }
    if (!st) {
        b->t->info.root_cols = b->p.root_cols;
        b->t->info.root_rows = b->p.root_rows;
        b->t->info.cols = b->p.cols;
        b->t->info.rows = b->p.rows;
        st = tree_init(b, b->max_depth + 1);
    }
    if (!st)
        st = setup_root(b);
    if (!st)
        st = build_levels(b);
    if (!st)
        st = b->root_selected ? count_part_vertices(b) : check_vertices_seen(b);
    if (!st && !b->root_selected)
        st = count_components(b);
    if (st == HPFC_E_NOMEM)
        diag_set(b->diag, st, "out of memory");
    free_builder(b);
    if (!st && !b->t->cross_seg &&
        !(b->t->zero_seg = calloc((size_t)b->t->info.max_word_symbols + 1, sizeof *b->t->zero_seg)))
        st = HPFC_E_NOMEM;
    if (st) {
        hpfc_tree_free(b->t);
        return st;
    }
    *out = b->t;
    return HPFC_OK;
}

int hpfc_build_sized(const hpfc_graph *g, const hpfc_build_params *params_arg,
                     size_t params_size, hpfc_tree **out, hpfc_diag *diag)
{
    hpfc_build_params full;
    hpfc_build_params_default(&full);
    if (!g || !params_arg || !out || sized_in(&full, sizeof full, params_arg, params_size))
        return HPFC_E_ARG;
    *out = NULL;
    int st = check_params(&full, diag);
    if (st)
        return st;
    st = graph_validate_threads(g, full.threads, diag);
    if (st)
        return st;
    builder b = {.g = g, .p = full, .diag = diag};
    return run_build(&b, NULL, out);
}

/* ---- a part of a split build -------------------------------------------- */

/* The domain must be one hpfc_build_domain gives with these params: its
 * size root_cols * cols^max_depth (and rows alike), its origin in range. */
static int check_part_domain(const hpfc_build_params *p, const hpfc_domain *d, hpfc_diag *diag)
{
    int64_t W = p->root_cols, H = p->root_rows;
    for (uint32_t k = 0; k < d->max_depth; k++) {
        if (W > HPFC_LATTICE_MAX / p->cols || H > HPFC_LATTICE_MAX / p->rows)
            return diag_set(diag, HPFC_E_ARG, "hpfc_build_part: a domain deeper than the lattice");
        W *= p->cols;
        H *= p->rows;
    }
    if (W != d->width || H != d->height || d->x0 < -HPFC_LATTICE_MAX || d->x0 > HPFC_LATTICE_MAX ||
        d->y0 < -HPFC_LATTICE_MAX || d->y0 > HPFC_LATTICE_MAX)
        return diag_set(diag, HPFC_E_ARG,
                        "hpfc_build_part: the domain is not one hpfc_build_domain gives with these params");
    return HPFC_OK;
}

/* Every point of the part's graph strictly inside the domain, as the whole
 * map's points are in the domain hpfc_build_domain gives for their box. */
static int check_part_points(const hpfc_graph *g, const hpfc_domain *d, hpfc_diag *diag)
{
    for (size_t v = 0; v < g->nv; v++) {
        int64_t x = g->vxy[2 * v], y = g->vxy[2 * v + 1];
        if (x <= d->x0 || x >= d->x0 + d->width || y <= d->y0 || y >= d->y0 + d->height)
            return diag_set(diag, HPFC_E_ARG, "hpfc_build_part: vertex %zu lies outside the domain", v);
    }
    for (size_t k = 0; k < g->npts; k++) {
        int64_t x = g->pts[2 * k], y = g->pts[2 * k + 1];
        if (x <= d->x0 || x >= d->x0 + d->width || y <= d->y0 || y >= d->y0 + d->height)
            return diag_set(diag, HPFC_E_ARG, "hpfc_build_part: a shape point lies outside the domain");
    }
    return HPFC_OK;
}

/* Root pixels ascending below the root's count; edge ids ascending below
 * the whole map's edge count (so that the part's graph orders its edges as
 * the whole map does, which orders crossings in a word). */
static int check_part_lists(const hpfc_graph *g, const hpfc_build_params *p, const hpfc_part *part,
                            hpfc_diag *diag)
{
    uint64_t roots = (uint64_t)p->root_cols * p->root_rows;
    if (part->root_pixel_count && !part->root_pixels)
        return diag_set(diag, HPFC_E_ARG, "hpfc_build_part: NULL root pixels");
    for (size_t k = 0; k < part->root_pixel_count; k++)
        if (part->root_pixels[k] >= roots || (k && part->root_pixels[k] <= part->root_pixels[k - 1]))
            return diag_set(diag, HPFC_E_ARG,
                            "hpfc_build_part: root pixels must be ascending indices below %llu",
                            (unsigned long long)roots);
    if (!part->edge_ids) {
        if (part->edge_count && part->edge_count != g->ne)
            return diag_set(diag, HPFC_E_ARG,
                            "hpfc_build_part: edge_count without edge_ids must be the graph's");
        return HPFC_OK;
    }
    if (part->edge_count > (uint64_t)UINT32_MAX + 1)
        return diag_set(diag, HPFC_E_ARG, "hpfc_build_part: more than 2^32 edges");
    for (size_t e = 0; e < g->ne; e++)
        if (part->edge_ids[e] >= part->edge_count || (e && part->edge_ids[e] <= part->edge_ids[e - 1]))
            return diag_set(diag, HPFC_E_ARG,
                            "hpfc_build_part: edge ids must be ascending and below edge_count");
    return HPFC_OK;
}

static int select_roots(builder *b, const hpfc_part *part)
{
    uint64_t roots = (uint64_t)b->p.root_cols * b->p.root_rows;
    b->root_selected = calloc((size_t)(roots + 7) / 8, 1);
    if (!b->root_selected)
        return HPFC_E_NOMEM;
    for (size_t k = 0; k < part->root_pixel_count; k++)
        b->root_selected[part->root_pixels[k] >> 3] |= (uint8_t)(1u << (part->root_pixels[k] & 7));
    return HPFC_OK;
}

int hpfc_build_part_sized(const hpfc_graph *g, const hpfc_build_params *params_arg,
                          size_t params_size, const hpfc_part *part, hpfc_tree **out,
                          hpfc_diag *diag)
{
    hpfc_build_params full;
    hpfc_build_params_default(&full);
    diag_clear(diag);
    if (!g || !params_arg || !part || !out || sized_in(&full, sizeof full, params_arg, params_size))
        return diag_set(diag, HPFC_E_ARG, "hpfc_build_part: NULL or unknown argument");
    *out = NULL;
    int st = check_params(&full, diag);
    if (!st && full.flat)
        st = diag_set(diag, HPFC_E_ARG, "hpfc_build_part: a flat rPFC is not built in parts");
    if (!st)
        st = check_part_domain(&full, &part->domain, diag);
    if (!st)
        st = check_part_lists(g, &full, part, diag);
    if (!st && (g->ne || g->nv)) /* a part may hold no edge: its pixels are private */
        st = graph_validate_threads(g, full.threads, diag);
    if (!st)
        st = check_part_points(g, &part->domain, diag);
    if (st)
        return st;
    builder b = {.g = g, .p = full, .diag = diag, .edge_ids = part->edge_ids,
                 .edge_count = part->edge_count};
    if (select_roots(&b, part))
        return diag_set(diag, HPFC_E_NOMEM, "out of memory");
    st = run_build(&b, &part->domain, out);
    free(b.root_selected);
    return st;
}

void hpfc_build_params_init(hpfc_build_params *params, size_t size)
{
    if (!params)
        return;
    const hpfc_build_params defaults = {
        .root_cols = 64, .root_rows = 64, .cols = 2, .rows = 2, .flat = 0,
        .max_flat_pixels = HPFC_DEFAULT_MAX_FLAT_PIXELS,
        .max_leaf_points = HPFC_DEFAULT_MAX_LEAF_POINTS,
        .progress = NULL, .progress_user = NULL, .threads = 1};
    sized_out(params, size, &defaults, sizeof defaults);
}

