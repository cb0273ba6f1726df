/*
 * Point queries (interfaces §4): --locate X,Y, --locate-lonlat LON,LAT and
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
#include "locator.h"

#include "attrs_json.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/types.h>

#include "grow.h"
#include "jsonw.h"
#include "projection.h"
#include "roads.h"



void locator_close(locator *L)
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

int locator_open(const hpfc_file *f, int lonlat, locator *L, char *why)
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
        if (!st && !array_grow((void **)&L->feat, &L->feat_cap, a->nfeat + count, sizeof *L->feat))
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
        if (!st && !array_grow((void **)&L->along, &L->along_cap, a->nalong + count, sizeof *L->along))
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
        if (!array_grow((void **)&L->cand, &L->cap, n, sizeof *L->cand))
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
        !array_grow((void **)&L->cand, &L->cap, len > 4 ? len - 4 : 1, sizeof *L->cand))
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
int locate_decimal(locator *L, const decimal xy[2], answer *a)
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
int project_lonlat(const locator *L, const decimal ll[2], decimal xy[2], char *why)
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

void json_decimal(jsonw *w, const char *key, const decimal *d)
{
    jsonw_double(w, key, d->value, decimal_fraction_digits(d));
}

void json_feature(jsonw *w, const locator *L, hpfc_id index)
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
void json_along(jsonw *w, const locator *L, const answer *a)
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
void json_exact(jsonw *w, const locator *L, const answer *a)
{
    jsonw_bool(w, "exact", L->exact);
    jsonw_bool(w, "on_boundary", a->exact && a->loc.on_boundary);
    if (a->exact && a->loc.on_vertex)
        jsonw_u64(w, "vertex", a->loc.vertex);
    else if (a->exact && a->loc.on_boundary)
        jsonw_u64(w, "edge", a->loc.edge);
}

/* One answer as the JSON object of interfaces §4. ll: the lon/lat asked
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

