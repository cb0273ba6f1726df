/*
 * Joining the parts of a split build (hpfc_build_part) into the tree that
 * hpfc_build gives for the whole map.
 *
 * The builder appends a level's images in the order of their parents, so
 * on every level the descendants of one root pixel form one run, in a
 * part's tree as in the whole map's. Walking the joined tree level by
 * level, each pixel copied from the part that built its root pixel, meets
 * the images, words and crossings in the single build's order: the joined
 * tree is the same tree, array for array.
 *
 * The counts a part cannot know come from the joined words: V is the
 * junctions, E the edges their crossings name (each edge leaves the word
 * pixels of its ends, so it crosses a road), C the classes of edges that
 * share a junction, and F = E + 1 + C - V (Euler), as hpfc_build counts
 * them on the graph.
 */
#include <stdlib.h>
#include <string.h>

#include "arrays.h"
#include "tree.h"
#include "words.h"

/* An image of a part, in the order the joined level holds them. */
typedef struct source_image {
    size_t part, image;
} source_image;

typedef struct merger {
    hpfc_tree *const *parts;
    size_t nparts;
    hpfc_tree *t;
    source_image *next;       /* the next level's images, in joined order */
    size_t nnext;
    bool count_components;    /* the map's components (and faces) counted */
    uint32_t *edge_parent;    /* union-find over the map's edges, when counted */
    uint8_t *edge_seen;       /* a bit an edge: met in some part's words */
    word_parts wp;
    hpfc_diag *diag;
} merger;

/* ---- checks ------------------------------------------------------------- */

static bool same_build(const hpfc_tree *a, const hpfc_tree *b)
{
    const hpfc_tree_info *x = &a->info, *y = &b->info;
    return x->root_cols == y->root_cols && x->root_rows == y->root_rows && x->cols == y->cols &&
           x->rows == y->rows && x->x0 == y->x0 && x->y0 == y->y0 && x->width == y->width &&
           x->height == y->height && x->unit_exp10 == y->unit_exp10 && x->edges == y->edges &&
           a->levels_cap == b->levels_cap;
}

/* owner[p]: the part that built root pixel p, each pixel exactly once. */
static int find_owners(const merger *m, uint32_t *owner, size_t roots)
{
    for (size_t p = 0; p < roots; p++)
        owner[p] = UINT32_MAX;
    for (size_t k = 0; k < m->nparts; k++) {
        const tpixel *pix = m->parts[k]->levels[0].pix;
        for (size_t p = 0; p < roots; p++) {
            if (pix[p].cross == TPIXEL_ABSENT)
                continue;
            if (owner[p] != UINT32_MAX)
                return diag_set(m->diag, HPFC_E_ARG, "hpfc_tree_merge: root pixel %zu is in parts %u and %zu",
                                p, owner[p], k);
            owner[p] = (uint32_t)k;
        }
    }
    for (size_t p = 0; p < roots; p++)
        if (owner[p] == UINT32_MAX)
            return diag_set(m->diag, HPFC_E_ARG, "hpfc_tree_merge: root pixel %zu is in no part", p);
    return HPFC_OK;
}

static int check_parts(const merger *m)
{
    if (!m->parts || m->nparts == 0)
        return diag_set(m->diag, HPFC_E_ARG, "hpfc_tree_merge: no part");
    if (m->nparts > UINT32_MAX - 1)
        return diag_set(m->diag, HPFC_E_ARG, "hpfc_tree_merge: too many parts");
    for (size_t k = 0; k < m->nparts; k++) {
        if (!m->parts[k] || !m->parts[k]->part)
            return diag_set(m->diag, HPFC_E_ARG, "hpfc_tree_merge: argument %zu is not a part's tree", k);
        if (!same_build(m->parts[0], m->parts[k]))
            return diag_set(m->diag, HPFC_E_ARG,
                            "hpfc_tree_merge: parts 0 and %zu come from different builds", k);
    }
    return HPFC_OK;
}

