/*
 * hpfc-pack: packs a planar map into an .hpfc file and prints the build
 * report (interfaces §2).
 *
 *   hpfc-pack [options] INPUT -o OUTPUT.hpfc
 *
 * Exit status: 0 on success, 1 when the input cannot be read or built or the
 * output cannot be written, 2 for a usage error (an input format this build
 * cannot read counts as one). Every failure is exactly one
 * line "hpfc-pack: <reason>" on standard error, and leaves no OUTPUT behind
 * (an existing OUTPUT is untouched): the library's writer is atomic, and the
 * report is gathered from the serialised bytes before OUTPUT is written.
 */
#include <ctype.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include "atomic_output.h"
#include "clock.h"
#include "cores.h"
#include "draco_input.h"
#include "gis_features.h"
#include "gis_input.h"
#include "hpfc.h"
#include "jsonw.h"
#include "pack_write.h"
#include "paths.h"
#include "progress.h"

enum { EXIT_FAIL = 1, EXIT_USAGE = 2 };
/* --jobs: threads are cheap to ask for and dear to start by the thousand */
#define MAX_JOBS 1024
/* its text in the message, made from the number so the two cannot differ */
#define TEXT_OF(x) #x
#define NUMBER_TEXT(x) TEXT_OF(x)
#define MAX_JOBS_TEXT NUMBER_TEXT(MAX_JOBS)

typedef struct pack_args {
    const char *input, *output;
    hpfc_build_params params;
    int json, quiet;
    int no_labels;            /* --no-labels: no LABL section */
    int no_geometry;          /* --no-geometry: no GEOM section */
    int force;                 /* --force, -overwrite: replace an existing OUTPUT */
    int to_stdout;             /* -o -: the file on standard output, the report on stderr */
    /* GIS input (gis_input.h) */
    const char *layers[64];
    size_t n_layers;
    const char *projection;
    int vertex_model;
    int invalid_mode;
    const char *key_field;
    const char *fields;        /* --fields */
    int dateline;
    const char *assign_srs, *source_srs; /* -a_srs, -s_srs (as ogr2ogr) */
    int layout; /* HPFC_LAYOUT_*: --layout */
    int link_witness; /* --link witness */
    uint32_t partitions; /* --partitions: build in parts, one after another */
    uint32_t jobs;       /* --jobs: that many parts at once, in threads (0: not given) */
    uint64_t memory;     /* --memory: the build's budget in bytes (0: not given) */
    uint32_t threads;    /* --threads: for the steps that share their work (0: not given) */
    const char *parts_dir; /* --parts-dir: the parts built by other processes */
    uint32_t read_ranges;  /* --read-ranges: GIS input read in about N ranges elsewhere */
    int has_range;         /* --read-range: read this range alone into OUTPUT */
    gis_range_plan range;
    const char *range_tag; /* --range-tag: the reading's tag, 16 hex digits */
} pack_args;

/* What the report needs about one level: counts and widths come from the
 * serialised file (what a reader sees), private pixels from the tree. */
typedef struct level_report {
    uint64_t images, word, refined, private_;
    uint32_t word_bits, address_bits;
    uint64_t pool_bits;
} level_report;

typedef struct pack_report {
    hpfc_tree_info tree;
    level_report *levels;      /* tree.levels entries */
    uint64_t file_bytes;
    stage_time read_t, build_t, write_t;
    int gis;                   /* INPUT was read by gis_read_graph() */
    gis_info gis_info;
    int draco;                 /* INPUT was a Draco mesh (draco_input.h) */
    mesh_graph_stats mesh;
    /* GIS polygon features (FEAT section) */
    uint32_t features;
    uint64_t faces_with_features, faces_without_witness;
    uint32_t all_features, edges_with_features;
    uint64_t faces_walked, faces_anchored, faces_checked, link_conflicts;
    int link_witness;
    stage_time link_t[4];
    stage_time features_t;
    uint32_t parts;                     /* the tree's parts (1: built whole) */
    uint64_t memory_held, memory_need;  /* --memory: before the build, the model's peak */
    uint64_t memory_sample_points, memory_sample_pixels; /* --memory: the model's sample */
} pack_report;

/* ---- messages ------------------------------------------------------------ */

/* Prints "hpfc-pack: <message>" as exactly one line: control characters a
 * message might carry from its input are replaced. */
