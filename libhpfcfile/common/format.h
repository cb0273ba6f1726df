/*
 * format.h: the .hpfc binary format (spec/hpfc-format.md) as the writer
 * and the reader see it: the format version it writes is FORMAT_MAJOR.
 * FORMAT_MINOR below, hpfc.h's HPFC_FORMAT_MAJOR and HPFC_FORMAT_MINOR
 * (1.3), not the library's own (hpfc_version.h, from meson's project
 * version). Internal to the library (and its tests).
 *
 * - Every field of the header, the level table and the section directory is
 *   touched only through the get/set helpers below, named after the spec's
 *   fields; they are explicit little-endian loads and stores, never a struct
 *   cast over file bytes.
 * - Pools are MSB-first bit streams: bit b of a pool is bit 7 - (b & 7) of
 *   byte b >> 3, and a k-bit field is stored most significant bit first.
 * - format_level_sizes() is the one place where k_@ and s are derived from
 *   the per-level counts (paper Sect. 4.4); the writer uses it to lay the
 *   pools out and the reader to check the level table.
 */
#ifndef HPFC_FORMAT_H
#define HPFC_FORMAT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "hpfc.h"

/* ---- sizes and constants ------------------------------------------------- */

enum {
    FORMAT_MAJOR = HPFC_FORMAT_MAJOR,
    FORMAT_MINOR = HPFC_FORMAT_MINOR, /* 1.1: FEAT; 1.2: LABL, ATTR, EDGF, GEOM, the compact pool; 1.3: SHIX */
    FORMAT_HEADER_SIZE = 128,       /* header_size written by this library */
    FORMAT_LEVEL_ENTRY_SIZE = 64,
    FORMAT_SECTION_ENTRY_SIZE = 32,
    FORMAT_MAX_SECTIONS = 1024,
    FORMAT_SECTION_ALIGN = 8,       /* sections and pools start at multiples of 8 */
    FORMAT_SECTION_REQUIRED = 0x1,  /* section flag: unknown tag -> refuse the file */
};

#define FORMAT_MAGIC "\x89HPFC\r\n\x1a"
#define FORMAT_MAGIC_SIZE 8
#define FORMAT_TAG_POOL "POOL"
#define FORMAT_TAG_CRS "CRS "
#define FORMAT_TAG_FEAT "FEAT"
#define FORMAT_TAG_ATTR "ATTR"
#define FORMAT_TAG_EDGF "EDGF"
#define FORMAT_TAG_SHIX "SHIX"

#define FORMAT_MAX_ROOT_PIXELS ((uint64_t)1 << 31)  /* n0 * m0 */
#define FORMAT_MAX_IMAGE_PIXELS ((uint64_t)1 << 20) /* n * m */
#define FORMAT_MAX_EXTENT ((int64_t)1 << 41)        /* W, H */
#define FORMAT_MAX_ORIGIN ((int64_t)1 << 62)        /* |x0|, |y0| */
#define FORMAT_MIN_UNIT_EXP10 (-30)
#define FORMAT_MAX_UNIT_EXP10 30
#define FORMAT_MAX_WORD_BITS ((uint32_t)1 << 22)    /* k_w: under 2^20 crossings a word */
#define FORMAT_MAX_FILE_SIZE ((uint64_t)1 << 41)    /* bit positions fit in 44 bits */
#define FORMAT_MIN_WORD_BITS 4                      /* a word has four '+' */

/* ---- little-endian integers ---------------------------------------------- */

static inline uint64_t le_load(const uint8_t *p, unsigned bytes)
{
    uint64_t v = 0;
    for (unsigned k = bytes; k-- > 0;)
        v = v << 8 | p[k];
    return v;
}

static inline void le_store(uint8_t *p, unsigned bytes, uint64_t v)
{
    for (unsigned k = 0; k < bytes; k++, v >>= 8)
        p[k] = (uint8_t)v;
}

/* FORMAT_FIELD(hdr, levels, 40, 4, uint32_t) defines hdr_get_levels(p) and
 * hdr_set_levels(p, v) for the 4-byte field at offset 40 of a structure
 * starting at p. Signed fields go through their two's complement.
 *
 * A structure's field table is a run of FORMAT_FIELD lines, one a row of
 * the spec's table for it: here, in geometry.h (GEOM), labels.h (LABL) and
 * pool.h. The runs look alike and a duplicate finder pairs them, but each
 * line names a different field; the logic they share is this macro. */
