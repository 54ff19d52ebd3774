/* converge.h -- the convergence and averaging-window bookkeeping of one
 * cfd_solver_run (converge.c; the criteria are stated there). Private to
 * the cfd library. */
#ifndef DISIM_CFD_CONVERGE_H
#define DISIM_CFD_CONVERGE_H

#include "cfd.h"

#include <stddef.h>

/* Residual columns: continuity, u, v, w, k (cfd_result.residual). */
#define CFD_CONVERGE_NRES 5

/* Plain data embedded in the solver (zeroed with it); the running-mean
 * arrays are allocated when the first averaging window opens and kept for
 * later runs; cfd_converge_release frees them. */
typedef struct cfd_converge {
    const cfd_solver *s; /* sampled at the monitors, its residual history read */
    const cfd_config *cfg;
    size_t ncell;
    double *avg[CFD_NVARS]; /* running sums of the open averaging window */
    size_t bytes;           /* bytes of avg */

    /* The figures of the run (cfd_converge_result copies them out). */
    double residual[CFD_CONVERGE_NRES];
    double monitor_change;
    int converged, steady_mean, averaged;
    double mean_drift, mean_change;

    /* The attempt under way (cfd_converge_attempt resets it). */
    double rmax[CFD_CONVERGE_NRES]; /* continuity scale: its largest value over iterations 1-5 */
    double rn[CFD_CONVERGE_NRES];   /* the last iterate's scaled residuals */
    double worst;                   /* ... and the largest of them */
    double mon_prev[CFD_MAX_MONITOR][3];
    int have_mon, mon_ok;
    int navg;   /* iterates summed in the window; -1: no averaging */
    int early;  /* avg_stop in effect (avg_window >= 2, monitors) */
    int wstart; /* first iteration of the open window; 0: none open */
    double hsum[2][CFD_MAX_MONITOR][3]; /* monitor sums over the window's halves */
    double wprev[CFD_MAX_MONITOR][3];   /* monitor means of the last window closed ... */
    int wprev_end;                      /* ... and its last iteration (0: none) */
    /* monitor_stop: the monitor velocities of the last 2 monitor_every + 1
     * iterations, iteration it in row it % (2 monitor_every + 1) (allocated
     * by the first update that needs it) */
    double *mring;
    size_t mring_bytes;
} cfd_converge;

/* The start of a run of s (its configuration as the run reads it): the
 * figures zero. */
void cfd_converge_init(cfd_converge *c, const cfd_solver *s);
/* The start of an attempt (the first, or a retry after divergence): the
 * monitors, the continuity scale and the averaging windows start afresh;
 * mean_drift 0 and mean_change -1 until a window closes. */
void cfd_converge_attempt(cfd_converge *c);
/* Iteration it's raw residuals r: scales them into rn (as cfd_result
 * reports them) and returns the largest. */
double cfd_converge_residuals(cfd_converge *c, int it, const double r[CFD_CONVERGE_NRES],
                              double rn[CFD_CONVERGE_NRES]);
/* After the iterate it has been accepted (not diverged; its scaled
 * residuals in the solver's history): the monitor check, the averaging
 * windows and the running mean. Returns 1 when the run stops here with a
 * steady mean, 0 to go on, < 0 out of memory (monitor_stop's history). */
int cfd_converge_update(cfd_converge *c, int it);
/* 1 (and converged) when the residuals and the monitors have met the
 * tolerances at iteration it (with monitor_stop: the monitors' two spans
 * alone); after the progress callback. */
int cfd_converge_done(cfd_converge *c, int it);
/* The end of an attempt at iteration it (max_iter + 1 when the loop ran
 * out). An attempt that neither diverged, converged nor was stopped and has
 * summed a window gets the window's mean written into var (averaged) and
 * returns 1: the caller rebuilds what derives from var. 0 otherwise. */
int cfd_converge_finish(cfd_converge *c, int it, int diverged, int stopped, double *const var[CFD_NVARS]);
/* The residuals have stalled (Anderson acceleration's accel_when_stalled). */
int cfd_converge_stalled(const cfd_converge *c);
/* Copy the figures into res (residual, monitor_change, converged,
 * steady_mean, averaged, mean_drift, mean_change). */
void cfd_converge_result(const cfd_converge *c, cfd_result *res);
size_t cfd_converge_bytes(const cfd_converge *c);
void cfd_converge_release(cfd_converge *c);

#endif
