/* embedded.c -- the embedded CFD engine for the builder: a key becomes a
 * cfd_airwake_spec (ship from the ships folder by name, WOD, grid level,
 * uniform actuator disk at the key's station, radius, thrust and shaft tilt;
 * a deck zone with the database's ship-only field as its boundary),
 * warm-started from the nearest finished field, run to convergence and
 * written as HDF5 to the builder's temporary path. A run that stops at the
 * iteration limit is kept (its metadata says not converged) and logged. */
#include "awdb.h"
#include "cfd.h"

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct awdb_embedded {
    const core_log *log;
    int nships;
    core_ship *ships;
    int max_iter;
    int threads; /* OpenMP threads per build (at least) */
    int pool;    /* cores of the machine: a build alone takes them all */
    int active;  /* builds running now (atomic) */
    awdb *db;    /* where deck-zone builds find their ship-only field */
};

void awdb_embedded_set_db(awdb_embedded *e, awdb *db)
{
    e->db = db;
}

awdb_embedded *awdb_embedded_create(const char *ships_dir, int max_iter, int threads,
                                    const core_log *log, core_err *err)
{
    awdb_embedded *e = calloc(1, sizeof *e);
    if (!e) {
        core_err_set(err, -1, "out of memory");
        return NULL;
    }
    e->log = log;
    e->max_iter = max_iter;
    e->threads = threads > 0 ? threads : 1;
    e->pool = omp_get_num_procs();
    if (core_ship_load_dir(ships_dir, &e->ships, &e->nships, err) != 0) {
        awdb_embedded_destroy(e);
        return NULL;
    }
    return e;
}

void awdb_embedded_destroy(awdb_embedded *e)
{
    if (!e)
        return;
    free(e->ships);
    free(e);
}

typedef struct prog_adapter {
    awdb_progress_fn fn;
    void *user;
    awdb_embedded *e;
} prog_adapter;

/* The cores a build may use now: its share of the machine among the builds
 * running. Why: a coupled point's isolated rotor finishes in a fifth of the
 * coupled field's time, and the coupled field then ran on one core of two
 * (a pair on the CG-47 deck zone: 27 s with one thread). */
static int share(awdb_embedded *e)
{
    int n = __atomic_load_n(&e->active, __ATOMIC_RELAXED);
    int t = n > 0 ? e->pool / n : e->pool;
    return t > e->threads ? t : e->threads;
}

static int on_cfd_progress(void *user, int iter, int max_iter, double residual, double elapsed_s)
{
    (void)elapsed_s;
    prog_adapter *p = user;
    /* each iteration's parallel regions take this thread's current share */
    omp_set_num_threads(share(p->e));
    if (!p->fn) /* no progress wanted */
        return 0;
    return p->fn(p->user, max_iter > 0 ? (double)iter / max_iter : 0.0, residual, iter);
}

static int build_one(awdb_embedded *e, const awdb_key *k, const char *warm, const char *out,
                     awdb_progress_fn progress, void *pu, core_err *err);

/* The database keeps the HDF5 file only: the XDMF side file the writer
 * adds would name the temporary. */
static void drop_xmf(const char *out)
{
    char xmf[1100];
    snprintf(xmf, sizeof xmf, "%s.xmf", out);
    remove(xmf);
    size_t l = strlen(out);
    if (l > 3 && !strcmp(out + l - 3, ".h5")) {
        snprintf(xmf, sizeof xmf, "%.*s.xmf", (int)(l - 3), out);
        remove(xmf);
    }
}

/* The key whose mirror image is k's field: a whole-domain ship-only field
 * of a ship symmetric about its centre line, from a wind off the centre
 * line (head and stern winds are their own images). Why: the RANS problem
 * is then mirror-symmetric, so green D is red D reflected, and a one-way
 * envelope of 7 directions needs 4 solves, not 7. */
