/* test_pilot_replay.c -- the replay pilot (sim/pilot_replay.c).
 *
 * 1. A landing flown from a station and logged: the automated pilot
 *    (scenarios/tasks/land_uh60a.ini) flies the UH-60A over the CG-47 as
 *    an LCM station (pilot_input_t over memq:// into the flight loop,
 *    sim_loop, every step), from a hover 3 m to starboard of and 2 m
 *    above the task's target to touchdown, in a 15 kt head wind in sea
 *    state 3 (free stream, no turbulence, the SAS off), the loop logging
 *    (--log) at the default 50 Hz state rate.
 * 2. The log read back: every state of the run is a sample (the positions
 *    as flown, to 1e-9 m), one station's inputs are the controls, the
 *    deck-relative velocity is the time derivative of the position in S
 *    (central differences over the flight's steps, to 0.001 m/s), and the
 *    reference's phases include a hover, a translation and a descent.
 * 3. Replayed in the same conditions: the replay's trajectory stays
 *    within 0.5 m of the recorded one at every recorded step (the
 *    acceptance; measured 0.309 m) with the loops alone (and their
 *    integrals and steady trims), its descent within 0.3 m and rms
 *    0.15 m (the height loop's feed-forward; measured 0.229 m, 0.094 m),
 *    its rms below that of a replay without
 *    the preview and of one without the acceleration's lead; with the
 *    recorded controls fed forward within 0.001 m.
 * 4. Replayed in another WOD and sea: 25 kt from green 30 (10 kt more,
 *    30 deg off) in sea state 4 with another seed, the loops alone and
 *    with the recorded controls fed forward: each flies to the
 *    reference's end, with every control inside its travel, and reports
 *    its errors (within the task's adequate 2 m).
 * 6. With the gear (sim/contact.c): the landing flown to settled on the
 *    deck and logged, replayed in the same conditions with the gear:
 *    within 0.5 m of the recorded steps, its on-deck phase counted, and it
 *    ends on the deck with the collective down.
 * 7. The SAS through the log: the SAS-off run reads back off; the
 *    landing flown with the SAS engaged (the automated pilot's gains
 *    scheduled with it) reads back on, and its replay flying the SAS as
 *    logged stays within 0.5 m of the recorded steps (measured 0.300 m,
 *    rms 0.175 m).
 * 5. Bad logs are refused naming the file and the event: missing, a
 *    folder, empty, not an event log, truncated, a heli_state_t that is
 *    not one, a NaN in a state, no heli_state_t, a state without its
 *    ship state, states out of time order. Run from the source root. */
#include "check.h"
#include "disim_lcm.h"
#include "hfm.h"
#include "sim.h"

#include <lcm/eventlog.h>
#include <lcm/lcm.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define UH60 "scenarios/aircraft/uh60a.ini"
#define SHIP "scenarios/ships/cg47.ini"
#define LAND "scenarios/tasks/land_uh60a.ini"
#define SCEN "scenarios/cg47_uh60a.ini"
#define RATE_HZ 200.0
#define KT 0.514444
#define MAX_STEPS 20000

typedef struct traj {
    long n;
    double t_s[MAX_STEPS], pos_S[MAX_STEPS][3];
} traj;

typedef struct conds {
    double wod_kt, dir_deg;
    int sea_state;
    uint64_t seed;
    int gear; /* the aircraft's [gear] on the deck (sim/contact.c) */
    int sas;  /* the SAS engaged (the aircraft file's [sas]); 0 off */
} conds;

/* A flight in conditions c from start_S (its ship motion into *motion). */
static sim_flight *make_flight(const hfm_aircraft *ac, const core_ship *ship, const conds *c, const double start_S[3],
                               sim_ship_motion **motion, core_err *err)
{
    sim_sea sea;
    sim_sea_default(&sea);
    sea.state = c->sea_state;
    if (!(*motion = sim_ship_motion_create(ship, &sea, c->seed, err)))
        return NULL;
    sim_flight_opts fo;
    sim_flight_opts_default(&fo);
    fo.rate_hz = RATE_HZ;
    fo.turbulence = 0;
    fo.sas = c->sas;
    fo.gear = c->gear;
    fo.wod_speed_mps = c->wod_kt * KT;
    fo.wod_dir_rad = c->dir_deg * CORE_DEG_TO_RAD;
    memcpy(fo.station_S_m, start_S, sizeof fo.station_S_m);
    sim_flight *f = sim_flight_create(ac, ship, &fo, sim_ship_motion_frame_fn, *motion, NULL, NULL, err);
    if (!f) {
        sim_ship_motion_destroy(*motion);
        *motion = NULL;
    }
    return f;
}

