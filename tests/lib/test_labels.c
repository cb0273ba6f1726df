/*
 * The LABL section (spec/hpfc-format.md §6.5) against independent oracles:
 *   - leaf numbers: within a level, ranking the leaves by their slot's
 *     position in the pool (reader_leaf_slot_bit) gives 0, 1, 2, ...; the
 *     walk without the section gives the same numbers;
 *   - faces: hpfc_faces_build's flood fill, on every stretch, dart and
 *     private leaf;
 *   - edge ids: the input graph: a dart's edge has its origin's pixel
 *     around one of its ends, its twin has the same edge, every edge has
 *     two darts; a crossing seen from both sides of its road has one edge.
 * On generated graphs under several image sizes, flat and deep.
 */
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "file.h"
#include "gen.h"
#include "hpfc.h"
#include "labels.h"
#include "reader.h"
#include "topo.h"

typedef struct packed {
    uint8_t *with, *without;
    hpfc_file *f, *f0;
    hpfc_tree *tree;
    hpfc_faces *handed; /* the faces the write of `with` handed out (faces_out) */
} packed;

static int pack(const hpfc_graph *g, uint32_t n0, uint32_t n, int flat, packed *p)
{
    memset(p, 0, sizeof *p);
    hpfc_build_params bp;
    hpfc_build_params_default(&bp);
    bp.root_cols = bp.root_rows = n0;
    bp.cols = bp.rows = n;
    bp.flat = flat;
    size_t s1, s0;
    hpfc_write_options o = {.face_labels = 1, .faces_out = &p->handed};
    int st = hpfc_build(g, &bp, &p->tree, NULL);
    if (!st)
        st = check_tree_serialize(p->tree, &o, &p->with, &s1, NULL);
    if (!st)
        st = check_tree_serialize(p->tree, NULL, &p->without, &s0, NULL);
    if (!st)
        st = hpfc_open_memory(p->with, s1, 0, &p->f);
    if (!st)
        st = hpfc_open_memory(p->without, s0, 0, &p->f0);
    return st;
}

static void unpack(packed *p)
{
    hpfc_close(p->f);
    hpfc_close(p->f0);
    hpfc_free(p->with);
    hpfc_free(p->without);
    hpfc_tree_free(p->tree);
    hpfc_faces_free(p->handed);
}

typedef struct slot_rank {
    uint64_t slot, rank;
} slot_rank;

static int cmp_slot(const void *a, const void *b)
{
    const slot_rank *x = a, *y = b;
    return (x->slot > y->slot) - (x->slot < y->slot);
}

/* A leaf's pieces (labels_leaf_pieces, `known` as a walk gave it or NULL)
 * against its labels loaded with its word (`a`): private alike, the face
 * of a private leaf, else as many pieces as the word has and crossing k's
 * edge at its piece. */
static void check_pieces(const packed *p, const hpfc_pixel *px, const reader_leaf_at *known,
                         const labels_leaf *a)
{
    labels_pieces lp = {0};
    uint64_t e = UINT64_MAX;
    CHECK_EQ_INT(labels_leaf_pieces(p->f, px, known, &lp), HPFC_OK);
    CHECK_EQ_INT(lp.is_private, a->rec.word.n == 0);
    CHECK_EQ_INT(lp.off, a->rec.off);
    if (a->rec.word.n == 0) {
        uint64_t face = UINT64_MAX;
        CHECK_EQ_INT(labels_leaf_face(p->f, a, 0, &face), HPFC_OK);
        CHECK_EQ_INT(lp.face, face);
        CHECK_EQ_INT(labels_piece_edge(p->f, &lp, 0, &e), HPFC_E_ARG);
        return;
    }
    CHECK_EQ_INT(lp.count, a->rec.word.pieces);
    for (uint32_t k = 0; k < a->rec.word.n; k++) {
        CHECK_EQ_INT(labels_piece_edge(p->f, &lp, a->rec.word.piece[k], &e), HPFC_OK);
        CHECK_EQ_INT(e, a->edge[k]);
    }
    CHECK_EQ_INT(labels_piece_edge(p->f, &lp, lp.count, &e), HPFC_E_ARG);
}

