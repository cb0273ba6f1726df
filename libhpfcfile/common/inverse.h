/*
 * inverse.h: a table of rows inverted by counting sort, in memory: LABL's
 * edge sides into each face's edges, FEAT's and EDGF's links into each
 * feature's faces and edges, as the shapes index makes them for a file
 * without SHIX (query/shapes.c). The writer stores the same inverses in
 * SHIX, sorted in the section's own offsets (read/shix.c, invert_into).
 * The caller visits its links twice, counting them
 * (inverse_count), then, after inverse_room, placing them (inverse_put)
 * in the same order, so each inverse row lists its sources in the order
 * they were visited (ascending when the sources are visited in order).
 */
#ifndef HPFC_INVERSE_H
#define HPFC_INVERSE_H

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "hpfc.h"

/* rows inverse rows: row r's items are item[start[r] .. start[r + 1]). */
typedef struct inverse_table {
    uint64_t rows;
    uint64_t *start; /* rows + 2: counts (shifted by one), then offsets */
    uint32_t *item;
    uint64_t *fill;  /* each row's next free item, between room and done */
} inverse_table;

/* An empty table of `rows` rows, no link counted: HPFC_E_NOMEM, or
 * HPFC_OK. */
static inline int inverse_begin(inverse_table *t, uint64_t rows)
{
    *t = (inverse_table){.rows = rows};
    if (rows > SIZE_MAX / sizeof *t->start - 2)
        return HPFC_E_NOMEM;
    t->start = calloc((size_t)rows + 2, sizeof *t->start);
    return t->start ? HPFC_OK : HPFC_E_NOMEM;
}

/* A link to row `row` (< rows, the caller's check), first pass. */
static inline void inverse_count(inverse_table *t, uint64_t row)
{
    t->start[row + 1]++;
}

/* The counts made offsets and room for the items: HPFC_E_LIMIT for more
 * than `most` items, HPFC_E_NOMEM, or HPFC_OK. */
static inline int inverse_room(inverse_table *t, uint64_t most)
{
    for (uint64_t r = 0; r < t->rows; r++)
        t->start[r + 1] += t->start[r];
    uint64_t items = t->start[t->rows];
    if (items > most)
        return HPFC_E_LIMIT;
    if (items >= SIZE_MAX / sizeof *t->item || t->rows >= SIZE_MAX / sizeof *t->fill)
        return HPFC_E_NOMEM;
    t->item = malloc(((size_t)items + 1) * sizeof *t->item);
    t->fill = malloc(((size_t)t->rows + 1) * sizeof *t->fill);
    if (!t->item || !t->fill)
        return HPFC_E_NOMEM;
    memcpy(t->fill, t->start, (size_t)t->rows * sizeof *t->fill);
    return HPFC_OK;
}

/* The same link again, second pass: `source` joins row `row`. */
static inline void inverse_put(inverse_table *t, uint64_t row, uint32_t source)
{
    t->item[t->fill[row]++] = source;
}

/* The scratch of the second pass released; the table stays. */
static inline void inverse_done(inverse_table *t)
{
    free(t->fill);
    t->fill = NULL;
}

static inline void inverse_free(inverse_table *t)
{
    free(t->start);
    free(t->item);
    free(t->fill);
    *t = (inverse_table){0};
}

#endif
