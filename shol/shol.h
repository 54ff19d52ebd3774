/*
 * shol.h -- the candidate ship-helicopter operating limits (SHOL): rejection
 * criteria, the trim-based envelope procedure of the seed paper (section
 * 2.8), and its outputs (CSV, JSON, polar and trim-versus-speed plots, a
 * Markdown report).
 *
 * The module knows nothing about the physics: the caller supplies a trim
 * callback (shol_trim_fn) that trims the helicopter at the hover-over-spot
 * station for a given wind over deck, e.g. in the coupled airwake. See
 * docs/shol.md for how a command drives it.
 *
 * Conventions (docs/conventions.md):
 *  - SI inside: speeds in m/s, angles in rad. Degrees, knots and km/h appear
 *    only in the data file keys and the output files, whose names say so.
 *  - WOD direction is where the wind comes FROM, from the bow, positive to
 *    starboard (green), negative to port (red), in (-180, 180].
 *  - Controls are percentages of full travel, 0..100, 50 mid-travel. A limit
 *    L% on a control rejects it above L% or below (100 - L)%. (The
 *    convention reads a cyclic or pedal limit as a displacement from
 *    neutral, rejected beyond 50 +- L/2 %, and a collective limit from full
 *    down; docs/conventions.md sets the two readings side by side.)
 *  - Functions return int: 0 ok, < 0 fatal (err filled), > 0 recoverable.
 */
#ifndef DISIM_SHOL_H
#define DISIM_SHOL_H

#include "core.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------- criteria */
/* The rejection criteria, in the order of the seed paper's Table 4. */
typedef enum shol_crit {
    SHOL_CRIT_ROLL = 0,
    SHOL_CRIT_PITCH = 1,
    SHOL_CRIT_LONG = 2, /* longitudinal cyclic */
    SHOL_CRIT_LAT = 3,  /* lateral cyclic */
    SHOL_CRIT_COLL = 4, /* collective */
    SHOL_CRIT_PEDAL = 5,
    SHOL_NCRIT = 6
} shol_crit;

/* What limited a direction: a criterion (0..5) or one of these. */
enum {
    SHOL_LIMIT_NONE = -1, /* nothing exceeded up to the highest speed searched */
    SHOL_LIMIT_TRIM = 6   /* the trim did not converge (treated as a rejection) */
};

/* Short names used in files and plots: "roll", "pitch", "long_cyclic",
 * "lat_cyclic", "collective", "pedal", "trim", "none"; NULL if unknown. */
const char *shol_limit_name(int limit);
/* Inverse of shol_limit_name; returns 0 and sets *limit, or -1. */
int shol_limit_parse(const char *name, int *limit);

/* The control limits here are bounds on the pilot controls, not controls,
 * read as displacements (docs/conventions.md): a cyclic's or the pedal's L
 * is a displacement from neutral of L % of the travel to the stop, so it
 * rejects the control below 50 - L/2 or above 50 + L/2 % of full travel;
 * the collective's L rejects it above L % (from full down). */
typedef struct shol_criteria {
    double roll_max_rad;    /* reject abs(phi) > roll_max_rad */
    double pitch_max_rad;   /* reject abs(theta) > pitch_max_rad */
    double long_cyclic_pct; /* reject below 50 - L/2 or above 50 + L/2 */
    double lat_cyclic_pct;  /* the same */
    double collective_pct;  /* reject above L */
    double pedal_pct;       /* reject below 50 - L/2 or above 50 + L/2 */
} shol_criteria;

/* The defaults of docs/conventions.md (seed paper Table 4): 5 deg, 8 deg, 85 %,
 * 85 %, 85 %, 80 %. */
void shol_criteria_default(shol_criteria *c);

/* Read the [rejection] section of an aircraft data file that is already
 * loaded: keys roll_deg, pitch_deg (0..90), long_cyclic_pct, lat_cyclic_pct,
 * collective_pct, pedal_pct (50..100); an absent key keeps its default, an
 * absent section gives all defaults. Unknown keys in [rejection] are errors;
 * other sections are left to their owners (not consumed). Returns 0, or < 0
 * with err "file:line: [rejection] key ...". */
int shol_criteria_read(core_ini *ini, shol_criteria *c, core_err *err);
/* Load path and read its [rejection] section (see shol_criteria_read). */
int shol_criteria_load(const char *path, shol_criteria *c, core_err *err);
/* Criterion i's allowed displacement, a margin's denominator when
 * criteria are ranked: the angle limit (rad) for roll and pitch, L/2 for
 * a cyclic or the pedal, L for the collective (percentage points); NaN
 * for an i out of range. */
double shol_criteria_half_band(const shol_criteria *c, int i);
/* Control i's (SHOL_CRIT_LONG .. SHOL_CRIT_PEDAL) passing range in percent
 * of full travel: 50 -+ L/2 for a cyclic or the pedal; -INFINITY (no lower
 * limit) and L for the collective. */
void shol_criteria_control_bounds(const shol_criteria *c, int i, double *lo_pct, double *hi_pct);
/* How c's control limits read, for reports and plots: "cyclic and pedal
 * limits are displacements from neutral: pedal 80 % = 10-90 % of travel,
 * cyclic 85 % = 7.5-92.5 %; collective 85 % from full down, rejected
 * above 85 %". */
void shol_criteria_reading(const shol_criteria *c, char *buf, size_t n);

/* The airframe's components whose loads a trim may report:
 * main rotor, tail rotor (or fenestron), fuselage, horizontal stabiliser
 * (stabilator), fin, and gravity (the weight, acting at the CG). */
enum {
    SHOL_COMP_MR = 0,
    SHOL_COMP_TR = 1,
    SHOL_COMP_FUS = 2,
    SHOL_COMP_STAB = 3,
    SHOL_COMP_FIN = 4,
    SHOL_COMP_GRAVITY = 5,
    SHOL_NCOMP = 6
};
/* "main_rotor", "tail_rotor", "fuselage", "stabilator", "fin", "gravity";
 * NULL if unknown. */
const char *shol_comp_name(int comp);

/* A trim's loads by component, as the flight model computed them: the
 * force and the moment about the centre of gravity in body axes (x
 * forward, y starboard, z down), and the rotors' aerodynamic power. In
 * trim they sum to zero (the accelerations of a hover over the spot).
 * Plain data, kept per sample of a sweep (shol_sample.loads). */
