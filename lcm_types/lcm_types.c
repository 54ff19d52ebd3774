/* lcm_types.c -- checks of received messages. LCM decodes any bytes that fit
 * the type, so NaNs, out-of-range percentages and unknown commands arrive
 * intact; a station's bad message must be refused with its field named, never
 * fed to the flight model. */
#include "disim_lcm.h"
#include "core.h"

#include <math.h>
#include <stdlib.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

static int pct_ok(double v) { return isfinite(v) && v >= 0.0 && v <= 100.0; }

int disim_lcm_check_pilot_input(const disim_pilot_input_t *m, char *err, size_t n)
{
    const char *bad = NULL;
    double v = 0.0;
    if (!m->station_id || !m->station_id[0])
        bad = "station_id";
    else if (m->seq < 0)
        bad = "seq";
    else if (!pct_ok(v = m->collective_pct))
        bad = "collective_pct";
    else if (!pct_ok(v = m->long_cyclic_pct))
        bad = "long_cyclic_pct";
    else if (!pct_ok(v = m->lat_cyclic_pct))
        bad = "lat_cyclic_pct";
    else if (!pct_ok(v = m->pedal_pct))
        bad = "pedal_pct";
    if (!bad)
        return 0;
    /* Say the value that was received: the id and seq have their own forms
     * (a "seq = 0" for a seq of -5 would send the reader the wrong way). */
    if (err && bad[0] == 's' && bad[1] == 't')
        snprintf(err, n, "pilot_input_t.station_id is empty: expected a non-empty id");
    else if (err && bad[0] == 's')
        snprintf(err, n, "pilot_input_t.seq = %lld: expected seq >= 0", (long long)m->seq);
    else if (err)
        snprintf(err, n, "pilot_input_t.%s = %g: expected a finite percentage 0 to 100", bad, v);
    return -1;
}

int disim_lcm_check_sim_control(const disim_sim_control_t *m, char *err, size_t n)
{
    if (m->seq < 0) { /* the value received, as for pilot_input_t */
        if (err)
            snprintf(err, n, "sim_control_t.seq = %lld: expected seq >= 0", (long long)m->seq);
        return -1;
    }
    if (m->command < DISIM_SIM_CONTROL_T_PAUSE || m->command > DISIM_SIM_CONTROL_T_RESTORE) {
        if (err)
            snprintf(err, n, "sim_control_t.command = %d: expected 1 (pause) to 12 (restore)", m->command);
        return -1;
    }
    if (m->command == DISIM_SIM_CONTROL_T_LOAD_SCENARIO && (!m->scenario_path || !m->scenario_path[0])) {
        if (err)
            snprintf(err, n, "sim_control_t.scenario_path: expected a path with LOAD_SCENARIO");
        return -1;
    }
    return 0;
}

/* 1 when v[0..n-1] are within [-lim, lim] (NaN is not). */
static int within(const double *v, int n, double lim)
{
    for (int i = 0; i < n; i++)
        if (!(fabs(v[i]) <= lim))
            return 0;
    return 1;
}

/* 1 when q (w, x, y, z) is a unit quaternion within 1e-6 of its square. */
static int unit_quat(const double q[4])
{
    double qn = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
    return fabs(qn - 1.0) < 1e-6;
}

