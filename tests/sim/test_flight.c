/* test_flight.c -- the flight loop's deterministic step (sim/flight.c,
 * sim/air.c): the trimmed start, the Earth frame with a moving ship, the
 * external loads, determinism, the free stream over the sea and the field
 * blend. Run from the source root. */
#include "cfd.h"
#include "check.h"
#include "hfm.h"
#include "sim.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define UH60 "scenarios/aircraft/uh60a.ini"
#define SHIP "scenarios/ships/sfs2.ini"

typedef struct run {
    sim_flight_out out[4096];
    int n;
} run;

/* Fly n steps holding the trim's controls. */
static int fly(sim_flight *f, int n, run *r)
{
    sim_flight_inputs in;
    sim_flight_trim_inputs(f, &in);
    core_err err = {{0}};
    r->n = 0;
    for (int i = 0; i < n && i < 4096; i++) {
        if (sim_flight_step(f, &in, &r->out[i], &err) != 0) {
            fprintf(stderr, "step %d: %s\n", i, err.msg);
            return -1;
        }
        r->n++;
    }
    return 0;
}

static sim_flight *make(const hfm_aircraft *ac, const core_ship *ship, double wod_mps, double dir_deg, double ship_mps)
{
    sim_flight_opts o;
    sim_flight_opts_default(&o);
    o.wod_speed_mps = wod_mps;
    o.wod_dir_rad = dir_deg * CORE_DEG_TO_RAD;
    o.ship_speed_mps = ship_mps;
    core_err err = {{0}};
    sim_flight *f = sim_flight_create(ac, ship, &o, NULL, NULL, NULL, NULL, &err);
    if (!f)
        fprintf(stderr, "flight: %s\n", err.msg);
    return f;
}

static double drift_m(const run *r, const double station[3])
{
    const double *p = r->out[r->n - 1].pos_S_m;
    return sqrt((p[0] - station[0]) * (p[0] - station[0]) + (p[1] - station[1]) * (p[1] - station[1]) +
                (p[2] - station[2]) * (p[2] - station[2]));
}

static run ra, rb;

/* A trimmed hover stays trimmed for a while; flown over a ship moving at
 * U in a WOD of V it is the same flight, relative to the ship, as over a
 * ship at rest in the same WOD (Galilean invariance of the Earth-frame
 * integration with the air attached to the ship); the same inputs give the
 * same trajectory bit for bit. */
static void test_frames(const hfm_aircraft *ac, const core_ship *ship)
{
    const double station[3] = {0.0, 0.0, -6.0};
    sim_flight *a = make(ac, ship, 10.0, 0.0, 0.0), *b = make(ac, ship, 10.0, 0.0, 10.0);
    CHECK(a && b);
    if (!a || !b) {
        sim_flight_destroy(a);
        sim_flight_destroy(b);
        return;
    }
    CHECK(fly(a, 400, &ra) == 0 && fly(b, 400, &rb) == 0);
    double d = drift_m(&ra, station);
    printf("hover in a 10 m/s head wind: %.2e m from the station after %.1f s (open loop, trim controls)\n", d,
           ra.out[ra.n - 1].t_s);
    CHECK(d < 0.01);
    double e = 0.0;
    for (int i = 0; i < ra.n && i < rb.n; i++)
        for (int k = 0; k < 3; k++) {
            e = fmax(e, fabs(ra.out[i].pos_S_m[k] - rb.out[i].pos_S_m[k]));
            e = fmax(e, fabs(ra.out[i].euler_E_rad[k] - rb.out[i].euler_E_rad[k]));
        }
    printf("moving ship (10 m/s) against a ship at rest, same WOD: max difference %.2e (m, rad) over %d steps\n", e,
           ra.n);
    CHECK(e < 1e-6);
    /* the moving ship's spot has gone 20 m north in 2 s and the helicopter with it */
    CHECK_NEAR(rb.out[rb.n - 1].pos_E_m[0] - ra.out[ra.n - 1].pos_E_m[0], 10.0 * rb.out[rb.n - 1].t_s, 1e-6);
    sim_flight_destroy(a);
    sim_flight_destroy(b);

    sim_flight *c = make(ac, ship, 10.0, 0.0, 0.0);
    CHECK(c != NULL);
    if (c) {
        CHECK(fly(c, 400, &rb) == 0);
        CHECK(rb.n == ra.n && memcmp(ra.out, rb.out, (size_t)ra.n * sizeof ra.out[0]) == 0);
        sim_flight_destroy(c);
    }
}

