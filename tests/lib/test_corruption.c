/*
 * The corruption campaign: every single-bit flip and every truncation of a
 * few small valid files (the .hpfc fixtures of $HPFC_TEST_DATA/valid and a
 * few generated ones).
 *
 * Every byte is also set to 0x00 and to 0xFF (many bits of a count, an
 * offset or a mask wrong at once). For each damaged copy:
 *   - opening it (hpfc_open_memory with the checksum verified, then
 *     hpfc_file_check_checksums) must fail with a file code; a flip is allowed
 *     through only in bytes no checksum covers (the zero padding between
 *     sections, spec/hpfc-format.md §4.1), and a truncation never;
 *   - opened with HPFC_OPEN_SKIP_CHECKSUM, it must traverse without a crash
 *     within a step budget: every leaf walked, every word decoded, the four
 *     moves from every leaf, twin / next / prev / origin / target and the
 *     keys on every dart, then hpfc_faces_build and the face of every dart.
 *     Every status is OK, NO_PIXEL or CORRUPT. The same walk without the
 *     walker's cache and with a tiny one must give the very same answers.
 * Each copy lives in a buffer of exactly its size, so AddressSanitizer (the
 * CI build, tools/run-tests.sh) sees any read past its end. A truncation is
 * also tried with the header's file_size patched to the cut, so the
 * shortened file gets past the size check to the level table and directory.
 *
 * It also checks the fuzz regressions: every line of fuzz/regressions/
 * EXPECTED names an input and the status a call on it must give.
 */
#include <dirent.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "format.h"
#include "gen.h"
#include "hpfc.h"
#include "key_ops.h"

#define BIT(code) ((uint64_t)1 << (code))
#define STEP_BUDGET 4000 /* operator calls per damaged copy */
#define MAX_DARTS 256

/* the layout under test (check_use_test_layout) */
static int test_layout_compact;

static const uint64_t ALLOWED = BIT(HPFC_OK) | BIT(HPFC_E_NO_PIXEL) | BIT(HPFC_E_CORRUPT);

/* What the campaign saw, for the summary line and the checks. */
static struct {
    long files, flips, flips_accepted, byte_sets, cuts, patched_cuts, skipped_opens, traversals;
    long budget_exhausted, corrupt, steps, cache_mismatches, key_calls, key_mismatches, key_corrupt;
    long index_calls, index_mismatches;
    long label_files, label_calls, label_corrupt, label_verified, label_disagreed;
    long geom_files, geom_calls, geom_corrupt, geom_verified, geom_disagreed;
    uint64_t open_codes, walk_codes;
} seen;

typedef struct walk {
    const hpfc_file *f;
    hpfc_walker *w;
    long steps;
    uint64_t codes;
    uint64_t digest;  /* of every answer the walker gave, in order */
    hpfc_dart darts[MAX_DARTS];
    size_t nd;
} walk;

static bool spend(walk *k)
{
    if (k->steps <= 0)
        return false;
    k->steps--;
    return true;
}

static int note(walk *k, int st)
{
    k->codes |= st >= 0 && st < 64 ? BIT(st) : BIT(63);
    return st;
}

static void mix(walk *k, uint64_t v)
{
    k->digest ^= v + 0x9E3779B97F4A7C15ull + (k->digest << 6) + (k->digest >> 2);
    k->digest *= 0xBF58476D1CE4E5B9ull;
}

/* A walker's answer: its status and, on success, the whole pixel path and
 * the crossing or local vertex (read through a pointer: only after the
 * call has written it). */
static int answer(walk *k, int st, const hpfc_pixel *px, const uint32_t *local)
{
    mix(k, (uint64_t)note(k, st));
    if (!st) {
        for (uint32_t l = 0; l <= px->depth && l < HPFC_MAX_LEVELS; l++)
            mix(k, px->path[l].image ^ (uint64_t)px->path[l].i << 32 ^ px->path[l].j);
        mix(k, *local);
    }
    return st;
}

/* The key calls on the dart's key and on keys near it (the next crossing,
 * the next bit position, a far one): known statuses (HPFC_E_ARG too, for
 * a key that names nothing), and each key operator equal to the dart
 * operator on hpfc_dart_from_key's dart, on corrupt files too. */
