/*
 * grid.c -- structured Cartesian grid with per-axis stretching and blocked
 * cells.
 *
 * Model: each axis has a focus interval [f0, f1] of uniform spacing h_fine
 * (the role of the seed paper's mesh density box, section 2.6) and cells
 * growing geometrically (ratio `growth`, at most h_max) toward both domain
 * ends; the outer widths are scaled so that the last node lands on the
 * domain end. A solid body is represented by blocked cells: a cell is solid
 * when its centre lies inside (a staircase of the body; its faces are walls).
 */
#include "cfd_private.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Widths marching away from the focus over a length `len`, scaled to fit. */
static int outer_widths(double len, double h0, double growth, double hmax, double **w, int *n)
{
    *w = NULL;
    *n = 0;
    if (len <= 1e-12)
        return 0;
    int cap = 16;
    double *a = malloc(cap * sizeof *a);
    if (!a)
        return -1;
    double sum = 0.0, h = h0;
    int m = 0;
    while (sum < len - 0.5 * h) {
        h = fmin(h * growth, hmax);
        if (m == cap) {
            cap *= 2;
            double *t = realloc(a, cap * sizeof *a);
            if (!t) {
                free(a);
                return -1;
            }
            a = t;
        }
        a[m++] = h;
        sum += h;
    }
    if (m == 0) {
        a[m++] = len;
        sum = len;
    }
    for (int i = 0; i < m; i++)
        a[i] *= len / sum;
    *w = a;
    *n = m;
    return 0;
}

int cfd_axis_build(const cfd_axis_spec *s, double **nodes, int *n, core_err *err)
{
    *nodes = NULL;
    *n = 0;
    if (!(s->hi_m > s->lo_m) || !(s->h_fine_m > 0.0) || !(s->growth >= 1.0) ||
        !(s->h_max_m >= s->h_fine_m))
        return core_err_set(err, -1,
                            "cfd grid axis: expected lo < hi, h_fine > 0, growth >= 1, h_max >= h_fine "
                            "(got lo %g hi %g h_fine %g growth %g h_max %g)",
                            s->lo_m, s->hi_m, s->h_fine_m, s->growth, s->h_max_m);
    double f0 = fmax(s->lo_m, fmin(s->f0_m, s->f1_m)), f1 = fmin(s->hi_m, fmax(s->f0_m, s->f1_m));
    if (f1 <= f0) { /* no focus inside: uniform at h_fine from the middle */
        f0 = f1 = 0.5 * (s->lo_m + s->hi_m);
    }
    int nf = (f1 > f0) ? (int)ceil((f1 - f0) / s->h_fine_m - 1e-9) : 0;
    double hf = nf ? (f1 - f0) / nf : s->h_fine_m;
    double *wl = NULL, *wr = NULL;
    int nl = 0, nr = 0;
    double growth = s->growth > 1.0 ? s->growth : 1.0;
    if (outer_widths(f0 - s->lo_m, hf, growth, s->h_max_m, &wl, &nl) ||
        outer_widths(s->hi_m - f1, hf, growth, s->h_max_m, &wr, &nr)) {
        free(wl);
        free(wr);
        return core_err_set(err, -2, "cfd grid axis: out of memory");
    }
    int cells = nl + nf + nr;
    if (cells > 100000) {
        free(wl);
        free(wr);
        return core_err_set(err, -1, "cfd grid axis: %d cells on one axis is too many", cells);
    }
    double *x = malloc((cells + 1) * sizeof *x);
    if (!x) {
        free(wl);
        free(wr);
        return core_err_set(err, -2, "cfd grid axis: out of memory");
    }
    int m = 0;
    x[m++] = s->lo_m;
    for (int i = nl - 1; i >= 0; i--, m++)
        x[m] = x[m - 1] + wl[i];
    for (int i = 0; i < nf; i++, m++)
        x[m] = f0 + (i + 1) * hf;
    for (int i = 0; i < nr; i++, m++)
        x[m] = x[m - 1] + wr[i];
    x[cells] = s->hi_m;
    free(wl);
    free(wr);
    *nodes = x;
    *n = cells;
    return 0;
}

