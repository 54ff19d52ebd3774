/*
 * disk.c -- actuator-disk rotor as a momentum source.
 *
 * Model: the steady actuator disk of the seed paper (section 2.2): the rotor
 * is an infinitely thin disk carrying a pressure jump, here spread over the
 * cells it crosses with a Gaussian of half-width sigma = smooth_cells local
 * cell sizes across the disk and a tanh edge of width sigma at the tip (and
 * root cut), so the source is smooth on the grid. Uniform loading is the
 * seed paper's eq. 5, Delta p = T / A. The loaded option multiplies the
 * pressure jump by a caller's table over (r/R, psi) and adds a tangential
 * (swirl) force with a radial shape, in the rotation sense.
 * Exactness: each cell's share is its integral of the kernel (4 x 4 x 4
 * sample points per cell) divided by the total, so the normal forces sum to
 * the requested thrust and the tangential forces' moment about the axis to
 * the requested torque, to round-off, whatever the grid.
 */
#include "cfd_private.h"

#include <math.h>
#include <string.h>

#define NS 4

double cfd_disk_hover_vi_mps(const cfd_disk *d, double rho_kgpm3)
{
    return d->thrust_N > 0.0 && d->radius_m > 0.0
               ? sqrt(d->thrust_N / (2.0 * rho_kgpm3 * CORE_PI * d->radius_m * d->radius_m))
               : 0.0;
}

void cfd_disk_from_attitude(cfd_disk *d, const double c[3], core_euler att, double radius_m, double thrust_N)
{
    memset(d, 0, sizeof *d);
    core_mat3 m = core_mat3_from_euler(att);
    core_vec3 n = core_mat3_mul_vec(m, core_vec3_make(0.0, 0.0, -1.0));
    core_vec3 r = core_mat3_mul_vec(m, core_vec3_make(-1.0, 0.0, 0.0));
    for (int q = 0; q < 3; q++)
        d->centre_m[q] = c[q];
    d->normal[0] = n.x, d->normal[1] = n.y, d->normal[2] = n.z;
    d->ref[0] = r.x, d->ref[1] = r.y, d->ref[2] = r.z;
    d->radius_m = radius_m;
    d->thrust_N = thrust_N;
    d->ccw_from_above = 1;
    d->smooth_cells = 1.5;
}

typedef struct frame {
    core_vec3 c, n, e1, e2;
    double R, sig, rc;
} frame;

static double table_load(const cfd_disk *d, double rr, double psi)
{
    if (d->nr <= 0)
        return 1.0;
    int npsi = d->npsi > 0 ? d->npsi : 1;
    double x = rr * d->nr - 0.5;
    int i0 = (int)floor(x);
    double fr = x - i0;
    if (i0 < 0)
        i0 = 0, fr = 0.0;
    if (i0 >= d->nr - 1)
        i0 = d->nr > 1 ? d->nr - 2 : 0, fr = d->nr > 1 ? 1.0 : 0.0;
    int i1 = d->nr > 1 ? i0 + 1 : i0;
    double y = psi / (2.0 * CORE_PI) * npsi;
    y -= floor(y / npsi) * npsi;
    int j0 = (int)floor(y) % npsi;
    double fp = y - floor(y);
    int j1 = (j0 + 1) % npsi;
    const double *L = d->load;
    double a = (1 - fr) * L[j0 * d->nr + i0] + fr * L[j0 * d->nr + i1];
    double b = (1 - fr) * L[j1 * d->nr + i0] + fr * L[j1 * d->nr + i1];
    return (1 - fp) * a + fp * b;
}

static double table_swirl(const cfd_disk *d, double rr)
{
    if (d->nr <= 0)
        return 0.0;
    double x = rr * d->nr - 0.5;
    int i0 = (int)floor(x);
    if (i0 < 0)
        return d->swirl[0];
    if (i0 >= d->nr - 1)
        return d->swirl[d->nr - 1];
    double f = x - i0;
    return (1 - f) * d->swirl[i0] + f * d->swirl[i0 + 1];
}

/* Kernel at point p: normal weight wn, tangential unit vector t and weight wt. */
static void kernel(const cfd_disk *d, const frame *F, core_vec3 p, double *wn, double *wt, core_vec3 *t,
                   double *r_out)
{
    core_vec3 q = core_vec3_sub(p, F->c);
    double dn = core_vec3_dot(q, F->n);
    core_vec3 rp = core_vec3_sub(q, core_vec3_scale(F->n, dn));
    double r = core_vec3_norm(rp);
    double g = exp(-(dn / F->sig) * (dn / F->sig));
    double edge = 0.5 * (1.0 - tanh((r - F->R) / (0.5 * F->sig)));
    if (F->rc > 0.0)
        edge *= 0.5 * (1.0 + tanh((r - F->rc) / (0.5 * F->sig)));
    double base = g * edge;
    *r_out = r;
    if (base < 1e-14) {
        *wn = *wt = 0.0;
        *t = core_vec3_make(0, 0, 0);
        return;
    }
    double x1 = core_vec3_dot(rp, F->e1), x2 = core_vec3_dot(rp, F->e2);
    double psi = atan2(x2, x1);
    if (psi < 0.0)
        psi += 2.0 * CORE_PI;
    double rr = r / F->R;
    *wn = base * table_load(d, rr, psi);
    if (d->nr > 0 && d->torque_Nm != 0.0 && r > 1e-12) {
        core_vec3 er = core_vec3_scale(rp, 1.0 / r);
        *t = core_vec3_cross(F->n, er);
        if (!d->ccw_from_above)
            *t = core_vec3_scale(*t, -1.0);
        *wt = base * table_swirl(d, rr);
    } else {
        *wt = 0.0;
        *t = core_vec3_make(0, 0, 0);
    }
}

