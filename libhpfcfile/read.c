/*
 * The zero-copy .hpfc reader (spec/hpfc-format.md, "Safe reading").
 *
 * Opening checks the header, the level table and the section directory in
 * O(levels + sections) and never decodes a pool. Navigation then trusts only
 * what open checked: every pixel access re-checks that the pixel's whole
 * image lies inside its level's pool (its size follows from its mask), so a
 * corrupt pool gives HPFC_E_CORRUPT, never a read outside the buffer. A
 * descent gains one level per step and a refined pixel at the last level is
 * corrupt, so no walk can loop.
 *
 * Nothing here allocates after open or writes to the handle: any number of
 * threads may share one.
 */
#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include "attrs.h"
#include "feat.h"
#include "format.h"
#include "geometry.h"
#include "labels.h"
#include "pool.h"
#include "internal.h"
#include "reader.h"

/* One level as navigation needs it, derived at open. */
typedef struct file_level {
    format_bits pool;       /* s^l bits; reads may look ahead to the buffer's end */
    uint32_t word_bits;     /* k_w */
    uint32_t address_bits;  /* k_@ */
    uint32_t cols, rows;    /* pixels per image */
    uint64_t image_pixels;  /* cols * rows */
    uint64_t record_bits;   /* level 0: 1 + max(k_@, k_w) */
    int64_t cell_w, cell_h;
    bool last;
    hpfc_level_info info;
    pool_level compact;     /* the compact layout's geometry (pool.h) */
} file_level;

struct hpfc_file {
    const uint8_t *data;
    size_t size;
    void *map; /* hpfc_open's mapping; NULL for a caller's buffer */
    size_t map_size;
    const uint8_t *directory;
    uint64_t meta_size;
    hpfc_file_info info;
    file_level lv[HPFC_MAX_LEVELS];
    /* log2 of cols and rows when both are powers of two, else 0: point
     * location then reads every level's cell index off one quotient */
    uint32_t shift_x, shift_y;
    bool compact;           /* incompat flag: the compact pool layout */
    const uint8_t *feat;    /* the FEAT section, NULL if none */
    uint64_t feat_len;
    labels_view labels;     /* the LABL section (labels.present: the file has one) */
    const uint8_t *attr, *edgf; /* the ATTR and EDGF sections, NULL if none */
    uint64_t attr_len, edgf_len;
    geom_view geom;         /* the GEOM section (geom.present: the file has one) */
};

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

/* The compact layout's own fields (§16.1): no address, the stabbed
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
 * offset (two sections at one offset must both be empty). */
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
                 tag_is(e, FORMAT_TAG_GEOM);
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

