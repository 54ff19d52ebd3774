/* rotor.c -- main rotor: blade elements, rigid flapping blades, Pitt-Peters
 * inflow.
 *
 * Model. Each blade is rigid, flapping about a hinge at offset e with a
 * spring K_beta (a hingeless rotor is an equivalent offset and spring).
 * Hub axes H: z down the shaft (tilted forward by the shaft tilt), x forward.
 * Azimuth psi runs from the tail in the sense of rotation (sense s = +1
 * counter-clockwise from above, -1 clockwise); the blade span is
 * e_r = (-cos psi, s sin psi, 0). Blade pitch (Johnson, "Helicopter Theory",
 * ch. 5): theta = theta0 + twist (r/R - r_ref) - s A1 cos psi - B1 sin psi.
 * At each of the radial segments the element velocity (hub motion, body
 * rate, rotation, flapping) and the air (the hfm_air callback at the element's
 * position in S, plus the Pitt-Peters inflow
 * lambda0 + r/R (lambda1s sin psi + lambda1c cos psi) along the shaft) give
 * U_T, U_P, the angle of attack over the full circle (reversed flow) and the
 * lift and drag from the airfoil table (stall included). Tip loss: lift
 * stops at B R (Johnson 4.5).
 *
 * Flap equation about the hinge (Padfield, "Helicopter Flight Dynamics",
 * 2nd ed., eq. 3.70 with hinge offset and spring, gyroscopic body-rate term):
 *   I_b beta'' = M_aero - Omega^2 sin(beta) (e S_b + I_b cos beta) - K_b beta
 *                + 2 Omega I_b (s p_H cos psi - q_H sin psi) - S_b g_zH cos beta.
 * In trim the flapping is beta0 + first and second harmonics, balanced on
 * the azimuth quadrature (harmonic balance); in time simulation each
 * blade is integrated. Hub loads per blade: the hinge force (aerodynamic + centrifugal + flap
 * inertia) times the offset, plus the moment at the hinge whose flap
 * component is the spring's.
 *
 * Pitt-Peters 3-state inflow (Peters and HaQuang, JAHS 33(4), 1988):
 *   M lambda'/Omega + Lhat^-1 lambda = (CT, CL, CM),
 *   Lhat = [[1/(2VT), 0, k/VM], [0, c/VM, 0], [k/VT, 0, c cos chi/VM]],
 *   k = 15 pi/64 tan(chi/2), c = 4/(1 + cos chi), M = diag(8/(3pi), 16/(45pi), 16/(45pi)),
 * (chi held at <= 70 deg in L, see hfm_rotor_inflow), with CL, CM the first moments of the thrust in sin psi and cos psi (signed so
 * that a positive moment raises the inflow where its harmonic is positive).
 */
#include "hfm_priv.h"

#include <string.h>

/* atan2 by a minimax polynomial (max error about 1e-5 rad, far below what
 * the airfoil table resolves): the blade loop's costliest call otherwise. */
static inline double fast_atan2(double y, double x)
{
    double ax = fabs(x), ay = fabs(y);
    double mx = ax > ay ? ax : ay, mn = ax > ay ? ay : ax;
    if (mx == 0.0)
        return 0.0;
    double a = mn / mx, s = a * a;
    double r = ((((-0.01172120 * s + 0.05265332) * s - 0.11643287) * s + 0.19354346) * s -
                0.33262347) * s * a + 0.99997726 * a;
    if (ay > ax)
        r = 0.5 * CORE_PI - r;
    if (x < 0.0)
        r = CORE_PI - r;
    return y < 0.0 ? -r : r;
}

