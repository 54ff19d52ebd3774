/* test_foam_blade.c -- the blade-element rotor (OpenFOAM's rotorDisk)
 * through the airwake builder's OpenFOAM engine: SFS2 in a 15 m/s head
 * wind on the quick grid, the rotor of the UH-60A (counter-clockwise seen
 * from above) and of the SA365N (clockwise) trimmed in the free-air WOD by
 * the flight model (couple_free_air_rotor, as `disim airwake` and the
 * sweeps make their keys), each built by the engine from its key with the
 * blades of its aircraft file, mpirun -np 2, 60 iterations.
 *
 * Checked: the thrust rotorDisk puts into the air, integrated from its
 * force field at the last iteration, within 1 % of the helicopter's (the
 * key's); the air below the disk moves down through it; the torque the
 * blades' drag puts into the air turns it in the rotor's sense, and is
 * less than the flight model's shaft torque (rotorDisk has no induced
 * torque);
 * a key whose aircraft has no file is refused with its name. Skips (77)
 * where OpenFOAM or mpirun is absent; under CI that fails. Run as
 * `test_foam blade` (test_foam.c). */
#include "awdb.h"
#include "cfd.h"
#include "check.h"
#include "core.h"
#include "couple.h"
#include "foam.h"
#include "hfm.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

int test_foam_blade(void);

static void log_stderr(void *user, int lv, const char *msg)
{
    (void)user;
    (void)lv;
    fprintf(stderr, "  %s\n", msg);
}

static int progress(void *user, double frac, double res, int iter)
{
    (void)user, (void)frac, (void)res, (void)iter;
    return 0;
}

/* The key of aircraft file ac_path's rotor, trimmed in free air at 15 m/s
 * from ahead, 8 m above SFS2's spot. 0 or -1. */
static int blade_key(const char *ac_path, awdb_key *k, const core_log *log)
{
    core_err err = {0};
    hfm_aircraft *ac = hfm_aircraft_load(ac_path, log, &err);
    if (!ac) {
        fprintf(stderr, "%s\n", err.msg);
        return -1;
    }
    memset(k, 0, sizeof *k);
    snprintf(k->ship, sizeof k->ship, "SFS2");
    snprintf(k->aircraft, sizeof k->aircraft, "%s", hfm_aircraft_name(ac));
    k->wod_speed_mps = 15.0;
    k->wod_dir_rad = 0.0;
    k->grid = CORE_GRID_QUICK;
    double station[3] = {0.0, 0.0, -8.0};
    int rc = couple_free_air_rotor(ac, station, k->wod_speed_mps, k->wod_dir_rad, 1, k, &err);
    if (rc != 0)
        fprintf(stderr, "%s: the free-air trim: %s\n", ac_path, err.msg);
    hfm_aircraft_destroy(ac);
    return rc == 0 ? 0 : -1;
}

/* Build the key through the engine and check the field. */
static void check_rotor(awdb_engine *eng, const awdb_key *k, const char *tmp)
{
    char out[1300];
    snprintf(out, sizeof out, "%s/%s.h5", tmp, k->aircraft);
    core_err err = {0};
    int rc = eng->build(eng->user, k, NULL, out, progress, NULL, &err);
    if (rc != 0)
        fprintf(stderr, "%s: %s\n", k->aircraft, err.msg);
    CHECK(rc == 0);
    cfd_field *f = rc == 0 ? cfd_field_load(out, &err) : NULL;
    CHECK(f != NULL);
    if (!f)
        return;
    const cfd_meta *m = cfd_field_meta(f);
    double dev = m->rotor_force_N / k->thrust_N - 1.0;
    /* 2 m below the hub: the downwash */
    const double *h = k->station_S_m;
    double down[CFD_NVARS], pd[3] = {h[0], h[1], h[2] + 2.0};
    cfd_field_sample(f, pd, down);
    printf("%s (%s from above): rotor_model %s, thrust %.0f N for %.0f N (%+.3f %%); 2 m below the hub w %.2f m/s; "
           "torque into the air %.0f N m in the rotor's sense (the flight model's shaft torque %.0f N m)\n",
           k->aircraft, k->ccw_from_above ? "counter-clockwise" : "clockwise", m->rotor_model, m->rotor_force_N,
           k->thrust_N, 100.0 * dev, down[CFD_VAR_W], m->rotor_torque_Nm, k->torque_Nm);
    CHECK(!strcmp(m->rotor_model, "rotorDisk"));
    CHECK(!strcmp(m->engine, "openfoam"));
    CHECK(fabs(dev) <= 0.01);
    CHECK(down[CFD_VAR_W] > 2.0);
    /* the blades' drag turns the air with the rotor: less than the shaft
     * torque, which has the induced part rotorDisk leaves out */
    CHECK(m->rotor_torque_Nm > 0.05 * k->torque_Nm && m->rotor_torque_Nm < k->torque_Nm);
    cfd_field_destroy(f);
    remove(out);
}

int test_foam_blade(void)
{
    core_log log = {log_stderr, NULL, CORE_LOG_INFO};
    char tmp[] = "/tmp/test_foam_blade_XXXXXX";
    CHECK(mkdtemp(tmp) != NULL);
    foam_opts o;
    foam_opts_default(&o);
    o.np = 2;
    o.max_iter = 60;
    o.log = &log;
    o.work_dir = tmp;
    char why[256];
    if (!foam_available(&o, why, sizeof why)) {
        rmdir(tmp);
        check_skip(why);
        return check_done("test_foam_blade");
    }
    core_err err = {0};
    foam_engine *fe = foam_engine_create("scenarios/ships", "scenarios/aircraft", &o, &err);
    CHECK(fe != NULL);
    if (!fe) {
        fprintf(stderr, "%s\n", err.msg);
        return check_done("test_foam_blade");
    }
    awdb_engine eng;
    foam_engine_get(fe, &eng);
    awdb_key k;
    CHECK(blade_key("scenarios/aircraft/uh60a.ini", &k, &log) == 0);
    CHECK(k.ccw_from_above == 1 && k.rotor == CORE_ROTOR_LOADED);
    check_rotor(&eng, &k, tmp);
    CHECK(blade_key("scenarios/aircraft/sa365n.ini", &k, &log) == 0);
    CHECK(k.ccw_from_above == 0);
    check_rotor(&eng, &k, tmp);

    /* an aircraft without a file: refused before OpenFOAM runs, by name */
    snprintf(k.aircraft, sizeof k.aircraft, "XH-99");
    char out[1300];
    snprintf(out, sizeof out, "%s/none.h5", tmp);
    int rc = eng.build(eng.user, &k, NULL, out, progress, NULL, &err);
    printf("unknown aircraft: rc %d: %s\n", rc, err.msg);
    CHECK(rc < 0 && strstr(err.msg, "XH-99") != NULL);
    CHECK(access(out, F_OK) != 0);
    foam_engine_destroy(fe);
    rmdir(tmp);
    return check_done("test_foam_blade");
}
