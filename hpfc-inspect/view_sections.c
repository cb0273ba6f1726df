/*
 * view_sections.c: --sections, the file's map: header, level table,
 * directory, every section with its checksum, each level's pool with the
 * padding between them. Checksums come from the mapping through the
 * library (hpfc_file_compute_checksum), each shown beside the stored one.
 */
#include "views.h"

#include <stdlib.h>
#include <string.h>

#include "jsonw.h"

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

/* Every checksum computed, so that all mismatches show, not only the first
 * one hpfc_file_check_checksums reports. */
static int read_map(const hpfc_file *f, file_map *m, char *why)
{
    hpfc_file_get_info(f, &m->info);
    for (uint32_t l = 0; l < m->info.levels && l < HPFC_MAX_LEVELS; l++)
        if (hpfc_file_get_level(f, l, &m->levels[l]))
            return view_fail(why, "level %u: cannot be read", l);
    m->sections = calloc(m->info.section_count + 1, sizeof *m->sections);
    if (!m->sections)
        return view_fail_status(why, "sections", HPFC_E_NOMEM);
    m->header_size = m->info.header_size;
    m->meta_size = m->info.meta_size;
    m->meta_crc = m->info.meta_crc32c;
    int st = hpfc_file_compute_checksum(f, HPFC_CHECKSUM_METADATA, &m->meta_computed);
    for (uint32_t k = 0; k < m->info.section_count && !st; k++) {
        section_row *s = &m->sections[k];
        if (!(st = hpfc_file_get_section(f, k, &s->info)))
            st = hpfc_file_compute_checksum(f, k, &s->computed);
        s->ok = s->computed == s->info.crc32c;
        m->bad += !s->ok;
    }
    if (st)
        return view_fail_status(why, "checksums", st);
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
    int status = read_map(f, &m, why);
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
