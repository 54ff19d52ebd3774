/*
 * output.c -- the envelope as data files: shol.csv (one row per direction:
 * limit speed, limiting criterion, margins, band) and shol.json (settings, criteria and how their
 * control limits read, results and the
 * whole trim-versus-speed history), and the CSV reader for comparisons.
 * Units are in the names: deg, kt, km/h, pct. Non-finite values are written
 * as nan (CSV) or null (JSON).
 */
#include "io.h"
#include "shol.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define CSV_HEADER_V1                                                                              \
    "wod_dir_deg,max_speed_kt,max_speed_kmh,limit,margin_roll_deg,margin_pitch_deg,"               \
    "margin_long_pct,margin_lat_pct,margin_coll_pct,margin_pedal_pct"
/* The band's columns follow the first ten, and the model's source the
 * band's first seven, so that a reader of the first ten (or seventeen)
 * reads on unchanged; shol_read_csv takes all three headers. */
#define CSV_BAND_COLS                                                                              \
    ",band_lo_kmh,band_hi_kmh,band_grid_kmh,band_window_kmh,band_sens_kmh,band_open_above,"        \
    "low_confidence"
#define CSV_HEADER_V2 CSV_HEADER_V1 CSV_BAND_COLS
#define CSV_HEADER CSV_HEADER_V2 ",band_model_kmh"
#define CSV_NCOL_V1 10
#define CSV_NCOL_V2 17
#define CSV_NCOL 18

static double margin_out(const shol_eval *e, int k)
{
    /* Attitude margins are rad inside, deg in files. */
    return k <= SHOL_CRIT_PITCH ? e->margin[k] * CORE_RAD_TO_DEG : e->margin[k];
}

int shol_write_csv(const char *dir, const shol_result *r, core_err *err)
{
    char final[SHOL_IO_PATH_MAX], tmp[SHOL_IO_PATH_MAX];
    if (shol_io_mkdir(dir, err) < 0 || shol_io_paths(dir, "shol.csv", final, tmp, err) < 0)
        return -1;
    FILE *f = shol_io_open(tmp, err);
    if (!f)
        return -1;
    fprintf(f, "%s\n", CSV_HEADER);
    for (int i = 0; i < r->n_dirs; i++) {
        const shol_dir_result *d = &r->dirs[i];
        double v = d->has_pass ? d->max_speed_mps : NAN;
        fprintf(f, "%.6f,", d->dir_rad * CORE_RAD_TO_DEG);
        shol_io_num(f, "%.6f", v / CORE_KT_TO_MPS);
        fputc(',', f);
        shol_io_num(f, "%.6f", v / CORE_KMH_TO_MPS);
        fprintf(f, ",%s", shol_limit_name(d->limit));
        for (int k = 0; k < SHOL_NCRIT; k++) {
            fputc(',', f);
            shol_io_num(f, "%.6f", margin_out(&d->margins, k));
        }
        shol_band b;
        shol_band_get(r, i, &b);
        shol_io_band_csv(f, &b, "%.6f");
        fputc('\n', f);
    }
    return shol_io_commit(f, tmp, final, err);
}

/* Split line (modified) at commas into at most n fields; returns the count. */
static int split(char *line, char **field, int n)
{
    int k = 0;
    char *p = line;
    while (k < n) {
        while (*p == ' ' || *p == '\t')
            p++;
        field[k++] = p;
        char *c = strchr(p, ',');
        char *e = c ? c : p + strlen(p);
        while (e > p && (e[-1] == ' ' || e[-1] == '\t' || e[-1] == '\r' || e[-1] == '\n'))
            e--;
        if (!c) {
            *e = '\0';
            return k;
        }
        *e = '\0';
        p = c + 1;
    }
    return k + 1; /* more fields than n */
}

static int parse_num(const char *s, double *v)
{
    char *end;
    *v = strtod(s, &end);
    return end == s || *end ? -1 : 0;
}

