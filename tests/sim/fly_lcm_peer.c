/* fly_lcm_peer.c -- the other processes of fly_lcm.sh, on the library's
 * default LCM URL (run only inside a private network namespace):
 *   pilot ID SECONDS DCOLL   a station: learns the trim controls from the
 *                            first heli_state_t, publishes them at 50 Hz,
 *                            the collective DCOLL % up after 1 s
 *   control CMD [PATH]       one sim_control_t (pause|resume|reset|load)
 *   listen SECONDS           counts every DISIM_ message received, each
 *                            checked and decoded with the project's types,
 *                            until 1.5 s of silence or SECONDS
 *   logcount LOG             the same counts from an LCM log
 *   held LOG HOLD_S          the run clock from the last pilot input to the
 *                            first status with the input-held flag after
 *                            it: 0 when within HOLD_S + 2 steps of 200 Hz,
 *                            and the controls held constant after it
 *   climb LOG                z in S at 1 s and at the last pilot input
 *   blend LOG                the first pilot input, the first status with
 *                            the blending flag and the first after it
 *                            without: 0 when it lasts 1 s to a step
 * Output lines are "name value" for the script to compare. */
#include "disim_lcm.h"

#include <lcm/eventlog.h>
#include <lcm/lcm.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* ---- decoding any disim message by its channel */
static const struct {
    const char *channel, *type;
} chans[] = {
    {DISIM_CH_HELI_STATE, "heli_state_t"},   {DISIM_CH_SHIP_STATE, "ship_state_t"},
    {DISIM_CH_PILOT_INPUT, "pilot_input_t"}, {DISIM_CH_SIM_CONTROL, "sim_control_t"},
    {DISIM_CH_SIM_STATUS, "sim_status_t"},
};
enum { NCH = sizeof chans / sizeof chans[0] };

typedef struct counts {
    long n[NCH], bad, other;
    double last_s;
} counts;

#define DECODE(T, d, n)                                                                                             \
    do {                                                                                                            \
        disim_##T m;                                                                                                \
        memset(&m, 0, sizeof m);                                                                                    \
        ok = disim_##T##_decode(d, 0, n, &m) == n;                                                                  \
        disim_##T##_decode_cleanup(&m);                                                                             \
    } while (0)

static void count(counts *c, const char *ch, const void *d, int n)
{
    for (int i = 0; i < NCH; i++)
        if (!strcmp(ch, chans[i].channel)) {
            int ok = disim_lcm_check_raw(chans[i].type, d, n, NULL, 0) == 0;
            if (ok) {
                switch (i) {
                case 0: DECODE(heli_state_t, d, n); break;
                case 1: DECODE(ship_state_t, d, n); break;
                case 2: DECODE(pilot_input_t, d, n); break;
                case 3: DECODE(sim_control_t, d, n); break;
                default: DECODE(sim_status_t, d, n); break;
                }
            }
            if (ok)
                c->n[i]++;
            else
                c->bad++;
            return;
        }
    c->other++;
}

static void print_counts(const counts *c)
{
    for (int i = 0; i < NCH; i++)
        printf("%s %ld\n", chans[i].channel, c->n[i]);
    printf("bad %ld\nother %ld\n", c->bad, c->other);
}

static void on_any(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    counts *c = u;
    count(c, ch, rb->data, (int)rb->data_size);
    c->last_s = now_s();
}

/* ---- the station */
typedef struct trim {
    int got;
    double c[4];
} trim;

static void on_heli(const lcm_recv_buf_t *rb, const char *ch, const disim_heli_state_t *m, void *u)
{
    (void)rb, (void)ch;
    trim *t = u;
    if (!t->got) {
        t->c[0] = m->collective_pct, t->c[1] = m->long_cyclic_pct, t->c[2] = m->lat_cyclic_pct, t->c[3] = m->pedal_pct;
        t->got = 1;
    }
}

static int pilot(lcm_t *lc, const char *id, double secs, double dcoll)
{
    trim t = {0};
    disim_heli_state_t_subscription_t *s = disim_heli_state_t_subscribe(lc, DISIM_CH_HELI_STATE, on_heli, &t);
    double t0 = now_s();
    while (!t.got && now_s() - t0 < 10.0)
        lcm_handle_timeout(lc, 100);
    disim_heli_state_t_unsubscribe(lc, s);
    if (!t.got) {
        fprintf(stderr, "fly_lcm_peer pilot: no heli_state_t in 10 s\n");
        return 1;
    }
    t0 = now_s();
    for (long k = 0; now_s() - t0 < secs; k++) {
        disim_pilot_input_t m;
        memset(&m, 0, sizeof m);
        m.utime = k * 20000;
        m.station_id = (char *)id;
        m.seq = k;
        m.collective_pct = t.c[0] + (now_s() - t0 >= 1.0 ? dcoll : 0.0);
        m.long_cyclic_pct = t.c[1];
        m.lat_cyclic_pct = t.c[2];
        m.pedal_pct = t.c[3];
        disim_pilot_input_t_publish(lc, DISIM_CH_PILOT_INPUT, &m);
        struct timespec d = {0, 20000000};
        nanosleep(&d, NULL);
    }
    return 0;
}

