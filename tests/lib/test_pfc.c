/*
 * Tests of the .pfc reader (spec/pfc-format.md): valid inputs read back
 * exactly, every rejection with its status code and line, hostile numbers,
 * big inputs, and the fixture files of $HPFC_TEST_DATA/{valid,invalid}.
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "fixtures.h"
#include "hpfc.h"

/* ------------------------------------------------------------------------
 * Helpers
 * ------------------------------------------------------------------------ */

/* Counts one check; on failure prints the caller's line and the input. */
static void check_at(int ok, int src_line, const char *text, const char *what)
{
    check_count++;
    if (!ok) {
        check_failures++;
        fprintf(stderr, "test_pfc.c:%d: %s\n  input: \"%.200s\"\n", src_line, what, text);
    }
}

/* Parses text that must be valid; returns the graph (NULL on failure). */
static hpfc_graph *parse_ok_at(int src_line, const char *text, size_t len)
{
    hpfc_graph *g = NULL;
    hpfc_diag diag;
    int st = hpfc_pfc_parse(text, len, &g, &diag);
    if (st != HPFC_OK)
        fprintf(stderr, "  unexpected failure %d: %s\n", st, diag.message);
    check_at(st == HPFC_OK && g != NULL, src_line, text, "expected a successful parse");
    check_at(diag.status == HPFC_OK, src_line, text, "diag.status should be HPFC_OK");
    return g;
}
#define PARSE_OK(text) parse_ok_at(__LINE__, (text), strlen(text))

/* Parses text that must fail with `code` at `line`; checks the message is
 * one line starting with "line N: " and that no graph comes back. */
static void expect_error_at(int src_line, const char *text, size_t len, int code,
                            uint32_t line)
{
    hpfc_graph *g = (hpfc_graph *)&g;   /* must be reset to NULL */
    hpfc_diag diag;
    char prefix[32];
    int st = hpfc_pfc_parse(text, len, &g, &diag);
    if (st != code || diag.line != line)
        fprintf(stderr, "  got status %d line %u (\"%s\"), expected %d line %u\n", st,
                (unsigned)diag.line, diag.message, code, (unsigned)line);
    check_at(st == code, src_line, text, "wrong status code");
    check_at(diag.status == code, src_line, text, "diag.status differs from the status");
    check_at(diag.line == line, src_line, text, "wrong diag.line");
    check_at(g == NULL, src_line, text, "*out must be NULL on failure");
    snprintf(prefix, sizeof prefix, "line %u: ", (unsigned)line);
    check_at(strncmp(diag.message, prefix, strlen(prefix)) == 0, src_line, text,
             "message must start with \"line N: \"");
    check_at(strchr(diag.message, '\n') == NULL && strchr(diag.message, '\r') == NULL,
             src_line, text, "message must be one line");
    hpfc_graph_free(g == (hpfc_graph *)&g ? NULL : g);
}
#define EXPECT_ERR(text, code, line) expect_error_at(__LINE__, (text), strlen(text), (code), (line))
/* For string literals with embedded NUL bytes. */
#define EXPECT_ERR_LIT(lit, code, line) expect_error_at(__LINE__, (lit), sizeof(lit) - 1, (code), (line))

static void check_vertex(const hpfc_graph *g, size_t i, int64_t x, int64_t y)
{
    int64_t gx, gy;
    hpfc_graph_vertex(g, i, &gx, &gy);
    CHECK_EQ_INT(gx, x);
    CHECK_EQ_INT(gy, y);
}

/* Growable string for generated inputs. */
typedef struct strbuf {
    char *p;
    size_t n, cap;
} strbuf;

static void sb_add(strbuf *s, const char *text)
{
    size_t k = strlen(text);
    if (s->n + k + 1 > s->cap) {
        size_t cap = s->cap ? s->cap : 4096;
        while (cap < s->n + k + 1)
            cap *= 2;
        char *p = realloc(s->p, cap);
        if (!p) {
            fprintf(stderr, "out of memory\n");
            exit(EXIT_FAILURE);
        }
        s->p = p;
        s->cap = cap;
    }
    memcpy(s->p + s->n, text, k + 1);
    s->n += k;
}

/* ------------------------------------------------------------------------
 * Valid inputs
 * ------------------------------------------------------------------------ */

