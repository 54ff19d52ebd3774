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
/* The field's air at a speed: calm air needs no field. */
typedef struct field_air {
    cfd_field_scaled fa;
    hfm_air air;
    double ref_mps;
} field_air;

static const hfm_air *field_air_at(void *user, double mps)
{
    field_air *f = user;
    f->fa.scale = mps / f->ref_mps;
    return mps > 0.0 ? &f->air : NULL;
}

/* The ship-only field's checks: rotor off, a WOD speed to scale from, the
 * direction --wod-dir-deg gives if given (the trims take the field's). */
static int field_check(const char *path, const cfd_meta *m, hfm_trim_cond *c, int have_dir)
{
    if (strcmp(m->rotor, "off") != 0) {
        fprintf(stderr, "disim trim: --field %s: rotor '%s': expected a ship-only field (rotor off); with the "
                        "rotor in it the aircraft's own inflow would count twice\n", path, m->rotor);
        return -1;
    }
    if (!(m->wod_speed_mps > 0.0)) {
        fprintf(stderr, "disim trim: --field %s: WOD speed %g m/s: expected > 0 to scale from\n", path,
                m->wod_speed_mps);
        return -1;
    }
    double fdir = core_wod_wrap_deg(m->wod_dir_deg);
    int rc = 0;
    if (have_dir && fabs(core_wod_wrap_deg(c->wod_dir_rad * CORE_RAD_TO_DEG - fdir)) > 0.01) {
        fprintf(stderr, "disim trim: --wod-dir-deg %.2f: the field %s is from %.2f deg\n",
                c->wod_dir_rad * CORE_RAD_TO_DEG, path, fdir);
        rc = -1;
    }
    c->wod_dir_rad = fdir * CORE_DEG_TO_RAD;
    return rc;
}

/* One-way hover trims in a ship-only field (hfm_trim_sweep_warm, the field
 * scaled from its WOD speed to each speed): 0, or non-zero after a
 * message. */
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
    int rc = field_check(path, m, c, have_dir), at = 0;
    field_air fa = {{f, 0.0}, {cfd_field_air_scaled, NULL, NULL}, m->wod_speed_mps};
    fa.air.user = &fa.fa;
    memcpy(c->pos_S_m, cg_S, sizeof c->pos_S_m);
    if (rc == 0 && hfm_trim_sweep_warm(tr, c, mps, n, field_air_at, &fa, res, &at) < 0) {
        fprintf(stderr, "disim trim: --field %s: the trim at %.2f kt sampled outside the field (CG %g, %g, %g m)\n",
                path, kt[at], cg_S[0], cg_S[1], cg_S[2]);
        rc = -1;
    }
    for (int i = 0; rc == 0 && i < n; i++)
        res[i].speed_kt = kt[i];
    cfd_field_destroy(f);
    return rc;
}
#endif

/* The command line of disim trim. */
typedef struct trim_args {
    const char *ac_path, *csv, *range, *field_path;
    int kind, constraint, modes, have_dir, have_cg;
    double dir_deg, cg_S[3];
} trim_args;

/* One flag with its value v: 0, 1 after a message on a bad value, -1 not
 * a flag of this command. */
