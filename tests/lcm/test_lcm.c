/* test_lcm.c -- every disim LCM type round-trips through publish/subscribe
 * over memq:// bit for bit; truncated buffers are refused; the checks of
 * received messages name the bad field. */
#include "check.h"
#include "disim_lcm.h"

#include <lcm/lcm.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* What a handler saw: the received message re-encoded (the encoding covers
 * every field, so equal bytes mean an exact round trip), plus one field. */
typedef struct seen {
    int got;
    char buf[8192];
    int len;
    char channel[64];
} seen;

/* For type T: a handler that re-encodes, and a round-trip check that
 * publishes msg, handles it, and compares the bytes with msg's encoding. */
#define RT_DEFINE(T)                                                                         \
    static void rt_handler_##T(const lcm_recv_buf_t *rb, const char *ch, const disim_##T *m, \
                               void *user)                                                   \
    {                                                                                        \
        (void)rb;                                                                            \
        seen *s = user;                                                                      \
        s->got++;                                                                            \
        snprintf(s->channel, sizeof s->channel, "%s", ch);                                  \
        s->len = disim_##T##_encoded_size(m);                                                \
        if (s->len > (int)sizeof s->buf || disim_##T##_encode(s->buf, 0, s->len, m) < 0)    \
            s->len = -1;                                                                     \
    }                                                                                        \
    static void round_trip_##T(lcm_t *lc, const char *chan, const disim_##T *msg)            \
    {                                                                                        \
        seen s = {0};                                                                        \
        disim_##T##_subscription_t *sub = disim_##T##_subscribe(lc, chan, rt_handler_##T, &s); \
        CHECK(disim_##T##_publish(lc, chan, msg) == 0);                                      \
        CHECK(lcm_handle_timeout(lc, 1000) > 0);                                             \
        CHECK(s.got == 1);                                                                   \
        CHECK(strcmp(s.channel, chan) == 0);                                                 \
        int n = disim_##T##_encoded_size(msg);                                               \
        char *b = malloc(n);                                                                 \
        CHECK(disim_##T##_encode(b, 0, n, msg) == n);                                        \
        CHECK(s.len == n && memcmp(b, s.buf, n) == 0);                                       \
        /* the raw check's layout is lcm-gen's: the whole message, no more */                \
        char rerr[256] = "";                                                                 \
        CHECK(disim_lcm_check_raw(#T, b, n, rerr, sizeof rerr) == 0);                        \
        if (rerr[0])                                                                         \
            fprintf(stderr, "  raw check of %s: %s\n", #T, rerr);                           \
        CHECK(disim_lcm_check_raw(#T, b, n - 1, NULL, 0) == -1);                             \
        /* Truncated: refused. lcm-gen 1.3.1 leaves the fields decoded so far \
         * allocated on failure, so start from zero and clean up either way. */ \
        disim_##T dec;                                                                       \
        memset(&dec, 0, sizeof dec);                                                         \
        CHECK(disim_##T##_decode(b, 0, n - 1, &dec) < 0);                                    \
        disim_##T##_decode_cleanup(&dec);                                                    \
        memset(&dec, 0, sizeof dec);                                                         \
        CHECK(disim_##T##_decode(b, 0, n, &dec) == n);                                       \
        disim_##T##_decode_cleanup(&dec);                                                    \
        free(b);                                                                             \
        disim_##T##_unsubscribe(lc, sub);                                                    \
    }

RT_DEFINE(heli_state_t)
RT_DEFINE(ship_state_t)
RT_DEFINE(pilot_input_t)
RT_DEFINE(sim_control_t)
RT_DEFINE(sim_status_t)
RT_DEFINE(airwake_request_t)
RT_DEFINE(airwake_status_t)
RT_DEFINE(shol_point_t)
RT_DEFINE(run_info_t)

/* Distinct values everywhere, so a swapped or dropped field shows. */
static void fill(double *a, int n, double base)
{
    for (int i = 0; i < n; i++)
        a[i] = base + 0.125 * i;
}

/* A message of an older sim_control_t or sim_status_t (this one without
 * the fields appended since, under the older fingerprint) reads as the
 * newest with those fields at their defaults. */
static void put_fp(unsigned char *b, uint64_t fp)
{
    for (int i = 0; i < 8; i++)
        b[i] = (unsigned char)(fp >> (56 - 8 * i));
}

static void test_older(const disim_sim_control_t *c, const disim_sim_status_t *st)
{
    static unsigned char nb[4096], old[4096], up[4096];
    disim_sim_control_t c0 = *c;
    memset(c0.pos_S_m, 0, sizeof c0.pos_S_m);
    c0.heading_rad = c0.wod_speed_mps = c0.wod_dir_rad = 0.0;
    c0.sea_state = c0.turbulence = 0;
    c0.name = "";
    int n = disim_sim_control_t_encode(nb, 0, sizeof nb, &c0), tail = 55;
    memcpy(old, nb, (size_t)(n - tail));
    put_fp(old, 0x8dd8480154a70f03ull);
    CHECK(disim_lcm_check_raw("sim_control_t", old, n - tail, NULL, 0) < 0);
    CHECK(disim_lcm_upgrade("sim_control_t", old, n - tail, up, sizeof up) == n && memcmp(up, nb, (size_t)n) == 0);
    CHECK(disim_lcm_upgrade("sim_control_t", nb, n, up, sizeof up) == 0);
    CHECK(disim_lcm_upgrade("sim_control_t", old, n - tail, up, 16) == -1);
    disim_sim_status_t s0 = *st;
    s0.control_seq = -1;
    s0.control_command = s0.control_result = 0;
    s0.control_message = "";
    s0.control_apply_s = 0.0;
    n = disim_sim_status_t_encode(nb, 0, sizeof nb, &s0), tail = 23;
    memcpy(old, nb, (size_t)(n - tail));
    put_fp(old, 0x7be0ef478700cc8eull);
    CHECK(disim_lcm_upgrade("sim_status_t", old, n - tail, up, sizeof up) == n && memcmp(up, nb, (size_t)n) == 0);
    CHECK(disim_lcm_check_raw("sim_status_t", up, n, NULL, 0) == 0);
    CHECK(disim_lcm_upgrade("heli_state_t", old, n - tail, up, sizeof up) == 0);
}

int main(void)
{
    lcm_t *lc = lcm_create("memq://");
    CHECK(lc != NULL);
    if (!lc)
        return check_done("test_lcm");

    disim_heli_state_t h = {0};
    h.utime = 1234567;
    h.seq = 42;
    fill(h.pos_E_m, 3, 1.0);
    fill(h.vel_E_mps, 3, 2.0);
    fill(h.pos_S_m, 3, 3.0);
    fill(h.vel_S_mps, 3, 4.0);
    double q[4] = {0.9, 0.1, 0.2, 0.3};
    memcpy(h.quat_EB, q, sizeof q);
    h.roll_rad = 0.05;
    h.pitch_rad = 0.06;
    h.yaw_rad = -1.2;
    fill(h.rates_B_radps, 3, 0.01);
    h.collective_pct = 57.1;
    h.long_cyclic_pct = 48.2;
    h.lat_cyclic_pct = 51.3;
    h.pedal_pct = 44.4;
    h.rotor_thrust_N = 73000.0;
    h.rotor_power_W = 1.2e6;
    h.on_deck = 1;
    double gear[3] = {1000.0, 2000.0, 3000.0};
    h.n_gear = 3;
    h.gear_load_N = gear;
    round_trip_heli_state_t(lc, DISIM_CH_HELI_STATE, &h);

    disim_ship_state_t s = {0};
    s.utime = 99;
    s.seq = 7;
    fill(s.pos_E_m, 3, 10.0);
    fill(s.vel_E_mps, 3, 5.0);
    memcpy(s.quat_ES, q, sizeof q);
    s.roll_rad = 0.02;
    s.pitch_rad = -0.01;
    s.yaw_rad = 0.5;
    fill(s.rates_S_radps, 3, 0.003);
    fill(s.spot_pos_E_m, 3, 11.0);
    fill(s.spot_vel_E_mps, 3, 0.3);
    fill(s.spot_acc_E_mps2, 3, -0.2);
    round_trip_ship_state_t(lc, DISIM_CH_SHIP_STATE, &s);

    disim_pilot_input_t p = {0};
    p.utime = 5;
    p.station_id = "station-1";
    p.seq = 1001;
    p.collective_pct = 60;
    p.long_cyclic_pct = 45;
    p.lat_cyclic_pct = 52;
    p.pedal_pct = 38;
    p.trim_button = 1;
    round_trip_pilot_input_t(lc, DISIM_CH_PILOT_INPUT, &p);

    disim_sim_control_t c = {0};
    c.utime = 6;
    c.seq = 2;
    c.command = DISIM_SIM_CONTROL_T_LOAD_SCENARIO;
    c.scenario_path = "scenarios/cg47_uh60a.ini";
    c.pos_S_m[0] = -3.0, c.pos_S_m[1] = 12.0, c.pos_S_m[2] = -8.0;
    c.heading_rad = 0.25;
    c.wod_speed_mps = 10.0;
    c.wod_dir_rad = -0.5;
    c.sea_state = 4;
    c.turbulence = 1;
    c.name = "approach_1";
    round_trip_sim_control_t(lc, DISIM_CH_SIM_CONTROL, &c);

    disim_sim_status_t st = {0};
    char *ids[2] = {"station-1", "station-2"};
    int64_t last[2] = {1001, 17};
    st.utime = 7;
    st.seq = 3;
    st.sim_time_s = 12.5;
    st.rate_hz = 199.8;
    st.real_time_factor = 1.0;
    st.overruns = 2;
    st.state = DISIM_SIM_STATUS_T_RUNNING;
    st.scenario = "cg47_uh60a";
    st.n_stations = 2;
    st.station_ids = ids;
    st.station_last_seq = last;
    int64_t rec[2] = {900, 16}, refd[2] = {3, 0}, gaps[2] = {2, 1};
    st.station_received = rec;
    st.station_refused = refd;
    st.station_gaps = gaps;
    st.active_station = 0;
    st.flags = DISIM_SIM_STATUS_T_FLAG_INPUT_HELD;
    st.message = "";
    st.control_seq = 77;
    st.control_command = DISIM_SIM_CONTROL_T_SET_SEA;
    st.control_result = DISIM_SIM_STATUS_T_CONTROL_ACCEPTED;
    st.control_message = "set sea: loop_a in the hover (sea state 3)";
    st.control_apply_s = 0.0123;
    round_trip_sim_status_t(lc, DISIM_CH_SIM_STATUS, &st);
    test_older(&c, &st);

    disim_airwake_request_t rq = {0};
    rq.utime = 8;
    rq.seq = 4;
    rq.request_id = "req-1";
    rq.ship = "CG-47";
    rq.aircraft = "UH-60A";
    rq.wod_speed_mps = 15.0;
    rq.wod_dir_rad = -0.5235987755982988;
    rq.rotor = DISIM_AIRWAKE_REQUEST_T_ROTOR_UNIFORM;
    rq.rotor_thrust_N = 72950.0;
    fill(rq.station_S_m, 3, -1.0);
    rq.rotor_radius_m = 8.18;
    rq.shaft_pitch_rad = 0.05;
    rq.shaft_roll_rad = -0.01;
    rq.grid = "default";
    round_trip_airwake_request_t(lc, DISIM_CH_AIRWAKE_REQUEST, &rq);
    {
        /* Hostile strings, refused before decoding with the field named:
         * the ship's NUL overwritten, a zero and a huge length. Offsets:
         * fingerprint 8, utime 8, seq 8, request_id 4 + 6, ship 4 + 6. */
        int n = disim_airwake_request_t_encoded_size(&rq);
        unsigned char *b = malloc(n), *c = malloc(n);
        disim_airwake_request_t_encode(b, 0, n, &rq);
        const int ship = 8 + 8 + 8 + 4 + 6;
        CHECK(b[ship + 3] == 6 && memcmp(b + ship + 4, "CG-47", 6) == 0);
        char err[256] = "";
        memcpy(c, b, n);
        c[ship + 4 + 5] = 'x';
        CHECK(disim_lcm_check_raw("airwake_request_t", c, n, err, sizeof err) == -1);
        CHECK(strstr(err, "airwake_request_t.ship") && strstr(err, "without its NUL"));
        /* a NUL inside a string (the fuzzer's find: the string decoded
         * shorter than received, the rest dropped) */
        memcpy(c, b, n);
        c[ship + 4 + 2] = 0;
        CHECK(disim_lcm_check_raw("airwake_request_t", c, n, err, sizeof err) == -1);
        CHECK(strstr(err, "airwake_request_t.ship: a NUL inside the string (byte 3 of 6)") != NULL);
        memcpy(c, b, n);
        c[ship + 3] = 0;
        CHECK(disim_lcm_check_raw("airwake_request_t", c, n, err, sizeof err) == -1);
        CHECK(strstr(err, "airwake_request_t.ship: string length 0") != NULL);
        memcpy(c, b, n);
        c[ship] = 0x7f;
        CHECK(disim_lcm_check_raw("airwake_request_t", c, n, err, sizeof err) == -1);
        CHECK(strstr(err, "airwake_request_t.ship") != NULL);
        /* a trailing byte, and a type that is not disim's */
        unsigned char *d = malloc(n + 1);
        memcpy(d, b, n);
        d[n] = 0;
        CHECK(disim_lcm_check_raw("airwake_request_t", d, n + 1, err, sizeof err) == -1);
        CHECK(disim_lcm_check_raw("no_such_t", b, n, err, sizeof err) == -2);
        /* another type's fingerprint is named as such, before the layout
         * (it was blamed on a field) */
        memcpy(c, b, n);
        c[0] ^= 0x40;
        CHECK(disim_lcm_check_raw("airwake_request_t", c, n, err, sizeof err) == -1);
        CHECK(strstr(err, "airwake_request_t: fingerprint") != NULL);
        CHECK(disim_lcm_check_raw("airwake_status_t", b, n, err, sizeof err) == -1);
        CHECK(strstr(err, "airwake_status_t: fingerprint") != NULL);
        free(b);
        free(c);
        free(d);
    }

    disim_airwake_status_t as = {0};
    as.utime = 9;
    as.seq = 5;
    as.request_id = "req-1";
    as.ship = "CG-47";
    as.aircraft = "UH-60A";
    as.wod_speed_mps = 15.0;
    as.wod_dir_rad = 0.5;
    as.state = DISIM_AIRWAKE_STATUS_T_RUNNING;
    as.progress = 0.37;
    as.residual = 3.2e-3;
    as.iterations = 412;
    as.path = "";
    as.message = "";
    round_trip_airwake_status_t(lc, DISIM_CH_AIRWAKE_STATUS, &as);

    disim_shol_point_t sp = {0};
    sp.utime = 10;
    sp.seq = 6;
    sp.ship = "LPD-17";
    sp.aircraft = "SA365N";
    sp.wod_speed_mps = 12.5;
    sp.wod_dir_rad = 0.5;
    sp.converged = 1;
    sp.passed = 0;
    sp.limit = "roll";
    sp.roll_rad = 0.09;
    sp.pitch_rad = 0.04;
    sp.collective_pct = 55;
    sp.long_cyclic_pct = 50;
    sp.lat_cyclic_pct = 60;
    sp.pedal_pct = 70;
    sp.margin_roll_rad = -0.003;
    sp.margin_pitch_rad = 0.1;
    sp.margin_long_pct = 35;
    sp.margin_lat_pct = 25;
    sp.margin_coll_pct = 30;
    sp.margin_pedal_pct = 10;
    round_trip_shol_point_t(lc, DISIM_CH_SHOL_POINT, &sp);

    disim_run_info_t ri = {0};
    ri.utime = 0;
    ri.seq = 2;
    ri.scenario_path = "scenarios/cg47_uh60a.ini";
    ri.scenario = "CG-47 + UH-60A";
    ri.aircraft_path = "scenarios/aircraft/uh60a.ini";
    ri.ship_path = "scenarios/ships/cg47.ini";
    ri.seed = 7;
    ri.sea_state = 4;
    ri.ship_speed_mps = 7.5;
    ri.wave_dir_rad = 0.25;
    ri.course_rad = 1.5;
    ri.spectrum = 1;
    ri.n_waves = 256;
    ri.wod_speed_mps = 12.0;
    ri.wod_dir_rad = -0.5;
    ri.rate_hz = 200.0;
    ri.state_rate_hz = 50.0;
    round_trip_run_info_t(lc, DISIM_CH_RUN_INFO, &ri);

    /* Checks of received messages. */
    char err[160];
    /* the loop's states: a good one taken, each kind of damage named */
    double qn = sqrt(0.95);
    for (int i = 0; i < 4; i++)
        h.quat_EB[i] = q[i] / qn, s.quat_ES[i] = q[i] / qn;
    CHECK(disim_lcm_check_heli_state(&h, err, sizeof err) == 0);
    CHECK(disim_lcm_check_ship_state(&s, err, sizeof err) == 0);
    h.quat_EB[0] = 0.9; /* |q|^2 0.95 */
    CHECK(disim_lcm_check_heli_state(&h, err, sizeof err) < 0 && strstr(err, "heli_state_t.quat_EB (expected"));
    h.quat_EB[0] = q[0] / qn;
    h.pitch_rad = NAN;
    CHECK(disim_lcm_check_heli_state(&h, err, sizeof err) < 0 && strstr(err, "heli_state_t.roll_rad / pitch_rad"));
    h.pitch_rad = 0.06;
    gear[1] = INFINITY;
    CHECK(disim_lcm_check_heli_state(&h, err, sizeof err) < 0 && strstr(err, "heli_state_t.gear_load_N"));
    gear[1] = 2000.0;
    h.pedal_pct = 100.5;
    CHECK(disim_lcm_check_heli_state(&h, err, sizeof err) < 0 && strstr(err, "the controls (expected finite"));
    h.pedal_pct = 44.4;
    h.pos_E_m[2] = 2e7;
    CHECK(disim_lcm_check_heli_state(&h, err, sizeof err) < 0 && strstr(err, "pos_S_m / pos_E_m"));
    h.pos_E_m[2] = 1.0;
    CHECK(disim_lcm_check_heli_state(&h, NULL, 0) == 0);
    s.yaw_rad = 7.0; /* a heading not wrapped: taken */
    CHECK(disim_lcm_check_ship_state(&s, err, sizeof err) == 0);
    s.spot_acc_E_mps2[1] = NAN;
    CHECK(disim_lcm_check_ship_state(&s, err, sizeof err) < 0 && strstr(err, "ship_state_t.spot_pos_E_m"));
    s.spot_acc_E_mps2[1] = -0.2;
    s.quat_ES[3] = 0.0;
    CHECK(disim_lcm_check_ship_state(&s, err, sizeof err) < 0 && strstr(err, "ship_state_t.quat_ES"));
    CHECK(disim_lcm_check_pilot_input(&p, err, sizeof err) == 0);
    p.pedal_pct = 120.0;
    CHECK(disim_lcm_check_pilot_input(&p, err, sizeof err) < 0);
    CHECK(strstr(err, "pilot_input_t.pedal_pct = 120") != NULL);
    p.pedal_pct = 50.0;
    p.collective_pct = NAN;
    CHECK(disim_lcm_check_pilot_input(&p, err, sizeof err) < 0);
    CHECK(strstr(err, "collective_pct") != NULL);
    p.collective_pct = 50.0;
    p.station_id = "";
    CHECK(disim_lcm_check_pilot_input(&p, err, sizeof err) < 0);
    CHECK(strstr(err, "station_id") != NULL);
    /* The error says the seq received, not a placeholder. */
    p.station_id = "station-1";
    p.seq = -5;
    CHECK(disim_lcm_check_pilot_input(&p, err, sizeof err) < 0);
    CHECK(strstr(err, "pilot_input_t.seq = -5") != NULL);
    p.seq = 1001;
    CHECK(disim_lcm_check_sim_control(&c, err, sizeof err) == 0);
    c.seq = -3;
    CHECK(disim_lcm_check_sim_control(&c, err, sizeof err) < 0);
    CHECK(strstr(err, "sim_control_t.seq = -3") != NULL);
    c.seq = 0;
    c.command = 13;
    CHECK(disim_lcm_check_sim_control(&c, err, sizeof err) < 0);
    CHECK(strstr(err, "sim_control_t.command = 13") != NULL);
    c.command = DISIM_SIM_CONTROL_T_LOAD_SCENARIO;
    c.scenario_path = "";
    CHECK(disim_lcm_check_sim_control(&c, err, sizeof err) < 0);
    CHECK(disim_lcm_check_airwake_request(&rq, err, sizeof err) == 0);
    rq.wod_speed_mps = -1;
    CHECK(disim_lcm_check_airwake_request(&rq, err, sizeof err) < 0);
    CHECK(strstr(err, "wod_speed_mps") != NULL);
    rq.wod_speed_mps = 10;
    rq.rotor_thrust_N = 0;
    CHECK(disim_lcm_check_airwake_request(&rq, err, sizeof err) < 0);
    CHECK(strstr(err, "rotor_thrust_N") != NULL);
    rq.rotor_thrust_N = 7e4;
    rq.rotor_radius_m = 0;
    CHECK(disim_lcm_check_airwake_request(&rq, err, sizeof err) < 0);
    CHECK(strstr(err, "rotor_radius_m") != NULL);
    rq.rotor_radius_m = 8.18;
    rq.grid = "medium";
    CHECK(disim_lcm_check_airwake_request(&rq, err, sizeof err) < 0);
    CHECK(strstr(err, "grid") != NULL);
    rq.grid = "default";
    /* A bad roll tilt is named as the roll, not the pitch. */
    rq.shaft_roll_rad = NAN;
    CHECK(disim_lcm_check_airwake_request(&rq, err, sizeof err) < 0);
    CHECK(strstr(err, "shaft_roll_rad") != NULL);
    rq.shaft_roll_rad = -0.01;
    /* The hub station is checked like every other field. */
    rq.station_S_m[1] = INFINITY;
    CHECK(disim_lcm_check_airwake_request(&rq, err, sizeof err) < 0);
    CHECK(strstr(err, "station_S_m") != NULL);
    rq.station_S_m[1] = 0.0;
    CHECK(disim_lcm_check_airwake_request(&rq, err, sizeof err) == 0);

    lcm_destroy(lc);
    return check_done("test_lcm");
}
