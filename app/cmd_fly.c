/* cmd_fly.c -- `disim fly SCENARIO`: the flight loop. The helicopter starts
 * in a trimmed hover at the scenario's station in the ship's airwake and is
 * flown by the deterministic step (sim_flight_step), paced in real time
 * (absolute deadlines, overruns counted) or as fast as it can (--fast);
 * the trajectory goes to a CSV file. The airwake is the scenario's
 * ship-only field from the database (or --field): while the database does
 * not have it yet, it is requested and the loop flies the free stream, and
 * blends the field in when it is ready.
 *
 * The loop's LCM side (sim_loop, sim/lcm_io.c): pilot stations fly it
 * (pilot_input_t, by the stations' rules), sim_control_t pauses, resumes,
 * resets it and loads another scenario; it publishes heli_state_t,
 * ship_state_t and sim_status_t; --log records every message sent and
 * received, --replay-inputs flies a log's pilot inputs and controls at
 * their logged steps. LCM is on in real time (the library's default URL
 * or --lcm URL) and off with --fast unless --lcm is given. */
#include "awdb.h"
#include "cfd.h"
#include "cmds.h"
#include "hfm.h"
#include "render.h"
#include "scene.h"
#include "sim.h"

#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static volatile sig_atomic_t fly_stop = 0;
static void on_signal(int sig)
{
    (void)sig;
    fly_stop = 1;
}

static void usage_fly(void)
{
    fprintf(stderr, "usage: disim fly SCENARIO [--realtime | --fast] [--duration S] [--rate-hz N]\n"
                    "                  [--wod-speed-kt V] [--wod-dir-deg D] [--field F.h5 | --db DIR]\n"
                    "                  [--csv OUT.csv] [--csv-rate-hz N] [--sea-state N] [--wave-dir-deg D]\n"
                    "                  [--ship-speed-kt U] [--seed N] [--no-turbulence] [--sas on|off] [--start hover|deck] [--no-gear]\n"
                    "                  [--lcm URL | --no-lcm] [--log FILE] [--replay-inputs LOG]\n"
                    "                  [--stations A,B,...] [--hold-after-s S] [--state-rate-hz N]\n"
                    "                  [--pilot auto --task FILE [--task-result PREFIX]]  (headless, as fast as it can)\n"
                    "                  [--pilot replay LOG [--feed-controls]]  (headless: LOG's run re-flown)\n"
                    "                  [--render DIR [--render-rate HZ] [--render-size WxH]\n"
                    "                   [--render-cameras deck,pilot,chase,overhead] [--render-video on|off]]\n");
}

typedef struct fly_args {
    const char *scen, *field, *db, *csv, *lcm_url, *log, *replay, *stations;
    int realtime, sea_state, turbulence, lcm; /* lcm: -1 as the mode says, 0 off, 1 on */
    double duration_s, rate_hz, csv_rate_hz, speed_kt, dir_deg, wave_dir_deg, ship_speed_kt, seed;
    double hold_after_s, state_rate_hz;
    const char *pilot, *task; /* --pilot auto --task FILE: the automated pilot flies */
    const char *task_result;  /* --task-result PREFIX: PREFIX.csv and PREFIX.json (sim_task_result_write) */
    int duration_set;
    int realtime_set; /* --realtime given (the automated pilot flies as fast as it can without) */
    int sas;          /* --sas on|off: 1, 0; -1 the aircraft file's [sas] engaged key */
    int gear, start_deck;     /* the aircraft's [gear] on the deck (--no-gear: 0); --start deck */
    int hold_set;             /* --hold-after-s given */
    /* the scenario's [pilot] and [task] where no flag says (fly_scenario_pilot) */
    char sc_task[SIM_PATH_MAX], sc_log[SIM_PATH_MAX], sc_stations[SIM_PATH_MAX];
    const char *replay_log;   /* --pilot replay LOG: the replay pilot re-flies LOG (sim/pilot_replay.c) */
    int feed_controls;        /* --feed-controls: LOG's controls fed forward too */
    int has_start;            /* the flight starts at start_S_m (the replayed run's start) */
    double start_S_m[3];
    /* --render DIR: live frames beside the loop (render_live): their rate
     * (s of simulation time), size, cameras (1 << render_camera_kind) and
     * MP4s instead of PNG frames (--render-video on) */
    const char *render_dir;
    double render_rate_hz;
    int render_w, render_h, render_video, render_flag; /* render_flag: a --render-* flag given */
    unsigned render_cameras;
} fly_args;

/* The scenario's [pilot] (and the automated pilot's [task] file) where
 * no flag says otherwise: a --pilot flag overrides the type, --task the
 * task file, --stations and --hold-after-s the stations' keys. A scenario
 * that does not load is left to world_build to report. */
static void fly_scenario_pilot(fly_args *o)
{
    sim_scenario *sc = malloc(sizeof *sc);
    core_err err = {0};
    if (!sc || sim_scenario_load(o->scen, sc, &err) != 0) {
        free(sc);
        return;
    }
    if (!o->pilot && sc->pilot == SIM_SC_PILOT_AUTO) {
        o->pilot = "auto";
        if (!o->task) {
            snprintf(o->sc_task, sizeof o->sc_task, "%s", sc->task_path);
            o->task = o->sc_task;
        }
    } else if (!o->pilot && sc->pilot == SIM_SC_PILOT_REPLAY) {
        o->pilot = "replay";
        snprintf(o->sc_log, sizeof o->sc_log, "%s", sc->pilot_log);
        o->replay_log = o->sc_log;
        o->feed_controls |= sc->pilot_feed_controls;
    } else if (!o->pilot && sc->pilot == SIM_SC_PILOT_STATION) {
        if (!o->stations && sc->pilot_stations[0]) {
            snprintf(o->sc_stations, sizeof o->sc_stations, "%s", sc->pilot_stations);
            o->stations = o->sc_stations;
        }
        if (!o->hold_set && sc->pilot_hold_after_s > 0.0)
            o->hold_after_s = sc->pilot_hold_after_s;
    }
    free(sc);
}

/* A --render flag and its value: 0, or -1 after saying what was expected. */
static int fly_parse_render(fly_args *o, const char *a, const char *v)
{
    const char *P = "disim fly";
    core_err err = {0};
    if (!strcmp(a, "--render")) {
        o->render_dir = v;
        return 0;
    }
    o->render_flag = 1;
    if (!strcmp(a, "--render-rate"))
        return app_parse_double(P, a, v, 0.1, 1000.0, &o->render_rate_hz);
    if (!strcmp(a, "--render-size")) {
        if (render_size_parse(v, &o->render_w, &o->render_h, &err) != 0) {
            fprintf(stderr, "disim fly: --render-size %s\n", err.msg);
            return -1;
        }
        return 0;
    }
    if (!strcmp(a, "--render-cameras")) {
        o->render_cameras = 0;
        char name[32];
        for (const char *p = v;;) {
            size_t n = strcspn(p, ",");
            render_camera_kind k;
            snprintf(name, sizeof name, "%.*s", (int)(n < sizeof name ? n : sizeof name - 1), p);
            if (n >= sizeof name || render_camera_parse(name, &k, &err) != 0) {
                fprintf(stderr, "disim fly: --render-cameras '%s': %s\n", v, err.msg[0] ? err.msg : "a name too long");
                return -1;
            }
            o->render_cameras |= 1u << k;
            if (!p[n])
                return 0;
            p += n + 1;
        }
    }
    if (!strcmp(a, "--render-video")) {
        if (strcmp(v, "on") && strcmp(v, "off")) {
            fprintf(stderr, "disim fly: --render-video '%s': expected on or off\n", v);
            return -1;
        }
        o->render_video = !strcmp(v, "on");
        return 0;
    }
    fprintf(stderr, "disim fly: unknown flag '%s'\n", a);
    return -1;
}

