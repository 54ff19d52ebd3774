/* cont.c -- Newton-Raphson and pseudo-arc-length continuation.
 *
 * Newton: J dx = -F with J by central differences (the seed paper, sec. 2.4),
 * LAPACK dgesv, and a backtracking line search on |F|_2 (Dennis and
 * Schnabel, "Numerical Methods for Unconstrained Optimization", 6.3), with
 * Levenberg-Marquardt steps (ibid. 10.2) where the Newton direction fails.
 * Continuation (Keller 1977; Allgower and Georg, "Introduction to Numerical
 * Continuation Methods", ch. 2-6; Seydel, "Practical Bifurcation and
 * Stability Analysis", ch. 4): in the scaled space y = (x/x_scale,
 * lam/lam_scale) the tangent t solves [F_y; t_prev^T] t = [0; 1] (so it keeps
 * its orientation through a turning point), an Euler predictor y + ds t is
 * corrected by Newton on [F(y); t.(y - y_pred)] = 0, and ds halves on failure
 * and grows by 1.5 when the corrector needs at most two iterations. A sign
 * change of dlam/ds between accepted points marks a turning point (fold).
 */
#include "hfm_priv.h"

#include <lapacke.h>
#include <stdlib.h>
#include <string.h>

static double maxabs(const double *f, int n, int *imax)
{
    double m = 0.0;
    int k = 0;
    for (int i = 0; i < n; i++)
        if (fabs(f[i]) > m || i == 0) {
            m = fabs(f[i]);
            k = i;
        }
    if (imax)
        *imax = k;
    return m;
}

static double norm2(const double *f, int n)
{
    double s = 0.0;
    for (int i = 0; i < n; i++)
        s += f[i] * f[i];
    return sqrt(s);
}

/* Column-major Jacobian J[j*n + i] = dF_i/dx_j by central differences. */
static int jacobian(hfm_sys_fn fn, void *user, int n, double *x, double lam, const double *dx,
                    double *J, double *fp, double *fm)
{
    for (int j = 0; j < n; j++) {
        double h = dx ? dx[j] : 1e-6, x0 = x[j];
        x[j] = x0 + h;
        int rc = fn(user, x, lam, fp);
        x[j] = x0 - h;
        rc |= fn(user, x, lam, fm);
        x[j] = x0;
        if (rc)
            return -1;
        for (int i = 0; i < n; i++)
            J[j * n + i] = (fp[i] - fm[i]) / (2.0 * h);
    }
    return 0;
}

