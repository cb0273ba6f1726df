/*
 * file.c: opening and checking an .hpfc file (spec/hpfc-format.md, "Safe
 * reading"), and what the level table and the section directory say.
 *
 * Opening checks the header, the level table and the section directory in
 * O(levels + sections) and never decodes a pool: it fills struct hpfc_file
 * (file.h), whose pools navigation (read.c) then reads, re-checking every
 * image it touches. Each optional section's own module checks its header
 * (feat_section_check, labels_open, attr_section_check, geometry_open);
 * none of them calls back here. Nothing here allocates after open or writes
 * to the handle: any number of threads may share one.
 */
#define _DEFAULT_SOURCE /* madvise's MADV_POPULATE_READ, beside the build's _POSIX_C_SOURCE */
#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include "attrs.h"
#include "feat.h"
#include "file.h"
#include "diag.h"
#include "sized.h"

/* ---- open: header ---------------------------------------------------------- */

/* The checks that precede the checksum: what identifies the file and the
 * extent the checksum covers. */
static int check_prefix(const uint8_t *d, size_t size)
{
    size_t n = size < FORMAT_MAGIC_SIZE ? size : FORMAT_MAGIC_SIZE;
    if (memcmp(d, FORMAT_MAGIC, n) != 0)
        return HPFC_E_MAGIC;
    if (size < FORMAT_HEADER_SIZE)
        return HPFC_E_TRUNCATED;
    if (hdr_get_format_major(d) != FORMAT_MAJOR)
        return HPFC_E_VERSION;
    uint64_t header_size = hdr_get_header_size(d), meta_size = hdr_get_meta_size(d);
    if (header_size < FORMAT_HEADER_SIZE || meta_size < header_size)
        return HPFC_E_HEADER;
    return meta_size > size ? HPFC_E_TRUNCATED : HPFC_OK;
}

static bool in_range(int64_t v, int64_t lo, int64_t hi)
{
    return v >= lo && v <= hi;
}

/* W = n0 * n^(levels-1) * (a whole cell), likewise H: every level's grid
 * lines fall on the lattice. Fills the per-level cell sizes. */
static bool split_extent(hpfc_file *f, int64_t extent, uint32_t root, uint32_t per, bool horizontal)
{
    if (extent % root)
        return false;
    int64_t cell = extent / root;
    for (uint32_t l = 0; l < f->info.levels; l++) {
        if (l > 0) {
            if (cell % per)
                return false;
            cell /= per;
        }
        if (horizontal)
            f->lv[l].cell_w = f->lv[l].info.cell_w = cell;
        else
            f->lv[l].cell_h = f->lv[l].info.cell_h = cell;
    }
    return true;
}

/* log2(n) when n >= 2 is a power of two, else 0. */
static uint32_t power_of_two_log(uint32_t n)
{
    uint32_t k = 0;
    if (n < 2 || (n & (n - 1)))
        return 0;
    while (n >> (k + 1))
        k++;
    return k;
}

