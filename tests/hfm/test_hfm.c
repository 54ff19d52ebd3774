/* test_hfm.c -- hfm acceptance tests (run from the source root):
 * aircraft files and bad input, UH-60A trim against the GenHel table
 * (uh60a_genhel_trim.csv beside this file, each row under the constraint
 * the reference flew), the hover thrust balance (a consistency check) and
 * figure of merit (plausibility), the power bucket, SA365N hover, a 0-150 kt
 * continuation sweep, turning-point handling on a curve with folds, pedal in
 * a WOD, WOD-speed sweeps over the ship, and the continuity of the
 * 0-160 kt trims through the main-rotor wake's sweep over the airframe,
 * the engine power against published power (uh60a_power.csv), and the
 * Bo105, written from published data alone, against its flight test
 * (bo105_trim.csv). */
#include "check.h"
#include "hfm.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define UH60 "scenarios/aircraft/uh60a.ini"
#define SA365 "scenarios/aircraft/sa365n.ini"
#define KT CORE_KT_TO_MPS

static char tmpdir[256];

/* ------------------------------------------------------------ bad input */
/* Write a copy of src with the line starting with `key` replaced by repl
 * (NULL: removed); returns the path. */
static const char *variant(const char *src, const char *section, const char *key,
                           const char *repl, const char *name)
{
    static char path[512];
    snprintf(path, sizeof path, "%s/%s", tmpdir, name);
    FILE *in = fopen(src, "r"), *out = fopen(path, "w");
    if (!in || !out) {
        if (in)
            fclose(in);
        if (out)
            fclose(out);
        return NULL;
    }
    char line[1024], sec[128] = "";
    size_t kl = strlen(key);
    while (fgets(line, sizeof line, in)) {
        if (line[0] == '[')
            sscanf(line, "[%127[^]]", sec);
        if (!strcmp(sec, section) && !strncmp(line, key, kl) &&
            (line[kl] == ' ' || line[kl] == '=')) {
            if (repl)
                fprintf(out, "%s\n", repl);
            continue;
        }
        fputs(line, out);
    }
    fclose(in);
    fclose(out);
    return path;
}

static void expect_error(const char *path, const char *needle)
{
    core_err err = {0};
    hfm_aircraft *ac = path ? hfm_aircraft_load(path, NULL, &err) : NULL;
    CHECK(path && ac == NULL);
    CHECK(strstr(err.msg, needle) != NULL);
    if (!strstr(err.msg, needle))
        fprintf(stderr, "  expected '%s' in: %s\n", needle, err.msg);
    hfm_aircraft_destroy(ac);
}

static void test_bad_input(void)
{
    expect_error(variant(UH60, "main_rotor", "radius_m", NULL, "a.ini"), "radius_m");
    expect_error(variant(UH60, "main_rotor", "chord_m", "chord_m = -0.5", "b.ini"), "chord_m");
    expect_error(variant(UH60, "aircraft", "mass_kg", "mass_kg = 0", "c.ini"), "mass_kg");
    expect_error(variant(UH60, "tail_rotor", "omega_radps", NULL, "d.ini"), "omega_radps");
    expect_error(variant(UH60, "main_rotor", "segments", "segments = 4", "e.ini"), "segments");
    expect_error(variant(UH60, "fuselage", "drag_m2", "drag_m2 = 1,2,3", "f.ini"), "drag_m2");
    expect_error(variant(UH60, "fin", "area_m2", "area_m2 = abc", "g.ini"), "area_m2");
    expect_error(variant(UH60, "controls", "swash_phase_deg",
                         "swash_phase_deg = 0\nrotor_speed = 3", "h.ini"),
                 "rotor_speed");
    expect_error(variant(UH60, "aircraft", "Ixz_kgm2", "Ixz_kgm2 = 30000", "i.ini"), "Ixz_kgm2");
    expect_error(variant(SA365, "tail_rotor", "fan_thrust_fraction", NULL, "j.ini"),
                 "fan_thrust_fraction");
    expect_error(variant(UH60, "fuselage", "side_force_m2", NULL, "k.ini"), "side_force_m2");
    expect_error(variant(UH60, "fuselage", "side_force_m2", "side_force_m2 = -1", "l.ini"),
                 "side_force_m2");
    /* the optional wake planform: stations fore to aft, one width or one
     * per station */
    expect_error(variant(UH60, "fuselage", "planform_x_B_m",
                         "planform_x_B_m = 5.3, 4.07, -3.17, -2.02, -8.6", "p.ini"),
                 "station 4 (-2.02 m) is ahead of station 3 (-3.17 m)");
    expect_error(variant(UH60, "fuselage", "planform_x_B_m", "planform_x_B_m = 5.3", "q.ini"),
                 "expected 2 to 12 stations");
    expect_error(variant(UH60, "fuselage", "planform_width_m", "planform_width_m = 2.36, 1.0", "s.ini"),
                 "expected 1 width or one per planform_x_B_m station (5), got 2");
    /* the wake factors the wake's path replaced are refused by name */
    expect_error(variant(UH60, "main_rotor", "segments", "segments = 10\nwake_factor_tail = 1.5", "t.ini"),
                 "wake_factor_tail: no longer a key");
    expect_error(variant(UH60, "fuselage", "planform_width_m", "planform_width_m = -1", "r.ini"),
                 "planform_width_m");
    /* mass properties no body has: Izz above Ixx + Iyy (a typo), a blade
     * whose first moment needs more mass than it has */
    expect_error(variant(UH60, "aircraft", "Izz_kgm2", "Izz_kgm2 = 70000", "m.ini"),
                 "principal moments 70082, 54233, 7550 kg m^2 break the triangle inequality (70082 > 54233 + 7550");
    expect_error(variant(UH60, "main_rotor", "blade_first_moment_kgm", "blade_first_moment_kgm = 600", "n.ini"),
                 "first moment^2 > mass x flap inertia");
    expect_error(variant(UH60, "main_rotor", "blade_flap_inertia_kgm2", "blade_flap_inertia_kgm2 = 9000", "o.ini"),
                 "flap inertia > mass x (radius - hinge offset)^2");
    expect_error("scenarios/aircraft/no_such_aircraft.ini", "no_such_aircraft");
}

