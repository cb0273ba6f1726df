/*
 * hpfc-inspect: shows, checks and exports an .hpfc file (interfaces §3).
 *
 *   hpfc-inspect FILE                       summary and per-level table
 *   hpfc-inspect --json FILE                the same as one JSON object
 *   hpfc-inspect --verify [--json] FILE     full structural and topological check
 *   hpfc-inspect --export-graph OUT FILE    the map as hpfc-graph JSON
 *   hpfc-inspect --export OUT [-f DRIVER] FILE        the features through GDAL (interfaces §5)
 *   hpfc-inspect --export-faces OUT [-f DRIVER] FILE  the faces through GDAL
 *   hpfc-inspect --sections FILE            the file's map, with checksum status
 *   hpfc-inspect --pixel PATH FILE          one pixel taken apart
 *   hpfc-inspect --locate X,Y FILE          the leaf and faces at a point (interfaces §4)
 *   hpfc-inspect --stats FILE               histograms of words, depths, stabbings
 *   hpfc-inspect --render OUT.svg|OUT.png FILE   a picture of the grid and the graph
 *
 * The summary shows only what hpfc_open() validates: opening checks the
 * header, the level table and the section directory without decoding the
 * pools, so it runs in O(levels + sections) on any file size. --verify
 * decodes everything (verify.c); --export-graph walks the map with the
 * library's operators (export.c). The queries live in views.c and render.c.
 * Every mode reads FILE through open_input.c, once: '-' and pipes work too.
 * Exit status: 0 success (for --verify: the file is valid), 1 when FILE
 * cannot be opened, is invalid, a query fails (no such pixel, a checksum that
 * --sections finds wrong) or OUT cannot be written ("hpfc-inspect: FILE:
 * <reason>"), 2 for a usage error. Every query takes --json.
 */
#include <errno.h>
#include <fcntl.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "atomic_output.h"
#include "export.h"
#include "export_gis.h"
#include "hpfc.h"
#include "jsonw.h"
#include "locate.h"
#include "open_input.h"
#include "paths.h"
#include "queries.h"
#include "render.h"
#include "verify.h"
#include "views.h"

enum { EXIT_FAIL = 1, EXIT_USAGE = 2 };

/* The options with a value that the queries of views.c and render.c take. */
enum {
    V_PIXEL, V_LOCATE, V_LOCATE_LONLAT, V_LOCATE_BATCH, V_RENDER, V_WINDOW, V_SIZE,
    V_WINDOW_LONLAT, V_LON_COL, V_LAT_COL, V_ID_COL, V_FORMAT, V_EXPORT, V_EXPORT_FACES,
    V_DRIVER, V_COUNT
};
static const char *const value_names[V_COUNT] = {
    "--pixel", "--locate", "--locate-lonlat", "--locate-batch", "--render", "--window", "--size",
    "--window-lonlat", "--lon-col", "--lat-col", "--id-col", "--format", "--export",
    "--export-faces", "-f"};

typedef struct inspect_args {
    const char *file;
    int json;
    int verify;
    int force;              /* --force, -overwrite: replace an existing OUT */
    const char *graph_out;  /* --export-graph OUT */
    int sections, stats;
    int lonlat;             /* --lonlat: --locate-batch reads lon,lat */
    const char *values[V_COUNT];
    pixel_path path;        /* --pixel, parsed */
    decimal point[2];       /* --locate or --locate-lonlat, parsed */
    render_params render;   /* --render, --window, --size, parsed */
    batch_options batch;    /* --locate-batch's --lonlat, --*-col, --format */
    topo_args topo;         /* the topology queries (queries.c) */
} inspect_args;

/* Everything shown, read once so that the printers cannot fail. */
typedef struct summary {
    hpfc_file_info info;
    hpfc_level_info levels[HPFC_MAX_LEVELS];
    hpfc_section_info *sections;    /* info.section_count entries */
    uint64_t word_pixels, refined_pixels;
    int has_geometry;               /* a GEOM section opens */
} summary;

