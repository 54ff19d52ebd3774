/*
 * solver.c -- steady incompressible RANS by SIMPLEC on a collocated grid.
 *
 * Model: continuity div u = 0 and momentum div(u u) = -grad p / rho +
 * div((nu + nu_t) grad u) + f / rho (f: actuator-disk force per volume),
 * finite volumes on the cells of a stretched Cartesian grid (Ferziger &
 * Peric, Computational Methods for Fluid Dynamics, 3rd ed., ch. 7-8):
 *  - convection: upwind implicit plus a van Leer TVD deferred correction
 *    (bounded, second order where smooth), continuity subtracted so the
 *    matrix stays an M-matrix while mass is not yet conserved. With wall
 *    functions, faces of wall-function cells (fluid cells with a wall face)
 *    are first-order upwind: the centre value of such a cell is the
 *    log-layer value at y_P, not a point of a smooth profile, and the
 *    explicit correction there (deck edges, hangar corners) kept the
 *    SIMPLEC iteration in a limit cycle that any limiter (van Leer, van
 *    Albada, minmod, limited linear upwind) reproduced and only heavy
 *    under-relaxation damped (docs/validation/cfd.md);
 *  - pressure-velocity coupling: SIMPLEC (Van Doormaal & Raithby 1984,
 *    Numer. Heat Transfer 7:147) with Rhie-Chow face velocities (Rhie & Chow
 *    1983, AIAA J. 21:1525), d = V / (a_P - sum a_nb);
 *  - linear systems: red-black Gauss-Seidel sweeps for u, v, w, k, eps; the
 *    pressure correction by multigrid-preconditioned CG (mg.c);
 *  - boundaries: walls (wall functions when turbulent), velocity inlet,
 *    pressure outlet (zero gradient, also an opening: where air comes back
 *    in, static pressure -rho u_n^2 / 2 for total pressure 0 and zero
 *    tangential velocity, as Fluent's backflow total pressure and
 *    OpenFOAM's totalPressure + pressureInletOutletVelocity), symmetry;
 *    blocked cells' faces are walls. At a wall the pressure (and its
 *    correction) is extrapolated linearly from the cell and the neighbour
 *    on the other side, so a wall cell's pressure gradient is the one-sided
 *    difference and the Rhie-Chow term vanishes for a linear pressure
 *    field (with p_w = p_P it did not, at deck edges and hangar corners);
 *  - convergence as in the seed paper (section 2.2): residuals (scaled as
 *    Fluent scales them) below tol_residual and monitor-point velocities
 *    changing less than tol_monitor times u_ref between two checks; the
 *    bookkeeping, with the averaged mean of an unconverged run and the
 *    steady-mean stop (avg_window, avg_stop), is converge.c's, where the
 *    criteria are stated in full;
 *  - divergence (NaN, residuals or velocities blowing up) restarts from the
 *    initial state with 0.6 times the under-relaxation, max_retries times;
 *  - with accel_depth > 0, Anderson acceleration (anderson.c) mixes the
 *    state (u, v, w, p and the face velocities; k and eps as SIMPLEC left
 *    them) after every iteration from iteration accel_start, or with
 *    accel_when_stalled from the first iteration after that at which the
 *    residuals have stopped falling (cfd_converge_stalled()).
 */
#include "cfd_private.h"
#include "converge.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#ifdef _OPENMP
#include <omp.h>
#endif

const char *const cfd_var_names[CFD_NVARS] = {"u", "v", "w", "p", "k", "epsilon", "nu_t"};

enum { NB_FLUID = 0, NB_WALL, NB_INLET, NB_OUTLET, NB_SYM };

#define NSNAP 6
#define HIST_COLS CFD_CONVERGE_NRES

struct cfd_solver {
    cfd_grid *g;
    cfd_config cfg;
    double *var[CFD_NVARS];
    double *uf[3];
    double *drc, *dc;
    double *a[6], *ap, *b;
    double *apm[3], *bm[3]; /* momentum: per-component diagonal and source (a_nb shared) */
    double *apsum, *anbsum;
    double *pp;
    unsigned char *wallcell; /* 1: a fluid cell with a wall face (wall-function cell) */
    /* the kind of each cell's six neighbours (NB_*, 3 bits per face f at
     * bit 3 f; fixed at create: the grid and the boundary types do not
     * change), read instead of testing the domain's ends and the solid
     * flags at every face */
    unsigned int *nbk;
    /* per axis d and cell index i along it: the weight of the neighbour in
     * the linear interpolation to the face (wlo: face i, neighbour i - 1;
     * whi: face i + 1, neighbour i + 1) and the centre distances (dlo,
     * dhi), the same expressions as computed at each face before, once */
    double *wlo[3], *whi[3], *dlo[3], *dhi[3];
    /* the cell pressure gradients of the iteration (grad_dir of p), from
     * the momentum assembly to the Rhie-Chow interpolation, where p does
     * not change: computed once per cell instead of once per use; kept in
     * the pressure solver's work arrays, free then */
    double *gradp[3];
    double *disk_f[3];
    /* CFD_INFLOW_FIELD: the sampled values (u, v, w, k, eps) on the open
     * faces, one array per value, indexed by the face's two cell indices
     * (bc_index); NULL on walls and symmetry planes */
    double *bcval[CFD_NFACES][5];
    float *snap[NSNAP]; /* the initial state, for a retry (single precision: it only restarts) */
    cfd_converge conv; /* the run's convergence and averaging windows (converge.c) */
    cfd_mg *mg;
    cfd_aa *aa; /* Anderson acceleration (accel_depth > 0) */
    int singular;
    double *hist;
    int nhist, caphist;
    double norm[HIST_COLS];
    double relax[3];
    size_t bytes;
};

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

void cfd_config_default(cfd_config *cfg)
{
    memset(cfg, 0, sizeof *cfg);
    cfg->turbulence = 1;
    cfg->rho_kgpm3 = CORE_RHO_SL_KGPM3;
    cfg->nu_m2ps = CORE_NU_SL_M2PS;
    for (int f = 0; f < CFD_NFACES; f++)
        cfg->bc[f].type = CFD_BC_WALL;
    cfg->inflow.type = CFD_INFLOW_UNIFORM;
    cfg->inflow.intensity = 0.01;
    cfg->inflow.length_m = 1.0;
    cfg->u_ref_mps = 1.0;
    cfg->max_iter = 2000;
    cfg->tol_residual = 1e-4;
    cfg->tol_monitor = 0.02;
    cfg->monitor_every = 50;
    cfg->relax_u = 0.7;
    cfg->relax_p = 0.9;
    cfg->relax_turb = 0.6;
    cfg->second_order = 1;
    cfg->max_retries = 2;
}

/* ------------------------------------------------------------- geometry */
static inline size_t fidx(const cfd_grid *g, int d, int i, int j, int k)
{
    const int nx = g->n[0], ny = g->n[1];
    switch (d) {
    case 0:
        return (size_t)i + (size_t)(nx + 1) * ((size_t)j + (size_t)ny * k);
    case 1:
        return (size_t)i + (size_t)nx * ((size_t)j + (size_t)(ny + 1) * k);
    default:
        return (size_t)i + (size_t)nx * ((size_t)j + (size_t)ny * k);
    }
}

static inline size_t nfaces(const cfd_grid *g, int d)
{
    return (size_t)(g->n[0] + (d == 0)) * (g->n[1] + (d == 1)) * (g->n[2] + (d == 2));
}

static const size_t *strides(const cfd_grid *g, size_t st[3])
{
    st[0] = 1;
    st[1] = (size_t)g->n[0];
    st[2] = (size_t)g->n[0] * g->n[1];
    return st;
}

/* Kind of the neighbour across face f (0 -x, 1 +x, 2 -y, 3 +y, 4 -z, 5 +z),
 * from the grid and the boundary types (fills s->nbk at create). */
static int nb_kind_slow(const cfd_solver *s, const int ijk[3], int f, size_t c, size_t *cn)
{
    const cfd_grid *g = s->g;
    int d = f >> 1, plus = f & 1;
    int q = ijk[d] + (plus ? 1 : -1);
    if (q < 0 || q >= g->n[d]) {
        switch (s->cfg.bc[f].type) {
        case CFD_BC_INLET:
            return NB_INLET;
        case CFD_BC_OUTLET:
            return NB_OUTLET;
        case CFD_BC_SYMMETRY:
            return NB_SYM;
        default:
            return NB_WALL;
        }
    }
    size_t st = d == 0 ? 1 : d == 1 ? (size_t)g->n[0] : (size_t)g->n[0] * g->n[1];
    *cn = plus ? c + st : c - st;
    return g->solid[*cn] ? NB_WALL : NB_FLUID;
}

/* ... from the table; cn is set for a neighbour inside the domain. */
static inline int nb_kind(const cfd_solver *s, const int ijk[3], int f, size_t c, size_t *cn)
{
    (void)ijk;
    const int kind = (int)((s->nbk[c] >> (3 * f)) & 7u);
    if (kind == NB_FLUID) {
        const int d = f >> 1;
        const size_t st = d == 0 ? 1 : d == 1 ? (size_t)s->g->n[0] : (size_t)s->g->n[0] * s->g->n[1];
        *cn = (f & 1) ? c + st : c - st;
    }
    return kind;
}

/* fmax's result for any two doubles (NaN loses to a number), inline: the
 * library call cost a call per face. */
static inline double fmaxd(double a, double b) { return a >= b ? a : b != b ? a : b; }

static inline double face_area(const cfd_grid *g, int d, const int ijk[3])
{
    int d1 = (d + 1) % 3, d2 = (d + 2) % 3;
    return g->h[d1][ijk[d1]] * g->h[d2][ijk[d2]];
}

/* Wall velocity of face f (a domain wall may move; blocked cells do not). */
static inline const double *wall_vel(const cfd_solver *s, const int ijk[3], int f)
{
    static const double zero[3] = {0.0, 0.0, 0.0};
    int d = f >> 1, q = ijk[d] + ((f & 1) ? 1 : -1);
    if (q < 0 || q >= s->g->n[d])
        return s->cfg.bc[f].vel_mps;
    return zero;
}

