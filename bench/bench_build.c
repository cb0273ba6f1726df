/*
 * bench_build: builder throughput and memory, and the hPFC paper's
 * Delaunay experiment (Sect. 6, "second experiment"). Not a test: run it
 * through bench/run.sh, which builds it in release mode.
 *
 *   bench_build [--runs K] grid N        N x N jittered grid mesh (gen_grid_mesh)
 *   bench_build [--runs K] delaunay N    N random points, 20% of edges removed
 *   bench_build [--runs K] paper [SEEDS] SEEDS (default 5) Delaunay graphs of
 *                                        4000 points, (n0, n) = (64, 2)
 *   bench_build --header grid|paper      the column names of those rows
 *
 * grid and delaunay print one row each. Peak RSS is the whole process's
 * (getrusage), so run one case per process, as run.sh does: the row gives
 * the peak after generating the graph and the peak after building it, and
 * their difference over the segment count is the builder's own memory per
 * segment. Times are the median of K runs (default 3) of hpfc_build(), which
 * includes validation; validation alone is timed separately.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>

#include "gen.h"
#include "hpfc.h"

enum { MAX_RUNS = 15 };

/* The flat rPFC is built only up to this many pixels; above it its size
 * follows from the depth: (n0 * n^depth)^2. (The builder reserves room for
 * 16 root images at once, so a flat grid of P pixels asks for 16 * 24 * P
 * bytes of address space: 6 GiB here.) */
#define FLAT_BUILD_LIMIT ((uint64_t)1 << 24)

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static double peak_rss_mib(void)
{
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return (double)ru.ru_maxrss / 1024.0; /* Linux reports KiB */
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
}

static _Noreturn void die(const char *what, int st, const hpfc_diag *diag)
{
    fprintf(stderr, "bench_build: %s: %s\n", what,
            diag && diag->message[0] ? diag->message : hpfc_strerror(st));
    exit(1);
}

static uint64_t segment_count(const hpfc_graph *g)
{
    uint64_t n = 0;
    for (size_t e = 0; e < hpfc_graph_edge_count(g); e++) {
        uint32_t u, v;
        const int64_t *xy;
        size_t k;
        hpfc_graph_edge(g, e, &u, &v, &xy, &k);
        n += k + 1;
    }
    return n;
}

/* Points in [1, C-1]^2 with C the smallest power of two >= 64 with
 * C^2 >= 256 N: about 16 lattice units between neighbours (as gen-pfc). */
static int64_t coord_max_for(uint64_t n)
{
    int64_t c = 64;
    while (c < GEN_COORD_MAX_DELAUNAY && (uint64_t)c * (uint64_t)c < 256 * n)
        c *= 2;
    return c;
}

/* Builds `runs` times; returns the median build time and keeps the last
 * tree in *keep (when non-NULL). */
static double timed_builds(const hpfc_graph *g, const hpfc_build_params *p, int runs,
                           hpfc_tree **keep)
{
    double t[MAX_RUNS];
    for (int r = 0; r < runs; r++) {
        hpfc_diag diag = {0};
        hpfc_tree *tree;
        double t0 = now_seconds();
        int st = hpfc_build(g, p, &tree, &diag);
        t[r] = now_seconds() - t0;
        if (st)
            die("hpfc_build", st, &diag);
        if (keep && r == runs - 1)
            *keep = tree;
        else
            hpfc_tree_free(tree);
    }
    return median(t, runs);
}

static double timed_validations(const hpfc_graph *g, int runs)
{
    double t[MAX_RUNS];
    for (int r = 0; r < runs; r++) {
        hpfc_diag diag = {0};
        double t0 = now_seconds();
        int st = hpfc_graph_validate(g, &diag);
        t[r] = now_seconds() - t0;
        if (st)
            die("hpfc_graph_validate", st, &diag);
    }
    return median(t, runs);
}

/* ---- (a) throughput and memory --------------------------------------------- */

static void throughput_header(void)
{
    printf("%-16s %9s %9s %9s %10s %9s %10s %6s %10s %9s %9s %9s\n", "case", "vertices",
           "edges", "segments", "validate_s", "build_s", "Mseg/s", "depth", "pixels",
           "rss_in_MiB", "rss_MiB", "B/seg");
}

static void throughput(const char *kind, uint64_t n, int runs)
{
    hpfc_graph *g = NULL;
    int st = strcmp(kind, "grid") == 0
                 ? gen_grid_mesh(1, (size_t)n, (size_t)n, 16, &g)
                 : gen_delaunay(1, (size_t)n, coord_max_for(n), 0.2, &g);
    if (st)
        die(kind, st, NULL);
    double rss_in = peak_rss_mib();
    uint64_t segs = segment_count(g);
    hpfc_build_params p;
    hpfc_build_params_default(&p);
    double tv = timed_validations(g, runs);
    hpfc_tree *t = NULL;
    double tb = timed_builds(g, &p, runs, &t);
    double rss = peak_rss_mib();
    hpfc_tree_info info;
    hpfc_tree_get_info(t, &info);
    char name[64];
    snprintf(name, sizeof name, "%s-%llu", kind, (unsigned long long)n);
    printf("%-16s %9zu %9zu %9llu %10.3f %9.3f %10.3f %6u %10llu %9.0f %9.0f %9.0f\n", name,
           hpfc_graph_vertex_count(g), hpfc_graph_edge_count(g), (unsigned long long)segs, tv,
           tb, (double)segs / tb / 1e6, info.levels - 1,
           (unsigned long long)(info.word_pixels + info.refined_pixels), rss_in, rss,
           (rss - rss_in) * 1048576.0 / (double)segs);
    hpfc_tree_free(t);
    hpfc_graph_free(g);
}

