/* fields.c -- a client's view of the airwake database: the fields it has
 * loaded (a small least-recently-used cache), a key's field fetched from
 * the database or queued and waited for (starting a builder through the
 * caller's launcher when none serves the database), the ship-only airwake
 * of a wind direction scaled to a speed, and the CFD case of a key (the
 * one place a key becomes a solver spec, for the builder's engine and for
 * `disim airwake` alike).
 *
 * Why a ship-only field serves every speed: without the rotor a bluff
 * body's high-Reynolds-number airwake scales with the wind speed (checked
 * by test_cfd_core), so one field per direction at a reference speed is
 * scaled by v / v_ref.
 */
#include "awdb.h"
#include "cfd.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define FIELDS_CACHE_MAX 32

struct awdb_fields {
    awdb *db;
    awdb_fields_opts o;
    const core_log *log;
    struct {
        char path[1024];
        cfd_field *f;
        unsigned long used;
    } cache[FIELDS_CACHE_MAX];
    int n;
    unsigned long tick;
};

void awdb_fields_opts_default(awdb_fields_opts *o)
{
    memset(o, 0, sizeof *o);
    o->cache_n = 8;
    o->wait_timeout_s = 3 * 3600.0;
    o->poll_s = 0.2;
}

awdb_fields *awdb_fields_create(awdb *db, const awdb_fields_opts *o, const core_log *log, core_err *err)
{
    if (!db || !o || o->cache_n < 1 || o->cache_n > FIELDS_CACHE_MAX || !(o->poll_s > 0.0)) {
        core_err_set(err, -1, "airwake fields: expected a database, 1 to %d cached fields and a poll interval > 0",
                     FIELDS_CACHE_MAX);
        return NULL;
    }
    awdb_fields *fc = calloc(1, sizeof *fc);
    if (!fc) {
        core_err_set(err, -1, "airwake fields: out of memory");
        return NULL;
    }
    fc->db = db;
    fc->o = *o;
    fc->log = log;
    fc->n = o->cache_n;
    return fc;
}

void awdb_fields_destroy(awdb_fields *fc)
{
    if (!fc)
        return;
    for (int i = 0; i < fc->n; i++)
        cfd_field_destroy(fc->cache[i].f);
    free(fc);
}

const cfd_field *awdb_fields_load(awdb_fields *fc, const char *path, core_err *err)
{
    int lru = 0;
    for (int i = 0; i < fc->n; i++) {
        if (fc->cache[i].f && !strcmp(fc->cache[i].path, path)) {
            fc->cache[i].used = ++fc->tick;
            return fc->cache[i].f;
        }
        if (fc->cache[i].used < fc->cache[lru].used)
            lru = i;
    }
    cfd_field *f = cfd_field_load(path, err);
    if (!f)
        return NULL;
    if (fc->o.loaded_fn)
        fc->o.loaded_fn(fc->o.loaded_user, path, f);
    cfd_field_destroy(fc->cache[lru].f);
    fc->cache[lru].f = f;
    snprintf(fc->cache[lru].path, sizeof fc->cache[lru].path, "%s", path);
    fc->cache[lru].used = ++fc->tick;
    return f;
}

const char *awdb_fields_path(const awdb_fields *fc, const cfd_field *f)
{
    for (int i = 0; i < fc->n; i++)
        if (f && fc->cache[i].f == f)
            return fc->cache[i].path;
    return NULL;
}

int awdb_fields_start_builder(awdb_fields *fc)
{
    if (!fc->o.launch || awdb_builder_alive(fc->db))
        return 0;
    return fc->o.launch(fc->o.launch_user, awdb_dir(fc->db));
}

