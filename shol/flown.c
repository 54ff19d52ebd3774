/*
 * flown.c -- the SHOL from flown tasks: a WOD point is flown,
 * not trimmed, and judged over its whole time history.
 *
 * Model. At each WOD point the caller's fly callback flies the task (an
 * automated pilot landing on the moving deck in the field's turbulence)
 * once per seed. A flight is rejected when a rejection criterion of the
 * trim-based procedure (seed paper Table 4, docs/conventions.md) is exceeded
 * during the flight (shol_flown_track), when the touchdown is
 * outside the task's adequate limits, when the task's adequate tolerances
 * are not met, when the aircraft strikes the ship, or when it cannot be
 * trimmed at the start. Turbulence and waves make a flight random, so a
 * point is judged by its pass rate over n_seeds seeds: it passes when the
 * rate reaches pass_rate_min (0.8 by default: 9 of the default 11 seeds).
 *
 * The pass rate's interval. n seeds sample the pass probability p; the
 * point's 90 % interval is Wilson's score interval (Wilson 1927, JASA
 * 22(158), 209-212), which keeps its coverage at rates near 0 and 1 where
 * the normal interval collapses: with p^ = k/n and z = 1.6449,
 *     centre = (p^ + z^2/(2n)) / (1 + z^2/n)
 *     half   = z / (1 + z^2/n) sqrt(p^(1 - p^)/n + z^2/(4n^2))
 * (9 of 10: 0.652 to 0.977). The rule, a flight-test engineer's: a point
 * CLEARLY PASSES when the interval's lower bound reaches the threshold,
 * CLEARLY FAILS when its upper bound is below it, and is UNDECIDED
 * between (more seeds would decide it). The flown limit is the highest
 * speed whose pass rate reaches the threshold (the search's verdict, as
 * before); its band runs from the highest speed flown whose lower bound
 * clears the threshold to the highest whose upper bound does, open above
 * where the highest point flown is not a clear failure. The default
 * number of seeds: with none failing, the lower bound is n/(n + z^2); it
 * clears 0.8 from n >= 4 z^2 = 10.8, so 11 seeds (at least 10) are the
 * fewest at which any point can clearly pass; at 11, 9 passes (0.82) give
 * 0.57 to 0.94 and 7 (0.64) 0.39 to 0.83, an interval wide
 * near the threshold (about 0.36). More seeds narrow it as 1/sqrt(n).
 *
 * The search per direction (its cost is the point): flights cost about a
 * second each where a one-way trim costs milliseconds, so the flown
 * search starts near the trim envelope's boundary instead of at 0: at the
 * grid speed start_steps_below steps below the trim radius. Unless that
 * point clearly passes, it steps down until one does (or 0 is flown;
 * with too few seeds for any point to pass clearly, until one passes);
 * unless it clearly fails, it steps up until one does (or the top of the
 * search), past points that fail narrowly (undecided), since the limit is
 * the highest speed whose pass rate clears the threshold below the lowest
 * clear failure, and the band needs both of its ends flown. The bracket
 * between that limit and the lowest failing speed above it may then be
 * bisected. The points below the lowest speed flown are taken as passing
 * without being flown: the assumption, as in the trim-based procedure, is
 * that along a direction the envelope is crossed once; where a clear
 * failure sits below it, the clear failure ends the search.
 *
 * The tracker (shol_flown_track). Table 4's limits are the trim's, steady
 * values, read as shol_criteria_eval reads them (a cyclic's or the
 * pedal's limit a displacement from neutral, the collective's from full
 * down); a flown history also holds gusts' peaks lasting fractions of a
 * second, which a steady limit does not judge. So the steady limits judge
 * the running mean of each quantity over the last window_s seconds of the
 * task's phase (bins of window_s / SHOL_FLOWN_BINS; from the time the
 * phase has lasted window_s, a shorter phase on its whole mean as it
 * ends; a new phase starts a new mean, so a manoeuvre's steady state is
 * not averaged with the last one's), and transient criteria judge every
 * step: a control at its stop (0 or 100 % of full travel, the collective
 * full down included: a pilot there has no control left that way, which
 * no reading of Table 4 covers), an attitude past the steady limit times
 * 1 + transient_frac. window_s = 0 judges the steady limits at every step,
 * as the trim-based criteria applied to each instant.
 */
