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

#include "clock.h"
#include "escape.h"
#include "grow.h"
#include "jsonw.h"
#include "roads.h"
#include "word.h"
#include "projection.h"
#include "views.h"

/* ---- the scene: what to draw, in image coordinates (y down) ---------------- */

#define RGB_WHITE 0xffffffu

typedef struct frect {
    float x, y, w, h;
    uint8_t depth, outline;
    uint32_t rgb;            /* fill: the colour of the face(s) under it */
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
    hpfc_faces *faces;       /* for the fills: every face's colour */
    int features;            /* the file has a FEAT section: colour by feature */
    int exact;               /* the file has GEOM and LABL: exact point location */
    uint64_t *cand;          /* candidate faces of one stabbed leaf */
    size_t cand_cap;
} scene;

#define PUSH(vec, item)                                                                  \
    (!array_grow((void **)&(vec).v, &(vec).cap, (vec).n + 1, sizeof *(vec).v)         \
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
    free(s->cand);
    hpfc_faces_free(s->faces);
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
    return (frect){(float)x0, (float)y0, (float)(x1 - x0), (float)(y1 - y0), (uint8_t)depth, 0,
                   RGB_WHITE};
}

/* ---- colours ------------------------------------------------------------------ */

/* ColorBrewer's Set3: light, categorical, so that borders stay visible. */
static const uint32_t palette[12] = {0x8dd3c7, 0xffffb3, 0xbebada, 0xfb8072,
                                     0x80b1d3, 0xfdb462, 0xb3de69, 0xfccde5,
                                     0xd9d9d9, 0xbc80bd, 0xccebc5, 0xffed6f};

/* A palette entry for an id, scattered so that consecutive ids (the
 * neighbouring counties of one state) seldom share a colour. */
static uint32_t id_rgb(uint64_t id)
{
    return palette[(uint32_t)((id * 0x9E3779B97F4A7C15u) >> 32) % 12u];
}

/* A face's colour: its first feature's (white for a face of no feature,
 * the outside), or without a FEAT section its own id's (white for the
 * unbounded face 0). */
static uint32_t face_rgb(const scene *s, uint64_t face)
{
    uint32_t count = 0;
    hpfc_id feature = 0;
    if (!s->features)
        return face == 0 ? RGB_WHITE : id_rgb(face);
    if (hpfc_face_feature_count(s->f, face, &count) != HPFC_OK || count == 0 ||
        hpfc_face_feature_id(s->f, face, 0, &feature) != HPFC_OK)
        return RGB_WHITE;
    return id_rgb(feature);
}

/* A leaf's fill: its face's colour when private; in a stabbed leaf, which
 * the drawn edges cut, the mean of the faces that meet it (one colour when
 * they agree): the word alone does not say which part lies where (a leaf
 * large on screen is refilled by stabbed_leaf_rgb). */
static int leaf_rgb(scene *s, const hpfc_pixel *leaf, uint32_t *rgb)
{
    int is_private;
    uint64_t face;
    size_t len, n = 0;
    int st = hpfc_pixel_is_private(s->f, leaf, &is_private);
    if (!st && is_private) {
        st = hpfc_faces_pixel_face(s->faces, leaf, &face);
        *rgb = st ? RGB_WHITE : face_rgb(s, face);
        return st;
    }
    if (!st)
        st = hpfc_pixel_word(s->f, leaf, NULL, 0, &len);
    if (!st && !array_grow((void **)&s->cand, &s->cand_cap, len + 1, sizeof *s->cand))
        st = HPFC_E_NOMEM;
    if (!st)
        st = view_pixel_faces(s->f, s->faces, leaf, s->cand, s->cand_cap, &n);
    if (st || n == 0) {
        *rgb = RGB_WHITE;
        return st;
    }
    uint32_t first = face_rgb(s, s->cand[0]), sum[3] = {0, 0, 0};
    int same = 1;
    for (size_t k = 0; k < n; k++) {
        uint32_t c = face_rgb(s, s->cand[k]);
        same &= c == first;
        sum[0] += c >> 16, sum[1] += c >> 8 & 0xff, sum[2] += c & 0xff;
    }
    *rgb = same ? first
                : (uint32_t)(sum[0] / n) << 16 | (uint32_t)(sum[1] / n) << 8 | (uint32_t)(sum[2] / n);
    return HPFC_OK;
}

