/* test_loop.c -- the flight loop's LCM side (sim/loop.c, sim/pilots.c) in one process
 * over memq://: the stations' rules (refused messages counted per station
 * and changing nothing, sequence gaps, hold after silence with its flag,
 * priority and take-over), pause, resume, reset and load (a good and a
 * broken scenario), and a log whose inputs, replayed, fly the same
 * trajectory bit for bit; the instructor's controls (each refused with
 * its reason and accepted with its effect, a snapshot restored and flown
 * on bit for bit) and the console's lines. Run from the source root. */
#include "check.h"
#include "disim_lcm.h"
#include "sim.h"

#include <lcm/lcm.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define SCEN_A "tests/sim/data/loop_a.ini"
#define SCEN_B "tests/sim/data/loop_b.ini"
#define SCEN_BAD "tests/sim/bad/bad_range.ini"

/* ---- an encoded pilot_input_t */
static int enc(unsigned char *b, const char *id, long long seq, double coll, double lon, double lat, double ped,
               int take)
{
    disim_pilot_input_t m;
    memset(&m, 0, sizeof m);
    m.utime = seq < 1000000000LL ? seq * 20000 : 0; /* a spoofed seq near 2^63 has no utime of its own */
    m.station_id = (char *)id;
    m.seq = seq;
    m.collective_pct = coll;
    m.long_cyclic_pct = lon;
    m.lat_cyclic_pct = lat;
    m.pedal_pct = ped;
    m.take_over = (int8_t)take;
    int n = disim_pilot_input_t_encoded_size(&m);
    return disim_pilot_input_t_encode(b, 0, n, &m) == n ? n : -1;
}

static const sim_pilot_station *st_of(const sim_pilots *p, const char *id, sim_pilot_station *s)
{
    for (int i = 0; i < sim_pilots_count(p); i++) {
        sim_pilots_station(p, i, s);
        if (!strcmp(s->id, id))
            return s;
    }
    memset(s, 0, sizeof *s);
    return s;
}

static int idx_of(const sim_pilots *p, const char *id)
{
    sim_pilot_station s;
    for (int i = 0; i < sim_pilots_count(p); i++) {
        sim_pilots_station(p, i, &s);
        if (!strcmp(s.id, id))
            return i;
    }
    return -2;
}

/* The rules alone, on buffers (no blend: the station's controls at once). */
static void test_rules(void)
{
    core_err err = {0};
    sim_pilots_opts o;
    sim_pilots_opts_default(&o);
    CHECK(o.blend_s == SIM_PILOTS_BLEND_S);
    o.blend_s = 0.0;
    const hfm_controls flown = {50.0, 50.0, 50.0, 50.0};
    sim_pilots *p = sim_pilots_create(&o, &err);
    CHECK(p != NULL);
    unsigned char b[512];
    char why[256];
    sim_flight_inputs in;
    sim_pilot_station s;
    /* before any station: held */
    CHECK(sim_pilots_inputs(p, 0.0, &flown, &in) == 1 && in.hold == 1);
    int n = enc(b, "A", 0, 60, 50, 50, 50, 0);
    CHECK(sim_pilots_offer(p, b, n, 0.0, why, sizeof why) == 0);
    CHECK(sim_pilots_inputs(p, 0.0, &flown, &in) == 0 && in.hold == 0 && in.ctl.collective_pct == 60.0);
    /* refused: truncated (the id is whole: A's), NaN, out of range, garbage */
    n = enc(b, "A", 1, 61, 50, 50, 50, 0);
    CHECK(sim_pilots_offer(p, b, n - 3, 0.01, why, sizeof why) == 1);
    CHECK(strstr(why, "ends at byte") != NULL);
    n = enc(b, "A", 1, NAN, 50, 50, 50, 0);
    CHECK(sim_pilots_offer(p, b, n, 0.01, why, sizeof why) == 1 && strstr(why, "collective_pct") != NULL);
    n = enc(b, "A", 1, 50, 101, 50, 50, 0);
    CHECK(sim_pilots_offer(p, b, n, 0.01, why, sizeof why) == 1 && strstr(why, "long_cyclic_pct") != NULL);
    memset(b, 0xAB, 64);
    CHECK(sim_pilots_offer(p, b, 64, 0.01, why, sizeof why) == 1 && strstr(why, "fingerprint") != NULL);
    st_of(p, "A", &s);
    CHECK(s.refused == 3 && s.received == 1 && s.last_seq == 0 && s.gaps == 0);
    CHECK(sim_pilots_refused_unknown(p) == 1);
    /* ... and changed nothing */
    CHECK(sim_pilots_inputs(p, 0.01, &flown, &in) == 0 && in.ctl.collective_pct == 60.0 && in.ctl.long_cyclic_pct == 50.0);
    /* a gap of 3 (seq 1-3 missing), then a stale seq refused */
    n = enc(b, "A", 4, 62, 50, 50, 50, 0);
    CHECK(sim_pilots_offer(p, b, n, 0.02, NULL, 0) == 0);
    n = enc(b, "A", 2, 70, 50, 50, 50, 0);
    CHECK(sim_pilots_offer(p, b, n, 0.03, why, sizeof why) == 1 && strstr(why, "stale") != NULL);
    st_of(p, "A", &s);
    CHECK(s.gaps == 3 && s.last_seq == 4 && s.refused == 4);
    CHECK(sim_pilots_inputs(p, 0.03, &flown, &in) == 0 && in.ctl.collective_pct == 62.0);
    /* silent: live at 0.5 s after the last message, held after */
    CHECK(sim_pilots_inputs(p, 0.02 + 0.5, &flown, &in) == 0);
    CHECK(sim_pilots_inputs(p, 0.02 + 0.505, &flown, &in) == 1 && in.hold == 1);
    /* a second station B connects: A stays active (silent, held) */
    n = enc(b, "B", 0, 40, 50, 50, 50, 0);
    CHECK(sim_pilots_offer(p, b, n, 0.6, NULL, 0) == 0);
    CHECK(sim_pilots_inputs(p, 0.6, &flown, &in) == 1 && sim_pilots_active(p) == idx_of(p, "A"));
    /* B takes over */
    n = enc(b, "B", 1, 41, 50, 50, 50, 1);
    CHECK(sim_pilots_offer(p, b, n, 0.61, NULL, 0) == 0);
    CHECK(sim_pilots_inputs(p, 0.61, &flown, &in) == 0 && in.ctl.collective_pct == 41.0 &&
          sim_pilots_active(p) == idx_of(p, "B"));
    /* A, first to connect (higher priority), speaks again (its restart:
     * seq back at 0 after its silence is taken): the take-over holds */
    n = enc(b, "A", 0, 63, 50, 50, 50, 0);
    CHECK(sim_pilots_offer(p, b, n, 0.62, NULL, 0) == 0);
    CHECK(sim_pilots_inputs(p, 0.62, &flown, &in) == 0 && in.ctl.collective_pct == 41.0);
    /* B replayed after a silence: a seq below its last but not a restart's is refused */
    n = enc(b, "B", 300, 41, 50, 50, 50, 0);
    CHECK(sim_pilots_offer(p, b, n, 0.63, NULL, 0) == 0);
    n = enc(b, "B", 250, 99, 50, 50, 50, 0);
    char rwhy[200] = "";
    CHECK(sim_pilots_offer(p, b, n, 1.19, rwhy, sizeof rwhy) != 0 && strstr(rwhy, "a replay") != NULL);
    /* B falls silent: A (live, higher priority) takes the controls back */
    n = enc(b, "A", 1, 64, 50, 50, 50, 0);
    CHECK(sim_pilots_offer(p, b, n, 1.2, NULL, 0) == 0);
    CHECK(sim_pilots_inputs(p, 1.2, &flown, &in) == 0 && in.ctl.collective_pct == 64.0 &&
          sim_pilots_active(p) == idx_of(p, "A"));
    sim_pilots_destroy(p);

    /* a priority list: B first; C not on it is refused; B preempts A */
    CHECK(sim_pilots_opts_parse(&o, "B,A", &err) == 0 && o.n_priority == 2);
    CHECK(sim_pilots_opts_parse(&o, "B,,A", &err) < 0);
    CHECK(sim_pilots_opts_parse(&o, "B,A,B", &err) < 0 && strstr(err.msg, "twice") != NULL);
    CHECK(sim_pilots_opts_parse(&o, "B,A", &err) == 0);
    p = sim_pilots_create(&o, &err);
    n = enc(b, "A", 0, 30, 50, 50, 50, 0);
    CHECK(sim_pilots_offer(p, b, n, 0.0, NULL, 0) == 0);
    CHECK(sim_pilots_inputs(p, 0.0, &flown, &in) == 0 && in.ctl.collective_pct == 30.0);
    n = enc(b, "C", 0, 20, 50, 50, 50, 1);
    CHECK(sim_pilots_offer(p, b, n, 0.0, why, sizeof why) == 1 && strstr(why, "not on the station list") != NULL);
    CHECK(sim_pilots_inputs(p, 0.0, &flown, &in) == 0 && in.ctl.collective_pct == 30.0);
    n = enc(b, "B", 0, 35, 50, 50, 50, 0);
    CHECK(sim_pilots_offer(p, b, n, 0.01, NULL, 0) == 0);
    CHECK(sim_pilots_inputs(p, 0.01, &flown, &in) == 0 && in.ctl.collective_pct == 35.0 && sim_pilots_active(p) == 0);
    /* A takes over from B explicitly */
    n = enc(b, "A", 1, 31, 50, 50, 50, 1);
    CHECK(sim_pilots_offer(p, b, n, 0.02, NULL, 0) == 0);
    CHECK(sim_pilots_inputs(p, 0.02, &flown, &in) == 0 && in.ctl.collective_pct == 31.0 && sim_pilots_active(p) == 1);
    sim_pilots_destroy(p);
    o.hold_after_s = 0.0;
    CHECK(sim_pilots_create(&o, &err) == NULL && strstr(err.msg, "hold after") != NULL);
    o.hold_after_s = 0.5;
    o.blend_s = -1.0;
    CHECK(sim_pilots_create(&o, &err) == NULL && strstr(err.msg, "blend over") != NULL);
}

