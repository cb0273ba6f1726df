#include "word.h"

#include <stdlib.h>
#include <string.h>

void word_info_free(word_info *wi)
{
    free(wi->sym);
    hpfc_word_parser_free(wi->parser);
    memset(wi, 0, sizeof *wi);
}

static int reserve_symbols(word_info *wi, size_t n)
{
    if (wi->sym && n <= wi->sym_cap)
        return 0;
    char *grown = realloc(wi->sym, n);
    if (!grown)
        return -1;
    wi->sym = grown;
    wi->sym_cap = n;
    return 0;
}

int word_parse(word_info *wi, const char *sym, size_t len)
{
    if (!wi->parser && hpfc_word_parser_create(&wi->parser))
        return -2;
    if (reserve_symbols(wi, len ? len : 1))
        return -2;
    hpfc_word_parts p;
    int st = hpfc_word_parse(wi->parser, sym, len, &p);
    if (st == HPFC_E_NOMEM || st == HPFC_E_LIMIT || st == HPFC_E_ARG)
        return -2;
    wi->n = st ? 0 : p.crossings;
    wi->ncomp = p.components;
    wi->nvert = p.junctions;
    memcpy(wi->road_off, p.road_first, sizeof wi->road_off);
    wi->comp = p.component;
    wi->comp_first = p.component_first;
    wi->comp_last = p.component_last;
    wi->comp_size = p.component_size;
    wi->comp_vertex = p.component_vertex;
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
    int road = 0;
    while (road < 3 && k >= wi->road_off[road + 1])
        road++;
    return road;
}

void word_road_counts(const char *sym, size_t len, uint32_t counts[4])
{
    uint32_t off[5];
    hpfc_word_count_roads(sym, len, off);
    for (int road = 0; road < 4; road++)
        counts[road] = off[road + 1] - off[road];
}

const char *word_symbol_code(char symbol)
{
    static const char *const codes[] = {"1000", "1001", "1010", "1011", "1100", "1101"};
    int code = hpfc_word_symbol_code(symbol);
    if (code == 0)
        return "0";
    return code >= 0x8 && code <= 0xD ? codes[code - 0x8] : "????";
}