/* The fill of a refined pixel drawn as a whole: the leaf at its centre's. */
static int centre_rgb(scene *s, const lbox *b, uint32_t *rgb)
{
    hpfc_pixel leaf;
    int64_t cx = b->x0 + (b->x1 - b->x0) / 2, cy = b->y0 + (b->y1 - b->y0) / 2;
    int st = hpfc_locate(s->f, cx, cy, &leaf);
    if (st == HPFC_E_NO_PIXEL) {
        *rgb = RGB_WHITE;
        return HPFC_OK;
    }
    return st ? st : leaf_rgb(s, &leaf, rgb);
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
    if (len == 4 && memcmp(s->r.buf, "++++", 4) == 0)
        return HPFC_OK; /* an empty leaf: its fill says enough, and a map stays readable */
    flabel l = {.x = r->x + 3, .y = r->y + 12};
    memcpy(l.text, s->r.buf, len);
    l.text[len] = '\0';
    return PUSH(s->labels, l);
}

/* Where crossing point q lies along the boundary of r, clockwise from its
 * south-west corner (up the west side first), in image pixels. */
static double perimeter_at(const frect *r, fpt q)
{
    double w = r->w, h = r->h, x = q.x - r->x, y = q.y - r->y;
    double dw = fabs(x), de = fabs(x - w), dn = fabs(y), ds = fabs(y - h);
    double m = fmin(fmin(dw, de), fmin(dn, ds));
    if (m == dw)
        return h - y;
    if (m == dn)
        return h + x;
    if (m == de)
        return h + w + y;
    return 2 * h + w + (w - x);
}

/* A stabbed leaf large on screen: the colour of the face that holds the
 * most of its boundary (the stretch after crossing k, clockwise, lies in
 * the face on the right of the dart leaving at k), so that a county cut
 * by a corner of its neighbour keeps the county's colour. The crossing
 * points are s->pts. */
static int majority_rgb(scene *s, const hpfc_pixel *px, const frect *r, uint32_t *rgb)
{
    uint32_t n = s->wi.n;
    double perimeter = 2.0 * (r->w + r->h), best = -1;
    for (uint32_t k = 0; k < n; k++)
        s->pos[k] = perimeter_at(r, s->pts[k]);
    for (uint32_t k = 0; k < n; k++) {
        hpfc_dart d = {.pixel = *px, .crossing = k};
        uint64_t face;
        int st = hpfc_faces_dart_face(s->faces, &d, &face);
        if (st)
            return st;
        double len = s->pos[(k + 1) % n] - s->pos[k];
        if (len <= 0)
            len += perimeter;
        s->sum[3 * k] = len, s->sum[3 * k + 1] = (double)face;
    }
    for (uint32_t k = 0; k < n; k++) { /* the face's whole share */
        double total = 0;
        for (uint32_t j = 0; j < n; j++)
            total += s->sum[3 * j + 1] == s->sum[3 * k + 1] ? s->sum[3 * j] : 0;
        if (total > best)
            best = total, *rgb = face_rgb(s, (uint64_t)s->sum[3 * k + 1]);
    }
    return HPFC_OK;
}

/* A stabbed leaf large on screen: with exact geometry, the colour of the
 * face that holds the leaf's centre (a leaf may be mostly one face whose
 * border holds little of its boundary); else, or when the centre lies on an
 * edge, the majority of its boundary. */
static int stabbed_leaf_rgb(scene *s, const hpfc_pixel *px, const lbox *b, const frect *r,
                            uint32_t *rgb)
{
    if (s->exact) {
        hpfc_point_location at;
        uint64_t face;
        size_t n = 0;
        int64_t cx = b->x0 + (b->x1 - b->x0) / 2, cy = b->y0 + (b->y1 - b->y0) / 2;
        int st = hpfc_locate_point(s->f, cx, cy, &at, &face, 1, &n);
        if (st == HPFC_OK && !at.on_boundary && n == 1) {
            *rgb = face_rgb(s, face);
            return HPFC_OK;
        }
        if (st != HPFC_OK && st != HPFC_E_BUFFER_SMALL)
            return st;
    }
    return majority_rgb(s, px, r, rgb);
}

