/* couple.c -- the coupling loop (seed paper section 2.5); see couple.h for
 * the model. Assumptions, beyond the seed paper's:
 *  - The actuator disk carries the trim's blade loads (hfm_rotor_disk: the
 *    blade-element thrust and in-plane force per unit area over 8 radial x
 *    12 azimuthal cells, resampled to the database key's table) with the
 *    trim's thrust, at the trimmed hub, tilted with the trimmed shaft; the
 *    uniform disk of eq. 5 is an option. Keys round thrust to 1 N, tilt to
 *    0.1 deg and the load shape to 0.001 of its mean, so a converged loop
 *    re-reads its last field.
 *  - "Change less than 5 %" is measured per quantity as |dx| / max(|x|, f)
 *    with floors f = 20 % of travel for controls and 5 deg for attitudes, so
 *    quantities near zero do not demand impossible relative accuracy.
 *  - The isolated-rotor field for the interaction velocity is the same case
 *    with the ship's cells left open (ship name + ".isolated").
 *  - Option (settings.zone): both fields cover the deck zone only, the
 *    coupled one bounded by the ship-only field scaled to the speed (see
 *    cfd/airwake.c for that model's assumptions), and the interaction gets
 *    the difference between the whole domain's ship-only airwake and the
 *    zone's own (zone_correction), so that the zone adds only what the
 *    rotor changes.
 *  - From the second coupled iteration on, the interaction velocity is
 *    under-relaxed: half this iteration's fields, half the previous ones
 *    (a plain fixed-point iteration oscillated where the interaction is
 *    strong).
 *  - Over the rotor disk the interaction velocity is projected on the
 *    inflow modes of the flight model's Pitt-Peters model (uniform and
 *    first harmonics, linear in r; Peters and HaQuang 1988): the blade
 *    elements see the disk-scale interaction, not the pointwise difference
 *    of two slipstream edges a cell wide (interaction.c). Fuselage, tail rotor
 *    and empennage see the pointwise field.
 */
#include "couple_priv.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void couple_settings_default(couple_settings *s)
{
    memset(s, 0, sizeof *s);
    s->mode = CORE_COUPLING_TWO_WAY;
    s->grid = CORE_GRID_DEFAULT;
    s->max_iter = 6;
    s->tol_frac = 0.05;
    s->ref_speed_mps = AWDB_SHIP_ONLY_REF_MPS;
    s->station_S_m[2] = -6.0;
    s->wait_timeout_s = 3 * 3600.0;
    s->seed_from_previous = 1;
    s->seed_one_way = 1;
}

couple_ctx *couple_create(const hfm_aircraft *ac, const core_ship *ship, awdb *db,
                          const couple_settings *s, const core_log *log, core_err *err)
{
    if (s->max_iter < 1 || s->max_iter > COUPLE_MAX_ITER) {
        core_err_set(err, -1, "coupling: max_iter = %d: expected 1 to %d", s->max_iter, COUPLE_MAX_ITER);
        return NULL;
    }
    if (s->zone && s->direct && s->mode == CORE_COUPLING_TWO_WAY) {
        core_err_set(err, -1, "coupling: the deck zone (zone = 1) works with the interaction velocity only, not "
                              "with the coupled field used directly (direct = 1)");
        return NULL;
    }
    if (!(s->tol_frac > 0.0 && s->tol_frac < 1.0) || !(s->ref_speed_mps > 0.0)) {
        core_err_set(err, -1, "coupling: tol_frac in (0, 1) and ref_speed_mps > 0 expected");
        return NULL;
    }
    couple_ctx *c = calloc(1, sizeof *c);
    if (!c) {
        core_err_set(err, -1, "coupling: out of memory");
        return NULL;
    }
    c->ac = ac;
    c->ship = ship;
    c->db = db;
    c->s = *s;
    c->log = log;
    awdb_fields_opts fo;
    awdb_fields_opts_default(&fo);
    fo.cache_n = COUPLE_CACHE_N;
    fo.wait_timeout_s = s->wait_timeout_s;
    fo.launch = s->launch;
    fo.launch_user = s->launch_user;
    fo.wait_fn = s->wait_fn;
    fo.wait_user = s->wait_user;
    fo.loaded_fn = couple_field_note;
    fo.loaded_user = c;
    if (!(c->fc = awdb_fields_create(db, &fo, log, err))) {
        couple_destroy(c);
        return NULL;
    }
    c->trim = hfm_trim_create(ac, log);
    c->disk = malloc(sizeof *c->disk);
    if (!c->trim || !c->disk) {
        core_err_set(err, -1, "coupling: out of memory");
        couple_destroy(c);
        return NULL;
    }
    return c;
}

