/*
 * verify.c: `hpfc-inspect --verify` (see verify.h).
 *
 * Five groups of checks run in order, each reporting every problem it finds
 * (the first VERIFY_MAX_PROBLEMS verbatim):
 *
 *   format     hpfc_open: everything the reader checks at open (§7.3);
 *   checksums  hpfc_file_check_checksums (R18);
 *   structure  every pixel of every level, reached from the root with
 *              hpfc_pixel_child in pool order: each decodes, each word matches
 *              the grammar (parsed by the traversal API), images lie back to
 *              back in parent order and fill the pool, the per-level counts
 *              and k_w match the level table, and every padding bit or byte
 *              is zero (§8.7);
 *   roads      both sides of every road carry the same number of crossings
 *              (the only trace of §3.5 a reader can see without the graph),
 *              and the domain's outer roads carry none;
 *   topology   the map rebuilt by export_map with the library's operators:
 *              twin is an involution without fixed points, next a permutation
 *              with prev(next(d)) = d, origin(next(d)) = target(d), vertex
 *              degrees, one face per boundary loop, every face used, and
 *              V - E + F = 1 + C, boundary loops = F + C - 1.
 *
 * A later group is skipped only when an earlier one makes it meaningless:
 * nothing runs on a file that does not open, and no traversal runs on a file
 * with a pixel that does not decode (the traversal would only report the same
 * pixel again).
 */
#include "verify.h"

#include <inttypes.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "clock.h"
#include "cores.h"
#include "export.h"
#include "hpfc.h"
#include "jsonw.h"
#include "common/road.h" /* header-only: roads walked exactly as the reader walks them */

#ifdef __GNUC__
#define PRINTF_LIKE(f, a) __attribute__((format(printf, f, a)))
#else
#define PRINTF_LIKE(f, a)
#endif

/* ---- problems ------------------------------------------------------------------ */

static void problem(verify_report *r, const char *fmt, ...) PRINTF_LIKE(2, 3);

static void problem(verify_report *r, const char *fmt, ...)
{
    /* Counting without formatting keeps a file with millions of bad darts
     * cheap to reject. */
    if (r->problem_count < VERIFY_MAX_PROBLEMS) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(r->problems[r->problem_count], VERIFY_PROBLEM_LEN, fmt, ap);
        va_end(ap);
    }
    r->problem_count++;
}

/* A pixel's path from the root, "i,j/i,j/..." as in interfaces §4. */
static const char *pixel_name(const hpfc_pixel *px, char *buf, size_t cap)
{
    size_t used = 0;
    buf[0] = '\0';
    for (uint32_t d = 0; d <= px->depth && d < HPFC_MAX_LEVELS && used < cap; d++) {
        int n = snprintf(buf + used, cap - used, "%s%u,%u", d ? "/" : "", px->path[d].i,
                         px->path[d].j);
        if (n < 0)
            break;
        used += (size_t)n;
    }
    return buf;
}

static const char *const road_names[4] = {"W", "N", "E", "S"};

/* Whether bits [b0, b1) of a pool are all zero; bit b is bit 7 - b % 8 of
 * byte b / 8 (spec §2.2). The caller keeps b1 within the pool's bytes. */
static bool bits_zero(const uint8_t *pool, uint64_t b0, uint64_t b1)
{
    for (; b0 < b1 && (b0 & 7); b0++)
        if (pool[b0 >> 3] >> (7 - (b0 & 7)) & 1)
            return false;
    for (; b0 + 8 <= b1; b0 += 8)
        if (pool[b0 >> 3])
            return false;
    for (; b0 < b1; b0++)
        if (pool[b0 >> 3] >> (7 - (b0 & 7)) & 1)
            return false;
    return true;
}

static uint64_t get_u64le(const uint8_t *p)
{
    uint64_t v = 0;
    for (int k = 7; k >= 0; k--)
        v = v << 8 | p[k];
    return v;
}

/* ---- the verifier ------------------------------------------------------------- */

/* How to reach image k of level l >= 1: its parent is pixel (i, j) of image
 * `parent` of level l - 1. Kept instead of whole hpfc_pixel stacks (about
 * 800 bytes each) so that memory stays proportional to the refined pixels. */
typedef struct image_ref {
    uint64_t parent;
    uint32_t i, j;
} image_ref;

typedef struct ref_list {
    image_ref *v;
    uint64_t n, cap;
} ref_list;

typedef struct verifier {
    const hpfc_file *f;
    const uint8_t *data;
    hpfc_file_info info;
    hpfc_level_info lv[HPFC_MAX_LEVELS];
    hpfc_walker *w;
    char *word;          /* decoded symbols of one word */
    size_t word_cap;
    ref_list images[HPFC_MAX_LEVELS];
    bool undecodable;    /* some pixel could not be read: skip traversals */
    bool compact;        /* the compact pool layout (incompat flag bit 0, spec §5.3) */
    verify_report *r;
} verifier;

static int push_ref(ref_list *l, uint64_t parent, uint32_t i, uint32_t j)
{
    if (l->n == l->cap) {
        uint64_t cap = l->cap ? 2 * l->cap : 64;
        if (cap > SIZE_MAX / sizeof *l->v)
            return HPFC_E_NOMEM;
        image_ref *v = realloc(l->v, (size_t)cap * sizeof *v);
        if (!v)
            return HPFC_E_NOMEM;
        l->v = v;
        l->cap = cap;
    }
    l->v[l->n++] = (image_ref){parent, i, j};
    return HPFC_OK;
}

/* Room for the longest word any level's slot can hold: at most four '+'
 * (1 bit each) and (k_w - 4) / 4 other symbols (4 bits each); k_w
 * crossings in the compact layout. */
static int alloc_word(verifier *v)
{
    uint64_t most = 4;
    for (uint32_t l = 0; l < v->info.levels; l++) {
        uint64_t k = v->lv[l].word_bits;
        /* compact layout (§5.3): a crossing costs at least 1 bit */
        uint64_t n = 4 + (v->compact ? k : k > 4 ? (k - 4) / 4 : 0);
        most = n > most ? n : most;
    }
    v->word_cap = (size_t)most + 1;
    v->word = malloc(v->word_cap);
    return v->word ? HPFC_OK : HPFC_E_NOMEM;
}

