/* shol_sweep.c -- the candidate SHOL's sweeps over coupling contexts (the
 * envelope disim shol writes): the one-way envelope, the two-way envelope
 * near the one-way boundary with one log line per coupled point, each
 * converged sample's component loads from the coupling histories, and the
 * report's texts on the coupling and its fields. */
#include "couple.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* The two-way trim of the sweep (shol_envelope_run_near calls it near the
 * one-way boundary), with one log line per coupled point so that a long run
 * leaves a trace before the outputs are written at the end. */
typedef struct two_ctx {
    couple_ctx *two;
    char err[1024];
    const core_log *log;
} two_ctx;

static int two_trim(void *user, double v, double dir, shol_trim_point *out)
{
    two_ctx *s = user;
    int rc = couple_shol_trim(s->two, v, dir, out);
    if (rc < 0) {
        snprintf(s->err, sizeof s->err, "%s", couple_last_error(s->two));
        return rc;
    }
    int n = 0;
    const couple_point *h = couple_history(s->two, &n);
    if (n > 0) {
        const couple_point *p = &h[n - 1];
        const couple_iter *it = &p->iter[p->n_iter - 1];
        char wn[32];
        core_wod_name(dir * CORE_RAD_TO_DEG, wn, sizeof wn);
        core_log_msg(s->log, CORE_LOG_INFO,
                     "coupled %s %.0f km/h: %s, %d iteration(s)%s, change %.1f %%; coll %.1f long %.1f lat %.1f "
                     "pedal %.1f %%, roll %.2f pitch %.2f deg",
                     wn, v / CORE_KMH_TO_MPS, rc == 0 ? "trimmed" : "no trim", p->n_iter - 1,
                     p->seed == COUPLE_SEED_PREVIOUS  ? " (seeded)"
                     : p->seed == COUPLE_SEED_ONE_WAY ? " (from one-way)"
                                                      : "",
                     100.0 * it->change_frac, it->ctl.collective_pct, it->ctl.long_cyclic_pct, it->ctl.lat_cyclic_pct,
                     it->ctl.pedal_pct, it->phi_rad * CORE_RAD_TO_DEG, it->theta_rad * CORE_RAD_TO_DEG);
    }
    return rc;
}

/* Each converged sample's component loads (shol_sample.loads, for the
 * report's "driven by": shol_envelope_attribution), from the coupling
 * history of the trim that made it: the last converged point at the same
 * WOD in first's history, else in second's (NULL: none). In a two-way
 * sweep first is the coupled context: a speed it trimmed at a direction
 * is coupled in the final sweep too (its coupled region only grows
 * downward), the rest are one-way. The weight is what the total holds
 * beyond the five components (hfm/body.c, hfm_eval_rest). */
static void fill_loads(shol_result *r, const couple_ctx *first, const couple_ctx *second)
{
    const couple_ctx *cx[2] = {first, second};
    for (int i = 0; i < r->n_dirs; i++) {
        shol_dir_result *d = &r->dirs[i];
        for (int j = 0; j < d->n_samples; j++) {
            shol_sample *sm = &d->samples[j];
            const couple_point *p = NULL;
            for (int k = 0; k < 2 && !p && sm->trim_status == 0; k++) {
                int n = 0;
                const couple_point *h = cx[k] ? couple_history(cx[k], &n) : NULL;
                for (int m = n - 1; m >= 0 && !p; m--)
                    if (h[m].converged && fabs(h[m].wod_speed_mps - sm->speed_mps) < 1e-9 &&
                        fabs(remainder(h[m].wod_dir_rad - d->dir_rad, 2 * CORE_PI)) < 1e-9)
                        p = &h[m];
            }
            memset(&sm->loads, 0, sizeof sm->loads);
            if (!p)
                continue;
            const hfm_loads *L = &p->trim.loads;
            const double *F[5] = {L->mr.F_B_N, L->tr.F_B_N, L->fus.F_B_N, L->stab.F_B_N, L->fin.F_B_N};
            const double *M[5] = {L->mr.M_B_Nm, L->tr.M_B_Nm, L->fus.M_B_Nm, L->stab.M_B_Nm, L->fin.M_B_Nm};
            shol_loads_set(&sm->loads, F, M, L->total.F_B_N, L->total.M_B_Nm, L->mr_power_W, L->tr_power_W);
        }
    }
}

int couple_shol_one_way(couple_ctx *one, const shol_settings *set, shol_progress_fn progress, void *progress_user,
                        const core_log *log, shol_result *r, core_err *err)
{
    if (shol_envelope_run(set, couple_shol_trim, one, progress, progress_user, log, r, err) != 0) {
        if (couple_last_error(one)[0])
            snprintf(err->msg, sizeof err->msg, "%s", couple_last_error(one));
        return -1;
    }
    fill_loads(r, one, NULL);
    return 0;
}

int couple_shol_two_way(couple_ctx *one, couple_ctx *two, const shol_settings *set, const shol_result *r1,
                        shol_progress_fn progress, void *progress_user, const core_log *log, shol_result *r2,
                        core_err *err)
{
    /* coupled from two steps of the resolution below the one-way limit
     * (the bisection's tolerance where it is finer than the step) */
    double res = set->bisect_tol_mps > 0.0 ? fmin(set->speed_step_mps, set->bisect_tol_mps) : set->speed_step_mps;
    two_ctx tc = {two, "", log};
    if (shol_envelope_run_near(set, r1, couple_shol_trim, one, two_trim, &tc, 2.0 * res, progress, progress_user, log,
                               r2, err) != 0) {
        if (tc.err[0])
            snprintf(err->msg, sizeof err->msg, "%s", tc.err);
        return -1;
    }
    fill_loads(r2, two, one);
    return 0;
}

const char *couple_shol_coupling_text(const couple_settings *cs)
{
    if (cs->mode != CORE_COUPLING_TWO_WAY)
        return "one-way";
    if (cs->zone)
        return cs->direct ? "two-way, coupled field used directly; coupled fields in the deck zone (5 R round the "
                            "hub, bounded by the ship-only field)"
                          : "two-way, interaction velocity (coupled - isolated rotor); both fields in the deck zone "
                            "(5 R round the hub, the coupled one bounded by the ship-only field)";
    return cs->direct ? "two-way, coupled field used directly" : "two-way, interaction velocity (coupled - isolated rotor)";
}

char *couple_shol_fields_md(const couple_ctx *one, const couple_ctx *two)
{
    int n1 = 0, n2 = 0;
    const couple_field_info *f1 = couple_fields(one, &n1), *f2 = two ? couple_fields(two, &n2) : NULL;
    return couple_fields_md(f1, n1, f2, n2);
}
