/* station_peer.c -- the other end of `disim station` in station_cli.sh: a
 * stand-in for the flight loop, over the LCM default URL (UDP multicast),
 * run only inside a private network namespace.
 *
 *   station_peer SECONDS READY_FILE OUT.csv
 *
 * writes every pilot_input_t it receives on DISIM_PILOT_INPUT as a row
 * recv_s,utime,station_id,seq,collective,long,lat,pedal,take_over to
 * OUT.csv (each checked with disim_lcm_check_raw and
 * disim_lcm_check_pilot_input first; a refused one is counted), and
 * publishes at 10 Hz a heli_state_t (height over the deck 7.25 m, 1.50 m
 * forward of the spot and 2.00 m to port, roll 3, pitch -1, yaw 90 deg,
 * controls 41 / 52 / 47 / 55 %) and a sim_status_t (sim time 12.5 s,
 * 200 Hz, real-time factor 1, 3 overruns, the stations "other" and the
 * first one heard, flags INPUT_HELD). 0.3, 0.6, 0.9 and 1.2 s after the
 * first pilot input it sends four bad messages on DISIM_HELI_STATE: one
 * byte short, a sim_status_t (another fingerprint), a NaN roll, and
 * n_gear = -1 (which only disim_lcm_check_raw refuses). It creates
 * READY_FILE once subscribed and stops after SECONDS, printing a line
 * "station_peer: received N refused R". */
#include "disim_lcm.h"

#include <lcm/lcm.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

typedef struct peer {
    FILE *out;
    double t0;
    long received, refused;
    double first_s; /* the first pilot input's time (< 0: none yet) */
    char first_id[64];
} peer;

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static void on_input(const lcm_recv_buf_t *rb, const char *ch, void *user)
{
    (void)ch;
    peer *p = user;
    char err[256];
    if (disim_lcm_check_raw("pilot_input_t", rb->data, (int)rb->data_size, err, sizeof err) != 0) {
        fprintf(stderr, "station_peer: refused: %s\n", err);
        p->refused++;
        return;
    }
    disim_pilot_input_t m;
    memset(&m, 0, sizeof m);
    if (disim_pilot_input_t_decode(rb->data, 0, (int)rb->data_size, &m) < 0) {
        p->refused++;
        return;
    }
    if (disim_lcm_check_pilot_input(&m, err, sizeof err) != 0) {
        fprintf(stderr, "station_peer: refused: %s\n", err);
        p->refused++;
    } else {
        double t = now_s() - p->t0;
        if (p->first_s < 0) {
            p->first_s = t;
            snprintf(p->first_id, sizeof p->first_id, "%s", m.station_id);
        }
        fprintf(p->out, "%.6f,%lld,%s,%lld,%.9g,%.9g,%.9g,%.9g,%d\n", t, (long long)m.utime, m.station_id,
                (long long)m.seq, m.collective_pct, m.long_cyclic_pct, m.lat_cyclic_pct, m.pedal_pct,
                m.take_over ? 1 : 0);
        p->received++;
    }
    disim_pilot_input_t_decode_cleanup(&m);
}

static void heli(disim_heli_state_t *h, double *gear)
{
    memset(h, 0, sizeof *h);
    h->pos_S_m[0] = 1.5;
    h->pos_S_m[1] = -2.0;
    h->pos_S_m[2] = -7.25;
    h->quat_EB[0] = 1.0;
    h->roll_rad = 3.0 * M_PI / 180.0;
    h->pitch_rad = -1.0 * M_PI / 180.0;
    h->yaw_rad = 90.0 * M_PI / 180.0;
    h->collective_pct = 41.0;
    h->long_cyclic_pct = 52.0;
    h->lat_cyclic_pct = 47.0;
    h->pedal_pct = 55.0;
    h->n_gear = 3;
    h->gear_load_N = gear;
}

