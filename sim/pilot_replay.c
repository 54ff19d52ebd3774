/* pilot_replay.c -- the replay pilot: re-flies a recorded run, relative to
 * the deck, in another wind over deck and sea state.
 *
 * The reference. A run of `disim fly --log FILE` is an LCM event log
 * (sim/lcm_io.c; lcm/eventlog.h) holding, every 1 / state_rate_hz, a
 * heli_state_t and a ship_state_t of the same utime (the flight's time),
 * and every pilot_input_t the loop received, its event timestamp the run
 * step it was taken at. The reference is the helicopter's motion relative
 * to the ship's landing spot as a function of the flight's time t:
 *     r_S(t)   = heli_state_t.pos_S_m                (the CG from the spot, S)
 *     v_S(t)   = C_SE (v_E - v_O,E) - w_S x r_S       (d r_S / dt: relative
 *                to the deck, not to the ship's mean motion)
 *     psi_S(t) = psi_E - psi_ship                     (heading from the bow)
 * with v_E the CG's velocity, v_O,E the velocity of S's origin, w_S the
 * ship's angular velocity in S and psi_ship the azimuth of S's x axis,
 * all of the same instant (ship_state_t). Between samples the reference
 * is linear in t (the heading unwrapped); before the first sample it is
 * the first, after the last the last with v_S = 0. So a landing flown
 * over a heaving, rolling deck is re-flown relative to the deck: in
 * another sea the replay follows its own deck.
 *
 * The recorded controls: with one station's pilot_input_t in the log, its
 * inputs by run step (the loop's zero-order hold: an input taken at step
 * k flies the steps from k until the next); else the flown controls of
 * the heli_state_t (those of the step ending at the next sample). The run
 * clock is the flight's clock while the log holds one flight from its
 * start, which the reader makes sure of (the states' utime strictly
 * increasing: a reset or a load in the log is refused).
 *
 * The pilot. The automated pilot's loops (sim/pilot_auto.c: crossover
 * model, McRuer and Krendel 1974; outer loops after Lee and Horn 2005)
 * track the reference through sim_pilot_auto_set_reference each step.
 * The loops act on the error from the reference now; what is fed forward
 * is the reference's motion tau ahead (tau = preview_s, default the
 * pilot's delay: a pilot flying a known profile leads it by about his
 * delay, the precognitive mode of McRuer and Krendel's successive
 * organisation of perception), through the pilot's own loop laws:
 *     horizontal:  v_ff = v_S(t + tau) + a_S(t + tau + tau_a) / w_v
 * (the velocity loop's a_c = w_v (v_c - v) then carries a_S, the
 * reference's acceleration, whole; the acceleration is the attitude's,
 * which follows its command about 1 / w_a behind, w_a the attitude loops'
 * crossover: the crossover model closed, Y / (1 + Y) ~ 1 / (1 + s / w_a);
 * tau_a = acc_lead_s, default 1 / w_a),
 * and
 *     vertical:    w_ff = w(t + tau) + (a_z(t + tau) - Z_w w(t + tau)) / w_h
 * (the height loop's rate term then gives the collective the linear model
 * needs for that rate and acceleration, (a_z - Z_w w) / Z_col; w_v and
 * w_h the velocity loop's bandwidth and the height loop's crossover, Z_w
 * the heave damping the gains come from); the heading is the reference's
 * at t + tau. With feed_controls, the recorded pilot's control activity is
 * fed forward as well, about this flight's trim, and the loops act on the
 * deviation from the recorded state:
 *     u = u_trim + (u_rec(t) - u_rec,0) + (P(x) - P(x_rec)),
 * u_rec,0 the controls of the log's first state (the recorded run's trim),
 * P the pilot's delayed command for a state, x the flown state, x_rec the
 * recorded one at the same time (a second copy of the pilot flies the
 * recorded states: their delays match, and the correction is 0 while the
 * flight is on the recorded trajectory). In the recorded conditions that
 * reproduces the run to the samples' precision; in other conditions the
 * loops' correction carries what the recorded controls get wrong, with the
 * position error it needs (the loops have no integrator).
 *
 * Assumptions: the log is of one flight from its start at the scenario's
 * station (the replay's flight starts where the reference starts); the
 * pilot's gains are the bare airframe's (fly with the SAS off, as the
 * automated pilot); the recorded pilot's inputs go through the loop's
 * stations unchanged (one station, never held long enough to matter).
 *
 * Errors reported: the 3-D distance of the flown CG from the reference at
 * the same time (no preview), rms and largest, over the run and per phase
 * of the reference: descend (sinking faster than 0.2 m/s and faster than
 * it moves across), translate (moving faster than 0.3 m/s, or climbing
 * faster than 0.2 m/s), hover (else), on deck (the recorded state has a
 * wheel on the deck). The heading's largest error too.
 *
 * On the deck. Where the reference and the flight both have a wheel on
 * the deck the pilot lowers the collective at 20 %/s to 0 and holds
 * cyclic and pedals where they were, at once (the automated pilot's hand
 * after touchdown); the loops take over again when the reference leaves
 * the deck.
 *
 * Bad logs: a file missing or not a file; not an event log (no LCM sync
 * word at byte 0); an event whose header or data runs past the end of the
 * file (truncated) or with no sync word where the last one ended
 * (corrupt); a heli_state_t, ship_state_t or sim_status_t (the loop's own
 * messages) that fails disim_lcm_check_raw, a state that decodes to values
 * not finite; no heli_state_t (or only one); a state
 * with no ship state of its time; states not in time order. Each is an
 * error naming the file and the event (its number from 1, its channel and
 * byte offset). A pilot_input_t that fails the checks is skipped and
 * counted (the loop refused it, and it did not fly).
 */
#include "sim.h"
#include "disim_lcm.h"

#include <errno.h>
#include <lcm/eventlog.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define LOG_MAGIC 0xEDA1DA01u
#define HDR_BYTES 28 /* sync word, event number, timestamp, channel and data lengths */