#include "io.h"
#include "shol.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

void shol_wilson(int n_pass, int n, double z, double *lo, double *hi)
{
    if (n < 1) {
        *lo = 0.0;
        *hi = 1.0;
        return;
    }
    double p = (double)n_pass / n, z2n = z * z / n;
    double c = (p + 0.5 * z2n) / (1.0 + z2n);
    double h = z / (1.0 + z2n) * sqrt(p * (1.0 - p) / n + z2n / (4.0 * n));
    *lo = fmax(0.0, c - h);
    *hi = fmin(1.0, c + h);
}

int shol_flown_verdict(double lo, double hi, double thr)
{
    if (lo >= thr - 1e-12)
        return SHOL_VERDICT_PASS;
    if (hi < thr - 1e-12)
        return SHOL_VERDICT_FAIL;
    return SHOL_VERDICT_UNDECIDED;
}

const char *shol_flown_verdict_name(int verdict)
{
    return verdict == SHOL_VERDICT_PASS ? "clear_pass" : verdict == SHOL_VERDICT_FAIL ? "clear_fail" : "undecided";
}

static const char *const crit_names[SHOL_NCRIT] = {"roll", "pitch", "long_cyclic", "lat_cyclic", "collective", "pedal"};

void shol_flown_judge_default(shol_flown_judge *j)
{
    j->window_s = 3.0;
    j->transient_frac = 0.5;
}

int shol_flown_judge_check(const shol_flown_judge *j, core_err *err)
{
    if (!(j->window_s >= 0.0 && j->window_s <= 60.0))
        return core_err_set(err, -1, "shol: flown window_s = %g: expected 0 to 60 s", j->window_s);
    if (!(j->transient_frac >= 0.0 && j->transient_frac <= 10.0))
        return core_err_set(err, -1, "shol: flown transient_frac = %g: expected 0 to 10", j->transient_frac);
    return 0;
}

void shol_flown_track_init(shol_flown_track *t, const shol_criteria *c, const shol_flown_judge *j)
{
    memset(t, 0, sizeof *t);
    t->criteria = *c;
    if (j)
        t->judge = *j;
    else
        shol_flown_judge_default(&t->judge);
    for (int i = 0; i < SHOL_NCRIT; i++) {
        t->min_frac[i] = INFINITY;
        t->min_t_s[i] = NAN;
        t->min_mean_frac[i] = INFINITY;
    }
    t->first_crit = SHOL_LIMIT_NONE;
    t->first_kind = SHOL_JUDGE_STEP;
    t->first_t_s = NAN;
    t->phase_t0_s = t->last_t_s = NAN;
    t->bin = -1; /* no phase yet */
}

/* A margin as a fraction of its criterion's allowed displacement
 * (shol_criteria_half_band). */
static double frac_of(const shol_criteria *c, int i, double margin)
{
    double b = shol_criteria_half_band(c, i);
    return b > 0 ? margin / b : (margin < 0 ? -INFINITY : 0.0);
}

/* The most exceeded of e's criteria (as a fraction of its allowed displacement), -1 if none. */
static int worst_exceeded(const shol_criteria *c, const shol_eval *e)
{
    int worst = -1;
    double worst_f = INFINITY;
    for (int i = 0; i < SHOL_NCRIT; i++) {
        double f = frac_of(c, i, e->margin[i]);
        if (e->margin[i] < 0 && f < worst_f) {
            worst_f = f;
            worst = i;
        }
    }
    return worst;
}

static int first_at(shol_flown_track *t, int crit, int kind, double t_s, const char *phase)
{
    if (t->first_crit == SHOL_LIMIT_NONE) {
        t->first_crit = crit;
        t->first_kind = kind;
        t->first_t_s = t_s;
        snprintf(t->first_phase, sizeof t->first_phase, "%s", phase ? phase : "");
    }
    return 1;
}

