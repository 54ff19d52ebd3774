/* sim_task.h -- the task file (sim/task.c) and a flight's task result
 * (sim/task_result.c).
 * Part of sim.h (the umbrella header). */
#ifndef DISIM_SIM_TASK_H
#define DISIM_SIM_TASK_H

#include "core.h"
#include "hfm.h"

#ifdef __cplusplus
extern "C" {
#endif

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
/* The same on a task file already read (core_ini_load or core_ini_parse;
 * the caller destroys it). */
int sim_task_from_ini(core_ini *ini, const core_ship *ship, sim_task *t, core_err *err);
/* The task's start (phase files: the first phase's target) into
 * start_S_m; left as it is for a file without one. 0, or < 0 with err. */
int sim_task_start_S(const char *path, const core_ship *ship, double start_S_m[3], core_err *err);
/* The task's length: each phase's longest time, and a landing's settling. */
double sim_task_length_s(const sim_task *t);
/* The phases of a task given by its legacy fields alone (target_S_m,
 * duration_s, the bands; land: descent_mps): a hold, and for land a
 * descend after it (no time asked); nphases set. */
void sim_task_legacy_phases(sim_task *t);

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

#ifdef __cplusplus
}
#endif

#endif
