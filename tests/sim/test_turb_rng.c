/* test_turb_rng.c -- the turbulence's normal deviates (sim/turb_rng.h, the
 * ziggurat of Marsaglia and Tsang 2000): the tables close (the top layer's
 * area is v), 98.5 % of draws take the first test; over 10^7 deviates of
 * one seed the mean, variance and fourth moment are 0, 1 and 3 within 5
 * standard errors, the distribution function is within the 1 % critical
 * Kolmogorov-Smirnov distance 1.63 / sqrt(n) of the normal one (on a
 * 0.01-wide grid over [-7, 7]), the counts beyond r (the tail method) and
 * beyond 4.5 are the normal ones within 5 standard errors; the same seed
 * gives the same bits. */
#include "check.h"
#include "turb_rng.h" /* private to sim/ */

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define N 10000000L
#define LO -7.0
#define BIN 0.01
#define NBIN 1400

static double phi_cdf(double x) { return 0.5 * erfc(-x / sqrt(2.0)); }

int main(void)
{
    turb_zig z;
    turb_zig_init(&z);
    double top = z.x[255] * (1.0 - z.f[255]);
    CHECK(fabs(top / TURB_ZIG_V - 1.0) < 1e-9);
    double first = 0.0;
    for (int i = 0; i < 256; i++)
        first += z.x[i + 1] / z.x[i] / 256.0;
    CHECK(fabs(first - 0.985) < 5e-4);
    printf("ziggurat: top layer's area / v - 1 = %.1e; %.2f %% of draws accepted by the first test\n",
           top / TURB_ZIG_V - 1.0, 100.0 * first);

    uint64_t s[4];
    turb_seed(s, 1);
    long *hist = calloc(NBIN, sizeof *hist);
    long below = 0, beyond_r = 0, beyond_45 = 0;
    double m1 = 0.0, m2 = 0.0, m4 = 0.0;
    for (long k = 0; k < N; k++) {
        double x = turb_zig_normal(&z, s), x2 = x * x;
        m1 += x;
        m2 += x2;
        m4 += x2 * x2;
        beyond_r += fabs(x) > TURB_ZIG_R;
        beyond_45 += fabs(x) > 4.5;
        long b = (long)floor((x - LO) / BIN);
        if (b < 0)
            below++;
        else if (b < NBIN)
            hist[b]++;
    }
    m1 /= N;
    m2 /= N;
    m4 /= N;
    double se1 = 1.0 / sqrt((double)N), se2 = sqrt(2.0 / N), se4 = sqrt(96.0 / N);
    CHECK(fabs(m1) < 5.0 * se1);
    CHECK(fabs(m2 - 1.0) < 5.0 * se2);
    CHECK(fabs(m4 - 3.0) < 5.0 * se4);
    double D = 0.0;
    long cum = below;
    for (int b = 0; b < NBIN; b++) {
        cum += hist[b];
        D = fmax(D, fabs((double)cum / N - phi_cdf(LO + (b + 1) * BIN)));
    }
    double Dcrit = 1.63 / sqrt((double)N);
    CHECK(D < Dcrit);
    double er = 2.0 * N * phi_cdf(-TURB_ZIG_R), e45 = 2.0 * N * phi_cdf(-4.5);
    CHECK(fabs(beyond_r - er) < 5.0 * sqrt(er));
    CHECK(fabs(beyond_45 - e45) < 5.0 * sqrt(e45));
    printf("ziggurat: %ld deviates: mean %.1e, variance %.5f, fourth moment %.4f; KS distance %.2e (1 %% critical "
           "%.2e); beyond r %ld (normal %.0f), beyond 4.5 %ld (normal %.0f)\n",
           N, m1, m2, m4, D, Dcrit, beyond_r, er, beyond_45, e45);
    free(hist);

    uint64_t a[4], b[4];
    turb_seed(a, 99);
    turb_seed(b, 99);
    int same = 1;
    for (int k = 0; k < 100000; k++) {
        double x = turb_zig_normal(&z, a), y = turb_zig_normal(&z, b);
        same &= memcmp(&x, &y, sizeof x) == 0;
    }
    CHECK(same);
    return check_done("test_turb_rng");
}
