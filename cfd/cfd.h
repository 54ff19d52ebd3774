/*
 * cfd.h -- disim's embedded airwake solver: steady incompressible RANS with
 * the RNG k-epsilon model and standard wall functions on a stretched
 * Cartesian grid, an actuator-disk rotor, HDF5 fields with a fast
 * trilinear loader, and the validation cases.
 *
 * Method (details and references at the top of each source file):
 *  - grid.c:     structured Cartesian grid, per-axis geometric stretching
 *                around a focus interval, blocked (solid) cells from the
 *                ship geometry (core_ship) or from boxes.
 *  - solver.c:   collocated finite volume, SIMPLEC with Rhie-Chow face
 *                velocities, bounded second-order convection (van Leer TVD
 *                by deferred correction), red-black Gauss-Seidel for the
 *                transport equations, OpenMP over the cells.
 *  - mg.c:       pressure-correction equation by conjugate gradients
 *                preconditioned with a geometric (additive-correction)
 *                multigrid V-cycle.
 *  - turb.c:     RNG k-epsilon (Yakhot et al. 1992) and standard wall
 *                functions (Launder & Spalding 1974).
 *  - disk.c:     actuator disk as a smoothed momentum source (seed paper
 *                section 2.2, eq. 5), uniform or loaded with swirl.
 *  - io.c:       HDF5 + XDMF output, loader with trilinear interpolation.
 *  - airwake.c:  a ship airwake case from a ship, a WOD and a rotor.
 *  - validate.c: the validation cases of `disim validate`.
 *
 * Frames and units follow docs/conventions.md: SI, positions and
 * velocities of airwakes in the ship frame S (x bow, y starboard, z down).
 * Pressures are stored in Pa (gauge, relative to the outlet pressure).
 * The library never prints; it reports through core_log and a progress
 * callback. Functions return 0 ok, < 0 fatal, > 0 recoverable.
 */
#ifndef DISIM_CFD_H
#define DISIM_CFD_H

#include "core.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

#define CFD_VERSION "disim-cfd 0.5.0"

/* ------------------------------------------------------------------ grid */
/* One axis: nodes from lo to hi, spacing h_fine inside [f0, f1], growing
 * geometrically by `growth` per cell outside up to h_max. */
typedef struct cfd_axis_spec {
    double lo_m, hi_m;
    double f0_m, f1_m;
    double h_fine_m, h_max_m;
    double growth; /* >= 1 (1: uniform h_fine everywhere) */
} cfd_axis_spec;

typedef struct cfd_grid cfd_grid;

/* Node coordinates of an axis from a spec: *nodes is malloc'ed (*n + 1
 * values, *n cells). Returns 0 or < 0 with err. */
int cfd_axis_build(const cfd_axis_spec *spec, double **nodes, int *n, core_err *err);

/* A grid from node coordinates (n[d] + 1 strictly increasing values per
 * axis; copied). Every cell starts as fluid. NULL with err on bad input. */
cfd_grid *cfd_grid_create(const double *xn, int nx, const double *yn, int ny, const double *zn,
                          int nz, core_err *err);
/* A grid from three axis specs. */
cfd_grid *cfd_grid_create_spec(const cfd_axis_spec spec[3], core_err *err);
void cfd_grid_destroy(cfd_grid *g);
/* Block the cells whose centre lies in the ship; returns the count. */
size_t cfd_grid_block_ship(cfd_grid *g, const core_ship *ship);
/* Block the cells whose centre lies in a box; returns the count. */
size_t cfd_grid_block_box(cfd_grid *g, const double lo_m[3], const double hi_m[3]);
void cfd_grid_dims(const cfd_grid *g, int n[3]);
size_t cfd_grid_cells(const cfd_grid *g);
size_t cfd_grid_fluid_cells(const cfd_grid *g);
/* Node (n[d] + 1 values) and centre (n[d] values) coordinates of axis d. */
const double *cfd_grid_nodes(const cfd_grid *g, int d);
const double *cfd_grid_centres(const cfd_grid *g, int d);
/* 1 where the cell (index i + nx (j + ny k)) is solid. */
const unsigned char *cfd_grid_solid(const cfd_grid *g);