static int down_load(void *user, double t_s, const hfm_body *b, double F_B_N[3], double M_B_Nm[3])
{
    (void)t_s, (void)b;
    F_B_N[0] = F_B_N[1] = 0.0;
    F_B_N[2] = *(const double *)user;
    M_B_Nm[0] = M_B_Nm[1] = M_B_Nm[2] = 0.0;
    return 0;
}

/* An external load reaches the body: 10 % of the weight downward makes
 * the hover sink, at first at 0.1 g. */
static void test_external(const hfm_aircraft *ac, const core_ship *ship)
{
    sim_flight *f = make(ac, ship, 0.0, 0.0, 0.0);
    CHECK(f != NULL);
    if (!f)
        return;
    double F = 0.1 * hfm_aircraft_weight_N(ac);
    sim_flight_set_external(f, down_load, &F);
    CHECK(fly(f, 40, &ra) == 0);
    double w = ra.out[ra.n - 1].vel_E_mps[2], t = ra.out[ra.n - 1].t_s;
    printf("10 %% of the weight down for %.2f s: sinks at %.3f m/s (0.1 g t = %.3f)\n", t, w,
           0.1 * CORE_G_MPS2 * t);
    CHECK(w > 0.5 * 0.1 * CORE_G_MPS2 * t && w < 1.2 * 0.1 * CORE_G_MPS2 * t);
    sim_flight_destroy(f);
}

static int level_ship(void *user, double t_s, sim_ship_frame *fr)
{
    (void)user, (void)t_s;
    memset(fr, 0, sizeof *fr);
    fr->C_ES[0] = fr->C_ES[4] = fr->C_ES[8] = 1.0;
    return 0;
}

/* The free stream: the WOD at anemometer height, the log law over the sea
 * below and above it; a new field offered at t blends in linearly over
 * blend_s (a field that is not ship-only is refused). */
static void test_air(const core_ship *ship, const cfd_field *fld)
{
    sim_air_opts o;
    sim_air_opts_default(&o);
    o.wod_speed_mps = 15.0;
    o.deck_height_m = ship->deck_height_m;
    o.anemometer_height_m = 20.0;
    core_err err = {{0}};
    sim_air *a = sim_air_create(&o, level_ship, NULL, &err);
    CHECK(a != NULL);
    if (!a)
        return;
    double at_an[3] = {0.0, 0.0, ship->deck_height_m - 20.0}, v[3];
    CHECK(sim_air_sample_S(a, at_an, 0.0, v) == 1);
    CHECK_NEAR(v[0], -15.0, 1e-9);
    CHECK_NEAR(v[1], 0.0, 1e-12);
    double low[3] = {0.0, 0.0, ship->deck_height_m - 2.0};
    sim_air_sample_S(a, low, 0.0, v);
    CHECK_NEAR(v[0], -15.0 * log(2.0 / 2e-4) / log(20.0 / 2e-4), 1e-9);
    CHECK(sim_air_flags(a, 0.0) == SIM_AIR_FREE_STREAM);
    if (fld) {
        CHECK(sim_air_set_field(a, fld, 10.0, &err) == 0);
        double p[3] = {-5.0, 0.0, -6.0}, vf[3], vh[3], o5[CFD_NVARS];
        CHECK(cfd_field_sample(fld, p, o5) == 0);
        double scale = 15.0 / cfd_field_meta(fld)->wod_speed_mps;
        sim_air_sample_S(a, p, 9.0, vf); /* before the blend starts: the free stream */
        double fs[3];
        CHECK(sim_air_sample_S(a, p, 20.0, vh) == 0); /* after: the field */
        CHECK_NEAR(vh[0], scale * o5[CFD_VAR_U], 1e-9);
        CHECK_NEAR(vh[2], scale * o5[CFD_VAR_W], 1e-9);
        double mid[3];
        sim_air_sample_S(a, p, 10.0 + 0.5 * 3.0, mid); /* half way */
        for (int k = 0; k < 3; k++)
            fs[k] = vf[k];
        CHECK_NEAR(mid[0], 0.5 * (fs[0] + vh[0]), 1e-9);
        CHECK(sim_air_flags(a, 11.0) == SIM_AIR_BLENDING);
        CHECK(sim_air_flags(a, 14.0) == 0);
        /* the largest change of the air in one 200 Hz step during the blend */
        double jump = 0.0, prev[3];
        sim_air_sample_S(a, p, 10.0, prev);
        for (int i = 1; i <= 600; i++) {
            double cur[3];
            sim_air_sample_S(a, p, 10.0 + i * 0.005, cur);
            for (int k = 0; k < 3; k++)
                jump = fmax(jump, fabs(cur[k] - prev[k]));
            memcpy(prev, cur, sizeof prev);
        }
        double bound = 0.0;
        for (int k = 0; k < 3; k++)
            bound = fmax(bound, fabs(vh[k] - fs[k]) * 0.005 / 3.0);
        printf("field blended in over 3 s: largest change per 200 Hz step %.4f m/s (bound %.4f)\n", jump, bound);
        CHECK(jump <= bound * (1.0 + 1e-9) + 1e-12);
    }
    sim_air_destroy(a);
}

