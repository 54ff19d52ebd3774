/*
 * converge.c -- when a steady RANS run (solver.c) is done, and the mean of
 * its last iterates when it is not: the convergence and averaging-window
 * bookkeeping of one cfd_solver_run, as OpenFOAM's simpleControl owns the
 * convergence of a SIMPLE loop. The solver iterates; this object scales
 * the residuals, watches the monitors, keeps the averaging windows and the
 * running mean, and says when the run stops.
 *
 * Criteria:
 *  - converged, as in the seed paper (section 2.2: "the residual of the
 *    average value of fluxes is less than 10x10^-5 and the variation of
 *    velocity at all monitor points is less than 2%", four monitor points
 *    on a line over the deck at the height of the fuselage centre of
 *    gravity): after iteration 5, every scaled residual below tol_residual
 *    and, with monitors, the monitor velocities changed by less than
 *    tol_monitor times u_ref (every component, every monitor) between the
 *    last two checks, monitor_every iterations apart;
 *  - with monitor_stop, the OpenFOAM engine's test instead (foam.c): from
 *    iteration 4 monitor_every on, every monitor velocity moved by less
 *    than tol_monitor times u_ref (the length of the change) over each of
 *    the last two spans of monitor_every iterations, tested every
 *    iteration; the residuals are not tested;
 *  - residuals as ANSYS Fluent scales them (Fluent User's Guide,
 *    "definition of residuals"): continuity = sum |mass imbalance| divided
 *    by its largest value over the first five iterations; u, v, w, k = sum
 *    |r| / sum |a_P phi_P| (the solver gives them scaled so);
 *  - the averaged mean (avg_window > 0): a run that reaches max_iter
 *    unconverged returns the mean of its last avg_window iterates. An
 *    iteration in a limit cycle (shedding in pseudo-time) has no last
 *    iterate worth more than another, and the mean over the cycle
 *    approximates the mean flow a trim needs;
 *  - a steady mean (avg_stop, avg_window >= 2, monitors): the windows are
 *    laid back to back so that the last ends at max_iter; one opens before
 *    the last only when the residuals, at their rate over the last
 *    TREND_LAG iterations, will not reach tol_residual by max_iter (a run
 *    that will converge is left to converge). The run stops at the end of
 *    the first window whose two halves have the same monitor means within
 *    tol_monitor times u_ref, and whose mean is that of the window just
 *    before it within tol_monitor times u_ref too: the seed paper's
 *    monitor criterion applied to the mean flow rather than to the
 *    iterate. Two windows, because the halves alone passed a slow drift
 *    (docs/validation.md): a drift moves two back-to-back windows' means
 *    twice as far as two halves' means. A window that fails closes and the
 *    next one opens when the trend test allows;
 *  - the figures of the last window either way: mean_drift (its halves'
 *    monitor means apart, / u_ref) and mean_change (its mean from the
 *    window before, / u_ref; -1 when none came just before); 0 and -1 for
 *    a field that is not averaged.
 * Each attempt (a retry after divergence) starts its monitors, continuity
 * scale and windows afresh.
 */
#include "converge.h"
#include "cfd_private.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef _OPENMP
#include <omp.h>
#endif

enum { TREND_W = 20, TREND_LAG = 100 };

void cfd_converge_init(cfd_converge *c, const cfd_solver *s)
{
    c->s = s;
    c->cfg = cfd_solver_config(s);
    c->ncell = cfd_grid_cells(cfd_solver_grid(s));
    memset(c->residual, 0, sizeof c->residual);
    c->monitor_change = 0.0;
    c->converged = c->steady_mean = c->averaged = 0;
    c->mean_drift = c->mean_change = 0.0;
}

void cfd_converge_attempt(cfd_converge *c)
{
    const cfd_config *cfg = c->cfg;
    /* each attempt's windows are its own; -1 until a window follows another */
    c->mean_drift = 0.0;
    c->mean_change = -1.0;
    memset(c->rmax, 0, sizeof c->rmax);
    c->worst = 0.0;
    c->have_mon = 0;
    c->mon_ok = cfg->n_monitor == 0 && !cfg->monitor_stop;
    c->navg = cfg->avg_window > 0 ? 0 : -1;
    c->early = cfg->avg_stop && cfg->avg_window >= 2 && cfg->n_monitor > 0;
    c->wstart = 0;
    c->wprev_end = 0;
}

