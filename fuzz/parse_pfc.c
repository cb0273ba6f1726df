/*
 * parse_pfc: the plain-text .pfc reader (spec/pfc-format.md) on the whole
 * input, then the graph checks on what it accepted.
 *
 * Oracle: the parser returns OK or a code of the spec's validity table
 * (never ARG, never NONPLANAR, never a file code) and fills the diagnostic with the same status and a
 * NUL-terminated message; on success it returns a graph whose edges name
 * existing vertices, whose coordinates are inside the lattice bound, and
 * whose unit exponent is in [-30, 0]; hpfc_graph_validate returns OK or a
 * graph validity code, the same one twice. Parsing is deterministic: the
 * same text gives the same graph.
 */
#include "input.h"

static bool parse_status_ok(int st)
{
    /* spec/pfc-format.md §5: every code of its table but NONPLANAR, which
     * only hpfc_graph_validate decides */
    return st == HPFC_OK || st == HPFC_E_NOMEM ||
           (st >= HPFC_E_PFC_SYNTAX && st <= HPFC_E_VERTEX_INDEX) ||
           (st >= HPFC_E_DUPLICATE_POINT && st <= HPFC_E_EMPTY && st != HPFC_E_NONPLANAR) ||
           st == HPFC_E_LIMIT;
}

static bool validate_status_ok(int st)
{
    return st == HPFC_OK || st == HPFC_E_NOMEM || (st >= HPFC_E_DUPLICATE_POINT && st <= HPFC_E_EMPTY);
}

static void check_diag(const hpfc_diag *d, int st)
{
    FUZZ_CHECK(d->status == st);
    FUZZ_CHECK(memchr(d->message, '\0', sizeof d->message) != NULL);
}

static bool same_graph(const hpfc_graph *a, const hpfc_graph *b)
{
    size_t nv = hpfc_graph_vertex_count(a), ne = hpfc_graph_edge_count(a);
    if (nv != hpfc_graph_vertex_count(b) || ne != hpfc_graph_edge_count(b) ||
        hpfc_graph_unit_exp10(a) != hpfc_graph_unit_exp10(b))
        return false;
    for (size_t v = 0; v < nv; v++) {
        int64_t ax, ay, bx, by;
        hpfc_graph_vertex(a, v, &ax, &ay);
        hpfc_graph_vertex(b, v, &bx, &by);
        if (ax != bx || ay != by)
            return false;
    }
    for (size_t e = 0; e < ne; e++) {
        uint32_t au, av, bu, bv;
        const int64_t *ap, *bp;
        size_t an, bn;
        hpfc_graph_edge(a, e, &au, &av, &ap, &an);
        hpfc_graph_edge(b, e, &bu, &bv, &bp, &bn);
        if (au != bu || av != bv || an != bn || (an && memcmp(ap, bp, 2 * an * sizeof *ap)))
            return false;
    }
    return true;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    hpfc_graph *g = NULL;
    hpfc_diag diag;
    int st = hpfc_pfc_parse((const char *)data, size, &g, &diag);
    FUZZ_CHECK(parse_status_ok(st));
    FUZZ_CHECK((st == HPFC_OK) == (g != NULL));
    check_diag(&diag, st);
    if (st) {
        FUZZ_CHECK(hpfc_strerror(st) != NULL);
        return 0;
    }
    size_t nv = hpfc_graph_vertex_count(g), ne = hpfc_graph_edge_count(g);
    int32_t unit = hpfc_graph_unit_exp10(g);
    FUZZ_CHECK(unit <= 0 && unit >= -30);
    for (size_t v = 0; v < nv; v++) {
        int64_t x, y;
        hpfc_graph_vertex(g, v, &x, &y);
        FUZZ_CHECK(x >= -HPFC_COORD_MAX && x <= HPFC_COORD_MAX && y >= -HPFC_COORD_MAX &&
                   y <= HPFC_COORD_MAX);
        FUZZ_CHECK(hpfc_graph_vertex_line(g, v) >= 1);
    }
    for (size_t e = 0; e < ne; e++) {
        uint32_t u, v;
        const int64_t *pts;
        size_t n;
        hpfc_graph_edge(g, e, &u, &v, &pts, &n);
        FUZZ_CHECK(u < nv && v < nv);
        FUZZ_CHECK(u != v || n >= 2);
        for (size_t k = 0; k < 2 * n; k++)
            FUZZ_CHECK(pts[k] >= -HPFC_COORD_MAX && pts[k] <= HPFC_COORD_MAX);
        FUZZ_CHECK(hpfc_graph_edge_line(g, e) > hpfc_graph_vertex_line(g, u) &&
                   hpfc_graph_edge_line(g, e) > hpfc_graph_vertex_line(g, v));
    }
    hpfc_diag vdiag;
    int vst = hpfc_graph_validate(g, &vdiag);
    FUZZ_CHECK(validate_status_ok(vst));
    check_diag(&vdiag, vst);
    FUZZ_CHECK(hpfc_graph_validate(g, NULL) == vst);
    /* deterministic: a second parse gives the same graph */
    hpfc_graph *again = NULL;
    FUZZ_CHECK(hpfc_pfc_parse((const char *)data, size, &again, NULL) == HPFC_OK);
    FUZZ_CHECK(same_graph(g, again));
    hpfc_graph_free(again);
    hpfc_graph_free(g);
    return 0;
}
