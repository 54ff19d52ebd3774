/* The landing gear on the moving deck, and strikes on the ship.
 *
 * Model (per leg of the aircraft file's [gear], hfm_gear_leg):
 *   1. Geometry: the tyre is a sphere of its radius at the wheel's centre
 *      (strut extended, pos_B_m). ODE's dCollide of a probe sphere (the
 *      tyre's radius plus s_off = stroke + radius, centred s_off up the
 *      strut) with the deck box (the flight deck, its top face the plane
 *      z_S = 0, a geom on a kinematic ODE body that moves with the ship's
 *      frame S) finds the contact; the tyre's penetration x (m) along the
 *      deck normal follows exactly from the probe's depth. The strut's
 *      force is taken along the deck normal (small body tilt on the deck:
 *      cos 10 deg = 0.985).
 *   2. Normal load: an oleo strut in series with a tyre, both massless
 *      (quasi-static series law). The strut does not move until its preload
 *      P is reached (the tyre alone, k_t), then the spring k_s in series with
 *      the tyre, then past the stroke a stiff end stop (10 k_t, here
 *      10 x the tyre) in series with the tyre:
 *        x <= P / k_t:            F = k_t x
 *        x <= F2 / k_t + stroke:  F = P + k1 (x - P / k_t),  k1 = k_s k_t / (k_s + k_t)
 *        beyond:                  F = F2 + k2 (x - x2),      k2 = k_e k_t / (k_e + k_t)
 *      with F2 = P + k_s stroke. The oleo's damping acts on the strut's share
 *      of the compression rate, d(x_s)/dx = k_t / (k_s + k_t) (0 below the
 *      preload): F += c share x', c the compression or the rebound damping
 *      by the sign of the strut's rate; F >= 0 (the tyre cannot pull).
 *      Currey, "Aircraft Landing Gear Design: Principles and Practices"
 *      (AIAA 1988), ch. 5 (the oleo's spring, preload and orifice damping
 *      with separate compression and rebound), linearised here.
 *   3. Friction, in the deck plane (JSBSim's FGLGear documentation,
 *      jsbsim.sourceforge.net/JSBSim/classJSBSim_1_1FGLGear.html: static
 *      and dynamic coefficients, rolling friction, brake groups, fixed and
 *      castered wheels). JSBSim holds a standing aircraft with Lagrange
 *      multipliers in its own integrator (FGAccelerations); hfm_tsim has
 *      none, so here a tyre that must not slip (side-ways always; along
 *      its heading too when braked; a castoring wheel is free unless locked)
 *      is held by a tangential spring-damper to an anchor on the deck (the
 *      tyre's lateral stiffness, assumed equal to its vertical k_t, damped
 *      critically for the leg's static share of the mass): a smooth,
 *      regularised Coulomb law that holds a standing aircraft with no creep.
 *      Its force is bounded by mu_static N; past that the tyre slides, the
 *      anchor follows so the force is mu_dynamic N (an elasto-plastic
 *      friction element). A rolling tyre feels -mu_rolling N v / sqrt(v^2 +
 *      v0^2) along its heading, v0 = 0.05 m/s. Anchors move only between
 *      steps (sim_contact_step), so within a step the loads are a smooth
 *      function of the state for the flight model's Runge-Kutta stages.
 *   4. The loads go to the flight model (hfm_tsim's integrator) through
 *      the flight's external loads (sim_contact_loads, with the deck's
 *      motion that the flight's ship stage gives): the force at each tyre's
 *      contact point, summed as a force and a moment about the CG in B.
 *      Nothing is integrated here; ODE's solver is not used (no
 *      soft-contact parameters to choose).
 *   5. Strikes: the aircraft file's strike points (rotor tips, tail, nose,
 *      belly) as small ODE spheres against the deck box and one ODE box per
 *      ship block (a tapered bow is taken as its box), checked after each
 *      step; a hit stops the run as a crash naming the point and the block
 *      (or the sea: a point below its mean surface, off the deck).
 *      A leg over 20 times the weight, or compressed past its stroke plus
 *      its tyre's radius (a wheel through the deck), is a
 *      crash too, and the normal load is bounded there, so it stays finite.
 *   6. Slide: a held tyre that has slid 0.05 m. Tip-over: the body's z axis
 *      tilted from the deck normal past the gear's static tip-over angle
 *      atan(d / h) (d the CG's distance to the nearest edge of the wheels'
 *      polygon, h the CG height at rest).
 */
