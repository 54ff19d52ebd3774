/* cmd_airwake.c -- the CFD commands: `disim airwake` (a ship airwake with an
 * optional actuator-disk rotor, written as HDF5 + XDMF), `disim probe`
 * (velocities along a line of a field, CSV) and `disim validate` (one
 * validation case, each figure beside its reference). */
#include "awdb.h"
#include "cfd.h"
#include "foam.h"
#ifdef DISIM_HAVE_SHOL_CMD
#include "couple.h"
#include "hfm.h"
#endif
#include "cmds.h"
#include "core.h"
#include "sim.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#ifdef _OPENMP
#include <omp.h>
#endif

typedef struct progress_state {
    int tty;
    double last_print_s;
} progress_state;

/* Percent, iteration rate and time left (to the iteration limit: an upper
 * bound, since the run stops at convergence) on a terminal; a line every
 * 200 iterations otherwise. */
static int progress_print(void *user, int iter, int max_iter, double residual, double elapsed_s)
{
    progress_state *p = user;
    double rate = elapsed_s > 0.0 ? iter / elapsed_s : 0.0;
    double left = rate > 0.0 ? (max_iter - iter) / rate : 0.0;
    if (p->tty) {
        if (elapsed_s - p->last_print_s < 0.25 && iter != max_iter)
            return 0;
        p->last_print_s = elapsed_s;
        fprintf(stderr, "\r  %3.0f%%  iteration %d/%d  residual %.2e  %.1f it/s  %.0f s elapsed, at most %.0f s left   ",
                100.0 * iter / max_iter, iter, max_iter, residual, rate, elapsed_s, left);
        fflush(stderr);
    } else if (iter % 200 == 0) {
        fprintf(stderr, "  iteration %d/%d  residual %.2e  %.1f it/s  %.0f s elapsed\n", iter, max_iter, residual, rate,
                elapsed_s);
    }
    return 0;
}

static void progress_end(progress_state *p)
{
    if (p->tty)
        fprintf(stderr, "\n");
}

/* A point of --line: X,Y,Z followed by the end or ':'. */
static int parse_vec(const char *s, double v[3])
{
    const char *end;
    return core_parse_vec3(s, v, &end) == 0 && (*end == 0 || *end == ':') ? 0 : -1;
}

static int parse_double(const char *flag, const char *s, double lo, double hi, double *out)
{
    return app_parse_double("disim airwake", flag, s, lo, hi, out);
}

/* --queue: the same case as an airwake database request. */
static int queue_request(const char *db_dir, const char *engine, const awdb_key *key, const core_log *log)
{
    awdb_key k = *key;
    core_err err = {0};
    awdb *db = awdb_open(db_dir, log, &err);
    awdb_state before;
    if (!db || awdb_engine_claim(db, engine, &err) != 0 || awdb_submit(db, &k, &before, &err) != 0) {
        fprintf(stderr, "disim airwake: --queue %s: %s\n", db_dir, err.msg);
        awdb_close(db);
        return 1;
    }
    awdb_key_canon(&k, &err);
    char name[200];
    awdb_key_name(&k, name, sizeof name);
    printf("%s: %s%s\n", name, awdb_state_name(before),
           before == AWDB_ABSENT || before == AWDB_FAILED ? " -> queued" : "");
    if (!awdb_builder_alive(db))
        fprintf(stderr, "disim airwake: no builder serves %s yet: start `disim airwaked %s%s`\n", db_dir, db_dir,
                strcmp(engine, "openfoam") ? "" : " --engine openfoam");
    awdb_close(db);
    return 0;
}

/* The rotor of the scenario's aircraft in the free-air WOD (couple). */
static int rotor_from_trim(const sim_scenario *sc, double speed, double dir, int loaded, awdb_key *key,
                           const core_log *log)
{
#ifdef DISIM_HAVE_SHOL_CMD
    core_err err = {0};
    hfm_aircraft *ac = hfm_aircraft_load(sc->aircraft_path, log, &err);
    if (!ac) {
        fprintf(stderr, "disim airwake: %s\n", err.msg);
        return -1;
    }
    int rc = couple_free_air_rotor(ac, sc->station_S_m, speed, dir, loaded, key, &err);
    hfm_aircraft_destroy(ac);
    if (rc != 0)
        fprintf(stderr, "disim airwake: %s: %s\n", sc->aircraft_path, err.msg);
    return rc != 0 ? -1 : 0;
#else
    (void)speed, (void)dir, (void)loaded, (void)key, (void)log;
    fprintf(stderr, "disim airwake: %s: the rotor needs the flight model, left out of this build\n", sc->path);
    return -1;
#endif
}

