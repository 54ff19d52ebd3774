/*
 * hfm.h -- helicopter flight mechanics: aircraft data files, a blade-element
 * main rotor with flapping and Pitt-Peters inflow, tail rotor / fenestron,
 * fuselage and empennage, the 6-DOF rigid body of the seed paper (eqs. 6-9),
 * trim by Newton-Raphson and pseudo-arc-length continuation, linearisation
 * and time simulation (SUNDIALS ARKODE fixed step, CVODE variable step).
 *
 * Frames and units follow docs/conventions.md: SI inside; the ship
 * frame S (x bow, y starboard, z down) is the reference frame of the
 * kinematics and is treated as inertial (steady ship translation); body
 * frame B at the centre of gravity; Euler angles 3-2-1 of B relative to S.
 * The time simulation only needs the reference frame to be inertial: the
 * flight loop (sim/) runs it in the Earth frame E, with an air callback
 * that takes positions in E and gives the air in E (names ending in _S
 * then mean "the kinematics frame").
 * Controls are percent of travel (collective 0 = full down, longitudinal
 * 0 = full forward, lateral 0 = full left, pedal 0 = full left).
 *
 * Every aerodynamic component samples the air through ONE callback, an
 * hfm_air_fn: at each main-rotor blade element, the tail-rotor hub, the
 * fuselage reference point and the tail surfaces.
 */
#ifndef DISIM_HFM_H
#define DISIM_HFM_H

#include "core.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------ air input */
/* Air velocity (m/s, frame S) at pos_S_m and time t_s. Returns 0, or
 * non-zero when the point cannot be sampled (the evaluation then fails). */
typedef int (*hfm_air_fn)(void *user, const double pos_S_m[3], double t_s, double vel_S_mps[3]);

/* The uniform wind: user points to an hfm_air_uniform. */
typedef struct hfm_air_uniform {
    double vel_S_mps[3];
} hfm_air_uniform;
int hfm_air_uniform_fn(void *user, const double pos_S_m[3], double t_s, double vel_S_mps[3]);

typedef struct hfm_air {
    hfm_air_fn fn;
    void *user;
    /* NULL, or the air that sets the geometry of the main rotor's wake on
     * the airframe (its skew and direction, sampled at the hub): when fn
     * already holds the airframe's share of the rotor's wake as a flow
     * field (coupled minus isolated CFD), the wake model must be the
     * isolated rotor's, i.e. skewed by the undisturbed wind, or the wake
     * on the tail is counted twice. The rotor itself sees fn. */
    const struct hfm_air *wake;
} hfm_air;

/* ------------------------------------------------------------- aircraft */
typedef struct hfm_aircraft hfm_aircraft;

/* Load an aircraft data file (INI). Every missing or non-physical parameter
 * and every unknown key is an error naming file, line and key. The
 * [rejection] section is left to shol. NULL on failure with err filled. */
hfm_aircraft *hfm_aircraft_load(const char *path, const core_log *log, core_err *err);
/* The same on an aircraft file already read (core_ini_load or
 * core_ini_parse; its entries are marked used, the caller destroys it). */
hfm_aircraft *hfm_aircraft_from_ini(core_ini *ini, const core_log *log, core_err *err);
void hfm_aircraft_destroy(hfm_aircraft *ac);
const char *hfm_aircraft_name(const hfm_aircraft *ac);
double hfm_aircraft_mass_kg(const hfm_aircraft *ac);
double hfm_aircraft_weight_N(const hfm_aircraft *ac);
int hfm_aircraft_blades(const hfm_aircraft *ac);
double hfm_aircraft_rotor_radius_m(const hfm_aircraft *ac);
double hfm_aircraft_rotor_omega_radps(const hfm_aircraft *ac);
/* 1 if the main rotor turns counter-clockwise seen from above (UH-60A), 0 if clockwise (SA365N). */
int hfm_aircraft_rotor_ccw(const hfm_aircraft *ac);

