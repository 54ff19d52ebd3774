/* test_turbulence.c -- the Dryden turbulence of sim/turbulence.c: over a
 * long run at fixed points with constant k and epsilon (10^6 steps at
 * 200 Hz, 5000 s, about 12 500 time scales), each component's standard
 * deviation is sqrt(2k/3) (within 10 %), its correlation time is
 * L/V with L = Cmu^0.75 k^1.5 / epsilon (within 20 %: the lag where the
 * autocorrelation falls to 1/e, which the Dryden correlations put at L/V
 * for u and 0.6253 L/V for v and w), and in hover in calm air L over the
 * convection floor; two points L/10 apart along or across the wind are
 * correlated as the Dryden correlations say (within 0.04: the field's rows
 * L/16 apart and lanes L/8 apart, interpolated linearly, raise the
 * correlation at L/10 by 0.02 to 0.03 over the continuous form; u along the
 * wind above 0.9), and L/2 apart (within 0.04, where the longitudinal f
 * and transverse g differ by 0.15), and points more than 5 L apart are not
 * (below 0.2); the
 * intensity is local; off, the gust is exactly zero; the same seed gives
 * the same bits and another seed other ones; bad options and input are
 * refused. */
#include "check.h"
#include "sim.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define RATE_HZ 200.0
#define NSTEP 1000000

static const double K = 6.0;   /* m^2/s^2: sigma = 2 m/s */
static const double L_M = 4.0; /* epsilon set for this L */
static double eps_for(double L)
{
    return pow(0.09, 0.75) * pow(K, 1.5) / L;
}

/* Sample correlation of a and b (n values each). */
static double corr(const double *a, const double *b, size_t n)
{
    double ma = 0, mb = 0;
    for (size_t i = 0; i < n; i++) {
        ma += a[i];
        mb += b[i];
    }
    ma /= n;
    mb /= n;
    double sab = 0, saa = 0, sbb = 0;
    for (size_t i = 0; i < n; i++) {
        sab += (a[i] - ma) * (b[i] - mb);
        saa += (a[i] - ma) * (a[i] - ma);
        sbb += (b[i] - mb) * (b[i] - mb);
    }
    return sab / sqrt(saa * sbb);
}

static double stdev(const double *a, size_t n)
{
    double m = 0, s = 0;
    for (size_t i = 0; i < n; i++)
        m += a[i];
    m /= n;
    for (size_t i = 0; i < n; i++)
        s += (a[i] - m) * (a[i] - m);
    return sqrt(s / n);
}

/* The lag (in samples, interpolated) where the autocorrelation of a first
 * falls below target; -1 if not within max_lag. */
static double lag_below(const double *a, size_t n, double target, int max_lag)
{
    double m = 0, s0 = 0;
    for (size_t i = 0; i < n; i++)
        m += a[i];
    m /= n;
    for (size_t i = 0; i < n; i++)
        s0 += (a[i] - m) * (a[i] - m);
    double prev = 1.0;
    for (int lag = 1; lag <= max_lag; lag++) {
        double s = 0;
        for (size_t i = 0; i + (size_t)lag < n; i++)
            s += (a[i] - m) * (a[i + lag] - m);
        double r = s / s0;
        if (r < target)
            return lag - 1 + (prev - target) / (prev - r);
        prev = r;
    }
    return -1.0;
}

/* x* with (1 - x/2) e^-x = 1/e: the 1/e lag of g in units of L. */
static double g_one_over_e(void)
{
    double lo = 0.0, hi = 1.0;
    for (int i = 0; i < 60; i++) {
        double x = 0.5 * (lo + hi);
        if ((1 - 0.5 * x) * exp(-x) > exp(-1.0))
            lo = x;
        else
            hi = x;
    }
    return 0.5 * (lo + hi);
}

/* The points of the long run, as offsets from the reference in wind axes
 * (along e1, across e2): the reference, L/10 downstream, L/10 across, and
 * the same L/2 away, and two pairs 5.5 L apart along and across the wind. */
enum { P_REF, P_DOWN, P_ACROSS, P_DOWN_HALF, P_ACROSS_HALF, P_UP_FAR, P_DOWN_FAR, P_LEFT_FAR, P_RIGHT_FAR, NP };
static const double offs[NP][2] = {{0, 0},     {0.1, 0},  {0, 0.1},   {0.5, 0},  {0, 0.5},
                                   {-2.75, 0}, {2.75, 0}, {0, -2.75}, {0, 2.75}}; /* in L */

/* One long run with the wind vel_S; series[p][c][i] of the components in
 * wind axes at point p. every: keep one step in every. */
