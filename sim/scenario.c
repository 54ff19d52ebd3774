/* scenario.c -- scenario files: parse with the core INI reader, check every
 * key against its type and range, resolve the referenced aircraft and ship
 * files, and refuse anything unknown. Every error names file, line and key.
 *
 * Every key that is accepted acts in some command (scenarios/README.md says
 * which). Keys that a later part of disim will read are refused with the
 * reason, not read and ignored: a user who writes `[cfd] residual_tol` must
 * not believe it acted. */
#include "sim.h"

#include <math.h>
#include <string.h>

/* The aircraft file is owned by hfm; here only its identity is read so that a
 * scenario names a real aircraft. hfm_aircraft_load checks the physics. */
static int peek_aircraft(const char *path, char *name, size_t n, core_err *err)
{
    core_ini *ini = core_ini_load(path, err);
    if (!ini)
        return -1;
    int rc = core_ini_get_name(ini, "aircraft", "name", 1, name, n, err);
    core_ini_destroy(ini);
    return rc;
}

static int wod_section(core_ini *ini, sim_scenario *sc, core_err *err)
{
    const char *W = "wod";
    int mode = 0, rc;
    if ((rc = core_ini_get_enum(ini, W, "mode", 1, "single|sweep", &mode, err)))
        return rc;
    sc->wod_mode = (sim_wod_mode)mode;
    if (sc->wod_mode == SIM_WOD_SINGLE) {
        double kt = 0, dir = 0;
        if ((rc = core_ini_get_double(ini, W, "speed_kt", 1, 0.0, 80.0, &kt, err)) ||
            (rc = core_ini_get_double(ini, W, "dir_deg", 1, -180.0, 180.0, &dir, err)))
            return rc;
        sc->wod_speed_mps = kt * CORE_KT_TO_MPS;
        sc->wod_dir_rad = core_wod_wrap_deg(dir) * CORE_DEG_TO_RAD;
        sc->n_dirs = 1;
        sc->dirs_rad[0] = sc->wod_dir_rad;
        return 0;
    }
    char range[128];
    if ((rc = core_ini_get_string(ini, W, "dir_deg", 1, range, sizeof range, err)))
        return rc;
    double dirs[SIM_MAX_WOD];
    int nd = 0;
    /* nd is checked too, defensively: disim shol copies n_dirs directions
     * (core_parse_range itself refuses more than nmax) */
    if (core_parse_range(range, dirs, SIM_MAX_WOD, &nd) != 0 || nd < 1 || nd > SIM_MAX_WOD)
        return core_err_set(err, -1,
                            "%s:%d: [wod] dir_deg = '%s': expected START:STOP:STEP in degrees "
                            "(e.g. -90:90:30; STOP >= START, STEP > 0, at most %d directions) "
                            "or one number",
                            core_ini_path(ini), core_ini_find(ini, W, "dir_deg")->line, range,
                            SIM_MAX_WOD);
    int kept = 0;
    for (int i = 0; i < nd; i++) {
        if (dirs[i] < -180.0 || dirs[i] > 180.0)
            return core_err_set(err, -1, "%s:%d: [wod] dir_deg: %g out of range, expected -180 to 180",
                                core_ini_path(ini), core_ini_find(ini, W, "dir_deg")->line, dirs[i]);
        /* -180 and 180 are one direction (the stern): a full circle
         * -180:180:30 sweeps it once, not twice */
        double d = core_wod_wrap_deg(dirs[i]) * CORE_DEG_TO_RAD;
        int dup = 0;
        for (int j = 0; j < kept; j++)
            dup |= fabs(sc->dirs_rad[j] - d) < 1e-9;
        if (!dup)
            sc->dirs_rad[kept++] = d;
    }
    sc->n_dirs = kept;
    double step = 5.0, max = 150.0;
    if ((rc = core_ini_get_double(ini, W, "speed_step_kmh", 0, 0.5, 50.0, &step, err)) < 0 ||
        (rc = core_ini_get_double(ini, W, "speed_max_kmh", 0, 5.0, 300.0, &max, err)) < 0)
        return rc;
    if (step > max) {
        const core_ini_entry *e = core_ini_find(ini, W, "speed_step_kmh");
        return core_err_set(err, -1, "%s:%d: [wod] speed_step_kmh = %g: expected at most speed_max_kmh (%g)",
                            core_ini_path(ini), e ? e->line : 0, step, max);
    }
    sc->speed_step_mps = step * CORE_KMH_TO_MPS;
    sc->speed_max_mps = max * CORE_KMH_TO_MPS;
    return 0;
}