#include "sim.h"

#include <ode/ode.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define V0_ROLL_MPS 0.05
#define SLIDE_REPORT_M 0.05
#define END_STOP_FACTOR 10.0
#define OVERLOAD_WEIGHTS 20.0
#define STRIKE_RADIUS_M 0.02

typedef struct leg_rt {
    dGeomID sphere;
    double anchor_S[2];
    int has_anchor;
    double mass_share_kg, cb_Nspm;
    sim_contact_leg st;
    /* the latest evaluation's contact, for the step's bookkeeping */
    double p_S[2], N, e_r[2];
    int held_roll;
} leg_rt;

struct sim_contact {
    hfm_gear g;
    core_ship ship;
    double h_s, weight_N;
    int brakes, lock, ode;
    dWorldID world;
    dBodyID deck_body;
    dGeomID deck;
    dGeomID blocks[CORE_SHIP_MAX_BLOCKS];
    dGeomID point;
    leg_rt leg[HFM_GEAR_MAX_LEGS];
    double tip_angle_rad;
    sim_contact_report rep;
};

/* ------------------------------------------------------------ the leg law */
static void leg_force(const hfm_gear_leg *l, double x, double xdot, double *F, double *xs)
{
    double kt = l->tyre_stiffness_Npm, ks = l->stiffness_Npm, ke = END_STOP_FACTOR * kt;
    double P = l->preload_N, F2 = P + ks * l->stroke_m;
    double x1 = P / kt, x2 = F2 / kt + l->stroke_m;
    double Fs, share;
    if (x <= x1) {
        Fs = kt * x;
        share = 0.0;
        *xs = 0.0;
    } else if (x <= x2) {
        Fs = P + ks * kt / (ks + kt) * (x - x1);
        share = kt / (ks + kt);
        *xs = (Fs - P) / ks;
    } else {
        Fs = F2 + ke * kt / (ke + kt) * (x - x2);
        share = kt / (ke + kt);
        *xs = l->stroke_m + (Fs - F2) / ke;
    }
    double rate = share * xdot;
    double c = rate > 0 ? l->damping_comp_Nspm : l->damping_reb_Nspm;
    double f = Fs + c * rate;
    *F = f > 0 ? f : 0.0;
}

double sim_contact_leg_compression(const hfm_gear_leg *l, double load_N)
{
    double kt = l->tyre_stiffness_Npm, ks = l->stiffness_Npm, ke = END_STOP_FACTOR * kt;
    double P = l->preload_N, F2 = P + ks * l->stroke_m;
    if (load_N <= P)
        return load_N / kt;
    if (load_N <= F2)
        return load_N / kt + (load_N - P) / ks;
    return load_N / kt + l->stroke_m + (load_N - F2) / ke;
}

int sim_contact_static_loads(const hfm_gear *g, double weight_N, double load_N[], core_err *err)
{
    /* minimum-norm loads with sum N = W, sum N x = 0, sum N y = 0:
     * N = A^T (A A^T)^-1 b, A the 3 x n rows (1, x_i, y_i) */
    int n = g->nlegs;
    double M[3][3] = {{0}}, b[3] = {weight_N, 0, 0};
    for (int i = 0; i < n; i++) {
        double a[3] = {1.0, g->leg[i].pos_B_m[0], g->leg[i].pos_B_m[1]};
        for (int r = 0; r < 3; r++)
            for (int k = 0; k < 3; k++)
                M[r][k] += a[r] * a[k];
    }
    double det = M[0][0] * (M[1][1] * M[2][2] - M[1][2] * M[2][1]) -
                 M[0][1] * (M[1][0] * M[2][2] - M[1][2] * M[2][0]) +
                 M[0][2] * (M[1][0] * M[2][1] - M[1][1] * M[2][0]);
    if (n < 3 || fabs(det) < 1e-9)
        return core_err_set(err, -1, "gear: %d legs do not make a support polygon", n);
    double inv[3][3];
    for (int r = 0; r < 3; r++)
        for (int k = 0; k < 3; k++) {
            int r1 = (k + 1) % 3, r2 = (k + 2) % 3, c1 = (r + 1) % 3, c2 = (r + 2) % 3;
            inv[r][k] = (M[r1][c1] * M[r2][c2] - M[r1][c2] * M[r2][c1]) / det;
        }
    double lam[3];
    for (int r = 0; r < 3; r++)
        lam[r] = inv[r][0] * b[0] + inv[r][1] * b[1] + inv[r][2] * b[2];
    for (int i = 0; i < n; i++) {
        load_N[i] = lam[0] + lam[1] * g->leg[i].pos_B_m[0] + lam[2] * g->leg[i].pos_B_m[1];
        if (load_N[i] <= 0)
            return core_err_set(err, -1, "gear: the CG is outside the wheels' support (leg %s would pull)",
                                g->leg[i].name);
    }
    return 0;
}

