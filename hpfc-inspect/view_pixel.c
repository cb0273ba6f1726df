/*
 * view_pixel.c: --pixel PATH, one pixel: its type, word and code, roads,
 * components, vertices, neighbours and labels; and the face candidates of a
 * word pixel, which --locate and --render share.
 */
#include "views.h"

#include <ctype.h>
#include <errno.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "jsonw.h"
#include "roads.h"
#include "word.h"

static const char *const road_names[4] = {"W", "N", "E", "S"};

static void json_user(jsonw *w, const char *key, int64_t v, int32_t e)
{
    char text[80];
    view_decimal_text(v, e, text, sizeof text);
    jsonw_double(w, key, strtod(text, NULL), e < 0 ? (-e > 17 ? 17 : -e) : 0);
}

static int resolve_path(const hpfc_file *f, const pixel_path *pp, hpfc_pixel *px, char *why)
{
    hpfc_file_info info;
    hpfc_file_get_info(f, &info);
    for (uint32_t l = 0; l < pp->levels; l++) {
        uint32_t i = pp->ij[l][0], j = pp->ij[l][1];
        uint32_t n = l ? info.cols : info.root_cols, m = l ? info.rows : info.root_rows;
        if (i >= n || j >= m)
            return view_fail(why, "no pixel %u,%u at depth %u: images there are %ux%u", i, j, l, n,
                             m);
        int type, st;
        if (l > 0) {
            if ((st = hpfc_pixel_type(f, px, &type)))
                return view_fail_status(why, "pixel type", st);
            if (type != HPFC_PIXEL_REFINED)
                return view_fail(
                    why, "the pixel at depth %u is a word pixel: the path goes no deeper", l - 1);
        }
        st = l ? hpfc_pixel_child(f, px, i, j, px) : hpfc_pixel_root(f, i, j, px);
        if (st)
            return view_fail_status(why, "pixel", st);
    }
    return VIEW_OK;
}

/* ---- faces of a pixel --------------------------------------------------------- */

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

int view_pixel_faces(const hpfc_file *f, const hpfc_faces *fc, const hpfc_pixel *px,
                     uint64_t *faces, size_t cap, size_t *count)
{
    int is_private;
    int st = hpfc_pixel_is_private(f, px, &is_private);
    *count = 0;
    if (st)
        return st;
    if (is_private) {
        if (cap < 1)
            return HPFC_E_ARG;
        *count = 1;
        return hpfc_faces_pixel_face(fc, px, &faces[0]);
    }
    size_t len;
    if ((st = hpfc_pixel_word(f, px, NULL, 0, &len)))
        return st;
    uint32_t n = (uint32_t)(len - 4); /* a word of c crossings has c + 4 symbols */
    if (len < 4 || cap < n)
        return HPFC_E_ARG;
    for (uint32_t k = 0; k < n; k++) {
        hpfc_dart d = {.pixel = *px, .crossing = k};
        if ((st = hpfc_faces_dart_face(fc, &d, &faces[k])))
            return st;
    }
    qsort(faces, n, sizeof *faces, cmp_u64);
    size_t u = 0;
    for (uint32_t k = 0; k < n; k++)
        if (u == 0 || faces[u - 1] != faces[k])
            faces[u++] = faces[k];
    *count = u;
    return HPFC_OK;
}

/* ---- --pixel ------------------------------------------------------------------- */

#define PATH_TEXT 1200

typedef struct pixel_view {
    hpfc_pixel px;
    char path[PATH_TEXT];
    int type, is_private;
    lbox b;
    int32_t e;                  /* unit_exp10 */
    hpfc_level_info level;
    char *word;                 /* word pixels: the symbols, NUL-ended */
    size_t len;
    word_info wi;
    uint32_t counts[4];
    uint32_t nvert;
    uint32_t *degree;
    uint64_t *vkey;
    int has_nb[4];
    char nb[4][PATH_TEXT];
    uint64_t child_image;       /* refined pixels: bit offset of the child image */
    int labels;                 /* the file's LABL section gave the next three */
    uint64_t leaf_number;
    uint64_t *stretch_face;     /* per stretch (one for a private leaf) */
    uint64_t *edge;             /* per crossing */
    int compact;                /* compact pool layout (spec §5.3): images are indices,
                                   words have no slot */
} pixel_view;

static void pixel_view_free(pixel_view *v)
{
    free(v->word);
    free(v->degree);
    free(v->vkey);
    free(v->stretch_face);
    free(v->edge);
    word_info_free(&v->wi);
}

