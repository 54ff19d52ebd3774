/* cmd_shol.c -- `disim shol SCENARIO [--grid coarse|default|fine]
 * [--coupling two-way|one-way] [-o DIR] [--db DIR] [--full-circle]
 * [--dir-step-deg D] [--speed-step-kmh S] [--speed-max-kmh M]
 * [--bisect-kmh T] [--direct] [--no-seed] [--domain whole|zone] [--max-coupling-iter N]
 * [--cfd-max-iter N] [--method trim|pilot] [--task FILE] [--seeds N]
 * [--criteria-window-s S] [--band-grid auto|none|coarse|default|fine]
 * [--band-grid-csv FILE]`.
 * Every direction's limit comes with a band (couple_shol_bands):
 * the window spreads of its fields, the limit on a second grid (auto: the
 * one-way envelope on another level over the fields the database already
 * has; LEVEL: on that level, its fields built; --band-grid-csv: an earlier
 * run's shol.csv), the 0.25 deg / 1 % sensitivity, and the flight model's
 * validated error (the aircraft file's [model_error]).
 * --method pilot flies the task (--task, default the landing
 * task tasks/land_<aircraft>.ini beside the scenario) with the automated
 * pilot at each WOD point (--task LOG, a file not named *.ini: the replay
 * pilot re-flies that disim fly --log recording), --seeds N flights per point
 * (default 11: the fewest at which a point's 90 % Wilson interval can clear 0.8)
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
 * which points were coupled). The sweeps are couple_shol_one_way and
 * couple_shol_two_way (couple/shol_sweep.c); this file parses the flags,
 * loads and opens what they need, and prints. */
#include "awdb.h"
#include "cmds.h"
#include "couple.h"
#include "hfm.h"
#include "progress.h"
#include "shol.h"
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

/* --method pilot's field cache: every direction's field stays loaded,
 * missing ones built and waited for as the trims do. */
static awdb_fields *pilot_fields_open(awdb *db, const couple_settings *cs, const core_log *log, core_err *err)
{
    awdb_fields_opts fopt;
    awdb_fields_opts_default(&fopt);
    fopt.cache_n = 32; /* every direction's field stays loaded */
    fopt.launch = cs->launch;
    fopt.launch_user = cs->launch_user;
    fopt.wait_fn = cs->wait_fn;
    fopt.wait_user = cs->wait_user;
    return awdb_fields_create(db, &fopt, log, err);
}

/* What --method pilot flew, for its report and messages. */
typedef struct pilot_run {
    const char *task_path;
    int replay, feed_controls, sea_state, turbulence;
    const char *notes_md; /* for the report, or NULL */
} pilot_run;

/* The flown envelope fr over the trim-based one (trim): its checks (one
 * line each on stderr), its files in outdir, its table on stdout. */
static int pilot_write(const sim_scenario *sc, const hfm_aircraft *ac, const couple_settings *cs,
                       const shol_result *trim, const shol_flown_result *fr, const pilot_run *pr, const char *outdir,
                       const char *scen, core_err *err)
{
    char title[160], what[256];
    snprintf(title, sizeof title, "%s + %s", sc->ship.name, hfm_aircraft_name(ac));
    snprintf(what, sizeof what, "%s %.150s%s, sea state %d, turbulence %s, one-way airwake",
             pr->replay ? "replay pilot, recorded run" : "automated pilot, task", pr->task_path,
             pr->feed_controls ? " (its controls fed forward)" : "", pr->sea_state, pr->turbulence ? "on" : "off");
    shol_report_info info;
    memset(&info, 0, sizeof info);
    info.title = title;
    info.label = pr->replay ? "replay pilot" : "automated pilot";
    info.scenario_path = scen;
    info.aircraft_path = sc->aircraft_path;
    info.grid = core_grid_name(cs->grid);
    info.coupling = what;
    info.compare = trim;
    info.compare_label = "one-way trim (ship-only airwake)";
    info.notes_md = pr->notes_md;
    shol_checks checks;
    shol_result as;
    memset(&as, 0, sizeof as);
    int rc = -1;
    if (shol_flown_as_result(fr, trim, &as, err) != 0)
        goto out;
    if (shol_checks_run(&as, hfm_aircraft_rotor_ccw(ac), &checks) == 0) {
        info.checks = &checks;
        for (int i = 0; i < checks.n; i++)
            fprintf(stderr, "shol: flown check %s: %s (%s)\n", checks.c[i].name,
                    !checks.c[i].applicable ? "not applicable" : checks.c[i].pass ? "pass" : "FAIL", checks.c[i].detail);
    }
    if (shol_flown_write_all(outdir, fr, trim, &info, err) != 0)
        goto out;
    printf("wod_dir_deg,trim_max_speed_kt,flown_max_speed_kt,pass_rate_at_fail,cause\n");
    for (int i = 0; i < fr->n_dirs; i++) {
        const shol_flown_dir *d = &fr->dirs[i];
        printf("%.1f,%.1f,%.1f,%.2f,%s\n", d->dir_rad * CORE_RAD_TO_DEG, d->trim_max_speed_mps / CORE_KT_TO_MPS,
               d->max_speed_mps / CORE_KT_TO_MPS, d->pass_rate_fail, d->cause);
    }
    fprintf(stderr, "shol: %d flights, %.0f s flown in %.0f s; wrote %s/shol_flown.csv, shol_flown_points.csv, "
                    "shol_flown.json, shol_polar_flown.png/.svg, report.md, shol.csv, shol.json\n",
            fr->n_flights, fr->flown_s, fr->wall_s, outdir);
    rc = 0;
out:
    shol_result_free(&as);
    return rc;
}