static int add_leaf(scene *s, const hpfc_pixel *px, const lbox *b, int shaded)
{
    frect r = box_rect(s, b, px->depth);
    size_t len;
    s->leaves++;
    r.outline = r.w >= 4 && r.h >= 4;
    int st = shaded ? HPFC_OK : leaf_rgb(s, px, &r.rgb);
    if (!st && !shaded)
        st = PUSH(s->rects, r);
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
        frect dot = {r.x + r.w / 2 - 0.5f, r.y + r.h / 2 - 0.5f, 1, 1, 0, 0, 0};
        return PUSH(s->ink, dot);
    }
    if ((st = reserve_leaf(s, s->wi.n)) || (st = crossing_points(s, b)))
        return st;
    if (!shaded && (st = stabbed_leaf_rgb(s, px, b, &r, &s->rects.v[s->rects.n - 1].rgb)))
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
        if ((st = centre_rgb(s, &b, &r.rgb)) || (st = PUSH(s->rects, r)))
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

/* The data's extent in lattice units: the union of the leaves that some
 * edge meets (the stabbed ones: with polyline edges a vertex's leaves may
 * hold a small part of the map), grown by 2 % a side and kept in the
 * domain; the domain itself for a map without edges. One pass over the
 * leaves, stopped on a corrupt file as build_scene is. */
static int data_extent(scene *s, double ext[4])
{
    const hpfc_file_info *in = &s->info;
    double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
    uint64_t seen = 0, words = 0;
    for (uint32_t l = 0; l < in->levels; l++)
        words += s->levels[l].word_pixels;
    hpfc_pixel px;
    int st = hpfc_leaf_first(s->f, &px);
    for (; st == HPFC_OK; st = hpfc_leaf_next(s->f, &px)) {
        size_t len;
        lbox b;
        if (++seen > words)
            return HPFC_E_CORRUPT;
        if ((st = roads_word(&s->r, &px, &len)) != HPFC_OK)
            return st;
        if (word_parse(&s->wi, s->r.buf, len))
            return HPFC_E_CORRUPT;
        if (s->wi.n == 0)
            continue;
        if ((st = roads_box(s->f, &px, &b)) != HPFC_OK)
            return st;
        x0 = fmin(x0, (double)b.x0), y0 = fmin(y0, (double)b.y0);
        x1 = fmax(x1, (double)b.x1), y1 = fmax(y1, (double)b.y1);
    }
    if (st != HPFC_E_NO_PIXEL)
        return st;
    double dx0 = (double)in->x0, dy0 = (double)in->y0;
    double dx1 = dx0 + (double)in->width, dy1 = dy0 + (double)in->height;
    if (!(x0 < x1 && y0 < y1))
        x0 = dx0, y0 = dy0, x1 = dx1, y1 = dy1;
    double mx = 0.02 * (x1 - x0), my = 0.02 * (y1 - y0);
    ext[0] = fmax(dx0, x0 - mx), ext[1] = fmax(dy0, y0 - my);
    ext[2] = fmin(dx1, x1 + mx), ext[3] = fmin(dy1, y1 + my);
    return HPFC_OK;
}

/* --window-lonlat: the user-coordinate box around the projected outline
 * of the lon/lat box (64 points a side: a conic bends its parallels). */
