/* sim_runner.h -- the pilot interface and the one flight runner (sim/runner.c),
 * and a trajectory as CSV (sim/trajectory.c).
 * Part of sim.h (the umbrella header). */
#ifndef DISIM_SIM_RUNNER_H
#define DISIM_SIM_RUNNER_H

#include "core.h"
#include "hfm.h"
#include "sim_flight.h"

#include <signal.h>

#ifdef __cplusplus
extern "C" {
#endif

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

#ifdef __cplusplus
}
#endif

#endif
