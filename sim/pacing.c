/* pacing.c -- the flight loop's clock: a step every 1 / rate_hz of wall
 * time, paced on absolute deadlines (clock_nanosleep with TIMER_ABSTIME on
 * CLOCK_MONOTONIC, so that the loop's period does not drift by the time
 * each step takes, as relative sleeps would), or no pacing at all (as fast
 * as it can). An overrun (a step that ended after the next deadline) is
 * counted and reported, never absorbed: the next deadline stays on the
 * grid t0 + k / rate_hz, so a late step is followed by steps that catch up
 * without sleeping, and the count says how many were late. Step times
 * (the work between two waits) are kept for percentiles.
 *
 * This is the only file of the flight loop that reads a clock; the step
 * itself (flight.c) never does, so paced and unpaced runs are the same
 * trajectory.
 */
#include "sim.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define PACER_SAMPLES 65536

struct sim_pacer {
    double period_s;
    int realtime;
    struct timespec t0, next, work0;
    long steps, overruns;
    double step_s[PACER_SAMPLES]; /* the last PACER_SAMPLES step times (ring) */
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

sim_pacer *sim_pacer_create(double rate_hz, int realtime, core_err *err)
{
    if (!(rate_hz >= 1.0 && rate_hz <= 100000.0)) {
        core_err_set(err, -1, "pacing: rate %g Hz: expected 1 to 100000", rate_hz);
        return NULL;
    }
    sim_pacer *p = calloc(1, sizeof *p);
    if (!p) {
        core_err_set(err, -1, "pacing: out of memory");
        return NULL;
    }
    p->period_s = 1.0 / rate_hz;
    p->realtime = realtime;
    clock_gettime(CLOCK_MONOTONIC, &p->t0);
    p->next = p->t0;
    p->work0 = p->t0;
    return p;
}

void sim_pacer_destroy(sim_pacer *p) { free(p); }

int sim_pacer_wait(sim_pacer *p)
{
    struct timespec now;
    clock_gettime(CLOCK_MONOTONIC, &now);
    double work = ts_s(&now) - ts_s(&p->work0);
    if (p->steps > 0) {
        p->step_s[p->nsamples % PACER_SAMPLES] = work;
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
            while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &p->next, NULL) == EINTR)
                ;
        }
    }
    clock_gettime(CLOCK_MONOTONIC, &p->work0);
    return late;
}

static int cmp_d(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

void sim_pacer_stats(const sim_pacer *p, sim_pacer_report *s)
{
    memset(s, 0, sizeof *s);
    struct timespec now;
    clock_gettime(CLOCK_MONOTONIC, &now);
    s->steps = p->steps;
    s->overruns = p->overruns;
    s->wall_s = ts_s(&now) - ts_s(&p->t0);
    s->sim_s = (double)p->steps * p->period_s;
    s->rate_hz = s->wall_s > 0.0 ? (double)p->steps / s->wall_s : 0.0;
    s->realtime_factor = s->wall_s > 0.0 ? s->sim_s / s->wall_s : 0.0;
    s->step_max_s = p->max_step_s;
    long n = p->nsamples < PACER_SAMPLES ? p->nsamples : PACER_SAMPLES;
    if (n > 0) {
        double *v = malloc((size_t)n * sizeof *v);
        if (v) {
            memcpy(v, p->step_s, (size_t)n * sizeof *v);
            qsort(v, (size_t)n, sizeof *v, cmp_d);
            s->step_p50_s = v[n / 2];
            s->step_p99_s = v[(long)(0.99 * (double)(n - 1))];
            free(v);
        }
    }
}