static int no_build(void *user, const char *path, sim_loop_world *w, core_err *err)
{
    (void)user, (void)w;
    return core_err_set(err, -1, "%s: no reset in this test", path);
}

/* 1. The landing flown by the automated pilot as a station, logged. */
static int record(const hfm_aircraft *ac, const core_ship *ship, const conds *c, const char *log, traj *tr)
{
    core_err err = {0};
    sim_task task;
    if (sim_task_load(LAND, &task, &err) != 0) {
        fprintf(stderr, "record: %s\n", err.msg);
        return -1;
    }
    const double start[3] = {task.target_S_m[0], task.target_S_m[1] + 3.0, task.target_S_m[2] - 2.0};
    sim_ship_motion *motion = NULL;
    sim_flight *f = make_flight(ac, ship, c, start, &motion, &err);
    if (!f) {
        fprintf(stderr, "record: %s\n", err.msg);
        return -1;
    }
    sim_pilot_auto_opts po;
    sim_pilot_auto_opts_default(&po);
    po.rate_hz = RATE_HZ;
    po.wod_speed_mps = c->wod_kt * KT;
    po.wod_dir_rad = c->dir_deg * CORE_DEG_TO_RAD;
    po.gear = c->gear;
    po.sas = c->sas;
    sim_flight_inputs in;
    sim_flight_trim_inputs(f, &in);
    sim_pilot_auto *p = sim_pilot_auto_create(ac, &task, &po, &in, NULL, &err);
    sim_loop_opts lo;
    sim_loop_opts_default(&lo);
    lo.rate_hz = RATE_HZ;
    lo.realtime = 0;
    lo.duration_s = MAX_STEPS / RATE_HZ;
    lo.lcm = 1;
    lo.lcm_url = "memq://";
    lo.log_path = log;
    lo.scenario_path = SCEN;
    /* the automated pilot's controls flown as it sends them from the first
     * step (it starts from the trim it was given): the log's inputs are
     * then the flown controls, which feeding them forward must reproduce;
     * with the take-over's 1 s blend the first second's flown controls
     * differ from the inputs logged */
    lo.pilots.blend_s = 0.0;
    sim_loop_world w = {.flight = f, .motion = motion, .scenario = "replay-test"};
    /* what the run was flown from: logged as run_info_t, read back in test_read */
    snprintf(w.info.scenario_path, sizeof w.info.scenario_path, "%s", SCEN);
    snprintf(w.info.scenario, sizeof w.info.scenario, "replay-test");
    snprintf(w.info.aircraft_path, sizeof w.info.aircraft_path, "scenarios/aircraft/uh60a.ini");
    snprintf(w.info.ship_path, sizeof w.info.ship_path, "scenarios/ships/cg47.ini");
    w.info.seed = c->seed;
    sim_sea_default(&w.info.sea);
    w.info.sea.state = c->sea_state;
    w.info.wod_speed_mps = c->wod_kt * KT;
    w.info.wod_dir_rad = c->dir_deg * CORE_DEG_TO_RAD;
    sim_loop *l = p ? sim_loop_create(&lo, &w, no_build, NULL, NULL, &err) : NULL;
    int rc = -1;
    if (!l) {
        fprintf(stderr, "record: %s\n", err.msg);
        goto out;
    }
    lcm_t *lc = sim_loop_lcm(l);
    sim_flight_out o;
    sim_flight_state(f, &o);
    tr->n = 0;
    for (long k = 0; k < MAX_STEPS - 1; k++) {
        sim_task_result r;
        sim_pilot_auto_step(p, &o, &in);
        sim_pilot_auto_result(p, &r);
        if (c->gear ? r.done : r.touched) /* with the gear: settled on the deck */
            break;
        disim_pilot_input_t m;
        memset(&m, 0, sizeof m);
        m.utime = (int64_t)llround(o.t_s * 1e6);
        m.station_id = "auto";
        m.seq = k;
        m.collective_pct = in.ctl.collective_pct;
        m.long_cyclic_pct = in.ctl.long_cyclic_pct;
        m.lat_cyclic_pct = in.ctl.lat_cyclic_pct;
        m.pedal_pct = in.ctl.pedal_pct;
        if (disim_pilot_input_t_publish(lc, DISIM_CH_PILOT_INPUT, &m) != 0 || sim_loop_iterate(l, &o, &err) != 0) {
            fprintf(stderr, "record: step %ld: %s\n", k, err.msg);
            goto out;
        }
        tr->t_s[tr->n] = o.t_s;
        memcpy(tr->pos_S[tr->n++], o.pos_S_m, sizeof o.pos_S_m);
    }
    sim_task_result r;
    sim_pilot_auto_result(p, &r);
    printf("recorded: %s, %.0f kt from %.0f deg, sea state %d%s: touchdown at %.2f s, sink %.2f m/s, %.2f m from the "
           "spot%s; %ld steps\n", hfm_aircraft_name(ac), c->wod_kt, c->dir_deg, c->sea_state, c->gear ? ", gear" : "",
           r.t_touchdown_s, r.sink_mps, r.dist_m, c->gear ? (r.settled ? ", settled" : ", not settled") : "", tr->n);
    if (!r.touched || (c->gear && !r.settled) || sim_loop_finish(l, &err) != 0) {
        fprintf(stderr, "record: no touchdown, or %s\n", err.msg);
        goto out;
    }
    rc = 0;
out:
    sim_loop_destroy(l);
    sim_pilot_auto_destroy(p);
    sim_flight_destroy(f);
    sim_ship_motion_destroy(motion);
    return rc;
}

