/*
 * mg.c -- pressure-correction equation: conjugate gradients preconditioned
 * by a geometric multigrid V-cycle.
 *
 * Model: the 7-point symmetric operator A x = diag x - sum c x_nb of the
 * SIMPLEC pressure correction. Coarse levels merge 2 x 2 x 2 cells (1 along
 * an axis with a single cell) and take the Galerkin product with piecewise
 * constant transfer, i.e. the additive-correction multigrid of Hutchinson &
 * Raithby (1986, Numer. Heat Transfer 9:511): a coarse face coupling is the
 * sum of the fine couplings across it, so blocked cells (zero couplings) and
 * stretched cells need no special rule. The V-cycle is symmetric (red-black
 * Gauss-Seidel, red then black going down, black then red going up), hence a
 * valid CG preconditioner, which also removes the additive-correction
 * method's under-scaled coarse corrections. A singular (all-Neumann) system
 * is solved in the space of zero-mean vectors.
 */
#include "cfd_private.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#define MG_MAX_LEVELS 16

typedef struct mg_level {
    int n[3];
    size_t nc;
    double *cx, *cy, *cz, *diag, *x, *b, *r;
    unsigned char *active;
} mg_level;

struct cfd_mg {
    int nlev;
    mg_level lev[MG_MAX_LEVELS];
    double *r, *z, *p, *q; /* CG vectors, fine level */
    int singular;
    size_t bytes;
};

static void level_free(mg_level *L)
{
    free(L->cx);
    free(L->cy);
    free(L->cz);
    free(L->diag);
    free(L->x);
    free(L->b);
    free(L->r);
    free(L->active);
}

static int level_alloc(mg_level *L, const int n[3], size_t *bytes)
{
    memcpy(L->n, n, sizeof L->n);
    L->nc = (size_t)n[0] * n[1] * n[2];
    L->cx = calloc(L->nc, sizeof(double));
    L->cy = calloc(L->nc, sizeof(double));
    L->cz = calloc(L->nc, sizeof(double));
    L->diag = calloc(L->nc, sizeof(double));
    L->x = calloc(L->nc, sizeof(double));
    L->b = calloc(L->nc, sizeof(double));
    L->r = calloc(L->nc, sizeof(double));
    L->active = calloc(L->nc, 1);
    *bytes += L->nc * (7 * sizeof(double) + 1);
    return (L->cx && L->cy && L->cz && L->diag && L->x && L->b && L->r && L->active) ? 0 : -1;
}

cfd_mg *cfd_mg_create(const int n[3])
{
    cfd_mg *m = calloc(1, sizeof *m);
    if (!m)
        return NULL;
    int cur[3] = {n[0], n[1], n[2]};
    for (;;) {
        if (level_alloc(&m->lev[m->nlev], cur, &m->bytes))
            goto fail;
        m->nlev++;
        size_t nc = (size_t)cur[0] * cur[1] * cur[2];
        if (nc <= 64 || m->nlev == MG_MAX_LEVELS || (cur[0] == 1 && cur[1] == 1 && cur[2] == 1))
            break;
        for (int d = 0; d < 3; d++)
            cur[d] = cur[d] > 1 ? (cur[d] + 1) / 2 : 1;
    }
    size_t nc = m->lev[0].nc;
    m->r = malloc(nc * sizeof(double));
    m->z = malloc(nc * sizeof(double));
    m->p = malloc(nc * sizeof(double));
    m->q = malloc(nc * sizeof(double));
    m->bytes += 4 * nc * sizeof(double);
    if (!m->r || !m->z || !m->p || !m->q)
        goto fail;
    return m;
fail:
    cfd_mg_destroy(m);
    return NULL;
}

void cfd_mg_destroy(cfd_mg *m)
{
    if (!m)
        return;
    for (int l = 0; l < m->nlev; l++)
        level_free(&m->lev[l]);
    free(m->r);
    free(m->z);
    free(m->p);
    free(m->q);
    free(m);
}