/* The steady criteria on the running mean of the current phase's window
 * (its samples so far where the phase is shorter). 1 when exceeded. */
static int judge_mean(shol_flown_track *t, double t_s)
{
    double sum[SHOL_NCRIT] = {0};
    long n = 0;
    for (int b = 0; b < SHOL_FLOWN_BINS; b++) {
        n += t->count[b];
        for (int i = 0; i < SHOL_NCRIT; i++)
            sum[i] += t->sum[b][i];
    }
    if (n == 0)
        return 0;
    shol_trim_point m = {sum[0] / n, sum[1] / n, sum[2] / n, sum[3] / n, sum[4] / n, sum[5] / n};
    shol_eval e;
    if (shol_criteria_eval(&t->criteria, &m, &e) != 0)
        return 0; /* the samples were finite: cannot happen */
    for (int i = 0; i < SHOL_NCRIT; i++) {
        double f = frac_of(&t->criteria, i, e.margin[i]);
        if (f < t->min_mean_frac[i])
            t->min_mean_frac[i] = f;
    }
    int w = worst_exceeded(&t->criteria, &e);
    return w < 0 ? 0 : first_at(t, w, SHOL_JUDGE_MEAN, t_s, t->phase);
}

int shol_flown_track_step(shol_flown_track *t, double t_s, const char *phase, const shol_trim_point *p)
{
    shol_eval e;
    t->n_steps++;
    if (shol_criteria_eval(&t->criteria, p, &e) != 0) {
        t->n_bad++;
        return -1;
    }
    const shol_criteria *c = &t->criteria;
    for (int i = 0; i < SHOL_NCRIT; i++) {
        double f = frac_of(c, i, e.margin[i]);
        if (f < t->min_frac[i]) {
            t->min_frac[i] = f;
            t->min_t_s[i] = t_s;
        }
    }
    const double W = t->judge.window_s;
    if (!(W > 0.0)) { /* the steady limits on the step's values */
        int w = worst_exceeded(c, &e);
        return w < 0 ? 0 : first_at(t, w, SHOL_JUDGE_STEP, t_s, phase);
    }
    /* transient: a control at its stop, then an attitude past its
     * transient limit (the most exceeded), on the step's values */
    const double ctl[4] = {p->long_cyclic_pct, p->lat_cyclic_pct, p->collective_pct, p->pedal_pct};
    for (int i = 0; i < 4; i++)
        if (ctl[i] <= 0.0 || ctl[i] >= 100.0)
            return first_at(t, SHOL_CRIT_LONG + i, SHOL_JUDGE_STOP, t_s, phase);
    const double k = 1.0 + t->judge.transient_frac;
    double over_r = fabs(p->phi_rad) / (k * c->roll_max_rad), over_p = fabs(p->theta_rad) / (k * c->pitch_max_rad);
    if (over_r > 1.0 || over_p > 1.0)
        return first_at(t, over_p > over_r ? SHOL_CRIT_PITCH : SHOL_CRIT_ROLL, SHOL_JUDGE_TRANSIENT, t_s, phase);
    /* steady: the running mean within the phase; a new phase starts a new
     * mean, and an earlier phase shorter than the window is judged as it
     * ends */
    char ph[sizeof t->phase];
    snprintf(ph, sizeof ph, "%s", phase ? phase : "");
    if (t->bin < 0 || strcmp(ph, t->phase) != 0) {
        if (t->bin >= 0 && !t->judged && judge_mean(t, t->last_t_s))
            return 1;
        memcpy(t->phase, ph, sizeof ph);
        t->phase_t0_s = t_s;
        t->bin = 0;
        t->judged = 0;
        memset(t->sum, 0, sizeof t->sum);
        memset(t->count, 0, sizeof t->count);
    }
    const double bw = W / SHOL_FLOWN_BINS;
    long b = (long)floor((t_s - t->phase_t0_s) / bw + 1e-9);
    if (b < t->bin)
        b = t->bin; /* time went back: the current bin */
    if (b - t->bin >= SHOL_FLOWN_BINS) {
        memset(t->sum, 0, sizeof t->sum);
        memset(t->count, 0, sizeof t->count);
    } else
        for (long j = t->bin + 1; j <= b; j++) {
            memset(t->sum[j % SHOL_FLOWN_BINS], 0, sizeof t->sum[0]);
            t->count[j % SHOL_FLOWN_BINS] = 0;
        }
    t->bin = b;
    const double v[SHOL_NCRIT] = {p->phi_rad, p->theta_rad, p->long_cyclic_pct, p->lat_cyclic_pct, p->collective_pct,
                                  p->pedal_pct};
    for (int i = 0; i < SHOL_NCRIT; i++)
        t->sum[b % SHOL_FLOWN_BINS][i] += v[i];
    t->count[b % SHOL_FLOWN_BINS]++;
    t->last_t_s = t_s;
    if (t_s - t->phase_t0_s >= W - 1e-9) {
        t->judged = 1;
        return judge_mean(t, t_s);
    }
    return 0;
}