/* ---- the joined tree's arrays, sized from the parts -------------------- */

/* Each level's images, the words' symbols and the crossings: the sums of
 * the parts' (a part holds only its own root pixels' subtrees). */
static int allocate_tree(merger *m)
{
    const hpfc_tree *first = m->parts[0];
    hpfc_tree *t = m->t;
    t->info = first->info;
    t->info.levels = 1;
    t->info.vertices = t->info.faces = t->info.components = 0;
    t->info.word_pixels = t->info.refined_pixels = t->info.private_pixels = 0;
    t->info.max_word_symbols = 0;
    if (!(t->levels = calloc(first->levels_cap, sizeof *t->levels)))
        return HPFC_E_NOMEM;
    t->levels_cap = first->levels_cap;
    size_t nsyms = 4, ncross = 0;
    bool segments = false;
    for (size_t k = 0; k < m->nparts; k++) {
        nsyms += m->parts[k]->nsyms - 4;
        ncross += m->parts[k]->ncross;
        segments |= m->parts[k]->cross_seg != NULL;
    }
    t->syms = malloc(nsyms);
    t->cross_edge = malloc((ncross ? ncross : 1) * sizeof *t->cross_edge);
    if (segments)
        t->cross_seg = malloc((ncross ? ncross : 1) * sizeof *t->cross_seg);
    if (!t->syms || !t->cross_edge || (segments && !t->cross_seg))
        return HPFC_E_NOMEM;
    memcpy(t->syms, first->syms, 4); /* every private pixel's "++++" */
    t->nsyms = 4;
    t->cap_syms = nsyms;
    t->cap_cross = ncross;
    for (uint32_t l = 0; l < t->levels_cap; l++) {
        tlevel *lv = &t->levels[l];
        size_t images = l ? 0 : 1;
        for (size_t k = 0; l && k < m->nparts; k++)
            images += m->parts[k]->levels[l].nimages;
        const tlevel *src = &first->levels[l];
        *lv = (tlevel){.cols = src->cols, .rows = src->rows, .cell_w = src->cell_w,
                       .cell_h = src->cell_h, .cap = images};
        for (size_t k = 1; !lv->cols && k < m->nparts; k++) /* a part that reached this level */
            lv->cols = m->parts[k]->levels[l].cols, lv->rows = m->parts[k]->levels[l].rows,
            lv->cell_w = m->parts[k]->levels[l].cell_w, lv->cell_h = m->parts[k]->levels[l].cell_h;
        size_t per = (size_t)lv->cols * lv->rows;
        if (!images)
            continue;
        lv->img_gx = malloc(images * sizeof *lv->img_gx);
        lv->img_gy = malloc(images * sizeof *lv->img_gy);
        lv->pix = per && images <= SIZE_MAX / per / sizeof *lv->pix ? malloc(images * per * sizeof *lv->pix)
                                                                   : NULL;
        if (!lv->img_gx || !lv->img_gy || !lv->pix)
            return HPFC_E_NOMEM;
    }
    return HPFC_OK;
}

/* ---- counting V, E and C from the words -------------------------------- */

static uint32_t find_edge(uint32_t *parent, uint32_t e)
{
    while (parent[e] != e) {
        parent[e] = parent[parent[e]];
        e = parent[e];
    }
    return e;
}

/* The word's junctions are vertices of the map, and the edges of one
 * junction's crossings meet there. */
static int count_word(merger *m, const char *sym, uint32_t len, const uint32_t *edge)
{
    if (word_parse_symbols(&m->wp, sym, len))
        return diag_set(m->diag, HPFC_E_ARG, "hpfc_tree_merge: a part holds a malformed word");
    const word_parts *wp = &m->wp;
    m->t->info.vertices += wp->nvert;
    for (uint32_t k = 0; k < wp->n; k++) {
        if (edge[k] >= m->t->info.edges)
            return diag_set(m->diag, HPFC_E_ARG, "hpfc_tree_merge: a part names edge %u of %llu", edge[k],
                            (unsigned long long)m->t->info.edges);
        m->edge_seen[edge[k] >> 3] |= (uint8_t)(1u << (edge[k] & 7));
        uint32_t c = wp->comp[k];
        if (!m->edge_parent || wp->comp_vertex[c] == WORD_NONE)
            continue;
        uint32_t a = find_edge(m->edge_parent, edge[k]);
        uint32_t b = find_edge(m->edge_parent, edge[wp->comp_first[c]]);
        if (a != b)
            m->edge_parent[a] = b;
    }
    return HPFC_OK;
}

