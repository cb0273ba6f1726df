/*
 * hpfc.h: the public interface of libhpfcfile.
 *
 * libhpfcfile stores the exact topology of a planar map as a hierarchical
 * rasterized Planar Face Complex (hPFC; Damiand, Gonzalez-Lorenzo, Rossignac,
 * Dupont, Computers & Graphics 74, 2018). It has three parts:
 *
 *   - the graph and its plain-text `.pfc` reader (spec/pfc-format.md);
 *   - the builder, which turns a planar graph into an in-memory hPFC tree;
 *   - the file writer and the zero-copy reader of `.hpfc` files
 *     (spec/hpfc-format.md).
 *
 * Conventions used throughout:
 *   - Every function that can fail returns an `int` status: HPFC_OK (0) or one
 *     of the pinned HPFC_E_* codes below. Results come back through
 *     out-parameters. hpfc_strerror() describes every code and
 *     hpfc_status_name() spells its name.
 *   - Variable-length answers go to a caller's buffer of `cap` items: a NULL
 *     buffer asks only the count; a buffer too small gives
 *     HPFC_E_BUFFER_SMALL with the count needed set, so the caller can grow
 *     it and call again. HPFC_E_ARG always means a wrong argument.
 *   - Objects are opaque handles with a create/free (or open/close) pair; the
 *     free functions accept NULL.
 *   - Names. A function is hpfc_<object>_<what>: <object> is what it acts
 *     on or answers about (graph, tree, file, walker, pixel, vertex, dart,
 *     key, faces, label, geometry, attr, layer, shapes, ...), and the
 *     handle it reads through (the file, walker, tree, faces or shapes)
 *     is its first argument, whatever the object: hpfc_pixel_word(file,
 *     px, ...) and hpfc_pixel_vertex_key(walker, px, ...) are both about
 *     a pixel, one read through the file, the other through a walker's
 *     cache. When the object is the handle itself, the prefix is the
 *     handle's (hpfc_file_check_checksums, hpfc_walker_set_cache_size).
 *     `get` is in the name of exactly the calls that fill a caller's struct
 *     describing the handle or one of its parts, as hpfc_<handle>_get_<part>
 *     (hpfc_file_get_info, hpfc_file_get_level, hpfc_file_get_feature,
 *     hpfc_file_get_attr_value); a call that answers numbers or strings through
 *     out-parameters names what it answers, without `get`
 *     (hpfc_layer_name, hpfc_pixel_type, hpfc_geometry_vertex). Counts end
 *     in _count, after the thing counted in the singular
 *     (hpfc_graph_edge_count, hpfc_faces_face_count, hpfc_face_feature_count);
 *     the k-th of those things, one at a time, names what it answers
 *     (hpfc_pixel_vertex_key, hpfc_face_feature_id); all of them at once,
 *     into a caller's buffer, is the plural (hpfc_key_vertex_darts,
 *     hpfc_label_leaf_faces). An object in the plural is a whole: a
 *     section (hpfc_file_get_labels, hpfc_labels_verify), a numbering
 *     (hpfc_faces) or an index (hpfc_shapes); in the singular, one item of
 *     it (hpfc_label_key_face, hpfc_face_feature_count). A question that
 *     several parts of the library answer, each from its own source, is
 *     hpfc_<source>_<part>_<answer>, the part asked about (key, dart, pixel,
 *     leaf, stretch, crossing, edge, face, feature) before the answer: the
 *     face on a dart's right is hpfc_faces_key_face (hpfc_faces_build's
 *     numbering) and hpfc_label_key_face (the stored labels), its edge
 *     hpfc_label_key_edge and hpfc_geometry_key_edge, a feature's shape
 *     hpfc_shapes_feature_polygons. hpfc_open, hpfc_open_memory, hpfc_close
 *     and hpfc_locate, the file's own life and its one basic query, keep
 *     their short names. Older names stay callable, deprecated, at the end
 *     of this header, until 1.0.
 *   - Ids. The vertices, edges, faces and features of a file are numbered
 *     from 0 and named by an hpfc_id, 64 bits wide in every call that
 *     reads a file, whatever the section it comes from; HPFC_ID_NONE is
 *     "none" wherever an id may be missing (hpfc_point_location). Vertex
 *     and edge ids are the input graph's indices (hpfc_graph_add_vertex and
 *     hpfc_graph_add_edge order), face ids hpfc_faces_build's numbering
 *     (spec §3.11), feature ids positions in the FEAT section (spec §6.2).
 *     Three places keep another width, each for its reason: the graph and
 *     tree being built (hpfc_graph_*, hpfc_tree_*) index with uint32_t, as
 *     the builder keeps vertices, edges and crossings in 32-bit tables and
 *     refuses graphs past 2^32 - 2 of them (HPFC_E_LIMIT); the tables a
 *     writer is given (hpfc_feature_table, hpfc_attr_table,
 *     hpfc_edge_feature_table) and hpfc_features_info hold the FEAT, ATTR
 *     and EDGF sections' own 32-bit fields; hpfc_batch.h fills int64_t
 *     columns for numpy and data frames, -1 (HPFC_ID_NONE's bits) for none.
 *     Dart and vertex keys and dense indices (traversal, below) are not ids.
 *   - Functions that take a `hpfc_diag *` fill it (when non-NULL) with a
 *     one-line human-readable explanation of a failure: which line of a
 *     `.pfc` file, which edges and which point, which section of a file.
 *   - Experimental calls. Declarations seen only when the program defines
 *     HPFC_EXPERIMENTAL before including this header (block
 *     "Experimental" near its end) expose the library's inner workings: the
 *     path form of darts and vertices that keys superseded, the builder's
 *     tree pixels, counters for benchmarks. They may change or go between
 *     minor versions: a program that uses them is built against the
 *     library it runs with (as this repository's tools, installed with
 *     it), and rebuilt for each minor version; every other call keeps its
 *     name and meaning, or a deprecated alias, as this header says. This is
 *     zstd's ZSTD_STATIC_LINKING_ONLY tier, named for what the calls are
 *     rather than for how zstd asks its users to link them.
 *   - Coordinates: a graph lives on an integer lattice. A lattice point
 *     (x, y) stands for the user coordinates (x * 10^e, y * 10^e), where e is
 *     the graph's decimal unit exponent (0 unless set). No floating-point
 *     value ever decides anything topological.
 *
 * Structs that grow. The structs the library fills (hpfc_tree_info,
 * hpfc_file_info, hpfc_level_info, hpfc_section_info, hpfc_features_info,
 * hpfc_feature, hpfc_labels_info, hpfc_attrs_info, hpfc_edge_links_info,
 * hpfc_geometry_info) and those it reads
 * (hpfc_build_params, hpfc_write_options, hpfc_limits, hpfc_batch.h's
 * hpfc_locate_out)
 * may gain fields in later releases. Each call that takes one is a
 * function named `..._sized` that also takes the struct's size as the
 * caller was compiled, e.g. hpfc_file_get_info_sized(file, &info,
 * sizeof info), behind a macro of the plain name that passes
 * sizeof(the struct) itself: ordinary calls read as they always did, and a
 * program compiled against an older hpfc.h keeps working with a newer
 * library. The library reads and writes only the bytes that size covers:
 * what it reads gets defaults for the fields past them, what it writes
 * ends there. A caller compiled against a newer hpfc.h gets the fields
 * this library does not know zeroed, and HPFC_E_ARG when it sets one of
 * them in an input struct (it would be ignored otherwise). This is zstd's
 * and libspng's aim by another road: a setter per field (spng_set_option,
 * ZSTD_CCtx_setParameter) would turn each option into a call, and a size
 * field inside the struct (Windows' cbSize) would have to be set by every
 * caller that zero-initialises its options, as most do. The plain names
 * are macros: take the address of the `_sized` function instead. For the
 * library's maintainers: a field is only ever appended, at an offset no
 * smaller than the struct's previous sizeof (pad explicitly where
 * alignment would put it inside the old padding), and a new input field's
 * default is 0 (hpfc_build_params's come from hpfc_build_params_default).
 * Other structs (hpfc_diag, the reports, hpfc_pixel, the tables a
 * hpfc_write_options points to, ...) are fixed: changing one makes a new
 * type.
 *
 * Thread safety: a graph or tree may be read from several threads at once
 * but must not be modified concurrently. Functions keep no global state.
 */
#ifndef HPFC_H
#define HPFC_H

#include <stddef.h>
#include <stdint.h>

#include "hpfc_version.h"