/* one recorded state (the heli and ship messages of one utime) */
typedef struct rec_state {
    double t_s;
    double pos_S[3], vel_S[3], vel_mean_S[3];
    double acc_S[3]; /* d vel_S / dt, central differences over the samples */
    double heading; /* unwrapped along the log */
    double euler[3]; /* yaw unwrapped */
    double rate_B[3];
    double C_ES[9];
    double ctl[4]; /* the flown controls (of the step ending here) */
    int on_deck;   /* a wheel on the deck */
    /* as published, for drawing the run (sim_replay_log_state) */
    double heli_pos_E[3], q_EB[4], ship_pos_E[3], q_ES[4];
    double thrust_N, power_W;
    int n_gear;
    double gear_N[HFM_GEAR_MAX_LEGS];
} rec_state;

typedef struct rec_input {
    int64_t ts_us; /* the run clock when the loop took it (the event's timestamp) */
    double ctl[4];
} rec_input;

typedef struct ship_rec {
    int64_t utime;
    double pos_E[3], vel_E[3], q[4], rates_S[3];
} ship_rec;

/* a heli state's gear loads, kept beside it (the decoded array is freed) */
typedef struct gear_rec {
    int n;
    double N[HFM_GEAR_MAX_LEGS];
} gear_rec;

struct sim_replay_log {
    rec_state *s;
    long n;
    rec_input *in;
    long nin;
    sim_replay_info info;
    int have_run_info;
    sim_run_info run_info; /* the first run_info_t */
};

/* ------------------------------------------------------------ growable arrays */
static int grow(void **p, long *cap, long need, size_t size)
{
    if (need <= *cap)
        return 0;
    long c = *cap ? *cap : 256;
    while (c < need)
        c *= 2;
    void *q = realloc(*p, (size_t)c * size);
    if (!q)
        return -1;
    *p = q;
    *cap = c;
    return 0;
}

static uint32_t be32u(const unsigned char *b)
{
    return (uint32_t)b[0] << 24 | (uint32_t)b[1] << 16 | (uint32_t)b[2] << 8 | b[3];
}

static int fin3(const double v[3], double lim) { return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]) && fabs(v[0]) <= lim && fabs(v[1]) <= lim && fabs(v[2]) <= lim; }

static double wrap_pi(double a) { return atan2(sin(a), cos(a)); }

/* C_ES (row major) of a unit quaternion q_ES (w, x, y, z). */
static void quat_dcm(const double q[4], double C[9])
{
    double w = q[0], x = q[1], y = q[2], z = q[3];
    double n = sqrt(w * w + x * x + y * y + z * z);
    w /= n, x /= n, y /= n, z /= n;
    C[0] = 1 - 2 * (y * y + z * z), C[1] = 2 * (x * y - w * z), C[2] = 2 * (x * z + w * y);
    C[3] = 2 * (x * y + w * z), C[4] = 1 - 2 * (x * x + z * z), C[5] = 2 * (y * z - w * x);
    C[6] = 2 * (x * z - w * y), C[7] = 2 * (y * z + w * x), C[8] = 1 - 2 * (x * x + y * y);
}

/* The heli state h with its ship state sh into a reference sample. */
static void make_state(const disim_heli_state_t *h, const ship_rec *sh, rec_state *s)
{
    memset(s, 0, sizeof *s);
    s->t_s = (double)h->utime * 1e-6;
    double *C = s->C_ES;
    quat_dcm(sh->q, C);
    double dv[3];
    for (int i = 0; i < 3; i++) {
        s->pos_S[i] = h->pos_S_m[i];
        dv[i] = h->vel_E_mps[i] - sh->vel_E[i];
        s->vel_mean_S[i] = h->vel_S_mps[i];
        s->rate_B[i] = h->rates_B_radps[i];
    }
    const double *w = sh->rates_S, *r = s->pos_S;
    double wxr[3] = {w[1] * r[2] - w[2] * r[1], w[2] * r[0] - w[0] * r[2], w[0] * r[1] - w[1] * r[0]};
    for (int i = 0; i < 3; i++)
        s->vel_S[i] = C[i] * dv[0] + C[3 + i] * dv[1] + C[6 + i] * dv[2] - wxr[i];
    double psi_ship = atan2(C[3], C[0]);
    s->heading = wrap_pi(h->yaw_rad - psi_ship);
    s->euler[0] = h->roll_rad, s->euler[1] = h->pitch_rad, s->euler[2] = h->yaw_rad;
    s->ctl[0] = h->collective_pct, s->ctl[1] = h->long_cyclic_pct;
    s->ctl[2] = h->lat_cyclic_pct, s->ctl[3] = h->pedal_pct;
    s->on_deck = h->on_deck != 0;
    memcpy(s->heli_pos_E, h->pos_E_m, sizeof s->heli_pos_E);
    memcpy(s->q_EB, h->quat_EB, sizeof s->q_EB);
    memcpy(s->ship_pos_E, sh->pos_E, sizeof s->ship_pos_E);
    memcpy(s->q_ES, sh->q, sizeof s->q_ES);
    s->thrust_N = h->rotor_thrust_N;
    s->power_W = h->rotor_power_W;
}

static int heli_ok(const disim_heli_state_t *h, const char **bad)
{
    const double c[4] = {h->collective_pct, h->long_cyclic_pct, h->lat_cyclic_pct, h->pedal_pct};
    *bad = NULL;
    if (h->utime < 0)
        *bad = "utime (expected >= 0)";
    else if (!fin3(h->pos_S_m, 1e6) || !fin3(h->pos_E_m, 1e7))
        *bad = "pos_S_m / pos_E_m (expected finite positions)";
    else if (!fin3(h->vel_E_mps, 1e4) || !fin3(h->vel_S_mps, 1e4))
        *bad = "vel_E_mps / vel_S_mps (expected finite velocities)";
    else if (!(fabs(h->roll_rad) <= 4.0 && fabs(h->pitch_rad) <= 4.0 && fabs(h->yaw_rad) <= 4.0))
        *bad = "roll_rad / pitch_rad / yaw_rad (expected finite angles within -pi to pi)";
    else if (!fin3(h->rates_B_radps, 1e3))
        *bad = "rates_B_radps (expected finite rates)";
    for (int i = 0; !*bad && i < 4; i++)
        if (!(c[i] >= 0.0 && c[i] <= 100.0))
            *bad = "the controls (expected finite percentages 0 to 100)";
    return *bad == NULL;
}

