/* station_auto.c -- the automated pilot as an external station,
 * `disim station --auto TASK.ini`: a process of its own beside the flight
 * loop that flies the task file with the automated pilot (sim/pilot_auto.c)
 * on the states the loop publishes.
 *
 * What it reads: heli_state_t (DISIM_HELI_STATE), ship_state_t
 * (DISIM_SHIP_STATE), run_info_t (DISIM_RUN_INFO: the aircraft, the ship,
 * the WOD the gains are scheduled at, the state rate) and sim_status_t
 * (DISIM_SIM_STATUS: whether the flight's SAS is engaged), each buffer
 * checked with disim_lcm_check_raw before it is decoded (a bad one is
 * counted, never used). The aircraft and ship come from the caller's paths
 * (a scenario) when given, else from run_info_t.
 *
 * The start. The pilot flies its task from the task's first point, as
 * `disim fly --pilot auto` starts there: when the flight is not within
 * START_TOL_M of it (or no run_info_t has been seen), the station sends one
 * sim_control_t REPOSITION to it, and the loop starts the hover there
 * again (and publishes run_info_t again). The first state there, paired
 * with the ship's state of the same time, is the pilot's start: its
 * controls are the pilot's trim inputs (the pilot starts from the flown
 * controls), its attitudes relative to S the attitude references
 * (sim_pilot_auto_set_trim_state), its utime the pilot's time 0.
 *
 * Each step. One pilot step per state received, at the state rate of
 * run_info_t (the pilot's rate_hz: its delay and filters count in
 * states): the state's heli_state_t and the ship_state_t of the same utime
 * are rebuilt into the sim_flight_out the pilot reads (time, position and
 * velocity relative to the deck in S, the Euler attitudes and body rates,
 * the flown controls, on_deck, the ship's frame from its origin and
 * quaternion), and the pilot's controls go out at once as pilot_input_t,
 * absolute controls (the loop blends them in over 1 s when this station
 * takes over; the first message sets take_over). A state whose ship state
 * did not come is flown with the latest ship state.
 *
 * The end: the task done (settled on the deck, or its last hold flown),
 * duration_s after the start, *stop set, or a flight that starts again
 * (a state's utime going back: a reset) all end the run; no state for
 * wait_s ends it with an error. */
#include "sim.h"

#include "disim_lcm.h"

#include <errno.h>
#include <lcm/lcm.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define START_TOL_M 0.5 /* the flight is at the task's start within this */

typedef struct auto_st {
    const sim_station_auto_opts *o;
    lcm_t *lc;
    core_err err;
    int failed;
    /* what was received */
    disim_heli_state_t heli;      /* the latest (scalars only: the gear loads dropped) */
    int have_heli, pending;       /* pending: a state not yet flown */
    disim_ship_state_t ship;
    int have_ship;
    int have_info, have_status, sas;
    long info_rx;                 /* run_info_t received */
    double wod_speed_mps, wod_dir_rad, state_rate_hz;
    char aircraft_path[SIM_PATH_MAX], ship_path[SIM_PATH_MAX];
    /* the start */
    sim_task task;
    double start_S_m[3];
    long info_at_reposition;      /* info_rx when the REPOSITION went (-1: none sent) */
    double t_reposition_s;        /* its wall time */
    /* the flight */
    hfm_aircraft *ac;
    sim_pilot_auto *p;
    int64_t utime0, utime_last;
    int64_t seq;
    sim_station_auto_stats *s;
    int done;
} auto_st;

