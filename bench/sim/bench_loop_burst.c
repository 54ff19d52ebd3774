/* bench_loop_burst.c -- the real-time loop's step time while sim control
 * is hammered with world changes, in one invocation, before and after:
 *   in the step: no builder: each world is built inside the step that
 *                carries out its control (one build a step, no rate
 *                limit), as the loop did before the worker;
 *   worker:      the loop's worker builds it while the old world flies,
 *                swapped in between two steps; one at a time (busy), the
 *                default rate limit (5 at once, one more a second).
 * The world is disim fly's at a reset: the scenario and the aircraft
 * read, a ship-only airwake field read from its file (a small one built
 * here once), the seaway of sea state 5, the flight trimmed in the hover.
 * Each mode flies DURATION s at 200 Hz in real time over memq://; every
 * second (at x.5 s) a burst of 16 resets, 4 loads and 4 sea states
 * arrives in one step, and from 6 s to 8 s a reset every step (a flood).
 * Printed per mode: the steps, the overruns, the step time (the loop's
 * work between its waits) p50 / p99 / max, the worlds built and what one
 * build took (mean, max), the controls refused. Wall time: the machine is
 * shared, so the max is what a build in the step costs, the rest noise.
 * Usage: bench_loop_burst [DURATION_S] from the source root. */
#include "cfd.h"
#include "disim_lcm.h"
#include "hfm.h"
#include "sim.h"

#include <lcm/lcm.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define SCEN "scenarios/cg47_uh60a.ini"

typedef struct bworld {
    sim_scenario sc;
    hfm_aircraft *ac;
    cfd_field *fld;
    sim_world sw;
} bworld;

typedef struct bench {
    const char *field_path;
    bworld w;        /* the running world */
    long long builds; /* written by whichever thread builds, read after the loop */
    double build_s, build_max_s;
} bench;

static double wall_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static void bworld_free(bworld *w)
{
    sim_world_free(&w->sw);
    cfd_field_destroy(w->fld);
    hfm_aircraft_destroy(w->ac);
    memset(w, 0, sizeof *w);
}

/* disim fly's world at a reset, timed. */
static int bworld_build(bench *b, const char *path, const sim_loop_setup *s, bworld *w, core_err *err)
{
    double t0 = wall_s();
    memset(w, 0, sizeof *w);
    if (sim_scenario_load(path, &w->sc, err) != 0 || !(w->ac = hfm_aircraft_load(w->sc.aircraft_path, NULL, err)) ||
        !(w->fld = cfd_field_load(b->field_path, err))) {
        bworld_free(w);
        return -1;
    }
    sim_world_overrides ov;
    sim_world_overrides_default(&ov);
    ov.wod_speed_mps = 15.0;
    ov.wod_dir_rad = 30.0 * CORE_DEG_TO_RAD;
    ov.sea_state = s && s->sea_state >= 0 ? s->sea_state : 5;
    ov.field = w->fld;
    if (sim_world_build(&w->sc, w->ac, &ov, NULL, &w->sw, err) != 0) {
        bworld_free(w);
        return -1;
    }
    double dt = wall_s() - t0;
    b->builds++;
    b->build_s += dt;
    b->build_max_s = fmax(b->build_max_s, dt);
    return 0;
}

static void bworld_lw(const bworld *w, sim_loop_world *lw)
{
    memset(lw, 0, sizeof *lw);
    lw->flight = w->sw.flight;
    lw->motion = w->sw.motion;
    lw->info = w->sw.info;
    snprintf(lw->scenario, sizeof lw->scenario, "%s", w->sc.name);
}

/* in the step: build and rebuild replace the running world */
static int b_rebuild(void *user, const char *path, const sim_loop_setup *s, sim_loop_world *lw, core_err *err)
{
    bench *b = user;
    bworld nw;
    if (bworld_build(b, path, s, &nw, err) != 0)
        return -1;
    bworld_free(&b->w);
    b->w = nw;
    bworld_lw(&b->w, lw);
    return 0;
}