static int read_header(hpfc_file *f)
{
    const uint8_t *d = f->data;
    hpfc_file_info *in = &f->info;
    in->format_major = hdr_get_format_major(d);
    in->format_minor = hdr_get_format_minor(d);
    in->compat_flags = hdr_get_compat_flags(d);
    in->incompat_flags = hdr_get_incompat_flags(d);
    in->root_cols = hdr_get_root_cols(d);
    in->root_rows = hdr_get_root_rows(d);
    in->cols = hdr_get_cols(d);
    in->rows = hdr_get_rows(d);
    in->levels = hdr_get_levels(d);
    in->section_count = hdr_get_section_count(d);
    in->x0 = hdr_get_x0(d);
    in->y0 = hdr_get_y0(d);
    in->width = hdr_get_width(d);
    in->height = hdr_get_height(d);
    in->unit_exp10 = hdr_get_unit_exp10(d);
    in->file_size = hdr_get_file_size(d);
    f->meta_size = hdr_get_meta_size(d);
    in->meta_size = f->meta_size;
    in->header_size = hdr_get_header_size(d);
    in->meta_crc32c = hdr_get_meta_crc32c(d);

    if (in->root_cols < 1 || in->root_rows < 1 ||
        (uint64_t)in->root_cols * in->root_rows > FORMAT_MAX_ROOT_PIXELS || in->cols < 2 ||
        in->rows < 2 || (uint64_t)in->cols * in->rows > FORMAT_MAX_IMAGE_PIXELS ||
        in->levels < 1 || in->levels > HPFC_MAX_LEVELS || in->section_count > FORMAT_MAX_SECTIONS)
        return HPFC_E_HEADER;
    if (!in_range(in->x0, -FORMAT_MAX_ORIGIN, FORMAT_MAX_ORIGIN) ||
        !in_range(in->y0, -FORMAT_MAX_ORIGIN, FORMAT_MAX_ORIGIN) ||
        !in_range(in->width, 1, FORMAT_MAX_EXTENT) || !in_range(in->height, 1, FORMAT_MAX_EXTENT) ||
        !in_range(in->unit_exp10, FORMAT_MIN_UNIT_EXP10, FORMAT_MAX_UNIT_EXP10))
        return HPFC_E_HEADER;
    if (!split_extent(f, in->width, in->root_cols, in->cols, true) ||
        !split_extent(f, in->height, in->root_rows, in->rows, false))
        return HPFC_E_HEADER;
    f->shift_x = power_of_two_log(in->cols);
    f->shift_y = power_of_two_log(in->rows);
    if (!format_all_zero(d + hdr_OFF_reserved0, hdr_SIZE_reserved0) ||
        !format_all_zero(d + hdr_OFF_reserved1, hdr_SIZE_reserved1) ||
        !format_all_zero(d + hdr_OFF_reserved2, hdr_SIZE_reserved2))
        return HPFC_E_HEADER;
    /* The level table follows the header (header_size bytes), then the
     * directory: nothing else is metadata. */
    uint64_t header_size = hdr_get_header_size(d);
    if (f->meta_size != header_size + (uint64_t)FORMAT_LEVEL_ENTRY_SIZE * in->levels +
                            (uint64_t)FORMAT_SECTION_ENTRY_SIZE * in->section_count)
        return HPFC_E_HEADER;
    if (in->file_size > FORMAT_MAX_FILE_SIZE)
        return HPFC_E_HEADER;
    if (in->file_size > f->size)
        return HPFC_E_TRUNCATED;
    if (in->file_size < f->size)
        return HPFC_E_HEADER;
    if (in->incompat_flags & ~(uint32_t)FORMAT_INCOMPAT_COMPACT_POOL) /* 1.2 defines one */
        return HPFC_E_INCOMPATIBLE;
    f->compact = in->incompat_flags & FORMAT_INCOMPAT_COMPACT_POOL;
    f->directory = d + header_size + (size_t)FORMAT_LEVEL_ENTRY_SIZE * in->levels;
    return HPFC_OK;
}

/* ---- open: level table ------------------------------------------------------ */

static const uint8_t *level_entry(const hpfc_file *f, uint32_t l)
{
    return f->data + hdr_get_header_size(f->data) + (size_t)l * FORMAT_LEVEL_ENTRY_SIZE;
}

/* The compact layout's own fields (§4.3): no address, the stabbed
 * pixels among the word pixels, a stream of at least one and at most k_w
 * bits a stabbed word, k_w = 0 exactly when no word is stabbed. */
static int check_compact_counts(const hpfc_file *f, uint32_t l, const hpfc_level_info *in)
{
    const uint8_t *e = level_entry(f, l);
    uint64_t stabbed = lvl_get_stabbed_pixels(e), stream = lvl_get_stream_bits(e), most;
    if (in->address_bits != 0 || stabbed > in->word_pixels || in->word_bits > POOL_MAX_WORD_BITS)
        return HPFC_E_LEVEL_TABLE;
    if (stabbed == 0)
        return stream == 0 && in->word_bits == 0 ? HPFC_OK : HPFC_E_LEVEL_TABLE;
    if (in->word_bits == 0 || stream < stabbed || !format_mul(stabbed, in->word_bits, &most) ||
        stream > most)
        return HPFC_E_LEVEL_TABLE;
    return HPFC_OK;
}

/* The counts of one level: every pixel is a word or refined pixel, every
 * refined pixel of the level above has its own image, and only the root
 * level lacks a parent. */