int hfm_rotor_setup(const hfm_aircraft *ac, const hfm_kin *k, const hfm_controls *u,
                    const double lam[3], hfm_rotor_in *in)
{
    const hfm_mr *mr = &ac->mr;
    double thtr;
    hfm_controls_to_pitch(ac, u, &in->theta0, &in->A1, &in->B1, &thtr);
    double v_B[3], wxr[3], tmp[3];
    v3_cross(k->rate_B, mr->hub_B, wxr);
    for (int i = 0; i < 3; i++)
        v_B[i] = k->vel_B[i] + wxr[i];
    m3_tmul(mr->C_BH, v_B, in->vhub_H);
    m3_tmul(mr->C_BH, k->rate_B, in->rate_H);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            in->C_SH[i][j] = k->C_SB[i][0] * mr->C_BH[0][j] + k->C_SB[i][1] * mr->C_BH[1][j] +
                             k->C_SB[i][2] * mr->C_BH[2][j];
    m3_mul(k->C_SB, mr->hub_B, tmp);
    for (int i = 0; i < 3; i++)
        in->hub_S[i] = k->pos_S[i] + tmp[i];
    memcpy(in->lam, lam, sizeof in->lam);
    in->t = k->t;
    in->air = k->air;
    double g_S[3] = {0, 0, CORE_G_MPS2};
    m3_tmul(in->C_SH, g_S, in->g_H);
    for (int i = 0; i < 3; i++)
        in->C_BH_z[i] = mr->C_BH[i][2];
    double a_S[3], a_H[3];
    if (k->air->fn(k->air->user, in->hub_S, k->t, a_S))
        return -1;
    m3_tmul(in->C_SH, a_S, a_H);
    for (int i = 0; i < 3; i++)
        in->rel_hub_H[i] = a_H[i] - in->vhub_H[i];
    return 0;
}

