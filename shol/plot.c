/*
 * plot.c -- the envelope drawn with cairo: the NATOPS-style polar plot
 * (PNG and SVG) and the trim-versus-speed plots per direction (PNG), like
 * the seed paper's Figs. 16-22.
 *
 * Polar plot habit (docs/conventions.md, NATOPS launch/recovery envelopes): the
 * bow up, starboard to the right, relative wind direction as the angle
 * (where the wind comes from), WOD speed in knots as the radius, one closed
 * line. Directions that were not swept count as not cleared: when the swept
 * directions leave a gap wider than 90 deg, the line closes through the
 * centre across that gap.
 * The drawing uses cairo paths and the toy text API (DejaVu Sans via
 * fontconfig); nothing is drawn pixel by pixel.
 */
#include "io.h"
#include "plot.h"
#include "shol.h"

#include <cairo-svg.h>
#include <cairo.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define FONT SHOL_PLOT_FONT

typedef struct rgb {
    double r, g, b;
} rgb;

/* One colour and marker per limit (index limit + 1: none, roll, ..., trim),
 * chosen to stay apart for colour-blind readers and in grey print. */
static const rgb limit_col[8] = {
    {0.45, 0.45, 0.45}, /* none */
    {0.84, 0.15, 0.16}, /* roll */
    {0.90, 0.45, 0.00}, /* pitch */
    {0.55, 0.34, 0.75}, /* long cyclic */
    {0.55, 0.34, 0.29}, /* lat cyclic */
    {0.80, 0.30, 0.65}, /* collective */
    {0.12, 0.47, 0.71}, /* pedal */
    {0.00, 0.00, 0.00}, /* trim */
};
static const char *const limit_label[8] = {
    "none up to max speed", "roll",       "pitch", "longitudinal cyclic",
    "lateral cyclic",       "collective", "pedal", "trim not converged"};
static const char *const short_label[8] = {"none",       "roll",       "pitch", "long cyclic",
                                           "lat cyclic", "collective", "pedal", "no trim"};
static const rgb ink = {0.10, 0.10, 0.10};
static const rgb env_col = {0.05, 0.45, 0.20};
static const rgb cmp_col = {0.15, 0.35, 0.85};
static const rgb grid_col = {0.80, 0.80, 0.80};
static const rgb reject_fill = {0.98, 0.88, 0.88};
static const rgb band_col = {0.93, 0.62, 0.10};  /* the bands' amber */
static const rgb low_col = {0.80, 0.05, 0.10};   /* a low-confidence band */

static void set_col(cairo_t *cr, rgb c)
{
    cairo_set_source_rgb(cr, c.r, c.g, c.b);
}

/* Text s at (x, y): ha -1 left, 0 centre, 1 right; va -1 top, 0 middle,
 * 1 baseline. Returns its advance width (legends lay their entries out
 * with it). */
static double text(cairo_t *cr, double x, double y, double size, int bold, int ha, int va,
                   const char *s)
{
    cairo_select_font_face(cr, FONT, CAIRO_FONT_SLANT_NORMAL,
                           bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, size);
    cairo_text_extents_t te;
    cairo_text_extents(cr, s, &te);
    double dx = ha < 0    ? -te.x_bearing
                : ha == 0 ? -(te.x_bearing + te.width / 2)
                          : -(te.x_bearing + te.width);
    double dy = va < 0 ? -te.y_bearing : va == 0 ? -(te.y_bearing + te.height / 2) : 0;
    cairo_move_to(cr, x + dx, y + dy);
    cairo_show_text(cr, s);
    return te.x_advance;
}

/* plot.h: size, or less so that s fits in width (normal weight). */
double shol_plot_fit_size(cairo_t *cr, const char *s, double size, double width)
{
    cairo_select_font_face(cr, FONT, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, size);
    cairo_text_extents_t te;
    cairo_text_extents(cr, s, &te);
    return te.width > width ? size * width / te.width : size;
}

/* A legend entry whose symbol takes lead points before label: when it
 * would pass the right margin, the row starts again at the left, above. */
static void legend_wrap(cairo_t *cr, const char *label, double lead, double W, double *lx, double *ly)
{
    cairo_text_extents_t te;
    cairo_text_extents(cr, label, &te);
    if (*lx + lead + te.x_advance > W - 20) {
        *ly -= 22;
        *lx = 40;
    }
}

/* Same, on a white box so it stays readable over lines. */
static void text_boxed(cairo_t *cr, double x, double y, double size, int bold, int ha, int va,
                       const char *s, rgb col)
{
    cairo_select_font_face(cr, FONT, CAIRO_FONT_SLANT_NORMAL,
                           bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, size);
    cairo_text_extents_t te;
    cairo_text_extents(cr, s, &te);
    double x0 = ha < 0 ? x : ha == 0 ? x - te.width / 2 : x - te.width;
    double y0 = va < 0 ? y : va == 0 ? y - te.height / 2 : y - te.height;
    cairo_set_source_rgba(cr, 1, 1, 1, 0.85);
    cairo_rectangle(cr, x0 - 3, y0 - 2, te.width + 6, te.height + 4);
    cairo_fill(cr);
    set_col(cr, col);
    text(cr, x, y, size, bold, ha, va, s);
}

/* A marker of the limit's shape, filled in its colour with a dark edge. */
static void marker(cairo_t *cr, int limit, double x, double y, double s)
{
    int k = limit + 1;
    cairo_new_path(cr);
    switch (limit) {
    case SHOL_CRIT_ROLL:
        cairo_arc(cr, x, y, s, 0, 2 * CORE_PI);
        break;
    case SHOL_CRIT_PITCH:
        cairo_rectangle(cr, x - s * 0.9, y - s * 0.9, 1.8 * s, 1.8 * s);
        break;
    case SHOL_CRIT_LONG:
        cairo_move_to(cr, x, y - 1.2 * s);
        cairo_line_to(cr, x + 1.1 * s, y + 0.8 * s);
        cairo_line_to(cr, x - 1.1 * s, y + 0.8 * s);
        cairo_close_path(cr);
        break;
    case SHOL_CRIT_LAT:
        cairo_move_to(cr, x, y + 1.2 * s);
        cairo_line_to(cr, x + 1.1 * s, y - 0.8 * s);
        cairo_line_to(cr, x - 1.1 * s, y - 0.8 * s);
        cairo_close_path(cr);
        break;
    case SHOL_CRIT_COLL:
        cairo_move_to(cr, x, y - 1.3 * s);
        cairo_line_to(cr, x + 1.3 * s, y);
        cairo_line_to(cr, x, y + 1.3 * s);
        cairo_line_to(cr, x - 1.3 * s, y);
        cairo_close_path(cr);
        break;
    case SHOL_CRIT_PEDAL:
        for (int i = 0; i < 10; i++) {
            double a = -CORE_PI / 2 + i * CORE_PI / 5, rr = i % 2 ? 0.6 * s : 1.4 * s;
            if (i == 0)
                cairo_move_to(cr, x + rr * cos(a), y + rr * sin(a));
            else
                cairo_line_to(cr, x + rr * cos(a), y + rr * sin(a));
        }
        cairo_close_path(cr);
        break;
    case SHOL_LIMIT_TRIM:
        cairo_set_line_width(cr, 0.5 * s);
        set_col(cr, limit_col[k]);
        cairo_move_to(cr, x - s, y - s);
        cairo_line_to(cr, x + s, y + s);
        cairo_move_to(cr, x - s, y + s);
        cairo_line_to(cr, x + s, y - s);
        cairo_stroke(cr);
        return;
    default: /* none: an open circle */
        cairo_set_line_width(cr, 0.35 * s);
        set_col(cr, limit_col[0]);
        cairo_arc(cr, x, y, s, 0, 2 * CORE_PI);
        cairo_stroke(cr);
        return;
    }
    set_col(cr, limit_col[k]);
    cairo_fill_preserve(cr);
    cairo_set_line_width(cr, 1.2);
    set_col(cr, ink);
    cairo_stroke(cr);
}

