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
 * blade is evaluated at its own azimuth and the flapping integrated
 * (tsim.c, multiblade coordinates). Hub loads per blade: the hinge force
 * (aerodynamic + centrifugal + flap inertia) times the offset, plus the
 * moment at the hinge whose flap component is the spring's.
 *
 * Evaluation (same results, less work): element positions and velocities
 * are linear in the span coordinate, so in the uniform wind (sampled once,
 * hfm_air_uniform_fn recognised) U_T and U_P are too; any other air
 * callback is sampled at every element. The elements of all the blades of
 * one evaluation go through vectorisable passes over arrays (velocities, a
 * branch-free polynomial atan2, forces); only the airfoil lookup is scalar
 * (and an AVX2 version of these passes is chosen at load time where the
 * processor has it, with the same results).
 *
 * Pitt-Peters 3-state inflow (Peters and HaQuang, JAHS 33(4), 1988):
 *   M lambda'/Omega + Lhat^-1 lambda = (CT, CL, CM),
 *   Lhat = [[1/(2VT), 0, k/VM], [0, c/VM, 0], [k/VT, 0, c cos chi/VM]],
 *   k = 15 pi/64 tan(chi/2), c = 4/(1 + cos chi), M = diag(8/(3pi), 16/(45pi), 16/(45pi)),
 * (chi held at <= 70 deg in L, see hfm_rotor_inflow), with CL, CM the first moments of the thrust in sin psi and cos psi (signed so
 * that a positive moment raises the inflow where its harmonic is positive).
 * Lhat is written in wind axes (Peters and HaQuang: azimuth from the
 * downstream direction of the in-plane air at the hub) and turned to the
 * hub's azimuth, so that a side wind skews the wake to the side; with the
 * in-plane speed's direction folded into k's components the inflow is
 * smooth through the hover (no term in |mu| alone).
 *
 * Profile drag: the section's table (aircraft file, [main_rotor_airfoil])
 * gives cl and cd over the full circle of angle of attack: attached flow,
 * the stall and the post-stall flat plate (cd to 2.0 at 90 deg) and reversed
 * flow, at low Mach number. Where the file gives the drag divergence Mach
 * number at zero lift (drag_divergence_mach, M_dd0) the element's drag has
 * the compressible drag rise added at its Mach number M = U / a (U the
 * element's speed normal to the span, a = 340.29 m/s, ISA sea level):
 *   M_dd = M_dd0 - |cl| / 10     (Korn's equation M_dd + cl/10 + t/c =
 *          kappa_A for an unswept section, with t/c and the technology
 *          factor kappa_A, 0.87 conventional to 0.95 supercritical, folded
 *          into M_dd0 = kappa_A - t/c),
 *   M_cr = M_dd - (0.1 / 80)^(1/3),
 *   dcd  = 20 (M - M_cr)^4 for M > M_cr   (Lock's fourth-power drag-rise
 *          law; Korn's and Lock's relations together as in Gur, Mason and
 *          Schetz, "Full-configuration drag estimation", J. Aircraft 47(4),
 *          2010, wave-drag section), so that dcd/dM = 0.1 at M_dd, the
 *          usual definition of drag divergence (Prouty, "Helicopter Performance,
 *          Stability and Control", ch. 6, Fig. 6.28a, gives the measured
 *          zero-lift M_dd of rotor sections against thickness ratio; Leishman,
 *          "Principles of Helicopter Aerodynamics", 2nd ed., ch. 7, the drag
 *          rise of rotor airfoils with Mach number; section not checked here).
 * Assumptions: quasi-steady two-dimensional drag (no yawed-flow or
 * three-dimensional tip relief, no unsteady shock motion); the lift is
 * left incompressible (no Prandtl-Glauert factor: the aircraft files'
 * lift slopes are the [TM]/GenHel values the trim is validated with,
 * themselves without one), so the Mach number changes the profile power
 * and the in-plane force, not the lift.
 *
 * Hub drag: a flat-plate area f (main_rotor hub_drag_m2: the hub, blade
 * cuffs and the hub-pylon interference) at the hub centre along the air
 * relative to the hub, D = 1/2 rho f |v| v (Prouty, sec. 5, parasite drag
 * as equivalent flat-plate areas of the components, section not checked
 * here); the rotor's induced
 * velocity at the hub is not in v. It is carried by the blades' hub loads,
 * a share f / N_b each, so that any sum over the blades (the trim's
 * azimuth quadrature, the time simulation's N_b blades) carries it once.
 */
#include "hfm_priv.h"

#include <string.h>

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
    for (int i = 0; i < 3; i++) {
        in->rel_hub_H[i] = a_H[i] - in->vhub_H[i];
        in->air_H[i] = a_H[i];
        in->wake_rel_H[i] = in->rel_hub_H[i];
    }
    if (k->air->wake) {
        double w_S[3], w_H[3];
        if (k->air->wake->fn(k->air->wake->user, in->hub_S, k->t, w_S))
            return -1;
        m3_tmul(in->C_SH, w_S, w_H);
        for (int i = 0; i < 3; i++)
            in->wake_rel_H[i] = w_H[i] - in->vhub_H[i];
    }
    /* The uniform wind is the same at every element: one sample (above)
     * stands for all of them, with the same result as sampling each. */
    in->uniform = k->air->fn == hfm_air_uniform_fn;
    return 0;
}

/* sin and cos of a flap angle: a Taylor polynomial to the 11th/12th power
 * (error below 1e-12 for |beta| <= 0.6 rad), libm beyond. */
static inline void flap_sincos(double b, double *sb, double *cb)
{
    if (fabs(b) > 0.6) {
        *sb = sin(b);
        *cb = cos(b);
        return;
    }
    double x = b * b;
    *sb = b * (1.0 + x * (-1.0 / 6 + x * (1.0 / 120 + x * (-1.0 / 5040 + x * (1.0 / 362880 +
                                                                             x * (-1.0 / 39916800))))));
    *cb = 1.0 + x * (-0.5 + x * (1.0 / 24 + x * (-1.0 / 720 + x * (1.0 / 40320 +
                                                                   x * (-1.0 / 3628800 +
                                                                        x * (1.0 / 479001600))))));
}

/* One blade's geometry and the coefficients of its element velocities. */
typedef struct blade_geo {
    double c, sn, beta, dbeta, sb, cb;
    double er[3], et[3], erp[3], eup[3];
    double tw0;                /* pitch at r = 0 (with the twist reference) */
    double UT0, UT1, UP0, UP1; /* U_T, U_P = U_0 + x U_1 (uniform wind part) */
    double a0[3], b0[3];       /* element position in S: a0 + x b0 */
} blade_geo;

static void blade_pre(const hfm_aircraft *ac, const hfm_rotor_in *in, double c, double sn,
                      double beta, double dbeta, blade_geo *g)
{
    const hfm_mr *mr = &ac->mr;
    const double s = mr->sense, Om = mr->omega, OR = mr->omega * mr->R, e = mr->e;
    double sb, cb;
    flap_sincos(beta, &sb, &cb);
    g->c = c;
    g->sn = sn;
    g->beta = beta;
    g->dbeta = dbeta;
    g->sb = sb;
    g->cb = cb;
    const double er[3] = {-c, s * sn, 0.0}, et[3] = {sn, s * c, 0.0};
    const double erp[3] = {-c * cb, s * sn * cb, -sb}, eup[3] = {c * sb, -s * sn * sb, -cb};
    memcpy(g->er, er, sizeof er);
    memcpy(g->et, et, sizeof et);
    memcpy(g->erp, erp, sizeof erp);
    memcpy(g->eup, eup, sizeof eup);
    const double wt[3] = {in->rate_H[0], in->rate_H[1], in->rate_H[2] - s * Om};
    const double th = in->theta0 - s * in->A1 * c - in->B1 * sn;
    const double lam_s = in->lam[1] * sn + in->lam[2] * c;
    /* Element position and velocity are linear in x = r - e along the
     * blade: p = e e_r + x e_r', v = v0 + x v1; positions in S likewise.
     * With the inflow linear in r, the velocity components normal to the
     * span (U_T in the disk, U_P normal to the blade) are linear in x too
     * in a uniform wind: U = U_0 + x U_1 with the air sampled per element
     * only when it varies. Sums of dF and x dF (along e_up and e_t) give
     * the forces, moments and power after the element loop. */
    double wer[3], werp[3], v0[3], v1[3];
    v3_cross(wt, er, wer);
    v3_cross(wt, erp, werp);
    for (int j = 0; j < 3; j++) {
        v0[j] = in->vhub_H[j] + e * wer[j];
        v1[j] = werp[j] + dbeta * eup[j];
    }
    g->tw0 = th - mr->twist * mr->twist_ref;
    const double l0 = in->lam[0] * OR, ls = lam_s * OR / mr->R;
    /* U_T = -(air - v).e_t, U_P = -(air - v).e_up, air_z += l0 + r ls */
    g->UT0 = v3_dot(v0, et);
    g->UT1 = v3_dot(v1, et);
    g->UP0 = v3_dot(v0, eup) + (l0 + e * ls) * cb;
    g->UP1 = v3_dot(v1, eup) + ls * cb;
    if (in->uniform) {
        g->UT0 -= v3_dot(in->air_H, et);
        g->UP0 -= v3_dot(in->air_H, eup);
    } else {
        double t3[3] = {e * er[0], e * er[1], e * er[2]};
        m3_mul(in->C_SH, t3, g->a0);
        m3_mul(in->C_SH, erp, g->b0);
        for (int j = 0; j < 3; j++)
            g->a0[j] += in->hub_S[j];
    }
}

/* The elements of nbl <= HFM_MAX_BLADES blades, element k = b ns + i, in
 * passes over arrays, so that the arithmetic (velocities, a branch-free
 * polynomial atan2, forces) vectorises over all of them and only the
 * airfoil table lookup stays scalar. Fu, Ft: force along e_up and e_t. */
/* Compiled for AVX2 and for the baseline, chosen when the program loads
 * (GCC function multi-versioning): 4 doubles per vector instead of 2 in the
 * sqrt and division bound passes. No FMA (ISO C mode: no contraction), so
 * both versions give bitwise the same results. */
__attribute__((target_clones("avx2", "default")))
static int blade_elements(const hfm_aircraft *ac, const hfm_rotor_in *in, int nbl,
                          const blade_geo *g, double *Fu, double *Ft)
{
    const hfm_mr *mr = &ac->mr;
    const int ns = mr->nseg, K = nbl * ns;
    double UT[HFM_MAX_BLADES * HFM_MAX_SEG], UP[HFM_MAX_BLADES * HFM_MAX_SEG],
        th[HFM_MAX_BLADES * HFM_MAX_SEG], U[HFM_MAX_BLADES * HFM_MAX_SEG],
        cl[HFM_MAX_BLADES * HFM_MAX_SEG], cd[HFM_MAX_BLADES * HFM_MAX_SEG],
        dl[HFM_MAX_BLADES * HFM_MAX_SEG], dd[HFM_MAX_BLADES * HFM_MAX_SEG];
    for (int b = 0; b < nbl; b++) {
        const blade_geo *gb = g + b;
        double *ut = UT + b * ns, *up = UP + b * ns, *tb = th + b * ns;
        double *lb = dl + b * ns, *db = dd + b * ns;
        for (int i = 0; i < ns; i++) {
            ut[i] = gb->UT0 + mr->x[i] * gb->UT1;
            up[i] = gb->UP0 + mr->x[i] * gb->UP1;
            tb[i] = gb->tw0 + mr->tw[i];
            lb[i] = mr->drl[i];
            db[i] = mr->drd[i];
        }
        if (!in->uniform)
            for (int i = 0; i < ns; i++) {
                const double x = mr->x[i];
                double pS[3] = {gb->a0[0] + x * gb->b0[0], gb->a0[1] + x * gb->b0[1],
                                gb->a0[2] + x * gb->b0[2]},
                       aS[3], aH[3];
                if (in->air->fn(in->air->user, pS, in->t, aS))
                    return -1;
                m3_tmul(in->C_SH, aS, aH);
                ut[i] -= v3_dot(aH, gb->et);
                up[i] -= v3_dot(aH, gb->eup);
            }
    }
    /* Angle of attack alpha = pitch - phi, phi = atan2(U_P, U_T) over the
     * full circle (reversed flow), without branches: with U = |(U_T, U_P)|,
     * p = 2 atan(U_P / (U + |U_T|)) lies in [-pi/2, pi/2]; phi = p for
     * U_T >= 0 and phi = sign(U_P) pi - p for U_T < 0 (half-angle formula).
     * atan on [-1, 1] by a minimax polynomial (max error 1e-5 rad, far below
     * the 1 deg airfoil grid). */
    for (int k = 0; k < K; k++) {
        const double ut = UT[k], up = UP[k];
        const double u = sqrt(ut * ut + up * up);
        const double q = up / (u + fabs(ut) + 1e-300), q2 = q * q;
        const double p = 2.0 * (((((-0.01172120 * q2 + 0.05265332) * q2 - 0.11643287) * q2 +
                                   0.19354346) * q2 - 0.33262347) * q2 * q + 0.99997726 * q);
        const double neg = 0.5 * (1.0 - copysign(1.0, ut));
        U[k] = u;
        th[k] -= p + neg * (copysign(CORE_PI, up) - 2.0 * p);
    }
    for (int k = 0; k < K; k++) {
        double al = th[k];
        if (al > CORE_PI)
            al -= 2.0 * CORE_PI;
        else if (al < -CORE_PI)
            al += 2.0 * CORE_PI;
        hfm_airfoil_eval(&mr->af, al, &cl[k], &cd[k]);
    }
    /* compressible drag rise (see the header): Korn's M_dd, Lock's law */
    if (mr->af.mach) {
        const double ia = 1.0 / 340.294, m0 = mr->af.mdd0 - 0.10772173450159418;
        for (int k = 0; k < K; k++) {
            double x = fmax(U[k] * ia - (m0 - 0.1 * fabs(cl[k])), 0.0);
            x *= x;
            cd[k] += 20.0 * x * x;
        }
    }
    /* L = q c cl dr, D = q c cd dr normal and along the element velocity:
     * F_up = L cos(phi) - D sin(phi), F_t = -L sin(phi) - D cos(phi) */
    for (int k = 0; k < K; k++) {
        const double h = mr->hqc * U[k], l = cl[k] * dl[k], d = cd[k] * dd[k];
        Fu[k] = h * (l * UT[k] - d * UP[k]);
        Ft[k] = -h * (l * UP[k] + d * UT[k]);
    }
    return 0;
}

/* Hub loads, flap moment, thrust moments and power of one blade from its
 * element forces (see hfm_rotor_blade). */
static void blade_post(const hfm_aircraft *ac, const hfm_rotor_in *in, const blade_geo *g,
                       const double *Fua, const double *Fta, double ddbeta, int solve_dd,
                       hfm_blade_out *o)
{
    const hfm_mr *mr = &ac->mr;
    const double s = mr->sense, Om = mr->omega, e = mr->e;
    const double c = g->c, sn = g->sn, sb = g->sb, cb = g->cb, beta = g->beta,
                 dbeta = g->dbeta;
    const double *er = g->er, *et = g->et, *erp = g->erp, *eup = g->eup;
    const double Omv[3] = {0.0, 0.0, -s * Om};
    double SFu = 0, SFt = 0, SxFu = 0, SxFt = 0;
    for (int i = 0; i < mr->nseg; i++) {
        SFu += Fua[i];
        SFt += Fta[i];
        SxFu += mr->x[i] * Fua[i];
        SxFt += mr->x[i] * Fta[i];
    }
    double F[3], Fx[3], Mflap = SxFu;
    for (int j = 0; j < 3; j++) {
        F[j] = SFu * eup[j] + SFt * et[j];
        Fx[j] = SxFu * eup[j] + SxFt * et[j];
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
        ddbeta = (Mflap + o->G) * mr->inv_I_beta;
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
    o->Lr = Lr * mr->inv_R;
    o->Mp = Mp * mr->inv_R;
    o->P = P;
}


int hfm_rotor_blade(const hfm_aircraft *ac, const hfm_rotor_in *in, double c, double sn,
                    double beta, double dbeta, double ddbeta, int solve_dd, hfm_blade_out *o,
                    double *dT, double *dS)
{
    blade_geo g;
    double Fu[HFM_MAX_SEG], Ft[HFM_MAX_SEG];
    blade_pre(ac, in, c, sn, beta, dbeta, &g);
    if (blade_elements(ac, in, 1, &g, Fu, Ft))
        return -1;
    if (dT)
        for (int i = 0; i < ac->mr.nseg; i++) {
            dT[i] = -(Fu[i] * g.eup[2] + Ft[i] * g.et[2]);
            dS[i] = -Ft[i];
        }
    blade_post(ac, in, &g, Fu, Ft, ddbeta, solve_dd, o);
    return 0;
}

int hfm_rotor_blades(const hfm_aircraft *ac, const hfm_rotor_in *in, int nbl,
                     const double *cos_psi, const double *sin_psi, const double *beta,
                     const double *dbeta, const double *ddbeta, hfm_blade_out *o)
{
    const int ns = ac->mr.nseg;
    for (int b0 = 0; b0 < nbl; b0 += HFM_MAX_BLADES) {
        int m = nbl - b0 < HFM_MAX_BLADES ? nbl - b0 : HFM_MAX_BLADES;
        blade_geo g[HFM_MAX_BLADES];
        double Fu[HFM_MAX_BLADES * HFM_MAX_SEG], Ft[HFM_MAX_BLADES * HFM_MAX_SEG];
        for (int b = 0; b < m; b++)
            blade_pre(ac, in, cos_psi[b0 + b], sin_psi[b0 + b], beta[b0 + b], dbeta[b0 + b],
                      &g[b]);
        if (blade_elements(ac, in, m, g, Fu, Ft))
            return -1;
        for (int b = 0; b < m; b++)
            blade_post(ac, in, &g[b], Fu + b * ns, Ft + b * ns, ddbeta ? ddbeta[b0 + b] : 0.0,
                       ddbeta == NULL, &o[b0 + b]);
    }
    /* the hub's drag, a share per blade (see the header) */
    if (ac->mr.hub_dq > 0.0) {
        const double *v = in->rel_hub_H, h = ac->mr.hub_dq * sqrt(v3_dot(v, v));
        for (int b = 0; b < nbl; b++)
            for (int j = 0; j < 3; j++)
                o[b].F_H[j] += h * v[j];
    }
    return 0;
}

/* Shaft power: what the drive train delivers to the main and tail rotors;
 * engine power: shaft power through the transmission's efficiency plus the
 * accessories ([power] of the aircraft file). A rotor that gives power back
 * (autorotation) is counted as it comes, negative. */
void hfm_loads_power(const hfm_aircraft *ac, hfm_loads *L)
{
    L->shaft_power_W = L->mr_power_W + L->tr_power_W;
    L->engine_power_W = L->shaft_power_W / ac->xmsn_eff + ac->acc_W;
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
    double chi = skew ? atan2(mu, ltp) : 0.0;
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
    /* Lhat in wind axes (psi_w from the downstream direction of the
     * in-plane air at the hub), turned to the hub's azimuth: the blade at
     * psi points downstream (-cos psi, s sin psi) = d at psi_d, cos psi_d =
     * -d_x, sin psi_d = s d_y, and (lambda1s, lambda1c) = R(psi_d)
     * (lambda1s_w, lambda1c_w), (CL_w, CM_w) = R^T (CL, CM); so Lhat =
     * Q Lhat_w Q^T with Q = diag(1, R). In hover the direction is
     * undefined, and k (proportional to mu) and the difference of the two
     * harmonic terms (to mu^2) vanish there: with k cos psi_d and k sin psi_d
     * taken from the velocity components, Lhat is smooth through mu = 0. */
    double cd = 1.0, sd = 0.0, hm = hypot(in->rel_hub_H[0], in->rel_hub_H[1]);
    if (hm > 0.0) {
        cd = -in->rel_hub_H[0] / hm;
        sd = mr->sense * in->rel_hub_H[1] / hm;
    }
    const double a = 1.0 / (2.0 * VT), b = k / VM, e = k / VT, c1 = cc / VM, c2 = cc * cchl / VM;
    Lh[0][0] = a;
    Lh[0][1] = b * sd;
    Lh[0][2] = b * cd;
    Lh[1][0] = e * sd;
    Lh[1][1] = c1 * cd * cd + c2 * sd * sd;
    Lh[1][2] = (c2 - c1) * sd * cd;
    Lh[2][0] = e * cd;
    Lh[2][1] = Lh[1][2];
    Lh[2][2] = c1 * sd * sd + c2 * cd * cd;
    if (skew)
        *skew = chi;
}

void hfm_rotor_harm_beta(const hfm_rotor_harm *rh, double Om, double c, double s, double *b,
                         double *db, double *ddb)
{
    double c2 = c * c - s * s, s2 = 2.0 * s * c;
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
    /* the wake's geometry in the wake's air (hfm_air.wake), see hfm.h */
    const double *r = in->wake_rel_H;
    double h = sqrt(r[0] * r[0] + r[1] * r[1]);
    /* tan of the skew chi = atan2(mu, lambda) (hfm_rotor_inflow), held at 89 deg */
    double lt = r[2] + in->lam[0] * ac->mr.omega * ac->mr.R;
    lt = lt > 1e-6 * ac->mr.omega * ac->mr.R ? lt : 1e-6 * ac->mr.omega * ac->mr.R;
    w->tan_skew = fmin(h / lt, 57.289961630759425); /* tan 89 deg */
    w->vin_mps = h;
    w->vax_mps = r[2];
    w->u0_mps = sqrt(h * h + (r[2] + w->vi_mps) * (r[2] + w->vi_mps));
    w->sec_skew = sqrt(1.0 + w->tan_skew * w->tan_skew);
    w->dir_H[0] = h > 1e-6 ? r[0] / h : 0.0;
    w->dir_H[1] = h > 1e-6 ? r[1] / h : 0.0;
    w->coll_pct = u->collective_pct;
    w->q_degps = b->rate_B_radps[1] * CORE_RAD_TO_DEG;
    w->ay_g = 0.0;
    w->airspeed_kt = 0.0;
    w->tr_inflow = NULL;
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
    double be[HFM_MAX_AZ], dbe[HFM_MAX_AZ], ddbe[HFM_MAX_AZ];
    hfm_blade_out o[HFM_MAX_AZ];
    for (int j = 0; j < mr->naz; j++)
        hfm_rotor_harm_beta(rh, Om, mr->az_c[j], mr->az_s[j], &be[j], &dbe[j], &ddbe[j]);
    if (hfm_rotor_blades(ac, &in, mr->naz, mr->az_c, mr->az_s, be, dbe, ddbe, o))
        return -1;
    for (int j = 0; j < mr->naz; j++) {
        double c = mr->az_c[j], s = mr->az_s[j];
        for (int i = 0; i < 3; i++) {
            F[i] += o[j].F_H[i];
            M[i] += o[j].M_H[i];
        }
        T += o[j].T;
        Lr += o[j].Lr;
        Mp += o[j].Mp;
        P += o[j].P;
        double R = mr->I_beta * ddbe[j] - o[j].M_flap - o[j].G;
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
    if (hfm_eval_rest(ac, &k, b, u, &w, L))
        return -1;
    hfm_loads_power(ac, L);
    return 0;
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
        double psi = 2.0 * CORE_PI * (j + 0.5) / npsi, c = cos(psi), s = sin(psi);
        double beta, db, ddb;
        hfm_rotor_harm_beta(rh, Om, c, s, &beta, &db, &ddb);
        hfm_blade_out o;
        double dT[HFM_MAX_SEG], dS[HFM_MAX_SEG];
        if (hfm_rotor_blade(ac, &in, c, s, beta, db, ddb, 0, &o, dT, dS))
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
