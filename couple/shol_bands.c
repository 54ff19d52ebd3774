/* shol_bands.c -- the candidate SHOL's uncertainty bands: the measured
 * spreads behind each direction's band gathered from the run and the
 * database, then shol_band_compute (shol/band.c, docs/shol.md
 * "Uncertainty bands"). Why each source comes from where it does: the window spread is what the
 * solver measured on the very field each trim flew (cfd_result.mean_drift
 * and mean_change, kept in the field file and in couple_field_info); the
 * grid spread is the same one-way procedure on another grid level, and
 * in auto mode only over fields the database already holds, so that a
 * band never costs a field build nobody asked for (a default-grid field
 * of the CG-47 takes tens of minutes on 2 cores); the model's error is the
 * aircraft's validation as its file states it ([model_error]). */
#include "couple.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int couple_band_grid_parse(const char *s)
{
    if (!strcmp(s, "auto"))
        return COUPLE_BAND_GRID_AUTO;
    if (!strcmp(s, "none"))
        return COUPLE_BAND_GRID_NONE;
    int g = core_grid_parse(s);
    return g >= 0 ? g : -3;
}

/* The flight model's validated error (the aircraft file's [model_error])
 * in shol's terms: per criterion, NAN where the file states none. */
static void model_error_of(const hfm_aircraft *ac, shol_model_error *m)
{
    shol_model_error_none(m);
    hfm_model_error he;
    if (hfm_aircraft_model_error(ac, &he) != 0)
        return;
    m->valid = 1;
    m->err[SHOL_CRIT_ROLL] = he.roll_rad;
    m->err[SHOL_CRIT_PITCH] = he.pitch_rad;
    m->err[SHOL_CRIT_LONG] = he.long_cyclic_pct;
    m->err[SHOL_CRIT_LAT] = he.lat_cyclic_pct;
    m->err[SHOL_CRIT_COLL] = he.collective_pct;
    m->err[SHOL_CRIT_PEDAL] = he.pedal_pct;
    snprintf(m->reference, sizeof m->reference, "%.31s at %g kt", he.reference, he.airspeed_mps / CORE_KT_TO_MPS);
}

/* The window spread s of each direction's ship-only field that one loaded. */
static void window_spreads(couple_ctx *one, const shol_settings *set, shol_band_inputs *in)
{
    int n = 0;
    const couple_field_info *fi = couple_fields(one, &n);
    in->n_window = 0;
    for (int d = 0; d < set->n_dirs && in->n_window < SHOL_MAX_DIRS; d++) {
        double s = NAN;
        for (int i = 0; i < n; i++) {
            const couple_field_info *f = &fi[i];
            if (strcmp(f->rotor, "off") != 0 ||
                fabs(core_wod_wrap_deg(f->wod_dir_deg - set->dirs_rad[d] * CORE_RAD_TO_DEG)) > 1e-3)
                continue;
            s = shol_band_window_frac(f->converged, f->averaged, f->mean_drift, f->mean_change);
        }
        in->window_dir_rad[in->n_window] = set->dirs_rad[d];
        in->window_frac[in->n_window++] = s;
    }
}

/* Directions whose ship-only field at level is ready in the database. */
static int ready_dirs(awdb *db, const hfm_aircraft *ac, const core_ship *ship, const couple_settings *cs,
                      const shol_settings *set, core_grid_level level, shol_settings *out)
{
    *out = *set;
    out->n_dirs = 0;
    for (int d = 0; d < set->n_dirs; d++) {
        awdb_key k;
        awdb_key_ship_only(&k, ship->name, hfm_aircraft_name(ac), cs->ref_speed_mps, set->dirs_rad[d], level);
        core_err e = {0};
        if (awdb_key_canon(&k, &e) == 0 && awdb_query(db, &k, NULL, 0) == AWDB_READY)
            out->dirs_rad[out->n_dirs++] = set->dirs_rad[d];
    }
    return out->n_dirs;
}