static void walk_keys(walk *k, const hpfc_dart *d)
{
    static const uint64_t ALLOWED_KEYS = BIT(HPFC_OK) | BIT(HPFC_E_ARG) | BIT(HPFC_E_CORRUPT);
    uint64_t key = hpfc_dart_key(k->f, d);
    const uint64_t keys[] = {key, key + 1, key + ((uint64_t)1 << 20), key ^ k->digest};
    for (size_t x = 0; x < sizeof keys / sizeof *keys; x++) {
        hpfc_dart from;
        hpfc_vertex v;
        int from_st = hpfc_dart_from_key(k->w, keys[x], &from);
        int vst = hpfc_vertex_from_key(k->w, keys[x], &v);
        uint64_t codes = BIT(from_st) | BIT(vst);
        for (int op = 0; op < 5; op++) {
            uint64_t got = 0, want = 0;
            int st = key_op_call(k->w, op, keys[x], &got), want_st = from_st;
            if (!from_st)
                want_st = dart_op_key(k->w, k->f, &from, op, &want);
            codes |= BIT(st);
            seen.key_corrupt += st == HPFC_E_CORRUPT;
            seen.key_mismatches += st != want_st || (!st && got != want);
            mix(k, (uint64_t)st), mix(k, got);
            seen.key_calls++;
        }
        /* dense indices: the statuses of hpfc_dart_from_key and
         * hpfc_vertex_from_key, below the bound; the _indexed operators
         * agree with the plain ones and with hpfc_dart_index */
        uint64_t dbound = 0, vbound = 0, di = 0, vi = 0;
        int bst = hpfc_key_index_bound(k->w, &dbound, &vbound);
        int dst = hpfc_dart_index(k->w, keys[x], &di);
        int vist = hpfc_vertex_index(k->w, keys[x], &vi);
        codes |= BIT(bst) | BIT(dst) | BIT(vist);
        seen.index_mismatches += dst != (bst ? bst : from_st) || vist != (bst ? bst : vst) ||
                                 (!dst && di >= dbound) || (!vist && vi >= vbound);
        for (int op = 0; op < 2; op++) {
            uint64_t got = 0, idx = 0, plain = 0, want_idx = 0;
            int st = op ? hpfc_key_next_indexed(k->w, keys[x], &got, &idx)
                        : hpfc_key_twin_indexed(k->w, keys[x], &got, &idx);
            int pst =
                op ? hpfc_key_next(k->w, keys[x], &plain) : hpfc_key_twin(k->w, keys[x], &plain);
            codes |= BIT(st);
            seen.index_mismatches += st != (bst ? bst : pst) || (!st && got != plain);
            if (!st)
                seen.index_mismatches += hpfc_dart_index(k->w, got, &want_idx) != HPFC_OK ||
                                         idx != want_idx || idx >= dbound;
            mix(k, (uint64_t)st), mix(k, idx);
        }
        seen.index_calls += 5;
        if (codes & ~ALLOWED_KEYS)
            fprintf(stderr, "key statuses 0x%llx\n", (unsigned long long)codes);
        CHECK((codes & ~ALLOWED_KEYS) == 0);
        note(k, from_st == HPFC_E_ARG ? HPFC_OK : from_st);
    }
}

static void walk_dart(walk *k, const hpfc_dart *d)
{
    hpfc_dart out;
    hpfc_vertex v;
    if (!spend(k))
        return;
    answer(k, hpfc_dart_twin(k->w, d, &out), &out.pixel, &out.crossing);
    answer(k, hpfc_dart_next(k->w, d, &out), &out.pixel, &out.crossing);
    answer(k, hpfc_dart_prev(k->w, d, &out), &out.pixel, &out.crossing);
    if (!answer(k, hpfc_dart_origin(k->w, d, &v), &v.pixel, &v.local))
        (void)hpfc_vertex_key(k->f, &v);
    if (!answer(k, hpfc_dart_target(k->w, d, &v), &v.pixel, &v.local))
        (void)hpfc_vertex_key(k->f, &v);
    walk_keys(k, d);
    k->steps -= 8;
}

static void walk_leaf(walk *k, const hpfc_pixel *px)
{
    char word[512];
    size_t len;
    int is_private;
    int64_t x0, y0, x1, y1;
    note(k, hpfc_pixel_word(k->f, px, NULL, 0, &len));
    int st = hpfc_pixel_word(k->f, px, word, sizeof word, &len);
    note(k, st == HPFC_E_ARG && len > sizeof word ? HPFC_OK : st); /* a long word: fine */
    note(k, hpfc_pixel_is_private(k->f, px, &is_private));
    note(k, hpfc_pixel_bounds(k->f, px, &x0, &y0, &x1, &y1));
    for (int dir = HPFC_WEST; dir <= HPFC_SOUTH && spend(k); dir++) {
        hpfc_pixel q;
        note(k, hpfc_pixel_move(k->f, px, dir, &q));
    }
    uint32_t count = 0;
    if (answer(k, hpfc_pixel_vertex_count(k->w, px, &count), px, &count))
        return;
    for (uint32_t i = 0; i < count && spend(k); i++) {
        hpfc_vertex v;
        uint32_t degree = 0;
        if (answer(k, hpfc_pixel_vertex(k->w, px, i, &v), &v.pixel, &v.local) ||
            answer(k, hpfc_vertex_degree(k->w, &v, &degree), px, &degree))
            continue;
        for (uint32_t e = 0; e < degree && spend(k); e++) {
            hpfc_dart d;
            if (answer(k, hpfc_vertex_dart(k->w, &v, e, &d), &d.pixel, &d.crossing))
                continue;
            if (k->nd < MAX_DARTS)
                k->darts[k->nd++] = d;
            walk_dart(k, &d);
        }
    }
}

static void walk_leaves(walk *k)
{
    hpfc_pixel px;
    int st = note(k, hpfc_leaf_first(k->f, &px));
    while (!st && spend(k)) {
        walk_leaf(k, &px);
        st = note(k, hpfc_leaf_next(k->f, &px));
    }
}

