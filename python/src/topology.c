/*
 * topology.c: the topology questions for the Python package, methods of
 * _Shapes over the library's hpfc_shapes_window, _feature_neighbours,
 * _adjacency, _nearest_edge, _edges_within, _features_polygons and _mesh.
 * Each runs without the GIL and answers flat arrays as bytes (ids uint64,
 * flags uint8, lengths float64, offsets and lattice points int64), which
 * hpfc/_topology.py wraps in numpy; nothing here computes geometry.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "hpfc.h"
#include "shapes.h"

static PyObject *raw(const void *p, size_t n, size_t size)
{
    return PyBytes_FromStringAndSize(n ? (const char *)p : "", (Py_ssize_t)(n * size));
}

/* size_t offsets as int64 bytes. */
static PyObject *offsets(const size_t *v, size_t n)
{
    PyObject *b = PyBytes_FromStringAndSize(NULL, (Py_ssize_t)(n * 8));
    if (!b)
        return NULL;
    int64_t *out = (int64_t *)PyBytes_AS_STRING(b);
    for (size_t k = 0; k < n; k++)
        out[k] = (int64_t)v[k];
    return b;
}

static PyObject *status_error(int st, const char *context)
{
    if (st == HPFC_E_ARG) {
        PyErr_Format(PyExc_ValueError, "%s: an argument out of range", context);
        return NULL;
    }
    return pyhpfc_raise(st, context);
}

/* A contiguous buffer of `itemsize`-byte items of format `fmt` (one of
 * two spellings), or -1 with TypeError. */
static int get_buffer(PyObject *o, Py_buffer *b, size_t itemsize, const char *f1, const char *f2,
                      const char *what)
{
    if (PyObject_GetBuffer(o, b, PyBUF_C_CONTIGUOUS | PyBUF_FORMAT) < 0)
        return -1;
    const char *fmt = b->format ? b->format : "B";
    if (*fmt == '<' || *fmt == '=')
        fmt++;
    if ((size_t)b->itemsize != itemsize || (strcmp(fmt, f1) && strcmp(fmt, f2))) {
        PyBuffer_Release(b);
        PyErr_Format(PyExc_TypeError, "%s: wrong array type", what);
        return -1;
    }
    return 0;
}

/* _window(x0, y0, x1, y1, what) -> (faces, inside, edges, inside, features,
 * inside). */
static PyObject *T_window(PyObject *self, PyObject *args)
{
    long long w[4];
    unsigned int what;
    if (!PyArg_ParseTuple(args, "LLLLI", &w[0], &w[1], &w[2], &w[3], &what))
        return NULL;
    const hpfc_file *f;
    int *busy;
    hpfc_shapes *s = pyhpfc_shapes_begin(self, &f, &busy);
    if (!s)
        return NULL;
    hpfc_window_hits h;
    int st;
    Py_BEGIN_ALLOW_THREADS
    st = hpfc_shapes_window(s, w[0], w[1], w[2], w[3], what, &h);
    Py_END_ALLOW_THREADS
    pyhpfc_shapes_end(self, busy);
    if (st)
        return status_error(st, "window");
    return Py_BuildValue("(NNNNNN)", raw(h.face, h.face_count, 8),
                         raw(h.face_inside, h.face_count, 1), raw(h.edge, h.edge_count, 8),
                         raw(h.edge_inside, h.edge_count, 1), raw(h.feature, h.feature_count, 8),
                         raw(h.feature_inside, h.feature_count, 1));
}

/* _neighbours(feature) -> (features, touch, length, edge_start, edges). */
static PyObject *T_neighbours(PyObject *self, PyObject *args)
{
    unsigned long long k;
    if (!PyArg_ParseTuple(args, "K", &k))
        return NULL;
    const hpfc_file *f;
    int *busy;
    hpfc_shapes *s = pyhpfc_shapes_begin(self, &f, &busy);
    if (!s)
        return NULL;
    hpfc_neighbours nb;
    int st;
    Py_BEGIN_ALLOW_THREADS
    st = hpfc_shapes_feature_neighbours(s, k, &nb);
    Py_END_ALLOW_THREADS
    pyhpfc_shapes_end(self, busy);
    if (st == HPFC_E_ARG) {
        PyErr_Format(PyExc_IndexError, "feature %llu out of range", k);
        return NULL;
    }
    if (st)
        return status_error(st, "neighbours");
    return Py_BuildValue("(NNNNN)", raw(nb.feature, nb.count, 8), raw(nb.touch, nb.count, 1),
                         raw(nb.length, nb.count, 8), offsets(nb.edge_start, nb.count + 1),
                         raw(nb.edge, nb.edge_start[nb.count], 8));
}

