/* test_pacing.c -- the flight loop's clock (sim/pacing.c) on an injected
 * clock (sim_pacer_opts.clock), so that every figure is exact whatever the
 * machine does: a fake clock the test advances by each step's work, whose
 * sleep_until wakes a set time after the deadline.
 *
 * 100 Hz, 1001 steps: most steps work 1.0005 ms, one in 40 3.0005 ms, one
 * in 200 25.0005 ms (over two periods). Each long step overruns its
 * deadline and so does the short one after it (still behind the grid);
 * the one after that sleeps again, on the grid t0 + k / rate (catch-up:
 * the deadlines never slip by the late steps). So: 10 overruns, sim_pacer_wait
 * returning 1 on exactly those steps; every wake-up at its grid deadline
 * plus the clock's lateness, to the nanosecond; the step time's p50 in
 * the 1.000-1.001 ms bin (1.001 ms), its p99 in the 3.000-3.001 ms one
 * (3.001 ms), its maximum 25.0005 ms exactly (past the histogram's 20 ms,
 * kept apart); the wake-ups 10.5 us late but one in 200 200.5 us: the
 * lateness p99 11 us (its bin's edge), the maximum 200.5 us; the wall time
 * the simulated time plus the last wake-up's lateness. Unpaced (realtime
 * 0), the same steps never sleep and count no overrun. A clock with one
 * of its two functions is refused; the default clock paces a few steps. */
#include "check.h"
#include "sim.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

typedef struct fake_clock {
    long long ns;    /* now */
    long sleeps;     /* sleep_until calls */
    long long late_ns; /* how late the next wake-up comes */
    long long last_deadline_ns;
} fake_clock;

static long long ts_ns(const struct timespec *t) { return (long long)t->tv_sec * 1000000000LL + t->tv_nsec; }

static void fake_now(void *user, struct timespec *t)
{
    const fake_clock *c = user;
    t->tv_sec = (time_t)(c->ns / 1000000000LL);
    t->tv_nsec = (long)(c->ns % 1000000000LL);
}

static void fake_sleep_until(void *user, const struct timespec *deadline)
{
    fake_clock *c = user;
    long long d = ts_ns(deadline);
    c->sleeps++;
    c->last_deadline_ns = d;
    if (d > c->ns)
        c->ns = d;
    c->ns += c->late_ns;
}

#define RATE_HZ 100.0
#define PERIOD_NS 10000000LL
#define NSTEPS 1001
#define T0_NS 1000000000000LL /* 1000 s: the clock need not start at 0 */

/* step i's work, ns */
static long long work_ns(int i)
{
    if (i % 200 == 100)
        return 25000500LL;
    if (i % 40 == 10)
        return 3000500LL;
    return 1000500LL;
}

/* A pacer at RATE_HZ on the fake clock c (realtime: paced on deadlines). */
static sim_pacer *fake_pacer(fake_clock *c, int realtime)
{
    sim_pacer_opts o;
    sim_pacer_opts_default(&o);
    o.rate_hz = RATE_HZ;
    o.realtime = realtime;
    o.clock.now = fake_now;
    o.clock.sleep_until = fake_sleep_until;
    o.clock.user = c;
    core_err err = {0};
    return sim_pacer_create_opts(&o, &err);
}

static void test_paced(void)
{
    fake_clock c = {T0_NS, 0, 0, 0};
    sim_pacer *p = fake_pacer(&c, 1);
    CHECK(p != NULL);
    if (!p)
        return;
    long overruns = 0, bad_return = 0, off_grid = 0;
    for (int i = 0; i < NSTEPS; i++) {
        c.ns += work_ns(i);
        /* the next wake-up's lateness */
        c.late_ns = (c.sleeps % 200 == 199) ? 200500LL : 10500LL;
        long sleeps0 = c.sleeps;
        long long late_ns = c.late_ns;
        int late = sim_pacer_wait(p);
        /* long step i overruns, and so does step i + 1 */
        int expect_late = (i % 200 == 100) || (i % 200 == 101);
        overruns += late;
        bad_return += late != expect_late;
        if (!late) {
            /* slept to deadline i + 1 on the grid, woke late_ns after it */
            long long deadline = T0_NS + (long long)(i + 1) * PERIOD_NS;
            off_grid += c.sleeps != sleeps0 + 1 || c.last_deadline_ns != deadline || c.ns != deadline + late_ns;
        } else
            off_grid += c.sleeps != sleeps0; /* a late step does not sleep */
    }
    sim_pacer_report r;
    sim_pacer_stats(p, &r);
    printf("paced, 100 Hz, %d steps: %ld overruns (%ld returns unexpected, %ld wake-ups off the grid), "
           "step p50 %.4f p99 %.4f max %.5f ms, lateness p99 %.1f max %.1f us, wall %.6f s for %.6f s\n",
           NSTEPS, r.overruns, bad_return, off_grid, 1e3 * r.step_p50_s, 1e3 * r.step_p99_s, 1e3 * r.step_max_s,
           1e6 * r.late_p99_s, 1e6 * r.late_max_s, r.wall_s, r.sim_s);
    CHECK(r.steps == NSTEPS);
    CHECK(r.overruns == 10 && overruns == 10);
    CHECK(bad_return == 0);
    CHECK(off_grid == 0);
    CHECK(c.sleeps == NSTEPS - 10);
    CHECK(fabs(r.step_p50_s - 1.001e-3) < 1e-12);
    CHECK(fabs(r.step_p99_s - 3.001e-3) < 1e-12);
    CHECK(fabs(r.step_max_s - 25.0005e-3) < 1e-9);
    CHECK(fabs(r.late_p99_s - 11e-6) < 1e-12);
    CHECK(fabs(r.late_max_s - 200.5e-6) < 1e-9);
    CHECK(fabs(r.sim_s - NSTEPS / RATE_HZ) < 1e-9);
    /* the last step slept to its deadline: wall = sim + that wake-up's lateness */
    CHECK(fabs(r.wall_s - (r.sim_s + 1e-9 * (double)(c.ns - c.last_deadline_ns))) < 1e-6);
    CHECK(fabs(r.realtime_factor - r.sim_s / r.wall_s) < 1e-12);
    sim_pacer_destroy(p);
}