/* The main rotor's blades as a blade-element rotor disk takes them (the
 * OpenFOAM engine's rotorDisk): plain data. Blade pitch at radius r is
 * theta0 + twist_rad (r / R - twist_ref); the airfoil is the file's table
 * on its 1 deg grid from -180 to 180 deg (no compressibility). */
#define HFM_BLADE_NALPHA 361
typedef struct hfm_blade_data {
    int blades, ccw;                 /* ccw: 1 counter-clockwise seen from above */
    double radius_m, omega_radps, chord_m;
    double root_cutout_m;            /* no lift inside */
    double tip_loss;                 /* Prandtl's B: r / R beyond which there is no lift */
    double twist_rad, twist_ref;     /* linear twist and the r / R where it is zero */
    double lift_slope_per_rad;       /* of the table, from cl at -4 and +4 deg */
    double hover_pitch0_rad;         /* theta0 of the blade-element momentum estimate of the hover
                                        collective at the aircraft's weight (hfm_aircraft_figures) */
    double alpha_deg[HFM_BLADE_NALPHA], cl[HFM_BLADE_NALPHA], cd[HFM_BLADE_NALPHA];
} hfm_blade_data;
void hfm_aircraft_blade_data(const hfm_aircraft *ac, hfm_blade_data *b);

/* The stability augmentation of the aircraft file's optional [sas] section
 * (docs/aircraft-format.md): per axis (0 roll, 1 pitch, 2 yaw) a rate gain
 * and an attitude-hold gain (percent of travel per rad/s and per rad of the
 * rate or attitude error; positive opposes the motion) and the authority
 * (+- percent of travel); engaged: on (1) or off (0) at the start of a
 * flight; detent_pct: how far (percent of travel) a pilot's control must
 * move from where the attitude hold last took its reference for the hold to
 * take a new one. sim/sas.c is the controller. Plain data. */
typedef struct hfm_sas_gains {
    int engaged;
    double rate_pct_per_radps[3];
    double att_pct_per_rad[3];
    double authority_pct[3];
    double detent_pct;
} hfm_sas_gains;
/* 0 and g filled when the file has a [sas] section; 1 (g zeroed, engaged 0)
 * when it has none (the aircraft flies bare). */
int hfm_aircraft_sas(const hfm_aircraft *ac, hfm_sas_gains *g);

/* ------------------------------------- the validated error [model_error] */
/* The optional [model_error] section (docs/aircraft-format.md): the
 * model's trim minus a reference's (a validated model's or flight test's)
 * at one airspeed, as the aircraft's validation measured it, in the
 * quantities the SHOL's criteria judge; shol's bands carry it into each
 * limit (shol/band.c). Plain data. */
typedef struct hfm_model_error {
    char reference[32];   /* what the trim was compared with, "GenHel" */
    double airspeed_mps;  /* the airspeed of the trim compared */
    double roll_rad, pitch_rad; /* model minus reference; NAN: not validated */
    double collective_pct, long_cyclic_pct, lat_cyclic_pct, pedal_pct; /* percentage points of travel */
} hfm_model_error;
/* 0 and out filled when the file has a [model_error] section; 1 (every
 * error NAN, reference "") when it has none: the model is not validated. */
int hfm_aircraft_model_error(const hfm_aircraft *ac, hfm_model_error *out);

/* ------------------------------------------------ the landing gear [gear] */
/* The optional [gear] section (docs/aircraft-format.md): the legs (an oleo
 * strut along the body z axis in series with a tyre) and the body points
 * checked for a strike on the ship (sim/contact.c uses both). */
