/* pacing.c -- the flight loop's clock: a step every 1 / rate_hz of wall
 * time, paced on absolute deadlines (clock_nanosleep with TIMER_ABSTIME on
 * CLOCK_MONOTONIC, so that the loop's period does not drift by the time
 * each step takes, as relative sleeps would), or no pacing at all (as fast
 * as it can). An overrun (a step that ended after the next deadline) is
 * counted and reported, never absorbed: the next deadline stays on the
 * grid t0 + k / rate_hz, so a late step is followed by steps that catch up
 * without sleeping, and the count says how many were late. Step times
 * (the work between two waits) go into a histogram of 1 us bins up to
 * 20 ms (longer ones in its last bin; the maximum is kept exactly), so a
 * percentile costs a pass over the bins however long the run.
 *
 * This is the only file of the flight loop that reads a clock; the step
 * itself (flight.c) never does, so paced and unpaced runs are the same
 * trajectory. The clock is the create options' (sim_pacer_clock):
 * CLOCK_MONOTONIC by default, one of its own in a test.
 */
#include "sim.h"

#include <errno.h>
#include <sched.h>
#include <sys/mman.h>
#include <math.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#define PACER_BINS 20000 /* 1 us each */

struct sim_pacer {
    sim_pacer_clock clock;
    double period_s;
    int realtime;
    struct timespec t0, next, work0;
    long steps, overruns;
    long hist[PACER_BINS]; /* step times, 1 us bins */
    long late_hist[PACER_BINS]; /* how late each wake-up came after its deadline */
    long nlate;
    double max_late_s;
    long nsamples;
    double max_step_s;
};

static double ts_s(const struct timespec *t) { return (double)t->tv_sec + 1e-9 * (double)t->tv_nsec; }

static void ts_add(struct timespec *t, double s)
{
    long ns = (long)(s * 1e9 + 0.5);
    t->tv_sec += ns / 1000000000L;
    t->tv_nsec += ns % 1000000000L;
    if (t->tv_nsec >= 1000000000L) {
        t->tv_sec++;
        t->tv_nsec -= 1000000000L;
    }
}

static void mono_now(void *user, struct timespec *t)
{
    (void)user;
    clock_gettime(CLOCK_MONOTONIC, t);
}

static void mono_sleep_until(void *user, const struct timespec *deadline)
{
    (void)user;
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, deadline, NULL) == EINTR)
        ;
}

void sim_pacer_opts_default(sim_pacer_opts *o)
{
    memset(o, 0, sizeof *o);
    o->rate_hz = 100.0;
    o->realtime = 1;
}

sim_pacer *sim_pacer_create(double rate_hz, int realtime, core_err *err)
{
    sim_pacer_opts o;
    sim_pacer_opts_default(&o);
    o.rate_hz = rate_hz;
    o.realtime = realtime;
    return sim_pacer_create_opts(&o, err);
}

sim_pacer *sim_pacer_create_opts(const sim_pacer_opts *o, core_err *err)
{
    double rate_hz = o->rate_hz;
    if (!(rate_hz >= 1.0 && rate_hz <= 100000.0)) {
        core_err_set(err, -1, "pacing: rate %g Hz: expected 1 to 100000", rate_hz);
        return NULL;
    }
    sim_pacer *p = calloc(1, sizeof *p);
    if (!p) {
        core_err_set(err, -1, "pacing: out of memory");
        return NULL;
    }
    if (!o->clock.now != !o->clock.sleep_until) {
        free(p);
        core_err_set(err, -1, "pacing: a clock needs both now and sleep_until");
        return NULL;
    }
    p->clock = o->clock;
    if (!p->clock.now) {
        p->clock.now = mono_now;
        p->clock.sleep_until = mono_sleep_until;
        p->clock.user = NULL;
    }
    p->period_s = 1.0 / rate_hz;
    p->realtime = o->realtime;
    p->clock.now(p->clock.user, &p->t0);
    p->next = p->t0;
    p->work0 = p->t0;
    return p;
}

void sim_pacer_destroy(sim_pacer *p) { free(p); }

