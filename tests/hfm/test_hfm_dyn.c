/* test_hfm_dyn.c -- hfm dynamics: linearisation and eigenvalues at
 * hover and 80 kt, consistency of trim and time simulation (a trimmed state
 * flown open loop for 10 s with ARKODE at 200 Hz drifts less than 0.5 m/s
 * and 0.5 deg), CVODE against ARKODE, and the disk loading export. */
#include "check.h"
#include "hfm.h"

#include <stdio.h>
#include <string.h>

#define UH60 "scenarios/aircraft/uh60a.ini"

static void trim_at(hfm_trim *tr, double kt, hfm_trim_cond *cd, hfm_trim_result *r)
{
    memset(cd, 0, sizeof *cd);
    cd->kind = HFM_TRIM_FORWARD;
    cd->airspeed_mps = kt * CORE_KT_TO_MPS;
    CHECK(hfm_trim_solve(tr, cd, NULL, r) == 0);
}

static void test_linear(hfm_trim *tr, double kt)
{
    hfm_trim_cond cd;
    hfm_trim_result r;
    trim_at(tr, kt, &cd, &r);
    hfm_linear lin;
    CHECK(hfm_linearise(tr, &cd, &r, &lin) == 0);
    printf("eigenvalues at %.0f kt:\n", kt);
    int roll = 0, heave = 0;
    for (int i = 0; i < HFM_LIN_NX; i++) {
        printf("  %9.4f %+9.4fi  %s\n", lin.eig_re[i], lin.eig_im[i], lin.mode[i]);
        CHECK(isfinite(lin.eig_re[i]) && isfinite(lin.eig_im[i]));
        if (!strcmp(lin.mode[i], "roll subsidence") && lin.eig_re[i] < -1.0)
            roll = 1;
        if (!strncmp(lin.mode[i], "heave", 5) && lin.eig_re[i] < -0.1)
            heave = 1;
    }
    CHECK(roll);
    if (kt < 1.0)
        CHECK(heave);
    /* control derivatives (percent): collective up -> climb force (w' < 0);
     * longitudinal toward aft -> nose up; lateral right -> roll right;
     * right pedal on a UH-60A (less tail-rotor pitch) -> nose right */
    const int nu = HFM_LIN_NU;
    CHECK(lin.B[2 * nu + 0] < 0);
    CHECK(lin.B[4 * nu + 1] > 0);
    CHECK(lin.B[3 * nu + 2] > 0);
    CHECK(lin.B[5 * nu + 3] > 0);
    /* speed stability at 80 kt: a speed increase pitches the nose up (M_u > 0) */
    if (kt > 1.0)
        CHECK(lin.A[4 * HFM_LIN_NX + 0] > 0);
}

static double drift(hfm_tsim *ts, const hfm_trim_result *r, double T, double *dang_deg)
{
    CHECK(hfm_tsim_init(ts, 0.0, &r->body, &r->u, &r->rotor) == 0);
    double dv = 0.0, da = 0.0;
    for (int k = 1; k <= 20; k++) {
        CHECK(hfm_tsim_advance(ts, T * k / 20.0) == 0);
        hfm_body b;
        hfm_tsim_body(ts, &b);
        double v = 0.0;
        for (int i = 0; i < 3; i++)
            v += pow(b.vel_B_mps[i] - r->body.vel_B_mps[i], 2);
        dv = isfinite(v) ? fmax(dv, sqrt(v)) : NAN;
        for (int i = 0; i < 2; i++)
            da = isfinite(b.euler_rad[i]) ? fmax(da, fabs(b.euler_rad[i] - r->body.euler_rad[i]) * CORE_RAD_TO_DEG) : NAN;
        if (!isfinite(dv) || !isfinite(da))
            break;
    }
    *dang_deg = isfinite(da) ? da : 1e9;
    return isfinite(dv) ? dv : 1e9;
}

