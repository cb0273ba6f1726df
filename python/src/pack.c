/*
 * pack.c: the C half of hpfc.pack (hpfc/_pack.py), a map packed in parts on
 * a Dask cluster through a shared directory (common/part_dir.h), each step
 * run where its data is:
 *
 *   _pack_cut     (the client, .pfc input) reads the .pfc once, chooses the
 *                 domain and cuts each part's graph into the directory; it
 *                 returns the plan, the dict a worker needs (for other inputs
 *                 hpfc-pack --parts-dir cuts, and prints the same plan);
 *   _pack_part    (a worker) builds one part into its part file
 *                 (spec/part-format.md);
 *   _pack_merge   (the client, .pfc input) reads the part files back, joins
 *                 them and writes the .hpfc atomically, GEOM from the .pfc
 *                 read again;
 *   _pack_check   (the client, after a part failed) validates the whole
 *                 graph to word its flaw as hpfc_build does;
 *   _pfc_chunks, _pfc_scan, _graph_create, _pfc_fill
 *                 the .pfc read by the workers a chunk each into the
 *                 graph file DIR/graph (part_dir.h);
 *   _pack_plan, _pfc_route, _pack_part_routed
 *                 the plan from the graph file and the chunks' box (the
 *                 client), each chunk's edges routed to the parts (a
 *                 worker each: DIR/route-C), each part's graph copied out
 *                 of DIR/graph and built (a worker each); _pack_merge maps
 *                 DIR/graph for GEOM (graph_file=True).
 *
 * A part's inputs come back through the library's hardened readers (the
 * .pfc parser, the part file reader) and hpfc_build_part checks the ids,
 * so a damaged file in the shared directory is an hpfc.Error.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h> /* munmap */
#include <unistd.h> /* sysconf */

#include "hpfc.h"
#include "part_dir.h"
#include "shapes.h" /* pyhpfc_raise */

static PyObject *raise_diag(int st, const hpfc_diag *d, const char *context)
{
    char text[600];
    snprintf(text, sizeof text, "%s: %s", context, d->message[0] ? d->message : hpfc_strerror(st));
    return pyhpfc_raise(st, text);
}

/* The plan as a dict, the JSON object hpfc-pack --parts-dir prints
 * (docs/interfaces.md §8): {"parts", "domain": [x0, y0, width, height,
 * max_depth], "unit_exp10", "edges", "root": [cols, rows], "refine": [cols,
 * rows], "leaf_points"}. */
static PyObject *plan_to_dict(const part_plan *p)
{
    const hpfc_domain *d = &p->domain;
    return Py_BuildValue("{s:I,s:(LLLLI),s:i,s:K,s:(II),s:(II),s:I}", "parts", p->parts, "domain",
                         (long long)d->x0, (long long)d->y0, (long long)d->width, (long long)d->height,
                         d->max_depth, "unit_exp10", (int)p->unit_exp10, "edges",
                         (unsigned long long)p->edges, "root", p->root_cols, p->root_rows, "refine",
                         p->cols, p->rows, "leaf_points", p->leaf_points);
}