static int count_map(merger *m)
{
    hpfc_tree_info *info = &m->t->info;
    uint64_t components = 0;
    for (uint64_t e = 0; e < info->edges; e++) {
        if (!(m->edge_seen[e >> 3] & (1u << (e & 7))))
            return diag_set(m->diag, HPFC_E_ARG, "hpfc_tree_merge: edge %llu is in no part's words",
                            (unsigned long long)e);
        components += m->edge_parent && find_edge(m->edge_parent, (uint32_t)e) == e;
    }
    if (m->edge_parent) { /* else both stay 0: not counted */
        info->components = components;
        info->faces = info->edges + 1 + components - info->vertices;
    }
    return HPFC_OK;
}

/* ---- copying pixels ----------------------------------------------------- */

static int copy_word(merger *m, const hpfc_tree *src, const tpixel *from, tpixel *to)
{
    hpfc_tree *t = m->t;
    uint64_t n = from->cross & ((UINT64_C(1) << TPIXEL_COUNT_BITS) - 1);
    t->info.word_pixels++;
    if (n == 0) {
        *to = (tpixel){0, (uint64_t)t->ncross << TPIXEL_COUNT_BITS};
        t->info.private_pixels++;
        return HPFC_OK;
    }
    size_t at = (size_t)(from->cross >> TPIXEL_COUNT_BITS), len = (size_t)n + 4;
    if (t->nsyms + len > t->cap_syms || t->ncross + n > t->cap_cross)
        return diag_set(m->diag, HPFC_E_ARG, "hpfc_tree_merge: a part's words overrun its arrays");
    memcpy(t->syms + t->nsyms, src->syms + from->off, len);
    memcpy(t->cross_edge + t->ncross, src->cross_edge + at, n * sizeof *t->cross_edge);
    if (t->cross_seg && src->cross_seg)
        memcpy(t->cross_seg + t->ncross, src->cross_seg + at, n * sizeof *t->cross_seg);
    else if (t->cross_seg)
        memset(t->cross_seg + t->ncross, 0, n * sizeof *t->cross_seg);
    int st = count_word(m, t->syms + t->nsyms, (uint32_t)len, t->cross_edge + t->ncross);
    *to = (tpixel){t->nsyms, (uint64_t)t->ncross << TPIXEL_COUNT_BITS | n};
    t->nsyms += len;
    t->ncross += n;
    if (len > t->info.max_word_symbols)
        t->info.max_word_symbols = (uint32_t)len;
    return st;
}

/* A refined pixel's child image joins the next level, after those already
 * there: the order in which the builder appends them. */
static int copy_pixel(merger *m, size_t part, uint32_t level, const tpixel *from, tpixel *to)
{
    if (from->cross != TPIXEL_REFINED)
        return copy_word(m, m->parts[part], from, to);
    const tlevel *next = &m->t->levels[level + 1];
    if (level + 1 >= m->t->levels_cap || m->nnext >= next->cap)
        return diag_set(m->diag, HPFC_E_ARG, "hpfc_tree_merge: a part's child image is out of range");
    m->next[m->nnext++] = (source_image){part, from->off};
    *to = (tpixel){m->nnext - 1, TPIXEL_REFINED};
    m->t->info.refined_pixels++;
    return HPFC_OK;
}

