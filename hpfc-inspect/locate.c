/*
 * Point queries (contracts §4): --locate X,Y, --locate-lonlat LON,LAT and
 * --locate-batch POINTS.
 *
 * A file with exact geometry (GEOM and LABL sections, format 1.2) answers
 * each point exactly (hpfc_locate_point): the one face holding it, or the
 * faces around it when it lies on an edge or a vertex ("on_boundary"),
 * "exact": true. Other files are answered by one descent (hpfc_locate)
 * and the faces of the leaf it reaches: exactly one in a private leaf,
 * the candidates (every face meeting the leaf) in a stabbed one,
 * "exact": false. A file with a LABL
 * section stores those faces (hpfc_label_leaf_faces reads the leaf's
 * record: the pixels of one descent, nothing else); a file without one
 * (format 1.0, 1.1, hpfc-pack --no-labels) has its faces numbered once
 * first (hpfc_faces_build, O(file)). With a FEAT section each face brings
 * its source features.
 */
#include "locate.h"

#include "attrs_json.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/types.h>

#include "jsonw.h"
#include "projection.h"
#include "roads.h"

#define PATH_TEXT 1200

/* ---- the locator ------------------------------------------------------------- */

typedef struct locator {
    const hpfc_file *f;
    hpfc_file_info info;
    hpfc_faces *faces;       /* NULL when the file stores its labels */
    int labels;              /* the file has a LABL section */
    int exact;               /* and a GEOM section: hpfc_locate_point answers */
    int features;            /* the file has a FEAT section */
    hpfc_features_info fi;
    uint64_t *cand;          /* candidate faces of one leaf */
    size_t cap;
    hpfc_id *feat;           /* features of the candidates */
    size_t feat_cap;
    int edge_features;       /* LABL and EDGF: the leaf's edges name their features */
    hpfc_id *along;          /* features of the located leaf's edges */
    size_t along_cap;
    mapproj_plan *plan;      /* --lonlat: the file's projection */
} locator;

/* The answer for one point. */
typedef struct answer {
    int inside;
    hpfc_pixel px;
    char path[PATH_TEXT];
    int is_private;
    char *word;
    size_t nfaces, nfeat;
    size_t nalong;           /* features whose lines or rings cross the leaf */
    int exact;               /* faces is the exact answer (else candidates) */
    hpfc_point_location loc; /* exact: on_boundary, vertex or edge */
} answer;

static void locator_close(locator *L)
{
    hpfc_faces_free(L->faces);
    free(L->cand);
    free(L->feat);
    free(L->along);
    if (L->plan)
        mapproj_free(L->plan);
}

/* The projection the file's CRS section records, for lon/lat points. */
static int open_projection(locator *L, char *why)
{
    if (!L->info.crs)
        return view_fail(why, "the file records no CRS, so no (lon, lat) can be placed in it");
    char reason[200];
    L->plan = mapproj_from_text(L->info.crs, L->info.crs_len, reason, sizeof reason);
    if (!L->plan)
        return view_fail(why, "cannot place (lon, lat) points: %s (use --locate X,Y)", reason);
    return VIEW_OK;
}

