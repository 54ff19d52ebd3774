/* report.c -- the airwake fields a coupling context loaded, with their
 * solver state, and their table for the SHOL report (Markdown). */
#include "couple_priv.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Record a loaded field's solver state once (for couple_fields); out of
 * memory only loses the record. */
void couple_field_note(void *user, const char *path, const cfd_field *f)
{
    couple_ctx *c = user;
    const char *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    size_t len = strlen(base);
    if (len > 3 && !strcmp(base + len - 3, ".h5"))
        len -= 3;
    for (int i = 0; i < c->nfields; i++)
        if (strlen(c->fields[i].name) == len && !strncmp(c->fields[i].name, base, len))
            return;
    if (c->nfields == c->capfields) {
        int cap = c->capfields ? 2 * c->capfields : 16;
        couple_field_info *p = realloc(c->fields, (size_t)cap * sizeof *p);
        if (!p)
            return;
        c->fields = p;
        c->capfields = cap;
    }
    const cfd_meta *m = cfd_field_meta(f);
    couple_field_info *fi = &c->fields[c->nfields++];
    memset(fi, 0, sizeof *fi);
    snprintf(fi->name, sizeof fi->name, "%.*s", (int)(len < sizeof fi->name ? len : sizeof fi->name - 1), base);
    fi->wod_speed_mps = m->wod_speed_mps;
    fi->wod_dir_deg = m->wod_dir_deg;
    snprintf(fi->rotor, sizeof fi->rotor, "%s", m->rotor);
    fi->iterations = m->result.iterations;
    fi->converged = m->result.converged;
    fi->averaged = m->result.averaged;
    fi->steady_mean = m->result.steady_mean;
    fi->mean_drift = m->result.mean_drift;
    fi->mean_change = m->result.mean_change;
    fi->residual_continuity = m->result.residual[0];
    fi->mirrored = m->mirrored;
    fi->monitor_change = m->result.monitor_change;
    if (strcmp(m->engine, "embedded") != 0)
        snprintf(fi->engine_version, sizeof fi->engine_version, "%s", m->engine_version);
    snprintf(fi->rotor_model, sizeof fi->rotor_model, "%s", m->rotor_model);
}

const couple_field_info *couple_fields(const couple_ctx *c, int *n)
{
    *n = c->nfields;
    return c->fields;
}

/* The report's field table. Why each flag: an unconverged field is the
 * mean of its last iterations (cfd.h avg_window); its mean_drift and
 * mean_change say how far that mean still moves (within its window, and
 * from the window before); a continuity residual above 1 means the mass
 * imbalance grew past the run's first iterations, which the solver's
 * divergence test (1e4) lets pass. */