static int check_level_counts(const hpfc_file *f, uint32_t l, const hpfc_level_info *in,
                              uint64_t parent_refined)
{
    uint64_t per = l ? (uint64_t)f->info.cols * f->info.rows
                     : (uint64_t)f->info.root_cols * f->info.root_rows;
    uint64_t pixels, sum;
    if (!f->compact && !format_all_zero(level_entry(f, l) + lvl_OFF_reserved, lvl_SIZE_reserved))
        return HPFC_E_LEVEL_TABLE;
    if (in->images != (l ? parent_refined : 1) || in->images == 0)
        return HPFC_E_LEVEL_TABLE;
    if (!format_mul(in->images, per, &pixels) ||
        !format_add(in->word_pixels, in->refined_pixels, &sum) || sum != pixels)
        return HPFC_E_LEVEL_TABLE;
    if (l + 1 == f->info.levels && in->refined_pixels != 0)
        return HPFC_E_LEVEL_TABLE;
    if (f->compact)
        return check_compact_counts(f, l, in);
    if (in->word_bits > FORMAT_MAX_WORD_BITS ||
        (in->word_pixels > 0 && in->word_bits < FORMAT_MIN_WORD_BITS))
        return HPFC_E_LEVEL_TABLE;
    return HPFC_OK;
}

static void read_level_entry(const uint8_t *e, hpfc_level_info *in)
{
    in->word_pixels = lvl_get_word_pixels(e);
    in->refined_pixels = lvl_get_refined_pixels(e);
    in->images = lvl_get_images(e);
    in->word_bits = lvl_get_word_bits(e);
    in->address_bits = lvl_get_address_bits(e);
    in->pool_offset = lvl_get_pool_offset(e);
    in->pool_bits = lvl_get_pool_bits(e);
}

/* Pools on 8-byte boundaries after the metadata, in level order, disjoint,
 * inside the file (the POOL section is checked with the directory). */
static int check_pool_places(const hpfc_file *f)
{
    uint64_t end_prev = f->meta_size;
    for (uint32_t l = 0; l < f->info.levels; l++) {
        const hpfc_level_info *in = &f->lv[l].info;
        uint64_t bytes = format_pool_bytes(in->pool_bits);
        if (in->pool_offset % FORMAT_SECTION_ALIGN || in->pool_offset < end_prev ||
            in->pool_offset > f->info.file_size || bytes > f->info.file_size - in->pool_offset)
            return HPFC_E_LEVEL_TABLE;
        end_prev = in->pool_offset + bytes;
    }
    return HPFC_OK;
}

static void derive_level(hpfc_file *f, uint32_t l)
{
    file_level *lv = &f->lv[l];
    const hpfc_level_info *in = &lv->info;
    lv->pool.base = f->data + in->pool_offset;
    lv->pool.bits = in->pool_bits;
    lv->pool.avail = f->size - in->pool_offset;
    lv->word_bits = in->word_bits;
    lv->address_bits = in->address_bits;
    lv->cols = l ? f->info.cols : f->info.root_cols;
    lv->rows = l ? f->info.rows : f->info.root_rows;
    lv->image_pixels = (uint64_t)lv->cols * lv->rows;
    lv->record_bits = 1 + (uint64_t)(in->address_bits > in->word_bits ? in->address_bits : in->word_bits);
    lv->last = l + 1 == f->info.levels;
}

/* The compact sizes (pool.h) of every level must be the table's s^l. */
static int read_compact_levels(hpfc_file *f)
{
    for (uint32_t l = 0; l < f->info.levels; l++) {
        const uint8_t *e = level_entry(f, l);
        const hpfc_level_info *in = &f->lv[l].info;
        uint64_t per = l ? (uint64_t)f->info.cols * f->info.rows
                         : (uint64_t)f->info.root_cols * f->info.root_rows;
        if (!pool_level_sizes(&f->lv[l].compact, in->images * per, in->refined_pixels,
                              lvl_get_stabbed_pixels(e), lvl_get_stream_bits(e)) ||
            f->lv[l].compact.pool_bits != in->pool_bits)
            return HPFC_E_LEVEL_TABLE;
    }
    int st = check_pool_places(f);
    for (uint32_t l = 0; l < f->info.levels && !st; l++)
        derive_level(f, l);
    return st;
}