/* The window's shortcuts against the public calls they stand for: a
 * child read from its parent's image (reader_child), a leaf's word with
 * its rank (reader_leaf_word: the rank only in the compact layout) and
 * its labels loaded with that word (labels_leaf_load_word), and its
 * pieces' edges read from the record's extent without the word
 * (labels_leaf_pieces), ranked here or from a walk over its image. */
static void check_leaf_shortcuts(const packed *p, const hpfc_pixel *px, uint64_t rank)
{
    char want[4096], got[4096], *grown = NULL;
    size_t want_len = 0, got_len = 0, cap = 0;
    uint64_t got_rank = 0;
    CHECK_EQ_INT(hpfc_pixel_word(p->f, px, want, sizeof want, &want_len), HPFC_OK);
    CHECK_EQ_INT(reader_leaf_word(p->f, px, NULL, got, sizeof got, &got_len, &got_rank), HPFC_OK);
    CHECK_EQ_INT(got_len, want_len);
    CHECK(memcmp(got, want, want_len) == 0);
    CHECK_EQ_INT(got_rank, p->f->compact ? rank : UINT64_MAX);
    if (want_len > 0) /* one byte short: the length needed */
        CHECK_EQ_INT(reader_leaf_word(p->f, px, NULL, got, want_len - 1, &got_len, &got_rank),
                     HPFC_E_BUFFER_SMALL);
    labels_leaf a = {0}, b = {0};
    CHECK_EQ_INT(labels_leaf_load(p->f, px, want, want_len, &a), HPFC_OK);
    CHECK_EQ_INT(labels_leaf_load_word(p->f, px, NULL, &grown, &cap, &b), HPFC_OK);
    CHECK_EQ_INT(b.rec.word.n, a.rec.word.n);
    CHECK_EQ_INT(b.rec.off, a.rec.off);
    for (uint32_t k = 0; k < a.rec.word.n && k < b.rec.word.n; k++)
        CHECK_EQ_INT(b.edge[k], a.edge[k]);
    /* the pieces without the word: the crossings' edges, each piece once
     * (a stabbing's two crossings share theirs), or the private face */
    check_pieces(p, px, NULL, &a);
    labels_leaf_free(&a);
    labels_leaf_free(&b);
    free(grown);
    if (px->depth == 0)
        return;
    hpfc_pixel parent, child, want_child;
    uint64_t image = 0;
    int type = -1;
    uint32_t i = px->path[px->depth].i, j = px->path[px->depth].j;
    CHECK_EQ_INT(hpfc_pixel_parent(px, &parent), HPFC_OK);
    CHECK_EQ_INT(reader_child_image(p->f, &parent, &image), HPFC_OK);
    CHECK_EQ_INT(reader_child_image(p->f, px, &image), HPFC_E_NO_PIXEL);
    CHECK_EQ_INT(reader_child_image(p->f, &parent, &image), HPFC_OK);
    CHECK_EQ_INT(hpfc_pixel_child(p->f, &parent, i, j, &want_child), HPFC_OK);
    CHECK_EQ_INT(reader_child(p->f, &parent, image, i, j, &child, &type), HPFC_OK);
    CHECK_EQ_INT(type, HPFC_PIXEL_WORD);
    CHECK_EQ_INT(child.depth, want_child.depth);
    CHECK(memcmp(child.path, want_child.path, (child.depth + 1) * sizeof child.path[0]) == 0);
    CHECK_EQ_INT(reader_child(p->f, &parent, image, UINT32_MAX, j, &child, &type), HPFC_E_ARG);
    /* the same child from a walk over its image's counts, with its rank and
     * its word's place (compact images of up to 28 pixels) */
    reader_children c;
    reader_leaf_at at;
    CHECK_EQ_INT(reader_children_begin(p->f, &parent, &c), HPFC_OK);
    CHECK_EQ_INT(reader_children_get(p->f, &c, i, j, &child, &type, &at), HPFC_OK);
    CHECK_EQ_INT(type, HPFC_PIXEL_WORD);
    CHECK(memcmp(child.path, want_child.path, (child.depth + 1) * sizeof child.path[0]) == 0);
    hpfc_file_info fi; /* px is below the root: its image is cols x rows */
    hpfc_file_get_info(p->f, &fi);
    bool counted = p->f->compact && (uint64_t)fi.cols * fi.rows <= 28;
    CHECK_EQ_INT(at.rank, counted ? rank : UINT64_MAX);
    if (counted) {
        int is_private = -1;
        CHECK_EQ_INT(hpfc_pixel_is_private(p->f, px, &is_private), HPFC_OK);
        CHECK_EQ_INT(at.word == UINT64_MAX, is_private);
        size_t len = 0;
        uint64_t r = 0;
        CHECK_EQ_INT(reader_leaf_word(p->f, px, &at, got, sizeof got, &len, &r), HPFC_OK);
        CHECK(len == want_len && memcmp(got, want, len) == 0 && r == rank);
        labels_leaf a2 = {0};
        CHECK_EQ_INT(labels_leaf_load(p->f, px, want, want_len, &a2), HPFC_OK);
        check_pieces(p, px, &at, &a2);
        labels_leaf_free(&a2);
    }
    CHECK_EQ_INT(reader_children_get(p->f, &c, i, UINT32_MAX, &child, &type, &at), HPFC_E_ARG);
}

