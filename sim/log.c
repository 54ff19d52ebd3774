/* log.c -- the LCM event log of a run: the writer (the loop's log of
 * `disim fly --log FILE`) and the reader (the run as a reference for the
 * replay pilot, and its states for drawing).
 *
 * The format is LCM's event log (lcm/eventlog.h, as lcm-logger writes it:
 * lcm-logplayer, lcm-spy and lcm_eventlog_read_next_event read it): each
 * event a 28-byte header (the sync word 0xEDA1DA01, the event number, the
 * timestamp in microseconds, the channel's and the data's lengths, all
 * big-endian), the channel's name, then the message. The loop (sim_loop)
 * writes every message it sends and receives, in its order, with the run
 * clock as the timestamp: every 1 / state_rate_hz a heli_state_t and a
 * ship_state_t of the same utime (the flight's time), every pilot_input_t
 * received, stamped with the run step it was taken at, the sim_status_t
 * and the run_info_t of what the run is flown from. The status's flags
 * say whether the SAS was engaged (FLAG_SAS, FLAG_SAS_OFF); the reader
 * keeps the first status's (a log whose statuses say neither, of an older
 * disim, reads as unknown).
 *
 * The writer writes through lcm_eventlog_write_event (the same bytes) to
 * a new file beside the log's path (PATH.tmpPID.N, created exclusively);
 * sim_log_writer_commit flushes and syncs it and renames it over PATH, so
 * a log is there whole or not at all: a failed write or commit, or a
 * writer destroyed before its commit, removes the temporary file.
 *
 * The reference. The reader makes of the log the helicopter's motion
 * relative to the ship's landing spot as a function of the flight's time t:
 *     r_S(t)   = heli_state_t.pos_S_m                (the CG from the spot, S)
 *     v_S(t)   = C_SE (v_E - v_O,E) - w_S x r_S       (d r_S / dt: relative
 *                to the deck, not to the ship's mean motion)
 *     psi_S(t) = psi_E - psi_ship                     (heading from the bow)
 * with v_E the CG's velocity, v_O,E the velocity of S's origin, w_S the
 * ship's angular velocity in S and psi_ship the azimuth of S's x axis,
 * all of the same instant (ship_state_t). Between samples the reference
 * is linear in t (the heading unwrapped); before the first sample it is
 * the first, after the last the last with v_S = 0. The phase of the
 * reference's motion: descend (sinking faster than 0.2 m/s and faster
 * than it moves across), translate (moving faster than 0.3 m/s, or
 * climbing faster than 0.2 m/s), hover (else), on deck (the recorded
 * state has a wheel on the deck).
 *
 * The recorded controls: with one station's pilot_input_t in the log, its
 * inputs by run step (the loop's zero-order hold: an input taken at step
 * k flies the steps from k until the next); else the flown controls of
 * the heli_state_t (those of the step ending at the next sample). The run
 * clock is the flight's clock while the log holds one flight from its
 * start, which the reader makes sure of (the states' utime strictly
 * increasing: a reset or a load in the log is refused).
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
 *
 * Reference: the log format, lcm-proj.github.io/lcm/content/log-file-format.html.
 */
#include "sim.h"
#include "disim_lcm.h"

#include <errno.h>
#include <fcntl.h>
#include <lcm/eventlog.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define LOG_MAGIC 0xEDA1DA01u
#define HDR_BYTES 28 /* sync word, event number, timestamp, channel and data lengths */

/* ----------------------------------------------------------------- the reader */
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
    /* as published, for drawing the run (sim_log_state_at) */
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

struct sim_log {
    rec_state *s;
    long n;
    rec_input *in;
    long nin;
    sim_log_summary info;
    int have_run_info;
    sim_run_info run_info; /* the first run_info_t */
};

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
    s->heading = core_wrap_pi(h->yaw_rad - psi_ship);
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


