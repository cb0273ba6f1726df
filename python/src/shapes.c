/*
 * shapes.c: geometry back from the file for the Python package: the type
 * _Shapes over the library's hpfc_shapes_*
 * (a face's rings, a feature's union of faces or its lines),
 * hpfc_geometry_* (an edge's exact polyline, a vertex) and
 * hpfc_geometry_key_points, plus the features' ATTR values and the
 * index's resource limits (hpfc_shapes_set_limits).
 *
 * Answers leave as flat int64 arrays (bytes) in one layout for every
 * kind, that of GeoArrow's ragged arrays, assembled by ragged.c (plain C,
 * fuzzed by fuzz/read_shapes.c). Python builds numpy arrays and shapely
 * objects from them; nothing here computes geometry.
 *
 * Lifetime: a _Shapes holds its _File, checks before every call that the
 * file is still the one it indexed (close() frees the mapping), and counts
 * its own GIL-free calls in the file's busy counter so close() refuses
 * while one runs. An hpfc_shapes answers one call at a time: a second
 * thread gets RuntimeError instead of a torn answer.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "hpfc.h"
#include "projection.h"
#include "ragged.h"
#include "shapes.h"

typedef struct {
    PyObject_HEAD
    PyObject *file;          /* the _File */
    const hpfc_file *f;      /* the mapping it was built on */
    hpfc_shapes *shapes;
    hpfc_walker *walker;     /* dart keys, made on first need */
    mapproj_plan *plan;      /* back to lon/lat, made on first need */
    int busy;                /* a call is running */
} ShapesObject;

static PyTypeObject ShapesType;

/* The file behind a _Shapes, or NULL with ValueError when it was closed. */
static const hpfc_file *shapes_file(ShapesObject *self, int **busy)
{
    if (!self->file || !self->shapes) {
        PyErr_SetString(PyExc_ValueError, "the geometry index is not open");
        return NULL;
    }
    const hpfc_file *f = pyhpfc_file_of(self->file, busy);
    if (!f)
        return NULL;
    if (f != self->f) {
        PyErr_SetString(PyExc_ValueError, "the hpfc file was closed and reopened");
        return NULL;
    }
    if (self->busy) {
        PyErr_SetString(PyExc_RuntimeError, "the geometry index is in use by another thread");
        return NULL;
    }
    return f;
}

/* The File caches its _Shapes, which holds the File: a cycle the
 * collector breaks (the library's index frees nothing of the mapping). */
static int Shapes_traverse(ShapesObject *self, visitproc visit, void *arg)
{
    Py_VISIT(self->file);
    return 0;
}

static int Shapes_clear(ShapesObject *self)
{
    Py_CLEAR(self->file);
    return 0;
}

static void Shapes_dealloc(ShapesObject *self)
{
    PyObject_GC_UnTrack(self);
    hpfc_shapes_free(self->shapes);
    hpfc_walker_free(self->walker);
    if (self->plan)
        mapproj_free(self->plan);
    Py_CLEAR(self->file);
    Py_TYPE(self)->tp_free((PyObject *)self);
}

/* _Shapes(file): the library's index over the file's geometry (O(edges +
 * faces + links), without the GIL). */
static int Shapes_init(ShapesObject *self, PyObject *args, PyObject *kwds)
{
    static char *kwlist[] = {"file", NULL};
    PyObject *file;
    if (!PyArg_ParseTupleAndKeywords(args, kwds, "O", kwlist, &file))
        return -1;
    if (self->shapes) {
        PyErr_SetString(PyExc_ValueError, "already initialised");
        return -1;
    }
    int *busy;
    const hpfc_file *f = pyhpfc_file_of(file, &busy);
    if (!f)
        return -1;
    hpfc_shapes *s = NULL;
    int st;
    (*busy)++;
    Py_BEGIN_ALLOW_THREADS
    st = hpfc_shapes_create(f, &s);
    Py_END_ALLOW_THREADS
    (*busy)--;
    if (st) {
        pyhpfc_raise(st, "geometry");
        return -1;
    }
    self->file = Py_NewRef(file);
    self->f = f;
    self->shapes = s;
    return 0;
}