static void usage_airwake(void)
{
    fprintf(stderr,
            "usage: disim airwake SCENARIO [--wod-speed-kt KT] [--wod-dir-deg DEG] [--rotor off|uniform|loaded]\n"
            "                      [--grid coarse|default|fine|quick] [--abl] [--warm FIELD.h5] [--max-iter N]\n"
            "                      [--thrust-n N] [--radius-m R] [--threads N] [--h-fine-m H]\n"
            "                      [--growth G] [--h-max-m H] [--focus-fwd-m X] [--avg-window N] [--limiter vanleer|minmod]\n"
            "                      [--zone OUTER.h5] [--engine embedded|openfoam] [--np N]\n"
            "                      [--hostfile FILE] [--work-dir DIR] -o FIELD.h5\n"
            "  --engine openfoam: solve the same case with OpenFOAM (mpirun -np N simpleFoam, N 2 by\n"
            "       default; the scenario's [cfd] engine and np otherwise; docs/openfoam.md); its ranks\n"
            "       over the hosts of an MPI --hostfile, its case in --work-dir (every host must see it)\n"
            "  --zone: solve the deck zone only (5 R round the hover station's hub, 4 R above it),\n"
            "  its open faces taken from OUTER.h5 (a whole-domain ship-only field of this ship and\n"
            "  direction, any grid) scaled to the WOD speed: a fine zone nested in a coarser field\n"
            "       disim airwake SCENARIO ... --queue DB_DIR   (queue it for `disim airwaked DB_DIR`)\n");
}

/* The command line of `disim airwake`. -1 (NAN for numbers, 0 for the
 * grid-study options): not given, the scenario's or the level's. */
typedef struct airwake_args {
    const char *scen, *out, *warm, *queue, *zone, *hostfile, *work_dir;
    double speed_kt, dir_deg, thrust_N, radius_m, h_fine_m, growth, h_max_m, focus_fwd_m;
    int rotor, level, abl, max_iter, threads, avg_window, limiter_fixed, engine, np;
    cfd_limiter limiter;
} airwake_args;

static int parse_engine(const char *v)
{
    return !strcmp(v, "embedded") ? SIM_ENGINE_EMBEDDED : !strcmp(v, "openfoam") ? SIM_ENGINE_OPENFOAM : -1;
}

static int parse_limiter(const char *v)
{
    return !strcmp(v, "vanleer") ? CFD_LIMITER_VANLEER : !strcmp(v, "minmod") ? CFD_LIMITER_MINMOD : -1;
}

/* One flag with its value v: 0, 1 after a message on a bad value, -1 not a
 * flag with a value. */
