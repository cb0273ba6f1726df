#include "render.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <time.h>
#include <unistd.h>

#ifdef HPFC_HAVE_CAIRO
#include <cairo.h>
#endif

#include "jsonw.h"
#include "roads.h"
#include "views.h"

/* ---- the scene: what to draw, in image coordinates (y down) ---------------- */

typedef struct frect {
    float x, y, w, h;
    uint8_t depth, outline;
} frect;

typedef struct fseg {
    float x0, y0, x1, y1;
} fseg;

typedef struct fpt {
    float x, y;
} fpt;

typedef struct flabel {
    float x, y;
    char text[64];
} flabel;

typedef struct scene {
    const hpfc_file *f;
    hpfc_file_info info;
    hpfc_level_info levels[HPFC_MAX_LEVELS];
    roads r;
    word_info wi;
    fpt *pts;                /* per crossing of the current leaf */
    double *pos, *sum;       /* per crossing; per component (x, y) */
    size_t cap;
    double wx0, wy0, wx1, wy1; /* window, lattice units */
    double scale, offx, offy;
    uint32_t width, height;
    struct { frect *v; size_t n, cap; } rects, ink;
    struct { fseg *v; size_t n, cap; } segs;
    struct { fpt *v; size_t n, cap; } dots;
    struct { flabel *v; size_t n, cap; } labels;
    uint64_t leaves;
    uint64_t visits, max_visits; /* pixels visited; all pixels the levels count */
} scene;

static int reserve(void **v, size_t *cap, size_t n, size_t size)
{
    if (n <= *cap)
        return 0;
    size_t c = *cap ? *cap : 256;
    while (c < n)
        c *= 2;
    void *p = realloc(*v, c * size);
    if (!p)
        return -1;
    *v = p;
    *cap = c;
    return 0;
}

#define PUSH(vec, item)                                                                  \
    (reserve((void **)&(vec).v, &(vec).cap, (vec).n + 1, sizeof *(vec).v)              \
         ? HPFC_E_NOMEM                                                                  \
         : ((vec).v[(vec).n++] = (item), HPFC_OK))

static void scene_free(scene *s)
{
    roads_free(&s->r);
    word_info_free(&s->wi);
    free(s->pts);
    free(s->pos);
    free(s->sum);
    free(s->rects.v);
    free(s->ink.v);
    free(s->segs.v);
    free(s->dots.v);
    free(s->labels.v);
}

static double img_x(const scene *s, double x)
{
    return s->offx + (x - s->wx0) * s->scale;
}

static double img_y(const scene *s, double y)
{
    return (double)s->height - (s->offy + (y - s->wy0) * s->scale);
}

static fpt to_img(const scene *s, double x, double y)
{
    return (fpt){(float)img_x(s, x), (float)img_y(s, y)};
}

static frect box_rect(const scene *s, const lbox *b, uint32_t depth)
{
    double x0 = img_x(s, (double)b->x0), x1 = img_x(s, (double)b->x1);
    double y0 = img_y(s, (double)b->y1), y1 = img_y(s, (double)b->y0);
    return (frect){(float)x0, (float)y0, (float)(x1 - x0), (float)(y1 - y0), (uint8_t)depth, 0};
}

/* ---- one leaf ------------------------------------------------------------------ */

static int reserve_leaf(scene *s, uint32_t n)
{
    if (n <= s->cap)
        return HPFC_OK;
    size_t cap = s->cap ? s->cap : 64;
    while (cap < n)
        cap *= 2;
    fpt *pts = realloc(s->pts, cap * sizeof *pts);
    if (pts)
        s->pts = pts;
    double *pos = realloc(s->pos, cap * sizeof *pos);
    if (pos)
        s->pos = pos;
    double *sum = realloc(s->sum, 3 * cap * sizeof *sum);
    if (sum)
        s->sum = sum;
    if (!pts || !pos || !sum)
        return HPFC_E_NOMEM;
    s->cap = cap;
    return HPFC_OK;
}