static int mirror_source(void *user, const awdb_key *k, awdb_key *src)
{
    const awdb_embedded *e = user;
    if (k->rotor != CORE_ROTOR_OFF || k->zone_ref_mps > 0.0 || strchr(k->ship, '.'))
        return 0;
    double d = k->wod_dir_rad;
    if (fabs(d) < 1e-9 || fabs(fabs(d) - M_PI) < 1e-9)
        return 0;
    const core_ship *ship = core_ship_find(e->ships, e->nships, k->ship, strlen(k->ship));
    if (!ship || !core_ship_mirror_symmetric(ship, 1e-6))
        return 0;
    *src = *k;
    src->wod_dir_rad = -d;
    src->station_S_m[1] = -k->station_S_m[1];
    src->shaft_roll_rad = -k->shaft_roll_rad;
    core_err err = {0};
    return awdb_key_canon(src, &err) == 0;
}

/* k's field as the mirror image of its source's when that is in the
 * database: 0 written, 1 not available (solve instead), < 0 failed. */
static int build_mirror(awdb_embedded *e, const awdb_key *k, const char *out, core_err *err)
{
    awdb_key src;
    char path[1200], name[200];
    if (!e->db || !mirror_source(e, k, &src) || awdb_query(e->db, &src, path, sizeof path) != AWDB_READY)
        return 1;
    awdb_key_name(&src, name, sizeof name);
    cfd_field *f = cfd_field_load(path, err);
    cfd_field *m = f ? cfd_field_mirror_y(f, err) : NULL;
    cfd_field_destroy(f);
    if (!m) {
        core_log_msg(e->log, CORE_LOG_WARN, "mirror of %s refused (%s): solving", name, err->msg);
        return 1;
    }
    int rc = cfd_field_write(m, out, err);
    cfd_field_destroy(m);
    drop_xmf(out);
    if (rc == 0)
        core_log_msg(e->log, CORE_LOG_INFO, "%s v=%.2f dir=%.1f: the mirror image of %s (the ship is symmetric)",
                     k->ship, k->wod_speed_mps, k->wod_dir_rad * CORE_RAD_TO_DEG, name);
    return rc;
}

static int build(void *user, const awdb_key *k, const char *warm, const char *out,
                 awdb_progress_fn progress, void *pu, core_err *err)
{
    awdb_embedded *e = user;
    int rc = build_mirror(e, k, out, err);
    if (rc <= 0)
        return rc;
    /* Builds run side by side in threads: share the cores among them (and
     * again at every iteration, as builds start and finish). */
    __atomic_add_fetch(&e->active, 1, __ATOMIC_RELAXED);
    omp_set_num_threads(share(e));
    rc = build_one(e, k, warm, out, progress, pu, err);
    __atomic_sub_fetch(&e->active, 1, __ATOMIC_RELAXED);
    return rc;
}