static void print_help(void)
{
    printf("usage: hpfc-inspect [--json] FILE\n"
           "       hpfc-inspect --verify [--json] FILE\n"
           "       hpfc-inspect --export-graph OUT.json [--json] FILE\n"
           "       hpfc-inspect --export OUT | --export-faces OUT [-f DRIVER] [--json] FILE\n"
           "       hpfc-inspect --sections | --stats [--json] FILE\n"
           "       hpfc-inspect --pixel PATH | --locate X,Y | --locate-lonlat LON,LAT [--json] FILE\n"
           "       hpfc-inspect --locate-batch POINTS [--lonlat] [--lon-col C] [--lat-col C]\n"
           "                    [--id-col C] [--format jsonl|csv|geojson] FILE\n"
           "       hpfc-inspect --render OUT.svg|OUT.png [--window X0,Y0,X1,Y1 |\n"
           "                    --window-lonlat LON0,LAT0,LON1,LAT1] [--size W[xH]] [--json] FILE\n"
           "       hpfc-inspect --window X0,Y0,X1,Y1 | --window-lonlat W,S,E,N [--json] FILE\n"
           "       hpfc-inspect --neighbours KEY|FID [--json] FILE\n"
           "       hpfc-inspect --nearest X,Y | --nearest-lonlat LON,LAT [--within D] [--json] FILE\n"
           "       hpfc-inspect --dissolve FIELD | --dissolve-features KEY|FID,...\n"
           "                    | --mesh [interior|exterior|all|FIELD]\n"
           "                    [--export OUT [-f DRIVER]] [--json] FILE\n"
           "\n"
           "Shows the header, the section directory and the per-level table of an\n"
           ".hpfc file; or checks it; or exports the planar map it encodes; or\n"
           "answers one query about it (one query a run). In every mode FILE '-' is\n"
           "standard input, and FILE may be a pipe or a FIFO (read into memory).\n"
           "\n"
           "options:\n"
           "  --json                 print one JSON object instead of text (every query)\n"
           "  --verify               full check: section checksums, every pixel of\n"
           "                         every level (decoding, word grammar, image layout,\n"
           "                         level counts, zero padding), both sides of every\n"
           "                         road, and the map the traversal operators rebuild\n"
           "                         (twin, next, prev, origin, target, faces, Euler)\n"
           "  --export-graph OUT     write the map as hpfc-graph JSON to OUT (atomic:\n"
           "                         no partial OUT on failure; - for standard output,\n"
           "                         the summary then on standard error)\n"
           );
    printf(
           "  --export OUT           write every feature as its exact (multi)polygon (the\n"
           "                         union of its faces) or (multi)line string, with its\n"
           "                         fid, key and stored attributes, one layer per source\n"
           "                         layer, in the source SRS (projected back to lon/lat\n"
           "                         when hpfc-pack projected it), through GDAL; atomic\n"
           "  --export-faces OUT     the same for the bounded faces: face id, and the fids\n"
           "                         and keys of their features\n"
           "  -f DRIVER              with --export*: the GDAL driver (ogr2ogr's names:\n"
           "                         GPKG, GeoJSON, FlatGeobuf, \"ESRI Shapefile\", ...);\n"
           "                         default: from OUT's extension\n"
           "  --force, -overwrite    replace an existing OUT (--export*, --render);\n"
           "                         without it an existing OUT is refused\n"
           "  --sections             the file's map: header, level table, directory, every\n"
           "                         section with offset, length and stored / computed\n"
           "                         CRC-32C, each level's pool with its bits, k_w, k_@\n"
           "  --pixel PATH           one pixel by its path from the root, i,j per level\n"
           "                         joined by '/' (i = column from the west, j = row\n"
           "                         from the north): type, word and code bits, crossings\n"
           "                         per road, components, vertices, bounds, neighbours\n"
           "  --locate X,Y           the leaf holding point X,Y (input coordinates): path,\n"
           "                         depth, word, and its faces: the one face of a private\n"
           "                         leaf, else every face that meets the leaf; and the\n"
           "                         source features of those faces (files packed from\n"
           "                         GIS polygons: id, layer, --key value)\n"
           "  --locate-lonlat LON,LAT the same for a point in degrees, placed with the\n"
           "                         projection the file's CRS records\n"
           "  --locate-batch POINTS  many points, one a line of a table (POINTS '-' is\n"
           "                         standard input): comma, tab, semicolon or blank\n"
           "                         separated, CSV quotes, an optional header line;\n"
           "                         blank and '#' lines skipped. One answer a data\n"
           "                         line, in input order, with its \"line\" number and\n"
           "                         \"id\"; a bad line is an error row (\"error\": why)\n"
           "                         and the run goes on; other columns are passed\n"
           "                         through. The faces are numbered once for all\n"
           "  --lonlat               with --locate-batch: the points are lon,lat degrees\n"
           "                         (also when the columns are named lon/lng/longitude\n"
           "                         and lat/latitude)\n"
           "  --lon-col C, --lat-col C\n"
           "                         with --locate-batch: the coordinate columns, by\n"
           "                         header name (any case) or number from 1 (default:\n"
           "                         named lon, lng, long, longitude, x, easting and\n"
           "                         lat, latitude, y, northing; else the first two)\n"
           "  --id-col C             with --locate-batch: the column copied to \"id\"\n"
           "                         (default: one named id)\n"
           "  --format F             with --locate-batch: jsonl (default, one JSON object\n"
           "                         a line), csv (a header, faces/fids/keys as lists) or\n"
           "                         geojson (a FeatureCollection of the points, the\n"
           "                         answers as properties)\n"
           );
    printf(
           "  --stats                histograms of word length, leaf depth, crossings per\n"
           "                         pixel and stabbings per edge (pixels an edge passes\n"
           "                         without a vertex)\n"
           "  --render OUT           draw the map into OUT.svg, or OUT.png when built with\n"
           "                         cairo: faces filled by feature (a categorical\n"
           "                         palette, the outside white; by face without GIS\n"
           "                         features), edges through their crossings, the grid's\n"
           "                         leaves outlined. The window fits the data. The SVG's\n"
           "                         coordinates are the file's user coordinates; a PNG\n"
           "                         gets a world file (OUT.pgw) to place it on a map\n"
           "  --window X0,Y0,X1,Y1   with --render: the window in user coordinates\n"
           "  --window-lonlat LON0,LAT0,LON1,LAT1\n"
           "                         with --render: the window in degrees, projected\n"
           "                         with the file's CRS\n"
           "  --size W[xH]           with --render: image size in pixels (default 1024 on\n"
           "                         the longer side; W alone keeps the window's aspect)\n"
           "  --window X0,Y0,X1,Y1   without --render: the features, faces and edges that\n"
           "                         meet the closed rectangle, each inside or crossing\n"
           "  --neighbours KEY|FID   the features whose border shares an edge (with the\n"
           "                         shared length, metres when the CRS says) or only a\n"
           "                         vertex with the feature's\n"
           "  --nearest X,Y          the nearest edge: closest point, distance, the\n"
           "                         features on its sides; --within D lists every edge\n"
           "                         within D user units. --nearest-lonlat LON,LAT\n"
           "  --dissolve FIELD       the features merged by FIELD's value: exact polygons\n"
           "                         (with --export OUT: a layer 'dissolved' through GDAL)\n"
           "  --dissolve-features KEY|FID,...\n"
           "                         the listed features merged into one exact polygon\n"
           "                         (each a key or a fid, as --neighbours takes it)\n"
           "  --mesh [K]             the borders as lines: interior (default: between\n"
           "                         features), exterior (the outline), all, or FIELD\n"
           "                         (between different values); --export OUT: layer 'mesh'\n"
           "  -h, --help             show this help\n"
           "  --version              show the version\n"
           "\n"
           );
    printf(
           "examples:\n"
           "  hpfc-inspect --sections map.hpfc\n"
           "  hpfc-inspect --pixel 3,5/1,0/0,1 map.hpfc\n"
           "  hpfc-inspect --locate 1.5,-2.25 --json map.hpfc\n"
           "  hpfc-inspect --locate-lonlat -97.74,30.27 --json counties.hpfc\n"
           "  hpfc-inspect --locate-batch points.txt --lonlat counties.hpfc\n"
           "  hpfc-inspect --locate-batch cities.csv --id-col name --format csv counties.hpfc\n"
           "  hpfc-inspect --stats --json map.hpfc\n"
           "  hpfc-inspect --export countries.gpkg countries.hpfc\n"
           "  hpfc-inspect --export-faces faces.fgb -f FlatGeobuf counties.hpfc\n"
           "  hpfc-inspect --render map.png --window 0,0,500,300 --size 1600x960 map.hpfc\n"
           "  hpfc-inspect --render texas.svg --window-lonlat -107,25,-93,37 counties.hpfc\n"
           "\n"
           "Exit status: 0 success (--verify: the file is valid; --locate: also for a\n"
           "point outside the domain, with no faces), 1 FILE cannot be opened or is\n"
           "invalid, a query fails (--pixel: no such pixel; --sections: a checksum does\n"
           "not match), or OUT cannot be written, 2 usage error (a malformed PATH,\n"
           "point, window or size, or several queries at once).\n");
}