/* --------------------------------------------------------- GenHel trim */
static double pct_coll(double in)
{
    return in / 10.0 * 100.0;
}
static double pct_long(double in_fwd)
{
    return 50.0 - in_fwd / 10.0 * 100.0;
}
static double pct_lat(double in_right)
{
    return 50.0 + in_right / 10.0 * 100.0;
}
static double pct_ped(double in_right)
{
    return 50.0 + in_right / 5.38 * 100.0;
}

/* Each row is trimmed under the constraint the reference flew (the CSV's
 * constraint column and its comment say why): "sideslip" rows hold zero
 * sideslip and leave roll free, so roll is compared with the published
 * roll; "roll" rows are wings level, so roll is the constraint (checked only
 * as a consistency check that the row was flown so) and the sideslip is
 * what the trim leaves free. The references publish no sideslip, so on
 * wings-level rows it is held to a physical band rather than compared: in
 * wings-level flight gravity has no lateral component and the tail rotor's
 * starboard thrust (4-5 kN) is carried partly by the airframe's side force,
 * which needs the relative wind from starboard (sideslip > 0), and the
 * band's upper end keeps it where the fin (aspect ratio 1.92) is far from
 * stall and GenHel's sideslip tables are dense (0-30 deg). */
#define GENHEL_TOL_CONTROL_PCT 8.0   /* each control, % of full travel */
#define GENHEL_TOL_ATTITUDE_DEG 1.5  /* pitch; roll where roll is free */
#define GENHEL_SIDESLIP_MIN_DEG 0.5  /* wings-level rows: sideslip band */
#define GENHEL_SIDESLIP_MAX_DEG 10.0

static int genhel_cmp(double v, const char *what, double model, double ref, double tol)
{
    int ok = fabs(model - ref) <= tol;
    printf("GenHel %5.0f kt %-14s model %7.2f GenHel %7.2f diff %+6.2f tol %.1f %s\n", v, what,
           model, ref, model - ref, tol, ok ? "holds" : "FAILS");
    return ok;
}

static void test_genhel(hfm_trim *tr)
{
    FILE *f = fopen("tests/hfm/uh60a_genhel_trim.csv", "r");
    CHECK(f != NULL);
    if (!f)
        return;
    char line[512];
    int rows = 0, level_rows = 0;
    while (fgets(line, sizeof line, f)) {
        double v, c, lo, la, pe, th, ph;
        char con[16];
        if (line[0] == '#' || sscanf(line, "%lf,%lf,%lf,%lf,%lf,%lf,%lf,%15s", &v, &c, &lo, &la,
                                     &pe, &th, &ph, con) != 8)
            continue;
        int level = !strcmp(con, "roll");
        CHECK(level || !strcmp(con, "sideslip"));
        rows++;
        level_rows += level;
        hfm_trim_cond cd;
        memset(&cd, 0, sizeof cd);
        cd.kind = HFM_TRIM_FORWARD;
        cd.constraint = level ? HFM_CONSTRAINT_ROLL : HFM_CONSTRAINT_SIDESLIP;
        cd.airspeed_mps = v * KT;
        hfm_trim_result r;
        int rc = hfm_trim_solve(tr, &cd, NULL, &r);
        CHECK(rc == 0);
        CHECK(r.converged);
        const double tc = GENHEL_TOL_CONTROL_PCT, ta = GENHEL_TOL_ATTITUDE_DEG;
        CHECK(genhel_cmp(v, "collective %", r.u.collective_pct, pct_coll(c), tc));
        CHECK(genhel_cmp(v, "longitudinal %", r.u.long_cyclic_pct, pct_long(lo), tc));
        CHECK(genhel_cmp(v, "lateral %", r.u.lat_cyclic_pct, pct_lat(la), tc));
        CHECK(genhel_cmp(v, "pedal %", r.u.pedal_pct, pct_ped(pe), tc));
        CHECK(genhel_cmp(v, "pitch deg", r.body.euler_rad[1] * CORE_RAD_TO_DEG, th, ta));
        double beta_deg = r.sideslip_rad * CORE_RAD_TO_DEG, phi_deg = r.body.euler_rad[0] * CORE_RAD_TO_DEG;
        /* consistency: the row was flown under its constraint */
        CHECK(r.wings_level == level);
        if (level) {
            CHECK(fabs(phi_deg) < 1e-9);
            int ok = beta_deg >= GENHEL_SIDESLIP_MIN_DEG && beta_deg <= GENHEL_SIDESLIP_MAX_DEG;
            printf("GenHel %5.0f kt %-14s model %7.2f (wings level, roll %.2f; no published "
                   "sideslip) band %.1f..%.1f %s\n",
                   v, "sideslip deg", beta_deg, phi_deg, GENHEL_SIDESLIP_MIN_DEG,
                   GENHEL_SIDESLIP_MAX_DEG, ok ? "holds" : "FAILS");
            CHECK(ok);
        } else {
            CHECK(fabs(beta_deg) < 1e-9);
            CHECK(genhel_cmp(v, "roll deg", phi_deg, ph, ta));
        }
    }
    fclose(f);
    CHECK(rows == 3);
    CHECK(level_rows == 2);
}