static int b_build(void *user, const char *path, sim_loop_world *lw, core_err *err)
{
    return b_rebuild(user, path, NULL, lw, err);
}

/* the worker: prepared, installed, dropped */
static int b_prepare(void *user, const char *path, const sim_loop_setup *s, void **world, sim_loop_world *lw,
                     core_err *err)
{
    bworld *nw = malloc(sizeof *nw);
    if (!nw || bworld_build(user, path, s, nw, err) != 0) {
        free(nw);
        return -1;
    }
    bworld_lw(nw, lw);
    *world = nw;
    return 0;
}

static void *b_install(void *user, void *world)
{
    bench *b = user;
    bworld *nw = world, old = b->w;
    b->w = *nw;
    *nw = old;
    return nw;
}

static void b_drop(void *user, void *world)
{
    (void)user;
    bworld_free(world);
    free(world);
}

static void send_ctl(lcm_t *lc, long long seq, int cmd, int sea)
{
    disim_sim_control_t c;
    memset(&c, 0, sizeof c);
    c.seq = seq;
    c.command = (int8_t)cmd;
    c.scenario_path = (char *)(cmd == DISIM_SIM_CONTROL_T_LOAD_SCENARIO ? SCEN : "");
    c.name = (char *)"";
    c.sea_state = (int8_t)sea;
    disim_sim_control_t_publish(lc, DISIM_CH_SIM_CONTROL, &c);
}

/* One mode flown: 0, or -1. */
static int fly_mode(const char *field_path, int worker, double duration_s)
{
    bench b;
    memset(&b, 0, sizeof b);
    b.field_path = field_path;
    core_err err = {0};
    sim_loop_world lw;
    if (bworld_build(&b, SCEN, NULL, &b.w, &err) != 0) {
        fprintf(stderr, "bench_loop_burst: %s\n", err.msg);
        return -1;
    }
    double first_build_s = b.build_s;
    b.builds = 0;
    b.build_s = b.build_max_s = 0.0;
    bworld_lw(&b.w, &lw);
    sim_loop_opts o;
    sim_loop_opts_default(&o);
    o.rate_hz = 200.0;
    o.realtime = 1;
    o.duration_s = duration_s;
    o.lcm = 1;
    o.lcm_url = "memq://";
    o.scenario_path = SCEN;
    o.rebuild = b_rebuild;
    if (worker) {
        o.builder.prepare = b_prepare;
        o.builder.install = b_install;
        o.builder.drop = b_drop;
    } else
        o.change_interval_s = 0.0; /* as before: no rate limit */
    sim_loop *l = sim_loop_create(&o, &lw, b_build, &b, NULL, &err);
    if (!l) {
        fprintf(stderr, "bench_loop_burst: %s\n", err.msg);
        bworld_free(&b.w);
        return -1;
    }
    lcm_t *lc = sim_loop_lcm(l);
    long long seq = 1, sent = 0;
    sim_flight_out out;
    int rc;
    for (long k = 0;; k++) {
        double t = k / o.rate_hz;
        if (k % 200 == 100) { /* a burst, every second at x.5 s */
            for (int i = 0; i < 16; i++)
                send_ctl(lc, seq++, DISIM_SIM_CONTROL_T_RESET, 0);
            for (int i = 0; i < 4; i++) {
                send_ctl(lc, seq++, DISIM_SIM_CONTROL_T_LOAD_SCENARIO, 0);
                send_ctl(lc, seq++, DISIM_SIM_CONTROL_T_SET_SEA, 3 + i % 2);
            }
            sent += 24;
        }
        if (t >= 6.0 && t < 8.0) { /* a flood: a reset every step */
            send_ctl(lc, seq++, DISIM_SIM_CONTROL_T_RESET, 0);
            sent++;
        }
        if ((rc = sim_loop_iterate(l, &out, &err)) < 0 || rc == SIM_LOOP_DONE || rc == SIM_LOOP_CRASHED)
            break;
    }
    sim_loop_report r;
    sim_loop_report_get(l, &r);
    sim_loop_destroy(l); /* the worker joined: b is this thread's again */
    bworld_free(&b.w);
    if (rc < 0) {
        fprintf(stderr, "bench_loop_burst: %s\n", err.msg);
        return -1;
    }
    /* the pacer's histogram ends at 20 ms: a p99 there is at least that */
    printf("| %s | %ld | %ld | %.3f / %s%.3f / %.2f | %lld | %.1f / %.1f | %lld of %lld (%lld busy, %lld rate "
           "limit) |\n",
           worker ? "worker" : "in the step", r.pace.steps, r.pace.overruns, 1e3 * r.pace.step_p50_s,
           r.pace.step_p99_s >= 0.02 ? ">= " : "", 1e3 * r.pace.step_p99_s, 1e3 * r.pace.step_max_s, b.builds,
           b.builds ? 1e3 * b.build_s / (double)b.builds : 0.0, 1e3 * b.build_max_s, r.control_refused, sent,
           r.refused_busy, r.refused_rate);
    if (!worker)
        fprintf(stderr, "bench_loop_burst: the first world built in %.1f ms\n", 1e3 * first_build_s);
    return 0;
}

