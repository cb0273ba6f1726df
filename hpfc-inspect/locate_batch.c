/*
 * locate_batch.c: --locate-batch POINTS (locate.h): one answer a data line
 * of the table, in JSON lines, CSV or GeoJSON, the faces numbered once.
 */
#include "locate.h"

#include <stdlib.h>
#include <string.h>
#include <sys/types.h>

#include "escape.h"
#include "grow.h"
#include "jsonw.h"
#include "locator.h"
#include "points_table.h"

/* ---- output rows ---- */

typedef struct batch_row {
    unsigned long line;
    const char *id;            /* NULL: no id column */
    const table_fields *fl;          /* the line's fields (NULL for none) */
    const decimal *ll, *xy;    /* NULL when the line gave no point */
    const char *error;         /* NULL for an answer */
} batch_row;

static int is_extra(const table_layout *t, size_t k)
{
    return k != t->lon && k != t->lat && (long)k != t->id;
}

/* The row's answer fields (interfaces §4) into an open JSON object. */
static void json_answer(jsonw *w, const locator *L, const batch_row *row, const answer *a)
{
    if (row->ll) {
        json_decimal(w, "lon", &row->ll[0]);
        json_decimal(w, "lat", &row->ll[1]);
    }
    if (row->xy) {
        json_decimal(w, "x", &row->xy[0]);
        json_decimal(w, "y", &row->xy[1]);
    }
    if (row->error) {
        jsonw_string(w, "error", row->error);
        return;
    }
    if (a->inside) {
        jsonw_string(w, "pixel", a->path);
        jsonw_u64(w, "depth", a->px.depth);
        jsonw_bool(w, "private", a->is_private);
    } else {
        jsonw_null(w, "pixel");
        jsonw_null(w, "depth");
        jsonw_null(w, "private");
    }
    json_exact(w, L, a);
    jsonw_array_begin(w, "faces");
    for (size_t k = 0; k < a->nfaces; k++)
        jsonw_u64(w, NULL, L->cand[k]);
    jsonw_array_end(w);
    jsonw_array_begin(w, "features");
    for (size_t k = 0; k < a->nfeat; k++)
        json_feature(w, L, L->feat[k]);
    jsonw_array_end(w);
    json_along(w, L, a);
    if (a->inside)
        jsonw_string(w, "word", a->word);
    jsonw_bool(w, "inside", a->inside);
}

static void json_row_head(jsonw *w, const batch_row *row)
{
    jsonw_u64(w, "line", row->line);
    if (row->id)
        jsonw_string(w, "id", row->id);
    else
        jsonw_null(w, "id");
}

/* The columns passed through, as "columns": {name: value}. */
static void json_columns(jsonw *w, const table_layout *t, const batch_row *row, const char *key)
{
    jsonw_object_begin(w, key);
    for (size_t k = 0; row->fl && k < t->ncols; k++)
        if (is_extra(t, k))
            jsonw_string(w, t->names[k], k < row->fl->n ? row->fl->v[k] : "");
    jsonw_object_end(w);
}

static void print_jsonl_row(FILE *out, const locator *L, const table_layout *t, const batch_row *row,
                            const answer *a)
{
    jsonw w;
    jsonw_init(&w, out);
    jsonw_object_begin(&w, NULL);
    json_row_head(&w, row);
    json_answer(&w, L, row, a);
    if (t->ncols > 2 + (t->id >= 0))
        json_columns(&w, t, row, "columns");
    jsonw_object_end(&w);
    jsonw_finish(&w);
}

/* GeoJSON: a Point at (lon, lat) for degrees (RFC 7946), else at the
 * file's (x, y); an error row has no geometry. */
static void print_geojson_row(FILE *out, const locator *L, const table_layout *t, const batch_row *row,
                              const answer *a, int first)
{
    jsonw w;
    if (!first)
        fputs(",\n", out);
    jsonw_init(&w, out);
    jsonw_object_begin(&w, NULL);
    jsonw_string(&w, "type", "Feature");
    const decimal *p = row->ll ? row->ll : row->xy;
    if (p && !row->error) {
        jsonw_object_begin(&w, "geometry");
        jsonw_string(&w, "type", "Point");
        jsonw_array_begin(&w, "coordinates");
        json_decimal(&w, NULL, &p[0]);
        json_decimal(&w, NULL, &p[1]);
        jsonw_array_end(&w);
        jsonw_object_end(&w);
    } else
        jsonw_null(&w, "geometry");
    jsonw_object_begin(&w, "properties");
    json_row_head(&w, row);
    json_answer(&w, L, row, a);
    for (size_t k = 0; row->fl && k < t->ncols; k++)
        if (is_extra(t, k))
            jsonw_string(&w, t->names[k], k < row->fl->n ? row->fl->v[k] : "");
    jsonw_object_end(&w);
    jsonw_object_end(&w);
}