/* Image positions of the current leaf's crossings (s->wi). */
static int crossing_points(scene *s, const lbox *b)
{
    const word_info *wi = &s->wi;
    for (int road = 0; road < 4; road++) {
        uint32_t off = wi->road_off[road], c = wi->road_off[road + 1] - off;
        int st = roads_positions(&s->r, b, road, c, s->pos + off);
        if (st)
            return st;
        for (uint32_t k = off; k < off + c; k++) {
            double t = s->pos[k];
            switch (road) {
            case HPFC_WEST: s->pts[k] = to_img(s, (double)b->x0, t); break;
            case HPFC_NORTH: s->pts[k] = to_img(s, t, (double)b->y1); break;
            case HPFC_EAST: s->pts[k] = to_img(s, (double)b->x1, t); break;
            default: s->pts[k] = to_img(s, t, (double)b->y0); break;
            }
        }
    }
    return HPFC_OK;
}

static fpt toward(fpt a, fpt b, double t)
{
    return (fpt){(float)(a.x + (b.x - a.x) * t), (float)(a.y + (b.y - a.y) * t)};
}

static int add_seg(scene *s, fpt a, fpt b)
{
    return PUSH(s->segs, ((fseg){a.x, a.y, b.x, b.y}));
}

/* A stabbing: a line between its crossings, bent toward the centre by an
 * amount that grows with its length, so nested stabbings along one road
 * stay apart and none hides under the grid line. */
static int draw_stabbing(scene *s, fpt a, fpt b, fpt centre, double diag)
{
    double dx = b.x - a.x, dy = b.y - a.y;
    double len = dx * dx + dy * dy > 0 ? sqrt(dx * dx + dy * dy) : 0;
    double t = diag > 0 ? 0.6 * len / diag : 0;
    fpt mid = toward(a, b, 0.5), bend = toward(mid, centre, t > 0.5 ? 0.5 : t);
    int st = add_seg(s, a, bend);
    return st ? st : add_seg(s, bend, b);
}

/* Vertex positions: per junction component, the centroid of its crossings
 * pulled a quarter of the way to the centre (so a dead end leaves the road),
 * or the centre itself when it is the leaf's only component. */
static void vertex_points(scene *s, fpt centre)
{
    const word_info *wi = &s->wi;
    for (uint32_t c = 0; c < wi->ncomp; c++)
        s->sum[3 * c] = s->sum[3 * c + 1] = s->sum[3 * c + 2] = 0;
    for (uint32_t k = 0; k < wi->n; k++) {
        double *sum = s->sum + 3 * wi->comp[k];
        sum[0] += s->pts[k].x, sum[1] += s->pts[k].y, sum[2] += 1;
    }
    for (uint32_t c = 0; c < wi->ncomp; c++) {
        double *sum = s->sum + 3 * c;
        fpt g = {(float)(sum[0] / sum[2]), (float)(sum[1] / sum[2])};
        g = wi->ncomp == 1 ? centre : toward(g, centre, 0.25);
        sum[0] = g.x, sum[1] = g.y;
    }
}

static int draw_components(scene *s, fpt centre, double diag)
{
    const word_info *wi = &s->wi;
    vertex_points(s, centre);
    for (uint32_t c = 0; c < wi->ncomp; c++) {
        int st = HPFC_OK;
        if (wi->comp_vertex[c] == WORD_NONE)
            st = draw_stabbing(s, s->pts[wi->comp_first[c]], s->pts[wi->comp_last[c]], centre, diag);
        else
            st = PUSH(s->dots, ((fpt){(float)s->sum[3 * c], (float)s->sum[3 * c + 1]}));
        if (st)
            return st;
    }
    for (uint32_t k = 0; k < wi->n; k++) {
        uint32_t c = wi->comp[k];
        if (wi->comp_vertex[c] == WORD_NONE)
            continue;
        fpt v = {(float)s->sum[3 * c], (float)s->sum[3 * c + 1]};
        int st = add_seg(s, v, s->pts[k]);
        if (st)
            return st;
    }
    return HPFC_OK;
}

