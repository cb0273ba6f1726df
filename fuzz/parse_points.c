/*
 * parse_points: hpfc-inspect's --locate-batch table reader (locate.c) on
 * untrusted text: separators, quotes, headers, column choices, numbers.
 *
 * The map is fixed: a 40-point Delaunay graph of tests/support/gen.h packed once in
 * memory (no CRS, so degrees are refused per row). The input is
 *   byte 0      options: bits 0-1 the format (jsonl, csv, geojson), bit 2
 *               --lonlat, bits 3-4 --lon-col (none, "x", "2", "lon"),
 *               bits 5-6 --lat-col (none, "y", "1", "lat"), bit 7 --id-col
 *               "id";
 *   the rest    the table, as POINTS.
 *
 * Oracle (any failure aborts): the reader returns OK, or FAIL with a
 * one-line reason (a table whose first line names no coordinate columns);
 * never more output lines than data lines (plus the CSV header, or the
 * GeoJSON collection's first and last lines); in jsonl every row is one
 * line starting {"line": with the line numbers increasing; a geojson run
 * that succeeds ends with "]}".
 */
#include "gen.h"
#include "input.h"
#include "locate.h"

static hpfc_file *map_file(void)
{
    static hpfc_file *file;
    static uint8_t *bytes;
    if (file)
        return file;
    hpfc_graph *g = NULL;
    hpfc_tree *t = NULL;
    hpfc_build_params p;
    hpfc_diag diag = {0};
    size_t size = 0;
    hpfc_build_params_default(&p);
    p.root_cols = p.root_rows = 8;
    FUZZ_CHECK(gen_delaunay(7, 40, 1000, 0.2, &g) == HPFC_OK);
    FUZZ_CHECK(hpfc_build(g, &p, &t, &diag) == HPFC_OK);
    FUZZ_CHECK(hpfc_tree_serialize(t, NULL, &bytes, &size, &diag) == HPFC_OK);
    FUZZ_CHECK(hpfc_open_memory(bytes, size, 0, &file) == HPFC_OK);
    hpfc_tree_free(t);
    hpfc_graph_free(g);
    return file;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const char *const lon[] = {NULL, "x", "2", "lon"}, *const lat[] = {NULL, "y", "1", "lat"};
    if (size == 0)
        return 0;
    uint8_t opt = data[0];
    batch_options o = {.format = opt & 3 ? (opt & 3) - 1 : 0,
                       .lonlat = opt >> 2 & 1,
                       .lon_col = lon[opt >> 3 & 3],
                       .lat_col = lat[opt >> 5 & 3],
                       .id_col = opt >> 7 ? "id" : NULL};
    FILE *in = fmemopen((void *)(data + 1), size - 1 ? size - 1 : 1, "r");
    char *text = NULL;
    size_t len = 0;
    FILE *out = open_memstream(&text, &len);
    FUZZ_CHECK(in && out);
    if (size == 1)
        fgetc(in); /* fmemopen needs a size of 1: read it away */
    char why[VIEW_WHY] = "";
    int st = view_locate_batch(map_file(), in, "POINTS", &o, out, why);
    fclose(in);
    FUZZ_CHECK(fclose(out) == 0);
    FUZZ_CHECK(st == VIEW_OK || (st == VIEW_FAIL && why[0] && !strchr(why, '\n')));
    size_t lines = 0, rows = 0;
    for (size_t k = 1; k < size; k++)
        lines += data[k] == '\n';
    lines++;
    long last = 0;
    for (char *p = text; p && *p; p = strchr(p, '\n') ? strchr(p, '\n') + 1 : p + strlen(p)) {
        if (o.format == BATCH_JSONL) {
            long line = -1;
            FUZZ_CHECK(sscanf(p, "{\"line\":%ld,", &line) == 1);
            FUZZ_CHECK(line > last);
            last = line;
        }
        rows++;
    }
    FUZZ_CHECK(rows <= lines + (o.format == BATCH_CSV ? 1 : o.format == BATCH_GEOJSON ? 2 : 0));
    if (st == VIEW_OK && o.format == BATCH_GEOJSON)
        FUZZ_CHECK(len >= 3 && memcmp(text + len - 3, "]}\n", 3) == 0);
    free(text);
    return 0;
}
