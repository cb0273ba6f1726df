/*
 * word_parser.c: the word grammar (common/words.c) behind the public
 * experimental calls, so that a tool explains a leaf with the library's own
 * parse rather than a copy of it.
 */
#include <stdlib.h>
#include <string.h>

#include "hpfc.h"
#include "words.h"

_Static_assert(WORD_NONE == HPFC_WORD_NONE, "one value for no local vertex");

struct hpfc_word_parser {
    word_parts parts; /* arrays for parts.cap crossings, grown by reserve */
};

int hpfc_word_parser_create(hpfc_word_parser **out)
{
    if (!out)
        return HPFC_E_ARG;
    *out = calloc(1, sizeof **out);
    return *out ? HPFC_OK : HPFC_E_NOMEM;
}

void hpfc_word_parser_free(hpfc_word_parser *p)
{
    if (!p)
        return;
    word_parts_free(&p->parts);
    free(p);
}

/* Arrays for n crossings; doubling keeps a tool's many small parses and a
 * rare long word from reallocating every time. */
static int reserve(hpfc_word_parser *p, size_t n)
{
    if (p->parts.cap && n <= p->parts.cap)
        return HPFC_OK;
    size_t cap = p->parts.cap ? p->parts.cap : 16;
    while (cap < n)
        cap *= 2;
    if (cap >= UINT32_MAX)
        return HPFC_E_LIMIT;
    word_parts_free(&p->parts);
    memset(&p->parts, 0, sizeof p->parts);
    if (word_parts_alloc(&p->parts, (uint32_t)cap)) {
        word_parts_free(&p->parts);
        memset(&p->parts, 0, sizeof p->parts);
        return HPFC_E_NOMEM;
    }
    return HPFC_OK;
}

int hpfc_word_parse(hpfc_word_parser *p, const char *symbols, size_t len, hpfc_word_parts *out)
{
    if (!p || !out || (!symbols && len))
        return HPFC_E_ARG;
    memset(out, 0, sizeof *out);
    int st = reserve(p, len ? len : 1); /* crossings never outnumber symbols */
    if (st)
        return st;
    const word_parts *wp = &p->parts;
    st = word_parse_symbols(&p->parts, symbols, len);
    out->crossings = wp->n;
    memcpy(out->road_first, wp->road_off, sizeof out->road_first);
    if (st)
        return st;
    out->components = wp->ncomp;
    out->junctions = wp->nvert;
    out->component = wp->comp;
    out->component_first = wp->comp_first;
    out->component_last = wp->comp_last;
    out->component_size = wp->comp_size;
    out->component_vertex = wp->comp_vertex;
    return HPFC_OK;
}

void hpfc_word_count_roads(const char *symbols, size_t len, uint32_t road_first[5])
{
    if (!road_first)
        return;
    if (!symbols)
        len = 0;
    word_count_roads(symbols, len, road_first);
}

int hpfc_word_symbol_code(char symbol)
{
    return symbol == '+' ? 0 : format_symbol_code(symbol);
}