int shol_flown_track_end(shol_flown_track *t)
{
    if (t->judge.window_s > 0.0 && t->bin >= 0 && !t->judged) {
        t->judged = 1;
        return judge_mean(t, t->last_t_s);
    }
    return 0;
}

void shol_flown_track_cause(const shol_flown_track *t, char *buf, size_t n)
{
    if (n == 0)
        return;
    buf[0] = '\0';
    const char *name = t->first_crit >= 0 ? shol_limit_name(t->first_crit) : NULL;
    if (!name)
        return;
    switch (t->first_kind) {
    case SHOL_JUDGE_MEAN:
        snprintf(buf, n, "%s (%.3g s mean) in %s", name, t->judge.window_s, t->first_phase);
        break;
    case SHOL_JUDGE_TRANSIENT:
        snprintf(buf, n, "%s (transient) in %s", name, t->first_phase);
        break;
    case SHOL_JUDGE_STOP:
        snprintf(buf, n, "%s at stop in %s", name, t->first_phase);
        break;
    default:
        snprintf(buf, n, "%s in %s", name, t->first_phase);
    }
}

void shol_flown_settings_default(shol_flown_settings *s)
{
    memset(s, 0, sizeof *s);
    s->n_seeds = 11; /* the fewest (>= 10) at which a point can clearly pass 0.8 (above) */
    s->seed0 = 1;
    s->pass_rate_min = 0.8;
    s->start_steps_below = 2;
    s->bisect_tol_mps = 0.0;
    shol_flown_judge_default(&s->judge);
}

int shol_flown_settings_check(const shol_flown_settings *s, core_err *err)
{
    if (s->n_seeds < 1 || s->n_seeds > SHOL_FLOWN_MAX_SEEDS)
        return core_err_set(err, -1, "shol: flown n_seeds = %d: expected 1 to %d", s->n_seeds, SHOL_FLOWN_MAX_SEEDS);
    if (!(s->pass_rate_min > 0.0 && s->pass_rate_min <= 1.0))
        return core_err_set(err, -1, "shol: flown pass_rate_min = %g: expected (0, 1]", s->pass_rate_min);
    if (s->start_steps_below < 0 || s->start_steps_below > 1000)
        return core_err_set(err, -1, "shol: flown start_steps_below = %d: expected 0 to 1000", s->start_steps_below);
    if (!(s->bisect_tol_mps >= 0.0) || !isfinite(s->bisect_tol_mps))
        return core_err_set(err, -1, "shol: flown bisect_tol_mps = %g: expected >= 0", s->bisect_tol_mps);
    return shol_flown_judge_check(&s->judge, err);
}