static int trim_flag(trim_args *o, const char *a, const char *v)
{
    static const char *constraint[] = {"sideslip", "roll", "auto"};
    static const int constraint_code[] = {HFM_CONSTRAINT_SIDESLIP, HFM_CONSTRAINT_ROLL, HFM_CONSTRAINT_AUTO};
    if (!strcmp(a, "--airspeed-kt") || !strcmp(a, "--hover-wod-kt")) {
        o->kind = !strcmp(a, "--airspeed-kt") ? HFM_TRIM_FORWARD : HFM_TRIM_HOVER_SHIP;
        o->range = v;
    } else if (!strcmp(a, "--wod-dir-deg")) {
        char *end;
        o->dir_deg = strtod(v, &end);
        if (*end || end == v) {
            fprintf(stderr, "disim trim: --wod-dir-deg '%s': expected a number\n", v);
            return 1;
        }
        o->have_dir = 1;
    } else if (!strcmp(a, "--field")) {
        o->field_path = v;
    } else if (!strcmp(a, "--cg-S")) {
        if (core_parse_vec3(v, o->cg_S, NULL)) {
            fprintf(stderr, "disim trim: --cg-S '%s': expected X,Y,Z in m\n", v);
            return 1;
        }
        o->have_cg = 1;
    } else if (!strcmp(a, "--trim-constraint")) {
        int k = 0;
        while (k < 3 && strcmp(v, constraint[k]))
            k++;
        if (k == 3) {
            fprintf(stderr, "disim trim: --trim-constraint '%s': expected sideslip, roll or auto\n", v);
            return 1;
        }
        o->constraint = constraint_code[k];
    } else if (!strcmp(a, "--csv")) {
        o->csv = v;
        if (strlen(v) > 4000) { /* room for the temporary's ".tmp.PID" */
            fprintf(stderr, "disim trim: --csv: path longer than 4000 characters\n");
            return 1;
        }
    } else {
        return -1;
    }
    return 0;
}

/* The flags into o: 0, 1 (a bad value) or 2 (usage) after the message. */
static int trim_parse(int argc, char **argv, trim_args *o)
{
    memset(o, 0, sizeof *o);
    o->kind = -1;
    o->constraint = HFM_CONSTRAINT_AUTO;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        int rc = v ? trim_flag(o, a, v) : -1;
        if (rc > 0)
            return rc;
        if (rc == 0)
            i++;
        else if (!strcmp(a, "--modes"))
            o->modes = 1;
        else if (a[0] != '-' && !o->ac_path)
            o->ac_path = a;
        else {
            usage();
            return 2;
        }
    }
    if (!o->ac_path || o->kind < 0 || (o->modes && !o->csv)) {
        usage();
        return 2;
    }
    if (o->field_path && (o->kind != HFM_TRIM_HOVER_SHIP || !o->have_cg || o->modes)) {
        fprintf(stderr, "disim trim: --field needs --hover-wod-kt and --cg-S (and takes no --modes)\n");
        return 2;
    }
#ifndef DISIM_HAVE_CFD
    if (o->field_path) {
        fprintf(stderr, "disim trim: --field: built without the CFD module\n");
        return 2;
    }
#endif
    return 0;
}

/* The speeds of the range A:B:STEP (kt and m/s, at most nmax): their
 * number, or -1 after a message. */
static int trim_speeds(const char *range, double *kt, double *mps, int nmax)
{
    int n = 0;
    if (core_parse_range(range, kt, nmax, &n) || n < 1) {
        fprintf(stderr, "disim trim: range '%s': expected A:B:STEP or a number\n", range);
        return -1;
    }
    for (int i = 0; i < n; i++) {
        if (kt[i] < 0 || (i > 0 && kt[i] <= kt[i - 1])) {
            fprintf(stderr, "disim trim: range '%s': speeds must be >= 0 and increasing\n", range);
            return -1;
        }
        mps[i] = kt[i] * CORE_KT_TO_MPS;
    }
    return n;
}

/* The table to csv (through a temporary renamed into place) or to stdout,
 * a message for each trim that did not converge: their number, or -1. */