double cfd_converge_residuals(cfd_converge *c, int it, const double r[CFD_CONVERGE_NRES],
                              double rn[CFD_CONVERGE_NRES])
{
    double worst = 0.0;
    /* continuity: divided by its largest value over the first five
     * iterations; u, v, w, k: already scaled by sum |a_P phi_P| */
    for (int q = 0; q < CFD_CONVERGE_NRES; q++) {
        if (q == 0) {
            if (it <= 5 && r[q] > c->rmax[q])
                c->rmax[q] = r[q];
            rn[q] = c->rmax[q] > 0.0 ? r[q] / c->rmax[q] : 0.0;
        } else {
            rn[q] = r[q];
        }
        if (rn[q] > worst)
            worst = rn[q];
    }
    memcpy(c->rn, rn, sizeof c->rn);
    c->worst = worst;
    return worst;
}

/* log of the largest scaled residual as a geometric mean over the last
 * TREND_W iterations (*now) and its change since TREND_LAG iterations
 * before (*change); 0 without enough history */
static int residual_trend(const cfd_converge *c, double *now, double *change)
{
    int n;
    const double *hist = cfd_solver_history(c->s, &n);
    const int w = TREND_W, lag = TREND_LAG;
    if (n < lag + w)
        return 0;
    double sn = 0.0, sb = 0.0;
    for (int i = 0; i < w; i++) {
        const double *a = hist + (size_t)(n - 1 - i) * CFD_CONVERGE_NRES;
        const double *b = hist + (size_t)(n - 1 - i - lag) * CFD_CONVERGE_NRES;
        double wa = 1e-300, wb = 1e-300;
        for (int q = 0; q < CFD_CONVERGE_NRES; q++) {
            wa = fmax(wa, a[q]);
            wb = fmax(wb, b[q]);
        }
        sn += log(wa);
        sb += log(wb);
    }
    *now = sn / w;
    *change = (sn - sb) / w;
    return 1;
}

/* The residuals have stalled: the largest scaled residual, as a geometric
 * mean over the last 20 iterations, is above 0.7 times its mean 100
 * iterations before (a converging SIMPLEC iteration on a ship grid falls
 * by a factor 2 or more per 100 iterations; a limit cycle stays flat). */
int cfd_converge_stalled(const cfd_converge *c)
{
    double now, change;
    return residual_trend(c, &now, &change) && change > log(0.7);
}

/* At its present rate the run will not reach tol_residual by max_iter: it
 * will end at the cap anyway (a stall is the extreme case). */
static int will_miss(const cfd_converge *c, int it)
{
    double now, change;
    if (!residual_trend(c, &now, &change))
        return 0;
    double left = c->cfg->max_iter - it;
    return now + (change < 0.0 ? change : 0.0) * left / TREND_LAG > log(c->cfg->tol_residual);
}

/* The seed paper's monitor test: every monitor_every iterations, the
 * largest change of a monitor velocity component since the last check. */
static void monitor_check(cfd_converge *c, int it)
{
    const cfd_config *cfg = c->cfg;
    if (!cfg->n_monitor || it % cfg->monitor_every != 0)
        return;
    double dmax = 0.0;
    for (int m = 0; m < cfg->n_monitor; m++) {
        double out[CFD_NVARS];
        cfd_solver_sample(c->s, cfg->monitor_m[m], out);
        for (int d = 0; d < 3; d++) {
            if (c->have_mon)
                dmax = fmax(dmax, fabs(out[d] - c->mon_prev[m][d]));
            c->mon_prev[m][d] = out[d];
        }
    }
    c->mon_ok = c->have_mon && dmax < cfg->tol_monitor * cfg->u_ref_mps;
    if (c->have_mon)
        c->monitor_change = dmax / cfg->u_ref_mps;
    c->have_mon = 1;
}

/* monitor_stop's test at iteration it: the monitor velocities kept for the
 * last 2 W + 1 iterations (W = monitor_every); from iteration 4 W on,
 * mon_ok when every monitor moved by less than tol_monitor u_ref over each
 * of the spans (it - 2 W, it - W) and (it - W, it), monitor_change the
 * larger of the two largest moves, / u_ref. < 0 out of memory. */