static int fly_parse(int argc, char **argv, fly_args *o)
{
    memset(o, 0, sizeof *o);
    o->realtime = 1;
    o->duration_s = 60.0;
    o->rate_hz = 200.0;
    o->csv_rate_hz = 50.0;
    o->speed_kt = o->dir_deg = NAN;
    o->db = "out/airwake-db";
    o->turbulence = -1;
    o->gear = 1;
    o->sea_state = -1;
    o->wave_dir_deg = o->ship_speed_kt = NAN;
    o->seed = 1;
    o->sas = -1;
    o->lcm = -1;
    o->hold_after_s = 0.5;
    o->state_rate_hz = 50.0;
    o->render_rate_hz = 10.0;
    o->render_w = 640;
    o->render_h = 480;
    o->render_cameras = 1u << RENDER_CAM_DECK;
    const char *P = "disim fly";
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        int more = i + 1 < argc;
        if (!strcmp(a, "--sas") && more) {
            const char *v = argv[++i];
            if (strcmp(v, "on") && strcmp(v, "off")) {
                fprintf(stderr, "disim fly: --sas '%s': expected on or off\n", v);
                return 2;
            }
            o->sas = !strcmp(v, "on");
        } else if (!strcmp(a, "--fast"))
            o->realtime = 0;
        else if (!strcmp(a, "--realtime"))
            o->realtime = 1, o->realtime_set = 1;
        else if (!strcmp(a, "--duration") && more) {
            if (app_parse_double(P, a, argv[++i], 0.0, 1e6, &o->duration_s))
                return 1;
            o->duration_set = 1;
        } else if (!strcmp(a, "--rate-hz") && more) {
            if (app_parse_double(P, a, argv[++i], 10.0, 10000.0, &o->rate_hz))
                return 1;
        } else if (!strcmp(a, "--csv-rate-hz") && more) {
            if (app_parse_double(P, a, argv[++i], 0.1, 10000.0, &o->csv_rate_hz))
                return 1;
        } else if (!strcmp(a, "--state-rate-hz") && more) {
            if (app_parse_double(P, a, argv[++i], 1.0, 10000.0, &o->state_rate_hz))
                return 1;
        } else if (!strcmp(a, "--hold-after-s") && more) {
            if (app_parse_double(P, a, argv[++i], 0.01, 60.0, &o->hold_after_s))
                return 1;
            o->hold_set = 1;
        } else if (!strcmp(a, "--wod-speed-kt") && more) {
            if (app_parse_double(P, a, argv[++i], 0.0, 100.0, &o->speed_kt))
                return 1;
        } else if (!strcmp(a, "--wod-dir-deg") && more) {
            if (app_parse_double(P, a, argv[++i], -360.0, 360.0, &o->dir_deg))
                return 1;
        } else if (!strcmp(a, "--no-turbulence"))
            o->turbulence = 0;
        else if (!strcmp(a, "--no-gear"))
            o->gear = 0;
        else if (!strcmp(a, "--start") && more) {
            const char *v = argv[++i];
            if (strcmp(v, "hover") && strcmp(v, "deck")) {
                fprintf(stderr, "disim fly: --start '%s': expected hover or deck\n", v);
                return 1;
            }
            o->start_deck = !strcmp(v, "deck");
        }
        else if (!strcmp(a, "--sea-state") && more) {
            if (app_parse_int(P, a, argv[++i], 0, 6, &o->sea_state))
                return 1;
        } else if (!strcmp(a, "--wave-dir-deg") && more) {
            if (app_parse_double(P, a, argv[++i], -360.0, 360.0, &o->wave_dir_deg))
                return 1;
        } else if (!strcmp(a, "--ship-speed-kt") && more) {
            if (app_parse_double(P, a, argv[++i], 0.0, 40.0, &o->ship_speed_kt))
                return 1;
        } else if (!strcmp(a, "--seed") && more) {
            if (app_parse_double(P, a, argv[++i], 0.0, 9007199254740992.0, &o->seed) || o->seed != floor(o->seed)) {
                fprintf(stderr, "disim fly: --seed: expected a whole number\n");
                return 1;
            }
        } else if (!strcmp(a, "--field") && more)
            o->field = argv[++i];
        else if (!strcmp(a, "--db") && more)
            o->db = argv[++i];
        else if (!strcmp(a, "--csv") && more)
            o->csv = argv[++i];
        else if (!strcmp(a, "--lcm") && more) {
            o->lcm = 1;
            o->lcm_url = argv[++i];
        } else if (!strcmp(a, "--no-lcm"))
            o->lcm = 0;
        else if (!strcmp(a, "--log") && more)
            o->log = argv[++i];
        else if (!strcmp(a, "--replay-inputs") && more)
            o->replay = argv[++i];
        else if (!strcmp(a, "--stations") && more)
            o->stations = argv[++i];
        else if (!strcmp(a, "--pilot") && more && !strcmp(argv[i + 1], "replay") && i + 2 < argc &&
                 argv[i + 2][0] != '-') {
            o->pilot = argv[++i];
            o->replay_log = argv[++i];
        } else if (!strcmp(a, "--feed-controls"))
            o->feed_controls = 1;
        else if (!strcmp(a, "--pilot") && more)
            o->pilot = argv[++i];
        else if (!strcmp(a, "--task") && more)
            o->task = argv[++i];
        else if (!strcmp(a, "--task-result") && more)
            o->task_result = argv[++i];
        else if (!strncmp(a, "--render", 8) && more) {
            if (fly_parse_render(o, a, argv[++i]) != 0)
                return 2;
        } else if (a[0] != '-' && !o->scen)
            o->scen = a;
        else {
            fprintf(stderr, "disim fly: unknown or incomplete argument '%s'\n", a);
            usage_fly();
            return 2;
        }
    }
    if (!o->scen) {
        usage_fly();
        return 2;
    }
    fly_scenario_pilot(o);
    int auto_ok = o->pilot && !strcmp(o->pilot, "auto") && o->task && !o->feed_controls;
    int replay_ok = o->replay_log && !o->task;
    if ((o->pilot || o->task || o->feed_controls) && !auto_ok && !replay_ok) {
        fprintf(stderr, "disim fly: --pilot '%s': expected --pilot auto with --task FILE, or --pilot replay LOG "
                        "[--feed-controls]\n", o->pilot ? o->pilot : "");
        return 1;
    }
    if (o->task_result && !auto_ok) {
        fprintf(stderr, "disim fly: --task-result: expected --pilot auto with --task FILE\n");
        return 1;
    }
    int is_auto = o->pilot && !strcmp(o->pilot, "auto");
    if (o->pilot && (o->replay || o->stations || (!is_auto && (o->lcm == 1 || o->log || o->realtime_set)))) {
        if (is_auto)
            fprintf(stderr, "disim fly: --pilot auto: --replay-inputs and --stations do not apply (the automated "
                            "pilot flies)\n");
        else
            fprintf(stderr, "disim fly: --pilot %s flies headless: --lcm, --log, --realtime, --replay-inputs and "
                            "--stations do not apply\n", o->pilot);
        return 1;
    }
    if (o->pilot && !o->realtime_set) /* as fast as it can, unless --realtime */
        o->realtime = 0;
    if (o->render_flag && !o->render_dir) {
        fprintf(stderr, "disim fly: --render-rate, --render-size, --render-cameras and --render-video need --render DIR\n");
        return 2;
    }
    if (o->render_dir && o->pilot) {
        fprintf(stderr, "disim fly: --render: not with --pilot %s (draw its --log with disim render)\n", o->pilot);
        return 1;
    }
    if (o->render_dir && o->render_rate_hz > o->rate_hz) {
        fprintf(stderr, "disim fly: --render-rate %g: expected at most the loop's rate (%g Hz)\n", o->render_rate_hz,
                o->rate_hz);
        return 2;
    }
    if (o->state_rate_hz > o->rate_hz) {
        fprintf(stderr, "disim fly: --state-rate-hz %g: expected at most the loop's rate (%g Hz)\n", o->state_rate_hz,
                o->rate_hz);
        return 1;
    }
    return 0;
}

