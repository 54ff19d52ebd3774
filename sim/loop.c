/* loop.c -- the real-time flight loop (sim_loop): pilot stations, sim control,
 * published states and the event log, all around the deterministic step
 * (sim/flight.c), never inside it.
 *
 * Model. The loop runs on a run clock: k steps of 1 / rate_hz since it
 * started, which pauses do not advance and resets do not set back. The
 * loop is the runner's wrap (sim/runner.c: sim_run_pass, sim_run); one
 * pass at run step k
 *   1. takes what was received since the last pass (or, replaying, the
 *      logged DISIM_PILOT_INPUT and DISIM_SIM_CONTROL events of run steps
 *      <= k): each pilot_input_t is offered to the stations' rules at run
 *      time k / rate_hz, each sim_control_t queued;
 *   2. carries out the controls in the order received (pause, resume,
 *      reset, load scenario, and the instructor's: the resets to the
 *      hover and the deck, a reposition, the WOD, sea state and
 *      turbulence, snapshots), each checked first and refused with the
 *      reason, each answered in a status of its own (control_seq,
 *      control_result, control_message, control_apply_s) and logged;
 *   3. unless paused, takes the step's inputs from the pilot (the
 *      stations' rules, the inputs the caller sets, or a pilot of the
 *      caller's, whose inputs go out as its station's pilot_input_t) and
 *      steps the flight (run step k + 1), then publishes heli_state_t
 *      and ship_state_t every rate_hz / state_rate_hz steps;
 *   4. publishes sim_status_t every status_period_s of wall time and at
 *      once when the state, the flags, the active station or a refusal
 *      change; then waits for the deadline (sim_pacer) in real time.
 * The stations' rules see only the messages and the run clock, so the
 * same messages at the same run steps give the same inputs, and with them
 * the same trajectory, in real time or as fast as it can (lockstep).
 *
 * The log is LCM's event-log format (lcm/eventlog.h, as lcm-logger writes
 * it: lcm-logplayer, lcm-spy and lcm_eventlog_read_next_event read it),
 * every message sent and received in the order of the loop. An event's
 * timestamp is the run clock in microseconds (llround(k * 1e6 / rate_hz)),
 * not the wall clock, so that lcm-logplayer plays it at simulated speed
 * and a replay applies each received message at the run step it was
 * taken at (the replay must use the logged run's --rate-hz). Messages
 * carry utime = the flight's simulation time and seq.
 *
 * The instructor's controls. The world's setup (sim_loop_setup: the
 * start, hover or deck, the hover's place, the deck's heading, the WOD,
 * the sea state, the turbulence) is what the instructor set over the
 * caller's settings. The WOD's speed and the turbulence change in
 * flight (sim_flight_set_wod, sim_flight_set_turbulence, between two
 * steps); a reset to the hover or the deck, a reposition, a new WOD
 * direction or sea state builds the world again through the caller's
 * rebuild (opts.rebuild: the seaway, the field of the WOD, the trimmed
 * start), which starts the flight again from its start. A reposition is
 * checked against the ship (inside it, within 2 m above it, under the
 * sea) and the others against their ranges, before anything is changed.
 * The journal holds the inputs of every step flown since the world was
 * built (opts.snapshot_max_s of them at most) and the changes made in
 * flight, each before the step it came before; a snapshot is the setup
 * the world was built with, its scenario and its journal, and a restore
 * builds that world again and flies the journal from its start: the
 * flight step is deterministic, so the state is the snapshot's bit for
 * bit (the helicopter, the gear, the SAS, the rotor's states, the
 * turbulence's field and the ship's motion at its time), without a copy
 * of each stage's internals; its cost is the steps flown again.
 *
 * World changes off the step. A world change (a reset, a load, a
 * restore, a reset to the hover or the deck, a reposition, a new WOD
 * direction or sea state) costs a world build: measured 1 to 10 ms for a
 * bare world (test_loop), 36 to 55 ms on average and up to 0.4 s on a
 * loaded machine for disim fly's (the aircraft, a field read from its
 * file, the seaway of sea state 5: bench_loop_burst), a restore 25 to 70
 * us a step flown again (seconds for a long one). With a builder
 * (opts.builder) the loop's worker thread (sim/loop_worker.c) builds the
 * new world while the old one flies on, and the loop swaps it in between
 * two steps and answers the control then: in real time at the start of
 * the first pass after the build ended (SIM_LOOP_SWAP_READY: before the
 * messages of that pass are taken), as fast as it can at the end of the
 * controls of the pass that asked, waiting for the worker there
 * (SIM_LOOP_SWAP_PASS: the same step whatever the timing). One at a
 * time: a world change that arrives while one is being built is refused,
 * busy (the latest does not supersede the one under way: each control is
 * answered, at once or at its swap). What stays in the step is bounded
 * and small (Release, test_loop): the WOD's speed and the turbulence in
 * flight (under 10 us), a snapshot (a copy of its journal, at most
 * snapshot_max_s of inputs: 4 to 10 us for 150 steps), pause and resume. A token bucket over the
 * run clock (opts.change_burst at once, one more each
 * opts.change_interval_s) limits the world changes asked, with or
 * without the worker; the excess is refused with the reason and counted.
 * Each world change carried out (swapped in, or refused by its build) is
 * marked in the log where it happened (SIM_LOOP_CH_CONTROL_DONE, log
 * only); a replay queues the marks with the controls in the log's order
 * and swaps at each (LOOP_SWAP_LOGGED), so the busy refusals, the rate
 * limit and the swap steps of a real-time run come again whatever the
 * replay's timing. A log without marks (its worlds built in the step)
 * is replayed so (LOOP_SWAP_NOW: the build waited for at once, one a
 * step, no rate limit).
 *
 * A received buffer goes through disim_lcm_check_raw before lcm-gen's
 * decoder sees it, then through disim_lcm_check_sim_control (NaN, range):
 * lcm_types/lcm_types.c; pilot_input_t goes to the stations' rules
 * (sim/pilots.c).
 *
 * References: LCM, Huang, Olson and Moore, "LCM: Lightweight
 * Communications and Marshalling", IROS 2010; the log format:
 * lcm-proj.github.io/lcm/content/log-file-format.html.
 */
#include "sim.h"
#include "disim_lcm.h"
#include "loop_worker.h"

#include <lcm/eventlog.h>
#include <lcm/lcm.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

/* ---------------------------------------------------------------- loop */
#define LOOP_CTL_MAX 64
#define LOOP_SWAPS_MAX 16 /* a replay's marks of world changes carried out, queued with the controls */
/* The queue's own entries beside the commands of sim_control_t: a
 * replayed log's mark that the world change under way was carried out
 * here (SIM_LOOP_CH_CONTROL_DONE). */
#define LOOP_SWAP_MARK 100
/* The swap of a replay beside SIM_LOOP_SWAP_*: where its log marks it
 * (LOGGED), or, a log with no marks (a disim that built in the step),
 * at once in the step that asked, one build a step, no rate limit (NOW). */
enum { LOOP_SWAP_LOGGED = 10, LOOP_SWAP_NOW };
#define LOOP_BUF 16384

#define LOOP_SNAP_MAX 16
#define LOOP_SNAP_NAME 32

typedef struct ctl {
    long long seq;
    int command;
    char path[SIM_PATH_MAX];
    double pos_S_m[3], heading_rad, wod_speed_mps, wod_dir_rad;
    int sea_state, turbulence;
    char name[LOOP_SNAP_NAME];
} ctl;

/* A change made in flight (the WOD's speed, the turbulence), before the
 * journal's step at. */
typedef struct jev {
    long long at;
    int command;
    double v[2];
} jev;

/* A snapshot: the world it was taken in (its scenario and the setup it
 * was built with), the inputs of every step flown in it since it was
 * built, the changes made in flight, and the setup then. */
typedef struct snap {
    char name[LOOP_SNAP_NAME];
    char path[SIM_PATH_MAX];
    sim_loop_setup base, setup;
    long long n;
    sim_flight_inputs *in;
    int nev;
    jev *ev;
} snap;

/* A world change on the worker: what to build (all copied: the worker
 * reads nothing of the loop's but a restore's snapshot, which is not
 * replaced while the job is under way), then what it built. */
typedef struct job {
    sim_loop_builder b;
    void *user;
    ctl c;
    char path[SIM_PATH_MAX];
    sim_loop_setup s;
    int has_setup;
    const snap *sn; /* a restore's */
    double t0_s;    /* wall time asked */
    int rc;         /* 0 built, else e says why not */
    core_err e;
    void *world;
    sim_loop_world w;
    sim_flight_inputs *jr; /* a restore's journal and changes in flight, its snapshot's */
    jev *ev;
} job;

struct sim_loop {
    sim_loop_opts o;
    sim_loop_world w;
    sim_loop_build_fn build;
    void *user;
    const core_log *log;
    char scenario_path[SIM_PATH_MAX];
    char log_path[SIM_PATH_MAX + 32], replay_path[SIM_PATH_MAX];
    lcm_t *lc;
    lcm_subscription_t *sub_pilot, *sub_ctl;
    sim_log_writer *elog; /* the run's log (sim/log.c), NULL: none */
    lcm_eventlog_t *replay;
    lcm_eventlog_event_t *pending; /* the next replayed event, not yet due */
    int replay_done;
    long long builds; /* worlds built or tried (a reset, a load, a rebuild, a restore) */
    long long replay_size; /* the bytes framed at create: nothing past them is read */
    sim_pilots *pilots;
    sim_pacer *pacer;
    long long run_step, nsteps, state_every;
    int paused, held;
    unsigned flags, last_flags;
    int last_active, last_paused, dirty;
    ctl q[LOOP_CTL_MAX + LOOP_SWAPS_MAX];
    int nq, nctl; /* entries, controls among them */
    /* the worker (opts.builder), the world change under way on it, where
     * it is swapped in (SIM_LOOP_SWAP_READY, _PASS, LOOP_SWAP_LOGGED,
     * _NOW); the rate limit's changes allowed now as of run time
     * tokens_t_s; the counts */
    loop_worker *worker;
    job *job;
    int swap;
    double tokens, tokens_t_s;
    long long builds_in_step, builds_on_worker, refused_busy, refused_rate;
    long long seq_heli, seq_ship, seq_status, seq_info, seq_source;
    char source_id[SIM_STATION_ID_MAX]; /* opts.pilot_source_id ("" the stations fly) */
    long long sent, received, logged, control_refused;
    char message[256];
    double status_wall_s;
    sim_flight_out out;
    int fatal;
    core_err ferr;
    int crashed;           /* the flight ended (a crash, a roll-over): nothing more steps */
    char crash_msg[256];
    /* the world's setup (the instructor's settings it was built with) and
     * the journal: the inputs of every step flown since it was built (full:
     * past opts.snapshot_max_s, no snapshot of it) */
    sim_loop_setup setup, base; /* now, and as the world was built */
    sim_flight_inputs *jr;
    long long njr, capjr, jr_max;
    int jr_full;
    jev *ev; /* the changes made in flight since the world was built */
    int nev, capev;
    int live; /* the last control was carried out in flight */
    snap snaps[LOOP_SNAP_MAX];
    int nsnaps;
    /* the last control answered (sim_status_t control_*) */
    long long ack_seq;
    int ack_cmd, ack_result;
    char ack_msg[256];
    double ack_apply_s;
    int ack_unsent, acks_pass; /* an answer not yet published; answers published early in this pass */
    unsigned char buf[LOOP_BUF];
};