#define HFM_GEAR_MAX_LEGS 6
#define HFM_GEAR_MAX_POINTS 16
typedef struct hfm_gear_leg {
    char name[32];
    double pos_B_m[3];             /* the wheel's centre, strut fully extended */
    double tyre_radius_m;
    double stroke_m;               /* the strut's travel to its end stop */
    double stiffness_Npm;          /* the strut's spring beyond the preload */
    double damping_comp_Nspm;      /* compressing */
    double damping_reb_Nspm;       /* extending (rebound) */
    double preload_N;              /* the strut's force fully extended */
    double tyre_stiffness_Npm;     /* vertical (and, assumed, lateral) */
    int brake;                     /* 1: the wheel has a brake */
    int castor;                    /* 1: the wheel castors unless locked */
} hfm_gear_leg;
typedef struct hfm_gear {
    int nlegs;
    hfm_gear_leg leg[HFM_GEAR_MAX_LEGS];
    double mu_static, mu_dynamic, mu_rolling;
    int brakes_on;                 /* the parking brake set at the start */
    int tail_lock_on;              /* castoring wheels locked at the start */
    int npoints;
    char point_name[HFM_GEAR_MAX_POINTS][32];
    double point_B_m[HFM_GEAR_MAX_POINTS][3];
} hfm_gear;
/* The gear of the aircraft file: 0, or 1 (g zeroed) when it has none. */
int hfm_aircraft_gear(const hfm_aircraft *ac, hfm_gear *g);

/* What an aircraft looks like, for drawing it (render/) and placing the
 * pilot's eye: the rotors, the gear and the strike points as the file
 * gives them, and the optional [cockpit] section (docs/aircraft-format.md).
 * Body axes from the CG. Plain data. */
typedef struct hfm_geometry {
    char name[64];
    int blades, rotor_ccw;         /* main rotor: blades; 1 counter-clockwise seen from above */
    double rotor_radius_m, rotor_omega_radps;
    double hub_B_m[3];
    double shaft_tilt_rad;         /* forward */
    int tail_fenestron;            /* 1 fenestron (ducted fan in the fin), 0 open tail rotor */
    int tail_blades;
    double tail_radius_m, tail_omega_radps;
    double tail_hub_B_m[3];
    double tail_dir_B[3];          /* the tail rotor's thrust direction (its disk's normal) */
    double stab_B_m[3];            /* the horizontal stabiliser's and the fin's reference points */
    double fin_B_m[3];
    int has_eye;                   /* 1: [cockpit] pilot_eye_B_m given */
    double eye_B_m[3];             /* the pilot's eye (design eye point) */
    hfm_gear gear;                 /* legs and strike points (nlegs 0: no [gear]) */
} hfm_geometry;
void hfm_aircraft_geometry(const hfm_aircraft *ac, hfm_geometry *g);

/* Figures derived from an aircraft file, for comparing it with published
 * data; hfm_aircraft_load checks them against the bands of real helicopters
 * (docs/aircraft-format.md, "Consistency checks"). */
typedef struct hfm_aircraft_figures {
    double tip_speed_mps;            /* main rotor Omega R */
    double solidity;                 /* blades x chord / (pi R) */
    double lift_slope_per_rad;       /* airfoil table, from cl at -4 and +4 deg */
    double airfoil_cl_max;           /* largest cl of the airfoil table */
    double lock_number;              /* rho a c R^4 / I_beta */
    double flap_freq_per_rev;        /* sqrt(1 + e S_beta/I_beta + K_beta/(I_beta Omega^2)) */
    double flap_freq_offset_per_rev; /* the hinge offset alone (no spring) */
    double flap_freq_spring_per_rev; /* the spring alone (no offset) */
    double disk_loading_Pa;          /* weight / disk area */
    double ct_over_sigma_hover;      /* weight / (rho A (Omega R)^2) / solidity */
    double hover_pitch75_deg;        /* blade-element momentum estimate of the hover collective at 0.75 R */
    double coll_pitch75_min_deg, coll_pitch75_max_deg; /* the collective rig's range at 0.75 R */
    double tr_tip_speed_mps, tr_solidity;
    double drag_area_m2;             /* fuselage D/q at alpha = 0 */
} hfm_aircraft_figures;
void hfm_aircraft_get_figures(const hfm_aircraft *ac, hfm_aircraft_figures *f);

/* ---------------------------------------------------------- state, loads */
/* Rigid-body state relative to S (transparent). */
typedef struct hfm_body {
    double pos_S_m[3];     /* centre of gravity in S */
    double vel_B_mps[3];   /* u v w: CG velocity relative to S, body axes */
    double rate_B_radps[3];/* p q r */
    double euler_rad[3];   /* phi theta psi (3-2-1, B relative to S) */
} hfm_body;

