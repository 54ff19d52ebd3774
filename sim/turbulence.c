/*
 * turbulence.c -- seeded Dryden turbulence from the RANS field's k and
 * epsilon, as one frozen gust field over the helicopter.
 *
 * Model
 *  - Intensity and scale from the steady k-epsilon field. Isotropic
 *    turbulence has k = (3/2) sigma^2, so each component's standard
 *    deviation is sigma = sqrt(2k/3), taken at each sampling point from its
 *    own k. The length scale is the k-epsilon model's dissipation length
 *    L = Cmu^0.75 k^1.5 / epsilon (Cmu = 0.09; the same relation the CFD
 *    inflow uses, cfd.h), held within [length_min_m, length_max_m]: k = 0
 *    gives the floor, epsilon = 0 the cap. L is the Dryden longitudinal
 *    scale L_u = L_v = L_w = L (the isotropic choice of the Dryden form).
 *  - Dryden spectra and correlations, MIL-F-8785C (1980) para. 3.7.2,
 *    "Dryden form", and MIL-HDBK-1797 (1997) Appendix A, "Dryden form":
 *        H_u(s) = sigma sqrt(2L/(pi V)) / (1 + (L/V) s)
 *        H_v(s) = sigma sqrt(L/(pi V)) (1 + sqrt(3) (L/V) s) / (1 + (L/V) s)^2
 *    (H_w as H_v with L_w), whose correlation functions over a separation
 *    xi along the wind are (Hoblit, "Gust Loads on Aircraft", AIAA 1988,
 *    ch. 2, the Dryden correlation functions)
 *        f(xi) = exp(-xi/L)                    (u: longitudinal)
 *        g(xi) = (1 - xi/(2L)) exp(-xi/L)      (v, w: transverse),
 *    the pair that isotropy ties together, g = f + (r/2) f' (von Karman and
 *    Howarth; Pope, "Turbulent Flows", 2000, sec. 6.2).
 *  - Frozen turbulence (Taylor's hypothesis): the gust field is a pattern
 *    in space convected at the mean velocity V of the reference point
 *    (sim_turb_step's mean_vel_S_mps, e.g. the mean air at the rotor hub),
 *    its speed held at least speed_min_mps (hover in calm air: the pattern
 *    still passes; default 2 m/s, below the rotor's induced velocity, see
 *    sim.h). A point fixed in S then sees u with the time correlation
 *    f(V tau), i.e. the MIL-F-8785C filters with time constant L/V; two
 *    points a distance d apart along the wind see the same gust d/V apart,
 *    correlated f(d) (u) or g(d) (v, w) at equal times.
 *  - The field: wind axes e1 (along V), e2 (horizontal, across), e3 = e1 x e2.
 *    Along e1 the field is a sequence of rows every ds_m, each generated
 *    from the one before by the exact discretisation of the Dryden filters
 *    over the spatial step h = ds/L (u: first order, a = e^-h,
 *    b = sqrt(1 - a^2); v, w: the second-order filter in its companion form
 *    with states normalised to the identity covariance, so that
 *    z' = Phi(h) z + chol(Q(h)) n with Phi = e^-h [[1+h, h], [-h, 1-h]] and
 *    Q = I - Phi Phi^T in closed form, output (z1 + sqrt(3) z2) / 2 of unit
 *    variance). Across the wind a row holds lanes every dy_m: the white
 *    noise that drives each lane is correlated from lane to lane by the
 *    Dryden correlation across the wind (u, w: g; v: f, its longitudinal
 *    direction), drawn by the same exact recursions along the lanes. The
 *    field's correlation is then separable, f or g along the wind times g
 *    or f across it: exact along each axis, approximate (not isotropic)
 *    obliquely. Points between rows and lanes are interpolated bilinearly
 *    and divided by the interpolant's own standard deviation, so the
 *    variance stays exactly sigma^2 everywhere.
 *  - Varying L: new rows use the latest L; states normalised to unit
 *    variance stay stationary when L changes (Phi P Phi^T + Q = I for P = I).
 *
 * Assumptions and limits (sim.h repeats them for users)
 *  - One length scale and one convection velocity over the whole field, the
 *    reference point's; the intensity is local (sigma from each point's k).
 *    A field whose k and epsilon vary strongly across the disk is
 *    approximated by the reference's L.
 *  - No variation along e3 (across the wind, vertically): the rotor disk is
 *    nearly in the e1-e2 plane; points above each other see the same gust.
 *  - The field covers a square extent_m wide around the reference point.
 *    A point outside takes the nearest edge's values (the gust stays
 *    sigma-sized, its correlation is lost). When the reference drifts
 *    across the wind by more than extent_m / 4 from where the lanes were
 *    laid, the field is laid anew around it (a discontinuity, counted in
 *    sim_turb_info); when it moves downstream faster than the air the
 *    field keeps its oldest rows for extent_m / 4 of such drift.
 *  - Turbulence scales below length_min_m (2 m by default) are not
 *    represented: the rotor's blade elements are about a metre apart and
 *    a gust shorter than that averages out over a blade.
 *  - The generator is xoshiro256** (Blackman and Vigna 2018) seeded by
 *    splitmix64, normal deviates by the ziggurat method of Marsaglia and
 *    Tsang (2000) (sim/turb_rng.h): private to each sim_turb, no global
 *    state; the same seed and inputs give the same bits.
 */
