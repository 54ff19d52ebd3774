/* bench_turb.c -- the cost of the Dryden turbulence (sim/turbulence.c) in
 * the flight loop: ns per sim_turb_sample (one point's gust) and per
 * sim_turb_step (the field advanced one 200 Hz step), with the default
 * options, at the points a flight model samples (a 64-point rotor disk of
 * 8 m radius, fuselage and tail), in a 10 m/s and a 20 m/s wind and in calm
 * air. The samples' time includes rotating the blade points (two
 * multiplications each) and a cos and sin per step. The baseline, in the same run, is one plain uniform random draw
 * (splitmix64 to a double); the ratio is printed. Each figure is the median
 * of 7 repeats, in process CPU time (the development machine is shared). */
#include "sim.h"
#include "../bench.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#define NPTS 66
#define STEPS 20000
#define REPEATS 7

static uint64_t splitmix64(uint64_t *x)
{
    uint64_t z = (*x += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

static volatile double sink;

int main(void)
{
    double pts[NPTS][3];
    for (int i = 0; i < 64; i++) { /* 4 blades x 16 elements, rotated each step below */
        double r = 0.5 * (1 + i % 16) * 8.0 / 16.0, a = (i / 16) * M_PI / 2;
        pts[i][0] = r * cos(a);
        pts[i][1] = r * sin(a);
        pts[i][2] = -6.0;
    }
    pts[64][0] = 0.0, pts[64][1] = 0.0, pts[64][2] = -4.0;   /* fuselage */
    pts[65][0] = -9.9, pts[65][1] = 0.0, pts[65][2] = -5.5; /* tail */
    const double k = 6.0, eps = pow(0.09, 0.75) * pow(k, 1.5) / 4.0, dt = 1.0 / 200.0;
    const double ref[3] = {0.0, 0.0, -6.0};
    const double speeds[3] = {10.0, 20.0, 0.0};

    /* baseline: one uniform draw */
    double tb[REPEATS];
    uint64_t s = 1;
    for (int r = 0; r < REPEATS; r++) {
        double t0 = bench_cpu_s(), acc = 0;
        for (long i = 0; i < (long)STEPS * NPTS; i++)
            acc += (double)(splitmix64(&s) >> 11) * 0x1.0p-53;
        tb[r] = (bench_cpu_s() - t0) / ((double)STEPS * NPTS) * 1e9;
        sink = acc;
    }
    double base = bench_median(tb, REPEATS);
    printf("baseline: one uniform draw %.2f ns\n", base);

    sim_turb_opts o;
    sim_turb_opts_default(&o);
    core_err err = {0};
    for (int c = 0; c < 3; c++) {
        double vel[3] = {-speeds[c], 0.0, 0.0}, tstep[REPEATS], tsamp[REPEATS];
        sim_turb *t = sim_turb_create(&o, 1, &err);
        if (!t) {
            fprintf(stderr, "bench_turb: %s\n", err.msg);
            return 1;
        }
        for (int r = 0; r < REPEATS; r++) {
            /* the steps alone, then the samples over the field as it stands */
            double t0 = bench_cpu_s(), acc = 0;
            for (int i = 0; i < STEPS; i++)
                if (sim_turb_step(t, ref, vel, k, eps, dt, &err)) {
                    fprintf(stderr, "bench_turb: %s\n", err.msg);
                    return 1;
                }
            double t1 = bench_cpu_s();
            for (int i = 0; i < STEPS; i++) {
                double ca = cos(0.14 * i), sa = sin(0.14 * i); /* the blades turn 27 rad/s */
                for (int p = 0; p < NPTS; p++) {
                    double q[3] = {pts[p][0], pts[p][1], pts[p][2]}, g[3];
                    if (p < 64) {
                        q[0] = ca * pts[p][0] - sa * pts[p][1];
                        q[1] = sa * pts[p][0] + ca * pts[p][1];
                    }
                    sim_turb_sample(t, q, k, g);
                    acc += g[0] + g[1] + g[2];
                }
            }
            double t2 = bench_cpu_s();
            sink = acc;
            tstep[r] = (t1 - t0) / STEPS * 1e9;
            tsamp[r] = (t2 - t1) / ((double)STEPS * NPTS) * 1e9;
        }
        sim_turb_state st;
        sim_turb_info(t, &st);
        double ms = bench_median(tsamp, REPEATS), mt = bench_median(tstep, REPEATS);
        printf("wind %4.1f m/s (%d lanes, %d rows): sample %.1f ns (%.1f x a uniform draw), "
               "step %.0f ns (%.1f x), per 200 Hz step with %d points %.2f us\n",
               speeds[c], st.lanes, st.rows, ms, ms / base, mt, mt / base, NPTS, (mt + NPTS * ms) * 1e-3);
        sim_turb_destroy(t);
    }
    return 0;
}