void sim_loop_opts_default(sim_loop_opts *o)
{
    memset(o, 0, sizeof *o);
    o->rate_hz = 200.0;
    o->realtime = 1;
    o->duration_s = 60.0;
    o->state_rate_hz = 50.0;
    o->status_period_s = 1.0;
    o->snapshot_max_s = 600.0;
    o->change_burst = 5;
    o->change_interval_s = 1.0;
    sim_pilots_opts_default(&o->pilots);
}

void sim_loop_setup_default(sim_loop_setup *s)
{
    memset(s, 0, sizeof *s);
    s->start = -1;
    s->wod_speed_mps = s->wod_dir_rad = NAN;
    s->sea_state = -1;
    s->turbulence = -1;
}

static double wall_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int64_t run_us(const sim_loop *l) { return (int64_t)llround((double)l->run_step * 1e6 / l->o.rate_hz); }
static double run_t(const sim_loop *l) { return (double)l->run_step / l->o.rate_hz; }

/* One event into the log; a failure is fatal and kept for the caller. */
static void log_event(sim_loop *l, const char *channel, const void *data, int size)
{
    if (!l->elog || l->fatal)
        return;
    if (sim_log_writer_write(l->elog, channel, run_us(l), data, size, &l->ferr) != 0) {
        l->fatal = 1;
        return;
    }
    l->logged++;
}

static void send_buf(sim_loop *l, const char *channel, const void *data, int size)
{
    if (l->lc) {
        if (lcm_publish(l->lc, channel, data, (unsigned)size) != 0 && !l->fatal) {
            l->fatal = 1;
            core_err_set(&l->ferr, -1, "LCM: cannot publish on %s", channel);
        }
        l->sent++;
    }
    log_event(l, channel, data, size);
}