size_t cfd_mg_bytes(const cfd_mg *m) { return m ? m->bytes + sizeof *m : 0; }
double *cfd_mg_cx(cfd_mg *m) { return m->lev[0].cx; }
double *cfd_mg_cy(cfd_mg *m) { return m->lev[0].cy; }
double *cfd_mg_cz(cfd_mg *m) { return m->lev[0].cz; }
double *cfd_mg_diag(cfd_mg *m) { return m->lev[0].diag; }
double *cfd_mg_work(cfd_mg *m, int i)
{
    double *w[4] = {m->r, m->z, m->p, m->q};
    return i >= 0 && i < 4 ? w[i] : NULL;
}

#define LIDX(L, i, j, k) ((size_t)(i) + (size_t)(L)->n[0] * ((size_t)(j) + (size_t)(L)->n[1] * (size_t)(k)))

static inline int child0(const mg_level *F, int d, int I) { return F->n[d] > 1 ? 2 * I : I; }
static inline int nchild(const mg_level *F, int d, int I)
{
    if (F->n[d] == 1)
        return 1;
    return (2 * I + 1 < F->n[d]) ? 2 : 1;
}

void cfd_mg_setup(cfd_mg *m, int singular)
{
    m->singular = singular;
    mg_level *F0 = &m->lev[0];
    #pragma omp parallel for schedule(static)
    for (size_t c = 0; c < F0->nc; c++) {
        F0->active[c] = F0->diag[c] > 0.0;
        if (!F0->active[c])
            F0->diag[c] = 1.0, F0->cx[c] = F0->cy[c] = F0->cz[c] = 0.0;
    }
    for (int l = 1; l < m->nlev; l++) {
        const mg_level *F = &m->lev[l - 1];
        mg_level *C = &m->lev[l];
        #pragma omp parallel for schedule(static)
        for (int K = 0; K < C->n[2]; K++)
            for (int J = 0; J < C->n[1]; J++)
                for (int I = 0; I < C->n[0]; I++) {
                    size_t cc = LIDX(C, I, J, K);
                    double dg = 0.0, sx = 0.0, sy = 0.0, sz = 0.0;
                    int act = 0;
                    int i0 = child0(F, 0, I), j0 = child0(F, 1, J), k0 = child0(F, 2, K);
                    int ni = nchild(F, 0, I), nj = nchild(F, 1, J), nk = nchild(F, 2, K);
                    for (int k = k0; k < k0 + nk; k++)
                        for (int j = j0; j < j0 + nj; j++)
                            for (int i = i0; i < i0 + ni; i++) {
                                size_t f = LIDX(F, i, j, k);
                                if (!F->active[f])
                                    continue;
                                act = 1;
                                dg += F->diag[f];
                                /* a coupling to a sibling is internal to the aggregate */
                                if (i + 1 < i0 + ni)
                                    dg -= 2.0 * F->cx[f];
                                else if (I + 1 < C->n[0])
                                    sx += F->cx[f];
                                if (j + 1 < j0 + nj)
                                    dg -= 2.0 * F->cy[f];
                                else if (J + 1 < C->n[1])
                                    sy += F->cy[f];
                                if (k + 1 < k0 + nk)
                                    dg -= 2.0 * F->cz[f];
                                else if (K + 1 < C->n[2])
                                    sz += F->cz[f];
                            }
                    C->active[cc] = (unsigned char)act;
                    C->diag[cc] = act ? dg : 1.0;
                    C->cx[cc] = sx;
                    C->cy[cc] = sy;
                    C->cz[cc] = sz;
                    if (act && !(C->diag[cc] > 0.0))
                        C->diag[cc] = sx + sy + sz + 1e-300;
                }
    }
}

/* Levels below this many cells run on one thread: a parallel loop there
 * costs more in fork and barrier than its work, and on a shared machine a
 * barrier waits a whole time slice for a descheduled thread. The results
 * do not depend on it (red-black sweeps and the transfers are the same per
 * cell in any order). */
