/*
 * The compact pool layout (pool.h, spec/hpfc-format.md §16): sizes, the
 * word code, O(1) pixel and word access, and the level writer.
 */
#include "pool.h"

#include <string.h>

/* ---- the word code ----------------------------------------------------------- */

/* The code of a symbol depends on its context, the last crossing symbol
 * before it in the word (the '+' do not change it): none yet, '[', '(' or
 * 'Y', or one that closes a group (']', ')', '='). In each context the
 * symbols the grammar (§3.8) allows there are listed by frequency on the
 * Delaunay and GIS maps measured for the issue; the k-th costs k + 1 bits,
 * k ones then a zero, the last one only its ones. Decoding counts the
 * leading ones: no table, no reserved code. */
enum { CTX_NONE, CTX_STABBING, CTX_JUNCTION, CTX_CLOSED };
static const char *const ctx_symbols[4] = {"[(+=", "+][(=", "+Y)[(=", "+][Y)(="};
static const unsigned ctx_last[4] = {3, 4, 5, 6}; /* index of the all-ones code */

static int next_context(int ctx, char c)
{
    switch (c) {
    case '+': return ctx;
    case '[': return CTX_STABBING;
    case '(': case 'Y': return CTX_JUNCTION;
    default: return CTX_CLOSED;
    }
}

/* The code of c in ctx: its length (0 when the context does not allow c). */
static unsigned symbol_code(int ctx, char c, uint64_t *value)
{
    const char *s = ctx_symbols[ctx];
    for (unsigned k = 0; s[k]; k++)
        if (s[k] == c) {
            unsigned last = ctx_last[ctx];
            *value = k < last ? (((uint64_t)1 << k) - 1) << 1 : ((uint64_t)1 << last) - 1;
            return k < last ? k + 1 : last;
        }
    return 0;
}

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
        unsigned n = symbol_code(ctx, word[k], &value);
        if (n == 0 || (word[k] == '+' && ++plus > 3))
            return UINT64_MAX;
        if (pool)
            format_put(pool, off + bits, n, value);
        bits += n;
        ctx = next_context(ctx, word[k]);
    }
    return plus == 3 ? bits : UINT64_MAX;
}

uint64_t pool_word_bits(const char *word, uint32_t len)
{
    if (len == 4 && memcmp(word, "++++", 4) == 0)
        return 0; /* private: its type bits say it all */
    return code_word(word, len, NULL, 0);
}

int pool_decode_word(const format_bits *pool, uint64_t start, uint64_t end, char *buf, size_t cap,
                     size_t *len)
{
    uint64_t pos = start, window = 0;
    unsigned plus = 0, have = 0; /* `have` bits of the word left-aligned in window */
    int ctx = CTX_NONE;
    size_t n = 0;
    while (pos < end || have) {
        if (have < 6 && pos < end) { /* a code has at most 6 bits: refill */
            uint64_t left = end - pos;
            unsigned take = left < 56 - have ? (unsigned)left : 56 - have;
            window |= format_peek(pool, pos, take) >> have;
            have += take;
            pos += take;
        }
        /* leading ones (the window's bits past `have` are zeros) */
        unsigned ones = (unsigned)__builtin_clzll(~window | 1), last = ctx_last[ctx];
        unsigned k = ones < last ? ones : last, bits = ones < last ? ones + 1 : last;
        if (bits > have)
            return HPFC_E_CORRUPT; /* a code cut by the word's end */
        char c = ctx_symbols[ctx][k];
        if (c == '+' && ++plus > 3)
            return HPFC_E_CORRUPT; /* the fourth '+' ends a word: none is stored */
        if (buf && n < cap)
            buf[n] = c;
        n++;
        window <<= bits;
        have -= bits;
        ctx = next_context(ctx, c);
    }
    if (plus != 3 || n == 3)
        return HPFC_E_CORRUPT; /* not a word, or "++++" where the type bits say stabbed */
    if (buf && n < cap)
        buf[n] = '+';
    *len = ++n;
    return buf && n > cap ? HPFC_E_ARG : HPFC_OK;
}

/* ---- sizes -------------------------------------------------------------------- */

/* Bits of an unsigned integer: the width that holds 0 .. v. */
static uint32_t bit_width(uint64_t v)
{
    return v ? (uint32_t)(64 - __builtin_clzll(v)) : 0;
}

