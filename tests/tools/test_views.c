/*
 * hpfc-inspect's views and renderer (hpfc-inspect/views.c, roads.c, word.c,
 * render.c) on generated graphs:
 *   - the pieces: CRC-32C check values, word parsing, decimals, pixel paths;
 *   - crossing identification done with the public reader API (roads.c)
 *     agrees with the library's traversal: every crossing seen from across
 *     its road and back is itself, both sides place it at the same point,
 *     and walking a dart through its stabbings ends at its twin;
 *   - the views run on every graph, count the graph's edges, find the
 *     unbounded face outside the graph and flag a damaged checksum;
 *   - the renderer draws every vertex and writes well-formed SVG.
 */
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "gen.h"
#include "hpfc.h"
#include "render.h"
#include "roads.h"
#include "locate.h"
#include "views.h"
#include "word.h"

/* ---- pieces ------------------------------------------------------------------------ */

/* the layout under test (check_use_test_layout) */
static int test_layout_compact;

static void test_words(void)
{
    word_info wi;
    memset(&wi, 0, sizeof wi);
    CHECK_EQ_INT(word_parse(&wi, "++++", 4), 0);
    CHECK_EQ_INT(wi.n, 0);
    CHECK_EQ_INT(word_parse(&wi, "(+Y+Y+)+", 8), 0);
    CHECK_EQ_INT(wi.n, 4);
    CHECK_EQ_INT(wi.ncomp, 1);
    CHECK_EQ_INT(wi.nvert, 1);
    CHECK_EQ_INT(wi.comp_size[0], 4);
    for (uint32_t k = 0; k < 4; k++)
        CHECK_EQ_INT(word_road_of(&wi, k), k);
    CHECK_EQ_INT(word_parse(&wi, "=(Y+Y)[(+)[+]]+", 15), 0);
    CHECK_EQ_INT(wi.ncomp, 5);
    CHECK_EQ_INT(wi.nvert, 3);
    CHECK_EQ_INT(wi.comp_vertex[2], WORD_NONE); /* the first '[' */
    CHECK_EQ_INT(wi.comp_first[2], 5);
    CHECK_EQ_INT(wi.comp_last[2], 10);
    const char *bad[] = {"=Y+Y[(+)[+]]+", "+++++", "+++", "[+)+++", "(+]+++", "++++=", "Y++++", "x++++"};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++)
        CHECK_EQ_INT(word_parse(&wi, bad[k], strlen(bad[k])), -1);
    uint32_t counts[4];
    word_road_counts("[+]+(Y)++", 9, counts);
    CHECK(counts[0] == 1 && counts[1] == 1 && counts[2] == 3 && counts[3] == 0);
    CHECK(strcmp(word_symbol_code('Y'), "1100") == 0 && strcmp(word_symbol_code('+'), "0") == 0);
    word_info_free(&wi);
}

static int64_t floor_of(const char *text, int32_t e)
{
    decimal d;
    int64_t v = 12345678;
    CHECK_EQ_INT(decimal_parse(text, strlen(text), &d), 0);
    CHECK_EQ_INT(decimal_floor_lattice(&d, e, &v), 0);
    return v;
}

static void test_decimals(void)
{
    CHECK_EQ_INT(floor_of("1.5", 0), 1);
    CHECK_EQ_INT(floor_of("-1.5", 0), -2);
    CHECK_EQ_INT(floor_of("-2", 0), -2);
    CHECK_EQ_INT(floor_of("-2.000", 0), -2);
    CHECK_EQ_INT(floor_of("1e3", 0), 1000);
    CHECK_EQ_INT(floor_of("0.001", -3), 1);
    CHECK_EQ_INT(floor_of("12.345", -2), 1234);
    CHECK_EQ_INT(floor_of("-12.345", -2), -1235);
    CHECK_EQ_INT(floor_of("1500", 3), 1);
    CHECK_EQ_INT(floor_of("-1500", 3), -2);
    CHECK_EQ_INT(floor_of(".5", 0), 0);
    CHECK_EQ_INT(floor_of("-.5", 0), -1);
    CHECK_EQ_INT(floor_of("0", 0), 0);
    CHECK_EQ_INT(floor_of("+7.", 0), 7);
    decimal d;
    int64_t v;
    CHECK_EQ_INT(decimal_parse("1e40", 4, &d), 0);
    CHECK_EQ_INT(decimal_floor_lattice(&d, 0, &v), -1);
    CHECK_EQ_INT(decimal_parse("1.50", 4, &d), 0);
    CHECK_EQ_INT(decimal_fraction_digits(&d), 1);
    CHECK(d.value == 1.5);
    const char *bad[] = {"", "-", ".", "1.2.3", "abc", "1e", "--1", "1,2", " 1", "0x10", "inf"};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++)
        CHECK_EQ_INT(decimal_parse(bad[k], strlen(bad[k]), &d), -1);
    decimal xy[4];
    CHECK_EQ_INT(decimal_list_parse("1,2", xy, 2), 0);
    CHECK_EQ_INT(decimal_list_parse("1,2,3", xy, 2), -1);
    CHECK_EQ_INT(decimal_list_parse("1", xy, 2), -1);
    CHECK_EQ_INT(decimal_list_parse("0,0,10.5,-3", xy, 4), 0);
    CHECK(xy[3].value == -3 && xy[2].value == 10.5);
    char text[64];
    view_decimal_text(1234, -2, text, sizeof text);
    CHECK(strcmp(text, "12.34") == 0);
    view_decimal_text(-5, -3, text, sizeof text);
    CHECK(strcmp(text, "-0.005") == 0);
    view_decimal_text(7, 2, text, sizeof text);
    CHECK(strcmp(text, "700") == 0);
}

