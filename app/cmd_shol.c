/* cmd_shol.c -- `disim shol SCENARIO [--grid coarse|default|fine]
 * [--coupling two-way|one-way] [-o DIR] [--db DIR] [--full-circle]
 * [--dir-step-deg D] [--speed-step-kmh S] [--speed-max-kmh M]
 * [--bisect-kmh T] [--direct] [--no-seed] [--domain whole|zone] [--max-coupling-iter N]
 * [--cfd-max-iter N] [--method trim|pilot] [--task FILE] [--seeds N]
 * [--criteria-window-s S] [--band-grid auto|none|coarse|default|fine]
 * [--band-grid-csv FILE]`.
 * Every direction's limit comes with a band (issue 28; app/shol_bands.c):
 * the window spreads of its fields, the limit on a second grid (auto: the
 * one-way envelope on another level over the fields the database already
 * has; LEVEL: on that level, its fields built; --band-grid-csv: an earlier
 * run's shol.csv), and the 0.25 deg / 1 % sensitivity.
 * --method pilot (issue 26) flies the task (--task, default the landing
 * task tasks/land_<aircraft>.ini beside the scenario) with the automated
 * pilot at each WOD point (--task LOG, a file not named *.ini: the replay
 * pilot re-flies that disim fly --log recording), --seeds N flights per point
 * (--criteria-window-s S: the steady criteria's running mean, else the
 * scenario's [flown] window_s, else 3 s; 0: every step), in the scenario's
 * [sea] state and turbulence, over the one-way airwake, and writes the
 * flown envelope beside the trim-based one (default folder: the
 * scenario's output folder + /pilot); see run_pilot and docs/shol.md.
 * --speed-max-kmh 0 trims in calm air only (a hover check, e.g. ground
 * effect over the deck): no ship-only field is built for it.
 * --no-seed starts every coupled point from the free-air trim (see
 * couple_settings.seed_from_previous and seed_one_way). --domain zone
 * solves the coupled points in the deck zone only (couple_settings.zone);
 * without --domain the scenario's [cfd] coupled_domain decides.
 *
 * The candidate SHOL of the seed paper's section 2.8. The one-way envelope
 * (ship-only airwake, one field per direction scaled with speed) is always
 * computed: it is cheap, it is the comparison the report gives, and it shows
 * where the boundary is. In two-way mode the coupled trims are concentrated
 * near that boundary: from two speed steps below the one-way limit upward
 * the trim is coupled; below, the one-way trim stands in (the report marks
 * which points were coupled). */
#include "awdb.h"
#include "cmds.h"
#include "couple.h"
#include "hfm.h"
#include "progress.h"
#include "shol.h"
#include "shol_bands.h"
#include "sim.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

typedef struct progress_ctx {
    int tty;
    const char *label;
} progress_ctx;

static void on_progress(void *user, const shol_progress *p)
{
    progress_ctx *pc = user;
    if (!pc->tty && !p->done)
        return; /* quiet in logs */
    char line[256];
    shol_progress_format(p, line, sizeof line);
    fprintf(stderr, "%s%s: %s%s", pc->tty ? "\r\033[K" : "", pc->label, line, p->done || !pc->tty ? "\n" : "");
}

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
                     p->seed == COUPLE_SEED_PREVIOUS ? " (seeded)" : p->seed == COUPLE_SEED_ONE_WAY ? " (from one-way)" : "", 100.0 * it->change_frac, it->collective_pct,
                     it->long_pct, it->lat_pct, it->pedal_pct, it->phi_rad * CORE_RAD_TO_DEG,
                     it->theta_rad * CORE_RAD_TO_DEG);
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

/* Markdown of the airwake fields the envelope used (couple_fields_md). */
static char *fields_md(const couple_ctx *one, const couple_ctx *two)
{
    int n1 = 0, n2 = 0;
    const couple_field_info *f1 = couple_fields(one, &n1), *f2 = two ? couple_fields(two, &n2) : NULL;
    return couple_fields_md(f1, n1, f2, n2);
}

/* --method pilot: the ship-only field of a direction for the flights,
 * through the database's field cache (the trim sweep has already fetched
 * them; a missing one is built and waited for as the trims do). */
