/*
 * sim.h -- the simulation layer: scenario files (and, in later work, the
 * fixed-rate flight loop, ship motion, deck contact and LCM stations).
 *
 * A scenario (INI, see scenarios/README.md) names the ship-aircraft
 * combination, the WOD or WOD sweep, the hover-over-spot station of the
 * SHOL task, CFD settings and the output folder, and for disim fly the sea,
 * the pilot and the piloted task. Paths inside are relative to the file.
 * Every key it accepts acts; the keys of later work (the OpenFOAM engine,
 * ...) are refused.
 */
#ifndef DISIM_SIM_H
#define DISIM_SIM_H

#include "core.h"
#include "hfm.h"

#include <stdio.h>
#include <time.h>

#ifdef __cplusplus
extern "C" {
#endif

#define SIM_PATH_MAX 512
#define SIM_MAX_WOD 128

typedef enum { SIM_WOD_SINGLE = 0, SIM_WOD_SWEEP = 1 } sim_wod_mode;

/* A piloted task's kind: a task file's (station_keep, land) and a
 * scenario's [task] type (hover: station keeping, landing: land; shol:
 * the trims of disim shol, no task file). */
enum { SIM_TASK_SHOL = -1, SIM_TASK_STATION_KEEP = 0, SIM_TASK_LAND = 1 };

/* The sea (sim/ship_motion.c has the model) */
#define SIM_SEA_MAX_STATE 6
#define SIM_SEA_DEFAULT_WAVES 256
#define SIM_SEA_MAX_WAVES 4096

typedef enum { SIM_SPECTRUM_ITTC = 0, SIM_SPECTRUM_JONSWAP = 1 } sim_spectrum;

/* The sea and the ship's steady course through it: plain data. */
typedef struct sim_sea {
    int state;             /* sea state 0 (calm: the ship still) to 6 */
    double ship_speed_mps; /* the ship's speed through the water, >= 0 */
    double wave_dir_rad;   /* heading to the waves: where they come FROM,
                              from the bow, + to starboard (as WOD):
                              0 head seas, pi/2 beam seas from starboard,
                              pi following seas */
    double course_rad;     /* the ship's mean heading in E (0: north) */
    sim_spectrum spectrum; /* ITTC (Bretschneider) or JONSWAP (gamma 3.3) */
    int n_waves;           /* sinusoids in the sum; 0: SIM_SEA_DEFAULT_WAVES */
} sim_sea;

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

    /* [sea] (disim fly: the ship's motion; disim shol refuses state > 0):
     * state, ship_speed_mps, wave_dir_rad, spectrum; course_rad 0 (north),
     * n_waves 0 (the default) */
    sim_sea sea;
    int turbulence;         /* [wod] turbulence (disim fly): 1 the field's turbulence */

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

    /* [task] type and the piloted task's file (disim fly: the automated
     * pilot flies it; scenarios/README.md) */
    int task_type;                 /* SIM_TASK_*: [task] type shol, hover (STATION_KEEP) or landing (LAND) */
    char task_path[SIM_PATH_MAX];  /* hover, landing: a task file (sim_task_load_ship) */
    /* [pilot] (disim fly; its flags override) */
    int pilot;                     /* SIM_SC_PILOT_* (station, the default) */
    char pilot_stations[SIM_PATH_MAX]; /* station: the priority list "A,B" ("" none) */
    double pilot_hold_after_s;     /* station: 0 (absent) or the hold time */
    char pilot_log[SIM_PATH_MAX];  /* replay: the recorded run's LCM log */
    int pilot_feed_controls;       /* replay: its controls fed forward too */
    /* [flown] (disim shol --method pilot; shol_flown_judge): NAN when absent */
    double flown_window_s;         /* window_s: the steady criteria's running mean (s) */
    double flown_transient_frac;   /* transient_frac: the transient attitude limits' margin */
} sim_scenario;
enum { SIM_SC_PILOT_STATION = 0, SIM_SC_PILOT_AUTO = 1, SIM_SC_PILOT_REPLAY = 2 };

/* Parse and resolve a scenario file. Returns 0, or < 0 with err naming the
 * file, line, key and what was expected (unknown keys and sections, wrong
 * types, values out of range, missing files, errors in referenced files), or
 * why a key no command acts on yet is refused ([task] approach_dir_deg,
 * [cfd] engine = openfoam, [cfd] residual_tol, [output] csv|plots; a key
 * of a mode not chosen; rotor = off with the two-way coupling; a piloted
 * task without the automated pilot). */
int sim_scenario_load(const char *path, sim_scenario *sc, core_err *err);

/* Print the resolved configuration as INI-like text. */
void sim_scenario_print(const sim_scenario *sc, FILE *out);

/* ------------------------------------------------ the ship's frame (flight) */
/* The ship frame S in the Earth frame E at one instant: its origin (the
 * landing spot on the deck), the rotation C_ES (row major, v_E = C_ES v_S)
 * and the ship's mean velocity (its steady translation, which the airwake
 * is relative to). */
typedef struct sim_ship_frame {
    double origin_E_m[3];
    double C_ES[9];
    double mean_vel_E_mps[3];
} sim_ship_frame;
/* The ship's frame at t_s (a pure function of t_s: the loop stays
 * deterministic). Returns 0, or non-zero when it cannot be had. */
typedef int (*sim_ship_frame_fn)(void *user, double t_s, sim_ship_frame *out);

/* The ship stage's frames (sim/ship_frame.c): S at the step times k h of
 * the steps around the one under way, step - 1 .. step + 2 (what the
 * gear's central differences reach from the step's start to its end),
 * computed once per step; a time between two step times is interpolated
 * between theirs. Plain data: zero it before the first advance. */
#define SIM_SHIP_FRAMES 4
typedef struct sim_ship_frames {
    double h_s;                         /* the step */
    long step;                          /* the step under way: fr[i] at (step - 1 + i) h */
    int n;                              /* frames held: 0 or SIM_SHIP_FRAMES */
    sim_ship_frame fr[SIM_SHIP_FRAMES];
} sim_ship_frames;
/* Move fs to the step `step` of h_s, the frames it held kept, the rest
 * from frame. 0, or non-zero as frame (fs then holds none). */
int sim_ship_frames_advance(sim_ship_frames *fs, sim_ship_frame_fn frame, void *user, double h_s, long step);
/* The frame at t_s: a step time's own, or interpolated linearly between
 * the two around it. 0, or -1 for a time outside the frames held. */
int sim_ship_frames_at(const sim_ship_frames *fs, double t_s, sim_ship_frame *fr);
/* sim_ship_frames_at as a sim_ship_frame_fn (user: a const sim_ship_frames *). */
int sim_ship_frames_fn(void *user, double t_s, sim_ship_frame *fr);
/* The deck's motion at one instant, the gear's input: S's frame and its
 * velocities in E, by central differences of the frame over 1e-4 s. */
typedef struct sim_ship_deck {
    sim_ship_frame fr;
    double vel_E_mps[3];     /* S's origin */
    double omega_E_radps[3]; /* S's angular velocity */
} sim_ship_deck;
/* The deck at t_s from frame. 0, or non-zero as frame. */
int sim_ship_deck_at(sim_ship_frame_fn frame, void *user, double t_s, sim_ship_deck *d);
/* S still and level at E's origin. */
void sim_ship_deck_still(sim_ship_deck *d);

/* ---------------------------------------------------- the air (sim/air.c) */
/* The air in E that the flight model meets: the ship-only airwake field
 * attached to the ship, scaled to the WOD speed, the log-law free stream
 * outside it (or with no field), a newly offered field blended in over
 * blend_s. See sim/air.c for the model. */
struct cfd_field;
typedef struct sim_air sim_air;
typedef struct sim_air_opts {
    double wod_speed_mps, wod_dir_rad; /* the WOD at anemometer height */
    double anemometer_height_m;        /* above the sea (20 m) */
    double deck_height_m;              /* S's origin above the waterline */
    double z0_m;                       /* sea-surface roughness (2e-4 m) */
    double blend_s;                    /* a new field's blend time (3 s) */
} sim_air_opts;
void sim_air_opts_default(sim_air_opts *o);
sim_air *sim_air_create(const sim_air_opts *o, core_err *err);
void sim_air_destroy(sim_air *a);
/* Fly the ship-only field f (NULL: the free stream) from t_s on, blended
 * from the air before over blend_s. f must outlive its use (this call and
 * the next). 0, or < 0 with err for a field that is not ship-only. */
int sim_air_set_field(sim_air *a, const struct cfd_field *f, double t_s, core_err *err);
/* What the air adds to the field's mean air, given with every sample:
 * the gusts of the frozen turbulence (sim/turbulence.c) and the coupled
 * rotor interaction near the station (sim/interaction.c); NULL: none. */
struct sim_turb;
struct sim_interaction;
typedef struct sim_air_in {
    const struct sim_turb *turb;
    const struct sim_interaction *inter;
} sim_air_in;
/* The air at a point of S (m/s, S, relative to the ship's mean motion),
 * in's interaction and gusts included (in NULL: none). Returns 1 where it
 * is the free stream, 0 inside the field. */
int sim_air_sample_S(const sim_air *a, const sim_air_in *in, const double p_S[3], double t_s, double v_S[3]);
/* The field's mean air alone (no interaction, no gust) and its k
 * (m^2/s^2) and epsilon (m^2/s^3) there, scaled to the WOD speed (0 in
 * the free stream); k and eps may be NULL. Returns as sim_air_sample_S. */
int sim_air_mean_S(const sim_air *a, const double p_S[3], double t_s, double v_S[3], double *k_m2ps2,
                   double *eps_m2ps3);
/* The air at a point of E at t_s, the ship's frame there being fr
 * (sim_air_sample_S carried into E). */
void sim_air_sample_E(const sim_air *a, const sim_air_in *in, const sim_ship_frame *fr, const double pos_E_m[3],
                      double t_s, double vel_E_mps[3]);
/* The weight of the newest field at t_s, 0 to 1 (1: no blend under way). */
double sim_air_blend(const sim_air *a, double t_s);
/* SIM_AIR_INTERACTION: the coupled rotor interaction inter is flown now
 * (its weight above 0, sim/interaction.c); without it, the ship-only air
 * alone. inter may be NULL. */
enum { SIM_AIR_FREE_STREAM = 1u, SIM_AIR_BLENDING = 2u, SIM_AIR_INTERACTION = 4u };
unsigned sim_air_flags(const sim_air *a, const struct sim_interaction *inter, double t_s);

/* ---------------------------------------------- the flight (sim/flight.c) */
/* The deterministic flight step (see sim/flight.c): pilot input -> ship ->
 * air -> flight model -> external loads -> outputs, at a fixed rate, with
 * no clock, socket or print inside. */