#define SEND(l, T, chan, msg)                                                                                       \
    do {                                                                                                            \
        int n_ = disim_##T##_encoded_size(msg);                                                                     \
        if (n_ > LOOP_BUF || disim_##T##_encode((l)->buf, 0, n_, msg) != n_) {                                      \
            if (!(l)->fatal)                                                                                        \
                core_err_set(&(l)->ferr, -1, "LCM: cannot encode %s", #T);                                          \
            (l)->fatal = 1;                                                                                         \
        } else                                                                                                      \
            send_buf(l, chan, (l)->buf, n_);                                                                        \
    } while (0)

/* ---- received: taken by the rules and the control queue */
static void got_pilot(sim_loop *l, const void *data, int size)
{
    l->received++;
    char why[256];
    if (sim_pilots_offer(l->pilots, data, size, run_t(l), why, sizeof why) != 0)
        core_log_msg(l->log, CORE_LOG_DEBUG, "refused: %s", why);
}

static void publish_status(sim_loop *l, int state);
static int status_state(const sim_loop *l);

/* Several controls answered in one pass: each answer published before the
 * next replaces it, up to LOOP_ACKS_PASS_MAX a pass (a flood of controls
 * is not echoed as a flood of statuses; past that the answers are
 * counted, the last published). */
#define LOOP_ACKS_PASS_MAX 16
static void ack_flush(sim_loop *l)
{
    if (l->ack_unsent && (l->lc || l->elog) && l->acks_pass < LOOP_ACKS_PASS_MAX) {
        publish_status(l, status_state(l));
        l->acks_pass++;
    }
}

static void refuse_ctl(sim_loop *l, long long seq, int command, const char *why_raw)
{
    ack_flush(l);
    char why[512]; /* a path or a name from the network, made safe to print and send on */
    core_escape(why_raw, why, sizeof why);
    l->control_refused++;
    snprintf(l->message, sizeof l->message, "%.250s", why);
    l->ack_seq = seq;
    l->ack_cmd = command;
    l->ack_result = DISIM_SIM_STATUS_T_CONTROL_REFUSED;
    snprintf(l->ack_msg, sizeof l->ack_msg, "%.250s", why);
    l->ack_apply_s = 0.0;
    l->ack_unsent = 1;
    l->dirty = 1;
    core_log_msg(l->log, CORE_LOG_WARN, "sim control %s (seq %lld) refused: %s", sim_ios_command_name(command), seq,
                 why);
}

static void got_ctl(sim_loop *l, const void *data, int size)
{
    l->received++;
    char e[256];
    unsigned char up[1024]; /* a control of an older disim's log, read as the newest */
    int un = disim_lcm_upgrade("sim_control_t", data, size, up, (int)sizeof up);
    if (un > 0) {
        data = up;
        size = un;
    }
    if (disim_lcm_check_raw("sim_control_t", data, size, e, sizeof e) != 0) {
        refuse_ctl(l, -1, 0, e);
        return;
    }
    disim_sim_control_t m;
    memset(&m, 0, sizeof m);
    if (disim_sim_control_t_decode(data, 0, size, &m) != size) {
        refuse_ctl(l, -1, 0, "sim_control_t: not decoded");
        return;
    }
    if (disim_lcm_check_sim_control(&m, e, sizeof e) != 0)
        refuse_ctl(l, m.seq, m.command, e);
    else if (l->nctl == LOOP_CTL_MAX)
        refuse_ctl(l, m.seq, m.command, "sim_control_t: too many controls at once");
    else if (strlen(m.scenario_path) >= SIM_PATH_MAX)
        refuse_ctl(l, m.seq, m.command, "sim_control_t.scenario_path: too long");
    else if (strlen(m.name) >= LOOP_SNAP_NAME)
        refuse_ctl(l, m.seq, m.command, "sim_control_t.name: longer than 31 characters");
    else {
        l->nctl++;
        ctl *c = &l->q[l->nq++];
        c->seq = m.seq;
        c->command = m.command;
        snprintf(c->path, sizeof c->path, "%s", m.scenario_path);
        memcpy(c->pos_S_m, m.pos_S_m, sizeof c->pos_S_m);
        c->heading_rad = m.heading_rad;
        c->wod_speed_mps = m.wod_speed_mps;
        c->wod_dir_rad = m.wod_dir_rad;
        c->sea_state = m.sea_state;
        c->turbulence = m.turbulence;
        snprintf(c->name, sizeof c->name, "%s", m.name);
    }
    disim_sim_control_t_decode_cleanup(&m);
}

static void on_raw(const lcm_recv_buf_t *rb, const char *channel, void *user)
{
    sim_loop *l = user;
    log_event(l, channel, rb->data, (int)rb->data_size);
    if (!strcmp(channel, DISIM_CH_PILOT_INPUT))
        got_pilot(l, rb->data, (int)rb->data_size);
    else
        got_ctl(l, rb->data, (int)rb->data_size);
}

/* A replayed log's mark of a world change carried out: queued with the
 * controls, so that the swap comes where it came among them. */
static void got_mark(sim_loop *l, const void *data, int size)
{
    disim_sim_control_t m;
    memset(&m, 0, sizeof m);
    if (disim_lcm_check_raw("sim_control_t", data, size, NULL, 0) != 0 ||
        disim_sim_control_t_decode(data, 0, size, &m) != size) {
        core_log_msg(l->log, CORE_LOG_WARN, "replay: a mark of a world change not read: passed over");
        return;
    }
    if (l->nq < LOOP_CTL_MAX + LOOP_SWAPS_MAX) {
        ctl *c = &l->q[l->nq++];
        memset(c, 0, sizeof *c);
        c->seq = m.seq;
        c->command = LOOP_SWAP_MARK;
    }
    disim_sim_control_t_decode_cleanup(&m);
}

/* The replayed log's events due at this run step (and earlier). */
static int replay_feed(sim_loop *l)
{
    int fed = 0;
    while (!l->replay_done) {
        if (!l->pending && ((long long)ftello(l->replay->f) >= l->replay_size ||
                            !(l->pending = lcm_eventlog_read_next_event(l->replay)))) {
            l->replay_done = 1;
            break;
        }
        lcm_eventlog_event_t *ev = l->pending;
        long long step = llround((double)ev->timestamp * l->o.rate_hz / 1e6);
        if (step > l->run_step)
            break;
        int pilot = !strcmp(ev->channel, DISIM_CH_PILOT_INPUT), control = !strcmp(ev->channel, DISIM_CH_SIM_CONTROL);
        if (l->swap == LOOP_SWAP_LOGGED && !strcmp(ev->channel, SIM_LOOP_CH_CONTROL_DONE)) {
            log_event(l, ev->channel, ev->data, ev->datalen); /* at its place among the inputs, as it came */
            got_mark(l, ev->data, ev->datalen);
        } else if (pilot || control) {
            log_event(l, ev->channel, ev->data, ev->datalen);
            if (pilot)
                got_pilot(l, ev->data, ev->datalen);
            else
                got_ctl(l, ev->data, ev->datalen);
            fed++;
        }
        lcm_eventlog_free_event(ev);
        l->pending = NULL;
    }
    return fed;
}

/* Take what arrived; wait up to timeout_ms for the first message. */
static void take_received(sim_loop *l, int timeout_ms)
{
    int fed = l->replay ? replay_feed(l) : 0;
    if (!l->lc)
        return;
    int wait = fed || (l->replay && !l->replay_done && l->paused) ? 0 : timeout_ms;
    for (int i = 0; i < 1000; i++) {
        if (lcm_handle_timeout(l->lc, i == 0 ? wait : 0) <= 0)
            break;
    }
}

/* ---- published */
static void publish_states(sim_loop *l, const sim_flight_out *o)
{
    disim_heli_state_t h;
    memset(&h, 0, sizeof h);
    h.utime = (int64_t)llround(o->t_s * 1e6);
    h.seq = l->seq_heli++;
    for (int i = 0; i < 3; i++) {
        h.pos_E_m[i] = o->pos_E_m[i];
        h.vel_E_mps[i] = o->vel_E_mps[i];
        h.pos_S_m[i] = o->pos_S_m[i];
        h.vel_S_mps[i] = o->vel_S_mps[i];
        h.rates_B_radps[i] = o->rate_B_radps[i];
    }
    core_euler e = {o->euler_E_rad[0], o->euler_E_rad[1], o->euler_E_rad[2]};
    core_quat q = core_quat_from_euler(e);
    h.quat_EB[0] = q.w, h.quat_EB[1] = q.x, h.quat_EB[2] = q.y, h.quat_EB[3] = q.z;
    h.roll_rad = e.phi_rad, h.pitch_rad = e.theta_rad, h.yaw_rad = e.psi_rad;
    h.collective_pct = o->ctl.collective_pct;
    h.long_cyclic_pct = o->ctl.long_cyclic_pct;
    h.lat_cyclic_pct = o->ctl.lat_cyclic_pct;
    h.pedal_pct = o->ctl.pedal_pct;
    /* the main rotor, the deck contact and each leg's load along the deck
     * normal (no legs: a flight without the gear) */
    h.rotor_thrust_N = o->rotor_thrust_N;
    h.rotor_power_W = o->rotor_power_W;
    h.on_deck = o->on_deck ? 1 : 0;
    h.n_gear = (int8_t)o->nlegs;
    double gear_N[HFM_GEAR_MAX_LEGS];
    for (int i = 0; i < o->nlegs && i < HFM_GEAR_MAX_LEGS; i++)
        gear_N[i] = o->gear_load_N[i];
    h.gear_load_N = gear_N;
    SEND(l, heli_state_t, DISIM_CH_HELI_STATE, &h);

    disim_ship_state_t s;
    memset(&s, 0, sizeof s);
    s.utime = h.utime;
    s.seq = l->seq_ship++;
    const sim_ship_frame *fr = &o->ship;
    sim_ship_state ss;
    sim_ship_point sp;
    core_vec3 spot = {0.0, 0.0, 0.0}; /* the landing spot: S's origin */
    if (l->w.motion && sim_ship_motion_at(l->w.motion, o->t_s, &ss) == 0 &&
        sim_ship_motion_point(l->w.motion, o->t_s, spot, &sp) == 0) {
        s.pos_E_m[0] = ss.pose.pos_E_m.x, s.pos_E_m[1] = ss.pose.pos_E_m.y, s.pos_E_m[2] = ss.pose.pos_E_m.z;
        s.vel_E_mps[0] = ss.vel_E_mps.x, s.vel_E_mps[1] = ss.vel_E_mps.y, s.vel_E_mps[2] = ss.vel_E_mps.z;
        s.quat_ES[0] = ss.pose.q_EF.w, s.quat_ES[1] = ss.pose.q_EF.x;
        s.quat_ES[2] = ss.pose.q_EF.y, s.quat_ES[3] = ss.pose.q_EF.z;
        s.roll_rad = ss.att.phi_rad, s.pitch_rad = ss.att.theta_rad, s.yaw_rad = ss.att.psi_rad;
        s.rates_S_radps[0] = ss.omega_S_radps.x, s.rates_S_radps[1] = ss.omega_S_radps.y;
        s.rates_S_radps[2] = ss.omega_S_radps.z;
        s.spot_pos_E_m[0] = sp.pos_E_m.x, s.spot_pos_E_m[1] = sp.pos_E_m.y, s.spot_pos_E_m[2] = sp.pos_E_m.z;
        s.spot_vel_E_mps[0] = sp.vel_E_mps.x, s.spot_vel_E_mps[1] = sp.vel_E_mps.y;
        s.spot_vel_E_mps[2] = sp.vel_E_mps.z;
        s.spot_acc_E_mps2[0] = sp.acc_E_mps2.x, s.spot_acc_E_mps2[1] = sp.acc_E_mps2.y;
        s.spot_acc_E_mps2[2] = sp.acc_E_mps2.z;
    } else {
        /* the frame alone: its origin moving steadily, no rates */
        core_mat3 C;
        memcpy(C.m, fr->C_ES, sizeof C.m);
        core_euler a = core_mat3_to_euler(C);
        core_quat qs = core_quat_from_euler(a);
        s.quat_ES[0] = qs.w, s.quat_ES[1] = qs.x, s.quat_ES[2] = qs.y, s.quat_ES[3] = qs.z;
        s.roll_rad = a.phi_rad, s.pitch_rad = a.theta_rad, s.yaw_rad = a.psi_rad;
        for (int i = 0; i < 3; i++) {
            s.pos_E_m[i] = s.spot_pos_E_m[i] = fr->origin_E_m[i];
            s.vel_E_mps[i] = s.spot_vel_E_mps[i] = fr->mean_vel_E_mps[i];
        }
    }
    SEND(l, ship_state_t, DISIM_CH_SHIP_STATE, &s);
}

/* What the world was built from (sim_run_info), the loop's rates added. */
static void publish_run_info(sim_loop *l)
{
    const sim_run_info *ri = &l->w.info;
    disim_run_info_t m;
    memset(&m, 0, sizeof m);
    m.utime = (int64_t)llround(l->out.t_s * 1e6);
    m.seq = l->seq_info++;
    m.scenario_path = (char *)ri->scenario_path;
    m.scenario = (char *)ri->scenario;
    m.aircraft_path = (char *)ri->aircraft_path;
    m.ship_path = (char *)ri->ship_path;
    m.seed = (int64_t)ri->seed;
    m.sea_state = (int8_t)ri->sea.state;
    m.ship_speed_mps = ri->sea.ship_speed_mps;
    m.wave_dir_rad = ri->sea.wave_dir_rad;
    m.course_rad = ri->sea.course_rad;
    m.spectrum = (int8_t)ri->sea.spectrum;
    m.n_waves = ri->sea.n_waves;
    m.wod_speed_mps = ri->wod_speed_mps;
    m.wod_dir_rad = ri->wod_dir_rad;
    m.rate_hz = l->o.rate_hz;
    m.state_rate_hz = l->o.rate_hz / (double)l->state_every;
    SEND(l, run_info_t, DISIM_CH_RUN_INFO, &m);
}

/* The inputs of this step of a pilot of the caller's, as a station's
 * message. */
static void publish_source(sim_loop *l, const sim_flight_inputs *in)
{
    disim_pilot_input_t m;
    memset(&m, 0, sizeof m);
    m.utime = (int64_t)llround(l->out.t_s * 1e6);
    m.station_id = l->source_id;
    m.seq = l->seq_source++;
    m.collective_pct = in->ctl.collective_pct;
    m.long_cyclic_pct = in->ctl.long_cyclic_pct;
    m.lat_cyclic_pct = in->ctl.lat_cyclic_pct;
    m.pedal_pct = in->ctl.pedal_pct;
    SEND(l, pilot_input_t, DISIM_CH_PILOT_INPUT, &m);
}


static void publish_status(sim_loop *l, int state)
{
    sim_loop_report r;
    sim_loop_report_get(l, &r);
    disim_sim_status_t m;
    memset(&m, 0, sizeof m);
    m.utime = (int64_t)llround(l->out.t_s * 1e6);
    m.seq = l->seq_status++;
    m.sim_time_s = l->out.t_s;
    m.rate_hz = r.pace.rate_hz;
    m.real_time_factor = r.pace.realtime_factor;
    m.overruns = r.pace.overruns;
    m.state = (int8_t)state;
    m.scenario = l->w.scenario;
    char *ids[SIM_PILOTS_MAX];
    int64_t last[SIM_PILOTS_MAX], rec[SIM_PILOTS_MAX], refd[SIM_PILOTS_MAX], gaps[SIM_PILOTS_MAX];
    sim_pilot_station st[SIM_PILOTS_MAX];
    int n = sim_pilots_count(l->pilots);
    for (int i = 0; i < n; i++) {
        sim_pilots_station(l->pilots, i, &st[i]);
        ids[i] = st[i].id;
        last[i] = st[i].last_seq;
        rec[i] = st[i].received;
        refd[i] = st[i].refused;
        gaps[i] = st[i].gaps;
    }
    m.n_stations = n;
    m.station_ids = ids;
    m.station_last_seq = last;
    m.station_received = rec;
    m.station_refused = refd;
    m.station_gaps = gaps;
    m.active_station = sim_pilots_active(l->pilots);
    m.refused_unknown = sim_pilots_refused_unknown(l->pilots);
    m.control_refused = l->control_refused;
    m.flags = (int32_t)r.flags;
    m.step_p50_s = r.pace.step_p50_s;
    m.step_p99_s = r.pace.step_p99_s;
    m.step_max_s = r.pace.step_max_s;
    m.message = l->message;
    m.control_seq = l->ack_seq;
    m.control_command = (int8_t)l->ack_cmd;
    m.control_result = (int8_t)l->ack_result;
    m.control_message = l->ack_msg;
    m.control_apply_s = l->ack_apply_s;
    SEND(l, sim_status_t, DISIM_CH_SIM_STATUS, &m);
    l->status_wall_s = wall_s();
    l->last_flags = r.flags;
    l->last_active = m.active_station;
    l->last_paused = l->paused;
    l->dirty = 0;
    l->ack_unsent = 0;
}

static unsigned loop_flags(const sim_loop *l)
{
    unsigned f = 0;
    if (l->held)
        f |= DISIM_SIM_STATUS_T_FLAG_INPUT_HELD;
    sim_pilots_blend_info b;
    sim_pilots_blend(l->pilots, &b);
    if (b.blending)
        f |= DISIM_SIM_STATUS_T_FLAG_CONTROLS_BLENDING;
    if (l->out.air_flags & SIM_AIR_FREE_STREAM)
        f |= DISIM_SIM_STATUS_T_FLAG_FREE_STREAM;
    if (l->out.air_flags & SIM_AIR_BLENDING)
        f |= DISIM_SIM_STATUS_T_FLAG_FIELD_BLENDING;
    if (l->out.air_flags & SIM_AIR_INTERACTION)
        f |= DISIM_SIM_STATUS_T_FLAG_ROTOR_INTERACTION;
    static const unsigned grid_flag[] = {DISIM_SIM_STATUS_T_FLAG_FIELD_COARSE, DISIM_SIM_STATUS_T_FLAG_FIELD_DEFAULT,
                                         DISIM_SIM_STATUS_T_FLAG_FIELD_FINE, DISIM_SIM_STATUS_T_FLAG_FIELD_QUICK};
    if (l->out.air_grid >= 0 && l->out.air_grid <= CORE_GRID_QUICK)
        f |= grid_flag[l->out.air_grid];
    if (l->out.on_deck)
        f |= DISIM_SIM_STATUS_T_FLAG_ON_DECK;
    if (l->out.contact_flags & SIM_CONTACT_SLIDE)
        f |= DISIM_SIM_STATUS_T_FLAG_SLIDE;
    if (l->out.contact_flags & SIM_CONTACT_TIP)
        f |= DISIM_SIM_STATUS_T_FLAG_TIP_OVER;
    if (l->out.contact_flags & SIM_CONTACT_CRASH)
        f |= DISIM_SIM_STATUS_T_FLAG_CRASH;
    if (l->paused)
        f |= DISIM_SIM_STATUS_T_FLAG_PAUSED;
    if (l->replay)
        f |= DISIM_SIM_STATUS_T_FLAG_REPLAY;
    /* the SAS, so that a log says how it was flown (the replay pilot flies it alike) */
    f |= sim_sas_engaged(sim_flight_sas(l->w.flight)) ? DISIM_SIM_STATUS_T_FLAG_SAS : DISIM_SIM_STATUS_T_FLAG_SAS_OFF;
    return f;
}

/* The deadlines from now: the run's pacer created, or rebased (its
 * counts and times over the whole run kept). */
static int new_pacer(sim_loop *l, core_err *err)
{
    if (l->pacer) {
        sim_pacer_rebase(l->pacer);
        return 0;
    }
    return (l->pacer = sim_pacer_create(l->o.rate_hz, l->o.realtime, err)) ? 0 : -1;
}

sim_loop *sim_loop_create(const sim_loop_opts *o, const sim_loop_world *w, sim_loop_build_fn build, void *user,
                          const core_log *log, core_err *err)
{
    if (!(o->rate_hz >= 1.0 && o->rate_hz <= 100000.0) || !(o->duration_s >= 0.0) ||
        !(o->snapshot_max_s >= 0.0 && o->snapshot_max_s <= 86400.0) ||
        !(o->state_rate_hz > 0.0 && o->state_rate_hz <= o->rate_hz) || !(o->status_period_s > 0.0)) {
        core_err_set(err, -1, "flight loop: rate %g Hz, duration %g s, state rate %g Hz, status every %g s: "
                     "expected a rate of 1 to 100000 Hz, a duration >= 0, a state rate above 0 and at most the "
                     "loop's, a status period above 0, a snapshot length of 0 to 86400 s", o->rate_hz, o->duration_s, o->state_rate_hz,
                     o->status_period_s);
        return NULL;
    }
    if (!(o->change_burst >= 1 && o->change_burst <= 1000) ||
        !(o->change_interval_s >= 0.0 && o->change_interval_s <= 3600.0) ||
        (o->builder.prepare && (!o->builder.install || !o->builder.drop)) || o->swap < SIM_LOOP_SWAP_AUTO ||
        o->swap > SIM_LOOP_SWAP_PASS) {
        core_err_set(err, -1, "flight loop: world changes %d at once, one more every %g s: expected 1 to 1000 and 0 "
                     "to 3600 s; a builder with prepare, install and drop; a swap of SIM_LOOP_SWAP_*",
                     o->change_burst, o->change_interval_s);
        return NULL;
    }
    if (!w || !w->flight || !build || !o->scenario_path || strlen(o->scenario_path) >= SIM_PATH_MAX ||
        (o->log_path && strlen(o->log_path) >= SIM_PATH_MAX) ||
        (o->replay_path && strlen(o->replay_path) >= SIM_PATH_MAX)) {
        core_err_set(err, -1, "flight loop: expected a flight, a build function and paths under %d characters",
                     SIM_PATH_MAX);
        return NULL;
    }
    sim_loop *l = calloc(1, sizeof *l);
    if (!l) {
        core_err_set(err, -1, "flight loop: out of memory");
        return NULL;
    }
    l->o = *o;
    l->w = *w;
    l->build = build;
    l->user = user;
    l->log = log;
    l->last_active = -1;
    l->ack_seq = -1;
    sim_loop_setup_default(&l->setup);
    l->tokens = (double)o->change_burst;
    l->swap = o->swap == SIM_LOOP_SWAP_AUTO ? (o->realtime ? SIM_LOOP_SWAP_READY : SIM_LOOP_SWAP_PASS) : o->swap;
    l->jr_max = llround(o->snapshot_max_s * o->rate_hz);
    snprintf(l->scenario_path, sizeof l->scenario_path, "%s", o->scenario_path);
    l->o.scenario_path = l->scenario_path;
    if (o->pilot_source_id) {
        core_err e = {0};
        if (sim_station_id_check(o->pilot_source_id, &e) != 0) {
            core_err_set(err, -1, "flight loop: pilot_source_id: %s", e.msg);
            free(l);
            return NULL;
        }
        snprintf(l->source_id, sizeof l->source_id, "%s", o->pilot_source_id);
        l->o.pilot_source_id = l->source_id;
    }
    l->nsteps = llround(o->duration_s * o->rate_hz);
    l->state_every = llround(o->rate_hz / o->state_rate_hz);
    if (l->state_every < 1)
        l->state_every = 1;
    sim_flight_state(w->flight, &l->out);
    if (!(l->pilots = sim_pilots_create(&o->pilots, err)))
        goto fail;
    if (o->replay_path) {
        snprintf(l->replay_path, sizeof l->replay_path, "%s", o->replay_path);
        l->o.replay_path = l->replay_path;
        sim_log_frames fr; /* framed whole before LCM's reader sees it (sim_log_check_frames) */
        if (sim_log_check_frames(o->replay_path, &fr, err) != 0)
            goto fail;
        l->replay_size = fr.size;
        l->swap = fr.n_marks > 0 ? LOOP_SWAP_LOGGED : LOOP_SWAP_NOW;
        if (fr.n_inputs == 0) {
            core_err_set(err, -1, "%s: %ld events and no pilot_input_t or sim_control_t: nothing to replay (a log "
                         "of disim fly --log with a station's inputs)", o->replay_path, fr.n_events);
            goto fail;
        }
        if (!(l->replay = lcm_eventlog_create(o->replay_path, "r"))) {
            core_err_set(err, -1, "%s: cannot read the LCM log", o->replay_path);
            goto fail;
        }
    }
    if (o->log_path) {
        snprintf(l->log_path, sizeof l->log_path, "%s", o->log_path);
        l->o.log_path = l->log_path;
        if (!(l->elog = sim_log_writer_create(o->log_path, err)))
            goto fail;
    }
    if (o->lcm) {
        if (!(l->lc = lcm_create(disim_lcm_url(o->lcm_url)))) {
            core_err_set(err, -1, "LCM: cannot open '%s' (lcm_create failed)", o->lcm_url ? o->lcm_url : "the default URL");
            goto fail;
        }
        l->o.lcm_url = NULL; /* the caller's string need not outlive create */
        /* replaying, the log's inputs fly: live stations and controls are
         * not listened to */
        if (!l->replay) {
            /* a pilot of the caller's flies: stations are not listened to */
            if (!o->pilot_source_id)
                l->sub_pilot = lcm_subscribe(l->lc, DISIM_CH_PILOT_INPUT, on_raw, l);
            l->sub_ctl = lcm_subscribe(l->lc, DISIM_CH_SIM_CONTROL, on_raw, l);
            if ((!o->pilot_source_id && !l->sub_pilot) || !l->sub_ctl) {
                core_err_set(err, -1, "LCM: cannot subscribe");
                goto fail;
            }
        }
    }
    if (o->builder.prepare && !(l->worker = loop_worker_create(err)))
        goto fail;
    if (new_pacer(l, err) != 0)
        goto fail;
    l->dirty = 1; /* the first status at once */
    if (l->lc || l->elog) /* the log's first event: what the run is flown from */
        publish_run_info(l);
    return l;
fail:
    sim_loop_destroy(l);
    return NULL;
}

void sim_loop_destroy(sim_loop *l)
{
    if (!l)
        return;
    loop_worker_destroy(l->worker); /* the job under way finished, the worlds swapped out freed */
    if (l->job) {
        if (l->job->rc == 0)
            l->o.builder.drop(l->user, l->job->world);
        free(l->job->jr);
        free(l->job->ev);
        free(l->job);
    }
    if (l->lc) {
        if (l->sub_pilot)
            lcm_unsubscribe(l->lc, l->sub_pilot);
        if (l->sub_ctl)
            lcm_unsubscribe(l->lc, l->sub_ctl);
        lcm_destroy(l->lc);
    }
    sim_log_writer_destroy(l->elog); /* an uncommitted log's temporary file removed */
    if (l->pending)
        lcm_eventlog_free_event(l->pending);
    if (l->replay)
        lcm_eventlog_destroy(l->replay);
    sim_pacer_destroy(l->pacer);
    sim_pilots_destroy(l->pilots);
    for (int i = 0; i < l->nsnaps; i++) {
        free(l->snaps[i].in);
        free(l->snaps[i].ev);
    }
    free(l->jr);
    free(l->ev);
    free(l);
}

/* ---- the controls: carried out between steps, each answered */
static void accept_ctl(sim_loop *l, const ctl *c, double t0_s, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
static void accept_ctl(sim_loop *l, const ctl *c, double t0_s, const char *fmt, ...)
{
    ack_flush(l);
    va_list ap;
    va_start(ap, fmt);
    char raw[sizeof l->ack_msg];
    vsnprintf(raw, sizeof raw, fmt, ap);
    va_end(ap);
    core_escape(raw, l->ack_msg, sizeof l->ack_msg);
    l->ack_unsent = 1;
    l->ack_seq = c->seq;
    l->ack_cmd = c->command;
    l->ack_result = DISIM_SIM_STATUS_T_CONTROL_ACCEPTED;
    l->ack_apply_s = wall_s() - t0_s;
    l->message[0] = '\0';
    l->dirty = 1;
    core_log_msg(l->log, CORE_LOG_INFO, "sim control %s (seq %lld): %s (applied in %.3f s)",
                 sim_ios_command_name(c->command), c->seq, l->ack_msg, l->ack_apply_s);
}

/* The step's inputs into the journal (NULL: held), while it is not full. */
static void journal_add(sim_loop *l, const sim_flight_inputs *in)
{
    if (l->jr_full || l->njr >= l->jr_max) {
        l->jr_full = 1;
        return;
    }
    if (l->njr == l->capjr) {
        long long cap = l->capjr ? 2 * l->capjr : 1024;
        if (cap > l->jr_max)
            cap = l->jr_max;
        sim_flight_inputs *p = realloc(l->jr, (size_t)cap * sizeof *p);
        if (!p) {
            l->jr_full = 1;
            return;
        }
        l->jr = p;
        l->capjr = cap;
    }
    sim_flight_inputs hold = {.hold = 1};
    l->jr[l->njr++] = in ? *in : hold;
}

/* A new world flying: its state, an empty journal, its run information
 * out (before its first state), the deadlines from now. */
static int world_started(sim_loop *l, const sim_loop_world *w, const char *path, const sim_loop_setup *s,
                         core_err *err)
{
    l->w = *w;
    if (path != l->scenario_path)
        snprintf(l->scenario_path, sizeof l->scenario_path, "%s", path);
    l->setup = l->base = *s;
    l->njr = 0;
    l->jr_full = 0;
    l->nev = 0;
    l->crashed = 0; /* a flight that ended flies again */
    l->crash_msg[0] = '\0';
    sim_flight_state(l->w.flight, &l->out);
    publish_run_info(l);
    return l->paused ? 0 : new_pacer(l, err);
}

/* Where the hover may be put: finite, within 1000 m of the spot and 300 m
 * above it, out of the ship and 2 m clear above it, above the sea. 0, or 1
 * with why. */
static int check_place(const core_ship *ship, const double p[3], char *why, size_t n)
{
    if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2]))
        return snprintf(why, n, "the position is not finite"), 1;
    if (fabs(p[0]) > 1000.0 || fabs(p[1]) > 1000.0 || p[2] < -300.0)
        return snprintf(why, n, "(%.1f, %.1f, %.1f) m: expected x and y within 1000 m of the spot, z above -300 m",
                        p[0], p[1], p[2]), 1;
    if (p[2] > ship->deck_height_m - 2.0)
        return snprintf(why, n, "(%.1f, %.1f, %.1f) m is under the sea or within 2 m of it (the sea is %.1f m "
                        "below the spot: z down)", p[0], p[1], p[2], ship->deck_height_m), 1;
    core_vec3 cg = {p[0], p[1], p[2]}, below = {p[0], p[1], p[2] + 2.0};
    if (core_ship_contains(ship, cg))
        return snprintf(why, n, "(%.1f, %.1f, %.1f) m is inside the ship", p[0], p[1], p[2]), 1;
    if (core_ship_contains(ship, below))
        return snprintf(why, n, "(%.1f, %.1f, %.1f) m is within 2 m above the ship (the wheels would be in it)",
                         p[0], p[1], p[2]), 1;
    return 0;
}