/* Index of face f of cell ijk in the face array of its axis. */
static inline size_t face_of(const cfd_grid *g, const int ijk[3], int f)
{
    int d = f >> 1, q[3] = {ijk[0], ijk[1], ijk[2]};
    q[d] += f & 1;
    return fidx(g, d, q[0], q[1], q[2]);
}

/* Pressure on a pressure-outlet face: 0 where the air leaves; where it comes
 * back in, the static pressure of air at rest at total pressure 0,
 * p = -rho u_n^2 / 2 (the "backflow total pressure" of Fluent, OpenFOAM's
 * totalPressure). Without it, backflow enters for free at p = 0 and a
 * wake reaching the outlet feeds itself until the run diverges. */
static inline double outlet_p(const cfd_solver *s, const int ijk[3], int f)
{
    double un = ((f & 1) ? 1.0 : -1.0) * s->uf[f >> 1][face_of(s->g, ijk, f)];
    return un < 0.0 ? -0.5 * s->cfg.rho_kgpm3 * un * un : 0.0;
}

/* --------------------------------------------------------------- inflow */
static void profile_at(const cfd_solver *s, const double pos[3], double vel[3], double *k, double *eps)
{
    const cfd_inflow *in = &s->cfg.inflow;
    if (in->type == CFD_INFLOW_FIELD) {
        double out[5];
        in->fn(in->fn_user, pos, out);
        for (int d = 0; d < 3; d++)
            vel[d] = out[d];
        *k = fmaxd(out[3], 1e-10);
        *eps = fmaxd(out[4], 1e-12);
        return;
    }
    double umag = sqrt(in->vel_mps[0] * in->vel_mps[0] + in->vel_mps[1] * in->vel_mps[1] +
                       in->vel_mps[2] * in->vel_mps[2]);
    double scale = 1.0;
    double kk, ee;
    double h = 0.0;
    if (in->type != CFD_INFLOW_UNIFORM) {
        h = in->ground_sign >= 0 ? in->ground_coord_m - pos[in->ground_axis]
                                 : pos[in->ground_axis] - in->ground_coord_m;
        if (h < 0.0)
            h = 0.0;
    }
    if (in->type == CFD_INFLOW_ABL) {
        double z0 = in->z0_m > 0.0 ? in->z0_m : 2e-4;
        double ustar = CFD_KAPPA * umag / log((in->z_ref_m + z0) / z0);
        scale = log((h + z0) / z0) / log((in->z_ref_m + z0) / z0);
        kk = ustar * ustar / sqrt(CFD_CMU);
        ee = ustar * ustar * ustar / (CFD_KAPPA * (h + z0));
    } else {
        if (in->type == CFD_INFLOW_POWER && in->delta_m > 0.0)
            scale = h >= in->delta_m ? 1.0 : pow(h / in->delta_m, 1.0 / 7.0);
        double iu = fmaxd(in->intensity, 1e-4) * fmaxd(umag, s->cfg.u_ref_mps);
        kk = 1.5 * iu * iu;
        ee = pow(CFD_CMU, 0.75) * pow(kk, 1.5) / fmaxd(in->length_m, 1e-9);
    }
    for (int d = 0; d < 3; d++)
        vel[d] = in->vel_mps[d] * scale;
    *k = kk;
    *eps = ee;
}

/* Index of a boundary face of face set f: its two cell indices across. */
static inline size_t bc_index(const cfd_grid *g, int f, const int ijk[3])
{
    int d = f >> 1, a = d == 0 ? 1 : 0, b = d == 2 ? 1 : 2;
    return (size_t)ijk[a] + (size_t)g->n[a] * (size_t)ijk[b];
}

/* The inflow on boundary face f of cell ijk (pos: the face centre). A
 * sampled inflow is read from the values stored at create: sampling an
 * outer field at every face each iteration cost a third of an iteration. */
static void inflow_at(const cfd_solver *s, int f, const int ijk[3], const double pos[3], double vel[3], double *k,
                      double *eps)
{
    if (s->cfg.inflow.type == CFD_INFLOW_FIELD && s->bcval[f][0]) {
        size_t q = bc_index(s->g, f, ijk);
        for (int d = 0; d < 3; d++)
            vel[d] = s->bcval[f][d][q];
        *k = s->bcval[f][3][q];
        *eps = s->bcval[f][4][q];
        return;
    }
    profile_at(s, pos, vel, k, eps);
}

/* The cell index along axis d whose span [xn[i], xn[i + 1]] holds x; -1
 * outside the grid. */
static int axis_cell(const cfd_grid *g, int d, double x)
{
    const double *xn = g->xn[d];
    if (!(x >= xn[0] && x <= xn[g->n[d]]))
        return -1;
    int lo = 0, hi = g->n[d] - 1;
    while (lo < hi) {
        int m = (lo + hi + 1) / 2;
        if (xn[m] <= x)
            lo = m;
        else
            hi = m - 1;
    }
    return lo;
}

int cfd_solver_inflow_at(const cfd_solver *s, int face, const double pos_m[3], double vel[3], double *k, double *eps)
{
    if (face < 0 || face >= CFD_NFACES ||
        (s->cfg.bc[face].type != CFD_BC_INLET && s->cfg.bc[face].type != CFD_BC_OUTLET))
        return -1;
    int d = face >> 1, ijk[3];
    ijk[d] = (face & 1) ? s->g->n[d] - 1 : 0;
    for (int e = 0; e < 3; e++)
        if (e != d && (ijk[e] = axis_cell(s->g, e, pos_m[e])) < 0)
            return -1;
    inflow_at(s, face, ijk, pos_m, vel, k, eps);
    return 0;
}

/* ---------------------------------------------------------- life cycle */
static double *alloc_arr(cfd_solver *s, size_t n)
{
    double *p = calloc(n ? n : 1, sizeof(double));
    if (p)
        s->bytes += n * sizeof(double);
    return p;
}

static float *alloc_snap(cfd_solver *s, size_t n)
{
    float *p = calloc(n ? n : 1, sizeof(float));
    if (p)
        s->bytes += n * sizeof(float);
    return p;
}

/* CFD_INFLOW_FIELD: sample the inflow once on every inlet and outlet face
 * (outlets take k and epsilon of backflow from it). */
static int sample_open_faces(cfd_solver *s, core_err *err)
{
    const cfd_grid *g = s->g;
    for (int f = 0; f < CFD_NFACES; f++) {
        if (s->cfg.bc[f].type != CFD_BC_INLET && s->cfg.bc[f].type != CFD_BC_OUTLET)
            continue;
        int d = f >> 1, a = d == 0 ? 1 : 0, b = d == 2 ? 1 : 2;
        size_t nf = (size_t)g->n[a] * g->n[b];
        for (int v = 0; v < 5; v++)
            if (!(s->bcval[f][v] = alloc_arr(s, nf)))
                return core_err_set(err, -2, "cfd solver: out of memory (inflow faces)");
        #pragma omp parallel for schedule(static)
        for (int jb = 0; jb < g->n[b]; jb++)
            for (int ja = 0; ja < g->n[a]; ja++) {
                int ijk[3];
                ijk[d] = (f & 1) ? g->n[d] - 1 : 0;
                ijk[a] = ja;
                ijk[b] = jb;
                double pos[3] = {g->xc[0][ijk[0]], g->xc[1][ijk[1]], g->xc[2][ijk[2]]}, vel[3], kk, ee;
                pos[d] = g->xn[d][(f & 1) ? g->n[d] : 0];
                profile_at(s, pos, vel, &kk, &ee);
                size_t q = bc_index(g, f, ijk);
                for (int e = 0; e < 3; e++)
                    s->bcval[f][e][q] = vel[e];
                s->bcval[f][3][q] = kk;
                s->bcval[f][4][q] = ee;
            }
    }
    return 0;
}

/* The configurations cfd_solver_create accepts (the message below names the ranges). */
static int config_ok(const cfd_config *cfg)
{
    return cfg->nu_m2ps > 0.0 && cfg->rho_kgpm3 > 0.0 && cfg->u_ref_mps > 0.0 && cfg->max_iter >= 1 &&
           cfg->n_monitor >= 0 && cfg->n_monitor <= CFD_MAX_MONITOR && cfg->relax_u > 0.0 && cfg->relax_u <= 1.0 &&
           cfg->relax_p > 0.0 && cfg->relax_p <= 1.0 && cfg->relax_turb > 0.0 && cfg->relax_turb <= 1.0 &&
           (cfg->limiter == CFD_LIMITER_VANLEER || cfg->limiter == CFD_LIMITER_MINMOD) && cfg->accel_depth >= 0 &&
           cfg->accel_depth <= 16 && !(cfg->inflow.type == CFD_INFLOW_FIELD && !cfg->inflow.fn);
}

/* The solver's arrays and the multigrid pressure solver, counted in
 * s->bytes; 0 ok, < 0 out of memory (the caller destroys s). */
