/* test_ship_motion.c -- the ship's motion in a sea state (sim/ship_motion.c):
 * the sea-state table and the spectra as published, the closed-form RAOs'
 * long-wave limits, the long-record statistics of the sum of sinusoids
 * against the table and the spectral integrals, calm seas, determinism by
 * seed, the landing spot's derivatives, the roll resonance at the ship
 * file's period, the sea surface drawn (sim_ship_motion_elevation) against
 * the motion's own elevation at the moving centre, and refusals of bad
 * input naming the field or key.
 *
 * Significant amplitudes here are single amplitudes, 2 sigma (for a narrow
 * band process the mean of the highest third of the amplitudes); the
 * significant wave height is 4 sigma of the elevation. Records are 3 h of
 * ship time at 2 Hz. */
#include "check.h"
#include "sim.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define REC_DT_S 0.5
#define REC_N 21600 /* 3 h at 2 Hz */
#define PITCH_DOF 1

static core_ship cg47, lpd17, sfs2;

static sim_sea make_sea(int state, double speed_kt, double dir_deg, sim_spectrum spec)
{
    sim_sea s;
    sim_sea_default(&s);
    s.state = state;
    s.ship_speed_mps = speed_kt * CORE_KT_TO_MPS;
    s.wave_dir_rad = dir_deg * CORE_DEG_TO_RAD;
    s.spectrum = spec;
    return s;
}

static double stdev(const double *x, int n)
{
    double mean = 0.0, var = 0.0;
    for (int i = 0; i < n; i++)
        mean += x[i];
    mean /= n;
    for (int i = 0; i < n; i++)
        var += (x[i] - mean) * (x[i] - mean);
    return sqrt(var / n);
}

/* The record of a motion: elevation, heave, pitch, roll. */
typedef struct record {
    double *elev, *heave, *pitch, *roll;
} record;

static void record_take(const sim_ship_motion *m, record *r)
{
    r->elev = malloc(REC_N * sizeof(double));
    r->heave = malloc(REC_N * sizeof(double));
    r->pitch = malloc(REC_N * sizeof(double));
    r->roll = malloc(REC_N * sizeof(double));
    for (int i = 0; i < REC_N; i++) {
        sim_ship_state st;
        CHECK(sim_ship_motion_at(m, i * REC_DT_S, &st) == 0);
        r->elev[i] = st.wave_elev_m;
        r->heave[i] = st.heave_m;
        r->pitch[i] = st.att.theta_rad;
        r->roll[i] = st.att.phi_rad;
    }
}

static void record_free(record *r)
{
    free(r->elev);
    free(r->heave);
    free(r->pitch);
    free(r->roll);
}

/* m0 of each motion: the integral of S(w) RAO(w)^2 over 0..w_max (trapezoid, fine grid). */
static void spectral_m0(const sim_ship_motion *m, double m0[4])
{
    sim_ship_motion_info info;
    sim_ship_motion_get_info(m, &info);
    const int n = 40000;
    double dw = info.omega_max_radps / n;
    memset(m0, 0, 4 * sizeof m0[0]);
    for (int j = 1; j <= n; j++) {
        double w = j * dw, S = sim_ship_motion_spectrum(m, w), h, p, r;
        CHECK(sim_ship_motion_rao(m, w, &h, &p, &r) == 0);
        double wt = j == n ? 0.5 : 1.0;
        m0[0] += wt * S * dw;
        m0[1] += wt * S * h * h * dw;
        m0[2] += wt * S * p * p * dw;
        m0[3] += wt * S * r * r * dw;
    }
}

/* ---------------------------------------------------------------- table */
static void test_table(void)
{
    double hs, tp;
    core_err err = {0};
    /* Bales (1983) Table 1, North Atlantic: state 5 3.25 m, 9.7 s; state 6 5.0 m, 12.4 s */
    CHECK(sim_sea_state_table(5, &hs, &tp, &err) == 0);
    CHECK_NEAR(hs, 3.25, 1e-12);
    CHECK_NEAR(tp, 9.7, 1e-12);
    CHECK(sim_sea_state_table(6, &hs, &tp, &err) == 0);
    CHECK_NEAR(hs, 5.0, 1e-12);
    CHECK_NEAR(tp, 12.4, 1e-12);
    CHECK(sim_sea_state_table(0, &hs, &tp, &err) == 0 && hs == 0.0);
    CHECK(sim_sea_state_table(7, &hs, &tp, &err) < 0 && strstr(err.msg, "expected 0 to 6"));
}

/* --------------------------------------------------------------- spectra */
static void test_spectra(void)
{
    core_err err = {0};
    for (int sp = 0; sp < 2; sp++) {
        sim_sea sea = make_sea(5, 0.0, 0.0, (sim_spectrum)sp);
        sim_ship_motion *m = sim_ship_motion_create(&cg47, &sea, 1, &err);
        CHECK(m != NULL);
        if (!m)
            continue;
        sim_ship_motion_info info;
        sim_ship_motion_get_info(m, &info);
        double m0[4];
        spectral_m0(m, m0);
        /* the zeroth moment is the table's H_s^2 / 16 */
        CHECK_NEAR(4.0 * sqrt(m0[0]), 3.25, 3.25 * 0.002);
        /* the peak at the modal period */
        double wp = 2.0 * CORE_PI / 9.7, best = 0.0, wbest = 0.0;
        for (double w = 0.2; w < 2.0; w += 1e-4) {
            double S = sim_ship_motion_spectrum(m, w);
            if (S > best) {
                best = S;
                wbest = w;
            }
        }
        CHECK_NEAR(wbest, wp, wp * 0.005);
        /* (S1) at its peak, 5/16 H_s^2 / w_p e^(-5/4) (the cut at 8 w_p scales it by 1.0003);
         * JONSWAP's peak is about gamma (1 - 0.287 ln gamma) = 2.17 times that */
        double s1 = 5.0 / 16.0 * 3.25 * 3.25 / wp * exp(-1.25);
        double want = sp == SIM_SPECTRUM_ITTC ? s1 : s1 * 3.3 * (1.0 - 0.287 * log(3.3));
        CHECK_NEAR(sim_ship_motion_spectrum(m, wp), want, want * (sp == SIM_SPECTRUM_ITTC ? 0.001 : 0.05));
        printf("spectrum %s, sea state 5: 4 sqrt(m0) = %.4f m (table 3.25), peak %.4f rad/s (2 pi / 9.7 = %.4f), "
               "S(w_p) = %.4f m^2 s (formula %.4f)\n",
               sp ? "JONSWAP" : "ITTC", 4.0 * sqrt(m0[0]), wbest, wp, sim_ship_motion_spectrum(m, wp), want);
        CHECK(sim_ship_motion_spectrum(m, info.omega_max_radps * 1.01) == 0.0);
        sim_ship_motion_destroy(m);
    }
}

