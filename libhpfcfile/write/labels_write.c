/*
 * The LABL section on the write side (spec/hpfc-format.md §6.5): from the
 * builder's tree (each crossing's input edge, hpfc_tree_pixel.cross_edge)
 * and the faces of the serialised file (hpfc_faces_build, the numbering of
 * §3.11), every leaf's record in leaf-number order, the block directory of
 * the records' offsets and the rank samples.
 *
 * Leaves are visited in the tree's image order, which is the pools' (§5.2.2:
 * images in parent order, back to back), so the running word count is the
 * leaf number and the running image offset is where the reader finds the
 * slot (in the compact layout, the pixel's type bits); faces_leaf_nodes
 * looks the leaf up by that position.
 *
 * labels_build_stream makes the same bytes with the faces numbered a root
 * pixel at a time (faces_stream, faces.h), for a writer whose memory must
 * follow the roots' borders: passes 1 and 2 go in leaf order without
 * faces (sizes, then the directory and each edge's first level) and note
 * where each root's run of images and records starts on each level; pass
 * 3 goes root by root, each root's runs level by level, and writes the
 * records and the sides.
 *
 * Either way pass 1 alone gives the section's length
 * (labels_writer_begin), and the other passes make it in bytes the caller
 * placed (labels_writer_emit): the file's own pages, for the writer that
 * makes a file in place.
 */
#include <stdlib.h>
#include <string.h>

#include "arrays.h"
#include "diag.h"
#include "faces.h"
#include "file.h"
#include "labels.h"

/* Block sizes 2^0 .. 2^(DIR_SHIFTS - 1) leaves for the directory. */
enum { DIR_SHIFTS = 11 };

/* What pass 1 learns: the records' bits, the largest offset inside a block
 * at each block size, each level's samples (whole; streamed, pass 2 writes
 * them into the section) and each edge's two faces.
 * Pass 2 lays the records and the directory out from the same running
 * offset, so no leaf's offset is kept. */
typedef struct label_plan {
    uint64_t leaves, label_bits;
    uint64_t at;                           /* the running record offset */
    uint64_t block_at[DIR_SHIFTS], most[DIR_SHIFTS];
    uint64_t *samples[HPFC_MAX_LEVELS];
    uint32_t rank_bits[HPFC_MAX_LEVELS];
    uint32_t face_bits, edge_bits, sample_shift;
    uint64_t faces, edges;
    /* per edge its two faces, face_bits each, as the section stores them
     * (0 for an edge with no crossing), and whether it was met */
    uint8_t *sides, *seen;
    bool own_sides; /* sides allocated (whole), or in the section (streamed) */
    /* streamed, when an edge's two sides have fewer bits than a level
     * (a map of at most four faces): per edge the level of its first piece
     * in leaf order; else that level waits in the sides' own bits
     * (first_level_get) */
    uint8_t *first_level;
    /* pass 2: the directory being written */
    uint8_t *dir;
    uint32_t shift, block_bits, offset_bits;
    uint64_t block_record_bits, dir_block_at; /* the current block's first offset */
    labels_levels lv;
} label_plan;

static void plan_free(label_plan *p)
{
    if (p->own_sides)
        free(p->sides);
    free(p->seen);
    free(p->first_level);
    for (uint32_t l = 0; l < HPFC_MAX_LEVELS; l++)
        free(p->samples[l]);
}

/* Pass 1: leaf g's record starts at `at`; at every block size, how far
 * into its block. */
static void measure_blocks(label_plan *p, uint64_t g, uint64_t at)
{
    for (uint32_t b = 0; b < DIR_SHIFTS; b++) {
        uint64_t B = UINT64_C(1) << b;
        if ((g & (B - 1)) == 0)
            p->block_at[b] = at;
        else if (at - p->block_at[b] > p->most[b])
            p->most[b] = at - p->block_at[b];
    }
}

/* Pass 2: leaf g's directory entry, its record starting at `at`: a
 * block's first leaf gets the offset, the others the distance from it. */
static void put_directory_entry(label_plan *p, uint64_t g, uint64_t at)
{
    uint64_t k = g & ((UINT64_C(1) << p->shift) - 1), rec = (g >> p->shift) * p->block_record_bits;
    if (k == 0) {
        format_put(p->dir, rec, p->block_bits, at);
        p->dir_block_at = at;
    } else {
        format_put(p->dir, rec + p->block_bits + (k - 1) * p->offset_bits, p->offset_bits,
                   at - p->dir_block_at);
    }
}