/* ---- structure: every pixel from the root, in pool order ----------------------- */

/* What one level's scan found. */
typedef struct level_tally {
    uint64_t words, refined, private_px;
    uint64_t longest_code;  /* bits of the longest word code */
    uint64_t next_image;    /* bit offset where the next image must start */
} level_tally;

/* The refined pixel of level l - 1 whose child is image k of level l >= 1,
 * rebuilt from the root (depth <= 47, so the recursion is shallow). */
static int image_parent(const verifier *v, uint32_t l, uint64_t k, hpfc_pixel *out)
{
    const image_ref *ref = &v->images[l].v[k];
    if (l == 1)
        return hpfc_pixel_root(v->f, ref->i, ref->j, out);
    int st = image_parent(v, l - 1, ref->parent, out);
    return st ? st : hpfc_pixel_child(v->f, out, ref->i, ref->j, out);
}

static const uint8_t *pool_of(const verifier *v, uint32_t l)
{
    return v->data + v->lv[l].pool_offset;
}

/* Bits [b0, b1) of level l's pool are zero padding. */
static void check_padding(verifier *v, uint32_t l, const hpfc_pixel *px, uint64_t b0, uint64_t b1,
                          const char *what)
{
    char name[128];
    if (b1 > v->lv[l].pool_bits) /* cannot happen after the library's S19 check */
        problem(v->r, "pixel %s: %s extends past the pool", pixel_name(px, name, sizeof name),
                what);
    else if (b0 < b1 && !bits_zero(pool_of(v, l), b0, b1))
        problem(v->r, "pixel %s: non-zero padding after the %s", pixel_name(px, name, sizeof name),
                what);
}

/* A word pixel: the word decodes, matches the grammar, and its slot is
 * zero after the code. The slot's payload is [slot, slot + slot_bits). */
static void check_word(verifier *v, uint32_t l, const hpfc_pixel *px, uint64_t slot,
                       uint64_t slot_bits, level_tally *t)
{
    char name[128];
    size_t len;
    uint32_t vertices;
    int st = hpfc_pixel_word(v->f, px, v->word, v->word_cap, &len);
    if (st == HPFC_E_BUFFER_SMALL)
        st = HPFC_E_CORRUPT; /* longer than its slot allows: cannot happen */
    if (st) {
        problem(v->r, "pixel %s: word does not decode (%s)", pixel_name(px, name, sizeof name),
                hpfc_strerror(st));
        v->undecodable = true;
        return;
    }
    /* The traversal API parses components with the stack of §3.8 and
     * refuses a word outside the grammar. */
    if ((st = hpfc_pixel_vertex_count(v->w, px, &vertices))) {
        problem(v->r, "pixel %s: word \"%.*s\" does not match the grammar (%s)",
                pixel_name(px, name, sizeof name), len > 64 ? 64 : (int)len, v->word,
                hpfc_strerror(st));
        v->undecodable = true;
        return;
    }
    t->private_px += len == 4;
    if (v->compact)
        return; /* no slots: hpfc_file_check_pool_layout checks the words' index and k_w */
    uint64_t code = 4 + 4 * ((uint64_t)len - 4); /* '+' costs 1 bit, the others 4 */
    t->longest_code = code > t->longest_code ? code : t->longest_code;
    check_padding(v, l, px, slot + code, slot + slot_bits, "word");
}

/* Pixel px of level l; for l >= 1 its slot starts at `slot`. */
static int check_pixel(verifier *v, uint32_t l, uint64_t image, const hpfc_pixel *px,
                       uint64_t slot, int *type, level_tally *t)
{
    char name[128];
    const hpfc_level_info *lv = &v->lv[l];
    int st = hpfc_pixel_type(v->f, px, type);
    if (st) {
        problem(v->r, "pixel %s: %s", pixel_name(px, name, sizeof name), hpfc_strerror(st));
        return st;
    }
    /* A root record is a type bit and a payload of R - 1 bits (§5.2.1); a slot
     * of a refined image is exactly k_w or k_@ bits (§5.2.2). */
    uint64_t payload = l ? (*type == HPFC_PIXEL_WORD ? lv->word_bits : lv->address_bits)
                         : lv->pool_bits / ((uint64_t)v->info.root_cols * v->info.root_rows) - 1;
    if (*type == HPFC_PIXEL_REFINED) {
        t->refined++;
        if (l == 0 && !v->compact)
            check_padding(v, l, px, slot + lv->address_bits, slot + payload, "address");
        if (l + 1 >= v->info.levels) /* the library reports this as corrupt first */
            return HPFC_E_CORRUPT;
        return push_ref(&v->images[l + 1], image, px->path[l].i, px->path[l].j);
    }
    t->words++;
    check_word(v, l, px, slot, payload, t);
    return HPFC_OK;
}