static int read_neighbours(const hpfc_file *f, pixel_view *v, char *why)
{
    for (int dir = 0; dir < 4; dir++) {
        hpfc_pixel nb;
        int st = hpfc_pixel_move(f, &v->px, dir, &nb);
        if (st == HPFC_E_NO_PIXEL)
            continue;
        if (st)
            return view_fail_status(why, "neighbour", st);
        v->has_nb[dir] = 1;
        pixel_path_text(&nb, v->nb[dir], sizeof v->nb[dir]);
    }
    return VIEW_OK;
}

/* The vertices as the traversal API sees them, with their degrees. */
static int read_vertices(const hpfc_file *f, pixel_view *v, char *why)
{
    hpfc_walker *w;
    int st = hpfc_walker_create(f, &w);
    if (!st)
        st = hpfc_pixel_vertex_count(w, &v->px, &v->nvert);
    if (!st) {
        v->degree = calloc(v->nvert + 1, sizeof *v->degree);
        v->vkey = calloc(v->nvert + 1, sizeof *v->vkey);
        if (!v->degree || !v->vkey)
            st = HPFC_E_NOMEM;
    }
    for (uint32_t k = 0; k < v->nvert && !st; k++) {
        st = hpfc_pixel_vertex_key(w, &v->px, k, &v->vkey[k]);
        if (!st)
            st = hpfc_key_degree(w, v->vkey[k], &v->degree[k]);
    }
    hpfc_walker_free(w);
    return st ? view_fail_status(why, "vertices", st) : VIEW_OK;
}

/* The leaf's stored labels (LABL, spec §6.5), when the file has them. */
static int read_labels(const hpfc_file *f, pixel_view *v, char *why)
{
    hpfc_labels_info li;
    if (hpfc_file_get_labels(f, &li) != HPFC_OK)
        return VIEW_OK;
    uint32_t n = v->wi.n, stretches = n ? n : 1;
    v->stretch_face = calloc(stretches, sizeof *v->stretch_face);
    v->edge = calloc(n + 1, sizeof *v->edge);
    int st = v->stretch_face && v->edge ? HPFC_OK : HPFC_E_NOMEM;
    if (!st)
        st = hpfc_leaf_number(f, &v->px, &v->leaf_number);
    for (uint32_t t = 0; t < stretches && !st; t++)
        st = hpfc_label_stretch_face(f, &v->px, t, &v->stretch_face[t]);
    for (uint32_t k = 0; k < n && !st; k++)
        st = hpfc_label_crossing_edge(f, &v->px, k, &v->edge[k]);
    if (st)
        return view_fail_status(why, "labels", st);
    v->labels = 1;
    return VIEW_OK;
}

static int read_word(const hpfc_file *f, pixel_view *v, char *why)
{
    int st = hpfc_pixel_word(f, &v->px, NULL, 0, &v->len);
    if (!st && !(v->word = malloc(v->len + 1)))
        st = HPFC_E_NOMEM;
    if (!st)
        st = hpfc_pixel_word(f, &v->px, v->word, v->len + 1, &v->len);
    if (st)
        return view_fail_status(why, "word", st);
    v->word[v->len] = '\0';
    int p = word_parse(&v->wi, v->word, v->len);
    if (p)
        return view_fail_status(why, "word", p == -2 ? HPFC_E_NOMEM : HPFC_E_CORRUPT);
    word_road_counts(v->word, v->len, v->counts);
    if (read_labels(f, v, why))
        return VIEW_FAIL;
    return read_vertices(f, v, why);
}

static int read_pixel_view(const hpfc_file *f, pixel_view *v, char *why)
{
    hpfc_file_info info;
    hpfc_file_get_info(f, &info);
    v->e = info.unit_exp10;
    v->compact = info.incompat_flags & 0x1;
    pixel_path_text(&v->px, v->path, sizeof v->path);
    int st = hpfc_pixel_type(f, &v->px, &v->type);
    if (!st)
        st = hpfc_pixel_is_private(f, &v->px, &v->is_private);
    if (!st)
        st = roads_box(f, &v->px, &v->b);
    if (!st)
        st = hpfc_file_get_level(f, v->px.depth, &v->level);
    if (st)
        return view_fail_status(why, "pixel", st);
    if (v->type == HPFC_PIXEL_REFINED) {
        hpfc_pixel child;
        if ((st = hpfc_pixel_child(f, &v->px, 0, 0, &child)))
            return view_fail_status(why, "child image", st);
        v->child_image = child.path[child.depth].image;
    } else if (read_word(f, v, why)) {
        return VIEW_FAIL;
    }
    return read_neighbours(f, v, why);
}