static int alloc_arrays(cfd_solver *s)
{
    const cfd_grid *grid = s->g;
    size_t n = grid->ncell;
    /* the grid: solid flags and three coordinate arrays per axis */
    s->bytes = sizeof *s + n + 3 * sizeof(double) * (grid->n[0] + grid->n[1] + grid->n[2] + 3);
    int ok = 1;
    for (int v = 0; v < CFD_NVARS; v++)
        ok &= (s->var[v] = alloc_arr(s, n)) != NULL;
    for (int d = 0; d < 3; d++)
        ok &= (s->uf[d] = alloc_arr(s, nfaces(grid, d))) != NULL;
    for (int f = 0; f < 6; f++)
        ok &= (s->a[f] = alloc_arr(s, n)) != NULL;
    ok &= (s->ap = alloc_arr(s, n)) != NULL;
    ok &= (s->b = alloc_arr(s, n)) != NULL;
    s->apm[0] = s->ap, s->bm[0] = s->b;
    for (int d = 1; d < 3; d++) {
        ok &= (s->apm[d] = alloc_arr(s, n)) != NULL;
        ok &= (s->bm[d] = alloc_arr(s, n)) != NULL;
    }
    ok &= (s->drc = alloc_arr(s, n)) != NULL;
    ok &= (s->dc = alloc_arr(s, n)) != NULL;
    ok &= (s->apsum = alloc_arr(s, n)) != NULL;
    ok &= (s->anbsum = alloc_arr(s, n)) != NULL;
    ok &= (s->pp = alloc_arr(s, n)) != NULL;
    for (int v = 0; v < NSNAP; v++)
        ok &= (s->snap[v] = alloc_snap(s, n)) != NULL;
    ok &= (s->wallcell = calloc(n ? n : 1, 1)) != NULL;
    s->bytes += n;
    ok &= (s->nbk = calloc(n ? n : 1, sizeof *s->nbk)) != NULL;
    s->bytes += n * sizeof *s->nbk;
    for (int d = 0; d < 3; d++) {
        ok &= (s->wlo[d] = alloc_arr(s, grid->n[d])) != NULL;
        ok &= (s->whi[d] = alloc_arr(s, grid->n[d])) != NULL;
        ok &= (s->dlo[d] = alloc_arr(s, grid->n[d])) != NULL;
        ok &= (s->dhi[d] = alloc_arr(s, grid->n[d])) != NULL;
    }
    s->mg = ok ? cfd_mg_create(grid->n) : NULL;
    if (!ok || !s->mg)
        return -1;
    s->bytes += cfd_mg_bytes(s->mg);
    for (int d = 0; d < 3; d++)
        s->gradp[d] = cfd_mg_work(s->mg, d);
    return 0;
}

/* Anderson acceleration (accel_depth > 0) over the state it mixes: cell u,
 * v, w (1/u_ref), p (1/(rho u_ref^2)) and the face velocities (1/u_ref),
 * whose combination keeps the discrete continuity of the iterates it
 * mixes. 0 ok, < 0 out of memory. */
static int accel_create(cfd_solver *s)
{
    const cfd_config *cfg = &s->cfg;
    size_t len[7];
    double w[7];
    for (int q = 0; q < 4; q++) {
        len[q] = s->g->ncell;
        w[q] = q < 3 ? 1.0 / cfg->u_ref_mps : 1.0 / (cfg->rho_kgpm3 * cfg->u_ref_mps * cfg->u_ref_mps);
    }
    for (int d = 0; d < 3; d++) {
        len[4 + d] = nfaces(s->g, d);
        w[4 + d] = 1.0 / cfg->u_ref_mps;
    }
    if (!(s->aa = cfd_aa_create(cfg->accel_depth, 7, len, w)))
        return -1;
    s->bytes += cfd_aa_bytes(s->aa);
    return 0;
}

/* The neighbour kinds (s->nbk) and the axis tables (s->wlo .. s->dhi). */
static void build_tables(cfd_solver *s)
{
    const cfd_grid *grid = s->g;
    #pragma omp parallel for schedule(static)
    for (int k = 0; k < grid->n[2]; k++)
        for (int j = 0; j < grid->n[1]; j++)
            for (int i = 0; i < grid->n[0]; i++) {
                int ijk[3] = {i, j, k};
                size_t c = CFD_IDX(grid, i, j, k), cn;
                unsigned int m = 0;
                for (int f = 0; f < 6; f++)
                    m |= (unsigned int)nb_kind_slow(s, ijk, f, c, &cn) << (3 * f);
                s->nbk[c] = m;
            }
    for (int d = 0; d < 3; d++) {
        const double *xc = grid->xc[d], *xn = grid->xn[d];
        for (int i = 0; i < grid->n[d]; i++) {
            s->wlo[d][i] = s->dlo[d][i] = s->whi[d][i] = s->dhi[d][i] = 0.0;
            if (i > 0) {
                s->wlo[d][i] = (xn[i] - xc[i]) / (xc[i - 1] - xc[i]);
                s->dlo[d][i] = fabs(xc[i - 1] - xc[i]);
            }
            if (i + 1 < grid->n[d]) {
                s->whi[d][i] = (xn[i + 1] - xc[i]) / (xc[i + 1] - xc[i]);
                s->dhi[d][i] = fabs(xc[i + 1] - xc[i]);
            }
        }
    }
}

/* The wall-function cells: fluid cells with a wall face. */
static void mark_wall_cells(cfd_solver *s)
{
    const cfd_grid *grid = s->g;
    #pragma omp parallel for schedule(static)
    for (int k = 0; k < grid->n[2]; k++)
        for (int j = 0; j < grid->n[1]; j++)
            for (int i = 0; i < grid->n[0]; i++) {
                int ijk[3] = {i, j, k};
                size_t c = CFD_IDX(grid, i, j, k), cn;
                unsigned char w = 0;
                for (int f = 0; f < 6 && !grid->solid[c]; f++)
                    w |= nb_kind(s, ijk, f, c, &cn) == NB_WALL;
                s->wallcell[c] = w;
            }
}

cfd_solver *cfd_solver_create(cfd_grid *grid, const cfd_config *cfg, core_err *err)
{
    if (!grid) {
        core_err_set(err, -1, "cfd solver: no grid");
        return NULL;
    }
    if (!config_ok(cfg)) {
        cfd_grid_destroy(grid);
        core_err_set(err, -1,
                     "cfd solver: bad configuration (need nu, rho, u_ref > 0, max_iter >= 1, "
                     "relaxation factors in (0, 1], at most %d monitors, a known limiter, "
                     "accel_depth 0..16, a sampler for a sampled inflow)",
                     CFD_MAX_MONITOR);
        return NULL;
    }
    cfd_solver *s = calloc(1, sizeof *s);
    if (!s) {
        cfd_grid_destroy(grid);
        core_err_set(err, -2, "cfd solver: out of memory");
        return NULL;
    }
    s->g = grid;
    s->cfg = *cfg;
    if (alloc_arrays(s) != 0) {
        cfd_solver_destroy(s);
        core_err_set(err, -2, "cfd solver: out of memory for %zu cells", grid->ncell);
        return NULL;
    }
    if (cfg->accel_depth > 0 && accel_create(s) != 0) {
        cfd_solver_destroy(s);
        core_err_set(err, -2, "cfd solver: out of memory for Anderson acceleration (%zu cells, depth %d)",
                     grid->ncell, cfg->accel_depth);
        return NULL;
    }
    s->singular = 1;
    for (int f = 0; f < CFD_NFACES; f++)
        if (cfg->bc[f].type == CFD_BC_OUTLET)
            s->singular = 0;
    build_tables(s);
    mark_wall_cells(s);
    if (cfg->inflow.type == CFD_INFLOW_FIELD && sample_open_faces(s, err) != 0) {
        cfd_solver_destroy(s);
        return NULL;
    }
    cfd_solver_init_inflow(s);
    return s;
}

void cfd_solver_destroy(cfd_solver *s)
{
    if (!s)
        return;
    cfd_aa_destroy(s->aa);
    for (int v = 0; v < CFD_NVARS; v++)
        free(s->var[v]);
    for (int d = 0; d < 3; d++) {
        free(s->uf[d]);
        free(s->disk_f[d]);
    }
    for (int f = 0; f < 6; f++)
        free(s->a[f]);
    free(s->ap);
    free(s->b);
    for (int d = 1; d < 3; d++) {
        free(s->apm[d]);
        free(s->bm[d]);
    }
    free(s->drc);
    free(s->dc);
    free(s->apsum);
    free(s->anbsum);
    free(s->pp);
    free(s->wallcell);
    free(s->nbk);
    for (int d = 0; d < 3; d++) {
        free(s->wlo[d]);
        free(s->whi[d]);
        free(s->dlo[d]);
        free(s->dhi[d]);
    }
    for (int f = 0; f < CFD_NFACES; f++)
        for (int v = 0; v < 5; v++)
            free(s->bcval[f][v]);
    for (int v = 0; v < NSNAP; v++)
        free(s->snap[v]);
    cfd_converge_release(&s->conv);
    free(s->hist);
    cfd_mg_destroy(s->mg);
    cfd_grid_destroy(s->g);
    free(s);
}

const cfd_grid *cfd_solver_grid(const cfd_solver *s) { return s->g; }
const cfd_config *cfd_solver_config(const cfd_solver *s) { return &s->cfg; }
const double *cfd_solver_var(const cfd_solver *s, int var)
{
    return (var >= 0 && var < CFD_NVARS) ? s->var[var] : NULL;
}
const double *cfd_solver_disk_force(const cfd_solver *s, int d)
{
    return (d >= 0 && d < 3) ? s->disk_f[d] : NULL;
}
const double *cfd_solver_history(const cfd_solver *s, int *n)
{
    *n = s->nhist;
    return s->hist;
}
size_t cfd_solver_bytes(const cfd_solver *s) { return s->bytes + cfd_converge_bytes(&s->conv); }

int cfd_solver_set_disk(cfd_solver *s, const cfd_disk *disk, core_err *err)
{
    if (!disk) {
        for (int d = 0; d < 3; d++) {
            free(s->disk_f[d]);
            s->disk_f[d] = NULL;
        }
        return 0;
    }
    for (int d = 0; d < 3; d++)
        if (!s->disk_f[d] && !(s->disk_f[d] = alloc_arr(s, s->g->ncell)))
            return core_err_set(err, -2, "cfd disk: out of memory");
    return cfd_disk_distribute(s->g, disk, s->disk_f, err);
}