/* The band's seven columns of a row (fld) into d->band, and with
 * ncol 8 the model's: lo and hi finite, lo <= the radius <= hi, the
 * sources nan or finite (window and sensitivity >= 0), the flags 0 or 1.
 * The model's error behind band_model_kmh is not in the file: the band
 * read keeps its quantity (the limit) and its shift. */
static int read_band(const char *path, int lineno, char **fld, int ncol, shol_dir_result *d, core_err *err)
{
    static const char *const names[8] = {"band_lo_kmh",     "band_hi_kmh",    "band_grid_kmh", "band_window_kmh",
                                         "band_sens_kmh",   "band_open_above", "low_confidence", "band_model_kmh"};
    double v[8];
    v[7] = NAN;
    for (int k = 0; k < ncol; k++)
        if (parse_num(fld[k], &v[k]) < 0)
            return core_err_set(err, -1, "%s:%d: %s '%s': expected a number", path, lineno, names[k], fld[k]);
    const double rad_kmh = d->has_pass ? d->max_speed_mps / CORE_KMH_TO_MPS : 0.0;
    if (!(isfinite(v[0]) && isfinite(v[1]) && v[0] >= 0 && v[0] <= rad_kmh + 1e-4 && v[1] >= rad_kmh - 1e-4))
        return core_err_set(err, -1,
                            "%s:%d: band_lo_kmh %g, band_hi_kmh %g: expected finite, 0 <= lo <= the radius (%g) <= hi",
                            path, lineno, v[0], v[1], rad_kmh);
    for (int k = 2; k < 5; k++)
        if (isinf(v[k]) || (k > 2 && v[k] < 0))
            return core_err_set(err, -1, "%s:%d: %s %g: expected nan or a finite value%s", path, lineno, names[k],
                                v[k], k > 2 ? " >= 0" : "");
    for (int k = 5; k < 7; k++)
        if (v[k] != 0 && v[k] != 1)
            return core_err_set(err, -1, "%s:%d: %s %g: expected 0 or 1", path, lineno, names[k], v[k]);
    if (isinf(v[7]))
        return core_err_set(err, -1, "%s:%d: %s %g: expected nan or a finite value", path, lineno, names[7], v[7]);
    shol_band *b = &d->band;
    memset(b, 0, sizeof *b);
    b->valid = 1;
    b->lo_mps = v[0] * CORE_KMH_TO_MPS;
    b->hi_mps = v[1] * CORE_KMH_TO_MPS;
    b->grid_mps = v[2] * CORE_KMH_TO_MPS;
    b->window_mps = v[3] * CORE_KMH_TO_MPS;
    b->window_frac = rad_kmh > 0 ? v[3] / rad_kmh : NAN; /* s is lost at a radius of 0 */
    b->sens_mps = v[4] * CORE_KMH_TO_MPS;
    b->open_above = (int)v[5];
    b->low_confidence = (int)v[6];
    b->model_mps = v[7] * CORE_KMH_TO_MPS;
    b->model_crit = d->limit >= SHOL_CRIT_ROLL && d->limit < SHOL_NCRIT ? d->limit : -1;
    b->model_err = NAN;
    /* the source that reaches furthest (before the clipping at 0 and at
     * an open top, which the file does not say) */
    double reach[SHOL_NBAND] = {isfinite(b->grid_mps) ? fabs(b->grid_mps) : 0,
                                isfinite(b->window_mps) ? b->window_mps : 0, isfinite(b->sens_mps) ? b->sens_mps : 0,
                                isfinite(b->model_mps) ? fabs(b->model_mps) : 0};
    double best = 0;
    b->widest = -1;
    for (int s = 0; s < SHOL_NBAND; s++)
        if (reach[s] > best + 1e-12) {
            best = reach[s];
            b->widest = s;
        }
    return 0;
}

/* far above any envelope's CSV (a few hundred rows) */
#define SHOL_CSV_MAX_BYTES (64LL * 1024 * 1024)