/* The sides' bits, to read. */
static format_bits sides_bits(const label_plan *p)
{
    uint64_t bits = 2 * p->edges * p->face_bits;
    return (format_bits){p->sides, bits, format_pool_bytes(bits)};
}

static uint64_t side_get(const label_plan *p, uint64_t e, int which)
{
    format_bits b = sides_bits(p);
    return format_get(&b, (2 * e + (uint64_t)which) * p->face_bits, p->face_bits);
}

/* The bits of a level (below HPFC_MAX_LEVELS). */
enum { LEVEL_BITS = 6 };
_Static_assert(HPFC_MAX_LEVELS <= 1 << LEVEL_BITS, "a level in LEVEL_BITS");

/* Streamed: the level of edge e's first piece in leaf order, noted by
 * pass 2 in the section's bits for e's two sides until pass 3 sets them
 * (the seen bit tells which the bits hold), or in first_level when they
 * are too few. The section's sides cost no memory of the writer's own:
 * a byte an edge less (16 MB at 2*10^8 street points). */
static bool first_level_in_sides(const label_plan *p)
{
    return 2 * p->face_bits >= LEVEL_BITS;
}

static void first_level_set(label_plan *p, uint64_t e, uint32_t level)
{
    if (first_level_in_sides(p))
        format_put(p->sides, 2 * e * p->face_bits, LEVEL_BITS, level);
    else
        p->first_level[e] = (uint8_t)level;
}

static uint32_t first_level_get(const label_plan *p, uint64_t e)
{
    if (!first_level_in_sides(p))
        return p->first_level[e];
    format_bits b = sides_bits(p);
    return (uint32_t)format_get(&b, 2 * e * p->face_bits, LEVEL_BITS);
}

/* A piece whose z bit waits for its edge's sides (streamed pass 3): a
 * piece met, root by root, before the first piece of its edge in leaf
 * order, which sets the sides. Only edges across roots have such pieces. */
typedef struct later_piece {
    uint64_t at; /* the z bit's offset in the records */
    uint64_t edge, right, left;
} later_piece;

/* Where each root's run of images, and of records, starts on each level
 * (streamed passes): noted in pass 1, followed in pass 3. */
typedef struct root_runs {
    uint64_t roots;
    uint64_t *image_first[HPFC_MAX_LEVELS]; /* roots + 1: the run's first image (l >= 1) */
    uint64_t *record_at[HPFC_MAX_LEVELS];   /* the run's first record's offset */
    uint64_t *image_at[HPFC_MAX_LEVELS];    /* the run's first image's bit in the pool */
} root_runs;

/* One leaf at a time, in one of the passes:
 *   - whole pass 1 (fc, no out, no directory): offsets measured, each edge's
 *     sides where it first comes;
 *   - whole pass 2 (fc, out, directory): directory entries and records;
 *   - streamed pass 1 (no fc, no out, no directory): offsets measured, the
 *     roots' runs;
 *   - streamed pass 2 (no fc, no out, directory): directory entries, the
 *     rank samples and each edge's first level, into the section;
 *   - streamed pass 3 (a root's fc, out, no directory): the records of one
 *     root, the sides as their first pieces come, other z bits later. */
typedef struct leaf_visit {
    label_plan *plan;
    const hpfc_faces *fc;
    uint8_t *out;
    bool directory;
    /* streamed pass 2: the section's rank samples, written as they come
     * (pass 1 keeps none) */
    uint8_t *rank;
    const labels_layout *lay;
    uint64_t next; /* global leaf number (passes in leaf order) */
    root_runs *runs;
    later_piece *later;
    size_t nlater, later_cap;
} leaf_visit;

static bool measuring(const leaf_visit *v)
{
    return !v->out && !v->directory;
}

static bool edge_seen(const label_plan *p, uint64_t e)
{
    return p->seen[e >> 3] & (1u << (e & 7));
}

static void set_seen(label_plan *p, uint64_t e)
{
    p->seen[e >> 3] |= (uint8_t)(1u << (e & 7));
}