void couple_destroy(couple_ctx *c)
{
    if (!c)
        return;
    awdb_fields_destroy(c->fc);
    hfm_trim_destroy(c->trim);
    free(c->disk);
    free(c->hist);
    free(c->warm);
    free(c->fields);
    free(c);
}
/* The relative change of a control or attitude, against at least `floor`:
 * 20 % of travel for a control, 5 deg (the roll limit) for an attitude, so
 * 5 % is 1 % of travel or 0.25 deg near zero. Why not less (the pedal's
 * limit leaves 10 % of travel to a stop): a control's percentage
 * has an arbitrary origin (pedal 9.7 % is 90.3 % from the other stop), and
 * with floors of 10 % and 1 deg a point near a stop keeps iterating on
 * changes of 0.6 % of travel and 0.09 deg, below what the averaged fields
 * resolve (CG-47 red 60 at 50 km/h: six coupled iterations, the last two
 * moving pedal 10.4 -> 9.8 -> 9.7 %). */
static double change(double a, double b, double floor)
{
    return fabs(a - b) / fmax(fmax(fabs(a), fabs(b)), floor);
}

static void record(couple_iter *it, const hfm_trim_result *r, const couple_iter *prev)
{
    it->thrust_N = r->loads.mr_thrust_N;
    it->ctl = r->u;
    it->phi_rad = r->body.euler_rad[0];
    it->theta_rad = r->body.euler_rad[1];
    it->change_frac = NAN;
    if (prev) {
        const double fc = 20.0, fa = 5.0 * CORE_DEG_TO_RAD;
        double m = change(it->ctl.collective_pct, prev->ctl.collective_pct, fc);
        m = fmax(m, change(it->ctl.long_cyclic_pct, prev->ctl.long_cyclic_pct, fc));
        m = fmax(m, change(it->ctl.lat_cyclic_pct, prev->ctl.lat_cyclic_pct, fc));
        m = fmax(m, change(it->ctl.pedal_pct, prev->ctl.pedal_pct, fc));
        m = fmax(m, change(it->phi_rad, prev->phi_rad, fa));
        m = fmax(m, change(it->theta_rad, prev->theta_rad, fa));
        it->change_frac = m;
    }
}

/* The warm start of direction dir (NULL: none yet). */
static struct couple_warm *warm_find(couple_ctx *c, double dir)
{
    for (int i = 0; i < c->nwarm; i++)
        if (fabs(remainder(c->warm[i].dir - dir, 2 * CORE_PI)) < 1e-9)
            return &c->warm[i];
    return NULL;
}

/* A trim at direction dir, warm-started from that direction's last
 * converged trim; a converged one becomes the direction's warm start.
 * < 0 fatal (out of memory), else hfm_trim_solve's code. */
static int solve(couple_ctx *c, double dir, const hfm_trim_cond *cond, hfm_trim_result *res)
{
    struct couple_warm *w = warm_find(c, dir);
    int rc = hfm_trim_solve(c->trim, cond, w ? &w->r : NULL, res);
    if (rc == 1 && w) /* a cold start sometimes finds what the warm one missed */
        rc = hfm_trim_solve(c->trim, cond, NULL, res);
    if (rc != 0)
        return rc;
    if (!w) {
        if (c->nwarm == c->capwarm) {
            int cap = c->capwarm ? 2 * c->capwarm : 16;
            struct couple_warm *nw = realloc(c->warm, cap * sizeof *nw);
            if (!nw)
                return -1;
            c->warm = nw;
            c->capwarm = cap;
        }
        w = &c->warm[c->nwarm++];
        w->dir = dir;
    }
    w->r = *res;
    return 0;
}

/* The one-way air at a WOD: the direction's ship-only field (at the
 * reference speed) scaled to v. 0, or -1 with err when the field cannot be
 * had. The field stays in the cache until the next fetch. */
