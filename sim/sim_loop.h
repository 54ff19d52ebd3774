/* sim_loop.h -- the real-time loop: its pacing (sim/pacing.c), the pilot
 * stations' rules (sim/pilots.c), the loop with its LCM side and log
 * (sim/loop.c).
 * Part of sim.h (the umbrella header). */
#ifndef DISIM_SIM_LOOP_H
#define DISIM_SIM_LOOP_H

#include "core.h"
#include "hfm.h"
#include "sim_ship_motion.h"
#include "sim_flight.h"
#include "sim_world.h"
#include "sim_runner.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

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
/* The deadlines from now (after a pause, a reset, a load): the run's
 * counts, wall time and step times kept, the step under way still timed
 * from its start, so that the summary's real-time factor and the step
 * times cover the whole run. */
void sim_pacer_rebase(sim_pacer *p);
/* A pass that steps nothing (frozen, or an ended flight waiting for a
 * reset): the next step is timed from now, so that the wait is no step's
 * work. */
void sim_pacer_idle(sim_pacer *p);
/* Call once per step after its work: sleeps to the next deadline (real
 * time). Returns 1 when the step overran its deadline, 0 otherwise. */
int sim_pacer_wait(sim_pacer *p);
void sim_pacer_stats(const sim_pacer *p, sim_pacer_report *s);
/* Ask the system for what a real-time loop wants: SCHED_FIFO at priority
 * (1-99) and all memory locked (no page faults mid-step). Returns bit 0
 * set when the scheduling was granted, bit 1 when the memory was locked;
 * what says which, and why not (e.g. not permitted for this user). */
int sim_pacer_os_realtime(int priority, char *what, size_t n);

/* ------------- the pilot stations' rules (sim/pilots.c) and the real-time
 * loop (sim/loop.c) */
/* Around the deterministic step, never inside it: pilot stations'
 * pilot_input_t taken by their rules (sim_pilots, sim/pilots.c),
 * sim_control_t (pause, resume, reset, load scenario, and the
 * instructor's resets, reposition, conditions and snapshots, each answered
 * in the status), heli_state_t,
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
 * - seq gaps count the messages missing (seq - last - 1); a seq more
 *   than SIM_PILOTS_SEQ_JUMP_MAX past the station's last (over an hour
 *   of messages at 200 Hz) is refused and counted, never adopted, so one
 *   spoofed or corrupt message cannot make the station's own stale;
 * - after a silence, a seq at or below the last is a restarted station
 *   (its count begins again at 0) only when it is below
 *   SIM_PILOTS_RESTART_SEQ_MAX; any other is refused as a replay;
 * - a station is live while its last taken message is at most
 *   hold_after_s old; with no active station the first live one by
 *   priority (the list's order, else the order of first connection) takes
 *   the controls, and a live station higher in priority takes them from a
 *   lower one; a message with take_over set gives its station the controls
 *   at once, and priority does not take them back until it falls silent;
 * - while the active station is silent the input is held (and the flag
 *   raised) until it speaks again or another station takes over;
 * - whenever the controls pass to a station (its first message, a
 *   take-over, priority, its return after a silence, a reset or a load)
 *   they blend from the controls flown at that step to the station's,
 *   linearly over blend_s (SIM_PILOTS_BLEND_S): never a step. */
#define SIM_PILOTS_BLEND_S 1.0
#define SIM_PILOTS_SEQ_JUMP_MAX 1000000LL
#define SIM_PILOTS_RESTART_SEQ_MAX 200LL /* a restarted station's first 1-4 s at 50-200 Hz */
typedef struct sim_pilots sim_pilots;
typedef struct sim_pilots_opts {
    double hold_after_s; /* 0.5 */
    double blend_s;      /* SIM_PILOTS_BLEND_S; 0: the station's controls at once (the rules' tests) */
    int n_priority;      /* 0: the first to connect flies */
    char priority[SIM_PILOTS_MAX][SIM_STATION_ID_MAX];
} sim_pilots_opts;
void sim_pilots_opts_default(sim_pilots_opts *o);
/* A comma-separated list "A,B,C" as the priority list: 0, or -1 with err
 * (an empty or too long id, a repeated one, too many). */
int sim_pilots_opts_parse(sim_pilots_opts *o, const char *list, core_err *err);
/* NULL with err for hold_after_s not in (0, 60] or blend_s not in [0, 10]. */
sim_pilots *sim_pilots_create(const sim_pilots_opts *o, core_err *err);
void sim_pilots_destroy(sim_pilots *p);
/* Offer one received DISIM_PILOT_INPUT buffer (encoded, its fingerprint
 * first) at run time t_s: 0 taken, 1 refused (why, if not NULL, says
 * why). */
int sim_pilots_offer(sim_pilots *p, const void *buf, int size, double t_s, char *why, size_t n);
/* The step's inputs at t_s: the active station's last controls (while a
 * blend runs, flown's at its start blended into them), or hold; flown:
 * the controls the flight flies now (its last step's). Returns 1 when the
 * input is held (no live active station), else 0. */
