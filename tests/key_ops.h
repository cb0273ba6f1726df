/*
 * key_ops.h: the key operators by number (0 twin, 1 next, 2 prev, 3 origin,
 * 4 target), for the tests and fuzzers that try each on the same key.
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

#endif
