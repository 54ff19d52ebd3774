/* scenario.c -- what a scenario file asks of the SHOL pipeline: the
 * envelope's directions, speeds and rejection criteria (the aircraft
 * file's [shol] section), and the coupling's grid, rotor disk, domain,
 * hover-over-spot station and mode. The one place a scenario becomes these
 * settings; a command's flags then override them. */
#include "couple_priv.h"
#include "sim.h"

#include <string.h>

int couple_shol_settings_scenario(shol_settings *set, const sim_scenario *sc, core_err *err)
{
    shol_settings_default(set);
    if (sc->sea.state > 0)
        return core_err_set(err, -1, "%s: [sea] state = %d: the candidate SHOL trims the aircraft over a ship at rest; "
                                     "the sea state is for the flight loop (disim fly): set state = 0 or remove it",
                            sc->path, sc->sea.state);
    if (shol_criteria_load(sc->aircraft_path, &set->criteria, err) != 0)
        return -1;
    if (sc->wod_mode == SIM_WOD_SWEEP) {
        set->n_dirs = sc->n_dirs;
        memcpy(set->dirs_rad, sc->dirs_rad, (size_t)sc->n_dirs * sizeof(double));
        set->speed_step_mps = sc->speed_step_mps;
        set->speed_max_mps = sc->speed_max_mps;
    } else {
        set->n_dirs = 1;
        set->dirs_rad[0] = sc->wod_dir_rad;
    }
    return 0;
}

void couple_settings_scenario(couple_settings *cs, const sim_scenario *sc)
{
    couple_settings_default(cs);
    cs->mode = sc->coupling;
    cs->grid = sc->grid;
    cs->zone = sc->coupled_zone;
    /* [cfd] rotor: the disk of the coupled solves (loaded: the trim's blade loads) */
    cs->uniform_disk = sc->rotor == CORE_ROTOR_UNIFORM;
    memcpy(cs->station_S_m, sc->station_S_m, sizeof cs->station_S_m);
}