typedef struct pilot_fields {
    awdb_fields *fc;
    const char *ship, *aircraft;
    core_grid_level grid;
    double ref_mps;
} pilot_fields;

static int pilot_field(void *user, double dir_rad, const struct cfd_field **out, core_err *err)
{
    pilot_fields *pf = user;
    awdb_key k;
    awdb_key_ship_only(&k, pf->ship, pf->aircraft, pf->ref_mps, dir_rad, pf->grid);
    *out = awdb_fields_get(pf->fc, &k, err);
    return *out ? 0 : -1;
}

static void on_progress_flown(void *user, const shol_progress *p)
{
    progress_ctx *pc = user;
    if (!pc->tty && !p->done)
        return; /* quiet in logs */
    char name[32], left[48];
    core_wod_name(p->dir_rad * CORE_RAD_TO_DEG, name, sizeof name);
    if (p->done)
        snprintf(left, sizeof left, "done in %.0f s", p->elapsed_s);
    else if (!isfinite(p->eta_s))
        snprintf(left, sizeof left, "time left unknown");
    else
        snprintf(left, sizeof left, "%d min %02d s left", (int)(p->eta_s / 60), (int)fmod(p->eta_s, 60));
    fprintf(stderr, "%sflown: %3.0f%% %s at %.0f km/h, %d flights, %.1f s/flight, %s%s", pc->tty ? "\r\033[K" : "",
            100 * p->fraction, name, p->speed_mps / CORE_KMH_TO_MPS, p->n_trims,
            p->rate_per_s > 0 ? 1.0 / p->rate_per_s : 0.0, left, p->done || !pc->tty ? "\n" : "");
}

/* The default task: tasks/land_<aircraft file's base name>.ini beside the scenario. */
static void default_task(const sim_scenario *sc, char *buf, size_t n)
{
    const char *slash = strrchr(sc->path, '/');
    int dl = slash ? (int)(slash - sc->path) : 1;
    const char *ab = strrchr(sc->aircraft_path, '/');
    ab = ab ? ab + 1 : sc->aircraft_path;
    int al = (int)strcspn(ab, ".");
    snprintf(buf, n, "%.*s/tasks/land_%.*s.ini", dl, slash ? sc->path : ".", al, ab);
}