/* Face velocities from cell values (linear) and the boundary conditions. */
static void faces_from_cells(cfd_solver *s)
{
    const cfd_grid *g = s->g;
    for (int d = 0; d < 3; d++) {
        const double *u = s->var[CFD_VAR_U + d];
        #pragma omp parallel for schedule(static)
        for (int k = 0; k < g->n[2] + (d == 2); k++)
            for (int j = 0; j < g->n[1] + (d == 1); j++)
                for (int i = 0; i < g->n[0] + (d == 0); i++) {
                    int ijk[3] = {i, j, k};
                    size_t fi = fidx(g, d, i, j, k);
                    int q = ijk[d];
                    int lo = q - 1, hi = q;
                    int jm[3] = {i, j, k}, jp[3] = {i, j, k};
                    jm[d] = lo;
                    jp[d] = hi;
                    int inm = lo >= 0, inp = hi < g->n[d];
                    size_t cm = inm ? CFD_IDX(g, jm[0], jm[1], jm[2]) : 0;
                    size_t cp = inp ? CFD_IDX(g, jp[0], jp[1], jp[2]) : 0;
                    double v = 0.0;
                    if (inm && inp) {
                        if (!g->solid[cm] && !g->solid[cp])
                            v = 0.5 * (u[cm] + u[cp]);
                    } else {
                        int f = 2 * d + (inp ? 0 : 1);
                        size_t c = inp ? cp : cm;
                        if (!g->solid[c]) {
                            if (s->cfg.bc[f].type == CFD_BC_INLET) {
                                double pos[3] = {g->xc[0][jp[0] < g->n[0] ? jp[0] : g->n[0] - 1],
                                                 g->xc[1][jp[1] < g->n[1] ? jp[1] : g->n[1] - 1],
                                                 g->xc[2][jp[2] < g->n[2] ? jp[2] : g->n[2] - 1]};
                                pos[d] = g->xn[d][q];
                                double vel[3], kk, ee;
                                inflow_at(s, f, inp ? jp : jm, pos, vel, &kk, &ee);
                                v = vel[d];
                            } else if (s->cfg.bc[f].type == CFD_BC_OUTLET) {
                                v = u[c];
                            }
                        }
                    }
                    s->uf[d][fi] = v;
                }
    }
}

void cfd_solver_init_inflow(cfd_solver *s)
{
    const cfd_grid *g = s->g;
    int has_inlet = 0;
    for (int f = 0; f < CFD_NFACES; f++)
        has_inlet |= s->cfg.bc[f].type == CFD_BC_INLET;
    #pragma omp parallel for schedule(static)
    for (int k = 0; k < g->n[2]; k++)
        for (int j = 0; j < g->n[1]; j++)
            for (int i = 0; i < g->n[0]; i++) {
                size_t c = CFD_IDX(g, i, j, k);
                double pos[3] = {g->xc[0][i], g->xc[1][j], g->xc[2][k]};
                double vel[3], kk, ee;
                profile_at(s, pos, vel, &kk, &ee);
                if (!has_inlet)
                    vel[0] = vel[1] = vel[2] = 0.0;
                if (g->solid[c])
                    vel[0] = vel[1] = vel[2] = 0.0;
                for (int d = 0; d < 3; d++)
                    s->var[CFD_VAR_U + d][c] = vel[d];
                s->var[CFD_VAR_P][c] = 0.0;
                s->var[CFD_VAR_K][c] = kk;
                s->var[CFD_VAR_EPS][c] = ee;
                s->var[CFD_VAR_NUT][c] =
                    (s->cfg.turbulence && !g->solid[c]) ? CFD_CMU * kk * kk / ee : 0.0;
            }
    faces_from_cells(s);
}

int cfd_solver_set_var(cfd_solver *s, int var, const double *values)
{
    if (var < 0 || var >= CFD_NVARS)
        return -1;
    memcpy(s->var[var], values, s->g->ncell * sizeof *values);
    faces_from_cells(s);
    return 0;
}

/* Warm starts: every fluid cell from a sampler of another state (a field
 * file or a coarser solver), k and epsilon kept positive. */
typedef int (*sample_fn)(const void *src, const double pos[3], double out[CFD_NVARS]);

static int sample_field(const void *src, const double pos[3], double out[CFD_NVARS])
{
    return cfd_field_sample(src, pos, out);
}

static int sample_solver(const void *src, const double pos[3], double out[CFD_NVARS])
{
    return cfd_solver_sample(src, pos, out);
}

static int init_interp(cfd_solver *s, sample_fn sample, const void *src, const char *what, core_err *err)
{
    const cfd_grid *g = s->g;
    cfd_solver_init_inflow(s);
    #pragma omp parallel for schedule(static)
    for (int k = 0; k < g->n[2]; k++)
        for (int j = 0; j < g->n[1]; j++)
            for (int i = 0; i < g->n[0]; i++) {
                size_t c = CFD_IDX(g, i, j, k);
                if (g->solid[c])
                    continue;
                double pos[3] = {g->xc[0][i], g->xc[1][j], g->xc[2][k]}, out[CFD_NVARS];
                sample(src, pos, out);
                for (int v = 0; v < CFD_NVARS; v++)
                    s->var[v][c] = out[v];
                if (!(s->var[CFD_VAR_K][c] > 1e-12))
                    s->var[CFD_VAR_K][c] = 1e-12;
                if (!(s->var[CFD_VAR_EPS][c] > 1e-12))
                    s->var[CFD_VAR_EPS][c] = 1e-12;
                if (!s->cfg.turbulence)
                    s->var[CFD_VAR_NUT][c] = 0.0;
            }
    faces_from_cells(s);
    if (cfd_solver_has_nan(s))
        return core_err_set(err, -1, "cfd %s: the source gives NaN values", what);
    return 0;
}

int cfd_solver_init_from_field(cfd_solver *s, const cfd_field *f, core_err *err)
{
    return init_interp(s, sample_field, f, "warm start", err);
}

int cfd_solver_init_from_solver(cfd_solver *s, const cfd_solver *src, core_err *err)
{
    return init_interp(s, sample_solver, src, "coarse-to-fine start", err);
}

int cfd_solver_has_nan(const cfd_solver *s)
{
    int bad = 0;
    for (int v = 0; v < CFD_NVARS; v++) {
        const double *a = s->var[v];
        #pragma omp parallel for reduction(| : bad) schedule(static)
        for (size_t c = 0; c < s->g->ncell; c++)
            bad |= !isfinite(a[c]);
    }
    return bad;
}

/* ----------------------------------------------------- cell gradients */
/* Face value of phi across face f of cell c for the gradient: neighbour
 * interpolation, the wall or inlet value, or the cell value. */
static inline double face_value(const cfd_solver *s, const double *phi, int var, const int ijk[3], int f,
                                size_t c)
{
    const cfd_grid *g = s->g;
    size_t cn = 0;
    int kind = nb_kind(s, ijk, f, c, &cn);
    int d = f >> 1;
    switch (kind) {
    case NB_FLUID: {
        double w = (f & 1) ? s->whi[d][ijk[d]] : s->wlo[d][ijk[d]];
        return (1.0 - w) * phi[c] + w * phi[cn];
    }
    case NB_WALL:
        if (var >= CFD_VAR_U && var <= CFD_VAR_W)
            return wall_vel(s, ijk, f)[var - CFD_VAR_U];
        if (var == CFD_VAR_P) {
            /* pressure (and its correction) extrapolated linearly from the
             * cell and its neighbour on the other side: with p_w = p_P the
             * cell gradient is half the true one, the Rhie-Chow term at
             * the next face does not vanish for a linear pressure field and
             * drives a spurious mass flux wherever the wall-normal pressure
             * gradient is large (deck edges, hangar corners) */
            size_t co = 0;
            int fo = f ^ 1;
            if (nb_kind(s, ijk, fo, c, &co) == NB_FLUID) {
                int qo = ijk[d] + ((fo & 1) ? 1 : -1);
                double dist = fabs(g->xc[d][qo] - g->xc[d][ijk[d]]);
                return phi[c] + (phi[c] - phi[co]) * 0.5 * g->h[d][ijk[d]] / dist;
            }
        }
        return phi[c];
    case NB_INLET:
        if (var >= CFD_VAR_U && var <= CFD_VAR_W) {
            double pos[3] = {g->xc[0][ijk[0]], g->xc[1][ijk[1]], g->xc[2][ijk[2]]}, vel[3], kk, ee;
            pos[d] = g->xn[d][ijk[d] + (f & 1)];
            inflow_at(s, f, ijk, pos, vel, &kk, &ee);
            return vel[var - CFD_VAR_U];
        }
        return phi[c];
    case NB_OUTLET:
        if (var == CFD_VAR_P)
            return phi == s->var[CFD_VAR_P] ? outlet_p(s, ijk, f) : 0.0;
        return phi[c];
    default:
        if (var - CFD_VAR_U == d)
            return 0.0;
        return phi[c];
    }
}

static inline double grad_dir(const cfd_solver *s, const double *phi, int var, const int ijk[3], int d,
                              size_t c)
{
    double hi = face_value(s, phi, var, ijk, 2 * d + 1, c);
    double lo = face_value(s, phi, var, ijk, 2 * d, c);
    return (hi - lo) / s->g->h[d][ijk[d]];
}

/* s->gradp: the pressure gradient of every fluid cell (0 in blocked cells). */
static void pressure_gradients(cfd_solver *s)
{
    const cfd_grid *g = s->g;
    const double *p = s->var[CFD_VAR_P];
    #pragma omp parallel for schedule(dynamic, 1)
    for (int k = 0; k < g->n[2]; k++)
        for (int j = 0; j < g->n[1]; j++)
            for (int i = 0; i < g->n[0]; i++) {
                int ijk[3] = {i, j, k};
                size_t c = CFD_IDX(g, i, j, k);
                for (int d = 0; d < 3; d++)
                    s->gradp[d][c] = g->solid[c] ? 0.0 : grad_dir(s, p, CFD_VAR_P, ijk, d, c);
            }
}

/* ------------------------------------------------------------ assembly */
/* The cells of the deferred correction of the face between c and its
 * neighbour cn across f, for the outward flux F from c: cc upwind, cd
 * downwind, cu the next upwind; 0 where there is no fluid cell cu (no
 * correction). Shared by the components assembled together. */
