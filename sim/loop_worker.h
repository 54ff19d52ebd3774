/* loop_worker.h -- the flight loop's worker thread (sim/loop_worker.c):
 * one job at a time (a world built while the loop flies the old one), and
 * after it the freeing of worlds the loop has swapped out. Private to
 * sim/loop.c. */
#ifndef DISIM_SIM_LOOP_WORKER_H
#define DISIM_SIM_LOOP_WORKER_H

#include "core.h"

typedef struct loop_worker loop_worker;
/* A started thread, or NULL with err. */
loop_worker *loop_worker_create(core_err *err);
/* Waits for the job under way, runs the frees left, ends the thread. */
void loop_worker_destroy(loop_worker *w);
/* fn(arg) on the thread: 0, or 1 when a job is under way or not yet
 * collected (loop_worker_poll). */
int loop_worker_submit(loop_worker *w, void (*fn)(void *), void *arg);
/* The job submitted: 1 it has run (collected: the worker takes another),
 * 0 it is still under way (wait 0), -1 none. wait 1: until it has run. */
int loop_worker_poll(loop_worker *w, int wait);
/* fn(user, arg) on the thread once the job under way (if any) has run, not
 * waited for (a world swapped out freed); run here at once when the queue
 * of them is full. */
void loop_worker_later(loop_worker *w, void (*fn)(void *, void *), void *user, void *arg);

#endif