static int add_label(scene *s, const frect *r, size_t len)
{
    if (len >= sizeof s->labels.v->text || r->w < 6.5f * (float)len + 8 || r->h < 18)
        return HPFC_OK;
    flabel l = {.x = r->x + 3, .y = r->y + 12};
    memcpy(l.text, s->r.buf, len);
    l.text[len] = '\0';
    return PUSH(s->labels, l);
}

static int add_leaf(scene *s, const hpfc_pixel *px, const lbox *b, int shaded)
{
    frect r = box_rect(s, b, px->depth);
    size_t len;
    s->leaves++;
    r.outline = r.w >= 4 && r.h >= 4;
    int st = shaded ? HPFC_OK : PUSH(s->rects, r);
    if (!st)
        st = roads_word(&s->r, px, &len);
    if (!st && !shaded)
        st = add_label(s, &r, len);
    if (!st && word_parse(&s->wi, s->r.buf, len))
        st = HPFC_E_CORRUPT;
    if (st || s->wi.n == 0)
        return st;
    if (r.w < 1 && r.h < 1) {
        /* below an image pixel: one dot of ink says "an edge passes here" */
        frect dot = {r.x + r.w / 2 - 0.5f, r.y + r.h / 2 - 0.5f, 1, 1, 0, 0};
        return PUSH(s->ink, dot);
    }
    if ((st = reserve_leaf(s, s->wi.n)) || (st = crossing_points(s, b)))
        return st;
    fpt centre = {r.x + r.w / 2, r.y + r.h / 2};
    return draw_components(s, centre, sqrt((double)r.w * r.w + (double)r.h * r.h));
}

/* ---- the tree, pruned to the window ------------------------------------------ */

static int meets_window(const scene *s, const lbox *b)
{
    return (double)b->x1 > s->wx0 && (double)b->x0 < s->wx1 && (double)b->y1 > s->wy0 &&
           (double)b->y0 < s->wy1;
}

/* Index range [*lo, *hi] of the cells of size `cell` from `origin` that the
 * window's [w0, w1) meets, clamped to [0, count). */
static void cell_range(double origin, double cell, double w0, double w1, uint32_t count,
                       uint32_t *lo, uint32_t *hi)
{
    double a = (w0 - origin) / cell, z = (w1 - origin) / cell;
    *lo = a <= 0 ? 0 : a >= count ? count - 1 : (uint32_t)a;
    *hi = z <= 0 ? 0 : z >= count ? count - 1 : (uint32_t)z;
}

static int visit_pixel(scene *s, const hpfc_pixel *px, int shaded);

/* The pixels of the image under `parent` (NULL: the root image) that meet
 * the window. */
static int visit_image(scene *s, const hpfc_pixel *parent, const lbox *pb, uint32_t level,
                       int shaded)
{
    uint32_t cols = level ? s->info.cols : s->info.root_cols;
    uint32_t rows = level ? s->info.rows : s->info.root_rows;
    double cw = (double)s->levels[level].cell_w, ch = (double)s->levels[level].cell_h;
    uint32_t i0, i1, g0, g1;
    cell_range((double)pb->x0, cw, s->wx0, s->wx1, cols, &i0, &i1);
    cell_range((double)pb->y0, ch, s->wy0, s->wy1, rows, &g0, &g1);
    for (uint32_t g = g1 + 1; g-- > g0;) {
        for (uint32_t i = i0; i <= i1; i++) {
            hpfc_pixel px;
            uint32_t j = rows - 1 - g;
            int st = parent ? hpfc_pixel_child(s->f, parent, i, j, &px)
                            : hpfc_pixel_root(s->f, i, j, &px);
            if (!st)
                st = visit_pixel(s, &px, shaded);
            if (st)
                return st;
        }
    }
    return HPFC_OK;
}