/* ---------------------------------------------------------------- hover */
static double vertical_S(const hfm_body *b, const double F_B[3])
{
    core_euler e = {b->euler_rad[0], b->euler_rad[1], b->euler_rad[2]};
    core_mat3 m = core_mat3_from_euler(e);
    core_vec3 v = core_mat3_mul_vec(m, core_vec3_make(F_B[0], F_B[1], F_B[2]));
    return v.z; /* down positive */
}

/* Hover: no validation here, since the references publish neither hover
 * power nor figure of merit for the UH-60A (GenHel's hover row is checked in
 * test_genhel).
 * - Consistency check: thrust along the shaft against weight + fuselage
 *   download + the other components' vertical loads. This is the trim's own
 *   vertical-force equation, evaluated again from the loads it returns; it
 *   shows that the loads the trim reports are the ones it balanced, not that
 *   the model is right.
 * - Plausibility: the figure of merit T^1.5 / sqrt(2 rho A) / P_MR inside the
 *   range of full-scale rotors, 0.6-0.8 (Leishman, "Principles of Helicopter
 *   Aerodynamics", 2nd ed., sec. 2.8), and a fuselage download above 1 % of
 *   the weight (the rotor's wake is on the airframe). */
static void test_hover(const hfm_aircraft *ac, hfm_trim *tr)
{
    hfm_trim_cond cd;
    memset(&cd, 0, sizeof cd);
    cd.kind = HFM_TRIM_HOVER_SHIP;
    hfm_trim_result r;
    CHECK(hfm_trim_solve(tr, &cd, NULL, &r) == 0);
    CHECK(r.converged);
    const hfm_loads *L = &r.loads;
    double W = hfm_aircraft_weight_N(ac);
    double Dfus = vertical_S(&r.body, L->fus.F_B_N);
    double others = vertical_S(&r.body, L->tr.F_B_N) + vertical_S(&r.body, L->stab.F_B_N) +
                    vertical_S(&r.body, L->fin.F_B_N);
    /* tail-rotor cant lift is up: negative */
    double need = W + Dfus + others;
    printf("hover (consistency, the trim's own equation): T %.0f N, W %.0f N, fuselage download "
           "%.0f N, tail rotor+tail %.0f N, T/(W+D+others) - 1 = %.5f (tol 0.005), "
           "T/(W+Dfus) - 1 = %.5f; rotor vertical force %.0f N\n",
           L->mr_thrust_N, W, Dfus, others, L->mr_thrust_N / need - 1.0,
           L->mr_thrust_N / (W + Dfus) - 1.0, -vertical_S(&r.body, L->mr.F_B_N));
    CHECK(Dfus > 0.01 * W);
    CHECK_NEAR(L->mr_thrust_N / need, 1.0, 0.005);
    double A = CORE_PI * pow(hfm_aircraft_rotor_radius_m(ac), 2);
    double fm = pow(L->mr_thrust_N, 1.5) / sqrt(2.0 * CORE_RHO_SL_KGPM3 * A) / L->mr_power_W;
    printf("hover (plausibility, no published value): main rotor power %.0f kW, figure of merit "
           "%.3f (band 0.6-0.8)\n",
           L->mr_power_W / 1e3, fm);
    CHECK(fm > 0.6 && fm < 0.8);
}

/* hfm_air.wake: the wake's geometry on the airframe from another air. With
 * the same air it changes nothing; in a 10 m/s head wind with the wake
 * set by still air the wake is not blown aft, so the stabilator, 1.05 R
 * behind the hub, stays inside it and its download (hence the trim pitch)
 * differs; the rotor itself sees the same wind either way. */
static void test_wake_air(hfm_trim *tr)
{
    hfm_air_uniform head = {{-10.0, 0.0, 0.0}}, still = {{0.0, 0.0, 0.0}};
    hfm_air wake_head = {hfm_air_uniform_fn, &head, NULL}, wake_still = {hfm_air_uniform_fn, &still, NULL};
    hfm_air plain = {hfm_air_uniform_fn, &head, NULL}, same = {hfm_air_uniform_fn, &head, &wake_head},
            other = {hfm_air_uniform_fn, &head, &wake_still};
    hfm_trim_cond cd;
    memset(&cd, 0, sizeof cd);
    cd.kind = HFM_TRIM_HOVER_SHIP;
    hfm_trim_result r0, r1, r2;
    cd.air = &plain;
    CHECK(hfm_trim_solve(tr, &cd, NULL, &r0) == 0);
    cd.air = &same;
    CHECK(hfm_trim_solve(tr, &cd, NULL, &r1) == 0);
    cd.air = &other;
    CHECK(hfm_trim_solve(tr, &cd, NULL, &r2) == 0);
    printf("wake air: pitch %.3f deg (wake in the wind), %.3f (the same, given), %.3f (wake in still air); "
           "stabilator lift %.0f / %.0f / %.0f N\n",
           r0.body.euler_rad[1] * CORE_RAD_TO_DEG, r1.body.euler_rad[1] * CORE_RAD_TO_DEG,
           r2.body.euler_rad[1] * CORE_RAD_TO_DEG, -r0.loads.stab.F_B_N[2], -r1.loads.stab.F_B_N[2],
           -r2.loads.stab.F_B_N[2]);
    CHECK_NEAR(r1.body.euler_rad[1], r0.body.euler_rad[1], 1e-9);
    CHECK_NEAR(r1.u.collective_pct, r0.u.collective_pct, 1e-9);
    CHECK(fabs(r2.body.euler_rad[1] - r0.body.euler_rad[1]) > 0.2 * CORE_DEG_TO_RAD);
    CHECK(fabs(r2.loads.stab.F_B_N[2] - r0.loads.stab.F_B_N[2]) > 100.0);
}

