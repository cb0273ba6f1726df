/*
 * The LABL section on the read side (spec/hpfc-format.md §6.5): leaf
 * numbers from a located pixel, the leaf's record through a two-level
 * directory of bit offsets, and the record's face and edge ids.
 *
 * Why this shape: a point query maps the file and answers from the few
 * pixels of one descent. The leaf's number (its rank among its level's
 * leaves, TEAM decision) comes from the descent itself: at each level the
 * image's index and the word pixels before it, read from a sample every
 * 2^sample_shift images and the masks of the images after the sample
 * (images lie back to back, §5.2.2, so an image's offset follows from its index
 * and the word pixels before it). The record's offset comes from a block
 * directory (an absolute offset every 2^block_shift leaves, a relative one
 * per other leaf), so no other leaf's word is decoded.
 */
#include <stdlib.h>
#include <string.h>

#include "arrays.h"
#include "file.h"
#include "labels.h"
#include "reader.h"
#include "sized.h"

#define NONE_REGION UINT32_MAX

/* ---- layout ------------------------------------------------------------------- */

bool labels_compute_layout(const labels_levels *lv, const uint32_t *rank_bits, uint64_t leaves,
                           uint32_t block_shift, uint32_t block_bits, uint32_t offset_bits,
                           uint32_t sample_shift, uint64_t edges, uint32_t face_bits,
                           uint64_t label_bits, labels_layout *out)
{
    memset(out, 0, sizeof *out);
    if (lv->levels < 1 || lv->levels > HPFC_MAX_LEVELS || block_shift > LABL_MAX_SHIFT ||
        sample_shift > LABL_MAX_SHIFT || block_bits > 64 || offset_bits > 64)
        return false;
    uint64_t total = 0, t;
    for (uint32_t l = 0; l < lv->levels; l++) {
        if (rank_bits[l] > 64)
            return false;
        uint64_t samples = (lv->units[l] >> sample_shift) +
                           ((lv->units[l] & ((UINT64_C(1) << sample_shift) - 1)) != 0);
        out->samples[l] = samples;
        out->rank_start[l] = total;
        if (!format_mul(samples, rank_bits[l], &t) || !format_add(total, t, &total))
            return false;
    }
    out->rank_bits_total = total;
    uint64_t per_block = UINT64_C(1) << block_shift;
    out->blocks = (leaves >> block_shift) + ((leaves & (per_block - 1)) != 0);
    if (!format_mul(per_block - 1, offset_bits, &t) ||
        !format_add(t, block_bits, &out->block_record_bits) ||
        !format_mul(out->blocks, out->block_record_bits, &out->dir_bits))
        return false;
    out->rank_at = LABL_HEADER_SIZE + (uint64_t)LABL_LEVEL_SIZE * lv->levels;
    uint64_t end;
    if (!format_add(out->rank_at, format_pool_bytes(out->rank_bits_total), &end) ||
        end > UINT64_MAX - 8)
        return false;
    out->dir_at = format_align8(end);
    if (!format_add(out->dir_at, format_pool_bytes(out->dir_bits), &end) || end > UINT64_MAX - 8)
        return false;
    out->sides_at = format_align8(end);
    if (face_bits > 64 || !format_mul(edges, 2 * (uint64_t)face_bits, &out->sides_bits) ||
        !format_add(out->sides_at, format_pool_bytes(out->sides_bits), &end) ||
        end > UINT64_MAX - 8)
        return false;
    out->labels_at = format_align8(end);
    return format_add(out->labels_at, format_pool_bytes(label_bits), &out->length);
}

bool labels_first_leaves(uint32_t levels, const uint64_t *word_pixels, uint64_t *first_leaf)
{
    uint64_t leaves = 0;
    for (uint32_t l = 0; l < levels; l++) {
        first_leaf[l] = leaves;
        if (!format_add(leaves, word_pixels[l], &leaves))
            return false;
    }
    first_leaf[levels] = leaves;
    return true;
}

static format_bits stream(const uint8_t *sec, uint64_t length, uint64_t at, uint64_t bits)
{
    return (format_bits){.base = sec + at, .bits = bits, .avail = length - at};
}

