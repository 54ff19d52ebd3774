/*
 * envelope.c -- the candidate SHOL procedure over a caller's trim.
 *
 * Model: the seed paper's section 2.8 (Fig. 4). For each WOD direction,
 * start at 0 km/h, trim, judge the trim against the rejection criteria,
 * raise the speed by a fixed step (5 km/h) and repeat until a criterion is
 * exceeded; the last passing speed is the envelope radius at that
 * direction and the exceeded criterion is reported. A trim that does not
 * converge counts as a rejection ("trim"). As an option the bracket
 * [last pass, first failure] is refined by bisection.
 * Assumptions: the trim is steady and depends only on the WOD (no ship
 * motion, no pilot model); along a direction the criteria are crossed once,
 * so the first failure bounds the envelope (a pass above a failure is not
 * searched for, which is the conservative reading), and the bisection
 * assumes a single crossing inside the bracket.
 */
#include "shol.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

void shol_settings_default(shol_settings *s)
{
    memset(s, 0, sizeof *s);
    shol_settings_dirs(s, -90.0 * CORE_DEG_TO_RAD, 90.0 * CORE_DEG_TO_RAD, 30.0 * CORE_DEG_TO_RAD,
                       NULL);
    s->speed_step_mps = 5.0 * CORE_KMH_TO_MPS;
    s->speed_max_mps = 150.0 * CORE_KMH_TO_MPS;
    s->bisect_tol_mps = 0.0;
    shol_criteria_default(&s->criteria);
}

static double wrap_rad(double a)
{
    return core_wod_wrap_deg(a * CORE_RAD_TO_DEG) * CORE_DEG_TO_RAD;
}

int shol_settings_dirs(shol_settings *s, double first_rad, double last_rad, double step_rad,
                       core_err *err)
{
    if (!(step_rad > 0) || !isfinite(first_rad) || !isfinite(last_rad) || last_rad < first_rad)
        return core_err_set(err, -1,
                            "shol: directions %g to %g deg by %g deg: expected first <= last "
                            "and a step > 0",
                            first_rad * CORE_RAD_TO_DEG, last_rad * CORE_RAD_TO_DEG,
                            step_rad * CORE_RAD_TO_DEG);
    double n_real = floor((last_rad - first_rad) / step_rad + 1e-9) + 1;
    if (n_real > SHOL_MAX_DIRS)
        return core_err_set(err, -1, "shol: %.0f directions, at most %d", n_real, SHOL_MAX_DIRS);
    s->n_dirs = (int)n_real;
    for (int i = 0; i < s->n_dirs; i++) {
        /* Round to 1e-9 deg so that -90 + 3 * 30 prints as 0, not -1e-15. */
        double d = (first_rad + i * step_rad) * CORE_RAD_TO_DEG;
        d = round(d * 1e9) / 1e9;
        s->dirs_rad[i] = wrap_rad(d * CORE_DEG_TO_RAD);
    }
    return 0;
}

int shol_settings_full_circle(shol_settings *s, double step_rad, core_err *err)
{
    double n = 2 * CORE_PI / step_rad;
    if (!(step_rad > 0) || fabs(n - round(n)) * step_rad > 1e-9)
        return core_err_set(err, -1, "shol: full circle step %g deg: expected a divisor of 360",
                            step_rad * CORE_RAD_TO_DEG);
    return shol_settings_dirs(s, -CORE_PI + step_rad, CORE_PI, step_rad, err);
}