/* The air over the spot at the hub, per direction of fr (the report's
 * evidence for a sheltered but turbulent beam wind), from the fields the
 * flights flew. 0, or < 0 with err. */
static int hub_air(couple_fly_task *ft, const couple_fly_task_user *fu, shol_flown_result *fr, core_err *err)
{
    for (int i = 0; i < fr->n_dirs; i++) {
        const shol_flown_dir *d = &fr->dirs[i];
        if (d->n_points < 1 || !(d->points[d->n_points - 1].speed_mps > 0.0))
            continue; /* flown in calm air only: no field was asked for, none is built for this */
        const struct cfd_field *f = NULL;
        if (fu->field(fu->field_user, fr->dirs[i].dir_rad, &f, err) != 0)
            return -1;
        if (f && couple_fly_task_air_at_hub(ft, f, &fr->dirs[i].hub_speed_frac, &fr->dirs[i].hub_ti_frac, err) != 0)
            return -1;
    }
    return 0;
}

/* The replay's recording judged by the criteria, as a report note (and a
 * line on stderr): 1 with buf filled, 0 when nothing to say. */
static int recording_note(const couple_fly_task *ft, char *buf, size_t n)
{
    char cause[SHOL_CAUSE_MAX];
    double t_s;
    core_err e = {0};
    int rc = couple_fly_task_judge_recording(ft, cause, sizeof cause, &t_s, &e);
    if (rc < 0)
        return 0;
    if (rc == 0)
        snprintf(buf, n, "The recording itself, judged by the same criteria up to its touchdown: within every "
                         "limit.");
    else
        snprintf(buf, n, "The recording itself, judged by the same criteria up to its touchdown: **%s at %.2f s**. "
                         "A replay that tracks it meets the same limit wherever the WOD leaves the attitude or "
                         "control it exceeds where it was, so directions that fail on that cause at every speed "
                         "say so of the recording, not of the airwake.", cause, t_s);
    if (rc)
        fprintf(stderr, "shol: the recording judged by the criteria: %s at %.2f s\n", cause, t_s);
    else
        fprintf(stderr, "shol: the recording judged by the criteria: within every limit\n");
    return 1;
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
    couple_fly_task_opts fo;
    couple_fly_task_opts_default(&fo);
    fo.replay = ref;
    fo.replay_feed_controls = feed_controls;
    fo.turbulence = sc->turbulence;
    fo.sea.state = sc->sea.state;
    fo.sea.ship_speed_mps = sc->sea.ship_speed_mps;
    fo.sea.wave_dir_rad = sc->sea.wave_dir_rad;
    fo.sea.spectrum = sc->sea.spectrum;
    memcpy(fo.station_S_m, sc->station_S_m, sizeof fo.station_S_m);
    /* the criteria's judgement: the flag, else the scenario's [flown], else the defaults */
    if (!isnan(sc->flown_window_s))
        fo.window_s = sc->flown_window_s;
    if (!isnan(sc->flown_transient_frac))
        fo.transient_frac = sc->flown_transient_frac;
    if (!isnan(window_s))
        fo.window_s = window_s;
    couple_fly_task *ft = couple_fly_task_create(ac, &sc->ship, replay ? NULL : &task, &set->criteria, &fo, log, err);
    if (!ft) {
        sim_log_destroy(ref);
        return -1;
    }
    awdb_fields *fc = pilot_fields_open(db, cs, log, err);
    int rc = -1;
    shol_flown_result fr;
    memset(&fr, 0, sizeof fr);
    if (!fc)
        goto out;
    pilot_fields pf = {fc, sc->ship.name, hfm_aircraft_name(ac), cs->grid, cs->ref_speed_mps};
    couple_fly_task_user fu = {ft, pilot_field, &pf};
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
    if (shol_flown_run(&fs, trim, couple_fly_task_shol, &fu, on_progress_flown, &pc, log, &fr, err) != 0) {
        if (couple_fly_task_last_error(ft)[0])
        {
            char why[512];
            snprintf(why, sizeof why, "%.500s", err->msg);
            snprintf(err->msg, sizeof err->msg, "%.500s: %.500s", why, couple_fly_task_last_error(ft));
        }
        goto out;
    }
    if (hub_air(ft, &fu, &fr, err) != 0)
        goto out;
    char notes[512];
    pilot_run pr = {task_path, replay, feed_controls, fo.sea.state, fo.turbulence,
                    replay && recording_note(ft, notes, sizeof notes) ? notes : NULL};
    if (pilot_write(sc, ac, cs, trim, &fr, &pr, outdir, scen, err) != 0)
        goto out;
    rc = 0;
out:
    shol_flown_result_free(&fr);
    awdb_fields_destroy(fc);
    couple_fly_task_destroy(ft);
    sim_log_destroy(ref);
    return rc;
}