/* The scenario's ship-only field from the database: loaded when READY (1),
 * requested when absent (0), or -1 with err. */
static int db_field(awdb *db, const sim_scenario *sc, double dir_rad, cfd_field **out, core_err *err)
{
    awdb_key k;
    awdb_key_ship_only(&k, sc->ship.name, sc->aircraft_name, AWDB_SHIP_ONLY_REF_MPS, dir_rad, sc->grid);
    if (awdb_key_canon(&k, err) != 0)
        return -1;
    char path[1024];
    awdb_state st = awdb_query(db, &k, path, sizeof path);
    if (st == AWDB_READY) {
        *out = cfd_field_load(path, err);
        return *out ? 1 : -1;
    }
    if (st == AWDB_FAILED)
        return 0; /* flown in the free stream; the failure is in the database */
    return awdb_submit(db, &k, NULL, err) != 0 ? -1 : 0;
}

/* The coupled rotor interaction at the WOD (issue 25): among the database's
 * whole-domain coupled fields of the scenario's ship, aircraft and grid
 * within 0.25 m/s and 0.5 deg of the WOD (the SHOL's speeds are in km/h
 * steps, the flight's in knots) whose isolated rotor's field (the same
 * key, ship NAME.isolated) is ready too, the one whose hub is nearest the
 * station, and of several within 0.5 m of that (the coupling's iterations
 * at one station) the newest, its converged iteration. A deck-zone pair
 * (couple.h's settings.zone) needs the whole domain's ship-only field and
 * the zone's own too (the coupling's keys: the zone at the station), for
 * the coupling's correction. 1 with the fields and their interaction, 0
 * none, -1 with err. */
typedef struct coupled_pick {
    const sim_scenario *sc;
    double v, dir_deg;
    awdb *db;
    int pass;             /* 0: the hub nearest the station; 1: the newest hub within 0.5 m of it */
    double near_hub_S_m[3];
    awdb_key best;
    double best_d, best_mtime;
    char cpath[1024], ipath[1024], wpath[1024], zpath[1024]; /* wpath, zpath "": a whole-domain pair */
} coupled_pick;

static int coupled_candidate(void *user, const awdb_key *k)
{
    coupled_pick *p = user;
    double dd = fabs(remainder(k->wod_dir_rad * CORE_RAD_TO_DEG - p->dir_deg, 360.0));
    if (strcmp(k->ship, p->sc->ship.name) || strcmp(k->aircraft, p->sc->aircraft_name) || k->rotor == CORE_ROTOR_OFF ||
        k->grid != p->sc->grid || fabs(k->wod_speed_mps - p->v) > 0.25 || dd > 0.5)
        return 0;
    double d2 = 0.0;
    for (int i = 0; i < 3; i++)
        d2 += (k->station_S_m[i] - p->sc->station_S_m[i]) * (k->station_S_m[i] - p->sc->station_S_m[i]);
    double d = sqrt(d2), dn2 = 0.0;
    for (int i = 0; i < 3; i++)
        dn2 += (k->station_S_m[i] - p->near_hub_S_m[i]) * (k->station_S_m[i] - p->near_hub_S_m[i]);
    if (p->pass == 1 && dn2 > 0.25)
        return 0;
    awdb_key ki = *k;
    char cp[1024], ip[1024];
    if (snprintf(ki.ship, sizeof ki.ship, "%s.isolated", k->ship) >= (int)sizeof ki.ship)
        return 0;
    struct stat st;
    if (awdb_query(p->db, k, cp, sizeof cp) != AWDB_READY || awdb_query(p->db, &ki, ip, sizeof ip) != AWDB_READY ||
        stat(cp, &st) != 0)
        return 0;
    double mt = (double)st.st_mtim.tv_sec + 1e-9 * (double)st.st_mtim.tv_nsec;
    char wp[1024] = "", zp[1024] = "";
    if (k->zone_ref_mps > 0.0) { /* the zone's correction: both ship-only fields at the zone's speed */
        awdb_key kw, kz;
        awdb_key_ship_only(&kw, k->ship, k->aircraft, k->zone_ref_mps, k->wod_dir_rad, k->grid);
        kz = kw;
        kz.zone_ref_mps = k->zone_ref_mps;
        memcpy(kz.station_S_m, p->sc->station_S_m, sizeof kz.station_S_m);
        kz.radius_m = k->radius_m;
        core_err e2 = {0};
        if (awdb_key_canon(&kw, &e2) || awdb_key_canon(&kz, &e2) || awdb_query(p->db, &kw, wp, sizeof wp) != AWDB_READY ||
            awdb_query(p->db, &kz, zp, sizeof zp) != AWDB_READY)
            return 0;
    }
    if (p->pass == 0) { /* ties by the hub's coordinates: the entries' order does not matter */
        int tie = d == p->best_d && memcmp(k->station_S_m, p->near_hub_S_m, sizeof p->near_hub_S_m) != 0 &&
                  (k->station_S_m[0] < p->near_hub_S_m[0] ||
                   (k->station_S_m[0] == p->near_hub_S_m[0] && (k->station_S_m[1] < p->near_hub_S_m[1] ||
                    (k->station_S_m[1] == p->near_hub_S_m[1] && k->station_S_m[2] < p->near_hub_S_m[2]))));
        if (d < p->best_d || tie) {
            p->best_d = d;
            memcpy(p->near_hub_S_m, k->station_S_m, sizeof p->near_hub_S_m);
        }
    } else if (mt > p->best_mtime) {
        p->best = *k;
        p->best_mtime = mt;
        snprintf(p->cpath, sizeof p->cpath, "%s", cp);
        snprintf(p->ipath, sizeof p->ipath, "%s", ip);
        snprintf(p->wpath, sizeof p->wpath, "%s", wp);
        snprintf(p->zpath, sizeof p->zpath, "%s", zp);
    }
    return 0;
}

static int db_coupled(awdb *db, const sim_scenario *sc, double v, double dir_rad, cfd_field *cf[4],
                      sim_interaction **inter, core_err *err)
{
    coupled_pick p;
    memset(&p, 0, sizeof p);
    p.sc = sc;
    p.v = v;
    p.dir_deg = dir_rad * CORE_RAD_TO_DEG;
    p.db = db;
    p.best_d = INFINITY;
    if (awdb_list(db, coupled_candidate, &p, err) < 0)
        return -1;
    if (!isfinite(p.best_d))
        return 0;
    p.pass = 1; /* the order the entries come in does not matter */
    if (awdb_list(db, coupled_candidate, &p, err) < 0)
        return -1;
    if (!p.cpath[0])
        return 0;
    if (!(cf[0] = cfd_field_load(p.cpath, err)) || !(cf[1] = cfd_field_load(p.ipath, err)))
        return -1;
    if (p.zpath[0] && (!(cf[2] = cfd_field_load(p.wpath, err)) || !(cf[3] = cfd_field_load(p.zpath, err))))
        return -1;
    sim_interaction_opts io;
    sim_interaction_opts_default(&io);
    memcpy(io.station_S_m, sc->station_S_m, sizeof io.station_S_m);
    io.ship_whole = cf[2];
    io.ship_zone = cf[3];
    return (*inter = sim_interaction_create(cf[0], cf[1], &io, err)) ? 1 : -1;
}

