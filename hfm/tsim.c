/* tsim.c -- time simulation with SUNDIALS (6.x API): ARKODE explicit
 * Runge-Kutta at a fixed step (real time) or CVODE BDF (reference runs).
 *
 * State: position in S (3), u v w, p q r, phi theta psi, the Pitt-Peters
 * inflow (3), the rotor azimuth, and each blade's flap angle and rate. The
 * blades turn with the azimuth: at each right-hand side every blade is
 * evaluated at its own azimuth (hfm_rotor_blade), its flap acceleration
 * from the flap equation, and the hub loads summed over the blades.
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
};

int hfm_tsim_size(const hfm_tsim *ts)
{
    return ts->n;
}

long hfm_tsim_rhs_evals(const hfm_tsim *ts)
{
    return ts->evals;
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
    memset(&L, 0, sizeof L);
    hfm_kin_setup(&k, &ts->air, t, &b);
    if (hfm_rotor_setup(ac, &k, &ts->u, y + I_LAM, &in))
        return -1;
    double F[3] = {0, 0, 0}, M[3] = {0, 0, 0}, T = 0, Lr = 0, Mp = 0, P = 0;
    for (int i = 0; i < nb; i++) {
        double psi = y[I_AZ] + 2.0 * CORE_PI * i / nb;
        hfm_blade_out o;
        if (hfm_rotor_blade(ac, &in, psi, y[I_BETA + i], y[I_BETA + nb + i], 0.0, 1, &o, NULL,
                            NULL))
            return -1;
        for (int j = 0; j < 3; j++) {
            F[j] += o.F_H[j];
            M[j] += o.M_H[j];
        }
        T += o.T;
        Lr += o.Lr;
        Mp += o.Mp;
        P += o.P;
        yd[I_BETA + i] = y[I_BETA + nb + i];
        yd[I_BETA + nb + i] = o.ddbeta;
    }
    hfm_rotor_to_body(ac, F, M, &L.mr);
    double OR = mr->omega * mr->R, q = mr->rho * mr->area * OR * OR;
    L.mr_thrust_N = -F[2];
    L.mr_power_W = P;
    double C[3] = {T / q, Lr / q, Mp / q}, Lh[3][3], skew;
    hfm_rotor_inflow(ac, &in, C[0], C[1], C[2], Lh, &skew);
    /* Lhat^-1: lambda1s alone, (lambda0, lambda1c) a 2x2 block */
    const double *lam = y + I_LAM;
    double det = Lh[0][0] * Lh[2][2] - Lh[0][2] * Lh[2][0];
    double li0 = (Lh[2][2] * lam[0] - Lh[0][2] * lam[2]) / det;
    double li2 = (-Lh[2][0] * lam[0] + Lh[0][0] * lam[2]) / det;
    double li1 = lam[1] / Lh[1][1];
    const double m0 = 8.0 / (3.0 * CORE_PI), m1 = 16.0 / (45.0 * CORE_PI);
    yd[I_LAM + 0] = mr->omega * (C[0] - li0) / m0;
    yd[I_LAM + 1] = mr->omega * (C[1] - li1) / m1;
    yd[I_LAM + 2] = mr->omega * (C[2] - li2) / m1;
    yd[I_AZ] = mr->omega;
    hfm_wake w;
    hfm_rotor_wake(ac, &in, skew, &ts->u, &b, &w);
    if (hfm_eval_rest(ac, &k, &b, &ts->u, &w, &L))
        return -1;
    double vS[3];
    m3_mul(k.C_SB, b.vel_B_mps, vS);
    for (int i = 0; i < 3; i++) {
        yd[I_POS + i] = vS[i];
        yd[I_VEL + i] = L.acc_B[i];
        yd[I_RATE + i] = L.acc_B[3 + i];
    }
    double ph = b.euler_rad[0], th = b.euler_rad[1];
    double p = b.rate_B_radps[0], qq = b.rate_B_radps[1], r = b.rate_B_radps[2];
    double sp = sin(ph), cp = cos(ph), ct = cos(th);
    yd[I_EUL + 0] = p + (qq * sp + r * cp) * tan(th);
    yd[I_EUL + 1] = qq * cp - r * sp;
    yd[I_EUL + 2] = (qq * sp + r * cp) / ct;
    return 0;
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
    if (SUNContext_Create(NULL, &ts->ctx)) {
        free(ts);
        return NULL;
    }
    ts->y = N_VNew_Serial(ts->n, ts->ctx);
    if (!ts->y) {
        hfm_tsim_destroy(ts);
        return NULL;
    }
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
    for (int i = 0; i < mr->nb; i++) {
        double psi = 2.0 * CORE_PI * i / mr->nb, dd;
        hfm_rotor_harm_beta(rh, mr->omega, psi, &y[I_BETA + i], &y[I_BETA + mr->nb + i], &dd);
    }
    ts->u = *u;
    ts->t = t0;
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
            ERKStepSetTableNum(ts->mem, ARKODE_KNOTH_WOLKE_3_3) ||
            ERKStepSetMaxNumSteps(ts->mem, 10000000))
            return -1;
    }
    return 0;
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

void hfm_tsim_body(const hfm_tsim *ts, hfm_body *b)
{
    const double *y = N_VGetArrayPointer(ts->y);
    memcpy(b->pos_S_m, y + I_POS, sizeof b->pos_S_m);
    memcpy(b->vel_B_mps, y + I_VEL, sizeof b->vel_B_mps);
    memcpy(b->rate_B_radps, y + I_RATE, sizeof b->rate_B_radps);
    memcpy(b->euler_rad, y + I_EUL, sizeof b->euler_rad);
}