static void test_basic(void)
{
    hpfc_graph *g = PARSE_OK("pfc 1\nv 0 0\nv 10 0\nv 10 10\ne 0 1\ne 1 2 20 5\ne 2 0\n");
    if (!g)
        return;
    CHECK_EQ_INT(hpfc_graph_vertex_count(g), 3);
    CHECK_EQ_INT(hpfc_graph_edge_count(g), 3);
    CHECK_EQ_INT(hpfc_graph_unit_exp10(g), 0);
    check_vertex(g, 0, 0, 0);
    check_vertex(g, 1, 10, 0);
    check_vertex(g, 2, 10, 10);
    uint32_t u, v;
    const int64_t *xy;
    size_t n;
    hpfc_graph_edge(g, 1, &u, &v, &xy, &n);
    CHECK_EQ_INT(u, 1);
    CHECK_EQ_INT(v, 2);
    CHECK_EQ_INT(n, 1);
    if (n == 1) {
        CHECK_EQ_INT(xy[0], 20);
        CHECK_EQ_INT(xy[1], 5);
    }
    hpfc_graph_edge(g, 2, &u, &v, &xy, &n);
    CHECK_EQ_INT(u, 2);
    CHECK_EQ_INT(v, 0);
    CHECK_EQ_INT(n, 0);
    /* line numbers of the records */
    CHECK_EQ_INT(hpfc_graph_vertex_line(g, 0), 2);
    CHECK_EQ_INT(hpfc_graph_vertex_line(g, 2), 4);
    CHECK_EQ_INT(hpfc_graph_edge_line(g, 0), 5);
    CHECK_EQ_INT(hpfc_graph_edge_line(g, 2), 7);
    hpfc_graph_free(g);
}

/* Exact decimal scaling: d = the most significant fractional digits. */
static void test_decimals(void)
{
    hpfc_graph *g = PARSE_OK("pfc 1\nv 0.5 2\nv 0 0\ne 0 1\n");
    if (g) {
        CHECK_EQ_INT(hpfc_graph_unit_exp10(g), -1);
        check_vertex(g, 0, 5, 20);
        hpfc_graph_free(g);
    }
    /* trailing zeros do not count: 1.250 has 2 significant fractional digits */
    g = PARSE_OK("pfc 1\nv 1.250 0\nv 0.000 3\ne 0 1\n");
    if (g) {
        CHECK_EQ_INT(hpfc_graph_unit_exp10(g), -2);
        check_vertex(g, 0, 125, 0);
        check_vertex(g, 1, 0, 300);
        hpfc_graph_free(g);
    }
    /* exponents shift the digits; signs; leading zeros; -0 */
    g = PARSE_OK("pfc 1\nv 1.5e-1 -2.5E+1\nv 120e-1 +007\nv -0 1E3\n"
                 "e 0 1\ne 1 2 -0.0 0.25e1\n");
    if (g) {
        CHECK_EQ_INT(hpfc_graph_unit_exp10(g), -2);
        check_vertex(g, 0, 15, -2500);
        check_vertex(g, 1, 1200, 700);
        check_vertex(g, 2, 0, 100000);
        uint32_t u, v;
        const int64_t *xy;
        size_t n;
        hpfc_graph_edge(g, 1, &u, &v, &xy, &n);
        CHECK_EQ_INT(n, 1);
        if (n == 1) {
            CHECK_EQ_INT(xy[0], 0);
            CHECK_EQ_INT(xy[1], 250);
        }
        hpfc_graph_free(g);
    }
    /* integers up to 2^31 are exact, and the lattice takes up to 2^40 */
    g = PARSE_OK("pfc 1\nv 2147483648 -2147483648\nv 1099511627776 -1099511627776\ne 0 1\n");
    if (g) {
        check_vertex(g, 0, INT64_C(2147483648), -INT64_C(2147483648));
        check_vertex(g, 1, INT64_C(1099511627776), -INT64_C(1099511627776));
        hpfc_graph_free(g);
    }
    /* 13 fractional digits, and 30 (the finest supported unit) */
    g = PARSE_OK("pfc 1\nv 0.0000000000001 0\nv 0 1e-12\ne 0 1\n");
    if (g) {
        CHECK_EQ_INT(hpfc_graph_unit_exp10(g), -13);
        check_vertex(g, 0, 1, 0);
        check_vertex(g, 1, 0, 10);
        hpfc_graph_free(g);
    }
    g = PARSE_OK("pfc 1\nv 1e-30 0\nv 0 7e-30\ne 0 1\n");
    if (g) {
        CHECK_EQ_INT(hpfc_graph_unit_exp10(g), -30);
        check_vertex(g, 1, 0, 7);
        hpfc_graph_free(g);
    }
    /* many digits are fine while the value fits: trailing zeros go away */
    g = PARSE_OK("pfc 1\nv 5.00000000000000000000000000000000000000000000000000 0\n"
                 "v 0000000000000000000000000000000000000000000000000001 0\ne 0 1\n");
    if (g) {
        CHECK_EQ_INT(hpfc_graph_unit_exp10(g), 0);
        check_vertex(g, 0, 5, 0);
        check_vertex(g, 1, 1, 0);
        hpfc_graph_free(g);
    }
}