/* A round tick spacing (1, 2, 2.5, 5 x 10^k) giving about n ticks. */
static double nice_step(double span, int n)
{
    if (!(span > 0))
        return 1;
    double raw = span / n, p = pow(10, floor(log10(raw))), m = raw / p;
    double f = m <= 1 ? 1 : m <= 2 ? 2 : m <= 2.5 ? 2.5 : m <= 5 ? 5 : 10;
    return f * p;
}

static void fmt_num(char *buf, size_t n, double v)
{
    if (fabs(v) < 1e-9)
        v = 0;
    snprintf(buf, n, "%g", v);
}

static int limit_index(int limit)
{
    return limit < SHOL_LIMIT_NONE || limit > SHOL_LIMIT_TRIM ? 0 : limit + 1;
}

/* ------------------------------------------------------------- polar */
typedef struct polar {
    double cx, cy, R, rmax_kt;
} polar;

static void polar_xy(const polar *p, double dir_rad, double kt, double *x, double *y)
{
    double r = p->R * kt / p->rmax_kt;
    *x = p->cx + r * sin(dir_rad); /* starboard to the right */
    *y = p->cy - r * cos(dir_rad); /* bow up */
}

static int by_angle(const void *a, const void *b)
{
    double x = (*(const shol_dir_result *const *)a)->dir_rad;
    double y = (*(const shol_dir_result *const *)b)->dir_rad;
    return (x > y) - (x < y);
}

/* Directions sorted by angle; *open_after = index after which the largest
 * gap (> 90 deg) lies, or -1 if the directions go round the circle. */
static const shol_dir_result **sorted_dirs(const shol_result *r, int *open_after, double *gap_mid)
{
    const shol_dir_result **v = malloc((r->n_dirs ? r->n_dirs : 1) * sizeof *v);
    if (!v)
        return NULL;
    for (int i = 0; i < r->n_dirs; i++)
        v[i] = &r->dirs[i];
    qsort(v, r->n_dirs, sizeof *v, by_angle);
    if (r->n_dirs == 0) {
        /* An empty envelope (e.g. a header-only shol.csv): no line to close,
         * ring labels toward the stern; v[0] below would be uninitialised. */
        *open_after = -1;
        *gap_mid = CORE_PI;
        return v;
    }
    double gmax = -1;
    int imax = 0;
    for (int i = 0; i < r->n_dirs; i++) {
        double a = v[i]->dir_rad, b = v[(i + 1) % r->n_dirs]->dir_rad;
        double g = b - a;
        if (g <= 0)
            g += 2 * CORE_PI;
        if (g > gmax + 1e-9) {
            gmax = g;
            imax = i;
        }
    }
    *open_after = gmax > CORE_PI / 2 + 1e-9 ? imax : -1;
    *gap_mid = v[imax]->dir_rad + gmax / 2;
    if (*open_after < 0) {
        /* Round the circle: ring labels in the gap nearest the stern,
         * between two directions so they do not sit on a point. */
        double best = INFINITY;
        for (int i = 0; i < r->n_dirs; i++) {
            double a = v[i]->dir_rad, g = v[(i + 1) % r->n_dirs]->dir_rad - a;
            if (g <= 0)
                g += 2 * CORE_PI;
            double mid = a + g / 2;
            double off = fabs(fabs(core_wod_wrap_deg(mid * CORE_RAD_TO_DEG)) - 180);
            if (off < best - 1e-9) {
                best = off;
                *gap_mid = mid;
            }
        }
    }
    return v;
}

static double dir_kt(const shol_dir_result *d)
{
    return d->has_pass ? d->max_speed_mps / CORE_KT_TO_MPS : 0;
}

/* The closed envelope line; fill then stroke. */
static void polar_envelope(cairo_t *cr, const polar *p, const shol_result *r, rgb col, int dashed,
                           int fill)
{
    int open_after;
    double gm;
    const shol_dir_result **v = sorted_dirs(r, &open_after, &gm);
    if (!v || r->n_dirs == 0) {
        free(v);
        return;
    }
    cairo_new_path(cr);
    int n = r->n_dirs, start = open_after < 0 ? 0 : (open_after + 1) % n;
    if (open_after >= 0)
        cairo_move_to(cr, p->cx, p->cy);
    for (int k = 0; k < n; k++) {
        const shol_dir_result *d = v[(start + k) % n];
        double x, y;
        polar_xy(p, d->dir_rad, dir_kt(d), &x, &y);
        if (k == 0 && open_after < 0)
            cairo_move_to(cr, x, y);
        else
            cairo_line_to(cr, x, y);
    }
    cairo_close_path(cr);
    if (fill) {
        cairo_set_source_rgba(cr, col.r, col.g, col.b, 0.13);
        cairo_fill_preserve(cr);
    }
    set_col(cr, col);
    cairo_set_line_width(cr, dashed ? 2.5 : 3.5);
    cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
    if (dashed) {
        double dash[] = {10, 6};
        cairo_set_dash(cr, dash, 2, 0);
    }
    cairo_stroke(cr);
    cairo_set_dash(cr, NULL, 0, 0);
    free(v);
}

/* The bands (shol_band_get): the region between every direction's lower
 * and upper ends, shaded under the envelope's line (whiskers 0), or a
 * whisker from lo to hi at each direction over it (whiskers 1), red where
 * the band is of low confidence. The
 * region follows the envelope's own closing: round the circle, or, with a
 * sector not swept, from the first direction to the last. */