/* _adjacency(touch) -> (a, b, touch, length). */
static PyObject *T_adjacency(PyObject *self, PyObject *args)
{
    unsigned int touch;
    if (!PyArg_ParseTuple(args, "I", &touch))
        return NULL;
    const hpfc_file *f;
    int *busy;
    hpfc_shapes *s = pyhpfc_shapes_begin(self, &f, &busy);
    if (!s)
        return NULL;
    hpfc_adjacency a;
    int st;
    Py_BEGIN_ALLOW_THREADS
    st = hpfc_shapes_adjacency(s, touch, &a);
    Py_END_ALLOW_THREADS
    pyhpfc_shapes_end(self, busy);
    if (st)
        return status_error(st, "adjacency");
    return Py_BuildValue("(NNNN)", raw(a.a, a.count, 8), raw(a.b, a.count, 8),
                         raw(a.touch, a.count, 1), raw(a.length, a.count, 8));
}

/* _nearest(xy, feature) -> (edge, segment, x, y, distance): for each
 * lattice point of xy (int64 pairs), the nearest edge of the map (feature
 * -1) or of a feature's border. */
static PyObject *T_nearest(PyObject *self, PyObject *args)
{
    PyObject *xy_obj;
    long long feature;
    if (!PyArg_ParseTuple(args, "OL", &xy_obj, &feature))
        return NULL;
    Py_buffer b;
    if (get_buffer(xy_obj, &b, 8, "q", "l", "points"))
        return NULL;
    size_t n = (size_t)(b.len / 16);
    const int64_t *xy = b.buf;
    PyObject *out[5] = {NULL};
    out[0] = PyBytes_FromStringAndSize(NULL, (Py_ssize_t)(8 * n));
    out[1] = PyBytes_FromStringAndSize(NULL, (Py_ssize_t)(8 * n));
    out[2] = PyBytes_FromStringAndSize(NULL, (Py_ssize_t)(8 * n));
    out[3] = PyBytes_FromStringAndSize(NULL, (Py_ssize_t)(8 * n));
    out[4] = PyBytes_FromStringAndSize(NULL, (Py_ssize_t)(8 * n));
    const hpfc_file *f;
    int *busy;
    hpfc_shapes *s = NULL;
    if (out[0] && out[1] && out[2] && out[3] && out[4])
        s = pyhpfc_shapes_begin(self, &f, &busy);
    if (!s) {
        PyBuffer_Release(&b);
        for (int k = 0; k < 5; k++)
            Py_XDECREF(out[k]);
        return NULL;
    }
    uint64_t *edge = (uint64_t *)PyBytes_AS_STRING(out[0]);
    uint64_t *seg = (uint64_t *)PyBytes_AS_STRING(out[1]);
    double *px = (double *)PyBytes_AS_STRING(out[2]), *py = (double *)PyBytes_AS_STRING(out[3]);
    double *dist = (double *)PyBytes_AS_STRING(out[4]);
    hpfc_id ft = feature < 0 ? HPFC_ID_NONE : (hpfc_id)feature;
    int st = HPFC_OK;
    size_t k = 0;
    Py_BEGIN_ALLOW_THREADS
    for (; k < n && !st; k++) {
        hpfc_nearest r;
        st = hpfc_shapes_nearest_edge(s, xy[2 * k], xy[2 * k + 1], ft, &r);
        if (!st)
            edge[k] = r.edge, seg[k] = r.segment, px[k] = r.x, py[k] = r.y, dist[k] = r.distance;
    }
    Py_END_ALLOW_THREADS
    pyhpfc_shapes_end(self, busy);
    PyBuffer_Release(&b);
    if (st) {
        for (int j = 0; j < 5; j++)
            Py_DECREF(out[j]);
        char context[64];
        snprintf(context, sizeof context, "nearest: point %zu", k - 1);
        return status_error(st, context);
    }
    return Py_BuildValue("(NNNNN)", out[0], out[1], out[2], out[3], out[4]);
}