static int locator_open(const hpfc_file *f, int lonlat, locator *L, char *why)
{
    memset(L, 0, sizeof *L);
    L->f = f;
    hpfc_file_get_info(f, &L->info);
    if (lonlat && open_projection(L, why))
        return VIEW_FAIL;
    hpfc_labels_info li;
    uint64_t faces;
    int st = hpfc_file_get_labels(f, &li);
    if (st == HPFC_OK) {
        L->labels = 1;
        faces = li.faces;
    } else if (st != HPFC_E_NO_SECTION) {
        return view_fail(why, "labels: %s", hpfc_strerror(st));
    } else if ((st = hpfc_faces_build(f, &L->faces))) {
        return view_fail(why, "faces: %s", hpfc_strerror(st));
    } else {
        faces = hpfc_faces_face_count(L->faces);
    }
    st = hpfc_file_get_features(f, &L->fi);
    if (st == HPFC_OK) {
        if (L->fi.faces != faces)
            return view_fail(why, "features: the FEAT section lists %u faces, the map has %llu",
                             L->fi.faces, (unsigned long long)faces);
        L->features = 1;
    } else if (st != HPFC_E_NO_SECTION)
        return view_fail(why, "features: %s", hpfc_strerror(st));
    hpfc_geometry_info gi;
    st = L->labels ? hpfc_file_get_geometry(f, &gi) : HPFC_E_NO_SECTION;
    if (st == HPFC_OK)
        L->exact = 1;
    else if (st != HPFC_E_NO_SECTION)
        return view_fail(why, "geometry: %s", hpfc_strerror(st));
    hpfc_edge_links_info ei;
    L->edge_features = L->features && L->labels && hpfc_file_get_edge_links(f, &ei) == HPFC_OK;
    return VIEW_OK;
}

/* Room for n candidate faces. */
static int reserve(void **p, size_t *cap, size_t n, size_t size)
{
    if (n <= *cap)
        return 0;
    void *q = realloc(*p, n * size);
    if (!q)
        return -1;
    *p = q;
    *cap = n;
    return 0;
}

static int cmp_id(const void *a, const void *b)
{
    hpfc_id x = *(const hpfc_id *)a, y = *(const hpfc_id *)b;
    return (x > y) - (x < y);
}

/* Sorts v[0 .. n) and drops repeats; returns the new length. */
static size_t sort_unique_ids(hpfc_id *v, size_t n)
{
    if (n > 1)
        qsort(v, n, sizeof *v, cmp_id);
    size_t u = 0;
    for (size_t k = 0; k < n; k++)
        if (u == 0 || v[u - 1] != v[k])
            v[u++] = v[k];
    return u;
}

/* The features of the candidate faces, each once, ascending. */
static int gather_features(locator *L, answer *a)
{
    a->nfeat = 0;
    if (!L->features)
        return HPFC_OK;
    for (size_t k = 0; k < a->nfaces; k++) {
        uint32_t count;
        int st = hpfc_face_feature_count(L->f, L->cand[k], &count);
        if (!st && reserve((void **)&L->feat, &L->feat_cap, a->nfeat + count, sizeof *L->feat))
            st = HPFC_E_NOMEM;
        for (uint32_t i = 0; i < count && !st; i++)
            st = hpfc_face_feature_id(L->f, L->cand[k], i, &L->feat[a->nfeat++]);
        if (st)
            return st;
    }
    a->nfeat = sort_unique_ids(L->feat, a->nfeat);
    return HPFC_OK;
}

/* The features of the edges that cross a stabbed leaf (EDGF, by the edge
 * ids of its LABL record): a line layer's river next to the point, or the
 * borders it lies near. */
static int gather_along(locator *L, answer *a)
{
    a->nalong = 0;
    if (!L->edge_features || a->is_private)
        return HPFC_OK;
    size_t crossings = strlen(a->word) - 4; /* a word of c crossings has c + 4 symbols */
    for (size_t k = 0; k < crossings; k++) {
        hpfc_id edge;
        uint32_t count = 0; /* read by the loop below even after a failed call */
        int st = hpfc_label_crossing_edge(L->f, &a->px, (uint32_t)k, &edge);
        if (!st)
            st = hpfc_edge_feature_count(L->f, edge, &count);
        if (!st && reserve((void **)&L->along, &L->along_cap, a->nalong + count, sizeof *L->along))
            st = HPFC_E_NOMEM;
        for (uint32_t i = 0; i < count && !st; i++)
            st = hpfc_edge_feature_id(L->f, edge, i, &L->along[a->nalong++]);
        if (st)
            return st;
    }
    a->nalong = sort_unique_ids(L->along, a->nalong);
    return HPFC_OK;
}

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

/* The faces of the located leaf's regions, from its LABL record, each once,
 * ascending (as view_pixel_faces gives them). */
