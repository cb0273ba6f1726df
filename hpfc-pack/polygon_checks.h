/*
 * polygon_checks.h: the GIS reader's polygons checked by GEOS (readable,
 * valid) on a thread of their own while GDAL parses the features after
 * them. GDAL's parse is sequential and most of the read; the checks are
 * the one other step of it that does not depend on what follows, so on
 * two cores they cost no wall time.
 *
 * The verdicts come back in the order the polygons were queued, whatever
 * the thread did, so the reader counts and words them exactly as it would
 * one at a time; and since a polygon is queued before anything after it
 * is read, a failure of the reader's own is preceded by every verdict of
 * an earlier polygon (polygon_checks_finish first, then its own).
 */
#ifndef HPFC_PACK_POLYGON_CHECKS_H
#define HPFC_PACK_POLYGON_CHECKS_H

#include <stddef.h>

typedef struct polygon_checks polygon_checks;

enum {
    POLYGON_VALID = 0,
    POLYGON_INVALID,    /* GEOS reads it and finds it invalid: `why` says how */
    POLYGON_UNREADABLE, /* GEOS cannot read its WKB: `why` is GEOS's message, or "" */
};

/* A verdict, handed to the reader's callback in queue order. `where` and
 * `item` are the texts the reader gave with the polygon. The callback
 * returns 0 to go on, else the reader's failure, which stops the verdicts
 * (the rest are dropped). */
typedef struct polygon_verdict {
    int kind;
    const char *why;
    const char *where; /* the feature, for a message */
    const char *item;  /* the feature, for the list of those repaired */
} polygon_verdict;

typedef int (*polygon_verdict_fn)(void *user, const polygon_verdict *v);

/* threaded: check on a second thread (else each polygon as it is
 * queued, in the caller's). A thread that cannot be started leaves the
 * checks to the caller. reasons: say why a polygon is invalid (GEOS then
 * checks an invalid one twice), else `why` is "" for POLYGON_INVALID.
 * NULL when out of memory. */
polygon_checks *polygon_checks_create(int threaded, int reasons, polygon_verdict_fn done,
                                      void *user);

/* Queues a polygon: its WKB (taken over, freed here, also on failure) and
 * the texts of its verdict. Verdicts already known are handed out first.
 * 0, else the callback's failure or -1 out of memory. Waits while the
 * polygons queued and not checked hold more than a bound of bytes. */
int polygon_checks_add(polygon_checks *pc, unsigned char *wkb, size_t size, const char *where,
                       const char *item);

/* Waits for every polygon queued and hands out the verdicts left; 0 or
 * the callback's failure. */
int polygon_checks_finish(polygon_checks *pc);

/* Stops the thread (dropping what is queued) and frees everything. */
void polygon_checks_free(polygon_checks *pc);

#endif