static PyObject *bytes_of(const ragged_i64s *a)
{
    return PyBytes_FromStringAndSize((const char *)a->v, (Py_ssize_t)(a->n * sizeof(int64_t)));
}

/* _collect(kind, ids) -> (part, polygon or None, ring, xy, hole_only or
 * None) as bytes of int64: the answers for ids (a uint64 array) of kind 0
 * face, 1 feature (union of faces), 2 feature lines, 3 edge, 4 dart key,
 * in one pass without the GIL. */
static PyObject *Shapes_collect(ShapesObject *self, PyObject *args)
{
    int kind;
    PyObject *ids_obj;
    if (!PyArg_ParseTuple(args, "iO", &kind, &ids_obj))
        return NULL;
    if (kind < RAGGED_FACE || kind > RAGGED_DART) {
        PyErr_Format(PyExc_ValueError, "unknown geometry kind %d", kind);
        return NULL;
    }
    int *busy;
    if (!shapes_file(self, &busy))
        return NULL;
    if (kind == RAGGED_DART && !self->walker) {
        int st = hpfc_walker_create(self->f, &self->walker);
        if (st)
            return pyhpfc_raise(st, "darts");
    }
    Py_buffer ids;
    if (PyObject_GetBuffer(ids_obj, &ids, PyBUF_C_CONTIGUOUS | PyBUF_FORMAT) < 0)
        return NULL;
    const char *fmt = ids.format ? ids.format : "B";
    if (*fmt == '<' || *fmt == '=')
        fmt++;
    if (ids.itemsize != 8 || (strcmp(fmt, "Q") != 0 && strcmp(fmt, "L") != 0) || ids.ndim > 1) {
        PyBuffer_Release(&ids);
        PyErr_SetString(PyExc_TypeError, "ids: a one-dimensional uint64 array expected");
        return NULL;
    }
    size_t n = (size_t)(ids.len / 8);
    const uint64_t *id = ids.buf;
    int polygons = kind == RAGGED_FACE || kind == RAGGED_FEATURE;
    ragged r;
    int st = ragged_start(&r, polygons);
    const ragged_source src = {.file = self->f, .shapes = self->shapes, .walker = self->walker};
    size_t k = 0;
    self->busy = 1;
    (*busy)++;
    Py_BEGIN_ALLOW_THREADS
    for (; k < n && !st; k++)
        st = ragged_add(&r, &src, kind, id[k]);
    Py_END_ALLOW_THREADS
    (*busy)--;
    self->busy = 0;
    PyObject *result = NULL;
    if (st) {
        static const char *what[] = {"face", "feature", "feature lines", "edge", "dart"};
        char context[80];
        if (k)
            snprintf(context, sizeof context, "%s %llu", what[kind],
                     (unsigned long long)id[k - 1]);
        else
            snprintf(context, sizeof context, "%s", what[kind]);
        if (st == HPFC_E_ARG)
            PyErr_Format(PyExc_IndexError, "%s out of range", context);
        else
            pyhpfc_raise(st, context);
    } else {
        result = Py_BuildValue("(NNNNN)", bytes_of(&r.part),
                               polygons ? bytes_of(&r.polygon) : Py_NewRef(Py_None),
                               bytes_of(&r.ring), bytes_of(&r.xy),
                               polygons ? bytes_of(&r.hole_only) : Py_NewRef(Py_None));
    }
    PyBuffer_Release(&ids);
    ragged_free(&r);
    return result;
}

/* ---- coordinates --------------------------------------------------------------- */

static int shapes_plan(ShapesObject *self)
{
    if (self->plan)
        return 0;
    hpfc_file_info fi;
    hpfc_file_get_info(self->f, &fi);
    if (!fi.crs) {
        PyErr_SetString(PyExc_ValueError, "the file records no CRS, so no lon/lat coordinates");
        return -1;
    }
    char why[200] = "";
    self->plan = mapproj_from_text(fi.crs, fi.crs_len, why, sizeof why);
    if (!self->plan) {
        PyErr_Format(PyExc_ValueError, "no lon/lat coordinates: %s", why);
        return -1;
    }
    return 0;
}

/* _to_user(xy, out, lonlat): lattice points (int64 pairs) to user
 * coordinates (hpfc_user_point: lattice x 10^unit_exp10, correctly
 * rounded) or, with lonlat, to degrees through the file's projection;
 * out is a float64 array of the same length. */