static void test_unpaced(void)
{
    fake_clock c = {T0_NS, 0, 10500LL, 0};
    sim_pacer *p = fake_pacer(&c, 0);
    CHECK(p != NULL);
    if (!p)
        return;
    int any_late = 0;
    long long total = 0;
    for (int i = 0; i < NSTEPS; i++) {
        c.ns += work_ns(i);
        total += work_ns(i);
        any_late |= sim_pacer_wait(p);
    }
    sim_pacer_report r;
    sim_pacer_stats(p, &r);
    printf("unpaced: %ld steps, %ld overruns, %ld sleeps, wall %.6f s (the work's %.6f s)\n", r.steps, r.overruns,
           c.sleeps, r.wall_s, 1e-9 * (double)total);
    CHECK(!any_late && r.overruns == 0 && c.sleeps == 0);
    CHECK(fabs(r.wall_s - 1e-9 * (double)total) < 1e-6);
    CHECK(r.late_p99_s == 0.0 && r.late_max_s == 0.0);
    CHECK(fabs(r.step_max_s - 25.0005e-3) < 1e-9);
    sim_pacer_destroy(p);
}

/* A frozen flight: passes that step nothing, 3 s of them, then the
 * flight again (its deadlines rebased, as the loop does at a resume): the
 * wait is no step's work, so the step maximum stays the steps' */
static void test_idle(void)
{
    fake_clock c = {T0_NS, 0, 0, 0};
    sim_pacer *p = fake_pacer(&c, 1);
    CHECK(p != NULL);
    if (!p)
        return;
    for (int i = 0; i < 10; i++) {
        c.ns += 1000500LL;
        sim_pacer_wait(p);
    }
    for (int k = 0; k < 30; k++) { /* frozen: a pass every 100 ms */
        c.ns += 100000000LL;
        sim_pacer_idle(p);
    }
    sim_pacer_rebase(p);
    for (int i = 0; i < 10; i++) {
        c.ns += 2000500LL;
        sim_pacer_wait(p);
    }
    sim_pacer_report r;
    sim_pacer_stats(p, &r);
    printf("idle: %ld steps, step max %.6f s over a 3 s freeze, %ld overruns\n", r.steps, r.step_max_s, r.overruns);
    CHECK(fabs(r.step_max_s - 2.0005e-3) < 1e-9 && r.overruns == 0);
    sim_pacer_destroy(p);
}

static void test_options(void)
{
    fake_clock c = {T0_NS, 0, 0, 0};
    sim_pacer_opts o;
    sim_pacer_opts_default(&o);
    o.clock.now = fake_now; /* no sleep_until */
    o.clock.user = &c;
    core_err err = {0};
    CHECK(sim_pacer_create_opts(&o, &err) == NULL && strstr(err.msg, "sleep_until"));
    sim_pacer_opts_default(&o);
    o.rate_hz = 0.5;
    CHECK(sim_pacer_create_opts(&o, &err) == NULL && strstr(err.msg, "rate"));
    /* the default clock (CLOCK_MONOTONIC): a few steps at 1 kHz paced */
    sim_pacer *p = sim_pacer_create(1000.0, 1, &err);
    CHECK(p != NULL);
    if (p) {
        for (int i = 0; i < 20; i++)
            sim_pacer_wait(p);
        sim_pacer_report r;
        sim_pacer_stats(p, &r);
        CHECK(r.steps == 20 && r.wall_s > 0.0);
        /* paced: the 20 deadlines 1 ms apart are all past (the wall time only
         * ever comes after them, whatever the machine's load) */
        CHECK(r.wall_s >= 0.020 - 1e-6);
        sim_pacer_destroy(p);
    }
}

int main(void)
{
    test_paced();
    test_idle();
    test_unpaced();
    test_options();
    return check_done("test_pacing");
}