static int airwake_flag(airwake_args *o, const char *a, const char *v)
{
    double n;
    const struct {
        const char *flag;
        double lo, hi, *out;
    } num[] = {
        {"--wod-speed-kt", 0.0, 200.0, &o->speed_kt}, {"--wod-dir-deg", -360.0, 360.0, &o->dir_deg},
        {"--thrust-n", 0.0, 1e7, &o->thrust_N},       {"--radius-m", 0.1, 50.0, &o->radius_m},
        {"--h-fine-m", 0.1, 5.0, &o->h_fine_m},       /* grid studies past the three levels: the focus box's spacing */
        {"--growth", 1.01, 1.5, &o->growth},          /* grid studies: the stretching outside the focus box */
        {"--focus-fwd-m", 0.5, 500.0, &o->focus_fwd_m}, /* grid studies: the focus box's reach forward of the deck */
        {"--h-max-m", 0.1, 50.0, &o->h_max_m},
    };
    const struct {
        const char *flag;
        double lo, hi;
        int *out;
    } whole[] = {
        {"--avg-window", 2, 1e6, &o->avg_window}, /* studies of shedding fields: how long a mean the field is */
        {"--max-iter", 1, 1e6, &o->max_iter},
        {"--threads", 1, 1024, &o->threads},
        {"--np", 1, 4096, &o->np}, /* the OpenFOAM engine's MPI ranks */
    };
    const struct {
        const char *flag, *expect;
        int (*parse)(const char *);
        int *out;
    } word[] = {
        {"--rotor", "off, uniform or loaded", core_rotor_parse, &o->rotor},
        {"--grid", "coarse, default, fine or quick", core_grid_parse_any, &o->level},
        {"--engine", "embedded or openfoam", parse_engine, &o->engine},
        {"--limiter", "vanleer or minmod", parse_limiter, NULL}, /* grid studies: one convection scheme on every grid */
    };
    const struct {
        const char *flag;
        const char **out;
    } str[] = {{"-o", &o->out},     {"--queue", &o->queue},       {"--warm", &o->warm},
               {"--zone", &o->zone}, {"--hostfile", &o->hostfile}, {"--work-dir", &o->work_dir}};
    for (size_t k = 0; k < sizeof num / sizeof num[0]; k++)
        if (!strcmp(a, num[k].flag))
            return parse_double(a, v, num[k].lo, num[k].hi, num[k].out) ? 1 : 0;
    for (size_t k = 0; k < sizeof whole / sizeof whole[0]; k++)
        if (!strcmp(a, whole[k].flag)) {
            if (parse_double(a, v, whole[k].lo, whole[k].hi, &n))
                return 1;
            *whole[k].out = (int)n;
            return 0;
        }
    for (size_t k = 0; k < sizeof word / sizeof word[0]; k++)
        if (!strcmp(a, word[k].flag)) {
            int c = word[k].parse(v);
            if (word[k].out)
                *word[k].out = c;
            else { /* --limiter */
                o->limiter_fixed = 1;
                if (c >= 0)
                    o->limiter = (cfd_limiter)c;
            }
            if (c >= 0)
                return 0;
            fprintf(stderr, "%s: expected %s, got '%s'\n", a, word[k].expect, v);
            return 1;
        }
    for (size_t k = 0; k < sizeof str / sizeof str[0]; k++)
        if (!strcmp(a, str[k].flag)) {
            *str[k].out = v;
            return 0;
        }
    return -1;
}

/* 0 ok, 1 bad value (printed), 2 usage. */
static int airwake_parse(int argc, char **argv, airwake_args *o)
{
    memset(o, 0, sizeof *o);
    o->speed_kt = o->dir_deg = o->thrust_N = o->radius_m = NAN;
    o->rotor = o->level = o->engine = -1;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        int rc = i + 1 < argc ? airwake_flag(o, a, argv[i + 1]) : -1;
        if (rc > 0)
            return rc;
        if (rc == 0)
            i++;
        else if (!strcmp(a, "--abl"))
            o->abl = 1;
        else if (a[0] != '-' && !o->scen)
            o->scen = a;
        else {
            fprintf(stderr, "disim airwake: unknown or incomplete argument '%s'\n", a);
            usage_airwake();
            return 2;
        }
    }
    if (!o->scen || (!o->out && !o->queue)) {
        usage_airwake();
        return 2;
    }
    /* a grading of its own outside the focus box (grid studies) */
    const int graded = o->growth > 0.0 || o->h_max_m > 0.0 || o->focus_fwd_m > 0.0;
    if ((o->h_fine_m > 0.0 || graded || o->limiter_fixed || o->zone || o->avg_window) && o->queue) {
        /* the database keys fields by grid level; a spacing of its own
         * would put a field under a level it was not solved on */
        fprintf(stderr, "disim airwake: --h-fine-m, --growth, --h-max-m, --focus-fwd-m, --avg-window, --limiter and "
                        "--zone write a field (-o), they cannot be queued (--queue)\n");
        return 2;
    }
    return 0;
}