static int lonlat_window(const scene *s, const double ll[4], double out[4], char *why)
{
    char reason[200];
    if (!s->info.crs) {
        snprintf(why, VIEW_WHY, "--window-lonlat: the file records no CRS (use --window X0,Y0,X1,Y1)");
        return 1;
    }
    if (ll[0] < -180 || ll[2] > 180 || ll[1] < -90 || ll[3] > 90) {
        snprintf(why, VIEW_WHY, "--window-lonlat: not longitudes and latitudes in degrees");
        return 1;
    }
    mapproj_plan *plan = mapproj_from_text(s->info.crs, s->info.crs_len, reason, sizeof reason);
    if (!plan) {
        snprintf(why, VIEW_WHY, "--window-lonlat: %s", reason);
        return 1;
    }
    out[0] = out[1] = INFINITY, out[2] = out[3] = -INFINITY;
    int bad = 0;
    for (int side = 0; side < 4; side++)
        for (int k = 0; k <= 64; k++) {
            double t = k / 64.0, lon, lat, x, y;
            lon = side == 0 ? ll[0] : side == 1 ? ll[2] : ll[0] + t * (ll[2] - ll[0]);
            lat = side == 2 ? ll[1] : side == 3 ? ll[3] : ll[1] + t * (ll[3] - ll[1]);
            if (mapproj_forward(plan, lon, lat, &x, &y) != 0) {
                bad = 1;
                continue;
            }
            out[0] = fmin(out[0], x), out[1] = fmin(out[1], y);
            out[2] = fmax(out[2], x), out[3] = fmax(out[3], y);
        }
    mapproj_free(plan);
    if (bad || !(out[0] < out[2] && out[1] < out[3])) {
        snprintf(why, VIEW_WHY, "--window-lonlat: the box cannot be projected with the file's CRS");
        return 1;
    }
    return 0;
}