/* Image k of level l: each pixel in scanline order. */
static int scan_image(verifier *v, uint32_t l, uint64_t k, level_tally *t)
{
    char name[128];
    const hpfc_level_info *lv = &v->lv[l];
    uint32_t cols = l ? v->info.cols : v->info.root_cols;
    uint32_t rows = l ? v->info.rows : v->info.root_rows;
    uint64_t per = (uint64_t)cols * rows, image = 0, words = 0, refined = 0;
    hpfc_pixel parent;
    int st = l ? image_parent(v, l, k, &parent) : HPFC_OK;
    if (st) {
        problem(v->r, "level %u image %" PRIu64 ": cannot reach it from the root (%s)", l, k,
                hpfc_strerror(st));
        return st;
    }
    for (uint32_t j = 0; j < rows; j++) {
        for (uint32_t i = 0; i < cols; i++) {
            hpfc_pixel px;
            st = l ? hpfc_pixel_child(v->f, &parent, i, j, &px) : hpfc_pixel_root(v->f, i, j, &px);
            if (st) {
                problem(v->r, "level %u image %" PRIu64 " pixel (%u,%u): %s", l, k, i, j,
                        hpfc_strerror(st));
                return st;
            }
            if (i == 0 && j == 0 && l > 0) {
                image = px.path[l].image;
                /* Images lie back to back in parent order (§5.2.2, W7). The
                 * scan stops at the first that does not: images that
                 * overlap or alias one another would make every walk over
                 * the tree (this scan, leaf iteration, the traversal)
                 * revisit them, multiplying the work level by level. */
                /* compact: images are numbered in that order */
                if (image != (v->compact ? k : t->next_image)) {
                    problem(v->r,
                            "level %u image %" PRIu64 " (pixel %s) starts at bit %" PRIu64
                            ", expected %" PRIu64,
                            l, k, pixel_name(&px, name, sizeof name), image, t->next_image);
                    return HPFC_E_CORRUPT;
                }
            }
            uint64_t root_record = l ? 0 : ((uint64_t)j * cols + i) * (lv->pool_bits / per);
            uint64_t slot = l ? image + per + words * lv->word_bits + refined * lv->address_bits
                              : root_record + 1;
            int type;
            if ((st = check_pixel(v, l, k, &px, slot, &type, t)))
                return st;
            words += type == HPFC_PIXEL_WORD;
            refined += type == HPFC_PIXEL_REFINED;
        }
    }
    if (l > 0)
        t->next_image = image + per + words * lv->word_bits + refined * lv->address_bits;
    return HPFC_OK;
}

/* What the level table says and what the scan found agree (§4.3, §8.7). */
static void check_level_tally(verifier *v, uint32_t l, uint64_t images, const level_tally *t)
{
    const hpfc_level_info *lv = &v->lv[l];
    verify_report *r = v->r;
    if (images != lv->images)
        problem(r, "level %u: %" PRIu64 " images reached, the level table says %" PRIu64, l,
                images, lv->images);
    if (t->words != lv->word_pixels || t->refined != lv->refined_pixels)
        problem(r,
                "level %u: %" PRIu64 " word and %" PRIu64 " refined pixels, the level table says %"
                PRIu64 " and %" PRIu64,
                l, t->words, t->refined, lv->word_pixels, lv->refined_pixels);
    if (v->compact) {
        hpfc_diag d;
        if (hpfc_file_check_pool_layout(v->f, l, &d))
            problem(r, "%s", d.message);
    } else if (t->longest_code != lv->word_bits) {
        problem(r, "level %u: word_bits is %u, the longest word code has %" PRIu64 " bits", l,
                lv->word_bits, t->longest_code);
    }
    if (l > 0 && !v->compact && t->next_image != lv->pool_bits)
        problem(r, "level %u: the images end at bit %" PRIu64 ", pool_bits is %" PRIu64, l,
                t->next_image, lv->pool_bits);
    uint64_t tail = (lv->pool_bits + 7) / 8 * 8;
    if (!bits_zero(pool_of(v, l), lv->pool_bits, tail))
        problem(r, "level %u: non-zero padding after the pool's last bit", l);
}

static int scan_level(verifier *v, uint32_t l)
{
    uint64_t images = l ? v->images[l].n : 1;
    level_tally t = {0};
    int st = HPFC_OK;
    for (uint64_t k = 0; k < images && !st; k++)
        st = scan_image(v, l, k, &t);
    if (st)
        return st;
    check_level_tally(v, l, images, &t);
    v->r->word_pixels += t.words;
    v->r->refined_pixels += t.refined;
    v->r->private_pixels += t.private_px;
    return HPFC_OK;
}

typedef struct byte_span {
    uint64_t lo, hi;
} byte_span;

static int span_cmp(const void *a, const void *b)
{
    const byte_span *x = a, *y = b;
    return (x->lo > y->lo) - (x->lo < y->lo);
}

static bool bytes_zero(const uint8_t *p, uint64_t lo, uint64_t hi)
{
    for (; lo < hi; lo++)
        if (p[lo])
            return false;
    return true;
}

/* Every byte after the metadata that no pool and no other section covers is
 * zero padding (§4.1, §4.4): between sections, between pools, inside POOL. */
static void check_file_padding(verifier *v)
{
    byte_span spans[HPFC_MAX_LEVELS + 1024];
    size_t n = 0;
    for (uint32_t l = 0; l < v->info.levels; l++)
        spans[n++] = (byte_span){v->lv[l].pool_offset,
                                 v->lv[l].pool_offset + (v->lv[l].pool_bits + 7) / 8};
    for (uint32_t k = 0; k < v->info.section_count && n < sizeof spans / sizeof spans[0]; k++) {
        hpfc_section_info s;
        if (!hpfc_file_get_section(v->f, k, &s) && memcmp(s.tag, "POOL", 4) != 0)
            spans[n++] = (byte_span){s.offset, s.offset + s.length};
    }
    qsort(spans, n, sizeof spans[0], span_cmp);
    uint64_t pos = get_u64le(v->data + 96); /* meta_size, checked at open */
    for (size_t k = 0; k <= n; k++) {
        uint64_t lo = k < n ? spans[k].lo : v->info.file_size;
        if (lo > pos && !bytes_zero(v->data, pos, lo)) {
            problem(v->r, "non-zero padding bytes in [%" PRIu64 ", %" PRIu64 ")", pos, lo);
            break;
        }
        if (k < n && spans[k].hi > pos)
            pos = spans[k].hi;
    }
}

static int check_structure(verifier *v)
{
    size_t before = v->r->problem_count;
    int st = HPFC_OK;
    for (uint32_t l = 0; l < v->info.levels && !st; l++)
        st = scan_level(v, l);
    if (st)
        v->undecodable = true;
    check_file_padding(v);
    v->r->structure = v->r->problem_count == before ? CHECK_OK : CHECK_FAILED;
    return st == HPFC_E_NOMEM ? st : HPFC_OK;
}

/* ---- roads: both sides of every road agree ------------------------------------------ */

/* Crossings on each road W, N, E, S of a word pixel (§3.6: one list per
 * road, each ended by '+'). */
