/*
 * polygon_checks.c: see polygon_checks.h. A queue of polygons in the order
 * the reader gave them; the thread checks them front to back with a GEOS
 * context of its own, and the reader hands out the verdicts from the front
 * while they are known.
 */
#include "polygon_checks.h"

#include <geos_c.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* WKB queued and not yet checked: past this the reader waits, so a layer
 * of huge polygons does not pile up copies of them. */
#define PENDING_BYTES_MAX ((size_t)64 << 20)

typedef struct check_job {
    struct check_job *next;
    unsigned char *wkb; /* NULL once checked, or when the reader had none */
    size_t size;
    char *where, *item;
    int kind;
    char why[256];
    int checked;
} check_job;

struct polygon_checks {
    polygon_verdict_fn done;
    void *user;
    int reasons; /* say why a polygon is invalid (a second GEOS pass) */
    GEOSContextHandle_t geos; /* the checker's */
    char geos_msg[256];
    int threaded;
    pthread_t thread;
    pthread_mutex_t lock; /* guards what follows, when threaded */
    pthread_cond_t queued, checked;
    check_job *head, *tail; /* the verdicts not yet handed out, oldest first */
    check_job *to_check;    /* the first job not checked, NULL when all are */
    size_t pending_bytes;
    int stop;
    int failed; /* the callback's failure: nothing is handed out after it */
};

static void geos_message(const char *msg, void *user)
{
    polygon_checks *pc = user;
    snprintf(pc->geos_msg, sizeof pc->geos_msg, "%s", msg);
}

static void geos_notice(const char *msg, void *user)
{
    (void)msg;
    (void)user;
}

/* GEOS's verdict on one polygon, in the checker's context. */
static void check_one(polygon_checks *pc, check_job *job)
{
    pc->geos_msg[0] = '\0';
    GEOSGeometry *g = job->wkb ? GEOSGeomFromWKB_buf_r(pc->geos, job->wkb, job->size) : NULL;
    if (!g) {
        job->kind = POLYGON_UNREADABLE;
        snprintf(job->why, sizeof job->why, "%s", pc->geos_msg);
    } else if (GEOSisValid_r(pc->geos, g) != 1) {
        job->kind = POLYGON_INVALID;
        char *why = pc->reasons ? GEOSisValidReason_r(pc->geos, g) : NULL;
        snprintf(job->why, sizeof job->why, "%s", why ? why : "");
        GEOSFree_r(pc->geos, why);
    } else
        job->kind = POLYGON_VALID;
    GEOSGeom_destroy_r(pc->geos, g);
    free(job->wkb);
    job->wkb = NULL;
}

static void *checker(void *arg)
{
    polygon_checks *pc = arg;
    pthread_mutex_lock(&pc->lock);
    for (;;) {
        while (!pc->stop && !pc->to_check)
            pthread_cond_wait(&pc->queued, &pc->lock);
        if (pc->stop)
            break;
        check_job *job = pc->to_check;
        size_t size = job->size;
        pthread_mutex_unlock(&pc->lock); /* the job is the checker's until marked checked */
        check_one(pc, job);
        pthread_mutex_lock(&pc->lock);
        job->checked = 1;
        pc->pending_bytes -= size;
        pc->to_check = job->next;
        pthread_cond_signal(&pc->checked);
    }
    pthread_mutex_unlock(&pc->lock);
    return NULL;
}

/* The checker thread and what it shares with the reader; 0 (nothing left
 * to undo) when any of them cannot be made. */
static int start_checker(polygon_checks *pc)
{
    if (pthread_mutex_init(&pc->lock, NULL) != 0)
        return 0;
    if (pthread_cond_init(&pc->queued, NULL) != 0)
        goto no_queued;
    if (pthread_cond_init(&pc->checked, NULL) != 0)
        goto no_checked;
    if (pthread_create(&pc->thread, NULL, checker, pc) != 0)
        goto no_thread;
    return 1;
no_thread:
    pthread_cond_destroy(&pc->checked);
no_checked:
    pthread_cond_destroy(&pc->queued);
no_queued:
    pthread_mutex_destroy(&pc->lock);
    return 0;
}