/* Pilot controls, percent of travel: the collective, the longitudinal
 * and lateral cyclic, the pedals, named as on the LCM wire (pilot_input_t,
 * heli_state_t). The one type of the four above hfm: sim_flight_inputs,
 * sim_flight_out, sim_station_controls and couple_iter carry it as `ctl`.
 * Its fields are in this order (hfm/linear.c steps through them). shol,
 * which knows no flight model, keeps its own (shol_trim_point). */
typedef struct hfm_controls {
    double collective_pct, long_cyclic_pct, lat_cyclic_pct, pedal_pct;
} hfm_controls;

/* Main-rotor states for a revolution-averaged (harmonic) evaluation. */
typedef struct hfm_rotor_harm {
    double beta0_rad, beta1c_rad, beta1s_rad; /* beta = b0 + b1c cos psi + b1s sin psi */
    double lambda0, lambda1s, lambda1c;       /* Pitt-Peters inflow, of Omega R */
    double beta2c_rad, beta2s_rad;            /* + b2c cos 2psi + b2s sin 2psi */
} hfm_rotor_harm;

/* Force and moment of one component, body axes, moment about the CG. */
typedef struct hfm_fm {
    double F_B_N[3];
    double M_B_Nm[3];
} hfm_fm;

typedef struct hfm_loads {
    hfm_fm mr, tr, fus, stab, fin, total; /* total includes gravity */
    double acc_B[6];          /* u' v' w' (m/s^2) p' q' r' (rad/s^2), eqs. (7)-(8) */
    double mr_thrust_N;       /* along the shaft, positive up */
    double mr_power_W;        /* aerodynamic power of the main rotor */
    double mr_torque_Nm;
    double tr_thrust_N, tr_power_W;
    /* Power accounting (hfm_loads_power): the shaft power the drive train
     * delivers to the rotors (main + tail rotor aerodynamic power) and the
     * engines' output power (shaft power / transmission efficiency +
     * accessory power, the aircraft file's [power] section). */
    double shaft_power_W, engine_power_W;
    double stab_incidence_rad;
    double airspeed_mps;      /* air relative speed at the fuselage reference */
    double wake_skew_rad;
    double mr_CT, mr_CL, mr_CM; /* aerodynamic forcing of Pitt-Peters */
    /* Harmonic evaluation only: flap residuals (0, 1c, 1s, 2c, 2s, of
     * I_beta Omega^2) and inflow residuals (lambda - L C). */
    double flap_res[5];
    double inflow_res[3];
} hfm_loads;

/* Evaluate all loads with a harmonic (revolution-averaged) rotor: the blade
 * is evaluated at the aircraft's trim azimuth points and the loads averaged
 * (the trim residual f(X, U) is built on this). t_s is passed to the air
 * callback. Returns 0, or < 0 if the air callback failed. */
int hfm_eval_harmonic(const hfm_aircraft *ac, const hfm_air *air, double t_s, const hfm_body *b,
                      const hfm_controls *u, const hfm_rotor_harm *rh, hfm_loads *out);

/* Fill L->shaft_power_W and L->engine_power_W from L's rotor powers
 * (hfm_eval_harmonic calls it; a time-simulation caller may). */
void hfm_loads_power(const hfm_aircraft *ac, hfm_loads *L);

/* Blade pitch angles (rad) for controls: root collective (at r = 0), the
 * cyclic angles A1 (lateral, + right) and B1 (longitudinal, + forward), and
 * the tail-rotor collective at its reference station. */
void hfm_controls_to_pitch(const hfm_aircraft *ac, const hfm_controls *u, double *theta0_rad,
                           double *A1_rad, double *B1_rad, double *theta_tr_rad);

/* Disk loading for a CFD actuator disk: a revolution-averaged distribution
 * on nr radial x npsi azimuthal cells (azimuth from the tail in the sense of
 * rotation, radial cells of equal width from the root cut-out to the tip).
 * thrust_Pa[i*npsi+j]: thrust per disk area (N/m^2, along the shaft, up);
 * swirl_Pa: in-plane force on the air per disk area in the sense of
 * rotation (N/m^2). Also the hub position (S) and attitude (q_SH). */