int labels_open(labels_view *v, const uint8_t *sec, uint64_t length, const labels_levels *lv)
{
    memset(v, 0, sizeof *v);
    if (length < LABL_HEADER_SIZE || labl_get_reserved0(sec) || labl_get_reserved1(sec) ||
        labl_get_levels(sec) != lv->levels)
        return HPFC_E_SECTION;
    if (length - LABL_HEADER_SIZE < (uint64_t)LABL_LEVEL_SIZE * lv->levels)
        return HPFC_E_SECTION;
    uint32_t rank_bits[HPFC_MAX_LEVELS];
    for (uint32_t l = 0; l < lv->levels; l++) {
        const uint8_t *e = sec + LABL_HEADER_SIZE + (size_t)l * LABL_LEVEL_SIZE;
        if (!format_all_zero(e + labll_OFF_reserved, labll_SIZE_reserved))
            return HPFC_E_SECTION;
        rank_bits[l] = labll_get_rank_bits(e);
    }
    if (!labels_first_leaves(lv->levels, lv->word_pixels, v->first_leaf))
        return HPFC_E_SECTION;
    uint64_t leaves = v->first_leaf[lv->levels];
    v->faces = labl_get_face_count(sec);
    v->edges = labl_get_edge_count(sec);
    v->leaves = labl_get_leaf_count(sec);
    v->label_bits = labl_get_label_bits(sec);
    v->face_bits = labl_get_face_bits(sec);
    v->edge_bits = labl_get_edge_bits(sec);
    v->block_shift = labl_get_block_shift(sec);
    v->block_bits = labl_get_block_bits(sec);
    v->offset_bits = labl_get_offset_bits(sec);
    v->sample_shift = labl_get_sample_shift(sec);
    v->levels = lv->levels;
    if (v->leaves != leaves || v->faces == 0 || v->edges == 0 || v->face_bits > 64 ||
        v->edge_bits > 64)
        return HPFC_E_SECTION;
    labels_layout lay;
    if (!labels_compute_layout(lv, rank_bits, leaves, v->block_shift, v->block_bits,
                               v->offset_bits, v->sample_shift, v->edges, v->face_bits,
                               v->label_bits, &lay) ||
        lay.length != length)
        return HPFC_E_SECTION;
    v->rank = stream(sec, length, lay.rank_at, lay.rank_bits_total);
    v->dir = stream(sec, length, lay.dir_at, lay.dir_bits);
    v->sides = stream(sec, length, lay.sides_at, lay.sides_bits);
    v->labels = stream(sec, length, lay.labels_at, v->label_bits);
    for (uint32_t l = 0; l < lv->levels; l++) {
        v->rank_start[l] = lay.rank_start[l];
        v->rank_bits[l] = rank_bits[l];
        v->samples[l] = lay.samples[l];
    }
    v->block_record_bits = lay.block_record_bits;
    v->section = sec;
    v->section_length = length;
    v->present = true;
    return HPFC_OK;
}

/* ---- leaf numbers -------------------------------------------------------------- */

/* Refined pixels (1 bits) among the first p mask bits of the image at bit
 * `image`, which must hold its mask in the pool. */
static int mask_ones(const file_level *g, uint64_t image, uint64_t p, uint64_t *ones)
{
    if (image > g->pool.bits || g->image_pixels > g->pool.bits - image)
        return HPFC_E_CORRUPT;
    *ones = format_popcount(&g->pool, image, p);
    return HPFC_OK;
}

/* The bit after the image at `image` (its mask checked inside the pool);
 * *zeros: its word pixels. */
static int image_end(const file_level *g, uint64_t image, uint64_t *end, uint64_t *zeros)
{
    uint64_t ones, t, size;
    int st = mask_ones(g, image, g->image_pixels, &ones);
    if (st)
        return st;
    *zeros = g->image_pixels - ones;
    if (!format_mul(*zeros, g->word_bits, &size) || !format_mul(ones, g->address_bits, &t) ||
        !format_add(size, t, &size) || !format_add(size, g->image_pixels, &size) ||
        size > g->pool.bits - image)
        return HPFC_E_CORRUPT;
    *end = image + size;
    return HPFC_OK;
}

/* Word records among root records [from, to). */
static uint64_t root_words(const file_level *g, uint64_t from, uint64_t to)
{
    uint64_t words = 0;
    for (uint64_t r = from; r < to; r++) /* s^0 holds every record */
        words += !format_get(&g->pool, r * g->record_bits, 1);
    return words;
}