static int read_levels(hpfc_file *f)
{
    format_level sizes[HPFC_MAX_LEVELS];
    uint32_t levels = f->info.levels;
    for (uint32_t l = 0; l < levels; l++) {
        hpfc_level_info *in = &f->lv[l].info;
        read_level_entry(level_entry(f, l), in);
        int st = check_level_counts(f, l, in, l ? f->lv[l - 1].info.refined_pixels : 0);
        if (st)
            return st;
        sizes[l] = (format_level){in->word_pixels, in->refined_pixels, in->images, in->word_bits, 0, 0};
    }
    if (f->compact)
        return read_compact_levels(f);
    if (!format_level_sizes(sizes, levels, (uint64_t)f->info.root_cols * f->info.root_rows,
                            (uint64_t)f->info.cols * f->info.rows))
        return HPFC_E_LEVEL_TABLE;
    for (uint32_t l = 0; l < levels; l++)
        if (sizes[l].address_bits != f->lv[l].info.address_bits ||
            sizes[l].pool_bits != f->lv[l].info.pool_bits)
            return HPFC_E_LEVEL_TABLE;
    int st = check_pool_places(f);
    for (uint32_t l = 0; l < levels && !st; l++)
        derive_level(f, l);
    return st;
}

/* ---- open: section directory ------------------------------------------------- */

typedef struct span {
    uint64_t offset, end;
    uint32_t tag;
} span;

/* By offset, the longer first at one offset: then checking neighbours finds
 * every overlap, including a non-empty section sharing an empty one's
 * offset (two sections at one offset must both be empty).
 * (Every qsort comparator of the library has this field-by-field shape;
 * each orders its own record, so they share no code.) */
static int cmp_offset(const void *a, const void *b)
{
    const span *x = a, *y = b;
    if (x->offset != y->offset)
        return x->offset < y->offset ? -1 : 1;
    return (x->end < y->end) - (x->end > y->end);
}

static int cmp_tag(const void *a, const void *b)
{
    const span *x = a, *y = b;
    return (x->tag > y->tag) - (x->tag < y->tag);
}

static const uint8_t *section_entry(const hpfc_file *f, uint32_t index)
{
    return f->directory + (size_t)index * FORMAT_SECTION_ENTRY_SIZE;
}

static bool tag_is(const uint8_t *entry, const char *tag)
{
    return memcmp(entry + sec_OFF_tag, tag, sec_SIZE_tag) == 0;
}

/* One entry on its own: printable tag, known flag bits, 8-aligned extent
 * inside the file after the metadata, and no unknown required tag. */
static int check_section_entry(const hpfc_file *f, const uint8_t *e, span *out)
{
    for (unsigned k = 0; k < sec_SIZE_tag; k++)
        if (e[sec_OFF_tag + k] < 0x20 || e[sec_OFF_tag + k] > 0x7e)
            return HPFC_E_SECTION;
    uint32_t flags = sec_get_flags(e);
    uint64_t offset = sec_get_offset(e), length = sec_get_length(e);
    if (flags & ~(uint32_t)FORMAT_SECTION_REQUIRED ||
        !format_all_zero(e + sec_OFF_reserved, sec_SIZE_reserved))
        return HPFC_E_SECTION;
    if (offset % FORMAT_SECTION_ALIGN || offset < f->meta_size || offset > f->info.file_size ||
        length > f->info.file_size - offset)
        return HPFC_E_SECTION;
    bool known = tag_is(e, FORMAT_TAG_POOL) || tag_is(e, FORMAT_TAG_CRS) || tag_is(e, FORMAT_TAG_FEAT) ||
                 tag_is(e, FORMAT_TAG_LABL) || tag_is(e, FORMAT_TAG_ATTR) || tag_is(e, FORMAT_TAG_EDGF) ||
                 tag_is(e, FORMAT_TAG_GEOM) || tag_is(e, FORMAT_TAG_SHIX);
    if (!known && (flags & FORMAT_SECTION_REQUIRED))
        return HPFC_E_INCOMPATIBLE;
    *out = (span){offset, offset + length, (uint32_t)le_load(e + sec_OFF_tag, sec_SIZE_tag)};
    return HPFC_OK;
}

/* No two sections overlap and no tag repeats (sorted copies, O(S log S)). */
static int check_section_set(span *spans, uint32_t count)
{
    qsort(spans, count, sizeof *spans, cmp_offset);
    for (uint32_t k = 1; k < count; k++)
        if (spans[k - 1].end > spans[k].offset)
            return HPFC_E_SECTION;
    qsort(spans, count, sizeof *spans, cmp_tag);
    for (uint32_t k = 1; k < count; k++)
        if (spans[k - 1].tag == spans[k].tag)
            return HPFC_E_SECTION;
    return HPFC_OK;
}

