/*
 * report.c -- the short Markdown report of a candidate SHOL: settings and
 * criteria, the polar plot, the envelope table, the trim-versus-speed plots,
 * the coupling histories (text the caller supplies) and, with a second
 * result set, a direction-by-direction comparison (e.g. two-way coupled
 * versus one-way airwake).
 */
#include "io.h"
#include "shol.h"

#include <math.h>
#include <string.h>

static const char *or_dash(const char *s)
{
    return s && *s ? s : "-";
}

static const shol_dir_result *find_dir(const shol_result *c, double dir_rad)
{
    for (int i = 0; c && i < c->n_dirs; i++)
        if (fabs(c->dirs[i].dir_rad - dir_rad) < 1e-6)
            return &c->dirs[i];
    return NULL;
}

/* "24.3 kt (45 km/h)" or "none" (rejected at 0). */
static void speed_txt(const shol_dir_result *d, char *buf, size_t n)
{
    if (!d)
        snprintf(buf, n, "not computed");
    else if (!d->has_pass)
        snprintf(buf, n, "none (rejected at 0)");
    else
        snprintf(buf, n, "%.1f kt (%.1f km/h)", d->max_speed_mps / CORE_KT_TO_MPS,
                 d->max_speed_mps / CORE_KMH_TO_MPS);
}

/* A table cell's text: a '|' in a path would end the cell, a newline the
 * row, and the rest of the table would be shifted. */
static void md_cell(FILE *f, const char *s)
{
    for (; *s; s++) {
        if (*s == '|' || *s == '\\')
            fputc('\\', f);
        fputc(*s == '\n' || *s == '\r' ? ' ' : *s, f);
    }
}

/* Beam winds sheltered by a steady mean (docs/shol.md, "LPD-17's
 * beam winds: physics or the steady mean"): a direction within 15 deg of
 * the beam whose trim-based limit reaches the top of the search or passes
 * the head wind's goes against the seed paper's expectation of crosswind
 * limits below those near the bow (shol/checks.c, "smaller in crosswinds").
 * Over a deck the hover there sits in the windward edge's separated shear
 * layer; the trim passes in the mean of that flow and sees none of its
 * gusts, so the limit rests on the steady mean's shelter. Named here as
 * low confidence whatever its band says (the band measures the spreads of
 * the mean, not the unsteadiness). */
static int beam_sheltered(const shol_result *r, int i, double head_mps)
{
    const shol_dir_result *d = &r->dirs[i];
    double deg = fabs(remainder(d->dir_rad * CORE_RAD_TO_DEG, 360.0));
    if (fabs(deg - 90.0) > 15.0 + 1e-9 || !d->has_pass)
        return 0;
    return d->limit == SHOL_LIMIT_NONE || (isfinite(head_mps) && d->max_speed_mps > head_mps + 1e-9);
}

static void write_beam_note(FILE *f, const shol_result *r)
{
    double head = NAN;
    for (int i = 0; i < r->n_dirs; i++)
        if (fabs(remainder(r->dirs[i].dir_rad * CORE_RAD_TO_DEG, 360.0)) < 1e-6 && r->dirs[i].has_pass)
            head = r->dirs[i].max_speed_mps;
    int j = 0;
    for (int i = 0; i < r->n_dirs; i++) {
        if (!beam_sheltered(r, i, head))
            continue;
        char n[32];
        core_wod_name(r->dirs[i].dir_rad * CORE_RAD_TO_DEG, n, sizeof n);
        fprintf(f, "%s%s (%.1f km/h%s)", j++ ? ", " : "**Low confidence: beam winds resting on the steady mean:** ",
                n, r->dirs[i].max_speed_mps / CORE_KMH_TO_MPS,
                r->dirs[i].limit == SHOL_LIMIT_NONE ? ", nothing failed" : ", above the head wind's");
    }
    if (j)
        fprintf(f, ". Here the hover sits in the shear layer of the windward deck edge's separation, and the "
                   "trim passed in the steady mean of that flow (for a field that sheds, the mean of its last "
                   "iterations), whose shelter moves with grid and iteration. A trim sees no gusts: with a "
                   "turbulence intensity I the limiting control swings by about |d control / d V| I U, more than "
                   "the margin a sheltered trim leaves for I of 0.1-0.2. The seed paper expects crosswind limits "
                   "below those near the bow (the physics check \"smaller in crosswinds\"); use the flown envelope (`--method pilot`, with turbulence) "
                   "or a time-accurate field for these directions (docs/shol.md, \"LPD-17's beam winds\").\n\n");
}

/* The bands section: each direction's value, band and what
 * makes it, and the directions of low confidence named. */
