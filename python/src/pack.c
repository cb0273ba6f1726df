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
 *                 graph to word its flaw as hpfc_build does.
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

/* _pack_cut(pfc, dir, root_cols, root_rows, cols, rows, leaf_points, parts)
 *   -> plan: the .pfc read, its parts' graphs written into dir */
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
    st = part_dir_merge(NULL, paths, (uint32_t)count, &joined, &d);
    if (!st && geometry && (st = hpfc_pfc_read_file(pfc, &g, &d)) != HPFC_OK)
        culprit = pfc;
    if (!st) {
        /* without GEOM the merge holds no graph: LABL's faces numbered a
         * root pixel at a time keep its memory to the root pixels' borders (with
         * GEOM the graph read whole dwarfs them: the faster numbering) */
        hpfc_write_options o = {.face_labels = labels, .layout = layout, .geometry = g,
                                .faces_by_root = !geometry, .threads = merge_threads()};
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
