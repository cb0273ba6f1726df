/*
 * verify.h: the full structural and topological check of an .hpfc file
 * behind `hpfc-inspect --verify` (interfaces §3, spec §8.7).
 *
 * The check reads the file with the library's public reader and traversal
 * API only, plus the raw bytes for what no API exposes (padding). It never
 * trusts the file: every walk is bounded by the library (spec §8.2, S16) or by
 * counts this code found itself, so a corrupt file yields problems, never a
 * hang or a crash.
 */
#ifndef HPFC_VERIFY_H
#define HPFC_VERIFY_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "open_input.h"

/* Problems kept verbatim; later ones are only counted. */
#define VERIFY_MAX_PROBLEMS 32
#define VERIFY_PROBLEM_LEN 240

/* State of one group of checks. */
enum { CHECK_SKIPPED = -1, CHECK_FAILED = 0, CHECK_OK = 1 };

typedef struct verify_report {
    /* Groups, in the order they run. A group is skipped when an earlier
     * failure makes its inputs meaningless (e.g. no traversal of a file whose
     * words do not decode). */
    int format;     /* hpfc_open: header, level table, directory (§7.3) */
    int checksums;  /* every section CRC-32C (R18) */
    int structure;  /* every pixel from the root: decoding, grammar, image
                       placement, counts, k_w, zero padding (§8.7) */
    int roads;      /* both sides of every road hold the same crossings */
    int topology;   /* operators, twin / next / prev, faces */
    int euler;      /* V - E + F = 1 + C */
    int loops_ok;   /* boundary loops = F + C - 1 */
    int features;   /* the FEAT section: its face count, every entry readable */
    int labels;     /* the LABL section: every stored label equals the recomputed one */
    int geometry;   /* the GEOM section: planar, in its leaves, on its roads (§6.6.6) */
    int index;      /* the SHIX section: the inverse of LABL, FEAT and EDGF (§6.8.4) */

    uint16_t format_major, format_minor;
    uint32_t levels;
    uint64_t word_pixels, refined_pixels, private_pixels;
    int have_graph; /* the counts below were computed */
    uint64_t vertices, edges, faces, components, loops;
    double seconds;

    size_t problem_count;  /* all problems found */
    char problems[VERIFY_MAX_PROBLEMS][VERIFY_PROBLEM_LEN];
} verify_report;

/* verify_file flags. */
#define VERIFY_STRUCTURE_ONLY 0x1u  /* format, checksums and structure only:
                                       enough to make any walk over the tree
                                       (leaf iteration, export_map) linear */

/* Runs every check on FILE, read by input_load ("-" is standard input),
 * fewer with flags. Returns 1 when the file is valid (no problem at all), 0
 * otherwise; r->problems[0] is then the first one. Failures to read the
 * file are problems too. */
int verify_file(const char *file, unsigned flags, verify_report *r);
/* The same on bytes already read, so that a caller that goes on to open
 * them (--export-graph) reads FILE once. */
int verify_bytes(const input_bytes *b, unsigned flags, verify_report *r);

void verify_print_text(FILE *out, const char *path, const verify_report *r);
void verify_print_json(FILE *out, const char *path, const verify_report *r);

#endif
