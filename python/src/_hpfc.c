/*
 * _hpfc: the C half of the Python package hpfc.
 *
 * A thin layer over libhpfcfile's public API (hpfc.h, hpfc_batch.h): the
 * types _File (an open, memory-mapped .hpfc file) and Pixel (a pixel of
 * it), and the calls the Python half (hpfc/_file.py) builds its API from.
 * Arrays come in and go out through the buffer protocol, so this file needs
 * no numpy headers: the Python half allocates the numpy arrays and hands
 * them over, and one call answers a whole array with the GIL released.
 *
 * Lifetime: Python never sees a pointer into the mapping; every string and
 * number is copied out. A _File counts the calls that run without the GIL,
 * and close() refuses while one runs, so the mapping never goes away under
 * a reader. Pixels hold a reference to their _File and fail cleanly once it
 * is closed.
 *
 * Every library status becomes hpfc.Error(code, name, message, context)
 * (hpfc/_errors.py).
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <structmember.h>

#include <stdint.h>
#include <string.h>

#include "cores.h"
#include "hpfc.h"
#include "hpfc_batch.h"
#include "lattice_point.h"
#include "projection.h"
#include "shapes.h"

static PyObject *ErrorType; /* hpfc._errors.Error */

/* ---- errors ----------------------------------------------------------------- */

/* Raises hpfc.Error for status st; returns NULL for the caller to return. */
static PyObject *raise_status(int st, const char *context)
{
    if (st == HPFC_E_NOMEM && !PyErr_Occurred())
        return PyErr_NoMemory();
    PyObject *err = PyObject_CallFunction(ErrorType, "isss", st, hpfc_status_name(st),
                                          hpfc_strerror(st), context ? context : "");
    if (err) {
        PyErr_SetObject(ErrorType, err);
        Py_DECREF(err);
    }
    return NULL;
}

PyObject *pyhpfc_raise(int st, const char *context)
{
    return raise_status(st, context);
}

/* ---- _File -------------------------------------------------------------------- */

typedef struct {
    PyObject_HEAD
    hpfc_file *f;
    hpfc_file_info info;
    hpfc_faces *faces;     /* numbered on first need */
    hpfc_walker *walker;   /* made on first traversal call (GIL held while used) */
    mapproj_plan *plan;    /* lon/lat projection, made on first need */
    int busy;              /* calls running without the GIL */
} FileObject;

typedef struct {
    PyObject_HEAD
    FileObject *file;
    hpfc_pixel px;
} PixelObject;

static PyTypeObject FileType;
static PyTypeObject PixelType;

static int file_ready(FileObject *self)
{
    if (!self->f) {
        PyErr_SetString(PyExc_ValueError, "I/O operation on a closed hpfc file");
        return -1;
    }
    return 0;
}

static void file_release(FileObject *self)
{
    hpfc_walker_free(self->walker);
    hpfc_faces_free(self->faces);
    if (self->plan)
        mapproj_free(self->plan);
    hpfc_close(self->f);
    self->walker = NULL;
    self->faces = NULL;
    self->plan = NULL;
    self->f = NULL;
}

static void File_dealloc(FileObject *self)
{
    file_release(self);
    Py_TYPE(self)->tp_free((PyObject *)self);
}

static int File_init(FileObject *self, PyObject *args, PyObject *kwds)
{
    static char *kwlist[] = {"path", "skip_checksum", NULL};
    PyObject *path_obj = NULL;
    int skip = 0;
    if (!PyArg_ParseTupleAndKeywords(args, kwds, "O&|p", kwlist, PyUnicode_FSConverter, &path_obj,
                                     &skip))
        return -1;
    if (self->f) {
        Py_DECREF(path_obj);
        PyErr_SetString(PyExc_ValueError, "the file is already open");
        return -1;
    }
    const char *path = PyBytes_AS_STRING(path_obj);
    if (strlen(path) != (size_t)PyBytes_GET_SIZE(path_obj)) {
        Py_DECREF(path_obj);
        PyErr_SetString(PyExc_ValueError, "embedded NUL in the path");
        return -1;
    }
    hpfc_file *f = NULL;
    int st;
    Py_BEGIN_ALLOW_THREADS
    st = hpfc_open(path, skip ? HPFC_OPEN_SKIP_CHECKSUM : 0, &f);
    Py_END_ALLOW_THREADS
    if (st) {
        raise_status(st, path);
        Py_DECREF(path_obj);
        return -1;
    }
    Py_DECREF(path_obj);
    self->f = f;
    hpfc_file_get_info(f, &self->info);
    return 0;
}

static PyObject *File_close(FileObject *self, PyObject *unused)
{
    (void)unused;
    if (self->busy) {
        PyErr_SetString(PyExc_RuntimeError, "the hpfc file is in use by another thread");
        return NULL;
    }
    file_release(self);
    Py_RETURN_NONE;
}

static PyObject *File_closed(FileObject *self, void *unused)
{
    (void)unused;
    return PyBool_FromLong(self->f == NULL);
}

#define DICT_SET(d, key, value)                                  \
    do {                                                         \
        PyObject *v_ = (value);                                  \
        if (!v_ || PyDict_SetItemString((d), (key), v_) < 0) {   \
            Py_XDECREF(v_);                                      \
            Py_DECREF(d);                                        \
            return NULL;                                         \
        }                                                        \
        Py_DECREF(v_);                                           \
    } while (0)

static PyObject *File_info(FileObject *self, PyObject *unused)
{
    (void)unused;
    if (file_ready(self))
        return NULL;
    const hpfc_file_info *i = &self->info;
    PyObject *d = PyDict_New();
    if (!d)
        return NULL;
    DICT_SET(d, "format_version", Py_BuildValue("(ii)", i->format_major, i->format_minor));
    DICT_SET(d, "compat_flags", PyLong_FromUnsignedLong(i->compat_flags));
    DICT_SET(d, "incompat_flags", PyLong_FromUnsignedLong(i->incompat_flags));
    DICT_SET(d, "root_cols", PyLong_FromUnsignedLong(i->root_cols));
    DICT_SET(d, "root_rows", PyLong_FromUnsignedLong(i->root_rows));
    DICT_SET(d, "cols", PyLong_FromUnsignedLong(i->cols));
    DICT_SET(d, "rows", PyLong_FromUnsignedLong(i->rows));
    DICT_SET(d, "levels", PyLong_FromUnsignedLong(i->levels));
    DICT_SET(d, "x0", PyLong_FromLongLong(i->x0));
    DICT_SET(d, "y0", PyLong_FromLongLong(i->y0));
    DICT_SET(d, "width", PyLong_FromLongLong(i->width));
    DICT_SET(d, "height", PyLong_FromLongLong(i->height));
    DICT_SET(d, "unit_exp10", PyLong_FromLong(i->unit_exp10));
    DICT_SET(d, "file_size", PyLong_FromUnsignedLongLong(i->file_size));
    DICT_SET(d, "section_count", PyLong_FromUnsignedLong(i->section_count));
    if (i->crs)
        DICT_SET(d, "crs", PyUnicode_DecodeUTF8(i->crs, (Py_ssize_t)i->crs_len, "replace"));
    else
        DICT_SET(d, "crs", Py_NewRef(Py_None));
    return d;
}