static int copy_root(merger *m, const uint32_t *owner)
{
    tlevel *lv = &m->t->levels[0];
    size_t roots = (size_t)lv->cols * lv->rows;
    lv->img_gx[0] = lv->img_gy[0] = 0;
    lv->nimages = 1;
    int st = HPFC_OK;
    for (size_t p = 0; p < roots && !st; p++)
        st = copy_pixel(m, owner[p], 0, &m->parts[owner[p]]->levels[0].pix[p], &lv->pix[p]);
    return st;
}

/* Level `level` holds the images `cur` names, in that order. */
static int copy_level(merger *m, uint32_t level, const source_image *cur, size_t ncur)
{
    tlevel *lv = &m->t->levels[level];
    size_t per = (size_t)lv->cols * lv->rows;
    int st = HPFC_OK;
    for (size_t im = 0; im < ncur && !st; im++) {
        const tlevel *src = &m->parts[cur[im].part]->levels[level];
        if (cur[im].image >= src->nimages)
            return diag_set(m->diag, HPFC_E_ARG, "hpfc_tree_merge: a part's child image is out of range");
        lv->img_gx[im] = src->img_gx[cur[im].image];
        lv->img_gy[im] = src->img_gy[cur[im].image];
        for (size_t p = 0; p < per && !st; p++)
            st = copy_pixel(m, cur[im].part, level, &src->pix[cur[im].image * per + p], &lv->pix[im * per + p]);
    }
    lv->nimages = ncur;
    return st;
}

static int copy_levels(merger *m, const uint32_t *owner)
{
    hpfc_tree *t = m->t;
    source_image *cur = NULL;
    size_t ncur = 0;
    int st = HPFC_OK;
    for (uint32_t l = 0; !st && l < t->levels_cap; l++) {
        size_t cap = l + 1 < t->levels_cap ? t->levels[l + 1].cap : 0;
        if (!(m->next = malloc((cap ? cap : 1) * sizeof *m->next))) {
            st = HPFC_E_NOMEM;
            break;
        }
        m->nnext = 0;
        st = l ? copy_level(m, l, cur, ncur) : copy_root(m, owner);
        free(cur);
        cur = m->next, ncur = m->nnext;
        m->next = NULL;
        if (!st && ncur == 0) {
            t->info.levels = l + 1;
            break;
        }
        if (!st && ncur != cap)
            st = diag_set(m->diag, HPFC_E_ARG, "hpfc_tree_merge: a part holds images no pixel refines");
    }
    free(cur);
    return st;
}

/* ---- entry point -------------------------------------------------------- */

/* What both merges (`who`) do first: the parts checked against each other,
 * the word parser sized for their longest word, and the union-find over
 * the map's edges made, refusing more edges than the parts' crossings
 * (every edge crosses a road of some part's pixels: more cannot be, and
 * would size the union-find for nothing). *roots: the root pixels. */
static int begin_merge(merger *m, const char *who, size_t *roots)
{
    int st = check_parts(m);
    if (st)
        return st;
    const hpfc_tree_info *first = &m->parts[0]->info;
    *roots = (size_t)first->root_cols * first->root_rows;
    uint64_t crossings = 0;
    uint32_t max_symbols = 4;
    for (size_t k = 0; k < m->nparts; k++) {
        crossings += m->parts[k]->ncross;
        if (m->parts[k]->info.max_word_symbols > max_symbols)
            max_symbols = m->parts[k]->info.max_word_symbols;
    }
    if (first->edges > crossings)
        return diag_set(m->diag, HPFC_E_ARG, "%s: %llu edges but %llu crossings in all parts", who,
                        (unsigned long long)first->edges, (unsigned long long)crossings);
    if (m->count_components &&
        !(m->edge_parent = malloc((first->edges ? first->edges : 1) * sizeof *m->edge_parent)))
        return HPFC_E_NOMEM;
    m->edge_seen = calloc((size_t)(first->edges / 8 + 1), 1);
    if (!m->edge_seen || word_parts_alloc(&m->wp, max_symbols))
        return HPFC_E_NOMEM;
    for (uint64_t e = 0; m->edge_parent && e < first->edges; e++)
        m->edge_parent[e] = (uint32_t)e;
    return HPFC_OK;
}

