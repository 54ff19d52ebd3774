/*
 * report_flown.c -- the flown envelope's files: CSV per direction and per
 * point, JSON, and the Markdown report that compares it with the
 * trim-based envelope direction by direction. Each file is written under a
 * temporary name and renamed into place (io.c).
 */
#include "io.h"
#include "shol.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static double kt(double mps) { return mps / CORE_KT_TO_MPS; }

/* A cause as one CSV field: commas and quotes never appear in the causes
 * this module writes, but a crash names what hit what: quote it. */
static void csv_str(FILE *f, const char *s)
{
    fputc('"', f);
    for (; *s; s++) {
        if (*s == '"')
            fputc('"', f);
        fputc(*s, f);
    }
    fputc('"', f);
}

/* A direction's band: the one shol_flown_run (or shol_flown_bands_update)
 * filled, else one without sources. */
static void band_of(const shol_flown_result *fr, int i, shol_band *b)
{
    *b = fr->dirs[i].band;
    if (!b->valid)
        shol_flown_band(fr, NULL, i, b);
}

int shol_flown_write_csv(const char *dir, const shol_flown_result *fr, core_err *err)
{
    char final[SHOL_IO_PATH_MAX], tmp[SHOL_IO_PATH_MAX];
    if (shol_io_mkdir(dir, err) < 0 || shol_io_paths(dir, "shol_flown.csv", final, tmp, err) < 0)
        return -1;
    FILE *f = shol_io_open(tmp, err);
    if (!f)
        return -1;
    /* the band's columns after the first nine, as in shol.csv */
    fprintf(f, "wod_dir_deg,max_speed_kt,max_speed_kmh,pass_rate_at_max,fail_speed_kt,pass_rate_at_fail,cause,"
               "trim_max_speed_kt,trim_limit,band_lo_kmh,band_hi_kmh,band_grid_kmh,band_window_kmh,band_sens_kmh,"
               "band_open_above,low_confidence,band_model_kmh,rate_band_lo_kmh,rate_band_hi_kmh,rate_band_open_above\n");
    for (int i = 0; i < fr->n_dirs; i++) {
        const shol_flown_dir *d = &fr->dirs[i];
        fprintf(f, "%.1f,", d->dir_rad * CORE_RAD_TO_DEG);
        shol_io_num(f, "%.2f", d->has_pass ? kt(d->max_speed_mps) : NAN);
        fputc(',', f);
        shol_io_num(f, "%.1f", d->has_pass ? d->max_speed_mps / CORE_KMH_TO_MPS : NAN);
        fputc(',', f);
        shol_io_num(f, "%.3f", d->pass_rate_max);
        fputc(',', f);
        shol_io_num(f, "%.2f", kt(d->fail_speed_mps));
        fputc(',', f);
        shol_io_num(f, "%.3f", d->pass_rate_fail);
        fputc(',', f);
        csv_str(f, d->cause);
        fputc(',', f);
        shol_io_num(f, "%.2f", d->trim_has_pass ? kt(d->trim_max_speed_mps) : NAN);
        fprintf(f, ",%s", shol_limit_name(d->trim_limit) ? shol_limit_name(d->trim_limit) : "none");
        shol_band b;
        band_of(fr, i, &b);
        shol_io_band_csv(f, &b, "%.3f");
        fputc(',', f);
        shol_io_num(f, "%.1f", d->rate_band_lo_mps / CORE_KMH_TO_MPS);
        fputc(',', f);
        shol_io_num(f, "%.1f", d->rate_band_hi_mps / CORE_KMH_TO_MPS);
        fprintf(f, ",%d\n", d->rate_band_open_above);
    }
    if (shol_io_commit(f, tmp, final, err) < 0)
        return -1;
    if (shol_io_paths(dir, "shol_flown_points.csv", final, tmp, err) < 0 || !(f = shol_io_open(tmp, err)))
        return -1;
    fprintf(f, "wod_dir_deg,speed_kt,speed_kmh,flights,passed,pass_rate,pass,cause,pass_rate_lo,pass_rate_hi,verdict,"
               "track_rms_m,track_max_m,tracked\n");
    for (int i = 0; i < fr->n_dirs; i++)
        for (int k = 0; k < fr->dirs[i].n_points; k++) {
            const shol_flown_point *q = &fr->dirs[i].points[k];
            fprintf(f, "%.1f,%.2f,%.1f,%d,%d,%.3f,%d,", fr->dirs[i].dir_rad * CORE_RAD_TO_DEG, kt(q->speed_mps),
                    q->speed_mps / CORE_KMH_TO_MPS, q->n_flights, q->n_pass, q->pass_rate, q->pass);
            csv_str(f, q->cause);
            fprintf(f, ",%.3f,%.3f,%s,", q->rate_lo, q->rate_hi, shol_flown_verdict_name(q->verdict));
            shol_io_num(f, "%.3f", q->track_rms_m);
            fputc(',', f);
            shol_io_num(f, "%.3f", q->track_max_m);
            fputc(',', f);
            if (q->n_tracked >= 0)
                fprintf(f, "%d", q->n_tracked);
            fputc('\n', f);
        }
    return shol_io_commit(f, tmp, final, err);
}