int hfm_rotor_blade(const hfm_aircraft *ac, const hfm_rotor_in *in, double psi, double beta,
                    double dbeta, double ddbeta, int solve_dd, hfm_blade_out *o, double *dT,
                    double *dS)
{
    const hfm_mr *mr = &ac->mr;
    const double s = mr->sense, Om = mr->omega, OR = mr->omega * mr->R, e = mr->e;
    const double c = cos(psi), sn = sin(psi), cb = cos(beta), sb = sin(beta);
    const double er[3] = {-c, s * sn, 0.0}, et[3] = {sn, s * c, 0.0};
    const double erp[3] = {-c * cb, s * sn * cb, -sb}, eup[3] = {c * sb, -s * sn * sb, -cb};
    const double wt[3] = {in->rate_H[0], in->rate_H[1], in->rate_H[2] - s * Om};
    const double Omv[3] = {0.0, 0.0, -s * Om};
    const double th = in->theta0 - s * in->A1 * c - in->B1 * sn;
    const double lam_s = in->lam[1] * sn + in->lam[2] * c;
    /* Element position and velocity are linear in x = r - e along the
     * blade: p = e e_r + x e_r', v = v0 + x v1; positions in S likewise.
     * Sums of dF and x dF give the moments and power after the loop. */
    double wer[3], werp[3], v0[3], v1[3], a0[3], b0[3], t3[3];
    v3_cross(wt, er, wer);
    v3_cross(wt, erp, werp);
    for (int j = 0; j < 3; j++) {
        v0[j] = in->vhub_H[j] + e * wer[j];
        v1[j] = werp[j] + dbeta * eup[j];
        t3[j] = e * er[j];
    }
    m3_mul(in->C_SH, t3, a0);
    m3_mul(in->C_SH, erp, b0);
    for (int j = 0; j < 3; j++)
        a0[j] += in->hub_S[j];
    const double tw0 = th - mr->twist * mr->twist_ref, twR = mr->twist / mr->R;
    const double l0 = in->lam[0] * OR, ls = lam_s * OR / mr->R;
    const double hq = 0.5 * mr->rho * mr->chord;
    double F[3] = {0, 0, 0}, Fx[3] = {0, 0, 0}, Mflap = 0;
    for (int i = 0; i < mr->nseg; i++) {
        const double r = mr->r[i], x = r - e;
        double pS[3] = {a0[0] + x * b0[0], a0[1] + x * b0[1], a0[2] + x * b0[2]}, aS[3], aH[3];
        if (in->air->fn(in->air->user, pS, in->t, aS))
            return -1;
        m3_tmul(in->C_SH, aS, aH);
        aH[2] += l0 + r * ls;
        double rel[3] = {aH[0] - v0[0] - x * v1[0], aH[1] - v0[1] - x * v1[1],
                         aH[2] - v0[2] - x * v1[2]};
        double UT = -v3_dot(rel, et), UP = -v3_dot(rel, eup);
        double U2 = UT * UT + UP * UP;
        if (U2 < 1e-12) {
            if (dT)
                dT[i] = dS[i] = 0.0;
            continue;
        }
        double Ui = 1.0 / sqrt(U2);
        double alpha = tw0 + twR * r - fast_atan2(UP, UT);
        if (alpha > CORE_PI)
            alpha -= 2.0 * CORE_PI;
        else if (alpha < -CORE_PI)
            alpha += 2.0 * CORE_PI;
        double cl, cd;
        hfm_airfoil_eval(&mr->af, alpha, &cl, &cd);
        double qc = hq * U2;
        double L = qc * cl * mr->drl[i], D = qc * cd * mr->drd[i];
        double cph = UT * Ui, sph = UP * Ui;
        double Fu = L * cph - D * sph, Ft = -L * sph - D * cph;
        for (int j = 0; j < 3; j++) {
            double d = Fu * eup[j] + Ft * et[j];
            F[j] += d;
            Fx[j] += x * d;
        }
        Mflap += x * Fu;
        if (dT) {
            dT[i] = -(Fu * eup[2] + Ft * et[2]);
            dS[i] = -Ft;
        }
    }
    double M[3], m1[3], m2[3], vr0[3], vr1[3];
    v3_cross(er, F, m1);
    v3_cross(erp, Fx, m2);
    for (int j = 0; j < 3; j++)
        M[j] = e * m1[j] + m2[j];
    v3_cross(Omv, er, vr0);
    v3_cross(Omv, erp, vr1);
    double P = -(e * v3_dot(F, vr0) + v3_dot(Fx, vr1));
    /* thrust (up) and its moments r_inplane sin/cos psi, r_inplane = e + x cos beta */
    double T = -F[2], Tx = -Fx[2];
    double Lr = (e * T + cb * Tx) * sn, Mp = (e * T + cb * Tx) * c;
    /* the flap equation's non-aerodynamic terms: centrifugal with offset,
     * spring, gyroscopic body rates, blade weight (see the header) */
    o->G = -Om * Om * sb * (e * mr->S_beta + mr->I_beta * cb) - mr->K_beta * beta +
           2.0 * Om * mr->I_beta * (s * in->rate_H[0] * c - in->rate_H[1] * sn) -
           mr->S_beta * in->g_H[2] * cb;
    if (solve_dd)
        ddbeta = (Mflap + o->G) / mr->I_beta;
    o->ddbeta = ddbeta;
    /* inertial forces of the blade on the hinge */
    double Fh[3], Mh[3], t1[3], ee[3] = {e * er[0], e * er[1], 0.0};
    double cen = Om * Om * (mr->m_blade * e + mr->S_beta * cb);
    for (int j = 0; j < 3; j++)
        Fh[j] = F[j] + cen * er[j] - mr->S_beta * ddbeta * eup[j] +
                mr->S_beta * dbeta * dbeta * erp[j];
    /* moment of the aerodynamic loads about the hinge; its flap component
     * is replaced by the spring's (the hinge passes no other flap moment) */
    v3_cross(ee, F, t1);
    for (int j = 0; j < 3; j++)
        Mh[j] = M[j] - t1[j];
    const double ax[3] = {-s * sn, -c, 0.0}; /* e_r x e_up: the flap axis */
    double Mb = v3_dot(Mh, ax), ksp = mr->K_beta * beta;
    v3_cross(ee, Fh, t1);
    for (int j = 0; j < 3; j++) {
        o->F_H[j] = Fh[j];
        o->M_H[j] = t1[j] + Mh[j] + (ksp - Mb) * ax[j];
    }
    o->M_flap = Mflap;
    o->T = T;
    o->Lr = Lr / mr->R;
    o->Mp = Mp / mr->R;
    o->P = P;
    return 0;
}