int shol_read_csv(const char *path, shol_result *r, core_err *err)
{
    memset(r, 0, sizeof *r);
    if (core_file_regular(path, SHOL_CSV_MAX_BYTES, err) != 0)
        return -1;
    FILE *f = fopen(path, "r");
    if (!f)
        return core_err_set(err, -1, "%s: cannot open", path);
    shol_settings_default(&r->settings);
    r->dirs = calloc(SHOL_MAX_DIRS, sizeof *r->dirs);
    if (!r->dirs) {
        fclose(f);
        return core_err_set(err, -1, "%s: out of memory", path);
    }
    char line[1024];
    int lineno = 0, rc = 0, ncol = CSV_NCOL;
    while (fgets(line, sizeof line, f)) {
        lineno++;
        size_t len = strlen(line);
        /* a line that filled the buffer without its newline would be read
         * on as a second line (the rest of its fields) */
        if (len == sizeof line - 1 && line[len - 1] != '\n' && !feof(f)) {
            rc = core_err_set(err, -1, "%s:%d: line longer than %zu characters", path, lineno,
                              sizeof line - 2);
            break;
        }
        while (len && (line[len - 1] == '\n' || line[len - 1] == '\r'))
            line[--len] = '\0';
        if (lineno == 1) {
            /* the header with the band's and the model's columns, or one
             * before them */
            if (strcmp(line, CSV_HEADER) == 0)
                ncol = CSV_NCOL;
            else if (strcmp(line, CSV_HEADER_V2) == 0)
                ncol = CSV_NCOL_V2;
            else if (strcmp(line, CSV_HEADER_V1) == 0)
                ncol = CSV_NCOL_V1;
            else {
                rc = core_err_set(err, -1, "%s:1: expected the header '%s'", path, CSV_HEADER);
                break;
            }
            continue;
        }
        if (len == 0)
            continue;
        char *fld[CSV_NCOL + 1];
        int nf = split(line, fld, ncol);
        if (nf != ncol) {
            rc = core_err_set(err, -1, "%s:%d: expected %d comma-separated fields, got %d", path,
                              lineno, ncol, nf);
            break;
        }
        if (r->n_dirs == SHOL_MAX_DIRS) {
            rc = core_err_set(err, -1, "%s:%d: more than %d directions", path, lineno,
                              SHOL_MAX_DIRS);
            break;
        }
        shol_dir_result *d = &r->dirs[r->n_dirs];
        double v[10];
        const char *names[10] = {"wod_dir_deg",     "max_speed_kt",    "max_speed_kmh",
                                 "limit",           "margin_roll_deg", "margin_pitch_deg",
                                 "margin_long_pct", "margin_lat_pct",  "margin_coll_pct",
                                 "margin_pedal_pct"};
        for (int k = 0; k < 10 && rc == 0; k++) {
            if (k == 3) {
                if (shol_limit_parse(fld[3], &d->limit) < 0)
                    rc = core_err_set(err, -1, "%s:%d: limit '%s': unknown criterion", path, lineno,
                                      fld[3]);
            } else if (parse_num(fld[k], &v[k]) < 0) {
                rc = core_err_set(err, -1, "%s:%d: %s '%s': expected a number", path, lineno,
                                  names[k], fld[k]);
            }
        }
        if (rc)
            break;
        if (!(v[0] > -180.0 - 1e-6 && v[0] <= 180.0 + 1e-6)) {
            rc = core_err_set(err, -1, "%s:%d: wod_dir_deg %g: expected (-180, 180]", path, lineno,
                              v[0]);
            break;
        }
        /* A negative radius would be drawn on the opposite side of the
         * polar plot. */
        if (v[1] < 0 || v[2] < 0) {
            rc = core_err_set(err, -1, "%s:%d: max_speed_kt %g, max_speed_kmh %g: expected >= 0 (or nan)",
                              path, lineno, v[1], v[2]);
            break;
        }
        d->has_pass = isfinite(v[1]);
        if (d->has_pass != isfinite(v[2]) ||
            (d->has_pass && fabs(v[1] * CORE_KT_TO_MPS - v[2] * CORE_KMH_TO_MPS) > 1e-3)) {
            rc = core_err_set(err, -1, "%s:%d: max_speed_kt %g and max_speed_kmh %g disagree", path,
                              lineno, v[1], v[2]);
            break;
        }
        d->dir_rad = core_wod_wrap_deg(v[0]) * CORE_DEG_TO_RAD;
        d->max_speed_mps = d->has_pass ? v[1] * CORE_KT_TO_MPS : 0;
        d->fail_speed_mps = NAN;
        for (int k = 0; k < SHOL_NCRIT; k++)
            d->margins.margin[k] = k <= SHOL_CRIT_PITCH ? v[4 + k] * CORE_DEG_TO_RAD : v[4 + k];
        d->margins.limit = d->limit;
        for (int k = 0; k < SHOL_NCRIT; k++)
            d->margins.n_exceeded += d->margins.margin[k] < 0;
        if (ncol > CSV_NCOL_V1 && (rc = read_band(path, lineno, fld + CSV_NCOL_V1, ncol - CSV_NCOL_V1, d, err)) != 0)
            break;
        r->settings.dirs_rad[r->n_dirs] = d->dir_rad;
        r->n_dirs++;
    }
    if (rc == 0 && ferror(f))
        rc = core_err_set(err, -1, "%s:%d: read error", path, lineno);
    fclose(f);
    if (rc == 0 && lineno == 0)
        rc = core_err_set(err, -1, "%s: empty file, expected the header '%s'", path, CSV_HEADER);
    if (rc) {
        shol_result_free(r);
        return rc;
    }
    r->settings.n_dirs = r->n_dirs;
    return 0;
}