int shol_settings_check(const shol_settings *s, core_err *err)
{
    if (s->n_dirs < 1 || s->n_dirs > SHOL_MAX_DIRS)
        return core_err_set(err, -1, "shol: n_dirs = %d: expected 1 to %d", s->n_dirs,
                            SHOL_MAX_DIRS);
    for (int i = 0; i < s->n_dirs; i++)
        if (!isfinite(s->dirs_rad[i]) || s->dirs_rad[i] <= -CORE_PI - 1e-12 ||
            s->dirs_rad[i] > CORE_PI + 1e-12)
            return core_err_set(err, -1, "shol: dirs_rad[%d] = %g: expected (-pi, pi]", i,
                                s->dirs_rad[i]);
    if (!(s->speed_step_mps > 0) || !isfinite(s->speed_step_mps))
        return core_err_set(err, -1, "shol: speed_step_mps = %g: expected > 0", s->speed_step_mps);
    if (!(s->speed_max_mps >= 0) || !isfinite(s->speed_max_mps))
        return core_err_set(err, -1, "shol: speed_max_mps = %g: expected >= 0", s->speed_max_mps);
    if (!(s->bisect_tol_mps >= 0) || !isfinite(s->bisect_tol_mps))
        return core_err_set(err, -1, "shol: bisect_tol_mps = %g: expected >= 0", s->bisect_tol_mps);
    /* A NaN limit is never exceeded (NaN < 0 is false): every trim would
     * pass and the envelope would be the whole search. Same ranges as the
     * [rejection] reader. */
    const shol_criteria *c = &s->criteria;
    const double ang[2] = {c->roll_max_rad, c->pitch_max_rad};
    const char *const ang_name[2] = {"roll_max_rad", "pitch_max_rad"};
    for (int i = 0; i < 2; i++)
        if (!(ang[i] >= 0 && ang[i] <= 0.5 * CORE_PI + 1e-12))
            return core_err_set(err, -1, "shol: criteria.%s = %g: expected 0 to pi/2", ang_name[i], ang[i]);
    const double ctl[4] = {c->long_cyclic_pct, c->lat_cyclic_pct, c->collective_pct, c->pedal_pct};
    const char *const ctl_name[4] = {"long_cyclic_pct", "lat_cyclic_pct", "collective_pct", "pedal_pct"};
    for (int i = 0; i < 4; i++)
        if (!(ctl[i] >= 50 && ctl[i] <= 100))
            return core_err_set(err, -1, "shol: criteria.%s = %g: expected 50 to 100", ctl_name[i], ctl[i]);
    if (s->speed_max_mps / s->speed_step_mps > 1e6)
        return core_err_set(err, -1, "shol: %g speeds per direction: step too small",
                            s->speed_max_mps / s->speed_step_mps);
    return 0;
}

void shol_result_free(shol_result *r)
{
    if (!r)
        return;
    if (r->dirs)
        for (int i = 0; i < r->n_dirs; i++)
            free(r->dirs[i].samples);
    free(r->dirs);
    r->dirs = NULL;
    r->n_dirs = 0;
}

void shol_progress_format(const shol_progress *p, char *buf, size_t n)
{
    char name[32], left[48];
    core_wod_name(p->dir_rad * CORE_RAD_TO_DEG, name, sizeof name);
    if (p->done)
        snprintf(left, sizeof left, "done in %.0f s", p->elapsed_s);
    else if (!isfinite(p->eta_s))
        snprintf(left, sizeof left, "time left unknown");
    else if (p->eta_s >= 60)
        snprintf(left, sizeof left, "%d min %02d s left", (int)(p->eta_s / 60),
                 (int)fmod(p->eta_s, 60));
    else
        snprintf(left, sizeof left, "%.0f s left", p->eta_s);
    /* Coupled trims take minutes, analytic ones microseconds: say it the
     * readable way round. */
    char rate[32];
    if (!(p->rate_per_s > 0))
        snprintf(rate, sizeof rate, "rate unknown");
    else if (p->rate_per_s < 1.0 / 60)
        snprintf(rate, sizeof rate, "%.1f min/trim", 1 / (60 * p->rate_per_s));
    else if (p->rate_per_s < 1)
        snprintf(rate, sizeof rate, "%.1f s/trim", 1 / p->rate_per_s);
    else
        snprintf(rate, sizeof rate, "%.0f trim/s", p->rate_per_s);
    snprintf(buf, n, "%3.0f%% %s at %.0f km/h, %d trims, %s, %s", 100 * p->fraction, name,
             p->speed_mps / CORE_KMH_TO_MPS, p->n_trims, rate, left);
}