int couple_shol_bands(const couple_band_opts *o, const hfm_aircraft *ac, const core_ship *ship, awdb *db,
                      const couple_settings *cs, couple_ctx *one, const shol_settings *set, shol_result *r1,
                      shol_result *r2, const core_log *log, core_err *err)
{
    shol_band_inputs *in = malloc(sizeof *in);
    if (!in)
        return core_err_set(err, -1, "shol: bands: out of memory");
    shol_band_inputs_default(in);
    window_spreads(one, set, in);
    model_error_of(ac, &in->model);
    shol_result g;
    memset(&g, 0, sizeof g);
    couple_ctx *c2 = NULL;
    char label[160] = "";
    int rc = -1, have_grid = 0;
    if (o->grid_csv) {
        if (shol_read_csv(o->grid_csv, &g, err) != 0)
            goto out;
        /* the file's folder and name: a run's folder says its grid */
        const char *p = o->grid_csv + strlen(o->grid_csv);
        for (int slashes = 0; p > o->grid_csv; p--)
            if (p[-1] == '/' && ++slashes == 2)
                break;
        snprintf(label, sizeof label, "%.150s", p);
        have_grid = 1;
    } else if (o->grid != COUPLE_BAND_GRID_NONE && set->speed_max_mps > 0) {
        shol_settings s2 = *set;
        int level = -1;
        if (o->grid >= 0) {
            level = o->grid == (int)cs->grid ? -1 : o->grid;
            if (level < 0)
                core_log_msg(log, CORE_LOG_WARN, "bands: --band-grid %s is the envelope's own grid: no grid spread",
                             core_grid_name(cs->grid));
        } else {
            /* finer first: it is the nearer the truth of the two where the family converges */
            static const int order[3][2] = {{CORE_GRID_DEFAULT, CORE_GRID_FINE},
                                            {CORE_GRID_FINE, CORE_GRID_COARSE},
                                            {CORE_GRID_DEFAULT, CORE_GRID_COARSE}};
            const shol_settings *choose = o->level_dirs ? o->level_dirs : set;
            for (int k = 0; k < 2 && level < 0; k++)
                if (ready_dirs(db, ac, ship, cs, choose, (core_grid_level)order[cs->grid][k], &s2) > 0)
                    level = order[cs->grid][k];
            if (level >= 0) /* this envelope's own directions that are ready there (none: no grid spread here) */
                ready_dirs(db, ac, ship, cs, set, (core_grid_level)level, &s2);
            if (level < 0)
                core_log_msg(log, CORE_LOG_INFO, "bands: the database has no ship-only field on another grid: no "
                                                 "grid spread (--band-grid LEVEL builds one)");
        }
        if (level >= 0) {
            couple_settings c2s = *cs;
            c2s.grid = (core_grid_level)level;
            c2s.mode = CORE_COUPLING_ONE_WAY;
            if (!(c2 = couple_create(ac, ship, db, &c2s, log, err)))
                goto out;
            if (couple_prefetch(c2, s2.dirs_rad, s2.n_dirs, err) != 0)
                goto out;
            if (o->on_grid)
                o->on_grid(o->user, c2s.grid, s2.n_dirs);
            if (s2.n_dirs > 0 && shol_envelope_run(&s2, couple_shol_trim, c2, NULL, NULL, log, &g, err) != 0) {
                if (couple_last_error(c2)[0])
                    snprintf(err->msg, sizeof err->msg, "%s", couple_last_error(c2));
                goto out;
            }
            snprintf(label, sizeof label, "%s grid, one-way", core_grid_name(c2s.grid));
            have_grid = 1;
        }
    }
    if (have_grid) {
        in->grid = &g;
        in->grid_label = label;
    }
    if (shol_band_compute(r1, in, err) != 0)
        goto out;
    if (r2) {
        in->grid_base = have_grid ? r1 : NULL;
        if (shol_band_compute(r2, in, err) != 0)
            goto out;
    }
    rc = 0;
out:
    couple_destroy(c2);
    shol_result_free(&g);
    free(in);
    return rc;
}
