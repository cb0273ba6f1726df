/*
 * traverse_darts: the traversal operators and the face builder on an opened
 * file.
 *
 * The input is an .hpfc file followed by command bytes (input.h), opened
 * with HPFC_OPEN_SKIP_CHECKSUM so mutated pools reach the word parser and
 * the crossing identification. The harness first collects the vertices and
 * darts of the leaves (in hpfc_leaf_first/next order) with the key calls
 * (hpfc_pixel_vertex_key, hpfc_key_degree, hpfc_key_vertex_dart), each
 * checked against its path form, and hpfc_key_vertex_darts against them. Without commands it
 * applies twin, next, prev, origin, target and the keys to every collected
 * dart, and the key calls to its key and to keys next to it, then builds
 * the faces (whole, and a root pixel at a time for up to 16 roots); with
 * commands each byte picks the next
 * operator from an input-chosen start (a collected dart, a vertex's k-th
 * dart, or a dart naming an arbitrary crossing, which the API must treat
 * as untrusted). At most FUZZ_STEPS operator calls per input.
 *
 * Oracle: statuses are known codes; every dart an operator returns is one
 * the operators accept (its origin exists), with a face when the faces were
 * built, and every private leaf has a face. The walker's cache changes no
 * answer: a second walker without cache gives the same status and the same
 * dart (whole pixel path) for every dart operator, and the same key for
 * every key operator, which equals the dart operator's answer on
 * hpfc_dart_from_key's dart (status included); the dense indices of every
 * key asked agree across the walkers, lie below the bound and come with the
 * _indexed operators' results; the key forms of the per-dart faces, LABL
 * and GEOM calls give the path form's answer on that dart. (The identities of a consistent
 * map, twin an involution and so on, are roundtrip_graph's oracle: a file
 * with matching checksums can still be a crafted inconsistent fixture.)
 */
#include "faces.h"
#include "input.h"
#include "key_ops.h"

#define FUZZ_STEPS 2000
#define MAX_DARTS 512
#define MAX_LEAVES 512

typedef struct trav {
    const hpfc_file *f;
    hpfc_walker *w;
    hpfc_walker *plain; /* the same file without the cache */
    long steps;
    bool complete;    /* every leaf and dart was collected */
    hpfc_dart darts[MAX_DARTS];
    uint64_t keys[MAX_DARTS]; /* the darts' keys, as the key calls gave them */
    size_t nd;
    hpfc_pixel leaves[MAX_LEAVES];
    size_t nleaves, nvertices;
    hpfc_faces *faces;
    int faces_status; /* -1: not built yet */
} trav;

static bool spend(trav *t)
{
    return t->steps-- > 0;
}

/* A status from an operator: a known code. */
static int status(int st)
{
    FUZZ_CHECK(fuzz_known_status(st));
    return st;
}

/* A dart an operator returned must be usable. */
static void check_result(trav *t, const hpfc_dart *d)
{
    hpfc_vertex v;
    FUZZ_CHECK(hpfc_dart_origin(t->w, d, &v) == HPFC_OK);
    if (t->faces) {
        uint64_t face;
        FUZZ_CHECK(hpfc_faces_dart_face(t->faces, d, &face) == HPFC_OK);
        FUZZ_CHECK(face < hpfc_faces_face_count(t->faces));
    }
}

