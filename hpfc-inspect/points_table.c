/*
 * points_table.c: the POINTS table of --locate-batch (points_table.h).
 */
#include "points_table.h"

#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "grow.h"

/* One line of POINTS without its end: blank or '#' lines are skipped. */
int table_blank_line(const char *s)
{
    s += strspn(s, " \t\r");
    return *s == '\0' || *s == '#';
}

/* The separator of POINTS, from its first line: a tab, else a comma, else
 * a semicolon, else runs of blanks (' '). */
char table_guess_separator(const char *line)
{
    if (strchr(line, '\t'))
        return '\t';
    if (strchr(line, ','))
        return ',';
    if (strchr(line, ';'))
        return ';';
    return ' ';
}

static char *trim(char *s)
{
    s += strspn(s, " \t");
    size_t n = strlen(s);
    while (n && (s[n - 1] == ' ' || s[n - 1] == '\t'))
        s[--n] = '\0';
    return s;
}

static int is_separator(char c, char sep)
{
    return c == sep || (sep == ' ' && c == '\t');
}

/* Splits `line` in place at `sep` (' ': runs of blanks and tabs). A field
 * in double quotes may hold the separator, and "" stands for one quote, as
 * in CSV; fields are trimmed of blanks. 0, or -1 when memory runs out. */
int table_split_fields(char *line, char sep, table_fields *fl)
{
    const char *blanks = sep == '\t' ? " " : " \t";
    char *p = line;
    fl->n = 0;
    if (sep == ' ' && !*(p += strspn(p, blanks)))
        return 0;
    for (;;) {
        if (!array_grow((void **)&fl->v, &fl->cap, fl->n + 1, sizeof *fl->v))
            return -1;
        char *start = p + strspn(p, blanks), *q = start, *w;
        if (*q == '"') { /* copied down over itself: w never passes q */
            w = start;
            for (q++; *q; *w++ = *q++)
                if (*q == '"' && q[1] == '"')
                    q++;
                else if (*q == '"') {
                    q++;
                    break;
                }
            while (*q && !is_separator(*q, sep))
                *w++ = *q++;
        } else {
            while (*q && !is_separator(*q, sep))
                q++;
            w = q;
        }
        char end = *q;
        *w = '\0';
        fl->v[fl->n++] = trim(start);
        if (!end)
            return 0;
        p = q + 1;
        if (sep == ' ' && !*(p += strspn(p, blanks)))
            return 0;
    }
}

static int name_is(const char *name, const char *const *list)
{
    for (; *list; list++)
        if (strcasecmp(name, *list) == 0)
            return 1;
    return 0;
}

static const char *const lon_names[] = {"lon", "lng", "long", "longitude", NULL};
static const char *const lat_names[] = {"lat", "latitude", NULL};
static const char *const x_names[] = {"x", "easting", NULL};
static const char *const y_names[] = {"y", "northing", NULL};
static const char *const id_names[] = {"id", NULL};

/* A column number ("3": the third column), 0 if `text` is a name. */
static size_t column_number(const char *text)
{
    size_t v = 0;
    for (const char *c = text; *c; c++) {
        if (*c < '0' || *c > '9' || v > 100000)
            return 0;
        v = v * 10 + (size_t)(*c - '0');
    }
    return v;
}


void table_layout_free(table_layout *t)
{
    for (size_t k = 0; t->names && k < t->ncols; k++)
        free(t->names[k]);
    free(t->names);
}

/* The column `opt` names (a header name, any case, or a number), or the
 * first whose name is in `guess`; -1 when none. */
static long find_column(const table_layout *t, const char *opt, const char *const *guess,
                        const char *const *guess2)
{
    if (opt && column_number(opt))
        return column_number(opt) <= t->ncols ? (long)column_number(opt) - 1 : -1;
    for (size_t k = 0; t->header && k < t->ncols; k++)
        if (opt ? strcasecmp(t->names[k], opt) == 0
                : name_is(t->names[k], guess) || (guess2 && name_is(t->names[k], guess2)))
            return (long)k;
    return -1;
}

int table_is_number(const char *s)
{
    decimal d;
    return *s && decimal_parse(s, strlen(s), &d) == 0;
}

/* Reads the layout from the first line: a header when its coordinate
 * fields are not numbers (or when columns are named by --lon-col ...). */
int table_layout_read(table_layout *t, const table_fields *fl, char sep, const batch_options *o,
                       const char *in_name, unsigned long line, char *why)
{
    memset(t, 0, sizeof *t);
    t->sep = sep;
    t->ncols = fl->n;
    t->id = -1;
    size_t lon_n = o->lon_col ? column_number(o->lon_col) : 1;
    size_t lat_n = o->lat_col ? column_number(o->lat_col) : 2;
    t->header = (o->lon_col && !lon_n) || (o->lat_col && !lat_n) || (o->id_col && !column_number(o->id_col)) ||
                (lon_n && lon_n <= fl->n && !table_is_number(fl->v[lon_n - 1])) ||
                (lat_n && lat_n <= fl->n && !table_is_number(fl->v[lat_n - 1]));
    if (!(t->names = calloc(t->ncols ? t->ncols : 1, sizeof *t->names)))
        return view_fail(why, "out of memory");
    for (size_t k = 0; k < t->ncols; k++) {
        char buf[32];
        snprintf(buf, sizeof buf, "col%zu", k + 1);
        if (!(t->names[k] = strdup(t->header ? fl->v[k] : buf)))
            return view_fail(why, "out of memory");
    }
    long lon = find_column(t, o->lon_col, lon_names, o->lonlat ? x_names : x_names);
    long lat = find_column(t, o->lat_col, lat_names, y_names);
    if (!t->header && !o->lon_col)
        lon = t->ncols >= 1 ? 0 : -1;
    if (!t->header && !o->lat_col)
        lat = t->ncols >= 2 ? 1 : -1;
    if (lon < 0 || lat < 0 || lon == lat)
        return view_fail(why, "%s line %lu: no %s column (%s; or give --lon-col and --lat-col)",
                         in_name, line, lon < 0 ? "longitude/x" : "latitude/y",
                         t->header ? "name it lon, lng, longitude or x, and lat, latitude or y"
                                   : "a line without header has x then y");
    t->lon = (size_t)lon, t->lat = (size_t)lat;
    if (o->id_col && (t->id = find_column(t, o->id_col, NULL, NULL)) < 0)
        return view_fail(why, "%s line %lu: --id-col %s: no such column", in_name, line, o->id_col);
    if (!o->id_col && t->header)
        t->id = find_column(t, NULL, id_names, NULL);
    /* degrees: --lonlat, or coordinate columns named as longitude/latitude */
    t->lonlat = o->lonlat || (t->header && name_is(t->names[t->lon], lon_names) &&
                              name_is(t->names[t->lat], lat_names));
    return VIEW_OK;
}