/* Keys and values that no command acts on, with the reason. key NULL: the
 * whole section; value NULL: any value. */
static const struct {
    const char *section, *key, *value, *why;
} refused[] = {
    {"task", "approach_dir_deg", NULL,
     "not supported: the approach is the task file's, in its phases (scenarios/tasks/land_port.ini); "
     "remove the key and give [task] file"},
    {"cfd", "residual_tol", NULL,
     "not supported: every airwake field is solved to the embedded solver's own convergence "
     "test (normalised residuals below 1e-4 with steady monitor velocities), which the "
     "airwake database does not record per field; remove the key"},
    {"output", "csv", NULL,
     "not supported: disim shol always writes its CSV table, JSON, plots and report; remove "
     "the key"},
    {"output", "plots", NULL,
     "not supported: disim shol always writes its CSV table, JSON, plots and report; remove "
     "the key"},
};

/* The first refused entry in file order, so that the message names the
 * line a user reads first. */
static int refused_keys(const core_ini *ini, core_err *err)
{
    for (size_t i = 0; i < core_ini_count(ini); i++) {
        const core_ini_entry *e = core_ini_at(ini, i);
        for (size_t j = 0; j < sizeof refused / sizeof refused[0]; j++) {
            if (strcmp(e->section, refused[j].section) != 0 ||
                (refused[j].key && strcmp(e->key, refused[j].key) != 0) ||
                (refused[j].value && strcmp(e->value, refused[j].value) != 0))
                continue;
            if (refused[j].value)
                return core_err_set(err, -1, "%s:%d: [%s] %s = %s: %s", core_ini_path(ini),
                                    e->line, e->section, e->key, e->value, refused[j].why);
            return core_err_set(err, -1, "%s:%d: [%s] %s: %s", core_ini_path(ini), e->line,
                                e->section, e->key, refused[j].why);
        }
    }
    return 0;
}

/* A key that belongs to another mode than the one chosen (speed_kt in a
 * sweep, coupled_domain with the one-way coupling) would otherwise be
 * reported as an "unknown key", though the README lists it: say which mode
 * it needs. */
static int mode_keys(const core_ini *ini, core_err *err)
{
    static const struct {
        const char *section, *key, *needs;
    } k[] = {
        {"wod", "speed_kt", "mode = single"},
        {"wod", "speed_step_kmh", "mode = sweep"},
        {"wod", "speed_max_kmh", "mode = sweep"},
        /* disim shol solves the deck zone only for coupled points */
        {"cfd", "coupled_domain", "coupling = two-way"},
        /* the embedded engine's threads are OpenMP's */
        {"cfd", "np", "engine = openfoam"},
        {"task", "file", "type = hover or landing"},
        {"pilot", "stations", "type = station"},
        {"pilot", "hold_after_s", "type = station"},
        {"pilot", "log", "type = replay"},
        {"pilot", "feed_controls", "type = replay"},
    };
    for (size_t i = 0; i < sizeof k / sizeof k[0]; i++) {
        const core_ini_entry *e = core_ini_find(ini, k[i].section, k[i].key);
        if (e && !e->used)
            return core_err_set(err, -1, "%s:%d: [%s] %s: only used with %s; remove it or set %s",
                                core_ini_path(ini), e->line, k[i].section, k[i].key, k[i].needs,
                                k[i].needs);
    }
    return 0;
}

/* A scenario's [task] type's name (SIM_TASK_*). */
static const char *task_name(int task)
{
    return task == SIM_TASK_STATION_KEEP ? "hover" : task == SIM_TASK_LAND ? "landing" : "shol";
}

/* [task] and [pilot]: shol (the trims), or a piloted hover or landing
 * (its task file) for the automated pilot; the stations, the replay
 * pilot. 0, or the failing reader's code. */