static void collect(trav *t)
{
    hpfc_pixel px;
    int st = status(hpfc_leaf_first(t->f, &px));
    t->complete = true;
    while (!st) {
        if (!spend(t) || t->nleaves == MAX_LEAVES) {
            t->complete = false;
            return;
        }
        t->leaves[t->nleaves++] = px;
        uint32_t count = 0;
        st = status(hpfc_pixel_vertex_count(t->w, &px, &count));
        for (uint32_t k = 0; k < count && !st; k++) {
            hpfc_vertex v;
            uint64_t vertex = 0, beyond;
            uint32_t degree = 0, path_degree = 0;
            if (!spend(t)) {
                t->complete = false;
                return;
            }
            if ((st = status(hpfc_pixel_vertex_key(t->w, &px, k, &vertex))))
                break;
            FUZZ_CHECK(hpfc_pixel_vertex(t->plain, &px, k, &v) == HPFC_OK &&
                       hpfc_vertex_key(t->f, &v) == vertex);
            /* A key call answers as the path form on the pixel the key
             * resolves to; on a corrupt layout that need not be px, or the
             * resolution fails and its status is the key call's. */
            hpfc_vertex rv;
            int from = hpfc_vertex_from_key(t->plain, vertex, &rv);
            st = status(hpfc_key_degree(t->w, vertex, &degree));
            FUZZ_CHECK(from ? st == from
                            : st == hpfc_vertex_degree(t->plain, &rv, &path_degree) &&
                                  (st || degree == path_degree));
            if (st)
                break;
            t->nvertices++;
            for (uint32_t e = 0; e < degree && !st; e++) {
                if (t->nd == MAX_DARTS || !spend(t)) {
                    t->complete = false;
                    return;
                }
                st = status(hpfc_key_vertex_dart(t->w, vertex, e, &t->keys[t->nd]));
                int path_st = hpfc_vertex_dart(t->plain, &rv, e, &t->darts[t->nd]);
                FUZZ_CHECK(st == path_st &&
                           (st || hpfc_dart_key(t->f, &t->darts[t->nd]) == t->keys[t->nd]));
                if (!st)
                    t->nd++;
            }
            FUZZ_CHECK(hpfc_key_vertex_dart(t->w, vertex, degree, &beyond) == HPFC_E_ARG);
            if (!st && degree <= 64) { /* all at once: the same keys in the same order */
                uint64_t all[64];
                uint32_t n = 0;
                FUZZ_CHECK(hpfc_key_vertex_darts(t->w, vertex, all, degree, &n) == HPFC_OK &&
                           n == degree &&
                           memcmp(all, t->keys + t->nd - degree, degree * sizeof *all) == 0);
                FUZZ_CHECK(degree == 0 || (hpfc_key_vertex_darts(t->w, vertex, all, degree - 1,
                                                                 &n) == HPFC_E_BUFFER_SMALL &&
                                           n == degree));
            }
        }
        if (st)
            t->complete = false;
        st = hpfc_leaf_next(t->f, &px);
        FUZZ_CHECK(fuzz_known_status(st));
    }
    if (st != HPFC_E_NO_PIXEL)
        t->complete = false;
}

/* The faces one root pixel at a time (faces.h, the merge's numbering):
 * known statuses, and every collected leaf of a root numbered has a face
 * below the plan's count when private. Its ids are not compared with the
 * whole file's: on a damaged file the two make different unions. The plan
 * is made on one thread and on two (its roots in blocks), refused by both
 * or made by both with one face count; the two threads' plan then numbers
 * its roots ahead, asked for in the collected leaves' order. At most
 * FUZZ_ROOTS roots are numbered again. */
enum { FUZZ_ROOTS = 16 };

static void stream_faces(trav *t)
{
    faces_stream *s = NULL, *one = NULL;
    int st = faces_stream_plan(t->f, 2, &s), st1 = faces_stream_plan(t->f, 1, &one);
    status(st);
    FUZZ_CHECK((st == HPFC_OK) == (s != NULL));
    FUZZ_CHECK((st == HPFC_OK) == (st1 == HPFC_OK));
    if (s && one)
        FUZZ_CHECK(faces_stream_face_count(s) == faces_stream_face_count(one));
    faces_stream_free(one);
    if (!s)
        return;
    uint64_t count = faces_stream_face_count(s);
    FUZZ_CHECK(count >= 1 || t->nleaves == 0);
    hpfc_file_info info;
    hpfc_file_get_info(t->f, &info);
    uint32_t done = 0;
    for (size_t k = 0; k < t->nleaves && done < FUZZ_ROOTS; k++) {
        const hpfc_pixel *px = &t->leaves[k];
        if (k > 0 && px->path[0].i == t->leaves[k - 1].path[0].i &&
            px->path[0].j == t->leaves[k - 1].path[0].j)
            continue; /* the root's first collected leaf numbers it */
        hpfc_faces *root = NULL;
        st = faces_stream_root(s, px->path[0].i, px->path[0].j, &root);
        status(st);
        done++;
        if (!root)
            continue;
        FUZZ_CHECK(hpfc_faces_face_count(root) == count);
        for (size_t q = k; q < t->nleaves && t->leaves[q].path[0].i == px->path[0].i &&
                           t->leaves[q].path[0].j == px->path[0].j;
             q++) {
            int is_private = 0;
            uint64_t face;
            if (hpfc_pixel_is_private(t->f, &t->leaves[q], &is_private) == HPFC_OK && is_private &&
                hpfc_faces_pixel_face(root, &t->leaves[q], &face) == HPFC_OK)
                FUZZ_CHECK(face < count);
        }
        hpfc_faces_free(root);
    }
    FUZZ_CHECK(faces_stream_root(s, info.root_cols, 0, &(hpfc_faces *){NULL}) == HPFC_E_ARG);
    faces_stream_free(s);
}