static int visit_pixel(scene *s, const hpfc_pixel *px, int shaded)
{
    lbox b;
    int type;
    /* A corrupt file can point several refined pixels at one image; no
     * valid tree has more pixels than its level table counts. */
    if (++s->visits > s->max_visits)
        return HPFC_E_CORRUPT;
    int st = roads_box(s->f, px, &b);
    if (!st)
        st = hpfc_pixel_type(s->f, px, &type);
    if (st || !meets_window(s, &b))
        return st;
    if (type == HPFC_PIXEL_WORD)
        return add_leaf(s, px, &b, shaded);
    uint32_t next = px->depth + 1;
    if (next >= s->info.levels)
        return HPFC_E_CORRUPT;
    /* children below an image pixel: shade this pixel as a whole instead */
    if (!shaded && (double)s->levels[next].cell_w * s->scale < 1.0 &&
        (double)s->levels[next].cell_h * s->scale < 1.0) {
        frect r = box_rect(s, &b, s->info.levels - 1);
        r.outline = r.w >= 4 && r.h >= 4;
        if ((st = PUSH(s->rects, r)))
            return st;
        shaded = 1;
    }
    return visit_image(s, px, &b, next, shaded);
}

/* ---- window and size ----------------------------------------------------------- */

static double pow10i(int32_t e)
{
    double v = 1;
    for (int32_t k = 0; k < (e < 0 ? -e : e); k++)
        v *= 10;
    return e < 0 ? 1 / v : v;
}

static int setup_view(scene *s, const render_params *p, render_report *rep, char *why)
{
    const hpfc_file_info *in = &s->info;
    double unit = pow10i(in->unit_exp10);
    if (p->have_window) {
        s->wx0 = p->window[0] / unit, s->wy0 = p->window[1] / unit;
        s->wx1 = p->window[2] / unit, s->wy1 = p->window[3] / unit;
    } else {
        s->wx0 = (double)in->x0, s->wy0 = (double)in->y0;
        s->wx1 = (double)in->x0 + (double)in->width, s->wy1 = (double)in->y0 + (double)in->height;
    }
    double ww = s->wx1 - s->wx0, wh = s->wy1 - s->wy0;
    if (!(ww > 0) || !(wh > 0)) {
        snprintf(why, VIEW_WHY, "the window is empty");
        return 1;
    }
    double w = p->width, h = p->height;
    if (!w && !h) {
        w = ww >= wh ? RENDER_DEFAULT_SIZE : RENDER_DEFAULT_SIZE * ww / wh;
        h = wh >= ww ? RENDER_DEFAULT_SIZE : RENDER_DEFAULT_SIZE * wh / ww;
    } else if (!h) {
        h = w * wh / ww;
    }
    w = w < 1 ? 1 : w > RENDER_MAX_SIZE ? RENDER_MAX_SIZE : w;
    h = h < 1 ? 1 : h > RENDER_MAX_SIZE ? RENDER_MAX_SIZE : h;
    s->width = (uint32_t)(w + 0.5), s->height = (uint32_t)(h + 0.5);
    s->scale = s->width / ww < s->height / wh ? s->width / ww : s->height / wh;
    s->offx = (s->width - ww * s->scale) / 2, s->offy = (s->height - wh * s->scale) / 2;
    rep->width = s->width, rep->height = s->height;
    rep->window[0] = s->wx0 * unit, rep->window[1] = s->wy0 * unit;
    rep->window[2] = s->wx1 * unit, rep->window[3] = s->wy1 * unit;
    return 0;
}

static int build_scene(scene *s, const hpfc_file *f)
{
    s->f = f;
    for (uint32_t l = 0; l < s->info.levels; l++) {
        if (hpfc_file_get_level(f, l, &s->levels[l]))
            return HPFC_E_ARG;
        s->max_visits += s->levels[l].word_pixels + s->levels[l].refined_pixels;
    }
    lbox domain = {s->info.x0, s->info.y0, s->info.x0 + s->info.width,
                   s->info.y0 + s->info.height};
    if (!meets_window(s, &domain))
        return HPFC_OK;
    return visit_image(s, NULL, &domain, 0, 0);
}