/* The command line of disim shol (numbers NAN or -1: not given). */
typedef struct shol_args {
    const char *scen, *outdir, *dbdir, *task_path, *run_id;
    int pilot, feed_controls, full, direct, no_seed;
    int grid, coupling, zone;
    double seeds, window_s, dstep, sstep, smax, bisect, maxit, cfdit;
    double rank, ranks, rank_wait_s; /* --rank, --ranks (-1: from the environment), --rank-wait-s */
    couple_band_opts bands; /* --band-grid, --band-grid-csv */
} shol_args;

static int parse_domain(const char *v) { return !strcmp(v, "zone") ? 1 : !strcmp(v, "whole") ? 0 : -2; }
static int parse_method(const char *v) { return !strcmp(v, "pilot") ? 1 : !strcmp(v, "trim") ? 0 : -1; }

/* One flag's value (a number in [lo, hi], a word parsed to a code, or a
 * string) into o: 0, 2 after the message, -1 not such a flag. */
static int shol_flag(shol_args *o, const char *a, const char *v)
{
    const struct {
        const char *flag;
        double lo, hi;
        double *out;
    } num[] = {
        {"--dir-step-deg", 1, 90, &o->dstep},          {"--speed-step-kmh", 0.5, 50, &o->sstep},
        {"--speed-max-kmh", 0, 300, &o->smax},         {"--bisect-kmh", 0.1, 50, &o->bisect},
        {"--cfd-max-iter", 10, 1e6, &o->cfdit},        {"--criteria-window-s", 0, 60, &o->window_s},
        {"--max-coupling-iter", 1, COUPLE_MAX_ITER - 1, &o->maxit},
        {"--rank", 0, SHOL_MAX_RANKS - 1, &o->rank},    {"--ranks", 1, SHOL_MAX_RANKS, &o->ranks},
        {"--rank-wait-s", 1, 1e7, &o->rank_wait_s},
    };
    const struct {
        const char *flag;
        int (*parse)(const char *);
        int bad_below;
        int *out;
        const char *expect;
    } word[] = {
        {"--grid", core_grid_parse, 0, &o->grid, "coarse, default or fine"},
        {"--band-grid", couple_band_grid_parse, -2, &o->bands.grid, "auto, none, coarse, default or fine"},
        {"--coupling", core_coupling_parse, 0, &o->coupling, "two-way or one-way"},
        {"--domain", parse_domain, 0, &o->zone, "whole or zone"},
        {"--method", parse_method, 0, &o->pilot, "trim or pilot"},
    };
    const struct {
        const char *flag;
        const char **out;
    } str[] = {{"-o", &o->outdir}, {"--db", &o->dbdir}, {"--band-grid-csv", &o->bands.grid_csv}, {"--task", &o->task_path},
              {"--run-id", &o->run_id}};
    for (size_t k = 0; k < sizeof num / sizeof num[0]; k++)
        if (!strcmp(a, num[k].flag))
            return app_parse_double("disim shol", a, v, num[k].lo, num[k].hi, num[k].out) ? 2 : 0;
    for (size_t k = 0; k < sizeof word / sizeof word[0]; k++)
        if (!strcmp(a, word[k].flag)) {
            *word[k].out = word[k].parse(v);
            if (*word[k].out >= word[k].bad_below)
                return 0;
            fprintf(stderr, "disim shol: %s '%s': expected %s\n", a, v, word[k].expect);
            return 2;
        }
    for (size_t k = 0; k < sizeof str / sizeof str[0]; k++)
        if (!strcmp(a, str[k].flag)) {
            *str[k].out = v;
            return 0;
        }
    if (!strcmp(a, "--seeds")) {
        if (app_parse_double("disim shol", a, v, 1, SHOL_FLOWN_MAX_SEEDS, &o->seeds) || o->seeds != floor(o->seeds)) {
            if (o->seeds != floor(o->seeds))
                fprintf(stderr, "disim shol: --seeds: expected a whole number\n");
            return 2;
        }
        return 0;
    }
    return -1;
}

