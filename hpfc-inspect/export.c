#include "export.h"

#include <inttypes.h>
#include <stdlib.h>
#include <string.h>

/* Open-addressing table from dart keys to dart indices. */
typedef struct key_table {
    uint64_t *keys;
    uint32_t *values;
    size_t mask;
} key_table;

static int table_init(key_table *t, size_t n)
{
    size_t cap = 16;
    while (cap < 2 * n + 16)
        cap *= 2;
    t->keys = malloc(cap * sizeof *t->keys);
    t->values = malloc(cap * sizeof *t->values);
    t->mask = cap - 1;
    if (!t->keys || !t->values)
        return HPFC_E_NOMEM;
    memset(t->values, 0xff, cap * sizeof *t->values);
    return HPFC_OK;
}

static size_t slot_of(const key_table *t, uint64_t key)
{
    size_t h = (size_t)((key * 0x9E3779B97F4A7C15ull) >> 17) & t->mask;
    while (t->values[h] != UINT32_MAX && t->keys[h] != key)
        h = (h + 1) & t->mask;
    return h;
}

static uint32_t table_get(const key_table *t, uint64_t key)
{
    return t->values[slot_of(t, key)];
}

/* Calls fn for every vertex of the file, in export order, with the leaf
 * that holds it (its box is the vertex's in the JSON). */
typedef int (*vertex_fn)(hpfc_walker *w, const hpfc_file *f, const hpfc_pixel *leaf,
                         uint64_t vertex, void *ctx);

static int for_each_vertex(const hpfc_file *f, hpfc_walker *w, vertex_fn fn, void *ctx)
{
    hpfc_pixel px;
    int st = hpfc_leaf_first(f, &px);
    while (!st) {
        uint32_t count;
        if ((st = hpfc_pixel_vertex_count(w, &px, &count)))
            return st;
        for (uint32_t k = 0; k < count && !st; k++) {
            uint64_t vertex;
            st = hpfc_pixel_vertex_key(w, &px, k, &vertex);
            if (!st)
                st = fn(w, f, &px, vertex, ctx);
        }
        if (!st)
            st = hpfc_leaf_next(f, &px);
    }
    return st == HPFC_E_NO_PIXEL ? HPFC_OK : st;
}

typedef struct export_ctx {
    exported_map *map;
    key_table table;
    uint64_t *darts; /* one vertex's darts */
    size_t cap;
} export_ctx;

/* The darts of a vertex, clockwise, into c->darts (grown as needed). */
static int vertex_darts(hpfc_walker *w, export_ctx *c, uint64_t vertex, uint32_t *degree)
{
    if (!c->darts) { /* never NULL below: that would ask for the degree only */
        if (!(c->darts = malloc(16 * sizeof *c->darts)))
            return HPFC_E_NOMEM;
        c->cap = 16;
    }
    int st = hpfc_key_vertex_darts(w, vertex, c->darts, c->cap, degree);
    if (st != HPFC_E_BUFFER_SMALL)
        return st;
    uint64_t *d = realloc(c->darts, *degree * sizeof *d);
    if (!d)
        return HPFC_E_NOMEM;
    c->darts = d;
    c->cap = *degree;
    return hpfc_key_vertex_darts(w, vertex, c->darts, c->cap, degree);
}

static int count_vertex(hpfc_walker *w, const hpfc_file *f, const hpfc_pixel *leaf,
                        uint64_t vertex, void *ctx)
{
    (void)f, (void)leaf;
    export_ctx *c = ctx;
    uint32_t degree;
    int st = hpfc_key_degree(w, vertex, &degree);
    c->map->nv++;
    c->map->nd += degree;
    return st;
}

/* First pass: number vertices and darts. */
static int number_vertex(hpfc_walker *w, const hpfc_file *f, const hpfc_pixel *leaf,
                         uint64_t vertex, void *ctx)
{
    export_ctx *c = ctx;
    exported_map *m = c->map;
    size_t vi = m->nv++;
    int64_t *b = m->box + 4 * vi;
    int st = hpfc_pixel_bounds(f, leaf, &b[0], &b[1], &b[2], &b[3]);
    uint32_t degree = 0;
    if (!st)
        st = vertex_darts(w, c, vertex, &degree);
    for (uint32_t k = 0; k < degree && !st; k++) {
        uint64_t dart = c->darts[k];
        size_t h = slot_of(&c->table, dart);
        if (c->table.values[h] != UINT32_MAX)
            return HPFC_E_CORRUPT; /* two darts with one key */
        c->table.keys[h] = dart;
        c->table.values[h] = (uint32_t)m->nd;
        m->origin[m->nd++] = (uint32_t)vi;
    }
    return st;
}

