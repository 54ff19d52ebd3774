/* bench_interaction.c -- what the coupled rotor interaction near the
 * station (sim/interaction.c) adds to the flight loop's air: the UH-60A in
 * a trimmed hover at the station, 10 m/s head wind, 200 Hz, a ship-only
 * field and a coupled / isolated pair (synthetic fields on a 2 m grid
 * built here: the lookup's cost does not depend on their values), each
 * case flown STEPS steps (the trimmed start excluded), median of REPEATS:
 *   ship-only:   the step in the ship-only field;
 *   interaction: the same with the interaction (the weight 1: every
 *                sampling point pays for it).
 * And the air alone at 2000 points (80 % on the disk, 20 % beside it, as
 * the flight model samples: blade elements, then fuselage and tail), ns a
 * point. Process CPU time (the machine is shared). Usage: bench_interaction
 * [STEPS] from the source root. */
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

/* v = c0 + g x (each component) */
typedef struct lin {
    double c0[3], g[3];
} lin;

static int lin_inflow(void *user, const double p[3], double out[5])
{
    const lin *L = user;
    for (int k = 0; k < 3; k++)
        out[k] = L->c0[k] + L->g[k] * p[0];
    out[3] = 0.5;
    out[4] = 0.05;
    return 0;
}

static cfd_field *make_field(lin *L, const char *rotor, double thrust_N, const double hub[3], const char *tag)
{
    cfd_axis_spec ax[3] = {{-40, 40, 0, 0, 2.0, 2.0, 1.0}, {-40, 40, 0, 0, 2.0, 2.0, 1.0}, {-30, 2, 0, 0, 2.0, 2.0, 1.0}};
    core_err err = {0};
    cfd_config cfg;
    cfd_config_default(&cfg);
    cfg.u_ref_mps = 10.0;
    cfg.bc[CFD_XMAX].type = CFD_BC_INLET;
    cfg.bc[CFD_XMIN].type = CFD_BC_OUTLET;
    cfg.inflow.type = CFD_INFLOW_FIELD;
    cfg.inflow.fn = lin_inflow;
    cfg.inflow.fn_user = L;
    cfd_solver *s = cfd_solver_create(cfd_grid_create_spec(ax, &err), &cfg, &err);
    if (!s)
        return NULL;
    cfd_solver_init_inflow(s);
    cfd_meta m;
    memset(&m, 0, sizeof m);
    m.wod_speed_mps = 10.0;
    snprintf(m.ship, sizeof m.ship, "bench");
    snprintf(m.rotor, sizeof m.rotor, "%s", rotor);
    snprintf(m.grid, sizeof m.grid, "h2.000 m");
    m.rotor_thrust_N = thrust_N;
    m.rotor_radius_m = thrust_N > 0.0 ? 8.18 : 0.0;
    if (hub)
        memcpy(m.rotor_centre_S_m, hub, sizeof m.rotor_centre_S_m);
    char path[256], xmf[300];
    snprintf(path, sizeof path, "/tmp/disim_bench_interaction_%ld_%s.h5", (long)getpid(), tag);
    cfd_field *f = cfd_solver_write(s, &m, path, &err) == 0 ? cfd_field_load(path, &err) : NULL;
    cfd_solver_destroy(s);
    unlink(path);
    snprintf(xmf, sizeof xmf, "/tmp/disim_bench_interaction_%ld_%s.xmf", (long)getpid(), tag);
    unlink(xmf);
    if (!f)
        fprintf(stderr, "bench_interaction: field %s: %s\n", tag, err.msg);
    return f;
}

static double fly_us(const hfm_aircraft *ac, const core_ship *ship, const cfd_field *fs, sim_interaction *ia, long steps)
{
    sim_flight_opts o;
    sim_flight_opts_default(&o);
    o.wod_speed_mps = 10.0;
    o.turbulence = 0;
    o.interaction = ia;
    core_err err = {0};
    double t[REPEATS];
    for (int r = 0; r < REPEATS; r++) {
        sim_flight *f = sim_flight_create(ac, ship, &o, NULL, NULL, fs, NULL, &err);
        if (!f) {
            fprintf(stderr, "bench_interaction: %s\n", err.msg);
            return NAN;
        }
        sim_flight_inputs in;
        sim_flight_trim_inputs(f, &in);
        double t0 = bench_cpu_s();
        for (long i = 0; i < steps; i++)
            if (sim_flight_step(f, &in, NULL, &err) != 0)
                break;
        t[r] = (bench_cpu_s() - t0) / steps;
        sim_flight_destroy(f);
    }
    return 1e6 * bench_median(t, REPEATS);
}