/* The flags into o: 0, or 2 (usage) after the message. */
static int shol_parse(int argc, char **argv, shol_args *o)
{
    memset(o, 0, sizeof *o);
    o->bands.grid = COUPLE_BAND_GRID_AUTO;
    o->grid = o->coupling = o->zone = -1;
    o->window_s = NAN;
    o->smax = -1;
    o->maxit = 6;
    o->rank = o->ranks = -1;
    o->rank_wait_s = 24 * 3600.0;
    const struct {
        const char *flag;
        int *out;
    } sw[] = {{"--full-circle", &o->full}, {"--direct", &o->direct}, {"--no-seed", &o->no_seed},
              {"--feed-controls", &o->feed_controls}};
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        int s = -1;
        for (size_t k = 0; k < sizeof sw / sizeof sw[0]; k++)
            if (!strcmp(a, sw[k].flag))
                s = (int)k;
        if (s >= 0) {
            *sw[s].out = 1;
            continue;
        }
        if (a[0] != '-') {
            if (o->scen) {
                fprintf(stderr, "disim shol: unexpected argument '%s'\n", a);
                return 2;
            }
            o->scen = a;
            continue;
        }
        if (!v) {
            fprintf(stderr, "disim shol: %s: expected a value\n", a);
            return 2;
        }
        int rc = shol_flag(o, a, v);
        if (rc < 0)
            fprintf(stderr, "disim shol: unknown flag '%s'\n", a);
        if (rc != 0)
            return 2;
        i++;
    }
    if (!o->scen) {
        fprintf(stderr, "usage: disim shol SCENARIO [--grid coarse|default|fine] [--coupling two-way|one-way] "
                        "[-o DIR] [--db DIR] [--full-circle] [--dir-step-deg D] [--speed-step-kmh S] "
                        "[--speed-max-kmh M] [--bisect-kmh T] [--direct] [--no-seed] [--domain whole|zone] [--max-coupling-iter N] "
                        "[--cfd-max-iter N] [--method trim|pilot] [--task FILE|LOG [--feed-controls]] [--seeds N] [--criteria-window-s S] "
                        "[--band-grid auto|none|coarse|default|fine] [--band-grid-csv FILE] "
                        "[--rank R --ranks N] [--run-id ID] [--rank-wait-s S]\n");
        return 2;
    }
    if ((o->rank >= 0) != (o->ranks >= 0) || o->rank != floor(o->rank) || o->ranks != floor(o->ranks) ||
        (o->rank >= 0 && o->rank >= o->ranks)) {
        fprintf(stderr, "disim shol: --rank R and --ranks N go together, whole numbers with 0 <= R < N\n");
        return 2;
    }
    if (!o->pilot && (o->task_path || o->seeds > 0 || !isnan(o->window_s) || o->feed_controls)) {
        fprintf(stderr, "disim shol: --task, --seeds, --criteria-window-s and --feed-controls go with --method pilot\n");
        return 2;
    }
    if (o->feed_controls) { /* the replay pilot's: a recorded run, not a task file */
        size_t tl = o->task_path ? strlen(o->task_path) : 0;
        if (!o->task_path || (tl >= 4 && !strcmp(o->task_path + tl - 4, ".ini"))) {
            fprintf(stderr, "disim shol: --feed-controls: the replay pilot's (--task LOG, a log of disim fly --log)\n");
            return 2;
        }
    }
    return 0;
}