/* u at a blend's fraction w from a to b */
/* One spoofed message with seq 2^63 - 1 in a station's name: refused and
 * counted, the station's own messages still taken, its gaps unchanged
 * (the seq arithmetic cannot overflow). */
static void test_seq_spoof(void)
{
    sim_pilots_opts o;
    sim_pilots_opts_default(&o);
    o.blend_s = 0.0;
    core_err err = {0};
    sim_pilots *p = sim_pilots_create(&o, &err);
    CHECK(p != NULL);
    if (!p)
        return;
    unsigned char b[256];
    char why[256] = "";
    sim_pilot_station s;
    int n = enc(b, "A", 10, 60, 50, 50, 50, 0);
    CHECK(sim_pilots_offer(p, b, n, 0.0, NULL, 0) == 0);
    n = enc(b, "A", 9223372036854775807LL, 99, 50, 50, 50, 0);
    CHECK(sim_pilots_offer(p, b, n, 0.005, why, sizeof why) == 1 && strstr(why, "jumps") != NULL);
    n = enc(b, "A", 11, 61, 50, 50, 50, 0);
    CHECK(sim_pilots_offer(p, b, n, 0.01, why, sizeof why) == 0);
    st_of(p, "A", &s);
    CHECK(s.last_seq == 11 && s.gaps == 0 && s.refused == 1 && s.received == 2);
    /* a jump within the limit is a gap, counted */
    n = enc(b, "A", 11 + SIM_PILOTS_SEQ_JUMP_MAX, 62, 50, 50, 50, 0);
    CHECK(sim_pilots_offer(p, b, n, 0.015, NULL, 0) == 0);
    st_of(p, "A", &s);
    CHECK(s.gaps == SIM_PILOTS_SEQ_JUMP_MAX - 1 && s.refused == 1);
    sim_flight_inputs in;
    const hfm_controls flown = {50.0, 50.0, 50.0, 50.0};
    CHECK(sim_pilots_inputs(p, 0.02, &flown, &in) == 0 && in.ctl.collective_pct == 62.0);
    sim_pilots_destroy(p);
}

static double lerp(double a, double b, double w) { return a + w * (b - a); }

/* The hand-over blend: a station's first message, a take-over, a return
 * after a silence and a reset each blend the flown controls into the
 * station's over blend_s, linearly, the station's own movement followed;
 * held in between; the blend's state for the status. */
static void test_blend(void)
{
    core_err err = {0};
    sim_pilots_opts o;
    sim_pilots_opts_default(&o);
    sim_pilots *p = sim_pilots_create(&o, &err);
    CHECK(p != NULL);
    const double T = SIM_PILOTS_BLEND_S;
    unsigned char b[512];
    sim_flight_inputs in;
    sim_pilots_blend_info bi;
    /* the trimmed hover the loop flies; station A sends 50 % everywhere */
    hfm_controls flown = {55.0, 48.0, 52.0, 33.0};
    int n = enc(b, "A", 0, 50, 50, 50, 50, 0);
    CHECK(sim_pilots_offer(p, b, n, 1.0, NULL, 0) == 0);
    CHECK(sim_pilots_inputs(p, 1.0, &flown, &in) == 0 && in.hold == 0);
    /* its first step flies the flown controls: no step */
    CHECK(in.ctl.collective_pct == 55.0 && in.ctl.long_cyclic_pct == 48.0 && in.ctl.lat_cyclic_pct == 52.0 &&
          in.ctl.pedal_pct == 33.0);
    sim_pilots_blend(p, &bi);
    CHECK(bi.blending == 1 && bi.station == idx_of(p, "A") && bi.t0_s == 1.0 && bi.started == 1 &&
          bi.from_pct[3] == 33.0);
    /* a quarter through; the station moves its collective meanwhile and
     * the blend follows it (the start's controls stay the blend's) */
    flown = in.ctl;
    n = enc(b, "A", 1, 60, 50, 50, 50, 0);
    CHECK(sim_pilots_offer(p, b, n, 1.0 + 0.25 * T, NULL, 0) == 0);
    CHECK(sim_pilots_inputs(p, 1.0 + 0.25 * T, &flown, &in) == 0);
    CHECK_NEAR(in.ctl.collective_pct, lerp(55.0, 60.0, 0.25), 1e-12);
    CHECK_NEAR(in.ctl.pedal_pct, lerp(33.0, 50.0, 0.25), 1e-12);
    /* the largest change of a control per 5 ms step: the step shared out */
    double prev = in.ctl.pedal_pct, worst = 0.0;
    long long seq = 2;
    for (int k = 1; k <= 200; k++) {
        double t = 1.0 + 0.25 * T + 0.005 * k;
        n = enc(b, "A", seq++, 60, 50, 50, 50, 0);
        CHECK(sim_pilots_offer(p, b, n, t, NULL, 0) == 0);
        flown = in.ctl;
        CHECK(sim_pilots_inputs(p, t, &flown, &in) == 0);
        worst = fmax(worst, fabs(in.ctl.pedal_pct - prev));
        prev = in.ctl.pedal_pct;
    }
    CHECK(worst <= 17.0 * 0.005 / T + 1e-9);
    /* done: the station's own, the blend no more */
    CHECK(in.ctl.collective_pct == 60.0 && in.ctl.pedal_pct == 50.0);
    sim_pilots_blend(p, &bi);
    CHECK(bi.blending == 0 && bi.started == 1);
    /* B takes over with other controls: blended from A's */
    flown = in.ctl;
    n = enc(b, "B", 0, 40, 50, 50, 70, 1);
    CHECK(sim_pilots_offer(p, b, n, 2.5, NULL, 0) == 0);
    CHECK(sim_pilots_inputs(p, 2.5, &flown, &in) == 0 && in.ctl.collective_pct == 60.0 && in.ctl.pedal_pct == 50.0);
    CHECK(sim_pilots_inputs(p, 2.5 + 0.5 * T, &flown, &in) == 0);
    CHECK_NEAR(in.ctl.collective_pct, 50.0, 1e-12);
    CHECK_NEAR(in.ctl.pedal_pct, 60.0, 1e-12);
    sim_pilots_blend(p, &bi);
    CHECK(bi.blending == 1 && bi.station == idx_of(p, "B") && bi.started == 2);
    /* B falls silent mid-blend: held, the blend dropped; A (live, first)
     * then flies, blended in from what was flown */
    flown = in.ctl;
    n = enc(b, "A", seq++, 61, 50, 50, 50, 0);
    CHECK(sim_pilots_offer(p, b, n, 3.1, NULL, 0) == 0);
    CHECK(sim_pilots_inputs(p, 3.1, &flown, &in) == 0 && sim_pilots_active(p) == idx_of(p, "A"));
    CHECK(in.ctl.collective_pct == 50.0 && in.ctl.pedal_pct == 60.0);
    sim_pilots_blend(p, &bi);
    CHECK(bi.blending == 1 && bi.started == 3);
    /* silence: held; A back after it blends in again */
    CHECK(sim_pilots_inputs(p, 3.7, &flown, &in) == 1 && in.hold == 1);
    sim_pilots_blend(p, &bi);
    CHECK(bi.blending == 0);
    n = enc(b, "A", seq++, 70, 50, 50, 50, 0);
    CHECK(sim_pilots_offer(p, b, n, 4.0, NULL, 0) == 0);
    CHECK(sim_pilots_inputs(p, 4.0, &flown, &in) == 0 && in.ctl.collective_pct == 50.0);
    n = enc(b, "A", seq++, 70, 50, 50, 50, 0);
    CHECK(sim_pilots_offer(p, b, n, 4.0 + T, NULL, 0) == 0);
    CHECK(sim_pilots_inputs(p, 4.0 + T, &flown, &in) == 0 && in.ctl.collective_pct == 70.0);
    /* a reset moves the flown controls: the station blends in from them */
    hfm_controls start = {52.0, 50.0, 50.0, 40.0};
    sim_pilots_reblend(p);
    n = enc(b, "A", seq++, 70, 50, 50, 50, 0);
    CHECK(sim_pilots_offer(p, b, n, 5.2, NULL, 0) == 0);
    CHECK(sim_pilots_inputs(p, 5.2, &start, &in) == 0 && in.ctl.collective_pct == 52.0 && in.ctl.pedal_pct == 40.0);
    sim_pilots_blend(p, &bi);
    CHECK(bi.blending == 1 && bi.started == 5);
    sim_pilots_destroy(p);
}