const cfd_field *awdb_fields_get(awdb_fields *fc, awdb_key *key, core_err *err)
{
    if (awdb_key_canon(key, err))
        return NULL;
    char path[1024], name[AWDB_NAME_MAX];
    awdb_key_name(key, name, sizeof name);
    struct timespec t0, now;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    int announced = 0;
    const cfd_field *f = NULL;
    for (;;) {
        awdb_state st = awdb_query(fc->db, key, path, sizeof path);
        if (st == AWDB_READY) {
            f = awdb_fields_load(fc, path, err);
            break;
        }
        if (st == AWDB_FAILED) {
            core_err_set(err, -1,
                         "airwake %s failed to build: the reason is in %s/failed/%s.txt; remove that file (or queue "
                         "the field again with disim airwake --queue) and it is built again when next asked for",
                         name, awdb_dir(fc->db), name);
            break;
        }
        if (st == AWDB_ABSENT && awdb_submit(fc->db, key, NULL, err) != 0)
            break;
        if (!announced) {
            core_log_msg(fc->log, CORE_LOG_INFO, "waiting for airwake %s", name);
            announced = 1;
            /* the builder serves a request someone waits for first; without
             * the mark the wait is only slower */
            core_err merr = {0};
            if (awdb_wait_mark(fc->db, key, &merr) != 0)
                core_log_msg(fc->log, CORE_LOG_WARN, "%s", merr.msg);
        }
        if (!awdb_builder_alive(fc->db)) {
            if (!fc->o.launch) {
                core_err_set(err, -1, "airwake %s is not in %s and no builder serves it (start `disim airwaked %s`)",
                             name, awdb_dir(fc->db), awdb_dir(fc->db));
                break;
            }
            if (fc->o.launch(fc->o.launch_user, awdb_dir(fc->db)) < 0) {
                core_err_set(err, -1, "airwake %s: no builder serves %s and none could be started", name,
                             awdb_dir(fc->db));
                break;
            }
        }
        clock_gettime(CLOCK_MONOTONIC, &now);
        double waited_s = (double)(now.tv_sec - t0.tv_sec) + 1e-9 * (double)(now.tv_nsec - t0.tv_nsec);
        if (fc->o.wait_fn)
            fc->o.wait_fn(fc->o.wait_user, key, waited_s);
        if (waited_s > fc->o.wait_timeout_s) {
            core_err_set(err, -1, "airwake %s: still not built after %.0f s", name, fc->o.wait_timeout_s);
            break;
        }
        double s = fc->o.poll_s;
        struct timespec ts = {(time_t)s, (long)((s - (double)(time_t)s) * 1e9)};
        nanosleep(&ts, NULL);
    }
    if (announced)
        awdb_wait_unmark(fc->db, key);
    return f;
}

void awdb_key_ship_only(awdb_key *k, const char *ship, const char *aircraft, double speed_mps, double dir_rad,
                        core_grid_level grid)
{
    memset(k, 0, sizeof *k);
    snprintf(k->ship, sizeof k->ship, "%s", ship);
    snprintf(k->aircraft, sizeof k->aircraft, "%s", aircraft ? aircraft : "");
    k->wod_speed_mps = speed_mps;
    k->wod_dir_rad = dir_rad;
    k->grid = grid;
    k->rotor = CORE_ROTOR_OFF;
}

int awdb_fields_ship_only_air(awdb_fields *fc, const char *ship, const char *aircraft, core_grid_level grid,
                              double ref_speed_mps, double speed_mps, double dir_rad, cfd_field_scaled *air,
                              core_err *err)
{
    awdb_key k;
    awdb_key_ship_only(&k, ship, aircraft, ref_speed_mps, dir_rad, grid);
    air->field = awdb_fields_get(fc, &k, err);
    air->scale = speed_mps / ref_speed_mps;
    return air->field ? 0 : -1;
}

struct cfd_field *awdb_zone_boundary(awdb *db, const awdb_key *k, core_err *err)
{
    awdb_key sk;
    awdb_key_zone_boundary(k, &sk);
    char name[200], path[1200];
    if (awdb_key_canon(&sk, err) != 0)
        return NULL;
    awdb_key_name(&sk, name, sizeof name);
    if (!db) {
        core_err_set(err, -1, "deck zone: no database to read the ship-only field %s from", name);
        return NULL;
    }
    if (awdb_query(db, &sk, path, sizeof path) != AWDB_READY) {
        core_err_set(err, -1,
                     "deck zone: its boundary, the ship-only field %s, is not in the database %s (request it "
                     "before the zone)",
                     name, awdb_dir(db));
        return NULL;
    }
    return cfd_field_load(path, err);
}

int awdb_key_spec(const awdb_key *k, const core_ship *ship, cfd_airwake_spec *spec, core_err *err)
{
    const char *iso = strstr(k->ship, ".isolated");
    memset(spec, 0, sizeof *spec);
    spec->ship = ship;
    spec->wod_speed_mps = k->wod_speed_mps;
    spec->wod_dir_rad = k->wod_dir_rad;
    spec->level = k->grid;
    spec->rotor = k->rotor;
    spec->monitor_z_m = awdb_key_monitor_z_m(k);
    spec->open_ship = iso && iso[9] == '\0';
    if (k->rotor != CORE_ROTOR_OFF && awdb_key_disk(k, &spec->disk) != 0)
        return core_err_set(err, -1, "airwake key %s: no rotor disk", k->ship);
    if (k->zone_ref_mps > 0.0) {
        spec->zone = 1;
        if (k->rotor == CORE_ROTOR_OFF) { /* the zone's ship-only field: the box from the station and radius */
            memcpy(spec->disk.centre_m, k->station_S_m, sizeof spec->disk.centre_m);
            spec->disk.radius_m = k->radius_m;
        }
    }
    return 0;
}