/* One run of disim shol: what it loaded and opened, freed by job_free. */
typedef struct shol_job {
    const shol_args *a;
    int tty, mode;
    app_log al;
    core_log log;
    core_err err;
    sim_scenario *sc;
    hfm_aircraft *ac;
    awdb *db;
    couple_ctx *one, *two;
    shol_settings set;
    couple_settings cs;
    shol_result r1, r2;
    app_progress pw; /* the status line on a terminal while a field is built (progress.c) */
    app_launcher launcher;
    const char *dbdir;
    char outdir[1024];
    /* a sweep spread over ranks (docs/cluster.md): this process's rank of
     * ranks, the whole sweep's settings (set holds this rank's share), the
     * stage folder of the parts, the run's key, the log's prefix and the
     * other ranks' report texts (rank 0, once gathered) */
    int rank, ranks;
    shol_settings all;
    char stage[1200], run_id[128], prefix[48];
    char *key;
    char **texts;
} shol_job;

/* The scenario, its aircraft and the envelope's settings with the flags. */
static int job_load(shol_job *j)
{
    const shol_args *a = j->a;
    if (!(j->sc = calloc(1, sizeof *j->sc)) || sim_scenario_load(a->scen, j->sc, &j->err) != 0)
        return -1;
    if (!(j->ac = hfm_aircraft_load(j->sc->aircraft_path, &j->log, &j->err)))
        return -1;
    /* --method pilot flies in the scenario's sea; its trims, as every
     * trim sweep, are over the ship at rest */
    int sea = j->sc->sea.state;
    if (a->pilot)
        j->sc->sea.state = 0;
    int src = couple_shol_settings_scenario(&j->set, j->sc, &j->err);
    j->sc->sea.state = sea;
    if (src != 0)
        return -1;
    shol_settings *set = &j->set;
    if (a->full && shol_settings_full_circle(set, (a->dstep > 0 ? a->dstep : 30.0) * CORE_DEG_TO_RAD, &j->err) != 0)
        return -1;
    if (!a->full && a->dstep > 0 &&
        shol_settings_dirs(set, -90 * CORE_DEG_TO_RAD, 90 * CORE_DEG_TO_RAD, a->dstep * CORE_DEG_TO_RAD, &j->err) != 0)
        return -1;
    if (a->sstep > 0)
        set->speed_step_mps = a->sstep * CORE_KMH_TO_MPS;
    if (a->smax >= 0) /* 0: calm air only (a hover check) */
        set->speed_max_mps = a->smax * CORE_KMH_TO_MPS;
    set->bisect_tol_mps = a->bisect * CORE_KMH_TO_MPS;
    if (shol_settings_check(set, &j->err) != 0)
        return -1;
    if (j->ranks < 2)
        return 0;
    /* this rank's share of the directions: whole directions, so that each
     * direction's trims run in one process in the serial order */
    j->all = *set;
    return shol_settings_deal(&j->all, j->rank, j->ranks, set, &j->err) < 0 ? -1 : 0;
}

/* The output folder, the database and the coupling settings. */
static int job_open(shol_job *j)
{
    const shol_args *a = j->a;
    if (!a->outdir && a->pilot)
        snprintf(j->outdir, sizeof j->outdir, "%s/pilot", j->sc->output_dir);
    else
        snprintf(j->outdir, sizeof j->outdir, "%s", a->outdir ? a->outdir : j->sc->output_dir);
    j->dbdir = a->dbdir ? a->dbdir : app_db_default(j->sc);
    if (j->ranks > 1) /* beside the outputs: a folder every rank can reach */
        snprintf(j->stage, sizeof j->stage, "%s/.shol-ranks%s%s", j->outdir, j->run_id[0] ? "-" : "", j->run_id);
    /* before the envelope is computed (hours on a two-way run) */
    core_err why = {0};
    if (core_dir_check(j->outdir, &why) != 0)
        return core_err_set(&j->err, -1, "output folder: %s", why.msg);
    if (core_mkdir_p(j->dbdir, &j->err) != 0) /* the database folder and its parents */
        return -1;
    if (!(j->db = awdb_open(j->dbdir, &j->log, &j->err)) ||
        awdb_engine_claim(j->db, j->sc->engine == SIM_ENGINE_OPENFOAM ? "openfoam" : "embedded", &j->err) != 0)
        return -1;
    couple_settings *cs = &j->cs;
    couple_settings_scenario(cs, j->sc);
    if (a->grid >= 0)
        cs->grid = (core_grid_level)a->grid;
    if (a->zone >= 0) /* --domain, else the scenario's [cfd] coupled_domain */
        cs->zone = a->zone;
    cs->direct = a->direct;
    cs->seed_from_previous = !a->no_seed;
    cs->seed_one_way = !a->no_seed;
    cs->max_iter = (int)a->maxit;
    app_progress_init(&j->pw, j->db, j->tty);
    cs->wait_fn = app_progress_wait;
    cs->wait_user = &j->pw;
    if (app_launcher_init(&j->launcher, j->sc, a->cfdit > 0 ? (int)a->cfdit : j->sc->max_iterations) == 0) {
        cs->launch = app_launch_builder;
        cs->launch_user = &j->launcher;
    }
    j->mode = a->coupling >= 0 ? a->coupling : (int)cs->mode;
    if (a->pilot) /* the flights fly the one-way airwake: its trims are the comparison */
        j->mode = CORE_COUPLING_ONE_WAY;
    return 0;
}