/* The RNG k-epsilon constants (Yakhot et al. 1992) and the standard wall
 * functions' (turb.c); another engine solving the same case takes these. */
#define CFD_RNG_CMU 0.0845
#define CFD_RNG_C1 1.42
#define CFD_RNG_C2 1.68
#define CFD_RNG_SIGMA_K 0.71942
#define CFD_RNG_SIGMA_E 0.71942
#define CFD_RNG_ETA0 4.38
#define CFD_RNG_BETA 0.012
#define CFD_WALL_KAPPA 0.41
#define CFD_WALL_E 9.8

/* ------------------------------------------------------ boundaries, setup */
enum { CFD_XMIN = 0, CFD_XMAX, CFD_YMIN, CFD_YMAX, CFD_ZMIN, CFD_ZMAX, CFD_NFACES };

typedef enum {
    CFD_BC_WALL = 0,     /* no-slip (moving with vel_mps), wall functions if turbulent */
    CFD_BC_INLET = 1,    /* velocity, k, epsilon from the inflow profile */
    CFD_BC_OUTLET = 2,   /* fixed pressure 0, zero gradient; also an opening (backflow) */
    CFD_BC_SYMMETRY = 3, /* slip, no flux */
} cfd_bc_type;

typedef struct cfd_bc {
    cfd_bc_type type;
    double vel_mps[3]; /* wall: wall velocity (tangential part used) */
} cfd_bc;

typedef enum {
    CFD_INFLOW_UNIFORM = 0, /* vel_mps everywhere */
    CFD_INFLOW_ABL = 1,     /* log law over the ground, Richards & Hoxey (1993) */
    CFD_INFLOW_POWER = 2,   /* 1/7 power-law boundary layer of thickness delta_m over ground */
    CFD_INFLOW_FIELD = 3,   /* sampled from fn (a zone's boundary values from an outer field) */
} cfd_inflow_type;

/* A sampled inflow: out[0..2] the velocity (m/s), out[3] k, out[4] epsilon
 * at pos (a point of the grid). Returns 0. */
typedef int (*cfd_inflow_fn)(void *user, const double pos_m[3], double out[5]);

typedef struct cfd_inflow {
    cfd_inflow_type type;
    double vel_mps[3];   /* uniform velocity, or the ABL velocity at z_ref_m above ground */
    double ground_coord_m; /* coordinate of the ground along ground_axis */
    int ground_axis;       /* 0, 1, 2: axis normal to the ground */
    int ground_sign;       /* +1: height = (ground - coord) (z down, S frame); -1: coord - ground */
    double z_ref_m;        /* ABL: reference height */
    double z0_m;           /* ABL: roughness length */
    double delta_m;        /* POWER: boundary-layer thickness */
    double intensity;      /* uniform / power: turbulence intensity (k = 1.5 (I U)^2) */
    double length_m;       /* uniform / power: turbulence length scale (eps = Cmu^0.75 k^1.5 / l) */
    /* FIELD: the sampler and its user data. The solver samples the inlet
     * and outlet faces once, at cfd_solver_create (and every cell in
     * cfd_solver_init_inflow, the initial state), so user must stay valid
     * for the solver's life. */
    cfd_inflow_fn fn;
    void *fn_user;
} cfd_inflow;

/* Progress: iteration, the iteration limit, the largest normalised residual
 * and the elapsed wall time. Return non-zero to stop the run. */
typedef int (*cfd_progress_fn)(void *user, int iter, int max_iter, double residual,
                               double elapsed_s);

#define CFD_MAX_MONITOR 16

/* TVD limiters psi(r) of the deferred correction (Sweby 1984; Versteeg and
 * Malalasekera 2007, sec. 5.10): van Leer (r + |r|) / (1 + |r|), the
 * default; minmod max(0, min(r, 1)), the most diffusive second-order TVD
 * limiter, which ship airwakes on grids finer than about 1 m use (see
 * cfd_airwake_create). */
typedef enum { CFD_LIMITER_VANLEER = 0, CFD_LIMITER_MINMOD = 1 } cfd_limiter;