/* Set, not or'ed: streamed, the bits held the edge's first level. */
static void set_sides(label_plan *p, uint64_t e, uint64_t right, uint64_t left)
{
    set_seen(p, e);
    format_set(p->sides, 2 * e * p->face_bits, p->face_bits, right);
    format_set(p->sides, (2 * e + 1) * p->face_bits, p->face_bits, left);
}

/* Piece of edge e at `at` (its z bit at at + edge_bits), the face on the
 * right of its first crossing's out-dart `right`, on its left `left`:
 * its z bit, from the edge's sides. */
static int put_side_bit(label_plan *p, uint8_t *out, uint64_t at, uint64_t e, uint64_t right,
                        uint64_t left, hpfc_diag *diag)
{
    uint64_t side[2] = {side_get(p, e, 0), side_get(p, e, 1)};
    uint32_t bit = side[0] != side[1] && right != side[0];
    if (right != side[bit] || left != side[!bit])
        return diag_set(diag, HPFC_E_ARG, "labels: edge %llu has more than two faces",
                        (unsigned long long)e);
    format_put(out, at, 1, bit);
    return HPFC_OK;
}

static int defer_piece(leaf_visit *v, uint64_t at, uint64_t e, uint64_t right, uint64_t left,
                       hpfc_diag *diag)
{
    if (array_reserve((void **)&v->later, &v->later_cap, v->nlater + 1, sizeof *v->later, 1024))
        return diag_set(diag, HPFC_E_NOMEM, "labels: out of memory");
    v->later[v->nlater++] = (later_piece){at, e, right, left};
    return HPFC_OK;
}

/* The pieces of a leaf whose record starts at `at` (pass 1: what the edges
 * need; the other passes with faces: the records' pieces). */
static int visit_pieces(leaf_visit *v, uint32_t level, const labels_word *w, const hpfc_tree_pixel *px,
                        uint64_t base, uint64_t at, hpfc_diag *diag)
{
    label_plan *p = v->plan;
    /* Each piece from its first crossing c: the face on the right of out_c
     * (stretch c + 1) and of in_c (stretch c), the two sides of its edge. */
    for (uint32_t c = 0, q = 0; c < w->n; c++) {
        if (w->piece[c] != q)
            continue; /* a stabbing's second crossing */
        q++;
        uint64_t e = px->cross_edge[c];
        if (e >= p->edges)
            return diag_set(diag, HPFC_E_ARG, "labels: a crossing of edge %llu, of %llu edges",
                            (unsigned long long)e, (unsigned long long)p->edges);
        if (!v->fc) { /* streamed pass 2 */
            if (!edge_seen(p, e)) {
                set_seen(p, e);
                first_level_set(p, e, level);
            }
            continue;
        }
        uint64_t right = faces_node_face(v->fc, base + (c + 1) % w->n);
        uint64_t left = faces_node_face(v->fc, base + c);
        if (!v->out) { /* whole pass 1: the sides where the edge first comes */
            if (!edge_seen(p, e))
                set_sides(p, e, right, left);
            continue;
        }
        format_put(v->out, at, p->edge_bits, e);
        int st = HPFC_OK;
        if (v->runs && !edge_seen(p, e)) {
            /* streamed: the first piece in leaf order comes in the first root
             * (root order) with a piece on the edge's first level */
            if (level == first_level_get(p, e))
                set_sides(p, e, right, left);
            else
                st = defer_piece(v, at + p->edge_bits, e, right, left, diag);
        }
        if (!st && edge_seen(p, e))
            st = put_side_bit(p, v->out, at + p->edge_bits, e, right, left, diag);
        if (st)
            return st;
        at += p->edge_bits + 1;
    }
    return HPFC_OK;
}

/* One leaf: its record's offset measured, its directory entry or its
 * record written, as the pass does. */
