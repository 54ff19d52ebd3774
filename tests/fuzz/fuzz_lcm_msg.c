/* fuzz_lcm_msg.c -- libFuzzer harness of what disim does with a buffer
 * that arrives on an LCM channel, for every type it receives:
 * disim_lcm_upgrade (an older sim_control_t / sim_status_t read as the
 * newest), disim_lcm_check_raw, lcm-gen's decoder, the type's own check
 * (heli_state_t and ship_state_t, as the view, the stations and the log
 * reader check them; pilot_input_t, sim_control_t, airwake_request_t)
 * and, for
 * pilot_input_t, the pilot stations' rules (sim_pilots_offer, which peeks
 * at the station id of a refused buffer and does the seq arithmetic); a
 * heli_state_t or sim_status_t also goes to a pilot station as its LCM
 * handler gives it (sim_station_receive: checked, decoded, its values
 * checked, taken into the view), and the view is formatted for a
 * terminal and for a log (sim_station_format).
 *
 * Input: one byte choosing the type (its value modulo the number of
 * types), then the buffer (its fingerprint first, as lcm_recv_buf_t
 * holds it). For pilot_input_t the rest is a run of buffers, each a
 * 2-byte big-endian length then its bytes, offered in turn 5 ms apart to
 * one sim_pilots.
 *
 * Checked, beyond no crash, hang, leak or sanitizer report: a buffer that
 * check_raw takes decodes to exactly its size, every string it holds ends
 * inside the message, and it encodes back to the same bytes (the check and
 * the decoder agree on the wire layout); sim_pilots's counts stay >= 0;
 * the station's line for a log holds no control character, and its
 * terminal display no escape but its own (cursor home, clear, bold; no
 * text from the network reaches a terminal raw). */
#include "disim_lcm.h"
#include "sim.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerInitialize(int *argc, char ***argv);

static sim_station *station;

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc, (void)argv;
    sim_station_opts o = {"fuzz-station", "memq://"};
    core_err err = {0};
    if (!(station = sim_station_create(&o, &err))) {
        fprintf(stderr, "fuzz_lcm_msg: %s\n", err.msg);
        exit(1);
    }
    return 0;
}

/* what the station shows of a received buffer */
static void station_view(const char *channel, const void *buf, int size)
{
    sim_station_receive(station, channel, buf, size);
    const sim_station_view *v = sim_station_get_view(station);
    static char text[16384];
    sim_station_format(v, "fuzz", 0, text, sizeof text);
    for (const unsigned char *p = (const unsigned char *)text; *p; p++)
        if (*p < 0x20 || *p == 0x7F)
            abort(); /* a control character in the line for a log: text from the network shown raw */
    sim_station_format(v, "fuzz", 1, text, sizeof text);
    static const char *const own[] = {"\033[H", "\033[K", "\033[J", "\033[1m", "\033[0m"};
    for (const char *p = text; *p; p++) {
        if (*p == '\n')
            continue;
        if (*p == '\033') {
            size_t k = 0;
            while (k < sizeof own / sizeof own[0] && strncmp(p, own[k], strlen(own[k])))
                k++;
            if (k == sizeof own / sizeof own[0])
                abort(); /* an escape not the display's own: text from the network reached the terminal */
            p += strlen(own[k]) - 1;
        } else if ((unsigned char)*p < 0x20 || *p == 0x7F) {
            abort(); /* a control character on the terminal */
        }
    }
}

/* Decode, check the strings, encode again and compare. 0 when check_raw
 * refused it (not decoded, as every receiver does), 1 when taken. */