static const char *pixel_kind(const pixel_view *v)
{
    return v->type == HPFC_PIXEL_REFINED ? "refined" : v->is_private ? "private" : "word";
}

static void print_code(FILE *out, const char *word, size_t len)
{
    for (size_t k = 0; k < len; k++)
        fprintf(out, "%s%s", k ? " " : "", word_symbol_code(word[k]));
}

static void print_components_text(FILE *out, const pixel_view *v)
{
    const word_info *wi = &v->wi;
    for (uint32_t c = 0; c < wi->ncomp; c++) {
        fprintf(out, "%s", c ? "            " : "components  ");
        if (wi->comp_vertex[c] == WORD_NONE)
            fprintf(out, "stabbing:");
        else
            fprintf(out, "junction of vertex %u, degree %u:", wi->comp_vertex[c], wi->comp_size[c]);
        for (uint32_t k = wi->comp_first[c]; k <= wi->comp_last[c]; k++)
            if (wi->comp[k] == c)
                fprintf(out, " %u%c(%s)", k, wi->sym[k], road_names[word_road_of(wi, k)]);
        fprintf(out, "\n");
    }
    if (wi->ncomp == 0)
        fprintf(out, "components  none\n");
}

static void print_pixel_text(FILE *out, const pixel_view *v)
{
    char x0[64], y0[64], x1[64], y1[64];
    view_decimal_text(v->b.x0, v->e, x0, sizeof x0);
    view_decimal_text(v->b.y0, v->e, y0, sizeof y0);
    view_decimal_text(v->b.x1, v->e, x1, sizeof x1);
    view_decimal_text(v->b.y1, v->e, y1, sizeof y1);
    fprintf(out, v->compact ? "pixel       %s (depth %u, image %llu of level %u)\n"
                            : "pixel       %s (depth %u, image at bit %llu of level %u's pool)\n",
            v->path, v->px.depth, (unsigned long long)v->px.path[v->px.depth].image, v->px.depth);
    fprintf(out, "type        %s\n", pixel_kind(v));
    fprintf(out, "bounds      [%s, %s) x [%s, %s)\n", x0, x1, y0, y1);
    if (v->type == HPFC_PIXEL_REFINED) {
        fprintf(out, v->compact ? "child       image %llu of level %u\n"
                                : "child       image at bit %llu of level %u's pool\n",
                (unsigned long long)v->child_image, v->px.depth + 1);
    } else {
        fprintf(out, "word        %s (%zu symbols, %u crossings)\n", v->word, v->len, v->wi.n);
        if (v->compact) {
            fprintf(out, "code        compact layout: context-coded in the level's word stream\n");
        } else {
            fprintf(out, "code        ");
            print_code(out, v->word, v->len);
            fprintf(out, " (%u of %u slot bits)\n", 4 + 4 * v->wi.n, v->level.word_bits);
        }
        fprintf(out, "crossings   W %u, N %u, E %u, S %u\n", v->counts[0], v->counts[1],
                v->counts[2], v->counts[3]);
        print_components_text(out, v);
        fprintf(out, "vertices    ");
        for (uint32_t k = 0; k < v->nvert; k++)
            fprintf(out, "%s%u: degree %u (key %llu)", k ? "; " : "", k, v->degree[k],
                    (unsigned long long)v->vkey[k]);
        fprintf(out, "%s\n", v->nvert ? "" : "none");
    }
    if (v->labels) {
        fprintf(out, "labels      leaf %llu; stretch faces", (unsigned long long)v->leaf_number);
        for (uint32_t t = 0; t < (v->wi.n ? v->wi.n : 1); t++)
            fprintf(out, " %llu", (unsigned long long)v->stretch_face[t]);
        fprintf(out, "; crossing edges%s", v->wi.n ? "" : " none");
        for (uint32_t k = 0; k < v->wi.n; k++)
            fprintf(out, " %llu", (unsigned long long)v->edge[k]);
        fputc('\n', out);
    }
    fprintf(out, "neighbours ");
    for (int dir = 0; dir < 4; dir++)
        fprintf(out, " %s %s%s", road_names[dir], v->has_nb[dir] ? v->nb[dir] : "none",
                dir < 3 ? "," : "\n");
}

static void json_bounds(jsonw *w, const lbox *b, int32_t e)
{
    jsonw_array_begin(w, "bounds");
    json_user(w, NULL, b->x0, e);
    json_user(w, NULL, b->y0, e);
    json_user(w, NULL, b->x1, e);
    json_user(w, NULL, b->y1, e);
    jsonw_array_end(w);
}

