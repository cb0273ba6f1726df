/*
 * A .pfc text read in chunks into a graph file (hpfc.h, "A .pfc text read
 * in chunks", "A graph file"), against hpfc_pfc_parse of the whole text:
 *
 *   - every text hpfc_pfc_parse reads gives, in 1 to 16 chunks, the same
 *     vertices, edges, points and unit, from the bytes and from the mapped
 *     file, and the same box; the tree built from the mapped graph is the
 *     parsed graph's, byte for byte;
 *   - no text that hpfc_pfc_parse or then hpfc_graph_validate refuses
 *     passes the chunks, hpfc_graph_check_whole and hpfc_graph_validate
 *     (the whole graph's checks that no chunk can make);
 *   - a graph file damaged at each field is refused with its code, and
 *     random damage never reads out of bounds (ASan in CI);
 *   - a mapped graph refuses to grow; a chunk filled from other text than
 *     it was scanned from is refused;
 *   - a graph file of more than a million values an array, mapped, reads
 *     back every value, and its check leaves at most a sliver of it
 *     resident in the process.
 */
#define _GNU_SOURCE
#include <dirent.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "fixtures.h"
#include "gen.h"
#include "graph.h" /* graph_from_file_bytes */
#include "hpfc.h"
#include "pfc_chunked.h"

/* Coordinate c at 10^-shift user units, exactly: "c" for shift 0, else
 * one of "I.FFF" (trailing zeros kept) or "Ce-S". */
static void put_coord(FILE *f, int64_t c, int shift, int style)
{
    if (shift == 0) {
        fprintf(f, " %lld", (long long)c);
        return;
    }
    if (style % 2) {
        fprintf(f, " %llde-%d", (long long)c, shift);
        return;
    }
    int64_t unit = 1;
    for (int k = 0; k < shift; k++)
        unit *= 10;
    uint64_t a = c < 0 ? (uint64_t)-c : (uint64_t)c;
    fprintf(f, " %s%llu.%0*llu", c < 0 ? "-" : "", (unsigned long long)(a / (uint64_t)unit), shift,
            (unsigned long long)(a % (uint64_t)unit));
}

/* The graph's text at 10^-shift units (the same graph, its unit exponent
 * -shift), with the comments, blank lines, blanks and line ends that
 * exercise the reader: CR LF on odd lines, a comment every 7th line. */
static char *decorated_text(const hpfc_graph *g, int shift, int bom, size_t *len)
{
    char *text = NULL;
    FILE *f = open_memstream(&text, len);
    if (!f)
        return NULL;
    if (bom)
        fputs("\xEF\xBB\xBF", f);
    fputs("# a map\n\n  pfc 1  # header\r\n", f);
    size_t line = 0;
    for (size_t v = 0; v < hpfc_graph_vertex_count(g); v++, line++) {
        int64_t x, y;
        hpfc_graph_vertex(g, v, &x, &y);
        fputs(line % 5 == 3 ? "\tv" : "v", f);
        put_coord(f, x, shift, (int)line);
        put_coord(f, y, shift, (int)line / 2);
        if (line % 7 == 0)
            fputs(" # note", f);
        fputs(line % 2 ? "\r\n" : "\n", f);
        if (line % 11 == 0)
            fputs("\n", f);
    }
    for (size_t e = 0; e < hpfc_graph_edge_count(g); e++, line++) {
        uint32_t u, v;
        const int64_t *xy;
        size_t n;
        hpfc_graph_edge(g, e, &u, &v, &xy, &n);
        fprintf(f, "e %u  %u", u, v);
        for (size_t k = 0; k < 2 * n; k++)
            put_coord(f, xy[k], shift, (int)(line + k));
        fputs(line % 3 ? "\n" : " #c\r\n", f);
    }
    fclose(f);
    return text;
}

static char *temp_path(void)
{
    static char path[64];
    snprintf(path, sizeof path, "/tmp/hpfc-chunks-XXXXXX");
    int fd = mkstemp(path);
    if (fd < 0)
        return NULL;
    close(fd);
    return path;
}

static int write_bytes(const char *path, const uint8_t *b, size_t n)
{
    FILE *f = fopen(path, "wb");
    if (!f)
        return -1;
    size_t done = fwrite(b, 1, n, f);
    return fclose(f) == 0 && done == n ? 0 : -1;
}