static int visit_leaf(leaf_visit *v, uint32_t level, uint64_t slot, const hpfc_tree_pixel *px,
                      hpfc_diag *diag)
{
    label_plan *p = v->plan;
    labels_word w;
    int st = labels_word_parse(&w, px->word, px->word_len);
    uint64_t base = 0, n = 0, g = v->next++;
    if (st)
        st = diag_set(diag, st, "labels: a word of the tree does not parse");
    else if (g >= p->leaves)
        st = diag_set(diag, HPFC_E_ARG, "labels: more leaves in the tree than in the file");
    else if (v->fc && (faces_leaf_nodes(v->fc, level, slot, &base, &n) || n != w.n))
        st = diag_set(diag, HPFC_E_ARG, "labels: the faces do not belong to this tree's file");
    if (st) {
        labels_word_free(&w);
        return st;
    }
    uint64_t at = p->at;
    p->at = at + labels_record_bits(&w, p->face_bits, p->edge_bits);
    if (v->directory)
        put_directory_entry(p, g, at);
    else if (!v->out)
        measure_blocks(p, g, at);
    if (v->out && w.n == 0)
        format_put(v->out, at, p->face_bits, faces_node_face(v->fc, base));
    if (v->fc || (v->directory && v->runs)) /* a streamed pass 1 needs none */
        st = visit_pieces(v, level, &w, px, base, at, diag);
    labels_word_free(&w);
    return st;
}

/* A level's grid and slots, as the writer lays the pools out. */
typedef struct level_walk {
    uint32_t level, cols, rows;
    bool compact;
    uint64_t record, word_bits, address_bits;
} level_walk;

static void level_walk_init(level_walk *lw, const hpfc_file *file, uint32_t l)
{
    hpfc_file_info fi;
    hpfc_level_info li;
    hpfc_file_get_info(file, &fi);
    hpfc_file_get_level(file, l, &li);
    lw->level = l;
    lw->cols = l ? fi.cols : fi.root_cols, lw->rows = l ? fi.rows : fi.root_rows;
    lw->compact = file->compact;
    lw->record = 1 + (uint64_t)(li.address_bits > li.word_bits ? li.address_bits : li.word_bits);
    lw->word_bits = li.word_bits, lw->address_bits = li.address_bits;
}

/* Root record r (level 0): visited if a leaf; *refined 1 if not. */
static int visit_root_pixel(leaf_visit *v, const hpfc_tree *tree, const level_walk *lw, uint64_t r,
                            uint64_t *words, uint64_t *refined, hpfc_diag *diag)
{
    uint32_t i = (uint32_t)(r % lw->cols), j = (uint32_t)(r / lw->cols);
    hpfc_tree_pixel px;
    int st = hpfc_tree_get_pixel(tree, 0, 0, i, j, &px);
    if (st)
        return diag_set(diag, st, "labels: no pixel (%u, %u)", i, j);
    *refined = px.type == HPFC_PIXEL_REFINED;
    if (*refined)
        return HPFC_OK;
    /* the compact layout names a leaf by its type-bit position (two bits a
     * pixel, spec §5.3.2), as the faces' leaf table does */
    (*words)++;
    return visit_leaf(v, 0, lw->compact ? 2 * r : r * lw->record, &px, diag);
}

/* Image im of level lw->level >= 1, at bit *image_at of its pool: its
 * leaves visited, *image_at past it, its word and refined pixels added. */
static int visit_image(leaf_visit *v, const hpfc_tree *tree, const level_walk *lw, uint64_t im,
                       uint64_t *image_at, uint64_t *words, uint64_t *refined, hpfc_diag *diag)
{
    uint64_t pixels = (uint64_t)lw->cols * lw->rows, slot = *image_at + pixels;
    for (uint32_t j = 0; j < lw->rows; j++)
        for (uint32_t i = 0; i < lw->cols; i++) {
            hpfc_tree_pixel px;
            int st = hpfc_tree_get_pixel(tree, lw->level, im, i, j, &px);
            if (st)
                return diag_set(diag, st, "labels: no pixel (%u, %u)", i, j);
            if (px.type == HPFC_PIXEL_REFINED) {
                slot += lw->address_bits;
                (*refined)++;
                continue;
            }
            uint64_t key = lw->compact ? 2 * (im * pixels + (uint64_t)j * lw->cols + i) : slot;
            if ((st = visit_leaf(v, lw->level, key, &px, diag)))
                return st;
            slot += lw->word_bits;
            (*words)++;
        }
    *image_at = slot;
    return HPFC_OK;
}

/* Streamed pass 1, before level l's image im (l >= 1): the root whose run
 * it starts, if any, notes where its run begins; *root follows. */