static void test_paths(void)
{
    pixel_path pp;
    char why[VIEW_WHY];
    CHECK_EQ_INT(pixel_path_parse("3,5/1,0/0,1", &pp, why, sizeof why), 0);
    CHECK_EQ_INT(pp.levels, 3);
    CHECK(pp.ij[0][0] == 3 && pp.ij[0][1] == 5 && pp.ij[2][1] == 1);
    const char *bad[] = {"", "3", "3,", "3,5/", "3;5", "3,5,1", "-1,0", "3,5//1,0", "99999999999,0"};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++)
        CHECK_EQ_INT(pixel_path_parse(bad[k], &pp, why, sizeof why), -1);
}

/* ---- on files -------------------------------------------------------------------------- */

typedef struct packed {
    uint8_t *buf;
    size_t size;
    hpfc_file *f;
    size_t nv, ne;
} packed;

static int pack(const hpfc_graph *g, uint32_t n0, uint32_t n, packed *p)
{
    hpfc_build_params bp;
    hpfc_build_params_default(&bp);
    bp.root_cols = bp.root_rows = n0;
    bp.cols = bp.rows = n;
    hpfc_tree *t = NULL;
    memset(p, 0, sizeof *p);
    p->nv = hpfc_graph_vertex_count(g);
    p->ne = hpfc_graph_edge_count(g);
    int st = hpfc_build(g, &bp, &t, NULL);
    if (!st)
        st = check_tree_serialize(t, NULL, &p->buf, &p->size, NULL);
    if (!st)
        st = hpfc_open_memory(p->buf, p->size, 0, &p->f);
    hpfc_tree_free(t);
    CHECK_EQ_INT(st, HPFC_OK);
    return st;
}

static void unpack(packed *p)
{
    hpfc_close(p->f);
    hpfc_free(p->buf);
}

/* Every crossing: across and back is itself; both sides agree on its place;
 * a dart walked through its stabbings ends at the library's twin. */