static int ship_ok(const disim_ship_state_t *m, const char **bad)
{
    double qn = 0.0;
    for (int i = 0; i < 4; i++)
        qn += m->quat_ES[i] * m->quat_ES[i];
    *bad = NULL;
    if (!fin3(m->pos_E_m, 1e7) || !fin3(m->vel_E_mps, 1e4))
        *bad = "pos_E_m / vel_E_mps (expected finite values)";
    else if (!(fabs(qn - 1.0) < 1e-6))
        *bad = "quat_ES (expected a unit quaternion)";
    else if (!fin3(m->rates_S_radps, 1e3))
        *bad = "rates_S_radps (expected finite rates)";
    return *bad == NULL;
}

/* A run_info_t's fields in range (the paths fit, the sea is one sim_ship_motion takes). */
static int run_info_ok(const disim_run_info_t *m, const char **bad)
{
    *bad = NULL;
    if (strlen(m->scenario_path) >= SIM_PATH_MAX || strlen(m->aircraft_path) >= SIM_PATH_MAX ||
        strlen(m->ship_path) >= SIM_PATH_MAX || strlen(m->scenario) >= 64)
        *bad = "scenario_path / aircraft_path / ship_path / scenario (expected shorter paths and name)";
    else if (m->seed < 0)
        *bad = "seed (expected >= 0)";
    else if (m->sea_state < 0 || m->sea_state > SIM_SEA_MAX_STATE)
        *bad = "sea_state (expected 0 to 6)";
    else if (m->spectrum < 0 || m->spectrum > 1 || m->n_waves < 0 || m->n_waves > SIM_SEA_MAX_WAVES)
        *bad = "spectrum / n_waves (expected 0 or 1, and 0 to 4096 waves)";
    else if (!(isfinite(m->ship_speed_mps) && m->ship_speed_mps >= 0.0 && fabs(m->wave_dir_rad) <= 10.0 &&
               fabs(m->course_rad) <= 10.0 && isfinite(m->wod_speed_mps) && m->wod_speed_mps >= 0.0 &&
               fabs(m->wod_dir_rad) <= 10.0))
        *bad = "ship_speed_mps / wave_dir_rad / course_rad / wod_speed_mps / wod_dir_rad (expected finite values)";
    else if (!(m->rate_hz > 0.0 && m->rate_hz <= 1e5 && m->state_rate_hz > 0.0 && m->state_rate_hz <= m->rate_hz))
        *bad = "rate_hz / state_rate_hz (expected positive rates, the states' no faster than the loop's)";
    return *bad == NULL;
}

static void run_info_take(const disim_run_info_t *m, sim_run_info *ri)
{
    memset(ri, 0, sizeof *ri);
    snprintf(ri->scenario_path, sizeof ri->scenario_path, "%s", m->scenario_path);
    snprintf(ri->scenario, sizeof ri->scenario, "%s", m->scenario);
    snprintf(ri->aircraft_path, sizeof ri->aircraft_path, "%s", m->aircraft_path);
    snprintf(ri->ship_path, sizeof ri->ship_path, "%s", m->ship_path);
    ri->seed = (unsigned long long)m->seed;
    sim_sea_default(&ri->sea);
    ri->sea.state = m->sea_state;
    ri->sea.ship_speed_mps = m->ship_speed_mps;
    ri->sea.wave_dir_rad = m->wave_dir_rad;
    ri->sea.course_rad = m->course_rad;
    ri->sea.spectrum = m->spectrum ? SIM_SPECTRUM_JONSWAP : SIM_SPECTRUM_ITTC;
    ri->sea.n_waves = m->n_waves;
    ri->wod_speed_mps = m->wod_speed_mps;
    ri->wod_dir_rad = m->wod_dir_rad;
    ri->rate_hz = m->rate_hz;
    ri->state_rate_hz = m->state_rate_hz;
}

typedef struct reader {
    const char *path;
    long ev;        /* the event's number, from 1 */
    long long at;   /* its byte offset */
    const char *ch; /* its channel */
    core_err *err;
} reader;

static int ev_err(const reader *r, const char *what)
{
    if (!r->ch)
        return core_err_set(r->err, -1, "%s: event %ld (byte %lld): %s", r->path, r->ev, r->at, what);
    return core_err_set(r->err, -1, "%s: event %ld (%s, byte %lld): %s", r->path, r->ev, r->ch, r->at, what);
}

