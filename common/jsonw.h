/*
 * jsonw.h: a tiny streaming JSON writer shared by hpfc-pack and hpfc-inspect.
 *
 * It keeps the commas and the nesting, so the tools' report code reads as a
 * list of fields. Output is one compact line. Strings are escaped, and bytes
 * that are not valid UTF-8 (file names are arbitrary bytes) become U+FFFD, so
 * the output is always valid JSON. Numbers that JSON cannot spell (NaN,
 * infinities) are written as null.
 */
#ifndef HPFC_JSONW_H
#define HPFC_JSONW_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#define JSONW_MAX_DEPTH 16

typedef struct jsonw {
    FILE *f;
    int depth;
    int count[JSONW_MAX_DEPTH]; /* values written so far in each open container */
} jsonw;

void jsonw_init(jsonw *w, FILE *f);

/* `key` names the value inside an object; pass NULL inside an array and for
 * the top-level value. */
void jsonw_object_begin(jsonw *w, const char *key);
void jsonw_object_end(jsonw *w);
void jsonw_array_begin(jsonw *w, const char *key);
void jsonw_array_end(jsonw *w);

void jsonw_u64(jsonw *w, const char *key, uint64_t v);
void jsonw_i64(jsonw *w, const char *key, int64_t v);
/* `digits` after the decimal point (fixed notation). */
void jsonw_double(jsonw *w, const char *key, double v, int digits);
/* The shortest decimal form that reads back as v (null if not finite). */
void jsonw_real(jsonw *w, const char *key, double v);
void jsonw_bool(jsonw *w, const char *key, int v);
void jsonw_null(jsonw *w, const char *key);
/* A string of `len` bytes (it may hold NULs, which are escaped). */
void jsonw_string_n(jsonw *w, const char *key, const char *s, size_t len);
void jsonw_string(jsonw *w, const char *key, const char *s);

/* Ends the top-level value with a newline. */
void jsonw_finish(jsonw *w);

#endif