static int monitor_spans(cfd_converge *c, int it)
{
    const cfd_config *cfg = c->cfg;
    const int W = cfg->monitor_every, rows = 2 * W + 1, nm = cfg->n_monitor;
    if (!nm || W < 1)
        return 0;
    if (!c->mring) {
        if (!(c->mring = malloc((size_t)rows * nm * 3 * sizeof(double))))
            return -1;
        c->mring_bytes = (size_t)rows * nm * 3 * sizeof(double);
    }
    double *row = c->mring + (size_t)(it % rows) * nm * 3;
    for (int m = 0; m < nm; m++) {
        double out[CFD_NVARS];
        cfd_solver_sample(c->s, cfg->monitor_m[m], out);
        memcpy(row + 3 * m, out, 3 * sizeof(double));
    }
    c->mon_ok = 0;
    if (it < 4 * W)
        return 0;
    const double *r[3] = {row, c->mring + (size_t)((it - W) % rows) * nm * 3,
                          c->mring + (size_t)((it - 2 * W) % rows) * nm * 3};
    double ch[2] = {0.0, 0.0};
    for (int w = 0; w < 2; w++)
        for (int m = 0; m < nm; m++) {
            double d2 = 0.0;
            for (int d = 0; d < 3; d++)
                d2 += (r[w][3 * m + d] - r[w + 1][3 * m + d]) * (r[w][3 * m + d] - r[w + 1][3 * m + d]);
            ch[w] = fmax(ch[w], sqrt(d2) / cfg->u_ref_mps);
        }
    c->monitor_change = fmax(ch[0], ch[1]);
    c->mon_ok = ch[0] < cfg->tol_monitor && ch[1] < cfg->tol_monitor;
    return 0;
}

/* The running mean: zeroed sums (allocated once); < 0 out of memory. */
static int averaging_start(cfd_converge *c)
{
    for (int v = 0; v < CFD_NVARS; v++) {
        if (!c->avg[v]) {
            if (!(c->avg[v] = calloc(c->ncell ? c->ncell : 1, sizeof(double))))
                return -1;
            c->bytes += c->ncell * sizeof(double);
        }
        memset(c->avg[v], 0, c->ncell * sizeof(double));
    }
    return 0;
}

static void averaging_add(cfd_converge *c)
{
    for (int v = 0; v < CFD_NVARS; v++) {
        double *a = c->avg[v];
        const double *x = cfd_solver_var(c->s, v);
        #pragma omp parallel for schedule(static)
        for (size_t i = 0; i < c->ncell; i++)
            a[i] += x[i];
    }
}

/* Open a window at it if one is due: the last window ends at max_iter;
 * with avg_stop, earlier windows are laid back to back before it, and one
 * opens only when the residuals, at their rate over the last TREND_LAG
 * iterations, will not reach tol_residual by max_iter (a run that will
 * converge is left to converge; one that will end at the cap anyway,
 * stalled in a limit cycle or creeping, may end at a steady mean). */
static void window_open(cfd_converge *c, int it)
{
    const cfd_config *cfg = c->cfg;
    const int W = cfg->avg_window;
    int last = it > cfg->max_iter - W;
    int open = last || (c->early && (cfg->max_iter - it + 1) % W == 0 && will_miss(c, it));
    if (!open)
        return;
    if (averaging_start(c) != 0) {
        c->navg = -1; /* out of memory: keep the last iterate */
    } else {
        c->wstart = it;
        c->navg = 0;
        memset(c->hsum, 0, sizeof c->hsum);
    }
}

/* The window closes at it: its figures, and with avg_stop whether its mean
 * is steady. Returns 1 when the run stops here. */
static int window_close(cfd_converge *c, int it)
{
    const cfd_config *cfg = c->cfg;
    const int W = cfg->avg_window;
    double dmax = 0.0, dprev = 0.0;
    const int follows = c->wprev_end > 0 && c->wprev_end == c->wstart - 1;
    for (int m = 0; m < cfg->n_monitor; m++)
        for (int d = 0; d < 3; d++) {
            double mean = (c->hsum[0][m][d] + c->hsum[1][m][d]) / W;
            dmax = fmax(dmax, fabs(c->hsum[0][m][d] / (W / 2) - c->hsum[1][m][d] / (W - W / 2)));
            if (follows)
                dprev = fmax(dprev, fabs(mean - c->wprev[m][d]));
            c->wprev[m][d] = mean;
        }
    c->wprev_end = it;
    c->mean_drift = dmax / cfg->u_ref_mps;
    c->mean_change = follows ? dprev / cfg->u_ref_mps : -1.0;
    char prev[48] = "none came just before";
    if (follows)
        snprintf(prev, sizeof prev, "%.2f %%", 100.0 * c->mean_change);
    core_log_msg(cfg->log, CORE_LOG_DEBUG,
                 "cfd: averaging window %d-%d: monitor means of its halves differ by %.2f %% "
                 "of u_ref, from the window before by %s",
                 c->wstart, it, 100.0 * c->mean_drift, prev);
    /* A steady mean: the two halves agree at the monitors as closely as
     * two checks of a converged run must (tol_monitor), and so does the
     * mean of the window before. The halves alone passed a slow drift
     * (CG-47 red 30, fine grid with the hangar in the focus box: halves
     * within 1 % of U after 700 iterations, the field 0.08 U away from
     * where it went on to stay; docs/validation.md). A limit cycle longer
     * than half a window, or a drift, fails this and the next window
     * starts. */
    if (c->early && it < cfg->max_iter) {
        if (dmax < cfg->tol_monitor * cfg->u_ref_mps && follows && dprev < cfg->tol_monitor * cfg->u_ref_mps) {
            c->steady_mean = 1;
            c->monitor_change = c->mean_drift;
            return 1;
        }
        c->wstart = 0;
    }
    return 0;
}