/* Comments, blank lines, CRLF, tabs, BOM, no final newline. */
static void test_layout(void)
{
    const char *text =
        "# a triangle\r\n"
        "\r\n"
        "pfc\t1   # header\r\n"
        "   \t\r\n"
        "v 0 0\r\n"
        "\tv\t4\t0\t\r\n"
        "v 0 4#glued comment\r\n"
        "# e 9 9\r\n"
        "e 0 1 # café ✓\r\n"
        "e 1 2\r\n"
        "e 2 0";
    hpfc_graph *g = PARSE_OK(text);
    if (g) {
        CHECK_EQ_INT(hpfc_graph_vertex_count(g), 3);
        CHECK_EQ_INT(hpfc_graph_edge_count(g), 3);
        check_vertex(g, 1, 4, 0);
        check_vertex(g, 2, 0, 4);
        CHECK_EQ_INT(hpfc_graph_vertex_line(g, 1), 6);
        CHECK_EQ_INT(hpfc_graph_edge_line(g, 2), 11);
        hpfc_graph_free(g);
    }
    /* CRLF line numbers in errors */
    EXPECT_ERR("pfc 1\r\nv 0 0\r\n\r\nv 1 x\r\n", HPFC_E_PFC_SYNTAX, 4);
    /* a UTF-8 byte-order mark before the header is skipped */
    g = PARSE_OK("\xEF\xBB\xBFpfc 1\nv 0 0\nv 1 1\ne 0 1\n");
    hpfc_graph_free(g);
    /* a lone CR at the very end is a line terminator too */
    g = PARSE_OK("pfc 1\nv 0 0\nv 1 1\ne 0 1\r");
    hpfc_graph_free(g);
}

/* Loops, multi-edges, dead ends, several components. */
static void test_topologies(void)
{
    hpfc_graph *g = PARSE_OK("pfc 1\n"
                             "v 0 0\nv 4 0\n"
                             "e 0 1\ne 0 1 2 2\ne 1 0 2 -2\n"   /* three parallel edges */
                             "e 0 0 -1 1 -1 -1\n"                /* loop, 2 interior points */
                             "v 2 1\ne 0 2\n"                    /* dead end */
                             "v 10 10\nv 11 10\nv 11 11\ne 3 4\ne 4 5\ne 5 3\n");
    if (g) {
        CHECK_EQ_INT(hpfc_graph_vertex_count(g), 6);
        CHECK_EQ_INT(hpfc_graph_edge_count(g), 8);
        uint32_t u, v;
        const int64_t *xy;
        size_t n;
        hpfc_graph_edge(g, 3, &u, &v, &xy, &n);
        CHECK_EQ_INT(u, 0);
        CHECK_EQ_INT(v, 0);
        CHECK_EQ_INT(n, 2);
        if (n == 2) {
            CHECK_EQ_INT(xy[0], -1);
            CHECK_EQ_INT(xy[1], 1);
            CHECK_EQ_INT(xy[2], -1);
            CHECK_EQ_INT(xy[3], -1);
        }
        hpfc_graph_free(g);
    }
}

/* Bad arguments, and an optional diag. */
static void test_arguments(void)
{
    hpfc_graph *g = (hpfc_graph *)&g;
    CHECK_EQ_INT(hpfc_pfc_parse("x", 1, NULL, NULL), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_pfc_parse(NULL, 1, &g, NULL), HPFC_E_ARG);
    CHECK(g == NULL);
    CHECK_EQ_INT(hpfc_pfc_parse(NULL, 0, &g, NULL), HPFC_E_PFC_VERSION);
    const char *bad = "pfc 1\nv 0 0\ne 0 1\n", *good = "pfc 1\nv 0 0\ne 0 0 1 0 1 1\n";
    CHECK_EQ_INT(hpfc_pfc_parse(bad, strlen(bad), &g, NULL), HPFC_E_VERTEX_INDEX);
    CHECK(g == NULL);
    CHECK_EQ_INT(hpfc_pfc_parse(good, strlen(good), &g, NULL), HPFC_OK);
    CHECK(g != NULL);
    hpfc_graph_free(g);
}

