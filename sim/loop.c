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
 *      reset, load scenario);
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

#include <lcm/eventlog.h>
#include <lcm/lcm.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

/* ---------------------------------------------------------------- loop */
#define LOOP_CTL_MAX 64
#define LOOP_BUF 16384

typedef struct ctl {
    int command;
    char path[SIM_PATH_MAX];
} ctl;

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
    sim_pilots *pilots;
    sim_pacer *pacer;
    long prior_overruns;
    long long run_step, nsteps, state_every;
    int paused, held;
    unsigned flags, last_flags;
    int last_active, last_paused, dirty;
    ctl q[LOOP_CTL_MAX];
    int nq;
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
    sim_pilots_opts_default(&o->pilots);
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

static void refuse_ctl(sim_loop *l, const char *why)
{
    l->control_refused++;
    snprintf(l->message, sizeof l->message, "%s", why);
    l->dirty = 1;
    core_log_msg(l->log, CORE_LOG_WARN, "sim control refused: %s", why);
}

static void got_ctl(sim_loop *l, const void *data, int size)
{
    l->received++;
    char e[256];
    if (disim_lcm_check_raw("sim_control_t", data, size, e, sizeof e) != 0) {
        refuse_ctl(l, e);
        return;
    }
    disim_sim_control_t m;
    memset(&m, 0, sizeof m);
    if (disim_sim_control_t_decode(data, 0, size, &m) != size)
        refuse_ctl(l, "sim_control_t: not decoded");
    else if (disim_lcm_check_sim_control(&m, e, sizeof e) != 0)
        refuse_ctl(l, e);
    else if (l->nq == LOOP_CTL_MAX)
        refuse_ctl(l, "sim_control_t: too many controls at once");
    else if (strlen(m.scenario_path) >= SIM_PATH_MAX)
        refuse_ctl(l, "sim_control_t.scenario_path: too long");
    else {
        ctl *c = &l->q[l->nq++];
        c->command = m.command;
        snprintf(c->path, sizeof c->path, "%s", m.scenario_path);
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

/* The replayed log's events due at this run step (and earlier). */
static int replay_feed(sim_loop *l)
{
    int fed = 0;
    while (!l->replay_done) {
        if (!l->pending && !(l->pending = lcm_eventlog_read_next_event(l->replay))) {
            l->replay_done = 1;
            break;
        }
        lcm_eventlog_event_t *ev = l->pending;
        long long step = llround((double)ev->timestamp * l->o.rate_hz / 1e6);
        if (step > l->run_step)
            break;
        int pilot = !strcmp(ev->channel, DISIM_CH_PILOT_INPUT), control = !strcmp(ev->channel, DISIM_CH_SIM_CONTROL);
        if (pilot || control) {
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
    SEND(l, sim_status_t, DISIM_CH_SIM_STATUS, &m);
    l->status_wall_s = wall_s();
    l->last_flags = r.flags;
    l->last_active = m.active_station;
    l->last_paused = l->paused;
    l->dirty = 0;
}

static unsigned loop_flags(const sim_loop *l)
{
    unsigned f = 0;
    if (l->held)
        f |= DISIM_SIM_STATUS_T_FLAG_INPUT_HELD;
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

static int new_pacer(sim_loop *l, core_err *err)
{
    if (l->pacer) {
        sim_pacer_report r;
        sim_pacer_stats(l->pacer, &r);
        l->prior_overruns += r.overruns;
        sim_pacer_destroy(l->pacer);
    }
    return (l->pacer = sim_pacer_create(l->o.rate_hz, l->o.realtime, err)) ? 0 : -1;
}

sim_loop *sim_loop_create(const sim_loop_opts *o, const sim_loop_world *w, sim_loop_build_fn build, void *user,
                          const core_log *log, core_err *err)
{
    if (!(o->rate_hz >= 1.0 && o->rate_hz <= 100000.0) || !(o->duration_s >= 0.0) ||
        !(o->state_rate_hz > 0.0 && o->state_rate_hz <= o->rate_hz) || !(o->status_period_s > 0.0)) {
        core_err_set(err, -1, "flight loop: rate %g Hz, duration %g s, state rate %g Hz, status every %g s: "
                     "expected a rate of 1 to 100000 Hz, a duration >= 0, a state rate above 0 and at most the "
                     "loop's, a status period above 0", o->rate_hz, o->duration_s, o->state_rate_hz,
                     o->status_period_s);
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
        if (!(l->lc = lcm_create(o->lcm_url))) {
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
    free(l);
}

static int do_controls(sim_loop *l, core_err *err)
{
    for (int i = 0; i < l->nq; i++) {
        ctl *c = &l->q[i];
        l->dirty = 1;
        if (c->command == DISIM_SIM_CONTROL_T_PAUSE)
            l->paused = 1;
        else if (c->command == DISIM_SIM_CONTROL_T_RESUME) {
            if (l->paused && new_pacer(l, err) != 0) /* deadlines from now, not from before the pause */
                return -1;
            l->paused = 0;
        } else {
            const char *path = c->command == DISIM_SIM_CONTROL_T_RESET ? l->scenario_path : c->path;
            sim_loop_world w = {0};
            core_err e = {0};
            if (l->build(l->user, path, &w, &e) != 0 || !w.flight) {
                char why[256];
                snprintf(why, sizeof why, "%s refused: %.200s", c->command == DISIM_SIM_CONTROL_T_RESET ? "reset" : "load",
                         e.msg[0] ? e.msg : "no flight");
                refuse_ctl(l, why);
                continue;
            }
            l->w = w;
            if (c->command == DISIM_SIM_CONTROL_T_LOAD_SCENARIO)
                snprintf(l->scenario_path, sizeof l->scenario_path, "%s", c->path);
            sim_flight_state(l->w.flight, &l->out);
            publish_run_info(l); /* the new run's, before its first state */
            core_log_msg(l->log, CORE_LOG_INFO, "%s: %s", c->command == DISIM_SIM_CONTROL_T_RESET ? "reset" : "loaded",
                         l->scenario_path);
        }
        l->message[0] = '\0';
    }
    l->nq = 0;
    return 0;
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
            publish_status(l, l->paused ? DISIM_SIM_STATUS_T_PAUSED : DISIM_SIM_STATUS_T_RUNNING);
    }
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
    if (l->crashed) {
        core_err_set(err, SIM_LOOP_CRASHED, "%s", l->crash_msg);
        return SIM_RUN_ENDED;
    }
    if (!l->paused && l->run_step >= l->nsteps)
        return SIM_RUN_LENGTH;
    take_received(l, l->paused ? 100 : 0);
    if (do_controls(l, err) != 0)
        return -1;
    if (!l->paused)
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
    l->held = sim_pilots_inputs(l->pilots, run_t(l), in);
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
    r->pace.overruns += l->prior_overruns;
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
}

const sim_pilots *sim_loop_pilots(const sim_loop *l) { return l->pilots; }
struct _lcm_t *sim_loop_lcm(sim_loop *l) { return l->lc; }