#define MG_PAR_MIN 16384

/* The sum b + sum_nb c x_nb of cell c (i, j, k), the terms in the order of
 * the generic rule (-x, +x, -y, +y, -z, +z), each present only where the
 * neighbour exists; jm .. kp say which of the four y, z neighbours do. */
static inline double gs_sum(const mg_level *L, const double *restrict x, size_t c, int i, int nx, int jm, int jp,
                            int km, int kp, size_t sy, size_t sz)
{
    double s = L->b[c];
    if (i > 0)
        s += L->cx[c - 1] * x[c - 1];
    if (i + 1 < nx)
        s += L->cx[c] * x[c + 1];
    if (jm)
        s += L->cy[c - sy] * x[c - sy];
    if (jp)
        s += L->cy[c] * x[c + sy];
    if (km)
        s += L->cz[c - sz] * x[c - sz];
    if (kp)
        s += L->cz[c] * x[c + sz];
    return s;
}

/* One row of a half-sweep: the two ends by the generic rule, the interior
 * with the row's y and z neighbours known (the compiler unswitches on
 * them). The same arithmetic per cell as the generic rule. */
static inline void gs_row(mg_level *L, int j, int k, int colour)
{
    const int nx = L->n[0], ny = L->n[1], nz = L->n[2];
    const size_t sy = (size_t)nx, sz = (size_t)nx * ny;
    const int jm = j > 0, jp = j + 1 < ny, km = k > 0, kp = k + 1 < nz;
    double *restrict x = L->x;
    const double *restrict b = L->b, *restrict cx = L->cx, *restrict cy = L->cy, *restrict cz = L->cz,
                           *restrict dg = L->diag;
    const unsigned char *restrict act = L->active;
    const size_t row = sy * j + sz * k;
    int i0 = (j + k + colour) & 1;
    int i = i0;
    if (i == 0) {
        if (act[row])
            x[row] = gs_sum(L, x, row, 0, nx, jm, jp, km, kp, sy, sz) / dg[row];
        i += 2;
    }
    for (; i + 1 < nx; i += 2) {
        const size_t c = row + (size_t)i;
        if (!act[c])
            continue;
        double s = b[c];
        s += cx[c - 1] * x[c - 1];
        s += cx[c] * x[c + 1];
        if (jm)
            s += cy[c - sy] * x[c - sy];
        if (jp)
            s += cy[c] * x[c + sy];
        if (km)
            s += cz[c - sz] * x[c - sz];
        if (kp)
            s += cz[c] * x[c + sz];
        x[c] = s / dg[c];
    }
    if (i < nx) { /* i = nx - 1 */
        const size_t c = row + (size_t)i;
        if (act[c])
            x[c] = gs_sum(L, x, c, i, nx, jm, jp, km, kp, sy, sz) / dg[c];
    }
}

/* One Gauss-Seidel half-sweep over the cells of one colour. */
static void gs_colour(mg_level *L, int colour)
{
    const int ny = L->n[1], nz = L->n[2];
    #pragma omp parallel for schedule(dynamic, 1) if (L->nc >= MG_PAR_MIN)
    for (int k = 0; k < nz; k++)
        for (int j = 0; j < ny; j++)
            gs_row(L, j, k, colour);
}

/* (A x)_c of cell c by the generic rule (the ends of a row). */
static inline double apply_cell(const mg_level *L, const double *restrict x, size_t c, int i, int nx, int jm,
                                int jp, int km, int kp, size_t sy, size_t sz)
{
    double s = L->diag[c] * x[c];
    if (i > 0)
        s -= L->cx[c - 1] * x[c - 1];
    if (i + 1 < nx)
        s -= L->cx[c] * x[c + 1];
    if (jm)
        s -= L->cy[c - sy] * x[c - sy];
    if (jp)
        s -= L->cy[c] * x[c + sy];
    if (km)
        s -= L->cz[c - sz] * x[c - sz];
    if (kp)
        s -= L->cz[c] * x[c + sz];
    return s;
}

