/* tsim.c -- time simulation with SUNDIALS (6.x API): ARKODE explicit
 * Runge-Kutta at a fixed step (real time: Ralston's 2-stage, 2nd-order
 * table) or CVODE BDF (reference runs).
 *
 * State: position in S (3), u v w, p q r, phi theta psi, the Pitt-Peters
 * inflow (3), the rotor azimuth, and the blades' flapping as multiblade
 * coordinates and their rates (Johnson, "Helicopter Theory", sec. 8.4: for
 * nb blades, nb coordinates b0, b_nc, b_ns, b_d; an exact change of
 * variables, see mbc_basis). The blades turn with the azimuth: at each
 * right-hand side every blade is evaluated at its own azimuth
 * (hfm_rotor_blades) with the flap angle and rate the coordinates give it,
 * its flap acceleration comes from its own flap equation, the hub loads are
 * summed over the blades, and the blade accelerations are projected back on
 * the coordinates. Why the coordinates: in the fixed frame they are nearly
 * constant in steady flight (the 1/rev blade motion becomes a tilt of the
 * disk), so a fixed-step explicit method integrates them with little
 * truncation error; the individual blade angles swing once per revolution
 * (7.7 deg of azimuth per 200 Hz step) and a 2-stage method drifted 1.5 m/s
 * and 2.8 deg in 10 s of hover on them (3 stages were needed).
 * Tail-rotor inflow (fixed step): Newton starts from the last evaluation's value.
 * Inflow dynamics (Pitt-Peters): lambda' = Omega M^-1 (C - Lhat^-1 lambda).
 * Euler rates: the seed paper's eq. (9) inverted. Controls are held between
 * calls (open loop).
 */
#include "hfm_priv.h"

#include <arkode/arkode_erkstep.h>
#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <stdlib.h>
#include <string.h>

enum { I_POS = 0, I_VEL = 3, I_RATE = 6, I_EUL = 9, I_LAM = 12, I_AZ = 15, I_BETA = 16 };

struct hfm_tsim {
    const hfm_aircraft *ac;
    hfm_air air;
    const core_log *log;
    int method, n;
    double h, rtol, t;
    hfm_controls u;
    SUNContext ctx;
    N_Vector y;
    void *mem;
    SUNMatrix A;
    SUNLinearSolver LS;
    long evals;
    double blade_c[HFM_MAX_BLADES], blade_s[HFM_MAX_BLADES]; /* blade i at az + 2 pi i / nb */
    double tr_inflow; /* tail-rotor inflow of the last evaluation: Newton's first guess */
    hfm_ext_fn ext;   /* external loads (NULL: none) */
    void *ext_user;
    double last_thrust_N, last_power_W; /* the main rotor's at the last right-hand side */
};

int hfm_tsim_size(const hfm_tsim *ts)
{
    return ts->n;
}

long hfm_tsim_rhs_evals(const hfm_tsim *ts)
{
    return ts->evals;
}

/* Multiblade coordinates (Johnson, "Helicopter Theory", sec. 8.4): for nb
 * blades at psi_i, beta_i = b0 + sum_n (b_nc cos n psi_i + b_ns sin n psi_i)
 * [+ b_d (-1)^i for an even nb], n = 1 .. (nb - 1)/2; coordinate k = 0 is
 * b0, k = 2n - 1 and 2n are b_nc and b_ns, k = nb - 1 is b_d (even nb).
 * An exact change of variables (nb coordinates for nb blades); phi gets the
 * basis at blade i, dphi its time derivative (Omega constant), so that
 * beta_i' = sum_k (q_k' phi_k + q_k dphi_k). */
static void mbc_basis(int nb, double Om, int i, double c, double s, double *phi, double *dphi)
{
    phi[0] = 1.0;
    dphi[0] = 0.0;
    double cn = c, sn = s;
    for (int n = 1; 2 * n < nb; n++) {
        phi[2 * n - 1] = cn;
        phi[2 * n] = sn;
        dphi[2 * n - 1] = -n * Om * sn;
        dphi[2 * n] = n * Om * cn;
        double t = cn * c - sn * s;
        sn = sn * c + cn * s;
        cn = t;
    }
    if (nb % 2 == 0) {
        phi[nb - 1] = (i % 2) ? -1.0 : 1.0;
        dphi[nb - 1] = 0.0;
    }
}