sim_replay_log *sim_replay_log_load(const char *path, core_err *err)
{
    if (!path)
        return core_err_set(err, -1, "replay: expected the path of an LCM log"), NULL;
    struct stat st;
    if (stat(path, &st) != 0) {
        core_err_set(err, -1, "%s: cannot read the LCM log (%s)", path, strerror(errno));
        return NULL;
    }
    if (!S_ISREG(st.st_mode)) {
        core_err_set(err, -1, "%s: not a file: expected an LCM event log (disim fly --log)", path);
        return NULL;
    }
    long long size = (long long)st.st_size;
    sim_replay_log *L = calloc(1, sizeof *L);
    lcm_eventlog_t *el = lcm_eventlog_create(path, "r");
    disim_heli_state_t *heli = NULL;
    ship_rec *ships = NULL;
    gear_rec *gears = NULL;
    long nheli = 0, capheli = 0, nship = 0, capship = 0, capin = 0, capgear = 0;
    long long *heli_ev = NULL; /* each heli state's event number, for the errors after the read */
    long cap_ev = 0;
    char st_id[SIM_STATION_ID_MAX] = "";
    int n_stations = 0;
    if (!L || !el) {
        core_err_set(err, -1, L ? "%s: cannot read the LCM log" : "%s: out of memory", path);
        goto fail;
    }
    if (size == 0) {
        core_err_set(err, -1, "%s: empty: expected an LCM event log (disim fly --log)", path);
        goto fail;
    }
    reader R = {path, 0, 0, NULL, err};
    for (;;) {
        long long at = (long long)ftello(el->f);
        if (at == size)
            break;
        R.ev++;
        R.at = at;
        R.ch = NULL;
        unsigned char hdr[HDR_BYTES];
        size_t got = fread(hdr, 1, sizeof hdr, el->f);
        if (got >= 4 && be32u(hdr) != LOG_MAGIC) {
            if (R.ev == 1)
                core_err_set(err, -1, "%s: not an LCM event log (no sync word at byte 0): expected a log of disim fly "
                                      "--log", path);
            else
                ev_err(&R, "no sync word where the last event ended (corrupt)");
            goto fail;
        }
        if (got < sizeof hdr) {
            ev_err(&R, "the file ends inside the event's header (truncated)");
            goto fail;
        }
        int32_t chlen = (int32_t)be32u(hdr + 20), dlen = (int32_t)be32u(hdr + 24);
        if (chlen <= 0 || chlen >= 256 || dlen < 0) {
            ev_err(&R, "a channel or data length out of range (corrupt)");
            goto fail;
        }
        if (at + HDR_BYTES + chlen + dlen > size) {
            char w[160];
            snprintf(w, sizeof w, "%d bytes of channel and data, %lld left in the file (truncated)", chlen + dlen,
                     size - at - HDR_BYTES);
            ev_err(&R, w);
            goto fail;
        }
        /* lcm_eventlog_read_next_event reads the next event's sync word
         * too (and prints when it is not there): look first, to name it */
        long long next = at + HDR_BYTES + chlen + dlen;
        if (next < size) {
            unsigned char sync[4];
            if (fseeko(el->f, (off_t)next, SEEK_SET) != 0 || fread(sync, 1, 4, el->f) != 4 ||
                be32u(sync) != LOG_MAGIC) {
                R.ev++;
                R.at = next;
                ev_err(&R, next + 4 > size ? "the file ends inside the event's header (truncated)"
                                           : "no sync word where the last event ended (corrupt)");
                goto fail;
            }
        }
        if (fseeko(el->f, (off_t)at, SEEK_SET) != 0) {
            ev_err(&R, "cannot seek back to the event");
            goto fail;
        }
        lcm_eventlog_event_t *ev = lcm_eventlog_read_next_event(el);
        if (!ev) {
            ev_err(&R, "not read by lcm_eventlog_read_next_event (corrupt)");
            goto fail;
        }
        R.ch = ev->channel;
        char e[256];
        int bad = 0;
        if (!strcmp(ev->channel, DISIM_CH_HELI_STATE)) {
            disim_heli_state_t h;
            const char *why;
            if (disim_lcm_check_raw("heli_state_t", ev->data, ev->datalen, e, sizeof e) != 0)
                bad = ev_err(&R, e);
            else if (disim_heli_state_t_decode(ev->data, 0, ev->datalen, &h) != ev->datalen)
                bad = ev_err(&R, "heli_state_t: not decoded");
            else {
                if (!heli_ok(&h, &why)) {
                    snprintf(e, sizeof e, "heli_state_t.%s", why);
                    bad = ev_err(&R, e);
                } else if (nheli > 0 && h.utime <= heli[nheli - 1].utime) {
                    snprintf(e, sizeof e, "heli_state_t.utime %lld us not after the last state's %lld us (a reset or "
                                          "a load in the log): expected one flight from its start",
                             (long long)h.utime, (long long)heli[nheli - 1].utime);
                    bad = ev_err(&R, e);
                } else if (grow((void **)&heli, &capheli, nheli + 1, sizeof *heli) ||
                           grow((void **)&heli_ev, &cap_ev, nheli + 1, sizeof *heli_ev) ||
                           grow((void **)&gears, &capgear, nheli + 1, sizeof *gears))
                    bad = ev_err(&R, "out of memory");
                else {
                    gear_rec *g = &gears[nheli];
                    g->n = h.n_gear < 0 ? 0 : h.n_gear > HFM_GEAR_MAX_LEGS ? HFM_GEAR_MAX_LEGS : h.n_gear;
                    for (int i = 0; i < g->n; i++)
                        g->N[i] = isfinite(h.gear_load_N[i]) ? h.gear_load_N[i] : 0.0;
                    heli_ev[nheli] = R.ev;
                    heli[nheli] = h;
                    heli[nheli].n_gear = 0; /* the fixed fields are kept, the gear's loads freed below */
                    heli[nheli++].gear_load_N = NULL;
                }
                disim_heli_state_t_decode_cleanup(&h);
            }
        } else if (!strcmp(ev->channel, DISIM_CH_SHIP_STATE)) {
            disim_ship_state_t m;
            const char *why;
            if (disim_lcm_check_raw("ship_state_t", ev->data, ev->datalen, e, sizeof e) != 0)
                bad = ev_err(&R, e);
            else if (disim_ship_state_t_decode(ev->data, 0, ev->datalen, &m) != ev->datalen)
                bad = ev_err(&R, "ship_state_t: not decoded");
            else if (!ship_ok(&m, &why)) {
                snprintf(e, sizeof e, "ship_state_t.%s", why);
                bad = ev_err(&R, e);
            } else if (grow((void **)&ships, &capship, nship + 1, sizeof *ships))
                bad = ev_err(&R, "out of memory");
            else {
                ship_rec *s = &ships[nship++];
                s->utime = m.utime;
                memcpy(s->pos_E, m.pos_E_m, sizeof s->pos_E);
                memcpy(s->vel_E, m.vel_E_mps, sizeof s->vel_E);
                memcpy(s->q, m.quat_ES, sizeof s->q);
                memcpy(s->rates_S, m.rates_S_radps, sizeof s->rates_S);
            }
        } else if (!strcmp(ev->channel, DISIM_CH_RUN_INFO)) {
            /* what the run was flown from: the first is kept */
            disim_run_info_t m;
            const char *why;
            if (disim_lcm_check_raw("run_info_t", ev->data, ev->datalen, e, sizeof e) != 0)
                bad = ev_err(&R, e);
            else if (disim_run_info_t_decode(ev->data, 0, ev->datalen, &m) != ev->datalen)
                bad = ev_err(&R, "run_info_t: not decoded");
            else {
                if (!run_info_ok(&m, &why)) {
                    snprintf(e, sizeof e, "run_info_t.%s", why);
                    bad = ev_err(&R, e);
                } else if (!L->have_run_info) {
                    run_info_take(&m, &L->run_info);
                    L->have_run_info = 1;
                }
                disim_run_info_t_decode_cleanup(&m);
            }
        } else if (!strcmp(ev->channel, DISIM_CH_SIM_STATUS)) {
            /* written by the loop, as the states: not used, but a bad one is a corrupt log */
            if (disim_lcm_check_raw("sim_status_t", ev->data, ev->datalen, e, sizeof e) != 0)
                bad = ev_err(&R, e);
        } else if (!strcmp(ev->channel, DISIM_CH_PILOT_INPUT)) {
            /* received: a message the loop refused is in the log too, and did not fly */
            disim_pilot_input_t m;
            memset(&m, 0, sizeof m);
            int ok = disim_lcm_check_raw("pilot_input_t", ev->data, ev->datalen, e, sizeof e) == 0 &&
                     disim_pilot_input_t_decode(ev->data, 0, ev->datalen, &m) == ev->datalen;
            if (ok && disim_lcm_check_pilot_input(&m, e, sizeof e) == 0 && ev->timestamp >= 0) {
                if (!n_stations || strcmp(st_id, m.station_id)) {
                    if (n_stations == 0)
                        snprintf(st_id, sizeof st_id, "%s", m.station_id);
                    n_stations = n_stations == 0 || strcmp(st_id, m.station_id) == 0 ? 1 : 2;
                }
                if (grow((void **)&L->in, &capin, L->nin + 1, sizeof *L->in))
                    bad = ev_err(&R, "out of memory");
                else {
                    rec_input *in = &L->in[L->nin++];
                    in->ts_us = ev->timestamp;
                    in->ctl[0] = m.collective_pct, in->ctl[1] = m.long_cyclic_pct;
                    in->ctl[2] = m.lat_cyclic_pct, in->ctl[3] = m.pedal_pct;
                }
            } else
                L->info.n_inputs_bad++;
            if (ok)
                disim_pilot_input_t_decode_cleanup(&m);
        }
        lcm_eventlog_free_event(ev);
        if (bad)
            goto fail;
        L->info.n_events = R.ev;
    }
    if (nheli < 2) {
        core_err_set(err, -1, "%s: %ld heli_state_t in %ld events: expected the states of a flight (disim fly --log)",
                     path, nheli, R.ev);
        goto fail;
    }
    if (!(L->s = calloc((size_t)nheli, sizeof *L->s))) {
        core_err_set(err, -1, "%s: out of memory", path);
        goto fail;
    }
    /* each heli state with the ship state of its utime (published together) */
    long j = 0;
    for (long i = 0; i < nheli; i++) {
        while (j < nship && ships[j].utime < heli[i].utime)
            j++;
        if (j >= nship || ships[j].utime != heli[i].utime) {
            R.ev = (long)heli_ev[i];
            R.ch = DISIM_CH_HELI_STATE;
            core_err_set(err, -1, "%s: event %ld (%s): no ship_state_t of its utime (%lld us): expected both, as disim "
                                  "fly --log writes them", path, R.ev, R.ch, (long long)heli[i].utime);
            goto fail;
        }
        make_state(&heli[i], &ships[j], &L->s[i]);
        L->s[i].n_gear = gears[i].n;
        memcpy(L->s[i].gear_N, gears[i].N, sizeof L->s[i].gear_N);
        if (i > 0) { /* unwrap the heading and the yaw along the log */
            rec_state *a = &L->s[i - 1], *b = &L->s[i];
            b->heading = a->heading + wrap_pi(b->heading - a->heading);
            b->euler[2] = a->euler[2] + wrap_pi(b->euler[2] - a->euler[2]);
        }
    }
    for (long i = 0; i < nheli; i++) {
        const rec_state *a = &L->s[i > 0 ? i - 1 : 0], *b = &L->s[i + 1 < nheli ? i + 1 : nheli - 1];
        for (int c = 0; c < 3; c++)
            L->s[i].acc_S[c] = (b->vel_S[c] - a->vel_S[c]) / (b->t_s - a->t_s);
    }
    L->n = nheli;
    L->info.n_states = nheli;
    L->info.n_ship = nship;
    L->info.t0_s = L->s[0].t_s;
    L->info.t1_s = L->s[nheli - 1].t_s;
    /* one station's inputs are the recorded controls (several: the flown ones) */
    if (n_stations == 1)
        L->info.n_inputs = L->nin;
    else
        L->nin = 0;
    L->info.n_stations = n_stations;
    if (n_stations == 1)
        snprintf(L->info.station, sizeof L->info.station, "%s", st_id);
    free(heli);
    free(heli_ev);
    free(ships);
    free(gears);
    lcm_eventlog_destroy(el);
    return L;
fail:
    free(heli);
    free(heli_ev);
    free(ships);
    free(gears);
    if (el)
        lcm_eventlog_destroy(el);
    sim_replay_log_destroy(L);
    return NULL;
}

