/* bench_fly.c -- the cost of the flight loop's step (sim_flight_step) with
 * what the air and the ship add, in one invocation: the UH-60A in a
 * trimmed hover over the CG-47's spot, 20 kt from green 30, 200 Hz, each
 * case flown STEPS steps in flights of 10 s from the trimmed hover (the
 * trims and each flight's first step excluded), median of REPEATS:
 *   baseline: the flight model alone (hfm_tsim in a uniform wind, the
 *             same trim), the floor the loop cannot go below;
 *   free:     the step in the free stream (log law), ship steady;
 *   field:    a ship-only airwake field (a small one built here: 2 m
 *             cells, a few iterations: the lookup's cost does not depend
 *             on convergence) sampled at every point;
 *   +turb:    the field's turbulence on;
 *   +sea:     the ship in sea state 5 (the frame a sum of 256 waves).
 * Printed: us per step, x real time at 200 Hz, and the ratio to the
 * baseline. Process CPU time (the machine is shared). Usage: bench_fly
 * [STEPS [CASE]] from the source root; CASE (1-4, the rows below the
 * baseline) flies that case alone, for a profile of it (perf record);
 * BENCH_FLY_WHERE=1 prints how far the flights drift from the station. */
#include "cfd.h"
#include "../bench.h"
#include "hfm.h"
#include "sim.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define REPEATS 5

static cfd_field *small_field(const core_ship *ship, const char *path)
{
    cfd_airwake_spec sp;
    memset(&sp, 0, sizeof sp);
    sp.ship = ship;
    sp.wod_speed_mps = 15.0;
    sp.wod_dir_rad = 30.0 * CORE_DEG_TO_RAD;
    sp.level = CORE_GRID_COARSE;
    sp.rotor = CORE_ROTOR_OFF;
    sp.monitor_z_m = -5.0;
    sp.max_iter = 3;
    sp.h_fine_m = 2.0;
    core_err err = {0};
    cfd_solver *s = cfd_airwake_create(&sp, NULL, NULL, NULL, &err);
    if (!s)
        return NULL;
    cfd_result res;
    cfd_meta meta;
    memset(&meta, 0, sizeof meta);
    meta.wod_speed_mps = 15.0;
    meta.wod_dir_deg = 30.0;
    snprintf(meta.ship, sizeof meta.ship, "%s", ship->name);
    snprintf(meta.rotor, sizeof meta.rotor, "off");
    snprintf(meta.grid, sizeof meta.grid, "h2.000 m");
    int bad = cfd_solver_run(s, &res, &err) < 0 || (meta.result = res, cfd_solver_write(s, &meta, path, &err));
    cfd_solver_destroy(s);
    if (bad) {
        fprintf(stderr, "bench_fly: field: %s\n", err.msg);
        return NULL;
    }
    return cfd_field_load(path, &err);
}

/* Median seconds per step of one case; < 0 on failure. The steps are
 * flown in flights of at most SEGMENT steps, each from the trimmed hover:
 * with the controls held the hover drifts (a few metres in 10 s, hundreds
 * in 100 s, out of the field), and the case is the loop over the deck.
 * Each flight's first step (the turbulence laying its field) is not timed. */
#define SEGMENT 2000

static double fly_case(const hfm_aircraft *ac, const core_ship *ship, const cfd_field *fld, int turb, int sea_state,
                       long steps)
{
    double t[REPEATS], drift = 0.0;
    for (int r = 0; r < REPEATS; r++) {
        core_err err = {0};
        sim_sea sea;
        sim_sea_default(&sea);
        sea.state = sea_state;
        sim_ship_motion *m = sim_ship_motion_create(ship, &sea, 7, &err);
        if (!m) {
            fprintf(stderr, "bench_fly: %s\n", err.msg);
            return -1.0;
        }
        double spent = 0.0;
        for (long done = 0; done < steps;) {
            long seg = steps - done < SEGMENT ? steps - done : SEGMENT;
            sim_flight_opts o;
            sim_flight_opts_default(&o);
            o.wod_speed_mps = 20.0 * CORE_KT_TO_MPS;
            o.wod_dir_rad = 30.0 * CORE_DEG_TO_RAD;
            o.turbulence = turb;
            sim_flight *f = sim_flight_create(ac, ship, &o, sim_ship_motion_frame_fn, m, fld, NULL, &err);
            sim_flight_inputs in;
            if (!f || (sim_flight_trim_inputs(f, &in), sim_flight_step(f, &in, NULL, &err)) != 0) {
                fprintf(stderr, "bench_fly: %s\n", err.msg);
                sim_flight_destroy(f);
                sim_ship_motion_destroy(m);
                return -1.0;
            }
            double t0 = bench_cpu_s();
            for (long i = 0; i < seg; i++)
                if (sim_flight_step(f, &in, NULL, &err) != 0) {
                    fprintf(stderr, "bench_fly: step %ld: %s\n", i, err.msg);
                    break;
                }
            spent += bench_cpu_s() - t0;
            sim_flight_out out;
            sim_flight_state(f, &out);
            double d = hypot(hypot(out.pos_S_m[0] - o.station_S_m[0], out.pos_S_m[1] - o.station_S_m[1]),
                             out.pos_S_m[2] - o.station_S_m[2]);
            drift = fmax(drift, d);
            sim_flight_destroy(f);
            done += seg;
        }
        t[r] = spent / (double)steps;
        sim_ship_motion_destroy(m);
    }
    if (getenv("BENCH_FLY_WHERE"))
        fprintf(stderr, "bench_fly: each flight ends within %.1f m of the station\n", drift);
    return bench_median(t, REPEATS);
}