static PyObject *File_level(FileObject *self, PyObject *arg)
{
    if (file_ready(self))
        return NULL;
    unsigned long level = PyLong_AsUnsignedLong(arg);
    if (level == (unsigned long)-1 && PyErr_Occurred())
        return NULL;
    if (level >= self->info.levels) {
        PyErr_Format(PyExc_IndexError, "level %lu of a file with %u levels", level,
                     self->info.levels);
        return NULL;
    }
    hpfc_level_info l;
    int st = hpfc_file_get_level(self->f, (uint32_t)level, &l);
    if (st)
        return raise_status(st, "level");
    PyObject *d = PyDict_New();
    if (!d)
        return NULL;
    DICT_SET(d, "level", PyLong_FromUnsignedLong(level));
    DICT_SET(d, "word_pixels", PyLong_FromUnsignedLongLong(l.word_pixels));
    DICT_SET(d, "refined_pixels", PyLong_FromUnsignedLongLong(l.refined_pixels));
    DICT_SET(d, "images", PyLong_FromUnsignedLongLong(l.images));
    DICT_SET(d, "word_bits", PyLong_FromUnsignedLong(l.word_bits));
    DICT_SET(d, "address_bits", PyLong_FromUnsignedLong(l.address_bits));
    DICT_SET(d, "pool_offset", PyLong_FromUnsignedLongLong(l.pool_offset));
    DICT_SET(d, "pool_bits", PyLong_FromUnsignedLongLong(l.pool_bits));
    DICT_SET(d, "cell_w", PyLong_FromLongLong(l.cell_w));
    DICT_SET(d, "cell_h", PyLong_FromLongLong(l.cell_h));
    return d;
}

static PyObject *File_section(FileObject *self, PyObject *arg)
{
    if (file_ready(self))
        return NULL;
    unsigned long index = PyLong_AsUnsignedLong(arg);
    if (index == (unsigned long)-1 && PyErr_Occurred())
        return NULL;
    if (index >= self->info.section_count) {
        PyErr_Format(PyExc_IndexError, "section %lu of %u", index, self->info.section_count);
        return NULL;
    }
    hpfc_section_info s;
    int st = hpfc_file_get_section(self->f, (uint32_t)index, &s);
    if (st)
        return raise_status(st, "section");
    PyObject *d = PyDict_New();
    if (!d)
        return NULL;
    DICT_SET(d, "tag", PyUnicode_DecodeLatin1(s.tag, (Py_ssize_t)strlen(s.tag), NULL));
    DICT_SET(d, "flags", PyLong_FromUnsignedLong(s.flags));
    DICT_SET(d, "offset", PyLong_FromUnsignedLongLong(s.offset));
    DICT_SET(d, "length", PyLong_FromUnsignedLongLong(s.length));
    DICT_SET(d, "crc32c", PyLong_FromUnsignedLong(s.crc32c));
    return d;
}

static PyObject *File_verify_checksums(FileObject *self, PyObject *unused)
{
    (void)unused;
    if (file_ready(self))
        return NULL;
    int st;
    hpfc_diag diag;
    self->busy++;
    Py_BEGIN_ALLOW_THREADS
    st = hpfc_file_check_checksums(self->f, &diag);
    Py_END_ALLOW_THREADS
    self->busy--;
    if (st) /* the context names the header or the section that fails */
        return raise_status(st, diag.message[0] ? diag.message : "verify_checksums");
    Py_RETURN_NONE;
}

/* Numbers the faces once (O(file)), without the GIL, on one thread a core
 * as hpfc-inspect does (the numbers do not depend on the threads). */
static int file_faces(FileObject *self)
{
    if (file_ready(self))
        return -1;
    if (self->faces)
        return 0;
    hpfc_faces *fc = NULL;
    int st;
    self->busy++;
    Py_BEGIN_ALLOW_THREADS
    st = hpfc_faces_build_threads(self->f, default_threads(), &fc);
    Py_END_ALLOW_THREADS
    self->busy--;
    if (st) {
        raise_status(st, "faces");
        return -1;
    }
    if (self->faces) /* another thread numbered them meanwhile */
        hpfc_faces_free(fc);
    else
        self->faces = fc;
    return 0;
}

static PyObject *File_face_count(FileObject *self, void *unused)
{
    (void)unused;
    if (file_faces(self))
        return NULL;
    return PyLong_FromUnsignedLongLong(hpfc_faces_face_count(self->faces));
}

static int file_walker(FileObject *self)
{
    if (file_ready(self))
        return -1;
    if (self->walker)
        return 0;
    int st = hpfc_walker_create(self->f, &self->walker);
    if (st) {
        raise_status(st, "walker");
        return -1;
    }
    return 0;
}

/* For shapes.c (shapes.h). */
const hpfc_file *pyhpfc_file_of(PyObject *file, int **busy)
{
    if (!PyObject_TypeCheck(file, &FileType)) {
        PyErr_Format(PyExc_TypeError, "an hpfc file expected, got %s", Py_TYPE(file)->tp_name);
        return NULL;
    }
    FileObject *self = (FileObject *)file;
    if (file_ready(self))
        return NULL;
    *busy = &self->busy;
    return self->f;
}

/* ---- arrays ----------------------------------------------------------------- */

/* A contiguous buffer of n items of `size` bytes with struct format `fmt`
 * (one of its accepted letters), writable when asked. */
