/* sim_log.h -- the LCM log of a run, its writer and reader (sim/log.c).
 * Part of sim.h (the umbrella header). */
#ifndef DISIM_SIM_LOG_H
#define DISIM_SIM_LOG_H

#include "core.h"
#include "hfm.h"
#include "sim_loop.h"
#include "sim_world.h"

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

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

/* Every reader of an LCM event log (sim_log_load, the loop's replay of
 * its inputs) checks it first: a regular file (no folder, FIFO or device)
 * of at most SIM_LOG_MAX_BYTES, not empty, and every event framed: the
 * sync word, a channel of 1 to 255 bytes, a data length >= 0 whose event
 * ends inside the file, the next event's sync word where it ends, so that
 * lcm_eventlog_read_next_event never meets a length it would allocate
 * blindly. 0 with the counts, or -1 with err naming the file and the bad
 * event (its number from 1 and byte offset). */
#define SIM_LOG_MAX_BYTES (16LL * 1024 * 1024 * 1024)
typedef struct sim_log_frames {
    long long size;  /* the file's bytes */
    long n_events;
    long n_inputs;   /* events on DISIM_PILOT_INPUT or DISIM_SIM_CONTROL (what a replay flies) */
    long n_marks;    /* the loop's marks of world changes carried out (SIM_LOOP_CH_CONTROL_DONE) */
} sim_log_frames;
int sim_log_check_frames(const char *path, sim_log_frames *fr, core_err *err);

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
    int sas;            /* the flight's SAS as its sim_status_t say: 1 engaged, 0 off, -1 unknown
                           (no status says: a log of an older disim) */
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

#ifdef __cplusplus
}
#endif

#endif