static int csv_row(FILE *f, const sim_flight_out *o)
{
    double gear_N = 0.0; /* the legs' loads along the deck normal, summed */
    for (int i = 0; i < o->nlegs; i++)
        gear_N += o->gear_load_N[i];
    return fprintf(f, "%.4f,%.4f,%.4f,%.4f,%.5f,%.5f,%.5f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.3f,%.3f,%.3f,%.3f,%u,%.1f,%.1f,%d,"
                      "%.1f,%u\n",
                   o->t_s, o->pos_S_m[0], o->pos_S_m[1], o->pos_S_m[2], o->euler_E_rad[0] * CORE_RAD_TO_DEG,
                   o->euler_E_rad[1] * CORE_RAD_TO_DEG, o->euler_E_rad[2] * CORE_RAD_TO_DEG, o->vel_S_mps[0],
                   o->vel_S_mps[1], o->vel_S_mps[2], o->pos_E_m[0], o->pos_E_m[1], o->pos_E_m[2], o->collective_pct,
                   o->long_pct, o->lat_pct, o->pedal_pct, o->air_flags, o->rotor_thrust_N, o->rotor_power_W,
                   o->on_deck, gear_N, o->contact_flags) < 0
               ? -1
               : 0;
}

/* The trajectory CSV (--csv): written to PATH.tmpPID and renamed at a
 * clean end, so a failed or stopped run leaves nothing half-written. */
typedef struct traj_csv {
    FILE *f;         /* NULL: no --csv (every call does nothing) */
    char tmp[1100];  /* the temporary, "" once renamed or never made */
    const char *path;
} traj_csv;

static int traj_open(traj_csv *t, const char *path, core_err *err)
{
    memset(t, 0, sizeof *t);
    t->path = path;
    if (!path)
        return 0;
    snprintf(t->tmp, sizeof t->tmp, "%s.tmp%ld", path, (long)getpid());
    if (!(t->f = fopen(t->tmp, "w"))) {
        core_err_set(err, -1, "%s: cannot write", t->tmp);
        t->tmp[0] = '\0';
        return -1;
    }
    fprintf(t->f, "t_s,x_S_m,y_S_m,z_S_m,roll_deg,pitch_deg,yaw_deg,u_S_mps,v_S_mps,w_S_mps,x_E_m,y_E_m,z_E_m,"
                  "collective_pct,long_pct,lat_pct,pedal_pct,air_flags,rotor_thrust_N,rotor_power_W,on_deck,gear_load_N,"
                  "contact_flags\n");
    return 0;
}

static int traj_row(traj_csv *t, const sim_flight_out *o) { return t->f ? csv_row(t->f, o) : 0; }

/* Flush, sync, close and rename into place: 0, or -1 with err. */
static int traj_commit(traj_csv *t, core_err *err)
{
    if (!t->f)
        return 0;
    int bad = fflush(t->f) != 0 || ferror(t->f) || fsync(fileno(t->f)) != 0;
    bad |= fclose(t->f) != 0;
    t->f = NULL;
    if (bad || rename(t->tmp, t->path) != 0)
        return core_err_set(err, -1, "%s: cannot write the trajectory (nothing written)", t->path);
    t->tmp[0] = '\0';
    return 0;
}

/* After a failure: close and remove the temporary. */
static void traj_close(traj_csv *t)
{
    if (t->f)
        fclose(t->f);
    t->f = NULL;
    if (t->tmp[0])
        unlink(t->tmp);
}

/* What one scenario flies: the scenario, the aircraft, the airwake fields,
 * the ship's motion and the flight. A reset or a load builds a new world
 * beside the running one, and replaces it only when the build succeeded. */
typedef struct fly_world {
    sim_scenario *sc;
    hfm_aircraft *ac;
    cfd_field *fld, *later;
    sim_ship_motion *motion;
    sim_flight *fl;
    int waiting; /* the database's field requested, not ready yet */
    cfd_field *cpl[4];      /* the coupled field of the WOD, its isolated rotor's (NULL: none) and, for a
                               deck-zone pair, the whole domain's ship-only field and the zone's own */
    sim_interaction *inter; /* their interaction near the station (sim/interaction.c) */
    double speed_mps, dir_rad;
    int sea_state;
    sim_run_info info; /* what it was built from (run_info_t in the log) */
} fly_world;

static void world_free(fly_world *w)
{
    sim_flight_destroy(w->fl);
    sim_interaction_destroy(w->inter);
    for (int i = 0; i < 4; i++)
        cfd_field_destroy(w->cpl[i]);
    sim_ship_motion_destroy(w->motion);
    cfd_field_destroy(w->later);
    cfd_field_destroy(w->fld);
    hfm_aircraft_destroy(w->ac);
    free(w->sc);
    memset(w, 0, sizeof *w);
}

typedef struct fly_ctx {
    const fly_args *o;
    const core_log *log;
    awdb *db;
    fly_world w;
} fly_ctx;

/* Every poll_every steps while the scenario's field is not ready: ask the
 * database again and hand a field that is now there to the flight (it
 * blends it in). 1 when it was handed over at this step, 0 if not, < 0
 * with err. */
static int world_poll(awdb *db, fly_world *w, long step, long poll_every, core_err *err)
{
    if (!w->waiting || step % poll_every != 0)
        return 0;
    int got = db_field(db, w->sc, w->dir_rad, &w->later, err);
    if (got < 0 || (got > 0 && sim_flight_set_field(w->fl, w->later, err) != 0))
        return -1;
    w->waiting = got == 0;
    return got > 0;
}