typedef struct sim_flight sim_flight;
typedef struct sim_flight_opts {
    double rate_hz;          /* the step rate (200) */
    double wod_speed_mps, wod_dir_rad;
    double ship_speed_mps;   /* the ship's steady speed, heading north (0) */
    double station_S_m[3];   /* the start: a trimmed hover with the CG here */
    double blend_s;          /* a field offered in flight blends in over this (3 s) */
    int turbulence;          /* 1 (default): the field's turbulence (sim/turbulence.c) */
    unsigned long long seed; /* the turbulence's seed (the ship motion has its own) */
    int sas;                 /* the stability augmentation (sim/sas.c) at the start: 1 on, 0 off,
                                -1 (default) as the aircraft file's [sas] engaged */
    int gear;                /* 1: the aircraft file's [gear] on the ship's deck (sim/contact.c),
                                owned by the flight; 0 (default): none */
    int start;               /* SIM_START_HOVER (default): the trimmed hover at the station;
                                SIM_START_DECK: standing on the deck (needs gear) */
    double start_heading_rad;/* SIM_START_DECK: the heading from the bow (0) */
    struct sim_interaction *interaction; /* NULL (default); else the coupled rotor interaction
                                the air adds near the station, the start's trim included, its
                                rotor set each step (sim/interaction.c); kept by the caller */
} sim_flight_opts;
/* The deck start: the CG over (station_S_m x, y), every wheel on the deck
 * at its static compression, the body moving with the deck, collective
 * full down, cyclic and pedals centred, the rotor at its speed with no
 * flapping and no inflow (they settle within the first second). */
enum { SIM_START_HOVER = 0, SIM_START_DECK = 1 };
void sim_flight_opts_default(sim_flight_opts *o);

/* The pilot's input to one step: the controls (percent of travel), or
 * hold = 1 to keep the last ones (e.g. a silent station). */
typedef struct sim_flight_inputs {
    double collective_pct, long_pct, lat_pct, pedal_pct;
    int hold;
} sim_flight_inputs;

/* The outputs of a step (plain data). */
typedef struct sim_flight_out {
    double t_s;
    long step;
    double pos_E_m[3], vel_E_mps[3], euler_E_rad[3], rate_B_radps[3];
    double pos_S_m[3];       /* the CG in the ship frame */
    double vel_S_mps[3];     /* relative to the ship's mean motion, in S */
    double collective_pct, long_pct, lat_pct, pedal_pct;
    double airspeed_mps;     /* at the fuselage reference */
    sim_ship_frame ship;
    unsigned air_flags;      /* SIM_AIR_* */
    double rotor_thrust_N, rotor_power_W; /* the main rotor's (hfm_tsim_rotor) */
    /* the gear (opts.gear; all 0 without): each leg's deck loads, the
     * contact's SIM_CONTACT_* flags (kept once set) and what they say */
    int nlegs, on_deck;
    double gear_load_N[HFM_GEAR_MAX_LEGS];        /* along the deck normal */
    double gear_friction_N[HFM_GEAR_MAX_LEGS][2]; /* in the deck plane, S x and y */
    unsigned contact_flags;
    char contact_what[160];
} sim_flight_out;

/* A flight of aircraft ac (kept by the caller) over ship (copied), its
 * ship frame from frame (NULL: the ship steady at ship_speed_mps, its S
 * level). The air starts as field (NULL: the free stream). Trims the hover
 * at the station in that air and starts there at t = 0. NULL with err (a
 * trim that does not converge is an error naming the station). */
sim_flight *sim_flight_create(const hfm_aircraft *ac, const core_ship *ship, const sim_flight_opts *o,
                              sim_ship_frame_fn frame, void *frame_user, const struct cfd_field *field,
                              const core_log *log, core_err *err);
void sim_flight_destroy(sim_flight *f);
/* The trimmed start's controls (for a pilot that holds them). */
void sim_flight_trim_inputs(const sim_flight *f, sim_flight_inputs *in);
/* External loads on the airframe (hfm_ext_fn; the landing gear): NULL for none. */
void sim_flight_set_external(sim_flight *f, hfm_ext_fn fn, void *user);
/* Offer a better field from the next step on (blended in). 0 or < 0. */
int sim_flight_set_field(sim_flight *f, const struct cfd_field *field, core_err *err);
/* One step of 1 / rate_hz: 0; 1 when the step ended the flight, a crash on
 * the ship or a roll-over on the deck (err says what hit what; the flight
 * steps no further and every later call returns 1); or < 0 (the
 * integrator failed) with err. */
int sim_flight_step(sim_flight *f, const sim_flight_inputs *in, sim_flight_out *out, core_err *err);
/* The state at the current time without stepping. */
void sim_flight_state(const sim_flight *f, sim_flight_out *out);

/* ------------------------------------------------ pacing (sim/pacing.c) */
/* The loop's clock: absolute deadlines every 1 / rate_hz (realtime 1), or
 * none (0: as fast as it can); overruns counted, step times kept. */
typedef struct sim_pacer sim_pacer;
typedef struct sim_pacer_stats {
    long steps, overruns;
    double wall_s, sim_s, rate_hz, realtime_factor;
    double step_p50_s, step_p99_s, step_max_s; /* the work of a step (between waits) */
    double late_p99_s, late_max_s; /* real time: how late the wake-ups came after their deadlines (jitter) */
} sim_pacer_report;
/* The pacer's clock: now (the time, on a clock that never steps back) and
 * sleep_until (back at or after the deadline), both with user. The
 * default (sim_pacer_opts_default) is CLOCK_MONOTONIC and clock_nanosleep
 * on absolute deadlines; a test injects a clock of its own. */
typedef struct sim_pacer_clock {
    void (*now)(void *user, struct timespec *t);
    void (*sleep_until)(void *user, const struct timespec *deadline);
    void *user;
} sim_pacer_clock;
typedef struct sim_pacer_opts {
    double rate_hz;        /* steps per second (1 to 100000) */
    int realtime;          /* 1: paced on deadlines, 0: as fast as it can */
    sim_pacer_clock clock; /* CLOCK_MONOTONIC (both functions NULL: the default) */
} sim_pacer_opts;
void sim_pacer_opts_default(sim_pacer_opts *o);
sim_pacer *sim_pacer_create_opts(const sim_pacer_opts *o, core_err *err);
/* sim_pacer_create_opts with the default clock. */
sim_pacer *sim_pacer_create(double rate_hz, int realtime, core_err *err);
void sim_pacer_destroy(sim_pacer *p);
/* Call once per step after its work: sleeps to the next deadline (real
 * time). Returns 1 when the step overran its deadline, 0 otherwise. */
int sim_pacer_wait(sim_pacer *p);
void sim_pacer_stats(const sim_pacer *p, sim_pacer_report *s);
/* Ask the system for what a real-time loop wants: SCHED_FIFO at priority
 * (1-99) and all memory locked (no page faults mid-step). Returns bit 0
 * set when the scheduling was granted, bit 1 when the memory was locked;
 * what says which, and why not (e.g. not permitted for this user). */
int sim_pacer_os_realtime(int priority, char *what, size_t n);

/* ------------------------------------- ship motion (sim/ship_motion.c) */
/* The ship's motion in a long-crested irregular sea (see sim/ship_motion.c
 * for the model and its references): sea states 0-6 of Bales (1983), an
 * ITTC or JONSWAP spectrum sampled into a seeded sum of sinusoids at the
 * encounter frequency, heave and pitch from the closed forms of Jensen,
 * Mansour and Olsen (2004), roll as one degree of freedom with the ship
 * file's natural period and damping. A pure function of time: the same
 * ship, sea and seed give the same motion bit for bit, at any t. */
#include <stdint.h>

/* Sea state 0 calm, in SIM_SPECTRUM_ITTC, everything else 0. */
void sim_sea_default(sim_sea *sea);
/* The significant wave height (m) and modal (peak) period (s) of a sea
 * state: Bales (1983) North Atlantic, the most probable modal period (state
 * 1: see sim/ship_motion.c). 0, or < 0 with err for a state out of 0-6. */
int sim_sea_state_table(int state, double *hs_m, double *tp_s, core_err *err);

typedef struct sim_ship_motion sim_ship_motion;

/* The ship's state at one instant (plain data). The pose is that of S (its
 * origin the landing spot) in E; E's origin is S's mean position at t = 0. */
typedef struct sim_ship_state {
    double t_s;
    core_pose pose;            /* S origin in E and q_ES */
    core_euler att;            /* S relative to E, 3-2-1 */
    core_vec3 vel_E_mps;       /* of S's origin */
    core_vec3 omega_S_radps;   /* angular velocity of S relative to E, in S */
    double heave_m, heave_rate_mps; /* the motion centre's, up positive */
    double wave_elev_m;        /* the sea surface at the motion centre's mean
                                  position, up positive */
} sim_ship_state;

/* A point fixed to the ship (e.g. the landing spot), in E. */
typedef struct sim_ship_point {
    core_vec3 pos_E_m, vel_E_mps, acc_E_mps2;
} sim_ship_point;

/* What a motion was built from (plain data). */
typedef struct sim_ship_motion_info {
    double hs_m, tp_s;         /* the sea state's */
    int n_waves;               /* 0 at sea state 0 */
    double omega_max_radps;    /* the spectrum's cut-off (above: 0) */
    double centre_S_m[3];      /* the motion centre (midships, waterline) in S */
    double roll_period_s, roll_damping_ratio;
} sim_ship_motion_info;

/* The motion of ship (its seakeeping keys are needed at a sea state above
 * 0) in sea, its phases and frequencies drawn from seed. NULL with err
 * naming the field or the missing [ship] key and what was expected. */
sim_ship_motion *sim_ship_motion_create(const core_ship *ship, const sim_sea *sea, uint64_t seed,
                                        core_err *err);
void sim_ship_motion_destroy(sim_ship_motion *m);
/* The state at t_s (any finite time). 0, or -1 for a NULL or t not finite. */
int sim_ship_motion_at(const sim_ship_motion *m, double t_s, sim_ship_state *out);
/* The position, velocity and acceleration in E at t_s of the point p_S_m
 * fixed to the ship (S). 0, or -1 as sim_ship_motion_at. */
int sim_ship_motion_point(const sim_ship_motion *m, double t_s, core_vec3 p_S_m, sim_ship_point *out);
/* A sim_ship_frame_fn (user: a const sim_ship_motion *) for the flight. */
int sim_ship_motion_frame_fn(void *user, double t_s, sim_ship_frame *out);
/* The loop's step (0: none, the default). With a step set, a time that is
 * exactly a step time (double)k * step_s sums the waves from phasors
 * advanced by exact rotation from the last step asked (re-anchored on the
 * direct sum every 256 steps; off it by at most 1e-11 of the motion's
 * standard deviation, test_ship_motion's bound, and still a pure function
 * of t), other times by the direct sum. The
 * phasors are a cache inside the motion: a motion with a step set is not
 * to be evaluated from two threads at once. 0, or -1 with err for a step
 * < 0 or not finite or out of memory. */