/* One row of y = A x, or with b of r = b - A x (0 at inactive cells). */
static inline void apply_row(const mg_level *L, const double *restrict x, const double *restrict b,
                             double *restrict y, int j, int k)
{
    const int nx = L->n[0], ny = L->n[1], nz = L->n[2];
    const size_t sy = (size_t)nx, sz = (size_t)nx * ny;
    const int jm = j > 0, jp = j + 1 < ny, km = k > 0, kp = k + 1 < nz;
    const double *restrict cx = L->cx, *restrict cy = L->cy, *restrict cz = L->cz, *restrict dg = L->diag;
    const unsigned char *restrict act = L->active;
    const size_t row = sy * j + sz * k;
    if (jm && jp && km && kp && nx > 2) {
        /* an interior row: the ends by the generic rule, the rest in one
         * branch-free loop the compiler vectorises (the same operations
         * per cell in the same order) */
        for (int e = 0; e < 2; e++) {
            const int i = e ? nx - 1 : 0;
            const size_t c = row + (size_t)i;
            const double s = apply_cell(L, x, c, i, nx, 1, 1, 1, 1, sy, sz);
            y[c] = act[c] ? (b ? b[c] - s : s) : 0.0;
        }
        const double *restrict xr = x + row, *restrict cxr = cx + row, *restrict dgr = dg + row;
        const double *restrict cyr = cy + row, *restrict cym = cy + row - sy, *restrict czr = cz + row,
                               *restrict czm = cz + row - sz;
        const unsigned char *restrict ar = act + row;
        double *restrict yr = y + row;
        if (b) {
            const double *restrict br = b + row;
            for (int i = 1; i + 1 < nx; i++) {
                double s = dgr[i] * xr[i];
                s -= cxr[i - 1] * xr[i - 1];
                s -= cxr[i] * xr[i + 1];
                s -= cym[i] * xr[(ptrdiff_t)i - (ptrdiff_t)sy];
                s -= cyr[i] * xr[i + sy];
                s -= czm[i] * xr[(ptrdiff_t)i - (ptrdiff_t)sz];
                s -= czr[i] * xr[i + sz];
                yr[i] = ar[i] ? br[i] - s : 0.0;
            }
        } else {
            for (int i = 1; i + 1 < nx; i++) {
                double s = dgr[i] * xr[i];
                s -= cxr[i - 1] * xr[i - 1];
                s -= cxr[i] * xr[i + 1];
                s -= cym[i] * xr[(ptrdiff_t)i - (ptrdiff_t)sy];
                s -= cyr[i] * xr[i + sy];
                s -= czm[i] * xr[(ptrdiff_t)i - (ptrdiff_t)sz];
                s -= czr[i] * xr[i + sz];
                yr[i] = ar[i] ? s : 0.0;
            }
        }
        return;
    }
    for (int i = 0; i < nx; i++) {
        const size_t c = row + (size_t)i;
        double s;
        if (i == 0 || i + 1 == nx) {
            s = apply_cell(L, x, c, i, nx, jm, jp, km, kp, sy, sz);
        } else {
            s = dg[c] * x[c];
            s -= cx[c - 1] * x[c - 1];
            s -= cx[c] * x[c + 1];
            if (jm)
                s -= cy[c - sy] * x[c - sy];
            if (jp)
                s -= cy[c] * x[c + sy];
            if (km)
                s -= cz[c - sz] * x[c - sz];
            if (kp)
                s -= cz[c] * x[c + sz];
        }
        if (b)
            y[c] = act[c] ? b[c] - s : 0.0;
        else
            y[c] = act[c] ? s : 0.0;
    }
}

/* y = A x on a level. */
static void apply(const mg_level *L, const double *x, double *y)
{
    #pragma omp parallel for schedule(dynamic, 1) if (L->nc >= MG_PAR_MIN)
    for (int k = 0; k < L->n[2]; k++)
        for (int j = 0; j < L->n[1]; j++)
            apply_row(L, x, NULL, y, j, k);
}