/* A small ship-only field of the scenario's ship, written to path. */
static int small_field(const char *path)
{
    sim_scenario sc;
    core_err err = {0};
    if (sim_scenario_load(SCEN, &sc, &err) != 0) {
        fprintf(stderr, "bench_loop_burst: %s\n", err.msg);
        return -1;
    }
    cfd_airwake_spec sp;
    memset(&sp, 0, sizeof sp);
    sp.ship = &sc.ship;
    sp.wod_speed_mps = 15.0;
    sp.wod_dir_rad = 30.0 * CORE_DEG_TO_RAD;
    sp.level = CORE_GRID_COARSE;
    sp.rotor = CORE_ROTOR_OFF;
    sp.monitor_z_m = -5.0;
    sp.max_iter = 3;
    sp.h_fine_m = 2.0;
    cfd_solver *s = cfd_airwake_create(&sp, NULL, NULL, NULL, &err);
    if (!s) {
        fprintf(stderr, "bench_loop_burst: field: %s\n", err.msg);
        return -1;
    }
    cfd_result res;
    cfd_meta meta;
    memset(&meta, 0, sizeof meta);
    meta.wod_speed_mps = 15.0;
    meta.wod_dir_deg = 30.0;
    snprintf(meta.ship, sizeof meta.ship, "%s", sc.ship.name);
    snprintf(meta.rotor, sizeof meta.rotor, "off");
    snprintf(meta.grid, sizeof meta.grid, "h2.000 m");
    int bad = cfd_solver_run(s, &res, &err) < 0 || (meta.result = res, cfd_solver_write(s, &meta, path, &err));
    cfd_solver_destroy(s);
    if (bad)
        fprintf(stderr, "bench_loop_burst: field: %s\n", err.msg);
    return bad ? -1 : 0;
}

int main(int argc, char **argv)
{
    double duration_s = argc > 1 ? atof(argv[1]) : 10.0;
    if (!(duration_s >= 9.0 && duration_s <= 3600.0)) {
        fprintf(stderr, "usage: bench_loop_burst [DURATION_S (9 to 3600)]\n");
        return 2;
    }
    char field[64];
    snprintf(field, sizeof field, "/tmp/bench_loop_burst_%d.h5", (int)getpid());
    if (small_field(field) != 0)
        return 1;
    printf("| mode | steps | overruns | step p50 / p99 / max (ms) | worlds built | one build mean / max (ms) | "
           "controls refused |\n|---|---|---|---|---|---|---|\n");
    int rc = fly_mode(field, 0, duration_s) != 0 || fly_mode(field, 1, duration_s) != 0;
    unlink(field);
    return rc;
}