static int get_array(PyObject *obj, Py_buffer *view, const char *fmts, Py_ssize_t size,
                     int writable, const char *name)
{
    int flags = PyBUF_C_CONTIGUOUS | PyBUF_FORMAT | (writable ? PyBUF_WRITABLE : 0);
    if (PyObject_GetBuffer(obj, view, flags) < 0)
        return -1;
    const char *f = view->format ? view->format : "B";
    if (*f == '<' || *f == '=' || *f == '@')
        f++;
    if (view->itemsize != size || strlen(f) != 1 || !strchr(fmts, *f) || view->ndim > 1) {
        PyErr_Format(PyExc_TypeError, "%s: a one-dimensional contiguous array of %zd-byte items "
                     "(format '%s') expected, got format '%s'", name, size, fmts,
                     view->format ? view->format : "B");
        PyBuffer_Release(view);
        return -1;
    }
    return 0;
}

static int require_len(Py_buffer *v, Py_ssize_t n, const char *name)
{
    if (v->len / v->itemsize != n) {
        PyErr_Format(PyExc_ValueError, "%s: %zd items, expected %zd", name,
                     v->len / v->itemsize, n);
        return -1;
    }
    return 0;
}

/* The file's projection for (lon, lat) points, made on first need. */
static int file_plan(FileObject *self)
{
    if (self->plan)
        return 0;
    if (!self->info.crs) {
        PyErr_SetString(PyExc_ValueError,
                        "the file records no CRS, so no (lon, lat) can be placed in it");
        return -1;
    }
    char why[200] = "";
    self->plan = mapproj_from_text(self->info.crs, self->info.crs_len, why, sizeof why);
    if (!self->plan) {
        PyErr_Format(PyExc_ValueError, "cannot place (lon, lat) points: %s", why);
        return -1;
    }
    return 0;
}

/* _lattice_points(u, v, x, y, valid, lonlat): floors user coordinates (or
 * projects lon/lat, then floors) into lattice points, without the GIL. */
static PyObject *File_lattice_points(FileObject *self, PyObject *args)
{
    PyObject *o[5];
    int lonlat;
    if (!PyArg_ParseTuple(args, "OOOOOp", &o[0], &o[1], &o[2], &o[3], &o[4], &lonlat))
        return NULL;
    if (file_ready(self) || (lonlat && file_plan(self)))
        return NULL;
    Py_buffer b[5];
    static const char *names[5] = {"u", "v", "x", "y", "valid"};
    static const char *fmts[5] = {"d", "d", "lq", "lq", "B?"};
    static const Py_ssize_t sizes[5] = {8, 8, 8, 8, 1};
    int got = 0;
    PyObject *result = NULL;
    for (; got < 5; got++)
        if (get_array(o[got], &b[got], fmts[got], sizes[got], got >= 2, names[got]))
            goto done;
    Py_ssize_t n = b[0].len / 8;
    for (int k = 1; k < 5; k++)
        if (require_len(&b[k], n, names[k]))
            goto done;
    const mapproj_plan *plan = lonlat ? self->plan : NULL;
    int32_t e = self->info.unit_exp10;
    self->busy++;
    Py_BEGIN_ALLOW_THREADS
    lattice_points(plan, e, (size_t)n, b[0].buf, b[1].buf, b[2].buf, b[3].buf, b[4].buf);
    Py_END_ALLOW_THREADS
    self->busy--;
    result = Py_NewRef(Py_None);
done:
    for (int k = 0; k < got; k++)
        PyBuffer_Release(&b[k]);
    return result;
}

/* _locate_into(x, y, valid or None, face, face_count, feature,
 * feature_count, flags, depth): hpfc_locate_batch over the arrays. */
static PyObject *File_locate_into(FileObject *self, PyObject *args)
{
    PyObject *o[9];
    if (!PyArg_ParseTuple(args, "OOOOOOOOO", &o[0], &o[1], &o[2], &o[3], &o[4], &o[5], &o[6],
                          &o[7], &o[8]))
        return NULL;
    if (file_ready(self))
        return NULL;
    /* The stored labels answer without numbering the faces first. */
    hpfc_labels_info labels;
    int stored = hpfc_file_get_labels(self->f, &labels) == HPFC_OK;
    if (!stored && file_faces(self))
        return NULL;
    static const char *names[9] = {"x", "y", "valid", "face", "face_count", "feature",
                                   "feature_count", "flags", "depth"};
    static const char *fmts[9] = {"lq", "lq", "B?", "lq", "I", "lq", "I", "B", "B"};
    static const Py_ssize_t sizes[9] = {8, 8, 1, 8, 4, 8, 4, 1, 1};
    Py_buffer b[9];
    int have[9] = {0};
    PyObject *result = NULL;
    for (int k = 0; k < 9; k++) {
        if (k == 2 && o[k] == Py_None)
            continue;
        if (get_array(o[k], &b[k], fmts[k], sizes[k], k >= 3, names[k]))
            goto done;
        have[k] = 1;
    }
    Py_ssize_t n = b[0].len / 8;
    for (int k = 1; k < 9; k++)
        if (have[k] && require_len(&b[k], n, names[k]))
            goto done;
    hpfc_locate_out out = {b[3].buf, b[4].buf, b[5].buf, b[6].buf, b[7].buf, b[8].buf};
    size_t failed = 0;
    int st;
    self->busy++;
    Py_BEGIN_ALLOW_THREADS
    st = hpfc_locate_batch(self->f, stored ? NULL : self->faces, (size_t)n, b[0].buf, b[1].buf,
                           have[2] ? b[2].buf : NULL, &out, &failed);
    Py_END_ALLOW_THREADS
    self->busy--;
    if (st) {
        char context[64];
        snprintf(context, sizeof context, "locate: point %zu", failed);
        raise_status(st, context);
        goto done;
    }
    result = Py_NewRef(Py_None);
done:
    for (int k = 0; k < 9; k++)
        if (have[k])
            PyBuffer_Release(&b[k]);
    return result;
}

/* ---- Pixel ---------------------------------------------------------------------- */

static PyObject *pixel_new(FileObject *file, const hpfc_pixel *px)
{
    PixelObject *p = PyObject_New(PixelObject, &PixelType);
    if (!p)
        return NULL;
    p->file = (FileObject *)Py_NewRef((PyObject *)file);
    p->px = *px;
    return (PyObject *)p;
}

static void Pixel_dealloc(PixelObject *self)
{
    Py_XDECREF(self->file);
    PyObject_Free(self);
}

static int pixel_ready(PixelObject *self)
{
    return file_ready(self->file);
}