static int trim_write(const char *csv, const hfm_aircraft *ac, const double *kt, const hfm_trim_result *res, int n)
{
    char tmp[4096] = "", row[512];
    FILE *f = NULL;
    if (csv) {
        snprintf(tmp, sizeof tmp, "%s.tmp.%ld", csv, (long)getpid());
        if (!(f = fopen(tmp, "w"))) {
            fprintf(stderr, "disim trim: cannot write %s\n", tmp);
            return -1;
        }
    }
    FILE *o = f ? f : stdout;
    fprintf(o, "%s\n", hfm_trim_csv_header());
    int failed = 0;
    for (int i = 0; i < n; i++) {
        const hfm_trim_result *r = &res[i];
        hfm_trim_csv_row(kt[i], r, row, sizeof row);
        fprintf(o, "%s\n", row);
        if (!r->converged) {
            failed++;
            fprintf(stderr,
                    "disim trim: %s at %.2f kt did not trim: residual norm %.3g, equation "
                    "'%s' did not close\n",
                    hfm_aircraft_name(ac), kt[i], r->resid_norm, r->worst_eq_name);
        }
    }
    if (f && (fclose(f) != 0 || rename(tmp, csv) != 0)) {
        fprintf(stderr, "disim trim: cannot write %s\n", csv);
        remove(tmp);
        return -1;
    }
    return failed;
}

/* --modes: each converged trim's eigenvalues and mode names on stdout; the
 * number of linearisations that failed. */
static int trim_modes(hfm_trim *tr, const hfm_trim_cond *c, const double *kt, const double *mps,
                      const hfm_trim_result *res, int n)
{
    int failed = 0;
    for (int i = 0; i < n; i++) {
        hfm_linear lin;
        if (!res[i].converged)
            continue;
        hfm_trim_cond ci = *c;
        if (c->kind == HFM_TRIM_FORWARD)
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
    return failed;
}

/* The trims of a, written: 0, or 1 (a failure, or a point that did not trim). */
static int trim_run(const trim_args *a, hfm_trim *tr, const hfm_aircraft *ac, const double *kt, const double *mps,
                    int n, hfm_trim_result *res)
{
    hfm_trim_cond c;
    memset(&c, 0, sizeof c);
    c.kind = a->kind;
    c.constraint = a->constraint;
    c.wod_dir_rad = core_wod_wrap_deg(a->dir_deg) * CORE_DEG_TO_RAD;
    if (a->field_path) {
#ifdef DISIM_HAVE_CFD
        if (field_trims(a->field_path, tr, &c, a->have_dir, a->cg_S, mps, kt, n, res) != 0)
            return 1;
#endif
    } else if (hfm_trim_sweep(tr, &c, a->kind == HFM_TRIM_FORWARD ? HFM_PARAM_AIRSPEED : HFM_PARAM_WOD_SPEED, mps, n,
                              res) < 0) {
        fprintf(stderr, "disim trim: evaluation failed\n");
        return 1;
    }
    int failed = trim_write(a->csv, ac, kt, res, n);
    if (failed < 0)
        return 1;
    if (a->modes)
        failed += trim_modes(tr, &c, kt, mps, res, n);
    return failed ? 1 : 0;
}

int cmd_trim(int argc, char **argv)
{
    trim_args a;
    int rc = trim_parse(argc, argv, &a);
    if (rc != 0)
        return rc;
    enum { NMAX = 2000 };
    double *kt = malloc(NMAX * sizeof *kt), *mps = malloc(NMAX * sizeof *mps);
    hfm_trim_result *res = calloc(NMAX, sizeof *res);
    hfm_aircraft *ac = NULL;
    hfm_trim *tr = NULL;
    int n = kt && mps && res ? trim_speeds(a.range, kt, mps, NMAX) : -1;
    rc = 1;
    if (n > 0) {
        core_err err = {0};
        app_log al = {NULL, 0};
        core_log log = {app_log_stderr, &al, CORE_LOG_WARN};
        if (!(ac = hfm_aircraft_load(a.ac_path, &log, &err)))
            fprintf(stderr, "disim trim: %s\n", err.msg);
        else if ((tr = hfm_trim_create(ac, &log)))
            rc = trim_run(&a, tr, ac, kt, mps, n, res);
    }
    hfm_trim_destroy(tr);
    hfm_aircraft_destroy(ac);
    free(kt);
    free(mps);
    free(res);
    return rc;
}
