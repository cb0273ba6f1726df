/*
 * render.h: `hpfc-inspect --render OUT.svg|OUT.png`: a
 * picture of the map as the file encodes it, and of its hierarchical grid.
 *
 * The window is the data's extent by default (the leaves holding a vertex,
 * plus 2 %), else --window in user coordinates or --window-lonlat in
 * degrees (projected with the file's CRS); it grows to the image's aspect.
 * What is drawn, from the file alone (public reader API):
 *   - every leaf (word pixel) meeting the window, filled with the colour of
 *     its face's feature (FEAT section; a categorical palette, white for
 *     the outside and faces of no feature) or, without features, of its
 *     face (the unbounded face white); a stabbed leaf, which edges cut,
 *     takes the mean of the faces meeting it. Leaves are outlined when at
 *     least a few image pixels wide;
 *   - the graph: each crossing at a point of its road, the crossings of every
 *     stretch of grid line shared by two leaves spread evenly along it in
 *     word order (roads.h: both sides agree, so edges join up across roads);
 *     inside each leaf every stabbing as a line between its two crossings
 *     (bent a little toward the leaf's centre so that a stabbing along one
 *     road stays visible) and every junction as a star from its vertex to its
 *     crossings. A vertex sits at its leaf's centre when it is the leaf's only
 *     component, otherwise at the centroid of its crossings (inside their
 *     convex hull, which keeps the stars and chords of one leaf apart since
 *     its components do not cross, spec §3.8);
 *   - the word of each leaf that is large on screen (no text on small ones).
 * Leaves smaller than an image pixel are drawn as one dot of ink when
 * stabbed, and a refined pixel whose children would be smaller than that is
 * filled as a whole with the colour at its centre: the output stays
 * proportional to the image, not to the file.
 *
 * The SVG's coordinates are the file's user coordinates (its viewBox is the
 * window, the drawing in a group that flips y); the PNG comes with a world
 * file (OUT.pgw), so that both drop onto a map in the file's CRS. SVG is
 * written directly; PNG goes through cairo when the build has it
 * (HPFC_HAVE_CAIRO).
 */
#ifndef HPFC_INSPECT_RENDER_H
#define HPFC_INSPECT_RENDER_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "hpfc.h"

enum { RENDER_SVG = 1, RENDER_PNG = 2 };

#define RENDER_DEFAULT_SIZE 1024u
#define RENDER_MAX_SIZE 16384u

typedef struct render_params {
    const char *output;
    int format;                /* RENDER_SVG or RENDER_PNG */
    int have_window;
    double window[4];          /* x0, y0, x1, y1 in user coordinates */
    int have_window_lonlat;
    double window_lonlat[4];   /* lon0, lat0, lon1, lat1 (--window-lonlat) */
    uint32_t width, height;    /* 0, 0: RENDER_DEFAULT_SIZE on the longer side;
                                  width only: height from the window's aspect */
} render_params;

typedef struct render_report {
    uint32_t width, height;
    double window[4];          /* the window drawn, user coordinates */
    uint64_t leaves, outlined, segments, vertices, labels, ink;
    double seconds;
    int by_feature;            /* fills by feature (FEAT section), else by face */
    char world_file[4096];     /* the PNG's world file, "" for none */
} render_report;

/* RENDER_SVG / RENDER_PNG from the output's suffix (case-insensitive), 0 if
 * neither. */
int render_format_of(const char *path);
/* Whether this build can write PNG. */
int render_png_available(void);

/* "W" or "WxH", each 1 .. RENDER_MAX_SIZE: 0, or -1. *h is 0 for "W". */
int render_size_parse(const char *text, uint32_t *w, uint32_t *h);
/* "x0,y0,x1,y1" with x0 < x1 and y0 < y1: 0, or -1. */
int render_window_parse(const char *text, double window[4]);

/* Draws the file into p->output. Returns 0, or 1 with a one-line reason in
 * why[] (VIEW_WHY bytes). */
int render_file(const hpfc_file *f, const render_params *p, render_report *report, char *why);

/* The one-line text or JSON summary of a rendering. */
void render_print_report(FILE *out, int json, const render_params *p, const render_report *r);

#endif
