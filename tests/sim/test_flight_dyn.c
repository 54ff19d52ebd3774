/* test_flight_dyn.c -- the flight loop's dynamics (issue 25, first
 * acceptance item): open loop, a hover perturbed by a cyclic step departs
 * as the linearised model (hfm_linearise) predicts over the first 2 s; the
 * stability augmentation (sim/sas.c) holds the attitudes within 2 deg of
 * trim for 60 s in calm air, and without it a disturbed hover departs; the
 * SAS's contribution never exceeds its authority; the [sas] section of the
 * aircraft files. Both shipped aircraft, hover 6 m above the spot in calm
 * air, 200 Hz. Run from the source root. */
#include "check.h"
#include "hfm.h"
#include "sim.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define UH60 "scenarios/aircraft/uh60a.ini"
#define SA365 "scenarios/aircraft/sa365n.ini"
#define LUH "tests/hfm/data/luh25.ini"
#define SHIP "scenarios/ships/sfs2.ini"
#define R2D CORE_RAD_TO_DEG
#define RATE_HZ 200.0
#define NX HFM_LIN_NX
#define NU HFM_LIN_NU

static const double station_S_m[3] = {0.0, 0.0, -6.0};

/* A hover at the station in calm air with no turbulence; sas as
 * sim_flight_opts (-1 the aircraft file's, 0 off, 1 on). */
static sim_flight *make(const hfm_aircraft *ac, const core_ship *ship, int sas, double wod_mps)
{
    sim_flight_opts o;
    sim_flight_opts_default(&o);
    o.rate_hz = RATE_HZ;
    o.turbulence = 0;
    o.sas = sas;
    o.wod_speed_mps = wod_mps;
    memcpy(o.station_S_m, station_S_m, sizeof o.station_S_m);
    core_err err = {{0}};
    sim_flight *f = sim_flight_create(ac, ship, &o, NULL, NULL, NULL, NULL, &err);
    if (!f)
        fprintf(stderr, "flight: %s\n", err.msg);
    return f;
}

/* The linear model's states from a flight output: u v w (body axes,
 * relative to the ship, here at rest) p q r phi theta psi. */
static void out_to_x(const sim_flight_out *o, double x[NX])
{
    core_euler e = {o->euler_E_rad[0], o->euler_E_rad[1], o->euler_E_rad[2]};
    core_mat3 C = core_mat3_from_euler(e); /* C_EB: v_E = C v_B */
    for (int i = 0; i < 3; i++) {
        x[i] = C.m[0][i] * o->vel_S_mps[0] + C.m[1][i] * o->vel_S_mps[1] + C.m[2][i] * o->vel_S_mps[2];
        x[3 + i] = o->rate_B_radps[i];
        x[6 + i] = o->euler_E_rad[i];
    }
}

static void lin_rhs(const hfm_linear *L, const double *x, const double *du, double *xd)
{
    for (int i = 0; i < NX; i++) {
        xd[i] = 0.0;
        for (int j = 0; j < NX; j++)
            xd[i] += L->A[i * NX + j] * x[j];
        for (int j = 0; j < NU; j++)
            xd[i] += L->B[i * NU + j] * du[j];
    }
}