static PyObject *Pixel_depth(PixelObject *self, void *unused)
{
    (void)unused;
    return PyLong_FromUnsignedLong(self->px.depth);
}

static PyObject *Pixel_path(PixelObject *self, void *unused)
{
    (void)unused;
    PyObject *t = PyTuple_New((Py_ssize_t)self->px.depth + 1);
    for (uint32_t l = 0; t && l <= self->px.depth; l++) {
        PyObject *ij = Py_BuildValue("(II)", self->px.path[l].i, self->px.path[l].j);
        if (!ij) {
            Py_DECREF(t);
            return NULL;
        }
        PyTuple_SET_ITEM(t, l, ij);
    }
    return t;
}

/* "i,j/i,j/...": hpfc-inspect's text form of a pixel path. */
static PyObject *Pixel_str(PixelObject *self)
{
    char buf[HPFC_MAX_LEVELS * 24];
    size_t used = 0;
    buf[0] = '\0';
    for (uint32_t l = 0; l <= self->px.depth && l < HPFC_MAX_LEVELS; l++)
        used += (size_t)snprintf(buf + used, sizeof buf - used, "%s%u,%u", l ? "/" : "",
                                 self->px.path[l].i, self->px.path[l].j);
    return PyUnicode_FromString(buf);
}

static PyObject *Pixel_repr(PixelObject *self)
{
    PyObject *s = Pixel_str(self);
    if (!s)
        return NULL;
    PyObject *r = PyUnicode_FromFormat("<hpfc.Pixel %U>", s);
    Py_DECREF(s);
    return r;
}

static int pixel_same(const hpfc_pixel *a, const hpfc_pixel *b)
{
    if (a->depth != b->depth)
        return 0;
    for (uint32_t l = 0; l <= a->depth && l < HPFC_MAX_LEVELS; l++)
        if (a->path[l].image != b->path[l].image || a->path[l].i != b->path[l].i ||
            a->path[l].j != b->path[l].j)
            return 0;
    return 1;
}

static PyObject *Pixel_richcompare(PyObject *a, PyObject *b, int op)
{
    if (!PyObject_TypeCheck(b, &PixelType) || (op != Py_EQ && op != Py_NE))
        Py_RETURN_NOTIMPLEMENTED;
    PixelObject *p = (PixelObject *)a, *q = (PixelObject *)b;
    int same = p->file == q->file && pixel_same(&p->px, &q->px);
    return PyBool_FromLong(op == Py_EQ ? same : !same);
}

static Py_hash_t Pixel_hash(PixelObject *self)
{
    uint64_t h = 1469598103934665603ull;
    for (uint32_t l = 0; l <= self->px.depth && l < HPFC_MAX_LEVELS; l++) {
        h = (h ^ self->px.path[l].image) * 1099511628211ull;
        h = (h ^ ((uint64_t)self->px.path[l].i << 32 | self->px.path[l].j)) * 1099511628211ull;
    }
    Py_hash_t r = (Py_hash_t)(h >> 1);
    return r == -1 ? -2 : r;
}

static PyObject *Pixel_kind(PixelObject *self, void *unused)
{
    (void)unused;
    int type;
    if (pixel_ready(self))
        return NULL;
    int st = hpfc_pixel_type(self->file->f, &self->px, &type);
    if (st)
        return raise_status(st, "pixel type");
    return PyUnicode_FromString(type == HPFC_PIXEL_WORD ? "word" : "refined");
}

static PyObject *Pixel_is_private(PixelObject *self, void *unused)
{
    (void)unused;
    int priv;
    if (pixel_ready(self))
        return NULL;
    int st = hpfc_pixel_is_private(self->file->f, &self->px, &priv);
    if (st)
        return raise_status(st, "pixel is_private");
    return PyBool_FromLong(priv);
}

static PyObject *Pixel_bounds(PixelObject *self, void *unused)
{
    (void)unused;
    int64_t x0, y0, x1, y1;
    if (pixel_ready(self))
        return NULL;
    int st = hpfc_pixel_bounds(self->file->f, &self->px, &x0, &y0, &x1, &y1);
    if (st)
        return raise_status(st, "pixel bounds");
    return Py_BuildValue("(LLLL)", (long long)x0, (long long)y0, (long long)x1, (long long)y1);
}

static PyObject *Pixel_word(PixelObject *self, void *unused)
{
    (void)unused;
    if (pixel_ready(self))
        return NULL;
    size_t len = 0;
    int st = hpfc_pixel_word(self->file->f, &self->px, NULL, 0, &len);
    if (st)
        return raise_status(st, "pixel word");
    char *buf = PyMem_Malloc(len + 1);
    if (!buf)
        return PyErr_NoMemory();
    st = hpfc_pixel_word(self->file->f, &self->px, buf, len + 1, &len);
    PyObject *r = st ? raise_status(st, "pixel word") : PyUnicode_FromStringAndSize(buf, (Py_ssize_t)len);
    PyMem_Free(buf);
    return r;
}

static PyObject *Pixel_child(PixelObject *self, PyObject *args)
{
    unsigned int i, j;
    if (!PyArg_ParseTuple(args, "II", &i, &j) || pixel_ready(self))
        return NULL;
    hpfc_pixel out;
    int st = hpfc_pixel_child(self->file->f, &self->px, i, j, &out);
    if (st)
        return raise_status(st, "pixel child");
    return pixel_new(self->file, &out);
}

static PyObject *Pixel_parent(PixelObject *self, void *unused)
{
    (void)unused;
    hpfc_pixel out;
    int st = hpfc_pixel_parent(&self->px, &out);
    if (st == HPFC_E_NO_PIXEL)
        Py_RETURN_NONE;
    if (st)
        return raise_status(st, "pixel parent");
    return pixel_new(self->file, &out);
}

static PyObject *Pixel_move(PixelObject *self, PyObject *arg)
{
    long dir = PyLong_AsLong(arg);
    if ((dir == -1 && PyErr_Occurred()) || pixel_ready(self))
        return NULL;
    if (dir < 0 || dir > 3) {
        PyErr_SetString(PyExc_ValueError, "direction: 0 (west), 1 (north), 2 (east), 3 (south)");
        return NULL;
    }
    hpfc_pixel out;
    int st = hpfc_pixel_move(self->file->f, &self->px, (int)dir, &out);
    if (st == HPFC_E_NO_PIXEL)
        Py_RETURN_NONE;
    if (st)
        return raise_status(st, "pixel move");
    return pixel_new(self->file, &out);
}