/* The database key of the case: the scenario's ship at the WOD, and with
 * the rotor on the disk of its aircraft trimmed in the free-air WOD at the
 * hover-over-spot station (thrust, hub, shaft tilt and, loaded, its blade
 * loads: the coupling loop's first step), --thrust-n and --radius-m
 * overriding. 0, or 1 (printed). */
static int airwake_key(const sim_scenario *sc, const airwake_args *o, double speed, double dir,
                       core_rotor_mode rotor, core_grid_level level, awdb_key *key, const core_log *log)
{
    awdb_key_ship_only(key, sc->ship.name, NULL, speed, dir, level);
    if (rotor == CORE_ROTOR_OFF)
        return 0;
    snprintf(key->aircraft, sizeof key->aircraft, "%.63s", sc->aircraft_name);
    if (rotor_from_trim(sc, speed, dir, rotor == CORE_ROTOR_LOADED, key, log) != 0)
        return 1;
    if (!isnan(o->thrust_N))
        key->thrust_N = o->thrust_N;
    if (!isnan(o->radius_m))
        key->radius_m = o->radius_m;
    core_err err = {0};
    if (awdb_key_canon(key, &err) != 0) {
        fprintf(stderr, "disim airwake: %s\n", err.msg);
        return 1;
    }
    fprintf(stderr, "rotor: %s disk, thrust %.0f N, radius %.2f m, hub (%.2f, %.2f, %.2f) m in S, shaft pitch %.1f deg, roll %.1f deg\n",
            core_rotor_name(rotor), key->thrust_N, key->radius_m, key->station_S_m[0], key->station_S_m[1],
            key->station_S_m[2], key->shaft_pitch_rad * CORE_RAD_TO_DEG, key->shaft_roll_rad * CORE_RAD_TO_DEG);
    if (rotor == CORE_ROTOR_LOADED)
        fprintf(stderr, "rotor: torque %.0f N m, root cut %.3f R, %s from above\n", key->torque_Nm, key->root_cut,
                key->ccw_from_above ? "counter-clockwise" : "clockwise");
    return 0;
}

/* --zone: the outer field, checked to be a ship-only field of this ship
 * and direction; the spec's zone set from it (its box, with the rotor off,
 * round the hub of the free-air hover trim, of the rotor's radius). NULL
 * after printing why. */
static cfd_field *airwake_zone(const sim_scenario *sc, const airwake_args *o, const awdb_key *key,
                               cfd_airwake_spec *sp, const core_log *log)
{
    if (key->rotor == CORE_ROTOR_OFF) {
        awdb_key hub = *key;
        snprintf(hub.aircraft, sizeof hub.aircraft, "%.63s", sc->aircraft_name);
        if (rotor_from_trim(sc, key->wod_speed_mps, key->wod_dir_rad, 0, &hub, log) != 0)
            return NULL;
        memcpy(sp->disk.centre_m, hub.station_S_m, sizeof sp->disk.centre_m);
        sp->disk.radius_m = hub.radius_m;
    }
    core_err err = {0};
    cfd_field *outer = cfd_field_load(o->zone, &err);
    const cfd_meta *om = outer ? cfd_field_meta(outer) : NULL;
    const char *why = !outer                                 ? err.msg
                      : strcmp(om->rotor, core_rotor_name(CORE_ROTOR_OFF)) != 0 ? "expected a ship-only field (rotor off)"
                      : strcmp(om->ship, sc->ship.name) != 0 ? "another ship's field"
                      : !(om->wod_speed_mps > 0.0)           ? "no WOD speed in the field"
                      : fabs(core_wod_wrap_deg(om->wod_dir_deg - key->wod_dir_rad * CORE_RAD_TO_DEG)) > 0.05
                          ? "another WOD direction's field"
                          : NULL;
    if (why) {
        fprintf(stderr, "disim airwake: --zone %s: %s\n", o->zone, why);
        cfd_field_destroy(outer);
        return NULL;
    }
    sp->zone = 1;
    sp->zone_field = outer;
    sp->zone_scale = key->wod_speed_mps / om->wod_speed_mps;
    return outer;
}

/* The field's grid attribute: the level's name, or the study's spacing,
 * its grading, the scheme when forced and the zone. */