/* What the reader gathers from the events before the states are paired. */
typedef struct loader {
    reader R;
    long long size;
    lcm_eventlog_t *el;
    sim_log *L;
    disim_heli_state_t *heli;
    long long *heli_ev; /* each heli state's event number, for the errors after the read */
    gear_rec *gears;
    ship_rec *ships;
    long nheli, capheli, cap_ev, capgear, nship, capship, capin;
    char st_id[SIM_STATION_ID_MAX];
    int n_stations;
} loader;

/* The file checked and opened: 0, or -1 with err. */
/* The frame of event R->ev at byte at of a file of size bytes: its
 * header read from f (positioned there), the sync word, the lengths, the
 * event inside the file. 0 with the lengths, or -1 with the error. */
static int frame_at(const reader *R, FILE *f, long long at, long long size, int32_t *chlen, int32_t *dlen)
{
    unsigned char hdr[HDR_BYTES];
    size_t got = fread(hdr, 1, sizeof hdr, f);
    if (got >= 4 && be32u(hdr) != LOG_MAGIC) {
        if (R->ev == 1)
            return core_err_set(R->err, -1, "%s: not an LCM event log (no sync word at byte 0): expected a log of "
                                            "disim fly --log", R->path);
        return ev_err(R, "no sync word where the last event ended (corrupt)");
    }
    if (got < sizeof hdr)
        return ev_err(R, "the file ends inside the event's header (truncated)");
    *chlen = (int32_t)be32u(hdr + 20), *dlen = (int32_t)be32u(hdr + 24);
    if (*chlen <= 0 || *chlen >= 256 || *dlen < 0)
        return ev_err(R, "a channel or data length out of range (corrupt)");
    long long need = (long long)*chlen + (long long)*dlen, left = size - at - HDR_BYTES;
    if (need > left) {
        char w[160];
        snprintf(w, sizeof w, "%lld bytes of channel and data, %lld left in the file (truncated)", need, left);
        return ev_err(R, w);
    }
    return 0;
}

int sim_log_check_frames(const char *path, sim_log_frames *fr, core_err *err)
{
    memset(fr, 0, sizeof *fr);
    if (!path)
        return core_err_set(err, -1, "expected the path of an LCM log");
    struct stat st;
    if (stat(path, &st) != 0)
        return core_err_set(err, -1, "%s: cannot read the LCM log (%s)", path, strerror(errno));
    if (core_file_check_stat(path, &st, SIM_LOG_MAX_BYTES, err) != 0) /* nothing opened: a FIFO does not block */
        return -1;
    FILE *f = fopen(path, "rb");
    if (!f || fstat(fileno(f), &st) != 0) {
        int e = errno;
        if (f)
            fclose(f);
        return core_err_set(err, -1, "%s: cannot read the LCM log (%s)", path, strerror(e));
    }
    int rc = core_file_check_stat(path, &st, SIM_LOG_MAX_BYTES, err); /* the file opened, as checked */
    fr->size = (long long)st.st_size;
    if (rc == 0 && fr->size == 0)
        rc = core_err_set(err, -1, "%s: empty: expected an LCM event log (disim fly --log)", path);
    reader R = {path, 0, 0, NULL, err};
    for (long long at = 0; rc == 0 && at < fr->size;) {
        R.ev++;
        R.at = at;
        int32_t chlen, dlen;
        char ch[256];
        if (fseeko(f, (off_t)at, SEEK_SET) != 0)
            rc = ev_err(&R, "cannot seek to the event");
        else if ((rc = frame_at(&R, f, at, fr->size, &chlen, &dlen)) == 0) {
            if (fread(ch, 1, (size_t)chlen, f) != (size_t)chlen) {
                rc = ev_err(&R, "the channel's name not read");
                break;
            }
            ch[chlen] = '\0';
            if (!strcmp(ch, DISIM_CH_PILOT_INPUT) || !strcmp(ch, DISIM_CH_SIM_CONTROL))
                fr->n_inputs++;
            else if (!strcmp(ch, SIM_LOOP_CH_CONTROL_DONE))
                fr->n_marks++;
            fr->n_events++;
            at += HDR_BYTES + (long long)chlen + (long long)dlen;
        }
    }
    fclose(f);
    return rc;
}

