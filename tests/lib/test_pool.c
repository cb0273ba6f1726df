/*
 * Unit tests of the compact pool's word code (libhpfcfile/pool.c, spec
 * §5.3.4) and of its Elias-Fano word index, against an encoder written here
 * from the spec's table alone: random words in every context, short and
 * long (past the decoder's 56-bit windows), at every bit offset of a
 * pool; truncated codes, a fourth '+' and "++++" rejected; and every
 * word span of a level written by pool_writer, found back by
 * pool_word_span.
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "pool.h"

/* Spec §5.3.4: per context, the symbols in code order; the k-th of m + 1 is
 * k ones then a zero, the last m ones. */
static const char *const spec_symbols[4] = {"[(+=", "+][(=", "+Y)[(=", "+][Y)(="};

static int spec_context(int ctx, char c)
{
    switch (c) {
    case '+': return ctx;
    case '[': return 1;
    case '(': case 'Y': return 2;
    default: return 3;
    }
}

/* Appends the code of c in ctx to bits[] as '0'/'1' characters. */
static size_t spec_code(int ctx, char c, char *bits, size_t at)
{
    const char *s = spec_symbols[ctx];
    size_t m = strlen(s) - 1, k = (size_t)(strchr(s, c) - s);
    for (size_t i = 0; i < k; i++)
        bits[at++] = '1';
    if (k < m)
        bits[at++] = '0';
    return at;
}

static uint64_t rng_state = 0x9E3779B97F4A7C15ull;
static uint64_t rng(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return rng_state;
}

/* A random word of `crossings` crossing symbols, each allowed in its
 * context, with the three '+' between them and the fourth at the end; its
 * code (all but the last '+') in bits[0 .. *nbits). */
static size_t random_word(char *word, size_t crossings, char *bits, size_t *nbits)
{
    size_t n = 0, at = 0, plus_at[3];
    for (int p = 0; p < 3; p++)
        plus_at[p] = (size_t)(rng() % (crossings + 1));
    int ctx = 0;
    for (size_t i = 0; i <= crossings; i++) {
        for (int p = 0; p < 3; p++)
            if (plus_at[p] == i) {
                word[n++] = '+';
                at = spec_code(ctx, '+', bits, at);
            }
        if (i == crossings)
            break;
        const char *s = spec_symbols[ctx];
        char c;
        do
            c = s[rng() % strlen(s)];
        while (c == '+');
        word[n++] = c;
        at = spec_code(ctx, c, bits, at);
        ctx = spec_context(ctx, c);
    }
    word[n++] = '+';
    *nbits = at;
    return n;
}

static void put_bits(uint8_t *pool, uint64_t off, const char *bits, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (bits[i] == '1')
            pool[(off + i) / 8] |= (uint8_t)(0x80 >> ((off + i) % 8));
}

static void test_code(void)
{
    enum { POOL_BYTES = 512 };
    static char word[600], bits[4000], got[600];
    static uint8_t pool[POOL_BYTES];
    for (int trial = 0; trial < 20000; trial++) {
        size_t crossings = trial % 3 == 0 ? (size_t)(rng() % 200) : (size_t)(rng() % 12);
        size_t nbits, n = random_word(word, crossings, bits, &nbits);
        CHECK_EQ_INT(pool_word_bits(word, (uint32_t)n), n == 4 ? 0 : nbits);
        if (n == 4)
            continue; /* "++++" is a private pixel: no code */
        memset(pool, 0, sizeof pool);
        uint64_t off = rng() % 64;
        put_bits(pool, off, bits, nbits);
        format_bits fb = {pool, 8 * POOL_BYTES, POOL_BYTES};
        size_t len = 0;
        CHECK_EQ_INT(pool_decode_word(&fb, off, off + nbits, got, sizeof got, &len), HPFC_OK);
        CHECK_EQ_INT(len, n);
        CHECK(memcmp(got, word, n) == 0);
        CHECK_EQ_INT(pool_decode_word(&fb, off, off + nbits, NULL, 0, &len), HPFC_OK);
        CHECK_EQ_INT(len, n);
        if (n > 1)
            CHECK_EQ_INT(pool_decode_word(&fb, off, off + nbits, got, n - 1, &len),
                         HPFC_E_BUFFER_SMALL);
        /* one bit short: a code cut, or three '+' no more */
        CHECK_EQ_INT(pool_decode_word(&fb, off, off + nbits - 1, got, sizeof got, &len),
                     HPFC_E_CORRUPT);
    }
    /* a fourth '+' inside the code, and "+++" coded as a stabbed word */
    static const char *const bad[] = {"110" "110" "110" "110", "110110110"};
    for (size_t b = 0; b < 2; b++) {
        memset(pool, 0, sizeof pool);
        put_bits(pool, 3, bad[b], strlen(bad[b]));
        format_bits fb = {pool, 8 * POOL_BYTES, POOL_BYTES};
        size_t len;
        CHECK_EQ_INT(pool_decode_word(&fb, 3, 3 + strlen(bad[b]), got, sizeof got, &len),
                     HPFC_E_CORRUPT);
    }
}