static int road_counts(verifier *v, const hpfc_pixel *px, uint64_t count[4])
{
    size_t len;
    uint32_t off[5];
    int st = hpfc_pixel_word(v->f, px, v->word, v->word_cap, &len);
    if (st)
        return st == HPFC_E_BUFFER_SMALL ? HPFC_E_CORRUPT : st;
    hpfc_word_count_roads(v->word, len, off);
    for (int road = 0; road < 4; road++)
        count[road] = off[road + 1] - off[road];
    return HPFC_OK;
}

/* Road `road` of leaf P (box b, counts c) against the leaves across it.
 * Leaves nest, so either one leaf across spans P's whole side (and, when it
 * is larger, its own check covers this road) or P's side is the union of
 * sides of leaves across: then P's crossings are theirs (§3.5). */
static int check_road(verifier *v, const hpfc_pixel *p, const road_box *b, const uint64_t c[4],
                      int road)
{
    char name[128];
    int64_t lo, hi;
    uint64_t sum = 0;
    road_extent(b, road, &lo, &hi);
    for (int64_t t = lo; t < hi;) {
        int64_t x, y, qlo, qhi;
        hpfc_pixel q;
        road_box qb;
        road_point(b, road, t, false, &x, &y);
        int st = hpfc_locate(v->f, x, y, &q);
        if (st == HPFC_E_NO_PIXEL && t == lo) { /* the domain's border (G1 keeps edges off it) */
            if (c[road])
                problem(v->r, "pixel %s: %" PRIu64 " crossings on the domain's border (road %s)",
                        pixel_name(p, name, sizeof name), c[road], road_names[road]);
            return HPFC_OK;
        }
        uint64_t qc[4];
        if (!st)
            st = hpfc_pixel_bounds(v->f, &q, &qb.x0, &qb.y0, &qb.x1, &qb.y1);
        if (!st)
            st = road_counts(v, &q, qc);
        if (st) {
            problem(v->r, "pixel %s: the leaf across road %s: %s", pixel_name(p, name, sizeof name),
                    road_names[road], hpfc_strerror(st));
            return st;
        }
        road_extent(&qb, road, &qlo, &qhi);
        if (qlo < lo || qhi > hi) {
            if (t == lo && qlo <= lo && qhi >= hi)
                return HPFC_OK;
            problem(v->r, "pixel %s: the leaves across road %s do not nest",
                    pixel_name(p, name, sizeof name), road_names[road]);
            return HPFC_E_CORRUPT;
        }
        sum += qc[road_opposite(road)];
        t = qhi; /* > t: q holds the point at t */
    }
    if (sum != c[road])
        problem(v->r, "pixel %s: %" PRIu64 " crossings on road %s, %" PRIu64 " across it",
                pixel_name(p, name, sizeof name), c[road], road_names[road], sum);
    return HPFC_OK;
}

static void check_roads(verifier *v)
{
    char name[128];
    size_t before = v->r->problem_count;
    hpfc_pixel px;
    int st = hpfc_leaf_first(v->f, &px);
    while (!st) {
        road_box b;
        uint64_t c[4];
        st = hpfc_pixel_bounds(v->f, &px, &b.x0, &b.y0, &b.x1, &b.y1);
        if (!st)
            st = road_counts(v, &px, c);
        if (st) {
            problem(v->r, "pixel %s: %s", pixel_name(&px, name, sizeof name), hpfc_strerror(st));
            break;
        }
        for (int road = 0; road < 4; road++)
            check_road(v, &px, &b, c, road);
        st = hpfc_leaf_next(v->f, &px);
    }
    if (st && st != HPFC_E_NO_PIXEL && v->r->problem_count == before)
        problem(v->r, "leaf iteration: %s", hpfc_strerror(st));
    v->r->roads = v->r->problem_count == before ? CHECK_OK : CHECK_FAILED;
}

/* ---- topology: the map the operators rebuild ----------------------------------------- */

typedef struct topo {
    exported_map m;
    hpfc_faces *faces;
    uint64_t nfaces;
    uint64_t *face;     /* per dart: hpfc_faces_key_face */
    uint32_t *degree;   /* per vertex: hpfc_key_degree */
} topo;

/* The operators on dart d (index di, leaving vertex `vertex` of index vi)
 * agree with each other and with the export's numbering. */
static void check_dart(verifier *v, topo *tp, uint64_t vertex, size_t vi, uint64_t d, size_t di)
{
    hpfc_walker *w = v->w;
    uint64_t o, tg, ot, n, p, t;
    int st;
    if ((st = hpfc_key_origin(w, d, &o)) || (st = hpfc_key_next(w, d, &n)) ||
        (st = hpfc_key_prev(w, n, &p)) || (st = hpfc_key_twin(w, d, &t)) ||
        (st = hpfc_key_target(w, d, &tg)) || (st = hpfc_key_origin(w, t, &ot)) ||
        (st = hpfc_faces_key_face(tp->faces, w, d, &tp->face[di]))) {
        problem(v->r, "dart %zu (vertex %zu): %s", di, vi, hpfc_strerror(st));
        tp->face[di] = UINT64_MAX;
        return;
    }
    if (tp->m.origin[di] != vi)
        problem(v->r, "dart %zu: the export numbers it from vertex %u, the walk from %zu", di,
                tp->m.origin[di], vi);
    if (o != vertex)
        problem(v->r, "dart %zu: origin(d) is not the vertex %zu it leaves", di, vi);
    if (p != d)
        problem(v->r, "dart %zu: prev(next(d)) != d", di);
    if (tg != ot)
        problem(v->r, "dart %zu: target(d) != origin(twin(d))", di);
    if (tp->face[di] >= tp->nfaces)
        problem(v->r, "dart %zu: face %" PRIu64 " out of range (%" PRIu64 " faces)", di,
                tp->face[di], tp->nfaces);
}

/* A leaf's private pixel lies in a face; each vertex's darts pass
 * check_dart. Darts are visited in export_map's order. */