static int world_build(fly_ctx *c, const char *path, fly_world *w, core_err *err)
{
    const fly_args *o = c->o;
    memset(w, 0, sizeof *w);
    if (!(w->sc = calloc(1, sizeof *w->sc))) {
        core_err_set(err, -1, "out of memory");
        goto fail;
    }
    sim_scenario *sc = w->sc;
    if (sim_scenario_load(path, sc, err) != 0)
        goto fail;
    if (!(w->ac = hfm_aircraft_load(sc->aircraft_path, c->log, err)))
        goto fail;
    double speed = isnan(o->speed_kt) ? sc->wod_speed_mps : o->speed_kt * CORE_KT_TO_MPS;
    double dir = isnan(o->dir_deg) ? sc->wod_dir_rad : core_wod_wrap_deg(o->dir_deg) * CORE_DEG_TO_RAD;
    w->speed_mps = speed;
    w->dir_rad = dir;
    if (sc->wod_mode == SIM_WOD_SWEEP && (isnan(o->speed_kt) || isnan(o->dir_deg))) {
        core_err_set(err, -1, "%s: a WOD sweep: give the flight's --wod-speed-kt and --wod-dir-deg", path);
        goto fail;
    }
    if (o->field) {
        if (!(w->fld = cfd_field_load(o->field, err)))
            goto fail;
    } else if (speed > 0.0) {
        if (!c->db) {
            if (core_mkdir_p(o->db, err) != 0 || !(c->db = awdb_open(o->db, c->log, err)))
                goto fail;
        }
        int got = db_field(c->db, sc, dir, &w->fld, err);
        if (got < 0)
            goto fail;
        w->waiting = got == 0;
    }
    if (!o->field && !c->db && access(o->db, F_OK) == 0 && !(c->db = awdb_open(o->db, c->log, err)))
        goto fail; /* calm air: coupled fields (ground effect) without a ship-only one */
    if (!o->field && c->db && db_coupled(c->db, sc, speed, dir, w->cpl, &w->inter, err) < 0)
        goto fail;
    sim_flight_opts fo;
    sim_flight_opts_default(&fo);
    fo.interaction = w->inter;
    fo.rate_hz = o->rate_hz;
    fo.wod_speed_mps = speed;
    fo.wod_dir_rad = dir;
    /* the flags, else the scenario's [sea] and [wod] turbulence */
    fo.turbulence = o->turbulence >= 0 ? o->turbulence : sc->turbulence;
    fo.seed = (unsigned long long)o->seed;
    /* the gear on the deck when the aircraft file has one (--no-gear: none) */
    hfm_gear gear;
    fo.gear = o->gear && hfm_aircraft_gear(w->ac, &gear) == 0;
    if (o->start_deck && !fo.gear) {
        core_err_set(err, -1, "--start deck: %s", o->gear ? "the aircraft file has no [gear] section" : "not with --no-gear");
        goto fail;
    }
    fo.start = o->start_deck ? SIM_START_DECK : SIM_START_HOVER;
    fo.ship_speed_mps = isnan(o->ship_speed_kt) ? sc->ship_speed_mps : o->ship_speed_kt * CORE_KT_TO_MPS;
    memcpy(fo.station_S_m, sc->station_S_m, sizeof fo.station_S_m);
    if (o->has_start) /* --pilot replay: where the replayed run starts */
        memcpy(fo.station_S_m, o->start_S_m, sizeof fo.station_S_m);
    if (o->task && sim_task_start_S(o->task, &sc->ship, fo.station_S_m, err) != 0)
        goto fail; /* --pilot auto: a phase task starts at its first point */
    if (o->pilot && strcmp(o->pilot, "auto"))
        fo.sas = 0; /* the replay pilot's gains are the bare airframe's; the automated pilot flies the SAS */
    else if (o->sas >= 0)
        fo.sas = o->sas; /* --sas on|off */
    /* the ship in a seaway (its own seed stream: the turbulence's + 1) */
    sim_sea sea;
    sim_sea_default(&sea);
    sea.state = o->sea_state >= 0 ? o->sea_state : sc->sea_state;
    sea.ship_speed_mps = fo.ship_speed_mps;
    sea.wave_dir_rad = isnan(o->wave_dir_deg) ? sc->wave_dir_rad : core_wod_wrap_deg(o->wave_dir_deg) * CORE_DEG_TO_RAD;
    sea.spectrum = sc->spectrum ? SIM_SPECTRUM_JONSWAP : SIM_SPECTRUM_ITTC;
    w->sea_state = sea.state;
    if (!(w->motion = sim_ship_motion_create(&sc->ship, &sea, (uint64_t)o->seed + 1u, err)))
        goto fail;
    sim_run_info *ri = &w->info;
    snprintf(ri->scenario_path, sizeof ri->scenario_path, "%s", path);
    snprintf(ri->scenario, sizeof ri->scenario, "%s", sc->name);
    snprintf(ri->aircraft_path, sizeof ri->aircraft_path, "%s", sc->aircraft_path);
    snprintf(ri->ship_path, sizeof ri->ship_path, "%s", sc->ship_path);
    ri->seed = (unsigned long long)o->seed;
    ri->sea = sea;
    ri->wod_speed_mps = speed;
    ri->wod_dir_rad = dir;
    ri->rate_hz = o->rate_hz;
    if (!(w->fl = sim_flight_create(w->ac, &sc->ship, &fo, sim_ship_motion_frame_fn, w->motion, w->fld, c->log, err)))
        goto fail;
    return 0;
fail:
    world_free(w);
    return -1;
}

static void loop_world(const fly_world *w, sim_loop_world *lw)
{
    memset(lw, 0, sizeof *lw);
    lw->flight = w->fl;
    lw->motion = w->motion;
    snprintf(lw->scenario, sizeof lw->scenario, "%s", w->sc->name);
    lw->info = w->info;
}

/* sim_loop's build: a new world, the old one freed only once it stands. */
static int loop_build(void *user, const char *path, sim_loop_world *lw, core_err *err)
{
    fly_ctx *c = user;
    fly_world nw;
    if (world_build(c, path, &nw, err) != 0)
        return -1;
    world_free(&c->w);
    c->w = nw;
    loop_world(&c->w, lw);
    return 0;
}

/* --pilot auto with --log, --lcm or --realtime: the loop flies, the
 * automated pilot its pilot source (sim_loop_set_inputs, station "auto"):
 * the log and LCM carry the run as a station's flight (the run
 * information, the states, the pilot's inputs, the status), and the
 * trajectory is the one flown straight, step for step. */
#define AUTO_STATION "auto"
static sim_loop *auto_loop(fly_ctx *c, double T, core_err *err)
{
    const fly_args *o = c->o;
    sim_loop_opts lo;
    sim_loop_opts_default(&lo);
    lo.rate_hz = o->rate_hz;
    lo.realtime = o->realtime;
    lo.duration_s = T + 2.0 / o->rate_hz;
    lo.state_rate_hz = o->state_rate_hz;
    lo.lcm = o->lcm >= 0 ? o->lcm : o->realtime; /* as a station's flight: LCM in real time unless --no-lcm */
    lo.lcm_url = o->lcm_url;
    lo.log_path = o->log;
    lo.scenario_path = o->scen;
    lo.pilot_source_id = AUTO_STATION;
    sim_loop_world lw;
    loop_world(&c->w, &lw);
    return sim_loop_create(&lo, &lw, loop_build, c, c->log, err);
}

/* One step of the automated pilot's flight: straight (l NULL) or through
 * the loop. 0 stepped, > 0 the flight ended (err says why), < 0 with err. */
static int auto_step(fly_world *w, sim_loop *l, const sim_flight_inputs *in, sim_flight_out *out, core_err *err)
{
    if (!l)
        return sim_flight_step(w->fl, in, out, err);
    sim_loop_set_inputs(l, in);
    int r = sim_loop_iterate(l, out, err);
    if (r == SIM_LOOP_STEPPED)
        return 0;
    if (r == SIM_LOOP_CRASHED)
        return 1;
    return r < 0 ? -1 : core_err_set(err, -1, "fly: the loop did not step (%d)", r);
}

/* --pilot auto: the automated pilot flies the task headless, as fast as
 * it can (the task's length unless --duration), the trajectory to --csv
 * and, with --log, the run to an LCM log; the task's grade and errors said
 * at the end. 0, or < 0 with err. */