static double wall_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The state's heli and ship messages as the flight's output the pilot reads. */
static void rebuild_out(const disim_heli_state_t *h, const disim_ship_state_t *sh, int64_t utime0,
                        sim_flight_out *out)
{
    memset(out, 0, sizeof *out);
    out->t_s = 1e-6 * (double)(h->utime - utime0);
    for (int i = 0; i < 3; i++) {
        out->pos_E_m[i] = h->pos_E_m[i];
        out->vel_E_mps[i] = h->vel_E_mps[i];
        out->pos_S_m[i] = h->pos_S_m[i];
        out->vel_S_mps[i] = h->vel_S_mps[i];
        out->rate_B_radps[i] = h->rates_B_radps[i];
        out->ship.origin_E_m[i] = sh->pos_E_m[i];
        out->ship.mean_vel_E_mps[i] = sh->vel_E_mps[i];
    }
    out->euler_E_rad[0] = h->roll_rad;
    out->euler_E_rad[1] = h->pitch_rad;
    out->euler_E_rad[2] = h->yaw_rad;
    out->ctl.collective_pct = h->collective_pct;
    out->ctl.long_cyclic_pct = h->long_cyclic_pct;
    out->ctl.lat_cyclic_pct = h->lat_cyclic_pct;
    out->ctl.pedal_pct = h->pedal_pct;
    out->on_deck = h->on_deck != 0;
    out->nlegs = h->n_gear;
    /* C_ES (row-major, S -> E): column j is S's axis j in E */
    core_quat q = core_quat_normalize((core_quat){sh->quat_ES[0], sh->quat_ES[1], sh->quat_ES[2], sh->quat_ES[3]});
    for (int j = 0; j < 3; j++) {
        core_vec3 e = {j == 0, j == 1, j == 2};
        core_vec3 c = core_quat_rotate(q, e);
        out->ship.C_ES[0 * 3 + j] = c.x;
        out->ship.C_ES[1 * 3 + j] = c.y;
        out->ship.C_ES[2 * 3 + j] = c.z;
    }
}

static int publish_input(auto_st *a, int64_t utime, const sim_flight_inputs *in)
{
    disim_pilot_input_t m;
    memset(&m, 0, sizeof m);
    m.utime = utime;
    m.station_id = (char *)a->o->id;
    m.seq = a->seq;
    m.collective_pct = fmin(fmax(in->ctl.collective_pct, 0.0), 100.0);
    m.long_cyclic_pct = fmin(fmax(in->ctl.long_cyclic_pct, 0.0), 100.0);
    m.lat_cyclic_pct = fmin(fmax(in->ctl.lat_cyclic_pct, 0.0), 100.0);
    m.pedal_pct = fmin(fmax(in->ctl.pedal_pct, 0.0), 100.0);
    m.take_over = a->seq == 0;
    if (disim_pilot_input_t_publish(a->lc, DISIM_CH_PILOT_INPUT, &m) != 0)
        return core_err_set(&a->err, -1, "LCM: publishing on %s failed", DISIM_CH_PILOT_INPUT);
    a->seq++;
    a->s->published++;
    return 0;
}

/* Fly the pending state with the ship state held. */
static void fly_state(auto_st *a)
{
    if (!a->p)
        return; /* the start's state: get_ready takes it */
    a->pending = 0;
    if (a->done || a->failed)
        return;
    if (a->heli.utime < a->utime_last) {
        a->done = 1; /* the flight started again (a reset) */
        a->s->reset = 1;
        return;
    }
    a->utime_last = a->heli.utime;
    sim_flight_out out;
    rebuild_out(&a->heli, &a->ship, a->utime0, &out);
    sim_flight_inputs in;
    sim_pilot_auto_step(a->p, &out, &in);
    a->s->steps++;
    a->s->t_s = out.t_s;
    if (a->ship.utime != a->heli.utime)
        a->s->unpaired++;
    if (publish_input(a, a->heli.utime, &in) != 0)
        a->failed = 1;
    sim_task_result r;
    sim_pilot_auto_result(a->p, &r);
    if (r.done)
        a->done = 1;
}

static void rx_heli(auto_st *a, const void *buf, int size)
{
    disim_heli_state_t m;
    memset(&m, 0, sizeof m);
    if (disim_heli_state_t_decode(buf, 0, size, &m) < 0) {
        a->s->bad_rx++;
        return;
    }
    if (disim_lcm_check_heli_state(&m, NULL, 0) != 0) {
        a->s->bad_rx++;
    } else {
        if (a->pending && a->p)
            fly_state(a); /* its ship state never came: flown with the latest */
        a->heli = m;
        a->heli.gear_load_N = NULL;
        a->have_heli = a->pending = 1;
        a->s->heli_rx++;
        if (a->have_ship && a->ship.utime == m.utime)
            fly_state(a);
    }
    disim_heli_state_t_decode_cleanup(&m);
}