static void polar_bands(cairo_t *cr, const polar *p, const shol_result *r, int whiskers)
{
    int open_after;
    double gm;
    const shol_dir_result **v = sorted_dirs(r, &open_after, &gm);
    shol_band *b = calloc(r->n_dirs ? r->n_dirs : 1, sizeof *b);
    if (!v || !b || r->n_dirs == 0) {
        free(v);
        free(b);
        return;
    }
    const int n = r->n_dirs, start = open_after < 0 ? 0 : (open_after + 1) % n;
    for (int k = 0; k < n; k++)
        shol_band_get(r, (int)(v[(start + k) % n] - r->dirs), &b[k]);
    double x, y;
    cairo_new_path(cr);
    for (int k = 0; k < n && !whiskers; k++) {
        polar_xy(p, v[(start + k) % n]->dir_rad, b[k].hi_mps / CORE_KT_TO_MPS, &x, &y);
        if (k == 0)
            cairo_move_to(cr, x, y);
        else
            cairo_line_to(cr, x, y);
    }
    if (whiskers)
        ;
    else if (open_after < 0) { /* an annulus: the inner line as its own loop */
        cairo_close_path(cr);
        for (int k = n - 1; k >= 0; k--) {
            polar_xy(p, v[(start + k) % n]->dir_rad, b[k].lo_mps / CORE_KT_TO_MPS, &x, &y);
            if (k == n - 1)
                cairo_move_to(cr, x, y);
            else
                cairo_line_to(cr, x, y);
        }
    } else {
        for (int k = n - 1; k >= 0; k--) {
            polar_xy(p, v[(start + k) % n]->dir_rad, b[k].lo_mps / CORE_KT_TO_MPS, &x, &y);
            cairo_line_to(cr, x, y);
        }
    }
    if (!whiskers) {
        cairo_close_path(cr);
        cairo_set_fill_rule(cr, CAIRO_FILL_RULE_EVEN_ODD);
        cairo_set_source_rgba(cr, band_col.r, band_col.g, band_col.b, 0.38);
        cairo_fill(cr);
        cairo_set_fill_rule(cr, CAIRO_FILL_RULE_WINDING);
    }
    /* whiskers with caps across the direction, over the envelope's line */
    for (int k = 0; k < n && whiskers; k++) {
        const double a = v[(start + k) % n]->dir_rad, cap = 6.0;
        double x0, y0, x1, y1;
        polar_xy(p, a, b[k].lo_mps / CORE_KT_TO_MPS, &x0, &y0);
        polar_xy(p, a, b[k].hi_mps / CORE_KT_TO_MPS, &x1, &y1);
        const double tx = cos(a) * cap, ty = sin(a) * cap; /* across the spoke */
        set_col(cr, b[k].low_confidence ? low_col : (rgb){0.55, 0.35, 0.02});
        cairo_set_line_width(cr, b[k].low_confidence ? 3.0 : 2.0);
        cairo_new_path(cr);
        cairo_move_to(cr, x0, y0);
        cairo_line_to(cr, x1, y1);
        cairo_move_to(cr, x0 - tx, y0 - ty);
        cairo_line_to(cr, x0 + tx, y0 + ty);
        if (!b[k].open_above) {
            cairo_move_to(cr, x1 - tx, y1 - ty);
            cairo_line_to(cr, x1 + tx, y1 + ty);
        }
        cairo_stroke(cr);
    }
    free(v);
    free(b);
}

/* The scale: rings every *step kt (at least 5), the outer ring above the
 * highest envelope speed of r and of the comparison c with room for the
 * labels; the centre and radius on a W-wide page. */
static polar polar_scale(const shol_result *r, const shol_result *c, double W, double *step_kt)
{
    double top_kt = 0;
    for (int i = 0; i < r->n_dirs; i++) {
        shol_band b;
        shol_band_get(r, i, &b);
        top_kt = fmax(top_kt, fmax(dir_kt(&r->dirs[i]), b.hi_mps / CORE_KT_TO_MPS));
    }
    for (int i = 0; c && i < c->n_dirs; i++)
        top_kt = fmax(top_kt, dir_kt(&c->dirs[i]));
    double step = top_kt > 0 ? nice_step(top_kt, 6) : 10;
    if (step < 5)
        step = 5;
    polar p = {W / 2, 110 + 0.40 * W, 0.36 * W, 0};
    p.rmax_kt = fmax(step, ceil(top_kt / step - 1e-9) * step);
    if (p.rmax_kt - top_kt < 0.15 * p.rmax_kt) /* room for the labels */
        p.rmax_kt += step;
    *step_kt = step;
    return p;
}

/* The title and, under it, the rejection criteria. */
static void polar_title(cairo_t *cr, double W, const shol_result *r, const shol_report_info *info)
{
    char buf[256];
    set_col(cr, ink);
    snprintf(buf, sizeof buf, "Candidate SHOL: %s",
             info && info->title ? info->title : "trim-based envelope");
    text(cr, W / 2, 34, 24, 1, 0, 0, buf);
    const shol_criteria *k = &r->settings.criteria;
    snprintf(buf, sizeof buf,
             "hover over the spot; rejected when |roll| > %g deg, |pitch| > %g deg, controls "
             "beyond %g/%g/%g/%g %% (long/lat/coll/pedal)",
             k->roll_max_rad * CORE_RAD_TO_DEG, k->pitch_max_rad * CORE_RAD_TO_DEG,
             k->long_cyclic_pct, k->lat_cyclic_pct, k->collective_pct, k->pedal_pct);
    text(cr, W / 2, 62, 13, 0, 0, 0, buf);
}

/* The axes: speed rings, spokes every 30 deg with the direction names at
 * the rim, the sides, and the ship in the centre. */
static void polar_grid(cairo_t *cr, const polar *p, double step)
{
    char buf[32];
    cairo_set_line_width(cr, 1.0);
    for (double s = step; s <= p->rmax_kt + 1e-9; s += step) {
        set_col(cr, grid_col);
        cairo_new_path(cr);
        cairo_arc(cr, p->cx, p->cy, p->R * s / p->rmax_kt, 0, 2 * CORE_PI);
        cairo_stroke(cr);
    }
    for (int a = -150; a <= 180; a += 30) {
        double x, y;
        polar_xy(p, a * CORE_DEG_TO_RAD, p->rmax_kt, &x, &y);
        set_col(cr, grid_col);
        cairo_move_to(cr, p->cx, p->cy);
        cairo_line_to(cr, x, y);
        cairo_stroke(cr);
        polar_xy(p, a * CORE_DEG_TO_RAD, p->rmax_kt * 1.075, &x, &y);
        set_col(cr, ink);
        if (a == 0)
            snprintf(buf, sizeof buf, "BOW 0");
        else if (a == 180)
            snprintf(buf, sizeof buf, "STERN 180");
        else
            snprintf(buf, sizeof buf, "%s %d", a > 0 ? "G" : "R", abs(a));
        text(cr, x, y, 15, a == 0 || abs(a) == 90, 0, 0, buf);
    }
    text(cr, p->cx + p->R * 1.075, p->cy + 20, 12, 0, 0, 0, "starboard");
    text(cr, p->cx - p->R * 1.075, p->cy + 20, 12, 0, 0, 0, "port");

    /* The ship, bow up, to scale with nothing: a reminder of the sense. */
    double L = 0.10 * p->R, B = 0.028 * p->R;
    cairo_new_path(cr);
    cairo_move_to(cr, p->cx, p->cy - L);
    cairo_curve_to(cr, p->cx + B, p->cy - 0.6 * L, p->cx + B, p->cy - 0.3 * L, p->cx + B, p->cy);
    cairo_line_to(cr, p->cx + B, p->cy + 0.8 * L);
    cairo_line_to(cr, p->cx - B, p->cy + 0.8 * L);
    cairo_line_to(cr, p->cx - B, p->cy);
    cairo_curve_to(cr, p->cx - B, p->cy - 0.3 * L, p->cx - B, p->cy - 0.6 * L, p->cx, p->cy - L);
    cairo_set_source_rgb(cr, 0.55, 0.55, 0.6);
    cairo_fill(cr);
}

