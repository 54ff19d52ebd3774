/* sim_flight.h -- the flight and the air it meets: the ship's frame, the air
 * (sim/air.c), the flight (sim/flight.c), turbulence (sim/turbulence.c),
 * the SAS (sim/sas.c), the landing gear (sim/contact.c) and the coupled
 * rotor interaction (sim/interaction.c).
 * Part of sim.h (the umbrella header). */
#ifndef DISIM_SIM_FLIGHT_H
#define DISIM_SIM_FLIGHT_H

#include "core.h"
#include "hfm.h"

#ifdef __cplusplus
extern "C" {
#endif

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
/* The WOD from now on: the free stream and the fields' scale to the new
 * speed (a field keeps its own direction). 0, or < 0 with err. */
int sim_air_set_wod(sim_air *a, double speed_mps, double dir_rad, core_err *err);
/* The grid level (core_grid_level) of the newest field offered, from its
 * metadata; -1 for the free stream or a field of no level (a grid study's). */
int sim_air_grid(const sim_air *a);
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
    hfm_controls ctl;
    int hold;
} sim_flight_inputs;

/* The outputs of a step (plain data). */
typedef struct sim_flight_out {
    double t_s;
    long step;
    double pos_E_m[3], vel_E_mps[3], euler_E_rad[3], rate_B_radps[3];
    double pos_S_m[3];       /* the CG in the ship frame */
    double vel_S_mps[3];     /* relative to the ship's mean motion, in S */
    hfm_controls ctl;        /* the pilot's (the rotor's add the SAS's) */
    double airspeed_mps;     /* at the fuselage reference */
    sim_ship_frame ship;
    unsigned air_flags;      /* SIM_AIR_* */
    int air_grid;            /* sim_air_grid: the level of the field flown, -1 none */
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
/* The WOD's speed changed in flight, from the next step on
 * (sim_air_set_wod: the free stream and the field re-scaled): 0; 1 with
 * err when it cannot be in flight (a new direction, which needs the field
 * of that direction, or the coupled interaction flown: the world must be
 * built again); < 0 with err for a speed < 0 or a direction not finite. */
int sim_flight_set_wod(sim_flight *f, double speed_mps, double dir_rad, core_err *err);
/* The turbulence on (1: a new frozen field, seeded by opts.seed) or off
 * (0) from the next step on. 0, or < 0 with err. */
int sim_flight_set_turbulence(sim_flight *f, int on, core_err *err);
/* The ship the flight flies over (its blocks, deck height). */
const core_ship *sim_flight_ship(const sim_flight *f);

/* ------------------------------------ turbulence (sim/turbulence.c) */
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

/* -------------------- stability augmentation (sim/sas.c) */
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

/* -------------- the coupled rotor interaction (sim/interaction.c) */
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