/* ---- styles -------------------------------------------------------------------- */

/* Leaf fill: from near white at the root to a grey blue at the last level. */
static void depth_rgb(uint32_t depth, uint32_t levels, double rgb[3])
{
    double t = levels > 1 ? (double)depth / (levels - 1) : 0;
    rgb[0] = 0.98 - 0.36 * t;
    rgb[1] = 0.98 - 0.28 * t;
    rgb[2] = 0.98 - 0.14 * t;
}

/* Thinner strokes and smaller dots as the drawing gets denser (per image
 * pixel), so that 10^5 edges in one view stay a map rather than a smear. */
static double density(const scene *s, size_t n)
{
    return (double)n / ((double)s->width * s->height);
}

static double edge_width(const scene *s)
{
    double d = density(s, s->segs.n);
    return d < 0.01 ? 1.2 : d < 0.05 ? 0.8 : d < 0.15 ? 0.5 : 0.35;
}

static double dot_radius(const scene *s)
{
    double d = density(s, s->dots.n);
    return d < 0.002 ? 2.2 : d < 0.008 ? 1.5 : d < 0.02 ? 0.9 : 0.6;
}

/* ---- SVG ------------------------------------------------------------------------ */

static void svg_rect_path(FILE *out, const frect *r)
{
    fprintf(out, "M%.2f %.2fh%.2fv%.2fh%.2fz", r->x, r->y, r->w, r->h, -r->w);
}

static void svg_fills(FILE *out, const scene *s)
{
    for (uint32_t d = 0; d < s->info.levels; d++) {
        double rgb[3];
        size_t n = 0;
        depth_rgb(d, s->info.levels, rgb);
        for (size_t k = 0; k < s->rects.n; k++) {
            if (s->rects.v[k].depth != d)
                continue;
            if (n++ == 0)
                fprintf(out, "<path class=\"depth%u\" fill=\"#%02x%02x%02x\" d=\"", d,
                        (unsigned)(rgb[0] * 255), (unsigned)(rgb[1] * 255), (unsigned)(rgb[2] * 255));
            svg_rect_path(out, &s->rects.v[k]);
            if (n % 8 == 0)
                fputc('\n', out);
        }
        if (n)
            fprintf(out, "\"/>\n");
    }
}

static void svg_grid(FILE *out, const scene *s)
{
    fprintf(out, "<path id=\"grid\" fill=\"none\" stroke=\"#7f8c99\" stroke-width=\"0.5\" d=\"");
    size_t n = 0;
    for (size_t k = 0; k < s->rects.n; k++)
        if (s->rects.v[k].outline) {
            svg_rect_path(out, &s->rects.v[k]);
            if (++n % 8 == 0)
                fputc('\n', out);
        }
    fprintf(out, "\"/>\n<path id=\"ink\" fill=\"#b03020\" d=\"");
    for (size_t k = 0; k < s->ink.n; k++) {
        svg_rect_path(out, &s->ink.v[k]);
        if ((k + 1) % 8 == 0)
            fputc('\n', out);
    }
    fprintf(out, "\"/>\n");
}

static void svg_graph(FILE *out, const scene *s)
{
    fprintf(out, "<path id=\"edges\" fill=\"none\" stroke=\"#b03020\" stroke-width=\"%.2f\" "
                 "stroke-linecap=\"round\" stroke-linejoin=\"round\" d=\"",
            edge_width(s));
    for (size_t k = 0; k < s->segs.n; k++) {
        const fseg *g = &s->segs.v[k];
        fprintf(out, "M%.2f %.2fL%.2f %.2f", g->x0, g->y0, g->x1, g->y1);
        if ((k + 1) % 6 == 0)
            fputc('\n', out);
    }
    fprintf(out, "\"/>\n<path id=\"vertices\" fill=\"none\" stroke=\"#101010\" "
                 "stroke-width=\"%.2f\" stroke-linecap=\"round\" d=\"",
            2 * dot_radius(s));
    for (size_t k = 0; k < s->dots.n; k++) {
        fprintf(out, "M%.2f %.2fh0", s->dots.v[k].x, s->dots.v[k].y);
        if ((k + 1) % 10 == 0)
            fputc('\n', out);
    }
    fprintf(out, "\"/>\n");
}