static void check_crossings(const hpfc_file *f)
{
    roads r;
    word_info wi, qi;
    memset(&wi, 0, sizeof wi);
    memset(&qi, 0, sizeof qi);
    CHECK_EQ_INT(roads_init(&r, f), HPFC_OK);
    hpfc_walker *w;
    CHECK_EQ_INT(hpfc_walker_create(f, &w), HPFC_OK);
    size_t bad_back = 0, bad_place = 0, bad_twin = 0, crossings = 0;
    hpfc_pixel px;
    for (int st = hpfc_leaf_first(f, &px); !st; st = hpfc_leaf_next(f, &px)) {
        CHECK_EQ_INT(roads_parse(&r, &px, &wi), HPFC_OK);
        lbox b;
        roads_box(f, &px, &b);
        for (uint32_t k = 0; k < wi.n; k++, crossings++) {
            hpfc_pixel q, back;
            uint32_t m, kk;
            int road = word_road_of(&wi, k), opp = (road + 2) % 4;
            CHECK_EQ_INT(roads_cross(&r, &px, &wi, k, &q, &m), HPFC_OK);
            CHECK_EQ_INT(roads_parse(&r, &q, &qi), HPFC_OK);
            CHECK_EQ_INT(roads_cross(&r, &q, &qi, m, &back, &kk), HPFC_OK);
            bad_back += kk != k || hpfc_dart_key(f, &(hpfc_dart){back, kk}) !=
                                       hpfc_dart_key(f, &(hpfc_dart){px, k});
            /* the same point from both sides */
            double here[64], there[64];
            uint32_t c = wi.road_off[road + 1] - wi.road_off[road];
            uint32_t cq = qi.road_off[opp + 1] - qi.road_off[opp];
            lbox qb;
            roads_box(f, &q, &qb);
            if (c <= 64 && cq <= 64) {
                CHECK_EQ_INT(roads_positions(&r, &b, road, c, here), HPFC_OK);
                CHECK_EQ_INT(roads_positions(&r, &qb, opp, cq, there), HPFC_OK);
                bad_place += fabs(here[k - wi.road_off[road]] - there[m - qi.road_off[opp]]) > 1e-6;
            }
            if (wi.comp_vertex[wi.comp[k]] == WORD_NONE)
                continue;
            hpfc_dart d = {px, k}, mine; /* roads_walk takes the path form */
            uint64_t stabbings, dart = 0, twin = 0;
            CHECK_EQ_INT(roads_walk(&r, &d, &stabbings, &mine), HPFC_OK);
            CHECK_EQ_INT(hpfc_pixel_dart_key(w, &px, k, &dart), HPFC_OK);
            CHECK_EQ_INT(hpfc_key_twin(w, dart, &twin), HPFC_OK);
            bad_twin += hpfc_dart_key(f, &mine) != twin;
        }
    }
    CHECK(crossings > 0);
    CHECK_EQ_INT(bad_back, 0);
    CHECK_EQ_INT(bad_place, 0);
    CHECK_EQ_INT(bad_twin, 0);
    hpfc_walker_free(w);
    word_info_free(&wi);
    word_info_free(&qi);
    roads_free(&r);
}

/* A view's output, in memory. */
typedef struct capture {
    char *text;
    size_t len;
    FILE *out;
} capture;

static FILE *capture_begin(capture *c)
{
    c->text = NULL;
    c->len = 0;
    c->out = open_memstream(&c->text, &c->len);
    return c->out;
}

static void capture_end(capture *c)
{
    fclose(c->out);
}

/* The unsigned number after "key": in a one-line JSON object, or -1. */
static long long json_number(const char *text, const char *key)
{
    char pattern[64];
    snprintf(pattern, sizeof pattern, "\"%s\":", key);
    const char *p = strstr(text, pattern);
    return p ? strtoll(p + strlen(pattern), NULL, 10) : -1;
}

/* Stabbing components in all words: each lies on one edge, so the edges'
 * stabbings must add up to them. */
static long long count_stabbings(const hpfc_file *f)
{
    roads r;
    word_info wi;
    memset(&wi, 0, sizeof wi);
    roads_init(&r, f);
    long long n = 0;
    hpfc_pixel px;
    for (int st = hpfc_leaf_first(f, &px); !st; st = hpfc_leaf_next(f, &px)) {
        CHECK_EQ_INT(roads_parse(&r, &px, &wi), HPFC_OK);
        for (uint32_t c = 0; c < wi.ncomp; c++)
            n += wi.comp_vertex[c] == WORD_NONE;
    }
    word_info_free(&wi);
    roads_free(&r);
    return n;
}

static void check_stats(const hpfc_file *f, const packed *p)
{
    capture c;
    char why[VIEW_WHY];
    CHECK_EQ_INT(view_stats(f, capture_begin(&c), 1, why), VIEW_OK);
    capture_end(&c);
    CHECK_EQ_INT(json_number(c.text, "edges"), (long long)p->ne);
    CHECK_EQ_INT(json_number(c.text, "vertices"), (long long)p->nv);
    CHECK_EQ_INT(json_number(c.text, "stabbings"), count_stabbings(f));
    CHECK(strstr(c.text, "\"stabbings_per_edge\":{\"count\":") != NULL);
    free(c.text);
    CHECK_EQ_INT(view_stats(f, capture_begin(&c), 0, why), VIEW_OK);
    capture_end(&c);
    CHECK(strstr(c.text, "stabbings per edge") != NULL);
    free(c.text);
}

