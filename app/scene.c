/* scene.c -- what `disim render LOG` and `disim fly --render` draw: a run's
 * ship, aircraft and seaway as a render_scene, the airwake flown for the
 * overlay, and the flight's or the log's states as render_states.
 *
 * The seaway drawn is its own sim_ship_motion, built from the run's ship,
 * sea and seed as the flight's is (sim_world_seaway), so it is the sea
 * the ship moved in and never the flight's motion object (whose
 * step cache is not for two threads). A log's ship states are checked
 * against it (app_scene_check_log): a log whose ship does not move as the
 * rebuilt seaway says (another ship file, an edited scenario) is drawn on
 * a flat sea with a warning, never on a sea that disagrees with its ship. */
#include "scene.h"
#include "disim_lcm.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The airwake overlay's render_air_fn: the mean air in S (no gusts). */
static int scene_air(void *user, const double p_S_m[3], double v_S_mps[3])
{
    return sim_air_mean_S(user, p_S_m, 0.0, v_S_mps, NULL, NULL) == 1 ? 1 : 0;
}

int app_scene_open(app_scene *s, const sim_run_info *ri, unsigned overlays, const core_log *log, core_err *err)
{
    memset(s, 0, sizeof *s);
    if (sim_run_scene_open(&s->run, ri, log, err) != 0)
        return -1;
    render_scene *sc = &s->scene;
    sc->ship = &s->run.ship;
    sc->heli = &s->run.geom;
    sc->sea = sim_ship_motion_elevation;
    sc->sea_user = s->run.sea;
    sc->overlays = overlays;
    sc->title = s->run.name;
    sc->air_ref_mps = ri->wod_speed_mps > 0.5 ? ri->wod_speed_mps : 1.0;
    return 0;
}

int app_scene_set_field(app_scene *s, struct cfd_field *field, core_err *err)
{
    sim_air_opts ao;
    sim_air_opts_default(&ao);
    ao.wod_speed_mps = s->run.info.wod_speed_mps;
    ao.wod_dir_rad = s->run.info.wod_dir_rad;
    ao.deck_height_m = s->run.ship.deck_height_m;
    sim_air_destroy(s->air);
    if (!(s->air = sim_air_create(&ao, err)) || sim_air_set_field(s->air, field, -1e9, err) != 0)
        return -1;
    s->field = field;
    s->scene.air = scene_air;
    s->scene.air_user = s->air;
    return 0;
}

void app_scene_close(app_scene *s)
{
    sim_air_destroy(s->air);
    cfd_field_destroy(s->field);
    sim_run_scene_close(&s->run);
    memset(s, 0, sizeof *s);
}

static void pose_from(core_pose *p, const double pos[3], core_quat q)
{
    p->pos_E_m = core_vec3_make(pos[0], pos[1], pos[2]);
    p->q_EF = q;
}

void app_render_state_from_flight(const app_scene *s, const sim_flight_out *o, render_state *rs)
{
    memset(rs, 0, sizeof *rs);
    rs->t_s = o->t_s;
    /* the ship frame the flight flew (no second sum of the seaway) */
    core_mat3 C;
    memcpy(C.m, o->ship.C_ES, sizeof C.m);
    core_euler a = core_mat3_to_euler(C);
    pose_from(&rs->ship, o->ship.origin_E_m, core_quat_from_euler(a));
    rs->ship_yaw_rad = a.psi_rad;
    rs->have_heli = 1;
    core_euler e = {o->euler_E_rad[0], o->euler_E_rad[1], o->euler_E_rad[2]};
    pose_from(&rs->heli, o->pos_E_m, core_quat_from_euler(e));
    memcpy(rs->pos_S_m, o->pos_S_m, sizeof rs->pos_S_m);
    memcpy(rs->vel_S_mps, o->vel_S_mps, sizeof rs->vel_S_mps);
    rs->roll_rad = e.phi_rad, rs->pitch_rad = e.theta_rad, rs->yaw_rad = e.psi_rad;
    rs->controls_pct[0] = o->ctl.collective_pct, rs->controls_pct[1] = o->ctl.long_cyclic_pct;
    rs->controls_pct[2] = o->ctl.lat_cyclic_pct, rs->controls_pct[3] = o->ctl.pedal_pct;
    rs->rotor_thrust_N = o->rotor_thrust_N;
    rs->on_deck = o->on_deck;
    rs->n_gear = o->nlegs < RENDER_MAX_LEGS ? o->nlegs : RENDER_MAX_LEGS;
    for (int i = 0; i < rs->n_gear; i++)
        rs->gear_load_N[i] = o->gear_load_N[i];
    rs->rotor_azimuth_rad = render_rotor_azimuth(&s->run.geom, o->t_s);
    rs->flags = (o->on_deck ? (unsigned)DISIM_SIM_STATUS_T_FLAG_ON_DECK : 0u) |
                (o->contact_flags & SIM_CONTACT_SLIDE ? (unsigned)DISIM_SIM_STATUS_T_FLAG_SLIDE : 0u) |
                (o->contact_flags & SIM_CONTACT_TIP ? (unsigned)DISIM_SIM_STATUS_T_FLAG_TIP_OVER : 0u) |
                (o->contact_flags & SIM_CONTACT_CRASH ? (unsigned)DISIM_SIM_STATUS_T_FLAG_CRASH : 0u);
}

void app_render_state_from_log(const app_scene *s, const sim_log_state *l, render_state *rs)
{
    memset(rs, 0, sizeof *rs);
    rs->t_s = l->t_s;
    rs->ship = l->ship;
    rs->ship_yaw_rad = l->ship_euler_E_rad[2];
    rs->have_heli = 1;
    rs->heli = l->heli;
    memcpy(rs->pos_S_m, l->pos_S_m, sizeof rs->pos_S_m);
    memcpy(rs->vel_S_mps, l->vel_S_mps, sizeof rs->vel_S_mps);
    rs->roll_rad = l->euler_E_rad[0], rs->pitch_rad = l->euler_E_rad[1], rs->yaw_rad = l->euler_E_rad[2];
    memcpy(rs->controls_pct, l->controls_pct, sizeof rs->controls_pct);
    rs->rotor_thrust_N = l->rotor_thrust_N;
    rs->on_deck = l->on_deck;
    rs->n_gear = l->n_gear < RENDER_MAX_LEGS ? l->n_gear : RENDER_MAX_LEGS;
    memcpy(rs->gear_load_N, l->gear_load_N, sizeof rs->gear_load_N);
    rs->rotor_azimuth_rad = render_rotor_azimuth(&s->run.geom, l->t_s);
    rs->flags = l->on_deck ? (unsigned)DISIM_SIM_STATUS_T_FLAG_ON_DECK : 0u;
}

double app_scene_check_log(const app_scene *s, const sim_log *log)
{
    sim_log_summary info;
    sim_log_info(log, &info);
    double rate = s->run.info.state_rate_hz > 0.0 ? s->run.info.state_rate_hz : 50.0, worst = 0.0;
    long n = (long)llround((info.t1_s - info.t0_s) * rate);
    for (int k = 0; k <= 20; k++) {
        /* at the samples' own times: between them the log is linear */
        double t = info.t0_s + (double)(n * k / 20) / rate;
        sim_log_state l;
        sim_ship_state ss;
        sim_log_state_at(log, t, &l);
        if (sim_ship_motion_at(s->run.sea, t, &ss) != 0)
            return INFINITY;
        worst = fmax(worst, core_vec3_norm(core_vec3_sub(l.ship.pos_E_m, ss.pose.pos_E_m)));
    }
    return worst;
}
