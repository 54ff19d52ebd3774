/* linear.c -- linearisation at a trim and its eigenvalues.
 *
 * x' = f(x, u) with x = [u v w p q r phi theta psi] relative to S and the
 * rotor quasi-steady: at each perturbed point the flapping harmonics and the
 * Pitt-Peters inflow are re-solved (Newton on their six equations) before
 * the body accelerations are taken (Padfield, "Helicopter Flight Dynamics",
 * ch. 4.2, 6-DOF derivatives with rotor states eliminated). A and B by
 * central differences; eigenvalues by LAPACK dgeev. Modes are named from
 * their eigenvectors (velocities over 5 m/s, rates and angles in rad):
 * longitudinal (u, w, q, theta) or lateral-directional (v, p, r, phi, psi).
 */
#include "hfm_priv.h"

#include <lapacke.h>
#include <stdio.h>
#include <string.h>

typedef struct lin_user {
    const hfm_aircraft *ac;
    hfm_air air;
    hfm_body b;
    hfm_controls u;
} lin_user;

static int rotor_fn(void *user, const double *x, double lam, double *f)
{
    (void)lam;
    lin_user *s = user;
    hfm_rotor_harm rh = {x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7]};
    hfm_loads L;
    if (hfm_eval_harmonic(s->ac, &s->air, 0.0, &s->b, &s->u, &rh, &L))
        return -1;
    for (int i = 0; i < 3; i++) {
        f[i] = L.flap_res[i];
        f[3 + i] = L.inflow_res[i];
    }
    f[6] = L.flap_res[3];
    f[7] = L.flap_res[4];
    return 0;
}

/* f(x, u) with quasi-steady rotor, starting the rotor solve from rh0. */
static int model_f(const hfm_aircraft *ac, const hfm_air *air, const hfm_body *b0,
                   const double *x, const hfm_controls *u, const hfm_rotor_harm *rh0, double *xd)
{
    lin_user s = {ac, *air, *b0, *u};
    memcpy(s.b.vel_B_mps, x, 3 * sizeof(double));
    memcpy(s.b.rate_B_radps, x + 3, 3 * sizeof(double));
    memcpy(s.b.euler_rad, x + 6, 3 * sizeof(double));
    double r[8] = {rh0->beta0_rad, rh0->beta1c_rad, rh0->beta1s_rad, rh0->lambda0,
                   rh0->lambda1s,  rh0->lambda1c,  rh0->beta2c_rad,  rh0->beta2s_rad};
    static const double dx[8] = {1e-6, 1e-6, 1e-6, 1e-7, 1e-7, 1e-7, 1e-6, 1e-6};
    hfm_newton_opts o = {30, 1e-12, dx};
    hfm_newton_info inf;
    if (hfm_newton(rotor_fn, &s, 8, r, 0.0, &o, &inf) < 0 || !inf.converged)
        return -1;
    hfm_rotor_harm rh = {r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7]};
    hfm_loads L;
    if (hfm_eval_harmonic(ac, air, 0.0, &s.b, u, &rh, &L))
        return -1;
    memcpy(xd, L.acc_B, 6 * sizeof(double));
    double ph = x[6], th = x[7], p = x[3], q = x[4], rr = x[5];
    xd[6] = p + (q * sin(ph) + rr * cos(ph)) * tan(th);
    xd[7] = q * cos(ph) - rr * sin(ph);
    xd[8] = (q * sin(ph) + rr * cos(ph)) / cos(th);
    return 0;
}

static void name_mode(double re, double im, const double *v, int hover, char *out)
{
    /* v: eigenvector magnitudes per state (velocities over 5 m/s) */
    int k = 0; /* dominant state; heading only for the neutral mode */
    for (int i = 1; i < HFM_LIN_NX - 1; i++)
        if (v[i] > v[k])
            k = i;
    if (v[8] > 10.0 * v[k])
        k = 8;
    const char *n;
    if (fabs(re) < 1e-6 && fabs(im) < 1e-6)
        n = k == 8 ? "heading (neutral)" : "neutral";
    else if (im == 0.0) {
        static const char *real_names[HFM_LIN_NX] = {
            "speed subsidence", "spiral",           "heave subsidence", "roll subsidence",
            "pitch subsidence", "yaw subsidence",   "spiral",           "speed/pitch",
            "spiral"};
        n = real_names[k];
    } else {
        double lon = v[0] + v[2] + v[4] + v[7], lat = v[1] + v[3] + v[5] + v[6] + v[8];
        if (k == 2)
            n = "heave-yaw oscillation";
        else if (hover) /* below 15 m/s: the coupled hover oscillations */
            n = lon >= lat ? "hover longitudinal osc." : "hover lateral osc.";
        else if (lon >= lat)
            n = fabs(im) < 1.0 ? "phugoid (longitudinal)" : "short period";
        else
            n = (v[3] + v[6] > v[1] + v[5]) ? "lateral oscillation" : "dutch roll";
    }
    snprintf(out, 32, "%s", n);
}