typedef struct replay_run {
    sim_replay_result r;
    double max_dev_m;  /* from the recorded trajectory at its steps (-1: not compared) */
    double min_pct[4], max_pct[4];
    int failed;
    int end_on_deck;   /* the last state's */
    double end_coll_pct;
} replay_run;

/* 3-4. The log replayed in conditions c; compared step by step with tr (NULL: not). */
static void replay(const hfm_aircraft *ac, const core_ship *ship, const sim_log *L, const conds *c,
                   int feed, double preview_s, double acc_lead_s, const traj *tr, replay_run *out)
{
    memset(out, 0, sizeof *out);
    out->max_dev_m = -1.0;
    core_err err = {0};
    sim_log_sample s0;
    sim_log_sample_at(L, 0.0, &s0);
    sim_ship_motion *motion = NULL;
    sim_flight *f = make_flight(ac, ship, c, s0.pos_S_m, &motion, &err);
    sim_pilot_replay *p = NULL;
    sim_flight_inputs in;
    if (f) {
        sim_pilot_replay_opts o;
        sim_pilot_replay_opts_default(&o);
        o.pilot.rate_hz = RATE_HZ;
        o.pilot.wod_speed_mps = c->wod_kt * KT;
        o.pilot.wod_dir_rad = c->dir_deg * CORE_DEG_TO_RAD;
        o.pilot.sas = c->sas;
        o.feed_controls = feed;
        o.preview_s = preview_s;
        o.acc_lead_s = acc_lead_s;
        sim_flight_trim_inputs(f, &in);
        p = sim_pilot_replay_create(ac, L, &o, &in, NULL, &err);
    }
    if (!p) {
        fprintf(stderr, "replay: %s\n", err.msg);
        out->failed = 1;
        goto done;
    }
    sim_log_summary info;
    sim_log_info(L, &info);
    for (int i = 0; i < 4; i++)
        out->min_pct[i] = 100.0, out->max_pct[i] = 0.0;
    sim_flight_out o;
    sim_flight_state(f, &o);
    long n = llround(info.t1_s * RATE_HZ);
    for (long k = 0; k < n; k++) {
        sim_pilot_replay_step(p, &o, &in);
        const double u[4] = {in.ctl.collective_pct, in.ctl.long_cyclic_pct, in.ctl.lat_cyclic_pct, in.ctl.pedal_pct};
        for (int i = 0; i < 4; i++)
            out->min_pct[i] = fmin(out->min_pct[i], u[i]), out->max_pct[i] = fmax(out->max_pct[i], u[i]);
        if (sim_flight_step(f, &in, &o, &err) != 0) {
            fprintf(stderr, "replay: %s\n", err.msg);
            out->failed = 1;
            break;
        }
        if (tr && k < tr->n) {
            double d2 = 0.0;
            for (int i = 0; i < 3; i++)
                d2 += (o.pos_S_m[i] - tr->pos_S[k][i]) * (o.pos_S_m[i] - tr->pos_S[k][i]);
            out->max_dev_m = fmax(out->max_dev_m, sqrt(d2));
        }
    }
    sim_pilot_replay_step(p, &o, &in); /* counts the last state */
    sim_pilot_replay_result(p, &out->r);
    out->end_on_deck = o.on_deck;
    out->end_coll_pct = o.ctl.collective_pct;
done:
    sim_pilot_replay_destroy(p);
    sim_flight_destroy(f);
    sim_ship_motion_destroy(motion);
}