static int read_feat(hpfc_file *f, const uint8_t *feat)
{
    const uint8_t *s = f->data + sec_get_offset(feat);
    uint64_t length = sec_get_length(feat);
    int st = feat_section_check(s, length);
    if (!st) {
        f->feat = s;
        f->feat_len = length;
    }
    return st;
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

/* An optional section checked by `check`: its bytes into *at, *len. */
static int read_optional(hpfc_file *f, const uint8_t *entry, int (*check)(const uint8_t *, uint64_t),
                         const uint8_t **at, uint64_t *len)
{
    const uint8_t *s = f->data + sec_get_offset(entry);
    int st = check(s, sec_get_length(entry));
    if (!st) {
        *at = s;
        *len = sec_get_length(entry);
    }
    return st;
}

static int read_directory(hpfc_file *f)
{
    uint32_t count = f->info.section_count;
    span *spans = malloc((count ? count : 1) * sizeof *spans);
    if (!spans)
        return HPFC_E_NOMEM;
    const uint8_t *pool = NULL, *crs = NULL, *feat = NULL, *labl = NULL, *attr = NULL, *edgf = NULL,
                  *geom = NULL;
    int st = HPFC_OK;
    for (uint32_t k = 0; k < count && !st; k++) {
        const uint8_t *e = section_entry(f, k);
        st = check_section_entry(f, e, &spans[k]);
        if (tag_is(e, FORMAT_TAG_POOL))
            pool = e;
        else if (tag_is(e, FORMAT_TAG_CRS))
            crs = e;
        else if (tag_is(e, FORMAT_TAG_FEAT))
            feat = e;
        else if (tag_is(e, FORMAT_TAG_LABL))
            labl = e;
        else if (tag_is(e, FORMAT_TAG_ATTR))
            attr = e;
        else if (tag_is(e, FORMAT_TAG_EDGF))
            edgf = e;
        else if (tag_is(e, FORMAT_TAG_GEOM))
            geom = e;
    }
    if (!st)
        st = check_section_set(spans, count);
    free(spans);
    if (!st && !pool)
        st = HPFC_E_SECTION;
    if (!st && crs)
        st = read_crs(f, crs);
    if (!st && feat)
        st = read_feat(f, feat);
    if (!st && labl)
        st = read_labl(f, labl);
    if (!st && attr)
        st = read_optional(f, attr, attr_section_check, &f->attr, &f->attr_len);
    if (!st && edgf)
        st = read_optional(f, edgf, edgf_section_check, &f->edgf, &f->edgf_len);
    if (!st && geom)
        st = read_geom(f, geom);
    if (!st)
        st = check_pools_in_section(f, pool);
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

int hpfc_open(const char *path, unsigned flags, hpfc_file **out)
{
    if (!path || !out)
        return HPFC_E_ARG;
    *out = NULL;
    int fd = open(path, O_RDONLY | O_CLOEXEC);
    if (fd < 0)
        return errno == ENOMEM ? HPFC_E_NOMEM : HPFC_E_IO;
    struct stat sb;
    if (fstat(fd, &sb) || !S_ISREG(sb.st_mode) || (uint64_t)sb.st_size > SIZE_MAX) {
        close(fd);
        return HPFC_E_IO;
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
    free(f);
}

int hpfc_verify_checksums(const hpfc_file *f)
{
    if (!f)
        return HPFC_E_ARG;
    if (format_meta_crc(f->data, f->meta_size) != hdr_get_meta_crc32c(f->data))
        return HPFC_E_CHECKSUM;
    for (uint32_t k = 0; k < f->info.section_count; k++) {
        const uint8_t *e = section_entry(f, k);
        if (crc32c_update(0, f->data + sec_get_offset(e), (size_t)sec_get_length(e)) != sec_get_crc32c(e))
            return HPFC_E_CHECKSUM;
    }
    return HPFC_OK;
}

const uint8_t *reader_attr_section(const hpfc_file *f, uint64_t *length)
{
    *length = f->attr_len;
    return f->attr;
}

const geom_view *reader_geometry(const hpfc_file *f)
{
    return &f->geom;
}

const uint8_t *reader_edgf_section(const hpfc_file *f, uint64_t *length)
{
    *length = f->edgf_len;
    return f->edgf;
}

const uint8_t *reader_feat_section(const hpfc_file *f, uint64_t *length)
{
    *length = f->feat_len;
    return f->feat;
}

const labels_view *reader_labels(const hpfc_file *f)
{
    return &f->labels;
}

const format_bits *reader_pool(const hpfc_file *f, uint32_t level)
{
    return &f->lv[level].pool;
}

/* ---- metadata queries -------------------------------------------------------------- */

void hpfc_file_get_info(const hpfc_file *f, hpfc_file_info *info)
{
    if (f && info)
        *info = f->info;
}

int hpfc_file_get_level(const hpfc_file *f, uint32_t level, hpfc_level_info *out)
{
    if (!f || !out || level >= f->info.levels)
        return HPFC_E_ARG;
    *out = f->lv[level].info;
    return HPFC_OK;
}

int hpfc_file_get_section(const hpfc_file *f, uint32_t index, hpfc_section_info *out)
{
    if (!f || !out || index >= f->info.section_count)
        return HPFC_E_ARG;
    const uint8_t *e = section_entry(f, index);
    memcpy(out->tag, e + sec_OFF_tag, sec_SIZE_tag);
    out->tag[4] = '\0';
    out->flags = sec_get_flags(e);
    out->offset = sec_get_offset(e);
    out->length = sec_get_length(e);
    out->crc32c = sec_get_crc32c(e);
    return HPFC_OK;
}

/* ---- pixels ---------------------------------------------------------------------------- */

/* Where pixel p (scanline index) of a refined image starts, after checking
 * the image: its mask and every slot the mask implies lie inside the pool,
 * and no pixel of the last level is refined. */
static inline int refined_image_pixel(const file_level *lv, uint64_t image, uint64_t p, int *type,
                               uint64_t *slot)
{
    uint64_t per = lv->image_pixels, bits = lv->pool.bits;
    if (image > bits || per > bits - image)
        return HPFC_E_CORRUPT;
    uint64_t before, total;
    if (per <= 57) { /* the common small image: one load holds the mask */
        uint64_t mask = format_peek(&lv->pool, image, (unsigned)per);
        total = format_ones(mask);
        before = format_ones(mask & ~(UINT64_MAX >> p));
        *type = (int)(mask >> (63 - p) & 1);
    } else {
        before = format_popcount(&lv->pool, image, p);
        *type = (int)format_get(&lv->pool, image + p, 1);
        total = before + (uint64_t)*type + format_popcount(&lv->pool, image + p + 1, per - p - 1);
    }
    if (total && lv->last)
        return HPFC_E_CORRUPT;
    /* at most 2^20 * (2^22 + 64) bits: no overflow */
    uint64_t slots = total * lv->address_bits + (per - total) * lv->word_bits;
    if (slots > bits - image - per)
        return HPFC_E_CORRUPT;
    *slot = image + per + before * lv->address_bits + (p - before) * lv->word_bits;
    return HPFC_OK;
}

/* A pixel as an access finds it, in either layout. */
typedef struct pixel_at {
    int type;       /* HPFC_PIXEL_WORD or HPFC_PIXEL_REFINED */
    uint64_t slot;  /* paper: pool bit of its address or word slot (root: after the
                       type bit); compact: its pixel index g in the level */
    uint64_t word;  /* compact word pixel: 0 stabbed, NO_WORD private (the
                       ranks are counted only when asked: pool_rank) */
} pixel_at;

#define NO_WORD UINT64_MAX

/* Pixel p of compact image `image` (its index in the level). */
static inline int compact_image_pixel(const file_level *lv, uint32_t level, uint64_t image,
                                      uint64_t p, pixel_at *at)
{
    if (image >= lv->info.images)
        return level ? HPFC_E_CORRUPT : HPFC_E_ARG; /* as a paper image past its pool */
    uint64_t g = image * lv->image_pixels + p; /* < P: open checked images * n * m */
    int kind;
    int st = pool_read_type(&lv->pool, &lv->compact, g, &kind);
    if (st)
        return st;
    if (kind == POOL_REFINED && lv->last)
        return HPFC_E_CORRUPT;
    at->type = kind == POOL_REFINED ? HPFC_PIXEL_REFINED : HPFC_PIXEL_WORD;
    at->slot = g;
    at->word = kind == POOL_PRIVATE ? NO_WORD : 0;
    return HPFC_OK;
}

/* Pixel (i, j) of the image `image` of `level` (paper: its bit offset;
 * compact: its index). */
static inline int image_pixel(const hpfc_file *f, uint32_t level, uint64_t image, uint32_t i, uint32_t j,
                              pixel_at *at)
{
    const file_level *lv = &f->lv[level];
    if (i >= lv->cols || j >= lv->rows)
        return HPFC_E_ARG;
    uint64_t p = (uint64_t)j * lv->cols + i;
    if (f->compact)
        return compact_image_pixel(lv, level, image, p, at);
    at->word = NO_WORD; /* unused in this layout */
    if (level > 0)
        return refined_image_pixel(lv, image, p, &at->type, &at->slot);
    if (image != 0)
        return HPFC_E_ARG;
    uint64_t record = p * lv->record_bits; /* fixed records: inside s^0 by construction */
    at->type = (int)format_get(&lv->pool, record, 1);
    at->slot = record + 1;
    return at->type == HPFC_PIXEL_REFINED && lv->last ? HPFC_E_CORRUPT : HPFC_OK;
}

static int top_pixel(const hpfc_file *f, const hpfc_pixel *px, pixel_at *at)
{
    if (!f || !px || px->depth >= f->info.levels)
        return HPFC_E_ARG;
    uint32_t d = px->depth;
    return image_pixel(f, d, px->path[d].image, px->path[d].i, px->path[d].j, at);
}

/* The child image of a refined pixel: its address, or (compact) the rank
 * of its refined bit, checked against the level's count (the next level's
 * images) by pool_rank. */
static inline int child_address(const hpfc_file *f, uint32_t level, const pixel_at *at,
                                uint64_t *child)
{
    const file_level *lv = &f->lv[level];
    if (f->compact)
        return pool_rank(&lv->pool, &lv->compact, at->slot, POOL_REFINED, child);
    *child = format_get(&lv->pool, at->slot, lv->address_bits);
    return HPFC_OK;
}

static void copy_path(hpfc_pixel *out, const hpfc_pixel *px, uint32_t depth)
{
    if (out != px)
        memcpy(out->path, px->path, (depth + 1) * sizeof px->path[0]);
}

int hpfc_pixel_root(const hpfc_file *f, uint32_t i, uint32_t j, hpfc_pixel *out)
{
    if (!f || !out || i >= f->info.root_cols || j >= f->info.root_rows)
        return HPFC_E_ARG;
    out->depth = 0;
    out->path[0].image = 0;
    out->path[0].i = i;
    out->path[0].j = j;
    return HPFC_OK;
}

int hpfc_pixel_type(const hpfc_file *f, const hpfc_pixel *px, int *type)
{
    pixel_at at;
    int st = type ? top_pixel(f, px, &at) : HPFC_E_ARG;
    if (!st)
        *type = at.type;
    return st;
}

int hpfc_pixel_child(const hpfc_file *f, const hpfc_pixel *px, uint32_t i, uint32_t j, hpfc_pixel *out)
{
    pixel_at at, child_at;
    int st = out ? top_pixel(f, px, &at) : HPFC_E_ARG;
    if (st)
        return st;
    if (at.type != HPFC_PIXEL_REFINED)
        return HPFC_E_NO_PIXEL;
    uint32_t d = px->depth; /* < levels - 1: a refined pixel at the last level is corrupt */
    uint64_t child;
    st = child_address(f, d, &at, &child);
    if (!st)
        st = image_pixel(f, d + 1, child, i, j, &child_at);
    if (st)
        return st;
    copy_path(out, px, d);
    out->depth = d + 1;
    out->path[d + 1].image = child;
    out->path[d + 1].i = i;
    out->path[d + 1].j = j;
    return HPFC_OK;
}

int hpfc_pixel_parent(const hpfc_pixel *px, hpfc_pixel *out)
{
    if (!px || !out || px->depth >= HPFC_MAX_LEVELS)
        return HPFC_E_ARG;
    if (px->depth == 0)
        return HPFC_E_NO_PIXEL;
    uint32_t d = px->depth - 1;
    copy_path(out, px, d);
    out->depth = d;
    return HPFC_OK;
}

/* ---- moves (paper Algorithm 1 and its mirrors) ------------------------------------------ */

/* Is the pixel at path entry k on the image border that dir leaves by? */
static bool on_border(const file_level *lv, uint32_t i, uint32_t j, int dir)
{
    switch (dir) {
    case HPFC_WEST: return i == 0;
    case HPFC_EAST: return i + 1 >= lv->cols;
    case HPFC_NORTH: return j == 0;
    default: return j + 1 >= lv->rows;
    }
}

/* Entry (i, j) of the image entered at `level` while descending: the column
 * (W/E) or row (N/S) next to the road crossed; along the road, P's own row
 * or column while level <= P's depth, else the neighbour's first pixel in its
 * clockwise order (W: north end, E: south end, N: east end, S: west end). */
static void entry_pixel(const file_level *lv, const hpfc_pixel *p, uint32_t level, int dir, uint32_t *i,
                        uint32_t *j)
{
    bool keep = level <= p->depth;
    switch (dir) {
    case HPFC_WEST:
        *i = lv->cols - 1;
        *j = keep ? p->path[level].j : 0;
        break;
    case HPFC_EAST:
        *i = 0;
        *j = keep ? p->path[level].j : lv->rows - 1;
        break;
    case HPFC_NORTH:
        *j = lv->rows - 1;
        *i = keep ? p->path[level].i : lv->cols - 1;
        break;
    default:
        *j = 0;
        *i = keep ? p->path[level].i : 0;
        break;
    }
}

/* One step down a pixel path: records pixel (i, j) of `image` at `level` in
 * out. A word pixel ends the path there (*word, out->depth = level); a
 * refined one replaces *image by its child image. */
static inline int descend(const hpfc_file *f, uint32_t level, uint64_t *image, uint32_t i, uint32_t j,
                          hpfc_pixel *out, bool *word)
{
    pixel_at at;
    int st = image_pixel(f, level, *image, i, j, &at);
    if (st)
        return st;
    out->path[level].image = *image;
    out->path[level].i = i;
    out->path[level].j = j;
    *word = at.type == HPFC_PIXEL_WORD;
    if (*word)
        out->depth = level;
    else
        return child_address(f, level, &at, image);
    return HPFC_OK;
}

int hpfc_pixel_move(const hpfc_file *f, const hpfc_pixel *px, int dir, hpfc_pixel *out)
{
    if (!f || !px || !out || px->depth >= f->info.levels || dir < HPFC_WEST || dir > HPFC_SOUTH)
        return HPFC_E_ARG;
    /* Up: the deepest ancestor that has a neighbour in its own image. */
    uint32_t k = px->depth;
    while (on_border(&f->lv[k], px->path[k].i, px->path[k].j, dir)) {
        if (k == 0)
            return HPFC_E_NO_PIXEL; /* the domain's border */
        k--;
    }
    uint32_t i = px->path[k].i - (dir == HPFC_WEST) + (dir == HPFC_EAST);
    uint32_t j = px->path[k].j - (dir == HPFC_NORTH) + (dir == HPFC_SOUTH);
    uint64_t image = px->path[k].image;
    copy_path(out, px, k);
    for (uint32_t level = k;; level++) {
        bool word;
        int st = descend(f, level, &image, i, j, out, &word);
        if (st || word)
            return st;
        /* px->path[level + 1] is read before out->path[level + 1] is written */
        entry_pixel(&f->lv[level + 1], px, level + 1, dir, &i, &j);
    }
}

/* ---- point location and geometry ---------------------------------------------------------- */

int hpfc_locate(const hpfc_file *f, int64_t x, int64_t y, hpfc_pixel *out)
{
    return f && out ? reader_locate_near(f, NULL, x, y, out) : HPFC_E_ARG;
}

int reader_locate_near(const hpfc_file *f, const hpfc_pixel *near, int64_t x, int64_t y,
                       hpfc_pixel *out)
{
    const hpfc_file_info *in = &f->info;
    if (x < in->x0 || y < in->y0)
        return HPFC_E_NO_PIXEL;
    /* offsets inside the domain (|x0| <= 2^62, so the differences fit) */
    uint64_t rx = (uint64_t)x - (uint64_t)in->x0, ry = (uint64_t)y - (uint64_t)in->y0;
    if (rx >= (uint64_t)in->width || ry >= (uint64_t)in->height)
        return HPFC_E_NO_PIXEL;
    /* levels above near's own whose refined pixel may also hold the point */
    uint32_t shared = near && near->depth < in->levels ? near->depth : 0;
    /* 2^a x 2^b images: the point's cell at the deepest level, whose bits
     * are every level's cell index (divisions are most of a descent's
     * arithmetic); cell_w(0) = cell_w(deepest) << (a * deepest) < 2^63
     * bounds the shifts */
    uint32_t deepest = in->levels - 1, sx = f->shift_x, sy = f->shift_y;
    bool radix = sx && sy;
    uint64_t qx = radix ? rx / (uint64_t)f->lv[deepest].cell_w : 0;
    uint64_t qy = radix ? ry / (uint64_t)f->lv[deepest].cell_h : 0;
    uint64_t image = 0;
    for (uint32_t level = 0;; level++) {
        const file_level *lv = &f->lv[level];
        uint64_t gx, gy; /* < cols, rows: the point lies in the parent cell */
        if (radix) {
            gx = qx >> (sx * (deepest - level));
            gy = qy >> (sy * (deepest - level));
            if (level > 0)
                gx &= lv->cols - 1, gy &= lv->rows - 1;
        } else {
            uint64_t cw = (uint64_t)lv->cell_w, ch = (uint64_t)lv->cell_h;
            gx = rx / cw, gy = ry / ch;
            rx -= gx * cw;
            ry -= gy * ch;
        }
        uint32_t i = (uint32_t)gx, j = lv->rows - 1 - (uint32_t)gy; /* j = 0 is the northern row */
        if (level < shared && near->path[level].image == image && near->path[level].i == i &&
            near->path[level].j == j) {
            /* near's ancestor: the descent through it is near's path (out may be near) */
            out->path[level] = near->path[level];
            image = near->path[level + 1].image;
            continue;
        }
        shared = 0;
        bool word;
        int st = descend(f, level, &image, i, j, out, &word);
        if (st || word)
            return st;
    }
}

int hpfc_pixel_bounds(const hpfc_file *f, const hpfc_pixel *px, int64_t *x0, int64_t *y0, int64_t *x1,
                      int64_t *y1)
{
    if (!f || !px || !x0 || !y0 || !x1 || !y1 || px->depth >= f->info.levels)
        return HPFC_E_ARG;
    int64_t gx = 0, gy = 0; /* south-west corner relative to the domain's */
    for (uint32_t l = 0; l <= px->depth; l++) {
        const file_level *lv = &f->lv[l];
        if (px->path[l].i >= lv->cols || px->path[l].j >= lv->rows)
            return HPFC_E_ARG;
        gx += (int64_t)px->path[l].i * lv->cell_w;
        gy += (int64_t)(lv->rows - 1 - px->path[l].j) * lv->cell_h;
    }
    const file_level *lv = &f->lv[px->depth];
    *x0 = f->info.x0 + gx;
    *y0 = f->info.y0 + gy;
    *x1 = *x0 + lv->cell_w;
    *y1 = *y0 + lv->cell_h;
    return HPFC_OK;
}

/* ---- words ------------------------------------------------------------------------------ */

/* Decodes the word in the k_w-bit slot at `off`, symbol by symbol up to its
 * fourth '+', in windows of up to 56 bits. Stores the first `cap` symbols
 * when buf is non-NULL; *len gets the full length. */
static int decode_word(const format_bits *pool, uint64_t off, uint32_t word_bits, char *buf, size_t cap,
                       size_t *len)
{
    uint64_t pos = 0, window = 0;
    unsigned have = 0, plus = 0; /* `have` bits of the slot are left-aligned in window */
    size_t n = 0;
    while (plus < 4) {
        if (have < 4) {
            uint64_t left = word_bits - pos;
            have = left < 56 ? (unsigned)left : 56;
            window = format_peek(pool, off + pos, have);
            if (have == 0)
                return HPFC_E_CORRUPT; /* no fourth '+' in the slot */
        }
        char c;
        if (!(window >> 63)) {
            c = '+';
            plus++;
            window <<= 1;
            have -= 1;
            pos += 1;
        } else {
            unsigned code = (unsigned)(window >> 60);
            if (have < 4 || code >= FORMAT_CODE_RESERVED_MIN)
                return HPFC_E_CORRUPT; /* a code cut by the slot's end, or reserved */
            c = format_code_symbol(code);
            window <<= 4;
            have -= 4;
            pos += 4;
        }
        if (buf && n < cap)
            buf[n] = c;
        n++;
    }
    *len = n;
    return buf && n > cap ? HPFC_E_ARG : HPFC_OK;
}

/* A compact word pixel's word: "++++" for a private one, else its code. */
static int compact_word(const file_level *lv, const pixel_at *at, char *buf, size_t cap, size_t *len)
{
    if (at->word == NO_WORD) {
        for (size_t k = 0; buf && k < cap && k < 4; k++)
            buf[k] = '+';
        *len = 4;
        return buf && cap < 4 ? HPFC_E_ARG : HPFC_OK;
    }
    uint64_t start, end, word;
    int st = pool_rank(&lv->pool, &lv->compact, at->slot, POOL_STABBED, &word);
    if (!st)
        st = pool_word_span(&lv->pool, &lv->compact, lv->word_bits, word, &start, &end);
    return st ? st : pool_decode_word(&lv->pool, start, end, buf, cap, len);
}

int hpfc_pixel_word(const hpfc_file *f, const hpfc_pixel *px, char *buf, size_t cap, size_t *len)
{
    pixel_at at;
    int st = len ? top_pixel(f, px, &at) : HPFC_E_ARG;
    if (st)
        return st;
    if (at.type != HPFC_PIXEL_WORD)
        return HPFC_E_ARG;
    const file_level *lv = &f->lv[px->depth];
    if (f->compact)
        return compact_word(lv, &at, buf, cap, len);
    return decode_word(&lv->pool, at.slot, lv->word_bits, buf, cap, len);
}

int hpfc_pixel_is_private(const hpfc_file *f, const hpfc_pixel *px, int *is_private)
{
    pixel_at at;
    int st = is_private ? top_pixel(f, px, &at) : HPFC_E_ARG;
    if (st)
        return st;
    const file_level *lv = &f->lv[px->depth];
    if (at.type == HPFC_PIXEL_REFINED) {
        *is_private = 0;
        return HPFC_OK;
    }
    if (f->compact) {
        *is_private = at.word == NO_WORD;
        return HPFC_OK;
    }
    if (lv->word_bits < FORMAT_MIN_WORD_BITS)
        return HPFC_E_CORRUPT;
    /* "++++" is the only word whose code starts with four 0 bits */
    *is_private = format_peek(&lv->pool, at.slot, 4) == 0;
    return HPFC_OK;
}

/* ---- internals for the traversal code (reader.h) ----------------------------------------- */

/* Over every level, whatever its word count says: a corrupt mask can put a
 * word pixel in any level, and its slot bounds its crossings. */
/* The crossings a word code of k bits can hold: the paper's code spends 4
 * bits a crossing after its four '+', the compact one at least 1. */
static uint32_t crossings_in(const hpfc_file *f, uint32_t k)
{
    if (f->compact)
        return k;
    return k >= FORMAT_MIN_WORD_BITS ? (k - FORMAT_MIN_WORD_BITS) / 4 : 0;
}

uint32_t reader_level_max_crossings(const hpfc_file *f, uint32_t level)
{
    return crossings_in(f, f->lv[level].word_bits);
}

uint32_t reader_max_crossings(const hpfc_file *f)
{
    uint32_t most = 0;
    for (uint32_t l = 0; l < f->info.levels; l++) {
        uint32_t c = crossings_in(f, f->lv[l].word_bits);
        most = c > most ? c : most;
    }
    return most;
}

uint64_t reader_total_crossings(const hpfc_file *f)
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

const uint8_t *reader_bytes(const hpfc_file *f)
{
    return f->data;
}

uint64_t reader_total_leaves(const hpfc_file *f)
{
    uint64_t total = 0;
    for (uint32_t l = 0; l < f->info.levels; l++)
        if (!format_add(total, f->lv[l].info.word_pixels, &total))
            return UINT64_MAX;
    return total;
}

/* The absolute bit of px's record or slot; a refined pixel's too unless
 * leaf_only (HPFC_E_ARG then). */
static int slot_bit(const hpfc_file *f, const hpfc_pixel *px, bool leaf_only, uint64_t *bit)
{
    pixel_at at;
    int st = bit ? top_pixel(f, px, &at) : HPFC_E_ARG;
    if (!st && leaf_only && at.type != HPFC_PIXEL_WORD)
        st = HPFC_E_ARG;
    if (st)
        return st;
    uint64_t slot = at.slot;
    if (f->compact)
        slot = pool_type_bit(&f->lv[px->depth].compact, slot);
    else if (px->depth == 0)
        slot -= 1; /* the root record starts at its type bit */
    *bit = f->lv[px->depth].info.pool_offset * 8 + slot;
    return HPFC_OK;
}

int reader_pixel_slot_bit(const hpfc_file *f, const hpfc_pixel *px, uint64_t *bit)
{
    return slot_bit(f, px, false, bit);
}

int reader_leaf_slot_bit(const hpfc_file *f, const hpfc_pixel *px, uint64_t *bit)
{
    return slot_bit(f, px, true, bit);
}

/* ---- pool layout, for the walker's key index (reader.h) ------------------------------------ */

/* A compact image is one unit of its level's image numbering; its refined
 * pixels are counted by reading each. */
static int compact_image_bits(const hpfc_file *f, uint32_t level, uint64_t image, uint64_t *bits,
                              uint64_t *refined)
{
    const file_level *lv = &f->lv[level];
    if (image >= lv->info.images)
        return level ? HPFC_E_CORRUPT : HPFC_E_ARG;
    uint64_t total = 0;
    for (uint64_t p = 0; p < lv->image_pixels; p++) {
        pixel_at at;
        int st = compact_image_pixel(lv, level, image, p, &at);
        if (st)
            return st;
        total += at.type == HPFC_PIXEL_REFINED;
    }
    *bits = 1;
    *refined = total;
    return HPFC_OK;
}

int reader_image_bits(const hpfc_file *f, uint32_t level, uint64_t image, uint64_t *bits,
                      uint64_t *refined)
{
    if (level >= f->info.levels)
        return HPFC_E_ARG;
    const file_level *lv = &f->lv[level];
    uint64_t per = lv->image_pixels, pool = lv->pool.bits, total = 0;
    if (f->compact)
        return compact_image_bits(f, level, image, bits, refined);
    if (level == 0) {
        if (image != 0)
            return HPFC_E_ARG;
        for (uint64_t p = 0; p < per; p++) /* s^0 holds every record (the recurrence) */
            total += format_get(&lv->pool, p * lv->record_bits, 1);
        *bits = per * lv->record_bits;
    } else {
        if (image > pool || per > pool - image)
            return HPFC_E_CORRUPT;
        total = format_popcount(&lv->pool, image, per);
        uint64_t slots = total * lv->address_bits + (per - total) * lv->word_bits;
        if (slots > pool - image - per)
            return HPFC_E_CORRUPT;
        *bits = per + slots;
    }
    if (total && lv->last)
        return HPFC_E_CORRUPT;
    *refined = total;
    return HPFC_OK;
}

int reader_next_refined(const hpfc_file *f, uint32_t level, uint64_t image, reader_refined *it,
                        uint32_t *pixel, uint64_t *address)
{
    const file_level *lv = &f->lv[level];
    uint64_t per = lv->image_pixels;
    if (f->compact) {
        for (; it->p < per; it->p++) {
            pixel_at at;
            int st = compact_image_pixel(lv, level, image, it->p, &at);
            if (st)
                return st;
            if (at.type == HPFC_PIXEL_REFINED) {
                *pixel = (uint32_t)it->p++;
                return child_address(f, level, &at, address);
            }
        }
        return HPFC_E_NO_PIXEL;
    }
    if (level == 0) {
        for (; it->p < per; it->p++)
            if (format_get(&lv->pool, it->p * lv->record_bits, 1)) {
                *pixel = (uint32_t)it->p;
                *address = format_get(&lv->pool, it->p * lv->record_bits + 1, lv->address_bits);
                it->p++;
                return HPFC_OK;
            }
        return HPFC_E_NO_PIXEL;
    }
    while (it->p < per) {
        unsigned k = per - it->p < 56 ? (unsigned)(per - it->p) : 56;
        uint64_t mask = format_peek(&lv->pool, image + it->p, k);
        if (!mask) {
            it->p += k;
            continue;
        }
        it->p += (uint64_t)__builtin_clzll(mask);
        uint64_t slot =
            image + per + it->before * lv->address_bits + (it->p - it->before) * lv->word_bits;
        *pixel = (uint32_t)it->p;
        *address = format_get(&lv->pool, slot, lv->address_bits);
        it->p++;
        it->before++;
        return HPFC_OK;
    }
    return HPFC_E_NO_PIXEL;
}

int reader_word_at(const hpfc_file *f, uint32_t level, uint64_t image, uint64_t bit,
                   uint32_t *pixel)
{
    const file_level *lv = &f->lv[level];
    uint64_t per = lv->image_pixels;
    if (f->compact) {
        uint64_t g;
        pixel_at at;
        if (!pool_pixel_at_bit(&lv->compact, bit, &g) || g / per != image ||
            compact_image_pixel(lv, level, image, g % per, &at) || at.type != HPFC_PIXEL_WORD)
            return HPFC_E_ARG;
        *pixel = (uint32_t)(g % per);
        return HPFC_OK;
    }
    if (level == 0) {
        uint64_t p = bit / lv->record_bits;
        if (bit % lv->record_bits || p >= per || format_get(&lv->pool, bit, 1))
            return HPFC_E_ARG;
        *pixel = (uint32_t)p;
        return HPFC_OK;
    }
    if (bit < image + per)
        return HPFC_E_ARG; /* in the mask, or before the image */
    uint64_t want = bit - image - per, at = 0;
    for (uint64_t p = 0; p < per && at <= want; p++) {
        int refined = (int)format_get(&lv->pool, image + p, 1);
        if (at == want && !refined) {
            *pixel = (uint32_t)p;
            return HPFC_OK;
        }
        at += refined ? lv->address_bits : lv->word_bits;
    }
    return HPFC_E_ARG;
}

/* ---- layout-neutral views for the traversal and faces code (reader.h) ----------------------- */

bool reader_is_compact(const hpfc_file *f)
{
    return f->compact;
}

uint64_t reader_image_end(const hpfc_file *f, uint32_t level)
{
    const file_level *lv = &f->lv[level];
    return f->compact ? lv->info.images : lv->info.pool_bits;
}

int reader_slot_image(const hpfc_file *f, uint32_t level, uint64_t bit, uint64_t *image)
{
    const file_level *lv = &f->lv[level];
    uint64_t g;
    if (!f->compact || !pool_pixel_at_bit(&lv->compact, bit, &g))
        return HPFC_E_ARG;
    *image = g / lv->image_pixels;
    return HPFC_OK;
}

void reader_slot_grid(const hpfc_file *f, uint32_t level, uint64_t *unit, uint64_t *entries)
{
    const file_level *lv = &f->lv[level];
    if (f->compact) { /* type bits, two a pixel, in the pool's first type_bits */
        *unit = 2;
        *entries = lv->compact.type_bits / 2 + 1;
    } else if (level == 0) {
        *unit = lv->record_bits;
        *entries = lv->image_pixels;
    } else {
        *unit = lv->word_bits ? lv->word_bits : 1; /* no word slots: no entries needed */
        *entries = lv->info.word_pixels ? lv->info.pool_bits / *unit + 1 : 0;
    }
}

/* Leaf number (TEAM decision): the word pixels of a level in pool order.
 * Compact: the pixels before the leaf that are not refined, O(1). */
int reader_leaf_rank(const hpfc_file *f, const hpfc_pixel *leaf, uint64_t *rank)
{
    pixel_at at;
    int st = rank ? top_pixel(f, leaf, &at) : HPFC_E_ARG;
    if (!st && at.type != HPFC_PIXEL_WORD)
        st = HPFC_E_ARG;
    if (st)
        return st;
    uint32_t d = leaf->depth;
    const file_level *lv = &f->lv[d];
    if (f->compact) {
        uint64_t g = leaf->path[d].image * lv->image_pixels +
                     (uint64_t)leaf->path[d].j * lv->cols + leaf->path[d].i;
        pool_pixel px;
        st = pool_read_pixel(&lv->pool, &lv->compact, g, &px);
        if (!st)
            *rank = g - px.refined;
        /* damaged block counts can rank a leaf past the level's leaves */
        return st ? st : *rank < lv->info.word_pixels ? HPFC_OK : HPFC_E_CORRUPT;
    }
    return labels_leaf_rank_paper(f, leaf, rank);
}

/* The compact layout's word pixels of a level before unit u (an image,
 * or a root pixel): what the LABL rank samples count (spec §15.2). */
int reader_compact_words_before(const hpfc_file *f, uint32_t level, uint64_t unit, uint64_t *words)
{
    const file_level *lv = &f->lv[level];
    uint64_t g = level ? unit * lv->image_pixels : unit;
    pool_pixel px;
    int st = pool_read_pixel(&lv->pool, &lv->compact, g, &px);
    if (!st)
        *words = g - px.refined;
    return st;
}

int hpfc_check_pool_layout(const hpfc_file *f, uint32_t level, hpfc_diag *diag)
{
    diag_clear(diag);
    if (!f || level >= f->info.levels)
        return diag_set(diag, HPFC_E_ARG, "hpfc_check_pool_layout: no such level");
    if (!f->compact)
        return HPFC_OK; /* the paper layout has no index of its own: its pixels say it all */
    const file_level *lv = &f->lv[level];
    const char *what = NULL;
    int st = pool_check_level(&lv->pool, &lv->compact, lv->word_bits, &what);
    return st ? diag_set(diag, st, "level %u: %s", level, what) : HPFC_OK;
}
