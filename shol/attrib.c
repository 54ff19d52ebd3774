/*
 * attrib.c -- what drives a direction's limit: the limiting
 * quantity's load budget, compared between the limiting trim and a
 * reference trim, names the flight-model component whose change the
 * limiting control (or attitude) had to balance.
 *
 * Model. A trim over the spot is an equilibrium: the sum over the
 * components c (main rotor, tail rotor, fuselage, stabiliser, fin,
 * gravity) of the force and of the moment about the CG is zero (the
 * seed paper's eqs. 7-8 with every acceleration zero). "The balance of
 * forces determines the orientation of the main rotor in space. The
 * balance of moments about the aircraft centre of gravity determines the
 * attitude adopted by the airframe" (Seddon and Newman, Basic Helicopter
 * Aerodynamics, 3rd ed., Wiley 2011, section 8.1). So each rejection
 * criterion is set by one row of that balance (shol.h, "What drives a
 * direction's limit"): the pedal by the yaw moment N, which the tail rotor
 * supplies; the cyclic and the attitudes by the pitch / roll moment M / L,
 * which the main rotor's hub moment and thrust offset supply (the
 * horizontal force is given as the attitude's secondary budget: it sets
 * where the rotor points, and with it how far the body must tilt); the
 * collective by the vertical force, which the main rotor's thrust
 * supplies. Differencing the row between a reference trim (r) and the
 * trim attributed (a):
 *
 *     sum_c [B_c(a) - B_c(r)] = 0   =>   dB_E = - sum_{c != E} dB_c,
 *
 * with E the effector the criterion's control moves. The share of
 * component c is s_c = -dB_c / dB_E; the shares of the others sum to 1
 * (less the trim residual's part, `closure`). The driver is the largest
 * share: the component whose change the effector (and so the limiting
 * control) had to balance most.
 *
 * Assumptions and limits: a first-difference budget, not a derivative;
 * it names which load changed, not how sensitive the control is to it.
 * A change in the effector's own effectiveness (the tail rotor's inflow
 * in a crosswind, the main rotor's translational lift) moves the control
 * without changing the effector's load; the effector's change relative to
 * its reference value (effector_ref) is given so that a reader can see it
 * (a pedal that moved far with the tail rotor's moment nearly unchanged).
 * The forces are taken in ship axes (psi = 0 over the spot), where the
 * weight is constant and drops out; the moments in body axes about the CG,
 * where the weight has none.
 */
#include "shol.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static const char *const comp_names[SHOL_NCOMP] = {"main_rotor", "tail_rotor", "fuselage",
                                                   "stabilator", "fin",        "gravity"};
static const char *const comp_words[SHOL_NCOMP] = {"main rotor", "tail rotor", "fuselage",
                                                   "stabilator", "fin",        "gravity"};
static const char *const budget_names[SHOL_NBUDGET] = {"x_force",     "y_force",      "z_force",
                                                       "roll_moment", "pitch_moment", "yaw_moment"};

void shol_loads_set(shol_loads *out, const double *const F_B_N[SHOL_NCOMP - 1],
                    const double *const M_B_Nm[SHOL_NCOMP - 1], const double total_F_B_N[3],
                    const double total_M_B_Nm[3], double mr_power_W, double tr_power_W)
{
    for (int a = 0; a < 3; a++) {
        double F = total_F_B_N[a], M = total_M_B_Nm[a];
        for (int k = 0; k < SHOL_NCOMP - 1; k++) {
            out->F_B_N[k][a] = F_B_N[k][a];
            out->M_B_Nm[k][a] = M_B_Nm[k][a];
            F -= F_B_N[k][a];
            M -= M_B_Nm[k][a];
        }
        out->F_B_N[SHOL_COMP_GRAVITY][a] = F;
        out->M_B_Nm[SHOL_COMP_GRAVITY][a] = M;
    }
    out->mr_power_W = mr_power_W;
    out->tr_power_W = tr_power_W;
    out->valid = 1;
}

const char *shol_comp_name(int comp)
{
    return comp >= 0 && comp < SHOL_NCOMP ? comp_names[comp] : NULL;
}

const char *shol_budget_name(int budget)
{
    return budget >= 0 && budget < SHOL_NBUDGET ? budget_names[budget] : NULL;
}

int shol_crit_budget(int crit, int *secondary)
{
    int p = -1, s = -1;
    switch (crit) {
    case SHOL_CRIT_ROLL: p = SHOL_BUDGET_L; s = SHOL_BUDGET_Y; break;
    case SHOL_CRIT_PITCH: p = SHOL_BUDGET_M; s = SHOL_BUDGET_X; break;
    case SHOL_CRIT_LONG: p = SHOL_BUDGET_M; break;
    case SHOL_CRIT_LAT: p = SHOL_BUDGET_L; break;
    case SHOL_CRIT_COLL: p = SHOL_BUDGET_Z; break;
    case SHOL_CRIT_PEDAL: p = SHOL_BUDGET_N; break;
    default: break;
    }
    if (secondary)
        *secondary = s;
    return p;
}

/* The effector of a budget: the tail rotor for yaw, else the main rotor. */
static int budget_effector(int budget)
{
    return budget == SHOL_BUDGET_N ? SHOL_COMP_TR : SHOL_COMP_MR;
}

static double crit_value(const shol_trim_point *p, int crit)
{
    const double v[SHOL_NCRIT] = {p->phi_rad,        p->theta_rad,      p->long_cyclic_pct,
                                  p->lat_cyclic_pct, p->collective_pct, p->pedal_pct};
    return v[crit];
}