static void print_replay(const char *what, const replay_run *r)
{
    printf("%s: rms %.3f m, max %.3f m at %.2f s, heading max %.2f deg", what, r->r.all.rms_m, r->r.all.max_m,
           r->r.all.t_max_s, r->r.max_heading_err_rad * CORE_RAD_TO_DEG);
    for (int ph = 0; ph < SIM_REPLAY_NPHASE; ph++)
        if (r->r.phase[ph].n)
            printf("; %s %.1f s: rms %.3f max %.3f m", sim_replay_phase_name(ph), r->r.phase[ph].duration_s,
                   r->r.phase[ph].rms_m, r->r.phase[ph].max_m);
    if (r->max_dev_m >= 0.0)
        printf("; from the recorded steps max %.4f m", r->max_dev_m);
    printf("; controls collective %.1f-%.1f long %.1f-%.1f lat %.1f-%.1f pedal %.1f-%.1f %%, %ld at a stop\n",
           r->min_pct[0], r->max_pct[0], r->min_pct[1], r->max_pct[1], r->min_pct[2], r->max_pct[2], r->min_pct[3],
           r->max_pct[3], r->r.stop_steps);
}

/* 2. The log read back. */
static void test_read(const sim_log *L, const traj *tr)
{
    sim_log_summary info;
    sim_log_info(L, &info);
    printf("log: %ld events, %ld states (%.2f-%.2f s), %ld ship states, %ld inputs of %d station '%s', %ld bad\n",
           info.n_events, info.n_states, info.t0_s, info.t1_s, info.n_ship, info.n_inputs, info.n_stations,
           info.station, info.n_inputs_bad);
    /* a state every 4th step (50 Hz of 200), each with its ship state; an input every step */
    CHECK(info.n_states == tr->n / 4);
    CHECK(info.n_ship == info.n_states);
    CHECK(info.n_inputs == tr->n && info.n_stations == 1 && !strcmp(info.station, "auto") && info.n_inputs_bad == 0);
    CHECK_NEAR(info.t0_s, 4.0 / RATE_HZ, 1e-9);
    double dpos = 0.0, dvel = 0.0;
    int phases[SIM_REPLAY_NPHASE] = {0};
    for (long k = 3; k < tr->n; k += 4) {
        sim_log_sample s;
        CHECK(sim_log_sample_at(L, tr->t_s[k], &s) == 0);
        for (int i = 0; i < 3; i++)
            dpos = fmax(dpos, fabs(s.pos_S_m[i] - tr->pos_S[k][i]));
        phases[s.phase]++;
        if (k >= 1 && k + 1 < tr->n) { /* the deck-relative velocity: d pos_S / dt over the steps */
            for (int i = 0; i < 3; i++) {
                double fd = (tr->pos_S[k + 1][i] - tr->pos_S[k - 1][i]) / (tr->t_s[k + 1] - tr->t_s[k - 1]);
                dvel = fmax(dvel, fabs(s.vel_S_mps[i] - fd));
            }
        }
    }
    printf("log: samples from the flown positions %.2e m; the deck-relative velocity from d pos_S / dt %.4f m/s; "
           "phases hover %d, translate %d, descend %d samples\n", dpos, dvel, phases[0], phases[1], phases[2]);
    CHECK(dpos <= 1e-9);
    CHECK(dvel <= 0.001);
    CHECK(phases[SIM_REPLAY_HOVER] > 0 && phases[SIM_REPLAY_TRANSLATE] > 0 && phases[SIM_REPLAY_DESCEND] > 0);
    /* outside: held at the ends, the velocity 0 after */
    sim_log_sample s;
    CHECK(sim_log_sample_at(L, info.t1_s + 5.0, &s) == 1);
    CHECK(s.vel_S_mps[0] == 0.0 && s.vel_S_mps[1] == 0.0 && s.vel_S_mps[2] == 0.0);
    CHECK_NEAR(s.pos_S_m[2], tr->pos_S[4 * info.n_states - 1][2], 1e-9);

    /* the run information, as the loop logged it before the first step */
    sim_run_info ri;
    CHECK(sim_log_run_info(L, &ri) == 0);
    CHECK(!strcmp(ri.scenario_path, SCEN) && !strcmp(ri.scenario, "replay-test"));
    CHECK(!strcmp(ri.ship_path, "scenarios/ships/cg47.ini") && ri.seed == 7 && ri.sea.state == 3);
    CHECK(ri.rate_hz == RATE_HZ && ri.state_rate_hz == RATE_HZ / 4);
    /* the states for drawing: the CG where pos_S says from the ship's pose
     * (samples and between them), the attitude a unit quaternion, the
     * positions of the samples exact */
    double dS = 0.0, dE = 0.0, dq = 0.0;
    for (long k = 3; k < 4 * info.n_states; k += 2) {
        sim_log_state ls;
        CHECK(sim_log_state_at(L, tr->t_s[k], &ls) == 0);
        if (k % 4 == 3)
            for (int i = 0; i < 3; i++)
                dS = fmax(dS, fabs(ls.pos_S_m[i] - tr->pos_S[k][i]));
        core_vec3 p = core_pose_point_to_E(&ls.ship, core_vec3_make(ls.pos_S_m[0], ls.pos_S_m[1], ls.pos_S_m[2]));
        dE = fmax(dE, core_vec3_norm(core_vec3_sub(p, ls.heli.pos_E_m)));
        core_quat q = ls.heli.q_EF;
        dq = fmax(dq, fabs(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z - 1.0));
    }
    printf("log states: pos_S from the flown %.1e m; the CG from the ship's pose and pos_S %.1e m; |q| - 1 %.1e\n", dS,
           dE, dq);
    CHECK(dS <= 1e-9);
    CHECK(dE < 1e-3); /* linear between samples 20 ms apart */
    CHECK(dq < 1e-12);
}