void shol_flown_result_free(shol_flown_result *r)
{
    if (!r)
        return;
    if (r->dirs)
        for (int i = 0; i < r->n_dirs; i++)
            free(r->dirs[i].points);
    free(r->dirs);
    r->dirs = NULL;
    r->n_dirs = 0;
}

typedef struct search {
    const shol_flown_settings *s;
    const shol_result *trim;
    shol_fly_fn fly;
    void *fly_user;
    shol_progress_fn progress;
    void *progress_user;
    const core_log *log;
    double t0;
    int n_flights;
    double flown_s;
    double speed_max;
} search;

static void report(search *w, int idir, double v, double dir_frac, int done)
{
    if (!w->progress)
        return;
    shol_progress p;
    memset(&p, 0, sizeof p);
    p.dir_index = idir;
    p.n_dirs = w->trim->n_dirs;
    p.dir_rad = w->trim->dirs[idir].dir_rad;
    p.speed_mps = v;
    p.n_trims = w->n_flights;
    p.fraction = done ? 1.0 : (idir + fmin(fmax(dir_frac, 0.0), 1.0)) / w->trim->n_dirs;
    p.elapsed_s = core_monotonic_s() - w->t0;
    p.rate_per_s = p.elapsed_s > 0 ? w->n_flights / p.elapsed_s : 0;
    p.eta_s = done ? 0 : (p.fraction > 0 ? p.elapsed_s * (1 - p.fraction) / p.fraction : NAN);
    p.done = done;
    w->progress(w->progress_user, &p);
}

/* Fly the point at v with every seed; append it to d (kept sorted by speed
 * at the end). 0, or < 0 with err. */
static int fly_point(search *w, shol_flown_dir *d, int *cap, double v, shol_flown_point **out, core_err *err)
{
    if (d->n_points == *cap) {
        int nc = *cap ? 2 * *cap : 16;
        shol_flown_point *np = realloc(d->points, (size_t)nc * sizeof *np);
        if (!np)
            return core_err_set(err, -1, "shol: out of memory");
        d->points = np;
        *cap = nc;
    }
    shol_flown_point *pt = &d->points[d->n_points];
    memset(pt, 0, sizeof *pt);
    pt->speed_mps = v;
    char causes[SHOL_FLOWN_MAX_SEEDS][SHOL_CAUSE_MAX];
    int n_fail = 0, n_track = 0;
    double track_ss = 0.0;
    pt->track_max_m = NAN;
    pt->n_tracked = -1;
    for (int k = 0; k < w->s->n_seeds; k++) {
        unsigned long long seed = w->s->seed0 + (unsigned long long)k;
        shol_flight f;
        memset(&f, 0, sizeof f);
        f.track_rms_m = f.track_max_m = NAN;
        f.tracked = -1;
        int rc = w->fly(w->fly_user, v, d->dir_rad, seed, &f);
        w->n_flights++;
        if (rc < 0) {
            char name[32];
            core_wod_name(d->dir_rad * CORE_RAD_TO_DEG, name, sizeof name);
            return core_err_set(err, -1, "shol: flying %s at %.1f km/h, seed %llu failed", name, v / CORE_KMH_TO_MPS,
                                seed);
        }
        if (rc > 0) {
            f.pass = 0;
            if (!f.cause[0])
                snprintf(f.cause, sizeof f.cause, "no trim");
        }
        pt->n_flights++;
        pt->flown_s += f.flown_s;
        w->flown_s += f.flown_s;
        if (isfinite(f.track_rms_m)) {
            track_ss += f.track_rms_m * f.track_rms_m;
            n_track++;
        }
        if (isfinite(f.track_max_m) && !(f.track_max_m <= pt->track_max_m))
            pt->track_max_m = f.track_max_m;
        if (f.tracked >= 0)
            pt->n_tracked = (pt->n_tracked < 0 ? 0 : pt->n_tracked) + (f.tracked > 0);
        if (f.pass)
            pt->n_pass++;
        else
            snprintf(causes[n_fail++], SHOL_CAUSE_MAX, "%s", f.cause[0] ? f.cause : "unnamed");
        char name[32];
        core_wod_name(d->dir_rad * CORE_RAD_TO_DEG, name, sizeof name);
        core_log_msg(w->log, CORE_LOG_DEBUG, "flown %s %.0f km/h seed %llu: %s%s%s, %.1f s", name,
                     v / CORE_KMH_TO_MPS, seed, f.pass ? "pass" : "fail", f.pass ? "" : ": ", f.pass ? "" : f.cause,
                     f.flown_s);
    }
    pt->pass_rate = (double)pt->n_pass / pt->n_flights;
    pt->pass = pt->pass_rate >= w->s->pass_rate_min - 1e-12;
    shol_wilson(pt->n_pass, pt->n_flights, SHOL_WILSON_Z90, &pt->rate_lo, &pt->rate_hi);
    pt->verdict = shol_flown_verdict(pt->rate_lo, pt->rate_hi, w->s->pass_rate_min);
    pt->track_rms_m = n_track ? sqrt(track_ss / n_track) : NAN;
    /* the most frequent cause (ties: the first seen) */
    for (int i = 0; i < n_fail; i++) {
        int n = 0;
        for (int j = 0; j < n_fail; j++)
            n += !strcmp(causes[i], causes[j]);
        if (n > pt->n_cause) {
            pt->n_cause = n;
            memcpy(pt->cause, causes[i], sizeof pt->cause);
        }
    }
    d->n_points++;
    *out = pt;
    char name[32];
    core_wod_name(d->dir_rad * CORE_RAD_TO_DEG, name, sizeof name);
    core_log_msg(w->log, CORE_LOG_INFO, "flown %s %.0f km/h: %d of %d passed (%s)%s%s", name, v / CORE_KMH_TO_MPS,
                 pt->n_pass, pt->n_flights, pt->pass ? "pass" : "fail", pt->cause[0] ? ", mostly " : "", pt->cause);
    return 0;
}