typedef struct hfm_disk {
    int nr, npsi;
    double r_m[64];          /* cell centres */
    double thrust_Pa[64 * 72];
    double swirl_Pa[64 * 72];
    double hub_S_m[3];
    core_quat q_SH;          /* hub frame (x fwd-ish, z down the shaft) to S */
    int sense;               /* +1 counter-clockwise from above, -1 clockwise */
    double thrust_N, power_W;
} hfm_disk;
int hfm_rotor_disk(const hfm_aircraft *ac, const hfm_air *air, double t_s, const hfm_body *b,
                   const hfm_controls *u, const hfm_rotor_harm *rh, int nr, int npsi,
                   hfm_disk *out);

/* ------------------------------------------------- continuation, Newton */
/* F(x, lam) = 0 with n unknowns; returns 0, non-zero if F cannot be evaluated. */
typedef int (*hfm_sys_fn)(void *user, const double *x, double lam, double *f);

typedef struct hfm_newton_opts {
    int max_iter;       /* default 40 */
    double tol;         /* on the max-norm of F, default 1e-9 */
    const double *dx;   /* central-difference steps per unknown (NULL: 1e-6) */
} hfm_newton_opts;

typedef struct hfm_newton_info {
    int converged, iterations, evaluations;
    double resid_norm; /* max-norm of F at the end */
    int worst_eq;      /* index of the largest |F_i| */
} hfm_newton_info;

/* Newton-Raphson with central-difference Jacobians (LAPACK dgesv) and a
 * backtracking line search, at fixed lam. x is updated in place. Returns 0
 * when converged, 1 when not (info says why), < 0 on a fatal error. */
int hfm_newton(hfm_sys_fn fn, void *user, int n, double *x, double lam,
               const hfm_newton_opts *opts, hfm_newton_info *info);

typedef struct hfm_cont_opts {
    double ds0, ds_min, ds_max; /* arc-length steps (in the scaled space) */
    double lam_scale;           /* arc length weight of the parameter */
    const double *x_scale;      /* per-unknown scale (NULL: 1) */
    int max_steps;
    int corr_max_iter;          /* corrector iterations before a step is cut */
    double tol;
    const double *dx;           /* central-difference steps (NULL: 1e-6) */
} hfm_cont_opts;

/* Called at each accepted point; return non-zero to stop the trace. */
typedef int (*hfm_cont_point_fn)(void *user, const double *x, double lam, double dlam_ds,
                                 int fold);

typedef struct hfm_cont_info {
    int steps, rejected, folds, evaluations;
    int stopped;         /* 1: stopped by the point callback */
    double lam_end;
} hfm_cont_info;

/* Pseudo-arc-length continuation from a converged (x0, lam0) in the
 * direction of increasing lam: Euler predictor along the tangent (null
 * vector of [F_x F_lam]), Newton corrector on the augmented system
 * [F; t.(y - y_pred)] = 0, step halving on failure and growth on easy
 * convergence; the tangent keeps its orientation through turning points
 * (where dlam/ds changes sign: fold = 1 at that point). Stops when lam
 * leaves [lam_min, lam_max], after max_steps, or at the callback's wish.
 * Returns 0, 1 if a step fell below ds_min, < 0 on a fatal error. */
int hfm_cont_trace(hfm_sys_fn fn, void *user, int n, const double *x0, double lam0,
                   double lam_min, double lam_max, const hfm_cont_opts *opts,
                   hfm_cont_point_fn point, void *point_user, hfm_cont_info *info);

/* ---------------------------------------------------------------- trim */
enum { HFM_TRIM_FORWARD = 0, HFM_TRIM_HOVER_SHIP = 1 };
enum { HFM_CONSTRAINT_AUTO = 0, HFM_CONSTRAINT_SIDESLIP = 1, HFM_CONSTRAINT_ROLL = 2 };
enum { HFM_PARAM_AIRSPEED = 0, HFM_PARAM_WOD_SPEED = 1 };