typedef struct shol_loads {
    int valid; /* 1: filled by the trim callback; 0: not supplied */
    double F_B_N[SHOL_NCOMP][3];
    double M_B_Nm[SHOL_NCOMP][3];
    double mr_power_W, tr_power_W;
} shol_loads;
/* Fill *out (valid = 1) from the flight model's components in SHOL_COMP
 * order without the gravity (F_B_N[k], M_B_Nm[k]: 3 each) and their sum
 * with the gravity: the gravity's row is what that sum holds beyond them. */
void shol_loads_set(shol_loads *out, const double *const F_B_N[SHOL_NCOMP - 1],
                    const double *const M_B_Nm[SHOL_NCOMP - 1], const double total_F_B_N[3],
                    const double total_M_B_Nm[3], double mr_power_W, double tr_power_W);

/* A trimmed state: attitude and pilot controls. The controls are
 * hfm_controls' four under the same names, kept here because shol
 * includes core alone (it judges any model's trims) and in the order of
 * the criteria (shol_crit); the callers fill them from hfm_controls. */
typedef struct shol_trim_point {
    double phi_rad;                                                    /* roll, right wing down + */
    double theta_rad;                                                  /* pitch, nose up + */
    double long_cyclic_pct, lat_cyclic_pct, collective_pct, pedal_pct; /* 0..100 */
} shol_trim_point;

/* A trim point judged against the criteria. */
typedef struct shol_eval {
    /* Signed margins, >= 0 inside the limits, < 0 when exceeded: roll and
     * pitch in rad (limit - abs(angle)), controls in percentage points of
     * full travel (a cyclic or the pedal L/2 - abs(c - 50), the collective
     * L - c). Indexed by shol_crit. */
    double margin[SHOL_NCRIT];
    int n_exceeded; /* criteria with margin < 0 */
    /* The limiting criterion: among the exceeded ones (or, if none, among
     * all) the one with the smallest margin as a fraction of its allowed
     * displacement (shol_criteria_half_band); ties go to the first in
     * shol_crit order. */
    int limit;
} shol_eval;

/* Judge p against c. Returns 0, or -1 if p holds a value that is not finite
 * (out then has n_exceeded = 0 and limit = SHOL_LIMIT_TRIM). */
int shol_criteria_eval(const shol_criteria *c, const shol_trim_point *p, shol_eval *out);

/* ------------------------------------------------------------- envelope */
/* Trim the helicopter for a WOD of speed wod_speed_mps from wod_dir_rad.
 * Returns 0 when converged (out filled), > 0 when it did not converge (a
 * rejection, reported as "trim"), < 0 on a fatal error (the sweep stops). */
typedef int (*shol_trim_fn)(void *user, double wod_speed_mps, double wod_dir_rad,
                            shol_trim_point *out);

#define SHOL_MAX_DIRS 360

typedef struct shol_settings {
    int n_dirs;                     /* directions to sweep, in this order */
    double dirs_rad[SHOL_MAX_DIRS]; /* each in (-pi, pi] */
    double speed_step_mps;          /* > 0; default 5 km/h */
    double speed_max_mps;           /* highest speed tried; default 150 km/h */
    double bisect_tol_mps;          /* > 0: refine the first failure by
                                       bisection to this width; 0: off */
    shol_criteria criteria;
} shol_settings;

/* Defaults: red 90 to green 90 by 30 deg, 5 km/h steps up to 150 km/h, no
 * bisection, default criteria. */
void shol_settings_default(shol_settings *s);
/* Directions first_rad, first_rad + step_rad, ... up to last_rad (inclusive,
 * within 1e-9 rad), wrapped into (-pi, pi]. Returns 0, or < 0 (step <= 0,
 * too many directions). */
int shol_settings_dirs(shol_settings *s, double first_rad, double last_rad, double step_rad,
                       core_err *err);
/* The full circle: -180 + step ... 180 deg (step must divide 360 deg within
 * 1e-9 rad). */
int shol_settings_full_circle(shol_settings *s, double step_rad, core_err *err);
/* Check settings, the criteria included (the ranges of
 * shol_criteria_read); < 0 with err naming the bad field. */
int shol_settings_check(const shol_settings *s, core_err *err);

/* One trim of the sweep. */
typedef struct shol_sample {
    double speed_mps;
    int trim_status;      /* what the trim callback returned: 0 or > 0 */
    shol_trim_point trim; /* valid when trim_status == 0 */
    shol_eval eval;       /* limit SHOL_LIMIT_TRIM when the trim failed */
    int pass;             /* 1: converged and nothing exceeded */
    /* The trim's loads by component (valid 0 from the sweep): the caller
     * fills them after the sweep from its trims' records (disim shol from
     * the coupling history) for shol_envelope_attribution. */
    shol_loads loads;
} shol_sample;

/* A direction's limit as a value and a band (shol/band.c,
 * docs/shol.md "Uncertainty bands"), from what the project measures. Each
 * source is a speed interval round the limit V:
 *  - grid: the same limit computed on another grid level, V_g: the
 *    interval from V to V_g (grid_mps = V_g - V, signed);
 *  - window: the field's mean is uncertain by s (its averaging windows'
 *    spread, cfd_result.mean_drift or mean_change, / WOD speed); the air
 *    at the rotor, V times the field, is then uncertain by s V, and through
 *    the limiting quantity's own slope with speed the limit by
 *    window_mps = s V (the slope cancels): V +- s V;
 *  - sensitivity: V +- shol_envelope_sensitivity's shift for 0.25 deg of
 *    attitude or 1 % of travel;
 *  - model: the flight model's validated error e (model minus reference,
 *    shol_model_error) in the limiting quantity, turned into speed through
 *    the limit's measured slope: the interval from V to V + model_mps
 *    (signed: out where the truth is further from the limit than the
 *    model, shol_band_model_shift).
 * The band is their hull, clipped at 0 (and at the radius where nothing
 * failed up to the highest speed searched: the search says nothing above
 * it). */