static int plan_from_dict(PyObject *dict, part_plan *p)
{
    if (!PyDict_Check(dict)) {
        PyErr_SetString(PyExc_TypeError, "plan: a dict");
        return -1;
    }
    PyObject *parts = PyDict_GetItemString(dict, "parts"), *dom = PyDict_GetItemString(dict, "domain");
    PyObject *unit = PyDict_GetItemString(dict, "unit_exp10"), *edges = PyDict_GetItemString(dict, "edges");
    PyObject *root = PyDict_GetItemString(dict, "root"), *refine = PyDict_GetItemString(dict, "refine");
    PyObject *leaf = PyDict_GetItemString(dict, "leaf_points");
    if (!parts || !dom || !unit || !edges || !root || !refine || !leaf) {
        PyErr_SetString(PyExc_ValueError, "plan: a key is missing");
        return -1;
    }
    long long x0, y0, w, h;
    unsigned long long e;
    int u;
    memset(p, 0, sizeof *p);
    /* lists from JSON (hpfc-pack's plan line) or tuples (_pack_cut's) */
    PyObject *dt = PySequence_Tuple(dom), *rt = PySequence_Tuple(root), *ft = PySequence_Tuple(refine);
    int ok = dt && rt && ft && PyArg_ParseTuple(dt, "LLLLI", &x0, &y0, &w, &h, &p->domain.max_depth) &&
             PyArg_ParseTuple(rt, "II", &p->root_cols, &p->root_rows) &&
             PyArg_ParseTuple(ft, "II", &p->cols, &p->rows);
    Py_XDECREF(dt), Py_XDECREF(rt), Py_XDECREF(ft);
    if (!ok)
        return -1;
    p->domain.x0 = x0, p->domain.y0 = y0, p->domain.width = w, p->domain.height = h;
    e = PyLong_AsUnsignedLongLong(edges);
    u = (int)PyLong_AsLong(unit);
    p->parts = (uint32_t)PyLong_AsUnsignedLong(parts);
    p->leaf_points = (uint32_t)PyLong_AsUnsignedLong(leaf);
    if (PyErr_Occurred())
        return -1;
    p->edges = e, p->unit_exp10 = u;
    return 0;
}

/* The graph of a .pfc, or of a graph file (DIR/graph, which the workers'
 * chunks filled: mapped, not read into the process). */
static int read_graph(const char *path, int graph_file, hpfc_graph **g, hpfc_diag *d)
{
    return graph_file ? hpfc_graph_map_file(path, g, d) : hpfc_pfc_read_file(path, g, d);
}

/* _pack_cut(pfc, dir, root_cols, root_rows, cols, rows, leaf_points, parts)
 *   -> plan: the .pfc read here, its parts' graphs written into dir */
static PyObject *mod_pack_cut(PyObject *m, PyObject *args)
{
    (void)m;
    const char *pfc, *dir;
    unsigned n0, m0, n, mm, leaf, parts;
    if (!PyArg_ParseTuple(args, "ssIIIIII", &pfc, &dir, &n0, &m0, &n, &mm, &leaf, &parts))
        return NULL;
    hpfc_build_params p;
    hpfc_build_params_default(&p);
    p.root_cols = n0, p.root_rows = m0, p.cols = n, p.rows = mm, p.max_leaf_points = leaf;
    hpfc_graph *g = NULL;
    hpfc_diag d = {0};
    part_plan plan;
    int st;
    Py_BEGIN_ALLOW_THREADS
    st = hpfc_pfc_read_file(pfc, &g, &d);
    if (!st)
        st = part_dir_cut(g, &p, parts, dir, &plan, &d);
    Py_END_ALLOW_THREADS
    hpfc_graph_free(g);
    if (st)
        return raise_diag(st, &d, pfc);
    return plan_to_dict(&plan);
}

/* _pack_part(dir, plan, k) -> DIR/part-K.part, built from DIR/part-K.pfc and .ids */
static PyObject *mod_pack_part(PyObject *m, PyObject *args)
{
    (void)m;
    const char *dir;
    PyObject *dict;
    unsigned k;
    part_plan plan;
    if (!PyArg_ParseTuple(args, "sOI", &dir, &dict, &k) || plan_from_dict(dict, &plan))
        return NULL;
    hpfc_diag d = {0};
    int st;
    Py_BEGIN_ALLOW_THREADS
    st = part_dir_build(dir, &plan, k, &d);
    Py_END_ALLOW_THREADS
    char where[64];
    snprintf(where, sizeof where, "part %u", k);
    if (st)
        return raise_diag(st, &d, where);
    return PyUnicode_FromFormat("%s/part-%u.part", dir, k);
}

/* The merge's threads (LABL's faces, GEOM's plan beside them): the
 * client's cores, which wait for the merge once the parts are built. */
static unsigned merge_threads(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1 : n > 8 ? 8 : (unsigned)n;
}