static void send_bad(lcm_t *lc, int which)
{
    double gear[3] = {0, 0, 0};
    disim_heli_state_t h;
    heli(&h, gear);
    unsigned char buf[4096];
    int n;
    if (which == 0) { /* one byte short */
        n = disim_heli_state_t_encode(buf, 0, sizeof buf, &h);
        lcm_publish(lc, DISIM_CH_HELI_STATE, buf, (unsigned)(n - 1));
    } else if (which == 1) { /* another type's fingerprint */
        disim_sim_status_t s;
        memset(&s, 0, sizeof s);
        s.scenario = "x";
        s.message = "";
        s.control_message = "";
        n = disim_sim_status_t_encode(buf, 0, sizeof buf, &s);
        lcm_publish(lc, DISIM_CH_HELI_STATE, buf, (unsigned)n);
    } else if (which == 2) { /* well formed, a NaN roll */
        h.roll_rad = NAN;
        disim_heli_state_t_publish(lc, DISIM_CH_HELI_STATE, &h);
    } else { /* n_gear = -1, no gear: lcm-gen's decoder takes it, the raw check does not */
        h.n_gear = 0;
        n = disim_heli_state_t_encode(buf, 0, sizeof buf, &h);
        buf[n - 1] = 0xff;
        lcm_publish(lc, DISIM_CH_HELI_STATE, buf, (unsigned)n);
    }
}

int main(int argc, char **argv)
{
    if (argc != 4) {
        fprintf(stderr, "usage: station_peer SECONDS READY_FILE OUT.csv\n");
        return 2;
    }
    double secs = atof(argv[1]);
    peer p = {0};
    p.first_s = -1.0;
    p.out = fopen(argv[3], "w");
    if (!p.out) {
        perror(argv[3]);
        return 1;
    }
    lcm_t *lc = lcm_create(NULL);
    if (!lc) {
        fprintf(stderr, "station_peer: lcm_create failed\n");
        return 1;
    }
    lcm_subscription_t *raw = lcm_subscribe(lc, DISIM_CH_PILOT_INPUT, on_input, &p);
    FILE *r = fopen(argv[2], "w");
    if (!r || !raw) {
        fprintf(stderr, "station_peer: cannot subscribe or write %s\n", argv[2]);
        return 1;
    }
    fclose(r);
    p.t0 = now_s();
    double next_pub = 0.0;
    int bad_sent = 0;
    long seq = 0;
    double gear[3] = {1000, 1000, 1000};
    while (now_s() - p.t0 < secs) {
        double t = now_s() - p.t0;
        if (t >= next_pub) {
            disim_heli_state_t h;
            heli(&h, gear);
            h.utime = (int64_t)(t * 1e6);
            h.seq = seq;
            disim_heli_state_t_publish(lc, DISIM_CH_HELI_STATE, &h);
            char *ids[2] = {"other", p.first_id[0] ? p.first_id : "nobody"};
            int64_t zero[2] = {0, 0}, taken[2] = {0, p.received};
            disim_sim_status_t s;
            memset(&s, 0, sizeof s);
            s.utime = h.utime;
            s.seq = seq++;
            s.sim_time_s = 12.5;
            s.rate_hz = 200.0;
            s.real_time_factor = 1.0;
            s.overruns = 3;
            s.state = DISIM_SIM_STATUS_T_RUNNING;
            s.scenario = "peer";
            s.n_stations = 2;
            s.station_ids = ids;
            s.station_last_seq = zero;
            s.station_received = taken;
            s.station_refused = zero;
            s.station_gaps = zero;
            s.active_station = 1;
            s.flags = DISIM_SIM_STATUS_T_FLAG_INPUT_HELD;
            s.message = "";
            s.control_message = "";
            disim_sim_status_t_publish(lc, DISIM_CH_SIM_STATUS, &s);
            next_pub += 0.1;
        }
        if (p.first_s >= 0 && bad_sent < 4 && t >= p.first_s + 0.3 * (bad_sent + 1))
            send_bad(lc, bad_sent++);
        lcm_handle_timeout(lc, 5);
    }
    lcm_unsubscribe(lc, raw);
    lcm_destroy(lc);
    fclose(p.out);
    printf("station_peer: received %ld refused %ld bad sent %d\n", p.received, p.refused, bad_sent);
    return 0;
}