static int stored_faces(locator *L, answer *a)
{
    size_t n = 0;
    int st = hpfc_label_leaf_faces(L->f, &a->px, L->cand, L->cap, &n);
    if (st)
        return st;
    qsort(L->cand, n, sizeof *L->cand, cmp_u64);
    size_t u = 0;
    for (size_t k = 0; k < n; k++)
        if (u == 0 || L->cand[u - 1] != L->cand[k])
            L->cand[u++] = L->cand[k];
    a->nfaces = u;
    return HPFC_OK;
}

/* The exact answer (hpfc_locate_point): one face, or the faces around a
 * point on an edge or a vertex, ascending. */
static int exact_faces(locator *L, int64_t x, int64_t y, answer *a)
{
    size_t n = 0;
    int st = hpfc_locate_point(L->f, x, y, &a->loc, L->cand, L->cap, &n);
    if (st == HPFC_E_BUFFER_SMALL) {
        if (reserve((void **)&L->cand, &L->cap, n, sizeof *L->cand))
            return HPFC_E_NOMEM;
        st = hpfc_locate_point(L->f, x, y, &a->loc, L->cand, L->cap, &n);
    }
    a->nfaces = n;
    a->exact = 1;
    return st;
}

/* Answers the lattice point (x, y). */
static int locate_lattice(locator *L, int64_t x, int64_t y, answer *a)
{
    free(a->word);
    memset(a, 0, sizeof *a);
    int st = hpfc_locate(L->f, x, y, &a->px);
    if (st == HPFC_E_NO_PIXEL)
        return HPFC_OK; /* outside the domain: no face */
    size_t len = 0;
    if (!st)
        st = hpfc_pixel_is_private(L->f, &a->px, &a->is_private);
    if (!st)
        st = hpfc_pixel_word(L->f, &a->px, NULL, 0, &len);
    if (st)
        return st;
    a->inside = 1;
    pixel_path_text(&a->px, a->path, sizeof a->path);
    if (!(a->word = malloc(len + 1)) ||
        reserve((void **)&L->cand, &L->cap, len > 4 ? len - 4 : 1, sizeof *L->cand))
        return HPFC_E_NOMEM;
    if ((st = hpfc_pixel_word(L->f, &a->px, a->word, len + 1, &len)))
        return st;
    a->word[len] = '\0';
    if (L->exact)
        st = exact_faces(L, x, y, a);
    else if (L->labels)
        st = stored_faces(L, a);
    else
        st = view_pixel_faces(L->f, L->faces, &a->px, L->cand, L->cap, &a->nfaces);
    if (!st)
        st = gather_features(L, a);
    return st ? st : gather_along(L, a);
}

/* Answers a point given in user coordinates. */
static int locate_decimal(locator *L, const decimal xy[2], answer *a)
{
    int64_t x, y;
    if (decimal_floor_lattice(&xy[0], L->info.unit_exp10, &x) ||
        decimal_floor_lattice(&xy[1], L->info.unit_exp10, &y)) {
        free(a->word);
        memset(a, 0, sizeof *a);
        return HPFC_OK; /* beyond any int64 lattice: outside every domain */
    }
    return locate_lattice(L, x, y, a);
}

/* Projects (lon, lat) into user coordinates, kept as exact decimals of
 * the projected doubles. */
static int project_lonlat(const locator *L, const decimal ll[2], decimal xy[2], char *why)
{
    double x, y;
    char text[2][40];
    if (ll[0].value < -180 || ll[0].value > 180 || ll[1].value < -90 || ll[1].value > 90)
        return view_fail(why, "(%g, %g) is not a longitude and latitude in degrees", ll[0].value,
                         ll[1].value);
    if (mapproj_forward(L->plan, ll[0].value, ll[1].value, &x, &y) != 0)
        return view_fail(why, "(%g, %g) cannot be projected with the file's CRS", ll[0].value,
                         ll[1].value);
    snprintf(text[0], sizeof text[0], "%.17g", x);
    snprintf(text[1], sizeof text[1], "%.17g", y);
    if (decimal_parse(text[0], strlen(text[0]), &xy[0]) ||
        decimal_parse(text[1], strlen(text[1]), &xy[1]))
        return view_fail(why, "(%g, %g) projects to no finite point", ll[0].value, ll[1].value);
    return VIEW_OK;
}