#include "sim.h"
#include "turb_rng.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define TURB_MAX_LANES 4096
#define TURB_MAX_CELLS (16L * 1024 * 1024) /* rows * lanes: 384 MiB of doubles at most */

/* Exact discretisation of the first-order filter over step h: a, b. */
typedef struct turb_d1 {
    double a, b;
} turb_d1;

/* Exact discretisation of the second-order filter over step h, states
 * normalised to unit covariance: z' = phi z + [l11 0; l21 l22] n. */
typedef struct turb_d2 {
    double phi[4], l11, l21, l22;
} turb_d2;

struct sim_turb {
    sim_turb_opts o;
    uint64_t rng[4];
    turb_zig zig; /* the ziggurat's tables */

    int laid;                 /* the field exists */
    double e1[3], e2[3], e3[3];
    double conv_mps, length_m;
    double X_m;               /* convection distance since the field was laid */
    double eta0_m;            /* cross-wind position of lane (lanes - 1) / 2 */
    int lanes, cap;
    long long n_lo, n_hi;     /* rows held, ring index n mod cap */
    double *rows;             /* cap * lanes * 3: u v w, unit variance */
    double *state;            /* lanes * 5: the newest row's filter states */
    double *noise;            /* lanes * 5: a row's driving noise */
    double h_s, h_y;          /* steps ds/L, dy/L of the coefficients below */
    double coef_L;            /* the L of s1, s2, y1, y2 (0: none yet) */
    turb_d1 s1, y1;           /* drawn when a row is (filter_coefs) */
    turb_d2 s2, y2;
    double rho_s[3], rho_y[3]; /* row-to-row and lane-to-lane correlation per component */
    long relays;
    size_t ring_lo;           /* ring(n_lo), kept by sim_turb_step */
    double inv_ds, inv_dy;    /* 1 / ds_m, 1 / dy_m */
};

/* ------------------------------------------------------------- generator */
static double normal(sim_turb *t) { return turb_zig_normal(&t->zig, t->rng); }

static void seed_rng(sim_turb *t, uint64_t seed) { turb_seed(t->rng, seed); }

/* --------------------------------------------------------- discretisation */
static turb_d1 d1_make(double h)
{
    turb_d1 d = {exp(-h), sqrt(-expm1(-2.0 * h))};
    return d;
}

/* Q = I - Phi Phi^T in closed form (x = 2h):
 *   Q11 = e^-x E3(x), Q12 = e^-x x^2/2, Q22 = e^-x (2x + E3(x)),
 * E3(x) = e^x - 1 - x - x^2/2, by its series below x = 1 where the
 * difference would cancel. */
static turb_d2 d2_make(double h)
{
    turb_d2 d;
    double e = exp(-h), x = 2.0 * h, ex = e * e, q11, q22;
    d.phi[0] = e * (1.0 + h);
    d.phi[1] = e * h;
    d.phi[2] = -e * h;
    d.phi[3] = e * (1.0 - h);
    if (x < 1.0) {
        double term = x * x * x / 6.0, e3 = 0.0;
        for (int n = 3; n < 24; n++) {
            e3 += term;
            term *= x / (n + 1);
        }
        q11 = ex * e3;
        q22 = ex * (2.0 * x + e3);
    } else {
        q11 = 1.0 - ex * (1.0 + x + 0.5 * x * x);
        q22 = 1.0 + ex * (x - 1.0 - 0.5 * x * x);
    }
    double q12 = ex * 0.5 * x * x;
    d.l11 = sqrt(q11);
    d.l21 = q12 / d.l11;
    double r = q22 - d.l21 * d.l21;
    d.l22 = r > 0.0 ? sqrt(r) : 0.0;
    return d;
}