/* Every pool inside the POOL section (a level table error: the pools are
 * the level table's claim). */
static int check_pools_in_section(const hpfc_file *f, const uint8_t *pool)
{
    uint64_t start = sec_get_offset(pool), end = start + sec_get_length(pool);
    for (uint32_t l = 0; l < f->info.levels; l++) {
        const hpfc_level_info *in = &f->lv[l].info;
        if (in->pool_offset < start || in->pool_offset + format_pool_bytes(in->pool_bits) > end)
            return HPFC_E_LEVEL_TABLE;
    }
    return HPFC_OK;
}

static int read_crs(hpfc_file *f, const uint8_t *crs)
{
    const uint8_t *text = f->data + sec_get_offset(crs);
    size_t length = (size_t)sec_get_length(crs);
    if (memchr(text, '\0', length))
        return HPFC_E_SECTION;
    f->info.crs = (const char *)text;
    f->info.crs_len = length;
    return HPFC_OK;
}

static int read_labl(hpfc_file *f, const uint8_t *labl)
{
    labels_levels lv = {.levels = f->info.levels};
    for (uint32_t l = 0; l < f->info.levels; l++) {
        lv.word_pixels[l] = f->lv[l].info.word_pixels;
        lv.units[l] = l ? f->lv[l].info.images : (uint64_t)f->info.root_cols * f->info.root_rows;
    }
    return labels_open(&f->labels, f->data + sec_get_offset(labl), sec_get_length(labl), &lv);
}

/* GEOM after LABL: its edge count must be LABL's. */
static int read_geom(hpfc_file *f, const uint8_t *geom)
{
    geom_levels lv = {.levels = f->info.levels,
                      .width = f->info.width,
                      .height = f->info.height,
                      .has_labels = f->labels.present,
                      .label_edges = f->labels.edges};
    for (uint32_t l = 0; l < f->info.levels; l++)
        lv.word_pixels[l] = f->lv[l].info.word_pixels;
    return geometry_open(&f->geom, f->data + sec_get_offset(geom), sec_get_length(geom), &lv);
}

/* A section checked by `check` against its own counts; its start into *at.
 * Its length is not kept: the check bounds every record the section's
 * accessors read by the section's length, once, here. */
static int read_checked(hpfc_file *f, const uint8_t *entry, int (*check)(const uint8_t *, uint64_t),
                        const uint8_t **at)
{
    const uint8_t *s = f->data + sec_get_offset(entry);
    int st = check(s, sec_get_length(entry));
    if (!st)
        *at = s;
    return st;
}

/* The sections this library reads, by tag: where read_directory finds
 * their entries (at most one each, check_section_set refuses a repeat). */
enum { SEC_POOL, SEC_CRS, SEC_FEAT, SEC_LABL, SEC_ATTR, SEC_EDGF, SEC_GEOM, SEC_SHIX, KNOWN_SECTIONS };
static const char *const known_tags[KNOWN_SECTIONS] = {
    FORMAT_TAG_POOL, FORMAT_TAG_CRS,  FORMAT_TAG_FEAT, FORMAT_TAG_LABL,
    FORMAT_TAG_ATTR, FORMAT_TAG_EDGF, FORMAT_TAG_GEOM, FORMAT_TAG_SHIX,
};

/* Records entry e in `known` if its tag is one this library reads. */
static void note_known_section(const uint8_t *e, const uint8_t *known[KNOWN_SECTIONS])
{
    for (int k = 0; k < KNOWN_SECTIONS; k++)
        if (tag_is(e, known_tags[k]))
            known[k] = e;
}