static double air_ns(const cfd_field *fs, const sim_interaction *ia)
{
    enum { N = 2000 };
    static double p[N][3];
    unsigned s = 1;
    for (int i = 0; i < N; i++) {
        double r = 8.0 * ((s = s * 1103515245u + 12345u) % 1000) / 1000.0;
        double ps = 2.0 * M_PI * ((s = s * 1103515245u + 12345u) % 1000) / 1000.0;
        if (i % 5) { /* a blade element */
            p[i][0] = r * cos(ps), p[i][1] = r * sin(ps), p[i][2] = -8.0;
        } else { /* fuselage, tail */
            p[i][0] = r - 10.0, p[i][1] = 0.0, p[i][2] = -5.0;
        }
    }
    sim_air_opts ao;
    sim_air_opts_default(&ao);
    ao.wod_speed_mps = 10.0;
    ao.deck_height_m = 10.0;
    core_err err = {0};
    sim_air *a = sim_air_create(&ao, &err);
    if (!a || sim_air_set_field(a, fs, -INFINITY, &err) != 0) {
        sim_air_destroy(a);
        return NAN;
    }
    sim_air_in in = {NULL, ia};
    double t[REPEATS], v[3], sum = 0.0;
    for (int r = 0; r < REPEATS; r++) {
        double t0 = bench_cpu_s();
        for (int k = 0; k < 100; k++)
            for (int i = 0; i < N; i++) {
                sim_air_sample_S(a, &in, p[i], 0.0, v);
                sum += v[2];
            }
        t[r] = (bench_cpu_s() - t0) / (100.0 * N);
    }
    sim_air_destroy(a);
    double m = bench_median(t, REPEATS);
    return sum == 1234.5 ? 0.0 : 1e9 * m; /* sum keeps the loop */
}

int main(int argc, char **argv)
{
    long steps = argc > 1 ? atol(argv[1]) : 20000;
    core_err err = {0};
    hfm_aircraft *ac = hfm_aircraft_load("scenarios/aircraft/uh60a.ini", NULL, &err);
    core_ship ship;
    if (!ac || core_ship_load("scenarios/ships/sfs2.ini", &ship, &err) != 0) {
        fprintf(stderr, "bench_interaction: %s (run from the source root)\n", err.msg);
        hfm_aircraft_destroy(ac);
        return 1;
    }
    double hub[3] = {0.0, 0.0, -8.0};
    lin S = {{-8.0, 0.6, 0.4}, {0.03, -0.01, 0.02}}, I = {{-10.0, 0.0, 9.0}, {0.05, 0.0, -0.02}},
        C = {{-8.0, 0.6, 7.8}, {0.08, -0.01, 0.0}};
    cfd_field *fs = make_field(&S, "off", 0.0, NULL, "ship"), *fi = make_field(&I, "uniform", 73000.0, hub, "iso"),
              *fc = make_field(&C, "uniform", 73000.0, hub, "cpl");
    sim_interaction_opts io;
    sim_interaction_opts_default(&io);
    io.station_S_m[2] = -6.0;
    sim_interaction *ia = fs && fi && fc ? sim_interaction_create(fc, fi, &io, &err) : NULL;
    if (!ia) {
        fprintf(stderr, "bench_interaction: %s\n", err.msg);
        return 1;
    }
    double a0 = air_ns(fs, NULL), a1 = air_ns(fs, ia);
    printf("the air at a point: ship-only %.1f ns, with the interaction %.1f ns (+%.1f)\n", a0, a1, a1 - a0);
    double s0 = fly_us(ac, &ship, fs, NULL, steps), s1 = fly_us(ac, &ship, fs, ia, steps);
    printf("the flight step (%ld steps, median of %d): ship-only %.2f us (%.0f x real time at 200 Hz), with the "
           "interaction %.2f us (%.0f x), +%.2f us\n", steps, REPEATS, s0, 5000.0 / s0, s1, 5000.0 / s1, s1 - s0);
    sim_interaction_destroy(ia);
    cfd_field_destroy(fs);
    cfd_field_destroy(fi);
    cfd_field_destroy(fc);
    hfm_aircraft_destroy(ac);
    return 0;
}