static uint64_t rank_sample(const labels_view *v, uint32_t l, uint64_t k)
{
    return format_get(&v->rank, v->rank_start[l] + k * v->rank_bits[l], v->rank_bits[l]);
}

/* Checks the pixel is a leaf of the file; its level's geometry. */
static int check_leaf(const hpfc_file *f, const hpfc_pixel *leaf)
{
    int type;
    int st = hpfc_pixel_type(f, leaf, &type);
    if (!st && type != HPFC_PIXEL_WORD)
        st = HPFC_E_ARG;
    return st;
}

/* The bit offset of image u of a level (W7: images back to back in index
 * order), given the word pixels before it. */
static int image_offset(const file_level *g, uint64_t u, uint64_t words, uint64_t *off)
{
    uint64_t pixels, a, b;
    if (!format_mul(u, g->image_pixels, &pixels) || words > pixels || words > g->info.word_pixels ||
        pixels - words > g->info.refined_pixels || !format_mul(words, g->word_bits, &a) ||
        !format_mul(pixels - words, g->address_bits, &b) || !format_add(a, b, &a) ||
        !format_add(a, pixels, off))
        return HPFC_E_CORRUPT;
    return HPFC_OK;
}

static int rank_by_samples(const hpfc_file *f, const labels_view *v, const hpfc_pixel *px,
                           uint64_t *rank)
{
    const hpfc_file_info *fi = &f->info;
    uint64_t index = 0; /* the image's index in its level */
    for (uint32_t l = 0; l <= px->depth; l++) {
        const file_level *g = &f->lv[l]; /* l <= depth < levels: check_leaf */
        int st;
        uint64_t words, ones_before, p;
        if (l == 0) {
            p = (uint64_t)px->path[0].j * fi->root_cols + px->path[0].i;
            uint64_t k = p >> v->sample_shift;
            words = rank_sample(v, 0, k) + root_words(g, k << v->sample_shift, p);
            if (words > p)
                return HPFC_E_CORRUPT;
            ones_before = p - words;
        } else {
            uint64_t k = index >> v->sample_shift, off, u = k << v->sample_shift, zeros;
            if (k >= v->samples[l])
                return HPFC_E_CORRUPT;
            words = rank_sample(v, l, k);
            if ((st = image_offset(g, u, words, &off)))
                return st;
            for (; u < index; u++, words += zeros) /* at most 2^sample_shift - 1 images */
                if ((st = image_end(g, off, &off, &zeros)))
                    return st;
            if (off != px->path[l].image)
                return HPFC_E_CORRUPT; /* the samples or the layout contradict §5.2.2 */
            p = (uint64_t)px->path[l].j * fi->cols + px->path[l].i;
            uint64_t pixels, ones_in;
            if ((st = mask_ones(g, off, p, &ones_in)))
                return st;
            if (!format_mul(index, g->image_pixels, &pixels) || words > pixels)
                return HPFC_E_CORRUPT;
            ones_before = (pixels - words) + ones_in; /* refined pixels before this one */
            words += p - ones_in;                     /* word pixels before this one */
        }
        if (l == px->depth) {
            if (words >= g->info.word_pixels)
                return HPFC_E_CORRUPT;
            *rank = words;
            return HPFC_OK;
        }
        if (ones_before >= g->info.refined_pixels)
            return HPFC_E_CORRUPT;
        index = ones_before; /* the k-th refined pixel points at image k (§5.1) */
    }
    return HPFC_E_ARG;
}

int labels_rank_by_walk(const hpfc_file *f, const hpfc_pixel *px, uint64_t *rank)
{
    int st = check_leaf(f, px);
    if (st)
        return st;
    const hpfc_file_info *fi = &f->info;
    uint32_t l = px->depth;
    const file_level *g = &f->lv[l];
    uint64_t words = 0, off = 0, zeros, ones;
    if (l == 0) {
        *rank = root_words(g, 0, (uint64_t)px->path[0].j * fi->root_cols + px->path[0].i);
        return HPFC_OK;
    }
    uint64_t images = 0;
    while (off < px->path[l].image) {
        if (++images > g->info.images || (st = image_end(g, off, &off, &zeros)))
            return st ? st : HPFC_E_CORRUPT;
        words += zeros;
    }
    if (off != px->path[l].image)
        return HPFC_E_CORRUPT; /* not an image of the back-to-back layout */
    uint64_t p = (uint64_t)px->path[l].j * fi->cols + px->path[l].i;
    if ((st = mask_ones(g, off, p, &ones)))
        return st;
    *rank = words + (p - ones);
    return *rank < g->info.word_pixels ? HPFC_OK : HPFC_E_CORRUPT;
}

