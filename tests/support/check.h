/* Minimal assertion helpers for the test programs. Each failed check prints
 * its location and is counted; a test program exits non-zero if any check
 * failed. */
#ifndef HPFC_TEST_CHECK_H
#define HPFC_TEST_CHECK_H

#include <stdio.h>
#include <stdlib.h>

#include "hpfc.h"

static int check_failures;
static long check_count;

#define CHECK(cond)                                                        \
    do {                                                                   \
        check_count++;                                                     \
        if (!(cond)) {                                                     \
            check_failures++;                                              \
            fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__,         \
                    __LINE__, #cond);                                      \
        }                                                                  \
    } while (0)

#define CHECK_EQ_INT(a, b)                                                 \
    do {                                                                   \
        long long check_a_ = (long long)(a), check_b_ = (long long)(b);    \
        check_count++;                                                     \
        if (check_a_ != check_b_) {                                        \
            check_failures++;                                              \
            fprintf(stderr, "%s:%d: %s == %lld, expected %s == %lld\n",    \
                    __FILE__, __LINE__, #a, check_a_, #b, check_b_);       \
        }                                                                  \
    } while (0)

/* The pool layout the tests write, from HPFC_TEST_LAYOUT ("compact" or
 * unset: the paper's): tests/meson.build runs the file tests once per
 * layout. check_tree_serialize writes it wherever a test asks for the
 * library's default layout; a layout a test names explicitly is kept. */
static int check_layout = HPFC_LAYOUT_PAPER;

/* Returns 1 for the compact layout. */
static inline int check_use_test_layout(void)
{
    const char *v = getenv("HPFC_TEST_LAYOUT");
    int compact = v && v[0] == 'c';
    check_layout = compact ? HPFC_LAYOUT_COMPACT : HPFC_LAYOUT_PAPER;
    if (compact)
        printf("layout: compact\n");
    return compact;
}

/* hpfc_tree_serialize in the layout under test. */
static inline int check_tree_serialize(const hpfc_tree *t, const hpfc_write_options *opts,
                                       uint8_t **out, size_t *out_size, hpfc_diag *diag)
{
    hpfc_write_options o = {0};
    if (opts)
        o = *opts;
    if (o.layout == HPFC_LAYOUT_DEFAULT)
        o.layout = check_layout;
    return hpfc_tree_serialize(t, &o, out, out_size, diag);
}

/* g built with bp, serialised with LABL and GEOM in the layout under test
 * and opened from the bytes: HPFC_OK with *buf, *size and *f for the
 * caller to free (hpfc_close, hpfc_free), or the first failing status,
 * nothing left to free. */
static inline int check_labelled_file(const hpfc_graph *g, const hpfc_build_params *bp, uint8_t **buf,
                                      size_t *size, hpfc_file **f)
{
    hpfc_tree *tree = NULL;
    hpfc_write_options o = {.face_labels = 1, .geometry = g};
    *buf = NULL, *f = NULL;
    int st = hpfc_build(g, bp, &tree, NULL);
    if (!st)
        st = check_tree_serialize(tree, &o, buf, size, NULL);
    hpfc_tree_free(tree);
    if (!st && (st = hpfc_open_memory(*buf, *size, 0, f)) != HPFC_OK) {
        hpfc_free(*buf);
        *buf = NULL;
    }
    return st;
}

static inline int check_report(const char *name)
{
    printf("%s: %ld checks, %d failed\n", name, check_count, check_failures);
    return check_failures ? EXIT_FAILURE : EXIT_SUCCESS;
}

#endif
