/* rotor.c -- a flight-model rotor disk as the actuator disk of an airwake
 * key (seed paper section 2.5: the trim's thrust at the trimmed hub, tilted
 * with the trimmed shaft; here also its blade loads over 8 radial x 12
 * azimuthal cells, resampled to the key's table, and the in-plane forces'
 * swirl and torque), and the free-air trim that gives a case its disk. */
#include "couple_priv.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Linear interpolation in a radial-major table t[i * np + j] of the flight
 * model's disk at radius r (clamped to the cell centres) and azimuth index
 * position y (periodic; cell j is centred at j + 0.5). */
static double disk_sample(const hfm_disk *d, const double *t, double r, double y)
{
    int i0 = 0;
    while (i0 < d->nr - 2 && d->r_m[i0 + 1] < r)
        i0++;
    int i1 = d->nr > 1 ? i0 + 1 : i0;
    double fr = d->nr > 1 ? (r - d->r_m[i0]) / (d->r_m[i1] - d->r_m[i0]) : 0.0;
    fr = fmin(fmax(fr, 0.0), 1.0);
    double x = y - 0.5;
    x -= floor(x / d->npsi) * d->npsi;
    int j0 = (int)floor(x) % d->npsi, j1 = (j0 + 1) % d->npsi;
    double fp = x - floor(x);
    double a = (1 - fr) * t[i0 * d->npsi + j0] + fr * t[i1 * d->npsi + j0];
    double b = (1 - fr) * t[i0 * d->npsi + j1] + fr * t[i1 * d->npsi + j1];
    return (1 - fp) * a + fp * b;
}

int couple_key_set_rotor(const hfm_aircraft *ac, const hfm_disk *d, int loaded, awdb_key *k)
{
    if (!(d->thrust_N > 0.0) || d->nr < 1 || d->npsi < 4)
        return -1;
    core_euler sh = core_quat_to_euler(d->q_SH);
    double R = hfm_aircraft_rotor_radius_m(ac);
    k->rotor = loaded ? CORE_ROTOR_LOADED : CORE_ROTOR_UNIFORM;
    k->thrust_N = d->thrust_N;
    memcpy(k->station_S_m, d->hub_S_m, sizeof k->station_S_m);
    k->radius_m = R;
    k->shaft_pitch_rad = sh.theta_rad;
    k->shaft_roll_rad = sh.phi_rad;
    if (!loaded)
        return 0;
    /* cells of the flight model's disk run from the root cut to the tip */
    double dr = d->nr > 1 ? d->r_m[1] - d->r_m[0] : 2.0 * (R - d->r_m[0]);
    double root = fmax(d->r_m[0] - 0.5 * dr, 0.0);
    k->root_cut = fmin(root / R, 0.5);
    k->ccw_from_above = d->sense > 0;
    double wsum = 0.0, lsum = 0.0, smax = 0.0;
    for (int i = 0; i < AWDB_LOAD_NR; i++) {
        double r = (i + 0.5) / AWDB_LOAD_NR * R;
        double sw = 0.0;
        for (int j = 0; j < AWDB_LOAD_NPSI; j++) {
            double y = (double)j * d->npsi / AWDB_LOAD_NPSI;
            double l = r < root ? 0.0 : disk_sample(d, d->thrust_Pa, r, y);
            k->load[j * AWDB_LOAD_NR + i] = l;
            lsum += l * r;
            sw += r < root ? 0.0 : disk_sample(d, d->swirl_Pa, r, y);
        }
        wsum += r * AWDB_LOAD_NPSI;
        k->swirl[i] = sw / AWDB_LOAD_NPSI;
        smax = fmax(smax, fabs(k->swirl[i]));
    }
    if (!(lsum > 0.0))
        return -1;
    double mean = lsum / wsum; /* area-weighted mean pressure jump */
    for (int i = 0; i < AWDB_LOAD_NR * AWDB_LOAD_NPSI; i++)
        k->load[i] /= mean;
    for (int i = 0; i < AWDB_LOAD_NR; i++)
        k->swirl[i] = smax > 0.0 ? k->swirl[i] / smax : 0.0;
    /* the in-plane forces' moment about the shaft: the rotor torque */
    double q = 0.0, dpsi = 2.0 * CORE_PI / d->npsi;
    for (int i = 0; i < d->nr; i++)
        for (int j = 0; j < d->npsi; j++)
            q += d->swirl_Pa[i * d->npsi + j] * d->r_m[i] * d->r_m[i] * dr * dpsi;
    k->torque_Nm = fmax(q, 0.0);
    return 0;
}

int couple_free_air_rotor(const hfm_aircraft *ac, const double station_S_m[3], double v, double dir, int loaded,
                          awdb_key *key, core_err *err)
{
    hfm_trim *t = hfm_trim_create(ac, NULL);
    hfm_disk *d = malloc(sizeof *d);
    if (!t || !d) {
        hfm_trim_destroy(t);
        free(d);
        return core_err_set(err, -1, "free-air trim: out of memory");
    }
    hfm_trim_cond cond;
    memset(&cond, 0, sizeof cond);
    cond.kind = HFM_TRIM_HOVER_SHIP;
    cond.wod_speed_mps = v;
    cond.wod_dir_rad = dir;
    memcpy(cond.pos_S_m, station_S_m, sizeof cond.pos_S_m);
    hfm_trim_result r;
    int rc = hfm_trim_solve(t, &cond, NULL, &r);
    if (rc == 0) {
        hfm_air_uniform uni;
        core_vec3 w = core_wod_vel_S_mps(v, dir);
        uni.vel_S_mps[0] = w.x, uni.vel_S_mps[1] = w.y, uni.vel_S_mps[2] = w.z;
        hfm_air air = {hfm_air_uniform_fn, &uni, NULL};
        if (hfm_rotor_disk(ac, &air, 0.0, &r.body, &r.u, &r.rotor, 8, 12, d) != 0 ||
            couple_key_set_rotor(ac, d, loaded, key) != 0)
            rc = core_err_set(err, -1, "free-air trim at %.2f m/s from %.1f deg: rotor disk evaluation failed", v,
                              dir * CORE_RAD_TO_DEG);
    } else if (rc > 0) {
        core_err_set(err, rc, "free-air trim at %.2f m/s from %.1f deg did not converge", v, dir * CORE_RAD_TO_DEG);
    } else {
        core_err_set(err, rc, "free-air trim at %.2f m/s from %.1f deg: fatal error", v, dir * CORE_RAD_TO_DEG);
    }
    hfm_trim_destroy(t);
    free(d);
    return rc;
}
