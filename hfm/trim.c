/* trim.c -- trim: f(X, U) = 0 for controls, attitudes and rotor states.
 *
 * Unknowns (14): collective, longitudinal, lateral, pedal (percent), pitch
 * theta, and roll phi (zero-sideslip constraint, and hover over the ship) or
 * sideslip beta (wings-level constraint); flapping beta0, beta1c, beta1s;
 * inflow lambda0, lambda1s, lambda1c; flapping beta2c, beta2s (the second
 * harmonics keep the trim consistent with the time simulation's blades).
 * Equations (14): the body accelerations
 * of eqs. (7)-(8) (u', v', w' over g; p', q', r' in rad/s^2) with the
 * revolution-averaged rotor loads, the flap equation's harmonic balance and
 * the steady Pitt-Peters equations (hfm_eval_harmonic). Straight level
 * flight at airspeed V: the air-relative velocity V (cos a cos b, sin b,
 * sin a cos b) with the angle of attack a solved so that the flight path is
 * level. Hover over the ship: zero velocity relative to S, heading along the
 * bow, in the WOD wind -V (cos dir, sin dir, 0) or a given field.
 * The auto constraint follows the GenHel table: zero sideslip up to 60 kt,
 * wings level above. Sweeps use hfm_cont_trace (pseudo-arc-length) between
 * the requested values and Newton at each requested value.
 */
#include "hfm_priv.h"

#include <stdlib.h>
#include <string.h>

struct hfm_trim {
    const hfm_aircraft *ac;
    const core_log *log;
};

static const char *eq_names[HFM_TRIM_N] = {
    "u-dot (longitudinal force)", "v-dot (lateral force)", "w-dot (vertical force)",
    "p-dot (rolling moment)",     "q-dot (pitching moment)", "r-dot (yawing moment)",
    "flap beta0",                 "flap beta1c",             "flap beta1s",
    "inflow lambda0",             "inflow lambda1s",         "inflow lambda1c",
    "flap beta2c",                "flap beta2s"};

static const double trim_dx[HFM_TRIM_N] = {1e-3, 1e-3, 1e-3, 1e-3, 1e-5, 1e-5, 1e-5,
                                           1e-5, 1e-5, 1e-6, 1e-6, 1e-6, 1e-5, 1e-5};

const hfm_aircraft *hfm_trim_aircraft(const hfm_trim *tr)
{
    return tr->ac;
}

hfm_trim *hfm_trim_create(const hfm_aircraft *ac, const core_log *log)
{
    if (!ac)
        return NULL;
    hfm_trim *t = calloc(1, sizeof *t);
    if (!t)
        return NULL;
    t->ac = ac;
    t->log = log;
    return t;
}

void hfm_trim_destroy(hfm_trim *tr)
{
    free(tr);
}

static int use_roll_constraint(const hfm_trim_cond *c)
{
    if (c->kind != HFM_TRIM_FORWARD)
        return 0;
    if (c->constraint == HFM_CONSTRAINT_ROLL)
        return 1;
    if (c->constraint == HFM_CONSTRAINT_SIDESLIP)
        return 0;
    return c->airspeed_mps > 60.0 * CORE_KT_TO_MPS + 1e-9;
}