static int fly_auto(fly_ctx *c, core_err *err)
{
    const fly_args *o = c->o;
    fly_world *w = &c->w;
    sim_task task;
    if (sim_task_load_ship(o->task, &w->sc->ship, &task, err) != 0)
        return -1;
    sim_pilot_auto_opts po;
    sim_pilot_auto_opts_default(&po);
    po.rate_hz = o->rate_hz;
    po.wod_speed_mps = w->speed_mps;
    po.wod_dir_rad = w->dir_rad;
    po.sas = sim_sas_engaged(sim_flight_sas(w->fl)); /* its gains know the SAS the flight has */
    hfm_gear gear;
    po.gear = o->gear && hfm_aircraft_gear(w->ac, &gear) == 0; /* the flight has the gear (world_build) */
    sim_flight_inputs in;
    sim_flight_trim_inputs(w->fl, &in);
    sim_pilot_auto *p = sim_pilot_auto_create(w->ac, &task, &po, &in, c->log, err);
    if (!p)
        return -1;
    sim_flight_out s0; /* the attitudes it aims at: the flight's trim in its air */
    sim_flight_state(w->fl, &s0);
    if (!o->start_deck && sim_pilot_auto_set_trim_state(p, &s0) != 0) {
        sim_pilot_auto_destroy(p);
        return core_err_set(err, -1, "fly: the flight's start is not a hover's trimmed state");
    }
    traj_csv csv;
    int rc = -1;
    sim_loop *loop = NULL;
    if (traj_open(&csv, o->csv, err) != 0)
        goto out;
    double T = o->duration_set ? o->duration_s : sim_task_length_s(&task);
    if ((o->log || o->lcm == 1 || o->realtime) && !(loop = auto_loop(c, T, err)))
        goto out;
    long n = (long)llround(T * o->rate_hz), csv_every = (long)fmax(1.0, llround(o->rate_hz / o->csv_rate_hz));
    long poll_every = (long)llround(o->rate_hz);
    fprintf(stderr, "fly: %s + %s, WOD %.1f kt from %.0f deg, sea state %d, %s, the automated pilot flies %s for %.0f s%s\n",
            w->sc->ship.name, hfm_aircraft_name(w->ac), w->speed_mps / CORE_KT_TO_MPS, w->dir_rad * CORE_RAD_TO_DEG,
            w->sea_state, w->fld ? "airwake field" : w->waiting ? "free stream until the airwake field is built" : "free stream",
            o->task, T, loop ? (o->realtime ? ", in real time" : ", through the loop") : "");
    sim_flight_out out;
    sim_flight_state(w->fl, &out);
    if (traj_row(&csv, &out) != 0)
        goto write_fail;
    sim_task_result r;
    char ended[256] = ""; /* what ended the flight ("" it flew on) */
    for (long s = 0; s < n && !fly_stop; s++) {
        sim_pilot_auto_step(p, &out, &in);
        sim_pilot_auto_result(p, &r);
        if (r.done) /* the task is over: settled on the deck (gear), touched down, its last hold flown */
            break;
        int st = auto_step(w, loop, &in, &out, err);
        if (st < 0)
            goto out;
        if ((st > 0 || out.step % csv_every == 0) && traj_row(&csv, &out) != 0)
            goto write_fail;
        if (st > 0) { /* a crash or a roll-over ended the flight: said, the trajectory kept */
            snprintf(ended, sizeof ended, "%.250s", err->msg);
            break;
        }
        int polled = world_poll(c->db, w, out.step, poll_every, err);
        if (polled < 0)
            goto out;
        if (polled > 0)
            fprintf(stderr, "fly: the airwake field is ready at t = %.1f s: blended in\n", out.t_s);
    }
    sim_pilot_auto_step(p, &out, &in); /* grades the last state */
    if (traj_commit(&csv, err) != 0 || (loop && sim_loop_finish(loop, err) != 0))
        goto out;
    if (loop)
        fprintf(stderr, "fly: the run logged to %s\n", o->log);
    sim_pilot_auto_result(p, &r);
    /* the task's result: --task-result PREFIX, else beside --csv (OUT_task.csv, .json) */
    char res[2][1100], pre[1024] = "";
    if (o->task_result)
        snprintf(pre, sizeof pre, "%s", o->task_result);
    else if (o->csv)
        snprintf(pre, sizeof pre, "%.*s_task", (int)(strlen(o->csv) - (strlen(o->csv) > 4 &&
                 !strcmp(o->csv + strlen(o->csv) - 4, ".csv") ? 4 : 0)), o->csv);
    if (pre[0]) {
        snprintf(res[0], sizeof res[0], "%s.csv", pre);
        snprintf(res[1], sizeof res[1], "%s.json", pre);
        if (sim_task_result_write(&task, &r, res[0], res[1], err) != 0)
            goto out;
        fprintf(stderr, "fly: the task's result in %s and %s\n", res[0], res[1]);
    }
    if (task.kind == SIM_TASK_LAND && r.touched)
        fprintf(stderr, "fly: touchdown %s at %.2f s (descent from %.2f s): sink %.2f m/s, drift %.2f m/s, %.2f m from "
                        "the spot\n",
                r.touchdown_grade == 2 ? "desired" : r.touchdown_grade == 1 ? "adequate" : "not met", r.t_touchdown_s,
                r.t_descent_s, r.sink_mps, r.drift_mps, r.dist_m);
    else if (task.kind == SIM_TASK_LAND)
        fprintf(stderr, "fly: no touchdown by %.1f s\n", r.t_s);
    fprintf(stderr, "fly: task %s at %.1f s%s: within desired since %.2f s, adequate since %.2f s; largest error after "
                    "%.0f s %.2f m, height %.2f m, heading %.1f deg; %ld steps with a control at a stop\n",
            r.grade == 2 ? "desired" : r.grade == 1 ? "adequate" : "not met", r.t_s, fly_stop ? " (stopped)" : "",
            r.t_desired_s, r.t_adequate_s, task.desired.time_s, r.max_err_pos_m, r.max_err_height_m,
            r.max_err_heading_rad * CORE_RAD_TO_DEG, r.stop_steps);
    rc = 0;
    if (ended[0]) {
        fprintf(stderr, "fly: the flight ended at %.2f s: %s\n", out.t_s, ended);
        core_err_set(err, 1, "%s", ended);
        rc = 1;
    }
    goto out;
write_fail:
    core_err_set(err, -1, "%s: cannot write the trajectory (nothing written)", o->csv);
out:
    traj_close(&csv);
    sim_loop_destroy(loop);
    sim_pilot_auto_destroy(p);
    return rc;
}

/* --pilot replay LOG: the replay pilot re-flies LOG's run relative to the
 * deck (sim/pilot_replay.c) headless, as fast as it can, for the log's
 * length unless --duration; the trajectory to --csv; how far it stayed
 * from the reference said at the end, per phase. 0, or < 0 with err. */
static int fly_replay(fly_ctx *c, const sim_log *ref, core_err *err)
{
    const fly_args *o = c->o;
    fly_world *w = &c->w;
    sim_log_summary info;
    sim_log_info(ref, &info);
    sim_pilot_replay_opts po;
    sim_pilot_replay_opts_default(&po);
    po.pilot.rate_hz = o->rate_hz;
    po.pilot.wod_speed_mps = w->speed_mps;
    po.pilot.wod_dir_rad = w->dir_rad;
    po.feed_controls = o->feed_controls;
    sim_flight_inputs in;
    sim_flight_trim_inputs(w->fl, &in);
    sim_pilot_replay *p = sim_pilot_replay_create(w->ac, ref, &po, &in, c->log, err);
    if (!p)
        return -1;
    sim_flight_out s0; /* the attitude references of the flight's own trim */
    sim_flight_state(w->fl, &s0);
    if (!s0.on_deck && sim_pilot_replay_set_trim_state(p, &s0) != 0)
        fprintf(stderr, "fly: warning: the replay pilot keeps the uniform-WOD trim's attitudes\n");
    traj_csv csv;
    int rc = -1;
    if (traj_open(&csv, o->csv, err) != 0)
        goto out;
    double T = o->duration_set ? o->duration_s : info.t1_s;
    long n = (long)llround(T * o->rate_hz), csv_every = (long)fmax(1.0, llround(o->rate_hz / o->csv_rate_hz));
    long poll_every = (long)llround(o->rate_hz);
    fprintf(stderr, "fly: %s + %s, WOD %.1f kt from %.0f deg, sea state %d, the replay pilot re-flies %s (%ld states, "
                    "%.2f s, controls from %s%s) for %.2f s\n",
            w->sc->ship.name, hfm_aircraft_name(w->ac), w->speed_mps / CORE_KT_TO_MPS, w->dir_rad * CORE_RAD_TO_DEG,
            w->sea_state, o->replay_log, info.n_states, info.t1_s,
            info.n_inputs ? "the station's inputs" : "the flown states", o->feed_controls ? ", fed forward" : "", T);
    sim_flight_out out;
    sim_flight_state(w->fl, &out);
    if (traj_row(&csv, &out) != 0)
        goto write_fail;
    for (long s = 0; s < n && !fly_stop; s++) {
        sim_pilot_replay_step(p, &out, &in);
        int st = sim_flight_step(w->fl, &in, &out, err);
        if (st < 0)
            goto out;
        if (out.step % csv_every == 0 && traj_row(&csv, &out) != 0)
            goto write_fail;
        if (st > 0) { /* the flight ended (a crash): said, the trajectory kept */
            fprintf(stderr, "fly: the flight ended at %.2f s: %s\n", out.t_s, err->msg);
            break;
        }
        if (world_poll(c->db, w, out.step, poll_every, err) < 0)
            goto out;
    }
    sim_pilot_replay_step(p, &out, &in); /* counts the last state */
    if (traj_commit(&csv, err) != 0)
        goto out;
    sim_replay_result r;
    sim_pilot_replay_result(p, &r);
    fprintf(stderr, "fly: replay to %.2f s%s: from the reference rms %.3f m, max %.3f m at %.2f s, heading max %.2f deg; "
                    "%ld steps with a control at a stop\n",
            r.t_s, fly_stop ? " (stopped)" : r.ended ? "" : " (the reference not ended)", r.all.rms_m, r.all.max_m,
            r.all.t_max_s, r.max_heading_err_rad * CORE_RAD_TO_DEG, r.stop_steps);
    for (int ph = 0; ph < SIM_REPLAY_NPHASE; ph++)
        if (r.phase[ph].n)
            fprintf(stderr, "fly: replay %s: %.2f s, rms %.3f m, max %.3f m at %.2f s\n", sim_replay_phase_name(ph),
                    r.phase[ph].duration_s, r.phase[ph].rms_m, r.phase[ph].max_m, r.phase[ph].t_max_s);
    /* 1: a crash or a roll-over ended the flight (said above) */
    rc = out.contact_flags & (SIM_CONTACT_CRASH | SIM_CONTACT_TIP) ? 1 : 0;
    goto out;
write_fail:
    core_err_set(err, -1, "%s: cannot write the trajectory (nothing written)", o->csv);
out:
    traj_close(&csv);
    sim_pilot_replay_destroy(p);
    return rc;
}