/* ------------------------------------------------------------------------
 * Rejections: status code and line
 * ------------------------------------------------------------------------ */

static void test_header_errors(void)
{
    EXPECT_ERR("", HPFC_E_PFC_VERSION, 1);
    EXPECT_ERR("# only a comment\n\n", HPFC_E_PFC_VERSION, 2);
    EXPECT_ERR("v 0 0\nv 1 1\ne 0 1\n", HPFC_E_PFC_VERSION, 1);
    EXPECT_ERR("# comment\n\nhello\n", HPFC_E_PFC_VERSION, 3);
    EXPECT_ERR("pfc 2\nv 0 0\n", HPFC_E_PFC_VERSION, 1);
    EXPECT_ERR("pfc 0\n", HPFC_E_PFC_VERSION, 1);
    EXPECT_ERR("pfc 2 extra\n", HPFC_E_PFC_VERSION, 1);
    EXPECT_ERR("pfc\n", HPFC_E_PFC_SYNTAX, 1);
    EXPECT_ERR("pfc one\n", HPFC_E_PFC_SYNTAX, 1);
    EXPECT_ERR("pfc 1.0\n", HPFC_E_PFC_SYNTAX, 1);
    EXPECT_ERR("pfc 1 1\n", HPFC_E_PFC_SYNTAX, 1);
    EXPECT_ERR("PFC 1\n", HPFC_E_PFC_VERSION, 1);
    EXPECT_ERR("pfc 1\nv 0 0\nv 1 1\npfc 1\ne 0 1\n", HPFC_E_PFC_VERSION, 4);
}

static void test_record_errors(void)
{
    EXPECT_ERR("pfc 1\nv 0 0\nx 1 2\n", HPFC_E_PFC_SYNTAX, 3);
    EXPECT_ERR("pfc 1\nV 0 0\n", HPFC_E_PFC_SYNTAX, 2);
    EXPECT_ERR("pfc 1\nvertex 0 0\n", HPFC_E_PFC_SYNTAX, 2);
    EXPECT_ERR("pfc 1\nv 0\n", HPFC_E_PFC_SYNTAX, 2);
    EXPECT_ERR("pfc 1\nv\n", HPFC_E_PFC_SYNTAX, 2);
    EXPECT_ERR("pfc 1\nv 0 0 0\n", HPFC_E_PFC_SYNTAX, 2);
    EXPECT_ERR("pfc 1\nv 0 0\nv 1 0\ne 0\n", HPFC_E_PFC_SYNTAX, 4);
    EXPECT_ERR("pfc 1\nv 0 0\nv 1 0\ne\n", HPFC_E_PFC_SYNTAX, 4);
    EXPECT_ERR("pfc 1\nv 0 0\nv 1 0\ne 0 1 5\n", HPFC_E_PFC_SYNTAX, 4);
    EXPECT_ERR("pfc 1\nv 0 0\nv 1 0\ne 0 1 5 5 6\n", HPFC_E_PFC_SYNTAX, 4);
    EXPECT_ERR("pfc 1\nv 0 0\nv 1 0\ne -0 1\n", HPFC_E_PFC_SYNTAX, 4);
    EXPECT_ERR("pfc 1\nv 0 0\nv 1 0\ne +0 1\n", HPFC_E_PFC_SYNTAX, 4);
    EXPECT_ERR("pfc 1\nv 0 0\nv 1 0\ne 0 1.0\n", HPFC_E_PFC_SYNTAX, 4);
    EXPECT_ERR("pfc 1\nv 0 0\nv 1 0\ne 0 1e0\n", HPFC_E_PFC_SYNTAX, 4);
    EXPECT_ERR("pfc 1\nv 0 0\nv 1 0\ne 0 1 2 x\n", HPFC_E_PFC_SYNTAX, 4);
    EXPECT_ERR("pfc 1\nv 0 0\nv 1 0\ne 0 1\n e 1 0 1 \r 1\n", HPFC_E_PFC_SYNTAX, 5);
    /* field separators are spaces and tabs only */
    EXPECT_ERR("pfc 1\nv 0\v0\n", HPFC_E_PFC_SYNTAX, 2);
    EXPECT_ERR("pfc 1\nv 0\xC2\xA0" "0\n", HPFC_E_PFC_SYNTAX, 2);
}