int shol_flown_write_json(const char *dir, const shol_flown_result *fr, const shol_report_info *info, core_err *err)
{
    char final[SHOL_IO_PATH_MAX], tmp[SHOL_IO_PATH_MAX];
    if (shol_io_mkdir(dir, err) < 0 || shol_io_paths(dir, "shol_flown.json", final, tmp, err) < 0)
        return -1;
    FILE *f = shol_io_open(tmp, err);
    if (!f)
        return -1;
    fprintf(f, "{\n  \"title\": ");
    shol_io_json_str(f, info && info->title ? info->title : "Candidate SHOL");
    fprintf(f, ",\n  \"method\": \"pilot\",\n  \"settings\": {\"seeds\": %d, \"seed0\": %llu, \"pass_rate_min\": %.3f, "
               "\"start_steps_below\": %d, \"bisect_tol_kmh\": %.2f, \"speed_step_kmh\": %.2f, "
               "\"speed_max_kmh\": %.2f, \"criteria_window_s\": %.3f, \"transient_frac\": %.3f, "
               "\"rate_interval\": \"Wilson 90 %%\", \"wilson_z\": %.4f},\n",
            fr->flown.n_seeds, fr->flown.seed0, fr->flown.pass_rate_min, fr->flown.start_steps_below,
            fr->flown.bisect_tol_mps / CORE_KMH_TO_MPS, fr->speed_step_mps / CORE_KMH_TO_MPS,
            fr->speed_max_mps / CORE_KMH_TO_MPS, fr->flown.judge.window_s, fr->flown.judge.transient_frac,
            SHOL_WILSON_Z90);
    fprintf(f, "  \"flights\": %d,\n  \"flown_s\": %.1f,\n  \"wall_s\": %.1f,\n  \"directions\": [", fr->n_flights,
            fr->flown_s, fr->wall_s);
    for (int i = 0; i < fr->n_dirs; i++) {
        const shol_flown_dir *d = &fr->dirs[i];
        fprintf(f, "%s\n    {\"wod_dir_deg\": %.2f, \"has_pass\": %d, \"max_speed_kt\": %.3f, \"fail_speed_kt\": ",
                i ? "," : "", d->dir_rad * CORE_RAD_TO_DEG, d->has_pass, kt(d->max_speed_mps));
        if (isnan(d->fail_speed_mps))
            fprintf(f, "null");
        else
            fprintf(f, "%.3f", kt(d->fail_speed_mps));
        fprintf(f, ", \"cause\": ");
        shol_io_json_str(f, d->cause);
        fputs(", \"rate_band_lo_kt\": ", f);
        shol_io_json_num(f, "%.4f", kt(d->rate_band_lo_mps));
        fputs(", \"rate_band_hi_kt\": ", f);
        shol_io_json_num(f, "%.4f", kt(d->rate_band_hi_mps));
        fprintf(f, ", \"rate_band_open_above\": %d", d->rate_band_open_above);
        fputs(", \"hub_speed_frac\": ", f);
        shol_io_json_num(f, "%.4f", d->hub_speed_frac);
        fputs(", \"hub_ti_frac\": ", f);
        shol_io_json_num(f, "%.4f", d->hub_ti_frac);
        shol_band b;
        band_of(fr, i, &b);
        fputs(", \"band\": ", f);
        shol_io_band_json(f, &b, "%.6g");
        fprintf(f, ", \"trim_max_speed_kt\": %.3f, \"trim_has_pass\": %d, \"trim_limit\": \"%s\", \"points\": [",
                kt(d->trim_max_speed_mps), d->trim_has_pass,
                shol_limit_name(d->trim_limit) ? shol_limit_name(d->trim_limit) : "none");
        for (int k = 0; k < d->n_points; k++) {
            const shol_flown_point *q = &d->points[k];
            fprintf(f, "%s\n      {\"speed_kt\": %.3f, \"flights\": %d, \"passed\": %d, \"pass_rate\": %.4f, "
                       "\"pass\": %d, \"cause\": ",
                    k ? "," : "", kt(q->speed_mps), q->n_flights, q->n_pass, q->pass_rate, q->pass);
            shol_io_json_str(f, q->cause);
            fprintf(f, ", \"cause_flights\": %d, \"flown_s\": %.1f, \"pass_rate_lo\": %.4f, \"pass_rate_hi\": %.4f, "
                       "\"verdict\": \"%s\", \"track_rms_m\": ",
                    q->n_cause, q->flown_s, q->rate_lo, q->rate_hi, shol_flown_verdict_name(q->verdict));
            shol_io_json_num(f, "%.4f", q->track_rms_m);
            fputs(", \"track_max_m\": ", f);
            shol_io_json_num(f, "%.4f", q->track_max_m);
            if (q->n_tracked >= 0)
                fprintf(f, ", \"tracked\": %d}", q->n_tracked);
            else
                fputs(", \"tracked\": null}", f);
        }
        fprintf(f, "%s]}", d->n_points ? "\n    " : "");
    }
    fprintf(f, "\n  ]\n}\n");
    return shol_io_commit(f, tmp, final, err);
}