/* Leaf number (TEAM decision): the word pixels of a level in pool order.
 * Compact: the pixels before the leaf that are not refined, O(1); paper:
 * through the rank samples, else by the walk. */
int labels_leaf_rank(const hpfc_file *f, const hpfc_pixel *leaf, uint64_t *rank)
{
    int st = rank ? check_leaf(f, leaf) : HPFC_E_ARG;
    if (st)
        return st;
    if (!f->compact)
        return f->labels.present ? rank_by_samples(f, &f->labels, leaf, rank)
                                 : labels_rank_by_walk(f, leaf, rank);
    uint32_t d = leaf->depth;
    const file_level *lv = &f->lv[d];
    uint64_t g = leaf->path[d].image * lv->image_pixels + (uint64_t)leaf->path[d].j * lv->cols +
                 leaf->path[d].i;
    pool_pixel px;
    st = pool_read_pixel(&lv->pool, &lv->compact, g, &px);
    if (!st)
        *rank = g - px.refined;
    /* damaged block counts can rank a leaf past the level's leaves */
    return st ? st : *rank < lv->info.word_pixels ? HPFC_OK : HPFC_E_CORRUPT;
}

/* ---- words: regions and pieces -------------------------------------------------------- */

void labels_word_free(labels_word *lw)
{
    free(lw->heap);
    lw->heap = NULL;
}

/* Per crossing: 1 for a stabbing's second crossing (its ']'), which runs
 * the other way along the stabbing's edge. A stabbing's component has no
 * vertex and two crossings, the ']' after the '['. */
static uint32_t is_flip(const word_parts *wp, uint32_t k)
{
    uint32_t c = wp->comp[k];
    return wp->comp_vertex[c] == WORD_NONE && wp->comp_first[c] != k;
}

/* Regions: stretch t continues inside the pixel as stretch pred(t) + 1
 * (the sidewalk in_t -> out_pred(t)); the orbits are the regions,
 * numbered by their smallest stretch. */
static void number_regions(labels_word *lw)
{
    uint32_t n = lw->n;
    for (uint32_t t = 0; t < n; t++)
        lw->region[t] = NONE_REGION;
    lw->regions = 0;
    for (uint32_t t = 0; t < n; t++) {
        if (lw->region[t] != NONE_REGION)
            continue;
        for (uint32_t u = t; lw->region[u] == NONE_REGION; u = (lw->parts.pred[u] + 1) % n)
            lw->region[u] = lw->regions;
        lw->regions++;
    }
}

/* Pieces: one per crossing but a stabbing's second, which shares the edge
 * of its first. */
static void number_pieces(labels_word *lw)
{
    uint32_t pieces = 0;
    for (uint32_t k = 0; k < lw->n; k++) {
        lw->flip[k] = is_flip(&lw->parts, k);
        lw->piece[k] = lw->flip[k] ? lw->piece[lw->parts.pred[k]] : pieces++;
    }
    lw->pieces = pieces;
}

/* The grammar and the components come from words.c's parser, the one
 * home of word parsing; what is the labels' own is numbering regions and
 * pieces from them. */
int labels_word_parse(labels_word *lw, const char *sym, size_t len)
{
    lw->heap = NULL;
    uint32_t n = 0;
    for (size_t s = 0; s < len; s++)
        n += sym[s] != '+';
    if (len > UINT32_MAX / 8)
        return HPFC_E_LIMIT;
    lw->n = n;
    uint32_t *mem = lw->small;
    if (n > LABELS_WORD_SMALL) {
        if (!(lw->heap = malloc((3 * (size_t)n + WORD_PARTS_MEM(n)) * sizeof *mem)))
            return HPFC_E_NOMEM;
        mem = lw->heap;
    }
    lw->region = mem;
    lw->piece = mem + n;
    lw->flip = mem + 2 * (size_t)n;
    word_parts_place(&lw->parts, mem + 3 * (size_t)n, n);
    int st = word_parse_symbols(&lw->parts, sym, len);
    if (st)
        return st;
    if (n == 0) {
        lw->regions = 1;
        lw->pieces = 0;
        return HPFC_OK;
    }
    number_regions(lw);
    number_pieces(lw);
    return HPFC_OK;
}

