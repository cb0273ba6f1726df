/*
 * fixtures.h: the verdicts of tests/data/invalid/ for the test programs.
 *
 * tests/data/invalid/EXPECTED lists every invalid fixture as "FILE
 * HPFC_E_NAME"; test_open checks the .hpfc ones, test_pfc the .pfc ones.
 * check_invalid_fixtures() runs one kind: every file of that suffix must
 * have a line, every line a file, and the file must give its status.
 * check_valid_fixtures() runs tests/data/valid/: every file gives HPFC_OK.
 */
#ifndef HPFC_TEST_FIXTURES_H
#define HPFC_TEST_FIXTURES_H

#include <dirent.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "hpfc.h"

static inline bool fixture_has_suffix(const char *name, const char *suffix)
{
    size_t n = strlen(name), s = strlen(suffix);
    return n > s && strcmp(name + n - s, suffix) == 0;
}

/* The status an "HPFC_E_NAME" of EXPECTED stands for, -1 if none. */
static inline int fixture_code_of_name(const char *name)
{
    static const struct {
        const char *name;
        int code;
    } codes[] = {
        {"HPFC_E_PFC_SYNTAX", HPFC_E_PFC_SYNTAX},
        {"HPFC_E_PFC_VERSION", HPFC_E_PFC_VERSION},
        {"HPFC_E_VERTEX_INDEX", HPFC_E_VERTEX_INDEX},
        {"HPFC_E_DUPLICATE_POINT", HPFC_E_DUPLICATE_POINT},
        {"HPFC_E_ZERO_LENGTH", HPFC_E_ZERO_LENGTH},
        {"HPFC_E_LOOP_INTERIOR", HPFC_E_LOOP_INTERIOR},
        {"HPFC_E_ISOLATED_VERTEX", HPFC_E_ISOLATED_VERTEX},
        {"HPFC_E_NONPLANAR", HPFC_E_NONPLANAR},
        {"HPFC_E_EXTENT", HPFC_E_EXTENT},
        {"HPFC_E_EMPTY", HPFC_E_EMPTY},
        {"HPFC_E_LIMIT", HPFC_E_LIMIT},
        {"HPFC_E_MAGIC", HPFC_E_MAGIC},
        {"HPFC_E_VERSION", HPFC_E_VERSION},
        {"HPFC_E_INCOMPATIBLE", HPFC_E_INCOMPATIBLE},
        {"HPFC_E_TRUNCATED", HPFC_E_TRUNCATED},
        {"HPFC_E_CHECKSUM", HPFC_E_CHECKSUM},
        {"HPFC_E_HEADER", HPFC_E_HEADER},
        {"HPFC_E_LEVEL_TABLE", HPFC_E_LEVEL_TABLE},
        {"HPFC_E_SECTION", HPFC_E_SECTION},
        {"HPFC_E_CORRUPT", HPFC_E_CORRUPT},
    };
    for (size_t k = 0; k < sizeof codes / sizeof codes[0]; k++)
        if (strcmp(codes[k].name, name) == 0)
            return codes[k].code;
    return -1;
}

typedef struct fixture_verdict {
    char file[256];
    int code;
    bool seen;
} fixture_verdict;

/* The lines of root/invalid/EXPECTED whose file ends in suffix. */
static inline size_t fixture_load_verdicts(const char *root, const char *suffix,
                                           fixture_verdict *list, size_t max)
{
    char path[4096], line[512], name[256], code[64];
    snprintf(path, sizeof path, "%s/invalid/EXPECTED", root);
    FILE *f = fopen(path, "r");
    CHECK(f != NULL);
    if (!f)
        return 0;
    size_t n = 0;
    while (fgets(line, sizeof line, f)) {
        if (line[0] == '#' || sscanf(line, "%255s", name) != 1 ||
            !fixture_has_suffix(name, suffix))
            continue;
        bool ok = sscanf(line, "%255s %63s", name, code) == 2 && fixture_code_of_name(code) >= 0;
        if (!ok)
            fprintf(stderr, "EXPECTED: bad line: %s", line);
        CHECK(ok);
        CHECK(n < max);
        if (!ok || n >= max)
            continue;
        snprintf(list[n].file, sizeof list[n].file, "%s", name);
        list[n].code = fixture_code_of_name(code);
        list[n++].seen = false;
    }
    fclose(f);
    return n;
}

