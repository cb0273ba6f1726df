/*
 * stage_time.h: the wall and CPU time of the stages of a pack, for its
 * report. The CPU time is the whole process's (user + system, every
 * thread): on a shared machine it varies less than the wall time.
 * Header-only.
 */
#ifndef HPFC_PACK_STAGE_TIME_H
#define HPFC_PACK_STAGE_TIME_H

#include <time.h>

typedef struct stage_time {
    double wall, cpu; /* seconds */
} stage_time;

static inline double stage_clock(clockid_t id)
{
    struct timespec ts;
    clock_gettime(id, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static inline stage_time stage_now(void)
{
    return (stage_time){stage_clock(CLOCK_MONOTONIC), stage_clock(CLOCK_PROCESS_CPUTIME_ID)};
}

/* The time since *t, which moves on to now: one stage's. */
static inline stage_time stage_lap(stage_time *t)
{
    stage_time now = stage_now();
    stage_time d = {now.wall - t->wall, now.cpu - t->cpu};
    *t = now;
    return d;
}

#endif