void sim_replay_log_destroy(sim_replay_log *r)
{
    if (!r)
        return;
    free(r->s);
    free(r->in);
    free(r);
}

void sim_replay_log_info(const sim_replay_log *r, sim_replay_info *i) { *i = r->info; }

/* The index k of the last sample with t_k <= t (0 .. n-1). */
static long find(const sim_replay_log *r, double t)
{
    long lo = 0, hi = r->n - 1;
    if (t <= r->s[0].t_s)
        return 0;
    if (t >= r->s[hi].t_s)
        return hi;
    while (hi - lo > 1) {
        long m = (lo + hi) / 2;
        if (r->s[m].t_s <= t)
            lo = m;
        else
            hi = m;
    }
    return lo;
}

static void controls_at(const sim_replay_log *r, double t_s, long k, double ctl[4])
{
    if (r->nin > 0) {
        /* the input taken last at or before the run step of t (the loop's
         * hold; run_us rounds the step's time to the microsecond) */
        double t_us = t_s * 1e6 + 0.5;
        long lo = 0, hi = r->nin - 1;
        if ((double)r->in[0].ts_us > t_us) {
            memcpy(ctl, r->s[0].ctl, 4 * sizeof *ctl); /* before the first input: the trim flown */
            return;
        }
        while (hi > lo) {
            long m = (lo + hi + 1) / 2;
            if ((double)r->in[m].ts_us <= t_us)
                lo = m;
            else
                hi = m - 1;
        }
        memcpy(ctl, r->in[lo].ctl, 4 * sizeof *ctl);
        return;
    }
    /* the flown controls of the step from t: those of the next sample */
    long j = k + 1 < r->n && r->s[k].t_s <= t_s + 1e-9 ? k + 1 : k;
    if (t_s < r->s[0].t_s)
        j = 0;
    memcpy(ctl, r->s[j].ctl, 4 * sizeof *ctl);
}

