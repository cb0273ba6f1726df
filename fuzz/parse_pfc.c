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

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    hpfc_graph *g = NULL;
    hpfc_diag diag;
    int st = hpfc_pfc_parse((const char *)data, size, &g, &diag);
    FUZZ_CHECK(parse_status_ok(st));
    FUZZ_CHECK((st == HPFC_OK) == (g != NULL));
    fuzz_check_diag(&diag, st);
    if (st) {
        FUZZ_CHECK(hpfc_strerror(st) != NULL);
        return 0;
    }
    fuzz_check_graph(g);
    FUZZ_CHECK(hpfc_graph_unit_exp10(g) <= 0 && hpfc_graph_unit_exp10(g) >= -30);
    /* line numbers: every record has one, an edge's after its vertices' */
    for (size_t v = 0; v < hpfc_graph_vertex_count(g); v++)
        FUZZ_CHECK(hpfc_graph_vertex_line(g, v) >= 1);
    for (size_t e = 0; e < hpfc_graph_edge_count(g); e++) {
        uint32_t u, v;
        const int64_t *pts;
        size_t n;
        hpfc_graph_edge(g, e, &u, &v, &pts, &n);
        FUZZ_CHECK(hpfc_graph_edge_line(g, e) > hpfc_graph_vertex_line(g, u) &&
                   hpfc_graph_edge_line(g, e) > hpfc_graph_vertex_line(g, v));
    }
    hpfc_diag vdiag;
    int vst = hpfc_graph_validate(g, &vdiag);
    FUZZ_CHECK(validate_status_ok(vst));
    fuzz_check_diag(&vdiag, vst);
    FUZZ_CHECK(hpfc_graph_validate(g, NULL) == vst);
    /* deterministic: a second parse gives the same graph */
    hpfc_graph *again = NULL;
    FUZZ_CHECK(hpfc_pfc_parse((const char *)data, size, &again, NULL) == HPFC_OK);
    FUZZ_CHECK(fuzz_same_graph(g, again));
    hpfc_graph_free(again);
    hpfc_graph_free(g);
    return 0;
}