/* ---- a world built from a scenario: calm air, the ship still */
typedef struct world {
    sim_scenario sc;
    hfm_aircraft *ac;
    sim_flight *fl;
    int builds;
} world;

static int build(void *user, const char *path, sim_loop_world *lw, core_err *err)
{
    world *w = user, nw;
    memset(&nw, 0, sizeof nw);
    if (sim_scenario_load(path, &nw.sc, err) != 0 || !(nw.ac = hfm_aircraft_load(nw.sc.aircraft_path, NULL, err)))
        return -1;
    sim_flight_opts fo;
    sim_flight_opts_default(&fo);
    fo.turbulence = 0;
    memcpy(fo.station_S_m, nw.sc.station_S_m, sizeof fo.station_S_m);
    if (!(nw.fl = sim_flight_create(nw.ac, &nw.sc.ship, &fo, NULL, NULL, NULL, NULL, err))) {
        hfm_aircraft_destroy(nw.ac);
        return -1;
    }
    sim_flight_destroy(w->fl);
    hfm_aircraft_destroy(w->ac);
    nw.builds = w->builds + 1;
    *w = nw;
    memset(lw, 0, sizeof *lw);
    lw->flight = w->fl;
    snprintf(lw->scenario, sizeof lw->scenario, "%s", w->sc.name);
    return 0;
}

/* what the loop published */
typedef struct seen {
    int status, heli;
    disim_sim_status_t last; /* scalar fields of the last status */
    char scenario[64], message[256], control_message[256];
    long long refused_A;
    int held_seen, paused_seen;
    double blend_on_s, blend_off_s; /* sim time of the first status with the blend's flag, the first after it without */
} seen;

static void on_status(const lcm_recv_buf_t *rb, const char *ch, const disim_sim_status_t *m, void *u)
{
    (void)rb, (void)ch;
    seen *s = u;
    s->status++;
    s->last = *m;
    snprintf(s->scenario, sizeof s->scenario, "%s", m->scenario);
    snprintf(s->message, sizeof s->message, "%s", m->message);
    snprintf(s->control_message, sizeof s->control_message, "%s", m->control_message);
    for (int i = 0; i < m->n_stations; i++)
        if (!strcmp(m->station_ids[i], "A"))
            s->refused_A = m->station_refused[i];
    if (m->flags & DISIM_SIM_STATUS_T_FLAG_INPUT_HELD)
        s->held_seen = 1;
    if ((m->flags & DISIM_SIM_STATUS_T_FLAG_CONTROLS_BLENDING) && s->blend_on_s < 0.0)
        s->blend_on_s = m->sim_time_s;
    if (!(m->flags & DISIM_SIM_STATUS_T_FLAG_CONTROLS_BLENDING) && s->blend_on_s >= 0.0 && s->blend_off_s < 0.0)
        s->blend_off_s = m->sim_time_s;
    if (m->state == DISIM_SIM_STATUS_T_PAUSED && (m->flags & DISIM_SIM_STATUS_T_FLAG_PAUSED))
        s->paused_seen = 1;
}

static void on_heli(const lcm_recv_buf_t *rb, const char *ch, const disim_heli_state_t *m, void *u)
{
    (void)rb, (void)ch, (void)m;
    ((seen *)u)->heli++;
}

/* Deliver what the loop published to the test's subscribers. */
static void drain(lcm_t *lc)
{
    while (lcm_handle_timeout(lc, 0) > 0)
        ;
}

static int iter(sim_loop *l, lcm_t *lc, sim_flight_out *out)
{
    core_err err = {0};
    int r = sim_loop_iterate(l, out, &err);
    drain(lc);
    return r;
}

static void control(lcm_t *lc, int cmd, const char *path)
{
    disim_sim_control_t c;
    memset(&c, 0, sizeof c);
    c.command = (int8_t)cmd;
    c.scenario_path = (char *)(path ? path : "");
    c.name = (char *)"";
    disim_sim_control_t_publish(lc, DISIM_CH_SIM_CONTROL, &c);
}

/* Fly n steps of a loop over memq, station A publishing every 4th step
 * (50 Hz) the trim with the collective 3 % up after step 40, and with
 * bad = 1 a malformed, a NaN and an out-of-range message among them.
 * The trajectory's z in S per step into z (n entries). */
static int fly_station(const char *log, const char *replay, int bad, int n, double *z, seen *sn)
{
    world w;
    memset(&w, 0, sizeof w);
    core_err err = {0};
    sim_loop_world lw;
    if (build(&w, SCEN_A, &lw, &err) != 0) {
        fprintf(stderr, "build: %s\n", err.msg);
        return -1;
    }
    sim_flight_inputs trim;
    sim_flight_trim_inputs(w.fl, &trim);
    sim_loop_opts o;
    sim_loop_opts_default(&o);
    o.realtime = 0;
    o.duration_s = n / o.rate_hz;
    o.lcm = replay ? 0 : 1;
    o.lcm_url = "memq://";
    o.log_path = log;
    o.replay_path = replay;
    o.scenario_path = SCEN_A;
    sim_loop *l = sim_loop_create(&o, &lw, build, &w, NULL, &err);
    if (!l) {
        fprintf(stderr, "loop: %s\n", err.msg);
        return -1;
    }
    lcm_t *lc = sim_loop_lcm(l);
    disim_sim_status_t_subscription_t *ss = lc ? disim_sim_status_t_subscribe(lc, DISIM_CH_SIM_STATUS, on_status, sn) : NULL;
    int rc = 0;
    long long seq = 0;
    for (int k = 0; k < n; k++) {
        if (lc && k % 4 == 0 && k < n - 200) { /* silent for the last second */
            unsigned char b[512];
            double c = trim.ctl.collective_pct + (k >= 40 ? 3.0 : 0.0);
            int len = enc(b, "A", seq++, c, trim.ctl.long_cyclic_pct, trim.ctl.lat_cyclic_pct, trim.ctl.pedal_pct, 0);
            if (bad && k % 40 == 8) {
                lcm_publish(lc, DISIM_CH_PILOT_INPUT, b, (unsigned)len - 5); /* truncated */
                len = enc(b, "A", seq, NAN, 50, 50, 50, 0);
                lcm_publish(lc, DISIM_CH_PILOT_INPUT, b, (unsigned)len);
                len = enc(b, "A", seq, 20, 50, -1, 50, 0);
                lcm_publish(lc, DISIM_CH_PILOT_INPUT, b, (unsigned)len);
                len = enc(b, "A", seq++, c, trim.ctl.long_cyclic_pct, trim.ctl.lat_cyclic_pct, trim.ctl.pedal_pct, 0);
            }
            lcm_publish(lc, DISIM_CH_PILOT_INPUT, b, (unsigned)len);
        }
        sim_flight_out out;
        int r = sim_loop_iterate(l, &out, &err);
        if (r != SIM_LOOP_STEPPED) {
            fprintf(stderr, "iterate %d: %d %s\n", k, r, err.msg);
            rc = -1;
            break;
        }
        z[k] = out.pos_S_m[2];
    }
    if (rc == 0 && sim_loop_iterate(l, NULL, &err) != SIM_LOOP_DONE)
        rc = -1;
    if (rc == 0 && sim_loop_finish(l, &err) != 0) {
        fprintf(stderr, "finish: %s\n", err.msg);
        rc = -1;
    }
    if (ss)
        disim_sim_status_t_unsubscribe(lc, ss);
    sim_loop_destroy(l);
    sim_flight_destroy(w.fl);
    hfm_aircraft_destroy(w.ac);
    return rc;
}