/* ------------------------------------------------------------------ RAOs */
static void test_rao_limits(void)
{
    core_err err = {0};
    /* Long waves (w = 0.05 rad/s, 25 km long), no speed: the ship lies in
     * the surface: heave 1 m/m, pitch the slope k in head seas, roll the
     * slope k in beam seas, and nothing of the other angle. */
    double w = 0.05, k = w * w / CORE_G_MPS2, h, p, r;
    sim_sea head = make_sea(5, 0.0, 0.0, SIM_SPECTRUM_ITTC), beam = make_sea(5, 0.0, 90.0, SIM_SPECTRUM_ITTC);
    sim_ship_motion *mh = sim_ship_motion_create(&cg47, &head, 1, &err);
    sim_ship_motion *mb = sim_ship_motion_create(&cg47, &beam, 1, &err);
    CHECK(mh && mb);
    if (!mh || !mb)
        return;
    CHECK(sim_ship_motion_rao(mh, w, &h, &p, &r) == 0);
    CHECK_NEAR(h, 1.0, 0.01);
    CHECK_NEAR(p / k, 1.0, 0.01);
    CHECK(r < 1e-12);
    CHECK(sim_ship_motion_rao(mb, w, &h, &p, &r) == 0);
    CHECK_NEAR(h, 1.0, 0.01);
    CHECK(p < 1e-12);
    CHECK_NEAR(r / k, 1.0, 0.01);
    /* waves far shorter than the ship move it little */
    CHECK(sim_ship_motion_rao(mh, 3.0, &h, &p, &r) == 0);
    CHECK(h < 0.01 && p < 0.001);
    CHECK(sim_ship_motion_rao(mh, -1.0, &h, &p, &r) < 0);
    sim_ship_motion_destroy(mh);
    sim_ship_motion_destroy(mb);
}

/* ----------------------------------------------- long-record statistics */
/* 4 sigma of the elevation against the table, 2 sigma of each motion
 * against 2 sqrt(integral of S RAO^2), both within 10 %. */
static void check_record(const char *what, const core_ship *ship, const sim_sea *sea, uint64_t seed, int motions)
{
    core_err err = {0};
    sim_ship_motion *m = sim_ship_motion_create(ship, sea, seed, &err);
    CHECK(m != NULL);
    if (!m) {
        fprintf(stderr, "%s\n", err.msg);
        return;
    }
    double hs;
    sim_sea_state_table(sea->state, &hs, NULL, &err);
    record r;
    record_take(m, &r);
    double hs_rec = 4.0 * stdev(r.elev, REC_N);
    CHECK_NEAR(hs_rec / hs, 1.0, 0.10);
    printf("%s: H_s 4 sigma %.3f m, table %.3f m (%+.1f %%)", what, hs_rec, hs, 100.0 * (hs_rec / hs - 1.0));
    if (motions) {
        double m0[4];
        spectral_m0(m, m0);
        const double *rec[3] = {r.heave, r.pitch, r.roll};
        const char *name[3] = {"heave", "pitch", "roll"};
        const char *unit[3] = {"m", "deg", "deg"};
        for (int d = 0; d < 3; d++) {
            double f = d ? CORE_RAD_TO_DEG : 1.0;
            double sig_rec = 2.0 * stdev(rec[d], REC_N) * f, sig_spec = 2.0 * sqrt(m0[d + 1]) * f;
            if (d == PITCH_DOF && fabs(cos(sea->wave_dir_rad)) < 1e-9) {
                CHECK(sig_rec < 1e-9); /* beam seas: no pitch */
                printf("; pitch 2 sigma %.1e deg (beam seas)", sig_rec);
                continue;
            }
            CHECK(sig_spec > 0.0);
            CHECK_NEAR(sig_rec / sig_spec, 1.0, 0.10);
            printf("; %s 2 sigma %.3f %s, spectral %.3f (%+.1f %%)", name[d], sig_rec, unit[d], sig_spec,
                   100.0 * (sig_rec / sig_spec - 1.0));
        }
    }
    printf("\n");
    record_free(&r);
    sim_ship_motion_destroy(m);
}

static void test_long_records(void)
{
    char what[96];
    for (int state = 1; state <= SIM_SEA_MAX_STATE; state++)
        for (int sp = 0; sp < 2; sp++) {
            sim_sea sea = make_sea(state, 10.0, 0.0, (sim_spectrum)sp);
            snprintf(what, sizeof what, "CG-47 sea state %d %s 10 kt head", state, sp ? "JONSWAP" : "ITTC");
            check_record(what, &cg47, &sea, 100u + (uint64_t)state, 0);
        }
    sim_sea a = make_sea(5, 15.0, 30.0, SIM_SPECTRUM_ITTC);
    check_record("CG-47 sea state 5 ITTC 15 kt green 30", &cg47, &a, 7, 1);
    sim_sea b = make_sea(6, 10.0, -135.0, SIM_SPECTRUM_JONSWAP);
    check_record("LPD-17 sea state 6 JONSWAP 10 kt red 135", &lpd17, &b, 8, 1);
    sim_sea c = make_sea(4, 0.0, 90.0, SIM_SPECTRUM_ITTC);
    check_record("LPD-17 sea state 4 ITTC 0 kt green 90", &lpd17, &c, 9, 1);
}