/* Every malformed number is a syntax error on its line. */
static void test_number_syntax(void)
{
    static const char *const bad[] = {
        "nan", "NaN", "inf", "-inf", "infinity", "0x10", "0x1p3", "1.", ".5", "-.5",
        "--1", "+-1", "-+1", "+", "-", "1e", "1e+", "1E-", "e5", "1.5.2", "1,5",
        "1e5.5", "1ee5", "1_000", "\xD9\xA1", "１", "0b1", "1d", "1f", "1e5e5", ".",
        "1..2", "- 1",
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        char text[128];
        snprintf(text, sizeof text, "pfc 1\nv 0 0\nv 1 %s\ne 0 1\n", bad[k]);
        EXPECT_ERR(text, HPFC_E_PFC_SYNTAX, 3);
        snprintf(text, sizeof text, "pfc 1\nv 0 0\nv 1 0\n\ne 0 1 %s 7\n", bad[k]);
        EXPECT_ERR(text, HPFC_E_PFC_SYNTAX, 5);
    }
}

static void test_index_errors(void)
{
    EXPECT_ERR("pfc 1\nv 0 0\nv 1 0\ne 0 2\n", HPFC_E_VERTEX_INDEX, 4);
    EXPECT_ERR("pfc 1\nv 0 0\nv 1 0\ne 7 0 3 3\n", HPFC_E_VERTEX_INDEX, 4);
    EXPECT_ERR("pfc 1\nv 0 0\nv 1 0\ne 0 99999999999999999999999999\n", HPFC_E_VERTEX_INDEX, 4);
    EXPECT_ERR("pfc 1\nv 0 0\nv 1 0\ne 0 4294967295\n", HPFC_E_VERTEX_INDEX, 4);
    /* forward reference: vertices must come before the edges naming them */
    EXPECT_ERR("pfc 1\nv 0 0\ne 0 1\nv 1 0\n", HPFC_E_VERTEX_INDEX, 3);
    EXPECT_ERR("pfc 1\ne 0 1\n", HPFC_E_VERTEX_INDEX, 2);

    /* the message names the vertex and the count */
    hpfc_graph *g;
    hpfc_diag diag;
    const char *text = "pfc 1\nv 0 0\nv 1 0\nv 2 0\nv 3 0\nv 4 0\ne 12 0\n";
    CHECK_EQ_INT(hpfc_pfc_parse(text, strlen(text), &g, &diag), HPFC_E_VERTEX_INDEX);
    CHECK(strcmp(diag.message, "line 7: edge names vertex 12 but only 5 vertices are defined") == 0);
    CHECK_EQ_INT(diag.edge[0], 0);
}

static void test_local_geometry_errors(void)
{
    /* loops need two interior points */
    EXPECT_ERR("pfc 1\nv 0 0\nv 1 0\ne 0 1\ne 1 1\n", HPFC_E_LOOP_INTERIOR, 5);
    EXPECT_ERR("pfc 1\nv 0 0\nv 1 0\ne 0 1\ne 1 1 5 5\n", HPFC_E_LOOP_INTERIOR, 5);
    /* zero-length segments: u = first interior point, interior, last = v,
     * and straight edges between vertices at one point */
    EXPECT_ERR("pfc 1\nv 0 0\nv 1 0\ne 0 1 0 0 1 1\n", HPFC_E_ZERO_LENGTH, 4);
    EXPECT_ERR("pfc 1\nv 0 0\nv 1 0\ne 0 1 2 2 2 2\n", HPFC_E_ZERO_LENGTH, 4);
    EXPECT_ERR("pfc 1\nv 0 0\nv 1 0\ne 0 1 2 2 1 0\n", HPFC_E_ZERO_LENGTH, 4);
    EXPECT_ERR("pfc 1\nv 0 0\nv 1 0\ne 0 1\ne 0 0 1 1 1 1\n", HPFC_E_ZERO_LENGTH, 5);
    EXPECT_ERR("pfc 1\nv 0 0\nv 1 0\ne 0 0 1 1 -1 1 0 0\n", HPFC_E_ZERO_LENGTH, 4);
    /* equality is exact and after scaling: 0.50 = 0.5 = 5e-1 */
    EXPECT_ERR("pfc 1\nv 0 0\nv 1 0\ne 0 1 0.50 3 5e-1 3.000\n", HPFC_E_ZERO_LENGTH, 4);
    EXPECT_ERR("pfc 1\nv 10 0\nv 0 0\ne 0 1 1e1 0\n", HPFC_E_ZERO_LENGTH, 4);
    /* ... but close is not equal */
    hpfc_graph *g = PARSE_OK("pfc 1\nv 0 0\nv 1 0\ne 0 1 0.5 3 0.500001 3\n");
    if (g)
        CHECK_EQ_INT(hpfc_graph_unit_exp10(g), -6);
    hpfc_graph_free(g);

    /* zero-length message with exact coordinates */
    hpfc_diag diag;
    const char *text = "pfc 1\nv 0 0\nv 1 0\ne 0 1 2.5 -0.25 2.50 -0.250\n";
    CHECK_EQ_INT(hpfc_pfc_parse(text, strlen(text), &g, &diag), HPFC_E_ZERO_LENGTH);
    CHECK(strstr(diag.message, "(2.5, -0.25)") != NULL);
    CHECK(diag.has_point && diag.x == 2.5 && diag.y == -0.25);
}

