/*
 * pack.c: the C half of hpfc.pack (hpfc/_pack.py), a .pfc graph packed in
 * parts on a Dask cluster: the library's split build (hpfc_part_graph,
 * hpfc_build_part, part files, hpfc_tree_merge) in three steps, each run
 * where its data is.
 *
 *   _pack_cut     (the client) reads the .pfc once, chooses the domain and
 *                 cuts each part's graph into DIR/part-K.pfc (lattice
 *                 integers: the unit exponent travels beside it) and
 *                 DIR/part-K.ids (each edge's id in the whole map, u32);
 *   _pack_part    (a worker) builds one part from those two files into a
 *                 part file (spec/part-format.md);
 *   _pack_merge   (the client) reads the part files back, joins them and
 *                 writes the .hpfc atomically, GEOM from the .pfc read again;
 *   _pack_check   (the client, after a part failed) validates the whole
 *                 graph to word its flaw as hpfc_build does.
 *
 * A part's inputs come back through the library's hardened readers (the
 * .pfc parser, the part file reader) and hpfc_build_part checks the ids,
 * so a damaged file in the shared directory is an hpfc.Error.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hpfc.h"
#include "shapes.h" /* pyhpfc_raise */

static PyObject *raise_diag(int st, const hpfc_diag *d, const char *context)
{
    char text[600];
    snprintf(text, sizeof text, "%s: %s", context, d->message[0] ? d->message : hpfc_strerror(st));
    return pyhpfc_raise(st, text);
}

static hpfc_build_params params_from(unsigned root_cols, unsigned root_rows, unsigned cols,
                                     unsigned rows, unsigned leaf_points)
{
    hpfc_build_params p;
    hpfc_build_params_default(&p);
    p.root_cols = root_cols, p.root_rows = root_rows, p.cols = cols, p.rows = rows;
    p.max_leaf_points = leaf_points;
    return p;
}

/* The graph as .pfc text of lattice integers (unit exponent 0: the reader
 * gets back the same integers, and the caller sets the unit). */
static int write_pfc(const hpfc_graph *g, const char *path)
{
    FILE *f = fopen(path, "w");
    if (!f)
        return errno ? errno : EIO;
    fputs("pfc 1\n", f);
    for (size_t v = 0; v < hpfc_graph_vertex_count(g); v++) {
        int64_t x, y;
        hpfc_graph_vertex(g, v, &x, &y);
        fprintf(f, "v %lld %lld\n", (long long)x, (long long)y);
    }
    for (size_t e = 0; e < hpfc_graph_edge_count(g); e++) {
        uint32_t u, v;
        const int64_t *xy;
        size_t n;
        hpfc_graph_edge(g, e, &u, &v, &xy, &n);
        fprintf(f, "e %u %u", u, v);
        for (size_t k = 0; k < 2 * n; k++)
            fprintf(f, " %lld", (long long)xy[k]);
        fputc('\n', f);
    }
    int err = ferror(f) ? EIO : 0;
    if (fclose(f) && !err)
        err = errno ? errno : EIO;
    return err;
}

static int write_ids(const uint32_t *ids, size_t n, const char *path)
{
    FILE *f = fopen(path, "wb");
    if (!f)
        return errno ? errno : EIO;
    size_t done = n ? fwrite(ids, sizeof *ids, n, f) : 0;
    int err = done != n || ferror(f) ? EIO : 0;
    if (fclose(f) && !err)
        err = errno ? errno : EIO;
    return err;
}

/* _pack_check(pfc) -> None: the whole graph validated, raising its first
 * flaw in hpfc_build's words (after a part found one). */
static PyObject *mod_pack_check(PyObject *m, PyObject *arg)
{
    (void)m;
    const char *pfc = PyUnicode_AsUTF8(arg);
    if (!pfc)
        return NULL;
    hpfc_graph *g = NULL;
    hpfc_diag d = {0};
    int st;
    Py_BEGIN_ALLOW_THREADS
    st = hpfc_pfc_read_file(pfc, &g, &d);
    if (!st)
        st = hpfc_graph_validate(g, &d);
    Py_END_ALLOW_THREADS
    hpfc_graph_free(g);
    if (st)
        return raise_diag(st, &d, pfc);
    Py_RETURN_NONE;
}

/* Part k of parts: a run of root pixels in scanline order. */
static void part_range(uint64_t roots, uint64_t parts, uint64_t k, uint64_t *first, uint64_t *end)
{
    *first = roots * k / parts;
    *end = roots * (k + 1) / parts;
}

/* _pack_cut(pfc, dir, root_cols, root_rows, cols, rows, leaf_points, parts)
 *   -> (x0, y0, width, height, max_depth, unit_exp10, edge_count, parts) */