static void note_run_start(leaf_visit *v, uint32_t l, uint64_t im, uint64_t image_at, uint64_t *root)
{
    root_runs *rr = v->runs;
    while (*root < rr->roots && rr->image_first[l][*root + 1] <= im)
        (*root)++;
    if (*root < rr->roots && rr->image_first[l][*root] == im) {
        rr->record_at[l][*root] = v->plan->at;
        rr->image_at[l][*root] = image_at;
    }
}

/* Level l's rank sample k, `words` word pixels before its unit: kept by
 * a whole pass 1, written into the section by a streamed pass 2. */
static void put_sample(const leaf_visit *v, uint32_t l, uint64_t k, uint64_t words)
{
    label_plan *p = v->plan;
    if (measuring(v) && p->samples[l])
        p->samples[l][k] = words;
    else if (v->rank)
        format_put(v->rank, v->lay->rank_start[l] + k * p->rank_bits[l], p->rank_bits[l], words);
}

/* Every leaf of the tree in leaf order, with its slot's pool offset (as the
 * writer lays the pools out) and, in pass 1, the rank samples (and, in a
 * streamed pass 1, the roots' runs). */
static int visit_all(leaf_visit *v, const hpfc_tree *tree, const hpfc_file *file, hpfc_diag *diag)
{
    hpfc_file_info fi;
    hpfc_file_get_info(file, &fi);
    uint64_t step = UINT64_C(1) << v->plan->sample_shift;
    uint32_t shift = v->plan->sample_shift;
    root_runs *rr = measuring(v) ? v->runs : NULL;
    for (uint32_t l = 0; l < fi.levels; l++) {
        hpfc_level_info li;
        hpfc_file_get_level(file, l, &li);
        level_walk lw;
        level_walk_init(&lw, file, l);
        uint64_t units = l ? hpfc_tree_image_count(tree, l) : (uint64_t)lw.cols * lw.rows;
        uint64_t words = 0, image_at = 0, root = 0;
        if (l && units != li.images)
            return diag_set(diag, HPFC_E_ARG, "labels: the tree and the file differ");
        for (uint64_t u = 0; u < units; u++) {
            if ((u & (step - 1)) == 0)
                put_sample(v, l, u >> shift, words);
            uint64_t refined = 0;
            int st;
            if (l == 0) {
                if (rr)
                    rr->record_at[0][u] = v->plan->at;
                st = visit_root_pixel(v, tree, &lw, u, &words, &refined, diag);
                root = u;
            } else {
                if (rr)
                    note_run_start(v, l, u, image_at, &root);
                st = visit_image(v, tree, &lw, u, &image_at, &words, &refined, diag);
            }
            if (st)
                return st;
            if (rr && l + 1 < fi.levels) /* the next level's images of this root */
                rr->image_first[l + 1][root + 1] += refined;
        }
        if (rr && l + 1 < fi.levels)
            for (uint64_t r = 0; r < rr->roots; r++) /* counts to starts */
                rr->image_first[l + 1][r + 1] += rr->image_first[l + 1][r];
        if (words != li.word_pixels)
            return diag_set(diag, HPFC_E_ARG, "labels: the tree and the file differ");
    }
    return HPFC_OK;
}

static uint32_t bits_for(uint64_t max_value)
{
    return max_value ? (uint32_t)(64 - __builtin_clzll(max_value)) : 0;
}

/* The block size whose directory is smallest: *shift, and its widths. */
static void choose_blocks(const label_plan *p, uint32_t *shift, uint32_t *block_bits,
                          uint32_t *offset_bits)
{
    uint64_t best = UINT64_MAX;
    *block_bits = bits_for(p->label_bits);
    for (uint32_t b = 0; b < DIR_SHIFTS; b++) {
        uint64_t B = UINT64_C(1) << b;
        uint32_t wr = bits_for(p->most[b]);
        uint64_t blocks = (p->leaves + B - 1) / B;
        uint64_t size = blocks * (*block_bits + (B - 1) * wr);
        if (size < best) {
            best = size;
            *shift = b;
            *offset_bits = wr;
        }
    }
}

/* The plan's counts; its sample rows and room for each edge's sides
 * unless streamed (`streamed`: the samples are then written into the
 * section's own bytes in pass 2, the sides in pass 3). */