static void airwake_grid_name(const airwake_args *o, core_grid_level level, char *buf, size_t n)
{
    char base[48];
    if (o->h_fine_m > 0.0)
        snprintf(base, sizeof base, "h%.3f m", o->h_fine_m);
    else
        snprintf(base, sizeof base, "%s", core_grid_name(level));
    if (o->growth > 0.0 || o->h_max_m > 0.0 || o->focus_fwd_m > 0.0) {
        size_t nb = strlen(base);
        snprintf(base + nb, sizeof base - nb, " g%.2f hm%.0f ff%.0f", o->growth > 0.0 ? o->growth : CFD_GRID_GROWTH,
                 o->h_max_m, o->focus_fwd_m);
    }
    snprintf(buf, n, "%s%s%s", base,
             !o->limiter_fixed ? "" : o->limiter == CFD_LIMITER_VANLEER ? " vanleer" : " minmod",
             o->zone ? " zone" : "");
}

/* The field's metadata but for the result. */
static void airwake_meta(const airwake_args *o, const cfd_airwake_spec *sp, const awdb_key *key, cfd_meta *meta)
{
    memset(meta, 0, sizeof *meta);
    meta->wod_speed_mps = key->wod_speed_mps;
    meta->wod_dir_deg = key->wod_dir_rad * CORE_RAD_TO_DEG;
    snprintf(meta->ship, sizeof meta->ship, "%s", sp->ship->name);
    snprintf(meta->rotor, sizeof meta->rotor, "%s", core_rotor_name(key->rotor));
    if (key->rotor != CORE_ROTOR_OFF) {
        meta->rotor_thrust_N = key->thrust_N;
        meta->rotor_radius_m = key->radius_m;
        memcpy(meta->rotor_centre_S_m, key->station_S_m, sizeof meta->rotor_centre_S_m);
    }
    airwake_grid_name(o, key->grid, meta->grid, sizeof meta->grid);
}

/* OpenFOAM's progress: its iteration and p residual (no known end: it
 * stops at convergence or once the monitors are steady). */
static int foam_progress(void *user, double frac, double residual, int iter)
{
    progress_state *p = user;
    (void)frac;
    if (p->tty)
        fprintf(stderr, "\r  openfoam: iteration %d  p residual %.2e   ", iter, residual);
    else if (iter >= p->last_print_s + 200) {
        p->last_print_s = iter;
        fprintf(stderr, "  openfoam: iteration %d  p residual %.2e\n", iter, residual);
    }
    return 0;
}

/* The same case through OpenFOAM (foam.h) with np MPI ranks; the loaded
 * rotor as rotorDisk with the blades of the aircraft file. 0 or 1. */
static int airwake_solve_foam(const airwake_args *o, const cfd_airwake_spec *sp, const awdb_key *key, int np,
                              const char *aircraft_path, const core_log *log)
{
    foam_opts fo;
    foam_opts_default(&fo);
    core_err err = {0};
    hfm_blade_data blades;
    if (sp->rotor == CORE_ROTOR_LOADED) {
        hfm_aircraft *ac = hfm_aircraft_load(aircraft_path, log, &err);
        if (!ac) {
            fprintf(stderr, "disim airwake: %s\n", err.msg);
            return 1;
        }
        hfm_aircraft_blade_data(ac, &blades);
        hfm_aircraft_destroy(ac);
        fo.blades = &blades;
    }
    fo.np = np;
    fo.log = log;
    fo.hostfile = o->hostfile;
    fo.work_dir = o->work_dir;
    fo.max_iter = sp->max_iter;
    progress_state ps = {isatty(2), 0.0};
    fo.progress = foam_progress;
    fo.progress_user = &ps;
    cfd_meta meta;
    airwake_meta(o, sp, key, &meta);
    foam_result r;
    int rc = foam_airwake(sp, &fo, &meta, o->out, &r, &err);
    progress_end(&ps);
    if (rc) {
        fprintf(stderr, "disim airwake: %s (nothing written)\n", rc > 0 ? "stopped" : err.msg);
        return 1;
    }
    fprintf(stderr,
            "disim airwake: wrote %s (OpenFOAM %s, %d rank%s, %zu cells, %d iterations, %s; simpleFoam %.1f s, "
            "every step %.1f s)\n",
            o->out, r.version, np, np > 1 ? "s" : "", r.cells, r.res.iterations,
            r.res.converged ? "converged" : r.steady_iter > 0 ? "monitors steady, residuals above 1e-4"
                                                              : "not converged (the iteration cap)",
            r.res.wall_s, r.total_wall_s);
    if (fo.blades)
        fprintf(stderr,
                "disim airwake: rotorDisk on %zu cells: thrust %.0f N for %.0f N (%+.2f %%); trim %s: theta0 %.2f deg, "
                "theta1c %.2f deg, theta1s %.2f deg\n",
                r.rotor_cells, r.rotor_force_N, sp->disk.thrust_N, 100.0 * (r.rotor_force_N / sp->disk.thrust_N - 1.0),
                r.trim_converged ? "converged" : "not converged", r.trim_pitch_deg[0], r.trim_pitch_deg[1],
                r.trim_pitch_deg[2]);
    return 0;
}