/* The walker's cache never changes an answer, even on a corrupt file: the
 * same walk without the cache, and with one so small that it is emptied or
 * bypassed all the time, gives the same digest. */
static void compare_caches(const hpfc_file *f, uint64_t digest)
{
    static const size_t sizes[] = {0, 700};
    for (size_t s = 0; s < sizeof sizes / sizeof *sizes; s++) {
        walk k = {.f = f, .steps = STEP_BUDGET};
        if (hpfc_walker_create(f, &k.w) || hpfc_walker_set_cache_size(k.w, sizes[s])) {
            hpfc_walker_free(k.w);
            continue;
        }
        walk_leaves(&k);
        seen.cache_mismatches += k.digest != digest;
        hpfc_walker_free(k.w);
    }
}

/* The LABL accessors on the walked leaves and darts, then the section
 * against hpfc_faces_build: never another status than OK, CORRUPT (or
 * NOMEM from the verifier), ids inside their counts, and a disagreement
 * reported with its reason. */
static void walk_labels(walk *k, const hpfc_faces *faces)
{
    hpfc_labels_info li;
    int st = hpfc_file_get_labels(k->f, &li);
    CHECK(st == HPFC_OK || st == HPFC_E_NO_SECTION);
    if (st)
        return;
    seen.label_files++;
    hpfc_pixel px;
    uint64_t id, ids[64];
    size_t n;
    int left = 64;
    for (st = hpfc_leaf_first(k->f, &px); !st && left-- > 0; st = hpfc_leaf_next(k->f, &px)) {
        int s1 = note(k, hpfc_label_leaf_faces(k->f, &px, NULL, 0, &n));
        if (!s1 && n <= 64 && !note(k, hpfc_label_leaf_faces(k->f, &px, ids, 64, &n)))
            for (size_t i = 0; i < n; i++)
                CHECK(ids[i] < li.faces);
        if (!note(k, hpfc_label_stretch_face(k->f, &px, 0, &id)))
            CHECK(id < li.faces);
        if (!note(k, hpfc_leaf_number(k->f, &px, &id))) {
            hpfc_level_info lv;
            hpfc_file_get_level(k->f, px.depth, &lv);
            CHECK(id < lv.word_pixels);
        }
        seen.label_calls += 3;
        seen.label_corrupt += s1 == HPFC_E_CORRUPT;
    }
    for (size_t d = 0; d < k->nd; d++) {
        if (!note(k, hpfc_label_dart_face(k->f, &k->darts[d], &id)))
            CHECK(id < li.faces);
        if (!note(k, hpfc_label_dart_edge(k->f, &k->darts[d], &id)))
            CHECK(id < li.edges);
        seen.label_calls += 2;
    }
    if (!faces)
        return;
    hpfc_labels_report rep;
    st = hpfc_labels_verify(k->f, faces, &rep);
    CHECK(st == HPFC_OK || st == HPFC_E_CORRUPT);
    CHECK(st != HPFC_E_CORRUPT || rep.message[0] != '\0');
    seen.label_verified += st == HPFC_OK;
    seen.label_disagreed += st == HPFC_E_CORRUPT;
}

/* The GEOM accessors on every vertex and edge (at most 64 points each) and
 * on the crossings of the first 64 leaves, then hpfc_geometry_verify:
 * never another status than OK or CORRUPT, every coordinate inside the
 * domain, every id inside its count, a disagreement reported with its
 * reason. */
static void walk_geometry(walk *k)
{
    hpfc_geometry_info gi;
    int st = hpfc_file_get_geometry(k->f, &gi);
    CHECK(st == HPFC_OK || st == HPFC_E_NO_SECTION);
    if (st)
        return;
    seen.geom_files++;
    hpfc_file_info fi;
    hpfc_file_get_info(k->f, &fi);
    long corrupt = 0;
    for (uint64_t v = 0; v < gi.vertices && v < 4096; v++) {
        int64_t x, y;
        if (!note(k, hpfc_geometry_vertex(k->f, v, &x, &y)))
            CHECK(x >= fi.x0 && x - fi.x0 < fi.width && y >= fi.y0 && y - fi.y0 < fi.height);
        seen.geom_calls++;
    }
    for (uint64_t e = 0; e < gi.edges && e < 4096; e++) {
        uint64_t u, v, n, left, right;
        int s1 = note(k, hpfc_geometry_edge(k->f, e, &u, &v, &n));
        corrupt += s1 == HPFC_E_CORRUPT;
        if (!s1)
            CHECK(u < gi.vertices && v < gi.vertices && n >= 2);
        for (uint64_t p = 0; !s1 && p < n && p < 64; p++) {
            int64_t x, y;
            if (!note(k, hpfc_geometry_edge_point(k->f, e, p, &x, &y)))
                CHECK(x >= fi.x0 && x - fi.x0 < fi.width && y >= fi.y0 && y - fi.y0 < fi.height);
        }
        st = hpfc_geometry_edge_faces(k->f, e, &left, &right);
        if (st != HPFC_E_NO_SECTION)
            note(k, st);
        seen.geom_calls += 2;
    }
    hpfc_pixel px;
    int left = 64;
    for (st = hpfc_leaf_first(k->f, &px); !st && left-- > 0; st = hpfc_leaf_next(k->f, &px)) {
        size_t len = 0;
        if (hpfc_pixel_word(k->f, &px, NULL, 0, &len) != HPFC_OK || len < 4)
            continue;
        for (uint32_t c = 0; c + 4 < len && c < 64; c++) {
            uint64_t seg;
            corrupt += note(k, hpfc_geometry_crossing_segment(k->f, &px, c, &seg)) == HPFC_E_CORRUPT;
            seen.geom_calls++;
        }
    }
    seen.geom_corrupt += corrupt;
    hpfc_geometry_report rep;
    st = hpfc_geometry_verify(k->f, &rep);
    CHECK(st == HPFC_OK || st == HPFC_E_CORRUPT);
    CHECK(st != HPFC_E_CORRUPT || rep.message[0] != '\0');
    seen.geom_verified += st == HPFC_OK;
    seen.geom_disagreed += st == HPFC_E_CORRUPT;
}

