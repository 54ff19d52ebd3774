/* cmd_fly.c -- `disim fly SCENARIO`: the flight loop. The helicopter starts
 * in a trimmed hover at the scenario's station in the ship's airwake and is
 * flown by the deterministic step (sim_flight_step), paced in real time
 * (absolute deadlines, overruns counted) or as fast as it can (--fast);
 * the trajectory goes to a CSV file. The airwake is the scenario's
 * ship-only field from the database (or --field): while the database does
 * not have it yet, it is requested and the loop flies the free stream, and
 * blends the field in when it is ready.
 *
 * The loop's LCM side (sim_loop, sim/loop.c): pilot stations fly it
 * (pilot_input_t, by the stations' rules), sim_control_t pauses, resumes,
 * resets it and loads another scenario; it publishes heli_state_t,
 * ship_state_t and sim_status_t; --log records every message sent and
 * received, --replay-inputs flies a log's pilot inputs and controls at
 * their logged steps. LCM is on in real time (the library's default URL
 * or --lcm URL) and off with --fast unless --lcm is given.
 *
 * What is here: the flags (a table), the world from the flags
 * (sim_world_build over the scenario, the fields from the database:
 * couple_flight_field, couple_flight_coupled), and one function per
 * pilot: the stations (the loop's own pilot), the automated pilot
 * (--pilot auto) and the replay pilot (--pilot replay), each flown by the
 * one runner (sim_run) with the same observer (the trajectory's rows,
 * sim_traj; the database polled; the render's frames; the progress
 * line) and its start and end said. */
#include "awdb.h"
#include "cfd.h"
#include "cmds.h"
#include "couple.h"
#include "disim_lcm.h"
#include "hfm.h"
#include "render.h"
#include "scene.h"
#include "sim.h"

#include <math.h>
#include <signal.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
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
                    "                  [--stations A,B,...] [--hold-after-s S] [--state-rate-hz N] [--snapshot-max-s S]\n"
                    "                  [--change-burst N] [--change-interval-s S] [--wait-after-crash]\n"
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
    double snapshot_max_s;    /* the longest flight disim ios takes a snapshot of */
    int change_burst;         /* the world changes disim ios may ask at once */
    double change_interval_s; /* and one more each (0: no limit) */
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
    int wait_after_crash;     /* --wait-after-crash: a crash stops the flight for disim ios, not the run */
    int replay_sas;           /* LOG's SAS (sim_log_summary.sas): 1 on, 0 off, -1 the log does not say */
    int has_start;            /* the flight starts at start_S_m (the replayed run's start) */
    double start_S_m[3];
    /* --render DIR: live frames beside the loop (render_live): their rate
     * (s of simulation time), size, cameras (1 << render_camera_kind) and
     * MP4s instead of PNG frames (--render-video on) */
    const char *render_dir;
    double render_rate_hz;
    int render_w, render_h, render_video, render_flag; /* render_flag: a --render-* flag given */
    const char *render_size, *render_cams; /* --render-size WxH, --render-cameras A,B,... */
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

/* A flag of disim fly: where its value goes (an offset into fly_args) and
 * how it is read. */
typedef enum { F_DOUBLE, F_WHOLE, F_INT, F_STR, F_SET, F_WORD } fly_flag_kind;
typedef struct fly_flag {
    const char *name;
    fly_flag_kind kind;
    size_t off;           /* the field: a double, an int (F_INT, F_SET, F_WORD) or a const char * */
    double lo, hi;        /* F_DOUBLE, F_WHOLE, F_INT: the range; F_SET: the value set */
    size_t given;         /* > 0: the offset of an int field set to 1 when the flag is given */
    const char *yes, *no; /* F_WORD: the words of 1 and of 0 */
    const char *said;     /* F_WORD: what is expected */
    int rc;               /* a bad value's exit status (0: 1) */
} fly_flag;

#define FA(f) offsetof(fly_args, f)
static const fly_flag fly_flags[] = {
    {.name = "--duration", F_DOUBLE, FA(duration_s), 0.0, 1e6, .given = FA(duration_set)},
    {.name = "--rate-hz", F_DOUBLE, FA(rate_hz), 10.0, 10000.0},
    {.name = "--csv-rate-hz", F_DOUBLE, FA(csv_rate_hz), 0.1, 10000.0},
    {.name = "--state-rate-hz", F_DOUBLE, FA(state_rate_hz), 1.0, 10000.0},
    {.name = "--hold-after-s", F_DOUBLE, FA(hold_after_s), 0.01, 60.0, .given = FA(hold_set)},
    {.name = "--snapshot-max-s", F_DOUBLE, FA(snapshot_max_s), 0.0, 86400.0},
    {.name = "--change-burst", F_INT, FA(change_burst), 1, 1000},
    {.name = "--change-interval-s", F_DOUBLE, FA(change_interval_s), 0.0, 3600.0},
    {.name = "--wod-speed-kt", F_DOUBLE, FA(speed_kt), 0.0, 100.0},
    {.name = "--wod-dir-deg", F_DOUBLE, FA(dir_deg), -360.0, 360.0},
    {.name = "--sea-state", F_INT, FA(sea_state), 0, 6},
    {.name = "--wave-dir-deg", F_DOUBLE, FA(wave_dir_deg), -360.0, 360.0},
    {.name = "--ship-speed-kt", F_DOUBLE, FA(ship_speed_kt), 0.0, 40.0},
    {.name = "--seed", F_WHOLE, FA(seed), 0.0, 9007199254740992.0},
    {.name = "--sas", F_WORD, FA(sas), .yes = "on", .no = "off", .said = "on or off", .rc = 2},
    {.name = "--start", F_WORD, FA(start_deck), .yes = "deck", .no = "hover", .said = "hover or deck"},
    {.name = "--fast", F_SET, FA(realtime), 0},
    {.name = "--realtime", F_SET, FA(realtime), 1, .given = FA(realtime_set)},
    {.name = "--no-turbulence", F_SET, FA(turbulence), 0},
    {.name = "--no-gear", F_SET, FA(gear), 0},
    {.name = "--no-lcm", F_SET, FA(lcm), 0},
    {.name = "--feed-controls", F_SET, FA(feed_controls), 1},
    {.name = "--wait-after-crash", F_SET, FA(wait_after_crash), 1},
    {.name = "--lcm", F_STR, FA(lcm_url), .given = FA(lcm)},
    {.name = "--field", F_STR, FA(field)},
    {.name = "--db", F_STR, FA(db)},
    {.name = "--csv", F_STR, FA(csv)},
    {.name = "--log", F_STR, FA(log)},
    {.name = "--replay-inputs", F_STR, FA(replay)},
    {.name = "--stations", F_STR, FA(stations)},
    {.name = "--pilot", F_STR, FA(pilot)},
    {.name = "--task", F_STR, FA(task)},
    {.name = "--task-result", F_STR, FA(task_result)},
    {.name = "--render", F_STR, FA(render_dir)},
    {.name = "--render-rate", F_DOUBLE, FA(render_rate_hz), 0.1, 1000.0, .given = FA(render_flag), .rc = 2},
    {.name = "--render-size", F_STR, FA(render_size), .given = FA(render_flag)},
    {.name = "--render-cameras", F_STR, FA(render_cams), .given = FA(render_flag)},
    {.name = "--render-video", F_WORD, FA(render_video), .yes = "on", .no = "off", .said = "on or off",
     .given = FA(render_flag), .rc = 2},
};
#undef FA

