/*
 * plot_flown.c -- the flown envelope over the trim-based one in one polar
 * plot (PNG and SVG), as the trim plot draws it (docs/conventions.md, NATOPS
 * habit: the bow up, starboard to the right, WOD speed in knots as the
 * radius, one closed line per envelope; a gap wider than 90 deg between
 * the directions closes through the centre). The trim envelope is dashed,
 * the flown one solid; every flown point is a dot coloured by its pass
 * rate (red 0 to green 1, its outline black when the point passed), and
 * each direction's flown cause is written beside its first failing point.
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

typedef struct fpolar {
    double cx, cy, R, rmax_kt;
} fpolar;

static void xy(const fpolar *p, double dir_rad, double kt, double *x, double *y)
{
    double r = p->R * kt / p->rmax_kt;
    *x = p->cx + r * sin(dir_rad);
    *y = p->cy - r * cos(dir_rad);
}

static void text(cairo_t *cr, double x, double y, double size, int bold, int ha, const char *s)
{
    cairo_select_font_face(cr, FONT, CAIRO_FONT_SLANT_NORMAL, bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, size);
    cairo_text_extents_t te;
    cairo_text_extents(cr, s, &te);
    double dx = ha < 0 ? -te.x_bearing : ha == 0 ? -(te.x_bearing + te.width / 2) : -(te.x_bearing + te.width);
    cairo_move_to(cr, x + dx, y - (te.y_bearing + te.height / 2));
    cairo_show_text(cr, s);
}

static int by_dir(const void *a, const void *b)
{
    double x = ((const double *)a)[0], y = ((const double *)b)[0];
    return (x > y) - (x < y);
}

/* One closed envelope line through (dir, kt) pairs. */
static void envelope(cairo_t *cr, const fpolar *p, double (*v)[2], int n, double r, double g, double b, int dashed)
{
    if (n < 1)
        return;
    qsort(v, (size_t)n, sizeof v[0], by_dir);
    double gmax = -1;
    int imax = 0;
    for (int i = 0; i < n; i++) {
        double gap = v[(i + 1) % n][0] - v[i][0];
        if (gap <= 0)
            gap += 2 * CORE_PI;
        if (gap > gmax + 1e-9) {
            gmax = gap;
            imax = i;
        }
    }
    int open = gmax > CORE_PI / 2 + 1e-9, start = open ? (imax + 1) % n : 0;
    cairo_new_path(cr);
    if (open)
        cairo_move_to(cr, p->cx, p->cy);
    for (int k = 0; k < n; k++) {
        double x, y;
        xy(p, v[(start + k) % n][0], v[(start + k) % n][1], &x, &y);
        if (k == 0 && !open)
            cairo_move_to(cr, x, y);
        else
            cairo_line_to(cr, x, y);
    }
    cairo_close_path(cr);
    cairo_set_source_rgba(cr, r, g, b, dashed ? 0.0 : 0.12);
    cairo_fill_preserve(cr);
    cairo_set_source_rgb(cr, r, g, b);
    cairo_set_line_width(cr, dashed ? 2.5 : 3.5);
    cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
    if (dashed) {
        double dash[] = {10, 6};
        cairo_set_dash(cr, dash, 2, 0);
    }
    cairo_stroke(cr);
    cairo_set_dash(cr, NULL, 0, 0);
}

/* A band's whisker from lo to hi kt at dir, side_px beside the spoke (so
 * that the points on it stay visible), capped (no cap above when open),
 * red and thicker when low is set. */
