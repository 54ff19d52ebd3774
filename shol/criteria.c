/*
 * criteria.c -- rejection criteria for the trim-based candidate SHOL.
 *
 * Model: a trimmed hover over the spot is rejected when an attitude or a
 * control position is beyond its limit (seed paper section 2.7, Table 4;
 * docs/conventions.md "Rejection criteria"). The seed paper's section
 * 3.4.1 gives Table 4's control limits as "the percentage of each control
 * variable to the design maximum", a displacement; read as the convention
 * reads it, with each control c in percent of full travel:
 *   roll and pitch      abs(phi) > roll limit, abs(theta) > pitch limit;
 *   cyclic and pedal    a displacement from neutral (50 %) of L % of the
 *                       travel to the stop: c < 50 - L/2 or c > 50 + L/2
 *                       (pedal 80 %: below 10 % or above 90 %);
 *   collective          a displacement from full down: c > L.
 * Margins are signed distances to the limit (negative beyond it):
 *   attitude            m = limit - abs(angle)       [rad]
 *   cyclic and pedal    m = L/2 - abs(c - 50)        [percentage points]
 *   collective          m = L - c                    [percentage points]
 * The limiting criterion compares margins as fractions of each allowed
 * displacement (the limit for an attitude, L/2 for a cyclic or the pedal,
 * L for the collective: shol_criteria_half_band), so that degrees and
 * percent can be ranked together.
 * Assumptions: only objective, steady-trim criteria (no pilot workload, no
 * transient response), as in the seed paper.
 */
#include "shol.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define SECTION "rejection"

static const char *const limit_names[] = {"roll",       "pitch", "long_cyclic", "lat_cyclic",
                                          "collective", "pedal", "trim"};

const char *shol_limit_name(int limit)
{
    if (limit == SHOL_LIMIT_NONE)
        return "none";
    if (limit >= 0 && limit <= SHOL_LIMIT_TRIM)
        return limit_names[limit];
    return NULL;
}

int shol_limit_parse(const char *name, int *limit)
{
    for (int i = SHOL_LIMIT_NONE; i <= SHOL_LIMIT_TRIM; i++)
        if (strcmp(name, shol_limit_name(i)) == 0) {
            *limit = i;
            return 0;
        }
    return -1;
}

void shol_criteria_default(shol_criteria *c)
{
    c->roll_max_rad = 5.0 * CORE_DEG_TO_RAD;
    c->pitch_max_rad = 8.0 * CORE_DEG_TO_RAD;
    c->long_cyclic_pct = 85.0;
    c->lat_cyclic_pct = 85.0;
    c->collective_pct = 85.0;
    c->pedal_pct = 80.0;
}

int shol_criteria_read(core_ini *ini, shol_criteria *c, core_err *err)
{
    static const char *const keys[] = {"roll_deg",       "pitch_deg",      "long_cyclic_pct",
                                       "lat_cyclic_pct", "collective_pct", "pedal_pct"};
    shol_criteria d;
    shol_criteria_default(&d);
    double roll_deg = d.roll_max_rad * CORE_RAD_TO_DEG;
    double pitch_deg = d.pitch_max_rad * CORE_RAD_TO_DEG;

    /* A misspelt key would silently fall back to a default and widen the
     * envelope: reject anything in [rejection] that is not ours. */
    size_t n = core_ini_count(ini);
    for (size_t i = 0; i < n; i++) {
        const core_ini_entry *e = core_ini_at(ini, i);
        if (strcmp(e->section, SECTION) != 0)
            continue;
        int known = 0;
        for (size_t k = 0; k < sizeof keys / sizeof keys[0]; k++)
            known |= strcmp(e->key, keys[k]) == 0;
        if (!known)
            return core_err_set(err, -1,
                                "%s:%d: [%s] %s: unknown key, expected one of roll_deg, "
                                "pitch_deg, long_cyclic_pct, lat_cyclic_pct, collective_pct, "
                                "pedal_pct",
                                core_ini_path(ini), e->line, SECTION, e->key);
    }

    /* The getters name file:line:key and the expected range. A control limit
     * is 50 to 100 %: a cyclic or the pedal then keeps at least a quarter of
     * full travel either side of neutral, the collective half its travel. */
    if (core_ini_get_double(ini, SECTION, keys[0], 0, 0.0, 90.0, &roll_deg, err) < 0 ||
        core_ini_get_double(ini, SECTION, keys[1], 0, 0.0, 90.0, &pitch_deg, err) < 0 ||
        core_ini_get_double(ini, SECTION, keys[2], 0, 50.0, 100.0, &d.long_cyclic_pct, err) < 0 ||
        core_ini_get_double(ini, SECTION, keys[3], 0, 50.0, 100.0, &d.lat_cyclic_pct, err) < 0 ||
        core_ini_get_double(ini, SECTION, keys[4], 0, 50.0, 100.0, &d.collective_pct, err) < 0 ||
        core_ini_get_double(ini, SECTION, keys[5], 0, 50.0, 100.0, &d.pedal_pct, err) < 0)
        return -1;
    d.roll_max_rad = roll_deg * CORE_DEG_TO_RAD;
    d.pitch_max_rad = pitch_deg * CORE_DEG_TO_RAD;
    *c = d;
    return 0;
}

