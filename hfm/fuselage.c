/* fuselage.c -- fuselage aerodynamics from tables versus angle of attack and
 * sideslip, per dynamic pressure: GenHel's fuselage tables (Howlett, "UH-60A
 * Black Hawk Engineering Simulation Program", NASA CR-166309, 1981;
 * docs/references.md).
 *
 * Drag D/q(alpha) + dD/q(|beta|) acts along the local air velocity, lift
 * L/q(alpha) normal to it in the body x-z plane, pitching moment M/q(alpha)
 * and a destabilising yaw moment N/q = -N10 sin(2 beta)/sin(20 deg) (the
 * published value at 10 deg, zero at 90 deg).
 * Side force (not in the GenHel tables as quoted): the slender-body
 * (potential) part of a body's normal force, rho S0 u v with u the axial
 * and v the lateral air velocity, i.e. Y/q = -2 S0 sin(beta) cos(beta) in
 * sideslip (Munk, NACA TR-184, 1924; USAF DATCOM sec. 4.2.1.1: normal-force
 * slope 2 S0/S_ref per rad, S0 the cross-section where the flow stops being
 * potential), acting at the reference point. The sideslip drag increment is
 * the viscous cross-flow part (GenHel's 170.5 ft^2 at 90 deg); the two
 * together are Allen and Perkins' body normal force (NACA Report 1048,
 * 1951). The potential part vanishes in a pure cross-flow (a side wind in
 * the hover downwash). Without it, a wings-level trim balanced the tail
 * rotor's side force with 6 deg of sideslip at 140 kt.
 * The air is sampled at the fuselage reference point (hfm_air callback);
 * the tables take it without the main-rotor wake (they are wind-tunnel
 * data of the fuselage alone). The wake acts as cross-flow drag on the
 * planform the data file gives (planform_x_B_m stations with their
 * planform_width_m, linear between them): on each cell the wake's
 * velocity (body.c) adds to the cell's own cross-flow u (the reference
 * point's air less the body's rotation about it, normal to the body axis:
 * the planform's yaw and pitch damping in the wake) and the cell carries the
 * increment 0.5 rho Cc A (|u + w| (u + w) -
 * |u| u), Cc A the table's drag at 90 deg shared by area, at the cell
 * (Allen and Perkins' cross-flow drag, NACA Report 1048, applied per
 * section). So the download in the hover is the table's 90 deg drag in
 * the wake's velocity, and a wake on the tail cone alone loads the tail
 * cone, not the whole body's angle of attack (which put the GenHel
 * pitching moment's unstable slope behind a nose-down moment there). Flow
 * from behind (|alpha| > 90) uses the mirrored angle: a crude stand-in for
 * rearward flight.
 */
#include "hfm_priv.h"

/* The tables and the side force for the air a (body axes, m/s) at the
 * reference point, |a|^2 = U2 > 0. */
static void tables(const hfm_aircraft *ac, const double a[3], double U2, hfm_fm *fm)
{
    const hfm_fus *f = &ac->fus;
    double U = sqrt(U2), q = 0.5 * ac->mr.rho * U2;
    double alpha = atan2(-a[2], -a[0]);
    if (alpha > 0.5 * CORE_PI)
        alpha = CORE_PI - alpha;
    else if (alpha < -0.5 * CORE_PI)
        alpha = -CORE_PI - alpha;
    double sbeta = clampd(-a[1] / U, -1.0, 1.0), beta = asin(sbeta);
    double D = q * (hfm_table_eval(&f->drag, alpha) + hfm_table_eval(&f->dbeta, fabs(beta)));
    double Lf = q * hfm_table_eval(&f->lift, alpha);
    double hxz = sqrt(a[0] * a[0] + a[2] * a[2]);
    double ld[3] = {0, 0, 0};
    if (hxz > 1e-9) {
        ld[0] = -a[2] / hxz;
        ld[2] = a[0] / hxz;
    }
    for (int i = 0; i < 3; i++)
        fm->F_B_N[i] = D * a[i] / U + Lf * ld[i];
    /* slender-body side force: rho S0 u_axial v_lateral, i.e. with side =
     * 2 S0, Y/q = -side sin(beta) cos(beta) in sideslip (2 S0 beta at small
     * beta); nothing without an axial component (a pure cross-flow, such as
     * a side wind in the hover downwash, is the cross-flow drag's) */
    fm->F_B_N[1] += 0.5 * ac->mr.rho * f->side_m2 * fabs(a[0]) * a[1];
    v3_cross(f->ref_B, fm->F_B_N, fm->M_B_Nm);
    fm->M_B_Nm[1] += q * hfm_table_eval(&f->pitch, alpha);
    /* sin(2 beta) = 2 sin(beta) cos(beta); sin(20 deg) */
    fm->M_B_Nm[2] -= q * f->yaw_m3_10deg * 2.0 * sbeta * sqrt(1.0 - sbeta * sbeta) /
                     0.34202014332566873;
}