/* The setup a control asks for over the world's: 0, or 1 with why. */
static int ctl_setup(const sim_loop *l, const ctl *c, sim_loop_setup *s, char *why, size_t n)
{
    *s = l->setup;
    switch (c->command) {
    case DISIM_SIM_CONTROL_T_RESET_HOVER:
        s->start = SIM_START_HOVER;
        s->has_station = 0;
        return 0;
    case DISIM_SIM_CONTROL_T_RESET_DECK:
        if (!isnan(c->heading_rad) && !(fabs(c->heading_rad) <= 2.0 * CORE_PI))
            return snprintf(why, n, "heading %g rad: expected -2 pi to 2 pi", c->heading_rad), 1;
        s->start = SIM_START_DECK;
        s->has_station = 0;
        s->heading_rad = isnan(c->heading_rad) ? 0.0 : c->heading_rad;
        return 0;
    case DISIM_SIM_CONTROL_T_REPOSITION:
        if (!isnan(c->heading_rad) && c->heading_rad != 0.0)
            return snprintf(why, n, "heading %g rad: the hover trim holds the heading along the bow (give 0)",
                            c->heading_rad), 1;
        if (check_place(sim_flight_ship(l->w.flight), c->pos_S_m, why, n))
            return 1;
        s->start = SIM_START_HOVER;
        s->has_station = 1;
        memcpy(s->station_S_m, c->pos_S_m, sizeof s->station_S_m);
        return 0;
    case DISIM_SIM_CONTROL_T_SET_WOD:
        if (!(c->wod_speed_mps >= 0.0 && c->wod_speed_mps <= 80.0 * CORE_KT_TO_MPS) || !isfinite(c->wod_dir_rad))
            return snprintf(why, n, "WOD %g m/s from %g rad: expected 0 to %.1f m/s (80 kt) from a finite direction",
                            c->wod_speed_mps, c->wod_dir_rad, 80.0 * CORE_KT_TO_MPS), 1;
        s->wod_speed_mps = c->wod_speed_mps;
        s->wod_dir_rad = core_wod_wrap_deg(c->wod_dir_rad * CORE_RAD_TO_DEG) * CORE_DEG_TO_RAD;
        return 0;
    case DISIM_SIM_CONTROL_T_SET_SEA:
        if (c->sea_state < 0 || c->sea_state > 6)
            return snprintf(why, n, "sea state %d: expected 0 to 6", c->sea_state), 1;
        s->sea_state = c->sea_state;
        return 0;
    case DISIM_SIM_CONTROL_T_SET_TURBULENCE:
        if (c->turbulence != 0 && c->turbulence != 1)
            return snprintf(why, n, "turbulence %d: expected 0 (off) or 1 (on)", c->turbulence), 1;
        s->turbulence = c->turbulence;
        return 0;
    default:
        return snprintf(why, n, "not a setup"), 1;
    }
}