/* Solve the spec (warm-started from --warm) and write the field. 0 or 1. */
static int airwake_solve(const airwake_args *o, const cfd_airwake_spec *sp, const awdb_key *key,
                         const core_log *log)
{
    core_err err = {0};
    progress_state ps = {isatty(2), -1.0};
    cfd_solver *s = cfd_airwake_create(sp, log, progress_print, &ps, &err);
    if (!s) {
        fprintf(stderr, "disim airwake: %s\n", err.msg);
        return 1;
    }
    if (o->warm) {
        cfd_field *f = cfd_field_load(o->warm, &err);
        int bad = !f || cfd_solver_init_from_field(s, f, &err);
        cfd_field_destroy(f);
        if (bad) {
            fprintf(stderr, "disim airwake: warm start: %s\n", err.msg);
            cfd_solver_destroy(s);
            return 1;
        }
    }
    cfd_result res;
    int rc = cfd_solver_run(s, &res, &err);
    progress_end(&ps);
    if (rc < 0) {
        fprintf(stderr, "disim airwake: %s (nothing written)\n", err.msg);
        cfd_solver_destroy(s);
        return 1;
    }
    if (rc > 0)
        fprintf(stderr, "disim airwake: warning: not converged after %d iterations (residuals %.2e); the field is "
                        "written with converged = 0\n",
                res.iterations, res.residual[0]);
    cfd_meta meta;
    airwake_meta(o, sp, key, &meta);
    meta.result = res;
    rc = cfd_solver_write(s, &meta, o->out, &err);
    cfd_solver_destroy(s);
    if (rc) {
        fprintf(stderr, "disim airwake: %s\n", err.msg);
        return 1;
    }
    fprintf(stderr, "disim airwake: wrote %s (%d iterations, %.1f s, %s)\n", o->out, res.iterations, res.wall_s,
            res.converged ? "converged" : "not converged");
    return 0;
}

