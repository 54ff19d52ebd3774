/* test_hfm_format.c -- the aircraft data-file reference (docs/aircraft-format.md)
 * in use (run from the source root):
 *  - data/luh25.ini, a made-up 2,500 kg light utility helicopter written from
 *    that page alone, loads without a warning, its derived figures are those
 *    its comments state, and it trims in hover (collective, attitude and power
 *    physical: figure of merit 0.6-0.8, power within 20 % of momentum theory
 *    over a figure of merit of 0.7) and at 60 kt (less power and collective
 *    than in hover: the bucket);
 *  - the shipped aircraft load without a warning;
 *  - each consistency check fires on a copy of a good file with the unit slip
 *    it is meant to catch (an error naming file, line, key and why, or a
 *    warning through core_log), and an unknown section is named;
 *  - the validated error ([model_error]) read as the files state it, and
 *    its bad keys refused.
 */
#include "check.h"
#include "hfm.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define LUH "tests/hfm/data/luh25.ini"
#define UH60 "scenarios/aircraft/uh60a.ini"
#define SA365 "scenarios/aircraft/sa365n.ini"

static char tmpdir[256];

/* ------------------------------------------------------------- log sink */
typedef struct sink {
    int warnings, infos;
    char text[4096]; /* the warnings and infos, one per line */
} sink;

static void sink_fn(void *user, int level, const char *msg)
{
    sink *s = user;
    if (level == CORE_LOG_WARN)
        s->warnings++;
    else if (level == CORE_LOG_INFO && strstr(msg, "hfm: loaded") == NULL)
        s->infos++;
    else
        return;
    size_t n = strlen(s->text);
    snprintf(s->text + n, sizeof s->text - n, "%s\n", msg);
}

/* ------------------------------------------------------ file variants */
/* One change: the line of `key` in [section] replaced by repl (NULL:
 * removed); with key NULL, repl is appended at the end of the file. */
typedef struct edit {
    const char *section, *key, *repl;
} edit;

static const char *variant(const char *src, const edit *ed, int ne, const char *name)
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
    while (fgets(line, sizeof line, in)) {
        if (line[0] == '[')
            sscanf(line, "[%127[^]]", sec);
        int done = 0;
        for (int i = 0; i < ne && !done; i++) {
            size_t kl = ed[i].key ? strlen(ed[i].key) : 0;
            if (ed[i].key && !strcmp(sec, ed[i].section) && !strncmp(line, ed[i].key, kl) &&
                (line[kl] == ' ' || line[kl] == '=')) {
                if (ed[i].repl)
                    fprintf(out, "%s\n", ed[i].repl);
                done = 1;
            }
        }
        if (!done)
            fputs(line, out);
    }
    for (int i = 0; i < ne; i++)
        if (!ed[i].key)
            fprintf(out, "%s\n", ed[i].repl);
    fclose(in);
    fclose(out);
    return path;
}

/* Load path; expect a refusal whose message holds every needle. */
static void expect_refused(const char *path, const char *const *needles, const char *what)
{
    core_err err = {0};
    hfm_aircraft *ac = path ? hfm_aircraft_load(path, NULL, &err) : NULL;
    int ok = path && !ac;
    for (int i = 0; needles[i]; i++)
        ok &= strstr(err.msg, needles[i]) != NULL;
    CHECK(ok);
    printf("%s: %s\n", what, ac ? "(loaded)" : err.msg);
    if (!ok)
        for (int i = 0; needles[i]; i++)
            if (!strstr(err.msg, needles[i]))
                fprintf(stderr, "  expected '%s'\n", needles[i]);
    hfm_aircraft_destroy(ac);
}

