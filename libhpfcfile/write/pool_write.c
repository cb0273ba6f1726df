/*
 * The compact pool layout written (pool.h, spec/hpfc-format.md §5.3): the
 * word code measured and emitted, the type bits, block counts and word
 * index of a level.
 */
#include "pool_code.h"

/* Calls emit(pool, off, bits, value) for each code of the word but its
 * fourth '+' and returns the total bits; UINT64_MAX for a malformed word. */
static uint64_t code_word(const char *word, uint32_t len, uint8_t *pool, uint64_t off)
{
    if (len < 4 || word[len - 1] != '+')
        return UINT64_MAX;
    uint64_t bits = 0;
    unsigned plus = 0;
    int ctx = CTX_NONE;
    for (uint32_t k = 0; k + 1 < len; k++) {
        uint64_t value;
        unsigned n = symbol_code(ctx, word[k], &value, &ctx);
        if (n == 0 || (word[k] == '+' && ++plus > 3))
            return UINT64_MAX;
        if (pool)
            format_put(pool, off + bits, n, value);
        bits += n;
    }
    return plus == 3 ? bits : UINT64_MAX;
}

uint64_t pool_word_bits(const char *word, uint32_t len)
{
    if (len == 4 && memcmp(word, "++++", 4) == 0)
        return 0; /* private: its type bits say it all */
    return code_word(word, len, NULL, 0);
}

static void put_boundary(pool_writer *pw, uint64_t w, uint64_t value)
{
    const pool_level *pl = pw->pl;
    uint64_t pos = (value >> pl->low_width) + w;
    format_put(pw->pool, pl->low_off + w * pl->low_width, pl->low_width, value);
    format_put(pw->pool, pl->high_off + pos, 1, 1);
    if (w % POOL_SELECT_STRIDE == 0)
        format_put(pw->pool, pl->select_off + w / POOL_SELECT_STRIDE * pl->select_width,
                   pl->select_width, pos);
}

void pool_writer_pixel(pool_writer *pw, int kind, const char *word, uint32_t len)
{
    const pool_level *pl = pw->pl;
    if (pw->g % POOL_BLOCK_PIXELS == 0) {
        uint64_t at = pool_counts_bit(pl, pw->g / POOL_BLOCK_PIXELS);
        format_put(pw->pool, at, pl->refined_width, pw->refined);
        format_put(pw->pool, at + pl->refined_width, pl->stabbed_width, pw->stabbed);
    }
    uint64_t type = pool_type_bit(pl, pw->g++);
    if (kind == POOL_REFINED) {
        format_put(pw->pool, type, 2, 2);
        pw->refined++;
    } else if (kind == POOL_STABBED) {
        format_put(pw->pool, type, 2, 1);
        put_boundary(pw, pw->stabbed++, pw->at);
        pw->at += code_word(word, len, pw->pool, pl->stream_off + pw->at);
    }
}

void pool_writer_finish(pool_writer *pw)
{
    if (pw->stabbed)
        put_boundary(pw, pw->stabbed, pw->at);
}

