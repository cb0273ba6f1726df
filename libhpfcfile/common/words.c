/*
 * A word's symbols parsed and counted (words.h): the one implementation of
 * the grammar of spec/hpfc-format.md §3.8. The fixed word code of §5.2.3 is
 * read in read/words_read.c and written in write/words_write.c.
 */
#include "words.h"

#include <stdlib.h>

#include "hpfc.h"

/* The arrays live in one block, comp's (word_parts_place lays them out). */
void word_parts_free(word_parts *wp)
{
    free(wp->comp);
    *wp = (word_parts){0};
}

int word_parts_alloc(word_parts *wp, uint32_t cap)
{
    *wp = (word_parts){0};
    if (WORD_PARTS_MEM(cap) > SIZE_MAX / sizeof(uint32_t))
        return HPFC_E_NOMEM;
    uint32_t *mem = malloc(WORD_PARTS_MEM(cap) * sizeof(uint32_t));
    if (!mem)
        return HPFC_E_NOMEM;
    word_parts_place(wp, mem, cap);
    return HPFC_OK;
}

void word_parts_place(word_parts *wp, uint32_t *mem, uint32_t cap)
{
    uint32_t **arrays[] = {&wp->comp, &wp->pred, &wp->succ, &wp->comp_vertex, &wp->comp_first,
                           &wp->comp_last, &wp->comp_size, &wp->vertex_comp, &wp->stack};
    _Static_assert(sizeof arrays / sizeof *arrays == WORD_PARTS_MEM(0),
                   "WORD_PARTS_MEM counts every array");
    size_t n = (size_t)cap + 1; /* elements per array, as WORD_PARTS_MEM counts */
    *wp = (word_parts){0};
    for (size_t i = 0; i < sizeof arrays / sizeof *arrays; i++)
        *arrays[i] = mem + i * n;
    wp->cap = cap;
}

static void add_crossing(word_parts *wp, uint32_t k, uint32_t c)
{
    wp->comp[k] = c;
    if (wp->comp_last[c] == WORD_NONE) {
        wp->comp_first[c] = k;
    } else {
        wp->succ[wp->comp_last[c]] = k;
        wp->pred[k] = wp->comp_last[c];
    }
    wp->comp_last[c] = k;
    wp->comp_size[c]++;
}

static uint32_t new_component(word_parts *wp, bool junction)
{
    uint32_t c = wp->ncomp++;
    wp->comp_last[c] = WORD_NONE;
    wp->comp_size[c] = 0;
    wp->comp_vertex[c] = WORD_NONE;
    if (junction) {
        wp->vertex_comp[wp->nvert] = c;
        wp->comp_vertex[c] = wp->nvert++;
    }
    return c;
}

/* A word the grammar rejects: only its road counts are left. Out of line
 * (and rare): the parse loop stays as small as the grammar. */
__attribute__((noinline, cold)) static int broken(word_parts *wp, const char *sym, size_t len)
{
    word_count_roads(sym, len, wp->road_off);
    wp->n = wp->road_off[4];
    wp->ncomp = wp->nvert = 0;
    return HPFC_E_CORRUPT;
}

/* Crossings (non-'+' symbols) of a string. */
static size_t crossing_count(const char *sym, size_t len)
{
    size_t n = 0;
    for (size_t s = 0; s < len; s++)
        n += sym[s] != '+';
    return n;
}

/* One pass with a stack of the open groups. The checks that are not the
 * grammar's own (room in the arrays, nothing after the fourth '+') sit
 * outside the per-symbol path: a walker parses a word per pixel visited. */
int word_parse_symbols(word_parts *wp, const char *sym, size_t len)
{
    if (len > wp->cap && crossing_count(sym, len) > wp->cap)
        return broken(wp, sym, len);
    uint32_t depth = 0, plus = 0;
    wp->n = wp->ncomp = wp->nvert = 0;
    wp->road_off[0] = 0;
    for (size_t s = 0; s < len; s++) {
        char c = sym[s];
        if (c == '+') {
            wp->road_off[++plus] = wp->n;
            if (plus == 4 && s + 1 < len) /* the fourth '+' ends the word */
                return broken(wp, sym, len);
            continue;
        }
        uint32_t k = wp->n++, top = depth ? wp->stack[depth - 1] : WORD_NONE;
        switch (c) {
        case '=': add_crossing(wp, k, new_component(wp, true)); break;
        case '(':
        case '[': {
            uint32_t comp = new_component(wp, c == '(');
            wp->stack[depth++] = comp;
            add_crossing(wp, k, comp);
            break;
        }
        case 'Y':
            if (top == WORD_NONE || wp->comp_vertex[top] == WORD_NONE)
                return broken(wp, sym, len);
            add_crossing(wp, k, top);
            break;
        case ')':
        case ']':
            if (top == WORD_NONE || (wp->comp_vertex[top] == WORD_NONE) != (c == ']'))
                return broken(wp, sym, len);
            depth--;
            add_crossing(wp, k, top);
            break;
        default: return broken(wp, sym, len);
        }
    }
    if (plus != 4 || depth != 0)
        return broken(wp, sym, len);
    for (uint32_t comp = 0; comp < wp->ncomp; comp++) {
        wp->pred[wp->comp_first[comp]] = wp->comp_last[comp];
        wp->succ[wp->comp_last[comp]] = wp->comp_first[comp];
    }
    return HPFC_OK;
}

void word_count_roads(const char *sym, size_t len, uint32_t road_off[5])
{
    uint32_t plus = 0, n = 0;
    road_off[0] = 0;
    for (size_t s = 0; s < len && plus < 4; s++) {
        if (sym[s] == '+')
            road_off[++plus] = n;
        else
            n++;
    }
    while (plus < 4)
        road_off[++plus] = n;
}

uint32_t word_road_count(const char *sym, size_t len, int road)
{
    uint32_t count = 0;
    int r = 0;
    for (size_t s = 0; s < len && r <= road; s++) {
        if (sym[s] == '+')
            r++;
        else if (r == road)
            count++;
    }
    return count;
}