/* Words use "+=[]()Y" only; anything else is escaped anyway. */
static void svg_text(FILE *out, const char *t)
{
    for (; *t; t++) {
        if (*t == '<')
            fputs("&lt;", out);
        else if (*t == '&')
            fputs("&amp;", out);
        else if (*t == '>')
            fputs("&gt;", out);
        else
            fputc(*t, out);
    }
}

static void write_svg(const scene *s, FILE *out)
{
    fprintf(out, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
                 "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%u\" height=\"%u\" "
                 "viewBox=\"0 0 %u %u\">\n"
                 "<rect width=\"100%%\" height=\"100%%\" fill=\"#ffffff\"/>\n",
            s->width, s->height, s->width, s->height);
    svg_fills(out, s);
    svg_grid(out, s);
    svg_graph(out, s);
    fprintf(out, "<g id=\"words\" font-family=\"monospace\" font-size=\"10\" fill=\"#303030\">\n");
    for (size_t k = 0; k < s->labels.n; k++) {
        fprintf(out, "<text x=\"%.2f\" y=\"%.2f\">", s->labels.v[k].x, s->labels.v[k].y);
        svg_text(out, s->labels.v[k].text);
        fprintf(out, "</text>\n");
    }
    fprintf(out, "</g>\n</svg>\n");
}

/* ---- PNG through cairo ------------------------------------------------------------ */

#ifdef HPFC_HAVE_CAIRO
static void cairo_rects(cairo_t *cr, const frect *v, size_t n, int depth, int outline)
{
    size_t pending = 0;
    for (size_t k = 0; k < n; k++) {
        if ((depth >= 0 && v[k].depth != depth) || (outline && !v[k].outline))
            continue;
        cairo_rectangle(cr, v[k].x, v[k].y, v[k].w, v[k].h);
        if (++pending == 4096) {
            outline ? cairo_stroke(cr) : cairo_fill(cr);
            pending = 0;
        }
    }
    outline ? cairo_stroke(cr) : cairo_fill(cr);
}

static void cairo_scene(cairo_t *cr, const scene *s)
{
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
    for (uint32_t d = 0; d < s->info.levels; d++) {
        double rgb[3];
        depth_rgb(d, s->info.levels, rgb);
        cairo_set_source_rgb(cr, rgb[0], rgb[1], rgb[2]);
        cairo_rects(cr, s->rects.v, s->rects.n, (int)d, 0);
    }
    cairo_set_source_rgb(cr, 0.50, 0.55, 0.60);
    cairo_set_line_width(cr, 0.5);
    cairo_rects(cr, s->rects.v, s->rects.n, -1, 1);
    cairo_set_source_rgb(cr, 0.69, 0.19, 0.13);
    cairo_rects(cr, s->ink.v, s->ink.n, -1, 0);
    cairo_set_line_width(cr, edge_width(s));
    cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
    for (size_t k = 0; k < s->segs.n; k++) {
        const fseg *g = &s->segs.v[k];
        cairo_move_to(cr, g->x0, g->y0);
        cairo_line_to(cr, g->x1, g->y1);
        if ((k + 1) % 4096 == 0)
            cairo_stroke(cr);
    }
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0.06, 0.06, 0.06);
    for (size_t k = 0; k < s->dots.n; k++) {
        cairo_new_sub_path(cr);
        cairo_arc(cr, s->dots.v[k].x, s->dots.v[k].y, dot_radius(s), 0, 6.283185307179586);
        if ((k + 1) % 4096 == 0)
            cairo_fill(cr);
    }
    cairo_fill(cr);
    cairo_set_source_rgb(cr, 0.19, 0.19, 0.19);
    cairo_select_font_face(cr, "monospace", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, 10);
    for (size_t k = 0; k < s->labels.n; k++) {
        cairo_move_to(cr, s->labels.v[k].x, s->labels.v[k].y);
        cairo_show_text(cr, s->labels.v[k].text);
    }
}

