/* cfd_private.h -- structures shared inside the cfd library. */
#ifndef DISIM_CFD_PRIVATE_H
#define DISIM_CFD_PRIVATE_H

#include "cfd.h"

#include <stddef.h>

struct cfd_grid {
    int n[3];
    size_t ncell;
    double *xn[3]; /* nodes */
    double *xc[3]; /* centres */
    double *h[3];  /* widths */
    unsigned char *solid;
    /* cell lookup (grid.c): lut[d][b] a centre index at or below bucket b
     * of lut_n[d] equal buckets from xc[d][0] (NULL: binary search) */
    int *lut[3];
    int lut_n[3];
    double lut_inv[3]; /* buckets per metre */
};

#define CFD_IDX(g, i, j, k) ((size_t)(i) + (size_t)(g)->n[0] * ((size_t)(j) + (size_t)(g)->n[1] * (size_t)(k)))

/* Pressure-correction solver (mg.c): A x = b with A = diag - sum of face
 * couplings c (symmetric, 7-point), by multigrid-preconditioned CG. */
typedef struct cfd_mg cfd_mg;
cfd_mg *cfd_mg_create(const int n[3]);
void cfd_mg_destroy(cfd_mg *m);
size_t cfd_mg_bytes(const cfd_mg *m);
/* Fine-level coefficient arrays the caller fills: cx[c] couples cell c with
 * its +x neighbour (0 at the last i), likewise cy, cz; diag; active (1 for
 * unknowns, 0 for blocked cells, which keep x = 0). */
double *cfd_mg_cx(cfd_mg *m);
double *cfd_mg_cy(cfd_mg *m);
double *cfd_mg_cz(cfd_mg *m);
double *cfd_mg_diag(cfd_mg *m);
/* Four fine-level work arrays of the solve, free between solves (the
 * solver keeps cell pressure gradients there), i 0..3. */
double *cfd_mg_work(cfd_mg *m, int i);
/* Build the coarse levels from the fine coefficients (after each refill). */
void cfd_mg_setup(cfd_mg *m, int singular);
/* Solve to |r| <= rtol |b| or maxit; x holds the start and the result.
 * Returns the iterations used. */
int cfd_mg_solve(cfd_mg *m, double *x, const double *b, double rtol, int maxit, double *rel_res);

/* Anderson acceleration of a fixed-point iteration (anderson.c) over a
 * state of nseg arrays of len[q] doubles, segment q scaled by weight[q] in
 * the least-squares norm; depth: the number of differences kept (1..16). */
typedef struct cfd_aa cfd_aa;
cfd_aa *cfd_aa_create(int depth, int nseg, const size_t *len, const double *weight);
void cfd_aa_destroy(cfd_aa *a);
size_t cfd_aa_bytes(const cfd_aa *a);
/* Mixing steps taken and history restarts (safeguards) since create. */
void cfd_aa_counts(const cfd_aa *a, int *mixes, int *restarts);
void cfd_aa_reset(cfd_aa *a);
/* Keep x_n (before one iteration). */
void cfd_aa_save(cfd_aa *a, double *const *x);
/* x holds G(x_n) on entry and x_{n+1} on return.
 * Returns the number of differences used (0: the plain step), < 0 on a
 * non-finite residual (the history is cleared). */
int cfd_aa_mix(cfd_aa *a, double *const *x);

/* Trilinear weights on cell centres along one axis (binary search). */
void cfd_axis_locate(const double *xc, int n, double x, int *i0, double *f);

/* Trilinear interpolation of narr cell-centred arrays at pos (clamped):
 * the cells found through the grid's lookup tables in O(1), the same
 * cells and weights as cfd_axis_locate's, the same bits. */
void cfd_sample_arrays(const cfd_grid *g, double *const *arr, int narr, const double pos[3], double *out);

/* Actuator-disk distribution (disk.c): fills f[3] (N per cell, force on the
 * air). Returns < 0 if the disk misses the grid. */
int cfd_disk_distribute(const cfd_grid *g, const cfd_disk *d, double *f[3], core_err *err);

/* Turbulence constants (turb.c; public in cfd.h). */
#define CFD_CMU CFD_RNG_CMU
#define CFD_C1 CFD_RNG_C1
#define CFD_C2 CFD_RNG_C2
#define CFD_SIGMA_K CFD_RNG_SIGMA_K
#define CFD_SIGMA_E CFD_RNG_SIGMA_E
#define CFD_ETA0 CFD_RNG_ETA0
#define CFD_BETA CFD_RNG_BETA
#define CFD_KAPPA CFD_WALL_KAPPA
#define CFD_EWALL CFD_WALL_E

/* Wall-function effective viscosity for a wall-adjacent cell at distance y
 * with turbulent kinetic energy k (log law for y* > 11.225, else nu). */
double cfd_wall_nu(double nu, double k, double y);
/* RNG C2* for strain-rate invariant eta = S k / eps. */
double cfd_rng_c2star(double eta);

#endif
