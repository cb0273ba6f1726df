/* Resource limits on an hpfc_shapes (hpfc_limits): a call whose answer
 * would pass a cap stops with HPFC_E_OVER_LIMIT and leaves the object
 * usable, a cap the answer fits in changes nothing. The oracle is the
 * same call without caps: an answer of P points gathered at least P and
 * at most 2P (every edge brings at least one point of its own), so a cap
 * of P - 1 must stop it and one of 2P must not; a window listing T ids
 * stops under T and passes at T. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "gen.h"
#include "hpfc.h"

#define FEATURES 3

static hpfc_file *make_file(uint8_t **bytes)
{
    hpfc_graph *g = NULL;
    hpfc_tree *t = NULL;
    hpfc_file *f = NULL, *out = NULL;
    hpfc_faces *faces = NULL;
    uint8_t *b0 = NULL;
    size_t n0 = 0, n1 = 0;
    *bytes = NULL;
    if (gen_polyline(7, 1200, 100000, 0.5, &g))
        return NULL;
    hpfc_build_params p;
    hpfc_build_params_default(&p);
    hpfc_write_options o = {.face_labels = 1, .geometry = g};
    int st = hpfc_build(g, &p, &t, NULL);
    if (!st)
        st = hpfc_tree_serialize(t, &o, &b0, &n0, NULL);
    if (!st)
        st = hpfc_open_memory(b0, n0, 0, &f);
    if (!st)
        st = hpfc_faces_build(f, &faces);
    if (!st) { /* face k > 0: feature k % FEATURES */
        uint32_t n = (uint32_t)hpfc_faces_face_count(faces);
        uint32_t *start = calloc((size_t)n + 1, sizeof *start);
        uint32_t *link = calloc((size_t)n + 1, sizeof *link);
        static const int64_t fid[FEATURES] = {1, 2, 3};
        static const uint32_t layer[FEATURES] = {0, 0, 0};
        static const char *const layers[1] = {"l"};
        for (uint32_t k = 0; start && link && k < n; k++) {
            start[k + 1] = start[k] + (k > 0);
            if (k > 0)
                link[start[k]] = k % FEATURES;
        }
        hpfc_feature_table ft = {.feature_count = FEATURES, .fid = fid, .layer = layer,
                                 .layer_count = 1, .layer_name = layers, .face_count = n,
                                 .face_start = start, .face_feature = link};
        hpfc_write_options o2 = {.face_labels = 1, .geometry = g, .features = &ft};
        st = start && link ? hpfc_file_serialize(f, &o2, bytes, &n1, NULL) : HPFC_E_NOMEM;
        if (!st)
            st = hpfc_open_memory(*bytes, n1, 0, &out);
        free(start);
        free(link);
    }
    hpfc_faces_free(faces);
    hpfc_close(f);
    hpfc_free(b0);
    hpfc_tree_free(t);
    hpfc_graph_free(g);
    return st ? NULL : out;
}

static int same(const hpfc_polygons *a, const hpfc_polygons *b)
{
    return a->polygon_count == b->polygon_count && a->ring_count == b->ring_count &&
           a->point_count == b->point_count &&
           !memcmp(a->xy, b->xy, 2 * a->point_count * sizeof *a->xy) &&
           !memcmp(a->ring_point, b->ring_point, (a->ring_count + 1) * sizeof *a->ring_point);
}

/* Copies an answer out of the object (the next call overwrites it). */
static hpfc_polygons keep(const hpfc_polygons *p)
{
    hpfc_polygons k = *p;
    int64_t *xy = malloc((2 * p->point_count + 1) * sizeof *xy);
    size_t *rp = malloc((p->ring_count + 1) * sizeof *rp);
    memcpy(xy, p->xy, 2 * p->point_count * sizeof *xy);
    memcpy(rp, p->ring_point, (p->ring_count + 1) * sizeof *rp);
    k.xy = xy, k.ring_point = rp;
    return k;
}

static void drop(hpfc_polygons *p)
{
    free((void *)p->xy);
    free((void *)p->ring_point);
}

typedef int (*shape_call)(hpfc_shapes *, hpfc_id, hpfc_polygons *);