/* Load path; expect it to load with a warning holding every needle. */
static void expect_warned(const char *path, const char *const *needles, const char *what, sink *s)
{
    core_err err = {0};
    memset(s, 0, sizeof *s);
    core_log log = {sink_fn, s, CORE_LOG_INFO};
    hfm_aircraft *ac = path ? hfm_aircraft_load(path, &log, &err) : NULL;
    int ok = ac && s->warnings >= 1;
    for (int i = 0; needles[i]; i++)
        ok &= strstr(s->text, needles[i]) != NULL;
    CHECK(ok);
    printf("%s: %s", what, ac ? s->text : err.msg);
    if (!ac)
        printf("\n");
    hfm_aircraft_destroy(ac);
}

#define NEEDLES(...) ((const char *const[]){__VA_ARGS__, NULL})

static void test_checks(void)
{
    sink s;
    /* twist in radians: -10 deg typed as -0.1745 */
    expect_refused(variant(LUH, (edit[]){{"main_rotor", "twist_deg", "twist_deg = -0.1745"}}, 1, "tw.ini"),
                   NEEDLES("tw.ini:", "[main_rotor] twist_deg = -0.1745", "radians", "-10.0 deg"), "twist in rad");
    expect_refused(variant(UH60, (edit[]){{"tail_rotor", "twist_deg", "twist_deg = -0.3"}}, 1, "tw2.ini"),
                   NEEDLES("[tail_rotor] twist_deg = -0.3", "-17.2 deg"), "tail twist in rad");
    /* the radius in ft: tip speed 39.3 x 18.04 = 709 m/s */
    expect_refused(variant(LUH, (edit[]){{"main_rotor", "radius_m", "radius_m = 18.04"}}, 1, "tip.ini"),
                   NEEDLES("[main_rotor] omega_radps = 39.3", "709 m/s", "in ft"), "radius in ft");
    expect_refused(variant(LUH, (edit[]){{"tail_rotor", "radius_m", "radius_m = 3.28"}}, 1, "tip2.ini"),
                   NEEDLES("[tail_rotor] omega_radps = 210", "689 m/s"), "tail radius in ft");
    /* the chord in ft */
    expect_refused(variant(LUH, (edit[]){{"main_rotor", "chord_m", "chord_m = 0.984"}}, 1, "sig.ini"),
                   NEEDLES("[main_rotor] chord_m = 0.984", "solidity", "0.2278"), "chord in ft");
    /* Lock number: a blade ten times too heavy in lb ft^2 (out of 2-20), and
     * a light blade (above 12: warned) */
    expect_refused(variant(LUH,
                           (edit[]){{"main_rotor", "blade_flap_inertia_kgm2", "blade_flap_inertia_kgm2 = 6666"},
                                    {"main_rotor", "blade_mass_kg", "blade_mass_kg = 300"}},
                           2, "lock.ini"),
                   NEEDLES("[main_rotor] blade_flap_inertia_kgm2 = 6666", "Lock number", "0.29"), "Lock 0.29");
    expect_warned(variant(LUH,
                          (edit[]){{"main_rotor", "blade_flap_inertia_kgm2", "blade_flap_inertia_kgm2 = 150"},
                                   {"main_rotor", "blade_first_moment_kgm", "blade_first_moment_kgm = 60"}},
                          2, "lock2.ini"),
                  NEEDLES("[main_rotor] blade_flap_inertia_kgm2 = 150", "Lock number", "12.85"), "Lock 12.85", &s);
    /* flap frequency: an offset of 1.107 /rev and a spring of 1.095 /rev
     * (each a plausible hingeless rotor) give 1.194 together: warned; a
     * stiffer spring takes it past 1.30: refused */
    expect_warned(variant(LUH,
                          (edit[]){{"main_rotor", "hinge_offset_m", "hinge_offset_m = 0.8"},
                                   {"main_rotor", "flap_spring_Nmprad", "flap_spring_Nmprad = 86770"}},
                          2, "flap.ini"),
                  NEEDLES("[main_rotor] hinge_offset_m = 0.8", "flaps at 1.194 /rev", "alone gives 1.107",
                          "alone 1.095", "not both", "together give a flap frequency of 1.194"),
                  "flap 1.194", &s);
    CHECK(s.infos == 1);
    expect_refused(variant(LUH,
                           (edit[]){{"main_rotor", "hinge_offset_m", "hinge_offset_m = 0.8"},
                                    {"main_rotor", "flap_spring_Nmprad", "flap_spring_Nmprad = 216900"}},
                           2, "flap2.ini"),
                   NEEDLES("[main_rotor] flap_spring_Nmprad = 216900", "1.314 /rev", "above 1.30"), "flap 1.314");
    /* the mass in lb: CT/sigma 0.143, warned (the rig widened so that it
     * still reaches the hover pitch); 12,000 kg cannot be lifted at all */
    expect_warned(variant(LUH,
                          (edit[]){{"aircraft", "mass_kg", "mass_kg = 5512"},
                                   {"controls", "collective_deg_per_in", "collective_deg_per_in = 2.0"}},
                          2, "mass.ini"),
                  NEEDLES("[aircraft] mass_kg = 5512", "CT/sigma = 0.143", "lb"), "mass in lb", &s);
    expect_refused(variant(LUH, (edit[]){{"aircraft", "mass_kg", "mass_kg = 12000"}}, 1, "mass2.ini"),
                   NEEDLES("[aircraft] mass_kg = 12000", "cannot lift"), "12 t");
    /* the UH-60A's root-pitch rig read as a 0.75 R rig */
    expect_refused(variant(UH60, (edit[]){{"main_rotor", "twist_ref_r_over_R", "twist_ref_r_over_R = 0.75"}}, 1,
                           "ref.ini"),
                   NEEDLES("[controls] collective_pitch0_deg = 13.098", "13.1 to 29.1 deg at 0.75 R",
                           "about 10.1 deg", "twist_ref_r_over_R"),
                   "rig at 0.75 R");
    /* signs of B: z up, x aft */
    expect_refused(variant(LUH, (edit[]){{"main_rotor", "hub_B_m", "hub_B_m = 0.0, 0.0, 1.6"}}, 1, "hub.ini"),
                   NEEDLES("[main_rotor] hub_B_m: z = 1.6 m", "z < 0"), "hub below the CG");
    expect_refused(variant(LUH, (edit[]){{"tail_rotor", "hub_B_m", "hub_B_m = 6.9, -0.3, -1.0"}}, 1, "tail.ini"),
                   NEEDLES("[tail_rotor] hub_B_m: x = 6.9 m", "x < 0"), "tail rotor ahead");
    /* the fuselage drag in ft^2 */
    expect_refused(variant(LUH,
                           (edit[]){{"fuselage", "drag_m2", "drag_m2 = 64.6,12.6,11.8,11.8,12.6,13.9,18.3,64.6"}}, 1,
                           "drag.ini"),
                   NEEDLES("[fuselage] drag_m2: 11.8 m^2", "ft^2"), "drag in ft^2");
    /* an unknown section is named with the line of its first key, before the
     * missing key of the section meant */
    const char *p = variant(LUH, (edit[]){{"fin", "cd0", NULL}, {NULL, NULL, "[fin_extra]\ncd0 = 0.01"}}, 2,
                            "sec.ini");
    expect_refused(p, NEEDLES("sec.ini:135: unknown section [fin_extra]"), "unknown section");
}