static int ship_only_air(couple_ctx *c, double v, double dir, cfd_field_scaled *a, core_err *err)
{
    return awdb_fields_ship_only_air(c->fc, c->ship->name, hfm_aircraft_name(c->ac), c->s.grid, c->s.ref_speed_mps,
                                     v, dir, a, err);
}

/* The key of a field of this ship and aircraft at a WOD (rotor off). */
static void base_key(const couple_ctx *c, awdb_key *k, double v, double dir)
{
    awdb_key_ship_only(k, c->ship->name, hfm_aircraft_name(c->ac), v, dir, c->s.grid);
}

/* Deck zone: the whole domain's and the zone's own ship-only fields of the
 * direction, for the correction ship_whole - ship_zone (both scale with the
 * speed). Why: the coupled zone field holds the zone's version of the ship
 * airwake, which is not the whole domain's where the wake is unsteady (CG-47
 * red 60 on the coarse grid: 10 m/s apart over the spot with no rotor);
 * corrected, the zone contributes only what the rotor changes, and a rotor
 * without thrust gives the one-way air exactly. The zone's ship-only field
 * is placed at the CG station (not at each trim's hub), so one serves a
 * direction. */
static void zone_ship_key(couple_ctx *c, double dir, awdb_key *k)
{
    base_key(c, k, c->s.ref_speed_mps, dir);
    k->zone_ref_mps = c->s.ref_speed_mps;
    memcpy(k->station_S_m, c->s.station_S_m, sizeof k->station_S_m);
    k->radius_m = hfm_aircraft_rotor_radius_m(c->ac);
}

static int zone_correction(couple_ctx *c, double v, double dir, air_interaction *ai, core_err *err)
{
    ai->ship_whole = ai->ship_zone = NULL;
    if (!c->s.zone || !(v > 0.0))
        return 0;
    awdb_key k;
    zone_ship_key(c, dir, &k);
    const cfd_field *sz = awdb_fields_get(c->fc, &k, err);
    if (!sz)
        return -1;
    cfd_field_scaled so;
    if (ship_only_air(c, v, dir, &so, err) != 0)
        return -1;
    /* the whole field's fetch may have evicted the zone's: fetch it again */
    if (!(sz = awdb_fields_get(c->fc, &k, err)))
        return -1;
    ai->ship_whole = so.field;
    ai->ship_zone = sz;
    ai->corr_scale = v / c->s.ref_speed_mps;
    return 0;
}

/* A coupled point's airs while it is trimmed. The air of the latest trim
 * outlives each iteration because the next disk is evaluated in it (before
 * any field is fetched, so the cached fields it points to are still
 * loaded). Lives on couple_trim's stack: cond.air and air point into it. */
typedef struct trim_state {
    hfm_trim_cond cond;
    hfm_air_uniform uni;
    hfm_air free_air;
    air_interaction ai;    /* the interaction air (air.user) */
    cfd_field_scaled direct; /* the coupled field used directly (air.user with direct) */
    hfm_air air;
    cfd_field_scaled ship_air; /* the one-way seed's scaled ship-only field */
    hfm_air ship_hfm_air;
} trim_state;

/* One-way: the trim in the ship-only airwake scaled to v. */
static int trim_one_way(couple_ctx *c, trim_state *st, double v, double dir, couple_point *p, core_err *err)
{
    /* calm air: the ship-only field scaled by v is zero everywhere, so
     * the one-way trim is the free-air one and needs no field */
    cfd_field_scaled a;
    hfm_air air = {cfd_field_air_scaled, &a, NULL};
    if (v > 0.0) {
        if (ship_only_air(c, v, dir, &a, err) != 0)
            return -1;
        st->cond.air = &air;
    }
    int rc = solve(c, dir, &st->cond, &p->trim);
    st->cond.air = NULL;
    if (rc < 0)
        return core_err_set(err, rc, "trim at %.2f m/s from %.1f deg: fatal error", v, dir * CORE_RAD_TO_DEG);
    p->converged = rc == 0;
    p->coupling_converged = 1;
    p->n_iter = 1;
    record(&p->iter[0], &p->trim, NULL);
    return rc;
}