/* The domain's rim is outside the graph: the unbounded face 0 alone. */
static void check_locate(const hpfc_file *f)
{
    hpfc_file_info info;
    hpfc_file_get_info(f, &info);
    char text[64], why[VIEW_WHY];
    decimal xy[2];
    snprintf(text, sizeof text, "%lld,%lld", (long long)info.x0,
             (long long)(info.y0 + info.height - 1));
    CHECK_EQ_INT(decimal_list_parse(text, xy, 2), 0);
    capture c;
    CHECK_EQ_INT(view_locate(f, xy, capture_begin(&c), 1, why), VIEW_OK);
    capture_end(&c);
    CHECK(strstr(c.text, "\"faces\":[0") != NULL);
    if (!strstr(c.text, "\"faces\":[0"))
        fprintf(stderr, "%s", c.text);
    CHECK(strstr(c.text, "\"features\":[]") != NULL);
    free(c.text);
    snprintf(text, sizeof text, "%lld,0", (long long)(info.x0 - 1));
    CHECK_EQ_INT(decimal_list_parse(text, xy, 2), 0);
    CHECK_EQ_INT(view_locate(f, xy, capture_begin(&c), 1, why), VIEW_OK);
    capture_end(&c);
    CHECK(strstr(c.text, "\"pixel\":null") != NULL && strstr(c.text, "\"faces\":[]") != NULL);
    free(c.text);
}

/* Faces of every leaf lie in [0, F); a private leaf has exactly one. */
static void check_pixel_faces(const hpfc_file *f)
{
    hpfc_faces *fc;
    CHECK_EQ_INT(hpfc_faces_build(f, &fc), HPFC_OK);
    uint64_t nf = hpfc_faces_face_count(fc), faces[4096];
    size_t bad = 0;
    hpfc_pixel px;
    for (int st = hpfc_leaf_first(f, &px); !st; st = hpfc_leaf_next(f, &px)) {
        size_t n = 0;
        int is_private;
        hpfc_pixel_is_private(f, &px, &is_private);
        if (view_pixel_faces(f, fc, &px, faces, 4096, &n))
            bad++;
        bad += n == 0 || (is_private && n != 1);
        for (size_t k = 0; k < n; k++)
            bad += faces[k] >= nf || (k && faces[k] <= faces[k - 1]);
    }
    CHECK_EQ_INT(bad, 0);
    hpfc_faces_free(fc);
}

static void check_pixel_view(const hpfc_file *f)
{
    pixel_path pp;
    char why[VIEW_WHY];
    capture c;
    CHECK_EQ_INT(pixel_path_parse("0,0", &pp, why, sizeof why), 0);
    CHECK_EQ_INT(view_pixel(f, &pp, capture_begin(&c), 1, why), VIEW_OK);
    capture_end(&c);
    CHECK(strstr(c.text, "\"pixel\":\"0,0\"") != NULL);
    CHECK(strstr(c.text, "\"W\":null") != NULL && strstr(c.text, "\"N\":null") != NULL);
    free(c.text);
    /* the first leaf in depth-first order, by its path */
    hpfc_pixel px;
    char path[1200];
    CHECK_EQ_INT(hpfc_leaf_first(f, &px), HPFC_OK);
    pixel_path_text(&px, path, sizeof path);
    CHECK_EQ_INT(pixel_path_parse(path, &pp, why, sizeof why), 0);
    CHECK_EQ_INT(view_pixel(f, &pp, capture_begin(&c), 0, why), VIEW_OK);
    capture_end(&c);
    CHECK(strstr(c.text, "word        ") != NULL && strstr(c.text, "neighbours") != NULL);
    free(c.text);
    /* a root pixel out of range */
    CHECK_EQ_INT(pixel_path_parse("100000,0", &pp, why, sizeof why), 0);
    CHECK_EQ_INT(view_pixel(f, &pp, capture_begin(&c), 0, why), VIEW_FAIL);
    capture_end(&c);
    free(c.text);
}