enum { SHOL_BAND_GRID = 0, SHOL_BAND_WINDOW = 1, SHOL_BAND_SENS = 2, SHOL_BAND_MODEL = 3, SHOL_NBAND = 4 };
#define SHOL_MODEL_REF_MAX 64
typedef struct shol_band {
    int valid;             /* 1: filled (shol_band_compute, shol_band_get, shol_read_csv) */
    double lo_mps, hi_mps; /* lo <= the radius <= hi */
    int open_above;        /* nothing failed up to speed_max: the band does not reach above it */
    double grid_mps;       /* V_g - V; NAN: no second grid at this direction */
    double window_mps;     /* s V >= 0; NAN: the window spread not known */
    double window_frac;    /* s; NAN: not known */
    double sens_mps;       /* >= 0; NAN: the sensitivity is not defined here */
    double model_mps;      /* the limit's signed move for the model's error; NAN: not validated in
                              the limiting quantity, or no slope to turn it into speed */
    int model_crit;        /* the quantity model_err is in (SHOL_CRIT_*); -1: none limits */
    double model_err;      /* model minus reference in it (rad or % of travel); NAN: not validated */
    char model_ref[SHOL_MODEL_REF_MAX]; /* where it was measured, "GenHel at 1 kt" ("" none) */
    int low_confidence;    /* 1: wider than the rule (shol_band_rule) */
    int widest;            /* SHOL_BAND_* that reaches furthest from V, the band's dominant source;
                              -1: a band of width 0 */
} shol_band;

/* Low confidence: a band wider than the larger of width_mps and frac times
 * the limit. Defaults 10 km/h and 0.25. */
typedef struct shol_band_rule {
    double width_mps;
    double frac;
} shol_band_rule;
void shol_band_rule_default(shol_band_rule *r);

/* The envelope at one direction. */
typedef struct shol_dir_result {
    double dir_rad;
    int has_pass;          /* 0: even the lowest speed (0) was rejected */
    double max_speed_mps;  /* last passing speed (0 if !has_pass) */
    double fail_speed_mps; /* lowest failing speed found, NAN if none */
    int limit;             /* criterion at fail_speed_mps, or SHOL_LIMIT_NONE */
    shol_eval margins;     /* at max_speed_mps; at 0 m/s when !has_pass */
    int n_samples;         /* the trim-versus-speed history, by speed */
    shol_sample *samples;
    shol_band band;        /* valid once shol_band_compute has run (zero before) */
} shol_dir_result;

/* A whole envelope: plain data; free the arrays with shol_result_free. */
typedef struct shol_result {
    shol_settings settings;
    int n_dirs;
    shol_dir_result *dirs; /* in the settings' order */
    int n_trims;           /* trim calls made */
    double wall_s;         /* wall-clock time of the sweep */
    shol_band_rule band_rule;  /* the bands' rule (zero: none computed yet) */
    char band_grid_label[96];  /* the second grid's name in the bands ("" none) */
    /* the model error's reference in the bands, "GenHel at 1 kt" (""
     * not validated, or no bands computed) */
    char band_model_label[SHOL_MODEL_REF_MAX];
} shol_result;

void shol_result_free(shol_result *r);

/* Progress of a sweep, sent after each trim. */
typedef struct shol_progress {
    int dir_index, n_dirs;
    double dir_rad, speed_mps;
    int n_trims;       /* trims so far */
    double fraction;   /* 0..1, an estimate (a direction counts as far as its
                          speed over speed_max, and whole once finished) */
    double elapsed_s;  /* wall clock since the start */
    double rate_per_s; /* trims per second */
    double eta_s;      /* estimated time left, NAN before the first estimate */
    int done;          /* 1 on the last call */
} shol_progress;

typedef void (*shol_progress_fn)(void *user, const shol_progress *p);

/* Format one progress line ("37% red 30 at 45 km/h, 12 trims, 2.5 min/trim,
 * 41 min 20 s left"), without newline. */
void shol_progress_format(const shol_progress *p, char *buf, size_t n);

/* Run the candidate SHOL procedure (seed paper section 2.8): for each
 * direction, trim at 0, step, 2 step, ... up to speed_max_mps; stop at the
 * first speed where a criterion is exceeded or the trim does not converge;
 * then, with bisect_tol_mps > 0, bisect between the last pass and the first
 * failure until they are at most bisect_tol_mps apart. progress and log may
 * be NULL. On success out is filled (free with shol_result_free); on error
 * (the callback returned < 0, bad settings, out of memory) out is empty and
 * err names the direction and speed. */
int shol_envelope_run(const shol_settings *s, shol_trim_fn trim, void *trim_user,
                      shol_progress_fn progress, void *progress_user, const core_log *log,
                      shol_result *out, core_err *err);

/* The procedure with an expensive trim (e.g. two-way coupled) only near the
 * boundary that a cheaper one (e.g. one-way) found: cheap_result is the
 * cheap trim's envelope; at each direction the speeds from margin_mps below
 * its radius up are trimmed with costly, those below with cheap. Where no
 * costly speed passes in a direction (its first costly speed already
 * fails), the radius would be a speed only the cheap trim passed: that
 * direction is swept again with the costly region 1, 3, 7, ... margins
 * lower, until a
 * costly speed passes or the region starts at 0: every radius is a speed
 * the costly trim passed (or 0 with has_pass = 0). Otherwise as
 * shol_envelope_run (out->n_trims and wall_s count every sweep). */
int shol_envelope_run_near(const shol_settings *s, const shol_result *cheap_result, shol_trim_fn cheap,
                           void *cheap_user, shol_trim_fn costly, void *costly_user, double margin_mps,
                           shol_progress_fn progress, void *progress_user, const core_log *log, shol_result *out,
                           core_err *err);

/* ---- a sweep dealt over several processes (part.c, docs/cluster.md)
 * Every direction's sweep depends on its own earlier trims only (the
 * caller's trim must keep it so: couple keeps a warm start per
 * direction), so a rank that sweeps the directions dealt to it makes the
 * same numbers as the serial run does for them, and the gathered envelope
 * is the serial one bit for bit. */
#define SHOL_MAX_RANKS 4096
/* The report texts a part carries (the caller's, e.g. its coupled points
 * and its fields as Markdown; NULL where none). */
#define SHOL_PART_TEXTS 2
/* mine = all with the directions dealt to rank of ranks (direction i of
 * all to rank i % ranks, in all's order): its number of directions (0:
 * none for this rank), or < 0 with err for a rank outside 0..ranks-1. */
int shol_settings_deal(const shol_settings *all, int rank, int ranks, shol_settings *mine, core_err *err);
/* Write rank's part into the folder stage (created if missing): its
 * one-way envelope r1, its two-way one r2 (NULL: one-way run), bands
 * included, and its texts (NULL: none), under key (the run's settings in
 * words: a part whose key differs is refused by the gather). Written
 * whole under a temporary name and renamed into place. 0, or < 0 with err. */
int shol_part_write(const char *stage, int rank, int ranks, const char *key, const shol_result *r1,
                    const shol_result *r2, const char *const texts[SHOL_PART_TEXTS], core_err *err);