/* The bands' second grid: its sweep starts. */
static void on_band_grid(void *user, core_grid_level level, int n_dirs)
{
    (void)user;
    fprintf(stderr, "shol: bands: the one-way envelope on the %s grid, %d direction%s\n", core_grid_name(level),
            n_dirs, n_dirs == 1 ? "" : "s");
}

/* The bands of r1, and r2's with r2 (couple_shol_bands), one line per
 * direction of the main envelope on stderr. */
static int job_bands(shol_job *j, shol_result *r2)
{
    couple_band_opts bo = j->a->bands;
    bo.on_grid = on_band_grid;
    bo.level_dirs = j->ranks > 1 ? &j->all : NULL;
    if (couple_shol_bands(&bo, j->ac, &j->sc->ship, j->db, &j->cs, j->one, &j->set, &j->r1, r2, &j->log, &j->err) != 0)
        return -1;
    const shol_result *m = r2 ? r2 : &j->r1;
    for (int i = 0; i < m->n_dirs; i++) {
        const shol_dir_result *d = &m->dirs[i];
        char name[32], what[256];
        core_wod_name(d->dir_rad * CORE_RAD_TO_DEG, name, sizeof name);
        shol_band_format(&d->band, m->band_grid_label, d->limit, what, sizeof what);
        fprintf(stderr, "shol: band %s: %.0f km/h, %.1f-%.1f km/h%s (%s)%s\n", name,
                d->has_pass ? d->max_speed_mps / CORE_KMH_TO_MPS : 0.0, d->band.lo_mps / CORE_KMH_TO_MPS,
                d->band.hi_mps / CORE_KMH_TO_MPS, d->band.open_above ? " open above" : "", what,
                d->band.low_confidence ? ", LOW confidence" : "");
    }
    return 0;
}

/* The one-way envelope, the two-way one near its boundary in two-way mode,
 * and the bands. */
static int job_sweep(shol_job *j)
{
    couple_settings *cs = &j->cs;
    if (j->set.n_dirs == 0) { /* a rank beyond the directions: an empty part */
        j->r1.settings = j->r2.settings = j->set;
        return 0;
    }
    cs->mode = CORE_COUPLING_ONE_WAY;
    if (!(j->one = couple_create(j->ac, &j->sc->ship, j->db, cs, &j->log, &j->err)))
        return -1;
    /* calm air only needs no ship-only field (couple_trim) */
    if (j->set.speed_max_mps > 0 && couple_prefetch(j->one, j->set.dirs_rad, j->set.n_dirs, &j->err) != 0)
        return -1;
    progress_ctx pc = {j->tty, "one-way"};
    fprintf(stderr, "shol: %s + %s, %d directions, grid %s, %s\n", j->sc->ship.name, hfm_aircraft_name(j->ac),
            j->set.n_dirs, core_grid_name(cs->grid),
            j->mode != CORE_COUPLING_TWO_WAY ? "one-way"
            : cs->zone                       ? "two-way coupling in the deck zone"
                                             : "two-way coupling");
    if (couple_shol_one_way(j->one, &j->set, on_progress, &pc, &j->log, &j->r1, &j->err) != 0)
        return -1;
    /* each direction's band, over the two-way envelope too in two-way mode */
    if (j->mode != CORE_COUPLING_TWO_WAY)
        return job_bands(j, NULL);
    cs->mode = CORE_COUPLING_TWO_WAY;
    if (!(j->two = couple_create(j->ac, &j->sc->ship, j->db, cs, &j->log, &j->err)))
        return -1;
    pc.label = "two-way";
    if (couple_shol_two_way(j->one, j->two, &j->set, &j->r1, on_progress, &pc, &j->log, &j->r2, &j->err) != 0)
        return -1;
    cs->mode = CORE_COUPLING_ONE_WAY;
    int rc = job_bands(j, &j->r2);
    cs->mode = CORE_COUPLING_TWO_WAY;
    return rc;
}

