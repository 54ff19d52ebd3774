/* ship_motion.c -- the ship's motion in a sea state: a seeded sum of
 * sinusoids sampled from a wave spectrum, seen at the encounter frequency,
 * through closed-form response amplitude operators for heave, pitch and
 * roll.
 *
 * Model (equations numbered here; the references say where each comes from)
 *
 *  Sea state. Bales (1983), Table 1 (North Atlantic, open ocean, annual):
 *  the mean significant wave height H_s of each sea state and its most
 *  probable modal period T_p (s): 0 calm (H_s = 0: no waves), 1 0.05 m (the
 *  table's 0-1 row) with 7.5 s (the table gives no period below state 2;
 *  state 1 takes state 2's, a low swell), 2 0.3 m 7.5 s, 3 0.88 m 7.5 s,
 *  4 1.88 m 8.8 s, 5 3.25 m 9.7 s, 6 5.0 m 12.4 s.
 *
 *  Spectrum, omega_p = 2 pi / T_p:
 *   (S1) ITTC two-parameter (Bretschneider, modified Pierson-Moskowitz) in
 *        its modal-period form, ITTC (1978); DNV-RP-C205 (2010) sec. 3.5.5:
 *        S(w) = 5/16 H_s^2 w_p^4 w^-5 exp(-5/4 (w_p/w)^4),
 *        whose zeroth moment is H_s^2 / 16.
 *   (S2) JONSWAP, DNV-RP-C205 sec. 3.5.5: S_J = (1 - 0.287 ln g) S(w)
 *        g^exp(-(w - w_p)^2 / (2 s^2 w_p^2)), g = 3.3, s = 0.07 (w <= w_p),
 *        0.09 (w > w_p).
 *   Either is cut at w_max = 8 w_p (0.03 % of (S1)'s energy lies above)
 *   and scaled so that its zeroth moment m0 over 0..w_max is H_s^2 / 16
 *   exactly (4 sqrt(m0) = H_s, the table's).
 *
 *  Sampling (a stratified, equal-energy sum of sinusoids):
 *   (W1) eta(t) = sum_i a_i cos(w_e,i t + eps_i), a_i = sqrt(2 m0 / N):
 *        the spectrum's cumulative energy is split into N equal parts and
 *        w_i drawn at random inside part i (u_i = (i + U_i) / N, w_i the
 *        u_i-quantile of the energy), eps_i uniform in [0, 2 pi). The draws
 *        come from this file's splitmix64 stream of the seed (no global
 *        state). Random, incommensurate frequencies never repeat the record
 *        over any run length (equal bins of fixed centres would, after
 *        2 pi / dw), and each part's mean of a_i^2 |H(w_i)|^2 / 2 is its
 *        share of the integral of S |H|^2: the variance of every response
 *        is the spectral one on average, exactly for the elevation.
 *   (W2) Long-crested waves from wave_dir (chi, from the bow, + starboard)
 *        in deep water, k = w^2 / g; at the ship's motion centre, moving at
 *        U along its course, a wave of frequency w is met at the
 *        encounter frequency w_e = w + k U cos chi (Lewis 1989, PNA III,
 *        ch. 8; chi = 0 head seas), negative in fast following seas. eps_i is the phase
 *        at the centre's mean position at t = 0; a point xi ahead of the
 *        centre and y to starboard sees phase + k (xi cos chi + y sin chi).
 *
 *  Heave and pitch. Jensen, Mansour and Olsen (2004), sec. 2: a
 *  homogeneously loaded box of length L, draft T and breadth B* = C_B B,
 *  with beta = pi - chi (their beta = pi is head seas), Fn = U / sqrt(g L):
 *   (H1) alpha = 1 - Fn sqrt(k L) cos beta (= w_e / w),
 *        A = 2 sin(k B* alpha^2 / 2) exp(-k T alpha^2),
 *        f = sqrt((1 - k T)^2 + (A^2 / (k B* alpha^3))^2),
 *        k_e = |k cos beta|, kappa = exp(-k_e T) (Smith correction),
 *   (H2) F = kappa f sin(k_e L / 2) / (k_e L / 2),
 *        G = kappa f 24 / ((k_e L)^2 L) (sin(k_e L/2) - (k_e L/2) cos(k_e L/2)),
 *   (H3) eta = 1 / sqrt((1 - 2 k T alpha^2)^2 + (A^2 / (k B* alpha^2))^2),
 *        heave amplitude per wave amplitude eta F (m/m), pitch eta G
 *        (rad/m). F and G keep their signs (short waves turn them over).
 *   (H4) Phases (the paper gives amplitudes only; these follow from the
 *        same complex terms): the force leads the elevation at the centre
 *        by phi_f = atan2(A^2 / (k B* |alpha|^3), 1 - k T) and the response
 *        lags the force by delta = atan2(A^2 / (k B* alpha^2), 1 - 2 k T
 *        alpha^2), both in time, so for w_e < 0 their signs turn:
 *        heave = eta F cos(th + s (phi_f - delta)),
 *        pitch = -sgn(cos chi) eta G sin(th + s (phi_f - delta)),
 *        th = w_e t + eps, s = sgn(w_e); pitch nose up positive (the long
 *        wave limit is the surface slope along the ship, G -> k).
 *
 *  Roll. One degree of freedom about the centre, the ship file's natural
 *  period T_r (w_n = 2 pi / T_r) and damping ratio zeta (linear,
 *  equivalent; unchanged with speed), forced by the effective wave slope
 *  (Lloyd 1989, Seakeeping, ch. 12; Lewis 1989, PNA III sec. 3.4):
 *   (R1) r = |w_e| / w_n, H4 = 1 / sqrt((1 - r^2)^2 + (2 zeta r)^2),
 *        delta4 = atan2(2 zeta r, 1 - r^2),
 *   (R2) effective slope per wave amplitude k sin chi r_eff with
 *        r_eff = exp(-k T / 2) b(k |sin chi| B / 2) sinc(k_e L / 2):
 *        the pressure's decay to about the centre of buoyancy, the
 *        waterplane's moment-weighted mean of the slope across the beam
 *        b(x) = 3 (sin x - x cos x) / x^3 (the beam analogue of (H2)'s G),
 *        and the mean along the length (as (H2)'s F),
 *   (R3) roll = k sin chi r_eff H4 sin(th - s delta4), starboard down
 *        positive: in long beam waves the ship lies in the surface.
 *
 *  Surface (for drawing the sea, sim_ship_motion_elevation). With u the
 *  horizontal unit vector toward where the waves come from (chi from the
 *  course, + starboard) and c0 the centre's mean position at t = 0 in E,
 *  (W2) seen from the Earth is
 *   (W3) eta(p, t) = sum_i a_i cos(w_i t + eps_i + k_i u . (p - c0)),
 *        since w_e = w + k U cos chi and the centre moves at U along its
 *        course: at the centre (p = c0 + U t e0) it is (W1). Long-crested:
 *        eta depends on s = u . (p - c0) alone, so the sum is taken on
 *        samples of s at most 1/8 of the shortest wave apart, by exact
 *        phasor rotation re-anchored every 256 samples, and interpolated
 *        by Catmull-Rom cubics.
 *
 *  Pose. The centre of the motion is midships (half-way between the ends
 *  of the ship file's blocks) on the centre line at the waterline (z =
 *  deck_height_m in S). With C_ES from the Euler angles (roll, pitch,
 *  course) and e0 the course's unit vector, a point p of S is at
 *   (P1) x_E(p) = U t e0 + (0, 0, -heave) + C0 c + C_ES (p - c),
 *        C0 = C_ES(0, 0, course), c the centre in S, so that E's origin is
 *        S's mean position at t = 0; its velocity and acceleration are the
 *        exact derivatives: v = U e0 - (0, 0, heave') + C_ES (w x d),
 *        a = -(0, 0, heave'') + C_ES (w' x d + w x (w x d)), d = p - c,
 *        w = (roll', pitch' cos roll, -pitch' sin roll) in S.
 *
 * Assumptions: linear (small) motions and waves, deep water, long-crested
 * seas, heave and pitch uncoupled from roll and each other as the box of
 * Jensen et al. (2004); no surge, sway or yaw (the ship holds its course
 * and speed); roll damping linear. At sea state 0 there are no sinusoids:
 * the ship moves exactly along its course at U, level.
 *
 * References
 *  Bales, S.L. (1983), Designing ships to the natural environment, Naval
 *   Engineers Journal 95(2), 31-40 (Table 1, open-ocean annual sea states).
 *  DNV-RP-C205 (2010), Environmental conditions and environmental loads,
 *   sec. 3.5.5 (Pierson-Moskowitz and JONSWAP spectra).
 *  ITTC (1978), Report of the Seakeeping Committee, 15th ITTC.
 *  Jensen, J.J., Mansour, A.E., Olsen, A.S. (2004), Estimation of ship
 *   motions using closed-form expressions, Ocean Engineering 31, 61-85.
 *  Lewis, E.V. (ed., 1989), Principles of Naval Architecture, vol. III
 *   (Motions in Waves), SNAME.
 *  Lloyd, A.R.J.M. (1989), Seakeeping: Ship Behaviour in Rough Weather,
 *   Ellis Horwood.
 */
