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

#include <stddef.h>

/* Past this the steps wait on memory, not on cores. */
#define TASKS_MAX_THREADS 64

/* work(ctx, task) for every task of [0, ntasks), taken in increasing
 * order by up to `threads` threads, the caller one of them. When a thread
 * cannot be started the others take its share: the call always completes.
 * work must be safe to run concurrently with itself on distinct tasks. */
void tasks_run(unsigned threads, size_t ntasks, void (*work)(void *ctx, size_t task), void *ctx);

#endif