static void rx_ship(auto_st *a, const void *buf, int size)
{
    disim_ship_state_t m;
    memset(&m, 0, sizeof m);
    if (disim_ship_state_t_decode(buf, 0, size, &m) < 0) {
        a->s->bad_rx++;
        return;
    }
    if (disim_lcm_check_ship_state(&m, NULL, 0) != 0) {
        a->s->bad_rx++;
    } else {
        a->ship = m;
        a->have_ship = 1;
        if (a->pending && a->heli.utime == m.utime)
            fly_state(a);
    }
    disim_ship_state_t_decode_cleanup(&m);
}

static void rx_info(auto_st *a, const void *buf, int size)
{
    disim_run_info_t m;
    memset(&m, 0, sizeof m);
    if (disim_run_info_t_decode(buf, 0, size, &m) < 0) {
        a->s->bad_rx++;
        return;
    }
    if (!(m.wod_speed_mps >= 0.0) || !isfinite(m.wod_dir_rad) || !(m.state_rate_hz >= 10.0) ||
        !(m.state_rate_hz <= 10000.0)) {
        a->s->bad_rx++; /* the pilot flies at 10 Hz or more */
    } else {
        a->have_info = 1;
        a->info_rx++;
        a->wod_speed_mps = m.wod_speed_mps;
        a->wod_dir_rad = m.wod_dir_rad;
        a->state_rate_hz = m.state_rate_hz;
        if (!a->o->aircraft_path) {
            snprintf(a->aircraft_path, sizeof a->aircraft_path, "%s", m.aircraft_path);
            snprintf(a->ship_path, sizeof a->ship_path, "%s", m.ship_path);
        }
    }
    disim_run_info_t_decode_cleanup(&m);
}

static void rx_status(auto_st *a, const void *buf, int size)
{
    disim_sim_status_t m;
    memset(&m, 0, sizeof m);
    if (disim_sim_status_t_decode(buf, 0, size, &m) < 0) {
        a->s->bad_rx++;
        return;
    }
    if (m.flags & (DISIM_SIM_STATUS_T_FLAG_SAS | DISIM_SIM_STATUS_T_FLAG_SAS_OFF)) {
        a->have_status = 1;
        a->sas = (m.flags & DISIM_SIM_STATUS_T_FLAG_SAS) != 0;
    }
    /* the REPOSITION's answer: a refusal ends the run, saying why */
    if (a->info_at_reposition >= 0 && !a->p && !a->failed && m.control_seq == 0 &&
        m.control_command == DISIM_SIM_CONTROL_T_REPOSITION &&
        m.control_result == DISIM_SIM_STATUS_T_CONTROL_REFUSED) {
        core_err_set(&a->err, -1, "station --auto: the loop refused the REPOSITION to the task's start: %s",
                     m.control_message ? m.control_message : "");
        a->failed = 1;
    }
    disim_sim_status_t_decode_cleanup(&m);
}

static void on_raw(const lcm_recv_buf_t *rb, const char *ch, void *user)
{
    auto_st *a = user;
    static const struct {
        const char *ch, *type;
        void (*rx)(auto_st *, const void *, int);
    } t[] = {{DISIM_CH_HELI_STATE, "heli_state_t", rx_heli},
             {DISIM_CH_SHIP_STATE, "ship_state_t", rx_ship},
             {DISIM_CH_RUN_INFO, "run_info_t", rx_info},
             {DISIM_CH_SIM_STATUS, "sim_status_t", rx_status}};
    for (size_t i = 0; i < sizeof t / sizeof t[0]; i++)
        if (!strcmp(ch, t[i].ch)) {
            char why[200];
            if (disim_lcm_check_raw(t[i].type, rb->data, (int)rb->data_size, why, sizeof why) != 0)
                a->s->bad_rx++;
            else
                t[i].rx(a, rb->data, (int)rb->data_size);
            return;
        }
}