static int usage_error(const char *what, const char *arg)
{
    fprintf(stderr, "hpfc-inspect: %s%s%s (see --help)\n", arg ? arg : "", arg ? ": " : "", what);
    return EXIT_USAGE;
}

/* One of the value options of the queries at argv[*i]: -1 when it is not
 * one, 0 when taken, or the usage exit status. */
static int query_option(int argc, char **argv, int *i, inspect_args *a)
{
    for (int k = 0; k < V_COUNT; k++) {
        int missing = 0, numeric = k == V_LOCATE || k == V_LOCATE_LONLAT || k == V_WINDOW ||
                                   k == V_WINDOW_LONLAT;
        const char *value = numeric ? option_numeric_value(argc, argv, i, value_names[k], &missing)
                                    : option_value(argc, argv, i, value_names[k], &missing);
        if (!value && !missing)
            continue;
        if (missing)
            return usage_error("missing its value", value_names[k]);
        if (a->values[k])
            return usage_error("given twice", value_names[k]);
        a->values[k] = value;
        return 0;
    }
    return -1;
}

/* The topology queries (queries.c): --window without --render is one;
 * --export and -f go with --dissolve, --dissolve-features and --mesh. -2 when
 * there is none. */
static int parse_topology(inspect_args *a)
{
    const char **v = a->values;
    topo_args *t = &a->topo;
    if (!v[V_RENDER] && (v[V_WINDOW] || v[V_WINDOW_LONLAT])) {
        t->window = v[V_WINDOW], t->window_lonlat = v[V_WINDOW_LONLAT];
        v[V_WINDOW] = v[V_WINDOW_LONLAT] = NULL;
    }
    if (!topo_count(t)) {
        if (t->within)
            return usage_error("only with --nearest or --nearest-lonlat", "--within");
        return -2;
    }
    for (int k = 0; k < V_COUNT; k++)
        if (v[k] && k != V_EXPORT && k != V_DRIVER)
            return usage_error("not with a topology query", value_names[k]);
    if (a->verify || a->graph_out || a->sections || a->stats || a->lonlat)
        return usage_error("use one query at a time", NULL);
    t->export_out = v[V_EXPORT], t->driver = v[V_DRIVER], t->json = a->json;
    if (t->driver && !t->export_out)
        return usage_error("only with --export", "-f");
    return topo_check(t);
}