#define ROUND_TRIP(T, CHECK_FN)                                                                          \
    static int rt_##T(const void *buf, int size)                                                         \
    {                                                                                                    \
        char e[256];                                                                                     \
        if (disim_lcm_check_raw(#T, buf, size, e, sizeof e) != 0)                                        \
            return 0;                                                                                    \
        disim_##T m;                                                                                     \
        memset(&m, 0, sizeof m);                                                                         \
        if (disim_##T##_decode(buf, 0, size, &m) != size)                                                \
            abort(); /* check_raw took what the decoder cannot read */                                   \
        strings_##T(&m);                                                                                 \
        CHECK_FN;                                                                                        \
        int n = disim_##T##_encoded_size(&m);                                                            \
        unsigned char *out = malloc((size_t)n);                                                          \
        if (!out || n != size || disim_##T##_encode(out, 0, n, &m) != n || memcmp(out, buf, (size_t)n)) \
            abort(); /* the decoded message is not the one received */                                   \
        free(out);                                                                                       \
        disim_##T##_decode_cleanup(&m);                                                                  \
        return 1;                                                                                        \
    }

/* strlen of every string: ASan reports one that runs past its buffer */
static volatile size_t sink;
static void s_(const char *s) { sink += strlen(s); }
static void strings_heli_state_t(const disim_heli_state_t *m) { (void)m; }
static void strings_ship_state_t(const disim_ship_state_t *m) { (void)m; }
static void strings_pilot_input_t(const disim_pilot_input_t *m) { s_(m->station_id); }
static void strings_sim_control_t(const disim_sim_control_t *m)
{
    s_(m->scenario_path);
    s_(m->name);
}
static void strings_sim_status_t(const disim_sim_status_t *m)
{
    s_(m->scenario);
    s_(m->message);
    s_(m->control_message);
    for (int i = 0; i < m->n_stations; i++)
        s_(m->station_ids[i]);
}
static void strings_airwake_request_t(const disim_airwake_request_t *m)
{
    s_(m->request_id);
    s_(m->ship);
    s_(m->aircraft);
    s_(m->grid);
}
static void strings_airwake_status_t(const disim_airwake_status_t *m)
{
    s_(m->request_id);
    s_(m->ship);
    s_(m->aircraft);
    s_(m->path);
    s_(m->message);
}
static void strings_run_info_t(const disim_run_info_t *m)
{
    s_(m->scenario_path);
    s_(m->scenario);
    s_(m->aircraft_path);
    s_(m->ship_path);
}
static void strings_shol_point_t(const disim_shol_point_t *m)
{
    s_(m->ship);
    s_(m->aircraft);
    s_(m->limit);
}

ROUND_TRIP(heli_state_t, disim_lcm_check_heli_state(&m, e, sizeof e))
ROUND_TRIP(ship_state_t, disim_lcm_check_ship_state(&m, e, sizeof e))
ROUND_TRIP(pilot_input_t, disim_lcm_check_pilot_input(&m, e, sizeof e))
ROUND_TRIP(sim_control_t, disim_lcm_check_sim_control(&m, e, sizeof e))
ROUND_TRIP(sim_status_t, (void)0)
ROUND_TRIP(airwake_request_t, disim_lcm_check_airwake_request(&m, e, sizeof e))
ROUND_TRIP(airwake_status_t, (void)0)
ROUND_TRIP(run_info_t, (void)0)
ROUND_TRIP(shol_point_t, (void)0)

static const struct {
    const char *type;
    int (*rt)(const void *, int);
} types[] = {
    {"pilot_input_t", rt_pilot_input_t},   {"sim_control_t", rt_sim_control_t},
    {"heli_state_t", rt_heli_state_t},     {"ship_state_t", rt_ship_state_t},
    {"sim_status_t", rt_sim_status_t},     {"run_info_t", rt_run_info_t},
    {"airwake_request_t", rt_airwake_request_t}, {"airwake_status_t", rt_airwake_status_t},
    {"shol_point_t", rt_shol_point_t},
};
#define NTYPES (sizeof types / sizeof types[0])

static void one(size_t t, const uint8_t *buf, int size)
{
    unsigned char up[4096];
    int un = disim_lcm_upgrade(types[t].type, buf, size, up, (int)sizeof up);
    if (un > 0 && disim_lcm_check_raw(types[t].type, up, un, NULL, 0) == 0 &&
        disim_lcm_check_raw(types[t].type, buf, size, NULL, 0) == 0)
        abort(); /* one buffer read as two versions of the type */
    if (un > 0)
        types[t].rt(up, un);
    types[t].rt(buf, size);
    if (!strcmp(types[t].type, "heli_state_t"))
        station_view(DISIM_CH_HELI_STATE, buf, size);
    else if (!strcmp(types[t].type, "sim_status_t"))
        station_view(DISIM_CH_SIM_STATUS, buf, size);
}

static void pilots(const uint8_t *data, size_t size)
{
    sim_pilots_opts o;
    sim_pilots_opts_default(&o);
    core_err err = {0};
    sim_pilots *p = sim_pilots_create(&o, &err);
    if (!p)
        abort();
    double t = 0.0;
    for (size_t pos = 0; pos + 2 <= size && t < 10.0; t += 0.005) {
        size_t n = (size_t)data[pos] << 8 | data[pos + 1];
        pos += 2;
        if (n > size - pos)
            n = size - pos;
        one(0, data + pos, (int)n);
        char why[256];
        sim_pilots_offer(p, data + pos, (int)n, t, why, sizeof why);
        pos += n;
        sim_flight_inputs in;
        hfm_controls flown = {50.0, 50.0, 50.0, 50.0};
        sim_pilots_inputs(p, t, &flown, &in);
    }
    for (int i = 0; i < sim_pilots_count(p); i++) {
        sim_pilot_station s;
        sim_pilots_station(p, i, &s);
        if (s.received < 0 || s.refused < 0 || s.gaps < 0 || s.last_seq < -1)
            abort();
    }
    if (sim_pilots_refused_unknown(p) < 0)
        abort();
    sim_pilots_destroy(p);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1 || size > 65536)
        return 0;
    size_t t = data[0] % NTYPES;
    if (t == 0)
        pilots(data + 1, size - 1);
    else
        one(t, data + 1, (int)(size - 1));
    return 0;
}
