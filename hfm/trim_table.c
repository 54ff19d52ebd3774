/* trim_table.c -- a table of trims over speeds: hover trims in air that
 * changes with the speed, each started from the last converged one, and
 * the table's CSV rows. */
#include "hfm.h"

#include <stdio.h>

int hfm_trim_sweep_warm(hfm_trim *tr, const hfm_trim_cond *c0, const double *mps, int n, hfm_air_at_fn air_at,
                        void *user, hfm_trim_result *res, int *at)
{
    hfm_trim_cond c = *c0;
    const hfm_trim_result *last = NULL;
    for (int i = 0; i < n; i++) {
        c.wod_speed_mps = mps[i];
        c.air = air_at(user, mps[i]);
        int t = hfm_trim_solve(tr, &c, last, &res[i]);
        if (t > 0 && last) /* retry from the free-air guess */
            t = hfm_trim_solve(tr, &c, NULL, &res[i]);
        if (t < 0) {
            *at = i;
            return t;
        }
        if (res[i].converged)
            last = &res[i];
    }
    return 0;
}

const char *hfm_trim_csv_header(void)
{
    return "speed_kt,collective_pct,long_cyclic_pct,lat_cyclic_pct,pedal_pct,pitch_deg,"
           "roll_deg,thrust_N,power_kW,engine_power_kW,beta0_deg,beta1c_deg,beta1s_deg,lambda0,"
           "converged";
}

int hfm_trim_csv_row(double speed_kt, const hfm_trim_result *r, char *buf, size_t n)
{
    const double R2D = CORE_RAD_TO_DEG;
    return snprintf(buf, n, "%.3f,%.3f,%.3f,%.3f,%.3f,%.4f,%.4f,%.1f,%.2f,%.2f,%.4f,%.4f,%.4f,%.6f,%d", speed_kt,
                    r->u.collective_pct, r->u.long_cyclic_pct, r->u.lat_cyclic_pct, r->u.pedal_pct,
                    r->body.euler_rad[1] * R2D, r->body.euler_rad[0] * R2D, r->loads.mr_thrust_N,
                    (r->loads.mr_power_W + r->loads.tr_power_W) / 1000.0, r->loads.engine_power_W / 1000.0,
                    r->rotor.beta0_rad * R2D, r->rotor.beta1c_rad * R2D, r->rotor.beta1s_rad * R2D, r->rotor.lambda0,
                    r->converged);
}