static void write_bands(FILE *f, const shol_result *r)
{
    const shol_band_rule k = shol_band_rule_of(r);
    const double K = CORE_KMH_TO_MPS;
    fprintf(f, "## Uncertainty bands\n\n");
    fprintf(f, "| WOD | limit (km/h) | band (km/h) | what makes it (km/h) | dominant | confidence |\n"
               "|---|---|---|---|---|---|\n");
    int n_low = 0, n_grid = 0;
    for (int i = 0; i < r->n_dirs; i++) {
        const shol_dir_result *d = &r->dirs[i];
        shol_band b;
        shol_band_get(r, i, &b);
        char n[32], what[256];
        core_wod_name(d->dir_rad * CORE_RAD_TO_DEG, n, sizeof n);
        shol_band_format(&b, r->band_grid_label, d->limit, what, sizeof what);
        fprintf(f, "| %s | %.1f | %.1f-%.1f%s | ", n, d->has_pass ? d->max_speed_mps / K : 0.0, b.lo_mps / K,
                b.hi_mps / K, b.open_above ? " (nothing failed: open above)" : "");
        md_cell(f, what);
        char dom[192];
        shol_band_dominant(&b, dom, sizeof dom);
        fputs(" | ", f);
        md_cell(f, dom);
        fprintf(f, " | %s |\n", b.low_confidence ? "**low**" : "ok");
        n_low += b.low_confidence;
        n_grid += isfinite(b.grid_mps);
    }
    fprintf(f,
            "\nEach source is a speed interval round the limit and the band is their hull (shol/band.c, "
            "docs/shol.md \"Uncertainty bands\"): **grid**, the same limit on another grid level, from the limit "
            "to that one (signed: the other grid's limit minus this one); **window**, the field's averaging-window "
            "spread s (the monitors' mean drift or mean change, / WOD speed) as +- s V at the limit V; "
            "**0.25 deg / 1 %%**, +- how far the limit moves for 0.25 deg of attitude or 1 %% of control travel in "
            "the limiting quantity (\"limit moves by\" above); **model**, the flight model's validated error in "
            "the limiting quantity (model minus reference, the aircraft file's `[model_error]`) turned into speed "
            "through the same slope, from the limit to where the truth (the model less its error) reaches the "
            "limit (signed: + where the truth is further from the limit). **Dominant**: the source that reaches "
            "furthest from the limit. A band is **low** confidence when it is wider than "
            "%g km/h or %g %% of the limit, whichever is larger.%s%s\n\n",
            k.width_mps / K, 100 * k.frac,
            n_grid ? ""
                   : " No second grid level was available for this envelope: its bands hold the window and "
                     "sensitivity sources only, and a grid's spread can be larger than both "
                     "(docs/validation.md, \"Grid sensitivity\").",
            r->band_model_label[0] ? ""
                                   : " The aircraft states no validated error (its file has no `[model_error]`: "
                                     "model: not validated): these bands hold nothing of the flight model's own "
                                     "error.");
    if (n_low) {
        fprintf(f, "**Low confidence, where an at-sea test is most needed:** ");
        int j = 0;
        for (int i = 0; i < r->n_dirs; i++) {
            shol_band b;
            shol_band_get(r, i, &b);
            if (!b.low_confidence)
                continue;
            char n[32];
            core_wod_name(r->dirs[i].dir_rad * CORE_RAD_TO_DEG, n, sizeof n);
            char dom[192];
            shol_band_dominant(&b, dom, sizeof dom);
            fprintf(f, "%s%s (%.1f-%.1f km/h, dominant: ", j++ ? ", " : "", n, b.lo_mps / K, b.hi_mps / K);
            md_cell(f, dom);
            fputc(')', f);
        }
        fprintf(f, ". The seed paper (section 2.8) uses a candidate SHOL so that \"only the regions with low "
                   "confidence in the candidate SHOL and/or small safety margins need to be tested\" at sea: "
                   "these directions are those regions.\n\n");
    } else {
        fprintf(f, "No band is wider than the rule: no direction is marked low confidence.\n\n");
    }
    write_beam_note(f, r);
}