/* ---- printing ------------------------------------------------------------------- */

static void json_decimal(jsonw *w, const char *key, const decimal *d)
{
    jsonw_double(w, key, d->value, decimal_fraction_digits(d));
}

static void json_feature(jsonw *w, const locator *L, hpfc_id index)
{
    hpfc_feature ft;
    const char *layer;
    size_t layer_len;
    jsonw_object_begin(w, NULL);
    if (hpfc_file_get_feature(L->f, index, &ft) == HPFC_OK) {
        jsonw_i64(w, "fid", ft.fid);
        if (L->fi.key_field && ft.key)
            jsonw_string_n(w, "key", ft.key, ft.key_len);
        else if (L->fi.key_field)
            jsonw_null(w, "key");
        if (hpfc_layer_name(L->f, ft.layer, &layer, &layer_len) == HPFC_OK)
            jsonw_string_n(w, "layer", layer, layer_len);
        json_feature_attributes(w, L->f, index);
    }
    jsonw_object_end(w);
}

/* "along": the features of the edges crossing the located leaf (files with
 * LABL and EDGF only), each as in "features". */
static void json_along(jsonw *w, const locator *L, const answer *a)
{
    if (!L->edge_features || !a->inside)
        return;
    jsonw_array_begin(w, "along");
    for (size_t k = 0; k < a->nalong; k++)
        json_feature(w, L, L->along[k]);
    jsonw_array_end(w);
}

/* "exact" (the file's geometry decided the face), "on_boundary" (the
 * point lies on an edge or a vertex: faces are those around it; false for
 * an answer that is not exact, which cannot tell) and, on the boundary,
 * the "vertex" or "edge" it lies on (input graph ids). */
static void json_exact(jsonw *w, const locator *L, const answer *a)
{
    jsonw_bool(w, "exact", L->exact);
    jsonw_bool(w, "on_boundary", a->exact && a->loc.on_boundary);
    if (a->exact && a->loc.on_vertex)
        jsonw_u64(w, "vertex", a->loc.vertex);
    else if (a->exact && a->loc.on_boundary)
        jsonw_u64(w, "edge", a->loc.edge);
}

/* One answer as the JSON object of contracts §4. ll: the lon/lat asked
 * for (NULL for a plain point). */
static void print_json(FILE *out, const locator *L, const decimal *ll, const decimal xy[2],
                       const answer *a)
{
    jsonw w;
    jsonw_init(&w, out);
    jsonw_object_begin(&w, NULL);
    if (ll) {
        json_decimal(&w, "lon", &ll[0]);
        json_decimal(&w, "lat", &ll[1]);
    }
    json_decimal(&w, "x", &xy[0]);
    json_decimal(&w, "y", &xy[1]);
    if (a->inside) {
        jsonw_string(&w, "pixel", a->path);
        jsonw_u64(&w, "depth", a->px.depth);
        jsonw_bool(&w, "private", a->is_private);
    } else {
        jsonw_null(&w, "pixel");
        jsonw_null(&w, "depth");
        jsonw_null(&w, "private");
    }
    json_exact(&w, L, a);
    jsonw_array_begin(&w, "faces");
    for (size_t k = 0; k < a->nfaces; k++)
        jsonw_u64(&w, NULL, L->cand[k]);
    jsonw_array_end(&w);
    jsonw_array_begin(&w, "features");
    for (size_t k = 0; k < a->nfeat; k++)
        json_feature(&w, L, L->feat[k]);
    jsonw_array_end(&w);
    json_along(&w, L, a);
    if (a->inside)
        jsonw_string(&w, "word", a->word);
    jsonw_bool(&w, "inside", a->inside);
    jsonw_object_end(&w);
    jsonw_finish(&w);
}

