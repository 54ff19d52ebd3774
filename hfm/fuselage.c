/* fuselage.c -- fuselage aerodynamics from tables versus angle of attack and
 * sideslip (GenHel, Howlett NASA CR-166309, fuselage data as quoted in
 * ../shared/reference/uh60a.md), per dynamic pressure.
 *
 * Drag D/q(alpha) + dD/q(|beta|) acts along the local air velocity, lift
 * L/q(alpha) normal to it in the body x-z plane, pitching moment M/q(alpha)
 * and a destabilising yaw moment N/q = -N10 sin(2 beta)/sin(20 deg) (the
 * published value at 10 deg, zero at 90 deg). The air is sampled at the
 * fuselage reference point (hfm_air callback) plus the main-rotor wake
 * (k_fus vi along the shaft where immersed). Flow from behind (|alpha| > 90)
 * uses the mirrored angle: a crude stand-in for rearward flight.
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
    double imm = hfm_wake_immersion(ac, w, f->ref_B) * ac->mr.k_fus * w->vi_mps;
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
    double beta = asin(clampd(-a[1] / U, -1.0, 1.0));
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
    v3_cross(f->ref_B, fm->F_B_N, fm->M_B_Nm);
    fm->M_B_Nm[1] += q * hfm_table_eval(&f->pitch, alpha);
    fm->M_B_Nm[2] -= q * f->yaw_m3_10deg * sin(2.0 * beta) / sin(20.0 * CORE_DEG_TO_RAD);
    return 0;
}