static PyObject *Shapes_to_user(ShapesObject *self, PyObject *args)
{
    PyObject *in_obj, *out_obj;
    int lonlat;
    if (!PyArg_ParseTuple(args, "OOp", &in_obj, &out_obj, &lonlat))
        return NULL;
    int *busy;
    if (!shapes_file(self, &busy) || (lonlat && shapes_plan(self)))
        return NULL;
    Py_buffer in, out;
    if (PyObject_GetBuffer(in_obj, &in, PyBUF_C_CONTIGUOUS | PyBUF_FORMAT) < 0)
        return NULL;
    if (PyObject_GetBuffer(out_obj, &out, PyBUF_C_CONTIGUOUS | PyBUF_FORMAT | PyBUF_WRITABLE) <
        0) {
        PyBuffer_Release(&in);
        return NULL;
    }
    PyObject *result = NULL;
    const char *fi = in.format ? in.format : "B", *fo = out.format ? out.format : "B";
    if (*fi == '<' || *fi == '=')
        fi++;
    if (*fo == '<' || *fo == '=')
        fo++;
    if (in.itemsize != 8 || (strcmp(fi, "q") != 0 && strcmp(fi, "l") != 0) ||
        out.itemsize != 8 || strcmp(fo, "d") != 0 || in.len != out.len || (in.len / 8) % 2) {
        PyErr_SetString(PyExc_TypeError,
                        "_to_user: int64 pairs in, a float64 array of the same length out");
        goto done;
    }
    size_t n = (size_t)(in.len / 16), bad = SIZE_MAX;
    const int64_t *xy = in.buf;
    double *uv = out.buf;
    const mapproj_plan *plan = lonlat ? self->plan : NULL;
    self->busy = 1;
    (*busy)++;
    Py_BEGIN_ALLOW_THREADS
    /* as hpfc-inspect --export writes them (mapproj_inverse_points); a
     * point that does not project back is reported, the rest converted */
    hpfc_user_points(self->f, xy, n, uv);
    for (size_t k = 0; plan && k < n;) {
        size_t done = k + mapproj_inverse_points(plan, uv + 2 * k, n - k);
        if (done < n && bad == SIZE_MAX)
            bad = done;
        k = done + 1;
    }
    Py_END_ALLOW_THREADS
    (*busy)--;
    self->busy = 0;
    if (bad != SIZE_MAX)
        PyErr_Format(PyExc_ValueError, "lattice point (%lld, %lld) cannot be projected back",
                     (long long)xy[2 * bad], (long long)xy[2 * bad + 1]);
    else
        result = Py_NewRef(Py_None);
done:
    PyBuffer_Release(&in);
    PyBuffer_Release(&out);
    return result;
}

/* ---- small queries -------------------------------------------------------------- */

static int u64_arg(PyObject *o, uint64_t *v, const char *what)
{
    if (!PyLong_Check(o)) {
        PyErr_Format(PyExc_TypeError, "%s: an integer expected, got %s", what,
                     Py_TYPE(o)->tp_name);
        return -1;
    }
    unsigned long long x = PyLong_AsUnsignedLongLong(o);
    if (x == (unsigned long long)-1 && PyErr_Occurred()) {
        PyErr_Clear();
        PyErr_Format(PyExc_IndexError, "%s out of range", what);
        return -1;
    }
    *v = x;
    return 0;
}

static PyObject *Shapes_face_count(ShapesObject *self, PyObject *unused)
{
    (void)unused;
    int *busy;
    if (!shapes_file(self, &busy))
        return NULL;
    return PyLong_FromUnsignedLongLong(hpfc_shapes_face_count(self->shapes));
}

/* _feature_face_count(k): faces linked to feature k (0: a line feature). */
static PyObject *Shapes_feature_face_count(ShapesObject *self, PyObject *arg)
{
    uint64_t k;
    size_t count;
    int *busy;
    if (u64_arg(arg, &k, "feature") || !shapes_file(self, &busy))
        return NULL;
    int st = hpfc_shapes_feature_faces(self->shapes, k, NULL, 0, &count);
    if (st == HPFC_E_ARG) {
        PyErr_Format(PyExc_IndexError, "feature %llu out of range", (unsigned long long)k);
        return NULL;
    }
    if (st)
        return pyhpfc_raise(st, "feature");
    return PyLong_FromUnsignedLongLong(count);
}

