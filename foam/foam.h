/*
 * foam.h -- OpenFOAM as a second airwake engine: the embedded solver's case
 * (cfd_airwake_spec: the same grid, blocked ship cells, boundaries, inflow,
 * RNG k-epsilon constants and uniform actuator disk) written as an OpenFOAM
 * case, run through the installed OpenFOAM (blockMesh, topoSet, subsetMesh,
 * decomposePar, mpirun -np N simpleFoam -parallel, reconstructPar,
 * postProcess), read back cell by cell onto the embedded solver's grid and
 * written as the same HDF5 airwake field (cfd_solver_write), with the
 * engine, its version and its convergence in the metadata.
 *
 * Nothing is compiled against OpenFOAM: every step is one of the package's
 * programs, started with fork/exec (no shell), each with a time limit, its
 * output in a log file in the case folder. A step that fails stops the run
 * with the step's name and the tail of its log; the field is written to a
 * temporary name and renamed, so a failure leaves none. The library never
 * prints. The case's settings and how they were chosen: docs/openfoam.md.
 *
 * The rotor: the uniform disk (the spec's rotor "uniform") as the embedded
 * solver's disk force, cell by cell (vectorSemiImplicitSource); the loaded
 * rotor ("loaded") as OpenFOAM's blade-element rotorDisk with the
 * aircraft's blades (hfm_blade_data), trimmed to the spec's thrust with no
 * hub moment (blade.c). The embedded solver's loaded disk takes its load
 * shape from the flight model's trim instead; both put the helicopter's
 * thrust into the air.
 */
#ifndef DISIM_FOAM_H
#define DISIM_FOAM_H

#include "awdb.h"
#include "cfd.h"
#include "core.h"
#include "hfm.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct foam_opts {
    int np;              /* MPI ranks (mpirun -np); 1: simpleFoam without MPI */
    int max_iter;        /* SIMPLE iteration cap (0: the spec's max_iter, else 3000) */
    double timeout_s;    /* longest any one step may run (0: 6 h) */
    const char *work_dir; /* where the case folder is made (NULL: $TMPDIR or /tmp); with a
                             hostfile, a folder every host sees at the same path */
    const char *hostfile; /* mpirun --hostfile: the ranks over these hosts (NULL: this one) */
    int keep_case;       /* 1: leave the case folder (its path in foam_result.case_dir) */
    /* Where OpenFOAM's etc folder is (NULL: $FOAM_ETC, else
     * /usr/share/openfoam/etc, Debian's); WM_PROJECT_DIR is its parent. */
    const char *foam_etc;
    const core_log *log;
    /* Progress while simpleFoam runs (about once a second, from its log):
     * non-zero stops the run (nothing written, returns 1). May be NULL. */
    awdb_progress_fn progress;
    void *progress_user;
    /* The blades of the loaded rotor (spec rotor CORE_ROTOR_LOADED, built
     * as rotorDisk); NULL refuses the loaded rotor. The builder engine sets
     * it from the key's aircraft. */
    const hfm_blade_data *blades;
} foam_opts;

void foam_opts_default(foam_opts *o);

/* The steps of foam_airwake, in order (foam_result.step_s): the case
 * (the embedded set-up and the case files), the OpenFOAM programs, reading
 * the latest time back onto the grid, writing the HDF5 field. */
enum {
    FOAM_STEP_CASE = 0,
    FOAM_STEP_BLOCKMESH,
    FOAM_STEP_TOPOSET,
    FOAM_STEP_SUBSETMESH,
    FOAM_STEP_DECOMPOSEPAR,
    FOAM_STEP_SIMPLEFOAM,
    FOAM_STEP_RECONSTRUCTPAR,
    FOAM_STEP_POSTPROCESS,
    FOAM_STEP_READ,
    FOAM_STEP_WRITE,
    FOAM_NSTEPS
};
/* Their names: "case", "blockMesh", ..., "read", "write". */
extern const char *const foam_step_names[FOAM_NSTEPS];