/* r = b - A x on a level (0 at inactive cells), in one pass. */
static void residual_lv(mg_level *L)
{
    #pragma omp parallel for schedule(dynamic, 1) if (L->nc >= MG_PAR_MIN)
    for (int k = 0; k < L->n[2]; k++)
        for (int j = 0; j < L->n[1]; j++)
            apply_row(L, L->x, L->b, L->r, j, k);
}

/* Two half-sweeps, colour first then the other, in one pass over the
 * planes: the second colour's plane k - 1 follows the first's plane k, by
 * when all its first-colour neighbours (planes k - 2 .. k) are done. Each
 * thread takes a block of planes; the second colour on a block's two end
 * planes, whose first-colour neighbours lie in the next blocks, waits for
 * a barrier. The same values as gs_colour(first), gs_colour(other) (each
 * colour reads only the other's), in about half the passes over memory. */
static void gs_pair(mg_level *L, int first)
{
    const int ny = L->n[1], nz = L->n[2], second = first ^ 1;
    #pragma omp parallel if (L->nc >= MG_PAR_MIN)
    {
        int t = 0, nt = 1;
#ifdef _OPENMP
        t = omp_get_thread_num();
        nt = omp_get_num_threads();
#endif
        const int k0 = (int)((long)nz * t / nt), k1 = (int)((long)nz * (t + 1) / nt);
        for (int k = k0; k < k1; k++) {
            for (int j = 0; j < ny; j++)
                gs_row(L, j, k, first);
            if (k - 1 > k0)
                for (int j = 0; j < ny; j++)
                    gs_row(L, j, k - 1, second);
        }
        #pragma omp barrier
        if (k1 > k0)
            for (int j = 0; j < ny; j++)
                gs_row(L, j, k0, second);
        if (k1 - 1 > k0)
            for (int j = 0; j < ny; j++)
                gs_row(L, j, k1 - 1, second);
    }
}

static void vcycle(cfd_mg *m, int l)
{
    mg_level *L = &m->lev[l];
    if (l == m->nlev - 1) {
        for (int it = 0; it < 40; it++) {
            gs_colour(L, 0);
            gs_colour(L, 1);
        }
        for (int it = 0; it < 40; it++) {
            gs_colour(L, 1);
            gs_colour(L, 0);
        }
        return;
    }
    gs_pair(L, 0);
    residual_lv(L);
    mg_level *C = &m->lev[l + 1];
    #pragma omp parallel for schedule(dynamic, 1) if (L->nc >= MG_PAR_MIN)
    for (int K = 0; K < C->n[2]; K++)
        for (int J = 0; J < C->n[1]; J++)
            for (int I = 0; I < C->n[0]; I++) {
                double s = 0.0;
                int i0 = child0(L, 0, I), j0 = child0(L, 1, J), k0 = child0(L, 2, K);
                int ni = nchild(L, 0, I), nj = nchild(L, 1, J), nk = nchild(L, 2, K);
                for (int k = k0; k < k0 + nk; k++)
                    for (int j = j0; j < j0 + nj; j++)
                        for (int i = i0; i < i0 + ni; i++)
                            s += L->r[LIDX(L, i, j, k)];
                size_t cc = LIDX(C, I, J, K);
                C->b[cc] = s;
                C->x[cc] = 0.0;
            }
    vcycle(m, l + 1);
    #pragma omp parallel for schedule(dynamic, 1) if (L->nc >= MG_PAR_MIN)
    for (int k = 0; k < L->n[2]; k++)
        for (int j = 0; j < L->n[1]; j++)
            for (int i = 0; i < L->n[0]; i++) {
                size_t c = LIDX(L, i, j, k);
                if (!L->active[c])
                    continue;
                int I = L->n[0] > 1 ? i / 2 : i, J = L->n[1] > 1 ? j / 2 : j, K = L->n[2] > 1 ? k / 2 : k;
                L->x[c] += C->x[LIDX(C, I, J, K)];
            }
    gs_pair(L, 1);
}