static void test_tsim(const hfm_aircraft *ac, hfm_trim *tr, double kt)
{
    hfm_trim_cond cd;
    hfm_trim_result r;
    trim_at(tr, kt, &cd, &r);
    hfm_air_uniform still = {{0, 0, 0}};
    hfm_air air = {hfm_air_uniform_fn, &still, NULL};
    hfm_tsim *ts = hfm_tsim_create(ac, &air, HFM_TSIM_ARKODE_FIXED, 0.005, 0.0, NULL);
    CHECK(ts != NULL);
    if (!ts)
        return;
    double da, dv = drift(ts, &r, 10.0, &da);
    printf("ARKODE 200 Hz, %.0f kt, 10 s open loop: velocity drift %.3f m/s, attitude drift "
           "%.3f deg (%ld evaluations)\n",
           kt, dv, da, hfm_tsim_rhs_evals(ts));
    CHECK(dv < 0.5);
    CHECK(da < 0.5);
    /* heading: the psi drift is the yaw equation's */
    hfm_body b;
    hfm_tsim_body(ts, &b);
    printf("  heading change %.3f deg\n", (b.euler_rad[2] - r.body.euler_rad[2]) * CORE_RAD_TO_DEG);
    CHECK(fabs(b.euler_rad[2] - r.body.euler_rad[2]) * CORE_RAD_TO_DEG < 0.5);
    /* CVODE reference over 2 s agrees with ARKODE */
    hfm_body ba, bc;
    CHECK(hfm_tsim_init(ts, 0.0, &r.body, &r.u, &r.rotor) == 0);
    CHECK(hfm_tsim_advance(ts, 2.0) == 0);
    hfm_tsim_body(ts, &ba);
    hfm_tsim *tc = hfm_tsim_create(ac, &air, HFM_TSIM_CVODE, 0.0, 1e-7, NULL);
    CHECK(tc != NULL);
    if (tc) {
        CHECK(hfm_tsim_init(tc, 0.0, &r.body, &r.u, &r.rotor) == 0);
        CHECK(hfm_tsim_advance(tc, 2.0) == 0);
        hfm_tsim_body(tc, &bc);
        double e = 0;
        for (int i = 0; i < 3; i++)
            e = fmax(e, fabs(ba.vel_B_mps[i] - bc.vel_B_mps[i]));
        printf("  ARKODE vs CVODE after 2 s: max velocity difference %.4f m/s\n", e);
        CHECK(e < 0.05);
    }
    hfm_tsim_destroy(tc);
    hfm_tsim_destroy(ts);
}

/* The multiblade coordinates of the time model are an exact change of
 * variables: at a trim (harmonic flapping balanced), each blade's flap
 * acceleration from its own flap equation must equal the second derivative
 * of the trimmed flapping at its azimuth, i.e. the coordinates' second
 * derivatives are those of the trimmed harmonics, at any rotor azimuth.
 * Checked through the right-hand side at the initial state: for 4 blades
 * the coordinate accelerations must be those of b0 + b1c cos + b1s sin
 * (constant: zero) plus the 2/rev part in the differential coordinate. */
