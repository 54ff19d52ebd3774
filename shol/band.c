/*
 * band.c -- each direction's limit as a value and a band.
 *
 * Model: a candidate SHOL supports at-sea flight test, which need test
 * only "the regions with low confidence in the candidate SHOL and/or small
 * safety margins" (the seed paper, section 2.8). The confidence is stated
 * from what the project measures, three sources per direction, each a
 * speed interval round the limit V (shol.h, shol_band):
 *  1. the grid: the same limit on another grid level, V_g. The interval
 *     runs from V to V_g: which of the two is nearer the truth is not
 *     known, and the grid family need not converge (docs/validation.md,
 *     "Grid sensitivity").
 *  2. the averaging window: an unconverged field is the mean of its last
 *     iterations, and that mean is uncertain by s (the largest difference
 *     of the monitors' means between the window's halves, mean_drift, or
 *     between the last window and the one before, mean_change; both / the
 *     WOD speed). A ship-only field serves every speed scaled by V, so at
 *     the limit the air at the rotor is uncertain by s V, and the limiting
 *     quantity q by |dq/dV| s V (its slope with speed, the secant of
 *     shol_envelope_sensitivity); the speed at which q reaches its limit
 *     then moves by s V: the slope cancels. The bound takes the spread as
 *     an error along the air the speed scales; a spread that turns the
 *     flow where the rotor sits in a slow region moves the limit more, and
 *     the grid spread is what measures that.
 *  3. the sensitivity: +- the limit's move for 0.25 deg of attitude or
 *     1 % of control travel (shol_envelope_sensitivity), the floors of the
 *     coupling loop's 5 % test and the smallest error the trim is held to.
 *  4. the model: the flight model's own error where it was validated, e
 *     (model minus reference: GenHel's trim for the UH-60A, the aircraft
 *     file's [model_error]) in the limiting quantity q. The truth is
 *     q - e; where q crosses its upper limit the truth's margin is the
 *     model's plus e, at a lower limit minus e, and through the margin's
 *     measured slope with speed (the secant of shol_envelope_sensitivity)
 *     the limit moves by side e / slope. The interval runs from V to that
 *     shifted limit, as the grid's does: the error is measured with its
 *     sign, so the side the truth lies on is known. It is the error at
 *     one condition (the validated trim of the hover the limits are
 *     reached in: the UH-60A's 1 kt row) carried to the limit unchanged:
 *     the error of a trim in the free air, not of the airwake's effect
 *     on it, and not measured at the limit's own speed.
 * The band is the hull of the four intervals, not a sum: 1-3 are not
 * independent (2 and 3 are both errors in the air at the rotor, and 1 is
 * one too), and the hull is what any one of them alone already allows.
 * The model's error is independent of the air's, and a sum of 4 with the
 * hull of 1-3 would be the bound of both errors at once; the hull keeps
 * the band what one source alone allows and names the dominant one, so
 * that a band set by the flight model is told from one set by the
 * airwake.
 * It is clipped at 0 km/h, and at the radius where nothing failed up to
 * the highest speed searched (the search says nothing above it).
 * Low confidence: a band wider than the larger of 10 km/h (two speed
 * steps) and a quarter of the limit (shol_band_rule).
 */
#include "shol.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

void shol_band_rule_default(shol_band_rule *r)
{
    r->width_mps = 10.0 * CORE_KMH_TO_MPS;
    r->frac = 0.25;
}

void shol_band_inputs_default(shol_band_inputs *in)
{
    memset(in, 0, sizeof *in);
    shol_model_error_none(&in->model);
    shol_band_rule_default(&in->rule);
}

double shol_band_window_frac(int converged, int averaged, double mean_drift, double mean_change)
{
    if (converged)
        return 0.0;
    if (averaged > 0 && isfinite(mean_drift) && mean_drift >= 0)
        return fmax(mean_drift, isfinite(mean_change) && mean_change >= 0 ? mean_change : 0.0);
    return NAN;
}

shol_band_rule shol_band_rule_of(const shol_result *r)
{
    shol_band_rule k = r->band_rule;
    if (!(k.width_mps > 0) || !(k.frac > 0))
        shol_band_rule_default(&k);
    return k;
}

const char *shol_band_source_name(int src)
{
    switch (src) {
    case SHOL_BAND_GRID:
        return "grid";
    case SHOL_BAND_WINDOW:
        return "window";
    case SHOL_BAND_SENS:
        return "sensitivity";
    case SHOL_BAND_MODEL:
        return "model";
    default:
        return "-";
    }
}