/* ------------------------------------------------------------ calm seas */
static void test_calm(void)
{
    core_err err = {0};
    /* still water, no way on: everything exactly zero, at any time */
    sim_sea sea = make_sea(0, 0.0, 30.0, SIM_SPECTRUM_ITTC);
    sim_ship_motion *m = sim_ship_motion_create(&cg47, &sea, 5, &err);
    CHECK(m != NULL);
    if (!m)
        return;
    core_vec3 bow = core_vec3_make(120.0, 3.0, -5.0);
    for (int i = 0; i < 50; i++) {
        double t = i * 37.3;
        sim_ship_state st;
        sim_ship_point pt;
        CHECK(sim_ship_motion_at(m, t, &st) == 0);
        CHECK(st.pose.pos_E_m.x == 0.0 && st.pose.pos_E_m.y == 0.0 && st.pose.pos_E_m.z == 0.0);
        CHECK(st.att.phi_rad == 0.0 && st.att.theta_rad == 0.0 && st.att.psi_rad == 0.0);
        CHECK(st.vel_E_mps.x == 0.0 && st.vel_E_mps.y == 0.0 && st.vel_E_mps.z == 0.0);
        CHECK(st.omega_S_radps.x == 0.0 && st.omega_S_radps.y == 0.0 && st.omega_S_radps.z == 0.0);
        CHECK(st.heave_m == 0.0 && st.wave_elev_m == 0.0);
        CHECK(sim_ship_motion_point(m, t, bow, &pt) == 0);
        CHECK(pt.vel_E_mps.x == 0.0 && pt.vel_E_mps.y == 0.0 && pt.vel_E_mps.z == 0.0);
        CHECK(pt.acc_E_mps2.x == 0.0 && pt.acc_E_mps2.y == 0.0 && pt.acc_E_mps2.z == 0.0);
        CHECK_NEAR(pt.pos_E_m.x, bow.x, 1e-12);
        CHECK_NEAR(pt.pos_E_m.y, bow.y, 1e-12);
        CHECK_NEAR(pt.pos_E_m.z, bow.z, 1e-12);
    }
    sim_ship_motion_destroy(m);

    /* calm, under way on course 060: level, at exactly U along the course */
    sea.ship_speed_mps = 8.0;
    sea.course_rad = 60.0 * CORE_DEG_TO_RAD;
    m = sim_ship_motion_create(&sfs2, &sea, 5, &err); /* no seakeeping keys: none needed at state 0 */
    CHECK(m != NULL);
    if (!m)
        return;
    for (int i = 0; i < 20; i++) {
        double t = i * 11.0;
        sim_ship_state st;
        CHECK(sim_ship_motion_at(m, t, &st) == 0);
        CHECK(st.att.phi_rad == 0.0 && st.att.theta_rad == 0.0);
        CHECK(st.att.psi_rad == sea.course_rad);
        CHECK(st.vel_E_mps.x == 8.0 * cos(sea.course_rad) && st.vel_E_mps.y == 8.0 * sin(sea.course_rad) &&
              st.vel_E_mps.z == 0.0);
        CHECK(st.omega_S_radps.x == 0.0 && st.omega_S_radps.y == 0.0 && st.omega_S_radps.z == 0.0);
        CHECK_NEAR(st.pose.pos_E_m.x, 8.0 * t * cos(sea.course_rad), 1e-9);
        CHECK_NEAR(st.pose.pos_E_m.y, 8.0 * t * sin(sea.course_rad), 1e-9);
        CHECK(st.pose.pos_E_m.z == 0.0);
    }
    sim_ship_motion_destroy(m);
}

/* ---------------------------------------------------------- determinism */
static void test_seeds(void)
{
    core_err err = {0};
    sim_sea sea = make_sea(5, 12.0, 45.0, SIM_SPECTRUM_JONSWAP);
    sim_ship_motion *a = sim_ship_motion_create(&cg47, &sea, 42, &err);
    sim_ship_motion *b = sim_ship_motion_create(&cg47, &sea, 43, &err);
    sim_ship_motion *a2 = sim_ship_motion_create(&cg47, &sea, 42, &err); /* made after another seed's */
    CHECK(a && b && a2);
    if (!a || !b || !a2)
        return;
    const int n = 7200; /* 1 h at 2 Hz */
    int same = 1;
    double sab = 0.0, saa = 0.0, sbb = 0.0;
    for (int i = 0; i < n; i++) {
        double t = i * REC_DT_S;
        sim_ship_state sa, sb, sa2;
        sim_ship_point pa, pa2;
        /* evaluate out of order too: a pure function of t */
        sim_ship_motion_at(a, t, &sa);
        sim_ship_motion_at(b, t, &sb);
        sim_ship_motion_at(a2, (n - 1 - i) * REC_DT_S, &sa2);
        sim_ship_motion_at(a2, t, &sa2);
        sim_ship_motion_point(a, t, core_vec3_make(0, 0, 0), &pa);
        sim_ship_motion_point(a2, t, core_vec3_make(0, 0, 0), &pa2);
        if (memcmp(&sa, &sa2, sizeof sa) != 0 || memcmp(&pa, &pa2, sizeof pa) != 0)
            same = 0;
        sab += sa.att.phi_rad * sb.att.phi_rad;
        saa += sa.att.phi_rad * sa.att.phi_rad;
        sbb += sb.att.phi_rad * sb.att.phi_rad;
    }
    CHECK(same);
    double corr = sab / sqrt(saa * sbb);
    CHECK(fabs(corr) < 0.3);
    printf("seeds: 42 twice bit for bit %s; roll of seeds 42 and 43 correlate %.3f\n", same ? "yes" : "NO", corr);
    sim_ship_motion_destroy(a);
    sim_ship_motion_destroy(b);
    sim_ship_motion_destroy(a2);
}

