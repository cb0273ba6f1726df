/*
 * Point queries (contracts §4): --locate X,Y, --locate-lonlat LON,LAT and
 * --locate-batch POINTS.
 *
 * A locator answers each point by one descent (hpfc_locate) and the faces
 * of the leaf it reaches: exactly one in a private leaf, the candidates
 * (every face meeting the leaf) in a stabbed one. A file with a LABL
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
    int features;            /* the file has a FEAT section */
    hpfc_features_info fi;
    uint64_t *cand;          /* candidate faces of one leaf */
    size_t cap;
    uint32_t *feat;          /* features of the candidates */
    size_t feat_cap;
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
} answer;

static void locator_close(locator *L)
{
    hpfc_faces_free(L->faces);
    free(L->cand);
    free(L->feat);
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
    int st = hpfc_file_labels(f, &li);
    if (st == HPFC_OK) {
        L->labels = 1;
        faces = li.faces;
    } else if (st != HPFC_E_NO_SECTION) {
        return view_fail(why, "labels: %s", hpfc_strerror(st));
    } else if ((st = hpfc_faces_build(f, &L->faces))) {
        return view_fail(why, "faces: %s", hpfc_strerror(st));
    } else {
        faces = hpfc_faces_count(L->faces);
    }
    st = hpfc_file_features(f, &L->fi);
    if (st == HPFC_OK) {
        if (L->fi.faces != faces)
            return view_fail(why, "features: the FEAT section lists %u faces, the map has %llu",
                             L->fi.faces, (unsigned long long)faces);
        L->features = 1;
    } else if (st != HPFC_E_NO_SECTION)
        return view_fail(why, "features: %s", hpfc_strerror(st));
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

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

/* The features of the candidate faces, each once, ascending. */
static int gather_features(locator *L, answer *a)
{
    a->nfeat = 0;
    if (!L->features)
        return HPFC_OK;
    for (size_t k = 0; k < a->nfaces; k++) {
        uint32_t count, feature;
        int st = hpfc_face_feature_count(L->f, L->cand[k], &count);
        if (!st && reserve((void **)&L->feat, &L->feat_cap, a->nfeat + count, sizeof *L->feat))
            st = HPFC_E_NOMEM;
        for (uint32_t i = 0; i < count && !st; i++)
            if (!(st = hpfc_face_feature(L->f, L->cand[k], i, &feature)))
                L->feat[a->nfeat++] = feature;
        if (st)
            return st;
    }
    if (a->nfeat > 1)
        qsort(L->feat, a->nfeat, sizeof *L->feat, cmp_u32);
    size_t u = 0;
    for (size_t k = 0; k < a->nfeat; k++)
        if (u == 0 || L->feat[u - 1] != L->feat[k])
            L->feat[u++] = L->feat[k];
    a->nfeat = u;
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
    if (L->labels)
        st = stored_faces(L, a);
    else
        st = view_pixel_faces(L->f, L->faces, &a->px, L->cand, L->cap, &a->nfaces);
    return st ? st : gather_features(L, a);
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

static void json_feature(jsonw *w, const locator *L, uint32_t index)
{
    hpfc_feature ft;
    const char *layer;
    size_t layer_len;
    jsonw_object_begin(w, NULL);
    if (hpfc_feature_get(L->f, index, &ft) == HPFC_OK) {
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
    jsonw_array_begin(&w, "faces");
    for (size_t k = 0; k < a->nfaces; k++)
        jsonw_u64(&w, NULL, L->cand[k]);
    jsonw_array_end(&w);
    jsonw_array_begin(&w, "features");
    for (size_t k = 0; k < a->nfeat; k++)
        json_feature(&w, L, L->feat[k]);
    jsonw_array_end(&w);
    if (a->inside)
        jsonw_string(&w, "word", a->word);
    jsonw_bool(&w, "inside", a->inside);
    jsonw_object_end(&w);
    jsonw_finish(&w);
}

static void print_feature_text(FILE *out, const locator *L, uint32_t index)
{
    hpfc_feature ft;
    const char *layer = "";
    size_t layer_len = 0;
    if (hpfc_feature_get(L->f, index, &ft) != HPFC_OK)
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
    fprintf(out, "faces       ");
    for (size_t k = 0; k < a->nfaces; k++)
        fprintf(out, "%s%llu", k ? " " : "", (unsigned long long)L->cand[k]);
    fprintf(out, a->is_private ? " (the point's face)\n"
                               : " (candidates: the faces that meet the pixel)\n");
    if (!L->features) {
        fprintf(out, "features    none (the file has no GIS features)\n");
        return;
    }
    fprintf(out, "features    %zu%s\n", a->nfeat,
            a->nfeat == 0 ? " (no source feature covers the face)" : "");
    for (size_t k = 0; k < a->nfeat; k++)
        print_feature_text(out, L, L->feat[k]);
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

/* One line of POINTS without its end: blank or '#' lines are skipped. */
static int blank_line(const char *s)
{
    s += strspn(s, " \t\r");
    return *s == '\0' || *s == '#';
}

int view_locate_batch(const hpfc_file *f, FILE *in, const char *in_name, int lonlat, FILE *out,
                      char *why)
{
    locator L;
    answer a = {0};
    int status = locator_open(f, lonlat, &L, why);
    char line[512];
    unsigned long n = 0;
    while (!status && fgets(line, sizeof line, in)) {
        n++;
        size_t len = strlen(line);
        if (len == sizeof line - 1 && line[len - 1] != '\n') {
            status =
                view_fail(why, "%s line %lu: longer than %zu bytes", in_name, n, sizeof line - 2);
            break;
        }
        line[strcspn(line, "\r\n")] = '\0';
        if (blank_line(line))
            continue;
        decimal given[2], xy[2];
        const char *p = line + strspn(line, " \t");
        if (decimal_list_parse(p, given, 2)) {
            status = view_fail(why, "%s line %lu: expected %s: two decimal numbers", in_name, n,
                               lonlat ? "lon,lat" : "x,y");
            break;
        }
        if (lonlat && (status = project_lonlat(&L, given, xy, why)) != VIEW_OK) {
            char inner[VIEW_WHY];
            snprintf(inner, sizeof inner, "%s", why);
            status = view_fail(why, "%s line %lu: %s", in_name, n, inner);
            break;
        }
        int st = locate_decimal(&L, lonlat ? xy : given, &a);
        if (st) {
            status = view_fail(why, "%s line %lu: locate: %s", in_name, n, hpfc_strerror(st));
            break;
        }
        print_json(out, &L, lonlat ? given : NULL, lonlat ? xy : given, &a);
    }
    if (!status && ferror(in))
        status = view_fail(why, "%s: read error", in_name);
    free(a.word);
    locator_close(&L);
    return status;
}