#if defined(__SANITIZE_ADDRESS__)
/* fontconfig (under cairo's text) keeps its configuration for the life of
 * the process and has no teardown cairo calls; the ASan test builds must not
 * count that as a leak of ours. LeakSanitizer reads this hook at exit. */
const char *__lsan_default_suppressions(void);
const char *__lsan_default_suppressions(void)
{
    return "leak:libfontconfig.so\n";
}

const char *__lsan_default_options(void);
const char *__lsan_default_options(void)
{
    return "print_suppressions=0";
}
#endif

static cairo_status_t png_bytes(void *closure, const unsigned char *data, unsigned int length)
{
    return fwrite(data, 1, length, closure) == length ? CAIRO_STATUS_SUCCESS
                                                      : CAIRO_STATUS_WRITE_ERROR;
}

/* 0, or 1 with the reason when cairo fails (not for a failed write: the
 * caller checks the stream). */
static int write_png(const scene *s, FILE *out, const char *path, char *why)
{
    cairo_surface_t *surface =
        cairo_image_surface_create(CAIRO_FORMAT_RGB24, (int)s->width, (int)s->height);
    cairo_t *cr = cairo_create(surface);
    cairo_scene(cr, s);
    cairo_status_t cs = cairo_status(cr);
    cairo_destroy(cr);
    if (cs == CAIRO_STATUS_SUCCESS)
        cs = cairo_surface_write_to_png_stream(surface, png_bytes, out);
    cairo_surface_destroy(surface);
    cairo_debug_reset_static_data(); /* cairo's caches, for leak checkers */
    if (cs != CAIRO_STATUS_SUCCESS && cs != CAIRO_STATUS_WRITE_ERROR) {
        snprintf(why, VIEW_WHY, "%s: cannot draw the PNG: %s", path, cairo_status_to_string(cs));
        return 1;
    }
    return 0;
}
#endif

int render_png_available(void)
{
#ifdef HPFC_HAVE_CAIRO
    return 1;
#else
    return 0;
#endif
}

int render_format_of(const char *path)
{
    size_t n = strlen(path);
    if (n >= 4 && strcasecmp(path + n - 4, ".svg") == 0)
        return RENDER_SVG;
    if (n >= 4 && strcasecmp(path + n - 4, ".png") == 0)
        return RENDER_PNG;
    return 0;
}

/* Writes the picture to "OUT.<pid>.tmp" next to OUT, then renames it over
 * OUT: a failed run leaves no partial OUT and an existing OUT untouched, as
 * for every output file of the tools. */
static int write_output(const scene *s, const render_params *p, char *why)
{
    size_t cap = strlen(p->output) + 32;
    char *tmp = malloc(cap);
    if (!tmp) {
        snprintf(why, VIEW_WHY, "%s: %s", p->output, strerror(ENOMEM));
        return 1;
    }
    snprintf(tmp, cap, "%s.%ld.tmp", p->output, (long)getpid());
    FILE *out = fopen(tmp, "wbx");
    int bad = !out, drawn = 0, err = out ? 0 : errno;
    if (out && p->format == RENDER_SVG)
        write_svg(s, out);
#ifdef HPFC_HAVE_CAIRO
    else if (out && (bad = write_png(s, out, p->output, why)))
        drawn = 1; /* why[] says what cairo refused */
#endif
    if (out) {
        errno = 0;
        bad |= ferror(out) != 0;
        bad |= fclose(out) != 0;
        err = errno;
        if (!bad && rename(tmp, p->output) != 0)
            bad = 1, err = errno;
    }
    if (bad && !drawn)
        snprintf(why, VIEW_WHY, "%s: cannot write: %s", p->output,
                 err ? strerror(err) : "I/O error");
    if (bad && out)
        unlink(tmp);
    free(tmp);
    return bad;
}

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