static void print_csv_header(FILE *out, const table_layout *t)
{
    static const char *const fixed[] = {"line",  "id",      "lon",   "lat",  "x",
                                        "y",     "inside",  "pixel", "depth", "private",
                                        "exact", "on_boundary", "faces", "fids", "keys",
                                        "error"};
    int first = 1;
    for (size_t k = 0; k < sizeof fixed / sizeof fixed[0]; k++)
        if (t->lonlat || (k != 2 && k != 3))
            csv_write_field(out, fixed[k], &first);
    for (size_t k = 0; k < t->ncols; k++)
        if (is_extra(t, k))
            csv_write_field(out, t->names[k], &first);
    fputc('\n', out);
}

/* A growing text buffer for the list fields. */
typedef struct text {
    char *s;
    size_t len, cap;
} text;

static void text_add(text *b, const char *sep, const char *s, size_t n)
{
    size_t m = b->len ? strlen(sep) : 0;
    if (!array_grow((void **)&b->s, &b->cap, b->len + m + n + 1, 1))
        return; /* out of memory: the list is cut short */
    memcpy(b->s + b->len, sep, m);
    memcpy(b->s + b->len + m, s, n);
    b->len += m + n;
    b->s[b->len] = '\0';
}

/* faces (space-separated ids), fids (space-separated) and keys ('|'). */
static void csv_lists(FILE *out, const locator *L, const answer *a, int *first)
{
    text faces = {0}, fids = {0}, keys = {0};
    char buf[32];
    for (size_t k = 0; k < a->nfaces; k++) {
        snprintf(buf, sizeof buf, "%llu", (unsigned long long)L->cand[k]);
        text_add(&faces, " ", buf, strlen(buf));
    }
    for (size_t k = 0; k < a->nfeat; k++) {
        hpfc_feature ft;
        if (hpfc_file_get_feature(L->f, L->feat[k], &ft) != HPFC_OK)
            continue;
        snprintf(buf, sizeof buf, "%lld", (long long)ft.fid);
        text_add(&fids, " ", buf, strlen(buf));
        if (ft.key)
            text_add(&keys, "|", ft.key, ft.key_len);
    }
    csv_write_field(out, faces.s ? faces.s : "", first);
    csv_write_field(out, fids.s ? fids.s : "", first);
    csv_write_field(out, keys.s ? keys.s : "", first);
    free(faces.s);
    free(fids.s);
    free(keys.s);
}

static void print_csv_row(FILE *out, const locator *L, const table_layout *t, const batch_row *row,
                          const answer *a)
{
    char buf[64];
    int first = 1;
    snprintf(buf, sizeof buf, "%lu", row->line);
    csv_write_field(out, buf, &first);
    csv_write_field(out, row->id ? row->id : "", &first);
    for (int k = t->lonlat ? 0 : 2; k < 4; k++) {
        const decimal *d = k < 2 ? row->ll : row->xy;
        if (d)
            snprintf(buf, sizeof buf, "%.*f", decimal_fraction_digits(&d[k % 2]), d[k % 2].value);
        csv_write_field(out, d ? buf : "", &first);
    }
    if (row->error) {
        for (int k = 0; k < 9; k++)
            csv_write_field(out, "", &first);
        csv_write_field(out, row->error, &first);
    } else {
        csv_write_field(out, a->inside ? "true" : "false", &first);
        snprintf(buf, sizeof buf, "%u", a->px.depth);
        csv_write_field(out, a->inside ? a->path : "", &first);
        csv_write_field(out, a->inside ? buf : "", &first);
        csv_write_field(out, !a->inside ? "" : a->is_private ? "true" : "false", &first);
        csv_write_field(out, L->exact ? "true" : "false", &first);
        csv_write_field(out, a->exact && a->loc.on_boundary ? "true" : "false", &first);
        csv_lists(out, L, a, &first);
        csv_write_field(out, "", &first);
    }
    for (size_t k = 0; k < t->ncols; k++)
        if (is_extra(t, k))
            csv_write_field(out, row->fl && k < row->fl->n ? row->fl->v[k] : "", &first);
    fputc('\n', out);
}