static int task_pilot_sections(core_ini *ini, sim_scenario *sc, core_err *err)
{
    int rc, v = 0;
    if ((rc = core_ini_get_enum(ini, "task", "type", 0, "shol|hover|landing", &v, err)) < 0)
        return rc;
    static const int task_of[] = {SIM_TASK_SHOL, SIM_TASK_STATION_KEEP, SIM_TASK_LAND}; /* as the names */
    sc->task_type = rc == 0 ? task_of[v] : SIM_TASK_SHOL;
    if (sc->task_type != SIM_TASK_SHOL &&
        (rc = core_ini_get_path(ini, "task", "file", 1, sc->task_path, sizeof sc->task_path, err)))
        return rc;
    /* pilot (disim fly): the stations, the automated pilot, the replay pilot */
    if ((rc = core_ini_get_enum(ini, "pilot", "type", 0, "station|auto|replay", &v, err)) < 0)
        return rc;
    sc->pilot = rc == 0 ? v : SIM_SC_PILOT_STATION;
    if (sc->pilot == SIM_SC_PILOT_STATION) {
        if ((rc = core_ini_get_string(ini, "pilot", "stations", 0, sc->pilot_stations, sizeof sc->pilot_stations,
                                      err)) < 0 ||
            (rc = core_ini_get_double(ini, "pilot", "hold_after_s", 0, 0.01, 60.0, &sc->pilot_hold_after_s, err)) < 0)
            return rc;
        sim_pilots_opts po;
        core_err e2 = {0};
        if (sc->pilot_stations[0] && sim_pilots_opts_parse(&po, sc->pilot_stations, &e2) != 0)
            return core_err_set(err, -1, "%s:%d: [pilot] stations: %s", core_ini_path(ini),
                                core_ini_find(ini, "pilot", "stations")->line, e2.msg);
    } else if (sc->pilot == SIM_SC_PILOT_REPLAY) {
        if ((rc = core_ini_get_path(ini, "pilot", "log", 1, sc->pilot_log, sizeof sc->pilot_log, err)) ||
            (rc = core_ini_get_bool(ini, "pilot", "feed_controls", 0, &sc->pilot_feed_controls, err)) < 0)
            return rc;
    }
    /* the piloted task is the automated pilot's; the automated pilot needs one */
    if ((sc->pilot == SIM_SC_PILOT_AUTO) != (sc->task_type != SIM_TASK_SHOL)) {
        const core_ini_entry *e = sc->pilot == SIM_SC_PILOT_AUTO ? core_ini_find(ini, "pilot", "type")
                                                                 : core_ini_find(ini, "task", "type");
        return core_err_set(err, -1,
                            sc->pilot == SIM_SC_PILOT_AUTO
                                ? "%s:%d: [pilot] type = auto: the automated pilot flies the scenario's task; set "
                                  "[task] type = hover or landing with its file"
                                : "%s:%d: [task] type = %s: a piloted task is flown by the automated pilot; set "
                                  "[pilot] type = auto (the stations and the replay pilot fly no task file)",
                            core_ini_path(ini), e ? e->line : 0, task_name(sc->task_type));
    }
    sc->hover_height_m = 5.0;
    if ((rc = core_ini_get_double(ini, "task", "hover_height_m", 0, 0.5, 100.0,
                                  &sc->hover_height_m, err)) < 0)
        return rc;
    sc->station_S_m[0] = 0.0;
    sc->station_S_m[1] = 0.0;
    sc->station_S_m[2] = -sc->hover_height_m;
    return 0;
}

/* [sea]: the ship's motion in disim fly (sim_ship_motion); the trims of
 * disim shol are on a ship at rest and refuse a sea state above 0
 * (couple_shol_settings_scenario). And [wod] turbulence: the air's
 * turbulence in disim fly (the trims are in the mean air). */
static int sea_section(core_ini *ini, sim_scenario *sc, core_err *err)
{
    int rc, v = 0;
    long state = 0;
    if ((rc = core_ini_get_int(ini, "sea", "state", 0, 0, 6, &state, err)) < 0)
        return rc;
    sim_sea_default(&sc->sea);
    sc->sea.state = (int)state;
    double kt = 0.0, wave_deg = 0.0;
    if ((rc = core_ini_get_double(ini, "sea", "ship_speed_kt", 0, 0.0, 40.0, &kt, err)) < 0 ||
        (rc = core_ini_get_double(ini, "sea", "wave_dir_deg", 0, -180.0, 180.0, &wave_deg, err)) < 0)
        return rc;
    sc->sea.ship_speed_mps = kt * CORE_KT_TO_MPS;
    sc->sea.wave_dir_rad = wave_deg * CORE_DEG_TO_RAD;
    if ((rc = core_ini_get_enum(ini, "sea", "spectrum", 0, "ittc|jonswap", &v, err)) < 0)
        return rc;
    if (rc == 0)
        sc->sea.spectrum = v ? SIM_SPECTRUM_JONSWAP : SIM_SPECTRUM_ITTC;
    sc->turbulence = 1;
    if ((rc = core_ini_get_bool(ini, "wod", "turbulence", 0, &sc->turbulence, err)) < 0)
        return rc;
    return 0;
}