/* ------------------------------------------------- sweep and the bucket */
static void test_sweep(hfm_trim *tr)
{
    double v[16];
    for (int i = 0; i < 16; i++)
        v[i] = 10.0 * i * KT;
    hfm_trim_result res[16];
    hfm_trim_cond cd;
    memset(&cd, 0, sizeof cd);
    cd.kind = HFM_TRIM_FORWARD;
    int rc = hfm_trim_sweep(tr, &cd, HFM_PARAM_AIRSPEED, v, 16, res);
    CHECK(rc == 0);
    int imin = 0, fails = 0;
    double p[16];
    for (int i = 0; i < 16; i++) {
        p[i] = res[i].loads.mr_power_W + res[i].loads.tr_power_W;
        fails += !res[i].converged;
        if (p[i] < p[imin])
            imin = i;
    }
    printf("sweep 0-150 kt: %d failed points; power minimum %.0f kW at %.0f kt (hover %.0f, "
           "150 kt %.0f kW)\n",
           fails, p[imin] / 1e3, res[imin].speed_kt, p[0] / 1e3, p[15] / 1e3);
    CHECK(fails == 0);
    CHECK(res[imin].speed_kt >= 50.0 && res[imin].speed_kt <= 90.0);
    CHECK(p[0] > 1.2 * p[imin]);
    CHECK(p[15] > 1.2 * p[imin]);
    /* the sweep agrees with an independent cold-start trim */
    hfm_trim_result r;
    cd.airspeed_mps = v[11];
    CHECK(hfm_trim_solve(tr, &cd, NULL, &r) == 0);
    CHECK_NEAR(r.u.collective_pct, res[11].u.collective_pct, 1e-5);
    CHECK_NEAR(r.u.pedal_pct, res[11].u.pedal_pct, 1e-5);
}

/* --------------------------------------------------- power vs airspeed */
/* Engine power against airspeed within 10 % of published data
 * (uh60a_power.csv beside this file, which says what the numbers are and
 * where they come from). Each row is trimmed at its own gross weight (a copy
 * of the aircraft file with that mass; inertia unchanged, it does not enter
 * a steady trim) and compared as engine output power: the rotors' shaft
 * power through the transmission efficiency plus the accessories ([power]).
 * Also printed, unchecked: the engine power curve 0-140 kt at the file's
 * weight, and the hover (1 kt) main-rotor torque, on which the hover pedal
 * depends. No SA365N power data were found (docs/validation/hfm.md). */
#define POWER_TOL 0.10
static void test_power(const char *src, const char *csv, const char *name)
{
    /* the new keys refuse bad values, naming file, line and key */
    expect_error(variant(src, "power", "transmission_efficiency", "transmission_efficiency = 1.5",
                         "pw1.ini"),
                 "transmission_efficiency");
    expect_error(variant(src, "power", "accessory_power_kW", NULL, "pw2.ini"), "accessory_power_kW");
    expect_error(variant(src, "main_rotor_airfoil", "drag_divergence_mach",
                         "drag_divergence_mach = 1.2", "pw3.ini"),
                 "drag_divergence_mach");
    expect_error(variant(src, "main_rotor", "hub_drag_m2", "hub_drag_m2 = -1", "pw4.ini"),
                 "hub_drag_m2");
    FILE *f = fopen(csv, "r");
    CHECK(f != NULL);
    if (!f)
        return;
    char line[512];
    int rows = 0;
    while (fgets(line, sizeof line, f)) {
        double v, w_lb, p_kw;
        char ex[16];
        if (line[0] == '#' || sscanf(line, "%lf,%lf,%lf,%15s", &v, &w_lb, &p_kw, ex) != 4)
            continue;
        int gap = !strcmp(ex, "gap");
        CHECK(gap || !strcmp(ex, "within"));
        rows++;
        char repl[64];
        snprintf(repl, sizeof repl, "mass_kg = %.3f", w_lb * 0.45359237);
        core_err err = {0};
        hfm_aircraft *ac = hfm_aircraft_load(variant(src, "aircraft", "mass_kg", repl, "pw.ini"),
                                             NULL, &err);
        CHECK(ac != NULL);
        if (!ac) {
            fprintf(stderr, "%s\n", err.msg);
            continue;
        }
        hfm_trim *tr = hfm_trim_create(ac, NULL);
        hfm_trim_cond cd;
        memset(&cd, 0, sizeof cd);
        cd.kind = HFM_TRIM_FORWARD;
        cd.airspeed_mps = v * KT;
        hfm_trim_result r;
        CHECK(hfm_trim_solve(tr, &cd, NULL, &r) == 0);
        double pe = r.loads.engine_power_W / 1e3, e = pe / p_kw - 1.0;
        int ok = r.converged && fabs(e) <= POWER_TOL;
        printf("%s power %3.0f kt %5.0f lb: engine %6.1f kW (shaft %6.1f = main %6.1f + tail "
               "%5.1f) against %6.1f kW: %+5.1f %% (tolerance %.0f %%) %s\n",
               name, v, w_lb, pe, r.loads.shaft_power_W / 1e3, r.loads.mr_power_W / 1e3,
               r.loads.tr_power_W / 1e3, p_kw, 100.0 * e, 100.0 * POWER_TOL,
               ok ? (gap ? "holds: the gap is closed, mark the row within" : "holds")
                  : (gap ? "misses (documented gap)" : "FAILS"));
        CHECK(r.converged);
        CHECK(gap ? !ok : ok);
        hfm_trim_destroy(tr);
        hfm_aircraft_destroy(ac);
    }
    fclose(f);
    CHECK(rows >= 2);
    /* the file's weight: the curve and the hover main-rotor torque, printed */
    core_err err = {0};
    hfm_aircraft *ac = hfm_aircraft_load(src, NULL, &err);
    CHECK(ac != NULL);
    if (!ac)
        return;
    hfm_trim *tr = hfm_trim_create(ac, NULL);
    double vs[16];
    hfm_trim_result res[16];
    for (int i = 0; i < 15; i++)
        vs[i] = 10.0 * i * KT;
    hfm_trim_cond cd;
    memset(&cd, 0, sizeof cd);
    cd.kind = HFM_TRIM_FORWARD;
    CHECK(hfm_trim_sweep(tr, &cd, HFM_PARAM_AIRSPEED, vs, 15, res) == 0);
    printf("%s engine power kW, 0-140 kt (%.0f kg):", name, hfm_aircraft_mass_kg(ac));
    for (int i = 0; i < 15; i++)
        printf(" %.0f", res[i].loads.engine_power_W / 1e3);
    printf("\n%s shaft power kW:", name);
    for (int i = 0; i < 15; i++)
        printf(" %.0f", res[i].loads.shaft_power_W / 1e3);
    printf("\n");
    cd.airspeed_mps = 1.0 * KT;
    hfm_trim_result r;
    CHECK(hfm_trim_solve(tr, &cd, NULL, &r) == 0);
    printf("%s 1 kt: main-rotor torque %.0f N m (power %.1f kW), pedal %.2f %%\n", name,
           r.loads.mr_torque_Nm, r.loads.mr_power_W / 1e3, r.u.pedal_pct);
    hfm_trim_destroy(tr);
    hfm_aircraft_destroy(ac);
}