static double corr_f(double h)
{
    return exp(-h);
}

static double corr_g(double h)
{
    return (1.0 - 0.5 * h) * exp(-h);
}

/* The scale L of the steps from now on: the correlations the sampling
 * needs at once; the filters' coefficients when a row is next drawn (L
 * follows the reference point's k and epsilon and changes at nearly every
 * step, rows come every few steps). */
static void set_scales(sim_turb *t, double L)
{
    if (L == t->length_m)
        return;
    t->length_m = L;
    t->h_s = t->o.ds_m / L;
    t->h_y = t->o.dy_m / L;
    t->rho_s[0] = corr_f(t->h_s); /* u along the wind: longitudinal */
    t->rho_s[1] = corr_g(t->h_s);
    t->rho_s[2] = corr_g(t->h_s);
    t->rho_y[0] = corr_g(t->h_y); /* v across the wind: longitudinal */
    t->rho_y[1] = corr_f(t->h_y);
    t->rho_y[2] = corr_g(t->h_y);
}

/* The filters' coefficients for the current L (before drawing a row). */
static void filter_coefs(sim_turb *t)
{
    if (t->coef_L == t->length_m)
        return;
    t->coef_L = t->length_m;
    t->s1 = d1_make(t->h_s);
    t->s2 = d2_make(t->h_s);
    t->y1 = d1_make(t->h_y);
    t->y2 = d2_make(t->h_y);
}

/* --------------------------------------------------------------- the field */
/* One stream of unit-variance noise along the lanes, lane-to-lane
 * correlation f (first order) or g (second order), into out[j * 5]. */
static void lanes_f(sim_turb *t, double *out)
{
    double x = normal(t);
    for (int j = 0; j < t->lanes; j++) {
        if (j)
            x = t->y1.a * x + t->y1.b * normal(t);
        out[j * 5] = x;
    }
}

static void lanes_g(sim_turb *t, double *out)
{
    const turb_d2 *d = &t->y2;
    double z1 = normal(t), z2 = normal(t);
    for (int j = 0; j < t->lanes; j++) {
        if (j) {
            double n1 = normal(t), n2 = normal(t);
            double a = d->phi[0] * z1 + d->phi[1] * z2 + d->l11 * n1;
            double b = d->phi[2] * z1 + d->phi[3] * z2 + d->l21 * n1 + d->l22 * n2;
            z1 = a;
            z2 = b;
        }
        out[j * 5] = 0.5 * (z1 + sqrt(3.0) * z2);
    }
}

/* A row's driving noise: u's stream, v's two, w's two. */
static void draw_noise(sim_turb *t)
{
    filter_coefs(t);
    lanes_g(t, t->noise + 0);
    lanes_f(t, t->noise + 1);
    lanes_f(t, t->noise + 2);
    lanes_g(t, t->noise + 3);
    lanes_g(t, t->noise + 4);
}

/* Row n's place in the ring (n may be negative). */
static size_t ring(const sim_turb *t, long long n)
{
    long long i = n % t->cap;
    return (size_t)(i < 0 ? i + t->cap : i);
}

static void emit_row(sim_turb *t, long long n)
{
    double *row = t->rows + ring(t, n) * (size_t)t->lanes * 3;
    for (int j = 0; j < t->lanes; j++) {
        const double *z = t->state + j * 5;
        row[j * 3 + 0] = z[0];
        row[j * 3 + 1] = 0.5 * (z[1] + sqrt(3.0) * z[2]);
        row[j * 3 + 2] = 0.5 * (z[3] + sqrt(3.0) * z[4]);
    }
}

/* Start the rows at n from the stationary distribution. */
static void fresh_rows(sim_turb *t, long long n)
{
    draw_noise(t);
    memcpy(t->state, t->noise, sizeof(double) * 5 * (size_t)t->lanes);
    t->n_lo = t->n_hi = n;
    emit_row(t, n);
}

static void next_row(sim_turb *t)
{
    const turb_d1 *a = &t->s1;
    const turb_d2 *d = &t->s2;
    draw_noise(t);
    for (int j = 0; j < t->lanes; j++) {
        double *z = t->state + j * 5;
        const double *n = t->noise + j * 5;
        z[0] = a->a * z[0] + a->b * n[0];
        for (int c = 1; c < 5; c += 2) {
            double p = d->phi[0] * z[c] + d->phi[1] * z[c + 1] + d->l11 * n[c];
            double q = d->phi[2] * z[c] + d->phi[3] * z[c + 1] + d->l21 * n[c] + d->l22 * n[c + 1];
            z[c] = p;
            z[c + 1] = q;
        }
    }
    t->n_hi++;
    if (t->n_hi - t->n_lo + 1 > t->cap)
        t->n_lo++;
    emit_row(t, t->n_hi);
}