/* The planform's width at body x (linear between stations, 0 outside). */
static double plan_width(const hfm_fus *f, double x)
{
    for (int i = 1; i < f->plan_n; i++)
        if (x >= f->plan_x_B[i] && x <= f->plan_x_B[i - 1]) {
            double d = f->plan_x_B[i - 1] - f->plan_x_B[i];
            double t = d > 0.0 ? (f->plan_x_B[i - 1] - x) / d : 0.0;
            return f->plan_w[i - 1] + t * (f->plan_w[i] - f->plan_w[i - 1]);
        }
    return 0.0;
}

void hfm_fuselage_cells(hfm_aircraft *ac)
{
    hfm_fus *f = &ac->fus;
    const double fore = f->plan_x_B[0], len = fore - f->plan_x_B[f->plan_n - 1];
    double wmax = 0.0;
    for (int i = 0; i < f->plan_n; i++)
        wmax = fmax(wmax, f->plan_w[i]);
    const int na = hfm_wake_cells(ac, len, HFM_WAKE_MAX_CELLS);
    const int nb = hfm_wake_cells(ac, wmax, HFM_WAKE_MAX_CELLS);
    double area = 0.0;
    for (int i = 0; i < na; i++) {
        f->cell_x[i] = fore - (i + 0.5) * len / na;
        f->cell_w[i] = plan_width(f, f->cell_x[i]);
        area += f->cell_w[i];
    }
    const double D90 = 0.5 * ac->mr.rho * hfm_table_eval(&f->drag, 0.5 * CORE_PI);
    for (int i = 0; i < na; i++)
        f->cell_cA[i] = D90 * (area > 0.0 ? f->cell_w[i] / (area * nb) : 1.0 / (na * nb));
    f->cell_na = na;
    f->cell_nb = nb;
}

/* The main-rotor wake on the planform: on each cell (hfm_fuselage_cells)
 * the increment of the cross-flow drag 0.5 rho Cc A |u| u (u the air
 * velocity normal to the body axis) that the wake velocity w adds to the
 * air's own cross-flow, applied at the cell; Cc A is the table's drag at
 * 90 deg shared by the cells by area (a planform of zero area: all of it
 * at the reference point). */
static void wake_crossflow(const hfm_aircraft *ac, const hfm_kin *k, const hfm_wake *w,
                           const double a_ref[3], hfm_fm *fm)
{
    const hfm_fus *f = &ac->fus;
    const int nb = f->cell_nb;
    const double n[3] = {0.0, ac->mr.C_BH[1][2], ac->mr.C_BH[2][2]}; /* the shaft, across the body */
    for (int i = 0; i < f->cell_na; i++) {
        for (int j = 0; j < nb; j++) {
            double p[3] = {f->cell_x[i], f->ref_B[1] + (-0.5 + (j + 0.5) / nb) * f->cell_w[i], f->ref_B[2]};
            double v, df[3], dm[3], a[3], d[3], wxd[3];
            if (hfm_wake_point(ac, w, p, &v) <= 0.0)
                continue;
            /* the cell's air: the reference point's, less the body's
             * rotation about it (the planform's yaw and pitch damping in
             * the wake); the air itself is sampled once, at the reference
             * point, as the tables are: a field sampled cell by cell put
             * the coupled hover's iterations into a cycle (test_couple
             * calm) */
            for (int c = 0; c < 3; c++)
                d[c] = p[c] - f->ref_B[c];
            v3_cross(k->rate_B, d, wxd);
            for (int c = 0; c < 3; c++)
                a[c] = a_ref[c] - wxd[c];
            const double u0[3] = {0.0, a[1], a[2]}, m0 = sqrt(v3_dot(u0, u0));
            double u[3] = {0.0, u0[1] + v * n[1], u0[2] + v * n[2]}, m = sqrt(v3_dot(u, u));
            for (int c = 0; c < 3; c++)
                df[c] = f->cell_cA[i] * (m * u[c] - m0 * u0[c]);
            v3_cross(p, df, dm);
            for (int c = 0; c < 3; c++) {
                fm->F_B_N[c] += df[c];
                fm->M_B_Nm[c] += dm[c];
            }
        }
    }
}

int hfm_fuselage(const hfm_aircraft *ac, const hfm_kin *k, const hfm_wake *w, hfm_fm *fm,
                 double *airspeed)
{
    double a[3];
    if (hfm_air_rel_B(k, ac->fus.ref_B, a))
        return -1;
    double U2 = v3_dot(a, a);
    *airspeed = sqrt(U2);
    for (int i = 0; i < 3; i++)
        fm->F_B_N[i] = fm->M_B_Nm[i] = 0.0;
    if (U2 >= 1e-8)
        tables(ac, a, U2, fm);
    wake_crossflow(ac, k, w, a, fm);
    return 0;
}