/* --render DIR: the live renderer and its scene (app/scene.c: the run's
 * ship and aircraft loaded again, so that a reset or a load, which frees
 * the world's, leaves it standing, and a seaway of its own built as the
 * flight's is, so that the render thread never touches the flight's
 * motion). A load of another scenario keeps the first one's scene. */
typedef struct fly_render {
    render_live *live;
    app_scene scene;
    int open;
    const char *dir;
} fly_render;

/* llvmpipe's rasteriser threads: one fewer than the cores, so that the
 * loop keeps one (LP_NUM_THREADS, read when the process's first GL context
 * is made; a value the user set is kept). Called before any thread starts. */
static void fly_render_threads(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    char v[24];
    snprintf(v, sizeof v, "%ld", n > 2 ? n - 1 : 1);
    setenv("LP_NUM_THREADS", v, 0);
}

static int fly_render_open(fly_render *r, const fly_args *o, const fly_world *w, const core_log *log, core_err *err)
{
    memset(r, 0, sizeof *r);
    if (!o->render_dir)
        return 0;
    r->dir = o->render_dir;
    if (app_scene_open(&r->scene, &w->info, RENDER_OVERLAY_HUD, log, err) != 0)
        return -1;
    r->open = 1;
    render_live_opts lo;
    render_live_opts_default(&lo);
    lo.dir = o->render_dir;
    lo.width = o->render_w;
    lo.height = o->render_h;
    lo.rate_hz = o->render_rate_hz;
    lo.cameras = o->render_cameras;
    lo.png = !o->render_video;
    lo.video = o->render_video;
    if (!(r->live = render_live_create(&r->scene.scene, &lo, err)))
        return -1;
    return 0;
}

/* A step's outputs, copied to the renderer (the flight is the same without). */
static void fly_render_offer(fly_render *r, const sim_flight_out *o)
{
    if (!r->live || !render_live_due(r->live, o->t_s))
        return; /* not due: not built (the conversion, in the loop's thread) */
    render_state s;
    app_render_state_from_flight(&r->scene, o, &s);
    render_live_offer(r->live, &s);
}

/* The end: the thread stopped, its videos finished, one line said (the
 * loop's step p99 beside the frames' times; lr NULL: nothing said). 0, or
 * < 0 with err. */
static int fly_render_close(fly_render *r, const sim_loop_report *lr, core_err *err)
{
    int rc = 0;
    if (r->live) {
        render_live_report rr;
        rc = render_live_destroy(r->live, &rr, err);
        r->live = NULL;
        if (lr)
            fprintf(stderr, "fly: rendered %ld frames into %s (%ld of %ld states not drawn): frame p50 %.1f ms p99 "
                            "%.1f ms; the loop's step p99 %.0f us\n",
                    rr.frames, r->dir, rr.dropped, rr.offered, 1e3 * rr.render_p50_s,
                    1e3 * rr.render_p99_s, 1e6 * lr->pace.step_p99_s);
        if (lr && rc == 0 && lr->pace.realtime_factor > 1.5)
            fprintf(stderr, "fly: the loop ran %.0fx real time and the renderer drew the states it could: disim render "
                            "draws every frame of a --log\n", lr->pace.realtime_factor);
    }
    if (r->open)
        app_scene_close(&r->scene);
    r->open = 0;
    return rc;
}