int disim_lcm_check_heli_state(const disim_heli_state_t *h, char *err, size_t n)
{
    const double att[3] = {h->roll_rad, h->pitch_rad, h->yaw_rad};
    const double c[4] = {h->collective_pct, h->long_cyclic_pct, h->lat_cyclic_pct, h->pedal_pct};
    const double rotor[2] = {h->rotor_thrust_N, h->rotor_power_W};
    const char *bad = NULL;
    if (h->utime < 0)
        bad = "utime (expected >= 0)";
    else if (!within(h->pos_S_m, 3, 1e6) || !within(h->pos_E_m, 3, 1e7))
        bad = "pos_S_m / pos_E_m (expected finite positions)";
    else if (!within(h->vel_E_mps, 3, 1e4) || !within(h->vel_S_mps, 3, 1e4))
        bad = "vel_E_mps / vel_S_mps (expected finite velocities)";
    else if (!within(att, 3, 4.0))
        bad = "roll_rad / pitch_rad / yaw_rad (expected finite angles within -pi to pi)";
    else if (!within(h->rates_B_radps, 3, 1e3))
        bad = "rates_B_radps (expected finite rates)";
    else if (!unit_quat(h->quat_EB)) /* NaN and infinities too: as the renderer checks a pose */
        bad = "quat_EB (expected a finite unit quaternion)";
    else if (!within(rotor, 2, 1e12))
        bad = "rotor_thrust_N / rotor_power_W (expected finite values)";
    else if (h->n_gear < 0 || (h->n_gear > 0 && !h->gear_load_N) || !within(h->gear_load_N, h->n_gear, 1e12))
        bad = "gear_load_N (expected a finite load on each leg)";
    for (int i = 0; !bad && i < 4; i++)
        if (!(c[i] >= 0.0 && c[i] <= 100.0))
            bad = "the controls (expected finite percentages 0 to 100)";
    if (!bad)
        return 0;
    if (err)
        snprintf(err, n, "heli_state_t.%s", bad);
    return -1;
}

int disim_lcm_check_ship_state(const disim_ship_state_t *m, char *err, size_t n)
{
    const double att[3] = {m->roll_rad, m->pitch_rad, m->yaw_rad};
    const char *bad = NULL;
    if (m->utime < 0)
        bad = "utime (expected >= 0)";
    else if (!within(m->pos_E_m, 3, 1e7) || !within(m->vel_E_mps, 3, 1e4))
        bad = "pos_E_m / vel_E_mps (expected finite values)";
    else if (!unit_quat(m->quat_ES))
        bad = "quat_ES (expected a unit quaternion)";
    else if (!within(att, 3, 1e3)) /* the ship's heading need not be wrapped */
        bad = "roll_rad / pitch_rad / yaw_rad (expected finite angles)";
    else if (!within(m->rates_S_radps, 3, 1e3))
        bad = "rates_S_radps (expected finite rates)";
    else if (!within(m->spot_pos_E_m, 3, 1e7) || !within(m->spot_vel_E_mps, 3, 1e4) ||
             !within(m->spot_acc_E_mps2, 3, 1e5))
        bad = "spot_pos_E_m / spot_vel_E_mps / spot_acc_E_mps2 (expected finite values)";
    if (!bad)
        return 0;
    if (err)
        snprintf(err, n, "ship_state_t.%s", bad);
    return -1;
}

int disim_lcm_check_airwake_request(const disim_airwake_request_t *m, char *err, size_t n)
{
    const char *bad = NULL, *want = NULL;
    if (!m->request_id || !m->request_id[0])
        bad = "request_id", want = "a non-empty id";
    else if (!isfinite(m->wod_speed_mps) || m->wod_speed_mps < 0.0 || m->wod_speed_mps > 60.0)
        bad = "wod_speed_mps", want = "0 to 60 m/s";
    else if (!isfinite(m->wod_dir_rad) || fabs(m->wod_dir_rad) > M_PI + 1e-9)
        bad = "wod_dir_rad", want = "-pi to pi";
    else if (m->rotor < DISIM_AIRWAKE_REQUEST_T_ROTOR_OFF || m->rotor > DISIM_AIRWAKE_REQUEST_T_ROTOR_LOADED)
        bad = "rotor", want = "0 (off), 1 (uniform) or 2 (loaded)";
    else if (m->rotor != DISIM_AIRWAKE_REQUEST_T_ROTOR_OFF &&
             (!isfinite(m->rotor_thrust_N) || m->rotor_thrust_N <= 0.0))
        bad = "rotor_thrust_N", want = "a positive thrust with the rotor on";
    else if (m->rotor != DISIM_AIRWAKE_REQUEST_T_ROTOR_OFF &&
             (!isfinite(m->rotor_radius_m) || m->rotor_radius_m <= 0.1 || m->rotor_radius_m > 50.0))
        bad = "rotor_radius_m", want = "0.1 to 50 m with the rotor on";
    else if (!isfinite(m->shaft_pitch_rad) || fabs(m->shaft_pitch_rad) > 1.0)
        bad = "shaft_pitch_rad", want = "a finite shaft tilt within -1 to 1 rad";
    else if (!isfinite(m->shaft_roll_rad) || fabs(m->shaft_roll_rad) > 1.0)
        bad = "shaft_roll_rad", want = "a finite shaft tilt within -1 to 1 rad";
    /* The hub station too, as disim_lcm.h promises "every field finite":
     * a consumer other than airwaked has no awdb key check behind it. Same
     * bounds as awdb_key_canon, so nothing it takes is refused here. */
    else if (!isfinite(m->station_S_m[0]) || fabs(m->station_S_m[0]) > 1000.0 ||
             !isfinite(m->station_S_m[1]) || fabs(m->station_S_m[1]) > 1000.0 ||
             !isfinite(m->station_S_m[2]) || fabs(m->station_S_m[2]) > 1000.0)
        bad = "station_S_m", want = "three finite coordinates within -1000 to 1000 m";
    else if (core_grid_parse(m->grid) < 0)
        bad = "grid", want = "coarse, default or fine";
    if (!bad)
        return 0;
    if (err)
        snprintf(err, n, "airwake_request_t.%s: expected %s", bad, want);
    return -1;
}