static void fmt_kt(char *b, size_t n, int has, double mps)
{
    if (has)
        snprintf(b, n, "%.1f", kt(mps));
    else
        snprintf(b, n, "none");
}

/* The bands of both envelopes, direction by direction, and the directions
 * of low confidence named. */
static void write_flown_bands(FILE *f, const shol_flown_result *fr, const shol_result *trim)
{
    const double K = CORE_KMH_TO_MPS;
    fprintf(f, "\n## Uncertainty bands\n\n| WOD | flown (km/h) | its band | trim-based (km/h) | its band | what makes "
               "the trim's band (km/h) | confidence (flown, trim) |\n|---|---|---|---|---|---|---|\n");
    int n_low = 0;
    for (int i = 0; i < fr->n_dirs; i++) {
        const shol_flown_dir *d = &fr->dirs[i];
        shol_band b, tb;
        band_of(fr, i, &b);
        const shol_dir_result *td = NULL;
        int ti = -1;
        for (int j = 0; trim && j < trim->n_dirs; j++)
            if (fabs(trim->dirs[j].dir_rad - d->dir_rad) < 1e-6) {
                td = &trim->dirs[j];
                ti = j;
            }
        char name[32], what[256] = "-", tband[64] = "-", tv[32] = "-";
        core_wod_name(d->dir_rad * CORE_RAD_TO_DEG, name, sizeof name);
        int tlow = 0;
        if (td) {
            shol_band_get(trim, ti, &tb);
            shol_band_format(&tb, trim->band_grid_label, td->limit, what, sizeof what);
            snprintf(tband, sizeof tband, "%.1f-%.1f%s", tb.lo_mps / K, tb.hi_mps / K, tb.open_above ? " (open above)" : "");
            snprintf(tv, sizeof tv, "%.1f", td->has_pass ? td->max_speed_mps / K : 0.0);
            tlow = tb.low_confidence;
        }
        fprintf(f, "| %s | %.1f | %.1f-%.1f%s | %s | %s | %s | %s, %s |\n", name,
                d->has_pass ? d->max_speed_mps / K : 0.0, b.lo_mps / K, b.hi_mps / K,
                b.open_above ? " (open above)" : "", tv, tband, what, b.low_confidence ? "**low**" : "ok",
                tlow ? "**low**" : "ok");
        n_low += b.low_confidence || tlow;
    }
    fprintf(f, "\nThe trim-based band is the hull of its grid, averaging-window, 0.25 deg / 1 %% and model "
               "sources (docs/shol.md, \"Uncertainty bands\"). The flown band carries the same sources to the "
               "flown radius V_f: the trim's grid shift, its window spread s as +- s V_f, its 0.25 deg / 1 %% "
               "shift, the model's shift; it does not hold the pass rate's sampling over the seeds (that is the band from the pass rate's "
               "interval, above). Low confidence: a band wider than the larger of %g km/h and %g %% of the limit.\n\n",
            trim ? shol_band_rule_of(trim).width_mps / K : 10.0, trim ? 100 * shol_band_rule_of(trim).frac : 25.0);
    if (n_low) {
        fprintf(f, "**Low confidence, where an at-sea test is most needed:** ");
        int j = 0;
        for (int i = 0; i < fr->n_dirs; i++) {
            shol_band b;
            band_of(fr, i, &b);
            int tlow = 0;
            for (int k = 0; trim && k < trim->n_dirs; k++)
                if (fabs(trim->dirs[k].dir_rad - fr->dirs[i].dir_rad) < 1e-6) {
                    shol_band tb;
                    shol_band_get(trim, k, &tb);
                    tlow = tb.low_confidence;
                }
            if (!b.low_confidence && !tlow)
                continue;
            char name[32];
            core_wod_name(fr->dirs[i].dir_rad * CORE_RAD_TO_DEG, name, sizeof name);
            fprintf(f, "%s%s (%s)", j++ ? ", " : "", name,
                    b.low_confidence && tlow ? "both envelopes" : b.low_confidence ? "flown" : "trim-based");
        }
        fprintf(f, ". The seed paper (section 2.8) uses a candidate SHOL so that \"only the regions with low "
                   "confidence in the candidate SHOL and/or small safety margins need to be tested\" at sea.\n");
    } else {
        fprintf(f, "No band is wider than the rule: no direction is marked low confidence.\n");
    }
}

