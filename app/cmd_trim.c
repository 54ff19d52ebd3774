/* cmd_trim.c -- `disim trim`: trim an aircraft over a range of airspeeds
 * (straight level flight) or WOD speeds (hover over the ship's spot, heading
 * along the bow) with hfm_trim_sweep, and write one CSV row per point. With
 * --field, the hover trims are one-way in a ship-only airwake file (the
 * field scaled from its WOD speed to each speed, as `disim shol --coupling
 * one-way` does), each warm-started from the previous one. A
 * point that does not trim is reported with its residual norm and the
 * equation that did not close, converged = 0, and exit status 1. The CSV is
 * written to a temporary file and renamed, so nothing is half-written. */
#include "cmds.h"
#include "core.h"
#include "hfm.h"
#ifdef DISIM_HAVE_CFD
#include "cfd.h"
#endif

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

int cmd_trim(int argc, char **argv);

static void usage(void)
{
    fprintf(stderr,
            "usage: disim trim AIRCRAFT.ini (--airspeed-kt A:B:STEP | --hover-wod-kt A:B:STEP\n"
            "                  [--wod-dir-deg D]) [--trim-constraint sideslip|roll|auto]\n"
            "                  [--csv OUT.csv [--modes]]\n"
            "       disim trim AIRCRAFT.ini --hover-wod-kt A:B:STEP --field SHIPONLY.h5 --cg-S X,Y,Z [--csv OUT.csv]\n"
            "  --field: hover with the CG at X,Y,Z (m, frame S) in a ship-only airwake\n"
            "  (rotor off) scaled from its WOD speed; the direction is the field's.\n"
            "  power_kW is main plus tail rotor aerodynamic power, engine_power_kW that\n"
            "  through the drive train ([power] of the aircraft file); --modes prints each\n"
            "  trim's eigenvalues and mode names (linearised, rotor quasi-steady).\n");
}

#ifdef DISIM_HAVE_CFD
/* One-way hover trims in a ship-only field: 0, or non-zero after a message.
 * A trim that fails to converge is kept (converged = 0) as in the sweep;
 * the next one starts from the last converged trim. */
static int field_trims(const char *path, hfm_trim *tr, hfm_trim_cond *c, int have_dir, const double cg_S[3],
                       const double *mps, const double *kt, int n, hfm_trim_result *res)
{
    core_err err = {0};
    cfd_field *f = cfd_field_load(path, &err);
    if (!f) {
        fprintf(stderr, "disim trim: --field: %s\n", err.msg);
        return -1;
    }
    const cfd_meta *m = cfd_field_meta(f);
    int rc = 0;
    if (strcmp(m->rotor, "off") != 0) {
        fprintf(stderr, "disim trim: --field %s: rotor '%s': expected a ship-only field (rotor off); with the "
                        "rotor in it the aircraft's own inflow would count twice\n", path, m->rotor);
        rc = -1;
    } else if (!(m->wod_speed_mps > 0.0)) {
        fprintf(stderr, "disim trim: --field %s: WOD speed %g m/s: expected > 0 to scale from\n", path,
                m->wod_speed_mps);
        rc = -1;
    } else {
        double fdir = core_wod_wrap_deg(m->wod_dir_deg);
        if (have_dir && fabs(core_wod_wrap_deg(c->wod_dir_rad * CORE_RAD_TO_DEG - fdir)) > 0.01) {
            fprintf(stderr, "disim trim: --wod-dir-deg %.2f: the field %s is from %.2f deg\n",
                    c->wod_dir_rad * CORE_RAD_TO_DEG, path, fdir);
            rc = -1;
        }
        c->wod_dir_rad = fdir * CORE_DEG_TO_RAD;
    }
    cfd_field_scaled fa = {f, 0.0};
    hfm_air air = {cfd_field_air_scaled, &fa, NULL};
    memcpy(c->pos_S_m, cg_S, sizeof c->pos_S_m);
    const hfm_trim_result *last = NULL;
    for (int i = 0; rc == 0 && i < n; i++) {
        c->wod_speed_mps = mps[i];
        c->air = mps[i] > 0.0 ? &air : NULL; /* calm air needs no field */
        fa.scale = mps[i] / m->wod_speed_mps;
        int t = hfm_trim_solve(tr, c, last, &res[i]);
        if (t > 0 && last) /* retry from the free-air guess */
            t = hfm_trim_solve(tr, c, NULL, &res[i]);
        if (t < 0) {
            fprintf(stderr, "disim trim: --field %s: the trim at %.2f kt sampled outside the field (CG %g, %g, %g m)\n",
                    path, kt[i], cg_S[0], cg_S[1], cg_S[2]);
            rc = -1;
            break;
        }
        res[i].speed_kt = kt[i];
        if (res[i].converged)
            last = &res[i];
    }
    c->air = NULL;
    cfd_field_destroy(f);
    return rc;
}
#endif