/* Turbulence in the loop: in the field (k > 0 there) the flight with gusts
 * departs from the flight without; the same seed flies the same gusts bit
 * for bit, another seed others. */
static void test_turbulence(const hfm_aircraft *ac, const core_ship *ship, const cfd_field *fld)
{
    sim_flight *fl[4] = {NULL};
    const int turb[4] = {0, 1, 1, 1};
    const unsigned long long seed[4] = {1, 1, 1, 2};
    for (int i = 0; i < 4; i++) {
        sim_flight_opts o;
        sim_flight_opts_default(&o);
        o.wod_speed_mps = 10.0;
        o.turbulence = turb[i];
        o.seed = seed[i];
        core_err err = {{0}};
        fl[i] = sim_flight_create(ac, ship, &o, NULL, NULL, fld, NULL, &err);
        CHECK(fl[i] != NULL);
        if (!fl[i]) {
            fprintf(stderr, "turbulence flight: %s\n", err.msg);
            goto done;
        }
    }
    static run r[4];
    for (int i = 0; i < 4; i++)
        CHECK(fly(fl[i], 200, &r[i]) == 0);
    double d01 = 0.0, d13 = 0.0;
    for (int k = 0; k < 3; k++) {
        d01 = fmax(d01, fabs(r[0].out[199].euler_E_rad[k] - r[1].out[199].euler_E_rad[k]));
        d13 = fmax(d13, fabs(r[1].out[199].euler_E_rad[k] - r[3].out[199].euler_E_rad[k]));
    }
    printf("turbulence in the field: attitude %.2e rad from the mean-air flight after 1 s, %.2e between seeds\n", d01,
           d13);
    CHECK(d01 > 1e-5 && d13 > 1e-5);
    CHECK(memcmp(r[1].out, r[2].out, 200 * sizeof r[1].out[0]) == 0);
done:
    for (int i = 0; i < 4; i++)
        sim_flight_destroy(fl[i]);
}

/* A ship heaving and rolling at 2 rad/s (faster than any ship's). */
static int rolling_ship(void *user, double t_s, sim_ship_frame *fr)
{
    (void)user;
    memset(fr, 0, sizeof *fr);
    double phi = 0.1 * sin(2.0 * t_s);
    fr->origin_E_m[2] = 1.5 * sin(2.0 * t_s + 0.3);
    fr->C_ES[0] = 1.0;
    fr->C_ES[4] = cos(phi), fr->C_ES[5] = -sin(phi);
    fr->C_ES[7] = sin(phi), fr->C_ES[8] = cos(phi);
    return 0;
}

/* The ship frame between two loop steps is interpolated (sim_air_set_step):
 * the air at a point at a stage time agrees with the exact frame's to
 * the order (h w)^2 of the motion, and exactly at the step times. */