static double dot(const double *a, const double *b, size_t n)
{
    double s = 0.0;
    #pragma omp parallel for reduction(+ : s) schedule(static)
    for (size_t c = 0; c < n; c++)
        s += a[c] * b[c];
    return s;
}

static void remove_mean(const mg_level *L, double *v)
{
    double s = 0.0, cnt = 0.0;
    #pragma omp parallel for reduction(+ : s, cnt) schedule(static)
    for (size_t c = 0; c < L->nc; c++)
        if (L->active[c])
            s += v[c], cnt += 1.0;
    if (cnt == 0.0)
        return;
    double mean = s / cnt;
    #pragma omp parallel for schedule(static)
    for (size_t c = 0; c < L->nc; c++)
        if (L->active[c])
            v[c] -= mean;
}

/* z = M^-1 r: one V-cycle from zero, run in place on r and z (the fine
 * level's b and x point at them for the cycle). */
static void precond(cfd_mg *m, const double *r, double *z)
{
    mg_level *L = &m->lev[0];
    double *b0 = L->b, *x0 = L->x;
    L->b = (double *)r;
    L->x = z;
    memset(z, 0, L->nc * sizeof(double));
    vcycle(m, 0);
    L->b = b0;
    L->x = x0;
    if (m->singular)
        remove_mean(L, z);
}

/* q = A p and the return p . q in one pass. */
static double apply_dot(const mg_level *L, const double *p, double *q)
{
    double s = 0.0;
    #pragma omp parallel for reduction(+ : s) schedule(static, 1)
    for (int k = 0; k < L->n[2]; k++)
        for (int j = 0; j < L->n[1]; j++) {
            apply_row(L, p, NULL, q, j, k);
            const size_t row = (size_t)L->n[0] * ((size_t)j + (size_t)L->n[1] * k);
            for (int i = 0; i < L->n[0]; i++)
                s += p[row + i] * q[row + i];
        }
    return s;
}

int cfd_mg_solve(cfd_mg *m, double *x, const double *b, double rtol, int maxit, double *rel_res)
{
    mg_level *L = &m->lev[0];
    size_t n = L->nc;
    double *r = m->r, *z = m->z, *p = m->p, *q = m->q;
    apply(L, x, q);
    #pragma omp parallel for schedule(static)
    for (size_t c = 0; c < n; c++)
        r[c] = L->active[c] ? b[c] - q[c] : 0.0;
    if (m->singular)
        remove_mean(L, r);
    double bn = sqrt(dot(b, b, n));
    double rn = sqrt(dot(r, r, n));
    if (bn == 0.0)
        bn = 1.0;
    int it = 0;
    if (rn > rtol * bn) {
        precond(m, r, z);
        memcpy(p, z, n * sizeof(double));
        double rz = dot(r, z, n);
        for (it = 1; it <= maxit; it++) {
            double pq = apply_dot(L, p, q);
            if (!(pq > 0.0))
                break;
            double alpha = rz / pq;
            double rr = 0.0;
            #pragma omp parallel for reduction(+ : rr) schedule(static)
            for (size_t c = 0; c < n; c++) {
                x[c] += alpha * p[c];
                double rc = r[c] - alpha * q[c];
                r[c] = rc;
                rr += rc * rc;
            }
            rn = sqrt(rr);
            if (rn <= rtol * bn)
                break;
            precond(m, r, z);
            double rz1 = dot(r, z, n);
            double beta = rz1 / rz;
            rz = rz1;
            #pragma omp parallel for schedule(static)
            for (size_t c = 0; c < n; c++)
                p[c] = z[c] + beta * p[c];
        }
    }
    if (rel_res)
        *rel_res = rn / bn;
    return it;
}