static int send_reposition(auto_st *a)
{
    disim_sim_control_t c;
    memset(&c, 0, sizeof c);
    c.command = DISIM_SIM_CONTROL_T_REPOSITION;
    c.scenario_path = (char *)"";
    c.name = (char *)"";
    memcpy(c.pos_S_m, a->start_S_m, sizeof c.pos_S_m);
    c.utime = a->have_heli ? a->heli.utime : 0;
    if (disim_sim_control_t_publish(a->lc, DISIM_CH_SIM_CONTROL, &c) != 0)
        return core_err_set(&a->err, -1, "LCM: publishing on %s failed", DISIM_CH_SIM_CONTROL);
    a->info_at_reposition = a->info_rx;
    a->s->repositioned = 1;
    a->t_reposition_s = wall_s();
    return 0;
}

static int at_start(const auto_st *a)
{
    double d = 0.0;
    for (int i = 0; i < 3; i++)
        d += (a->heli.pos_S_m[i] - a->start_S_m[i]) * (a->heli.pos_S_m[i] - a->start_S_m[i]);
    return sqrt(d) <= START_TOL_M;
}

/* The aircraft and the task once the paths are known. 0, or -1 with err. */
static int load_world(auto_st *a)
{
    core_ship ship;
    if (core_ship_load(a->ship_path, &ship, &a->err) != 0)
        return -1;
    if (sim_task_load_ship(a->o->task_path, &ship, &a->task, &a->err) != 0 ||
        sim_task_start_S(a->o->task_path, &ship, a->start_S_m, &a->err) != 0)
        return -1;
    if (!(a->ac = hfm_aircraft_load(a->aircraft_path, a->o->log, &a->err)))
        return -1;
    memcpy(a->s->start_S_m, a->start_S_m, sizeof a->start_S_m);
    return 0;
}

/* The pilot from the state at the start. 0, or -1 with err. */
static int start_pilot(auto_st *a)
{
    sim_pilot_auto_opts po;
    sim_pilot_auto_opts_default(&po);
    po.rate_hz = a->state_rate_hz;
    po.wod_speed_mps = a->wod_speed_mps;
    po.wod_dir_rad = a->wod_dir_rad;
    po.sas = a->sas;
    hfm_gear gear;
    po.gear = a->heli.n_gear > 0 && hfm_aircraft_gear(a->ac, &gear) == 0 && gear.nlegs > 0;
    sim_flight_out out;
    rebuild_out(&a->heli, &a->ship, a->heli.utime, &out);
    sim_flight_inputs in;
    memset(&in, 0, sizeof in);
    in.ctl = out.ctl;
    if (!(a->p = sim_pilot_auto_create(a->ac, &a->task, &po, &in, a->o->log, &a->err)))
        return -1;
    if (sim_pilot_auto_set_trim_state(a->p, &out) != 0)
        return core_err_set(&a->err, -1, "station --auto: the flight at the task's start is not a hover");
    a->utime0 = a->utime_last = a->heli.utime;
    a->s->rate_hz = po.rate_hz;
    a->s->sas = po.sas;
    a->s->gear = po.gear;
    a->pending = 1; /* the start's state is the pilot's first */
    fly_state(a);
    return 0;
}

/* Before the pilot flies: the world known, the flight at the task's start
 * (a REPOSITION sent once when it is not). 0 not yet, 1 started, -1 err. */
static int get_ready(auto_st *a)
{
    int paths = a->aircraft_path[0] && a->ship_path[0];
    if (!paths || !a->have_heli || !a->have_ship || !a->have_status)
        return 0;
    if (!a->ac && load_world(a) != 0)
        return -1;
    if (a->info_at_reposition < 0) {
        if (a->have_info && at_start(a))
            return a->pending && a->ship.utime == a->heli.utime ? (start_pilot(a) == 0 ? 1 : -1) : 0;
        return send_reposition(a) == 0 ? 0 : -1;
    }
    /* after the REPOSITION: the new run's info, then a state at the start */
    if (a->info_rx <= a->info_at_reposition || !at_start(a) || !a->pending || a->ship.utime != a->heli.utime)
        return 0;
    return start_pilot(a) == 0 ? 1 : -1;
}