int sim_ship_motion_set_step(sim_ship_motion *m, double step_s, core_err *err);
void sim_ship_motion_get_info(const sim_ship_motion *m, sim_ship_motion_info *info);
/* The wave spectrum the sum samples, S(omega) in m^2 s at the wave
 * frequency omega (rad/s): the table's Hs exactly over 0 to
 * omega_max_radps, 0 outside. */
double sim_ship_motion_spectrum(const sim_ship_motion *m, double omega_radps);
/* The response amplitude operators at wave frequency omega for the
 * motion's speed and heading: heave (m per m of wave amplitude), pitch and
 * roll (rad per m). 0, or -1 for omega not > 0. */
int sim_ship_motion_rao(const sim_ship_motion *m, double omega_radps, double *heave_mpm,
                        double *pitch_radpm, double *roll_radpm);
/* The sea surface elevation (m, up positive) at n points (x_E_m[i],
 * y_E_m[i]) of E at t_s: the same sum of sinusoids as the motion (W1, W2
 * of sim/ship_motion.c), seen from the Earth (wave frequency, not the
 * encounter's). Long-crested: the sum is evaluated on samples along the
 * waves' direction, at most 1/16 of the shortest wave apart, and
 * interpolated (cubic) between them: within 1e-3 of H_s of the direct sum
 * (test_ship_motion). Never touches the motion's step cache: safe to call
 * from another thread. 0 (all 0 at sea state 0), or -1 for t not finite
 * or out of memory. The signature is render_sea_fn's (user: the motion). */
int sim_ship_motion_elevation(void *motion, double t_s, int n, const double *x_E_m, const double *y_E_m,
                              double *eta_m);

/* ------------------------------------ turbulence (sim/turbulence.c, issue 25) */
/* Seeded Dryden turbulence (MIL-F-8785C / MIL-HDBK-1797 Dryden form) from
 * the steady field's k and epsilon: per component sigma = sqrt(2k/3) at
 * each point, length scale L = Cmu^0.75 k^1.5 / epsilon held within
 * [length_min_m, length_max_m], one frozen gust field convected at the
 * reference point's mean velocity (its speed at least speed_min_mps), so
 * points along the wind see the same gust delayed by their distance / V
 * and points across it are correlated by the Dryden correlation. One L and
 * one convection velocity (the reference's) over the field; no variation
 * with height across the wind; the field covers extent_m around the
 * reference. sim/turbulence.c has the model, its references and limits.
 *
 * Use: once per loop step, sim_turb_step with the reference point (e.g. the
 * rotor hub) and the mean air, k and epsilon there; then sim_turb_sample at
 * any number of points (blade elements, fuselage, tail), as often as the
 * integrator asks: sampling changes nothing, so repeated evaluations within
 * a step agree. Positions and velocities in S, relative to the ship. */
#include <stdint.h>

typedef struct sim_turb sim_turb;
typedef struct sim_turb_opts {
    int enabled;          /* 1 (default): gusts; 0: sim_turb_sample gives exactly zero */
    double cmu;           /* k-epsilon model constant in L (0.09) */
    double length_min_m;  /* floor of L (2 m; also k = 0) */
    double length_max_m;  /* cap of L (300 m; also epsilon = 0) */
    double speed_min_mps; /* floor of the convection speed, hover in calm air (2 m/s) */
    double extent_m;      /* the field's width along and across the wind around the reference (40 m) */
    double ds_m;          /* along-wind spacing of the field's rows (0.25 m, at most length_min_m / 4) */
    double dy_m;          /* across-wind spacing of its lanes (0.5 m, at most length_min_m / 2) */
} sim_turb_opts;
void sim_turb_opts_default(sim_turb_opts *o);

/* NULL with err naming the option and what was expected for bad options
 * (non-finite or non-positive values, enabled not 0 or 1, cmu > 1,
 * length_max_m < length_min_m, a spacing too coarse for length_min_m, a
 * field too large). The generator is private and seeded by seed. */
sim_turb *sim_turb_create(const sim_turb_opts *o, uint64_t seed, core_err *err);
void sim_turb_destroy(sim_turb *t);
/* Back to the state just after create with this seed (the loop's reset). */
void sim_turb_reset(sim_turb *t, uint64_t seed);
/* Advance the field by dt_s (>= 0) and set its length scale and convection
 * from the reference point: its position, mean air velocity (m/s, S), k
 * (m^2/s^2) and epsilon (m^2/s^3). 0, or < 0 with err for non-finite or
 * negative input. Off, it checks the input and does nothing else. */
int sim_turb_step(sim_turb *t, const double ref_S_m[3], const double mean_vel_S_mps[3], double k_m2ps2,
                  double eps_m2ps3, double dt_s, core_err *err);
/* The gust (m/s, S) at pos_S_m where the field's k is k_m2ps2: 0; 1 (zero
 * gust) before the first step; -1 (zero gust) for a non-finite position or
 * a k that is negative or not finite. Off: exactly zero, 0. */
int sim_turb_sample(const sim_turb *t, const double pos_S_m[3], double k_m2ps2, double gust_S_mps[3]);
/* L (m) that sim_turb_step uses for k and epsilon, floors and caps applied. */
double sim_turb_length_m(const sim_turb_opts *o, double k_m2ps2, double eps_m2ps3);
/* The field now (plain data). */
typedef struct sim_turb_state {
    double length_m, conv_speed_mps; /* of the last step */
    double e1[3], e2[3], e3[3];      /* wind axes in S: along, across (horizontal), e1 x e2 */
    int lanes, rows;                 /* the field's size */
    long relays;                     /* times laid anew after drifting across the wind */
} sim_turb_state;
void sim_turb_info(const sim_turb *t, sim_turb_state *s);

/* -------------------- stability augmentation (sim/sas.c, issue 25) */
/* The aircraft's SAS between the pilot's controls and the rotor: rate
 * damping and attitude (heading) hold per axis, roll on the lateral
 * cyclic, pitch on the longitudinal, yaw on the pedals, each within +-
 * its authority; gains from the aircraft file's [sas] (hfm_aircraft_sas).
 * A discrete controller, once per step from the body state at the step's
 * start. sim/sas.c has the model, its references and what it leaves out. */
typedef struct sim_sas sim_sas;
/* What the SAS did in its last step (plain data); axes roll, pitch, yaw. */
typedef struct sim_sas_out {
    int engaged;
    double delta_pct[3];   /* its contribution: lateral, longitudinal, pedal (% of travel) */
    double att_err_rad[3]; /* phi, theta, psi less the hold's reference */
    int saturated[3];      /* 1: the contribution was cut to the authority */
} sim_sas_out;
/* NULL with err for gains that are not finite, an authority or detent
 * outside 0-100 %, engaged not 0 or 1. Engaged as g->engaged. */
sim_sas *sim_sas_create(const hfm_sas_gains *g, core_err *err);
void sim_sas_destroy(sim_sas *s);
/* Engage (1) or disengage (0); engaging holds the attitude of the next step. */
void sim_sas_set_engaged(sim_sas *s, int on);
int sim_sas_engaged(const sim_sas *s);
void sim_sas_gains(const sim_sas *s, hfm_sas_gains *g);
/* One step: the rotor's controls from the pilot's and the body state b
 * (Euler angles and rates as hfm_tsim_body gives them), each clamped to
 * 0-100 %; disengaged, the pilot's (clamped). */
void sim_sas_step(sim_sas *s, const hfm_body *b, const hfm_controls *pilot, hfm_controls *rotor);
void sim_sas_last(const sim_sas *s, sim_sas_out *out);
/* The flight's SAS (sim/flight.c; never NULL: an aircraft without [sas]
 * has one with zero gains, disengaged). */
sim_sas *sim_flight_sas(sim_flight *f);

/* ---------------------------- the pilot station (sim/station.c, issue 25) */
/* The parts of `disim station`, the reference pilot station: the sources of
 * the four controls (a scripted CSV, the keyboard's keys, an evdev joystick
 * or gamepad) and the LCM side, which publishes pilot_input_t on
 * DISIM_PILOT_INPUT at a fixed rate and receives DISIM_HELI_STATE and
 * DISIM_SIM_STATUS (each buffer checked with disim_lcm_check_raw before it
 * is decoded; a bad one is counted, never used). Controls are percent of
 * full travel (CONVENTIONS.md). */
#include <signal.h>
#include <stdint.h>
typedef struct sim_station_controls {
    double collective_pct, long_cyclic_pct, lat_cyclic_pct, pedal_pct;
    int trim_button, trim_release; /* held (evdev buttons) */
    int take_over;                 /* this station takes the controls (sim/pilots.c) */
} sim_station_controls;
/* All four at 50 %, the buttons released. */
void sim_station_controls_centre(sim_station_controls *c);

/* A scripted pilot: a CSV of rows time_s,collective,long,lat,pedal (times
 * not decreasing from 0, percentages 0 to 100; '#' comments, blank lines
 * and one header line allowed). Between rows the controls are interpolated
 * linearly (two rows at one time make a step), before the first row they
 * are the first row's, after the last they hold the last's. NULL with err
 * naming file and line. */
typedef struct sim_station_script sim_station_script;
sim_station_script *sim_station_script_load(const char *path, core_err *err);
void sim_station_script_destroy(sim_station_script *s);
void sim_station_script_at(const sim_station_script *s, double t_s, sim_station_controls *c);

/* The keyboard in a terminal (raw bytes): w / s collective up / down, the
 * arrows the cyclic (up = forward, left = left), a / d the pedals, each by
 * step_pct per press (clamped to 0..100); space centres the cyclic and the
 * pedals (the collective is a lever and stays); t takes the controls over
 * (take_over in the next message); q or ctrl-C quits. Escape
 * sequences (ESC [ A, ESC O A) may arrive split across reads. */
typedef struct sim_station_keys {
    double step_pct;
    int esc;     /* 0, 1 after ESC, 2 after ESC [ or ESC O */
    long presses; /* keys that moved a control */
} sim_station_keys;
enum { SIM_KEY_NONE = 0, SIM_KEY_MOVED = 1, SIM_KEY_QUIT = 2 };
void sim_station_keys_init(sim_station_keys *k, double step_pct);
/* One byte from the terminal: SIM_KEY_NONE, SIM_KEY_MOVED (c changed or
 * centred) or SIM_KEY_QUIT. */
int sim_station_keys_feed(sim_station_keys *k, unsigned char byte, sim_station_controls *c);

