/*
 * sim.h -- the simulation layer: scenario files (and, in later work, the
 * fixed-rate flight loop, ship motion, deck contact and LCM stations).
 *
 * A scenario (INI, see scenarios/README.md) names the ship-aircraft
 * combination, the WOD or WOD sweep, the hover-over-spot station of the
 * SHOL task, CFD settings and the output folder. Paths inside are relative
 * to the file. Every key it accepts acts; the sections and keys of later
 * work ([sea], [pilot], the piloted tasks, the OpenFOAM engine) are refused.
 */
#ifndef DISIM_SIM_H
#define DISIM_SIM_H

#include "core.h"

#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

#define SIM_PATH_MAX 512
#define SIM_MAX_WOD 128

typedef enum { SIM_WOD_SINGLE = 0, SIM_WOD_SWEEP = 1 } sim_wod_mode;

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

    /* CFD (the embedded engine, the only one) */
    core_grid_level grid;
    core_rotor_mode rotor;
    core_coupling_mode coupling;
    int coupled_zone;     /* [cfd] coupled_domain = zone: a coupled point's fields in the deck zone
                             (couple_settings.zone); whole (default): the whole domain */
    int max_iterations;   /* [cfd] max_iterations: the CFD iteration limit of the fields this
                             scenario builds; 0 (absent): the solver's default */

    /* outputs */
    char output_dir[SIM_PATH_MAX]; /* [output] dir; default out/NAME */
} sim_scenario;

/* Parse and resolve a scenario file. Returns 0, or < 0 with err naming the
 * file, line, key and what was expected (unknown keys and sections, wrong
 * types, values out of range, missing files, errors in referenced files), or
 * why a key no command acts on yet is refused ([sea], [pilot], [task] type =
 * hover|landing, [task] approach_dir_deg, [cfd] engine = openfoam, [cfd]
 * residual_tol, [output] csv|plots; a key of a mode not chosen; rotor = off
 * with the two-way coupling). */
int sim_scenario_load(const char *path, sim_scenario *sc, core_err *err);

/* Print the resolved configuration as INI-like text. */
void sim_scenario_print(const sim_scenario *sc, FILE *out);

#ifdef __cplusplus
}
#endif
#endif
