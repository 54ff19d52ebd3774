/* foam_private.h -- the OpenFOAM engine's parts: the case writer (case.c),
 * the process runner (run.c) and the result reader (read.c). */
#ifndef DISIM_FOAM_PRIVATE_H
#define DISIM_FOAM_PRIVATE_H

#include "foam.h"

#include <stdio.h>

/* The boundary patches of the block: the grid's faces in cfd's order
 * (CFD_XMIN .. CFD_ZMAX), then the ship's walls (empty until subsetMesh). */
extern const char *const foam_patch_names[CFD_NFACES];
#define FOAM_SHIP_PATCH "ship"
/* The file in the case folder whose appearance makes simpleFoam write its
 * fields and stop (the abort function object of the controlDict). */
#define FOAM_STOP_FILE "STOP"
/* The disk's force bands (cell zones rotorBand0..); see case.c. */
#define FOAM_DISK_BANDS 4
/* Cells below this fraction of the peak force density are in no band. */
#define FOAM_DISK_TAIL 0.01

/* Write the case of solver s (the embedded solver's set-up of spec, its
 * state the inflow) into dir: system/, constant/, 0/; with blades and the
 * rotor on, the rotor is rotorDisk (blade.c), else the disk's force. *has_ship: 1 when
 * cells are blocked (topoSet and subsetMesh carve them out). 0 or < 0. */
int foam_case_files(const cfd_solver *s, const cfd_airwake_spec *sp, const hfm_blade_data *blades, int np,
                    int max_iter, const char *dir, int *has_ship, core_err *err);

/* A poll while a step runs (about once a second): non-zero stops it. */
typedef int (*foam_poll_fn)(void *user);

/* Run argv (argv[0] found on PATH) in case_dir with its output in
 * case_dir/log.STEP, with OpenFOAM's environment (etc: FOAM_ETC), at most
 * timeout_s. 0 ok, 1 stopped by poll, < 0 failed: err names the step, how
 * it ended and the tail of its log. */
int foam_exec(const char *case_dir, const char *step, char *const argv[], const char *etc, double timeout_s,
              foam_poll_fn poll, void *poll_user, core_err *err);
/* The last n bytes of a file, whole lines, into buf. */
void foam_log_tail(const char *path, char *buf, size_t n);
/* Find prog on PATH: 1 found (full path in out), 0 not. */
int foam_which(const char *prog, char *out, size_t n);

/* From simpleFoam's log: the last iteration, the last initial residuals
 * of p, Ux, Uy, Uz, k, whether the residual control ended it, and the
 * version in the banner. 0, or < 0 when the log has no iteration. */
typedef struct foam_log_info {
    int iterations;
    double residual[5];
    int converged;
    char version[64];
} foam_log_info;
int foam_log_parse(const char *path, foam_log_info *info);

/* A whole file, NUL-terminated (*len its length when len is not NULL);
 * NULL if it cannot be read. */
char *foam_slurp(const char *path, size_t *len);
/* The latest time folder's name of a case (out); 0, or -1 when none. */
int foam_latest_time(const char *case_dir, char *out, size_t n);
/* The internalField of a volField file: ncomp values per cell into *vals
 * (malloc'ed), *n cells. 0, or < 0 with err. */
int foam_read_internal(const char *path, int ncomp, double **vals, size_t *n, core_err *err);
/* disim's cell *k (and its volume when vol is not NULL) whose centre is
 * OpenFOAM cell c's centre xyz; < 0 with err when none is. */
int foam_cell_index(const cfd_grid *g, const double xyz[3], size_t c, size_t *k, double *vol, core_err *err);

/* Read the latest time's U, p, k, epsilon, nut and cell centres C of the
 * reconstructed case and place them on s's grid (fluid cells matched by
 * centre; blocked cells keep s's state), p times rho. 0 or < 0. */
int foam_read_fields(const char *case_dir, cfd_solver *s, size_t *cells, core_err *err);
/* The largest change of the monitor velocities over the last `back`
 * iterations of the probes' output, / u_ref; -1 when not known. */
double foam_monitor_change(const char *case_dir, int back, double u_ref);

/* --------------------------------------- the blade-element rotor (blade.c) */
/* The rotorDisk's cell zone: in each grid column the fluid cell the disk's
 * plane crosses, if its centre is between root_m and the radius from the
 * axis: zone[c] 0, else -1. Returns the cells in the zone. */
size_t foam_blade_zone(const cfd_solver *s, const cfd_disk *d, double root_m, int *zone);
/* The rotorDisk entry (named "rotor") of constant/fvOptions on the cell
 * zone `zone`, trimmed to d's thrust, into f. */
void foam_blade_options(FILE *f, const char *zone, const cfd_disk *d, const hfm_blade_data *b, double rho);
/* After the run: the trim's last report (res->trim_*) from the log, and the
 * thrust integrated from the force field of time_dir (res->rotor_force_N,
 * rotor_cells). 0 or < 0 with err. */
int foam_blade_result(const char *case_dir, const char *time_dir, const cfd_solver *s, const cfd_disk *d,
                      foam_result *res, core_err *err);

#endif