#include "sim.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define G_MPS2 CORE_G_MPS2
#define JONSWAP_GAMMA 3.3
#define OMEGA_MAX_OVER_P 8.0 /* the spectrum's cut-off, in w_p */
#define CDF_CELLS 8192       /* the quantile table's cells over 0..w_max */
#define MAX_SPEED_MPS 30.0   /* 58 kt */

/* Bales (1983) Table 1, North Atlantic: mean H_s (m), most probable modal
 * period (s); state 1: see the file's opening. */
static const double bales_hs_m[SIM_SEA_MAX_STATE + 1] = {0.0, 0.05, 0.3, 0.88, 1.88, 3.25, 5.0};
static const double bales_tp_s[SIM_SEA_MAX_STATE + 1] = {0.0, 7.5, 7.5, 7.5, 8.8, 9.7, 12.4};

/* One sinusoid of the sum: the wave at the centre, a cos(th), th = w_e t
 * + eps, and each motion as c cos th + s sin th (a included). */
typedef struct wave {
    double omega, omega_e, eps, amp; /* wave and encounter frequencies */
    double c[3], s[3]; /* heave (m), pitch, roll (rad) */
} wave;

enum { HEAVE = 0, PITCH = 1, ROLL = 2 };

/* The waves' phasors (cos th, sin th) at one step time k h, advanced step
 * by step by the exact rotation (cos w_e h, sin w_e h) and re-anchored by
 * the direct cos and sin every PHASOR_ANCHOR steps: the phasors of step k
 * are those of the anchor floor(k / PHASOR_ANCHOR) PHASOR_ANCHOR rotated
 * the same number of times whichever steps were asked before, so the
 * motion stays a pure function of t. A rotation rounds each component to
 * a few ulps: after at most PHASOR_ANCHOR - 1 rotations each phasor is
 * within a few 1e-14 of the direct one (test_ship_motion checks the bound
 * on every motion). */