/* A joystick or gamepad through evdev (/dev/input/event*). Each control
 * reads one EV_ABS axis: code (ABS_X = 0 ...), invert (1: the axis's
 * minimum is 100 %), and the range and dead band (flat, around the
 * centre) from EVIOCGABS. The default is a common gamepad in the
 * helicopter layout: left stick up/down the collective (up = more,
 * ABS_Y inverted), left stick left/right the pedals (ABS_X), right stick
 * the cyclic (ABS_RY forward = 0 %, ABS_RX); the shoulder buttons BTN_TL
 * and BTN_TR are the force-trim set and release, BTN_START (held) takes
 * the controls over. */
enum { SIM_AXIS_COLLECTIVE = 0, SIM_AXIS_LONG = 1, SIM_AXIS_LAT = 2, SIM_AXIS_PEDAL = 3, SIM_AXES = 4 };
typedef struct sim_station_axis {
    int code, invert;
    int min, max, flat;
} sim_station_axis;
typedef struct sim_station_axes {
    sim_station_axis axis[SIM_AXES];
    int trim_button_code, trim_release_code, take_over_code; /* EV_KEY codes, -1: none */
} sim_station_axes;
void sim_station_axes_default(sim_station_axes *a);
/* "ABS_RY", "ABS_RY:invert" or a number ("4", "4:invert"): 0, or -1 with err. */
int sim_station_axis_parse(const char *s, sim_station_axis *ax, core_err *err);
/* "ABS_X" ... for an axis code, "ABS_0x.." style for others (static). */
const char *sim_station_axis_name(int code, char *buf, size_t n);
/* Percent of travel for a value of the axis (dead band, clamp, invert). */
double sim_station_axis_pct(const sim_station_axis *ax, int value);
/* Apply one input event (type, code, value) to c: 1 if it was one of the
 * mapped axes or buttons, else 0. */
int sim_station_axes_apply(const sim_station_axes *a, int type, int code, int value, sim_station_controls *c);

typedef struct sim_station_evdev sim_station_evdev;
/* Open the device read-only, non-blocking, read each mapped axis's range
 * and position (EVIOCGABS) into the handle's axes and c. NULL with err
 * naming the path: missing, unreadable, not an evdev device, or without
 * one of the axes (the message names it and points to --list). */
sim_station_evdev *sim_station_evdev_open(const char *path, const sim_station_axes *axes,
                                          sim_station_controls *c, core_err *err);
/* A handle on an open descriptor whose axes' ranges are already in axes (a
 * pipe of struct input_event in the tests); takes the descriptor. */
sim_station_evdev *sim_station_evdev_wrap(int fd, const sim_station_axes *axes, core_err *err);
void sim_station_evdev_destroy(sim_station_evdev *d);
int sim_station_evdev_fd(const sim_station_evdev *d);
/* Read every pending event (read(2) of struct input_event) into c: 0 (none
 * or some), or -1 with err when the device is gone or failed. After
 * SYN_DROPPED the axes are read again with EVIOCGABS. */
int sim_station_evdev_read(sim_station_evdev *d, sim_station_controls *c, core_err *err);

/* The evdev devices in dir ("/dev/input"), event* in order of number. */
#define SIM_STATION_MAX_DEV_AXES 64
typedef struct sim_station_devinfo {
    char path[512], name[256];
    char error[256]; /* non-empty: it could not be read (what failed) */
    int naxes;
    struct {
        int code, min, max, flat, value;
    } axis[SIM_STATION_MAX_DEV_AXES];
} sim_station_devinfo;
typedef void (*sim_station_dev_fn)(void *user, const sim_station_devinfo *d);
/* Calls fn for each device: the number of devices (0: none), or -1 with
 * err when dir cannot be read. */
int sim_station_evdev_list(const char *dir, sim_station_dev_fn fn, void *user, core_err *err);

/* The station on LCM. */
typedef struct sim_station sim_station;
typedef struct sim_station_opts {
    const char *id;      /* station_id, 1 to 63 characters [A-Za-z0-9._:/@-] */
    const char *lcm_url; /* NULL: the library default */
} sim_station_opts;
/* What the station has sent and received (plain data). */
typedef struct sim_station_view {
    const char *id;
    long published, late;  /* messages sent; deadlines missed (frames skipped) */
    int64_t last_seq;      /* -1 before the first */
    double t_s;            /* station time of the last message */
    sim_station_controls sent;
    long heli_rx, status_rx, bad_rx;
    char bad_last[256]; /* why the last bad message was refused */
    int have_heli;
    double heli_t_s, heli_pos_S_m[3], heli_vel_S_mps[3], roll_rad, pitch_rad, yaw_rad;
    double heli_ctl_pct[4]; /* collective, long, lat, pedal as the loop flies them */
    int on_deck;
    int have_status;
    double sim_time_s, rate_hz, real_time_factor;
    int64_t overruns;
    int state; /* DISIM_SIM_STATUS_T_RUNNING ... */
    char scenario[128];
    int n_stations, listed; /* listed: this station's id is among them */
    char stations[512];     /* the ids, comma-separated */
    char active[64];        /* the station flying ("" none) */
    int32_t flags;          /* DISIM_SIM_STATUS_T_FLAG_* */
    int64_t my_received, my_refused, my_gaps; /* the loop's counts for this station (listed) */
    char message[256];      /* why the loop refused the last sim_control_t */
} sim_station_view;
/* 0 for an id the station may have, else -1 with err. */
int sim_station_id_check(const char *id, core_err *err);
/* A default id: the host's name (characters an id may hold, '-' for the
 * others, at most 40) and source (at most 20), joined by '-'. */
void sim_station_default_id(char *id, size_t n, const char *source);
/* NULL with err for a bad id or an LCM URL it cannot open. */
sim_station *sim_station_create(const sim_station_opts *o, core_err *err);
void sim_station_destroy(sim_station *st);
/* The LCM descriptor to poll for received messages. */
int sim_station_fd(const sim_station *st);
/* Publish c as the next pilot_input_t (seq + 1) stamped utime: 0, or -1. */
int sim_station_publish(sim_station *st, int64_t utime, const sim_station_controls *c, core_err *err);
/* Handle every message already received (does not wait). */
void sim_station_handle(sim_station *st);
/* One received buffer of channel (DISIM_HELI_STATE or DISIM_SIM_STATUS,
 * as lcm_recv_buf_t holds it), what the LCM handlers call: checked with
 * disim_lcm_check_raw, decoded, its shown values checked finite, then
 * taken into the view; otherwise counted as bad with the reason. */
void sim_station_receive(sim_station *st, const char *channel, const void *buf, int size);
const sim_station_view *sim_station_get_view(const sim_station *st);
/* The view as text: tty 1, a block of lines that redraws in place (ANSI:
 * cursor home, each line cleared); tty 0, one line without escapes. */
void sim_station_format(const sim_station_view *v, const char *source, int tty, char *buf, size_t n);

/* The station's loop: publish every 1 / rate_hz on absolute deadlines
 * (a deadline already missed is skipped and counted as late, never
 * published in a burst), the controls from exactly one source, received
 * messages handled between deadlines, show called show_hz times a second.
 * take_over 1: every message carries take_over (a keyboard's t, a
 * device's button: the next message, or while held).
 * With keys, the controls start at 50 % and take the first received
 * heli_state_t's controls while no key has been pressed (no jump when the
 * station joins a flight). Ends at duration_s (> 0), when *stop is set, on
 * a quit key or the end of the key input: 0; < 0 with err (a device gone,
 * a failed publish). */
typedef struct sim_station_run_opts {
    double rate_hz, duration_s; /* duration_s <= 0: until stopped */
    const sim_station_script *script;
    sim_station_evdev *dev;
    int key_fd; /* >= 0: read keys from it, with keys */
    sim_station_keys *keys;
    sim_station_controls start; /* the controls of a device (from its open) */
    int take_over;
    const volatile sig_atomic_t *stop; /* set (by a signal handler): stop */
    void (*show)(void *user, const sim_station_view *v);
    void *user;
    double show_hz;
} sim_station_run_opts;
int sim_station_run(sim_station *st, const sim_station_run_opts *o, core_err *err);

/* ----------------------------- the world a flight flies in (sim/world.c) */
/* What a run was flown from, as disim fly publishes it once at the start
 * and after every reset or load on DISIM_RUN_INFO (run_info_t) and so logs
 * it: enough to draw the run again (its ship, aircraft and seaway). Plain
 * data. */
typedef struct sim_run_info {
    char scenario_path[SIM_PATH_MAX];
    char scenario[64];       /* its name */
    char aircraft_path[SIM_PATH_MAX];
    char ship_path[SIM_PATH_MAX];
    unsigned long long seed; /* the run's seed (the seaway's is seed + 1: sim_world_seaway) */
    sim_sea sea;             /* the seaway flown */
    double wod_speed_mps, wod_dir_rad;
    double rate_hz, state_rate_hz;
} sim_run_info;
/* What the caller sets over a scenario (disim fly's flags, the flown
 * SHOL's WOD point and seed). */
struct sim_interaction;
typedef struct sim_world_overrides {
    double rate_hz;                      /* the step rate (200) */
    double wod_speed_mps, wod_dir_rad;   /* NAN (default): the scenario's single WOD */
    unsigned long long seed;             /* 1: the turbulence's; the seaway's is seed + 1 */
    int turbulence;                      /* -1 (default): the scenario's [wod] turbulence; 0, 1 */
    int sea_state;                       /* -1 (default): the scenario's [sea] state */
    double wave_dir_rad, ship_speed_mps; /* NAN (default): the scenario's */
    const sim_sea *sea;                  /* NULL (default); else the whole seaway, the three above unused */
    int gear;                            /* 1 (default): the aircraft file's [gear] where it has one; 0 none */
    int start;                           /* SIM_START_HOVER (default), SIM_START_DECK */
    int sas;                             /* -1 (default): as the aircraft file's [sas]; 0 off, 1 on */
    int has_station;                     /* 1: the start at station_S_m, else the scenario's station */
    double station_S_m[3];
    const struct cfd_field *field;       /* the ship-only airwake (NULL: the free stream); kept by the caller */
    struct sim_interaction *interaction; /* the coupled rotor interaction (NULL: none); kept by the caller */
} sim_world_overrides;
void sim_world_overrides_default(sim_world_overrides *o);
/* The run information of scenario sc under ov (state_rate_hz 0). */
void sim_world_run_info(const sim_scenario *sc, const sim_world_overrides *ov, sim_run_info *ri);
/* The seaway of a run of seed over ship: its own stream, seed + 1 (the
 * one place that rule is written). NULL with err. */
sim_ship_motion *sim_world_seaway(const core_ship *ship, const sim_sea *sea, unsigned long long seed, core_err *err);
/* A world: the ship's motion in the seaway, the flight in it, and what
 * they were built from. */