/* ------------------------------------------- phasors at the loop's step */
/* A motion with the loop's step set (sim_ship_motion_set_step) against the
 * direct sum: bit for bit at every re-anchoring step (every 256) and at
 * times off the step grid, whatever was asked before; in between within
 * the rotations' rounding bound. A wave's phasor takes at most 255
 * rotations from its anchor, each rounding it by at most 4 ulps (the
 * complex product and the rotation's own rounding; a rotation keeps the
 * error's size): |d| <= 255 * 4 * sqrt(2) * 2^-53 per unit amplitude. Over
 * N waves sum_i (|c_i| + |s_i|) <= 2 sqrt(N) sigma (sigma^2 = sum (c_i^2 +
 * s_i^2) / 2), so a motion is off by at most 2 sqrt(N) sigma |d|, its rate
 * by w_max times that; checked an hour into the record, where w_e t is
 * large. */
static void test_phasors(void)
{
    core_err err = {0};
    sim_sea sea = make_sea(6, 20.0, 30.0, SIM_SPECTRUM_ITTC);
    const double h = 0.005;
    sim_ship_motion *a = sim_ship_motion_create(&cg47, &sea, 11, &err); /* direct */
    sim_ship_motion *b = sim_ship_motion_create(&cg47, &sea, 11, &err); /* in order */
    sim_ship_motion *c = sim_ship_motion_create(&cg47, &sea, 11, &err); /* scrambled */
    CHECK(a && b && c);
    if (!a || !b || !c)
        return;
    CHECK(sim_ship_motion_set_step(b, h, &err) == 0 && sim_ship_motion_set_step(c, h, &err) == 0);
    CHECK(sim_ship_motion_set_step(b, -1.0, &err) < 0 && strstr(err.msg, "expected 0 (none)"));
    CHECK(sim_ship_motion_set_step(b, h, &err) == 0);
    sim_ship_motion_info info;
    sim_ship_motion_get_info(a, &info);
    const long long k_start = 720000, nk = 4 * 256 + 77; /* 1 h at 200 Hz, then 5.4 s */
    double sig[3] = {0, 0, 0}, dmax[3] = {0, 0, 0}, dvmax[3] = {0, 0, 0}, vsig[3] = {0, 0, 0};
    int anchors_same = 1, off_grid_same = 1, scrambled_same = 1, anchors = 0;
    sim_ship_state *sb = malloc((size_t)nk * sizeof *sb);
    for (long long i = 0; i < nk; i++) {
        long long k = k_start + i;
        double t = (double)k * h;
        sim_ship_state sa;
        sim_ship_frame fa, fb;
        /* b: the frame first, as the flight asks, then the state (the
         * sums kept for the step must not lend the frame's missing rates) */
        sim_ship_motion_frame_fn(b, t, &fb);
        CHECK(sim_ship_motion_at(a, t, &sa) == 0 && sim_ship_motion_at(b, t, &sb[i]) == 0);
        sim_ship_motion_frame_fn(a, t, &fa);
        double x[3] = {sa.heave_m, sa.att.theta_rad, sa.att.phi_rad};
        double y[3] = {sb[i].heave_m, sb[i].att.theta_rad, sb[i].att.phi_rad};
        double xv[3] = {sa.heave_rate_mps, sa.omega_S_radps.x, sa.omega_S_radps.y};
        double yv[3] = {sb[i].heave_rate_mps, sb[i].omega_S_radps.x, sb[i].omega_S_radps.y};
        for (int d = 0; d < 3; d++) {
            sig[d] += x[d] * x[d];
            vsig[d] += xv[d] * xv[d];
            dmax[d] = fmax(dmax[d], fabs(x[d] - y[d]));
            dvmax[d] = fmax(dvmax[d], fabs(xv[d] - yv[d]));
        }
        if (k % 256 == 0) {
            anchors++;
            if (memcmp(&sa, &sb[i], sizeof sa) != 0 || memcmp(&fa, &fb, sizeof fa) != 0)
                anchors_same = 0;
        }
        /* between the steps: the direct sum, bit for bit */
        sim_ship_state ha, hb;
        sim_ship_motion_at(a, t + 0.5 * h, &ha);
        sim_ship_motion_at(b, t + 0.5 * h, &hb);
        if (memcmp(&ha, &hb, sizeof ha) != 0)
            off_grid_same = 0;
    }
    /* the same steps asked backwards and in jumps: the same bits */
    for (long long j = 0; j < nk; j++) {
        long long i = (j * 389) % nk, k = k_start + i;
        sim_ship_state sc;
        sim_ship_motion_at(c, (double)k * h, &sc);
        if (memcmp(&sc, &sb[i], sizeof sc) != 0)
            scrambled_same = 0;
    }
    /* as the loop with the gear asks: the frame a step ahead, then the
     * state at the step (the walk's previous phasors serve it): the same
     * bits, and no walk from the anchor (bench: disim fly with --log) */
    int back_same = 1;
    sim_ship_motion *d = sim_ship_motion_create(&cg47, &sea, 11, &err);
    CHECK(d && sim_ship_motion_set_step(d, h, &err) == 0);
    for (long long i = 0; d && i + 1 < nk; i++) {
        long long k = k_start + i;
        sim_ship_frame fd;
        sim_ship_state sd;
        sim_ship_motion_frame_fn(d, (double)(k + 1) * h, &fd);
        sim_ship_motion_at(d, (double)k * h, &sd);
        if (memcmp(&sd, &sb[i], sizeof sd) != 0)
            back_same = 0;
    }
    sim_ship_motion_destroy(d);
    CHECK(back_same);
    printf("phasors: a step back after a frame ahead: %s\n", back_same ? "the same bits" : "DIFFER");
    free(sb);
    const double eps = 0x1.0p-53, dwave = 255.0 * 4.0 * sqrt(2.0) * eps;
    const double kbound = 2.0 * sqrt((double)info.n_waves) * dwave;
    const char *name[3] = {"heave", "pitch", "roll"};
    for (int d = 0; d < 3; d++) {
        double s = sqrt(sig[d] / (double)nk), sv = sqrt(vsig[d] / (double)nk);
        /* sigma of the record stands for the spectral one (a 2x margin) */
        CHECK(dmax[d] <= 2.0 * kbound * s);
        CHECK(dvmax[d] <= 2.0 * kbound * fmax(sv, info.omega_max_radps * s));
        printf("phasors: %s off the direct sum by %.2e sigma at most (bound %.2e), its rate %.2e\n", name[d],
               dmax[d] / s, 2.0 * kbound, dvmax[d] / sv);
    }
    CHECK(anchors == 4 && anchors_same); /* 720128, 720384, 720640, 720896 */
    CHECK(off_grid_same);
    CHECK(scrambled_same);
    printf("phasors: %d anchors bit for bit %s; off the grid %s; asked out of order %s\n", anchors,
           anchors_same ? "yes" : "NO", off_grid_same ? "yes" : "NO", scrambled_same ? "the same bits" : "DIFFER");
    sim_ship_motion_destroy(a);
    sim_ship_motion_destroy(b);
    sim_ship_motion_destroy(c);
}