/* A direction's attribution (shol_envelope_attribution) in budget (-1:
 * the criterion's primary one), or null where it is not defined. Forces
 * in N, moments in N m, power in W; the control at both trims in deg for
 * an attitude, % of travel for a control. */
static void json_attribution(FILE *f, const shol_dir_result *d, int budget)
{
    shol_attribution a;
    if (shol_envelope_attribution(d, budget, &a) != 0) {
        fputs("null", f);
        return;
    }
    const double k = a.crit <= SHOL_CRIT_PITCH ? CORE_RAD_TO_DEG : 1.0;
    fprintf(f, "{\"criterion\": \"%s\", \"at_limit\": %s, \"budget\": \"%s\", \"unit\": \"%s\", ",
            shol_limit_name(a.crit), a.at_limit ? "true" : "false", shol_budget_name(a.budget),
            a.budget >= SHOL_BUDGET_L ? "N m" : "N");
    fprintf(f, "\"effector\": \"%s\", \"driver\": \"%s\", \"ref_speed_kmh\": ", shol_comp_name(a.effector),
            shol_comp_name(a.driver));
    shol_io_json_num(f, "%.9g", a.ref_speed_mps / CORE_KMH_TO_MPS);
    fputs(", \"speed_kmh\": ", f);
    shol_io_json_num(f, "%.9g", a.at_speed_mps / CORE_KMH_TO_MPS);
    fputs(", \"value_ref\": ", f);
    shol_io_json_num(f, "%.9g", a.control_ref * k);
    fputs(", \"value\": ", f);
    shol_io_json_num(f, "%.9g", a.control_at * k);
    fputs(", \"effector_ref\": ", f);
    shol_io_json_num(f, "%.9g", a.effector_ref);
    fputs(", \"effector_change\": ", f);
    shol_io_json_num(f, "%.9g", a.effector_change);
    fputs(", \"closure\": ", f);
    shol_io_json_num(f, "%.9g", a.closure);
    fputs(",\n       \"components\": {", f);
    for (int c = 0; c < SHOL_NCOMP; c++) {
        fprintf(f, "%s\"%s\": {\"ref\": ", c ? ", " : "", shol_comp_name(c));
        shol_io_json_num(f, "%.9g", a.value_ref[c]);
        fputs(", \"change\": ", f);
        shol_io_json_num(f, "%.9g", a.change[c]);
        fputs(", \"share\": ", f);
        shol_io_json_num(f, "%.9g", a.share[c]);
        fputc('}', f);
    }
    fputs("},\n       \"mr_power_change_W\": ", f);
    shol_io_json_num(f, "%.9g", a.mr_power_change_W);
    fputs(", \"tr_power_change_W\": ", f);
    shol_io_json_num(f, "%.9g", a.tr_power_change_W);
    fputc('}', f);
}