/* The state of one sweep. */
typedef struct sweep {
    const shol_settings *s;
    shol_trim_fn trim;
    void *trim_user;
    shol_progress_fn progress;
    void *progress_user;
    const core_log *log;
    double t0;
    int n_trims;
} sweep;

static void report(sweep *w, int idir, double speed_mps, double dir_fraction, int done)
{
    if (!w->progress)
        return;
    shol_progress p = {0};
    p.dir_index = idir;
    p.n_dirs = w->s->n_dirs;
    p.dir_rad = w->s->dirs_rad[idir];
    p.speed_mps = speed_mps;
    p.n_trims = w->n_trims;
    if (dir_fraction > 1)
        dir_fraction = 1;
    p.fraction = done ? 1.0 : (idir + dir_fraction) / w->s->n_dirs;
    p.elapsed_s = core_monotonic_s() - w->t0;
    p.rate_per_s = p.elapsed_s > 0 ? w->n_trims / p.elapsed_s : 0;
    p.eta_s = done ? 0 : (p.fraction > 0 ? p.elapsed_s * (1 - p.fraction) / p.fraction : NAN);
    p.done = done;
    w->progress(w->progress_user, &p);
}

/* Append a sample; < 0 on out of memory or a fatal trim error. */
static int trim_at(sweep *w, shol_dir_result *d, int *cap, double v, core_err *err)
{
    if (d->n_samples == *cap) {
        int nc = *cap ? 2 * *cap : 32;
        shol_sample *ns = realloc(d->samples, nc * sizeof *ns);
        if (!ns)
            return core_err_set(err, -1, "shol: out of memory");
        d->samples = ns;
        *cap = nc;
    }
    shol_sample *sm = &d->samples[d->n_samples];
    memset(sm, 0, sizeof *sm);
    sm->speed_mps = v;
    char name[32];
    core_wod_name(d->dir_rad * CORE_RAD_TO_DEG, name, sizeof name);
    int rc = w->trim(w->trim_user, v, d->dir_rad, &sm->trim);
    w->n_trims++;
    if (rc < 0)
        return core_err_set(err, -1, "shol: trim failed fatally at %s, %.3f km/h (%.3f kt)", name,
                            v / CORE_KMH_TO_MPS, v / CORE_KT_TO_MPS);
    sm->trim_status = rc;
    if (rc > 0) {
        for (int k = 0; k < SHOL_NCRIT; k++)
            sm->eval.margin[k] = NAN;
        sm->eval.limit = SHOL_LIMIT_TRIM;
        core_log_msg(w->log, CORE_LOG_INFO, "shol: %s %.1f km/h: trim did not converge (%d)", name,
                     v / CORE_KMH_TO_MPS, rc);
    } else if (shol_criteria_eval(&w->s->criteria, &sm->trim, &sm->eval) < 0) {
        /* A "converged" trim with NaN inside cannot clear a speed. */
        sm->trim_status = 1;
        core_log_msg(w->log, CORE_LOG_WARN,
                     "shol: %s %.1f km/h: trim reported converged with a non-finite value; "
                     "counted as not converged",
                     name, v / CORE_KMH_TO_MPS);
    } else {
        sm->pass = sm->eval.n_exceeded == 0;
        core_log_msg(w->log, CORE_LOG_DEBUG,
                     "shol: %s %.1f km/h: roll %.2f deg pitch %.2f deg long %.1f%% lat %.1f%% "
                     "coll %.1f%% pedal %.1f%%: %s (%s)",
                     name, v / CORE_KMH_TO_MPS, sm->trim.phi_rad * CORE_RAD_TO_DEG,
                     sm->trim.theta_rad * CORE_RAD_TO_DEG, sm->trim.long_cyclic_pct,
                     sm->trim.lat_cyclic_pct, sm->trim.collective_pct, sm->trim.pedal_pct,
                     sm->pass ? "pass" : "reject", shol_limit_name(sm->eval.limit));
    }
    d->n_samples++;
    return 0;
}