int hfm_tsim_rhs(hfm_tsim *ts, double t, const double *y, double *yd)
{
    const hfm_aircraft *ac = ts->ac;
    const hfm_mr *mr = &ac->mr;
    const int nb = mr->nb;
    ts->evals++;
    hfm_body b;
    memcpy(b.pos_S_m, y + I_POS, sizeof b.pos_S_m);
    memcpy(b.vel_B_mps, y + I_VEL, sizeof b.vel_B_mps);
    memcpy(b.rate_B_radps, y + I_RATE, sizeof b.rate_B_radps);
    memcpy(b.euler_rad, y + I_EUL, sizeof b.euler_rad);
    hfm_kin k;
    hfm_rotor_in in;
    hfm_loads L;
    hfm_kin_setup(&k, &ts->air, t, &b);
    if (hfm_rotor_setup(ac, &k, &ts->u, y + I_LAM, &in))
        return -1;
    double F[3] = {0, 0, 0}, M[3] = {0, 0, 0}, T = 0, Lr = 0, Mp = 0, P = 0;
    /* one sin/cos of the azimuth; the other blades by their fixed offsets */
    const double ca = cos(y[I_AZ]), sa = sin(y[I_AZ]);
    const double *qm = y + I_BETA, *qd = y + I_BETA + nb;
    double phi[HFM_MAX_BLADES][HFM_MAX_BLADES], dphi[HFM_MAX_BLADES][HFM_MAX_BLADES];
    double Q[HFM_MAX_BLADES] = {0}, cb[HFM_MAX_BLADES], sb[HFM_MAX_BLADES];
    double be[HFM_MAX_BLADES], dbe[HFM_MAX_BLADES];
    for (int i = 0; i < nb; i++) {
        cb[i] = ca * ts->blade_c[i] - sa * ts->blade_s[i];
        sb[i] = sa * ts->blade_c[i] + ca * ts->blade_s[i];
        /* the blade's flap angle and rate from the multiblade coordinates */
        mbc_basis(nb, mr->omega, i, cb[i], sb[i], phi[i], dphi[i]);
        double bi = 0.0, dbi = 0.0;
        for (int k2 = 0; k2 < nb; k2++) {
            bi += qm[k2] * phi[i][k2];
            dbi += qd[k2] * phi[i][k2] + qm[k2] * dphi[i][k2];
        }
        be[i] = bi;
        dbe[i] = dbi;
    }
    hfm_blade_out o[HFM_MAX_BLADES];
    if (hfm_rotor_blades(ac, &in, nb, cb, sb, be, dbe, NULL, o))
        return -1;
    for (int i = 0; i < nb; i++) {
        for (int j = 0; j < 3; j++) {
            F[j] += o[i].F_H[j];
            M[j] += o[i].M_H[j];
        }
        T += o[i].T;
        Lr += o[i].Lr;
        Mp += o[i].Mp;
        P += o[i].P;
        for (int k2 = 0; k2 < nb; k2++)
            Q[k2] += o[i].ddbeta * phi[i][k2];
    }
    /* multiblade accelerations: the projection of the blades' flap
     * accelerations less the azimuth's Coriolis and centripetal terms */
    for (int k2 = 0; k2 < nb; k2++) {
        int n = (k2 + 1) / 2;
        double w = (k2 == 0 || (nb % 2 == 0 && k2 == nb - 1)) ? 1.0 : 2.0;
        double a = w * Q[k2] / nb;
        if (w == 2.0) {
            double nO = n * mr->omega;
            if (k2 % 2) /* cos n psi: + n^2 Omega^2 b_nc - 2 n Omega b_ns' */
                a += nO * nO * qm[k2] - 2.0 * nO * qd[k2 + 1];
            else /* sin n psi: + n^2 Omega^2 b_ns + 2 n Omega b_nc' */
                a += nO * nO * qm[k2] + 2.0 * nO * qd[k2 - 1];
        }
        yd[I_BETA + k2] = qd[k2];
        yd[I_BETA + nb + k2] = a;
    }
    hfm_rotor_to_body(ac, F, M, &L.mr);
    double OR = mr->omega * mr->R, q = mr->rho * mr->area * OR * OR;
    L.mr_thrust_N = -F[2];
    L.mr_power_W = P;
    ts->last_thrust_N = L.mr_thrust_N;
    ts->last_power_W = P;
    double C[3] = {T / q, Lr / q, Mp / q}, Lh[3][3];
    hfm_rotor_inflow(ac, &in, C[0], C[1], C[2], Lh, NULL);
    /* Lhat^-1 lambda by the adjugate (Lhat in hub axes is full: its wind
     * axes turned to the hub's, hfm_rotor_inflow; det Lhat = det Lhat_w > 0) */
    const double *lam = y + I_LAM;
    double Li[3][3];
    Li[0][0] = Lh[1][1] * Lh[2][2] - Lh[1][2] * Lh[2][1];
    Li[0][1] = Lh[0][2] * Lh[2][1] - Lh[0][1] * Lh[2][2];
    Li[0][2] = Lh[0][1] * Lh[1][2] - Lh[0][2] * Lh[1][1];
    Li[1][0] = Lh[1][2] * Lh[2][0] - Lh[1][0] * Lh[2][2];
    Li[1][1] = Lh[0][0] * Lh[2][2] - Lh[0][2] * Lh[2][0];
    Li[1][2] = Lh[0][2] * Lh[1][0] - Lh[0][0] * Lh[1][2];
    Li[2][0] = Lh[1][0] * Lh[2][1] - Lh[1][1] * Lh[2][0];
    Li[2][1] = Lh[0][1] * Lh[2][0] - Lh[0][0] * Lh[2][1];
    Li[2][2] = Lh[0][0] * Lh[1][1] - Lh[0][1] * Lh[1][0];
    double det = Lh[0][0] * Li[0][0] + Lh[0][1] * Li[1][0] + Lh[0][2] * Li[2][0];
    double li0 = (Li[0][0] * lam[0] + Li[0][1] * lam[1] + Li[0][2] * lam[2]) / det;
    double li1 = (Li[1][0] * lam[0] + Li[1][1] * lam[1] + Li[1][2] * lam[2]) / det;
    double li2 = (Li[2][0] * lam[0] + Li[2][1] * lam[1] + Li[2][2] * lam[2]) / det;
    const double m0 = 8.0 / (3.0 * CORE_PI), m1 = 16.0 / (45.0 * CORE_PI);
    yd[I_LAM + 0] = mr->omega * (C[0] - li0) / m0;
    yd[I_LAM + 1] = mr->omega * (C[1] - li1) / m1;
    yd[I_LAM + 2] = mr->omega * (C[2] - li2) / m1;
    yd[I_AZ] = mr->omega;
    hfm_wake w;
    hfm_rotor_wake(ac, &in, NAN, &ts->u, &b, &w); /* the components use tan_skew only */
    /* fixed-step runs only: a CVODE reference run keeps a right-hand side
     * that depends on its arguments alone (its Newton iterations and
     * difference-quotient Jacobians evaluate far-off trial states) */
    w.tr_inflow = ts->method == HFM_TSIM_ARKODE_FIXED ? &ts->tr_inflow : NULL;
    if (hfm_eval_rest(ac, &k, &b, &ts->u, &w, &L))
        return -1;
    if (ts->ext) {
        double Fe[3] = {0, 0, 0}, Me[3] = {0, 0, 0};
        if (ts->ext(ts->ext_user, t, &b, Fe, Me))
            return -1;
        for (int i = 0; i < 3; i++) {
            L.total.F_B_N[i] += Fe[i];
            L.total.M_B_Nm[i] += Me[i];
        }
        hfm_body_accel(ac, &b, &L);
    }
    double vS[3];
    m3_mul(k.C_SB, b.vel_B_mps, vS);
    for (int i = 0; i < 3; i++) {
        yd[I_POS + i] = vS[i];
        yd[I_VEL + i] = L.acc_B[i];
        yd[I_RATE + i] = L.acc_B[3 + i];
    }
    double p = b.rate_B_radps[0], qq = b.rate_B_radps[1], r = b.rate_B_radps[2];
    double sp = k.sphi, cp = k.cphi, ct = k.cth;
    yd[I_EUL + 0] = p + (qq * sp + r * cp) * k.sth / ct;
    yd[I_EUL + 1] = qq * cp - r * sp;
    yd[I_EUL + 2] = (qq * sp + r * cp) / ct;
    return 0;
}

