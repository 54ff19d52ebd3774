/* anderson.c -- Anderson acceleration of the SIMPLEC fixed-point iteration.
 *
 * Model: one SIMPLEC iteration is a map x -> G(x) of the whole state x
 * (cell u, v, w, p, k, eps and the face velocities); a steady solution is
 * a fixed point. Anderson mixing (D. G. Anderson, "Iterative procedures
 * for nonlinear integral equations", J. ACM 12:547-560, 1965; in the form
 * of H. F. Walker and P. Ni, "Anderson acceleration for fixed-point
 * iterations", SIAM J. Numer. Anal. 49:1715-1735, 2011, Algorithm AA, with
 * the differences of consecutive iterates as its columns) takes, with
 * f_n = G(x_n) - x_n and the last m differences dF_i = f_{i+1} - f_i,
 * dG_i = G(x_{i+1}) - G(x_i):
 *     gamma   = argmin_gamma || f_n - sum_i gamma_i dF_i ||_W
 *     x_{n+1} = G(x_n) - sum_i gamma_i dG_i.
 * For a linear map this is GMRES on (I - G') (Walker and Ni, section 2):
 * it converges where the plain iteration ends in a limit cycle because a
 * few modes of G' have |lambda| near or above 1 -- on ship grids the
 * hangar-edge shear layers shed in pseudo-time (docs/validation/cfd.md).
 *
 * Assumptions and safeguards (ours, not from the references):
 *  - the objective norm W scales each segment (the solver: cell and face
 *    velocities by 1/u_ref, pressure by 1/(rho u_ref^2)); k and eps are
 *    not in the state (they keep SIMPLEC's values: mixing them needed a
 *    positivity clip and did not converge faster);
 *  - the history is stored in single precision (differences only; the
 *    current iterate stays double);
 *  - the small least-squares problem is solved by the normal equations
 *    with a relative Tikhonov term 1e-10 of the largest diagonal; a
 *    failed factorisation, non-finite coefficients or sum |gamma_i| above
 *    gamma_max restart the history and take the plain step.
 */
#include "cfd_private.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define AA_MAX_SEG 12
#define AA_GAMMA_MAX 50.0

struct cfd_aa {
    int m, nseg;
    size_t len[AA_MAX_SEG], off[AA_MAX_SEG], nall;
    double weight[AA_MAX_SEG];
    double *xn;     /* x_n (double) */
    double *gprev;  /* G(x_{n-1}) (double) */
    float *fprev;   /* W f_{n-1} */
    float *dg;      /* m columns: G(x_{i+1}) - G(x_i) */
    float *df;      /* m columns: W (f_{i+1} - f_i) */
    double gram[16 * 16]; /* <dF_i, dF_j> by slot, updated one column at a time */
    int have_prev, nhist, head;
    int mixes, restarts; /* counts since create, for the log */
    size_t bytes;
};

cfd_aa *cfd_aa_create(int depth, int nseg, const size_t *len, const double *weight)
{
    if (depth < 1 || depth > 16 || nseg < 1 || nseg > AA_MAX_SEG)
        return NULL;
    cfd_aa *a = calloc(1, sizeof *a);
    if (!a)
        return NULL;
    a->m = depth;
    a->nseg = nseg;
    for (int q = 0; q < nseg; q++) {
        a->len[q] = len[q];
        a->off[q] = a->nall;
        a->nall += len[q];
        a->weight[q] = weight[q];
    }
    a->xn = malloc(a->nall * sizeof(double));
    a->gprev = malloc(a->nall * sizeof(double));
    a->fprev = malloc(a->nall * sizeof(float));
    a->dg = malloc((size_t)depth * a->nall * sizeof(float));
    a->df = malloc((size_t)depth * a->nall * sizeof(float));
    if (!a->xn || !a->gprev || !a->fprev || !a->dg || !a->df) {
        cfd_aa_destroy(a);
        return NULL;
    }
    a->bytes = sizeof *a + 2 * a->nall * sizeof(double) + (1 + 2 * (size_t)depth) * a->nall * sizeof(float);
    return a;
}

void cfd_aa_destroy(cfd_aa *a)
{
    if (!a)
        return;
    free(a->xn);
    free(a->gprev);
    free(a->fprev);
    free(a->dg);
    free(a->df);
    free(a);
}

size_t cfd_aa_bytes(const cfd_aa *a) { return a ? a->bytes : 0; }

void cfd_aa_counts(const cfd_aa *a, int *mixes, int *restarts)
{
    *mixes = a->mixes;
    *restarts = a->restarts;
}

void cfd_aa_reset(cfd_aa *a)
{
    a->have_prev = 0;
    a->nhist = 0;
    a->head = 0;
}

void cfd_aa_save(cfd_aa *a, double *const *x)
{
    for (int q = 0; q < a->nseg; q++)
        memcpy(a->xn + a->off[q], x[q], a->len[q] * sizeof(double));
}