typedef struct sim_world {
    sim_ship_motion *motion;
    sim_flight *flight;
    sim_run_info info;
} sim_world;
/* Build the world of sc (only its ship, station, [sea], [wod] and paths
 * used) and aircraft ac (kept by the caller) under ov. 0, or < 0 with err
 * and nothing left to free (err->code CORE_ERR_NO_TRIM: the start does
 * not trim). */
int sim_world_build(const sim_scenario *sc, const hfm_aircraft *ac, const sim_world_overrides *ov,
                    const core_log *log, sim_world *w, core_err *err);
void sim_world_free(sim_world *w);

/* ------------------------------ a trajectory as CSV (sim/trajectory.c) */
/* Rows of a flight's outputs, every rate_hz / row_rate_hz steps, written
 * to PATH.tmpPID and renamed into place by sim_traj_commit (a trajectory
 * destroyed uncommitted leaves nothing). A NULL sim_traj takes every call
 * and writes nothing (no trajectory asked for). */
typedef struct sim_traj sim_traj;
/* The header written. NULL with err. */
sim_traj *sim_traj_create(const char *path, double rate_hz, double row_rate_hz, core_err *err);
/* o's row at its step's turn (always: whatever the step). 0, or < 0 with err. */
int sim_traj_row(sim_traj *t, const sim_flight_out *o, int always, core_err *err);
/* Flushed, synced and renamed into place: 0, or < 0 with err. */
int sim_traj_commit(sim_traj *t, core_err *err);
void sim_traj_destroy(sim_traj *t);

/* ------------------------ a pilot, and the one flight runner (sim/runner.c) */
/* A pilot gives each step's inputs from the flight's output (the state
 * after the last step). Its implementations: the automated pilot
 * (sim_pilot_auto_pilot), the replay pilot (sim_pilot_replay_pilot), and
 * in the real-time loop the LCM stations or the inputs its caller sets
 * (sim_loop_pilot). A sim_pilot is a view: whoever created the pilot
 * destroys it. */
typedef struct sim_pilot_ops {
    const char *kind; /* "auto", "replay", "stations", "inputs" */
    /* The next step's inputs: 0 fly on; > 0 the pilot is done (nothing
     * more to fly; in not used); < 0 it failed. */
    int (*step)(void *self, const sim_flight_out *out, sim_flight_inputs *in);
} sim_pilot_ops;
typedef struct sim_pilot {
    const sim_pilot_ops *ops;
    void *self;
} sim_pilot;
int sim_pilot_step(const sim_pilot *p, const sim_flight_out *out, sim_flight_inputs *in);

/* The runner: one pass (sim_run_pass) asks the wrap's before whether to
 * step, the pilot for the inputs, steps the flight (sim_flight_step, or
 * the wrap's step) and shows the observer the output; sim_run passes
 * until an end and returns which (or < 0 with err). sim/runner.c has the
 * order. */
enum {
    SIM_RUN_STEPPED = 0, /* a pass: the flight stepped */
    SIM_RUN_SKIPPED,     /* a pass: nothing stepped (the real-time loop paused) */
    SIM_RUN_LENGTH,      /* max_steps stepped, or the wrap's length flown */
    SIM_RUN_PILOT_DONE,  /* the pilot is done: nothing stepped */
    SIM_RUN_ENDED,       /* the step ended the flight (a crash, a roll-over; err says what) */
    SIM_RUN_OBSERVED,    /* the observer stopped the run */
    SIM_RUN_STOPPED      /* *stop was set before a pass */
};
/* What wraps the step (the real-time loop's I/O and pacing): before
 * returns SIM_RUN_STEPPED to step, SIM_RUN_SKIPPED for a pass that does
 * not, another end, or < 0 with err; step (NULL: sim_flight_step on the
 * run's flight) returns as sim_flight_step does. */
typedef struct sim_run_wrap {
    int (*before)(void *user, core_err *err);
    int (*step)(void *user, const sim_flight_inputs *in, sim_flight_out *out, core_err *err);
    void *user;
} sim_run_wrap;
/* After every step: out, and st as the step returned it (> 0: the flight
 * ended, err says what; < 0: it failed, err says why). 0 runs on, > 0
 * stops the run (SIM_RUN_OBSERVED), < 0 fails it with err. */
typedef int (*sim_run_observe_fn)(void *user, const sim_flight_out *out, int st, core_err *err);
typedef struct sim_run_opts {
    long max_steps;                    /* < 0 (the default): no limit */
    const volatile sig_atomic_t *stop; /* set (by a signal handler): stop; NULL: none */
    sim_run_wrap wrap;                 /* zeroed: the flight stepped bare */
    sim_run_observe_fn observe;        /* NULL: none */
    void *observe_user;
} sim_run_opts;
void sim_run_opts_default(sim_run_opts *o);
/* One pass on flight fl (NULL where the wrap steps its own) with pilot p
 * from out, which becomes the step's output: a SIM_RUN_* or < 0 with err. */
int sim_run_pass(sim_flight *fl, const sim_pilot *p, const sim_run_opts *o, sim_flight_out *out, core_err *err);
/* Passes until an end: SIM_RUN_LENGTH, _PILOT_DONE, _ENDED, _OBSERVED,
 * _STOPPED, or < 0 with err; out is the last output. */
int sim_run(sim_flight *fl, const sim_pilot *p, const sim_run_opts *o, sim_flight_out *out, core_err *err);

/* ------------- the pilot stations' rules (sim/pilots.c) and the real-time
 * loop (sim/loop.c) */
/* Around the deterministic step, never inside it: pilot stations'
 * pilot_input_t taken by their rules (sim_pilots, sim/pilots.c),
 * sim_control_t (pause, resume, reset, load scenario), heli_state_t,
 * ship_state_t and sim_status_t published, every message sent and
 * received written to an LCM event log, a log's inputs replayed (sim_loop,
 * sim/loop.c, which has the log's clock and its references). */
#define SIM_PILOTS_MAX 16
#define SIM_STATION_ID_MAX 64

/* The pilot stations' rules (a pure function of the messages offered and
 * the run clock t_s, the simulated time since the loop started, which a
 * reset does not set back):
 * - a message is refused, counted against its station and changes nothing
 *   when it fails disim_lcm_check_raw or disim_lcm_check_pilot_input, when
 *   its station is not on a given priority list, or when its seq is not
 *   above the last taken while the station is live (stale); a refused
 *   message whose station id cannot be read counts as refused_unknown;
 * - seq gaps count the messages missing (seq - last - 1);
 * - a station is live while its last taken message is at most
 *   hold_after_s old; with no active station the first live one by
 *   priority (the list's order, else the order of first connection) takes
 *   the controls, and a live station higher in priority takes them from a
 *   lower one; a message with take_over set gives its station the controls
 *   at once, and priority does not take them back until it falls silent;
 * - while the active station is silent the input is held (and the flag
 *   raised) until it speaks again or another station takes over. */
typedef struct sim_pilots sim_pilots;
typedef struct sim_pilots_opts {
    double hold_after_s; /* 0.5 */
    int n_priority;      /* 0: the first to connect flies */
    char priority[SIM_PILOTS_MAX][SIM_STATION_ID_MAX];
} sim_pilots_opts;
void sim_pilots_opts_default(sim_pilots_opts *o);
/* A comma-separated list "A,B,C" as the priority list: 0, or -1 with err
 * (an empty or too long id, a repeated one, too many). */
int sim_pilots_opts_parse(sim_pilots_opts *o, const char *list, core_err *err);
/* NULL with err for hold_after_s not in (0, 60]. */
sim_pilots *sim_pilots_create(const sim_pilots_opts *o, core_err *err);
void sim_pilots_destroy(sim_pilots *p);
/* Offer one received DISIM_PILOT_INPUT buffer (encoded, its fingerprint
 * first) at run time t_s: 0 taken, 1 refused (why, if not NULL, says
 * why). */
int sim_pilots_offer(sim_pilots *p, const void *buf, int size, double t_s, char *why, size_t n);
/* The step's inputs at t_s: the active station's last controls, or hold.
 * Returns 1 when the input is held (no live active station), else 0. */
int sim_pilots_inputs(sim_pilots *p, double t_s, sim_flight_inputs *in);
typedef struct sim_pilot_station {
    char id[SIM_STATION_ID_MAX];
    long long last_seq, received, refused, gaps;
    double heard_t_s; /* run time of the last message taken (-1: none) */
} sim_pilot_station;
int sim_pilots_count(const sim_pilots *p);
void sim_pilots_station(const sim_pilots *p, int i, sim_pilot_station *s);
int sim_pilots_active(const sim_pilots *p); /* index, or -1 */
long long sim_pilots_refused_unknown(const sim_pilots *p);

/* The loop: one call of sim_loop_iterate per step takes the messages
 * received (or the replayed log's, at their logged steps), carries out
 * the controls, steps the flight unless paused, publishes and paces. */
typedef struct sim_loop sim_loop;
typedef struct sim_loop_world {
    sim_flight *flight;            /* the flight stepped */
    const sim_ship_motion *motion; /* its ship's motion (NULL: the frame alone) */
    char scenario[64];             /* the scenario's name, for the status */
    sim_run_info info;             /* published (and logged) as run_info_t when the world starts */
} sim_loop_world;
/* Build the world of the scenario at path (the running one's, for a
 * reset): 0 after the caller has replaced its world with the new one (and
 * freed the old) and filled w; < 0 with err and the old world untouched
 * (the loop keeps flying it and publishes err in the status). */
typedef int (*sim_loop_build_fn)(void *user, const char *path, sim_loop_world *w, core_err *err);
typedef struct sim_loop_opts {
    double rate_hz;          /* the step rate (200) */
    int realtime;            /* 1: paced (sim_pacer), 0: as fast as it can */
    double duration_s;       /* run time to fly (paused time not counted) */
    double state_rate_hz;    /* heli_state_t and ship_state_t (50; at most rate_hz) */
    double status_period_s;  /* sim_status_t, wall time (1) */
    int lcm;                 /* 1: publish and receive on LCM */
    const char *lcm_url;     /* NULL: the library default */
    const char *log_path;    /* NULL: no log; else written to PATH.tmpPID, renamed by finish */
    const char *replay_path; /* NULL; else the pilot inputs and controls of this log, not LCM's */
    const char *scenario_path;
    sim_pilots_opts pilots;
    /* NULL: the stations fly. Else a pilot in the caller's thread flies
     * (the automated pilot of disim fly --pilot auto): its inputs, given
     * by sim_loop_set_inputs before each step, go out on LCM and into the
     * log as pilot_input_t of this station id at the step they fly, as a
     * station's would, and live pilot inputs are not listened to. */
    const char *pilot_source_id;
} sim_loop_opts;
void sim_loop_opts_default(sim_loop_opts *o);
/* A loop flying w (built by the caller from o->scenario_path). NULL with
 * err (the LCM URL, the log or the replayed log cannot be opened). */