/* A level of random pixels written by pool_writer: every stabbed word's
 * span and code found back through the index. */
static void test_index(void)
{
    for (int trial = 0; trial < 40; trial++) {
        uint64_t pixels = 1 + rng() % 3000;
        int *kind = malloc(pixels * sizeof *kind);
        char (*words)[600] = malloc(pixels * sizeof *words);
        size_t *lens = malloc(pixels * sizeof *lens);
        uint64_t refined = 0, stabbed = 0, stream = 0;
        static char bits[4000];
        for (uint64_t g = 0; g < pixels; g++) {
            uint64_t r = rng() % 10;
            kind[g] = r < 2 ? POOL_REFINED : r < 6 ? POOL_STABBED : POOL_PRIVATE;
            if (kind[g] != POOL_STABBED)
                continue;
            size_t nbits;
            do
                lens[g] = random_word(words[g], (size_t)(rng() % (trial % 4 ? 8 : 90)), bits,
                                      &nbits);
            while (lens[g] == 4);
            /* the writer's own count sizes the level (a code that disagrees
             * with the spec's is reported, not written past the pool) */
            uint64_t b = pool_word_bits(words[g], (uint32_t)lens[g]);
            CHECK_EQ_INT(b, nbits);
            stream += b;
        }
        for (uint64_t g = 0; g < pixels; g++) {
            refined += kind[g] == POOL_REFINED;
            stabbed += kind[g] == POOL_STABBED;
        }
        pool_level pl;
        CHECK(pool_level_sizes(&pl, pixels, refined, stabbed, stream));
        uint64_t bytes = (pl.pool_bits + 7) / 8 + 8;
        uint8_t *pool = calloc(bytes, 1);
        pool_writer pw = {.pool = pool, .pl = &pl};
        uint32_t longest = 0;
        for (uint64_t g = 0; g < pixels; g++) {
            pool_writer_pixel(&pw, kind[g], kind[g] == POOL_STABBED ? words[g] : NULL,
                              kind[g] == POOL_STABBED ? (uint32_t)lens[g] : 0);
            if (kind[g] == POOL_STABBED) {
                uint64_t b = pool_word_bits(words[g], (uint32_t)lens[g]);
                longest = b > longest ? (uint32_t)b : longest;
            }
        }
        pool_writer_finish(&pw);
        format_bits fb = {pool, pl.pool_bits, bytes};
        const char *what = NULL;
        CHECK_EQ_INT(pool_check_level(&fb, &pl, longest, &what), HPFC_OK);
        uint64_t w = 0, at = 0;
        for (uint64_t g = 0; g < pixels; g++) {
            pool_pixel px;
            CHECK_EQ_INT(pool_read_pixel(&fb, &pl, g, &px), HPFC_OK);
            CHECK_EQ_INT(px.kind, kind[g]);
            if (kind[g] != POOL_STABBED)
                continue;
            uint64_t rank, start, end;
            CHECK_EQ_INT(pool_rank(&fb, &pl, g, POOL_STABBED, &rank), HPFC_OK);
            CHECK_EQ_INT(rank, w);
            CHECK_EQ_INT(pool_word_span(&fb, &pl, longest, w, &start, &end), HPFC_OK);
            uint64_t b = pool_word_bits(words[g], (uint32_t)lens[g]);
            CHECK_EQ_INT(start, pl.stream_off + at);
            CHECK_EQ_INT(end - start, b);
            char got[600];
            size_t len = 0;
            CHECK_EQ_INT(pool_decode_word(&fb, start, end, got, sizeof got, &len), HPFC_OK);
            CHECK(len == lens[g] && memcmp(got, words[g], len) == 0);
            at += b;
            w++;
        }
        free(pool);
        free(kind);
        free(words);
        free(lens);
    }
}

int main(void)
{
    test_code();
    test_index();
    return check_report("pool");
}