static inline int tvd_cells(const cfd_solver *s, const int ijk[3], int f, size_t c, size_t cn, double F,
                            size_t *cc, size_t *cd, size_t *cu)
{
    const cfd_grid *g = s->g;
    int d = f >> 1, plus = f & 1;
    size_t st = d == 0 ? 1 : d == 1 ? (size_t)g->n[0] : (size_t)g->n[0] * g->n[1];
    int qu;
    if (F >= 0.0) {
        *cc = c, *cd = cn;
        qu = ijk[d] + (plus ? -1 : 1);
        *cu = plus ? c - st : c + st;
    } else {
        *cc = cn, *cd = c;
        qu = ijk[d] + (plus ? 2 : -2);
        *cu = plus ? cn + st : cn - st;
    }
    return !(qu < 0 || qu >= g->n[d] || g->solid[*cu]);
}

/* Deferred-correction flux F (phi_HO - phi_C) = F psi(r) delta / 2 on the
 * cells tvd_cells gave, with delta = phi_D - phi_C, n = phi_C - phi_U and
 * r = n / delta, written without r: van Leer's psi delta = 2 n delta /
 * (delta + n) for r > 0 (one division where r and psi took two, each
 * waiting on the other), minmod's psi delta = n for 0 < r < 1 and delta
 * for r >= 1 (none). The same values to round-off (tests/cfd/test_cfd_same). */
static inline double tvd_flux(const double *phi, size_t cc, size_t cd, size_t cu, double F, int minmod)
{
    double pc = phi[cc], pd = phi[cd];
    double delta = pd - pc;
    if (fabs(delta) < 1e-30)
        return 0.0;
    double n = pc - phi[cu];
    if (n * delta != n * delta)
        return n * delta; /* not finite: the NaN goes on, as it did through r */
    if (!(n * delta > 0.0)) /* r <= 0: psi = 0 */
        return 0.0;
    double pd_lim;
    if (minmod)
        pd_lim = fabs(n) < fabs(delta) ? n : delta;
    else
        pd_lim = 2.0 * n * delta / (delta + n);
    return F * 0.5 * pd_lim;
}

/* Assemble a_nb, a_P, b with relaxation alpha for K or EPS, or, with var =
 * CFD_VAR_U, for the three momentum components at once: they share the
 * convection-diffusion coefficients a_nb (same face fluxes, same nu + nu_t),
 * which are computed once; the per-component diagonal and source go to
 * apm[d], bm[d]. Components along an axis with one cell (2-D cases) are not
 * assembled. */
static void assemble(cfd_solver *s, int var, double alpha, const double *pk)
{
    const cfd_grid *g = s->g;
    const cfd_config *cfg = &s->cfg;
    const double nu = cfg->nu_m2ps, rho = cfg->rho_kgpm3;
    const double *nut = s->var[CFD_VAR_NUT];
    const double *kk = s->var[CFD_VAR_K], *ee = s->var[CFD_VAR_EPS];
    const int mom = var <= CFD_VAR_W;
    const double sigma = var == CFD_VAR_K ? CFD_SIGMA_K : var == CFD_VAR_EPS ? CFD_SIGMA_E : 1.0;
    const int turb = cfg->turbulence;
    const int minmod = cfg->limiter == CFD_LIMITER_MINMOD;
    /* the variables assembled: u, v, w (those solved) or one of k, eps */
    int nv = 0, comps[3];
    if (mom) {
        for (int d = 0; d < 3; d++)
            if (g->n[d] > 1)
                comps[nv++] = d;
    } else {
        comps[nv++] = -1;
    }
    double *apv[3], *bv[3];
    const double *phiv[3];
    for (int m = 0; m < nv; m++) {
        apv[m] = mom ? s->apm[comps[m]] : s->ap;
        bv[m] = mom ? s->bm[comps[m]] : s->b;
        phiv[m] = mom ? s->var[CFD_VAR_U + comps[m]] : s->var[var];
    }
    #pragma omp parallel for schedule(dynamic, 1)
    for (int k = 0; k < g->n[2]; k++)
        for (int j = 0; j < g->n[1]; j++)
            for (int i = 0; i < g->n[0]; i++) {
                int ijk[3] = {i, j, k};
                size_t c = CFD_IDX(g, i, j, k);
                if (g->solid[c]) {
                    for (int f = 0; f < 6; f++)
                        s->a[f][c] = 0.0;
                    for (int m = 0; m < nv; m++) {
                        apv[m][c] = 1.0;
                        bv[m][c] = phiv[m][c];
                    }
                    if (mom)
                        s->apsum[c] = s->anbsum[c] = 0.0;
                    continue;
                }
                double V = g->h[0][i] * g->h[1][j] * g->h[2][k];
                double ap[3] = {0.0, 0.0, 0.0}, bb[3] = {0.0, 0.0, 0.0}, anb = 0.0;
                int nwall = 0;
                double pkw = 0.0, ymin = 1e300;
                const int ho = cfg->second_order && !(turb && s->wallcell[c]);
                for (int f = 0; f < 6; f++) {
                    int d = f >> 1, plus = f & 1;
                    double A = face_area(g, d, ijk);
                    size_t fi = plus ? (d == 0 ? fidx(g, 0, i + 1, j, k) : d == 1 ? fidx(g, 1, i, j + 1, k) : fidx(g, 2, i, j, k + 1))
                                     : fidx(g, d, i, j, k);
                    double F = (plus ? 1.0 : -1.0) * s->uf[d][fi] * A;
                    size_t cn = 0;
                    int kind = nb_kind(s, ijk, f, c, &cn);
                    double a_f = 0.0;
                    if (kind == NB_FLUID) {
                        double dist = plus ? s->dhi[d][ijk[d]] : s->dlo[d][ijk[d]];
                        /* x / 1 is x: the momentum's sigma costs no division */
                        double gam = nu + (turb ? (mom ? 0.5 * (nut[c] + nut[cn]) : 0.5 * (nut[c] + nut[cn]) / sigma)
                                                : 0.0);
                        a_f = gam * A / dist + fmaxd(-F, 0.0);
                        size_t tc, td, tu;
                        if (ho && !(turb && s->wallcell[cn]) && tvd_cells(s, ijk, f, c, cn, F, &tc, &td, &tu))
                            for (int m = 0; m < nv; m++)
                                bb[m] -= tvd_flux(phiv[m], tc, td, tu, F, minmod);
                        anb += a_f;
                    } else if (kind == NB_WALL) {
                        double y = 0.5 * g->h[d][ijk[d]];
                        if (mom) {
                            /* wall shear on the tangential components */
                            double nuw = turb ? cfd_wall_nu(nu, kk[c], y) : nu;
                            double cw = nuw * A / y;
                            const double *uw = wall_vel(s, ijk, f);
                            for (int m = 0; m < nv; m++)
                                if (comps[m] != d) {
                                    ap[m] += cw;
                                    bb[m] += cw * uw[comps[m]];
                                }
                        }
                        if (turb && var == CFD_VAR_K) {
                            /* P_k = tau_w u* / (kappa y) from the log law */
                            const double *uw = wall_vel(s, ijk, f);
                            double ut2 = 0.0;
                            for (int e = 0; e < 3; e++)
                                if (e != d) {
                                    double du = s->var[CFD_VAR_U + e][c] - uw[e];
                                    ut2 += du * du;
                                }
                            double up = sqrt(ut2);
                            double nuw = cfd_wall_nu(nu, kk[c], y);
                            double us = pow(CFD_CMU, 0.25) * sqrt(fmaxd(kk[c], 0.0));
                            double tau = nuw * up / y;
                            pkw += tau * us / (CFD_KAPPA * y);
                        }
                        nwall++;
                        if (y < ymin)
                            ymin = y;
                    } else if (kind == NB_INLET) {
                        double pos[3] = {g->xc[0][i], g->xc[1][j], g->xc[2][k]}, vel[3], ki, ei;
                        pos[d] = g->xn[d][ijk[d] + plus];
                        inflow_at(s, f, ijk, pos, vel, &ki, &ei);
                        double gam = nu + (turb ? nut[c] / sigma : 0.0);
                        double cb = gam * A / (0.5 * g->h[d][ijk[d]]) + fmaxd(-F, 0.0);
                        for (int m = 0; m < nv; m++) {
                            double val = mom ? vel[comps[m]] : var == CFD_VAR_K ? ki : ei;
                            ap[m] += cb;
                            bb[m] += cb * val;
                        }
                    } else if (kind == NB_OUTLET) {
                        /* backflow: the tangential velocity of the air
                         * coming in is 0 (OpenFOAM's
                         * pressureInletOutletVelocity), the normal one
                         * zero-gradient; k and eps from the inflow */
                        if (F < 0.0 && mom) {
                            for (int m = 0; m < nv; m++)
                                if (comps[m] != d)
                                    ap[m] += -F;
                        }
                        if (F < 0.0 && !mom) {
                            double pos[3] = {g->xc[0][i], g->xc[1][j], g->xc[2][k]}, vel[3], ki, ei;
                            inflow_at(s, f, ijk, pos, vel, &ki, &ei);
                            ap[0] += -F;
                            bb[0] += -F * (var == CFD_VAR_K ? ki : ei);
                        }
                    } else { /* symmetry */
                        if (mom) {
                            double gam = nu + (turb ? nut[c] : 0.0);
                            for (int m = 0; m < nv; m++)
                                if (comps[m] == d)
                                    ap[m] += gam * A / (0.5 * g->h[d][ijk[d]]);
                        }
                    }
                    s->a[f][c] = a_f;
                }
                if (mom) {
                    double apsum = 0.0;
                    for (int m = 0; m < nv; m++) {
                        int comp = comps[m];
                        double a = ap[m] + anb;
                        double b = bb[m] - V / rho * s->gradp[comp][c];
                        if (s->disk_f[comp])
                            b += s->disk_f[comp][c] / rho;
                        double apr = a / alpha;
                        b += (apr - a) * phiv[m][c];
                        apv[m][c] = apr;
                        bv[m][c] = b;
                        apsum += apr;
                    }
                    s->apsum[c] = apsum;
                    s->anbsum[c] = nv * anb;
                    continue;
                }
                double a = ap[0] + anb, b = bb[0];
                double kc = fmaxd(kk[c], 1e-30), ec = fmaxd(ee[c], 1e-30);
                double P = pk[c];
                if (nwall)
                    P = pkw / nwall;
                /* production limiter P_k <= 10 eps (Menter 1994): keeps k
                 * from running away while eps is still small (jets,
                 * stagnation points) */
                if (P > 10.0 * ec)
                    P = 10.0 * ec;
                if (var == CFD_VAR_K) {
                    b += P * V;
                    a += ec / kc * V;
                } else {
                    if (nwall) {
                        /* eps fixed in a wall cell by the log law */
                        for (int f = 0; f < 6; f++)
                            s->a[f][c] = 0.0;
                        s->ap[c] = 1.0;
                        s->b[c] = pow(CFD_CMU, 0.75) * pow(fmaxd(kk[c], 0.0), 1.5) / (CFD_KAPPA * ymin);
                        continue;
                    }
                    double S = sqrt(fmaxd(pk[c], 0.0) / fmaxd(nut[c], 1e-30));
                    double eta = S * kc / ec;
                    double c2s = cfd_rng_c2star(eta);
                    b += CFD_C1 * ec / kc * P * V;
                    if (c2s > 0.0)
                        a += c2s * ec / kc * V;
                    else
                        b += -c2s * ec * ec / kc * V;
                }
                double apr = a / alpha;
                b += (apr - a) * phiv[0][c];
                s->ap[c] = apr;
                s->b[c] = b;
            }
}