/* Component c's term of the budget at sample s. */
static double term(const shol_sample *s, int budget, int c)
{
    const shol_loads *L = &s->loads;
    if (budget >= SHOL_BUDGET_L)
        return L->M_B_Nm[c][budget - SHOL_BUDGET_L];
    core_euler e = {s->trim.phi_rad, s->trim.theta_rad, 0.0}; /* heading along the bow */
    core_vec3 F = core_mat3_mul_vec(core_mat3_from_euler(e),
                                    core_vec3_make(L->F_B_N[c][0], L->F_B_N[c][1], L->F_B_N[c][2]));
    return budget == SHOL_BUDGET_X ? F.x : budget == SHOL_BUDGET_Y ? F.y : F.z;
}

static int usable(const shol_sample *s)
{
    return s && s->trim_status == 0 && s->loads.valid;
}

static const shol_sample *sample_at(const shol_dir_result *d, double v)
{
    for (int i = 0; i < d->n_samples; i++)
        if (fabs(d->samples[i].speed_mps - v) < 1e-9)
            return &d->samples[i];
    return NULL;
}

static void undefined(shol_attribution *out)
{
    memset(out, 0, sizeof *out);
    out->crit = SHOL_LIMIT_NONE;
    out->budget = out->effector = out->driver = -1;
    out->ref_speed_mps = out->at_speed_mps = out->closure = NAN;
    out->control_ref = out->control_at = out->effector_ref = out->effector_change = NAN;
    out->mr_power_change_W = out->tr_power_change_W = NAN;
    for (int c = 0; c < SHOL_NCOMP; c++)
        out->value_ref[c] = out->change[c] = out->share[c] = NAN;
}

int shol_envelope_attribution(const shol_dir_result *d, int budget, shol_attribution *out)
{
    undefined(out);
    if (!d || d->n_samples < 1 || budget < -1 || budget >= SHOL_NBUDGET)
        return 1;
    /* the trim attributed: the first failure where a criterion limited
     * the direction, else the closest criterion at the last pass */
    const shol_sample *a = NULL;
    int crit = -1, at_limit = 0;
    if (d->limit >= SHOL_CRIT_ROLL && d->limit < SHOL_NCRIT && isfinite(d->fail_speed_mps)) {
        a = sample_at(d, d->fail_speed_mps);
        crit = d->limit;
        at_limit = 1;
    }
    if (!usable(a) && d->has_pass) {
        a = sample_at(d, d->max_speed_mps);
        crit = a ? a->eval.limit : -1;
        at_limit = 0;
    }
    if (!usable(a) || crit < SHOL_CRIT_ROLL || crit >= SHOL_NCRIT)
        return 1;
    /* the reference: the lowest converged speed with loads (the calm hover) */
    const shol_sample *r = NULL;
    for (int i = 0; i < d->n_samples && !r; i++)
        if (usable(&d->samples[i]))
            r = &d->samples[i];
    if (!r || !(a->speed_mps > r->speed_mps))
        return 1;
    int b = budget >= 0 ? budget : shol_crit_budget(crit, NULL);
    int e = budget_effector(b);
    double sum = 0.0, big = 0.0;
    for (int c = 0; c < SHOL_NCOMP; c++) {
        out->value_ref[c] = term(r, b, c);
        double at = term(a, b, c);
        out->change[c] = at - out->value_ref[c];
        sum += out->change[c];
        big = fmax(big, fmax(fabs(at), fabs(out->value_ref[c])));
    }
    double de = out->change[e];
    /* an effector that did not change (to rounding of the budget's largest
     * term) balanced nothing: no share means anything */
    if (!(fabs(de) > 1e-9 * big) || !isfinite(de) || !isfinite(sum)) {
        undefined(out);
        return 1;
    }
    out->crit = crit;
    out->at_limit = at_limit;
    out->budget = b;
    out->effector = e;
    out->ref_speed_mps = r->speed_mps;
    out->at_speed_mps = a->speed_mps;
    out->control_ref = crit_value(&r->trim, crit);
    out->control_at = crit_value(&a->trim, crit);
    out->effector_ref = out->value_ref[e];
    out->effector_change = de;
    out->closure = fabs(sum) / fabs(de);
    out->driver = -1;
    for (int c = 0; c < SHOL_NCOMP; c++) {
        if (c == e)
            continue;
        out->share[c] = -out->change[c] / de;
        if (out->driver < 0 || out->share[c] > out->share[out->driver])
            out->driver = c;
    }
    out->mr_power_change_W = a->loads.mr_power_W - r->loads.mr_power_W;
    out->tr_power_change_W = a->loads.tr_power_W - r->loads.tr_power_W;
    return 0;
}

void shol_attribution_format(const shol_attribution *a, char *buf, size_t n)
{
    if (!a || a->driver < 0 || a->effector < 0) {
        snprintf(buf, n, "-");
        return;
    }
    const char *u = a->budget >= SHOL_BUDGET_L ? "kN m" : "kN";
    const double k = 1e-3; /* kN, kN m */
    /* the quantity attributed at both trims, with its primary budget only */
    char ctl[96] = "";
    if (shol_crit_budget(a->crit, NULL) == a->budget) {
        const int ang = a->crit <= SHOL_CRIT_PITCH;
        const double q = ang ? CORE_RAD_TO_DEG : 1.0;
        snprintf(ctl, sizeof ctl, "; %s %.1f to %.1f %s", shol_limit_name(a->crit), q * a->control_ref,
                 q * a->control_at, ang ? "deg" : "%");
    }
    snprintf(buf, n, "%s: %s %.0f %% of the %s's change %+.2f %s (%.2f %s at %.0f km/h)%s", budget_names[a->budget],
             comp_words[a->driver], 100.0 * a->share[a->driver], comp_words[a->effector], k * a->effector_change, u,
             k * a->effector_ref, u, a->ref_speed_mps / CORE_KMH_TO_MPS, ctl);
}