/* Iteration 0 seeded with the interaction of the previous coupled point of
 * this direction (seed_from_previous). Why: from free air the first
 * coupled trim always moved more than 5 %, so every speed took two coupled
 * and two isolated fields; the interaction changes little over one speed
 * step, and a trim seeded with it is usually within 5 % of the trim in its
 * own fields after one pair. The first coupled iteration takes the new
 * fields whole (no relaxation), so a point that converges there is trimmed
 * in its own fields only. 0 trimmed, 1 no seed or no trim (free air
 * again), < 0 fatal. */
static int seed_previous(couple_ctx *c, trim_state *st, double v, double dir, couple_point *p, core_err *err)
{
    const struct couple_seed_slot *sd = couple_seed_find(c, dir);
    if (!(c->s.seed_from_previous && !c->s.direct && sd && fabs(sd->v - v) <= SEED_MAX_DV_MPS &&
          fabs(sd->v - v) > 1e-6))
        return 1;
    /* four fields in a cache of COUPLE_CACHE_N: none evicts another */
    air_interaction *ai = &st->ai;
    *ai = sd->ai;
    int ok = (ai->coupled = awdb_fields_load(c->fc, sd->coupled, err)) != NULL &&
             (ai->isolated = awdb_fields_load(c->fc, sd->isolated, err)) != NULL;
    if (ok && sd->prev_coupled[0])
        ok = (ai->prev_coupled = awdb_fields_load(c->fc, sd->prev_coupled, err)) != NULL &&
             (ai->prev_isolated = awdb_fields_load(c->fc, sd->prev_isolated, err)) != NULL;
    if (ok && zone_correction(c, v, dir, ai, err) != 0)
        return -1;
    if (!ok) { /* a field gone from the database: start in free air */
        memset(ai, 0, sizeof *ai);
        return 1;
    }
    memcpy(ai->wind, st->uni.vel_S_mps, sizeof ai->wind);
    st->air.fn = couple_interaction_air;
    st->air.user = ai;
    st->air.wake = &st->free_air; /* the flight model's wake is the isolated rotor's (hfm.h) */
    st->cond.air = &st->air;
    int rc = solve(c, dir, &st->cond, &p->trim);
    if (rc < 0)
        return core_err_set(err, rc, "seeded trim at %.2f m/s: fatal error", v);
    if (rc == 0) {
        p->seed = COUPLE_SEED_PREVIOUS;
        p->seed_speed_mps = sd->v;
    } else
        st->cond.air = NULL;
    return rc;
}

/* Iteration 0 of a point with no previous coupled point to seed it: the
 * one-way trim (seed_one_way). Why: the ship-only airwake holds most of
 * what moves the trim away from free air (CG-47 red 60: one-way pedal 70 %
 * at 60 km/h, free-air pedal 39 % at 50 km/h), so the first coupled disk,
 * loaded from it, is nearer the coupled solution. The scaled field stays
 * in the cache while the first disk is evaluated in it (nothing is fetched
 * before). 0 trimmed, 1 not (free air again), < 0 fatal. */
static int seed_one_way(couple_ctx *c, trim_state *st, double v, double dir, couple_point *p, core_err *err)
{
    if (!(c->s.seed_one_way && !c->s.direct && v > 0.0)) /* calm: the scaled field is free air */
        return 1;
    if (ship_only_air(c, v, dir, &st->ship_air, err) != 0)
        return -1;
    st->ship_hfm_air.fn = cfd_field_air_scaled;
    st->ship_hfm_air.user = &st->ship_air;
    st->ship_hfm_air.wake = NULL;
    st->cond.air = &st->ship_hfm_air;
    int rc = solve(c, dir, &st->cond, &p->trim);
    if (rc < 0)
        return core_err_set(err, rc, "one-way seed trim at %.2f m/s: fatal error", v);
    if (rc == 0)
        p->seed = COUPLE_SEED_ONE_WAY;
    else
        st->cond.air = NULL;
    return rc;
}

/* The fields of coupled iteration it: the disk from the current trim,
 * evaluated in the air it was trimmed in, solved with the ship (and, for
 * the interaction velocity, without it), and the air made of them. 0, or
 * < 0 fatal. */