static int walk_leaf(verifier *v, topo *tp, const hpfc_pixel *px, size_t *vi, size_t *di)
{
    char name[128];
    uint32_t count, degree;
    int st = hpfc_pixel_vertex_count(v->w, px, &count), priv = 0;
    if (!st && count == 0)
        st = hpfc_pixel_is_private(v->f, px, &priv);
    uint64_t face;
    if (!st && priv && !(st = hpfc_faces_pixel_face(tp->faces, px, &face)) &&
        face >= tp->nfaces)
        problem(v->r, "pixel %s: private pixel in face %" PRIu64 " of %" PRIu64,
                pixel_name(px, name, sizeof name), face, tp->nfaces);
    for (uint32_t k = 0; k < count && !st; k++, (*vi)++) {
        uint64_t vertex, darts[64]; /* most vertices' darts, got at once */
        degree = 0;
        if ((st = hpfc_pixel_vertex_key(v->w, px, k, &vertex)))
            break;
        st = hpfc_key_vertex_darts(v->w, vertex, darts, 64, &degree);
        bool all = !st; /* else one by one, when there are more than 64 */
        if (st == HPFC_E_ARG && degree > 64)
            st = HPFC_OK;
        if (st)
            break;
        if (*vi >= tp->m.nv || degree > tp->m.nd - *di) {
            problem(v->r, "the walk finds more vertices or darts than the export");
            return HPFC_E_CORRUPT;
        }
        tp->degree[*vi] = degree;
        for (uint32_t e = 0; e < degree && !st; e++, (*di)++) {
            uint64_t d = all ? darts[e] : 0;
            if (all || !(st = hpfc_key_vertex_dart(v->w, vertex, e, &d)))
                check_dart(v, tp, vertex, *vi, d, *di);
        }
    }
    if (st)
        problem(v->r, "pixel %s: %s", pixel_name(px, name, sizeof name), hpfc_strerror(st));
    return st;
}

/* Whether every vertex and dart was walked (else the per-dart arrays are
 * incomplete and the checks that read them are skipped). */
static bool walk_all(verifier *v, topo *tp)
{
    size_t vi = 0, di = 0;
    hpfc_pixel px;
    int st = hpfc_leaf_first(v->f, &px);
    while (!st) {
        if (walk_leaf(v, tp, &px, &vi, &di))
            return false; /* reported */
        st = hpfc_leaf_next(v->f, &px);
    }
    if (st != HPFC_E_NO_PIXEL) {
        problem(v->r, "leaf iteration: %s", hpfc_strerror(st));
        return false;
    }
    if (vi != tp->m.nv || di != tp->m.nd) {
        problem(v->r, "the walk finds %zu vertices and %zu darts, the export %zu and %zu", vi, di,
                tp->m.nv, tp->m.nd);
        return false;
    }
    return true;
}

/* twin is an involution without fixed points, next a permutation, and
 * origin(next(d)) = origin(twin(d)) = target(d); every vertex has as many
 * darts as its degree. Returns whether next is a permutation. */
static bool check_arrays(verifier *v, topo *tp, uint8_t *seen, uint32_t *count, bool walked)
{
    const exported_map *m = &tp->m;
    bool permutation = true;
    if (m->nd % 2)
        problem(v->r, "%zu darts: not two per edge", m->nd);
    for (size_t d = 0; d < m->nd; d++) {
        uint32_t t = m->twin[d], n = m->next[d];
        if (t >= m->nd || m->twin[t] != d)
            problem(v->r, "dart %zu: twin(twin(d)) != d", d);
        else if (t == d)
            problem(v->r, "dart %zu: twin(d) == d", d);
        if (n >= m->nd || seen[n]++) {
            problem(v->r, "dart %zu: next is not a permutation", d);
            permutation = false;
        } else if (t < m->nd && m->origin[n] != m->origin[t]) {
            problem(v->r, "dart %zu: origin(next(d)) != target(d)", d);
        }
        if (m->origin[d] < m->nv)
            count[m->origin[d]]++;
    }
    for (size_t vi = 0; walked && vi < m->nv; vi++)
        if (count[vi] != tp->degree[vi])
            problem(v->r, "vertex %zu: degree %u but %u darts", vi, tp->degree[vi], count[vi]);
    return permutation;
}

/* Orbits of next (boundary loops): each lies in one face, and every face
 * has a loop. Needs next to be a permutation; `seen` is reused as marks. */
static uint64_t check_loops(verifier *v, topo *tp, uint8_t *seen)
{
    const exported_map *m = &tp->m;
    uint64_t loops = 0;
    uint8_t *used = tp->nfaces <= m->nd ? calloc(tp->nfaces + 1, 1) : NULL;
    if (!used)
        problem(v->r, "%" PRIu64 " faces but only %zu darts to bound them", tp->nfaces, m->nd);
    memset(seen, 0, m->nd);
    for (size_t d = 0; d < m->nd; d++) {
        if (seen[d])
            continue;
        loops++;
        bool one_face = true;
        for (size_t x = d; !seen[x]; x = m->next[x]) { /* a cycle: next is a permutation */
            seen[x] = 1;
            one_face &= tp->face[x] == tp->face[d];
            if (used && tp->face[x] < tp->nfaces)
                used[tp->face[x]] = 1;
        }
        if (!one_face)
            problem(v->r, "dart %zu: its boundary loop lies in several faces", d);
    }
    for (uint64_t f = 0; used && f < tp->nfaces; f++)
        if (!used[f]) {
            problem(v->r, "face %" PRIu64 " has no boundary loop", f);
            break;
        }
    free(used);
    return loops;
}

/* Connected components by union-find over the edges (origin, target). */
static uint64_t count_components(const exported_map *m, uint32_t *parent)
{
    for (size_t vi = 0; vi < m->nv; vi++)
        parent[vi] = (uint32_t)vi;
    uint64_t c = m->nv;
    for (size_t d = 0; d < m->nd; d++) {
        uint32_t a = m->origin[d], b = m->twin[d] < m->nd ? m->origin[m->twin[d]] : a;
        while (parent[a] != a)
            a = parent[a] = parent[parent[a]];
        while (parent[b] != b)
            b = parent[b] = parent[parent[b]];
        if (a != b) {
            parent[a] = b;
            c--;
        }
    }
    return c;
}