sim_loop *sim_loop_create(const sim_loop_opts *o, const sim_loop_world *w, sim_loop_build_fn build, void *user,
                          const core_log *log, core_err *err);
/* A log not finished is removed. */
void sim_loop_destroy(sim_loop *l);
enum { SIM_LOOP_STEPPED = 0, SIM_LOOP_PAUSED = 1, SIM_LOOP_DONE = 2, SIM_LOOP_CRASHED = 3 };
/* One pass: SIM_LOOP_STEPPED with out the step's outputs (a reset or a
 * load shows as out->step back to 1), SIM_LOOP_PAUSED (nothing stepped;
 * waited up to 100 ms for a message), SIM_LOOP_DONE (duration flown),
 * SIM_LOOP_CRASHED (the step ended the flight: out is its last state, its
 * states published, err says what hit what; finish the loop as at the
 * end), or < 0 with err (the integrator, a log write, a publish that
 * failed). */
int sim_loop_iterate(sim_loop *l, sim_flight_out *out, core_err *err);
/* With opts.pilot_source_id: the inputs of the next step (kept for the
 * steps after until set again) that the loop's own pilot gives. */
void sim_loop_set_inputs(sim_loop *l, const sim_flight_inputs *in);
/* The loop as the runner's wrap (o's wrap set, the rest kept): sim_run
 * with it (a NULL flight: the loop steps the world it flies) passes as
 * sim_loop_iterate does, with the pilot the caller gives; the run ends
 * SIM_RUN_LENGTH at the duration, SIM_RUN_ENDED at a crash (the loop to
 * be finished as at the end). */
void sim_loop_run_opts(sim_loop *l, sim_run_opts *o);
/* The loop's own pilot: the stations by their rules at the run clock (the
 * messages LCM brought, or with opts.replay_path the replayed log's at
 * their logged steps), or with opts.pilot_source_id the inputs of
 * sim_loop_set_inputs. A pilot of the caller's given to sim_run instead
 * flies as pilot_source_id. */
sim_pilot sim_loop_own_pilot(sim_loop *l);
/* The end: a last status (STOPPED), the log flushed, synced and renamed.
 * 0, or < 0 with err (the log is then removed). */
int sim_loop_finish(sim_loop *l, core_err *err);
typedef struct sim_loop_report {
    sim_pacer_report pace; /* overruns counted over every pacer of the run */
    double run_s;          /* run time flown */
    int paused, held;
    unsigned flags;        /* the sim_status_t FLAG_* bits */
    long long sent, received, logged, control_refused;
    char scenario[64];
    char message[256];     /* why the last control was refused ("" none) */
} sim_loop_report;
void sim_loop_report_get(const sim_loop *l, sim_loop_report *r);
const sim_pilots *sim_loop_pilots(const sim_loop *l);
/* The loop's LCM instance (NULL without LCM): a memq:// test publishes
 * into it and subscribes to what the loop sends. */
struct _lcm_t;
struct _lcm_t *sim_loop_lcm(sim_loop *l);

/* ------------------------- the automated pilot (sim/pilot_auto.c, issue 26) */
/* A multi-loop pilot model (position -> velocity -> attitude -> rates,
 * heading on the pedals, height on the collective) with a human pilot's
 * crossover frequency and pure delay, its gains scheduled from the
 * linearised flight model (hfm_linearise) at the task's hover; it flies a
 * task file. sim/pilot_auto.c has the model and its references. */
/* A task's tolerances (ADS-33E-PRF style): horizontal distance from the
 * target, height, heading, and the time by which the helicopter must be
 * (and from then on stay) within them. */
typedef struct sim_task_tol {
    double pos_m, height_m, heading_rad, time_s;
    double sink_mps;       /* land: the largest sink rate at touchdown */
    double drift_mps;      /* land: the largest drift at touchdown (phase files; 0: not graded) */
} sim_task_tol;
/* One phase of a task (scenarios/README.md, the task files): hold keeps
 * the CG at target_S_m for duration_s; move takes the reference there
 * along a straight line at speed_mps; descend waits (quiescent = 1) for a
 * quiescent period of the deck's heave, then descends at descent_mps over
 * target_S_m's x, y to touchdown. Times in the tolerances count from the
 * phase's start. */
#define SIM_TASK_MAX_PHASES 8
enum { SIM_PHASE_HOLD = 0, SIM_PHASE_MOVE = 1, SIM_PHASE_DESCEND = 2 };
typedef struct sim_task_phase {
    char name[32];
    int kind;                  /* SIM_PHASE_* */
    double target_S_m[3];      /* the CG in S (descend: z unused) */
    double heading_rad;        /* from the bow */
    double duration_s;         /* hold: the time to stay within the band */
    double speed_mps;          /* move */
    double descent_mps;        /* descend */
    int quiescent;             /* descend: wait for a quiescent period of heave */
    double quiet_energy;       /* descend: the heave energy index below which the deck is quiescent */
    double quiet_window_s;     /* descend: it must stay below over this long */
    double max_wait_s;         /* descend: the longest wait for one */
    sim_task_tol desired, adequate;
} sim_task_phase;
/* A task (INI, scenarios/README.md): station keeping holds the CG at
 * target_S_m (z < 0: above the deck) at heading_rad from the bow for
 * duration_s; land holds it there as station keeping does, then descends
 * at descent_mps to touchdown. A phase file (a [task] phases key) gives
 * its phases; the fields above are then its last hold phase's. */
typedef struct sim_task {
    int kind;
    double target_S_m[3];
    double heading_rad;
    double duration_s;
    double touchdown_height_m; /* land: the CG's height above the deck at wheel contact (no [gear]) */
    double descent_mps;        /* land: the commanded rate of descent */
    sim_task_tol desired, adequate;
    int nphases;
    sim_task_phase phase[SIM_TASK_MAX_PHASES];
    int has_start;             /* phase files: the flight starts at the first phase's target */
    double start_S_m[3];
} sim_task;
/* Read a task file: 0, or < 0 with err naming the file, line and key. A
 * phase file's points are placed on the ship's deck (spot, deck edges,
 * line-up line): ship NULL refuses any anchor but the spot. */
int sim_task_load(const char *path, sim_task *t, core_err *err);
int sim_task_load_ship(const char *path, const core_ship *ship, sim_task *t, core_err *err);
/* The task's start (phase files: the first phase's target) into
 * start_S_m; left as it is for a file without one. 0, or < 0 with err. */
int sim_task_start_S(const char *path, const core_ship *ship, double start_S_m[3], core_err *err);
/* The task's length: each phase's longest time, and a landing's settling. */
double sim_task_length_s(const sim_task *t);
/* The phases of a task given by its legacy fields alone (target_S_m,
 * duration_s, the bands; land: descent_mps): a hold, and for land a
 * descend after it (no time asked); nphases set. */
void sim_task_legacy_phases(sim_task *t);

typedef struct sim_pilot_auto sim_pilot_auto;
typedef struct sim_pilot_auto_opts {
    double rate_hz;            /* the flight's step rate (200) */
    double delay_s;            /* the pilot's pure delay (0.25 s) */
    double att_crossover_radps;/* roll and pitch attitude loops (2.5) */
    double yaw_crossover_radps;/* heading loop (1.5) */
    double hgt_crossover_radps;/* height loop (2.0) */
    double vel_bw_radps;       /* horizontal velocity loop (0.8) */
    double pos_bw_radps;       /* horizontal position loop (0.3) */
    double max_speed_mps;      /* the largest commanded speed (3) */
    double max_att_rad;        /* the largest attitude command from trim (10 deg) */
    double wod_speed_mps, wod_dir_rad; /* the WOD the gains are scheduled at */
    int sas;                   /* 1: the flight's SAS is engaged (the aircraft's [sas]; the
                                  gains scheduled with its rate damping in the loop); 0 (default): off */
    int gear;                  /* 1: the flight has the landing gear (sim/contact.c): after the
                                  touchdown the collective goes down and the run is done once
                                  settled; 0 (default): done at touchdown */
    double cutoff_fraction;    /* the control-activity cut-off frequency's share of the rate
                                  variance below it (0.5) */
    double trim_s;             /* the pilot's trim: integral action on the position and height
                                  errors with this time constant (8 s; 0: none) */
} sim_pilot_auto_opts;
void sim_pilot_auto_opts_default(sim_pilot_auto_opts *o);
/* The derivatives the gains come from (hfm_linearise at the task's hover;
 * per s, per % of travel) and the inputs' trim. */
typedef struct sim_pilot_gains {
    double L_p, L_lat, M_q, M_long, N_r, N_ped, Z_w, Z_col; /* A, B entries */
    double X_u, X_theta, Y_v, Y_phi;
    double trim_pct[4];        /* collective, long, lat, pedal */
    double trim_att_rad[2];    /* phi, theta */
} sim_pilot_gains;
/* A pilot for task t on aircraft ac, from the flight's trimmed inputs
 * (sim_flight_trim_inputs). Trims and linearises ac at the target in the
 * uniform WOD of o for the gains and, until sim_pilot_auto_set_trim_state
 * gives the flight's, the attitude references. NULL with err (bad
 * options, no trim). */
sim_pilot_auto *sim_pilot_auto_create(const hfm_aircraft *ac, const sim_task *t, const sim_pilot_auto_opts *o,
                                      const sim_flight_inputs *trim, const core_log *log, core_err *err);
void sim_pilot_auto_destroy(sim_pilot_auto *p);
void sim_pilot_auto_gains(const sim_pilot_auto *p, sim_pilot_gains *g);
/* The attitude references (trim_att_rad) from the flight's own trim: s0
 * is the flight's state at its hover start (sim_flight_state right after
 * sim_flight_create), trimmed in the flight's air (the airwake), whose
 * roll and pitch relative to S the pilot then aims at instead of the
 * uniform WOD's. 0, or -1 (nothing changed) for a state not finite or
 * not a hover's attitude (|roll|, |pitch| >= 0.5 rad). */
int sim_pilot_auto_set_trim_state(sim_pilot_auto *p, const sim_flight_out *s0);
/* One step: from the flight's output (the state after the last step) the
 * controls for the next step (within 0-100 %), the pilot's delay applied;
 * the task's grading advanced. 0, or 1 when a control is at a stop. */
int sim_pilot_auto_step(sim_pilot_auto *p, const sim_flight_out *out, sim_flight_inputs *in);
/* The pilot's reference (plain data): what the outer loops track. The
 * task's phases set it each step; a caller (e.g. a replay pilot) may set
 * it instead. */