polygon_checks *polygon_checks_create(int threaded, int reasons, polygon_verdict_fn done, void *user)
{
    polygon_checks *pc = calloc(1, sizeof *pc);
    if (!pc)
        return NULL;
    pc->done = done, pc->user = user, pc->reasons = reasons;
    if (!(pc->geos = GEOS_init_r())) {
        free(pc);
        return NULL;
    }
    GEOSContext_setErrorMessageHandler_r(pc->geos, geos_message, pc);
    GEOSContext_setNoticeMessageHandler_r(pc->geos, geos_notice, pc);
    if (threaded)
        pc->threaded = start_checker(pc);
    return pc; /* unthreaded: the caller's thread checks */
}

static void free_job(check_job *job)
{
    free(job->wkb);
    free(job->where);
    free(job->item);
    free(job);
}

/* Hands out the verdicts at the front while they are known; with `wait`,
 * waits for each (all of them). */
static int hand_out(polygon_checks *pc, int wait)
{
    while (!pc->failed) {
        if (pc->threaded)
            pthread_mutex_lock(&pc->lock);
        check_job *job = pc->head;
        while (pc->threaded && wait && job && !job->checked)
            pthread_cond_wait(&pc->checked, &pc->lock);
        int ready = job && job->checked;
        if (ready && !(pc->head = job->next))
            pc->tail = NULL;
        if (pc->threaded)
            pthread_mutex_unlock(&pc->lock);
        if (!ready)
            return 0;
        polygon_verdict v = {job->kind, job->why, job->where, job->item};
        pc->failed = pc->done(pc->user, &v);
        free_job(job);
    }
    return pc->failed;
}

int polygon_checks_add(polygon_checks *pc, unsigned char *wkb, size_t size, const char *where,
                       const char *item)
{
    if (pc->failed) {
        free(wkb);
        return pc->failed;
    }
    check_job *job = calloc(1, sizeof *job);
    if (!job || !(job->where = strdup(where)) || !(job->item = strdup(item))) {
        if (job)
            free(job->where);
        free(job);
        free(wkb);
        return -1;
    }
    job->wkb = wkb, job->size = size;
    if (!pc->threaded) {
        check_one(pc, job);
        job->checked = 1;
        pc->head = pc->tail = job;
        return hand_out(pc, 0);
    }
    pthread_mutex_lock(&pc->lock);
    if (pc->tail)
        pc->tail->next = job;
    else
        pc->head = job;
    pc->tail = job;
    if (!pc->to_check)
        pc->to_check = job;
    pc->pending_bytes += size;
    pthread_cond_signal(&pc->queued);
    while (pc->pending_bytes > PENDING_BYTES_MAX)
        pthread_cond_wait(&pc->checked, &pc->lock);
    pthread_mutex_unlock(&pc->lock);
    return hand_out(pc, 0);
}

int polygon_checks_finish(polygon_checks *pc)
{
    return hand_out(pc, 1);
}

void polygon_checks_free(polygon_checks *pc)
{
    if (!pc)
        return;
    if (pc->threaded) {
        pthread_mutex_lock(&pc->lock);
        pc->stop = 1;
        pthread_cond_signal(&pc->queued);
        pthread_mutex_unlock(&pc->lock);
        pthread_join(pc->thread, NULL);
        pthread_cond_destroy(&pc->checked);
        pthread_cond_destroy(&pc->queued);
        pthread_mutex_destroy(&pc->lock);
    }
    for (check_job *job = pc->head, *next; job; job = next) {
        next = job->next;
        free_job(job);
    }
    GEOS_finish_r(pc->geos);
    free(pc);
}