int hfm_linearise(hfm_trim *tr, const hfm_trim_cond *c, const hfm_trim_result *t,
                  hfm_linear *lin)
{
    const hfm_aircraft *ac = hfm_trim_aircraft(tr);
    hfm_air_uniform wind;
    hfm_air air;
    hfm_trim_cond_air(c, &wind, &air);
    double x0[HFM_LIN_NX], xp[HFM_LIN_NX], fp[HFM_LIN_NX], fm[HFM_LIN_NX];
    memcpy(x0, t->body.vel_B_mps, 3 * sizeof(double));
    memcpy(x0 + 3, t->body.rate_B_radps, 3 * sizeof(double));
    memcpy(x0 + 6, t->body.euler_rad, 3 * sizeof(double));
    static const double hx[HFM_LIN_NX] = {0.05, 0.05, 0.05, 0.002, 0.002, 0.002,
                                          0.002, 0.002, 0.002};
    for (int j = 0; j < HFM_LIN_NX; j++) {
        memcpy(xp, x0, sizeof xp);
        xp[j] = x0[j] + hx[j];
        if (model_f(ac, &air, &t->body, xp, &t->u, &t->rotor, fp))
            return -1;
        xp[j] = x0[j] - hx[j];
        if (model_f(ac, &air, &t->body, xp, &t->u, &t->rotor, fm))
            return -1;
        for (int i = 0; i < HFM_LIN_NX; i++)
            lin->A[i * HFM_LIN_NX + j] = (fp[i] - fm[i]) / (2.0 * hx[j]);
    }
    for (int j = 0; j < HFM_LIN_NU; j++) {
        hfm_controls up = t->u, um = t->u;
        double *pp = &up.collective_pct + j, *pm = &um.collective_pct + j;
        *pp += 0.1;
        *pm -= 0.1;
        if (model_f(ac, &air, &t->body, x0, &up, &t->rotor, fp) ||
            model_f(ac, &air, &t->body, x0, &um, &t->rotor, fm))
            return -1;
        for (int i = 0; i < HFM_LIN_NX; i++)
            lin->B[i * HFM_LIN_NU + j] = (fp[i] - fm[i]) / 0.2;
    }
    double A[HFM_LIN_NX * HFM_LIN_NX], vr[HFM_LIN_NX * HFM_LIN_NX], vl[1];
    memcpy(A, lin->A, sizeof A);
    if (LAPACKE_dgeev(LAPACK_ROW_MAJOR, 'N', 'V', HFM_LIN_NX, A, HFM_LIN_NX, lin->eig_re,
                      lin->eig_im, vl, 1, vr, HFM_LIN_NX) != 0)
        return -1;
    static const double sc[HFM_LIN_NX] = {0.2, 0.2, 0.2, 1, 1, 1, 1, 1, 1};
    for (int j = 0; j < HFM_LIN_NX; j++) {
        double mag[HFM_LIN_NX];
        int jr = j, ji = -1;
        if (lin->eig_im[j] > 0)
            ji = j + 1;
        else if (lin->eig_im[j] < 0) {
            jr = j - 1;
            ji = j;
        }
        for (int i = 0; i < HFM_LIN_NX; i++) {
            double re = vr[i * HFM_LIN_NX + jr], im = ji >= 0 ? vr[i * HFM_LIN_NX + ji] : 0.0;
            mag[i] = hypot(re, im) * sc[i];
        }
        double V = sqrt(x0[0] * x0[0] + x0[1] * x0[1] + x0[2] * x0[2]);
        name_mode(lin->eig_re[j], lin->eig_im[j], mag, V < 15.0, lin->mode[j]);
    }
    return 0;
}