/* Ring labels along label_dir (the widest unswept sector), on white boxes. */
static void polar_ring_labels(cairo_t *cr, const polar *p, double step, double label_dir)
{
    char buf[32];
    for (double s = step; s <= p->rmax_kt + 1e-9; s += step) {
        double x, y;
        polar_xy(p, label_dir, s, &x, &y);
        snprintf(buf, sizeof buf, "%g kt", s);
        text_boxed(cr, x, y, 13, 0, 0, 0, buf, ink);
    }
}

/* Each direction's limiting criterion: a marker on the line, then "NN kt
 * limit" beside it. Labels go outside the line if they stay clear of the
 * direction names at the rim, else inside; one that would cover an earlier
 * label moves further out (or in) by a label offset at a time. */
static void polar_limits(cairo_t *cr, const polar *p, const shol_result *r)
{
    char buf[256];
    for (int i = 0; i < r->n_dirs; i++) {
        double x, y;
        polar_xy(p, r->dirs[i].dir_rad, dir_kt(&r->dirs[i]), &x, &y);
        marker(cr, r->dirs[i].limit, x, y, 7);
    }
    double (*box)[4] = calloc(r->n_dirs ? r->n_dirs : 1, sizeof *box);
    int nbox = 0;
    for (int i = 0; box && i < r->n_dirs; i++) {
        const shol_dir_result *d = &r->dirs[i];
        if (!d->has_pass)
            continue; /* listed under the title: labels at the centre would pile up */
        double kt = dir_kt(d), off = 0.09 * p->rmax_kt, sx = sin(d->dir_rad), cx_ = cos(d->dir_rad);
        int ha0 = sx > 0.25 ? -1 : sx < -0.25 ? 1 : 0;
        shol_band bd;
        shol_band_get(r, i, &bd);
        if (bd.open_above)
            snprintf(buf, sizeof buf, "%.1f kt %s (from %.0f)%s", kt, short_label[limit_index(d->limit)],
                     bd.lo_mps / CORE_KT_TO_MPS, bd.low_confidence ? " LOW" : "");
        else
            snprintf(buf, sizeof buf, "%.1f kt %s (%.0f-%.0f)%s", kt, short_label[limit_index(d->limit)],
                     bd.lo_mps / CORE_KT_TO_MPS, bd.hi_mps / CORE_KT_TO_MPS, bd.low_confidence ? " LOW" : "");
        /* outside the band's whisker, not on it: from its ends */
        const double hi_kt = bd.hi_mps / CORE_KT_TO_MPS, lo_kt = bd.lo_mps / CORE_KT_TO_MPS;
        cairo_text_extents_t te;
        cairo_select_font_face(cr, FONT, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_BOLD);
        cairo_set_font_size(cr, 13);
        cairo_text_extents(cr, buf, &te);
        /* candidates: out past the band (1-3 offsets), then out from the
         * point but beside the spoke (clear of the whisker; above it, then
         * below), then in below
         * the band */
        static const struct {
            double step;
            int shift;
        } cand[] = {{1, 0}, {2, 0}, {3, 0}, {1, 1},  {2, 1},  {3, 1},
                    {1, -1}, {2, -1}, {3, -1}, {-1, 0}, {-2, 0}, {-3, 0}};
        /* across the spoke on the page, pointing up (or right) */
        double nx = cos(d->dir_rad), ny = sin(d->dir_rad);
        if (ny > 1e-9 || (fabs(ny) <= 1e-9 && nx < 0))
            nx = -nx, ny = -ny;
        const double sh = 0.5 * te.height + 9;
        double best[4] = {0}, lx = 0, ly = 0;
        int ha = ha0, found = 0, have = 0; /* have: a candidate inside the rim */
        for (int k = 0; k < (int)(sizeof cand / sizeof cand[0]) && !found; k++) {
            double o = cand[k].step * off, rkt = (cand[k].shift ? kt : o > 0 ? hi_kt : lo_kt) + o;
            int h = o > 0 ? ha0 : -ha0;
            double reach = p->R * rkt / p->rmax_kt + (h ? te.width : 0.5 * te.width) * fabs(sx) +
                           0.5 * te.height * fabs(cx_) + (cand[k].shift ? sh : 0);
            if (o > 0 && reach > 0.97 * p->R)
                continue; /* would reach the direction names */
            if (rkt < 0.0)
                break;
            double tx, ty;
            polar_xy(p, d->dir_rad, rkt, &tx, &ty);
            if (cand[k].shift)
                tx += cand[k].shift * sh * nx, ty += cand[k].shift * sh * ny;
            double b0[4] = {h < 0 ? tx : h == 0 ? tx - te.width / 2 : tx - te.width, ty - te.height / 2, 0, 0};
            b0[2] = b0[0] + te.width;
            b0[3] = b0[1] + te.height;
            int clear = 1;
            for (int j = 0; j < nbox && clear; j++)
                clear = b0[2] + 4 < box[j][0] || box[j][2] + 4 < b0[0] || b0[3] + 3 < box[j][1] ||
                        box[j][3] + 3 < b0[1];
            if (clear || !have) {
                memcpy(best, b0, sizeof best);
                lx = tx, ly = ty, ha = h;
                have = 1;
            }
            found = clear;
        }
        if (!have) { /* nowhere inside the rim: just inside the line */
            polar_xy(p, d->dir_rad, fmax(0.0, kt - off), &lx, &ly);
            ha = -ha0;
        }
        memcpy(box[nbox++], best, sizeof best);
        text_boxed(cr, lx, ly, 13, 1, ha, 0, buf, limit_col[limit_index(d->limit)]);
    }
    free(box);
}

/* Directions rejected already at 0 kt, in one line under the title
 * (shrunk to the page width rather than run off it). */
static void polar_not_cleared(cairo_t *cr, double W, const shol_result *r)
{
    char buf[256];
    size_t used = 0;
    buf[0] = '\0';
    for (int i = 0; i < r->n_dirs; i++) {
        const shol_dir_result *d = &r->dirs[i];
        if (d->has_pass)
            continue;
        char name[32];
        core_wod_name(d->dir_rad * CORE_RAD_TO_DEG, name, sizeof name);
        int n = snprintf(buf + used, sizeof buf - used, "%s%s (%s)", used ? ", " : "", name,
                         short_label[limit_index(d->limit)]);
        if (n < 0 || (size_t)n >= sizeof buf - used) {
            snprintf(buf + sizeof buf - 5, 5, "...");
            break;
        }
        used += n;
    }
    if (!buf[0])
        return;
    char line[300];
    snprintf(line, sizeof line, "Not cleared at any speed: %s", buf);
    cairo_select_font_face(cr, FONT, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_BOLD);
    cairo_set_font_size(cr, 13);
    cairo_text_extents_t te;
    cairo_text_extents(cr, line, &te);
    double size = te.width > W - 60 ? 13 * (W - 60) / te.width : 13;
    text_boxed(cr, W / 2, 84, size, 1, 0, 0, line, (rgb){0.84, 0.15, 0.16});
}