static int open_log(loader *ld, const char *path, core_err *err)
{
    struct stat st;
    if (stat(path, &st) != 0)
        return core_err_set(err, -1, "%s: cannot read the LCM log (%s)", path, strerror(errno));
    if (core_file_check_stat(path, &st, SIM_LOG_MAX_BYTES, err) != 0)
        return -1;
    ld->size = (long long)st.st_size;
    ld->L = calloc(1, sizeof *ld->L);
    if (ld->L)
        ld->L->info.sas = -1; /* until a status says */
    ld->el = lcm_eventlog_create(path, "r");
    if (!ld->L || !ld->el)
        return core_err_set(err, -1, ld->L ? "%s: cannot read the LCM log" : "%s: out of memory", path);
    if (ld->size == 0)
        return core_err_set(err, -1, "%s: empty: expected an LCM event log (disim fly --log)", path);
    ld->R = (reader){path, 0, 0, NULL, err};
    return 0;
}

/* The event at byte at, its frame checked (the sync word, the lengths,
 * the next event's sync word): NULL with the error. */
static lcm_eventlog_event_t *next_event(loader *ld, long long at)
{
    reader *R = &ld->R;
    FILE *f = ld->el->f;
    R->ev++;
    R->at = at;
    R->ch = NULL;
    int32_t chlen, dlen;
    if (frame_at(R, f, at, ld->size, &chlen, &dlen) != 0)
        return NULL;
    /* lcm_eventlog_read_next_event reads the next event's sync word too
     * (and prints when it is not there): look first, to name it */
    long long next = at + HDR_BYTES + chlen + dlen;
    if (next < ld->size) {
        unsigned char sync[4];
        if (fseeko(f, (off_t)next, SEEK_SET) != 0 || fread(sync, 1, 4, f) != 4 || be32u(sync) != LOG_MAGIC) {
            R->ev++;
            R->at = next;
            ev_err(R, next + 4 > ld->size ? "the file ends inside the event's header (truncated)"
                                          : "no sync word where the last event ended (corrupt)");
            return NULL;
        }
    }
    if (fseeko(f, (off_t)at, SEEK_SET) != 0)
        return ev_err(R, "cannot seek back to the event"), NULL;
    lcm_eventlog_event_t *ev = lcm_eventlog_read_next_event(ld->el);
    if (!ev)
        ev_err(R, "not read by lcm_eventlog_read_next_event (corrupt)");
    return ev;
}

/* A heli_state_t kept (its gear loads beside it): 0, or -1 with the error. */
static int take_heli(loader *ld, const lcm_eventlog_event_t *ev)
{
    const reader *R = &ld->R;
    disim_heli_state_t h;
    char e[256];
    if (disim_lcm_check_raw("heli_state_t", ev->data, ev->datalen, e, sizeof e) != 0)
        return ev_err(R, e);
    if (disim_heli_state_t_decode(ev->data, 0, ev->datalen, &h) != ev->datalen)
        return ev_err(R, "heli_state_t: not decoded");
    int bad = 0;
    long n = ld->nheli;
    if (disim_lcm_check_heli_state(&h, e, sizeof e) != 0) {
        bad = ev_err(R, e);
    } else if (n > 0 && h.utime <= ld->heli[n - 1].utime) {
        snprintf(e, sizeof e, "heli_state_t.utime %lld us not after the last state's %lld us (a reset or a load in "
                              "the log): expected one flight from its start",
                 (long long)h.utime, (long long)ld->heli[n - 1].utime);
        bad = ev_err(R, e);
    } else if (grow((void **)&ld->heli, &ld->capheli, n + 1, sizeof *ld->heli) ||
               grow((void **)&ld->heli_ev, &ld->cap_ev, n + 1, sizeof *ld->heli_ev) ||
               grow((void **)&ld->gears, &ld->capgear, n + 1, sizeof *ld->gears))
        bad = ev_err(R, "out of memory");
    else {
        gear_rec *g = &ld->gears[n];
        g->n = h.n_gear < 0 ? 0 : h.n_gear > HFM_GEAR_MAX_LEGS ? HFM_GEAR_MAX_LEGS : h.n_gear;
        for (int i = 0; i < g->n; i++)
            g->N[i] = isfinite(h.gear_load_N[i]) ? h.gear_load_N[i] : 0.0;
        ld->heli_ev[n] = R->ev;
        ld->heli[n] = h;
        ld->heli[n].n_gear = 0; /* the fixed fields are kept, the gear's loads freed below */
        ld->heli[n].gear_load_N = NULL;
        ld->nheli = n + 1;
    }
    disim_heli_state_t_decode_cleanup(&h);
    return bad;
}