static void check_ranks(const packed *p)
{
    hpfc_file_info fi;
    hpfc_file_get_info(p->f, &fi);
    uint64_t leaves = file_total_leaves(p->f);
    slot_rank *sr[HPFC_MAX_LEVELS] = {0};
    uint64_t count[HPFC_MAX_LEVELS] = {0};
    for (uint32_t l = 0; l < fi.levels; l++)
        sr[l] = calloc(leaves + 1, sizeof **sr);
    hpfc_pixel px;
    int st;
    for (st = hpfc_leaf_first(p->f, &px); !st; st = hpfc_leaf_next(p->f, &px)) {
        uint64_t slot = 0, rank = 0, walk = 0;
        CHECK_EQ_INT(reader_leaf_slot_bit(p->f, &px, &slot), HPFC_OK);
        CHECK_EQ_INT(hpfc_leaf_number(p->f, &px, &rank), HPFC_OK);
        CHECK_EQ_INT(hpfc_leaf_number(p->f0, &px, &walk), HPFC_OK); /* no section: the walk */
        CHECK_EQ_INT(rank, walk);
        check_leaf_shortcuts(p, &px, rank);
        sr[px.depth][count[px.depth]++] = (slot_rank){slot, rank};
    }
    CHECK_EQ_INT(st, HPFC_E_NO_PIXEL);
    for (uint32_t l = 0; l < fi.levels; l++) {
        hpfc_level_info li;
        hpfc_file_get_level(p->f, l, &li);
        CHECK_EQ_INT(count[l], li.word_pixels);
        qsort(sr[l], count[l], sizeof **sr, cmp_slot);
        for (uint64_t k = 0; k < count[l]; k++)
            if (sr[l][k].rank != k) {
                CHECK_EQ_INT(sr[l][k].rank, k);
                break;
            }
        free(sr[l]);
    }
}

/* A leaf as a subtree scan gives it. */
typedef struct scan_leaf {
    uint32_t level;
    uint64_t rank;
    bool is_private;
    hpfc_pixel px; /* found child by child */
} scan_leaf;

typedef struct scan_list {
    scan_leaf *at;
    size_t n, cap;
} scan_list;

static int cmp_scan_leaf(const void *a, const void *b)
{
    const scan_leaf *x = a, *y = b;
    if (x->level != y->level)
        return (x->level > y->level) - (x->level < y->level);
    return (x->rank > y->rank) - (x->rank < y->rank);
}