/* ------------------------------------------------ derivatives of a point */
static double vdist(core_vec3 a, core_vec3 b)
{
    return core_vec3_norm(core_vec3_sub(a, b));
}

static void test_derivatives(void)
{
    core_err err = {0};
    sim_sea sea = make_sea(6, 10.0, 60.0, SIM_SPECTRUM_ITTC);
    sea.course_rad = 200.0 * CORE_DEG_TO_RAD;
    sim_ship_motion *m = sim_ship_motion_create(&lpd17, &sea, 3, &err);
    CHECK(m != NULL);
    if (!m)
        return;
    const core_vec3 pts[2] = {core_vec3_make(0, 0, 0), core_vec3_make(150.0, 8.0, -10.0)}; /* spot, bow */
    const double h = 1e-3;
    double ev = 0.0, ea = 0.0, ew = 0.0, vmax = 0.0, amax = 0.0, wmax = 0.0;
    for (int i = 0; i < 40; i++) {
        double t = 17.0 + i * 91.7;
        for (int k = 0; k < 2; k++) {
            sim_ship_point p0, pm, pp;
            sim_ship_motion_point(m, t, pts[k], &p0);
            sim_ship_motion_point(m, t - h, pts[k], &pm);
            sim_ship_motion_point(m, t + h, pts[k], &pp);
            core_vec3 fd_v = core_vec3_scale(core_vec3_sub(pp.pos_E_m, pm.pos_E_m), 0.5 / h);
            core_vec3 fd_a = core_vec3_scale(core_vec3_sub(pp.vel_E_mps, pm.vel_E_mps), 0.5 / h);
            ev = fmax(ev, vdist(fd_v, p0.vel_E_mps));
            ea = fmax(ea, vdist(fd_a, p0.acc_E_mps2));
            vmax = fmax(vmax, fabs(p0.vel_E_mps.z));
            amax = fmax(amax, core_vec3_norm(p0.acc_E_mps2));
        }
        /* the state's pose and velocity are the spot's; its rate the attitude's derivative */
        sim_ship_state st, sm, sp;
        sim_ship_point spot;
        sim_ship_motion_at(m, t, &st);
        sim_ship_motion_point(m, t, pts[0], &spot);
        CHECK(vdist(st.pose.pos_E_m, spot.pos_E_m) == 0.0 && vdist(st.vel_E_mps, spot.vel_E_mps) == 0.0);
        sim_ship_motion_at(m, t - h, &sm);
        sim_ship_motion_at(m, t + h, &sp);
        core_mat3 C = core_mat3_from_euler(st.att), Cm = core_mat3_from_euler(sm.att),
                  Cp = core_mat3_from_euler(sp.att);
        double W[3][3]; /* C^T dC/dt = [w x] */
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++) {
                W[r][c] = 0.0;
                for (int j = 0; j < 3; j++)
                    W[r][c] += C.m[j][r] * (Cp.m[j][c] - Cm.m[j][c]) * 0.5 / h;
            }
        core_vec3 w_fd = core_vec3_make(W[2][1], W[0][2], W[1][0]);
        ew = fmax(ew, vdist(w_fd, st.omega_S_radps));
        wmax = fmax(wmax, core_vec3_norm(st.omega_S_radps));
    }
    CHECK(vmax > 0.1 && amax > 0.1 && wmax > 0.005); /* the sea moves the ship */
    CHECK(ev < 1e-5);
    CHECK(ea < 1e-5);
    CHECK(ew < 1e-7);
    printf("LPD-17 sea state 6: |v - dx/dt| <= %.1e m/s (vertical speeds to %.2f m/s), |a - dv/dt| <= %.1e m/s^2 "
           "(to %.2f), |w - C^T dC/dt| <= %.1e rad/s (to %.3f)\n",
           ev, vmax, ea, amax, ew, wmax);
    sim_ship_motion_destroy(m);
}

