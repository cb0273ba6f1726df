/*
 * hpfc-inspect: shows the header, section directory and level table of an
 * .hpfc file (contracts §3).
 *
 *   hpfc-inspect FILE              summary and per-level table
 *   hpfc-inspect --json FILE       the same as one JSON object
 *
 * Only what hpfc_open() validates is shown: opening checks the header, the
 * level table and the section directory without decoding the pools, so this
 * runs in O(levels + sections) on any file size. Exit status: 0 success,
 * 1 when FILE cannot be opened ("hpfc-inspect: FILE: <reason>"), 2 for a
 * usage error.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hpfc.h"
#include "jsonw.h"

enum { EXIT_FAIL = 1, EXIT_USAGE = 2 };

typedef struct inspect_args {
    const char *file;
    int json;
} inspect_args;

/* Everything shown, read once so that the printers cannot fail. */
typedef struct summary {
    hpfc_file_info info;
    hpfc_level_info levels[HPFC_MAX_LEVELS];
    hpfc_section_info *sections;    /* info.section_count entries */
    uint64_t word_pixels, refined_pixels;
} summary;

static void print_help(void)
{
    printf("usage: hpfc-inspect [--json] FILE\n"
           "\n"
           "Shows the header, the section directory and the per-level table of an\n"
           ".hpfc file.\n"
           "\n"
           "options:\n"
           "  --json         print one JSON object instead of text\n"
           "  -h, --help     show this help\n"
           "  --version      show the version\n"
           "\n"
           "Exit status: 0 success, 1 FILE cannot be opened, 2 usage error.\n");
}

static int usage_error(const char *what, const char *arg)
{
    fprintf(stderr, "hpfc-inspect: %s%s%s (see --help)\n", arg ? arg : "", arg ? ": " : "", what);
    return EXIT_USAGE;
}

/* Returns -1 to go on, or the exit status (0 after --help / --version). */
static int parse_args(int argc, char **argv, inspect_args *a)
{
    static const char *const later[] = {"--verify", "--export-graph", "--locate",
                                        "--locate-lonlat", "--locate-batch", "--lonlat"};
    int only_files = 0;
    memset(a, 0, sizeof *a);
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        if (only_files || arg[0] != '-' || strcmp(arg, "-") == 0) {
            if (a->file)
                return usage_error("more than one FILE", arg);
            a->file = arg;
            continue;
        }
        if (strcmp(arg, "--") == 0)
            only_files = 1;
        else if (strcmp(arg, "-h") == 0 || strcmp(arg, "--help") == 0) {
            print_help();
            return 0;
        } else if (strcmp(arg, "--version") == 0) {
            printf("hpfc-inspect %s\n", hpfc_version_string());
            return 0;
        } else if (strcmp(arg, "--json") == 0)
            a->json = 1;
        else {
            for (size_t k = 0; k < sizeof later / sizeof later[0]; k++)
                if (strncmp(arg, later[k], strlen(later[k])) == 0 &&
                    (arg[strlen(later[k])] == '\0' || arg[strlen(later[k])] == '='))
                    return usage_error("not implemented yet", later[k]);
            return usage_error("unknown option", arg);
        }
    }
    if (!a->file)
        return usage_error("missing FILE", NULL);
    return -1;
}

/* Reads the header, levels and sections; HPFC_OK or the first failure. */
static int read_summary(const hpfc_file *f, summary *s)
{
    hpfc_file_get_info(f, &s->info);
    if (s->info.levels > HPFC_MAX_LEVELS)
        return HPFC_E_LEVEL_TABLE;
    for (uint32_t l = 0; l < s->info.levels; l++) {
        int st = hpfc_file_get_level(f, l, &s->levels[l]);
        if (st)
            return st;
        s->word_pixels += s->levels[l].word_pixels;
        s->refined_pixels += s->levels[l].refined_pixels;
    }
    s->sections = calloc(s->info.section_count ? s->info.section_count : 1, sizeof *s->sections);
    if (!s->sections)
        return HPFC_E_NOMEM;
    for (uint32_t k = 0; k < s->info.section_count; k++) {
        int st = hpfc_file_get_section(f, k, &s->sections[k]);
        if (st)
            return st;
    }
    return HPFC_OK;
}