static int read_directory(hpfc_file *f)
{
    uint32_t count = f->info.section_count;
    span *spans = malloc((count ? count : 1) * sizeof *spans);
    if (!spans)
        return HPFC_E_NOMEM;
    const uint8_t *known[KNOWN_SECTIONS] = {NULL};
    int st = HPFC_OK;
    for (uint32_t k = 0; k < count && !st; k++) {
        const uint8_t *e = section_entry(f, k);
        st = check_section_entry(f, e, &spans[k]);
        note_known_section(e, known);
    }
    if (!st)
        st = check_section_set(spans, count);
    free(spans);
    if (!st && !known[SEC_POOL])
        st = HPFC_E_SECTION;
    if (!st && known[SEC_CRS])
        st = read_crs(f, known[SEC_CRS]);
    if (!st && known[SEC_FEAT])
        st = read_checked(f, known[SEC_FEAT], feat_section_check, &f->feat);
    if (!st && known[SEC_LABL])
        st = read_labl(f, known[SEC_LABL]);
    if (!st && known[SEC_ATTR])
        st = read_checked(f, known[SEC_ATTR], attr_section_check, &f->attr);
    if (!st && known[SEC_EDGF])
        st = read_checked(f, known[SEC_EDGF], edgf_section_check, &f->edgf);
    if (!st && known[SEC_GEOM])
        st = read_geom(f, known[SEC_GEOM]);
    if (!st && known[SEC_SHIX])
        st = shix_open(&f->shix, f->data + sec_get_offset(known[SEC_SHIX]),
                       sec_get_length(known[SEC_SHIX]));
    if (!st)
        st = check_pools_in_section(f, known[SEC_POOL]);
    return st;
}

/* ---- open and close ------------------------------------------------------------ */

int hpfc_open_memory(const void *data, size_t size, unsigned flags, hpfc_file **out)
{
    if (!out)
        return HPFC_E_ARG;
    *out = NULL;
    if (!data)
        return HPFC_E_ARG;
    const uint8_t *d = data;
    int st = check_prefix(d, size);
    if (st)
        return st;
    uint64_t meta_size = hdr_get_meta_size(d);
    if (!(flags & HPFC_OPEN_SKIP_CHECKSUM) && format_meta_crc(d, meta_size) != hdr_get_meta_crc32c(d))
        return HPFC_E_CHECKSUM;
    hpfc_file *f = calloc(1, sizeof *f);
    if (!f)
        return HPFC_E_NOMEM;
    f->data = d;
    f->size = size;
    st = read_header(f);
    if (!st)
        st = read_levels(f);
    if (!st)
        st = read_directory(f);
    if (st) {
        free(f);
        return st;
    }
    *out = f;
    return HPFC_OK;
}

/* HPFC_OPEN_READ: the whole of fd into a buffer of its own, to EOF (a
 * pipe's size is not known before; a regular file's st_size is only the
 * first guess, as it may change under us). */
static int read_whole(int fd, size_t guess, unsigned flags, hpfc_file **out)
{
    size_t cap = guess > 0 ? guess + 1 : 65536, size = 0;
    uint8_t *buf = malloc(cap);
    if (!buf)
        return HPFC_E_NOMEM;
    for (;;) {
        if (size == cap) {
            size_t grown = cap > SIZE_MAX / 2 ? SIZE_MAX : cap * 2;
            uint8_t *b = grown > cap ? realloc(buf, grown) : NULL;
            if (!b) {
                free(buf);
                return HPFC_E_NOMEM;
            }
            buf = b, cap = grown;
        }
        ssize_t n = read(fd, buf + size, cap - size);
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0) {
            free(buf);
            return HPFC_E_IO;
        }
        if (n == 0)
            break;
        size += (size_t)n;
    }
    int st = hpfc_open_memory(buf, size, flags, out);
    if (st) {
        free(buf);
        return st;
    }
    (*out)->owned = buf;
    return HPFC_OK;
}

int hpfc_open(const char *path, unsigned flags, hpfc_file **out)
{
    if (!path || !out)
        return HPFC_E_ARG;
    *out = NULL;
    int fd = open(path, O_RDONLY | O_CLOEXEC);
    if (fd < 0)
        return errno == ENOMEM ? HPFC_E_NOMEM : HPFC_E_IO;
    struct stat sb;
    if (fstat(fd, &sb) || S_ISDIR(sb.st_mode) || (uint64_t)sb.st_size > SIZE_MAX ||
        (!S_ISREG(sb.st_mode) && !(flags & HPFC_OPEN_READ))) {
        close(fd);
        return HPFC_E_IO;
    }
    if (flags & HPFC_OPEN_READ) {
        int st = read_whole(fd, S_ISREG(sb.st_mode) ? (size_t)sb.st_size : 0, flags, out);
        close(fd);
        return st;
    }
    size_t size = (size_t)sb.st_size;
    if (size == 0) { /* mmap refuses empty mappings; the verdict is the same */
        static const uint8_t empty[1];
        close(fd);
        return hpfc_open_memory(empty, 0, flags, out);
    }
    void *map = mmap(NULL, size, PROT_READ, MAP_PRIVATE, fd, 0);
    int map_errno = errno;
    close(fd);
    if (map == MAP_FAILED)
        return map_errno == ENOMEM ? HPFC_E_NOMEM : HPFC_E_IO;
    int st = hpfc_open_memory(map, size, flags, out);
    if (st) {
        munmap(map, size);
        return st;
    }
    (*out)->map = map;
    (*out)->map_size = size;
    return HPFC_OK;
}

