/* tailrotor.c -- tail rotor: Bailey-type closed-form thrust and torque, or a
 * ducted fan (fenestron).
 *
 * Model (Bailey, NACA TR-716, 1941, in the simplified form of GenHel,
 * Howlett NASA CR-166309, sec. 5; and Padfield ch. 3.2.3): thrust
 * coefficient of a linearly twisted rotor with tip loss B,
 *   CT = sigma a/2 [theta0 (B^3/3 + mu^2 B/2) + theta_tw (B^4/4 + mu^2 B^2/4) - lambda B^2/2],
 * with delta-3 pitch-flap coupling through the coning
 *   beta0 = gamma/8 [theta0 (B^4 + mu^2 B^2) + 4/5 theta_tw (B^5 + 5/6 mu^2 B^3) - 4/3 lambda B^3]
 * (the flap moment, like the thrust, integrated to the tip-loss radius B R;
 * integrated to R it gave the UH-60A 0.8 % of pedal less in the hover),
 *   theta0 -> theta0 - tan(delta3) beta0 (solved in closed form),
 * and the momentum inflow CT = k lambda_i sqrt(mu^2 + lambda^2), k = 2 for an
 * open rotor; for a fenestron (ideal duct, exit area = fan area) k = 1 on the
 * total thrust and the fan carries fan_thrust_fraction of it (Vuillet and
 * Morelli, 12th European Rotorcraft Forum, 1986). lambda = lambda_c + lambda_i.
 * Torque CQ = lambda CT_fan + sigma cd0/8 (1 + 4.6 mu^2).
 * Inflow: the air at the hub (hfm_air callback) plus the main-rotor wake,
 * its velocity along the shaft averaged over the tail-rotor disk
 * (body.c); fin blockage scales the thrust below
 * blockage_below_kt (GenHel: 0.9 below 30 kt), blended over 10 kt.
 * The inflow equation is solved by Newton's method from a momentum first
 * guess (in fixed-step time simulation, from the last evaluation's value).
 * Assumptions: the tail-rotor torque reaction and H-force are neglected.
 */
#include "hfm_priv.h"

int hfm_tailrotor(const hfm_aircraft *ac, const hfm_kin *k, const hfm_wake *w, double theta,
                  hfm_fm *fm, double *thrust, double *power)
{
    const hfm_tr *t = &ac->tr;
    double rel[3];
    if (hfm_air_rel_B(k, t->hub_B, rel))
        return -1;
    double imm = hfm_wake_speed_disk(ac, w, t->hub_B, t->dir_B, t->R);
    for (int i = 0; i < 3; i++)
        rel[i] += imm * ac->mr.C_BH[i][2];
    double OR = t->omega * t->R, ax = v3_dot(rel, t->dir_B);
    double lc = -ax / OR;
    double pe[3] = {rel[0] - ax * t->dir_B[0], rel[1] - ax * t->dir_B[1], rel[2] - ax * t->dir_B[2]};
    double mu = sqrt(v3_dot(pe, pe)) / OR, mu2 = mu * mu;
    double B = t->B, sa2 = 0.5 * t->sigma * t->a, K = t->tan_d3, g8 = t->lock / 8.0;
    double tw = t->twist, th0 = theta - tw * t->twist_ref; /* pitch at the root */
    /* the coning's flap moment stops at the tip-loss radius too */
    double B2 = B * B, B3 = B2 * B, B4 = B3 * B, B5 = B4 * B;
    double den = 1.0 + K * g8 * (B4 + mu2 * B2);
    double c1 = B3 / 3.0 + mu2 * B / 2.0, c2 = B4 / 4.0 + mu2 * B * B / 4.0;
    double km = t->kind == HFM_TR_FENESTRON ? 1.0 : 2.0, ff = t->fan_fraction;
    /* CT_fan(lambda) = a0 + a1 lambda (linear through the delta-3 solve) */
    double thA = (th0 - K * g8 * 0.8 * tw * (B5 + 5.0 / 6.0 * mu2 * B3)) / den;
    double thL = K * g8 * (4.0 / 3.0) * B3 / den;
    double a0 = sa2 * (thA * c1 + tw * c2), a1 = sa2 * (thL * c1 - B2 / 2.0);
    /* first guess from momentum with the thrust at lambda = lambda_c (exact
     * in hover for a1 = 0, CT/(k mu) in edgewise flight); Newton from it */
    double ct0 = (a0 + a1 * lc) / ff;
    double li = ct0 / (km * sqrt(mu2 + lc * lc + fabs(ct0) / km + 1e-12));
    if (w->tr_inflow && isfinite(*w->tr_inflow)) /* time simulation: the last value */
        li = *w->tr_inflow;
    const double a0f = a0 / ff, a1f = a1 / ff;
    for (int it = 0; it < 30; it++) {
        /* g = CT_fan/ff - k li s, s = sqrt(mu^2 + l^2); step -g/g' with one division */
        double l = lc + li, s2 = mu2 + l * l + 1e-12, s = sqrt(s2);
        double g = a0f + a1f * l - km * li * s;
        double step = -g * s / (a1f * s - km * (s2 + li * l));
        if (step > 0.05)
            step = 0.05;
        if (step < -0.05)
            step = -0.05;
        li += step;
        if (fabs(step) < 1e-8) /* quadratic convergence: li is then exact to ~1e-15 */
            break;
    }
    if (w->tr_inflow)
        *w->tr_inflow = li;
    double l = lc + li, ctf = a0 + a1 * l;
    double q = ac->mr.rho * CORE_PI * t->R * t->R * OR * OR;
    double bf = 1.0;
    if (w->airspeed_kt < t->blockage_kt)
        bf = t->blockage;
    else if (w->airspeed_kt < t->blockage_kt + 10.0)
        bf = t->blockage + (1.0 - t->blockage) * (w->airspeed_kt - t->blockage_kt) / 10.0;
    double T = ctf / ff * q * bf;
    double cq = l * ctf + t->sigma * t->cd0 / 8.0 * (1.0 + 4.6 * mu2);
    for (int i = 0; i < 3; i++)
        fm->F_B_N[i] = T * t->dir_B[i];
    v3_cross(t->hub_B, fm->F_B_N, fm->M_B_Nm);
    *thrust = T;
    *power = cq * q * OR;
    return 0;
}