typedef struct cfd_config {
    int turbulence;        /* 0 laminar, 1 RNG k-epsilon with wall functions */
    double rho_kgpm3, nu_m2ps;
    cfd_bc bc[CFD_NFACES];
    cfd_inflow inflow;
    double u_ref_mps;      /* velocity scale for residuals and monitors */
    int max_iter;
    double tol_residual;   /* normalised residuals below this (1e-4) ... */
    double tol_monitor;    /* ... and monitor velocities changing less than this fraction of u_ref (0.02) */
    int monitor_every;     /* iterations between monitor comparisons (50) */
    int avg_window;        /* > 0: a run that reaches max_iter without converging returns the
                              mean of its last avg_window iterations instead of the last one
                              (cfd_result.averaged says so); 0: the last iterate (default) */
    int avg_stop;          /* 1 (with avg_window >= 2 and monitors): also stop before max_iter once
                              the mean flow is steady. The averaging windows are avg_window long
                              and laid back to back so that the last ends at max_iter; a window
                              starts early only when the residuals, at their rate over the last 100
                              iterations, will not reach tol_residual by max_iter; the run stops
                              at its end, with its mean, when the monitor velocities' means over
                              its two halves, and its mean and the mean of the window just before
                              it, differ by less than tol_monitor times u_ref (so never at the
                              first window; cfd_result.steady_mean says so); 0: off (default) */
    int monitor_stop;      /* 1: converged on the monitors alone, the residuals not tested: from
                              iteration 4 monitor_every on, once every monitor velocity has moved
                              by less than tol_monitor times u_ref (the length of its change) over
                              each of the last two spans of monitor_every iterations, tested every
                              iteration (the OpenFOAM engine's stopping test, foam.h: the two
                              engines compared to one criterion); without monitors the run goes to
                              max_iter. 0: residuals and monitors (default) */
    int n_monitor;
    double monitor_m[CFD_MAX_MONITOR][3];
    double relax_u, relax_p, relax_turb; /* under-relaxation (0.7, 0.9, 0.6; ship airwakes u 0.85) */
    int second_order;      /* 1: TVD deferred correction (first order on the faces of wall-function cells), 0: upwind */
    cfd_limiter limiter;   /* the TVD limiter: CFD_LIMITER_VANLEER (default) or CFD_LIMITER_MINMOD */
    int max_retries;       /* retries with more under-relaxation after divergence (2) */
    int accel_depth;       /* > 0: Anderson acceleration of the SIMPLEC iteration keeping this many
                              differences (1..16; about 140 B per cell plus 56 B per cell and
                              difference);
                              0: off (default) */
    int accel_start;       /* the iteration of each run from which it mixes (>= 1) ... */
    int accel_when_stalled; /* ... 1: and only once the largest residual has fallen by less than
                               30 % over 100 iterations (a run that converges by itself is left
                               alone); 0: from accel_start on */
    const core_log *log;
    cfd_progress_fn progress;
    void *progress_user;
} cfd_config;

/* Defaults: RNG k-epsilon on, sea-level air, walls on every face, uniform
 * inflow, van Leer convection, tolerances as in the seed paper (1e-4, 2 %),
 * relaxation 0.7 / 0.9 / 0.6, two retries. */
void cfd_config_default(cfd_config *cfg);

/* ----------------------------------------------------------- actuator disk */
#define CFD_DISK_MAX_TABLE 64

typedef struct cfd_disk {
    double centre_m[3];
    double normal[3];   /* unit vector of the thrust on the rotor (air is pushed along -normal) */
    double ref[3];      /* in-plane direction of azimuth psi = 0 (e.g. over the tail) */
    double radius_m;
    double root_cut;    /* r/R inside which there is no load (0..0.5) */
    double thrust_N;    /* the force on the air is exactly -thrust_N * normal */
    int ccw_from_above; /* rotation sense seen from the side the thrust points to */
    double smooth_cells; /* Gaussian half-width across the disk, in local cells (1.5) */
    /* Loaded option: relative pressure-jump shape load[ipsi * nr + ir] at
     * r/R = (ir + 0.5) / nr and psi = 2 pi ipsi / npsi (bilinear; periodic in
     * psi), and the tangential force shape swirl[ir]; the tangential forces
     * integrate to torque_Nm about the axis, in the rotation sense. nr = 0:
     * uniform T/A (seed paper eq. 5), no swirl. */
    int nr, npsi;
    double load[CFD_DISK_MAX_TABLE * CFD_DISK_MAX_TABLE];
    double swirl[CFD_DISK_MAX_TABLE];
    double torque_Nm;
} cfd_disk;