static void print_json(const char *path, const summary *s)
{
    const hpfc_file_info *fi = &s->info;
    char version[32];
    snprintf(version, sizeof version, "%u.%u", fi->format_major, fi->format_minor);
    jsonw w;
    jsonw_init(&w, stdout);
    jsonw_object_begin(&w, NULL);
    jsonw_string(&w, "file", path);
    jsonw_string(&w, "format", "hpfc");
    jsonw_string(&w, "format_version", version);
    jsonw_u64(&w, "format_major", fi->format_major);
    jsonw_u64(&w, "format_minor", fi->format_minor);
    jsonw_u64(&w, "compat_flags", fi->compat_flags);
    jsonw_u64(&w, "incompat_flags", fi->incompat_flags);
    jsonw_u64(&w, "root_cols", fi->root_cols);
    jsonw_u64(&w, "root_rows", fi->root_rows);
    jsonw_u64(&w, "refine_cols", fi->cols);
    jsonw_u64(&w, "refine_rows", fi->rows);
    jsonw_u64(&w, "depth", fi->levels ? fi->levels - 1 : 0);
    jsonw_u64(&w, "level_count", fi->levels);
    jsonw_object_begin(&w, "domain");
    jsonw_i64(&w, "x0", fi->x0);
    jsonw_i64(&w, "y0", fi->y0);
    jsonw_i64(&w, "width", fi->width);
    jsonw_i64(&w, "height", fi->height);
    jsonw_object_end(&w);
    jsonw_i64(&w, "unit_exp10", fi->unit_exp10);
    if (fi->crs)
        jsonw_string_n(&w, "crs", fi->crs, fi->crs_len);
    else
        jsonw_null(&w, "crs");
    jsonw_u64(&w, "file_bytes", fi->file_size);
    jsonw_u64(&w, "word_pixels", s->word_pixels);
    jsonw_u64(&w, "refined_pixels", s->refined_pixels);
    jsonw_u64(&w, "total_pixels", s->word_pixels + s->refined_pixels);
    jsonw_array_begin(&w, "sections");
    for (uint32_t k = 0; k < fi->section_count; k++) {
        const hpfc_section_info *sec = &s->sections[k];
        jsonw_object_begin(&w, NULL);
        jsonw_string_n(&w, "tag", sec->tag, strnlen(sec->tag, 4));
        jsonw_u64(&w, "flags", sec->flags);
        jsonw_u64(&w, "offset", sec->offset);
        jsonw_u64(&w, "length", sec->length);
        jsonw_u64(&w, "crc32c", sec->crc32c);
        jsonw_object_end(&w);
    }
    jsonw_array_end(&w);
    jsonw_array_begin(&w, "levels");
    for (uint32_t l = 0; l < fi->levels; l++) {
        const hpfc_level_info *lv = &s->levels[l];
        jsonw_object_begin(&w, NULL);
        jsonw_u64(&w, "level", l);
        jsonw_u64(&w, "images", lv->images);
        jsonw_u64(&w, "word_pixels", lv->word_pixels);
        jsonw_u64(&w, "refined_pixels", lv->refined_pixels);
        jsonw_u64(&w, "word_bits", lv->word_bits);
        jsonw_u64(&w, "address_bits", lv->address_bits);
        jsonw_u64(&w, "pool_offset", lv->pool_offset);
        jsonw_u64(&w, "pool_bits", lv->pool_bits);
        jsonw_i64(&w, "cell_w", lv->cell_w);
        jsonw_i64(&w, "cell_h", lv->cell_h);
        jsonw_object_end(&w);
    }
    jsonw_array_end(&w);
    jsonw_object_end(&w);
    jsonw_finish(&w);
}

/* Text from the file, with control characters shown as '?': the file is
 * untrusted and must not drive the terminal. */
static void put_printable(const char *s, size_t len)
{
    for (size_t k = 0; k < len; k++)
        putchar((unsigned char)s[k] < 0x20 || s[k] == 0x7F ? '?' : s[k]);
}

/* A section tag as printable text (a corrupt-looking tag must not garble
 * the terminal). */