static const shol_dir_result *find_dir(const shol_result *c, double dir_rad)
{
    for (int i = 0; c && i < c->n_dirs; i++)
        if (fabs(c->dirs[i].dir_rad - dir_rad) < 1e-6)
            return &c->dirs[i];
    return NULL;
}

void shol_model_error_none(shol_model_error *m)
{
    memset(m, 0, sizeof *m);
    for (int c = 0; c < SHOL_NCRIT; c++)
        m->err[c] = NAN;
}

double shol_band_model_shift(const shol_dir_result *d, const shol_model_error *m, int *crit_out, double *err_out)
{
    const int crit = d->limit >= SHOL_CRIT_ROLL && d->limit < SHOL_NCRIT ? d->limit : -1;
    const double e = crit >= 0 && m && m->valid ? m->err[crit] : NAN;
    if (crit_out)
        *crit_out = crit;
    if (err_out)
        *err_out = e;
    shol_sensitivity se;
    if (!isfinite(e) || shol_envelope_sensitivity(d, &se) != 0)
        return NAN;
    return se.side * e / se.slope_per_mps;
}

/* The model source of a band: the shift, the quantity, its error and
 * where it was measured. */
typedef struct model_src {
    double mps;
    int crit;
    double err;
    const char *ref;
} model_src;

/* The band of d from its four sources (NAN: absent), under rule k. */
static void band_make(const shol_dir_result *d, double grid_mps, double window_frac, double sens_mps,
                      const model_src *ms, const shol_band_rule *k, shol_band *b)
{
    memset(b, 0, sizeof *b);
    const double v = d->has_pass ? d->max_speed_mps : 0.0;
    /* a second grid's radius read from a CSV (kt to 6 decimals) can miss
     * this one's by 1e-7 m/s: that is the same limit, not a spread */
    if (fabs(grid_mps) < 1e-4)
        grid_mps = 0.0;
    const double window_mps = window_frac * v; /* NAN stays NAN */
    b->valid = 1;
    b->grid_mps = grid_mps;
    b->window_mps = window_mps;
    b->window_frac = window_frac;
    b->sens_mps = sens_mps;
    b->model_mps = ms->mps;
    b->model_crit = ms->crit;
    b->model_err = ms->err;
    snprintf(b->model_ref, sizeof b->model_ref, "%s", ms->ref ? ms->ref : "");
    /* each source's reach below and above v */
    double below[SHOL_NBAND] = {0}, above[SHOL_NBAND] = {0};
    if (isfinite(grid_mps)) {
        below[SHOL_BAND_GRID] = fmax(0.0, -grid_mps);
        above[SHOL_BAND_GRID] = fmax(0.0, grid_mps);
    }
    if (isfinite(window_mps))
        below[SHOL_BAND_WINDOW] = above[SHOL_BAND_WINDOW] = window_mps;
    if (isfinite(sens_mps))
        below[SHOL_BAND_SENS] = above[SHOL_BAND_SENS] = sens_mps;
    if (isfinite(ms->mps)) {
        below[SHOL_BAND_MODEL] = fmax(0.0, -ms->mps);
        above[SHOL_BAND_MODEL] = fmax(0.0, ms->mps);
    }
    b->open_above = d->limit == SHOL_LIMIT_NONE;
    double lo = v, hi = v, reach = 0.0;
    b->widest = -1;
    for (int s = 0; s < SHOL_NBAND; s++) {
        double lo_s = fmax(0.0, v - below[s]), hi_s = b->open_above ? v : v + above[s];
        lo = fmin(lo, lo_s);
        hi = fmax(hi, hi_s);
        double r = fmax(v - lo_s, hi_s - v);
        if (r > reach + 1e-12) {
            reach = r;
            b->widest = s;
        }
    }
    b->lo_mps = lo;
    b->hi_mps = hi;
    b->low_confidence = hi - lo > fmax(k->width_mps, k->frac * v) + 1e-9;
}

static double sens_of(const shol_dir_result *d)
{
    shol_sensitivity se;
    return shol_envelope_sensitivity(d, &se) == 0 ? se.shift_mps : NAN;
}

/* d's model source under m (NULL: not validated). */
static model_src model_of(const shol_dir_result *d, const shol_model_error *m)
{
    model_src ms = {NAN, -1, NAN, NULL};
    ms.mps = shol_band_model_shift(d, m, &ms.crit, &ms.err);
    ms.ref = m && m->valid ? m->reference : NULL;
    return ms;
}

