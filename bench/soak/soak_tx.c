/* soak_tx.c -- the hostile side of the flight loop's soak (bench/soak/soak.sh):
 * every kind of bad traffic a host on the LCM network can send to the
 * processes of disim, at stated rates, for --duration seconds of wall time
 * or until SIGINT / SIGTERM, then what it sent per class as JSON (--out, or
 * standard output).
 *
 * Classes (the rate a second; docs/benchmarks.md, "The soak"):
 *   DISIM_PILOT_INPUT (the flight loop's stations' rules)
 *     pilot_random    20  random bytes, 0 to 300 of them
 *     pilot_trunc     10  a valid message of station soak-trunc cut short
 *                         after its id, or with bytes added
 *     pilot_nan       10  station soak-nan, a control NaN or +-inf
 *     pilot_huge      10  station soak-huge, a control of +-1e300, 150 or -5 %,
 *                         or a negative seq
 *     pilot_replay     5  a message of the genuine station (--good) sent
 *                         again, byte for byte, at least 20 of its messages
 *                         after it was first seen (stale)
 *     pilot_ahead      5  the genuine station's id and controls with a seq
 *                         2e6 to 2^63-1 past its last (far ahead)
 *     pilot_takeover   5  a valid message with take_over set from a station
 *                         not on the loop's list (intruder-N)
 *     pilot_flood         station soak-flood at --flood-hz (10000) for
 *                         --flood-s (2) every --flood-every (60) seconds,
 *                         a control of 150 %
 *   DISIM_SIM_CONTROL (the loop's controls)
 *     ctl_random       2  random bytes
 *     ctl_trunc        1  a valid control cut short
 *     ctl_bad          1  values the loop must refuse (a cycle: loads of
 *                         /dev/zero, a missing file, a folder, a FIFO and
 *                         a file of garbage (--bad-dir), an empty path, a
 *                         path of 4000 characters, commands 0, 13 and -1, a
 *                         negative seq, repositions NaN, inside the ship and
 *                         1e9 m away, WOD NaN and 100 m/s, sea state 9,
 *                         turbulence 5, a snapshot name of 40 characters or
 *                         with a slash, a restore of no snapshot)
 *     ctl_good      0.5   valid controls in a cycle: pause (a resume 0.2 s
 *                         later), reset, reset hover, reset deck,
 *                         reposition, WOD speed in flight, WOD direction,
 *                         sea state, turbulence, snapshot, restore, a load
 *                         of --scenario; a resume whenever a status says
 *                         paused for 3 s
 *     ctl_burst           every --burst-every (45) s, 20 resets and loads
 *                         at once
 *   the other processes' channels
 *     heli_garbage     2  random bytes and cut heli_state_t on
 *                         DISIM_HELI_STATE (the stations read it)
 *     status_garbage   2  the same on DISIM_SIM_STATUS (stations, ios)
 *     awreq_garbage    1  random bytes on DISIM_AIRWAKE_REQUEST, and every
 *                         other one a request with a NaN WOD (airwaked)
 * It also times the loop from outside: the wall time between two
 * heli_state_t received (50 Hz) while the loop runs (a gap with a status
 * PAUSED or STOPPED in it left out), p50, p99 and maximum in the JSON.
 * A control's seq carries its class in bits 40 and up (SOAK_SEQ_CLASS), so
 * that the log says which answer belongs to which class (soak_check).
 * Usage: soak_tx [--duration S] [--out FILE.json] [--seed N] [--good ID]
 *        [--scenario PATH] [--bad-dir DIR] [--flood-hz N] [--flood-s S]
 *        [--flood-every S] [--burst-every S] [--lcm URL] */
#include "disim_lcm.h"
#include "soak.h"