/* Keys of the pixel's vertices (word pixels), in the pixel's order. */
static PyObject *Pixel_vertices(PixelObject *self, PyObject *unused)
{
    (void)unused;
    if (file_walker(self->file))
        return NULL;
    uint32_t n;
    int st = hpfc_pixel_vertex_count(self->file->walker, &self->px, &n);
    if (st)
        return raise_status(st, "pixel vertices");
    PyObject *list = PyList_New(n);
    for (uint32_t k = 0; list && k < n; k++) {
        uint64_t vertex;
        if ((st = hpfc_pixel_vertex_key(self->file->walker, &self->px, k, &vertex))) {
            Py_DECREF(list);
            return raise_status(st, "pixel vertex");
        }
        PyObject *key = PyLong_FromUnsignedLongLong(vertex);
        if (!key) {
            Py_DECREF(list);
            return NULL;
        }
        PyList_SET_ITEM(list, k, key);
    }
    return list;
}

/* The faces meeting a word pixel: its one face (private), else the faces of
 * its crossings' darts, ascending; as hpfc-inspect --locate lists them. */
static PyObject *Pixel_faces(PixelObject *self, PyObject *unused)
{
    (void)unused;
    if (file_faces(self->file))
        return NULL;
    const hpfc_file *f = self->file->f;
    int priv;
    int st = hpfc_pixel_is_private(f, &self->px, &priv);
    if (st)
        return raise_status(st, "pixel faces");
    if (priv) {
        uint64_t face;
        if ((st = hpfc_faces_pixel_face(self->file->faces, &self->px, &face)))
            return raise_status(st, "pixel faces");
        return Py_BuildValue("[K]", (unsigned long long)face);
    }
    size_t len;
    if ((st = hpfc_pixel_word(f, &self->px, NULL, 0, &len)))
        return raise_status(st, "pixel faces");
    PyObject *set = PySet_New(NULL);
    for (size_t k = 0; set && k + 4 < len; k++) {
        hpfc_dart d = {.pixel = self->px, .crossing = (uint32_t)k};
        uint64_t face;
        PyObject *o = NULL;
        if ((st = hpfc_faces_dart_face(self->file->faces, &d, &face)) ||
            !(o = PyLong_FromUnsignedLongLong(face)) || PySet_Add(set, o) < 0) {
            Py_XDECREF(o);
            Py_DECREF(set);
            return st ? raise_status(st, "pixel faces") : NULL;
        }
        Py_DECREF(o);
    }
    if (!set)
        return NULL;
    PyObject *list = PySequence_List(set);
    Py_DECREF(set);
    if (list && PyList_Sort(list) < 0) {
        Py_DECREF(list);
        return NULL;
    }
    return list;
}

static PyGetSetDef Pixel_getset[] = {
    {"depth", (getter)Pixel_depth, NULL, "level of the pixel (0: the root image)", NULL},
    {"path", (getter)Pixel_path, NULL, "((i, j) per level from the root)", NULL},
    {"kind", (getter)Pixel_kind, NULL, "'word' (a leaf) or 'refined'", NULL},
    {"is_private", (getter)Pixel_is_private, NULL, "a word pixel with no crossing", NULL},
    {"bounds", (getter)Pixel_bounds, NULL, "(x0, y0, x1, y1), lattice units, half-open", NULL},
    {"word", (getter)Pixel_word, NULL, "the word's symbols, '+=[]()Y'", NULL},
    {"parent", (getter)Pixel_parent, NULL, "the refined pixel holding it, None at the root", NULL},
    {NULL, NULL, NULL, NULL, NULL}};

static PyMethodDef Pixel_methods[] = {
    {"child", (PyCFunction)Pixel_child, METH_VARARGS, "child(i, j): pixel of a refined pixel's image"},
    {"move", (PyCFunction)Pixel_move, METH_O,
     "move(direction): the adjacent pixel (hpfc.WEST/NORTH/EAST/SOUTH), None at the border"},
    {"vertex_keys", (PyCFunction)Pixel_vertices, METH_NOARGS, "keys of the leaf's vertices"},
    {"faces", (PyCFunction)Pixel_faces, METH_NOARGS,
     "faces meeting the leaf (one for a private leaf), ascending"},
    {NULL, NULL, 0, NULL}};

static PyTypeObject PixelType = {
    PyVarObject_HEAD_INIT(NULL, 0)
    .tp_name = "hpfc.Pixel",
    .tp_basicsize = sizeof(PixelObject),
    .tp_dealloc = (destructor)Pixel_dealloc,
    .tp_repr = (reprfunc)Pixel_repr,
    .tp_str = (reprfunc)Pixel_str,
    .tp_hash = (hashfunc)Pixel_hash,
    .tp_richcompare = Pixel_richcompare,
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "A pixel of an open hpfc file: the stack of (i, j) from the root.",
    .tp_getset = Pixel_getset,
    .tp_methods = Pixel_methods,
};

/* ---- pixels from the file -------------------------------------------------------- */

static PyObject *File_root(FileObject *self, PyObject *args)
{
    unsigned int i, j;
    if (!PyArg_ParseTuple(args, "II", &i, &j) || file_ready(self))
        return NULL;
    hpfc_pixel px;
    int st = hpfc_pixel_root(self->f, i, j, &px);
    if (st)
        return raise_status(st, "root pixel");
    return pixel_new(self, &px);
}

static int lattice_arg(PyObject *o, int64_t *v)
{
    long long x = PyLong_AsLongLong(o);
    if (x == -1 && PyErr_Occurred())
        return -1;
    *v = x;
    return 0;
}

/* _leaf_at(x, y): the leaf holding lattice point (x, y), None outside. */
static PyObject *File_leaf_at(FileObject *self, PyObject *args)
{
    PyObject *ox, *oy;
    int64_t x, y;
    if (!PyArg_ParseTuple(args, "OO", &ox, &oy) || lattice_arg(ox, &x) || lattice_arg(oy, &y) ||
        file_ready(self))
        return NULL;
    hpfc_pixel px;
    int st = hpfc_locate(self->f, x, y, &px);
    if (st == HPFC_E_NO_PIXEL)
        Py_RETURN_NONE;
    if (st)
        return raise_status(st, "locate");
    return pixel_new(self, &px);
}

