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
/* The disk's force bands (cell zones rotorBand0..); see case.c. */
#define FOAM_DISK_BANDS 4
/* Cells below this fraction of the peak force density are in no band. */
#define FOAM_DISK_TAIL 0.01

/* Write the case of solver s (the embedded solver's set-up of spec, its
 * state the inflow) into dir: system/, constant/, 0/. *has_ship: 1 when
 * cells are blocked (topoSet and subsetMesh carve them out). 0 or < 0. */
int foam_case_files(const cfd_solver *s, const cfd_airwake_spec *sp, int np, int max_iter, const char *dir,
                    int *has_ship, core_err *err);

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

/* Read the latest time's U, p, k, epsilon, nut and cell centres C of the
 * reconstructed case and place them on s's grid (fluid cells matched by
 * centre; blocked cells keep s's state), p times rho. 0 or < 0. */
int foam_read_fields(const char *case_dir, cfd_solver *s, size_t *cells, core_err *err);
/* The largest change of the monitor velocities over the last `back`
 * iterations of the probes' output, / u_ref; -1 when not known. */
double foam_monitor_change(const char *case_dir, int back, double u_ref);

#endif