/* Reads or opens one fixture the way its test does; returns the first
 * failing status and may describe it in detail[0 .. n). */
typedef int (*fixture_check)(const char *path, char *detail, size_t n);

/* Runs `run` on every file of root/sub/ ending in suffix, in directory
 * order; `verdict` gets each file's name and status. Returns the number of
 * files run. */
typedef void (*fixture_verdict_fn)(const char *name, const char *path, int st,
                                   const char *detail, void *user);

static inline size_t run_fixtures(const char *root, const char *sub, const char *suffix,
                                  fixture_check run, fixture_verdict_fn verdict, void *user)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", root, sub);
    DIR *dir = opendir(path);
    CHECK(dir != NULL);
    if (!dir)
        return 0;
    size_t files = 0;
    for (struct dirent *de; (de = readdir(dir));) {
        if (!fixture_has_suffix(de->d_name, suffix))
            continue;
        char detail[512] = "";
        snprintf(path, sizeof path, "%s/%s/%s", root, sub, de->d_name);
        verdict(de->d_name, path, run(path, detail, sizeof detail), detail, user);
        files++;
    }
    closedir(dir);
    return files;
}

/* "STATUS" or "STATUS (detail)" on stderr, after `what: `. */
static inline void fixture_report(const char *what, int st, const char *detail)
{
    fprintf(stderr, "%s: %s%s%s%s", what, hpfc_strerror(st), detail[0] ? " (" : "", detail,
            detail[0] ? ")" : "");
}

static inline void expect_ok(const char *name, const char *path, int st, const char *detail,
                             void *user)
{
    (void)name;
    (void)user;
    if (st != HPFC_OK) {
        fixture_report(path, st, detail);
        fputc('\n', stderr);
    }
    CHECK_EQ_INT(st, HPFC_OK);
}

/* Every root/valid/ file ending in suffix gives HPFC_OK, and there are at
 * least `least`. */
static inline void check_valid_fixtures(const char *root, const char *suffix, fixture_check run,
                                        size_t least)
{
    CHECK(run_fixtures(root, "valid", suffix, run, expect_ok, NULL) >= least);
}

typedef struct verdict_list {
    fixture_verdict *list;
    size_t n;
} verdict_list;

static inline void expect_verdict(const char *name, const char *path, int st, const char *detail,
                                  void *user)
{
    (void)path;
    verdict_list *v = user;
    fixture_verdict *want = NULL;
    for (size_t k = 0; k < v->n; k++)
        if (strcmp(v->list[k].file, name) == 0)
            want = &v->list[k];
    if (!want)
        fprintf(stderr, "%s has no line in EXPECTED\n", name);
    CHECK(want != NULL);
    if (!want)
        return;
    want->seen = true;
    if (st != want->code) {
        fixture_report(name, st, detail);
        fprintf(stderr, ", expected %s\n", hpfc_strerror(want->code));
    }
    CHECK_EQ_INT(st, want->code);
}

/* Every root/invalid/ file ending in suffix gives the status of its line of
 * EXPECTED, every such line names a file, and there are at least `least`. */
static inline void check_invalid_fixtures(const char *root, const char *suffix, fixture_check run,
                                          size_t least)
{
    static fixture_verdict list[256];
    verdict_list v = {list, fixture_load_verdicts(root, suffix, list, sizeof list / sizeof *list)};
    run_fixtures(root, "invalid", suffix, run, expect_verdict, &v);
    for (size_t k = 0; k < v.n; k++) {
        if (!list[k].seen)
            fprintf(stderr, "EXPECTED names %s, which does not exist\n", list[k].file);
        CHECK(list[k].seen);
    }
    CHECK(v.n >= least);
}

#endif
