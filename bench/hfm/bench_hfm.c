/* bench_hfm.c -- the flight model's speed: one evaluation of the trim
 * residual f(X, U), one trim from a cold start, a 16-point continuation
 * sweep (0-150 kt), and the time simulation's speed (ARKODE, 200 Hz) as a
 * multiple of real time. Each figure is the median of several repeats, in
 * process CPU time (the development machine is shared). */
#include "hfm.h"
#include "../bench.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

int main(int argc, char **argv)
{
    const char *path = argc > 1 ? argv[1] : "scenarios/aircraft/uh60a.ini";
    core_err err = {0};
    hfm_aircraft *ac = hfm_aircraft_load(path, NULL, &err);
    if (!ac) {
        fprintf(stderr, "bench_hfm: %s\n", err.msg);
        return 1;
    }
    hfm_trim *tr = hfm_trim_create(ac, NULL);
    hfm_trim_cond c;
    memset(&c, 0, sizeof c);
    c.kind = HFM_TRIM_FORWARD;
    c.airspeed_mps = 80.0 * CORE_KT_TO_MPS;
    hfm_trim_result r;
    if (hfm_trim_solve(tr, &c, NULL, &r)) {
        fprintf(stderr, "bench_hfm: trim failed\n");
        return 1;
    }
    printf("aircraft %s: %d blades, %s\n", hfm_aircraft_name(ac), hfm_aircraft_blades(ac), path);

    /* 1. f(X, U) */
    double rep[9], f[HFM_TRIM_N], sink = 0.0;
    int nf = 20000;
    for (int k = 0; k < 9; k++) {
        double t0 = bench_cpu_s();
        for (int i = 0; i < nf; i++) {
            r.x[0] += 1e-9;
            hfm_trim_residual(tr, &c, r.x, f);
            sink += f[0];
        }
        rep[k] = (bench_cpu_s() - t0) / nf;
    }
    printf("f(X, U) trim residual evaluation: %.2f us (limit 20 us)\n", bench_median(rep, 9) * 1e6);

    /* 2. trim from a cold start (hover, 80 kt, 140 kt) */
    const double spd[3] = {0.0, 80.0, 140.0};
    for (int s = 0; s < 3; s++) {
        c.airspeed_mps = spd[s] * CORE_KT_TO_MPS;
        int it = 0;
        for (int k = 0; k < 9; k++) {
            double t0 = bench_cpu_s();
            for (int i = 0; i < 20; i++)
                hfm_trim_solve(tr, &c, NULL, &r);
            rep[k] = (bench_cpu_s() - t0) / 20;
            it = r.iterations;
        }
        printf("cold-start trim at %3.0f kt: %.2f ms, %d Newton iterations, converged %d "
               "(limit 10 ms)\n",
               spd[s], bench_median(rep, 9) * 1e3, it, r.converged);
    }

    /* 3. 16-point sweep 0-150 kt */
    double v[16];
    hfm_trim_result res[16];
    for (int i = 0; i < 16; i++)
        v[i] = 10.0 * i * CORE_KT_TO_MPS;
    int bad = 0;
    for (int k = 0; k < 5; k++) {
        double t0 = bench_cpu_s();
        bad = hfm_trim_sweep(tr, &c, HFM_PARAM_AIRSPEED, v, 16, res);
        rep[k] = bench_cpu_s() - t0;
    }
    printf("16-point continuation sweep 0-150 kt: %.3f s, all converged %s (limit 0.2 s)\n",
           bench_median(rep, 5), bad ? "no" : "yes");

    /* 4. time simulation, ARKODE fixed step 200 Hz */
    c.airspeed_mps = 80.0 * CORE_KT_TO_MPS;
    hfm_trim_solve(tr, &c, NULL, &r);
    hfm_air_uniform still = {{0, 0, 0}};
    hfm_air air = {hfm_air_uniform_fn, &still, NULL};
    hfm_tsim *ts = hfm_tsim_create(ac, &air, HFM_TSIM_ARKODE_FIXED, 0.005, 0.0, NULL);
    double T = 60.0, best = 1e30;
    long ev0 = 0, ev = 0;
    for (int k = 0; k < 5; k++) {
        hfm_tsim_init(ts, 0.0, &r.body, &r.u, &r.rotor);
        ev0 = hfm_tsim_rhs_evals(ts);
        double t0 = bench_cpu_s();
        for (int i = 1; i <= 600; i++)
            hfm_tsim_advance(ts, T * i / 600.0);
        rep[k] = bench_cpu_s() - t0;
        best = rep[k] < best ? rep[k] : best;
        ev = hfm_tsim_rhs_evals(ts) - ev0;
    }
    double wall = bench_median(rep, 5);
    printf("time simulation (ARKODE ERKStep, Ralston 2-stage ERK2, multiblade coordinates, 200 Hz, "
           "80 kt): median %.0f x real time (best %.0f x), %.2f us per step, %.2f right-hand "
           "sides per step (limit >= 2000 x)\n",
           T / wall, T / best, wall / (T * 200.0) * 1e6, (double)ev / (T * 200.0));
    /* one right-hand side alone, at the state one step into the 80 kt run */
    {
        int n = hfm_tsim_size(ts);
        double y[64], yd[64];
        hfm_tsim_init(ts, 0.0, &r.body, &r.u, &r.rotor);
        hfm_tsim_advance(ts, 0.005);
        hfm_tsim_state(ts, y, n);
        int nr = 200000;
        for (int k = 0; k < 5; k++) {
            double t0 = bench_cpu_s();
            for (int i = 0; i < nr; i++) {
                y[0] += 1e-12;
                hfm_tsim_rhs(ts, 0.0, y, yd);
                sink += yd[3];
            }
            rep[k] = (bench_cpu_s() - t0) / nr;
        }
        printf("  one right-hand side (4 blades x 10 elements, tail rotor, fuselage, tail, "
               "6-DOF, inflow): %.2f us\n",
               bench_median(rep, 5) * 1e6);
    }
    hfm_tsim_destroy(ts);
    if (sink == 12345.678)
        printf("%g\n", sink);
    hfm_trim_destroy(tr);
    hfm_aircraft_destroy(ac);
    return 0;
}