/* The traversal of one opened (possibly corrupt) file: the statuses seen. */
static uint64_t traverse(const hpfc_file *f)
{
    walk k = {.f = f, .steps = STEP_BUDGET};
    if (note(&k, hpfc_walker_create(f, &k.w)))
        goto done;
    walk_leaves(&k);
    compare_caches(f, k.digest);
    /* a few point locations across the domain */
    hpfc_file_info info;
    hpfc_file_get_info(f, &info);
    for (int i = 0; i < 8 && spend(&k); i++) {
        hpfc_pixel at;
        note(&k, hpfc_locate(f, info.x0 + info.width * i / 8, info.y0 + info.height * (i * 5 % 8) / 8, &at));
    }
    hpfc_faces *faces = NULL;
    if (k.steps > 0 && !note(&k, hpfc_faces_build(f, &faces))) {
        uint64_t count = hpfc_faces_face_count(faces), face;
        CHECK(count >= 1);
        for (size_t d = 0; d < k.nd; d++) {
            if (!note(&k, hpfc_faces_dart_face(faces, &k.darts[d], &face)))
                CHECK(face < count);
        }
    }
    walk_labels(&k, faces);
    walk_geometry(&k);
    hpfc_faces_free(faces);
done:
    hpfc_walker_free(k.w);
    seen.traversals++;
    seen.steps += STEP_BUDGET - (k.steps > 0 ? k.steps : 0);
    seen.budget_exhausted += k.steps <= 0;
    seen.corrupt += (k.codes & BIT(HPFC_E_CORRUPT)) != 0;
    seen.walk_codes |= k.codes;
    if (k.codes & ~ALLOWED)
        fprintf(stderr, "traversal statuses 0x%llx outside OK, NO_PIXEL, CORRUPT\n",
                (unsigned long long)k.codes);
    CHECK((k.codes & ~ALLOWED) == 0);
    return k.codes;
}

static bool is_file_code(int st)
{
    return st >= HPFC_E_MAGIC && st <= HPFC_E_SECTION;
}

/* Opens with the checksums verified: the first failing status. */
static int open_checked(const uint8_t *data, size_t size)
{
    hpfc_file *f = NULL;
    int st = hpfc_open_memory(data, size, 0, &f);
    if (!st)
        st = hpfc_file_check_checksums(f, NULL);
    hpfc_close(f);
    return st;
}

static void open_skipped(const uint8_t *data, size_t size)
{
    hpfc_file *f = NULL;
    int st = hpfc_open_memory(data, size, HPFC_OPEN_SKIP_CHECKSUM, &f);
    seen.open_codes |= BIT(st);
    CHECK(st == HPFC_OK || is_file_code(st));
    if (!st) {
        seen.skipped_opens++;
        traverse(f);
    }
    hpfc_close(f);
}

/* Which bytes a checksum covers: the metadata block and every section. */
static uint8_t *coverage(const uint8_t *buf, size_t size)
{
    uint8_t *covered = calloc(size, 1);
    hpfc_file *f = NULL;
    CHECK_EQ_INT(hpfc_open_memory(buf, size, 0, &f), HPFC_OK);
    if (!covered || !f) {
        hpfc_close(f);
        return covered;
    }
    memset(covered, 1, (size_t)hdr_get_meta_size(buf));
    hpfc_file_info info;
    hpfc_file_get_info(f, &info);
    for (uint32_t k = 0; k < info.section_count; k++) {
        hpfc_section_info s;
        CHECK_EQ_INT(hpfc_file_get_section(f, k, &s), HPFC_OK);
        memset(covered + s.offset, 1, (size_t)s.length);
    }
    hpfc_close(f);
    return covered;
}