/* _locate_point(x, y): hpfc_locate_point's answer for lattice point
 * (x, y) as (faces, on_boundary, vertex or None, edge or None, leaf), None
 * outside the domain. */
static PyObject *File_locate_point(FileObject *self, PyObject *args)
{
    PyObject *ox, *oy;
    int64_t x, y;
    if (!PyArg_ParseTuple(args, "OO", &ox, &oy) || lattice_arg(ox, &x) || lattice_arg(oy, &y) ||
        file_ready(self))
        return NULL;
    hpfc_point_location loc;
    uint64_t small[16], *faces = small;
    size_t count = 0;
    int st = hpfc_locate_point(self->f, x, y, &loc, faces, 16, &count);
    if (st == HPFC_E_BUFFER_SMALL) {
        if (!(faces = PyMem_Malloc(count * sizeof *faces)))
            return PyErr_NoMemory();
        st = hpfc_locate_point(self->f, x, y, &loc, faces, count, &count);
    }
    PyObject *list = NULL, *result = NULL;
    if (st == HPFC_E_NO_PIXEL) {
        result = Py_NewRef(Py_None);
        goto done;
    }
    if (st) {
        raise_status(st, "locate_point");
        goto done;
    }
    if (!(list = PyList_New((Py_ssize_t)count)))
        goto done;
    for (size_t k = 0; k < count; k++) {
        PyObject *o = PyLong_FromUnsignedLongLong(faces[k]);
        if (!o)
            goto done;
        PyList_SET_ITEM(list, (Py_ssize_t)k, o);
    }
    PyObject *px = pixel_new(self, &loc.leaf);
    if (!px)
        goto done;
    PyObject *vertex = loc.on_vertex ? PyLong_FromUnsignedLongLong(loc.vertex) : Py_NewRef(Py_None);
    PyObject *edge = loc.on_boundary && !loc.on_vertex ? PyLong_FromUnsignedLongLong(loc.edge)
                                                       : Py_NewRef(Py_None);
    if (vertex && edge)
        result = Py_BuildValue("(OOOOO)", list, loc.on_boundary ? Py_True : Py_False, vertex,
                               edge, px);
    Py_XDECREF(vertex);
    Py_XDECREF(edge);
    Py_DECREF(px);
done:
    Py_XDECREF(list);
    if (faces != small)
        PyMem_Free(faces);
    return result;
}

/* _has_geometry(): the file has GEOM and LABL, so locations are exact. */
static PyObject *File_has_geometry(FileObject *self, PyObject *unused)
{
    (void)unused;
    if (file_ready(self))
        return NULL;
    hpfc_geometry_info gi;
    hpfc_labels_info li;
    int st = hpfc_file_get_geometry(self->f, &gi);
    if (!st)
        st = hpfc_file_get_labels(self->f, &li);
    if (st && st != HPFC_E_NO_SECTION)
        return raise_status(st, "geometry");
    return PyBool_FromLong(st == HPFC_OK);
}

static PyObject *File_leaf_first(FileObject *self, PyObject *unused)
{
    (void)unused;
    if (file_ready(self))
        return NULL;
    hpfc_pixel px;
    int st = hpfc_leaf_first(self->f, &px);
    if (st)
        return raise_status(st, "leaves");
    return pixel_new(self, &px);
}

static PyObject *File_leaf_next(FileObject *self, PyObject *arg)
{
    if (!PyObject_TypeCheck(arg, &PixelType)) {
        PyErr_SetString(PyExc_TypeError, "a Pixel expected");
        return NULL;
    }
    if (file_ready(self))
        return NULL;
    hpfc_pixel px = ((PixelObject *)arg)->px;
    int st = hpfc_leaf_next(self->f, &px);
    if (st == HPFC_E_NO_PIXEL)
        Py_RETURN_NONE;
    if (st)
        return raise_status(st, "leaves");
    return pixel_new(self, &px);
}

/* ---- features ------------------------------------------------------------------- */

static PyObject *File_features_info(FileObject *self, PyObject *unused)
{
    (void)unused;
    if (file_ready(self))
        return NULL;
    hpfc_features_info fi;
    int st = hpfc_file_get_features(self->f, &fi);
    if (st == HPFC_E_NO_SECTION)
        Py_RETURN_NONE;
    if (st)
        return raise_status(st, "features");
    PyObject *d = PyDict_New();
    if (!d)
        return NULL;
    DICT_SET(d, "features", PyLong_FromUnsignedLong(fi.features));
    DICT_SET(d, "faces", PyLong_FromUnsignedLong(fi.faces));
    DICT_SET(d, "layers", PyLong_FromUnsignedLong(fi.layers));
    DICT_SET(d, "links", PyLong_FromUnsignedLong(fi.links));
    if (fi.key_field)
        DICT_SET(d, "key_field",
                 PyUnicode_DecodeUTF8(fi.key_field, (Py_ssize_t)fi.key_field_len, "replace"));
    else
        DICT_SET(d, "key_field", Py_NewRef(Py_None));
    return d;
}

static int u32_arg(PyObject *o, uint32_t *v, const char *what)
{
    unsigned long long x = PyLong_AsUnsignedLongLong(o);
    if (x == (unsigned long long)-1 && PyErr_Occurred()) {
        if (PyErr_ExceptionMatches(PyExc_OverflowError)) {
            PyErr_Clear();
            PyErr_Format(PyExc_IndexError, "%s out of range", what);
        }
        return -1;
    }
    if (x > UINT32_MAX) {
        PyErr_Format(PyExc_IndexError, "%s out of range", what);
        return -1;
    }
    *v = (uint32_t)x;
    return 0;
}

/* _feature(index) -> (fid, layer, key or None). */
static PyObject *File_feature(FileObject *self, PyObject *arg)
{
    uint32_t index;
    if (file_ready(self) || u32_arg(arg, &index, "feature index"))
        return NULL;
    hpfc_feature ft;
    int st = hpfc_file_get_feature(self->f, index, &ft);
    if (st)
        return raise_status(st, "feature");
    PyObject *key = ft.key ? PyUnicode_DecodeUTF8(ft.key, (Py_ssize_t)ft.key_len, "replace")
                           : Py_NewRef(Py_None);
    if (!key)
        return NULL;
    return Py_BuildValue("(LIN)", (long long)ft.fid, ft.layer, key);
}