static int snap_find(const sim_loop *l, const char *name)
{
    for (int i = 0; i < l->nsnaps; i++)
        if (!strcmp(l->snaps[i].name, name))
            return i;
    return -1;
}

static int name_ok(const char *name)
{
    if (!name[0])
        return 0;
    for (const char *p = name; *p; p++)
        if (!((*p >= 'a' && *p <= 'z') || (*p >= 'A' && *p <= 'Z') || (*p >= '0' && *p <= '9') || *p == '_' ||
              *p == '-' || *p == '.'))
            return 0;
    return 1;
}

/* SNAPSHOT: the world's setup and journal under the name (one of that name
 * replaced). 0, or 1 with why. */
static int take_snapshot(sim_loop *l, const char *name, char *why, size_t n)
{
    if (!name_ok(name))
        return snprintf(why, n, "snapshot name '%s': expected 1 to 31 of A-Z a-z 0-9 _ . -", name), 1;
    if (l->jr_full)
        return snprintf(why, n, "the flight is longer than %.0f s since its world was built: "
                        "a restore would re-fly all of it", l->o.snapshot_max_s), 1;
    int i = snap_find(l, name);
    if (i < 0 && l->nsnaps == LOOP_SNAP_MAX)
        return snprintf(why, n, "%d snapshots held already: reuse a name", LOOP_SNAP_MAX), 1;
    sim_flight_inputs *in = malloc((size_t)(l->njr ? l->njr : 1) * sizeof *in);
    jev *ev = malloc((size_t)(l->nev ? l->nev : 1) * sizeof *ev);
    if (!in || !ev) {
        free(in);
        free(ev);
        return snprintf(why, n, "out of memory"), 1;
    }
    if (l->njr)
        memcpy(in, l->jr, (size_t)l->njr * sizeof *in);
    if (l->nev)
        memcpy(ev, l->ev, (size_t)l->nev * sizeof *ev);
    if (i < 0)
        i = l->nsnaps++;
    else {
        free(l->snaps[i].in);
        free(l->snaps[i].ev);
    }
    snap *sn = &l->snaps[i];
    snprintf(sn->name, sizeof sn->name, "%s", name);
    snprintf(sn->path, sizeof sn->path, "%s", l->scenario_path);
    sn->base = l->base;
    sn->setup = l->setup;
    sn->n = l->njr;
    sn->in = in;
    sn->nev = l->nev;
    sn->ev = ev;
    return 0;
}

/* A change made in flight, to flight f: 0; 1 with err when it cannot be
 * in flight; < 0 with err. */
static int live_apply(sim_flight *f, const jev *e, core_err *err)
{
    if (e->command == DISIM_SIM_CONTROL_T_SET_WOD)
        return sim_flight_set_wod(f, e->v[0], e->v[1], err);
    return sim_flight_set_turbulence(f, e->v[0] != 0.0, err);
}

/* Room for n inputs and m changes in the journal: 0, or -1. */
static int journal_room(sim_loop *l, long long n, int m)
{
    if (n > l->capjr) {
        sim_flight_inputs *p = realloc(l->jr, (size_t)n * sizeof *p);
        if (!p)
            return -1;
        l->jr = p;
        l->capjr = n;
    }
    if (m > l->capev) {
        jev *p = realloc(l->ev, (size_t)m * sizeof *p);
        if (!p)
            return -1;
        l->ev = p;
        l->capev = m;
    }
    return 0;
}

/* A snapshot's flight flown again by the one runner (sim_run): its
 * inputs as the pilot's, each change in flight made before the step it
 * came before (the observer, after the step before it). */
typedef struct refly {
    const snap *sn;
    sim_flight *f;
    long long k; /* the steps flown */
    int j;       /* the changes made */
} refly;