typedef struct sim_pilot_ref {
    double pos_S_m[3];   /* the CG's reference in S, from the spot (z < 0: above the deck) */
    double vel_S_mps[3]; /* its velocity in S, fed forward to the velocity loop; DESCEND:
                            vel_S_mps[2] > 0 is the rate of descent */
    double heading_rad;  /* from the bow, + to starboard, in [-pi, pi] */
    int mode;            /* a phase's kind, SIM_PHASE_HOLD or SIM_PHASE_DESCEND (a move
                            phase flies as HOLD with the reference moving):
                            HOLD: the height loop holds pos_S_m[2];
                            DESCEND: the height reference moves down at
                            vel_S_mps[2] from where it is to the deck (pos_S_m[2] not
                            used), the collective lowered once the wheels touch */
} sim_pilot_ref;
/* Set the reference the pilot flies from its next step on. Once a caller
 * has set it, the task's phases no longer move it (the task is still
 * graded against its own phases). 0, or -1 with the reference unchanged
 * for a value not finite, a heading outside [-pi, pi], a mode not HOLD or
 * DESCEND, or a DESCEND rate not in (0, 5] m/s. */
int sim_pilot_auto_set_reference(sim_pilot_auto *p, const sim_pilot_ref *r);
/* The reference the pilot flies now. */
void sim_pilot_auto_reference(const sim_pilot_auto *p, sim_pilot_ref *r);
/* A phase's result: its grade (2 desired, 1 adequate, 0 not met, -1
 * not flown), when it started and ended, its largest errors (hold: after
 * its desired time; move: from the moving reference). */
typedef struct sim_phase_result {
    int grade;
    double t_start_s, t_end_s;
    double max_err_pos_m, max_err_height_m, max_err_heading_rad;
    double t_wait_s;           /* descend: the wait for a quiescent period */
    double energy;             /* descend: the heave energy index as the descent began */
} sim_phase_result;
/* The task's result so far (plain data). */
typedef struct sim_task_result {
    int grade;                 /* 2 desired, 1 adequate, 0 not (yet) met: the
                                  lowest of the phases' (the touchdown's included) */
    double t_desired_s;        /* since when within the desired tolerances (-1: not now) */
    double t_adequate_s;       /* likewise adequate */
    double err_pos_m, err_height_m, err_heading_rad; /* the latest */
    double max_err_pos_m, max_err_height_m, max_err_heading_rad; /* after the desired time */
    double min_pct[4], max_pct[4]; /* the controls' extremes: collective, long, lat, pedal */
    long stop_steps;           /* steps with a control at a stop */
    /* land: the descent began at t_descent_s (-1: not yet); at touchdown
     * (touched 1) the sink rate and drift relative to the deck, the
     * distance from the spot, and the touchdown's grade (2, 1, 0) */
    double t_descent_s, t_touchdown_s, sink_mps, drift_mps, dist_m;
    int touched, touchdown_grade;
    double t_s;                /* the latest time */
    /* the touchdown, further: the heading error, roll and pitch of the
     * body relative to the deck (rad), the deck's heave at the spot (m,
     * up, from its mean; m/s) and its phase (rad: 0 at a crest, pi in a
     * trough, pi/2 going down), the heave energy index then (1: the
     * average) */
    double td_heading_err_rad, td_roll_deck_rad, td_pitch_deck_rad;
    double td_heave_m, td_heave_rate_mps, td_heave_phase_rad, td_energy;
    int settled, done;         /* settled on deck (gear); done: the run may end */
    double t_settled_s;
    int nphases, phase_now;    /* the phase flown now (nphases: the task is over) */
    sim_phase_result phase[SIM_TASK_MAX_PHASES];
    /* control activity from the start to touchdown (or now), per control
     * (collective, long, lat, pedal): rms about the mean (%), rms of the
     * rate (%/s), the cut-off frequency (rad/s, cutoff_fraction of the
     * rate's variance below it) */
    double ctl_rms_pct[4], ctl_rate_rms_pctps[4], ctl_cutoff_radps[4];
} sim_task_result;
/* Write the result of a run of task t as CSV (one header line, one row)
 * and JSON, each to PATH.tmpPID and renamed (either path may be NULL).
 * 0, or < 0 with err and nothing half-written. */
int sim_task_result_write(const sim_task *t, const sim_task_result *r, const char *csv_path,
                          const char *json_path, core_err *err);
void sim_pilot_auto_result(const sim_pilot_auto *p, sim_task_result *r);
/* The automated pilot as a sim_pilot (kind "auto"): done once its task
 * result says done (touched down and settled, or its last hold flown). */
sim_pilot sim_pilot_auto_pilot(sim_pilot_auto *p);

/* ------------------------------------------- the LCM log of a run (sim/log.c) */
/* The writer: an LCM event log written whole or not at all. Events go to
 * a new temporary file beside path, in LCM's format (the bytes of
 * lcm_eventlog_write_event); commit flushes, syncs and renames it to
 * path. NULL with err naming the file. */
typedef struct sim_log_writer sim_log_writer;
sim_log_writer *sim_log_writer_create(const char *path, core_err *err);
/* One event: the channel (1 to 255 characters), the timestamp (the loop's
 * run clock, us) and the message. 0, or -1 with err naming the temporary
 * file (a failed write fails the commit too). */
int sim_log_writer_write(sim_log_writer *w, const char *channel, int64_t utime_us, const void *data, int size,
                         core_err *err);
/* The events written so far. */
long sim_log_writer_events(const sim_log_writer *w);
/* The log flushed, synced and renamed to its path: 0, or -1 with err
 * naming the path, the temporary file removed (nothing half-written).
 * Once only. */
int sim_log_writer_commit(sim_log_writer *w, core_err *err);
/* Frees w; an uncommitted log's temporary file is removed. */
void sim_log_writer_destroy(sim_log_writer *w);

/* The reader: a recorded run (the LCM event log of `disim fly --log`) as
 * a reference: the helicopter's position, velocity and heading relative
 * to the ship's landing spot (S) as functions of the flight's time, and
 * the recorded pilot's controls (the replay pilot re-flies it, relative
 * to its own deck); and its states for drawing. sim/log.c has the
 * reference's model and the log's rules. */
typedef struct sim_log sim_log;
typedef struct sim_log_summary {
    long n_events;      /* every event in the log */
    long n_states;      /* heli_state_t (each with its ship_state_t): the reference's samples */
    long n_ship;        /* ship_state_t */
    long n_inputs;      /* pilot_input_t taken as the recorded controls (one station; else 0) */
    long n_inputs_bad;  /* pilot_input_t that fail the checks (skipped: the loop refused them) */
    int n_stations;     /* stations heard (2: two or more) */
    char station[SIM_STATION_ID_MAX]; /* the one station's id ("" otherwise) */
    double t0_s, t1_s;  /* the first and the last state's time */
} sim_log_summary;
enum { SIM_REPLAY_HOVER = 0, SIM_REPLAY_TRANSLATE = 1, SIM_REPLAY_DESCEND = 2, SIM_REPLAY_ON_DECK = 3,
       SIM_REPLAY_NPHASE = 4 };
/* (SIM_REPLAY_*: the recorded reference's motion at a sample, classified
 * from its velocities for the replay's error statistics: what the logged
 * flight did, not a phase a pilot is asked to fly, SIM_PHASE_*.) */
/* The reference at one time (plain data). */
typedef struct sim_log_sample {
    double t_s;
    double pos_S_m[3];        /* the CG from the landing spot, in S */
    double vel_S_mps[3];      /* d pos_S_m / dt: relative to the deck, in S (0 after the end) */
    double acc_S_mps2[3];     /* d vel_S_mps / dt (central differences over the samples) */
    double heading_rad;       /* from the bow, + to starboard */
    int phase;                /* SIM_REPLAY_*: of the reference's motion (sim/log.c) */
    int on_deck;              /* the recorded state has a wheel on the deck */
    /* the recorded state as sim_flight_out has it */
    double vel_mean_S_mps[3]; /* relative to the ship's mean motion, in S */
    double euler_E_rad[3], rate_B_radps[3];
    double C_ES[9];
    double controls_pct[4];   /* the recorded controls of the step from t_s: collective, long, lat, pedal */
} sim_log_sample;
/* Read a log. NULL with err naming the file and, for a bad event, its
 * number (from 1), channel and byte offset: missing, not a file, empty,
 * not an event log, truncated, corrupt, a state failing
 * disim_lcm_check_raw or not finite, fewer than two heli_state_t, a state
 * without the ship state of its time, states not in time order (a reset
 * or a load: one flight is expected). */
sim_log *sim_log_load(const char *path, core_err *err);
void sim_log_destroy(sim_log *r);
void sim_log_info(const sim_log *r, sim_log_summary *i);
/* The reference at t_s, linear between samples, held at the nearest end
 * outside them. 0 inside [t0_s, t1_s], 1 outside. */
int sim_log_sample_at(const sim_log *r, double t_s, sim_log_sample *s);

/* A logged instant for drawing it (render/, disim render LOG): the states'
 * poses in E as published, linear between samples (the attitude by
 * normalised linear interpolation of the quaternions, the sign of the
 * second taken nearer the first: the samples are 1 / state_rate_hz apart),
 * the discrete fields (on deck, gear) of the nearer sample. Plain data. */
typedef struct sim_log_state {
    double t_s;
    core_pose ship;          /* S's origin in E and q_ES (ship_state_t) */
    core_pose heli;          /* the CG in E and q_EB (heli_state_t) */
    double pos_S_m[3], vel_S_mps[3];
    double euler_E_rad[3];   /* roll, pitch, yaw of B in E */
    double ship_euler_E_rad[3];
    double controls_pct[4];
    double rotor_thrust_N, rotor_power_W;
    int on_deck;
    int n_gear;
    double gear_load_N[HFM_GEAR_MAX_LEGS];
} sim_log_state;
/* The log's state at t_s: 0 inside [t0_s, t1_s], 1 outside (held at the
 * nearer end). */
int sim_log_state_at(const sim_log *r, double t_s, sim_log_state *s);

/* The run information of the log's first run_info_t: 0, or 1 when the log
 * has none (a log of an older disim: draw it with --scenario). */
int sim_log_run_info(const sim_log *r, sim_run_info *ri);

/* ------------------------------------------ the replay pilot (sim/pilot_replay.c) */
/* Re-flies a recorded run (sim_log) through the automated pilot's loops
 * in another wind over deck and sea state, relative to its own deck.
 * sim/pilot_replay.c has the model. */