static void whisker(cairo_t *cr, const fpolar *p, double dir, double side_px, double lo_kt, double hi_kt, int open,
                    int low, double r, double g, double b, double width)
{
    double x0, y0, x1, y1;
    const double ax = cos(dir), ay = sin(dir); /* across the spoke, on the page */
    xy(p, dir, lo_kt, &x0, &y0);
    xy(p, dir, hi_kt, &x1, &y1);
    x0 += side_px * ax, y0 += side_px * ay, x1 += side_px * ax, y1 += side_px * ay;
    const double tx = ax * 6, ty = ay * 6;
    if (low)
        cairo_set_source_rgb(cr, 0.80, 0.05, 0.10);
    else
        cairo_set_source_rgb(cr, r, g, b);
    cairo_set_line_width(cr, low ? width + 1 : width);
    cairo_new_path(cr);
    cairo_move_to(cr, x0, y0);
    cairo_line_to(cr, x1, y1);
    cairo_move_to(cr, x0 - tx, y0 - ty);
    cairo_line_to(cr, x0 + tx, y0 + ty);
    if (!open) {
        cairo_move_to(cr, x1 - tx, y1 - ty);
        cairo_line_to(cr, x1 + tx, y1 + ty);
    }
    cairo_stroke(cr);
}

static void draw(cairo_t *cr, double W, double H, const shol_flown_result *f, const shol_result *t,
                 const shol_report_info *info, double (*buf)[2])
{
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
    double top = 0;
    for (int i = 0; i < f->n_dirs; i++)
        for (int k = 0; k < f->dirs[i].n_points; k++)
            top = fmax(top, f->dirs[i].points[k].speed_mps / CORE_KT_TO_MPS);
    for (int i = 0; t && i < t->n_dirs; i++) {
        shol_band b;
        shol_band_get(t, i, &b);
        top = fmax(top, b.hi_mps / CORE_KT_TO_MPS);
        if (t->dirs[i].has_pass)
            top = fmax(top, t->dirs[i].max_speed_mps / CORE_KT_TO_MPS);
    }
    for (int i = 0; i < f->n_dirs; i++) {
        shol_band b = f->dirs[i].band;
        if (!b.valid)
            shol_flown_band(f, t, i, &b);
        top = fmax(top, b.hi_mps / CORE_KT_TO_MPS);
    }
    double step = top > 60 ? 20 : top > 25 ? 10 : 5;
    fpolar p = {W / 2, 110 + 0.40 * W, 0.36 * W, 0};
    p.rmax_kt = fmax(step, ceil(top / step - 1e-9) * step);
    if (p.rmax_kt - top < 0.15 * p.rmax_kt)
        p.rmax_kt += step;
    /* title */
    char s[256];
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    snprintf(s, sizeof s, "%s: flown SHOL over the trim-based one", info && info->title ? info->title : "Candidate SHOL");
    text(cr, W / 2, 30, 24, 1, 0, s);
    snprintf(s, sizeof s, "%d seed%s per point, a point passes at a pass rate >= %.2f; %d flights", f->flown.n_seeds,
             f->flown.n_seeds == 1 ? "" : "s", f->flown.pass_rate_min, f->n_flights);
    text(cr, W / 2, 62, 15, 0, 0, s);
    if (t) {
        shol_criteria_reading(&t->settings.criteria, s, sizeof s);
        text(cr, W / 2, 86, shol_plot_fit_size(cr, s, 12, W - 40), 0, 0, s);
    }
    /* rings and spokes */
    cairo_set_line_width(cr, 1);
    for (double kt = step; kt <= p.rmax_kt + 1e-9; kt += step) {
        cairo_set_source_rgb(cr, 0.8, 0.8, 0.8);
        cairo_new_path(cr);
        cairo_arc(cr, p.cx, p.cy, p.R * kt / p.rmax_kt, 0, 2 * CORE_PI);
        cairo_stroke(cr);
        cairo_set_source_rgb(cr, 0.35, 0.35, 0.35);
        snprintf(s, sizeof s, "%.0f kt", kt);
        text(cr, p.cx + 4, p.cy + p.R * kt / p.rmax_kt - 9, 12, 0, -1, s);
    }
    for (int a = -150; a <= 180; a += 30) {
        double x, y;
        xy(&p, a * CORE_DEG_TO_RAD, p.rmax_kt, &x, &y);
        cairo_set_source_rgb(cr, 0.8, 0.8, 0.8);
        cairo_move_to(cr, p.cx, p.cy);
        cairo_line_to(cr, x, y);
        cairo_stroke(cr);
        char name[32];
        core_wod_name((double)a, name, sizeof name);
        xy(&p, a * CORE_DEG_TO_RAD, p.rmax_kt * 1.08, &x, &y);
        cairo_set_source_rgb(cr, 0.25, 0.25, 0.25);
        text(cr, x, y, 13, 0, 0, name);
    }
    /* the envelopes: trim dashed blue, flown solid green */
    int n = 0;
    for (int i = 0; t && i < t->n_dirs; i++) {
        buf[n][0] = t->dirs[i].dir_rad;
        buf[n++][1] = t->dirs[i].has_pass ? t->dirs[i].max_speed_mps / CORE_KT_TO_MPS : 0;
    }
    envelope(cr, &p, buf, n, 0.15, 0.35, 0.85, 1);
    n = 0;
    for (int i = 0; i < f->n_dirs; i++) {
        buf[n][0] = f->dirs[i].dir_rad;
        buf[n++][1] = f->dirs[i].has_pass ? f->dirs[i].max_speed_mps / CORE_KT_TO_MPS : 0;
    }
    envelope(cr, &p, buf, n, 0.05, 0.45, 0.20, 0);
    /* the points, and the cause at each direction's first failure */
    double(*box)[4] = calloc((size_t)(f->n_dirs > 0 ? f->n_dirs : 1), sizeof *box);
    int nbox = 0;
    for (int i = 0; i < f->n_dirs; i++) {
        const shol_flown_dir *d = &f->dirs[i];
        for (int k = 0; k < d->n_points; k++) {
            const shol_flown_point *q = &d->points[k];
            double x, y;
            xy(&p, d->dir_rad, q->speed_mps / CORE_KT_TO_MPS, &x, &y);
            cairo_new_path(cr);
            cairo_arc(cr, x, y, 6, 0, 2 * CORE_PI);
            cairo_set_source_rgb(cr, 0.85 * (1 - q->pass_rate) + 0.1, 0.15 + 0.6 * q->pass_rate, 0.15);
            cairo_fill_preserve(cr);
            cairo_set_line_width(cr, q->pass ? 2.0 : 1.0);
            cairo_set_source_rgb(cr, q->pass ? 0 : 0.4, q->pass ? 0 : 0.4, q->pass ? 0 : 0.4);
            cairo_stroke(cr);
        }
        if (!isnan(d->fail_speed_mps) && box) {
            double x = 0, y = 0;
            snprintf(s, sizeof s, "%s (%.0f%%)", d->cause, 100 * d->pass_rate_fail);
            cairo_select_font_face(cr, FONT, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
            cairo_set_font_size(cr, 11);
            cairo_text_extents_t te;
            cairo_text_extents(cr, s, &te);
            /* the first place, out from the first failure and then beside
             * the spoke, where the label covers no earlier one (else the
             * first tried) */
            const double ax = cos(d->dir_rad), ay = sin(d->dir_rad);
            static const double cand[][2] = {{0.06, 0}, {0.12, 0}, {0.06, 1}, {0.06, -1}, {0.18, 0},
                                             {0.12, 1}, {0.12, -1}, {0.24, 0}, {0.18, 1}, {0.18, -1}};
            for (int k = 0; k < (int)(sizeof cand / sizeof cand[0]); k++) {
                double tx, ty;
                xy(&p, d->dir_rad, d->fail_speed_mps / CORE_KT_TO_MPS + cand[k][0] * p.rmax_kt, &tx, &ty);
                tx += cand[k][1] * (te.height + 8) * ax, ty += cand[k][1] * (te.height + 8) * ay;
                const double b0[4] = {tx - te.width / 2 - 2, ty - te.height / 2 - 2, tx + te.width / 2 + 2,
                                      ty + te.height / 2 + 2};
                int clear = 1;
                for (int j = 0; j < nbox && clear; j++)
                    clear = b0[2] + 2 < box[j][0] || box[j][2] + 2 < b0[0] || b0[3] + 1 < box[j][1] ||
                            box[j][3] + 1 < b0[1];
                if (k == 0 || clear) {
                    x = tx, y = ty;
                    memcpy(box[nbox], b0, sizeof b0);
                }
                if (clear)
                    break;
            }
            nbox++;
            cairo_set_source_rgba(cr, 1, 1, 1, 0.8);
            cairo_rectangle(cr, x - te.width / 2 - 2, y - te.height / 2 - 2, te.width + 4, te.height + 4);
            cairo_fill(cr);
            cairo_set_source_rgb(cr, 0.3, 0.05, 0.05);
            text(cr, x, y, 11, 0, 0, s);
        }
    }
    free(box);
    /* the bands (shol_band_get, shol_flown_band), beside the points: the
     * trim's thin and blue on one side, the flown one's amber on the
     * other; red where of low confidence */
    for (int i = 0; t && i < t->n_dirs; i++) {
        shol_band b;
        shol_band_get(t, i, &b);
        whisker(cr, &p, t->dirs[i].dir_rad, 11, b.lo_mps / CORE_KT_TO_MPS, b.hi_mps / CORE_KT_TO_MPS, b.open_above,
                b.low_confidence, 0.15, 0.35, 0.85, 1.5);
    }
    for (int i = 0; i < f->n_dirs; i++) {
        shol_band b = f->dirs[i].band;
        if (!b.valid)
            shol_flown_band(f, t, i, &b);
        whisker(cr, &p, f->dirs[i].dir_rad, -11, b.lo_mps / CORE_KT_TO_MPS, b.hi_mps / CORE_KT_TO_MPS, b.open_above,
                b.low_confidence, 0.75, 0.48, 0.05, 3.0);
    }
    /* legend */
    double ly = H - 88;
    cairo_set_line_width(cr, 2.5);
    double dash[] = {10, 6};
    cairo_set_dash(cr, dash, 2, 0);
    cairo_set_source_rgb(cr, 0.15, 0.35, 0.85);
    cairo_move_to(cr, 40, ly);
    cairo_line_to(cr, 90, ly);
    cairo_stroke(cr);
    cairo_set_dash(cr, NULL, 0, 0);
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    snprintf(s, sizeof s, "trim-based%s%s", info && info->compare_label ? ": " : "",
             info && info->compare_label ? info->compare_label : "");
    text(cr, 100, ly, 14, 0, -1, s);
    cairo_set_line_width(cr, 3.5);
    cairo_set_source_rgb(cr, 0.05, 0.45, 0.20);
    cairo_move_to(cr, 40, ly + 28);
    cairo_line_to(cr, 90, ly + 28);
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    snprintf(s, sizeof s, "flown%s%s; dots: each point's pass rate, red 0 to green 1 (black edge: passed)",
             info && info->label ? ": " : "", info && info->label ? info->label : "");
    text(cr, 100, ly + 28, 14, 0, -1, s);
    /* the bands' key */
    const shol_band_rule br = t ? shol_band_rule_of(t) : (shol_band_rule){10 * CORE_KMH_TO_MPS, 0.25};
    cairo_set_source_rgb(cr, 0.75, 0.48, 0.05);
    cairo_set_line_width(cr, 3.0);
    cairo_move_to(cr, 65, ly + 49);
    cairo_line_to(cr, 65, ly + 63);
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0.80, 0.05, 0.10);
    cairo_set_line_width(cr, 4.0);
    cairo_move_to(cr, 80, ly + 49);
    cairo_line_to(cr, 80, ly + 63);
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    snprintf(s, sizeof s, "bands: flown amber, trim thin blue (grid, window, 0.25 deg / 1 %%, model); red: low, wider than %g "
                          "km/h and %g %% of the limit",
             br.width_mps / CORE_KMH_TO_MPS, 100 * br.frac);
    text(cr, 100, ly + 56, 13, 0, -1, s);
}