static void json_margins(FILE *f, const shol_eval *e)
{
    static const char *const key[SHOL_NCRIT] = {"roll_deg", "pitch_deg", "long_pct",
                                                "lat_pct",  "coll_pct",  "pedal_pct"};
    fputc('{', f);
    for (int k = 0; k < SHOL_NCRIT; k++) {
        fprintf(f, "%s\"%s\": ", k ? ", " : "", key[k]);
        shol_io_json_num(f, "%.9g", margin_out(e, k));
    }
    fputc('}', f);
}

int shol_write_json(const char *dir, const shol_result *r, const shol_report_info *info,
                    core_err *err)
{
    char final[SHOL_IO_PATH_MAX], tmp[SHOL_IO_PATH_MAX];
    if (shol_io_mkdir(dir, err) < 0 || shol_io_paths(dir, "shol.json", final, tmp, err) < 0)
        return -1;
    FILE *f = shol_io_open(tmp, err);
    if (!f)
        return -1;
    const shol_settings *s = &r->settings;
    const shol_criteria *c = &s->criteria;
    shol_report_info none = {0};
    if (!info)
        info = &none;
    fputs("{\n  \"title\": ", f);
    shol_io_json_str(f, info->title ? info->title : "Candidate SHOL");
    fputs(",\n  \"label\": ", f);
    shol_io_json_str(f, info->label ? info->label : "");
    fputs(",\n  \"scenario\": ", f);
    shol_io_json_str(f, info->scenario_path ? info->scenario_path : "");
    fputs(",\n  \"aircraft\": ", f);
    shol_io_json_str(f, info->aircraft_path ? info->aircraft_path : "");
    fputs(",\n  \"grid\": ", f);
    shol_io_json_str(f, info->grid ? info->grid : "");
    fputs(",\n  \"coupling\": ", f);
    shol_io_json_str(f, info->coupling ? info->coupling : "");
    fprintf(f, ",\n  \"settings\": {\"speed_step_kmh\": ");
    shol_io_json_num(f, "%.9g", s->speed_step_mps / CORE_KMH_TO_MPS);
    fputs(", \"speed_max_kmh\": ", f);
    shol_io_json_num(f, "%.9g", s->speed_max_mps / CORE_KMH_TO_MPS);
    fputs(", \"bisect_tol_kmh\": ", f);
    shol_io_json_num(f, "%.9g", s->bisect_tol_mps / CORE_KMH_TO_MPS);
    fputs(", \"dirs_deg\": [", f);
    for (int i = 0; i < s->n_dirs; i++) {
        fputs(i ? ", " : "", f);
        shol_io_json_num(f, "%.9g", s->dirs_rad[i] * CORE_RAD_TO_DEG);
    }
    /* Through shol_io_json_num like every other number: %g would write nan or inf,
     * which no JSON reader accepts. */
    const char *ckey[SHOL_NCRIT] = {"roll_deg",       "pitch_deg",      "long_cyclic_pct",
                                    "lat_cyclic_pct", "collective_pct", "pedal_pct"};
    const double cval[SHOL_NCRIT] = {c->roll_max_rad * CORE_RAD_TO_DEG, c->pitch_max_rad * CORE_RAD_TO_DEG,
                                     c->long_cyclic_pct, c->lat_cyclic_pct, c->collective_pct,
                                     c->pedal_pct};
    fputs("]},\n  \"criteria\": {", f);
    for (int k = 0; k < SHOL_NCRIT; k++) {
        fprintf(f, "%s\"%s\": ", k ? ", " : "", ckey[k]);
        shol_io_json_num(f, "%.9g", cval[k]);
    }
    char reading[256];
    shol_criteria_reading(c, reading, sizeof reading);
    fputs("},\n  \"criteria_reading\": ", f);
    shol_io_json_str(f, reading);
    fputs(",\n", f);
    /* how the bands were made */
    const shol_band_rule br = shol_band_rule_of(r);
    fputs("  \"band_rule\": {\"low_confidence_width_kmh\": ", f);
    shol_io_json_num(f, "%.9g", br.width_mps / CORE_KMH_TO_MPS);
    fputs(", \"low_confidence_frac\": ", f);
    shol_io_json_num(f, "%.9g", br.frac);
    fputs(", \"grid\": ", f);
    shol_io_json_str(f, r->band_grid_label);
    fputs(", \"model_reference\": ", f);
    shol_io_json_str(f, r->band_model_label);
    fputs("},\n", f);
    fprintf(f, "  \"n_trims\": %d,\n  \"wall_s\": ", r->n_trims);
    shol_io_json_num(f, "%.9g", r->wall_s);
    fputs(",\n  \"directions\": [", f);
    for (int i = 0; i < r->n_dirs; i++) {
        const shol_dir_result *d = &r->dirs[i];
        char name[32];
        core_wod_name(d->dir_rad * CORE_RAD_TO_DEG, name, sizeof name);
        double v = d->has_pass ? d->max_speed_mps : NAN;
        fprintf(f, "%s\n    {\"wod_dir_deg\": ", i ? "," : "");
        shol_io_json_num(f, "%.9g", d->dir_rad * CORE_RAD_TO_DEG);
        fputs(", \"name\": ", f);
        shol_io_json_str(f, name);
        fputs(", \"max_speed_kt\": ", f);
        shol_io_json_num(f, "%.9g", v / CORE_KT_TO_MPS);
        fputs(", \"max_speed_kmh\": ", f);
        shol_io_json_num(f, "%.9g", v / CORE_KMH_TO_MPS);
        fputs(", \"fail_speed_kmh\": ", f);
        shol_io_json_num(f, "%.9g", d->fail_speed_mps / CORE_KMH_TO_MPS);
        fprintf(f, ", \"limit\": \"%s\",\n     \"margins\": ", shol_limit_name(d->limit));
        json_margins(f, &d->margins);
        /* how far the limit would move for a small error in the limiting
         * quantity (shol_envelope_sensitivity); null where undefined */
        shol_sensitivity se;
        if (shol_envelope_sensitivity(d, &se) == 0) {
            const int ang = se.crit <= SHOL_CRIT_PITCH;
            const double k = ang ? CORE_RAD_TO_DEG : 1.0;
            fprintf(f, ",\n     \"sensitivity\": {\"criterion\": \"%s\", \"unit\": \"%s\", \"margin_slope_per_kmh\": ",
                    shol_limit_name(se.crit), ang ? "deg" : "pct");
            shol_io_json_num(f, "%.9g", se.slope_per_mps * k * CORE_KMH_TO_MPS);
            fputs(", \"ref_error\": ", f);
            shol_io_json_num(f, "%.9g", se.ref_error * k);
            fputs(", \"limit_shift_kmh\": ", f);
            shol_io_json_num(f, "%.9g", se.shift_mps / CORE_KMH_TO_MPS);
            fputs("}", f);
        } else {
            fputs(",\n     \"sensitivity\": null", f);
        }
        /* what drives the limit (shol_envelope_attribution):
         * the criterion's budget, and an attitude's secondary one */
        fputs(",\n     \"attribution\": ", f);
        json_attribution(f, d, -1);
        {
            shol_attribution a0;
            int sec = -1;
            if (shol_envelope_attribution(d, -1, &a0) == 0)
                shol_crit_budget(a0.crit, &sec);
            fputs(",\n     \"attribution_secondary\": ", f);
            if (sec >= 0)
                json_attribution(f, d, sec);
            else
                fputs("null", f);
        }
        /* the band (shol_band; km/h, null where a source is absent) */
        shol_band b;
        shol_band_get(r, i, &b);
        fputs(",\n     \"band\": ", f);
        shol_io_band_json(f, &b, "%.9g");
        fputs(",\n     \"history\": [", f);
        for (int j = 0; j < d->n_samples; j++) {
            const shol_sample *sm = &d->samples[j];
            fprintf(f, "%s\n       {\"speed_kmh\": ", j ? "," : "");
            shol_io_json_num(f, "%.9g", sm->speed_mps / CORE_KMH_TO_MPS);
            fputs(", \"speed_kt\": ", f);
            shol_io_json_num(f, "%.9g", sm->speed_mps / CORE_KT_TO_MPS);
            /* limit: what rejected this trim ("none" when it passed);
             * closest: the criterion nearest its limit (the rejecting one
             * when rejected). */
            fprintf(f,
                    ", \"trim_status\": %d, \"pass\": %s, \"limit\": \"%s\", "
                    "\"closest\": \"%s\"",
                    sm->trim_status, sm->pass ? "true" : "false",
                    shol_limit_name(sm->pass ? SHOL_LIMIT_NONE : sm->eval.limit),
                    shol_limit_name(sm->eval.limit));
            if (sm->trim_status == 0) {
                fputs(", \"roll_deg\": ", f);
                shol_io_json_num(f, "%.9g", sm->trim.phi_rad * CORE_RAD_TO_DEG);
                fputs(", \"pitch_deg\": ", f);
                shol_io_json_num(f, "%.9g", sm->trim.theta_rad * CORE_RAD_TO_DEG);
                fputs(", \"long_cyclic_pct\": ", f);
                shol_io_json_num(f, "%.9g", sm->trim.long_cyclic_pct);
                fputs(", \"lat_cyclic_pct\": ", f);
                shol_io_json_num(f, "%.9g", sm->trim.lat_cyclic_pct);
                fputs(", \"collective_pct\": ", f);
                shol_io_json_num(f, "%.9g", sm->trim.collective_pct);
                fputs(", \"pedal_pct\": ", f);
                shol_io_json_num(f, "%.9g", sm->trim.pedal_pct);
                fputs(", \"margins\": ", f);
                json_margins(f, &sm->eval);
            }
            fputc('}', f);
        }
        fputs("]}", f);
    }
    fputs("\n  ]\n}\n", f);
    return shol_io_commit(f, tmp, final, err);
}