static void test_graph_errors(void)
{
    /* duplicate vertices: the later one's line, the earlier one named */
    EXPECT_ERR("pfc 1\nv 0 0\nv 1 0\nv 2 0\nv 1.0 0\ne 0 1\ne 1 2\ne 2 3 5 5\n",
               HPFC_E_DUPLICATE_POINT, 5);
    EXPECT_ERR("pfc 1\nv 3 3\nv 1 1\nv 2 2\nv 1 1\nv 3 3\ne 0 1\ne 1 2\ne 2 3 5 0\ne 3 4 5 9\n",
               HPFC_E_DUPLICATE_POINT, 5);
    hpfc_graph *g;
    hpfc_diag diag;
    const char *text = "pfc 1\nv 0 0\n\nv 0.5 7\nv 1 0\nv 5e-1 7e0\ne 0 1\ne 1 2\ne 2 3 9 9\n";
    CHECK_EQ_INT(hpfc_pfc_parse(text, strlen(text), &g, &diag), HPFC_E_DUPLICATE_POINT);
    CHECK_EQ_INT(diag.line, 6);
    CHECK(strstr(diag.message, "line 4") != NULL);
    CHECK(strstr(diag.message, "(0.5, 7)") != NULL);

    /* isolated vertex: its own line */
    EXPECT_ERR("pfc 1\nv 0 0\nv 1 0\nv 2 0\ne 0 2 1 1\n", HPFC_E_ISOLATED_VERTEX, 3);
    EXPECT_ERR("pfc 1\nv 0 0\nv 1 0\ne 0 1\nv 5 5\n# end\n", HPFC_E_ISOLATED_VERTEX, 5);
    /* no edge at all: the end of the input */
    EXPECT_ERR("pfc 1\n", HPFC_E_EMPTY, 1);
    EXPECT_ERR("pfc 1\nv 0 0\nv 1 1\n\n# nothing else\n", HPFC_E_EMPTY, 5);
}

/* Encoding: NUL bytes and invalid UTF-8 anywhere, comments included. */
static void test_encoding_errors(void)
{
    EXPECT_ERR_LIT("pfc 1\nv 0 0\nv 1\0 0\ne 0 1\n", HPFC_E_PFC_SYNTAX, 3);
    EXPECT_ERR_LIT("pfc 1\nv 0 0\n# \0\nv 1 0\ne 0 1\n", HPFC_E_PFC_SYNTAX, 3);
    EXPECT_ERR_LIT("pfc 1\0\n", HPFC_E_PFC_SYNTAX, 1);
    EXPECT_ERR_LIT("pfc 1\nv 0 0\nv 1 0\ne 0 1\0", HPFC_E_PFC_SYNTAX, 4);
    static const char *const bad[] = {
        "\xC3\x28", "\xC0\xAF", "\xE0\x80\xAF", "\xED\xA0\x80", "\xF4\x90\x80\x80",
        "\xF8\x88\x80\x80\x80", "\x80", "\xFF", "\xE2\x82", "\xF0\x9F\x98",
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        char text[128];
        snprintf(text, sizeof text, "pfc 1\nv 0 0\nv 1 0\ne 0 1 # %s\n", bad[k]);
        EXPECT_ERR(text, HPFC_E_PFC_SYNTAX, 4);
        snprintf(text, sizeof text, "pfc 1\nv 0 0\nv 1 0\ne 0 1 # ok\n%s\n", bad[k]);
        EXPECT_ERR(text, HPFC_E_PFC_SYNTAX, 5);
    }
    /* valid multi-byte sequences are fine in comments */
    hpfc_graph *g = PARSE_OK("pfc 1 # \xC3\xA9 \xE2\x82\xAC \xF0\x9F\x98\x80 \xF4\x8F\xBF\xBF\n"
                             "v 0 0\nv 1 0\ne 0 1\n");
    hpfc_graph_free(g);
}