/* Checks and converts the queries' values; -1 to go on, or EXIT_USAGE. */
static int parse_queries(inspect_args *a)
{
    char why[VIEW_WHY];
    const char **v = a->values;
    int status = parse_topology(a);
    if (status != -2)
        return status;
    int queries = a->verify + !!a->graph_out + a->sections + a->stats + !!v[V_PIXEL] +
                  !!v[V_LOCATE] + !!v[V_LOCATE_LONLAT] + !!v[V_LOCATE_BATCH] + !!v[V_RENDER] +
                  !!v[V_EXPORT] + !!v[V_EXPORT_FACES];
    if (queries > 1)
        return usage_error("use one of --verify, --export-graph, --export, --export-faces, "
                           "--sections, --stats, --pixel, --locate, --locate-lonlat, "
                           "--locate-batch and --render", NULL);
    if (v[V_DRIVER] && !v[V_EXPORT] && !v[V_EXPORT_FACES])
        return usage_error("only with --export or --export-faces", "-f");
    for (int k = V_EXPORT; k <= V_DRIVER; k++)
        if (v[k] && !v[k][0])
            return usage_error("empty value", value_names[k]);
    if (a->lonlat && !v[V_LOCATE_BATCH])
        return usage_error("only with --locate-batch", "--lonlat");
    for (int k = V_LON_COL; k <= V_FORMAT; k++)
        if (v[k] && !v[V_LOCATE_BATCH])
            return usage_error("only with --locate-batch", value_names[k]);
    if (v[V_LOCATE_BATCH] && strcmp(v[V_LOCATE_BATCH], "-") == 0 && strcmp(a->file, "-") == 0)
        return usage_error("POINTS and FILE cannot both be standard input", "--locate-batch");
    if (v[V_LOCATE_BATCH] && a->json)
        return usage_error("--locate-batch prints JSON lines, or --format csv|geojson", "--json");
    if ((v[V_WINDOW] || v[V_SIZE] || v[V_WINDOW_LONLAT]) && !v[V_RENDER])
        return usage_error("only with --render", v[V_WINDOW]   ? "--window"
                                                 : v[V_SIZE] ? "--size"
                                                             : "--window-lonlat");
    batch_options *b = &a->batch;
    b->lonlat = a->lonlat;
    b->lon_col = v[V_LON_COL], b->lat_col = v[V_LAT_COL], b->id_col = v[V_ID_COL];
    for (int k = V_LON_COL; k <= V_ID_COL; k++)
        if (v[k] && !v[k][0])
            return usage_error("a column name or number", value_names[k]);
    if (v[V_FORMAT]) {
        if (strcmp(v[V_FORMAT], "jsonl") == 0 || strcmp(v[V_FORMAT], "json") == 0)
            b->format = BATCH_JSONL;
        else if (strcmp(v[V_FORMAT], "csv") == 0)
            b->format = BATCH_CSV;
        else if (strcmp(v[V_FORMAT], "geojson") == 0)
            b->format = BATCH_GEOJSON;
        else
            return usage_error("expected jsonl, csv or geojson", "--format");
    }
    if (v[V_PIXEL] && pixel_path_parse(v[V_PIXEL], &a->path, why, sizeof why))
        return usage_error(why, "--pixel");
    if (v[V_LOCATE] && decimal_list_parse(v[V_LOCATE], a->point, 2))
        return usage_error("expected X,Y: two decimal numbers", "--locate");
    if (v[V_LOCATE_LONLAT] && decimal_list_parse(v[V_LOCATE_LONLAT], a->point, 2))
        return usage_error("expected LON,LAT: two decimal numbers", "--locate-lonlat");
    if (!v[V_RENDER])
        return -1;
    render_params *r = &a->render;
    r->output = v[V_RENDER];
    if (!(r->format = render_format_of(r->output)))
        return usage_error("OUT must end in .svg or .png", "--render");
    if (v[V_WINDOW] && render_window_parse(v[V_WINDOW], r->window))
        return usage_error("expected X0,Y0,X1,Y1 with X0 < X1 and Y0 < Y1", "--window");
    r->have_window = v[V_WINDOW] != NULL;
    if (v[V_WINDOW] && v[V_WINDOW_LONLAT])
        return usage_error("use one of --window and --window-lonlat", NULL);
    if (v[V_WINDOW_LONLAT] && render_window_parse(v[V_WINDOW_LONLAT], r->window_lonlat))
        return usage_error("expected LON0,LAT0,LON1,LAT1 with LON0 < LON1 and LAT0 < LAT1",
                           "--window-lonlat");
    r->have_window_lonlat = v[V_WINDOW_LONLAT] != NULL;
    if (v[V_SIZE] && render_size_parse(v[V_SIZE], &r->width, &r->height))
        return usage_error("expected W or WxH, from 1 to 16384", "--size");
    return -1;
}

/* Returns -1 to go on, or the exit status (0 after --help / --version). */
static int parse_args(int argc, char **argv, inspect_args *a)
{
    int only_files = 0;
    memset(a, 0, sizeof *a);
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i], *value;
        int missing = 0, status;
        if (only_files || arg[0] != '-' || strcmp(arg, "-") == 0) {
            if (a->file)
                return usage_error("more than one FILE", arg);
            a->file = arg;
            continue;
        }
        if (strcmp(arg, "--") == 0)
            only_files = 1;
        else if (strcmp(arg, "-h") == 0 || strcmp(arg, "--help") == 0) {
            print_help();
            return 0;
        } else if (strcmp(arg, "--version") == 0) {
            printf("hpfc-inspect %s\n", hpfc_version_string());
            return 0;
        } else if (strcmp(arg, "--json") == 0) {
            a->json = 1;
        } else if (strcmp(arg, "--verify") == 0) {
            a->verify = 1;
        } else if (strcmp(arg, "--force") == 0 || strcmp(arg, "-overwrite") == 0) {
            a->force = 1;
        } else if (strcmp(arg, "--sections") == 0) {
            a->sections = 1;
        } else if (strcmp(arg, "--stats") == 0) {
            a->stats = 1;
        } else if (strcmp(arg, "--lonlat") == 0) {
            a->lonlat = 1;
        } else if ((status = topo_option(argc, argv, &i, &a->topo)) >= 0) {
            if (status)
                return status;
        } else if ((status = query_option(argc, argv, &i, a)) >= 0) {
            if (status)
                return status;
        } else if ((value = option_value(argc, argv, &i, "--export-graph", &missing)) || missing) {
            if (missing)
                return usage_error("missing OUT", "--export-graph");
            if (a->graph_out)
                return usage_error("given twice", "--export-graph");
            if (*value == '\0')
                return usage_error("empty OUT", "--export-graph");
            a->graph_out = value;
        } else {
            return usage_error("unknown option", arg);
        }
    }
    if (!a->file)
        return usage_error("missing FILE", NULL);
    if (a->verify && a->graph_out)
        return usage_error("use one of --verify and --export-graph", NULL);
    return parse_queries(a);
}