void shol_trim_plot_name(double dir_rad, char *buf, size_t n)
{
    double d = core_wod_wrap_deg(dir_rad * CORE_RAD_TO_DEG);
    double a = fabs(d);
    if (a < 1e-6)
        snprintf(buf, n, "shol_trim_head.png");
    else if (fabs(a - 180.0) < 1e-6)
        snprintf(buf, n, "shol_trim_stern.png");
    else if (fabs(a - round(a)) < 1e-6)
        snprintf(buf, n, "shol_trim_%s%03d.png", d > 0 ? "green" : "red", (int)round(a));
    else {
        /* 7.5 -> 007p5, 7.25 -> 007p25: no dot inside a name that ends in
         * .png, and hundredths where the direction has them (7.25 and 7.3
         * of one sweep would share a name in tenths) */
        int h = (int)round(a * 100);
        if (h % 10 == 0)
            snprintf(buf, n, "shol_trim_%s%03dp%d.png", d > 0 ? "green" : "red", h / 100, h / 10 % 10);
        else
            snprintf(buf, n, "shol_trim_%s%03dp%02d.png", d > 0 ? "green" : "red", h / 100, h % 100);
    }
}

int shol_write_all(const char *dir, const shol_result *r, const shol_report_info *info,
                   core_err *err)
{
    char stage[SHOL_IO_PATH_MAX];
    if (shol_io_stage_begin(dir, stage, err) < 0)
        return -1;
    if (shol_write_csv(stage, r, err) < 0 || shol_write_json(stage, r, info, err) < 0 ||
        shol_plot_polar(stage, r, info, err) < 0 || shol_plot_trim(stage, r, info, err) < 0 ||
        shol_write_report(stage, r, info, err) < 0) {
        shol_io_stage_abort(stage);
        return -1;
    }
    return shol_io_stage_commit(dir, stage, err);
}