/* ------------------------------------------------------ turning points */
/* lam = x^3 - 3x: folds at x = -1 (lam = 2) and x = 1 (lam = -2). */
static int cubic(void *user, const double *x, double lam, double *f)
{
    (void)user;
    f[0] = x[0] * x[0] * x[0] - 3.0 * x[0] - lam;
    return 0;
}

typedef struct fold_rec {
    int n, folds, decreasing;
    double x_last, lam_last, max_err;
} fold_rec;

static int fold_point(void *user, const double *x, double lam, double dlam_ds, int fold)
{
    fold_rec *r = user;
    r->n++;
    r->folds += fold;
    r->decreasing += dlam_ds < 0;
    r->x_last = x[0];
    r->lam_last = lam;
    double e = fabs(x[0] * x[0] * x[0] - 3.0 * x[0] - lam);
    if (e > r->max_err)
        r->max_err = e;
    return 0;
}

static void test_fold(void)
{
    double x0 = -2.2, lam0 = x0 * x0 * x0 - 3.0 * x0;
    hfm_cont_opts o = {0};
    o.ds0 = 0.1;
    o.ds_min = 1e-6;
    o.ds_max = 0.3;
    o.lam_scale = 1.0;
    o.max_steps = 2000;
    o.corr_max_iter = 8;
    o.tol = 1e-12;
    fold_rec r = {0, 0, 0, 0, 0, 0};
    hfm_cont_info inf;
    int rc = hfm_cont_trace(cubic, NULL, 1, &x0, lam0, -10.0, 3.0, &o, fold_point, &r, &inf);
    printf("fold curve: %d points, %d turning points, %d with dlam/ds < 0, end x %.4f at lam "
           "%.4f, max |F| %.2g\n",
           r.n, r.folds, r.decreasing, r.x_last, r.lam_last, r.max_err);
    CHECK(rc == 0);
    CHECK(r.folds == 2);
    CHECK(r.decreasing > 3);   /* the middle branch is traced backwards in lam */
    CHECK(r.x_last > 1.9);     /* ended on the upper branch */
    CHECK(r.lam_last > 3.0);
    CHECK(r.max_err < 1e-9);
    /* Natural-parameter Newton from the lower branch past its fold (lam =
     * 2.5 > 2): the only root is on the upper branch (x = 2.04), so Newton
     * either fails or jumps there. What is checked is that hfm_newton does
     * not report convergence at a point that is not a root (the Jacobian
     * vanishes at x = -1, where a step-size test alone would stop). */
    double x = -1.05;
    hfm_newton_info ni;
    hfm_newton(cubic, NULL, 1, &x, 2.5, NULL, &ni);
    printf("Newton past the fold: converged %d at x %.4f, |F| %.2g\n", ni.converged, x,
           fabs(x * x * x - 3.0 * x - 2.5));
    CHECK(!ni.converged || fabs(x * x * x - 3.0 * x - 2.5) < 1e-8);
}

/* -------------------------------------------------------------- SA365N */
/* Plausibility, not validation: the references publish no SA365N trim, and
 * most of its data file is estimated. The bands are the aircraft acceptance bands: collective
 * 40-75 %, attitudes within 6 deg, power within twice 550 kW. */
static void test_sa365n(hfm_trim *tr)
{
    hfm_trim_cond cd;
    memset(&cd, 0, sizeof cd);
    cd.kind = HFM_TRIM_HOVER_SHIP;
    hfm_trim_result r;
    CHECK(hfm_trim_solve(tr, &cd, NULL, &r) == 0);
    double P = r.loads.mr_power_W + r.loads.tr_power_W;
    printf("SA365N hover: coll %.1f%% long %.1f%% lat %.1f%% ped %.1f%% pitch %.2f roll %.2f "
           "deg, power %.0f kW (main %.0f, fenestron %.0f)\n",
           r.u.collective_pct, r.u.long_cyclic_pct, r.u.lat_cyclic_pct, r.u.pedal_pct,
           r.body.euler_rad[1] * CORE_RAD_TO_DEG, r.body.euler_rad[0] * CORE_RAD_TO_DEG, P / 1e3,
           r.loads.mr_power_W / 1e3, r.loads.tr_power_W / 1e3);
    CHECK(r.u.collective_pct >= 40.0 && r.u.collective_pct <= 75.0);
    CHECK(fabs(r.body.euler_rad[1] * CORE_RAD_TO_DEG) <= 6.0);
    CHECK(fabs(r.body.euler_rad[0] * CORE_RAD_TO_DEG) <= 6.0);
    CHECK(P <= 2.0 * 550e3);
}