void sim_pacer_rebase(sim_pacer *p)
{
    p->clock.now(p->clock.user, &p->next);
}

void sim_pacer_idle(sim_pacer *p)
{
    p->clock.now(p->clock.user, &p->work0);
}

int sim_pacer_wait(sim_pacer *p)
{
    struct timespec now;
    p->clock.now(p->clock.user, &now);
    double work = ts_s(&now) - ts_s(&p->work0);
    if (p->steps > 0) {
        long b = (long)(work * 1e6);
        p->hist[b < 0 ? 0 : b >= PACER_BINS ? PACER_BINS - 1 : b]++;
        p->nsamples++;
        if (work > p->max_step_s)
            p->max_step_s = work;
    }
    p->steps++;
    int late = 0;
    ts_add(&p->next, p->period_s);
    if (p->realtime) {
        if (ts_s(&now) > ts_s(&p->next)) {
            late = 1;
            p->overruns++;
        } else {
            p->clock.sleep_until(p->clock.user, &p->next);
            struct timespec woke;
            p->clock.now(p->clock.user, &woke);
            double l = ts_s(&woke) - ts_s(&p->next);
            long b = (long)(l * 1e6);
            p->late_hist[b < 0 ? 0 : b >= PACER_BINS ? PACER_BINS - 1 : b]++;
            p->nlate++;
            if (l > p->max_late_s)
                p->max_late_s = l;
        }
    }
    p->clock.now(p->clock.user, &p->work0);
    return late;
}

/* The step time below which a fraction q of the steps fall (the bin's
 * upper edge, s). */
static double percentile(const long *hist, long count, double q, double max_s)
{
    long want = (long)ceil(q * (double)count), n = 0;
    for (long b = 0; b < PACER_BINS; b++) {
        n += hist[b];
        if (n >= want && n > 0)
            return fmin(1e-6 * (double)(b + 1), max_s);
    }
    return max_s;
}

void sim_pacer_stats(const sim_pacer *p, sim_pacer_report *s)
{
    memset(s, 0, sizeof *s);
    struct timespec now;
    p->clock.now(p->clock.user, &now);
    s->steps = p->steps;
    s->overruns = p->overruns;
    s->wall_s = ts_s(&now) - ts_s(&p->t0);
    s->sim_s = (double)p->steps * p->period_s;
    s->rate_hz = s->wall_s > 0.0 ? (double)p->steps / s->wall_s : 0.0;
    s->realtime_factor = s->wall_s > 0.0 ? s->sim_s / s->wall_s : 0.0;
    s->step_max_s = p->max_step_s;
    if (p->nsamples > 0) {
        s->step_p50_s = percentile(p->hist, p->nsamples, 0.5, p->max_step_s);
        s->step_p99_s = percentile(p->hist, p->nsamples, 0.99, p->max_step_s);
    }
    if (p->nlate > 0) {
        s->late_p99_s = percentile(p->late_hist, p->nlate, 0.99, p->max_late_s);
        s->late_max_s = p->max_late_s;
    }
}

int sim_pacer_os_realtime(int priority, char *what, size_t n)
{
    struct sched_param sp;
    memset(&sp, 0, sizeof sp);
    sp.sched_priority = priority;
    int fifo = sched_setscheduler(0, SCHED_FIFO, &sp) == 0;
    int fifo_errno = fifo ? 0 : errno;
    int locked = mlockall(MCL_CURRENT | MCL_FUTURE) == 0;
    int lock_errno = locked ? 0 : errno;
    snprintf(what, n, "%s; %s", fifo ? "SCHED_FIFO real-time scheduling" : "no real-time scheduling",
             locked ? "memory locked" : "memory not locked");
    if (!fifo || !locked) {
        size_t l = strlen(what);
        snprintf(what + l, n - l, " (%s%s%s)", fifo ? "" : strerror(fifo_errno), !fifo && !locked ? "; " : "",
                 locked ? "" : strerror(lock_errno));
    }
    return (fifo ? 1 : 0) | (locked ? 2 : 0);
}
