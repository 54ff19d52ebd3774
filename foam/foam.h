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
 */
#ifndef DISIM_FOAM_H
#define DISIM_FOAM_H

#include "awdb.h"
#include "cfd.h"
#include "core.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct foam_opts {
    int np;              /* MPI ranks (mpirun -np); 1: simpleFoam without MPI */
    int max_iter;        /* SIMPLE iteration cap (0: the spec's max_iter, else 3000) */
    double timeout_s;    /* longest any one step may run (0: 6 h) */
    const char *work_dir; /* where the case folder is made (NULL: $TMPDIR or /tmp) */
    int keep_case;       /* 1: leave the case folder (its path in foam_result.case_dir) */
    /* Where OpenFOAM's etc folder is (NULL: $FOAM_ETC, else
     * /usr/share/openfoam/etc, Debian's); WM_PROJECT_DIR is its parent. */
    const char *foam_etc;
    const core_log *log;
    /* Progress while simpleFoam runs (about once a second, from its log):
     * non-zero stops the run (nothing written, returns 1). May be NULL. */
    awdb_progress_fn progress;
    void *progress_user;
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
} foam_result;

/* 1 when the OpenFOAM programs (simpleFoam, blockMesh, ...) and, for np > 1,
 * mpirun are found on PATH with an etc folder; 0 with why filled. */
int foam_available(const foam_opts *o, char *why, size_t n);

/* Solve spec with OpenFOAM and write the field to out_path (HDF5 and its
 * XDMF side file, as cfd_solver_write; meta's engine, version and result
 * are filled here). 0 written (converged or at the cap: res.converged
 * says), 1 stopped by progress (nothing written), < 0 failed with err
 * naming the step and the tail of its log (nothing written). The spec must
 * be a whole-domain case with a wind and uniform inflow: a deck zone, calm
 * air, a loaded rotor or an ABL inflow are refused. */
int foam_airwake(const cfd_airwake_spec *spec, const foam_opts *o, const cfd_meta *meta, const char *out_path,
                 foam_result *res, core_err *err);

/* Write the case of spec into dir (which must exist and be empty) without
 * running anything: system/, constant/, 0/ and the topoSet dictionaries.
 * 0, or < 0 with err. (foam_airwake's first step; for inspection.) */
int foam_case_write(const cfd_airwake_spec *spec, const foam_opts *o, const char *dir, core_err *err);

/* ------------------------------------------------------- builder engine */
/* OpenFOAM as an airwake builder engine (awdb_engine): ships looked up by
 * name among ships_dir's *.ini as the embedded engine does; each key
 * becomes its case through awdb_key_spec. Deck zones and the loaded rotor
 * are refused (the build fails with the reason). The options are copied
 * (strings must outlive the engine). */
typedef struct foam_engine foam_engine;
foam_engine *foam_engine_create(const char *ships_dir, const foam_opts *o, core_err *err);
void foam_engine_destroy(foam_engine *e);
void foam_engine_get(foam_engine *e, awdb_engine *eng);

#ifdef __cplusplus
}
#endif
#endif