/* Body state, controls and rotor state from the unknowns. */
static void unpack(const hfm_trim_cond *c, const double *x, hfm_body *b, hfm_controls *u,
                   hfm_rotor_harm *rh, double *sideslip)
{
    memset(b, 0, sizeof *b);
    memcpy(b->pos_S_m, c->pos_S_m, sizeof b->pos_S_m);
    u->collective_pct = x[0];
    u->long_cyclic_pct = x[1];
    u->lat_cyclic_pct = x[2];
    u->pedal_pct = x[3];
    double th = x[4], ph = 0.0, be = 0.0;
    if (use_roll_constraint(c))
        be = x[5];
    else
        ph = x[5];
    b->euler_rad[0] = ph;
    b->euler_rad[1] = th;
    if (c->kind == HFM_TRIM_FORWARD) {
        double V = c->airspeed_mps;
        double A = -sin(th) * cos(be), B = cos(ph) * cos(th) * cos(be),
               C = -sin(ph) * cos(th) * sin(be);
        double R = hypot(A, B), dl = atan2(B, A), ac = acos(clampd(C / R, -1.0, 1.0));
        double a1 = dl - ac, a2 = dl + ac;
        a1 = remainder(a1 - th, 2 * CORE_PI) + th;
        a2 = remainder(a2 - th, 2 * CORE_PI) + th;
        double al = fabs(a1 - th) < fabs(a2 - th) ? a1 : a2;
        b->vel_B_mps[0] = V * cos(al) * cos(be);
        b->vel_B_mps[1] = V * sin(be);
        b->vel_B_mps[2] = V * sin(al) * cos(be);
    }
    rh->beta0_rad = x[6];
    rh->beta1c_rad = x[7];
    rh->beta1s_rad = x[8];
    rh->lambda0 = x[9];
    rh->lambda1s = x[10];
    rh->lambda1c = x[11];
    rh->beta2c_rad = x[12];
    rh->beta2s_rad = x[13];
    *sideslip = be;
}

void hfm_trim_cond_air(const hfm_trim_cond *c, hfm_air_uniform *wind, hfm_air *air)
{
    /* Still air for forward flight, the WOD for a hover over the ship, or
     * the condition's own air (a field) when it has one. */
    wind->vel_S_mps[0] = wind->vel_S_mps[1] = wind->vel_S_mps[2] = 0.0;
    air->fn = hfm_air_uniform_fn;
    air->user = wind;
    air->wake = NULL;
    if (c->air)
        *air = *c->air;
    else if (c->kind == HFM_TRIM_HOVER_SHIP) {
        core_vec3 v = core_wod_vel_S_mps(c->wod_speed_mps, c->wod_dir_rad);
        wind->vel_S_mps[0] = v.x;
        wind->vel_S_mps[1] = v.y;
        wind->vel_S_mps[2] = v.z;
    }
}

static int residual_loads(hfm_trim *tr, const hfm_trim_cond *c, const double *x, double *f,
                          hfm_loads *L, hfm_body *b, hfm_controls *u, hfm_rotor_harm *rh,
                          double *sideslip)
{
    hfm_air_uniform wind;
    hfm_air air;
    hfm_trim_cond_air(c, &wind, &air);
    unpack(c, x, b, u, rh, sideslip);
    if (hfm_eval_harmonic(tr->ac, &air, 0.0, b, u, rh, L))
        return -1;
    for (int i = 0; i < 3; i++) {
        f[i] = L->acc_B[i] / CORE_G_MPS2;
        f[3 + i] = L->acc_B[3 + i];
        f[6 + i] = L->flap_res[i];
        f[9 + i] = L->inflow_res[i];
    }
    f[12] = L->flap_res[3];
    f[13] = L->flap_res[4];
    return 0;
}

int hfm_trim_residual(hfm_trim *tr, const hfm_trim_cond *c, const double *x, double *f)
{
    hfm_loads L;
    hfm_body b;
    hfm_controls u;
    hfm_rotor_harm rh;
    double be;
    return residual_loads(tr, c, x, f, &L, &b, &u, &rh, &be);
}

typedef struct sys_user {
    hfm_trim *tr;
    hfm_trim_cond c;
    int param; /* -1: none */
} sys_user;

static void set_param(hfm_trim_cond *c, int param, double lam)
{
    if (param == HFM_PARAM_AIRSPEED)
        c->airspeed_mps = lam;
    else if (param == HFM_PARAM_WOD_SPEED)
        c->wod_speed_mps = lam;
}

static int sys_fn(void *user, const double *x, double lam, double *f)
{
    sys_user *s = user;
    hfm_trim_cond c = s->c;
    set_param(&c, s->param, lam);
    return hfm_trim_residual(s->tr, &c, x, f);
}

/* A cold-start guess: mid controls, level attitude, coning from the Lock
 * number, Glauert's uniform inflow for the weight. */