static int check(const shol_flown_result *f, const shol_result *t, core_err *err)
{
    for (int i = 0; i < f->n_dirs; i++) {
        const shol_flown_dir *d = &f->dirs[i];
        if (!isfinite(d->dir_rad) || !isfinite(d->max_speed_mps))
            return core_err_set(err, -1, "shol: flown plot: direction %d: a direction or speed not finite", i);
        for (int k = 0; k < d->n_points; k++)
            if (!isfinite(d->points[k].speed_mps) || !isfinite(d->points[k].pass_rate))
                return core_err_set(err, -1, "shol: flown plot: direction %d point %d: speed or pass rate not finite",
                                    i, k);
    }
    for (int i = 0; t && i < t->n_dirs; i++)
        if (!isfinite(t->dirs[i].dir_rad) || (t->dirs[i].has_pass && !isfinite(t->dirs[i].max_speed_mps)))
            return core_err_set(err, -1, "shol: flown plot: trim direction %d: not finite", i);
    /* the bands drawn (a band of NaN would draw to nowhere) */
    for (int i = 0; i < f->n_dirs + (t ? t->n_dirs : 0); i++) {
        const int fl = i < f->n_dirs;
        shol_band b;
        if (fl) {
            b = f->dirs[i].band;
            if (!b.valid)
                shol_flown_band(f, t, i, &b);
        } else
            shol_band_get(t, i - f->n_dirs, &b);
        if (!(isfinite(b.lo_mps) && isfinite(b.hi_mps) && b.lo_mps >= 0 && b.hi_mps >= b.lo_mps)) {
            char name[32];
            core_wod_name((fl ? f->dirs[i].dir_rad : t->dirs[i - f->n_dirs].dir_rad) * CORE_RAD_TO_DEG, name,
                          sizeof name);
            return core_err_set(err, -1, "shol: flown plot: %s %s: band %g to %g m/s: expected finite, 0 <= lo <= hi",
                                fl ? "flown" : "trim", name, b.lo_mps, b.hi_mps);
        }
    }
    return 0;
}