/* The lookup table of axis d (cfd_sample_arrays): equal buckets about as
 * wide as the narrowest centre spacing (at most LUT_PER_CELL per cell),
 * each holding the last centre at or below its start, so that a point
 * lies within a step or two of the centre the table gives. Axes of one
 * cell or centres not strictly increasing keep the binary search (NULL).
 * Returns -1 out of memory. */
#define LUT_PER_CELL 16

static int axis_lut_build(cfd_grid *g, int d)
{
    const int n = g->n[d];
    const double *xc = g->xc[d];
    if (n < 2)
        return 0;
    double hmin = INFINITY;
    for (int i = 0; i + 1 < n; i++)
        hmin = fmin(hmin, xc[i + 1] - xc[i]);
    double span = xc[n - 1] - xc[0];
    if (!(hmin > 0.0) || !isfinite(span))
        return 0;
    double nb = fmin(ceil(span / hmin), (double)LUT_PER_CELL * (n - 1));
    int nbi = (int)fmax(nb, 1.0);
    int *lut = malloc(((size_t)nbi + 1) * sizeof *lut);
    if (!lut)
        return -1;
    int lo = 0;
    for (int b = 0; b <= nbi; b++) {
        double x = xc[0] + span * ((double)b / nbi);
        while (lo + 1 < n - 1 && xc[lo + 1] <= x)
            lo++;
        lut[b] = lo;
    }
    g->lut[d] = lut;
    g->lut_n[d] = nbi;
    g->lut_inv[d] = nbi / span;
    return 0;
}

cfd_grid *cfd_grid_create(const double *xn, int nx, const double *yn, int ny, const double *zn,
                          int nz, core_err *err)
{
    const double *in[3] = {xn, yn, zn};
    int nn[3] = {nx, ny, nz};
    for (int d = 0; d < 3; d++) {
        if (nn[d] < 1 || !in[d]) {
            core_err_set(err, -1, "cfd grid: axis %d needs at least one cell (got %d)", d, nn[d]);
            return NULL;
        }
        for (int i = 0; i < nn[d]; i++)
            if (!(in[d][i + 1] > in[d][i])) {
                core_err_set(err, -1, "cfd grid: axis %d nodes must increase (node %d: %g, %g)", d, i,
                             in[d][i], in[d][i + 1]);
                return NULL;
            }
    }
    cfd_grid *g = calloc(1, sizeof *g);
    if (!g)
        goto oom;
    g->ncell = (size_t)nx * ny * nz;
    for (int d = 0; d < 3; d++) {
        g->n[d] = nn[d];
        g->xn[d] = malloc((nn[d] + 1) * sizeof(double));
        g->xc[d] = malloc(nn[d] * sizeof(double));
        g->h[d] = malloc(nn[d] * sizeof(double));
        if (!g->xn[d] || !g->xc[d] || !g->h[d])
            goto oom;
        memcpy(g->xn[d], in[d], (nn[d] + 1) * sizeof(double));
        for (int i = 0; i < nn[d]; i++) {
            g->xc[d][i] = 0.5 * (in[d][i] + in[d][i + 1]);
            g->h[d][i] = in[d][i + 1] - in[d][i];
        }
    }
    g->solid = calloc(g->ncell, 1);
    if (!g->solid)
        goto oom;
    for (int d = 0; d < 3; d++)
        if (axis_lut_build(g, d))
            goto oom;
    return g;
oom:
    cfd_grid_destroy(g);
    core_err_set(err, -2, "cfd grid: out of memory");
    return NULL;
}

cfd_grid *cfd_grid_create_spec(const cfd_axis_spec spec[3], core_err *err)
{
    double *x[3] = {NULL, NULL, NULL};
    int n[3];
    cfd_grid *g = NULL;
    for (int d = 0; d < 3; d++)
        if (cfd_axis_build(&spec[d], &x[d], &n[d], err))
            goto out;
    g = cfd_grid_create(x[0], n[0], x[1], n[1], x[2], n[2], err);
out:
    for (int d = 0; d < 3; d++)
        free(x[d]);
    return g;
}

void cfd_grid_destroy(cfd_grid *g)
{
    if (!g)
        return;
    for (int d = 0; d < 3; d++) {
        free(g->xn[d]);
        free(g->xc[d]);
        free(g->h[d]);
        free(g->lut[d]);
    }
    free(g->solid);
    free(g);
}