static double baseline(const hfm_aircraft *ac, long steps)
{
    hfm_trim *tr = hfm_trim_create(ac, NULL);
    hfm_trim_cond c;
    memset(&c, 0, sizeof c);
    c.kind = HFM_TRIM_HOVER_SHIP;
    c.wod_speed_mps = 20.0 * CORE_KT_TO_MPS;
    c.wod_dir_rad = 30.0 * CORE_DEG_TO_RAD;
    c.pos_S_m[2] = -6.0;
    hfm_trim_result r;
    if (!tr || hfm_trim_solve(tr, &c, NULL, &r) != 0) {
        hfm_trim_destroy(tr);
        return -1.0;
    }
    hfm_trim_destroy(tr);
    core_vec3 w = core_wod_vel_S_mps(c.wod_speed_mps, c.wod_dir_rad);
    hfm_air_uniform u = {{w.x, w.y, w.z}};
    hfm_air air = {hfm_air_uniform_fn, &u, NULL};
    double t[REPEATS];
    for (int k = 0; k < REPEATS; k++) {
        hfm_tsim *ts = hfm_tsim_create(ac, &air, HFM_TSIM_ARKODE_FIXED, 0.005, 0.0, NULL);
        if (!ts || hfm_tsim_init(ts, 0.0, &r.body, &r.u, &r.rotor) != 0) {
            hfm_tsim_destroy(ts);
            return -1.0;
        }
        double t0 = bench_cpu_s();
        for (long i = 1; i <= steps; i++)
            hfm_tsim_advance(ts, 0.005 * (double)i);
        t[k] = (bench_cpu_s() - t0) / (double)steps;
        hfm_tsim_destroy(ts);
    }
    return bench_median(t, REPEATS);
}

int main(int argc, char **argv)
{
    long steps = argc > 1 ? atol(argv[1]) : 20000;
    int only = argc > 2 ? atoi(argv[2]) : 0;
    if (steps < 100 || only < 0 || only > 4 || argc > 3) {
        fprintf(stderr, "usage: bench_fly [STEPS >= 100 [CASE 1-4]]\n");
        return 2;
    }
    core_err err = {0};
    hfm_aircraft *ac = hfm_aircraft_load("scenarios/aircraft/uh60a.ini", NULL, &err);
    core_ship ship;
    if (!ac || core_ship_load("scenarios/ships/cg47.ini", &ship, &err)) {
        fprintf(stderr, "bench_fly: %s (run from the source root)\n", err.msg);
        return 1;
    }
    char path[128];
    snprintf(path, sizeof path, "/tmp/bench_fly_%ld.h5", (long)getpid());
    cfd_field *fld = small_field(&ship, path);
    unlink(path);
    if (!fld)
        return 1;
    double b = only ? 0.0 : baseline(ac, steps);
    struct {
        const char *name;
        const cfd_field *f;
        int turb, sea;
    } cases[] = {
        {"free stream, ship steady", NULL, 0, 0},
        {"field", fld, 0, 0},
        {"field + turbulence", fld, 1, 0},
        {"field + turbulence + sea state 5", fld, 1, 5},
    };
    printf("bench_fly: %ld steps at 200 Hz, median of %d, process CPU time\n", steps, REPEATS);
    printf("%-36s %10s %14s %10s\n", "case", "us/step", "x real time", "/ baseline");
    if (!only)
        printf("%-36s %10.2f %14.0f %10.2f\n", "baseline: hfm_tsim, uniform wind", 1e6 * b, 0.005 / b, 1.0);
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        if (only && (size_t)only != i + 1)
            continue;
        double t = fly_case(ac, &ship, cases[i].f, cases[i].turb, cases[i].sea, steps);
        if (t < 0)
            return 1;
        printf("%-36s %10.2f %14.0f %10.2f\n", cases[i].name, 1e6 * t, 0.005 / t, b > 0.0 ? t / b : NAN);
    }
    cfd_field_destroy(fld);
    hfm_aircraft_destroy(ac);
    return 0;
}