/* _pack_merge(part_paths, pfc, out, layout, labels, geometry, graph_file=False) -> None */
static PyObject *mod_pack_merge(PyObject *m, PyObject *args)
{
    (void)m;
    PyObject *list;
    const char *pfc, *out;
    int layout, labels, geometry, graph_file = 0;
    if (!PyArg_ParseTuple(args, "O!ssipp|p", &PyList_Type, &list, &pfc, &out, &layout, &labels, &geometry,
                          &graph_file))
        return NULL;
    Py_ssize_t count = PyList_Size(list);
    if (count < 1 || count > UINT32_MAX)
        return pyhpfc_raise(HPFC_E_ARG, "merge: no part");
    const char **paths = calloc((size_t)count, sizeof *paths);
    if (!paths)
        return PyErr_NoMemory();
    for (Py_ssize_t k = 0; k < count; k++)
        if (!(paths[k] = PyUnicode_AsUTF8(PyList_GetItem(list, k)))) {
            free(paths);
            return NULL;
        }
    hpfc_diag d = {0};
    hpfc_tree *joined = NULL;
    hpfc_graph *g = NULL;
    const char *culprit = "merge";
    int st;
    Py_BEGIN_ALLOW_THREADS
    /* no report here needs the map's components: not counted, the join
     * holds a bit an edge, not a union-find over them */
    st = part_dir_merge(NULL, paths, (uint32_t)count, false, &joined, &d);
    if (!st && geometry && (st = read_graph(pfc, graph_file, &g, &d)) != HPFC_OK)
        culprit = pfc;
    if (!st) {
        /* LABL's faces numbered a root pixel at a time keep the merge's
         * memory to the root pixels' borders when it holds no graph: none
         * without GEOM, or the graph file mapped (its pages the page
         * cache's). A text read whole here dwarfs them: the faster
         * numbering then. */
        hpfc_write_options o = {.face_labels = labels, .layout = layout, .geometry = g,
                                .faces_by_root = !geometry || graph_file, .threads = merge_threads()};
        st = hpfc_tree_write_file(joined, &o, out, &d);
        culprit = out;
    }
    Py_END_ALLOW_THREADS
    hpfc_graph_free(g);
    hpfc_tree_free(joined);
    free(paths);
    if (st)
        return raise_diag(st, &d, culprit);
    Py_RETURN_NONE;
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

/* ---- the .pfc read by the workers (part_dir.h: DIR/graph) ------------------- */

/* _pfc_chunks(pfc, count) -> [(begin, end), ...]: at most count chunks,
 * cut at line starts (hpfc_pfc_chunk_bounds) */
static PyObject *mod_pfc_chunks(PyObject *m, PyObject *args)
{
    (void)m;
    const char *pfc;
    Py_ssize_t count;
    if (!PyArg_ParseTuple(args, "sn", &pfc, &count))
        return NULL;
    if (count < 1 || count > (1 << 20))
        return pyhpfc_raise(HPFC_E_ARG, "chunks: 1 to 2^20");
    const char *text;
    size_t length;
    hpfc_diag d = {0};
    size_t *at = malloc(((size_t)count + 1) * sizeof *at), n = 0;
    if (!at)
        return PyErr_NoMemory();
    int st;
    Py_BEGIN_ALLOW_THREADS
    st = part_dir_map_text(pfc, &text, &length, &d);
    if (!st) {
        n = hpfc_pfc_chunk_bounds(text ? text : "", length, (size_t)count, at);
        if (text)
            munmap((void *)(uintptr_t)text, length);
    }
    Py_END_ALLOW_THREADS
    PyObject *list = st ? NULL : PyList_New((Py_ssize_t)n);
    for (size_t k = 0; list && k < n; k++) {
        PyObject *pair = Py_BuildValue("(nn)", (Py_ssize_t)at[k], (Py_ssize_t)at[k + 1]);
        if (!pair)
            Py_CLEAR(list);
        else
            PyList_SET_ITEM(list, (Py_ssize_t)k, pair);
    }
    free(at);
    if (st)
        return raise_diag(st, &d, pfc);
    return list;
}

/* _pfc_scan(pfc, begin, end) -> (vertices, edges, points, digits) */
static PyObject *mod_pfc_scan(PyObject *m, PyObject *args)
{
    (void)m;
    const char *pfc;
    Py_ssize_t begin, end;
    if (!PyArg_ParseTuple(args, "snn", &pfc, &begin, &end))
        return NULL;
    const char *text;
    size_t length;
    hpfc_diag d = {0};
    hpfc_pfc_chunk c = {0};
    int st;
    Py_BEGIN_ALLOW_THREADS
    st = part_dir_map_text(pfc, &text, &length, &d);
    if (!st) {
        st = begin < 0 || end < 0 ? HPFC_E_ARG
                                  : hpfc_pfc_chunk_scan(text, length, (size_t)begin, (size_t)end, &c, &d);
        if (text)
            munmap((void *)(uintptr_t)text, length);
    }
    Py_END_ALLOW_THREADS
    if (st)
        return raise_diag(st, &d, pfc);
    return Py_BuildValue("(KKKi)", (unsigned long long)c.vertices, (unsigned long long)c.edges,
                         (unsigned long long)c.points, (int)c.digits);
}

/* _graph_create(path, vertices, edges, points, unit_exp10) -> None */
static PyObject *mod_graph_create(PyObject *m, PyObject *args)
{
    (void)m;
    const char *path;
    unsigned long long nv, ne, np;
    int unit;
    if (!PyArg_ParseTuple(args, "sKKKi", &path, &nv, &ne, &np, &unit))
        return NULL;
    hpfc_diag d = {0};
    int st;
    Py_BEGIN_ALLOW_THREADS
    st = part_dir_graph_create(path, nv, ne, np, unit, &d);
    Py_END_ALLOW_THREADS
    if (st)
        return raise_diag(st, &d, path);
    Py_RETURN_NONE;
}

/* _pfc_fill(pfc, begin, end, scan, graph, totals, digits, firsts)
 *   -> (xmin, ymin, xmax, ymax), or None for a chunk of no point; scan is
 *   _pfc_scan's tuple, totals (vertices, edges, points) the whole text's,
 *   firsts the vertices, edges and points of the chunks before */
static PyObject *mod_pfc_fill(PyObject *m, PyObject *args)
{
    (void)m;
    const char *pfc, *graph;
    Py_ssize_t begin, end;
    int scan_digits;
    hpfc_pfc_chunk c = {0};
    part_dir_chunk_place place = {0};
    if (!PyArg_ParseTuple(args, "snn(KKKi)s(KKK)i(KKK)", &pfc, &begin, &end, &c.vertices, &c.edges,
                          &c.points, &scan_digits, &graph, &place.vertices, &place.edges, &place.points,
                          &place.digits, &place.first_vertex, &place.first_edge, &place.first_point))
        return NULL;
    if (begin < 0 || end < 0)
        return pyhpfc_raise(HPFC_E_ARG, "chunk: negative bounds");
    c.digits = scan_digits;
    hpfc_diag d = {0};
    int64_t box[4];
    int st;
    Py_BEGIN_ALLOW_THREADS
    st = part_dir_fill_chunk(pfc, (size_t)begin, (size_t)end, &c, graph, &place, box, &d);
    Py_END_ALLOW_THREADS
    if (st)
        return raise_diag(st, &d, pfc);
    if (box[0] > box[2])
        Py_RETURN_NONE;
    return Py_BuildValue("(LLLL)", (long long)box[0], (long long)box[1], (long long)box[2],
                         (long long)box[3]);
}

/* _pack_plan(graph, root_cols, root_rows, cols, rows, leaf_points, parts, box) -> plan:
 * the plan of the graph file's graph (mapped; box its points' box, from
 * the chunks' fills), checking what no part can see */
static PyObject *mod_pack_plan(PyObject *m, PyObject *args)
{
    (void)m;
    const char *graph;
    unsigned n0, m0, n, mm, leaf, parts;
    long long b[4];
    if (!PyArg_ParseTuple(args, "sIIIIII(LLLL)", &graph, &n0, &m0, &n, &mm, &leaf, &parts, &b[0], &b[1],
                          &b[2], &b[3]))
        return NULL;
    hpfc_build_params p;
    hpfc_build_params_default(&p);
    p.root_cols = n0, p.root_rows = m0, p.cols = n, p.rows = mm, p.max_leaf_points = leaf;
    int64_t box[4] = {b[0], b[1], b[2], b[3]};
    hpfc_graph *g = NULL;
    hpfc_diag d = {0};
    part_plan plan;
    int st;
    Py_BEGIN_ALLOW_THREADS
    st = hpfc_graph_map_file(graph, &g, &d);
    if (!st)
        st = part_dir_plan(g, &p, parts, box, &plan, &d);
    Py_END_ALLOW_THREADS
    hpfc_graph_free(g);
    if (st)
        return raise_diag(st, &d, graph);
    return plan_to_dict(&plan);
}

/* _pfc_route(dir, plan, chunk, first_edge, end_edge) -> None: DIR/route-CHUNK */
static PyObject *mod_pfc_route(PyObject *m, PyObject *args)
{
    (void)m;
    const char *dir;
    PyObject *dict;
    unsigned chunk;
    unsigned long long e0, e1;
    part_plan plan;
    if (!PyArg_ParseTuple(args, "sOIKK", &dir, &dict, &chunk, &e0, &e1) || plan_from_dict(dict, &plan))
        return NULL;
    char path[4096];
    snprintf(path, sizeof path, "%s/graph", dir);
    hpfc_graph *g = NULL;
    hpfc_diag d = {0};
    int st;
    Py_BEGIN_ALLOW_THREADS
    st = hpfc_graph_map_file(path, &g, &d);
    if (!st)
        st = part_dir_route(dir, g, &plan, chunk, e0, e1, &d);
    Py_END_ALLOW_THREADS
    hpfc_graph_free(g);
    if (st)
        return raise_diag(st, &d, dir);
    Py_RETURN_NONE;
}

/* _pack_part_routed(dir, plan, k, chunks) -> DIR/part-K.part, from
 * DIR/graph and DIR/route-0 .. route-(chunks - 1) */
static PyObject *mod_pack_part_routed(PyObject *m, PyObject *args)
{
    (void)m;
    const char *dir;
    PyObject *dict;
    unsigned k, chunks;
    part_plan plan;
    if (!PyArg_ParseTuple(args, "sOII", &dir, &dict, &k, &chunks) || plan_from_dict(dict, &plan))
        return NULL;
    hpfc_diag d = {0};
    int st;
    Py_BEGIN_ALLOW_THREADS
    st = part_dir_build_routed(dir, &plan, k, chunks, &d);
    Py_END_ALLOW_THREADS
    char where[64];
    snprintf(where, sizeof where, "part %u", k);
    if (st)
        return raise_diag(st, &d, where);
    return PyUnicode_FromFormat("%s/part-%u.part", dir, k);
}

static PyMethodDef pack_methods[] = {
    {"_pack_plan", mod_pack_plan, METH_VARARGS, NULL},
    {"_pfc_route", mod_pfc_route, METH_VARARGS, NULL},
    {"_pack_part_routed", mod_pack_part_routed, METH_VARARGS, NULL},
    {"_pfc_chunks", mod_pfc_chunks, METH_VARARGS, NULL},
    {"_pfc_scan", mod_pfc_scan, METH_VARARGS, NULL},
    {"_graph_create", mod_graph_create, METH_VARARGS, NULL},
    {"_pfc_fill", mod_pfc_fill, METH_VARARGS, NULL},
    {"_pack_cut", mod_pack_cut, METH_VARARGS, NULL},
    {"_pack_part", mod_pack_part, METH_VARARGS, NULL},
    {"_pack_merge", mod_pack_merge, METH_VARARGS, NULL},
    {"_pack_check", mod_pack_check, METH_O, NULL},
    {NULL, NULL, 0, NULL}};

int pyhpfc_pack_add(PyObject *module)
{
    return PyModule_AddFunctions(module, pack_methods);
}