int cfd_converge_update(cfd_converge *c, int it)
{
    const cfd_config *cfg = c->cfg;
    if (!cfg->monitor_stop)
        monitor_check(c, it);
    else if (monitor_spans(c, it) < 0)
        return -1;
    memcpy(c->residual, c->rn, sizeof c->residual);
    if (c->navg >= 0 && !c->wstart)
        window_open(c, it);
    if (c->navg < 0 || !c->wstart)
        return 0;
    averaging_add(c);
    c->navg++;
    /* the monitors' means over the two halves of the window: how steady
     * the mean is (mean_drift), and with avg_stop whether the run may stop
     * here */
    const int W = cfg->avg_window;
    const int drift = W >= 2 && cfg->n_monitor > 0;
    if (!drift)
        return 0;
    int half = it - c->wstart < W / 2 ? 0 : 1;
    for (int m = 0; m < cfg->n_monitor; m++) {
        double out[CFD_NVARS];
        cfd_solver_sample(c->s, cfg->monitor_m[m], out);
        for (int d = 0; d < 3; d++)
            c->hsum[half][m][d] += out[d];
    }
    return c->navg == W ? window_close(c, it) : 0;
}

int cfd_converge_done(cfd_converge *c, int it)
{
    if (c->cfg->monitor_stop ? c->mon_ok : it > 5 && c->worst < c->cfg->tol_residual && c->mon_ok)
        c->converged = 1;
    return c->converged;
}

int cfd_converge_finish(cfd_converge *c, int it, int diverged, int stopped, double *const var[CFD_NVARS])
{
    const int navg = c->navg;
    if (c->converged || stopped || navg <= 0) {
        c->mean_drift = 0.0; /* not an averaged field */
        c->mean_change = -1.0;
    }
    if (diverged || c->converged || stopped || navg <= 0)
        return 0;
    for (int v = 0; v < CFD_NVARS; v++) {
        double *x = var[v];
        const double *a = c->avg[v];
        #pragma omp parallel for schedule(static)
        for (size_t i = 0; i < c->ncell; i++)
            x[i] = a[i] / navg;
    }
    c->averaged = navg;
    if (c->steady_mean)
        core_log_msg(c->cfg->log, CORE_LOG_INFO,
                     "cfd: not converged, mean flow steady after %d iterations (the monitor "
                     "means of the two halves of the last %d iterations differ by %.2f %% of "
                     "u_ref, their mean from the %d before by %.2f %%); the field is their mean",
                     it, navg, 100.0 * c->monitor_change, navg, 100.0 * c->mean_change);
    else
        core_log_msg(c->cfg->log, CORE_LOG_INFO, "cfd: not converged; the field is the mean of the last %d iterations",
                     navg);
    return 1;
}

void cfd_converge_result(const cfd_converge *c, cfd_result *res)
{
    memcpy(res->residual, c->residual, sizeof res->residual);
    res->monitor_change = c->monitor_change;
    res->converged = c->converged;
    res->steady_mean = c->steady_mean;
    res->averaged = c->averaged;
    res->mean_drift = c->mean_drift;
    res->mean_change = c->mean_change;
}

size_t cfd_converge_bytes(const cfd_converge *c) { return c->bytes + c->mring_bytes; }

void cfd_converge_release(cfd_converge *c)
{
    for (int v = 0; v < CFD_NVARS; v++) {
        free(c->avg[v]);
        c->avg[v] = NULL;
    }
    c->bytes = 0;
    free(c->mring);
    c->mring = NULL;
    c->mring_bytes = 0;
}
