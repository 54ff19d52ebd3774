/* sim_ship_motion.h -- the ship's motion in a seaway (sim/ship_motion.c).
 * Part of sim.h (the umbrella header). */
#ifndef DISIM_SIM_SHIP_MOTION_H
#define DISIM_SIM_SHIP_MOTION_H

#include "core.h"
#include "hfm.h"
#include "sim_scenario.h"
#include "sim_flight.h"

#ifdef __cplusplus
extern "C" {
#endif

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

#ifdef __cplusplus
}
#endif

#endif
