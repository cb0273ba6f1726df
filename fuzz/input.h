/*
 * input.h: helpers shared by the harnesses (not a harness itself).
 *
 * - fuzz_bytes: reads integers off the input, yielding zeros once it runs
 *   out, so every byte string is a valid program.
 * - fuzz_split_file: the .hpfc harnesses take an input as a file followed
 *   by command bytes. The file is the prefix whose length its own header
 *   declares (`file_size`, at byte 88); what follows drives the harness. A
 *   plain fixture is thus a seed as it is (no commands: the default
 *   exploration), and libFuzzer grows command tails by appending. The file
 *   is copied into a buffer of exactly its size so AddressSanitizer catches
 *   any read past its end, even with commands behind it.
 * - FUZZ_CHECK: the harness's oracle; a failed check aborts with a message,
 *   which libFuzzer (and the replay test) report as a finding.
 * - fuzz_check_graph, fuzz_same_graph: the checks every harness that makes
 *   an hpfc_graph (the .pfc parser, the mesh and GIS inputs) applies to it.
 */
#ifndef HPFC_FUZZ_INPUT_H
#define HPFC_FUZZ_INPUT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hpfc.h"

#define FUZZ_CHECK(cond)                                                                  \
    do {                                                                                  \
        if (!(cond)) {                                                                    \
            fprintf(stderr, "%s:%d: fuzz oracle failed: %s\n", __FILE__, __LINE__, #cond); \
            abort();                                                                      \
        }                                                                                 \
    } while (0)

typedef struct fuzz_bytes {
    const uint8_t *p;
    size_t n;
} fuzz_bytes;

static inline bool fuzz_empty(const fuzz_bytes *in)
{
    return in->n == 0;
}

static inline uint8_t fuzz_u8(fuzz_bytes *in)
{
    if (!in->n)
        return 0;
    in->n--;
    return *in->p++;
}

static inline uint16_t fuzz_u16(fuzz_bytes *in)
{
    uint16_t v = fuzz_u8(in);
    return (uint16_t)(v | fuzz_u8(in) << 8);
}

static inline uint32_t fuzz_u32(fuzz_bytes *in)
{
    uint32_t v = fuzz_u16(in);
    return v | (uint32_t)fuzz_u16(in) << 16;
}

static inline uint64_t fuzz_u64(fuzz_bytes *in)
{
    uint64_t v = fuzz_u32(in);
    return v | (uint64_t)fuzz_u32(in) << 32;
}

/* The header's file_size field (spec/hpfc-format.md §4.2: u64 LE at 88). */
enum { FUZZ_FILE_SIZE_OFFSET = 88, FUZZ_HEADER_SIZE = 128 };

/* Splits data into an exact-size malloc'ed copy of the file part (*file,
 * *file_size; free() it) and the command bytes behind it. Returns false
 * only when the copy cannot be allocated. */
static inline bool fuzz_split_file(const uint8_t *data, size_t size, uint8_t **file, size_t *file_size,
                                   fuzz_bytes *cmds)
{
    size_t cut = size;
    if (size >= FUZZ_HEADER_SIZE) {
        uint64_t declared = 0;
        for (int k = 7; k >= 0; k--)
            declared = declared << 8 | data[FUZZ_FILE_SIZE_OFFSET + k];
        if (declared >= FUZZ_HEADER_SIZE && declared <= size)
            cut = (size_t)declared;
    }
    *file = (uint8_t *)malloc(cut ? cut : 1);
    if (!*file)
        return false;
    memcpy(*file, data, cut);
    *file_size = cut;
    cmds->p = data + cut;
    cmds->n = size - cut;
    return true;
}

/* A status an operator on an open file may legitimately return. */
static inline bool fuzz_known_status(int st)
{
    switch (st) {
    case HPFC_OK:
    case HPFC_E_NOMEM:
    case HPFC_E_ARG:
    case HPFC_E_BUFFER_SMALL:
    case HPFC_E_LIMIT:
    case HPFC_E_CORRUPT:
    case HPFC_E_NO_PIXEL:
        return true;
    default:
        return false;
    }
}

/* The shape every graph handed out must have, whatever the input: edges name
 * existing vertices, a loop has at least two shape points, and every vertex
 * and shape point lies within the lattice bound. */
static inline void fuzz_check_graph(const hpfc_graph *g)
{
    size_t nv = hpfc_graph_vertex_count(g), ne = hpfc_graph_edge_count(g);
    for (size_t v = 0; v < nv; v++) {
        int64_t x, y;
        hpfc_graph_vertex(g, v, &x, &y);
        FUZZ_CHECK(x >= -HPFC_COORD_MAX && x <= HPFC_COORD_MAX && y >= -HPFC_COORD_MAX &&
                   y <= HPFC_COORD_MAX);
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
    }
}

/* Same vertices, edges, shape points and unit, in the same order. */
static inline bool fuzz_same_graph(const hpfc_graph *a, const hpfc_graph *b)
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

/* A diagnostic filled for status st: the same status, a terminated message. */
static inline void fuzz_check_diag(const hpfc_diag *d, int st)
{
    FUZZ_CHECK(d->status == st);
    FUZZ_CHECK(memchr(d->message, '\0', sizeof d->message) != NULL);
}

#endif