static void print_feature_text(FILE *out, const locator *L, hpfc_id index)
{
    hpfc_feature ft;
    const char *layer = "";
    size_t layer_len = 0;
    if (hpfc_file_get_feature(L->f, index, &ft) != HPFC_OK)
        return;
    hpfc_layer_name(L->f, ft.layer, &layer, &layer_len);
    fprintf(out, "            fid %lld in layer '%.*s'", (long long)ft.fid, (int)layer_len, layer);
    if (ft.key)
        fprintf(out, ", %.*s '%.*s'", (int)L->fi.key_field_len, L->fi.key_field, (int)ft.key_len,
                ft.key);
    fputc('\n', out);
}

static void print_text(FILE *out, const locator *L, const decimal *ll, const decimal xy[2],
                       const answer *a)
{
    if (ll)
        fprintf(out, "lon, lat    %.*f, %.*f\n", decimal_fraction_digits(&ll[0]), ll[0].value,
                decimal_fraction_digits(&ll[1]), ll[1].value);
    fprintf(out, "point       %.*f, %.*f\n", decimal_fraction_digits(&xy[0]), xy[0].value,
            decimal_fraction_digits(&xy[1]), xy[1].value);
    if (!a->inside) {
        fprintf(out, "pixel       none: outside the domain\nfaces       none\n");
        return;
    }
    fprintf(out, "pixel       %s (depth %u)\n", a->path, a->px.depth);
    fprintf(out, "word        %s (%s)\n", a->word, a->is_private ? "private" : "stabbed");
    fprintf(out, "%s", a->nfaces == 1 ? "face        " : "faces       ");
    for (size_t k = 0; k < a->nfaces; k++)
        fprintf(out, "%s%llu", k ? " " : "", (unsigned long long)L->cand[k]);
    if (a->exact && a->loc.on_vertex)
        fprintf(out, " (on the boundary: the faces around vertex %llu)\n",
                (unsigned long long)a->loc.vertex);
    else if (a->exact && a->loc.on_boundary)
        fprintf(out, " (on the boundary: the faces beside edge %llu)\n",
                (unsigned long long)a->loc.edge);
    else
        fprintf(out, a->exact || a->is_private
                         ? " (the point's face)\n"
                         : " (candidates: the faces that meet the pixel; the file has no exact "
                           "geometry)\n");
    if (!L->features) {
        fprintf(out, "features    none (the file has no GIS features)\n");
        return;
    }
    if (a->nfeat == 0)
        fprintf(out, "features    none (outside every feature)\n");
    else
        fprintf(out, "features    %zu\n", a->nfeat);
    for (size_t k = 0; k < a->nfeat; k++)
        print_feature_text(out, L, L->feat[k]);
    if (!L->edge_features || a->is_private)
        return;
    fprintf(out, "along       %zu%s\n", a->nalong,
            a->nalong ? " (features whose lines or rings cross the pixel)" : "");
    for (size_t k = 0; k < a->nalong; k++)
        print_feature_text(out, L, L->along[k]);
}

/* ---- entry points ------------------------------------------------------------------ */

static int answer_one(const hpfc_file *f, const decimal *ll, const decimal *given, FILE *out,
                      int json, char *why)
{
    locator L;
    answer a = {0};
    decimal xy[2];
    int status = locator_open(f, ll != NULL, &L, why);
    if (!status && ll)
        status = project_lonlat(&L, ll, xy, why);
    else if (!status)
        memcpy(xy, given, sizeof xy);
    int st = status ? HPFC_OK : locate_decimal(&L, xy, &a);
    if (st)
        status = view_fail(why, "locate: %s", hpfc_strerror(st));
    else if (!status && json)
        print_json(out, &L, ll, xy, &a);
    else if (!status)
        print_text(out, &L, ll, xy, &a);
    free(a.word);
    locator_close(&L);
    return status;
}

int view_locate(const hpfc_file *f, const decimal xy[2], FILE *out, int json, char *why)
{
    return answer_one(f, NULL, xy, out, json, why);
}