/* Ralston's second-order explicit Runge-Kutta (the 2-stage method of least
 * truncation error bound; Ralston, Math. Comp. 16, 1962): c = (0, 2/3),
 * a21 = 2/3, b = (1/4, 3/4). */
/* Error weights: a fixed-step explicit run has no error test, so the weights
 * are a constant 1 rather than recomputed from the state at every step
 * (ARKODE still forms one norm of the state per step). */
static int unit_weights(N_Vector y, N_Vector ewt, void *user)
{
    (void)y;
    (void)user;
    N_VConst(1.0, ewt);
    return 0;
}

static int set_ralston(void *mem)
{
    double c[2] = {0.0, 2.0 / 3.0}, A[4] = {0.0, 0.0, 2.0 / 3.0, 0.0}, b[2] = {0.25, 0.75};
    ARKodeButcherTable B = ARKodeButcherTable_Create(2, 2, 0, c, A, b, NULL);
    if (!B)
        return -1;
    int rc = ERKStepSetTable(mem, B);
    ARKodeButcherTable_Free(B);
    return rc;
}

static int sun_rhs(sunrealtype t, N_Vector y, N_Vector yd, void *user)
{
    return hfm_tsim_rhs(user, t, N_VGetArrayPointer(y), N_VGetArrayPointer(yd)) ? -1 : 0;
}

