/* test_sim.c -- scenario files resolve to the values their keys say, in SI,
 * with the conventions applied (WOD wrap and velocity, station in S), the
 * pilot and the piloted task, and every key that no command acts on is
 * refused naming file, line, key and why, never read and ignored. */
#include "check.h"
#include "sim.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* "scenarios/././.../cg47_uh60a.ini", its "./" repeated until the folder
 * part is at least min_len characters long */
static void dotted_path(char *buf, size_t size, size_t min_len)
{
    size_t n = (size_t)snprintf(buf, size, "scenarios/");
    while (n < min_len)
        n += (size_t)snprintf(buf + n, size - n, "./");
    snprintf(buf + n, size - n, "cg47_uh60a.ini");
}

/* A key or section that no command acts on yet: the file's first refused
 * entry (file:line: [section] key) and the reason. */
static const struct {
    const char *file, *where, *why;
} refusals[] = {
    {"refused_task_approach.ini", "refused_task_approach.ini:15: [task] approach_dir_deg: ",
     "not supported: the approach is the task file's, in its phases"},
    {"np_without_openfoam.ini", "np_without_openfoam.ini:17: [cfd] np: ", "only used with engine = openfoam"},
    {"refused_residual_tol.ini", "refused_residual_tol.ini:17: [cfd] residual_tol: ",
     "not supported: every airwake field is solved to the embedded solver's own convergence test"},
    {"refused_output_csv.ini", "refused_output_csv.ini:19: [output] csv: ",
     "not supported: disim shol always writes its CSV table, JSON, plots and report"},
    {"refused_output_plots.ini", "refused_output_plots.ini:20: [output] plots: ",
     "not supported: disim shol always writes its CSV table, JSON, plots and report"},
    /* the pilot and the piloted task: a key of another pilot, a task
     * without the automated pilot or the automated pilot without one, a
     * task file of the other kind */
    {"pilot_bad_type.ini", "pilot_bad_type.ini:16: [pilot] type = 'automated': ", "expected one of station|auto|replay"},
    {"pilot_replay_no_log.ini", "pilot_replay_no_log.ini: [pilot] log: ", "missing required key"},
    {"pilot_station_log.ini", "pilot_station_log.ini:18: [pilot] log: ", "only used with type = replay"},
    {"pilot_stations_twice.ini", "pilot_stations_twice.ini:14: [pilot] stations: ", "'a' appears twice"},
    {"pilot_auto_no_task.ini", "pilot_auto_no_task.ini:16: [pilot] type = auto: ",
     "the automated pilot flies the scenario's task; set [task] type = hover or landing"},
    {"task_hover_no_file.ini", "task_hover_no_file.ini: [task] file: ", "missing required key"},
    {"task_landing_station.ini", "task_landing_station.ini:13: [task] type = landing: ",
     "a piloted task is flown by the automated pilot; set [pilot] type = auto"},
    {"task_kind_mismatch.ini", "task_kind_mismatch.ini:14: [task] file = ",
     "a landing task, expected a station-keeping task for type = hover"},
    /* keys the file's other settings would leave unread */
    {"rotor_off_two_way.ini", "rotor_off_two_way.ini:17: [cfd] rotor = off: ",
     "the two-way coupling (coupling = two-way, the default) solves with the rotor's disk"},
    {"mode_key_domain.ini", "mode_key_domain.ini:18: [cfd] coupled_domain: ",
     "only used with coupling = two-way"},
};