static void test_station_flight(void)
{
    enum { N = 600 };
    static double z0[N], z1[N], z2[N];
    seen s0 = {0}, s1 = {0}, s2 = {0};
    s0.blend_on_s = s0.blend_off_s = -1.0;
    char log[64];
    snprintf(log, sizeof log, "/tmp/test_loop_%ld.lcmlog", (long)getpid());
    CHECK(fly_station(NULL, NULL, 0, N, z0, &s0) == 0);
    CHECK(fly_station(log, NULL, 1, N, z1, &s1) == 0);
    /* the collective step climbs (z down in S): by 2 s, well above */
    CHECK(z0[399] < z0[39] - 0.5);
    /* the bad messages were refused, counted against A, changed nothing */
    CHECK(s1.refused_A > 0 && s0.refused_A == 0);
    CHECK(s1.refused_A == 3 * 10); /* at k = 8, 48, ..., 368 */
    CHECK(memcmp(z0, z1, sizeof z0) == 0);
    /* silent for the last second: held, the flag published */
    CHECK(s0.held_seen && s0.last.flags & DISIM_SIM_STATUS_T_FLAG_INPUT_HELD);
    /* the station's first message blended in: the flag raised at its first
     * step, lowered SIM_PILOTS_BLEND_S later (to a step, 5 ms) */
    CHECK(s0.blend_on_s >= 0.0 && s0.blend_on_s <= 0.0051);
    CHECK(fabs(s0.blend_off_s - s0.blend_on_s - SIM_PILOTS_BLEND_S) <= 0.0051);
    CHECK(s0.last.state == DISIM_SIM_STATUS_T_STOPPED);
    /* the log's inputs replayed (no LCM): the same trajectory bit for bit */
    CHECK(access(log, R_OK) == 0);
    CHECK(fly_station(NULL, log, 0, N, z2, &s2) == 0);
    CHECK(memcmp(z1, z2, sizeof z1) == 0);
    /* the log holds what was sent and received */
    lcm_eventlog_t *el = lcm_eventlog_create(log, "r");
    CHECK(el != NULL);
    int pil = 0, heli = 0, status = 0, ship = 0;
    long long last_ts = -1;
    int mono = 1;
    for (lcm_eventlog_event_t *ev; el && (ev = lcm_eventlog_read_next_event(el));) {
        pil += !strcmp(ev->channel, DISIM_CH_PILOT_INPUT);
        heli += !strcmp(ev->channel, DISIM_CH_HELI_STATE);
        ship += !strcmp(ev->channel, DISIM_CH_SHIP_STATE);
        status += !strcmp(ev->channel, DISIM_CH_SIM_STATUS);
        mono &= ev->timestamp >= last_ts;
        last_ts = ev->timestamp;
        lcm_eventlog_free_event(ev);
    }
    if (el)
        lcm_eventlog_destroy(el);
    CHECK(heli == N / 4 && ship == N / 4 && status >= 2 && mono);
    CHECK(pil == (N - 200) / 4 + 3 * 10);
    printf("test_loop: station flight: climb %.2f m by 2 s, %lld refused, log %d pilot inputs, %d states, %d statuses\n",
           z0[39] - z0[399], s1.refused_A, pil, heli, status);
    unlink(log);
}

/* Pause, resume, reset, load a good and a broken scenario. */
static void test_control(void)
{
    world w;
    memset(&w, 0, sizeof w);
    core_err err = {0};
    sim_loop_world lw;
    CHECK(build(&w, SCEN_A, &lw, &err) == 0);
    if (!w.fl)
        return;
    sim_loop_opts o;
    sim_loop_opts_default(&o);
    o.realtime = 0;
    o.duration_s = 100.0;
    o.lcm = 1;
    o.lcm_url = "memq://";
    o.scenario_path = SCEN_A;
    o.change_interval_s = 0.0; /* builds in the step, one a step: no rate limit (test_worker has it) */
    sim_loop *l = sim_loop_create(&o, &lw, build, &w, NULL, &err);
    CHECK(l != NULL);
    if (!l)
        return;
    lcm_t *lc = sim_loop_lcm(l);
    seen s = {0};
    disim_sim_status_t_subscription_t *ss = disim_sim_status_t_subscribe(lc, DISIM_CH_SIM_STATUS, on_status, &s);
    disim_heli_state_t_subscription_t *hs = disim_heli_state_t_subscribe(lc, DISIM_CH_HELI_STATE, on_heli, &s);
    sim_flight_out out;
    double z_start = w.sc.station_S_m[2];
    /* flying, no station: held at the trim; the ship still, calm air */
    for (int k = 0; k < 100; k++)
        CHECK(iter(l, lc, &out) == SIM_LOOP_STEPPED);
    CHECK(out.step == 100 && s.heli == 25);
    double t_paused = out.t_s;
    control(lc, DISIM_SIM_CONTROL_T_PAUSE, NULL);
    int heli_before = s.heli;
    for (int k = 0; k < 3; k++)
        CHECK(iter(l, lc, &out) == SIM_LOOP_PAUSED);
    CHECK(s.paused_seen && s.last.sim_time_s == t_paused && s.heli == heli_before);
    control(lc, DISIM_SIM_CONTROL_T_RESUME, NULL);
    CHECK(iter(l, lc, &out) == SIM_LOOP_STEPPED && out.step == 101);
    /* a nudge off the station (an external push: step with a big input
     * from station A), then reset: back at t 0 at the station */
    unsigned char b[512];
    int n = enc(b, "A", 0, 90, 50, 50, 50, 0);
    lcm_publish(lc, DISIM_CH_PILOT_INPUT, b, (unsigned)n);
    for (int k = 0; k < 150; k++)
        iter(l, lc, &out);
    CHECK(out.pos_S_m[2] < z_start - 0.3); /* climbed */
    control(lc, DISIM_SIM_CONTROL_T_RESET, NULL);
    /* the station is silent by now (0.5 s): held at the new trim */
    for (int k = 0; k < 200; k++)
        iter(l, lc, &out);
    CHECK(s.held_seen);
    CHECK(iter(l, lc, &out) == SIM_LOOP_STEPPED);
    CHECK(out.step == 201 && w.builds == 2);
    CHECK_NEAR(out.pos_S_m[2], z_start, 0.05);
    /* the pacing over the whole run, the reset and the pause in it: the
     * summary's "flown in ... (x real time)" is of the run, not of the
     * last world's pacer */
    sim_loop_report rr;
    sim_loop_report_get(l, &rr);
    CHECK(rr.pace.steps == 452 && fabs(rr.pace.sim_s - rr.run_s) < 1e-9 && fabs(rr.run_s - 452 / 200.0) < 1e-9);
    /* load another scenario: its name in the status, its station flown */
    control(lc, DISIM_SIM_CONTROL_T_LOAD_SCENARIO, SCEN_B);
    CHECK(iter(l, lc, &out) == SIM_LOOP_STEPPED);
    CHECK(out.step == 1 && w.builds == 3 && !strcmp(s.scenario, "loop_b") && s.message[0] == 0);
    CHECK_NEAR(out.pos_S_m[2], w.sc.station_S_m[2], 0.05);
    CHECK(fabs(w.sc.station_S_m[2] - z_start) > 1.0);
    /* a broken one: refused, the error published, loop_b kept flying */
    control(lc, DISIM_SIM_CONTROL_T_LOAD_SCENARIO, SCEN_BAD);
    CHECK(iter(l, lc, &out) == SIM_LOOP_STEPPED);
    CHECK(out.step == 2 && w.builds == 3 && !strcmp(s.scenario, "loop_b"));
    CHECK(strstr(s.message, "load refused") != NULL && strstr(s.message, "bad_range.ini") != NULL);
    CHECK(s.last.control_refused == 1);
    /* a load of /dev/zero (it would be read for ever): refused unread */
    control(lc, DISIM_SIM_CONTROL_T_LOAD_SCENARIO, "/dev/zero");
    CHECK(iter(l, lc, &out) == SIM_LOOP_STEPPED);
    CHECK(out.step == 3 && w.builds == 3 && !strcmp(s.scenario, "loop_b"));
    CHECK(strstr(s.message, "/dev/zero: a character device") != NULL && s.last.control_refused == 2);
    /* a path with terminal controls in it (ESC [2J clears a screen): the
     * refusal names it escaped, in the status and the log */
    control(lc, DISIM_SIM_CONTROL_T_LOAD_SCENARIO, "/tmp/\x1b[2J\x07_evil.ini");
    CHECK(iter(l, lc, &out) == SIM_LOOP_STEPPED && out.step == 4);
    printf("a path with terminal controls: %s\n", s.message);
    CHECK(strstr(s.message, "\\x1b[2J\\x07_evil.ini") != NULL && !strchr(s.message, 0x1b) && !strchr(s.message, 0x07));
    /* a malformed control: refused and counted */
    unsigned char junk[12] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};
    lcm_publish(lc, DISIM_CH_SIM_CONTROL, junk, sizeof junk);
    CHECK(iter(l, lc, &out) == SIM_LOOP_STEPPED && out.step == 5);
    CHECK(s.last.control_refused == 4 && strstr(s.message, "fingerprint") != NULL);
    /* a burst of 64 resets in one step: one world built, the others
     * refused with the reason (the step's time bounded by one build) */
    int builds0 = w.builds;
    for (int k = 0; k < 64; k++)
        control(lc, DISIM_SIM_CONTROL_T_RESET, NULL);
    CHECK(iter(l, lc, &out) == SIM_LOOP_STEPPED && out.step == 1);
    CHECK(w.builds == builds0 + 1 && s.last.control_refused == 4 + 63);
    CHECK(strstr(s.message, "one build per step") != NULL);
    /* the next step builds again */
    control(lc, DISIM_SIM_CONTROL_T_RESET, NULL);
    CHECK(iter(l, lc, &out) == SIM_LOOP_STEPPED && out.step == 1 && w.builds == builds0 + 2);
    printf("test_loop: control: paused at %.3f s, reset to z %.2f m, loaded %s, refused '%s'\n", t_paused,
           out.pos_S_m[2], s.scenario, s.message);
    disim_sim_status_t_unsubscribe(lc, ss);
    disim_heli_state_t_unsubscribe(lc, hs);
    sim_loop_destroy(l);
    sim_flight_destroy(w.fl);
    hfm_aircraft_destroy(w.ac);
}