int cmd_trim(int argc, char **argv)
{
    const char *ac_path = NULL, *csv = NULL, *range = NULL, *field_path = NULL;
    int kind = -1, constraint = HFM_CONSTRAINT_AUTO, modes = 0, have_dir = 0, have_cg = 0;
    double dir_deg = 0.0, cg_S[3] = {0, 0, 0};
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "--airspeed-kt") && v) {
            kind = HFM_TRIM_FORWARD;
            range = v;
            i++;
        } else if (!strcmp(a, "--hover-wod-kt") && v) {
            kind = HFM_TRIM_HOVER_SHIP;
            range = v;
            i++;
        } else if (!strcmp(a, "--wod-dir-deg") && v) {
            char *end;
            dir_deg = strtod(v, &end);
            if (*end || end == v) {
                fprintf(stderr, "disim trim: --wod-dir-deg '%s': expected a number\n", v);
                return 1;
            }
            have_dir = 1;
            i++;
        } else if (!strcmp(a, "--field") && v) {
            field_path = v;
            i++;
        } else if (!strcmp(a, "--cg-S") && v) {
            if (core_parse_vec3(v, cg_S, NULL)) {
                fprintf(stderr, "disim trim: --cg-S '%s': expected X,Y,Z in m\n", v);
                return 1;
            }
            have_cg = 1;
            i++;
        } else if (!strcmp(a, "--trim-constraint") && v) {
            if (!strcmp(v, "sideslip"))
                constraint = HFM_CONSTRAINT_SIDESLIP;
            else if (!strcmp(v, "roll"))
                constraint = HFM_CONSTRAINT_ROLL;
            else if (!strcmp(v, "auto"))
                constraint = HFM_CONSTRAINT_AUTO;
            else {
                fprintf(stderr, "disim trim: --trim-constraint '%s': expected sideslip, roll or auto\n", v);
                return 1;
            }
            i++;
        } else if (!strcmp(a, "--modes")) {
            modes = 1;
        } else if (!strcmp(a, "--csv") && v) {
            csv = v;
            if (strlen(csv) > 4000) { /* room for the temporary's ".tmp.PID" */
                fprintf(stderr, "disim trim: --csv: path longer than 4000 characters\n");
                return 1;
            }
            i++;
        } else if (a[0] != '-' && !ac_path) {
            ac_path = a;
        } else {
            usage();
            return 2;
        }
    }
    if (!ac_path || kind < 0 || (modes && !csv)) {
        usage();
        return 2;
    }
    if (field_path && (kind != HFM_TRIM_HOVER_SHIP || !have_cg || modes)) {
        fprintf(stderr, "disim trim: --field needs --hover-wod-kt and --cg-S (and takes no --modes)\n");
        return 2;
    }
#ifndef DISIM_HAVE_CFD
    if (field_path) {
        fprintf(stderr, "disim trim: --field: built without the CFD module\n");
        return 2;
    }