/* The legend at the foot: the markers of the limiting criteria that occur,
 * the envelope's line (and the comparison's), and, when a sector was not
 * swept (open), what the line through the centre means. */
static void polar_legend(cairo_t *cr, double W, double H, const shol_result *r, const shol_report_info *info,
                         int open)
{
    const shol_result *c = info ? info->compare : NULL;
    char buf[256];
    double ly = H - 158, lx = 40;
    set_col(cr, ink);
    text(cr, lx, ly, 14, 1, -1, 0, "Limiting criterion at each direction:");
    int shown = 0;
    for (int l = SHOL_LIMIT_NONE; l <= SHOL_LIMIT_TRIM; l++) {
        int used = 0;
        for (int i = 0; i < r->n_dirs; i++)
            used |= r->dirs[i].limit == l;
        if (!used)
            continue;
        double x = lx + 10 + (shown % 4) * 210, y = ly + 26 + (shown / 4) * 24;
        marker(cr, l, x, y, 6);
        set_col(cr, ink);
        text(cr, x + 14, y, 13, 0, -1, 0, limit_label[l + 1]);
        shown++;
    }
    double y2 = ly + 26 + ((shown + 3) / 4) * 24 + 4;
    set_col(cr, env_col);
    cairo_set_line_width(cr, 3.5);
    cairo_move_to(cr, lx, y2);
    cairo_line_to(cr, lx + 40, y2);
    cairo_stroke(cr);
    set_col(cr, ink);
    snprintf(buf, sizeof buf, "%s (last passing speed, %g km/h steps%s)",
             info && info->label ? info->label : "envelope",
             r->settings.speed_step_mps / CORE_KMH_TO_MPS,
             r->settings.bisect_tol_mps > 0 ? ", bisection" : "");
    text(cr, lx + 50, y2, 13, 0, -1, 0, buf);
    if (c) {
        double dash[] = {10, 6};
        set_col(cr, cmp_col);
        cairo_set_line_width(cr, 2.5);
        cairo_set_dash(cr, dash, 2, 0);
        cairo_move_to(cr, lx + 450, y2);
        cairo_line_to(cr, lx + 490, y2);
        cairo_stroke(cr);
        cairo_set_dash(cr, NULL, 0, 0);
        set_col(cr, ink);
        text(cr, lx + 500, y2, 13, 0, -1, 0,
             info->compare_label ? info->compare_label : "comparison");
    }
    /* the bands' key (polar_bands) */
    const double y3 = y2 + 26;
    const shol_band_rule br = shol_band_rule_of(r);
    cairo_set_source_rgba(cr, band_col.r, band_col.g, band_col.b, 0.38);
    cairo_rectangle(cr, lx, y3 - 7, 40, 14);
    cairo_fill(cr);
    set_col(cr, (rgb){0.55, 0.35, 0.02});
    cairo_set_line_width(cr, 2.0);
    cairo_move_to(cr, lx + 20, y3 - 7);
    cairo_line_to(cr, lx + 20, y3 + 7);
    cairo_stroke(cr);
    set_col(cr, ink);
    snprintf(buf, sizeof buf, "band (kt in brackets): grid%s, window, 0.25 deg / 1 %%, model error",
             r->band_grid_label[0] ? "" : " (no second grid)");
    text(cr, lx + 50, y3, 13, 0, -1, 0, buf);
    set_col(cr, low_col);
    cairo_set_line_width(cr, 3.0);
    cairo_move_to(cr, lx + 590, y3 - 7);
    cairo_line_to(cr, lx + 590, y3 + 7);
    cairo_stroke(cr);
    snprintf(buf, sizeof buf, "LOW: wider than %g km/h and %g %% of V", br.width_mps / CORE_KMH_TO_MPS, 100 * br.frac);
    text(cr, lx + 602, y3, 13, 1, -1, 0, buf);
    set_col(cr, ink);
    shol_criteria_reading(&r->settings.criteria, buf, sizeof buf);
    text(cr, lx, y3 + 22, shol_plot_fit_size(cr, buf, 12, W - 2 * lx), 0, -1, 0, buf);
    if (open) {
        set_col(cr, ink);
        text(cr, W - 20, H - 16, 12, 0, 1, 1,
             "Directions not swept are not cleared: the line closes through the centre.");
    }
}

static void draw_polar(cairo_t *cr, double W, double H, const shol_result *r,
                       const shol_report_info *info)
{
    const shol_result *c = info ? info->compare : NULL;
    set_col(cr, (rgb){1, 1, 1});
    cairo_paint(cr);
    double step;
    polar p = polar_scale(r, c, W, &step);
    polar_title(cr, W, r, info);
    int open_after;
    double label_dir;
    free(sorted_dirs(r, &open_after, &label_dir));
    polar_grid(cr, &p, step);
    /* Envelopes: the comparison under the main one. */
    if (c)
        polar_envelope(cr, &p, c, cmp_col, 1, 0);
    polar_bands(cr, &p, r, 0);
    polar_envelope(cr, &p, r, env_col, 0, 1);
    polar_bands(cr, &p, r, 1);
    polar_ring_labels(cr, &p, step, label_dir);
    polar_limits(cr, &p, r);
    polar_not_cleared(cr, W, r);
    polar_legend(cr, W, H, r, info, open_after >= 0);
}

/* Reject data cairo cannot place: a NaN or infinite coordinate is not an
 * error to cairo, it draws lines to nowhere. Checks what the plots use:
 * directions, passing speeds, and the converged trims of the history. */