/* Mark rank as failed with why (one line), so that rank 0 stops waiting
 * and names it. 0, or -1 if the mark cannot be written. */
int shol_part_fail(const char *stage, int rank, const char *why);
/* Rank 0: r1 and r2 (NULL: one-way) hold rank 0's own envelopes (the
 * directions dealt to it); wait up to timeout_s for every other rank's
 * part in stage and replace r1 and r2 by the whole envelopes over all, as
 * the serial run makes them (n_trims summed, wall_s the longest rank's).
 * texts (NULL: not wanted; else ranks * SHOL_PART_TEXTS pointers) gets
 * each other rank's texts at [rank * SHOL_PART_TEXTS + k] (malloc'd or
 * NULL; rank 0's are left alone). 0, or < 0 with err naming the rank that
 * failed, did not come in time or wrote a part of another run. */
int shol_part_gather(const char *stage, int ranks, const char *key, const shol_settings *all, double timeout_s,
                     shol_result *r1, shol_result *r2, char **texts, core_err *err);
/* Remove every rank's part (and failure mark) and the stage folder if empty. */
void shol_part_clean(const char *stage, int ranks);

/* How firmly a direction's limit is placed: the limiting criterion's
 * margin falls by slope_per_mps (rad per m/s for roll and pitch, percentage
 * points per m/s for a control) between the last passing speed and the
 * first failing one, so an error of ref_error in that quantity (0.25 deg
 * for an attitude, 1 % of travel for a control: the floors of the coupling
 * loop's 5 % convergence test) moves the limit by shift_mps = ref_error /
 * slope_per_mps. A slope of 0.2 deg of pitch per 5 km/h (CG-47 + UH-60A at
 * 30 deg) puts 6 km/h on each 0.25 deg: a limit no sharper than the trim
 * and the airwake behind it. */
typedef struct shol_sensitivity {
    int crit;             /* the limiting criterion (SHOL_CRIT_*) */
    int side;             /* +1: the quantity crossed its upper limit (above neutral: the
                             collective always), -1: its lower one (0: not defined) */
    double slope_per_mps; /* margin lost per m/s of wind, > 0 */
    double ref_error;     /* rad or percentage points */
    double shift_mps;     /* ref_error / slope_per_mps */
} shol_sensitivity;

/* Fill out for d. Returns 0, or 1 when it is not defined (no passing speed,
 * no failure, a failed trim or no criterion at the failure, or a margin
 * that did not fall between the two speeds), out->crit then
 * SHOL_LIMIT_NONE and the figures NAN. */
int shol_envelope_sensitivity(const shol_dir_result *d, shol_sensitivity *out);

/* What drives a direction's limit (docs/shol.md, "What drives
 * a limit"): the limiting quantity's budget, compared between the limiting
 * trim and a reference trim (the direction's lowest converged speed, the
 * calm hover of a sweep from 0). Each criterion belongs to a budget:
 *  - pedal: the yaw moment N about the CG (body axes); the tail rotor is
 *    the effector that the pedal moves;
 *  - longitudinal cyclic and pitch attitude / lateral cyclic and roll
 *    attitude: the pitch moment M / roll moment L (body axes); the main
 *    rotor is the effector (its hub moment and thrust offset, set by the
 *    cyclic and the disk's tilt to the shaft). The moments about the CG
 *    set the airframe's attitude, the forces where the rotor points
 *    (Seddon and Newman 2011, section 8.1); so an attitude's secondary
 *    budget is the horizontal force, longitudinal / lateral, in the ship's
 *    horizontal plane (ship axes, where the weight has no component);
 *  - collective: the vertical force (ship axes), main rotor effector; the
 *    rotors' power changes are given beside it.
 * In trim the budget sums to zero, so the effector's change balances the
 * sum of the others' changes; each other component's share of it is
 * share = -change / effector_change (the shares sum to 1 less the trim
 * residual's part, `closure`). The driver is the component with the
 * largest share. The budget cannot see a change in the effector's own
 * effectiveness (the tail rotor's inflow in a crosswind, the main rotor's
 * translational lift): that moves the control with no change in the
 * effector's load, which the effector's change relative to its reference
 * value (effector_ref) shows. */
enum {
    SHOL_BUDGET_X = 0, /* longitudinal force, ship axes (N) */
    SHOL_BUDGET_Y = 1, /* lateral force, ship axes (N) */
    SHOL_BUDGET_Z = 2, /* vertical force, ship axes, down + (N) */
    SHOL_BUDGET_L = 3, /* roll moment about the CG, body axes (N m) */
    SHOL_BUDGET_M = 4, /* pitch moment */
    SHOL_BUDGET_N = 5, /* yaw moment */
    SHOL_NBUDGET = 6
};
/* "x_force", "y_force", "z_force", "roll_moment", "pitch_moment",
 * "yaw_moment"; NULL if unknown. */
const char *shol_budget_name(int budget);
/* A criterion's budget (as above) and its secondary one (-1: none);
 * -1 when crit is not a criterion. */
int shol_crit_budget(int crit, int *secondary);

typedef struct shol_attribution {
    int crit;               /* the quantity attributed (SHOL_CRIT_*) */
    int at_limit;           /* 1: crit limited the direction and the trim is the first failure;
                               0: the closest criterion at the last pass (the limit was "trim" or
                               "none", or the failing trim had no loads) */
    int budget;             /* SHOL_BUDGET_* */
    int effector;           /* SHOL_COMP_MR or SHOL_COMP_TR */
    double ref_speed_mps;   /* the reference trim's WOD speed */
    double at_speed_mps;    /* the attributed trim's WOD speed */
    double control_ref, control_at; /* crit's value at both (rad or % of travel) */
    double value_ref[SHOL_NCOMP];   /* each component's budget term at the reference (N or N m) */
    double change[SHOL_NCOMP];      /* its change from the reference to the trim attributed */
    double effector_ref, effector_change;
    double share[SHOL_NCOMP];       /* -change / effector_change; NAN for the effector */
    double closure;         /* |sum of all changes| / |effector_change| (the trim residual's part) */
    int driver;             /* SHOL_COMP_* of the largest share */
    double mr_power_change_W, tr_power_change_W;
} shol_attribution;

/* Attribute d's limit in budget (-1: the criterion's primary budget).
 * Returns 0 and out filled, or 1 when it is not defined (no loads at the
 * trims, no trim other than the reference, an effector change below 1e-9
 * of the budget's largest term), out then with crit SHOL_LIMIT_NONE,
 * driver -1 and the figures NAN. */