/* Fly the flown envelope over the trim-based one (trim) and write it. */
static int run_pilot(const sim_scenario *sc, const hfm_aircraft *ac, awdb *db, const couple_settings *cs,
                     const shol_settings *set, const shol_result *trim, const char *task_path, int seeds,
                     double window_s, int feed_controls, const char *outdir, const char *scen, int tty,
                     const core_log *log, core_err *err)
{
    char tbuf[1024];
    if (!task_path) {
        default_task(sc, tbuf, sizeof tbuf);
        task_path = tbuf;
    }
    /* a task file (*.ini) for the automated pilot, else a recorded run
     * (an LCM event log of disim fly --log) for the replay pilot */
    size_t tl = strlen(task_path);
    int replay = !(tl >= 4 && !strcmp(task_path + tl - 4, ".ini"));
    sim_task task;
    sim_log *ref = NULL;
    if (replay ? !(ref = sim_log_load(task_path, err)) : sim_task_load_ship(task_path, &sc->ship, &task, err) != 0)
        return -1;
    sim_fly_task_opts fo;
    sim_fly_task_opts_default(&fo);
    fo.replay = ref;
    fo.replay_feed_controls = feed_controls;
    fo.turbulence = sc->turbulence;
    fo.sea.state = sc->sea_state;
    fo.sea.ship_speed_mps = sc->ship_speed_mps;
    fo.sea.wave_dir_rad = sc->wave_dir_rad;
    fo.sea.spectrum = sc->spectrum ? SIM_SPECTRUM_JONSWAP : SIM_SPECTRUM_ITTC;
    memcpy(fo.station_S_m, sc->station_S_m, sizeof fo.station_S_m);
    /* the criteria's judgement: the flag, else the scenario's [flown], else the defaults */
    if (!isnan(sc->flown_window_s))
        fo.window_s = sc->flown_window_s;
    if (!isnan(sc->flown_transient_frac))
        fo.transient_frac = sc->flown_transient_frac;
    if (!isnan(window_s))
        fo.window_s = window_s;
    sim_fly_task *ft = sim_fly_task_create(ac, &sc->ship, replay ? NULL : &task, &set->criteria, &fo, log, err);
    if (!ft) {
        sim_log_destroy(ref);
        return -1;
    }
    awdb_fields_opts fopt;
    awdb_fields_opts_default(&fopt);
    fopt.cache_n = 32; /* every direction's field stays loaded */
    fopt.launch = cs->launch;
    fopt.launch_user = cs->launch_user;
    fopt.wait_fn = cs->wait_fn;
    fopt.wait_user = cs->wait_user;
    awdb_fields *fc = awdb_fields_create(db, &fopt, log, err);
    int rc = -1;
    shol_flown_result fr;
    shol_result as;
    memset(&fr, 0, sizeof fr);
    memset(&as, 0, sizeof as);
    if (!fc)
        goto out;
    pilot_fields pf = {fc, sc->ship.name, hfm_aircraft_name(ac), cs->grid, cs->ref_speed_mps};
    sim_fly_task_user fu = {ft, pilot_field, &pf};
    shol_flown_settings fs;
    shol_flown_settings_default(&fs);
    if (seeds > 0)
        fs.n_seeds = seeds;
    fs.judge.window_s = fo.window_s;
    fs.judge.transient_frac = fo.transient_frac;
    progress_ctx pc = {tty, "flown"};
    fprintf(stderr, "shol: flown: %s %s, %d seed%s per point, sea state %d, turbulence %s, steady criteria on %s\n",
            replay ? "the replay pilot re-flies" : "the automated pilot flies", task_path, fs.n_seeds,
            fs.n_seeds == 1 ? "" : "s", fo.sea.state, fo.turbulence ? "on" : "off",
            fo.window_s > 0 ? "a running mean" : "every step");
    if (shol_flown_run(&fs, trim, sim_fly_task_shol, &fu, on_progress_flown, &pc, log, &fr, err) != 0) {
        if (sim_fly_task_last_error(ft)[0])
        {
            char why[512];
            snprintf(why, sizeof why, "%.500s", err->msg);
            snprintf(err->msg, sizeof err->msg, "%.500s: %.500s", why, sim_fly_task_last_error(ft));
        }
        goto out;
    }
    char title[160], what[256];
    snprintf(title, sizeof title, "%s + %s", sc->ship.name, hfm_aircraft_name(ac));
    snprintf(what, sizeof what, "%s %.150s%s, sea state %d, turbulence %s, one-way airwake",
             replay ? "replay pilot, recorded run" : "automated pilot, task", task_path,
             feed_controls ? " (its controls fed forward)" : "", fo.sea.state, fo.turbulence ? "on" : "off");
    shol_report_info info;
    memset(&info, 0, sizeof info);
    info.title = title;
    info.label = replay ? "replay pilot" : "automated pilot";
    info.scenario_path = scen;
    info.aircraft_path = sc->aircraft_path;
    info.grid = core_grid_name(cs->grid);
    info.coupling = what;
    info.compare = trim;
    info.compare_label = "one-way trim (ship-only airwake)";
    shol_checks checks;
    if (shol_flown_as_result(&fr, trim, &as, err) != 0)
        goto out;
    if (shol_checks_run(&as, hfm_aircraft_rotor_ccw(ac), &checks) == 0) {
        info.checks = &checks;
        for (int i = 0; i < checks.n; i++)
            fprintf(stderr, "shol: flown check %s: %s (%s)\n", checks.c[i].name,
                    !checks.c[i].applicable ? "not applicable" : checks.c[i].pass ? "pass" : "FAIL", checks.c[i].detail);
    }
    if (shol_flown_write_all(outdir, &fr, trim, &info, err) != 0)
        goto out;
    printf("wod_dir_deg,trim_max_speed_kt,flown_max_speed_kt,pass_rate_at_fail,cause\n");
    for (int i = 0; i < fr.n_dirs; i++) {
        const shol_flown_dir *d = &fr.dirs[i];
        printf("%.1f,%.1f,%.1f,%.2f,%s\n", d->dir_rad * CORE_RAD_TO_DEG, d->trim_max_speed_mps / CORE_KT_TO_MPS,
               d->max_speed_mps / CORE_KT_TO_MPS, d->pass_rate_fail, d->cause);
    }
    fprintf(stderr, "shol: %d flights, %.0f s flown in %.0f s; wrote %s/shol_flown.csv, shol_flown_points.csv, "
                    "shol_flown.json, shol_polar_flown.png/.svg, report.md, shol.csv, shol.json\n",
            fr.n_flights, fr.flown_s, fr.wall_s, outdir);
    rc = 0;
out:
    shol_result_free(&as);
    shol_flown_result_free(&fr);
    awdb_fields_destroy(fc);
    sim_fly_task_destroy(ft);
    sim_log_destroy(ref);
    return rc;
}