/* ---- the instructor's controls: a world with its seaway (sim_world_build)
 * built again under the loop's setup */
typedef struct iworld {
    sim_scenario sc;
    hfm_aircraft *ac;
    sim_world sw;
    int builds;
} iworld;

/* The world of path under s into nw: 0, or -1 with err and nothing held. */
static int iworld_build(const char *path, const sim_loop_setup *s, iworld *nw, core_err *err)
{
    memset(nw, 0, sizeof *nw);
    if (sim_scenario_load(path, &nw->sc, err) != 0 || !(nw->ac = hfm_aircraft_load(nw->sc.aircraft_path, NULL, err)))
        return -1;
    sim_world_overrides ov;
    sim_world_overrides_default(&ov);
    if (s) {
        if (s->start >= 0)
            ov.start = s->start;
        ov.start_heading_rad = s->heading_rad;
        if (!isnan(s->wod_speed_mps)) {
            ov.wod_speed_mps = s->wod_speed_mps;
            ov.wod_dir_rad = s->wod_dir_rad;
        }
        if (s->sea_state >= 0)
            ov.sea_state = s->sea_state;
        if (s->turbulence >= 0)
            ov.turbulence = s->turbulence;
        if (s->has_station) {
            ov.has_station = 1;
            memcpy(ov.station_S_m, s->station_S_m, sizeof ov.station_S_m);
        }
    }
    if (sim_world_build(&nw->sc, nw->ac, &ov, NULL, &nw->sw, err) != 0) {
        hfm_aircraft_destroy(nw->ac);
        return -1;
    }
    return 0;
}

static void iworld_lw(const iworld *w, sim_loop_world *lw)
{
    memset(lw, 0, sizeof *lw);
    lw->flight = w->sw.flight;
    lw->motion = w->sw.motion;
    lw->info = w->sw.info;
    snprintf(lw->scenario, sizeof lw->scenario, "%s", w->sc.name);
}

static int ios_rebuild(void *user, const char *path, const sim_loop_setup *s, sim_loop_world *lw, core_err *err)
{
    iworld *w = user, nw;
    if (iworld_build(path, s, &nw, err) != 0)
        return -1;
    sim_world_free(&w->sw);
    hfm_aircraft_destroy(w->ac);
    nw.builds = w->builds + 1;
    *w = nw;
    iworld_lw(w, lw);
    return 0;
}

static int ios_build(void *user, const char *path, sim_loop_world *lw, core_err *err)
{
    return ios_rebuild(user, path, NULL, lw, err);
}

/* The same worlds through the loop's worker (sim_loop_builder). */
static int ios_prepare(void *user, const char *path, const sim_loop_setup *s, void **world, sim_loop_world *lw,
                       core_err *err)
{
    (void)user;
    iworld *nw = malloc(sizeof *nw);
    if (!nw || iworld_build(path, s, nw, err) != 0) {
        free(nw);
        return -1;
    }
    iworld_lw(nw, lw);
    *world = nw;
    return 0;
}

static void *ios_install(void *user, void *world)
{
    iworld *w = user, *nw = world, old = *w;
    nw->builds = w->builds + 1;
    *w = *nw;
    *nw = old;
    return nw;
}

static void ios_drop(void *user, void *world)
{
    (void)user;
    iworld *w = world;
    sim_world_free(&w->sw);
    hfm_aircraft_destroy(w->ac);
    free(w);
}

typedef struct ictl {
    int cmd;
    double pos[3], hdg, spd, dir;
    int sea, turb;
    const char *name;
} ictl;

/* Publish a control; its seq. */
static long long send_ctl(lcm_t *lc, const ictl *k)
{
    static const long long base = 1000;
    static long long n = 0; /* the test's own count (a test file, not a library) */
    disim_sim_control_t c;
    memset(&c, 0, sizeof c);
    c.seq = base + ++n;
    c.command = (int8_t)k->cmd;
    c.scenario_path = (char *)"";
    memcpy(c.pos_S_m, k->pos, sizeof c.pos_S_m);
    c.heading_rad = k->hdg;
    c.wod_speed_mps = k->spd;
    c.wod_dir_rad = k->dir;
    c.sea_state = (int8_t)k->sea;
    c.turbulence = (int8_t)k->turb;
    c.name = (char *)(k->name ? k->name : "");
    disim_sim_control_t_publish(lc, DISIM_CH_SIM_CONTROL, &c);
    return c.seq;
}

/* A control sent and the pass that carries it out: 1 when its answer is
 * result with sub in its message (sub NULL: any); rc the pass's. */
static int answer(sim_loop *l, lcm_t *lc, seen *s, const ictl *k, int result, const char *sub, sim_flight_out *out,
                  int *rc)
{
    long long seq = send_ctl(lc, k);
    *rc = iter(l, lc, out);
    int ok = s->last.control_seq == seq && s->last.control_result == result && s->last.control_command == k->cmd &&
             (!sub || strstr(s->control_message, sub) != NULL);
    if (!ok)
        fprintf(stderr, "control %d: seq %lld result %d: '%s' (expected seq %lld result %d '%s')\n", k->cmd,
                (long long)s->last.control_seq, s->last.control_result, s->control_message, seq, result,
                sub ? sub : "");
    return ok;
}

/* Station A's controls for pass j of a run: a slow weave about the trim. */
static void weave(lcm_t *lc, const sim_flight_inputs *trim, long long *seq, int j)
{
    unsigned char b[512];
    double c = trim->ctl.collective_pct + 3.0 * sin(j / 20.0), lat = trim->ctl.lat_cyclic_pct + 2.0 * cos(j / 15.0);
    int n = enc(b, "A", (*seq)++, c, trim->ctl.long_cyclic_pct, lat, trim->ctl.pedal_pct, 0);
    lcm_publish(lc, DISIM_CH_PILOT_INPUT, b, (unsigned)n);
}

/* n passes with the weave from pass j0, every step's output into o. */
static int weave_fly(sim_loop *l, lcm_t *lc, const sim_flight_inputs *trim, long long *seq, int j0, int n,
                     sim_flight_out *o)
{
    for (int j = 0; j < n; j++) {
        weave(lc, trim, seq, j0 + j);
        if (iter(l, lc, &o[j]) != SIM_LOOP_STEPPED)
            return -1;
    }
    return 0;
}