int shol_envelope_attribution(const shol_dir_result *d, int budget, shol_attribution *out);
/* One line for a report: "yaw_moment: fin 94 % of the tail rotor's change
 * +6.36 kN m (-41.51 kN m at 0 km/h); pedal 20.6 to 26.1 %" (the
 * quantity's values at both trims with its primary budget only); "-" when
 * a is undefined (driver < 0). */
void shol_attribution_format(const shol_attribution *a, char *buf, size_t n);

/* ---------------------------------------------------- uncertainty bands */
/* The flight model's validated error, model minus reference, in each
 * criterion's quantity at one condition (the aircraft file's
 * [model_error], docs/aircraft-format.md; couple fills it from
 * hfm_aircraft_model_error). */
typedef struct shol_model_error {
    int valid;               /* 1: the aircraft states one; 0: not validated (err ignored) */
    double err[SHOL_NCRIT];  /* by shol_crit: rad for roll and pitch, percentage points of
                                travel for a control; NAN: that quantity not validated */
    char reference[SHOL_MODEL_REF_MAX]; /* what it was measured against and where, for the
                                           reports: "GenHel at 1 kt" */
} shol_model_error;
/* Not validated: valid 0, every error NAN, no reference. */
void shol_model_error_none(shol_model_error *m);
/* The limit's move for the model's error e in d's limiting quantity q
 * (m NULL or not valid: none): the truth is q - e, so where q crosses its
 * upper limit the truth's margin is the model's plus e, at a lower limit
 * the model's minus e, and the limit moves by side e / slope
 * (shol_envelope_sensitivity's secant slope and side): out (> 0) where the
 * truth is further from the limit. *crit_out: the limiting criterion
 * (-1 when the limit is none or trim), *err_out: its error (NAN: not
 * validated); either may be NULL. NAN when the error or the slope is not
 * there. */
double shol_band_model_shift(const shol_dir_result *d, const shol_model_error *m, int *crit_out,
                             double *err_out);

/* What the bands are made of. grid: the same envelope on another grid
 * level (its directions matched to r's within 1e-6 rad; a direction it
 * lacks has no second grid; one with no passing speed has V_g = 0), NULL
 * for none; grid_label names it ("default grid"). window: per direction
 * (window_dir_rad, matched within 1e-6 rad) the field's averaging-window
 * spread s as a fraction of the WOD speed (0 for a converged field, NAN
 * not known, a direction not listed not known). */
typedef struct shol_band_inputs {
    const shol_result *grid;
    /* NULL: the grid spread is grid's radius minus r's. Set: grid and
     * grid_base are one method on two grids (e.g. the one-way envelopes
     * under a two-way r), and the spread is grid's radius minus
     * grid_base's, applied to r's radius. */
    const shol_result *grid_base;
    const char *grid_label;
    int n_window;
    double window_dir_rad[SHOL_MAX_DIRS];
    double window_frac[SHOL_MAX_DIRS];
    /* the flight model's validated error (shol_model_error_none: not validated) */
    shol_model_error model;
    shol_band_rule rule;
} shol_band_inputs;
/* No grid, no window, the model not validated, the default rule. */
void shol_band_inputs_default(shol_band_inputs *in);
/* A field's window spread s from its solver state (cfd_result): 0 when it
 * converged; when it is the mean of its last iterations (averaged > 0),
 * the larger of mean_drift and mean_change (mean_change < 0: none came
 * before the window, mean_drift alone); NAN otherwise (the last iterate
 * of an unconverged run: its spread was not measured). */
double shol_band_window_frac(int converged, int averaged, double mean_drift, double mean_change);
/* Fill every direction's band (r->dirs[i].band), r->band_rule,
 * r->band_grid_label and r->band_model_label. Returns 0, or < 0 with err naming the direction and
 * the bad value (a window spread that is negative or infinite, a second
 * grid's (or grid_base's) radius that is not finite or negative, a rule
 * that is not > 0, a grid_base without grid,
 * n_window out of range); r is then unchanged. */
int shol_band_compute(shol_result *r, const shol_band_inputs *in, core_err *err);
/* The band of r->dirs[i]: its own when valid, else the sensitivity-only
 * band under r's rule (the default if none). */
void shol_band_get(const shol_result *r, int i, shol_band *out);
/* r's rule, the default where none was set. */
shol_band_rule shol_band_rule_of(const shol_result *r);
/* What makes a band, e.g. "grid +15.0 (default grid), window +-2.1,
 * 0.25 deg +-9.0, model +6.2 (pedal -4.27 % vs GenHel at 1 kt)" (km/h);
 * limit (the direction's) names the sensitivity's unit (0.25 deg for an
 * attitude, 1 % for a control). The model source reads "model: not
 * validated" where the aircraft states no error in the limiting quantity,
 * "model: not defined" where no criterion limits or the slope is not
 * there. */
void shol_band_format(const shol_band *b, const char *grid_label, int limit, char *buf, size_t n);
/* The model's error in words: "pedal -4.27 % vs GenHel at 1 kt" (without
 * " vs ..." where the band has no reference); "" when there is none. */
void shol_band_model_text(const shol_band *b, char *buf, size_t n);
/* The band's dominant source (widest) in words: "model (pedal -4.27 % vs
 * GenHel at 1 kt)" when it is the model, else its name ("grid", "window",
 * "sensitivity"; "-" for a band of width 0). */
void shol_band_dominant(const shol_band *b, char *buf, size_t n);
/* The name of a band source: "grid", "window", "sensitivity", "model";
 * "-" for -1. */
const char *shol_band_source_name(int src);

/* -------------------------------------------------------------- outputs */
/* Optional text and a second envelope for the report and plots. */
/* Physics checks of an envelope (shol/checks.c has the reasoning): largest
 * near the bow, smaller in crosswinds, the tail rotor's port/starboard
 * asymmetry (ccw_from_above: 1 for a main rotor turning counter-clockwise
 * seen from above, which should tolerate red winds better; 0 green), and
 * the limiting criteria named and mostly roll, pitch or pedal. */
#define SHOL_MAX_CHECKS 8
typedef struct shol_check {
    char name[96];
    int applicable, pass;
    char detail[160];
} shol_check;
typedef struct shol_checks {
    int n, passed, failed;
    shol_check c[SHOL_MAX_CHECKS];
} shol_checks;
int shol_checks_run(const shol_result *r, int ccw_from_above, shol_checks *out);