static int coupled_air(couple_ctx *c, trim_state *st, double v, double dir, int it, couple_point *p, core_err *err)
{
    const hfm_air *air_now = st->cond.air ? st->cond.air : &st->free_air;
    if (hfm_rotor_disk(c->ac, air_now, 0.0, &p->trim.body, &p->trim.u, &p->trim.rotor, 8, 12, c->disk) != 0)
        return core_err_set(err, -1, "rotor disk at %.2f m/s from %.1f deg: evaluation failed", v, dir * CORE_RAD_TO_DEG);
    awdb_key kc;
    base_key(c, &kc, v, dir);
    if (couple_key_set_rotor(c->ac, c->disk, !c->s.uniform_disk, &kc) != 0)
        return core_err_set(err, -1, "rotor disk at %.2f m/s from %.1f deg: no thrust", v, dir * CORE_RAD_TO_DEG);
    if (c->s.zone && v > 0.0) {
        /* the zone's boundary must be in the database before the zone
         * is built (it usually is: the one-way trim used it) */
        kc.zone_ref_mps = c->s.ref_speed_mps;
        awdb_key kb;
        awdb_key_zone_boundary(&kc, &kb);
        if (!awdb_fields_get(c->fc, &kb, err))
            return -1;
        /* the zone's own ship-only field (zone_correction), queued now
         * to be built beside the first pair */
        awdb_key kz;
        zone_ship_key(c, dir, &kz);
        if (awdb_submit(c->db, &kz, NULL, err) != 0)
            return -1;
    }
    awdb_key ki = kc;
    snprintf(ki.ship, sizeof ki.ship, "%s.isolated", c->ship->name);
    if (!c->s.direct) {
        /* queue the isolated rotor now, so that a builder with two jobs
         * runs it beside the coupled field */
        if (awdb_key_canon(&ki, err) != 0 || awdb_submit(c->db, &ki, NULL, err) != 0)
            return -1;
    }
    const cfd_field *fc = awdb_fields_get(c->fc, &kc, err);
    if (!fc)
        return -1;
    st->direct.field = fc;
    st->direct.scale = 1.0;
    if (c->s.direct) {
        st->air.fn = cfd_field_air_scaled;
        st->air.user = &st->direct;
    } else {
        const cfd_field *fi = awdb_fields_get(c->fc, &ki, err);
        if (!fi)
            return -1;
        /* the fetch may have evicted fc from the cache: fetch it again. */
        fc = awdb_fields_get(c->fc, &kc, err);
        if (!fc)
            return -1;
        /* The fixed-point iteration trim -> CFD -> trim overshoots where
         * the interaction is strong (the collective was seen to swing
         * +-10 % between iterations): each iteration takes half of the
         * new interaction and half of the previous one. */
        air_interaction *ai = &st->ai;
        ai->prev_coupled = it > 1 ? ai->coupled : NULL;
        ai->prev_isolated = it > 1 ? ai->isolated : NULL;
        ai->w = 0.5;
        ai->coupled = fc;
        ai->isolated = fi;
        /* after fc and fi: six fields in a cache of COUPLE_CACHE_N */
        if (zone_correction(c, v, dir, ai, err) != 0)
            return -1;
        memcpy(ai->wind, st->uni.vel_S_mps, sizeof ai->wind);
        couple_interaction_fit(ai, c->disk, hfm_aircraft_rotor_radius_m(c->ac));
        st->air.fn = couple_interaction_air;
        st->air.user = ai;
        st->air.wake = &st->free_air; /* the flight model's wake is the isolated rotor's (hfm.h) */
    }
    st->cond.air = &st->air;
    return 0;
}

