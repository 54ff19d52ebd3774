/* world.c -- what a flight is flown in, built in one place for every
 * flight of disim (sim_world_build): `disim fly` in every mode, the flown
 * SHOL's flights (couple/fly_task.c), and the seaway `disim render` and
 * `disim fly --render` draw (sim_world_seaway).
 *
 * From a scenario and the caller's overrides (disim fly's flags, the
 * flown SHOL's WOD point and seed): the seaway (the overrides' whole sea,
 * else the scenario's [sea] with the state, wave direction and ship
 * speed overridden), the ship's motion in it seeded by seed + 1 (the
 * seaway's own stream; the flight's turbulence has seed), the flight
 * trimmed at the start (the scenario's station unless the overrides give
 * one) in the overrides' field and interaction, and the run information
 * (sim_run_info) that the loop logs as run_info_t and the renderer
 * rebuilds the seaway from. */
#include "sim.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

void sim_world_overrides_default(sim_world_overrides *o)
{
    memset(o, 0, sizeof *o);
    o->rate_hz = 200.0;
    o->wod_speed_mps = o->wod_dir_rad = NAN;
    o->seed = 1;
    o->turbulence = -1;
    o->sea_state = -1;
    o->wave_dir_rad = o->ship_speed_mps = NAN;
    o->gear = 1;
    o->start = SIM_START_HOVER;
    o->sas = -1;
}

void sim_world_run_info(const sim_scenario *sc, const sim_world_overrides *ov, sim_run_info *ri)
{
    memset(ri, 0, sizeof *ri);
    snprintf(ri->scenario_path, sizeof ri->scenario_path, "%s", sc->path);
    snprintf(ri->scenario, sizeof ri->scenario, "%s", sc->name);
    snprintf(ri->aircraft_path, sizeof ri->aircraft_path, "%s", sc->aircraft_path);
    snprintf(ri->ship_path, sizeof ri->ship_path, "%s", sc->ship_path);
    ri->seed = ov->seed;
    if (ov->sea)
        ri->sea = *ov->sea;
    else {
        sim_sea_default(&ri->sea);
        ri->sea.state = ov->sea_state >= 0 ? ov->sea_state : sc->sea.state;
        ri->sea.ship_speed_mps = isnan(ov->ship_speed_mps) ? sc->sea.ship_speed_mps : ov->ship_speed_mps;
        ri->sea.wave_dir_rad = isnan(ov->wave_dir_rad) ? sc->sea.wave_dir_rad : ov->wave_dir_rad;
        ri->sea.spectrum = sc->sea.spectrum;
    }
    ri->wod_speed_mps = isnan(ov->wod_speed_mps) ? sc->wod_speed_mps : ov->wod_speed_mps;
    ri->wod_dir_rad = isnan(ov->wod_dir_rad) ? sc->wod_dir_rad : ov->wod_dir_rad;
    ri->rate_hz = ov->rate_hz;
}

sim_ship_motion *sim_world_seaway(const core_ship *ship, const sim_sea *sea, unsigned long long seed, core_err *err)
{
    return sim_ship_motion_create(ship, sea, (uint64_t)seed + 1u, err);
}

int sim_run_scene_open(sim_run_scene *s, const sim_run_info *ri, const core_log *log, core_err *err)
{
    memset(s, 0, sizeof *s);
    s->info = *ri;
    if (core_ship_load(ri->ship_path, &s->ship, err) != 0)
        return -1;
    if (!(s->ac = hfm_aircraft_load(ri->aircraft_path, log, err)))
        return -1;
    hfm_aircraft_geometry(s->ac, &s->geom);
    if (!(s->sea = sim_world_seaway(&s->ship, &ri->sea, ri->seed, err))) {
        sim_run_scene_close(s);
        return -1;
    }
    char wod[48];
    core_wod_label(ri->wod_speed_mps, ri->wod_dir_rad * CORE_RAD_TO_DEG, wod, sizeof wod);
    snprintf(s->name, sizeof s->name, "%s + %s, %s, sea state %d", s->ship.name, hfm_aircraft_name(s->ac), wod,
             ri->sea.state);
    return 0;
}

void sim_run_scene_close(sim_run_scene *s)
{
    sim_ship_motion_destroy(s->sea);
    hfm_aircraft_destroy(s->ac);
    memset(s, 0, sizeof *s);
}

int sim_world_build(const sim_scenario *sc, const hfm_aircraft *ac, const sim_world_overrides *ov,
                    const core_log *log, sim_world *w, core_err *err)
{
    memset(w, 0, sizeof *w);
    sim_world_run_info(sc, ov, &w->info);
    const sim_run_info *ri = &w->info;
    if (!(w->motion = sim_world_seaway(&sc->ship, &ri->sea, ri->seed, err)))
        return -1;
    sim_flight_opts fo;
    sim_flight_opts_default(&fo);
    fo.interaction = ov->interaction;
    fo.rate_hz = ov->rate_hz;
    fo.wod_speed_mps = ri->wod_speed_mps;
    fo.wod_dir_rad = ri->wod_dir_rad;
    fo.ship_speed_mps = ri->sea.ship_speed_mps;
    fo.turbulence = ov->turbulence >= 0 ? ov->turbulence : sc->turbulence;
    fo.seed = ov->seed;
    hfm_gear gear; /* the wheels and strike points on the deck and the ship (sim/contact.c) */
    fo.gear = ov->gear && hfm_aircraft_gear(ac, &gear) == 0;
    fo.start = ov->start;
    fo.start_heading_rad = ov->start_heading_rad;
    if (ov->sas >= 0)
        fo.sas = ov->sas;
    memcpy(fo.station_S_m, ov->has_station ? ov->station_S_m : sc->station_S_m, sizeof fo.station_S_m);
    if (!(w->flight = sim_flight_create(ac, &sc->ship, &fo, sim_ship_motion_frame_fn, w->motion, ov->field, log,
                                        err))) {
        sim_world_free(w);
        return -1; /* err->code CORE_ERR_NO_TRIM: the start does not trim */
    }
    return 0;
}

void sim_world_free(sim_world *w)
{
    sim_flight_destroy(w->flight);
    sim_ship_motion_destroy(w->motion);
    memset(w, 0, sizeof *w);
}