static void print_row(FILE *out, const batch_options *o, const locator *L, const table_layout *t,
                      const batch_row *row, const answer *a, unsigned long *rows)
{
    if (o->format == BATCH_CSV)
        print_csv_row(out, L, t, row, a);
    else if (o->format == BATCH_GEOJSON)
        print_geojson_row(out, L, t, row, a, *rows == 0);
    else
        print_jsonl_row(out, L, t, row, a);
    ++*rows;
}

/* The point of one data line, or the reason it has none (in err). */
static int read_point(locator *L, const table_layout *t, const table_fields *fl, decimal ll[2],
                      decimal xy[2], char *err)
{
    size_t need = (t->lon > t->lat ? t->lon : t->lat) + 1;
    if (fl->n < need)
        return view_fail(err, "expected at least %zu columns, found %zu", need, fl->n);
    const char *v[2] = {fl->v[t->lon], fl->v[t->lat]};
    decimal *d = t->lonlat ? ll : xy;
    for (int k = 0; k < 2; k++)
        if (decimal_parse(v[k], strlen(v[k]), &d[k]))
            return view_fail(err, "column '%.40s': '%.40s' is not a decimal number",
                             t->names[k ? t->lat : t->lon], v[k]);
    return t->lonlat ? project_lonlat(L, ll, xy, err) : VIEW_OK;
}

int view_locate_batch(const hpfc_file *f, FILE *in, const char *in_name, const batch_options *o,
                      FILE *out, char *why)
{
    locator L;
    answer a = {0};
    table_layout t = {0};
    table_fields fl = {0};
    char *line = NULL;
    size_t line_cap = 0;
    unsigned long n = 0, rows = 0;
    int status = VIEW_OK, ready = 0;
    memset(&L, 0, sizeof L);
    ssize_t got;
    while (!status && (got = getline(&line, &line_cap, in)) >= 0) {
        n++;
        line[strcspn(line, "\r\n")] = '\0';
        if (table_blank_line(line))
            continue;
        char sep = ready ? t.sep : table_guess_separator(line);
        if (table_split_fields(line, sep, &fl)) {
            status = view_fail(why, "out of memory");
            break;
        }
        if (!ready) {
            /* the first line sets the layout; the locator opens once it
             * knows whether the points are degrees */
            ready = 1;
            if ((status = table_layout_read(&t, &fl, sep, o, in_name, n, why)) ||
                (status = locator_open(f, t.lonlat, &L, why)))
                break;
            if (o->format == BATCH_CSV)
                print_csv_header(out, &t);
            else if (o->format == BATCH_GEOJSON)
                fputs("{\"type\": \"FeatureCollection\", \"features\": [\n", out);
            if (t.header)
                continue;
        }
        decimal ll[2], xy[2];
        char err[VIEW_WHY];
        batch_row row = {.line = n, .fl = &fl};
        row.id = t.id >= 0 && (size_t)t.id < fl.n ? fl.v[t.id] : NULL;
        if (read_point(&L, &t, &fl, ll, xy, err)) {
            row.error = err;
            row.ll = t.lonlat && fl.n > (t.lon > t.lat ? t.lon : t.lat) &&
                             table_is_number(fl.v[t.lon]) && table_is_number(fl.v[t.lat])
                         ? ll
                         : NULL;
            print_row(out, o, &L, &t, &row, &a, &rows);
            continue;
        }
        row.ll = t.lonlat ? ll : NULL;
        row.xy = xy;
        int st = locate_decimal(&L, xy, &a);
        if (st) {
            status = view_fail(why, "%s line %lu: locate: %s", in_name, n, hpfc_strerror(st));
            break;
        }
        print_row(out, o, &L, &t, &row, &a, &rows);
    }
    if (!status && ferror(in))
        status = view_fail(why, "%s: read error", in_name);
    if (!status && !ready && (status = locator_open(f, 0, &L, why)) == VIEW_OK &&
        o->format == BATCH_CSV) /* no points: the CSV still gets its header */
        print_csv_header(out, &t);
    if (!status && o->format == BATCH_GEOJSON)
        fputs(ready ? "\n]}\n" : "{\"type\": \"FeatureCollection\", \"features\": []}\n", out);
    free(line);
    free(fl.v);
    free(a.word);
    table_layout_free(&t);
    locator_close(&L);
    return status;
}