static int check_plot_data(const shol_result *r, const char *what, core_err *err)
{
    for (int i = 0; r && i < r->n_dirs; i++) {
        const shol_dir_result *d = &r->dirs[i];
        if (!isfinite(d->dir_rad))
            return core_err_set(err, -1,
                                "shol: plot: %s direction %d: dir_rad = %g: expected a finite angle", what,
                                i, d->dir_rad);
        char name[32];
        core_wod_name(d->dir_rad * CORE_RAD_TO_DEG, name, sizeof name);
        if (d->has_pass && !(isfinite(d->max_speed_mps) && d->max_speed_mps >= 0))
            return core_err_set(err, -1,
                                "shol: plot: %s %s: max_speed_mps = %g: expected a finite speed >= 0", what,
                                name, d->max_speed_mps);
        /* a band set by hand (or read) that cairo could not place */
        if (d->band.valid && !(isfinite(d->band.lo_mps) && isfinite(d->band.hi_mps) && d->band.lo_mps >= 0 &&
                               d->band.hi_mps >= d->band.lo_mps))
            return core_err_set(err, -1,
                                "shol: plot: %s %s: band %g to %g m/s: expected finite ends, 0 <= lo <= hi", what,
                                name, d->band.lo_mps, d->band.hi_mps);
        for (int j = 0; j < d->n_samples; j++) {
            const shol_sample *sm = &d->samples[j];
            if (!(isfinite(sm->speed_mps) && sm->speed_mps >= 0))
                return core_err_set(err, -1,
                                    "shol: plot: %s %s sample %d: speed_mps = %g: expected a finite speed >= 0",
                                    what, name, j, sm->speed_mps);
            const double q[6] = {sm->trim.phi_rad,         sm->trim.theta_rad,
                                 sm->trim.long_cyclic_pct, sm->trim.lat_cyclic_pct,
                                 sm->trim.collective_pct,  sm->trim.pedal_pct};
            static const char *const qn[6] = {"phi_rad",        "theta_rad",      "long_cyclic_pct",
                                              "lat_cyclic_pct", "collective_pct", "pedal_pct"};
            for (int k = 0; sm->trim_status == 0 && k < 6; k++)
                if (!isfinite(q[k]))
                    return core_err_set(err, -1,
                                        "shol: plot: %s %s at %g km/h: trim %s = %g: expected a finite value "
                                        "(or trim_status > 0)",
                                        what, name, sm->speed_mps / CORE_KMH_TO_MPS, qn[k], q[k]);
        }
    }
    return 0;
}

static int check_plot_inputs(const shol_result *r, const shol_report_info *info, core_err *err)
{
    if (check_plot_data(r, "envelope", err) < 0)
        return -1;
    return info ? check_plot_data(info->compare, "comparison", err) : 0;
}

static int cairo_fail(cairo_status_t st, const char *path, core_err *err)
{
    return core_err_set(err, -1, "%s: cairo: %s", path, cairo_status_to_string(st));
}

/* Write a drawn image surface to tmp as PNG and rename it to final; frees
 * the context and the surface whatever happens. */
static int png_finish(cairo_surface_t *sf, cairo_t *cr, const char *tmp, const char *final,
                      core_err *err)
{
    cairo_status_t st = cairo_status(cr);
    cairo_destroy(cr);
    if (st == CAIRO_STATUS_SUCCESS)
        st = cairo_surface_write_to_png(sf, tmp);
    cairo_surface_destroy(sf);
    if (st != CAIRO_STATUS_SUCCESS) {
        shol_io_abort(NULL, tmp);
        return cairo_fail(st, final, err);
    }
    return shol_io_commit(NULL, tmp, final, err) < 0 ? -1 : 0;
}

int shol_plot_polar(const char *dir, const shol_result *r, const shol_report_info *info,
                    core_err *err)
{
    const double W = 1000, H = 1100;
    char final[SHOL_IO_PATH_MAX], tmp[SHOL_IO_PATH_MAX];
    if (check_plot_inputs(r, info, err) < 0 || shol_io_mkdir(dir, err) < 0)
        return -1;

    /* PNG */
    if (shol_io_paths(dir, "shol_polar.png", final, tmp, err) < 0)
        return -1;
    cairo_surface_t *sf = cairo_image_surface_create(CAIRO_FORMAT_RGB24, (int)W, (int)H);
    cairo_t *cr = cairo_create(sf);
    draw_polar(cr, W, H, r, info);
    if (png_finish(sf, cr, tmp, final, err) < 0)
        return -1;

    /* SVG: the same drawing on a vector surface (points = pixels). */
    if (shol_io_paths(dir, "shol_polar.svg", final, tmp, err) < 0)
        return -1;
    sf = cairo_svg_surface_create(tmp, W, H);
    cr = cairo_create(sf);
    draw_polar(cr, W, H, r, info);
    cairo_status_t st = cairo_status(cr);
    cairo_destroy(cr);
    cairo_surface_finish(sf);
    if (st == CAIRO_STATUS_SUCCESS)
        st = cairo_surface_status(sf);
    cairo_surface_destroy(sf);
    if (st != CAIRO_STATUS_SUCCESS) {
        shol_io_abort(NULL, tmp);
        return cairo_fail(st, final, err);
    }
    return shol_io_commit(NULL, tmp, final, err);
}

/* ------------------------------------------------------ trim vs speed */
typedef struct panel {
    double x0, y0, w, h;     /* plot area in pixels */
    double xmax, ymin, ymax; /* data range: kt, quantity */
} panel;

static double px(const panel *p, double x)
{
    return p->x0 + p->w * x / p->xmax;
}
static double py(const panel *p, double y)
{
    return p->y0 + p->h * (p->ymax - y) / (p->ymax - p->ymin);
}

/* Value of quantity q (0..5) of a sample, in plot units (deg or %). */
static double sample_val(const shol_sample *s, int q)
{
    switch (q) {
    case 0:
        return s->trim.phi_rad * CORE_RAD_TO_DEG;
    case 1:
        return s->trim.theta_rad * CORE_RAD_TO_DEG;
    case 2:
        return s->trim.long_cyclic_pct;
    case 3:
        return s->trim.lat_cyclic_pct;
    case 4:
        return s->trim.collective_pct;
    default:
        return s->trim.pedal_pct;
    }
}

static void series(cairo_t *cr, const panel *p, const shol_dir_result *d, int q, rgb col,
                   int dashed)
{
    cairo_save(cr);
    cairo_rectangle(cr, p->x0, p->y0, p->w, p->h);
    cairo_clip(cr);
    cairo_new_path(cr);
    int started = 0;
    for (int i = 0; i < d->n_samples; i++) {
        const shol_sample *s = &d->samples[i];
        if (s->trim_status != 0) {
            started = 0;
            continue;
        }
        double x = px(p, s->speed_mps / CORE_KT_TO_MPS), y = py(p, sample_val(s, q));
        if (started)
            cairo_line_to(cr, x, y);
        else
            cairo_move_to(cr, x, y);
        started = 1;
    }
    set_col(cr, col);
    cairo_set_line_width(cr, dashed ? 1.8 : 2.2);
    if (dashed) {
        double dash[] = {7, 4};
        cairo_set_dash(cr, dash, 2, 0);
    }
    cairo_stroke(cr);
    cairo_set_dash(cr, NULL, 0, 0);
    for (int i = 0; i < d->n_samples; i++) {
        const shol_sample *s = &d->samples[i];
        if (s->trim_status != 0)
            continue;
        double x = px(p, s->speed_mps / CORE_KT_TO_MPS), y = py(p, sample_val(s, q));
        cairo_new_path(cr);
        cairo_arc(cr, x, y, dashed ? 2.5 : 3.5, 0, 2 * CORE_PI);
        if (s->pass) {
            set_col(cr, col);
            cairo_fill(cr);
        } else if (s->eval.margin[q] < 0) {
            /* This quantity is beyond its limit here: a big red ring. */
            cairo_new_path(cr);
            cairo_set_source_rgb(cr, 0.84, 0.15, 0.16);
            cairo_set_line_width(cr, 2.5);
            cairo_arc(cr, x, y, 7, 0, 2 * CORE_PI);
            cairo_stroke(cr);
        } else {
            /* Rejected by another quantity: an open ring in the series colour. */
            cairo_new_path(cr);
            set_col(cr, col);
            cairo_set_line_width(cr, 1.5);
            cairo_arc(cr, x, y, 4, 0, 2 * CORE_PI);
            cairo_set_source_rgb(cr, 1, 1, 1);
            cairo_fill_preserve(cr);
            set_col(cr, col);
            cairo_stroke(cr);
        }
    }
    cairo_restore(cr);
}

