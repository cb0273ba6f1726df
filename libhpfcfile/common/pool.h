/*
 * pool.h: the compact pool layout (spec/hpfc-format.md §5.3), chosen per
 * file by the incompat flag FORMAT_INCOMPAT_COMPACT_POOL. Internal to the
 * library (and its tests).
 *
 * Why a layout of its own: the paper's pools give every word of a level a
 * slot as long as the level's longest word and every refined pixel a
 * stored address. Here every level (the root included, as one image) is
 *
 *   type pairs | block counts | select samples | EF low | EF high | word stream
 *
 * - two type bits a pixel (refined, stabbed; 00 is a private word pixel,
 *   which costs nothing more), then for each block of 128 pixels the
 *   counts of refined and stabbed pixels before it: a pixel's child image
 *   is the rank of its refined bit, its word the rank of its stabbed bit,
 *   both O(1) (the pairs of a block are four aligned 64-bit words);
 * - the stabbed words back to back in one stream, each with a context code
 *   (pool_word_bits) and without its fourth '+';
 * - the word boundaries as an Elias-Fano sequence, with the position of
 *   every 64th one of its high bits sampled, so word w is found in O(1)
 *   from w without decoding any other word.
 *
 * Everything a reader needs comes from the level table (counts, the
 * stabbed count and the stream's length in the entry's last 16 bytes):
 * open derives it in O(levels) and builds nothing.
 */
#ifndef HPFC_POOL_H
#define HPFC_POOL_H

#include <stdbool.h>
#include <stdint.h>

#include "format.h"

enum {
    FORMAT_INCOMPAT_COMPACT_POOL = 0x1, /* header incompat_flags bit 0 */
    POOL_BLOCK_PIXELS = 128,            /* pixels of a type block */
    POOL_SELECT_STRIDE = 64,            /* one select sample every 64 boundaries */
    POOL_MAX_WORD_BITS = (1u << 20) - 1,/* k_w: a crossing costs >= 1 bit, keys hold 20 */
};

/* Pixel kinds in the type bits. */
enum { POOL_PRIVATE = 0, POOL_STABBED = 1, POOL_REFINED = 2 };

/* Compact level table fields: the paper layout's reserved bytes 48..63. */
FORMAT_FIELD(lvl, stabbed_pixels, 48, 8, uint64_t)
FORMAT_FIELD(lvl, stream_bits, 56, 8, uint64_t)

/* The geometry of one compact level, a function of its counts only. */
typedef struct pool_level {
    uint64_t pixels;        /* P = images * pixels per image */
    uint64_t refined;       /* n_@ */
    uint64_t stabbed;       /* n_s */
    uint64_t stream_bits;   /* U */
    uint32_t refined_width; /* kr: bits of a block's refined count */
    uint32_t stabbed_width; /* ks */
    uint64_t blocks;
    uint64_t type_bits;     /* 2P + blocks * (kr + ks): pairs, then counts */
    uint64_t bounds;        /* N = n_s + 1 word boundaries (0 when n_s = 0) */
    uint32_t low_width;     /* Lw */
    uint32_t select_width;  /* ks_el */
    uint64_t select_count;
    uint64_t select_off, low_off, high_off, high_bits, stream_off;
    uint64_t pool_bits;     /* s^l */
} pool_level;

/* ---- the layout (common/pool_layout.c; the code: common/pool_code.h) ---- */

/* Fills pl from the counts; false when a size overflows 64 bits. */
bool pool_level_sizes(pool_level *pl, uint64_t pixels, uint64_t refined, uint64_t stabbed,
                      uint64_t stream_bits);


/* ---- reading (read/pool_read.c; every function checks what it reads
 * against the pool) ---- */

/* What the type bits say of pixel g (< P) of a level. */
typedef struct pool_pixel {
    int kind;          /* POOL_PRIVATE, POOL_STABBED, POOL_REFINED */
    uint64_t refined;  /* refined pixels before g: a refined pixel's child image */
    uint64_t stabbed;  /* stabbed pixels before g: a stabbed pixel's word */
} pool_pixel;

/* HPFC_E_CORRUPT for type bits 11 or counts beyond the level's. */
int pool_read_pixel(const format_bits *pool, const pool_level *pl, uint64_t g, pool_pixel *out);
/* Only the kind of pixel g (HPFC_E_CORRUPT for 11): one load. */
int pool_read_type(const format_bits *pool, const pool_level *pl, uint64_t g, int *kind);
/* The pixels of `kind` (POOL_REFINED or POOL_STABBED) before g, for a pixel
 * g of that kind: HPFC_E_CORRUPT when that is not below the level's count. */
int pool_rank(const format_bits *pool, const pool_level *pl, uint64_t g, int kind, uint64_t *rank);
/* Pool bit of pixel g's type bits: the pixel's unique position. */
uint64_t pool_type_bit(const pool_level *pl, uint64_t g);
/* The pixel whose type bits start at pool bit `bit`; false if none does. */
bool pool_pixel_at_bit(const pool_level *pl, uint64_t bit, uint64_t *g);
/* Word w's code, [*start, *end) in pool bits: HPFC_E_CORRUPT when the
 * boundaries run past the index or the stream, overlap, or make a word
 * longer than k_w (`longest`). */
int pool_word_span(const format_bits *pool, const pool_level *pl, uint32_t longest, uint64_t w,
                   uint64_t *start, uint64_t *end);
/* Decodes the code in [start, end) as a word (the fourth '+' appended);
 * stores its first `cap` symbols when buf is non-NULL, *len its length.
 * HPFC_E_CORRUPT when it does not hold exactly three '+' or a symbol is
 * cut by its end; HPFC_E_ARG when buf is too small. */
int pool_decode_word(const format_bits *pool, uint64_t start, uint64_t end, char *buf, size_t cap,
                     size_t *len);

/* The whole level, O(pool): block counts, type bits, every boundary, select
 * sample and word, k_w the longest code. *what names the first fault. */
int pool_check_level(const format_bits *pool, const pool_level *pl, uint32_t longest,
                     const char **what);

/* ---- writing (write/pool_write.c) -------------------------------------- */

/* Bits of a word's compact code (0 for "++++", which is no stabbed word);
 * UINT64_MAX when the word is not symbols ending at their fourth '+'. */
uint64_t pool_word_bits(const char *word, uint32_t len);

/* Emits one level's pixels in pool order into a zeroed pool. */
typedef struct pool_writer {
    uint8_t *pool;
    const pool_level *pl;
    uint64_t g, refined, stabbed, at; /* pixels, counts and stream bits so far */
} pool_writer;

void pool_writer_pixel(pool_writer *pw, int kind, const char *word, uint32_t len);
/* After the last pixel: the end boundary of the last word. */
void pool_writer_finish(pool_writer *pw);

#endif