/* "hover", "translate", "descend", "on deck"; "all" for SIM_REPLAY_NPHASE. */
const char *sim_replay_phase_name(int phase);
typedef struct sim_pilot_replay sim_pilot_replay;
typedef struct sim_pilot_replay_opts {
    sim_pilot_auto_opts pilot; /* the automated pilot's loops (rate, delay, the WOD of the gains) */
    double preview_s;          /* the reference is taken this far ahead (< 0, the default: the pilot's delay) */
    double acc_lead_s;         /* its acceleration this much further (< 0, the default: the attitude
                                  loops' lag, 1 / att_crossover_radps) */
    int feed_controls;         /* 1: the recorded controls' change from the log's first state fed
                                  forward about this flight's trim, the loops acting on the
                                  deviation from the recorded state; 0 (default): the loops alone */
} sim_pilot_replay_opts;
void sim_pilot_replay_opts_default(sim_pilot_replay_opts *o);
/* The flown CG's distance from the reference at the same time (m). */
typedef struct sim_replay_err {
    long n;                    /* steps counted */
    double duration_s, rms_m, max_m, t_max_s;
} sim_replay_err;
typedef struct sim_replay_result {
    sim_replay_err all, phase[SIM_REPLAY_NPHASE]; /* the run's, and per phase of the reference */
    double err_m;              /* the latest */
    double max_heading_err_rad;
    long stop_steps;           /* steps with a control at a stop */
    double t_s;                /* the latest time counted */
    int ended;                 /* the reference has ended (the run may stop) */
} sim_replay_result;
/* A replay pilot for ref (kept by the caller) on aircraft ac, from the
 * flight's trimmed inputs; the flight should start at the reference's
 * start (its first sample's pos_S_m) with the SAS off. NULL with err. */
sim_pilot_replay *sim_pilot_replay_create(const hfm_aircraft *ac, const sim_log *ref,
                                          const sim_pilot_replay_opts *o, const sim_flight_inputs *trim,
                                          const core_log *log, core_err *err);
/* The attitude references from the flight's own trim (its state s0 right
 * after sim_flight_create), as sim_pilot_auto_set_trim_state: 0, or
 * non-zero (then the uniform-WOD references stay). */
int sim_pilot_replay_set_trim_state(sim_pilot_replay *p, const sim_flight_out *s0);
void sim_pilot_replay_destroy(sim_pilot_replay *p);
/* One step: the errors of out counted, the controls for the next step.
 * 0, or 1 when a control is at a stop. */
int sim_pilot_replay_step(sim_pilot_replay *p, const sim_flight_out *out, sim_flight_inputs *in);
void sim_pilot_replay_result(const sim_pilot_replay *p, sim_replay_result *r);
/* The replay pilot as a sim_pilot (kind "replay"): never done (the run
 * goes the length its caller gives). */
sim_pilot sim_pilot_replay_pilot(sim_pilot_replay *p);

/* ---------------------------------------- the landing gear (sim/contact.c) */
/* The aircraft file's [gear] on the ship's deck: each leg an oleo strut in
 * series with a tyre, pressed on the deck (the plane z_S = 0 over the flight
 * deck, moving with the ship) with a regularised Coulomb friction that holds
 * a standing aircraft; the body's strike points against the ship's blocks.
 * ODE finds the contacts; the loads go to the flight model as external
 * loads (the flight owns one with sim_flight_opts.gear; by hand, an
 * hfm_ext_fn that calls sim_contact_loads with the deck at its time,
 * sim_ship_deck_at). See sim/contact.c. */
typedef struct sim_contact sim_contact;
enum {
    SIM_CONTACT_SLIDE = 1u, /* a braked or locked wheel slid on the deck */
    SIM_CONTACT_TIP = 2u,   /* tilted off the deck past the gear's tip-over angle */
    SIM_CONTACT_CRASH = 4u  /* a strike on the ship, or the gear overloaded */
};
typedef struct sim_contact_leg {
    int on_deck;
    double compression_m;  /* tyre and strut together, along the deck normal */
    double strut_m;        /* the strut's share of it */
    double normal_N;       /* the deck's push on the tyre, along its normal */
    double friction_N[2];  /* in the deck plane, along S x and S y */
    double slip_m;         /* how far the tyre has slid on the deck so far */
} sim_contact_leg;
typedef struct sim_contact_report {
    double t_s;
    unsigned flags;        /* SIM_CONTACT_*, kept once set */
    double t_slide_s, t_tip_s, t_crash_s; /* when each was first seen (-1: not) */
    char what[160];        /* what happened: "tail_rotor_low hit hangar", ... */
    int nlegs;
    sim_contact_leg leg[HFM_GEAR_MAX_LEGS];
    double tilt_rad;       /* the body z axis from the deck normal */
    double tip_angle_rad;  /* the gear's static tip-over angle */
} sim_contact_report;
/* The gear of ac (it needs a [gear] section) on ship (copied), for a
 * flight stepping at rate_hz. NULL with err. */
sim_contact *sim_contact_create(const hfm_aircraft *ac, const core_ship *ship, double rate_hz, core_err *err);
void sim_contact_destroy(sim_contact *c);
/* The gear's force and moment about the CG in B for the body state b in E
 * (as sim/flight.c flies it) on the deck moving as deck (the deck at the
 * right-hand side's time). Non-zero only when the loads are not finite. */
int sim_contact_loads(sim_contact *c, const sim_ship_deck *deck, const hfm_body *b, double F_B_N[3],
                      double M_B_Nm[3]);
/* After each flight step, with the state it ended at (sim_contact_body)
 * and the deck at t_s: the tyres' slides taken, the strike points
 * checked, the report filled (rep may be NULL). 0; 1 when a crash stops
 * the run (rep->what says what hit what). */
int sim_contact_step(sim_contact *c, double t_s, const sim_ship_deck *deck, const hfm_body *b,
                     sim_contact_report *rep);
void sim_contact_report_get(const sim_contact *c, sim_contact_report *rep);
/* The body state in E of a flight step's output. */
void sim_contact_body(const sim_flight_out *out, hfm_body *b);
/* The flight's gear (opts.gear): its report, 0; 1 (rep zeroed) without. */
int sim_flight_contact(const sim_flight *f, sim_contact_report *rep);
/* The legs' static loads (N) holding weight_N on a level deck (the CG over
 * the support, moments balanced; three legs exactly, more by least squares).
 * 0, or < 0 with err when the CG is outside the support. */
int sim_contact_static_loads(const hfm_gear *g, double weight_N, double load_N[], core_err *err);
/* A leg's compression (m, tyre and strut) under the static load load_N,
 * from the series law (the inverse of the leg's force law). */
double sim_contact_leg_compression(const hfm_gear_leg *l, double load_N);

/* -------------- the coupled rotor interaction (sim/interaction.c, issue 25) */
/* An interaction over a rotor disk projected on the flight model's inflow
 * modes (Pitt-Peters: uniform and first harmonics, linear in r), the hub
 * frame q_SH (z down the shaft) giving r/R and psi: v(r, psi) = m + (r/R)
 * (c cos psi + s sin psi). The coupling (couple/interaction.c) and the
 * loop share it. */
typedef int (*sim_point_fn)(void *user, const double pos_S_m[3], double v_S_mps[3]);
typedef struct sim_disk_modes {
    double hub_S_m[3];
    core_quat q_SH;
    double R;
    double m[3], c[3], s[3];
} sim_disk_modes;
/* Fit fn over the disk at hub_S_m (area-weighted least squares on a polar
 * grid of 16 x 36 points over 0.2 R to R). */
void sim_disk_modes_fit(sim_disk_modes *dm, const double hub_S_m[3], core_quat q_SH, double R, sim_point_fn fn,
                        void *user);
/* 1 with r/R and psi when pos is within 1.1 R of the shaft through hub_S_m
 * and 0.3 R of the disk plane (dm's frame and radius), else 0. */
int sim_disk_modes_in(const sim_disk_modes *dm, const double hub_S_m[3], const double pos_S_m[3], double *rr,
                      double *psi);

/* The loop's air near the rotor station: the ship-only air S plus g times
 * the interaction velocity v_int = wind + (coupled - isolated) - S (over
 * the disk the difference's fitted modes, moving with the hub), g = w f:
 * w 1 while the CG is within plateau_m of the station the coupled field's
 * rotor was trimmed at, fading smoothly to 0 over fade_m beyond; f the
 * rotor's induced velocity at its thrust over that at the field's (Glauert
 * momentum theory in the WOD; the thrust through the wake's lag). See
 * sim/interaction.c for the model and its assumptions. */
typedef struct sim_interaction sim_interaction;
typedef struct sim_interaction_opts {
    double station_S_m[3];  /* the CG station of the coupling's trim (the scenario's) */
    core_quat q_SH;         /* the disk frame of the fit (identity: the disk level in S) */
    double plateau_m;       /* weight 1 within this of the station (0: 0.25 R) */
    double fade_m;          /* the fade's length beyond it (0: R) */
    double rho_kgpm3;       /* air density (1.225) */
    /* a deck-zone pair (the coupled and isolated fields over the deck zone
     * only): the whole domain's ship-only field of the direction and the
     * zone's own (couple.h, settings.zone), kept by the caller; NULL both
     * for a whole-domain pair */
    const struct cfd_field *ship_whole, *ship_zone;
    /* set from the coupled field: its WOD (the coupling's wind) */
    double wod_speed_mps, wod_dir_rad;
} sim_interaction_opts;
void sim_interaction_opts_default(sim_interaction_opts *o);
/* The interaction of a coupled field and its isolated rotor's (the same
 * case without the ship: rotor, thrust, hub, radius and WOD must agree),
 * both kept by the caller. Starts at the station with the field's thrust
 * (g = 1), as the start's trim needs. NULL with err. */
sim_interaction *sim_interaction_create(const struct cfd_field *coupled, const struct cfd_field *isolated,
                                        const sim_interaction_opts *o, core_err *err);
void sim_interaction_destroy(sim_interaction *ia);
/* One step of the rotor's interaction, its inputs the rotor now: the CG
 * in S and the main rotor's thrust (N; NaN: not known, the lagged thrust
 * kept) over dt_s. 0, or -1 for a position that is not finite or
 * dt_s < 0. The air applies it where it is given (sim_air_in.inter). */
int sim_interaction_step(sim_interaction *ia, const double cg_S_m[3], double thrust_N, double dt_s);
/* Add g v_int at p_S to the ship-only air v_S (m/s, S), in place. */
void sim_interaction_apply(const sim_interaction *ia, const double p_S[3], double v_S[3]);
typedef struct sim_interaction_info {
    double weight, factor;  /* w and f: g = w f */
    double dist_m;          /* the CG from the station */
    double thrust_N, thrust_field_N; /* the lagged thrust, the coupled field's */
    double hub_S_m[3];      /* the coupled field's hub */
    double m_mps[3], c_mps[3], s_mps[3]; /* the fitted modes of coupled - isolated */
} sim_interaction_info;
void sim_interaction_state(const sim_interaction *ia, sim_interaction_info *s);

#ifdef __cplusplus
}
#endif
#endif