typedef struct shol_report_info {
    const char *title;         /* e.g. "CG-47 + UH-60A"; NULL: "Candidate SHOL" */
    const char *label;         /* name of the main envelope, e.g. "two-way coupled" */
    const char *scenario_path; /* settings listed in the report, each may be NULL */
    const char *aircraft_path;
    const char *grid;
    const char *coupling;
    /* A second result set on the same directions (e.g. one-way airwake):
     * drawn dashed on the plots and compared direction by direction in the
     * report. NULL: none. */
    const shol_result *compare;
    const char *compare_label; /* e.g. "one-way (ship-only airwake)" */
    /* Markdown the caller writes about the coupling iterations (histories
     * per direction and speed); NULL: the report says none was supplied. */
    const char *coupling_md;
    /* Markdown the caller writes about the airwake fields used (their
     * convergence); NULL: the report says none was supplied. */
    const char *fields_md;
    /* Physics checks of the main envelope to list in the report; NULL: none. */
    const shol_checks *checks;
    /* Markdown the caller adds after the settings (e.g. the replay's
     * recording judged by the criteria); NULL: none. */
    const char *notes_md;
} shol_report_info;

/* Each writer creates DIR if needed and writes through a temporary file
 * renamed into place, so a failure leaves no partial file. The plots
 * refuse (< 0, err naming the direction and field) a direction, a speed or
 * a converged trim (trim_status 0) that is not finite, in r or in
 * info->compare; an empty result gives an empty chart. */

/* DIR/shol.csv, one row per direction, columns exactly:
 * wod_dir_deg, max_speed_kt, max_speed_kmh, limit, margin_roll_deg,
 * margin_pitch_deg, margin_long_pct, margin_lat_pct, margin_coll_pct,
 * margin_pedal_pct, then the band (shol_band_get): band_lo_kmh,
 * band_hi_kmh, band_grid_kmh, band_window_kmh, band_sens_kmh (nan: not
 * measured), band_open_above, low_confidence (0 or 1), band_model_kmh
 * (signed; nan: not validated or not defined). A direction with no passing
 * speed has "nan" speeds and the margins at 0 m/s. */
int shol_write_csv(const char *dir, const shol_result *r, core_err *err);
/* Read a shol.csv back (directions, speeds, limits, margins, and the band
 * where the file has its columns: the first ten columns alone, and the
 * first seventeen (without band_model_kmh), are read too; no history,
 * settings default apart from the directions; the model's error behind
 * band_model_kmh is not in the file, model_err NAN). */
int shol_read_csv(const char *path, shol_result *r, core_err *err);
/* DIR/shol.json: settings, criteria and per direction the result and the
 * whole trim-versus-speed history. */
int shol_write_json(const char *dir, const shol_result *r, const shol_report_info *info,
                    core_err *err);
/* DIR/shol_polar.png and DIR/shol_polar.svg: the NATOPS-style polar plot
 * (bow up, starboard right, speed rings in knots, one closed line, each
 * direction's limiting criterion marked; info->compare dashed). */
int shol_plot_polar(const char *dir, const shol_result *r, const shol_report_info *info,
                    core_err *err);
/* DIR/shol_trim_<dir>.png per direction (e.g. shol_trim_red030.png):
 * roll, pitch and the four controls against WOD speed with the rejection
 * limits, like the seed paper's Figs. 16-20. */
int shol_plot_trim(const char *dir, const shol_result *r, const shol_report_info *info,
                   core_err *err);
/* File name (no folder) of the trim plot for a direction, e.g.
 * "shol_trim_green030.png", "shol_trim_head.png". */
void shol_trim_plot_name(double dir_rad, char *buf, size_t n);
/* DIR/report.md: settings, the plots, the envelope table, the coupling
 * histories and the comparison table. */
int shol_write_report(const char *dir, const shol_result *r, const shol_report_info *info,
                      core_err *err);
/* All of the above into DIR, whole or not at all: written to a staging
 * folder in DIR, then renamed into DIR once every file is written and no
 * target is a folder, a device or a FIFO; on a failure nothing is left. */
int shol_write_all(const char *dir, const shol_result *r, const shol_report_info *info,
                   core_err *err);

/* --------------------------------------------------- the flown envelope */
/* SHOL points from flown tasks (shol/flown.c): at each WOD point the
 * caller's fly callback flies the task (an automated pilot, ship motion,
 * turbulence) with one seed; the point's pass rate over n_seeds seeds
 * decides it. The criteria are judged at every step of the flown history
 * (shol_flown_track), not only at trim. See docs/shol.md, "The flown
 * envelope". */

/* How a flown history is judged. The criteria are the trim-based SHOL's
 * STEADY limits: with window_s > 0 they judge the running mean of each
 * quantity over the last window_s seconds of the task's phase (never
 * across a phase boundary), from the time the phase has lasted window_s
 * (a phase that ends sooner is judged on its whole mean as it ends);
 * TRANSIENT criteria judge every step's instantaneous values: a control
 * at its stop (0 or 100 %), a roll or pitch beyond its steady limit times
 * 1 + transient_frac. window_s = 0 judges the steady limits at every step
 * on the instantaneous values and no transient criterion. docs/shol.md
 * gives the defaults' reasons. */
typedef struct shol_flown_judge {
    double window_s;             /* 3 s; 0 to 60 */
    double transient_frac;       /* 0.5 (roll 7.5 deg, pitch 12 deg by default); 0 to 10 */
} shol_flown_judge;
void shol_flown_judge_default(shol_flown_judge *j);
/* < 0 with err naming the field. */
int shol_flown_judge_check(const shol_flown_judge *j, core_err *err);

/* How a flight's first exceedance was judged (shol_flown_track.first_kind). */
enum {
    SHOL_JUDGE_STEP = 0,      /* a steady limit on the step's value (window_s = 0): "pitch in hover" */
    SHOL_JUDGE_MEAN = 1,      /* a steady limit on the running mean: "pitch (3 s mean) in hover" */
    SHOL_JUDGE_TRANSIENT = 2, /* an attitude past the transient limit: "pitch (transient) in hover" */
    SHOL_JUDGE_STOP = 3       /* a control at its stop: "long_cyclic at stop in hover" */
};

/* The running mean's bins: a phase's time is cut into bins of
 * window_s / SHOL_FLOWN_BINS; the mean is over the samples of the last
 * SHOL_FLOWN_BINS bins (the current one partly filled), a window between
 * window_s (1 - 1 / SHOL_FLOWN_BINS) and window_s long. */
#define SHOL_FLOWN_BINS 100