/* ---------------------------------------------------------------- phases */
static double corr(const double *a, const double *b, int n)
{
    double ab = 0.0, aa = 0.0, bb = 0.0;
    for (int i = 0; i < n; i++) {
        ab += a[i] * b[i];
        aa += a[i] * a[i];
        bb += b[i] * b[i];
    }
    return ab / sqrt(aa * bb);
}

/* The senses of the motions against the wave at the centre, at rest in
 * waves long against a small ship and its resonances (CG-47 cut to 40 m x
 * 8 m, 2 m draft, roll period 2 s; sea state 6): heave rises with the
 * elevation; in head seas the bow rises while the elevation at the centre
 * rises (the crest is ahead); in beam seas from starboard the starboard
 * side rises first (roll to port, negative), from port the other way. */
static void test_phases(void)
{
    core_err err = {0};
    core_ship ship = cg47;
    ship.length_m = 40.0;
    ship.beam_m = 8.0;
    ship.hull_draft_m = 2.0;
    ship.roll_period_s = 2.0;
    const double dirs[3] = {0.0, 90.0, -90.0};
    double c_heave = 0.0, c_pitch = 0.0, c_roll[3] = {0.0, 0.0, 0.0};
    for (int k = 0; k < 3; k++) {
        sim_sea sea = make_sea(6, 0.0, dirs[k], SIM_SPECTRUM_ITTC);
        sim_ship_motion *m = sim_ship_motion_create(&ship, &sea, 21, &err);
        CHECK(m != NULL);
        if (!m)
            return;
        record r;
        record_take(m, &r);
        double *rate = malloc(REC_N * sizeof *rate);
        for (int i = 1; i < REC_N - 1; i++)
            rate[i] = (r.elev[i + 1] - r.elev[i - 1]) / (2.0 * REC_DT_S);
        if (k == 0) {
            c_heave = corr(r.heave, r.elev, REC_N);
            c_pitch = corr(r.pitch + 1, rate + 1, REC_N - 2);
        }
        c_roll[k] = corr(r.roll + 1, rate + 1, REC_N - 2);
        free(rate);
        record_free(&r);
        sim_ship_motion_destroy(m);
    }
    CHECK(c_heave > 0.5);
    CHECK(c_pitch > 0.5);
    CHECK(c_roll[1] < -0.5);
    CHECK(c_roll[2] > 0.5);
    printf("40 m ship, sea state 6 at rest: heave with elevation %.2f; head seas pitch with elevation rate %.2f; "
           "beam seas roll with elevation rate %.2f (from starboard), %.2f (from port)\n",
           c_heave, c_pitch, c_roll[1], c_roll[2]);
}

/* ------------------------------------------------------- roll resonance */
/* Welch estimates (Hann, 2048-sample segments, half overlap) of the
 * spectra of x and y (y may be NULL) at w: sums of the segments'
 * periodograms, in arbitrary units. */
static void welch_at(const double *x, const double *y, double w, double *sxx, double *syy)
{
    const int ns = 2048;
    *sxx = 0.0;
    *syy = 0.0;
    double c1 = cos(w * REC_DT_S), s1 = sin(w * REC_DT_S);
    for (int s0 = 0; s0 + ns <= REC_N; s0 += ns / 2) {
        double xr = 0.0, xi = 0.0, yr = 0.0, yi = 0.0, pc = 1.0, ps = 0.0;
        for (int i = 0; i < ns; i++) {
            double win = 0.5 - 0.5 * cos(2.0 * CORE_PI * i / (ns - 1));
            xr += win * x[s0 + i] * pc;
            xi += win * x[s0 + i] * ps;
            if (y) {
                yr += win * y[s0 + i] * pc;
                yi += win * y[s0 + i] * ps;
            }
            double t = pc * c1 - ps * s1; /* the phasor e^(i w t) by rotation */
            ps = pc * s1 + ps * c1;
            pc = t;
        }
        *sxx += xr * xr + xi * xi;
        *syy += yr * yr + yi * yi;
    }
}

/* The frequency in [w0, w1] (steps of 0.001 rad/s) where the spectrum of
 * x peaks, or with y where the ratio of y's spectrum to x's does (where
 * x's is above 1e-3 of its peak): with x the elevation and y the roll,
 * the roll RAO squared as a record shows it. */
static double spectrum_peak(const double *x, const double *y, double w0, double w1)
{
    const int nw = (int)((w1 - w0) / 0.001) + 1;
    double *sx = calloc((size_t)nw, sizeof *sx), *sy = calloc((size_t)nw, sizeof *sy);
    double smax = 0.0, best = 0.0, wbest = 0.0;
    for (int j = 0; j < nw; j++) {
        welch_at(x, y, w0 + j * 0.001, &sx[j], &sy[j]);
        smax = fmax(smax, sx[j]);
    }
    for (int j = 0; j < nw; j++) {
        double v = y ? (sx[j] > 1e-3 * smax ? sy[j] / sx[j] : 0.0) : sx[j];
        if (v > best) {
            best = v;
            wbest = w0 + j * 0.001;
        }
    }
    free(sx);
    free(sy);
    return wbest;
}

/* The elevation met at the moving centre peaks at the encounter frequency
 * of the modal one, w_p + w_p^2 U / g in head seas (JONSWAP's sharp peak,
 * CG-47 at 20 kt, sea state 5), and at w_p itself in beam seas. */