static void campaign(const char *name, const uint8_t *buf, size_t size)
{
    CHECK_EQ_INT(open_checked(buf, size), HPFC_OK);
    hpfc_file *f = NULL;
    CHECK_EQ_INT(hpfc_open_memory(buf, size, 0, &f), HPFC_OK);
    if (!f)
        return;
    /* the intact file traverses cleanly */
    long corrupt_before = seen.corrupt;
    traverse(f);
    CHECK_EQ_INT(seen.corrupt, corrupt_before);
    hpfc_close(f);
    uint8_t *covered = coverage(buf, size);
    uint8_t *copy = malloc(size);
    if (!covered || !copy) {
        free(covered), free(copy);
        return;
    }
    seen.files++;
    long accepted = 0;
    for (size_t bit = 0; bit < 8 * size; bit++) {
        memcpy(copy, buf, size);
        copy[bit / 8] ^= (uint8_t)(0x80 >> (bit % 8));
        int st = open_checked(copy, size);
        seen.open_codes |= BIT(st);
        if (covered[bit / 8]) {
            if (st == HPFC_OK || !is_file_code(st))
                fprintf(stderr, "%s: flip of bit %zu: %s\n", name, bit, hpfc_strerror(st));
            CHECK(is_file_code(st));
        } else {
            CHECK(st == HPFC_OK || is_file_code(st));
            accepted += st == HPFC_OK;
        }
        open_skipped(copy, size);
        seen.flips++;
    }
    seen.flips_accepted += accepted;
    /* every byte set to 0x00 and to 0xFF: counts, offsets and masks with
     * many bits wrong at once */
    for (size_t byte = 0; byte < size; byte++)
        for (int v = 0; v < 2; v++) {
            memcpy(copy, buf, size);
            if (copy[byte] == (v ? 0xFF : 0x00))
                continue;
            copy[byte] = v ? 0xFF : 0x00;
            int st = open_checked(copy, size);
            CHECK(covered[byte] ? is_file_code(st) : st == HPFC_OK || is_file_code(st));
            open_skipped(copy, size);
            seen.byte_sets++;
        }
    free(copy);
    for (size_t cut = 0; cut < size; cut++) {
        uint8_t *part = malloc(cut ? cut : 1); /* exact size */
        if (!part)
            break;
        memcpy(part, buf, cut);
        int st = open_checked(part, cut);
        if (st != HPFC_E_TRUNCATED)
            fprintf(stderr, "%s: cut at %zu: %s\n", name, cut, hpfc_strerror(st));
        CHECK_EQ_INT(st, HPFC_E_TRUNCATED);
        open_skipped(part, cut);
        seen.cuts++;
        if (cut >= hdr_get_meta_size(buf)) {
            /* the header believes the cut: the pools or sections now end
             * past the file */
            hdr_set_file_size(part, cut);
            hpfc_file *g = NULL;
            st = hpfc_open_memory(part, cut, HPFC_OPEN_SKIP_CHECKSUM, &g);
            if (st == HPFC_OK)
                fprintf(stderr, "%s: cut at %zu with file_size patched opens\n", name, cut);
            CHECK(is_file_code(st));
            hpfc_close(g);
            seen.patched_cuts++;
        }
        free(part);
    }
    free(covered);
    printf("%s: %zu bytes, %ld flips accepted (all in uncovered padding)\n", name, size, accepted);
    fflush(stdout);
}

/* ---- fuzz regressions (fuzz/regressions/EXPECTED) ------------------------------ */

static const struct {
    const char *name;
    int code;
} CODES[] = {
    {"HPFC_E_MAGIC", HPFC_E_MAGIC},     {"HPFC_E_VERSION", HPFC_E_VERSION},
    {"HPFC_E_INCOMPATIBLE", HPFC_E_INCOMPATIBLE}, {"HPFC_E_TRUNCATED", HPFC_E_TRUNCATED},
    {"HPFC_E_CHECKSUM", HPFC_E_CHECKSUM}, {"HPFC_E_HEADER", HPFC_E_HEADER},
    {"HPFC_E_LEVEL_TABLE", HPFC_E_LEVEL_TABLE}, {"HPFC_E_SECTION", HPFC_E_SECTION},
    {"HPFC_E_CORRUPT", HPFC_E_CORRUPT}, {"HPFC_E_NO_PIXEL", HPFC_E_NO_PIXEL},
};

static int code_of(const char *name)
{
    for (size_t k = 0; k < sizeof CODES / sizeof *CODES; k++)
        if (strcmp(CODES[k].name, name) == 0)
            return CODES[k].code;
    return -1;
}

static uint8_t *read_all(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    uint8_t *buf = malloc(1 << 16);
    *size = buf ? fread(buf, 1, 1 << 16, f) : 0;
    fclose(f);
    return buf;
}

