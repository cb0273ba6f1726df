/* Minimal assertion helpers for the test programs. Each failed check prints
 * its location and is counted; a test program exits non-zero if any check
 * failed. */
#ifndef HPFC_TEST_CHECK_H
#define HPFC_TEST_CHECK_H

#include <stdio.h>
#include <stdlib.h>

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

/* The pool layout the library writes by default, from HPFC_TEST_LAYOUT
 * ("compact" or unset): tests/meson.build runs the file tests once per
 * layout. Returns 1 for the compact layout. */
extern int write_default_layout;
static inline int check_use_test_layout(void)
{
    const char *v = getenv("HPFC_TEST_LAYOUT");
    int compact = v && v[0] == 'c';
    write_default_layout = compact ? 2 : 1; /* HPFC_LAYOUT_COMPACT, _PAPER */
    if (compact)
        printf("layout: compact\n");
    return compact;
}

static inline int check_report(const char *name)
{
    printf("%s: %ld checks, %d failed\n", name, check_count, check_failures);
    return check_failures ? EXIT_FAILURE : EXIT_SUCCESS;
}

#endif
