#include "jsonw.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void jsonw_init(jsonw *w, FILE *f)
{
    memset(w, 0, sizeof *w);
    w->f = f;
}

/* Length of the valid UTF-8 sequence at s (at most n bytes), 0 if invalid:
 * no overlong forms, no surrogates, nothing above U+10FFFF (RFC 3629). */
static size_t utf8_sequence(const unsigned char *s, size_t n)
{
    unsigned c = s[0];
    size_t len;
    unsigned lo = 0x80, hi = 0xBF; /* allowed range of the second byte */
    if (c < 0x80)
        return 1;
    if (c >= 0xC2 && c <= 0xDF)
        len = 2;
    else if (c >= 0xE0 && c <= 0xEF) {
        len = 3;
        lo = c == 0xE0 ? 0xA0 : 0x80;
        hi = c == 0xED ? 0x9F : 0xBF;
    } else if (c >= 0xF0 && c <= 0xF4) {
        len = 4;
        lo = c == 0xF0 ? 0x90 : 0x80;
        hi = c == 0xF4 ? 0x8F : 0xBF;
    } else
        return 0;
    if (n < len || s[1] < lo || s[1] > hi)
        return 0;
    for (size_t k = 2; k < len; k++)
        if (s[k] < 0x80 || s[k] > 0xBF)
            return 0;
    return len;
}

static void put_escaped(FILE *f, const char *str, size_t len)
{
    const unsigned char *s = (const unsigned char *)str;
    fputc('"', f);
    for (size_t i = 0; i < len;) {
        unsigned c = s[i];
        size_t n = utf8_sequence(s + i, len - i);
        if (c == '"' || c == '\\')
            fprintf(f, "\\%c", c);
        else if (c == '\n')
            fputs("\\n", f);
        else if (c == '\t')
            fputs("\\t", f);
        else if (c < 0x20 || c == 0x7F)
            fprintf(f, "\\u%04x", c);
        else if (n == 0)
            fputs("\\ufffd", f);
        else
            fwrite(s + i, 1, n, f);
        i += n ? n : 1;
    }
    fputc('"', f);
}

/* The comma and key that come before every value. */
static void prefix(jsonw *w, const char *key)
{
    if (w->depth > 0 && w->depth <= JSONW_MAX_DEPTH && w->count[w->depth - 1]++ > 0)
        fputc(',', w->f);
    if (key) {
        put_escaped(w->f, key, strlen(key));
        fputc(':', w->f);
    }
}

static void open_container(jsonw *w, const char *key, char c)
{
    prefix(w, key);
    fputc(c, w->f);
    if (w->depth < JSONW_MAX_DEPTH)
        w->count[w->depth] = 0;
    w->depth++;
}

static void close_container(jsonw *w, char c)
{
    if (w->depth > 0)
        w->depth--;
    fputc(c, w->f);
}

void jsonw_object_begin(jsonw *w, const char *key) { open_container(w, key, '{'); }
void jsonw_object_end(jsonw *w) { close_container(w, '}'); }
void jsonw_array_begin(jsonw *w, const char *key) { open_container(w, key, '['); }
void jsonw_array_end(jsonw *w) { close_container(w, ']'); }

void jsonw_u64(jsonw *w, const char *key, uint64_t v)
{
    prefix(w, key);
    fprintf(w->f, "%llu", (unsigned long long)v);
}

void jsonw_i64(jsonw *w, const char *key, int64_t v)
{
    prefix(w, key);
    fprintf(w->f, "%lld", (long long)v);
}

void jsonw_double(jsonw *w, const char *key, double v, int digits)
{
    prefix(w, key);
    if (isfinite(v))
        fprintf(w->f, "%.*f", digits, v);
    else
        fputs("null", w->f);
}

void jsonw_real(jsonw *w, const char *key, double v)
{
    prefix(w, key);
    if (!isfinite(v)) {
        fputs("null", w->f);
        return;
    }
    char buf[40];
    for (int digits = 15; digits <= 17; digits++) {
        snprintf(buf, sizeof buf, "%.*g", digits, v);
        if (strtod(buf, NULL) == v)
            break;
    }
    fputs(buf, w->f); /* %g never writes a form JSON refuses for a finite value */
}

void jsonw_bool(jsonw *w, const char *key, int v)
{
    prefix(w, key);
    fputs(v ? "true" : "false", w->f);
}

void jsonw_null(jsonw *w, const char *key)
{
    prefix(w, key);
    fputs("null", w->f);
}

void jsonw_string_n(jsonw *w, const char *key, const char *s, size_t len)
{
    prefix(w, key);
    put_escaped(w->f, s, len);
}

void jsonw_string(jsonw *w, const char *key, const char *s)
{
    jsonw_string_n(w, key, s, strlen(s));
}

void jsonw_finish(jsonw *w)
{
    fputc('\n', w->f);
}