/* ---- (b) the paper's experiment -------------------------------------------- */

typedef struct paper_row {
    uint64_t vertices, edges, pixels, privates;
    uint32_t depth, max_word;
    double stabs_per_edge, build_s;
    uint64_t flat_pixels;
    int flat_built;
    uint64_t hpfc_bytes, flat_bytes; /* flat_bytes: 0 when not built */
} paper_row;

/* Stabbings (paper Sect. 2.4: the pieces of edges that cross a leaf pixel
 * between two crossings, with no junction inside) over the whole tree; each
 * starts with a '[' in its pixel's word. */
static uint64_t count_stabbings(const hpfc_tree *t, const hpfc_tree_info *info)
{
    uint64_t stabs = 0;
    for (uint32_t l = 0; l < info->levels; l++) {
        uint32_t cols = l ? info->cols : info->root_cols;
        uint32_t rows = l ? info->rows : info->root_rows;
        for (size_t im = 0; im < hpfc_tree_image_count(t, l); im++)
            for (uint32_t j = 0; j < rows; j++)
                for (uint32_t i = 0; i < cols; i++) {
                    hpfc_tree_pixel px;
                    if (hpfc_tree_get_pixel(t, l, im, i, j, &px) || px.type != HPFC_PIXEL_WORD)
                        continue;
                    for (uint32_t k = 0; k < px.word_len; k++)
                        stabs += px.word[k] == '[';
                }
    }
    return stabs;
}

/* The flat rPFC of the same graph: built when small enough, else its size
 * from the depth (the flat grid is the hPFC's finest level, spread over the
 * whole domain). */
static void flat_size(const hpfc_graph *g, const hpfc_tree_info *info, paper_row *row)
{
    uint64_t side_c = info->root_cols, side_r = info->root_rows;
    for (uint32_t l = 1; l < info->levels; l++) {
        side_c *= info->cols;
        side_r *= info->rows;
    }
    row->flat_pixels = side_c * side_r;
    row->flat_built = 0;
    row->flat_bytes = 0;
    if (row->flat_pixels > FLAT_BUILD_LIMIT)
        return;
    hpfc_build_params p;
    hpfc_build_params_default(&p);
    p.flat = 1;
    p.max_flat_pixels = FLAT_BUILD_LIMIT;
    hpfc_tree *t;
    hpfc_diag diag = {0};
    int st = hpfc_build(g, &p, &t, &diag);
    if (st == HPFC_E_NOMEM)
        return; /* too big for this machine: keep the computed size */
    if (st)
        die("flat hpfc_build", st, &diag);
    hpfc_tree_info fi;
    hpfc_tree_get_info(t, &fi);
    if (fi.word_pixels + fi.refined_pixels != row->flat_pixels)
        fprintf(stderr, "bench_build: flat grid %llu pixels, predicted %llu\n",
                (unsigned long long)(fi.word_pixels + fi.refined_pixels),
                (unsigned long long)row->flat_pixels);
    row->flat_pixels = fi.word_pixels + fi.refined_pixels;
    row->flat_built = 1;
    uint8_t *bytes = NULL;
    size_t size = 0;
    st = hpfc_tree_serialize(t, NULL, &bytes, &size, &diag);
    if (st)
        die("flat hpfc_tree_serialize", st, &diag);
    row->flat_bytes = size;
    hpfc_free(bytes);
    hpfc_tree_free(t);
}

static void paper_case(uint64_t seed, int runs, paper_row *row)
{
    hpfc_graph *g = NULL;
    int st = gen_delaunay(seed, 4000, (int64_t)1 << 20, 0.2, &g);
    if (st)
        die("gen_delaunay", st, NULL);
    hpfc_build_params p;
    hpfc_build_params_default(&p); /* (n0, n) = (64, 2) */
    hpfc_tree *t = NULL;
    row->build_s = timed_builds(g, &p, runs, &t);
    hpfc_tree_info info;
    hpfc_tree_get_info(t, &info);
    row->vertices = info.vertices;
    row->edges = info.edges;
    row->pixels = info.word_pixels + info.refined_pixels;
    row->privates = info.private_pixels;
    row->depth = info.levels - 1;
    row->max_word = info.max_word_symbols;
    row->stabs_per_edge = (double)count_stabbings(t, &info) / (double)info.edges;
    uint8_t *bytes = NULL;
    size_t size = 0;
    hpfc_diag diag = {0};
    st = hpfc_tree_serialize(t, NULL, &bytes, &size, &diag);
    if (st)
        die("hpfc_tree_serialize", st, &diag);
    row->hpfc_bytes = size;
    hpfc_free(bytes);
    flat_size(g, &info, row);
    hpfc_tree_free(t);
    hpfc_graph_free(g);
}