static void cold_guess(const hfm_trim *tr, const hfm_trim_cond *c, double *x)
{
    const hfm_mr *mr = &tr->ac->mr;
    double OR = mr->omega * mr->R;
    double CT = tr->ac->mass * CORE_G_MPS2 / (mr->rho * mr->area * OR * OR);
    double V = c->kind == HFM_TRIM_FORWARD ? c->airspeed_mps : c->wod_speed_mps;
    double mu = V / OR, l = sqrt(CT / 2.0);
    for (int i = 0; i < 30; i++)
        l = 0.5 * l + 0.5 * CT / (2.0 * sqrt(mu * mu + l * l));
    for (int i = 0; i < 4; i++)
        x[i] = 50.0;
    x[4] = x[5] = 0.0;
    x[6] = 0.04;
    x[7] = x[8] = 0.0;
    x[9] = l;
    x[10] = x[11] = x[12] = x[13] = 0.0;
}

static void fill_result(hfm_trim *tr, const hfm_trim_cond *c, const double *x,
                        const hfm_newton_info *inf, hfm_trim_result *r)
{
    double f[HFM_TRIM_N];
    memset(r, 0, sizeof *r);
    memcpy(r->x, x, sizeof r->x);
    residual_loads(tr, c, x, f, &r->loads, &r->body, &r->u, &r->rotor, &r->sideslip_rad);
    r->wings_level = use_roll_constraint(c);
    r->converged = inf->converged;
    r->iterations = inf->iterations;
    int k = 0;
    double m = 0.0;
    for (int i = 0; i < HFM_TRIM_N; i++)
        if (fabs(f[i]) > m) {
            m = fabs(f[i]);
            k = i;
        }
    r->resid_norm = m;
    r->worst_eq = k;
    r->worst_eq_name = eq_names[k];
    r->speed_kt = (c->kind == HFM_TRIM_FORWARD ? c->airspeed_mps : c->wod_speed_mps) /
                  CORE_KT_TO_MPS;
}

static int solve_at(hfm_trim *tr, const hfm_trim_cond *c, double *x, hfm_trim_result *res)
{
    sys_user su = {tr, *c, -1};
    hfm_newton_opts o = {40, 1e-9, trim_dx};
    hfm_newton_info inf;
    int rc = hfm_newton(sys_fn, &su, HFM_TRIM_N, x, 0.0, &o, &inf);
    if (rc < 0)
        return rc;
    /* A kink (airfoil or fuselage table, stabilator schedule, wake edge) at
     * the solution can stall Newton: go on with wider difference steps,
     * whose Jacobian averages over the kink. */
    double wide[HFM_TRIM_N];
    for (int k = 0; k < 2 && !inf.converged; k++) {
        for (int i = 0; i < HFM_TRIM_N; i++)
            wide[i] = trim_dx[i] * (k == 0 ? 30.0 : 300.0);
        hfm_newton_opts ow = {40, 1e-9, wide};
        int it = inf.iterations;
        if ((rc = hfm_newton(sys_fn, &su, HFM_TRIM_N, x, 0.0, &ow, &inf)) < 0)
            return rc;
        inf.iterations += it;
    }
    fill_result(tr, c, x, &inf, res);
    if (!inf.converged)
        core_log_msg(tr->log, CORE_LOG_WARN,
                     "hfm trim: %s at %.1f kt not converged: |f| = %.3g in %s", tr->ac->name,
                     res->speed_kt, res->resid_norm, res->worst_eq_name);
    return inf.converged ? 0 : 1;
}

int hfm_trim_solve(hfm_trim *tr, const hfm_trim_cond *c, const hfm_trim_result *guess,
                   hfm_trim_result *res)
{
    double x[HFM_TRIM_N];
    if (guess) {
        memcpy(x, guess->x, sizeof x);
        /* the sixth unknown changes meaning with the constraint */
        if (guess->wings_level != use_roll_constraint(c))
            x[5] = 0.0;
    } else {
        cold_guess(tr, c, x);
    }
    int rc = solve_at(tr, c, x, res);
    if (rc > 0 && guess) { /* retry from a cold start */
        cold_guess(tr, c, x);
        rc = solve_at(tr, c, x, res);
    }
    return rc;
}

/* Sweep segment: trace from the first value, correcting at each target. */
typedef struct sweep_user {
    hfm_trim *tr;
    hfm_trim_cond c;
    int param;
    const double *vals;
    int n, next;
    hfm_trim_result *res;
    double xprev[HFM_TRIM_N], lprev;
    int failed;
} sweep_user;