/* The log's times are whole microseconds (utime) and the loop's are sums
 * of its step: a time within half a tick of a sample is that sample's, so
 * the loop's time of the last logged step is inside the log. */
#define LOG_TICK_HALF_S 0.5e-6

int sim_replay_log_sample(const sim_replay_log *r, double t_s, sim_replay_sample *out)
{
    memset(out, 0, sizeof *out);
    out->t_s = t_s;
    long k = find(r, t_s);
    const rec_state *a = &r->s[k], *b = k + 1 < r->n ? &r->s[k + 1] : a;
    double w = 0.0;
    int outside = !(t_s >= r->s[0].t_s - LOG_TICK_HALF_S && t_s <= r->s[r->n - 1].t_s + LOG_TICK_HALF_S);
    if (b != a && t_s > a->t_s)
        w = fmin(1.0, (t_s - a->t_s) / (b->t_s - a->t_s));
    for (int i = 0; i < 3; i++) {
        out->pos_S_m[i] = a->pos_S[i] + w * (b->pos_S[i] - a->pos_S[i]);
        out->vel_S_mps[i] = a->vel_S[i] + w * (b->vel_S[i] - a->vel_S[i]);
        out->acc_S_mps2[i] = a->acc_S[i] + w * (b->acc_S[i] - a->acc_S[i]);
        out->vel_mean_S_mps[i] = a->vel_mean_S[i] + w * (b->vel_mean_S[i] - a->vel_mean_S[i]);
        out->euler_E_rad[i] = a->euler[i] + w * (b->euler[i] - a->euler[i]);
        out->rate_B_radps[i] = a->rate_B[i] + w * (b->rate_B[i] - a->rate_B[i]);
    }
    out->euler_E_rad[2] = wrap_pi(out->euler_E_rad[2]);
    for (int i = 0; i < 9; i++)
        out->C_ES[i] = a->C_ES[i] + w * (b->C_ES[i] - a->C_ES[i]);
    out->heading_rad = wrap_pi(a->heading + w * (b->heading - a->heading));
    if (t_s > r->s[r->n - 1].t_s + LOG_TICK_HALF_S) /* after the end: held there */
        for (int i = 0; i < 3; i++)
            out->vel_S_mps[i] = out->acc_S_mps2[i] = out->vel_mean_S_mps[i] = out->rate_B_radps[i] = 0.0;
    controls_at(r, t_s, k, out->controls_pct);
    out->on_deck = a->on_deck;
    double vh = hypot(out->vel_S_mps[0], out->vel_S_mps[1]), vz = out->vel_S_mps[2];
    out->phase = out->on_deck           ? SIM_REPLAY_ON_DECK
                 : vz > 0.2 && vz > vh  ? SIM_REPLAY_DESCEND
                 : vh > 0.3 || vz < -0.2 ? SIM_REPLAY_TRANSLATE
                                         : SIM_REPLAY_HOVER;
    return outside;
}

/* q0 + w (q1 - q0), q1's sign taken nearer q0, normalised (nlerp). */
static core_quat nlerp(const double a[4], const double b[4], double w)
{
    double d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3], sg = d < 0.0 ? -1.0 : 1.0;
    core_quat q = {a[0] + w * (sg * b[0] - a[0]), a[1] + w * (sg * b[1] - a[1]), a[2] + w * (sg * b[2] - a[2]),
                   a[3] + w * (sg * b[3] - a[3])};
    return core_quat_normalize(q);
}

int sim_replay_log_state(const sim_replay_log *r, double t_s, sim_log_state *out)
{
    memset(out, 0, sizeof *out);
    out->t_s = t_s;
    long k = find(r, t_s);
    const rec_state *a = &r->s[k], *b = k + 1 < r->n ? &r->s[k + 1] : a;
    int outside = !(t_s >= r->s[0].t_s - LOG_TICK_HALF_S && t_s <= r->s[r->n - 1].t_s + LOG_TICK_HALF_S);
    double w = 0.0;
    if (b != a && t_s > a->t_s)
        w = fmin(1.0, (t_s - a->t_s) / (b->t_s - a->t_s));
    double hp[3], sp[3];
    for (int i = 0; i < 3; i++) {
        hp[i] = a->heli_pos_E[i] + w * (b->heli_pos_E[i] - a->heli_pos_E[i]);
        sp[i] = a->ship_pos_E[i] + w * (b->ship_pos_E[i] - a->ship_pos_E[i]);
        out->pos_S_m[i] = a->pos_S[i] + w * (b->pos_S[i] - a->pos_S[i]);
        out->vel_S_mps[i] = a->vel_S[i] + w * (b->vel_S[i] - a->vel_S[i]);
        out->euler_E_rad[i] = a->euler[i] + w * (b->euler[i] - a->euler[i]);
    }
    out->euler_E_rad[2] = wrap_pi(out->euler_E_rad[2]);
    out->heli.pos_E_m = core_vec3_make(hp[0], hp[1], hp[2]);
    out->heli.q_EF = nlerp(a->q_EB, b->q_EB, w);
    out->ship.pos_E_m = core_vec3_make(sp[0], sp[1], sp[2]);
    out->ship.q_EF = nlerp(a->q_ES, b->q_ES, w);
    core_euler se = core_quat_to_euler(out->ship.q_EF); /* of the attitude drawn */
    out->ship_euler_E_rad[0] = se.phi_rad, out->ship_euler_E_rad[1] = se.theta_rad, out->ship_euler_E_rad[2] = se.psi_rad;
    for (int i = 0; i < 4; i++)
        out->controls_pct[i] = a->ctl[i] + w * (b->ctl[i] - a->ctl[i]);
    out->rotor_thrust_N = a->thrust_N + w * (b->thrust_N - a->thrust_N);
    out->rotor_power_W = a->power_W + w * (b->power_W - a->power_W);
    const rec_state *near = w < 0.5 ? a : b;
    out->on_deck = near->on_deck;
    out->n_gear = near->n_gear;
    memcpy(out->gear_load_N, near->gear_N, sizeof out->gear_load_N);
    return outside;
}