static int long_run(const double vel_S[3], uint64_t seed, int every, double *series[NP][3], size_t *n_out)
{
    core_err err = {0};
    sim_turb_opts o;
    sim_turb_opts_default(&o);
    sim_turb *t = sim_turb_create(&o, seed, &err);
    if (!t) {
        fprintf(stderr, "%s\n", err.msg);
        return -1;
    }
    const double ref[3] = {0.0, 0.0, -5.0};
    size_t n = 0;
    long bad = 0;
    double dt = 1.0 / RATE_HZ, eps = eps_for(L_M);
    sim_turb_state st;
    for (long i = 0; i < NSTEP; i++) {
        if (sim_turb_step(t, ref, vel_S, K, eps, dt, &err)) {
            fprintf(stderr, "%s\n", err.msg);
            sim_turb_destroy(t);
            return -1;
        }
        if (i == 0)
            sim_turb_info(t, &st);
        if (i % every)
            continue;
        for (int p = 0; p < NP; p++) {
            double pos[3], g[3];
            for (int k = 0; k < 3; k++)
                pos[k] = ref[k] + L_M * (offs[p][0] * st.e1[k] + offs[p][1] * st.e2[k]);
            bad += sim_turb_sample(t, pos, K, g) != 0;
            series[p][0][n] = g[0] * st.e1[0] + g[1] * st.e1[1] + g[2] * st.e1[2];
            series[p][1][n] = g[0] * st.e2[0] + g[1] * st.e2[1] + g[2] * st.e2[2];
            series[p][2][n] = g[0] * st.e3[0] + g[1] * st.e3[1] + g[2] * st.e3[2];
        }
        n++;
    }
    CHECK(bad == 0);
    sim_turb_info(t, &st);
    CHECK(st.relays == 0);
    CHECK_NEAR(st.length_m, L_M, 1e-12);
    sim_turb_destroy(t);
    *n_out = n;
    return 0;
}

static void statistics(void)
{
    static double *series[NP][3];
    for (int p = 0; p < NP; p++)
        for (int c = 0; c < 3; c++)
            series[p][c] = malloc(sizeof(double) * NSTEP);
    const char *name[3] = {"u", "v", "w"};
    double sigma = sqrt(2.0 * K / 3.0), xg = g_one_over_e();
    double f01 = exp(-0.1), g01 = 0.95 * exp(-0.1), f05 = exp(-0.5), g05 = 0.75 * exp(-0.5);

    /* a 10 m/s wind from green 30: S axes are not the wind axes */
    const double vel[3] = {-10.0 * cos(M_PI / 6), -10.0 * sin(M_PI / 6), 0.0};
    size_t n = 0;
    CHECK(long_run(vel, 1, 1, series, &n) == 0);
    double T_steps = L_M / 10.0 * RATE_HZ;
    for (int c = 0; c < 3 && n; c++) {
        double sd = stdev(series[P_REF][c], n);
        double lag = lag_below(series[P_REF][c], n, exp(-1.0), (int)(3 * T_steps));
        double T = lag / (c == 0 ? 1.0 : xg);
        double r_along = corr(series[P_REF][c], series[P_DOWN][c], n);
        double r_across = corr(series[P_REF][c], series[P_ACROSS][c], n);
        double r_along2 = corr(series[P_REF][c], series[P_DOWN_HALF][c], n);
        double r_across2 = corr(series[P_REF][c], series[P_ACROSS_HALF][c], n);
        double r_far_along = corr(series[P_UP_FAR][c], series[P_DOWN_FAR][c], n);
        double r_far_across = corr(series[P_LEFT_FAR][c], series[P_RIGHT_FAR][c], n);
        printf("V 10 m/s, %s: sd %.4f m/s (sqrt(2k/3) %.4f), correlation time %.4f s (L/V %.4f), "
               "corr L/10 along %.4f across %.4f, L/2 along %.4f across %.4f, 5.5 L along %.4f across %.4f\n",
               name[c], sd, sigma, T / RATE_HZ, T_steps / RATE_HZ, r_along, r_across, r_along2, r_across2,
               r_far_along, r_far_across);
        CHECK(fabs(sd / sigma - 1.0) < 0.10);
        CHECK(fabs(T / T_steps - 1.0) < 0.20);
        /* Dryden: along the wind f for u, g for v and w; across, g for u
         * and w, f for v (its own direction) */
        CHECK(fabs(r_along - (c == 0 ? f01 : g01)) < 0.04);
        CHECK(fabs(r_across - (c == 1 ? f01 : g01)) < 0.04);
        /* at L/2, where f (0.607) and g (0.455) differ */
        CHECK(fabs(r_along2 - (c == 0 ? f05 : g05)) < 0.04);
        CHECK(fabs(r_across2 - (c == 1 ? f05 : g05)) < 0.04);
        if (c == 0)
            CHECK(r_along > 0.9);
        CHECK(fabs(r_far_along) < 0.2);
        CHECK(fabs(r_far_across) < 0.2);
    }
    /* a downstream point sees the reference's gust later by d / V: the
     * cross-correlation at that lag is the highest */
    if (n) {
        int d_steps = (int)lround(0.1 * L_M / 10.0 * RATE_HZ); /* 0.4 m at 10 m/s: 8 steps */
        double best = -2;
        int best_lag = -1;
        for (int lag = 0; lag <= 3 * d_steps; lag++) {
            double r = corr(series[P_REF][0], series[P_DOWN][0] + lag, n - (size_t)lag);
            if (r > best) {
                best = r;
                best_lag = lag;
            }
        }
        printf("u downstream L/10: highest correlation %.4f at lag %d steps (d/V = %d)\n", best, best_lag, d_steps);
        CHECK(abs(best_lag - d_steps) <= 1);
        CHECK(best > 0.99);
    }

    /* hover in calm air: the pattern passes at the 2 m/s floor, L/V = 2 s;
     * one step in 10 kept (the time scale is 400 steps) */
    const double calm[3] = {0.0, 0.0, 0.0};
    CHECK(long_run(calm, 2, 10, series, &n) == 0);
    double T_calm = L_M / 2.0 * RATE_HZ / 10.0;
    for (int c = 0; c < 3 && n; c++) {
        double sd = stdev(series[P_REF][c], n);
        double lag = lag_below(series[P_REF][c], n, exp(-1.0), (int)(3 * T_calm));
        double T = lag / (c == 0 ? 1.0 : xg);
        printf("calm, %s: sd %.4f m/s, correlation time %.3f s (L / 2 m/s = %.3f)\n", name[c], sd, T * 10 / RATE_HZ,
               T_calm * 10 / RATE_HZ);
        CHECK(fabs(sd / sigma - 1.0) < 0.10);
        CHECK(fabs(T / T_calm - 1.0) < 0.20);
    }
    for (int p = 0; p < NP; p++)
        for (int c = 0; c < 3; c++)
            free(series[p][c]);
}

