/*
 * Unit tests of hpfc-pack's in-place sort (hpfc-pack/sort.h) against the C
 * library's qsort: elements of the two sizes hpfc-pack sorts (16-byte points
 * and 32-byte segments), on random arrays with many or few equal keys,
 * sorted, reversed, constant and organ-pipe inputs, sizes around the
 * insertion-sort cutoff and large ones; and the heapsort fallback forced
 * on its own. The threaded sort (sort_in_place_split) on 2, 3 and 4
 * threads, its sides split from 2, 64 and SORT_SPLIT_MIN elements, must be
 * the same bytes too (it runs under ThreadSanitizer in tools/run-tests.sh).
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "sort.h"
#include "check.h"

typedef struct point16 {
    int64_t x, y;
} point16;

typedef struct seg32 {
    int64_t ax, ay, bx, by;
} seg32;

static int cmp_i64(int64_t a, int64_t b)
{
    return (a > b) - (a < b);
}

static int cmp_point16(const void *a, const void *b)
{
    const point16 *p = a, *q = b;
    int c = cmp_i64(p->x, q->x);
    return c ? c : cmp_i64(p->y, q->y);
}

static int cmp_seg32(const void *a, const void *b)
{
    const seg32 *p = a, *q = b;
    int c = cmp_i64(p->ax, q->ax);
    c = c ? c : cmp_i64(p->ay, q->ay);
    c = c ? c : cmp_i64(p->bx, q->bx);
    return c ? c : cmp_i64(p->by, q->by);
}

static uint64_t rng_state = 0x9E3779B97F4A7C15ull;

static uint64_t rng(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return rng_state;
}

enum { RANDOM, FEW_KEYS, SORTED, REVERSED, CONSTANT, ORGAN_PIPE, SHAPES };

/* Key i of an array of n in the given shape. */
static int64_t shaped_key(int shape, size_t i, size_t n)
{
    switch (shape) {
    case RANDOM:
        return (int64_t)(rng() >> 1) - INT64_MAX / 2;
    case FEW_KEYS:
        return (int64_t)(rng() % 3) - 1;
    case SORTED:
        return (int64_t)i;
    case REVERSED:
        return -(int64_t)i;
    case CONSTANT:
        return 7;
    default:
        return (int64_t)(i < n / 2 ? i : n - i);
    }
}

/* Sorts a copy with sort_in_place (or, with depth 0, sort_intro's heapsort
 * at once) and another with qsort: the two must be the same bytes; and
 * copies on several threads, splitting from several sizes. */
static void check_against_qsort(const void *in, size_t n, size_t size, sort_cmp cmp, int heap_only)
{
    static const size_t splits[] = {2, 64, SORT_SPLIT_MIN};
    char *a = malloc(n * size + 1), *b = malloc(n * size + 1);
    memcpy(a, in, n * size);
    memcpy(b, in, n * size);
    if (heap_only && n > SORT_SMALL)
        sort_intro(a, n, size, cmp, 0);
    else
        sort_in_place(a, n, size, cmp);
    qsort(b, n, size, cmp);
    CHECK(memcmp(a, b, n * size) == 0);
    for (unsigned threads = 2; threads <= 4 && !heap_only; threads++)
        for (size_t k = 0; k < sizeof splits / sizeof splits[0]; k++) {
            memcpy(a, in, n * size);
            sort_in_place_split(a, n, size, cmp, threads, splits[k]);
            CHECK(memcmp(a, b, n * size) == 0);
        }
    free(a);
    free(b);
}

static void check_shape(int shape, size_t n, int heap_only)
{
    point16 *p = malloc((n + 1) * sizeof *p);
    seg32 *s = malloc((n + 1) * sizeof *s);
    for (size_t i = 0; i < n; i++) {
        int64_t k = shaped_key(shape, i, n);
        p[i] = (point16){k, shape == RANDOM ? (int64_t)(rng() % 5) : k};
        s[i] = (seg32){k, (int64_t)(rng() % 2), k, shape == FEW_KEYS ? 0 : (int64_t)rng()};
    }
    check_against_qsort(p, n, sizeof *p, cmp_point16, heap_only);
    check_against_qsort(s, n, sizeof *s, cmp_seg32, heap_only);
    free(p);
    free(s);
}

int main(void)
{
    static const size_t sizes[] = {0, 1, 2, 3, 15, 16, 17, 18, 31, 32, 33, 100, 1000, 4099, 200000};
    for (int shape = 0; shape < SHAPES; shape++)
        for (size_t k = 0; k < sizeof sizes / sizeof sizes[0]; k++)
            for (int heap_only = 0; heap_only < 2; heap_only++)
                check_shape(shape, sizes[k], heap_only);
    return check_report("sort");
}