/* ---- records ---------------------------------------------------------------------------- */

/* A located leaf's record: its word's regions and pieces, and the bit
 * offset of its labels. */
typedef labels_record leaf_record;

/* The file's labels for an accessor; *st: HPFC_E_ARG without a file,
 * HPFC_E_NO_SECTION without LABL, then HPFC_E_ARG without the accessor's
 * arguments (args_ok false). */
static const labels_view *labels_of(const hpfc_file *f, bool args_ok, int *st)
{
    const labels_view *v = f ? &f->labels : NULL;
    *st = !f ? HPFC_E_ARG : !v->present ? HPFC_E_NO_SECTION : !args_ok ? HPFC_E_ARG : HPFC_OK;
    return v;
}

/* The bit offset of global leaf g's record, from the block directory. */
static inline int record_offset(const labels_view *v, uint64_t g, uint64_t *off)
{
    uint64_t block = g >> v->block_shift, k = g & ((UINT64_C(1) << v->block_shift) - 1);
    uint64_t at = block * v->block_record_bits; /* < the directory's bits: g < leaves */
    *off = format_get(&v->dir, at, v->block_bits);
    if (k) {
        uint64_t rel = format_get(&v->dir, at + v->block_bits + (k - 1) * v->offset_bits,
                                  v->offset_bits);
        if (!format_add(*off, rel, off))
            return HPFC_E_CORRUPT;
    }
    return HPFC_OK;
}

/* Parses the leaf's word sym[0 .. len) into rec->word (free with
 * labels_word_free), finds its record (the leaf is the rank-th of its
 * level, rank < the level's leaves) and checks that it lies in the label
 * stream. */
static int load_record_ranked(const labels_view *v, const hpfc_pixel *leaf, uint64_t rank,
                              const char *sym, size_t len, leaf_record *rec)
{
    rec->off = 0;
    rec->word.heap = NULL;
    uint64_t g = v->first_leaf[leaf->depth] + rank; /* rank < word_pixels: g < leaves */
    int st = labels_word_parse(&rec->word, sym, len);
    if (!st)
        st = record_offset(v, g, &rec->off);
    if (st) {
        labels_word_free(&rec->word);
        return st;
    }
    uint64_t need = labels_record_bits(&rec->word, v->face_bits, v->edge_bits); /* < 2^28 */
    if (rec->off > v->label_bits || need > v->label_bits - rec->off) {
        labels_word_free(&rec->word);
        return HPFC_E_CORRUPT;
    }
    return HPFC_OK;
}

/* The same, the leaf ranked here. */
static int load_record_sym(const hpfc_file *f, const labels_view *v, const hpfc_pixel *leaf,
                           const char *sym, size_t len, leaf_record *rec)
{
    rec->off = 0;
    rec->word.heap = NULL;
    uint64_t rank;
    int st = labels_leaf_rank(f, leaf, &rank);
    return st ? st : load_record_ranked(v, leaf, rank, sym, len, rec);
}

/* The same, decoding the leaf's word first. */
static int load_record(const hpfc_file *f, const labels_view *v, const hpfc_pixel *leaf,
                       leaf_record *rec)
{
    char small[256], *sym = small;
    size_t len = 0;
    int st = hpfc_pixel_word(f, leaf, NULL, 0, &len);
    if (st)
        return st;
    if (len > sizeof small && !(sym = malloc(len)))
        return HPFC_E_NOMEM;
    st = hpfc_pixel_word(f, leaf, sym, len, &len);
    if (!st)
        st = load_record_sym(f, v, leaf, sym, len, rec);
    else
        memset(rec, 0, sizeof *rec);
    if (sym != small)
        free(sym);
    return st;
}

/* Piece q's edge id and side bit. */
static int record_piece(const labels_view *v, const leaf_record *rec, uint32_t q, uint64_t *edge,
                        uint32_t *side)
{
    uint64_t at = rec->off + (uint64_t)q * (v->edge_bits + 1);
    uint64_t id = format_get(&v->labels, at, v->edge_bits);
    if (id >= v->edges)
        return HPFC_E_CORRUPT;
    *edge = id;
    *side = (uint32_t)format_get(&v->labels, at + v->edge_bits, 1);
    return HPFC_OK;
}

/* The face on the right of out_c, crossing c's out-dart: side s of its
 * edge, s the piece's bit, flipped at a stabbing's second crossing (whose
 * out-dart runs the other way along the edge). */