/* A disk from a position in S and a rotor attitude (3-2-1 Euler angles of the
 * rotor shaft frame in S, shaft along -z of that frame): psi = 0 points aft. */
void cfd_disk_from_attitude(cfd_disk *d, const double centre_S_m[3], core_euler att,
                            double radius_m, double thrust_N);
/* The disk's ideal hover induced velocity sqrt(T / (2 rho A)) (momentum
 * theory) in air of density rho_kgpm3; 0 for a disk without thrust or
 * radius. */
double cfd_disk_hover_vi_mps(const cfd_disk *d, double rho_kgpm3);

/* ------------------------------------------------------------------ solver */
typedef struct cfd_solver cfd_solver;

enum { CFD_VAR_U = 0, CFD_VAR_V, CFD_VAR_W, CFD_VAR_P, CFD_VAR_K, CFD_VAR_EPS, CFD_VAR_NUT, CFD_NVARS };
extern const char *const cfd_var_names[CFD_NVARS];

/* Takes ownership of grid (destroyed with the solver, also on failure). */
cfd_solver *cfd_solver_create(cfd_grid *grid, const cfd_config *cfg, core_err *err);
void cfd_solver_destroy(cfd_solver *s);
const cfd_grid *cfd_solver_grid(const cfd_solver *s);
const cfd_config *cfd_solver_config(const cfd_solver *s);
/* Set (or clear with NULL) the actuator disk; distributes its source now.
 * Returns < 0 if the disk misses the grid. */
int cfd_solver_set_disk(cfd_solver *s, const cfd_disk *disk, core_err *err);
/* The disk's momentum source per cell in N (force on the air), component d;
 * NULL when there is no disk. */
const double *cfd_solver_disk_force(const cfd_solver *s, int d);
/* The inflow the solver applies on boundary face set face (CFD_XMIN ..
 * CFD_ZMAX) at pos_m, a point of that side of the domain (a face centre of
 * the grid: the node coordinate of the side along its axis, the cell
 * centres across): the velocity (m/s), k and epsilon an inlet face there
 * is fixed to (an outlet face takes k and epsilon of backflow from it).
 * The profile at pos_m, or with a sampled inflow (CFD_INFLOW_FIELD) the
 * values sampled at create for the face whose cell span holds pos_m.
 * 0, or -1 when face is not an inlet or outlet or pos_m is off the side. */
int cfd_solver_inflow_at(const cfd_solver *s, int face, const double pos_m[3], double vel[3], double *k,
                         double *eps);
/* Initial state: the inflow (or u_ref along +x when there is no inlet). */
void cfd_solver_init_inflow(cfd_solver *s);

typedef struct cfd_field cfd_field;
/* Warm start: interpolate every variable from a field (another WOD, or the
 * same case on a coarser grid: coarse-to-fine). */
int cfd_solver_init_from_field(cfd_solver *s, const cfd_field *f, core_err *err);
/* Coarse-to-fine start in memory: interpolate every variable from another
 * solver's state (the same case solved on a coarser grid). */
int cfd_solver_init_from_solver(cfd_solver *s, const cfd_solver *src, core_err *err);

typedef struct cfd_result {
    int iterations;
    int converged;       /* residuals and monitors met */
    int retries;
    double residual[5];  /* final residuals: continuity (divided by its largest value over the
                            first five iterations), u, v, w, k (sum |r| / sum |a_P phi_P|) */
    double wall_s;
    double cell_updates; /* cells x iterations */
    double monitor_change; /* last monitor-velocity change / u_ref between two checks */
    int averaged;        /* > 0: not converged, the state is the mean of this many last iterations */
    int steady_mean;     /* 1: stopped before max_iter with a steady mean (cfd_config.avg_stop) */
    int stopped;         /* 1: stopped by the progress callback (the state is the last iterate) */
    double mean_drift;   /* averaged runs with monitors: the largest difference between the
                            monitor velocities' means over the two halves of the averaging
                            window, / u_ref (how far the mean itself still moves; 0 otherwise) */
    double mean_change;  /* averaged runs with monitors: the largest difference between the
                            monitor velocities' means over the last averaging window and the
                            window just before it, / u_ref; -1 when none came just before, or
                            the field is not averaged */
} cfd_result;