static int same_flight(const sim_flight_out *a, const sim_flight_out *b, int n)
{
    for (int j = 0; j < n; j++)
        if (a[j].step != b[j].step || memcmp(a[j].pos_E_m, b[j].pos_E_m, sizeof a[j].pos_E_m) ||
            memcmp(a[j].vel_E_mps, b[j].vel_E_mps, sizeof a[j].vel_E_mps) ||
            memcmp(a[j].euler_E_rad, b[j].euler_E_rad, sizeof a[j].euler_E_rad) ||
            memcmp(a[j].rate_B_radps, b[j].rate_B_radps, sizeof a[j].rate_B_radps) ||
            memcmp(a[j].pos_S_m, b[j].pos_S_m, sizeof a[j].pos_S_m) ||
            memcmp(&a[j].rotor_thrust_N, &b[j].rotor_thrust_N, sizeof(double)) ||
            memcmp(a[j].gear_load_N, b[j].gear_load_N, sizeof a[j].gear_load_N))
            return 0;
    return 1;
}

/* Every instructor's control refused with its reason, changing nothing. */
static void ios_refusals(sim_loop *l, lcm_t *lc, seen *s, iworld *w)
{
    sim_flight_out out;
    int rc, R = DISIM_SIM_STATUS_T_CONTROL_REFUSED, builds = w->builds;
    long long refused = s->last.control_refused;
    struct {
        ictl k;
        const char *why;
    } bad[] = {
        {{DISIM_SIM_CONTROL_T_REPOSITION, {0, 0, 1}, 0, 0, 0, 0, 0, NULL}, "inside the ship"},
        {{DISIM_SIM_CONTROL_T_REPOSITION, {0, 0, -1}, 0, 0, 0, 0, 0, NULL}, "within 2 m above the ship"},
        {{DISIM_SIM_CONTROL_T_REPOSITION, {0, 200, 30}, 0, 0, 0, 0, 0, NULL}, "under the sea"},
        {{DISIM_SIM_CONTROL_T_REPOSITION, {NAN, 0, -10}, 0, 0, 0, 0, 0, NULL}, "not finite"},
        {{DISIM_SIM_CONTROL_T_REPOSITION, {0, 5000, -10}, 0, 0, 0, 0, 0, NULL}, "within 1000 m"},
        {{DISIM_SIM_CONTROL_T_REPOSITION, {0, 40, -10}, 0.5, 0, 0, 0, 0, NULL}, "heading"},
        {{DISIM_SIM_CONTROL_T_RESET_DECK, {0, 0, 0}, INFINITY, 0, 0, 0, 0, NULL}, "heading"},
        {{DISIM_SIM_CONTROL_T_SET_WOD, {0, 0, 0}, 0, NAN, 0, 0, 0, NULL}, "WOD nan"},
        {{DISIM_SIM_CONTROL_T_SET_WOD, {0, 0, 0}, 0, 50, 0, 0, 0, NULL}, "WOD 50 m/s"},
        {{DISIM_SIM_CONTROL_T_SET_WOD, {0, 0, 0}, 0, 10, NAN, 0, 0, NULL}, "finite direction"},
        {{DISIM_SIM_CONTROL_T_SET_SEA, {0, 0, 0}, 0, 0, 0, 7, 0, NULL}, "sea state 7"},
        {{DISIM_SIM_CONTROL_T_SET_TURBULENCE, {0, 0, 0}, 0, 0, 0, 0, 2, NULL}, "turbulence 2"},
        {{DISIM_SIM_CONTROL_T_SNAPSHOT, {0, 0, 0}, 0, 0, 0, 0, 0, "two words"}, "snapshot name"},
        {{DISIM_SIM_CONTROL_T_SNAPSHOT, {0, 0, 0}, 0, 0, 0, 0, 0, ""}, "snapshot name"},
        {{DISIM_SIM_CONTROL_T_RESTORE, {0, 0, 0}, 0, 0, 0, 0, 0, "nope"}, "no snapshot 'nope'"},
        {{13, {0, 0, 0}, 0, 0, 0, 0, 0, NULL}, "command = 13"},
    };
    int n = (int)(sizeof bad / sizeof bad[0]);
    for (int i = 0; i < n; i++) {
        long long step = s->last.utime;
        CHECK(answer(l, lc, s, &bad[i].k, R, bad[i].why, &out, &rc) && rc == SIM_LOOP_STEPPED);
        CHECK(s->last.utime > step && strstr(s->message, bad[i].why) != NULL); /* flying on */
    }
    CHECK(w->builds == builds && s->last.control_refused == refused + n);
}

/* Each instructor's control accepted and its effect; the times taken. */
static void ios_accepted(sim_loop *l, lcm_t *lc, seen *s, iworld *w, double *t_apply)
{
    sim_flight_out out;
    int rc, A = DISIM_SIM_STATUS_T_CONTROL_ACCEPTED;
    ictl k = {DISIM_SIM_CONTROL_T_PAUSE, {0, 0, 0}, 0, 0, 0, 0, 0, NULL};
    CHECK(answer(l, lc, s, &k, A, "frozen", &out, &rc) && rc == SIM_LOOP_PAUSED);
    CHECK(s->last.state == DISIM_SIM_STATUS_T_PAUSED);
    k.cmd = DISIM_SIM_CONTROL_T_RESUME;
    CHECK(answer(l, lc, s, &k, A, "running", &out, &rc) && rc == SIM_LOOP_STEPPED);
    /* repositioned: a new world, the hover there from step 1 */
    ictl r = {DISIM_SIM_CONTROL_T_REPOSITION, {0, 40, -10}, NAN, 0, 0, 0, 0, NULL};
    CHECK(answer(l, lc, s, &r, A, "reposition", &out, &rc) && rc == SIM_LOOP_STEPPED);
    t_apply[0] = s->last.control_apply_s;
    CHECK(out.step == 1 && w->builds == 2);
    CHECK_NEAR(out.pos_S_m[0], 0, 0.05);
    CHECK_NEAR(out.pos_S_m[1], 40, 0.05);
    CHECK_NEAR(out.pos_S_m[2], -10, 0.05);
    /* the WOD, the sea, the turbulence: from the same start, in the new conditions */
    ictl wod = {DISIM_SIM_CONTROL_T_SET_WOD, {0, 0, 0}, 0, 10.0, 30.0 * CORE_DEG_TO_RAD, 0, 0, NULL};
    CHECK(answer(l, lc, s, &wod, A, "19.4 kt from 30 deg", &out, &rc) && rc == SIM_LOOP_STEPPED);
    t_apply[1] = s->last.control_apply_s;
    CHECK(w->sw.info.wod_speed_mps == 10.0 && fabs(w->sw.info.wod_dir_rad - 30.0 * CORE_DEG_TO_RAD) < 1e-12);
    CHECK_NEAR(out.pos_S_m[1], 40, 0.05);
    CHECK(w->builds == 3 && out.step == 1);
    /* the speed alone: in flight, the air re-scaled, nothing built */
    for (int j = 0; j < 10; j++)
        iter(l, lc, &out);
    wod.spd = 12.0;
    CHECK(answer(l, lc, s, &wod, A, "in flight at t = 0.055 s: WOD 23.3 kt from 30 deg", &out, &rc) &&
          rc == SIM_LOOP_STEPPED);
    t_apply[10] = s->last.control_apply_s;
    CHECK(w->builds == 3 && out.step == 12);
    ictl sea = {DISIM_SIM_CONTROL_T_SET_SEA, {0, 0, 0}, 0, 0, 0, 4, 0, NULL};
    CHECK(answer(l, lc, s, &sea, A, "sea state 4", &out, &rc) && rc == SIM_LOOP_STEPPED);
    t_apply[2] = s->last.control_apply_s;
    CHECK(w->sw.info.sea.state == 4 && w->sw.info.wod_speed_mps == 12.0 && w->builds == 4);
    ictl turb = {DISIM_SIM_CONTROL_T_SET_TURBULENCE, {0, 0, 0}, 0, 0, 0, 0, 1, NULL};
    CHECK(answer(l, lc, s, &turb, A, "in flight at t = 0.005 s: turbulence on", &out, &rc) && rc == SIM_LOOP_STEPPED);
    t_apply[3] = s->last.control_apply_s;
    CHECK(w->builds == 4 && w->sw.info.sea.state == 4 && out.step == 2);
    /* on the deck, then back in the hover at the scenario's station */
    ictl deck = {DISIM_SIM_CONTROL_T_RESET_DECK, {0, 0, 0}, 0.3, 0, 0, 0, 0, NULL};
    CHECK(answer(l, lc, s, &deck, A, "on the deck", &out, &rc) && rc == SIM_LOOP_STEPPED);
    t_apply[4] = s->last.control_apply_s;
    CHECK(out.on_deck && out.step == 1);
    double psi = out.euler_E_rad[2] - atan2(out.ship.C_ES[3], out.ship.C_ES[0]); /* from the bow */
    CHECK_NEAR(remainder(psi, 2.0 * CORE_PI), 0.3, 0.02);
    for (int j = 0; j < 100; j++)
        iter(l, lc, &out);
    CHECK(out.on_deck && (s->last.flags & DISIM_SIM_STATUS_T_FLAG_ON_DECK));
    ictl hov = {DISIM_SIM_CONTROL_T_RESET_HOVER, {0, 0, 0}, 0, 0, 0, 0, 0, NULL};
    CHECK(answer(l, lc, s, &hov, A, "in the hover", &out, &rc) && rc == SIM_LOOP_STEPPED);
    t_apply[5] = s->last.control_apply_s;
    CHECK_NEAR(out.pos_S_m[2], w->sc.station_S_m[2], 0.05);
    CHECK(!out.on_deck && w->builds == 6 && w->sw.info.sea.state == 4 && w->sw.info.wod_speed_mps == 12.0);
}