static void draw_panel(cairo_t *cr, panel *p, int q, const char *title, double lim_lo,
                       double lim_hi, const shol_dir_result *d, const shol_dir_result *dc)
{
    char buf[64];
    /* Rejected zones shaded, limits dashed red; a limit of -INFINITY (the
     * collective's lower) is none. */
    set_col(cr, reject_fill);
    if (lim_hi < p->ymax) {
        cairo_rectangle(cr, p->x0, p->y0, p->w, py(p, lim_hi) - p->y0);
        cairo_fill(cr);
    }
    if (lim_lo > p->ymin) {
        cairo_rectangle(cr, p->x0, py(p, lim_lo), p->w, p->y0 + p->h - py(p, lim_lo));
        cairo_fill(cr);
    }
    /* Grid and ticks. */
    double xs = nice_step(p->xmax, 6), ys = nice_step(p->ymax - p->ymin, 5);
    cairo_set_line_width(cr, 0.8);
    for (double x = 0; x <= p->xmax + 1e-9; x += xs) {
        set_col(cr, grid_col);
        cairo_move_to(cr, px(p, x), p->y0);
        cairo_line_to(cr, px(p, x), p->y0 + p->h);
        cairo_stroke(cr);
        set_col(cr, ink);
        fmt_num(buf, sizeof buf, x);
        text(cr, px(p, x), p->y0 + p->h + 6, 12, 0, 0, -1, buf);
    }
    for (double y = ceil(p->ymin / ys - 1e-9) * ys; y <= p->ymax + 1e-9; y += ys) {
        set_col(cr, grid_col);
        cairo_move_to(cr, p->x0, py(p, y));
        cairo_line_to(cr, p->x0 + p->w, py(p, y));
        cairo_stroke(cr);
        set_col(cr, ink);
        fmt_num(buf, sizeof buf, y);
        text(cr, p->x0 - 6, py(p, y), 12, 0, 1, 0, buf);
    }
    double dash[] = {8, 5};
    cairo_set_dash(cr, dash, 2, 0);
    cairo_set_line_width(cr, 1.8);
    cairo_set_source_rgb(cr, 0.84, 0.15, 0.16);
    double lims[2] = {lim_lo, lim_hi};
    for (int i = 0; i < 2; i++) {
        if (!isfinite(lims[i]))
            continue;
        cairo_move_to(cr, p->x0, py(p, lims[i]));
        cairo_line_to(cr, p->x0 + p->w, py(p, lims[i]));
        cairo_stroke(cr);
        fmt_num(buf, sizeof buf, lims[i]);
        char lab[80];
        snprintf(lab, sizeof lab, "limit %s", buf);
        text_boxed(cr, p->x0 + 4, py(p, lims[i]) + (i ? 3 : -3), 11, 0, -1, i ? -1 : 1, lab,
                   (rgb){0.84, 0.15, 0.16});
    }
    /* The envelope edge (last pass) and trims that did not converge. */
    if (d->has_pass) {
        cairo_set_source_rgb(cr, env_col.r, env_col.g, env_col.b);
        cairo_move_to(cr, px(p, d->max_speed_mps / CORE_KT_TO_MPS), p->y0);
        cairo_line_to(cr, px(p, d->max_speed_mps / CORE_KT_TO_MPS), p->y0 + p->h);
        cairo_stroke(cr);
    }
    cairo_set_dash(cr, NULL, 0, 0);
    /* Trims that did not converge: a cross on the speed axis (no value to
     * plot), labelled once at the lowest such speed. */
    int labelled = 0;
    double ym = p->y0 + p->h - 12;
    for (int i = 0; i < d->n_samples; i++)
        if (d->samples[i].trim_status != 0) {
            double x = px(p, d->samples[i].speed_mps / CORE_KT_TO_MPS);
            set_col(cr, ink);
            cairo_set_line_width(cr, 2.5);
            cairo_move_to(cr, x - 5, ym - 5);
            cairo_line_to(cr, x + 5, ym + 5);
            cairo_move_to(cr, x - 5, ym + 5);
            cairo_line_to(cr, x + 5, ym - 5);
            cairo_stroke(cr);
            if (!labelled)
                text_boxed(cr, x - 9, ym, 11, 0, 1, 0, "no trim", ink);
            labelled = 1;
        }
    if (dc)
        series(cr, p, dc, q, cmp_col, 1);
    series(cr, p, d, q, env_col, 0);
    /* Frame and title. */
    set_col(cr, ink);
    cairo_set_line_width(cr, 1.2);
    cairo_rectangle(cr, p->x0, p->y0, p->w, p->h);
    cairo_stroke(cr);
    text(cr, p->x0 + p->w / 2, p->y0 - 10, 15, 1, 0, 1, title);
    text(cr, p->x0 + p->w / 2, p->y0 + p->h + 24, 12, 0, 0, -1, "WOD speed (kt)");
}

static const shol_dir_result *find_dir(const shol_result *c, double dir_rad)
{
    for (int i = 0; c && i < c->n_dirs; i++)
        if (fabs(c->dirs[i].dir_rad - dir_rad) < 1e-6)
            return &c->dirs[i];
    return NULL;
}

/* The trim plots' legend: the entries flow from the left, each after the
 * last one's text (labels such as "one-way (ship-only airwake)" vary in
 * length); an entry that does not fit starts a row above. dc: the
 * comparison's direction, or NULL. */