int sim_pilots_inputs(sim_pilots *p, double t_s, const hfm_controls *flown, sim_flight_inputs *in);
/* The controls blend in afresh at the next step a station flies (a reset
 * or a load has moved the flown controls to the new start's). */
void sim_pilots_reblend(sim_pilots *p);
/* The blend (plain data): running now (the last sim_pilots_inputs), the
 * station it blends to, its start (run time), the controls it blends
 * from (collective, long, lat, pedal), and how many blends have started. */
typedef struct sim_pilots_blend_info {
    int blending, station;
    double t0_s, from_pct[4];
    long long started;
} sim_pilots_blend_info;
void sim_pilots_blend(const sim_pilots *p, sim_pilots_blend_info *b);
typedef struct sim_pilot_station {
    char id[SIM_STATION_ID_MAX];
    long long last_seq, received, refused, gaps;
    double heard_t_s; /* run time of the last message taken (-1: none) */
    double in_pct[4]; /* its last controls taken: collective, long, lat, pedal */
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
/* What the instructor's controls (sim_control_t RESET_HOVER, RESET_DECK,
 * REPOSITION, SET_WOD, SET_SEA, SET_TURBULENCE) set over the scenario and
 * the caller's own settings (its command line) when a world is built
 * again; each field at its default leaves the caller's. */
typedef struct sim_loop_setup {
    int start;                         /* -1 (default): the caller's; SIM_START_HOVER, SIM_START_DECK */
    int has_station;                   /* 1: the hover's CG at station_S_m (a reposition), else the scenario's */
    double station_S_m[3];
    double heading_rad;                /* the deck start's heading from the bow (0) */
    double wod_speed_mps, wod_dir_rad; /* NAN (default): the caller's */
    int sea_state;                     /* -1 (default): the caller's; 0-6 */
    int turbulence;                    /* -1 (default): the caller's; 0 off, 1 on */
} sim_loop_setup;
void sim_loop_setup_default(sim_loop_setup *s);
/* Build the world of the scenario at path under s, as sim_loop_build_fn
 * (the build of a default s is the build_fn's). */
typedef int (*sim_loop_rebuild_fn)(void *user, const char *path, const sim_loop_setup *s, sim_loop_world *w,
                                   core_err *err);
/* A world built off the loop's thread (sim_loop_opts.builder), in three
 * parts, all with the loop's user:
 * - prepare, on the loop's worker thread: the world of the scenario at
 *   path under s (NULL: the caller's settings alone, as build) into a
 *   world of the caller's own (*world), w filled from it. It must touch
 *   nothing that the running flight or the caller's code between steps
 *   reads (the caller's running world stays as it is). 0, or < 0 with err
 *   and nothing left to free;
 * - install, on the loop's thread between two steps: world becomes the
 *   caller's running one; returns the one it replaces (to be dropped);
 * - drop, on the worker: a world replaced, or prepared and not installed,
 *   freed. */
typedef struct sim_loop_builder {
    int (*prepare)(void *user, const char *path, const sim_loop_setup *s, void **world, sim_loop_world *w,
                   core_err *err);
    void *(*install)(void *user, void *world);
    void (*drop)(void *user, void *world);
} sim_loop_builder;
/* Where a world prepared on the worker is swapped in (sim_loop_opts.swap). */
enum {
    SIM_LOOP_SWAP_AUTO = 0, /* real time: READY; as fast as it can: PASS */
    SIM_LOOP_SWAP_READY,    /* at the start of the first pass after the worker has finished (the step it
                               lands on depends on the thread's timing: it is logged) */
    SIM_LOOP_SWAP_PASS      /* at the end of the controls of the pass that asked (the loop waits for the
                               worker there): the same step whatever the timing */
};
/* The channel of the log-only event that marks a world change carried out
 * (built and swapped in, or refused by its build) at its step: a
 * sim_control_t with the control's seq and command. A replay swaps its
 * world where the log has it. */
#define SIM_LOOP_CH_CONTROL_DONE "DISIM_SIM_CONTROL_DONE"
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
    /* NULL: the stations fly. Else the caller's pilot, given to sim_run
     * with the loop's wrap (the automated pilot of disim fly --pilot
     * auto), flies: its inputs go out on LCM and into the log as
     * pilot_input_t of this station id at the step they fly, as a
     * station's would, and live pilot inputs are not listened to. */
    const char *pilot_source_id;
    /* NULL: the instructor's controls that build the world again (the
     * resets to the hover and the deck, a reposition, the WOD, sea state
     * and turbulence, a restore) are refused; else they build with it
     * (the same user as build). */
    sim_loop_rebuild_fn rebuild;
    /* The longest flight a snapshot is taken of (600 s): a restore builds
     * the world of the snapshot's flight again and flies its inputs from
     * its start (the same inputs, the same state bit for bit), which takes
     * up to about this flight time over the step's speed. */
    double snapshot_max_s;
    /* 0 (default): a flight that ended (a crash, a roll-over) ends the
     * run (SIM_LOOP_CRASHED). 1: the loop stops it (the status STOPPED,
     * its passes SIM_LOOP_PAUSED) and waits for a control that builds the
     * world again (a reset, a reposition, a condition, a load, a restore:
     * the instructor's), then flies on; the run ends at its duration. */
    int wait_after_end;
    /* NULL prepare (default): a world is built in the step that asked for
     * it, through build and rebuild (one build per step: a further
     * control that would build one is refused). Else a world is built on
     * the loop's worker thread while the old one flies on, and swapped in
     * between two steps (swap); the control is answered then. While one
     * is being built, a further control that would change the world is
     * refused ("busy"). */
    sim_loop_builder builder;
    int swap; /* SIM_LOOP_SWAP_AUTO (default); a replay swaps where its log says, whatever this is */
    /* The world changes (a reset, a load, a restore, the instructor's
     * controls that build the world again) asked for, limited over the run
     * clock: at most change_burst (5) at once, one more each
     * change_interval_s (1 s) of run time; the excess refused with the
     * reason and counted; a frozen or ended flight is not held by it.
     * change_interval_s 0: no limit. */
    int change_burst;
    double change_interval_s;
} sim_loop_opts;
void sim_loop_opts_default(sim_loop_opts *o);
/* A loop flying w (built by the caller from o->scenario_path). NULL with
 * err (the LCM URL, the log or the replayed log cannot be opened). */