static int merge_into(merger *m)
{
    size_t roots = 0;
    int st = begin_merge(m, "hpfc_tree_merge", &roots);
    if (st)
        return st;
    uint32_t *owner = malloc(roots * sizeof *owner);
    if (!owner)
        st = HPFC_E_NOMEM;
    if (!st)
        st = find_owners(m, owner, roots);
    if (!st)
        st = allocate_tree(m);
    if (!st)
        st = copy_levels(m, owner);
    if (!st)
        st = count_map(m);
    if (!st && !m->t->cross_seg &&
        !(m->t->zero_seg = calloc((size_t)m->t->info.max_word_symbols + 1, sizeof *m->t->zero_seg)))
        st = HPFC_E_NOMEM;
    free(owner);
    return st;
}

/* What both merges do last: their working arrays freed, and the joined
 * tree handed out, or freed with the status `st`. */
static int end_merge(merger *m, int st, hpfc_tree **out)
{
    free(m->edge_parent);
    free(m->edge_seen);
    word_parts_free(&m->wp);
    if (st == HPFC_E_NOMEM)
        diag_set(m->diag, st, "out of memory");
    if (st) {
        hpfc_tree_free(m->t);
        return st;
    }
    *out = m->t;
    return HPFC_OK;
}

int hpfc_tree_merge(hpfc_tree *const *parts, size_t count, hpfc_tree **out, hpfc_diag *diag)
{
    diag_clear(diag);
    if (!out)
        return diag_set(diag, HPFC_E_ARG, "hpfc_tree_merge: NULL argument");
    *out = NULL;
    merger m = {.parts = parts, .nparts = count, .count_components = true, .diag = diag};
    if (!(m.t = calloc(1, sizeof *m.t)))
        return diag_set(diag, HPFC_E_NOMEM, "out of memory");
    return end_merge(&m, merge_into(&m), out);
}

/* ---- joining part files without copying them ---------------------------
 *
 * hpfc_tree_merge_files reads each part in place (part_read.c: its arrays
 * are its mapped file) and joins them as a view: the joined tree holds the
 * levels' sizes and, per level, the runs of images that come from one part
 * in a row (one per band of root pixels a part owns, so as many as the
 * parts' borders cross rows), and hpfc_tree_get_pixel reads each pixel
 * from its part, its child renumbered by its run's delta. The counts that
 * need every word (V, C, F) are made in one pass over the parts' words, as
 * hpfc_tree_merge makes them; its union-find over the map's edges (4 bytes
 * an edge) and the edges met (a bit an edge) are the only memory that
 * grows with the map. hpfc_tree_merge_files_uncounted leaves out the
 * union-find, and with it C and F, which no writer needs.
 */

/* Image `part_image` of `part` is the next image of joined level `level`:
 * it extends the level's last run, or starts one. */
static int view_append(tree_view *v, uint32_t level, uint32_t part, uint64_t part_image)
{
    size_t n = v->nruns[level];
    view_run *last = n ? &v->runs[level][n - 1] : NULL;
    if (last && last->part == part && last->part_first + last->count == part_image) {
        last->count++;
        return HPFC_OK;
    }
    uint64_t first = last ? last->first + last->count : 0; /* before the table moves */
    void *runs = v->runs[level];
    if (array_grow(&runs, &v->cap[level], n + 1, sizeof *v->runs[level]))
        return HPFC_E_NOMEM;
    v->runs[level] = runs;
    v->runs[level][n] = (view_run){first, part_image, 1, 0, part};
    v->nruns[level]++;
    return HPFC_OK;
}

/* A word of a part: counted for V and C as hpfc_tree_merge counts it. */
static int view_word(merger *m, const hpfc_tree *part, const tpixel *px)
{
    uint64_t n = px->cross & ((UINT64_C(1) << TPIXEL_COUNT_BITS) - 1);
    if (n == 0)
        return HPFC_OK;
    return count_word(m, part->syms + px->off, (uint32_t)n + 4,
                      part->cross_edge + (px->cross >> TPIXEL_COUNT_BITS));
}