void hpfc_close(hpfc_file *f)
{
    if (!f)
        return;
    if (f->map)
        munmap(f->map, f->map_size);
    free(f->owned);
    free(f);
}

/* A mapped file's pages are first touched by the checksums, a page fault
 * every few pages: mapping a 3.6 MB file anew and taking its CRC-32C took
 * 1.4 ms here, 0.4 ms with its pages asked for first, 0.15 ms for the
 * CRC-32C of the bytes in memory. So each window's pages are asked for at
 * once (Linux 5.14's MADV_POPULATE_READ, a hint: an error changes
 * nothing) before they are read; a window at a time, so that a file
 * larger than memory is not read twice. */
enum { POPULATE_WINDOW = 8u << 20 };

static void populate(const hpfc_file *f, const uint8_t *p, size_t n)
{
#ifdef MADV_POPULATE_READ
    if (!f->map || !n)
        return;
    long ps = sysconf(_SC_PAGESIZE); /* libc's, without a system call */
    size_t page = ps > 0 ? (size_t)ps : 4096;
    uintptr_t a = (uintptr_t)p & ~(uintptr_t)(page - 1);
    (void)madvise((void *)a, (uintptr_t)p + n - a, MADV_POPULATE_READ);
#else
    (void)f, (void)p, (void)n;
#endif
}

/* The CRC-32C of bytes [offset, offset + length) of the file. */
static uint32_t file_crc(const hpfc_file *f, uint64_t offset, uint64_t length)
{
    const uint8_t *p = f->data + offset;
    uint32_t crc = 0;
    for (size_t n = (size_t)length; n;) {
        size_t take = n < POPULATE_WINDOW ? n : POPULATE_WINDOW;
        populate(f, p, take);
        crc = crc32c_update(crc, p, take);
        p += take, n -= take;
    }
    return crc;
}

int hpfc_file_check_checksums(const hpfc_file *f, hpfc_diag *diag)
{
    diag_clear(diag);
    if (!f)
        return diag_set(diag, HPFC_E_ARG, "no file");
    uint32_t stored = hdr_get_meta_crc32c(f->data);
    uint32_t computed = format_meta_crc(f->data, f->meta_size);
    if (computed != stored)
        return diag_set(diag, HPFC_E_CHECKSUM,
                        "the header's (its first %llu bytes): CRC-32C 0x%08x stored, "
                        "0x%08x computed",
                        (unsigned long long)f->meta_size, stored, computed);
    for (uint32_t k = 0; k < f->info.section_count; k++) {
        const uint8_t *e = section_entry(f, k);
        uint64_t offset = sec_get_offset(e), length = sec_get_length(e);
        stored = sec_get_crc32c(e);
        computed = file_crc(f, offset, length);
        if (computed != stored) {
            char tag[sec_SIZE_tag + 1];
            for (size_t c = 0; c < sec_SIZE_tag; c++) /* any bytes in a damaged entry */
                tag[c] = e[sec_OFF_tag + c] >= 0x20 && e[sec_OFF_tag + c] < 0x7f
                             ? (char)e[sec_OFF_tag + c]
                             : '?';
            tag[sec_SIZE_tag] = '\0';
            return diag_set(diag, HPFC_E_CHECKSUM,
                            "section %u (%s) at offset %llu, %llu bytes: CRC-32C 0x%08x stored, "
                            "0x%08x computed",
                            k, tag, (unsigned long long)offset, (unsigned long long)length, stored,
                            computed);
        }
    }
    return HPFC_OK;
}