int shol_write_report(const char *dir, const shol_result *r, const shol_report_info *info,
                      core_err *err)
{
    char final[SHOL_IO_PATH_MAX], tmp[SHOL_IO_PATH_MAX];
    if (shol_io_mkdir(dir, err) < 0 || shol_io_paths(dir, "report.md", final, tmp, err) < 0)
        return -1;
    FILE *f = shol_io_open(tmp, err);
    if (!f)
        return -1;
    shol_report_info none = {0};
    if (!info)
        info = &none;
    const shol_settings *s = &r->settings;
    const shol_criteria *k = &s->criteria;
    const char *label = info->label ? info->label : "envelope";

    fprintf(f, "# Candidate SHOL: %s\n\n", info->title ? info->title : "trim-based envelope");
    fprintf(f, "Trim-based candidate ship-helicopter operating limits (the seed paper's "
               "section 2.8): at each wind-over-deck direction the helicopter is trimmed over the "
               "spot at rising wind speeds; the envelope radius is the last speed at which no "
               "rejection criterion is exceeded. A candidate envelope supports, and does not "
               "replace, at-sea flight test.\n\n");

    fprintf(f, "## Settings\n\n| setting | value |\n|---|---|\n");
    const char *row[4][2] = {{"scenario", info->scenario_path},
                             {"aircraft", info->aircraft_path},
                             {"grid", info->grid},
                             {"coupling", info->coupling}};
    for (int i = 0; i < 4; i++) {
        fprintf(f, "| %s | ", row[i][0]);
        md_cell(f, or_dash(row[i][1]));
        fprintf(f, " |\n");
    }
    fprintf(f, "| directions | %d:", s->n_dirs);
    for (int i = 0; i < s->n_dirs; i++) {
        char n[32];
        core_wod_name(s->dirs_rad[i] * CORE_RAD_TO_DEG, n, sizeof n);
        fprintf(f, "%s %s", i ? "," : "", n);
    }
    fprintf(f,
            " |\n| speed step | %g km/h (%.2f kt) |\n| highest speed searched | %g km/h "
            "(%.1f kt) |\n",
            s->speed_step_mps / CORE_KMH_TO_MPS, s->speed_step_mps / CORE_KT_TO_MPS,
            s->speed_max_mps / CORE_KMH_TO_MPS, s->speed_max_mps / CORE_KT_TO_MPS);
    if (s->bisect_tol_mps > 0)
        fprintf(f, "| bisection | to %g km/h after the first failure |\n",
                s->bisect_tol_mps / CORE_KMH_TO_MPS);
    else
        fprintf(f, "| bisection | off |\n");
    fprintf(f, "| trims | %d in %.1f s |\n\n", r->n_trims, r->wall_s);
    char reading[256];
    shol_criteria_reading(k, reading, sizeof reading);
    fprintf(f,
            "Rejection criteria (aircraft data file `[rejection]`): |roll| > %g deg, |pitch| > %g deg, "
            "longitudinal cyclic %g %%, lateral cyclic %g %%, collective %g %%, pedal %g %%. Controls in %% of "
            "full travel; %s (docs/conventions.md).\n\n",
            k->roll_max_rad * CORE_RAD_TO_DEG, k->pitch_max_rad * CORE_RAD_TO_DEG,
            k->long_cyclic_pct, k->lat_cyclic_pct, k->collective_pct, k->pedal_pct, reading);

    fprintf(f, "## Envelope\n\n![Candidate SHOL polar plot](shol_polar.png)\n\n"
               "Vector version: [shol_polar.svg](shol_polar.svg); data: [shol.csv](shol.csv), "
               "[shol.json](shol.json).\n\n");
    fprintf(f,
            "| WOD | max speed (%s) | limit | margins at the last pass: roll deg, pitch deg, "
            "long %%, lat %%, coll %%, pedal %% (points of travel to the limit) | limit moves by | driven by | "
            "trim plot |\n|---|---|---|---|---|---|---|\n",
            label);
    for (int i = 0; i < r->n_dirs; i++) {
        const shol_dir_result *d = &r->dirs[i];
        char n[32], sp[64], plot[64];
        core_wod_name(d->dir_rad * CORE_RAD_TO_DEG, n, sizeof n);
        speed_txt(d, sp, sizeof sp);
        shol_trim_plot_name(d->dir_rad, plot, sizeof plot);
        fprintf(f, "| %s | %s | %s |", n, sp, shol_limit_name(d->limit));
        for (int c = 0; c < SHOL_NCRIT; c++) {
            double m = d->margins.margin[c] * (c <= SHOL_CRIT_PITCH ? CORE_RAD_TO_DEG : 1);
            if (isfinite(m))
                fprintf(f, "%s %.2f", c ? "," : "", m);
            else
                fprintf(f, "%s -", c ? "," : "");
        }
        shol_sensitivity se;
        if (shol_envelope_sensitivity(d, &se) == 0) {
            /* the reference error as shol_envelope_sensitivity chose it */
            const int ang = se.crit <= SHOL_CRIT_PITCH;
            fprintf(f, " | %.1f km/h per %g %s |", se.shift_mps / CORE_KMH_TO_MPS,
                    se.ref_error * (ang ? CORE_RAD_TO_DEG : 1.0), ang ? "deg" : "%");
        } else
            fprintf(f, " | - |");
        /* what drives the limiting quantity (shol_envelope_attribution) */
        shol_attribution at;
        char drv[256];
        if (shol_envelope_attribution(d, -1, &at) == 0) {
            shol_attribution_format(&at, drv, sizeof drv);
            fputc(' ', f);
            if (!at.at_limit)
                fprintf(f, "(closest, %s) ", shol_limit_name(at.crit));
            md_cell(f, drv);
            int sec = -1;
            shol_attribution as;
            shol_crit_budget(at.crit, &sec);
            if (sec >= 0 && shol_envelope_attribution(d, sec, &as) == 0) {
                shol_attribution_format(&as, drv, sizeof drv);
                fputs("; ", f);
                md_cell(f, drv);
            }
            fputs(" |", f);
        } else
            fprintf(f, " - |");
        fprintf(f, " [%s](%s) |\n", plot, plot);
    }
    fprintf(f, "\n\"none\" means no criterion was exceeded up to the highest speed searched; "
               "\"trim\" means the trim did not converge, which counts as a rejection. "
               "\"Limit moves by\": how far the limit would move if the limiting quantity were "
               "off by 0.25 deg (an attitude) or 1 %% of travel (a control), from its margin's "
               "fall between the last pass and the first failure; a limit that moves by more "
               "than a speed step for an error that small is no sharper than the trim and the "
               "airwake behind it. \"Driven by\": the flight-model component whose load change, from "
               "the direction's lowest speed to the first failure, the limiting quantity had to "
               "balance most (shol/attrib.c, docs/shol.md \"What drives a limit\"): the limiting "
               "quantity's budget (pedal: the yaw moment; cyclic and attitudes: the pitch or roll "
               "moment; collective: the vertical force; an attitude also its horizontal force), its "
               "largest share of the change of the effector (the tail rotor for the pedal, else the "
               "main rotor), and that change against the effector's value at the lowest speed. A "
               "change of the effector's own effectiveness (tail-rotor inflow, translational lift) "
               "moves the control without a change in the budget; \"closest\" marks a direction "
               "limited by no criterion (or a failed trim), attributed at the last pass.\n\n");

    write_bands(f, r);

    fprintf(f, "## Physics checks\n\n");
    if (info->checks && info->checks->n) {
        fprintf(f, "| check | result | figures |\n|---|---|---|\n");
        for (int i = 0; i < info->checks->n; i++) {
            const shol_check *k = &info->checks->c[i];
            fprintf(f, "| %s | %s | %s |\n", k->name, !k->applicable ? "not applicable" : k->pass ? "pass" : "**FAIL**",
                    k->detail);
        }
        fprintf(f, "\nThe checks and their reasoning are in shol/checks.c (docs/shol.md).\n\n");
    } else {
        fprintf(f, "No physics checks were run on this envelope.\n\n");
    }

    fprintf(f, "## Airwake fields\n\n");
    if (info->fields_md && *info->fields_md)
        fprintf(f, "%s\n\n", info->fields_md);
    else
        fprintf(f, "No list of the airwake fields was supplied with this envelope.\n\n");

    fprintf(f, "## Coupling histories\n\n");
    if (info->coupling_md && *info->coupling_md)
        fprintf(f, "%s\n\n", info->coupling_md);
    else
        fprintf(f, "No coupling history was supplied with this envelope.\n\n");

    fprintf(f, "## Comparison\n\n");
    if (info->compare) {
        const char *cl = info->compare_label ? info->compare_label : "comparison";
        fprintf(f, "| WOD | %s | limit | %s | limit | difference |\n|---|---|---|---|---|---|\n",
                label, cl);
        for (int i = 0; i < r->n_dirs; i++) {
            const shol_dir_result *d = &r->dirs[i];
            const shol_dir_result *c = find_dir(info->compare, d->dir_rad);
            char n[32], a[64], b[64];
            core_wod_name(d->dir_rad * CORE_RAD_TO_DEG, n, sizeof n);
            speed_txt(d, a, sizeof a);
            speed_txt(c, b, sizeof b);
            fprintf(f, "| %s | %s | %s | %s | %s | ", n, a, shol_limit_name(d->limit), b,
                    c ? shol_limit_name(c->limit) : "-");
            if (c) {
                double dv = d->max_speed_mps - c->max_speed_mps;
                fprintf(f, "%+.1f kt (%+.1f km/h) |\n", dv / CORE_KT_TO_MPS, dv / CORE_KMH_TO_MPS);
            } else {
                fprintf(f, "- |\n");
            }
        }
        fprintf(f,
                "\nDifference = %s minus %s; with fixed speed steps a difference below one "
                "step (%g km/h) is not resolved.\n",
                label, cl, s->speed_step_mps / CORE_KMH_TO_MPS);
    } else {
        fprintf(f, "No second envelope was supplied for comparison.\n");
    }
    return shol_io_commit(f, tmp, final, err);
}
