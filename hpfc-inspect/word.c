#include "word.h"

#include <stdlib.h>
#include <string.h>

void word_info_free(word_info *wi)
{
    free(wi->sym);
    free(wi->comp);
    free(wi->comp_first);
    free(wi->comp_last);
    free(wi->comp_size);
    free(wi->comp_vertex);
    free(wi->stack);
    memset(wi, 0, sizeof *wi);
}

static int grow(void **p, size_t count, size_t size)
{
    void *q = realloc(*p, count * size);
    if (!q)
        return -1;
    *p = q;
    return 0;
}

/* Components never outnumber crossings, so one capacity serves all arrays. */
static int reserve(word_info *wi, size_t n)
{
    if (n <= wi->cap)
        return 0;
    size_t cap = wi->cap ? wi->cap : 16;
    while (cap < n)
        cap *= 2;
    if (cap > UINT32_MAX)
        return -1;
    if (grow((void **)&wi->sym, cap, 1) || grow((void **)&wi->comp, cap, sizeof(uint32_t)) ||
        grow((void **)&wi->comp_first, cap, sizeof(uint32_t)) ||
        grow((void **)&wi->comp_last, cap, sizeof(uint32_t)) ||
        grow((void **)&wi->comp_size, cap, sizeof(uint32_t)) ||
        grow((void **)&wi->comp_vertex, cap, sizeof(uint32_t)) ||
        grow((void **)&wi->stack, cap, sizeof(uint32_t)))
        return -1;
    wi->cap = (uint32_t)cap;
    return 0;
}

static uint32_t open_component(word_info *wi, uint32_t k, int junction)
{
    uint32_t c = wi->ncomp++;
    wi->comp_first[c] = k;
    wi->comp_last[c] = k;
    wi->comp_size[c] = 0;
    wi->comp_vertex[c] = junction ? wi->nvert++ : WORD_NONE;
    return c;
}

static void add_crossing(word_info *wi, uint32_t k, uint32_t c, char symbol)
{
    wi->sym[k] = symbol;
    wi->comp[k] = c;
    wi->comp_last[c] = k;
    wi->comp_size[c]++;
}

/* One crossing symbol against the stack of open groups (§3.8). */
static int parse_crossing(word_info *wi, uint32_t k, char s, uint32_t *top)
{
    uint32_t c;
    switch (s) {
    case '=':
        c = open_component(wi, k, 1);
        break;
    case '[':
    case '(':
        c = open_component(wi, k, s == '(');
        wi->stack[(*top)++] = c;
        break;
    case 'Y':
        if (*top == 0 || wi->comp_vertex[wi->stack[*top - 1]] == WORD_NONE)
            return -1;
        c = wi->stack[*top - 1];
        break;
    case ')':
    case ']':
        if (*top == 0 || (wi->comp_vertex[wi->stack[*top - 1]] == WORD_NONE) != (s == ']'))
            return -1;
        c = wi->stack[--*top];
        break;
    default:
        return -1;
    }
    add_crossing(wi, k, c, s);
    return 0;
}

int word_parse(word_info *wi, const char *sym, size_t len)
{
    if (reserve(wi, len ? len : 1))
        return -2;
    uint32_t k = 0, top = 0, road = 0;
    wi->n = wi->ncomp = wi->nvert = 0;
    wi->road_off[0] = 0;
    for (size_t p = 0; p < len; p++) {
        if (sym[p] == '+') {
            if (road == 4)
                return -1;
            wi->road_off[++road] = k;
            continue;
        }
        if (road == 4 || parse_crossing(wi, k, sym[p], &top))
            return -1;
        k++;
    }
    /* the fourth '+' must be the last symbol and close every group */
    if (road != 4 || top != 0 || len == 0 || sym[len - 1] != '+')
        return -1;
    wi->n = k;
    return 0;
}

int word_road_of(const word_info *wi, uint32_t k)
{
    int r = 0;
    while (r < 3 && k >= wi->road_off[r + 1])
        r++;
    return r;
}

void word_road_counts(const char *sym, size_t len, uint32_t counts[4])
{
    int road = 0;
    counts[0] = counts[1] = counts[2] = counts[3] = 0;
    for (size_t p = 0; p < len && road < 4; p++) {
        if (sym[p] == '+')
            road++;
        else
            counts[road]++;
    }
}

const char *word_symbol_code(char symbol)
{
    switch (symbol) {
    case '+': return "0";
    case '=': return "1000";
    case '[': return "1001";
    case ']': return "1010";
    case '(': return "1011";
    case 'Y': return "1100";
    case ')': return "1101";
    default: return "????";
    }
}