/* The off-diagonal sum of cell c at (i, j, k) (sum a_nb phi_nb of the
 * 7-point operator, shared by the residual and the Gauss-Seidel sweep)
 * with its coefficients a[6] loaded once, in the order -x, +x, -y, +y,
 * -z, +z; jm .. kp: whether the four y, z neighbours exist. */
static inline double nb_sum(const double a[6], const double *phi, size_t c, int i, int nx, int jm, int jp, int km,
                            int kp, const size_t st[3])
{
    double r = 0.0;
    if (i > 0)
        r += a[0] * phi[c - 1];
    if (i + 1 < nx)
        r += a[1] * phi[c + 1];
    if (jm)
        r += a[2] * phi[c - st[1]];
    if (jp)
        r += a[3] * phi[c + st[1]];
    if (km)
        r += a[4] * phi[c - st[2]];
    if (kp)
        r += a[5] * phi[c + st[2]];
    return r;
}

/* Scaled residual (Fluent's; ANSYS Fluent User's Guide, residuals):
 * sum |a_P phi_P - sum a_nb phi_nb - b| / sum |a_P phi_P| over fluid cells,
 * with a_P the unrelaxed diagonal (alpha: the relaxation the matrix was
 * assembled with); the relaxation terms cancel in the numerator. nv
 * variables sharing the a_nb (u, v, w) in one pass: out[m] for phi[m],
 * each summed as alone. */
static void residual_n(const cfd_solver *s, int nv, double *const *phi, double *const *ap, double *const *b,
                       double alpha, double *out)
{
    const cfd_grid *g = s->g;
    size_t st[3];
    strides(g, st);
    double s0 = 0.0, s1 = 0.0, s2 = 0.0, q0 = 0.0, q1 = 0.0, q2 = 0.0;
    const int nx = g->n[0];
    #pragma omp parallel for reduction(+ : s0, s1, s2, q0, q1, q2) schedule(static, 1)
    for (int k = 0; k < g->n[2]; k++)
        for (int j = 0; j < g->n[1]; j++) {
            const int jm = j > 0, jp = j + 1 < g->n[1], km = k > 0, kp = k + 1 < g->n[2];
            for (int i = 0; i < nx; i++) {
                size_t c = CFD_IDX(g, i, j, k);
                if (g->solid[c])
                    continue;
                const double a[6] = {s->a[0][c], s->a[1][c], s->a[2][c], s->a[3][c], s->a[4][c], s->a[5][c]};
                for (int m = 0; m < nv; m++) {
                    double r = b[m][c] - ap[m][c] * phi[m][c] + nb_sum(a, phi[m], c, i, nx, jm, jp, km, kp, st);
                    double sc = fabs(alpha * ap[m][c] * phi[m][c]);
                    if (m == 0)
                        s0 += fabs(r), q0 += sc;
                    else if (m == 1)
                        s1 += fabs(r), q1 += sc;
                    else
                        s2 += fabs(r), q2 += sc;
                }
            }
        }
    const double sum[3] = {s0, s1, s2}, scale[3] = {q0, q1, q2};
    for (int m = 0; m < nv; m++)
        out[m] = scale[m] > 0.0 ? sum[m] / scale[m] : sum[m] > 0.0 ? 1.0 : 0.0;
}

static double residual(const cfd_solver *s, double *phi, double *ap, double *b, double alpha)
{
    double out;
    residual_n(s, 1, &phi, &ap, &b, alpha, &out);
    return out;
}

/* sweeps red-black Gauss-Seidel sweeps of nv variables sharing the a_nb,
 * every half-sweep over all of them in one pass (each variable's sweeps
 * are independent of the others': the same values as one by one). */
static void gs_sweeps_n(cfd_solver *s, int nv, double *const *phi, double *const *ap, double *const *b, int sweeps,
                        double floor)
{
    const cfd_grid *g = s->g;
    size_t st[3];
    strides(g, st);
    const int nx = g->n[0];
    for (int it = 0; it < 2 * sweeps; it++) {
        int colour = it & 1;
        #pragma omp parallel for schedule(dynamic, 1)
        for (int k = 0; k < g->n[2]; k++)
            for (int j = 0; j < g->n[1]; j++) {
                const int jm = j > 0, jp = j + 1 < g->n[1], km = k > 0, kp = k + 1 < g->n[2];
                for (int i = (j + k + colour) & 1; i < nx; i += 2) {
                    size_t c = CFD_IDX(g, i, j, k);
                    if (g->solid[c])
                        continue;
                    const double a[6] = {s->a[0][c], s->a[1][c], s->a[2][c], s->a[3][c], s->a[4][c], s->a[5][c]};
                    for (int m = 0; m < nv; m++) {
                        double r = b[m][c] + nb_sum(a, phi[m], c, i, nx, jm, jp, km, kp, st);
                        double v = r / ap[m][c];
                        phi[m][c] = v > floor ? v : floor;
                    }
                }
            }
    }
}

static void gs_sweeps(cfd_solver *s, double *phi, double *ap, double *b, int sweeps, double floor)
{
    gs_sweeps_n(s, 1, &phi, &ap, &b, sweeps, floor);
}

/* Production P_k = nu_t S^2 into pk (the pressure-correction array, free
 * after the pressure step). */
static void turbulence_prepare(cfd_solver *s, double *pk)
{
    const cfd_grid *g = s->g;
    #pragma omp parallel for schedule(dynamic, 1)
    for (int k = 0; k < g->n[2]; k++)
        for (int j = 0; j < g->n[1]; j++)
            for (int i = 0; i < g->n[0]; i++) {
                int ijk[3] = {i, j, k};
                size_t c = CFD_IDX(g, i, j, k);
                if (g->solid[c]) {
                    pk[c] = 0.0;
                    continue;
                }
                double gr[3][3];
                for (int a = 0; a < 3; a++)
                    for (int d = 0; d < 3; d++)
                        gr[a][d] = g->n[d] > 1 ? grad_dir(s, s->var[CFD_VAR_U + a], CFD_VAR_U + a, ijk, d, c) : 0.0;
                double s2 = 0.0;
                for (int a = 0; a < 3; a++)
                    for (int d = 0; d < 3; d++) {
                        double sij = 0.5 * (gr[a][d] + gr[d][a]);
                        s2 += 2.0 * sij * sij;
                    }
                pk[c] = s->var[CFD_VAR_NUT][c] * s2;
            }
}

static void update_nut(cfd_solver *s)
{
    const cfd_grid *g = s->g;
    const double numax = 1e5 * s->cfg.nu_m2ps;
    #pragma omp parallel for schedule(static)
    for (size_t c = 0; c < g->ncell; c++) {
        if (g->solid[c]) {
            s->var[CFD_VAR_NUT][c] = 0.0;
            continue;
        }
        double kc = s->var[CFD_VAR_K][c], ec = s->var[CFD_VAR_EPS][c];
        double nt = CFD_CMU * kc * kc / fmaxd(ec, 1e-30);
        s->var[CFD_VAR_NUT][c] = nt < numax ? nt : numax;
    }
}

/* Rhie-Chow face velocities after the momentum solve. */
static void rhie_chow(cfd_solver *s)
{
    const cfd_grid *g = s->g;
    const double rho = s->cfg.rho_kgpm3;
    const double *p = s->var[CFD_VAR_P];
    /* pass 0: interior faces, pass 1: boundary faces (an interior face's
     * pressure gradients read the outlet faces' backflow pressure) */
    for (int pass = 0; pass < 2; pass++)
    for (int d = 0; d < 3; d++) {
        const double *u = s->var[CFD_VAR_U + d];
        #pragma omp parallel for schedule(dynamic, 1)
        for (int k = 0; k < g->n[2] + (d == 2); k++)
            for (int j = 0; j < g->n[1] + (d == 1); j++)
                for (int i = 0; i < g->n[0] + (d == 0); i++) {
                    int jf[3] = {i, j, k};
                    size_t fi = fidx(g, d, i, j, k);
                    int q = jf[d];
                    int jm[3] = {i, j, k}, jp[3] = {i, j, k};
                    jm[d] = q - 1;
                    int inm = q - 1 >= 0, inp = q < g->n[d];
                    size_t cm = inm ? CFD_IDX(g, jm[0], jm[1], jm[2]) : 0;
                    size_t cp = inp ? CFD_IDX(g, jp[0], jp[1], jp[2]) : 0;
                    if ((inm && inp) != (pass == 0))
                        continue;
                    if (inm && inp) {
                        if (g->solid[cm] || g->solid[cp]) {
                            s->uf[d][fi] = 0.0;
                            continue;
                        }
                        double dist = g->xc[d][q] - g->xc[d][q - 1];
                        double w = (g->xn[d][q] - g->xc[d][q - 1]) / dist;
                        double gm = s->gradp[d][cm];
                        double gp = s->gradp[d][cp];
                        double df = (1.0 - w) * s->drc[cm] + w * s->drc[cp];
                        s->uf[d][fi] = (1.0 - w) * u[cm] + w * u[cp] +
                                       df / rho * (((1.0 - w) * gm + w * gp) - (p[cp] - p[cm]) / dist);
                    } else {
                        int f = 2 * d + (inp ? 0 : 1);
                        size_t c = inp ? cp : cm;
                        int *jc = inp ? jp : jm;
                        if (g->solid[c] || s->cfg.bc[f].type == CFD_BC_WALL ||
                            s->cfg.bc[f].type == CFD_BC_SYMMETRY) {
                            s->uf[d][fi] = 0.0;
                        } else if (s->cfg.bc[f].type == CFD_BC_OUTLET) {
                            double gc = grad_dir(s, p, CFD_VAR_P, jc, d, c);
                            double half = 0.5 * g->h[d][jc[d]];
                            double pb = outlet_p(s, jc, f);
                            double gf = inp ? (p[c] - pb) / half : (pb - p[c]) / half;
                            s->uf[d][fi] = u[c] + s->drc[c] / rho * (gc - gf);
                        } /* inlet faces keep their prescribed value */
                    }
                }
    }
}