static int by_speed(const void *a, const void *b)
{
    double x = ((const shol_sample *)a)->speed_mps, y = ((const shol_sample *)b)->speed_mps;
    return (x > y) - (x < y);
}

static int sweep_dir(sweep *w, int idir, shol_dir_result *d, core_err *err)
{
    const shol_settings *s = w->s;
    int cap = 0;
    d->dir_rad = s->dirs_rad[idir];
    d->fail_speed_mps = NAN;
    d->limit = SHOL_LIMIT_NONE;
    int ipass = -1, ifail = -1;

    /* Speeds k * step, computed from k so that steps do not accumulate
     * rounding; the top is speed_max within a 1e-9 step. */
    long kmax = (long)floor(s->speed_max_mps / s->speed_step_mps + 1e-9);
    for (long k = 0; k <= kmax; k++) {
        double v = k * s->speed_step_mps;
        if (trim_at(w, d, &cap, v, err) < 0)
            return -1;
        int i = d->n_samples - 1;
        report(w, idir, v, s->speed_max_mps > 0 ? v / s->speed_max_mps : 1, 0);
        if (d->samples[i].pass) {
            ipass = i;
        } else {
            ifail = i;
            break;
        }
    }

    /* Bisection between the last pass and the first failure. */
    if (ipass >= 0 && ifail >= 0 && s->bisect_tol_mps > 0) {
        double lo = d->samples[ipass].speed_mps, hi = d->samples[ifail].speed_mps;
        while (hi - lo > s->bisect_tol_mps) {
            double v = 0.5 * (lo + hi);
            if (trim_at(w, d, &cap, v, err) < 0)
                return -1;
            int i = d->n_samples - 1;
            report(w, idir, hi, s->speed_max_mps > 0 ? hi / s->speed_max_mps : 1, 0);
            if (d->samples[i].pass) {
                lo = v;
                ipass = i;
            } else {
                hi = v;
                ifail = i;
            }
        }
    }

    /* Copy the verdict before the history is sorted (indices move). */
    if (ipass >= 0) {
        d->has_pass = 1;
        d->max_speed_mps = d->samples[ipass].speed_mps;
        d->margins = d->samples[ipass].eval;
    } else {
        d->has_pass = 0;
        d->max_speed_mps = 0;
        d->margins = d->samples[0].eval;
    }
    if (ifail >= 0) {
        d->fail_speed_mps = d->samples[ifail].speed_mps;
        d->limit = d->samples[ifail].eval.limit;
    }
    qsort(d->samples, d->n_samples, sizeof *d->samples, by_speed);

    char name[32];
    core_wod_name(d->dir_rad * CORE_RAD_TO_DEG, name, sizeof name);
    if (d->has_pass)
        core_log_msg(w->log, CORE_LOG_INFO, "shol: %s: %.1f km/h (%.1f kt), limited by %s", name,
                     d->max_speed_mps / CORE_KMH_TO_MPS, d->max_speed_mps / CORE_KT_TO_MPS,
                     shol_limit_name(d->limit));
    else
        core_log_msg(w->log, CORE_LOG_WARN, "shol: %s: rejected already at 0 km/h (%s)", name,
                     shol_limit_name(d->limit));
    return 0;
}