/* The worst of the criteria over a flown history. */
typedef struct shol_flown_track {
    shol_criteria criteria;
    shol_flown_judge judge;
    double min_frac[SHOL_NCRIT]; /* smallest margin of the step's values over the history as a
                                    fraction of its allowed displacement (shol_criteria_half_band: 1
                                    at neutral, the collective full down; < 0 exceeded) */
    double min_t_s[SHOL_NCRIT];  /* when */
    double min_mean_frac[SHOL_NCRIT]; /* the same for the running means judged (INFINITY: none) */
    int first_crit;              /* the first criterion exceeded (SHOL_LIMIT_NONE: none) */
    int first_kind;              /* how (SHOL_JUDGE_*) */
    double first_t_s;
    char first_phase[32];        /* the task's phase then ("hover", "descent", ...) */
    long n_steps, n_bad;         /* steps judged; steps not finite */
    /* the running mean (private) */
    char phase[32];              /* the phase being averaged (a task's names are at most 31) */
    double phase_t0_s, last_t_s;
    int judged;                  /* its mean has been judged (the phase has lasted window_s) */
    long bin;                    /* the current bin's index from the phase's start */
    double sum[SHOL_FLOWN_BINS][SHOL_NCRIT];
    long count[SHOL_FLOWN_BINS];
} shol_flown_track;
/* j NULL: shol_flown_judge_default. */
void shol_flown_track_init(shol_flown_track *t, const shol_criteria *c, const shol_flown_judge *j);
/* Judge one step's attitudes and controls (p) in phase at t_s (steps in
 * time order). Returns 1 when a criterion is exceeded at this step (or the
 * previous phase, shorter than the window, is exceeded on its mean as it
 * ends here), 0 when none, -1 when p is not finite (counted in n_bad). */
int shol_flown_track_step(shol_flown_track *t, double t_s, const char *phase, const shol_trim_point *p);
/* The history ends (touchdown, the task's end): a phase shorter than the
 * window is judged on its mean. 1 when exceeded, else 0. */
int shol_flown_track_end(shol_flown_track *t);
/* The cause of the first exceedance ("pitch (3 s mean) in hover",
 * "pitch (transient) in descent", "long_cyclic at stop in hover", "roll in
 * hover"), "" when none. */
void shol_flown_track_cause(const shol_flown_track *t, char *buf, size_t n);

/* One flight: what the fly callback fills. */
#define SHOL_CAUSE_MAX 96
typedef struct shol_flight {
    int pass;                    /* 1: nothing exceeded, touchdown and tolerances met */
    /* Why it failed ("" when it passed): a criterion as
     * shol_flown_track_cause names it (e.g. "roll (3 s mean) in descent",
     * "pitch (transient) in hover", "pedal at stop in hover"; "roll in
     * descent" with window_s 0), "touchdown sink", "touchdown position",
     * "adequate tolerance: position|height|heading|time", "no touchdown",
     * "could not track" (the replay pilot's distance from its recording),
     * "crash: <what hit what>", "no trim". */
    char cause[SHOL_CAUSE_MAX];
    double flown_s;              /* simulated time flown */
    double sink_mps, dist_m;     /* at touchdown (NAN: none) */
    int grade;                   /* the task's grade: 2 desired, 1 adequate, 0 not met */
    /* The replay pilot's tracking error: the flown CG's distance from the
     * recorded run at the same time, rms and max over the flight (m);
     * NAN for a pilot without a recording. It is judged apart from the
     * criteria: "could not track" is the cause only where the max exceeds
     * the replay's tolerance and nothing came first. */
    double track_rms_m, track_max_m;
    int tracked;                 /* 1: track_max_m within the replay's tolerance, 0: not, -1: no recording */
    shol_flown_track track;
} shol_flight;

/* Fly the task at the WOD (speed, direction) with seed. 0 when flown (out
 * filled, pass or not), > 0 when it could not start (no trim: out->cause
 * "no trim", a rejection), < 0 on a fatal error (the sweep stops). */
typedef int (*shol_fly_fn)(void *user, double wod_speed_mps, double wod_dir_rad, unsigned long long seed,
                           shol_flight *out);

#define SHOL_FLOWN_MAX_SEEDS 64
/* The pass rate's interval: the Wilson score interval (Wilson 1927, JASA
 * 22(158)) at 90 % two-sided, z the normal's 95th percentile. */
#define SHOL_WILSON_Z90 1.6448536269514722
/* The Wilson score interval of n_pass passes in n flights at z: *lo, *hi
 * in [0, 1] (0, 1 when n < 1). */
void shol_wilson(int n_pass, int n, double z, double *lo, double *hi);
/* A point's verdict from its interval (shol_flown_point.verdict). */
enum {
    SHOL_VERDICT_FAIL = -1,      /* clearly fails: the interval's upper bound is below the threshold */
    SHOL_VERDICT_UNDECIDED = 0,  /* the interval holds the threshold */
    SHOL_VERDICT_PASS = 1        /* clearly passes: its lower bound clears the threshold */
};
/* The verdict of an interval [lo, hi] against threshold thr. */
int shol_flown_verdict(double lo, double hi, double thr);
/* "clear_pass", "undecided", "clear_fail". */
const char *shol_flown_verdict_name(int verdict);
typedef struct shol_flown_settings {
    int n_seeds;                 /* flights per point, seeds seed0 .. seed0 + n - 1 (1..64; default 11:
                                    the fewest of at least 10 at which a point can clearly pass) */
    unsigned long long seed0;    /* 1 */
    double pass_rate_min;        /* a point passes when its pass rate is >= this (0.8: 9 of 11) */
    int start_steps_below;       /* the search starts this many speed steps below the trim
                                    envelope's radius (2) */
    double bisect_tol_mps;       /* > 0: bisect [last pass, first failure] to this width; 0 off */
    shol_flown_judge judge;      /* how the fly callback judges a flight (it applies it; the
                                    outputs record it) */
} shol_flown_settings;
void shol_flown_settings_default(shol_flown_settings *s);
/* < 0 with err naming the field. */
int shol_flown_settings_check(const shol_flown_settings *s, core_err *err);