void hfm_rotor_inflow(const hfm_aircraft *ac, const hfm_rotor_in *in, double CT, double CL,
                      double CM, double Lh[3][3], double *skew)
{
    (void)CT;
    (void)CL;
    (void)CM;
    const hfm_mr *mr = &ac->mr;
    double OR = mr->omega * mr->R;
    double mu = sqrt(in->rel_hub_H[0] * in->rel_hub_H[0] + in->rel_hub_H[1] * in->rel_hub_H[1]) / OR;
    double lc = in->rel_hub_H[2] / OR;
    double l0 = in->lam[0];
    double lt = lc + l0;
    double VT = sqrt(mu * mu + lt * lt);
    if (VT < 1e-4)
        VT = 1e-4;
    double VM = (mu * mu + lt * (lt + l0)) / VT;
    if (VM < 1e-4)
        VM = 1e-4;
    double ltp = lt > 1e-6 ? lt : 1e-6, rr = sqrt(mu * mu + ltp * ltp);
    double chi = atan2(mu, ltp);
    /* The Pitt-Peters L turns indefinite above chi = 77.7 deg (its (0, 2)
     * block's determinant is 1 - 1.5422 tan^2(chi/2)), which makes the
     * inflow dynamics diverge in fast forward flight: L is evaluated at
     * chi <= 70 deg (determinant >= 0.25). The wake skew itself is not held. */
    const double cos70 = 0.34202014332566871, tan35 = 0.70020753820970977;
    double cchl = ltp / rr, th2 = mu / (rr + ltp); /* cos chi, tan(chi/2) */
    if (cchl < cos70) {
        cchl = cos70;
        th2 = tan35;
    }
    double k = 15.0 * CORE_PI / 64.0 * th2, cc = 4.0 / (1.0 + cchl);
    memset(Lh, 0, 9 * sizeof(double));
    Lh[0][0] = 1.0 / (2.0 * VT);
    Lh[0][2] = k / VM;
    Lh[1][1] = cc / VM;
    Lh[2][0] = k / VT;
    Lh[2][2] = cc * cchl / VM;
    *skew = chi;
}

void hfm_rotor_harm_beta(const hfm_rotor_harm *rh, double Om, double psi, double *b, double *db,
                         double *ddb)
{
    double c = cos(psi), s = sin(psi), c2 = cos(2 * psi), s2 = sin(2 * psi);
    *b = rh->beta0_rad + rh->beta1c_rad * c + rh->beta1s_rad * s + rh->beta2c_rad * c2 +
         rh->beta2s_rad * s2;
    *db = Om * (-rh->beta1c_rad * s + rh->beta1s_rad * c - 2 * rh->beta2c_rad * s2 +
                2 * rh->beta2s_rad * c2);
    *ddb = -Om * Om * (rh->beta1c_rad * c + rh->beta1s_rad * s + 4 * rh->beta2c_rad * c2 +
                       4 * rh->beta2s_rad * s2);
}

void hfm_rotor_to_body(const hfm_aircraft *ac, const double F_H[3], const double M_H[3],
                       hfm_fm *fm)
{
    double t[3];
    m3_mul(ac->mr.C_BH, F_H, fm->F_B_N);
    m3_mul(ac->mr.C_BH, M_H, fm->M_B_Nm);
    v3_cross(ac->mr.hub_B, fm->F_B_N, t);
    for (int i = 0; i < 3; i++)
        fm->M_B_Nm[i] += t[i];
}

/* Wake data for the other components, from the rotor's inflow state. */
void hfm_rotor_wake(const hfm_aircraft *ac, const hfm_rotor_in *in, double skew,
                      const hfm_controls *u, const hfm_body *b, hfm_wake *w)
{
    w->vi_mps = in->lam[0] * ac->mr.omega * ac->mr.R;
    w->skew_rad = skew;
    w->tan_skew = tan(skew < 89.0 * CORE_DEG_TO_RAD ? skew : 89.0 * CORE_DEG_TO_RAD);
    double h = sqrt(in->rel_hub_H[0] * in->rel_hub_H[0] + in->rel_hub_H[1] * in->rel_hub_H[1]);
    w->dir_H[0] = h > 1e-6 ? in->rel_hub_H[0] / h : 0.0;
    w->dir_H[1] = h > 1e-6 ? in->rel_hub_H[1] / h : 0.0;
    w->coll_pct = u->collective_pct;
    w->q_degps = b->rate_B_radps[1] * CORE_RAD_TO_DEG;
    w->ay_g = 0.0;
    w->airspeed_kt = 0.0;
}