/* _edge(e) -> (u, v, point_count, left face, right face). */
static PyObject *Shapes_edge(ShapesObject *self, PyObject *arg)
{
    uint64_t e, u, v, n, left, right;
    int *busy;
    if (u64_arg(arg, &e, "edge") || !shapes_file(self, &busy))
        return NULL;
    int st = hpfc_geometry_edge(self->f, e, &u, &v, &n);
    if (!st)
        st = hpfc_geometry_edge_faces(self->f, e, &left, &right);
    if (st == HPFC_E_ARG) {
        PyErr_Format(PyExc_IndexError, "edge %llu out of range", (unsigned long long)e);
        return NULL;
    }
    if (st)
        return pyhpfc_raise(st, "edge");
    return Py_BuildValue("(KKKKK)", (unsigned long long)u, (unsigned long long)v,
                         (unsigned long long)n, (unsigned long long)left,
                         (unsigned long long)right);
}

/* _vertex(v) -> (x, y) lattice. */
static PyObject *Shapes_vertex(ShapesObject *self, PyObject *arg)
{
    uint64_t v;
    int64_t x, y;
    int *busy;
    if (u64_arg(arg, &v, "vertex") || !shapes_file(self, &busy))
        return NULL;
    int st = hpfc_geometry_vertex(self->f, v, &x, &y);
    if (st == HPFC_E_ARG) {
        PyErr_Format(PyExc_IndexError, "vertex %llu out of range", (unsigned long long)v);
        return NULL;
    }
    if (st)
        return pyhpfc_raise(st, "vertex");
    return Py_BuildValue("(LL)", (long long)x, (long long)y);
}

/* _dart_edge(dart key) -> (edge, reversed). */
static PyObject *Shapes_dart_edge(ShapesObject *self, PyObject *arg)
{
    uint64_t key, e;
    int reversed, *busy;
    if (u64_arg(arg, &key, "dart") || !shapes_file(self, &busy))
        return NULL;
    int st = self->walker ? HPFC_OK : hpfc_walker_create(self->f, &self->walker);
    if (!st)
        st = hpfc_geometry_key_edge(self->walker, key, &e, &reversed);
    if (st)
        return pyhpfc_raise(st, "dart edge");
    return Py_BuildValue("(KO)", (unsigned long long)e, reversed ? Py_True : Py_False);
}

/* _set_limits(max_points, max_items): the caps of every later call
 * (hpfc_shapes_set_limits: 0 the default, HPFC_LIMIT_NONE none); the
 * Python half checks the range and remembers them, the library has no
 * getter. */
static PyObject *Shapes_set_limits(ShapesObject *self, PyObject *args)
{
    unsigned long long points, items;
    if (!PyArg_ParseTuple(args, "KK", &points, &items))
        return NULL;
    int *busy;
    if (!shapes_file(self, &busy))
        return NULL;
    hpfc_limits limits = {.max_points = points, .max_items = items};
    int st = hpfc_shapes_set_limits(self->shapes, &limits);
    if (st)
        return pyhpfc_raise(st, "limits");
    Py_RETURN_NONE;
}

hpfc_shapes *pyhpfc_shapes_begin(PyObject *o, const hpfc_file **f, int **busy)
{
    ShapesObject *self = (ShapesObject *)o;
    if (!(*f = shapes_file(self, busy)))
        return NULL;
    self->busy = 1;
    (**busy)++;
    return self->shapes;
}

void pyhpfc_shapes_end(PyObject *o, int *busy)
{
    (*busy)--;
    ((ShapesObject *)o)->busy = 0;
}