/* Which of the pass rate's interval and the model's error moves the
 * flown limit of d further (band b, shol_flown_band): each one's reach
 * from the flown limit V_f, the interval's from its two ends (no clear
 * pass: down to 0; open above: without end), the model's its shift
 * clipped as the band clips it. "interval", "model (pedal -4.27 % vs
 * ...)", or "-" where neither reaches. */
static void rate_dominant(const shol_flown_dir *d, const shol_band *b, char *buf, size_t n)
{
    const double v = d->has_pass ? d->max_speed_mps : 0.0;
    double interval = d->rate_band_open_above ? INFINITY : 0.0;
    interval = fmax(interval, v - (isnan(d->rate_band_lo_mps) ? 0.0 : d->rate_band_lo_mps));
    if (!isnan(d->rate_band_hi_mps))
        interval = fmax(interval, d->rate_band_hi_mps - v);
    double model = 0.0;
    if (isfinite(b->model_mps))
        model = b->model_mps < 0 ? fmin(-b->model_mps, v) : b->open_above ? 0.0 : b->model_mps;
    char mt[128];
    shol_band_model_text(b, mt, sizeof mt);
    if (model > interval + 1e-12 && mt[0])
        snprintf(buf, n, "model (%s)", mt);
    else if (model > interval + 1e-12)
        snprintf(buf, n, "model");
    else
        snprintf(buf, n, interval > 1e-12 ? "interval" : "-");
}

/* The limit's band from the pass rate's interval, direction by direction,
 * beside the model's error carried from the trim-based envelope. */
