/* test_loop.c -- the flight loop's LCM side (sim/loop.c, sim/pilots.c) in one process
 * over memq://: the stations' rules (refused messages counted per station
 * and changing nothing, sequence gaps, hold after silence with its flag,
 * priority and take-over), pause, resume, reset and load (a good and a
 * broken scenario), and a log whose inputs, replayed, fly the same
 * trajectory bit for bit. Run from the source root. */
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
    m.utime = seq * 20000;
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
    char scenario[64], message[256];
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
    /* a malformed control: refused and counted */
    unsigned char junk[12] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};
    lcm_publish(lc, DISIM_CH_SIM_CONTROL, junk, sizeof junk);
    CHECK(iter(l, lc, &out) == SIM_LOOP_STEPPED && out.step == 3);
    CHECK(s.last.control_refused == 2 && strstr(s.message, "fingerprint") != NULL);
    printf("test_loop: control: paused at %.3f s, reset to z %.2f m, loaded %s, refused '%s'\n", t_paused,
           out.pos_S_m[2], s.scenario, s.message);
    disim_sim_status_t_unsubscribe(lc, ss);
    disim_heli_state_t_unsubscribe(lc, hs);
    sim_loop_destroy(l);
    sim_flight_destroy(w.fl);
    hfm_aircraft_destroy(w.ac);
}

int main(void)
{
    test_rules();
    test_blend();
    test_station_flight();
    test_control();
    printf("test_loop: %d checks, %d failed\n", check_count, check_failures);
    return check_failures != 0;
}
