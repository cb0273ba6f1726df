#include "views.h"

#include <ctype.h>
#include <errno.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "jsonw.h"
#include "roads.h"
#include "word.h"

static const char *const road_names[4] = {"W", "N", "E", "S"};

int view_fail(char *why, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(why, VIEW_WHY, fmt, ap);
    va_end(ap);
    return VIEW_FAIL;
}

static int fail_status(char *why, const char *what, int st)
{
    return view_fail(why, "%s: %s", what, hpfc_strerror(st));
}

/* ---- decimals ----------------------------------------------------------------- */

static size_t scan_digits(const char *s, size_t len, size_t p)
{
    while (p < len && isdigit((unsigned char)s[p]))
        p++;
    return p;
}

/* Appends digit c to the significand; leading zeros are dropped, so only
 * the significant digits count against the limit. */
static int push_digit(decimal *d, size_t *nd, char c)
{
    if (*nd == 0 && c == '0')
        return 0;
    if (*nd + 1 >= sizeof d->digits)
        return -1;
    d->digits[(*nd)++] = c;
    return 0;
}

static int parse_exponent(const char *s, size_t len, size_t p, long *e)
{
    int neg = 0;
    if (p < len && (s[p] == '+' || s[p] == '-'))
        neg = s[p++] == '-';
    size_t q = scan_digits(s, len, p);
    if (q == p || q != len)
        return -1;
    *e = 0;
    for (; p < q; p++)
        if (*e < 100000)
            *e = *e * 10 + (s[p] - '0');
    if (neg)
        *e = -*e;
    return 0;
}

int decimal_parse(const char *s, size_t len, decimal *d)
{
    memset(d, 0, sizeof *d);
    size_t p = 0, nd = 0;
    long exp10 = 0, e = 0;
    if (p < len && (s[p] == '+' || s[p] == '-'))
        d->neg = s[p++] == '-';
    size_t int_end = scan_digits(s, len, p), frac_end = int_end;
    for (size_t k = p; k < int_end; k++)
        if (push_digit(d, &nd, s[k]))
            return -1;
    if (int_end < len && s[int_end] == '.') {
        frac_end = scan_digits(s, len, int_end + 1);
        for (size_t k = int_end + 1; k < frac_end; k++) {
            if (push_digit(d, &nd, s[k]))
                return -1;
            exp10--;
        }
    }
    size_t ndig = (int_end - p) + (frac_end > int_end ? frac_end - int_end - 1 : 0);
    if (ndig == 0)
        return -1;
    if (frac_end < len) {
        if ((s[frac_end] != 'e' && s[frac_end] != 'E') || parse_exponent(s, len, frac_end + 1, &e))
            return -1;
    }
    while (nd > 0 && d->digits[nd - 1] == '0') {
        nd--;
        exp10++;
    }
    d->digits[nd] = '\0';
    exp10 += e;
    if (exp10 > 1000000 || exp10 < -1000000)
        return -1;
    d->exp10 = nd ? (int32_t)exp10 : 0;
    if (!nd)
        d->neg = 0;
    char tmp[96];
    snprintf(tmp, sizeof tmp, "%s%se%d", d->neg ? "-" : "", nd ? d->digits : "0", (int)d->exp10);
    d->value = strtod(tmp, NULL);
    return 0;
}

int decimal_list_parse(const char *text, decimal *out, int n)
{
    const char *p = text;
    for (int k = 0; k < n; k++) {
        const char *end = strchr(p, ',');
        if ((k < n - 1) != (end != NULL))
            return -1;
        size_t len = end ? (size_t)(end - p) : strlen(p);
        if (decimal_parse(p, len, &out[k]))
            return -1;
        p = end ? end + 1 : p + len;
    }
    return 0;
}

int decimal_floor_lattice(const decimal *d, int32_t unit_exp10, int64_t *out)
{
    long k = (long)d->exp10 - unit_exp10;
    long nd = (long)strlen(d->digits);
    long int_digits = nd + k; /* digits before the point after scaling */
    uint64_t mag = 0;
    bool frac = false;
    if (int_digits > 19)
        return -1;
    for (long i = 0; i < int_digits; i++) {
        uint64_t digit = i < nd ? (uint64_t)(d->digits[i] - '0') : 0;
        if (mag > (UINT64_MAX - digit) / 10)
            return -1;
        mag = mag * 10 + digit;
    }
    frac = nd > (int_digits > 0 ? int_digits : 0); /* trailing digits are non-zero */
    if (d->neg && frac)
        mag++;
    if (mag > (uint64_t)INT64_MAX)
        return -1;
    *out = d->neg ? -(int64_t)mag : (int64_t)mag;
    return 0;
}

int decimal_fraction_digits(const decimal *d)
{
    return d->exp10 >= 0 ? 0 : d->exp10 < -17 ? 17 : -d->exp10;
}

void view_decimal_text(int64_t v, int32_t e, char *buf, size_t cap)
{
    uint64_t mag = v < 0 ? (uint64_t)0 - (uint64_t)v : (uint64_t)v;
    char digits[32];
    int n = snprintf(digits, sizeof digits, "%llu", (unsigned long long)mag);
    const char *sign = v < 0 ? "-" : "";
    if (e >= 0 || mag == 0) {
        snprintf(buf, cap, "%s%s%.*s", sign, digits, mag ? (int)(e > 40 ? 40 : e) : 0,
                 "0000000000000000000000000000000000000000");
        return;
    }
    int frac = -e;
    if (n <= frac)
        snprintf(buf, cap, "%s0.%.*s%s", sign, frac - n, "000000000000000000000000000000000000000",
                 digits);
    else
        snprintf(buf, cap, "%s%.*s.%s", sign, n - frac, digits, digits + n - frac);
}

