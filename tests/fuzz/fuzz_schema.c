/* fuzz_schema.c -- libFuzzer harnesses of the readers of the files people
 * write, each on its input in memory, exactly as their path loaders run on
 * a file's text: one source built as five harnesses (FUZZ_SCHEMA):
 *   fuzz_scenario   core_ini_parse, sim_scenario_from_ini (every section,
 *                   the aircraft, ship and task files it names resolved from
 *                   scenarios/, as the input is named scenarios/fuzz.ini:
 *                   run from the source root)
 *   fuzz_aircraft   core_ini_parse, hfm_aircraft_from_ini (every section,
 *                   the physical checks)
 *   fuzz_ship       core_ini_parse, core_ship_from_ini (with the consistency
 *                   warnings on a log), then core_ship_contains and
 *                   core_ship_mirror_symmetric on the ship read
 *   fuzz_task       core_ini_parse, sim_task_from_ini against the CG-47
 *                   (read once), both file forms (legacy and phases)
 *   fuzz_station_script  sim_station_script_parse, then
 *                   sim_station_script_at across the script's times
 * Checked, beyond no crash, hang, leak or sanitizer report: a refused input
 * says why (err set); what a script gives is a percentage 0 to 100. */
#include "hfm.h"
#include "sim.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerInitialize(int *argc, char ***argv);

#define SCHEMA_SCENARIO 1
#define SCHEMA_AIRCRAFT 2
#define SCHEMA_SHIP 3
#define SCHEMA_TASK 4
#define SCHEMA_SCRIPT 5

#if FUZZ_SCHEMA == SCHEMA_TASK
static core_ship cg47;
#endif

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc, (void)argv;
#if FUZZ_SCHEMA == SCHEMA_TASK
    core_err err = {0};
    if (core_ship_load("scenarios/ships/cg47.ini", &cg47, &err) != 0) {
        fprintf(stderr, "fuzz_task: %s (run from the source root)\n", err.msg);
        exit(1);
    }
#endif
    return 0;
}

#if FUZZ_SCHEMA == SCHEMA_AIRCRAFT || FUZZ_SCHEMA == SCHEMA_SHIP
/* every message the readers log is formatted and read */
static volatile size_t logged;
static void log_sink(void *user, int level, const char *msg)
{
    (void)user, (void)level;
    logged += strlen(msg);
}
static const core_log fuzz_log = {log_sink, NULL, 100};
#endif

static void refused(const core_err *err)
{
    if (!err->msg[0])
        abort(); /* refused without a word */
}

#if FUZZ_SCHEMA != SCHEMA_SCRIPT
static void run_ini(const char *text, size_t size)
{
    core_err err = {0};
    core_ini *ini = core_ini_parse(text, size, "scenarios/fuzz.ini", &err);
    if (!ini) {
        refused(&err);
        return;
    }
#if FUZZ_SCHEMA == SCHEMA_SCENARIO
    sim_scenario *sc = malloc(sizeof *sc);
    if (!sc)
        abort();
    if (sim_scenario_from_ini(ini, sc, &err) != 0)
        refused(&err);
    free(sc);
#elif FUZZ_SCHEMA == SCHEMA_AIRCRAFT
    hfm_aircraft *ac = hfm_aircraft_from_ini(ini, &fuzz_log, &err);
    if (!ac)
        refused(&err);
    else if (!(hfm_aircraft_mass_kg(ac) > 0.0) || !isfinite(hfm_aircraft_weight_N(ac)))
        abort(); /* taken, but not a physical aircraft */
    hfm_aircraft_destroy(ac);
#elif FUZZ_SCHEMA == SCHEMA_SHIP
    core_ship *ship = malloc(sizeof *ship);
    if (!ship)
        abort();
    if (core_ship_from_ini(ini, ship, &fuzz_log, &err) != 0)
        refused(&err);
    else {
        core_vec3 p = {0.5 * (ship->deck_x0_m + ship->deck_x1_m), 0.0, -ship->deck_height_m};
        (void)core_ship_contains(ship, p);
        (void)core_ship_mirror_symmetric(ship, 0.01);
    }
    free(ship);
#elif FUZZ_SCHEMA == SCHEMA_TASK
    sim_task *t = malloc(sizeof *t);
    if (!t)
        abort();
    if (sim_task_from_ini(ini, &cg47, t, &err) != 0)
        refused(&err);
    free(t);
#endif
    core_ini_destroy(ini);
}
#endif

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
#if FUZZ_SCHEMA == SCHEMA_SCRIPT
    core_err err = {0};
    sim_station_script *s = sim_station_script_parse((const char *)data, size, "fuzz.csv", &err);
    if (!s) {
        refused(&err);
        return 0;
    }
    static const double t_s[] = {0.0, 0.001, 0.5, 1.0, 2.5, 10.0, 1e3, 1e9, 1e300};
    for (size_t i = 0; i < sizeof t_s / sizeof t_s[0]; i++) {
        sim_station_controls c;
        sim_station_script_at(s, t_s[i], &c);
        const double v[4] = {c.ctl.collective_pct, c.ctl.long_cyclic_pct, c.ctl.lat_cyclic_pct, c.ctl.pedal_pct};
        for (int k = 0; k < 4; k++)
            if (!(v[k] >= 0.0 && v[k] <= 100.0))
                abort(); /* a control out of its travel (or NaN) */
    }
    sim_station_script_destroy(s);
#else
    run_ini((const char *)data, size);
#endif
    return 0;
}
