/*
 * Opening a file (hpfc_open_memory; spec/hpfc-format.md, "Safe reading"):
 * every metadata byte mutated, with and without a recomputed checksum, each
 * field against the codes it may give; a header grown by a later minor
 * version; overlapping sections; every metadata prefix truncated; and the
 * fixtures of $HPFC_TEST_DATA/{valid,invalid} opened, verified and walked.
 */
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "file_helpers.h"
#include "fixtures.h"
#include "format.h"
#include "gen.h"
#include "hpfc.h"
#include "pool.h"

/* ---- helpers --------------------------------------------------------------- */

static int open_buf(const uint8_t *buf, size_t size, unsigned flags)
{
    hpfc_file *f = NULL;
    int st = hpfc_open_memory(buf, size, flags, &f);
    CHECK((st == HPFC_OK) == (f != NULL));
    hpfc_close(f);
    return st;
}

/* A graph whose tree is several levels deep, written with a CRS: the
 * subject of the mutation tests. */
static uint8_t *sample_file(size_t *size, uint32_t *levels)
{
    hpfc_graph *g = NULL;
    CHECK_EQ_INT(gen_delaunay(11, 40, 1 << 10, 0.2, &g), HPFC_OK);
    const shape sh = {4, 3, 2, 2, 0};
    hpfc_tree *t = g ? build(g, &sh) : NULL;
    uint8_t *buf = t ? serialize(t, "EPSG:32631", size) : NULL;
    hpfc_tree_info info = {0};
    if (t)
        hpfc_tree_get_info(t, &info);
    *levels = info.levels;
    CHECK(info.levels >= 3);
    hpfc_tree_free(t);
    hpfc_graph_free(g);
    return buf;
}

/* ---- metadata mutations ------------------------------------------------------------ */

typedef struct field {
    char name[40];
    size_t off, size;
    uint64_t fixed;  /* statuses allowed once the meta checksum is recomputed */
    uint64_t raw;    /* ... and without recomputing it */
    uint64_t verify; /* hpfc_file_check_checksums after an accepted mutation */
} field;

typedef struct field_list {
    field f[512];
    size_t n;
} field_list;

static void add_field(field_list *L, const char *name, size_t off, size_t size, uint64_t fixed, uint64_t raw,
                      uint64_t verify)
{
    if (L->n == sizeof L->f / sizeof L->f[0])
        return;
    field *f = &L->f[L->n++];
    snprintf(f->name, sizeof f->name, "%s", name);
    f->off = off, f->size = size, f->fixed = fixed, f->raw = raw, f->verify = verify;
}

#define CSUM BIT(HPFC_E_CHECKSUM)
#define HDR(name, fixed) add_field(L, "header." #name, hdr_OFF_##name, hdr_SIZE_##name, fixed, CSUM, OKB)

static void header_fields(field_list *L)
{
    const uint64_t H = BIT(HPFC_E_HEADER), LT = BIT(HPFC_E_LEVEL_TABLE);
    add_field(L, "header.magic", hdr_OFF_magic, hdr_SIZE_magic, BIT(HPFC_E_MAGIC), BIT(HPFC_E_MAGIC), 0);
    add_field(L, "header.format_major", hdr_OFF_format_major, hdr_SIZE_format_major, BIT(HPFC_E_VERSION),
              BIT(HPFC_E_VERSION), 0);
    HDR(format_minor, OKB); /* a higher minor is compatible */
    add_field(L, "header.header_size", hdr_OFF_header_size, hdr_SIZE_header_size, H, H | CSUM, 0);
    HDR(compat_flags, OKB);
    /* unknown bits are refused; bit 0 (compact pool) reads the level table
     * in the other layout, whose sizes then disagree */
    HDR(incompat_flags, BIT(HPFC_E_INCOMPATIBLE) | BIT(HPFC_E_LEVEL_TABLE));
    HDR(root_cols, H | LT);
    HDR(root_rows, H | LT);
    HDR(cols, H | LT);
    HDR(rows, H | LT);
    HDR(levels, H);
    HDR(section_count, H);
    HDR(x0, OKB | H);
    HDR(y0, OKB | H);
    HDR(width, OKB | H); /* another multiple of n0 * n^(levels-1) is valid */
    HDR(height, OKB | H);
    HDR(unit_exp10, OKB | H);
    HDR(reserved0, H);
    HDR(file_size, H | BIT(HPFC_E_TRUNCATED));
    add_field(L, "header.meta_size", hdr_OFF_meta_size, hdr_SIZE_meta_size, H | BIT(HPFC_E_TRUNCATED),
              H | BIT(HPFC_E_TRUNCATED) | CSUM, 0);
    HDR(reserved1, H);
    HDR(reserved2, H);
    add_field(L, "header.meta_crc32c", hdr_OFF_meta_crc32c, hdr_SIZE_meta_crc32c, 0, CSUM, 0);
}