static int plan_init(label_plan *p, const hpfc_tree *tree, const hpfc_file *file, uint64_t faces,
                     bool streamed, hpfc_diag *diag)
{
    hpfc_file_info fi;
    hpfc_tree_info ti;
    hpfc_file_get_info(file, &fi);
    hpfc_tree_get_info(tree, &ti);
    p->faces = faces;
    p->edges = ti.edges;
    if (!p->faces || !p->edges)
        return diag_set(diag, HPFC_E_ARG, "labels: a map with no face or no edge");
    p->face_bits = bits_for(p->faces - 1);
    p->edge_bits = bits_for(p->edges - 1);
    p->sample_shift = 3;
    p->lv.levels = fi.levels;
    for (uint32_t l = 0; l < fi.levels; l++) {
        hpfc_level_info li;
        hpfc_file_get_level(file, l, &li);
        p->lv.word_pixels[l] = li.word_pixels;
        p->lv.units[l] = l ? li.images : (uint64_t)fi.root_cols * fi.root_rows;
        p->leaves += li.word_pixels;
        p->rank_bits[l] = bits_for(li.word_pixels);
        uint64_t samples = (p->lv.units[l] + 7) >> 3;
        if (!streamed && !(p->samples[l] = calloc(samples ? samples : 1, sizeof *p->samples[l])))
            return diag_set(diag, HPFC_E_NOMEM, "labels: out of memory");
    }
    if (p->edges > SIZE_MAX / 128)
        return diag_set(diag, HPFC_E_NOMEM, "labels: out of memory");
    uint64_t side_bytes = format_pool_bytes(2 * p->edges * p->face_bits);
    if (!streamed) {
        p->sides = calloc(1, side_bytes ? (size_t)side_bytes : 1);
        p->own_sides = true;
    }
    p->seen = calloc(1, (size_t)format_pool_bytes(p->edges));
    if ((!streamed && !p->sides) || !p->seen)
        return diag_set(diag, HPFC_E_NOMEM, "labels: out of memory");
    return HPFC_OK;
}

/* After pass 1: the directory's block size and widths and the section's
 * layout. */
static int plan_layout(label_plan *p, labels_layout *lay, hpfc_diag *diag)
{
    p->label_bits = p->at;
    choose_blocks(p, &p->shift, &p->block_bits, &p->offset_bits);
    if (!labels_compute_layout(&p->lv, p->rank_bits, p->leaves, p->shift, p->block_bits,
                               p->offset_bits, p->sample_shift, p->edges, p->face_bits,
                               p->label_bits, lay) ||
        lay->length > SIZE_MAX)
        return diag_set(diag, HPFC_E_LIMIT, "labels: the section would be too large");
    return HPFC_OK;
}

/* The directory and record streams in `sec` (the section's zeroed bytes),
 * ready for the next pass. */
static void start_emit(label_plan *p, const labels_layout *lay, uint8_t *sec)
{
    p->dir = sec + lay->dir_at;
    p->block_record_bits = lay->block_record_bits;
    p->at = 0;
}

/* The header, the level entries, the samples and the sides. */
static void finish_section(const label_plan *p, const labels_layout *lay, uint8_t *sec)
{
    labl_set_face_count(sec, p->faces);
    labl_set_edge_count(sec, p->edges);
    labl_set_leaf_count(sec, p->leaves);
    labl_set_label_bits(sec, p->label_bits);
    labl_set_face_bits(sec, (uint8_t)p->face_bits);
    labl_set_edge_bits(sec, (uint8_t)p->edge_bits);
    labl_set_block_shift(sec, (uint8_t)p->shift);
    labl_set_block_bits(sec, (uint8_t)p->block_bits);
    labl_set_offset_bits(sec, (uint8_t)p->offset_bits);
    labl_set_sample_shift(sec, (uint8_t)p->sample_shift);
    labl_set_levels(sec, p->lv.levels);
    for (uint32_t l = 0; l < p->lv.levels; l++) {
        labll_set_rank_bits(sec + LABL_HEADER_SIZE + (size_t)l * LABL_LEVEL_SIZE, (uint8_t)p->rank_bits[l]);
        for (uint64_t k = 0; p->samples[l] && k < lay->samples[l]; k++) /* else set when streamed */
            format_put(sec + lay->rank_at, lay->rank_start[l] + k * p->rank_bits[l], p->rank_bits[l],
                       p->samples[l][k]);
    }
    /* already in the section's bit layout (set there when streamed); an
     * edge with no crossing: faces 0 */
    if (p->sides != sec + lay->sides_at)
        memcpy(sec + lay->sides_at, p->sides, (size_t)format_pool_bytes(2 * p->edges * p->face_bits));
}