static void test_mbc(const hfm_aircraft *ac, hfm_trim *tr)
{
    hfm_trim_cond cd;
    hfm_trim_result r;
    trim_at(tr, 100.0, &cd, &r);
    hfm_air_uniform still = {{0, 0, 0}};
    hfm_air air = {hfm_air_uniform_fn, &still, NULL};
    hfm_tsim *ts = hfm_tsim_create(ac, &air, HFM_TSIM_ARKODE_FIXED, 0.005, 0.0, NULL);
    CHECK(ts != NULL);
    if (!ts)
        return;
    CHECK(hfm_tsim_init(ts, 0.0, &r.body, &r.u, &r.rotor) == 0);
    int n = hfm_tsim_size(ts), nb = hfm_aircraft_blades(ac);
    CHECK(n == 16 + 2 * nb && nb == 4);
    /* state at azimuth 0 as hfm_tsim_init builds it, rebuilt here from the
     * definition of the coordinates: b0, b1c, b1s, b_d = b2c cos 2psi + ... */
    double y[64] = {0}, yd[64];
    memcpy(y + 3, r.body.vel_B_mps, sizeof r.body.vel_B_mps);
    memcpy(y + 6, r.body.rate_B_radps, sizeof r.body.rate_B_radps);
    memcpy(y + 9, r.body.euler_rad, sizeof r.body.euler_rad);
    y[12] = r.rotor.lambda0;
    y[13] = r.rotor.lambda1s;
    y[14] = r.rotor.lambda1c;
    const double Om = hfm_aircraft_rotor_omega_radps(ac);
    double maxerr = 0.0, scale = 0.0;
    for (int k = 0; k < 8; k++) {
        double psi = 2.0 * CORE_PI * k / 8.0 / 4.0; /* a quarter revolution */
        double c2 = cos(2 * psi), s2 = sin(2 * psi);
        y[15] = psi;
        y[16] = r.rotor.beta0_rad;
        y[17] = r.rotor.beta1c_rad;
        y[18] = r.rotor.beta1s_rad;
        y[19] = r.rotor.beta2c_rad * c2 + r.rotor.beta2s_rad * s2;
        y[20] = y[21] = y[22] = 0.0;
        y[23] = 2 * Om * (-r.rotor.beta2c_rad * s2 + r.rotor.beta2s_rad * c2);
        CHECK(hfm_tsim_rhs(ts, 0.0, y, yd) == 0);
        /* expected: b0'' = b1c'' = b1s'' = 0, b_d'' = -4 Om^2 b_d */
        double exp[4] = {0, 0, 0, -4 * Om * Om * y[19]};
        for (int i = 0; i < 4; i++) {
            maxerr = fmax(maxerr, fabs(yd[20 + i] - exp[i]));
            scale = fmax(scale, fabs(exp[i]));
        }
    }
    /* the trim balances the harmonics on a 16-point quadrature, not the
     * higher harmonics: the residual is those (small) harmonics' share */
    printf("multiblade coordinates at a 100 kt trim over a quarter revolution: max |q'' - "
           "q''_trim| %.3f rad/s^2 (2/rev flapping acceleration %.3f rad/s^2, Omega^2 b0 "
           "%.1f rad/s^2)\n",
           maxerr, scale, Om * Om * r.rotor.beta0_rad);
    CHECK(maxerr < 0.05 * Om * Om * r.rotor.beta0_rad);
    hfm_tsim_destroy(ts);
}

/* The uniform wind is sampled once per evaluation (hfm_air_uniform_fn is
 * recognised); any other callback is sampled at every blade element and
 * component. A callback returning the same wind must give the same loads
 * and state derivative, through both paths. */
static int same_wind(void *user, const double pos_S_m[3], double t_s, double vel_S_mps[3])
{
    (void)pos_S_m;
    (void)t_s;
    const hfm_air_uniform *u = user;
    for (int i = 0; i < 3; i++)
        vel_S_mps[i] = u->vel_S_mps[i];
    return 0;
}