int hfm_newton(hfm_sys_fn fn, void *user, int n, double *x, double lam,
               const hfm_newton_opts *opts, hfm_newton_info *info)
{
    int maxit = opts && opts->max_iter > 0 ? opts->max_iter : 40;
    double tol = opts && opts->tol > 0 ? opts->tol : 1e-9;
    const double *dx = opts ? opts->dx : NULL;
    hfm_newton_info inf = {0, 0, 0, 0.0, 0};
    double *w = malloc(sizeof(double) * (size_t)(3 * n * n + 6 * n));
    lapack_int *piv = malloc(sizeof(lapack_int) * (size_t)n);
    if (!w || !piv) {
        free(w);
        free(piv);
        return -1;
    }
    double *J = w, *f = J + n * n, *fp = f + n, *fm = fp + n, *d = fm + n, *xt = d + n,
           *ft = xt + n, *Jc = ft + n, *N = Jc + n * n;
    int rc = 1;
    if (fn(user, x, lam, f)) {
        rc = -1;
        goto done;
    }
    inf.evaluations++;
    for (;;) {
        inf.resid_norm = maxabs(f, n, &inf.worst_eq);
        if (inf.resid_norm <= tol) {
            inf.converged = 1;
            rc = 0;
            break;
        }
        if (inf.iterations >= maxit)
            break;
        inf.iterations++;
        if (jacobian(fn, user, n, x, lam, dx, J, fp, fm)) {
            rc = -1;
            break;
        }
        inf.evaluations += 2 * n;
        memcpy(Jc, J, sizeof(double) * (size_t)(n * n));
        for (int i = 0; i < n; i++)
            d[i] = -f[i];
        int ok = 0;
        double n0 = norm2(f, n), s = 1.0;
        if (LAPACKE_dgesv(LAPACK_COL_MAJOR, n, 1, J, n, piv, d, n) == 0) {
            for (int ls = 0; ls < 8; ls++) {
                for (int i = 0; i < n; i++)
                    xt[i] = x[i] + s * d[i];
                int frc = fn(user, xt, lam, ft);
                inf.evaluations++;
                if (!frc && norm2(ft, n) < (1.0 - 1e-4 * s) * n0) {
                    ok = 1;
                    break;
                }
                s *= 0.5;
            }
        }
        /* Fallback where the Newton direction fails (a kink in a table or
         * schedule, a singular J): Levenberg-Marquardt steps
         * (J^T J + mu diag(J^T J)) d = -J^T f with mu growing. */
        for (double mu = 1e-4; !ok && mu < 1e4; mu *= 10.0) {
            for (int a = 0; a < n; a++) {
                double g = 0.0;
                for (int k = 0; k < n; k++)
                    g += Jc[a * n + k] * f[k];
                d[a] = -g;
                for (int b = 0; b < n; b++) {
                    double t = 0.0;
                    for (int k = 0; k < n; k++)
                        t += Jc[a * n + k] * Jc[b * n + k];
                    N[b * n + a] = t;
                }
            }
            for (int a = 0; a < n; a++)
                N[a * n + a] *= 1.0 + mu;
            if (LAPACKE_dgesv(LAPACK_COL_MAJOR, n, 1, N, n, piv, d, n) != 0)
                continue;
            for (int i = 0; i < n; i++)
                xt[i] = x[i] + d[i];
            int frc = fn(user, xt, lam, ft);
            inf.evaluations++;
            if (!frc && norm2(ft, n) < n0)
                ok = 1;
        }
        if (!ok)
            break;
        memcpy(x, xt, sizeof(double) * (size_t)n);
        memcpy(f, ft, sizeof(double) * (size_t)n);
    }
done:
    if (info)
        *info = inf;
    free(w);
    free(piv);
    return rc;
}

/* The continuation works on y = (x / xs, lam / ls). */
typedef struct ctx {
    hfm_sys_fn fn;
    void *user;
    int n;
    const double *xs;
    double ls;
    double *xb; /* unscaled x buffer */
    int evals;
} ctx;

static int eval_scaled(ctx *c, const double *y, double *f)
{
    for (int i = 0; i < c->n; i++)
        c->xb[i] = y[i] * (c->xs ? c->xs[i] : 1.0);
    c->evals++;
    return c->fn(c->user, c->xb, y[c->n] * c->ls, f);
}

/* Jacobian of F wrt y (n x (n+1), column-major with leading dimension m =
 * n+1, rows 0..n-1), h in scaled units. */
static int jac_y(ctx *c, double *y, const double *dx, double *A, int m, double *fp, double *fm)
{
    int n = c->n;
    for (int j = 0; j <= n; j++) {
        double h = 1e-6;
        if (dx && j < n)
            h = dx[j] / (c->xs ? c->xs[j] : 1.0);
        double y0 = y[j];
        y[j] = y0 + h;
        int rc = eval_scaled(c, y, fp);
        y[j] = y0 - h;
        rc |= eval_scaled(c, y, fm);
        y[j] = y0;
        if (rc)
            return -1;
        for (int i = 0; i < n; i++)
            A[j * m + i] = (fp[i] - fm[i]) / (2.0 * h);
    }
    return 0;
}