/* Reads the header, levels and sections; HPFC_OK or the first failure. */
static int read_summary(const hpfc_file *f, summary *s)
{
    hpfc_file_get_info(f, &s->info);
    if (s->info.levels > HPFC_MAX_LEVELS)
        return HPFC_E_LEVEL_TABLE;
    for (uint32_t l = 0; l < s->info.levels; l++) {
        int st = hpfc_file_get_level(f, l, &s->levels[l]);
        if (st)
            return st;
        s->word_pixels += s->levels[l].word_pixels;
        s->refined_pixels += s->levels[l].refined_pixels;
    }
    hpfc_geometry_info gi;
    s->has_geometry = hpfc_file_get_geometry(f, &gi) == HPFC_OK;
    s->sections = calloc(s->info.section_count ? s->info.section_count : 1, sizeof *s->sections);
    if (!s->sections)
        return HPFC_E_NOMEM;
    for (uint32_t k = 0; k < s->info.section_count; k++) {
        int st = hpfc_file_get_section(f, k, &s->sections[k]);
        if (st)
            return st;
    }
    return HPFC_OK;
}

/* ---- the lattice unit: the resolution stated ------------------------------------ */

/* What one lattice unit is: 10^unit_exp10 user units, and in metres when
 * the CRS section's description names its unit (+units=, +to_meter=, or
 * degrees of a longlat CRS: then metres along the equator). *metres is 0
 * when unknown; *how says which. Every coordinate of the file is a lattice
 * point, so this is the finest and the coarsest step of its geometry. */
static void lattice_unit(const hpfc_file_info *fi, double *user, double *metres,
                         const char **how)
{
    double u = 1.0;
    for (int32_t k = 0; k < (fi->unit_exp10 < 0 ? -fi->unit_exp10 : fi->unit_exp10); k++)
        u *= 10.0;
    *user = fi->unit_exp10 < 0 ? 1.0 / u : u;
    *metres = 0.0;
    *how = "unknown: the file records no CRS";
    if (!fi->crs)
        return;
    *how = "unknown: the CRS does not name its unit";
    char desc[512];
    size_t n = 0;
    while (n < fi->crs_len && n < sizeof desc - 1 && fi->crs[n] != ';')
        n++;
    memcpy(desc, fi->crs, n);
    desc[n] = '\0';
    const char *to_meter = strstr(desc, "+to_meter=");
    if (strstr(desc, "+proj=longlat") || strstr(desc, "+proj=latlong")) {
        *metres = *user * 6378137.0 * 3.14159265358979323846 / 180.0;
        *how = "degrees: metres along the equator";
    } else if (strstr(desc, "+units=m ") || (n >= 8 && strcmp(desc + n - 8, "+units=m") == 0)) {
        *metres = *user;
        *how = "metres of the projected plane";
    } else if (strstr(desc, "+units=km")) {
        *metres = *user * 1000.0;
        *how = "kilometres of the projected plane";
    } else if (strstr(desc, "+units=us-ft")) {
        *metres = *user * 1200.0 / 3937.0;
        *how = "US survey feet of the projected plane";
    } else if (strstr(desc, "+units=ft")) {
        *metres = *user * 0.3048;
        *how = "feet of the projected plane";
    } else if (to_meter) {
        *metres = *user * strtod(to_meter + 10, NULL);
        *how = "+to_meter of the projected plane";
    }
}

static void print_json(const char *path, const summary *s)
{
    const hpfc_file_info *fi = &s->info;
    char version[32];
    snprintf(version, sizeof version, "%u.%u", fi->format_major, fi->format_minor);
    jsonw w;
    jsonw_init(&w, stdout);
    jsonw_object_begin(&w, NULL);
    jsonw_string(&w, "file", path);
    jsonw_string(&w, "format", "hpfc");
    jsonw_string(&w, "format_version", version);
    jsonw_u64(&w, "format_major", fi->format_major);
    jsonw_u64(&w, "format_minor", fi->format_minor);
    jsonw_u64(&w, "compat_flags", fi->compat_flags);
    jsonw_u64(&w, "incompat_flags", fi->incompat_flags);
    jsonw_u64(&w, "root_cols", fi->root_cols);
    jsonw_u64(&w, "root_rows", fi->root_rows);
    jsonw_u64(&w, "refine_cols", fi->cols);
    jsonw_u64(&w, "refine_rows", fi->rows);
    jsonw_u64(&w, "depth", fi->levels ? fi->levels - 1 : 0);
    jsonw_u64(&w, "level_count", fi->levels);
    jsonw_object_begin(&w, "domain");
    jsonw_i64(&w, "x0", fi->x0);
    jsonw_i64(&w, "y0", fi->y0);
    jsonw_i64(&w, "width", fi->width);
    jsonw_i64(&w, "height", fi->height);
    jsonw_object_end(&w);
    jsonw_i64(&w, "unit_exp10", fi->unit_exp10);
    double user, metres;
    const char *how;
    lattice_unit(fi, &user, &metres, &how);
    jsonw_object_begin(&w, "lattice_unit");
    jsonw_real(&w, "user", user);
    if (metres > 0)
        jsonw_real(&w, "metres", metres);
    else
        jsonw_null(&w, "metres");
    jsonw_string(&w, "metres_are", how);
    jsonw_object_end(&w);
    jsonw_bool(&w, "exact_geometry", s->has_geometry);
    if (fi->crs)
        jsonw_string_n(&w, "crs", fi->crs, fi->crs_len);
    else
        jsonw_null(&w, "crs");
    jsonw_u64(&w, "file_bytes", fi->file_size);
    jsonw_u64(&w, "word_pixels", s->word_pixels);
    jsonw_u64(&w, "refined_pixels", s->refined_pixels);
    jsonw_u64(&w, "total_pixels", s->word_pixels + s->refined_pixels);
    jsonw_array_begin(&w, "sections");
    for (uint32_t k = 0; k < fi->section_count; k++) {
        const hpfc_section_info *sec = &s->sections[k];
        jsonw_object_begin(&w, NULL);
        jsonw_string_n(&w, "tag", sec->tag, strnlen(sec->tag, 4));
        jsonw_u64(&w, "flags", sec->flags);
        jsonw_u64(&w, "offset", sec->offset);
        jsonw_u64(&w, "length", sec->length);
        jsonw_u64(&w, "crc32c", sec->crc32c);
        jsonw_object_end(&w);
    }
    jsonw_array_end(&w);
    /* --sections --json lists the levels too, with the byte positions it
     * shows instead of the cell sizes: two documents, each with its own
     * fields, so written apart. */
    jsonw_array_begin(&w, "levels");
    for (uint32_t l = 0; l < fi->levels; l++) {
        const hpfc_level_info *lv = &s->levels[l];
        jsonw_object_begin(&w, NULL);
        jsonw_u64(&w, "level", l);
        jsonw_u64(&w, "images", lv->images);
        jsonw_u64(&w, "word_pixels", lv->word_pixels);
        jsonw_u64(&w, "refined_pixels", lv->refined_pixels);
        jsonw_u64(&w, "word_bits", lv->word_bits);
        jsonw_u64(&w, "address_bits", lv->address_bits);
        jsonw_u64(&w, "pool_offset", lv->pool_offset);
        jsonw_u64(&w, "pool_bits", lv->pool_bits);
        jsonw_i64(&w, "cell_w", lv->cell_w);
        jsonw_i64(&w, "cell_h", lv->cell_h);
        jsonw_object_end(&w);
    }
    jsonw_array_end(&w);
    jsonw_object_end(&w);
    jsonw_finish(&w);
}