#define FORMAT_FIELD(scope, name, offset, bytes, type)                              \
    enum { scope##_OFF_##name = (offset), scope##_SIZE_##name = (bytes) };           \
    static inline type scope##_get_##name(const uint8_t *p)                          \
    {                                                                                \
        return (type)le_load(p + (offset), (bytes));                                 \
    }                                                                                \
    static inline void scope##_set_##name(uint8_t *p, type v)                        \
    {                                                                                \
        le_store(p + (offset), (bytes), (uint64_t)v);                                \
    }

/* Header (128 bytes), a field table (see FORMAT_FIELD). The magic and the
 * reserved areas are byte strings: their offsets and sizes come from the
 * enum only. */
enum {
    hdr_OFF_magic = 0, hdr_SIZE_magic = 8,
    hdr_OFF_reserved0 = 84, hdr_SIZE_reserved0 = 4,
    hdr_OFF_reserved1 = 104, hdr_SIZE_reserved1 = 16,
    hdr_OFF_reserved2 = 120, hdr_SIZE_reserved2 = 4,
};
FORMAT_FIELD(hdr, format_major, 8, 2, uint16_t)
FORMAT_FIELD(hdr, format_minor, 10, 2, uint16_t)
FORMAT_FIELD(hdr, header_size, 12, 4, uint32_t)
FORMAT_FIELD(hdr, compat_flags, 16, 4, uint32_t)
FORMAT_FIELD(hdr, incompat_flags, 20, 4, uint32_t)
FORMAT_FIELD(hdr, root_cols, 24, 4, uint32_t)
FORMAT_FIELD(hdr, root_rows, 28, 4, uint32_t)
FORMAT_FIELD(hdr, cols, 32, 4, uint32_t)
FORMAT_FIELD(hdr, rows, 36, 4, uint32_t)
FORMAT_FIELD(hdr, levels, 40, 4, uint32_t)
FORMAT_FIELD(hdr, section_count, 44, 4, uint32_t)
FORMAT_FIELD(hdr, x0, 48, 8, int64_t)
FORMAT_FIELD(hdr, y0, 56, 8, int64_t)
FORMAT_FIELD(hdr, width, 64, 8, int64_t)
FORMAT_FIELD(hdr, height, 72, 8, int64_t)
FORMAT_FIELD(hdr, unit_exp10, 80, 4, int32_t)
FORMAT_FIELD(hdr, file_size, 88, 8, uint64_t)
FORMAT_FIELD(hdr, meta_size, 96, 8, uint64_t)
FORMAT_FIELD(hdr, meta_crc32c, 124, 4, uint32_t)

/* Level table entry (64 bytes). */
enum { lvl_OFF_reserved = 48, lvl_SIZE_reserved = 16 };
FORMAT_FIELD(lvl, word_pixels, 0, 8, uint64_t)
FORMAT_FIELD(lvl, refined_pixels, 8, 8, uint64_t)
FORMAT_FIELD(lvl, images, 16, 8, uint64_t)
FORMAT_FIELD(lvl, word_bits, 24, 4, uint32_t)
FORMAT_FIELD(lvl, address_bits, 28, 4, uint32_t)
FORMAT_FIELD(lvl, pool_offset, 32, 8, uint64_t)
FORMAT_FIELD(lvl, pool_bits, 40, 8, uint64_t)

/* Section directory entry (32 bytes). The tag is four bytes, not a number. */
enum { sec_OFF_tag = 0, sec_SIZE_tag = 4, sec_OFF_reserved = 28, sec_SIZE_reserved = 4 };
FORMAT_FIELD(sec, flags, 4, 4, uint32_t)
FORMAT_FIELD(sec, offset, 8, 8, uint64_t)
FORMAT_FIELD(sec, length, 16, 8, uint64_t)
FORMAT_FIELD(sec, crc32c, 24, 4, uint32_t)

/* ATTR section (spec/hpfc-format.md §6.3): a 32-byte header, then the
 * column table (16 bytes a column), the cells (8 bytes each, row-major),
 * the null bits (one per cell, padded to 8 bytes) and the strings. Its
 * field tables, as the ones below, are FORMAT_FIELD runs (see there). */
enum { ATTR_HEADER_SIZE = 32, ATTR_COLUMN_SIZE = 16, ATTR_CELL_SIZE = 8 };
FORMAT_FIELD(attr, feature_count, 0, 4, uint32_t)
FORMAT_FIELD(attr, column_count, 4, 4, uint32_t)
FORMAT_FIELD(attr, string_bytes, 8, 8, uint64_t)
enum { attr_OFF_reserved = 16, attr_SIZE_reserved = 16 };
FORMAT_FIELD(attrc, name_offset, 0, 4, uint32_t)
FORMAT_FIELD(attrc, name_length, 4, 4, uint32_t)
FORMAT_FIELD(attrc, type, 8, 1, uint8_t)
enum { attrc_OFF_reserved = 9, attrc_SIZE_reserved = 7 };
/* A string cell: offset (4 bytes) then length (4 bytes) in the strings. */
FORMAT_FIELD(attrs, offset, 0, 4, uint32_t)
FORMAT_FIELD(attrs, length, 4, 4, uint32_t)

/* EDGF section (spec/hpfc-format.md §6.4): a 16-byte header, then
 * edge_count + 1 offsets and link_count feature indices, 4 bytes each. */
enum { EDGF_HEADER_SIZE = 16 };
FORMAT_FIELD(edgf, edge_count, 0, 4, uint32_t)
FORMAT_FIELD(edgf, link_count, 4, 4, uint32_t)
FORMAT_FIELD(edgf, feature_count, 8, 4, uint32_t)
FORMAT_FIELD(edgf, reserved, 12, 4, uint32_t)

/* SHIX section (spec/hpfc-format.md §6.8): a 32-byte header, then the
 * faces' edges and, as `tables` says, the features' faces and the
 * features' edges, each an index of rows + 1 offsets and its links,
 * bit-packed at the widths the counts give (read/shix.c). */
enum { SHIX_HEADER_SIZE = 32, SHIX_FEATURE_FACES = 0x1, SHIX_FEATURE_EDGES = 0x2 };
FORMAT_FIELD(shix, face_count, 0, 4, uint32_t)
FORMAT_FIELD(shix, edge_count, 4, 4, uint32_t)
FORMAT_FIELD(shix, feature_count, 8, 4, uint32_t)
FORMAT_FIELD(shix, tables, 12, 4, uint32_t)
FORMAT_FIELD(shix, face_links, 16, 4, uint32_t)
FORMAT_FIELD(shix, feature_face_links, 20, 4, uint32_t)
FORMAT_FIELD(shix, feature_edge_links, 24, 4, uint32_t)
FORMAT_FIELD(shix, reserved, 28, 4, uint32_t)

/* FEAT section header (32 bytes; spec/hpfc-format.md §6.2). */
enum { FEAT_HEADER_SIZE = 32, FEAT_LAYER_SIZE = 8, FEAT_FEATURE_SIZE = 24 };
#define FEAT_NONE UINT32_MAX /* a length meaning "no value" */
FORMAT_FIELD(feat, feature_count, 0, 4, uint32_t)
FORMAT_FIELD(feat, face_count, 4, 4, uint32_t)
FORMAT_FIELD(feat, link_count, 8, 4, uint32_t)
FORMAT_FIELD(feat, layer_count, 12, 4, uint32_t)
FORMAT_FIELD(feat, string_bytes, 16, 4, uint32_t)
FORMAT_FIELD(feat, key_field_offset, 20, 4, uint32_t)
FORMAT_FIELD(feat, key_field_length, 24, 4, uint32_t)
FORMAT_FIELD(feat, reserved, 28, 4, uint32_t)
/* Layer entry (8 bytes). */
FORMAT_FIELD(featl, name_offset, 0, 4, uint32_t)
FORMAT_FIELD(featl, name_length, 4, 4, uint32_t)
/* Feature entry (24 bytes). */
FORMAT_FIELD(featf, fid, 0, 8, int64_t)
FORMAT_FIELD(featf, layer, 8, 4, uint32_t)
FORMAT_FIELD(featf, key_offset, 12, 4, uint32_t)
FORMAT_FIELD(featf, key_length, 16, 4, uint32_t)
FORMAT_FIELD(featf, reserved, 20, 4, uint32_t)

static inline bool format_all_zero(const uint8_t *p, size_t n)
{
    for (size_t k = 0; k < n; k++)
        if (p[k])
            return false;
    return true;
}

/* ---- CRC-32C (crc32c.c) --------------------------------------------------- */

/* Continues a CRC-32C (Castagnoli) over data: start with crc = 0; the
 * pre- and post-inversion are inside, so calls chain. */
uint32_t crc32c_update(uint32_t crc, const void *data, size_t length);
/* The same, always by the table (the tests hold the two paths equal), and
 * whether crc32c_update uses the CPU's crc32 instruction here. */
uint32_t crc32c_update_sliced(uint32_t crc, const void *data, size_t length);
int crc32c_hardware(void);
/* The CRC-32C of A followed by B, from crc_a, crc_b and B's length: a
 * section written in pieces out of order gets its checksum from theirs. */
uint32_t crc32c_combine(uint32_t crc_a, uint32_t crc_b, uint64_t length_b);

/* The header checksum: CRC-32C of [0, meta_size) with the meta_crc32c field
 * taken as zero. meta_size >= FORMAT_HEADER_SIZE. */
uint32_t format_meta_crc(const uint8_t *file, uint64_t meta_size);

/* ---- arithmetic ------------------------------------------------------------ */

/* *r = a * b and a + b; false on 64-bit overflow. */
static inline bool format_mul(uint64_t a, uint64_t b, uint64_t *r)
{
    if (a && b > UINT64_MAX / a)
        return false;
    *r = a * b;
    return true;
}

static inline bool format_add(uint64_t a, uint64_t b, uint64_t *r)
{
    if (b > UINT64_MAX - a)
        return false;
    *r = a + b;
    return true;
}

/* ceil(log2(s)), 0 for s <= 1: the bits of an address into s bits. */
static inline uint32_t format_address_bits(uint64_t s)
{
    return s <= 1 ? 0 : (uint32_t)(64 - __builtin_clzll(s - 1));
}

/* Bytes of a pool of `bits` bits. */
static inline uint64_t format_pool_bytes(uint64_t bits)
{
    return (bits >> 3) + ((bits & 7) != 0);
}

static inline uint64_t format_align8(uint64_t v)
{
    return (v + 7) & ~(uint64_t)7;
}

/* ---- level sizes (paper Sect. 4.4) ---------------------------------------- */

typedef struct format_level {
    uint64_t word_pixels;    /* n_w */
    uint64_t refined_pixels; /* n_@ */
    uint64_t images;
    uint32_t word_bits;      /* k_w */
    uint32_t address_bits;   /* k_@: computed */
    uint64_t pool_bits;      /* s: computed */
} format_level;

/* Fills address_bits and pool_bits of levels[0 .. count) from the counts and
 * word_bits, bottom-up: the last level has no address, k_@^l addresses any
 * bit of level l+1's pool, and
 *   s^0 = n0*m0 * (1 + max(k_@^0, k_w^0))            (fixed root records)
 *   s^l = images*n*m + n_w*k_w + n_@*k_@   (l >= 1)  (masks, then slots).
 * Returns false when a size overflows 64 bits. */
static inline bool format_level_sizes(format_level *levels, uint32_t count, uint64_t root_pixels,
                                      uint64_t image_pixels)
{
    uint64_t below = 0; /* s^(l+1) */
    for (uint32_t l = count; l-- > 0;) {
        format_level *lv = &levels[l];
        lv->address_bits = l + 1 < count ? format_address_bits(below) : 0;
        uint64_t s, t;
        if (l == 0) {
            uint32_t payload = lv->address_bits > lv->word_bits ? lv->address_bits : lv->word_bits;
            if (!format_mul(root_pixels, 1 + (uint64_t)payload, &s))
                return false;
        } else {
            if (!format_mul(lv->images, image_pixels, &s) ||
                !format_mul(lv->word_pixels, lv->word_bits, &t) || !format_add(s, t, &s) ||
                !format_mul(lv->refined_pixels, lv->address_bits, &t) || !format_add(s, t, &s))
                return false;
        }
        lv->pool_bits = s;
        below = s;
    }
    return true;
}

/* ---- word code ------------------------------------------------------------- */

/* '+' is the single bit 0; every other symbol is 1 followed by three bits:
 * '=' 1000, '[' 1001, ']' 1010, '(' 1011, 'Y' 1100, ')' 1101. The codes 1110
 * and 1111 are reserved. */
enum { FORMAT_CODE_RESERVED_MIN = 0xE };

/* The symbol of a 4-bit code 8..13. */
static inline char format_code_symbol(unsigned code)
{
    return "=[](Y)??"[code & 7];
}

/* The 4-bit code of a crossing symbol, or -1 for '+' or a non-symbol. */
static inline int format_symbol_code(char c)
{
    switch (c) {
    case '=': return 0x8;
    case '[': return 0x9;
    case ']': return 0xA;
    case '(': return 0xB;
    case 'Y': return 0xC;
    case ')': return 0xD;
    default: return -1;
    }
}

/* ---- bit streams ------------------------------------------------------------ */

/* A pool as the bit reader sees it: `bits` meaningful bits starting at
 * `base`, and `avail` readable bytes from `base` (up to the end of the
 * buffer, so most reads can load 8 bytes at once even near the pool's end;
 * the bits beyond the pool are masked off). */
typedef struct format_bits {
    const uint8_t *base;
    uint64_t bits;
    uint64_t avail;
} format_bits;

static inline uint64_t format_be64(const uint8_t *p)
{
    return (uint64_t)p[0] << 56 | (uint64_t)p[1] << 48 | (uint64_t)p[2] << 40 |
           (uint64_t)p[3] << 32 | (uint64_t)p[4] << 24 | (uint64_t)p[5] << 16 |
           (uint64_t)p[6] << 8 | (uint64_t)p[7];
}

/* v as the int64_t of the same bits (two's complement), without the
 * conversion of a value past INT64_MAX, which C leaves to the compiler. */
static inline int64_t format_as_int64(uint64_t v)
{
    int64_t r;
    memcpy(&r, &v, sizeof r);
    return r;
}

/* 64 bits starting at byte `byte`, zeros past `avail`. */
static inline uint64_t format_window(const format_bits *b, uint64_t byte)
{
    if (byte + 8 <= b->avail)
        return format_be64(b->base + byte);
    uint64_t w = 0;
    for (unsigned k = 0; k < 8; k++)
        w = w << 8 | (byte + k < b->avail ? b->base[byte + k] : 0);
    return w;
}

/* The k-bit field (0 <= k <= 57) at bit offset off, left-aligned in the
 * result (its first bit is bit 63). The caller has checked off + k <= bits. */
static inline uint64_t format_peek(const format_bits *b, uint64_t off, unsigned k)
{
    if (k == 0)
        return 0;
    uint64_t w = format_window(b, off >> 3) << (off & 7);
    return w & ~(UINT64_MAX >> k);
}

/* A field of 58 to 64 bits: its first k - 32 bits, then 32. */
static uint64_t format_get_wide(const format_bits *b, uint64_t off, unsigned k)
{
    uint64_t high = format_peek(b, off, k - 32) >> (64 - (k - 32));
    return high << 32 | format_peek(b, off + k - 32, 32) >> 32;
}

/* The k-bit field (0 <= k <= 64) at bit offset off, as an integer. Not
 * recursive, so that compilers inline it into every access. */
static inline uint64_t format_get(const format_bits *b, uint64_t off, unsigned k)
{
    if (k == 0)
        return 0;
    if (k <= 57)
        return format_peek(b, off, k) >> (64 - k);
    return format_get_wide(b, off, k);
}

/* Number of 1 bits in x. Without a popcount instruction in the target,
 * __builtin_popcountll is a call into the compiler's runtime; the
 * arithmetic version inlines to a dozen instructions, and every pixel
 * access counts bits twice. */
static inline uint64_t format_ones(uint64_t x)
{
#if defined(__POPCNT__)
    return (uint64_t)__builtin_popcountll(x);
#else
    x -= (x >> 1) & 0x5555555555555555ull;
    x = (x & 0x3333333333333333ull) + ((x >> 2) & 0x3333333333333333ull);
    x = (x + (x >> 4)) & 0x0F0F0F0F0F0F0F0Full;
    return (x * 0x0101010101010101ull) >> 56;
#endif
}

/* Number of 1 bits among the n bits at off (MSB-first). */
static inline uint64_t format_popcount(const format_bits *b, uint64_t off, uint64_t n)
{
    uint64_t ones = 0;
    while (n > 56) {
        ones += format_ones(format_peek(b, off, 56));
        off += 56;
        n -= 56;
    }
    return ones + format_ones(format_peek(b, off, (unsigned)n));
}

/* Writes the low k bits of v (0 <= k <= 64) at bit offset off of a zeroed
 * pool, most significant first. */
static inline void format_put(uint8_t *pool, uint64_t off, unsigned k, uint64_t v)
{
    while (k > 0) {
        unsigned shift = (unsigned)(off & 7), room = 8 - shift;
        unsigned take = k < room ? k : room;
        uint64_t part = (v >> (k - take)) & ((1u << take) - 1);
        pool[off >> 3] |= (uint8_t)(part << (room - take));
        off += take;
        k -= take;
    }
}

/* Overwrites the k-bit field (0 <= k <= 64) at bit offset off with the
 * low k bits of v: format_put for a field that may already hold bits
 * (a count kept in place while a table is built in its own bytes). */
static inline void format_set(uint8_t *pool, uint64_t off, unsigned k, uint64_t v)
{
    while (k > 0) {
        unsigned shift = (unsigned)(off & 7), room = 8 - shift;
        unsigned take = k < room ? k : room;
        unsigned mask = ((1u << take) - 1) << (room - take);
        uint64_t part = (v >> (k - take)) & ((1u << take) - 1);
        pool[off >> 3] = (uint8_t)((pool[off >> 3] & ~mask) | (unsigned)(part << (room - take)));
        off += take;
        k -= take;
    }
}

#endif