/* ---- 5. bad logs */
static void write_bytes(const char *path, const void *b, size_t n)
{
    FILE *f = fopen(path, "wb");
    if (f) {
        fwrite(b, 1, n, f);
        fclose(f);
    }
}

static void put_event(lcm_eventlog_t *el, const char *ch, const void *data, int n, int64_t ts)
{
    lcm_eventlog_event_t ev;
    memset(&ev, 0, sizeof ev);
    ev.timestamp = ts;
    ev.channellen = (int32_t)strlen(ch);
    ev.datalen = n;
    ev.channel = (char *)ch;
    ev.data = (void *)data;
    lcm_eventlog_write_event(el, &ev);
}

/* A log of n states (heli and ship), state k at utime[k]; nan_at: that
 * state's pos_S_m[1] NaN; no_ship_at: that state without its ship state. */
static void write_states(const char *path, int n, const int64_t *utime, int nan_at, int no_ship_at)
{
    lcm_eventlog_t *el = lcm_eventlog_create(path, "w");
    if (!el)
        return;
    unsigned char buf[2048];
    for (int k = 0; k < n; k++) {
        disim_heli_state_t h;
        memset(&h, 0, sizeof h);
        h.utime = utime[k];
        h.seq = k;
        h.pos_S_m[2] = -6.0;
        h.pos_S_m[1] = k == nan_at ? NAN : 0.0;
        h.quat_EB[0] = 1.0;
        h.collective_pct = h.long_cyclic_pct = h.lat_cyclic_pct = h.pedal_pct = 50.0;
        int m = disim_heli_state_t_encode(buf, 0, sizeof buf, &h);
        put_event(el, DISIM_CH_HELI_STATE, buf, m, h.utime);
        if (k == no_ship_at)
            continue;
        disim_ship_state_t s;
        memset(&s, 0, sizeof s);
        s.utime = h.utime;
        s.quat_ES[0] = 1.0;
        m = disim_ship_state_t_encode(buf, 0, sizeof buf, &s);
        put_event(el, DISIM_CH_SHIP_STATE, buf, m, s.utime);
    }
    lcm_eventlog_destroy(el);
}

static void expect_refused(const char *what, const char *path, const char *want1, const char *want2)
{
    core_err err = {0};
    sim_log *L = sim_log_load(path, &err);
    printf("bad log, %s: %s\n", what, err.msg);
    CHECK(L == NULL && strstr(err.msg, path) && strstr(err.msg, want1) && (!want2 || strstr(err.msg, want2)));
    sim_log_destroy(L);
}