static int locate_node(const double *xn, int n, double x)
{
    if (x <= xn[0])
        return 0;
    if (x >= xn[n])
        return n - 1;
    int lo = 0, hi = n;
    while (hi - lo > 1) {
        int m = (lo + hi) / 2;
        if (xn[m] <= x)
            lo = m;
        else
            hi = m;
    }
    return lo;
}

int cfd_disk_distribute(const cfd_grid *g, const cfd_disk *d, double *f[3], core_err *err)
{
    for (int q = 0; q < 3; q++)
        memset(f[q], 0, g->ncell * sizeof(double));
    frame F;
    F.c = core_vec3_make(d->centre_m[0], d->centre_m[1], d->centre_m[2]);
    F.n = core_vec3_make(d->normal[0], d->normal[1], d->normal[2]);
    double nn = core_vec3_norm(F.n);
    if (!(d->radius_m > 0.0) || !(nn > 0.0) || !isfinite(d->thrust_N) || d->nr < 0 ||
        d->nr > CFD_DISK_MAX_TABLE || d->npsi < 0 || d->npsi > CFD_DISK_MAX_TABLE ||
        (d->nr > 0 && d->npsi < 1))
        return core_err_set(err, -1,
                            "cfd disk: expected radius > 0, a non-zero normal, a finite thrust and "
                            "table sizes 0..%d (got R %g, |n| %g, T %g, nr %d, npsi %d)",
                            CFD_DISK_MAX_TABLE, d->radius_m, nn, d->thrust_N, d->nr, d->npsi);
    F.n = core_vec3_scale(F.n, 1.0 / nn);
    core_vec3 ref = core_vec3_make(d->ref[0], d->ref[1], d->ref[2]);
    ref = core_vec3_sub(ref, core_vec3_scale(F.n, core_vec3_dot(ref, F.n)));
    if (core_vec3_norm(ref) < 1e-9) { /* any in-plane direction */
        core_vec3 a = fabs(F.n.x) < 0.9 ? core_vec3_make(1, 0, 0) : core_vec3_make(0, 1, 0);
        ref = core_vec3_sub(a, core_vec3_scale(F.n, core_vec3_dot(a, F.n)));
    }
    F.e1 = core_vec3_scale(ref, 1.0 / core_vec3_norm(ref));
    F.e2 = core_vec3_cross(F.n, F.e1);
    if (!d->ccw_from_above)
        F.e2 = core_vec3_scale(F.e2, -1.0);
    F.R = d->radius_m;
    F.rc = d->root_cut * d->radius_m;
    int ic[3];
    for (int q = 0; q < 3; q++)
        ic[q] = locate_node(g->xn[q], g->n[q], d->centre_m[q]);
    double hn = fabs(F.n.x) * g->h[0][ic[0]] + fabs(F.n.y) * g->h[1][ic[1]] + fabs(F.n.z) * g->h[2][ic[2]];
    double sm = d->smooth_cells > 0.0 ? d->smooth_cells : 1.5;
    F.sig = sm * hn;
    double ext = F.R + 3.0 * F.sig;
    int lo[3], hi[3];
    for (int q = 0; q < 3; q++) {
        lo[q] = locate_node(g->xn[q], g->n[q], d->centre_m[q] - ext);
        hi[q] = locate_node(g->xn[q], g->n[q], d->centre_m[q] + ext);
    }
    double Wn = 0.0, Qw = 0.0;
    for (int pass = 0; pass < 2; pass++) {
        double sn = pass ? -d->thrust_N / Wn : 0.0;
        double st = (pass && Qw > 0.0) ? d->torque_Nm / Qw : 0.0;
        double wn_sum = 0.0, q_sum = 0.0;
        #pragma omp parallel for reduction(+ : wn_sum, q_sum) schedule(dynamic)
        for (int k = lo[2]; k <= hi[2]; k++)
            for (int j = lo[1]; j <= hi[1]; j++)
                for (int i = lo[0]; i <= hi[0]; i++) {
                    size_t c = CFD_IDX(g, i, j, k);
                    if (g->solid[c])
                        continue;
                    double dv = g->h[0][i] * g->h[1][j] * g->h[2][k] / (NS * NS * NS);
                    double cn = 0.0;
                    core_vec3 ct = core_vec3_make(0, 0, 0);
                    for (int c3 = 0; c3 < NS; c3++)
                        for (int c2 = 0; c2 < NS; c2++)
                            for (int c1 = 0; c1 < NS; c1++) {
                                core_vec3 p = core_vec3_make(g->xn[0][i] + (c1 + 0.5) / NS * g->h[0][i],
                                                             g->xn[1][j] + (c2 + 0.5) / NS * g->h[1][j],
                                                             g->xn[2][k] + (c3 + 0.5) / NS * g->h[2][k]);
                                double wn, wt, r;
                                core_vec3 t;
                                kernel(d, &F, p, &wn, &wt, &t, &r);
                                cn += wn * dv;
                                ct = core_vec3_add(ct, core_vec3_scale(t, wt * dv));
                                q_sum += wt * dv * r;
                            }
                    wn_sum += cn;
                    if (pass) {
                        f[0][c] = sn * cn * F.n.x + st * ct.x;
                        f[1][c] = sn * cn * F.n.y + st * ct.y;
                        f[2][c] = sn * cn * F.n.z + st * ct.z;
                    }
                }
        if (!pass) {
            Wn = wn_sum;
            Qw = q_sum;
            if (!(Wn > 0.0))
                return core_err_set(err, -1,
                                    "cfd disk: the disk at (%g, %g, %g) radius %g m misses the fluid cells of the grid",
                                    d->centre_m[0], d->centre_m[1], d->centre_m[2], d->radius_m);
        }
    }
    return 0;
}