hfm_tsim *hfm_tsim_create(const hfm_aircraft *ac, const hfm_air *air, int method, double h_s,
                          double rtol, const core_log *log)
{
    if (!ac || !air || !air->fn || (method == HFM_TSIM_ARKODE_FIXED && !(h_s > 0)))
        return NULL;
    hfm_tsim *ts = calloc(1, sizeof *ts);
    if (!ts)
        return NULL;
    ts->ac = ac;
    ts->air = *air;
    ts->log = log;
    ts->method = method;
    ts->h = h_s;
    ts->rtol = rtol > 0 ? rtol : 1e-6;
    ts->n = I_BETA + 2 * ac->mr.nb;
    for (int i = 0; i < ac->mr.nb; i++) {
        ts->blade_c[i] = cos(2.0 * CORE_PI * i / ac->mr.nb);
        ts->blade_s[i] = sin(2.0 * CORE_PI * i / ac->mr.nb);
    }
    if (SUNContext_Create(NULL, &ts->ctx)) {
        free(ts);
        return NULL;
    }
    ts->y = N_VNew_Serial(ts->n, ts->ctx);
    if (!ts->y) {
        hfm_tsim_destroy(ts);
        return NULL;
    }
    /* fused vector operations: one loop per Runge-Kutta combination (the
     * integrators' clones of y inherit the setting) */
    N_VEnableFusedOps_Serial(ts->y, SUNTRUE);
    N_VConst(0.0, ts->y);
    return ts;
}

void hfm_tsim_destroy(hfm_tsim *ts)
{
    if (!ts)
        return;
    if (ts->mem) {
        if (ts->method == HFM_TSIM_CVODE)
            CVodeFree(&ts->mem);
        else
            ERKStepFree(&ts->mem);
    }
    if (ts->LS)
        SUNLinSolFree(ts->LS);
    if (ts->A)
        SUNMatDestroy(ts->A);
    if (ts->y)
        N_VDestroy(ts->y);
    if (ts->ctx)
        SUNContext_Free(&ts->ctx);
    free(ts);
}