/* Text from the file, with control characters shown as '?': the file is
 * untrusted and must not drive the terminal. */
static void put_printable(const char *s, size_t len)
{
    for (size_t k = 0; k < len; k++)
        putchar((unsigned char)s[k] < 0x20 || s[k] == 0x7F ? '?' : s[k]);
}

/* A section tag as printable text (a corrupt-looking tag must not garble
 * the terminal). */
static void printable_tag(const char *tag, char out[5])
{
    for (int k = 0; k < 4; k++)
        out[k] = tag[k] >= 0x20 && tag[k] < 0x7F ? tag[k] : '?';
    out[4] = '\0';
}

static void print_text(const char *path, const summary *s)
{
    const hpfc_file_info *fi = &s->info;
    printf("file       %s (%llu bytes)\n", path, (unsigned long long)fi->file_size);
    printf("format     hpfc %u.%u, compat flags 0x%x, incompat flags 0x%x\n", fi->format_major,
           fi->format_minor, fi->compat_flags, fi->incompat_flags);
    printf("images     root %ux%u, refined %ux%u\n", fi->root_cols, fi->root_rows, fi->cols,
           fi->rows);
    printf("depth      %u (%u level%s)\n", fi->levels ? fi->levels - 1 : 0, fi->levels,
           fi->levels == 1 ? "" : "s");
    printf("domain     x0 %lld, y0 %lld, %lld x %lld lattice units of 10^%d\n",
           (long long)fi->x0, (long long)fi->y0, (long long)fi->width, (long long)fi->height,
           fi->unit_exp10);
    printf("crs        ");
    if (fi->crs)
        put_printable(fi->crs, fi->crs_len);
    else
        printf("none");
    printf("\n");
    double user, metres;
    const char *how;
    lattice_unit(fi, &user, &metres, &how);
    printf("unit       1 lattice unit = %g user units", user);
    if (metres > 0)
        printf(" = %.6g m (%s)\n", metres, how);
    else
        printf(" (metres %s)\n", how);
    printf("geometry   %s\n", s->has_geometry
                                  ? "exact (GEOM section): every vertex and shape point is a "
                                    "lattice point"
                                  : "none: each vertex is known to its leaf pixel only");
    printf("pixels     %llu (%llu word, %llu refined)\n",
           (unsigned long long)(s->word_pixels + s->refined_pixels),
           (unsigned long long)s->word_pixels, (unsigned long long)s->refined_pixels);

    printf("\n%-4s %12s %12s %10s %6s\n", "tag", "offset", "length", "crc32c", "flags");
    for (uint32_t k = 0; k < fi->section_count; k++) {
        const hpfc_section_info *sec = &s->sections[k];
        char tag[5];
        printable_tag(sec->tag, tag);
        printf("%-4s %12llu %12llu 0x%08x 0x%04x\n", tag, (unsigned long long)sec->offset,
               (unsigned long long)sec->length, sec->crc32c, sec->flags);
    }

    printf("\n%5s %10s %12s %12s %5s %5s %12s %14s %12s\n", "level", "images", "word",
           "refined", "k_w", "k_@", "pool offset", "pool bits", "cell");
    for (uint32_t l = 0; l < fi->levels; l++) {
        const hpfc_level_info *lv = &s->levels[l];
        char cell[48];
        snprintf(cell, sizeof cell, "%lldx%lld", (long long)lv->cell_w, (long long)lv->cell_h);
        printf("%5u %10llu %12llu %12llu %5u %5u %12llu %14llu %12s\n", l,
               (unsigned long long)lv->images, (unsigned long long)lv->word_pixels,
               (unsigned long long)lv->refined_pixels, lv->word_bits, lv->address_bits,
               (unsigned long long)lv->pool_offset, (unsigned long long)lv->pool_bits, cell);
    }
}

/* One line naming FILE and the reason; for an I/O failure the system's
 * reason as every tool says it ("No such file or directory"). */
