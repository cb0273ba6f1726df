/*
 * labels.h: the LABL section (spec/hpfc-format.md §6.5): the face of every
 * region of every leaf and the edge id of every crossing, stored so that a
 * located leaf's labels are read in O(levels) without touching another
 * leaf. Internal to the library (and its tests).
 */
#ifndef HPFC_LABELS_H
#define HPFC_LABELS_H

#include <stdbool.h>
#include <stdint.h>

#include "format.h"
#include "hpfc.h"
#include "reader.h"
#include "words.h"

#define FORMAT_TAG_LABL "LABL"

enum {
    LABL_HEADER_SIZE = 48,
    LABL_LEVEL_SIZE = 8,
    LABL_MAX_SHIFT = 16,      /* block_shift and sample_shift */
};

/* Header (48 bytes), then one 8-byte entry per level: a FORMAT_FIELD per
 * field of §6.5.2's tables, alike in shape to every section's field list
 * (format.h, geometry.h) and each with its own fields. */
FORMAT_FIELD(labl, face_count, 0, 8, uint64_t)
FORMAT_FIELD(labl, edge_count, 8, 8, uint64_t)
FORMAT_FIELD(labl, leaf_count, 16, 8, uint64_t)
FORMAT_FIELD(labl, label_bits, 24, 8, uint64_t)
FORMAT_FIELD(labl, face_bits, 32, 1, uint8_t)
FORMAT_FIELD(labl, edge_bits, 33, 1, uint8_t)
FORMAT_FIELD(labl, block_shift, 34, 1, uint8_t)
FORMAT_FIELD(labl, block_bits, 35, 1, uint8_t)
FORMAT_FIELD(labl, offset_bits, 36, 1, uint8_t)
FORMAT_FIELD(labl, sample_shift, 37, 1, uint8_t)
FORMAT_FIELD(labl, reserved0, 38, 2, uint16_t)
FORMAT_FIELD(labl, levels, 40, 4, uint32_t)
FORMAT_FIELD(labl, reserved1, 44, 4, uint32_t)
/* Level entry: the width of the level's rank samples, 7 reserved bytes. */
FORMAT_FIELD(labll, rank_bits, 0, 1, uint8_t)
enum { labll_OFF_reserved = 1, labll_SIZE_reserved = 7 };

/* The section as a reader sees it, checked at open (labels_open). */
typedef struct labels_view {
    bool present;
    uint64_t faces, edges, leaves, label_bits;
    uint32_t face_bits, edge_bits, block_shift, block_bits, offset_bits, sample_shift;
    uint32_t levels;
    format_bits rank, dir, sides, labels;         /* the four bit streams */
    uint64_t rank_start[HPFC_MAX_LEVELS];         /* level l's samples in `rank` */
    uint32_t rank_bits[HPFC_MAX_LEVELS];
    uint64_t samples[HPFC_MAX_LEVELS];            /* sample count of level l */
    uint64_t first_leaf[HPFC_MAX_LEVELS + 1];     /* global number of level l's leaf 0 */
    uint64_t block_record_bits;                   /* block_bits + (B - 1) * offset_bits */
    const uint8_t *section;                       /* its bytes */
    uint64_t section_length;
} labels_view;

/* Whether LABL's edge and face counts are ones its bytes pay for, to hold
 * them to before anything is sized by them (a damaged header may claim
 * billions): every edge has crossings, each storing an edge id of
 * edge_bits, and Euler's formula with at most V components gives
 * F <= E + 1. */
static inline bool labels_counts_paid(const labels_view *v)
{
    uint64_t edge_room = v->edge_bits ? v->label_bits / v->edge_bits + 1 : 1;
    return v->edges <= edge_room && v->faces <= v->edges + 1;
}

/* What labels_open needs of the level table: per level its leaves
 * (word_pixels) and its units (root records at level 0, images below). */
typedef struct labels_levels {
    uint32_t levels;
    uint64_t word_pixels[HPFC_MAX_LEVELS];
    uint64_t units[HPFC_MAX_LEVELS];
} labels_levels;

/* The section's layout as a function of its header (shared by the writer
 * and labels_open): byte offsets of the three streams and the exact
 * length. false on overflow or an out-of-range field. */