static void complain(const char *fmt, ...)
{
    char msg[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    for (char *c = msg; *c; c++)
        if ((unsigned char)*c < 0x20 || *c == 0x7F)
            *c = '?';
    fprintf(stderr, "hpfc-pack: %s\n", msg);
}

/* The library's explanation of a failure, or the code's name when the
 * function left no message. */
static const char *diag_text(const hpfc_diag *diag, int status)
{
    return diag->message[0] ? diag->message : hpfc_strerror(status);
}

static void print_help(void)
{
    printf("usage: hpfc-pack [options] INPUT -o OUTPUT.hpfc\n"
           "\n"
           "Packs a planar map into a hierarchical rasterized Planar Face Complex and\n"
           "prints the build report. INPUT is a .pfc file (known by its suffix or its\n"
           "first record 'pfc'), a Draco mesh (.drc, or data starting 'DRACO'; its\n"
           "triangle edges in x, y), or - for standard input; any other INPUT is a\n"
           "vector dataset read with GDAL/OGR (lines and polygons, see --layer).\n"
           "\n"
           "options:\n"
           "  -o, --output FILE     the .hpfc file to write (atomically); - writes it to\n"
           "                        standard output (not a terminal) and the report to\n"
           "                        standard error. An existing FILE is refused unless\n"
           "                        --force; FILE's directory is checked before reading\n"
           "  --force, -overwrite   replace an existing OUTPUT\n"
           "  --root N | NxM        root image size (default 64)\n"
           "  --refine N | NxM      refined image size, each side >= 2 (default 2)\n"
           "  --flat                build a one-level rPFC: the coarsest regular grid in\n"
           "                        which no edge lies inside a single pixel\n"
           "  --max-pixels N        refuse a --flat grid of more than N pixels\n"
           "                        (default %llu)\n"
           "  --leaf-points N       also refine a pixel holding more than N shape points\n"
           "                        of polyline edges (--vertices junctions), so a query\n"
           "                        reads few segments per leaf (default %u; 0: no bound)\n"
           , (unsigned long long)HPFC_DEFAULT_MAX_FLAT_PIXELS, HPFC_DEFAULT_MAX_LEAF_POINTS);
    printf(
           "  --partitions N        build the tree in N parts (runs of root pixels of\n"
           "                        about equal shape points; fewer where one root pixel\n"
           "                        holds more than a share), one\n"
           "                        after another, each from the edges near its pixels\n"
           "                        and kept in a file beside the output until they are\n"
           "                        joined: the same file, byte for byte, with the\n"
           "                        builder's working memory for one part at a time\n"
           "                        (at most one part a root pixel; not with --flat)\n"
           "  -j, --jobs N          build N parts at a time, in threads (on N cores up to\n"
           "                        N times the builder's speed, N parts' builder memory\n"
           "                        at once; 1.5-1.8x with 2 on street networks); without\n"
           "                        --partitions, the tree is built in N parts (not with\n"
           "                        --flat or --parts-dir; default: one part at a time).\n"
           "                        Also the threads of --threads when that is not given\n"
           "  --memory SIZE         build in as few parts as keep the pack's own memory\n"
           "                        within SIZE (500M, 4G: powers of 1024), as a model of\n"
           "                        each step's needs estimates it (bench/README.md); a\n"
           "                        note on stderr says when no cut can. The input's\n"
           "                        reading (GDAL's) is outside it (not with --partitions,\n"
           "                        --flat or --parts-dir)\n"
           "  --threads N           threads for the steps that share their work:\n"
           "                        validation, the build of a whole tree, numbering the\n"
           "                        faces, checking the faces' features; for GIS input\n"
           "                        also its sorts, the noding's search for crossings\n"
           "                        and the graph's points (default: --jobs, else one a\n"
           "                        core, up to 8; at most 64; the same file whatever N)\n"
           "  --parts-dir DIR       with --partitions: the parts are built by other\n"
           "                        processes (python3 -m hpfc pack on Dask): their\n"
           "                        graphs are cut into DIR, the plan printed as one\n"
           "                        JSON line on standard output, then a line on\n"
           "                        standard input, 'built' or 'failed', says whether\n"
           "                        every DIR/part-K.part is there to be joined\n"
           "                        (docs/interfaces.md section 8)\n"
           "  --read-ranges N       with --parts-dir, GIS input: its features are read\n"
           "                        by other processes in about N ranges (hpfc.pack's\n"
           "                        workers): the ranges are printed as one JSON line\n"
           "                        first, then a line on standard input, 'read' or\n"
           "                        'failed', says whether every DIR/range-K is there\n"
           "                        (after 'failed' the features are read here)\n"
           "  --read-range L:B:E    GIS input: read features B to E-1 (E 'end': to the\n"
           "                        end) of layer L (numbered as --layer or the dataset\n"
           "                        list them, from 0) with --range-tag T into the range\n"
           "                        file OUTPUT, for a --read-ranges pack\n"
           "  --range-tag T         the tag (16 hex digits) --read-ranges printed\n"
           );
    printf(
           "  -l, --layer NAME      GIS input: read layer NAME (repeatable; default: all)\n"
           "  -a_srs SRS, -s_srs SRS\n"
           "                        GIS input: INPUT's coordinates are in SRS (EPSG:4326,\n"
           "                        a PROJ string, WKT...), whatever its layers record;\n"
           "                        as ogr2ogr (here both mean the same, since hpfc-pack\n"
           "                        chooses the projection itself). Without either, a\n"
           "                        layer with no SRS whose coordinates all lie in the\n"
           "                        longitude/latitude range is taken as WGS 84, said on\n"
           "                        stderr and in the report (TopoJSON has no SRS)\n"
           "  --projection P        GIS input: auto (default), none (keep coordinates),\n"
           "                        tm, lcc, aea (central meridian at the data's median\n"
           "                        longitude, across the antimeridian too) or eqc\n"
           "  --vertices all|junctions\n"
           "                        GIS input: every shape point is a vertex, or only\n"
           "                        points where other than two edges meet (default;\n"
           "                        the points between are kept exactly as polyline\n"
           "                        shape points)\n"
           "  --invalid node|reject GIS input: node the rings of invalid polygons as\n"
           "                        linework (default; counted in the report), or refuse\n"
           "                        them\n"
           "  --key FIELD[,FIELD..] GIS input: record attribute FIELD of every feature\n"
           "                        with its id (several: values joined by commas;\n"
           "                        hpfc-inspect --locate shows it; messages name\n"
           "                        features by it)\n"
           "  --fields F,G,..|all   GIS input: store these attributes of every feature\n"
           "                        as typed columns (hpfc-inspect --locate shows them)\n"
           "  --wrap-dateline yes|no\n"
           "                        GIS input: cut longitude/latitude lines and polygons\n"
           "                        that cross the antimeridian (a segment spanning more\n"
           "                        than 180 degrees) at +-180 (default), or refuse them\n"
           "  --no-labels           write no LABL section (the faces and edge ids of every\n"
           "                        leaf, which let queries skip numbering the faces)\n"
           "  --no-geometry         write no GEOM section (the exact coordinates of every\n"
           "                        vertex and shape point, which exact point location\n"
           "                        and export need)\n"
           "  --link topology|witness\n"
           "                        GIS input: link faces to polygon features from the\n"
           "                        map's topology, each face then confirmed by an exact\n"
           "                        point-in-rings check (default), or every face by its\n"
           "                        witness point alone (a cross-check)\n"
           "  --layout compact|paper\n"
           "                        pool layout: words in the bits they need and\n"
           "                        children by rank (default; format 1.2), or the\n"
           "                        paper's fixed word slots and addresses\n"
           "  --json                print the build report as one JSON object\n"
           "  -q, --quiet           print no report (and no progress)\n"
           "  -h, --help            show this help\n"
           "  --version             show the version\n"
           "\n"
           );
    printf(
           "examples:\n"
           "  hpfc-pack states-10m.json -l states --key name -o states.hpfc\n"
           "  hpfc-pack -a_srs EPSG:4269 --projection lcc counties.shp -o counties.hpfc\n"
           "  hpfc-pack --invalid reject --force parcels.gpkg -o parcels.hpfc\n"
           "\n"
           "Exit status: 0 success, 1 input, build or write error (an existing OUTPUT\n"
           "without --force), 2 usage error or unsupported input format.\n");
}

/* A note the pack's steps give (pack_parts.notice): printed even with -q,
 * since it says the pack may need more than was asked. */
static void note(const char *text)
{
    complain("note: %s", text);
}

/* ---- option parsing -------------------------------------------------------- */

/* A whole unsigned decimal number in [1, max]: digits only, so signs, spaces,
 * hex and trailing garbage are refused, and so is overflow. */
static int parse_positive(const char *s, size_t len, uint64_t max, uint64_t *out)
{
    uint64_t v = 0;
    if (len == 0)
        return 0;
    for (size_t k = 0; k < len; k++) {
        if (s[k] < '0' || s[k] > '9')
            return 0;
        unsigned d = (unsigned)(s[k] - '0');
        if (v > (max - d) / 10)
            return 0;
        v = v * 10 + d;
    }
    if (v == 0)
        return 0;
    *out = v;
    return 1;
}

/* A number of bytes: N, or N followed by K, M, G or T (powers of 1024, as
 * sort -S takes them; either case, an optional trailing B or iB), at least
 * one MiB and at most 2^60 bytes. */
static int parse_bytes(const char *s, uint64_t *out)
{
    size_t n = strspn(s, "0123456789");
    const char *unit = s + n;
    static const char letters[] = "KMGT";
    const char *at = *unit ? strchr(letters, toupper((unsigned char)*unit)) : NULL;
    unsigned shift = at ? 10u * (unsigned)(at - letters + 1) : 0;
    const char *rest = at ? unit + 1 : unit;
    if (at && (*rest == 'i' || *rest == 'I') && (rest[1] == 'B' || rest[1] == 'b'))
        rest += 2;
    else if (*rest == 'B' || *rest == 'b')
        rest += 1;
    uint64_t v = 0, most = UINT64_C(1) << 60;
    if (*rest || !parse_positive(s, n, most >> shift, &v) || (v << shift) < (UINT64_C(1) << 20))
        return 0;
    *out = v << shift;
    return 1;
}

/* "N" (a square) or "NxM" (N columns, M rows), each side in [min, 2^32 - 1]. */
static int parse_size(const char *s, uint32_t min, uint32_t *cols, uint32_t *rows)
{
    const char *x = strpbrk(s, "xX");
    size_t n1 = x ? (size_t)(x - s) : strlen(s);
    uint64_t c, r;
    if (!parse_positive(s, n1, UINT32_MAX, &c))
        return 0;
    if (!x)
        r = c;
    else if (!parse_positive(x + 1, strlen(x + 1), UINT32_MAX, &r))
        return 0;
    if (c < min || r < min)
        return 0;
    *cols = (uint32_t)c;
    *rows = (uint32_t)r;
    return 1;
}

/* The value of option `name` given as "--name=value" or "--name value".
 * Returns the value, or NULL when `arg` is not this option; *missing is set
 * when the option came without a value. */
static const char *option_value(char **argv, int argc, int *i, const char *name, int *missing)
{
    const char *arg = argv[*i];
    size_t n = strlen(name);
    if (strncmp(arg, name, n) != 0)
        return NULL;
    if (arg[n] == '=')
        return arg + n + 1;
    if (arg[n] != '\0')
        return NULL;
    if (*i + 1 >= argc) {
        *missing = 1;
        return NULL;
    }
    return argv[++*i];
}

/* A whole decimal number in [0, max] (parse_positive, and 0). */
static int parse_count(const char *s, size_t len, uint64_t max, uint64_t *out)
{
    if (len == 1 && s[0] == '0') {
        *out = 0;
        return 1;
    }
    return parse_positive(s, len, max, out);
}

/* --read-range's LAYER:BEGIN:END (END 'end' for the layer's end). */
static int parse_range(const char *v, gis_range_plan *out)
{
    const char *c1 = strchr(v, ':'), *c2 = c1 ? strchr(c1 + 1, ':') : NULL;
    uint64_t layer = 0, begin = 0, end = 0;
    int to_end = c2 && strcmp(c2 + 1, "end") == 0;
    if (!c2 || !parse_count(v, (size_t)(c1 - v), 65535, &layer) ||
        !parse_count(c1 + 1, (size_t)(c2 - c1 - 1), INT64_MAX / 2, &begin) ||
        (!to_end && (!parse_count(c2 + 1, strlen(c2 + 1), INT64_MAX / 2, &end) || end <= begin)))
        return 0;
    *out = (gis_range_plan){(uint32_t)layer, (int64_t)begin, to_end ? -1 : (int64_t)end};
    return 1;
}

/* Stores the value of option `name`; NULL on success, else what a valid
 * value looks like. */
static const char *apply_value(pack_args *a, const char *name, const char *v)
{
    hpfc_build_params *p = &a->params;
    if (strcmp(name, "--root") == 0)
        return parse_size(v, 1, &p->root_cols, &p->root_rows) ? NULL
                                                               : "N or NxM, each at least 1";
    if (strcmp(name, "--refine") == 0)
        return parse_size(v, 2, &p->cols, &p->rows) ? NULL : "N or NxM, each at least 2";
    if (strcmp(name, "--max-pixels") == 0)
        return parse_positive(v, strlen(v), UINT64_MAX, &p->max_flat_pixels)
                   ? NULL
                   : "a positive integer";
    if (strcmp(name, "--leaf-points") == 0) {
        uint64_t n = 0;
        if (strcmp(v, "0") != 0 && !parse_positive(v, strlen(v), UINT32_MAX, &n))
            return "0 (no bound) or a positive integer";
        p->max_leaf_points = (uint32_t)n;
        return NULL;
    }
    if (strcmp(name, "--partitions") == 0) {
        uint64_t n = 0;
        if (!parse_positive(v, strlen(v), UINT32_MAX, &n))
            return "a positive integer";
        a->partitions = (uint32_t)n;
        return NULL;
    }
    if (strcmp(name, "--memory") == 0)
        return parse_bytes(v, &a->memory) ? NULL : "a size such as 4G, 500M or 2048M, at least 1M";
    if (strcmp(name, "--jobs") == 0 || strcmp(name, "-j") == 0) {
        uint64_t n = 0;
        if (!parse_positive(v, strlen(v), MAX_JOBS, &n))
            return "a positive integer, at most " MAX_JOBS_TEXT;
        a->jobs = (uint32_t)n;
        return NULL;
    }
    if (strcmp(name, "--threads") == 0) {
        uint64_t n = 0;
        if (!parse_positive(v, strlen(v), 64, &n))
            return "a positive integer, at most 64";
        a->threads = (uint32_t)n;
        return NULL;
    }
    if (strcmp(name, "--parts-dir") == 0) {
        a->parts_dir = v;
        return v[0] ? NULL : "a directory";
    }
    if (strcmp(name, "--read-ranges") == 0) {
        uint64_t n = 0;
        if (!parse_positive(v, strlen(v), 1u << 20, &n))
            return "a positive integer, at most 1048576";
        a->read_ranges = (uint32_t)n;
        return NULL;
    }
    if (strcmp(name, "--read-range") == 0) {
        a->has_range = 1;
        return parse_range(v, &a->range) ? NULL
                                          : "LAYER:BEGIN:END, END above BEGIN or 'end'";
    }
    if (strcmp(name, "--range-tag") == 0) {
        a->range_tag = v;
        return strlen(v) == 16 && strspn(v, "0123456789abcdef") == 16 ? NULL : "16 hex digits";
    }
    if (strcmp(name, "--layer") == 0 || strcmp(name, "-l") == 0) {
        if (a->n_layers == sizeof a->layers / sizeof a->layers[0])
            return "at most 64 layers";
        a->layers[a->n_layers++] = v;
        return v[0] ? NULL : "a layer name";
    }
    if (strcmp(name, "--projection") == 0) {
        a->projection = v;
        return gis_projection_valid(v) ? NULL : "auto, none, tm, lcc, aea or eqc";
    }
    if (strcmp(name, "--invalid") == 0) {
        a->invalid_mode = strcmp(v, "node") == 0 ? GIS_INVALID_NODE : GIS_INVALID_REJECT;
        return strcmp(v, "node") == 0 || strcmp(v, "reject") == 0 ? NULL : "reject or node";
    }
    if (strcmp(name, "-a_srs") == 0 || strcmp(name, "-s_srs") == 0) {
        *(name[1] == 'a' ? &a->assign_srs : &a->source_srs) = v;
        return v[0] ? NULL : "an SRS such as EPSG:4326";
    }
    if (strcmp(name, "--key") == 0 || strcmp(name, "--fields") == 0) {
        if (strcmp(name, "--key") == 0)
            a->key_field = v;
        else
            a->fields = v;
        return v[0] && v[0] != ',' && !strstr(v, ",,") && v[strlen(v) - 1] != ','
                   ? NULL
                   : "field names separated by commas";
    }
    if (strcmp(name, "--wrap-dateline") == 0) {
        a->dateline = strcmp(v, "no") == 0 ? GIS_DATELINE_REJECT : GIS_DATELINE_CUT;
        return strcmp(v, "yes") == 0 || strcmp(v, "no") == 0 ? NULL : "yes or no";
    }
    if (strcmp(name, "--layout") == 0) {
        a->layout = strcmp(v, "compact") == 0 ? HPFC_LAYOUT_COMPACT : HPFC_LAYOUT_PAPER;
        return strcmp(v, "paper") == 0 || strcmp(v, "compact") == 0 ? NULL : "paper or compact";
    }
    if (strcmp(name, "--link") == 0) {
        a->link_witness = strcmp(v, "witness") == 0;
        return strcmp(v, "topology") == 0 || strcmp(v, "witness") == 0 ? NULL
                                                                       : "topology or witness";
    }
    if (strcmp(name, "--vertices") == 0) {
        a->vertex_model = strcmp(v, "junctions") == 0 ? GIS_VERTICES_JUNCTIONS : GIS_VERTICES_ALL;
        return strcmp(v, "all") == 0 || strcmp(v, "junctions") == 0 ? NULL : "all or junctions";
    }
    a->output = v; /* -o, --output */
    return v[0] ? NULL : "a file name";
}

/* Handles an option that takes a value; returns 1 if argv[*i] was one
 * (*status is set to EXIT_USAGE when its value is missing or invalid). */
static int value_option(pack_args *a, char **argv, int argc, int *i, int *status)
{
    static const char *const names[] = {"--root",     "--refine",   "--max-pixels", "--leaf-points",
                                        "--layer",    "--projection", "--vertices",
                                        "--invalid",  "--wrap-dateline", "--key",
                                        "--fields",   "--output",   "-o",
                                        "-l",         "-a_srs",     "-s_srs",
                                        "--layout",   "--link",     "--partitions",
                                        "--parts-dir", "--jobs",   "-j",
                                        "--threads",  "--memory", "--read-ranges",
                                        "--read-range", "--range-tag"};
    for (size_t k = 0; k < sizeof names / sizeof names[0]; k++) {
        int missing = 0;
        const char *v = option_value(argv, argc, i, names[k], &missing);
        if (missing) {
            complain("%s needs a value", names[k]);
            *status = EXIT_USAGE;
            return 1;
        }
        if (!v)
            continue;
        const char *expected = apply_value(a, names[k], v);
        if (expected) {
            complain("%s: invalid value '%s' (expected %s)", names[k], v, expected);
            *status = EXIT_USAGE;
        }
        return 1;
    }
    return 0;
}

/* Returns -1 to go on, or the exit status (0 after --help / --version). */
static int parse_args(int argc, char **argv, pack_args *a)
{
    int status = -1, only_files = 0;
    memset(a, 0, sizeof *a);
    hpfc_build_params_default(&a->params);
    a->invalid_mode = GIS_INVALID_NODE; /* real layers have invalid rings */
    /* A GIS user expects topology at junctions (as TopoJSON's arcs) and the
     * shape points kept exactly (GEOM): 2-5x smaller than a vertex at every
     * shape point, and with --leaf-points as fast to query (bench/README.md). */
    a->vertex_model = GIS_VERTICES_JUNCTIONS;
    for (int i = 1; i < argc && status < 0; i++) {
        const char *arg = argv[i];
        if (only_files || arg[0] != '-' || strcmp(arg, "-") == 0) {
            if (a->input) {
                complain("more than one INPUT ('%s' and '%s')", a->input, arg);
                return EXIT_USAGE;
            }
            a->input = arg;
        } else if (strcmp(arg, "--") == 0)
            only_files = 1;
        else if (strcmp(arg, "-h") == 0 || strcmp(arg, "--help") == 0) {
            print_help();
            return 0;
        } else if (strcmp(arg, "--version") == 0) {
            printf("hpfc-pack %s\n", hpfc_version_string());
            return 0;
        } else if (strcmp(arg, "--flat") == 0)
            a->params.flat = 1;
        else if (strcmp(arg, "--json") == 0)
            a->json = 1;
        else if (strcmp(arg, "--quiet") == 0 || strcmp(arg, "-q") == 0)
            a->quiet = 1;
        else if (strcmp(arg, "--no-labels") == 0)
            a->no_labels = 1;
        else if (strcmp(arg, "--no-geometry") == 0)
            a->no_geometry = 1;
        else if (strcmp(arg, "--force") == 0 || strcmp(arg, "-overwrite") == 0)
            a->force = 1;
        else if (!value_option(a, argv, argc, &i, &status)) {
            complain("unknown option '%s' (see --help)", arg);
            return EXIT_USAGE;
        }
    }
    if (status >= 0)
        return status;
    if (!a->input) {
        complain("missing INPUT (usage: hpfc-pack [options] INPUT -o OUTPUT.hpfc)");
        return EXIT_USAGE;
    }
    if (!a->output) {
        complain("missing -o OUTPUT (usage: hpfc-pack [options] INPUT -o OUTPUT.hpfc)");
        return EXIT_USAGE;
    }
    if (a->assign_srs && a->source_srs) {
        complain("-a_srs and -s_srs: give one of them");
        return EXIT_USAGE;
    }
    if (a->jobs > 1 && (a->params.flat || a->parts_dir)) {
        complain("--jobs: not with --flat (built whole) or --parts-dir (built elsewhere)");
        return EXIT_USAGE;
    }
    if (a->memory && (a->partitions || a->params.flat || a->parts_dir)) {
        complain("--memory: not with --partitions (it chooses them), --flat (built whole)"
                 " or --parts-dir");
        return EXIT_USAGE;
    }
    if (a->jobs > 1 && a->partitions == 0 && !a->memory)
        a->partitions = a->jobs;
    if (a->partitions > 1 && a->params.flat) {
        complain("--partitions and --flat: a flat grid is built whole");
        return EXIT_USAGE;
    }
    a->to_stdout = strcmp(a->output, "-") == 0;
    if (a->parts_dir && (a->to_stdout || a->partitions < 1 || a->params.flat)) {
        complain("--parts-dir: with --partitions N, without --flat, and an OUTPUT other than -"
                 " (standard output carries the plan)");
        return EXIT_USAGE;
    }
    if (a->read_ranges && !a->parts_dir) {
        complain("--read-ranges: with --parts-dir (the ranges' files are in its directory)");
        return EXIT_USAGE;
    }
    if (a->has_range != (a->range_tag != NULL) ||
        (a->has_range && (a->parts_dir || a->partitions || a->memory || a->to_stdout))) {
        complain("--read-range and --range-tag: both, with a file OUTPUT, and not with "
                 "--parts-dir, --partitions or --memory");
        return EXIT_USAGE;
    }
    return -1;
}

/* ---- input --------------------------------------------------------------- */

/* Reads the rest of an open stream; reads in chunks so that pipes work
 * too. */
static int read_all(FILE *f, char **out, size_t *out_len)
{
    size_t len = 0, cap = 1 << 16;
    char *buf = malloc(cap);
    int err = buf ? 0 : ENOMEM;
    while (!err) {
        if (len == cap) {
            char *nb = cap > SIZE_MAX / 2 ? NULL : realloc(buf, cap * 2);
            if (!nb) {
                err = ENOMEM;
                break;
            }
            buf = nb;
            cap *= 2;
        }
        size_t n = fread(buf + len, 1, cap - len, f);
        len += n;
        if (n == 0) {
            err = ferror(f) ? (errno ? errno : EIO) : 0;
            break;
        }
    }
    if (err) {
        free(buf);
        return err;
    }
    *out = buf;
    *out_len = len;
    return 0;
}

/* The input's bytes. A regular file (standard input too, when it is one)
 * is mapped read-only: its pages are the page cache's, which the kernel
 * may drop and read again, so a large map's text (the parser reads it
 * twice) does not sit in the process's own memory beside the graph it
 * becomes. Anything else (a pipe) is read whole. */
typedef struct input_bytes {
    char *text;
    size_t len;
    int mapped;
} input_bytes;

static int input_map(const char *path, input_bytes *in)
{
    *in = (input_bytes){0};
    int is_stdin = strcmp(path, "-") == 0;
    FILE *f = is_stdin ? stdin : fopen(path, "rb");
    if (!f)
        return errno ? errno : EIO;
    int fd = fileno(f);
    struct stat sb;
    /* standard input only from its start: a caller may have read some */
    if (fd >= 0 && fstat(fd, &sb) == 0 && S_ISREG(sb.st_mode) && sb.st_size > 0 &&
        (uintmax_t)sb.st_size <= SIZE_MAX && (!is_stdin || lseek(fd, 0, SEEK_CUR) == 0)) {
        size_t size = (size_t)sb.st_size;
        void *p = mmap(NULL, size, PROT_READ, MAP_PRIVATE, fd, 0);
        if (p != MAP_FAILED) {
            posix_madvise(p, size, POSIX_MADV_SEQUENTIAL);
            *in = (input_bytes){.text = p, .len = size, .mapped = 1};
        }
    }
    int err = in->mapped ? 0 : read_all(f, &in->text, &in->len);
    if (!is_stdin)
        fclose(f);
    return err;
}

static void input_release(input_bytes *in)
{
    if (in->mapped)
        munmap(in->text, in->len);
    else
        free(in->text);
    *in = (input_bytes){0};
}

static int has_suffix(const char *s, const char *suffix)
{
    size_t n = strlen(s), m = strlen(suffix);
    return n >= m && strcmp(s + n - m, suffix) == 0;
}

/* Is the first record (after blank and comment lines) the `pfc` magic word? */
static int looks_like_pfc(const char *s, size_t len)
{
    size_t i = 0;
    while (i < len) {
        while (i < len && (s[i] == ' ' || s[i] == '\t' || s[i] == '\r' || s[i] == '\n'))
            i++;
        if (i < len && s[i] == '#') {
            while (i < len && s[i] != '\n')
                i++;
            continue;
        }
        break;
    }
    if (len - i < 3 || memcmp(s + i, "pfc", 3) != 0)
        return 0;
    i += 3;
    return i == len || strchr(" \t\r\n#", s[i]) != NULL;
}

/* Is INPUT for GDAL: not standard input, not named .pfc or .drc, and not
 * starting with the `pfc` record (a directory, e.g. of shapefiles, is)? */
static int is_gis_input(const char *path)
{
    if (strcmp(path, "-") == 0 || has_suffix(path, ".pfc") || has_suffix(path, ".drc"))
        return 0;
    FILE *f = fopen(path, "rb");
    if (!f)
        return 1; /* GDAL opens directories and reports unreadable files */
    char head[4096];
    size_t n = fread(head, 1, sizeof head, f);
    fclose(f);
    return !looks_like_pfc(head, n) && !draco_has_magic(head, n);
}

/* Decodes a Draco mesh; 0 or an exit status (the message is printed). */
static int read_draco(const pack_args *a, const char *bytes, size_t len, hpfc_graph **g,
                      pack_report *r)
{
    draco_options opt = {.stats = &r->mesh};
    hpfc_diag diag = {0};
    r->draco = 1;
    int st = draco_graph_from_memory(bytes, len, &opt, g, &diag);
    if (st)
        complain("%s: %s", a->input, diag_text(&diag, st));
    return st == 0 ? 0 : st == DRACO_E_NOT_BUILT ? EXIT_USAGE : EXIT_FAIL;
}

/* GDAL's GeoJSON reader parses every feature into a tree of small json-c
 * objects and frees it before the next. With glibc's default trim
 * threshold the freed top of the heap goes back to the kernel after each
 * large feature and comes back as page faults for the next one: on
 * countries-land-1m that churn was a third of the read, and GDAL's read
 * is the pack's peak. So a GIS pack keeps its heap: the build then reuses
 * what GDAL freed instead of faulting in fresh pages (returning it after
 * the read cost the build as much again). The build's end still gives
 * the free heap back (release_free_memory in pack_write.c). Measured in
 * bench/README.md, "The heap kept while GDAL reads". */
static void keep_heap(void)
{
#if defined(__GLIBC__)
    mallopt(M_TRIM_THRESHOLD, INT_MAX);
#endif
}

/* Threads for the steps that share their work (validation, the build of
 * a whole tree, numbering the faces, checking the faces' features, and
 * GEOS's check of the polygons beside GDAL's read):
 * --threads, else --jobs when given, else the tools' default (cores.h). */
static unsigned step_threads(const pack_args *a)
{
    return a->threads ? a->threads : a->jobs ? a->jobs : default_threads();
}

/* The GIS options of the command line. */
static gis_options gis_options_of(const pack_args *a)
{
    return (gis_options){.layers = a->layers,
                         .n_layers = a->n_layers,
                         .projection = a->projection,
                         .vertex_model = a->vertex_model,
                         .progress = isatty(2) && !a->quiet,
                         .invalid_mode = a->invalid_mode,
                         .dateline = a->dateline,
                         .key_field = a->key_field,
                         .fields = a->fields,
                         .assign_srs = a->assign_srs,
                         .source_srs = a->source_srs,
                         .threads = step_threads(a)};
}

/* --read-ranges (docs/interfaces.md §8): the ranges as one JSON line on
 * standard output ([layer, begin, end], end -1 for the layer's end), then
 * one line on standard input: "read" when every DIR/range-K is there; any
 * other line, or none, has the features read here. */
static int await_ranges(void *user, const gis_range_plan *ranges, size_t n, uint64_t tag)
{
    (void)user;
    printf("{\"ranges\": [");
    for (size_t k = 0; k < n; k++)
        printf("%s[%u, %lld, %lld]", k ? ", " : "", ranges[k].layer, (long long)ranges[k].begin,
               (long long)ranges[k].end);
    printf("], \"tag\": \"%016llx\"}\n", (unsigned long long)tag);
    char line[16];
    if (fflush(stdout) != 0 || !fgets(line, sizeof line, stdin))
        return 1;
    return strcmp(line, "read\n") != 0;
}

/* --read-range: the range read into the range file OUTPUT; an exit
 * status (the message is printed). */
static int read_range(const pack_args *a)
{
    if (!is_gis_input(a->input)) {
        complain("%s: --read-range reads GIS input only", a->input);
        return EXIT_USAGE;
    }
    gis_options opt = gis_options_of(a);
    opt.progress = 0;
    uint64_t tag = strtoull(a->range_tag, NULL, 16);
    char err[1024], why[ATOMIC_WHY];
    uint8_t *bytes = NULL;
    size_t len = 0;
    int st = gis_read_range(a->input, &opt, &a->range, tag, &bytes, &len, err, sizeof err);
    if (st) {
        complain("%s: %s", a->input, err);
        return st == 2 ? EXIT_USAGE : EXIT_FAIL;
    }
    st = atomic_output_write(a->output, bytes, len, why);
    free(bytes);
    if (st)
        complain("%s", why);
    return st ? EXIT_FAIL : 0;
}

/* Reads a GDAL dataset; 0 or an exit status (the message is printed). */
static int read_gis(const pack_args *a, hpfc_graph **g, pack_report *r)
{
    gis_options opt = gis_options_of(a);
    gis_ranges ranges = {a->read_ranges, a->parts_dir, await_ranges, NULL};
    if (a->read_ranges)
        opt.ranges = &ranges;
    char err[1024];
    r->gis = 1;
    keep_heap();
    int st = gis_read_graph(a->input, &opt, g, &r->gis_info, err, sizeof err);
    if (st)
        complain("%s: %s", a->input, err);
    if (!st && r->gis_info.srs_assumed[0] && !a->quiet)
        fprintf(stderr, "hpfc-pack: note: %s: layer '%s' has no SRS and its coordinates are "
                        "longitudes/latitudes: taken as WGS 84 (EPSG:4326); -a_srs sets another\n",
                a->input, r->gis_info.srs_assumed);
    if (!st && r->gis_info.ranges_declined[0]) /* printed with -q too: the reading was slower */
        fprintf(stderr, "hpfc-pack: note: %s: the ranges read elsewhere were not taken, %s; "
                        "the features were read here\n",
                a->input, r->gis_info.ranges_declined);
    return st == 0 ? 0 : st == 2 ? EXIT_USAGE : EXIT_FAIL;
}

/* Reads INPUT into a graph; 0 or an exit status (the message is printed). */
static int read_graph(const pack_args *a, hpfc_graph **g, pack_report *r)
{
    if (is_gis_input(a->input))
        return read_gis(a, g, r);
    input_bytes in;
    int err = input_map(a->input, &in);
    if (err) {
        complain("%s: %s", a->input, strerror(err));
        return EXIT_FAIL;
    }
    if (draco_has_magic(in.text, in.len) || has_suffix(a->input, ".drc")) {
        int status = read_draco(a, in.text, in.len, g, r);
        input_release(&in);
        return status;
    }
    if (!has_suffix(a->input, ".pfc") && !looks_like_pfc(in.text, in.len)) {
        input_release(&in);
        complain("%s: unsupported input format (standard input takes .pfc or Draco data)",
                 a->input);
        return EXIT_USAGE;
    }
    hpfc_diag diag = {0};
    int st = hpfc_pfc_parse(in.text, in.len, g, &diag);
    input_release(&in);
    if (st) {
        complain("%s: %s", a->input, diag_text(&diag, st));
        return EXIT_FAIL;
    }
    return 0;
}

/* ---- report ------------------------------------------------------------------ */

/* Word pixels with the word "++++" (no crossing), per level, by walking the
 * tree: the file format does not count them. */
static int count_private(const hpfc_tree *t, const hpfc_tree_info *info, level_report *lv)
{
    for (uint32_t l = 0; l < info->levels; l++) {
        uint32_t cols = l ? info->cols : info->root_cols;
        uint32_t rows = l ? info->rows : info->root_rows;
        size_t images = hpfc_tree_image_count(t, l);
        lv[l].private_ = 0;
        for (size_t im = 0; im < images; im++)
            for (uint32_t j = 0; j < rows; j++)
                for (uint32_t i = 0; i < cols; i++) {
                    hpfc_tree_pixel px;
                    int st = hpfc_tree_get_pixel(t, l, im, i, j, &px);
                    if (st)
                        return st;
                    if (px.type == HPFC_PIXEL_WORD && px.word_len == 4 &&
                        memcmp(px.word, "++++", 4) == 0)
                        lv[l].private_++;
                }
    }
    return HPFC_OK;
}

/* Per-level counts and bit widths as a reader sees them in the serialised
 * bytes; fails when they disagree with the tree, so that a writer bug never
 * reaches OUTPUT. */
static int read_levels(const hpfc_file *f, pack_report *r)
{
    int st = HPFC_OK;
    hpfc_file_info fi;
    hpfc_file_get_info(f, &fi);
    uint64_t word = 0, refined = 0;
    if (fi.levels != r->tree.levels)
        st = HPFC_E_LEVEL_TABLE;
    for (uint32_t l = 0; l < fi.levels && !st; l++) {
        hpfc_level_info li;
        st = hpfc_file_get_level(f, l, &li);
        if (st)
            break;
        level_report *lv = &r->levels[l];
        lv->images = li.images;
        lv->word = li.word_pixels;
        lv->refined = li.refined_pixels;
        lv->word_bits = li.word_bits;
        lv->address_bits = li.address_bits;
        lv->pool_bits = li.pool_bits;
        word += li.word_pixels;
        refined += li.refined_pixels;
    }
    if (!st && (word != r->tree.word_pixels || refined != r->tree.refined_pixels))
        st = HPFC_E_LEVEL_TABLE;
    r->file_bytes = fi.file_size;
    return st;
}

static double bits_per_edge(const pack_report *r)
{
    return r->tree.edges ? (double)r->file_bytes * 8.0 / (double)r->tree.edges : 0.0;
}

static void print_json(FILE *out, const pack_args *a, const pack_report *r)
{
    const hpfc_tree_info *t = &r->tree;
    jsonw w;
    jsonw_init(&w, out);
    jsonw_object_begin(&w, NULL);
    jsonw_string(&w, "input", a->input);
    jsonw_string(&w, "output", a->output);
    jsonw_string(&w, "input_format", r->gis ? r->gis_info.driver : r->draco ? "draco" : "pfc");
    if (r->draco) {
        const mesh_graph_stats *m = &r->mesh;
        jsonw_i64(&w, "unit_exp10", m->unit_exp10);
        jsonw_bool(&w, "unit_exact", m->exact);
        jsonw_u64(&w, "mesh_points_used", m->points_used);
        jsonw_u64(&w, "mesh_points_merged", m->merged_points);
        jsonw_u64(&w, "mesh_triangles_degenerate", m->degenerate_triangles);
        jsonw_u64(&w, "mesh_triangles_duplicate", m->duplicate_triangles);
        jsonw_u64(&w, "mesh_triangles_collinear", m->collinear_triangles);
        jsonw_u64(&w, "mesh_edges_split", m->split_edges);
    }
    if (r->gis) {
        const gis_info *gi = &r->gis_info;
        jsonw_string(&w, "projection", gi->projection);
        jsonw_bool(&w, "srs_assumed", gi->srs_assumed[0] != 0);
        jsonw_string(&w, "invalid_mode", a->invalid_mode == GIS_INVALID_NODE ? "node" : "reject");
        if (gi->crs)
            jsonw_string(&w, "crs", gi->crs);
        else
            jsonw_null(&w, "crs");
        jsonw_i64(&w, "unit_exp10", gi->unit_exp10);
        jsonw_string(&w, "vertex_model", a->vertex_model ? "junctions" : "all");
        jsonw_u64(&w, "layers_read", gi->layers);
        jsonw_u64(&w, "features", gi->features);
        jsonw_u64(&w, "skipped_empty", gi->skipped_empty);
        jsonw_u64(&w, "skipped_points", gi->skipped_points);
        jsonw_u64(&w, "invalid_polygons_noded", gi->invalid_noded);
        jsonw_u64(&w, "polygon_features", r->features);
        if (a->key_field)
            jsonw_string(&w, "key_field", a->key_field);
        else
            jsonw_null(&w, "key_field");
        jsonw_u64(&w, "faces_with_features", r->faces_with_features);
        jsonw_u64(&w, "faces_without_witness", r->faces_without_witness);
        jsonw_double(&w, "features_seconds", r->features_t.wall, 6);
        jsonw_u64(&w, "features_recorded", r->all_features);
        jsonw_u64(&w, "edges_with_features", r->edges_with_features);
        jsonw_object_begin(&w, "linking");
        jsonw_string(&w, "method", r->link_witness ? "witness" : "topology");
        jsonw_u64(&w, "faces_walked", r->faces_walked);
        jsonw_u64(&w, "faces_anchored", r->faces_anchored);
        jsonw_u64(&w, "faces_checked", r->faces_checked);
        jsonw_u64(&w, "conflicts", r->link_conflicts);
        jsonw_double(&w, "faces_seconds", r->link_t[0].wall, 6);
        jsonw_double(&w, "witness_seconds", r->link_t[1].wall, 6);
        jsonw_double(&w, "topology_seconds", r->link_t[2].wall, 6);
        jsonw_double(&w, "check_seconds", r->link_t[3].wall, 6);
        jsonw_object_end(&w);
        jsonw_u64(&w, "antimeridian_cut", gi->dateline_cut);
        jsonw_u64(&w, "points_read", gi->points_read);
        jsonw_string(&w, "noding", gi->noding);
        jsonw_u64(&w, "noding_segments", gi->noded_segments);
        /* the stages inside read_seconds */
        jsonw_object_begin(&w, "gis_seconds");
        jsonw_double(&w, "read", gi->read_t.wall, 6);
        jsonw_double(&w, "project", gi->project_t.wall, 6);
        jsonw_double(&w, "node", gi->node_t.wall, 6);
        jsonw_double(&w, "graph", gi->graph_t.wall, 6);
        jsonw_object_end(&w);
    }
    jsonw_u64(&w, "vertices", t->vertices);
    jsonw_u64(&w, "edges", t->edges);
    jsonw_u64(&w, "faces", t->faces);
    jsonw_u64(&w, "components", t->components);
    jsonw_bool(&w, "flat", a->params.flat);
    jsonw_u64(&w, "parts", r->parts);
    if (a->memory) {
        jsonw_object_begin(&w, "memory");
        jsonw_u64(&w, "budget_bytes", a->memory);
        jsonw_u64(&w, "held_bytes", r->memory_held);
        jsonw_u64(&w, "estimate_bytes", r->memory_need);
        jsonw_u64(&w, "sample_points", r->memory_sample_points);
        jsonw_u64(&w, "sample_pixels", r->memory_sample_pixels);
        jsonw_object_end(&w);
    }
    jsonw_u64(&w, "root_cols", t->root_cols);
    jsonw_u64(&w, "root_rows", t->root_rows);
    jsonw_u64(&w, "refine_cols", t->cols);
    jsonw_u64(&w, "refine_rows", t->rows);
    jsonw_u64(&w, "leaf_points", a->params.flat ? 0 : a->params.max_leaf_points);
    jsonw_u64(&w, "depth", t->levels - 1);
    jsonw_u64(&w, "level_count", t->levels);
    jsonw_array_begin(&w, "levels");
    for (uint32_t l = 0; l < t->levels; l++) {
        const level_report *lv = &r->levels[l];
        jsonw_object_begin(&w, NULL);
        jsonw_u64(&w, "level", l);
        jsonw_u64(&w, "images", lv->images);
        jsonw_u64(&w, "word_pixels", lv->word);
        jsonw_u64(&w, "refined_pixels", lv->refined);
        jsonw_u64(&w, "private_pixels", lv->private_);
        jsonw_u64(&w, "word_bits", lv->word_bits);
        jsonw_u64(&w, "address_bits", lv->address_bits);
        jsonw_u64(&w, "pool_bits", lv->pool_bits);
        jsonw_object_end(&w);
    }
    jsonw_array_end(&w);
    jsonw_u64(&w, "word_pixels", t->word_pixels);
    jsonw_u64(&w, "refined_pixels", t->refined_pixels);
    jsonw_u64(&w, "private_pixels", t->private_pixels);
    jsonw_u64(&w, "total_pixels", t->word_pixels + t->refined_pixels);
    jsonw_u64(&w, "max_word_symbols", t->max_word_symbols);
    jsonw_u64(&w, "file_bytes", r->file_bytes);
    jsonw_double(&w, "bits_per_edge", bits_per_edge(r), 3);
    jsonw_double(&w, "build_seconds", r->build_t.wall, 6);
    jsonw_double(&w, "read_seconds", r->read_t.wall, 6);
    jsonw_double(&w, "write_seconds", r->write_t.wall, 6);
    /* the CPU time of the same stages */
    jsonw_object_begin(&w, "cpu_seconds");
    jsonw_double(&w, "read", r->read_t.cpu, 6);
    jsonw_double(&w, "build", r->build_t.cpu, 6);
    jsonw_double(&w, "write", r->write_t.cpu, 6);
    if (r->gis) {
        const gis_info *gi = &r->gis_info;
        jsonw_double(&w, "gis_read", gi->read_t.cpu, 6);
        jsonw_double(&w, "gis_project", gi->project_t.cpu, 6);
        jsonw_double(&w, "gis_node", gi->node_t.cpu, 6);
        jsonw_double(&w, "gis_graph", gi->graph_t.cpu, 6);
        jsonw_double(&w, "features", r->features_t.cpu, 6);
        jsonw_double(&w, "link_faces", r->link_t[0].cpu, 6);
        jsonw_double(&w, "link_witness", r->link_t[1].cpu, 6);
        jsonw_double(&w, "link_topology", r->link_t[2].cpu, 6);
        jsonw_double(&w, "link_check", r->link_t[3].cpu, 6);
    }
    jsonw_object_end(&w);
    jsonw_object_end(&w);
    jsonw_finish(&w);
}

/* What the GIS reading repaired or left out, so that a default run says
 * what it did to the data (the JSON report has the same counts). */
static void print_repairs(FILE *out, const gis_info *gi)
{
    fprintf(out, "repaired   %llu invalid polygon%s noded as linework",
            (unsigned long long)gi->invalid_noded, gi->invalid_noded == 1 ? "" : "s");
    if (gi->invalid_noded)
        fprintf(out, " (%s%s)", gi->repaired, gi->invalid_noded > 5 ? ", ..." : "");
    if (gi->dateline_cut)
        fprintf(out, "; %llu cut at the antimeridian", (unsigned long long)gi->dateline_cut);
    fprintf(out, "\nskipped    %llu empty geometr%s, %llu point feature%s\n",
            (unsigned long long)gi->skipped_empty, gi->skipped_empty == 1 ? "y" : "ies",
            (unsigned long long)gi->skipped_points, gi->skipped_points == 1 ? "" : "s");
}

static void print_text(FILE *out, const pack_args *a, const pack_report *r)
{
    const hpfc_tree_info *t = &r->tree;
    uint64_t total = t->word_pixels + t->refined_pixels;
    fprintf(out, "%s -> %s\n", a->input, a->output);
    if (r->gis)
        fprintf(out, "input      %s, %llu features in %llu layer%s, projection %s, unit 1e%d\n",
               r->gis_info.driver, (unsigned long long)r->gis_info.features,
               (unsigned long long)r->gis_info.layers, r->gis_info.layers == 1 ? "" : "s",
               r->gis_info.projection, (int)r->gis_info.unit_exp10);
    if (r->gis && r->gis_info.srs_assumed[0])
        fprintf(out, "srs        none recorded; coordinates in lon/lat range: assumed WGS 84 "
                     "(EPSG:4326)\n");
    if (r->gis)
        print_repairs(out, &r->gis_info);
    if (r->gis && r->features)
        fprintf(out, "features   %u polygon features%s%s%s; %llu faces lie in one or more\n",
               r->features, a->key_field ? " (key " : "", a->key_field ? a->key_field : "",
               a->key_field ? ")" : "", (unsigned long long)r->faces_with_features);
    if (r->gis && r->features)
        fprintf(out, "linking    %llu faces walked over the edges, %llu checked at a witness "
                     "point: %llu conflict%s%s\n",
               (unsigned long long)r->faces_walked, (unsigned long long)r->faces_checked,
               (unsigned long long)r->link_conflicts, r->link_conflicts == 1 ? "" : "s",
               r->link_conflicts ? " (each face given its witness's answer)" : "");
    if (r->draco)
        fprintf(out, "input      Draco mesh, unit 1e%d%s, %zu points (%zu merged), %zu triangles "
               "dropped\n",
               (int)r->mesh.unit_exp10, r->mesh.exact ? " (exact)" : "", r->mesh.points_used,
               r->mesh.merged_points,
               r->mesh.degenerate_triangles + r->mesh.duplicate_triangles +
                   r->mesh.collinear_triangles);
    fprintf(out, "graph      %llu vertices, %llu edges, %llu faces, %llu component%s\n",
           (unsigned long long)t->vertices, (unsigned long long)t->edges,
           (unsigned long long)t->faces, (unsigned long long)t->components,
           t->components == 1 ? "" : "s");
    fprintf(out, "images     root %ux%u, refined %ux%u%s", t->root_cols, t->root_rows, t->cols,
           t->rows, a->params.flat ? " (flat rPFC)" : "");
    if (!a->params.flat && a->params.max_leaf_points)
        fprintf(out, ", at most %u shape points a leaf", a->params.max_leaf_points);
    fputc('\n', out);
    fprintf(out, "depth      %u (%u level%s)\n", t->levels - 1, t->levels, t->levels == 1 ? "" : "s");
    if (r->parts > 1 || a->memory)
        fprintf(out, "parts      %u%s\n", r->parts,
                r->parts > 1 ? " (runs of root pixels)" : " (built whole)");
    if (a->memory)
        fprintf(out, "memory     --memory %llu MiB: %llu MiB held before the build, about %llu MiB "
                     "at the peak (estimated)\n",
               (unsigned long long)(a->memory >> 20), (unsigned long long)(r->memory_held >> 20),
               (unsigned long long)(r->memory_need >> 20));
    fprintf(out, "\n%5s %10s %12s %12s %12s %5s %5s %14s\n", "level", "images", "word", "refined",
           "private", "k_w", "k_@", "pool bits");
    for (uint32_t l = 0; l < t->levels; l++) {
        const level_report *lv = &r->levels[l];
        fprintf(out, "%5u %10llu %12llu %12llu %12llu %5u %5u %14llu\n", l,
               (unsigned long long)lv->images, (unsigned long long)lv->word,
               (unsigned long long)lv->refined, (unsigned long long)lv->private_, lv->word_bits,
               lv->address_bits, (unsigned long long)lv->pool_bits);
    }
    fprintf(out, "%5s %10s %12llu %12llu %12llu\n\n", "all", "", (unsigned long long)t->word_pixels,
           (unsigned long long)t->refined_pixels, (unsigned long long)t->private_pixels);
    fprintf(out, "pixels     %llu (%.1f%% private)\n", (unsigned long long)total,
           total ? 100.0 * (double)t->private_pixels / (double)total : 0.0);
    fprintf(out, "max word   %u symbols\n", t->max_word_symbols);
    fprintf(out, "file       %llu bytes, %.2f bits per edge\n", (unsigned long long)r->file_bytes,
           bits_per_edge(r));
    fprintf(out, "time       build %.6f s (read %.6f s, write %.6f s)\n", r->build_t.wall,
           r->read_t.wall, r->write_t.wall);
    if (r->gis)
        fprintf(out, "read       %.3f s: read %.3f s, project %.3f s, node %.3f s, graph %.3f s "
               "(%llu shape points, noding %s)\n",
               r->read_t.wall, r->gis_info.read_t.wall, r->gis_info.project_t.wall,
               r->gis_info.node_t.wall, r->gis_info.graph_t.wall, (unsigned long long)r->gis_info.points_read,
               r->gis_info.noding);
}

/* ---- main ------------------------------------------------------------------ */

/* OUTPUT can be made, checked before the read and the build (minutes on a
 * continent): not a directory, not an existing file unless --force, in a
 * directory where a new file can be created (probed by creating one). 0 or
 * an exit status (the message is printed). */
static int check_output(const pack_args *a)
{
    if (a->to_stdout) {
        if (!isatty(1))
            return 0;
        complain("-o -: standard output is a terminal; redirect it or name a file");
        return EXIT_USAGE;
    }
    struct stat st;
    size_t n = strlen(a->output);
    if (a->output[n - 1] == '/' || (stat(a->output, &st) == 0 && S_ISDIR(st.st_mode))) {
        complain("%s: is a directory (-o names the .hpfc file to write)", a->output);
        return EXIT_USAGE;
    }
    if (lstat(a->output, &st) == 0 && !a->force) {
        complain("%s: exists; --force (or -overwrite) replaces it", a->output);
        return EXIT_FAIL;
    }
    char why[ATOMIC_WHY];
    if (atomic_output_check(a->output, why)) {
        complain("%s", why);
        return EXIT_FAIL;
    }
    return 0;
}

/* The tree's private pixels and the levels as the serialised bytes give
 * them, for the report (pack_write's hook). */
static int report_tree(void *user, const hpfc_tree *t, const hpfc_file *f)
{
    pack_report *r = user;
    hpfc_tree_get_info(t, &r->tree);
    r->levels = calloc(r->tree.levels, sizeof *r->levels);
    int st = r->levels ? count_private(t, &r->tree, r->levels) : HPFC_E_NOMEM;
    return st ? st : read_levels(f, r);
}

/* --parts-dir (docs/interfaces.md §8): the plan as one JSON line on
 * standard output, then one line on standard input: "built" when every
 * part file is in the directory, "failed" when a part's build failed. */
static int await_parts(void *user, const part_plan *plan, hpfc_diag *diag)
{
    (void)user;
    const hpfc_domain *d = &plan->domain;
    printf("{\"parts\": %u, \"domain\": [%lld, %lld, %lld, %lld, %u], \"unit_exp10\": %d, "
           "\"edges\": %llu, \"root\": [%u, %u], \"refine\": [%u, %u], \"leaf_points\": %u}\n",
           plan->parts, (long long)d->x0, (long long)d->y0, (long long)d->width,
           (long long)d->height, d->max_depth, (int)plan->unit_exp10,
           (unsigned long long)plan->edges, plan->root_cols, plan->root_rows, plan->cols,
           plan->rows, plan->leaf_points);
    if (fflush(stdout) != 0) {
        snprintf(diag->message, sizeof diag->message, "cannot write the plan: %s", strerror(errno));
        return HPFC_E_IO;
    }
    char line[16];
    if (!fgets(line, sizeof line, stdin)) {
        snprintf(diag->message, sizeof diag->message,
                 "standard input ended before the parts were built");
        return HPFC_E_IO;
    }
    if (strcmp(line, "built\n") == 0)
        return HPFC_OK;
    snprintf(diag->message, sizeof diag->message, "%s",
             strcmp(line, "failed\n") == 0 ? "a part's build failed"
                                            : "standard input: 'built' or 'failed' expected");
    return HPFC_E_IO; /* the parts' builders' failure, not this process's */
}

/* Builds, checks the serialised bytes, then writes OUTPUT (pack_write.h);
 * 0 or an exit status (the message is printed). */
static int build_and_write(const pack_args *a, const hpfc_graph *g, pack_report *r)
{
    hpfc_write_options wopts = {.crs = r->gis ? r->gis_info.crs : NULL,
                                .face_labels = !a->no_labels,
                                .layout = a->layout,
                                .geometry = a->no_geometry ? NULL : g,
                                .threads = step_threads(a)};
    pack_write_stats w;
    hpfc_diag diag;
    pack_parts parts = {.count = a->partitions, .jobs = a->jobs, .dir = a->parts_dir,
                        .await_parts = await_parts, .memory = a->memory, .notice = note};
    hpfc_build_params params = a->params; /* a build in parts builds each on one thread */
    params.threads = step_threads(a);
    int st = pack_write(g, &params, &parts, &wopts, r->gis ? &r->gis_info : NULL, a->link_witness,
                        a->to_stdout ? NULL : a->output, isatty(2) && !a->quiet, report_tree,
                        r, &w, &diag);
    r->build_t = w.build_t, r->write_t = w.write_t, r->features_t = w.features_t;
    r->parts = w.parts, r->memory_held = w.memory_held, r->memory_need = w.memory_need;
    r->memory_sample_points = w.memory_sample_points, r->memory_sample_pixels = w.memory_sample_pixels;
    if (w.file_bytes)
        r->file_bytes = w.file_bytes;
    r->features = w.features, r->all_features = w.all_features;
    r->edges_with_features = w.edges_with_features;
    r->faces_with_features = w.faces_with_features;
    r->faces_without_witness = w.faces_without_witness;
    r->faces_walked = w.faces_walked, r->faces_anchored = w.faces_anchored;
    r->faces_checked = w.faces_checked, r->link_conflicts = w.link_conflicts;
    r->link_witness = w.link_witness;
    memcpy(r->link_t, w.link_t, sizeof r->link_t);
    if (st && w.build_failed) {
        complain("%s: %s", a->input, diag_text(&diag, st));
        return st == HPFC_E_ARG ? EXIT_USAGE : EXIT_FAIL;
    }
    if (st) {
        complain("%s: %s", a->output, diag_text(&diag, st));
        return EXIT_FAIL;
    }
    return 0;
}

int main(int argc, char **argv)
{
    pack_args a;
    int status = parse_args(argc, argv, &a);
    if (status >= 0)
        return status;
    if (!a.to_stdout && same_file(a.input, a.output)) {
        complain("%s: OUTPUT is the same file as INPUT", a.output);
        return EXIT_USAGE;
    }
    if ((status = check_output(&a)) != 0)
        return status;
    if (a.has_range)
        return read_range(&a);
    pack_report r = {0};
    hpfc_graph *g = NULL;
    stage_time t0 = stage_now();
    status = read_graph(&a, &g, &r);
    r.read_t = stage_lap(&t0);
    if (!status)
        status = build_and_write(&a, g, &r);
    hpfc_graph_free(g);
    if (!status && !a.quiet) {
        FILE *out = a.to_stdout ? stderr : stdout; /* stdout holds the file */
        if (a.json)
            print_json(out, &a, &r);
        else
            print_text(out, &a, &r);
        if (fflush(out) != 0) {
            complain("cannot write the report: %s", strerror(errno));
            status = EXIT_FAIL;
        }
    }
    free(r.levels);
    gis_info_free(&r.gis_info);
    return status;
}