sim_loop *sim_loop_create(const sim_loop_opts *o, const sim_loop_world *w, sim_loop_build_fn build, void *user,
                          const core_log *log, core_err *err);
/* A log not finished is removed. */
void sim_loop_destroy(sim_loop *l);
enum { SIM_LOOP_STEPPED = 0, SIM_LOOP_PAUSED = 1, SIM_LOOP_DONE = 2, SIM_LOOP_CRASHED = 3 };
/* One pass: SIM_LOOP_STEPPED with out the step's outputs (a reset, a
 * load or a world built again shows as out->step back to 1, a restore as
 * the snapshot's step + 1), SIM_LOOP_PAUSED (nothing stepped;
 * waited up to 100 ms for a message), SIM_LOOP_DONE (duration flown),
 * SIM_LOOP_CRASHED (the step ended the flight: out is its last state, its
 * states published, err says what hit what; finish the loop as at the
 * end), or < 0 with err (the integrator, a log write, a publish that
 * failed). */
int sim_loop_iterate(sim_loop *l, sim_flight_out *out, core_err *err);
/* The loop as the runner's wrap (o's wrap set, the rest kept): sim_run
 * with it (a NULL flight: the loop steps the world it flies) passes as
 * sim_loop_iterate does, with the pilot the caller gives; the run ends
 * SIM_RUN_LENGTH at the duration, SIM_RUN_ENDED at a crash (the loop to
 * be finished as at the end). */
void sim_loop_run_opts(sim_loop *l, sim_run_opts *o);
/* The loop's own pilot: the stations by their rules at the run clock (the
 * messages LCM brought, or with opts.replay_path the replayed log's at
 * their logged steps; with none live, the flight holds). With
 * opts.pilot_source_id the caller gives its own pilot to sim_run instead,
 * and it flies as that station. */
sim_pilot sim_loop_own_pilot(sim_loop *l);
/* The end: a last status (STOPPED), the log flushed, synced and renamed.
 * 0, or < 0 with err (the log is then removed). */
int sim_loop_finish(sim_loop *l, core_err *err);
typedef struct sim_loop_report {
    sim_pacer_report pace; /* over the whole run: its wall time (pauses and rebuilds in it), steps, overruns, step times */
    double run_s;          /* run time flown */
    int paused, held;
    unsigned flags;        /* the sim_status_t FLAG_* bits */
    long long sent, received, logged, control_refused;
    char scenario[64];
    char message[256];     /* why the last control was refused ("" none) */
    /* the last control answered: its seq (-1 none), command, result
     * (sim_status_t CONTROL_*), what was done or why not, and the wall
     * time its application took (a world built on the worker: from the
     * control's arrival to its swap) */
    long long control_seq;
    int control_command, control_result;
    char control_message[256];
    double control_apply_s;
    int snapshots;         /* snapshots held */
    /* world builds: run in a step on the loop's thread (no builder), run
     * on the worker; controls refused as the worker was busy, refused by
     * the rate limit; a world change being built now (0, 1) */
    long long builds_in_step, builds_on_worker, refused_busy, refused_rate;
    int change_pending;
} sim_loop_report;
void sim_loop_report_get(const sim_loop *l, sim_loop_report *r);
const sim_pilots *sim_loop_pilots(const sim_loop *l);
/* The loop's LCM instance (NULL without LCM): a memq:// test publishes
 * into it and subscribes to what the loop sends. */
struct _lcm_t;
struct _lcm_t *sim_loop_lcm(sim_loop *l);

#ifdef __cplusplus
}
#endif

#endif