/* ---- a root pixel at a time ------------------------------------------------ */

static void root_runs_free(root_runs *rr)
{
    for (uint32_t l = 0; l < HPFC_MAX_LEVELS; l++) {
        free(rr->image_first[l]);
        free(rr->record_at[l]);
        free(rr->image_at[l]);
    }
}

static int root_runs_init(root_runs *rr, const hpfc_file *file, hpfc_diag *diag)
{
    hpfc_file_info fi;
    hpfc_file_get_info(file, &fi);
    *rr = (root_runs){.roots = (uint64_t)fi.root_cols * fi.root_rows};
    if (rr->roots > SIZE_MAX / 16)
        return diag_set(diag, HPFC_E_NOMEM, "labels: out of memory");
    size_t n = (size_t)rr->roots + 1;
    for (uint32_t l = 0; l < fi.levels; l++)
        if (!(rr->image_first[l] = calloc(n, 8)) || !(rr->record_at[l] = calloc(n, 8)) ||
            !(rr->image_at[l] = calloc(n, 8)))
            return diag_set(diag, HPFC_E_NOMEM, "labels: out of memory");
    return HPFC_OK;
}

/* Streamed pass 3, root r: its faces numbered again, its runs' records
 * level by level, each from the offset pass 1 noted. */
static int visit_root(leaf_visit *v, const hpfc_tree *tree, const hpfc_file *file, faces_stream *fs,
                      uint64_t r, hpfc_diag *diag)
{
    hpfc_file_info fi;
    hpfc_file_get_info(file, &fi);
    const root_runs *rr = v->runs;
    hpfc_faces *fc = NULL;
    int st = faces_stream_root(fs, (uint32_t)(r % fi.root_cols), (uint32_t)(r / fi.root_cols), &fc);
    if (st)
        return diag_set(diag, st, "labels: numbering the faces of root pixel %llu failed",
                        (unsigned long long)r);
    v->fc = fc;
    v->next = 0;
    for (uint32_t l = 0; l < fi.levels && !st; l++) {
        level_walk lw;
        level_walk_init(&lw, file, l);
        uint64_t words = 0, refined = 0, image_at = rr->image_at[l][r];
        v->plan->at = rr->record_at[l][r];
        if (l == 0) {
            st = visit_root_pixel(v, tree, &lw, r, &words, &refined, diag);
            continue;
        }
        for (uint64_t im = rr->image_first[l][r]; im < rr->image_first[l][r + 1] && !st; im++)
            st = visit_image(v, tree, &lw, im, &image_at, &words, &refined, diag);
    }
    v->fc = NULL;
    hpfc_faces_free(fc);
    return st;
}

/* After pass 3: the z bits that waited for their edges' sides. */
static int put_later_bits(leaf_visit *v, hpfc_diag *diag)
{
    label_plan *p = v->plan;
    for (size_t k = 0; k < v->nlater; k++) {
        const later_piece *q = &v->later[k];
        if (!edge_seen(p, q->edge))
            return diag_set(diag, HPFC_E_ARG, "labels: edge %llu has no first piece",
                            (unsigned long long)q->edge);
        int st = put_side_bit(p, v->out, q->at, q->edge, q->right, q->left, diag);
        if (st)
            return st;
    }
    return HPFC_OK;
}

/* ---- the writer: pass 1, then the section in the caller's bytes -------------- */

struct labels_writer {
    const hpfc_tree *tree;
    const hpfc_file *file;
    const hpfc_faces *fc; /* the faces numbered whole, or */
    faces_stream *fs;     /* a root pixel at a time */
    label_plan p;
    root_runs rr;
    labels_layout lay;
};

void labels_writer_free(labels_writer *w)
{
    if (!w)
        return;
    root_runs_free(&w->rr);
    plan_free(&w->p);
    free(w);
}

/* Pass 1 whole: sizes, samples and each edge's sides. */
static int begin_whole(labels_writer *w, hpfc_diag *diag)
{
    int st = plan_init(&w->p, w->tree, w->file, hpfc_faces_face_count(w->fc), false, diag);
    leaf_visit v = {.plan = &w->p, .fc = w->fc};
    return st ? st : visit_all(&v, w->tree, w->file, diag);
}

