/*
 * escape.h: text written into the tools' outputs so that any byte of a
 * user's data (a column name, a feature key, a path) reads back as itself:
 * CSV fields (RFC 4180 quoting) and XML character data (--render's SVG).
 * JSON strings are jsonw.h's. Header-only.
 */
#ifndef HPFC_TOOLS_ESCAPE_H
#define HPFC_TOOLS_ESCAPE_H

#include <stdio.h>
#include <string.h>

/* One CSV field, after a comma unless it is the line's first (*first is
 * then cleared), quoted when it holds a comma, a quote or a line end, a
 * quote doubled inside. */
static inline void csv_write_field(FILE *out, const char *s, int *first)
{
    if (!*first)
        fputc(',', out);
    *first = 0;
    if (!strpbrk(s, ",\"\r\n")) {
        fputs(s, out);
        return;
    }
    fputc('"', out);
    for (; *s; s++) {
        if (*s == '"')
            fputc('"', out);
        fputc(*s, out);
    }
    fputc('"', out);
}

/* XML character data: '<', '&' and '>' as entities. */
static inline void xml_write_text(FILE *out, const char *t)
{
    for (; *t; t++) {
        if (*t == '<')
            fputs("&lt;", out);
        else if (*t == '&')
            fputs("&amp;", out);
        else if (*t == '>')
            fputs("&gt;", out);
        else
            fputc(*t, out);
    }
}

#endif