int hfm_cont_trace(hfm_sys_fn fn, void *user, int n, const double *x0, double lam0,
                   double lam_min, double lam_max, const hfm_cont_opts *o,
                   hfm_cont_point_fn point, void *point_user, hfm_cont_info *info)
{
    int m = n + 1;
    double ds = o->ds0, tol = o->tol > 0 ? o->tol : 1e-9;
    int cmax = o->corr_max_iter > 0 ? o->corr_max_iter : 6;
    hfm_cont_info inf = {0, 0, 0, 0, 0, lam0};
    double *w = malloc(sizeof(double) * (size_t)(m * m + 10 * m));
    lapack_int *piv = malloc(sizeof(lapack_int) * (size_t)m);
    if (!w || !piv) {
        free(w);
        free(piv);
        return -1;
    }
    double *A = w, *y = A + m * m, *t = y + m, *tp = t + m, *yp = tp + m, *yn = yp + m,
           *f = yn + m, *fp = f + m, *fm = fp + m, *d = fm + m, *xb = d + m;
    ctx c = {fn, user, n, o->x_scale, o->lam_scale > 0 ? o->lam_scale : 1.0, xb, 0};
    for (int i = 0; i < n; i++)
        y[i] = x0[i] / (c.xs ? c.xs[i] : 1.0);
    y[n] = lam0 / c.ls;
    memset(tp, 0, sizeof(double) * (size_t)m);
    tp[n] = 1.0; /* start toward increasing lam */
    int rc = 0;
    double prev_dl = 1.0;
    while (inf.steps < o->max_steps) {
        /* tangent at y */
        if (jac_y(&c, y, o->dx, A, m, fp, fm)) {
            rc = -1;
            break;
        }
        for (int j = 0; j < m; j++)
            A[j * m + n] = tp[j];
        memset(t, 0, sizeof(double) * (size_t)m);
        t[n] = 1.0;
        if (LAPACKE_dgesv(LAPACK_COL_MAJOR, m, 1, A, m, piv, t, m) != 0) {
            rc = 1;
            break;
        }
        double tn = norm2(t, m);
        for (int j = 0; j < m; j++)
            t[j] /= tn;
        /* predictor-corrector with step control */
        int accepted = 0, iters = 0;
        while (!accepted) {
            for (int j = 0; j < m; j++)
                yp[j] = yn[j] = y[j] + ds * t[j];
            int conv = 0;
            for (iters = 0; iters < cmax; iters++) {
                if (eval_scaled(&c, yn, f)) {
                    rc = -1;
                    goto out;
                }
                double s = 0.0;
                for (int j = 0; j < m; j++)
                    s += t[j] * (yn[j] - yp[j]);
                f[n] = s;
                if (maxabs(f, m, NULL) <= tol) {
                    conv = 1;
                    break;
                }
                if (jac_y(&c, yn, o->dx, A, m, fp, fm)) {
                    rc = -1;
                    goto out;
                }
                for (int j = 0; j < m; j++)
                    A[j * m + n] = t[j];
                for (int j = 0; j < m; j++)
                    d[j] = -f[j];
                if (LAPACKE_dgesv(LAPACK_COL_MAJOR, m, 1, A, m, piv, d, m) != 0)
                    break;
                for (int j = 0; j < m; j++)
                    yn[j] += d[j];
            }
            if (conv) {
                accepted = 1;
            } else {
                inf.rejected++;
                ds *= 0.5;
                if (ds < o->ds_min) {
                    rc = 1;
                    goto out;
                }
            }
        }
        memcpy(tp, t, sizeof(double) * (size_t)m);
        memcpy(y, yn, sizeof(double) * (size_t)m);
        inf.steps++;
        int fold = (t[n] > 0) != (prev_dl > 0);
        if (fold)
            inf.folds++;
        prev_dl = t[n];
        inf.lam_end = y[n] * c.ls;
        for (int i = 0; i < n; i++)
            xb[i] = y[i] * (c.xs ? c.xs[i] : 1.0);
        if (point && point(point_user, xb, inf.lam_end, t[n], fold)) {
            inf.stopped = 1;
            break;
        }
        if (inf.lam_end < lam_min || inf.lam_end > lam_max)
            break;
        if (iters <= 2)
            ds = fmin(ds * 1.5, o->ds_max);
        else if (iters >= 4)
            ds *= 0.7;
    }
out:
    inf.evaluations = c.evals;
    if (info)
        *info = inf;
    free(w);
    free(piv);
    return rc;
}