/* Snapshot, fly on, restore, fly the same inputs: the same flight bit for
 * bit, twice. */
static void ios_snapshot(sim_loop *l, lcm_t *lc, seen *s, iworld *w, double *t_apply)
{
    enum { N = 300 };
    static sim_flight_out a[N], b[N], c[N];
    sim_flight_out out;
    int rc, A = DISIM_SIM_STATUS_T_CONTROL_ACCEPTED;
    sim_flight_inputs trim;
    sim_flight_trim_inputs(w->sw.flight, &trim);
    long long seq = 0;
    /* a flight to take a snapshot of, with changes in flight in it */
    ictl wod = {DISIM_SIM_CONTROL_T_SET_WOD, {0, 0, 0}, 0, 6.0, 30.0 * CORE_DEG_TO_RAD, 0, 0, NULL};
    ictl toff = {DISIM_SIM_CONTROL_T_SET_TURBULENCE, {0, 0, 0}, 0, 0, 0, 0, 0, NULL};
    CHECK(weave_fly(l, lc, &trim, &seq, 0, 50, a) == 0);
    weave(lc, &trim, &seq, 50);
    CHECK(answer(l, lc, s, &wod, A, "in flight", &out, &rc) && rc == SIM_LOOP_STEPPED);
    CHECK(weave_fly(l, lc, &trim, &seq, 51, 50, a) == 0);
    weave(lc, &trim, &seq, 101);
    CHECK(answer(l, lc, s, &toff, A, "turbulence off", &out, &rc) && rc == SIM_LOOP_STEPPED);
    CHECK(weave_fly(l, lc, &trim, &seq, 102, 48, a) == 0);
    ictl snp = {DISIM_SIM_CONTROL_T_SNAPSHOT, {0, 0, 0}, 0, 0, 0, 0, 0, "s1"};
    weave(lc, &trim, &seq, 150);
    CHECK(answer(l, lc, s, &snp, A, "snapshot 's1'", &a[0], &rc) && rc == SIM_LOOP_STEPPED);
    t_apply[6] = s->last.control_apply_s;
    long step = a[0].step;
    /* and after it: the WOD up in flight 100 passes on, the same in each flight after a restore */
    ictl wod2 = {DISIM_SIM_CONTROL_T_SET_WOD, {0, 0, 0}, 0, 14.0, 30.0 * CORE_DEG_TO_RAD, 0, 0, NULL};
#define AFTER(o)                                                                                                    \
    do {                                                                                                            \
        CHECK(weave_fly(l, lc, &trim, &seq, 151, 99, (o) + 1) == 0);                                                \
        weave(lc, &trim, &seq, 250);                                                                                \
        CHECK(answer(l, lc, s, &wod2, A, "in flight", &(o)[100], &rc) && rc == SIM_LOOP_STEPPED);                   \
        CHECK(weave_fly(l, lc, &trim, &seq, 251, N - 101, (o) + 101) == 0);                                         \
    } while (0)
    AFTER(a);
    ictl rst = {DISIM_SIM_CONTROL_T_RESTORE, {0, 0, 0}, 0, 0, 0, 0, 0, "s1"};
    weave(lc, &trim, &seq, 150);
    CHECK(answer(l, lc, s, &rst, A, "restored 's1'", &b[0], &rc) && rc == SIM_LOOP_STEPPED);
    t_apply[7] = s->last.control_apply_s;
    CHECK(b[0].step == step);
    AFTER(b);
    CHECK(same_flight(a, b, N));
    weave(lc, &trim, &seq, 150);
    CHECK(answer(l, lc, s, &rst, A, "restored 's1'", &c[0], &rc) && rc == SIM_LOOP_STEPPED);
    AFTER(c);
#undef AFTER
    CHECK(same_flight(a, c, N));
    /* the weave moved it: the comparison is of a flight, not of a hover */
    CHECK(fabs(a[N - 1].pos_S_m[2] - a[0].pos_S_m[2]) > 0.05 || fabs(a[N - 1].euler_E_rad[0] - a[0].euler_E_rad[0]) > 1e-3);
    /* flown on differently, the restore still takes it back */
    CHECK(weave_fly(l, lc, &trim, &seq, 1000, 50, c) == 0);
    weave(lc, &trim, &seq, 150);
    CHECK(answer(l, lc, s, &rst, A, NULL, &out, &rc) && rc == SIM_LOOP_STEPPED);
    CHECK(same_flight(a, &out, 1));
    printf("test_loop: snapshot at step %ld, %d steps flown again bit for bit after each restore (z moved %.3f m)\n",
           step, N, a[N - 1].pos_S_m[2] - a[0].pos_S_m[2]);
    /* a longer flight's restore, clear of the ship: its time per step flown again */
    ictl far = {DISIM_SIM_CONTROL_T_REPOSITION, {0, 80, -20}, NAN, 0, 0, 0, 0, NULL};
    CHECK(answer(l, lc, s, &far, A, "reposition", &out, &rc) && rc == SIM_LOOP_STEPPED);
    static sim_flight_out lng[4000];
    CHECK(weave_fly(l, lc, &trim, &seq, 0, 4000, lng) == 0);
    ictl snl = {DISIM_SIM_CONTROL_T_SNAPSHOT, {0, 0, 0}, 0, 0, 0, 0, 0, "long"};
    CHECK(answer(l, lc, s, &snl, A, "snapshot 'long'", &out, &rc));
    long nl = out.step - 1;
    ictl rsl = {DISIM_SIM_CONTROL_T_RESTORE, {0, 0, 0}, 0, 0, 0, 0, 0, "long"};
    CHECK(answer(l, lc, s, &rsl, A, "restored 'long'", &out, &rc) && out.step == nl + 1);
    t_apply[8] = s->last.control_apply_s;
    t_apply[9] = (double)nl;
}

/* A flight that ends (into the hangar, the stick forward) waits, stopped,
 * for the instructor: a restore flies on. */
static void ios_crash(sim_loop *l, lcm_t *lc, seen *s)
{
    sim_flight_out out;
    int rc, A = DISIM_SIM_STATUS_T_CONTROL_ACCEPTED, R = DISIM_SIM_STATUS_T_CONTROL_REFUSED;
    ictl hov = {DISIM_SIM_CONTROL_T_RESET_HOVER, {0, 0, 0}, 0, 0, 0, 0, 0, NULL};
    CHECK(answer(l, lc, s, &hov, A, "in the hover", &out, &rc) && rc == SIM_LOOP_STEPPED);
    ictl snp = {DISIM_SIM_CONTROL_T_SNAPSHOT, {0, 0, 0}, 0, 0, 0, 0, 0, "before"};
    CHECK(answer(l, lc, s, &snp, A, "snapshot 'before'", &out, &rc) && rc == SIM_LOOP_STEPPED);
    unsigned end = DISIM_SIM_STATUS_T_FLAG_CRASH | DISIM_SIM_STATUS_T_FLAG_TIP_OVER;
    long long seq = 1000000;
    int k, r = SIM_LOOP_STEPPED;
    for (k = 0; k < 6000 && r == SIM_LOOP_STEPPED && !(s->last.flags & end); k++) {
        unsigned char b[512];
        int n = enc(b, "A", seq++, 55, 25, 50, 50, 0);
        lcm_publish(lc, DISIM_CH_PILOT_INPUT, b, (unsigned)n);
        r = iter(l, lc, &out);
    }
    CHECK(r == SIM_LOOP_STEPPED && (s->last.flags & end) && s->last.state == DISIM_SIM_STATUS_T_STOPPED);
    printf("test_loop: the flight ended after %.2f s: %s; stopped, waiting\n", k / 200.0, s->message);
    CHECK(iter(l, lc, &out) == SIM_LOOP_PAUSED && s->last.state == DISIM_SIM_STATUS_T_STOPPED);
    ictl res = {DISIM_SIM_CONTROL_T_RESUME, {0, 0, 0}, 0, 0, 0, 0, 0, NULL};
    CHECK(answer(l, lc, s, &res, R, "has ended", &out, &rc) && rc == SIM_LOOP_PAUSED);
    ictl sn2 = {DISIM_SIM_CONTROL_T_SNAPSHOT, {0, 0, 0}, 0, 0, 0, 0, 0, "after"};
    CHECK(answer(l, lc, s, &sn2, R, "has ended", &out, &rc) && rc == SIM_LOOP_PAUSED);
    ictl rst = {DISIM_SIM_CONTROL_T_RESTORE, {0, 0, 0}, 0, 0, 0, 0, 0, "before"};
    CHECK(answer(l, lc, s, &rst, A, "restored 'before'", &out, &rc) && rc == SIM_LOOP_STEPPED);
    CHECK(s->last.state == DISIM_SIM_STATUS_T_RUNNING && !(s->last.flags & end) && out.step == 2);
}