int cmd_fly(int argc, char **argv)
{
    fly_args o;
    int rc = fly_parse(argc, argv, &o);
    if (rc)
        return rc;
    if (o.render_dir)
        fly_render_threads(); /* before any thread or GL context */
    core_err err = {0};
    int tty = isatty(2);
    app_log al = {"fly", tty};
    core_log log = {app_log_stderr, &al, CORE_LOG_WARN};
    fly_ctx ctx = {&o, &log, NULL, {0}};
    sim_loop *loop = NULL;
    traj_csv csv;
    memset(&csv, 0, sizeof csv);
    fly_render fr; /* --render: the live renderer */
    memset(&fr, 0, sizeof fr);
    rc = 1;
    sim_log *replay_ref = NULL; /* --pilot replay: read first, the flight starts where it does */
    if (o.replay_log) {
        sim_log_sample s0;
        if (!(replay_ref = sim_log_load(o.replay_log, &err)))
            goto fail;
        sim_log_sample_at(replay_ref, 0.0, &s0);
        memcpy(o.start_S_m, s0.pos_S_m, sizeof o.start_S_m);
        o.has_start = 1;
    }
    if (world_build(&ctx, o.scen, &ctx.w, &err) != 0)
        goto fail;
    if (o.replay_log) {
        int rr = fly_replay(&ctx, replay_ref, &err);
        if (rr < 0)
            goto fail;
        rc = rr > 0 ? 3 : 0; /* 3: a crash or a roll-over ended the flight */
        goto done;
    }
    if (o.pilot) {
        int ra = fly_auto(&ctx, &err);
        if (ra < 0)
            goto fail;
        rc = ra > 0 ? 3 : 0; /* 3: a crash or a roll-over ended the flight (said above) */
        goto done;
    }
    sim_loop_opts lo;
    sim_loop_opts_default(&lo);
    lo.rate_hz = o.rate_hz;
    lo.realtime = o.realtime;
    lo.duration_s = o.duration_s;
    lo.state_rate_hz = o.state_rate_hz;
    lo.lcm = o.lcm >= 0 ? o.lcm : o.realtime;
    lo.lcm_url = o.lcm_url;
    lo.log_path = o.log;
    lo.replay_path = o.replay;
    lo.scenario_path = o.scen;
    lo.pilots.hold_after_s = o.hold_after_s;
    if (o.stations && sim_pilots_opts_parse(&lo.pilots, o.stations, &err) != 0)
        goto fail;
    if (traj_open(&csv, o.csv, &err) != 0)
        goto fail;
    sim_loop_world lw;
    loop_world(&ctx.w, &lw);
    /* before the loop's clock starts: locking the memory takes a while */
    if (fly_render_open(&fr, &o, &ctx.w, &log, &err) != 0)
        goto fail;
    if (o.realtime) { /* what the system grants a real-time loop, said either way */
        char rt[256];
        sim_pacer_os_realtime(50, rt, sizeof rt);
        fprintf(stderr, "fly: %s\n", rt);
    }
    if (!(loop = sim_loop_create(&lo, &lw, loop_build, &ctx, &log, &err)))
        goto fail;
    {
        const fly_world *w = &ctx.w;
        fprintf(stderr, "fly: %s + %s, WOD %.1f kt from %.0f deg, sea state %d, %s, %s, %.0f Hz, %.0f s%s%s%s%s\n",
                w->sc->ship.name, hfm_aircraft_name(w->ac), w->speed_mps / CORE_KT_TO_MPS, w->dir_rad * CORE_RAD_TO_DEG,
                w->sea_state, w->fld ? "airwake field" : w->waiting ? "free stream until the airwake field is built" : "free stream",
                o.realtime ? "real time" : "as fast as it can", o.rate_hz, o.duration_s, lo.lcm ? ", LCM " : "",
                lo.lcm ? (o.lcm_url ? o.lcm_url : "(default URL)") : "", o.replay ? ", inputs from " : "",
                o.replay ? o.replay : "");
    }
    if (ctx.w.inter) {
        sim_interaction_info ii;
        sim_interaction_state(ctx.w.inter, &ii);
        fprintf(stderr, "fly: the coupled rotor interaction near the station (the database's coupled field of %.0f N, "
                        "hub (%.2f, %.2f, %.2f) m in S%s)\n",
                ii.thrust_field_N, ii.hub_S_m[0], ii.hub_S_m[1], ii.hub_S_m[2], ctx.w.cpl[3] ? ", deck zone" : "");
    } else if (ctx.db)
        fprintf(stderr, "fly: no coupled fields for this WOD in the database: the ship-only airwake alone\n");
    signal(SIGINT, on_signal);
    signal(SIGTERM, on_signal);
    long csv_every = (long)fmax(1.0, llround(o.rate_hz / o.csv_rate_hz));
    long poll_every = (long)llround(o.rate_hz); /* the database, once a simulated second */
    sim_flight_out out;
    sim_flight_state(ctx.w.fl, &out);
    if (traj_row(&csv, &out) != 0)
        goto write_fail;
    fly_render_offer(&fr, &out); /* frame 0 at t = 0 */
    long n_stepped = 0;
    char ended[256] = ""; /* what ended the flight: a crash, a roll-over ("" none) */
    while (!fly_stop) {
        int r = sim_loop_iterate(loop, &out, &err);
        if (r < 0)
            goto fail;
        if (r == SIM_LOOP_DONE)
            break;
        if (r == SIM_LOOP_CRASHED) { /* its last state into the trajectory; the log finished as at the end */
            n_stepped++;
            fly_render_offer(&fr, &out);
            snprintf(ended, sizeof ended, "%.250s", err.msg);
            if (traj_row(&csv, &out) != 0)
                goto write_fail;
            break;
        }
        if (r != SIM_LOOP_STEPPED)
            continue;
        n_stepped++;
        fly_render_offer(&fr, &out); /* a copy: the flight is the same without it */
        if (out.step % csv_every == 0 && traj_row(&csv, &out) != 0)
            goto write_fail;
        fly_world *w = &ctx.w; /* the running world (a load may have replaced it) */
        int polled = world_poll(ctx.db, w, out.step, poll_every, &err);
        if (polled < 0)
            goto fail;
        if (polled > 0)
            fprintf(stderr, "%sfly: the airwake field is ready at t = %.1f s: blended in\n", tty ? "\r\033[K" : "",
                    out.t_s);
        if (tty && n_stepped % poll_every == 0) {
            sim_loop_report lr;
            sim_loop_report_get(loop, &lr);
            fprintf(stderr, "\r\033[Kfly: t %.0f s  x %.2f y %.2f z %.2f m (S)  roll %.1f pitch %.1f deg  %.1fx real time  "
                            "%ld overruns%s%s",
                    out.t_s, out.pos_S_m[0], out.pos_S_m[1], out.pos_S_m[2], out.euler_E_rad[0] * CORE_RAD_TO_DEG,
                    out.euler_E_rad[1] * CORE_RAD_TO_DEG, lr.pace.realtime_factor, lr.pace.overruns,
                    out.air_flags & SIM_AIR_FREE_STREAM ? "  free stream" : "", lr.held && lo.lcm ? "  input held" : "");
        }
    }
    if (sim_loop_finish(loop, &err) != 0)
        goto fail;
    if (traj_commit(&csv, &err) != 0)
        goto fail;
    sim_loop_report lr;
    sim_loop_report_get(loop, &lr);
    const sim_pacer_report *ps = &lr.pace;
    fprintf(stderr, "%sfly: %.2f s flown in %.2f s (%.1fx real time), %ld steps, %ld overruns, step p50 %.0f us p99 %.0f "
                    "us max %.0f us; ends at (%.2f, %.2f, %.2f) m in S%s\n",
            tty ? "\r\033[K" : "", lr.run_s, ps->wall_s, ps->realtime_factor, n_stepped, ps->overruns,
            1e6 * ps->step_p50_s, 1e6 * ps->step_p99_s, 1e6 * ps->step_max_s, out.pos_S_m[0], out.pos_S_m[1],
            out.pos_S_m[2], fly_stop ? " (stopped)" : "");
    if (o.realtime)
        fprintf(stderr, "fly: wake-up after the deadline: p99 %.0f us, max %.0f us\n", 1e6 * ps->late_p99_s,
                1e6 * ps->late_max_s);
    if (lo.lcm || o.log || o.replay) {
        const sim_pilots *pl = sim_loop_pilots(loop);
        fprintf(stderr, "fly: LCM %lld sent, %lld received, %lld logged, %lld controls refused", lr.sent, lr.received,
                lr.logged, lr.control_refused);
        for (int i = 0; i < sim_pilots_count(pl); i++) {
            sim_pilot_station st;
            sim_pilots_station(pl, i, &st);
            fprintf(stderr, "; station %s: %lld taken, %lld refused, %lld missing", st.id, st.received, st.refused,
                    st.gaps);
        }
        if (sim_pilots_refused_unknown(pl))
            fprintf(stderr, "; %lld refused from no readable station", sim_pilots_refused_unknown(pl));
        /* after a crash the status's message is the crash's, said below */
        fprintf(stderr, "%s%s\n", lr.message[0] && !ended[0] ? "; last refusal: " : "", ended[0] ? "" : lr.message);
    }
    if (out.nlegs > 0)
        fprintf(stderr, "fly: gear: %s at the end%s%s\n", out.on_deck ? "on the deck" : "off the deck",
                out.contact_flags ? "; " : "", out.contact_what);
    rc = 0;
    if (ended[0]) { /* stopped cleanly: the log and the trajectory are written */
        fprintf(stderr, "disim fly: the flight ended: %s\n", ended);
        rc = 3;
    }
    if (fly_render_close(&fr, &lr, &err) != 0) { /* after the flight's own outputs */
        fprintf(stderr, "disim fly: %s\n", err.msg);
        rc = rc ? rc : 1;
    }
    goto done;
write_fail:
    core_err_set(&err, -1, "%s: cannot write the trajectory (nothing written)", o.csv);
fail:
    fprintf(stderr, "%sdisim fly: %s\n", tty ? "\r\033[K" : "", err.msg);
done:
    fly_render_close(&fr, NULL, &err);
    traj_close(&csv);
    sim_loop_destroy(loop);
    world_free(&ctx.w);
    awdb_close(ctx.db);
    sim_log_destroy(replay_ref);
    return rc;
}