int shol_envelope_run(const shol_settings *s, shol_trim_fn trim, void *trim_user,
                      shol_progress_fn progress, void *progress_user, const core_log *log,
                      shol_result *out, core_err *err)
{
    memset(out, 0, sizeof *out);
    if (!trim)
        return core_err_set(err, -1, "shol: no trim callback");
    if (shol_settings_check(s, err) < 0)
        return -1;
    sweep w = {s, trim, trim_user, progress, progress_user, log, core_monotonic_s(), 0};
    out->settings = *s;
    out->dirs = calloc(s->n_dirs, sizeof *out->dirs);
    if (!out->dirs)
        return core_err_set(err, -1, "shol: out of memory");
    out->n_dirs = s->n_dirs;
    for (int i = 0; i < s->n_dirs; i++) {
        if (sweep_dir(&w, i, &out->dirs[i], err) < 0) {
            shol_result_free(out);
            return -1;
        }
        report(&w, i, out->dirs[i].max_speed_mps, 1.0, i == s->n_dirs - 1);
    }
    out->n_trims = w.n_trims;
    out->wall_s = core_monotonic_s() - w.t0;
    return 0;
}

/* ------------------------------------------------- near a cheap boundary */
typedef struct near_ctx {
    const shol_result *cheap_res;
    shol_trim_fn cheap, costly;
    void *cheap_user, *costly_user;
    double margin_mps;
    double *extra_mps; /* per direction of cheap_res: the costly region starts this much lower */
} near_ctx;

/* The index of dir in the cheap sweep, or -1. */
static int near_index(const near_ctx *n, double dir)
{
    for (int i = 0; i < n->cheap_res->n_dirs; i++)
        if (fabs(n->cheap_res->dirs[i].dir_rad - dir) < 1e-9)
            return i;
    return -1;
}

/* The lowest speed trimmed with the costly trim at dir. */
static double near_from(const near_ctx *n, double dir)
{
    int i = near_index(n, dir);
    if (i < 0)
        return 0.0; /* a direction the cheap sweep did not see: costly throughout */
    const shol_dir_result *d = &n->cheap_res->dirs[i];
    return (d->has_pass ? d->max_speed_mps : 0.0) - n->margin_mps - n->extra_mps[i];
}

static int near_trim(void *user, double v, double dir, shol_trim_point *out)
{
    near_ctx *n = user;
    if (v >= near_from(n, dir) - 1e-9)
        return n->costly(n->costly_user, v, dir, out);
    return n->cheap(n->cheap_user, v, dir, out);
}