/* Solve (H + lambda I) g = r for symmetric positive H (n <= m) by Cholesky;
 * returns -1 if the factorisation fails. */
static int chol_solve(int n, double *H, double *r)
{
    double dmax = 0.0;
    for (int i = 0; i < n; i++)
        dmax = fmax(dmax, H[i * n + i]);
    if (!(dmax > 0.0))
        return -1;
    for (int i = 0; i < n; i++)
        H[i * n + i] += 1e-10 * dmax;
    for (int j = 0; j < n; j++) {
        double d = H[j * n + j];
        for (int k = 0; k < j; k++)
            d -= H[j * n + k] * H[j * n + k];
        if (!(d > 0.0))
            return -1;
        H[j * n + j] = sqrt(d);
        for (int i = j + 1; i < n; i++) {
            double s = H[i * n + j];
            for (int k = 0; k < j; k++)
                s -= H[i * n + k] * H[j * n + k];
            H[i * n + j] = s / H[j * n + j];
        }
    }
    for (int i = 0; i < n; i++) { /* L y = r */
        double s = r[i];
        for (int k = 0; k < i; k++)
            s -= H[i * n + k] * r[k];
        r[i] = s / H[i * n + i];
    }
    for (int i = n - 1; i >= 0; i--) { /* L^T g = y */
        double s = r[i];
        for (int k = i + 1; k < n; k++)
            s -= H[k * n + i] * r[k];
        r[i] = s / H[i * n + i];
    }
    return 0;
}

int cfd_aa_mix(cfd_aa *a, double *const *x)
{
    const int m = a->m;
    double ff = 0.0;
    /* the new history column (if any) and f_n, G(x_n) as the new "previous" */
    float *dfc = a->have_prev ? a->df + (size_t)a->head * a->nall : NULL;
    float *dgc = a->have_prev ? a->dg + (size_t)a->head * a->nall : NULL;
    for (int q = 0; q < a->nseg; q++) {
        const size_t o = a->off[q], n = a->len[q];
        const double w = a->weight[q];
        const double *g = x[q], *xn = a->xn + o;
        double *gp = a->gprev + o;
        float *fp = a->fprev + o;
        #pragma omp parallel for reduction(+ : ff) schedule(static)
        for (size_t c = 0; c < n; c++) {
            double f = w * (g[c] - xn[c]);
            ff += f * f;
            if (dfc) {
                dfc[o + c] = (float)(f - fp[c]);
                dgc[o + c] = (float)(g[c] - gp[c]);
            }
            fp[c] = (float)f;
            gp[c] = g[c];
        }
    }
    int newc = -1; /* the slot just written */
    if (a->have_prev) {
        newc = a->head;
        a->head = (a->head + 1) % m;
        if (a->nhist < m)
            a->nhist++;
    }
    a->have_prev = 1;
    if (!isfinite(ff)) {
        cfd_aa_reset(a);
        return -1;
    }
    const int nh = a->nhist;
    if (nh == 0)
        return 0;
    /* One pass over the history: the new column's products with every
     * column (the Gram matrix changes by one row and column) and every
     * column's product with f_n. */
    double acc[32] = {0};
    const size_t N = a->nall;
    const float *df = a->df, *fp = a->fprev, *dn = newc >= 0 ? a->df + (size_t)newc * N : NULL;
    #pragma omp parallel for reduction(+ : acc[:32]) schedule(static)
    for (size_t c = 0; c < N; c++) {
        const double fv = fp[c], nv = dn ? dn[c] : 0.0;
        for (int i = 0; i < nh; i++) {
            const double d = df[(size_t)i * N + c];
            acc[i] += nv * d;
            acc[16 + i] += d * fv;
        }
    }
    if (newc >= 0)
        for (int i = 0; i < nh; i++)
            a->gram[newc * 16 + i] = a->gram[i * 16 + newc] = acc[i];
    double H[16 * 16], r[16];
    for (int i = 0; i < nh; i++) {
        for (int j = 0; j < nh; j++)
            H[i * nh + j] = a->gram[i * 16 + j];
        r[i] = acc[16 + i];
    }
    if (chol_solve(nh, H, r)) {
        cfd_aa_reset(a);
        a->restarts++;
        return 0;
    }
    double gsum = 0.0;
    for (int i = 0; i < nh; i++)
        gsum += fabs(r[i]);
    if (!isfinite(gsum) || gsum > AA_GAMMA_MAX) {
        cfd_aa_reset(a);
        a->restarts++;
        return 0;
    }
    a->mixes++;
    /* x_{n+1} = G(x_n) - sum gamma_i dG_i */
    for (int q = 0; q < a->nseg; q++) {
        double *xq = x[q];
        const size_t off = a->off[q], n = a->len[q];
        #pragma omp parallel for schedule(static)
        for (size_t c = 0; c < n; c++) {
            double v = xq[c];
            for (int i = 0; i < nh; i++)
                v -= r[i] * a->dg[(size_t)i * a->nall + off + c];
            xq[c] = v;
        }
    }
    return nh;
}