static void test_encounter(void)
{
    core_err err = {0};
    const double dirs[2] = {0.0, 90.0}, U = 20.0 * CORE_KT_TO_MPS, wp = 2.0 * CORE_PI / 9.7;
    for (int k = 0; k < 2; k++) {
        sim_sea sea = make_sea(5, 20.0, dirs[k], SIM_SPECTRUM_JONSWAP);
        sim_ship_motion *m = sim_ship_motion_create(&cg47, &sea, 31, &err);
        CHECK(m != NULL);
        if (!m)
            return;
        record r;
        record_take(m, &r);
        double want = wp + wp * wp * U * cos(sea.wave_dir_rad) / CORE_G_MPS2, got = spectrum_peak(r.elev, NULL, 0.3, 2.0);
        CHECK_NEAR(got / want, 1.0, 0.03);
        printf("CG-47 at 20 kt, %s seas: the elevation met peaks at %.3f rad/s (encounter of w_p: %.3f, %+.1f %%)\n",
               k ? "beam" : "head", got, want, 100.0 * (got / want - 1.0));
        record_free(&r);
        sim_ship_motion_destroy(m);
    }
}

static void test_roll_resonance(void)
{
    core_err err = {0};
    /* CG-47 in beam seas at rest, sea state 5: the roll's peak is at the
     * ship file's roll_period_s (11 s), and follows it when it changes */
    const double periods[2] = {cg47.roll_period_s, 8.0};
    for (int k = 0; k < 2; k++) {
        core_ship ship = cg47;
        ship.roll_period_s = periods[k];
        sim_sea sea = make_sea(5, 0.0, 90.0, SIM_SPECTRUM_ITTC);
        sim_ship_motion *m = sim_ship_motion_create(&ship, &sea, 11, &err);
        CHECK(m != NULL);
        if (!m)
            return;
        record r;
        record_take(m, &r);
        double wn = 2.0 * CORE_PI / periods[k], wpk = spectrum_peak(r.elev, r.roll, 0.3, 1.2);
        CHECK_NEAR(wpk / wn, 1.0, 0.03);
        printf("CG-47 roll_period_s %.1f s, sea state 5 beam seas: roll/elevation spectrum peaks at %.3f rad/s "
               "(%.2f s; 2 pi / T_roll = %.3f rad/s, %+.1f %%)\n",
               periods[k], wpk, 2.0 * CORE_PI / wpk, wn, 100.0 * (wpk / wn - 1.0));
        record_free(&r);
        sim_ship_motion_destroy(m);
    }
}

/* ------------------------------------------------------------ bad input */
static void expect_refused(const core_ship *ship, const sim_sea *sea, const char *a, const char *b)
{
    core_err err = {0};
    sim_ship_motion *m = sim_ship_motion_create(ship, sea, 1, &err);
    CHECK(m == NULL);
    CHECK(strstr(err.msg, a) != NULL);
    CHECK(strstr(err.msg, b) != NULL);
    if (m || !strstr(err.msg, a) || !strstr(err.msg, b))
        fprintf(stderr, "expected '%s' ... '%s', got: %s\n", a, b, err.msg);
    sim_ship_motion_destroy(m);
}

static void test_refusals(void)
{
    sim_sea sea = make_sea(3, 10.0, 0.0, SIM_SPECTRUM_ITTC);
    sim_sea bad = sea;
    bad.state = 7;
    expect_refused(&cg47, &bad, "sea state = 7", "expected 0 to 6");
    bad.state = -1;
    expect_refused(&cg47, &bad, "sea state = -1", "expected 0 to 6");
    bad = sea;
    bad.ship_speed_mps = -2.0;
    expect_refused(&cg47, &bad, "ship_speed_mps = -2", "not negative");
    bad.ship_speed_mps = NAN;
    expect_refused(&cg47, &bad, "ship_speed_mps = nan", "expected 0 to");
    bad = sea;
    bad.wave_dir_rad = INFINITY;
    expect_refused(&cg47, &bad, "wave_dir_rad", "finite");
    bad = sea;
    bad.spectrum = (sim_spectrum)5;
    expect_refused(&cg47, &bad, "spectrum = 5", "JONSWAP");
    bad = sea;
    bad.n_waves = SIM_SEA_MAX_WAVES + 1;
    expect_refused(&cg47, &bad, "n_waves = 4097", "expected 0");
    /* a ship without seakeeping keys at a sea state: the key is named */
    expect_refused(&sfs2, &sea, "ship SFS2: [ship] block_coefficient missing", "sea state 3");
    core_ship ship = cg47;
    ship.roll_damping_ratio = 0.0;
    expect_refused(&ship, &sea, "[ship] roll_damping_ratio missing", "CG-47");

    /* the ship loader: the values, the default hull draft, a partial set refused */
    CHECK_NEAR(cg47.block_coefficient, 0.51, 1e-12);
    CHECK_NEAR(cg47.hull_draft_m, 6.5, 1e-12);
    CHECK_NEAR(cg47.roll_period_s, 11.0, 1e-12);
    CHECK_NEAR(lpd17.hull_draft_m, lpd17.draft_m, 1e-12);
    CHECK(sfs2.block_coefficient == 0.0 && sfs2.roll_period_s == 0.0);
    core_ship partial;
    core_err err = {0};
    CHECK(core_ship_load("tests/sim/data/ship_partial_seakeeping.ini", &partial, &err) < 0);
    CHECK(strstr(err.msg, "ship_partial_seakeeping.ini:12: [ship] roll_period_s given without block_coefficient"));
    if (!strstr(err.msg, "given without block_coefficient"))
        fprintf(stderr, "got: %s\n", err.msg);

    /* a time that is not finite */
    sim_ship_motion *m = sim_ship_motion_create(&cg47, &sea, 1, &err);
    sim_ship_state st;
    CHECK(m && sim_ship_motion_at(m, NAN, &st) < 0);
    sim_ship_motion_destroy(m);
}