static void write_rate_bands(FILE *f, const shol_flown_result *fr)
{
    fprintf(f, "\n## The limit's band from the pass rate\n\n| WOD | flown limit (kt) | pass rate there (90 %% "
               "interval) | clearly passes up to (kt) | may pass up to (kt) | model (kt) | dominant | air at the "
               "hub over the spot: mean speed, turbulence intensity (%% of WOD) |\n|---|---|---|---|---|---|---|---|\n");
    for (int i = 0; i < fr->n_dirs; i++) {
        const shol_flown_dir *d = &fr->dirs[i];
        char name[32], lim[16], at[48] = "-", lo[16], hi[48];
        core_wod_name(d->dir_rad * CORE_RAD_TO_DEG, name, sizeof name);
        fmt_kt(lim, sizeof lim, d->has_pass, d->max_speed_mps);
        for (int k = 0; k < d->n_points; k++)
            if (d->has_pass && d->points[k].speed_mps == d->max_speed_mps)
                snprintf(at, sizeof at, "%.2f (%.2f-%.2f)", d->points[k].pass_rate, d->points[k].rate_lo,
                         d->points[k].rate_hi);
        fmt_kt(lo, sizeof lo, !isnan(d->rate_band_lo_mps), d->rate_band_lo_mps);
        fmt_kt(hi, sizeof hi, !isnan(d->rate_band_hi_mps), d->rate_band_hi_mps);
        if (d->rate_band_open_above)
            snprintf(hi + strlen(hi), sizeof hi - strlen(hi), " (open above: no clear failure flown)");
        shol_band b;
        band_of(fr, i, &b);
        char model[160], dom[192];
        if (isfinite(b.model_mps)) {
            char mt[128];
            shol_band_model_text(&b, mt, sizeof mt);
            snprintf(model, sizeof model, "%+.1f%s%s%s", kt(b.model_mps), mt[0] ? " (" : "", mt, mt[0] ? ")" : "");
        } else
            snprintf(model, sizeof model, b.model_crit >= 0 && isnan(b.model_err) ? "not validated" : "not defined");
        rate_dominant(d, &b, dom, sizeof dom);
        char air[48] = "not known";
        if (isfinite(d->hub_speed_frac) && isfinite(d->hub_ti_frac))
            snprintf(air, sizeof air, "%.0f %%, %.1f %%", 100.0 * d->hub_speed_frac, 100.0 * d->hub_ti_frac);
        fprintf(f, "| %s | %s | %s | %s | %s | %s | %s | %s |\n", name, lim, at, lo, hi, model, dom, air);
    }
    fprintf(f, "\n\"none\" in the first band column: no point flown clearly passes (the points below the lowest "
               "flown are taken as passing, not flown); in the second: every point flown clearly fails. "
               "\"Model\": the flight model's validated error in the trim-based envelope's limiting quantity at "
               "this direction, as the limit's move (shol/band.c, the trim-based band's model source, carried to "
               "the flown limit); \"not validated\" where the aircraft states no error in it, \"not defined\" where "
               "the trim-based limit has no criterion or slope. \"Dominant\": which of the pass rate's interval and "
               "the model's error reaches further from the flown limit. The air at the hub: the "
               "direction's ship-only field at the main-rotor hub of the hover over the spot, its mean speed and "
               "sqrt(2k/3), each over the WOD speed: where the mean is sheltered (well under 100 %%) the "
               "intensity says how much of the wind comes as turbulence, which the flights fly and a trim cannot "
               "see.\n");
}