static long texts, chunked_reads, many_chunks;

/* A text hpfc_pfc_parse reads: the same graph from every chunk count. */
static void check_valid_text(const char *text, size_t len, const char *what)
{
    hpfc_graph *whole = NULL;
    hpfc_diag d;
    int st = hpfc_pfc_parse(text, len, &whole, &d);
    CHECK_EQ_INT(st, HPFC_OK);
    if (st) {
        fprintf(stderr, "%s: %s\n", what, d.message);
        return;
    }
    int64_t box[4];
    CHECK_EQ_INT(hpfc_graph_bounds(whole, box), HPFC_OK);
    texts++;
    for (size_t count = 1; count <= 16; count++) {
        uint8_t *bytes;
        size_t size, chunks;
        st = pfc_chunked_bytes(text, len, count, &bytes, &size, &chunks, &d);
        CHECK_EQ_INT(st, HPFC_OK);
        if (st) {
            fprintf(stderr, "%s in %zu chunks: %s\n", what, count, d.message);
            continue;
        }
        CHECK(chunks >= 1 && chunks <= count);
        chunked_reads++;
        many_chunks += chunks >= 4;
        hpfc_graph *g = NULL;
        CHECK_EQ_INT(graph_from_file_bytes(bytes, size, &g, &d), HPFC_OK);
        CHECK(g && pfc_chunked_same(whole, g));
        int64_t gbox[4];
        CHECK(g && hpfc_graph_bounds(g, gbox) == HPFC_OK && memcmp(box, gbox, sizeof box) == 0);
        hpfc_graph_free(g);
        if (count % 5 == 1) { /* and mapped from a file */
            const char *path = temp_path();
            hpfc_graph *m = NULL;
            CHECK(path && write_bytes(path, bytes, size) == 0);
            CHECK_EQ_INT(path ? hpfc_graph_map_file(path, &m, &d) : -1, HPFC_OK);
            CHECK(m && pfc_chunked_same(whole, m));
            CHECK_EQ_INT(hpfc_graph_add_vertex(m, 0, 0, NULL), m ? HPFC_E_ARG : HPFC_E_ARG);
            hpfc_graph_free(m);
            if (path)
                unlink(path);
        }
        free(bytes);
    }
    hpfc_graph_free(whole);
}

/* A text hpfc_pfc_parse refuses: the chunks refuse it, or its graph fails
 * the whole graph's checks. */
static void check_refused_text(const char *text, size_t len, const char *what)
{
    hpfc_graph *whole = NULL;
    hpfc_diag d;
    int st = hpfc_pfc_parse(text, len, &whole, &d);
    if (!st && hpfc_graph_validate(whole, &d) == HPFC_OK) {
        hpfc_graph_free(whole);
        check_valid_text(text, len, what);
        return;
    }
    hpfc_graph_free(whole);
    texts++;
    for (size_t count = 1; count <= 9; count += 2) {
        uint8_t *bytes;
        size_t size, chunks;
        st = pfc_chunked_bytes(text, len, count, &bytes, &size, &chunks, &d);
        chunked_reads++;
        if (st)
            continue;
        hpfc_graph *g = NULL;
        st = graph_from_file_bytes(bytes, size, &g, &d);
        if (!st) {
            st = hpfc_graph_check_whole(g, &d);
            if (!st)
                st = hpfc_graph_validate(g, &d);
        }
        if (!st)
            fprintf(stderr, "%s in %zu chunks: a refused text passed\n", what, count);
        CHECK(st != HPFC_OK);
        hpfc_graph_free(g);
        free(bytes);
    }
}

static int read_fixture(const char *path, char **text, size_t *len)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return -1;
    *text = NULL, *len = 0;
    FILE *m = open_memstream(text, len);
    for (int c; (c = fgetc(f)) != EOF;)
        fputc(c, m);
    fclose(m);
    fclose(f);
    return 0;
}