#include <lcm/lcm.h>
#include <math.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static volatile sig_atomic_t stop_flag = 0;
static void on_signal(int sig)
{
    (void)sig;
    stop_flag = 1;
}

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static uint64_t rnd(uint64_t *x)
{
    uint64_t z = (*x += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

#define REPLAY_RING 256
#define GAP_BINS 10000
#define BUF 8192

typedef struct tx {
    lcm_t *lc;
    uint64_t rng;
    const char *good, *scenario, *bad_dir;
    long long sent[SOAK_NCLASS], send_failed;
    long long ctl_n[SOAK_NCLASS];
    /* the genuine station's messages, kept for replays */
    unsigned char ring[REPLAY_RING][256];
    int ring_len[REPLAY_RING];
    long long ring_seq[REPLAY_RING];
    int ring_n, ring_next;
    long long good_seen, good_last_seq;
    double good_ctl[4];
    /* the loop's state from its statuses */
    int state;
    double paused_since_s, resume_at_s;
    long long statuses;
    long long flood_seq, huge_seq, nan_seq, trunc_seq;
    /* the loop seen from outside: the wall time between two heli_state_t
     * (50 Hz: 20 ms) while it runs, as a histogram of 1 ms bins; a gap
     * with a status PAUSED or STOPPED in it is left out */
    double heli_last_s, gap_max_s;
    int idle_seen;
    long long gaps[GAP_BINS], ngaps, heli_rx, gaps_over_100ms;
    int good_i, bad_i, snaps;
    unsigned char buf[BUF];
} tx;

static void publish(tx *t, int cls, const char *ch, const void *data, int n)
{
    if (lcm_publish(t->lc, ch, data, (unsigned)n) != 0)
        t->send_failed++;
    t->sent[cls]++;
}

static void random_bytes(tx *t, int cls, const char *ch)
{
    int n = (int)(rnd(&t->rng) % 301);
    for (int i = 0; i < n; i++)
        t->buf[i] = (unsigned char)rnd(&t->rng);
    publish(t, cls, ch, t->buf, n);
}

/* ---- received: the genuine station's messages, the loop's statuses */
static void on_pilot(const lcm_recv_buf_t *rb, const char *ch, void *user)
{
    (void)ch;
    tx *t = user;
    int n = (int)rb->data_size;
    if (n > 256 || disim_lcm_check_raw("pilot_input_t", rb->data, n, NULL, 0) != 0)
        return;
    disim_pilot_input_t m;
    memset(&m, 0, sizeof m);
    if (disim_pilot_input_t_decode(rb->data, 0, n, &m) == n && !strcmp(m.station_id, t->good) &&
        m.seq > t->good_last_seq && m.seq < t->good_last_seq + 1000000LL && disim_lcm_check_pilot_input(&m, NULL, 0) == 0) {
        /* the genuine station's next (not our replays or jumps ahead) */
        t->good_last_seq = m.seq;
        t->good_seen++;
        t->good_ctl[0] = m.collective_pct, t->good_ctl[1] = m.long_cyclic_pct;
        t->good_ctl[2] = m.lat_cyclic_pct, t->good_ctl[3] = m.pedal_pct;
        memcpy(t->ring[t->ring_next], rb->data, (size_t)n);
        t->ring_len[t->ring_next] = n;
        t->ring_seq[t->ring_next] = m.seq;
        t->ring_next = (t->ring_next + 1) % REPLAY_RING;
        if (t->ring_n < REPLAY_RING)
            t->ring_n++;
    }
    disim_pilot_input_t_decode_cleanup(&m);
}

static void on_status(const lcm_recv_buf_t *rb, const char *ch, void *user)
{
    (void)ch;
    tx *t = user;
    int n = (int)rb->data_size;
    if (disim_lcm_check_raw("sim_status_t", rb->data, n, NULL, 0) != 0)
        return;
    disim_sim_status_t m;
    memset(&m, 0, sizeof m);
    if (disim_sim_status_t_decode(rb->data, 0, n, &m) == n) {
        t->statuses++;
        if (m.state == DISIM_SIM_STATUS_T_PAUSED && t->state != DISIM_SIM_STATUS_T_PAUSED)
            t->paused_since_s = now_s();
        t->state = m.state;
        if (m.state != DISIM_SIM_STATUS_T_RUNNING)
            t->idle_seen = 1;
    }
    disim_sim_status_t_decode_cleanup(&m);
}

static void on_heli(const lcm_recv_buf_t *rb, const char *ch, void *user)
{
    (void)ch;
    tx *t = user;
    if (disim_lcm_check_raw("heli_state_t", rb->data, (int)rb->data_size, NULL, 0) != 0)
        return; /* our own garbage */
    double now = now_s();
    t->heli_rx++;
    if (t->heli_last_s > 0.0 && !t->idle_seen && t->state == DISIM_SIM_STATUS_T_RUNNING) {
        double g = now - t->heli_last_s;
        long b = (long)(g * 1e3);
        t->gaps[b < 0 ? 0 : b >= GAP_BINS ? GAP_BINS - 1 : b]++;
        t->ngaps++;
        if (g > 0.1)
            t->gaps_over_100ms++;
        if (g > t->gap_max_s)
            t->gap_max_s = g;
    }
    t->heli_last_s = now;
    t->idle_seen = 0;
}

static double gap_pct(const tx *t, double q)
{
    long long want = (long long)ceil(q * (double)t->ngaps), n = 0;
    for (long b = 0; b < GAP_BINS; b++)
        if ((n += t->gaps[b]) >= want && n > 0)
            return (double)(b + 1);
    return 0.0;
}

/* ---- pilot_input_t */
static void pilot_msg(disim_pilot_input_t *m, const char *id, long long seq)
{
    memset(m, 0, sizeof *m);
    m->utime = (int64_t)(now_s() * 1e6);
    m->station_id = (char *)id;
    m->seq = seq;
    m->collective_pct = m->long_cyclic_pct = m->lat_cyclic_pct = m->pedal_pct = 50.0;
}

static void send_pilot(tx *t, int cls, const disim_pilot_input_t *m, int cut, int extra)
{
    int n = disim_pilot_input_t_encoded_size(m);
    if (n > BUF - 64 || disim_pilot_input_t_encode(t->buf, 0, n, m) != n)
        return;
    if (cut) /* after the id (fingerprint 8, utime 8, length 4, id and NUL), before the end */
        n = 20 + (int)strlen(m->station_id) + 1 + (int)(rnd(&t->rng) % (uint64_t)(n - 21 - (int)strlen(m->station_id)));
    for (int i = 0; i < extra; i++)
        t->buf[n++] = (unsigned char)rnd(&t->rng);
    publish(t, cls, DISIM_CH_PILOT_INPUT, t->buf, n);
}

static double bad_value(tx *t, int huge)
{
    static const double nanv[] = {NAN, INFINITY, -INFINITY};
    static const double hugev[] = {1e300, -1e300, 150.0, -5.0, 100.000001, 1e18};
    return huge ? hugev[rnd(&t->rng) % 6] : nanv[rnd(&t->rng) % 3];
}

static void pilot_bad(tx *t, int cls)
{
    disim_pilot_input_t m;
    switch (cls) {
    case SOAK_PILOT_TRUNC:
        pilot_msg(&m, "soak-trunc", t->trunc_seq++);
        if (rnd(&t->rng) % 4)
            send_pilot(t, cls, &m, 1, 0);
        else
            send_pilot(t, cls, &m, 0, 1 + (int)(rnd(&t->rng) % 40));
        return;
    case SOAK_PILOT_NAN:
    case SOAK_PILOT_HUGE: {
        int huge = cls == SOAK_PILOT_HUGE;
        pilot_msg(&m, huge ? "soak-huge" : "soak-nan", huge ? t->huge_seq++ : t->nan_seq++);
        double *c[4] = {&m.collective_pct, &m.long_cyclic_pct, &m.lat_cyclic_pct, &m.pedal_pct};
        if (huge && rnd(&t->rng) % 8 == 0)
            m.seq = -1 - (long long)(rnd(&t->rng) % 1000); /* a negative seq */
        else
            *c[rnd(&t->rng) % 4] = bad_value(t, huge);
        send_pilot(t, cls, &m, 0, 0);
        return;
    }
    case SOAK_PILOT_TAKEOVER: {
        char id[32];
        snprintf(id, sizeof id, "intruder-%d", (int)(rnd(&t->rng) % 100));
        pilot_msg(&m, id, (long long)(rnd(&t->rng) % 100000));
        m.take_over = 1;
        send_pilot(t, cls, &m, 0, 0);
        return;
    }
    case SOAK_PILOT_FLOOD:
        pilot_msg(&m, "soak-flood", t->flood_seq++);
        m.collective_pct = 150.0;
        send_pilot(t, cls, &m, 0, 0);
        return;
    default: return;
    }
}

/* A genuine message again (stale), or the genuine id far ahead. */
static void pilot_spoof(tx *t, int cls)
{
    if (t->good_seen < 100)
        return; /* the station not yet flying: a replay could be taken as its restart */
    if (cls == SOAK_PILOT_REPLAY) {
        for (int tries = 0; tries < 8; tries++) {
            int i = (int)(rnd(&t->rng) % (uint64_t)t->ring_n);
            if (t->ring_seq[i] <= t->good_last_seq - 20) {
                publish(t, cls, DISIM_CH_PILOT_INPUT, t->ring[i], t->ring_len[i]);
                return;
            }
        }
        return;
    }
    disim_pilot_input_t m;
    long long jump = 2000000LL + (long long)(rnd(&t->rng) % 1000000000LL);
    pilot_msg(&m, t->good, rnd(&t->rng) % 4 == 0 ? INT64_MAX : t->good_last_seq + jump);
    m.collective_pct = t->good_ctl[0], m.long_cyclic_pct = t->good_ctl[1];
    m.lat_cyclic_pct = t->good_ctl[2], m.pedal_pct = t->good_ctl[3];
    send_pilot(t, cls, &m, 0, 0);
}

/* ---- sim_control_t */
static void ctl_msg(tx *t, int cls, disim_sim_control_t *m, int command)
{
    memset(m, 0, sizeof *m);
    m->utime = (int64_t)(now_s() * 1e6);
    m->seq = SOAK_SEQ(cls, t->ctl_n[cls]++);
    m->command = (int8_t)command;
    m->scenario_path = (char *)"";
    m->name = (char *)"";
}

static void send_ctl(tx *t, int cls, const disim_sim_control_t *m, int cut)
{
    int n = disim_sim_control_t_encoded_size(m);
    if (n > BUF || disim_sim_control_t_encode(t->buf, 0, n, m) != n)
        return;
    if (cut)
        n = 1 + (int)(rnd(&t->rng) % (uint64_t)(n - 1));
    publish(t, cls, DISIM_CH_SIM_CONTROL, t->buf, n);
}

#define C(x) DISIM_SIM_CONTROL_T_##x

/* The next valid control of the cycle. */
static void ctl_good(tx *t, int cls)
{
    disim_sim_control_t m;
    char name[32];
    int k = t->good_i++ % 14;
    static const int cmd[] = {C(PAUSE),          C(RESET),    C(RESET_HOVER), C(REPOSITION),  C(SET_WOD),
                              C(SET_WOD),        C(SET_SEA),  C(SET_TURBULENCE), C(SNAPSHOT), C(RESTORE),
                              C(SET_TURBULENCE), C(RESET_DECK), C(LOAD_SCENARIO), C(SET_WOD)};
    ctl_msg(t, cls, &m, cmd[k]);
    switch (k) {
    case 0: t->resume_at_s = now_s() + 0.2; break;
    case 3: m.pos_S_m[0] = -2.0 + (double)(rnd(&t->rng) % 5), m.pos_S_m[1] = -15.0, m.pos_S_m[2] = -8.0; break;
    case 4: m.wod_speed_mps = 7.716, m.wod_dir_rad = 0.0; break; /* 15 kt from ahead: the speed in flight */
    case 5: /* a direction of the database (+-30, 60) or one it builds (+-45) */
        m.wod_speed_mps = 7.716;
        m.wod_dir_rad = (double)((int)(rnd(&t->rng) % 5) - 2) * (rnd(&t->rng) % 2 ? 30.0 : 45.0) * M_PI / 180.0;
        break;
    case 6: m.sea_state = (int8_t)(rnd(&t->rng) % 7); break;
    case 7: m.turbulence = 0; break;
    case 8: snprintf(name, sizeof name, "soak_%d", t->snaps++ % 8), m.name = name; break;
    case 9: snprintf(name, sizeof name, "soak_%d", t->snaps > 0 ? (t->snaps - 1) % 8 : 0), m.name = name; break;
    case 10: m.turbulence = 1; break;
    case 12: m.scenario_path = (char *)t->scenario; break;
    case 13: m.wod_speed_mps = 7.716, m.wod_dir_rad = 0.0; break; /* back to the database's direction */
    default: break;
    }
    send_ctl(t, cls, &m, 0);
}

static void ctl_bad(tx *t, int cls)
{
    disim_sim_control_t m;
    char path[4100];
    int k = t->bad_i++ % 22;
    ctl_msg(t, cls, &m, C(LOAD_SCENARIO));
    switch (k) {
    case 0: m.scenario_path = (char *)"/dev/zero"; break;
    case 1: snprintf(path, sizeof path, "%s/missing.ini", t->bad_dir), m.scenario_path = path; break;
    case 2: m.scenario_path = (char *)t->bad_dir; break;
    case 3: snprintf(path, sizeof path, "%s/fifo", t->bad_dir), m.scenario_path = path; break;
    case 4: snprintf(path, sizeof path, "%s/garbage.ini", t->bad_dir), m.scenario_path = path; break;
    case 5: m.scenario_path = (char *)""; break;
    case 6: memset(path, 'a', 4000), path[4000] = '\0', m.scenario_path = path; break;
    case 7: m.command = 0; break;
    case 8: m.command = 13; break;
    case 9: m.command = -1; break;
    case 10: m.command = C(RESET), m.seq = -1 - (long long)(rnd(&t->rng) % 100); break;
    case 11: m.command = C(REPOSITION), m.pos_S_m[0] = NAN; break;
    case 12: m.command = C(REPOSITION), m.pos_S_m[2] = 3.0; break; /* under the deck, in the ship */
    case 13: m.command = C(REPOSITION), m.pos_S_m[0] = 1e9; break;
    case 14: m.command = C(SET_WOD), m.wod_speed_mps = NAN; break;
    case 15: m.command = C(SET_WOD), m.wod_speed_mps = 100.0; break;
    case 16: m.command = C(SET_SEA), m.sea_state = 9; break;
    case 17: m.command = C(SET_TURBULENCE), m.turbulence = 5; break;
    case 18: memset(path, 'n', 40), path[40] = '\0', m.command = C(SNAPSHOT), m.name = path; break;
    case 19: m.command = C(SNAPSHOT), m.name = (char *)"../evil"; break;
    case 20: m.command = C(RESTORE), m.name = (char *)"never_taken"; break;
    default: m.command = C(SET_WOD), m.wod_speed_mps = 5.0, m.wod_dir_rad = INFINITY; break;
    }
    send_ctl(t, cls, &m, 0);
}

static void ctl_burst(tx *t, int cls)
{
    for (int i = 0; i < 20; i++) {
        disim_sim_control_t m;
        ctl_msg(t, cls, &m, i % 2 ? C(RESET) : C(LOAD_SCENARIO));
        if (i % 2 == 0)
            m.scenario_path = (char *)t->scenario;
        send_ctl(t, cls, &m, 0);
    }
}

/* ---- the other processes' channels */
static void other_garbage(tx *t, int cls)
{
    const char *ch = cls == SOAK_HELI_GARBAGE ? DISIM_CH_HELI_STATE : cls == SOAK_STATUS_GARBAGE ? DISIM_CH_SIM_STATUS
                                                                                                : DISIM_CH_AIRWAKE_REQUEST;
    if (cls == SOAK_AWREQ_GARBAGE && t->sent[cls] % 2) {
        disim_airwake_request_t m;
        memset(&m, 0, sizeof m);
        m.request_id = (char *)"soak-bad";
        m.ship = (char *)"CG-47";
        m.aircraft = (char *)"";
        m.wod_speed_mps = NAN;
        m.grid = (char *)"coarse";
        int n = disim_airwake_request_t_encoded_size(&m);
        if (n <= BUF && disim_airwake_request_t_encode(t->buf, 0, n, &m) == n)
            publish(t, cls, ch, t->buf, n);
        return;
    }
    if (cls != SOAK_AWREQ_GARBAGE && rnd(&t->rng) % 2) { /* a valid status or state cut short */
        int n = 0;
        if (cls == SOAK_HELI_GARBAGE) {
            disim_heli_state_t h;
            memset(&h, 0, sizeof h);
            h.n_gear = 3;
            double g[3] = {0, 0, 0};
            h.gear_load_N = g;
            n = disim_heli_state_t_encoded_size(&h);
            if (n > BUF || disim_heli_state_t_encode(t->buf, 0, n, &h) != n)
                return;
        } else {
            disim_sim_status_t s;
            memset(&s, 0, sizeof s);
            s.scenario = s.message = s.control_message = (char *)"soak";
            n = disim_sim_status_t_encoded_size(&s);
            if (n > BUF || disim_sim_status_t_encode(t->buf, 0, n, &s) != n)
                return;
        }
        publish(t, cls, ch, t->buf, 1 + (int)(rnd(&t->rng) % (uint64_t)(n - 1)));
        return;
    }
    random_bytes(t, cls, ch);
}

static void resume(tx *t)
{
    disim_sim_control_t m;
    ctl_msg(t, SOAK_CTL_GOOD, &m, C(RESUME));
    send_ctl(t, SOAK_CTL_GOOD, &m, 0);
    t->resume_at_s = 0.0;
    t->paused_since_s = now_s(); /* once a second while a status says paused */
}

/* ---- the schedule */
typedef struct sched {
    int cls;
    double period_s, next_s;
} sched;

static void write_json(const tx *t, FILE *f, double wall_s, const double *flood)
{
    fprintf(f, "{\n  \"wall_s\": %.1f,\n  \"flood\": {\"hz\": %.0f, \"burst_s\": %.1f, \"every_s\": %.1f},\n", wall_s,
            flood[0], flood[1], flood[2]);
    fprintf(f, "  \"heli_state_seen\": %lld,\n  \"heli_gap_running_n\": %lld,\n  \"heli_gap_p50_ms\": %.0f,\n"
               "  \"heli_gap_p99_ms\": %.0f,\n  \"heli_gap_max_ms\": %.1f,\n  \"heli_gaps_over_100ms\": %lld,\n",
            t->heli_rx, t->ngaps, gap_pct(t, 0.5), gap_pct(t, 0.99), 1e3 * t->gap_max_s, t->gaps_over_100ms);
    fprintf(f, "  \"genuine_seen\": %lld,\n  \"statuses_seen\": %lld,\n  \"publish_failed\": %lld,\n  \"sent\": {",
            t->good_seen, t->statuses, t->send_failed);
    for (int c = 0; c < SOAK_NCLASS; c++)
        fprintf(f, "%s\n    \"%s\": %lld", c ? "," : "", soak_class_name[c], t->sent[c]);
    fprintf(f, "\n  }\n}\n");
}

static int arg_num(const char *flag, const char *v, double lo, double hi, double *out)
{
    char *e;
    double x = v ? strtod(v, &e) : NAN;
    if (!v || *e || !(x >= lo && x <= hi)) {
        fprintf(stderr, "soak_tx: %s: expected a number in [%g, %g]\n", flag, lo, hi);
        return -1;
    }
    *out = x;
    return 0;
}

int main(int argc, char **argv)
{
    double duration = 3600.0, seed = 1.0, flood[3] = {10000.0, 2.0, 60.0}, burst_every = 45.0;
    const char *out = NULL, *url = NULL;
    static tx t;
    t.good = "soak-good";
    t.scenario = "scenarios/cg47_uh60a_flown.ini";
    t.bad_dir = "/nonexistent";
    for (int i = 1; i < argc; i += 2) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        int rc = 0;
        if (!strcmp(a, "--duration")) rc = arg_num(a, v, 0.0, 1e6, &duration);
        else if (!strcmp(a, "--seed")) rc = arg_num(a, v, 0.0, 1e15, &seed);
        else if (!strcmp(a, "--flood-hz")) rc = arg_num(a, v, 0.0, 100000.0, &flood[0]);
        else if (!strcmp(a, "--flood-s")) rc = arg_num(a, v, 0.0, 3600.0, &flood[1]);
        else if (!strcmp(a, "--flood-every")) rc = arg_num(a, v, 1.0, 86400.0, &flood[2]);
        else if (!strcmp(a, "--burst-every")) rc = arg_num(a, v, 1.0, 86400.0, &burst_every);
        else if (!strcmp(a, "--out") && v) out = v;
        else if (!strcmp(a, "--good") && v) t.good = v;
        else if (!strcmp(a, "--scenario") && v) t.scenario = v;
        else if (!strcmp(a, "--bad-dir") && v) t.bad_dir = v;
        else if (!strcmp(a, "--lcm") && v) url = v;
        else {
            fprintf(stderr, "usage: soak_tx [--duration S] [--out FILE.json] [--seed N] [--good ID] [--scenario PATH]\n"
                            "               [--bad-dir DIR] [--flood-hz N] [--flood-s S] [--flood-every S]\n"
                            "               [--burst-every S] [--lcm URL]\n");
            return 2;
        }
        if (rc)
            return 2;
    }
    t.rng = (uint64_t)seed;
    t.good_last_seq = -1;
    t.state = -1;
    if (!(t.lc = lcm_create(url))) {
        fprintf(stderr, "soak_tx: cannot open LCM\n");
        return 1;
    }
    lcm_subscribe(t.lc, DISIM_CH_PILOT_INPUT, on_pilot, &t);
    lcm_subscribe(t.lc, DISIM_CH_SIM_STATUS, on_status, &t);
    lcm_subscribe(t.lc, DISIM_CH_HELI_STATE, on_heli, &t);
    signal(SIGINT, on_signal);
    signal(SIGTERM, on_signal);
    double t0 = now_s();
    sched s[] = {{SOAK_PILOT_RANDOM, 1 / 20.0, 0},  {SOAK_PILOT_TRUNC, 1 / 10.0, 0}, {SOAK_PILOT_NAN, 1 / 10.0, 0},
                 {SOAK_PILOT_HUGE, 1 / 10.0, 0},    {SOAK_PILOT_REPLAY, 1 / 5.0, 0}, {SOAK_PILOT_AHEAD, 1 / 5.0, 0},
                 {SOAK_PILOT_TAKEOVER, 1 / 5.0, 0}, {SOAK_CTL_RANDOM, 1 / 2.0, 0},   {SOAK_CTL_TRUNC, 1.0, 0},
                 {SOAK_CTL_BAD, 1.0, 0},            {SOAK_CTL_GOOD, 2.0, 0},         {SOAK_CTL_BURST, burst_every, 0},
                 {SOAK_HELI_GARBAGE, 1 / 2.0, 0},   {SOAK_STATUS_GARBAGE, 1 / 2.0, 0},
                 {SOAK_AWREQ_GARBAGE, 1.0, 0}};
    const int ns = (int)(sizeof s / sizeof s[0]);
    for (int i = 0; i < ns; i++) /* staggered starts, the burst after a first quiet period */
        s[i].next_s = t0 + 1.0 + (s[i].cls == SOAK_CTL_BURST ? burst_every : 0.01 * i);
    double flood_next = t0 + flood[2], flood_end = 0.0, flood_sent_to = 0.0;
    struct timespec tick;
    clock_gettime(CLOCK_MONOTONIC, &tick);
    while (!stop_flag && now_s() - t0 < duration) {
        for (int k = 0; k < 4000 && lcm_handle_timeout(t.lc, 0) > 0; k++) {
        }
        double now = now_s();
        for (int i = 0; i < ns; i++) {
            while (s[i].next_s <= now) {
                int c = s[i].cls;
                if (c <= SOAK_PILOT_TAKEOVER && c != SOAK_PILOT_RANDOM && c != SOAK_PILOT_REPLAY && c != SOAK_PILOT_AHEAD)
                    pilot_bad(&t, c);
                else if (c == SOAK_PILOT_RANDOM)
                    random_bytes(&t, c, DISIM_CH_PILOT_INPUT);
                else if (c == SOAK_PILOT_REPLAY || c == SOAK_PILOT_AHEAD)
                    pilot_spoof(&t, c);
                else if (c == SOAK_CTL_RANDOM)
                    random_bytes(&t, c, DISIM_CH_SIM_CONTROL);
                else if (c == SOAK_CTL_TRUNC) {
                    disim_sim_control_t m;
                    ctl_msg(&t, c, &m, C(RESET));
                    send_ctl(&t, c, &m, 1);
                } else if (c == SOAK_CTL_BAD)
                    ctl_bad(&t, c);
                else if (c == SOAK_CTL_GOOD)
                    ctl_good(&t, c);
                else if (c == SOAK_CTL_BURST)
                    ctl_burst(&t, c);
                else
                    other_garbage(&t, c);
                s[i].next_s += s[i].period_s;
            }
        }
        /* a pause resumed 0.2 s after, and whenever the loop says paused for 3 s */
        if ((t.resume_at_s > 0.0 && now >= t.resume_at_s) ||
            (t.state == DISIM_SIM_STATUS_T_PAUSED && now - t.paused_since_s > 3.0))
            resume(&t);
        /* the flood: its messages due by now, at flood_hz, in bursts */
        if (flood[0] > 0.0 && flood[1] > 0.0 && now >= flood_next) {
            flood_end = flood_next + flood[1];
            flood_sent_to = flood_next;
            flood_next += flood[2];
        }
        if (now < flood_end || flood_sent_to < flood_end) {
            double to = now < flood_end ? now : flood_end;
            long due = (long)((to - flood_sent_to) * flood[0]);
            for (long i = 0; i < due; i++)
                pilot_bad(&t, SOAK_PILOT_FLOOD);
            flood_sent_to += (double)due / flood[0];
            if (now >= flood_end)
                flood_sent_to = flood_end;
        }
        tick.tv_nsec += 1000000; /* 1 ms ticks */
        if (tick.tv_nsec >= 1000000000) {
            tick.tv_sec++;
            tick.tv_nsec -= 1000000000;
        }
        clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &tick, NULL);
        if (now_s() - ((double)tick.tv_sec + 1e-9 * (double)tick.tv_nsec) > 0.1) /* far behind: ticks from now */
            clock_gettime(CLOCK_MONOTONIC, &tick);
    }
    FILE *f = out ? fopen(out, "w") : stdout;
    if (!f) {
        fprintf(stderr, "soak_tx: %s: cannot write\n", out);
        lcm_destroy(t.lc);
        return 1;
    }
    write_json(&t, f, now_s() - t0, flood);
    int bad = out && fclose(f) != 0;
    lcm_destroy(t.lc);
    return bad;
}