/* One line of EXPECTED: the call on the file must give the status. */
static void check_regression(const char *dir, const char *file, const char *call, int code)
{
    char path[4096 + 256];
    snprintf(path, sizeof path, "%s/%s", dir, file);
    size_t size = 0;
    uint8_t *buf = read_all(path, &size);
    CHECK(buf != NULL);
    if (!buf)
        return;
    uint8_t *exact = malloc(size ? size : 1);
    memcpy(exact, buf, size);
    free(buf);
    hpfc_file *f = NULL;
    int st = hpfc_open_memory(exact, size, HPFC_OPEN_SKIP_CHECKSUM, &f);
    bool ok;
    if (strcmp(call, "open") == 0) {
        ok = st == code;
    } else if (st) {
        ok = false;
    } else if (strcmp(call, "faces") == 0) {
        hpfc_faces *faces = NULL;
        st = hpfc_faces_build(f, &faces);
        hpfc_faces_free(faces);
        ok = st == code;
    } else if (strcmp(call, "walk") == 0) {
        uint64_t codes = traverse(f);
        ok = (codes & BIT(code)) != 0;
        st = code;
    } else {
        fprintf(stderr, "EXPECTED: unknown call %s\n", call);
        ok = false;
    }
    if (!ok)
        fprintf(stderr, "%s: %s gives %s, expected %s\n", file, call, hpfc_strerror(st), hpfc_strerror(code));
    CHECK(ok);
    hpfc_close(f);
    free(exact);
}

static void fuzz_regressions(const char *data_root)
{
    /* $HPFC_TEST_DATA is tests/data of the source tree */
    char dir[4096], path[4200], line[512], file[256], call[32], code[64];
    snprintf(dir, sizeof dir, "%s/../../fuzz/regressions", data_root);
    snprintf(path, sizeof path, "%s/EXPECTED", dir);
    FILE *list = fopen(path, "r");
    CHECK(list != NULL);
    int lines = 0;
    while (list && fgets(line, sizeof line, list)) {
        if (line[0] == '#' || sscanf(line, "%255s %31s %63s", file, call, code) != 3)
            continue;
        CHECK(code_of(code) >= 0);
        check_regression(dir, file, call, code_of(code));
        lines++;
    }
    if (list)
        fclose(list);
    CHECK(lines >= 2);
}

/* ---- the files ------------------------------------------------------------------ */

static void fixture_campaigns(const char *root)
{
    static const char *names[] = {"square_diagonal.hpfc", "loop_quadtree.hpfc",
                                  "two_components_hole_crs.hpfc", "borders_features.hpfc"};
    for (size_t k = 0; k < sizeof names / sizeof *names; k++) {
        char path[4096];
        snprintf(path, sizeof path, "%s/valid/%s", root, names[k]);
        size_t size = 0;
        uint8_t *buf = read_all(path, &size);
        CHECK(buf != NULL && size > 128);
        if (buf && size > 128) {
            uint8_t *exact = malloc(size);
            memcpy(exact, buf, size);
            campaign(names[k], exact, size);
            free(exact);
        }
        free(buf);
    }
}

typedef struct generated {
    const char *name;
    int kind;            /* -1: Delaunay, -2: polyline, else a gen_special kind */
    uint32_t root_cols, root_rows, cols, rows;
    int flat;
    const char *crs;
    int labels; /* with a LABL section */
    int geometry; /* with a GEOM section */
} generated;

static void generated_campaigns(void)
{
    static const generated list[] = {
        {"hole, 2x2 root, 3x2 images, CRS", GEN_SPECIAL_HOLE, 2, 2, 3, 2, 0, "EPSG:4326", 0, 0},
        {"loop, 1x1 root, 2x3 images", GEN_SPECIAL_LOOP, 1, 1, 2, 3, 0, NULL, 0, 0},
        {"multi-edges, 3x1 root, 2x2 images", GEN_SPECIAL_MULTI, 3, 1, 2, 2, 0, NULL, 0, 0},
        {"crack, flat", GEN_SPECIAL_CRACK, 4, 4, 2, 2, 1, NULL, 0, 0},
        {"Delaunay 10 points, 2x3 root, 3x3 images", -1, 2, 3, 3, 3, 0, NULL, 0, 0},
        {"polyline 16 points, 1x1 root, 2x2 images", -2, 1, 1, 2, 2, 0, NULL, 0, 0},
        {"triangle, 1x2 root, 4x2 images", GEN_SPECIAL_TRIANGLE, 1, 2, 4, 2, 0, NULL, 0, 0},
        {"hole, 2x2 root, 2x2 images, labels", GEN_SPECIAL_HOLE, 2, 2, 2, 2, 0, NULL, 1, 0},
        {"loop, 1x1 root, 3x2 images, labels", GEN_SPECIAL_LOOP, 1, 1, 3, 2, 0, NULL, 1, 0},
        {"Delaunay 10 points, 2x2 root, 2x2 images, labels", -1, 2, 2, 2, 2, 0, NULL, 1, 0},
        {"polyline 16 points, 3x1 root, 2x2 images, labels", -2, 3, 1, 2, 2, 0, NULL, 1, 0},
        {"polyline 16 points, 2x2 root, 2x2 images, labels, geometry", -2, 2, 2, 2, 2, 0, NULL, 1, 1},
        {"multi-edges, 3x1 root, 2x2 images, geometry", GEN_SPECIAL_MULTI, 3, 1, 2, 2, 0, NULL, 0, 1},
    };
    for (size_t k = 0; k < sizeof list / sizeof *list; k++) {
        const generated *gd = &list[k];
        hpfc_graph *g = NULL;
        int st = gd->kind == -1   ? gen_delaunay(11, 10, 64, 0.2, &g)
                 : gd->kind == -2 ? gen_polyline(7, 16, 256, 0.5, &g)
                                  : gen_special(gd->kind, &g);
        CHECK_EQ_INT(st, HPFC_OK);
        hpfc_build_params p;
        hpfc_build_params_default(&p);
        p.root_cols = gd->root_cols, p.root_rows = gd->root_rows;
        p.cols = gd->cols, p.rows = gd->rows, p.flat = gd->flat;
        hpfc_tree *t = NULL;
        if (!st)
            CHECK_EQ_INT(hpfc_build(g, &p, &t, NULL), HPFC_OK);
        uint8_t *buf = NULL;
        size_t size = 0;
        hpfc_write_options opts = {.crs = gd->crs, .face_labels = gd->labels,
                                   .geometry = gd->geometry ? g : NULL};
        if (t)
            CHECK_EQ_INT(check_tree_serialize(t, &opts, &buf, &size, NULL), HPFC_OK);
        CHECK(buf == NULL || size <= 4096); /* keep the campaign fast */
        if (buf && size <= 4096)
            campaign(gd->name, buf, size);
        free(buf);
        hpfc_tree_free(t);
        hpfc_graph_free(g);
    }
}