/* Hostile numbers: no overflow, no crash, the right code. */
static void test_extent(void)
{
    EXPECT_ERR("pfc 1\nv 0 0\nv 1099511627777 0\ne 0 1\n", HPFC_E_EXTENT, 3);
    EXPECT_ERR("pfc 1\nv 0 0\nv 0 -1099511627777\ne 0 1\n", HPFC_E_EXTENT, 3);
    EXPECT_ERR("pfc 1\nv 0 0\nv 1e400 0\ne 0 1\n", HPFC_E_EXTENT, 3);
    EXPECT_ERR("pfc 1\nv 0 0\nv 1e999999999 0\ne 0 1\n", HPFC_E_EXTENT, 3);
    EXPECT_ERR("pfc 1\nv 0 0\nv 1e99999999999999999999999999999 0\ne 0 1\n", HPFC_E_EXTENT, 3);
    EXPECT_ERR("pfc 1\nv 0 0\nv 1 1\ne 0 1 1e13 0\n", HPFC_E_EXTENT, 4);
    /* fine coordinates make coarse ones too big: scaled by 10^13, 110 > 2^40 */
    EXPECT_ERR("pfc 1\nv 110 0\nv 0.0000000000001 0\ne 0 1\n", HPFC_E_EXTENT, 2);
    /* 10^-999999999 forces d = 999999999, which no other value survives */
    EXPECT_ERR("pfc 1\nv 1e-999999999 0\nv 1 0\ne 0 1\n", HPFC_E_EXTENT, 3);
    EXPECT_ERR("pfc 1\nv 0 0\nv 1 0\ne 0 1 0.12345678901234567890 5\n", HPFC_E_EXTENT, 3);
    /* 19 significant digits never fit, whatever the other coordinates */
    EXPECT_ERR("pfc 1\nv 0 0\nv -0 0.0\ne 0 1 0.1234567890123456789 0\n", HPFC_E_EXTENT, 4);
    /* representable values but finer than 10^-30: an implementation limit */
    EXPECT_ERR("pfc 1\nv 0 0\nv 1e-31 0\ne 0 1\n", HPFC_E_LIMIT, 3);
    EXPECT_ERR("pfc 1\nv 0 0\nv 1e-999999999 2e-999999999\ne 0 1\n", HPFC_E_LIMIT, 3);
    EXPECT_ERR("pfc 1\nv 0 0\nv 1e-9999999999999999999999999 0\ne 0 1\n", HPFC_E_LIMIT, 3);

    /* 50000-digit numbers, integer and fractional */
    strbuf s = {0};
    sb_add(&s, "pfc 1\nv 0 0\nv ");
    for (int k = 0; k < 50000; k++)
        sb_add(&s, k % 7 ? "3" : "0");
    sb_add(&s, " 0\ne 0 1\n");
    EXPECT_ERR(s.p, HPFC_E_EXTENT, 3);
    s.n = 0;
    sb_add(&s, "pfc 1\nv 0 0\nv 0.");
    for (int k = 0; k < 50000; k++)
        sb_add(&s, "0");
    sb_add(&s, "1 0\ne 0 1\n");
    EXPECT_ERR(s.p, HPFC_E_LIMIT, 3);
    s.n = 0;
    sb_add(&s, "pfc 1\nv 0 0\nv 7.");
    for (int k = 0; k < 50000; k++)
        sb_add(&s, "0");
    sb_add(&s, "e0 0\ne 0 1\n");
    hpfc_graph *g = PARSE_OK(s.p);   /* 7.000...0 is just 7 */
    if (g) {
        CHECK_EQ_INT(hpfc_graph_unit_exp10(g), 0);
        check_vertex(g, 1, 7, 0);
    }
    hpfc_graph_free(g);
    free(s.p);
}