static int refly_changes(refly *r, core_err *err)
{
    for (; r->j < r->sn->nev && r->sn->ev[r->j].at == r->k; r->j++)
        if (live_apply(r->f, &r->sn->ev[r->j], err) != 0)
            return -1;
    return 0;
}

static int refly_pilot(void *self, const sim_flight_out *out, sim_flight_inputs *in)
{
    refly *r = self;
    (void)out;
    *in = r->sn->in[r->k];
    return 0;
}

static int refly_observe(void *user, const sim_flight_out *out, int st, core_err *err)
{
    refly *r = user;
    (void)out;
    if (st < 0)
        return 0; /* the pass fails with err */
    if (st > 0)
        return -1; /* the flight ended: it did not the first time */
    r->k++;
    return refly_changes(r, err);
}

/* A snapshot's flight flown again in f, the flight of a world just built
 * from it: 0, or < 0 with err. */
static int refly_world(const snap *sn, sim_flight *f, core_err *err)
{
    static const sim_pilot_ops journal = {"journal", refly_pilot};
    refly r = {sn, f, 0, 0};
    sim_pilot p = {&journal, &r};
    sim_run_opts ro;
    sim_run_opts_default(&ro);
    ro.max_steps = sn->n;
    ro.observe = refly_observe;
    ro.observe_user = &r;
    sim_flight_out out;
    sim_flight_state(f, &out);
    if (refly_changes(&r, err) != 0 || (sn->n > 0 && sim_run(f, &p, &ro, &out, err) != SIM_RUN_LENGTH)) {
        char m[sizeof err->msg];
        snprintf(m, sizeof m, "%s", err->msg);
        return core_err_set(err, -1, "restore '%s': flying it again failed at step %lld: %.200s", sn->name, r.k + 1,
                            m);
    }
    return 0;
}

/* SET_WOD (its speed alone) and SET_TURBULENCE in flight, kept in the
 * journal: 0 done; 1 not in flight (the world to be built again); 1 with
 * why set: refused; < 0 fatal. */
static int do_live(sim_loop *l, const ctl *c, const sim_loop_setup *s, char *why, size_t n, core_err *err)
{
    jev e = {l->njr, c->command, {0.0, 0.0}};
    if (c->command == DISIM_SIM_CONTROL_T_SET_WOD)
        e.v[0] = s->wod_speed_mps, e.v[1] = s->wod_dir_rad;
    else
        e.v[0] = s->turbulence;
    core_err ee = {0};
    int r = live_apply(l->w.flight, &e, &ee);
    if (r > 0)
        return 1;
    if (r < 0)
        return snprintf(why, n, "%.200s", ee.msg), 1;
    l->setup = *s;
    l->live = 1;
    if (!l->jr_full) { /* a journal past its length takes no snapshot: no need */
        if (journal_room(l, l->capjr, l->nev + 1) != 0)
            return core_err_set(err, -1, "the journal: out of memory");
        l->ev[l->nev++] = e;
    }
    return 0;
}

/* A world built for control c (from path under base, NULL: the caller's
 * settings; a restore's snapshot sn flown again in it) flying: the
 * stations' controls blended in afresh (the stick is where the pilot left
 * it), its start published; a restore's setup and journal (the job's
 * copies taken, or without a job sn's copied). 0, or < 0 with err. */
static int world_apply(sim_loop *l, const ctl *c, const char *path, const sim_loop_setup *base,
                       const sim_loop_world *w, const snap *sn, job *j, core_err *err)
{
    sim_loop_setup s;
    if (base)
        s = *base;
    else
        sim_loop_setup_default(&s);
    sim_pilots_reblend(l->pilots);
    if (world_started(l, w, path, &s, err) != 0)
        return -1;
    if (sn) {
        l->setup = sn->setup;
        if (j && j->jr && j->ev) { /* the worker's copies: no copy here */
            free(l->jr);
            free(l->ev);
            l->jr = j->jr;
            l->capjr = sn->n > 0 ? sn->n : 1;
            l->ev = j->ev;
            l->capev = sn->nev > 0 ? sn->nev : 1;
            j->jr = NULL;
            j->ev = NULL;
        } else {
            if (journal_room(l, sn->n, sn->nev) != 0)
                return core_err_set(err, -1, "restore: out of memory");
            if (sn->n)
                memcpy(l->jr, sn->in, (size_t)sn->n * sizeof *l->jr);
            if (sn->nev)
                memcpy(l->ev, sn->ev, (size_t)sn->nev * sizeof *l->ev);
        }
        l->njr = sn->n;
        l->nev = sn->nev;
    }
    if (c->command == DISIM_SIM_CONTROL_T_RESET || c->command == DISIM_SIM_CONTROL_T_LOAD_SCENARIO) {
        char shown[2 * SIM_PATH_MAX];
        core_escape(l->scenario_path, shown, sizeof shown);
        core_log_msg(l->log, CORE_LOG_INFO, "%s: %s", c->command == DISIM_SIM_CONTROL_T_RESET ? "reset" : "loaded",
                     shown);
    }
    return 0;
}

/* The rate limit: a world change taken from the changes allowed now (1
 * refused with why). It guards a flight's steps, and refills on the run
 * clock: a frozen or ended flight (whose clock stands still, and which
 * steps nothing) is not held by it, so a crash with the budget spent waits
 * for nothing but its reset; the worker's one build at a time bounds it. */
static int rate_take(sim_loop *l, char *why, size_t n)
{
    double dt = l->o.change_interval_s, burst = (double)l->o.change_burst;
    if (!(dt > 0.0) || l->swap == LOOP_SWAP_NOW || l->paused || l->crashed)
        return 0;
    double t = run_t(l);
    l->tokens = fmin(burst, l->tokens + (t - l->tokens_t_s) / dt);
    l->tokens_t_s = t;
    if (l->tokens >= 1.0) {
        l->tokens -= 1.0;
        return 0;
    }
    l->refused_rate++;
    return snprintf(why, n, "rate limit: at most %d world changes at once and one more every %g s of run time: "
                    "the next in %.2f s", l->o.change_burst, dt, (1.0 - l->tokens) * dt), 1;
}

/* A world change refused while another is under way: 1 with why. */
static int busy(sim_loop *l, char *why, size_t n)
{
    l->refused_busy++;
    return snprintf(why, n, "busy: a world change (%s) is being prepared: send it again once that is answered",
                    sim_ios_command_name(l->job->c.command)), 1;
}

/* On the worker: the job's world prepared, a restore's flight flown again
 * in it (its journal copied first: the snapshot is not replaced while
 * the job is under way). */
static void job_run(void *arg)
{
    job *j = arg;
    j->rc = j->b.prepare(j->user, j->path, j->has_setup ? &j->s : NULL, &j->world, &j->w, &j->e);
    if (j->rc != 0)
        j->world = NULL;
    else if (!j->w.flight)
        j->rc = core_err_set(&j->e, -1, "no flight");
    const snap *sn = j->sn;
    if (j->rc == 0 && sn) {
        j->jr = malloc((size_t)(sn->n > 0 ? sn->n : 1) * sizeof *j->jr);
        j->ev = malloc((size_t)(sn->nev > 0 ? sn->nev : 1) * sizeof *j->ev);
        if (!j->jr || !j->ev)
            j->rc = core_err_set(&j->e, -1, "restore: out of memory");
        else {
            if (sn->n)
                memcpy(j->jr, sn->in, (size_t)sn->n * sizeof *j->jr);
            if (sn->nev)
                memcpy(j->ev, sn->ev, (size_t)sn->nev * sizeof *j->ev);
            j->rc = refly_world(sn, j->w.flight, &j->e);
        }
    }
    if (j->rc != 0 && j->world) {
        j->b.drop(j->user, j->world);
        j->world = NULL;
    }
}

static int job_finish(sim_loop *l, int wait, core_err *err);

/* The world change asked of the worker: 2 (answered when it is swapped
 * in), 1 refused (why), < 0 fatal. */
static int ask_worker(sim_loop *l, const ctl *c, const char *path, const sim_loop_setup *s, const snap *sn,
                      char *why, size_t n, core_err *err)
{
    job *j = calloc(1, sizeof *j);
    if (!j)
        return snprintf(why, n, "out of memory"), 1;
    j->b = l->o.builder;
    j->user = l->user;
    j->c = *c;
    snprintf(j->path, sizeof j->path, "%s", path);
    if (s) {
        j->s = *s;
        j->has_setup = 1;
    }
    j->sn = sn;
    j->t0_s = wall_s();
    if (loop_worker_submit(l->worker, job_run, j) != 0) {
        free(j);
        return snprintf(why, n, "busy: the worker is still at work"), 1;
    }
    l->job = j;
    core_log_msg(l->log, CORE_LOG_DEBUG, "sim control %s (seq %lld): its world being prepared",
                 sim_ios_command_name(c->command), c->seq);
    if (l->swap == LOOP_SWAP_NOW && job_finish(l, 1, err) != 0)
        return -1;
    return 2;
}

/* A world change for control c: the world of path under s (NULL: the
 * caller's build), a restore's snapshot sn flown again in it. Refused
 * while another is under way (busy) and past the rate limit; else built
 * here, in the step (no builder: flying at return), or asked of the
 * worker. 0 done, 1 refused (why), 2 asked (answered when swapped in),
 * < 0 fatal. */
static int world_change(sim_loop *l, const ctl *c, const char *path, const sim_loop_setup *s, const snap *sn,
                        char *why, size_t n, core_err *err)
{
    if (l->job) {
        return busy(l, why, n);
    }
    if (rate_take(l, why, n))
        return 1;
    if (l->worker)
        return ask_worker(l, c, path, s, sn, why, n, err);
    sim_loop_world w;
    memset(&w, 0, sizeof w);
    core_err e = {0};
    l->builds++;
    l->builds_in_step++;
    if ((s ? l->o.rebuild(l->user, path, s, &w, &e) : l->build(l->user, path, &w, &e)) != 0 || !w.flight)
        return snprintf(why, n, "%.200s", e.msg[0] ? e.msg : "no flight"), 1;
    if (sn) {
        l->w = w; /* the old world is gone */
        if (refly_world(sn, w.flight, err) != 0)
            return -1;
    }
    return world_apply(l, c, path, s, &w, sn, NULL, err);
}

/* RESET and LOAD_SCENARIO: the caller's build, the console's setup
 * dropped. 0, 1 refused (why), 2 asked, < 0 fatal. */
