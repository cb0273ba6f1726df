/*
 * pfc_chunked.h: a .pfc text read as a split build's workers read it
 * (hpfc.h, "A .pfc text read in chunks"), in one process: cut into chunks,
 * each scanned, then each filled into its own stretch of one graph file's
 * bytes, as separate processes fill theirs. For the tests and the fuzz
 * harness that hold it against hpfc_pfc_parse.
 */
#ifndef HPFC_TEST_PFC_CHUNKED_H
#define HPFC_TEST_PFC_CHUNKED_H

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "hpfc.h"

/* The text in at most `count` chunks into a graph file's bytes (malloc'd:
 * *bytes, *size; *chunks gets how many there were). HPFC_OK, or the first
 * chunk's failure in text order (scans first, then fills), or HPFC_E_LIMIT
 * for more than 30 digits. */
static inline int pfc_chunked_bytes(const char *text, size_t length, size_t count,
                                    uint8_t **bytes, size_t *size, size_t *chunks,
                                    hpfc_diag *diag)
{
    *bytes = NULL, *size = 0, *chunks = 0;
    size_t *at = malloc((count + 1) * sizeof *at);
    hpfc_pfc_chunk *scan = malloc((count ? count : 1) * sizeof *scan);
    uint8_t *buf = NULL;
    int st = at && scan ? HPFC_OK : HPFC_E_NOMEM;
    size_t n = st ? 0 : hpfc_pfc_chunk_bounds(text, length, count, at);
    uint64_t vertices = 0, edges = 0, points = 0;
    int32_t digits = 0;
    for (size_t k = 0; !st && k < n; k++) {
        st = hpfc_pfc_chunk_scan(text, length, at[k], at[k + 1], &scan[k], diag);
        vertices += scan[k].vertices, edges += scan[k].edges, points += scan[k].points;
        digits = !st && scan[k].digits > digits ? scan[k].digits : digits;
    }
    hpfc_graph_file_layout l;
    if (!st && digits > 30) { /* the whole text's verdict, which the fills would each give */
        memset(diag, 0, sizeof *diag);
        diag->status = st = HPFC_E_LIMIT;
        strcpy(diag->message, "more than 30 fractional digits");
    }
    if (!st)
        st = hpfc_graph_file_layout_of(vertices, edges, points, -digits, &l);
    if (!st && !(buf = (l.size <= SIZE_MAX ? calloc(1, (size_t)l.size) : NULL)))
        st = HPFC_E_NOMEM;
    if (!st) {
        memcpy(buf, l.header, sizeof l.header);
        memcpy(buf + l.eoff + 8 * edges, &points, 8);
    }
    uint64_t v0 = 0, e0 = 0, p0 = 0;
    for (size_t k = 0; !st && k < n; k++) {
        hpfc_pfc_fill f = {.digits = digits, .first_vertex = v0, .first_point = p0,
                           .vxy = (int64_t *)(void *)(buf + l.vxy) + 2 * v0,
                           .eu = (uint32_t *)(void *)(buf + l.eu) + e0,
                           .ev = (uint32_t *)(void *)(buf + l.ev) + e0,
                           .eoff = (uint64_t *)(void *)(buf + l.eoff) + e0,
                           .pts = (int64_t *)(void *)(buf + l.pts) + 2 * p0};
        st = hpfc_pfc_chunk_fill(text, length, at[k], at[k + 1], &scan[k], &f, diag);
        v0 += scan[k].vertices, e0 += scan[k].edges, p0 += scan[k].points;
    }
    free(at);
    free(scan);
    if (st) {
        free(buf);
        return st;
    }
    *bytes = buf, *size = (size_t)l.size, *chunks = n;
    return HPFC_OK;
}

/* Do a and b hold the same vertices, edges, points and unit? */
static inline int pfc_chunked_same(const hpfc_graph *a, const hpfc_graph *b)
{
    size_t nv = hpfc_graph_vertex_count(a), ne = hpfc_graph_edge_count(a);
    if (nv != hpfc_graph_vertex_count(b) || ne != hpfc_graph_edge_count(b) ||
        hpfc_graph_unit_exp10(a) != hpfc_graph_unit_exp10(b))
        return 0;
    for (size_t v = 0; v < nv; v++) {
        int64_t ax, ay, bx, by;
        hpfc_graph_vertex(a, v, &ax, &ay);
        hpfc_graph_vertex(b, v, &bx, &by);
        if (ax != bx || ay != by)
            return 0;
    }
    for (size_t e = 0; e < ne; e++) {
        uint32_t au, av, bu, bv;
        const int64_t *ap, *bp;
        size_t an, bn;
        hpfc_graph_edge(a, e, &au, &av, &ap, &an);
        hpfc_graph_edge(b, e, &bu, &bv, &bp, &bn);
        if (au != bu || av != bv || an != bn || (an && memcmp(ap, bp, 16 * an) != 0))
            return 0;
    }
    return 1;
}

#endif
