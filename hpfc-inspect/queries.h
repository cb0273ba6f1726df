/*
 * queries.h: hpfc-inspect's topology queries (contracts §6): --window
 * (without --render), --neighbours, --nearest, --nearest-lonlat (with
 * --within), --dissolve FIELD, --dissolve-features KEY|FID,... and --mesh
 * [interior|exterior|all|FIELD]
 * (each alone or with --export OUT), over the library's hpfc_shapes calls.
 * Parsed here, dispatched from hpfc-inspect.c.
 */
#ifndef HPFC_INSPECT_QUERIES_H
#define HPFC_INSPECT_QUERIES_H

#include <stdio.h>

typedef struct topo_args {
    const char *window, *window_lonlat;   /* X0,Y0,X1,Y1 / W,S,E,N */
    const char *neighbours;               /* KEY or FID */
    const char *nearest, *nearest_lonlat; /* X,Y / LON,LAT */
    const char *within;                   /* D, with --nearest* */
    const char *dissolve;                 /* FIELD */
    const char *dissolve_features;        /* KEY|FID,KEY|FID,... */
    const char *mesh;                     /* interior, exterior, all or FIELD */
    const char *export_out, *driver;      /* --export OUT, -f DRIVER */
    int json;
} topo_args;

/* The option at argv[*i] if it is one of this file's (--neighbours,
 * --nearest, --nearest-lonlat, --within, --dissolve, --dissolve-features,
 * --mesh): -1 when it is
 * not, 0 when taken (*i advanced past its value), 2 after a usage message. */
int topo_option(int argc, char **argv, int *i, topo_args *t);

/* How many topology queries t asks (0: none; more than 1 is a usage
 * error). */
int topo_count(const topo_args *t);

/* Checks the values (2 and one line on stderr when malformed), else -1. */
int topo_check(const topo_args *t);

/* Runs the one query on FILE: 0, or 1 with one line on stderr. */
int topo_run(const char *file, const topo_args *t, FILE *out);

#endif