static int out_face(const labels_view *v, const leaf_record *rec, uint32_t c, uint64_t *face)
{
    uint64_t edge;
    uint32_t side;
    int st = record_piece(v, rec, rec->word.piece[c], &edge, &side);
    if (st)
        return st;
    side ^= rec->word.flip[c];
    uint64_t id = format_get(&v->sides, (2 * edge + side) * v->face_bits, v->face_bits);
    if (id >= v->faces)
        return HPFC_E_CORRUPT;
    *face = id;
    return HPFC_OK;
}

/* The face of stretch t: that on the right of the out-dart before it. */
static int stretch_face(const labels_view *v, const leaf_record *rec, uint32_t t, uint64_t *face)
{
    uint32_t n = rec->word.n;
    if (n)
        return out_face(v, rec, (t + n - 1) % n, face);
    uint64_t id = format_get(&v->labels, rec->off, v->face_bits);
    if (id >= v->faces)
        return HPFC_E_CORRUPT;
    *face = id;
    return HPFC_OK;
}

/* The edge id of crossing k: its piece's. */
static int crossing_edge(const labels_view *v, const leaf_record *rec, uint32_t k, uint64_t *edge)
{
    uint32_t side;
    return record_piece(v, rec, rec->word.piece[k], edge, &side);
}

/* Stretches of a word: one after each crossing, or the one boundary of a
 * private leaf. */
static uint32_t stretch_count(const labels_word *w)
{
    return w->n ? w->n : 1;
}

/* One answer about crossing or stretch k of a loaded record. */
typedef int (*record_query)(const labels_view *v, const leaf_record *rec, uint32_t k,
                            uint64_t *out);

/* The one-leaf accessors: the labels as labels_of answers (args_ok: the
 * accessor has its arguments), then the leaf's record loaded and `query`
 * answered about k, which must be one of its stretches (per_stretch) or
 * of its crossings, else HPFC_E_ARG. */
static int ask_record(const hpfc_file *f, bool args_ok, const hpfc_pixel *leaf, uint32_t k,
                      bool per_stretch, record_query query, uint64_t *out)
{
    int st;
    const labels_view *v = labels_of(f, args_ok, &st);
    leaf_record rec;
    if (st || (st = load_record(f, v, leaf, &rec)))
        return st;
    if (k >= (per_stretch ? stretch_count(&rec.word) : rec.word.n))
        st = HPFC_E_ARG;
    else
        st = query(v, &rec, k, out);
    labels_word_free(&rec.word);
    return st;
}

/* ---- public -------------------------------------------------------------------------------- */

int hpfc_file_get_labels_sized(const hpfc_file *f, hpfc_labels_info *out, size_t size)
{
    int st;
    const labels_view *v = labels_of(f, out != NULL, &st);
    if (st)
        return st;
    const hpfc_labels_info full = {.faces = v->faces,
                                   .edges = v->edges,
                                   .leaves = v->leaves,
                                   .face_bits = v->face_bits,
                                   .edge_bits = v->edge_bits,
                                   .section_bytes = v->section_length,
                                   .label_bits = v->label_bits,
                                   .directory_bits = v->dir.bits,
                                   .rank_bits = v->rank.bits};
    sized_out(out, size, &full, sizeof full);
    return HPFC_OK;
}

int hpfc_leaf_number(const hpfc_file *f, const hpfc_pixel *leaf, uint64_t *number)
{
    if (!f || !leaf || !number)
        return HPFC_E_ARG;
    return labels_leaf_rank(f, leaf, number);
}

int hpfc_label_leaf_faces(const hpfc_file *f, const hpfc_pixel *leaf, uint64_t *faces,
                          size_t cap, size_t *count)
{
    int st;
    const labels_view *v = labels_of(f, leaf && count, &st);
    if (st)
        return st;
    leaf_record rec;
    if ((st = load_record(f, v, leaf, &rec)))
        return st;
    *count = rec.word.regions;
    if (faces && cap < rec.word.regions)
        st = HPFC_E_BUFFER_SMALL;
    /* regions are numbered in the order their smallest stretch comes */
    for (uint32_t t = 0, r = 0; faces && !st && r < rec.word.regions; t++)
        if (rec.word.n == 0 || rec.word.region[t] == r)
            st = stretch_face(v, &rec, t, &faces[r++]);
    labels_word_free(&rec.word);
    return st;
}