static void test_bad(const char *good)
{
    char dir[64], p[128];
    snprintf(dir, sizeof dir, "/tmp/test_pilot_replay_%d", (int)getpid());
    mkdir(dir, 0700);
    snprintf(p, sizeof p, "%s/missing.log", dir);
    expect_refused("missing", p, "cannot read", "No such file");
    expect_refused("a folder", dir, "a folder", "expected a regular file");
    snprintf(p, sizeof p, "%s/empty.log", dir);
    write_bytes(p, "", 0);
    expect_refused("empty", p, "empty: expected", NULL);
    snprintf(p, sizeof p, "%s/text.log", dir);
    write_bytes(p, "[scenario]\nname = x\n", 20);
    expect_refused("not a log", p, "not an LCM event log", NULL);
    /* the good log cut inside its 200th event */
    FILE *f = fopen(good, "rb");
    static unsigned char big[1 << 22];
    size_t n = f ? fread(big, 1, sizeof big, f) : 0;
    if (f)
        fclose(f);
    CHECK(n > 100000 && n < sizeof big);
    lcm_eventlog_t *el = lcm_eventlog_create(good, "r");
    long long cut = 0;
    for (int k = 0; el && k < 200; k++) {
        lcm_eventlog_event_t *ev = lcm_eventlog_read_next_event(el);
        if (!ev)
            break;
        lcm_eventlog_free_event(ev);
        if (k == 198)
            cut = (long long)ftello(el->f) + 40; /* 12 bytes into event 200's channel and data */
    }
    if (el)
        lcm_eventlog_destroy(el);
    snprintf(p, sizeof p, "%s/truncated.log", dir);
    write_bytes(p, big, (size_t)cut);
    expect_refused("truncated", p, "event 200 ", "(truncated)");
    /* the header alone of the next event, cut */
    snprintf(p, sizeof p, "%s/truncated_hdr.log", dir);
    write_bytes(p, big, (size_t)cut - 30);
    expect_refused("truncated in a header", p, "event 200 ", "header (truncated)");
    /* garbage after a whole event */
    snprintf(p, sizeof p, "%s/corrupt.log", dir);
    memcpy(big + cut - 40, "garbage!", 8);
    write_bytes(p, big, n);
    expect_refused("corrupt", p, "event 200 ", "no sync word");
    /* a heli_state_t that is not one, and a NaN in one */
    snprintf(p, sizeof p, "%s/not_heli.log", dir);
    if ((el = lcm_eventlog_create(p, "w"))) {
        put_event(el, "ANOTHER_CHANNEL", "not read", 8, 0);
        put_event(el, DISIM_CH_HELI_STATE, "not a heli_state_t", 18, 0);
        lcm_eventlog_destroy(el);
    }
    expect_refused("a heli_state_t that is not one", p, "event 2 (DISIM_HELI_STATE", "heli_state_t: fingerprint");
    int64_t ut[4] = {20000, 40000, 60000, 80000};
    snprintf(p, sizeof p, "%s/nan.log", dir);
    write_states(p, 4, ut, 2, -1);
    expect_refused("a NaN", p, "event 5 (DISIM_HELI_STATE", "pos_S_m");
    /* a sim_status_t that is not one (the loop's own message) */
    snprintf(p, sizeof p, "%s/bad_status.log", dir);
    if ((el = lcm_eventlog_create(p, "w"))) {
        put_event(el, DISIM_CH_SIM_STATUS, "not a sim_status_t", 18, 0);
        lcm_eventlog_destroy(el);
    }
    expect_refused("a sim_status_t that is not one", p, "event 1 (DISIM_SIM_STATUS", "sim_status_t: fingerprint");
    /* no heli_state_t: pilot inputs alone */
    snprintf(p, sizeof p, "%s/no_heli.log", dir);
    if ((el = lcm_eventlog_create(p, "w"))) {
        unsigned char b[256];
        disim_pilot_input_t m;
        memset(&m, 0, sizeof m);
        m.station_id = "a";
        m.collective_pct = m.long_cyclic_pct = m.lat_cyclic_pct = m.pedal_pct = 50.0;
        int len = disim_pilot_input_t_encode(b, 0, sizeof b, &m);
        put_event(el, DISIM_CH_PILOT_INPUT, b, len, 0);
        put_event(el, DISIM_CH_PILOT_INPUT, b, len, 5000);
        lcm_eventlog_destroy(el);
    }
    expect_refused("no heli_state_t", p, "0 heli_state_t in 2 events", NULL);
    snprintf(p, sizeof p, "%s/no_ship.log", dir);
    write_states(p, 4, ut, -1, 1);
    expect_refused("a state without its ship state", p, "event 3 (DISIM_HELI_STATE", "no ship_state_t");
    int64_t back[4] = {20000, 40000, 20000, 40000};
    snprintf(p, sizeof p, "%s/reset.log", dir);
    write_states(p, 4, back, -1, -1);
    expect_refused("a reset", p, "event 5 (DISIM_HELI_STATE", "one flight");
    /* the same writer's log without a fault reads */
    snprintf(p, sizeof p, "%s/ok.log", dir);
    write_states(p, 4, ut, -1, -1);
    core_err err = {0};
    sim_log *L = sim_log_load(p, &err);
    CHECK(L != NULL);
    sim_log_destroy(L);
    /* inputs: one station's are the controls, a NaN one skipped and
     * counted; with a second station the flown controls are */
    for (int two = 0; two < 2; two++) {
        snprintf(p, sizeof p, "%s/inputs.log", dir);
        write_states(p, 4, ut, -1, -1);
        FILE *fa = fopen(p, "ab");
        lcm_eventlog_t ela = {fa, 0};
        unsigned char b[256];
        for (int k = 0; fa && k < 3 + two; k++) {
            disim_pilot_input_t m;
            memset(&m, 0, sizeof m);
            m.station_id = k == 3 ? "other" : "a";
            m.seq = k;
            m.collective_pct = k == 1 ? NAN : 30.0 + k;
            m.long_cyclic_pct = m.lat_cyclic_pct = m.pedal_pct = 50.0;
            int len = disim_pilot_input_t_encode(b, 0, sizeof b, &m);
            put_event(&ela, DISIM_CH_PILOT_INPUT, b, len, 20000 * (k + 1));
        }
        if (fa)
            fclose(fa);
        L = sim_log_load(p, &err);
        CHECK(L != NULL);
        if (!L) {
            fprintf(stderr, "inputs: %s\n", err.msg);
            continue;
        }
        sim_log_summary in;
        sim_log_info(L, &in);
        sim_log_sample smp;
        sim_log_sample_at(L, 0.065, &smp); /* after the third input (60000 us) */
        printf("inputs, %s: %d station(s) '%s', %ld taken, %ld bad; collective at 0.065 s %.1f %%\n",
               two ? "two stations" : "one station", in.n_stations, in.station, in.n_inputs, in.n_inputs_bad,
               smp.controls_pct[0]);
        CHECK(in.n_inputs_bad == 1);
        if (!two)
            CHECK(in.n_stations == 1 && !strcmp(in.station, "a") && in.n_inputs == 2 && smp.controls_pct[0] == 32.0);
        else
            CHECK(in.n_stations == 2 && in.n_inputs == 0 && smp.controls_pct[0] == 50.0);
        sim_log_destroy(L);
    }
    const char *names[] = {"empty", "text", "truncated", "truncated_hdr", "corrupt", "not_heli", "nan",
                           "no_heli", "no_ship", "reset", "ok", "bad_status", "inputs"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        snprintf(p, sizeof p, "%s/%s.log", dir, names[i]);
        unlink(p);
    }
    rmdir(dir);
}

