/* fuselage.c -- fuselage aerodynamics from tables versus angle of attack and
 * sideslip (GenHel, Howlett NASA CR-166309, fuselage data as quoted in
 * ../shared/reference/uh60a.md), per dynamic pressure.
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
 * The air is sampled at the fuselage reference point (hfm_air callback)
 * plus the main-rotor wake: k_fus vi along the shaft times the fraction of
 * the fuselage planform inside the wake (body.c): a rectangle from
 * planform_x_B_m's fore to aft end, planform_width_m wide, at the
 * reference point's y and z (the data file; absent, the reference point
 * alone). Flow
 * from behind (|alpha| > 90) uses the mirrored angle: a crude stand-in for
 * rearward flight.
 */
#include "hfm_priv.h"

int hfm_fuselage(const hfm_aircraft *ac, const hfm_kin *k, const hfm_wake *w, hfm_fm *fm,
                 double *airspeed)
{
    const hfm_fus *f = &ac->fus;
    double a[3];
    if (hfm_air_rel_B(k, f->ref_B, a))
        return -1;
    *airspeed = sqrt(v3_dot(a, a));
    const double c[3] = {0.5 * (f->plan_x_B[0] + f->plan_x_B[1]), f->ref_B[1], f->ref_B[2]};
    const double ha[3] = {0.5 * (f->plan_x_B[0] - f->plan_x_B[1]), 0, 0};
    const double hb[3] = {0, 0.5 * f->plan_width, 0};
    double imm = hfm_wake_immersion_patch(ac, w, c, ha, hb) * ac->mr.k_fus * w->vi_mps;
    for (int i = 0; i < 3; i++)
        a[i] += imm * ac->mr.C_BH[i][2];
    double U2 = v3_dot(a, a);
    for (int i = 0; i < 3; i++)
        fm->F_B_N[i] = fm->M_B_Nm[i] = 0.0;
    if (U2 < 1e-8)
        return 0;
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
    return 0;
}
