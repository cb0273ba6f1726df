/*
 * views.h: hpfc-inspect's queries on an open file:
 *
 *   --sections      the file's map: header, level table, directory, every
 *                   section with its checksum status, each level's pool
 *   --pixel PATH    one pixel: type, word and code, roads, components,
 *                   vertices, neighbours
 *   --locate X,Y    the leaf holding a point and the faces it may lie in
 *                   (interfaces §4)
 *   --stats         histograms of word length, leaf depth, crossings per
 *                   pixel and stabbings per edge
 *
 * Each view prints text or, with `json`, one JSON object, on `out`. It
 * returns an exit status (VIEW_OK, VIEW_FAIL) and on failure a one-line
 * reason in why[]. Parsing of the arguments is separate, so that a malformed
 * argument is a usage error (VIEW_USAGE) found before the file is opened.
 */
#ifndef HPFC_INSPECT_VIEWS_H
#define HPFC_INSPECT_VIEWS_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "hpfc.h"

enum { VIEW_OK = 0, VIEW_FAIL = 1, VIEW_USAGE = 2 };

#define VIEW_WHY 256

/* Writes the reason (printf-style, one line) into why; returns VIEW_FAIL. */
int view_fail(char *why, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
/* view_fail with "what: " and the status's hpfc_strerror text. */
int view_fail_status(char *why, const char *what, int st);

/* ---- arguments (args.c) ------------------------------------------------------------ */

/* The value of option `name` at argv[*i], as "--name VALUE" or
 * "--name=VALUE" (*i moves past a separate VALUE); NULL when argv[*i] is
 * another option, and *missing set when the option is there without its
 * value. A separate VALUE that starts with '-' is a slip ("--export-graph
 * --json FILE"), except in option_numeric_value when a digit or a point
 * follows: a negative number ("--locate -5,3 FILE"). */
const char *option_value(int argc, char **argv, int *i, const char *name, int *missing);
const char *option_numeric_value(int argc, char **argv, int *i, const char *name, int *missing);

/* A decimal number as written, kept exact: value = digits * 10^exp10. */
typedef struct decimal {
    int neg;
    char digits[40];   /* significant digits, no leading or trailing zero; "" for 0 */
    int32_t exp10;
    double value;      /* the nearest double */
} decimal;

/* Parses "[+-]digits[.digits][e[+-]digits]" (also ".5", "5."). 0 or -1. */
int decimal_parse(const char *text, size_t len, decimal *out);
/* Parses exactly n comma-separated decimals ("x,y", "x0,y0,x1,y1"). */
int decimal_list_parse(const char *text, decimal *out, int n);
/* floor(d / 10^unit_exp10): the lattice cell column holding the value.
 * -1 when it does not fit an int64 (then it is outside every domain). */
int decimal_floor_lattice(const decimal *d, int32_t unit_exp10, int64_t *out);
/* Digits after the point that print d exactly (capped at 17). */
int decimal_fraction_digits(const decimal *d);

/* A pixel path "i,j/i,j/..." from the root: column i (0 = west), row j
 * (0 = north) per level. */
typedef struct pixel_path {
    uint32_t levels;
    uint32_t ij[HPFC_MAX_LEVELS][2];
} pixel_path;

/* 0, or -1 with a reason in why[]. */
int pixel_path_parse(const char *text, pixel_path *out, char *why, size_t cap);

/* ---- views ---------------------------------------------------------------- */

/* view_sections.c: every checksum computed and shown beside the stored one
 * (`path` is only printed). VIEW_FAIL when one mismatches. */
int view_sections(const hpfc_file *f, const char *path, FILE *out, int json, char *why);
/* view_pixel.c */
int view_pixel(const hpfc_file *f, const pixel_path *pp, FILE *out, int json, char *why);
/* view_stats.c */
int view_stats(const hpfc_file *f, FILE *out, int json, char *why);

/* ---- helpers shared with render.c and the tests --------------------------- */

/* The face candidates of a word pixel (interfaces §4): its one face when
 * private, else the faces on the right of the out-dart of each of its
 * crossings, sorted and without repeats. Every region of a word pixel cut
 * by its components reaches the pixel's boundary (no edge lies inside a
 * word pixel, so components are trees hanging from crossings), and the
 * boundary stretch after crossing k, clockwise, lies in the face on the
 * right of out_k (spec §3.11 rule 2): these are exactly the faces that
 * meet the pixel. faces[] needs room for max(1, crossings) ids; *count
 * receives how many were written. */
int view_pixel_faces(const hpfc_file *f, const hpfc_faces *fc, const hpfc_pixel *px,
                     uint64_t *faces, size_t cap, size_t *count);

/* Lattice value v * 10^e as an exact decimal string. */
void view_decimal_text(int64_t v, int32_t e, char *buf, size_t cap);

#endif