int couple_trim(couple_ctx *c, double v, double dir, couple_point *p, core_err *err)
{
    memset(p, 0, sizeof *p);
    p->wod_speed_mps = v;
    p->wod_dir_rad = dir;
    trim_state st;
    memset(&st, 0, sizeof st);
    st.cond.kind = HFM_TRIM_HOVER_SHIP;
    st.cond.wod_speed_mps = v;
    st.cond.wod_dir_rad = dir;
    memcpy(st.cond.pos_S_m, c->s.station_S_m, sizeof st.cond.pos_S_m);
    if (c->s.mode == CORE_COUPLING_ONE_WAY)
        return trim_one_way(c, &st, v, dir, p, err);

    core_vec3 w = core_wod_vel_S_mps(v, dir);
    st.uni.vel_S_mps[0] = w.x;
    st.uni.vel_S_mps[1] = w.y;
    st.uni.vel_S_mps[2] = w.z;
    st.free_air.fn = hfm_air_uniform_fn;
    st.free_air.user = &st.uni;

    /* Iteration 0: seeded from the previous point of the direction, else
     * from the one-way trim, else the free-air trim. */
    int rc = seed_previous(c, &st, v, dir, p, err);
    if (rc > 0)
        rc = seed_one_way(c, &st, v, dir, p, err);
    if (rc < 0)
        return -1;
    if (rc > 0) {
        rc = solve(c, dir, &st.cond, &p->trim);
        if (rc != 0) {
            if (rc < 0)
                return core_err_set(err, rc, "free-air trim at %.2f m/s: fatal error", v);
            p->converged = 0;
            return 1;
        }
    }
    record(&p->iter[0], &p->trim, NULL);
    p->n_iter = 1;
    for (int it = 1; it < c->s.max_iter + 1 && it < COUPLE_MAX_ITER; it++) {
        if (coupled_air(c, &st, v, dir, it, p, err) != 0)
            return -1;
        hfm_trim_result next;
        rc = solve(c, dir, &st.cond, &next);
        if (rc != 0) {
            if (rc < 0)
                return core_err_set(err, rc, "coupled trim at %.2f m/s: fatal error", v);
            p->converged = 0;
            return 1;
        }
        p->trim = next;
        record(&p->iter[it], &p->trim, &p->iter[it - 1]);
        p->n_iter = it + 1;
        if (p->iter[it].change_frac < c->s.tol_frac) {
            p->coupling_converged = 1;
            break;
        }
    }
    p->converged = 1;
    if (!c->s.direct) /* keep this point's interaction as the seed of the next speed */
        couple_seed_keep(c, v, dir, &st.ai);
    if (!p->coupling_converged)
        core_log_msg(c->log, CORE_LOG_WARN, "coupling at %.2f m/s from %.1f deg: change %.1f %% after %d iterations",
                     v, dir * CORE_RAD_TO_DEG, 100.0 * p->iter[p->n_iter - 1].change_frac, p->n_iter - 1);
    return 0;
}

int couple_prefetch(couple_ctx *c, const double *dirs, int n, core_err *err)
{
    int missing = 0;
    for (int i = 0; i < n; i++) {
        awdb_key k;
        awdb_state st;
        base_key(c, &k, c->s.ref_speed_mps, dirs[i]);
        if (awdb_submit(c->db, &k, &st, err) != 0)
            return -1;
        missing += st != AWDB_READY;
    }
    if (missing && awdb_fields_start_builder(c->fc) < 0)
        return core_err_set(err, -1, "coupling: no builder serves %s and none could be started", awdb_dir(c->db));
    return 0;
}

int couple_shol_trim(void *user, double v, double dir, shol_trim_point *out)
{
    couple_ctx *c = user;
    if (c->nhist == c->caphist) {
        int cap = c->caphist ? 2 * c->caphist : 64;
        couple_point *h = realloc(c->hist, cap * sizeof *h);
        if (!h) {
            snprintf(c->last_error, sizeof c->last_error, "coupling: out of memory");
            return -1;
        }
        c->hist = h;
        c->caphist = cap;
    }
    couple_point *p = &c->hist[c->nhist];
    core_err err = {0};
    int rc = couple_trim(c, v, dir, p, &err);
    if (rc < 0) {
        snprintf(c->last_error, sizeof c->last_error, "%s", err.msg);
        return -1;
    }
    c->nhist++;
    if (rc > 0 || !p->converged)
        return 1;
    out->phi_rad = p->trim.body.euler_rad[0];
    out->theta_rad = p->trim.body.euler_rad[1];
    out->collective_pct = p->trim.u.collective_pct;
    out->long_cyclic_pct = p->trim.u.long_cyclic_pct;
    out->lat_cyclic_pct = p->trim.u.lat_cyclic_pct;
    out->pedal_pct = p->trim.u.pedal_pct;
    return 0;
}

const couple_point *couple_history(const couple_ctx *c, int *n)
{
    *n = c->nhist;
    return c->hist;
}

const char *couple_last_error(const couple_ctx *c) { return c->last_error; }