static PyObject *File_layer_name(FileObject *self, PyObject *arg)
{
    uint32_t index;
    if (file_ready(self) || u32_arg(arg, &index, "layer index"))
        return NULL;
    const char *name;
    size_t len;
    int st = hpfc_layer_name(self->f, index, &name, &len);
    if (st)
        return raise_status(st, "layer name");
    return PyUnicode_DecodeUTF8(name, (Py_ssize_t)len, "replace");
}

static PyObject *File_face_features(FileObject *self, PyObject *arg)
{
    unsigned long long face = PyLong_AsUnsignedLongLong(arg);
    if ((face == (unsigned long long)-1 && PyErr_Occurred()) || file_ready(self))
        return NULL;
    uint32_t n;
    int st = hpfc_face_feature_count(self->f, face, &n);
    if (st)
        return raise_status(st, "face features");
    PyObject *list = PyList_New(n);
    for (uint32_t k = 0; list && k < n; k++) {
        hpfc_id feature;
        if ((st = hpfc_face_feature_id(self->f, face, k, &feature))) {
            Py_DECREF(list);
            return raise_status(st, "face features");
        }
        PyList_SET_ITEM(list, k, PyLong_FromUnsignedLongLong(feature));
    }
    return list;
}

/* ---- traversal by keys --------------------------------------------------------- */

static int key_arg(PyObject *o, uint64_t *key)
{
    unsigned long long k = PyLong_AsUnsignedLongLong(o);
    if (k == (unsigned long long)-1 && PyErr_Occurred())
        return -1;
    *key = k;
    return 0;
}

typedef int (*key_op)(hpfc_walker *, uint64_t, uint64_t *);

static PyObject *key_call(FileObject *self, PyObject *arg, key_op op, const char *what)
{
    uint64_t key, out;
    if (key_arg(arg, &key) || file_walker(self))
        return NULL;
    int st = op(self->walker, key, &out);
    if (st)
        return raise_status(st, what);
    return PyLong_FromUnsignedLongLong(out);
}

static PyObject *File_twin(FileObject *s, PyObject *a) { return key_call(s, a, hpfc_key_twin, "twin"); }
static PyObject *File_next(FileObject *s, PyObject *a) { return key_call(s, a, hpfc_key_next, "next"); }
static PyObject *File_prev(FileObject *s, PyObject *a) { return key_call(s, a, hpfc_key_prev, "prev"); }
static PyObject *File_origin(FileObject *s, PyObject *a) { return key_call(s, a, hpfc_key_origin, "origin"); }
static PyObject *File_target(FileObject *s, PyObject *a) { return key_call(s, a, hpfc_key_target, "target"); }
static PyObject *File_dart_index(FileObject *s, PyObject *a) { return key_call(s, a, hpfc_dart_index, "dart_index"); }
static PyObject *File_vertex_index(FileObject *s, PyObject *a) { return key_call(s, a, hpfc_vertex_index, "vertex_index"); }

/* The face on the right of a dart. */
static PyObject *File_dart_face(FileObject *self, PyObject *arg)
{
    uint64_t key, face;
    if (key_arg(arg, &key) || file_faces(self) || file_walker(self))
        return NULL;
    int st = hpfc_faces_key_face(self->faces, self->walker, key, &face);
    if (st)
        return raise_status(st, "dart_face");
    return PyLong_FromUnsignedLongLong(face);
}

/* The darts leaving a vertex, clockwise, as keys. */
static PyObject *File_vertex_darts(FileObject *self, PyObject *arg)
{
    uint64_t key;
    if (key_arg(arg, &key) || file_walker(self))
        return NULL;
    uint32_t degree;
    int st = hpfc_key_degree(self->walker, key, &degree);
    if (st)
        return raise_status(st, "vertex_darts");
    PyObject *list = PyList_New(degree);
    for (uint32_t k = 0; list && k < degree; k++) {
        uint64_t dart;
        if ((st = hpfc_key_vertex_dart(self->walker, key, k, &dart))) {
            Py_DECREF(list);
            return raise_status(st, "vertex_darts");
        }
        PyList_SET_ITEM(list, k, PyLong_FromUnsignedLongLong(dart));
    }
    return list;
}

/* The leaf holding a dart's origin (or a vertex). */
static PyObject *File_key_pixel(FileObject *self, PyObject *args)
{
    PyObject *o;
    int vertex;
    uint64_t key;
    if (!PyArg_ParseTuple(args, "Op", &o, &vertex) || key_arg(o, &key) || file_walker(self))
        return NULL;
    int st;
    hpfc_pixel px;
    if (vertex) {
        hpfc_vertex v;
        st = hpfc_vertex_from_key(self->walker, key, &v);
        px = v.pixel;
    } else {
        hpfc_dart d;
        st = hpfc_dart_from_key(self->walker, key, &d);
        px = d.pixel;
    }
    if (st)
        return raise_status(st, vertex ? "vertex pixel" : "dart pixel");
    return pixel_new(self, &px);
}

static PyObject *File_key_index_bound(FileObject *self, PyObject *unused)
{
    (void)unused;
    uint64_t darts, vertices;
    if (file_walker(self))
        return NULL;
    int st = hpfc_key_index_bound(self->walker, &darts, &vertices);
    if (st)
        return raise_status(st, "key_index_bound");
    return Py_BuildValue("(KK)", (unsigned long long)darts, (unsigned long long)vertices);
}