static void check_fixtures(const char *sub)
{
    const char *root = getenv("HPFC_TEST_DATA");
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", root ? root : "tests/data", sub);
    DIR *dir = opendir(path);
    CHECK(dir != NULL);
    for (struct dirent *de; dir && (de = readdir(dir));) {
        if (!fixture_has_suffix(de->d_name, ".pfc"))
            continue;
        char *text;
        size_t len;
        snprintf(path, sizeof path, "%s/%s/%s", root ? root : "tests/data", sub, de->d_name);
        CHECK(read_fixture(path, &text, &len) == 0);
        check_refused_text(text, len, de->d_name);
        free(text);
    }
    if (dir)
        closedir(dir);
}

static void check_generated(const hpfc_graph *g, const char *what)
{
    for (int shift = 0; shift <= 3; shift += 3) {
        size_t len;
        char *text = decorated_text(g, shift, shift == 3, &len);
        CHECK(text != NULL);
        if (text)
            check_valid_text(text, len, what);
        free(text);
    }
}

/* Texts the chunks must refuse, each in every cut. */
static void check_hand_made(void)
{
    static const char *bad[] = {
        "pfc 1\nv 0 0\nv 1 0\ne 0 2\nv 2 2\n",                /* a vertex named before it is defined */
        "pfc 1\nv 0 0\nv 1 0\nv 1 1\ne 0 1\npfc 1\ne 1 2\n",   /* a second header */
        "v 0 0\npfc 1\nv 1 0\ne 0 1\n",                        /* a record before the header */
        "pfc 1\nv 0 0\nv 1 0\ne 0 1 0.5 0.5 0.5 0.5\n",        /* a zero-length segment inside */
        "pfc 1\nv 0 0\nv 1 0\ne 0 0 1 1\n",                    /* a loop of one interior point */
        "pfc 1\nv 0 0\nv 0 0\nv 1 1\ne 0 2\ne 1 2\n",           /* a duplicate vertex */
        "pfc 1\nv 0 0\nv 1 1\nv 5 5\ne 0 1\n",                 /* an isolated vertex */
        "pfc 1\nv 0 0\nv 1 1\n",                               /* no edge */
        "pfc 1\nv 0 0\nv 1 0.0000000000000000000000000000001\ne 0 1\n", /* 31 digits */
        "pfc 1\nv 0 0\nv 1099511627777 0\ne 0 1\n",            /* past 2^40 */
        "pfc 1\nv 0 0\nv 1 1e-12\ne 0 1\nv 2000 0\ne 0 2\n",    /* past 2^40 once scaled by the last digits */
        "\n# nothing\n",
        "",
        "pfc 1\nv 0 0\nv 2 0\nv 1 -1\nv 1 1\ne 0 1\ne 2 3\n",   /* crossing edges */
    };
    for (size_t k = 0; k < sizeof bad / sizeof *bad; k++) {
        char what[32];
        snprintf(what, sizeof what, "hand-made %zu", k);
        hpfc_graph *g = NULL;
        hpfc_diag d;
        int st = hpfc_pfc_parse(bad[k], strlen(bad[k]), &g, &d);
        CHECK(st != HPFC_OK || hpfc_graph_validate(g, &d) != HPFC_OK);
        hpfc_graph_free(g);
        check_refused_text(bad[k], strlen(bad[k]), what);
    }
    /* a chunk filled from other text than it was scanned from */
    const char *a = "pfc 1\nv 0 0\nv 1 0\ne 0 1\n", *b = "pfc 1\nv 0 0\nv 1 0\nv 2 0\ne 0 1\n";
    hpfc_pfc_chunk scan;
    hpfc_diag d;
    CHECK_EQ_INT(hpfc_pfc_chunk_scan(a, strlen(a), 0, strlen(a), &scan, &d), HPFC_OK);
    int64_t vxy[8], pts[2];
    uint32_t eu[2], ev[2];
    uint64_t eoff[2];
    hpfc_pfc_fill f = {.vxy = vxy, .eu = eu, .ev = ev, .eoff = eoff, .pts = pts};
    CHECK_EQ_INT(hpfc_pfc_chunk_fill(b, strlen(b), 0, strlen(b), &scan, &f, &d), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_pfc_chunk_fill(a, strlen(a), 0, strlen(a), &scan, &f, &d), HPFC_OK);
    CHECK(vxy[2] == 1 && eu[0] == 0 && ev[0] == 1 && eoff[0] == 0 && f.box[2] == 1);
    /* chunks that do not start or end at a line start */
    CHECK_EQ_INT(hpfc_pfc_chunk_scan(a, strlen(a), 1, strlen(a), &scan, &d), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_pfc_chunk_scan(a, strlen(a), 0, 3, &scan, &d), HPFC_E_ARG);
    size_t at[4];
    CHECK_EQ_INT(hpfc_pfc_chunk_bounds(a, strlen(a), 0, at), 0);
    CHECK_EQ_INT(hpfc_pfc_chunk_bounds(a, strlen(a), 3, at), 3);
    CHECK(at[0] == 0 && at[1] == 12 && at[2] == 18 && at[3] == strlen(a)); /* at line starts */
    size_t many[40];
    size_t n = hpfc_pfc_chunk_bounds(a, strlen(a), 24, many);
    CHECK(n == 4 && many[1] == 6 && many[4] == strlen(a)); /* the header's line in the first */
}