/* A short run's samples at a few points: n steps of 3 points, 3 components. */
static void short_run(const sim_turb_opts *o, uint64_t seed, int n, double *out)
{
    core_err err = {0};
    sim_turb *t = sim_turb_create(o, seed, &err);
    CHECK(t != NULL);
    if (!t)
        return;
    const double ref[3] = {1.0, -2.0, -5.0}, vel[3] = {-12.0, 3.0, 0.5};
    const double pts[3][3] = {{1.0, -2.0, -5.0}, {-6.0, 4.0, -4.0}, {30.0, -30.0, 0.0}};
    for (int i = 0; i < n; i++) {
        CHECK(sim_turb_step(t, ref, vel, K, eps_for(L_M), 1.0 / RATE_HZ, &err) == 0);
        for (int p = 0; p < 3; p++)
            CHECK(sim_turb_sample(t, pts[p], K, out + (i * 3 + p) * 3) == 0);
    }
    sim_turb_destroy(t);
}

static void determinism_and_off(void)
{
    enum { N = 4000 };
    static double a[N * 9], b[N * 9], c[N * 9];
    sim_turb_opts o;
    sim_turb_opts_default(&o);
    short_run(&o, 42, N, a);
    short_run(&o, 42, N, b);
    short_run(&o, 43, N, c);
    CHECK(memcmp(a, b, sizeof a) == 0);
    int same = 0;
    for (int i = 0; i < N * 9; i++)
        same += a[i] == c[i];
    CHECK(same == 0);
    double amax = 0;
    for (int i = 0; i < N * 9; i++)
        amax = fmax(amax, fabs(a[i]));
    CHECK(amax > 1.0); /* the run is turbulent at all */

    /* reset gives the run again */
    core_err err = {0};
    sim_turb *t = sim_turb_create(&o, 7, &err);
    const double ref[3] = {0, 0, -5}, vel[3] = {-10, 0, 0}, p[3] = {-3, 2, -5};
    double g1[3], g2[3];
    for (int i = 0; i < 100; i++)
        sim_turb_step(t, ref, vel, K, eps_for(L_M), 0.005, &err);
    sim_turb_sample(t, p, K, g1);
    sim_turb_reset(t, 7);
    double g0[3];
    CHECK(sim_turb_sample(t, p, K, g0) == 1); /* no field before a step */
    CHECK(g0[0] == 0 && g0[1] == 0 && g0[2] == 0);
    for (int i = 0; i < 100; i++)
        sim_turb_step(t, ref, vel, K, eps_for(L_M), 0.005, &err);
    sim_turb_sample(t, p, K, g2);
    CHECK(memcmp(g1, g2, sizeof g1) == 0);
    /* sampling changes nothing; the intensity is the point's own */
    double g3[3], g4[3];
    sim_turb_sample(t, p, K, g3);
    CHECK(memcmp(g2, g3, sizeof g2) == 0);
    sim_turb_sample(t, p, 4.0 * K, g4);
    for (int i = 0; i < 3; i++)
        CHECK_NEAR(g4[i], 2.0 * g3[i], 1e-12 * fabs(g3[i]) + 1e-15);
    sim_turb_sample(t, p, 0.0, g4);
    CHECK(g4[0] == 0 && g4[1] == 0 && g4[2] == 0);
    sim_turb_destroy(t);

    /* off: exactly zero at every point and step */
    o.enabled = 0;
    short_run(&o, 42, N, c);
    int nonzero = 0;
    for (int i = 0; i < N * 9; i++)
        nonzero += c[i] != 0.0;
    CHECK(nonzero == 0);
}