int hpfc_file_compute_checksum(const hpfc_file *f, uint32_t index, uint32_t *crc32c)
{
    if (!f || !crc32c)
        return HPFC_E_ARG;
    if (index == HPFC_CHECKSUM_METADATA) {
        *crc32c = format_meta_crc(f->data, f->meta_size);
        return HPFC_OK;
    }
    if (index >= f->info.section_count)
        return HPFC_E_ARG;
    /* open checked every section lies inside the file */
    const uint8_t *e = section_entry(f, index);
    *crc32c = file_crc(f, sec_get_offset(e), sec_get_length(e));
    return HPFC_OK;
}

/* ---- metadata queries -------------------------------------------------------------- */

void hpfc_file_get_info_sized(const hpfc_file *f, hpfc_file_info *info, size_t size)
{
    if (f && info)
        sized_out(info, size, &f->info, sizeof f->info);
}

int hpfc_file_get_level_sized(const hpfc_file *f, uint32_t level, hpfc_level_info *out,
                              size_t size)
{
    if (!f || !out || level >= f->info.levels)
        return HPFC_E_ARG;
    sized_out(out, size, &f->lv[level].info, sizeof f->lv[level].info);
    return HPFC_OK;
}

int hpfc_file_get_section_sized(const hpfc_file *f, uint32_t index, hpfc_section_info *out,
                                size_t size)
{
    if (!f || !out || index >= f->info.section_count)
        return HPFC_E_ARG;
    const uint8_t *e = section_entry(f, index);
    hpfc_section_info full;
    memset(&full, 0, sizeof full); /* padding too: the caller gets known bytes */
    memcpy(full.tag, e + sec_OFF_tag, sec_SIZE_tag);
    full.flags = sec_get_flags(e);
    full.offset = sec_get_offset(e);
    full.length = sec_get_length(e);
    full.crc32c = sec_get_crc32c(e);
    sized_out(out, size, &full, sizeof full);
    return HPFC_OK;
}

/* ---- what the level table bounds ----------------------------------------------------- */

/* The crossings a word code of k bits can hold: the paper's code spends 4
 * bits a crossing after its four '+', the compact one at least 1. */
static uint32_t crossings_in(const hpfc_file *f, uint32_t k)
{
    if (f->compact)
        return k;
    return k >= FORMAT_MIN_WORD_BITS ? (k - FORMAT_MIN_WORD_BITS) / 4 : 0;
}

uint32_t file_level_max_crossings(const hpfc_file *f, uint32_t level)
{
    return crossings_in(f, f->lv[level].word_bits);
}

/* Over every level, whatever its word count says: a corrupt mask can put a
 * word pixel in any level, and its slot bounds its crossings. */
uint32_t file_max_crossings(const hpfc_file *f)
{
    uint32_t most = 0;
    for (uint32_t l = 0; l < f->info.levels; l++) {
        uint32_t c = crossings_in(f, f->lv[l].word_bits);
        most = c > most ? c : most;
    }
    return most;
}

uint64_t file_total_crossings(const hpfc_file *f)
{
    uint64_t total = 0, part;
    for (uint32_t l = 0; l < f->info.levels; l++) {
        const file_level *lv = &f->lv[l];
        uint64_t c = crossings_in(f, lv->word_bits);
        if (!format_mul(lv->info.word_pixels, c, &part) || !format_add(total, part, &total))
            return UINT64_MAX;
    }
    return total;
}

uint64_t file_total_leaves(const hpfc_file *f)
{
    uint64_t total = 0;
    for (uint32_t l = 0; l < f->info.levels; l++)
        if (!format_add(total, f->lv[l].info.word_pixels, &total))
            return UINT64_MAX;
    return total;
}

/* ---- the compact pools' own index ------------------------------------------------------- */

int hpfc_file_check_pool_layout(const hpfc_file *f, uint32_t level, hpfc_diag *diag)
{
    diag_clear(diag);
    if (!f || level >= f->info.levels)
        return diag_set(diag, HPFC_E_ARG, "hpfc_file_check_pool_layout: no such level");
    if (!f->compact)
        return HPFC_OK; /* the paper layout has no index of its own: its pixels say it all */
    const file_level *lv = &f->lv[level];
    const char *what = NULL;
    int st = pool_check_level(&lv->pool, &lv->compact, lv->word_bits, &what);
    return st ? diag_set(diag, st, "level %u: %s", level, what) : HPFC_OK;
}