static void check_sections(const packed *p)
{
    char path[] = "/tmp/hpfc-test-views-XXXXXX", why[VIEW_WHY];
    int fd = mkstemp(path);
    CHECK(fd >= 0);
    if (fd < 0)
        return;
    CHECK_EQ_INT(write(fd, p->buf, p->size), (long long)p->size);
    close(fd);
    capture c;
    CHECK_EQ_INT(view_sections(p->f, path, capture_begin(&c), 1, why), VIEW_OK);
    capture_end(&c);
    CHECK(strstr(c.text, "\"checksums_ok\":true") != NULL);
    free(c.text);
    /* damage the last pool byte: the file still opens, POOL no longer verifies */
    FILE *io = fopen(path, "r+b");
    fseek(io, (long)p->size - 1, SEEK_SET);
    int byte = fgetc(io);
    fseek(io, (long)p->size - 1, SEEK_SET);
    fputc(byte ^ 0x5A, io);
    fclose(io);
    hpfc_file *f;
    CHECK_EQ_INT(hpfc_open(path, 0, &f), HPFC_OK);
    CHECK_EQ_INT(view_sections(f, path, capture_begin(&c), 0, why), VIEW_FAIL);
    capture_end(&c);
    CHECK(strstr(c.text, "MISMATCH") != NULL);
    free(c.text);
    hpfc_close(f);
    unlink(path);
}

static void check_render(const packed *p)
{
    char dir[] = "/tmp/hpfc-test-render-XXXXXX", path[64], why[VIEW_WHY];
    CHECK(mkdtemp(dir) != NULL);
    snprintf(path, sizeof path, "%s/out.svg", dir);
    render_params rp = {.output = path, .format = RENDER_SVG, .width = 2048};
    render_report rep;
    CHECK_EQ_INT(render_file(p->f, &rp, &rep, why), 0);
    CHECK_EQ_INT(rep.width, 2048);
    CHECK(rep.segments > 0);
    if (rep.ink == 0)
        CHECK_EQ_INT(rep.vertices, (long long)p->nv);
    FILE *in = fopen(path, "rb");
    char head[64] = {0};
    CHECK(in && fread(head, 1, sizeof head - 1, in) > 0);
    if (in)
        fclose(in);
    CHECK(strncmp(head, "<?xml", 5) == 0);
    /* a window beside the domain draws nothing, and is no error */
    hpfc_file_info info;
    hpfc_file_get_info(p->f, &info);
    rp.have_window = 1;
    rp.window[0] = (double)info.x0 - 100, rp.window[1] = (double)info.y0 - 100;
    rp.window[2] = (double)info.x0 - 50, rp.window[3] = (double)info.y0 - 50;
    CHECK_EQ_INT(render_file(p->f, &rp, &rep, why), 0);
    CHECK_EQ_INT(rep.leaves, 0);
    rp.window[2] = rp.window[0];
    CHECK_EQ_INT(render_file(p->f, &rp, &rep, why), 1); /* empty window */
    CHECK_EQ_INT(render_format_of("a.PNG"), RENDER_PNG);
    CHECK_EQ_INT(render_format_of("a.svg"), RENDER_SVG);
    CHECK_EQ_INT(render_format_of("a.pdf"), 0);
    unlink(path);
    rmdir(dir);
}

static void check_graph(const char *name, hpfc_graph *g, uint32_t n0, uint32_t n)
{
    packed p;
    if (!g || pack(g, n0, n, &p)) {
        fprintf(stderr, "%s: cannot pack\n", name);
        CHECK(0);
        hpfc_graph_free(g);
        return;
    }
    int before = check_failures;
    check_crossings(p.f);
    check_stats(p.f, &p);
    check_locate(p.f);
    check_pixel_faces(p.f);
    check_pixel_view(p.f);
    check_sections(&p);
    check_render(&p);
    if (check_failures != before)
        fprintf(stderr, "  (in %s, root %u, refine %u)\n", name, n0, n);
    unpack(&p);
    hpfc_graph_free(g);
}

int main(void)
{
    test_layout_compact = check_use_test_layout();
    test_words();
    test_decimals();
    test_paths();
    for (int k = 0; k < GEN_SPECIAL_COUNT; k++) {
        static const uint32_t roots[] = {1, 3, 8};
        for (int r = 0; r < 3; r++) {
            hpfc_graph *g = NULL;
            gen_special(k, &g);
            check_graph(gen_special_name(k), g, roots[r], r == 2 ? 3 : 2);
        }
    }
    for (uint64_t seed = 1; seed <= 6; seed++) {
        hpfc_graph *g = NULL;
        gen_delaunay(seed, 60, 400, 0.2, &g);
        check_graph("delaunay", g, (uint32_t)(seed % 3) + 1, 2 + (uint32_t)(seed % 2));
        gen_polyline(seed, 80, 500, 0.5, &g);
        check_graph("polyline", g, 4, 2);
    }
    hpfc_graph *g = NULL;
    gen_grid_mesh(3, 12, 9, 7, &g);
    check_graph("grid", g, 2, 2);
    return check_report("views");
}