/* Run to convergence or max_iter. 0: converged; 1: stopped at max_iter or by
 * the progress callback (field usable); < 0: diverged after the retries, or
 * out of memory (err says which; the state is not usable). */
int cfd_solver_run(cfd_solver *s, cfd_result *res, core_err *err);

/* Cell-centred array of a variable (p in Pa, nu_t in m^2/s). */
const double *cfd_solver_var(const cfd_solver *s, int var);
/* Replace a variable's cell values (ncell values; a state solved elsewhere,
 * on this grid, to be written by cfd_solver_write). Returns < 0 for a
 * variable out of range. */
int cfd_solver_set_var(cfd_solver *s, int var, const double *values);
/* Trilinear sample of u, v, w (out[0..2]), p, k, eps, nut at a point. */
int cfd_solver_sample(const cfd_solver *s, const double pos_m[3], double out[CFD_NVARS]);
/* Residual history: n iterations x 5 values (continuity, u, v, w, k). */
const double *cfd_solver_history(const cfd_solver *s, int *n);
/* 1 if any variable holds a NaN or an infinity. */
int cfd_solver_has_nan(const cfd_solver *s);
/* Bytes allocated by the solver (grid, fields, work arrays, multigrid). */
size_t cfd_solver_bytes(const cfd_solver *s);

/* ------------------------------------------------------------------ output */
typedef struct cfd_meta {
    double wod_speed_mps, wod_dir_deg;
    char ship[64];
    char rotor[32];   /* "off", "uniform", "loaded" */
    double rotor_thrust_N, rotor_radius_m, rotor_centre_S_m[3];
    char grid[32];    /* "coarse", "default", "fine", or a case name */
    cfd_result result;
    int mirrored;     /* 1: the port-starboard mirror image of the field of the
                         opposite direction (cfd_field_mirror_y); result is that field's */
    int checksum;     /* cfd_field_load: 1 when the file carries data_crc64 and the data match
                         it; 0 for a field written before files carried one (read as it is) */
    int sealed;       /* cfd_field_load: 1 when the file's seal (its size and CRC-64 in its
                         first 512 bytes, cfd_field_seal) held; 0 for a field written before
                         fields were sealed (read as it is) */
    /* the engine that solved the field and its version: "" writes "embedded"
     * and CFD_VERSION (a field without them reads back so); "openfoam" and
     * e.g. "v1912" for the OpenFOAM engine (foam.h), whose result.residual[]
     * are OpenFOAM's initial residuals of p, Ux, Uy, Uz and k */
    char engine[32];
    char engine_version[64];
    /* how the engine built the rotor: "" (a field without it reads back so)
     * for its actuator disk of the rotor's mode, "rotorDisk" for the
     * OpenFOAM engine's blade-element rotor, whose trimmed thrust,
     * integrated from its force field, is rotor_force_N, and the torque it
     * put into the air about the thrust direction, in the rotor's sense,
     * rotor_torque_Nm (0 otherwise) */
    char rotor_model[32];
    double rotor_force_N, rotor_torque_Nm;
} cfd_meta;

/* Write the field to path (HDF5, sealed: cfd_field_seal) and path with
 * .xmf (XDMF side file), each through a temporary file and a rename.
 * Refuses (< 0) a state with a NaN. */
int cfd_solver_write(const cfd_solver *s, const cfd_meta *meta, const char *path, core_err *err);

/* A loaded field: grid, u v w p k eps nut and metadata. */
cfd_field *cfd_field_load(const char *path, core_err *err);
void cfd_field_destroy(cfd_field *f);
/* Trilinear interpolation of all variables (cell centres; clamped at the
 * domain edges). Returns 1 if pos is outside the domain (clamped values). */
int cfd_field_sample(const cfd_field *f, const double pos_S_m[3], double out[CFD_NVARS]);
/* The same for the nvar variables vars[0..nvar-1] (CFD_VAR_*) only, into
 * out[0..nvar-1]: the bits cfd_field_sample gives them. Returns as
 * cfd_field_sample, -1 for a variable out of range. */
