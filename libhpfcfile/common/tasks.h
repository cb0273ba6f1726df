/*
 * tasks.h: a step's work shared by a few threads. The step cuts its work
 * into tasks whose results do not depend on which thread runs them or
 * when (each writes only its own outputs), and combines the results in
 * task order afterwards, so the outcome is the one thread's, bytes and
 * errors alike. The threads start for the call and end with it: a step
 * runs a few times a build, where keeping them would save nothing.
 */
#ifndef HPFC_TASKS_H
#define HPFC_TASKS_H

#include <stdatomic.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* Past this the steps wait on memory, not on cores. */
#define TASKS_MAX_THREADS 64

/* work(ctx, task) for every task of [0, ntasks), taken in increasing
 * order by up to `threads` threads, the caller one of them. When a thread
 * cannot be started the others take its share: the call always completes.
 * work must be safe to run concurrently with itself on distinct tasks. */
void tasks_run(unsigned threads, size_t ntasks, void (*work)(void *ctx, size_t task), void *ctx);

/* The lowest task that failed, for a step whose error must be the one a
 * single thread meets first, going in task order: a later task that sees
 * an earlier failure stops, since its work will not be used. */
typedef atomic_size_t tasks_failure;

static inline void tasks_failure_init(tasks_failure *f)
{
    atomic_init(f, SIZE_MAX);
}

/* Records that `task` failed, keeping the lowest such task. */
static inline void tasks_failure_note(tasks_failure *f, size_t task)
{
    size_t seen = atomic_load_explicit(f, memory_order_relaxed);
    while (task < seen &&
           !atomic_compare_exchange_weak_explicit(f, &seen, task, memory_order_relaxed,
                                                  memory_order_relaxed))
        ;
}

/* Whether a task before `task` is known to have failed. */
static inline bool tasks_failed_before(tasks_failure *f, size_t task)
{
    return atomic_load_explicit(f, memory_order_relaxed) < task;
}

/* The lowest task that failed, or SIZE_MAX; after tasks_run. */
static inline size_t tasks_first_failure(tasks_failure *f)
{
    return atomic_load(f);
}

#endif