static int by_speed(const void *a, const void *b)
{
    double x = ((const shol_flown_point *)a)->speed_mps, y = ((const shol_flown_point *)b)->speed_mps;
    return (x > y) - (x < y);
}

/* The lowest speed flown that clearly fails (INFINITY: none). */
static double clear_fail_speed(const shol_flown_dir *d)
{
    double v = INFINITY;
    for (int i = 0; i < d->n_points; i++)
        if (d->points[i].verdict == SHOL_VERDICT_FAIL && d->points[i].speed_mps < v)
            v = d->points[i].speed_mps;
    return v;
}

/* The limit: the highest passing speed below the lowest clear failure
 * (NAN: none); the failure it is bisected against: the lowest failing
 * speed above it (NAN: none). */
static void bracket(const shol_flown_dir *d, double *v_pass, double *v_fail)
{
    double v_clear = clear_fail_speed(d);
    *v_pass = *v_fail = NAN;
    for (int i = 0; i < d->n_points; i++) {
        const shol_flown_point *q = &d->points[i];
        if (q->pass && q->speed_mps < v_clear && !(q->speed_mps <= *v_pass))
            *v_pass = q->speed_mps;
    }
    for (int i = 0; i < d->n_points; i++) {
        const shol_flown_point *q = &d->points[i];
        if (!q->pass && (isnan(*v_pass) || q->speed_mps > *v_pass) && !(q->speed_mps >= *v_fail))
            *v_fail = q->speed_mps;
    }
}

/* The band from the pass rate's interval (the model above), over the
 * points below the lowest clear failure; d->points sorted by speed. */
static void rate_band(shol_flown_dir *d)
{
    double v_clear = clear_fail_speed(d);
    d->rate_band_lo_mps = d->rate_band_hi_mps = NAN;
    for (int i = 0; i < d->n_points; i++) {
        const shol_flown_point *q = &d->points[i];
        if (q->speed_mps >= v_clear)
            break;
        if (q->verdict == SHOL_VERDICT_PASS)
            d->rate_band_lo_mps = q->speed_mps;
        d->rate_band_hi_mps = q->speed_mps;
    }
    d->rate_band_open_above = d->n_points > 0 && isinf(v_clear);
}