/* A lattice coordinate as a JSON number in user units: exact while the
 * value has at most 15-17 significant digits (jsonw writes doubles). */
static void json_user(jsonw *w, const char *key, int64_t v, int32_t e)
{
    char text[80];
    view_decimal_text(v, e, text, sizeof text);
    jsonw_double(w, key, strtod(text, NULL), e < 0 ? (-e > 17 ? 17 : -e) : 0);
}

/* ---- pixel paths ------------------------------------------------------------- */

static int parse_u32(const char **p, uint32_t *out)
{
    const char *s = *p;
    uint64_t v = 0;
    if (!isdigit((unsigned char)*s))
        return -1;
    for (; isdigit((unsigned char)*s); s++) {
        v = v * 10 + (uint64_t)(*s - '0');
        if (v > UINT32_MAX)
            return -1;
    }
    *out = (uint32_t)v;
    *p = s;
    return 0;
}

int pixel_path_parse(const char *text, pixel_path *out, char *why, size_t cap)
{
    const char *p = text;
    memset(out, 0, sizeof *out);
    for (;;) {
        if (out->levels == HPFC_MAX_LEVELS) {
            snprintf(why, cap, "more than %d levels", HPFC_MAX_LEVELS);
            return -1;
        }
        uint32_t *ij = out->ij[out->levels];
        if (parse_u32(&p, &ij[0]) || *p++ != ',' || parse_u32(&p, &ij[1])) {
            snprintf(why, cap, "expected i,j per level joined by '/', e.g. 3,5/1,0");
            return -1;
        }
        out->levels++;
        if (*p == '\0')
            return 0;
        if (*p++ != '/') {
            snprintf(why, cap, "expected i,j per level joined by '/', e.g. 3,5/1,0");
            return -1;
        }
    }
}

/* The pixel a path names, or VIEW_FAIL with the reason. */
static int resolve_path(const hpfc_file *f, const pixel_path *pp, hpfc_pixel *px, char *why)
{
    hpfc_file_info info;
    hpfc_file_get_info(f, &info);
    for (uint32_t l = 0; l < pp->levels; l++) {
        uint32_t i = pp->ij[l][0], j = pp->ij[l][1];
        uint32_t n = l ? info.cols : info.root_cols, m = l ? info.rows : info.root_rows;
        if (i >= n || j >= m)
            return view_fail(why, "no pixel %u,%u at depth %u: images there are %ux%u", i, j, l, n,
                             m);
        int type, st;
        if (l > 0) {
            if ((st = hpfc_pixel_type(f, px, &type)))
                return fail_status(why, "pixel type", st);
            if (type != HPFC_PIXEL_REFINED)
                return view_fail(
                    why, "the pixel at depth %u is a word pixel: the path goes no deeper", l - 1);
        }
        st = l ? hpfc_pixel_child(f, px, i, j, px) : hpfc_pixel_root(f, i, j, px);
        if (st)
            return fail_status(why, "pixel", st);
    }
    return VIEW_OK;
}

/* ---- CRC-32C ------------------------------------------------------------------- */

uint32_t view_crc32c(uint32_t crc, const void *data, size_t len)
{
    static uint32_t table[256];
    static int ready;
    if (!ready) {
        for (uint32_t n = 0; n < 256; n++) {
            uint32_t c = n;
            for (int k = 0; k < 8; k++)
                c = c & 1 ? (c >> 1) ^ 0x82F63B78u : c >> 1;
            table[n] = c;
        }
        ready = 1;
    }
    const unsigned char *p = data;
    crc = ~crc;
    for (size_t k = 0; k < len; k++)
        crc = table[(crc ^ p[k]) & 0xFF] ^ (crc >> 8);
    return ~crc;
}

/* CRC-32C of `length` bytes of the stream from `offset`, continuing crc. */
static int crc_range(FILE *in, uint64_t offset, uint64_t length, uint32_t *crc)
{
    unsigned char buf[65536];
    if (fseeko(in, (off_t)offset, SEEK_SET))
        return -1;
    while (length > 0) {
        size_t want = length < sizeof buf ? (size_t)length : sizeof buf;
        if (fread(buf, 1, want, in) != want)
            return -1;
        *crc = view_crc32c(*crc, buf, want);
        length -= want;
    }
    return 0;
}

/* ---- --sections ------------------------------------------------------------------ */