int hfm_eval_harmonic(const hfm_aircraft *ac, const hfm_air *air, double t_s, const hfm_body *b,
                      const hfm_controls *u, const hfm_rotor_harm *rh, hfm_loads *L)
{
    const hfm_mr *mr = &ac->mr;
    hfm_kin k;
    hfm_rotor_in in;
    memset(L, 0, sizeof *L);
    hfm_kin_setup(&k, air, t_s, b);
    double lam[3] = {rh->lambda0, rh->lambda1s, rh->lambda1c};
    if (hfm_rotor_setup(ac, &k, u, lam, &in))
        return -1;
    const double Om = mr->omega, nb = mr->nb, naz = mr->naz;
    double F[3] = {0, 0, 0}, M[3] = {0, 0, 0}, T = 0, Lr = 0, Mp = 0, P = 0;
    double fr[5] = {0, 0, 0, 0, 0};
    for (int j = 0; j < mr->naz; j++) {
        double psi = 2.0 * CORE_PI * j / naz, c = cos(psi), s = sin(psi);
        double beta, db, ddb;
        hfm_rotor_harm_beta(rh, Om, psi, &beta, &db, &ddb);
        hfm_blade_out o;
        if (hfm_rotor_blade(ac, &in, psi, beta, db, ddb, 0, &o, NULL, NULL))
            return -1;
        for (int i = 0; i < 3; i++) {
            F[i] += o.F_H[i];
            M[i] += o.M_H[i];
        }
        T += o.T;
        Lr += o.Lr;
        Mp += o.Mp;
        P += o.P;
        double R = mr->I_beta * ddb - o.M_flap - o.G;
        fr[0] += R;
        fr[1] += 2.0 * R * c;
        fr[2] += 2.0 * R * s;
        fr[3] += 2.0 * R * (c * c - s * s);
        fr[4] += 4.0 * R * s * c;
    }
    double f = nb / naz;
    for (int i = 0; i < 3; i++) {
        F[i] *= f;
        M[i] *= f;
    }
    for (int i = 0; i < 5; i++)
        L->flap_res[i] = fr[i] / (naz * mr->I_beta * Om * Om);
    hfm_rotor_to_body(ac, F, M, &L->mr);
    double q = mr->rho * mr->area * (Om * mr->R) * (Om * mr->R);
    L->mr_thrust_N = -F[2];
    L->mr_power_W = P * f;
    L->mr_torque_Nm = L->mr_power_W / Om;
    L->mr_CT = T * f / q;
    L->mr_CL = Lr * f / q;
    L->mr_CM = Mp * f / q;
    double Lh[3][3], skew;
    hfm_rotor_inflow(ac, &in, L->mr_CT, L->mr_CL, L->mr_CM, Lh, &skew);
    double C[3] = {L->mr_CT, L->mr_CL, L->mr_CM};
    for (int i = 0; i < 3; i++)
        L->inflow_res[i] = 10.0 * (lam[i] - (Lh[i][0] * C[0] + Lh[i][1] * C[1] + Lh[i][2] * C[2]));
    L->wake_skew_rad = skew;
    hfm_wake w;
    hfm_rotor_wake(ac, &in, skew, u, b, &w);
    return hfm_eval_rest(ac, &k, b, u, &w, L);
}