#ifdef __cplusplus
extern "C" {
#endif

#if defined(HPFC_BUILDING_LIBRARY) && defined(__GNUC__)
#define HPFC_API __attribute__((visibility("default")))
#else
#define HPFC_API
#endif

/* ------------------------------------------------------------------------
 * Status codes. The numbers are pinned: they never change meaning.
 * ------------------------------------------------------------------------ */
enum {
    HPFC_OK = 0,
    HPFC_E_NOMEM = 1,           /* an allocation failed */
    HPFC_E_ARG = 2,             /* a caller passed an invalid argument */
    HPFC_E_IO = 3,              /* the operating system refused a read/write */
    HPFC_E_BUFFER_SMALL = 4,    /* the caller's buffer is too small: the count
                                   it needs has been written (nothing else) */

    /* .pfc input (spec/pfc-format.md) */
    HPFC_E_PFC_SYNTAX = 10,     /* unknown record, bad number, missing/extra field */
    HPFC_E_PFC_VERSION = 11,    /* missing or unsupported `pfc` header record */
    HPFC_E_VERTEX_INDEX = 12,   /* an edge names a vertex that does not exist */

    /* graph validity (any input path) */
    HPFC_E_DUPLICATE_POINT = 20,  /* two vertices / shape points at one point */
    HPFC_E_ZERO_LENGTH = 21,      /* a segment whose two ends coincide */
    HPFC_E_LOOP_INTERIOR = 22,    /* a loop edge with fewer than 2 interior points */
    HPFC_E_ISOLATED_VERTEX = 23,  /* a vertex with no incident edge */
    HPFC_E_NONPLANAR = 24,        /* edges cross or touch away from a shared end */
    HPFC_E_EXTENT = 25,           /* coordinates too large for the lattice */
    HPFC_E_EMPTY = 26,            /* a graph with no edge */
    HPFC_E_TOO_MANY_PIXELS = 27,  /* the flat rPFC grid exceeds the pixel limit */
    HPFC_E_LIMIT = 28,            /* an implementation limit (depth, word length) */

    /* .hpfc files (spec/hpfc-format.md) */
    HPFC_E_MAGIC = 40,          /* not an hpfc file */
    HPFC_E_VERSION = 41,        /* unknown format major version */
    HPFC_E_INCOMPATIBLE = 42,   /* an incompatible flag this reader does not know */
    HPFC_E_TRUNCATED = 43,      /* the file ends before a structure it declares */
    HPFC_E_CHECKSUM = 44,       /* a checksum does not match */
    HPFC_E_HEADER = 45,         /* a header field is out of its range */
    HPFC_E_LEVEL_TABLE = 46,    /* the level table is inconsistent */
    HPFC_E_SECTION = 47,        /* the section directory is inconsistent */
    HPFC_E_CORRUPT = 48,        /* pool contents contradict the format */
    HPFC_E_NO_PIXEL = 49,       /* a move leaves the domain, or no such pixel */
    HPFC_E_NO_SECTION = 50,     /* the file has no section of the kind asked for */
    HPFC_E_OVER_LIMIT = 51      /* a call would pass a resource limit (hpfc_limits) */
};

/* A short static English description of a status code. Never NULL. */
HPFC_API const char *hpfc_strerror(int status);
/* The code's name as this header spells it: hpfc_status_name(HPFC_E_CORRUPT)
 * is "HPFC_E_CORRUPT", for logs and bindings that show or match names. A
 * number no code has gives "HPFC_E_UNKNOWN" (no code is named so). Never
 * NULL; the strings are static. */
HPFC_API const char *hpfc_status_name(int status);

/* The library's version, "MAJOR.MINOR.PATCH", and as one number,
 * MAJOR * 10000 + MINOR * 100 + PATCH (as ZSTD_versionNumber): what the
 * running library is, where HPFC_VERSION_STRING and HPFC_VERSION_NUMBER
 * (hpfc_version.h) say what the caller was compiled against. */
HPFC_API const char *hpfc_version_string(void);
HPFC_API unsigned hpfc_version_number(void);

/* The version of the .hpfc format (spec/hpfc-format.md) this library
 * writes, a property of the format and not of the library's own version:
 * it reads every file of major HPFC_FORMAT_MAJOR (HPFC_E_VERSION for
 * another major), whatever its minor, and hpfc_file_info says which
 * version a file has. */
#define HPFC_FORMAT_MAJOR 1
#define HPFC_FORMAT_MINOR 3

/* Frees a buffer the library allocated and handed over (the serialised
 * files of hpfc_tree_serialize and hpfc_file_serialize). Always use it
 * rather than free(): the library and its caller may not share an
 * allocator (another C runtime, a sanitizer, a binding). NULL is fine. */
HPFC_API void hpfc_free(void *buffer);

/* The id of a vertex, edge, face or feature of a file (the introduction,
 * "Ids"), and the value that stands for none. */
typedef uint64_t hpfc_id;
#define HPFC_ID_NONE UINT64_MAX

/* Explanation of a failure, filled by functions that take one. */
typedef struct hpfc_diag {
    int status;           /* the status the function returned */
    uint32_t line;        /* 1-based source line of the culprit, 0 if none */
    int64_t edge[2];      /* the edges involved (graph indices), -1 if none */
    double x, y;          /* the point involved, in user coordinates */
    int has_point;        /* whether x, y are meaningful */
    char message[320];    /* one line, no trailing newline */
} hpfc_diag;

/* ------------------------------------------------------------------------
 * Graph: vertices and straight or polyline edges on the integer lattice.
 * ------------------------------------------------------------------------ */
typedef struct hpfc_graph hpfc_graph;

/* Largest |coordinate| a graph accepts; the builder may refuse smaller
 * extents when the domain it needs exceeds HPFC_LATTICE_MAX. */
#define HPFC_COORD_MAX ((int64_t)1 << 40)
#define HPFC_LATTICE_MAX ((int64_t)1 << 41)

HPFC_API int hpfc_graph_create(hpfc_graph **out);
HPFC_API void hpfc_graph_free(hpfc_graph *graph);

/* Coordinates are multiples of 10^exp10 user units (default 0). */
HPFC_API int hpfc_graph_set_unit_exp10(hpfc_graph *graph, int32_t exp10);
HPFC_API int32_t hpfc_graph_unit_exp10(const hpfc_graph *graph);

/* Adds a vertex; its index (0, 1, 2, ...) goes to *out_index when non-NULL.
 * Fails with HPFC_E_EXTENT when |x| or |y| exceeds HPFC_COORD_MAX. */
HPFC_API int hpfc_graph_add_vertex(hpfc_graph *graph, int64_t x, int64_t y,
                                   uint32_t *out_index);

/* Adds an edge from vertex u to vertex v through n_interior interior points
 * given as interior_xy[2*k], interior_xy[2*k+1]. u == v makes a loop.
 * Only index ranges and coordinate bounds are checked here; the geometry
 * (planarity, duplicates, ...) is checked by hpfc_graph_validate() and
 * hpfc_build(). */
HPFC_API int hpfc_graph_add_edge(hpfc_graph *graph, uint32_t u, uint32_t v,
                                 const int64_t *interior_xy, size_t n_interior,
                                 uint32_t *out_index);

HPFC_API size_t hpfc_graph_vertex_count(const hpfc_graph *graph);
HPFC_API size_t hpfc_graph_edge_count(const hpfc_graph *graph);
HPFC_API void hpfc_graph_vertex(const hpfc_graph *graph, size_t index,
                                int64_t *x, int64_t *y);
/* The edge's end vertices and its interior points (owned by the graph,
 * valid until the next modification). */
HPFC_API void hpfc_graph_edge(const hpfc_graph *graph, size_t index,
                              uint32_t *u, uint32_t *v,
                              const int64_t **interior_xy, size_t *n_interior);
HPFC_API uint32_t hpfc_graph_vertex_line(const hpfc_graph *graph, size_t index);
HPFC_API uint32_t hpfc_graph_edge_line(const hpfc_graph *graph, size_t index);

/* Checks that the graph is a valid planar embedding: no isolated vertex, no
 * duplicate point, no zero-length segment, loops with >= 2 interior points,
 * no two edges crossing or touching except at a shared end vertex. Exact. */
HPFC_API int hpfc_graph_validate(const hpfc_graph *graph, hpfc_diag *diag);

/* What hpfc_graph_validate checks that the parts of a split build cannot
 * (hpfc_build_part validates each part's graph, and every other flaw lies
 * at a point of one root pixel, whose part holds every edge through it):
 * a graph of no edge, a vertex of no edge. On either, the whole
 * hpfc_graph_validate runs, so the flaw is reported as hpfc_build reports
 * it. O(V) memory, where hpfc_graph_validate needs O(points). */
HPFC_API int hpfc_graph_check_whole(const hpfc_graph *graph, hpfc_diag *diag);

/* The closed box {xmin, ymin, xmax, ymax} of the graph's vertices and
 * interior points (lattice units): hpfc_build_domain's input for the
 * whole map. HPFC_E_ARG for NULL, HPFC_E_EMPTY for a graph of no vertex. */
HPFC_API int hpfc_graph_bounds(const hpfc_graph *graph, int64_t box[4]);

/* ------------------------------------------------------------------------
 * Plain-text .pfc reader (spec/pfc-format.md). Untrusted input is safe.
 * Checks the syntax and the per-record rules; call hpfc_graph_validate()
 * (or hpfc_build(), which does) for the geometric rules.
 * ------------------------------------------------------------------------ */
HPFC_API int hpfc_pfc_parse(const char *text, size_t length,
                            hpfc_graph **out, hpfc_diag *diag);
/* The same from a file: a regular file is mapped while it is parsed (its
 * text stays in the page cache, not in the process), anything else read
 * into memory. As with hpfc_open, do not truncate the file while it is
 * being read. */
HPFC_API int hpfc_pfc_read_file(const char *path, hpfc_graph **out,
                                hpfc_diag *diag);

/* ------------------------------------------------------------------------
 * Builder: planar graph to in-memory hPFC tree.
 * ------------------------------------------------------------------------ */
typedef struct hpfc_build_params {
    uint32_t root_cols, root_rows;  /* n0 x m0, each >= 1 (default 64 x 64) */
    uint32_t cols, rows;            /* n x m of refined images, >= 2 (2 x 2) */
    int flat;                       /* build a one-level rPFC instead */
    uint64_t max_flat_pixels;       /* refuse a flat grid above this */
    /* Also refine a pixel that holds more shape points (interior points of
     * polyline edges) than this, down to 1 x 1 pixels (0: no bound). Keeps
     * a located leaf's exact geometry short. */
    uint32_t max_leaf_points;
    /* Called as the build goes (NULL: not at all): level l's images done
     * of its total, at most every 4096 images and at each level's end. */
    void (*progress)(void *user, uint32_t level, uint64_t images_done, uint64_t images_total);
    void *progress_user;
    /* Threads the build may start, the calling thread among them (0 or 1:
     * the calling thread alone; at most 64 are used): validation's search
     * for crossing segments and each level's images are shared among
     * them. The tree and any error are the same as with one thread;
     * progress is still called from the calling thread only. */
    uint32_t threads;
} hpfc_build_params;

#define HPFC_DEFAULT_MAX_FLAT_PIXELS ((uint64_t)1 << 28)
#define HPFC_DEFAULT_MAX_LEAF_POINTS 16

/* Sets every field of the caller's `size` bytes of *params to its default
 * (the defaults above, progress NULL). */
HPFC_API void hpfc_build_params_init(hpfc_build_params *params, size_t size);
#define hpfc_build_params_default(params) \
    hpfc_build_params_init((params), sizeof(hpfc_build_params))

/* The domain a build gives a map whose points span the closed box
 * {xmin, ymin, xmax, ymax}: [x0, x0 + width) x [y0, y0 + height) with
 * width = root_cols * cols^max_depth (and height likewise) for the
 * smallest max_depth that leaves a lattice unit of margin on every side,
 * the map centred. hpfc_build chooses it this way from its graph's points;
 * a build split into parts computes it once from their boxes (a cheap
 * pre-pass: the min and max over the parts) so that every part shares one
 * lattice. A tree's levels are at most max_depth + 1. HPFC_E_ARG for an
 * empty box or bad params, HPFC_E_EXTENT as hpfc_build. */
typedef struct hpfc_domain {
    int64_t x0, y0, width, height;
    uint32_t max_depth;
} hpfc_domain;
HPFC_API int hpfc_build_domain_sized(const int64_t box[4], const hpfc_build_params *params,
                                     size_t params_size, hpfc_domain *out, hpfc_diag *diag);
#define hpfc_build_domain(box, params, out, diag) \
    hpfc_build_domain_sized((box), (params), sizeof(hpfc_build_params), (out), (diag))

typedef struct hpfc_tree hpfc_tree;

/* Validates the graph and builds its hPFC. The graph is not kept. Fields
 * past params_size get their defaults. */
HPFC_API int hpfc_build_sized(const hpfc_graph *graph, const hpfc_build_params *params,
                              size_t params_size, hpfc_tree **out, hpfc_diag *diag);
#define hpfc_build(graph, params, out, diag) \
    hpfc_build_sized((graph), (params), sizeof(hpfc_build_params), (out), (diag))
HPFC_API void hpfc_tree_free(hpfc_tree *tree);

/* A build split into parts, for maps too large for one build: each part
 * builds the subtrees of some root pixels, and hpfc_tree_merge joins the
 * parts into the tree hpfc_build gives for the whole map, pixel for pixel
 * (so every write call writes the same bytes from it). A root pixel's
 * subtree depends only on the segments that meet it and on the domain, so
 * a part's graph need only hold the edges that meet its root pixels (more
 * do no harm), each with its id in the whole map; every point of the
 * whole map must lie in the domain, as hpfc_build_domain over the whole
 * map's box gives it (with the same params). Root pixels are numbered
 * j * root_cols + i, row j = 0 the northern one. */
typedef struct hpfc_part {
    hpfc_domain domain;            /* the whole map's (hpfc_build_domain) */
    const uint32_t *root_pixels;   /* the part's root pixels, ascending */
    size_t root_pixel_count;
    /* Per edge of the part's graph, its index in the whole map's graph,
     * ascending (the part's graph keeps the whole map's order of edges,
     * which orders a word's crossings). NULL: the part's graph is the
     * whole map's (and edge_count 0 or its edge count). */
    const uint32_t *edge_ids;
    uint64_t edge_count;           /* edges of the whole map */
} hpfc_part;

/* A part's graph from the whole map's: the edges with a segment whose
 * closed box meets one of part->root_pixels' closed cells (in the domain
 * part->domain; every edge that meets them, and some that pass near), in
 * the whole map's order, and their vertices; *edge_ids gets each kept
 * edge's index in `graph` (ascending; free it with hpfc_free), as
 * hpfc_build_part takes them. part->edge_ids and edge_count are not read.
 * HPFC_E_ARG for a root pixel beyond the root or a domain smaller than
 * it. */
HPFC_API int hpfc_part_graph_sized(const hpfc_graph *graph, const hpfc_build_params *params,
                                   size_t params_size, const hpfc_part *part, hpfc_graph **out,
                                   uint32_t **edge_ids, hpfc_diag *diag);
#define hpfc_part_graph(graph, params, part, out, edge_ids, diag) \
    hpfc_part_graph_sized((graph), (params), sizeof(hpfc_build_params), (part), (out), (edge_ids), \
                          (diag))

/* Every part's graph from one pass over the whole map's segments, where
 * hpfc_part_graph makes a pass a part: owner[p] is root pixel p's part
 * (< part_count) or UINT32_MAX for none, over the root_cols * root_rows
 * root pixels. The cut keeps `graph`, which must outlive it, and each
 * part's list of edges (O(segments) time, O(the parts' edges) memory);
 * hpfc_cut_part_graph then gives part k's graph and edge ids, exactly what
 * hpfc_part_graph gives for the pixels k owns, in time that grows with
 * that part only. HPFC_E_ARG as hpfc_part_graph, and for an owner >=
 * part_count. */
typedef struct hpfc_cut hpfc_cut;
HPFC_API int hpfc_cut_create_sized(const hpfc_graph *graph, const hpfc_build_params *params,
                                   size_t params_size, const hpfc_domain *domain,
                                   const uint32_t *owner, uint32_t part_count, hpfc_cut **out,
                                   hpfc_diag *diag);
#define hpfc_cut_create(graph, params, domain, owner, part_count, out, diag) \
    hpfc_cut_create_sized((graph), (params), sizeof(hpfc_build_params), (domain), (owner), \
                          (part_count), (out), (diag))
HPFC_API int hpfc_cut_part_graph(const hpfc_cut *cut, uint32_t part, hpfc_graph **out,
                                 uint32_t **edge_ids, hpfc_diag *diag);
HPFC_API void hpfc_cut_free(hpfc_cut *cut);

/* Builds one part: the subtrees of part->root_pixels. The tree it gives is
 * only for hpfc_tree_merge (the write calls refuse it with HPFC_E_ARG, and
 * hpfc_tree_get_pixel another part's root pixel); its info has the whole
 * map's edge count, the vertices that lie in its root pixels, faces and
 * components 0. HPFC_E_ARG for a flat build, a domain these params do not
 * give, root pixels or edge ids out of order or range, a point outside
 * the domain; then as hpfc_build. */
HPFC_API int hpfc_build_part_sized(const hpfc_graph *graph, const hpfc_build_params *params,
                                   size_t params_size, const hpfc_part *part, hpfc_tree **out,
                                   hpfc_diag *diag);
#define hpfc_build_part(graph, params, part, out, diag) \
    hpfc_build_part_sized((graph), (params), sizeof(hpfc_build_params), (part), (out), (diag))

/* Joins parts that cover every root pixel once, built with the same
 * params and domain, into the whole map's tree (counted: its vertices,
 * faces and components are the whole map's). The parts are not changed;
 * free them after. HPFC_E_ARG for no part, a tree that is not a part,
 * parts of different builds, a root pixel in no part or in two, or
 * parts whose words leave an edge of the map in none. */
HPFC_API int hpfc_tree_merge(hpfc_tree *const *parts, size_t count, hpfc_tree **out,
                             hpfc_diag *diag);

/* A part's tree on disk (spec/part-format.md), for a merge in another
 * process: written atomically as hpfc_tree_write_file writes (HPFC_E_ARG
 * for a tree that is not a part), read back from a path or a buffer (which
 * the tree does not keep) into the same tree. The reader takes any bytes:
 * a file that is not one hpfc_build_part's tree can give (its pixels in
 * the builder's order, words of the grammar, counts that its pixels give)
 * gets HPFC_E_MAGIC, HPFC_E_VERSION, HPFC_E_CHECKSUM or HPFC_E_CORRUPT,
 * with the reason in diag. */
HPFC_API int hpfc_tree_write_part(const hpfc_tree *part, const char *path, hpfc_diag *diag);
/* The same part file written from the start of `fd`, an open regular file
 * the caller owns (truncated to the part's size, neither synced nor
 * closed): for parts that live as long as one build, which need no
 * durable rename. HPFC_E_IO (with the system's reason) when a write
 * fails. */
HPFC_API int hpfc_tree_write_part_fd(const hpfc_tree *part, int fd, hpfc_diag *diag);
HPFC_API int hpfc_tree_read_part(const char *path, hpfc_tree **out, hpfc_diag *diag);
HPFC_API int hpfc_tree_read_part_memory(const void *data, size_t size, hpfc_tree **out,
                                        hpfc_diag *diag);

/* Joins the part files at paths[0 .. count) (hpfc_tree_write_part) into the
 * whole map's tree, as hpfc_tree_merge joins their trees, without copying
 * them: each file is mapped read-only and checked as hpfc_tree_read_part
 * checks it, and the joined tree reads its pixels, words and crossings from
 * the mappings, which it keeps until hpfc_tree_free. What it holds besides
 * is a table of runs per level (a run per stretch of root pixels one part
 * owns in a row) and, while it counts the map's components, a union-find
 * over the edges (4 bytes and a bit an edge;
 * hpfc_tree_merge_files_uncounted, experimental, does without it): a
 * merge's memory is the parts' borders and the writer's, the pixels
 * staying in the files (the page cache). Every
 * write call takes the tree and writes the bytes hpfc_tree_merge's would
 * give. Errors as hpfc_tree_read_part (the message names the part's path)
 * and hpfc_tree_merge; HPFC_E_ARG for no path. The files must not change
 * while the tree lives. */
HPFC_API int hpfc_tree_merge_files(const char *const *paths, size_t count, hpfc_tree **out,
                                   hpfc_diag *diag);

/* Geometry of a tree. The domain is [x0, x0 + width) x [y0, y0 + height) in
 * lattice units; level l has root_cols * cols^l columns of equal width
 * (integers), and rows likewise. Row 0 of an image is its northern row. */
typedef struct hpfc_tree_info {
    uint32_t root_cols, root_rows, cols, rows;
    uint32_t levels;           /* number of levels (depth + 1) */
    int64_t x0, y0;            /* south-west corner of the domain (lattice) */
    int64_t width, height;     /* domain size (lattice units) */
    int32_t unit_exp10;        /* user coordinate = lattice * 10^unit_exp10 */
    uint64_t vertices, edges, faces, components;
    uint64_t word_pixels, refined_pixels, private_pixels;
    uint32_t max_word_symbols;
} hpfc_tree_info;

HPFC_API void hpfc_tree_get_info_sized(const hpfc_tree *tree, hpfc_tree_info *info,
                                       size_t size);
#define hpfc_tree_get_info(tree, info) \
    hpfc_tree_get_info_sized((tree), (info), sizeof(hpfc_tree_info))



/* ------------------------------------------------------------------------
 * Writing .hpfc files (spec/hpfc-format.md).
 * ------------------------------------------------------------------------ */

/* The source features of a file's faces, for the FEAT section
 * (spec/hpfc-format.md §6.2): a GIS layer's polygons, each face of the map
 * linked to the features that cover it. Face ids are those of
 * hpfc_faces_build() on the written file, which depend on the pools only:
 * serialise once without features, number the faces, then serialise again
 * with them (hpfc_file_serialize() does it from the open file, without the
 * tree). */
typedef struct hpfc_feature_table {
    uint32_t feature_count;
    const int64_t *fid;             /* per feature: its id in the source layer */
    const uint32_t *layer;          /* per feature: index into layer_name */
    const char *key_field;          /* the key attribute's name, NULL for none */
    const char *const *key;         /* per feature: its key value (UTF-8), NULL
                                       for a null value; NULL when key_field is */
    uint32_t layer_count;
    const char *const *layer_name;  /* per layer: its name (UTF-8) */
    uint32_t face_count;
    const uint32_t *face_start;     /* face_count + 1 non-decreasing offsets */
    const uint32_t *face_feature;   /* face f's features: face_feature[face_start[f]
                                       .. face_start[f + 1]), ascending */
} hpfc_feature_table;

/* Attribute value types (ATTR section, spec/hpfc-format.md §6.3). Dates
 * and times are strings (ISO 8601). */
enum { HPFC_ATTR_NULL = 0, HPFC_ATTR_INTEGER = 1, HPFC_ATTR_REAL = 2, HPFC_ATTR_STRING = 3 };

/* One attribute value: `type` says which member holds it (HPFC_ATTR_NULL:
 * none). A string is UTF-8, `len` bytes, not NUL-terminated when read
 * from a file. */
typedef struct hpfc_attr_value {
    int type;
    int64_t i;
    double r;
    const char *s;
    size_t len;
} hpfc_attr_value;

/* The features' attributes as typed columns, for the ATTR section: the
 * value of column c for feature k is cells[k * column_count + c], of the
 * column's type or HPFC_ATTR_NULL. Features are those of the FEAT section,
 * in its order. */
typedef struct hpfc_attr_table {
    uint32_t feature_count, column_count;
    const char *const *name;        /* per column: its name (UTF-8) */
    const uint8_t *type;            /* per column: HPFC_ATTR_INTEGER, _REAL or _STRING */
    const hpfc_attr_value *cells;
} hpfc_attr_table;

/* The features of each edge of the map, for the EDGF section
 * (spec/hpfc-format.md §6.4): edge e (its id: the input graph's edge
 * index) lies along the lines or rings of features
 * edge_feature[edge_start[e] .. edge_start[e + 1]), ascending indices into
 * the FEAT section's features. */
typedef struct hpfc_edge_feature_table {
    uint32_t edge_count, feature_count;
    const uint32_t *edge_start;     /* edge_count + 1 non-decreasing offsets */
    const uint32_t *edge_feature;
} hpfc_edge_feature_table;

/* Optional metadata recorded with a tree. */
/* Pool layouts (spec/hpfc-format.md §5.2 and §5.3). */
enum {
    HPFC_LAYOUT_DEFAULT = 0, /* the library's default: HPFC_LAYOUT_COMPACT */
    HPFC_LAYOUT_PAPER = 1,   /* the paper's fixed slots and addresses (Sect. 4.1) */
    HPFC_LAYOUT_COMPACT = 2, /* words in the bits they need, children by rank (1.2) */
};

typedef struct hpfc_write_options {
    const char *crs;          /* coordinate reference (e.g. "EPSG:32631" or a
                                 projection description), NULL for none */
    const hpfc_feature_table *features; /* FEAT section, NULL for none */
    /* Write the LABL section (spec §6.5: every leaf's faces and crossings'
     * edge ids) from the tree: hpfc_tree_serialize numbers the faces of
     * the pools it writes. hpfc_file_serialize keeps the source file's
     * LABL section, whose labels stay valid since its pools are copied. */
    int face_labels;
    const hpfc_attr_table *attributes;  /* ATTR section, NULL for none */
    const hpfc_edge_feature_table *edge_features; /* EDGF section, NULL for none */
    int layout;               /* HPFC_LAYOUT_*; hpfc_file_serialize keeps the file's */
    /* Write the GEOM section (spec §6.6: exact coordinates, shape points,
     * crossings' segments) from this graph, the one the tree was built
     * from (hpfc_tree_serialize; HPFC_E_ARG for another graph); NULL for
     * none. hpfc_file_serialize ignores it and keeps the source file's
     * GEOM section, which stays true since its pools are copied. */
    const hpfc_graph *geometry;
    /* With face_labels, from the tree calls (hpfc_tree_serialize,
     * hpfc_tree_write_file): when not NULL, receives the faces the LABL
     * section was numbered with, the answers hpfc_faces_build gives on the
     * file written, so that a caller who opens that file and needs them
     * does not number them again (on a continental map, seconds).
     * They answer HPFC_E_ARG until hpfc_faces_attach binds them to the
     * opened file; the caller frees them with hpfc_faces_free. NULL after
     * every other call and on any error. */
    struct hpfc_faces **faces_out;
    /* Threads the tree calls may number LABL's faces on
     * (hpfc_faces_build_threads), the calling one among them; 0 or 1: the
     * calling thread alone. The same bytes whatever the count. */
    unsigned threads;
    /* With face_labels, from the tree calls: number LABL's faces one root
     * pixel at a time, holding what the root pixels' borders need rather
     * than every fragment of the map (a street network of 10^7 points:
     * 2 MB instead of 32 MB). Each root is numbered twice, once to plan
     * and once as LABL is written, on `threads` threads (blocks of roots
     * for the plan; roots numbered ahead of the writing): about twice the
     * numbering's work, and a merge of 3*10^7 street points in 1.3 times
     * the time on two threads. The same bytes. For a merge of parts whose
     * memory matters more than its time; ignored when faces_out is set. */
    int faces_by_root;
} hpfc_write_options;

/* Every write call takes its options (NULL: all defaults) with their size
 * (hpfc.h's introduction, "Structs that grow"); a zeroed
 * hpfc_write_options is the defaults, and every field added later keeps
 * 0 as its default. */

/* Serialises the tree into a new buffer (*out, *out_size); the caller
 * frees it with hpfc_free(). This pair (to a buffer, to a path) has a twin
 * for an open file, hpfc_file_serialize and hpfc_file_write_file below:
 * the same options and outputs, declared alike on purpose. */
HPFC_API int hpfc_tree_serialize_sized(const hpfc_tree *tree, const hpfc_write_options *opts,
                                       size_t opts_size, uint8_t **out, size_t *out_size,
                                       hpfc_diag *diag);
#define hpfc_tree_serialize(tree, opts, out, out_size, diag) \
    hpfc_tree_serialize_sized((tree), (opts), sizeof(hpfc_write_options), (out), (out_size), \
                              (diag))

/* Writes the tree to `path` atomically: a temporary file in the same
 * directory, fsync, rename. On failure no partial file is left and an
 * existing file at `path` is untouched. The file is never held whole in
 * memory: each section is made in a mapping of the file's own pages, the
 * face labels (LABL) numbered on the pools written there, so the writer
 * holds no section beside what making one needs (each growth of the file
 * reserves its blocks first: a full disk is HPFC_E_IO). */
HPFC_API int hpfc_tree_write_file_sized(const hpfc_tree *tree, const hpfc_write_options *opts,
                                        size_t opts_size, const char *path, hpfc_diag *diag);
#define hpfc_tree_write_file(tree, opts, path, diag) \
    hpfc_tree_write_file_sized((tree), (opts), sizeof(hpfc_write_options), (path), (diag))
/* The same, written from the start of `fd`, an open regular file the
 * caller owns (a tool with its own way of replacing its output); fd is
 * neither synced nor closed. Opened for reading and writing, fd is
 * written in place as above; opened for writing only (it cannot be
 * mapped), it is set to the file's size and written a section at a time
 * at known offsets, as hpfc_file_write_fd writes, the face labels and the
 * shape index made in memory first. The same bytes either way. HPFC_E_IO
 * (with the system's reason in diag) when a write fails. */
HPFC_API int hpfc_tree_write_fd_sized(const hpfc_tree *tree, const hpfc_write_options *opts,
                                      size_t opts_size, int fd, hpfc_diag *diag);
#define hpfc_tree_write_fd(tree, opts, fd, diag) \
    hpfc_tree_write_fd_sized((tree), (opts), sizeof(hpfc_write_options), (fd), (diag))

/* ------------------------------------------------------------------------
 * Reading .hpfc files: a zero-copy reader over a memory-mapped file or a
 * caller's buffer. Opening validates the header, level table and section
 * directory in O(levels) and never decodes the pools; every later read is
 * bounds-checked, so a corrupt file yields HPFC_E_CORRUPT (or another code),
 * never a crash, an out-of-bounds read or an endless loop. Safe on
 * untrusted input.
 *
 * Thread safety, handle by handle (tests/lib/test_threads.c runs them from 8
 * threads under ThreadSanitizer):
 *   - hpfc_file: read-only once open; any number of threads may call
 *     any function on one handle at once (hpfc_locate, hpfc_locate_point,
 *     hpfc_locate_batch, the file's info, features, attributes, labels and
 *     geometry calls). Close it after every other thread is done.
 *   - hpfc_faces (hpfc_faces_build): read-only once built; shared as the
 *     file is, by every call that takes it (hpfc_locate_batch,
 *     hpfc_faces_pixel_face, hpfc_faces_key_face, whose walker is the
 *     calling thread's own).
 *   - hpfc_walker: one thread at a time. It holds the cache and scratch
 *     of the traversal calls; a thread that walks creates its own.
 *   - hpfc_shapes: one thread at a time. Its answers live in the object
 *     until its next call; a thread that asks for shapes creates its own
 *     (from the shared hpfc_file).
 *   - hpfc_pixel, hpfc_polygons and every caller buffer belong to their
 *     caller. The library keeps no global state.
 *
 * A mapped file must not change under its mapping. hpfc_open maps the file
 * (MAP_PRIVATE, read-only): a file replaced by rename, as every writer of
 * this library and its tools replaces one, leaves open handles reading
 * the old bytes, which stay as long as the mapping. A file truncated in
 * place while mapped makes the next read past its new end fault (SIGBUS),
 * and one rewritten in place makes the handle read bytes that open did not
 * check: as with LMDB and SQLite's mmap mode, do not truncate or rewrite in
 * place a file that a program has open. For a file on storage that others
 * may change (a shared or network file system, a file of another user), or
 * one that cannot be mapped (a pipe, a FIFO, standard input), open it with
 * HPFC_OPEN_READ: the library reads it into memory of its own, and later
 * changes to the file do not reach the handle.
 * ------------------------------------------------------------------------ */
typedef struct hpfc_file hpfc_file;

/* Open flags. */
#define HPFC_OPEN_SKIP_CHECKSUM 0x1u  /* do not verify the header checksum
                                         (for fuzzing past it; all bounds are
                                         still checked) */
#define HPFC_OPEN_READ 0x2u           /* read the file into memory the handle
                                         owns instead of mapping it (above):
                                         pipes and character devices too,
                                         read to their end */

/* Opens `path` (mapped, or read under HPFC_OPEN_READ) and validates it
 * as hpfc_open_memory does. HPFC_E_IO when the file cannot be opened or
 * read, is a directory, or is not a regular file without HPFC_OPEN_READ
 * (errno says why); HPFC_E_NOMEM when it does not fit in memory. */
HPFC_API int hpfc_open(const char *path, unsigned flags, hpfc_file **out);
/* The buffer must stay valid and unchanged until hpfc_close(). */
HPFC_API int hpfc_open_memory(const void *data, size_t size, unsigned flags,
                              hpfc_file **out);
HPFC_API void hpfc_close(hpfc_file *file);

/* Verifies the header's checksum and every section's (spec §4.5; reads
 * the whole file): HPFC_OK, or HPFC_E_CHECKSUM with diag naming the first
 * that fails, as "section 2 (LABL) at offset 4096, 812 bytes: CRC-32C
 * 0x1c2d3e4f stored, 0x5a6b7c8d computed" or "the header's (its first 352
 * bytes): ..."; a file opened with HPFC_OPEN_SKIP_CHECKSUM gets its header
 * checked here too. HPFC_E_ARG for a NULL file. */
HPFC_API int hpfc_file_check_checksums(const hpfc_file *file, hpfc_diag *diag);

/* The CRC-32C the file's bytes give, computed from the mapping, to set
 * beside the stored one: of section `index` (hpfc_section_info.crc32c), or,
 * with index HPFC_CHECKSUM_METADATA, of the metadata block with its own CRC
 * field taken as zero (hpfc_file_info.meta_crc32c, spec §4.5). A tool shows
 * every mismatch this way, where hpfc_file_check_checksums stops at the
 * first. HPFC_E_ARG for a NULL argument or no such section. O(its bytes). */
#define HPFC_CHECKSUM_METADATA UINT32_MAX
HPFC_API int hpfc_file_compute_checksum(const hpfc_file *file, uint32_t index,
                                        uint32_t *crc32c);

/* Serialises an open file's map again with opts' CRS and FEAT sections in
 * place of its own (opts NULL: neither), into a new buffer the caller
 * frees with hpfc_free(). The pools are copied bit for bit, so pixels,
 * darts, keys and face ids stay the same; no tree is needed. This is how a
 * map gets its features once its faces are numbered: serialise the tree,
 * open the bytes, free the tree, link, then hpfc_file_write_file(). The
 * file's LABL and GEOM sections are kept (they describe the pools, copied
 * unchanged); its ATTR and EDGF sections only through opts; the output has
 * this library's format version. Safe on any file that opened: every pool
 * was bounds-checked at open. The pair mirrors hpfc_tree_serialize and
 * hpfc_tree_write_file above, declared alike on purpose: only the source
 * differs. */
HPFC_API int hpfc_file_serialize_sized(const hpfc_file *file, const hpfc_write_options *opts,
                                       size_t opts_size, uint8_t **out, size_t *out_size,
                                       hpfc_diag *diag);
#define hpfc_file_serialize(file, opts, out, out_size, diag) \
    hpfc_file_serialize_sized((file), (opts), sizeof(hpfc_write_options), (out), (out_size), \
                              (diag))
/* The same, written to `path` atomically as hpfc_tree_write_file() does. */
HPFC_API int hpfc_file_write_file_sized(const hpfc_file *file, const hpfc_write_options *opts,
                                        size_t opts_size, const char *path, hpfc_diag *diag);
#define hpfc_file_write_file(file, opts, path, diag) \
    hpfc_file_write_file_sized((file), (opts), sizeof(hpfc_write_options), (path), (diag))
/* The same, written from the start of `fd`, an open regular file the
 * caller owns (for a tool with its own way of replacing its output): set
 * to the file's size, then written a section at a time at known offsets
 * (pwrite), so the output is never held in memory; the sections the file
 * already has (pools, LABL, GEOM) are written straight from its mapping.
 * HPFC_E_IO (with the system's reason in diag) when a write fails; fd is
 * neither synced nor closed. Both write_file calls write this way. */
HPFC_API int hpfc_file_write_fd_sized(const hpfc_file *file, const hpfc_write_options *opts,
                                      size_t opts_size, int fd, hpfc_diag *diag);
#define hpfc_file_write_fd(file, opts, fd, diag) \
    hpfc_file_write_fd_sized((file), (opts), sizeof(hpfc_write_options), (fd), (diag))

#define HPFC_MAX_LEVELS 48

typedef struct hpfc_file_info {
    uint16_t format_major, format_minor;
    uint32_t compat_flags, incompat_flags;
    uint32_t root_cols, root_rows, cols, rows;
    uint32_t levels;
    int64_t x0, y0, width, height;  /* domain, lattice units */
    int32_t unit_exp10;             /* user coordinate = lattice * 10^unit_exp10 */
    uint64_t file_size;
    uint32_t section_count;
    const char *crs;                /* NUL-free text, crs_len bytes; NULL if none */
    size_t crs_len;
    /* The metadata block (spec §4.1): header, level table and directory,
     * the bytes meta_crc32c covers (read with hpfc_file_compute_checksum). */
    uint32_t header_size;
    uint32_t meta_crc32c;
    uint64_t meta_size;
} hpfc_file_info;

typedef struct hpfc_level_info {
    uint64_t word_pixels, refined_pixels, images;
    uint32_t word_bits;     /* k_w: bits of one word slot */
    uint32_t address_bits;  /* k_@: bits of one refined-pixel address */
    uint64_t pool_offset;   /* byte offset of the level's pool in the file */
    uint64_t pool_bits;     /* s^l */
    int64_t cell_w, cell_h; /* pixel size at this level, lattice units */
} hpfc_level_info;

typedef struct hpfc_section_info {
    char tag[5];            /* four characters, NUL-terminated */
    uint32_t flags;
    uint64_t offset, length;
    uint32_t crc32c;
} hpfc_section_info;

HPFC_API void hpfc_file_get_info_sized(const hpfc_file *file, hpfc_file_info *info,
                                       size_t size);
#define hpfc_file_get_info(file, info) \
    hpfc_file_get_info_sized((file), (info), sizeof(hpfc_file_info))
HPFC_API int hpfc_file_get_level_sized(const hpfc_file *file, uint32_t level,
                                       hpfc_level_info *out, size_t size);
#define hpfc_file_get_level(file, level, out) \
    hpfc_file_get_level_sized((file), (level), (out), sizeof(hpfc_level_info))
HPFC_API int hpfc_file_get_section_sized(const hpfc_file *file, uint32_t index,
                                         hpfc_section_info *out, size_t size);
#define hpfc_file_get_section(file, index, out) \
    hpfc_file_get_section_sized((file), (index), (out), sizeof(hpfc_section_info))

/* A pixel: the paper's stack of (image, i, j) triplets from the root. An
 * image is named by its bit offset in its level's pool (the root is 0). */
typedef struct hpfc_pixel {
    uint32_t depth;  /* level of the pixel; path[0..depth] are valid */
    struct {
        uint64_t image;  /* bit offset of the image in its level's pool */
        uint32_t i, j;   /* column (0 = west), row (0 = north) */
    } path[HPFC_MAX_LEVELS];
} hpfc_pixel;

enum { HPFC_WEST = 0, HPFC_NORTH = 1, HPFC_EAST = 2, HPFC_SOUTH = 3 };
/* What a pixel holds: a word (a leaf), or a refined image below it. */
enum { HPFC_PIXEL_WORD = 0, HPFC_PIXEL_REFINED = 1 };

/* Pixel (i, j) of the root image. */
HPFC_API int hpfc_pixel_root(const hpfc_file *file, uint32_t i, uint32_t j, hpfc_pixel *out);
/* HPFC_PIXEL_WORD or HPFC_PIXEL_REFINED. */
HPFC_API int hpfc_pixel_type(const hpfc_file *file, const hpfc_pixel *px, int *type);
/* Is the pixel a private word pixel (word "++++")? */
HPFC_API int hpfc_pixel_is_private(const hpfc_file *file, const hpfc_pixel *px, int *is_private);
/* The pool layout's own structure at `level`, O(pool): for the compact
 * layout (spec §5.3) its block counts, type bits, word index and words agree;
 * for the paper layout nothing beyond what pixel access checks. HPFC_OK, or
 * HPFC_E_CORRUPT with the first fault in diag. */
HPFC_API int hpfc_file_check_pool_layout(const hpfc_file *file, uint32_t level, hpfc_diag *diag);
/* Pixel (i, j) of the image a refined pixel points to (px may equal out). */
HPFC_API int hpfc_pixel_child(const hpfc_file *file, const hpfc_pixel *px, uint32_t i,
                              uint32_t j, hpfc_pixel *out);
/* The refined pixel containing px (HPFC_E_NO_PIXEL at the root). */
HPFC_API int hpfc_pixel_parent(const hpfc_pixel *px, hpfc_pixel *out);
/* The first pixel adjacent to px in direction dir (paper Algorithm 1 and its
 * three mirrors): at depths <= px's it keeps px's row (W/E) or column (N/S);
 * deeper it takes the neighbour that comes first along the shared road in
 * that neighbour's clockwise order. HPFC_E_NO_PIXEL at the domain border. */
HPFC_API int hpfc_pixel_move(const hpfc_file *file, const hpfc_pixel *px, int dir,
                             hpfc_pixel *out);
/* The word pixel (leaf) containing lattice point (x, y), half-open cells. */
HPFC_API int hpfc_locate(const hpfc_file *file, int64_t x, int64_t y, hpfc_pixel *out);
/* Lattice bounds [x0, x1) x [y0, y1) of the pixel. */
HPFC_API int hpfc_pixel_bounds(const hpfc_file *file, const hpfc_pixel *px, int64_t *x0,
                               int64_t *y0, int64_t *x1, int64_t *y1);
/* Decodes a word pixel's word in place into symbols "+=[]()Y". With
 * buf == NULL (or too small), *len receives the length and HPFC_OK (or
 * HPFC_E_BUFFER_SMALL when cap is too small) is returned. A refined pixel
 * is HPFC_E_ARG. */
HPFC_API int hpfc_pixel_word(const hpfc_file *file, const hpfc_pixel *px, char *buf,
                             size_t cap, size_t *len);

/* ------------------------------------------------------------------------
 * Graph traversal on an open file (spec/hpfc-format.md, "Traversal").
 *
 * The application sees the input graph's vertices and darts; crossings stay
 * hidden. A dart is a directed edge u -> v, named by its first piece: the
 * out-dart of crossing `crossing` in the word pixel holding u. Darts turn
 * with the face on their right (rpfc-operators convention): next() follows
 * a face's boundary clockwise around a bounded face.
 *
 * Handles. A dart or a vertex is handled by its 64-bit key (spec §3.10:
 * the word pixel's slot position << 20 | crossing or local vertex id). A
 * key names its dart or vertex on its own: it is a hash key, stable
 * across walkers, opens and processes, and any key of the file works on
 * any walker of it. Every traversal call below takes and gives keys;
 * hpfc_dart_index / hpfc_vertex_index turn them into small integers for
 * arrays. The path form (hpfc_dart, hpfc_vertex: the key's pixel with its
 * whole path from the root, HPFC_MAX_LEVELS steps) is experimental (block
 * "Experimental" below): the operators are defined on it, and the key
 * calls answer as it does.
 *
 * Traversal needs scratch memory sized by the file's longest word and a
 * cache; both live in an hpfc_walker, one per thread. Operators never
 * allocate (but the first key a walker resolves builds its parent index,
 * below).
 *
 * The cache keeps the words the walker has parsed and the crossings it has
 * identified across roads, so that an operator on a dart near darts already
 * visited follows a few links instead of decoding the words of about four
 * pixels: a full traversal decodes each word about once. Answers never
 * depend on the cache (size, contents or being off), and its entries are
 * checked as a fresh decode is, so the file may still be untrusted.
 * ------------------------------------------------------------------------ */
typedef struct hpfc_walker hpfc_walker;

/* The cache size a new walker gets (bytes). */
#define HPFC_WALKER_DEFAULT_CACHE ((size_t)8 << 20)

/* A new walker with a cache of HPFC_WALKER_DEFAULT_CACHE bytes (or none,
 * when that much memory cannot be had). */
HPFC_API int hpfc_walker_create(const hpfc_file *file, hpfc_walker **out);
HPFC_API void hpfc_walker_free(hpfc_walker *walker);
/* Empties the walker's cache and gives it at most `bytes` bytes from now on
 * (never more than caching every word of the file can use); 0 turns it off.
 * When the cache is full it is emptied and filled again, so any size works:
 * a small one only makes the walker decode words again. HPFC_E_NOMEM leaves
 * the walker without a cache. */
HPFC_API int hpfc_walker_set_cache_size(hpfc_walker *walker, size_t bytes);

/* What every key call shares (the calls below, and the per-dart calls of
 * the faces, LABL and GEOM modules further on), unless its own block says
 * otherwise.
 *
 * Statuses: HPFC_OK; HPFC_E_ARG for a NULL argument or a key that names no
 * dart (vertex) of the file (a position that is not the start of a word
 * slot: inside a mask, on a refined pixel's address, past the pools; a
 * crossing index past the word's crossings or on a stabbing; a local
 * vertex id past the pixel's vertices), HPFC_KEY_INVALID included;
 * HPFC_E_CORRUPT when the pools contradict the format, including a layout
 * that names a pixel ambiguously (two addresses aliasing one image, images
 * out of parent order or not back to back, §5.2.2); HPFC_E_LIMIT past 2^32
 * images in one level; HPFC_E_NOMEM. Outputs are written only on success.
 * Safe on untrusted files and keys: no crash, no read outside the file, no
 * endless loop.
 *
 * Answers: each call gives exactly what its path-form counterpart
 * (experimental) gives on the key's dart (vertex), status included,
 * whatever the walker's cache holds.
 *
 * Cost: a key whose pixel the walker's cache holds costs one hash probe
 * more than the operator's own work, and no pixel path is built; a twin,
 * next or prev the cache has answered before is then one hash probe and
 * one load from a compact copy of the answers (bench/README.md, "Targets
 * and results", traversal). Otherwise the key is resolved to its pixel
 * path, O(levels * log(images)), and the operator runs as on its path
 * form. The first such key builds the walker's parent index, once, by one
 * pass over the pools: O(pixels) time and 16 bytes per image of the levels
 * below the root, kept until hpfc_walker_free. A file whose layout fails
 * that pass gives its status to every key call of the walker after it
 * (the path-form operators still work). Every key call resolves only a key
 * whose pixel the cache does not hold.
 *
 * Thread safety: as every walker call, one walker per thread; keys are
 * plain numbers any thread may hold. */

/* No dart or vertex: the key of a slot at bit 2^44 - 1, which no file
 * under 2 TiB has; every key call answers HPFC_E_ARG for it, as for any
 * key that names nothing. */
#define HPFC_KEY_INVALID UINT64_MAX

/* The vertices of a word pixel (a leaf, from hpfc_leaf_first/next or
 * hpfc_locate): their number, and the key of the index-th of them
 * (index < count, else HPFC_E_ARG). A path that names no pixel:
 * HPFC_E_ARG; a refined pixel (no word in its slot) or a word outside the
 * grammar: HPFC_E_CORRUPT. O(the word) the first time, then a cache probe. */
HPFC_API int hpfc_pixel_vertex_count(hpfc_walker *w, const hpfc_pixel *px, uint32_t *count);
HPFC_API int hpfc_pixel_vertex_key(hpfc_walker *w, const hpfc_pixel *px, uint32_t index,
                                   uint64_t *vertex_key);
/* The key of the dart that leaves a leaf at its crossing `crossing` (0-based,
 * word order): HPFC_E_ARG when that crossing belongs to a stabbing (no
 * vertex of the leaf: no dart starts there) or is past the word's
 * crossings. Cost as hpfc_pixel_vertex_key. */
HPFC_API int hpfc_pixel_dart_key(hpfc_walker *w, const hpfc_pixel *px, uint32_t crossing,
                                 uint64_t *dart_key);

/* A vertex's degree (a loop counts twice) and the key of its index-th
 * outgoing dart, clockwise (index < degree, else HPFC_E_ARG). */
HPFC_API int hpfc_key_degree(hpfc_walker *w, uint64_t vertex_key, uint32_t *degree);
HPFC_API int hpfc_key_vertex_dart(hpfc_walker *w, uint64_t vertex_key, uint32_t index,
                                  uint64_t *dart_key);
/* All of them at once, for one call: the degree into *degree and the
 * darts' keys, clockwise, into darts[0 .. *degree). darts NULL asks only
 * the degree; cap too small is HPFC_E_BUFFER_SMALL with *degree set. */
HPFC_API int hpfc_key_vertex_darts(hpfc_walker *w, uint64_t vertex_key, uint64_t *darts,
                                   size_t cap, uint32_t *degree);

/* The opposite dart v -> u (twin), the next and previous dart along the
 * same face, and the dart's origin and target vertices, as keys. */
HPFC_API int hpfc_key_twin(hpfc_walker *w, uint64_t dart_key, uint64_t *out_key);
HPFC_API int hpfc_key_next(hpfc_walker *w, uint64_t dart_key, uint64_t *out_key);
HPFC_API int hpfc_key_prev(hpfc_walker *w, uint64_t dart_key, uint64_t *out_key);
HPFC_API int hpfc_key_origin(hpfc_walker *w, uint64_t dart_key, uint64_t *vertex_key);
HPFC_API int hpfc_key_target(hpfc_walker *w, uint64_t dart_key, uint64_t *vertex_key);

/* Dense indices. Keys are sparse 64-bit numbers; these are small integers
 * for arrays of per-dart (per-vertex) data and visited bitmaps.
 *
 * Definition (a pure function of the key and the file, so the same on any
 * walker, cache or not, and across opens): number the file's pixels, word
 * and refined alike, level by level; the root image's in scanline order
 * first, then each level's images in pool order (the order of their
 * addresses, §5.2.2), each image's pixels in scanline order:
 *   pixel(l, image, i, j) = P[l] + image * cols * rows + j * w + i
 * with P[0] = 0, P[1] = root_cols * root_rows, P[l + 1] = P[l] +
 * images[l] * cols * rows (hpfc_level_info.images), `image` the rank of the
 * image's address among its level's, w = root_cols at level 0, else cols.
 * With K the most crossings a word of the file can hold (a constant of the
 * file: the largest word_bits of its levels in the compact layout, where a
 * crossing takes at least one bit, the largest (word_bits - 4) / 4 in the
 * paper's), a dart's index is pixel * K + crossing and a vertex's
 * pixel * K + local (a word has no more vertices than crossings). Distinct
 * darts (vertices) have distinct indices.
 *
 * hpfc_key_index_bound: both indices are below total pixels * K: a visited
 * bitmap takes that many bits (data/delaunay-4000 packed by default, in
 * the compact layout: 9,616 pixels, K = 56: 538,496 bits, 66 KiB, for
 * 19,154 darts). HPFC_E_LIMIT when the product does not fit 64 bits (the
 * key operators still work).
 * hpfc_dart_index / hpfc_vertex_index: the index of a key. The
 * *_indexed operators: hpfc_key_twin/next/prev that also give the
 * result's dart index, read from where the cache found the result.
 *
 * Statuses as the key calls' (a key naming no dart, vertex: HPFC_E_ARG;
 * also a NULL index), and HPFC_E_LIMIT as above. All build the parent
 * index if needed. Cost: a key whose pixel the cache holds costs one hash
 * probe and a few loads; an _indexed operator costs its operator's work
 * (the result's pixel id is kept beside its answer); otherwise as a key
 * call that resolves its key. */
HPFC_API int hpfc_key_index_bound(hpfc_walker *w, uint64_t *darts, uint64_t *vertices);
HPFC_API int hpfc_dart_index(hpfc_walker *w, uint64_t dart_key, uint64_t *index);
HPFC_API int hpfc_vertex_index(hpfc_walker *w, uint64_t vertex_key, uint64_t *index);
HPFC_API int hpfc_key_twin_indexed(hpfc_walker *w, uint64_t dart_key, uint64_t *out_key,
                                   uint64_t *out_index);
HPFC_API int hpfc_key_next_indexed(hpfc_walker *w, uint64_t dart_key, uint64_t *out_key,
                                   uint64_t *out_index);
HPFC_API int hpfc_key_prev_indexed(hpfc_walker *w, uint64_t dart_key, uint64_t *out_key,
                                   uint64_t *out_index);

/* Iteration over the word pixels of the file in depth-first order (each
 * image in scanline order): start with hpfc_leaf_first, then call
 * hpfc_leaf_next until it returns HPFC_E_NO_PIXEL. On an untrusted file,
 * stop with an error after more leaves than the levels' word_pixels add up
 * to: a corrupt file can point several refined pixels at one image. */
HPFC_API int hpfc_leaf_first(const hpfc_file *file, hpfc_pixel *px);
HPFC_API int hpfc_leaf_next(const hpfc_file *file, hpfc_pixel *px);

/* ------------------------------------------------------------------------
 * Faces (spec/hpfc-format.md, "Faces"). A face with holes is one face with
 * several boundary loops. hpfc_faces_build groups every dart and every
 * private pixel into its face by a flood fill over the file's pixels (O(file),
 * no table written by the writer): sidewalks that continue each other,
 * stretches of a pixel's boundary between two crossings, and crossing-free
 * stretches of roads all join one face. Face 0 is the unbounded face.
 * ------------------------------------------------------------------------ */
typedef struct hpfc_faces hpfc_faces;

/* Memory: 8 bytes per k_w bits of every level's pool (a table of the
 * leaves by position, about 9 bytes a leaf) and 4 bytes per crossing and
 * per private leaf (8 past 2^31 of them); bench/README.md has a continental
 * map's figures. HPFC_E_CORRUPT on a file whose pixels contradict each
 * other, HPFC_E_LIMIT past 2^24 crossings in one leaf or 2^40 crossings in
 * all, HPFC_E_NOMEM. */
HPFC_API int hpfc_faces_build(const hpfc_file *file, hpfc_faces **out);
/* The same faces, numbered on up to `threads` threads (0 or 1: the calling
 * thread alone; at most 64), the calling thread among them: the same
 * answers and statuses as hpfc_faces_build whatever the count, faster on
 * a large map when the threads have cores of their own (1.5-1.6x on two
 * for a continental map; bench/README.md). Adds 772 bytes per 4,096
 * leaves and a walker a thread. A thread that cannot be started leaves its
 * share to the others. */
HPFC_API int hpfc_faces_build_threads(const hpfc_file *file, unsigned threads, hpfc_faces **out);
HPFC_API void hpfc_faces_free(hpfc_faces *faces);
/* The number of faces (ids 0 .. count - 1). */
HPFC_API uint64_t hpfc_faces_face_count(const hpfc_faces *faces);
/* The face on the right of a dart, given by its key: statuses and cost as
 * every key call's (a key naming no dart: HPFC_E_ARG), then one lookup.
 * The walker resolves the key (only it can find a slot's path, by its
 * parent index); `faces` must come from hpfc_faces_build on the walker's
 * file. */
HPFC_API int hpfc_faces_key_face(const hpfc_faces *faces, hpfc_walker *w, uint64_t dart_key,
                                 hpfc_id *face);
/* The face holding a private pixel (HPFC_E_ARG if px is not private). */
HPFC_API int hpfc_faces_pixel_face(const hpfc_faces *faces, const hpfc_pixel *px,
                                   hpfc_id *face);
/* Binds faces a write handed out (hpfc_write_options.faces_out) to the
 * file it wrote, opened: HPFC_E_ARG when they are bound already or when
 * the file's levels or pools are not those they were numbered on (each
 * level's counts, widths and pool size, and its pool's CRC-32C, read here:
 * O(the pools)). */
HPFC_API int hpfc_faces_attach(hpfc_faces *faces, const hpfc_file *file);

/* ------------------------------------------------------------------------
 * Source features (spec/hpfc-format.md §6.2, the FEAT section): which
 * feature of the packed GIS layers each face belongs to. Read in place from
 * the file; every access is bounds-checked (HPFC_E_CORRUPT on a corrupt
 * table). Without a FEAT section these return HPFC_E_NO_SECTION; a feature,
 * layer or face id out of range is HPFC_E_ARG. Strings point into the file
 * and are not NUL-terminated.
 * ------------------------------------------------------------------------ */
typedef struct hpfc_features_info {
    uint32_t features, faces, layers;
    uint32_t links;               /* face-to-feature links in all */
    const char *key_field;        /* NULL when packed without a key field */
    size_t key_field_len;
} hpfc_features_info;

typedef struct hpfc_feature {
    int64_t fid;                  /* the feature's id in its source layer */
    uint32_t layer;
    const char *key;              /* NULL for no key field or a null value */
    size_t key_len;
} hpfc_feature;

HPFC_API int hpfc_file_get_features_sized(const hpfc_file *file, hpfc_features_info *out,
                                          size_t size);
#define hpfc_file_get_features(file, out) \
    hpfc_file_get_features_sized((file), (out), sizeof(hpfc_features_info))
/* Feature `feature`'s record: its source fid, layer and key. */
HPFC_API int hpfc_file_get_feature_sized(const hpfc_file *file, hpfc_id feature,
                                         hpfc_feature *out, size_t size);
#define hpfc_file_get_feature(file, feature, out) \
    hpfc_file_get_feature_sized((file), (feature), (out), sizeof(hpfc_feature))
HPFC_API int hpfc_layer_name(const hpfc_file *file, uint32_t layer, const char **name,
                             size_t *len);
/* The features of face `face` (an id of hpfc_faces_build): *count of them,
 * then the k-th (k < count, else HPFC_E_ARG), in ascending feature ids. */
HPFC_API int hpfc_face_feature_count(const hpfc_file *file, hpfc_id face, uint32_t *count);
HPFC_API int hpfc_face_feature_id(const hpfc_file *file, hpfc_id face, uint32_t k,
                                  hpfc_id *feature);

/* ------------------------------------------------------------------------
 * Stored face labels (spec/hpfc-format.md §6.5, the LABL section, 1.2):
 * the face of every region of every leaf and the edge id of every
 * crossing, written by the writer so that a query needs no
 * hpfc_faces_build. Each call reads the pixels of one descent (the leaf's
 * number comes from the descent, O(levels)) and the leaf's own record,
 * never another leaf. Face ids are those of hpfc_faces_build (§3.11), edge
 * ids the input graph's edge indices (hpfc_graph_add_edge order).
 *
 * A leaf's *stretches* are the pieces of its boundary between consecutive
 * crossings: stretch t runs clockwise from crossing t - 1 (cyclically) to
 * crossing t; a private leaf has one, stretch 0. Its *regions* are the
 * parts of the pixel its components cut it into, numbered by their
 * smallest stretch; a private leaf has one region, a stabbed leaf of n
 * crossings and c components n - c + 1.
 *
 * Without a LABL section these return HPFC_E_NO_SECTION; a record that
 * contradicts the map's layout (a face id >= faces, an edge id >= edges,
 * a record outside the section, samples that do not lead to the pixel)
 * gives HPFC_E_CORRUPT. hpfc-inspect --verify compares every stored label
 * with hpfc_faces_build's.
 * ------------------------------------------------------------------------ */
typedef struct hpfc_labels_info {
    uint64_t faces, edges, leaves;
    uint32_t face_bits, edge_bits;  /* widths of one face id, one edge id */
    uint64_t section_bytes;         /* the whole section */
    uint64_t label_bits;            /* the records */
    uint64_t directory_bits;        /* the records' offsets */
    uint64_t rank_bits;             /* the leaf-number samples */
} hpfc_labels_info;

HPFC_API int hpfc_file_get_labels_sized(const hpfc_file *file, hpfc_labels_info *out,
                                        size_t size);
#define hpfc_file_get_labels(file, out) \
    hpfc_file_get_labels_sized((file), (out), sizeof(hpfc_labels_info))
/* The faces of a leaf's regions, in region order: *count of them (1 for a
 * private leaf); faces NULL asks only the count; cap too small is
 * HPFC_E_BUFFER_SMALL with *count set. A point located in a private leaf is in
 * faces[0]; in a stabbed one, in one of them. */
HPFC_API int hpfc_label_leaf_faces(const hpfc_file *file, const hpfc_pixel *leaf,
                                   hpfc_id *faces, size_t cap, size_t *count);
/* The face along stretch `stretch` of a leaf. */
HPFC_API int hpfc_label_stretch_face(const hpfc_file *file, const hpfc_pixel *leaf,
                                     uint32_t stretch, hpfc_id *face);
/* The edge id of crossing `crossing` of a leaf. */
HPFC_API int hpfc_label_crossing_edge(const hpfc_file *file, const hpfc_pixel *leaf,
                                      uint32_t crossing, hpfc_id *edge);
/* The face on the right of a dart (hpfc_faces_key_face's answer) and the
 * id of its edge, given by its key: statuses and cost as every key call's,
 * then the stored label. The walker names the file and finds the key's
 * leaf with its path from the root, which the leaf's number needs. */
HPFC_API int hpfc_label_key_face(hpfc_walker *w, uint64_t dart_key, hpfc_id *face);
HPFC_API int hpfc_label_key_edge(hpfc_walker *w, uint64_t dart_key, hpfc_id *edge);
/* A leaf's number: its rank among the word pixels of its level, in pool
 * order (images in the order they lie in the pool, each in scanline
 * order). O(levels) with a LABL section, else a walk over the level's pool
 * up to the leaf. */
HPFC_API int hpfc_leaf_number(const hpfc_file *file, const hpfc_pixel *leaf, uint64_t *number);

/* The stored labels against the map (hpfc-inspect --verify): the face
 * count; every rank sample recounted from the pools; every leaf's number
 * distinct; each record right after the previous one, the last ending the
 * label stream; every stretch's face equal to faces' (hpfc_faces_build on
 * the same file); every edge id below the edge count and equal on both
 * sides of its road. HPFC_OK when all agree; HPFC_E_CORRUPT with
 * report->message naming the first disagreement; HPFC_E_NO_SECTION,
 * HPFC_E_NOMEM. O(file). */
typedef struct hpfc_labels_report {
    uint64_t leaves_checked, labels_checked;
    char message[240];
} hpfc_labels_report;
HPFC_API int hpfc_labels_verify(const hpfc_file *file, const hpfc_faces *faces,
                                hpfc_labels_report *report);

/* The SHIX section (format 1.3, spec §6.8: each face's edges, each
 * feature's faces and edges, which hpfc_shapes reads instead of inverting
 * LABL, FEAT and EDGF at create) against the sections it inverts
 * (hpfc-inspect --verify): its counts and tables are the ones the writer
 * derives, row for row. HPFC_OK; HPFC_E_CORRUPT with report->message
 * naming the first disagreement; HPFC_E_NO_SECTION without SHIX. O(file);
 * allocates nothing. */
typedef struct hpfc_index_report {
    uint64_t rows_checked;
    char message[240];
} hpfc_index_report;
HPFC_API int hpfc_index_verify(const hpfc_file *file, hpfc_index_report *report);

/* ------------------------------------------------------------------------
 * Attributes (spec/hpfc-format.md §6.3, the ATTR section): typed columns,
 * one row per feature of the FEAT section, each value read in O(1) from
 * the mapped file. Every access is bounds-checked (HPFC_E_CORRUPT on a
 * corrupt section); without an ATTR section these return
 * HPFC_E_NO_SECTION; a column or feature out of range is HPFC_E_ARG.
 * Names and strings point into the file and are not NUL-terminated.
 * ------------------------------------------------------------------------ */
typedef struct hpfc_attrs_info {
    uint64_t features;       /* rows: FEAT's feature count */
    uint64_t columns;
    uint64_t string_bytes;   /* the names' and string values' bytes */
    uint64_t section_bytes;  /* the whole section */
} hpfc_attrs_info;

HPFC_API int hpfc_file_get_attrs_sized(const hpfc_file *file, hpfc_attrs_info *out,
                                       size_t size);
#define hpfc_file_get_attrs(file, out) \
    hpfc_file_get_attrs_sized((file), (out), sizeof(hpfc_attrs_info))
HPFC_API int hpfc_attr_column(const hpfc_file *file, uint32_t column, const char **name,
                              size_t *name_len, int *type);
/* The column named name[0 .. len) (HPFC_E_ARG when there is none). */
HPFC_API int hpfc_attr_find(const hpfc_file *file, const char *name, size_t len,
                            uint32_t *column);
/* The value of column `column` for feature `feature`. */
HPFC_API int hpfc_file_get_attr_value(const hpfc_file *file, hpfc_id feature, uint32_t column,
                                      hpfc_attr_value *out);

/* ------------------------------------------------------------------------
 * Features of edges (spec/hpfc-format.md §6.4, the EDGF section): which
 * features' lines or rings each edge of the map lies along, as links from
 * edges to features; edge ids are the input graph's edge indices. Same
 * error rules as the face accessors.
 * ------------------------------------------------------------------------ */
typedef struct hpfc_edge_links_info {
    uint64_t edges;          /* the map's edge count */
    uint64_t features;       /* FEAT's feature count */
    uint64_t links;          /* edge-to-feature links in all */
    uint64_t section_bytes;  /* the whole section */
} hpfc_edge_links_info;

HPFC_API int hpfc_file_get_edge_links_sized(const hpfc_file *file, hpfc_edge_links_info *out,
                                            size_t size);
#define hpfc_file_get_edge_links(file, out) \
    hpfc_file_get_edge_links_sized((file), (out), sizeof(hpfc_edge_links_info))
/* The features along edge `edge`: *count of them, then the k-th (k <
 * count, else HPFC_E_ARG), in ascending feature ids. */
HPFC_API int hpfc_edge_feature_count(const hpfc_file *file, hpfc_id edge, uint32_t *count);
HPFC_API int hpfc_edge_feature_id(const hpfc_file *file, hpfc_id edge, uint32_t k,
                                  hpfc_id *feature);

/* ------------------------------------------------------------------------
 * Exact geometry (spec/hpfc-format.md §6.6, the GEOM section): the input
 * graph's lattice coordinates, read in O(1) per point from the mapped file.
 * Vertex ids are the input graph's vertex indices (hpfc_graph_add_vertex
 * order, `.pfc` `v` records), edge ids its edge indices (as LABL's).
 * Coordinates are absolute lattice coordinates, the numbers the graph was
 * given: user coordinates are lattice * 10^unit_exp10. Without a GEOM
 * section these return HPFC_E_NO_SECTION; an id out of range is HPFC_E_ARG;
 * a section that contradicts itself or the map HPFC_E_CORRUPT.
 * ------------------------------------------------------------------------ */
typedef struct hpfc_geometry_info {
    uint64_t vertices;       /* V: vertices of the input graph */
    uint64_t edges;          /* E: edges of the input graph (LABL's edge count) */
    uint64_t points;         /* interior (shape) points of all edges */
    uint64_t section_bytes;  /* the whole section */
} hpfc_geometry_info;

HPFC_API int hpfc_file_get_geometry_sized(const hpfc_file *file, hpfc_geometry_info *out,
                                          size_t size);
#define hpfc_file_get_geometry(file, out) \
    hpfc_file_get_geometry_sized((file), (out), sizeof(hpfc_geometry_info))
HPFC_API int hpfc_geometry_vertex(const hpfc_file *file, hpfc_id vertex, int64_t *x,
                                  int64_t *y);
/* The smallest box holding every vertex and every shape point, in lattice
 * coordinates (box: x0, y0, x1, y1, corners included). Exact, yet without
 * reading every point: each block of GEOM's columns stores its base (at
 * most its values) and width (its values at most base + 2^width - 1), so
 * only the blocks whose bounds could still widen the box are read; for
 * files whose bases are their blocks' minima (spec §6.6 "Writers"), a
 * few blocks a side. O(points) at worst. */
HPFC_API int hpfc_geometry_bounds(const hpfc_file *file, int64_t box[4]);
/* Edge `edge` runs from vertex *u to vertex *v through *point_count points,
 * its ends included (2 for a straight edge). */
HPFC_API int hpfc_geometry_edge(const hpfc_file *file, hpfc_id edge, hpfc_id *u, hpfc_id *v,
                                uint64_t *point_count);
/* Point k of an edge: k = 0 is vertex u, k = point_count - 1 vertex v. */
HPFC_API int hpfc_geometry_edge_point(const hpfc_file *file, hpfc_id edge, uint64_t k,
                                      int64_t *x, int64_t *y);
/* The faces on the left and on the right of an edge run from u to v
 * (needs LABL too). Equal for a dangling edge. */
HPFC_API int hpfc_geometry_edge_faces(const hpfc_file *file, hpfc_id edge, hpfc_id *left,
                                      hpfc_id *right);
/* The segment of its edge (k: from point k to point k + 1) on which crossing
 * `crossing` (0-based, word order) of a stabbed leaf lies. O(levels). */
HPFC_API int hpfc_geometry_crossing_segment(const hpfc_file *file, const hpfc_pixel *leaf,
                                            uint32_t crossing, uint64_t *segment);
/* The section against itself and the map (hpfc-inspect --verify, spec
 * §6.6.6): zero padding; every vertex, edge and point reads; the coordinates
 * form a valid planar map (hpfc_graph_validate); every leaf holds as many
 * vertices as its word has junctions; with LABL, every crossing's segment
 * crosses its road, in the word's order along it, with the faces
 * hpfc_geometry_edge_faces gives on its two sides. HPFC_OK; HPFC_E_CORRUPT
 * with report->message naming the first disagreement; HPFC_E_NO_SECTION;
 * HPFC_E_NOMEM. O(file) plus O(n log n) for planarity. */
typedef struct hpfc_geometry_report {
    uint64_t vertices_checked, crossings_checked;
    char message[240];
} hpfc_geometry_report;
HPFC_API int hpfc_geometry_verify(const hpfc_file *file, hpfc_geometry_report *report);

/* ------------------------------------------------------------------------
 * Exact point location (needs LABL and GEOM): the one face that contains a
 * lattice point, or, when the point lies on an edge or a vertex, the faces
 * around it, decided by exact integer predicates on the edges that cross
 * the point's leaf only. O(levels + the leaf's geometry).
 * ------------------------------------------------------------------------ */
typedef struct hpfc_point_location {
    hpfc_pixel leaf;      /* the leaf holding the point */
    int on_boundary;      /* 1: on an edge or a vertex; faces lists those around */
    int on_vertex;        /* 1: on vertex `vertex` */
    hpfc_id vertex;       /* on_vertex: its id (else HPFC_ID_NONE) */
    hpfc_id edge;         /* on an edge (not at a vertex): its id (else HPFC_ID_NONE) */
} hpfc_point_location;

/* faces[0 .. *count): the face containing (x, y) (one), or the distinct
 * faces around a boundary point in increasing order (around a vertex: the
 * faces beside its edges; on an edge: its two sides, one face for a
 * dangling edge or a bridge). The answer is spec §6.7's; ties between
 * segments and grid lines fall by the perturbation rule of §3.5. A point
 * outside the domain gives HPFC_E_NO_PIXEL and *count = 0. cap too small
 * is HPFC_E_BUFFER_SMALL with *count and *out set; faces NULL asks only the
 * count.
 * Without GEOM or LABL: HPFC_E_NO_SECTION; GEOM that contradicts the
 * leaf's word (a segment off its crossing's road, a piece leaving the
 * leaf): HPFC_E_CORRUPT. Keeps no state (threads may share the file); its
 * scratch is allocated per call (hpfc_locate_batch keeps one per array). */
HPFC_API int hpfc_locate_point(const hpfc_file *file, int64_t x, int64_t y,
                               hpfc_point_location *out, hpfc_id *faces, size_t cap,
                               size_t *count);

/* ------------------------------------------------------------------------
 * Geometry back from the file (needs GEOM and LABL; FEAT and EDGF for the
 * features): a dart's exact polyline, a face's boundary as exact rings, a
 * feature's geometry as the union of its faces or the lines along its
 * edges. Every coordinate is an absolute lattice point, exact; user
 * coordinates are lattice * 10^unit_exp10 (hpfc_user_point). No
 * floating-point value decides anything.
 *
 * Rings. A region's boundary is the set of edges with the region on
 * exactly one side (an edge with the region on both sides, a dead end or a
 * bridge inside it, is no part of it), each run with the region on its
 * left. At a vertex where several such edges meet, each edge arriving is
 * continued by the first edge leaving clockwise from it (the region's
 * corner there), and a walk that comes back to a vertex it has visited is
 * cut there into two rings; so every ring is simple (no vertex twice, the
 * first point repeated last), rings meet at most at vertices and never
 * cross, and a region pinched at a vertex gives two rings touching there.
 * A ring that runs counter-clockwise (exact signed area > 0) is an outer
 * ring; clockwise, a hole. Each hole goes with the smallest outer ring that
 * contains it. A bounded face has exactly one outer ring; the unbounded
 * face (0) only holes.
 * ------------------------------------------------------------------------ */

/* The edge of a dart, given by its key, and the way the dart runs along
 * it: *reversed 0 when it goes from the edge's u to its v, 1 when from v
 * to u. Decided exactly: which end lies in the dart's pixel, and for an
 * edge with both ends there, on which of its segments the dart's crossing
 * lies. */
HPFC_API int hpfc_geometry_key_edge(hpfc_walker *w, uint64_t dart_key, hpfc_id *edge,
                                    int *reversed);
/* The exact polyline of a dart, given by its key, from its origin to its
 * target, both included: xy[2k], xy[2k + 1] for k < *count. xy NULL asks
 * only the count; cap (points) too small is HPFC_E_BUFFER_SMALL with
 * *count set. Both: statuses and cost as every key call's, then GEOM's
 * (and LABL's) reads. */
HPFC_API int hpfc_geometry_key_points(hpfc_walker *w, uint64_t dart_key, int64_t *xy,
                                      size_t cap, size_t *count);

/* User coordinates of a lattice point: x * 10^unit_exp10, correctly
 * rounded to double. */
HPFC_API void hpfc_user_point(const hpfc_file *file, int64_t x, int64_t y, double *ux,
                              double *uy);

/* The same for n lattice points at once (xy[2k], xy[2k + 1] to
 * uv[2k], uv[2k + 1]; two arrays that do not overlap): the values
 * hpfc_user_point gives, without a call per point. */
HPFC_API void hpfc_user_points(const hpfc_file *file, const int64_t *xy, size_t n, double *uv);

/* Polygons as rings of lattice points. Polygon p is rings
 * [polygon_ring[p], polygon_ring[p + 1]): its outer ring, then its holes.
 * Rings [polygon_ring[polygon_count], ring_count) are holes that no outer
 * ring of the answer contains (the unbounded face's). Ring r is points
 * [ring_point[r], ring_point[r + 1]) of xy (2 int64 a point), closed: its
 * last point equals its first. Polylines (hpfc_shapes_feature_polylines)
 * are rings [0, ring_count) as open polylines, with polygon_count 0 and
 * polygon_ring[0] == ring_count. */
typedef struct hpfc_polygons {
    size_t polygon_count, ring_count, point_count;
    const size_t *polygon_ring;  /* polygon_count + 1 entries */
    const size_t *ring_point;    /* ring_count + 1 entries */
    const int64_t *xy;           /* 2 * point_count values */
} hpfc_polygons;

/* The index over a file's geometry that the region calls need: each
 * edge's ends and faces, each face's edges, each feature's faces and edges.
 * The last three are read in place from the file's SHIX section (format
 * 1.3, spec §6.8), each row checked as it is read, and each edge's record
 * and vertex's coordinates are read on first use, 64 at a time: with SHIX
 * the object is made in O(1) (address space for 40 bytes an edge, 24 a
 * vertex and 8 a face, touched as queries read them; fresh pages, not
 * cleared) and a query pays for the edges it meets. A file without SHIX
 * (1.2) has the tables inverted from LABL, FEAT and EDGF here, in
 * O(edges + faces + links), 16 bytes a face and 8 a feature link more.
 * The answers live in the object until its next call: one per thread.
 * Statuses:
 * HPFC_E_NO_SECTION without GEOM or LABL, HPFC_E_CORRUPT when the sections
 * disagree (an edge's face past the face count, GEOM's edge count not
 * LABL's, SHIX's counts not theirs) or claim more edges, vertices, faces
 * or shape points than their bits can hold (checked before any allocation),
 * HPFC_E_LIMIT past 2^32 - 1 vertices, edges or faces, HPFC_E_NOMEM. Safe
 * on untrusted files: every answer is bounded by the file's size. */
typedef struct hpfc_shapes hpfc_shapes;
HPFC_API int hpfc_shapes_create(const hpfc_file *file, hpfc_shapes **out);
HPFC_API void hpfc_shapes_free(hpfc_shapes *shapes);
HPFC_API uint64_t hpfc_shapes_face_count(const hpfc_shapes *shapes);

/* Caps on what one call of an hpfc_shapes may spend (as libspng's
 * spng_set_image_limits). A file's sections bound every answer, but a
 * valid or hostile file may still hold a feature of 10^8 points or put
 * every face in one window: the call would then allocate gigabytes. With
 * a cap set, a call that would pass it stops first, before it gathers the
 * points or lists the ids, and returns HPFC_E_OVER_LIMIT; the object stays
 * usable. The defaults (a field 0, or never calling
 * hpfc_shapes_set_limits) keep one call under about 300 MB:
 *   max_points  shape points one hpfc_shapes_face_polygons,
 *               _feature_polygons or _feature_polylines answer gathers
 *               (about 32 bytes each: read once, kept in the answer);
 *               HPFC_LIMIT_POINTS_DEFAULT, 2^23
 *   max_items   faces + edges + features one hpfc_shapes_window answer
 *               lists (9 bytes each); HPFC_LIMIT_ITEMS_DEFAULT, 2^24
 * HPFC_LIMIT_NONE lifts a cap. hpfc_locate_batch needs none: it keeps at
 * most 16 MB of its own whatever the number of points, and spends per
 * point the cost of one location; hpfc_locate_point and the walker calls
 * allocate in proportion to one leaf. */
typedef struct hpfc_limits {
    uint64_t max_points;
    uint64_t max_items;
} hpfc_limits;
#define HPFC_LIMIT_POINTS_DEFAULT ((uint64_t)1 << 23)
#define HPFC_LIMIT_ITEMS_DEFAULT ((uint64_t)1 << 24)
#define HPFC_LIMIT_NONE UINT64_MAX
/* Sets the caps of every later call on `shapes` (limits NULL: the
 * defaults). HPFC_E_ARG for a NULL shapes. hpfc_limits can grow (the
 * introduction, "Structs that grow"). */
HPFC_API int hpfc_shapes_set_limits_sized(hpfc_shapes *shapes, const hpfc_limits *limits,
                                          size_t limits_size);
#define hpfc_shapes_set_limits(shapes, limits) \
    hpfc_shapes_set_limits_sized((shapes), (limits), sizeof(hpfc_limits))

/* The rings of face `face` (HPFC_E_ARG past the face count), each polygon
 * an outer ring then its holes, a hole going to the smallest outer ring
 * around it. O(n log n) in the boundary's points, near-linear in
 * practice: a hole belongs to the outer ring of the region's part (faces
 * joined across edges) that surrounds it, known without geometry when
 * that part has one outer ring; otherwise it finds the outer rings whose
 * box holds its own through a tree over the boxes, and is tested against
 * a long one through an index of its segments by y. HPFC_E_CORRUPT when
 * the boundary does not close into rings. */
HPFC_API int hpfc_shapes_face_polygons(hpfc_shapes *shapes, hpfc_id face, hpfc_polygons *out);
/* The geometry of feature `feature` as the union of its faces: the
 * boundary of the faces linked to it, as above. HPFC_E_NO_SECTION without
 * FEAT; HPFC_E_ARG past the feature count; a feature with no face gives no
 * ring. */
HPFC_API int hpfc_shapes_feature_polygons(hpfc_shapes *shapes, hpfc_id feature,
                                          hpfc_polygons *out);
/* The lines of a feature: the edges EDGF links to it, joined end to end
 * through every vertex where exactly two of them meet; each polyline runs
 * the way its lowest-numbered edge goes from u to v, and a closed one
 * repeats its first point.
 * HPFC_E_NO_SECTION without EDGF. */
HPFC_API int hpfc_shapes_feature_polylines(hpfc_shapes *shapes, hpfc_id feature,
                                           hpfc_polygons *out);
/* The faces linked to a feature, ascending: *count of them (0: a line
 * feature, or one that covers no face); faces NULL asks only the count;
 * cap too small is HPFC_E_BUFFER_SMALL with *count set. HPFC_E_NO_SECTION
 * without FEAT; HPFC_E_ARG past the feature count. */
HPFC_API int hpfc_shapes_feature_faces(const hpfc_shapes *shapes, hpfc_id feature,
                                       hpfc_id *faces, size_t cap, size_t *count);

/* What each FEAT layer holds, for a reader that types and counts a layer
 * before it reads its features (a GIS driver's geometry type and feature
 * count): kinds[l] gets HPFC_KIND_POLYGONS when a feature of layer l
 * covers a face and HPFC_KIND_LINES when one covers none (a line feature,
 * or a polygon the lattice collapsed), 0 for an empty layer; counts[l]
 * (counts may be NULL) its features; layer_count is FEAT's layer count
 * (hpfc_features_info.layers), else HPFC_E_ARG. One pass over the
 * features' layers (none with one layer) and the offsets of their rows,
 * not over their faces: the faces a row lists are checked when it is read
 * (hpfc_shapes_feature_faces, HPFC_E_CORRUPT for a damaged row), so on a
 * damaged file this answers what the offsets say. HPFC_E_NO_SECTION
 * without FEAT; HPFC_E_CORRUPT for a feature's layer past the layers. */
enum { HPFC_KIND_POLYGONS = 1, HPFC_KIND_LINES = 2 };
HPFC_API int hpfc_shapes_layer_kinds(const hpfc_shapes *shapes, uint8_t *kinds,
                                     uint64_t *counts, size_t layer_count);

/* ------------------------------------------------------------------------
 * Windows: what of the map meets a rectangle (needs GEOM and LABL; FEAT or
 * EDGF for features), through the hpfc_shapes index. The window is the
 * closed lattice rectangle [x0, x1] x [y0, y1]; faces, edges and features
 * are closed sets (a face holds its border), and one meets the window when
 * they share a point. Each one found is flagged inside (it lies wholly in
 * the window) or crossing (it reaches outside). Exact: decided by integer
 * predicates on the GEOM coordinates of the leaves the window's border
 * cuts; the leaves wholly inside give their faces and edges from LABL
 * alone. The cost grows with the leaves the window meets and what it
 * returns (and, to flag a face, with the edges around it), not with the
 * file. The unbounded face (0) is never inside.
 * ------------------------------------------------------------------------ */
enum { HPFC_WINDOW_FACES = 1, HPFC_WINDOW_EDGES = 2, HPFC_WINDOW_FEATURES = 4 };

/* What a window met: ids in increasing order, each with 1 (inside) or 0
 * (crossing) in the matching *_inside array. Lists not asked for are
 * empty. Valid until the shapes object's next call. */
typedef struct hpfc_window_hits {
    size_t face_count, edge_count, feature_count;
    const hpfc_id *face, *edge, *feature;
    const uint8_t *face_inside, *edge_inside, *feature_inside;
} hpfc_window_hits;

/* `what`: HPFC_WINDOW_FACES | _EDGES | _FEATURES. HPFC_E_ARG for x0 > x1,
 * y0 > y1 or an unknown flag; HPFC_E_NO_SECTION for features without FEAT
 * and EDGF; HPFC_E_CORRUPT when the sections contradict each other. A
 * window beyond the domain meets the unbounded face. */
HPFC_API int hpfc_shapes_window(hpfc_shapes *shapes, int64_t x0, int64_t y0, int64_t x1,
                                int64_t y1, unsigned what, hpfc_window_hits *out);

/* ------------------------------------------------------------------------
 * Topology questions over the hpfc_shapes index (needs GEOM and LABL; FEAT
 * for polygon features, EDGF for line features): which features touch
 * which, the nearest edge to a point, the union of a set of features and
 * the borders between groups of them. Each is a walk over the stored map
 * that touches what it returns (and, for the nearest edge, the pixels
 * nearer than it); answers live in the shapes object until its next call
 * (one object per thread). Safe on untrusted files: a damaged section
 * gives HPFC_E_CORRUPT, never a read outside the file.
 *
 * A feature's border is the set of edges it covers exactly one side of
 * (one of the edge's two faces is the feature's, the other not), for a
 * feature with faces; for a feature without faces (a line of a line
 * layer), the edges EDGF links to it. Decided from the side labels alone
 * (FEAT on each side's face, EDGF): no geometry is tested. An edge with
 * one face on both sides (a dead end, a bridge) is on no polygon
 * feature's border. Borders are whole edges: where one line ends and
 * another begins at a point of degree 2, which the map need not make a
 * vertex (hpfc-pack --vertices junctions), EDGF links the edge through it
 * to both lines, and they share that edge here.
 * ------------------------------------------------------------------------ */
enum { HPFC_TOUCH_EDGE = 1, HPFC_TOUCH_VERTEX = 2 };

/* The features that touch one feature, in increasing feature id: those
 * whose border shares an edge with its border (HPFC_TOUCH_EDGE, "rook")
 * and those whose border shares only vertices with it (HPFC_TOUCH_VERTEX;
 * "queen" is both kinds), each with the length of the shared edges
 * (Euclidean, lattice units, summed segment by segment in double; 0 for a
 * vertex) and the shared edges themselves (ascending), from which a
 * caller measures the border in its own metric (geodesic metres, say). */
typedef struct hpfc_neighbours {
    size_t count;
    const hpfc_id *feature;
    const uint8_t *touch;       /* HPFC_TOUCH_EDGE or HPFC_TOUCH_VERTEX */
    const double *length;
    const size_t *edge_start;   /* count + 1: neighbour k's shared edges are */
    const hpfc_id *edge;        /* edge[edge_start[k] .. edge_start[k + 1]) */
} hpfc_neighbours;

/* Feature `feature`'s neighbours. Cost: its border's edges, the edges at
 * their end vertices and those edges' faces' features (FEAT, O(1) each);
 * the first call builds a table of the edges at each vertex (O(edges),
 * 4 bytes an edge end and 8 a vertex, kept with the object).
 * HPFC_E_NO_SECTION without FEAT and EDGF; HPFC_E_ARG past the feature
 * count; HPFC_E_NOMEM. */
HPFC_API int hpfc_shapes_feature_neighbours(hpfc_shapes *shapes, hpfc_id feature,
                                            hpfc_neighbours *out);

/* Every pair of touching features at once: pair k is features a[k] < b[k],
 * in increasing (a, b), touching by touch[k] with the shared length as
 * above. */
typedef struct hpfc_adjacency {
    size_t count;
    const hpfc_id *a, *b;
    const uint8_t *touch;       /* HPFC_TOUCH_EDGE or HPFC_TOUCH_VERTEX */
    const double *length;
} hpfc_adjacency;

/* `touch`: HPFC_TOUCH_EDGE for the pairs that share an edge (rook), with
 * HPFC_TOUCH_VERTEX also those that share only a vertex (queen). One pass
 * over the edges and one over the vertices: O(edges + the pairs each edge
 * and vertex gives, sorted). HPFC_E_ARG without HPFC_TOUCH_EDGE or with an
 * unknown flag; other statuses as hpfc_shapes_feature_neighbours. */
HPFC_API int hpfc_shapes_adjacency(hpfc_shapes *shapes, unsigned touch, hpfc_adjacency *out);

/* The edge of the map nearest to a lattice point: the closest point on
 * it (lattice coordinates, rounded to double: the point is exact, the
 * rounding within a few units in the last place), on segment
 * `segment` (from point segment to point segment + 1), and the distance
 * (lattice units, rounded; the decision is exact). Ties between edges at
 * the same exact distance go to the lowest edge id, on one edge to the
 * lowest segment. */
typedef struct hpfc_nearest {
    hpfc_id edge;
    uint64_t segment;
    double x, y;
    double distance;
} hpfc_nearest;

/* Edges nearest to (x, y), |x| and |y| at most HPFC_LATTICE_MAX (else
 * HPFC_E_ARG). feature HPFC_ID_NONE: any edge of the map, searched best
 * first over the tree: pixels in the order of their box's distance to the
 * point (branch and bound, children nearest first; the root image halved
 * as a virtual tree over its pixels), each leaf's crossings giving the
 * edges' segments in it, until the next pixel lies farther than the
 * nearest edge found: the cost grows with the
 * leaves nearer than the answer, not with the map. Otherwise the nearest
 * edge of that feature's border (above), compared one by one: O(its
 * border's points). Squared distances are rationals compared exactly
 * (products of up to 264 bits, in 64-bit limbs). HPFC_E_NO_SECTION for a
 * feature without FEAT and EDGF; HPFC_E_ARG for a feature past the count
 * or one with no border (out->edge HPFC_ID_NONE is never returned with
 * HPFC_OK). */
HPFC_API int hpfc_shapes_nearest_edge(hpfc_shapes *shapes, int64_t x, int64_t y,
                                      hpfc_id feature, hpfc_nearest *out);

/* The edges within distance d of a point: ids ascending, each with its
 * distance (lattice units, rounded; d is compared exactly with the
 * rational distance). */
typedef struct hpfc_edge_hits {
    size_t count;
    const hpfc_id *edge;
    const double *distance;
} hpfc_edge_hits;

/* 0 <= d <= 2 * HPFC_LATTICE_MAX and the point as for
 * hpfc_shapes_nearest_edge (else HPFC_E_ARG). Best first over the tree as
 * hpfc_shapes_nearest_edge, every pixel whose box lies within d. */
HPFC_API int hpfc_shapes_edges_within(hpfc_shapes *shapes, int64_t x, int64_t y, int64_t d,
                                      hpfc_edge_hits *out);

/* The union of a set of features (features[0 .. n), repeats allowed) as
 * exact polygons: the boundary of the faces linked to any of them, so the
 * edges whose two sides both belong to the set are dropped; rings as in
 * "Rings" above, the same for the same faces as
 * hpfc_shapes_feature_polygons. Dissolving a layer by an attribute is a
 * call per value. O(the set's faces and their edges, n log n in the
 * rings). HPFC_E_NO_SECTION without FEAT; HPFC_E_ARG for an id past the
 * feature count. */
HPFC_API int hpfc_shapes_features_polygons(hpfc_shapes *shapes, const hpfc_id *features,
                                           size_t n, hpfc_polygons *out);

/* The borders between groups of features, as line strings. Each feature
 * is in group group[k] (n must be the feature count), or in none when
 * group[k] is HPFC_GROUP_NONE; group NULL puts each feature in a group of
 * its own. A side of an edge is the set of groups of the features of the
 * face on that side. Edges are kept by `sides`:
 * HPFC_MESH_INTERIOR, both sides in some group and the two sets differ
 * (with groups from a field's values: the borders between different
 * values); HPFC_MESH_EXTERIOR, exactly one side in no group (the
 * coverage's outline). The edges kept are joined end to end through every
 * vertex where exactly two of them meet, as
 * hpfc_shapes_feature_polylines joins a feature's (polylines: ring_count
 * lines, no polygon). One pass over the edges. HPFC_E_NO_SECTION without
 * FEAT; HPFC_E_ARG for no or an unknown flag, or a group array whose n is
 * not the feature count. */
#define HPFC_GROUP_NONE UINT32_MAX
enum { HPFC_MESH_INTERIOR = 1, HPFC_MESH_EXTERIOR = 2 };
HPFC_API int hpfc_shapes_mesh(hpfc_shapes *shapes, const uint32_t *group, size_t n,
                              unsigned sides, hpfc_polygons *out);

/* ------------------------------------------------------------------------
 * Experimental (the introduction, "Experimental calls"): seen only with
 * HPFC_EXPERIMENTAL defined before this header is included; may change
 * between minor versions.
 * ------------------------------------------------------------------------ */
#ifdef HPFC_EXPERIMENTAL

/* ---- the builder's tree, pixel by pixel -------------------------------- */

/* Images of a level are numbered 0, 1, ... in pool order: the children of
 * level l's refined pixels, in the order those pixels appear in level l
 * (image by image, each image in scanline order: j = 0 (north) first,
 * i = 0 (west) first within a row). Level 0 has the root image only. */
HPFC_API size_t hpfc_tree_image_count(const hpfc_tree *tree, uint32_t level);

typedef struct hpfc_tree_pixel {
    int type;                  /* HPFC_PIXEL_WORD or HPFC_PIXEL_REFINED */
    uint32_t child;            /* refined: image index at the next level */
    const char *word;          /* word: symbols of "+=[]()Y", not 0-ended */
    uint32_t word_len;
    /* word: for crossing k (k-th non-'+' symbol), the input edge it lies on,
     * and the index of the edge segment (0 = the one leaving vertex u). */
    const uint32_t *cross_edge;
    const uint32_t *cross_segment;
    /* bounds of the pixel in the graph's lattice: [x0, x1) x [y0, y1) */
    int64_t x0, y0, x1, y1;
} hpfc_tree_pixel;

/* Pixel (i, j) of image `image` of level `level`. */
HPFC_API int hpfc_tree_get_pixel(const hpfc_tree *tree, uint32_t level,
                                 size_t image, uint32_t i, uint32_t j,
                                 hpfc_tree_pixel *out);

/* ---- the path form of darts and vertices --------------------------------
 *
 * An hpfc_dart (hpfc_vertex) is a key spelled out: its word pixel with the
 * whole path from the root, and its crossing (local vertex id). Get one
 * from a key with hpfc_dart_from_key (hpfc_vertex_from_key), and its key
 * back with hpfc_dart_key (hpfc_vertex_key). The operators on it are the
 * key calls' counterparts (the key calls are defined by them); a caller
 * who only traverses never needs them. */
typedef struct hpfc_vertex {
    hpfc_pixel pixel;   /* the word pixel holding the vertex */
    uint32_t local;     /* rank of its component among the pixel's junctions */
} hpfc_vertex;

typedef struct hpfc_dart {
    hpfc_pixel pixel;   /* the word pixel holding the dart's origin */
    uint32_t crossing;  /* k: the dart leaves the pixel at its crossing k */
} hpfc_dart;

/* The dart (vertex) a key names, with its pixel's path from the root: the
 * value whose hpfc_dart_key (hpfc_vertex_key) is `key`. Statuses and cost
 * as the key calls' (the path is copied from the cache when it holds the
 * key's pixel). */
HPFC_API int hpfc_dart_from_key(hpfc_walker *w, uint64_t key, hpfc_dart *out);
HPFC_API int hpfc_vertex_from_key(hpfc_walker *w, uint64_t key, hpfc_vertex *out);

/* The path-form operators: the index-th vertex of a word pixel; a vertex's
 * degree and index-th outgoing dart, clockwise; twin, next, prev, origin
 * and target. Statuses as the key calls' (a path that names no word
 * pixel, a crossing or local id that names no dart or vertex of it:
 * HPFC_E_ARG). */
HPFC_API int hpfc_pixel_vertex(hpfc_walker *w, const hpfc_pixel *px, uint32_t index,
                               hpfc_vertex *out);
HPFC_API int hpfc_vertex_degree(hpfc_walker *w, const hpfc_vertex *v, uint32_t *degree);
HPFC_API int hpfc_vertex_dart(hpfc_walker *w, const hpfc_vertex *v, uint32_t index,
                              hpfc_dart *out);
HPFC_API int hpfc_dart_twin(hpfc_walker *w, const hpfc_dart *d, hpfc_dart *out);
HPFC_API int hpfc_dart_next(hpfc_walker *w, const hpfc_dart *d, hpfc_dart *out);
HPFC_API int hpfc_dart_prev(hpfc_walker *w, const hpfc_dart *d, hpfc_dart *out);
HPFC_API int hpfc_dart_origin(hpfc_walker *w, const hpfc_dart *d, hpfc_vertex *out);
HPFC_API int hpfc_dart_target(hpfc_walker *w, const hpfc_dart *d, hpfc_vertex *out);

/* Stable identifiers, usable as hash keys: equal for the same vertex/dart
 * whichever way it was reached, distinct otherwise, the same across opens
 * of the same file. HPFC_KEY_INVALID when the value's pixel path names no
 * pixel of the file (a NULL argument too); the key of a pixel that is no
 * word pixel, or of a local id it does not have, is not checked here: the
 * key operators answer HPFC_E_ARG for it. */
HPFC_API uint64_t hpfc_vertex_key(const hpfc_file *file, const hpfc_vertex *v);
HPFC_API uint64_t hpfc_dart_key(const hpfc_file *file, const hpfc_dart *d);

/* The per-dart questions on a path-form dart, the counterparts of
 * hpfc_faces_key_face, hpfc_label_key_face, hpfc_label_key_edge,
 * hpfc_geometry_key_edge and hpfc_geometry_key_points (which answer as
 * these do on hpfc_dart_from_key's dart). A dart whose pixel is refined
 * or has no crossing d->crossing: HPFC_E_ARG. */
HPFC_API int hpfc_faces_dart_face(const hpfc_faces *faces, const hpfc_dart *d, hpfc_id *face);
HPFC_API int hpfc_label_dart_face(const hpfc_file *file, const hpfc_dart *d, hpfc_id *face);
HPFC_API int hpfc_label_dart_edge(const hpfc_file *file, const hpfc_dart *d, hpfc_id *edge);
HPFC_API int hpfc_geometry_dart_edge(const hpfc_file *file, const hpfc_dart *d, hpfc_id *edge,
                                     int *reversed);
HPFC_API int hpfc_geometry_dart_points(const hpfc_file *file, const hpfc_dart *d, int64_t *xy,
                                       size_t cap, size_t *count);

/* ---- a word taken apart (spec §3.6-§3.8, §5.2.3) -------------------------
 *
 * The components of a word pixel's word as the traversal sees them, for a
 * tool that draws or explains one leaf (hpfc-inspect --pixel, --render):
 * get the symbols with hpfc_pixel_word, then parse them here. The parser
 * grows its arrays to any word's length and owns them; a parse's
 * hpfc_word_parts points into it until its next parse or free. */
typedef struct hpfc_word_parser hpfc_word_parser;

#define HPFC_WORD_NONE UINT32_MAX /* no local vertex: a stabbing's component */

typedef struct hpfc_word_parts {
    uint32_t crossings;          /* the symbols other than '+' */
    uint32_t road_first[5];      /* first crossing of roads W, N, E, S; then crossings */
    uint32_t components;         /* junctions and stabbings */
    uint32_t junctions;          /* the pixel's vertices */
    const uint32_t *component;        /* per crossing: its component */
    const uint32_t *component_first;  /* per component: first crossing in word order */
    const uint32_t *component_last;   /* per component: last crossing in word order */
    const uint32_t *component_size;   /* per component: crossings (a junction's degree) */
    const uint32_t *component_vertex; /* per component: local vertex id, or HPFC_WORD_NONE */
} hpfc_word_parts;

HPFC_API int hpfc_word_parser_create(hpfc_word_parser **out);
HPFC_API void hpfc_word_parser_free(hpfc_word_parser *parser);

/* Parses `len` symbols of "+=[]()Y" with the one-pass stack of spec §3.8:
 * HPFC_OK; HPFC_E_CORRUPT for a word outside the grammar (then only
 * crossings and road_first are filled, as hpfc_word_count_roads gives
 * them); HPFC_E_NOMEM; HPFC_E_ARG for a NULL argument. O(len). */
HPFC_API int hpfc_word_parse(hpfc_word_parser *parser, const char *symbols, size_t len,
                             hpfc_word_parts *out);

/* The crossings of each road straight from the symbols, grammar or not:
 * road_first as hpfc_word_parse gives it. */
HPFC_API void hpfc_word_count_roads(const char *symbols, size_t len, uint32_t road_first[5]);

/* The fixed code of one symbol in the paper layout (spec §5.2.3): 0 for
 * '+', 0x8 '=', 0x9 '[', 0xA ']', 0xB '(', 0xC 'Y', 0xD ')'; -1 for any
 * other byte. */
HPFC_API int hpfc_word_symbol_code(char symbol);

/* ---- counters -------------------------------------------------------- */

/* Word pixels whose word this walker has decoded so far. Without the cache
 * this is the paper's "pixels visited" (Sect. 5.1): every word an operator
 * reads; with it, a word read again from the cache does not count. */
HPFC_API uint64_t hpfc_walker_pixels_visited(const hpfc_walker *walker);

/* ---- A .pfc read in chunks, into a graph file ----------------------------
 * The parallel read of a split build (python/hpfc/_pack.py): experimental
 * while the split build's entry points settle. */
/* A .pfc text read in chunks, by many processes at once (a split build's
 * parallel read, docs/interfaces.md §8): the text cut at line starts
 * (hpfc_pfc_chunk_bounds), each chunk scanned alone for its records'
 * counts and finest digits (hpfc_pfc_chunk_scan), then, with the file's
 * digits and the counts of the chunks before it, each filled into its own
 * stretch of the graph's arrays (hpfc_pfc_chunk_fill), which a graph file
 * (below) holds. Where hpfc_pfc_parse reads a text, its chunks give the
 * same vertices, edges and points, value for value, and the same unit
 * exponent (-digits). A chunk checks what it sees alone: encoding, syntax,
 * the header (in the first chunk only), loops, the extent, edges naming
 * vertices not yet defined, zero-length segments between interior points.
 * What needs the whole text is the caller's: more than 30 digits
 * (HPFC_E_LIMIT from the fill), no edge at all, and, through
 * hpfc_graph_check_whole and hpfc_graph_validate (or a split build's
 * parts), duplicate and isolated vertices and zero-length segments at an
 * edge's ends. Messages name lines counted from the chunk's start: read
 * the whole text with hpfc_pfc_read_file to word a flaw with its line. */

/* Cuts text into at most `count` chunks of about equal length, each
 * starting at a line start, the first holding the header's line: fills
 * bounds[0 .. n] (bounds[0] = 0, bounds[n] = length; the caller's array
 * has count + 1 entries) and returns n, 0 for a NULL argument or count 0. */
HPFC_API size_t hpfc_pfc_chunk_bounds(const char *text, size_t length, size_t count,
                                      size_t *bounds);

typedef struct hpfc_pfc_chunk {
    uint64_t vertices, edges;  /* its v and e records */
    uint64_t points;           /* its edges' interior points */
    int32_t digits;            /* its finest coordinate's significant fractional digits */
} hpfc_pfc_chunk;

/* Scans text[begin, end), a chunk of hpfc_pfc_chunk_bounds (begin 0 or
 * after a line end, end the text's end or after a line end: else
 * HPFC_E_ARG). The chunk at 0 must start with the header; no other may
 * hold one. */
HPFC_API int hpfc_pfc_chunk_scan(const char *text, size_t length, size_t begin, size_t end,
                                 hpfc_pfc_chunk *out, hpfc_diag *diag);

/* Where a scanned chunk's records go: the whole text's digits (the
 * chunks' largest), the vertices and interior points of the chunks before
 * it, and the caller's arrays for this chunk's share (vxy: 2 per vertex;
 * eu, ev, eoff: 1 per edge, eoff[k] the index of edge k's first interior
 * point in the whole text; pts: 2 per interior point). box is set to the
 * chunk's points' closed box {xmin, ymin, xmax, ymax} (INT64_MAX, INT64_MAX,
 * INT64_MIN, INT64_MIN when it has none). */
typedef struct hpfc_pfc_fill {
    int32_t digits;
    uint64_t first_vertex, first_point;
    int64_t *vxy;
    uint32_t *eu, *ev;
    uint64_t *eoff;
    int64_t *pts;
    int64_t box[4];
} hpfc_pfc_fill;

/* Fills *fill from text[begin, end), which hpfc_pfc_chunk_scan gave
 * *scan: HPFC_E_ARG if the chunk's records are no longer scan's counts. */
HPFC_API int hpfc_pfc_chunk_fill(const char *text, size_t length, size_t begin, size_t end,
                                 const hpfc_pfc_chunk *scan, hpfc_pfc_fill *fill,
                                 hpfc_diag *diag);

/* A graph file: a graph's arrays in the machine's byte order after a
 * 64-byte header (docs/interfaces.md §8), written in place by the chunks
 * of a .pfc read and mapped back as a graph that lives in the page cache,
 * not in the process's own memory. hpfc_graph_file_layout gives, for the
 * counts, the header's bytes, each array's byte offset and the file's
 * size (HPFC_E_LIMIT past 2^32 - 2 vertices or edges, or past 2^58
 * points); eoff has edges + 1 entries, the last one `points`. */
typedef struct hpfc_graph_file_layout {
    uint8_t header[64];
    uint64_t vxy, eu, ev, eoff, pts;  /* int64 x 2, uint32, uint32, uint64, int64 x 2 */
    uint64_t size;
} hpfc_graph_file_layout;
HPFC_API int hpfc_graph_file_layout_of(uint64_t vertices, uint64_t edges, uint64_t points,
                                       int32_t unit_exp10, hpfc_graph_file_layout *out);

/* Maps a graph file read-only as a graph (HPFC_E_ARG from
 * hpfc_graph_add_vertex and hpfc_graph_add_edge on it), checked as
 * hpfc_graph_add_* check what they add: HPFC_E_MAGIC (another file, or
 * another byte order), HPFC_E_TRUNCATED (a size that is not the header's),
 * HPFC_E_HEADER, HPFC_E_EXTENT (a coordinate past HPFC_COORD_MAX),
 * HPFC_E_VERTEX_INDEX, HPFC_E_CORRUPT (offsets out of order), and as the
 * .pfc reader, HPFC_E_LOOP_INTERIOR (a loop of fewer than 2 interior
 * points). The check leaves none of the file's pages resident in the
 * process (they stay in the page cache): a caller that uses a few edges
 * touches only theirs. The graph has no source lines. As with hpfc_open,
 * do not change the file while it is mapped. */
HPFC_API int hpfc_graph_map_file(const char *path, hpfc_graph **out, hpfc_diag *diag);

/* ---- A split build's join, without the map's component count -------------
 * (hpfc.pack's merge, python/src/pack.c) */
/* hpfc_tree_merge_files without counting the map's components: the joined
 * tree's faces and components are 0 (hpfc_tree_get_info), not counted;
 * everything else, every check and every byte written from it are
 * hpfc_tree_merge_files's. The count is the one step of a join that needs
 * a word per edge of the map (a union-find over them: 64 MB at 1.6*10^7
 * edges, the peak of a Dask client's merge of 2*10^8 street points); what
 * stays is a bit an edge, for the check that every edge is in some part's
 * words. No writer needs the count: LABL's header gives the faces F of a
 * file written with face labels, and then C = F + V - E - 1 (Euler). */
HPFC_API int hpfc_tree_merge_files_uncounted(const char *const *paths, size_t count,
                                             hpfc_tree **out, hpfc_diag *diag);

/* The cut of hpfc_cut_create over edges [first_edge, end_edge) only (a
 * chunk's edges, routed to the parts by the process that read them);
 * HPFC_E_ARG for a range past the graph's edges. hpfc_cut_part_edges
 * gives part k's edges of that range, ascending (owned by the cut). */
HPFC_API int hpfc_cut_create_range(const hpfc_graph *graph, const hpfc_build_params *params,
                                   size_t params_size, const hpfc_domain *domain,
                                   const uint32_t *owner, uint32_t part_count, size_t first_edge,
                                   size_t end_edge, hpfc_cut **out, hpfc_diag *diag);
HPFC_API int hpfc_cut_part_edges(const hpfc_cut *cut, uint32_t part, const uint32_t **edge_ids,
                                 size_t *count);

/* A new graph of the listed edges of `graph` (ids ascending, else
 * HPFC_E_ARG) and their end vertices, renumbered in graph's order: the
 * graph hpfc_cut_part_graph gives for the same list. */
HPFC_API int hpfc_graph_copy_edges(const hpfc_graph *graph, const uint32_t *edge_ids, size_t count,
                                   hpfc_graph **out, hpfc_diag *diag);

#endif /* HPFC_EXPERIMENTAL */

/* ------------------------------------------------------------------------
 * Deprecated names. Calls renamed to follow the naming rule and the ids
 * of the introduction; the old names still compile (with a deprecation
 * warning) and will be removed at 1.0. CHANGELOG.md lists them. Those
 * that answered 32-bit feature ids or counts still do: a FEAT, ATTR or
 * EDGF section counts its features, columns, edges and links in 32 bits.
 * ------------------------------------------------------------------------ */
#if defined(__GNUC__) || defined(__clang__)
#define HPFC_DEPRECATED(use) __attribute__((deprecated("use " use)))
#else
#define HPFC_DEPRECATED(use)
#endif

HPFC_DEPRECATED("hpfc_file_check_checksums")
static inline int hpfc_file_verify_checksums(const hpfc_file *file)
{
    return hpfc_file_check_checksums(file, NULL);
}
HPFC_DEPRECATED("hpfc_file_check_checksums")
static inline int hpfc_verify_checksums(const hpfc_file *file)
{
    return hpfc_file_check_checksums(file, NULL);
}
HPFC_DEPRECATED("hpfc_file_check_pool_layout")
static inline int hpfc_check_pool_layout(const hpfc_file *file, uint32_t level, hpfc_diag *diag)
{
    return hpfc_file_check_pool_layout(file, level, diag);
}
HPFC_DEPRECATED("hpfc_file_get_features")
static inline int hpfc_file_features(const hpfc_file *file, hpfc_features_info *out)
{
    return hpfc_file_get_features(file, out);
}
HPFC_DEPRECATED("hpfc_file_get_feature")
static inline int hpfc_feature_get(const hpfc_file *file, uint32_t index, hpfc_feature *out)
{
    return hpfc_file_get_feature(file, index, out);
}
HPFC_DEPRECATED("hpfc_face_feature_id")
static inline int hpfc_face_feature(const hpfc_file *file, hpfc_id face, uint32_t k,
                                    uint32_t *feature)
{
    hpfc_id id = 0;
    int st = feature ? hpfc_face_feature_id(file, face, k, &id) : HPFC_E_ARG;
    if (st == HPFC_OK)
        *feature = (uint32_t)id;
    return st;
}
HPFC_DEPRECATED("hpfc_file_get_labels")
static inline int hpfc_file_labels(const hpfc_file *file, hpfc_labels_info *out)
{
    return hpfc_file_get_labels(file, out);
}
HPFC_DEPRECATED("hpfc_file_get_attrs")
static inline int hpfc_attr_info(const hpfc_file *file, uint32_t *features, uint32_t *columns)
{
    hpfc_attrs_info info;
    int st = features && columns ? hpfc_file_get_attrs(file, &info) : HPFC_E_ARG;
    if (st == HPFC_OK) {
        *features = (uint32_t)info.features;
        *columns = (uint32_t)info.columns;
    }
    return st;
}
HPFC_DEPRECATED("hpfc_file_get_attr_value")
static inline int hpfc_file_get_attr(const hpfc_file *file, uint32_t feature, uint32_t column,
                                     hpfc_attr_value *out)
{
    return hpfc_file_get_attr_value(file, feature, column, out);
}
HPFC_DEPRECATED("hpfc_file_get_attr_value")
static inline int hpfc_attr_get(const hpfc_file *file, uint32_t feature, uint32_t column,
                                hpfc_attr_value *out)
{
    return hpfc_file_get_attr_value(file, feature, column, out);
}
HPFC_DEPRECATED("hpfc_file_get_edge_links")
static inline int hpfc_edge_features_info(const hpfc_file *file, uint32_t *edges,
                                          uint32_t *links)
{
    hpfc_edge_links_info info;
    int st = edges && links ? hpfc_file_get_edge_links(file, &info) : HPFC_E_ARG;
    if (st == HPFC_OK) {
        *edges = (uint32_t)info.edges;
        *links = (uint32_t)info.links;
    }
    return st;
}
HPFC_DEPRECATED("hpfc_edge_feature_id")
static inline int hpfc_edge_feature(const hpfc_file *file, hpfc_id edge, uint32_t k,
                                    uint32_t *feature)
{
    hpfc_id id = 0;
    int st = feature ? hpfc_edge_feature_id(file, edge, k, &id) : HPFC_E_ARG;
    if (st == HPFC_OK)
        *feature = (uint32_t)id;
    return st;
}
HPFC_DEPRECATED("hpfc_file_get_geometry")
static inline int hpfc_file_geometry(const hpfc_file *file, hpfc_geometry_info *out)
{
    return hpfc_file_get_geometry(file, out);
}
HPFC_DEPRECATED("hpfc_faces_face_count")
static inline uint64_t hpfc_faces_count(const hpfc_faces *faces)
{
    return hpfc_faces_face_count(faces);
}
HPFC_DEPRECATED("hpfc_faces_key_face")
static inline int hpfc_faces_of_key(const hpfc_faces *faces, hpfc_walker *w, uint64_t dart_key,
                                    hpfc_id *face)
{
    return hpfc_faces_key_face(faces, w, dart_key, face);
}
HPFC_DEPRECATED("hpfc_faces_pixel_face")
static inline int hpfc_faces_of_private_pixel(const hpfc_faces *faces, const hpfc_pixel *px,
                                              hpfc_id *face)
{
    return hpfc_faces_pixel_face(faces, px, face);
}
HPFC_DEPRECATED("hpfc_label_key_face")
static inline int hpfc_key_label_face(hpfc_walker *w, uint64_t dart_key, hpfc_id *face)
{
    return hpfc_label_key_face(w, dart_key, face);
}
HPFC_DEPRECATED("hpfc_label_key_edge")
static inline int hpfc_key_label_edge(hpfc_walker *w, uint64_t dart_key, hpfc_id *edge)
{
    return hpfc_label_key_edge(w, dart_key, edge);
}
HPFC_DEPRECATED("hpfc_geometry_key_edge")
static inline int hpfc_key_geometry_edge(hpfc_walker *w, uint64_t dart_key, hpfc_id *edge,
                                         int *reversed)
{
    return hpfc_geometry_key_edge(w, dart_key, edge, reversed);
}
HPFC_DEPRECATED("hpfc_geometry_key_points")
static inline int hpfc_key_geometry_points(hpfc_walker *w, uint64_t dart_key, int64_t *xy,
                                           size_t cap, size_t *count)
{
    return hpfc_geometry_key_points(w, dart_key, xy, cap, count);
}
HPFC_DEPRECATED("hpfc_shapes_face_polygons")
static inline int hpfc_shapes_face(hpfc_shapes *shapes, hpfc_id face, hpfc_polygons *out)
{
    return hpfc_shapes_face_polygons(shapes, face, out);
}
HPFC_DEPRECATED("hpfc_shapes_feature_polygons")
static inline int hpfc_shapes_feature(hpfc_shapes *shapes, uint32_t feature, hpfc_polygons *out)
{
    return hpfc_shapes_feature_polygons(shapes, feature, out);
}
HPFC_DEPRECATED("hpfc_shapes_feature_polylines")
static inline int hpfc_shapes_feature_lines(hpfc_shapes *shapes, uint32_t feature,
                                            hpfc_polygons *out)
{
    return hpfc_shapes_feature_polylines(shapes, feature, out);
}
HPFC_DEPRECATED("hpfc_shapes_feature_faces")
static inline int hpfc_shapes_feature_face_count(const hpfc_shapes *shapes, uint32_t feature,
                                                 uint64_t *count)
{
    size_t n = 0;
    int st = count ? hpfc_shapes_feature_faces(shapes, feature, NULL, 0, &n) : HPFC_E_ARG;
    if (st == HPFC_OK)
        *count = n;
    return st;
}
#ifdef HPFC_EXPERIMENTAL
HPFC_DEPRECATED("hpfc_faces_dart_face")
static inline int hpfc_faces_of_dart(const hpfc_faces *faces, const hpfc_dart *d, hpfc_id *face)
{
    return hpfc_faces_dart_face(faces, d, face);
}
#endif

#ifdef __cplusplus
}
#endif
#endif /* HPFC_H */