static int parse_num(const char *flag, const char *v, double lo, double hi, double *out)
{
    return app_parse_double("disim shol", flag, v, lo, hi, out);
}

int cmd_shol(int argc, char **argv)
{
    const char *scen = NULL, *outdir = NULL, *dbdir = NULL, *task_path = NULL;
    int pilot = 0;
    double seeds = 0, window_s = NAN;
    int feed_controls = 0;
    app_band_opts bands = {APP_BAND_GRID_AUTO, NULL}; /* --band-grid, --band-grid-csv (shol_bands.h) */
    int grid = -1, coupling = -1, full = 0, direct = 0, no_seed = 0, zone = -1;
    double dstep = 0, sstep = 0, smax = -1, bisect = 0, maxit = 6, cfdit = 0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        int takes = strcmp(a, "--full-circle") && strcmp(a, "--direct") && strcmp(a, "--no-seed") &&
                    strcmp(a, "--feed-controls") && a[0] == '-';
        if (takes && !v) {
            fprintf(stderr, "disim shol: %s: expected a value\n", a);
            return 2;
        }
        if (!strcmp(a, "--full-circle")) {
            full = 1;
            continue;
        }
        if (!strcmp(a, "--direct")) {
            direct = 1;
            continue;
        }
        if (!strcmp(a, "--no-seed")) {
            no_seed = 1;
            continue;
        }
        if (!strcmp(a, "-o"))
            outdir = v;
        else if (!strcmp(a, "--db"))
            dbdir = v;
        else if (!strcmp(a, "--grid")) {
            grid = core_grid_parse(v);
            if (grid < 0) {
                fprintf(stderr, "disim shol: --grid '%s': expected coarse, default or fine\n", v);
                return 2;
            }
        } else if (!strcmp(a, "--band-grid")) {
            bands.grid = app_band_grid_parse(v);
            if (bands.grid < -2) {
                fprintf(stderr, "disim shol: --band-grid '%s': expected auto, none, coarse, default or fine\n", v);
                return 2;
            }
        } else if (!strcmp(a, "--band-grid-csv"))
            bands.grid_csv = v;
        else if (!strcmp(a, "--coupling")) {
            coupling = core_coupling_parse(v);
            if (coupling < 0) {
                fprintf(stderr, "disim shol: --coupling '%s': expected two-way or one-way\n", v);
                return 2;
            }
        } else if (!strcmp(a, "--dir-step-deg")) {
            if (parse_num(a, v, 1, 90, &dstep))
                return 2;
        } else if (!strcmp(a, "--speed-step-kmh")) {
            if (parse_num(a, v, 0.5, 50, &sstep))
                return 2;
        } else if (!strcmp(a, "--speed-max-kmh")) {
            if (parse_num(a, v, 0, 300, &smax))
                return 2;
        } else if (!strcmp(a, "--bisect-kmh")) {
            if (parse_num(a, v, 0.1, 50, &bisect))
                return 2;
        } else if (!strcmp(a, "--domain")) {
            zone = !strcmp(v, "zone") ? 1 : !strcmp(v, "whole") ? 0 : -2;
            if (zone == -2) {
                fprintf(stderr, "disim shol: --domain '%s': expected whole or zone\n", v);
                return 2;
            }
        } else if (!strcmp(a, "--cfd-max-iter")) {
            if (parse_num(a, v, 10, 1e6, &cfdit))
                return 2;
        } else if (!strcmp(a, "--method")) {
            pilot = !strcmp(v, "pilot") ? 1 : !strcmp(v, "trim") ? 0 : -1;
            if (pilot < 0) {
                fprintf(stderr, "disim shol: --method '%s': expected trim or pilot\n", v);
                return 2;
            }
        } else if (!strcmp(a, "--task"))
            task_path = v;
        else if (!strcmp(a, "--feed-controls")) {
            feed_controls = 1;
            continue;
        }
        else if (!strcmp(a, "--criteria-window-s")) {
            if (parse_num(a, v, 0, 60, &window_s))
                return 2;
        } else if (!strcmp(a, "--seeds")) {
            if (parse_num(a, v, 1, SHOL_FLOWN_MAX_SEEDS, &seeds) || seeds != floor(seeds)) {
                if (seeds != floor(seeds))
                    fprintf(stderr, "disim shol: --seeds: expected a whole number\n");
                return 2;
            }
        } else if (!strcmp(a, "--max-coupling-iter")) {
            if (parse_num(a, v, 1, COUPLE_MAX_ITER - 1, &maxit))
                return 2;
        } else if (a[0] == '-') {
            fprintf(stderr, "disim shol: unknown flag '%s'\n", a);
            return 2;
        } else if (!scen) {
            scen = a;
            continue;
        } else {
            fprintf(stderr, "disim shol: unexpected argument '%s'\n", a);
            return 2;
        }
        i++;
    }
    if (!scen) {
        fprintf(stderr, "usage: disim shol SCENARIO [--grid coarse|default|fine] [--coupling two-way|one-way] "
                        "[-o DIR] [--db DIR] [--full-circle] [--dir-step-deg D] [--speed-step-kmh S] "
                        "[--speed-max-kmh M] [--bisect-kmh T] [--direct] [--no-seed] [--domain whole|zone] [--max-coupling-iter N] "
                        "[--cfd-max-iter N] [--method trim|pilot] [--task FILE|LOG [--feed-controls]] [--seeds N] [--criteria-window-s S] "
                        "[--band-grid auto|none|coarse|default|fine] [--band-grid-csv FILE]\n");
        return 2;
    }
    if (!pilot && (task_path || seeds > 0 || !isnan(window_s) || feed_controls)) {
        fprintf(stderr, "disim shol: --task, --seeds, --criteria-window-s and --feed-controls go with --method pilot\n");
        return 2;
    }
    if (feed_controls) { /* the replay pilot's: a recorded run, not a task file */
        size_t tl = task_path ? strlen(task_path) : 0;
        if (!task_path || (tl >= 4 && !strcmp(task_path + tl - 4, ".ini"))) {
            fprintf(stderr, "disim shol: --feed-controls: the replay pilot's (--task LOG, a log of disim fly --log)\n");
            return 2;
        }
    }
    int tty = isatty(2);
    app_log al = {"shol", tty};
    core_log log = {app_log_stderr, &al, CORE_LOG_INFO};
    core_err err = {0};
    sim_scenario *sc = calloc(1, sizeof *sc);
    hfm_aircraft *ac = NULL;
    awdb *db = NULL;
    couple_ctx *one = NULL, *two = NULL;
    shol_result r1, r2;
    memset(&r1, 0, sizeof r1);
    memset(&r2, 0, sizeof r2);
    char *md = NULL, *fmd = NULL;
    int rc = 1;
    if (!sc || sim_scenario_load(scen, sc, &err) != 0)
        goto fail;
    if (!(ac = hfm_aircraft_load(sc->aircraft_path, &log, &err)))
        goto fail;
    shol_settings set;
    {
        /* --method pilot flies in the scenario's sea; its trims, as every
         * trim sweep, are over the ship at rest */
        int sea = sc->sea_state;
        if (pilot)
            sc->sea_state = 0;
        int src = couple_shol_settings_scenario(&set, sc, &err);
        sc->sea_state = sea;
        if (src != 0)
            goto fail;
    }
    if (full && shol_settings_full_circle(&set, (dstep > 0 ? dstep : 30.0) * CORE_DEG_TO_RAD, &err) != 0)
        goto fail;
    if (!full && dstep > 0 && shol_settings_dirs(&set, -90 * CORE_DEG_TO_RAD, 90 * CORE_DEG_TO_RAD, dstep * CORE_DEG_TO_RAD, &err) != 0)
        goto fail;
    if (sstep > 0)
        set.speed_step_mps = sstep * CORE_KMH_TO_MPS;
    if (smax >= 0) /* 0: calm air only (a hover check) */
        set.speed_max_mps = smax * CORE_KMH_TO_MPS;
    set.bisect_tol_mps = bisect * CORE_KMH_TO_MPS;
    if (shol_settings_check(&set, &err) != 0)
        goto fail;

    char dbbuf[1024], outbuf[1024];
    if (!outdir && pilot)
        snprintf(outbuf, sizeof outbuf, "%s/pilot", sc->output_dir);
    else
        snprintf(outbuf, sizeof outbuf, "%s", outdir ? outdir : sc->output_dir);
    if (!dbdir) {
        snprintf(dbbuf, sizeof dbbuf, "out/airwake-db");
        dbdir = dbbuf;
    }
    if (core_mkdir_p(dbdir, &err) != 0) /* the database folder and its parents */
        goto fail;
    if (!(db = awdb_open(dbdir, &log, &err)))
        goto fail;

    couple_settings cs;
    couple_settings_scenario(&cs, sc);
    if (grid >= 0)
        cs.grid = (core_grid_level)grid;
    if (zone >= 0) /* --domain, else the scenario's [cfd] coupled_domain */
        cs.zone = zone;
    cs.direct = direct;
    cs.seed_from_previous = !no_seed;
    cs.seed_one_way = !no_seed;
    cs.max_iter = (int)maxit;
    app_progress pw; /* the status line on a terminal while a field is built (progress.c) */
    app_progress_init(&pw, db, tty);
    cs.wait_fn = app_progress_wait;
    cs.wait_user = &pw;
    app_launcher launcher;
    if (app_launcher_init(&launcher, sc->ship_path, cfdit > 0 ? (int)cfdit : sc->max_iterations) == 0) {
        cs.launch = app_launch_builder;
        cs.launch_user = &launcher;
    }
    int mode = coupling >= 0 ? coupling : (int)cs.mode;
    if (pilot) /* the flights fly the one-way airwake: its trims are the comparison */
        mode = CORE_COUPLING_ONE_WAY;

    cs.mode = CORE_COUPLING_ONE_WAY;
    if (!(one = couple_create(ac, &sc->ship, db, &cs, &log, &err)))
        goto fail;
    /* calm air only needs no ship-only field (couple_trim) */
    if (set.speed_max_mps > 0 && couple_prefetch(one, set.dirs_rad, set.n_dirs, &err) != 0)
        goto fail;
    progress_ctx pc = {tty, "one-way"};
    fprintf(stderr, "shol: %s + %s, %d directions, grid %s, %s\n", sc->ship.name, hfm_aircraft_name(ac), set.n_dirs,
            core_grid_name(cs.grid),
            mode != CORE_COUPLING_TWO_WAY ? "one-way" : cs.zone ? "two-way coupling in the deck zone" : "two-way coupling");
    if (shol_envelope_run(&set, couple_shol_trim, one, on_progress, &pc, &log, &r1, &err) != 0) {
        if (couple_last_error(one)[0])
            snprintf(err.msg, sizeof err.msg, "%s", couple_last_error(one));
        goto fail;
    }
    fill_loads(&r1, one, NULL);
    /* each direction's band (issue 28; app/shol_bands.c); two-way below */
    if (mode != CORE_COUPLING_TWO_WAY &&
        app_shol_bands(&bands, ac, &sc->ship, db, &cs, one, &set, &r1, NULL, &log, &err) != 0)
        goto fail;
    if (pilot) {
        cs.mode = CORE_COUPLING_ONE_WAY;
        if (run_pilot(sc, ac, db, &cs, &set, &r1, task_path, (int)seeds, window_s, feed_controls, outbuf, scen, tty, &log,
                      &err) != 0)
            goto fail;
        rc = 0;
        goto done;
    }
    char title[160];
    snprintf(title, sizeof title, "%s + %s", sc->ship.name, hfm_aircraft_name(ac));
    shol_report_info info;
    memset(&info, 0, sizeof info);
    info.title = title;
    info.scenario_path = scen;
    info.aircraft_path = sc->aircraft_path;
    info.grid = core_grid_name(cs.grid);
    const shol_result *main_r = &r1;
    if (mode == CORE_COUPLING_TWO_WAY) {
        cs.mode = CORE_COUPLING_TWO_WAY;
        if (!(two = couple_create(ac, &sc->ship, db, &cs, &log, &err)))
            goto fail;
        /* coupled from two steps of the resolution below the one-way limit
         * (the bisection's tolerance where it is finer than the step) */
        double res = set.bisect_tol_mps > 0.0 ? fmin(set.speed_step_mps, set.bisect_tol_mps) : set.speed_step_mps;
        two_ctx tc = {two, "", &log};
        pc.label = "two-way";
        if (shol_envelope_run_near(&set, &r1, couple_shol_trim, one, two_trim, &tc, 2.0 * res, on_progress, &pc,
                                   &log, &r2, &err) != 0) {
            if (tc.err[0])
                snprintf(err.msg, sizeof err.msg, "%s", tc.err);
            goto fail;
        }
        fill_loads(&r2, two, one);
        cs.mode = CORE_COUPLING_ONE_WAY;
        if (app_shol_bands(&bands, ac, &sc->ship, db, &cs, one, &set, &r1, &r2, &log, &err) != 0)
            goto fail;
        cs.mode = CORE_COUPLING_TWO_WAY;
        main_r = &r2;
        md = couple_points_md(two);
        info.label = "two-way coupled";
        if (cs.zone)
            info.coupling = cs.direct ? "two-way, coupled field used directly; coupled fields in the deck zone (5 R "
                                        "round the hub, bounded by the ship-only field)"
                                      : "two-way, interaction velocity (coupled - isolated rotor); both fields in the "
                                        "deck zone (5 R round the hub, the coupled one bounded by the ship-only field)";
        else
            info.coupling = cs.direct ? "two-way, coupled field used directly"
                                      : "two-way, interaction velocity (coupled - isolated rotor)";
        info.compare = &r1;
        info.compare_label = "one-way (ship-only airwake)";
        info.coupling_md = md;
    } else {
        info.label = "one-way (ship-only airwake)";
        info.coupling = "one-way";
    }
    fmd = fields_md(one, two);
    info.fields_md = fmd;
    /* The physics checks of the main envelope (shol/checks.c). */
    shol_checks checks;
    if (shol_checks_run(main_r, hfm_aircraft_rotor_ccw(ac), &checks) == 0) {
        info.checks = &checks;
        for (int i = 0; i < checks.n; i++)
            fprintf(stderr, "shol: check %s: %s (%s)\n", checks.c[i].name,
                    !checks.c[i].applicable ? "not applicable" : checks.c[i].pass ? "pass" : "FAIL", checks.c[i].detail);
    }
    if (shol_write_all(outbuf, main_r, &info, &err) != 0)
        goto fail;
    printf("wod_dir_deg,max_speed_kt,limit\n");
    for (int i = 0; i < main_r->n_dirs; i++) {
        const shol_dir_result *d = &main_r->dirs[i];
        printf("%.1f,%.1f,%s\n", d->dir_rad * CORE_RAD_TO_DEG, d->max_speed_mps / CORE_KT_TO_MPS, shol_limit_name(d->limit));
    }
    fprintf(stderr, "shol: wrote %s/shol.csv, shol.json, shol_polar.png/.svg, trim plots and report.md\n", outbuf);
    rc = 0;
    goto done;
fail:
    fprintf(stderr, "%sdisim shol: %s\n", tty ? "\r\033[K" : "", err.msg);
done:
    free(md);
    free(fmd);
    shol_result_free(&r1);
    shol_result_free(&r2);
    couple_destroy(two);
    couple_destroy(one);
    awdb_close(db);
    hfm_aircraft_destroy(ac);
    free(sc);
    return rc;
}