/* --------------------------------------------- wake-interaction continuity */
/* Every load must be a continuous function of the state, so the
 * level, zero-sideslip trim at 1 kt steps over 0-160 kt has no jump. A step
 * d_i = y(V_i) - y(V_i-1) fails when it exceeds three times the larger of its
 * neighbouring steps plus an absolute tolerance: 0.3 % of travel for the
 * controls, 0.1 deg for pitch and roll (a jump such as the point-immersion
 * model's 1.6 % of long. cyclic between 47 and 48 kt fails; the steepest
 * smooth change, the hover-to-transition collective drop, passes). The
 * tolerances are judgement, not published data. */
static void wake_continuity(hfm_trim *tr, const char *name)
{
    enum { NV = 161, NQ = 6 };
    static double v[NV], y[NQ][NV];
    static hfm_trim_result res[NV];
    for (int i = 0; i < NV; i++)
        v[i] = i * KT;
    hfm_trim_cond cd;
    memset(&cd, 0, sizeof cd);
    cd.kind = HFM_TRIM_FORWARD;
    cd.constraint = HFM_CONSTRAINT_SIDESLIP;
    int rc = hfm_trim_sweep(tr, &cd, HFM_PARAM_AIRSPEED, v, NV, res);
    CHECK(rc == 0);
    int fails = 0, bad = 0;
    for (int i = 0; i < NV; i++) {
        fails += !res[i].converged;
        y[0][i] = res[i].u.collective_pct;
        y[1][i] = res[i].u.long_cyclic_pct;
        y[2][i] = res[i].u.lat_cyclic_pct;
        y[3][i] = res[i].u.pedal_pct;
        y[4][i] = res[i].body.euler_rad[1] * CORE_RAD_TO_DEG;
        y[5][i] = res[i].body.euler_rad[0] * CORE_RAD_TO_DEG;
    }
    CHECK(fails == 0);
    static const char *qn[NQ] = {"collective %", "long %", "lat %", "pedal %", "pitch deg",
                                 "roll deg"};
    static const double tol[NQ] = {0.3, 0.3, 0.3, 0.3, 0.1, 0.1};
    for (int q = 0; q < NQ; q++) {
        double worst = 0.0;
        int iw = 0;
        for (int i = 1; i < NV; i++) {
            double d = fabs(y[q][i] - y[q][i - 1]);
            double dl = i >= 2 ? fabs(y[q][i - 1] - y[q][i - 2]) : 0.0;
            double dr = i + 1 < NV ? fabs(y[q][i + 1] - y[q][i]) : 0.0;
            double ex = d - (3.0 * fmax(dl, dr) + tol[q]);
            if (ex > worst) {
                worst = ex;
                iw = i;
            }
        }
        if (worst > 0.0) {
            printf("%s wake continuity: %s jumps %.3f between %d and %d kt (neighbouring steps "
                   "%.3f, %.3f)\n",
                   name, qn[q], y[q][iw] - y[q][iw - 1], iw - 1, iw,
                   iw >= 2 ? y[q][iw - 1] - y[q][iw - 2] : 0.0,
                   iw + 1 < NV ? y[q][iw + 1] - y[q][iw] : 0.0);
            bad++;
        }
    }
    printf("%s wake continuity 0-160 kt: %d failed trims, %d quantities with a jump; 47/48 kt: "
           "coll %.2f/%.2f long %.2f/%.2f pitch %.2f/%.2f, fuselage Z %.0f/%.0f N\n",
           name, fails, bad, y[0][47], y[0][48], y[1][47], y[1][48], y[4][47], y[4][48],
           res[47].loads.fus.F_B_N[2], res[48].loads.fus.F_B_N[2]);
    for (int i = 0; i <= 50; i += i < 40 ? 40 : 2)
        printf("%s %3d kt: coll %.2f long %.2f lat %.2f ped %.2f %% pitch %.2f roll %.2f deg, "
               "fuselage Z %.0f N\n",
               name, i, y[0][i], y[1][i], y[2][i], y[3][i], y[4][i], y[5][i],
               res[i].loads.fus.F_B_N[2]);
    CHECK(bad == 0);
}

/* ----------------------------------------------------------------- WOD */
static double wod_pedal(hfm_trim *tr, double kt, double dir_deg, int *ok)
{
    hfm_trim_cond cd;
    memset(&cd, 0, sizeof cd);
    cd.kind = HFM_TRIM_HOVER_SHIP;
    cd.wod_speed_mps = kt * KT;
    cd.wod_dir_rad = dir_deg * CORE_DEG_TO_RAD;
    hfm_trim_result r;
    *ok &= hfm_trim_solve(tr, &cd, NULL, &r) == 0;
    return r.u.pedal_pct;
}

static void test_wod(hfm_trim *uh, hfm_trim *sa)
{
    const double dirs[2] = {45.0, 90.0}, kts[2] = {15.0, 30.0};
    for (int k = 0; k < 2; k++)
        for (int d = 0; d < 2; d++) {
            int ok = 1;
            double ug = wod_pedal(uh, kts[k], dirs[d], &ok), ur = wod_pedal(uh, kts[k], -dirs[d], &ok);
            double sg = wod_pedal(sa, kts[k], dirs[d], &ok), sr = wod_pedal(sa, kts[k], -dirs[d], &ok);
            printf("WOD %2.0f kt %2.0f deg: UH-60A pedal green %.1f%% red %.1f%%; SA365N pedal "
                   "green %.1f%% red %.1f%%\n",
                   kts[k], dirs[d], ug, ur, sg, sr);
            CHECK(ok);
            /* UH-60A (anti-torque = left pedal): more left pedal in green */
            CHECK(ug < ur);
            /* SA365N (anti-torque = right pedal): more right pedal in red --
             * its critical side is the reverse of the UH-60A's */
            CHECK(sr > sg);
        }
}