/* The leaves below px by hpfc_pixel_child, numbered by hpfc_leaf_number. */
static void subtree_leaves(const packed *p, const hpfc_pixel *px, scan_list *out)
{
    hpfc_file_info fi;
    hpfc_file_get_info(p->f, &fi);
    for (uint32_t j = 0; j < fi.rows; j++)
        for (uint32_t i = 0; i < fi.cols; i++) {
            hpfc_pixel c;
            int type = -1, is_private = -1;
            CHECK_EQ_INT(hpfc_pixel_child(p->f, px, i, j, &c), HPFC_OK);
            CHECK_EQ_INT(hpfc_pixel_type(p->f, &c, &type), HPFC_OK);
            if (type == HPFC_PIXEL_REFINED) {
                subtree_leaves(p, &c, out);
                continue;
            }
            if (out->n == out->cap) {
                out->cap = out->cap ? 2 * out->cap : 64;
                out->at = realloc(out->at, out->cap * sizeof *out->at);
                CHECK(out->at != NULL);
            }
            scan_leaf *l = &out->at[out->n++];
            l->level = c.depth;
            l->px = c;
            CHECK_EQ_INT(hpfc_leaf_number(p->f, &c, &l->rank), HPFC_OK);
            CHECK_EQ_INT(hpfc_pixel_is_private(p->f, &c, &is_private), HPFC_OK);
            l->is_private = is_private;
        }
}

/* The scan below refined pixel px (reader_scan, compact only) against its
 * leaves found child by child, in (level, rank) order; and each leaf's
 * pieces read in the scan's order, chained from record to record
 * (labels_leaf_pieces_ranked), against labels_leaf_pieces. */
static void check_scan(const packed *p, const hpfc_pixel *px)
{
    reader_scan sc;
    if (!p->f->compact) {
        CHECK_EQ_INT(reader_scan_begin(p->f, px, &sc), HPFC_E_ARG);
        return;
    }
    scan_list want = {0};
    subtree_leaves(p, px, &want);
    qsort(want.at, want.n, sizeof *want.at, cmp_scan_leaf);
    CHECK_EQ_INT(reader_scan_begin(p->f, px, &sc), HPFC_OK);
    scan_leaf got;
    size_t n = 0;
    uint64_t next = UINT64_MAX;
    int st;
    while (!(st = reader_scan_next(p->f, &sc, &got.level, &got.rank, &got.is_private))) {
        CHECK(n < want.n);
        if (n >= want.n)
            break;
        const scan_leaf *w = &want.at[n];
        CHECK(got.level == w->level && got.rank == w->rank && got.is_private == w->is_private);
        if (n > 0 && want.at[n - 1].level != got.level)
            next = UINT64_MAX; /* a new level's run */
        labels_pieces a, b;
        CHECK_EQ_INT(labels_leaf_pieces_ranked(p->f, got.level, got.rank, got.is_private, &next,
                                               &a), HPFC_OK);
        CHECK_EQ_INT(labels_leaf_pieces(p->f, &w->px, NULL, &b), HPFC_OK);
        CHECK(a.is_private == b.is_private && a.off == b.off && a.count == b.count &&
              (!a.is_private || a.face == b.face));
        n++;
    }
    CHECK_EQ_INT(st, HPFC_E_NO_PIXEL);
    CHECK_EQ_INT(n, want.n);
    free(want.at);
}

/* check_scan below px and every refined pixel under it. */
static void check_scans_below(const packed *p, const hpfc_pixel *px)
{
    hpfc_file_info fi;
    hpfc_file_get_info(p->f, &fi);
    check_scan(p, px);
    for (uint32_t j = 0; j < fi.rows; j++)
        for (uint32_t i = 0; i < fi.cols; i++) {
            hpfc_pixel c;
            int type = -1;
            CHECK_EQ_INT(hpfc_pixel_child(p->f, px, i, j, &c), HPFC_OK);
            CHECK_EQ_INT(hpfc_pixel_type(p->f, &c, &type), HPFC_OK);
            if (type == HPFC_PIXEL_REFINED)
                check_scans_below(p, &c);
        }
}

/* Every refined pixel's subtree scan (the window's inside subtrees); a
 * leaf has none. */
