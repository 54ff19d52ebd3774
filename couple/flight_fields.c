/* flight_fields.c -- the airwake a flight of `disim fly` flies in, from the
 * airwake database: the scenario's ship-only field of the WOD direction
 * (couple_flight_field: the best level ready among quick and coarse up
 * to the scenario's grid; the finer ones requested and marked waited
 * for, the flight in the free stream or the coarser field meanwhile) and
 * the coupled rotor interaction at the WOD (couple_flight_coupled: among the database's whole-domain
 * coupled fields of the scenario's ship, aircraft and grid within
 * 0.25 m/s and 0.5 deg of the WOD (the SHOL's speeds are in km/h steps,
 * the flight's in knots) whose isolated rotor's field (the same key, ship
 * NAME.isolated) is ready too, the one whose hub is nearest the station,
 * and of several within 0.5 m of that (the coupling's iterations at one
 * station) the newest, its converged iteration. A deck-zone pair
 * (couple_settings.zone) needs the whole domain's ship-only field and the
 * zone's own too (the coupling's keys: the zone at the station), for the
 * coupling's correction). */
#include "couple.h"
#include "cfd.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

/* The levels a flight flies, coarsest first: quick, then coarse up to the
 * scenario's grid. Their number. */
static int flight_levels(const sim_scenario *sc, core_grid_level lv[4])
{
    int n = 0;
    lv[n++] = CORE_GRID_QUICK;
    static const core_grid_level by_rank[] = {CORE_GRID_COARSE, CORE_GRID_DEFAULT, CORE_GRID_FINE};
    for (int r = 1; r <= core_grid_rank(sc->grid) && r <= 3; r++)
        lv[n++] = by_rank[r - 1];
    return n;
}

int couple_flight_field(awdb *db, const sim_scenario *sc, double dir_rad, int have_rank, cfd_field **out,
                        core_grid_level *level, int *pending, core_err *err)
{
    core_grid_level lv[4];
    int n = flight_levels(sc, lv), best = -1;
    awdb_key k[4];
    awdb_state st[4];
    char path[1024];
    *out = NULL;
    *pending = 0;
    for (int i = 0; i < n; i++) {
        awdb_key_ship_only(&k[i], sc->ship.name, sc->aircraft_name, AWDB_SHIP_ONLY_REF_MPS, dir_rad, lv[i]);
        if (awdb_key_canon(&k[i], err) != 0)
            return -1;
        st[i] = awdb_query(db, &k[i], NULL, 0);
        if (st[i] == AWDB_READY)
            best = i;
    }
    /* the levels up to the best there is: no longer waited for (a quick
     * field still queued goes behind what others wait for) */
    for (int i = 0; i <= best; i++)
        awdb_wait_unmark(db, &k[i]);
    /* the levels finer than the best there is, coarsest first (quick only
     * while none is ready); a failed one stays failed (its reason is in the
     * database), the flight in the best field it has meanwhile */
    for (int i = best + 1; i < n; i++) {
        if (st[i] == AWDB_FAILED)
            continue;
        if (st[i] == AWDB_ABSENT && awdb_submit(db, &k[i], NULL, err) != 0)
            return -1;
        *pending = 1;
        core_err merr = {0}; /* without the mark the builder serves it later, nothing worse */
        awdb_wait_mark(db, &k[i], &merr);
    }
    if (best < 0 || core_grid_rank(lv[best]) <= have_rank)
        return 0;
    if (awdb_query(db, &k[best], path, sizeof path) != AWDB_READY) /* removed since: asked again next time */
        return 0;
    *level = lv[best];
    return (*out = cfd_field_load(path, err)) ? 1 : -1;
}

void couple_flight_field_done(awdb *db, const sim_scenario *sc, double dir_rad)
{
    core_grid_level lv[4];
    int n = flight_levels(sc, lv);
    for (int i = 0; i < n; i++) {
        awdb_key k;
        awdb_key_ship_only(&k, sc->ship.name, sc->aircraft_name, AWDB_SHIP_ONLY_REF_MPS, dir_rad, lv[i]);
        awdb_wait_unmark(db, &k);
    }
}

/* The two passes over the database's entries (couple_flight_coupled). */
typedef struct coupled_pick {
    const sim_scenario *sc;
    double v, dir_deg;
    awdb *db;
    int pass;             /* 0: the hub nearest the station; 1: the newest hub within 0.5 m of it */
    double near_hub_S_m[3];
    awdb_key best;
    double best_d, best_mtime;
    char cpath[1024], ipath[1024], wpath[1024], zpath[1024]; /* wpath, zpath "": a whole-domain pair */
} coupled_pick;