static PyObject *mod_pack_cut(PyObject *m, PyObject *args)
{
    (void)m;
    const char *pfc, *dir;
    unsigned n0, m0, n, mm, leaf, parts;
    if (!PyArg_ParseTuple(args, "ssIIIIII", &pfc, &dir, &n0, &m0, &n, &mm, &leaf, &parts))
        return NULL;
    hpfc_build_params p = params_from(n0, m0, n, mm, leaf);
    hpfc_graph *g = NULL;
    hpfc_diag d = {0};
    int st = hpfc_pfc_read_file(pfc, &g, &d);
    if (!st) /* the parts validate their own graphs: what none of them can see */
        st = hpfc_graph_check_whole(g, &d);
    int64_t box[4];
    hpfc_domain dom = {0};
    if (!st)
        st = hpfc_graph_bounds(g, box);
    if (!st)
        st = hpfc_build_domain(box, &p, &dom, &d);
    uint64_t roots = (uint64_t)n0 * m0;
    if (!st && (parts < 1 || parts > roots))
        st = HPFC_E_ARG, snprintf(d.message, sizeof d.message, "partitions must be 1 to %llu",
                                  (unsigned long long)roots);
    uint32_t *pixels = st ? NULL : malloc((size_t)roots * sizeof *pixels);
    if (!st && !pixels)
        st = HPFC_E_NOMEM;
    for (uint64_t k = 0; !st && k < roots; k++)
        pixels[k] = (uint32_t)k;
    char path[4096];
    for (uint64_t k = 0; !st && k < parts; k++) {
        uint64_t first, end;
        part_range(roots, parts, k, &first, &end);
        hpfc_part part = {.domain = dom, .root_pixels = pixels + first, .root_pixel_count = (size_t)(end - first)};
        hpfc_graph *sub = NULL;
        uint32_t *ids = NULL;
        st = hpfc_part_graph(g, &p, &part, &sub, &ids, &d);
        int err = 0;
        if (!st) {
            snprintf(path, sizeof path, "%s/part-%llu.pfc", dir, (unsigned long long)k);
            err = write_pfc(sub, path);
            snprintf(path, sizeof path, "%s/part-%llu.ids", dir, (unsigned long long)k);
            if (!err)
                err = write_ids(ids, hpfc_graph_edge_count(sub), path);
        }
        if (err)
            st = HPFC_E_IO, snprintf(d.message, sizeof d.message, "cannot write %.200s: %s", path, strerror(err));
        hpfc_graph_free(sub);
        hpfc_free(ids);
    }
    free(pixels);
    int32_t unit = g ? hpfc_graph_unit_exp10(g) : 0;
    size_t edges = g ? hpfc_graph_edge_count(g) : 0;
    hpfc_graph_free(g);
    if (st)
        return raise_diag(st, &d, pfc);
    return Py_BuildValue("(LLLLIiKI)", (long long)dom.x0, (long long)dom.y0, (long long)dom.width,
                         (long long)dom.height, dom.max_depth, (int)unit, (unsigned long long)edges, parts);
}

/* The ids file: u32 each, as many as the part's edges (hpfc_build_part
 * checks their order and range). */
static int read_ids(const char *path, size_t count, uint32_t **out, hpfc_diag *d)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        snprintf(d->message, sizeof d->message, "cannot open %.200s: %s", path, strerror(errno));
        return HPFC_E_IO;
    }
    uint32_t *ids = malloc((count ? count : 1) * sizeof *ids);
    int st = ids ? HPFC_OK : HPFC_E_NOMEM;
    if (!st && (fread(ids, sizeof *ids, count, f) != count || fgetc(f) != EOF)) {
        snprintf(d->message, sizeof d->message, "%.200s: not one id for each of the part's %zu edges", path, count);
        st = HPFC_E_CORRUPT;
    }
    fclose(f);
    if (st)
        free(ids);
    else
        *out = ids;
    return st;
}

/* _pack_part(pfc, ids, out, unit_exp10, edge_count, x0, y0, width, height, max_depth,
 *            root_cols, root_rows, cols, rows, leaf_points, part, parts) -> out */