/* One WOD point: its flights' tally. */
typedef struct shol_flown_point {
    double speed_mps;
    int n_flights, n_pass;
    double pass_rate;            /* n_pass / n_flights */
    int pass;                    /* pass_rate >= pass_rate_min */
    char cause[SHOL_CAUSE_MAX];  /* the most frequent cause of the failed flights ("" none) */
    int n_cause;                 /* flights that failed with it */
    double flown_s;
    double rate_lo, rate_hi;     /* the pass rate's 90 % Wilson interval (shol_wilson) */
    int verdict;                 /* SHOL_VERDICT_* of [rate_lo, rate_hi] against pass_rate_min */
    double track_rms_m, track_max_m; /* the flights' tracking error (shol_flight): the rms of their
                                        rms, the largest max; NAN where no flight has one */
    int n_tracked;               /* flights whose tracking stayed within the replay's tolerance,
                                    whatever their cause (-1: no flight has a recording) */
} shol_flown_point;

typedef struct shol_flown_dir {
    double dir_rad;
    double trim_max_speed_mps;   /* the trim envelope's radius here (0 if it had no pass) */
    int trim_has_pass, trim_limit;
    int has_pass;                /* 0: even the lowest speed flown failed */
    double max_speed_mps;        /* the last passing speed (0 if !has_pass) */
    double fail_speed_mps;       /* the lowest failing speed flown, NAN if none */
    double pass_rate_max, pass_rate_fail; /* at those two (NAN when absent) */
    char cause[SHOL_CAUSE_MAX];  /* at fail_speed_mps ("none" when nothing failed) */
    /* The limit's band from the pass rate's interval, below the lowest
     * speed that clearly fails: the highest flown speed whose Wilson lower
     * bound clears pass_rate_min (NAN: none) to the highest whose upper
     * bound does (NAN: none); open above when no point flown clearly
     * fails. */
    double rate_band_lo_mps, rate_band_hi_mps;
    int rate_band_open_above;
    /* The air over the spot at the rotor hub, from the direction's field
     * (the caller fills them; NAN: not known): mean speed and turbulence
     * intensity sqrt(2k/3), each a fraction of the WOD speed. */
    double hub_speed_frac, hub_ti_frac;
    int n_points;                /* flown points, by speed */
    shol_flown_point *points;
    shol_band band;              /* shol_flown_band, filled by shol_flown_run and shol_flown_bands_update */
} shol_flown_dir;

typedef struct shol_flown_result {
    shol_flown_settings flown;
    double speed_step_mps, speed_max_mps; /* the trim sweep's, used for the search */
    int n_dirs;
    shol_flown_dir *dirs;        /* the trim result's directions, in its order */
    int n_flights;
    double flown_s, wall_s;      /* simulated and wall time of the whole run */
} shol_flown_result;
void shol_flown_result_free(shol_flown_result *r);

/* The flown procedure, per direction of trim (the trim-based envelope,
 * whose settings give the speed step and maximum): start at the speed
 * grid point start_steps_below steps below the trim radius (at least 0);
 * unless that point clearly passes, step down until one does or 0 is
 * flown; unless it clearly fails, step up by the speed step until one
 * does or speed_max is passed; the limit is the highest passing speed
 * below the lowest clear failure; then optionally bisect between it and
 * the lowest failing speed above it. Points below the lowest flown speed
 * are taken as passing (not flown). progress (n_trims counts flights) and
 * log may be NULL. 0 and out filled, or < 0 with err (a fatal callback
 * error names the direction, speed and seed). */
int shol_flown_run(const shol_flown_settings *s, const shol_result *trim, shol_fly_fn fly, void *fly_user,
                   shol_progress_fn progress, void *progress_user, const core_log *log, shol_flown_result *out,
                   core_err *err);

/* The flown envelope as a shol_result (radii, NAN-free), for the physics
 * checks: a cause that names a criterion maps to it, any other to
 * SHOL_LIMIT_TRIM, none to SHOL_LIMIT_NONE. Free with shol_result_free. */
int shol_flown_as_result(const shol_flown_result *f, const shol_result *trim, shol_result *out, core_err *err);

/* Outputs of the flown envelope into DIR (atomic, as the trim ones):
 * shol_flown.csv, one row per direction, columns exactly: wod_dir_deg,
 * max_speed_kt, max_speed_kmh, pass_rate_at_max, fail_speed_kt,
 * pass_rate_at_fail, cause, trim_max_speed_kt, trim_limit, then the
 * flown band's eight columns as in shol.csv, then rate_band_lo_kmh,
 * rate_band_hi_kmh, rate_band_open_above (the pass rate's band);
 * shol_flown_points.csv, one row per flown point: wod_dir_deg, speed_kt,
 * speed_kmh, flights, passed, pass_rate, pass, cause, pass_rate_lo,
 * pass_rate_hi, verdict, track_rms_m, track_max_m (nan where none),
 * tracked (flights within the replay's tolerance; empty without one);
 * shol_flown.json (the settings and every point). */
int shol_flown_write_csv(const char *dir, const shol_flown_result *f, core_err *err);
int shol_flown_write_json(const char *dir, const shol_flown_result *f, const shol_report_info *info, core_err *err);
/* DIR/shol_polar_flown.png and .svg: the trim envelope (dashed) and the
 * flown one (solid) in one polar plot, each flown point a dot coloured by
 * its pass rate, each direction's flown cause at its first failure. */
int shol_flown_plot_polar(const char *dir, const shol_flown_result *f, const shol_result *trim,
                          const shol_report_info *info, core_err *err);
/* DIR/report.md: the settings, the plot, the flown envelope against the
 * trim-based one direction by direction, every point's pass rate and cause. */
int shol_flown_write_report(const char *dir, const shol_flown_result *f, const shol_result *trim,
                            const shol_report_info *info, core_err *err);
/* The band of the flown envelope's direction i (shol_band): the
 * trim envelope's sources carried to the flown radius V_f, as what the
 * project measures of the air the flights fly: the trim's grid spread
 * (grid_mps, the same signed shift), its window spread s (window_frac)
 * as +- s V_f, its 0.25 deg / 1 % shift, and its model shift (model_mps,
 * the same signed shift, with its quantity and error). Open
 * above where no flown point failed; the rule is the trim result's.
 * Without a trim direction (or trim NULL) every source is absent. */
void shol_flown_band(const shol_flown_result *f, const shol_result *trim, int i, shol_band *out);
/* Every direction's band (f->dirs[i].band) from trim's, again: after the
 * trim envelope's bands were computed or changed (shol_band_compute). */
void shol_flown_bands_update(shol_flown_result *f, const shol_result *trim);

/* All four, whole or not at all (as shol_write_all). */
int shol_flown_write_all(const char *dir, const shol_flown_result *f, const shol_result *trim,
                         const shol_report_info *info, core_err *err);

#ifdef __cplusplus
}
#endif
#endif