/* Pass 1 streamed: sizes and the roots' runs. */
static int begin_stream(labels_writer *w, hpfc_diag *diag)
{
    label_plan *p = &w->p;
    int st = plan_init(p, w->tree, w->file, faces_stream_face_count(w->fs), true, diag);
    if (!st)
        st = root_runs_init(&w->rr, w->file, diag);
    bool own_levels = !first_level_in_sides(p);
    if (!st && own_levels && !(p->first_level = malloc(p->edges ? (size_t)p->edges : 1)))
        st = diag_set(diag, HPFC_E_NOMEM, "labels: out of memory");
    leaf_visit v = {.plan = p, .runs = &w->rr};
    return st ? st : visit_all(&v, w->tree, w->file, diag);
}

int labels_writer_begin(const hpfc_tree *tree, const hpfc_file *file, const hpfc_faces *fc,
                        faces_stream *fs, labels_writer **out, uint64_t *length, hpfc_diag *diag)
{
    *out = NULL;
    *length = 0;
    labels_writer *w = calloc(1, sizeof *w);
    if (!w)
        return diag_set(diag, HPFC_E_NOMEM, "labels: out of memory");
    *w = (labels_writer){.tree = tree, .file = file, .fc = fc, .fs = fc ? NULL : fs};
    int st = fc ? begin_whole(w, diag) : begin_stream(w, diag);
    if (!st)
        st = plan_layout(&w->p, &w->lay, diag);
    if (st) {
        labels_writer_free(w);
        return st;
    }
    *out = w;
    *length = w->lay.length;
    return HPFC_OK;
}

/* Pass 2 whole: the directory and the records. */
static int emit_whole(labels_writer *w, uint8_t *sec, hpfc_diag *diag)
{
    leaf_visit v = {.plan = &w->p, .fc = w->fc, .out = sec + w->lay.labels_at, .directory = true};
    return visit_all(&v, w->tree, w->file, diag);
}

/* Streamed passes 2 and 3: the directory and the edges' first levels in
 * leaf order, then the records root by root, the sides in the section as
 * their first pieces come. */
static int emit_stream(labels_writer *w, uint8_t *sec, hpfc_diag *diag)
{
    label_plan *p = &w->p;
    p->sides = sec + w->lay.sides_at;
    leaf_visit v = {.plan = p, .runs = &w->rr, .directory = true, .rank = sec + w->lay.rank_at,
                    .lay = &w->lay};
    int st = visit_all(&v, w->tree, w->file, diag);
    if (st)
        return st;
    memset(p->seen, 0, (size_t)format_pool_bytes(p->edges));
    v = (leaf_visit){.plan = p, .runs = &w->rr, .out = sec + w->lay.labels_at};
    for (uint64_t r = 0; r < w->rr.roots && !st; r++)
        st = visit_root(&v, w->tree, w->file, w->fs, r, diag);
    if (!st)
        st = put_later_bits(&v, diag);
    free(v.later);
    return st;
}

int labels_writer_emit(labels_writer *w, uint8_t *sec, hpfc_diag *diag)
{
    start_emit(&w->p, &w->lay, sec);
    int st = w->fc ? emit_whole(w, sec, diag) : emit_stream(w, sec, diag);
    if (!st)
        finish_section(&w->p, &w->lay, sec);
    return st;
}

/* Streamed, the section in bytes of its own (labels_writer_begin, then
 * emit into them). */
int labels_build_stream(const hpfc_tree *tree, const hpfc_file *file, faces_stream *fs,
                        uint8_t **out, uint64_t *length, hpfc_diag *diag)
{
    labels_writer *w = NULL;
    uint64_t n = 0;
    uint8_t *sec = NULL;
    *out = NULL;
    *length = 0;
    int st = labels_writer_begin(tree, file, NULL, fs, &w, &n, diag);
    if (!st && !(sec = calloc(1, (size_t)n)))
        st = diag_set(diag, HPFC_E_NOMEM, "labels: out of memory");
    if (!st)
        st = labels_writer_emit(w, sec, diag);
    labels_writer_free(w);
    if (st) {
        free(sec);
        return st;
    }
    *out = sec;
    *length = n;
    return HPFC_OK;
}
