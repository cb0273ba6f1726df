/*
 * clock.h: the tools' stage timers: wall seconds on the monotonic clock
 * (reports, progress bars, --json stage times) and the process's CPU
 * seconds beside them. Header-only.
 */
#ifndef HPFC_TOOLS_CLOCK_H
#define HPFC_TOOLS_CLOCK_H

#include <time.h>

/* Seconds on a clock that never jumps (differences only). */
static inline double clock_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Seconds since *t, which moves on to now: one stage's wall time. */
static inline double clock_lap(double *t)
{
    double now = clock_seconds();
    double d = now - *t;
    *t = now;
    return d;
}

/* CPU seconds the process has used, all its threads. */
static inline double clock_cpu_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

#endif