/* ---------------------------------------------------------- the ship frame */
/* The deck's kinematic body: the ship's frame and its velocities. */
static void place_deck(sim_contact *c, const sim_ship_deck *d)
{
    const sim_ship_frame *fr = &d->fr;
    dMatrix3 R;
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++)
            R[4 * i + j] = fr->C_ES[3 * i + j];
        R[4 * i + 3] = 0;
    }
    dBodySetPosition(c->deck_body, fr->origin_E_m[0], fr->origin_E_m[1], fr->origin_E_m[2]);
    dBodySetRotation(c->deck_body, R);
    dBodySetLinearVel(c->deck_body, d->vel_E_mps[0], d->vel_E_mps[1], d->vel_E_mps[2]);
    dBodySetAngularVel(c->deck_body, d->omega_E_radps[0], d->omega_E_radps[1], d->omega_E_radps[2]);
}

/* v_S = C_ES^T v_E */
static void to_S(const sim_ship_frame *fr, const double vE[3], double vS[3])
{
    for (int i = 0; i < 3; i++)
        vS[i] = fr->C_ES[i] * vE[0] + fr->C_ES[3 + i] * vE[1] + fr->C_ES[6 + i] * vE[2];
}

static void cross(const double a[3], const double b[3], double o[3])
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

static core_quat body_quat(const hfm_body *b)
{
    core_euler e = {b->euler_rad[0], b->euler_rad[1], b->euler_rad[2]};
    return core_quat_from_euler(e);
}

static void rot(core_quat q, const double v[3], double o[3])
{
    core_vec3 r = core_quat_rotate(q, core_vec3_make(v[0], v[1], v[2]));
    o[0] = r.x;
    o[1] = r.y;
    o[2] = r.z;
}

/* ------------------------------------------------------------- the loads */
/* The body at one evaluation, in E: its attitude, the CG and its
 * velocity, the angular velocity; the deck's normal (up) and the body's
 * heading in the deck plane (e_r along it, e_s to its right). */
typedef struct gear_body {
    core_quat q;
    const double *cg;
    double vcg[3], w[3];
    double n_up[3];
    double e_r[2], e_s[2];
} gear_body;

static void gear_body_at(const sim_ship_frame *fr, const hfm_body *b, gear_body *gb)
{
    gb->q = body_quat(b);
    rot(gb->q, b->vel_B_mps, gb->vcg);
    rot(gb->q, b->rate_B_radps, gb->w);
    gb->cg = b->pos_S_m;
    gb->n_up[0] = -fr->C_ES[2];
    gb->n_up[1] = -fr->C_ES[5];
    gb->n_up[2] = -fr->C_ES[8];
    double xb[3] = {1, 0, 0}, xE[3], xS[3];
    rot(gb->q, xb, xE);
    to_S(fr, xE, xS);
    double hx = hypot(xS[0], xS[1]);
    gb->e_r[0] = hx > 1e-9 ? xS[0] / hx : 1.0;
    gb->e_r[1] = hx > 1e-9 ? xS[1] / hx : 0.0;
    gb->e_s[0] = -gb->e_r[1];
    gb->e_s[1] = gb->e_r[0];
}

/* A leg's tyre on the deck: its penetration x (m, along the deck normal;
 * 0 off the deck) and the contact point pc in E. */
