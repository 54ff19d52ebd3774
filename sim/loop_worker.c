/* loop_worker.c -- the flight loop's worker thread: a world built (tens
 * of milliseconds, a restore's re-flight seconds) off the loop's thread,
 * so that the step's time does not hold it; and the worlds swapped out
 * freed there too. One job at a time: the loop asks, polls between steps
 * (or waits, where the swap must not depend on the thread's timing),
 * collects; the frees queue behind it. A mutex and a condition variable
 * hand everything over, so that what the job wrote is seen whole by the
 * loop once poll says it has run. The thread runs at the system's normal
 * scheduling (SCHED_OTHER), whatever the loop's thread was given: a world
 * built at the loop's real-time priority would take a core from the
 * stations and the view for as long as it lasts. */
#include "loop_worker.h"

#include <pthread.h>
#include <sched.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>

#define LATER_MAX 8

typedef struct later {
    void (*fn)(void *, void *);
    void *user, *arg;
} later;

struct loop_worker {
    pthread_t th;
    pthread_mutex_t mu;
    pthread_cond_t work, done;
    int quit;
    void (*fn)(void *); /* the job (NULL: none) */
    void *arg;
    int running, finished; /* taken by the thread; run, not yet collected */
    later q[LATER_MAX];
    int nq;
};

static void *worker_main(void *p)
{
    loop_worker *w = p;
    pthread_mutex_lock(&w->mu);
    for (;;) {
        if (w->nq > 0) { /* the frees first: memory back before the next world */
            later t = w->q[0];
            for (int i = 1; i < w->nq; i++)
                w->q[i - 1] = w->q[i];
            w->nq--;
            pthread_mutex_unlock(&w->mu);
            t.fn(t.user, t.arg);
            pthread_mutex_lock(&w->mu);
            continue;
        }
        if (w->fn && !w->running && !w->finished) {
            w->running = 1;
            void (*fn)(void *) = w->fn;
            void *arg = w->arg;
            pthread_mutex_unlock(&w->mu);
            fn(arg);
            pthread_mutex_lock(&w->mu);
            w->running = 0;
            w->finished = 1;
            pthread_cond_broadcast(&w->done);
            continue;
        }
        if (w->quit)
            break;
        pthread_cond_wait(&w->work, &w->mu);
    }
    pthread_mutex_unlock(&w->mu);
    return NULL;
}

loop_worker *loop_worker_create(core_err *err)
{
    loop_worker *w = calloc(1, sizeof *w);
    if (!w) {
        core_err_set(err, -1, "flight loop: out of memory");
        return NULL;
    }
    pthread_mutex_init(&w->mu, NULL);
    pthread_cond_init(&w->work, NULL);
    pthread_cond_init(&w->done, NULL);
    pthread_attr_t at;
    struct sched_param sp;
    memset(&sp, 0, sizeof sp);
    sigset_t all, old;
    sigfillset(&all);
    int bad = pthread_attr_init(&at);
    if (!bad) {
        bad = pthread_attr_setinheritsched(&at, PTHREAD_EXPLICIT_SCHED) ||
              pthread_attr_setschedpolicy(&at, SCHED_OTHER) || pthread_attr_setschedparam(&at, &sp);
        pthread_sigmask(SIG_SETMASK, &all, &old); /* signals stay the loop's thread's */
        if (!bad)
            bad = pthread_create(&w->th, &at, worker_main, w);
        pthread_sigmask(SIG_SETMASK, &old, NULL);
        pthread_attr_destroy(&at);
    }
    if (bad) {
        core_err_set(err, -1, "flight loop: cannot start the worker thread");
        pthread_cond_destroy(&w->done);
        pthread_cond_destroy(&w->work);
        pthread_mutex_destroy(&w->mu);
        free(w);
        return NULL;
    }
    return w;
}

void loop_worker_destroy(loop_worker *w)
{
    if (!w)
        return;
    pthread_mutex_lock(&w->mu);
    w->quit = 1;
    pthread_cond_signal(&w->work);
    pthread_mutex_unlock(&w->mu);
    pthread_join(w->th, NULL);
    pthread_cond_destroy(&w->done);
    pthread_cond_destroy(&w->work);
    pthread_mutex_destroy(&w->mu);
    free(w);
}

int loop_worker_submit(loop_worker *w, void (*fn)(void *), void *arg)
{
    pthread_mutex_lock(&w->mu);
    int busy = w->fn != NULL;
    if (!busy) {
        w->fn = fn;
        w->arg = arg;
        w->finished = 0;
        pthread_cond_signal(&w->work);
    }
    pthread_mutex_unlock(&w->mu);
    return busy;
}

int loop_worker_poll(loop_worker *w, int wait)
{
    pthread_mutex_lock(&w->mu);
    int r = -1;
    if (w->fn) {
        while (wait && !w->finished)
            pthread_cond_wait(&w->done, &w->mu);
        r = w->finished;
        if (r) {
            w->fn = NULL;
            w->arg = NULL;
            w->finished = 0;
        }
    }
    pthread_mutex_unlock(&w->mu);
    return r;
}

void loop_worker_later(loop_worker *w, void (*fn)(void *, void *), void *user, void *arg)
{
    pthread_mutex_lock(&w->mu);
    int queued = w->nq < LATER_MAX;
    if (queued) {
        w->q[w->nq++] = (later){fn, user, arg};
        pthread_cond_signal(&w->work);
    }
    pthread_mutex_unlock(&w->mu);
    if (!queued)
        fn(user, arg);
}