static int setup_view(scene *s, const render_params *p, render_report *rep, char *why)
{
    double unit = pow10i(s->info.unit_exp10), user[4], ext[4];
    if (p->have_window_lonlat) {
        if (lonlat_window(s, p->window_lonlat, user, why))
            return 1;
    } else if (p->have_window)
        memcpy(user, p->window, sizeof user);
    if (p->have_window || p->have_window_lonlat) {
        s->wx0 = user[0] / unit, s->wy0 = user[1] / unit;
        s->wx1 = user[2] / unit, s->wy1 = user[3] / unit;
    } else {
        int st = data_extent(s, ext);
        if (st) {
            snprintf(why, VIEW_WHY, "render: %s", hpfc_strerror(st));
            return 1;
        }
        s->wx0 = ext[0], s->wy0 = ext[1], s->wx1 = ext[2], s->wy1 = ext[3];
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
    /* the window grows to the image's aspect, centred: the picture shows
     * what lies there, and every image pixel has user coordinates (the
     * world file, the SVG's viewBox) */
    double gx = (s->width / s->scale - ww) / 2, gy = (s->height / s->scale - wh) / 2;
    s->wx0 -= gx, s->wy0 -= gy;
    s->wx1 = s->wx0 + s->width / s->scale, s->wy1 = s->wy0 + s->height / s->scale;
    s->offx = s->offy = 0;
    rep->width = s->width, rep->height = s->height;
    rep->window[0] = s->wx0 * unit, rep->window[1] = s->wy0 * unit;
    rep->window[2] = s->wx1 * unit, rep->window[3] = s->wy1 * unit;
    return 0;
}

/* The file's levels, its faces (hpfc_faces_build, O(file)) and whether
 * they have features, before the window is set up. */
static int open_scene(scene *s, const hpfc_file *f, char *why)
{
    s->f = f;
    hpfc_features_info fi;
    int st = HPFC_OK;
    for (uint32_t l = 0; l < s->info.levels && !st; l++) {
        st = hpfc_file_get_level(f, l, &s->levels[l]);
        s->max_visits += s->levels[l].word_pixels + s->levels[l].refined_pixels;
    }
    if (!st)
        st = roads_init(&s->r, f);
    if (!st)
        st = hpfc_faces_build(f, &s->faces);
    if (st) {
        snprintf(why, VIEW_WHY, "render: %s", hpfc_strerror(st));
        return 1;
    }
    st = hpfc_file_get_features(f, &fi);
    if (st == HPFC_OK && fi.faces != hpfc_faces_face_count(s->faces)) {
        snprintf(why, VIEW_WHY, "features: the FEAT section lists %u faces, the map has %llu",
                 fi.faces, (unsigned long long)hpfc_faces_face_count(s->faces));
        return 1;
    }
    if (st != HPFC_OK && st != HPFC_E_NO_SECTION) {
        snprintf(why, VIEW_WHY, "features: %s", hpfc_strerror(st));
        return 1;
    }
    s->features = st == HPFC_OK;
    hpfc_geometry_info gi;
    s->exact = hpfc_file_get_geometry(f, &gi) == HPFC_OK;
    return 0;
}

static int build_scene(scene *s)
{
    lbox domain = {s->info.x0, s->info.y0, s->info.x0 + s->info.width,
                   s->info.y0 + s->info.height};
    if (!meets_window(s, &domain))
        return HPFC_OK;
    return visit_image(s, NULL, &domain, 0, 0);
}

/* ---- styles -------------------------------------------------------------------- */

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

/* The SVG speaks the file's user coordinates: its viewBox is the window
 * (y negated, as SVG's y goes down) and the drawing sits in a group that
 * flips y back, so that every path point is an (x, y) of the map and the
 * picture drops onto other layers of the same CRS. Strokes keep their
 * width in screen pixels (non-scaling-stroke). */
typedef struct svg_out {
    FILE *f;
    const scene *s;
    double unit;     /* user units per lattice unit */
    int digits;      /* decimals: a hundredth of an image pixel */
} svg_out;

static double user_x(const svg_out *o, double img_x)
{
    return (o->s->wx0 + img_x / o->s->scale) * o->unit;
}

static double user_y(const svg_out *o, double img_y)
{
    return (o->s->wy0 + ((double)o->s->height - img_y) / o->s->scale) * o->unit;
}

static void svg_num(const svg_out *o, double v)
{
    fprintf(o->f, "%.*f", o->digits, v);
}

static void svg_point(const svg_out *o, char cmd, double img_x, double img_y)
{
    fputc(cmd, o->f);
    svg_num(o, user_x(o, img_x));
    fputc(' ', o->f);
    svg_num(o, user_y(o, img_y));
}

static void svg_rect_path(const svg_out *o, const frect *r)
{
    svg_point(o, 'M', r->x, r->y);
    fputc('H', o->f);
    svg_num(o, user_x(o, r->x + r->w));
    fputc('V', o->f);
    svg_num(o, user_y(o, r->y + r->h));
    fputc('H', o->f);
    svg_num(o, user_x(o, r->x));
    fputc('Z', o->f);
}

static int cmp_rect_rgb(const void *a, const void *b)
{
    uint32_t x = ((const frect *)a)->rgb, y = ((const frect *)b)->rgb;
    return (x > y) - (x < y);
}

/* One path per fill colour (the rects are sorted by colour in place). */
static void svg_fills(const svg_out *o, frect *rects, size_t n)
{
    if (n > 1) /* NULL when nothing meets the window */
        qsort(rects, n, sizeof *rects, cmp_rect_rgb);
    for (size_t k = 0; k < n; k++) {
        if (k == 0 || rects[k].rgb != rects[k - 1].rgb)
            fprintf(o->f, "%s<path class=\"fill\" fill=\"#%06x\" d=\"", k ? "\"/>\n" : "",
                    rects[k].rgb);
        svg_rect_path(o, &rects[k]);
        if (k % 8 == 7)
            fputc('\n', o->f);
    }
    if (n)
        fprintf(o->f, "\"/>\n");
}

static void svg_grid(const svg_out *o)
{
    const scene *s = o->s;
    fprintf(o->f, "<path id=\"grid\" fill=\"none\" stroke=\"#7f8c99\" stroke-opacity=\"0.5\" "
                  "stroke-width=\"0.5\" vector-effect=\"non-scaling-stroke\" d=\"");
    size_t n = 0;
    for (size_t k = 0; k < s->rects.n; k++)
        if (s->rects.v[k].outline) {
            svg_rect_path(o, &s->rects.v[k]);
            if (++n % 8 == 0)
                fputc('\n', o->f);
        }
    fprintf(o->f, "\"/>\n<path id=\"ink\" fill=\"#202020\" d=\"");
    for (size_t k = 0; k < s->ink.n; k++) {
        svg_rect_path(o, &s->ink.v[k]);
        if ((k + 1) % 8 == 0)
            fputc('\n', o->f);
    }
    fprintf(o->f, "\"/>\n");
}

static void svg_graph(const svg_out *o)
{
    const scene *s = o->s;
    fprintf(o->f, "<path id=\"edges\" fill=\"none\" stroke=\"#202020\" stroke-width=\"%.2f\" "
                  "stroke-linecap=\"round\" stroke-linejoin=\"round\" "
                  "vector-effect=\"non-scaling-stroke\" d=\"",
            edge_width(s));
    for (size_t k = 0; k < s->segs.n; k++) {
        const fseg *g = &s->segs.v[k];
        svg_point(o, 'M', g->x0, g->y0);
        svg_point(o, 'L', g->x1, g->y1);
        if ((k + 1) % 4 == 0)
            fputc('\n', o->f);
    }
    fprintf(o->f, "\"/>\n<path id=\"vertices\" fill=\"none\" stroke=\"#101010\" "
                  "stroke-width=\"%.2f\" stroke-linecap=\"round\" "
                  "vector-effect=\"non-scaling-stroke\" d=\"",
            2 * dot_radius(s));
    for (size_t k = 0; k < s->dots.n; k++) {
        svg_point(o, 'M', s->dots.v[k].x, s->dots.v[k].y);
        fputs("h0", o->f);
        if ((k + 1) % 8 == 0)
            fputc('\n', o->f);
    }
    fprintf(o->f, "\"/>\n");
}

static void write_svg(scene *s, FILE *out)
{
    double unit = pow10i(s->info.unit_exp10), px = unit / s->scale;
    svg_out o = {.f = out, .s = s, .unit = unit};
    o.digits = px > 0 ? (int)ceil(-log10(px / 100)) : 0;
    o.digits = o.digits < 0 ? 0 : o.digits > 12 ? 12 : o.digits;
    double w = s->width * px, h = s->height * px;
    double left = user_x(&o, 0), top = user_y(&o, 0);
    fprintf(out, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
                 "<!-- user coordinates of the .hpfc file: x, y = (x, -y) of this viewBox -->\n"
                 "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%u\" height=\"%u\" "
                 "viewBox=\"",
            s->width, s->height);
    svg_num(&o, left), fputc(' ', out), svg_num(&o, -top), fputc(' ', out);
    svg_num(&o, w), fputc(' ', out), svg_num(&o, h);
    fprintf(out, "\">\n<rect x=\"");
    svg_num(&o, left), fputs("\" y=\"", out), svg_num(&o, -top);
    fputs("\" width=\"100%\" height=\"100%\" fill=\"#ffffff\"/>\n"
          "<g id=\"map\" transform=\"scale(1,-1)\">\n", out);
    svg_fills(&o, s->rects.v, s->rects.n);
    svg_grid(&o);
    svg_graph(&o);
    fprintf(out, "</g>\n<g id=\"words\" font-family=\"monospace\" font-size=\"");
    svg_num(&o, 10 * px);
    fprintf(out, "\" fill=\"#303030\">\n");
    for (size_t k = 0; k < s->labels.n; k++) {
        fputs("<text x=\"", out);
        svg_num(&o, user_x(&o, s->labels.v[k].x));
        fputs("\" y=\"", out);
        svg_num(&o, -user_y(&o, s->labels.v[k].y));
        fputs("\">", out);
        xml_write_text(out, s->labels.v[k].text);
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

static void cairo_scene(cairo_t *cr, scene *s)
{
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
    /* fills, one colour at a time (sorted by colour) */
    if (s->rects.n > 1)
        qsort(s->rects.v, s->rects.n, sizeof *s->rects.v, cmp_rect_rgb);
    for (size_t k = 0, run; k < s->rects.n; k += run) {
        uint32_t c = s->rects.v[k].rgb;
        for (run = 1; k + run < s->rects.n && s->rects.v[k + run].rgb == c; run++)
            ;
        cairo_set_source_rgb(cr, (c >> 16) / 255.0, (c >> 8 & 0xff) / 255.0, (c & 0xff) / 255.0);
        cairo_rects(cr, s->rects.v + k, run, -1, 0);
    }
    cairo_set_source_rgba(cr, 0.50, 0.55, 0.60, 0.5);
    cairo_set_line_width(cr, 0.5);
    cairo_rects(cr, s->rects.v, s->rects.n, -1, 1);
    cairo_set_source_rgb(cr, 0.125, 0.125, 0.125);
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
static int write_png(scene *s, FILE *out, const char *path, char *why)
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
static int write_output(scene *s, const render_params *p, char *why)
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

/* OUT's world file (OUT.png -> OUT.pgw): the affine map from image pixels
 * to the file's user coordinates (A, D, B, E, C, F; C, F the centre of the
 * top-left pixel), so that GIS software places the picture. Written like
 * the picture, through a temporary file. */
static int write_world_file(const scene *s, const render_params *p, render_report *rep,
                            char *why)
{
    size_t n = strlen(p->output);
    snprintf(rep->world_file, sizeof rep->world_file, "%.*spgw", (int)(n - 3), p->output);
    if (n - 3 + 4 > sizeof rep->world_file - 1) {
        snprintf(why, VIEW_WHY, "%s: name too long for its world file", p->output);
        return 1;
    }
    char tmp[sizeof rep->world_file + 32];
    snprintf(tmp, sizeof tmp, "%s.%ld.tmp", rep->world_file, (long)getpid());
    double unit = pow10i(s->info.unit_exp10), px = unit / s->scale;
    FILE *out = fopen(tmp, "wx");
    int err = out ? 0 : errno;
    if (out) {
        fprintf(out, "%.17g\n0\n0\n%.17g\n%.17g\n%.17g\n", px, -px,
                s->wx0 * unit + px / 2, s->wy1 * unit - px / 2);
        err = ferror(out) ? EIO : 0;
        if (fclose(out) != 0 && !err)
            err = errno;
        if (!err && rename(tmp, rep->world_file) != 0)
            err = errno;
        if (err)
            unlink(tmp);
    }
    if (err)
        snprintf(why, VIEW_WHY, "%.180s: cannot write: %s", rep->world_file, strerror(err));
    return err != 0;
}

int render_file(const hpfc_file *f, const render_params *p, render_report *rep, char *why)
{
    double t0 = clock_seconds();
    scene s;
    memset(&s, 0, sizeof s);
    memset(rep, 0, sizeof *rep);
    hpfc_file_get_info(f, &s.info);
    if (p->format == RENDER_PNG && !render_png_available()) {
        snprintf(why, VIEW_WHY, "%s: this build has no PNG output (cairo was not found); "
                                "render to .svg instead", p->output);
        return 1;
    }
    int bad = open_scene(&s, f, why);
    if (!bad)
        bad = setup_view(&s, p, rep, why);
    int st = bad ? HPFC_OK : build_scene(&s);
    if (!bad && st) {
        snprintf(why, VIEW_WHY, "render: %s", hpfc_strerror(st));
        bad = 1;
    }
    if (!bad)
        bad = write_output(&s, p, why);
    if (!bad && p->format == RENDER_PNG)
        bad = write_world_file(&s, p, rep, why);
    rep->by_feature = s.features;
    rep->leaves = s.leaves;
    rep->segments = s.segs.n;
    rep->vertices = s.dots.n;
    rep->labels = s.labels.n;
    rep->ink = s.ink.n;
    for (size_t k = 0; k < s.rects.n; k++)
        rep->outlined += s.rects.v[k].outline;
    rep->seconds = clock_seconds() - t0;
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
        fprintf(out, "%s: %s %ux%u, window [%.10g, %.10g] x [%.10g, %.10g]: %llu leaves, "
                     "%llu segments, %llu vertices, faces coloured by %s%s%s (%.3f s)\n",
                p->output, format, r->width, r->height, r->window[0], r->window[2], r->window[1],
                r->window[3], (unsigned long long)r->leaves, (unsigned long long)r->segments,
                (unsigned long long)r->vertices, r->by_feature ? "feature" : "face",
                r->world_file[0] ? ", world file " : "", r->world_file, r->seconds);
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
        jsonw_double(&w, NULL, r->window[k], 9);
    jsonw_array_end(&w);
    jsonw_u64(&w, "leaves", r->leaves);
    jsonw_u64(&w, "outlined", r->outlined);
    jsonw_u64(&w, "segments", r->segments);
    jsonw_u64(&w, "vertices", r->vertices);
    jsonw_u64(&w, "ink", r->ink);
    jsonw_u64(&w, "labels", r->labels);
    jsonw_string(&w, "colour", r->by_feature ? "feature" : "face");
    if (r->world_file[0])
        jsonw_string(&w, "world_file", r->world_file);
    else
        jsonw_null(&w, "world_file");
    jsonw_double(&w, "seconds", r->seconds, 6);
    jsonw_object_end(&w);
    jsonw_finish(&w);
}