#define LVL(name, fixed)                                                                     \
    do {                                                                                     \
        snprintf(name_buf, sizeof name_buf, "level%u." #name, l);                            \
        add_field(L, name_buf, base + lvl_OFF_##name, lvl_SIZE_##name, fixed, CSUM, OKB);    \
    } while (0)

static void level_fields(field_list *L, const uint8_t *buf)
{
    uint32_t levels = hdr_get_levels(buf);
    const uint64_t LT = BIT(HPFC_E_LEVEL_TABLE);
    char name_buf[40];
    for (uint32_t l = 0; l < levels; l++) {
        size_t base = FORMAT_HEADER_SIZE + (size_t)l * FORMAT_LEVEL_ENTRY_SIZE;
        const uint8_t *e = buf + base;
        LVL(word_pixels, LT);
        LVL(refined_pixels, LT);
        LVL(images, LT);
        /* k_w leaves the sizes alone when no word uses it, or at the root
         * while k_@ is the wider payload */
        bool loose = lvl_get_word_pixels(e) == 0 || (l == 0 && lvl_get_word_bits(e) < lvl_get_address_bits(e));
        /* compact: k_w bounds the words, the sizes do not depend on it */
        loose = loose || (hdr_get_incompat_flags(buf) & FORMAT_INCOMPAT_COMPACT_POOL);
        LVL(word_bits, LT | (loose ? OKB : 0));
        LVL(address_bits, LT);
        LVL(pool_offset, LT);
        LVL(pool_bits, LT);
        LVL(reserved, LT);
    }
}

#define SEC(name, fixed, verify)                                                             \
    do {                                                                                     \
        snprintf(name_buf, sizeof name_buf, "section%u." #name, k);                          \
        add_field(L, name_buf, base + sec_OFF_##name, sec_SIZE_##name, fixed, CSUM, verify); \
    } while (0)

static void section_fields(field_list *L, const uint8_t *buf)
{
    uint32_t levels = hdr_get_levels(buf), count = hdr_get_section_count(buf);
    const uint64_t S = BIT(HPFC_E_SECTION), LT = BIT(HPFC_E_LEVEL_TABLE);
    char name_buf[40];
    for (uint32_t k = 0; k < count; k++) {
        size_t base = FORMAT_HEADER_SIZE + (size_t)levels * FORMAT_LEVEL_ENTRY_SIZE +
                      (size_t)k * FORMAT_SECTION_ENTRY_SIZE;
        bool pool = memcmp(buf + base, "POOL", 4) == 0;
        if (pool) {
            SEC(tag, BIT(HPFC_E_INCOMPATIBLE) | S, OKB);
            SEC(flags, OKB | S, OKB); /* REQUIRED may be dropped from a known tag */
            SEC(offset, S | LT, OKB);
            SEC(length, OKB | S | LT, OKB | CSUM); /* growing into the padding is fine */
        } else { /* CRS, the last section */
            SEC(tag, OKB | S, OKB); /* an unknown optional section is ignored */
            SEC(flags, OKB | S, OKB);
            SEC(offset, S, OKB);
            SEC(length, OKB | S, OKB | CSUM);
        }
        SEC(crc32c, OKB, CSUM);
        SEC(reserved, S, OKB);
    }
}

/* The field's bytes replaced by each test value in turn: every bit flipped,
 * every byte 0x00 and 0xFF, and the whole field 0, 1, all ones, its value
 * plus and minus one, and its top bit set. */
static size_t mutations(const field *fd, const uint8_t *orig, uint8_t out[][16])
{
    size_t n = 0;
    for (size_t b = 0; b < fd->size; b++) {
        for (int bit = 0; bit < 8; bit++, n++) {
            memcpy(out[n], orig, fd->size);
            out[n][b] ^= (uint8_t)(1u << bit);
        }
        memcpy(out[n], orig, fd->size), out[n++][b] = 0x00;
        memcpy(out[n], orig, fd->size), out[n++][b] = 0xFF;
    }
    unsigned sz = (unsigned)fd->size <= 8 ? (unsigned)fd->size : 8;
    uint64_t v = le_load(orig, sz);
    const uint64_t values[] = {0, 1, UINT64_MAX, v + 1, v - 1, (uint64_t)1 << (8 * sz - 1), v ^ ((uint64_t)1 << (8 * sz - 1))};
    for (size_t k = 0; k < sizeof values / sizeof *values && fd->size <= 8; k++) {
        le_store(out[n++], sz, values[k]);
    }
    return n;
}

static void mutate_field(const field *fd, const uint8_t *buf, size_t size, uint8_t *copy, long *tried)
{
    static uint8_t values[16 * 10 + 8][16];
    size_t nv = mutations(fd, buf + fd->off, values);
    for (size_t v = 0; v < nv; v++) {
        if (memcmp(values[v], buf + fd->off, fd->size) == 0)
            continue;
        (*tried)++;
        memcpy(copy, buf, size);
        memcpy(copy + fd->off, values[v], fd->size);
        int raw = open_buf(copy, size, 0);
        int skip = open_buf(copy, size, HPFC_OPEN_SKIP_CHECKSUM);
        if (!(BIT(raw) & fd->raw))
            fprintf(stderr, "%s mutation %zu: %s without a new checksum\n", fd->name, v, hpfc_strerror(raw));
        CHECK(BIT(raw) & fd->raw);
        uint64_t meta = hdr_get_meta_size(copy);
        if (!fd->fixed || meta < FORMAT_HEADER_SIZE || meta > size)
            continue;
        hdr_set_meta_crc32c(copy, format_meta_crc(copy, meta));
        hpfc_file *f = NULL;
        int st = hpfc_open_memory(copy, size, 0, &f);
        if (!(BIT(st) & fd->fixed))
            fprintf(stderr, "%s mutation %zu: %s\n", fd->name, v, hpfc_strerror(st));
        CHECK(BIT(st) & fd->fixed);
        CHECK_EQ_INT(skip, st); /* skipping the checksum reaches the same field check */
        if (!f)
            continue;
        CHECK(BIT(hpfc_file_check_checksums(f, NULL)) & fd->verify);
        uint64_t codes = probe_file(f, 2000);
        CHECK((codes & ~(OKB | BIT(HPFC_E_NO_PIXEL) | BIT(HPFC_E_CORRUPT))) == 0);
        hpfc_close(f);
    }
}

static void test_metadata_mutations(void)
{
    size_t size = 0;
    uint32_t levels = 0;
    uint8_t *buf = sample_file(&size, &levels);
    if (!buf)
        return;
    static field_list L;
    L.n = 0;
    header_fields(&L);
    level_fields(&L, buf);
    section_fields(&L, buf);
    CHECK_EQ_INT(L.n, 23 + 8 * levels + 2 * 6);
    /* the table covers every metadata byte exactly once */
    uint64_t meta = hdr_get_meta_size(buf);
    uint8_t *cover = calloc(1, (size_t)meta);
    for (size_t k = 0; k < L.n; k++)
        for (size_t b = 0; b < L.f[k].size; b++)
            cover[L.f[k].off + b]++;
    for (uint64_t b = 0; b < meta; b++)
        CHECK_EQ_INT(cover[b], 1);
    free(cover);
    uint8_t *copy = malloc(size);
    long tried = 0;
    for (size_t k = 0; k < L.n; k++)
        mutate_field(&L.f[k], buf, size, copy, &tried);
    CHECK(tried > 5000);
    free(copy);
    free(buf);
}

/* A later minor version may grow the header: the level table then starts at
 * header_size, and a 1.0 reader skips the bytes it does not know. */
static void test_header_extension(void)
{
    size_t size = 0;
    uint32_t levels = 0;
    uint8_t *buf = sample_file(&size, &levels);
    if (!buf)
        return;
    enum { EXTRA = 16 };
    uint8_t *big = calloc(1, size + EXTRA);
    memcpy(big, buf, FORMAT_HEADER_SIZE);
    memset(big + FORMAT_HEADER_SIZE, 0xA5, EXTRA); /* unknown header bytes */
    memcpy(big + FORMAT_HEADER_SIZE + EXTRA, buf + FORMAT_HEADER_SIZE, size - FORMAT_HEADER_SIZE);
    hdr_set_header_size(big, FORMAT_HEADER_SIZE + EXTRA);
    hdr_set_meta_size(big, hdr_get_meta_size(buf) + EXTRA);
    hdr_set_file_size(big, size + EXTRA);
    hdr_set_format_minor(big, 7);
    for (uint32_t l = 0; l < levels; l++) {
        uint8_t *e = big + FORMAT_HEADER_SIZE + EXTRA + (size_t)l * FORMAT_LEVEL_ENTRY_SIZE;
        lvl_set_pool_offset(e, lvl_get_pool_offset(e) + EXTRA);
    }
    for (uint32_t k = 0; k < hdr_get_section_count(big); k++) {
        uint8_t *e = big + FORMAT_HEADER_SIZE + EXTRA + (size_t)levels * FORMAT_LEVEL_ENTRY_SIZE +
                     (size_t)k * FORMAT_SECTION_ENTRY_SIZE;
        sec_set_offset(e, sec_get_offset(e) + EXTRA);
    }
    hdr_set_meta_crc32c(big, format_meta_crc(big, hdr_get_meta_size(big)));
    hpfc_file *a = NULL, *b = NULL;
    CHECK_EQ_INT(hpfc_open_memory(buf, size, 0, &a), HPFC_OK);
    CHECK_EQ_INT(hpfc_open_memory(big, size + EXTRA, 0, &b), HPFC_OK);
    if (a && b) {
        CHECK_EQ_INT(hpfc_file_check_checksums(b, NULL), HPFC_OK);
        hpfc_file_info fa, fb;
        hpfc_file_get_info(a, &fa);
        hpfc_file_get_info(b, &fb);
        CHECK_EQ_INT(fb.format_minor, 7);
        CHECK(fb.crs_len == fa.crs_len && memcmp(fb.crs, fa.crs, fa.crs_len) == 0);
        gen_rng rng;
        gen_rng_seed(&rng, 3);
        for (int k = 0; k < 2000; k++) { /* the same leaves and words */
            int64_t x = fa.x0 + (int64_t)gen_rng_below(&rng, (uint64_t)fa.width);
            int64_t y = fa.y0 + (int64_t)gen_rng_below(&rng, (uint64_t)fa.height);
            hpfc_pixel pa, pb;
            char wa[512], wb[512];
            size_t la = 0, lb = 0;
            CHECK_EQ_INT(hpfc_locate(a, x, y, &pa), HPFC_OK);
            CHECK_EQ_INT(hpfc_locate(b, x, y, &pb), HPFC_OK);
            CHECK(same_pixel(&pa, &pb));
            CHECK_EQ_INT(hpfc_pixel_word(a, &pa, wa, sizeof wa, &la), HPFC_OK);
            CHECK_EQ_INT(hpfc_pixel_word(b, &pb, wb, sizeof wb, &lb), HPFC_OK);
            CHECK(la == lb && memcmp(wa, wb, la) == 0);
        }
    }
    hpfc_close(a);
    hpfc_close(b);
    free(big);
    free(buf);
}

/* Sections at one offset must both be empty; an empty section may sit at
 * the end of another. */
static void test_section_overlaps(void)
{
    size_t size = 0;
    uint32_t levels = 0;
    uint8_t *buf = sample_file(&size, &levels);
    if (!buf)
        return;
    uint8_t *pool = buf + FORMAT_HEADER_SIZE + (size_t)levels * FORMAT_LEVEL_ENTRY_SIZE;
    uint8_t *crs = pool + FORMAT_SECTION_ENTRY_SIZE;
    CHECK(memcmp(crs, "CRS ", 4) == 0);
    uint64_t pool_end = sec_get_offset(pool) + sec_get_length(pool);
    const struct {
        uint64_t offset, length;
        int want;
    } cases[] = {
        {sec_get_offset(pool), 0, HPFC_E_SECTION},     /* at POOL's start */
        {sec_get_offset(pool) + 8, 0, HPFC_E_SECTION}, /* inside POOL */
        {sec_get_offset(crs), 0, HPFC_OK},             /* after POOL, empty */
        {format_align8(pool_end) - 8, 8, HPFC_E_SECTION},
        {sec_get_offset(crs) + 1, 1, HPFC_E_SECTION},  /* misaligned */
    };
    for (size_t k = 0; k < sizeof cases / sizeof *cases; k++) {
        uint8_t *copy = malloc(size);
        memcpy(copy, buf, size);
        uint8_t *e = copy + (crs - buf);
        sec_set_offset(e, cases[k].offset);
        sec_set_length(e, cases[k].length);
        sec_set_crc32c(e, crc32c_update(0, copy + cases[k].offset, (size_t)cases[k].length));
        hdr_set_meta_crc32c(copy, format_meta_crc(copy, hdr_get_meta_size(copy)));
        CHECK_EQ_INT(open_buf(copy, size, 0), cases[k].want);
        free(copy);
    }
    /* the same two sections in the other directory order */
    uint8_t *copy = malloc(size);
    memcpy(copy, buf, size);
    uint8_t *e0 = copy + (pool - buf), *e1 = copy + (crs - buf), tmp[FORMAT_SECTION_ENTRY_SIZE];
    memcpy(tmp, e0, sizeof tmp);
    memcpy(e0, e1, sizeof tmp);
    memcpy(e1, tmp, sizeof tmp);
    hdr_set_meta_crc32c(copy, format_meta_crc(copy, hdr_get_meta_size(copy)));
    CHECK_EQ_INT(open_buf(copy, size, 0), HPFC_OK);
    sec_set_offset(e0, sec_get_offset(e1)); /* CRS at POOL's offset */
    sec_set_length(e0, 0);
    hdr_set_meta_crc32c(copy, format_meta_crc(copy, hdr_get_meta_size(copy)));
    CHECK_EQ_INT(open_buf(copy, size, 0), HPFC_E_SECTION);
    free(copy);
    free(buf);
}

/* Every prefix of the metadata, and some of the pools, is TRUNCATED: the
 * header states the file size. A longer buffer is a HEADER error. */
static void test_truncation(void)
{
    size_t size = 0;
    uint32_t levels = 0;
    uint8_t *buf = sample_file(&size, &levels);
    if (!buf)
        return;
    uint64_t meta = hdr_get_meta_size(buf);
    size_t cuts[] = {(size_t)meta + 1, (size_t)meta + 8, size / 2, size - 8, size - 1};
    for (size_t cut = 0; cut <= size; cut++) {
        bool in_meta = cut <= meta;
        bool listed = false;
        for (size_t k = 0; k < sizeof cuts / sizeof *cuts; k++)
            listed |= cuts[k] == cut;
        if (!in_meta && !listed)
            continue;
        uint8_t *part = malloc(cut ? cut : 1); /* exact size: ASan sees over-reads */
        memcpy(part, buf, cut);
        int st = open_buf(part, cut, 0);
        if (st != HPFC_E_TRUNCATED)
            fprintf(stderr, "cut at %zu of %zu: %s\n", cut, size, hpfc_strerror(st));
        CHECK_EQ_INT(st, HPFC_E_TRUNCATED);
        free(part);
    }
    uint8_t *longer = malloc(size + 1);
    memcpy(longer, buf, size);
    longer[size] = 0;
    CHECK_EQ_INT(open_buf(longer, size + 1, 0), HPFC_E_HEADER);
    /* a prefix that is not the magic's is not an hpfc file, however short */
    longer[0] = 'P';
    CHECK_EQ_INT(open_buf(longer, 1, 0), HPFC_E_MAGIC);
    CHECK_EQ_INT(open_buf(longer, 100, 0), HPFC_E_MAGIC);
    free(longer);
    free(buf);
}

/* ---- checksums computed from the mapping -------------------------------------------- */

/* CRC-32C bit by bit, the definition itself (spec §4.5): the oracle for the
 * library's table-driven one. */
static uint32_t crc32c_bitwise(uint32_t crc, const uint8_t *p, size_t n)
{
    crc = ~crc;
    for (size_t k = 0; k < n; k++) {
        crc ^= p[k];
        for (int b = 0; b < 8; b++)
            crc = crc & 1 ? (crc >> 1) ^ 0x82F63B78u : crc >> 1;
    }
    return ~crc;
}

static uint32_t meta_crc_oracle(const uint8_t *buf, uint64_t meta)
{
    static const uint8_t zero[4];
    uint32_t crc = crc32c_bitwise(0, buf, hdr_OFF_meta_crc32c);
    crc = crc32c_bitwise(crc, zero, 4);
    return crc32c_bitwise(crc, buf + hdr_OFF_meta_crc32c + 4,
                          (size_t)meta - hdr_OFF_meta_crc32c - 4);
}

/* Each section's computed checksum against the bitwise oracle, before and
 * after one byte of it is flipped: only that section's changes, and
 * hpfc_file_check_checksums then fails. */
static void test_computed_checksums(void)
{
    size_t size = 0;
    uint32_t levels = 0;
    uint8_t *buf = sample_file(&size, &levels);
    if (!buf)
        return;
    hpfc_file *f = NULL;
    CHECK_EQ_INT(hpfc_open_memory(buf, size, 0, &f), HPFC_OK);
    if (!f) {
        free(buf);
        return;
    }
    hpfc_file_info fi;
    hpfc_file_get_info(f, &fi);
    CHECK_EQ_INT(fi.header_size, hdr_get_header_size(buf));
    CHECK_EQ_INT(fi.meta_size, hdr_get_meta_size(buf));
    CHECK_EQ_INT(fi.meta_crc32c, hdr_get_meta_crc32c(buf));
    uint32_t crc = 0;
    CHECK_EQ_INT(hpfc_file_compute_checksum(f, HPFC_CHECKSUM_METADATA, &crc), HPFC_OK);
    CHECK_EQ_INT(crc, meta_crc_oracle(buf, fi.meta_size));
    CHECK_EQ_INT(crc, fi.meta_crc32c);
    CHECK_EQ_INT(hpfc_file_compute_checksum(f, fi.section_count, &crc), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_file_compute_checksum(NULL, 0, &crc), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_file_compute_checksum(f, 0, NULL), HPFC_E_ARG);
    CHECK(fi.section_count >= 2);
    for (uint32_t k = 0; k < fi.section_count; k++) {
        hpfc_section_info si;
        CHECK_EQ_INT(hpfc_file_get_section(f, k, &si), HPFC_OK);
        CHECK_EQ_INT(hpfc_file_compute_checksum(f, k, &crc), HPFC_OK);
        CHECK_EQ_INT(crc, crc32c_bitwise(0, buf + si.offset, (size_t)si.length));
        CHECK_EQ_INT(crc, si.crc32c);
    }
    hpfc_close(f);
    for (uint32_t k = 0; k < fi.section_count; k++) {
        f = NULL;
        CHECK_EQ_INT(hpfc_open_memory(buf, size, 0, &f), HPFC_OK);
        hpfc_section_info si;
        CHECK_EQ_INT(hpfc_file_get_section(f, k, &si), HPFC_OK);
        hpfc_close(f);
        if (si.length == 0)
            continue;
        size_t at = (size_t)(si.offset + si.length / 2);
        buf[at] ^= 0x10; /* section bytes are outside the header's checksum */
        f = NULL;
        CHECK_EQ_INT(hpfc_open_memory(buf, size, HPFC_OPEN_SKIP_CHECKSUM, &f), HPFC_OK);
        for (uint32_t j = 0; f && j < fi.section_count; j++) {
            hpfc_section_info sj;
            CHECK_EQ_INT(hpfc_file_get_section(f, j, &sj), HPFC_OK);
            CHECK_EQ_INT(hpfc_file_compute_checksum(f, j, &crc), HPFC_OK);
            CHECK((crc == sj.crc32c) == (j != k));
        }
        if (f)
            CHECK_EQ_INT(hpfc_file_check_checksums(f, NULL), HPFC_E_CHECKSUM);
        hpfc_close(f);
        buf[at] ^= 0x10;
    }
    free(buf);
}

/* ---- fixtures ------------------------------------------------------------------------------ */

/* Opens and verifies a fixture: the first failing status. */
static int open_and_verify(const char *path)
{
    hpfc_file *f = NULL;
    int st = hpfc_open(path, 0, &f);
    if (!st)
        st = hpfc_file_check_checksums(f, NULL);
    if (!st) {
        uint64_t codes = probe_file(f, 1 << 20);
        st = codes & BIT(HPFC_E_CORRUPT) ? HPFC_E_CORRUPT : HPFC_OK;
        CHECK((codes & ~(OKB | BIT(HPFC_E_NO_PIXEL) | BIT(HPFC_E_CORRUPT))) == 0);
    }
    hpfc_close(f);
    return st;
}

static int check_hpfc_fixture(const char *path, char *detail, size_t n)
{
    (void)detail;
    (void)n;
    return open_and_verify(path);
}

static void test_valid_fixtures(const char *root)
{
    check_valid_fixtures(root, ".hpfc", check_hpfc_fixture, 2);
}

static void test_invalid_fixtures(const char *root)
{
    check_invalid_fixtures(root, ".hpfc", check_hpfc_fixture, 5);
}

int main(void)
{
    check_use_test_layout();
    test_metadata_mutations();
    test_header_extension();
    test_section_overlaps();
    test_truncation();
    test_computed_checksums();
    const char *root = getenv("HPFC_TEST_DATA");
    CHECK(root != NULL);
    if (root) {
        test_valid_fixtures(root);
        test_invalid_fixtures(root);
    }
    return check_report("test_open");
}