int hpfc_label_stretch_face(const hpfc_file *f, const hpfc_pixel *leaf, uint32_t stretch,
                            uint64_t *face)
{
    return ask_record(f, leaf && face, leaf, stretch, true, stretch_face, face);
}

int hpfc_label_dart_face(const hpfc_file *f, const hpfc_dart *d, uint64_t *face)
{
    if (!f || !d || !face) /* before the section: HPFC_E_ARG without LABL too */
        return HPFC_E_ARG;
    /* the stretch after out_k is on its right: out_face */
    return ask_record(f, true, &d->pixel, d->crossing, false, out_face, face);
}

int hpfc_label_crossing_edge(const hpfc_file *f, const hpfc_pixel *leaf, uint32_t crossing,
                             uint64_t *edge)
{
    return ask_record(f, leaf && edge, leaf, crossing, false, crossing_edge, edge);
}

int hpfc_label_dart_edge(const hpfc_file *f, const hpfc_dart *d, uint64_t *edge)
{
    if (!d)
        return HPFC_E_ARG;
    return hpfc_label_crossing_edge(f, &d->pixel, d->crossing, edge);
}

/* ---- a whole leaf at once (point location) ------------------------------------------- */

void labels_leaf_free(labels_leaf *l)
{
    labels_word_free(&l->rec.word);
    free(l->edge);
    memset(l, 0, sizeof *l);
}

/* The crossings' edges of a loaded record into out->edge. */
static int load_edges(const labels_view *v, labels_leaf *out)
{
    const leaf_record *rec = &out->rec;
    uint32_t n = rec->word.n, entries = n ? n : 1;
    if (entries > out->cap) {
        uint64_t *e = realloc(out->edge, entries * sizeof *e);
        if (!e)
            return HPFC_E_NOMEM;
        out->edge = e;
        out->cap = entries;
    }
    int st = HPFC_OK;
    for (uint32_t k = 0; k < n && !st; k++)
        st = crossing_edge(v, rec, k, &out->edge[k]);
    return st;
}

int labels_leaf_load(const hpfc_file *f, const hpfc_pixel *leaf, const char *sym, size_t len,
                     labels_leaf *out)
{
    int st;
    const labels_view *v = labels_of(f, true, &st);
    if (st)
        return st;
    labels_word_free(&out->rec.word);
    if ((st = load_record_sym(f, v, leaf, sym, len, &out->rec)))
        return st;
    return load_edges(v, out);
}

/* A leaf's word into *word (grown to fit) and its rank among its level's
 * leaves: from `known` (a walk over its image counted them), else from one
 * read of the pool where the layout allows. */
static int read_leaf_word(const hpfc_file *f, const hpfc_pixel *leaf, const reader_leaf_at *known,
                          char **word, size_t *cap, size_t *len, uint64_t *rank)
{
    int st = *cap ? reader_leaf_word(f, leaf, known, *word, *cap, len, rank) : HPFC_E_BUFFER_SMALL;
    if (st == HPFC_E_BUFFER_SMALL) { /* rare: the buffer keeps the longest word yet */
        st = reader_leaf_word(f, leaf, known, NULL, 0, len, rank);
        if (!st && array_grow((void **)word, cap, *len < 64 ? 64 : *len + 1, 1))
            st = HPFC_E_NOMEM;
        if (!st)
            st = reader_leaf_word(f, leaf, known, *word, *cap, len, rank);
    }
    if (!st && *rank == UINT64_MAX) /* the paper layout ranks apart */
        st = labels_leaf_rank(f, leaf, rank);
    return st;
}

int labels_leaf_load_word(const hpfc_file *f, const hpfc_pixel *leaf, const reader_leaf_at *known,
                          char **word, size_t *cap, labels_leaf *out)
{
    int st;
    const labels_view *v = labels_of(f, word && cap && out, &st);
    if (st)
        return st;
    labels_word_free(&out->rec.word);
    size_t len = 0;
    uint64_t rank;
    if (!(st = read_leaf_word(f, leaf, known, word, cap, &len, &rank)))
        st = load_record_ranked(v, leaf, rank, *word, len, &out->rec);
    return st ? st : load_edges(v, out);
}

/* A leaf's rank among its level's leaves and whether it is private: from
 * `known` when a walk over its image counted them, else from its pool. */