/* The report text k (SHOL_PART_TEXTS) of a run over ranks: rank 0's own
 * (taken) and every other rank's, each under a line naming its rank; own
 * itself in a serial run. */
static char *rank_texts(shol_job *j, int k, char *own)
{
    if (j->ranks < 2 || !j->texts)
        return own;
    core_str b = {0};
    for (int r = 0; r < j->ranks; r++) {
        const char *t = r == 0 ? own : j->texts[r * SHOL_PART_TEXTS + k];
        if (!t || !*t)
            continue;
        core_str_printf(&b, "%s*Rank %d of %d:", r ? "\n" : "", r, j->ranks);
        for (int i = r; i < j->all.n_dirs; i += j->ranks) {
            char name[32];
            core_wod_name(j->all.dirs_rad[i] * CORE_RAD_TO_DEG, name, sizeof name);
            core_str_printf(&b, "%s %s", i == r ? "" : ",", name);
        }
        core_str_printf(&b, "*\n\n%s", t);
    }
    free(own);
    return core_str_take(&b);
}

/* A run over ranks: a rank other than 0 writes its part; rank 0 gathers
 * every part into the whole envelopes (then written as the serial run
 * writes them). */
static int job_ranks(shol_job *j)
{
    const shol_result *r2 = j->mode == CORE_COUPLING_TWO_WAY ? &j->r2 : NULL;
    if (j->rank > 0) {
        char *t[SHOL_PART_TEXTS] = {j->two ? couple_points_md(j->two) : NULL,
                                    j->one ? couple_shol_fields_md(j->one, j->two) : NULL};
        const char *ct[SHOL_PART_TEXTS] = {t[0], t[1]};
        int rc = shol_part_write(j->stage, j->rank, j->ranks, j->key, &j->r1, r2, ct, &j->err);
        free(t[0]);
        free(t[1]);
        if (rc == 0)
            fprintf(stderr, "shol: rank %d of %d: %d direction%s, its part in %s\n", j->rank, j->ranks,
                    j->set.n_dirs, j->set.n_dirs == 1 ? "" : "s", j->stage);
        return rc;
    }
    fprintf(stderr, "shol: rank 0 of %d: %d direction%s done; gathering the other ranks' parts in %s\n", j->ranks,
            j->set.n_dirs, j->set.n_dirs == 1 ? "" : "s", j->stage);
    if (!(j->texts = calloc((size_t)j->ranks * SHOL_PART_TEXTS, sizeof *j->texts)))
        return core_err_set(&j->err, -1, "out of memory");
    if (shol_part_gather(j->stage, j->ranks, j->key, &j->all, j->a->rank_wait_s, &j->r1,
                         r2 ? &j->r2 : NULL, j->texts, &j->err) != 0)
        return -1;
    shol_part_clean(j->stage, j->ranks);
    j->set = j->all;
    return 0;
}

/* The trim-based envelope's checks (one line each on stderr), files and
 * table on stdout. */