static PyMethodDef Shapes_methods[] = {
    {"_collect", (PyCFunction)Shapes_collect, METH_VARARGS, NULL},
    {"_to_user", (PyCFunction)Shapes_to_user, METH_VARARGS, NULL},
    {"_face_count", (PyCFunction)Shapes_face_count, METH_NOARGS, NULL},
    {"_feature_face_count", (PyCFunction)Shapes_feature_face_count, METH_O, NULL},
    {"_edge", (PyCFunction)Shapes_edge, METH_O, NULL},
    {"_vertex", (PyCFunction)Shapes_vertex, METH_O, NULL},
    {"_dart_edge", (PyCFunction)Shapes_dart_edge, METH_O, NULL},
    {"_set_limits", (PyCFunction)Shapes_set_limits, METH_VARARGS, NULL},
    {NULL, NULL, 0, NULL}};

static PyTypeObject ShapesType = {
    PyVarObject_HEAD_INIT(NULL, 0)
    .tp_name = "hpfc._hpfc._Shapes",
    .tp_basicsize = sizeof(ShapesObject),
    .tp_dealloc = (destructor)Shapes_dealloc,
    .tp_flags = Py_TPFLAGS_DEFAULT | Py_TPFLAGS_HAVE_GC,
    .tp_traverse = (traverseproc)Shapes_traverse,
    .tp_clear = (inquiry)Shapes_clear,
    .tp_doc = "The library's geometry index over an open file (hpfc_shapes).",
    .tp_methods = Shapes_methods,
    .tp_init = (initproc)Shapes_init,
    .tp_new = PyType_GenericNew,
};

/* ---- module-level: geometry and attributes of a _File ---------------------------- */

/* geometry_info(file) -> dict, or None without a GEOM section. */
static PyObject *mod_geometry_info(PyObject *m, PyObject *file)
{
    (void)m;
    int *busy;
    const hpfc_file *f = pyhpfc_file_of(file, &busy);
    if (!f)
        return NULL;
    hpfc_geometry_info gi;
    int st = hpfc_file_get_geometry(f, &gi);
    if (st == HPFC_E_NO_SECTION)
        Py_RETURN_NONE;
    if (st)
        return pyhpfc_raise(st, "geometry");
    return Py_BuildValue("{sKsKsKsK}", "vertices", (unsigned long long)gi.vertices, "edges",
                         (unsigned long long)gi.edges, "points", (unsigned long long)gi.points,
                         "section_bytes", (unsigned long long)gi.section_bytes);
}

/* geometry_bounds(file) -> (xmin, ymin, xmax, ymax), lattice coordinates
 * of every vertex and shape point (hpfc_geometry_bounds: GEOM's block
 * directories, not the points); None without a GEOM section. */
static PyObject *mod_geometry_bounds(PyObject *m, PyObject *file)
{
    (void)m;
    int *busy;
    const hpfc_file *f = pyhpfc_file_of(file, &busy);
    if (!f)
        return NULL;
    int64_t box[4];
    int st = hpfc_geometry_bounds(f, box);
    if (st == HPFC_E_NO_SECTION)
        Py_RETURN_NONE;
    if (st)
        return pyhpfc_raise(st, "geometry bounds");
    return Py_BuildValue("(LLLL)", (long long)box[0], (long long)box[1], (long long)box[2],
                         (long long)box[3]);
}

/* attribute_columns(file) -> [(name, type)], [] without an ATTR section. */
static PyObject *mod_attribute_columns(PyObject *m, PyObject *file)
{
    (void)m;
    int *busy;
    const hpfc_file *f = pyhpfc_file_of(file, &busy);
    if (!f)
        return NULL;
    hpfc_attrs_info ai;
    int st = hpfc_file_get_attrs(f, &ai);
    if (st == HPFC_E_NO_SECTION)
        return PyList_New(0);
    if (st)
        return pyhpfc_raise(st, "attributes");
    PyObject *list = PyList_New((Py_ssize_t)ai.columns);
    for (uint32_t c = 0; list && c < ai.columns; c++) {
        const char *name;
        size_t len;
        int type;
        if ((st = hpfc_attr_column(f, c, &name, &len, &type))) {
            Py_DECREF(list);
            return pyhpfc_raise(st, "attribute column");
        }
        const char *tname = type == HPFC_ATTR_INTEGER ? "integer"
                            : type == HPFC_ATTR_REAL  ? "real"
                                                      : "string";
        PyObject *item = Py_BuildValue("(Ns)", PyUnicode_DecodeUTF8(name, (Py_ssize_t)len,
                                                                    "replace"), tname);
        if (!item) {
            Py_DECREF(list);
            return NULL;
        }
        PyList_SET_ITEM(list, c, item);
    }
    return list;
}