/* A flight condition. FORWARD: straight level flight at airspeed_mps in
 * still air (or in `air` when given), heading along S's x. HOVER_SHIP: the
 * CG fixed at pos_S_m, heading along the ship's bow (psi = 0), in a WOD
 * of wod_speed_mps from wod_dir_rad (docs/conventions.md), or in `air` when
 * given (a field). */
typedef struct hfm_trim_cond {
    int kind;
    int constraint;        /* FORWARD: zero sideslip / wings level / auto */
    double airspeed_mps;
    double wod_speed_mps, wod_dir_rad;
    double pos_S_m[3];
    const hfm_air *air;    /* NULL: the uniform wind of the condition */
} hfm_trim_cond;

#define HFM_TRIM_N 14
typedef struct hfm_trim_result {
    int converged, iterations;
    double resid_norm;
    int worst_eq;
    const char *worst_eq_name;
    double x[HFM_TRIM_N];  /* the unknowns (warm start for the next trim) */
    hfm_controls u;
    hfm_body body;
    hfm_rotor_harm rotor;
    double sideslip_rad;
    int wings_level;       /* 1: x[5] is the sideslip (roll held at zero) */
    double speed_kt;       /* airspeed or WOD speed of the condition */
    hfm_loads loads;
} hfm_trim_result;

typedef struct hfm_trim hfm_trim;
hfm_trim *hfm_trim_create(const hfm_aircraft *ac, const core_log *log);
void hfm_trim_destroy(hfm_trim *tr);
/* The trim residual f(X, U) for the unknown vector x (controls %, theta,
 * phi or sideslip, beta0, beta1c, beta1s, lambda0, lambda1s, lambda1c,
 * beta2c, beta2s). Scaled equations: 0-2 body accelerations / g, 3-5
 * angular accelerations (rad/s^2), 6-8 flapping 0/1c/1s, 9-11 inflow,
 * 12-13 flapping 2c/2s. Returns 0 or < 0. */
int hfm_trim_residual(hfm_trim *tr, const hfm_trim_cond *c, const double *x, double *f);
/* Trim one condition; guess may be NULL (cold start) or a previous result.
 * Returns 0 converged, 1 not converged (res->worst_eq says which equation),
 * < 0 fatal. */
int hfm_trim_solve(hfm_trim *tr, const hfm_trim_cond *c, const hfm_trim_result *guess,
                   hfm_trim_result *res);
/* A sweep over a parameter (airspeed or WOD speed, m/s) at the values
 * vals[0..n-1] (increasing), by pseudo-arc-length continuation from a trim
 * at vals[0]; every value is hit exactly by a corrector at fixed parameter.
 * Returns 0 when every point converged, 1 otherwise (see res[i].converged). */
int hfm_trim_sweep(hfm_trim *tr, const hfm_trim_cond *c, int param, const double *vals, int n,
                   hfm_trim_result *res);
/* The air of a trim at a WOD speed for hfm_trim_sweep_warm (NULL: calm). */
typedef const hfm_air *(*hfm_air_at_fn)(void *user, double wod_speed_mps);
/* Hover trims (c's kind and constraint, WOD direction and station) at the
 * WOD speeds mps[0..n-1], each in the air air_at gives for its speed and
 * started from the last converged trim (from the free-air guess again where
 * that does not converge; a trim that does not converge is kept, see
 * res[i].converged). Returns 0, or < 0 when trim *at failed fatally (e.g.
 * sampled air outside a field); the later ones are not trimmed then. */
int hfm_trim_sweep_warm(hfm_trim *tr, const hfm_trim_cond *c, const double *mps, int n, hfm_air_at_fn air_at,
                        void *user, hfm_trim_result *res, int *at);
/* The trim table's CSV (disim trim): the header line and the row of a trim
 * at speed_kt, without newline (the row as snprintf returns). */
const char *hfm_trim_csv_header(void);
int hfm_trim_csv_row(double speed_kt, const hfm_trim_result *r, char *buf, size_t n);

