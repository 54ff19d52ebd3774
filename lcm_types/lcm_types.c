/* lcm_types.c -- checks of received messages. LCM decodes any bytes that fit
 * the type, so NaNs, out-of-range percentages and unknown commands arrive
 * intact; a station's bad message must be refused with its field named, never
 * fed to the flight model. */
#include "disim_lcm.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static int pct_ok(double v) { return isfinite(v) && v >= 0.0 && v <= 100.0; }

int disim_lcm_check_pilot_input(const disim_pilot_input_t *m, char *err, size_t n)
{
    const char *bad = NULL;
    double v = 0.0;
    if (!m->station_id || !m->station_id[0])
        bad = "station_id";
    else if (m->seq < 0)
        bad = "seq";
    else if (!pct_ok(v = m->collective_pct))
        bad = "collective_pct";
    else if (!pct_ok(v = m->long_cyclic_pct))
        bad = "long_cyclic_pct";
    else if (!pct_ok(v = m->lat_cyclic_pct))
        bad = "lat_cyclic_pct";
    else if (!pct_ok(v = m->pedal_pct))
        bad = "pedal_pct";
    if (!bad)
        return 0;
    /* Say the value that was received: the id and seq have their own forms
     * (a "seq = 0" for a seq of -5 would send the reader the wrong way). */
    if (err && bad[0] == 's' && bad[1] == 't')
        snprintf(err, n, "pilot_input_t.station_id is empty: expected a non-empty id");
    else if (err && bad[0] == 's')
        snprintf(err, n, "pilot_input_t.seq = %lld: expected seq >= 0", (long long)m->seq);
    else if (err)
        snprintf(err, n, "pilot_input_t.%s = %g: expected a finite percentage 0 to 100", bad, v);
    return -1;
}

int disim_lcm_check_sim_control(const disim_sim_control_t *m, char *err, size_t n)
{
    if (m->command < DISIM_SIM_CONTROL_T_PAUSE || m->command > DISIM_SIM_CONTROL_T_LOAD_SCENARIO) {
        if (err)
            snprintf(err, n, "sim_control_t.command = %d: expected 1 (pause) to 4 (load scenario)",
                     m->command);
        return -1;
    }
    if (m->command == DISIM_SIM_CONTROL_T_LOAD_SCENARIO && (!m->scenario_path || !m->scenario_path[0])) {
        if (err)
            snprintf(err, n, "sim_control_t.scenario_path: expected a path with LOAD_SCENARIO");
        return -1;
    }
    return 0;
}

int disim_lcm_check_airwake_request(const disim_airwake_request_t *m, char *err, size_t n)
{
    const char *bad = NULL, *want = NULL;
    if (!m->request_id || !m->request_id[0])
        bad = "request_id", want = "a non-empty id";
    else if (!isfinite(m->wod_speed_mps) || m->wod_speed_mps < 0.0 || m->wod_speed_mps > 60.0)
        bad = "wod_speed_mps", want = "0 to 60 m/s";
    else if (!isfinite(m->wod_dir_rad) || fabs(m->wod_dir_rad) > M_PI + 1e-9)
        bad = "wod_dir_rad", want = "-pi to pi";
    else if (m->rotor < DISIM_AIRWAKE_REQUEST_T_ROTOR_OFF || m->rotor > DISIM_AIRWAKE_REQUEST_T_ROTOR_LOADED)
        bad = "rotor", want = "0 (off), 1 (uniform) or 2 (loaded)";
    else if (m->rotor != DISIM_AIRWAKE_REQUEST_T_ROTOR_OFF &&
             (!isfinite(m->rotor_thrust_N) || m->rotor_thrust_N <= 0.0))
        bad = "rotor_thrust_N", want = "a positive thrust with the rotor on";
    else if (m->rotor != DISIM_AIRWAKE_REQUEST_T_ROTOR_OFF &&
             (!isfinite(m->rotor_radius_m) || m->rotor_radius_m <= 0.1 || m->rotor_radius_m > 50.0))
        bad = "rotor_radius_m", want = "0.1 to 50 m with the rotor on";
    else if (!isfinite(m->shaft_pitch_rad) || fabs(m->shaft_pitch_rad) > 1.0)
        bad = "shaft_pitch_rad", want = "a finite shaft tilt within -1 to 1 rad";
    else if (!isfinite(m->shaft_roll_rad) || fabs(m->shaft_roll_rad) > 1.0)
        bad = "shaft_roll_rad", want = "a finite shaft tilt within -1 to 1 rad";
    /* The hub station too, as disim_lcm.h promises "every field finite":
     * a consumer other than airwaked has no awdb key check behind it. Same
     * bounds as awdb_key_canon, so nothing it takes is refused here. */
    else if (!isfinite(m->station_S_m[0]) || fabs(m->station_S_m[0]) > 1000.0 ||
             !isfinite(m->station_S_m[1]) || fabs(m->station_S_m[1]) > 1000.0 ||
             !isfinite(m->station_S_m[2]) || fabs(m->station_S_m[2]) > 1000.0)
        bad = "station_S_m", want = "three finite coordinates within -1000 to 1000 m";
    else if (!m->grid || (strcmp(m->grid, "coarse") && strcmp(m->grid, "default") && strcmp(m->grid, "fine")))
        bad = "grid", want = "coarse, default or fine";
    if (!bad)
        return 0;
    if (err)
        snprintf(err, n, "airwake_request_t.%s: expected %s", bad, want);
    return -1;
}
