/*
 * points_table.h: the POINTS table of --locate-batch read as a user's CSV
 * or blank-separated file: the separator guessed from the first line, CSV
 * quotes understood, a header told from data, the coordinate and id
 * columns found by name or number (locate.h says how).
 */
#ifndef HPFC_INSPECT_POINTS_TABLE_H
#define HPFC_INSPECT_POINTS_TABLE_H

#include <stddef.h>

#include "locate.h"

/* The fields of one line of POINTS, pointing into the line (which the
 * split rewrites in place). */
typedef struct table_fields {
    char **v;
    size_t n, cap;
} table_fields;

/* How POINTS is laid out, from its first line. */
typedef struct table_layout {
    char sep;
    int header;
    size_t ncols;
    char **names;            /* per column: its header name, or "colN" */
    size_t lon, lat;         /* the coordinate columns */
    long id;                 /* the id column, -1 for none */
    int lonlat;              /* the coordinates are degrees */
} table_layout;

/* A line with nothing but blanks, or a '#' comment. */
int table_blank_line(const char *s);
/* The separator of POINTS, from its first line: a tab, else a comma, else
 * a semicolon, else runs of blanks (' '). */
char table_guess_separator(const char *line);
/* Splits `line` in place at `sep` (' ': runs of blanks and tabs). A field
 * in double quotes may hold the separator, and "" stands for one quote, as
 * in CSV; fields are trimmed of blanks. 0, or -1 when memory runs out. */
int table_split_fields(char *line, char sep, table_fields *fl);
/* A decimal number as decimal_parse reads it. */
int table_is_number(const char *s);
/* Reads the layout from the first line: a header when its coordinate
 * fields are not numbers (or when columns are named by --lon-col ...).
 * VIEW_OK, or VIEW_FAIL with the reason (naming in_name and line). */
int table_layout_read(table_layout *t, const table_fields *fl, char sep, const batch_options *o,
                      const char *in_name, unsigned long line, char *why);
void table_layout_free(table_layout *t);

#endif