/* -------------------------------------------------------- linearisation */
#define HFM_LIN_NX 9
#define HFM_LIN_NU 4
typedef struct hfm_linear {
    double A[HFM_LIN_NX * HFM_LIN_NX]; /* row major, states u v w p q r phi theta psi */
    double B[HFM_LIN_NX * HFM_LIN_NU]; /* controls in percent */
    double eig_re[HFM_LIN_NX], eig_im[HFM_LIN_NX];
    char mode[HFM_LIN_NX][32];         /* a name per eigenvalue */
} hfm_linear;

/* A and B at a trim by central differences with the rotor states
 * quasi-steady (flapping and inflow re-solved at each perturbation), and
 * the eigenvalues (LAPACK dgeev) with modes named from their eigenvectors. */
int hfm_linearise(hfm_trim *tr, const hfm_trim_cond *c, const hfm_trim_result *trim,
                  hfm_linear *lin);

/* ------------------------------------------------------ time simulation */
enum { HFM_TSIM_ARKODE_FIXED = 0, HFM_TSIM_CVODE = 1 };
typedef struct hfm_tsim hfm_tsim;

/* A time simulation of the body, the individual blades (turning with the
 * rotor azimuth, each evaluated at its own azimuth; their flapping held as
 * multiblade coordinates, an exact change of variables) and the inflow
 * states. method ARKODE_FIXED uses Ralston's explicit RK (2 stages, 2nd
 * order) at step h_s (real time); CVODE uses BDF with rtol. air is copied
 * (not its user data). */
hfm_tsim *hfm_tsim_create(const hfm_aircraft *ac, const hfm_air *air, int method, double h_s,
                          double rtol, const core_log *log);
void hfm_tsim_destroy(hfm_tsim *ts);
/* Start from a body state, controls and harmonic rotor state (e.g. a trim):
 * blade flap angles and rates from the harmonics at the blade azimuths
 * (azimuth 0), projected on the multiblade coordinates. */
int hfm_tsim_init(hfm_tsim *ts, double t0_s, const hfm_body *b, const hfm_controls *u,
                  const hfm_rotor_harm *rh);
void hfm_tsim_set_controls(hfm_tsim *ts, const hfm_controls *u);
/* External loads on the airframe (the landing gear on the deck, a test
 * load): the force and the moment about the centre of gravity, both in B,
 * for the body state b at t_s. Added to the aerodynamic loads and gravity
 * at every right-hand side. Returns 0, or non-zero to fail the evaluation
 * (the step then fails). */
typedef int (*hfm_ext_fn)(void *user, double t_s, const hfm_body *b, double F_B_N[3], double M_B_Nm[3]);
/* fn NULL: none (the default). */
void hfm_tsim_set_external(hfm_tsim *ts, hfm_ext_fn fn, void *user);
/* Advance to t_s. Returns 0, or < 0 on a solver failure. */
int hfm_tsim_advance(hfm_tsim *ts, double t_s);
void hfm_tsim_body(const hfm_tsim *ts, hfm_body *b);
/* The main rotor's thrust (N, along the shaft, up) and aerodynamic power
 * (W) at the last right-hand side evaluated (a fixed step's last stage:
 * 2/3 of the step into it); 0 before the first. */
void hfm_tsim_rotor(const hfm_tsim *ts, double *thrust_N, double *power_W);
long hfm_tsim_rhs_evals(const hfm_tsim *ts);
/* The state derivative of the time model (n = hfm_tsim_size): position,
 * u v w, p q r, Euler angles, inflow (3), azimuth, nb multiblade flap
 * coordinates and their nb rates. */
int hfm_tsim_size(const hfm_tsim *ts);
int hfm_tsim_rhs(hfm_tsim *ts, double t_s, const double *y, double *ydot);
/* Copy the current state (n >= hfm_tsim_size) into y. Returns 0, or -1 if n is too small. */
int hfm_tsim_state(const hfm_tsim *ts, double *y, int n);

#ifdef __cplusplus
}
#endif
#endif