static void build_faces(trav *t)
{
    if (t->faces_status >= 0)
        return;
    t->faces_status = hpfc_faces_build(t->f, &t->faces);
    status(t->faces_status);
    FUZZ_CHECK((t->faces_status == HPFC_OK) == (t->faces != NULL));
    if (!t->faces)
        return;
    uint64_t count = hpfc_faces_face_count(t->faces);
    FUZZ_CHECK(count >= 1);
    for (size_t k = 0; k < t->nleaves; k++) {
        int is_private = 0;
        uint64_t face;
        if (hpfc_pixel_is_private(t->f, &t->leaves[k], &is_private) == HPFC_OK && is_private) {
            FUZZ_CHECK(hpfc_faces_pixel_face(t->faces, &t->leaves[k], &face) == HPFC_OK);
            FUZZ_CHECK(face < count);
        }
    }
    stream_faces(t);
}

static bool same_pixel(const hpfc_pixel *a, const hpfc_pixel *b)
{
    return a->depth == b->depth && a->depth < HPFC_MAX_LEVELS &&
           memcmp(a->path, b->path, (a->depth + 1) * sizeof a->path[0]) == 0;
}

/* Operator op (0 twin, 1 next, 2 prev, 3 target) on d by the cached walker:
 * the plain walker must give the very same answer. */
static int dart_op(trav *t, int op, const hpfc_dart *d, hpfc_dart *out, hpfc_vertex *v)
{
    hpfc_dart plain_out;
    hpfc_vertex plain_v;
    int st, plain_st;
    if (op == 3) {
        st = hpfc_dart_target(t->w, d, v);
        plain_st = hpfc_dart_target(t->plain, d, &plain_v);
        FUZZ_CHECK(st == plain_st && (st || (same_pixel(&v->pixel, &plain_v.pixel) && v->local == plain_v.local)));
        return st;
    }
    hpfc_walker *w[2] = {t->w, t->plain};
    hpfc_dart *o[2] = {out, &plain_out};
    int *s[2] = {&st, &plain_st};
    for (int k = 0; k < 2; k++)
        *s[k] = op == 0 ? hpfc_dart_twin(w[k], d, o[k]) : op == 1 ? hpfc_dart_next(w[k], d, o[k])
                                                                 : hpfc_dart_prev(w[k], d, o[k]);
    FUZZ_CHECK(st == plain_st && (st || (same_pixel(&out->pixel, &plain_out.pixel) && out->crossing == plain_out.crossing)));
    return st;
}

static int indexed_call(hpfc_walker *w, int op, uint64_t key, uint64_t *out, uint64_t *index)
{
    return op == 0   ? hpfc_key_twin_indexed(w, key, out, index)
           : op == 1 ? hpfc_key_next_indexed(w, key, out, index)
                     : hpfc_key_prev_indexed(w, key, out, index);
}

/* The dense indices of any key: the same bound, status and index from both
 * walkers; the status of hpfc_dart_from_key (`from`) or
 * hpfc_vertex_from_key unless the bound fails; below the bound; the
 * _indexed operators give the key operators' answers and hpfc_dart_index
 * of their result. */