/* [cfd]: the embedded engine's grid, rotor, coupling, deck zone and
 * iteration limit. */
static int cfd_section(core_ini *ini, sim_scenario *sc, core_err *err)
{
    int rc, v = 0;
    long it = 0;
    sc->grid = CORE_GRID_DEFAULT;
    sc->rotor = CORE_ROTOR_UNIFORM;
    if ((rc = core_ini_get_enum(ini, "cfd", "engine", 0, "embedded|openfoam", &v, err)) < 0)
        return rc;
    sc->engine = rc == 0 && v == 1 ? SIM_ENGINE_OPENFOAM : SIM_ENGINE_EMBEDDED;
    /* np: the OpenFOAM engine's MPI ranks (the embedded engine's threads
     * are OpenMP's: mode_keys refuses np there) */
    if (sc->engine == SIM_ENGINE_OPENFOAM) {
        if ((rc = core_ini_get_int(ini, "cfd", "np", 0, 1, 4096, &it, err)) < 0)
            return rc;
        sc->engine_np = rc == 0 ? (int)it : 2;
        it = 0;
    }
    if ((rc = core_ini_get_enum(ini, "cfd", "grid", 0, core_grid_choices(), &v, err)) < 0)
        return rc;
    if (rc == 0)
        sc->grid = (core_grid_level)v;
    if ((rc = core_ini_get_enum(ini, "cfd", "rotor", 0, core_rotor_choices(), &v, err)) < 0)
        return rc;
    if (rc == 0)
        sc->rotor = (core_rotor_mode)v;
    if ((rc = core_ini_get_enum(ini, "cfd", "coupling", 0, core_coupling_choices(), &v, err)) < 0)
        return rc;
    sc->coupling = rc == 0 ? (core_coupling_mode)v : CORE_COUPLING_TWO_WAY;
    /* the deck zone is a coupled point's: with the one-way coupling the key
     * stays unused and mode_keys names it */
    if (sc->coupling == CORE_COUPLING_TWO_WAY) {
        if ((rc = core_ini_get_enum(ini, "cfd", "coupled_domain", 0, "whole|zone", &v, err)) < 0)
            return rc;
        sc->coupled_zone = rc == 0 && v == 1;
    }
    /* the two-way coupling solves with the rotor's disk: rotor = off would
     * be read and ignored there */
    if (sc->rotor == CORE_ROTOR_OFF && sc->coupling == CORE_COUPLING_TWO_WAY) {
        const core_ini_entry *e = core_ini_find(ini, "cfd", "rotor");
        return core_err_set(err, -1,
                            "%s:%d: [cfd] rotor = off: the two-way coupling (coupling = two-way, "
                            "the default) solves with the rotor's disk; set rotor = uniform or "
                            "loaded, or coupling = one-way",
                            core_ini_path(ini), e ? e->line : 0);
    }
    if ((rc = core_ini_get_int(ini, "cfd", "max_iterations", 0, 0, 1000000, &it, err)) < 0)
        return rc;
    sc->max_iterations = (int)it;
    return 0;
}

/* The referenced files: the aircraft's name, the ship, and the task file
 * with the ship's deck for its points (hover a station keeping task,
 * landing a landing). */
