/*
 * couple.h -- the ship-rotor coupling loop (seed paper section 2.5) and the
 * trim callback that the candidate SHOL procedure calls.
 *
 * Two-way: trim in the free-air WOD -> CFD with the actuator disk loaded from
 * that trim (thrust, hub position and shaft tilt from hfm_rotor_disk) at the
 * hover-over-spot station -> velocities back to the flight model -> re-trim,
 * until controls and attitudes change less than 5 % between two iterations.
 * The rotor's own induced velocity is not counted twice: by default the
 * flight model keeps its Pitt-Peters inflow and takes from CFD the
 * interaction velocity, the coupled field minus the isolated rotor (same
 * thrust, disk, wind and grid, no ship); `direct` uses the coupled field as
 * the air itself.
 *
 * One-way: the ship-only airwake (no disk). A ship-only field without the
 * rotor is independent of the wind speed when scaled by it (high-Reynolds
 * bluff-body flow; checked by the cfd tests), so one field per direction at
 * a reference speed serves every speed: velocities scale with V.
 *
 * Fields come from the airwake database (awdb_fields); missing ones are
 * queued for the builder, which the caller's launcher starts whenever none
 * serves the database.
 */
#ifndef DISIM_COUPLE_H
#define DISIM_COUPLE_H

#include "awdb.h"
#include "core.h"
#include "hfm.h"
#include "shol.h"
#include "sim.h"