/* x <- x + h f(x) by the classical Runge-Kutta method (du held). */
static void lin_rk4(const hfm_linear *L, double *x, const double *du, double h)
{
    double k1[NX], k2[NX], k3[NX], k4[NX], y[NX];
    lin_rhs(L, x, du, k1);
    for (int i = 0; i < NX; i++)
        y[i] = x[i] + 0.5 * h * k1[i];
    lin_rhs(L, y, du, k2);
    for (int i = 0; i < NX; i++)
        y[i] = x[i] + 0.5 * h * k2[i];
    lin_rhs(L, y, du, k3);
    for (int i = 0; i < NX; i++)
        y[i] = x[i] + h * k3[i];
    lin_rhs(L, y, du, k4);
    for (int i = 0; i < NX; i++)
        x[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
}

#define T_LIN_S 2.0
#define N_LIN ((int)(T_LIN_S * RATE_HZ + 0.5))

/* 1. Open loop: a step of 2 % of travel on control j (1 longitudinal, 2
 * lateral) from the hover trim, flown by the flight loop (SAS off) and by
 * the linear model x' = A x + B du of hfm_linearise at the same trim, in
 * the same air, over T_LIN_S. The measure: the stepped axis's attitude
 * (theta for the longitudinal step, phi for the lateral), the largest
 * difference between the two histories over the 2 s over the largest
 * magnitude of the linear response, within 5 %. The other states are
 * printed, not checked: the rates differ by up to about 30 % in the first
 * tenths of a second, where the flight loop's rotor flaps and its inflow
 * lags (they are states of its model, quasi-steady in the linear one).
 * The hover is in a light head wind (LIN_WOD_MPS): at zero airspeed the
 * wake's direction on the airframe is undefined, and the linearisation's
 * velocity derivatives (central differences of 0.05 m/s about zero) are
 * not those the flight meets (in calm air the lateral step's phi differs
 * by 17 %). */
#define LIN_WOD_MPS 3.0
static int level_ship(void *user, double t_s, sim_ship_frame *fr)
{
    (void)user, (void)t_s;
    memset(fr, 0, sizeof *fr);
    fr->C_ES[0] = fr->C_ES[4] = fr->C_ES[8] = 1.0;
    return 0;
}

static void test_linear(const hfm_aircraft *ac, const core_ship *ship, const char *name)
{
    hfm_trim *tr = hfm_trim_create(ac, NULL);
    CHECK(tr != NULL);
    if (!tr)
        return;
    hfm_trim_cond c;
    memset(&c, 0, sizeof c);
    c.kind = HFM_TRIM_HOVER_SHIP;
    memcpy(c.pos_S_m, station_S_m, sizeof c.pos_S_m);
    c.wod_speed_mps = LIN_WOD_MPS;
    /* the air of the flight (sim/flight.c): the free stream over the sea */
    sim_air_opts ao;
    sim_air_opts_default(&ao);
    ao.wod_speed_mps = LIN_WOD_MPS;
    ao.deck_height_m = ship->deck_height_m;
    ao.anemometer_height_m = fmax(ship->deck_height_m - ship->anemometer_S_m[2], 2.0);
    core_err aerr = {{0}};
    sim_air *sa = sim_air_create(&ao, level_ship, NULL, &aerr);
    CHECK(sa != NULL);
    if (!sa) {
        hfm_trim_destroy(tr);
        return;
    }
    hfm_air ha = {sim_air_fn, sa, NULL};
    c.air = &ha;
    hfm_trim_result r;
    hfm_linear L;
    int ok = hfm_trim_solve(tr, &c, NULL, &r) == 0 && hfm_linearise(tr, &c, &r, &L) == 0;
    CHECK(ok);
    hfm_trim_destroy(tr);
    sim_air_destroy(sa);
    if (!ok)
        return;
    printf("%s hover derivatives (per s, per %% of travel): L_p %.3f L_lat %.4f; M_q %.3f M_long %.4f; "
           "N_r %.3f N_ped %.4f\n",
           name, L.A[3 * NX + 3], L.B[3 * NU + 2], L.A[4 * NX + 4], L.B[4 * NU + 1], L.A[5 * NX + 5],
           L.B[5 * NU + 3]);
    static const char *const sn[NX] = {"u", "v", "w", "p", "q", "r", "phi", "theta", "psi"};
    for (int j = 1; j <= 2; j++) {
        sim_flight *f = make(ac, ship, 0, LIN_WOD_MPS);
        CHECK(f != NULL);
        if (!f)
            return;
        sim_flight_inputs in;
        sim_flight_trim_inputs(f, &in);
        /* the flight starts from the trim the linear model is taken at */
        CHECK_NEAR(in.long_pct, r.u.long_pct, 1e-6);
        CHECK_NEAR(in.lat_pct, r.u.lat_pct, 1e-6);
        CHECK_NEAR(in.collective_pct, r.u.collective_pct, 1e-6);
        CHECK_NEAR(in.pedal_pct, r.u.pedal_pct, 1e-6);
        double du[NU] = {0.0, 0.0, 0.0, 0.0};
        du[j] = 2.0;
        *(j == 1 ? &in.long_pct : &in.lat_pct) += 2.0;
        double x0[NX], xl[NX] = {0.0}, xn[NX];
        sim_flight_out o;
        sim_flight_state(f, &o);
        out_to_x(&o, x0);
        double err[NX] = {0.0}, mag[NX] = {0.0};
        core_err e = {{0}};
        for (int s = 0; s < N_LIN; s++) {
            if (sim_flight_step(f, &in, &o, &e) != 0) {
                fprintf(stderr, "step %d: %s\n", s, e.msg);
                CHECK(0);
                break;
            }
            lin_rk4(&L, xl, du, 1.0 / RATE_HZ);
            out_to_x(&o, xn);
            for (int i = 0; i < NX; i++) {
                err[i] = fmax(err[i], fabs(xn[i] - x0[i] - xl[i]));
                mag[i] = fmax(mag[i], fabs(xl[i]));
            }
        }
        sim_flight_destroy(f);
        /* the measure: the stepped axis's attitude */
        const int chk[1] = {j == 1 ? 7 : 6};
        printf("%s, +2 %% %s cyclic, %.0f s open loop, flight loop against the linear model "
               "(largest difference / largest linear response):",
               name, j == 1 ? "longitudinal" : "lateral", T_LIN_S);
        for (int i = 0; i < NX; i++)
            printf(" %s %.1f%%", sn[i], mag[i] > 0.0 ? 100.0 * err[i] / mag[i] : 0.0);
        printf("\n");
        for (int k = 0; k < 1; k++) {
            int i = chk[k];
            printf("  %s: linear response up to %.4g, difference %.4g (%.2f %%)\n", sn[i], mag[i], err[i],
                   100.0 * err[i] / mag[i]);
            CHECK(mag[i] > 0.0 && err[i] <= 0.05 * mag[i]);
        }
    }
}

/* ------------------------------------------------ 2. the attitude hold */
/* A disturbance: a roll and a pitch moment (and a yaw moment) from t0 for
 * dt, each giving an angular acceleration acc_radps2 about its axis. */
typedef struct pulse {
    double t0_s, dt_s, M_B_Nm[3];
} pulse;

static int pulse_fn(void *user, double t_s, const hfm_body *b, double F_B_N[3], double M_B_Nm[3])
{
    (void)b;
    const pulse *p = user;
    int on = t_s >= p->t0_s && t_s < p->t0_s + p->dt_s;
    for (int i = 0; i < 3; i++) {
        F_B_N[i] = 0.0;
        M_B_Nm[i] = on ? p->M_B_Nm[i] : 0.0;
    }
    return 0;
}

/* Fly T_s holding the trim's controls, with an optional disturbance: the
 * largest roll and pitch attitude change from trim (deg), stopped early
 * once one exceeds stop_deg; the largest SAS contribution against its
 * authority (ratio) and whether it saturated. */
typedef struct hold_run {
    double max_att_deg[3]; /* roll, pitch, heading */
    double t_end_s;
    double max_ratio[3];
    int saturated;
    int failed;
} hold_run;

static void fly_hold(sim_flight *f, const pulse *dist, double T_s, double stop_deg, hold_run *h)
{
    memset(h, 0, sizeof *h);
    if (dist)
        sim_flight_set_external(f, pulse_fn, (void *)dist);
    sim_flight_inputs in;
    sim_flight_trim_inputs(f, &in);
    sim_flight_out o0, o;
    sim_flight_state(f, &o0);
    hfm_sas_gains g;
    sim_sas *sas = sim_flight_sas(f);
    sim_sas_gains(sas, &g);
    core_err e = {{0}};
    long n = (long)(T_s * RATE_HZ + 0.5);
    for (long s = 0; s < n; s++) {
        if (sim_flight_step(f, &in, &o, &e) != 0) {
            h->failed = 1;
            break;
        }
        sim_sas_out so;
        sim_sas_last(sas, &so);
        for (int i = 0; i < 3; i++) {
            double d = o.euler_E_rad[i] - o0.euler_E_rad[i];
            if (i == 2)
                d = atan2(sin(d), cos(d));
            h->max_att_deg[i] = fmax(h->max_att_deg[i], fabs(d) * R2D);
            if (g.authority_pct[i] > 0.0)
                h->max_ratio[i] = fmax(h->max_ratio[i], fabs(so.delta_pct[i]) / g.authority_pct[i]);
            h->saturated |= so.saturated[i];
        }
        h->t_end_s = o.t_s;
        if (h->max_att_deg[0] > stop_deg || h->max_att_deg[1] > stop_deg)
            break;
    }
}

/* strict: the disturbed hover too within 2 deg (the UH-60A, whose SAS
 * authority is sourced); otherwise only much nearer trim than without the
 * SAS (the SA365N's estimated gains hold a proportional attitude error of
 * about 4 deg in roll and 5 deg in heading after this pulse: the hold has
 * no integral term). */
static void test_hold(const hfm_aircraft *ac, const core_ship *ship, const char *name, const double I_kgm2[3],
                      int strict)
{
    /* 0.035 rad/s^2 about each axis for half a second: 1 deg/s of roll,
     * pitch and yaw rate, were the aircraft without damping */
    pulse p = {1.0, 0.5, {0.035 * I_kgm2[0], 0.035 * I_kgm2[1], 0.035 * I_kgm2[2]}};
    hfm_sas_gains g;
    if (hfm_aircraft_sas(ac, &g) != 0) {
        CHECK(0);
        return;
    }
    CHECK(g.engaged == 1);
    hold_run calm, on, off;
    sim_flight *f = make(ac, ship, -1, 0.0); /* the file's default: on */
    CHECK(f && sim_sas_engaged(sim_flight_sas(f)));
    if (!f)
        return;
    fly_hold(f, NULL, 60.0, 90.0, &calm);
    sim_flight_destroy(f);
    f = make(ac, ship, 1, 0.0);
    if (!f) {
        CHECK(0);
        return;
    }
    fly_hold(f, &p, 60.0, 90.0, &on);
    sim_flight_destroy(f);
    f = make(ac, ship, 0, 0.0);
    if (!f) {
        CHECK(0);
        return;
    }
    CHECK(!sim_sas_engaged(sim_flight_sas(f)));
    fly_hold(f, &p, 60.0, 20.0, &off);
    sim_flight_destroy(f);
    printf("%s, SAS on, no input, calm air, 60 s: largest attitude change roll %.3f, pitch %.3f, heading %.3f deg\n",
           name, calm.max_att_deg[0], calm.max_att_deg[1], calm.max_att_deg[2]);
    printf("%s, a half-second moment pulse at 1 s: SAS on, 60 s: roll %.3f, pitch %.3f, heading %.3f deg; "
           "SAS off: roll %.2f, pitch %.2f deg by %.1f s%s\n",
           name, on.max_att_deg[0], on.max_att_deg[1], on.max_att_deg[2], off.max_att_deg[0], off.max_att_deg[1],
           off.t_end_s, off.failed ? " (the integrator failed)" : "");
    CHECK(!calm.failed && calm.t_end_s > 59.99);
    CHECK(!on.failed && on.t_end_s > 59.99);
    for (int i = 0; i < 3; i++) {
        CHECK(calm.max_att_deg[i] < 2.0);
        if (strict)
            CHECK(on.max_att_deg[i] < 2.0);
    }
    /* without the SAS the same disturbance takes the hover far from trim */
    double moff = fmax(off.max_att_deg[0], off.max_att_deg[1]), mon = fmax(on.max_att_deg[0], on.max_att_deg[1]);
    CHECK(moff > 5.0 && moff > 4.0 * mon);
}

/* 3. The authority: a disturbance the SAS cannot hold within its
 * authority saturates it, and its contribution never exceeds the limit;
 * the controller alone gives -(K_rate w + K_att e) below the limit and the
 * limit above it, and nothing disengaged. */
static void test_authority(const hfm_aircraft *ac, const core_ship *ship, const char *name, const double I_kgm2[3])
{
    pulse big = {0.5, 1.0, {3.0 * I_kgm2[0], 1.2 * I_kgm2[1], 0.8 * I_kgm2[2]}};
    sim_flight *f = make(ac, ship, 1, 0.0);
    CHECK(f != NULL);
    if (!f)
        return;
    hold_run h;
    fly_hold(f, &big, 6.0, 60.0, &h);
    sim_flight_destroy(f);
    printf("%s, a large moment pulse, SAS on: largest contribution / authority: roll %.6f, pitch %.6f, yaw %.6f "
           "(saturated: %s)\n",
           name, h.max_ratio[0], h.max_ratio[1], h.max_ratio[2], h.saturated ? "yes" : "no");
    CHECK(h.saturated);
    for (int i = 0; i < 3; i++)
        CHECK(h.max_ratio[i] <= 1.0 + 1e-12);
    CHECK(h.max_ratio[0] > 0.999 || h.max_ratio[1] > 0.999 || h.max_ratio[2] > 0.999);

    hfm_sas_gains g;
    hfm_aircraft_sas(ac, &g);
    core_err err = {{0}};
    sim_sas *s = sim_sas_create(&g, &err);
    CHECK(s != NULL);
    if (!s)
        return;
    hfm_body b;
    memset(&b, 0, sizeof b);
    hfm_controls pilot = {50.0, 50.0, 50.0, 50.0}, rot;
    sim_sas_step(s, &b, &pilot, &rot); /* takes the references: level, heading 0 */
    sim_sas_out so;
    for (int i = 0; i < 3; i++) {
        /* a small rate and attitude error: the linear law */
        memset(&b, 0, sizeof b);
        b.rate_B_radps[i] = 0.01;
        b.euler_rad[i] = 0.005;
        sim_sas_step(s, &b, &pilot, &rot);
        sim_sas_last(s, &so);
        double want = -(g.rate_pct_per_radps[i] * 0.01 + g.att_pct_per_rad[i] * 0.005);
        CHECK(fabs(want) < g.authority_pct[i]);
        CHECK_NEAR(so.delta_pct[i], want, 1e-12);
        double *c = i == 0 ? &rot.lat_pct : i == 1 ? &rot.long_pct : &rot.pedal_pct;
        CHECK_NEAR(*c, 50.0 + want, 1e-12);
        /* a large one: the limit, with the sign that opposes */
        b.rate_B_radps[i] = -3.0 * g.authority_pct[i] / g.rate_pct_per_radps[i];
        sim_sas_step(s, &b, &pilot, &rot);
        sim_sas_last(s, &so);
        CHECK_NEAR(so.delta_pct[i], g.authority_pct[i], 1e-12);
        CHECK(so.saturated[i]);
    }
    /* the pilot moves the lateral stick past the detent: the roll hold
     * takes the attitude of that moment as its reference */
    memset(&b, 0, sizeof b);
    b.euler_rad[0] = 0.1;
    hfm_controls moved = pilot;
    moved.lat_pct += g.detent_pct + 0.5;
    sim_sas_step(s, &b, &moved, &rot);
    sim_sas_last(s, &so);
    CHECK_NEAR(so.att_err_rad[0], 0.0, 1e-15);
    CHECK_NEAR(so.att_err_rad[1], 0.0, 1e-15);
    /* disengaged: the pilot's controls reach the rotor unchanged */
    sim_sas_set_engaged(s, 0);
    b.rate_B_radps[1] = 1.0;
    sim_sas_step(s, &b, &pilot, &rot);
    CHECK(memcmp(&rot, &pilot, sizeof rot) == 0);
    sim_sas_destroy(s);
}

/* The [sas] section: optional (an aircraft without it flies bare, and
 * asking for the SAS is refused), each of its keys required once it is
 * there. */
static void test_format(const core_ship *ship)
{
    core_err err = {{0}};
    hfm_aircraft *luh = hfm_aircraft_load(LUH, NULL, &err);
    CHECK(luh != NULL);
    if (luh) {
        hfm_sas_gains g;
        CHECK(hfm_aircraft_sas(luh, &g) == 1 && g.engaged == 0);
        sim_flight *f = make(luh, ship, -1, 0.0);
        CHECK(f && !sim_sas_engaged(sim_flight_sas(f)));
        sim_flight_destroy(f);
        sim_flight_opts o;
        sim_flight_opts_default(&o);
        o.sas = 1;
        f = sim_flight_create(luh, ship, &o, NULL, NULL, NULL, NULL, &err);
        CHECK(f == NULL && strstr(err.msg, "has none") != NULL);
        sim_flight_destroy(f);
        hfm_aircraft_destroy(luh);
    }
    char path[128];
    snprintf(path, sizeof path, "/tmp/disim_test_flight_dyn_%ld.ini", (long)getpid());
    FILE *in = fopen(UH60, "r"), *out = fopen(path, "w");
    CHECK(in && out);
    if (in && out) {
        char line[1024];
        while (fgets(line, sizeof line, in))
            if (strncmp(line, "pitch_authority_pct", 19) != 0)
                fputs(line, out);
    }
    if (in)
        fclose(in);
    if (out)
        fclose(out);
    hfm_aircraft *ac = hfm_aircraft_load(path, NULL, &err);
    printf("[sas] without pitch_authority_pct: %s\n", ac ? "loaded" : err.msg);
    CHECK(ac == NULL && strstr(err.msg, "[sas]") && strstr(err.msg, "pitch_authority_pct"));
    hfm_aircraft_destroy(ac);
    unlink(path);
}

int main(void)
{
    setvbuf(stdout, NULL, _IOLBF, 0);
    core_err err = {{0}};
    core_ship ship;
    if (core_ship_load(SHIP, &ship, &err) != 0) {
        fprintf(stderr, "set-up: %s\n", err.msg);
        CHECK(0);
        return check_done("test_flight_dyn");
    }
    const char *files[2] = {UH60, SA365};
    for (int k = 0; k < 2; k++) {
        hfm_aircraft *ac = hfm_aircraft_load(files[k], NULL, &err);
        CHECK(ac != NULL);
        if (!ac) {
            fprintf(stderr, "set-up: %s\n", err.msg);
            continue;
        }
        const char *name = hfm_aircraft_name(ac);
        /* the moments of inertia, to size the disturbances */
        double I[3] = {0.0, 0.0, 0.0};
        core_ini *ini = core_ini_load(files[k], &err);
        CHECK(ini && core_ini_get_double(ini, "aircraft", "Ixx_kgm2", 1, 1.0, 1e7, &I[0], &err) == 0 &&
              core_ini_get_double(ini, "aircraft", "Iyy_kgm2", 1, 1.0, 1e7, &I[1], &err) == 0 &&
              core_ini_get_double(ini, "aircraft", "Izz_kgm2", 1, 1.0, 1e7, &I[2], &err) == 0);
        core_ini_destroy(ini);
        test_linear(ac, &ship, name);
        test_hold(ac, &ship, name, I, k == 0);
        test_authority(ac, &ship, name, I);
        hfm_aircraft_destroy(ac);
    }
    test_format(&ship);
    return check_done("test_flight_dyn");
}