/* ---- the key calls' parent index on a bad layout --------------------------- */

static uint64_t get_bits(const uint8_t *buf, uint64_t off, unsigned k)
{
    uint64_t v = 0;
    for (unsigned b = 0; b < k; b++, off++)
        v = v << 1 | (buf[off / 8] >> (7 - off % 8) & 1);
    return v;
}

static void set_bits(uint8_t *buf, uint64_t off, unsigned k, uint64_t v)
{
    for (unsigned b = 0; b < k; b++, off++) {
        uint8_t bit = (uint8_t)(0x80 >> (off % 8));
        buf[off / 8] = (uint8_t)(v >> (k - 1 - b) & 1 ? buf[off / 8] | bit : buf[off / 8] & ~bit);
    }
}

/* Every key call on a file whose addresses break the layout of §5.2.2 (two
 * root records aliasing one image, two images swapped, an address past
 * the pool) gives HPFC_E_CORRUPT: a key's pixel would have no single path.
 * The dart operators still walk what the addresses say. */
static void test_key_layout(void)
{
    hpfc_graph *g = NULL;
    CHECK_EQ_INT(gen_delaunay(3, 60, 1 << 12, 0.2, &g), HPFC_OK);
    hpfc_build_params p;
    hpfc_build_params_default(&p);
    p.root_cols = p.root_rows = 4;
    hpfc_tree *t = NULL;
    uint8_t *buf = NULL;
    size_t size = 0;
    CHECK_EQ_INT(hpfc_build(g, &p, &t, NULL), HPFC_OK);
    /* addresses exist in the paper layout only (compact children are ranks) */
    const hpfc_write_options paper = {.layout = HPFC_LAYOUT_PAPER};
    CHECK_EQ_INT(check_tree_serialize(t, &paper, &buf, &size, NULL), HPFC_OK);
    hpfc_file *f = NULL;
    CHECK_EQ_INT(hpfc_open_memory(buf, size, 0, &f), HPFC_OK);
    if (!f)
        goto done;
    /* the refined root records and a dart key to ask about */
    hpfc_level_info lv0, lv1;
    hpfc_file_get_level(f, 0, &lv0);
    CHECK_EQ_INT(hpfc_file_get_level(f, 1, &lv1), HPFC_OK);
    uint64_t record = 1 + (lv0.address_bits > lv0.word_bits ? lv0.address_bits : lv0.word_bits);
    uint64_t refined[2], n = 0, key = 0;
    for (uint64_t r = 0; r < 16 && n < 2; r++)
        if (get_bits(buf, lv0.pool_offset * 8 + r * record, 1))
            refined[n++] = lv0.pool_offset * 8 + r * record + 1;
    hpfc_walker *w;
    CHECK_EQ_INT(hpfc_walker_create(f, &w), HPFC_OK);
    hpfc_pixel px;
    for (int st = hpfc_leaf_first(f, &px); !st && !key; st = hpfc_leaf_next(f, &px)) {
        hpfc_vertex v;
        hpfc_dart d;
        if (!hpfc_pixel_vertex(w, &px, 0, &v) && !hpfc_vertex_dart(w, &v, 0, &d))
            key = hpfc_dart_key(f, &d);
    }
    hpfc_walker_free(w);
    hpfc_close(f);
    CHECK_EQ_INT(n, 2);
    CHECK(key != 0);
    if (n < 2)
        goto done;
    uint64_t a0 = get_bits(buf, refined[0], lv0.address_bits);
    uint64_t a1 = get_bits(buf, refined[1], lv0.address_bits);
    const uint64_t bad[][2] = {{a0, a0}, {a1, a0}, {a0, lv1.pool_bits}, {a0, a1}};
    for (size_t b = 0; b < sizeof bad / sizeof *bad; b++) {
        uint8_t *copy = malloc(size);
        memcpy(copy, buf, size);
        set_bits(copy, refined[0], lv0.address_bits, bad[b][0]);
        set_bits(copy, refined[1], lv0.address_bits, bad[b][1]);
        CHECK_EQ_INT(hpfc_open_memory(copy, size, 0, &f), HPFC_OK); /* pools: no checksum at open */
        CHECK_EQ_INT(hpfc_walker_create(f, &w), HPFC_OK);
        int want =
            b + 1 < sizeof bad / sizeof *bad ? HPFC_E_CORRUPT : HPFC_OK; /* the last: intact */
        uint64_t out;
        hpfc_dart d;
        hpfc_vertex v;
        CHECK_EQ_INT(hpfc_key_next(w, key, &out), want);
        CHECK_EQ_INT(hpfc_key_origin(w, key, &out), want);
        CHECK_EQ_INT(hpfc_dart_from_key(w, key, &d), want);
        CHECK_EQ_INT(hpfc_vertex_from_key(w, key & ~(uint64_t)0xFFFFF, &v), want);
        CHECK_EQ_INT(hpfc_key_index_bound(w, &out, &out), want);
        CHECK_EQ_INT(hpfc_dart_index(w, key, &out), want);
        CHECK_EQ_INT(hpfc_key_prev_indexed(w, key, &out, &out), want);
        CHECK_EQ_INT(hpfc_walker_set_cache_size(w, 0), HPFC_OK);
        CHECK_EQ_INT(hpfc_key_twin(w, key, &out), want);
        CHECK_EQ_INT(hpfc_vertex_index(w, key & ~(uint64_t)0xFFFFF, &out), want);
        CHECK_EQ_INT(hpfc_key_next_indexed(w, key, &out, &out), want);
        hpfc_walker_free(w);
        hpfc_close(f);
        free(copy);
    }
done:
    free(buf);
    hpfc_tree_free(t);
    hpfc_graph_free(g);
}

