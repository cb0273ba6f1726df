/*
 * clock.h: the tools' timers: wall seconds on the monotonic clock (reports,
 * progress bars, --json times) and, for hpfc-pack's stages, the wall and
 * CPU time together. The CPU time is the whole process's (user + system,
 * every thread): on a shared machine it varies less than the wall time.
 * Header-only.
 */
#ifndef HPFC_TOOLS_CLOCK_H
#define HPFC_TOOLS_CLOCK_H

#include <time.h>

static inline double clock_read(clockid_t id)
{
    struct timespec ts;
    clock_gettime(id, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Seconds on a clock that never jumps (differences only). */
static inline double clock_seconds(void)
{
    return clock_read(CLOCK_MONOTONIC);
}

typedef struct stage_time {
    double wall, cpu; /* seconds */
} stage_time;

/* (no compound literal: C++ includes this header through pack_write.h) */
static inline stage_time stage_now(void)
{
    stage_time t;
    t.wall = clock_seconds();
    t.cpu = clock_read(CLOCK_PROCESS_CPUTIME_ID);
    return t;
}

/* The time since *t, which moves on to now: one stage's. */
static inline stage_time stage_lap(stage_time *t)
{
    stage_time now = stage_now(), d;
    d.wall = now.wall - t->wall;
    d.cpu = now.cpu - t->cpu;
    *t = now;
    return d;
}

#endif