/* WOD-speed continuation for both aircraft: 0-60 kt in 5 kt, green 45 and
 * red 45, every point converged and agreeing with a cold-start trim. */
static void test_wod_sweep(hfm_trim *tr, const char *name)
{
    double v[13];
    for (int i = 0; i < 13; i++)
        v[i] = 5.0 * i * KT;
    for (int d = -1; d <= 1; d += 2) {
        hfm_trim_cond cd;
        memset(&cd, 0, sizeof cd);
        cd.kind = HFM_TRIM_HOVER_SHIP;
        cd.wod_dir_rad = d * 45.0 * CORE_DEG_TO_RAD;
        hfm_trim_result res[13], r;
        int rc = hfm_trim_sweep(tr, &cd, HFM_PARAM_WOD_SPEED, v, 13, res);
        int fails = 0;
        for (int i = 0; i < 13; i++)
            fails += !res[i].converged;
        cd.wod_speed_mps = v[9];
        CHECK(hfm_trim_solve(tr, &cd, NULL, &r) == 0);
        printf("%s WOD sweep 0-60 kt at %+.0f deg: %d failed; 45 kt pedal %.3f%% (cold start "
               "%.3f%%)\n",
               name, d * 45.0, fails, res[9].u.pedal_pct, r.u.pedal_pct);
        CHECK(rc == 0);
        CHECK(fails == 0);
        CHECK_NEAR(res[9].u.pedal_pct, r.u.pedal_pct, 1e-4);
    }
}

/* ---------------------------------------------------------------- Bo105 */
/* The third aircraft, written from published data alone: its
 * trims against Bo105 flight test (bo105_trim.csv beside this file: the
 * flight-test points of Padfield's chapter 4 figures as digitised by
 * HEROES; its header says how). Each row is trimmed level at its airspeed,
 * zero sideslip, 2200 kg, sea level, cold start, and compared in blade
 * pitch (Padfield's theta1s = -B1, theta1c = -A1 for a ccw rotor, whose
 * pitch is theta0 - A1 cos psi - B1 sin psi here) and in power (main plus
 * tail rotor, aerodynamic). Tolerances: the issue's, 1.5 deg for attitude
 * and blade pitch, 15 % of the flight-test power.
 * A point outside the tolerance fails unless it lies in one of the KNOWN
 * GAPS below, each measured, documented with the physics the model lacks
 * (docs/validation/hfm.md, "Bo105") and checked as a band of the signed
 * difference model - flight test (degrees, or a fraction of the flight-test
 * power): a point outside its band, or a failing point outside every
 * band's speed range, fails the test. The bands are the measured gaps
 * widened by about 0.5 deg (0.05 of power) for reading error; they are a
 * record of what is missing, not a tolerance the model meets. */
#define BO105 "scenarios/aircraft/bo105.ini"
#define BO105_TOL_DEG 1.5
#define BO105_TOL_POWER 0.15

typedef struct bo105_gap {
    const char *quantity;
    double kt_lo, kt_hi;   /* airspeed range of the gap */
    double lo, hi;         /* band of model - flight test (deg, or of power) */
    const char *why;
} bo105_gap;

static const bo105_gap bo105_gaps[] = {
    {"pitch_deg", 35.0, 42.0, 1.5, 2.5,
     "the tailplane leaves the wake later than in flight: the flight-test pitch falls 3.4 deg "
     "between 27 and 39 kt, the model's wake (uniform across its section, a 0.15 R cosine "
     "edge) lets go of the tailplane more gradually"},
    {"theta1s_deg", 0.0, 10.0, -2.1, -1.5,
     "hover longitudinal cyclic 1.5-1.6 deg aft of flight: the contracted wake (R/sqrt(k)) "
     "leaves the tailplane (0.91 R behind the shaft) outside it in hover, where flight asks "
     "for a tail download; the wake's diffuse outer edge and the tail boom's share are not "
     "modelled (the UH-60A hover shows the same sign, 6 % of travel aft of GenHel)"},
    {"theta0tr_deg", 20.0, 45.0, 1.5, 3.0,
     "the wake is along the shaft only: no swirl or sidewash at the fin and tail rotor, whose "
     "flight-test pitch falls 3.7 deg between 15 and 23 kt"},
    {"theta0tr_deg", 95.0, 105.0, -2.1, -1.5,
     "follows the power gap: the main-rotor torque the tail rotor balances is 28 % low"},
    {"power_kW", 55.0, 105.0, -0.33, -0.15,
     "no compressibility in the airfoil table (advancing tip M 0.79 at 100 kt), no hub or skid "
     "drag beyond Padfield's fuselage polynomial, aerodynamic power without transmission losses"},
};