/* The pressure-correction equation's coefficients (into the multigrid
 * solver's fine level) and right-hand side (s->b: minus each cell's mass
 * imbalance, with the face velocities as they are); returns the sum of
 * |mass imbalance|, the raw continuity residual. */
static double pp_assemble(cfd_solver *s)
{
    const cfd_grid *g = s->g;
    const double rho = s->cfg.rho_kgpm3;
    double *cx = cfd_mg_cx(s->mg), *cy = cfd_mg_cy(s->mg), *cz = cfd_mg_cz(s->mg),
           *dg = cfd_mg_diag(s->mg);
    double *rhs = s->b;
    double cont = 0.0;
    #pragma omp parallel for reduction(+ : cont) schedule(static, 1)
    for (int k = 0; k < g->n[2]; k++)
        for (int j = 0; j < g->n[1]; j++)
            for (int i = 0; i < g->n[0]; i++) {
                int ijk[3] = {i, j, k};
                size_t c = CFD_IDX(g, i, j, k);
                double *cc[3] = {cx, cy, cz};
                if (g->solid[c]) {
                    cx[c] = cy[c] = cz[c] = dg[c] = 0.0;
                    rhs[c] = 0.0;
                    continue;
                }
                double diag = 0.0, imb = 0.0;
                for (int f = 0; f < 6; f++) {
                    int d = f >> 1, plus = f & 1;
                    double A = face_area(g, d, ijk);
                    size_t fi = plus ? (d == 0 ? fidx(g, 0, i + 1, j, k) : d == 1 ? fidx(g, 1, i, j + 1, k) : fidx(g, 2, i, j, k + 1))
                                     : fidx(g, d, i, j, k);
                    imb += (plus ? 1.0 : -1.0) * s->uf[d][fi] * A;
                    size_t cn = 0;
                    int kind = nb_kind(s, ijk, f, c, &cn);
                    double coef = 0.0;
                    if (kind == NB_FLUID) {
                        int q = ijk[d] + (plus ? 1 : -1);
                        double dist = fabs(g->xc[d][q] - g->xc[d][ijk[d]]);
                        double w = fabs(g->xn[d][ijk[d] + plus] - g->xc[d][ijk[d]]) / dist;
                        double df = (1.0 - w) * s->dc[c] + w * s->dc[cn];
                        coef = df * A / (rho * dist);
                        if (plus)
                            cc[d][c] = coef;
                    } else if (kind == NB_OUTLET) {
                        coef = s->dc[c] * A / (rho * 0.5 * g->h[d][ijk[d]]);
                    }
                    if (plus && kind != NB_FLUID)
                        cc[d][c] = 0.0;
                    diag += coef;
                }
                dg[c] = diag;
                rhs[c] = -imb;
                cont += fabs(imb);
            }
    return cont;
}

/* Solve for the pressure correction s->pp from the system pp_assemble
 * left. Without an outlet the system is singular (pressure up to a
 * constant): the right-hand side loses its mean first. */
static void pp_solve(cfd_solver *s)
{
    const cfd_grid *g = s->g;
    double *rhs = s->b;
    cfd_mg_setup(s->mg, s->singular);
    if (s->singular) {
        double sum = 0.0, cnt = 0.0;
        #pragma omp parallel for reduction(+ : sum, cnt) schedule(static)
        for (size_t c = 0; c < g->ncell; c++)
            if (!g->solid[c])
                sum += rhs[c], cnt += 1.0;
        double mean = cnt > 0.0 ? sum / cnt : 0.0;
        #pragma omp parallel for schedule(static)
        for (size_t c = 0; c < g->ncell; c++)
            if (!g->solid[c])
                rhs[c] -= mean;
    }
    memset(s->pp, 0, g->ncell * sizeof(double));
    double rel;
    /* an inexact inner solve is enough for SIMPLEC: the outer iterations
     * converge the pressure */
    cfd_mg_solve(s->mg, s->pp, rhs, 2e-2, 30, &rel);
}

/* SIMPLEC's correction of the face velocities by the pressure-correction
 * gradient across each face (at an outlet, against pp = 0 on the face). */
static void pp_correct_faces(cfd_solver *s)
{
    const cfd_grid *g = s->g;
    const double rho = s->cfg.rho_kgpm3;
    const double *pp = s->pp;
    for (int d = 0; d < 3; d++) {
        #pragma omp parallel for schedule(dynamic, 1)
        for (int k = 0; k < g->n[2] + (d == 2); k++)
            for (int j = 0; j < g->n[1] + (d == 1); j++)
                for (int i = 0; i < g->n[0] + (d == 0); i++) {
                    int jf[3] = {i, j, k};
                    int q = jf[d];
                    size_t fi = fidx(g, d, i, j, k);
                    int jm[3] = {i, j, k};
                    jm[d] = q - 1;
                    int inm = q - 1 >= 0, inp = q < g->n[d];
                    size_t cm = inm ? CFD_IDX(g, jm[0], jm[1], jm[2]) : 0;
                    size_t cp = inp ? CFD_IDX(g, jf[0], jf[1], jf[2]) : 0;
                    if (inm && inp) {
                        if (g->solid[cm] || g->solid[cp])
                            continue;
                        double dist = g->xc[d][q] - g->xc[d][q - 1];
                        double w = (g->xn[d][q] - g->xc[d][q - 1]) / dist;
                        double df = (1.0 - w) * s->dc[cm] + w * s->dc[cp];
                        s->uf[d][fi] -= df / rho * (pp[cp] - pp[cm]) / dist;
                    } else {
                        int f = 2 * d + (inp ? 0 : 1);
                        size_t c = inp ? cp : cm;
                        int qc = inp ? q : q - 1;
                        if (g->solid[c] || s->cfg.bc[f].type != CFD_BC_OUTLET)
                            continue;
                        double half = 0.5 * g->h[d][qc];
                        double gf = inp ? (pp[c] - 0.0) / half : (0.0 - pp[c]) / half;
                        s->uf[d][fi] -= s->dc[c] / rho * gf;
                    }
                }
    }
}

/* ... and of the cell velocities and, under-relaxed by relax_p, the
 * pressure. */
static void pp_correct_cells(cfd_solver *s)
{
    const cfd_grid *g = s->g;
    const double rho = s->cfg.rho_kgpm3;
    const double *pp = s->pp;
    const double ap_ = s->relax[1];
    #pragma omp parallel for schedule(dynamic, 1)
    for (int k = 0; k < g->n[2]; k++)
        for (int j = 0; j < g->n[1]; j++)
            for (int i = 0; i < g->n[0]; i++) {
                int ijk[3] = {i, j, k};
                size_t c = CFD_IDX(g, i, j, k);
                if (g->solid[c])
                    continue;
                for (int d = 0; d < 3; d++)
                    s->var[CFD_VAR_U + d][c] -= s->dc[c] / rho * grad_dir(s, pp, CFD_VAR_P, ijk, d, c);
            }
    #pragma omp parallel for schedule(static)
    for (size_t c = 0; c < g->ncell; c++)
        if (!g->solid[c])
            s->var[CFD_VAR_P][c] += ap_ * pp[c];
}

/* SIMPLEC pressure correction: assemble, solve, correct faces and cells.
 * Returns the raw continuity residual (before the correction). */
static double pressure_correction(cfd_solver *s)
{
    double cont = pp_assemble(s);
    pp_solve(s);
    pp_correct_faces(s);
    pp_correct_cells(s);
    return cont;
}

/* -------------------------------------------------------------- sampling */
int cfd_solver_sample(const cfd_solver *s, const double pos[3], double out[CFD_NVARS])
{
    cfd_sample_arrays(s->g, (double *const *)s->var, CFD_NVARS, pos, out);
    int outside = 0;
    for (int d = 0; d < 3; d++)
        outside |= pos[d] < s->g->xn[d][0] || pos[d] > s->g->xn[d][s->g->n[d]];
    return outside;
}

/* ------------------------------------------------------------------ run */
static int push_hist(cfd_solver *s, const double r[HIST_COLS])
{
    if (s->nhist == s->caphist) {
        int cap = s->caphist ? 2 * s->caphist : 256;
        double *h = realloc(s->hist, (size_t)cap * HIST_COLS * sizeof(double));
        if (!h)
            return -1;
        s->hist = h;
        s->caphist = cap;
    }
    memcpy(s->hist + (size_t)s->nhist * HIST_COLS, r, HIST_COLS * sizeof(double));
    s->nhist++;
    return 0;
}