static int leaf_rank_kind(const hpfc_file *f, const hpfc_pixel *leaf, const reader_leaf_at *known,
                          uint64_t *rank, bool *is_private)
{
    if (known && known->rank != UINT64_MAX) { /* reader_children_get checked it */
        *rank = known->rank;
        *is_private = known->word == UINT64_MAX;
        return HPFC_OK;
    }
    int priv = 0;
    int st = labels_leaf_rank(f, leaf, rank);
    if (!st)
        st = hpfc_pixel_is_private(f, leaf, &priv);
    *is_private = priv;
    return st;
}

/* Record [off, end) of a leaf of that kind as its pieces. */
static int record_pieces(const labels_view *v, bool is_private, uint64_t off, uint64_t end,
                         labels_pieces *out)
{
    if (off > end || end > v->label_bits)
        return HPFC_E_CORRUPT;
    uint64_t bits = end - off, unit = (uint64_t)v->edge_bits + 1;
    out->is_private = is_private;
    out->off = off;
    out->count = 0;
    if (is_private) {
        if (bits != v->face_bits)
            return HPFC_E_CORRUPT;
        out->face = format_get(&v->labels, off, v->face_bits);
        return out->face < v->faces ? HPFC_OK : HPFC_E_CORRUPT;
    }
    if (bits == 0 || bits % unit)
        return HPFC_E_CORRUPT; /* a stabbed leaf has a piece; pieces are whole */
    out->count = bits / unit;
    return HPFC_OK;
}

/* Where global leaf g's record ends: the next one's offset, the stream's
 * end after the last leaf. */
static int record_end(const labels_view *v, uint64_t g, uint64_t *end)
{
    *end = v->label_bits;
    return g + 1 < v->leaves ? record_offset(v, g + 1, end) : HPFC_OK;
}

int labels_leaf_pieces(const hpfc_file *f, const hpfc_pixel *leaf, const reader_leaf_at *known,
                       labels_pieces *out)
{
    int st;
    const labels_view *v = labels_of(f, leaf && out, &st);
    if (st)
        return st;
    uint64_t rank, off, end;
    bool is_private;
    if ((st = leaf_rank_kind(f, leaf, known, &rank, &is_private)))
        return st;
    uint64_t g = v->first_leaf[leaf->depth] + rank; /* rank < word_pixels: g < leaves */
    if ((st = record_offset(v, g, &off)) || (st = record_end(v, g, &end)))
        return st;
    return record_pieces(v, is_private, off, end, out);
}

int labels_leaf_pieces_ranked(const hpfc_file *f, uint32_t level, uint64_t rank, bool is_private,
                              uint64_t *next, labels_pieces *out)
{
    int st;
    const labels_view *v = labels_of(f, next && out && f && level < f->info.levels, &st);
    if (st)
        return st;
    if (rank >= v->first_leaf[level + 1] - v->first_leaf[level])
        return HPFC_E_ARG;
    uint64_t g = v->first_leaf[level] + rank, off = *next, end;
    if (off == UINT64_MAX && (st = record_offset(v, g, &off)))
        return st;
    /* a private record's extent is k_F; a stabbed one's from the directory */
    if (is_private)
        end = off <= v->label_bits ? off + v->face_bits : off;
    else if ((st = record_end(v, g, &end)))
        return st;
    if ((st = record_pieces(v, is_private, off, end, out)))
        return st;
    *next = end;
    return HPFC_OK;
}

int labels_piece_edge(const hpfc_file *f, const labels_pieces *p, uint64_t q, uint64_t *edge)
{
    int st;
    const labels_view *v = labels_of(f, p && edge && !p->is_private && q < p->count, &st);
    if (st)
        return st;
    /* off + count * (k_E + 1) <= label_bits: labels_leaf_pieces checked it */
    *edge = format_get(&v->labels, p->off + q * ((uint64_t)v->edge_bits + 1), v->edge_bits);
    return *edge < v->edges ? HPFC_OK : HPFC_E_CORRUPT;
}

int labels_leaf_face(const hpfc_file *f, const labels_leaf *l, uint32_t stretch, uint64_t *face)
{
    int st;
    const labels_view *v = labels_of(f, true, &st);
    if (st)
        return st;
    if (stretch >= stretch_count(&l->rec.word))
        return HPFC_E_ARG;
    return stretch_face(v, &l->rec, stretch, face);
}