/* The instructor's controls, their worlds built in the step (worker 0)
 * or on the loop's worker, swapped in at the end of the controls of the
 * pass that asked (worker 1): the same answers, the same flights. */
static void test_ios(int worker)
{
    iworld w;
    memset(&w, 0, sizeof w);
    core_err err = {0};
    sim_loop_world lw;
    CHECK(ios_build(&w, SCEN_A, &lw, &err) == 0);
    if (!w.sw.flight) {
        fprintf(stderr, "build: %s\n", err.msg);
        return;
    }
    sim_loop_opts o;
    sim_loop_opts_default(&o);
    o.realtime = 0;
    o.duration_s = 1000.0;
    o.lcm = 1;
    o.lcm_url = "memq://";
    o.scenario_path = SCEN_A;
    o.rebuild = worker ? NULL : ios_rebuild;
    if (worker) {
        o.builder.prepare = ios_prepare;
        o.builder.install = ios_install;
        o.builder.drop = ios_drop;
        o.swap = SIM_LOOP_SWAP_PASS;
    }
    /* the station's controls at once: a restore blends a station's
     * controls in afresh (the stick is where the pilot left it), which
     * the flight before the snapshot did not; without the blend the same
     * inputs fly the same flight */
    o.pilots.blend_s = 0.0;
    o.wait_after_end = 1;
    sim_loop *l = sim_loop_create(&o, &lw, ios_build, &w, NULL, &err);
    CHECK(l != NULL);
    if (!l)
        return;
    lcm_t *lc = sim_loop_lcm(l);
    seen s = {0};
    disim_sim_status_t_subscription_t *ss = disim_sim_status_t_subscribe(lc, DISIM_CH_SIM_STATUS, on_status, &s);
    sim_flight_out out;
    for (int k = 0; k < 20; k++)
        CHECK(iter(l, lc, &out) == SIM_LOOP_STEPPED);
    CHECK(s.last.control_seq == -1 && s.last.control_result == DISIM_SIM_STATUS_T_CONTROL_NONE);
    double t[11] = {0};
    ios_refusals(l, lc, &s, &w);
    ios_accepted(l, lc, &s, &w, t);
    ios_snapshot(l, lc, &s, &w, t);
    ios_crash(l, lc, &s);
    sim_loop_report r;
    sim_loop_report_get(l, &r);
    CHECK(r.snapshots == 3 && r.control_result == DISIM_SIM_STATUS_T_CONTROL_ACCEPTED);
    CHECK(worker ? r.builds_in_step == 0 && r.builds_on_worker == w.builds - 1
                 : r.builds_on_worker == 0 && r.builds_in_step == w.builds - 1);
    printf("test_loop: %s: applied in (s): reposition %.4f, WOD %.4f, sea state 4 %.4f, turbulence %.4f, deck %.4f, "
           "hover %.4f, snapshot %.6f, restore (152 steps) %.4f, restore (%.0f steps) %.3f (%.1f us a step), WOD speed "
           "in flight %.6f\n", worker ? "worker" : "in the step", t[0], t[1], t[2], t[3], t[4], t[5], t[6], t[7], t[9], t[8], 1e6 * t[8] / t[9], t[10]);
    disim_sim_status_t_unsubscribe(lc, ss);
    sim_loop_destroy(l);
    sim_world_free(&w.sw);
    hfm_aircraft_destroy(w.ac);
}

/* The console's lines (sim/ios.c): each command, its fields in SI, and
 * what is not one. */
static void test_ios_parse(void)
{
    sim_ios_cmd c;
    core_err err = {0};
    CHECK(sim_ios_parse("freeze", &c, &err) == 0 && c.command == DISIM_SIM_CONTROL_T_PAUSE);
    CHECK(sim_ios_parse("  resume  # go", &c, &err) == 0 && c.command == DISIM_SIM_CONTROL_T_RESUME);
    CHECK(sim_ios_parse("reset", &c, &err) == 0 && c.command == DISIM_SIM_CONTROL_T_RESET);
    CHECK(sim_ios_parse("reset hover", &c, &err) == 0 && c.command == DISIM_SIM_CONTROL_T_RESET_HOVER);
    CHECK(sim_ios_parse("reset deck 90", &c, &err) == 0 && c.command == DISIM_SIM_CONTROL_T_RESET_DECK &&
          fabs(c.heading_rad - CORE_PI / 2) < 1e-12);
    CHECK(sim_ios_parse("reposition -20 5.5 -8", &c, &err) == 0 && c.command == DISIM_SIM_CONTROL_T_REPOSITION &&
          c.pos_S_m[0] == -20.0 && c.pos_S_m[1] == 5.5 && c.pos_S_m[2] == -8.0 && isnan(c.heading_rad));
    CHECK(sim_ios_parse("wod 20 -30", &c, &err) == 0 && c.command == DISIM_SIM_CONTROL_T_SET_WOD &&
          fabs(c.wod_speed_mps - 20 * CORE_KT_TO_MPS) < 1e-12 && fabs(c.wod_dir_rad + 30 * CORE_DEG_TO_RAD) < 1e-12);
    CHECK(sim_ios_parse("sea 4", &c, &err) == 0 && c.command == DISIM_SIM_CONTROL_T_SET_SEA && c.sea_state == 4);
    CHECK(sim_ios_parse("turb off", &c, &err) == 0 && c.command == DISIM_SIM_CONTROL_T_SET_TURBULENCE &&
          c.turbulence == 0);
    CHECK(sim_ios_parse("snap approach_1", &c, &err) == 0 && c.command == DISIM_SIM_CONTROL_T_SNAPSHOT &&
          !strcmp(c.name, "approach_1"));
    CHECK(sim_ios_parse("restore approach_1", &c, &err) == 0 && c.command == DISIM_SIM_CONTROL_T_RESTORE);
    CHECK(sim_ios_parse("load a.ini", &c, &err) == 0 && c.command == DISIM_SIM_CONTROL_T_LOAD_SCENARIO &&
          !strcmp(c.path, "a.ini"));
    CHECK(sim_ios_parse("status", &c, &err) == 0 && c.command == SIM_IOS_STATUS);
    CHECK(sim_ios_parse("wait 0.5", &c, &err) == 0 && c.command == SIM_IOS_WAIT && c.wait_s == 0.5);
    CHECK(sim_ios_parse("# nothing", &c, &err) == 0 && c.command == SIM_IOS_NONE);
    /* NaN passes: the loop says why it refuses it */
    CHECK(sim_ios_parse("reposition nan 0 -8", &c, &err) == 0 && isnan(c.pos_S_m[0]));
    CHECK(sim_ios_parse("wod 20", &c, &err) < 0 && strstr(err.msg, "wod KT DIR_DEG") != NULL);
    CHECK(sim_ios_parse("reposition 1 2 x", &c, &err) < 0 && strstr(err.msg, "'x' is not a number") != NULL);
    CHECK(sim_ios_parse("turb maybe", &c, &err) < 0 && strstr(err.msg, "turb on") != NULL);
    CHECK(sim_ios_parse("sea 2.5", &c, &err) < 0 && strstr(err.msg, "whole number") != NULL);
    CHECK(sim_ios_parse("freeze now", &c, &err) < 0);
    CHECK(sim_ios_parse("snap aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa", &c, &err) < 0 && strstr(err.msg, "31") != NULL);
    CHECK(sim_ios_parse("fly away", &c, &err) < 0 && strstr(err.msg, "not a command") != NULL);
}

int main(void)
{
    test_rules();
    test_blend();
    test_seq_spoof();
    test_station_flight();
    test_control();
    test_ios(0);
    test_ios(1);
    test_ios_parse();
    printf("test_loop: %d checks, %d failed\n", check_count, check_failures);
    return check_failures != 0;
}
