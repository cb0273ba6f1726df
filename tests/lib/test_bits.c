/*
 * The format's arithmetic on bits and bytes (libhpfcfile/format.h,
 * crc32c.c; spec/hpfc-format.md): CRC-32C, the bit streams of the pools and
 * the word code table, and the pool and address sizes of the paper's Fig. 7
 * worked by hand. No file is written.
 */
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "format.h"
#include "gen.h"

/* ---- CRC-32C and bit streams ---------------------------------------------------- */

static void test_crc32c(void)
{
    CHECK_EQ_INT(crc32c_update(0, "123456789", 9), 0xE3069283u);
    CHECK_EQ_INT(crc32c_update(0, "", 0), 0);
    uint8_t buf[9000];
    for (size_t k = 0; k < sizeof buf; k++)
        buf[k] = (uint8_t)(k * 131 + 7);
    uint32_t whole = crc32c_update(0, buf, sizeof buf);
    for (size_t cut = 0; cut <= sizeof buf; cut += 37) /* chaining, every alignment */
        CHECK_EQ_INT(crc32c_update(crc32c_update(0, buf, cut), buf + cut, sizeof buf - cut), whole);
    uint32_t bytewise = 0;
    for (size_t k = 0; k < sizeof buf; k++)
        bytewise = crc32c_update(bytewise, buf + k, 1);
    CHECK_EQ_INT(bytewise, whole);
    /* pieces checked apart, then combined: every cut, both pieces empty */
    for (size_t cut = 0; cut <= sizeof buf; cut += 1 + cut / 3)
        CHECK_EQ_INT(crc32c_combine(crc32c_update(0, buf, cut), crc32c_update(0, buf + cut, sizeof buf - cut),
                                    sizeof buf - cut),
                     whole);
    /* the table and the instruction (where this CPU has it) agree at every
     * length and alignment */
    for (size_t at = 0; at < 9; at++)
        for (size_t n = 0; n + at <= sizeof buf; n += 1 + n / 5)
            CHECK_EQ_INT(crc32c_update(0x1234567u, buf + at, n),
                         crc32c_update_sliced(0x1234567u, buf + at, n));
    /* long runs, where the instruction goes three blocks at a time and
     * joins them: past one, two and many 24 KiB steps, from every offset
     * mod 8 and with tails of every kind */
    enum { BIG = 200000 };
    uint8_t *big = malloc(BIG);
    CHECK(big != NULL);
    for (size_t k = 0; big && k < BIG; k++)
        big[k] = (uint8_t)(k * 2654435761u >> 13);
    static const size_t lengths[] = {24575, 24576, 24577, 49151, 49152, 49160, 73735, 199990};
    for (size_t at = 0; big && at < 9; at++)
        for (size_t q = 0; q < sizeof lengths / sizeof *lengths; q++)
            CHECK_EQ_INT(crc32c_update(0xfeedbeefu, big + at, lengths[q]),
                         crc32c_update_sliced(0xfeedbeefu, big + at, lengths[q]));
    free(big);
    printf("crc32c: %s\n", crc32c_hardware() ? "crc32 instruction and table agree" : "table only");
}

static void test_bit_streams(void)
{
    gen_rng rng;
    gen_rng_seed(&rng, 7);
    enum { BYTES = 256, FIELDS = 40 };
    uint8_t pool[BYTES];
    for (int round = 0; round < 200; round++) {
        memset(pool, 0, sizeof pool);
        uint64_t off[FIELDS], val[FIELDS], at = gen_rng_below(&rng, 8);
        unsigned k[FIELDS];
        for (int f = 0; f < FIELDS; f++) {
            k[f] = (unsigned)gen_rng_below(&rng, 65);
            val[f] = k[f] == 64 ? gen_rng_next(&rng) : gen_rng_next(&rng) & (((uint64_t)1 << k[f]) - 1);
            off[f] = at;
            format_put(pool, at, k[f], val[f]);
            at += k[f];
        }
        /* avail is cut at the last byte used, so reads near the end take
         * the byte-by-byte path */
        format_bits b = {pool, at, format_pool_bytes(at)};
        uint64_t ones = 0;
        for (int f = 0; f < FIELDS; f++) {
            CHECK(format_get(&b, off[f], k[f]) == val[f]);
            ones += (uint64_t)__builtin_popcountll(val[f]);
        }
        CHECK_EQ_INT(format_popcount(&b, 0, at), ones);
    }
    /* the first bit of a pool is the most significant bit of its first byte */
    memset(pool, 0, sizeof pool);
    format_put(pool, 0, 1, 1);
    format_put(pool, 9, 3, 5);
    CHECK_EQ_INT(pool[0], 0x80);
    CHECK_EQ_INT(pool[1], 0x50);
    /* the word code table round-trips */
    for (unsigned c = 8; c < FORMAT_CODE_RESERVED_MIN; c++)
        CHECK_EQ_INT(format_symbol_code(format_code_symbol(c)), (int)c);
    CHECK_EQ_INT(format_symbol_code('+'), -1);
}

/* ---- Fig. 7 --------------------------------------------------------------------------- */

/* The paper's Fig. 4 tree as level statistics (Sect. 4.5). */
static void test_fig7_arithmetic(void)
{
    format_level lv[3] = {
        {8, 4, 1, 20, 0, 0},   /* root 4x3: 4 refined + 8 word pixels, k_w = 20 */
        {10, 6, 4, 20, 0, 0},  /* 4 images: 6 refined + 10 word, k_w = 20 */
        {24, 0, 6, 16, 0, 0},  /* 6 images of 4 word pixels, k_w = 16 */
    };
    CHECK(format_level_sizes(lv, 3, 4 * 3, 2 * 2));
    CHECK_EQ_INT(lv[2].pool_bits, 408);
    CHECK_EQ_INT(lv[2].address_bits, 0);
    CHECK_EQ_INT(lv[1].address_bits, 9);
    CHECK_EQ_INT(lv[1].pool_bits, 270);
    CHECK_EQ_INT(lv[0].address_bits, 9);
    CHECK_EQ_INT(lv[0].pool_bits, 252);
    /* address bits: just enough for every bit offset of the next pool */
    CHECK_EQ_INT(format_address_bits(0), 0);
    CHECK_EQ_INT(format_address_bits(1), 0);
    CHECK_EQ_INT(format_address_bits(2), 1);
    CHECK_EQ_INT(format_address_bits(512), 9);
    CHECK_EQ_INT(format_address_bits(513), 10);
    CHECK_EQ_INT(format_address_bits(UINT64_MAX), 64);
    format_level big[2] = {{0, 1, 1, 0, 0, 0}, {UINT64_MAX / 2, 0, 1, 16, 0, 0}};
    CHECK(!format_level_sizes(big, 2, 1, 4)); /* overflow is refused */
}

int main(void)
{
    test_crc32c();
    test_bit_streams();
    test_fig7_arithmetic();
    return check_report("test_bits");
}