/* ---------------------------------------------------- [model_error] */
/* The validated error: the UH-60A's GenHel hover row as its file states
 * it, the SA365N not validated, the Bo105 its pitch alone; an unknown,
 * malformed or out-of-range key refused naming file, line and key; a
 * section without an error refused; an error from a cruise trim warned. */
static void test_model_error(void)
{
    core_err err = {0};
    hfm_model_error m;
    hfm_aircraft *ac = hfm_aircraft_load(UH60, NULL, &err);
    CHECK(ac && hfm_aircraft_model_error(ac, &m) == 0);
    if (ac) {
        CHECK(strcmp(m.reference, "GenHel") == 0);
        CHECK_NEAR(m.airspeed_mps, 1.0 * CORE_KT_TO_MPS, 1e-12);
        CHECK_NEAR(m.pedal_pct, -4.27, 1e-12);
        CHECK_NEAR(m.long_cyclic_pct, -5.94, 1e-12);
        CHECK_NEAR(m.collective_pct, 1.56, 1e-12);
        CHECK_NEAR(m.lat_cyclic_pct, 0.92, 1e-12);
        CHECK_NEAR(m.pitch_rad, 1.20 * CORE_DEG_TO_RAD, 1e-12);
        CHECK_NEAR(m.roll_rad, 0.42 * CORE_DEG_TO_RAD, 1e-12);
        printf("UH-60A model error vs %s at %.0f kt: pedal %+.2f %%, pitch %+.2f deg\n", m.reference,
               m.airspeed_mps / CORE_KT_TO_MPS, m.pedal_pct, m.pitch_rad * CORE_RAD_TO_DEG);
    }
    hfm_aircraft_destroy(ac);
    ac = hfm_aircraft_load(SA365, NULL, &err);
    CHECK(ac && hfm_aircraft_model_error(ac, &m) == 1);
    CHECK(isnan(m.pedal_pct) && isnan(m.pitch_rad) && isnan(m.roll_rad) && isnan(m.collective_pct) &&
          m.reference[0] == '\0');
    hfm_aircraft_destroy(ac);
    ac = hfm_aircraft_load("scenarios/aircraft/bo105.ini", NULL, &err);
    CHECK(ac && hfm_aircraft_model_error(ac, &m) == 0);
    CHECK(ac && fabs(m.pitch_rad - (-0.18 * CORE_DEG_TO_RAD)) < 1e-12 && isnan(m.pedal_pct) && isnan(m.roll_rad));
    hfm_aircraft_destroy(ac);

    expect_refused(variant(UH60, (edit[]){{"model_error", "pedal_pct", "pedal_pct = -4.27\npedal_pc = 1"}}, 1,
                           "me_unknown.ini"),
                   NEEDLES("me_unknown.ini:", "[model_error] pedal_pc", "unknown key"), "model_error unknown key");
    expect_refused(variant(UH60, (edit[]){{"model_error", "pedal_pct", "pedal_pct = -4.27 %"}}, 1, "me_bad.ini"),
                   NEEDLES("me_bad.ini:", "[model_error] pedal_pct"), "model_error malformed");
    expect_refused(variant(UH60, (edit[]){{"model_error", "pitch_deg", "pitch_deg = 12"}}, 1, "me_range.ini"),
                   NEEDLES("me_range.ini:", "[model_error] pitch_deg"), "model_error out of range");
    expect_refused(variant(UH60, (edit[]){{"model_error", "reference", NULL}}, 1, "me_noref.ini"),
                   NEEDLES("me_noref.ini", "[model_error] reference"), "model_error without reference");
    const edit none[6] = {{"model_error", "roll_deg", NULL},        {"model_error", "pitch_deg", NULL},
                          {"model_error", "collective_pct", NULL},  {"model_error", "long_cyclic_pct", NULL},
                          {"model_error", "lat_cyclic_pct", NULL},  {"model_error", "pedal_pct", NULL}};
    expect_refused(variant(UH60, none, 6, "me_none.ini"), NEEDLES("me_none.ini:", "[model_error] reference", "no error"),
                   "model_error without an error");
    sink s;
    expect_warned(variant(UH60, (edit[]){{"model_error", "airspeed_kt", "airspeed_kt = 60"}}, 1, "me_60.ini"),
                  NEEDLES("me_60.ini:", "[model_error] airspeed_kt = 60", "0-45 kt"), "model_error at 60 kt", &s);
}