int main(void)
{
    test_layout_compact = check_use_test_layout();
    const char *root = getenv("HPFC_TEST_DATA");
    CHECK(root != NULL);
    if (root) {
        fuzz_regressions(root);
        fixture_campaigns(root);
    }
    generated_campaigns();
    test_key_layout();
    CHECK(seen.files >= 10);
    /* the campaign must reach the decoder: some damaged copies open without
     * their checksum and then fail while traversing */
    CHECK(seen.skipped_opens > 1000);
    CHECK(seen.corrupt > 100);
    CHECK_EQ_INT(seen.cache_mismatches, 0);
    /* the key calls ran, met corrupt files, and always agreed with the
     * dart operators */
    CHECK(seen.key_calls > 10000);
    CHECK(seen.key_corrupt > 100);
    CHECK_EQ_INT(seen.key_mismatches, 0);
    CHECK(seen.index_calls > 10000);
    CHECK_EQ_INT(seen.index_mismatches, 0);
    /* damaged LABL sections reached the label code and the verifier */
    CHECK(seen.label_files > 1000);
    CHECK(seen.label_corrupt > 10);
    CHECK(seen.label_disagreed > 100);
    CHECK(seen.label_verified > 100);
    printf("labels: %ld damaged copies with a LABL section, %ld label calls (%ld CORRUPT); "
           "hpfc_labels_verify accepted %ld, reported %ld\n",
           seen.label_files, seen.label_calls, seen.label_corrupt, seen.label_verified,
           seen.label_disagreed);
    /* damaged GEOM sections reached the geometry code and the verifier */
    CHECK(seen.geom_files > 500);
    CHECK(seen.geom_corrupt > 10);
    CHECK(seen.geom_disagreed > 50);
    CHECK(seen.geom_verified > 50);
    printf("geometry: %ld damaged copies with a GEOM section, %ld geometry calls (%ld CORRUPT); "
           "hpfc_geometry_verify accepted %ld, reported %ld\n",
           seen.geom_files, seen.geom_calls, seen.geom_corrupt, seen.geom_verified,
           seen.geom_disagreed);
    printf("keys: %ld calls, %ld CORRUPT, %ld differ from the dart operators; %ld index calls, "
           "%ld broke a promise\n",
           seen.key_calls, seen.key_corrupt, seen.key_mismatches, seen.index_calls,
           seen.index_mismatches);
    printf("corruption: %ld files, %ld bit flips (%ld accepted: padding), %ld bytes set to "
           "0x00/0xFF, %ld truncations (%ld with file_size patched); %ld opened without "
           "checksum and traversed, %ld of them found corrupt, %ld ran out of the %d-step "
           "budget, %ld steps in all; open codes 0x%llx, traversal codes 0x%llx\n",
           seen.files, seen.flips, seen.flips_accepted, seen.byte_sets, seen.cuts, seen.patched_cuts, seen.skipped_opens,
           seen.corrupt, seen.budget_exhausted, STEP_BUDGET, seen.steps,
           (unsigned long long)seen.open_codes, (unsigned long long)seen.walk_codes);
    return check_report("corruption");
}
