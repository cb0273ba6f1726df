#include "word.h"

#include <stdlib.h>
#include <string.h>

#include "format.h"

void word_info_free(word_info *wi)
{
    free(wi->sym);
    word_parts_free(&wi->parts);
    memset(wi, 0, sizeof *wi);
}

/* Arrays for n crossings (the library's parse rejects more than they hold). */
static int reserve(word_info *wi, size_t n)
{
    if (wi->sym && n <= wi->parts.cap)
        return 0;
    size_t cap = wi->parts.cap ? wi->parts.cap : 16;
    while (cap < n)
        cap *= 2;
    if (cap >= UINT32_MAX)
        return -1;
    word_info_free(wi);
    if (!(wi->sym = malloc(cap)) || word_parts_alloc(&wi->parts, (uint32_t)cap)) {
        word_info_free(wi);
        return -1;
    }
    return 0;
}

int word_parse(word_info *wi, const char *sym, size_t len)
{
    if (reserve(wi, len ? len : 1))
        return -2;
    const word_parts *p = &wi->parts;
    int st = word_parse_symbols(&wi->parts, sym, len);
    wi->n = st ? 0 : p->n;
    wi->ncomp = st ? 0 : p->ncomp;
    wi->nvert = st ? 0 : p->nvert;
    memcpy(wi->road_off, p->road_off, sizeof wi->road_off);
    wi->comp = p->comp;
    wi->comp_first = p->comp_first;
    wi->comp_last = p->comp_last;
    wi->comp_size = p->comp_size;
    wi->comp_vertex = p->comp_vertex;
    if (st)
        return -1;
    uint32_t k = 0;
    for (size_t s = 0; s < len; s++)
        if (sym[s] != '+')
            wi->sym[k++] = sym[s];
    return 0;
}

int word_road_of(const word_info *wi, uint32_t k)
{
    return word_road_of_crossing(wi->road_off, k);
}

void word_road_counts(const char *sym, size_t len, uint32_t counts[4])
{
    uint32_t off[5];
    word_count_roads(sym, len, off);
    for (int road = 0; road < 4; road++)
        counts[road] = off[road + 1] - off[road];
}

const char *word_symbol_code(char symbol)
{
    static const char *const codes[] = {"1000", "1001", "1010", "1011", "1100", "1101"};
    int code = format_symbol_code(symbol);
    if (symbol == '+')
        return "0";
    return code >= 0 ? codes[code - 0x8] : "????";
}