static int referenced_files(core_ini *ini, sim_scenario *sc, core_err *err)
{
    int rc;
    if ((rc = peek_aircraft(sc->aircraft_path, sc->aircraft_name, sizeof sc->aircraft_name, err)))
        return rc;
    if ((rc = core_ship_load(sc->ship_path, &sc->ship, err)))
        return rc;
    if (sc->task_type == SIM_TASK_SHOL)
        return 0;
    sim_task t;
    if ((rc = sim_task_load_ship(sc->task_path, &sc->ship, &t, err)))
        return rc;
    int want = sc->task_type;
    if (t.kind != want) {
        const core_ini_entry *e = core_ini_find(ini, "task", "file");
        return core_err_set(err, -1, "%s:%d: [task] file = %s: a %s task, expected a %s task for type = %s",
                            core_ini_path(ini), e ? e->line : 0, sc->task_path,
                            t.kind == SIM_TASK_LAND ? "landing" : "station-keeping",
                            want == SIM_TASK_LAND ? "landing" : "station-keeping", task_name(sc->task_type));
    }
    return 0;
}

/* the path names the scenario in every later message and report: a cut
 * one would name another file */
static int set_path(sim_scenario *sc, const char *path, core_err *err)
{
    if (strlen(path) >= sizeof sc->path)
        return core_err_set(err, -1, "%.60s...: scenario path longer than %zu characters", path,
                            sizeof sc->path - 1);
    snprintf(sc->path, sizeof sc->path, "%s", path);
    return 0;
}

int sim_scenario_load(const char *path, sim_scenario *sc, core_err *err)
{
    memset(sc, 0, sizeof *sc);
    if (set_path(sc, path, err) != 0)
        return -1;
    /* a regular file of a sane size, so that a load (over LCM too) of
     * /dev/zero, a FIFO or a huge file is refused at once, unread */
    if (core_file_regular(path, SIM_SCENARIO_MAX_BYTES, err) != 0)
        return -1;
    core_ini *ini = core_ini_load(path, err);
    if (!ini)
        return -1;
    int rc = sim_scenario_from_ini(ini, sc, err);
    core_ini_destroy(ini);
    return rc;
}

int sim_scenario_from_ini(core_ini *ini, sim_scenario *sc, core_err *err)
{
    memset(sc, 0, sizeof *sc);
    if (set_path(sc, core_ini_path(ini), err) != 0)
        return -1;
    int rc = 0;
    const char *S = "scenario";
    if ((rc = refused_keys(ini, err)))
        goto out;
    if ((rc = core_ini_get_name(ini, S, "name", 1, sc->name, sizeof sc->name, err)) ||
        (rc = core_ini_get_string(ini, S, "description", 0, sc->description,
                                  sizeof sc->description, err)) < 0 ||
        (rc = core_ini_get_path(ini, S, "aircraft", 1, sc->aircraft_path,
                                sizeof sc->aircraft_path, err)) ||
        (rc = core_ini_get_path(ini, S, "ship", 1, sc->ship_path, sizeof sc->ship_path, err)))
        goto out;
    if ((rc = wod_section(ini, sc, err)) || (rc = task_pilot_sections(ini, sc, err)) ||
        (rc = sea_section(ini, sc, err)) || (rc = cfd_section(ini, sc, err)))
        goto out;

    /* [flown]: how disim shol --method pilot judges a flight (shol_flown_judge) */
    sc->flown_window_s = sc->flown_transient_frac = NAN;
    if ((rc = core_ini_get_double(ini, "flown", "window_s", 0, 0.0, 60.0, &sc->flown_window_s, err)) < 0 ||
        (rc = core_ini_get_double(ini, "flown", "transient_frac", 0, 0.0, 10.0, &sc->flown_transient_frac, err)) < 0)
        goto out;

    /* output */
    snprintf(sc->output_dir, sizeof sc->output_dir, "out/%s", sc->name);
    if ((rc = core_ini_get_string(ini, "output", "dir", 0, sc->output_dir, sizeof sc->output_dir,
                                  err)) < 0)
        goto out;

    if ((rc = mode_keys(ini, err)) || (rc = core_ini_check_unused(ini, err)))
        goto out;
    rc = referenced_files(ini, sc, err);
out:
    return rc < 0 ? rc : 0;
}