int shol_flown_write_report(const char *dir, const shol_flown_result *fr, const shol_result *trim,
                            const shol_report_info *info, core_err *err)
{
    char final[SHOL_IO_PATH_MAX], tmp[SHOL_IO_PATH_MAX];
    if (shol_io_mkdir(dir, err) < 0 || shol_io_paths(dir, "report.md", final, tmp, err) < 0)
        return -1;
    FILE *f = shol_io_open(tmp, err);
    if (!f)
        return -1;
    fprintf(f, "# %s: SHOL from flown landings\n\n", info && info->title ? info->title : "Candidate SHOL");
    fprintf(f, "Method: `disim shol --method pilot` (docs/shol.md, \"The flown envelope\"): at each WOD point the "
               "task is flown headless by the automated pilot, %d seed%s per point (seeds %llu to %llu); a flight "
               "fails at the first exceedance of a rejection criterion, at a crash, at a touchdown outside the "
               "task's adequate limits or when the adequate tolerances are not met; a point passes when its pass "
               "rate is at least %.2f. The search starts %d speed step%s below the trim-based radius.\n\n",
            fr->flown.n_seeds, fr->flown.n_seeds == 1 ? "" : "s", fr->flown.seed0,
            fr->flown.seed0 + (unsigned long long)fr->flown.n_seeds - 1, fr->flown.pass_rate_min,
            fr->flown.start_steps_below, fr->flown.start_steps_below == 1 ? "" : "s");
    fprintf(f, "Pass rate's interval: each point's 90 %% Wilson score interval (Wilson 1927, JASA 22(158); z = "
               "%.4f). A point **clearly passes** when the interval's lower bound reaches %.2f, **clearly fails** "
               "when its upper bound is below it, and is **undecided** between (more seeds would decide it). The "
               "flown limit is the highest speed whose pass rate reaches %.2f below the lowest speed that clearly "
               "fails (the search flies up to that failure); its band runs from the highest speed flown whose "
               "lower bound clears %.2f to the highest whose upper bound does.\n\n",
            SHOL_WILSON_Z90, fr->flown.pass_rate_min, fr->flown.pass_rate_min, fr->flown.pass_rate_min);
    fprintf(f, "Turbulence: where the scenario has it (`[wod] turbulence`, on unless set false; the `flown` line "
               "below says), every flight flies its own frozen gust field (seeded by the flight's seed) whose "
               "intensity and length scale come from the airwake field's k and epsilon at the aircraft's CG, "
               "sampled at every step where the aircraft is (sim/turbulence.c); calm air (0 kt) has none.\n\n");
    if (fr->flown.judge.window_s > 0)
        fprintf(f, "Criteria: the steady limits judge each quantity's running mean over the last %.3g s of the "
                   "task's phase; at every step a control at its stop and a roll or pitch beyond %.3g times its "
                   "limit reject at once.\n\n",
                fr->flown.judge.window_s, 1.0 + fr->flown.judge.transient_frac);
    else
        fprintf(f, "Criteria: the steady limits judge every step's values (no running mean).\n\n");
    if (trim) {
        const shol_criteria *k = &trim->settings.criteria;
        char reading[256];
        shol_criteria_reading(k, reading, sizeof reading);
        fprintf(f, "Rejection limits: |roll| > %g deg, |pitch| > %g deg; controls in %% of full travel, %s "
                   "(docs/conventions.md).\n\n",
                k->roll_max_rad * CORE_RAD_TO_DEG, k->pitch_max_rad * CORE_RAD_TO_DEG, reading);
    }
    if (info) {
        if (info->scenario_path)
            fprintf(f, "- scenario: `%s`\n", info->scenario_path);
        if (info->aircraft_path)
            fprintf(f, "- aircraft: `%s`\n", info->aircraft_path);
        if (info->grid)
            fprintf(f, "- grid: %s\n", info->grid);
        if (info->coupling)
            fprintf(f, "- flown: %s\n", info->coupling);
        if (info->compare_label)
            fprintf(f, "- trim-based envelope: %s\n", info->compare_label);
    }
    fprintf(f, "- %d flights, %.0f s flown in %.0f s of wall time (%.2f s of wall time per minute flown)\n\n",
            fr->n_flights, fr->flown_s, fr->wall_s, fr->flown_s > 0 ? 60.0 * fr->wall_s / fr->flown_s : 0.0);
    if (info && info->notes_md)
        fprintf(f, "%s\n\n", info->notes_md);
    fprintf(f, "![flown over trim-based](shol_polar_flown.png)\n\n");
    fprintf(f, "## Direction by direction\n\n");
    fprintf(f, "| WOD | trim-based (kt) | its limit | flown (kt) | pass rate there | first failure (kt) | pass rate | "
               "cause | flown - trim (kt) |\n|---|---|---|---|---|---|---|---|---|\n");
    for (int i = 0; i < fr->n_dirs; i++) {
        const shol_flown_dir *d = &fr->dirs[i];
        char name[32], a[16], b[16], c[16], pr[16], pf[16], dd[16];
        core_wod_name(d->dir_rad * CORE_RAD_TO_DEG, name, sizeof name);
        fmt_kt(a, sizeof a, d->trim_has_pass, d->trim_max_speed_mps);
        fmt_kt(b, sizeof b, d->has_pass, d->max_speed_mps);
        fmt_kt(c, sizeof c, !isnan(d->fail_speed_mps), d->fail_speed_mps);
        snprintf(pr, sizeof pr, isnan(d->pass_rate_max) ? "-" : "%.2f", d->pass_rate_max);
        snprintf(pf, sizeof pf, isnan(d->pass_rate_fail) ? "-" : "%.2f", d->pass_rate_fail);
        snprintf(dd, sizeof dd, "%+.1f", kt((d->has_pass ? d->max_speed_mps : 0) - d->trim_max_speed_mps));
        fprintf(f, "| %s | %s | %s | %s | %s | %s | %s | %s | %s |\n", name, a,
                shol_limit_name(d->trim_limit) ? shol_limit_name(d->trim_limit) : "none", b, pr, c, pf, d->cause,
                dd);
    }
    /* the shape, said in numbers: the largest radius and where */
    int ibest = -1, tbest = -1;
    for (int i = 0; i < fr->n_dirs; i++) {
        if (fr->dirs[i].has_pass && (ibest < 0 || fr->dirs[i].max_speed_mps > fr->dirs[ibest].max_speed_mps))
            ibest = i;
        if (fr->dirs[i].trim_has_pass &&
            (tbest < 0 || fr->dirs[i].trim_max_speed_mps > fr->dirs[tbest].trim_max_speed_mps))
            tbest = i;
    }
    if (ibest >= 0) {
        char n1[32], n2[32];
        core_wod_name(fr->dirs[ibest].dir_rad * CORE_RAD_TO_DEG, n1, sizeof n1);
        core_wod_name(tbest >= 0 ? fr->dirs[tbest].dir_rad * CORE_RAD_TO_DEG : 0, n2, sizeof n2);
        fprintf(f, "\nThe flown envelope is largest at %s (%.1f kt); the trim-based one at %s (%.1f kt).\n", n1,
                kt(fr->dirs[ibest].max_speed_mps), tbest >= 0 ? n2 : "none",
                tbest >= 0 ? kt(fr->dirs[tbest].trim_max_speed_mps) : 0.0);
    }
    write_rate_bands(f, fr);
    write_flown_bands(f, fr, trim);
    if (info && info->checks) {
        fprintf(f, "\n## Physics checks of the flown envelope\n\n| check | result | detail |\n|---|---|---|\n");
        for (int i = 0; i < info->checks->n; i++) {
            const shol_check *c = &info->checks->c[i];
            fprintf(f, "| %s | %s | %s |\n", c->name, !c->applicable ? "not applicable" : c->pass ? "pass" : "FAIL",
                    c->detail);
        }
    }
    fprintf(f, "\n## Every point flown\n\nThe criteria's result (the pass rate, its interval and verdict, the most "
               "frequent cause) and, for the replay pilot, its tracking beside it: the flown CG's distance from the "
               "recorded run (rms over the flights' rms, the largest max) and the flights that stayed within the "
               "replay's tolerance, whatever failed them. The tracking is not a rejection criterion: it is the "
               "replay's distance from its recording, and a flight fails on \"could not track\" only where that "
               "distance exceeded the tolerance and no crash, criterion or touchdown sink came first.\n\n| WOD | "
               "speed (kt) | flights | passed | pass rate | 90 %% interval | point | verdict | most frequent cause "
               "| tracking rms / max (m) | tracked |\n|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (int i = 0; i < fr->n_dirs; i++)
        for (int k = 0; k < fr->dirs[i].n_points; k++) {
            const shol_flown_point *q = &fr->dirs[i].points[k];
            char name[32];
            core_wod_name(fr->dirs[i].dir_rad * CORE_RAD_TO_DEG, name, sizeof name);
            char tr[48] = "-", tk[24] = "-";
            if (isfinite(q->track_rms_m))
                snprintf(tr, sizeof tr, "%.2f / %.2f", q->track_rms_m, q->track_max_m);
            if (q->n_tracked >= 0)
                snprintf(tk, sizeof tk, "%d of %d", q->n_tracked, q->n_flights);
            fprintf(f, "| %s | %.1f | %d | %d | %.2f | %.2f-%.2f | %s | %s | %s | %s | %s |\n", name,
                    kt(q->speed_mps), q->n_flights, q->n_pass, q->pass_rate, q->rate_lo, q->rate_hi,
                    q->pass ? "pass" : "fail", shol_flown_verdict_name(q->verdict), q->cause[0] ? q->cause : "-", tr,
                    tk);
        }
    fprintf(f, "\nFiles: `shol_flown.csv` (per direction), `shol_flown_points.csv` (per point), `shol_flown.json`, "
               "`shol_polar_flown.png`/`.svg`; the trim-based envelope beside them as `shol.csv` and `shol.json`.\n");
    return shol_io_commit(f, tmp, final, err);
}

int shol_flown_write_all(const char *dir, const shol_flown_result *f, const shol_result *trim,
                         const shol_report_info *info, core_err *err)
{
    char stage[SHOL_IO_PATH_MAX];
    if (shol_io_stage_begin(dir, stage, err) < 0)
        return -1;
    if (shol_flown_write_csv(stage, f, err) < 0 || shol_flown_write_json(stage, f, info, err) < 0 ||
        shol_flown_plot_polar(stage, f, trim, info, err) < 0 ||
        shol_flown_write_report(stage, f, trim, info, err) < 0 ||
        (trim && (shol_write_csv(stage, trim, err) < 0 || shol_write_json(stage, trim, NULL, err) < 0))) {
        shol_io_stage_abort(stage);
        return -1;
    }
    return shol_io_stage_commit(dir, stage, err);
}