/* A valid graph file's bytes, each field damaged: its code. */
static void check_damaged_file(void)
{
    hpfc_graph *g = NULL;
    CHECK_EQ_INT(gen_polyline(7, 300, 1000, 0.5, &g), HPFC_OK);
    size_t len;
    char *text = decorated_text(g, 0, 0, &len);
    uint8_t *good;
    size_t size, chunks;
    hpfc_diag d;
    CHECK_EQ_INT(pfc_chunked_bytes(text, len, 4, &good, &size, &chunks, &d), HPFC_OK);
    hpfc_graph_file_layout l;
    uint64_t ne = hpfc_graph_edge_count(g), nv = hpfc_graph_vertex_count(g), np;
    memcpy(&np, good + 32, 8);
    CHECK_EQ_INT(hpfc_graph_file_layout_of(nv, ne, np, 0, &l), HPFC_OK);
    CHECK_EQ_INT(l.size, size);
    size_t straight = 0; /* an edge of fewer than 2 interior points, made a loop below */
    for (uint32_t u, v; straight < ne; straight++) {
        const int64_t *xy;
        size_t n;
        hpfc_graph_edge(g, straight, &u, &v, &xy, &n);
        if (n < 2)
            break;
    }
    CHECK(straight < ne);
    uint32_t straight_u;
    memcpy(&straight_u, good + l.eu + 4 * straight, 4);
    uint8_t *b = malloc(size + 8);
    struct {
        size_t at;
        uint64_t value;
        int bytes, code;
    } cases[] = {
        {0, 'X', 1, HPFC_E_MAGIC},
        {8, 0x0D0C0B0A, 4, HPFC_E_MAGIC},                    /* the other byte order */
        {12, 31, 4, HPFC_E_HEADER},                          /* unit past 10^31 */
        {44, 1, 1, HPFC_E_HEADER},                           /* reserved */
        {16, nv + 1, 8, HPFC_E_TRUNCATED},                   /* counts the size does not hold */
        {24, UINT64_MAX, 8, HPFC_E_HEADER},
        {(size_t)l.vxy + 8, (uint64_t)HPFC_COORD_MAX + 1, 8, HPFC_E_EXTENT},
        {(size_t)l.pts, (uint64_t)-HPFC_COORD_MAX - 1, 8, np ? HPFC_E_EXTENT : HPFC_OK},
        {(size_t)l.eu + 4, nv, 4, HPFC_E_VERTEX_INDEX},
        {(size_t)l.ev, UINT32_MAX, 4, HPFC_E_VERTEX_INDEX},
        {(size_t)l.ev + 4 * straight, straight_u, 4, HPFC_E_LOOP_INTERIOR},
        {(size_t)l.eoff, 1, 8, HPFC_E_CORRUPT},
        {(size_t)l.eoff + 8 * ne, np + 1, 8, HPFC_E_CORRUPT},
        {(size_t)l.eoff + 8 * (ne / 2), np + 1, 8, HPFC_E_CORRUPT}, /* out of order */
    };
    for (size_t k = 0; k < sizeof cases / sizeof *cases; k++) {
        memcpy(b, good, size);
        memcpy(b + cases[k].at, &cases[k].value, (size_t)cases[k].bytes);
        hpfc_graph *m = NULL;
        int st = graph_from_file_bytes(b, size, &m, &d);
        if (st != cases[k].code)
            fprintf(stderr, "damage %zu: %d (%s)\n", k, st, d.message);
        CHECK_EQ_INT(st, cases[k].code);
        CHECK((m != NULL) == (st == HPFC_OK));
        hpfc_graph_free(m);
    }
    memcpy(b, good, size);
    hpfc_graph *none = NULL;
    CHECK_EQ_INT(graph_from_file_bytes(b, size - 8, &none, &d), HPFC_E_TRUNCATED);
    CHECK_EQ_INT(graph_from_file_bytes(b, 40, &none, &d), HPFC_E_MAGIC);
    CHECK(none == NULL);
    /* random damage: a verdict, and a graph whose every value is read */
    gen_rng rng;
    gen_rng_seed(&rng, 11);
    long opened = 0;
    for (int round = 0; round < 3000; round++) {
        memcpy(b, good, size);
        for (int flips = 1 + (int)gen_rng_below(&rng, 3); flips > 0; flips--)
            b[gen_rng_below(&rng, size)] ^= (uint8_t)(1u << gen_rng_below(&rng, 8));
        hpfc_graph *m = NULL;
        if (graph_from_file_bytes(b, size, &m, &d) == HPFC_OK) {
            opened++;
            int64_t box[4];
            hpfc_graph_bounds(m, box);
            hpfc_graph_check_whole(m, &d);
            hpfc_graph_validate(m, &d);
        }
        hpfc_graph_free(m);
    }
    CHECK(opened > 0 && opened < 3000);
    free(b);
    free(good);
    free(text);
    hpfc_graph_free(g);
}