int cfd_field_sample_vars(const cfd_field *f, const double pos_S_m[3], const int *vars, int nvar, double *out);
/* The flight model's air callback: user is a cfd_field*. 0 inside, 1 outside
 * the domain (clamped velocity). */
int cfd_field_air(void *user, const double pos_S_m[3], double t_s, double vel_S_mps[3]);
/* The one-way air: a ship-only field scaled to another WOD speed (the
 * field scales with the speed). user is a cfd_field_scaled*; returns as
 * cfd_field_air. */
typedef struct cfd_field_scaled {
    const cfd_field *field;
    double scale;            /* the wanted WOD speed over the field's */
} cfd_field_scaled;
int cfd_field_air_scaled(void *user, const double pos_S_m[3], double t_s, double vel_S_mps[3]);
const cfd_meta *cfd_field_meta(const cfd_field *f);
/* Write a loaded (or mirrored) field, as cfd_solver_write does (temporary
 * file and rename; no residual history). */
int cfd_field_write(const cfd_field *f, const char *path, core_err *err);
/* Seal a field file again: the header in its first 512 bytes (HDF5's user
 * block, which the writers reserve) made to hold the file's size and the
 * CRC-64 of the rest as they are now. The writers seal every field; a
 * field changed in place since (through HDF5: h5py, a test) is refused by
 * cfd_field_load until it is sealed again. < 0 with err for a file without
 * that user block. */
int cfd_field_seal(const char *path, core_err *err);
/* The port-starboard mirror image (y -> -y, v -> -v) of a ship-only field:
 * for a ship symmetric about its centre line (core_ship_mirror_symmetric)
 * the steady RANS solution for a wind from green D is the mirror of the one
 * from red D; the image's grid is the mirrored grid, its direction -D, its
 * meta.mirrored 1. A field with a rotor is refused (its mirror image turns
 * the other way). NULL with err. */
cfd_field *cfd_field_mirror_y(const cfd_field *src, core_err *err);
void cfd_field_dims(const cfd_field *f, int n[3]);

/* ----------------------------------------------------------------- airwake */
/* the ship grids' growth ratio of the cells outside the focus box, every level */
#define CFD_GRID_GROWTH 1.12

typedef struct cfd_airwake_spec {
    const core_ship *ship;
    double wod_speed_mps, wod_dir_rad;
    core_grid_level level;
    int abl;                 /* 1: ABL inflow (z0 = 2e-4 m, sea), 0: uniform */
    core_rotor_mode rotor;   /* with the rotor on, disk is filled in */
    cfd_disk disk;
    double monitor_z_m;      /* monitor line height in S (CG height, z < 0 above deck) */
    int max_iter;            /* 0: default */
    double h_fine_m;         /* > 0: overrides the level's fine spacing (tests, grid studies) */
    double growth;           /* > 1: overrides the cells' growth ratio outside the focus box
                                (CFD_GRID_GROWTH; grid studies) */
    double focus_fwd_m;      /* > 0: the focus box reaches this far forward of the deck's
                                forward end (the level's: 0.3 deck, at most 8 m; grid studies) */
    double h_max_m;          /* > 0: overrides the largest cell (the level's, at least
                                4 x the fine spacing; grid studies) */
    int avg_window;          /* > 0: the averaging window of a field that does not converge
                                (iterations, at most max_iter; the default min(max_iter / 4,
                                200); grid studies of shedding fields) */
    int limiter_fixed;       /* 1: limiter on every level (grid studies with one scheme on
                                every grid); 0: the level's (van Leer on the coarse grid,
                                minmod below 1 m spacing) */
    cfd_limiter limiter;
    int monitor_stop;        /* 1: stop on the monitors alone (cfd_config.monitor_stop: the
                                OpenFOAM engine's test), with no averaging window and no
                                steady-mean stop (the last iterate, as OpenFOAM's); 0: the
                                default criterion */
    int open_ship;           /* 1: the same grid and boundaries with no cell blocked
                                (the isolated rotor of the coupling's interaction velocity) */
    /* 1: the deck zone only, for a coupled point (needs a wind and the disk's
     * centre and radius; with rotor 0 the zone's ship-only field):
     * a box 5 R from the hub across and along, 4 R above it, down to the
     * sea, with the grid of the level inside it. Its open faces (all but the
     * sea; inlet or outlet by the wind as for the whole domain, the top and
     * the faces along the wind fixed) take their values from zone_field
     * scaled by zone_scale (velocities by the factor, k by its square,
     * epsilon by its cube: the ship-only field scales with the wind speed)
     * or, with zone_field NULL (the isolated rotor), from the inflow
     * profile. The spec and zone_field must outlive the solver. */
    int zone;
    const cfd_field *zone_field;
    double zone_scale;
} cfd_airwake_spec;

