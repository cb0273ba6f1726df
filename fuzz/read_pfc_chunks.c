/*
 * read_pfc_chunks: a .pfc text read in chunks into a graph file, as a split
 * build's workers read it (hpfc.h, "A .pfc text read in chunks"), and a
 * graph file's bytes mapped back as a graph (graph_file.c).
 *
 * The first byte picks the input's kind. Even: the rest is a .pfc text,
 * cut into 1 + byte / 2 % 16 chunks. Oracle: hpfc_pfc_parse of the whole
 * text; where it accepts, the chunks accept and give the same graph, and
 * where it or hpfc_graph_validate refuses, the chunks refuse or their
 * graph fails hpfc_graph_check_whole or hpfc_graph_validate. Odd: the rest
 * is a graph file's bytes; a graph comes back only with every edge naming
 * its vertices and every coordinate in the lattice (fuzz_check_graph), and
 * the whole graph's checks run on it.
 */
#include <stdlib.h>
#include <string.h>

#include "graph.h"
#include "input.h"
#include "pfc_chunked.h"

static bool whole_ok(const char *text, size_t len, hpfc_graph **out)
{
    hpfc_diag d;
    int st = hpfc_pfc_parse(text, len, out, &d);
    return st == HPFC_OK && hpfc_graph_validate(*out, &d) == HPFC_OK;
}

static void chunks_against_whole(const char *text, size_t len, size_t count)
{
    hpfc_graph *whole = NULL, *g = NULL;
    bool ok = whole_ok(text, len, &whole);
    uint8_t *bytes;
    size_t size, chunks;
    hpfc_diag d;
    int st = pfc_chunked_bytes(text, len, count, &bytes, &size, &chunks, &d);
    fuzz_check_diag(&d, st);
    if (st == HPFC_E_NOMEM)
        goto out;
    if (ok)
        FUZZ_CHECK(st == HPFC_OK);
    if (!st) {
        FUZZ_CHECK(chunks >= 1 && chunks <= count);
        FUZZ_CHECK(graph_from_file_bytes(bytes, size, &g, &d) == HPFC_OK);
        fuzz_check_graph(g);
        if (ok)
            FUZZ_CHECK(pfc_chunked_same(whole, g));
        else
            FUZZ_CHECK(hpfc_graph_check_whole(g, &d) != HPFC_OK || hpfc_graph_validate(g, &d) != HPFC_OK);
        free(bytes);
    }
out:
    hpfc_graph_free(g);
    hpfc_graph_free(whole);
}

static void graph_file_bytes(const uint8_t *data, size_t size)
{
    /* the arrays are read in place: 8-byte aligned, as a mapping is */
    uint8_t *copy = malloc(size ? size : 1);
    if (!copy)
        return;
    memcpy(copy, data, size);
    hpfc_graph *g = NULL;
    hpfc_diag d;
    int st = graph_from_file_bytes(copy, size, &g, &d);
    fuzz_check_diag(&d, st);
    FUZZ_CHECK((st == HPFC_OK) == (g != NULL));
    FUZZ_CHECK(st == HPFC_OK || st == HPFC_E_MAGIC || st == HPFC_E_HEADER || st == HPFC_E_TRUNCATED ||
               st == HPFC_E_EXTENT || st == HPFC_E_VERTEX_INDEX || st == HPFC_E_CORRUPT ||
               st == HPFC_E_LOOP_INTERIOR ||
               st == HPFC_E_NOMEM);
    if (g) {
        fuzz_check_graph(g);
        FUZZ_CHECK(hpfc_graph_add_vertex(g, 0, 0, NULL) == HPFC_E_ARG);
        int64_t box[4];
        hpfc_graph_bounds(g, box);
        hpfc_graph_check_whole(g, &d);
        hpfc_graph_validate(g, &d);
    }
    hpfc_graph_free(g);
    free(copy);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1)
        return 0;
    if (data[0] % 2 == 0)
        chunks_against_whole((const char *)data + 1, size - 1, 1 + (size_t)(data[0] / 2) % 16);
    else
        graph_file_bytes(data + 1, size - 1);
    return 0;
}