static int sweep_point(void *user, const double *x, double lam, double dlam_ds, int fold)
{
    (void)dlam_ds;
    (void)fold;
    sweep_user *s = user;
    while (s->next < s->n && lam >= s->vals[s->next]) {
        double tgt = s->vals[s->next], f = (tgt - s->lprev) / (lam - s->lprev);
        double xg[HFM_TRIM_N];
        for (int i = 0; i < HFM_TRIM_N; i++)
            xg[i] = s->xprev[i] + f * (x[i] - s->xprev[i]);
        hfm_trim_cond c = s->c;
        set_param(&c, s->param, tgt);
        int rc = solve_at(s->tr, &c, xg, &s->res[s->next]);
        /* near a turning point the interpolated guess can sit on the wrong
         * side: try the bracketing points of the arc, then a cold start */
        for (int k = 0; rc > 0 && k < 3; k++) {
            if (k == 2) {
                cold_guess(s->tr, &c, xg);
            } else {
                const double *src = k == 0 ? x : s->xprev;
                memcpy(xg, src, sizeof xg);
            }
            rc = solve_at(s->tr, &c, xg, &s->res[s->next]);
        }
        if (rc)
            s->failed = 1;
        s->next++;
    }
    memcpy(s->xprev, x, sizeof s->xprev);
    s->lprev = lam;
    return s->next >= s->n;
}

int hfm_trim_sweep(hfm_trim *tr, const hfm_trim_cond *c0, int param, const double *vals, int n,
                   hfm_trim_result *res)
{
    static const double xs[HFM_TRIM_N] = {10, 10, 10, 10, 0.05, 0.05, 0.02, 0.02, 0.02,
                                          0.01, 0.01, 0.01, 0.005, 0.005};
    int i = 0, bad = 0;
    hfm_trim_result *prev = NULL;
    while (i < n) {
        hfm_trim_cond c = *c0;
        set_param(&c, param, vals[i]);
        int seg_roll = use_roll_constraint(&c);
        int j = i + 1; /* the segment: same constraint */
        while (j < n) {
            hfm_trim_cond cj = *c0;
            set_param(&cj, param, vals[j]);
            if (use_roll_constraint(&cj) != seg_roll)
                break;
            j++;
        }
        int rc = hfm_trim_solve(tr, &c, prev, &res[i]);
        if (rc < 0)
            return rc;
        if (rc)
            bad = 1;
        if (j > i + 1) {
            sweep_user su;
            memset(&su, 0, sizeof su);
            su.tr = tr;
            su.c = *c0;
            su.param = param;
            su.vals = vals;
            su.n = j;
            su.next = i + 1;
            su.res = res;
            memcpy(su.xprev, res[i].x, sizeof su.xprev);
            su.lprev = vals[i];
            sys_user sy = {tr, *c0, param};
            double span = vals[j - 1] - vals[i];
            hfm_cont_opts o = {0};
            o.ds0 = 0.5 * span / (j - i);
            o.ds_min = 1e-4;
            o.ds_max = 2.0 * span / (j - i);
            o.lam_scale = 1.0;
            o.x_scale = xs;
            o.max_steps = 50 * (j - i);
            o.corr_max_iter = 8;
            o.tol = 1e-9;
            o.dx = trim_dx;
            hfm_cont_info inf;
            int crc = hfm_cont_trace(sys_fn, &sy, HFM_TRIM_N, res[i].x, vals[i], -1e9,
                                     vals[j - 1] + 1.0, &o, sweep_point, &su, &inf);
            if (crc < 0)
                return crc;
            if (su.failed)
                bad = 1;
            for (int k = su.next; k < j; k++) { /* not reached: mark and report */
                memset(&res[k], 0, sizeof res[k]);
                hfm_trim_cond ck = *c0;
                set_param(&ck, param, vals[k]);
                if (hfm_trim_solve(tr, &ck, &res[k - 1], &res[k]))
                    bad = 1;
            }
        }
        prev = &res[j - 1];
        i = j;
    }
    return bad ? 1 : 0;
}