/* ------------------------------------------------ raw buffers, before decoding */
/* The wire layout of every disim type after its 8-byte fingerprint, field by
 * field in the .lcm order: q 8 bytes (int64_t, double), i 4 (int32_t), b 1
 * (int8_t, boolean), s a string (int32 length counting its NUL, then the
 * bytes); I and B an int32 / int8 count, then S or Q that many strings or
 * 8-byte values. test_lcm checks each layout against lcm-gen's encoder. */
static const struct {
    const char *type;
    int64_t (*hash)(void); /* lcm-gen's fingerprint of the type */
    const char *layout;
} wire[] = {
    {"heli_state_t", __disim_heli_state_t_get_hash, "q:utime q:seq q:pos_E_m q:pos_E_m q:pos_E_m q:vel_E_mps q:vel_E_mps q:vel_E_mps "
                     "q:pos_S_m q:pos_S_m q:pos_S_m q:vel_S_mps q:vel_S_mps q:vel_S_mps "
                     "q:quat_EB q:quat_EB q:quat_EB q:quat_EB q:roll_rad q:pitch_rad q:yaw_rad "
                     "q:rates_B_radps q:rates_B_radps q:rates_B_radps q:collective_pct q:long_cyclic_pct "
                     "q:lat_cyclic_pct q:pedal_pct q:rotor_thrust_N q:rotor_power_W b:on_deck B:n_gear "
                     "Q:gear_load_N"},
    {"ship_state_t", __disim_ship_state_t_get_hash, "q:utime q:seq q:pos_E_m q:pos_E_m q:pos_E_m q:vel_E_mps q:vel_E_mps q:vel_E_mps "
                     "q:quat_ES q:quat_ES q:quat_ES q:quat_ES q:roll_rad q:pitch_rad q:yaw_rad "
                     "q:rates_S_radps q:rates_S_radps q:rates_S_radps q:spot_pos_E_m q:spot_pos_E_m "
                     "q:spot_pos_E_m q:spot_vel_E_mps q:spot_vel_E_mps q:spot_vel_E_mps q:spot_acc_E_mps2 "
                     "q:spot_acc_E_mps2 q:spot_acc_E_mps2"},
    {"pilot_input_t", __disim_pilot_input_t_get_hash, "q:utime s:station_id q:seq q:collective_pct q:long_cyclic_pct q:lat_cyclic_pct "
                      "q:pedal_pct b:trim_button b:trim_release b:take_over"},
    {"sim_control_t", __disim_sim_control_t_get_hash, "q:utime q:seq b:command s:scenario_path q:pos_S_m q:pos_S_m "
                      "q:pos_S_m q:heading_rad q:wod_speed_mps q:wod_dir_rad b:sea_state b:turbulence s:name"},
    {"sim_status_t", __disim_sim_status_t_get_hash, "q:utime q:seq q:sim_time_s q:rate_hz q:real_time_factor q:overruns b:state s:scenario "
                     "I:n_stations S:station_ids Q:station_last_seq Q:station_received Q:station_refused "
                     "Q:station_gaps i:active_station q:refused_unknown q:control_refused i:flags "
                     "q:step_p50_s q:step_p99_s q:step_max_s s:message q:control_seq b:control_command "
                     "b:control_result s:control_message q:control_apply_s"},
    {"airwake_request_t", __disim_airwake_request_t_get_hash, "q:utime q:seq s:request_id s:ship s:aircraft q:wod_speed_mps q:wod_dir_rad b:rotor "
                          "q:rotor_thrust_N q:station_S_m q:station_S_m q:station_S_m q:rotor_radius_m "
                          "q:shaft_pitch_rad q:shaft_roll_rad s:grid"},
    {"airwake_status_t", __disim_airwake_status_t_get_hash, "q:utime q:seq s:request_id s:ship s:aircraft q:wod_speed_mps q:wod_dir_rad b:state "
                         "q:progress q:residual i:iterations s:path s:message"},
    {"run_info_t", __disim_run_info_t_get_hash, "q:utime q:seq s:scenario_path s:scenario s:aircraft_path s:ship_path q:seed "
                   "b:sea_state q:ship_speed_mps q:wave_dir_rad q:course_rad b:spectrum i:n_waves q:wod_speed_mps "
                   "q:wod_dir_rad q:rate_hz q:state_rate_hz"},
    {"shol_point_t", __disim_shol_point_t_get_hash, "q:utime q:seq s:ship s:aircraft q:wod_speed_mps q:wod_dir_rad b:converged b:passed "
                     "s:limit q:roll_rad q:pitch_rad q:collective_pct q:long_cyclic_pct q:lat_cyclic_pct "
                     "q:pedal_pct q:margin_roll_rad q:margin_pitch_rad q:margin_long_pct q:margin_lat_pct "
                     "q:margin_coll_pct q:margin_pedal_pct"},
};