typedef struct labels_layout {
    uint64_t rank_bits_total, dir_bits, sides_bits, rank_at, dir_at, sides_at, labels_at, length;
    uint64_t rank_start[HPFC_MAX_LEVELS], samples[HPFC_MAX_LEVELS];
    uint64_t blocks, block_record_bits;
} labels_layout;

bool labels_compute_layout(const labels_levels *lv, const uint32_t *rank_bits, uint64_t leaves,
                           uint32_t block_shift, uint32_t block_bits, uint32_t offset_bits,
                           uint32_t sample_shift, uint64_t edges, uint32_t face_bits,
                           uint64_t label_bits, labels_layout *out);

/* Global leaf numbers (§6.5.1), which GEOM shares (§6.6.1): level l's leaves
 * come after the word pixels of the levels above, so its first leaf is
 * first_leaf[l], and first_leaf[levels] counts them all. false when that
 * count overflows. */
bool labels_first_leaves(uint32_t levels, const uint64_t *word_pixels, uint64_t *first_leaf);

/* Checks a LABL section's header against the level table and fills v;
 * HPFC_E_SECTION when it fails. O(levels). */
int labels_open(labels_view *v, const uint8_t *sec, uint64_t length, const labels_levels *lv);

/* The leaf number of a word pixel (spec §6.5.4): its rank among its
 * level's leaves in pool order. Compact layout: O(1) from the type blocks'
 * counts. Paper layout: through the LABL rank samples when the file has
 * them (O(levels * 2^sample_shift)), else by a walk over the level's pool
 * before the leaf (O(pool)). HPFC_E_ARG for a refined pixel or a path
 * outside the file, HPFC_E_CORRUPT when the pools or the samples
 * contradict the layout of §5.2.2 (or §5.3). */
int labels_leaf_rank(const hpfc_file *file, const hpfc_pixel *leaf, uint64_t *rank);
/* The slow walk on its own (the tests' oracle). */
int labels_rank_by_walk(const hpfc_file *file, const hpfc_pixel *leaf, uint64_t *rank);

/* Words of up to this many crossings parse without a malloc. */
#define LABELS_WORD_SMALL 64

/* A word's regions and edge pieces (§6.5.1), from its components. */
typedef struct labels_word {
    uint32_t n;          /* crossings */
    uint32_t regions;    /* 1 when private, else n - components + 1 */
    uint32_t pieces;     /* edge labels: n minus the stabbings */
    uint32_t *region;    /* per stretch t (between crossings t-1 and t): its region */
    uint32_t *piece;     /* per crossing: its piece */
    uint32_t *flip;      /* per crossing: 1 for a stabbing's second crossing (`]`) */
    word_parts parts;    /* the grammar's parse (words.h): parts.pred, the cyclic
                          * predecessor of each crossing in its component */
    uint32_t small[3 * LABELS_WORD_SMALL + WORD_PARTS_MEM(LABELS_WORD_SMALL)];
    uint32_t *heap;
} labels_word;

/* Bits of a leaf's record: a face id for a private leaf, else an edge id
 * and a side bit per piece. */
static inline uint64_t labels_record_bits(const labels_word *w, uint32_t face_bits,
                                          uint32_t edge_bits)
{
    return w->n ? (uint64_t)w->pieces * (edge_bits + 1) : face_bits;
}

/* Parses `len` symbols (a word of the grammar of §3.8, else
 * HPFC_E_CORRUPT); HPFC_E_NOMEM for a long word. labels_word_free after,
 * whatever it returns. */
int labels_word_parse(labels_word *lw, const char *sym, size_t len);
void labels_word_free(labels_word *lw);

/* A leaf's labels all at once (point location): its word parsed and per
 * crossing its edge id; its stretches' faces on demand
 * (labels_leaf_face). Reuse one value across leaves (its arrays grow),
 * then labels_leaf_free. */
typedef struct labels_record {
    labels_word word;
    uint64_t off;         /* the record's bit offset in the label stream */
} labels_record;
typedef struct labels_leaf {
    labels_record rec;    /* rec.word: the word parsed (rec.word.n crossings) */
    uint64_t *edge;       /* per crossing k < word.n */
    size_t cap;
} labels_leaf;

/* Loads the labels of `leaf`, whose word is sym[0 .. len) (hpfc_pixel_word).
 * Statuses as hpfc_label_stretch_face's. */