/* ---- logs */
static int held(const char *path, double hold_s)
{
    lcm_eventlog_t *el = lcm_eventlog_create(path, "r");
    if (!el)
        return 2;
    long long last_in = -1, held_at = -1;
    double held_coll = NAN, max_dev = 0.0;
    for (lcm_eventlog_event_t *ev; (ev = lcm_eventlog_read_next_event(el)); lcm_eventlog_free_event(ev)) {
        if (!strcmp(ev->channel, DISIM_CH_PILOT_INPUT)) {
            last_in = ev->timestamp;
            held_at = -1;
            held_coll = NAN;
            max_dev = 0.0;
        } else if (!strcmp(ev->channel, DISIM_CH_SIM_STATUS) && last_in >= 0 && held_at < 0) {
            disim_sim_status_t m;
            memset(&m, 0, sizeof m);
            if (disim_lcm_check_raw("sim_status_t", ev->data, ev->datalen, NULL, 0) == 0 &&
                disim_sim_status_t_decode(ev->data, 0, ev->datalen, &m) == ev->datalen &&
                (m.flags & DISIM_SIM_STATUS_T_FLAG_INPUT_HELD))
                held_at = ev->timestamp;
            disim_sim_status_t_decode_cleanup(&m);
        } else if (!strcmp(ev->channel, DISIM_CH_HELI_STATE) && held_at >= 0) {
            disim_heli_state_t m;
            memset(&m, 0, sizeof m);
            if (disim_heli_state_t_decode(ev->data, 0, ev->datalen, &m) == ev->datalen) {
                if (isnan(held_coll))
                    held_coll = m.collective_pct;
                max_dev = fmax(max_dev, fabs(m.collective_pct - held_coll));
            }
            disim_heli_state_t_decode_cleanup(&m);
        }
    }
    lcm_eventlog_destroy(el);
    double d = held_at >= 0 ? 1e-6 * (double)(held_at - last_in) : NAN;
    printf("last_input_s %.3f\nheld_after_s %.3f\nheld_collective_pct %.3f\nheld_max_change_pct %.3g\n", 1e-6 * last_in,
           d, held_coll, max_dev);
    return d >= hold_s && d <= hold_s + 2.0 / 200.0 + 1e-9 && max_dev == 0.0 ? 0 : 1;
}

static int climb(const char *path)
{
    lcm_eventlog_t *el = lcm_eventlog_create(path, "r");
    if (!el)
        return 2;
    long long last_in = -1;
    for (lcm_eventlog_event_t *ev; (ev = lcm_eventlog_read_next_event(el)); lcm_eventlog_free_event(ev))
        if (!strcmp(ev->channel, DISIM_CH_PILOT_INPUT))
            last_in = ev->timestamp;
    lcm_eventlog_destroy(el);
    el = lcm_eventlog_create(path, "r");
    double z1 = NAN, z2 = NAN;
    long long first_in = -1;
    for (lcm_eventlog_event_t *ev; (ev = lcm_eventlog_read_next_event(el)); lcm_eventlog_free_event(ev)) {
        if (!strcmp(ev->channel, DISIM_CH_PILOT_INPUT) && first_in < 0)
            first_in = ev->timestamp;
        if (strcmp(ev->channel, DISIM_CH_HELI_STATE) || first_in < 0)
            continue;
        disim_heli_state_t m;
        memset(&m, 0, sizeof m);
        if (disim_heli_state_t_decode(ev->data, 0, ev->datalen, &m) == ev->datalen) {
            if (isnan(z1) && ev->timestamp >= first_in + 1000000) /* the step is 1 s after the station starts */
                z1 = m.pos_S_m[2];
            if (ev->timestamp <= last_in)
                z2 = m.pos_S_m[2];
        }
        disim_heli_state_t_decode_cleanup(&m);
    }
    lcm_eventlog_destroy(el);
    printf("z_at_step_m %.3f\nz_at_last_input_m %.3f\nclimb_m %.3f\n", z1, z2, z1 - z2);
    return 0;
}