int shol_band_compute(shol_result *r, const shol_band_inputs *in, core_err *err)
{
    shol_band_inputs none;
    if (!in) {
        shol_band_inputs_default(&none);
        in = &none;
    }
    const shol_band_rule *k = &in->rule;
    if (!(k->width_mps > 0 && isfinite(k->width_mps)) || !(k->frac > 0 && isfinite(k->frac)))
        return core_err_set(err, -1, "shol: band rule: width %g km/h, fraction %g: expected both finite and > 0",
                            k->width_mps / CORE_KMH_TO_MPS, k->frac);
    if (in->n_window < 0 || in->n_window > SHOL_MAX_DIRS)
        return core_err_set(err, -1, "shol: band: %d window spreads: expected 0 to %d", in->n_window, SHOL_MAX_DIRS);
    for (int j = 0; j < in->n_window; j++) {
        char name[32];
        core_wod_name(in->window_dir_rad[j] * CORE_RAD_TO_DEG, name, sizeof name);
        double s = in->window_frac[j];
        if (!isfinite(in->window_dir_rad[j]))
            return core_err_set(err, -1, "shol: band: window spread %d: direction %g: expected a finite angle", j,
                                in->window_dir_rad[j]);
        if (!isnan(s) && !(s >= 0 && isfinite(s)))
            return core_err_set(err, -1,
                                "shol: band: %s: window spread %g: expected >= 0 and finite (NAN: not known)", name,
                                s);
    }
    const shol_model_error *me = &in->model;
    for (int c = 0; me->valid && c < SHOL_NCRIT; c++)
        if (isinf(me->err[c]))
            return core_err_set(err, -1, "shol: band: model error in %s %g: expected finite (NAN: not validated)",
                                shol_limit_name(c), me->err[c]);
    if (in->grid_base && !in->grid)
        return core_err_set(err, -1, "shol: band: a grid base without a second grid");
    for (int w = 0; w < 2; w++) {
        const shol_result *gr = w ? in->grid_base : in->grid;
        for (int i = 0; gr && i < gr->n_dirs; i++) {
            const shol_dir_result *g = &gr->dirs[i];
            char name[32];
            core_wod_name(g->dir_rad * CORE_RAD_TO_DEG, name, sizeof name);
            if (g->has_pass && !(isfinite(g->max_speed_mps) && g->max_speed_mps >= 0))
                return core_err_set(err, -1, "shol: band: %s %s%s: radius %g m/s: expected finite and >= 0", name,
                                    in->grid_label ? in->grid_label : "second grid", w ? " (its base)" : "",
                                    g->max_speed_mps);
        }
    }
    for (int i = 0; i < r->n_dirs; i++) {
        shol_dir_result *d = &r->dirs[i];
        double grid = NAN, win = NAN; /* win: s */
        const shol_dir_result *g = find_dir(in->grid, d->dir_rad);
        const shol_dir_result *gb = in->grid_base ? find_dir(in->grid_base, d->dir_rad) : d;
        if (g && gb)
            grid = (g->has_pass ? g->max_speed_mps : 0.0) - (gb->has_pass ? gb->max_speed_mps : 0.0);
        for (int j = 0; j < in->n_window; j++)
            if (fabs(in->window_dir_rad[j] - d->dir_rad) < 1e-6 && !isnan(in->window_frac[j]))
                win = in->window_frac[j];
        const model_src ms = model_of(d, me);
        band_make(d, grid, win, sens_of(d), &ms, k, &d->band);
    }
    r->band_rule = *k;
    snprintf(r->band_grid_label, sizeof r->band_grid_label, "%s", in->grid && in->grid_label ? in->grid_label : in->grid ? "second grid" : "");
    snprintf(r->band_model_label, sizeof r->band_model_label, "%s", me->valid ? me->reference : "");
    return 0;
}

void shol_band_get(const shol_result *r, int i, shol_band *out)
{
    const shol_dir_result *d = &r->dirs[i];
    if (d->band.valid) {
        *out = d->band;
        return;
    }
    shol_band_rule k = shol_band_rule_of(r);
    const model_src ms = model_of(d, NULL);
    band_make(d, NAN, NAN, sens_of(d), &ms, &k, out);
}