bool pool_level_sizes(pool_level *pl, uint64_t pixels, uint64_t refined, uint64_t stabbed,
                      uint64_t stream_bits)
{
    *pl = (pool_level){.pixels = pixels, .refined = refined, .stabbed = stabbed,
                       .stream_bits = stream_bits};
    pl->refined_width = bit_width(refined);
    pl->stabbed_width = bit_width(stabbed);
    pl->blocks = pixels / POOL_BLOCK_PIXELS + (pixels % POOL_BLOCK_PIXELS != 0);
    uint64_t s, t;
    if (!format_mul(pl->blocks, (uint64_t)pl->refined_width + pl->stabbed_width, &s) ||
        !format_mul(pixels, 2, &t) || !format_add(s, t, &pl->type_bits))
        return false;
    pl->select_off = pl->low_off = pl->high_off = pl->stream_off = pl->pool_bits = pl->type_bits;
    if (stabbed == 0)
        return true;
    if (stabbed == UINT64_MAX)
        return false;
    pl->bounds = stabbed + 1;
    uint64_t q = stream_bits / pl->bounds;
    pl->low_width = q ? (uint32_t)(63 - __builtin_clzll(q)) : 0;
    if (!format_add(pl->bounds, stream_bits >> pl->low_width, &pl->high_bits))
        return false;
    pl->select_width = bit_width(pl->high_bits - 1);
    pl->select_count = pl->bounds / POOL_SELECT_STRIDE + (pl->bounds % POOL_SELECT_STRIDE != 0);
    pl->select_off = pl->type_bits;
    return format_mul(pl->select_count, pl->select_width, &s) &&
           format_add(pl->select_off, s, &pl->low_off) &&
           format_mul(pl->bounds, pl->low_width, &s) && format_add(pl->low_off, s, &pl->high_off) &&
           format_add(pl->high_off, pl->high_bits, &pl->stream_off) &&
           format_add(pl->stream_off, stream_bits, &pl->pool_bits);
}

/* ---- pixels ------------------------------------------------------------------------ */

uint64_t pool_type_bit(const pool_level *pl, uint64_t g)
{
    (void)pl;
    return 2 * g;
}

/* Where block b's counts start: after all the type pairs. */
static uint64_t counts_bit(const pool_level *pl, uint64_t block)
{
    return 2 * pl->pixels + block * ((uint64_t)pl->refined_width + pl->stabbed_width);
}

bool pool_pixel_at_bit(const pool_level *pl, uint64_t bit, uint64_t *g)
{
    if (bit % 2 || bit / 2 >= pl->pixels)
        return false;
    *g = bit / 2;
    return true;
}

/* In a left-aligned window of type pairs, the refined bits are the odd
 * positions from the top (63, 61, ...), the stabbed bits the even ones. */
#define REFINED_BITS 0xAAAAAAAAAAAAAAAAull
#define STABBED_BITS 0x5555555555555555ull

int pool_read_pixel(const format_bits *pool, const pool_level *pl, uint64_t g, pool_pixel *out)
{
    uint64_t block = g / POOL_BLOCK_PIXELS;
    uint64_t at = counts_bit(pl, block); /* < type_bits <= s^l: open checked the sizes */
    /* the block's counts (one load when they fit 57 bits), then its pairs */
    unsigned kr = pl->refined_width, ks = pl->stabbed_width;
    uint64_t refined, stabbed;
    if (kr + ks <= 57 && kr && ks) {
        uint64_t head = format_peek(pool, at, kr + ks);
        refined = head >> (64 - kr);
        stabbed = head << kr >> (64 - ks);
    } else {
        refined = format_get(pool, at, kr);
        stabbed = format_get(pool, at + kr, ks);
    }
    /* the pairs of the block before g: whole aligned 64-bit words (32 pairs;
     * pools start on 8-byte boundaries), then the top of g's own word */
    uint64_t word = g / 32, w;
    for (uint64_t k = block * (POOL_BLOCK_PIXELS / 32); k < word; k++) {
        w = format_window(pool, 8 * k);
        refined += format_ones(w & REFINED_BITS);
        stabbed += format_ones(w & STABBED_BITS);
    }
    w = format_window(pool, 8 * word);
    unsigned shift = 2 * (unsigned)(g % 32); /* bits of g's word before its pair */
    uint64_t before = shift ? w & ~(UINT64_MAX >> shift) : 0;
    refined += format_ones(before & REFINED_BITS);
    stabbed += format_ones(before & STABBED_BITS);
    unsigned type = (unsigned)(w << shift >> 62);
    if (type == 3)
        return HPFC_E_CORRUPT; /* refined and stabbed */
    out->kind = type == 2 ? POOL_REFINED : type == 1 ? POOL_STABBED : POOL_PRIVATE;
    out->refined = refined;
    out->stabbed = stabbed;
    if ((type == 2 && refined >= pl->refined) || (type == 1 && stabbed >= pl->stabbed))
        return HPFC_E_CORRUPT; /* counts that disagree with the level table */
    return HPFC_OK;
}