typedef struct foam_result {
    cfd_result res;        /* iterations, converged, residual[] (p, Ux, Uy, Uz, k initial
                              residuals), wall_s (simpleFoam), monitor_change */
    size_t cells;          /* fluid cells of the OpenFOAM mesh */
    int steady_iter;       /* > 0: stopped once the monitors were steady, at this iteration (the
                              residuals had not reached 1e-4: res.converged 0) */
    double total_wall_s;   /* every step, meshing and sampling included */
    double step_s[FOAM_NSTEPS]; /* each step's wall time (0: not run) */
    char version[64];      /* OpenFOAM's, from its banner (e.g. "v1912") */
    char case_dir[1024];   /* the case folder (removed unless keep_case) */
    /* the loaded rotor (rotorDisk), 0 otherwise: the thrust integrated from
     * its force field at the last iteration over rotor_cells cells; its
     * trim's last thrust and blade pitch (theta0, theta1c, theta1s) from
     * OpenFOAM's log, and whether that trim's Newton iteration converged */
    double rotor_force_N;
    double rotor_torque_Nm; /* the torque it puts into the air about the thrust direction, in the
                               rotor's sense of rotation (its blades' profile drag: rotorDisk
                               turns the lift along the axis, so there is no induced torque) */
    size_t rotor_cells;
    double trim_thrust_N, trim_pitch_deg[3];
    int trim_converged;
} foam_result;

/* 1 when the OpenFOAM programs (simpleFoam, blockMesh, ...) and, for np > 1,
 * mpirun are found on PATH with an etc folder; 0 with why filled. */
int foam_available(const foam_opts *o, char *why, size_t n);

/* Solve spec with OpenFOAM and write the field to out_path (HDF5 and its
 * XDMF side file, as cfd_solver_write; meta's engine, version and result
 * are filled here). 0 written (converged or at the cap: res.converged
 * says), 1 stopped by progress (nothing written), < 0 failed with err
 * naming the step and the tail of its log (nothing written). The spec
 * needs a wind: calm air is refused, and the loaded rotor without
 * o->blades. A deck zone (its inlets the outer field's values) and the ABL
 * inflow are built with the embedded solver's inflow on every inlet face.
 * With the loaded rotor the field's meta says rotor_model "rotorDisk",
 * rotor_force_N and rotor_torque_Nm (as res's). */
int foam_airwake(const cfd_airwake_spec *spec, const foam_opts *o, const cfd_meta *meta, const char *out_path,
                 foam_result *res, core_err *err);

/* Write the case of spec into dir (which must exist and be empty) without
 * running anything: system/, constant/, 0/ and the topoSet dictionaries.
 * 0, or < 0 with err. (foam_airwake's first step; for inspection.) */
int foam_case_write(const cfd_airwake_spec *spec, const foam_opts *o, const char *dir, core_err *err);

/* ------------------------------------------------------- builder engine */
/* OpenFOAM as an airwake builder engine (awdb_engine): ships looked up by
 * name among ships_dir's *.ini as the embedded engine does; each key
 * becomes its case through awdb_key_spec. A key with the loaded rotor
 * takes the blades of the aircraft file in aircraft_dir whose [aircraft]
 * name is the key's (NULL aircraft_dir: the loaded rotor is refused).
 * A deck-zone key of a ship takes its boundary, the ship-only field, from
 * the database given by foam_engine_set_db (awdb_zone_boundary; without
 * one, or before that field is ready, the build fails saying so); the
 * isolated rotor's zone takes the inflow profile. The options are copied
 * (strings must outlive the engine). */
typedef struct foam_engine foam_engine;
foam_engine *foam_engine_create(const char *ships_dir, const char *aircraft_dir, const foam_opts *o, core_err *err);
/* The database deck-zone builds read their ship-only boundary field from. */
void foam_engine_set_db(foam_engine *e, awdb *db);
void foam_engine_destroy(foam_engine *e);
void foam_engine_get(foam_engine *e, awdb_engine *eng);

#ifdef __cplusplus
}
#endif
#endif