static void printable_tag(const char *tag, char out[5])
{
    for (int k = 0; k < 4; k++)
        out[k] = tag[k] >= 0x20 && tag[k] < 0x7F ? tag[k] : '?';
    out[4] = '\0';
}

static void print_text(const char *path, const summary *s)
{
    const hpfc_file_info *fi = &s->info;
    printf("file       %s (%llu bytes)\n", path, (unsigned long long)fi->file_size);
    printf("format     hpfc %u.%u, compat flags 0x%x, incompat flags 0x%x\n", fi->format_major,
           fi->format_minor, fi->compat_flags, fi->incompat_flags);
    printf("images     root %ux%u, refined %ux%u\n", fi->root_cols, fi->root_rows, fi->cols,
           fi->rows);
    printf("depth      %u (%u level%s)\n", fi->levels ? fi->levels - 1 : 0, fi->levels,
           fi->levels == 1 ? "" : "s");
    printf("domain     x0 %lld, y0 %lld, %lld x %lld lattice units of 10^%d\n",
           (long long)fi->x0, (long long)fi->y0, (long long)fi->width, (long long)fi->height,
           fi->unit_exp10);
    printf("crs        ");
    if (fi->crs)
        put_printable(fi->crs, fi->crs_len);
    else
        printf("none");
    printf("\n");
    printf("pixels     %llu (%llu word, %llu refined)\n",
           (unsigned long long)(s->word_pixels + s->refined_pixels),
           (unsigned long long)s->word_pixels, (unsigned long long)s->refined_pixels);

    printf("\n%-4s %12s %12s %10s %6s\n", "tag", "offset", "length", "crc32c", "flags");
    for (uint32_t k = 0; k < fi->section_count; k++) {
        const hpfc_section_info *sec = &s->sections[k];
        char tag[5];
        printable_tag(sec->tag, tag);
        printf("%-4s %12llu %12llu 0x%08x 0x%04x\n", tag, (unsigned long long)sec->offset,
               (unsigned long long)sec->length, sec->crc32c, sec->flags);
    }

    printf("\n%5s %10s %12s %12s %5s %5s %12s %14s %12s\n", "level", "images", "word",
           "refined", "k_w", "k_@", "pool offset", "pool bits", "cell");
    for (uint32_t l = 0; l < fi->levels; l++) {
        const hpfc_level_info *lv = &s->levels[l];
        char cell[48];
        snprintf(cell, sizeof cell, "%lldx%lld", (long long)lv->cell_w, (long long)lv->cell_h);
        printf("%5u %10llu %12llu %12llu %5u %5u %12llu %14llu %12s\n", l,
               (unsigned long long)lv->images, (unsigned long long)lv->word_pixels,
               (unsigned long long)lv->refined_pixels, lv->word_bits, lv->address_bits,
               (unsigned long long)lv->pool_offset, (unsigned long long)lv->pool_bits, cell);
    }
}

/* One line naming FILE and the reason, with the system's reason for an I/O
 * failure (a missing file is the usual one). */
static int open_error(const char *path, int st, int err)
{
    if (st == HPFC_E_IO && err)
        fprintf(stderr, "hpfc-inspect: %s: %s (%s)\n", path, hpfc_strerror(st), strerror(err));
    else
        fprintf(stderr, "hpfc-inspect: %s: %s\n", path, hpfc_strerror(st));
    return EXIT_FAIL;
}

int main(int argc, char **argv)
{
    inspect_args a;
    int status = parse_args(argc, argv, &a);
    if (status >= 0)
        return status;
    hpfc_file *f = NULL;
    errno = 0;
    int st = hpfc_open(a.file, 0, &f);
    if (st)
        return open_error(a.file, st, errno);
    summary s = {0};
    st = read_summary(f, &s);
    if (st)
        status = open_error(a.file, st, 0);
    else if (a.json)
        print_json(a.file, &s);
    else
        print_text(a.file, &s);
    if (!st && fflush(stdout) != 0) {
        fprintf(stderr, "hpfc-inspect: cannot write the output: %s\n", strerror(errno));
        status = EXIT_FAIL;
    }
    free(s.sections);
    hpfc_close(f);
    return status < 0 ? 0 : status;
}