/* A line longer than 1 MiB, and a long file (linear time). */
static void test_big_inputs(void)
{
    strbuf s = {0};
    char rec[96];
    sb_add(&s, "pfc 1\nv 0 0\nv 300000 0\ne 0 1");
    for (int k = 1; k <= 150000; k++) {
        snprintf(rec, sizeof rec, " %d.5 %d", 2 * k - 1, 1 + k % 2);
        sb_add(&s, rec);
    }
    sb_add(&s, "\n");
    CHECK(s.n > (size_t)1 << 20);
    hpfc_graph *g = PARSE_OK(s.p);
    if (g) {
        uint32_t u, v;
        const int64_t *xy;
        size_t n;
        CHECK_EQ_INT(hpfc_graph_unit_exp10(g), -1);
        hpfc_graph_edge(g, 0, &u, &v, &xy, &n);
        CHECK_EQ_INT(n, 150000);
        if (n == 150000) {
            CHECK_EQ_INT(xy[0], 15);
            CHECK_EQ_INT(xy[2 * 149999], 2999995);
            CHECK_EQ_INT(xy[2 * 149999 + 1], 10);
        }
        check_vertex(g, 1, 3000000, 0);
    }
    hpfc_graph_free(g);

    /* 200000 segments of a comb: a long file of short records */
    s.n = 0;
    sb_add(&s, "pfc 1\n");
    const int teeth = 100000;
    for (int k = 0; k < teeth; k++) {
        snprintf(rec, sizeof rec, "v %d 0\nv %d 1 # tooth %d\n", k, k, k);
        sb_add(&s, rec);
    }
    for (int k = 0; k < teeth; k++) {
        if (k + 1 < teeth) {
            snprintf(rec, sizeof rec, "e %d %d\n", 2 * k, 2 * k + 2);
            sb_add(&s, rec);
        }
        snprintf(rec, sizeof rec, "e %d %d\n", 2 * k, 2 * k + 1);
        sb_add(&s, rec);
    }
    g = PARSE_OK(s.p);
    if (g) {
        CHECK_EQ_INT(hpfc_graph_vertex_count(g), 2 * teeth);
        CHECK_EQ_INT(hpfc_graph_edge_count(g), 2 * teeth - 1);
        CHECK_EQ_INT(hpfc_graph_edge_line(g, 2 * teeth - 2), 1 + 2 * teeth + 2 * teeth - 1);
        CHECK_EQ_INT(hpfc_graph_validate(g, NULL), HPFC_OK);
    }
    hpfc_graph_free(g);
    /* the same with one duplicate near the end: found by the final sort */
    sb_add(&s, "v 5 1\n");
    EXPECT_ERR(s.p, HPFC_E_DUPLICATE_POINT, 2 * teeth + 2 * teeth - 1 + 2);
    free(s.p);
}

static void test_read_file(void)
{
    hpfc_graph *g = (hpfc_graph *)&g;
    hpfc_diag diag;
    const char *path = "/nonexistent-dir/no-such-file.pfc";
    CHECK_EQ_INT(hpfc_pfc_read_file(path, &g, &diag), HPFC_E_IO);
    CHECK(g == NULL);
    CHECK_EQ_INT(diag.status, HPFC_E_IO);
    CHECK(strstr(diag.message, path) != NULL);
    CHECK(strstr(diag.message, "No such file") != NULL);
    CHECK_EQ_INT(hpfc_pfc_read_file(NULL, &g, &diag), HPFC_E_ARG);
}

/* ------------------------------------------------------------------------
 * Fixture files
 * ------------------------------------------------------------------------ */

/* Reads a fixture and validates it; returns the first failing status. */
static int read_and_validate(const char *path, hpfc_diag *diag)
{
    hpfc_graph *g = NULL;
    int st = hpfc_pfc_read_file(path, &g, diag);
    if (st == HPFC_OK) {
        CHECK(g != NULL);
        st = hpfc_graph_validate(g, diag);
    } else {
        /* parse errors name a line */
        CHECK(g == NULL);
        CHECK(diag->line > 0);
        CHECK(strncmp(diag->message, "line ", 5) == 0);
    }
    hpfc_graph_free(g);
    return st;
}

static int check_pfc_fixture(const char *path, char *detail, size_t n)
{
    hpfc_diag diag;
    int st = read_and_validate(path, &diag);
    snprintf(detail, n, "%s", diag.message);
    return st;
}

static void test_valid_fixtures(const char *root)
{
    check_valid_fixtures(root, ".pfc", check_pfc_fixture, 6);
}

static void test_invalid_fixtures(const char *root)
{
    check_invalid_fixtures(root, ".pfc", check_pfc_fixture, 15);
}

int main(void)
{
    test_basic();
    test_decimals();
    test_layout();
    test_topologies();
    test_arguments();
    test_header_errors();
    test_record_errors();
    test_number_syntax();
    test_index_errors();
    test_local_geometry_errors();
    test_graph_errors();
    test_encoding_errors();
    test_extent();
    test_big_inputs();
    test_read_file();

    const char *root = getenv("HPFC_TEST_DATA");
    CHECK(root != NULL);
    if (root) {
        test_valid_fixtures(root);
        test_invalid_fixtures(root);
    }
    return check_report("test_pfc");
}