void shol_band_format(const shol_band *b, const char *grid_label, int limit, char *buf, size_t n)
{
    const char *sens_unit = limit == SHOL_CRIT_ROLL || limit == SHOL_CRIT_PITCH ? "0.25 deg"
                            : limit >= SHOL_CRIT_LONG && limit < SHOL_NCRIT    ? "1 %"
                                                                                : "sensitivity";
    const double K = CORE_KMH_TO_MPS;
    size_t u = 0;
    buf[0] = '\0';
#define ADD(...)                                                                                                       \
    do {                                                                                                               \
        if (u < n) {                                                                                                   \
            int w_ = snprintf(buf + u, n - u, __VA_ARGS__);                                                            \
            u += w_ > 0 ? (size_t)w_ : 0;                                                                              \
        }                                                                                                              \
    } while (0)
    if (isfinite(b->grid_mps))
        ADD("grid %+.1f (%s)", b->grid_mps / K, grid_label && *grid_label ? grid_label : "second grid");
    else
        ADD("grid: no second grid");
    if (isfinite(b->window_mps))
        ADD(", window +-%.1f", b->window_mps / K);
    else
        ADD(", window: not known");
    if (isfinite(b->sens_mps))
        ADD(", %s +-%.1f", sens_unit, b->sens_mps / K);
    else
        ADD(", sensitivity: not defined");
    char mt[128];
    shol_band_model_text(b, mt, sizeof mt);
    if (isfinite(b->model_mps))
        ADD(", model %+.1f%s%s%s", b->model_mps / K, mt[0] ? " (" : "", mt, mt[0] ? ")" : "");
    else if (b->model_crit >= 0 && isnan(b->model_err))
        ADD(", model: not validated");
    else
        ADD(", model: not defined");
#undef ADD
}

void shol_band_model_text(const shol_band *b, char *buf, size_t n)
{
    buf[0] = '\0';
    if (b->model_crit < 0 || b->model_crit >= SHOL_NCRIT || !isfinite(b->model_err))
        return;
    const int ang = b->model_crit <= SHOL_CRIT_PITCH;
    snprintf(buf, n, "%s %+.2f %s%s%s", shol_limit_name(b->model_crit), b->model_err * (ang ? CORE_RAD_TO_DEG : 1.0), ang ? "deg" : "%", b->model_ref[0] ? " vs " : "",
             b->model_ref);
}

void shol_band_dominant(const shol_band *b, char *buf, size_t n)
{
    char mt[128];
    shol_band_model_text(b, mt, sizeof mt);
    if (b->widest == SHOL_BAND_MODEL && mt[0])
        snprintf(buf, n, "model (%s)", mt);
    else
        snprintf(buf, n, "%s", shol_band_source_name(b->widest));
}

void shol_flown_band(const shol_flown_result *f, const shol_result *trim, int i, shol_band *out)
{
    const shol_flown_dir *fd = &f->dirs[i];
    /* the flown direction as a dir_result: its radius, and "none" where
     * nothing failed (the band is then open above) */
    shol_dir_result d;
    memset(&d, 0, sizeof d);
    d.dir_rad = fd->dir_rad;
    d.has_pass = fd->has_pass;
    d.max_speed_mps = fd->max_speed_mps;
    d.limit = isnan(fd->fail_speed_mps) ? SHOL_LIMIT_NONE : SHOL_LIMIT_TRIM;
    double grid = NAN, win = NAN, sens = NAN;
    /* the model's error moves the flown limit as it moves the trim's: the
     * same quantity limits both where the flights fail on a criterion, and
     * the trim's slope is the only one measured */
    model_src ms = {NAN, -1, NAN, NULL};
    shol_band tb;
    for (int j = 0; trim && j < trim->n_dirs; j++) {
        if (fabs(trim->dirs[j].dir_rad - fd->dir_rad) >= 1e-6)
            continue;
        shol_band_get(trim, j, &tb);
        grid = tb.grid_mps;
        win = tb.window_frac;
        sens = tb.sens_mps;
        ms.mps = tb.model_mps;
        ms.crit = tb.model_crit;
        ms.err = tb.model_err;
        ms.ref = tb.model_ref;
        break;
    }
    shol_band_rule k;
    if (trim)
        k = shol_band_rule_of(trim);
    else
        shol_band_rule_default(&k);
    band_make(&d, grid, win, sens, &ms, &k, out);
}

void shol_flown_bands_update(shol_flown_result *f, const shol_result *trim)
{
    for (int i = 0; i < f->n_dirs; i++)
        shol_flown_band(f, trim, i, &f->dirs[i].band);
}