static int build_one(awdb_embedded *e, const awdb_key *k, const char *warm, const char *out,
                     awdb_progress_fn progress, void *pu, core_err *err)
{
    /* "NAME.isolated": the ship's grid and boundaries with its cells open. */
    const char *iso = strstr(k->ship, ".isolated");
    int open_ship = iso && iso[9] == '\0';
    size_t base_len = open_ship ? (size_t)(iso - k->ship) : strlen(k->ship);
    const core_ship *ship = core_ship_find(e->ships, e->nships, k->ship, base_len);
    if (!ship)
        return core_err_set(err, -1, "ship '%s': no ship file of that name", k->ship);
    cfd_airwake_spec spec;
    if (awdb_key_spec(k, ship, &spec, err) != 0)
        return -1;
    spec.max_iter = e->max_iter;
    cfd_field *outer = NULL; /* a deck zone's boundary field; outlives the solver */
    if (spec.zone && !open_ship) {
        if (!(outer = awdb_zone_boundary(e->db, k, err)))
            return -1;
        spec.zone_field = outer;
        spec.zone_scale = k->wod_speed_mps / k->zone_ref_mps;
    }
    prog_adapter pa = {progress, pu, e};
    cfd_solver *s = cfd_airwake_create(&spec, e->log, on_cfd_progress, &pa, err);
    if (!s) {
        cfd_field_destroy(outer);
        return -1;
    }
    int rc = 0;
    if (warm) {
        cfd_field *f = cfd_field_load(warm, err);
        rc = f ? cfd_solver_init_from_field(s, f, err) : -1;
        cfd_field_destroy(f);
        if (rc) {
            core_log_msg(e->log, CORE_LOG_WARN, "warm start from %s refused (%s): starting cold", warm, err->msg);
            cfd_solver_init_inflow(s);
            rc = 0;
        }
    }
    cfd_result res;
    rc = cfd_solver_run(s, &res, err);
    if (rc < 0 && warm) {
        /* A neighbour's wake 30 deg away can start a solution that diverges
         * where the uniform inflow converges (CG-47 red 90 with the rotor
         * from a red 60 field): one more run from the inflow before the
         * field is marked failed. */
        core_log_msg(e->log, CORE_LOG_WARN, "%s v=%.2f dir=%.1f: diverged from the warm start (%s); starting cold",
                     k->ship, k->wod_speed_mps, k->wod_dir_rad * CORE_RAD_TO_DEG, err->msg);
        cfd_solver_init_inflow(s);
        rc = cfd_solver_run(s, &res, err);
    }
    /* stopped from outside (the builder's SIGTERM, rc 1): no field, and no
     * "not converged" warning, the caller puts the request back */
    if (rc > 0 && res.stopped)
        core_log_msg(e->log, CORE_LOG_INFO, "%s v=%.2f dir=%.1f: stopped after %d iterations, nothing written",
                     k->ship, k->wod_speed_mps, k->wod_dir_rad * CORE_RAD_TO_DEG, res.iterations);
    if (rc < 0 || res.stopped) {
        cfd_solver_destroy(s);
        cfd_field_destroy(outer);
        return rc;
    }
    if (rc > 0)
        core_log_msg(e->log, CORE_LOG_WARN,
                     "%s v=%.2f dir=%.1f: not converged after %d iterations (residual %.2e)%s",
                     k->ship, k->wod_speed_mps, k->wod_dir_rad * CORE_RAD_TO_DEG, res.iterations, res.residual[0],
                     res.steady_mean ? "; the mean flow is steady: the field is the mean of the last iterations"
                     : res.averaged ? "; the field is the mean of the last iterations" : "");
    cfd_meta meta;
    memset(&meta, 0, sizeof meta);
    meta.wod_speed_mps = k->wod_speed_mps;
    meta.wod_dir_deg = k->wod_dir_rad * CORE_RAD_TO_DEG;
    snprintf(meta.ship, sizeof meta.ship, "%.63s", k->ship);
    snprintf(meta.rotor, sizeof meta.rotor, "%s", core_rotor_name(k->rotor));
    snprintf(meta.grid, sizeof meta.grid, "%s%s", core_grid_name(k->grid), spec.zone ? "-zone" : "");
    meta.rotor_thrust_N = k->thrust_N;
    meta.rotor_radius_m = k->radius_m;
    memcpy(meta.rotor_centre_S_m, k->station_S_m, sizeof meta.rotor_centre_S_m);
    meta.result = res;
    rc = cfd_solver_write(s, &meta, out, err);
    cfd_solver_destroy(s);
    cfd_field_destroy(outer);
    drop_xmf(out);
    return rc;
}

int awdb_key_disk(const awdb_key *k, cfd_disk *d)
{
    if (k->rotor == CORE_ROTOR_OFF)
        return -1;
    core_euler att = {k->shaft_roll_rad, k->shaft_pitch_rad, 0.0};
    cfd_disk_from_attitude(d, k->station_S_m, att, k->radius_m, k->thrust_N);
    if (k->rotor == CORE_ROTOR_LOADED) {
        d->nr = AWDB_LOAD_NR;
        d->npsi = AWDB_LOAD_NPSI;
        memcpy(d->load, k->load, sizeof k->load);
        memcpy(d->swirl, k->swirl, sizeof k->swirl);
        d->torque_Nm = k->torque_Nm;
        d->root_cut = k->root_cut;
        d->ccw_from_above = k->ccw_from_above;
    }
    return 0;
}

double awdb_key_monitor_z_m(const awdb_key *k)
{
    /* a ship-only key has no station (it serves every hover height) */
    return k->rotor == CORE_ROTOR_OFF ? -5.0 : k->station_S_m[2];
}

void awdb_embedded_engine(awdb_embedded *e, awdb_engine *eng)
{
    eng->name = "embedded";
    eng->build = build;
    eng->user = e;
    eng->source = mirror_source;
}