#ifdef __cplusplus
extern "C" {
#endif


typedef struct couple_settings {
    core_coupling_mode mode;
    int direct;               /* two-way: 1 uses the coupled field directly */
    core_grid_level grid;
    int max_iter;             /* coupling iterations (default 6) */
    double tol_frac;          /* change between iterations (default 0.05) */
    double ref_speed_mps;     /* one-way: the speed of the ship-only fields (15 m/s) */
    double station_S_m[3];    /* CG at the hover-over-spot station */
    double wait_timeout_s;    /* longest wait for one field (default 3 h) */
    /* Called about every 0.2 s while a field is waited for (NULL: never),
     * with the key waited for and the seconds waited so far, e.g. to show
     * the builder's progress on a terminal. */
    void (*wait_fn)(void *user, const awdb_key *key, double waited_s);
    void *wait_user;
    /* How to start a builder when none serves the database
     * (awdb_fields_opts.launch; NULL: never start one). */
    int (*launch)(void *user, const char *db_dir);
    void *launch_user;
    int uniform_disk;         /* 1: uniform disk (seed paper eq. 5) instead of the trim's blade loads */
    /* 1 (default): two-way with the interaction velocity starts a point
     * (iteration 0) from the trim in the interaction of the last coupled
     * point of the same direction within 3 m/s (not the same speed),
     * instead of free air; the first coupled iteration then takes its own
     * fields whole. */
    int seed_from_previous;
    /* 1 (default): two-way with the interaction velocity starts a point
     * that has no previous coupled point to seed it (a direction's first)
     * from the one-way trim, i.e. in the ship-only airwake scaled to the
     * speed, instead of free air. The first coupled disk then already
     * carries the airwake's loads. */
    int seed_one_way;
    /* 1: two-way builds its coupled and isolated fields in the deck zone
     * only (cfd_airwake_spec.zone: 5 R round the hub, 4 R above it), with
     * the direction's ship-only field at ref_speed_mps, scaled to the
     * speed, as the zone's boundary, and the interaction velocity gets
     * the difference between the whole domain's ship-only field and the
     * zone's own (one more field per direction), so the zone adds only what
     * the rotor changes; 0 (default): the whole domain. Not with direct. */
    int zone;
} couple_settings;

void couple_settings_default(couple_settings *s);

/* A database key (ship, WOD and grid already set by the caller) gets the
 * rotor of a flight-model disk: thrust, hub station, radius, shaft tilt and,
 * with loaded = 1, the blade loads resampled to the key's table (r/R =
 * (i + 0.5) / AWDB_LOAD_NR, psi = 2 pi j / AWDB_LOAD_NPSI, linear in r,
 * periodic linear in psi; zero inside the root cut), the azimuthal mean of
 * the in-plane forces as the swirl shape and their moment as the torque.
 * Returns < 0 if the disk carries no thrust. */
int couple_key_set_rotor(const hfm_aircraft *ac, const hfm_disk *d, int loaded, awdb_key *key);

/* Trim in the free-air WOD at a CG station and give the key the rotor of that
 * trim (as couple_key_set_rotor), e.g. for a single `disim airwake` case.
 * 0 ok; > 0 the trim did not converge; < 0 fatal (err). */
int couple_free_air_rotor(const hfm_aircraft *ac, const double station_S_m[3], double wod_speed_mps,
                          double wod_dir_rad, int loaded, awdb_key *key, core_err *err);

/* One iteration of the loop: what the flight model trimmed to. */
typedef struct couple_iter {
    double thrust_N;
    hfm_controls ctl;
    double phi_rad, theta_rad;
    double change_frac;       /* largest change from the previous iteration: of each control
                               * relative to max(|value|, 20 % of travel), of each attitude
                               * relative to max(|value|, 5 deg) */
} couple_iter;

#define COUPLE_MAX_ITER 16

/* The start of a coupled point (its iteration 0). */
typedef enum couple_seed {
    COUPLE_SEED_FREE_AIR = 0, /* the free-air trim */
    COUPLE_SEED_PREVIOUS = 1, /* the interaction of the previous coupled point of the direction */
    COUPLE_SEED_ONE_WAY = 2,  /* the one-way trim (ship-only airwake scaled to the speed) */
} couple_seed;

/* The result of a coupled trim at one WOD. */
typedef struct couple_point {
    double wod_speed_mps, wod_dir_rad;
    int converged;            /* the last trim converged */
    int coupling_converged;   /* changes fell below tol_frac */
    int n_iter;
    couple_seed seed;         /* what iteration 0 was trimmed in */
    double seed_speed_mps;    /* COUPLE_SEED_PREVIOUS: that point's speed (0 for a hover in calm air) */
    couple_iter iter[COUPLE_MAX_ITER];
    hfm_trim_result trim;     /* the final trim */
} couple_point;

typedef struct couple_ctx couple_ctx;

/* A coupling context over an aircraft, a ship and a database (all kept by
 * the caller and outliving the context). NULL with err on failure. */
couple_ctx *couple_create(const hfm_aircraft *ac, const core_ship *ship, awdb *db,
                          const couple_settings *s, const core_log *log, core_err *err);
void couple_destroy(couple_ctx *c);

/* Trim at one WOD in the coupled (or one-way) airwake. 0: trimmed (see
 * p->converged), > 0: the trim did not converge, < 0: fatal (err). */
int couple_trim(couple_ctx *c, double wod_speed_mps, double wod_dir_rad, couple_point *p,
                core_err *err);

/* One-way: queue the ship-only fields of these directions at once, so the
 * builder can run them side by side while the sweep waits for the first. */
int couple_prefetch(couple_ctx *c, const double *dirs_rad, int n, core_err *err);

/* The shol_trim_fn for shol_envelope_run; user is a couple_ctx. Every point
 * is kept in the context (couple_history) for the report. */
int couple_shol_trim(void *user, double wod_speed_mps, double wod_dir_rad, shol_trim_point *out);
/* The points trimmed so far (in call order). */
const couple_point *couple_history(const couple_ctx *c, int *n);

/* An airwake field the context loaded, with its solver state, for the
 * report (plain data). */
typedef struct couple_field_info {
    char name[200];            /* the database entry (file name without .h5) */
    double wod_speed_mps, wod_dir_deg;
    char rotor[32];            /* "off", "uniform", "loaded" */
    int iterations, converged; /* converged: residuals and monitors met */
    int averaged;              /* > 0: not converged; the mean of this many last iterations */
    int steady_mean;           /* 1: ... stopped early with a steady mean (cfd_config.avg_stop) */
    double mean_drift;         /* averaged fields: how far the mean still moves at the deck
                                  monitors, / WOD speed (cfd_result.mean_drift) */
    double mean_change;        /* averaged fields: how far the mean moved from the window before
                                  at the deck monitors, / WOD speed; < 0 not known
                                  (cfd_result.mean_change) */
    double residual_continuity;
    int mirrored;              /* 1: the mirror image of the opposite direction's field
                                  (cfd_meta.mirrored); the other members are that field's */
    char engine_version[64];   /* "" for the embedded engine; else its name and version
                                  ("OpenFOAM v1912 ...", cfd_meta.engine_version) */
    double monitor_change;     /* the OpenFOAM engine: the deck monitors' last change over 50
                                  iterations, / WOD speed (cfd_result.monitor_change; < 0 unknown) */
    char rotor_model[32];      /* cfd_meta.rotor_model ("rotorDisk"; "" the engine's disk) */
} couple_field_info;

/* The fields loaded so far, each once, in the order first loaded. */
const couple_field_info *couple_fields(const couple_ctx *c, int *n);
/* The fields of one or two coupling contexts (f2 may be NULL with n2 0) as
 * Markdown for a report: a summary (how many converged, averaged, stopped
 * at a steady mean, with a growing continuity residual, mirror images) and
 * a table with each field's iterations, state, continuity residual and
 * mean drift and mean change.
 * Returns a malloc'd string (the caller frees it) or NULL without memory. */
char *couple_fields_md(const couple_field_info *f1, int n1, const couple_field_info *f2, int n2);
/* The coupling iterations of a context's points as Markdown for a report
 * (one row per iteration: thrust, controls, attitudes, change, seed).
 * A malloc'd string (the caller frees it) or NULL without memory. */
char *couple_points_md(const couple_ctx *c);

/* From a scenario (sim.h): the envelope's directions, speeds and the
 * aircraft's rejection criteria (0, or < 0 with err naming the aircraft
 * file), and the coupling settings (mode, grid, rotor disk, domain,
 * station; the rest at their defaults). */
struct sim_scenario;
int couple_shol_settings_scenario(shol_settings *set, const struct sim_scenario *sc, core_err *err);
void couple_settings_scenario(couple_settings *cs, const struct sim_scenario *sc);

/* The last fatal error of couple_shol_trim. */
const char *couple_last_error(const couple_ctx *c);

/* The candidate SHOL's sweeps (shol_sweep.c). One-way: shol_envelope_run
 * with couple_shol_trim over one, each converged sample's component loads
 * (shol_sample.loads) from one's history. Two-way: shol_envelope_run_near
 * over r1 (one's envelope), coupled by two from two steps of the
 * resolution (the speed step, or the bisection's tolerance where finer)
 * below r1's limit, one info line on log per coupled point, the loads from
 * two's history, else one's. 0, or < 0 with err (the coupling's own
 * message where it has one). */
int couple_shol_one_way(couple_ctx *one, const shol_settings *set, shol_progress_fn progress, void *progress_user,
                        const core_log *log, shol_result *r, core_err *err);
int couple_shol_two_way(couple_ctx *one, couple_ctx *two, const shol_settings *set, const shol_result *r1,
                        shol_progress_fn progress, void *progress_user, const core_log *log, shol_result *r2,
                        core_err *err);
/* The bands of the candidate SHOL (shol_bands.c). */
#define COUPLE_BAND_GRID_AUTO (-1) /* another level whose fields the database has for some directions */
#define COUPLE_BAND_GRID_NONE (-2)
typedef struct couple_band_opts {
    int grid;             /* COUPLE_BAND_GRID_AUTO, _NONE, or a core_grid_level (its fields built if missing) */
    const char *grid_csv; /* the second grid's envelope from an earlier run's shol.csv; NULL: none */
    /* Called (NULL: not) when the second grid's one-way sweep starts, its
     * fields queued: the level and the number of directions. */
    void (*on_grid)(void *user, core_grid_level level, int n_dirs);
    void *user;
    /* The directions whose ready fields choose the auto level (NULL: the
     * envelope's own): a rank of a dealt sweep passes the whole sweep's,
     * so that every rank chooses the level the serial run does. */
    const shol_settings *level_dirs;
} couple_band_opts;
/* The grid of the bands' second envelope in words: auto, none, coarse,
 * default or fine; < -2 if none of those. */
int couple_band_grid_parse(const char *s);
/* The bands of r1 (shol_dir_result.band), the one-way envelope on
 * cs->grid that the context one trimmed: the window spreads of one's
 * fields (each direction's ship-only field: 0 converged, max(mean_drift,
 * mean_change) averaged, unknown otherwise), the second grid's one-way
 * envelope (o->grid_csv, or a second one-way sweep on the level o->grid
 * names, auto: the directions whose ship-only field the database already
 * has at the first level of finer-then-coarser that has any), and the
 * sensitivity, and the model's validated error (ac's [model_error],
 * hfm_aircraft_model_error; none: not validated). With r2 (the two-way
 * envelope over r1), r2's bands too: the same window spreads and model
 * error, and the one-way grid spread (second grid minus r1) applied to
 * r2. 0, or < 0 with err. */
int couple_shol_bands(const couple_band_opts *o, const hfm_aircraft *ac, const core_ship *ship, awdb *db,
                      const couple_settings *cs, couple_ctx *one, const shol_settings *set, shol_result *r1,
                      shol_result *r2, const core_log *log, core_err *err);
/* The report's words for the coupling of cs (shol_report_info.coupling). */
const char *couple_shol_coupling_text(const couple_settings *cs);
/* couple_fields_md of one's fields and two's (two may be NULL). */
char *couple_shol_fields_md(const couple_ctx *one, const couple_ctx *two);

/* ------------- a flight's airwake from the database (couple/flight_fields.c) */
struct cfd_field;
struct sim_interaction;
/* The ship-only field of sc's ship and aircraft for WOD direction dir_rad
 * on the finest level ready among the flight's levels: quick (twice the
 * coarse spacing, about a minute to solve), then coarse up to sc's grid.
 * 1 with *out loaded (the caller's) and *level set when that level is
 * finer than have_rank (core_grid_rank; -1: the flight has none); 0 when
 * none finer is ready; -1 with err. The levels finer than the best ready
 * (quick only while none is) are requested from the database's builder
 * where absent and marked waited for by this process (awdb_wait_mark), so
 * that the builder serves them before requests nobody waits for;
 * *pending says whether one may still come (a failed build stays failed).
 * couple_flight_field_done takes the marks back. */
int couple_flight_field(awdb *db, const sim_scenario *sc, double dir_rad, int have_rank, struct cfd_field **out,
                        core_grid_level *level, int *pending, core_err *err);
void couple_flight_field_done(awdb *db, const sim_scenario *sc, double dir_rad);
/* The coupled rotor interaction at WOD v, dir_rad near sc's station
 * (couple/flight_fields.c says which): 1 with cf[0] the coupled field,
 * cf[1] its isolated rotor's, for a deck-zone pair cf[2], cf[3] the whole
 * domain's ship-only field and the zone's (NULL otherwise), all the
 * caller's, and *inter their interaction (the caller's); 0 none; -1 with
 * err. */
int couple_flight_coupled(awdb *db, const sim_scenario *sc, double v, double dir_rad, struct cfd_field *cf[4],
                          struct sim_interaction **inter, core_err *err);

/* ------------------ one task flown for the flown SHOL (couple/fly_task.c) */
/* The automated pilot flies a task headless at one WOD point with one
 * seed, in the ship's motion, the field's turbulence and (where the
 * aircraft has one) the landing gear; the flight is judged against the
 * SHOL's rejection criteria at every step, the touchdown and the task's
 * adequate tolerances. couple/fly_task.c has the order of the causes. */
typedef struct couple_fly_task couple_fly_task;
typedef struct couple_fly_task_opts {
    double rate_hz;        /* the step rate (200) */
    int turbulence;        /* 1 (default): the field's turbulence, seeded by the flight's seed */
    sim_sea sea;           /* the ship's sea and speed (calm by default), seeded by seed + 1 */
    double station_S_m[3]; /* the start: the trimmed hover with the CG here */
    double max_s;          /* the longest flight (s); 0: the task's length (sim_task_length_s) */
    /* The replay pilot instead of the automated one (sim/pilot_replay.c):
     * it re-flies this log (kept by the caller; NULL: none, the default)
     * and the task may be NULL; the flight fails farther than
     * replay_pos_m (2 m) from the recorded run, or at a touchdown sink
     * above replay_sink_mps (2 m/s). */
    const sim_log *replay;
    double replay_pos_m, replay_sink_mps;
    int replay_feed_controls; /* 1: the recorded controls fed forward too (sim_pilot_replay_opts) */
    /* How the criteria judge the flight (shol_flown_judge): the steady
     * limits on the phase's running mean over window_s (3 s; 0: every
     * step's values), the transient ones (a control at its stop, an
     * attitude past the limit times 1 + transient_frac, 0.5) at each step. */
    double window_s, transient_frac;
} couple_fly_task_opts;
void couple_fly_task_opts_default(couple_fly_task_opts *o);
/* ac (and o->replay) kept by the caller; the rest is copied. NULL with err. */
couple_fly_task *couple_fly_task_create(const hfm_aircraft *ac, const core_ship *ship, const sim_task *task,
                                        const shol_criteria *crit, const couple_fly_task_opts *o,
                                        const core_log *log, core_err *err);
void couple_fly_task_destroy(couple_fly_task *t);
/* Fly once in field (the direction's ship-only field, NULL: the free
 * stream): 0 flown (out filled, passed or not), 1 no trim at the start
 * (out->cause "no trim"), < 0 fatal (couple_fly_task_last_error says why). */
int couple_fly_task_run(couple_fly_task *t, double wod_speed_mps, double wod_dir_rad, unsigned long long seed,
                        const struct cfd_field *field, struct shol_flight *out);
const char *couple_fly_task_last_error(const couple_fly_task *t);
/* The air the flights meet over the spot: field (a ship-only field)
 * sampled at the main-rotor hub of the hover station (o.station_S_m plus
 * the hub's height above the CG), its mean speed and its turbulence
 * intensity sqrt(2k/3) as fractions of the field's WOD speed (both scale
 * with the WOD speed, so one number holds at every speed). 0, or < 0 with
 * err (a field without a WOD speed). */
int couple_fly_task_air_at_hub(const couple_fly_task *t, const struct cfd_field *field, double *speed_frac,
                               double *ti_frac, core_err *err);
/* The replay pilot's recording judged as its flights are (the criteria
 * of t, the reference's phases, up to its first wheel on the deck), at
 * the log's own samples: 1 when a criterion is exceeded (cause as
 * shol_flown_track_cause names it, *t_s when), 0 when it holds, < 0 with
 * err (t flies no recording). A recording that itself exceeds a criterion
 * is one that no replay tracking it can pass. */
int couple_fly_task_judge_recording(const couple_fly_task *t, char *cause, size_t n, double *t_s, core_err *err);
/* The last flight's task result and final state. */
typedef struct couple_fly_task_last {
    sim_task_result result;        /* the automated pilot's */
    sim_replay_result replay;      /* the replay pilot's */
    sim_flight_out end;
} couple_fly_task_last;
void couple_fly_task_last_get(const couple_fly_task *t, couple_fly_task_last *out);
/* A shol_fly_fn (user: a couple_fly_task_user): the field of the direction
 * from field (NULL: always the free stream; never asked at 0 m/s, where a
 * field scales to still air), then couple_fly_task_run. */
typedef int (*couple_fly_field_fn)(void *user, double wod_dir_rad, const struct cfd_field **out, core_err *err);
typedef struct couple_fly_task_user {
    couple_fly_task *task;
    couple_fly_field_fn field; /* 0 and *out (NULL: the free stream), or < 0 with err */
    void *field_user;
} couple_fly_task_user;
int couple_fly_task_shol(void *user, double wod_speed_mps, double wod_dir_rad, unsigned long long seed,
                         struct shol_flight *out);

#ifdef __cplusplus
}
#endif
#endif