static void index_calls(trav *t, uint64_t key, int from)
{
    uint64_t bound = 0, vbound = 0, b2 = 0, vb2 = 0;
    int bst = status(hpfc_key_index_bound(t->w, &bound, &vbound));
    FUZZ_CHECK(bst == hpfc_key_index_bound(t->plain, &b2, &vb2));
    FUZZ_CHECK(bst || (bound == b2 && vbound == vb2 && bound == vbound));
    uint64_t di = 0, di2 = 0, vi = 0, vi2 = 0;
    hpfc_vertex v;
    int vfrom = hpfc_vertex_from_key(t->plain, key, &v);
    int dst = status(hpfc_dart_index(t->w, key, &di));
    int vst = status(hpfc_vertex_index(t->w, key, &vi));
    FUZZ_CHECK(dst == hpfc_dart_index(t->plain, key, &di2) && (dst || di == di2));
    FUZZ_CHECK(vst == hpfc_vertex_index(t->plain, key, &vi2) && (vst || vi == vi2));
    FUZZ_CHECK(dst == (bst ? bst : from) && vst == (bst ? bst : vfrom));
    FUZZ_CHECK((dst || di < bound) && (vst || vi < vbound));
    for (int op = 0; op < 3; op++) {
        uint64_t a = 0, ai = 0, b = 0, bi = 0, plain = 0, want = 0;
        int sa = status(indexed_call(t->w, op, key, &a, &ai));
        int sb = indexed_call(t->plain, op, key, &b, &bi);
        int sp = key_op_call(t->plain, op, key, &plain);
        FUZZ_CHECK(sa == sb && sa == (bst ? bst : sp));
        FUZZ_CHECK(sa || (a == b && a == plain && ai == bi && ai < bound));
        FUZZ_CHECK(sa || (hpfc_dart_index(t->plain, a, &want) == HPFC_OK && ai == want));
    }
    t->steps -= 4;
}

/* The key forms of the per-dart calls of the faces, LABL and GEOM modules
 * on `key`: the path form's status and answer on d, the dart the key names
 * (from: hpfc_dart_from_key's status; not OK: that status). */
static int module_status(int st)
{
    FUZZ_CHECK(st == HPFC_E_NO_SECTION || fuzz_known_status(st)); /* a file without the section */
    return st;
}

static void module_calls(trav *t, uint64_t key, int from, const hpfc_dart *d)
{
    uint64_t a = 0, b = 0;
    int ra = 0, rb = 0, want;
    size_t na = 0, nb = 0;
    if (t->faces) {
        int got = module_status(hpfc_faces_key_face(t->faces, t->w, key, &a));
        want = from ? from : hpfc_faces_dart_face(t->faces, d, &b);
        FUZZ_CHECK(got == want && (got || a == b));
    }
    int got = module_status(hpfc_label_key_face(t->w, key, &a));
    want = from ? from : hpfc_label_dart_face(t->f, d, &b);
    FUZZ_CHECK(got == want && (got || a == b));
    got = module_status(hpfc_label_key_edge(t->w, key, &a));
    want = from ? from : hpfc_label_dart_edge(t->f, d, &b);
    FUZZ_CHECK(got == want && (got || a == b));
    got = module_status(hpfc_geometry_key_edge(t->w, key, &a, &ra));
    want = from ? from : hpfc_geometry_dart_edge(t->f, d, &b, &rb);
    FUZZ_CHECK(got == want && (got || (a == b && ra == rb)));
    got = module_status(hpfc_geometry_key_points(t->w, key, NULL, 0, &na));
    want = from ? from : hpfc_geometry_dart_points(t->f, d, NULL, 0, &nb);
    FUZZ_CHECK(got == want && (got || na == nb));
    t->steps -= 5;
}

/* The key calls on any key: both walkers give the same answers, each the
 * dart operator's on hpfc_dart_from_key's dart as a key (or, when the key
 * names no dart, from_key's status), and from_key gives back the key. */
