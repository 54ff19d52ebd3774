/* sim_scenario.h -- the scenario file (sim/scenario.c).
 * Part of sim.h (the umbrella header). */
#ifndef DISIM_SIM_SCENARIO_H
#define DISIM_SIM_SCENARIO_H

#include "core.h"
#include "hfm.h"

#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

#define SIM_PATH_MAX 512
#define SIM_MAX_WOD 128

typedef enum { SIM_WOD_SINGLE = 0, SIM_WOD_SWEEP = 1 } sim_wod_mode;

/* A piloted task's kind: a task file's (station_keep, land) and a
 * scenario's [task] type (hover: station keeping, landing: land; shol:
 * the trims of disim shol, no task file). */
enum { SIM_TASK_SHOL = -1, SIM_TASK_STATION_KEEP = 0, SIM_TASK_LAND = 1 };

/* The sea (sim/ship_motion.c has the model) */
#define SIM_SEA_MAX_STATE 6
#define SIM_SEA_DEFAULT_WAVES 256
#define SIM_SEA_MAX_WAVES 4096

typedef enum { SIM_SPECTRUM_ITTC = 0, SIM_SPECTRUM_JONSWAP = 1 } sim_spectrum;

/* The sea and the ship's steady course through it: plain data. */
typedef struct sim_sea {
    int state;             /* sea state 0 (calm: the ship still) to 6 */
    double ship_speed_mps; /* the ship's speed through the water, >= 0 */
    double wave_dir_rad;   /* heading to the waves: where they come FROM,
                              from the bow, + to starboard (as WOD):
                              0 head seas, pi/2 beam seas from starboard,
                              pi following seas */
    double course_rad;     /* the ship's mean heading in E (0: north) */
    sim_spectrum spectrum; /* ITTC (Bretschneider) or JONSWAP (gamma 3.3) */
    int n_waves;           /* sinusoids in the sum; 0: SIM_SEA_DEFAULT_WAVES */
} sim_sea;

/* A resolved scenario: plain data. */
typedef struct sim_scenario {
    char path[SIM_PATH_MAX];
    char name[64];
    char description[160];
    char aircraft_path[SIM_PATH_MAX];
    char aircraft_name[64];
    char ship_path[SIM_PATH_MAX];
    core_ship ship;

    /* wind over deck */
    sim_wod_mode wod_mode;
    double wod_speed_mps, wod_dir_rad; /* single */
    int n_dirs;                        /* sweep: directions, speeds */
    double dirs_rad[SIM_MAX_WOD];
    double speed_step_mps, speed_max_mps;

    /* task (shol, the only one) */
    double hover_height_m; /* CG height above the landing spot for the hover-over-spot station */
    double station_S_m[3]; /* hover-over-spot station in S (CG position) */

    /* [sea] (disim fly: the ship's motion; disim shol refuses state > 0):
     * state, ship_speed_mps, wave_dir_rad, spectrum; course_rad 0 (north),
     * n_waves 0 (the default) */
    sim_sea sea;
    int turbulence;         /* [wod] turbulence (disim fly): 1 the field's turbulence */

    /* CFD */
    int engine;           /* [cfd] engine: SIM_ENGINE_EMBEDDED (default) or SIM_ENGINE_OPENFOAM
                             (disim airwake; the commands that build through the airwake
                             database refuse it) */
    int engine_np;        /* [cfd] np: the OpenFOAM engine's MPI ranks (default 2); 0 embedded */
    core_grid_level grid;
    core_rotor_mode rotor;
    core_coupling_mode coupling;
    int coupled_zone;     /* [cfd] coupled_domain = zone: a coupled point's fields in the deck zone
                             (couple_settings.zone); whole (default): the whole domain */
    int max_iterations;   /* [cfd] max_iterations: the CFD iteration limit of the fields this
                             scenario builds; 0 (absent): the solver's default */

    /* outputs */
    char output_dir[SIM_PATH_MAX]; /* [output] dir; default out/NAME */

    /* [task] type and the piloted task's file (disim fly: the automated
     * pilot flies it; scenarios/README.md) */
    int task_type;                 /* SIM_TASK_*: [task] type shol, hover (STATION_KEEP) or landing (LAND) */
    char task_path[SIM_PATH_MAX];  /* hover, landing: a task file (sim_task_load_ship) */
    /* [pilot] (disim fly; its flags override) */
    int pilot;                     /* SIM_SC_PILOT_* (station, the default) */
    char pilot_stations[SIM_PATH_MAX]; /* station: the priority list "A,B" ("" none) */
    double pilot_hold_after_s;     /* station: 0 (absent) or the hold time */
    char pilot_log[SIM_PATH_MAX];  /* replay: the recorded run's LCM log */
    int pilot_feed_controls;       /* replay: its controls fed forward too */
    /* [flown] (disim shol --method pilot; shol_flown_judge): NAN when absent */
    double flown_window_s;         /* window_s: the steady criteria's running mean (s) */
    double flown_transient_frac;   /* transient_frac: the transient attitude limits' margin */
} sim_scenario;
enum { SIM_SC_PILOT_STATION = 0, SIM_SC_PILOT_AUTO = 1, SIM_SC_PILOT_REPLAY = 2 };
enum { SIM_ENGINE_EMBEDDED = 0, SIM_ENGINE_OPENFOAM = 1 };

/* Parse and resolve a scenario file. Returns 0, or < 0 with err naming the
 * file, line, key and what was expected (unknown keys and sections, wrong
 * types, values out of range, missing files, errors in referenced files), or
 * why a key no command acts on yet is refused ([task] approach_dir_deg,
 * [cfd] residual_tol, [output] csv|plots; a key
 * of a mode not chosen; rotor = off with the two-way coupling; a piloted
 * task without the automated pilot). */
/* The largest scenario file read (bytes), far above any real one: a path
 * that is not a regular file (a folder, a FIFO, /dev/zero) or is larger
 * is refused before it is opened. */
#define SIM_SCENARIO_MAX_BYTES (16LL * 1024 * 1024)
int sim_scenario_load(const char *path, sim_scenario *sc, core_err *err);
/* The same on a scenario file already read (core_ini_load or
 * core_ini_parse; the caller destroys it): its path names it and its
 * folder is where the aircraft, ship and task files are looked for. */
int sim_scenario_from_ini(core_ini *ini, sim_scenario *sc, core_err *err);

/* Print the resolved configuration as INI-like text. */
void sim_scenario_print(const sim_scenario *sc, FILE *out);

#ifdef __cplusplus
}
#endif

#endif