/* A ship_state_t kept: 0, or -1 with the error. */
static int take_ship(loader *ld, const lcm_eventlog_event_t *ev)
{
    const reader *R = &ld->R;
    disim_ship_state_t m;
    char e[256];
    if (disim_lcm_check_raw("ship_state_t", ev->data, ev->datalen, e, sizeof e) != 0)
        return ev_err(R, e);
    if (disim_ship_state_t_decode(ev->data, 0, ev->datalen, &m) != ev->datalen)
        return ev_err(R, "ship_state_t: not decoded");
    if (disim_lcm_check_ship_state(&m, e, sizeof e) != 0)
        return ev_err(R, e);
    if (grow((void **)&ld->ships, &ld->capship, ld->nship + 1, sizeof *ld->ships))
        return ev_err(R, "out of memory");
    ship_rec *s = &ld->ships[ld->nship++];
    s->utime = m.utime;
    memcpy(s->pos_E, m.pos_E_m, sizeof s->pos_E);
    memcpy(s->vel_E, m.vel_E_mps, sizeof s->vel_E);
    memcpy(s->q, m.quat_ES, sizeof s->q);
    memcpy(s->rates_S, m.rates_S_radps, sizeof s->rates_S);
    return 0;
}

/* A run_info_t checked, the first kept: 0, or -1 with the error. */
static int take_run_info(loader *ld, const lcm_eventlog_event_t *ev)
{
    const reader *R = &ld->R;
    disim_run_info_t m;
    const char *why;
    char e[256];
    if (disim_lcm_check_raw("run_info_t", ev->data, ev->datalen, e, sizeof e) != 0)
        return ev_err(R, e);
    if (disim_run_info_t_decode(ev->data, 0, ev->datalen, &m) != ev->datalen)
        return ev_err(R, "run_info_t: not decoded");
    int bad = 0;
    if (!run_info_ok(&m, &why)) {
        snprintf(e, sizeof e, "run_info_t.%s", why);
        bad = ev_err(R, e);
    } else if (!ld->L->have_run_info) {
        run_info_take(&m, &ld->L->run_info);
        ld->L->have_run_info = 1;
    }
    disim_run_info_t_decode_cleanup(&m);
    return bad;
}

/* A received pilot_input_t kept, or skipped and counted when it fails the
 * checks (the loop refused it, and it did not fly): 0, or -1 with the error. */