static void test_air_paths(const hfm_aircraft *ac, hfm_trim *tr)
{
    hfm_trim_cond cd;
    hfm_trim_result r;
    trim_at(tr, 60.0, &cd, &r);
    hfm_air_uniform wind = {{4.0, -7.0, 1.5}};
    hfm_air fast = {hfm_air_uniform_fn, &wind, NULL}, slow = {same_wind, &wind, NULL};
    hfm_loads La, Lb;
    CHECK(hfm_eval_harmonic(ac, &fast, 0.0, &r.body, &r.u, &r.rotor, &La) == 0);
    CHECK(hfm_eval_harmonic(ac, &slow, 0.0, &r.body, &r.u, &r.rotor, &Lb) == 0);
    double e = 0.0, m = 0.0;
    for (int i = 0; i < 6; i++) {
        e = fmax(e, fabs(La.acc_B[i] - Lb.acc_B[i]));
        m = fmax(m, fabs(La.acc_B[i]));
    }
    e = fmax(e, fabs(La.mr_thrust_N - Lb.mr_thrust_N) / La.mr_thrust_N);
    hfm_tsim *ta = hfm_tsim_create(ac, &fast, HFM_TSIM_ARKODE_FIXED, 0.005, 0.0, NULL);
    hfm_tsim *tb = hfm_tsim_create(ac, &slow, HFM_TSIM_ARKODE_FIXED, 0.005, 0.0, NULL);
    CHECK(ta && tb);
    if (ta && tb) {
        double y[64], ya[64], yb[64];
        CHECK(hfm_tsim_init(ta, 0.0, &r.body, &r.u, &r.rotor) == 0);
        CHECK(hfm_tsim_init(tb, 0.0, &r.body, &r.u, &r.rotor) == 0);
        CHECK(hfm_tsim_advance(ta, 0.1) == 0);
        CHECK(hfm_tsim_state(ta, y, 64) == 0);
        CHECK(hfm_tsim_rhs(ta, 0.1, y, ya) == 0 && hfm_tsim_rhs(tb, 0.1, y, yb) == 0);
        for (int i = 0; i < hfm_tsim_size(ta); i++)
            e = fmax(e, fabs(ya[i] - yb[i]) / (1.0 + fabs(ya[i])));
    }
    hfm_tsim_destroy(ta);
    hfm_tsim_destroy(tb);
    printf("air sampled once (uniform wind) against at every element (a callback): max "
           "difference %.2g (accelerations up to %.2g)\n",
           e, m);
    CHECK(e < 1e-9);
}

static void test_disk(const hfm_aircraft *ac, hfm_trim *tr)
{
    hfm_trim_cond cd;
    hfm_trim_result r;
    trim_at(tr, 0.0, &cd, &r);
    hfm_air_uniform still = {{0, 0, 0}};
    hfm_air air = {hfm_air_uniform_fn, &still, NULL};
    static hfm_disk d;
    CHECK(hfm_rotor_disk(ac, &air, 0.0, &r.body, &r.u, &r.rotor, 16, 24, &d) == 0);
    /* integrate the loading over the disk: it must give the rotor thrust */
    double T = 0.0, R = hfm_aircraft_rotor_radius_m(ac), r0 = d.r_m[0] - 0.5 * (d.r_m[1] - d.r_m[0]);
    double dr = (R - r0) / d.nr;
    for (int i = 0; i < d.nr; i++)
        for (int j = 0; j < d.npsi; j++)
            T += d.thrust_Pa[i * d.npsi + j] * d.r_m[i] * dr * 2.0 * CORE_PI / d.npsi;
    printf("disk: integrated %.0f N, rotor %.0f N, trim %.0f N; hub at z_S %.2f m\n", T,
           d.thrust_N, r.loads.mr_thrust_N, d.hub_S_m[2]);
    CHECK_NEAR(T / d.thrust_N, 1.0, 0.03);
    CHECK_NEAR(d.thrust_N / r.loads.mr_thrust_N, 1.0, 0.03);
}

/* A test load: a fixed force and moment in B (user: six doubles), or a
 * failure (user NULL). */
static int test_load(void *user, double t_s, const hfm_body *b, double F_B_N[3], double M_B_Nm[3])
{
    (void)t_s, (void)b;
    const double *fm = user;
    if (!fm)
        return -1;
    for (int i = 0; i < 3; i++) {
        F_B_N[i] = fm[i];
        M_B_Nm[i] = fm[3 + i];
    }
    return 0;
}

