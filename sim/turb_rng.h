/* turb_rng.h -- the turbulence's random numbers (private to sim/; tests
 * include it to check the distribution).
 *
 *  - xoshiro256** (Blackman and Vigna, "Scrambled linear pseudorandom
 *    number generators", ACM TOMS 47(4), 2021), seeded by splitmix64.
 *  - Standard normal deviates by the ziggurat method of Marsaglia and Tsang
 *    ("The ziggurat method for generating random variables", J. Stat.
 *    Software 5(8), 2000) with 256 layers of equal area v under the
 *    density's unnormalised form f(x) = exp(-x^2/2): the base layer
 *    (i = 0) is [0, v / f(r)] x [0, f(r)] with the tail beyond r, layer i
 *    (1..255) is [0, x_i] x [f(x_i), f(x_(i+1))], x_1 = r, x_(i+1) =
 *    sqrt(-2 ln(v / x_i + f(x_i))), x_256 = 0; r = 3.6541528853610088 and
 *    v = 0.00492867323399 close the recursion (x_255 (1 - f(x_255)) = v
 *    within 1e-9, test_turb_rng). One 64-bit draw gives the layer (bits
 *    0-7), the sign (bit 8) and the abscissa (bits 11-63); x < x_(i+1) is
 *    accepted at once (98.5 % of draws); otherwise the wedge is tested
 *    against f, or the
 *    tail drawn by Marsaglia's (1964) method, as the paper does.
 * The state is the caller's: no global state, the same seed gives the
 * same bits. */
#ifndef DISIM_SIM_TURB_RNG_H
#define DISIM_SIM_TURB_RNG_H

#include <math.h>
#include <stdint.h>

#define TURB_ZIG_R 3.6541528853610088
#define TURB_ZIG_V 0.00492867323399

typedef struct turb_zig {
    double x[257]; /* x[0] = v / f(r), x[1] = r, ..., x[256] = 0 */
    double f[257]; /* f(x[i]) */
} turb_zig;

static inline uint64_t turb_splitmix64(uint64_t *x)
{
    uint64_t z = (*x += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

static inline uint64_t turb_rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

static inline uint64_t turb_xoshiro(uint64_t s[4])
{
    uint64_t r = turb_rotl(s[1] * 5, 7) * 9, t = s[1] << 17;
    s[2] ^= s[0];
    s[3] ^= s[1];
    s[1] ^= s[2];
    s[0] ^= s[3];
    s[2] ^= t;
    s[3] = turb_rotl(s[3], 45);
    return r;
}

static inline void turb_seed(uint64_t s[4], uint64_t seed)
{
    uint64_t x = seed;
    for (int i = 0; i < 4; i++)
        s[i] = turb_splitmix64(&x);
}

/* Uniform in (0, 1) from the top 53 bits. */
static inline double turb_uniform_open(uint64_t u) { return ((double)(u >> 11) + 0.5) * 0x1.0p-53; }

static inline void turb_zig_init(turb_zig *z)
{
    const double r = TURB_ZIG_R, v = TURB_ZIG_V;
    z->x[0] = v / exp(-0.5 * r * r);
    z->x[1] = r;
    for (int i = 1; i < 255; i++)
        z->x[i + 1] = sqrt(-2.0 * log(v / z->x[i] + exp(-0.5 * z->x[i] * z->x[i])));
    z->x[256] = 0.0;
    for (int i = 0; i <= 256; i++)
        z->f[i] = exp(-0.5 * z->x[i] * z->x[i]);
}

/* A standard normal deviate. */
static inline double turb_zig_normal(const turb_zig *z, uint64_t s[4])
{
    for (;;) {
        uint64_t u = turb_xoshiro(s);
        int i = (int)(u & 255);
        double sign = (u & 256) ? -1.0 : 1.0;
        double x = (double)(u >> 11) * 0x1.0p-53 * z->x[i];
        if (x < z->x[i + 1])
            return sign * x;
        if (i == 0) { /* the tail beyond r */
            double a, b;
            do {
                a = -log(turb_uniform_open(turb_xoshiro(s))) / TURB_ZIG_R;
                b = -log(turb_uniform_open(turb_xoshiro(s)));
            } while (b + b < a * a);
            return sign * (TURB_ZIG_R + a);
        }
        /* the wedge between x[i + 1] and x[i]: under f? */
        double y = z->f[i] + turb_uniform_open(turb_xoshiro(s)) * (z->f[i + 1] - z->f[i]);
        if (y < exp(-0.5 * x * x))
            return sign * x;
    }
}

#endif