static int run_dir(search *w, int idir, shol_flown_dir *d, core_err *err)
{
    const shol_dir_result *td = &w->trim->dirs[idir];
    double step = w->trim->settings.speed_step_mps, vmax = w->speed_max;
    d->dir_rad = td->dir_rad;
    d->trim_has_pass = td->has_pass;
    d->trim_max_speed_mps = td->has_pass ? td->max_speed_mps : 0.0;
    d->trim_limit = td->limit;
    d->fail_speed_mps = d->pass_rate_max = d->pass_rate_fail = NAN;
    d->hub_speed_frac = d->hub_ti_frac = NAN;
    int cap = 0;
    long k_top = (long)floor(vmax / step + 1e-9);
    long k = (long)floor(d->trim_max_speed_mps / step + 1e-9) - w->s->start_steps_below;
    if (k < 0)
        k = 0;
    if (k > k_top)
        k = k_top;
    shol_flown_point *pt;
    double frac_den = (double)k_top + 1.0;
    report(w, idir, k * step, 0.0, 0);
    if (fly_point(w, d, &cap, k * step, &pt, err) != 0)
        return -1;
    /* speeds, not pointers: the points move when the array grows. Down
     * from a failure until a point clearly passes (or 0); up from the
     * start until a point clearly fails (or the top): the band's ends are
     * then both flown (the model above). */
    int start_clear_fail = pt->verdict == SHOL_VERDICT_FAIL;
    /* below 11 seeds (at the default threshold) no point can clearly
     * pass: down then only to a pass */
    double all_lo, all_hi;
    shol_wilson(w->s->n_seeds, w->s->n_seeds, SHOL_WILSON_Z90, &all_lo, &all_hi);
    int can_clear = all_lo >= w->s->pass_rate_min - 1e-12;
    if (pt->verdict != SHOL_VERDICT_PASS && (can_clear || !pt->pass)) {
        for (long j = k - 1; j >= 0 && pt->verdict != SHOL_VERDICT_PASS && (can_clear || !pt->pass); j--) {
            report(w, idir, j * step, (k - j) / (k + 1.0), 0);
            if (fly_point(w, d, &cap, j * step, &pt, err) != 0)
                return -1;
        }
    }
    if (!start_clear_fail) {
        for (long j = k + 1; j <= k_top; j++) {
            report(w, idir, j * step, (j - k) / (frac_den - k), 0);
            if (fly_point(w, d, &cap, j * step, &pt, err) != 0)
                return -1;
            if (pt->verdict == SHOL_VERDICT_FAIL)
                break;
        }
    }
    double v_pass, v_fail;
    bracket(d, &v_pass, &v_fail);
    if (w->s->bisect_tol_mps > 0 && !isnan(v_pass) && !isnan(v_fail)) {
        while (v_fail - v_pass > w->s->bisect_tol_mps) {
            double v = 0.5 * (v_pass + v_fail);
            report(w, idir, v, 0.99, 0);
            if (fly_point(w, d, &cap, v, &pt, err) != 0)
                return -1;
            if (pt->pass)
                v_pass = v;
            else
                v_fail = v;
        }
    }
    qsort(d->points, (size_t)d->n_points, sizeof *d->points, by_speed);
    d->has_pass = !isnan(v_pass);
    d->max_speed_mps = d->has_pass ? v_pass : 0.0;
    d->fail_speed_mps = v_fail;
    snprintf(d->cause, sizeof d->cause, "none");
    rate_band(d);
    for (int i = 0; i < d->n_points; i++) {
        const shol_flown_point *q = &d->points[i];
        if (d->has_pass && q->speed_mps == v_pass)
            d->pass_rate_max = q->pass_rate;
        if (!isnan(v_fail) && q->speed_mps == v_fail) {
            d->pass_rate_fail = q->pass_rate;
            snprintf(d->cause, sizeof d->cause, "%s", q->cause[0] ? q->cause : "unnamed");
        }
    }
    return 0;
}