static int do_load(sim_loop *l, const ctl *c, char *why, size_t n, core_err *err)
{
    const char *path = c->command == DISIM_SIM_CONTROL_T_RESET ? l->scenario_path : c->path;
    return world_change(l, c, path, NULL, NULL, why, n, err);
}

/* A loop that can build its world again under the instructor's setup. */
static int can_rebuild(const sim_loop *l) { return l->o.rebuild || l->worker; }

/* The instructor's world controls: the setup checked, the world built
 * again under it (none while a world change is under way: it would
 * replace what this one set). 0, 1 refused (why), 2 asked, < 0 fatal. */
static int do_setup(sim_loop *l, const ctl *c, char *why, size_t n, core_err *err)
{
    sim_loop_setup s;
    l->live = 0;
    if (ctl_setup(l, c, &s, why, n))
        return 1;
    if (l->job) {
        return busy(l, why, n);
    }
    if (c->command == DISIM_SIM_CONTROL_T_SET_WOD || c->command == DISIM_SIM_CONTROL_T_SET_TURBULENCE) {
        int r = do_live(l, c, &s, why, n, err);
        if (r <= 0 || why[0])
            return r;
    }
    if (!can_rebuild(l))
        return snprintf(why, n, "this loop cannot build its world again with the instructor's settings"), 1;
    return world_change(l, c, l->scenario_path, &s, NULL, why, n, err);
}

/* What an accepted control did, for its answer. */
static void said(const sim_loop *l, const ctl *c, char *msg, size_t n)
{
    const sim_loop_setup *s = &l->setup;
    if (l->live && c->command == DISIM_SIM_CONTROL_T_SET_WOD) {
        snprintf(msg, n, "in flight at t = %.3f s: WOD %.1f kt from %.0f deg (the air re-scaled)", l->out.t_s,
                 s->wod_speed_mps / CORE_KT_TO_MPS, s->wod_dir_rad * CORE_RAD_TO_DEG);
        return;
    }
    if (l->live && c->command == DISIM_SIM_CONTROL_T_SET_TURBULENCE) {
        snprintf(msg, n, "in flight at t = %.3f s: turbulence %s", l->out.t_s, s->turbulence ? "on" : "off");
        return;
    }
    switch (c->command) {
    case DISIM_SIM_CONTROL_T_PAUSE: snprintf(msg, n, "frozen at t = %.3f s", l->out.t_s); break;
    case DISIM_SIM_CONTROL_T_RESUME: snprintf(msg, n, "running from t = %.3f s", l->out.t_s); break;
    case DISIM_SIM_CONTROL_T_SNAPSHOT:
        snprintf(msg, n, "snapshot '%s' at t = %.3f s (%lld steps)", c->name, l->out.t_s, l->njr);
        break;
    case DISIM_SIM_CONTROL_T_RESTORE:
        snprintf(msg, n, "restored '%s': t = %.3f s, %lld steps flown again", c->name, l->out.t_s, l->njr);
        break;
    default:
        snprintf(msg, n, "%s: %s %s at (%.2f, %.2f, %.2f) m in S, WOD %s, sea %s, turbulence %s",
                 sim_ios_command_name(c->command),
                 l->w.scenario, s->start == SIM_START_DECK ? "on the deck" : "in the hover", l->out.pos_S_m[0],
                 l->out.pos_S_m[1], l->out.pos_S_m[2], isnan(s->wod_speed_mps) ? "as started" : "set",
                 s->sea_state < 0 ? "as started" : "set",
                 s->turbulence < 0 ? "as started" : s->turbulence ? "on" : "off");
        if (!isnan(s->wod_speed_mps)) {
            size_t k = strlen(msg);
            snprintf(msg + k, n - k, " (%.1f kt from %.0f deg)", s->wod_speed_mps / CORE_KT_TO_MPS,
                     s->wod_dir_rad * CORE_RAD_TO_DEG);
        }
        if (s->sea_state >= 0) {
            size_t k = strlen(msg);
            snprintf(msg + k, n - k, " (sea state %d)", s->sea_state);
        }
    }
}

/* The name a refusal gives its control. */
static const char *refused_name(int command)
{
    return command == DISIM_SIM_CONTROL_T_LOAD_SCENARIO ? "load" : sim_ios_command_name(command);
}

/* The state the status says. */
static int status_state(const sim_loop *l)
{
    return l->crashed && l->o.wait_after_end ? DISIM_SIM_STATUS_T_STOPPED
           : l->paused                       ? DISIM_SIM_STATUS_T_PAUSED
                                             : DISIM_SIM_STATUS_T_RUNNING;
}

/* The mark of a world change carried out (or refused by its build), into
 * the log only (SIM_LOOP_CH_CONTROL_DONE). */
static void log_mark(sim_loop *l, const ctl *c)
{
    disim_sim_control_t m;
    memset(&m, 0, sizeof m);
    m.seq = c->seq;
    m.command = (int8_t)c->command;
    m.scenario_path = (char *)"";
    m.name = (char *)"";
    int n = disim_sim_control_t_encoded_size(&m);
    if (n > LOOP_BUF || disim_sim_control_t_encode(l->buf, 0, n, &m) != n) {
        if (!l->fatal)
            core_err_set(&l->ferr, -1, "LCM: cannot encode sim_control_t");
        l->fatal = 1;
        return;
    }
    log_event(l, SIM_LOOP_CH_CONTROL_DONE, l->buf, n);
}

/* The world change under way, once the worker has built it (wait 1: the
 * loop waits for it): swapped in (the caller's world replaced, the old
 * one freed on the worker) and accepted, or refused with the build's
 * reason, the old world flying on; answered in a status at once, marked
 * in the log. 0 (done or not yet), < 0 with err (fatal). */
static int job_finish(sim_loop *l, int wait, core_err *err)
{
    job *j = l->job;
    if (!j || loop_worker_poll(l->worker, wait) != 1)
        return 0;
    l->job = NULL;
    l->builds++;
    l->builds_on_worker++;
    if (l->swap == SIM_LOOP_SWAP_READY || l->swap == SIM_LOOP_SWAP_PASS) /* a replay's own are its log's */
        log_mark(l, &j->c);
    int rc = 0;
    if (j->rc != 0) {
        char why[300];
        snprintf(why, sizeof why, "%s refused: %.200s", refused_name(j->c.command), j->e.msg);
        refuse_ctl(l, j->c.seq, j->c.command, why);
    } else {
        void *old = j->b.install(j->user, j->world);
        loop_worker_later(l->worker, j->b.drop, j->user, old);
        rc = world_apply(l, &j->c, j->path, j->has_setup ? &j->s : NULL, &j->w, j->sn, j, err);
        if (rc == 0) {
            char msg[256];
            l->live = 0;
            said(l, &j->c, msg, sizeof msg);
            accept_ctl(l, &j->c, j->t0_s, "%s", msg);
        }
    }
    free(j->jr);
    free(j->ev);
    free(j);
    if (rc == 0 && (l->lc || l->elog)) /* its answer out before any other control's */
        publish_status(l, status_state(l));
    return rc;
}

/* One control: 0 (answered: accepted or refused; or a world change asked
 * of the worker, answered when swapped in), < 0 with err (fatal). */
static int do_control(sim_loop *l, const ctl *c, core_err *err)
{
    double t0 = wall_s();
    char why[256] = "";
    int rc = 0;
    switch (c->command) {
    case DISIM_SIM_CONTROL_T_PAUSE: l->paused = 1; break;
    case DISIM_SIM_CONTROL_T_RESUME:
        if (l->crashed) {
            rc = (snprintf(why, sizeof why, "the flight has ended (%.150s): reset, reposition or restore",
                           l->crash_msg), 1);
            break;
        }
        if (l->paused && new_pacer(l, err) != 0) /* deadlines from now, not from before the pause */
            return -1;
        l->paused = 0;
        break;
    case DISIM_SIM_CONTROL_T_RESET:
    case DISIM_SIM_CONTROL_T_LOAD_SCENARIO: rc = do_load(l, c, why, sizeof why, err); break;
    case DISIM_SIM_CONTROL_T_SNAPSHOT: {
        int i = snap_find(l, c->name);
        if (!can_rebuild(l))
            rc = (snprintf(why, sizeof why, "this loop cannot build its world again: no snapshots"), 1);
        else if (l->crashed)
            rc = (snprintf(why, sizeof why, "the flight has ended (%.150s): no snapshot of it", l->crash_msg), 1);
        else if (i >= 0 && l->job && l->job->sn == &l->snaps[i])
            rc = (snprintf(why, sizeof why, "busy: '%s' is being restored", c->name), 1);
        else
            rc = take_snapshot(l, c->name, why, sizeof why);
        break;
    }
    case DISIM_SIM_CONTROL_T_RESTORE: {
        int i = snap_find(l, c->name);
        if (!can_rebuild(l))
            rc = (snprintf(why, sizeof why, "this loop cannot build its world again: no restore"), 1);
        else if (l->source_id[0])
            rc = (snprintf(why, sizeof why, "a pilot of the caller's flies (%s): its own state is not restored",
                           l->source_id), 1);
        else if (i < 0)
            rc = (snprintf(why, sizeof why, "no snapshot '%s'", c->name), 1);
        else
            rc = world_change(l, c, l->snaps[i].path, &l->snaps[i].base, &l->snaps[i], why, sizeof why, err);
        break;
    }
    default: rc = do_setup(l, c, why, sizeof why, err); break;
    }
    if (rc < 0)
        return -1;
    if (rc == 2) /* asked of the worker: answered when swapped in */
        return 0;
    if (rc > 0) {
        char full[300];
        snprintf(full, sizeof full, "%s refused: %s", refused_name(c->command), why);
        refuse_ctl(l, c->seq, c->command, full);
        return 0;
    }
    char msg[256];
    said(l, c, msg, sizeof msg);
    accept_ctl(l, c, t0, "%s", msg);
    return 0;
}

/* A control that may build the world again (all but pause, resume,
 * snapshot and the turbulence, which change nothing or change it in
 * flight). */
static int may_build(int command)
{
    return command != DISIM_SIM_CONTROL_T_PAUSE && command != DISIM_SIM_CONTROL_T_RESUME &&
           command != DISIM_SIM_CONTROL_T_SNAPSHOT && command != DISIM_SIM_CONTROL_T_SET_TURBULENCE;
}