int main(void)
{
    sim_scenario *sc = malloc(sizeof *sc);
    core_err err = {0};
    CHECK(sim_scenario_load("scenarios/sfs2_validation.ini", sc, &err) == 0);
    if (err.msg[0])
        fprintf(stderr, "%s\n", err.msg);
    CHECK(strcmp(sc->ship.name, "SFS2") == 0);
    CHECK(strcmp(sc->aircraft_name, "UH-60A") == 0);
    CHECK(sc->wod_mode == SIM_WOD_SINGLE);
    /* 29.16 kt = 15.00 m/s (the seed paper's 54 km/h). */
    CHECK_NEAR(sc->wod_speed_mps, 15.0, 0.01);
    CHECK_NEAR(sc->wod_dir_rad, 0.0, 1e-12);
    CHECK(sc->rotor == CORE_ROTOR_OFF && sc->grid == CORE_GRID_DEFAULT);
    CHECK_NEAR(sc->station_S_m[2], -6.8, 1e-12);
    /* no [cfd] max_iterations: 0, the solver's default */
    CHECK(sc->max_iterations == 0);
    CHECK(sc->coupling == CORE_COUPLING_ONE_WAY && sc->coupled_zone == 0);

    CHECK(sim_scenario_load("scenarios/cg47_uh60a.ini", sc, &err) == 0);
    CHECK(sc->wod_mode == SIM_WOD_SWEEP && sc->n_dirs == 7);
    CHECK_NEAR(sc->dirs_rad[0], -M_PI / 2, 1e-12);
    CHECK_NEAR(sc->dirs_rad[6], M_PI / 2, 1e-12);
    CHECK_NEAR(sc->speed_step_mps, 5.0 / 3.6, 1e-12);
    CHECK(sc->ship.nblocks >= 5);
    CHECK(sc->coupling == CORE_COUPLING_TWO_WAY && sc->coupled_zone == 1);

    CHECK(sim_scenario_load("scenarios/lpd17_sa365n.ini", sc, &err) == 0);
    CHECK(strcmp(sc->aircraft_name, "SA365N") == 0);
    CHECK(strcmp(sc->ship.name, "LPD-17") == 0);

    /* A load failure leaves a message naming the file. */
    CHECK(sim_scenario_load("tests/sim/bad/typo_key.ini", sc, &err) < 0);
    CHECK(strstr(err.msg, "typo_key.ini:10:") != NULL);

    /* A sweep step so small that the direction count overflows an int is
     * refused, not resolved to an empty (negative-count) sweep. */
    err.msg[0] = '\0';
    CHECK(sim_scenario_load("tests/sim/bad/sweep_step_overflow.ini", sc, &err) < 0);
    CHECK(strstr(err.msg, "sweep_step_overflow.ini:9: [wod] dir_deg") != NULL);
    /* A key of the other mode says which mode it needs. */
    CHECK(sim_scenario_load("tests/sim/bad/mode_key.ini", sc, &err) < 0);
    CHECK(strstr(err.msg, "mode_key.ini:10: [wod] speed_kt: only used with mode = single") != NULL);
    /* A full circle sweeps the stern once (-180 and 180 are one direction). */
    CHECK(sim_scenario_load("tests/sim/data/full_circle.ini", sc, &err) == 0);
    CHECK(sc->n_dirs == 12);
    CHECK(sc->max_iterations == 400);
    int sterns = 0;
    for (int i = 0; i < sc->n_dirs; i++)
        sterns += fabs(fabs(sc->dirs_rad[i]) - M_PI) < 1e-9;
    CHECK(sterns == 1);
    /* The sea and the turbulence as the flight loop reads them; absent, a
     * calm sea, the ship at rest and turbulence on. */
    CHECK(sim_scenario_load("tests/sim/data/sea.ini", sc, &err) == 0);
    CHECK(sc->sea.state == 4 && sc->sea.spectrum == SIM_SPECTRUM_JONSWAP && sc->turbulence == 0);
    CHECK_NEAR(sc->sea.ship_speed_mps, 15.0 * CORE_KT_TO_MPS, 1e-12);
    CHECK_NEAR(sc->sea.wave_dir_rad, -30.0 * CORE_DEG_TO_RAD, 1e-12);
    CHECK(sim_scenario_load("tests/sim/data/full_circle.ini", sc, &err) == 0);
    CHECK(sc->sea.state == 0 && sc->sea.ship_speed_mps == 0.0 && sc->sea.spectrum == SIM_SPECTRUM_ITTC && sc->turbulence == 1);
    CHECK(sim_scenario_load("tests/sim/bad/bad_sea_state.ini", sc, &err) < 0);
    CHECK(strstr(err.msg, "bad_sea_state.ini:13: [sea] state = 7: out of range, expected 0 to 6") != NULL);
    /* The pilot and the task as disim fly reads them; absent, the stations
     * (the first to connect) and the shol task. */
    CHECK(sim_scenario_load("tests/sim/data/pilot_auto.ini", sc, &err) == 0);
    CHECK(sc->pilot == SIM_SC_PILOT_AUTO && sc->task_type == SIM_TASK_LAND);
    CHECK(strstr(sc->task_path, "scenarios/tasks/land_port.ini") != NULL);
    CHECK(sim_scenario_load("tests/sim/data/pilot_station.ini", sc, &err) == 0);
    CHECK(sc->pilot == SIM_SC_PILOT_STATION && strcmp(sc->pilot_stations, "deck,cockpit") == 0);
    CHECK_NEAR(sc->pilot_hold_after_s, 1.5, 0);
    CHECK(sim_scenario_load("tests/sim/data/pilot_replay.ini", sc, &err) == 0);
    CHECK(sc->pilot == SIM_SC_PILOT_REPLAY && sc->pilot_feed_controls == 1 && strstr(sc->pilot_log, "sea.ini"));
    CHECK(sim_scenario_load("tests/sim/data/sea.ini", sc, &err) == 0);
    CHECK(sc->pilot == SIM_SC_PILOT_STATION && sc->pilot_stations[0] == '\0' && sc->pilot_hold_after_s == 0.0 &&
          sc->task_type == SIM_TASK_SHOL);
    /* A speed step larger than the sweep's top is refused naming the line. */
    CHECK(sim_scenario_load("tests/sim/bad/speed_step_over_max.ini", sc, &err) < 0);
    CHECK(strstr(err.msg, "speed_step_over_max.ini:10: [wod] speed_step_kmh = 20: expected at most") != NULL);
    /* A path longer than the scenario keeps is refused, not cut to another
     * file's name (which could exist: here the cut one would be the CG-47
     * scenario's folder). */
    {
        char longp[SIM_PATH_MAX + 64], okp[SIM_PATH_MAX];
        dotted_path(longp, sizeof longp, SIM_PATH_MAX + 20);
        CHECK(sim_scenario_load(longp, sc, &err) < 0);
        CHECK(strstr(err.msg, "scenario path longer than 511 characters") != NULL);
        /* and a long path that fits (with room for the aircraft and ship
         * paths resolved beside it) loads */
        dotted_path(okp, sizeof okp, 400);
        CHECK(sim_scenario_load(okp, sc, &err) == 0);
    }
    /* Each key that no command acts on is refused with its reason. */
    for (size_t i = 0; i < sizeof refusals / sizeof refusals[0]; i++) {
        char path[128];
        snprintf(path, sizeof path, "tests/sim/bad/%s", refusals[i].file);
        err.msg[0] = '\0';
        int rc = sim_scenario_load(path, sc, &err);
        CHECK(rc < 0);
        CHECK(strstr(err.msg, refusals[i].where) != NULL);
        CHECK(strstr(err.msg, refusals[i].why) != NULL);
        if (rc >= 0 || !strstr(err.msg, refusals[i].where) || !strstr(err.msg, refusals[i].why))
            fprintf(stderr, "  %s: got '%s'\n", refusals[i].file, rc < 0 ? err.msg : "(loaded)");
    }
    free(sc);
    return check_done("test_sim");
}