void sim_scenario_print(const sim_scenario *sc, FILE *f)
{
    char wn[32];
    fprintf(f, "[scenario]\nfile = %s\nname = %s\n", sc->path, sc->name);
    if (sc->description[0])
        fprintf(f, "description = %s\n", sc->description);
    fprintf(f, "aircraft = %s (%s)\n", sc->aircraft_name, sc->aircraft_path);
    fprintf(f, "ship = %s (%s)\n", sc->ship.name, sc->ship_path);
    fprintf(f, "ship_length_m = %.2f\nship_beam_m = %.2f\ndeck_height_m = %.2f\nship_blocks = %d\n",
            sc->ship.length_m, sc->ship.beam_m, sc->ship.deck_height_m, sc->ship.nblocks);
    fprintf(f, "\n[wod]\n");
    if (sc->wod_mode == SIM_WOD_SINGLE) {
        core_wod_name(sc->wod_dir_rad * CORE_RAD_TO_DEG, wn, sizeof wn);
        core_vec3 w = core_wod_vel_S_mps(sc->wod_speed_mps, sc->wod_dir_rad);
        fprintf(f, "mode = single\nspeed_kt = %.2f (%.3f m/s)\ndir_deg = %.1f (%s)\n",
                sc->wod_speed_mps / CORE_KT_TO_MPS, sc->wod_speed_mps,
                sc->wod_dir_rad * CORE_RAD_TO_DEG, wn);
        fprintf(f, "wind_vel_S_mps = %.3f, %.3f, %.3f\n", w.x, w.y, w.z);
    } else {
        fprintf(f, "mode = sweep\ndir_deg =");
        for (int i = 0; i < sc->n_dirs; i++)
            fprintf(f, "%s %.1f", i ? "," : "", sc->dirs_rad[i] * CORE_RAD_TO_DEG);
        fprintf(f, "\nspeed_step_kmh = %.2f\nspeed_max_kmh = %.1f\n", sc->speed_step_mps * 3.6,
                sc->speed_max_mps * 3.6);
    }
    fprintf(f, "turbulence = %s\n", sc->turbulence ? "true" : "false");
    fprintf(f, "\n[sea]\nstate = %d\nship_speed_kt = %.1f\nwave_dir_deg = %.1f\nspectrum = %s\n", sc->sea.state,
            sc->sea.ship_speed_mps / CORE_KT_TO_MPS, sc->sea.wave_dir_rad * CORE_RAD_TO_DEG,
            sc->sea.spectrum == SIM_SPECTRUM_JONSWAP ? "jonswap" : "ittc");
    static const char *pt[] = {"station", "auto", "replay"};
    fprintf(f, "\n[task]\ntype = %s\n", task_name(sc->task_type));
    if (sc->task_type != SIM_TASK_SHOL)
        fprintf(f, "file = %s\n", sc->task_path);
    fprintf(f, "hover_height_m = %.2f\nstation_S_m = %.2f, %.2f, %.2f\n", sc->hover_height_m, sc->station_S_m[0],
            sc->station_S_m[1], sc->station_S_m[2]);
    fprintf(f, "\n[pilot]\ntype = %s\n", pt[sc->pilot]);
    if (sc->pilot == SIM_SC_PILOT_STATION)
        fprintf(f, "stations = %s\nhold_after_s = %.2f\n", sc->pilot_stations[0] ? sc->pilot_stations : "(the first to connect)",
                sc->pilot_hold_after_s > 0 ? sc->pilot_hold_after_s : 0.5);
    if (sc->pilot == SIM_SC_PILOT_REPLAY)
        fprintf(f, "log = %s\nfeed_controls = %s\n", sc->pilot_log, sc->pilot_feed_controls ? "true" : "false");
    fprintf(f, "\n[cfd]\nengine = %s\n", sc->engine == SIM_ENGINE_OPENFOAM ? "openfoam" : "embedded");
    if (sc->engine == SIM_ENGINE_OPENFOAM)
        fprintf(f, "np = %d\n", sc->engine_np);
    fprintf(f, "grid = %s\nrotor = %s\ncoupling = %s\n", core_grid_name(sc->grid), core_rotor_name(sc->rotor),
            core_coupling_name(sc->coupling));
    if (sc->coupling == CORE_COUPLING_TWO_WAY)
        fprintf(f, "coupled_domain = %s\n", sc->coupled_zone ? "zone" : "whole");
    if (sc->max_iterations > 0)
        fprintf(f, "max_iterations = %d\n", sc->max_iterations);
    else
        fprintf(f, "max_iterations = 0 (the solver's default)\n");
    fprintf(f, "\n[output]\ndir = %s\n", sc->output_dir);
}