static int coupled_candidate(void *user, const awdb_key *k)
{
    coupled_pick *p = user;
    double dd = fabs(remainder(k->wod_dir_rad * CORE_RAD_TO_DEG - p->dir_deg, 360.0));
    if (strcmp(k->ship, p->sc->ship.name) || strcmp(k->aircraft, p->sc->aircraft_name) || k->rotor == CORE_ROTOR_OFF ||
        k->grid != p->sc->grid || fabs(k->wod_speed_mps - p->v) > 0.25 || dd > 0.5)
        return 0;
    double d2 = 0.0;
    for (int i = 0; i < 3; i++)
        d2 += (k->station_S_m[i] - p->sc->station_S_m[i]) * (k->station_S_m[i] - p->sc->station_S_m[i]);
    double d = sqrt(d2), dn2 = 0.0;
    for (int i = 0; i < 3; i++)
        dn2 += (k->station_S_m[i] - p->near_hub_S_m[i]) * (k->station_S_m[i] - p->near_hub_S_m[i]);
    if (p->pass == 1 && dn2 > 0.25)
        return 0;
    awdb_key ki = *k;
    char cp[1024], ip[1024];
    if (snprintf(ki.ship, sizeof ki.ship, "%s.isolated", k->ship) >= (int)sizeof ki.ship)
        return 0;
    struct stat st;
    if (awdb_query(p->db, k, cp, sizeof cp) != AWDB_READY || awdb_query(p->db, &ki, ip, sizeof ip) != AWDB_READY ||
        stat(cp, &st) != 0)
        return 0;
    double mt = (double)st.st_mtim.tv_sec + 1e-9 * (double)st.st_mtim.tv_nsec;
    char wp[1024] = "", zp[1024] = "";
    if (k->zone_ref_mps > 0.0) { /* the zone's correction: both ship-only fields at the zone's speed */
        awdb_key kw, kz;
        awdb_key_ship_only(&kw, k->ship, k->aircraft, k->zone_ref_mps, k->wod_dir_rad, k->grid);
        kz = kw;
        kz.zone_ref_mps = k->zone_ref_mps;
        memcpy(kz.station_S_m, p->sc->station_S_m, sizeof kz.station_S_m);
        kz.radius_m = k->radius_m;
        core_err e2 = {0};
        if (awdb_key_canon(&kw, &e2) || awdb_key_canon(&kz, &e2) || awdb_query(p->db, &kw, wp, sizeof wp) != AWDB_READY ||
            awdb_query(p->db, &kz, zp, sizeof zp) != AWDB_READY)
            return 0;
    }
    if (p->pass == 0) { /* ties by the hub's coordinates: the entries' order does not matter */
        int tie = d == p->best_d && memcmp(k->station_S_m, p->near_hub_S_m, sizeof p->near_hub_S_m) != 0 &&
                  (k->station_S_m[0] < p->near_hub_S_m[0] ||
                   (k->station_S_m[0] == p->near_hub_S_m[0] && (k->station_S_m[1] < p->near_hub_S_m[1] ||
                    (k->station_S_m[1] == p->near_hub_S_m[1] && k->station_S_m[2] < p->near_hub_S_m[2]))));
        if (d < p->best_d || tie) {
            p->best_d = d;
            memcpy(p->near_hub_S_m, k->station_S_m, sizeof p->near_hub_S_m);
        }
    } else if (mt > p->best_mtime) {
        p->best = *k;
        p->best_mtime = mt;
        snprintf(p->cpath, sizeof p->cpath, "%s", cp);
        snprintf(p->ipath, sizeof p->ipath, "%s", ip);
        snprintf(p->wpath, sizeof p->wpath, "%s", wp);
        snprintf(p->zpath, sizeof p->zpath, "%s", zp);
    }
    return 0;
}

int couple_flight_coupled(awdb *db, const sim_scenario *sc, double v, double dir_rad, cfd_field *cf[4],
                          sim_interaction **inter, core_err *err)
{
    coupled_pick p;
    memset(&p, 0, sizeof p);
    p.sc = sc;
    p.v = v;
    p.dir_deg = dir_rad * CORE_RAD_TO_DEG;
    p.db = db;
    p.best_d = INFINITY;
    if (awdb_list(db, coupled_candidate, &p, err) < 0)
        return -1;
    if (!isfinite(p.best_d))
        return 0;
    p.pass = 1; /* the order the entries come in does not matter */
    if (awdb_list(db, coupled_candidate, &p, err) < 0)
        return -1;
    if (!p.cpath[0])
        return 0;
    if (!(cf[0] = cfd_field_load(p.cpath, err)) || !(cf[1] = cfd_field_load(p.ipath, err)))
        return -1;
    if (p.zpath[0] && (!(cf[2] = cfd_field_load(p.wpath, err)) || !(cf[3] = cfd_field_load(p.zpath, err))))
        return -1;
    sim_interaction_opts io;
    sim_interaction_opts_default(&io);
    memcpy(io.station_S_m, sc->station_S_m, sizeof io.station_S_m);
    io.ship_whole = cf[2];
    io.ship_zone = cf[3];
    return (*inter = sim_interaction_create(cf[0], cf[1], &io, err)) ? 1 : -1;
}