static void check_caps(hpfc_shapes *s, shape_call call, hpfc_id id, size_t *stopped)
{
    hpfc_limits none = {HPFC_LIMIT_NONE, HPFC_LIMIT_NONE};
    hpfc_polygons p;
    CHECK_EQ_INT(hpfc_shapes_set_limits(s, &none), HPFC_OK);
    int st = call(s, id, &p);
    CHECK_EQ_INT(st, HPFC_OK);
    if (st || p.point_count < 2)
        return;
    hpfc_polygons want = keep(&p);
    hpfc_limits tight = {want.point_count - 1, 0}, loose = {2 * want.point_count, 0};
    CHECK_EQ_INT(hpfc_shapes_set_limits(s, &tight), HPFC_OK);
    CHECK_EQ_INT(call(s, id, &p), HPFC_E_OVER_LIMIT);
    *stopped += 1;
    CHECK_EQ_INT(hpfc_shapes_set_limits(s, &loose), HPFC_OK);
    CHECK_EQ_INT(call(s, id, &p), HPFC_OK);
    CHECK(same(&p, &want));
    drop(&want);
}

int main(void)
{
    uint8_t *bytes;
    hpfc_file *f = make_file(&bytes);
    CHECK(f != NULL);
    if (!f)
        return check_report("limits");
    hpfc_shapes *s = NULL;
    CHECK_EQ_INT(hpfc_shapes_create(f, &s), HPFC_OK);
    if (!s)
        return check_report("limits");
    uint64_t faces = hpfc_shapes_face_count(s);
    size_t stopped = 0;
    for (hpfc_id face = 0; face < faces; face += 1 + face / 8)
        check_caps(s, hpfc_shapes_face_polygons, face, &stopped);
    for (hpfc_id k = 0; k < FEATURES; k++)
        check_caps(s, hpfc_shapes_feature_polygons, k, &stopped);
    CHECK(stopped > 10);

    /* a window over everything: T ids; T - 1 stops it, T does not */
    hpfc_file_info in;
    hpfc_file_get_info(f, &in);
    hpfc_window_hits h;
    unsigned all = HPFC_WINDOW_FACES | HPFC_WINDOW_EDGES | HPFC_WINDOW_FEATURES;
    CHECK_EQ_INT(hpfc_shapes_set_limits(s, NULL), HPFC_OK);
    CHECK_EQ_INT(hpfc_shapes_window(s, in.x0 - 1, in.y0 - 1, in.x0 + in.width,
                                    in.y0 + in.height, all, &h),
                 HPFC_OK);
    uint64_t total = h.face_count + h.edge_count + h.feature_count;
    CHECK(h.face_count == faces && h.feature_count == FEATURES);
    hpfc_limits under = {0, total - 1}, at = {0, total};
    CHECK_EQ_INT(hpfc_shapes_set_limits(s, &under), HPFC_OK);
    CHECK_EQ_INT(hpfc_shapes_window(s, in.x0 - 1, in.y0 - 1, in.x0 + in.width,
                                    in.y0 + in.height, all, &h),
                 HPFC_E_OVER_LIMIT);
    CHECK_EQ_INT(hpfc_shapes_set_limits(s, &at), HPFC_OK);
    CHECK_EQ_INT(hpfc_shapes_window(s, in.x0 - 1, in.y0 - 1, in.x0 + in.width,
                                    in.y0 + in.height, all, &h),
                 HPFC_OK);
    CHECK_EQ_INT(h.face_count + h.edge_count + h.feature_count, total);

    /* the struct's rules: NULL shapes, a newer caller's unknown field set */
    CHECK_EQ_INT(hpfc_shapes_set_limits(NULL, &at), HPFC_E_ARG);
    struct {
        hpfc_limits l;
        uint64_t newer;
    } bigger = {{0, 0}, 1};
    CHECK_EQ_INT(hpfc_shapes_set_limits_sized(s, &bigger.l, sizeof bigger), HPFC_E_ARG);
    bigger.newer = 0;
    CHECK_EQ_INT(hpfc_shapes_set_limits_sized(s, &bigger.l, sizeof bigger), HPFC_OK);
    CHECK_EQ_INT(strcmp(hpfc_status_name(HPFC_E_OVER_LIMIT), "HPFC_E_OVER_LIMIT"), 0);
    printf("%llu faces, %zu answers stopped by a cap and answered under a looser one, "
           "window of %llu ids\n",
           (unsigned long long)faces, stopped, (unsigned long long)total);

    hpfc_shapes_free(s);
    hpfc_close(f);
    hpfc_free(bytes);
    return check_report("limits");
}
