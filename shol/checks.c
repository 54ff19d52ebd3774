/*
 * checks.c -- physics checks of a candidate SHOL envelope.
 *
 * What a flight-test engineer looks at first on a new candidate envelope,
 * after the seed paper's section 3.4 and the NATOPS SHOLs it compares with:
 *  1. The envelope is largest near the bow: its highest speed lies within
 *     30 deg of the bow (headwinds are what a helicopter flies best in, and
 *     the superstructure's wake is then along the deck centre line).
 *  2. It is smaller in crosswinds: red 90 and green 90, where present, are
 *     each below the largest speed within 30 deg of the bow.
 *  3. Port/starboard asymmetry from the tail rotor: a main rotor turning
 *     counter-clockwise seen from above (UH-60A) pushes its tail rotor's
 *     thrust to starboard, so a green (starboard) wind drives the tail
 *     rotor toward vortex-ring/climb-like inflow and needs more pedal; such
 *     a helicopter tolerates red winds better, a clockwise rotor (SA365N)
 *     green winds (seed paper section 3.4: "the UH-60A ... red winds", the
 *     SA365N the mirror). Measured as the envelope's area on each side: the
 *     sum of v^2 over mirrored pairs of directions (red d, green d).
 *  4. The limiting criteria are named and plausible: every direction that
 *     stopped names a rejection criterion or a failed trim, and at least
 *     half of them are roll, pitch or pedal (the criteria the seed paper
 *     reports at the edges of both envelopes).
 * A check that has nothing to look at (e.g. no mirrored pair) is reported
 * as not applicable, neither passed nor failed.
 */
#include "shol.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static void add(shol_checks *c, const char *name, int applicable, int pass, const char *fmt, double a, double b)
{
    if (c->n >= SHOL_MAX_CHECKS)
        return;
    shol_check *k = &c->c[c->n++];
    snprintf(k->name, sizeof k->name, "%s", name);
    k->applicable = applicable;
    k->pass = applicable && pass;
    snprintf(k->detail, sizeof k->detail, fmt, a, b);
    if (applicable && k->pass)
        c->passed++;
    else if (applicable)
        c->failed++;
}

static double speed(const shol_dir_result *d) { return d->has_pass ? d->max_speed_mps : 0.0; }

int shol_checks_run(const shol_result *r, int ccw_from_above, shol_checks *c)
{
    memset(c, 0, sizeof *c);
    if (!r || r->n_dirs < 1)
        return -1;
    const double kt = 0.514444, near = 30.5 * M_PI / 180.0, cross = 89.5 * M_PI / 180.0;
    double vmax = -1.0, vbow = -1.0, dmax = 0.0;
    for (int i = 0; i < r->n_dirs; i++) {
        double v = speed(&r->dirs[i]), d = remainder(r->dirs[i].dir_rad, 2.0 * M_PI);
        if (v > vmax || (v == vmax && fabs(d) < fabs(dmax)))
            vmax = v, dmax = d;
        if (fabs(d) <= near)
            vbow = fmax(vbow, v);
    }
    add(c, "largest near the bow", vbow >= 0.0, fabs(dmax) <= near,
        "largest speed %.1f kt at %.0f deg (within 30 deg of the bow expected)", vmax / kt, dmax * 180.0 / M_PI);

    int ncross = 0, cross_ok = 1;
    double worst = 0.0;
    for (int i = 0; i < r->n_dirs; i++) {
        double d = remainder(r->dirs[i].dir_rad, 2.0 * M_PI);
        if (fabs(fabs(d) - M_PI / 2) < M_PI / 2 - cross + 1e-9) {
            ncross++;
            double v = speed(&r->dirs[i]);
            worst = fmax(worst, v);
            cross_ok &= v < vbow;
        }
    }
    add(c, "smaller in crosswinds", ncross > 0 && vbow >= 0.0, cross_ok,
        "red/green 90: largest %.1f kt, below the bow's %.1f kt expected", worst / kt, vbow / kt);

    double red = 0.0, green = 0.0;
    int npairs = 0;
    for (int i = 0; i < r->n_dirs; i++) {
        double d = remainder(r->dirs[i].dir_rad, 2.0 * M_PI);
        if (d >= -1e-9 || d < -M_PI + 1e-9)
            continue; /* red side only, without the bow and the stern */
        for (int j = 0; j < r->n_dirs; j++) {
            double e = remainder(r->dirs[j].dir_rad, 2.0 * M_PI);
            if (fabs(e + d) < 1e-6) {
                double vr = speed(&r->dirs[i]), vg = speed(&r->dirs[j]);
                red += vr * vr;
                green += vg * vg;
                npairs++;
            }
        }
    }
    char name[96];
    snprintf(name, sizeof name, "%s winds tolerated better", ccw_from_above ? "red (port)" : "green (starboard)");
    add(c, name, npairs > 0, ccw_from_above ? red > green : green > red,
        "area on the red side %.0f, green side %.0f (kt^2, sum over mirrored directions)", red / (kt * kt),
        green / (kt * kt));

    int nlim = 0, named = 1, edge = 0;
    for (int i = 0; i < r->n_dirs; i++) {
        int l = r->dirs[i].limit;
        if (l == SHOL_LIMIT_NONE)
            continue;
        nlim++;
        named &= shol_limit_name(l) != NULL && l >= 0 && l <= SHOL_LIMIT_TRIM;
        edge += l == SHOL_CRIT_ROLL || l == SHOL_CRIT_PITCH || l == SHOL_CRIT_PEDAL;
    }
    add(c, "limits named and plausible", nlim > 0, named && 2 * edge >= nlim,
        "%.0f of %.0f limited directions stop at roll, pitch or pedal (at least half expected)", edge, nlim);
    return 0;
}