static const fly_flag *fly_flag_find(const char *name)
{
    for (size_t i = 0; i < sizeof fly_flags / sizeof fly_flags[0]; i++)
        if (!strcmp(fly_flags[i].name, name))
            return &fly_flags[i];
    return NULL;
}

/* One flag's value v into o: 0, or its exit status after saying what was
 * expected. */
static int fly_flag_set(fly_args *o, const fly_flag *f, const char *v)
{
    char *base = (char *)o;
    double *d = (double *)(base + f->off);
    int *n = (int *)(base + f->off), bad = 0;
    if (f->kind == F_DOUBLE)
        bad = app_parse_double("disim fly", f->name, v, f->lo, f->hi, d) != 0;
    else if (f->kind == F_WHOLE && (app_parse_double("disim fly", f->name, v, f->lo, f->hi, d) || *d != floor(*d))) {
        fprintf(stderr, "disim fly: %s: expected a whole number\n", f->name);
        bad = 1;
    } else if (f->kind == F_INT)
        bad = app_parse_int("disim fly", f->name, v, (int)f->lo, (int)f->hi, n) != 0;
    else if (f->kind == F_STR)
        *(const char **)(base + f->off) = v;
    else if (f->kind == F_SET)
        *n = (int)f->lo;
    else if (f->kind == F_WORD && strcmp(v, f->yes) && strcmp(v, f->no)) {
        fprintf(stderr, "disim fly: %s '%s': expected %s\n", f->name, v, f->said);
        bad = 1;
    } else if (f->kind == F_WORD)
        *n = !strcmp(v, f->yes);
    if (bad)
        return f->rc ? f->rc : 1;
    if (f->given)
        *(int *)(base + f->given) = 1;
    return 0;
}

static void fly_defaults(fly_args *o)
{
    memset(o, 0, sizeof *o);
    o->realtime = 1;
    o->duration_s = 60.0;
    o->rate_hz = 200.0;
    o->csv_rate_hz = 50.0;
    o->speed_kt = o->dir_deg = NAN;
    o->db = NULL; /* app_db_default: the scenario's engine's */
    o->turbulence = -1;
    o->gear = 1;
    o->sea_state = -1;
    o->wave_dir_deg = o->ship_speed_kt = NAN;
    o->seed = 1;
    o->sas = -1;
    o->lcm = -1;
    o->hold_after_s = 0.5;
    o->snapshot_max_s = 600.0;
    o->change_burst = 5;
    o->change_interval_s = 1.0;
    o->state_rate_hz = 50.0;
    o->render_rate_hz = 10.0;
    o->render_w = 640;
    o->render_h = 480;
    o->render_cameras = 1u << RENDER_CAM_DECK;
}

/* --render-size WxH and --render-cameras A,B: 0, or 2 after saying what
 * was expected. */
static int fly_render_flags(fly_args *o)
{
    core_err err = {0};
    if (o->render_size && render_size_parse(o->render_size, &o->render_w, &o->render_h, &err) != 0) {
        fprintf(stderr, "disim fly: --render-size %s\n", err.msg);
        return 2;
    }
    if (!o->render_cams)
        return 0;
    o->render_cameras = 0;
    char name[32];
    for (const char *p = o->render_cams;;) {
        size_t n = strcspn(p, ",");
        render_camera_kind k;
        snprintf(name, sizeof name, "%.*s", (int)(n < sizeof name ? n : sizeof name - 1), p);
        if (n >= sizeof name || render_camera_parse(name, &k, &err) != 0) {
            fprintf(stderr, "disim fly: --render-cameras '%s': %s\n", o->render_cams,
                    err.msg[0] ? err.msg : "a name too long");
            return 2;
        }
        o->render_cameras |= 1u << k;
        if (!p[n])
            return 0;
        p += n + 1;
    }
}