static double leg_contact(const sim_contact *c, int i, const gear_body *gb, double pc[3])
{
    const hfm_gear_leg *l = &c->g.leg[i];
    const leg_rt *L = &c->leg[i];
    /* the probe sphere: radius tyre + s_off, its centre s_off up the
     * strut from the wheel's, so the penetration stays measured (the
     * centre above the deck) to s_off past the tyre's radius */
    double s_off = l->stroke_m + l->tyre_radius_m, top_B[3], off[3], ctr[3], zB[3], zb[3] = {0, 0, 1};
    for (int k = 0; k < 3; k++)
        top_B[k] = l->pos_B_m[k] - s_off * zb[k];
    rot(gb->q, top_B, off);
    rot(gb->q, zb, zB);
    for (int k = 0; k < 3; k++)
        ctr[k] = gb->cg[k] + off[k];
    dGeomSetPosition(L->sphere, ctr[0], ctr[1], ctr[2]);
    dContactGeom cgm;
    int n = dCollide(L->sphere, c->deck, 1, &cgm, sizeof cgm);
    /* the tyre's own penetration: the probe's less s_off (1 - cos beta),
     * beta the strut's tilt from the deck normal (exact for the plane) */
    const double *n_up = gb->n_up;
    double cb = -(zB[0] * n_up[0] + zB[1] * n_up[1] + zB[2] * n_up[2]);
    double x = n > 0 ? cgm.depth - s_off * (1 - cb) : 0.0;
    if (n < 1 || !(x > 0))
        return 0.0;
    if (x > s_off)
        x = s_off; /* the probe's centre at the deck: a crash the step reports */
    for (int k = 0; k < 3; k++)
        ctr[k] += s_off * zB[k]; /* back to the wheel's centre */
    for (int k = 0; k < 3; k++)
        pc[k] = ctr[k] - n_up[k] * (l->tyre_radius_m - x);
    return x;
}

/* A leg's friction in the deck plane (S x, y) for the normal load N, the
 * tyre's velocity vt (S) over the deck and its place pS (S). *held_roll:
 * 1 braked along its heading too, 0 rolling, -1 a free castor. */
static void leg_friction(const sim_contact *c, int i, const gear_body *gb, double N, const double vt[3],
                         const double pS[3], double Ft[2], int *held_roll)
{
    const hfm_gear_leg *l = &c->g.leg[i];
    const leg_rt *L = &c->leg[i];
    const double *e_r = gb->e_r, *e_s = gb->e_s;
    int free_castor = l->castor && !c->lock;
    int held = l->brake && c->brakes && !free_castor;
    double dS[2] = {0, 0};
    if (L->has_anchor) {
        dS[0] = pS[0] - L->anchor_S[0];
        dS[1] = pS[1] - L->anchor_S[1];
    }
    double vr = vt[0] * e_r[0] + vt[1] * e_r[1], vs = vt[0] * e_s[0] + vt[1] * e_s[1];
    *held_roll = free_castor ? -1 : held;
    if (free_castor) {
        double vm = sqrt(vt[0] * vt[0] + vt[1] * vt[1] + V0_ROLL_MPS * V0_ROLL_MPS);
        Ft[0] = -c->g.mu_rolling * N * vt[0] / vm;
        Ft[1] = -c->g.mu_rolling * N * vt[1] / vm;
        return;
    }
    double kb = l->tyre_stiffness_Npm, cb = L->cb_Nspm;
    double ds = dS[0] * e_s[0] + dS[1] * e_s[1], dr = dS[0] * e_r[0] + dS[1] * e_r[1];
    double fs = -kb * ds - cb * vs, fr_ = 0;
    if (held)
        fr_ = -kb * dr - cb * vr;
    double lim = c->g.mu_static * N, fm = hypot(fs, fr_);
    if (fm > lim && fm > 0) {
        double sc = c->g.mu_dynamic * N / fm;
        fs *= sc;
        fr_ *= sc;
    }
    if (!held)
        fr_ = -c->g.mu_rolling * N * vr / sqrt(vr * vr + V0_ROLL_MPS * V0_ROLL_MPS);
    Ft[0] = fs * e_s[0] + fr_ * e_r[0];
    Ft[1] = fs * e_s[1] + fr_ * e_r[1];
}

/* A leg's load on the body (force f and moment m about the CG, E), its
 * state kept for the step's bookkeeping; 0 off the deck. */