static int job_write(shol_job *j)
{
    char title[160];
    snprintf(title, sizeof title, "%s + %s", j->sc->ship.name, hfm_aircraft_name(j->ac));
    shol_report_info info;
    memset(&info, 0, sizeof info);
    info.title = title;
    info.scenario_path = j->a->scen;
    info.aircraft_path = j->sc->aircraft_path;
    info.grid = core_grid_name(j->cs.grid);
    info.coupling = couple_shol_coupling_text(&j->cs);
    const shol_result *main_r = j->two ? &j->r2 : &j->r1;
    char *md = rank_texts(j, 0, j->two ? couple_points_md(j->two) : NULL),
         *fmd = rank_texts(j, 1, couple_shol_fields_md(j->one, j->two));
    if (j->two) {
        info.label = "two-way coupled";
        info.compare = &j->r1;
        info.compare_label = "one-way (ship-only airwake)";
        info.coupling_md = md;
    } else {
        info.label = "one-way (ship-only airwake)";
    }
    info.fields_md = fmd;
    /* The physics checks of the main envelope (shol/checks.c). */
    shol_checks checks;
    if (shol_checks_run(main_r, hfm_aircraft_rotor_ccw(j->ac), &checks) == 0) {
        info.checks = &checks;
        for (int i = 0; i < checks.n; i++)
            fprintf(stderr, "shol: check %s: %s (%s)\n", checks.c[i].name,
                    !checks.c[i].applicable ? "not applicable" : checks.c[i].pass ? "pass" : "FAIL", checks.c[i].detail);
    }
    int rc = shol_write_all(j->outdir, main_r, &info, &j->err);
    free(md);
    free(fmd);
    if (rc != 0)
        return -1;
    printf("wod_dir_deg,max_speed_kt,limit\n");
    for (int i = 0; i < main_r->n_dirs; i++) {
        const shol_dir_result *d = &main_r->dirs[i];
        printf("%.1f,%.1f,%s\n", d->dir_rad * CORE_RAD_TO_DEG, d->max_speed_mps / CORE_KT_TO_MPS,
               shol_limit_name(d->limit));
    }
    fprintf(stderr, "shol: wrote %s/shol.csv, shol.json, shol_polar.png/.svg, trim plots and report.md\n", j->outdir);
    return 0;
}

static int job_run(shol_job *j)
{
    const shol_args *a = j->a;
    if (job_load(j) != 0 || job_open(j) != 0 || job_sweep(j) != 0)
        return -1;
    if (j->ranks > 1 && job_ranks(j) != 0)
        return -1;
    if (j->rank > 0) /* its part is written: rank 0 writes the outputs */
        return 0;
    if (!a->pilot)
        return job_write(j);
    j->cs.mode = CORE_COUPLING_ONE_WAY;
    return run_pilot(j->sc, j->ac, j->db, &j->cs, &j->set, &j->r1, a->task_path, (int)a->seeds, a->window_s,
                     a->feed_controls, j->outdir, a->scen, j->tty, &j->log, &j->err);
}

/* The run's settings in words, the same on every rank: the command line
 * without the flags that differ between ranks (NULL without memory). */
static char *run_key(int argc, char **argv)
{
    core_str b = {0};
    for (int i = 1; i < argc; i++) {
        if (i + 1 < argc && (!strcmp(argv[i], "--rank") || !strcmp(argv[i], "--rank-wait-s"))) {
            i++;
            continue;
        }
        core_str_printf(&b, "%s%s", i > 1 ? " " : "", argv[i]);
    }
    char *k = core_str_take(&b);
    if (!k)
        fprintf(stderr, "disim shol: out of memory\n");
    return k;
}

int cmd_shol(int argc, char **argv)
{
    shol_args a;
    int rc = shol_parse(argc, argv, &a);
    if (rc != 0)
        return rc;
    shol_job j;
    memset(&j, 0, sizeof j);
    j.a = &a;
    if (app_ranks_from_env(&j.rank, &j.ranks, j.run_id, sizeof j.run_id) != 0)
        return 2;
    if (a.ranks >= 0) { /* the flags over the environment */
        j.rank = (int)a.rank;
        j.ranks = (int)a.ranks;
    }
    if (a.run_id)
        snprintf(j.run_id, sizeof j.run_id, "%s", a.run_id);
    if (j.ranks > 1 && !(j.key = run_key(argc, argv)))
        return 1;
    j.tty = isatty(2);
    snprintf(j.prefix, sizeof j.prefix, j.rank > 0 ? "shol rank %d" : "shol", j.rank);
    j.al = (app_log){j.prefix, j.tty};
    j.log = (core_log){app_log_stderr, &j.al, CORE_LOG_INFO};
    rc = job_run(&j);
    if (rc != 0) {
        fprintf(stderr, "%sdisim shol%s: %s\n", j.tty ? "\r\033[K" : "", j.rank > 0 ? j.prefix + 4 : "", j.err.msg);
        if (j.rank > 0 && j.stage[0]) /* rank 0 stops waiting and names this one */
            shol_part_fail(j.stage, j.rank, j.err.msg);
    }
    for (int i = 0; j.texts && i < j.ranks * SHOL_PART_TEXTS; i++)
        free(j.texts[i]);
    free(j.texts);
    free(j.key);
    shol_result_free(&j.r1);
    shol_result_free(&j.r2);
    couple_destroy(j.two);
    couple_destroy(j.one);
    awdb_close(j.db);
    hfm_aircraft_destroy(j.ac);
    free(j.sc);
    return rc != 0 ? 1 : 0;
}