static void json_components(jsonw *w, const word_info *wi)
{
    jsonw_array_begin(w, "components");
    for (uint32_t c = 0; c < wi->ncomp; c++) {
        jsonw_object_begin(w, NULL);
        int junction = wi->comp_vertex[c] != WORD_NONE;
        jsonw_string(w, "kind", junction ? "junction" : "stabbing");
        if (junction)
            jsonw_u64(w, "vertex", wi->comp_vertex[c]);
        jsonw_array_begin(w, "crossings");
        for (uint32_t k = wi->comp_first[c]; k <= wi->comp_last[c]; k++)
            if (wi->comp[k] == c) {
                jsonw_object_begin(w, NULL);
                jsonw_u64(w, "index", k);
                jsonw_string_n(w, "symbol", &wi->sym[k], 1);
                jsonw_string(w, "road", road_names[word_road_of(wi, k)]);
                jsonw_object_end(w);
            }
        jsonw_array_end(w);
        jsonw_object_end(w);
    }
    jsonw_array_end(w);
}

static void json_word(jsonw *w, const pixel_view *v)
{
    jsonw_string(w, "word", v->word);
    jsonw_u64(w, "symbols", v->len);
    if (v->compact) { /* no slot, no fixed code: spec §5.3 */
        jsonw_string(w, "layout", "compact");
    } else {
        jsonw_u64(w, "code_bits", 4 + 4ull * v->wi.n);
        jsonw_u64(w, "slot_bits", v->level.word_bits);
        jsonw_array_begin(w, "code");
        for (size_t k = 0; k < v->len; k++)
            jsonw_string(w, NULL, word_symbol_code(v->word[k]));
        jsonw_array_end(w);
    }
    jsonw_object_begin(w, "crossings");
    for (int r = 0; r < 4; r++)
        jsonw_u64(w, road_names[r], v->counts[r]);
    jsonw_object_end(w);
    json_components(w, &v->wi);
    jsonw_array_begin(w, "vertices");
    for (uint32_t k = 0; k < v->nvert; k++) {
        jsonw_object_begin(w, NULL);
        jsonw_u64(w, "local", k);
        jsonw_u64(w, "degree", v->degree[k]);
        jsonw_u64(w, "key", v->vkey[k]);
        jsonw_object_end(w);
    }
    jsonw_array_end(w);
    if (!v->labels)
        return;
    jsonw_object_begin(w, "labels");
    jsonw_u64(w, "leaf_number", v->leaf_number);
    jsonw_array_begin(w, "stretch_faces");
    for (uint32_t t = 0; t < (v->wi.n ? v->wi.n : 1); t++)
        jsonw_u64(w, NULL, v->stretch_face[t]);
    jsonw_array_end(w);
    jsonw_array_begin(w, "edges");
    for (uint32_t k = 0; k < v->wi.n; k++)
        jsonw_u64(w, NULL, v->edge[k]);
    jsonw_array_end(w);
    jsonw_object_end(w);
}

static void print_pixel_json(FILE *out, const pixel_view *v)
{
    jsonw w;
    jsonw_init(&w, out);
    jsonw_object_begin(&w, NULL);
    jsonw_string(&w, "pixel", v->path);
    jsonw_u64(&w, "depth", v->px.depth);
    jsonw_u64(&w, "image", v->px.path[v->px.depth].image);
    jsonw_string(&w, "type", pixel_kind(v));
    jsonw_bool(&w, "private", v->is_private);
    json_bounds(&w, &v->b, v->e);
    if (v->type == HPFC_PIXEL_REFINED)
        jsonw_u64(&w, "child_image", v->child_image);
    else
        json_word(&w, v);
    jsonw_object_begin(&w, "neighbours");
    for (int dir = 0; dir < 4; dir++) {
        if (v->has_nb[dir])
            jsonw_string(&w, road_names[dir], v->nb[dir]);
        else
            jsonw_null(&w, road_names[dir]);
    }
    jsonw_object_end(&w);
    jsonw_object_end(&w);
    jsonw_finish(&w);
}

int view_pixel(const hpfc_file *f, const pixel_path *pp, FILE *out, int json, char *why)
{
    pixel_view *v = calloc(1, sizeof *v);
    if (!v)
        return view_fail_status(why, "pixel", HPFC_E_NOMEM);
    int status = resolve_path(f, pp, &v->px, why);
    if (!status)
        status = read_pixel_view(f, v, why);
    if (!status && json)
        print_pixel_json(out, v);
    else if (!status)
        print_pixel_text(out, v);
    pixel_view_free(v);
    free(v);
    return status;
}