int sim_replay_log_run_info(const sim_replay_log *r, sim_run_info *ri)
{
    if (!r->have_run_info) {
        memset(ri, 0, sizeof *ri);
        return 1;
    }
    *ri = r->run_info;
    return 0;
}

/* ------------------------------------------------------------------ the pilot */
struct sim_pilot_replay {
    const sim_replay_log *ref;
    sim_pilot_replay_opts o;
    sim_pilot_auto *pilot;  /* flies the flight */
    sim_pilot_auto *shadow; /* feed_controls: flies the recorded states */
    double Z_w;             /* the heave damping the pilot's gains come from (1/s) */
    double trim_pct[4];     /* this flight's trim: the recorded controls are fed forward about it */
    int deck;               /* on the deck with the reference: the collective going down */
    double deck_u[4];       /* the controls then (cyclic and pedals held) */
    double last_u[4];       /* the last controls given */
    double sum2[SIM_REPLAY_NPHASE + 1];
    sim_replay_result r;
};

void sim_pilot_replay_opts_default(sim_pilot_replay_opts *o)
{
    memset(o, 0, sizeof *o);
    sim_pilot_auto_opts_default(&o->pilot);
    o->preview_s = -1.0;
    o->acc_lead_s = -1.0;
}

const char *sim_replay_phase_name(int phase)
{
    return phase == SIM_REPLAY_HOVER       ? "hover"
           : phase == SIM_REPLAY_TRANSLATE ? "translate"
           : phase == SIM_REPLAY_DESCEND   ? "descend"
           : phase == SIM_REPLAY_ON_DECK   ? "on deck"
                                           : "all";
}

sim_pilot_replay *sim_pilot_replay_create(const hfm_aircraft *ac, const sim_replay_log *ref,
                                          const sim_pilot_replay_opts *o, const sim_flight_inputs *trim,
                                          const core_log *log, core_err *err)
{
    if (!ac || !ref || !o || !trim) {
        core_err_set(err, -1, "pilot_replay: expected an aircraft, a reference log, options and the trim");
        return NULL;
    }
    double pv = o->preview_s < 0.0 ? o->pilot.delay_s : o->preview_s;
    if (!(pv >= 0.0 && pv <= 10.0) || !(o->acc_lead_s <= 10.0) || !(o->pilot.att_crossover_radps > 0.0)) {
        core_err_set(err, -1, "pilot_replay: preview %g s, acceleration lead %g s: expected up to 10 s each (< 0: the "
                              "defaults) and a positive attitude crossover", o->preview_s, o->acc_lead_s);
        return NULL;
    }
    sim_pilot_replay *p = calloc(1, sizeof *p);
    if (!p) {
        core_err_set(err, -1, "pilot_replay: out of memory");
        return NULL;
    }
    p->ref = ref;
    p->o = *o;
    p->o.preview_s = pv;
    p->o.acc_lead_s = o->acc_lead_s < 0.0 ? 1.0 / o->pilot.att_crossover_radps : o->acc_lead_s;
    /* the automated pilot's gains at the reference's start, as a station
     * keeping there for the log's length; the reference then moves on */
    sim_replay_sample s0;
    sim_replay_log_sample(ref, ref->s[0].t_s, &s0);
    sim_task t;
    memset(&t, 0, sizeof t);
    t.kind = SIM_TASK_STATION_KEEP;
    memcpy(t.target_S_m, s0.pos_S_m, sizeof t.target_S_m);
    if (!(t.target_S_m[2] < -0.1))
        t.target_S_m[2] = -0.1; /* a log that starts on the deck: the gains of a hover just above it */
    t.heading_rad = s0.heading_rad;
    t.duration_s = fmax(0.1, ref->info.t1_s);
    t.desired.pos_m = t.adequate.pos_m = 1.0;
    t.desired.height_m = t.adequate.height_m = 1.0;
    t.desired.heading_rad = t.adequate.heading_rad = 5.0 * CORE_DEG_TO_RAD;
    sim_task_phase *h = &t.phase[0]; /* one hold phase, as sim_task_load makes a station keeping */
    snprintf(h->name, sizeof h->name, "replay");
    h->kind = SIM_PHASE_HOLD;
    memcpy(h->target_S_m, t.target_S_m, sizeof h->target_S_m);
    h->heading_rad = t.heading_rad;
    h->duration_s = t.duration_s;
    h->desired = t.desired;
    h->adequate = t.adequate;
    t.nphases = 1;
    if (!(p->pilot = sim_pilot_auto_create(ac, &t, &o->pilot, trim, log, err)))
        goto fail;
    sim_pilot_gains g;
    sim_pilot_auto_gains(p->pilot, &g);
    p->Z_w = g.Z_w;
    memcpy(p->last_u, g.trim_pct, sizeof p->last_u);
    p->trim_pct[0] = trim->collective_pct, p->trim_pct[1] = trim->long_pct;
    p->trim_pct[2] = trim->lat_pct, p->trim_pct[3] = trim->pedal_pct;
    if (o->feed_controls && !(p->shadow = sim_pilot_auto_create(ac, &t, &o->pilot, trim, log, err)))
        goto fail;
    p->r.t_s = -1.0;
    return p;
fail:
    sim_pilot_replay_destroy(p);
    return NULL;
}

int sim_pilot_replay_set_trim_state(sim_pilot_replay *p, const sim_flight_out *s0)
{
    if (!p || !s0)
        return -1;
    int rc = sim_pilot_auto_set_trim_state(p->pilot, s0);
    if (rc == 0 && p->shadow)
        rc = sim_pilot_auto_set_trim_state(p->shadow, s0);
    return rc;
}

void sim_pilot_replay_destroy(sim_pilot_replay *p)
{
    if (!p)
        return;
    sim_pilot_auto_destroy(p->pilot);
    sim_pilot_auto_destroy(p->shadow);
    free(p);
}

static void add_err(sim_replay_err *e, double *sum2, double d, double t_s, double h_s)
{
    e->n++;
    *sum2 += d * d;
    e->rms_m = sqrt(*sum2 / (double)e->n);
    if (d > e->max_m || e->n == 1) {
        e->max_m = d;
        e->t_max_s = t_s;
    }
    e->duration_s += h_s;
}