static uint32_t le32(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static uint64_t le64(const unsigned char *p)
{
    return (uint64_t)le32(p) | (uint64_t)le32(p + 4) << 32;
}

typedef struct section_row {
    hpfc_section_info info;
    uint32_t computed;
    int ok;
} section_row;

typedef struct file_map {
    hpfc_file_info info;
    hpfc_level_info levels[HPFC_MAX_LEVELS];
    section_row *sections;
    uint32_t header_size, meta_crc, meta_computed;
    uint64_t meta_size;
    int api_status;   /* hpfc_file_check_checksums */
    uint32_t bad;     /* checksums that do not match */
} file_map;

/* The metadata CRC takes bytes 124..127 (the CRC itself) as zero (§4.5). */
static int meta_checksum(FILE *in, file_map *m)
{
    static const unsigned char zero[4];
    uint32_t crc = 0;
    if (crc_range(in, 0, 124, &crc))
        return -1;
    crc = view_crc32c(crc, zero, 4);
    if (crc_range(in, 128, m->meta_size - 128, &crc))
        return -1;
    m->meta_computed = crc;
    return 0;
}

static int read_map(const hpfc_file *f, const char *path, file_map *m, char *why)
{
    hpfc_file_get_info(f, &m->info);
    for (uint32_t l = 0; l < m->info.levels && l < HPFC_MAX_LEVELS; l++)
        if (hpfc_file_get_level(f, l, &m->levels[l]))
            return view_fail(why, "level %u: cannot be read", l);
    m->sections = calloc(m->info.section_count + 1, sizeof *m->sections);
    if (!m->sections)
        return fail_status(why, "sections", HPFC_E_NOMEM);
    FILE *in = fopen(path, "rb");
    if (!in)
        return view_fail(why, "cannot reread the file: %s", strerror(errno));
    unsigned char hdr[128];
    int bad_io = fread(hdr, 1, sizeof hdr, in) != sizeof hdr;
    if (!bad_io) {
        m->header_size = le32(hdr + 12);
        m->meta_size = le64(hdr + 96);
        m->meta_crc = le32(hdr + 124);
        bad_io = meta_checksum(in, m);
    }
    for (uint32_t k = 0; k < m->info.section_count && !bad_io; k++) {
        section_row *s = &m->sections[k];
        if (hpfc_file_get_section(f, k, &s->info))
            bad_io = 1;
        s->computed = 0;
        bad_io = bad_io || crc_range(in, s->info.offset, s->info.length, &s->computed);
        s->ok = s->computed == s->info.crc32c;
        m->bad += !s->ok;
    }
    fclose(in);
    if (bad_io)
        return view_fail(why, "cannot reread the file (changed since it was opened?)");
    m->bad += m->meta_computed != m->meta_crc;
    m->api_status = hpfc_file_check_checksums(f, NULL);
    return VIEW_OK;
}

static uint64_t pool_bytes(const hpfc_level_info *lv)
{
    return (lv->pool_bits + 7) / 8;
}

static void printable_tag(const char *tag, char out[5])
{
    for (int k = 0; k < 4; k++)
        out[k] = tag[k] >= 0x20 && tag[k] < 0x7F ? tag[k] : '?';
    out[4] = '\0';
}

static void row(FILE *out, uint64_t off, uint64_t len, const char *indent)
{
    fprintf(out, "%12llu %12llu  %s", (unsigned long long)off, (unsigned long long)len, indent);
}

static int is_pool(const hpfc_section_info *s)
{
    return memcmp(s->tag, "POOL", 4) == 0;
}

/* The pools inside the POOL section, with the padding between them. */
static void print_pools(FILE *out, const file_map *m, const hpfc_section_info *s)
{
    uint64_t at = s->offset;
    for (uint32_t l = 0; l < m->info.levels; l++) {
        const hpfc_level_info *lv = &m->levels[l];
        if (lv->pool_offset > at) {
            row(out, at, lv->pool_offset - at, "  ");
            fprintf(out, "zero padding\n");
        }
        row(out, lv->pool_offset, pool_bytes(lv), "  ");
        fprintf(out, "pool of level %u: %llu bits; %llu images, %llu word + %llu refined pixels, "
                     "k_w %u, k_@ %u\n",
                l, (unsigned long long)lv->pool_bits, (unsigned long long)lv->images,
                (unsigned long long)lv->word_pixels, (unsigned long long)lv->refined_pixels,
                lv->word_bits, lv->address_bits);
        at = lv->pool_offset + pool_bytes(lv);
    }
}

static int cmp_section_offset(const void *a, const void *b)
{
    const section_row *x = a, *y = b;
    return x->info.offset < y->info.offset ? -1 : x->info.offset > y->info.offset;
}

static void print_map_text(FILE *out, const char *path, const file_map *m)
{
    const hpfc_file_info *fi = &m->info;
    fprintf(out, "file        %s, %llu bytes, hpfc %u.%u\n", path,
            (unsigned long long)fi->file_size, fi->format_major, fi->format_minor);
    fprintf(out, "checksums   %s (%u section%s and the metadata block)\n\n",
            m->bad ? "MISMATCH" : "all verify", fi->section_count,
            fi->section_count == 1 ? "" : "s");
    fprintf(out, "%12s %12s  %s\n", "offset", "length", "region");
    row(out, 0, m->header_size, "");
    fprintf(out, "header: format %u.%u, header_size %u, compat 0x%x, incompat 0x%x, "
                 "%u level(s), %u section(s)\n",
            fi->format_major, fi->format_minor, m->header_size, fi->compat_flags,
            fi->incompat_flags, fi->levels, fi->section_count);
    row(out, m->header_size, 64ull * fi->levels, "");
    fprintf(out, "level table: %u entr%s of 64 bytes\n", fi->levels, fi->levels == 1 ? "y" : "ies");
    row(out, m->header_size + 64ull * fi->levels, 32ull * fi->section_count, "");
    fprintf(out, "section directory: %u entr%s of 32 bytes\n", fi->section_count,
            fi->section_count == 1 ? "y" : "ies");
    row(out, 0, m->meta_size, "");
    fprintf(out, "metadata block (the three above): meta_crc32c 0x%08x, computed 0x%08x: %s\n",
            m->meta_crc, m->meta_computed,
            m->meta_crc == m->meta_computed ? "ok" : "MISMATCH");
    section_row *sorted = malloc((fi->section_count + 1) * sizeof *sorted);
    if (!sorted)
        return;
    memcpy(sorted, m->sections, fi->section_count * sizeof *sorted);
    qsort(sorted, fi->section_count, sizeof *sorted, cmp_section_offset);
    uint64_t at = m->meta_size;
    for (uint32_t k = 0; k < fi->section_count; k++) {
        const section_row *s = &sorted[k];
        char tag[5];
        printable_tag(s->info.tag, tag);
        if (s->info.offset > at) {
            row(out, at, s->info.offset - at, "");
            fprintf(out, "zero padding\n");
        }
        row(out, s->info.offset, s->info.length, "");
        fprintf(out, "section \"%s\"%s: crc32c 0x%08x, computed 0x%08x: %s\n", tag,
                s->info.flags & 1 ? " REQUIRED" : "", s->info.crc32c, s->computed,
                s->ok ? "ok" : "MISMATCH");
        if (is_pool(&s->info))
            print_pools(out, m, &s->info);
        if (s->info.offset + s->info.length > at)
            at = s->info.offset + s->info.length;
    }
    free(sorted);
    if (fi->file_size > at) {
        row(out, at, fi->file_size - at, "");
        fprintf(out, "trailing bytes\n");
    }
    fprintf(out, "\nhpfc_verify_checksums: %s\n", hpfc_strerror(m->api_status));
}

static void print_map_json(FILE *out, const char *path, const file_map *m)
{
    const hpfc_file_info *fi = &m->info;
    jsonw w;
    jsonw_init(&w, out);
    jsonw_object_begin(&w, NULL);
    jsonw_string(&w, "file", path);
    jsonw_u64(&w, "file_bytes", fi->file_size);
    jsonw_bool(&w, "checksums_ok", m->bad == 0);
    jsonw_string(&w, "verify_checksums", hpfc_strerror(m->api_status));
    jsonw_object_begin(&w, "header");
    jsonw_u64(&w, "offset", 0);
    jsonw_u64(&w, "length", m->header_size);
    jsonw_u64(&w, "format_major", fi->format_major);
    jsonw_u64(&w, "format_minor", fi->format_minor);
    jsonw_u64(&w, "compat_flags", fi->compat_flags);
    jsonw_u64(&w, "incompat_flags", fi->incompat_flags);
    jsonw_u64(&w, "meta_size", m->meta_size);
    jsonw_u64(&w, "meta_crc32c", m->meta_crc);
    jsonw_u64(&w, "meta_crc32c_computed", m->meta_computed);
    jsonw_bool(&w, "meta_ok", m->meta_crc == m->meta_computed);
    jsonw_object_end(&w);
    jsonw_object_begin(&w, "level_table");
    jsonw_u64(&w, "offset", m->header_size);
    jsonw_u64(&w, "length", 64ull * fi->levels);
    jsonw_object_end(&w);
    jsonw_object_begin(&w, "directory");
    jsonw_u64(&w, "offset", m->header_size + 64ull * fi->levels);
    jsonw_u64(&w, "length", 32ull * fi->section_count);
    jsonw_object_end(&w);
    jsonw_array_begin(&w, "levels");
    for (uint32_t l = 0; l < fi->levels; l++) {
        const hpfc_level_info *lv = &m->levels[l];
        jsonw_object_begin(&w, NULL);
        jsonw_u64(&w, "level", l);
        jsonw_u64(&w, "entry_offset", m->header_size + 64ull * l);
        jsonw_u64(&w, "images", lv->images);
        jsonw_u64(&w, "word_pixels", lv->word_pixels);
        jsonw_u64(&w, "refined_pixels", lv->refined_pixels);
        jsonw_u64(&w, "word_bits", lv->word_bits);
        jsonw_u64(&w, "address_bits", lv->address_bits);
        jsonw_u64(&w, "pool_offset", lv->pool_offset);
        jsonw_u64(&w, "pool_bits", lv->pool_bits);
        jsonw_u64(&w, "pool_bytes", pool_bytes(lv));
        jsonw_object_end(&w);
    }
    jsonw_array_end(&w);
    jsonw_array_begin(&w, "sections");
    for (uint32_t k = 0; k < fi->section_count; k++) {
        const section_row *s = &m->sections[k];
        jsonw_object_begin(&w, NULL);
        jsonw_string_n(&w, "tag", s->info.tag, strnlen(s->info.tag, 4));
        jsonw_u64(&w, "flags", s->info.flags);
        jsonw_u64(&w, "offset", s->info.offset);
        jsonw_u64(&w, "length", s->info.length);
        jsonw_u64(&w, "crc32c", s->info.crc32c);
        jsonw_u64(&w, "crc32c_computed", s->computed);
        jsonw_bool(&w, "ok", s->ok);
        jsonw_object_end(&w);
    }
    jsonw_array_end(&w);
    jsonw_object_end(&w);
    jsonw_finish(&w);
}

int view_sections(const hpfc_file *f, const char *path, FILE *out, int json, char *why)
{
    file_map m;
    memset(&m, 0, sizeof m);
    int status = read_map(f, path, &m, why);
    if (status == VIEW_OK) {
        if (json)
            print_map_json(out, path, &m);
        else
            print_map_text(out, path, &m);
        if (m.bad)
            status = view_fail(why, "%u checksum%s do%s not match", m.bad, m.bad == 1 ? "" : "s",
                               m.bad == 1 ? "es" : "");
    }
    free(m.sections);
    return status;
}

/* ---- faces of a pixel --------------------------------------------------------- */

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

int view_pixel_faces(const hpfc_file *f, const hpfc_faces *fc, const hpfc_pixel *px,
                     uint64_t *faces, size_t cap, size_t *count)
{
    int is_private;
    int st = hpfc_pixel_is_private(f, px, &is_private);
    *count = 0;
    if (st)
        return st;
    if (is_private) {
        if (cap < 1)
            return HPFC_E_ARG;
        *count = 1;
        return hpfc_faces_pixel_face(fc, px, &faces[0]);
    }
    size_t len;
    if ((st = hpfc_pixel_word(f, px, NULL, 0, &len)))
        return st;
    uint32_t n = (uint32_t)(len - 4); /* a word of c crossings has c + 4 symbols */
    if (len < 4 || cap < n)
        return HPFC_E_ARG;
    for (uint32_t k = 0; k < n; k++) {
        hpfc_dart d = {.pixel = *px, .crossing = k};
        if ((st = hpfc_faces_dart_face(fc, &d, &faces[k])))
            return st;
    }
    qsort(faces, n, sizeof *faces, cmp_u64);
    size_t u = 0;
    for (uint32_t k = 0; k < n; k++)
        if (u == 0 || faces[u - 1] != faces[k])
            faces[u++] = faces[k];
    *count = u;
    return HPFC_OK;
}

/* ---- --pixel ------------------------------------------------------------------- */

#define PATH_TEXT 1200

typedef struct pixel_view {
    hpfc_pixel px;
    char path[PATH_TEXT];
    int type, is_private;
    lbox b;
    int32_t e;                  /* unit_exp10 */
    hpfc_level_info level;
    char *word;                 /* word pixels: the symbols, NUL-ended */
    size_t len;
    word_info wi;
    uint32_t counts[4];
    uint32_t nvert;
    uint32_t *degree;
    uint64_t *vkey;
    int has_nb[4];
    char nb[4][PATH_TEXT];
    uint64_t child_image;       /* refined pixels: bit offset of the child image */
    int labels;                 /* the file's LABL section gave the next three */
    uint64_t leaf_number;
    uint64_t *stretch_face;     /* per stretch (one for a private leaf) */
    uint64_t *edge;             /* per crossing */
    int compact;                /* compact pool layout (spec §5.3): images are indices,
                                   words have no slot */
} pixel_view;

static void pixel_view_free(pixel_view *v)
{
    free(v->word);
    free(v->degree);
    free(v->vkey);
    free(v->stretch_face);
    free(v->edge);
    word_info_free(&v->wi);
}

static int read_neighbours(const hpfc_file *f, pixel_view *v, char *why)
{
    for (int dir = 0; dir < 4; dir++) {
        hpfc_pixel nb;
        int st = hpfc_pixel_move(f, &v->px, dir, &nb);
        if (st == HPFC_E_NO_PIXEL)
            continue;
        if (st)
            return fail_status(why, "neighbour", st);
        v->has_nb[dir] = 1;
        pixel_path_text(&nb, v->nb[dir], sizeof v->nb[dir]);
    }
    return VIEW_OK;
}

/* The vertices as the traversal API sees them, with their degrees. */
static int read_vertices(const hpfc_file *f, pixel_view *v, char *why)
{
    hpfc_walker *w;
    int st = hpfc_walker_create(f, &w);
    if (!st)
        st = hpfc_pixel_vertex_count(w, &v->px, &v->nvert);
    if (!st) {
        v->degree = calloc(v->nvert + 1, sizeof *v->degree);
        v->vkey = calloc(v->nvert + 1, sizeof *v->vkey);
        if (!v->degree || !v->vkey)
            st = HPFC_E_NOMEM;
    }
    for (uint32_t k = 0; k < v->nvert && !st; k++) {
        st = hpfc_pixel_vertex_key(w, &v->px, k, &v->vkey[k]);
        if (!st)
            st = hpfc_key_degree(w, v->vkey[k], &v->degree[k]);
    }
    hpfc_walker_free(w);
    return st ? fail_status(why, "vertices", st) : VIEW_OK;
}

/* The leaf's stored labels (LABL, spec §6.5), when the file has them. */
static int read_labels(const hpfc_file *f, pixel_view *v, char *why)
{
    hpfc_labels_info li;
    if (hpfc_file_get_labels(f, &li) != HPFC_OK)
        return VIEW_OK;
    uint32_t n = v->wi.n, stretches = n ? n : 1;
    v->stretch_face = calloc(stretches, sizeof *v->stretch_face);
    v->edge = calloc(n + 1, sizeof *v->edge);
    int st = v->stretch_face && v->edge ? HPFC_OK : HPFC_E_NOMEM;
    if (!st)
        st = hpfc_leaf_number(f, &v->px, &v->leaf_number);
    for (uint32_t t = 0; t < stretches && !st; t++)
        st = hpfc_label_stretch_face(f, &v->px, t, &v->stretch_face[t]);
    for (uint32_t k = 0; k < n && !st; k++)
        st = hpfc_label_crossing_edge(f, &v->px, k, &v->edge[k]);
    if (st)
        return fail_status(why, "labels", st);
    v->labels = 1;
    return VIEW_OK;
}

static int read_word(const hpfc_file *f, pixel_view *v, char *why)
{
    int st = hpfc_pixel_word(f, &v->px, NULL, 0, &v->len);
    if (!st && !(v->word = malloc(v->len + 1)))
        st = HPFC_E_NOMEM;
    if (!st)
        st = hpfc_pixel_word(f, &v->px, v->word, v->len + 1, &v->len);
    if (st)
        return fail_status(why, "word", st);
    v->word[v->len] = '\0';
    int p = word_parse(&v->wi, v->word, v->len);
    if (p)
        return fail_status(why, "word", p == -2 ? HPFC_E_NOMEM : HPFC_E_CORRUPT);
    word_road_counts(v->word, v->len, v->counts);
    if (read_labels(f, v, why))
        return VIEW_FAIL;
    return read_vertices(f, v, why);
}

static int read_pixel_view(const hpfc_file *f, pixel_view *v, char *why)
{
    hpfc_file_info info;
    hpfc_file_get_info(f, &info);
    v->e = info.unit_exp10;
    v->compact = info.incompat_flags & 0x1;
    pixel_path_text(&v->px, v->path, sizeof v->path);
    int st = hpfc_pixel_type(f, &v->px, &v->type);
    if (!st)
        st = hpfc_pixel_is_private(f, &v->px, &v->is_private);
    if (!st)
        st = roads_box(f, &v->px, &v->b);
    if (!st)
        st = hpfc_file_get_level(f, v->px.depth, &v->level);
    if (st)
        return fail_status(why, "pixel", st);
    if (v->type == HPFC_PIXEL_REFINED) {
        hpfc_pixel child;
        if ((st = hpfc_pixel_child(f, &v->px, 0, 0, &child)))
            return fail_status(why, "child image", st);
        v->child_image = child.path[child.depth].image;
    } else if (read_word(f, v, why)) {
        return VIEW_FAIL;
    }
    return read_neighbours(f, v, why);
}

static const char *pixel_kind(const pixel_view *v)
{
    return v->type == HPFC_PIXEL_REFINED ? "refined" : v->is_private ? "private" : "word";
}

static void print_code(FILE *out, const char *word, size_t len)
{
    for (size_t k = 0; k < len; k++)
        fprintf(out, "%s%s", k ? " " : "", word_symbol_code(word[k]));
}

static void print_components_text(FILE *out, const pixel_view *v)
{
    const word_info *wi = &v->wi;
    for (uint32_t c = 0; c < wi->ncomp; c++) {
        fprintf(out, "%s", c ? "            " : "components  ");
        if (wi->comp_vertex[c] == WORD_NONE)
            fprintf(out, "stabbing:");
        else
            fprintf(out, "junction of vertex %u, degree %u:", wi->comp_vertex[c], wi->comp_size[c]);
        for (uint32_t k = wi->comp_first[c]; k <= wi->comp_last[c]; k++)
            if (wi->comp[k] == c)
                fprintf(out, " %u%c(%s)", k, wi->sym[k], road_names[word_road_of(wi, k)]);
        fprintf(out, "\n");
    }
    if (wi->ncomp == 0)
        fprintf(out, "components  none\n");
}

static void print_pixel_text(FILE *out, const pixel_view *v)
{
    char x0[64], y0[64], x1[64], y1[64];
    view_decimal_text(v->b.x0, v->e, x0, sizeof x0);
    view_decimal_text(v->b.y0, v->e, y0, sizeof y0);
    view_decimal_text(v->b.x1, v->e, x1, sizeof x1);
    view_decimal_text(v->b.y1, v->e, y1, sizeof y1);
    fprintf(out, v->compact ? "pixel       %s (depth %u, image %llu of level %u)\n"
                            : "pixel       %s (depth %u, image at bit %llu of level %u's pool)\n",
            v->path, v->px.depth, (unsigned long long)v->px.path[v->px.depth].image, v->px.depth);
    fprintf(out, "type        %s\n", pixel_kind(v));
    fprintf(out, "bounds      [%s, %s) x [%s, %s)\n", x0, x1, y0, y1);
    if (v->type == HPFC_PIXEL_REFINED) {
        fprintf(out, v->compact ? "child       image %llu of level %u\n"
                                : "child       image at bit %llu of level %u's pool\n",
                (unsigned long long)v->child_image, v->px.depth + 1);
    } else {
        fprintf(out, "word        %s (%zu symbols, %u crossings)\n", v->word, v->len, v->wi.n);
        if (v->compact) {
            fprintf(out, "code        compact layout: context-coded in the level's word stream\n");
        } else {
            fprintf(out, "code        ");
            print_code(out, v->word, v->len);
            fprintf(out, " (%u of %u slot bits)\n", 4 + 4 * v->wi.n, v->level.word_bits);
        }
        fprintf(out, "crossings   W %u, N %u, E %u, S %u\n", v->counts[0], v->counts[1],
                v->counts[2], v->counts[3]);
        print_components_text(out, v);
        fprintf(out, "vertices    ");
        for (uint32_t k = 0; k < v->nvert; k++)
            fprintf(out, "%s%u: degree %u (key %llu)", k ? "; " : "", k, v->degree[k],
                    (unsigned long long)v->vkey[k]);
        fprintf(out, "%s\n", v->nvert ? "" : "none");
    }
    if (v->labels) {
        fprintf(out, "labels      leaf %llu; stretch faces", (unsigned long long)v->leaf_number);
        for (uint32_t t = 0; t < (v->wi.n ? v->wi.n : 1); t++)
            fprintf(out, " %llu", (unsigned long long)v->stretch_face[t]);
        fprintf(out, "; crossing edges%s", v->wi.n ? "" : " none");
        for (uint32_t k = 0; k < v->wi.n; k++)
            fprintf(out, " %llu", (unsigned long long)v->edge[k]);
        fputc('\n', out);
    }
    fprintf(out, "neighbours ");
    for (int dir = 0; dir < 4; dir++)
        fprintf(out, " %s %s%s", road_names[dir], v->has_nb[dir] ? v->nb[dir] : "none",
                dir < 3 ? "," : "\n");
}

static void json_bounds(jsonw *w, const lbox *b, int32_t e)
{
    jsonw_array_begin(w, "bounds");
    json_user(w, NULL, b->x0, e);
    json_user(w, NULL, b->y0, e);
    json_user(w, NULL, b->x1, e);
    json_user(w, NULL, b->y1, e);
    jsonw_array_end(w);
}

static void json_components(jsonw *w, const word_info *wi)
{
    jsonw_array_begin(w, "components");
    for (uint32_t c = 0; c < wi->ncomp; c++) {
        jsonw_object_begin(w, NULL);
        int junction = wi->comp_vertex[c] != WORD_NONE;
        jsonw_string(w, "kind", junction ? "junction" : "stabbing");
        if (junction)
            jsonw_u64(w, "vertex", wi->comp_vertex[c]);
        jsonw_array_begin(w, "crossings");
        for (uint32_t k = wi->comp_first[c]; k <= wi->comp_last[c]; k++)
            if (wi->comp[k] == c) {
                jsonw_object_begin(w, NULL);
                jsonw_u64(w, "index", k);
                jsonw_string_n(w, "symbol", &wi->sym[k], 1);
                jsonw_string(w, "road", road_names[word_road_of(wi, k)]);
                jsonw_object_end(w);
            }
        jsonw_array_end(w);
        jsonw_object_end(w);
    }
    jsonw_array_end(w);
}

static void json_word(jsonw *w, const pixel_view *v)
{
    jsonw_string(w, "word", v->word);
    jsonw_u64(w, "symbols", v->len);
    if (v->compact) { /* no slot, no fixed code: spec §5.3 */
        jsonw_string(w, "layout", "compact");
    } else {
        jsonw_u64(w, "code_bits", 4 + 4ull * v->wi.n);
        jsonw_u64(w, "slot_bits", v->level.word_bits);
        jsonw_array_begin(w, "code");
        for (size_t k = 0; k < v->len; k++)
            jsonw_string(w, NULL, word_symbol_code(v->word[k]));
        jsonw_array_end(w);
    }
    jsonw_object_begin(w, "crossings");
    for (int r = 0; r < 4; r++)
        jsonw_u64(w, road_names[r], v->counts[r]);
    jsonw_object_end(w);
    json_components(w, &v->wi);
    jsonw_array_begin(w, "vertices");
    for (uint32_t k = 0; k < v->nvert; k++) {
        jsonw_object_begin(w, NULL);
        jsonw_u64(w, "local", k);
        jsonw_u64(w, "degree", v->degree[k]);
        jsonw_u64(w, "key", v->vkey[k]);
        jsonw_object_end(w);
    }
    jsonw_array_end(w);
    if (!v->labels)
        return;
    jsonw_object_begin(w, "labels");
    jsonw_u64(w, "leaf_number", v->leaf_number);
    jsonw_array_begin(w, "stretch_faces");
    for (uint32_t t = 0; t < (v->wi.n ? v->wi.n : 1); t++)
        jsonw_u64(w, NULL, v->stretch_face[t]);
    jsonw_array_end(w);
    jsonw_array_begin(w, "edges");
    for (uint32_t k = 0; k < v->wi.n; k++)
        jsonw_u64(w, NULL, v->edge[k]);
    jsonw_array_end(w);
    jsonw_object_end(w);
}

static void print_pixel_json(FILE *out, const pixel_view *v)
{
    jsonw w;
    jsonw_init(&w, out);
    jsonw_object_begin(&w, NULL);
    jsonw_string(&w, "pixel", v->path);
    jsonw_u64(&w, "depth", v->px.depth);
    jsonw_u64(&w, "image", v->px.path[v->px.depth].image);
    jsonw_string(&w, "type", pixel_kind(v));
    jsonw_bool(&w, "private", v->is_private);
    json_bounds(&w, &v->b, v->e);
    if (v->type == HPFC_PIXEL_REFINED)
        jsonw_u64(&w, "child_image", v->child_image);
    else
        json_word(&w, v);
    jsonw_object_begin(&w, "neighbours");
    for (int dir = 0; dir < 4; dir++) {
        if (v->has_nb[dir])
            jsonw_string(&w, road_names[dir], v->nb[dir]);
        else
            jsonw_null(&w, road_names[dir]);
    }
    jsonw_object_end(&w);
    jsonw_object_end(&w);
    jsonw_finish(&w);
}

int view_pixel(const hpfc_file *f, const pixel_path *pp, FILE *out, int json, char *why)
{
    pixel_view *v = calloc(1, sizeof *v);
    if (!v)
        return fail_status(why, "pixel", HPFC_E_NOMEM);
    int status = resolve_path(f, pp, &v->px, why);
    if (!status)
        status = read_pixel_view(f, v, why);
    if (!status && json)
        print_pixel_json(out, v);
    else if (!status)
        print_pixel_text(out, v);
    pixel_view_free(v);
    free(v);
    return status;
}

/* ---- --stats ------------------------------------------------------------------- */

/* Counts per value 0, 1, 2, ... */
typedef struct histogram {
    const char *name, *unit;
    uint64_t *count;
    size_t cap;
    uint64_t n, sum, max;
} histogram;

static int hist_add(histogram *h, uint64_t value)
{
    if (value >= h->cap) {
        size_t cap = h->cap ? h->cap : 16;
        while (cap <= value)
            cap *= 2;
        uint64_t *c = realloc(h->count, cap * sizeof *c);
        if (!c)
            return HPFC_E_NOMEM;
        memset(c + h->cap, 0, (cap - h->cap) * sizeof *c);
        h->count = c;
        h->cap = cap;
    }
    h->count[value]++;
    h->n++;
    h->sum += value;
    if (value > h->max)
        h->max = value;
    return HPFC_OK;
}

enum { H_WORD_LENGTH, H_DEPTH, H_CROSSINGS, H_STABBINGS, H_COUNT };

typedef struct stats {
    histogram h[H_COUNT];
    uint64_t leaves, private_leaves, vertices, edges, stabbings, faces;
    int faces_status;
} stats;

/* Every dart leaving a vertex of the leaf: walk it to its target, counting
 * the stabbings on the way; each edge is counted once, from the dart whose
 * key is the smaller of the two. */
static int leaf_edges(roads *r, const hpfc_pixel *px, const word_info *wi, stats *s)
{
    for (uint32_t k = 0; k < wi->n; k++) {
        if (wi->comp_vertex[wi->comp[k]] == WORD_NONE)
            continue;
        hpfc_dart d = {.pixel = *px, .crossing = k}, twin;
        uint64_t stabbings;
        int st = roads_walk(r, &d, &stabbings, &twin);
        if (st)
            return st;
        if (hpfc_dart_key(r->file, &d) < hpfc_dart_key(r->file, &twin)) {
            s->edges++;
            s->stabbings += stabbings;
            if ((st = hist_add(&s->h[H_STABBINGS], stabbings)))
                return st;
        }
    }
    return HPFC_OK;
}

static int collect_stats(const hpfc_file *f, stats *s)
{
    roads r;
    word_info wi;
    memset(&wi, 0, sizeof wi);
    hpfc_pixel px;
    int st = roads_init(&r, f);
    for (st = st ? st : hpfc_leaf_first(f, &px); !st; st = hpfc_leaf_next(f, &px)) {
        if ((st = roads_parse(&r, &px, &wi)))
            break;
        s->leaves++;
        s->private_leaves += wi.n == 0;
        s->vertices += wi.nvert;
        if ((st = hist_add(&s->h[H_WORD_LENGTH], wi.n + 4)) ||
            (st = hist_add(&s->h[H_DEPTH], px.depth)) ||
            (st = hist_add(&s->h[H_CROSSINGS], wi.n)) || (st = leaf_edges(&r, &px, &wi, s)))
            break;
    }
    roads_free(&r);
    word_info_free(&wi);
    if (st != HPFC_E_NO_PIXEL)
        return st;
    hpfc_faces *fc;
    s->faces_status = hpfc_faces_build(f, &fc);
    if (!s->faces_status)
        s->faces = hpfc_faces_face_count(fc);
    hpfc_faces_free(fc);
    return HPFC_OK;
}

static void print_hist_text(FILE *out, const histogram *h)
{
    fprintf(out, "\n%s (%llu %s", h->name, (unsigned long long)h->n, h->unit);
    if (h->n)
        fprintf(out, ", mean %.3f, max %llu", (double)h->sum / (double)h->n,
                (unsigned long long)h->max);
    fprintf(out, ")\n");
    uint64_t top = 0;
    for (size_t v = 0; v < h->cap; v++)
        if (h->count[v] > top)
            top = h->count[v];
    for (size_t v = 0; v < h->cap; v++) {
        if (!h->count[v])
            continue;
        int bar = (int)((h->count[v] * 50 + top - 1) / (top ? top : 1));
        fprintf(out, "%8zu %12llu  %.*s\n", v, (unsigned long long)h->count[v], bar,
                "##################################################");
    }
}

static void print_stats_text(FILE *out, const stats *s)
{
    fprintf(out, "leaves      %llu (%llu private, %llu stabbed)\n",
            (unsigned long long)s->leaves, (unsigned long long)s->private_leaves,
            (unsigned long long)(s->leaves - s->private_leaves));
    fprintf(out, "graph       %llu vertices, %llu edges, ", (unsigned long long)s->vertices,
            (unsigned long long)s->edges);
    if (s->faces_status)
        fprintf(out, "faces: %s\n", hpfc_strerror(s->faces_status));
    else
        fprintf(out, "%llu faces\n", (unsigned long long)s->faces);
    fprintf(out, "stabbings   %llu along all edges\n", (unsigned long long)s->stabbings);
    for (int k = 0; k < H_COUNT; k++)
        print_hist_text(out, &s->h[k]);
}

static void print_hist_json(jsonw *w, const histogram *h, const char *key)
{
    jsonw_object_begin(w, key);
    jsonw_u64(w, "count", h->n);
    jsonw_u64(w, "sum", h->sum);
    jsonw_u64(w, "max", h->max);
    jsonw_double(w, "mean", h->n ? (double)h->sum / (double)h->n : 0.0, 4);
    jsonw_array_begin(w, "bins"); /* [value, count] for every value that occurs */
    for (size_t v = 0; v < h->cap; v++) {
        if (!h->count[v])
            continue;
        jsonw_array_begin(w, NULL);
        jsonw_u64(w, NULL, v);
        jsonw_u64(w, NULL, h->count[v]);
        jsonw_array_end(w);
    }
    jsonw_array_end(w);
    jsonw_object_end(w);
}

static void print_stats_json(FILE *out, const stats *s)
{
    static const char *const keys[H_COUNT] = {"word_length", "depth", "crossings_per_pixel",
                                              "stabbings_per_edge"};
    jsonw w;
    jsonw_init(&w, out);
    jsonw_object_begin(&w, NULL);
    jsonw_u64(&w, "leaves", s->leaves);
    jsonw_u64(&w, "private_leaves", s->private_leaves);
    jsonw_u64(&w, "vertices", s->vertices);
    jsonw_u64(&w, "edges", s->edges);
    if (s->faces_status)
        jsonw_null(&w, "faces");
    else
        jsonw_u64(&w, "faces", s->faces);
    jsonw_u64(&w, "stabbings", s->stabbings);
    for (int k = 0; k < H_COUNT; k++)
        print_hist_json(&w, &s->h[k], keys[k]);
    jsonw_object_end(&w);
    jsonw_finish(&w);
}

int view_stats(const hpfc_file *f, FILE *out, int json, char *why)
{
    stats s;
    memset(&s, 0, sizeof s);
    s.h[H_WORD_LENGTH] = (histogram){.name = "word length, symbols", .unit = "word pixels"};
    s.h[H_DEPTH] = (histogram){.name = "depth of leaves", .unit = "word pixels"};
    s.h[H_CROSSINGS] = (histogram){.name = "crossings per pixel", .unit = "word pixels"};
    s.h[H_STABBINGS] = (histogram){.name = "stabbings per edge", .unit = "edges"};
    int st = collect_stats(f, &s);
    if (!st) {
        if (json)
            print_stats_json(out, &s);
        else
            print_stats_text(out, &s);
    }
    for (int k = 0; k < H_COUNT; k++)
        free(s.h[k].count);
    return st ? fail_status(why, "stats", st) : VIEW_OK;
}