static void key_calls(trav *t, uint64_t key)
{
    hpfc_dart d, d2;
    hpfc_vertex v;
    int from = status(hpfc_dart_from_key(t->plain, key, &d));
    int from2 = hpfc_dart_from_key(t->w, key, &d2);
    FUZZ_CHECK(from == from2 &&
               (from || (same_pixel(&d.pixel, &d2.pixel) && d.crossing == d2.crossing)));
    FUZZ_CHECK(from || hpfc_dart_key(t->f, &d) == key);
    if (!status(hpfc_vertex_from_key(t->w, key, &v)))
        FUZZ_CHECK(hpfc_vertex_key(t->f, &v) == key);
    for (int op = 0; op < 5; op++) {
        uint64_t a = 0, b = 0, want = 0;
        int sa = status(key_op_call(t->w, op, key, &a)), sb = key_op_call(t->plain, op, key, &b);
        FUZZ_CHECK(sa == sb && (sa || a == b));
        int want_st = from;
        if (!from) {
            hpfc_dart r;
            hpfc_vertex u;
            want_st = op == 0   ? hpfc_dart_twin(t->plain, &d, &r)
                      : op == 1 ? hpfc_dart_next(t->plain, &d, &r)
                      : op == 2 ? hpfc_dart_prev(t->plain, &d, &r)
                      : op == 3 ? hpfc_dart_origin(t->plain, &d, &u)
                                : hpfc_dart_target(t->plain, &d, &u);
            if (!want_st)
                want = op >= 3 ? hpfc_vertex_key(t->f, &u) : hpfc_dart_key(t->f, &r);
        }
        FUZZ_CHECK(sa == want_st && (sa || a == want));
    }
    index_calls(t, key, from);
    module_calls(t, key, from, &d);
    t->steps -= 6;
}

/* All operators on one dart. */
static void all_operators(trav *t, const hpfc_dart *d)
{
    hpfc_dart tw, nx, pv;
    hpfc_vertex o, g;
    if (!spend(t))
        return;
    int st_twin = status(dart_op(t, 0, d, &tw, NULL));
    int st_next = status(dart_op(t, 1, d, &nx, NULL));
    int st_prev = status(dart_op(t, 2, d, &pv, NULL));
    if (!status(hpfc_dart_origin(t->w, d, &o)))
        (void)hpfc_vertex_key(t->f, &o);
    if (!status(dart_op(t, 3, d, NULL, &g)))
        (void)hpfc_vertex_key(t->f, &g);
    uint64_t key = hpfc_dart_key(t->f, d);
    key_calls(t, key);
    key_calls(t, key + 1);                   /* the next crossing, if any */
    key_calls(t, key + ((uint64_t)1 << 20)); /* inside the slot */
    t->steps -= 4;
    if (!st_twin)
        check_result(t, &tw);
    if (!st_next)
        check_result(t, &nx);
    if (!st_prev)
        check_result(t, &pv);
}

static void explore(trav *t)
{
    for (size_t k = 0; k < t->nd && t->steps > 0; k++)
        all_operators(t, &t->darts[k]);
    build_faces(t);
    if (!t->faces || !t->complete)
        return;
    for (size_t k = 0; k < t->nd && spend(t); k++)
        check_result(t, &t->darts[k]);
}