/* The root image: each pixel from its owner, its child numbered in the
 * joined order; the children's runs start level 1. */
static int view_root(merger *m, tree_view *v, size_t roots)
{
    uint64_t joined = 0;
    int st = HPFC_OK;
    for (size_t p = 0; p < roots && !st; p++) {
        const hpfc_tree *part = v->parts[v->owner[p]];
        const tpixel *px = &part->levels[0].pix[p];
        if (px->cross != TPIXEL_REFINED) {
            st = view_word(m, part, px);
            continue;
        }
        v->root_delta[p] = (int64_t)joined - (int64_t)px->off;
        st = view_append(v, 1, v->owner[p], px->off);
        joined++;
    }
    return st;
}

/* Level l's runs give level l + 1's: each run's refined pixels, in order,
 * have their part's next children, which are the joined level's next. */
static int view_level(merger *m, tree_view *v, uint32_t l)
{
    const tlevel *shape = &m->t->levels[l];
    size_t per = (size_t)shape->cols * shape->rows;
    uint64_t joined = 0;
    int st = HPFC_OK;
    for (size_t r = 0; r < v->nruns[l] && !st; r++) {
        view_run *run = &v->runs[l][r];
        const hpfc_tree *part = v->parts[run->part];
        const tlevel *lv = &part->levels[l];
        bool first_child = true;
        if (run->part_first + run->count > lv->nimages)
            return diag_set(m->diag, HPFC_E_ARG, "hpfc_tree_merge_files: a part's child image is out of range");
        for (uint64_t im = run->part_first; im < run->part_first + run->count && !st; im++)
            for (size_t p = 0; p < per && !st; p++) {
                const tpixel *px = &lv->pix[im * per + p];
                if (px->cross != TPIXEL_REFINED) {
                    st = view_word(m, part, px);
                    continue;
                }
                int64_t delta = (int64_t)joined - (int64_t)px->off;
                if (first_child)
                    run->child_delta = delta, first_child = false;
                else if (delta != run->child_delta) /* the parts' order makes it constant */
                    return diag_set(m->diag, HPFC_E_ARG, "hpfc_tree_merge_files: a part's children out of order");
                if (l + 1 >= m->t->levels_cap)
                    return diag_set(m->diag, HPFC_E_ARG, "hpfc_tree_merge_files: a part refines its deepest level");
                st = view_append(v, l + 1, run->part, px->off);
                joined++;
            }
    }
    return st;
}

/* The joined levels' sizes: the parts' shapes, the runs' image counts. */
static int view_shape(merger *m)
{
    hpfc_tree *t = m->t;
    const hpfc_tree *first = m->parts[0];
    t->info = first->info;
    t->info.vertices = t->info.faces = t->info.components = 0;
    t->info.word_pixels = t->info.refined_pixels = t->info.private_pixels = 0;
    t->info.max_word_symbols = 0;
    for (size_t k = 0; k < m->nparts; k++) {
        const hpfc_tree_info *i = &m->parts[k]->info;
        t->info.word_pixels += i->word_pixels;
        t->info.refined_pixels += i->refined_pixels;
        t->info.private_pixels += i->private_pixels;
        if (i->max_word_symbols > t->info.max_word_symbols)
            t->info.max_word_symbols = i->max_word_symbols;
    }
    if (!(t->levels = calloc(first->levels_cap, sizeof *t->levels)))
        return HPFC_E_NOMEM;
    t->levels_cap = first->levels_cap;
    t->info.levels = 1;
    for (uint32_t l = 0; l < t->levels_cap; l++) {
        const tlevel *s = &first->levels[l];
        t->levels[l] = (tlevel){.cols = s->cols, .rows = s->rows, .cell_w = s->cell_w, .cell_h = s->cell_h};
    }
    t->levels[0].nimages = 1;
    return HPFC_OK;
}

