/*
 * read_route: a route file (common/part_dir.h, DIR/route-C), the edges of a
 * chunk of a .pfc that a worker routed to the parts, as a part's builder
 * reads it back (part_dir_build_routed).
 *
 * Once per process: a small street grid read in 3 chunks into a graph file
 * (the workers' read, tests/support/pfc_chunked.h), planned in 4 parts on a
 * 6 x 6 root, in a temporary directory. Per input: the first byte picks a
 * part; the rest is written as the one chunk's route file (route-0 of a
 * plan of one chunk), and that part is built from it.
 *
 * Oracle: a status the reader names (corrupt, I/O, memory) or one of the
 * builder's refusals of a part graph it copied (a graph whose edges are
 * not the plan's: ARG, and the validation codes), never a crash; with a
 * status, a diagnostic; the genuine route file of the plan builds every
 * part.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "input.h"
#include "part_dir.h"
#include "pfc_chunked.h"

static char dir[64];
static part_plan plan;

/* A 7 x 7 grid of junctions and its streets, each with one bend. */
static char *grid_text(size_t *len)
{
    char *text = NULL;
    FILE *f = open_memstream(&text, len);
    fputs("pfc 1\n", f);
    for (int j = 0; j < 7; j++)
        for (int i = 0; i < 7; i++)
            fprintf(f, "v %d %d\n", 100 * i + (j % 3), 100 * j + (i % 2));
    for (int j = 0; j < 7; j++)
        for (int i = 0; i < 7; i++) {
            if (i + 1 < 7)
                fprintf(f, "e %d %d %d %d\n", 7 * j + i, 7 * j + i + 1, 100 * i + 50, 100 * j + 20);
            if (j + 1 < 7)
                fprintf(f, "e %d %d %d %d\n", 7 * j + i, 7 * (j + 1) + i, 100 * i + 20, 100 * j + 50);
        }
    fclose(f);
    return text;
}

/* DIR/name copied to path. */
static void copy_file(const char *name, const char *path)
{
    char from[128];
    snprintf(from, sizeof from, "%s/%s", dir, name);
    FILE *in = fopen(from, "rb"), *out = fopen(path, "wb");
    FUZZ_CHECK(in && out);
    for (int c; (c = fgetc(in)) != EOF;)
        fputc(c, out);
    fclose(in);
    FUZZ_CHECK(fclose(out) == 0);
}

/* The directory and what the builds left in it, at exit. */
static void clean_up(void)
{
    char path[128];
    const char *names[] = {"graph", "route-0"};
    for (size_t k = 0; k < 2; k++) {
        snprintf(path, sizeof path, "%s/%s", dir, names[k]);
        unlink(path);
    }
    for (uint32_t k = 0; k < plan.parts; k++) {
        snprintf(path, sizeof path, "%s/part-%u.part", dir, k);
        unlink(path);
    }
    rmdir(dir);
}

static void set_up(void)
{
    snprintf(dir, sizeof dir, "/tmp/hpfc-fuzz-route-XXXXXX");
    FUZZ_CHECK(mkdtemp(dir) != NULL);
    size_t len, size, chunks;
    char *text = grid_text(&len);
    uint8_t *bytes;
    hpfc_diag d;
    FUZZ_CHECK(pfc_chunked_bytes(text, len, 3, &bytes, &size, &chunks, &d) == HPFC_OK);
    char path[128];
    snprintf(path, sizeof path, "%s/graph", dir);
    FILE *f = fopen(path, "wb");
    FUZZ_CHECK(f && fwrite(bytes, 1, size, f) == size && fclose(f) == 0);
    hpfc_graph *g = NULL;
    FUZZ_CHECK(hpfc_graph_map_file(path, &g, &d) == HPFC_OK);
    hpfc_build_params p;
    hpfc_build_params_default(&p);
    p.root_cols = p.root_rows = 6;
    FUZZ_CHECK(part_dir_plan(g, &p, 4, NULL, &plan, &d) == HPFC_OK);
    /* the genuine route file builds every part (HPFC_FUZZ_SEED=PATH keeps
     * a copy, a seed for the corpus) */
    FUZZ_CHECK(part_dir_route(dir, g, &plan, 0, 0, hpfc_graph_edge_count(g), &d) == HPFC_OK);
    for (uint32_t k = 0; k < plan.parts; k++)
        FUZZ_CHECK(part_dir_build_routed(dir, &plan, k, 1, &d) == HPFC_OK);
    const char *seed = getenv("HPFC_FUZZ_SEED");
    if (seed)
        copy_file("route-0", seed);
    atexit(clean_up);
    hpfc_graph_free(g);
    free(bytes);
    free(text);
}

static bool routed_status(int st)
{
    return st == HPFC_OK || st == HPFC_E_CORRUPT || st == HPFC_E_IO || st == HPFC_E_NOMEM ||
           st == HPFC_E_ARG || (st >= HPFC_E_DUPLICATE_POINT && st <= HPFC_E_EMPTY) ||
           st == HPFC_E_LIMIT;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (!dir[0])
        set_up();
    if (size < 1)
        return 0;
    char path[128];
    snprintf(path, sizeof path, "%s/route-0", dir);
    FILE *f = fopen(path, "wb");
    FUZZ_CHECK(f != NULL);
    FUZZ_CHECK(fwrite(data + 1, 1, size - 1, f) == size - 1 && fclose(f) == 0);
    hpfc_diag d;
    int st = part_dir_build_routed(dir, &plan, data[0] % plan.parts, 1, &d);
    FUZZ_CHECK(routed_status(st));
    FUZZ_CHECK(st == HPFC_OK || d.message[0]);
    return 0;
}