int shol_flown_plot_polar(const char *dir, const shol_flown_result *f, const shol_result *trim,
                          const shol_report_info *info, core_err *err)
{
    const double W = 1000, H = 1090;
    if (check(f, trim, err) < 0 || shol_io_mkdir(dir, err) < 0)
        return -1;
    int nmax = f->n_dirs + (trim ? trim->n_dirs : 0) + 1;
    double(*buf)[2] = malloc((size_t)nmax * sizeof *buf);
    if (!buf)
        return core_err_set(err, -1, "shol: out of memory");
    char final[SHOL_IO_PATH_MAX], tmp[SHOL_IO_PATH_MAX];
    int rc = -1;
    for (int svg = 0; svg < 2; svg++) {
        if (shol_io_paths(dir, svg ? "shol_polar_flown.svg" : "shol_polar_flown.png", final, tmp, err) < 0)
            goto out;
        cairo_surface_t *sf = svg ? cairo_svg_surface_create(tmp, W, H)
                                  : cairo_image_surface_create(CAIRO_FORMAT_RGB24, (int)W, (int)H);
        cairo_t *cr = cairo_create(sf);
        draw(cr, W, H, f, trim, info, buf);
        cairo_status_t st = cairo_status(cr);
        cairo_destroy(cr);
        if (svg)
            cairo_surface_finish(sf);
        if (st == CAIRO_STATUS_SUCCESS)
            st = svg ? cairo_surface_status(sf) : cairo_surface_write_to_png(sf, tmp);
        cairo_surface_destroy(sf);
        if (st != CAIRO_STATUS_SUCCESS) {
            shol_io_abort(NULL, tmp);
            core_err_set(err, -1, "%s: cairo: %s", final, cairo_status_to_string(st));
            goto out;
        }
        if (shol_io_commit(NULL, tmp, final, err) < 0)
            goto out;
    }
    rc = 0;
out:
    free(buf);
    return rc;
}