static int open_error(const char *path, int st, int err)
{
    struct stat sb;
    if (st == HPFC_E_IO && !err && stat(input_path(path), &sb) == 0 && S_ISDIR(sb.st_mode))
        err = EISDIR; /* the map fails, not the open */
    if (st == HPFC_E_IO && err)
        fprintf(stderr, "hpfc-inspect: %s: %s\n", path, strerror(err));
    else
        fprintf(stderr, "hpfc-inspect: %s: %s\n", path, hpfc_strerror(st));
    return EXIT_FAIL;
}

/* ---- --verify ------------------------------------------------------------------- */

/* The report on stdout, and when the file is invalid its first problem as
 * the one line on stderr that every failure of the tool prints. */
static int run_verify(const inspect_args *a)
{
    verify_report *r = malloc(sizeof *r); /* ~8 KiB of problem text */
    if (!r) {
        fprintf(stderr, "hpfc-inspect: %s: %s\n", a->file, hpfc_strerror(HPFC_E_NOMEM));
        return EXIT_FAIL;
    }
    int valid = verify_file(a->file, 0, r);
    if (a->json)
        verify_print_json(stdout, a->file, r);
    else
        verify_print_text(stdout, a->file, r);
    if (!valid)
        fprintf(stderr, "hpfc-inspect: %s: %s\n", a->file, r->problems[0]);
    free(r);
    return valid ? 0 : EXIT_FAIL;
}

/* ---- --export-graph ------------------------------------------------------------ */

/* Writes OUT through common/atomic_output.h (no partial OUT, an existing
 * OUT untouched on failure). Returns 0 or EXIT_FAIL after printing the
 * reason. */
static int write_graph(const char *out, const hpfc_file *f, const exported_map *m)
{
    if (strcmp(out, "-") == 0) { /* standard output: written as it goes */
        errno = 0;
        if (export_map_json(f, m, stdout) != HPFC_OK || fflush(stdout) != 0) {
            fprintf(stderr, "hpfc-inspect: standard output: cannot write: %s\n",
                    strerror(errno ? errno : EIO));
            return EXIT_FAIL;
        }
        return 0;
    }
    char why[ATOMIC_WHY];
    atomic_output o;
    if (atomic_output_open(&o, out, why)) {
        fprintf(stderr, "hpfc-inspect: %s\n", why);
        return EXIT_FAIL;
    }
    FILE *fp = atomic_output_stream(&o);
    errno = 0;
    if (!fp || export_map_json(f, m, fp) != HPFC_OK) {
        int err = errno ? errno : EIO;
        atomic_output_discard(&o);
        fprintf(stderr, "hpfc-inspect: %s: cannot write: %s\n", out, strerror(err));
        return EXIT_FAIL;
    }
    if (atomic_output_commit(&o, why)) {
        fprintf(stderr, "hpfc-inspect: %s\n", why);
        return EXIT_FAIL;
    }
    return 0;
}

/* The summary goes to standard output, or to standard error when the
 * graph itself does (OUT "-"). */
static void print_export_summary(const inspect_args *a, const exported_map *m)
{
    FILE *to = strcmp(a->graph_out, "-") == 0 ? stderr : stdout;
    if (a->json) {
        jsonw w;
        jsonw_init(&w, to);
        jsonw_object_begin(&w, NULL);
        jsonw_string(&w, "file", a->file);
        jsonw_string(&w, "output", a->graph_out);
        jsonw_u64(&w, "vertices", m->nv);
        jsonw_u64(&w, "edges", m->nd / 2);
        jsonw_u64(&w, "darts", m->nd);
        jsonw_object_end(&w);
        jsonw_finish(&w);
    } else {
        fprintf(to, "%s: %zu vertices, %zu edges (%zu darts)\n", a->graph_out, m->nv, m->nd / 2,
                m->nd);
    }
}

/* FILE's checksums and structure verify (verify.c): a damaged file must
 * not yield a plausible but wrong graph, and a tree whose images alias one
 * another would make export_map's walks over the tree explode. The check is
 * linear in the file and cheaper than the export. Returns 0 or EXIT_FAIL
 * after printing the first problem. */
static int check_before_export(const char *file, const input_bytes *b)
{
    verify_report *r = malloc(sizeof *r);
    int valid = r && verify_bytes(b, VERIFY_STRUCTURE_ONLY, r);
    if (!valid)
        fprintf(stderr, "hpfc-inspect: %s: %s\n", file,
                r ? r->problems[0] : hpfc_strerror(HPFC_E_NOMEM));
    free(r);
    return valid ? 0 : EXIT_FAIL;
}

/* An existing OUT is replaced only with --force, as hpfc-pack's OUTPUT:
 * 0, or EXIT_FAIL after saying so. Checked before any work. */
static int check_new_output(const inspect_args *a, const char *out)
{
    struct stat st;
    if (a->force || strcmp(out, "-") == 0 || lstat(out, &st) != 0)
        return 0;
    fprintf(stderr, "hpfc-inspect: %s: exists; --force (or -overwrite) replaces it\n", out);
    return EXIT_FAIL;
}

/* The graph of the file open on FILE's bytes. */
static int export_open(const inspect_args *a, hpfc_file *f)
{
    exported_map m;
    int st = export_map(f, &m);
    if (st)
        return open_error(a->file, st, 0);
    int status = write_graph(a->graph_out, f, &m);
    if (!status)
        print_export_summary(a, &m);
    exported_map_free(&m);
    return status;
}

/* The map as the reader rebuilds it, once the file's structure verifies.
 * FILE is read once (it may be a pipe): verified and opened in memory. */
