/* sim_world.h -- the world a flight flies in: its seaway, flight and run
 * information (sim/world.c).
 * Part of sim.h (the umbrella header). */
#ifndef DISIM_SIM_WORLD_H
#define DISIM_SIM_WORLD_H

#include "core.h"
#include "hfm.h"
#include "sim_scenario.h"
#include "sim_ship_motion.h"
#include "sim_flight.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ----------------------------- the world a flight flies in (sim/world.c) */
/* What a run was flown from, as disim fly publishes it once at the start
 * and after every reset or load on DISIM_RUN_INFO (run_info_t) and so logs
 * it: enough to draw the run again (its ship, aircraft and seaway). Plain
 * data. */
typedef struct sim_run_info {
    char scenario_path[SIM_PATH_MAX];
    char scenario[64];       /* its name */
    char aircraft_path[SIM_PATH_MAX];
    char ship_path[SIM_PATH_MAX];
    unsigned long long seed; /* the run's seed (the seaway's is seed + 1: sim_world_seaway) */
    sim_sea sea;             /* the seaway flown */
    double wod_speed_mps, wod_dir_rad;
    double rate_hz, state_rate_hz;
} sim_run_info;
/* What the caller sets over a scenario (disim fly's flags, the flown
 * SHOL's WOD point and seed). */
struct sim_interaction;
typedef struct sim_world_overrides {
    double rate_hz;                      /* the step rate (200) */
    double wod_speed_mps, wod_dir_rad;   /* NAN (default): the scenario's single WOD */
    unsigned long long seed;             /* 1: the turbulence's; the seaway's is seed + 1 */
    int turbulence;                      /* -1 (default): the scenario's [wod] turbulence; 0, 1 */
    int sea_state;                       /* -1 (default): the scenario's [sea] state */
    double wave_dir_rad, ship_speed_mps; /* NAN (default): the scenario's */
    const sim_sea *sea;                  /* NULL (default); else the whole seaway, the three above unused */
    int gear;                            /* 1 (default): the aircraft file's [gear] where it has one; 0 none */
    int start;                           /* SIM_START_HOVER (default), SIM_START_DECK */
    double start_heading_rad;            /* SIM_START_DECK: the heading from the bow (0) */
    int sas;                             /* -1 (default): as the aircraft file's [sas]; 0 off, 1 on */
    int has_station;                     /* 1: the start at station_S_m, else the scenario's station */
    double station_S_m[3];
    const struct cfd_field *field;       /* the ship-only airwake (NULL: the free stream); kept by the caller */
    struct sim_interaction *interaction; /* the coupled rotor interaction (NULL: none); kept by the caller */
} sim_world_overrides;
void sim_world_overrides_default(sim_world_overrides *o);
/* The run information of scenario sc under ov (state_rate_hz 0). */
void sim_world_run_info(const sim_scenario *sc, const sim_world_overrides *ov, sim_run_info *ri);
/* The seaway of a run of seed over ship: its own stream, seed + 1 (the
 * one place that rule is written). NULL with err. */
sim_ship_motion *sim_world_seaway(const core_ship *ship, const sim_sea *sea, unsigned long long seed, core_err *err);
/* What a run is drawn from, for a view of it (live or from its log): its
 * ship and aircraft files loaded, its seaway rebuilt from its ship, sea
 * and seed (sim_world_seaway: its own, never the flight's motion, whose
 * step cache is not for two threads), and its name "SHIP + AIRCRAFT, WOD,
 * sea state N". */
typedef struct sim_run_scene {
    sim_run_info info;
    core_ship ship;
    hfm_aircraft *ac;
    hfm_geometry geom;
    sim_ship_motion *sea;
    char name[200];
} sim_run_scene;
/* 0, or < 0 with err and nothing left to close. log: the aircraft file's
 * warnings (NULL: none). */
int sim_run_scene_open(sim_run_scene *s, const sim_run_info *ri, const core_log *log, core_err *err);
void sim_run_scene_close(sim_run_scene *s);
/* A world: the ship's motion in the seaway, the flight in it, and what
 * they were built from. */
typedef struct sim_world {
    sim_ship_motion *motion;
    sim_flight *flight;
    sim_run_info info;
} sim_world;
/* Build the world of sc (only its ship, station, [sea], [wod] and paths
 * used) and aircraft ac (kept by the caller) under ov. 0, or < 0 with err
 * and nothing left to free (err->code CORE_ERR_NO_TRIM: the start does
 * not trim). */
int sim_world_build(const sim_scenario *sc, const hfm_aircraft *ac, const sim_world_overrides *ov,
                    const core_log *log, sim_world *w, core_err *err);
void sim_world_free(sim_world *w);

#ifdef __cplusplus
}
#endif

#endif
