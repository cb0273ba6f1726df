/*
 * The word module (libhpfcfile/words.h): a crossing's symbol, the fixed
 * word code decoded, the §3.8 grammar parsed and the roads counted. The
 * parse is checked on every string of up to seven symbols of "+=[]()Yx"
 * against an oracle written another way (the grammar as bracket matching
 * on a stack of characters), and every word it accepts against the parts
 * it must have; the decoder against words encoded bit by bit here.
 */
#include <string.h>

#include "check.h"
#include "format.h"
#include "words.h"

static void test_crossing_symbol(void)
{
    CHECK_EQ_INT(word_crossing_symbol(false, 1, 2), '[');
    CHECK_EQ_INT(word_crossing_symbol(false, 2, 2), ']');
    CHECK_EQ_INT(word_crossing_symbol(true, 1, 1), '=');
    CHECK_EQ_INT(word_crossing_symbol(true, 1, 3), '(');
    CHECK_EQ_INT(word_crossing_symbol(true, 2, 3), 'Y');
    CHECK_EQ_INT(word_crossing_symbol(true, 3, 3), ')');
}

/* The grammar, stated as brackets: four roads each ended by '+', nothing
 * after the fourth; '(' ... ')' and '[' ... ']' nest, 'Y' only where the
 * innermost open group is a '('; '=' anywhere. */
static bool oracle_valid(const char *s, size_t len)
{
    char open[16];
    size_t depth = 0, plus = 0;
    for (size_t k = 0; k < len; k++) {
        if (plus == 4)
            return false;
        switch (s[k]) {
        case '+': plus++; break;
        case '=': break;
        case '(':
        case '[': open[depth++] = s[k]; break;
        case 'Y':
            if (!depth || open[depth - 1] != '(')
                return false;
            break;
        case ')':
        case ']':
            if (!depth || open[--depth] != (s[k] == ')' ? '(' : '['))
                return false;
            break;
        default: return false;
        }
    }
    return plus == 4 && depth == 0;
}

/* What a parsed word must hold: its components partition its crossings,
 * each a cycle by succ with pred its inverse, in word order from
 * comp_first to comp_last; junctions are the '=' and '(' groups. */
static size_t bad_parts(const word_parts *wp, const char *s, size_t len)
{
    size_t bad = 0;
    uint32_t off[5], sizes = 0, junctions = 0, k = 0;
    word_count_roads(s, len, off);
    bad += memcmp(off, wp->road_off, sizeof off) != 0 || wp->n != off[4];
    for (size_t p = 0; p < len; p++)
        if (s[p] == '=' || s[p] == '(')
            junctions++;
    bad += wp->nvert != junctions;
    for (uint32_t c = 0; c < wp->ncomp; c++) {
        sizes += wp->comp_size[c];
        uint32_t x = wp->comp_first[c], steps = 0;
        do {
            bad += wp->comp[x] != c || wp->pred[wp->succ[x]] != x;
            bad += steps + 1 < wp->comp_size[c] && wp->succ[x] <= x; /* word order */
            x = wp->succ[x];
        } while (x != wp->comp_first[c] && ++steps <= wp->n);
        bad += steps + 1 != wp->comp_size[c] && wp->comp_size[c] != 1;
        bad += wp->pred[wp->comp_first[c]] != wp->comp_last[c];
        if (wp->comp_vertex[c] != WORD_NONE)
            bad += wp->vertex_comp[wp->comp_vertex[c]] != c;
    }
    for (size_t p = 0; p < len; p++)
        if (s[p] != '+')
            k++;
    bad += sizes != k;
    return bad;
}

