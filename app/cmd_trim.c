/* cmd_trim.c -- `disim trim`: trim an aircraft over a range of airspeeds
 * (straight level flight) or WOD speeds (hover over the ship's spot, heading
 * along the bow) with hfm_trim_sweep, and write one CSV row per point. A
 * point that does not trim is reported with its residual norm and the
 * equation that did not close, converged = 0, and exit status 1. The CSV is
 * written to a temporary file and renamed, so nothing is half-written. */
#include "core.h"
#include "hfm.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int cmd_trim(int argc, char **argv);

static void usage(void)
{
    fprintf(stderr,
            "usage: disim trim AIRCRAFT.ini (--airspeed-kt A:B:STEP | --hover-wod-kt A:B:STEP\n"
            "                  [--wod-dir-deg D]) [--trim-constraint sideslip|roll|auto]\n"
            "                  [--csv OUT.csv [--modes]]\n"
            "  power_kW is main plus tail rotor aerodynamic power; --modes prints each\n"
            "  trim's eigenvalues and mode names (linearised, rotor quasi-steady).\n");
}

static void log_stderr(void *user, int level, const char *msg)
{
    (void)user;
    fprintf(stderr, "%s: %s\n", level == CORE_LOG_ERROR ? "error" : "warning", msg);
}

int cmd_trim(int argc, char **argv)
{
    const char *ac_path = NULL, *csv = NULL, *range = NULL;
    int kind = -1, constraint = HFM_CONSTRAINT_AUTO, modes = 0;
    double dir_deg = 0.0;
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
    core_err err = {{0}};
    core_log log = {log_stderr, NULL, CORE_LOG_WARN};
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
    int rc = hfm_trim_sweep(tr, &c, kind == HFM_TRIM_FORWARD ? HFM_PARAM_AIRSPEED
                                                            : HFM_PARAM_WOD_SPEED,
                            mps, n, res);
    if (rc < 0) {
        fprintf(stderr, "disim trim: evaluation failed\n");
        goto out;
    }
    if (csv) {
        snprintf(tmp, sizeof tmp, "%s.tmp", csv);
        f = fopen(tmp, "w");
        if (!f) {
            fprintf(stderr, "disim trim: cannot write %s\n", tmp);
            goto out;
        }
    }
    FILE *o = f ? f : stdout;
    fprintf(o, "speed_kt,collective_pct,long_cyclic_pct,lat_cyclic_pct,pedal_pct,pitch_deg,"
               "roll_deg,thrust_N,power_kW,beta0_deg,beta1c_deg,beta1s_deg,lambda0,converged\n");
    int failed = 0;
    for (int i = 0; i < n; i++) {
        const hfm_trim_result *r = &res[i];
        const double R2D = CORE_RAD_TO_DEG;
        fprintf(o, "%.3f,%.3f,%.3f,%.3f,%.3f,%.4f,%.4f,%.1f,%.2f,%.4f,%.4f,%.4f,%.6f,%d\n", kt[i],
                r->u.collective_pct, r->u.long_pct, r->u.lat_pct, r->u.pedal_pct,
                r->body.euler_rad[1] * R2D, r->body.euler_rad[0] * R2D, r->loads.mr_thrust_N,
                (r->loads.mr_power_W + r->loads.tr_power_W) / 1000.0, r->rotor.beta0_rad * R2D,
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