static void trim_legend(cairo_t *cr, double W, double H, const shol_dir_result *d, const shol_dir_result *dc,
                        const shol_report_info *info)
{
    char buf[256];
    double ly = H - 30, lx = 40;
    const double gap = 26;
    set_col(cr, env_col);
    cairo_set_line_width(cr, 2.2);
    cairo_move_to(cr, lx, ly);
    cairo_line_to(cr, lx + 40, ly);
    cairo_stroke(cr);
    cairo_arc(cr, lx + 20, ly, 3.5, 0, 2 * CORE_PI);
    cairo_fill(cr);
    set_col(cr, ink);
    snprintf(buf, sizeof buf, "%s: trims passing", info && info->label ? info->label : "trim");
    lx += 48 + text(cr, lx + 48, ly, 13, 0, -1, 0, buf) + gap;
    cairo_set_source_rgb(cr, 0.84, 0.15, 0.16);
    cairo_set_line_width(cr, 2);
    cairo_new_path(cr);
    cairo_arc(cr, lx + 6, ly, 6, 0, 2 * CORE_PI);
    cairo_stroke(cr);
    set_col(cr, ink);
    lx += 18 + text(cr, lx + 18, ly, 13, 0, -1, 0, "beyond this limit") + gap;
    set_col(cr, env_col);
    double dash[] = {8, 5};
    cairo_set_dash(cr, dash, 2, 0);
    cairo_set_line_width(cr, 1.8);
    cairo_move_to(cr, lx, ly - 8);
    cairo_line_to(cr, lx, ly + 8);
    cairo_stroke(cr);
    cairo_set_dash(cr, NULL, 0, 0);
    set_col(cr, ink);
    lx += 8 + text(cr, lx + 8, ly, 13, 0, -1, 0, "envelope edge (last pass)") + gap;
    if (dc) {
        const char *cl = info->compare_label ? info->compare_label : "comparison";
        legend_wrap(cr, cl, 48, W, &lx, &ly);
        set_col(cr, cmp_col);
        cairo_set_dash(cr, dash, 2, 0);
        cairo_move_to(cr, lx, ly);
        cairo_line_to(cr, lx + 40, ly);
        cairo_stroke(cr);
        cairo_set_dash(cr, NULL, 0, 0);
        set_col(cr, ink);
        lx += 48 + text(cr, lx + 48, ly, 13, 0, -1, 0, cl) + gap;
    }
    int any_fail = 0;
    for (int i = 0; i < d->n_samples; i++)
        any_fail |= d->samples[i].trim_status != 0;
    if (any_fail) {
        const char *fl = "trim did not converge (a rejection)";
        legend_wrap(cr, fl, 33, W, &lx, &ly);
        set_col(cr, ink);
        cairo_set_line_width(cr, 2.5);
        cairo_move_to(cr, lx + 15, ly - 5);
        cairo_line_to(cr, lx + 25, ly + 5);
        cairo_move_to(cr, lx + 15, ly + 5);
        cairo_line_to(cr, lx + 25, ly - 5);
        cairo_stroke(cr);
        text(cr, lx + 33, ly, 13, 0, -1, 0, fl);
    }
}

static void draw_trim(cairo_t *cr, double W, double H, const shol_result *r,
                      const shol_dir_result *d, const shol_report_info *info)
{
    const shol_dir_result *dc = find_dir(info ? info->compare : NULL, d->dir_rad);
    const shol_criteria *k = &r->settings.criteria;
    set_col(cr, (rgb){1, 1, 1});
    cairo_paint(cr);

    char name[32], buf[256];
    core_wod_name(d->dir_rad * CORE_RAD_TO_DEG, name, sizeof name);
    set_col(cr, ink);
    snprintf(buf, sizeof buf, "Trim vs WOD speed, %s%s%s", name, info && info->title ? ": " : "",
             info && info->title ? info->title : "");
    text(cr, W / 2, 30, 22, 1, 0, 0, buf);
    if (d->has_pass)
        snprintf(buf, sizeof buf, "envelope %.1f kt (%.1f km/h); first rejected by %s at %.1f kt",
                 d->max_speed_mps / CORE_KT_TO_MPS, d->max_speed_mps / CORE_KMH_TO_MPS,
                 limit_label[limit_index(d->limit)],
                 isfinite(d->fail_speed_mps) ? d->fail_speed_mps / CORE_KT_TO_MPS : NAN);
    else
        snprintf(buf, sizeof buf, "rejected already at 0 kt (%s)",
                 limit_label[limit_index(d->limit)]);
    if (d->limit == SHOL_LIMIT_NONE && d->has_pass)
        snprintf(buf, sizeof buf,
                 "no criterion exceeded up to %.1f kt (%.0f km/h, highest searched)",
                 d->max_speed_mps / CORE_KT_TO_MPS, d->max_speed_mps / CORE_KMH_TO_MPS);
    text(cr, W / 2, 58, 14, 0, 0, 0, buf);
    shol_criteria_reading(k, buf, sizeof buf);
    text(cr, W / 2, 82, shol_plot_fit_size(cr, buf, 12, W - 40), 0, 0, 0, buf);

    /* Data range: speeds up to the last sample (at least one step). */
    double xmax = r->settings.speed_step_mps / CORE_KT_TO_MPS;
    for (int i = 0; i < d->n_samples; i++)
        xmax = fmax(xmax, d->samples[i].speed_mps / CORE_KT_TO_MPS);
    for (int i = 0; dc && i < dc->n_samples; i++)
        xmax = fmax(xmax, dc->samples[i].speed_mps / CORE_KT_TO_MPS);
    xmax = ceil(xmax / nice_step(xmax, 6) - 1e-9) * nice_step(xmax, 6);

    const char *titles[6] = {
        "Roll (deg, right wing down +)",         "Pitch (deg, nose up +)",
        "Longitudinal cyclic (%, 0 = full fwd)", "Lateral cyclic (%, 0 = full left)",
        "Collective (%, 0 = full down)",         "Pedal (%, 0 = full left)"};
    double att[2] = {k->roll_max_rad * CORE_RAD_TO_DEG, k->pitch_max_rad * CORE_RAD_TO_DEG};
    double pw = (W - 3 * 90) / 2 + 15, ph = (H - 150 - 3 * 95) / 3;
    for (int q = 0; q < 6; q++) {
        panel p;
        p.x0 = 85 + (q % 2) * (pw + 95);
        p.y0 = 120 + (q / 2) * (ph + 95);
        p.w = pw;
        p.h = ph;
        p.xmax = xmax;
        double lo, hi;
        if (q < 2) {
            double m = att[q] * 1.6;
            for (int i = 0; i < d->n_samples; i++)
                if (d->samples[i].trim_status == 0)
                    m = fmax(m, 1.1 * fabs(sample_val(&d->samples[i], q)));
            double ys = nice_step(2 * m, 5);
            p.ymax = ceil(m / ys) * ys;
            p.ymin = -p.ymax;
            lo = -att[q];
            hi = att[q];
        } else {
            p.ymin = 0;
            p.ymax = 100;
            shol_criteria_control_bounds(k, q, &lo, &hi);
        }
        draw_panel(cr, &p, q, titles[q], lo, hi, d, dc);
    }

    trim_legend(cr, W, H, d, dc, info);
}

int shol_plot_trim(const char *dir, const shol_result *r, const shol_report_info *info,
                   core_err *err)
{
    const double W = 1100, H = 1050;
    if (check_plot_inputs(r, info, err) < 0 || shol_io_mkdir(dir, err) < 0)
        return -1;
    for (int i = 0; i < r->n_dirs; i++) {
        char name[64], final[SHOL_IO_PATH_MAX], tmp[SHOL_IO_PATH_MAX];
        shol_trim_plot_name(r->dirs[i].dir_rad, name, sizeof name);
        if (shol_io_paths(dir, name, final, tmp, err) < 0)
            return -1;
        cairo_surface_t *sf = cairo_image_surface_create(CAIRO_FORMAT_RGB24, (int)W, (int)H);
        cairo_t *cr = cairo_create(sf);
        draw_trim(cr, W, H, r, &r->dirs[i], info);
        if (png_finish(sf, cr, tmp, final, err) < 0)
            return -1;
    }
    return 0;
}
