/*
 * tasks.c: see tasks.h. POSIX threads, which ThreadSanitizer intercepts
 * (C11's thrd_create it does not), and a shared counter from which each
 * thread takes the next task.
 */
#include "tasks.h"

#include <pthread.h>
#include <stdatomic.h>

typedef struct task_pool {
    void (*work)(void *ctx, size_t task);
    void *ctx;
    size_t ntasks;
    atomic_size_t next;
} task_pool;

static void *take_tasks(void *arg)
{
    task_pool *tp = arg;
    for (;;) {
        size_t task = atomic_fetch_add_explicit(&tp->next, 1, memory_order_relaxed);
        if (task >= tp->ntasks)
            return NULL;
        tp->work(tp->ctx, task);
    }
}

void tasks_run(unsigned threads, size_t ntasks, void (*work)(void *ctx, size_t task), void *ctx)
{
    task_pool tp = {.work = work, .ctx = ctx, .ntasks = ntasks};
    atomic_init(&tp.next, 0);
    if (threads > TASKS_MAX_THREADS)
        threads = TASKS_MAX_THREADS;
    if (threads > ntasks)
        threads = (unsigned)ntasks;
    pthread_t id[TASKS_MAX_THREADS];
    unsigned started = 0;
    while (started + 1 < threads && pthread_create(&id[started], NULL, take_tasks, &tp) == 0)
        started++;
    take_tasks(&tp);
    for (unsigned k = 0; k < started; k++)
        pthread_join(id[k], NULL);
}