int cmd_airwake(int argc, char **argv)
{
    airwake_args o;
    int rc = airwake_parse(argc, argv, &o);
    if (rc)
        return rc;
#ifdef _OPENMP
    if (o.threads > 0)
        omp_set_num_threads(o.threads);
#endif
    sim_scenario *sc = malloc(sizeof *sc);
    if (!sc)
        return 1;
    core_err err = {0};
    if (sim_scenario_load(o.scen, sc, &err)) {
        fprintf(stderr, "disim airwake: %s\n", err.msg);
        free(sc);
        return 1;
    }
    double speed = isnan(o.speed_kt) ? sc->wod_speed_mps : o.speed_kt * CORE_KT_TO_MPS;
    double dir = isnan(o.dir_deg) ? sc->wod_dir_rad : core_wod_wrap_deg(o.dir_deg) * CORE_DEG_TO_RAD;
    core_rotor_mode rotor = o.rotor >= 0 ? (core_rotor_mode)o.rotor : sc->rotor;
    core_grid_level level = o.level >= 0 ? (core_grid_level)o.level : sc->grid;
    if (!(speed > 0.0) && (isnan(o.speed_kt) || rotor == CORE_ROTOR_OFF)) {
        fprintf(stderr, "disim airwake: %s: %s\n", o.scen,
                isnan(o.speed_kt) ? "no single WOD speed; give --wod-speed-kt"
                                  : "a WOD speed of 0 needs the rotor (--rotor uniform|loaded)");
        free(sc);
        return 1;
    }
    app_log al = {NULL, 0};
    core_log log = {app_log_stderr, &al, CORE_LOG_INFO};
    awdb_key key;
    if (airwake_key(sc, &o, speed, dir, rotor, level, &key, &log) != 0) {
        free(sc);
        return 1;
    }
    int engine = o.engine >= 0 ? o.engine : sc->engine;
    int np = o.np > 0 ? o.np : sc->engine_np > 0 ? sc->engine_np : 2;
    const char *clash = engine != SIM_ENGINE_OPENFOAM && o.np > 0 ? "--np is the OpenFOAM engine's (--engine openfoam)"
                        : engine != SIM_ENGINE_OPENFOAM && (o.hostfile || o.work_dir)
                            ? "--hostfile and --work-dir are the OpenFOAM engine's (--engine openfoam)"
                        : o.queue && (o.hostfile || o.work_dir)
                            ? "--hostfile and --work-dir with --queue: the builder has its own (disim airwaked)"
                        : engine == SIM_ENGINE_OPENFOAM && o.queue && o.np > 0
                            ? "--np with --queue: the database's builder runs its own ranks (disim airwaked --np)"
                        : engine == SIM_ENGINE_OPENFOAM && o.warm ? "--warm: the OpenFOAM engine starts from the inflow"
                                                                  : NULL;
    if (clash) {
        fprintf(stderr, "disim airwake: %s\n", clash);
        free(sc);
        return 2;
    }
    if (o.queue) {
        rc = queue_request(o.queue, engine == SIM_ENGINE_OPENFOAM ? "openfoam" : "embedded", &key, &log);
        free(sc);
        return rc;
    }
    /* the builder's case for this key (awdb_key_spec), so that the field
     * written here is the one the builder would put in the database, with
     * the grid-study options on top */
    cfd_airwake_spec sp;
    if (awdb_key_spec(&key, &sc->ship, &sp, &err) != 0) {
        fprintf(stderr, "disim airwake: %s\n", err.msg);
        free(sc);
        return 1;
    }
    sp.abl = o.abl;
    sp.max_iter = o.max_iter > 0 ? o.max_iter : sc->max_iterations;
    sp.h_fine_m = o.h_fine_m;
    sp.growth = o.growth;
    sp.h_max_m = o.h_max_m;
    sp.focus_fwd_m = o.focus_fwd_m;
    sp.limiter_fixed = o.limiter_fixed;
    sp.limiter = o.limiter;
    sp.avg_window = o.avg_window;
    cfd_field *outer = NULL; /* the zone's boundary; outlives the solver */
    if (o.zone && !(outer = airwake_zone(sc, &o, &key, &sp, &log))) {
        free(sc);
        return 1;
    }
    rc = engine == SIM_ENGINE_OPENFOAM ? airwake_solve_foam(&o, &sp, &key, np, sc->aircraft_path, &log) : airwake_solve(&o, &sp, &key, &log);
    cfd_field_destroy(outer);
    free(sc);
    return rc;
}

