/*
 * feature_links.h: links to features as FEAT keeps them per face and EDGF
 * per edge (spec/hpfc-format.md §6.2, §6.4), in one place for both: an
 * index of row_count + 1 u32 offsets, non-decreasing from 0 to link_count,
 * then link_count u32 feature indices, each row's ascending. The writer's
 * check and bytes and the reader's checked access are the same for a face
 * and for an edge, so the two sections answer alike.
 */
#ifndef HPFC_FEATURE_LINKS_H
#define HPFC_FEATURE_LINKS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "format.h"
#include "hpfc.h"

/* ---- writer ---- */

/* The first row (< rows) a writer must not store, else rows: its offsets
 * decrease (*decreases true), or its links are not ascending feature
 * indices below `features` (*decreases false). start: rows + 1 offsets. */
static inline uint32_t feature_links_first_bad(const uint32_t *start, const uint32_t *feature,
                                               uint32_t rows, uint32_t features, bool *decreases)
{
    for (uint32_t r = 0; r < rows; r++) {
        *decreases = start[r + 1] < start[r];
        if (*decreases)
            return r;
        for (uint32_t i = start[r]; i < start[r + 1]; i++)
            if (feature[i] >= features || (i > start[r] && feature[i] <= feature[i - 1]))
                return r;
    }
    return rows;
}

/* The index and then the links at out: 4 * (rows + 1 + start[rows]) bytes. */
static inline void feature_links_emit(uint8_t *out, const uint32_t *start, const uint32_t *feature,
                                      uint32_t rows)
{
    for (uint32_t r = 0; r <= rows; r++, out += 4)
        le_store(out, 4, start[r]);
    for (uint32_t i = 0; i < start[rows]; i++, out += 4)
        le_store(out, 4, feature[i]);
}

/* ---- reader ---- */

/* A section's links as its header gives them; `index` lies in the section
 * with the links after it (the section's length was checked at open). */
typedef struct feature_links {
    const uint8_t *index;
    uint32_t rows, links, features; /* row_count, link_count, feature_count */
} feature_links;

/* Row `row`'s links [*first, *end): HPFC_E_ARG past the rows,
 * HPFC_E_CORRUPT for index entries that decrease or pass the links. */
static inline int feature_links_row(const feature_links *t, uint64_t row, uint32_t *first,
                                    uint32_t *end)
{
    if (row >= t->rows)
        return HPFC_E_ARG;
    const uint8_t *entry = t->index + 4 * (size_t)row;
    *first = (uint32_t)le_load(entry, 4);
    *end = (uint32_t)le_load(entry + 4, 4);
    if (*first > *end || *end > t->links)
        return HPFC_E_CORRUPT;
    return HPFC_OK;
}

/* How many features row `row` links. */
static inline int feature_links_count(const feature_links *t, uint64_t row, uint32_t *count)
{
    uint32_t first, end;
    int st = feature_links_row(t, row, &first, &end);
    if (!st)
        *count = end - first;
    return st;
}

/* The k-th feature of row `row`: HPFC_E_ARG for k past the row's links,
 * HPFC_E_CORRUPT for a feature index not below the feature count. */
static inline int feature_links_get(const feature_links *t, uint64_t row, uint32_t k,
                                    hpfc_id *feature)
{
    uint32_t first, end;
    int st = feature_links_row(t, row, &first, &end);
    if (st)
        return st;
    if (k >= end - first)
        return HPFC_E_ARG;
    const uint8_t *links = t->index + 4 * ((size_t)t->rows + 1);
    uint32_t v = (uint32_t)le_load(links + 4 * ((size_t)first + k), 4);
    if (v >= t->features)
        return HPFC_E_CORRUPT;
    *feature = v;
    return HPFC_OK;
}

#endif