size_t cfd_grid_block_ship(cfd_grid *g, const core_ship *ship)
{
    size_t count = 0;
    for (int k = 0; k < g->n[2]; k++)
        for (int j = 0; j < g->n[1]; j++)
            for (int i = 0; i < g->n[0]; i++) {
                core_vec3 p = core_vec3_make(g->xc[0][i], g->xc[1][j], g->xc[2][k]);
                if (core_ship_contains(ship, p)) {
                    g->solid[CFD_IDX(g, i, j, k)] = 1;
                    count++;
                }
            }
    return count;
}

size_t cfd_grid_block_box(cfd_grid *g, const double lo[3], const double hi[3])
{
    size_t count = 0;
    for (int k = 0; k < g->n[2]; k++)
        for (int j = 0; j < g->n[1]; j++)
            for (int i = 0; i < g->n[0]; i++) {
                double c[3] = {g->xc[0][i], g->xc[1][j], g->xc[2][k]};
                if (c[0] > lo[0] && c[0] < hi[0] && c[1] > lo[1] && c[1] < hi[1] && c[2] > lo[2] &&
                    c[2] < hi[2]) {
                    g->solid[CFD_IDX(g, i, j, k)] = 1;
                    count++;
                }
            }
    return count;
}

void cfd_grid_dims(const cfd_grid *g, int n[3])
{
    for (int d = 0; d < 3; d++)
        n[d] = g->n[d];
}

size_t cfd_grid_cells(const cfd_grid *g) { return g->ncell; }

size_t cfd_grid_fluid_cells(const cfd_grid *g)
{
    size_t n = 0;
    for (size_t c = 0; c < g->ncell; c++)
        n += !g->solid[c];
    return n;
}

const double *cfd_grid_nodes(const cfd_grid *g, int d) { return g->xn[d]; }
const double *cfd_grid_centres(const cfd_grid *g, int d) { return g->xc[d]; }
const unsigned char *cfd_grid_solid(const cfd_grid *g) { return g->solid; }

void cfd_axis_locate(const double *xc, int n, double x, int *i0, double *f)
{
    if (n == 1 || x <= xc[0]) {
        *i0 = 0;
        *f = 0.0;
        return;
    }
    if (x >= xc[n - 1]) {
        *i0 = n - 2;
        *f = 1.0;
        return;
    }
    int lo = 0, hi = n - 1;
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (xc[mid] <= x)
            lo = mid;
        else
            hi = mid;
    }
    *i0 = lo;
    *f = (x - xc[lo]) / (xc[lo + 1] - xc[lo]);
}

/* cfd_axis_locate through axis d's table: the walk from the bucket's
 * centre ends at the one lo with xc[lo] <= x < xc[lo + 1], the binary
 * search's, and f is computed the same way. */
static void axis_locate_lut(const cfd_grid *g, int d, double x, int *i0, double *f)
{
    const double *xc = g->xc[d];
    const int n = g->n[d];
    if (!g->lut[d] || x <= xc[0] || x >= xc[n - 1]) {
        cfd_axis_locate(xc, n, x, i0, f); /* also one cell, and the clamps */
        return;
    }
    double u = (x - xc[0]) * g->lut_inv[d];
    int b = u >= 0.0 ? (u < g->lut_n[d] ? (int)u : g->lut_n[d]) : 0; /* NaN: 0 */
    int lo = g->lut[d][b];
    while (lo > 0 && xc[lo] > x)
        lo--;
    while (lo < n - 2 && xc[lo + 1] <= x)
        lo++;
    *i0 = lo;
    *f = (x - xc[lo]) / (xc[lo + 1] - xc[lo]);
}

/* The common case: a point strictly inside the centres of three tabled
 * axes; the eight corners' weights written out in the loop's order. */