int labels_leaf_load(const hpfc_file *file, const hpfc_pixel *leaf, const char *sym, size_t len,
                     labels_leaf *out);
/* The same, the word read here into *word (a buffer of *cap bytes that
 * grows to the longest word yet, for a caller that loads many leaves) and
 * the leaf ranked from the same read of its pool (compact layout), or from
 * `known` (reader.h: a walk over its image counted both; NULL: none). */
int labels_leaf_load_word(const hpfc_file *file, const hpfc_pixel *leaf,
                          const reader_leaf_at *known, char **word, size_t *cap,
                          labels_leaf *out);
void labels_leaf_free(labels_leaf *l);
/* What a leaf's record says without its word: the edge of each piece (a
 * crossing's, one for both crossings of a stabbing) or a private leaf's
 * face. Enough for a caller that wants the set of the leaf's edges and
 * not which crossing lies on which (a window's leaves inside it). Records
 * follow each other with no gap (§6.5.2), so a record's extent is the
 * next one's offset (the stream's end after the last leaf) and its pieces
 * are that extent over k_E + 1; whether the leaf is private comes from its
 * type bits. No word is decoded: the cost is the directory's two entries
 * (and the leaf's rank, from `known` when a walk over its image counted it).
 * A record whose extent is not what its kind needs is HPFC_E_CORRUPT; a
 * stabbed record of any whole number of pieces is taken as it is (its
 * word would say how many, full verification checks that they agree). */
typedef struct labels_pieces {
    bool is_private;      /* then `face`, else `count` pieces */
    uint64_t face;
    uint64_t count;       /* pieces, read with labels_piece_edge */
    uint64_t off;         /* the record's bit offset in the label stream */
} labels_pieces;
int labels_leaf_pieces(const hpfc_file *file, const hpfc_pixel *leaf, const reader_leaf_at *known,
                       labels_pieces *out);
/* The same for the leaf of `rank` among level `level`'s leaves, of the
 * kind given (a scan over its image's type bits found both: reader_scan).
 * *next: where its record starts when the caller knows it (the end of the
 * record of the level's leaf rank - 1, which this call returned in *next),
 * UINT64_MAX to read it from the directory; set to where the record ends.
 * A private leaf's extent is then k_F without a directory read: a run of
 * leaves costs one directory entry per stabbed leaf. */
int labels_leaf_pieces_ranked(const hpfc_file *file, uint32_t level, uint64_t rank,
                              bool is_private, uint64_t *next, labels_pieces *out);
/* Piece q < p->count's edge id (< the section's edge count, else
 * HPFC_E_CORRUPT). */
int labels_piece_edge(const hpfc_file *file, const labels_pieces *p, uint64_t q, uint64_t *edge);

/* The face of stretch `stretch` (< max(word.n, 1)) of a loaded leaf. */
int labels_leaf_face(const hpfc_file *file, const labels_leaf *l, uint32_t stretch,
                     uint64_t *face);

/* The section's bytes for a tree and its serialised file, with the faces
 * numbered a root pixel at a time (fs, of the same file: faces.h):
 * *out (malloc'ed), *length: the writer's bytes (the writer itself uses
 * labels_writer below). What the build holds besides the section is
 * the plan, one root's numbering, the roots' runs on each level, each
 * edge's first level, and the pieces met before their edge's first one
 * (pieces of edges across roots). */
typedef struct faces_stream faces_stream;
int labels_build_stream(const hpfc_tree *tree, const hpfc_file *file, faces_stream *fs,
                        uint8_t **out, uint64_t *length, hpfc_diag *diag);

/* Either build in two steps, so that a writer can place the section
 * before it is made and make it in the file's own bytes: begin reads the
 * tree once in leaf order (the faces `fc` numbered whole, or else `fs` a
 * root pixel at a time) and gives the section's exact *length; emit
 * makes the section in `sec` (*length zeroed bytes), the streamed sides
 * in place. The writer holds neither the section nor, streamed, its
 * sides. */
typedef struct labels_writer labels_writer;
int labels_writer_begin(const hpfc_tree *tree, const hpfc_file *file, const hpfc_faces *fc,
                        faces_stream *fs, labels_writer **w, uint64_t *length, hpfc_diag *diag);
int labels_writer_emit(labels_writer *w, uint8_t *sec, hpfc_diag *diag);
void labels_writer_free(labels_writer *w);

#endif
