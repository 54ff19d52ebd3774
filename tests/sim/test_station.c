/* test_station.c -- the pilot station's parts (sim/station.c) without a
 * network: the script's interpolation and its errors, the keys (escape
 * sequences split across reads included), the evdev axis mapping and the
 * reading of struct input_event records (through a pipe, as a device gives
 * them), and a station on memq:// whose received messages (good, broken,
 * of the wrong type, with a NaN) are checked before they are shown. */
#include "check.h"
#include "disim_lcm.h"
#include "sim.h"

#include <linux/input.h>
#include <lcm/lcm.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static void write_file(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    if (!f) {
        perror(path);
        exit(1);
    }
    fputs(text, f);
    fclose(f);
}

static void test_script(const char *dir)
{
    char path[600];
    snprintf(path, sizeof path, "%s/ok.csv", dir);
    write_file(path, "# a header and a comment\n"
                     "time_s,collective,long,lat,pedal\n"
                     "0.5, 40, 50, 50, 50\n"
                     "\n"
                     "1.5, 60, 30, 70, 10   # a ramp\n"
                     "1.5, 20, 30, 70, 10\n"
                     "2.0, 20, 30, 70, 10\n");
    core_err err;
    sim_station_script *s = sim_station_script_load(path, &err);
    CHECK(s != NULL);
    if (!s) {
        fprintf(stderr, "%s\n", err.msg);
        return;
    }
    sim_station_controls c;
    sim_station_script_at(s, 0.0, &c); /* before the first row: the first row */
    CHECK_NEAR(c.ctl.collective_pct, 40.0, 1e-12);
    sim_station_script_at(s, 1.0, &c); /* half way along the ramp */
    CHECK_NEAR(c.ctl.collective_pct, 50.0, 1e-12);
    CHECK_NEAR(c.ctl.long_cyclic_pct, 40.0, 1e-12);
    CHECK_NEAR(c.ctl.lat_cyclic_pct, 60.0, 1e-12);
    CHECK_NEAR(c.ctl.pedal_pct, 30.0, 1e-12);
    sim_station_script_at(s, 1.25, &c);
    CHECK_NEAR(c.ctl.collective_pct, 55.0, 1e-12);
    sim_station_script_at(s, 1.4999, &c); /* just before the step */
    CHECK_NEAR(c.ctl.collective_pct, 60.0, 1e-2);
    sim_station_script_at(s, 1.5, &c); /* at the step: the later row */
    CHECK_NEAR(c.ctl.collective_pct, 20.0, 1e-12);
    sim_station_script_at(s, 100.0, &c); /* after the last row: held */
    CHECK_NEAR(c.ctl.collective_pct, 20.0, 1e-12);
    CHECK_NEAR(c.ctl.pedal_pct, 10.0, 1e-12);
    sim_station_script_destroy(s);

    static const struct {
        const char *text, *want;
    } bad[] = {
        {"0,50,50,50\n", "ok.csv:1: '0,50,50,50': expected 5 numbers"},
        {"0,50,50,50,50\n1,50,50,50,50,7\n", ":2: "},
        {"0,50,50,50,50\n1,50,101,50,50\n", ":2: long = 101: expected a percentage 0 to 100"},
        {"1,50,50,50,50\n0.5,50,50,50,50\n", ":2: time 0.5 s is before the previous row's 1 s"},
        {"-1,50,50,50,50\n", ":1: time = -1: expected a time >= 0 s"},
        {"0,50,nan,50,50\n", ":1: long = nan"},
        {"# only a comment\n", "no rows"},
        {"time,collective,long,lat,pedal\nhead,er,again,x,y\n", ":2: 'head,er,again,x,y': expected 5 numbers"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        write_file(path, bad[i].text);
        s = sim_station_script_load(path, &err);
        CHECK(s == NULL);
        CHECK(s == NULL && strstr(err.msg, bad[i].want) != NULL);
        if (s || !strstr(err.msg, bad[i].want))
            fprintf(stderr, "  case %zu: got '%s', expected '%s'\n", i, s ? "(loaded)" : err.msg, bad[i].want);
        sim_station_script_destroy(s);
    }
    snprintf(path, sizeof path, "%s/none.csv", dir);
    CHECK(sim_station_script_load(path, &err) == NULL &&
          strstr(err.msg, "none.csv: cannot open: No such file") != NULL);
    /* a NUL byte is refused, not read as the end of its line (the row
     * after it would be silently cut), in memory as in a file */
    static const char nul[] = "0,50,50,50,50\n1,50,50,50,50\0,7\n";
    s = sim_station_script_parse(nul, sizeof nul - 1, "mem.csv", &err);
    CHECK(s == NULL && strstr(err.msg, "mem.csv:2: a NUL byte") != NULL);
    sim_station_script_destroy(s);
    s = sim_station_script_parse(nul, 14, "mem.csv", &err); /* the first row alone */
    CHECK(s != NULL);
    sim_station_script_destroy(s);
}

static int feed(sim_station_keys *k, const char *bytes, double t_s, sim_station_controls *c)
{
    int last = SIM_KEY_NONE;
    for (const char *p = bytes; *p; p++)
        last = sim_station_keys_feed(k, (unsigned char)*p, t_s, c);
    return last;
}

/* The keyboard: from the flown controls, a key held moves its control at
 * the rate (a tap: rate x SIM_STATION_KEY_HOLD_S; autorepeat: steadily),
 * escape sequences whole or split, space back to the reference at the
 * rate, the stops. */
static void test_keys(void)
{
    const double R = 10.0, H = SIM_STATION_KEY_HOLD_S;
    const hfm_controls ref = {55.0, 48.0, 52.0, 33.0};
    sim_station_keys k;
    sim_station_controls c;
    sim_station_controls_centre(&c);
    c.ctl = ref;
    sim_station_keys_init(&k, R, &ref, 0.0);
    /* nothing pressed: nothing moves */
    sim_station_keys_advance(&k, 0.9, &c);
    CHECK(memcmp(&c.ctl, &ref, sizeof ref) == 0);
    /* a tap at 1 s: the collective rises at R for H */
    CHECK(feed(&k, "w", 1.0, &c) == SIM_KEY_MOVED);
    CHECK_NEAR(c.ctl.collective_pct, 55.0, 1e-12);
    sim_station_keys_advance(&k, 1.0 + 0.5 * H, &c);
    CHECK_NEAR(c.ctl.collective_pct, 55.0 + R * 0.5 * H, 1e-9);
    sim_station_keys_advance(&k, 1.5, &c);
    CHECK_NEAR(c.ctl.collective_pct, 55.0 + R * H, 1e-9);
    /* held: autorepeat every 40 ms from 2 s for 1 s moves it steadily */
    double c0 = c.ctl.collective_pct;
    for (int i = 0; i <= 25; i++) {
        feed(&k, "w", 2.0 + 0.04 * i, &c);
        CHECK_NEAR(c.ctl.collective_pct, c0 + R * 0.04 * i, 1e-9);
    }
    sim_station_keys_advance(&k, 3.5, &c);
    CHECK_NEAR(c.ctl.collective_pct, c0 + R * (1.0 + H), 1e-9);
    feed(&k, "s", 4.0, &c);
    sim_station_keys_advance(&k, 4.5, &c);
    CHECK_NEAR(c.ctl.collective_pct, c0 + R * 1.0, 1e-9);
    /* the arrows: up forward, ESC O B (application mode) back, a sequence
     * split across reads */
    feed(&k, "\033[A", 5.0, &c);
    sim_station_keys_advance(&k, 5.5, &c);
    CHECK_NEAR(c.ctl.long_cyclic_pct, 48.0 - R * H, 1e-9);
    feed(&k, "\033OB", 6.0, &c);
    sim_station_keys_advance(&k, 6.5, &c);
    CHECK_NEAR(c.ctl.long_cyclic_pct, 48.0, 1e-9);
    CHECK(feed(&k, "\033", 7.0, &c) == SIM_KEY_NONE);
    CHECK(feed(&k, "[", 7.0, &c) == SIM_KEY_NONE);
    CHECK(feed(&k, "C", 7.0, &c) == SIM_KEY_MOVED);
    sim_station_keys_advance(&k, 7.5, &c);
    CHECK_NEAR(c.ctl.lat_cyclic_pct, 52.0 + R * H, 1e-9);
    /* a and d the pedals; bytes at once hold the key once */
    feed(&k, "ddd", 8.0, &c);
    sim_station_keys_advance(&k, 8.5, &c);
    CHECK_NEAR(c.ctl.pedal_pct, 33.0 + R * H, 1e-9);
    /* a function key (ESC [ 1 5 ~) moves nothing, and the key after it counts */
    sim_station_controls before = c;
    CHECK(feed(&k, "\033[15~", 9.0, &c) == SIM_KEY_NONE);
    sim_station_keys_advance(&k, 9.5, &c);
    CHECK(memcmp(&before, &c, sizeof c) == 0);
    /* space: cyclic and pedals back to the reference at R, the collective stays */
    c.ctl.long_cyclic_pct = 45.0, c.ctl.lat_cyclic_pct = 53.0, c.ctl.pedal_pct = 43.0;
    double coll = c.ctl.collective_pct;
    CHECK(feed(&k, " ", 10.0, &c) == SIM_KEY_MOVED);
    sim_station_keys_advance(&k, 10.5, &c);
    CHECK_NEAR(c.ctl.long_cyclic_pct, 48.0, 1e-12);
    CHECK_NEAR(c.ctl.lat_cyclic_pct, 52.0, 1e-12);
    CHECK_NEAR(c.ctl.pedal_pct, 38.0, 1e-9);
    CHECK(k.centring == 1);
    sim_station_keys_advance(&k, 11.5, &c);
    CHECK_NEAR(c.ctl.pedal_pct, 33.0, 1e-12);
    CHECK(c.ctl.collective_pct == coll && k.centring == 0);
    /* t asks for the controls once; clamped at the stops */
    CHECK(feed(&k, "t", 12.0, &c) == SIM_KEY_MOVED && c.take_over == 1);
    c.ctl.collective_pct = 99.5;
    feed(&k, "w", 13.0, &c);
    sim_station_keys_advance(&k, 14.0, &c);
    CHECK_NEAR(c.ctl.collective_pct, 100.0, 1e-12);
    CHECK(feed(&k, "x", 15.0, &c) == SIM_KEY_NONE);
    CHECK(feed(&k, "q", 15.0, &c) == SIM_KEY_QUIT);
    CHECK(feed(&k, "\003", 15.0, &c) == SIM_KEY_QUIT);
}

/* Force trim: sticks fly about the reference (the take-over's), the trim
 * button sets it where the controls are, the release frees it and sets it
 * where let go, a lever is picked up at the reference; never a step. */
static void test_trim(void)
{
    sim_station_axes a;
    sim_station_axes_default(&a);
    const double ref[SIM_AXES] = {55.0, 48.0, 52.0, 33.0}, A = SIM_STATION_AUTHORITY_PCT;
    sim_station_controls pos, c;
    sim_station_controls_centre(&pos); /* the sticks at rest */
    sim_station_controls_centre(&c);
    sim_station_trim t;
    sim_station_trim_init(&t, A, &a, ref, &pos);
    sim_station_trim_apply(&t, &pos, &c);
    /* hands off: the flown controls */
    CHECK(c.ctl.collective_pct == 55.0 && c.ctl.long_cyclic_pct == 48.0 && c.ctl.lat_cyclic_pct == 52.0 &&
          c.ctl.pedal_pct == 33.0);
    /* deflections about the reference, +-A at full, clamped */
    pos.ctl.long_cyclic_pct = 25.0; /* half forward */
    sim_station_trim_apply(&t, &pos, &c);
    CHECK_NEAR(c.ctl.long_cyclic_pct, 48.0 - 0.5 * A, 1e-12);
    pos.ctl.long_cyclic_pct = 0.0;
    sim_station_trim_apply(&t, &pos, &c);
    CHECK_NEAR(c.ctl.long_cyclic_pct, 0.0, 1e-12);
    pos.ctl.long_cyclic_pct = 50.0;
    /* the trim button with the stick right: the reference where the
     * control is, no step; the stick flies the reference until back at
     * its centre, then about the new reference */
    pos.ctl.lat_cyclic_pct = 75.0;
    sim_station_trim_apply(&t, &pos, &c);
    double lat = c.ctl.lat_cyclic_pct;
    CHECK_NEAR(lat, 52.0 + 0.5 * A, 1e-12);
    pos.trim_button = 1;
    sim_station_trim_apply(&t, &pos, &c);
    CHECK(c.ctl.lat_cyclic_pct == lat && t.ref_pct[SIM_AXIS_LAT] == lat && t.sets == 1 && c.trim_button == 1);
    pos.trim_button = 0;
    pos.ctl.lat_cyclic_pct = 62.0; /* springing back */
    sim_station_trim_apply(&t, &pos, &c);
    CHECK(c.ctl.lat_cyclic_pct == lat);
    pos.ctl.lat_cyclic_pct = 50.0;
    sim_station_trim_apply(&t, &pos, &c);
    CHECK(c.ctl.lat_cyclic_pct == lat);
    pos.ctl.lat_cyclic_pct = 60.0;
    sim_station_trim_apply(&t, &pos, &c);
    CHECK_NEAR(c.ctl.lat_cyclic_pct, lat + 0.2 * A, 1e-12);
    pos.ctl.lat_cyclic_pct = 50.0;
    /* the trim release: held, the stick flies about the old reference;
     * let go with the stick left, the reference there */
    pos.trim_release = 1;
    pos.ctl.pedal_pct = 40.0;
    sim_station_trim_apply(&t, &pos, &c);
    CHECK_NEAR(c.ctl.pedal_pct, 33.0 - 0.2 * A, 1e-12);
    CHECK(t.sets == 1);
    pos.trim_release = 0;
    sim_station_trim_apply(&t, &pos, &c);
    CHECK_NEAR(c.ctl.pedal_pct, 33.0 - 0.2 * A, 1e-12);
    CHECK(t.sets == 2);
    pos.ctl.pedal_pct = 50.0;
    sim_station_trim_apply(&t, &pos, &c);
    CHECK_NEAR(c.ctl.pedal_pct, 33.0 - 0.2 * A, 1e-12);
    /* a stick off centre at take-over flies the reference until centred */
    pos.ctl.long_cyclic_pct = 90.0;
    sim_station_trim_init(&t, A, &a, ref, &pos);
    sim_station_trim_apply(&t, &pos, &c);
    CHECK(c.ctl.long_cyclic_pct == 48.0);
    pos.ctl.long_cyclic_pct = 50.5; /* within SIM_STATION_TRIM_CENTRE */
    sim_station_trim_apply(&t, &pos, &c);
    CHECK_NEAR(c.ctl.long_cyclic_pct, 48.0 + 0.01 * A, 1e-12);
    /* a lever (the collective on a throttle) at 20 %: held at the
     * reference until brought to it, then it follows */
    a.axis[SIM_AXIS_COLLECTIVE].lever = 1;
    sim_station_controls_centre(&pos);
    pos.ctl.collective_pct = 20.0;
    sim_station_trim_init(&t, A, &a, ref, &pos);
    sim_station_trim_apply(&t, &pos, &c);
    CHECK(c.ctl.collective_pct == 55.0);
    pos.ctl.collective_pct = 50.0;
    sim_station_trim_apply(&t, &pos, &c);
    CHECK(c.ctl.collective_pct == 55.0);
    pos.ctl.collective_pct = 56.5; /* across it */
    sim_station_trim_apply(&t, &pos, &c);
    CHECK(c.ctl.collective_pct == 56.5);
    pos.ctl.collective_pct = 70.0;
    sim_station_trim_apply(&t, &pos, &c);
    CHECK(c.ctl.collective_pct == 70.0);
    /* the take-over button passes through */
    pos.take_over = 1;
    sim_station_trim_apply(&t, &pos, &c);
    CHECK(c.take_over == 1);
}

static void test_axes(void)
{
    sim_station_axes a;
    sim_station_axes_default(&a);
    CHECK(a.axis[SIM_AXIS_COLLECTIVE].code == ABS_Y && a.axis[SIM_AXIS_COLLECTIVE].invert == 1);
    CHECK(a.axis[SIM_AXIS_LONG].code == ABS_RY && a.axis[SIM_AXIS_LONG].invert == 0);
    core_err err;
    sim_station_axis ax = {0, 0, 0, 255, 0, 0};
    CHECK(sim_station_axis_parse("ABS_THROTTLE:invert", &ax, &err) == 0 && ax.code == ABS_THROTTLE && ax.invert);
    CHECK(!ax.lever);
    CHECK(sim_station_axis_parse("ABS_THROTTLE:lever", &ax, &err) == 0 && ax.code == ABS_THROTTLE && ax.lever &&
          !ax.invert);
    CHECK(sim_station_axis_parse("ABS_Z:invert:lever", &ax, &err) == 0 && ax.code == ABS_Z && ax.lever && ax.invert);
    CHECK(sim_station_axis_parse("abs_rz", &ax, &err) == 0 && ax.code == ABS_RZ && !ax.invert && !ax.lever);
    CHECK(sim_station_axis_parse("7", &ax, &err) == 0 && ax.code == 7);
    CHECK(sim_station_axis_parse("ABS_NOPE", &ax, &err) == -1 && strstr(err.msg, "ABS_NOPE"));
    CHECK(sim_station_axis_parse("ABS_X:backwards", &ax, &err) == -1 && strstr(err.msg, ":backwards"));
    CHECK(sim_station_axis_parse("99", &ax, &err) == -1);
    char nb[32];
    CHECK(!strcmp(sim_station_axis_name(ABS_RX, nb, sizeof nb), "ABS_RX"));

    /* a 0..255 axis: ends and middle, inverted, clamped */
    sim_station_axis t = {ABS_THROTTLE, 0, 0, 255, 0, 0};
    CHECK_NEAR(sim_station_axis_pct(&t, 0), 0.0, 1e-12);
    CHECK_NEAR(sim_station_axis_pct(&t, 255), 100.0, 1e-12);
    CHECK_NEAR(sim_station_axis_pct(&t, 51), 20.0, 1e-12);
    CHECK_NEAR(sim_station_axis_pct(&t, 400), 100.0, 1e-12);
    t.invert = 1;
    CHECK_NEAR(sim_station_axis_pct(&t, 51), 80.0, 1e-12);
    /* a centred stick with a dead band: 50 % inside it, no step at its edge,
     * the stops still 0 and 100 */
    sim_station_axis s = {ABS_X, 0, -1000, 1000, 100, 0};
    CHECK_NEAR(sim_station_axis_pct(&s, 80), 50.0, 1e-12);
    CHECK_NEAR(sim_station_axis_pct(&s, -100), 50.0, 1e-12);
    CHECK_NEAR(sim_station_axis_pct(&s, 101), 50.0 + 50.0 / 900.0, 1e-9);
    CHECK_NEAR(sim_station_axis_pct(&s, 1000), 100.0, 1e-12);
    CHECK_NEAR(sim_station_axis_pct(&s, -1000), 0.0, 1e-12);
    CHECK_NEAR(sim_station_axis_pct(&s, 550), 75.0, 1e-9);
    sim_station_axis z = {ABS_X, 0, 5, 5, 0, 0}; /* no range: the middle */
    CHECK_NEAR(sim_station_axis_pct(&z, 5), 50.0, 1e-12);
}

static void put_ev(int fd, int type, int code, int value)
{
    struct input_event e;
    memset(&e, 0, sizeof e);
    e.type = (unsigned short)type;
    e.code = (unsigned short)code;
    e.value = value;
    if (write(fd, &e, sizeof e) != (ssize_t)sizeof e)
        perror("write");
}

static void test_evdev_pipe(void)
{
    sim_station_axes a;
    sim_station_axes_default(&a);
    for (int k = 0; k < SIM_AXES; k++) {
        a.axis[k].min = -32768;
        a.axis[k].max = 32767;
    }
    int p[2];
    if (pipe(p) != 0) {
        perror("pipe");
        CHECK(0);
        return;
    }
    core_err err;
    sim_station_evdev *d = sim_station_evdev_wrap(p[0], &a, &err);
    CHECK(d != NULL);
    if (!d)
        return;
    sim_station_controls c;
    sim_station_controls_centre(&c);
    CHECK(sim_station_evdev_read(d, &c, &err) == 0); /* nothing yet */
    put_ev(p[1], EV_ABS, ABS_Y, -32768); /* left stick full up: collective 100 % (inverted) */
    put_ev(p[1], EV_ABS, ABS_RY, -32768); /* right stick forward: long 0 % */
    put_ev(p[1], EV_ABS, ABS_RX, 32767);  /* right: lat 100 % */
    put_ev(p[1], EV_ABS, ABS_X, -32768);  /* left: pedal 0 % */
    put_ev(p[1], EV_ABS, ABS_Z, 1000);    /* not mapped */
    put_ev(p[1], EV_KEY, BTN_TL, 1);
    put_ev(p[1], EV_SYN, SYN_REPORT, 0);
    CHECK(sim_station_evdev_read(d, &c, &err) == 0);
    CHECK_NEAR(c.ctl.collective_pct, 100.0, 1e-12);
    CHECK_NEAR(c.ctl.long_cyclic_pct, 0.0, 1e-12);
    CHECK_NEAR(c.ctl.lat_cyclic_pct, 100.0, 1e-12);
    CHECK_NEAR(c.ctl.pedal_pct, 0.0, 1e-12);
    CHECK(c.trim_button == 1 && c.trim_release == 0);
    /* half an event, then the rest: no event lost or garbled */
    struct input_event e;
    memset(&e, 0, sizeof e);
    e.type = EV_ABS;
    e.code = ABS_RY;
    e.value = 32767;
    CHECK(write(p[1], &e, 7) == 7);
    CHECK(sim_station_evdev_read(d, &c, &err) == 0);
    CHECK_NEAR(c.ctl.long_cyclic_pct, 0.0, 1e-12);
    CHECK(write(p[1], (char *)&e + 7, sizeof e - 7) == (ssize_t)(sizeof e - 7));
    CHECK(sim_station_evdev_read(d, &c, &err) == 0);
    CHECK_NEAR(c.ctl.long_cyclic_pct, 100.0, 1e-12);
    /* after SYN_DROPPED the events up to the next SYN_REPORT are dropped */
    put_ev(p[1], EV_SYN, SYN_DROPPED, 0);
    put_ev(p[1], EV_ABS, ABS_RX, -32768);
    put_ev(p[1], EV_SYN, SYN_REPORT, 0);
    put_ev(p[1], EV_KEY, BTN_TL, 0);
    CHECK(sim_station_evdev_read(d, &c, &err) == 0);
    CHECK_NEAR(c.ctl.lat_cyclic_pct, 100.0, 1e-12);
    CHECK(c.trim_button == 0);
    close(p[1]);
    CHECK(sim_station_evdev_read(d, &c, &err) == -1 && strstr(err.msg, "end of input"));
    sim_station_evdev_destroy(d);

    sim_station_controls c2;
    CHECK(sim_station_evdev_open("/nonexistent/event7", &a, &c2, &err) == NULL &&
          strstr(err.msg, "/nonexistent/event7: No such file"));
    CHECK(sim_station_evdev_open("/dev/null", &a, &c2, &err) == NULL && strstr(err.msg, "not an evdev input device"));
}

/* Received buffers through sim_station_receive (what the LCM handlers
 * call): good ones shown, broken ones, another type's and NaNs counted. */
static int enc_heli(const disim_heli_state_t *m, unsigned char *buf, int cap)
{
    int n = disim_heli_state_t_encoded_size(m);
    return n <= cap ? disim_heli_state_t_encode(buf, 0, cap, m) : -1;
}

static void test_station_rx(void)
{
    core_err err;
    sim_station_opts bad_id = {"has space", "memq://"};
    CHECK(sim_station_create(&bad_id, &err) == NULL && strstr(err.msg, "'has space'"));
    sim_station_opts o = {"me", "memq://"};
    sim_station *st = sim_station_create(&o, &err);
    CHECK(st != NULL);
    if (!st) {
        fprintf(stderr, "%s\n", err.msg);
        return;
    }
    const sim_station_view *v = sim_station_get_view(st);
    CHECK(v->last_seq == -1 && v->published == 0);
    sim_station_controls c;
    sim_station_controls_centre(&c);
    c.ctl.collective_pct = 61.0;
    CHECK(sim_station_publish(st, 20000, &c, &err) == 0);
    CHECK(sim_station_publish(st, 40000, &c, &err) == 0);
    CHECK(v->last_seq == 1 && v->published == 2 && v->sent.ctl.collective_pct == 61.0);

    double gear[3] = {1, 2, 3};
    disim_heli_state_t h;
    memset(&h, 0, sizeof h);
    h.utime = 3000000;
    h.pos_S_m[0] = 1.5;
    h.pos_S_m[1] = -2.0;
    h.pos_S_m[2] = -7.25;
    h.roll_rad = 3.0 * CORE_DEG_TO_RAD;
    h.quat_EB[0] = 1.0;
    h.collective_pct = 41.0;
    h.n_gear = 3;
    h.gear_load_N = gear;
    unsigned char buf[2048];
    int n = enc_heli(&h, buf, sizeof buf);
    CHECK(n > 0);
    sim_station_receive(st, DISIM_CH_HELI_STATE, buf, n);
    CHECK(v->heli_rx == 1 && v->bad_rx == 0 && v->have_heli);
    CHECK_NEAR(v->heli_pos_S_m[2], -7.25, 0.0);
    CHECK_NEAR(v->heli_ctl_pct[0], 41.0, 0.0);
    /* one byte short: refused by the raw check, nothing taken */
    h.pos_S_m[2] = -99.0;
    n = enc_heli(&h, buf, sizeof buf);
    sim_station_receive(st, DISIM_CH_HELI_STATE, buf, n - 1);
    CHECK(v->bad_rx == 1 && v->heli_rx == 1 && v->heli_pos_S_m[2] == -7.25);
    CHECK(strstr(v->bad_last, "DISIM_HELI_STATE: ") == v->bad_last);
    /* a NaN attitude: decoded, refused */
    h.roll_rad = NAN;
    n = enc_heli(&h, buf, sizeof buf);
    sim_station_receive(st, DISIM_CH_HELI_STATE, buf, n);
    CHECK(v->bad_rx == 2 && v->heli_rx == 1 && v->heli_pos_S_m[2] == -7.25);
    CHECK(strstr(v->bad_last, "heli_state_t.roll_rad / pitch_rad / yaw_rad (expected finite angles") != NULL);
    /* a status on the heli channel: the wrong fingerprint */
    char *ids[2] = {"other", "me"};
    int64_t last[2] = {5, 1}, rx[2] = {6, 2}, refused[2] = {0, 4}, gaps[2] = {0, 7};
    disim_sim_status_t s;
    memset(&s, 0, sizeof s);
    s.sim_time_s = 12.5;
    s.rate_hz = 200.0;
    s.real_time_factor = 1.0;
    s.overruns = 3;
    s.state = DISIM_SIM_STATUS_T_PAUSED;
    s.scenario = "sfs2";
    s.n_stations = 2;
    s.station_ids = ids;
    s.station_last_seq = last;
    s.station_received = rx;
    s.station_refused = refused;
    s.station_gaps = gaps;
    s.active_station = 0;
    s.flags = DISIM_SIM_STATUS_T_FLAG_INPUT_HELD | DISIM_SIM_STATUS_T_FLAG_FREE_STREAM;
    s.message = "";
    s.control_message = "";
    n = disim_sim_status_t_encode(buf, 0, sizeof buf, &s);
    CHECK(n > 0);
    sim_station_receive(st, DISIM_CH_HELI_STATE, buf, n);
    CHECK(v->bad_rx == 3 && v->heli_rx == 1 && v->status_rx == 0);
    sim_station_receive(st, DISIM_CH_SIM_STATUS, buf, n);
    CHECK(v->status_rx == 1 && v->bad_rx == 3 && v->have_status);
    CHECK(v->n_stations == 2 && v->listed == 1 && !strcmp(v->stations, "other, me"));
    CHECK(v->overruns == 3 && v->state == DISIM_SIM_STATUS_T_PAUSED && !strcmp(v->scenario, "sfs2"));
    CHECK(!strcmp(v->active, "other") && v->my_received == 2 && v->my_refused == 4 && v->my_gaps == 7);
    /* a string without its NUL, the size right: only the raw check sees it */
    unsigned char b2[2048];
    memcpy(b2, buf, (size_t)n);
    /* the scenario's length field: after 8 (hash) + 6 x 8 + 1 bytes */
    int off = 8 + 6 * 8 + 1;
    CHECK(b2[off + 3] == 5); /* "sfs2" and its NUL */
    b2[off + 4 + 4] = 'X'; /* its NUL overwritten, the size unchanged: lcm-gen's decoder takes it */
    sim_station_receive(st, DISIM_CH_SIM_STATUS, b2, n);
    CHECK(v->bad_rx == 4 && v->status_rx == 1 && strstr(v->bad_last, "scenario") != NULL);
    sim_station_receive(st, "DISIM_SOMETHING", buf, n);
    CHECK(v->bad_rx == 5);
    /* a heli state with n_gear = -1 and no gear: lcm-gen's decoder takes
     * it too (a NULL array), the raw check refuses a negative count */
    h.roll_rad = 0.0;
    h.n_gear = 0;
    n = enc_heli(&h, buf, sizeof buf);
    CHECK(n == 250 && buf[249] == 0);
    buf[249] = 0xff;
    sim_station_receive(st, DISIM_CH_HELI_STATE, buf, n);
    CHECK(v->bad_rx == 6 && v->heli_rx == 1 && v->heli_pos_S_m[2] == -7.25);
    CHECK(strstr(v->bad_last, "heli_state_t.n_gear") != NULL);

    /* the display: the values received, the counts; ANSI only on a tty */
    char text[4096];
    sim_station_format(v, "keyboard", 0, text, sizeof text);
    CHECK(strstr(text, "heli h 7.25 m x 1.50 y -2.00 roll 3.0 pitch 0.0 yaw 0.0 deg") != NULL);
    CHECK(strstr(text, "sim t 12.50 s PAUSED 200.0 Hz rtf 1.00 overruns 3 stations 2 (listed) active other "
                       "INPUT-HELD FREE-STREAM |") != NULL);
    CHECK(strstr(text, "rx heli 1 status 1 bad 6") != NULL);
    CHECK(strchr(text, '\033') == NULL && strchr(text, '\n') == NULL);
    sim_station_format(v, "keyboard", 1, text, sizeof text);
    CHECK(strncmp(text, "\033[H", 3) == 0 && strstr(text, "height over deck   7.25 m") != NULL);
    CHECK(strstr(text, "stations (2): other, me   flying: other") != NULL && strstr(text, "w/s collective") != NULL);
    CHECK(strstr(text, "taken 2   refused 4   missing 7") != NULL);
    CHECK(strstr(text, "instructor") == NULL); /* no command answered yet */

    /* The instructor's answer as the loop sends it, and a hostile status
     * whose strings would move the cursor or clear the pilot's screen:
     * shown escaped, never raw (every string of a status is the network's). */
    s.control_seq = 41;
    s.control_command = DISIM_SIM_CONTROL_T_REPOSITION;
    s.control_result = DISIM_SIM_STATUS_T_CONTROL_ACCEPTED;
    s.control_message = "reposition: sfs2 in the hover at (0.00, 0.00, -10.00) m in S";
    s.flags = DISIM_SIM_STATUS_T_FLAG_CRASH | DISIM_SIM_STATUS_T_FLAG_SAS_OFF;
    n = disim_sim_status_t_encode(buf, 0, sizeof buf, &s);
    sim_station_receive(st, DISIM_CH_SIM_STATUS, buf, n);
    CHECK(v->control_seq == 41 && v->control_result == DISIM_SIM_STATUS_T_CONTROL_ACCEPTED);
    sim_station_format(v, "keyboard", 0, text, sizeof text);
    CHECK(strstr(text, " CRASH") != NULL && strstr(text, " SAS-OFF") != NULL);
    CHECK(strstr(text, "| instructor reposition: sfs2 in the hover at (0.00, 0.00, -10.00) m in S |") != NULL);
    sim_station_format(v, "keyboard", 1, text, sizeof text);
    CHECK(strstr(text, "  instructor  reposition: sfs2 in the hover at (0.00, 0.00, -10.00) m in S   (0 s ago)") != NULL);
    CHECK(strstr(text, "CRASH SAS-OFF") != NULL);
    char *evil_ids[2] = {"other\033]0;owned\007", "me"};
    s.station_ids = evil_ids;
    s.scenario = "sfs2\033[2J";
    s.message = "\033[31mred";
    s.control_seq = 42;
    s.control_command = DISIM_SIM_CONTROL_T_SET_WOD;
    s.control_result = DISIM_SIM_STATUS_T_CONTROL_REFUSED;
    s.control_message = "no\rway\033[H";
    n = disim_sim_status_t_encode(buf, 0, sizeof buf, &s);
    sim_station_receive(st, DISIM_CH_SIM_STATUS, buf, n);
    CHECK(v->status_rx == 3 && !strcmp(v->active, "other\\x1b]0;owned\\x07"));
    CHECK(!strcmp(v->scenario, "sfs2\\x1b[2J") && !strcmp(v->message, "\\x1b[31mred"));
    CHECK(strstr(v->stations, "other\\x1b]0;owned\\x07, me") != NULL);
    sim_station_format(v, "keyboard", 0, text, sizeof text);
    CHECK(strstr(text, "| instructor REFUSED: no\\x0dway\\x1b[H |") != NULL);
    for (const char *c = text; *c; c++)
        CHECK(*c >= 0x20 && *c != 0x7f);
    sim_station_format(v, "keyboard", 1, text, sizeof text);
    /* the escapes on a tty are the display's own: cursor home, bold, clear
     * to the end of a line and below */
    size_t esc = 0;
    for (const char *c = text; (c = strchr(c, '\033')); c++)
        esc += !strncmp(c, "\033[H", 3) || !strncmp(c, "\033[K", 3) || !strncmp(c, "\033[J", 3) ||
               !strncmp(c, "\033[1m", 4) || !strncmp(c, "\033[0m", 4);
    size_t all = 0;
    for (const char *c = text; (c = strchr(c, '\033')); c++)
        all++;
    CHECK(esc == all && all > 0);
    CHECK(strchr(text, '\r') == NULL && strchr(text, '\007') == NULL);
    /* a refusal is the loop's message too: shown once, on the instructor's line */
    s.station_ids = ids;
    s.scenario = "sfs2";
    s.message = s.control_message = "set wod refused: WOD 99 m/s";
    s.control_seq = 43;
    n = disim_sim_status_t_encode(buf, 0, sizeof buf, &s);
    sim_station_receive(st, DISIM_CH_SIM_STATUS, buf, n);
    sim_station_format(v, "keyboard", 1, text, sizeof text);
    const char *first = strstr(text, "WOD 99 m/s");
    CHECK(first && strstr(first + 1, "WOD 99 m/s") == NULL && strstr(text, "instructor  \033[1mREFUSED: set wod") != NULL);
    sim_station_destroy(st);
}

int main(int argc, char **argv)
{
    (void)argc;
    (void)argv;
    char dir[] = "/tmp/test_station.XXXXXX";
    if (!mkdtemp(dir)) {
        perror("mkdtemp");
        return 1;
    }
    test_script(dir);
    test_keys();
    test_trim();
    test_axes();
    test_evdev_pipe();
    test_station_rx();
    char cmd[64];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    if (system(cmd) != 0)
        fprintf(stderr, "could not remove %s\n", dir);
    return check_done("test_station");
}