int pool_read_type(const format_bits *pool, const pool_level *pl, uint64_t g, int *kind)
{
    (void)pl;
    unsigned type = (unsigned)(format_window(pool, g / 32 * 8) << 2 * (g % 32) >> 62);
    *kind = type == 2 ? POOL_REFINED : type == 1 ? POOL_STABBED : POOL_PRIVATE;
    return type == 3 ? HPFC_E_CORRUPT : HPFC_OK;
}

int pool_rank(const format_bits *pool, const pool_level *pl, uint64_t g, int kind, uint64_t *rank)
{
    uint64_t block = g / POOL_BLOCK_PIXELS, at = counts_bit(pl, block), count;
    uint64_t bits = kind == POOL_REFINED ? REFINED_BITS : STABBED_BITS;
    if (kind == POOL_REFINED)
        count = format_get(pool, at, pl->refined_width);
    else
        count = format_get(pool, at + pl->refined_width, pl->stabbed_width);
    uint64_t word = g / 32;
    for (uint64_t k = block * (POOL_BLOCK_PIXELS / 32); k < word; k++)
        count += format_ones(format_window(pool, 8 * k) & bits);
    unsigned shift = 2 * (unsigned)(g % 32);
    if (shift)
        count += format_ones(format_window(pool, 8 * word) & bits & ~(UINT64_MAX >> shift));
    *rank = count;
    if (count >= (kind == POOL_REFINED ? pl->refined : pl->stabbed))
        return HPFC_E_CORRUPT; /* counts that disagree with the level table */
    return HPFC_OK;
}

/* ---- words ---------------------------------------------------------------------------- */

/* Position from the top of the one of w after `skip` others (skip <
 * ones(w)): a byte at a time, then a bit at a time (at most 7). */
static unsigned select_in_word(uint64_t w, uint64_t skip)
{
    unsigned pos = 0;
    for (uint64_t c; skip >= (c = format_ones(w >> 56)); w <<= 8, pos += 8)
        skip -= c;
    while (skip--)
        w &= ~((uint64_t)1 << 63 >> __builtin_clzll(w));
    return pos + (unsigned)__builtin_clzll(w);
}

/* The first one of the high bits at or after `from`, skipping `skip` ones. */
static int select_from(const format_bits *pool, const pool_level *pl, uint64_t from, uint64_t skip,
                       uint64_t *pos)
{
    uint64_t end = pl->high_bits;
    while (from < end) {
        unsigned k = end - from < 56 ? (unsigned)(end - from) : 56;
        uint64_t w = format_peek(pool, pl->high_off + from, k);
        uint64_t ones = format_ones(w);
        if (ones <= skip) {
            skip -= ones;
            from += k;
            continue;
        }
        *pos = from + select_in_word(w, skip);
        return HPFC_OK;
    }
    return HPFC_E_CORRUPT; /* the boundaries run past the index */
}

/* Boundary w from the position of its one in the high bits. */
static int boundary(const format_bits *pool, const pool_level *pl, uint64_t w, uint64_t pos,
                    uint64_t *value)
{
    if (pos < w)
        return HPFC_E_CORRUPT;
    uint64_t low = format_get(pool, pl->low_off + w * pl->low_width, pl->low_width);
    *value = (pos - w) << pl->low_width | low;
    return HPFC_OK;
}