static void scales(void)
{
    sim_turb_opts o;
    sim_turb_opts_default(&o);
    CHECK_NEAR(sim_turb_length_m(&o, K, eps_for(L_M)), L_M, 1e-12);
    CHECK_NEAR(sim_turb_length_m(&o, 1.0, pow(0.09, 0.75) / 50.0), 50.0, 1e-9);
    CHECK(sim_turb_length_m(&o, 0.0, 1.0) == o.length_min_m);
    CHECK(sim_turb_length_m(&o, 1.0, 0.0) == o.length_max_m);
    CHECK(sim_turb_length_m(&o, 1e-4, 1.0) == o.length_min_m);
    CHECK(sim_turb_length_m(&o, 1e4, 1e-3) == o.length_max_m);
}

static void refusals(void)
{
    core_err err = {0};
    sim_turb_opts o;
    /* each bad option refused, its name in the message */
    const char *names[] = {"enabled", "cmu", "cmu", "length_min_m", "length_max_m", "length_max_m",
                           "speed_min_mps", "extent_m", "extent_m", "ds_m", "dy_m", "ds_m", "extent_m"};
    for (int i = 0; i < (int)(sizeof names / sizeof *names); i++) {
        sim_turb_opts_default(&o);
        switch (i) {
        case 0: o.enabled = 2; break;
        case 1: o.cmu = 0.0; break;
        case 2: o.cmu = 1.5; break;
        case 3: o.length_min_m = -1.0; break;
        case 4: o.length_max_m = NAN; break;
        case 5: o.length_max_m = 1.0; break; /* below the 2 m floor */
        case 6: o.speed_min_mps = 0.0; break;
        case 7: o.extent_m = INFINITY; break;
        case 8: o.extent_m = 0.5; break;
        case 9: o.ds_m = 0.0; break;
        case 10: o.dy_m = 1.5; break; /* coarser than length_min_m / 2 */
        case 11: o.ds_m = 0.6; break; /* coarser than length_min_m / 4 */
        case 12: o.extent_m = 1e5; break; /* too many lanes */
        }
        err.msg[0] = 0;
        sim_turb *t = sim_turb_create(&o, 1, &err);
        CHECK(t == NULL);
        CHECK(strstr(err.msg, names[i]) != NULL);
        if (!t && !strstr(err.msg, names[i]))
            fprintf(stderr, "case %d: %s\n", i, err.msg);
        sim_turb_destroy(t);
    }
    CHECK(sim_turb_create(NULL, 1, &err) == NULL);

    /* bad input to a step or a sample */
    sim_turb_opts_default(&o);
    sim_turb *t = sim_turb_create(&o, 1, &err);
    const double ref[3] = {0, 0, -5}, vel[3] = {-10, 0, 0}, nanp[3] = {0, NAN, 0};
    CHECK(sim_turb_step(t, ref, vel, -1.0, 1.0, 0.005, &err) < 0);
    CHECK(strstr(err.msg, "k = -1") != NULL);
    CHECK(sim_turb_step(t, ref, vel, 1.0, NAN, 0.005, &err) < 0);
    CHECK(sim_turb_step(t, ref, vel, 1.0, 1.0, -0.005, &err) < 0);
    CHECK(strstr(err.msg, "dt") != NULL);
    CHECK(sim_turb_step(t, nanp, vel, 1.0, 1.0, 0.005, &err) < 0);
    CHECK(sim_turb_step(t, ref, nanp, 1.0, 1.0, 0.005, &err) < 0);
    CHECK(sim_turb_step(t, ref, vel, 1.0, 1.0, 0.005, &err) == 0);
    double g[3] = {1, 1, 1};
    CHECK(sim_turb_sample(t, nanp, 1.0, g) < 0);
    CHECK(g[0] == 0 && g[1] == 0 && g[2] == 0);
    CHECK(sim_turb_sample(t, ref, -1.0, g) < 0);
    CHECK(sim_turb_sample(t, ref, 1.0, g) == 0);
    sim_turb_destroy(t);
}

int main(void)
{
    scales();
    refusals();
    determinism_and_off();
    statistics();
    return check_done("test_turbulence");
}