int shol_criteria_load(const char *path, shol_criteria *c, core_err *err)
{
    core_ini *ini = core_ini_load(path, err);
    if (!ini)
        return -1;
    int rc = shol_criteria_read(ini, c, err);
    core_ini_destroy(ini);
    return rc;
}

double shol_criteria_half_band(const shol_criteria *c, int i)
{
    switch (i) {
    case SHOL_CRIT_ROLL: return c->roll_max_rad;
    case SHOL_CRIT_PITCH: return c->pitch_max_rad;
    case SHOL_CRIT_LONG: return 0.5 * c->long_cyclic_pct;
    case SHOL_CRIT_LAT: return 0.5 * c->lat_cyclic_pct;
    case SHOL_CRIT_COLL: return c->collective_pct;
    case SHOL_CRIT_PEDAL: return 0.5 * c->pedal_pct;
    default: return NAN;
    }
}

void shol_criteria_control_bounds(const shol_criteria *c, int i, double *lo_pct, double *hi_pct)
{
    if (i == SHOL_CRIT_COLL) {
        *lo_pct = -INFINITY;
        *hi_pct = c->collective_pct;
        return;
    }
    double h = i >= SHOL_CRIT_LONG && i <= SHOL_CRIT_PEDAL ? shol_criteria_half_band(c, i) : NAN;
    *lo_pct = 50.0 - h;
    *hi_pct = 50.0 + h;
}

void shol_criteria_reading(const shol_criteria *c, char *buf, size_t n)
{
    char cyc[160];
    if (c->long_cyclic_pct == c->lat_cyclic_pct)
        snprintf(cyc, sizeof cyc, "cyclic %g %% = %g-%g %%", c->long_cyclic_pct, 50 - 0.5 * c->long_cyclic_pct,
                 50 + 0.5 * c->long_cyclic_pct);
    else
        snprintf(cyc, sizeof cyc, "long cyclic %g %% = %g-%g %%, lat cyclic %g %% = %g-%g %%", c->long_cyclic_pct,
                 50 - 0.5 * c->long_cyclic_pct, 50 + 0.5 * c->long_cyclic_pct, c->lat_cyclic_pct,
                 50 - 0.5 * c->lat_cyclic_pct, 50 + 0.5 * c->lat_cyclic_pct);
    snprintf(buf, n,
             "cyclic and pedal limits are displacements from neutral: pedal %g %% = %g-%g %% of travel, %s; "
             "collective %g %% from full down, rejected above %g %%",
             c->pedal_pct, 50 - 0.5 * c->pedal_pct, 50 + 0.5 * c->pedal_pct, cyc, c->collective_pct,
             c->collective_pct);
}

/* A cyclic's or the pedal's margin: half_pct (L/2) less the displacement
 * from neutral. */
static double neutral_margin(double c_pct, double half_pct) { return half_pct - fabs(c_pct - 50.0); }

int shol_criteria_eval(const shol_criteria *c, const shol_trim_point *p, shol_eval *out)
{
    const double v[SHOL_NCRIT] = {p->phi_rad,        p->theta_rad,      p->long_cyclic_pct,
                                  p->lat_cyclic_pct, p->collective_pct, p->pedal_pct};
    memset(out, 0, sizeof *out);
    for (int i = 0; i < SHOL_NCRIT; i++)
        if (!isfinite(v[i])) {
            for (int k = 0; k < SHOL_NCRIT; k++)
                out->margin[k] = NAN;
            out->limit = SHOL_LIMIT_TRIM;
            return -1;
        }
    out->margin[SHOL_CRIT_ROLL] = c->roll_max_rad - fabs(p->phi_rad);
    out->margin[SHOL_CRIT_PITCH] = c->pitch_max_rad - fabs(p->theta_rad);
    out->margin[SHOL_CRIT_LONG] = neutral_margin(p->long_cyclic_pct, shol_criteria_half_band(c, SHOL_CRIT_LONG));
    out->margin[SHOL_CRIT_LAT] = neutral_margin(p->lat_cyclic_pct, shol_criteria_half_band(c, SHOL_CRIT_LAT));
    out->margin[SHOL_CRIT_COLL] = c->collective_pct - p->collective_pct;
    out->margin[SHOL_CRIT_PEDAL] = neutral_margin(p->pedal_pct, shol_criteria_half_band(c, SHOL_CRIT_PEDAL));

    double best = INFINITY;
    out->limit = 0;
    for (int i = 0; i < SHOL_NCRIT; i++)
        if (out->margin[i] < 0)
            out->n_exceeded++;
    for (int i = 0; i < SHOL_NCRIT; i++) {
        if (out->n_exceeded && out->margin[i] >= 0)
            continue;
        /* A zero-width band (a limit of 0) leaves only the sign. */
        double b = shol_criteria_half_band(c, i);
        double f = b > 0 ? out->margin[i] / b : (out->margin[i] < 0 ? -INFINITY : 0);
        if (f < best) {
            best = f;
            out->limit = i;
        }
    }
    return 0;
}