static void run_commands(trav *t, fuzz_bytes *in)
{
    hpfc_dart cur = t->darts[0];
    hpfc_dart out;
    hpfc_vertex v;
    while (!fuzz_empty(in) && spend(t)) {
        uint8_t op = fuzz_u8(in);
        int st;
        switch (op % 10) {
        case 0:
            cur = t->darts[fuzz_u16(in) % t->nd];
            break;
        case 1:
        case 2:
        case 3:
            st = dart_op(t, op % 10 - 1, &cur, &out, NULL);
            if (!status(st)) {
                check_result(t, &out);
                cur = out;
            }
            break;
        case 4:
        case 5: {
            st = op % 10 == 4 ? hpfc_dart_origin(t->w, &cur, &v) : hpfc_dart_target(t->w, &cur, &v);
            uint32_t degree = 0;
            if (status(st) || status(hpfc_vertex_degree(t->w, &v, &degree)))
                break;
            FUZZ_CHECK(degree >= 1);
            uint32_t k = fuzz_u8(in) % (degree + 1);
            st = hpfc_vertex_dart(t->w, &v, k, &out);
            FUZZ_CHECK((st == HPFC_OK) == (k < degree));
            if (!st) {
                check_result(t, &out);
                cur = out;
            }
            break;
        }
        case 6: /* keys: the current dart's, or with the high bit any key */
            FUZZ_CHECK(hpfc_dart_key(t->f, &cur) == hpfc_dart_key(t->f, &cur));
            if (!hpfc_dart_origin(t->w, &cur, &v))
                (void)hpfc_vertex_key(t->f, &v);
            (void)hpfc_walker_pixels_visited(t->w);
            key_calls(t, op & 0x80 ? fuzz_u64(in) : hpfc_dart_key(t->f, &cur));
            break;
        case 7: { /* an untrusted dart: any crossing of a collected leaf */
            hpfc_dart raw = {.pixel = t->leaves[fuzz_u16(in) % t->nleaves], .crossing = fuzz_u8(in)};
            if (op & 0x80)
                raw.crossing = fuzz_u32(in);
            for (int k = 0; k < 4; k++)
                FUZZ_CHECK(fuzz_known_status(dart_op(t, k, &raw, &out, &v)));
            uint64_t key = 0;
            st = status(hpfc_pixel_dart_key(t->w, &raw.pixel, raw.crossing, &key));
            FUZZ_CHECK(st == hpfc_dart_origin(t->plain, &raw, &v) &&
                       (st || key == hpfc_dart_key(t->f, &raw)));
            if (t->faces) {
                uint64_t face;
                FUZZ_CHECK(fuzz_known_status(hpfc_faces_dart_face(t->faces, &raw, &face)));
            }
            t->steps -= 3;
            break;
        }
        case 8: { /* an untrusted vertex index */
            const hpfc_pixel *px = &t->leaves[fuzz_u16(in) % t->nleaves];
            uint32_t count = 0, index = fuzz_u8(in);
            if (!status(hpfc_pixel_vertex_count(t->w, px, &count))) {
                st = hpfc_pixel_vertex(t->w, px, index, &v);
                FUZZ_CHECK((st == HPFC_OK) == (index < count));
                uint64_t key = 0;
                FUZZ_CHECK(hpfc_pixel_vertex_key(t->w, px, index, &key) == st &&
                           (st || key == hpfc_vertex_key(t->f, &v)));
            }
            break;
        }
        default:
            build_faces(t);
            if (t->faces) {
                uint64_t face;
                st = hpfc_faces_dart_face(t->faces, &cur, &face);
                FUZZ_CHECK(st == HPFC_OK && face < hpfc_faces_face_count(t->faces));
            }
            break;
        }
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    uint8_t *file;
    size_t file_size;
    fuzz_bytes cmds;
    if (!fuzz_split_file(data, size, &file, &file_size, &cmds))
        return 0;
    hpfc_file *f = NULL;
    trav *t = NULL;
    if (hpfc_open_memory(file, file_size, HPFC_OPEN_SKIP_CHECKSUM, &f) != HPFC_OK)
        goto done;
    t = calloc(1, sizeof *t);
    if (!t)
        goto done;
    *t = (trav){.f = f, .steps = FUZZ_STEPS, .faces_status = -1};
    int st = hpfc_walker_create(f, &t->w);
    if (!st)
        st = hpfc_walker_create(f, &t->plain);
    if (!st)
        st = hpfc_walker_set_cache_size(t->plain, 0);
    FUZZ_CHECK(st == HPFC_OK || st == HPFC_E_NOMEM);
    if (st)
        goto done;
    collect(t);
    if (fuzz_empty(&cmds) || t->nd == 0)
        explore(t);
    else
        run_commands(t, &cmds);
done:
    if (t) {
        hpfc_faces_free(t->faces);
        hpfc_walker_free(t->w);
        hpfc_walker_free(t->plain);
    }
    free(t);
    hpfc_close(f);
    free(file);
    return 0;
}