static int take_input(loader *ld, const lcm_eventlog_event_t *ev)
{
    sim_log *L = ld->L;
    disim_pilot_input_t m;
    char e[256];
    int bad = 0;
    memset(&m, 0, sizeof m);
    int ok = disim_lcm_check_raw("pilot_input_t", ev->data, ev->datalen, e, sizeof e) == 0 &&
             disim_pilot_input_t_decode(ev->data, 0, ev->datalen, &m) == ev->datalen;
    if (ok && disim_lcm_check_pilot_input(&m, e, sizeof e) == 0 && ev->timestamp >= 0) {
        if (!ld->n_stations || strcmp(ld->st_id, m.station_id)) {
            if (ld->n_stations == 0)
                snprintf(ld->st_id, sizeof ld->st_id, "%s", m.station_id);
            ld->n_stations = ld->n_stations == 0 || strcmp(ld->st_id, m.station_id) == 0 ? 1 : 2;
        }
        if (grow((void **)&L->in, &ld->capin, L->nin + 1, sizeof *L->in))
            bad = ev_err(&ld->R, "out of memory");
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
    return bad;
}

/* A sim_status_t checked (a bad one is a corrupt log); the SAS state of
 * the first that says it kept: 0, or -1 with the error. */
static int take_status(loader *ld, const lcm_eventlog_event_t *ev)
{
    char e[256];
    /* a status of an older disim's log, read as the newest (fields appended since) */
    unsigned char *up = malloc((size_t)ev->datalen + 64);
    if (!up)
        return ev_err(&ld->R, "out of memory");
    const void *data = ev->data;
    int size = ev->datalen;
    int un = disim_lcm_upgrade("sim_status_t", data, size, up, ev->datalen + 64);
    if (un > 0)
        data = up, size = un;
    int rc = 0;
    disim_sim_status_t m;
    if (disim_lcm_check_raw("sim_status_t", data, size, e, sizeof e) != 0)
        rc = ev_err(&ld->R, e);
    else if (ld->L->info.sas >= 0)
        rc = 0;
    else if (disim_sim_status_t_decode(data, 0, size, &m) != size)
        rc = ev_err(&ld->R, "sim_status_t: not decoded");
    else {
        if (m.flags & DISIM_SIM_STATUS_T_FLAG_SAS)
            ld->L->info.sas = 1;
        else if (m.flags & DISIM_SIM_STATUS_T_FLAG_SAS_OFF)
            ld->L->info.sas = 0;
        disim_sim_status_t_decode_cleanup(&m);
    }
    free(up);
    return rc;
}

/* One event by its channel (others are passed over): 0, or -1 with the error. */
static int take_event(loader *ld, const lcm_eventlog_event_t *ev)
{
    if (!strcmp(ev->channel, DISIM_CH_HELI_STATE))
        return take_heli(ld, ev);
    if (!strcmp(ev->channel, DISIM_CH_SHIP_STATE))
        return take_ship(ld, ev);
    if (!strcmp(ev->channel, DISIM_CH_RUN_INFO)) /* what the run was flown from */
        return take_run_info(ld, ev);
    if (!strcmp(ev->channel, DISIM_CH_SIM_STATUS)) /* written by the loop, as the states */
        return take_status(ld, ev);
    if (!strcmp(ev->channel, DISIM_CH_PILOT_INPUT)) /* received: a message the loop refused is in the log too */
        return take_input(ld, ev);
    return 0;
}

/* Every event read: 0, or -1 with the error. */
static int read_events(loader *ld)
{
    for (;;) {
        long long at = (long long)ftello(ld->el->f);
        if (at == ld->size)
            return 0;
        lcm_eventlog_event_t *ev = next_event(ld, at);
        if (!ev)
            return -1;
        ld->R.ch = ev->channel;
        int bad = take_event(ld, ev);
        lcm_eventlog_free_event(ev);
        if (bad)
            return -1;
        ld->L->info.n_events = ld->R.ev;
    }
}

/* The reference's samples: each heli state with the ship state of its
 * utime (published together), the heading and yaw unwrapped along the
 * log, the accelerations; the log's summary. 0, or -1 with err. */
static int make_samples(loader *ld)
{
    sim_log *L = ld->L;
    reader *R = &ld->R;
    long nheli = ld->nheli, nship = ld->nship;
    if (nheli < 2)
        return core_err_set(R->err, -1, "%s: %ld heli_state_t in %ld events: expected the states of a flight (disim fly "
                                        "--log)", R->path, nheli, R->ev);
    if (!(L->s = calloc((size_t)nheli, sizeof *L->s)))
        return core_err_set(R->err, -1, "%s: out of memory", R->path);
    long j = 0;
    for (long i = 0; i < nheli; i++) {
        const disim_heli_state_t *h = &ld->heli[i];
        while (j < nship && ld->ships[j].utime < h->utime)
            j++;
        if (j >= nship || ld->ships[j].utime != h->utime)
            return core_err_set(R->err, -1, "%s: event %ld (%s): no ship_state_t of its utime (%lld us): expected "
                                            "both, as disim fly --log writes them",
                                R->path, (long)ld->heli_ev[i], DISIM_CH_HELI_STATE, (long long)h->utime);
        make_state(h, &ld->ships[j], &L->s[i]);
        L->s[i].n_gear = ld->gears[i].n;
        memcpy(L->s[i].gear_N, ld->gears[i].N, sizeof L->s[i].gear_N);
        if (i > 0) { /* unwrap the heading and the yaw along the log */
            rec_state *a = &L->s[i - 1], *b = &L->s[i];
            b->heading = a->heading + core_wrap_pi(b->heading - a->heading);
            b->euler[2] = a->euler[2] + core_wrap_pi(b->euler[2] - a->euler[2]);
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
    if (ld->n_stations == 1)
        L->info.n_inputs = L->nin;
    else
        L->nin = 0;
    L->info.n_stations = ld->n_stations;
    if (ld->n_stations == 1)
        snprintf(L->info.station, sizeof L->info.station, "%s", ld->st_id);
    return 0;
}

sim_log *sim_log_load(const char *path, core_err *err)
{
    if (!path)
        return core_err_set(err, -1, "replay: expected the path of an LCM log"), NULL;
    loader ld;
    memset(&ld, 0, sizeof ld);
    int rc = open_log(&ld, path, err);
    if (rc == 0)
        rc = read_events(&ld);
    if (rc == 0)
        rc = make_samples(&ld);
    free(ld.heli);
    free(ld.heli_ev);
    free(ld.ships);
    free(ld.gears);
    if (ld.el)
        lcm_eventlog_destroy(ld.el);
    if (rc == 0)
        return ld.L;
    sim_log_destroy(ld.L);
    return NULL;
}

void sim_log_destroy(sim_log *r)
{
    if (!r)
        return;
    free(r->s);
    free(r->in);
    free(r);
}

void sim_log_info(const sim_log *r, sim_log_summary *i) { *i = r->info; }

/* The index k of the last sample with t_k <= t (0 .. n-1). */
static long find(const sim_log *r, double t)
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

static void controls_at(const sim_log *r, double t_s, long k, double ctl[4])
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

int sim_log_sample_at(const sim_log *r, double t_s, sim_log_sample *out)
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
    out->euler_E_rad[2] = core_wrap_pi(out->euler_E_rad[2]);
    for (int i = 0; i < 9; i++)
        out->C_ES[i] = a->C_ES[i] + w * (b->C_ES[i] - a->C_ES[i]);
    out->heading_rad = core_wrap_pi(a->heading + w * (b->heading - a->heading));
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

int sim_log_state_at(const sim_log *r, double t_s, sim_log_state *out)
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
    out->euler_E_rad[2] = core_wrap_pi(out->euler_E_rad[2]);
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

int sim_log_run_info(const sim_log *r, sim_run_info *ri)
{
    if (!r->have_run_info) {
        memset(ri, 0, sizeof *ri);
        return 1;
    }
    *ri = r->run_info;
    return 0;
}


/* ----------------------------------------------------------------- the writer */
struct sim_log_writer {
    char path[SIM_PATH_MAX];
    char tmp[SIM_PATH_MAX + 48];
    lcm_eventlog_t *el;
    long events;
    int failed; /* a write failed: the log is not committed */
    int fail_errno; /* the system's reason for it (EIO where none was given) */
};

/* A new, empty file beside path, created with O_EXCL (no other writer's):
 * 0, or -1 with err. The mode is the umask's, as fopen's. */
static int make_tmp(sim_log_writer *w, core_err *err)
{
    for (int k = 0; k < 100; k++) {
        snprintf(w->tmp, sizeof w->tmp, "%s.tmp%ld.%d", w->path, (long)getpid(), k);
        int fd = open(w->tmp, O_WRONLY | O_CREAT | O_EXCL, 0666);
        if (fd >= 0) {
            close(fd);
            return 0;
        }
        if (errno != EEXIST)
            break;
    }
    core_err_set(err, -1, "%s: cannot write the LCM log (%s)", w->tmp, strerror(errno));
    w->tmp[0] = '\0';
    return -1;
}

sim_log_writer *sim_log_writer_create(const char *path, core_err *err)
{
    if (!path || !*path)
        return core_err_set(err, -1, "log: expected the path of the LCM log to write"), NULL;
    if (strlen(path) >= SIM_PATH_MAX)
        return core_err_set(err, -1, "%s: path too long for the LCM log (at most %d bytes)", path, SIM_PATH_MAX - 1),
               NULL;
    sim_log_writer *w = calloc(1, sizeof *w);
    if (!w)
        return core_err_set(err, -1, "%s: out of memory", path), NULL;
    snprintf(w->path, sizeof w->path, "%s", path);
    if (make_tmp(w, err) != 0) {
        free(w);
        return NULL;
    }
    if (!(w->el = lcm_eventlog_create(w->tmp, "w"))) {
        core_err_set(err, -1, "%s: cannot write the LCM log", w->tmp);
        sim_log_writer_destroy(w);
        return NULL;
    }
    return w;
}

int sim_log_writer_write(sim_log_writer *w, const char *channel, int64_t utime_us, const void *data, int size,
                         core_err *err)
{
    if (!w->el)
        return core_err_set(err, -1, "%s: the LCM log is closed (committed, or its commit failed)", w->path);
    if (w->failed)
        return core_err_set(err, -1, "%s: cannot write the LCM log (an earlier write failed: %s)", w->path,
                            strerror(w->fail_errno));
    size_t chlen = channel ? strlen(channel) : 0;
    if (chlen == 0 || chlen >= 256 || size < 0 || (size > 0 && !data))
        return core_err_set(err, -1, "%s: an event on channel '%s' of %d bytes: expected a channel of 1 to 255 "
                                     "characters and the data", w->tmp, channel ? channel : "", size);
    lcm_eventlog_event_t ev;
    memset(&ev, 0, sizeof ev);
    ev.timestamp = utime_us;
    ev.channellen = (int32_t)chlen;
    ev.datalen = size;
    ev.channel = (char *)channel;
    ev.data = (void *)data;
    errno = 0;
    if (lcm_eventlog_write_event(w->el, &ev) != 0 || ferror(w->el->f)) {
        w->failed = 1;
        w->fail_errno = errno ? errno : EIO;
        return core_err_set(err, -1, "%s: cannot write the LCM log (%s; nothing will be written there)", w->path,
                            strerror(w->fail_errno));
    }
    w->events++;
    return 0;
}

long sim_log_writer_events(const sim_log_writer *w) { return w->events; }

int sim_log_writer_commit(sim_log_writer *w, core_err *err)
{
    if (!w->el)
        return core_err_set(err, -1, "%s: the LCM log is closed (committed, or its commit failed)", w->path);
    FILE *f = w->el->f;
    int e = w->failed ? w->fail_errno : 0;
    errno = 0;
    if (!e && (fflush(f) != 0 || ferror(f) || fsync(fileno(f)) != 0))
        e = errno ? errno : EIO;
    lcm_eventlog_destroy(w->el);
    w->el = NULL;
    errno = 0;
    if (!e && rename(w->tmp, w->path) != 0)
        e = errno ? errno : EIO;
    if (e) {
        unlink(w->tmp);
        w->tmp[0] = '\0';
        return core_err_set(err, -1, "%s: cannot write the LCM log (%s; nothing written)", w->path, strerror(e));
    }
    w->tmp[0] = '\0';
    return 0;
}

void sim_log_writer_destroy(sim_log_writer *w)
{
    if (!w)
        return;
    if (w->el)
        lcm_eventlog_destroy(w->el);
    if (w->tmp[0])
        unlink(w->tmp);
    free(w);
}