/* The flags together: 0, or the exit status after saying what does not go. */
static int fly_check(fly_args *o)
{
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

static int fly_parse(int argc, char **argv, fly_args *o)
{
    fly_defaults(o);
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        const fly_flag *f = fly_flag_find(a);
        int takes = f && f->kind != F_SET;
        if (!strcmp(a, "--pilot") && i + 2 < argc && !strcmp(argv[i + 1], "replay") && argv[i + 2][0] != '-') {
            o->pilot = argv[++i]; /* --pilot replay LOG */
            o->replay_log = argv[++i];
        } else if (f && (!takes || i + 1 < argc)) {
            int rc = fly_flag_set(o, f, takes ? argv[++i] : NULL);
            if (rc)
                return rc;
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
    int rc = fly_render_flags(o);
    if (rc)
        return rc;
    fly_scenario_pilot(o);
    return fly_check(o);
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

static int fly_render_open(fly_render *r, const fly_args *o, const sim_run_info *ri, const core_log *log, core_err *err)
{
    memset(r, 0, sizeof *r);
    if (!o->render_dir)
        return 0;
    r->dir = o->render_dir;
    if (app_scene_open(&r->scene, ri, RENDER_OVERLAY_HUD, log, err) != 0)
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

/* What one scenario flies: the scenario, the aircraft, the airwake fields,
 * the ship's motion and the flight. A reset or a load builds a new world
 * beside the running one, and replaces it only when the build succeeded. */
/* The airwake levels a flight flew from the database: from when (its own
 * time), free stream (-1) or a grid level. */
#define FLY_AIR_SPANS 6
typedef struct fly_air_span {
    int level;
    double t_s;
} fly_air_span;

typedef struct fly_world {
    sim_scenario *sc;
    hfm_aircraft *ac;
    cfd_field *fld;         /* the field flown from the start (NULL: the free stream) */
    int fld_shared;         /* fld is the run's --field (fly_ctx.field), not this world's own */
    cfd_field *later[4];    /* fields handed over in flight, by the rank of their level (kept while blended) */
    int waiting;            /* a finer level of the database's field may still come */
    int level;              /* the level flown (core_grid_level), -1 none */
    awdb *db;               /* where the marks of the fields waited for are (NULL: none) */
    double dir_rad;         /* the WOD direction of those fields */
    fly_air_span span[FLY_AIR_SPANS];
    int nspan;
    cfd_field *cpl[4];      /* the coupled field of the WOD, its isolated rotor's (NULL: none) and, for a
                               deck-zone pair, the whole domain's ship-only field and the zone's own */
    sim_interaction *inter; /* their interaction near the station (sim/interaction.c) */
    sim_world sw;           /* the ship's motion, the flight, what they were built from (run_info_t) */
} fly_world;

static void world_free(fly_world *w)
{
    if (w->db && w->sc)
        couple_flight_field_done(w->db, w->sc, w->dir_rad);
    sim_world_free(&w->sw);
    sim_interaction_destroy(w->inter);
    for (int i = 0; i < 4; i++)
        cfd_field_destroy(w->cpl[i]);
    for (int i = 0; i < 4; i++)
        cfd_field_destroy(w->later[i]);
    if (!w->fld_shared)
        cfd_field_destroy(w->fld);
    hfm_aircraft_destroy(w->ac);
    free(w->sc);
    memset(w, 0, sizeof *w);
}

/* A run of disim fly: its flags, the world flown, the database, the
 * trajectory, the loop (NULL: the flight stepped bare) and the renderer. */
typedef struct fly_ctx {
    const fly_args *o;
    const core_log *log;
    int tty;
    awdb *db;
    cfd_field *field; /* --field, read once for every world built */
    fly_world w;
    sim_traj *csv;
    sim_loop *loop;
    core_log loop_log; /* the loop's: its controls said (info) */
    fly_render fr;
    double t_end_s; /* the flight's last step's time */
} fly_ctx;

/* The level flown from t_s on (the spans said at the end). */
static void world_span(fly_world *w, int level, double t_s)
{
    if (w->nspan < FLY_AIR_SPANS)
        w->span[w->nspan++] = (fly_air_span){level, t_s};
}

/* Every poll_every steps while a finer level of the scenario's field may
 * come: ask the database again and hand a field that is now there to the
 * flight (it blends it in). 1 when one was handed over at this step, 0 if
 * not, < 0 with err. */
static int world_poll(awdb *db, fly_world *w, long step, double t_s, long poll_every, core_err *err)
{
    if (!w->waiting || step % poll_every != 0)
        return 0;
    cfd_field *f = NULL;
    core_grid_level level = CORE_GRID_QUICK;
    int have = w->level >= 0 ? core_grid_rank(w->level) : -1;
    int got = couple_flight_field(db, w->sc, w->sw.info.wod_dir_rad, have, &f, &level, &w->waiting, err);
    if (got <= 0)
        return got;
    int r = core_grid_rank(level);
    w->later[r] = f; /* each level comes once: have < r */
    if (sim_flight_set_field(w->sw.flight, f, err) != 0)
        return -1;
    w->level = level;
    world_span(w, level, t_s);
    return 1;
}

/* The flags over the scenario's keys (sim_world_build's overrides). */
static void world_overrides(const fly_args *o, const fly_world *w, sim_world_overrides *ov)
{
    sim_world_overrides_default(ov);
    ov->rate_hz = o->rate_hz;
    ov->wod_speed_mps = isnan(o->speed_kt) ? NAN : o->speed_kt * CORE_KT_TO_MPS;
    ov->wod_dir_rad = isnan(o->dir_deg) ? NAN : core_wod_wrap_deg(o->dir_deg) * CORE_DEG_TO_RAD;
    ov->seed = (unsigned long long)o->seed;
    ov->turbulence = o->turbulence;
    ov->sea_state = o->sea_state;
    ov->wave_dir_rad = isnan(o->wave_dir_deg) ? NAN : core_wod_wrap_deg(o->wave_dir_deg) * CORE_DEG_TO_RAD;
    ov->ship_speed_mps = isnan(o->ship_speed_kt) ? NAN : o->ship_speed_kt * CORE_KT_TO_MPS;
    ov->gear = o->gear;
    ov->start = o->start_deck ? SIM_START_DECK : SIM_START_HOVER;
    /* the replay pilot flies the SAS as the log's run had it (off where the
     * log does not say), unless --sas; the others as --sas or the aircraft file */
    ov->sas = o->replay_log && o->sas < 0 ? o->replay_sas > 0 : o->sas;
    ov->field = w->fld;
    ov->interaction = w->inter;
}

/* The database, claimed for the scenario's engine (awdb_engine_claim). */
static awdb *fly_db_open(const char *dir, const sim_scenario *sc, const core_log *log, core_err *err)
{
    awdb *db = awdb_open(dir, log, err);
    if (db && awdb_engine_claim(db, sc->engine == SIM_ENGINE_OPENFOAM ? "openfoam" : "embedded", err) != 0) {
        awdb_close(db);
        db = NULL;
    }
    return db;
}

/* The airwake of the WOD: --field, else the database's ship-only field
 * (requested when absent: w->waiting) and its coupled fields. */
static int world_fields(fly_ctx *c, fly_world *w, double speed, double dir, core_err *err)
{
    const fly_args *o = c->o;
    if (o->field) { /* read once: a world built again (disim ios) flies the same */
        if (!c->field && !(c->field = cfd_field_load(o->field, err)))
            return -1;
        w->fld = c->field;
        w->fld_shared = 1;
        return 0;
    }
    const char *dbdir = o->db ? o->db : app_db_default(w->sc);
    if (speed > 0.0) {
        if (!c->db && (core_mkdir_p(dbdir, err) != 0 || !(c->db = fly_db_open(dbdir, w->sc, c->log, err))))
            return -1;
        core_grid_level level = CORE_GRID_QUICK;
        int got = couple_flight_field(c->db, w->sc, dir, -1, &w->fld, &level, &w->waiting, err);
        if (got < 0)
            return -1;
        w->db = c->db;
        w->dir_rad = dir;
        w->level = got > 0 ? (int)level : -1;
        world_span(w, w->level, 0.0);
    }
    if (!c->db && access(dbdir, F_OK) == 0 && !(c->db = fly_db_open(dbdir, w->sc, c->log, err)))
        return -1; /* calm air: coupled fields (ground effect) without a ship-only one */
    if (c->db && couple_flight_coupled(c->db, w->sc, speed, dir, w->cpl, &w->inter, err) < 0)
        return -1;
    return 0;
}

/* The instructor's setup (disim ios) over the flags. */
static void world_setup(const sim_loop_setup *s, sim_world_overrides *ov)
{
    if (!s)
        return;
    if (s->start >= 0)
        ov->start = s->start;
    ov->start_heading_rad = s->heading_rad;
    if (!isnan(s->wod_speed_mps)) {
        ov->wod_speed_mps = s->wod_speed_mps;
        ov->wod_dir_rad = s->wod_dir_rad;
    }
    if (s->sea_state >= 0)
        ov->sea_state = s->sea_state;
    if (s->turbulence >= 0)
        ov->turbulence = s->turbulence;
}

static int world_build(fly_ctx *c, const char *path, const sim_loop_setup *setup, fly_world *w, core_err *err)
{
    const fly_args *o = c->o;
    memset(w, 0, sizeof *w);
    w->level = -1;
    if (!(w->sc = calloc(1, sizeof *w->sc))) {
        core_err_set(err, -1, "out of memory");
        goto fail;
    }
    sim_scenario *sc = w->sc;
    if (sim_scenario_load(path, sc, err) != 0)
        goto fail;
    if (!(w->ac = hfm_aircraft_load(sc->aircraft_path, c->log, err)))
        goto fail;
    sim_world_overrides ov;
    world_overrides(o, w, &ov);
    world_setup(setup, &ov);
    sim_run_info ri; /* the WOD flown */
    sim_world_run_info(sc, &ov, &ri);
    if (sc->wod_mode == SIM_WOD_SWEEP && (isnan(o->speed_kt) || isnan(o->dir_deg))) {
        core_err_set(err, -1, "%s: a WOD sweep: give the flight's --wod-speed-kt and --wod-dir-deg", path);
        goto fail;
    }
    if (world_fields(c, w, ri.wod_speed_mps, ri.wod_dir_rad, err) != 0)
        goto fail;
    hfm_gear gear;
    if (ov.start == SIM_START_DECK && !(o->gear && hfm_aircraft_gear(w->ac, &gear) == 0)) {
        core_err_set(err, -1, "--start deck: %s", o->gear ? "the aircraft file has no [gear] section" : "not with --no-gear");
        goto fail;
    }
    world_overrides(o, w, &ov); /* with the fields */
    world_setup(setup, &ov);
    if (o->has_start) { /* --pilot replay: where the replayed run starts */
        ov.has_station = 1;
        memcpy(ov.station_S_m, o->start_S_m, sizeof ov.station_S_m);
    }
    if (o->task) { /* --pilot auto: a phase task starts at its first point */
        ov.has_station = 1;
        memcpy(ov.station_S_m, sc->station_S_m, sizeof ov.station_S_m);
        if (sim_task_start_S(o->task, &sc->ship, ov.station_S_m, err) != 0)
            goto fail;
    }
    if (setup && setup->has_station) { /* a reposition */
        ov.has_station = 1;
        memcpy(ov.station_S_m, setup->station_S_m, sizeof ov.station_S_m);
    }
    if (sim_world_build(sc, w->ac, &ov, c->log, &w->sw, err) != 0)
        goto fail;
    return 0;
fail:
    world_free(w);
    return -1;
}

static void loop_world(const fly_world *w, sim_loop_world *lw)
{
    memset(lw, 0, sizeof *lw);
    lw->flight = w->sw.flight;
    lw->motion = w->sw.motion;
    snprintf(lw->scenario, sizeof lw->scenario, "%s", w->sc->name);
    lw->info = w->sw.info;
}

/* sim_loop's build (setup NULL: the flags alone) and rebuild: a new
 * world, the old one freed only once it stands. */
static int loop_rebuild(void *user, const char *path, const sim_loop_setup *setup, sim_loop_world *lw,
                        core_err *err)
{
    fly_ctx *c = user;
    fly_world nw;
    if (world_build(c, path, setup, &nw, err) != 0)
        return -1;
    world_free(&c->w);
    c->w = nw;
    loop_world(&c->w, lw);
    return 0;
}

static int loop_build(void *user, const char *path, sim_loop_world *lw, core_err *err)
{
    return loop_rebuild(user, path, NULL, lw, err);
}

/* sim_loop's builder: a world prepared on the loop's worker thread
 * (world_build touches only the new world, the database's handle and the
 * --field read once at the start, never c->w: the running flight's, which
 * the loop's thread polls), installed between two steps, the old one
 * freed on the worker. */
static int loop_prepare(void *user, const char *path, const sim_loop_setup *setup, void **world, sim_loop_world *lw,
                        core_err *err)
{
    fly_ctx *c = user;
    fly_world *nw = malloc(sizeof *nw);
    if (!nw)
        return core_err_set(err, -1, "out of memory");
    if (world_build(c, path, setup, nw, err) != 0) {
        free(nw);
        return -1;
    }
    loop_world(nw, lw);
    *world = nw;
    return 0;
}

static void *loop_install(void *user, void *world)
{
    fly_ctx *c = user;
    fly_world *nw = world, old = c->w;
    c->w = *nw;
    *nw = old; /* the handle now holds the world replaced */
    return nw;
}

static void loop_drop(void *user, void *world)
{
    (void)user;
    world_free(world);
    free(world);
}

/* What every flight of disim fly does after each step (the runner's
 * observer): the frame offered to --render, the trajectory's row at its
 * rate (and the row of the step that ended the flight, row_at_end), the
 * database polled once a simulated second for a field not ready (said
 * with say_ready), the loop's progress line on a terminal. A step that
 * ended the flight stops the run, what ended it kept in ended. */
typedef struct fly_obs {
    fly_ctx *c;
    long poll_every, n_stepped;
    int row_at_end, say_ready;
    int progress, lcm_on; /* the loop's progress line (on a terminal), its LCM on */
    char ended[256];
} fly_obs;

static void fly_progress(const fly_obs *b, const sim_flight_out *out)
{
    sim_loop_report lr;
    sim_loop_report_get(b->c->loop, &lr);
    fprintf(stderr, "\r\033[Kfly: t %.0f s  x %.2f y %.2f z %.2f m (S)  roll %.1f pitch %.1f deg  %.1fx real time  "
                    "%ld overruns%s%s%s%s",
            out->t_s, out->pos_S_m[0], out->pos_S_m[1], out->pos_S_m[2], out->euler_E_rad[0] * CORE_RAD_TO_DEG,
            out->euler_E_rad[1] * CORE_RAD_TO_DEG, lr.pace.realtime_factor, lr.pace.overruns,
            out->air_flags & SIM_AIR_FREE_STREAM ? "  free stream" : "", out->air_grid >= 0 ? "  " : "",
            out->air_grid >= 0 ? core_grid_name(out->air_grid) : "", out->air_grid >= 0 ? " field" : "");
    if (lr.held && b->lcm_on)
        fprintf(stderr, "  input held");
}

static int fly_observe(void *user, const sim_flight_out *out, int st, core_err *err)
{
    fly_obs *b = user;
    fly_ctx *c = b->c;
    if (st < 0)
        return 0; /* the run fails with err */
    b->n_stepped++;
    fly_render_offer(&c->fr, out); /* a copy: the flight is the same without it */
    if (sim_traj_row(c->csv, out, st > 0 && b->row_at_end, err) != 0)
        return -1;
    if (st > 0) { /* a crash or a roll-over ended the flight: said by the caller, the trajectory kept */
        snprintf(b->ended, sizeof b->ended, "%.250s", err->msg);
        return 1;
    }
    /* the running world (a reset or a load may have replaced it) */
    int polled = world_poll(c->w.db, &c->w, out->step, out->t_s, b->poll_every, err); /* c->db: the worker's */
    if (polled < 0)
        return -1;
    c->t_end_s = out->t_s;
    if (polled > 0 && b->say_ready)
        fprintf(stderr, "%sfly: the %s airwake field is ready at t = %.1f s: blended in over 3 s%s\n",
                b->progress ? "\r\033[K" : "", core_grid_name(c->w.level), out->t_s,
                c->w.waiting ? " (a finer one to come)" : "");
    if (b->progress && b->n_stepped % b->poll_every == 0)
        fly_progress(b, out);
    return 0;
}

/* Fly pilot from the world's start (its row and frame first) for
 * max_steps (< 0: the loop's duration), through the loop where there is
 * one, observed by b: a SIM_RUN_* end, or < 0 with err. */
static int fly_fly(fly_ctx *c, const sim_pilot *pilot, long max_steps, fly_obs *b, sim_flight_out *out,
                   core_err *err)
{
    b->c = c;
    b->poll_every = (long)llround(c->o->rate_hz); /* the database, once a simulated second */
    sim_flight_state(c->w.sw.flight, out);
    if (sim_traj_row(c->csv, out, 1, err) != 0)
        return -1;
    fly_render_offer(&c->fr, out); /* frame 0 at t = 0 */
    sim_run_opts ro;
    sim_run_opts_default(&ro);
    ro.max_steps = max_steps;
    ro.stop = &fly_stop;
    ro.observe = fly_observe;
    ro.observe_user = b;
    if (c->loop)
        sim_loop_run_opts(c->loop, &ro);
    return sim_run(c->loop ? NULL : c->w.sw.flight, pilot, &ro, out, err);
}

/* The loop's options for duration_s: the stations fly it, or (source_id)
 * a pilot of disim fly's whose inputs go out as that station's. LCM in
 * real time unless --no-lcm, or with --lcm. 0, or < 0 with err. */
static int fly_loop_opts(const fly_args *o, double duration_s, const char *source_id, sim_loop_opts *lo,
                         core_err *err)
{
    sim_loop_opts_default(lo);
    lo->rate_hz = o->rate_hz;
    lo->realtime = o->realtime;
    lo->duration_s = duration_s;
    lo->state_rate_hz = o->state_rate_hz;
    lo->lcm = o->lcm >= 0 ? o->lcm : o->realtime;
    lo->lcm_url = o->lcm_url;
    lo->log_path = o->log;
    lo->replay_path = o->replay;
    lo->scenario_path = o->scen;
    lo->pilot_source_id = source_id;
    lo->pilots.hold_after_s = o->hold_after_s;
    lo->rebuild = loop_rebuild;
    lo->builder.prepare = loop_prepare;
    lo->builder.install = loop_install;
    lo->builder.drop = loop_drop;
    lo->snapshot_max_s = o->snapshot_max_s;
    lo->change_burst = o->change_burst;
    lo->change_interval_s = o->change_interval_s;
    lo->wait_after_end = o->wait_after_crash;
    return o->stations ? sim_pilots_opts_parse(&lo->pilots, o->stations, err) : 0;
}

static int fly_loop_create(fly_ctx *c, const sim_loop_opts *lo, core_err *err)
{
    sim_loop_world lw;
    loop_world(&c->w, &lw);
    c->loop_log = *c->log;
    if (c->loop_log.max_level < CORE_LOG_INFO)
        c->loop_log.max_level = CORE_LOG_INFO;
    return (c->loop = sim_loop_create(lo, &lw, loop_build, c, &c->loop_log, err)) ? 0 : -1;
}

/* The free stream, the field, or the field to come, as the start says
 * (the level of a field that stays: fly_air_said at the end). */
static const char *fly_air(const fly_world *w)
{
    if (w->fld && w->waiting)
        return w->level == CORE_GRID_QUICK ? "quick airwake field until a finer one is built"
                                           : "airwake field until a finer one is built";
    return w->fld ? "airwake field" : w->waiting ? "free stream until the airwake field is built" : "free stream";
}

/* The levels flown from the database, said at the end: "free stream
 * 0.0-17.0 s, quick 17.0-95.0 s, coarse 95.0-120.0 s". */
static void fly_air_said(const fly_ctx *c)
{
    const fly_world *w = &c->w;
    if (!w->db || w->nspan == 0)
        return;
    fprintf(stderr, "fly: the airwake flown:");
    for (int i = 0; i < w->nspan; i++) {
        double t1 = i + 1 < w->nspan ? w->span[i + 1].t_s : c->t_end_s;
        fprintf(stderr, "%s %s %.1f-%.1f s", i ? "," : "", w->span[i].level < 0 ? "free stream"
                : core_grid_name(w->span[i].level), w->span[i].t_s, t1);
    }
    fprintf(stderr, "%s\n", !w->waiting ? "" : w->level >= 0 ? " (a finer field still to come)" : " (a field still to come)");
}

/* The task result's prefix (--task-result PREFIX, else beside --csv:
 * OUT_task), "" for none. */
static void fly_task_prefix(const fly_args *o, char *pre, size_t n)
{
    pre[0] = '\0';
    if (o->task_result)
        snprintf(pre, n, "%s", o->task_result);
    else if (o->csv)
        snprintf(pre, n, "%.*s_task", (int)(strlen(o->csv) - (strlen(o->csv) > 4 &&
                 !strcmp(o->csv + strlen(o->csv) - 4, ".csv") ? 4 : 0)), o->csv);
}

/* Before the flight: every output (--csv, --log, the task's result) may
 * be written, that is, is a regular file or new, is no input of the run
 * (the scenario, its aircraft, ship and task files, --field, the logs
 * read) and is named once. 0, or < 0 with err. */
static int fly_outputs_check(const fly_args *o, const sim_scenario *sc, core_err *err)
{
    char pre[1024], res[2][1100];
    fly_task_prefix(o, pre, sizeof pre);
    const int task_out = pre[0] && o->pilot && !strcmp(o->pilot, "auto");
    snprintf(res[0], sizeof res[0], "%s.csv", pre);
    snprintf(res[1], sizeof res[1], "%s.json", pre);
    const char *out[][2] = {{"--csv", o->csv}, {"--log", o->log}, {"the task's result", task_out ? res[0] : NULL},
                            {"the task's result", task_out ? res[1] : NULL}};
    const char *in[] = {o->scen, o->field, o->replay, o->replay_log, o->task, sc ? sc->aircraft_path : NULL,
                        sc ? sc->ship_path : NULL, sc && sc->task_path[0] ? sc->task_path : NULL};
    const int nout = (int)(sizeof out / sizeof out[0]), nin = (int)(sizeof in / sizeof in[0]);
    for (int i = 0; i < nout; i++) {
        if (!out[i][1])
            continue;
        core_err why = {0};
        if (core_output_check(out[i][1], &why) != 0)
            return core_err_set(err, -1, "%s %s", out[i][0], why.msg);
        for (int j = 0; j < nin; j++)
            if (core_path_same(out[i][1], in[j]))
                return core_err_set(err, -1, "%s %s: an input of this run (%s): expected another name", out[i][0],
                                    out[i][1], in[j]);
        for (int j = 0; j < i; j++)
            if (core_path_same(out[i][1], out[j][1]))
                return core_err_set(err, -1, "%s %s: named as %s too: expected a name for each output", out[i][0],
                                    out[i][1], out[j][0]);
    }
    return 0;
}

/* The task's result written (--task-result PREFIX, else beside --csv:
 * OUT_task.csv, .json) and said. 0, or < 0 with err. */
static int fly_auto_report(const fly_args *o, const sim_task *task, const sim_task_result *r, core_err *err)
{
    char res[2][1100], pre[1024];
    fly_task_prefix(o, pre, sizeof pre);
    if (pre[0]) {
        snprintf(res[0], sizeof res[0], "%s.csv", pre);
        snprintf(res[1], sizeof res[1], "%s.json", pre);
        if (sim_task_result_write(task, r, res[0], res[1], err) != 0)
            return -1;
        fprintf(stderr, "fly: the task's result in %s and %s\n", res[0], res[1]);
    }
    if (task->kind == SIM_TASK_LAND && r->touched)
        fprintf(stderr, "fly: touchdown %s at %.2f s (descent from %.2f s): sink %.2f m/s, drift %.2f m/s, %.2f m from "
                        "the spot\n",
                r->touchdown_grade == 2 ? "desired" : r->touchdown_grade == 1 ? "adequate" : "not met",
                r->t_touchdown_s, r->t_descent_s, r->sink_mps, r->drift_mps, r->dist_m);
    else if (task->kind == SIM_TASK_LAND)
        fprintf(stderr, "fly: no touchdown by %.1f s\n", r->t_s);
    fprintf(stderr, "fly: task %s at %.1f s%s: within desired since %.2f s, adequate since %.2f s; largest error after "
                    "%.0f s %.2f m, height %.2f m, heading %.1f deg; %ld steps with a control at a stop\n",
            r->grade == 2 ? "desired" : r->grade == 1 ? "adequate" : "not met", r->t_s, fly_stop ? " (stopped)" : "",
            r->t_desired_s, r->t_adequate_s, task->desired.time_s, r->max_err_pos_m, r->max_err_height_m,
            r->max_err_heading_rad * CORE_RAD_TO_DEG, r->stop_steps);
    return 0;
}

/* --pilot auto: the automated pilot flies the task headless, as fast as
 * it can (the task's length unless --duration), the trajectory to --csv;
 * with --log, --lcm or --realtime through the loop as station "auto" (the
 * log and LCM carry the run as a station's flight, the trajectory the one
 * flown straight); the task's grade and errors said at the end. 0, 1 when
 * a crash or a roll-over ended the flight (said), or < 0 with err. */
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
    po.wod_speed_mps = w->sw.info.wod_speed_mps;
    po.wod_dir_rad = w->sw.info.wod_dir_rad;
    po.sas = sim_sas_engaged(sim_flight_sas(w->sw.flight)); /* its gains know the SAS the flight has */
    hfm_gear gear;
    po.gear = o->gear && hfm_aircraft_gear(w->ac, &gear) == 0; /* the flight has the gear (sim_world_build) */
    sim_flight_inputs in;
    sim_flight_trim_inputs(w->sw.flight, &in);
    sim_pilot_auto *p = sim_pilot_auto_create(w->ac, &task, &po, &in, c->log, err);
    if (!p)
        return -1;
    sim_flight_out out; /* the attitudes it aims at: the flight's trim in its air */
    sim_flight_state(w->sw.flight, &out);
    int rc = -1;
    if (!o->start_deck && sim_pilot_auto_set_trim_state(p, &out) != 0) {
        core_err_set(err, -1, "fly: the flight's start is not a hover's trimmed state");
        goto out;
    }
    double T = o->duration_set ? o->duration_s : sim_task_length_s(&task);
    sim_loop_opts lo; /* its inputs go out as station "auto"'s */
    if ((o->log || o->lcm == 1 || o->realtime) && (fly_loop_opts(o, T + 2.0 / o->rate_hz, "auto", &lo, err) != 0 ||
                                                   fly_loop_create(c, &lo, err) != 0))
        goto out;
    fprintf(stderr, "fly: %s + %s, WOD %.1f kt from %.0f deg, sea state %d, %s, the automated pilot flies %s for %.0f s%s\n",
            w->sc->ship.name, hfm_aircraft_name(w->ac), w->sw.info.wod_speed_mps / CORE_KT_TO_MPS,
            w->sw.info.wod_dir_rad * CORE_RAD_TO_DEG, w->sw.info.sea.state, fly_air(w), o->task, T,
            c->loop ? (o->realtime ? ", in real time" : ", through the loop") : "");
    /* the task over (settled on the deck, touched down, its last hold
     * flown) ends the run before the step, a crash or a roll-over after it */
    fly_obs ob = {.row_at_end = 1, .say_ready = 1};
    sim_pilot pilot = sim_pilot_auto_pilot(p);
    if (fly_fly(c, &pilot, (long)llround(T * o->rate_hz), &ob, &out, err) < 0)
        goto out;
    sim_pilot_auto_step(p, &out, &in); /* grades the last state */
    if (sim_traj_commit(c->csv, err) != 0 || (c->loop && sim_loop_finish(c->loop, err) != 0))
        goto out;
    if (c->loop)
        fprintf(stderr, "fly: the run logged to %s\n", o->log);
    sim_task_result r;
    sim_pilot_auto_result(p, &r);
    if (fly_auto_report(o, &task, &r, err) != 0)
        goto out;
    rc = 0;
    if (ob.ended[0]) {
        fprintf(stderr, "fly: the flight ended at %.2f s: %s\n", out.t_s, ob.ended);
        core_err_set(err, 1, "%s", ob.ended);
        rc = 1;
    }
out:
    sim_pilot_auto_destroy(p);
    return rc;
}

/* --pilot replay LOG: the replay pilot re-flies LOG's run relative to the
 * deck (sim/pilot_replay.c) headless, as fast as it can, for the log's
 * length unless --duration; the trajectory to --csv; how far it stayed
 * from the reference said at the end, per phase. 0, 1 when a crash or a
 * roll-over ended the flight (said), or < 0 with err. */
static int fly_replay(fly_ctx *c, const sim_log *ref, core_err *err)
{
    const fly_args *o = c->o;
    fly_world *w = &c->w;
    sim_log_summary info;
    sim_log_info(ref, &info);
    sim_pilot_replay_opts po;
    sim_pilot_replay_opts_default(&po);
    po.pilot.rate_hz = o->rate_hz;
    po.pilot.wod_speed_mps = w->sw.info.wod_speed_mps;
    po.pilot.wod_dir_rad = w->sw.info.wod_dir_rad;
    po.feed_controls = o->feed_controls;
    po.pilot.sas = sim_sas_engaged(sim_flight_sas(w->sw.flight)); /* the gains scheduled with it */
    sim_flight_inputs in;
    sim_flight_trim_inputs(w->sw.flight, &in);
    sim_pilot_replay *p = sim_pilot_replay_create(w->ac, ref, &po, &in, c->log, err);
    if (!p)
        return -1;
    sim_flight_out out; /* the attitude references of the flight's own trim */
    sim_flight_state(w->sw.flight, &out);
    if (!out.on_deck && sim_pilot_replay_set_trim_state(p, &out) != 0)
        fprintf(stderr, "fly: warning: the replay pilot keeps the uniform-WOD trim's attitudes\n");
    double T = o->duration_set ? o->duration_s : info.t1_s;
    fprintf(stderr, "fly: %s + %s, WOD %.1f kt from %.0f deg, sea state %d, the replay pilot re-flies %s (%ld states, "
                    "%.2f s, controls from %s%s) for %.2f s\n",
            w->sc->ship.name, hfm_aircraft_name(w->ac), w->sw.info.wod_speed_mps / CORE_KT_TO_MPS,
            w->sw.info.wod_dir_rad * CORE_RAD_TO_DEG, w->sw.info.sea.state, o->replay_log, info.n_states, info.t1_s,
            info.n_inputs ? "the station's inputs" : "the flown states", o->feed_controls ? ", fed forward" : "", T);
    fprintf(stderr, "fly: the SAS %s; the log's run flew it %s\n", po.pilot.sas ? "on" : "off",
            info.sas > 0 ? "on" : info.sas == 0 ? "off" : "unknown (the log does not say: flown off)");
    fly_obs ob = {.row_at_end = 0, .say_ready = 0}; /* a crash ends the run (its row at the rate alone) */
    sim_pilot pilot = sim_pilot_replay_pilot(p);
    int rc = -1;
    if (fly_fly(c, &pilot, (long)llround(T * o->rate_hz), &ob, &out, err) < 0)
        goto out;
    if (ob.ended[0])
        fprintf(stderr, "fly: the flight ended at %.2f s: %s\n", out.t_s, ob.ended);
    sim_pilot_replay_step(p, &out, &in); /* counts the last state */
    if (sim_traj_commit(c->csv, err) != 0)
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
out:
    sim_pilot_replay_destroy(p);
    return rc;
}

/* The station flight's start said: the world, the pacing, LCM, the
 * coupled interaction or its absence. */
static void fly_station_start(const fly_ctx *c, int lcm_on)
{
    const fly_args *o = c->o;
    const fly_world *w = &c->w;
    const char *url = disim_lcm_url(o->lcm_url);
    char shown[256];
    core_escape(url, shown, sizeof shown);
    fprintf(stderr, "fly: %s + %s, WOD %.1f kt from %.0f deg, sea state %d, %s, %s, %.0f Hz, %.0f s%s%s%s%s%s\n",
            w->sc->ship.name, hfm_aircraft_name(w->ac), w->sw.info.wod_speed_mps / CORE_KT_TO_MPS,
            w->sw.info.wod_dir_rad * CORE_RAD_TO_DEG, w->sw.info.sea.state, fly_air(w),
            o->realtime ? "real time" : "as fast as it can", o->rate_hz, o->duration_s, lcm_on ? ", LCM " : "",
            lcm_on ? shown : "",
            !lcm_on ? "" : strstr(url, "ttl=0") ? " (this host only)" : " (other hosts: any of them can fly and "
                                                                          "command this simulator)",
            o->replay ? ", inputs from " : "", o->replay ? o->replay : "");
    if (w->inter) {
        sim_interaction_info ii;
        sim_interaction_state(w->inter, &ii);
        fprintf(stderr, "fly: the coupled rotor interaction near the station (the database's coupled field of %.0f N, "
                        "hub (%.2f, %.2f, %.2f) m in S%s)\n",
                ii.thrust_field_N, ii.hub_S_m[0], ii.hub_S_m[1], ii.hub_S_m[2], w->cpl[3] ? ", deck zone" : "");
    } else if (c->db)
        fprintf(stderr, "fly: no coupled fields for this WOD in the database: the ship-only airwake alone\n");
}

/* The station flight's end said: the pacing, LCM and the stations, the gear. */
static void fly_station_end(const fly_ctx *c, const sim_loop_report *lr, const fly_obs *b, const sim_flight_out *out)
{
    const fly_args *o = c->o;
    const sim_pacer_report *ps = &lr->pace;
    fprintf(stderr, "%sfly: %.2f s flown in %.2f s (%.1fx real time), %ld steps, %ld overruns, step p50 %.0f us p99 %.0f "
                    "us max %.0f us; ends at (%.2f, %.2f, %.2f) m in S%s\n",
            c->tty ? "\r\033[K" : "", lr->run_s, ps->wall_s, ps->realtime_factor, b->n_stepped, ps->overruns,
            1e6 * ps->step_p50_s, 1e6 * ps->step_p99_s, 1e6 * ps->step_max_s, out->pos_S_m[0], out->pos_S_m[1],
            out->pos_S_m[2], fly_stop ? " (stopped)" : "");
    if (o->realtime)
        fprintf(stderr, "fly: wake-up after the deadline: p99 %.0f us, max %.0f us\n", 1e6 * ps->late_p99_s,
                1e6 * ps->late_max_s);
    if (b->lcm_on || o->log || o->replay) {
        const sim_pilots *pl = sim_loop_pilots(c->loop);
        fprintf(stderr, "fly: LCM %lld sent, %lld received, %lld logged, %lld controls refused", lr->sent, lr->received,
                lr->logged, lr->control_refused);
        if (lr->builds_on_worker || lr->refused_busy || lr->refused_rate)
            fprintf(stderr, " (%lld busy, %lld past the rate limit); %lld worlds built on the loop's worker",
                    lr->refused_busy, lr->refused_rate, lr->builds_on_worker);
        for (int i = 0; i < sim_pilots_count(pl); i++) {
            sim_pilot_station st;
            sim_pilots_station(pl, i, &st);
            fprintf(stderr, "; station %s: %lld taken, %lld refused, %lld missing", st.id, st.received, st.refused,
                    st.gaps);
        }
        if (sim_pilots_refused_unknown(pl))
            fprintf(stderr, "; %lld refused from no readable station", sim_pilots_refused_unknown(pl));
        /* after a crash the status's message is the crash's, said below */
        fprintf(stderr, "%s%s\n", lr->message[0] && !b->ended[0] ? "; last refusal: " : "",
                b->ended[0] ? "" : lr->message);
    }
    if (out->nlegs > 0)
        fprintf(stderr, "fly: gear: %s at the end%s%s\n", out->on_deck ? "on the deck" : "off the deck",
                out->contact_flags ? "; " : "", out->contact_what);
}

/* The stations fly (or the replayed log's inputs through them): the
 * loop for --duration, paced in real time or as fast as it can, until
 * the duration, a crash (its last state into the trajectory, the log
 * finished as at the end) or a signal. 0, 3 when a crash or a roll-over
 * ended the flight, 1 when only the renderer failed, or < 0 with err. */
static int fly_station(fly_ctx *c, core_err *err)
{
    const fly_args *o = c->o;
    sim_loop_opts lo;
    if (fly_loop_opts(o, o->duration_s, NULL, &lo, err) != 0)
        return -1;
    /* before the loop's clock starts: locking the memory takes a while */
    if (fly_render_open(&c->fr, o, &c->w.sw.info, c->log, err) != 0)
        return -1;
    if (o->realtime) { /* what the system grants a real-time loop, said either way */
        char rt[256];
        sim_pacer_os_realtime(50, rt, sizeof rt);
        fprintf(stderr, "fly: %s\n", rt);
    }
    if (fly_loop_create(c, &lo, err) != 0)
        return -1;
    fly_obs ob = {.row_at_end = 1, .say_ready = 1, .progress = c->tty, .lcm_on = lo.lcm};
    fly_station_start(c, ob.lcm_on);
    signal(SIGINT, on_signal);
    signal(SIGTERM, on_signal);
    sim_flight_out out;
    sim_pilot pilot = sim_loop_own_pilot(c->loop);
    if (fly_fly(c, &pilot, -1, &ob, &out, err) < 0 || sim_loop_finish(c->loop, err) != 0 ||
        sim_traj_commit(c->csv, err) != 0)
        return -1;
    sim_loop_report lr;
    sim_loop_report_get(c->loop, &lr);
    fly_station_end(c, &lr, &ob, &out);
    int rc = 0;
    if (ob.ended[0]) { /* stopped cleanly: the log and the trajectory are written */
        fprintf(stderr, "disim fly: the flight ended: %s\n", ob.ended);
        rc = 3;
    }
    if (fly_render_close(&c->fr, &lr, err) != 0) { /* after the flight's own outputs */
        fprintf(stderr, "disim fly: %s\n", err->msg);
        rc = rc ? rc : 1;
    }
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
    fly_ctx ctx;
    memset(&ctx, 0, sizeof ctx);
    ctx.o = &o;
    ctx.log = &log;
    ctx.tty = tty;
    rc = -1;
    sim_log *replay_ref = NULL; /* --pilot replay: read first, the flight starts where it does */
    sim_log_frames rf; /* --replay-inputs: checked before anything is built or written */
    if (o.replay && sim_log_check_frames(o.replay, &rf, &err) != 0)
        goto done;
    if (o.replay_log) {
        sim_log_sample s0;
        if (!(replay_ref = sim_log_load(o.replay_log, &err)))
            goto done;
        sim_log_sample_at(replay_ref, 0.0, &s0);
        memcpy(o.start_S_m, s0.pos_S_m, sizeof o.start_S_m);
        sim_log_summary li;
        sim_log_info(replay_ref, &li);
        o.replay_sas = li.sas;
        o.has_start = 1;
    }
    if (world_build(&ctx, o.scen, NULL, &ctx.w, &err) != 0 || fly_outputs_check(&o, ctx.w.sc, &err) != 0 ||
        (o.csv && !(ctx.csv = sim_traj_create(o.csv, o.rate_hz, o.csv_rate_hz, &err))))
        goto done;
    rc = o.replay_log ? fly_replay(&ctx, replay_ref, &err) : o.pilot ? fly_auto(&ctx, &err) : fly_station(&ctx, &err);
    if (rc >= 0)
        fly_air_said(&ctx);
    if (o.pilot && rc > 0)
        rc = 3; /* a crash or a roll-over ended the flight (said) */
done:
    if (rc < 0) {
        fprintf(stderr, "%sdisim fly: %s\n", tty ? "\r\033[K" : "", err.msg);
        rc = 1;
    }
    fly_render_close(&ctx.fr, NULL, &err);
    sim_traj_destroy(ctx.csv);
    sim_loop_destroy(ctx.loop);
    world_free(&ctx.w);
    cfd_field_destroy(ctx.field);
    awdb_close(ctx.db);
    sim_log_destroy(replay_ref);
    return rc;
}