/* 7. The SAS through the log: the SAS-off run above reads back off; the
 * landing flown with the SAS engaged and logged reads back on, and the
 * replay flying it so (the flight's SAS and the gains scheduled with it,
 * as disim fly --pilot replay does from the log) stays within 0.5 m of
 * the recorded steps. */
static void test_sas(const hfm_aircraft *ac, const core_ship *ship, const sim_log *off)
{
    sim_log_summary info;
    sim_log_info(off, &info);
    printf("the SAS-off run's log: SAS %d\n", info.sas);
    CHECK(info.sas == 0);
    char slog[80];
    snprintf(slog, sizeof slog, "/tmp/test_pilot_replay_sas_%d.log", (int)getpid());
    static traj str;
    const conds srec = {15.0, 0.0, 3, 7, 0, 1};
    core_err err = {0};
    sim_log *S = NULL;
    if (record(ac, ship, &srec, slog, &str) != 0 || !(S = sim_log_load(slog, &err))) {
        fprintf(stderr, "the recorded run with the SAS: %s\n", err.msg);
        CHECK(0);
    } else {
        sim_log_info(S, &info);
        printf("the SAS-on run's log: SAS %d\n", info.sas);
        CHECK(info.sas == 1);
        conds as = srec;
        as.sas = info.sas > 0;
        replay_run ss;
        replay(ac, ship, S, &as, 0, -1.0, -1.0, &str, &ss);
        print_replay("replay with the SAS as logged, the same conditions", &ss);
        CHECK(!ss.failed && ss.r.ended && ss.max_dev_m >= 0.0 && ss.max_dev_m <= 0.5 && ss.r.all.max_m <= 0.5);
    }
    sim_log_destroy(S);
    unlink(slog);
}

