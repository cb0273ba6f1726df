/*
 * key_ops.h: the key operators by number (0 twin, 1 next, 2 prev, 3 origin,
 * 4 target), for the tests and fuzzers that try each on the same key, and
 * the dart operators by the same numbers, their answers as keys.
 */
#ifndef HPFC_TESTS_KEY_OPS_H
#define HPFC_TESTS_KEY_OPS_H

#include "hpfc.h"

static inline int key_op_call(hpfc_walker *w, int op, uint64_t key, uint64_t *out)
{
    switch (op) {
    case 0:
        return hpfc_key_twin(w, key, out);
    case 1:
        return hpfc_key_next(w, key, out);
    case 2:
        return hpfc_key_prev(w, key, out);
    case 3:
        return hpfc_key_origin(w, key, out);
    default:
        return hpfc_key_target(w, key, out);
    }
}

/* The dart operator of the same number on d, its answer as a key (0 when
 * it fails): the oracle of the key operators. */
static inline int dart_op_key(hpfc_walker *w, const hpfc_file *f, const hpfc_dart *d, int op,
                              uint64_t *key)
{
    hpfc_dart r;
    hpfc_vertex v;
    int st;
    switch (op) {
    case 0:
        st = hpfc_dart_twin(w, d, &r);
        break;
    case 1:
        st = hpfc_dart_next(w, d, &r);
        break;
    case 2:
        st = hpfc_dart_prev(w, d, &r);
        break;
    case 3:
        st = hpfc_dart_origin(w, d, &v);
        break;
    default:
        st = hpfc_dart_target(w, d, &v);
        break;
    }
    *key = st ? 0 : op >= 3 ? hpfc_vertex_key(f, &v) : hpfc_dart_key(f, &r);
    return st;
}

#endif