/* Second pass: twin and next of every dart, by key. */
static int link_vertex(hpfc_walker *w, const hpfc_file *f, const hpfc_pixel *leaf,
                       uint64_t vertex, void *ctx)
{
    (void)f, (void)leaf;
    export_ctx *c = ctx;
    uint32_t degree;
    int st = vertex_darts(w, c, vertex, &degree);
    for (uint32_t k = 0; k < degree && !st; k++) {
        uint64_t d = c->darts[k], t, n;
        if ((st = hpfc_key_twin(w, d, &t)) || (st = hpfc_key_next(w, d, &n)))
            break;
        uint32_t di = table_get(&c->table, d);
        uint32_t ti = table_get(&c->table, t);
        uint32_t ni = table_get(&c->table, n);
        if (di == UINT32_MAX || ti == UINT32_MAX || ni == UINT32_MAX)
            return HPFC_E_CORRUPT;
        c->map->twin[di] = ti;
        c->map->next[di] = ni;
    }
    return st;
}

int export_map(const hpfc_file *f, exported_map *out)
{
    memset(out, 0, sizeof *out);
    hpfc_walker *w;
    int st = hpfc_walker_create(f, &w);
    if (st)
        return st;
    export_ctx c = {.map = out};
    st = for_each_vertex(f, w, count_vertex, &c);
    if (!st && (out->nd > UINT32_MAX - 1 || out->nv > UINT32_MAX - 1))
        st = HPFC_E_LIMIT;
    if (!st) {
        size_t nv = out->nv, nd = out->nd;
        out->box = malloc((nv + 1) * 4 * sizeof *out->box);
        out->origin = malloc((nd + 1) * sizeof *out->origin);
        out->twin = malloc((nd + 1) * sizeof *out->twin);
        out->next = malloc((nd + 1) * sizeof *out->next);
        if (!out->box || !out->origin || !out->twin || !out->next || table_init(&c.table, nd))
            st = HPFC_E_NOMEM;
        out->nv = out->nd = 0;
    }
    if (!st)
        st = for_each_vertex(f, w, number_vertex, &c);
    if (!st)
        st = for_each_vertex(f, w, link_vertex, &c);
    free(c.table.keys);
    free(c.table.values);
    free(c.darts);
    hpfc_walker_free(w);
    if (st)
        exported_map_free(out);
    return st;
}

void exported_map_free(exported_map *m)
{
    free(m->box);
    free(m->origin);
    free(m->twin);
    free(m->next);
    memset(m, 0, sizeof *m);
}

/* Prints lattice value v * 10^e exactly, as a decimal. */
static void print_decimal(FILE *out, int64_t v, int32_t e)
{
    if (e >= 0) {
        fprintf(out, "%" PRId64, v);
        for (int32_t k = 0; k < e && v != 0; k++) /* "0", never "000" */
            fputc('0', out);
        return;
    }
    uint64_t mag = v < 0 ? (uint64_t)0 - (uint64_t)v : (uint64_t)v;
    char digits[64];
    int n = snprintf(digits, sizeof digits, "%" PRIu64, mag);
    int frac = -e;
    if (v < 0)
        fputc('-', out);
    if (n <= frac) {
        fputs("0.", out);
        for (int k = 0; k < frac - n; k++)
            fputc('0', out);
        fputs(digits, out);
    } else {
        fwrite(digits, 1, (size_t)(n - frac), out);
        fputc('.', out);
        fputs(digits + n - frac, out);
    }
}

int export_map_json(const hpfc_file *f, const exported_map *m, FILE *out)
{
    hpfc_file_info info;
    hpfc_file_get_info(f, &info);
    fputs("{\"format\": \"hpfc-graph\", \"version\": 1,\n \"vertices\": [", out);
    for (size_t v = 0; v < m->nv; v++) {
        fputs(v ? ",\n  {\"box\": [" : "\n  {\"box\": [", out);
        for (int k = 0; k < 4; k++) {
            if (k)
                fputs(", ", out);
            print_decimal(out, m->box[4 * v + k], info.unit_exp10);
        }
        fputs("]}", out);
    }
    fputs("],\n \"darts\": [", out);
    for (size_t d = 0; d < m->nd; d++)
        fprintf(out, "%s{\"origin\": %u, \"twin\": %u, \"next\": %u}", d ? ",\n  " : "\n  ", m->origin[d],
                m->twin[d], m->next[d]);
    fputs("]}\n", out);
    return ferror(out) ? HPFC_E_IO : HPFC_OK;
}