static int sample_inside(const cfd_grid *g, double *const *arr, int narr, const double pos[3], double *out)
{
    int i0[3];
    double f[3];
    for (int d = 0; d < 3; d++) {
        const double *xc = g->xc[d];
        const int n = g->n[d];
        double x = pos[d];
        if (!g->lut[d] || !(x > xc[0] && x < xc[n - 1]))
            return 0;
        double u = (x - xc[0]) * g->lut_inv[d];
        int lo = g->lut[d][u < g->lut_n[d] ? (int)u : g->lut_n[d]];
        while (lo > 0 && xc[lo] > x)
            lo--;
        while (lo < n - 2 && xc[lo + 1] <= x)
            lo++;
        i0[d] = lo;
        f[d] = (x - xc[lo]) / (xc[lo + 1] - xc[lo]);
    }
    const double x0 = 1.0 - f[0], x1 = f[0], y0 = 1.0 - f[1], y1 = f[1], z0 = 1.0 - f[2], z1 = f[2];
    const double w[8] = {x0 * y0 * z0, x1 * y0 * z0, x0 * y1 * z0, x1 * y1 * z0,
                         x0 * y0 * z1, x1 * y0 * z1, x0 * y1 * z1, x1 * y1 * z1};
    const size_t sy = (size_t)g->n[0], sz = (size_t)g->n[0] * (size_t)g->n[1];
    const size_t b = CFD_IDX(g, i0[0], i0[1], i0[2]);
    const size_t off[8] = {b, b + 1, b + sy, b + sy + 1, b + sz, b + sz + 1, b + sy + sz, b + sy + sz + 1};
    if (w[0] != 0.0 && w[1] != 0.0 && w[2] != 0.0 && w[3] != 0.0 && w[4] != 0.0 && w[5] != 0.0 && w[6] != 0.0 &&
        w[7] != 0.0) {
        for (int v = 0; v < narr; v++) {
            const double *a = arr[v];
            double s = 0.0;
            s += w[0] * a[off[0]];
            s += w[1] * a[off[1]];
            s += w[2] * a[off[2]];
            s += w[3] * a[off[3]];
            s += w[4] * a[off[4]];
            s += w[5] * a[off[5]];
            s += w[6] * a[off[6]];
            s += w[7] * a[off[7]];
            out[v] = s;
        }
        return 1;
    }
    for (int v = 0; v < narr; v++) { /* on a centre plane: zero weights left out */
        const double *a = arr[v];
        double s = 0.0;
        for (int c = 0; c < 8; c++)
            if (w[c] != 0.0)
                s += w[c] * a[off[c]];
        out[v] = s;
    }
    return 1;
}

/* The eight corners in the order c8 = up_x + 2 up_y + 4 up_z, each weight
 * the product (w_x w_y) w_z as the corner loop forms it, corners of zero
 * weight left out, the arrays summed corner by corner in that order: the
 * bits of the loop over corners and axes, in one pass over each array. */
void cfd_sample_arrays(const cfd_grid *g, double *const *arr, int narr, const double pos[3], double *out)
{
    if (sample_inside(g, arr, narr, pos, out))
        return;
    int i0[3];
    double f[3];
    for (int d = 0; d < 3; d++)
        axis_locate_lut(g, d, pos[d], &i0[d], &f[d]);
    double w1[3][2];
    size_t st[3] = {1, (size_t)g->n[0], (size_t)g->n[0] * (size_t)g->n[1]};
    int nup[3];
    for (int d = 0; d < 3; d++) {
        w1[d][0] = 1.0 - f[d];
        w1[d][1] = f[d];
        nup[d] = g->n[d] == 1 ? 1 : 2; /* one cell: no upper corner */
        if (g->n[d] == 1)
            w1[d][0] = 1.0;
    }
    double w[8];
    size_t off[8];
    int nc = 0;
    size_t base = CFD_IDX(g, i0[0], i0[1], i0[2]);
    for (int c8 = 0; c8 < 8; c8++) {
        int ux = c8 & 1, uy = (c8 >> 1) & 1, uz = (c8 >> 2) & 1;
        if (ux >= nup[0] || uy >= nup[1] || uz >= nup[2])
            continue;
        double wc = w1[0][ux] * w1[1][uy] * w1[2][uz];
        if (wc == 0.0)
            continue;
        w[nc] = wc;
        off[nc] = base + ux * st[0] + uy * st[1] + uz * st[2];
        nc++;
    }
    for (int v = 0; v < narr; v++) {
        const double *a = arr[v];
        double s = 0.0;
        for (int c = 0; c < nc; c++)
            s += w[c] * a[off[c]];
        out[v] = s;
    }
}