#define PHASOR_ANCHOR 256

typedef struct phasors {
    double h_s;      /* the step */
    long long k;     /* the step the phasors hold (k_none: none) */
    double *c, *s;   /* per wave, at step k */
    /* the phasors the walk held before k (step pk, k_none: none): a state
     * or spot asked at step k - 1 after a frame at k (the gear's deck
     * velocity looks a little ahead) costs no walk from the anchor. The
     * walk writes each step into these and swaps: no copy. */
    long long pk;
    double *pc, *ps;
    double *rc, *rs; /* per wave, cos and sin of w_e h */
    /* the sums of the last step evaluated (a frame, then the state and the
     * spot at the same step time): step xk (k_none: none), with rates if
     * xrates */
    long long xk;
    int xrates;
    double x[3][3], elev;
} phasors;

static const long long k_none = -(1LL << 62);

struct sim_ship_motion {
    sim_sea sea;
    phasors *ph; /* NULL: no step set (every time by the direct sum) */
    double hs_m, tp_s, omega_p, omega_max, scale; /* scale: m0 normalisation of the shape */
    int n;
    wave *w;
    int has_rao; /* the ship's seakeeping keys are there */
    double L_m, B_m, T_m, cb, U_mps;
    double omega_n, zeta;
    core_vec3 centre_S;
    core_vec3 e0;    /* the course's unit vector in E */
    core_vec3 c0_E;  /* C0 c */
};