/* The tree built from the mapped graph is the parsed graph's. */
/* Pages resident in this process (/proc/self/statm), 0 when unknown. */
static long resident_pages(void)
{
    FILE *f = fopen("/proc/self/statm", "r");
    long size = 0, resident = 0;
    if (f) {
        if (fscanf(f, "%ld %ld", &size, &resident) != 2)
            resident = 0;
        fclose(f);
    }
    return resident;
}

/* A path of 1.2 million edges, each with an interior point, written as a
 * graph file and mapped: the check goes over it a stretch at a time and
 * hands each back, so the process holds a sliver of the file's pages, yet
 * every value reads back (the pages come again from the page cache). */
static void check_large_mapping(void)
{
    enum { EDGES = 1200000 };
    hpfc_graph *g = NULL;
    CHECK_EQ_INT(hpfc_graph_create(&g), HPFC_OK);
    int st = g ? HPFC_OK : HPFC_E_NOMEM;
    for (uint32_t v = 0; !st && v <= EDGES; v++)
        st = hpfc_graph_add_vertex(g, 2 * (int64_t)v, (int64_t)(v % 7), NULL);
    for (uint32_t e = 0; !st && e < EDGES; e++) {
        int64_t mid[2] = {2 * (int64_t)e + 1, -1 - (int64_t)(e % 5)};
        st = hpfc_graph_add_edge(g, e, e + 1, mid, 1, NULL);
    }
    CHECK_EQ_INT(st, HPFC_OK);
    hpfc_graph_file_layout l;
    CHECK_EQ_INT(hpfc_graph_file_layout_of(EDGES + 1, EDGES, EDGES, 0, &l), HPFC_OK);
    uint8_t *b = st ? NULL : calloc(1, (size_t)l.size);
    const char *path = temp_path();
    CHECK(b && path);
    if (b && path) {
        memcpy(b, l.header, sizeof l.header);
        memcpy(b + l.vxy, g->vxy, 16 * (size_t)(EDGES + 1));
        memcpy(b + l.eu, g->eu, 4 * (size_t)EDGES);
        memcpy(b + l.ev, g->ev, 4 * (size_t)EDGES);
        memcpy(b + l.eoff, g->eoff, 8 * (size_t)(EDGES + 1));
        memcpy(b + l.pts, g->pts, 16 * (size_t)EDGES);
        CHECK_EQ_INT(write_bytes(path, b, (size_t)l.size), 0);
        free(b);
        b = NULL;
        long before = resident_pages(), page = sysconf(_SC_PAGESIZE);
        hpfc_graph *m = NULL;
        hpfc_diag d;
        CHECK_EQ_INT(hpfc_graph_map_file(path, &m, &d), HPFC_OK);
        /* a quarter: AddressSanitizer reads a shadow byte for every 8
         * bytes the check reads, which stays resident (an eighth) */
        long grown = resident_pages() - before;
        if (before && grown * page > (long)(l.size / 4))
            fprintf(stderr, "a %llu-byte graph file left %ld pages resident\n",
                    (unsigned long long)l.size, grown);
        CHECK(before && grown * page <= (long)(l.size / 4));
        CHECK(m && pfc_chunked_same(g, m));
        hpfc_graph_free(m);
    }
    free(b);
    if (path)
        unlink(path);
    hpfc_graph_free(g);
}