static int open_lcm(auto_st *a)
{
    if (!(a->lc = lcm_create(disim_lcm_url(a->o->lcm_url))))
        return core_err_set(&a->err, -1,
                            "LCM '%s': cannot create (a bad URL, or no multicast route: see docs/conventions.md, LCM)",
                            a->o->lcm_url ? a->o->lcm_url : "(default)");
    const char *ch[] = {DISIM_CH_HELI_STATE, DISIM_CH_SHIP_STATE, DISIM_CH_RUN_INFO, DISIM_CH_SIM_STATUS};
    for (int i = 0; i < 4; i++)
        if (!lcm_subscribe(a->lc, ch[i], on_raw, a))
            return core_err_set(&a->err, -1, "LCM: cannot subscribe to %s", ch[i]);
    return 0;
}

int sim_station_auto_run(const sim_station_auto_opts *o, sim_station_auto_stats *s, sim_task_result *r,
                         core_err *err)
{
    memset(s, 0, sizeof *s);
    memset(r, 0, sizeof *r);
    if (!o || !o->task_path || sim_station_id_check(o->id, err) != 0)
        return o && o->task_path ? -1 : core_err_set(err, -1, "station --auto: expected a task file");
    if (!(o->wait_s > 0.0))
        return core_err_set(err, -1, "station --auto: wait_s %g: expected > 0", o->wait_s);
    FILE *tf = fopen(o->task_path, "r"); /* read once the ship is known: said missing now */
    if (!tf)
        return core_err_set(err, -1, "%s: %s", o->task_path, strerror(errno));
    fclose(tf);
    auto_st *a = calloc(1, sizeof *a);
    if (!a)
        return core_err_set(err, -1, "station --auto: out of memory");
    a->o = o;
    a->s = s;
    a->info_at_reposition = -1;
    if (o->aircraft_path) {
        snprintf(a->aircraft_path, sizeof a->aircraft_path, "%s", o->aircraft_path);
        snprintf(a->ship_path, sizeof a->ship_path, "%s", o->ship_path ? o->ship_path : "");
    }
    int rc = open_lcm(a);
    double t_last = wall_s(), t_begin = t_last;
    long heli_seen = 0;
    while (rc == 0 && !a->done && !a->failed && !(o->stop && *o->stop)) {
        lcm_handle_timeout(a->lc, 50);
        if (a->failed)
            break;
        if (!a->p && get_ready(a) < 0)
            rc = -1;
        double now = wall_s();
        if (s->heli_rx != heli_seen)
            heli_seen = s->heli_rx, t_last = now;
        if (rc == 0 && now - t_last > o->wait_s)
            rc = core_err_set(&a->err, -1, "station --auto: no %s on %s within %g s",
                              a->p ? "state" : "heli_state_t", DISIM_CH_HELI_STATE, o->wait_s);
        if (rc == 0 && !a->p && !(a->aircraft_path[0] && a->ship_path[0]) && now - t_begin > o->wait_s)
            rc = core_err_set(&a->err, -1, "station --auto: no run_info_t on %s within %g s (start the station "
                              "before disim fly, or give the scenario)", DISIM_CH_RUN_INFO, o->wait_s);
        if (rc == 0 && !a->p && a->info_at_reposition >= 0 && now - a->t_reposition_s > o->wait_s)
            rc = core_err_set(&a->err, -1, "station --auto: the flight was not at the task's start (%.2f, %.2f, %.2f) "
                              "m in S within %g s of the REPOSITION", a->start_S_m[0], a->start_S_m[1],
                              a->start_S_m[2], o->wait_s);
        if (a->p && o->duration_s > 0.0 && s->t_s >= o->duration_s)
            break;
    }
    if (a->failed)
        rc = -1;
    if (rc != 0)
        *err = a->err;
    if (a->p)
        sim_pilot_auto_result(a->p, r);
    s->started = a->p != NULL;
    sim_pilot_auto_destroy(a->p);
    hfm_aircraft_destroy(a->ac);
    if (a->lc)
        lcm_destroy(a->lc);
    free(a);
    return rc;
}