/* ------------------------------------------------------------ generator */
/* splitmix64 (Steele, Lea, Flood 2014): a 64-bit state per motion. */
static uint64_t rng_next(uint64_t *s)
{
    uint64_t z = (*s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/* Uniform in [0, 1). */
static double rng_uniform(uint64_t *s)
{
    return (double)(rng_next(s) >> 11) * 0x1.0p-53;
}

/* ----------------------------------------------------------- small maths */
static double sinc(double x)
{
    return fabs(x) < 1e-4 ? 1.0 - x * x / 6.0 : sin(x) / x;
}

/* 3 (sin x - x cos x) / x^3, 1 at 0: the moment-weighted mean slope. */
static double slope_mean(double x)
{
    double x2 = x * x;
    return fabs(x) < 1e-2 ? 1.0 - x2 / 10.0 + x2 * x2 / 280.0 : 3.0 * (sin(x) - x * cos(x)) / (x2 * x);
}

/* ------------------------------------------------------------- spectrum */
/* The unscaled shape (S1) or (S2) at w. */
static double spectrum_shape(const sim_ship_motion *m, double w)
{
    if (!(w > 0.0) || m->hs_m <= 0.0)
        return 0.0;
    double x = m->omega_p / w;
    if (x > 10.0)
        return 0.0; /* exp(-5/4 x^4) underflows */
    double x4 = x * x * x * x;
    double s = 5.0 / 16.0 * m->hs_m * m->hs_m * x4 / w * exp(-1.25 * x4);
    if (m->sea.spectrum == SIM_SPECTRUM_JONSWAP) {
        double sig = w <= m->omega_p ? 0.07 : 0.09;
        double d = (w - m->omega_p) / (sig * m->omega_p);
        s *= (1.0 - 0.287 * log(JONSWAP_GAMMA)) * pow(JONSWAP_GAMMA, exp(-0.5 * d * d));
    }
    return s;
}

double sim_ship_motion_spectrum(const sim_ship_motion *m, double omega_radps)
{
    if (!m || !(omega_radps > 0.0) || omega_radps > m->omega_max)
        return 0.0;
    return m->scale * spectrum_shape(m, omega_radps);
}

/* ----------------------------------------------------------------- RAOs */
/* Per unit wave amplitude at w: each motion's (c, s) of c cos th + s sin th
 * ((H1)-(H4), (R1)-(R3)), and w_e. */
static void rao_terms(const sim_ship_motion *m, double w, double c[3], double s[3], double *omega_e)
{
    const double chi = m->sea.wave_dir_rad, U = m->U_mps, L = m->L_m, B = m->B_m, T = m->T_m;
    double k = w * w / G_MPS2;
    double alpha = 1.0 + U * w * cos(chi) / G_MPS2; /* (H1), cos beta = -cos chi */
    double we = alpha * w;
    *omega_e = we;
    double sgn_e = we < 0.0 ? -1.0 : 1.0;
    double aa = fabs(alpha);

    /* (H1)-(H3) without dividing by alpha: A / (k B* alpha^2) = sinc(q) e^(-k T alpha^2) */
    double Bs = m->cb * B;
    double q = 0.5 * k * Bs * alpha * alpha;
    double R = sinc(q) * exp(-k * T * alpha * alpha);
    double d2 = R * R * k * Bs * alpha * alpha; /* A^2 / (k B* alpha^2) */
    double d3 = R * R * k * Bs * aa;            /* A^2 / (k B* |alpha|^3) */
    double f = hypot(1.0 - k * T, d3);
    double phi_f = atan2(d3, 1.0 - k * T);
    double ke = fabs(k * cos(chi));
    double xl = 0.5 * ke * L;
    double kappa = exp(-ke * T);
    double F = kappa * f * sinc(xl);
    double Gp = kappa * f * ke * slope_mean(xl);
    double re = 1.0 - 2.0 * k * T * alpha * alpha;
    double eta = 1.0 / hypot(re, d2);
    double delta = atan2(d2, re);
    double ph = sgn_e * (phi_f - delta);
    double sg = cos(chi) < 0.0 ? -1.0 : 1.0;
    c[HEAVE] = eta * F * cos(ph);
    s[HEAVE] = -eta * F * sin(ph);
    c[PITCH] = -sg * eta * Gp * sin(ph);
    s[PITCH] = -sg * eta * Gp * cos(ph);

    /* (R1)-(R3) */
    double r = fabs(we) / m->omega_n;
    double H4 = 1.0 / hypot(1.0 - r * r, 2.0 * m->zeta * r);
    double ph4 = -sgn_e * atan2(2.0 * m->zeta * r, 1.0 - r * r);
    double reff = exp(-0.5 * k * T) * slope_mean(0.5 * k * fabs(sin(chi)) * B) * sinc(xl);
    double A4 = k * sin(chi) * reff * H4;
    c[ROLL] = A4 * sin(ph4);
    s[ROLL] = A4 * cos(ph4);
}

int sim_ship_motion_rao(const sim_ship_motion *m, double omega_radps, double *heave_mpm, double *pitch_radpm,
                        double *roll_radpm)
{
    if (!m || !m->has_rao || !(omega_radps > 0.0) || !isfinite(omega_radps))
        return -1;
    double c[3], s[3], we;
    rao_terms(m, omega_radps, c, s, &we);
    if (heave_mpm)
        *heave_mpm = hypot(c[HEAVE], s[HEAVE]);
    if (pitch_radpm)
        *pitch_radpm = hypot(c[PITCH], s[PITCH]);
    if (roll_radpm)
        *roll_radpm = hypot(c[ROLL], s[ROLL]);
    return 0;
}

/* ------------------------------------------------------------- creation */
void sim_sea_default(sim_sea *sea)
{
    memset(sea, 0, sizeof *sea);
    sea->spectrum = SIM_SPECTRUM_ITTC;
}

int sim_sea_state_table(int state, double *hs_m, double *tp_s, core_err *err)
{
    if (state < 0 || state > SIM_SEA_MAX_STATE)
        return core_err_set(err, -1, "sea state %d: expected 0 to %d", state, SIM_SEA_MAX_STATE);
    if (hs_m)
        *hs_m = bales_hs_m[state];
    if (tp_s)
        *tp_s = bales_tp_s[state];
    return 0;
}

static int check_sea(const sim_sea *sea, core_err *err)
{
    if (sea->state < 0 || sea->state > SIM_SEA_MAX_STATE)
        return core_err_set(err, -1, "sea state = %d: expected 0 to %d", sea->state, SIM_SEA_MAX_STATE);
    if (!isfinite(sea->ship_speed_mps) || sea->ship_speed_mps < 0.0 || sea->ship_speed_mps > MAX_SPEED_MPS)
        return core_err_set(err, -1, "sea ship_speed_mps = %g: expected 0 to %g m/s (the ship's speed, not negative)",
                            sea->ship_speed_mps, MAX_SPEED_MPS);
    if (!isfinite(sea->wave_dir_rad))
        return core_err_set(err, -1, "sea wave_dir_rad = %g: expected a finite angle", sea->wave_dir_rad);
    if (!isfinite(sea->course_rad))
        return core_err_set(err, -1, "sea course_rad = %g: expected a finite angle", sea->course_rad);
    if (sea->spectrum != SIM_SPECTRUM_ITTC && sea->spectrum != SIM_SPECTRUM_JONSWAP)
        return core_err_set(err, -1, "sea spectrum = %d: expected ITTC (%d) or JONSWAP (%d)", (int)sea->spectrum,
                            SIM_SPECTRUM_ITTC, SIM_SPECTRUM_JONSWAP);
    if (sea->n_waves < 0 || sea->n_waves > SIM_SEA_MAX_WAVES)
        return core_err_set(err, -1, "sea n_waves = %d: expected 0 (the default, %d) to %d", sea->n_waves,
                            SIM_SEA_DEFAULT_WAVES, SIM_SEA_MAX_WAVES);
    return 0;
}

/* The ship's dimensions and seakeeping data; need: a sea state above 0. */
static int take_ship(sim_ship_motion *m, const core_ship *ship, int need, core_err *err)
{
    if (!(ship->length_m > 0.0) || !(ship->beam_m > 0.0))
        return core_err_set(err, -1, "ship %s: length_m = %g, beam_m = %g: expected positive", ship->name,
                            ship->length_m, ship->beam_m);
    if (ship->nblocks < 1)
        return core_err_set(err, -1, "ship %s: no [block]: the motion centre is midships between the blocks' ends",
                            ship->name);
    double x0 = 1e300, x1 = -1e300;
    for (int i = 0; i < ship->nblocks; i++) {
        x0 = fmin(x0, ship->blocks[i].x0_m);
        x1 = fmax(x1, ship->blocks[i].x1_m);
    }
    m->centre_S = core_vec3_make(0.5 * (x0 + x1), 0.0, ship->deck_height_m);
    m->L_m = ship->length_m;
    m->B_m = ship->beam_m;
    m->T_m = ship->hull_draft_m > 0.0 ? ship->hull_draft_m : ship->draft_m;
    m->cb = ship->block_coefficient;
    m->omega_n = ship->roll_period_s > 0.0 ? 2.0 * CORE_PI / ship->roll_period_s : 0.0;
    m->zeta = ship->roll_damping_ratio;
    const char *missing = !(m->cb > 0.0)                        ? "block_coefficient"
                          : !(ship->roll_period_s > 0.0)        ? "roll_period_s"
                          : !(ship->roll_damping_ratio > 0.0)   ? "roll_damping_ratio"
                          : !(m->T_m > 0.0)                     ? "draft_m"
                                                                : NULL;
    m->has_rao = missing == NULL;
    if (need && missing)
        return core_err_set(err, -1,
                            "ship %s: [ship] %s missing: the ship's motion at sea state %d needs its seakeeping "
                            "keys block_coefficient, roll_period_s and roll_damping_ratio (docs/ship-format.md)",
                            ship->name, missing, m->sea.state);
    return 0;
}

/* The table of the cumulative energy over 0..w_max (CDF_CELLS + 1 points),
 * its total setting the scale; then the N sinusoids (W1). */
static int sample_waves(sim_ship_motion *m, uint64_t seed, core_err *err)
{
    double *cdf = malloc((CDF_CELLS + 1) * sizeof *cdf);
    m->w = calloc((size_t)m->n, sizeof *m->w);
    if (!cdf || !m->w) {
        free(cdf);
        return core_err_set(err, -1, "ship motion: out of memory for %d waves", m->n);
    }
    double dw = m->omega_max / CDF_CELLS, prev = 0.0;
    cdf[0] = 0.0;
    for (int j = 1; j <= CDF_CELLS; j++) {
        double s = spectrum_shape(m, j * dw);
        cdf[j] = cdf[j - 1] + 0.5 * (prev + s) * dw;
        prev = s;
    }
    double total = cdf[CDF_CELLS];
    double m0 = m->hs_m * m->hs_m / 16.0;
    m->scale = m0 / total;
    double amp = sqrt(2.0 * m0 / m->n);
    uint64_t rs = seed;
    int lo = 0;
    for (int i = 0; i < m->n; i++) {
        double u = (i + rng_uniform(&rs)) / m->n * total;
        while (lo < CDF_CELLS - 1 && cdf[lo + 1] < u)
            lo++; /* u grows with i: the search goes on from the last cell */
        double span = cdf[lo + 1] - cdf[lo];
        double frac = span > 0.0 ? (u - cdf[lo]) / span : 0.5;
        double w = (lo + fmin(fmax(frac, 0.0), 1.0)) * dw;
        if (w <= 0.0)
            w = 0.5 * dw;
        wave *wv = &m->w[i];
        wv->eps = 2.0 * CORE_PI * rng_uniform(&rs);
        wv->amp = amp;
        wv->omega = w;
        double c[3], s[3];
        rao_terms(m, w, c, s, &wv->omega_e);
        for (int d = 0; d < 3; d++) {
            wv->c[d] = amp * c[d];
            wv->s[d] = amp * s[d];
        }
    }
    free(cdf);
    return 0;
}

sim_ship_motion *sim_ship_motion_create(const core_ship *ship, const sim_sea *sea, uint64_t seed, core_err *err)
{
    if (!ship || !sea) {
        core_err_set(err, -1, "ship motion: %s is NULL", ship ? "the sea" : "the ship");
        return NULL;
    }
    if (check_sea(sea, err))
        return NULL;
    sim_ship_motion *m = calloc(1, sizeof *m);
    if (!m) {
        core_err_set(err, -1, "ship motion: out of memory");
        return NULL;
    }
    m->sea = *sea;
    m->U_mps = sea->ship_speed_mps;
    m->hs_m = bales_hs_m[sea->state];
    m->tp_s = bales_tp_s[sea->state];
    if (take_ship(m, ship, sea->state > 0, err)) {
        free(m);
        return NULL;
    }
    m->e0 = core_vec3_make(cos(sea->course_rad), sin(sea->course_rad), 0.0);
    core_euler e_course = {0.0, 0.0, sea->course_rad};
    m->c0_E = core_mat3_mul_vec(core_mat3_from_euler(e_course), m->centre_S);
    if (sea->state > 0) {
        m->omega_p = 2.0 * CORE_PI / m->tp_s;
        m->omega_max = OMEGA_MAX_OVER_P * m->omega_p;
        m->n = sea->n_waves > 0 ? sea->n_waves : SIM_SEA_DEFAULT_WAVES;
        if (sample_waves(m, seed, err)) {
            sim_ship_motion_destroy(m);
            return NULL;
        }
    }
    return m;
}

static void phasors_free(phasors *p)
{
    if (!p)
        return;
    free(p->c);
    free(p->s);
    free(p->pc);
    free(p->ps);
    free(p->rc);
    free(p->rs);
    free(p);
}

void sim_ship_motion_destroy(sim_ship_motion *m)
{
    if (!m)
        return;
    phasors_free(m->ph);
    free(m->w);
    free(m);
}

int sim_ship_motion_set_step(sim_ship_motion *m, double step_s, core_err *err)
{
    if (!m)
        return core_err_set(err, -1, "ship motion: NULL");
    if (!(step_s >= 0.0) || !isfinite(step_s))
        return core_err_set(err, -1, "ship motion step = %g s: expected 0 (none) or a finite step > 0", step_s);
    phasors_free(m->ph);
    m->ph = NULL;
    if (step_s == 0.0 || m->n == 0)
        return 0;
    phasors *p = calloc(1, sizeof *p);
    size_t n = (size_t)m->n;
    if (!p || !(p->c = malloc(n * sizeof(double))) || !(p->s = malloc(n * sizeof(double))) ||
        !(p->pc = malloc(n * sizeof(double))) || !(p->ps = malloc(n * sizeof(double))) || !(p->rc = malloc(n * sizeof(double))) || !(p->rs = malloc(n * sizeof(double)))) {
        phasors_free(p);
        return core_err_set(err, -1, "ship motion: out of memory for the phasors of %d waves", m->n);
    }
    p->h_s = step_s;
    p->k = k_none;
    p->pk = k_none;
    p->xk = k_none;
    for (int i = 0; i < m->n; i++) {
        p->rc[i] = cos(m->w[i].omega_e * step_s);
        p->rs[i] = sin(m->w[i].omega_e * step_s);
    }
    m->ph = p;
    return 0;
}

void sim_ship_motion_get_info(const sim_ship_motion *m, sim_ship_motion_info *info)
{
    memset(info, 0, sizeof *info);
    if (!m)
        return;
    info->hs_m = m->hs_m;
    info->tp_s = m->tp_s;
    info->n_waves = m->n;
    info->omega_max_radps = m->omega_max;
    info->centre_S_m[0] = m->centre_S.x;
    info->centre_S_m[1] = m->centre_S.y;
    info->centre_S_m[2] = m->centre_S.z;
    info->roll_period_s = m->omega_n > 0.0 ? 2.0 * CORE_PI / m->omega_n : 0.0;
    info->roll_damping_ratio = m->zeta;
}

/* ----------------------------------------------------------- evaluation */
/* A wave's phase at t: the one expression the direct sum and the anchors use. */
static double wave_phase(const wave *w, double t) { return w->omega_e * t + w->eps; }

/* The step k of t when t is exactly the step time (double)k h, as a loop
 * computes it; 0 when it is not (or no step is set). */
static int step_of(const sim_ship_motion *m, double t, long long *k)
{
    if (!m->ph)
        return 0;
    double h = m->ph->h_s, kn = nearbyint(t / h);
    if (!(fabs(kn) < 1e15) || kn * h != t)
        return 0;
    *k = (long long)kn;
    return 1;
}

/* The phasors at step k (m's cache; see struct phasors). */
static void phasors_at(const sim_ship_motion *m, long long k)
{
    phasors *p = m->ph;
    if (p->k == k)
        return;
    if (p->pk == k) { /* one step back: the walk's previous phasors */
        double *t = p->c;
        p->c = p->pc;
        p->pc = t;
        t = p->s;
        p->s = p->ps;
        p->ps = t;
        p->pk = p->k;
        p->k = k;
        return;
    }
    long long r = k % PHASOR_ANCHOR;
    long long k0 = k - (r < 0 ? r + PHASOR_ANCHOR : r);
    if (!(p->k >= k0 && p->k < k)) { /* anchor: the direct phasors at k0 */
        long long was = p->k;
        if (was == k0 - 1 && k == k0) { /* the step before stays to hand */
            double *t = p->pc;
            p->pc = p->c;
            p->c = t;
            t = p->ps;
            p->ps = p->s;
            p->s = t;
        }
        double t0 = (double)k0 * p->h_s;
        for (int i = 0; i < m->n; i++) {
            double th = wave_phase(&m->w[i], t0);
            p->c[i] = cos(th);
            p->s[i] = sin(th);
        }
        p->k = k0;
        p->pk = (was == k0 - 1 && k == k0) ? was : k_none;
    }
    const double *restrict rc = p->rc, *restrict rs = p->rs;
    for (; p->k < k; p->k++) {
        const double *restrict c = p->c, *restrict s = p->s;
        double *restrict nc = p->pc, *restrict ns = p->ps;
        for (int i = 0; i < m->n; i++) {
            nc[i] = c[i] * rc[i] - s[i] * rs[i];
            ns[i] = s[i] * rc[i] + c[i] * rs[i];
        }
        p->pc = p->c;
        p->ps = p->s;
        p->c = nc;
        p->s = ns;
        p->pk = p->k;
    }
}

/* The motions at the centre at t: x[d][0..2] value, rate, acceleration
 * (rates 0: the values alone, the rest 0; the values' bits are the same);
 * the elevation there (rates 0: 0). The sums run in locals: the wave
 * table cannot alias them. */
static void eval_motions(const sim_ship_motion *m, double t, int rates, double x[3][3], double *elev)
{
    double x0[3] = {0.0, 0.0, 0.0}, x1[3] = {0.0, 0.0, 0.0}, x2[3] = {0.0, 0.0, 0.0}, e = 0.0;
    long long k;
    const double *pc = NULL, *ps = NULL;
    if (m->n > 0 && step_of(m, t, &k)) {
        phasors *p = m->ph;
        if (p->xk == k && p->xrates >= rates) { /* the same sums again */
            memcpy(x, p->x, sizeof p->x);
            if (!rates)
                for (int d = 0; d < 3; d++)
                    x[d][1] = x[d][2] = 0.0;
            *elev = rates ? p->elev : 0.0;
            return;
        }
        phasors_at(m, k);
        pc = p->c;
        ps = p->s;
    }
    for (int i = 0; i < m->n; i++) {
        const wave *w = &m->w[i];
        double ct, st, we = w->omega_e;
        if (pc) {
            ct = pc[i];
            st = ps[i];
        } else {
            double th = wave_phase(w, t);
            ct = cos(th);
            st = sin(th);
        }
        if (!rates) {
            for (int d = 0; d < 3; d++)
                x0[d] += w->c[d] * ct + w->s[d] * st;
            continue;
        }
        e += w->amp * ct;
        for (int d = 0; d < 3; d++) {
            double v = w->c[d] * ct + w->s[d] * st;
            x0[d] += v;
            x1[d] += we * (w->s[d] * ct - w->c[d] * st);
            x2[d] -= we * we * v;
        }
    }
    for (int d = 0; d < 3; d++) {
        x[d][0] = x0[d];
        x[d][1] = x1[d];
        x[d][2] = x2[d];
    }
    *elev = e;
    if (pc) {
        phasors *p = m->ph;
        memcpy(p->x, x, sizeof p->x);
        p->elev = e;
        p->xk = k;
        p->xrates = rates;
    }
}

/* (P1) for the point p at t, from the motions x. */
static void point_from(const sim_ship_motion *m, double t, const double x[3][3], core_vec3 p, core_mat3 *C_out,
                       sim_ship_point *out)
{
    double phi = x[ROLL][0], dphi = x[ROLL][1], ddphi = x[ROLL][2];
    double dth = x[PITCH][1], ddth = x[PITCH][2];
    core_euler att = {phi, x[PITCH][0], m->sea.course_rad};
    core_mat3 C = core_mat3_from_euler(att);
    double cf = cos(phi), sf = sin(phi);
    core_vec3 w = core_vec3_make(dphi, dth * cf, -dth * sf);
    core_vec3 wd = core_vec3_make(ddphi, ddth * cf - dth * dphi * sf, -ddth * sf - dth * dphi * cf);
    core_vec3 d = core_vec3_sub(p, m->centre_S);
    core_vec3 pos = core_vec3_add(m->c0_E, core_mat3_mul_vec(C, d));
    pos = core_vec3_add(pos, core_vec3_make(0.0, 0.0, -x[HEAVE][0]));
    out->pos_E_m = core_vec3_add(core_vec3_scale(m->e0, m->U_mps * t), pos);
    core_vec3 wxd = core_vec3_cross(w, d);
    out->vel_E_mps = core_vec3_add(core_vec3_scale(m->e0, m->U_mps),
                                   core_vec3_add(core_vec3_make(0.0, 0.0, -x[HEAVE][1]), core_mat3_mul_vec(C, wxd)));
    core_vec3 acc_S = core_vec3_add(core_vec3_cross(wd, d), core_vec3_cross(w, wxd));
    out->acc_E_mps2 = core_vec3_add(core_vec3_make(0.0, 0.0, -x[HEAVE][2]), core_mat3_mul_vec(C, acc_S));
    if (C_out)
        *C_out = C;
}

int sim_ship_motion_point(const sim_ship_motion *m, double t_s, core_vec3 p_S_m, sim_ship_point *out)
{
    if (!m || !out || !isfinite(t_s))
        return -1;
    double x[3][3], elev;
    eval_motions(m, t_s, 1, x, &elev);
    point_from(m, t_s, x, p_S_m, NULL, out);
    return 0;
}

int sim_ship_motion_at(const sim_ship_motion *m, double t_s, sim_ship_state *out)
{
    if (!m || !out || !isfinite(t_s))
        return -1;
    double x[3][3], elev;
    eval_motions(m, t_s, 1, x, &elev);
    sim_ship_point o;
    point_from(m, t_s, x, core_vec3_make(0.0, 0.0, 0.0), NULL, &o);
    memset(out, 0, sizeof *out);
    out->t_s = t_s;
    out->att.phi_rad = x[ROLL][0];
    out->att.theta_rad = x[PITCH][0];
    out->att.psi_rad = m->sea.course_rad;
    out->pose.pos_E_m = o.pos_E_m;
    out->pose.q_EF = core_quat_from_euler(out->att);
    out->vel_E_mps = o.vel_E_mps;
    double cf = cos(x[ROLL][0]), sf = sin(x[ROLL][0]);
    out->omega_S_radps = core_vec3_make(x[ROLL][1], x[PITCH][1] * cf, -x[PITCH][1] * sf);
    out->heave_m = x[HEAVE][0];
    out->heave_rate_mps = x[HEAVE][1];
    out->wave_elev_m = elev;
    return 0;
}

int sim_ship_motion_frame_fn(void *user, double t_s, sim_ship_frame *out)
{
    const sim_ship_motion *m = user;
    if (!m || !out || !isfinite(t_s))
        return -1;
    double x[3][3], elev;
    eval_motions(m, t_s, 0, x, &elev); /* the pose alone: no rates */
    sim_ship_point o;
    core_mat3 C;
    point_from(m, t_s, x, core_vec3_make(0.0, 0.0, 0.0), &C, &o);
    out->origin_E_m[0] = o.pos_E_m.x;
    out->origin_E_m[1] = o.pos_E_m.y;
    out->origin_E_m[2] = o.pos_E_m.z;
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            out->C_ES[3 * r + c] = C.m[r][c];
    out->mean_vel_E_mps[0] = m->U_mps * m->e0.x;
    out->mean_vel_E_mps[1] = m->U_mps * m->e0.y;
    out->mean_vel_E_mps[2] = 0.0;
    return 0;
}

/* ----------------------------------------------------- the sea surface */
#define ELEV_ANCHOR 256 /* samples between direct cos/sin */

int sim_ship_motion_elevation(void *motion, double t_s, int n, const double *x_E_m, const double *y_E_m,
                              double *eta_m)
{
    const sim_ship_motion *m = motion;
    if (!m || n < 0 || (n > 0 && (!x_E_m || !y_E_m || !eta_m)) || !isfinite(t_s))
        return -1;
    if (m->n == 0) {
        for (int j = 0; j < n; j++)
            eta_m[j] = 0.0;
        return 0;
    }
    /* (W3): u toward the waves' source, s along it from c0 */
    double a = m->sea.course_rad + m->sea.wave_dir_rad;
    double ux = cos(a), uy = sin(a);
    double smin = INFINITY, smax = -INFINITY;
    for (int j = 0; j < n; j++) {
        double sj = ux * (x_E_m[j] - m->c0_E.x) + uy * (y_E_m[j] - m->c0_E.y);
        if (!isfinite(sj))
            return -1;
        smin = fmin(smin, sj);
        smax = fmax(smax, sj);
    }
    if (n == 0)
        return 0;
    double kmax = 0.0;
    for (int i = 0; i < m->n; i++)
        kmax = fmax(kmax, m->w[i].omega * m->w[i].omega / G_MPS2);
    double ds = 2.0 * CORE_PI / kmax / 8.0;
    /* samples from smin - ds to smax + 2 ds (the cubic's neighbours) */
    double s0 = smin - ds;
    long ns = (long)ceil((smax - smin) / ds) + 4;
    if (ns > 50000000L)
        return -1;
    double *f = calloc((size_t)ns, sizeof *f);
    double *zr = malloc((size_t)m->n * 4 * sizeof *zr);
    if (!f || !zr) {
        free(f);
        free(zr);
        return -1;
    }
    double *zi = zr + m->n, *rr = zi + m->n, *ri = rr + m->n;
    for (int i = 0; i < m->n; i++) {
        double k = m->w[i].omega * m->w[i].omega / G_MPS2;
        rr[i] = cos(k * ds);
        ri[i] = sin(k * ds);
    }
    double amp = m->w[0].amp; /* equal for every wave (W1) */
    for (long j = 0; j < ns; j++) {
        if (j % ELEV_ANCHOR == 0)
            for (int i = 0; i < m->n; i++) {
                const wave *w = &m->w[i];
                double th = w->omega * t_s + w->eps + w->omega * w->omega / G_MPS2 * (s0 + j * ds);
                zr[i] = cos(th);
                zi[i] = sin(th);
            }
        double sum = 0.0;
        for (int i = 0; i < m->n; i++) {
            sum += zr[i];
            double r = zr[i] * rr[i] - zi[i] * ri[i];
            zi[i] = zr[i] * ri[i] + zi[i] * rr[i];
            zr[i] = r;
        }
        f[j] = amp * sum;
    }
    for (int j = 0; j < n; j++) {
        double sj = ux * (x_E_m[j] - m->c0_E.x) + uy * (y_E_m[j] - m->c0_E.y);
        double q = (sj - s0) / ds;
        long i1 = (long)floor(q);
        if (i1 < 1)
            i1 = 1;
        if (i1 > ns - 3)
            i1 = ns - 3;
        double u = q - i1, p0 = f[i1 - 1], p1 = f[i1], p2 = f[i1 + 1], p3 = f[i1 + 2];
        eta_m[j] = p1 + 0.5 * u * (p2 - p0 + u * (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3 + u * (3.0 * (p1 - p2) + p3 - p0)));
    }
    free(f);
    free(zr);
    return 0;
}