static void check_euler(verifier *v, uint64_t loops)
{
    verify_report *r = v->r;
    r->euler = (int64_t)r->vertices - (int64_t)r->edges + (int64_t)r->faces ==
                       1 + (int64_t)r->components
                   ? CHECK_OK
                   : CHECK_FAILED;
    if (r->euler != CHECK_OK)
        problem(r, "V - E + F = %" PRIu64 " - %" PRIu64 " + %" PRIu64 ", not 1 + C = %" PRIu64,
                r->vertices, r->edges, r->faces, 1 + r->components);
    r->loops = loops;
    r->loops_ok = loops + 1 == r->faces + r->components ? CHECK_OK : CHECK_FAILED;
    if (r->loops_ok != CHECK_OK)
        problem(r, "%" PRIu64 " boundary loops, F + C - 1 = %" PRIu64, loops,
                r->faces + r->components - 1);
}

/* The FEAT section against the faces just numbered: its face count, and
 * every feature, layer and link readable (an access checks each entry). */
static void check_features(verifier *v, uint64_t faces)
{
    verify_report *r = v->r;
    hpfc_features_info fi;
    int st = hpfc_file_get_features(v->f, &fi);
    if (st == HPFC_E_NO_SECTION)
        return;
    size_t before = r->problem_count;
    if (st)
        problem(r, "features: %s", hpfc_strerror(st));
    else if (fi.faces != faces)
        problem(r, "features: the FEAT section lists %u faces, the map has %" PRIu64, fi.faces,
                faces);
    for (uint32_t k = 0; !st && k < fi.features && r->problem_count == before; k++) {
        hpfc_feature ft;
        if ((st = hpfc_file_get_feature(v->f, k, &ft)))
            problem(r, "features: feature %u: %s", k, hpfc_strerror(st));
    }
    for (uint32_t l = 0; !st && l < fi.layers && r->problem_count == before; l++) {
        const char *name;
        size_t len;
        if ((st = hpfc_layer_name(v->f, l, &name, &len)))
            problem(r, "features: layer %u: %s", l, hpfc_strerror(st));
    }
    for (uint64_t f = 0; !st && f < fi.faces && r->problem_count == before; f++) {
        uint32_t count;
        hpfc_id feature;
        st = hpfc_face_feature_count(v->f, f, &count);
        for (uint32_t k = 0; !st && k < count; k++)
            st = hpfc_face_feature_id(v->f, f, k, &feature);
        if (st)
            problem(r, "features: face %" PRIu64 ": %s", f, hpfc_strerror(st));
    }
    r->features = r->problem_count == before ? CHECK_OK : CHECK_FAILED;
}

/* The LABL section against the faces just numbered (hpfc_labels_verify):
 * a disagreement is a problem of the file, never a crash. */
static void check_labels(verifier *v, const hpfc_faces *faces)
{
    verify_report *r = v->r;
    hpfc_labels_report rep;
    int st = hpfc_labels_verify(v->f, faces, &rep);
    if (st == HPFC_E_NO_SECTION)
        return;
    if (st == HPFC_E_CORRUPT)
        problem(r, "labels: %s", rep.message);
    else if (st)
        problem(r, "labels: %s", hpfc_strerror(st));
    r->labels = st ? CHECK_FAILED : CHECK_OK;
}

/* The GEOM section against the map (hpfc_geometry_verify), with the
 * traversal's vertex and edge counts. */
static void check_geometry(verifier *v, uint64_t vertices, uint64_t edges)
{
    verify_report *r = v->r;
    hpfc_geometry_info gi;
    int st = hpfc_file_get_geometry(v->f, &gi);
    if (st == HPFC_E_NO_SECTION)
        return;
    size_t before = r->problem_count;
    if (!st && (gi.vertices != vertices || gi.edges != edges))
        problem(r, "geometry: the GEOM section has %" PRIu64 " vertices and %" PRIu64
                   " edges, the map %" PRIu64 " and %" PRIu64,
                gi.vertices, gi.edges, vertices, edges);
    hpfc_geometry_report rep;
    if (!st)
        st = hpfc_geometry_verify(v->f, &rep);
    if (st == HPFC_E_CORRUPT)
        problem(r, "geometry: %s", rep.message);
    else if (st)
        problem(r, "geometry: %s", hpfc_strerror(st));
    r->geometry = r->problem_count == before ? CHECK_OK : CHECK_FAILED;
}

/* The SHIX section (1.3) against LABL, FEAT and EDGF (hpfc_index_verify). */
static void check_index(verifier *v)
{
    verify_report *r = v->r;
    hpfc_index_report rep;
    int st = hpfc_index_verify(v->f, &rep);
    if (st == HPFC_E_NO_SECTION)
        return;
    if (st == HPFC_E_CORRUPT)
        problem(r, "index: %s", rep.message);
    else if (st)
        problem(r, "index: %s", hpfc_strerror(st));
    r->index = st ? CHECK_FAILED : CHECK_OK;
}

/* The ATTR and EDGF sections (1.2) against FEAT and the map: one row per
 * feature, one entry per edge, every value and link readable. */
static void check_attr_edgf(verifier *v, uint32_t features, uint64_t edges)
{
    verify_report *r = v->r;
    hpfc_attrs_info ai;
    int st = hpfc_file_get_attrs(v->f, &ai);
    if (st && st != HPFC_E_NO_SECTION)
        problem(r, "attributes: %s", hpfc_strerror(st));
    else if (!st && ai.features != features)
        problem(r, "attributes: the ATTR section has %" PRIu64 " rows, FEAT %u features",
                ai.features, features);
    for (hpfc_id k = 0; !st && k < ai.features; k++)
        for (uint32_t c = 0; !st && c < ai.columns; c++) {
            hpfc_attr_value val;
            if ((st = hpfc_file_get_attr_value(v->f, k, c, &val)))
                problem(r, "attributes: feature %" PRIu64 " column %u: %s", k, c,
                        hpfc_strerror(st));
        }
    hpfc_edge_links_info ei;
    st = hpfc_file_get_edge_links(v->f, &ei);
    if (st && st != HPFC_E_NO_SECTION)
        problem(r, "edge features: %s", hpfc_strerror(st));
    else if (!st && ei.edges != edges)
        problem(r, "edge features: the EDGF section lists %" PRIu64 " edges, the map has %" PRIu64,
                ei.edges, edges);
    for (hpfc_id e = 0; !st && e < ei.edges; e++) {
        uint32_t count;
        hpfc_id feature;
        st = hpfc_edge_feature_count(v->f, e, &count);
        for (uint32_t k = 0; !st && k < count; k++)
            if (!(st = hpfc_edge_feature_id(v->f, e, k, &feature)) && feature >= features)
                st = HPFC_E_CORRUPT; /* EDGF's feature count is not FEAT's */
        if (st)
            problem(r, "edge features: edge %" PRIu64 ": %s", e, hpfc_strerror(st));
    }
}