/* The older versions of a type, read as the newest: their fingerprint,
 * and the encoded defaults of the fields appended since (a version is the
 * newest's prefix). */
static const struct {
    const char *type;
    uint64_t hash;
    const unsigned char *tail;
    int tail_size;
} older[] = {
    /* pos_S_m 0 0 0, heading, WOD speed and direction 0, sea_state 0, turbulence 0, name "" */
    {"sim_control_t", 0x8dd8480154a70f03ull,
     (const unsigned char[]){0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
                             0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
                             0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0},
     55},
    /* control_seq -1, control_command 0, control_result 0, control_message "", control_apply_s 0 */
    {"sim_status_t", 0x7be0ef478700cc8eull,
     (const unsigned char[]){0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0,
                             0, 0, 0},
     23},
};

static int32_t be32(const unsigned char *p)
{
    return (int32_t)((uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3]);
}

int disim_lcm_check_raw(const char *type, const void *buf, int size, char *err, size_t n)
{
    const char *layout = NULL;
    uint64_t hash = 0;
    for (size_t t = 0; t < sizeof wire / sizeof wire[0]; t++)
        if (!strcmp(wire[t].type, type)) {
            layout = wire[t].layout;
            hash = (uint64_t)wire[t].hash();
        }
    if (!layout) {
        if (err)
            snprintf(err, n, "%s: not a disim LCM type", type);
        return -2;
    }
    const unsigned char *b = buf;
    long pos = 8, count = 0;
    if (!buf || size < 8) {
        if (err)
            snprintf(err, n, "%s: %d bytes: expected at least the 8-byte fingerprint", type, size);
        return -1;
    }
    /* the fingerprint first: another type's message (or another version
     * of this one) would otherwise be blamed on whichever field its bytes
     * happen not to fit */
    uint64_t fp = (uint64_t)(uint32_t)be32(b) << 32 | (uint32_t)be32(b + 4);
    if (fp != hash) {
        if (err)
            snprintf(err, n, "%s: fingerprint %016llx: expected %016llx (a message of another type or version)", type,
                     (unsigned long long)fp, (unsigned long long)hash);
        return -1;
    }
    for (const char *f = layout; *f;) {
        char kind = f[0];
        const char *name = f + 2, *end = strchr(name, ' ');
        int len = end ? (int)(end - name) : (int)strlen(name);
        long items = kind == 'S' || kind == 'Q' ? count : 1;
        for (long it = 0; it < items; it++) {
            long need = kind == 'q' || kind == 'Q' ? 8 : kind == 'i' || kind == 'I' || kind == 's' || kind == 'S' ? 4 : 1;
            if (size - pos < need) {
                if (err)
                    snprintf(err, n, "%s.%.*s: the message ends at byte %d: expected %ld more", type, len, name, size,
                             need);
                return -1;
            }
            if (kind == 'I' || kind == 'B') {
                count = kind == 'I' ? be32(b + pos) : (signed char)b[pos];
                if (count < 0) {
                    if (err)
                        snprintf(err, n, "%s.%.*s = %ld: expected a count >= 0", type, len, name, count);
                    return -1;
                }
            }
            if (kind == 's' || kind == 'S') {
                /* lcm 1.3.1 mallocs the length it reads and copies that many
                 * bytes: a length < 1 or a last byte other than NUL leaves
                 * the decoded string unterminated (strlen would run past it) */
                int32_t sl = be32(b + pos);
                const unsigned char *nul = sl >= 1 && sl <= size - pos - 4 ? memchr(b + pos + 4, 0, (size_t)sl) : NULL;
                if (nul && nul != b + pos + 4 + sl - 1) {
                    /* a NUL inside: the decoded string would end there and
                     * the bytes after it (logged, never acted on) be lost */
                    if (err)
                        snprintf(err, n, "%s.%.*s: a NUL inside the string (byte %d of %d): expected one string "
                                 "ending in its NUL", type, len, name, (int)(nul - (b + pos + 4)) + 1, (int)sl);
                    return -1;
                }
                if (sl < 1 || sl > size - pos - 4 || b[pos + 4 + sl - 1] != 0) {
                    if (err)
                        snprintf(err, n, "%s.%.*s: string length %d%s: expected a NUL-terminated string within "
                                 "the message", type, len, name, (int)sl,
                                 sl >= 1 && sl <= size - pos - 4 ? " without its NUL" : "");
                    return -1;
                }
                need += sl;
            }
            pos += need;
        }
        f = end ? end + 1 : name + len;
    }
    if (pos != size) {
        if (err)
            snprintf(err, n, "%s: %d bytes: expected %ld for its fields", type, size, pos);
        return -1;
    }
    return 0;
}

