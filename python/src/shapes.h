/*
 * shapes.h: the geometry half of the extension (shapes.c) and what it
 * needs from _hpfc.c, kept apart so that the two grow without touching
 * each other.
 */
#ifndef HPFC_PY_SHAPES_H
#define HPFC_PY_SHAPES_H

#include <Python.h>

#include "hpfc.h"

/* _hpfc.c: the open file behind a _File, with *busy its counter of calls
 * running without the GIL (close() refuses while it is not 0); NULL with
 * TypeError (not a _File) or ValueError (closed) set. */
const hpfc_file *pyhpfc_file_of(PyObject *file, int **busy);
/* _hpfc.c: raises hpfc.Error for library status st; returns NULL. */
PyObject *pyhpfc_raise(int st, const char *context);

/* shapes.c: the index of a _Shapes and its file, marked busy for a call
 * that runs without the GIL (pyhpfc_shapes_end after it, with the same
 * busy); NULL with an exception set (closed, in use by another thread). */
hpfc_shapes *pyhpfc_shapes_begin(PyObject *self, const hpfc_file **f, int **busy);
void pyhpfc_shapes_end(PyObject *self, int *busy);

/* topology.c: the topology questions, methods of _Shapes (_window,
 * _neighbours, _adjacency, _nearest, _within, _union, _mesh). */
extern PyMethodDef pyhpfc_topology_methods[];

/* shapes.c: adds _Shapes, geometry_info, attribute_columns and
 * attribute_rows to the module; -1 with an exception set. */
int pyhpfc_shapes_add(PyObject *module);

/* pack.c: adds _pack_cut, _pack_part and _pack_merge (hpfc.pack's C
 * half); -1 with an exception set. */
int pyhpfc_pack_add(PyObject *module);

#endif