int sim_pilot_replay_step(sim_pilot_replay *p, const sim_flight_out *out, sim_flight_inputs *in)
{
    const sim_replay_log *L = p->ref;
    const double h = 1.0 / p->o.pilot.rate_hz;
    /* the errors of the state the pilot sees, against the reference at its time */
    sim_replay_sample now, ahead;
    sim_replay_log_sample(L, out->t_s, &now);
    sim_replay_result *r = &p->r;
    if (out->t_s > r->t_s + 1e-9 && out->t_s <= L->info.t1_s + 1e-9) {
        double d2 = 0.0;
        for (int i = 0; i < 3; i++)
            d2 += (out->pos_S_m[i] - now.pos_S_m[i]) * (out->pos_S_m[i] - now.pos_S_m[i]);
        double d = sqrt(d2);
        double psi_ship = atan2(out->ship.C_ES[3], out->ship.C_ES[0]);
        double dpsi = fabs(wrap_pi(out->euler_E_rad[2] - psi_ship - now.heading_rad));
        r->err_m = d;
        r->max_heading_err_rad = fmax(r->max_heading_err_rad, dpsi);
        add_err(&r->all, &p->sum2[SIM_REPLAY_NPHASE], d, out->t_s, h);
        add_err(&r->phase[now.phase], &p->sum2[now.phase], d, out->t_s, h);
        r->t_s = out->t_s;
    }
    r->ended = out->t_s >= L->info.t1_s - 1e-9;
    /* on the deck, as the reference is: the collective down at 20 %/s,
     * cyclic and pedals held, no delay (the hand goes down, as the
     * automated pilot's after touchdown); off again when the reference
     * leaves the deck */
    if (now.on_deck && out->on_deck) {
        if (!p->deck)
            memcpy(p->deck_u, p->last_u, sizeof p->deck_u);
        p->deck = 1;
        p->deck_u[0] = fmax(p->deck_u[0] - 20.0 * h, 0.0);
        memset(in, 0, sizeof *in);
        in->collective_pct = p->deck_u[0], in->long_pct = p->deck_u[1];
        in->lat_pct = p->deck_u[2], in->pedal_pct = p->deck_u[3];
        memcpy(p->last_u, p->deck_u, sizeof p->last_u);
        return 0;
    }
    p->deck = 0;
    /* the loops act on the error from the reference now; what is fed
     * forward is the reference's motion preview_s ahead (the pilot's
     * delay), through the velocity loop (acceleration) and the height
     * loop's rate term (the linear model's collective) */
    sim_replay_log_sample(L, out->t_s + p->o.preview_s, &ahead);
    sim_pilot_ref ref;
    memset(&ref, 0, sizeof ref);
    memcpy(ref.pos_S_m, now.pos_S_m, sizeof ref.pos_S_m);
    sim_replay_sample acc_ahead; /* the attitude (and so the acceleration) follows its command 1 / w_a late */
    sim_replay_log_sample(L, out->t_s + p->o.preview_s + p->o.acc_lead_s, &acc_ahead);
    for (int i = 0; i < 2; i++)
        ref.vel_S_mps[i] = ahead.vel_S_mps[i] + acc_ahead.acc_S_mps2[i] / p->o.pilot.vel_bw_radps;
    ref.vel_S_mps[2] = ahead.vel_S_mps[2] + (ahead.acc_S_mps2[2] - p->Z_w * ahead.vel_S_mps[2]) / p->o.pilot.hgt_crossover_radps;
    ref.heading_rad = ahead.heading_rad;
    ref.mode = SIM_PILOT_HOLD;
    if (sim_pilot_auto_set_reference(p->pilot, &ref) != 0)
        return -1; /* not reached: the log's values were checked finite */
    int stop = sim_pilot_auto_step(p->pilot, out, in);
    if (p->shadow) {
        /* the same pilot on the recorded state: its command there, delayed alike */
        sim_flight_out x;
        memset(&x, 0, sizeof x);
        x.t_s = out->t_s;
        x.step = out->step;
        memcpy(x.pos_S_m, now.pos_S_m, sizeof x.pos_S_m);
        memcpy(x.vel_S_mps, now.vel_mean_S_mps, sizeof x.vel_S_mps);
        memcpy(x.euler_E_rad, now.euler_E_rad, sizeof x.euler_E_rad);
        memcpy(x.rate_B_radps, now.rate_B_radps, sizeof x.rate_B_radps);
        memcpy(x.ship.C_ES, now.C_ES, sizeof x.ship.C_ES);
        sim_flight_inputs xs;
        sim_pilot_auto_set_reference(p->shadow, &ref);
        sim_pilot_auto_step(p->shadow, &x, &xs);
        const double c[4] = {in->collective_pct, in->long_pct, in->lat_pct, in->pedal_pct};
        const double cs[4] = {xs.collective_pct, xs.long_pct, xs.lat_pct, xs.pedal_pct};
        double u[4];
        for (int i = 0; i < 4; i++)
            u[i] = p->trim_pct[i] + (now.controls_pct[i] - L->s[0].ctl[i]) + (c[i] - cs[i]);
        stop = 0;
        for (int i = 0; i < 4; i++) {
            if (u[i] <= 0.0 || u[i] >= 100.0)
                stop = 1;
            u[i] = fmin(fmax(u[i], 0.0), 100.0);
        }
        in->collective_pct = u[0], in->long_pct = u[1], in->lat_pct = u[2], in->pedal_pct = u[3];
        in->hold = 0;
    }
    if (stop)
        r->stop_steps++;
    p->last_u[0] = in->collective_pct, p->last_u[1] = in->long_pct;
    p->last_u[2] = in->lat_pct, p->last_u[3] = in->pedal_pct;
    return stop;
}

void sim_pilot_replay_result(const sim_pilot_replay *p, sim_replay_result *r) { *r = p->r; }

/* ---------------------------------------------- as a sim_pilot (runner) */
static int replay_pilot_step(void *self, const sim_flight_out *out, sim_flight_inputs *in)
{
    sim_pilot_replay_step(self, out, in);
    return 0;
}

sim_pilot sim_pilot_replay_pilot(sim_pilot_replay *p)
{
    static const sim_pilot_ops ops = {"replay", replay_pilot_step};
    sim_pilot pl = {&ops, p};
    return pl;
}