static PyObject *mod_pack_part(PyObject *m, PyObject *args)
{
    (void)m;
    const char *pfc, *ids_path, *out;
    int unit;
    unsigned long long edges;
    long long x0, y0, w, h;
    unsigned depth, n0, m0, n, mm, leaf, k, parts;
    if (!PyArg_ParseTuple(args, "sssiKLLLLIIIIIIII", &pfc, &ids_path, &out, &unit, &edges, &x0, &y0, &w, &h,
                          &depth, &n0, &m0, &n, &mm, &leaf, &k, &parts))
        return NULL;
    hpfc_build_params p = params_from(n0, m0, n, mm, leaf);
    uint64_t roots = (uint64_t)n0 * m0, first = 0, end = 0;
    if (parts < 1 || k >= parts || parts > roots)
        return pyhpfc_raise(HPFC_E_ARG, "part: no such part");
    part_range(roots, parts, k, &first, &end);
    hpfc_graph *g = NULL;
    uint32_t *ids = NULL, *pixels = malloc((size_t)(end - first + 1) * sizeof *pixels);
    hpfc_tree *t = NULL;
    hpfc_diag d = {0};
    int st = pixels ? HPFC_OK : HPFC_E_NOMEM;
    for (uint64_t q = first; !st && q < end; q++)
        pixels[q - first] = (uint32_t)q;
    Py_BEGIN_ALLOW_THREADS
    if (!st)
        st = hpfc_pfc_read_file(pfc, &g, &d);
    if (st == HPFC_E_EMPTY) /* a part that no edge comes near: its pixels are private */
        st = hpfc_graph_create(&g);
    if (!st && hpfc_graph_unit_exp10(g) != 0)
        st = HPFC_E_CORRUPT, snprintf(d.message, sizeof d.message, "a part's graph has fractions");
    if (!st)
        st = hpfc_graph_set_unit_exp10(g, unit);
    if (!st)
        st = read_ids(ids_path, hpfc_graph_edge_count(g), &ids, &d);
    if (!st) {
        hpfc_part part = {.domain = {x0, y0, w, h, depth}, .root_pixels = pixels,
                          .root_pixel_count = (size_t)(end - first), .edge_ids = ids, .edge_count = edges};
        st = hpfc_build_part(g, &p, &part, &t, &d);
    }
    if (!st)
        st = hpfc_tree_write_part(t, out, &d);
    Py_END_ALLOW_THREADS
    hpfc_tree_free(t);
    hpfc_graph_free(g);
    free(ids);
    free(pixels);
    if (st)
        return raise_diag(st, &d, pfc);
    return PyUnicode_FromString(out);
}

/* _pack_merge(part_paths, pfc, out, layout, labels, geometry) -> None */
static PyObject *mod_pack_merge(PyObject *m, PyObject *args)
{
    (void)m;
    PyObject *list;
    const char *pfc, *out;
    int layout, labels, geometry;
    if (!PyArg_ParseTuple(args, "O!ssipp", &PyList_Type, &list, &pfc, &out, &layout, &labels, &geometry))
        return NULL;
    Py_ssize_t count = PyList_Size(list);
    hpfc_tree **parts = calloc(count ? (size_t)count : 1, sizeof *parts);
    const char **paths = calloc(count ? (size_t)count : 1, sizeof *paths);
    if (!parts || !paths) {
        free(parts), free(paths);
        return PyErr_NoMemory();
    }
    for (Py_ssize_t k = 0; k < count; k++)
        if (!(paths[k] = PyUnicode_AsUTF8(PyList_GetItem(list, k)))) {
            free(parts), free(paths);
            return NULL;
        }
    hpfc_diag d = {0};
    hpfc_tree *joined = NULL;
    hpfc_graph *g = NULL;
    const char *culprit = pfc;
    int st = HPFC_OK;
    Py_BEGIN_ALLOW_THREADS
    for (Py_ssize_t k = 0; !st && k < count; k++)
        if ((st = hpfc_tree_read_part(paths[k], &parts[k], &d)))
            culprit = paths[k];
    if (!st)
        st = hpfc_tree_merge(parts, (size_t)count, &joined, &d);
    for (Py_ssize_t k = 0; k < count; k++) /* the joined tree holds its own copy */
        hpfc_tree_free(parts[k]);
    if (!st && geometry)
        st = hpfc_pfc_read_file(pfc, &g, &d);
    if (!st) {
        hpfc_write_options o = {.face_labels = labels, .layout = layout, .geometry = g};
        st = hpfc_tree_write_file(joined, &o, out, &d);
        culprit = out;
    }
    Py_END_ALLOW_THREADS
    hpfc_graph_free(g);
    hpfc_tree_free(joined);
    free(parts);
    free(paths);
    if (st)
        return raise_diag(st, &d, culprit);
    Py_RETURN_NONE;
}

static PyMethodDef pack_methods[] = {
    {"_pack_cut", mod_pack_cut, METH_VARARGS, NULL},
    {"_pack_part", mod_pack_part, METH_VARARGS, NULL},
    {"_pack_merge", mod_pack_merge, METH_VARARGS, NULL},
    {"_pack_check", mod_pack_check, METH_O, NULL},
    {NULL, NULL, 0, NULL}};

int pyhpfc_pack_add(PyObject *module)
{
    return PyModule_AddFunctions(module, pack_methods);
}