/* The pieces a flight gets: the frame callback agrees with the state. */
static void test_frame_fn(void)
{
    core_err err = {0};
    sim_sea sea = make_sea(5, 15.0, 30.0, SIM_SPECTRUM_ITTC);
    sim_ship_motion *m = sim_ship_motion_create(&cg47, &sea, 2, &err);
    CHECK(m != NULL);
    if (!m)
        return;
    sim_ship_frame fr;
    sim_ship_state st;
    CHECK(sim_ship_motion_frame_fn(m, 123.4, &fr) == 0);
    CHECK(sim_ship_motion_at(m, 123.4, &st) == 0);
    core_mat3 C = core_mat3_from_euler(st.att);
    CHECK(fr.origin_E_m[0] == st.pose.pos_E_m.x && fr.origin_E_m[2] == st.pose.pos_E_m.z);
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            CHECK(fr.C_ES[3 * r + c] == C.m[r][c]);
    CHECK_NEAR(fr.mean_vel_E_mps[0], 15.0 * CORE_KT_TO_MPS, 1e-12);
    /* the quaternion rotates as the matrix does */
    core_vec3 v = core_vec3_make(1.0, 2.0, 3.0);
    CHECK(vdist(core_quat_rotate(st.pose.q_EF, v), core_mat3_mul_vec(C, v)) < 1e-12);
    sim_ship_motion_destroy(m);
}

/* The sea surface of sim_ship_motion_elevation: at the motion centre's
 * moving position it is the state's wave_elev_m (the direct sum, (W1))
 * within 1e-3 H_s, over 60 s at 12 m/s (the centre crosses 700 m of the
 * surface, so the spatial phase k u . (p - c0) is checked, not only the
 * time); the same along each crest (long-crested); calm is flat; a
 * non-finite point or time is refused. */
static void test_elevation(void)
{
    double dirs[3] = {0.0, 60.0, 150.0};
    for (int d = 0; d < 3; d++) {
        sim_sea sea = make_sea(5, 23.3, dirs[d], SIM_SPECTRUM_ITTC);
        sea.course_rad = 0.7;
        core_err err = {0};
        sim_ship_motion *m = sim_ship_motion_create(&cg47, &sea, 42, &err);
        CHECK(m != NULL);
        if (!m)
            continue;
        sim_ship_motion_info info;
        sim_ship_motion_get_info(m, &info);
        core_euler course = {0.0, 0.0, sea.course_rad};
        core_vec3 c0 = core_mat3_mul_vec(core_mat3_from_euler(course),
                                         core_vec3_make(info.centre_S_m[0], info.centre_S_m[1], info.centre_S_m[2]));
        double worst = 0.0, worst_crest = 0.0;
        for (int k = 0; k <= 120; k++) {
            double t = 0.5 * k;
            sim_ship_state st;
            CHECK(sim_ship_motion_at(m, t, &st) == 0);
            /* the centre now, and two points 40 m and 300 m along the crest */
            double a = sea.course_rad + sea.wave_dir_rad, px = -sin(a), py = cos(a);
            double x0 = c0.x + sea.ship_speed_mps * t * cos(sea.course_rad);
            double y0 = c0.y + sea.ship_speed_mps * t * sin(sea.course_rad);
            /* and one 123.4 m (plus a fraction of t) down-wave, the lowest s: the samples start
             * there, so the others fall between samples and the interpolation is checked */
            double off = 123.4 + 0.0137 * k;
            double x[4] = {x0, x0 + 40.0 * px, x0 - 300.0 * px, x0 - off * cos(a)};
            double y[4] = {y0, y0 + 40.0 * py, y0 - 300.0 * py, y0 - off * sin(a)};
            double eta[4];
            CHECK(sim_ship_motion_elevation(m, t, 4, x, y, eta) == 0);
            worst = fmax(worst, fabs(eta[0] - st.wave_elev_m));
            worst_crest = fmax(worst_crest, fmax(fabs(eta[1] - eta[0]), fabs(eta[2] - eta[0])));
        }
        printf("elevation, wave dir %3.0f deg: the surface at the centre off its elevation by %.2e m, along a "
               "crest by %.2e m (H_s %.2f m; tolerance 1e-3 H_s)\n",
               dirs[d], worst, worst_crest, info.hs_m);
        CHECK(worst < 1e-3 * info.hs_m);
        CHECK(worst_crest < 1e-3 * info.hs_m);
        double xb[1] = {NAN}, yb[1] = {0.0}, eb[1];
        CHECK(sim_ship_motion_elevation(m, 0.0, 1, xb, yb, eb) == -1);
        CHECK(sim_ship_motion_elevation(m, NAN, 1, yb, yb, eb) == -1);
        sim_ship_motion_destroy(m);
    }
    sim_sea calm = make_sea(0, 10.0, 0.0, SIM_SPECTRUM_ITTC);
    core_err err = {0};
    sim_ship_motion *m = sim_ship_motion_create(&cg47, &calm, 1, &err);
    double x[2] = {0.0, 100.0}, y[2] = {5.0, -50.0}, eta[2] = {1.0, 1.0};
    CHECK(m && sim_ship_motion_elevation(m, 3.0, 2, x, y, eta) == 0 && eta[0] == 0.0 && eta[1] == 0.0);
    sim_ship_motion_destroy(m);
}

int main(void)
{
    core_err err = {0};
    if (core_ship_load("scenarios/ships/cg47.ini", &cg47, &err) || core_ship_load("scenarios/ships/lpd17.ini", &lpd17, &err) ||
        core_ship_load("scenarios/ships/sfs2.ini", &sfs2, &err)) {
        fprintf(stderr, "%s\n", err.msg);
        return 1;
    }
    test_table();
    test_spectra();
    test_rao_limits();
    test_calm();
    test_seeds();
    test_phasors();
    test_derivatives();
    test_frame_fn();
    test_elevation();
    test_refusals();
    test_long_records();
    test_phases();
    test_encounter();
    test_roll_resonance();
    return check_done("test_ship_motion");
}
