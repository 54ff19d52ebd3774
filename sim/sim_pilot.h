/* sim_pilot.h -- the automated pilot (sim/pilot_auto.c) and the replay pilot
 * (sim/pilot_replay.c).
 * Part of sim.h (the umbrella header). */
#ifndef DISIM_SIM_PILOT_H
#define DISIM_SIM_PILOT_H

#include "core.h"
#include "hfm.h"
#include "sim_flight.h"
#include "sim_runner.h"
#include "sim_task.h"
#include "sim_log.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------- the automated pilot (sim/pilot_auto.c) */
/* A multi-loop pilot model (position -> velocity -> attitude -> rates,
 * heading on the pedals, height on the collective) with a human pilot's
 * crossover frequency and pure delay, its gains scheduled from the
 * linearised flight model (hfm_linearise) at the task's hover; it flies a
 * task file. sim/pilot_auto.c has the model and its references. */

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
    double moment_s;           /* the steady roll and pitch moments the linear model lacks, estimated
                                  over this time constant and taken out with the cyclic (0, default:
                                  none; the replay pilot's 4 / att_crossover) */
    double heave_s;            /* the same for the steady vertical force, with the collective (0,
                                  default: none; the replay pilot's 4 / hgt_crossover) */
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

void sim_pilot_auto_result(const sim_pilot_auto *p, sim_task_result *r);
/* The automated pilot as a sim_pilot (kind "auto"): done once its task
 * result says done (touched down and settled, or its last hold flown). */
sim_pilot sim_pilot_auto_pilot(sim_pilot_auto *p);

/* ------------------------------------------ the replay pilot (sim/pilot_replay.c) */
/* Re-flies a recorded run (sim_log) through the automated pilot's loops
 * in another wind over deck and sea state, relative to its own deck.
 * sim/pilot_replay.c has the model. */
/* "hover", "translate", "descend", "on deck"; "all" for SIM_REPLAY_NPHASE. */
const char *sim_replay_phase_name(int phase);
typedef struct sim_pilot_replay sim_pilot_replay;
typedef struct sim_pilot_replay_opts {
    sim_pilot_auto_opts pilot; /* the automated pilot's loops (rate, delay, the WOD of the gains,
                                  sas: the flight's SAS; trim_s 0 by default: the replay's own
                                  integrals on position and heading and its steady trims instead,
                                  moment_s and heave_s set from the crossovers, the height's
                                  integral for them with feed_controls) */
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
 * start (its first sample's pos_S_m) with the SAS as the log says the
 * recorded run had it (sim_log_summary.sas; off where it does not say),
 * o->pilot.sas saying the same. NULL with err. */
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

#ifdef __cplusplus
}
#endif

#endif