static void test_parse_exhaustive(void)
{
    static const char alphabet[] = "+=[]()Yx";
    enum { MAX_LEN = 7, A = sizeof alphabet - 1 };
    word_parts wp;
    CHECK_EQ_INT(word_parts_alloc(&wp, MAX_LEN), HPFC_OK);
    size_t words = 0, accepted = 0, disagree = 0, bad = 0;
    char s[MAX_LEN];
    for (size_t len = 0; len <= MAX_LEN; len++) {
        size_t count = 1;
        for (size_t k = 0; k < len; k++)
            count *= A;
        for (size_t code = 0; code < count; code++, words++) {
            size_t c = code;
            for (size_t k = 0; k < len; k++, c /= A)
                s[k] = alphabet[c % A];
            int st = word_parse_symbols(&wp, s, len);
            bool ok = oracle_valid(s, len);
            disagree += (st == HPFC_OK) != ok || (st != HPFC_OK && st != HPFC_E_CORRUPT);
            if (ok) {
                accepted++;
                bad += bad_parts(&wp, s, len);
            } else { /* a broken word keeps its road counts */
                uint32_t off[5];
                word_count_roads(s, len, off);
                bad += memcmp(off, wp.road_off, sizeof off) != 0 || wp.n != off[4];
            }
        }
    }
    CHECK_EQ_INT(disagree, 0);
    CHECK_EQ_INT(bad, 0);
    CHECK(accepted > 100 && words > 2000000);
    /* more crossings than the arrays hold */
    CHECK_EQ_INT(word_parse_symbols(&wp, "========++++", 12), HPFC_E_CORRUPT);
    CHECK_EQ_INT(word_parse_symbols(&wp, "=======++++", 11), HPFC_OK);
    word_parts_free(&wp);
    CHECK_EQ_INT(word_road_count("[+]+(Y)++", 9, 2), 3);
    CHECK_EQ_INT(word_road_count("[+]+(Y)++", 9, 3), 0);
    uint32_t off[5];
    word_count_roads("[+]+(Y)++", 9, off);
    CHECK_EQ_INT(word_road_of_crossing(off, 4), 2);
    CHECK_EQ_INT(word_road_of_crossing(off, 0), 0);
}

/* Appends the §5.2.3 code of each symbol of s at bit *at of buf. */
static void encode(const char *s, uint8_t *buf, uint64_t *at)
{
    for (; *s; s++) {
        int code = format_symbol_code(*s);
        unsigned bits = code < 0 ? 1 : 4, value = code < 0 ? 0 : (unsigned)code;
        for (unsigned b = bits; b-- > 0; ++*at)
            if (value >> b & 1)
                buf[*at >> 3] |= (uint8_t)(0x80 >> (*at & 7));
    }
}

static void test_decode(void)
{
    static const char *const words[] = {"++++", "=+(+Y+)+", "[(+Y+)]=++", "(+Y+)+=+[]"};
    for (size_t w = 0; w < sizeof words / sizeof *words; w++) {
        uint8_t buf[32] = {0};
        uint64_t at = 3; /* any bit offset */
        encode(words[w], buf, &at);
        format_bits pool = {buf, sizeof buf * 8, sizeof buf};
        char out[64];
        size_t len = 0;
        const char *end = words[w];
        for (int plus = 0; plus < 4; end++) /* the word ends at its fourth '+' */
            plus += *end == '+';
        size_t want = (size_t)(end - words[w]);
        CHECK_EQ_INT(word_decode_code(&pool, 3, (uint32_t)(at - 3), out, sizeof out, &len), HPFC_OK);
        CHECK(len == want && memcmp(out, words[w], want) == 0);
        CHECK_EQ_INT(word_decode_code(&pool, 3, (uint32_t)(at - 3), NULL, 0, &len), HPFC_OK);
        CHECK_EQ_INT(len, want);
        CHECK_EQ_INT(word_decode_code(&pool, 3, (uint32_t)(at - 3), out, want - 1, &len),
                     HPFC_E_BUFFER_SMALL);
    }
    uint8_t reserved[8] = {0xE0}, cut[8] = {0x80}, none[8] = {0x0F, 0xFF};
    format_bits r = {reserved, 64, 8}, c = {cut, 64, 8}, n = {none, 64, 8};
    char out[16];
    size_t len;
    CHECK_EQ_INT(word_decode_code(&r, 0, 64, out, sizeof out, &len), HPFC_E_CORRUPT); /* 1110 */
    CHECK_EQ_INT(word_decode_code(&c, 0, 2, out, sizeof out, &len), HPFC_E_CORRUPT); /* a cut code */
    CHECK_EQ_INT(word_decode_code(&n, 0, 4, out, sizeof out, &len), HPFC_OK);
    CHECK_EQ_INT(word_decode_code(&n, 4, 8, out, sizeof out, &len), HPFC_E_CORRUPT); /* 1111 */
    CHECK_EQ_INT(word_decode_code(&n, 1, 3, out, sizeof out, &len), HPFC_E_CORRUPT); /* three '+' */
}

int main(void)
{
    test_crossing_symbol();
    test_parse_exhaustive();
    test_decode();
    return check_report("words");
}