static void test_frame_interp(void)
{
    sim_air_opts o;
    sim_air_opts_default(&o);
    o.wod_speed_mps = 15.0;
    o.deck_height_m = 5.0;
    core_err err = {{0}};
    sim_air *ex = sim_air_create(&o, rolling_ship, NULL, &err), *in = sim_air_create(&o, rolling_ship, NULL, &err);
    CHECK(ex && in);
    if (!ex || !in) {
        sim_air_destroy(ex);
        sim_air_destroy(in);
        return;
    }
    sim_air_set_step(in, 0.005);
    double p[3] = {3.0, -2.0, -10.0}, worst = 0.0, at_step = 0.0;
    for (int i = 0; i < 1000; i++) {
        double t = 0.005 * i + 0.005 * 2.0 / 3.0, ve[3], vi[3];
        sim_air_fn(ex, p, t, ve);
        sim_air_fn(in, p, t, vi);
        for (int k = 0; k < 3; k++)
            worst = fmax(worst, fabs(ve[k] - vi[k]));
        sim_air_fn(ex, p, 0.005 * i, ve);
        sim_air_fn(in, p, 0.005 * i, vi);
        for (int k = 0; k < 3; k++)
            at_step = fmax(at_step, fabs(ve[k] - vi[k]));
    }
    /* the air changes with the frame through the log law's height and the
     * rotation: at most about |v| (h w)^2 = 15 x 1e-4 */
    printf("ship frame interpolated within a 200 Hz step (2 rad/s motion): air within %.2e m/s of the exact frame's, "
           "%.1e at the steps\n", worst, at_step);
    CHECK(worst < 15.0 * (0.005 * 2.0) * (0.005 * 2.0));
    CHECK(worst > 0.0 && at_step == 0.0);
    sim_air_destroy(ex);
    sim_air_destroy(in);
}

/* A small ship-only field of the ship: 2 m cells, a few iterations (the
 * air's tests need a field, not a converged one). NULL on failure. */
static cfd_field *small_field(const core_ship *ship, char *path, size_t n)
{
    cfd_airwake_spec sp;
    memset(&sp, 0, sizeof sp);
    sp.ship = ship;
    sp.wod_speed_mps = 10.0;
    sp.level = CORE_GRID_COARSE;
    sp.rotor = CORE_ROTOR_OFF;
    sp.monitor_z_m = -5.0;
    sp.max_iter = 3;
    sp.h_fine_m = 2.0;
    core_err err = {{0}};
    cfd_solver *s = cfd_airwake_create(&sp, NULL, NULL, NULL, &err);
    if (!s)
        return NULL;
    cfd_result res;
    cfd_meta meta;
    memset(&meta, 0, sizeof meta);
    meta.wod_speed_mps = 10.0;
    snprintf(meta.ship, sizeof meta.ship, "%s", ship->name);
    snprintf(meta.rotor, sizeof meta.rotor, "off");
    snprintf(meta.grid, sizeof meta.grid, "h2.000 m");
    snprintf(path, n, "/tmp/disim_test_flight_%ld.h5", (long)getpid());
    int rc = cfd_solver_run(s, &res, &err) < 0 || (meta.result = res, cfd_solver_write(s, &meta, path, &err));
    cfd_solver_destroy(s);
    if (rc) {
        fprintf(stderr, "small field: %s\n", err.msg);
        return NULL;
    }
    return cfd_field_load(path, &err);
}

int main(void)
{
    setvbuf(stdout, NULL, _IOLBF, 0);
    core_err err = {{0}};
    hfm_aircraft *ac = hfm_aircraft_load(UH60, NULL, &err);
    core_ship ship;
    int ok = ac && core_ship_load(SHIP, &ship, &err) == 0;
    CHECK(ok);
    if (!ok) {
        fprintf(stderr, "set-up: %s\n", err.msg);
        hfm_aircraft_destroy(ac);
        return check_done("test_flight");
    }
    test_frames(ac, &ship);
    test_external(ac, &ship);
    test_frame_interp();
    char fpath[128];
    cfd_field *fld = small_field(&ship, fpath, sizeof fpath);
    CHECK(fld != NULL);
    test_air(&ship, fld);
    if (fld)
        test_turbulence(ac, &ship, fld);
    cfd_field_destroy(fld);
    if (fld)
        unlink(fpath);
    hfm_aircraft_destroy(ac);
    return check_done("test_flight");
}
