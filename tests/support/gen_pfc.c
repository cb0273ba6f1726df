/*
 * gen-pfc: writes a generated test graph as plain-text .pfc, to make shipped
 * sample data.
 *
 *   gen-pfc KIND SEED N OUT.pfc
 *
 *   delaunay  N random points, Delaunay triangulation, 20% of edges removed
 *   polyline  N random points, 50% removed, degree-2 chains contracted
 *   grid      an N x N cell jittered grid mesh, spacing 16
 *   special   hand-made graph number N or its name (edge, triangle, crack,
 *             loop, multi, hole, star, comb); SEED is ignored
 *
 * The random points of delaunay/polyline lie in [1, C-1]^2 where C is the
 * smallest power of two >= 64 with C^2 >= 256 N (about 16 lattice units
 * between neighbouring points), capped at 2^21. OUT.pfc may be "-" for
 * standard output.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gen.h"

static void usage(void)
{
    fprintf(stderr, "usage: gen-pfc delaunay|polyline|grid|special SEED N OUT.pfc [COORD_MAX]\n");
}

/* Parses a whole decimal (or 0x hex) unsigned number; 0 on failure. */
static int parse_u64(const char *s, uint64_t *out)
{
    char *end;
    errno = 0;
    if (!*s || *s == '-')
        return 0;
    unsigned long long v = strtoull(s, &end, 0);
    if (errno || *end)
        return 0;
    *out = (uint64_t)v;
    return 1;
}

static int64_t coord_max_for(uint64_t n)
{
    int64_t c = 64;
    while (c < GEN_COORD_MAX_DELAUNAY && (uint64_t)c * (uint64_t)c < 256 * n)
        c *= 2;
    return c;
}

/* Special graph by number or name; -1 if neither. */
static int special_index(const char *arg)
{
    uint64_t n;
    if (parse_u64(arg, &n))
        return n < GEN_SPECIAL_COUNT ? (int)n : -1;
    for (int k = 0; k < GEN_SPECIAL_COUNT; k++)
        if (strcmp(arg, gen_special_name(k)) == 0)
            return k;
    return -1;
}

/* COORD_MAX bounds the random points' coordinates; 0 picks about 16
 * lattice units between neighbouring points. */
static int generate(const char *kind, uint64_t seed, const char *narg, uint64_t coord_max, hpfc_graph **g)
{
    uint64_t n = 0;
    if (strcmp(kind, "special") == 0) {
        int k = special_index(narg);
        return k < 0 ? HPFC_E_ARG : gen_special(k, g);
    }
    if (!parse_u64(narg, &n) || n > ((uint64_t)1 << 28) || coord_max > (uint64_t)GEN_COORD_MAX_DELAUNAY)
        return HPFC_E_ARG;
    int64_t cmax = coord_max ? (int64_t)coord_max : coord_max_for(n);
    if (strcmp(kind, "delaunay") == 0)
        return gen_delaunay(seed, (size_t)n, cmax, 0.2, g);
    if (strcmp(kind, "polyline") == 0)
        return gen_polyline(seed, (size_t)n, cmax, 0.5, g);
    if (strcmp(kind, "grid") == 0)
        return gen_grid_mesh(seed, (size_t)n, (size_t)n, 16, g);
    return HPFC_E_ARG;
}

int main(int argc, char **argv)
{
    uint64_t seed, coord_max = 0;
    if ((argc != 5 && argc != 6) || !parse_u64(argv[2], &seed) || (argc == 6 && !parse_u64(argv[5], &coord_max))) {
        usage();
        return 2;
    }
    hpfc_graph *g = NULL;
    int st = generate(argv[1], seed, argv[3], coord_max, &g);
    if (st) {
        fprintf(stderr, "gen-pfc: %s\n", hpfc_strerror(st));
        if (st == HPFC_E_ARG)
            usage();
        return 1;
    }
    int to_stdout = strcmp(argv[4], "-") == 0;
    FILE *f = to_stdout ? stdout : fopen(argv[4], "w");
    if (!f) {
        fprintf(stderr, "gen-pfc: %s: %s\n", argv[4], strerror(errno));
        hpfc_graph_free(g);
        return 1;
    }
    st = gen_write_pfc(g, f);
    if ((!to_stdout && fclose(f) != 0) || (to_stdout && fflush(f) != 0))
        st = HPFC_E_IO;
    hpfc_graph_free(g);
    if (st) {
        fprintf(stderr, "gen-pfc: %s: %s\n", argv[4], hpfc_strerror(st));
        return 1;
    }
    return 0;
}