static PyMethodDef File_methods[] = {
    {"close", (PyCFunction)File_close, METH_NOARGS, "close(): unmaps the file"},
    {"_info", (PyCFunction)File_info, METH_NOARGS, NULL},
    {"_level", (PyCFunction)File_level, METH_O, NULL},
    {"_section", (PyCFunction)File_section, METH_O, NULL},
    {"verify_checksums", (PyCFunction)File_verify_checksums, METH_NOARGS,
     "verify_checksums(): reads the whole file; raises hpfc.Error on a mismatch, its\n"
     "context naming the header or the section that fails"},
    {"_lattice_points", (PyCFunction)File_lattice_points, METH_VARARGS, NULL},
    {"_locate_into", (PyCFunction)File_locate_into, METH_VARARGS, NULL},
    {"_leaf_at", (PyCFunction)File_leaf_at, METH_VARARGS, NULL},
    {"_locate_point", (PyCFunction)File_locate_point, METH_VARARGS, NULL},
    {"_has_geometry", (PyCFunction)File_has_geometry, METH_NOARGS, NULL},
    {"_leaf_first", (PyCFunction)File_leaf_first, METH_NOARGS, NULL},
    {"_leaf_next", (PyCFunction)File_leaf_next, METH_O, NULL},
    {"root", (PyCFunction)File_root, METH_VARARGS, "root(i, j): pixel (i, j) of the root image"},
    {"_features_info", (PyCFunction)File_features_info, METH_NOARGS, NULL},
    {"_feature", (PyCFunction)File_feature, METH_O, NULL},
    {"layer_name", (PyCFunction)File_layer_name, METH_O, "layer_name(index)"},
    {"face_features", (PyCFunction)File_face_features, METH_O,
     "face_features(face): the feature indices linked to a face, ascending"},
    {"twin", (PyCFunction)File_twin, METH_O, "twin(dart_key): the opposite dart's key"},
    {"next", (PyCFunction)File_next, METH_O, "next(dart_key): the next dart along its face"},
    {"prev", (PyCFunction)File_prev, METH_O, "prev(dart_key): the previous dart along its face"},
    {"origin", (PyCFunction)File_origin, METH_O, "origin(dart_key): its origin vertex's key"},
    {"target", (PyCFunction)File_target, METH_O, "target(dart_key): its target vertex's key"},
    {"dart_index", (PyCFunction)File_dart_index, METH_O, "dart_index(dart_key): dense index"},
    {"vertex_index", (PyCFunction)File_vertex_index, METH_O, "vertex_index(vertex_key)"},
    {"dart_face", (PyCFunction)File_dart_face, METH_O, "dart_face(dart_key): face on its right"},
    {"vertex_darts", (PyCFunction)File_vertex_darts, METH_O,
     "vertex_darts(vertex_key): keys of the darts leaving it, clockwise"},
    {"_key_pixel", (PyCFunction)File_key_pixel, METH_VARARGS, NULL},
    {"key_index_bound", (PyCFunction)File_key_index_bound, METH_NOARGS,
     "key_index_bound(): (darts, vertices) bounds of the dense indices"},
    {NULL, NULL, 0, NULL}};

static PyGetSetDef File_getset[] = {
    {"closed", (getter)File_closed, NULL, "whether close() was called", NULL},
    {"face_count", (getter)File_face_count, NULL, "number of faces (numbered on first use)", NULL},
    {NULL, NULL, NULL, NULL, NULL}};

static PyTypeObject FileType = {
    PyVarObject_HEAD_INIT(NULL, 0)
    .tp_name = "hpfc._hpfc._File",
    .tp_basicsize = sizeof(FileObject),
    .tp_dealloc = (destructor)File_dealloc,
    .tp_flags = Py_TPFLAGS_DEFAULT | Py_TPFLAGS_BASETYPE,
    .tp_doc = "An open .hpfc file (the C half of hpfc.File).",
    .tp_methods = File_methods,
    .tp_getset = File_getset,
    .tp_init = (initproc)File_init,
    .tp_new = PyType_GenericNew,
};

/* ---- module --------------------------------------------------------------------- */

static PyObject *mod_strerror(PyObject *m, PyObject *arg)
{
    (void)m;
    long code = PyLong_AsLong(arg);
    if (code == -1 && PyErr_Occurred())
        return NULL;
    return PyUnicode_FromString(hpfc_strerror((int)code));
}

static PyObject *mod_status_name(PyObject *m, PyObject *arg)
{
    (void)m;
    long code = PyLong_AsLong(arg);
    if (code == -1 && PyErr_Occurred())
        return NULL;
    return PyUnicode_FromString(hpfc_status_name((int)code));
}

/* lattice_floor(v, unit_exp10): the lattice coordinate of a user one, or
 * None beyond the lattice (exposed for the tests). */
static PyObject *mod_lattice_floor(PyObject *m, PyObject *args)
{
    (void)m;
    double v;
    int e, shortest = 1;
    if (!PyArg_ParseTuple(args, "di|p", &v, &e, &shortest))
        return NULL;
    int64_t out;
    if (lattice_floor(v, e, shortest, &out))
        Py_RETURN_NONE;
    return PyLong_FromLongLong(out);
}

static PyMethodDef module_methods[] = {
    {"strerror", mod_strerror, METH_O, "strerror(code): the library's text for a status"},
    {"status_name", mod_status_name, METH_O, "status_name(code): e.g. 'HPFC_E_CORRUPT'"},
    {"lattice_floor", mod_lattice_floor, METH_VARARGS, NULL},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef module_def = {
    PyModuleDef_HEAD_INIT, "hpfc._hpfc", "C half of the hpfc package (libhpfcfile).", -1,
    module_methods, NULL, NULL, NULL, NULL};

PyMODINIT_FUNC PyInit__hpfc(void);

PyMODINIT_FUNC PyInit__hpfc(void)
{
    PyObject *errors = PyImport_ImportModule("hpfc._errors");
    if (!errors)
        return NULL;
    ErrorType = PyObject_GetAttrString(errors, "Error");
    Py_DECREF(errors);
    if (!ErrorType)
        return NULL;
    if (PyType_Ready(&FileType) < 0 || PyType_Ready(&PixelType) < 0)
        return NULL;
    PyObject *m = PyModule_Create(&module_def);
    if (!m)
        return NULL;
    if (pyhpfc_shapes_add(m) < 0 || pyhpfc_pack_add(m) < 0) {
        Py_DECREF(m);
        return NULL;
    }
    if (PyModule_AddObject(m, "_File", Py_NewRef((PyObject *)&FileType)) < 0 ||
        PyModule_AddObject(m, "Pixel", Py_NewRef((PyObject *)&PixelType)) < 0 ||
        PyModule_AddStringConstant(m, "library_version", hpfc_version_string()) < 0 ||
        PyModule_AddIntConstant(m, "LOC_INSIDE", HPFC_LOC_INSIDE) < 0 ||
        PyModule_AddIntConstant(m, "LOC_PRIVATE", HPFC_LOC_PRIVATE) < 0 ||
        PyModule_AddIntConstant(m, "LOC_SINGLE", HPFC_LOC_SINGLE) < 0 ||
        PyModule_AddIntConstant(m, "LOC_EXACT", HPFC_LOC_EXACT) < 0 ||
        PyModule_AddIntConstant(m, "LOC_BOUNDARY", HPFC_LOC_BOUNDARY) < 0) {
        Py_DECREF(m);
        return NULL;
    }
    return m;
}