static void check_scans(const packed *p)
{
    hpfc_file_info fi;
    hpfc_file_get_info(p->f, &fi);
    for (uint32_t j = 0; j < fi.root_rows; j++)
        for (uint32_t i = 0; i < fi.root_cols; i++) {
            hpfc_pixel root;
            int type = -1;
            reader_scan sc;
            CHECK_EQ_INT(hpfc_pixel_root(p->f, i, j, &root), HPFC_OK);
            CHECK_EQ_INT(hpfc_pixel_type(p->f, &root, &type), HPFC_OK);
            if (type == HPFC_PIXEL_REFINED)
                check_scans_below(p, &root);
            else
                CHECK_EQ_INT(reader_scan_begin(p->f, &root, &sc), HPFC_E_ARG);
        }
}

/* Faces: every stretch, dart and region against hpfc_faces_build. */
static void check_leaf_faces(const packed *p, const hpfc_faces *fc, const hpfc_pixel *px,
                             const word_parts *lw)
{
    size_t count = 0;
    uint64_t regions[512];
    CHECK_EQ_INT(hpfc_label_leaf_faces(p->f, px, NULL, 0, &count), HPFC_OK);
    if (lw->n == 0) {
        uint64_t want = 0, got = 1, handed = 2;
        CHECK_EQ_INT(count, 1);
        CHECK_EQ_INT(hpfc_faces_pixel_face(fc, px, &want), HPFC_OK);
        CHECK_EQ_INT(hpfc_faces_pixel_face(p->handed, px, &handed), HPFC_OK);
        CHECK_EQ_INT(handed, want);
        CHECK_EQ_INT(hpfc_label_stretch_face(p->f, px, 0, &got), HPFC_OK);
        CHECK_EQ_INT(got, want);
        CHECK_EQ_INT(hpfc_label_stretch_face(p->f, px, 1, &got), HPFC_E_ARG);
        return;
    }
    CHECK_EQ_INT(count, lw->n - lw->ncomp + 1);
    if (count > 512)
        return;
    CHECK_EQ_INT(hpfc_label_leaf_faces(p->f, px, regions, count, &count), HPFC_OK);
    if (count > 1) { /* one short: the count needed, HPFC_E_BUFFER_SMALL */
        size_t need = count;
        CHECK_EQ_INT(hpfc_label_leaf_faces(p->f, px, regions, count - 1, &count),
                     HPFC_E_BUFFER_SMALL);
        CHECK_EQ_INT(count, need);
    }
    for (uint32_t k = 0; k < lw->n; k++) {
        hpfc_dart d = {.pixel = *px, .crossing = k};
        uint64_t want = 0, got = 1, stretch = 2, handed = 3;
        CHECK_EQ_INT(hpfc_faces_dart_face(fc, &d, &want), HPFC_OK);
        CHECK_EQ_INT(hpfc_faces_dart_face(p->handed, &d, &handed), HPFC_OK);
        CHECK_EQ_INT(handed, want);
        CHECK_EQ_INT(hpfc_label_dart_face(p->f, &d, &got), HPFC_OK);
        CHECK_EQ_INT(got, want);
        CHECK_EQ_INT(hpfc_label_stretch_face(p->f, px, (k + 1) % lw->n, &stretch), HPFC_OK);
        CHECK_EQ_INT(stretch, want);
        bool listed = false; /* the region holding that stretch is among the leaf's */
        for (size_t r = 0; r < count; r++)
            listed |= regions[r] == want;
        CHECK(listed);
    }
    hpfc_dart bad = {.pixel = *px, .crossing = lw->n};
    uint64_t x;
    CHECK_EQ_INT(hpfc_label_dart_face(p->f, &bad, &x), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_label_crossing_edge(p->f, px, lw->n, &x), HPFC_E_ARG);
}