char *couple_fields_md(const couple_field_info *f1, int n1, const couple_field_info *f2, int n2)
{
    core_str md = {0};
    int nconv = 0, navg = 0, ngrew = 0, nmir = 0, nother = 0;
    const char *other = NULL;
    for (int i = 0; i < n1 + n2; i++) {
        const couple_field_info *fi = i < n1 ? &f1[i] : &f2[i - n1];
        nmir += fi->mirrored;
        if (fi->engine_version[0]) {
            nother++;
            other = fi->engine_version;
        }
        nconv += fi->converged;
        navg += fi->averaged > 0;
        ngrew += !fi->converged && fi->residual_continuity > 1.0;
    }
    core_str_printf(&md,
                    "%d fields, %d converged (residuals below 1e-4 and deck-line monitors changing less than "
                    "2 %% of the WOD speed per 50 iterations), %d not converged and averaged over their last "
                    "iterations (an unconverged field is the mean of its limit cycle; docs/validation/cfd.md; "
                    "\"steady mean\": the run stopped before its iteration cap once the means over the two "
                    "halves of its last window, and that window's mean and the mean of the window before "
                    "it, agreed at the deck monitors within 2 %% of the WOD speed; before solver 0.5.0 the "
                    "halves alone). Trims in unconverged fields are less certain than the others; \"mean "
                    "drift\" and \"mean change\" say how much: the largest difference between the deck "
                    "monitors' mean velocities over the two halves of the averaging window, and between "
                    "the window and the one before it (\"-\": none before it), in %% of the WOD speed (a "
                    "steady mean is below 2 %% in both).\n\n",
                    n1 + n2, nconv, navg);
    if (nother)
        core_str_printf(&md,
                        "%d field%s solved by %s (docs/openfoam.md): its residuals stall above 1e-4 on these "
                        "grids, so such a field stops once its deck monitors change less than 2 %% of the WOD "
                        "speed over each of two 50-iteration windows (\"monitors steady\" below); its "
                        "continuity column is OpenFOAM's initial residual of p.\n\n",
                        nother, nother > 1 ? "s were" : " was", other);
    if (nmir)
        core_str_printf(&md,
                        "%d field%s the mirror image of the opposite direction's (the ship is symmetric about "
                        "its centre line; \"mirror of\" in the state; iterations and residuals are the "
                        "solved field's).\n\n",
                        nmir, nmir > 1 ? "s are" : " is");
    /* Continuity is divided by its largest value over a run's first five
     * iterations: above 1 at the end, the mass imbalance grew (CG-47 green
     * 90 on the default grid ended at 68 with its monitors settled), and
     * the divergence test (1e4) does not stop it. */
    if (ngrew)
        core_str_printf(&md,
                        "**%d field%s ended with a continuity residual above 1**: the mass imbalance grew "
                        "beyond that of the run's first iterations, even where its monitors settled. Trims in "
                        "%s are the least certain of all.\n\n",
                        ngrew, ngrew > 1 ? "s" : "", ngrew > 1 ? "them" : "it");
    core_str_printf(&md,
                    "| field | WOD speed (m/s) | WOD dir (deg) | rotor | iterations | state | continuity "
                    "| mean drift (%% of U) | mean change (%% of U) |\n"
                    "|---|---|---|---|---|---|---|---|---|\n");
    for (int i = 0; i < n1 + n2; i++) {
        const couple_field_info *fi = i < n1 ? &f1[i] : &f2[i - n1];
        char st[128] = "";
        size_t sl = 0;
        if (fi->mirrored)
            sl = (size_t)snprintf(st, sizeof st, "mirror of %.1f: ", core_wod_mirror_deg(fi->wod_dir_deg));
        if (fi->converged)
            snprintf(st + sl, sizeof st - sl, "converged");
        else if (fi->engine_version[0] && fi->monitor_change >= 0.0 && fi->monitor_change < 0.02)
            snprintf(st + sl, sizeof st - sl, "monitors steady (%.1f %% of U)", 100.0 * fi->monitor_change);
        else if (fi->averaged && fi->steady_mean)
            snprintf(st + sl, sizeof st - sl, "steady mean of last %d", fi->averaged);
        else if (fi->averaged)
            snprintf(st + sl, sizeof st - sl, "not converged, mean of last %d", fi->averaged);
        else
            snprintf(st + sl, sizeof st - sl, "not converged");
        if (!fi->converged && fi->residual_continuity > 1.0) {
            size_t l = strlen(st);
            snprintf(st + l, sizeof st - l, "; continuity grew");
        }
        if (fi->rotor_model[0]) {
            size_t l = strlen(st);
            snprintf(st + l, sizeof st - l, "; rotor %s", fi->rotor_model);
        }
        char drift[24] = "-", change[24] = "-";
        if (fi->averaged && fi->mean_drift > 0.0)
            snprintf(drift, sizeof drift, "%.1f", 100.0 * fi->mean_drift);
        if (fi->averaged && fi->mean_change >= 0.0)
            snprintf(change, sizeof change, "%.1f", 100.0 * fi->mean_change);
        core_str_printf(&md, "| %s | %.2f | %.1f | %s | %d | %s | %.1e | %s | %s |\n", fi->name,
                        fi->wod_speed_mps, fi->wod_dir_deg, fi->rotor, fi->iterations, st, fi->residual_continuity,
                        drift, change);
    }
    return core_str_take(&md);
}

/* The coupling iterations of the points, for the report. */
char *couple_points_md(const couple_ctx *c)
{
    int n = 0;
    const couple_point *h = couple_history(c, &n);
    core_str md = {0};
    core_str_printf(&md,
                    "Coupled points (trim -> CFD with the loaded disk -> re-trim), each row one "
                    "iteration; `change` is the largest relative change of a control or attitude "
                    "from the previous iteration, against at least 20 %% of travel or 5 deg "
                    "(converged below 5 %%).\n\n"
                    "| WOD | speed (kt) | iter | thrust (kN) | coll %% | long %% | lat %% | pedal %% | roll (deg) | pitch (deg) | change |\n"
                    "|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (int i = 0; i < n; i++) {
        char wn[32];
        core_wod_name(h[i].wod_dir_rad * CORE_RAD_TO_DEG, wn, sizeof wn);
        for (int k = 0; k < h[i].n_iter; k++) {
            const couple_iter *it = &h[i].iter[k];
            char ch[64] = "free air";
            if (k == 0 && h[i].seed == COUPLE_SEED_PREVIOUS)
                snprintf(ch, sizeof ch, "seed: interaction at %.1f kt", h[i].seed_speed_mps / CORE_KT_TO_MPS);
            else if (k == 0 && h[i].seed == COUPLE_SEED_ONE_WAY)
                snprintf(ch, sizeof ch, "seed: one-way trim");
            if (k > 0)
                snprintf(ch, sizeof ch, "%.1f %%", 100.0 * it->change_frac);
            core_str_printf(&md, "| %s | %.1f | %d | %.2f | %.1f | %.1f | %.1f | %.1f | %.2f | %.2f | %s |\n", wn,
                            h[i].wod_speed_mps / CORE_KT_TO_MPS, k, it->thrust_N / 1000.0, it->ctl.collective_pct,
                            it->ctl.long_cyclic_pct, it->ctl.lat_cyclic_pct, it->ctl.pedal_pct,
                            it->phi_rad * CORE_RAD_TO_DEG, it->theta_rad * CORE_RAD_TO_DEG, ch);
        }
    }
    if (n == 0)
        core_str_printf(&md, "\nNo point needed a coupled trim.\n");
    return core_str_take(&md);
}