int view_locate_lonlat(const hpfc_file *f, const decimal lonlat[2], FILE *out, int json,
                       char *why)
{
    return answer_one(f, lonlat, NULL, out, json, why);
}

/* ---- --locate-batch ------------------------------------------------------------------ */

/* The fields of one line of POINTS, pointing into the line (which the
 * split rewrites in place). */
typedef struct fields {
    char **v;
    size_t n, cap;
} fields;

/* One line of POINTS without its end: blank or '#' lines are skipped. */
static int blank_line(const char *s)
{
    s += strspn(s, " \t\r");
    return *s == '\0' || *s == '#';
}

/* The separator of POINTS, from its first line: a tab, else a comma, else
 * a semicolon, else runs of blanks (' '). */
static char guess_separator(const char *line)
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
static int split_fields(char *line, char sep, fields *fl)
{
    const char *blanks = sep == '\t' ? " " : " \t";
    char *p = line;
    fl->n = 0;
    if (sep == ' ' && !*(p += strspn(p, blanks)))
        return 0;
    for (;;) {
        if (reserve((void **)&fl->v, &fl->cap, fl->n + 1, sizeof *fl->v))
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

/* How POINTS is laid out, from its first line. */
typedef struct layout {
    char sep;
    int header;
    size_t ncols;
    char **names;            /* per column: its header name, or "colN" */
    size_t lon, lat;         /* the coordinate columns */
    long id;                 /* the id column, -1 for none */
    int lonlat;              /* the coordinates are degrees */
} layout;

static void layout_free(layout *t)
{
    for (size_t k = 0; t->names && k < t->ncols; k++)
        free(t->names[k]);
    free(t->names);
}

/* The column `opt` names (a header name, any case, or a number), or the
 * first whose name is in `guess`; -1 when none. */
static long find_column(const layout *t, const char *opt, const char *const *guess,
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

static int is_number(const char *s)
{
    decimal d;
    return *s && decimal_parse(s, strlen(s), &d) == 0;
}

/* Reads the layout from the first line: a header when its coordinate
 * fields are not numbers (or when columns are named by --lon-col ...). */
static int layout_read(layout *t, const fields *fl, char sep, const batch_options *o,
                       const char *in_name, unsigned long line, char *why)
{
    memset(t, 0, sizeof *t);
    t->sep = sep;
    t->ncols = fl->n;
    t->id = -1;
    size_t lon_n = o->lon_col ? column_number(o->lon_col) : 1;
    size_t lat_n = o->lat_col ? column_number(o->lat_col) : 2;
    t->header = (o->lon_col && !lon_n) || (o->lat_col && !lat_n) || (o->id_col && !column_number(o->id_col)) ||
                (lon_n && lon_n <= fl->n && !is_number(fl->v[lon_n - 1])) ||
                (lat_n && lat_n <= fl->n && !is_number(fl->v[lat_n - 1]));
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

/* ---- output rows ---- */

typedef struct batch_row {
    unsigned long line;
    const char *id;            /* NULL: no id column */
    const fields *fl;          /* the line's fields (NULL for none) */
    const decimal *ll, *xy;    /* NULL when the line gave no point */
    const char *error;         /* NULL for an answer */
} batch_row;

static int is_extra(const layout *t, size_t k)
{
    return k != t->lon && k != t->lat && (long)k != t->id;
}

/* The row's answer fields (contracts §4) into an open JSON object. */
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
static void json_columns(jsonw *w, const layout *t, const batch_row *row, const char *key)
{
    jsonw_object_begin(w, key);
    for (size_t k = 0; row->fl && k < t->ncols; k++)
        if (is_extra(t, k))
            jsonw_string(w, t->names[k], k < row->fl->n ? row->fl->v[k] : "");
    jsonw_object_end(w);
}

static void print_jsonl_row(FILE *out, const locator *L, const layout *t, const batch_row *row,
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
static void print_geojson_row(FILE *out, const locator *L, const layout *t, const batch_row *row,
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

/* One CSV field, after a comma unless it is the line's first, quoted when
 * it holds a comma, a quote or a line end. */
static void csv_field(FILE *out, const char *s, int *first)
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

static void print_csv_header(FILE *out, const layout *t)
{
    static const char *const fixed[] = {"line",  "id",      "lon",   "lat",  "x",
                                        "y",     "inside",  "pixel", "depth", "private",
                                        "exact", "on_boundary", "faces", "fids", "keys",
                                        "error"};
    int first = 1;
    for (size_t k = 0; k < sizeof fixed / sizeof fixed[0]; k++)
        if (t->lonlat || (k != 2 && k != 3))
            csv_field(out, fixed[k], &first);
    for (size_t k = 0; k < t->ncols; k++)
        if (is_extra(t, k))
            csv_field(out, t->names[k], &first);
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
    if (reserve((void **)&b->s, &b->cap, b->len + m + n + 1, 1))
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
    csv_field(out, faces.s ? faces.s : "", first);
    csv_field(out, fids.s ? fids.s : "", first);
    csv_field(out, keys.s ? keys.s : "", first);
    free(faces.s);
    free(fids.s);
    free(keys.s);
}

static void print_csv_row(FILE *out, const locator *L, const layout *t, const batch_row *row,
                          const answer *a)
{
    char buf[64];
    int first = 1;
    snprintf(buf, sizeof buf, "%lu", row->line);
    csv_field(out, buf, &first);
    csv_field(out, row->id ? row->id : "", &first);
    for (int k = t->lonlat ? 0 : 2; k < 4; k++) {
        const decimal *d = k < 2 ? row->ll : row->xy;
        if (d)
            snprintf(buf, sizeof buf, "%.*f", decimal_fraction_digits(&d[k % 2]), d[k % 2].value);
        csv_field(out, d ? buf : "", &first);
    }
    if (row->error) {
        for (int k = 0; k < 9; k++)
            csv_field(out, "", &first);
        csv_field(out, row->error, &first);
    } else {
        csv_field(out, a->inside ? "true" : "false", &first);
        snprintf(buf, sizeof buf, "%u", a->px.depth);
        csv_field(out, a->inside ? a->path : "", &first);
        csv_field(out, a->inside ? buf : "", &first);
        csv_field(out, !a->inside ? "" : a->is_private ? "true" : "false", &first);
        csv_field(out, L->exact ? "true" : "false", &first);
        csv_field(out, a->exact && a->loc.on_boundary ? "true" : "false", &first);
        csv_lists(out, L, a, &first);
        csv_field(out, "", &first);
    }
    for (size_t k = 0; k < t->ncols; k++)
        if (is_extra(t, k))
            csv_field(out, row->fl && k < row->fl->n ? row->fl->v[k] : "", &first);
    fputc('\n', out);
}

static void print_row(FILE *out, const batch_options *o, const locator *L, const layout *t,
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
static int read_point(locator *L, const layout *t, const fields *fl, decimal ll[2],
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
    layout t = {0};
    fields fl = {0};
    char *line = NULL;
    size_t line_cap = 0;
    unsigned long n = 0, rows = 0;
    int status = VIEW_OK, ready = 0;
    memset(&L, 0, sizeof L);
    ssize_t got;
    while (!status && (got = getline(&line, &line_cap, in)) >= 0) {
        n++;
        line[strcspn(line, "\r\n")] = '\0';
        if (blank_line(line))
            continue;
        char sep = ready ? t.sep : guess_separator(line);
        if (split_fields(line, sep, &fl)) {
            status = view_fail(why, "out of memory");
            break;
        }
        if (!ready) {
            /* the first line sets the layout; the locator opens once it
             * knows whether the points are degrees */
            ready = 1;
            if ((status = layout_read(&t, &fl, sep, o, in_name, n, why)) ||
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
                             is_number(fl.v[t.lon]) && is_number(fl.v[t.lat])
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
    layout_free(&t);
    locator_close(&L);
    return status;
}