/* The hand-over blend in a log: the first pilot input's time, the first
 * status with FLAG_CONTROLS_BLENDING and the first after it without; 0
 * when it starts within a step of the input and lasts 1 s (to a step). */
static int blend(const char *path, double rate_hz)
{
    lcm_eventlog_t *el = lcm_eventlog_create(path, "r");
    if (!el)
        return 2;
    long long first_in = -1, on = -1, off = -1;
    for (lcm_eventlog_event_t *ev; (ev = lcm_eventlog_read_next_event(el)); lcm_eventlog_free_event(ev)) {
        if (!strcmp(ev->channel, DISIM_CH_PILOT_INPUT) && first_in < 0)
            first_in = ev->timestamp;
        if (strcmp(ev->channel, DISIM_CH_SIM_STATUS) || first_in < 0 || off >= 0)
            continue;
        disim_sim_status_t m;
        memset(&m, 0, sizeof m);
        if (disim_lcm_check_raw("sim_status_t", ev->data, ev->datalen, NULL, 0) == 0 &&
            disim_sim_status_t_decode(ev->data, 0, ev->datalen, &m) == ev->datalen) {
            int f = (m.flags & DISIM_SIM_STATUS_T_FLAG_CONTROLS_BLENDING) != 0;
            if (f && on < 0)
                on = ev->timestamp;
            else if (!f && on >= 0)
                off = ev->timestamp;
        }
        disim_sim_status_t_decode_cleanup(&m);
    }
    lcm_eventlog_destroy(el);
    double t_in = 1e-6 * (double)first_in, t_on = 1e-6 * (double)on, t_off = 1e-6 * (double)off, step = 1.0 / rate_hz;
    printf("first_input_s %.3f\nblend_on_s %.3f\nblend_off_s %.3f\n", t_in, t_on, t_off);
    return first_in >= 0 && on >= 0 && off >= 0 && t_on - t_in <= step + 1e-6 && t_on >= t_in &&
                   fabs(t_off - t_on - 1.0) <= step + 1e-6
               ? 0
               : 1;
}

int main(int argc, char **argv)
{
    if (argc >= 3 && !strcmp(argv[1], "logcount")) {
        lcm_eventlog_t *el = lcm_eventlog_create(argv[2], "r");
        if (!el)
            return 2;
        counts c;
        memset(&c, 0, sizeof c);
        for (lcm_eventlog_event_t *ev; (ev = lcm_eventlog_read_next_event(el)); lcm_eventlog_free_event(ev))
            count(&c, ev->channel, ev->data, ev->datalen);
        lcm_eventlog_destroy(el);
        print_counts(&c);
        return 0;
    }
    if (argc >= 4 && !strcmp(argv[1], "held"))
        return held(argv[2], atof(argv[3]));
    if (argc >= 3 && !strcmp(argv[1], "climb"))
        return climb(argv[2]);
    if (argc >= 3 && !strcmp(argv[1], "blend"))
        return blend(argv[2], 200.0);
    lcm_t *lc = lcm_create(NULL);
    if (!lc) {
        fprintf(stderr, "fly_lcm_peer: lcm_create failed\n");
        return 1;
    }
    int rc = 2;
    if (argc >= 5 && !strcmp(argv[1], "pilot"))
        rc = pilot(lc, argv[2], atof(argv[3]), atof(argv[4]));
    else if (argc >= 3 && !strcmp(argv[1], "control")) {
        static const char *names[] = {"", "pause", "resume", "reset", "load"};
        disim_sim_control_t m;
        memset(&m, 0, sizeof m);
        for (int i = 1; i <= 4; i++)
            if (!strcmp(argv[2], names[i]))
                m.command = (int8_t)i;
        m.scenario_path = argc >= 4 ? argv[3] : "";
        m.name = "";
        rc = disim_sim_control_t_publish(lc, DISIM_CH_SIM_CONTROL, &m) == 0 ? 0 : 1;
    } else if (argc >= 3 && !strcmp(argv[1], "listen")) {
        counts c;
        memset(&c, 0, sizeof c);
        lcm_subscribe(lc, "DISIM_.*", on_any, &c);
        double t0 = now_s();
        while (now_s() - t0 < atof(argv[2]) && !(c.last_s > 0 && now_s() - c.last_s > 1.5))
            lcm_handle_timeout(lc, 100);
        print_counts(&c);
        rc = 0;
    } else
        fprintf(stderr, "usage: fly_lcm_peer pilot ID SECONDS DCOLL | control CMD [PATH] | listen SECONDS | "
                        "logcount LOG | held LOG HOLD_S | climb LOG | blend LOG\n");
    lcm_destroy(lc);
    return rc;
}
