/* cmd_check.c -- disim check FILE: load a scenario, an aircraft file or a
 * ship file fully and print what was resolved, or the first error (file,
 * line, key, why). The kind comes from the file's sections: [scenario] is a
 * scenario, [ship] or [block NAME] a ship file, [aircraft] or [main_rotor]
 * an aircraft file; [task] a task file, which is refused with a pointer to
 * the scenario that names it; anything else is read as a scenario (whose
 * loader then says what is missing). Warnings of the loaders go to standard error; the
 * last line on standard output says which kind was checked:
 * "aircraft file PATH: NAME, ok". */
#include "cmds.h"
#include "core.h"
#include "sim.h"
#ifdef DISIM_HAVE_HFM
#include "hfm.h"
#endif
#ifdef DISIM_HAVE_SHOL
#include "shol.h"
#endif

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

enum { KIND_SCENARIO, KIND_AIRCRAFT, KIND_SHIP, KIND_TASK };

/* The kind of file path is, from its sections; -1 (err set) if it cannot be read. */
static int file_kind(const char *path, core_err *err)
{
    if (core_file_regular(path, SIM_SCENARIO_MAX_BYTES, err) != 0) /* /dev/zero, a FIFO: refused unread */
        return -1;
    core_ini *ini = core_ini_load(path, err);
    if (!ini)
        return -1;
    int kind = KIND_SCENARIO;
    if (core_ini_has_section(ini, "scenario"))
        kind = KIND_SCENARIO;
    else if (core_ini_has_section(ini, "ship"))
        kind = KIND_SHIP;
    else if (core_ini_has_section(ini, "aircraft") || core_ini_has_section(ini, "main_rotor"))
        kind = KIND_AIRCRAFT;
    else if (core_ini_has_section(ini, "task"))
        kind = KIND_TASK;
    else
        for (size_t i = 0; i < core_ini_count(ini); i++)
            if (!strncmp(core_ini_at(ini, i)->section, "block ", 6))
                kind = KIND_SHIP;
    core_ini_destroy(ini);
    return kind;
}

#ifdef DISIM_HAVE_HFM
/* The aircraft file in full: every parameter, the consistency checks and the
 * rejection criteria. 0, or 1 after printing the error. */
static int check_aircraft(const char *path, const core_log *log, char *name, size_t n)
{
    core_err err = {0};
    hfm_aircraft *ac = hfm_aircraft_load(path, log, &err);
    if (!ac) {
        fprintf(stderr, "disim check: %s\n", err.msg);
        return 1;
    }
    hfm_aircraft_figures f;
    hfm_aircraft_get_figures(ac, &f);
    printf("[aircraft]\nname = %s\nmass_kg = %.1f\nrotor_radius_m = %.3f\nrotor_omega_radps = %.3f\nblades = %d\n"
           "tip_speed_mps = %.1f\nsolidity = %.4f\nlift_slope_per_rad = %.2f\nlock_number = %.2f\n"
           "flap_frequency_per_rev = %.3f (hinge offset alone %.3f, spring alone %.3f)\n"
           "disk_loading_Pa = %.0f\nhover_ct_over_sigma = %.4f\n"
           "hover_pitch_75_deg = %.1f (estimate; the collective gives %.1f to %.1f at 0.75 R)\n"
           "tail_rotor_tip_speed_mps = %.1f\ntail_rotor_solidity = %.3f\nfuselage_drag_area_m2 = %.3f\n",
           hfm_aircraft_name(ac), hfm_aircraft_mass_kg(ac), hfm_aircraft_rotor_radius_m(ac),
           hfm_aircraft_rotor_omega_radps(ac), hfm_aircraft_blades(ac), f.tip_speed_mps, f.solidity,
           f.lift_slope_per_rad, f.lock_number, f.flap_freq_per_rev, f.flap_freq_offset_per_rev,
           f.flap_freq_spring_per_rev, f.disk_loading_Pa, f.ct_over_sigma_hover, f.hover_pitch75_deg,
           f.coll_pitch75_min_deg, f.coll_pitch75_max_deg, f.tr_tip_speed_mps, f.tr_solidity, f.drag_area_m2);
    snprintf(name, n, "%s", hfm_aircraft_name(ac));
    hfm_aircraft_destroy(ac);
#ifdef DISIM_HAVE_SHOL
    shol_criteria crit;
    if (shol_criteria_load(path, &crit, &err) != 0) {
        fprintf(stderr, "disim check: %s\n", err.msg);
        return 1;
    }
    printf("\n[rejection]\nroll_deg = %g\npitch_deg = %g\nlong_cyclic_pct = %g\nlat_cyclic_pct = %g\n"
           "collective_pct = %g\npedal_pct = %g\n",
           crit.roll_max_rad * CORE_RAD_TO_DEG, crit.pitch_max_rad * CORE_RAD_TO_DEG, crit.long_cyclic_pct,
           crit.lat_cyclic_pct, crit.collective_pct, crit.pedal_pct);
#endif
    return 0;
}
#endif