static int run_export(const inspect_args *a)
{
    if (strcmp(a->graph_out, "-") != 0 && same_file(input_path(a->file), a->graph_out))
        return usage_error("OUT is FILE; refusing to overwrite the input", a->graph_out);
    if (check_new_output(a, a->graph_out))
        return EXIT_FAIL;
    input_bytes b;
    int err, st = input_load(a->file, &b, &err);
    int status;
    hpfc_file *f = NULL;
    if (st) {
        status = open_error(a->file, st, err);
    } else if ((status = check_before_export(a->file, &b)) == 0) {
        st = hpfc_open_memory(b.data, b.size, 0, &f);
        status = st ? open_error(a->file, st, 0) : export_open(a, f);
    }
    hpfc_close(f);
    input_unload(&b);
    return status;
}

/* ---- --export, --export-faces (export_gis.c) ---------------------------------- */

static int run_export_gis(const inspect_args *a)
{
    gis_export_options o = {.file = a->file, .driver = a->values[V_DRIVER], .json = a->json};
    o.faces = a->values[V_EXPORT_FACES] != NULL;
    o.output = o.faces ? a->values[V_EXPORT_FACES] : a->values[V_EXPORT];
    if (same_file(input_path(a->file), o.output))
        return usage_error("OUT is FILE; refusing to overwrite the input", o.output);
    if (check_new_output(a, o.output))
        return EXIT_FAIL;
    return export_gis(&o, stdout) ? EXIT_FAIL : 0;
}

/* The topology queries, and --dissolve / --mesh written with --export. */
static int run_topology(const inspect_args *a)
{
    const char *out = a->topo.export_out;
    if (out && same_file(input_path(a->file), out))
        return usage_error("OUT is FILE; refusing to overwrite the input", out);
    if (out && check_new_output(a, out))
        return EXIT_FAIL;
    return topo_run(a->file, &a->topo, stdout) ? EXIT_FAIL : 0;
}

/* ---- queries (views.c, render.c) ---------------------------------------------- */

static int run_render(const inspect_args *a, const hpfc_file *f, char *why)
{
    render_report rep;
    int status = render_file(f, &a->render, &rep, why);
    if (!status)
        render_print_report(stdout, a->json, &a->render, &rep);
    return status ? EXIT_FAIL : 0;
}

/* --locate-batch POINTS ('-': standard input). */
static int run_batch(const inspect_args *a, const hpfc_file *f, char *why)
{
    const char *name = a->values[V_LOCATE_BATCH];
    FILE *in = strcmp(name, "-") == 0 ? stdin : fopen(name, "r");
    if (!in) {
        snprintf(why, VIEW_WHY, "%s: %s", name, strerror(errno));
        return EXIT_FAIL;
    }
    int status = view_locate_batch(f, in, name, &a->batch, stdout, why);
    if (in != stdin)
        fclose(in);
    return status;
}

/* One query on the open file; a failure is one line naming FILE. */
static int run_query(const inspect_args *a)
{
    const char *out = a->values[V_RENDER];
    if (out && same_file(input_path(a->file), out))
        return usage_error("OUT is FILE; refusing to overwrite the input", out);
    if (out && check_new_output(a, out))
        return EXIT_FAIL;
    hpfc_file *f = NULL;
    errno = 0;
    int st = open_input(a->file, &f);
    if (st)
        return open_error(a->file, st, errno);
    char why[VIEW_WHY] = "";
    int status;
    if (a->sections)
        status = view_sections(f, a->file, stdout, a->json, why);
    else if (a->stats)
        status = view_stats(f, stdout, a->json, why);
    else if (a->values[V_PIXEL])
        status = view_pixel(f, &a->path, stdout, a->json, why);
    else if (a->values[V_LOCATE])
        status = view_locate(f, a->point, stdout, a->json, why);
    else if (a->values[V_LOCATE_LONLAT])
        status = view_locate_lonlat(f, a->point, stdout, a->json, why);
    else if (a->values[V_LOCATE_BATCH])
        status = run_batch(a, f, why);
    else
        status = run_render(a, f, why);
    if (status)
        fprintf(stderr, "hpfc-inspect: %s: %s\n", a->file, why);
    hpfc_close(f);
    return status;
}

/* The default mode: the summary that hpfc_open validates. */
static int run_summary(const inspect_args *a)
{
    hpfc_file *f = NULL;
    errno = 0;
    int st = open_input(a->file, &f);
    if (st)
        return open_error(a->file, st, errno);
    summary s = {0};
    int status = 0;
    st = read_summary(f, &s);
    if (st)
        status = open_error(a->file, st, 0);
    else if (a->json)
        print_json(a->file, &s);
    else
        print_text(a->file, &s);
    free(s.sections);
    hpfc_close(f);
    return status;
}

int main(int argc, char **argv)
{
    inspect_args a;
    int status = parse_args(argc, argv, &a);
    if (status >= 0)
        return status;
    if (topo_count(&a.topo))
        status = run_topology(&a);
    else if (a.verify)
        status = run_verify(&a);
    else if (a.graph_out)
        status = run_export(&a);
    else if (a.values[V_EXPORT] || a.values[V_EXPORT_FACES])
        status = run_export_gis(&a);
    else if (a.sections || a.stats || a.values[V_PIXEL] || a.values[V_LOCATE] ||
             a.values[V_LOCATE_LONLAT] || a.values[V_LOCATE_BATCH] || a.values[V_RENDER])
        status = run_query(&a);
    else
        status = run_summary(&a);
    /* A report that did not reach its reader is a failure (a full disk, a
     * closed pipe). */
    if (fflush(stdout) != 0 && status != EXIT_USAGE) {
        fprintf(stderr, "hpfc-inspect: cannot write the output: %s\n", strerror(errno));
        status = EXIT_FAIL;
    }
    return status;
}
