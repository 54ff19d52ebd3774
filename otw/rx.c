/* rx.c -- the view's receive thread: heli_state_t, ship_state_t,
 * sim_status_t and run_info_t on an LCM instance of its own, each buffer
 * checked (disim_lcm_check_raw) before it is decoded and its values
 * checked finite; a refused message is counted, never drawn.
 *
 * A state is the heli_state_t and the ship_state_t of one step of the loop
 * (the same utime; the loop sends the helicopter's first). It is posted to
 * the mailbox when the second of the pair arrives, stamped with the
 * arrival of the first (CLOCK_MONOTONIC, taken as the handler runs). When
 * one stream runs ahead of the other by more than 0.1 s (a publisher of
 * one kind only, a lost message) each message is posted with the newest
 * of the other kind. */
#include "otw_priv.h"

#include "disim_lcm.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PAIR_SLACK_US 100000

static void refuse(otw *w, const char *ch, const char *why)
{
    pthread_mutex_lock(&w->mu);
    w->bad_rx++;
    snprintf(w->bad_last, sizeof w->bad_last, "%s: %s", ch, why);
    pthread_mutex_unlock(&w->mu);
}

static core_quat quat(const double q[4])
{
    core_quat r = {q[0], q[1], q[2], q[3]};
    return core_quat_normalize(r);
}

/* Post w->next if the pair is complete (or one stream is far ahead);
 * under mu. */
static void post(otw *w, otw_part *mine, otw_part *other)
{
    if (!other->have)
        return;
    int64_t d = mine->utime - other->utime;
    if (d != 0 && d < PAIR_SLACK_US && d > -PAIR_SLACK_US)
        return; /* the other of this step is still to come */
    double arrival = mine->arrival_s;
    if (d == 0 && !other->posted && other->arrival_s < arrival)
        arrival = other->arrival_s;
    w->slot = w->next;
    w->slot.flags = w->status_flags;
    w->slot_arrival_s = arrival;
    w->slot_seq++;
    w->states++;
    mine->posted = 1;
    if (d == 0)
        other->posted = 1;
    pthread_cond_broadcast(&w->cv);
}

static void rx_heli(otw *w, const char *ch, const void *buf, int size, double now)
{
    char e[200];
    if (disim_lcm_check_raw("heli_state_t", buf, size, e, sizeof e) != 0) {
        refuse(w, ch, e);
        return;
    }
    disim_heli_state_t m;
    memset(&m, 0, sizeof m);
    if (disim_heli_state_t_decode(buf, 0, size, &m) != size) {
        refuse(w, ch, "heli_state_t: cannot decode");
        return;
    }
    if (disim_lcm_check_heli_state(&m, e, sizeof e) != 0) {
        refuse(w, ch, e);
        disim_heli_state_t_decode_cleanup(&m);
        return;
    }
    double ctl[5] = {m.collective_pct, m.long_cyclic_pct, m.lat_cyclic_pct, m.pedal_pct, m.rotor_thrust_N};
    pthread_mutex_lock(&w->mu);
    render_state *s = &w->next;
    s->t_s = 1e-6 * (double)m.utime;
    s->have_heli = 1;
    s->heli.pos_E_m = core_vec3_make(m.pos_E_m[0], m.pos_E_m[1], m.pos_E_m[2]);
    s->heli.q_EF = quat(m.quat_EB);
    memcpy(s->pos_S_m, m.pos_S_m, sizeof s->pos_S_m);
    memcpy(s->vel_S_mps, m.vel_S_mps, sizeof s->vel_S_mps);
    s->roll_rad = m.roll_rad, s->pitch_rad = m.pitch_rad, s->yaw_rad = m.yaw_rad;
    memcpy(s->controls_pct, ctl, sizeof s->controls_pct);
    s->rotor_thrust_N = m.rotor_thrust_N;
    s->on_deck = m.on_deck != 0;
    s->n_gear = m.n_gear < RENDER_MAX_LEGS ? m.n_gear : RENDER_MAX_LEGS;
    for (int i = 0; i < s->n_gear; i++)
        s->gear_load_N[i] = m.gear_load_N[i];
    w->heli = (otw_part){1, m.utime, now, 0};
    post(w, &w->heli, &w->ship);
    pthread_mutex_unlock(&w->mu);
    disim_heli_state_t_decode_cleanup(&m);
}

static void rx_ship(otw *w, const char *ch, const void *buf, int size, double now)
{
    char e[200];
    if (disim_lcm_check_raw("ship_state_t", buf, size, e, sizeof e) != 0) {
        refuse(w, ch, e);
        return;
    }
    disim_ship_state_t m;
    memset(&m, 0, sizeof m);
    if (disim_ship_state_t_decode(buf, 0, size, &m) != size) {
        refuse(w, ch, "ship_state_t: cannot decode");
        return;
    }
    if (disim_lcm_check_ship_state(&m, e, sizeof e) != 0) {
        refuse(w, ch, e);
        disim_ship_state_t_decode_cleanup(&m);
        return;
    }
    pthread_mutex_lock(&w->mu);
    render_state *s = &w->next;
    s->ship.pos_E_m = core_vec3_make(m.pos_E_m[0], m.pos_E_m[1], m.pos_E_m[2]);
    s->ship.q_EF = quat(m.quat_ES);
    s->ship_yaw_rad = m.yaw_rad;
    w->ship = (otw_part){1, m.utime, now, 0};
    post(w, &w->ship, &w->heli);
    pthread_mutex_unlock(&w->mu);
    disim_ship_state_t_decode_cleanup(&m);
}