static void leg_load(sim_contact *c, int i, const sim_ship_frame *fr, const gear_body *gb, double f[3], double m[3])
{
    const hfm_gear_leg *l = &c->g.leg[i];
    leg_rt *L = &c->leg[i];
    memset(&L->st, 0, sizeof L->st); /* slip_m: its callers keep it */
    L->N = 0;
    f[0] = f[1] = f[2] = m[0] = m[1] = m[2] = 0.0;
    double pc[3], r[3], vc[3], vd[3], vrel[3];
    double x = leg_contact(c, i, gb, pc);
    if (!(x > 0))
        return;
    const double *n_up = gb->n_up;
    for (int k = 0; k < 3; k++)
        r[k] = pc[k] - gb->cg[k];
    cross(gb->w, r, vc);
    dVector3 dv;
    dBodyGetPointVel(c->deck_body, pc[0], pc[1], pc[2], dv);
    for (int k = 0; k < 3; k++) {
        vd[k] = dv[k];
        vrel[k] = gb->vcg[k] + vc[k] - vd[k];
    }
    double xdot = -(vrel[0] * n_up[0] + vrel[1] * n_up[1] + vrel[2] * n_up[2]);
    double N, xs;
    leg_force(l, x, xdot, &N, &xs);
    if (N > OVERLOAD_WEIGHTS * c->weight_N)
        N = OVERLOAD_WEIGHTS * c->weight_N;
    /* tangential, in S's deck plane */
    double vt_E[3], vt[3], pS[3], d[3];
    for (int k = 0; k < 3; k++) {
        vt_E[k] = vrel[k] + xdot * n_up[k];
        d[k] = pc[k] - fr->origin_E_m[k];
    }
    to_S(fr, vt_E, vt);
    to_S(fr, d, pS);
    double Ft[2];
    int held_roll;
    leg_friction(c, i, gb, N, vt, pS, Ft, &held_roll);
    for (int k = 0; k < 3; k++)
        f[k] = N * n_up[k] + fr->C_ES[3 * k] * Ft[0] + fr->C_ES[3 * k + 1] * Ft[1];
    cross(r, f, m);
    L->st.on_deck = 1;
    L->st.compression_m = x;
    L->st.strut_m = xs;
    L->st.normal_N = N;
    L->st.friction_N[0] = Ft[0];
    L->st.friction_N[1] = Ft[1];
    L->N = N;
    L->p_S[0] = pS[0];
    L->p_S[1] = pS[1];
    L->e_r[0] = gb->e_r[0];
    L->e_r[1] = gb->e_r[1];
    L->held_roll = held_roll;
}

/* The gear's loads in E (force, moment about the CG) for body state b on
 * the deck; each leg's state kept for the step's bookkeeping. */
static int gear_loads(sim_contact *c, const sim_ship_deck *deck, const hfm_body *b, double F_E[3], double Mom_E[3])
{
    place_deck(c, deck);
    gear_body gb;
    gear_body_at(&deck->fr, b, &gb);
    F_E[0] = F_E[1] = F_E[2] = Mom_E[0] = Mom_E[1] = Mom_E[2] = 0;
    for (int i = 0; i < c->g.nlegs; i++) {
        double f[3], m[3];
        leg_load(c, i, &deck->fr, &gb, f, m);
        if (!c->leg[i].st.on_deck)
            continue;
        for (int k = 0; k < 3; k++) {
            F_E[k] += f[k];
            Mom_E[k] += m[k];
        }
    }
    for (int k = 0; k < 3; k++)
        if (!isfinite(F_E[k]) || !isfinite(Mom_E[k]))
            return -1;
    return 0;
}

int sim_contact_loads(sim_contact *c, const sim_ship_deck *deck, const hfm_body *b, double F_B_N[3], double M_B_Nm[3])
{
    double F[3], M[3];
    double slip[HFM_GEAR_MAX_LEGS];
    for (int i = 0; i < c->g.nlegs; i++)
        slip[i] = c->leg[i].st.slip_m;
    int rc = gear_loads(c, deck, b, F, M);
    for (int i = 0; i < c->g.nlegs; i++)
        c->leg[i].st.slip_m = slip[i];
    if (rc)
        return -1;
    core_quat q = body_quat(b);
    core_vec3 f = core_quat_rotate_inv(q, core_vec3_make(F[0], F[1], F[2]));
    core_vec3 m = core_quat_rotate_inv(q, core_vec3_make(M[0], M[1], M[2]));
    F_B_N[0] = f.x;
    F_B_N[1] = f.y;
    F_B_N[2] = f.z;
    M_B_Nm[0] = m.x;
    M_B_Nm[1] = m.y;
    M_B_Nm[2] = m.z;
    return 0;
}