static void paper_header(void)
{
    printf("%-6s %8s %8s %9s %8s %6s %8s %10s %9s %12s %-8s %10s %10s %11s %10s\n", "seed",
           "vertices", "edges", "pixels", "private%", "depth", "max_word", "stabs/edge",
           "build_ms", "rPFC_pixels", "rPFC", "pix_ratio", "hPFC_bytes", "rPFC_bytes",
           "byte_ratio");
}

static void paper_print(const char *label, const paper_row *r)
{
    char fb[24] = "-", ratio[24] = "-";
    if (r->flat_bytes) {
        snprintf(fb, sizeof fb, "%llu", (unsigned long long)r->flat_bytes);
        snprintf(ratio, sizeof ratio, "%.0f", (double)r->flat_bytes / (double)r->hpfc_bytes);
    }
    printf("%-6s %8llu %8llu %9llu %8.1f %6u %8u %10.2f %9.2f %12llu %-8s %10.0f %10llu %11s %10s\n",
           label, (unsigned long long)r->vertices, (unsigned long long)r->edges,
           (unsigned long long)r->pixels, 100.0 * (double)r->privates / (double)r->pixels,
           r->depth, r->max_word, r->stabs_per_edge, r->build_s * 1e3,
           (unsigned long long)r->flat_pixels, r->flat_built ? "built" : "computed",
           (double)r->flat_pixels / (double)r->pixels, (unsigned long long)r->hpfc_bytes, fb,
           ratio);
}

static void paper(int seeds, int runs)
{
    double pixels = 0, privates = 0, flat = 0, bytes = 0, build = 0, stabs = 0;
    uint32_t dmin = UINT32_MAX, dmax = 0, wmin = UINT32_MAX, wmax = 0;
    for (int s = 0; s < seeds; s++) {
        paper_row row, *r = &row;
        paper_case((uint64_t)s + 1, runs, r);
        char label[16];
        snprintf(label, sizeof label, "%d", s + 1);
        paper_print(label, r);
        pixels += (double)r->pixels;
        privates += (double)r->privates;
        flat += (double)r->flat_pixels;
        bytes += (double)r->hpfc_bytes;
        build += r->build_s;
        stabs += r->stabs_per_edge;
        dmin = r->depth < dmin ? r->depth : dmin;
        dmax = r->depth > dmax ? r->depth : dmax;
        wmin = r->max_word < wmin ? r->max_word : wmin;
        wmax = r->max_word > wmax ? r->max_word : wmax;
    }
    /* Means over the seeds; the private share and the rPFC/hPFC ratio are
     * taken over the sums, as the paper's averages are. */
    char depth[24], word[24];
    snprintf(depth, sizeof depth, "%u-%u", dmin, dmax);
    snprintf(word, sizeof word, "%u-%u", wmin, wmax);
    printf("%-6s %8s %8s %9.0f %8.1f %6s %8s %10.2f %9.2f %12.0f %-8s %10.0f %10.0f\n", "mean",
           "", "", pixels / seeds, 100.0 * privates / pixels, depth, word, stabs / seeds,
           build / seeds * 1e3, flat / seeds, "", flat / pixels, bytes / seeds);
}

/* ---- main ---------------------------------------------------------------------- */

static int usage(void)
{
    fprintf(stderr, "usage: bench_build [--runs K] grid N | delaunay N | paper [SEEDS]\n"
                    "       bench_build --header grid|delaunay|paper\n");
    return 2;
}

static int parse_count(const char *s, uint64_t *out)
{
    char *end;
    unsigned long long v = strtoull(s, &end, 10);
    if (!*s || *s == '-' || *end || v == 0)
        return 0;
    *out = v;
    return 1;
}

int main(int argc, char **argv)
{
    int runs = 3, i = 1;
    uint64_t n = 0;
    if (argc == 3 && strcmp(argv[1], "--header") == 0) {
        if (strcmp(argv[2], "paper") == 0)
            paper_header();
        else
            throughput_header();
        return 0;
    }
    if (argc > 2 && strcmp(argv[1], "--runs") == 0) {
        if (!parse_count(argv[2], &n) || n > MAX_RUNS)
            return usage();
        runs = (int)n;
        i = 3;
    }
    if (i < argc && strcmp(argv[i], "paper") == 0) {
        n = 5;
        if (i + 1 < argc && !parse_count(argv[i + 1], &n))
            return usage();
        paper((int)n, runs);
        return 0;
    }
    if (i + 2 != argc || !parse_count(argv[i + 1], &n) ||
        (strcmp(argv[i], "grid") != 0 && strcmp(argv[i], "delaunay") != 0))
        return usage();
    throughput(argv[i], n, runs);
    return 0;
}
