/*
 * test_api.c: the conventions of the public header itself, checked against
 * independent sources: every status code against the spec's table (§12.4)
 * and every `HPFC_E_NAME (number)` the specs cite.
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "hpfc.h"

/* Every code of hpfc.h, by the header's own names and values. */
#define CODE(c) {c, #c}
static const struct {
    int code;
    const char *name;
} all_codes[] = {
    CODE(HPFC_OK), CODE(HPFC_E_NOMEM), CODE(HPFC_E_ARG), CODE(HPFC_E_IO),
    CODE(HPFC_E_BUFFER_SMALL), CODE(HPFC_E_PFC_SYNTAX), CODE(HPFC_E_PFC_VERSION),
    CODE(HPFC_E_VERTEX_INDEX), CODE(HPFC_E_DUPLICATE_POINT), CODE(HPFC_E_ZERO_LENGTH),
    CODE(HPFC_E_LOOP_INTERIOR), CODE(HPFC_E_ISOLATED_VERTEX), CODE(HPFC_E_NONPLANAR),
    CODE(HPFC_E_EXTENT), CODE(HPFC_E_EMPTY), CODE(HPFC_E_TOO_MANY_PIXELS), CODE(HPFC_E_LIMIT),
    CODE(HPFC_E_MAGIC), CODE(HPFC_E_VERSION), CODE(HPFC_E_INCOMPATIBLE), CODE(HPFC_E_TRUNCATED),
    CODE(HPFC_E_CHECKSUM), CODE(HPFC_E_HEADER), CODE(HPFC_E_LEVEL_TABLE), CODE(HPFC_E_SECTION),
    CODE(HPFC_E_CORRUPT), CODE(HPFC_E_NO_PIXEL), CODE(HPFC_E_NO_SECTION),
};
#define CODE_COUNT (sizeof all_codes / sizeof all_codes[0])

static char *read_text(const char *dir, const char *name)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *fp = fopen(path, "rb");
    if (!fp) {
        fprintf(stderr, "cannot open %s\n", path);
        exit(EXIT_FAILURE);
    }
    fseek(fp, 0, SEEK_END);
    long n = ftell(fp);
    rewind(fp);
    char *s = malloc((size_t)n + 1);
    if (!s || fread(s, 1, (size_t)n, fp) != (size_t)n)
        exit(EXIT_FAILURE);
    s[n] = '\0';
    fclose(fp);
    return s;
}

static int code_of_name(const char *name, size_t len)
{
    for (size_t k = 0; k < CODE_COUNT; k++)
        if (strlen(all_codes[k].name) == len && memcmp(all_codes[k].name, name, len) == 0)
            return all_codes[k].code;
    return -1;
}

/* The spec's §12.4 rows "| number | `NAME` | meaning |": each names a code
 * of the header with its number, and each code has its row. */
static void check_spec_table(const char *spec)
{
    const char *at = strstr(spec, "### 12.4 Status codes");
    CHECK(at != NULL);
    if (!at)
        return;
    const char *end = strstr(at, "\n## ");
    int seen[CODE_COUNT] = {0};
    size_t rows = 0;
    for (const char *line = at; line && line < end; line = strchr(line + 1, '\n')) {
        int number;
        char name[64];
        if (sscanf(line, "\n| %d | `%63[A-Z_]` |", &number, name) != 2)
            continue;
        rows++;
        int code = code_of_name(name, strlen(name));
        if (code != number)
            fprintf(stderr, "spec row %s (%d): header says %d\n", name, number, code);
        CHECK_EQ_INT(code, number);
        for (size_t k = 0; k < CODE_COUNT; k++)
            seen[k] += all_codes[k].code == number;
    }
    CHECK_EQ_INT(rows, CODE_COUNT);
    for (size_t k = 0; k < CODE_COUNT; k++)
        if (seen[k] != 1)
            fprintf(stderr, "%s: %d rows in the spec's table\n", all_codes[k].name, seen[k]);
    for (size_t k = 0; k < CODE_COUNT; k++)
        CHECK_EQ_INT(seen[k], 1);
}

/* Every "`HPFC_E_NAME` (number)" in a spec's text gives the header's number. */
static void check_citations(const char *text, const char *file)
{
    size_t cited = 0;
    for (const char *p = strstr(text, "`HPFC_"); p; p = strstr(p + 1, "`HPFC_")) {
        const char *close = strchr(p + 1, '`');
        int number;
        if (!close || sscanf(close + 1, " (%d)", &number) != 1)
            continue;
        cited++;
        int code = code_of_name(p + 1, (size_t)(close - p - 1));
        if (code != number)
            fprintf(stderr, "%s: %.*s (%d): header says %d\n", file, (int)(close - p - 1), p + 1,
                    number, code);
        CHECK_EQ_INT(code, number);
    }
    CHECK(cited > 10);
}

/* hpfc_strerror names every code, each differently, and no other. */
static void check_strerror(void)
{
    const char *unknown = hpfc_strerror(9999);
    CHECK(unknown != NULL);
    for (size_t k = 0; k < CODE_COUNT; k++) {
        const char *s = hpfc_strerror(all_codes[k].code);
        CHECK(s != NULL && strcmp(s, unknown) != 0);
        for (size_t j = 0; j < k; j++)
            CHECK(strcmp(s, hpfc_strerror(all_codes[j].code)) != 0);
    }
    CHECK(strcmp(hpfc_strerror(-1), unknown) == 0);
    CHECK(strcmp(hpfc_strerror(5), unknown) == 0);
}

int main(void)
{
    const char *dir = getenv("HPFC_SPEC_DIR");
    if (!dir) {
        fprintf(stderr, "HPFC_SPEC_DIR is not set\n");
        return EXIT_FAILURE;
    }
    char *spec = read_text(dir, "hpfc-format.md");
    char *pfc = read_text(dir, "pfc-format.md");
    check_spec_table(spec);
    check_citations(spec, "hpfc-format.md");
    check_citations(pfc, "pfc-format.md");
    check_strerror();
    free(spec);
    free(pfc);
    return check_report("api");
}