int render_file(const hpfc_file *f, const render_params *p, render_report *rep, char *why)
{
    double t0 = now();
    scene s;
    memset(&s, 0, sizeof s);
    memset(rep, 0, sizeof *rep);
    hpfc_file_get_info(f, &s.info);
    if (p->format == RENDER_PNG && !render_png_available()) {
        snprintf(why, VIEW_WHY, "%s: this build has no PNG output (cairo was not found); "
                                "render to .svg instead", p->output);
        return 1;
    }
    int bad = setup_view(&s, p, rep, why);
    int st = bad ? HPFC_OK : roads_init(&s.r, f);
    if (!bad && !st)
        st = build_scene(&s, f);
    if (!bad && st) {
        snprintf(why, VIEW_WHY, "render: %s", hpfc_strerror(st));
        bad = 1;
    }
    if (!bad)
        bad = write_output(&s, p, why);
    rep->leaves = s.leaves;
    rep->segments = s.segs.n;
    rep->vertices = s.dots.n;
    rep->labels = s.labels.n;
    rep->ink = s.ink.n;
    for (size_t k = 0; k < s.rects.n; k++)
        rep->outlined += s.rects.v[k].outline;
    rep->seconds = now() - t0;
    scene_free(&s);
    return bad;
}

/* ---- arguments and report ---------------------------------------------------------- */

static int parse_dimension(const char **p, uint32_t *out)
{
    uint64_t v = 0;
    const char *s = *p;
    if (*s < '0' || *s > '9')
        return -1;
    for (; *s >= '0' && *s <= '9'; s++)
        if ((v = v * 10 + (uint64_t)(*s - '0')) > RENDER_MAX_SIZE)
            return -1;
    if (v == 0)
        return -1;
    *out = (uint32_t)v;
    *p = s;
    return 0;
}

int render_size_parse(const char *text, uint32_t *w, uint32_t *h)
{
    const char *p = text;
    *h = 0;
    if (parse_dimension(&p, w))
        return -1;
    if (*p == 'x' && (p++, parse_dimension(&p, h)))
        return -1;
    return *p == '\0' ? 0 : -1;
}

int render_window_parse(const char *text, double window[4])
{
    decimal d[4];
    if (decimal_list_parse(text, d, 4))
        return -1;
    for (int k = 0; k < 4; k++)
        window[k] = d[k].value;
    return window[0] < window[2] && window[1] < window[3] ? 0 : -1;
}

void render_print_report(FILE *out, int json, const render_params *p, const render_report *r)
{
    const char *format = p->format == RENDER_PNG ? "png" : "svg";
    if (!json) {
        fprintf(out, "%s: %s %ux%u, window [%g, %g] x [%g, %g]: %llu leaves, %llu segments, "
                     "%llu vertices (%.3f s)\n",
                p->output, format, r->width, r->height, r->window[0], r->window[2], r->window[1],
                r->window[3], (unsigned long long)r->leaves, (unsigned long long)r->segments,
                (unsigned long long)r->vertices, r->seconds);
        return;
    }
    jsonw w;
    jsonw_init(&w, out);
    jsonw_object_begin(&w, NULL);
    jsonw_string(&w, "output", p->output);
    jsonw_string(&w, "format", format);
    jsonw_u64(&w, "width", r->width);
    jsonw_u64(&w, "height", r->height);
    jsonw_array_begin(&w, "window");
    for (int k = 0; k < 4; k++)
        jsonw_double(&w, NULL, r->window[k], 6);
    jsonw_array_end(&w);
    jsonw_u64(&w, "leaves", r->leaves);
    jsonw_u64(&w, "outlined", r->outlined);
    jsonw_u64(&w, "segments", r->segments);
    jsonw_u64(&w, "vertices", r->vertices);
    jsonw_u64(&w, "ink", r->ink);
    jsonw_u64(&w, "labels", r->labels);
    jsonw_double(&w, "seconds", r->seconds, 6);
    jsonw_object_end(&w);
    jsonw_finish(&w);
}