/* ------------------------------------------------------------ after a step */
static void flag(sim_contact *c, unsigned what, double t, double *t_first, const char *msg)
{
    if (!(c->rep.flags & what)) {
        *t_first = t;
        if (!c->rep.what[0] || what == SIM_CONTACT_CRASH)
            snprintf(c->rep.what, sizeof c->rep.what, "%s", msg);
    }
    c->rep.flags |= what;
}

int sim_contact_step(sim_contact *c, double t_s, const sim_ship_deck *deck, const hfm_body *b,
                     sim_contact_report *rep)
{
    double F[3], M[3];
    const sim_ship_frame *fr = &deck->fr;
    double slip[HFM_GEAR_MAX_LEGS];
    for (int i = 0; i < c->g.nlegs; i++)
        slip[i] = c->leg[i].st.slip_m;
    int bad = gear_loads(c, deck, b, F, M);
    char msg[160];
    c->rep.t_s = t_s;
    for (int i = 0; i < c->g.nlegs; i++) {
        leg_rt *L = &c->leg[i];
        const hfm_gear_leg *l = &c->g.leg[i];
        L->st.slip_m = slip[i];
        if (!L->st.on_deck || L->held_roll < 0) {
            L->has_anchor = 0;
            continue;
        }
        if (!L->has_anchor) {
            L->anchor_S[0] = L->p_S[0];
            L->anchor_S[1] = L->p_S[1];
            L->has_anchor = 1;
            continue;
        }
        /* the held directions' spring stretch; past mu_static N the anchor
         * follows the tyre, leaving mu_dynamic N */
        double d[2] = {L->p_S[0] - L->anchor_S[0], L->p_S[1] - L->anchor_S[1]};
        double er[2] = {L->e_r[0], L->e_r[1]}, es[2] = {-er[1], er[0]};
        double ds = d[0] * es[0] + d[1] * es[1], dr = L->held_roll ? d[0] * er[0] + d[1] * er[1] : 0.0;
        double kb = l->tyre_stiffness_Npm, dm = hypot(ds, dr);
        if (kb * dm > c->g.mu_static * L->N && dm > 0) {
            double keep = c->g.mu_dynamic * L->N / kb / dm;
            double mv_s = ds * (1 - keep), mv_r = dr * (1 - keep);
            L->anchor_S[0] += mv_s * es[0] + mv_r * er[0];
            L->anchor_S[1] += mv_s * es[1] + mv_r * er[1];
            L->st.slip_m += hypot(mv_s, mv_r);
        }
        if (!L->held_roll) /* free to roll: the anchor rolls along with the tyre */
        {
            double a = d[0] * er[0] + d[1] * er[1];
            L->anchor_S[0] += a * er[0];
            L->anchor_S[1] += a * er[1];
        }
        if (L->st.slip_m > SLIDE_REPORT_M) {
            snprintf(msg, sizeof msg, "slide: %s tyre slid %.3f m on the deck", l->name, L->st.slip_m);
            flag(c, SIM_CONTACT_SLIDE, t_s, &c->rep.t_slide_s, msg);
        }
        if (L->st.compression_m >= l->stroke_m + l->tyre_radius_m || L->st.normal_N >= OVERLOAD_WEIGHTS * c->weight_N) {
            snprintf(msg, sizeof msg, "crash: %s gear overloaded (%.0f N, %.2f m into the deck)", l->name,
                     L->st.normal_N, L->st.compression_m);
            flag(c, SIM_CONTACT_CRASH, t_s, &c->rep.t_crash_s, msg);
        }
    }
    if (bad) {
        flag(c, SIM_CONTACT_CRASH, t_s, &c->rep.t_crash_s, "crash: the gear's loads are not finite");
    }
    /* tilt from the deck normal */
    core_quat q = body_quat(b);
    double zb[3] = {0, 0, 1}, zE[3];
    rot(q, zb, zE);
    double cz = zE[0] * fr->C_ES[2] + zE[1] * fr->C_ES[5] + zE[2] * fr->C_ES[8];
    c->rep.tilt_rad = acos(cz > 1 ? 1 : cz < -1 ? -1 : cz);
    int any = 0;
    for (int i = 0; i < c->g.nlegs; i++)
        any |= c->leg[i].st.on_deck;
    if (any && c->rep.tilt_rad > c->tip_angle_rad) {
        snprintf(msg, sizeof msg, "tip-over: tilted %.1f deg from the deck (tip angle %.1f deg)",
                 c->rep.tilt_rad * CORE_RAD_TO_DEG, c->tip_angle_rad * CORE_RAD_TO_DEG);
        flag(c, SIM_CONTACT_TIP, t_s, &c->rep.t_tip_s, msg);
    }
    /* strikes */
    for (int i = 0; i < c->g.npoints; i++) {
        double p[3];
        rot(q, c->g.point_B_m[i], p);
        dGeomSetPosition(c->point, b->pos_S_m[0] + p[0], b->pos_S_m[1] + p[1], b->pos_S_m[2] + p[2]);
        dContactGeom cgm;
        const char *hit = NULL;
        if (dCollide(c->point, c->deck, 1, &cgm, sizeof cgm) > 0)
            hit = "the deck";
        for (int k = 0; !hit && k < c->ship.nblocks; k++)
            if (dCollide(c->point, c->blocks[k], 1, &cgm, sizeof cgm) > 0)
                hit = c->ship.blocks[k].name;
        /* off the deck and down: the sea's mean surface, deck_height_m
         * below E's origin (S's mean position) */
        if (!hit && b->pos_S_m[2] + p[2] > c->ship.deck_height_m)
            hit = "the sea";
        if (hit) {
            snprintf(msg, sizeof msg, "crash: %s hit %s", c->g.point_name[i], hit);
            flag(c, SIM_CONTACT_CRASH, t_s, &c->rep.t_crash_s, msg);
            break;
        }
    }
    sim_contact_report_get(c, rep);
    return (c->rep.flags & SIM_CONTACT_CRASH) ? 1 : 0;
}