/* The controls received, in order, each answered in a status of its own
 * (a replay's marks of world changes carried out among them: the swap
 * there). Building in the step (no builder, or a replay of a log without
 * marks), at most one world is built in a pass (a build takes tens of
 * ms): a further control that may build one is refused with the reason,
 * so a burst of resets or loads costs one build, not one per message.
 * With the worker, one world change at a time (busy) and the rate limit;
 * SIM_LOOP_SWAP_PASS swaps at the end. */
static int do_controls(sim_loop *l, core_err *err)
{
    long long built = l->builds;
    int one_a_step = !l->worker || l->swap == LOOP_SWAP_NOW;
    int rc = 0;
    for (int i = 0; i < l->nq && rc == 0; i++) {
        const ctl *c = &l->q[i];
        if (c->command == LOOP_SWAP_MARK) {
            if (l->job && l->job->c.seq == c->seq)
                rc = job_finish(l, 1, err);
            else
                core_log_msg(l->log, CORE_LOG_DEBUG, "replay: a mark of seq %lld and no world change of it "
                             "under way: passed over", c->seq);
            continue;
        }
        if (one_a_step && l->builds != built && may_build(c->command)) {
            refuse_ctl(l, c->seq, c->command, "a world was built in this step already: one build per "
                       "step, send it again");
            continue;
        }
        rc = do_control(l, c, err);
        if (rc == 0 && (l->lc || l->elog) && i + 1 < l->nq)
            publish_status(l, status_state(l));
    }
    l->nq = l->nctl = 0;
    if (rc == 0 && l->job && l->swap == SIM_LOOP_SWAP_PASS)
        rc = job_finish(l, 1, err);
    return rc != 0 ? -1 : 0;
}

/* ---- the loop's pass, as the runner's wrap (sim/runner.c) */
/* After a pass: the status when due, then (a step flown) the deadline
 * waited for. 0, or < 0 with err (a log write or a publish failed). */
static int pass_end(sim_loop *l, int stepped, core_err *err)
{
    if (l->lc || l->elog) {
        unsigned f = loop_flags(l);
        if (l->dirty || f != l->last_flags || sim_pilots_active(l->pilots) != l->last_active ||
            wall_s() - l->status_wall_s >= l->o.status_period_s)
            publish_status(l, status_state(l));
    }
    l->acks_pass = 0;
    if (l->fatal)
        return core_err_set(err, -1, "%s", l->ferr.msg);
    if (stepped)
        sim_pacer_wait(l->pacer);
    return 0;
}

/* Before the pilot: the messages received taken, the controls carried
 * out; a pause ends the pass here. */
static int pass_before(void *user, core_err *err)
{
    sim_loop *l = user;
    if (l->fatal)
        return core_err_set(err, -1, "%s", l->ferr.msg);
    /* a flight that ended waits while a control can still come (LCM, or
     * the replayed log's events not all read) */
    if (l->crashed && (!l->o.wait_after_end || (!l->lc && (!l->replay || l->replay_done)))) {
        core_err_set(err, SIM_LOOP_CRASHED, "%s", l->crash_msg);
        return SIM_RUN_ENDED;
    }
    if (!l->paused && l->run_step >= l->nsteps)
        return SIM_RUN_LENGTH;
    /* a world built on the worker, swapped in once ready: before what
     * arrived in this pass, as its mark in the log */
    if (l->job && l->swap == SIM_LOOP_SWAP_READY && job_finish(l, 0, err) != 0)
        return -1;
    int waiting = l->paused || l->crashed; /* a flight that ended waits for a control that builds it again */
    take_received(l, waiting ? 100 : 0);
    if (waiting && l->pacer) /* the wait for a control is no step's work */
        sim_pacer_idle(l->pacer);
    if (do_controls(l, err) != 0)
        return -1;
    if (!l->paused && !l->crashed)
        return SIM_RUN_STEPPED;
    return pass_end(l, 0, err) != 0 ? -1 : SIM_RUN_SKIPPED;
}

/* The step with the pilot's inputs: a pilot of the caller's said as a
 * station's message, the flight stepped (run step k + 1), its states
 * published at their rate (the last state of a flight that ended
 * whatever the rate), the status, the deadline. As sim_flight_step. */
static int pass_step(void *user, const sim_flight_inputs *in, sim_flight_out *out, core_err *err)
{
    sim_loop *l = user;
    if (l->source_id[0]) {
        l->held = 0;
        if (l->lc || l->elog)
            publish_source(l, in);
    }
    journal_add(l, in);
    int frc = sim_flight_step(l->w.flight, in, &l->out, err);
    if (frc < 0)
        return -1;
    l->run_step++;
    if (frc > 0) { /* the flight ended: nothing more steps */
        l->crashed = 1;
        snprintf(l->crash_msg, sizeof l->crash_msg, "%.250s", err->msg);
        snprintf(l->message, sizeof l->message, "%s", l->crash_msg); /* the status says what hit what */
        l->dirty = 1;
        core_log_msg(l->log, CORE_LOG_WARN, "the flight ended: %s", l->crash_msg);
    }
    if ((l->lc || l->elog) && (frc > 0 || l->run_step % l->state_every == 0))
        publish_states(l, &l->out);
    *out = l->out;
    if (pass_end(l, frc == 0, err) != 0)
        return -1;
    if (frc > 0 && l->o.wait_after_end) { /* stopped, waiting for the instructor */
        core_log_msg(l->log, CORE_LOG_WARN, "stopped: a reset, a reposition, a load or a restore flies on");
        return 0;
    }
    return frc > 0 ? core_err_set(err, SIM_LOOP_CRASHED, "%s", l->crash_msg) : 0;
}

void sim_loop_run_opts(sim_loop *l, sim_run_opts *o)
{
    o->wrap.before = pass_before;
    o->wrap.step = pass_step;
    o->wrap.user = l;
}

/* The loop's own pilots: the stations by their rules at the run clock,
 * or the inputs the caller sets (opts.pilot_source_id). */
static int stations_step(void *self, const sim_flight_out *out, sim_flight_inputs *in)
{
    sim_loop *l = self;
    (void)out;
    sim_pilots_blend_info b0, b;
    sim_pilots_blend(l->pilots, &b0);
    l->held = sim_pilots_inputs(l->pilots, run_t(l), &l->out.ctl, in);
    sim_pilots_blend(l->pilots, &b);
    if (b.started != b0.started) {
        sim_pilot_station s;
        sim_pilots_station(l->pilots, b.station, &s);
        /* WARN: what the operator sees (disim fly shows warnings) */
        core_log_msg(l->log, CORE_LOG_WARN,
                     "t %.2f s: station '%s' takes the controls: blending over %g s from the flown %.1f %.1f %.1f %.1f "
                     "to its %.1f %.1f %.1f %.1f %% (collective, long, lat, pedal)",
                     run_t(l), s.id, l->o.pilots.blend_s, b.from_pct[0], b.from_pct[1], b.from_pct[2], b.from_pct[3],
                     s.in_pct[0], s.in_pct[1], s.in_pct[2], s.in_pct[3]);
    }
    return 0;
}

sim_pilot sim_loop_own_pilot(sim_loop *l)
{
    static const sim_pilot_ops stations = {"stations", stations_step};
    sim_pilot p = {&stations, l};
    return p;
}

int sim_loop_iterate(sim_loop *l, sim_flight_out *out, core_err *err)
{
    sim_run_opts o;
    sim_run_opts_default(&o);
    sim_loop_run_opts(l, &o);
    sim_pilot p = sim_loop_own_pilot(l);
    sim_flight_out step_out = l->out;
    long long k0 = l->run_step;
    int r = sim_run_pass(NULL, &p, &o, &step_out, err);
    if (out && l->run_step != k0)
        *out = step_out;
    if (r < 0)
        return -1;
    if (r == SIM_RUN_ENDED)
        return SIM_LOOP_CRASHED; /* err says what hit what */
    return r == SIM_RUN_STEPPED ? SIM_LOOP_STEPPED : r == SIM_RUN_SKIPPED ? SIM_LOOP_PAUSED : SIM_LOOP_DONE;
}

int sim_loop_finish(sim_loop *l, core_err *err)
{
    /* a world change still under way is dropped: marked, so that a replay
     * of the log knows its world changes are swapped where marked */
    if (l->job && (l->swap == SIM_LOOP_SWAP_READY || l->swap == SIM_LOOP_SWAP_PASS))
        log_mark(l, &l->job->c);
    if (l->lc || l->elog)
        publish_status(l, DISIM_SIM_STATUS_T_STOPPED);
    if (l->lc) /* what arrived meanwhile, into the log */
        take_received(l, 0);
    if (l->fatal)
        return core_err_set(err, -1, "%s", l->ferr.msg);
    if (!l->elog)
        return 0;
    int rc = sim_log_writer_commit(l->elog, err);
    sim_log_writer_destroy(l->elog);
    l->elog = NULL;
    return rc;
}

void sim_loop_report_get(const sim_loop *l, sim_loop_report *r)
{
    memset(r, 0, sizeof *r);
    sim_pacer_stats(l->pacer, &r->pace);
    r->run_s = run_t(l);
    r->paused = l->paused;
    r->held = l->held;
    r->flags = loop_flags(l);
    r->sent = l->sent;
    r->received = l->received;
    r->logged = l->logged;
    r->control_refused = l->control_refused;
    snprintf(r->scenario, sizeof r->scenario, "%s", l->w.scenario);
    snprintf(r->message, sizeof r->message, "%s", l->message);
    r->control_seq = l->ack_seq;
    r->control_command = l->ack_cmd;
    r->control_result = l->ack_result;
    snprintf(r->control_message, sizeof r->control_message, "%s", l->ack_msg);
    r->control_apply_s = l->ack_apply_s;
    r->snapshots = l->nsnaps;
    r->builds_in_step = l->builds_in_step;
    r->builds_on_worker = l->builds_on_worker;
    r->refused_busy = l->refused_busy;
    r->refused_rate = l->refused_rate;
    r->change_pending = l->job != NULL;
}

const sim_pilots *sim_loop_pilots(const sim_loop *l) { return l->pilots; }
struct _lcm_t *sim_loop_lcm(sim_loop *l) { return l->lc; }
