/*
 * turb.c -- RNG k-epsilon closure constants and standard wall functions.
 *
 * Model: RNG k-epsilon (Yakhot, Orszag, Thangam, Gatski & Speziale 1992,
 * Phys. Fluids A 4:1510; seed paper eqs. 2-3 without the compressible
 * terms): nu_t = Cmu k^2 / eps, P_k = nu_t S^2 with S^2 = 2 S_ij S_ij,
 *   Dk/Dt   = div((nu + nu_t / sigma_k) grad k) + P_k - eps
 *   Deps/Dt = div((nu + nu_t / sigma_e) grad eps) + C1 eps/k P_k - C2* eps^2/k
 * with C2* = C2 + Cmu eta^3 (1 - eta/eta0) / (1 + beta eta^3), eta = S k/eps,
 * Cmu 0.0845, C1 1.42, C2 1.68, sigma_k = sigma_e = 0.71942, eta0 4.38,
 * beta 0.012. The transport equations are assembled in solver.c, with
 * Menter's production limiter P_k <= 10 eps (Menter 1994, AIAA J.
 * 32:1598), without which k runs away in the rotor wake before eps grows.
 * Standard wall functions (Launder & Spalding 1974, Comput. Methods Appl.
 * Mech. Eng. 3:269): with u* = Cmu^1/4 k^1/2 and y* = u* y / nu, the wall
 * shear is tau_w / rho = kappa u* U_p / ln(E y*) for y* > 11.225 (kappa 0.41,
 * E 9.8), otherwise the laminar nu U_p / y; in a wall cell P_k =
 * tau_w u* / (kappa y) and eps = Cmu^3/4 k^3/2 / (kappa y).
 */
#include "cfd_private.h"

#include <math.h>

double cfd_wall_nu(double nu, double k, double y)
{
    double us = pow(CFD_CMU, 0.25) * sqrt(k > 0.0 ? k : 0.0);
    double ys = us * y / nu;
    if (ys <= 11.225)
        return nu;
    return CFD_KAPPA * us * y / log(CFD_EWALL * ys);
}

double cfd_rng_c2star(double eta)
{
    double e3 = eta * eta * eta;
    return CFD_C2 + CFD_CMU * e3 * (1.0 - eta / CFD_ETA0) / (1.0 + CFD_BETA * e3);
}