/* ------------------------------------------------------------- LUH-25 */
static void test_shipped(void)
{
    const char *files[] = {UH60, SA365, LUH};
    for (int i = 0; i < 3; i++) {
        sink s = {0};
        core_log log = {sink_fn, &s, CORE_LOG_WARN};
        core_err err = {0};
        hfm_aircraft *ac = hfm_aircraft_load(files[i], &log, &err);
        CHECK(ac != NULL && s.warnings == 0);
        if (!ac || s.warnings)
            fprintf(stderr, "%s: %s%s\n", files[i], err.msg, s.text);
        hfm_aircraft_destroy(ac);
    }
}

static double weight_down_S(const hfm_body *b, const double F_B[3])
{
    core_euler e = {b->euler_rad[0], b->euler_rad[1], b->euler_rad[2]};
    core_vec3 v = core_mat3_mul_vec(core_mat3_from_euler(e), core_vec3_make(F_B[0], F_B[1], F_B[2]));
    return v.z;
}

static void test_luh25(void)
{
    core_err err = {0};
    hfm_aircraft *ac = hfm_aircraft_load(LUH, NULL, &err);
    CHECK(ac != NULL);
    if (!ac) {
        fprintf(stderr, "%s\n", err.msg);
        return;
    }
    CHECK(!strcmp(hfm_aircraft_name(ac), "LUH-25"));
    /* the figures the file's comments state */
    hfm_aircraft_figures f;
    hfm_aircraft_get_figures(ac, &f);
    printf("LUH-25: tip speed %.1f m/s, solidity %.4f, Lock number %.2f, flap frequency %.3f /rev, "
           "CT/sigma %.4f, hover pitch estimate %.1f deg at 0.75 R (rig %.1f to %.1f)\n",
           f.tip_speed_mps, f.solidity, f.lock_number, f.flap_freq_per_rev, f.ct_over_sigma_hover,
           f.hover_pitch75_deg, f.coll_pitch75_min_deg, f.coll_pitch75_max_deg);
    CHECK_NEAR(f.tip_speed_mps, 216.0, 0.5);
    CHECK_NEAR(f.solidity, 0.069, 0.0005);
    CHECK_NEAR(f.lock_number, 6.9, 0.05);
    CHECK_NEAR(f.flap_freq_per_rev, 1.028, 0.0005);
    CHECK_NEAR(f.coll_pitch75_min_deg, -1.0, 1e-9);
    CHECK_NEAR(f.coll_pitch75_max_deg, 15.0, 1e-9);

    hfm_trim *tr = hfm_trim_create(ac, NULL);
    hfm_trim_cond cd;
    memset(&cd, 0, sizeof cd);
    cd.kind = HFM_TRIM_HOVER_SHIP;
    hfm_trim_result h, c;
    CHECK(hfm_trim_solve(tr, &cd, NULL, &h) == 0 && h.converged);
    const hfm_loads *L = &h.loads;
    double T = L->mr_thrust_N, W = hfm_aircraft_weight_N(ac), A = CORE_PI * pow(hfm_aircraft_rotor_radius_m(ac), 2);
    double P_ideal = pow(T, 1.5) / sqrt(2.0 * CORE_RHO_SL_KGPM3 * A), fm = P_ideal / L->mr_power_W;
    double theta0, A1, B1, thtr;
    hfm_controls_to_pitch(ac, &h.u, &theta0, &A1, &B1, &thtr);
    printf("LUH-25 hover: collective %.1f %%, long %.1f %%, lat %.1f %%, pedal %.1f %%, pitch %.2f deg, roll "
           "%.2f deg; thrust %.0f N = %.3f W (download %.0f N); power %.0f kW, momentum theory %.0f kW, figure of "
           "merit %.3f; root pitch %.2f deg (%.2f at 0.75 R, estimate %.1f)\n",
           h.u.collective_pct, h.u.long_cyclic_pct, h.u.lat_cyclic_pct, h.u.pedal_pct,
           h.body.euler_rad[1] * CORE_RAD_TO_DEG, h.body.euler_rad[0] * CORE_RAD_TO_DEG, T, T / W,
           weight_down_S(&h.body, L->fus.F_B_N), L->mr_power_W / 1e3, P_ideal / 1e3, fm, theta0 * CORE_RAD_TO_DEG,
           theta0 * CORE_RAD_TO_DEG - 7.5, f.hover_pitch75_deg);
    CHECK(h.u.collective_pct > 35.0 && h.u.collective_pct < 75.0);
    CHECK(fabs(h.u.long_cyclic_pct - 50.0) < 25.0 && fabs(h.u.lat_cyclic_pct - 50.0) < 25.0);
    CHECK(h.u.pedal_pct > 20.0 && h.u.pedal_pct < 80.0);
    CHECK(h.body.euler_rad[1] * CORE_RAD_TO_DEG > -2.0 && h.body.euler_rad[1] * CORE_RAD_TO_DEG < 8.0); /* nose up a little */
    CHECK(fabs(h.body.euler_rad[0] * CORE_RAD_TO_DEG) < 5.0);
    CHECK(T > W && T < 1.08 * W); /* weight plus a few per cent of download */
    CHECK(fm > 0.6 && fm < 0.8);
    CHECK(fabs(L->mr_power_W / (P_ideal / 0.7) - 1.0) < 0.2);
    CHECK(fabs(theta0 * CORE_RAD_TO_DEG - 7.5 - f.hover_pitch75_deg) < 2.0); /* the estimate the check uses */

    cd.kind = HFM_TRIM_FORWARD;
    cd.airspeed_mps = 60.0 * CORE_KT_TO_MPS;
    CHECK(hfm_trim_solve(tr, &cd, NULL, &c) == 0 && c.converged);
    printf("LUH-25 60 kt: collective %.1f %%, long %.1f %%, lat %.1f %%, pedal %.1f %%, pitch %.2f deg, roll %.2f "
           "deg, power %.0f kW (%.2f of hover)\n",
           c.u.collective_pct, c.u.long_cyclic_pct, c.u.lat_cyclic_pct, c.u.pedal_pct,
           c.body.euler_rad[1] * CORE_RAD_TO_DEG, c.body.euler_rad[0] * CORE_RAD_TO_DEG, c.loads.mr_power_W / 1e3,
           c.loads.mr_power_W / L->mr_power_W);
    CHECK(c.u.collective_pct < h.u.collective_pct);
    CHECK(c.loads.mr_power_W < 0.8 * L->mr_power_W && c.loads.mr_power_W > 0.3 * L->mr_power_W);
    CHECK(fabs(c.body.euler_rad[1] * CORE_RAD_TO_DEG) < 8.0 && fabs(c.body.euler_rad[0] * CORE_RAD_TO_DEG) < 5.0);
    CHECK(c.u.long_cyclic_pct > 15.0 && c.u.long_cyclic_pct < 85.0 && c.u.lat_cyclic_pct > 15.0 &&
          c.u.lat_cyclic_pct < 85.0);
    CHECK(c.u.pedal_pct > 20.0 && c.u.pedal_pct < 80.0);
    hfm_trim_destroy(tr);
    hfm_aircraft_destroy(ac);
}

int main(void)
{
    setvbuf(stdout, NULL, _IOLBF, 0);
    snprintf(tmpdir, sizeof tmpdir, "/tmp/test_hfm_format_XXXXXX");
    if (!mkdtemp(tmpdir))
        return 1;
    test_shipped();
    test_luh25();
    test_checks();
    test_model_error();
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf %s", tmpdir);
    if (system(cmd) != 0)
        fprintf(stderr, "could not remove %s\n", tmpdir);
    return check_done("test_hfm_format");
}