static void check_same_tree(void)
{
    hpfc_graph *g = NULL;
    CHECK_EQ_INT(gen_delaunay(3, 600, 4000, 0.2, &g), HPFC_OK);
    size_t len;
    char *text = decorated_text(g, 2, 0, &len);
    hpfc_graph *whole = NULL, *m = NULL;
    hpfc_diag d;
    uint8_t *bytes;
    size_t size, chunks;
    CHECK_EQ_INT(hpfc_pfc_parse(text, len, &whole, &d), HPFC_OK);
    CHECK_EQ_INT(pfc_chunked_bytes(text, len, 5, &bytes, &size, &chunks, &d), HPFC_OK);
    const char *path = temp_path();
    CHECK(path && write_bytes(path, bytes, size) == 0);
    CHECK_EQ_INT(hpfc_graph_map_file(path, &m, &d), HPFC_OK);
    hpfc_build_params p;
    hpfc_build_params_default(&p);
    p.root_cols = p.root_rows = 8;
    hpfc_tree *a = NULL, *t = NULL;
    CHECK_EQ_INT(hpfc_build(whole, &p, &a, &d), HPFC_OK);
    CHECK_EQ_INT(hpfc_build(m, &p, &t, &d), HPFC_OK);
    hpfc_write_options o = {.face_labels = 1, .geometry = whole};
    uint8_t *fa = NULL, *ft = NULL;
    size_t na = 0, nt = 0;
    CHECK_EQ_INT(hpfc_tree_serialize(a, &o, &fa, &na, &d), HPFC_OK);
    o.geometry = m;
    CHECK_EQ_INT(hpfc_tree_serialize(t, &o, &ft, &nt, &d), HPFC_OK);
    CHECK(na > 0 && na == nt && memcmp(fa, ft, na) == 0);
    hpfc_free(fa), hpfc_free(ft);
    hpfc_tree_free(a), hpfc_tree_free(t);
    hpfc_graph_free(m), hpfc_graph_free(whole), hpfc_graph_free(g);
    if (path)
        unlink(path);
    free(bytes);
    free(text);
}

int main(void)
{
    check_fixtures("valid");
    check_fixtures("invalid");
    check_hand_made();
    for (int k = 0; k < GEN_SPECIAL_COUNT; k++) {
        hpfc_graph *g = NULL;
        CHECK_EQ_INT(gen_special(k, &g), HPFC_OK);
        check_generated(g, gen_special_name(k));
        hpfc_graph_free(g);
    }
    for (uint64_t seed = 1; seed <= 4; seed++) {
        hpfc_graph *g = NULL;
        CHECK_EQ_INT(gen_delaunay(seed, 50 * seed, 1000, 0.2, &g), HPFC_OK);
        check_generated(g, "delaunay");
        hpfc_graph_free(g);
        CHECK_EQ_INT(gen_polyline(seed, 80 * seed, 1000, 0.5, &g), HPFC_OK);
        check_generated(g, "polyline");
        hpfc_graph_free(g);
    }
    check_damaged_file();
    check_large_mapping();
    check_same_tree();
    CHECK(many_chunks > 400); /* the reads were cut, most in 4 chunks or more */
    printf("pfc_chunks: %ld texts, %ld chunked reads (%ld in 4 chunks or more), %ld checks, %d failed\n",
           texts, chunked_reads, many_chunks, check_count, check_failures);
    return check_failures ? 1 : 0;
}