/* Edge ids: a crossing and the same crossing across its road. */
static void check_leaf_edges(const packed *p, hpfc_walker *w, const hpfc_pixel *px,
                             uint64_t *darts_of_edge, const hpfc_graph *g)
{
    const word_parts *lw = &w->p_word;
    for (uint32_t k = 0; k < lw->n; k++) {
        uint64_t e = UINT64_MAX, e2 = UINT64_MAX;
        CHECK_EQ_INT(hpfc_label_crossing_edge(p->f, px, k, &e), HPFC_OK);
        CHECK(e < hpfc_graph_edge_count(g));
        if (e >= hpfc_graph_edge_count(g))
            continue;
        if (lw->comp_vertex[lw->comp[k]] != TOPO_NONE) { /* a dart: its origin's pixel holds an end */
            darts_of_edge[e]++;
            uint32_t u, v;
            const int64_t *xy;
            size_t ni;
            int64_t ux, uy, vx, vy, x0, y0, x1, y1;
            hpfc_graph_edge(g, e, &u, &v, &xy, &ni);
            hpfc_graph_vertex(g, u, &ux, &uy);
            hpfc_graph_vertex(g, v, &vx, &vy);
            hpfc_pixel_bounds(p->f, px, &x0, &y0, &x1, &y1);
            CHECK((ux >= x0 && ux < x1 && uy >= y0 && uy < y1) ||
                  (vx >= x0 && vx < x1 && vy >= y0 && vy < y1));
        } else { /* a stabbing's two crossings lie on one edge */
            CHECK_EQ_INT(hpfc_label_crossing_edge(p->f, px, lw->pred[k], &e2), HPFC_OK);
            CHECK_EQ_INT(e2, e);
        }
        if (k < lw->road_off[HPFC_EAST]) { /* W and N roads: across is Q's E or S */
            hpfc_pixel q;
            uint32_t m;
            CHECK_EQ_INT(topo_cross_road(w, px, true, lw, k, &q, &w->q_word, &m), HPFC_OK);
            CHECK_EQ_INT(hpfc_label_crossing_edge(p->f, &q, m, &e2), HPFC_OK);
            CHECK_EQ_INT(e2, e);
        }
    }
}

/* The faces the write handed out: the count at once, nothing else until
 * bound to the file written (then every answer hpfc_faces_build's, which
 * check_leaf_faces compares), bound once only. */
static void check_handed_faces(const packed *p, hpfc_faces *fc)
{
    CHECK(p->handed != NULL);
    if (!p->handed)
        return;
    CHECK_EQ_INT(hpfc_faces_face_count(p->handed), hpfc_faces_face_count(fc));
    hpfc_pixel px;
    uint64_t face;
    CHECK_EQ_INT(hpfc_leaf_first(p->f, &px), HPFC_OK);
    hpfc_dart d = {.pixel = px, .crossing = 0};
    CHECK_EQ_INT(hpfc_faces_pixel_face(p->handed, &px, &face), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_faces_dart_face(p->handed, &d, &face), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_faces_attach(p->handed, NULL), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_faces_attach(NULL, p->f), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_faces_attach(p->handed, p->f), HPFC_OK);
    CHECK_EQ_INT(hpfc_faces_attach(p->handed, p->f), HPFC_E_ARG);
    CHECK_EQ_INT(hpfc_faces_attach(fc, p->f), HPFC_E_ARG); /* bound from the start */
}

/* Faces handed out for one file are refused by another: a map with other
 * pools, and the same file with one pool byte changed; no faces are handed
 * out without LABL, nor by the calls that copy an open file. */
