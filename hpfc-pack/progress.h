/*
 * progress.h: hpfc-pack's progress bar on standard error, drawn only when
 * it is a terminal (the caller decides: `on`), at most ten times a second.
 */
#ifndef HPFC_PACK_PROGRESS_H
#define HPFC_PACK_PROGRESS_H

typedef struct progress {
    int on;
    double last;
    int drawn;
} progress;

/* "hpfc-pack: STAGE [####......]  40%"; total <= 0 draws the stage name
 * alone; force draws even within a tenth of a second of the last time. */
void progress_show(progress *p, const char *stage, double done, double total, int force);
/* Clears the bar's line, if one was drawn. */
void progress_end(progress *p);

#endif