static void snapshot(cfd_solver *s, int save)
{
    for (int v = 0; v < NSNAP; v++) {
        float *sv = s->snap[v];
        double *x = s->var[v];
        #pragma omp parallel for schedule(static)
        for (size_t c = 0; c < s->g->ncell; c++) {
            if (save)
                sv[c] = (float)x[c];
            else
                x[c] = sv[c];
        }
    }
    if (!save) {
        update_nut(s);
        if (!s->cfg.turbulence)
            memset(s->var[CFD_VAR_NUT], 0, s->g->ncell * sizeof(double));
        faces_from_cells(s);
    }
}

/* One SIMPLEC iteration; r gets the raw residuals. */
static void iterate(cfd_solver *s, double r[HIST_COLS])
{
    const double au = s->relax[0], at = s->relax[2];
    pressure_gradients(s);
    assemble(s, CFD_VAR_U, au, NULL);
    /* u, v, w together (a 2-D case: no velocity across the single layer) */
    double *phiv[3], *apv[3], *bv[3], rv[3];
    int comp[3], nv = 0;
    for (int d = 0; d < 3; d++) {
        r[1 + d] = 0.0;
        if (s->g->n[d] > 1) {
            comp[nv] = d;
            phiv[nv] = s->var[CFD_VAR_U + d], apv[nv] = s->apm[d], bv[nv] = s->bm[d];
            nv++;
        }
    }
    residual_n(s, nv, phiv, apv, bv, au, rv);
    for (int m = 0; m < nv; m++)
        r[1 + comp[m]] = rv[m];
    gs_sweeps_n(s, nv, phiv, apv, bv, 2, -1e300);
    const cfd_grid *g = s->g;
    int ncomp = (g->n[0] > 1) + (g->n[1] > 1) + (g->n[2] > 1);
    #pragma omp parallel for schedule(static)
    for (size_t c = 0; c < g->ncell; c++) {
        if (g->solid[c]) {
            s->drc[c] = s->dc[c] = 0.0;
            continue;
        }
        double V = g->h[0][c % g->n[0]] * g->h[1][(c / g->n[0]) % g->n[1]] * g->h[2][c / ((size_t)g->n[0] * g->n[1])];
        double apm = s->apsum[c] / ncomp, anb = s->anbsum[c] / ncomp;
        s->drc[c] = V / apm;
        s->dc[c] = V / fmaxd(apm - anb, 1e-3 * apm);
    }
    rhie_chow(s);
    r[0] = pressure_correction(s);
    if (s->cfg.turbulence) {
        double *pk = s->pp; /* scratch */
        turbulence_prepare(s, pk);
        assemble(s, CFD_VAR_K, at, pk);
        r[4] = residual(s, s->var[CFD_VAR_K], s->ap, s->b, at);
        gs_sweeps(s, s->var[CFD_VAR_K], s->ap, s->b, 2, 1e-14 * s->cfg.u_ref_mps * s->cfg.u_ref_mps);
        assemble(s, CFD_VAR_EPS, at, pk);
        gs_sweeps(s, s->var[CFD_VAR_EPS], s->ap, s->b, 2, 1e-20);
        update_nut(s);
    } else {
        r[4] = 0.0;
    }
}

static double max_speed(const cfd_solver *s)
{
    double m = 0.0;
    const double *u = s->var[0], *v = s->var[1], *w = s->var[2];
    #pragma omp parallel for reduction(max : m) schedule(static)
    for (size_t c = 0; c < s->g->ncell; c++) {
        double q = u[c] * u[c] + v[c] * v[c] + w[c] * w[c];
        if (!(q <= 1e300))
            q = 1e300;
        if (q > m)
            m = q;
    }
    return sqrt(m);
}

/* Divergence: NaN, the mass imbalance or the velocities blowing up. Not
 * the scaled momentum residuals: a component that is zero in the inflow (u
 * in a wind exactly from the beam) has a scale sum |a_P u_P| near zero, and
 * with a rotor forcing it from the first iteration its scaled residual
 * exceeded 1e4 on a healthy solution (CG-47, WOD 90 deg with the loaded
 * disk: refused in two iterations, 89 deg ran). r: the raw residuals, rn:
 * scaled. */
static int diverging(const cfd_solver *s, int it, const double r[HIST_COLS], const double rn[HIST_COLS])
{
    int bad = 0;
    for (int q = 0; q < HIST_COLS; q++)
        bad |= !isfinite(r[q]);
    return bad || rn[0] > 1e4 || (it % 10 == 0 && max_speed(s) > 100.0 * s->cfg.u_ref_mps);
}

/* Before retry number attempt: 0.6 times the under-relaxation, the initial
 * state back, the residual history cleared. */
static void retry_from_start(cfd_solver *s, int attempt)
{
    for (int q = 0; q < 3; q++)
        s->relax[q] *= 0.6;
    core_log_msg(s->cfg.log, CORE_LOG_WARN,
                 "cfd: diverged; retry %d from the initial state with under-relaxation "
                 "u %.2f p %.2f turb %.2f",
                 attempt, s->relax[0], s->relax[1], s->relax[2]);
    snapshot(s, 0);
    s->nhist = 0;
}

/* One attempt from the present state: SIMPLEC iterations (Anderson-mixed
 * once it is on) until the convergence bookkeeping says done (converged, or
 * a steady mean), the progress callback stops the run, or max_iter.
 * *it: the iteration it ended at (max_iter + 1 when it ran out); *stop: 1
 * when the callback stopped it; *accel_on: 1 when Anderson acceleration
 * was on; *total_iter counts the iterations. Returns 0, 1 when it diverged,
 * < 0 out of memory. */
static int run_attempt(cfd_solver *s, double t0, int *total_iter, int *it_out, int *stop, int *accel_on,
                       core_err *err)
{
    const cfd_config *cfg = &s->cfg;
    cfd_converge *cv = &s->conv;
    double *aseg[7] = {s->var[CFD_VAR_U], s->var[CFD_VAR_V], s->var[CFD_VAR_W], s->var[CFD_VAR_P],
                       s->uf[0], s->uf[1], s->uf[2]};
    if (s->aa)
        cfd_aa_reset(s->aa);
    *stop = *accel_on = 0;
    int it, diverged = 0;
    for (it = 1; it <= cfg->max_iter; it++) {
        double r[HIST_COLS], rn[HIST_COLS];
        if (s->aa && !*accel_on && it >= cfg->accel_start && (!cfg->accel_when_stalled || cfd_converge_stalled(cv))) {
            *accel_on = 1;
            core_log_msg(cfg->log, CORE_LOG_INFO, "cfd: Anderson acceleration from iteration %d", it);
        }
        if (*accel_on)
            cfd_aa_save(s->aa, aseg);
        iterate(s, r);
        if (*accel_on) /* k and eps (so nu_t) are not mixed */
            cfd_aa_mix(s->aa, aseg);
        (*total_iter)++;
        double worst = cfd_converge_residuals(cv, it, r, rn);
        if (push_hist(s, rn))
            return core_err_set(err, -2, "cfd: out of memory for the residual history");
        if (diverging(s, it, r, rn)) {
            diverged = 1;
            break;
        }
        int up = cfd_converge_update(cv, it);
        if (up < 0)
            return core_err_set(err, -2, "cfd: out of memory for the monitors' history");
        if (up)
            break; /* a steady mean */
        if (cfg->progress && cfg->progress(cfg->progress_user, it, cfg->max_iter, worst, now_s() - t0)) {
            *stop = 1;
            break;
        }
        if (cfd_converge_done(cv, it))
            break;
    }
    *it_out = it;
    return diverged;
}

int cfd_solver_run(cfd_solver *s, cfd_result *res, core_err *err)
{
    const cfd_config *cfg = &s->cfg;
    cfd_converge *cv = &s->conv;
    double t0 = now_s();
    memset(res, 0, sizeof *res);
    s->relax[0] = cfg->relax_u;
    s->relax[1] = cfg->relax_p;
    s->relax[2] = cfg->relax_turb;
    snapshot(s, 1);
    size_t nfluid = cfd_grid_fluid_cells(s->g);
    int total_iter = 0;
    cfd_converge_init(cv, s);
    for (int attempt = 0; attempt <= cfg->max_retries; attempt++) {
        if (attempt > 0) {
            retry_from_start(s, attempt);
            res->retries = attempt;
        }
        cfd_converge_attempt(cv);
        int it = 0, stop = 0, accel_on = 0;
        int rc = run_attempt(s, t0, &total_iter, &it, &stop, &accel_on, err);
        if (rc < 0) {
            cfd_converge_result(cv, res);
            return rc;
        }
        const int diverged = rc == 1;
        res->iterations = it > cfg->max_iter ? cfg->max_iter : it;
        res->stopped = stop;
        if (cfd_converge_finish(cv, it, diverged, stop, s->var))
            faces_from_cells(s); /* the state is the window's mean */
        cfd_converge_result(cv, res);
        if (!diverged) {
            res->wall_s = now_s() - t0;
            if (accel_on) {
                int nm, nr;
                cfd_aa_counts(s->aa, &nm, &nr);
                core_log_msg(cfg->log, CORE_LOG_INFO, "cfd: Anderson acceleration: %d mixing steps, %d restarts", nm,
                             nr);
            }
            res->cell_updates = (double)nfluid * total_iter;
            core_log_msg(cfg->log, CORE_LOG_INFO,
                         "cfd: %s after %d iterations, %.1f s, residuals %.2e %.2e %.2e %.2e %.2e, "
                         "monitor change %.2f %% of u_ref",
                         res->converged ? "converged" : stop ? "stopped" : res->steady_mean ? "steady mean" : "iteration limit",
                         res->iterations, res->wall_s, res->residual[0], res->residual[1],
                         res->residual[2], res->residual[3], res->residual[4], 100.0 * res->monitor_change);
            return res->converged ? 0 : 1;
        }
    }
    res->wall_s = now_s() - t0;
    snapshot(s, 0); /* never leave a NaN state behind */
    return core_err_set(err, -3,
                        "cfd: the solution diverged (NaN or growing residuals) after %d retries "
                        "with under-relaxation down to u %.2f p %.2f; try a finer or smoother grid, "
                        "or a warm start",
                        cfg->max_retries, s->relax[0], s->relax[1]);
}