int hfm_rotor_disk(const hfm_aircraft *ac, const hfm_air *air, double t_s, const hfm_body *b,
                   const hfm_controls *u, const hfm_rotor_harm *rh, int nr, int npsi,
                   hfm_disk *out)
{
    const hfm_mr *mr = &ac->mr;
    if (nr < 1 || nr > 64 || npsi < 4 || npsi > 72)
        return -1;
    hfm_kin k;
    hfm_rotor_in in;
    hfm_kin_setup(&k, air, t_s, b);
    double lam[3] = {rh->lambda0, rh->lambda1s, rh->lambda1c};
    if (hfm_rotor_setup(ac, &k, u, lam, &in))
        return -1;
    memset(out, 0, sizeof *out);
    out->nr = nr;
    out->npsi = npsi;
    out->sense = mr->sense;
    memcpy(out->hub_S_m, in.hub_S, sizeof out->hub_S_m);
    core_mat3 m;
    memcpy(m.m, in.C_SH, sizeof m.m);
    /* rotation matrix -> quaternion (Shepperd) */
    double tr = m.m[0][0] + m.m[1][1] + m.m[2][2];
    core_quat q;
    if (tr > 0) {
        double S = sqrt(tr + 1.0) * 2.0;
        q.w = 0.25 * S;
        q.x = (m.m[2][1] - m.m[1][2]) / S;
        q.y = (m.m[0][2] - m.m[2][0]) / S;
        q.z = (m.m[1][0] - m.m[0][1]) / S;
    } else if (m.m[0][0] > m.m[1][1] && m.m[0][0] > m.m[2][2]) {
        double S = sqrt(1.0 + m.m[0][0] - m.m[1][1] - m.m[2][2]) * 2.0;
        q.w = (m.m[2][1] - m.m[1][2]) / S;
        q.x = 0.25 * S;
        q.y = (m.m[0][1] + m.m[1][0]) / S;
        q.z = (m.m[0][2] + m.m[2][0]) / S;
    } else if (m.m[1][1] > m.m[2][2]) {
        double S = sqrt(1.0 + m.m[1][1] - m.m[0][0] - m.m[2][2]) * 2.0;
        q.w = (m.m[0][2] - m.m[2][0]) / S;
        q.x = (m.m[0][1] + m.m[1][0]) / S;
        q.y = 0.25 * S;
        q.z = (m.m[1][2] + m.m[2][1]) / S;
    } else {
        double S = sqrt(1.0 + m.m[2][2] - m.m[0][0] - m.m[1][1]) * 2.0;
        q.w = (m.m[1][0] - m.m[0][1]) / S;
        q.x = (m.m[0][2] + m.m[2][0]) / S;
        q.y = (m.m[1][2] + m.m[2][1]) / S;
        q.z = 0.25 * S;
    }
    out->q_SH = core_quat_normalize(q);
    double drc = (mr->R - mr->root) / nr;
    for (int i = 0; i < nr; i++)
        out->r_m[i] = mr->root + (i + 0.5) * drc;
    const double Om = mr->omega;
    for (int j = 0; j < npsi; j++) {
        double psi = 2.0 * CORE_PI * (j + 0.5) / npsi;
        double beta, db, ddb;
        hfm_rotor_harm_beta(rh, Om, psi, &beta, &db, &ddb);
        hfm_blade_out o;
        double dT[HFM_MAX_SEG], dS[HFM_MAX_SEG];
        if (hfm_rotor_blade(ac, &in, psi, beta, db, ddb, 0, &o, dT, dS))
            return -1;
        out->thrust_N += o.T * mr->nb / npsi;
        out->power_W += o.P * mr->nb / npsi;
        for (int i = 0; i < nr; i++) {
            /* loading per unit span at the cell centre, linear between segments */
            double r = out->r_m[i];
            int a = 0;
            while (a < mr->nseg - 2 && mr->r[a + 1] < r)
                a++;
            double f = (r - mr->r[a]) / (mr->r[a + 1] - mr->r[a]);
            f = clampd(f, 0.0, 1.0);
            double t = (1 - f) * dT[a] / mr->drd[a] + f * dT[a + 1] / mr->drd[a + 1];
            double w = (1 - f) * dS[a] / mr->drd[a] + f * dS[a + 1] / mr->drd[a + 1];
            out->thrust_Pa[i * npsi + j] = mr->nb * t / (2.0 * CORE_PI * r);
            out->swirl_Pa[i * npsi + j] = mr->nb * w / (2.0 * CORE_PI * r);
        }
    }
    return 0;
}