/* Every level's runs, then the image counts they give, which must be all
 * of the parts' images. */
static int view_levels(merger *m, tree_view *v, size_t roots)
{
    int st = view_root(m, v, roots);
    for (uint32_t l = 1; !st && l < m->t->levels_cap && v->nruns[l]; l++) {
        st = view_level(m, v, l);
        const view_run *last = &v->runs[l][v->nruns[l] - 1];
        m->t->levels[l].nimages = m->t->levels[l].cap = (size_t)(last->first + last->count);
        m->t->info.levels = l + 1;
        uint64_t all = 0;
        for (size_t k = 0; k < m->nparts; k++)
            all += m->parts[k]->levels[l].nimages;
        if (!st && all != last->first + last->count)
            st = diag_set(m->diag, HPFC_E_ARG, "hpfc_tree_merge_files: a part holds images no pixel refines");
    }
    return st;
}

static int merge_view(merger *m, tree_view *v)
{
    size_t roots = 0;
    int st = begin_merge(m, "hpfc_tree_merge_files", &roots);
    if (st)
        return st;
    v->owner = malloc(roots * sizeof *v->owner);
    v->root_delta = calloc(roots, sizeof *v->root_delta);
    if (!v->owner || !v->root_delta)
        return HPFC_E_NOMEM;
    if ((st = find_owners(m, v->owner, roots)) || (st = view_shape(m)) ||
        (st = view_levels(m, v, roots)) || (st = count_map(m)))
        return st;
    if (!(m->t->zero_seg = calloc((size_t)m->t->info.max_word_symbols + 1, sizeof *m->t->zero_seg)))
        return HPFC_E_NOMEM;
    return HPFC_OK;
}

/* Part k at `path`, read in place; a refusal names the path. */
static int read_part_file(const char *path, hpfc_tree **out, hpfc_diag *diag)
{
    int st = path ? hpfc_tree_read_part(path, out, diag)
                  : diag_set(diag, HPFC_E_ARG, "hpfc_tree_merge_files: NULL path");
    if (st && path && diag) {
        char why[sizeof diag->message];
        memcpy(why, diag->message, sizeof why);
        diag_set(diag, st, "%s: %s", path, why[0] ? why : hpfc_strerror(st));
    }
    return st;
}

static int merge_files(const char *const *paths, size_t count, bool count_components,
                       hpfc_tree **out, hpfc_diag *diag)
{
    diag_clear(diag);
    if (!out || (!paths && count))
        return diag_set(diag, HPFC_E_ARG, "hpfc_tree_merge_files: NULL argument");
    *out = NULL;
    if (count == 0)
        return diag_set(diag, HPFC_E_ARG, "hpfc_tree_merge_files: no part");
    tree_view *v = calloc(1, sizeof *v);
    hpfc_tree *t = calloc(1, sizeof *t);
    if (v)
        v->parts = calloc(count, sizeof *v->parts);
    if (!v || !t || !v->parts) {
        tree_view_free(v);
        free(t);
        return diag_set(diag, HPFC_E_NOMEM, "out of memory");
    }
    t->view = v; /* hpfc_tree_free(t) frees the view and its parts */
    int st = HPFC_OK;
    for (size_t k = 0; k < count && !st; k++, v->nparts++)
        st = read_part_file(paths[k], &v->parts[k], diag);
    merger m = {.parts = v->parts, .nparts = count, .t = t, .count_components = count_components,
                .diag = diag};
    return end_merge(&m, st ? st : merge_view(&m, v), out);
}

int hpfc_tree_merge_files(const char *const *paths, size_t count, hpfc_tree **out, hpfc_diag *diag)
{
    return merge_files(paths, count, true, out, diag);
}

int hpfc_tree_merge_files_uncounted(const char *const *paths, size_t count, hpfc_tree **out,
                                    hpfc_diag *diag)
{
    return merge_files(paths, count, false, out, diag);
}