int shol_flown_run(const shol_flown_settings *s, const shol_result *trim, shol_fly_fn fly, void *fly_user,
                   shol_progress_fn progress, void *progress_user, const core_log *log, shol_flown_result *out,
                   core_err *err)
{
    memset(out, 0, sizeof *out);
    if (!s || !trim || !fly)
        return core_err_set(err, -1, "shol: flown run: expected settings, a trim envelope and a fly callback");
    if (shol_flown_settings_check(s, err) != 0)
        return -1;
    if (trim->n_dirs < 1 || !trim->dirs)
        return core_err_set(err, -1, "shol: flown run: the trim envelope has no directions");
    if (!(trim->settings.speed_step_mps > 0) || !(trim->settings.speed_max_mps >= 0))
        return core_err_set(err, -1, "shol: flown run: the trim envelope's speed step %g m/s and maximum %g m/s: "
                                     "expected > 0 and >= 0",
                            trim->settings.speed_step_mps, trim->settings.speed_max_mps);
    search w = {s, trim, fly, fly_user, progress, progress_user, log, core_monotonic_s(), 0, 0.0,
                trim->settings.speed_max_mps};
    out->dirs = calloc((size_t)trim->n_dirs, sizeof *out->dirs);
    if (!out->dirs)
        return core_err_set(err, -1, "shol: out of memory");
    out->n_dirs = trim->n_dirs;
    out->flown = *s;
    out->speed_step_mps = trim->settings.speed_step_mps;
    out->speed_max_mps = trim->settings.speed_max_mps;
    for (int i = 0; i < trim->n_dirs; i++)
        if (run_dir(&w, i, &out->dirs[i], err) != 0) {
            shol_flown_result_free(out);
            return -1;
        }
    out->n_flights = w.n_flights;
    out->flown_s = w.flown_s;
    out->wall_s = core_monotonic_s() - w.t0;
    shol_flown_bands_update(out, trim); /* the trim's bands carried to the flown radii */
    report(&w, trim->n_dirs - 1, 0.0, 1.0, 1);
    return 0;
}

/* The criterion a cause names ("roll in descent" -> roll), or -1. */
static int cause_crit(const char *cause)
{
    for (int i = 0; i < SHOL_NCRIT; i++) {
        size_t n = strlen(crit_names[i]);
        if (!strncmp(cause, crit_names[i], n) && (cause[n] == ' ' || cause[n] == '\0'))
            return i;
    }
    return -1;
}

int shol_flown_as_result(const shol_flown_result *f, const shol_result *trim, shol_result *out, core_err *err)
{
    memset(out, 0, sizeof *out);
    if (!(out->dirs = calloc((size_t)(f->n_dirs > 0 ? f->n_dirs : 1), sizeof *out->dirs)))
        return core_err_set(err, -1, "shol: out of memory");
    out->settings = trim ? trim->settings : out->settings;
    out->n_dirs = f->n_dirs;
    out->settings.n_dirs = f->n_dirs < SHOL_MAX_DIRS ? f->n_dirs : SHOL_MAX_DIRS;
    for (int i = 0; i < f->n_dirs; i++) {
        const shol_flown_dir *d = &f->dirs[i];
        shol_dir_result *o = &out->dirs[i];
        if (i < SHOL_MAX_DIRS)
            out->settings.dirs_rad[i] = d->dir_rad;
        o->dir_rad = d->dir_rad;
        o->has_pass = d->has_pass;
        o->max_speed_mps = d->max_speed_mps;
        o->fail_speed_mps = d->fail_speed_mps;
        int c = cause_crit(d->cause);
        o->limit = isnan(d->fail_speed_mps) ? SHOL_LIMIT_NONE : c >= 0 ? c : SHOL_LIMIT_TRIM;
        o->margins.limit = o->limit;
    }
    out->n_trims = f->n_flights;
    out->wall_s = f->wall_s;
    return 0;
}