int hfm_tsim_init(hfm_tsim *ts, double t0, const hfm_body *b, const hfm_controls *u,
                  const hfm_rotor_harm *rh)
{
    double *y = N_VGetArrayPointer(ts->y);
    const hfm_mr *mr = &ts->ac->mr;
    memcpy(y + I_POS, b->pos_S_m, 3 * sizeof(double));
    memcpy(y + I_VEL, b->vel_B_mps, 3 * sizeof(double));
    memcpy(y + I_RATE, b->rate_B_radps, 3 * sizeof(double));
    memcpy(y + I_EUL, b->euler_rad, 3 * sizeof(double));
    y[I_LAM + 0] = rh->lambda0;
    y[I_LAM + 1] = rh->lambda1s;
    y[I_LAM + 2] = rh->lambda1c;
    y[I_AZ] = 0.0;
    /* blade flap angles and rates from the harmonics, then projected on
     * the multiblade coordinates (the inverse of mbc_basis's sums) */
    const int nb = mr->nb;
    double *q = y + I_BETA, *qd = y + I_BETA + nb;
    for (int k = 0; k < 2 * nb; k++)
        q[k] = 0.0;
    for (int i = 0; i < nb; i++) {
        double be, dbe, dd, phi[HFM_MAX_BLADES], dphi[HFM_MAX_BLADES];
        hfm_rotor_harm_beta(rh, mr->omega, ts->blade_c[i], ts->blade_s[i], &be, &dbe, &dd);
        mbc_basis(nb, mr->omega, i, ts->blade_c[i], ts->blade_s[i], phi, dphi);
        for (int k = 0; k < nb; k++) {
            double w = (k == 0 || (nb % 2 == 0 && k == nb - 1)) ? 1.0 : 2.0;
            q[k] += w * be * phi[k] / nb;
            qd[k] += w * dbe * phi[k] / nb;
        }
    }
    /* rates: the projection of beta_i' is q_k' + (the azimuth's part) */
    for (int n = 1; 2 * n < nb; n++) {
        double bc = q[2 * n - 1], bs = q[2 * n];
        qd[2 * n - 1] -= n * mr->omega * bs;
        qd[2 * n] += n * mr->omega * bc;
    }
    ts->u = *u;
    ts->t = t0;
    ts->tr_inflow = NAN;
    if (ts->mem) {
        if (ts->method == HFM_TSIM_CVODE)
            CVodeFree(&ts->mem);
        else
            ERKStepFree(&ts->mem);
    }
    if (ts->method == HFM_TSIM_CVODE) {
        ts->mem = CVodeCreate(CV_BDF, ts->ctx);
        /* the library reports through core_log, not SUNDIALS' stderr */
        if (!ts->mem || CVodeSetErrFile(ts->mem, NULL) || CVodeInit(ts->mem, sun_rhs, t0, ts->y) ||
            CVodeSetUserData(ts->mem, ts) || CVodeSStolerances(ts->mem, ts->rtol, 1e-8) ||
            CVodeSetMaxNumSteps(ts->mem, 1000000))
            return -1;
        if (!ts->A) {
            ts->A = SUNDenseMatrix(ts->n, ts->n, ts->ctx);
            ts->LS = SUNLinSol_Dense(ts->y, ts->A, ts->ctx);
            if (!ts->A || !ts->LS)
                return -1;
        }
        if (CVodeSetLinearSolver(ts->mem, ts->LS, ts->A))
            return -1;
    } else {
        /* ARKODE's explicit stepper (ERKStep);
         * Lagrange dense output needs no extra right-hand side per step
         * (Hermite evaluates f at each step's end) */
        ts->mem = ERKStepCreate(sun_rhs, t0, ts->y, ts->ctx);
        if (!ts->mem || ERKStepSetErrFile(ts->mem, NULL) ||
            ERKStepSetInterpolantType(ts->mem, ARK_INTERP_LAGRANGE) ||
            ERKStepSetUserData(ts->mem, ts) || ERKStepSetFixedStep(ts->mem, ts->h) ||
            set_ralston(ts->mem) || ERKStepWFtolerances(ts->mem, unit_weights) ||
            ERKStepSetMaxNumSteps(ts->mem, 10000000))
            return -1;
    }
    return 0;
}

void hfm_tsim_set_external(hfm_tsim *ts, hfm_ext_fn fn, void *user)
{
    ts->ext = fn;
    ts->ext_user = user;
}

void hfm_tsim_set_controls(hfm_tsim *ts, const hfm_controls *u)
{
    ts->u = *u;
}

int hfm_tsim_advance(hfm_tsim *ts, double t_s)
{
    if (!ts->mem)
        return -1;
    sunrealtype tret = ts->t;
    int rc;
    if (ts->method == HFM_TSIM_CVODE) {
        rc = CVode(ts->mem, t_s, ts->y, &tret, CV_NORMAL);
    } else {
        ERKStepSetStopTime(ts->mem, t_s);
        rc = ERKStepEvolve(ts->mem, t_s, ts->y, &tret, ARK_NORMAL);
    }
    ts->t = tret;
    if (rc < 0) {
        core_log_msg(ts->log, CORE_LOG_ERROR, "hfm tsim: solver failed (%d) at t = %.4f s", rc,
                     (double)tret);
        return -1;
    }
    return 0;
}

int hfm_tsim_state(const hfm_tsim *ts, double *y, int n)
{
    if (n < ts->n)
        return -1;
    memcpy(y, N_VGetArrayPointer(ts->y), (size_t)ts->n * sizeof *y);
    return 0;
}

void hfm_tsim_rotor(const hfm_tsim *ts, double *thrust_N, double *power_W)
{
    *thrust_N = ts->last_thrust_N;
    *power_W = ts->last_power_W;
}

void hfm_tsim_body(const hfm_tsim *ts, hfm_body *b)
{
    const double *y = N_VGetArrayPointer(ts->y);
    memcpy(b->pos_S_m, y + I_POS, sizeof b->pos_S_m);
    memcpy(b->vel_B_mps, y + I_VEL, sizeof b->vel_B_mps);
    memcpy(b->rate_B_radps, y + I_RATE, sizeof b->rate_B_radps);
    memcpy(b->euler_rad, y + I_EUL, sizeof b->euler_rad);
}