static void check_attach_refused(const hpfc_graph *g)
{
    packed a, b;
    CHECK_EQ_INT(pack(g, 4, 2, 0, &a), HPFC_OK);
    CHECK_EQ_INT(pack(g, 3, 3, 0, &b), HPFC_OK);
    if (a.f && b.f && a.handed) {
        CHECK_EQ_INT(hpfc_faces_attach(a.handed, b.f), HPFC_E_ARG);
        /* a byte of the deepest level's pool changed in a copy */
        hpfc_file_info fi;
        hpfc_level_info lv;
        hpfc_file_get_info(a.f, &fi);
        hpfc_file_get_level(a.f, fi.levels - 1, &lv);
        size_t size = a.f->size;
        uint8_t *copy = malloc(size);
        hpfc_file *changed = NULL;
        CHECK(copy != NULL);
        if (copy) {
            memcpy(copy, a.with, size);
            copy[lv.pool_offset + (lv.pool_bits / 8) / 2] ^= 0x10;
            if (hpfc_open_memory(copy, size, 0, &changed) == HPFC_OK)
                CHECK_EQ_INT(hpfc_faces_attach(a.handed, changed), HPFC_E_ARG);
            hpfc_close(changed);
            free(copy);
        }
        CHECK_EQ_INT(hpfc_faces_attach(a.handed, a.f0), HPFC_OK); /* the same pools, no LABL */
    }
    hpfc_faces *out = (hpfc_faces *)&out; /* not NULL: the calls must clear it */
    uint8_t *bytes = NULL;
    size_t n = 0;
    hpfc_write_options none = {.faces_out = &out};
    CHECK_EQ_INT(check_tree_serialize(a.tree, &none, &bytes, &n, NULL), HPFC_OK);
    CHECK(out == NULL);
    hpfc_free(bytes);
    out = (hpfc_faces *)&out;
    CHECK_EQ_INT(hpfc_file_serialize(a.f, &none, &bytes, &n, NULL), HPFC_OK);
    CHECK(out == NULL);
    hpfc_free(bytes);
    unpack(&a);
    unpack(&b);
}

static void check_map(const hpfc_graph *g, uint32_t n0, uint32_t n, int flat)
{
    packed p;
    int st = pack(g, n0, n, flat, &p);
    CHECK_EQ_INT(st, HPFC_OK);
    if (st) {
        unpack(&p);
        return;
    }
    hpfc_labels_info li;
    CHECK_EQ_INT(hpfc_file_get_labels(p.f0, &li), HPFC_E_NO_SECTION);
    CHECK_EQ_INT(hpfc_file_get_labels(p.f, &li), HPFC_OK);
    CHECK_EQ_INT(li.edges, hpfc_graph_edge_count(g));
    check_ranks(&p);
    check_scans(&p);
    hpfc_faces *fc = NULL;
    hpfc_walker *w = NULL;
    CHECK_EQ_INT(hpfc_faces_build(p.f, &fc), HPFC_OK);
    CHECK_EQ_INT(hpfc_walker_create(p.f, &w), HPFC_OK);
    CHECK_EQ_INT(li.faces, hpfc_faces_face_count(fc));
    check_handed_faces(&p, fc);
    uint64_t *darts_of_edge = calloc(hpfc_graph_edge_count(g), sizeof *darts_of_edge);
    hpfc_pixel px;
    for (st = hpfc_leaf_first(p.f, &px); !st; st = hpfc_leaf_next(p.f, &px)) {
        CHECK_EQ_INT(topo_parse_pixel(w, &w->p_word, &px), HPFC_OK);
        check_leaf_faces(&p, fc, &px, &w->p_word);
        check_leaf_edges(&p, w, &px, darts_of_edge, g);
    }
    for (size_t e = 0; e < hpfc_graph_edge_count(g); e++)
        if (darts_of_edge[e] != 2) {
            CHECK_EQ_INT(darts_of_edge[e], 2);
            break;
        }
    hpfc_labels_report rep;
    CHECK_EQ_INT(hpfc_labels_verify(p.f, fc, &rep), HPFC_OK);
    if (rep.message[0])
        fprintf(stderr, "verify: %s\n", rep.message);
    CHECK_EQ_INT(rep.leaves_checked, file_total_leaves(p.f));
    /* hpfc_file_serialize keeps the section: the same labels after */
    uint8_t *again = NULL;
    size_t size = 0;
    hpfc_file *f2 = NULL;
    CHECK_EQ_INT(hpfc_file_serialize(p.f, NULL, &again, &size, NULL), HPFC_OK);
    CHECK_EQ_INT(hpfc_open_memory(again, size, 0, &f2), HPFC_OK);
    hpfc_labels_info li2;
    CHECK_EQ_INT(hpfc_file_get_labels(f2, &li2), HPFC_OK);
    CHECK_EQ_INT(li2.section_bytes, li.section_bytes);
    hpfc_close(f2);
    hpfc_free(again);
    free(darts_of_edge);
    hpfc_walker_free(w);
    hpfc_faces_free(fc);
    unpack(&p);
}