static void test_bo105(void)
{
    core_err err = {0};
    hfm_aircraft *ac = hfm_aircraft_load(BO105, NULL, &err);
    CHECK(ac != NULL);
    if (!ac) {
        fprintf(stderr, "%s\n", err.msg);
        return;
    }
    CHECK(!strcmp(hfm_aircraft_name(ac), "Bo105"));
    CHECK(hfm_aircraft_rotor_ccw(ac));
    hfm_trim *tr = hfm_trim_create(ac, NULL);
    FILE *f = fopen("tests/hfm/bo105_trim.csv", "r");
    CHECK(f != NULL);
    CHECK(tr != NULL);
    if (!f || !tr) {
        if (f)
            fclose(f);
        hfm_trim_destroy(tr);
        hfm_aircraft_destroy(ac);
        return;
    }
    const int ngaps = (int)(sizeof bo105_gaps / sizeof bo105_gaps[0]);
    char line[256];
    int rows = 0, held = 0, known = 0, bad = 0;
    printf("Bo105 vs flight test: quantity, kt, computed, flight test, difference, tolerance\n");
    while (fgets(line, sizeof line, f)) {
        char q[32];
        double v, ref;
        if (line[0] == '#' || sscanf(line, "%31[^,],%lf,%lf", q, &v, &ref) != 3)
            continue;
        hfm_trim_cond cd;
        memset(&cd, 0, sizeof cd);
        cd.kind = HFM_TRIM_FORWARD;
        cd.constraint = HFM_CONSTRAINT_SIDESLIP;
        cd.airspeed_mps = v * KT;
        hfm_trim_result r;
        int rc = hfm_trim_solve(tr, &cd, NULL, &r);
        CHECK(rc == 0);
        CHECK(r.converged);
        double th0, A1, B1, thtr;
        hfm_controls_to_pitch(ac, &r.u, &th0, &A1, &B1, &thtr);
        double model;
        int power = 0;
        if (!strcmp(q, "pitch_deg"))
            model = r.body.euler_rad[1] * CORE_RAD_TO_DEG;
        else if (!strcmp(q, "theta0_deg"))
            model = th0 * CORE_RAD_TO_DEG;
        else if (!strcmp(q, "theta1s_deg"))
            model = -B1 * CORE_RAD_TO_DEG;
        else if (!strcmp(q, "theta1c_deg"))
            model = -A1 * CORE_RAD_TO_DEG;
        else if (!strcmp(q, "theta0tr_deg"))
            model = thtr * CORE_RAD_TO_DEG;
        else if (!strcmp(q, "power_kW")) {
            model = (r.loads.mr_power_W + r.loads.tr_power_W) / 1e3;
            power = 1;
        } else {
            printf("bo105_trim.csv: unknown quantity '%s'\n", q);
            CHECK(0);
            continue;
        }
        rows++;
        double tol = power ? BO105_TOL_POWER * ref : BO105_TOL_DEG;
        double gap = power ? (model - ref) / ref : model - ref;
        const char *verdict = "holds";
        if (fabs(model - ref) <= tol) {
            held++;
        } else {
            verdict = "FAILS";
            for (int g = 0; g < ngaps; g++) {
                const bo105_gap *k = &bo105_gaps[g];
                if (strcmp(k->quantity, q) || v < k->kt_lo || v > k->kt_hi)
                    continue;
                if (gap >= k->lo && gap <= k->hi) {
                    verdict = "KNOWN GAP";
                    known++;
                } else {
                    verdict = "FAILS (outside its known-gap band)";
                }
                break;
            }
            if (!strncmp(verdict, "FAILS", 5))
                bad++;
        }
        printf("Bo105 %-13s %6.1f kt  model %7.2f  flight %7.2f  diff %+7.2f%s  tol %5.2f  %s\n", q,
               v, model, ref, model - ref, power ? " kW" : "", tol, verdict);
    }
    fclose(f);
    printf("Bo105: %d of %d flight-test points within tolerance, %d in a documented known gap, "
           "%d failing\n",
           held, rows, known, bad);
    for (int g = 0; g < ngaps; g++)
        printf("Bo105 known gap: %s %.0f-%.0f kt, model - flight %+.2f..%+.2f%s: %s\n",
               bo105_gaps[g].quantity, bo105_gaps[g].kt_lo, bo105_gaps[g].kt_hi, bo105_gaps[g].lo,
               bo105_gaps[g].hi, strcmp(bo105_gaps[g].quantity, "power_kW") ? " deg" : " of power",
               bo105_gaps[g].why);
    CHECK(rows == 71);
    CHECK(bad == 0);
    /* the continuity on the third aircraft: 0-160 kt at 1 kt, no jump */
    wake_continuity(tr, "Bo105");
    hfm_trim_destroy(tr);
    hfm_aircraft_destroy(ac);
}

int main(void)
{
    setvbuf(stdout, NULL, _IOLBF, 0);
    snprintf(tmpdir, sizeof tmpdir, "/tmp/test_hfm_XXXXXX");
    if (!mkdtemp(tmpdir))
        return 1;
    test_bad_input();
    core_err err = {0};
    hfm_aircraft *uh = hfm_aircraft_load(UH60, NULL, &err);
    CHECK(uh != NULL);
    hfm_aircraft *sa = hfm_aircraft_load(SA365, NULL, &err);
    CHECK(sa != NULL);
    if (!uh || !sa) {
        fprintf(stderr, "%s\n", err.msg);
        return check_done("test_hfm");
    }
    CHECK(!strcmp(hfm_aircraft_name(uh), "UH-60A"));
    CHECK(!strcmp(hfm_aircraft_name(sa), "SA365N"));
    hfm_trim *tu = hfm_trim_create(uh, NULL), *ts = hfm_trim_create(sa, NULL);
    test_genhel(tu);
    test_hover(uh, tu);
    test_wake_air(tu);
    test_sweep(tu);
    test_power(UH60, "tests/hfm/uh60a_power.csv", "UH-60A");
    test_fold();
    test_sa365n(ts);
    test_wod(tu, ts);
    test_wod_sweep(tu, "UH-60A");
    test_wod_sweep(ts, "SA365N");
    wake_continuity(tu, "UH-60A");
    wake_continuity(ts, "SA365N");
    test_bo105();
    hfm_trim_destroy(tu);
    hfm_trim_destroy(ts);
    hfm_aircraft_destroy(uh);
    hfm_aircraft_destroy(sa);
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf %s", tmpdir);
    if (system(cmd) != 0)
        fprintf(stderr, "could not remove %s\n", tmpdir);
    return check_done("test_hfm");
}