/* Build the grid, boundaries (inflow and outflow faces from the WOD
 * direction; the sea is a no-slip wall; top symmetry) and the solver. */
cfd_solver *cfd_airwake_create(const cfd_airwake_spec *spec, const core_log *log,
                               cfd_progress_fn progress, void *progress_user, core_err *err);
/* Recirculation behind the hangar: *len_m gets the distance (m) aft of the
 * hangar face (deck_x1) along y = y_m at height z_m (S) where the flow,
 * reversed next to the hangar, turns forward again along the wind; 0 when
 * there is no reversed flow next to the hangar. Returns 1 if the flow is
 * still reversed three deck lengths aft (len_m = that distance), else 0. */
int cfd_airwake_reattachment(const cfd_solver *s, const core_ship *ship, double wod_dir_rad,
                             double y_m, double z_m, double *len_m);

/* A flow to sample: a solver's state (solver) or a loaded field (field);
 * the one that is not NULL. */
typedef struct cfd_flow {
    const cfd_solver *solver;
    const cfd_field *field;
} cfd_flow;

/* The deck lines two airwakes are compared along: the port quarter
 * (y = -3.4 m), the centre line and the starboard quarter (3.4 m) at 3.8 m,
 * 6.8 m (the hangar's height) and 10 m above the deck, each from the stern
 * (deck_x0) to the hangar face (deck_x1) in CFD_DECK_LINE_POINTS points. */
#define CFD_DECK_LINES 9
#define CFD_DECK_LINE_POINTS 25

typedef struct cfd_deck_diff {
    double worst;                           /* the largest velocity difference |a - b|, / u_ref */
    double worst_at_m[3];                   /* ... where (S) */
    double rms;                             /* RMS of |a - b| / u_ref over every point */
    double line_y_m[CFD_DECK_LINES];        /* each line's y and z (S) ... */
    double line_z_m[CFD_DECK_LINES];
    double line_worst[CFD_DECK_LINES];      /* ... its largest difference, / u_ref ... */
    double line_worst_x_m[CFD_DECK_LINES];  /* ... and where along it (x, S) */
} cfd_deck_diff;

/* The velocities of a and b compared along the deck lines of ship. */
void cfd_airwake_deck_diff(const core_ship *ship, const cfd_flow *a, const cfd_flow *b, double u_ref_mps,
                           cfd_deck_diff *out);

/* -------------------------------------------------------------- validation */
#define CFD_MAX_CHECKS 96

typedef struct cfd_check {
    char name[64];
    double measured, reference, tol; /* pass when |measured - reference| <= tol; a window
                                        (reference its centre, tol its half-width) passes
                                        strictly inside; NaN (nothing measured) fails */
    int pass;
} cfd_check;

typedef struct cfd_report {
    int n;
    cfd_check c[CFD_MAX_CHECKS];
    int passed, failed;
    double wall_s;
} cfd_report;

/* Run one validation case by name (cavity100, cavity1000, bfs, disk-oge,
 * disk-ige, sfs2, sfs2-grid). small = 1: the reduced grid and the stated
 * looser tolerances of the CI tests. data_dir holds the reference tables
 * (NULL: the source tree's tests/cfd/data). ships_dir holds sfs2.ini (NULL:
 * the source tree's scenarios/ships). */
int cfd_validate(const char *name, int small, const char *data_dir, const char *ships_dir,
                 const core_log *log, cfd_progress_fn progress, void *progress_user,
                 cfd_report *rep, core_err *err);
/* The names, NULL-terminated. */
extern const char *const cfd_validate_cases[];

#ifdef __cplusplus
}
#endif
#endif
