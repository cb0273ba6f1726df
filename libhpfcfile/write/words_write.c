/*
 * The fixed word code of spec/hpfc-format.md §5.2.3 written (words.h): its
 * size and its bits, for the paper layout's word slots.
 */
#include "words.h"

/* The fixed code of a word, written at `off` of a zeroed pool when pool is
 * non-NULL; its bits, 0 for a malformed word. One loop for the size and the
 * bits, so the two cannot disagree. */
static uint64_t fixed_code(const char *word, uint32_t len, uint8_t *pool, uint64_t off)
{
    uint64_t bits = 0;
    unsigned plus = 0;
    for (uint32_t k = 0; k < len; k++) {
        if (plus == 4)
            return 0;
        int code = format_symbol_code(word[k]);
        if (word[k] == '+') {
            plus++;
            bits += 1;
        } else if (code >= 0) {
            if (pool)
                format_put(pool, off + bits, 4, (uint64_t)code);
            bits += 4;
        } else {
            return 0;
        }
    }
    return plus == 4 ? bits : 0;
}

uint64_t word_code_bits(const char *word, uint32_t len)
{
    return fixed_code(word, len, NULL, 0);
}

void word_encode_code(uint8_t *pool, uint64_t off, const char *word, uint32_t len)
{
    fixed_code(word, len, pool, off);
}