static int check_topology(verifier *v)
{
    verify_report *r = v->r;
    size_t before = r->problem_count;
    topo tp = {0};
    /* the same faces on any number of threads, faster on a large file */
    int st = hpfc_faces_build_threads(v->f, default_threads(), &tp.faces);
    if (st) {
        problem(r, "faces: %s", hpfc_strerror(st));
    } else if ((st = export_map(v->f, &tp.m))) {
        problem(r, "traversal: %s", hpfc_strerror(st));
    } else {
        size_t nv = tp.m.nv + 1, nd = tp.m.nd + 1;
        tp.nfaces = hpfc_faces_face_count(tp.faces);
        check_features(v, tp.nfaces);
        check_labels(v, tp.faces);
        check_geometry(v, tp.m.nv, tp.m.nd / 2);
        check_index(v);
        hpfc_features_info fi;
        if (hpfc_file_get_features(v->f, &fi) == HPFC_OK) {
            size_t before = v->r->problem_count;
            check_attr_edgf(v, fi.features, tp.m.nd / 2);
            if (v->r->problem_count != before)
                v->r->features = CHECK_FAILED;
        }
        tp.face = malloc(nd * sizeof *tp.face);
        tp.degree = calloc(nv, sizeof *tp.degree);
        uint32_t *scratch = calloc(nv, sizeof *scratch);
        uint8_t *seen = calloc(nd, 1);
        if (!tp.face || !tp.degree || !scratch || !seen) {
            st = HPFC_E_NOMEM;
        } else {
            bool walked = walk_all(v, &tp);
            bool permutation = check_arrays(v, &tp, seen, scratch, walked);
            r->have_graph = 1;
            r->vertices = tp.m.nv;
            r->edges = tp.m.nd / 2;
            r->faces = tp.nfaces;
            r->components = count_components(&tp.m, scratch);
            if (permutation && walked)
                check_euler(v, check_loops(v, &tp, seen));
        }
        free(scratch);
        free(seen);
    }
    free(tp.face);
    free(tp.degree);
    exported_map_free(&tp.m);
    hpfc_faces_free(tp.faces);
    r->topology = r->problem_count == before ? CHECK_OK : CHECK_FAILED;
    return st == HPFC_E_NOMEM ? st : HPFC_OK;
}

/* ---- driver ---------------------------------------------------------------------- */

static int open_checked(verifier *v, const input_bytes *b, hpfc_file **f)
{
    int st = hpfc_open_memory(b->data, b->size, 0, f);
    if (st) {
        problem(v->r, "%s", hpfc_strerror(st));
        return st;
    }
    v->f = *f;
    hpfc_file_get_info(*f, &v->info);
    v->compact = v->info.incompat_flags & 0x1;
    v->data = b->data;
    v->r->format_major = v->info.format_major;
    v->r->format_minor = v->info.format_minor;
    v->r->levels = v->info.levels;
    for (uint32_t l = 0; l < v->info.levels && !st; l++)
        st = hpfc_file_get_level(*f, l, &v->lv[l]);
    if (!st)
        st = hpfc_walker_create(*f, &v->w);
    if (!st)
        st = alloc_word(v);
    if (st)
        problem(v->r, "%s", hpfc_strerror(st));
    return st;
}

static int run_checks(verifier *v, unsigned flags)
{
    verify_report *r = v->r;
    hpfc_diag diag;
    int st = hpfc_file_check_checksums(v->f, &diag);
    r->checksums = st ? CHECK_FAILED : CHECK_OK;
    if (st)
        problem(r, "section checksums: %s: %s", hpfc_strerror(st), diag.message);
    if ((st = check_structure(v)))
        return st;
    if (v->undecodable || (flags & VERIFY_STRUCTURE_ONLY))
        return HPFC_OK;
    check_roads(v);
    return check_topology(v);
}

static void report_init(verify_report *r)
{
    memset(r, 0, sizeof *r);
    r->format = r->checksums = r->structure = r->roads = r->topology = CHECK_SKIPPED;
    r->euler = r->loops_ok = r->features = r->labels = r->geometry = r->index = CHECK_SKIPPED;
}

int verify_bytes(const input_bytes *b, unsigned flags, verify_report *r)
{
    report_init(r);
    double t0 = clock_seconds();
    verifier v = {.r = r};
    hpfc_file *f = NULL;
    int st = open_checked(&v, b, &f);
    r->format = st ? CHECK_FAILED : CHECK_OK;
    if (!st && (st = run_checks(&v, flags)))
        problem(r, "%s", hpfc_strerror(st)); /* out of memory: the verdict is incomplete */
    for (uint32_t l = 0; l < HPFC_MAX_LEVELS; l++)
        free(v.images[l].v);
    free(v.word);
    hpfc_walker_free(v.w);
    hpfc_close(f);
    r->seconds = clock_seconds() - t0;
    return r->problem_count == 0;
}

int verify_file(const char *file, unsigned flags, verify_report *r)
{
    double t0 = clock_seconds();
    input_bytes b;
    int err, st = input_load(file, &b, &err);
    int valid = 0;
    if (st) {
        report_init(r);
        r->format = CHECK_FAILED;
        problem(r, "%s%s%s%s", hpfc_strerror(st), err ? " (" : "", err ? strerror(err) : "",
                err ? ")" : "");
    } else {
        valid = verify_bytes(&b, flags, r);
    }
    input_unload(&b);
    r->seconds = clock_seconds() - t0; /* reading FILE counts, as a pipe's writer sets its pace */
    return valid;
}