int pool_word_span(const format_bits *pool, const pool_level *pl, uint32_t longest, uint64_t w,
                   uint64_t *start, uint64_t *end)
{
    if (w >= pl->stabbed)
        return HPFC_E_CORRUPT;
    uint64_t t = w / POOL_SELECT_STRIDE;
    uint64_t sample = format_get(pool, pl->select_off + t * pl->select_width, pl->select_width);
    if (sample >= pl->high_bits || !format_get(pool, pl->high_off + sample, 1))
        return HPFC_E_CORRUPT; /* a sample that names no boundary */
    uint64_t here, next, a, b;
    int st = select_from(pool, pl, sample, w % POOL_SELECT_STRIDE, &here);
    if (!st)
        st = select_from(pool, pl, here + 1, 0, &next);
    if (!st)
        st = boundary(pool, pl, w, here, &a);
    if (!st)
        st = boundary(pool, pl, w + 1, next, &b);
    if (st)
        return st;
    if (a >= b || b > pl->stream_bits || b - a > longest)
        return HPFC_E_CORRUPT; /* overlapping, empty, too long or past the stream */
    *start = pl->stream_off + a;
    *end = pl->stream_off + b;
    return HPFC_OK;
}

/* ---- writing ----------------------------------------------------------------------------- */

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
        uint64_t at = counts_bit(pl, pw->g / POOL_BLOCK_PIXELS);
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

/* ---- the whole level, for verification -------------------------------------------------------- */

static int check_types(const format_bits *pool, const pool_level *pl, const char **what)
{
    uint64_t refined = 0, stabbed = 0;
    for (uint64_t g = 0; g < pl->pixels; g++) {
        if (g % POOL_BLOCK_PIXELS == 0) {
            uint64_t at = counts_bit(pl, g / POOL_BLOCK_PIXELS);
            if (format_get(pool, at, pl->refined_width) != refined ||
                format_get(pool, at + pl->refined_width, pl->stabbed_width) != stabbed) {
                *what = "a type block's counts disagree with the pixels before it";
                return HPFC_E_CORRUPT;
            }
        }
        unsigned type = (unsigned)(format_peek(pool, pool_type_bit(pl, g), 2) >> 62);
        if (type == 3) {
            *what = "a pixel's type bits say both refined and stabbed";
            return HPFC_E_CORRUPT;
        }
        refined += type == 2;
        stabbed += type == 1;
    }
    if (refined != pl->refined || stabbed != pl->stabbed) {
        *what = "the type bits disagree with the level table's counts";
        return HPFC_E_CORRUPT;
    }
    return HPFC_OK;
}

static int check_words(const format_bits *pool, const pool_level *pl, uint32_t longest,
                       const char **what)
{
    uint64_t pos = 0, prev = 0, most = 0;
    for (uint64_t w = 0; w < pl->bounds; w++, pos++) {
        uint64_t value, len;
        if (select_from(pool, pl, pos, 0, &pos) || boundary(pool, pl, w, pos, &value)) {
            *what = "the word index has fewer boundaries than stabbed words";
            return HPFC_E_CORRUPT;
        }
        if (w % POOL_SELECT_STRIDE == 0 &&
            format_get(pool, pl->select_off + w / POOL_SELECT_STRIDE * pl->select_width,
                       pl->select_width) != pos) {
            *what = "a select sample names the wrong boundary";
            return HPFC_E_CORRUPT;
        }
        if ((w == 0 && value != 0) || (w > 0 && value <= prev) ||
            (w + 1 == pl->bounds && value != pl->stream_bits)) {
            *what = "word boundaries that overlap or do not span the stream";
            return HPFC_E_CORRUPT;
        }
        if (w > 0) {
            size_t n;
            len = value - prev;
            most = len > most ? len : most;
            if (len > longest ||
                pool_decode_word(pool, pl->stream_off + prev, pl->stream_off + value, NULL, 0, &n)) {
                *what = "a stabbed word does not decode within k_w bits";
                return HPFC_E_CORRUPT;
            }
        }
        prev = value;
    }
    if (pos < pl->high_bits && !select_from(pool, pl, pos, 0, &pos)) {
        *what = "the word index has more boundaries than stabbed words";
        return HPFC_E_CORRUPT;
    }
    if (most != longest) {
        *what = "word_bits is not the longest stabbed word's code";
        return HPFC_E_CORRUPT;
    }
    return HPFC_OK;
}

int pool_check_level(const format_bits *pool, const pool_level *pl, uint32_t longest,
                     const char **what)
{
    int st = check_types(pool, pl, what);
    return st ? st : check_words(pool, pl, longest, what);
}