int main(void)
{
    setvbuf(stdout, NULL, _IOLBF, 0);
    core_err err = {0};
    core_ship ship;
    hfm_aircraft *ac = NULL;
    if (core_ship_load(SHIP, &ship, &err) != 0 || !(ac = hfm_aircraft_load(UH60, NULL, &err))) {
        fprintf(stderr, "set-up: %s\n", err.msg);
        CHECK(0);
        return check_done("test_pilot_replay");
    }
    char log[64];
    snprintf(log, sizeof log, "/tmp/test_pilot_replay_%d.log", (int)getpid());
    static traj tr;
    const conds rec = {15.0, 0.0, 3, 7, 0, 0};
    sim_log *L = NULL;
    if (record(ac, &ship, &rec, log, &tr) != 0 || !(L = sim_log_load(log, &err))) {
        fprintf(stderr, "the recorded run: %s\n", err.msg);
        CHECK(0);
    } else {
        test_read(L, &tr);
        replay_run same, same_np, same_ff, other, other_ff;
        replay(ac, &ship, L, &rec, 0, -1.0, -1.0, &tr, &same);
        print_replay("replay, the same conditions, the loops alone", &same);
        CHECK(!same.failed && same.max_dev_m >= 0.0 && same.max_dev_m <= 0.5 && same.r.all.max_m <= 0.5);
        CHECK(same.r.ended);
        /* the descent: the height loop's feed-forward keeps it within 0.3 m, rms 0.15 m
         * (measured 0.234 m, rms 0.139 m with the replay's integrals; without the
         * feed-forward 0.27 m, rms 0.17 m) */
        CHECK(same.r.phase[SIM_REPLAY_DESCEND].n > 0 && same.r.phase[SIM_REPLAY_DESCEND].max_m <= 0.3 &&
              same.r.phase[SIM_REPLAY_DESCEND].rms_m <= 0.15);
        /* the preview (the pilot's delay) does better than none */
        replay(ac, &ship, L, &rec, 0, 0.0, -1.0, &tr, &same_np);
        print_replay("replay, the same conditions, no preview", &same_np);
        CHECK(!same_np.failed && same.r.all.rms_m < same_np.r.all.rms_m);
        /* the acceleration led by the attitude loops' lag does better than not */
        replay_run same_nl;
        replay(ac, &ship, L, &rec, 0, -1.0, 0.0, &tr, &same_nl);
        print_replay("replay, the same conditions, the acceleration not led", &same_nl);
        CHECK(!same_nl.failed && same.r.all.rms_m < same_nl.r.all.rms_m);
        replay(ac, &ship, L, &rec, 1, -1.0, -1.0, &tr, &same_ff);
        print_replay("replay, the same conditions, the recorded controls fed forward", &same_ff);
        CHECK(!same_ff.failed && same_ff.max_dev_m >= 0.0 && same_ff.max_dev_m <= 0.001);
        const conds oth = {25.0, 30.0, 4, 11, 0, 0};
        replay(ac, &ship, L, &oth, 0, -1.0, -1.0, NULL, &other);
        print_replay("replay, 25 kt from green 30, sea state 4", &other);
        CHECK(!other.failed && other.r.ended && isfinite(other.r.all.rms_m) && other.r.all.max_m <= 2.0);
        CHECK(other.r.stop_steps == 0);
        /* the recorded controls there: the loops correct the recorded trim's error */
        replay(ac, &ship, L, &oth, 1, -1.0, -1.0, NULL, &other_ff);
        print_replay("replay, 25 kt from green 30, sea state 4, the recorded controls fed forward", &other_ff);
        CHECK(!other_ff.failed && other_ff.r.ended && other_ff.r.all.max_m <= 2.0 && other_ff.r.stop_steps == 0);
        test_bad(log);
        /* 6. with the gear: the landing to settled on the deck, replayed */
        char glog[80];
        snprintf(glog, sizeof glog, "/tmp/test_pilot_replay_gear_%d.log", (int)getpid());
        static traj gtr;
        const conds grec = {15.0, 0.0, 3, 7, 1, 0};
        sim_log *G = NULL;
        if (record(ac, &ship, &grec, glog, &gtr) != 0 || !(G = sim_log_load(glog, &err))) {
            fprintf(stderr, "the recorded run with the gear: %s\n", err.msg);
            CHECK(0);
        } else {
            replay_run gs;
            replay(ac, &ship, G, &grec, 0, -1.0, -1.0, &gtr, &gs);
            print_replay("replay with the gear, the same conditions", &gs);
            printf("  ends %s the deck, collective %.1f %%\n", gs.end_on_deck ? "on" : "off", gs.end_coll_pct);
            CHECK(!gs.failed && gs.max_dev_m >= 0.0 && gs.max_dev_m <= 0.5);
            CHECK(gs.r.phase[SIM_REPLAY_ON_DECK].n > 0 && gs.end_on_deck && gs.end_coll_pct == 0.0);
        }
        sim_log_destroy(G);
        unlink(glog);
        test_sas(ac, &ship, L);
    }
    sim_log_destroy(L);
    unlink(log);
    hfm_aircraft_destroy(ac);
    return check_done("test_pilot_replay");
}