static void rx_status(otw *w, const char *ch, const void *buf, int size)
{
    char e[200];
    if (disim_lcm_check_raw("sim_status_t", buf, size, e, sizeof e) != 0) {
        refuse(w, ch, e);
        return;
    }
    disim_sim_status_t m;
    memset(&m, 0, sizeof m);
    if (disim_sim_status_t_decode(buf, 0, size, &m) != size) {
        refuse(w, ch, "sim_status_t: cannot decode");
        return;
    }
    pthread_mutex_lock(&w->mu);
    w->status_flags = (unsigned)m.flags;
    pthread_mutex_unlock(&w->mu);
    disim_sim_status_t_decode_cleanup(&m);
}

/* A run_info_t into w->run_info (the drawing thread opens its scene). */
static void rx_run_info(otw *w, const char *ch, const void *buf, int size)
{
    char e[200];
    if (disim_lcm_check_raw("run_info_t", buf, size, e, sizeof e) != 0) {
        refuse(w, ch, e);
        return;
    }
    disim_run_info_t m;
    memset(&m, 0, sizeof m);
    if (disim_run_info_t_decode(buf, 0, size, &m) != size) {
        refuse(w, ch, "run_info_t: cannot decode");
        return;
    }
    if (strlen(m.aircraft_path) >= SIM_PATH_MAX || strlen(m.ship_path) >= SIM_PATH_MAX ||
        strlen(m.scenario_path) >= SIM_PATH_MAX || m.seed < 0 || m.sea_state < 0 || m.sea_state > SIM_SEA_MAX_STATE ||
        m.spectrum < 0 || m.spectrum > 1 || m.n_waves < 0 || m.n_waves > SIM_SEA_MAX_WAVES ||
        !(isfinite(m.ship_speed_mps) && fabs(m.wave_dir_rad) <= 10.0 && fabs(m.course_rad) <= 10.0 &&
          isfinite(m.wod_speed_mps) && fabs(m.wod_dir_rad) <= 10.0)) {
        refuse(w, ch, "run_info_t: a path too long or the sea out of range");
        disim_run_info_t_decode_cleanup(&m);
        return;
    }
    sim_run_info ri;
    memset(&ri, 0, sizeof ri);
    snprintf(ri.scenario_path, sizeof ri.scenario_path, "%s", m.scenario_path);
    snprintf(ri.scenario, sizeof ri.scenario, "%s", m.scenario);
    snprintf(ri.aircraft_path, sizeof ri.aircraft_path, "%s", m.aircraft_path);
    snprintf(ri.ship_path, sizeof ri.ship_path, "%s", m.ship_path);
    ri.seed = (unsigned long long)m.seed;
    sim_sea_default(&ri.sea);
    ri.sea.state = m.sea_state;
    ri.sea.ship_speed_mps = m.ship_speed_mps;
    ri.sea.wave_dir_rad = m.wave_dir_rad;
    ri.sea.course_rad = m.course_rad;
    ri.sea.spectrum = m.spectrum ? SIM_SPECTRUM_JONSWAP : SIM_SPECTRUM_ITTC;
    ri.sea.n_waves = m.n_waves;
    ri.wod_speed_mps = m.wod_speed_mps;
    ri.wod_dir_rad = m.wod_dir_rad;
    ri.rate_hz = m.rate_hz;
    ri.state_rate_hz = m.state_rate_hz;
    pthread_mutex_lock(&w->mu);
    w->run_info = ri;
    w->run_info_seq++;
    pthread_cond_broadcast(&w->cv);
    pthread_mutex_unlock(&w->mu);
    disim_run_info_t_decode_cleanup(&m);
}

static void on_raw(const lcm_recv_buf_t *rb, const char *ch, void *user)
{
    double now = core_monotonic_s();
    otw *w = user;
    int size = (int)rb->data_size;
    if (!strcmp(ch, DISIM_CH_HELI_STATE))
        rx_heli(w, ch, rb->data, size, now);
    else if (!strcmp(ch, DISIM_CH_SHIP_STATE))
        rx_ship(w, ch, rb->data, size, now);
    else if (!strcmp(ch, DISIM_CH_SIM_STATUS))
        rx_status(w, ch, rb->data, size);
    else if (!strcmp(ch, DISIM_CH_RUN_INFO))
        rx_run_info(w, ch, rb->data, size);
}

static void *rx_main(void *arg)
{
    otw *w = arg;
    while (!atomic_load(&w->stop))
        lcm_handle_timeout(w->lc, 50);
    return NULL;
}

int otw_rx_start(otw *w, core_err *err)
{
    w->lc = lcm_create(disim_lcm_url(w->o.lcm_url));
    if (!w->lc)
        return core_err_set(err, -1,
                            "view: LCM '%s': cannot create (a bad URL, or no multicast route: see docs/conventions.md, LCM)",
                            w->o.lcm_url ? w->o.lcm_url : "(default)");
    const char *ch[] = {DISIM_CH_HELI_STATE, DISIM_CH_SHIP_STATE, DISIM_CH_SIM_STATUS, DISIM_CH_RUN_INFO};
    for (size_t i = 0; i < sizeof ch / sizeof ch[0]; i++)
        if (!lcm_subscribe(w->lc, ch[i], on_raw, w))
            return core_err_set(err, -1, "view: LCM: cannot subscribe to %s", ch[i]);
    if (pthread_create(&w->rx_th, NULL, rx_main, w) != 0)
        return core_err_set(err, -1, "view: cannot start the receive thread");
    w->rx_started = 1;
    return 0;
}

void otw_rx_stop(otw *w)
{
    atomic_store(&w->stop, 1);
    if (w->rx_started)
        pthread_join(w->rx_th, NULL);
    w->rx_started = 0;
    if (w->lc)
        lcm_destroy(w->lc);
    w->lc = NULL;
}
