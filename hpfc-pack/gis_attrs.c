/*
 * Attributes of GIS features (gis_attrs.h). Values are kept sparse while
 * reading (a row of entries per feature), then laid out as a dense table
 * converted to each column's final type.
 */
#include "gis_attrs.h"

#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "grow.h"

typedef struct entry {
    uint32_t row, column;
    int type;
    int64_t i;
    double r;
    size_t s; /* offset in text */
} entry;

struct gis_attrs {
    char **name;
    uint8_t *type;
    size_t columns, cap_columns, cap_types;
    entry *e;
    size_t n, cap;
    char *text; /* the strings, NUL-terminated */
    size_t text_len, cap_text;
    uint32_t rows;
    /* the table */
    hpfc_attr_value *cells;
    char *converted; /* numbers written as strings */
    const char **names;
};

gis_attrs *gis_attrs_create(void)
{
    return calloc(1, sizeof(gis_attrs));
}

static void free_table(gis_attrs *a)
{
    free(a->cells);
    free(a->converted);
    free(a->names);
    a->cells = NULL, a->converted = NULL, a->names = NULL;
}

void gis_attrs_free(gis_attrs *a)
{
    if (!a)
        return;
    for (size_t c = 0; c < a->columns; c++)
        free(a->name[c]);
    free(a->name);
    free(a->type);
    free(a->e);
    free(a->text);
    free_table(a);
    free(a);
}

static int widen(int have, int got)
{
    if (have == got)
        return have;
    if ((have == HPFC_ATTR_INTEGER || have == HPFC_ATTR_REAL) &&
        (got == HPFC_ATTR_INTEGER || got == HPFC_ATTR_REAL))
        return HPFC_ATTR_REAL;
    return HPFC_ATTR_STRING;
}

long gis_attrs_column(gis_attrs *a, const char *name, int type)
{
    for (size_t c = 0; c < a->columns; c++)
        if (strcmp(a->name[c], name) == 0) {
            a->type[c] = (uint8_t)widen(a->type[c], type);
            return (long)c;
        }
    if (a->columns >= UINT32_MAX / 2 ||
        !array_grow((void **)&a->name, &a->cap_columns, a->columns + 1, sizeof *a->name) ||
        !array_grow((void **)&a->type, &a->cap_types, a->columns + 1, sizeof *a->type) ||
        !(a->name[a->columns] = strdup(name)))
        return -1;
    a->type[a->columns] = (uint8_t)type;
    return (long)a->columns++;
}

int gis_attrs_row(gis_attrs *a)
{
    if (a->rows == UINT32_MAX)
        return -1;
    a->rows++;
    return 0;
}

uint32_t gis_attrs_rows(const gis_attrs *a)
{
    return a->rows;
}

static entry *push(gis_attrs *a, uint32_t column, int type)
{
    if (!a->rows || column >= a->columns ||
        !array_grow((void **)&a->e, &a->cap, a->n + 1, sizeof *a->e))
        return NULL;
    entry *e = &a->e[a->n++];
    memset(e, 0, sizeof *e);
    e->row = a->rows - 1, e->column = column, e->type = type;
    return e;
}

int gis_attrs_set_integer(gis_attrs *a, uint32_t column, int64_t v)
{
    entry *e = push(a, column, HPFC_ATTR_INTEGER);
    if (e)
        e->i = v;
    return e ? 0 : -1;
}

int gis_attrs_set_real(gis_attrs *a, uint32_t column, double v)
{
    entry *e = push(a, column, HPFC_ATTR_REAL);
    if (e)
        e->r = v;
    return e ? 0 : -1;
}

int gis_attrs_set_string(gis_attrs *a, uint32_t column, const char *s)
{
    size_t len = strlen(s);
    if (!array_grow((void **)&a->text, &a->cap_text, a->text_len + len + 1, 1))
        return -1;
    entry *e = push(a, column, HPFC_ATTR_STRING);
    if (!e)
        return -1;
    e->s = a->text_len;
    memcpy(a->text + a->text_len, s, len + 1);
    a->text_len += len + 1;
    return 0;
}

/* A number as text for a string column: shortest exact form of a real. */
static int number_text(const entry *e, char *buf, size_t n)
{
    if (e->type == HPFC_ATTR_INTEGER)
        return snprintf(buf, n, "%" PRId64, e->i);
    for (int digits = 15; digits <= 17; digits++) {
        int len = snprintf(buf, n, "%.*g", digits, e->r);
        if (digits == 17 || strtod(buf, NULL) == e->r)
            return len;
    }
    return 0;
}

int gis_attrs_table(gis_attrs *a, hpfc_attr_table *out)
{
    free_table(a);
    uint64_t cells = (uint64_t)a->rows * a->columns;
    if (cells > SIZE_MAX / sizeof *a->cells)
        return -1;
    a->cells = calloc(cells ? (size_t)cells : 1, sizeof *a->cells);
    a->names = malloc((a->columns ? a->columns : 1) * sizeof *a->names);
    size_t numbers = 0; /* numbers in string columns */
    for (size_t k = 0; k < a->n; k++)
        numbers += a->e[k].type != HPFC_ATTR_STRING && a->type[a->e[k].column] == HPFC_ATTR_STRING;
    enum { NUMBER_TEXT = 32 };
    a->converted = malloc(numbers ? numbers * NUMBER_TEXT : 1);
    if (!a->cells || !a->names || !a->converted) {
        free_table(a);
        return -1;
    }
    for (size_t c = 0; c < a->columns; c++)
        a->names[c] = a->name[c];
    size_t used = 0;
    for (size_t k = 0; k < a->n; k++) {
        const entry *e = &a->e[k];
        int type = a->type[e->column];
        hpfc_attr_value *v = &a->cells[(size_t)e->row * a->columns + e->column];
        v->type = type;
        if (type == HPFC_ATTR_INTEGER) {
            v->i = e->i;
        } else if (type == HPFC_ATTR_REAL) {
            v->r = e->type == HPFC_ATTR_INTEGER ? (double)e->i : e->r;
        } else if (e->type == HPFC_ATTR_STRING) {
            v->s = a->text + e->s;
            v->len = strlen(v->s);
        } else {
            char *buf = a->converted + used * NUMBER_TEXT;
            int len = number_text(e, buf, NUMBER_TEXT);
            v->s = buf;
            v->len = len > 0 ? (size_t)len : 0;
            used++;
        }
    }
    *out = (hpfc_attr_table){.feature_count = a->rows, .column_count = (uint32_t)a->columns,
                             .name = a->names, .type = a->type, .cells = a->cells};
    return 0;
}