static int finite3(const double v[3])
{
    return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Wind axes from the convection direction d (unit). */
static void set_axes(sim_turb *t, const double d[3])
{
    double e2[3] = {-d[1], d[0], 0.0}; /* z_S x d: horizontal, across */
    double n = sqrt(e2[0] * e2[0] + e2[1] * e2[1]);
    if (n < 1e-6) { /* vertical wind: any horizontal axis across it */
        e2[0] = 0.0;
        e2[1] = 1.0;
        n = 1.0;
    }
    for (int i = 0; i < 3; i++) {
        t->e1[i] = d[i];
        t->e2[i] = e2[i] / n;
    }
    t->e3[0] = t->e1[1] * t->e2[2] - t->e1[2] * t->e2[1];
    t->e3[1] = t->e1[2] * t->e2[0] - t->e1[0] * t->e2[2];
    t->e3[2] = t->e1[0] * t->e2[1] - t->e1[1] * t->e2[0];
}

/* ------------------------------------------------------------------ API */
void sim_turb_opts_default(sim_turb_opts *o)
{
    memset(o, 0, sizeof *o);
    o->enabled = 1;
    o->cmu = 0.09;
    o->length_min_m = 2.0;
    o->length_max_m = 300.0;
    o->speed_min_mps = 2.0;
    o->extent_m = 40.0;
    o->ds_m = 0.25;
    o->dy_m = 0.5;
}

static int check_pos(double v, const char *name, core_err *err)
{
    if (!isfinite(v) || v <= 0.0)
        return core_err_set(err, -1, "sim_turb_opts: %s = %g: expected a finite value > 0", name, v);
    return 0;
}

sim_turb *sim_turb_create(const sim_turb_opts *o, uint64_t seed, core_err *err)
{
    if (!o) {
        core_err_set(err, -1, "sim_turb_create: no options");
        return NULL;
    }
    if (o->enabled != 0 && o->enabled != 1) {
        core_err_set(err, -1, "sim_turb_opts: enabled = %d: expected 0 or 1", o->enabled);
        return NULL;
    }
    if (check_pos(o->cmu, "cmu", err) || check_pos(o->length_min_m, "length_min_m", err) ||
        check_pos(o->length_max_m, "length_max_m", err) || check_pos(o->speed_min_mps, "speed_min_mps", err) ||
        check_pos(o->extent_m, "extent_m", err) || check_pos(o->ds_m, "ds_m", err) ||
        check_pos(o->dy_m, "dy_m", err))
        return NULL;
    if (o->cmu > 1.0) {
        core_err_set(err, -1, "sim_turb_opts: cmu = %g: expected at most 1 (the k-epsilon model's 0.09)", o->cmu);
        return NULL;
    }
    if (o->length_max_m < o->length_min_m) {
        core_err_set(err, -1, "sim_turb_opts: length_max_m = %g is below length_min_m = %g", o->length_max_m,
                     o->length_min_m);
        return NULL;
    }
    if (o->ds_m > 0.25 * o->length_min_m || o->dy_m > 0.5 * o->length_min_m) {
        core_err_set(err, -1,
                     "sim_turb_opts: ds_m = %g, dy_m = %g: expected ds_m <= length_min_m / 4 and dy_m <= "
                     "length_min_m / 2 (= %g, %g) to resolve the smallest scale",
                     o->ds_m, o->dy_m, 0.25 * o->length_min_m, 0.5 * o->length_min_m);
        return NULL;
    }
    if (o->extent_m < 4.0 * o->ds_m || o->extent_m < 4.0 * o->dy_m) {
        core_err_set(err, -1, "sim_turb_opts: extent_m = %g: expected at least 4 ds_m and 4 dy_m", o->extent_m);
        return NULL;
    }
    double lanes = ceil(o->extent_m / o->dy_m) + 1.0;
    double cap = ceil(1.25 * o->extent_m / o->ds_m) + 3.0;
    if (lanes > TURB_MAX_LANES || lanes * cap > (double)TURB_MAX_CELLS) {
        core_err_set(err, -1,
                     "sim_turb_opts: extent_m = %g with ds_m = %g, dy_m = %g needs %.0f lanes of %.0f rows: "
                     "expected at most %d lanes and %ld cells",
                     o->extent_m, o->ds_m, o->dy_m, lanes, cap, TURB_MAX_LANES, TURB_MAX_CELLS);
        return NULL;
    }
    sim_turb *t = calloc(1, sizeof *t);
    if (!t) {
        core_err_set(err, -1, "sim_turb_create: out of memory");
        return NULL;
    }
    t->o = *o;
    turb_zig_init(&t->zig);
    t->inv_ds = 1.0 / o->ds_m;
    t->inv_dy = 1.0 / o->dy_m;
    t->lanes = (int)lanes;
    t->cap = (int)cap;
    if (o->enabled) {
        t->rows = malloc(sizeof(double) * 3 * (size_t)t->lanes * (size_t)t->cap);
        t->state = malloc(sizeof(double) * 5 * (size_t)t->lanes);
        t->noise = malloc(sizeof(double) * 5 * (size_t)t->lanes);
        if (!t->rows || !t->state || !t->noise) {
            core_err_set(err, -1, "sim_turb_create: out of memory for %d lanes of %d rows", t->lanes, t->cap);
            sim_turb_destroy(t);
            return NULL;
        }
    }
    sim_turb_reset(t, seed);
    return t;
}

void sim_turb_destroy(sim_turb *t)
{
    if (!t)
        return;
    free(t->rows);
    free(t->state);
    free(t->noise);
    free(t);
}

void sim_turb_reset(sim_turb *t, uint64_t seed)
{
    seed_rng(t, seed);
    t->laid = 0;
    t->length_m = 0.0;
    t->coef_L = 0.0;
    t->conv_mps = 0.0;
    t->X_m = 0.0;
    t->relays = 0;
    double d[3] = {-1.0, 0.0, 0.0}; /* a headwind until a step says otherwise */
    set_axes(t, d);
}

double sim_turb_length_m(const sim_turb_opts *o, double k_m2ps2, double eps_m2ps3)
{
    double L = eps_m2ps3 > 0.0 ? pow(o->cmu, 0.75) * pow(k_m2ps2, 1.5) / eps_m2ps3 : o->length_max_m;
    if (!(L >= o->length_min_m)) /* also k = 0 */
        L = o->length_min_m;
    return L < o->length_max_m ? L : o->length_max_m;
}

int sim_turb_step(sim_turb *t, const double ref_S_m[3], const double mean_vel_S_mps[3], double k_m2ps2,
                  double eps_m2ps3, double dt_s, core_err *err)
{
    if (!finite3(ref_S_m) || !finite3(mean_vel_S_mps))
        return core_err_set(err, -1, "sim_turb_step: the reference point or its mean velocity is not finite");
    if (!isfinite(k_m2ps2) || k_m2ps2 < 0.0 || !isfinite(eps_m2ps3) || eps_m2ps3 < 0.0)
        return core_err_set(err, -1, "sim_turb_step: k = %g m^2/s^2, epsilon = %g m^2/s^3: expected finite values >= 0",
                            k_m2ps2, eps_m2ps3);
    if (!isfinite(dt_s) || dt_s < 0.0)
        return core_err_set(err, -1, "sim_turb_step: dt = %g s: expected a finite step >= 0", dt_s);
    if (!t->o.enabled)
        return 0;

    double V = sqrt(dot3(mean_vel_S_mps, mean_vel_S_mps));
    if (V > 1e-9) {
        double d[3] = {mean_vel_S_mps[0] / V, mean_vel_S_mps[1] / V, mean_vel_S_mps[2] / V};
        set_axes(t, d);
    }
    t->conv_mps = V > t->o.speed_min_mps ? V : t->o.speed_min_mps;
    set_scales(t, sim_turb_length_m(&t->o, k_m2ps2, eps_m2ps3));

    double E = t->o.extent_m, ds = t->o.ds_m;
    double eta = dot3(ref_S_m, t->e2);
    if (t->laid && fabs(eta - t->eta0_m) > 0.25 * E) {
        t->laid = 0; /* drifted off the lanes: lay the field anew around the reference */
        t->relays++;
    }
    if (t->laid)
        t->X_m += t->conv_mps * dt_s;
    else {
        t->X_m = 0.0;
        t->eta0_m = eta;
    }
    /* the rows the window [xi - E/2, xi + E/2] along the wind needs, row n
     * lying at frozen coordinate q = X - xi = n ds */
    double xi = dot3(ref_S_m, t->e1);
    long long need_lo = (long long)floor((t->X_m - xi - 0.5 * E) / ds);
    long long need_hi = (long long)floor((t->X_m - xi + 0.5 * E) / ds) + 1;
    if (!t->laid || need_lo > t->n_hi) {
        fresh_rows(t, need_lo);
        t->laid = 1;
    }
    while (t->n_hi < need_hi)
        next_row(t);
    t->ring_lo = ring(t, t->n_lo);
    return 0;
}

int sim_turb_sample(const sim_turb *t, const double pos_S_m[3], double k_m2ps2, double gust_S_mps[3])
{
    gust_S_mps[0] = gust_S_mps[1] = gust_S_mps[2] = 0.0;
    if (!finite3(pos_S_m) || !isfinite(k_m2ps2) || k_m2ps2 < 0.0)
        return -1;
    if (!t->o.enabled)
        return 0;
    if (!t->laid)
        return 1;

    /* along the wind: rows n0, n0 + 1, weights 1 - fs, fs */
    double fn = (t->X_m - dot3(pos_S_m, t->e1)) * t->inv_ds;
    long long n0;
    double fs;
    if (!(fn > (double)t->n_lo)) {
        n0 = t->n_lo;
        fs = 0.0;
    } else if (!(fn < (double)t->n_hi)) {
        n0 = t->n_hi - 1;
        fs = 1.0;
    } else {
        n0 = (long long)fn; /* floor: fn > n_lo, so truncation is it but below 0 */
        if ((double)n0 > fn)
            n0--;
        fs = fn - (double)n0;
    }
    /* across the wind: lanes j0, j0 + 1 */
    double fl = (dot3(pos_S_m, t->e2) - t->eta0_m) * t->inv_dy + 0.5 * (t->lanes - 1);
    int j0;
    double fy;
    if (!(fl > 0.0)) {
        j0 = 0;
        fy = 0.0;
    } else if (!(fl < (double)(t->lanes - 1))) {
        j0 = t->lanes - 2;
        fy = 1.0;
    } else {
        j0 = (int)fl; /* fl > 0 */
        fy = fl - j0;
    }
    /* row n0's slot from n_lo's (n_lo <= n0 < n_lo + cap): no division */
    size_t cap = (size_t)t->cap, i0 = t->ring_lo + (size_t)(n0 - t->n_lo);
    if (i0 >= cap)
        i0 -= cap;
    size_t stride = (size_t)t->lanes * 3, i1 = i0 + 1 == cap ? 0 : i0 + 1;
    const double *r0 = t->rows + i0 * stride + (size_t)j0 * 3;
    const double *r1 = t->rows + i1 * stride + (size_t)j0 * 3;
    double ws0 = 1.0 - fs, wy0 = 1.0 - fy, c[3], sd[3];
    for (int i = 0; i < 3; i++) {
        double vs = ws0 * ws0 + fs * fs + 2.0 * ws0 * fs * t->rho_s[i];
        double vy = wy0 * wy0 + fy * fy + 2.0 * wy0 * fy * t->rho_y[i];
        sd[i] = sqrt(vs * vy); /* the interpolant's standard deviation */
    }
    /* 1 / sd[i] from one division (the three sd lie in [1/2, 1]) */
    double inv = 1.0 / (sd[0] * sd[1] * sd[2]);
    double isd[3] = {sd[1] * sd[2] * inv, sd[0] * sd[2] * inv, sd[0] * sd[1] * inv};
    for (int i = 0; i < 3; i++)
        c[i] = (ws0 * (wy0 * r0[i] + fy * r0[3 + i]) + fs * (wy0 * r1[i] + fy * r1[3 + i])) * isd[i];
    double sigma = sqrt(2.0 * k_m2ps2 / 3.0);
    for (int i = 0; i < 3; i++)
        gust_S_mps[i] = sigma * (c[0] * t->e1[i] + c[1] * t->e2[i] + c[2] * t->e3[i]);
    return 0;
}

void sim_turb_info(const sim_turb *t, sim_turb_state *s)
{
    s->length_m = t->length_m;
    s->conv_speed_mps = t->conv_mps;
    for (int i = 0; i < 3; i++) {
        s->e1[i] = t->e1[i];
        s->e2[i] = t->e2[i];
        s->e3[i] = t->e3[i];
    }
    s->lanes = t->lanes;
    s->rows = t->cap;
    s->relays = t->relays;
}