void sim_contact_report_get(const sim_contact *c, sim_contact_report *rep)
{
    if (!rep)
        return;
    *rep = c->rep;
    rep->nlegs = c->g.nlegs;
    for (int i = 0; i < c->g.nlegs; i++)
        rep->leg[i] = c->leg[i].st;
    rep->tip_angle_rad = c->tip_angle_rad;
}

void sim_contact_body(const sim_flight_out *out, hfm_body *b)
{
    memcpy(b->pos_S_m, out->pos_E_m, sizeof b->pos_S_m);
    memcpy(b->euler_rad, out->euler_E_rad, sizeof b->euler_rad);
    memcpy(b->rate_B_radps, out->rate_B_radps, sizeof b->rate_B_radps);
    core_euler e = {out->euler_E_rad[0], out->euler_E_rad[1], out->euler_E_rad[2]};
    core_vec3 v = core_quat_rotate_inv(core_quat_from_euler(e),
                                       core_vec3_make(out->vel_E_mps[0], out->vel_E_mps[1], out->vel_E_mps[2]));
    b->vel_B_mps[0] = v.x;
    b->vel_B_mps[1] = v.y;
    b->vel_B_mps[2] = v.z;
}

/* ------------------------------------------------------------ create */
/* The static tip-over angle: atan(d / h), d the CG's distance to the
 * nearest edge of the wheels' convex polygon (body x, y), h the CG's mean
 * height over the deck at rest. */
static double tip_angle(const hfm_gear *g, const double *load_N)
{
    double dmin = INFINITY, h = 0;
    int n = g->nlegs;
    for (int i = 0; i < n; i++) {
        h += (g->leg[i].pos_B_m[2] + g->leg[i].tyre_radius_m - sim_contact_leg_compression(&g->leg[i], load_N[i])) / n;
        for (int j = i + 1; j < n; j++) {
            double ax = g->leg[i].pos_B_m[0], ay = g->leg[i].pos_B_m[1];
            double ex = g->leg[j].pos_B_m[0] - ax, ey = g->leg[j].pos_B_m[1] - ay, el = hypot(ex, ey);
            if (el < 1e-6)
                continue;
            /* a hull edge: all the other wheels on one side */
            int pos = 0, neg = 0;
            for (int k = 0; k < n; k++) {
                double s = ex * (g->leg[k].pos_B_m[1] - ay) - ey * (g->leg[k].pos_B_m[0] - ax);
                pos |= s > 1e-9;
                neg |= s < -1e-9;
            }
            if (pos && neg)
                continue;
            double dist = fabs(ex * (0 - ay) - ey * (0 - ax)) / el;
            if (dist < dmin)
                dmin = dist;
        }
    }
    return atan2(dmin, h);
}

