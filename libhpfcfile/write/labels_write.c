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
 */
#include <stdlib.h>
#include <string.h>

#include "diag.h"
#include "faces.h"
#include "file.h"
#include "labels.h"

/* Block sizes 2^0 .. 2^(DIR_SHIFTS - 1) leaves for the directory. */
enum { DIR_SHIFTS = 11 };

/* What pass 1 learns: the records' bits, the largest offset inside a block
 * at each block size, each level's samples and each edge's two faces.
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
    /* pass 2: the directory being written */
    uint8_t *dir;
    uint32_t shift, block_bits, offset_bits;
    uint64_t block_record_bits, dir_block_at; /* the current block's first offset */
    labels_levels lv;
} label_plan;

static void plan_free(label_plan *p)
{
    free(p->sides);
    free(p->seen);
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

static uint64_t side_get(const label_plan *p, uint64_t e, int which)
{
    format_bits b = {p->sides, 2 * p->edges * p->face_bits, format_pool_bytes(2 * p->edges * p->face_bits)};
    return format_get(&b, (2 * e + (uint64_t)which) * p->face_bits, p->face_bits);
}

/* One leaf, visited in leaf order: pass 1 (out NULL) records its offset,
 * pass 2 writes its labels at out (the label stream). */
typedef struct leaf_visit {
    label_plan *plan;
    const hpfc_faces *fc;
    uint8_t *out;
    uint64_t next; /* global leaf number */
} leaf_visit;

static int visit_leaf(leaf_visit *lv, uint32_t level, uint64_t slot, const hpfc_tree_pixel *px,
                      hpfc_diag *diag)
{
    label_plan *p = lv->plan;
    labels_word w;
    int st = labels_word_parse(&w, px->word, px->word_len);
    uint64_t base = 0, n = 0, g = lv->next++;
    if (st)
        st = diag_set(diag, st, "labels: a word of the tree does not parse");
    else if (g >= p->leaves)
        st = diag_set(diag, HPFC_E_ARG, "labels: more leaves in the tree than in the file");
    else if (faces_leaf_nodes(lv->fc, level, slot, &base, &n) || n != w.n)
        st = diag_set(diag, HPFC_E_ARG, "labels: the faces do not belong to this tree's file");
    if (st) {
        labels_word_free(&w);
        return st;
    }
    uint64_t at = p->at;
    p->at = at + labels_record_bits(&w, p->face_bits, p->edge_bits);
    if (!lv->out) {
        measure_blocks(p, g, at);
    } else {
        put_directory_entry(p, g, at);
        if (w.n == 0)
            format_put(lv->out, at, p->face_bits, faces_node_face(lv->fc, base));
    }
    /* Each piece from its first crossing c: the face on the right of out_c
     * (stretch c + 1) and of in_c (stretch c), the two sides of its edge.
     * Pass 1 records an edge's sides where it first comes; pass 2 writes
     * which of them is on the right of out_c. */
    for (uint32_t c = 0, q = 0; c < w.n; c++) {
        if (w.piece[c] != q)
            continue; /* a stabbing's second crossing */
        uint64_t e = px->cross_edge[c];
        uint64_t right = faces_node_face(lv->fc, base + (c + 1) % w.n);
        uint64_t left = faces_node_face(lv->fc, base + c);
        if (e >= p->edges) {
            st = diag_set(diag, HPFC_E_ARG, "labels: a crossing of edge %llu, of %llu edges",
                          (unsigned long long)e, (unsigned long long)p->edges);
            break;
        }
        if (!lv->out) {
            if (!(p->seen[e >> 3] & (1u << (e & 7)))) {
                p->seen[e >> 3] |= (uint8_t)(1u << (e & 7));
                format_put(p->sides, 2 * e * p->face_bits, p->face_bits, right);
                format_put(p->sides, (2 * e + 1) * p->face_bits, p->face_bits, left);
            }
        } else {
            uint64_t side[2] = {side_get(p, e, 0), side_get(p, e, 1)};
            uint32_t bit = side[0] != side[1] && right != side[0];
            if (right != side[bit] || left != side[!bit]) {
                st = diag_set(diag, HPFC_E_ARG, "labels: edge %llu has more than two faces",
                              (unsigned long long)e);
                break;
            }
            format_put(lv->out, at, p->edge_bits, e);
            format_put(lv->out, at + p->edge_bits, 1, bit);
            at += p->edge_bits + 1;
        }
        q++;
    }
    labels_word_free(&w);
    return st;
}

/* Every leaf of the tree in leaf order, with its slot's pool offset (as the
 * writer lays the pools out) and, in pass 1, the rank samples. */
static int visit_all(leaf_visit *v, const hpfc_tree *tree, const hpfc_file *file, hpfc_diag *diag)
{
    hpfc_file_info fi;
    hpfc_file_get_info(file, &fi);
    bool compact = file->compact;
    uint64_t step = UINT64_C(1) << v->plan->sample_shift;
    for (uint32_t l = 0; l < fi.levels; l++) {
        hpfc_level_info li;
        hpfc_file_get_level(file, l, &li);
        uint32_t cols = l ? fi.cols : fi.root_cols, rows = l ? fi.rows : fi.root_rows;
        uint64_t record = 1 + (uint64_t)(li.address_bits > li.word_bits ? li.address_bits : li.word_bits);
        uint64_t images = hpfc_tree_image_count(tree, l), words = 0, image_at = 0;
        uint32_t shift = v->plan->sample_shift;
        if (images != li.images)
            return diag_set(diag, HPFC_E_ARG, "labels: the tree and the file differ");
        for (uint64_t im = 0; im < images; im++) {
            uint64_t slot = image_at + (l ? (uint64_t)cols * rows : 0);
            if (l && !v->out && (im & (step - 1)) == 0)
                v->plan->samples[l][im >> shift] = words;
            for (uint32_t j = 0; j < rows; j++)
                for (uint32_t i = 0; i < cols; i++) {
                    if (l == 0) {
                        uint64_t r = (uint64_t)j * cols + i;
                        if (!v->out && (r & (step - 1)) == 0)
                            v->plan->samples[0][r >> shift] = words;
                        slot = r * record;
                    }
                    hpfc_tree_pixel px;
                    int st = hpfc_tree_get_pixel(tree, l, im, i, j, &px);
                    if (st)
                        return diag_set(diag, st, "labels: no pixel (%u, %u)", i, j);
                    if (px.type == HPFC_PIXEL_REFINED) {
                        slot += l ? li.address_bits : 0;
                        continue;
                    }
                    /* the compact layout names a leaf by its type-bit position
                     * (two bits a pixel, spec §5.3.2), as the faces' leaf table does */
                    uint64_t key = compact ? 2 * ((l ? im * cols * rows : 0) + (uint64_t)j * cols + i)
                                           : slot;
                    if ((st = visit_leaf(v, l, key, &px, diag)))
                        return st;
                    slot += l ? li.word_bits : 0;
                    words++;
                }
            if (l)
                image_at = slot;
        }
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

static int plan_init(label_plan *p, const hpfc_tree *tree, const hpfc_file *file,
                     const hpfc_faces *fc, hpfc_diag *diag)
{
    hpfc_file_info fi;
    hpfc_tree_info ti;
    hpfc_file_get_info(file, &fi);
    hpfc_tree_get_info(tree, &ti);
    p->faces = hpfc_faces_face_count(fc);
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
        if (!(p->samples[l] = calloc(samples ? samples : 1, sizeof *p->samples[l])))
            return diag_set(diag, HPFC_E_NOMEM, "labels: out of memory");
    }
    uint64_t side_bytes = format_pool_bytes(2 * p->edges * p->face_bits);
    if (p->edges > SIZE_MAX / 128 || !(p->sides = calloc(1, side_bytes ? (size_t)side_bytes : 1)) ||
        !(p->seen = calloc(1, (size_t)format_pool_bytes(p->edges))))
        return diag_set(diag, HPFC_E_NOMEM, "labels: out of memory");
    return HPFC_OK;
}

int labels_build(const hpfc_tree *tree, const hpfc_file *file, const hpfc_faces *fc, uint8_t **out,
                 uint64_t *length, hpfc_diag *diag)
{
    label_plan p = {0};
    *out = NULL;
    *length = 0;
    int st = plan_init(&p, tree, file, fc, diag);
    leaf_visit v = {.plan = &p, .fc = fc};
    if (!st)
        st = visit_all(&v, tree, file, diag);
    labels_layout lay;
    uint32_t shift = 0, block_bits = 0, offset_bits = 0;
    uint8_t *sec = NULL;
    if (!st) {
        p.label_bits = p.at;
        choose_blocks(&p, &shift, &block_bits, &offset_bits);
        if (!labels_compute_layout(&p.lv, p.rank_bits, p.leaves, shift, block_bits, offset_bits,
                                   p.sample_shift, p.edges, p.face_bits, p.label_bits, &lay) ||
            lay.length > SIZE_MAX)
            st = diag_set(diag, HPFC_E_LIMIT, "labels: the section would be too large");
    }
    if (!st && !(sec = calloc(1, (size_t)lay.length)))
        st = diag_set(diag, HPFC_E_NOMEM, "labels: out of memory");
    if (!st) {
        v.out = sec + lay.labels_at;
        v.next = 0;
        p.at = 0;
        p.dir = sec + lay.dir_at;
        p.shift = shift, p.block_bits = block_bits, p.offset_bits = offset_bits;
        p.block_record_bits = lay.block_record_bits;
        st = visit_all(&v, tree, file, diag);
    }
    if (!st) {
        labl_set_face_count(sec, p.faces);
        labl_set_edge_count(sec, p.edges);
        labl_set_leaf_count(sec, p.leaves);
        labl_set_label_bits(sec, p.label_bits);
        labl_set_face_bits(sec, (uint8_t)p.face_bits);
        labl_set_edge_bits(sec, (uint8_t)p.edge_bits);
        labl_set_block_shift(sec, (uint8_t)shift);
        labl_set_block_bits(sec, (uint8_t)block_bits);
        labl_set_offset_bits(sec, (uint8_t)offset_bits);
        labl_set_sample_shift(sec, (uint8_t)p.sample_shift);
        labl_set_levels(sec, p.lv.levels);
        for (uint32_t l = 0; l < p.lv.levels; l++) {
            labll_set_rank_bits(sec + LABL_HEADER_SIZE + (size_t)l * LABL_LEVEL_SIZE,
                                (uint8_t)p.rank_bits[l]);
            for (uint64_t k = 0; k < lay.samples[l]; k++)
                format_put(sec + lay.rank_at, lay.rank_start[l] + k * p.rank_bits[l],
                           p.rank_bits[l], p.samples[l][k]);
        }
        /* already in the section's bit layout; an edge with no crossing: faces 0 */
        memcpy(sec + lay.sides_at, p.sides, (size_t)format_pool_bytes(2 * p.edges * p.face_bits));
        *out = sec;
        *length = lay.length;
        sec = NULL;
    }
    free(sec);
    plan_free(&p);
    return st;
}