int cmd_probe(int argc, char **argv)
{
    const char *path = NULL, *line = NULL;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--line") && i + 1 < argc)
            line = argv[++i];
        else if (argv[i][0] != '-' && !path)
            path = argv[i];
        else {
            fprintf(stderr, "disim probe: unknown or incomplete argument '%s'\n", argv[i]);
            path = NULL;
            break;
        }
    }
    if (!path || !line) {
        fprintf(stderr, "usage: disim probe FIELD.h5 --line X0,Y0,Z0:X1,Y1,Z1:N   (ship frame S, metres)\n");
        return 2;
    }
    double p0[3], p1[3];
    const char *c1 = strchr(line, ':');
    const char *c2 = c1 ? strchr(c1 + 1, ':') : NULL;
    char *end = NULL;
    long n = c2 ? strtol(c2 + 1, &end, 10) : 0;
    if (!c1 || !c2 || parse_vec(line, p0) || parse_vec(c1 + 1, p1) || !end || *end || n < 1 || n > 1000000) {
        fprintf(stderr, "disim probe: --line: expected X0,Y0,Z0:X1,Y1,Z1:N with N in [1, 1000000], got '%s'\n", line);
        return 1;
    }
    core_err err = {0};
    cfd_field *f = cfd_field_load(path, &err);
    if (!f) {
        fprintf(stderr, "disim probe: %s\n", err.msg);
        return 1;
    }
    printf("x_m,y_m,z_m,u_mps,v_mps,w_mps,k_m2ps2\n");
    int outside = 0;
    for (long i = 0; i < n; i++) {
        double t = n > 1 ? (double)i / (n - 1) : 0.0, p[3], o[CFD_NVARS];
        for (int d = 0; d < 3; d++)
            p[d] = p0[d] + t * (p1[d] - p0[d]);
        outside |= cfd_field_sample(f, p, o);
        printf("%.4f,%.4f,%.4f,%.5f,%.5f,%.5f,%.6f\n", p[0], p[1], p[2], o[CFD_VAR_U], o[CFD_VAR_V], o[CFD_VAR_W],
               o[CFD_VAR_K]);
    }
    if (outside)
        fprintf(stderr, "disim probe: warning: part of the line is outside the field; values there are clamped\n");
    cfd_field_destroy(f);
    /* a full disk or a closed pipe must not look like a complete profile */
    if (fflush(stdout) != 0 || ferror(stdout)) {
        fprintf(stderr, "disim probe: cannot write the profile to standard output: %s\n", strerror(errno));
        return 1;
    }
    return 0;
}

int cmd_validate(int argc, char **argv)
{
    const char *name = NULL, *data = NULL;
    int small = 0, threads = 0;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--small"))
            small = 1;
        else if (!strcmp(argv[i], "--data") && i + 1 < argc)
            data = argv[++i];
        else if (!strcmp(argv[i], "--threads") && i + 1 < argc) {
            double t;
            if (parse_double("--threads", argv[++i], 0, 256, &t))
                return 2;
            if (t != (int)t) {
                fprintf(stderr, "--threads: expected a whole number 0 (the default) to 256, got '%s'\n", argv[i]);
                return 2;
            }
            threads = (int)t;
        }
        else if (argv[i][0] != '-' && !name)
            name = argv[i];
        else {
            name = NULL;
            break;
        }
    }
    if (!name) {
        fprintf(stderr, "usage: disim validate CASE [--small] [--data DIR] [--threads N]\n  cases:");
        for (int i = 0; cfd_validate_cases[i]; i++)
            fprintf(stderr, " %s", cfd_validate_cases[i]);
        fprintf(stderr, "\n");
        return 2;
    }
#ifdef _OPENMP
    if (threads > 0)
        omp_set_num_threads(threads);
#endif
    app_log al = {NULL, 0};
    core_log log = {app_log_stderr, &al, CORE_LOG_INFO};
    progress_state ps = {isatty(2), -1.0};
    cfd_report *rep = malloc(sizeof *rep);
    if (!rep)
        return 1;
    core_err err = {0};
    int rc = cfd_validate(name, small, data, NULL, &log, progress_print, &ps, rep, &err);
    progress_end(&ps);
    if (rc) {
        fprintf(stderr, "disim validate: %s\n", err.msg);
        free(rep);
        return 1;
    }
    printf("%-46s %12s %12s %10s  %s\n", "figure", "measured", "reference", "tolerance", "result");
    for (int i = 0; i < rep->n; i++)
        printf("%-46s %12.4f %12.4f %10.4f  %s\n", rep->c[i].name, rep->c[i].measured, rep->c[i].reference,
               rep->c[i].tol, rep->c[i].pass ? "pass" : "FAIL");
    printf("%s: %d passed, %d failed\n", name, rep->passed, rep->failed);
    int failed = rep->failed;
    free(rep);
    return failed ? 1 : 0;
}
