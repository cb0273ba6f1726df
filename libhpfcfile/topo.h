/* Traversal internals shared by topo.c and faces.c. */
#ifndef HPFC_TOPO_H
#define HPFC_TOPO_H

#include <stdbool.h>

#include "hpfc.h"

#define NONE UINT32_MAX

/* The parsed structure of one word. */
typedef struct local_word {
    uint32_t n;              /* crossings */
    uint32_t road_off[5];    /* first crossing of roads W, N, E, S; then n */
    uint32_t ncomp, nvert;
    uint32_t *comp;          /* per crossing */
    uint32_t *pred, *succ;   /* per crossing, cyclic within its component */
    uint32_t *comp_vertex;   /* per component: local vertex, NONE for a stabbing */
    uint32_t *comp_first;    /* per component: first crossing (word order) */
    uint32_t *comp_last;
    uint32_t *comp_size;
    uint32_t *vertex_comp;   /* per local vertex */
    uint32_t *stack;
    char *sym;
} local_word;

struct hpfc_walker {
    const hpfc_file *file;
    uint32_t cap;            /* most crossings of any word in the file */
    uint64_t budget;         /* most stabbings a walk may follow */
    local_word here, there;
    char *scratch;           /* symbols of other leaves (road counts) */
    uint64_t visited;        /* words decoded */
    bool here_valid;         /* `here` holds the pixel at bit here_slot */
    uint64_t here_slot;
};

typedef struct box {
    int64_t x0, y0, x1, y1;
} box;

/* Decodes and parses px's word into lw (HPFC_E_CORRUPT if malformed). */
int topo_parse_pixel(hpfc_walker *w, local_word *lw, const hpfc_pixel *px);
/* Crossings on road `road` of a word pixel. */
int topo_road_count(hpfc_walker *w, const hpfc_pixel *px, int road, uint32_t *count);
int topo_leaf_box(const hpfc_file *f, const hpfc_pixel *px, box *b);
/* Extent [lo, hi) of box b along the line of `road`. */
void topo_road_extent(const box *b, int road, int64_t *lo, int64_t *hi);
/* Whether the road's clockwise order runs toward increasing coordinates. */
bool topo_road_ascends(int road);
/* The leaf at position t along b's road, on b's side (inside) or across. */
int topo_locate_on_road(const hpfc_file *f, const box *b, int road, int64_t t, bool inside,
                   hpfc_pixel *out, box *out_box);
/* Crossing k of P (parsed in lw) seen from across its road: pixel Q (parsed
 * into qlw, which must differ from lw) and the crossing's index *m in Q. */
int topo_cross_road(hpfc_walker *w, const hpfc_pixel *p, const local_word *lw, uint32_t k,
               hpfc_pixel *q, local_word *qlw, uint32_t *m);
/* Sum of road-`road` crossings of the leaves on b's side that follow b, in
 * b's clockwise order, up to the end of the extent [qlo, qhi). */
int topo_crossings_after(hpfc_walker *w, const box *b, int road, int64_t qlo, int64_t qhi,
                    uint64_t *sum);

#endif