/* attribute_rows(file) -> [tuple of values a feature]: every feature's
 * stored attributes (None for a null). */
static PyObject *mod_attribute_rows(PyObject *m, PyObject *file)
{
    (void)m;
    int *busy;
    const hpfc_file *f = pyhpfc_file_of(file, &busy);
    if (!f)
        return NULL;
    hpfc_attrs_info ai;
    int st = hpfc_file_get_attrs(f, &ai);
    if (st == HPFC_E_NO_SECTION)
        return PyList_New(0);
    if (st)
        return pyhpfc_raise(st, "attributes");
    PyObject *rows = PyList_New((Py_ssize_t)ai.features);
    for (hpfc_id k = 0; rows && k < ai.features; k++) {
        PyObject *row = PyTuple_New((Py_ssize_t)ai.columns);
        if (!row)
            goto fail;
        PyList_SET_ITEM(rows, (Py_ssize_t)k, row);
        for (uint32_t c = 0; c < ai.columns; c++) {
            hpfc_attr_value v;
            if ((st = hpfc_file_get_attr_value(f, k, c, &v))) {
                char context[64];
                snprintf(context, sizeof context, "feature %llu, attribute %u",
                         (unsigned long long)k, c);
                pyhpfc_raise(st, context);
                goto fail;
            }
            PyObject *o = v.type == HPFC_ATTR_INTEGER ? PyLong_FromLongLong(v.i)
                          : v.type == HPFC_ATTR_REAL  ? PyFloat_FromDouble(v.r)
                          : v.type == HPFC_ATTR_STRING
                              ? PyUnicode_DecodeUTF8(v.s, (Py_ssize_t)v.len, "replace")
                              : Py_NewRef(Py_None);
            if (!o)
                goto fail;
            PyTuple_SET_ITEM(row, c, o);
        }
    }
    return rows;
fail:
    Py_XDECREF(rows);
    return NULL;
}

static PyMethodDef shapes_module_methods[] = {
    {"geometry_info", mod_geometry_info, METH_O, NULL},
    {"geometry_bounds", mod_geometry_bounds, METH_O, NULL},
    {"attribute_columns", mod_attribute_columns, METH_O, NULL},
    {"attribute_rows", mod_attribute_rows, METH_O, NULL},
    {NULL, NULL, 0, NULL}};

int pyhpfc_shapes_add(PyObject *module)
{
    /* the topology methods (topology.c) join the table: a type has one */
    static PyMethodDef all[64];
    size_t n = 0;
    for (PyMethodDef *d = Shapes_methods; d->ml_name; d++)
        all[n++] = *d;
    for (PyMethodDef *d = pyhpfc_topology_methods; d->ml_name && n + 1 < 64; d++)
        all[n++] = *d;
    ShapesType.tp_methods = all;
    if (PyType_Ready(&ShapesType) < 0)
        return -1;
    if (PyModule_AddObject(module, "_Shapes", Py_NewRef((PyObject *)&ShapesType)) < 0)
        return -1;
    /* the limits' values from hpfc.h, so that Python cannot drift from them */
    if (PyModule_AddObject(module, "LIMIT_NONE",
                           PyLong_FromUnsignedLongLong(HPFC_LIMIT_NONE)) < 0 ||
        PyModule_AddObject(module, "LIMIT_POINTS_DEFAULT",
                           PyLong_FromUnsignedLongLong(HPFC_LIMIT_POINTS_DEFAULT)) < 0 ||
        PyModule_AddObject(module, "LIMIT_ITEMS_DEFAULT",
                           PyLong_FromUnsignedLongLong(HPFC_LIMIT_ITEMS_DEFAULT)) < 0)
        return -1;
    for (PyMethodDef *d = shapes_module_methods; d->ml_name; d++) {
        PyObject *fn = PyCFunction_NewEx(d, NULL, NULL);
        if (!fn || PyModule_AddObject(module, d->ml_name, fn) < 0) {
            Py_XDECREF(fn);
            return -1;
        }
    }
    return 0;
}