static void check_graph(const hpfc_graph *g)
{
    check_attach_refused(g);
    check_map(g, 1, 2, 0);
    check_map(g, 4, 2, 0);
    check_map(g, 3, 3, 0);
    check_map(g, 16, 4, 0);
    check_map(g, 64, 2, 0);
}

/* spec/hpfc-format.md §6.5.7: the triangle with a dead end of §9, root
 * 2 x 2, refined 2 x 2: the LABL section's 84 bytes as printed there, and
 * §6.8.5: the SHIX section's 40 bytes after it (the file 432 bytes). */
static void check_worked_example(void)
{
    static const uint8_t want_shix[40] = {
        0x02, 0, 0, 0, 0x04, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
        0x06, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
        0x0f, 0x0c, 0x30, 0, 0, 0, 0, 0};
    static const uint8_t want[84] = {
        0x02, 0, 0, 0, 0, 0, 0, 0, 0x04, 0, 0, 0, 0, 0, 0, 0,
        0x04, 0, 0, 0, 0, 0, 0, 0, 0x1b, 0, 0, 0, 0, 0, 0, 0,
        0x01, 0x02, 0x01, 0x05, 0x04, 0x03, 0, 0, 0x01, 0, 0, 0, 0, 0, 0, 0,
        0x03, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
        0x01, 0xa6, 0x40, 0, 0, 0, 0, 0, 0x6b, 0, 0, 0, 0, 0, 0, 0,
        0x95, 0x4c, 0x0e, 0x60};
    static const int64_t xy[4][2] = {{0, 0}, {10, 0}, {5, 8}, {5, 3}};
    static const uint32_t uv[4][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}};
    hpfc_graph *g = NULL;
    CHECK_EQ_INT(hpfc_graph_create(&g), HPFC_OK);
    for (int k = 0; k < 4; k++)
        CHECK_EQ_INT(hpfc_graph_add_vertex(g, xy[k][0], xy[k][1], NULL), HPFC_OK);
    for (int k = 0; k < 4; k++)
        CHECK_EQ_INT(hpfc_graph_add_edge(g, uv[k][0], uv[k][1], NULL, 0, NULL), HPFC_OK);
    packed p;
    CHECK_EQ_INT(pack(g, 2, 2, 0, &p), HPFC_OK);
    hpfc_section_info si;
    bool found = false;
    for (uint32_t k = 0; p.f && hpfc_file_get_section(p.f, k, &si) == HPFC_OK; k++)
        if (memcmp(si.tag, "LABL", 4) == 0) {
            found = true;
            CHECK_EQ_INT(si.offset, 304);
            CHECK_EQ_INT(si.length, sizeof want);
            CHECK(si.length == sizeof want && memcmp(p.with + si.offset, want, sizeof want) == 0);
        } else if (memcmp(si.tag, "SHIX", 4) == 0) {
            CHECK_EQ_INT(si.offset, 392);
            CHECK(si.length == sizeof want_shix &&
                  memcmp(p.with + si.offset, want_shix, sizeof want_shix) == 0);
            CHECK_EQ_INT(si.offset + si.length, 432);
        }
    CHECK(found);
    unpack(&p);
    hpfc_graph_free(g);
}

int main(void)
{
    check_use_test_layout();
    check_worked_example();
    for (int which = 0; which < GEN_SPECIAL_COUNT; which++) {
        hpfc_graph *g = NULL;
        CHECK_EQ_INT(gen_special(which, &g), HPFC_OK);
        if (g)
            check_graph(g);
        hpfc_graph_free(g);
    }
    for (uint64_t seed = 1; seed <= 3; seed++) {
        hpfc_graph *g = NULL;
        CHECK_EQ_INT(gen_delaunay(seed, 120 * seed, 1 << 16, 0.2, &g), HPFC_OK);
        if (g)
            check_graph(g);
        hpfc_graph_free(g);
        g = NULL;
        CHECK_EQ_INT(gen_polyline(seed, 200, 1 << 16, 0.5, &g), HPFC_OK);
        if (g)
            check_graph(g);
        hpfc_graph_free(g);
    }
    return check_report("test_labels");
}