/* ---- reports --------------------------------------------------------------------- */

static const char *state_word(int s)
{
    return s == CHECK_OK ? "ok" : s == CHECK_FAILED ? "FAILED" : "skipped";
}

static const char *state_json(int s)
{
    return s == CHECK_OK ? "ok" : s == CHECK_FAILED ? "failed" : "skipped";
}

void verify_print_text(FILE *out, const char *path, const verify_report *r)
{
    fprintf(out, "file            %s\n", path);
    fprintf(out, "format          %s", state_word(r->format));
    if (r->format == CHECK_OK)
        fprintf(out, " (hpfc %u.%u)", r->format_major, r->format_minor);
    fprintf(out, "\nchecksums       %s\n", state_word(r->checksums));
    fprintf(out, "structure       %s\n", state_word(r->structure));
    fprintf(out, "roads           %s\n", state_word(r->roads));
    fprintf(out, "topology        %s\n", state_word(r->topology));
    if (r->format == CHECK_OK) {
        fprintf(out, "levels          %u\n", r->levels);
        fprintf(out, "pixels          %" PRIu64 " (%" PRIu64 " word, %" PRIu64 " refined, %" PRIu64
                     " private)\n",
                r->word_pixels + r->refined_pixels, r->word_pixels, r->refined_pixels,
                r->private_pixels);
    }
    if (r->have_graph) {
        fprintf(out, "vertices V      %" PRIu64 "\n", r->vertices);
        fprintf(out, "edges E         %" PRIu64 "\n", r->edges);
        fprintf(out, "faces F         %" PRIu64 "\n", r->faces);
        fprintf(out, "components C    %" PRIu64 "\n", r->components);
        if (r->loops_ok != CHECK_SKIPPED)
            fprintf(out, "boundary loops  %" PRIu64 " (= F + C - 1: %s)\n", r->loops,
                    state_word(r->loops_ok));
        if (r->euler != CHECK_SKIPPED)
            fprintf(out, "Euler           V - E + F = 1 + C: %s\n", state_word(r->euler));
    }
    if (r->features != CHECK_SKIPPED)
        fprintf(out, "features        FEAT section: %s\n", state_word(r->features));
    if (r->labels != CHECK_SKIPPED)
        fprintf(out, "labels          LABL section: %s\n", state_word(r->labels));
    if (r->geometry != CHECK_SKIPPED)
        fprintf(out, "geometry        GEOM section: %s\n", state_word(r->geometry));
    if (r->index != CHECK_SKIPPED)
        fprintf(out, "index           SHIX section: %s\n", state_word(r->index));
    fprintf(out, "time            %.3f s\n", r->seconds);
    if (r->problem_count == 0) {
        fprintf(out, "verdict         valid\n");
        return;
    }
    fprintf(out, "verdict         INVALID (%zu problem%s)\n", r->problem_count,
            r->problem_count == 1 ? "" : "s");
    for (size_t k = 0; k < r->problem_count && k < VERIFY_MAX_PROBLEMS; k++)
        fprintf(out, "  %s\n", r->problems[k]);
    if (r->problem_count > VERIFY_MAX_PROBLEMS)
        fprintf(out, "  ... and %zu more\n", r->problem_count - VERIFY_MAX_PROBLEMS);
}

void verify_print_json(FILE *out, const char *path, const verify_report *r)
{
    jsonw w;
    jsonw_init(&w, out);
    jsonw_object_begin(&w, NULL);
    jsonw_string(&w, "file", path);
    jsonw_bool(&w, "valid", r->problem_count == 0);
    jsonw_object_begin(&w, "checks");
    jsonw_string(&w, "format", state_json(r->format));
    jsonw_string(&w, "checksums", state_json(r->checksums));
    jsonw_string(&w, "structure", state_json(r->structure));
    jsonw_string(&w, "roads", state_json(r->roads));
    jsonw_string(&w, "topology", state_json(r->topology));
    jsonw_string(&w, "euler", state_json(r->euler));
    jsonw_string(&w, "boundary_loops", state_json(r->loops_ok));
    if (r->features != CHECK_SKIPPED) /* only files with a FEAT section */
        jsonw_string(&w, "features", state_json(r->features));
    if (r->labels != CHECK_SKIPPED) /* only files with a LABL section */
        jsonw_string(&w, "labels", state_json(r->labels));
    if (r->geometry != CHECK_SKIPPED) /* only files with a GEOM section */
        jsonw_string(&w, "geometry", state_json(r->geometry));
    if (r->index != CHECK_SKIPPED) /* only files with a SHIX section */
        jsonw_string(&w, "index", state_json(r->index));
    jsonw_object_end(&w);
    if (r->format == CHECK_OK) {
        jsonw_u64(&w, "levels", r->levels);
        jsonw_u64(&w, "pixels", r->word_pixels + r->refined_pixels);
        jsonw_u64(&w, "word_pixels", r->word_pixels);
        jsonw_u64(&w, "refined_pixels", r->refined_pixels);
        jsonw_u64(&w, "private_pixels", r->private_pixels);
    }
    if (r->have_graph) {
        jsonw_u64(&w, "vertices", r->vertices);
        jsonw_u64(&w, "edges", r->edges);
        jsonw_u64(&w, "faces", r->faces);
        jsonw_u64(&w, "components", r->components);
        if (r->loops_ok != CHECK_SKIPPED)
            jsonw_u64(&w, "boundary_loops", r->loops);
    }
    jsonw_double(&w, "seconds", r->seconds, 3);
    jsonw_u64(&w, "problem_count", r->problem_count);
    jsonw_array_begin(&w, "problems");
    for (size_t k = 0; k < r->problem_count && k < VERIFY_MAX_PROBLEMS; k++)
        jsonw_string(&w, NULL, r->problems[k]);
    jsonw_array_end(&w);
    jsonw_object_end(&w);
    jsonw_finish(&w);
}