/* _within(x, y, d) -> (edges, distances). */
static PyObject *T_within(PyObject *self, PyObject *args)
{
    long long x, y, d;
    if (!PyArg_ParseTuple(args, "LLL", &x, &y, &d))
        return NULL;
    const hpfc_file *f;
    int *busy;
    hpfc_shapes *s = pyhpfc_shapes_begin(self, &f, &busy);
    if (!s)
        return NULL;
    hpfc_edge_hits h;
    int st;
    Py_BEGIN_ALLOW_THREADS
    st = hpfc_shapes_edges_within(s, x, y, d, &h);
    Py_END_ALLOW_THREADS
    pyhpfc_shapes_end(self, busy);
    if (st)
        return status_error(st, "within");
    return Py_BuildValue("(NN)", raw(h.edge, h.count, 8), raw(h.distance, h.count, 8));
}

static PyObject *polygons_value(const hpfc_polygons *p)
{
    return Py_BuildValue("(NNN)", offsets(p->polygon_ring, p->polygon_count + 1),
                         offsets(p->ring_point, p->ring_count + 1),
                         raw(p->xy, 2 * p->point_count, 8));
}

/* _union(ids) -> (polygon_ring, ring_point, xy): the union of features. */
static PyObject *T_union(PyObject *self, PyObject *args)
{
    PyObject *ids_obj;
    if (!PyArg_ParseTuple(args, "O", &ids_obj))
        return NULL;
    Py_buffer b;
    if (get_buffer(ids_obj, &b, 8, "Q", "L", "features"))
        return NULL;
    const hpfc_file *f;
    int *busy;
    hpfc_shapes *s = pyhpfc_shapes_begin(self, &f, &busy);
    if (!s) {
        PyBuffer_Release(&b);
        return NULL;
    }
    hpfc_polygons p;
    int st;
    Py_BEGIN_ALLOW_THREADS
    st = hpfc_shapes_features_polygons(s, b.buf, (size_t)(b.len / 8), &p);
    Py_END_ALLOW_THREADS
    pyhpfc_shapes_end(self, busy);
    PyBuffer_Release(&b);
    if (st == HPFC_E_ARG) {
        PyErr_SetString(PyExc_IndexError, "union: a feature out of range");
        return NULL;
    }
    return st ? status_error(st, "union") : polygons_value(&p);
}

/* _mesh(groups or None, sides) -> (polygon_ring, ring_point, xy). */
static PyObject *T_mesh(PyObject *self, PyObject *args)
{
    PyObject *g_obj;
    unsigned int sides;
    if (!PyArg_ParseTuple(args, "OI", &g_obj, &sides))
        return NULL;
    Py_buffer b = {0};
    int have = g_obj != Py_None;
    if (have && get_buffer(g_obj, &b, 4, "I", "L", "groups"))
        return NULL;
    const hpfc_file *f;
    int *busy;
    hpfc_shapes *s = pyhpfc_shapes_begin(self, &f, &busy);
    if (!s) {
        if (have)
            PyBuffer_Release(&b);
        return NULL;
    }
    hpfc_polygons p;
    int st;
    Py_BEGIN_ALLOW_THREADS
    st = hpfc_shapes_mesh(s, have ? b.buf : NULL, have ? (size_t)(b.len / 4) : 0, sides, &p);
    Py_END_ALLOW_THREADS
    pyhpfc_shapes_end(self, busy);
    if (have)
        PyBuffer_Release(&b);
    return st ? status_error(st, "mesh") : polygons_value(&p);
}

PyMethodDef pyhpfc_topology_methods[] = {
    {"_window", T_window, METH_VARARGS, NULL},
    {"_neighbours", T_neighbours, METH_VARARGS, NULL},
    {"_adjacency", T_adjacency, METH_VARARGS, NULL},
    {"_nearest", T_nearest, METH_VARARGS, NULL},
    {"_within", T_within, METH_VARARGS, NULL},
    {"_union", T_union, METH_VARARGS, NULL},
    {"_mesh", T_mesh, METH_VARARGS, NULL},
    {NULL, NULL, 0, NULL}};