static int check_ship(const char *path, const core_log *log, char *name, size_t n)
{
    core_err err = {0};
    core_ship *ship = malloc(sizeof *ship);
    if (!ship)
        return 1;
    if (core_ship_load_log(path, ship, log, &err)) {
        fprintf(stderr, "disim check: %s\n", err.msg);
        free(ship);
        return 1;
    }
    printf("[ship]\nname = %s\nlength_m = %.2f\nbeam_m = %.2f\ndraft_m = %.2f\ndeck_height_m = %.2f\n"
           "deck_x_m = %g, %g\ndeck_halfwidth_m = %g\nanemometer_S_m = %g, %g, %g\nblocks = %d\n"
           "mirror_symmetric = %s\n",
           ship->name, ship->length_m, ship->beam_m, ship->draft_m, ship->deck_height_m, ship->deck_x0_m,
           ship->deck_x1_m, ship->deck_halfwidth_m, ship->anemometer_S_m[0], ship->anemometer_S_m[1],
           ship->anemometer_S_m[2], ship->nblocks, core_ship_mirror_symmetric(ship, 1e-6) ? "yes" : "no");
    snprintf(name, n, "%s", ship->name);
    free(ship);
    return 0;
}

static int check_scenario(const char *path, const core_log *log, char *name, size_t n)
{
    sim_scenario *sc = malloc(sizeof *sc);
    if (!sc)
        return 1;
    core_err err = {0};
    if (sim_scenario_load(path, sc, &err)) {
        fprintf(stderr, "disim check: %s\n", err.msg);
        free(sc);
        return 1;
    }
    /* the ship again, for its warnings (the scenario loader loaded it without a log) */
    core_ship *ship = malloc(sizeof *ship);
    if (ship)
        (void)core_ship_load_log(sc->ship_path, ship, log, &err);
    free(ship);
    sim_scenario_print(sc, stdout);
    int rc = 0;
#ifdef DISIM_HAVE_HFM
    char acname[64];
    printf("\n");
    rc = check_aircraft(sc->aircraft_path, log, acname, sizeof acname);
#endif
    snprintf(name, n, "%s", sc->name);
    free(sc);
    return rc;
}

int cmd_check(int argc, char **argv)
{
    if (argc != 2 || argv[1][0] == '-') {
        fprintf(stderr, "usage: disim check FILE.ini   (a scenario, an aircraft file or a ship file)\n");
        return 2;
    }
    const char *path = argv[1];
    app_log al = {"disim check", isatty(2)};
    core_log log = {app_log_stderr, &al, CORE_LOG_WARN};
    core_err err = {0};
    int kind = file_kind(path, &err);
    if (kind < 0) {
        fprintf(stderr, "disim check: %s\n", err.msg);
        return 1;
    }
    char name[64] = "";
    int rc;
    const char *what;
    switch (kind) {
    case KIND_AIRCRAFT:
        what = "aircraft file";
#ifdef DISIM_HAVE_HFM
        rc = check_aircraft(path, &log, name, sizeof name);
#else
        fprintf(stderr, "disim check: %s: an aircraft file, and this disim is built without hfm\n", path);
        rc = 1;
#endif
        break;
    case KIND_TASK:
        /* a task's deck-edge points need the ship: checked through its scenario */
        fprintf(stderr,
                "disim check: %s: a task file ([task]): check it through the scenario that names it "
                "([task] file), as its positions may need the ship\n",
                path);
        return 1;
    case KIND_SHIP:
        what = "ship file";
        rc = check_ship(path, &log, name, sizeof name);
        break;
    default:
        what = "scenario file";
        rc = check_scenario(path, &log, name, sizeof name);
        break;
    }
    if (rc)
        return 1;
    printf("\n%s %s: %s, ok\n", what, path, name);
    return 0;
}