int disim_lcm_upgrade(const char *type, const void *buf, int size, void *out, int cap)
{
    const unsigned char *b = buf;
    if (!buf || size < 8)
        return 0;
    uint64_t fp = (uint64_t)(uint32_t)be32(b) << 32 | (uint32_t)be32(b + 4);
    for (size_t t = 0; t < sizeof older / sizeof older[0]; t++) {
        if (strcmp(older[t].type, type) || fp != older[t].hash)
            continue;
        if (size + older[t].tail_size > cap)
            return -1;
        uint64_t now = 0;
        for (size_t w = 0; w < sizeof wire / sizeof wire[0]; w++)
            if (!strcmp(wire[w].type, type))
                now = (uint64_t)wire[w].hash();
        unsigned char *o = out;
        for (int i = 0; i < 8; i++)
            o[i] = (unsigned char)(now >> (56 - 8 * i));
        memcpy(o + 8, b + 8, (size_t)size - 8);
        memcpy(o + size, older[t].tail, (size_t)older[t].tail_size);
        return size + older[t].tail_size;
    }
    return 0;
}

const char *disim_lcm_url(const char *given)
{
    if (given)
        return given;
    const char *env = getenv("LCM_DEFAULT_URL");
    return env && env[0] ? env : DISIM_LCM_DEFAULT_URL;
}