int shol_envelope_run_near(const shol_settings *s, const shol_result *cheap_result, shol_trim_fn cheap,
                           void *cheap_user, shol_trim_fn costly, void *costly_user, double margin_mps,
                           shol_progress_fn progress, void *progress_user, const core_log *log, shol_result *out,
                           core_err *err)
{
    memset(out, 0, sizeof *out);
    if (!cheap || !costly || !cheap_result)
        return core_err_set(err, -1, "shol: no trim callback or no cheap result");
    if (!(margin_mps > 0.0))
        return core_err_set(err, -1, "shol: margin_mps = %g: expected > 0", margin_mps);
    near_ctx n = {cheap_result, cheap, costly, cheap_user, costly_user, margin_mps, NULL};
    n.extra_mps = calloc(cheap_result->n_dirs > 0 ? cheap_result->n_dirs : 1, sizeof *n.extra_mps);
    int *idx = malloc(sizeof *idx * SHOL_MAX_DIRS);
    shol_settings *again = malloc(sizeof *again);
    if (!n.extra_mps || !idx || !again) {
        free(n.extra_mps);
        free(idx);
        free(again);
        return core_err_set(err, -1, "shol: out of memory");
    }
    int rc = shol_envelope_run(s, near_trim, &n, progress, progress_user, log, out, err);
    /* Where no costly-trimmed speed passed, the radius would be a speed that
     * only the cheap trim passed: sweep that direction again with the costly
     * region lower, until a costly speed passes or it starts at 0. The
     * region starts 1, 3, 7, 15, ... margins lower (a cheap boundary far too
     * high costs a few rounds, not one per margin); the sweep up from there
     * finds the first failure at the step. */
    while (rc == 0) {
        *again = *s;
        again->n_dirs = 0;
        for (int i = 0; i < out->n_dirs; i++) {
            const shol_dir_result *d = &out->dirs[i];
            double from = near_from(&n, d->dir_rad);
            if (!isfinite(d->fail_speed_mps) || from <= 1e-9 || (d->has_pass && d->max_speed_mps >= from - 1e-9))
                continue;
            int j = near_index(&n, d->dir_rad); /* >= 0: from > 0 */
            n.extra_mps[j] = 2.0 * n.extra_mps[j] + margin_mps; /* 1, 3, 7, 15 margins lower */
            char name[32];
            core_wod_name(d->dir_rad * CORE_RAD_TO_DEG, name, sizeof name);
            core_log_msg(log, CORE_LOG_INFO, "shol: %s: no costly trim passed; again with the costly region from %.1f km/h",
                         name, fmax(near_from(&n, d->dir_rad), 0.0) / CORE_KMH_TO_MPS);
            idx[again->n_dirs] = i;
            again->dirs_rad[again->n_dirs++] = d->dir_rad;
        }
        if (again->n_dirs == 0)
            break;
        shol_result r;
        if ((rc = shol_envelope_run(again, near_trim, &n, progress, progress_user, log, &r, err)) != 0) {
            shol_result_free(out);
            break;
        }
        for (int k = 0; k < again->n_dirs; k++) {
            shol_dir_result tmp = out->dirs[idx[k]];
            out->dirs[idx[k]] = r.dirs[k];
            r.dirs[k] = tmp; /* the superseded sweep is freed with r */
        }
        out->n_trims += r.n_trims;
        out->wall_s += r.wall_s;
        shol_result_free(&r);
    }
    free(n.extra_mps);
    free(idx);
    free(again);
    return rc;
}

static const shol_sample *sample_at(const shol_dir_result *d, double v)
{
    for (int i = 0; i < d->n_samples; i++)
        if (fabs(d->samples[i].speed_mps - v) < 1e-9)
            return &d->samples[i];
    return NULL;
}

int shol_envelope_sensitivity(const shol_dir_result *d, shol_sensitivity *out)
{
    out->crit = SHOL_LIMIT_NONE;
    out->side = 0;
    out->slope_per_mps = out->ref_error = out->shift_mps = NAN;
    if (!d->has_pass || !isfinite(d->fail_speed_mps) || d->limit < SHOL_CRIT_ROLL || d->limit >= SHOL_NCRIT)
        return 1;
    const shol_sample *p = sample_at(d, d->max_speed_mps), *q = sample_at(d, d->fail_speed_mps);
    if (!p || !q || p->trim_status || q->trim_status || !(q->speed_mps > p->speed_mps))
        return 1;
    /* the limiting criterion's own margin at both speeds: a secant through
     * the crossing, so the slope is the one the step actually saw */
    const int c = d->limit;
    double slope = (p->eval.margin[c] - q->eval.margin[c]) / (q->speed_mps - p->speed_mps);
    if (!(slope > 0.0))
        return 1;
    /* the side of its limit the quantity crossed: its value at the failure
     * against neutral (0 for an attitude, 50 % for a cyclic or the pedal;
     * the collective has only its upper limit) */
    const shol_trim_point *t = &q->trim;
    const double beyond[SHOL_NCRIT] = {t->phi_rad,          t->theta_rad,          t->long_cyclic_pct - 50.0,
                                       t->lat_cyclic_pct - 50.0, 1.0, t->pedal_pct - 50.0};
    out->crit = c;
    out->side = beyond[c] < 0 ? -1 : 1;
    out->slope_per_mps = slope;
    out->ref_error = c <= SHOL_CRIT_PITCH ? 0.25 * CORE_DEG_TO_RAD : 1.0;
    out->shift_mps = out->ref_error / slope;
    return 0;
}