#endif
    enum { NMAX = 2000 };
    double *kt = malloc(NMAX * sizeof *kt), *mps = malloc(NMAX * sizeof *mps);
    hfm_trim_result *res = calloc(NMAX, sizeof *res);
    int n = 0, status = 1;
    hfm_aircraft *ac = NULL;
    hfm_trim *tr = NULL;
    FILE *f = NULL;
    char tmp[4096] = "";
    if (!kt || !mps || !res)
        goto out;
    if (core_parse_range(range, kt, NMAX, &n) || n < 1) {
        fprintf(stderr, "disim trim: range '%s': expected A:B:STEP or a number\n", range);
        goto out;
    }
    for (int i = 0; i < n; i++) {
        if (kt[i] < 0 || (i > 0 && kt[i] <= kt[i - 1])) {
            fprintf(stderr, "disim trim: range '%s': speeds must be >= 0 and increasing\n", range);
            goto out;
        }
        mps[i] = kt[i] * CORE_KT_TO_MPS;
    }
    core_err err = {0};
    app_log al = {NULL, 0};
    core_log log = {app_log_stderr, &al, CORE_LOG_WARN};
    ac = hfm_aircraft_load(ac_path, &log, &err);
    if (!ac) {
        fprintf(stderr, "disim trim: %s\n", err.msg);
        goto out;
    }
    tr = hfm_trim_create(ac, &log);
    if (!tr)
        goto out;
    hfm_trim_cond c;
    memset(&c, 0, sizeof c);
    c.kind = kind;
    c.constraint = constraint;
    c.wod_dir_rad = core_wod_wrap_deg(dir_deg) * CORE_DEG_TO_RAD;
    if (field_path) {
#ifdef DISIM_HAVE_CFD
        if (field_trims(field_path, tr, &c, have_dir, cg_S, mps, kt, n, res) != 0)
            goto out;
#endif
    } else {
        int rc = hfm_trim_sweep(tr, &c, kind == HFM_TRIM_FORWARD ? HFM_PARAM_AIRSPEED
                                                                : HFM_PARAM_WOD_SPEED,
                                mps, n, res);
        if (rc < 0) {
            fprintf(stderr, "disim trim: evaluation failed\n");
            goto out;
        }
    }
    if (csv) {
        snprintf(tmp, sizeof tmp, "%s.tmp.%ld", csv, (long)getpid());
        f = fopen(tmp, "w");
        if (!f) {
            fprintf(stderr, "disim trim: cannot write %s\n", tmp);
            goto out;
        }
    }
    FILE *o = f ? f : stdout;
    fprintf(o, "speed_kt,collective_pct,long_cyclic_pct,lat_cyclic_pct,pedal_pct,pitch_deg,"
               "roll_deg,thrust_N,power_kW,engine_power_kW,beta0_deg,beta1c_deg,beta1s_deg,lambda0,"
               "converged\n");
    int failed = 0;
    for (int i = 0; i < n; i++) {
        const hfm_trim_result *r = &res[i];
        const double R2D = CORE_RAD_TO_DEG;
        fprintf(o, "%.3f,%.3f,%.3f,%.3f,%.3f,%.4f,%.4f,%.1f,%.2f,%.2f,%.4f,%.4f,%.4f,%.6f,%d\n", kt[i],
                r->u.collective_pct, r->u.long_pct, r->u.lat_pct, r->u.pedal_pct,
                r->body.euler_rad[1] * R2D, r->body.euler_rad[0] * R2D, r->loads.mr_thrust_N,
                (r->loads.mr_power_W + r->loads.tr_power_W) / 1000.0,
                r->loads.engine_power_W / 1000.0, r->rotor.beta0_rad * R2D,
                r->rotor.beta1c_rad * R2D, r->rotor.beta1s_rad * R2D, r->rotor.lambda0,
                r->converged);
        if (!r->converged) {
            failed++;
            fprintf(stderr,
                    "disim trim: %s at %.2f kt did not trim: residual norm %.3g, equation "
                    "'%s' did not close\n",
                    hfm_aircraft_name(ac), kt[i], r->resid_norm, r->worst_eq_name);
        }
    }
    if (f) {
        if (fclose(f) != 0 || rename(tmp, csv) != 0) {
            f = NULL;
            fprintf(stderr, "disim trim: cannot write %s\n", csv);
            remove(tmp);
            goto out;
        }
        f = NULL;
    }
    for (int i = 0; modes && i < n; i++) {
        hfm_linear lin;
        if (!res[i].converged)
            continue;
        hfm_trim_cond ci = c;
        if (kind == HFM_TRIM_FORWARD)
            ci.airspeed_mps = mps[i];
        else
            ci.wod_speed_mps = mps[i];
        if (hfm_linearise(tr, &ci, &res[i], &lin)) {
            fprintf(stderr, "disim trim: linearisation failed at %.2f kt\n", kt[i]);
            failed++;
            continue;
        }
        printf("%.2f kt:", kt[i]);
        for (int k = 0; k < HFM_LIN_NX; k++)
            printf("%s %.4f%+.4fi (%s)", k ? "," : "", lin.eig_re[k], lin.eig_im[k], lin.mode[k]);
        printf("\n");
    }
    status = failed ? 1 : 0;
out:
    if (f) {
        fclose(f);
        remove(tmp);
    }
    hfm_trim_destroy(tr);
    hfm_aircraft_destroy(ac);
    free(kt);
    free(mps);
    free(res);
    return status;
}