sim_contact *sim_contact_create(const hfm_aircraft *ac, const core_ship *ship, double rate_hz, core_err *err)
{
    if (!ac || !ship || !(rate_hz > 0)) {
        core_err_set(err, -1, "sim_contact_create: an aircraft, a ship and a rate > 0 are needed");
        return NULL;
    }
    sim_contact *c = calloc(1, sizeof *c);
    if (!c) {
        core_err_set(err, -1, "sim_contact_create: out of memory");
        return NULL;
    }
    c->ode = dInitODE2(0) != 0;
    if (hfm_aircraft_gear(ac, &c->g) != 0 || c->g.nlegs < 3) {
        core_err_set(err, -1, "%s: the aircraft file has no [gear] section with 3 or more legs (docs/aircraft-format.md)",
                     hfm_aircraft_name(ac));
        goto fail;
    }
    c->ship = *ship;
    c->h_s = 1.0 / rate_hz;
    c->weight_N = hfm_aircraft_weight_N(ac);
    c->brakes = c->g.brakes_on;
    c->lock = c->g.tail_lock_on;
    c->rep.t_slide_s = c->rep.t_tip_s = c->rep.t_crash_s = -1;
    double load[HFM_GEAR_MAX_LEGS];
    if (sim_contact_static_loads(&c->g, c->weight_N, load, err))
        goto fail;
    c->tip_angle_rad = tip_angle(&c->g, load);
    c->world = dWorldCreate();
    c->deck_body = dBodyCreate(c->world);
    dBodySetKinematic(c->deck_body);
    double lx = ship->deck_x1_m - ship->deck_x0_m, ly = 2 * ship->deck_halfwidth_m;
    if (!(lx > 0 && ly > 0)) {
        core_err_set(err, -1, "%s: the ship's flight deck has no extent (deck_x_m, deck_halfwidth_m)", ship->name);
        goto fail;
    }
    /* the deck box: the flight deck, its top face z_S = 0, 1 m deep */
    c->deck = dCreateBox(0, lx, ly, 1.0);
    dGeomSetBody(c->deck, c->deck_body);
    dGeomSetOffsetPosition(c->deck, 0.5 * (ship->deck_x0_m + ship->deck_x1_m), 0.0, 0.5);
    for (int k = 0; k < ship->nblocks; k++) {
        const core_ship_block *bl = &ship->blocks[k];
        c->blocks[k] = dCreateBox(0, bl->x1_m - bl->x0_m, bl->y1_m - bl->y0_m, bl->z1_m - bl->z0_m);
        dGeomSetBody(c->blocks[k], c->deck_body);
        dGeomSetOffsetPosition(c->blocks[k], 0.5 * (bl->x0_m + bl->x1_m), 0.5 * (bl->y0_m + bl->y1_m),
                               0.5 * (bl->z0_m + bl->z1_m));
    }
    c->point = dCreateSphere(0, STRIKE_RADIUS_M);
    for (int i = 0; i < c->g.nlegs; i++) {
        leg_rt *L = &c->leg[i];
        L->sphere = dCreateSphere(0, 2 * c->g.leg[i].tyre_radius_m + c->g.leg[i].stroke_m);
        L->mass_share_kg = load[i] / CORE_G_MPS2;
        /* critical damping of the tyre's tangential spring with the leg's share of the mass */
        L->cb_Nspm = 2.0 * sqrt(c->g.leg[i].tyre_stiffness_Npm * L->mass_share_kg);
    }
    return c;
fail:
    sim_contact_destroy(c);
    return NULL;
}

void sim_contact_destroy(sim_contact *c)
{
    if (!c)
        return;
    for (int i = 0; i < HFM_GEAR_MAX_LEGS; i++)
        if (c->leg[i].sphere)
            dGeomDestroy(c->leg[i].sphere);
    for (int k = 0; k < CORE_SHIP_MAX_BLOCKS; k++)
        if (c->blocks[k])
            dGeomDestroy(c->blocks[k]);
    if (c->point)
        dGeomDestroy(c->point);
    if (c->deck)
        dGeomDestroy(c->deck);
    if (c->world)
        dWorldDestroy(c->world); /* and the deck's body */
    if (c->ode)
        dCloseODE();
    free(c);
}