/* External loads (hfm_tsim_set_external) add to the body's equations of
 * motion: a force F in B changes u' v' w' by F / m exactly, a moment
 * changes p' q' r' linearly (twice the moment, twice the change), and a
 * failing load fails the evaluation. */
static void test_external(const hfm_aircraft *ac, hfm_trim *tr)
{
    hfm_trim_cond cd;
    hfm_trim_result r;
    trim_at(tr, 0.0, &cd, &r);
    hfm_air_uniform calm = {{0.0, 0.0, 0.0}};
    hfm_air air = {hfm_air_uniform_fn, &calm, NULL};
    hfm_tsim *ts = hfm_tsim_create(ac, &air, HFM_TSIM_ARKODE_FIXED, 0.005, 0.0, NULL);
    CHECK(ts != NULL);
    if (!ts)
        return;
    CHECK(hfm_tsim_init(ts, 0.0, &r.body, &r.u, &r.rotor) == 0);
    double y[64], y0[64], y1[64], y2[64];
    CHECK(hfm_tsim_state(ts, y, 64) == 0);
    CHECK(hfm_tsim_rhs(ts, 0.0, y, y0) == 0);
    const double W = hfm_aircraft_weight_N(ac);
    double one[6] = {0.02 * W, -0.03 * W, 0.1 * W, 5000.0, -3000.0, 2000.0};
    double two[6] = {0.02 * W, -0.03 * W, 0.1 * W, 10000.0, -6000.0, 4000.0};
    hfm_tsim_set_external(ts, test_load, one);
    CHECK(hfm_tsim_rhs(ts, 0.0, y, y1) == 0);
    hfm_tsim_set_external(ts, test_load, two);
    CHECK(hfm_tsim_rhs(ts, 0.0, y, y2) == 0);
    const double g_frac[3] = {0.02, -0.03, 0.1};
    for (int i = 0; i < 3; i++) {
        CHECK_NEAR(y1[3 + i] - y0[3 + i], g_frac[i] * CORE_G_MPS2, 1e-9);
        double d1 = y1[6 + i] - y0[6 + i], d2 = y2[6 + i] - y0[6 + i];
        CHECK(fabs(d1) > 1e-4);
        CHECK_NEAR(d2, 2.0 * d1, 1e-9 * (1.0 + fabs(d2)));
    }
    CHECK(y1[6] > y0[6]); /* a right-wing-down moment rolls right */
    hfm_tsim_set_external(ts, test_load, NULL);
    CHECK(hfm_tsim_rhs(ts, 0.0, y, y1) != 0);
    hfm_tsim_set_external(ts, NULL, NULL);
    CHECK(hfm_tsim_rhs(ts, 0.0, y, y1) == 0 && y1[5] == y0[5]);
    printf("external loads: w' %+.4f m/s^2 for 0.1 W down, p' %+.5f rad/s^2 for 10 kN m\n", y2[5] - y0[5],
           y2[6] - y0[6]);
    hfm_tsim_destroy(ts);
}

int main(void)
{
    setvbuf(stdout, NULL, _IOLBF, 0);
    core_err err = {0};
    hfm_aircraft *ac = hfm_aircraft_load(UH60, NULL, &err);
    CHECK(ac != NULL);
    if (!ac) {
        fprintf(stderr, "%s\n", err.msg);
        return check_done("test_hfm_dyn");
    }
    hfm_trim *tr = hfm_trim_create(ac, NULL);
    test_linear(tr, 0.0);
    test_linear(tr, 80.0);
    test_tsim(ac, tr, 0.0);
    test_tsim(ac, tr, 80.0);
    test_tsim(ac, tr, 140.0);
    test_mbc(ac, tr);
    test_air_paths(ac, tr);
    test_disk(ac, tr);
    test_external(ac, tr);
    hfm_trim_destroy(tr);
    hfm_aircraft_destroy(ac);
    return check_done("test_hfm_dyn");
}
