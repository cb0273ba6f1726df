/*
 * The compact pool layout read (pool.h, spec/hpfc-format.md §5.3): the word
 * code decoded, O(1) pixel and word access, and the whole level checked.
 */
#include "pool_code.h"

/* The decoder's state from one window of bits to the next. */
typedef struct decode_state {
    int ctx;
    unsigned plus;
    size_t n;
} decode_state;

/* Decodes codes from the first `have` bits of window (the bits past them
 * zeros) while at least `keep` bits are left, so that no code is cut when
 * keep >= 6 (the longest code); with keep = 1, to the window's end.
 * Returns the bits left, negative when the last code overran the window.
 * A fourth '+' is not checked here: the caller checks the count at the end. */

static int decode_window(uint64_t *window, int have, int keep, decode_state *d, char *buf,
                         size_t cap)
{
    /* locals, since a store through buf (a char pointer) may alias *d */
    uint64_t w = *window;
    size_t n = d->n;
    unsigned plus = d->plus;
    int ctx = d->ctx;
    while (have >= keep) {
        unsigned ones = (unsigned)__builtin_clzll(~w | 1);
        const code_entry *e = &codes[ctx][ones < CODE_ONES_CAP ? ones : CODE_ONES_CAP];
        if (n < cap)
            buf[n] = e->symbol;
        n++;
        plus += e->symbol == '+';
        w <<= e->bits;
        have -= e->bits;
        ctx = e->next;
    }
    *window = w;
    *d = (decode_state){ctx, plus, n};
    return have;
}

int pool_decode_word(const format_bits *pool, uint64_t start, uint64_t end, char *buf, size_t cap,
                     size_t *len)
{
    decode_state d = {CTX_NONE, 0, 0};
    if (!buf)
        cap = 0;
    if (end < start)
        return HPFC_E_CORRUPT;
    uint64_t pos = start, window = 0;
    int have = 0; /* bits of the word left-aligned in window */
    /* a long word: refill whenever fewer bits than the longest code are left */
    while (end - pos > (uint64_t)(56 - have)) {
        unsigned take = (unsigned)(56 - have);
        window |= format_peek(pool, pos, take) >> have;
        have = decode_window(&window, have + (int)take, 6, &d, buf, cap);
        pos += take;
    }
    /* the word's last bits: decode to the end */
    unsigned take = (unsigned)(end - pos);
    window |= format_peek(pool, pos, take) >> have;
    if (decode_window(&window, have + (int)take, 1, &d, buf, cap) < 0)
        return HPFC_E_CORRUPT; /* a code cut by the word's end */
    if (d.plus != 3 || d.n == 3)
        return HPFC_E_CORRUPT; /* not three '+' (a fourth ends a word: none is stored),
                                  or "++++" where the type bits say stabbed */
    if (d.n < cap)
        buf[d.n] = '+';
    *len = ++d.n;
    return buf && d.n > cap ? HPFC_E_BUFFER_SMALL : HPFC_OK;
}

/* ---- pixels ------------------------------------------------------------------------ */

/* In a left-aligned window of type pairs, the refined bits are the odd
 * positions from the top (63, 61, ...), the stabbed bits the even ones. */
#define REFINED_BITS 0xAAAAAAAAAAAAAAAAull
#define STABBED_BITS 0x5555555555555555ull

int pool_read_pixel(const format_bits *pool, const pool_level *pl, uint64_t g, pool_pixel *out)
{
    uint64_t block = g / POOL_BLOCK_PIXELS;
    uint64_t at = pool_counts_bit(pl, block); /* < type_bits <= s^l: open checked the sizes */
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
    uint64_t block = g / POOL_BLOCK_PIXELS, at = pool_counts_bit(pl, block), count;
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
 * ones(w)), without a loop over the bytes: the bytes' running counts from
 * the top are the products of one multiplication, and one subtraction
 * compares all eight with skip + 1 (every count is at most 64, so the
 * bytes never borrow from each other); then at most 7 steps in the byte. */
static unsigned select_in_word(uint64_t w, uint64_t skip)
{
    const uint64_t ones8 = 0x0101010101010101ull, high8 = 0x8080808080808080ull;
    uint64_t r = __builtin_bswap64(w); /* the top byte of w is r's lowest */
    uint64_t c = r - ((r >> 1) & 0x5555555555555555ull);
    c = (c & 0x3333333333333333ull) + ((c >> 2) & 0x3333333333333333ull);
    c = (c + (c >> 4)) & 0x0F0F0F0F0F0F0F0Full;
    uint64_t running = c * ones8; /* byte k: ones in w's top k + 1 bytes */
    uint64_t reached = ((running | high8) - (skip + 1) * ones8) & high8;
    unsigned byte = (unsigned)__builtin_ctzll(reached) / 8;
    if (byte)
        skip -= (running >> (8 * (byte - 1))) & 0xFF;
    unsigned bits = (unsigned)(w >> (56 - 8 * byte)) & 0xFF;
    while (skip--)
        bits &= ~(0x80u >> (__builtin_clz(bits) - 24));
    return 8 * byte + (unsigned)__builtin_clz(bits) - 24;
}

/* The one of the high bits `skip` ones after the first at or after
 * `from` (*here), and the next one after it (*next). With `sampled`, the
 * bit at `from` must itself be a one (a select sample names a boundary). */
static int select_pair(const format_bits *pool, const pool_level *pl, uint64_t from, uint64_t skip,
                       bool sampled, uint64_t *here, uint64_t *next)
{
    uint64_t end = pl->high_bits;
    bool found = false;
    if (sampled && (from >= end || !(format_peek(pool, pl->high_off + from, 1) >> 63)))
        return HPFC_E_CORRUPT; /* a sample that names no boundary */
    while (from < end) {
        unsigned k = end - from < 56 ? (unsigned)(end - from) : 56;
        uint64_t w = format_peek(pool, pl->high_off + from, k);
        if (!found) {
            uint64_t ones = format_ones(w);
            if (ones <= skip) {
                skip -= ones;
                from += k;
                continue;
            }
            unsigned at = select_in_word(w, skip);
            *here = from + at;
            found = true;
            w = at < 63 ? w << (at + 1) : 0; /* the bits after *here */
            if (w) {
                *next = *here + 1 + (unsigned)__builtin_clzll(w);
                return HPFC_OK;
            }
        } else if (w) {
            *next = from + (unsigned)__builtin_clzll(w);
            return HPFC_OK;
        }
        from += k;
    }
    return HPFC_E_CORRUPT; /* the boundaries run past the index */
}

/* The first one of the high bits at or after `from`, skipping `skip` ones
 * (the verifier's sequential walk). */
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
    uint64_t here, next, a, b;
    int st = select_pair(pool, pl, sample, w % POOL_SELECT_STRIDE, true, &here, &next);
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

/* ---- the whole level, for verification -------------------------------------------------------- */

static int check_types(const format_bits *pool, const pool_level *pl, const char **what)
{
    uint64_t refined = 0, stabbed = 0;
    for (uint64_t g = 0; g < pl->pixels; g++) {
        if (g % POOL_BLOCK_PIXELS == 0) {
            uint64_t at = pool_counts_bit(pl, g / POOL_BLOCK_PIXELS);
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
