/* test_cfd_sample.c -- the trilinear sampler (cfd_sample_arrays, cfd/grid.c)
 * with its O(1) cell lookup against the binary search and corner loop it
 * replaced (kept here as the reference), bit for bit: stretched axes as the
 * airwake builds them, a strongly graded one, one- and two-cell axes, and
 * points inside, outside (clamped), on centres and nodes, one ulp either
 * side of a centre, and not finite. */
#include "cfd_private.h" /* the private sampler and the grid's tables */
#include "check.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define NARR CFD_NVARS

/* The reference: the sampler as a binary search and a loop over corners and axes. */
static void ref_sample(const cfd_grid *g, double *const *arr, int narr, const double pos[3], double *out)
{
    int i0[3];
    double f[3];
    for (int d = 0; d < 3; d++)
        cfd_axis_locate(g->xc[d], g->n[d], pos[d], &i0[d], &f[d]);
    for (int v = 0; v < narr; v++)
        out[v] = 0.0;
    for (int c8 = 0; c8 < 8; c8++) {
        int ii[3];
        double w = 1.0;
        for (int d = 0; d < 3; d++) {
            int up = (c8 >> d) & 1;
            if (g->n[d] == 1) {
                if (up)
                    w = 0.0;
                ii[d] = 0;
                continue;
            }
            ii[d] = i0[d] + up;
            w *= up ? f[d] : 1.0 - f[d];
        }
        if (w == 0.0)
            continue;
        size_t c = CFD_IDX(g, ii[0], ii[1], ii[2]);
        for (int v = 0; v < narr; v++)
            out[v] += w * arr[v][c];
    }
}

static uint64_t rng = 0x1234567ull;
static double urand(void) /* [0, 1) */
{
    rng = rng * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(rng >> 11) * 0x1.0p-53;
}

/* The same bits, NaN matching any NaN. */
static int same(const double *a, const double *b, int n)
{
    for (int i = 0; i < n; i++)
        if (!(isnan(a[i]) && isnan(b[i])) && memcmp(&a[i], &b[i], sizeof a[i]) != 0)
            return 0;
    return 1;
}

/* One coordinate along axis d: a random kind of point. */
static double coord(const cfd_grid *g, int d)
{
    const double *xc = g->xc[d], *xn = g->xn[d];
    int n = g->n[d];
    double lo = xn[0], hi = xn[n], r = urand();
    int i = (int)(urand() * n);
    if (r < 0.5)
        return lo - 0.05 * (hi - lo) + 1.1 * (hi - lo) * urand(); /* inside and a little outside */
    if (r < 0.6)
        return xc[i];
    if (r < 0.7)
        return xn[i + (urand() < 0.5)];
    if (r < 0.8)
        return nextafter(xc[i], -INFINITY);
    if (r < 0.9)
        return nextafter(xc[i], INFINITY);
    if (r < 0.93)
        return NAN;
    if (r < 0.96)
        return urand() < 0.5 ? -INFINITY : INFINITY;
    return urand() < 0.5 ? xc[0] : xc[n - 1];
}

static void check_grid(const char *what, cfd_grid *g, long npts)
{
    int n[3];
    cfd_grid_dims(g, n);
    size_t nc = cfd_grid_cells(g);
    double *arr[NARR];
    for (int v = 0; v < NARR; v++) {
        arr[v] = malloc(nc * sizeof(double));
        for (size_t c = 0; c < nc; c++)
            arr[v][c] = 40.0 * urand() - 20.0;
    }
    int tables = 0;
    for (int d = 0; d < 3; d++)
        tables += g->lut[d] != NULL;
    long bad = 0;
    for (long p = 0; p < npts; p++) {
        double pos[3] = {coord(g, 0), coord(g, 1), coord(g, 2)}, a[NARR], b[NARR];
        ref_sample(g, arr, NARR, pos, a);
        cfd_sample_arrays(g, arr, NARR, pos, b);
        int nv = 1 + (int)(urand() * NARR); /* fewer arrays too */
        double c[NARR];
        cfd_sample_arrays(g, arr, nv, pos, c);
        if (!same(a, b, NARR) || !same(a, c, nv)) {
            if (bad < 3)
                fprintf(stderr, "%s: (%.17g, %.17g, %.17g): u %.17g, reference %.17g\n", what, pos[0], pos[1],
                        pos[2], b[0], a[0]);
            bad++;
        }
    }
    CHECK(bad == 0);
    printf("%s: %d x %d x %d cells, %d axes by table: %ld points, %ld differ from the binary search's bits\n", what,
           n[0], n[1], n[2], tables, npts, bad);
    for (int v = 0; v < NARR; v++)
        free(arr[v]);
}

int main(void)
{
    core_err err = {0};
    /* the airwake's kind of grid: fine over the ship, stretched outwards */
    cfd_axis_spec airwake[3] = {{-250.0, 150.0, -90.0, 20.0, 1.0, 16.0, 1.12},
                                {-120.0, 120.0, -15.0, 15.0, 1.0, 16.0, 1.12},
                                {-60.0, 10.0, -25.0, 5.0, 0.5, 8.0, 1.1}};
    cfd_grid *g = cfd_grid_create_spec(airwake, &err);
    CHECK(g != NULL);
    if (g) {
        for (int d = 0; d < 3; d++)
            CHECK(g->lut[d] != NULL); /* the tables are what is tested */
        check_grid("airwake grid", g, 300000);
        cfd_grid_destroy(g);
    }
    /* strongly graded: each cell 1.5 times the last (the table's buckets
     * then span many of the small cells' widths at most 16 per cell) */
    double xg[41], y2[3] = {0.0, 1.0, 3.0}, z1[2] = {-1.0, 2.0};
    xg[0] = 0.0;
    for (int i = 1; i <= 40; i++)
        xg[i] = xg[i - 1] + 1e-3 * pow(1.5, i);
    g = cfd_grid_create(xg, 40, y2, 2, z1, 1, &err);
    CHECK(g != NULL);
    if (g) {
        CHECK(g->lut[0] != NULL && g->lut[1] != NULL && g->lut[2] == NULL);
        check_grid("graded x, two-cell y, one-cell z", g, 200000);
        cfd_grid_destroy(g);
    }
    /* one cell on two axes */
    double x3[4] = {0.0, 0.1, 0.5, 2.0};
    g = cfd_grid_create(z1, 1, x3, 3, z1, 1, &err);
    CHECK(g != NULL);
    if (g) {
        check_grid("one-cell x and z", g, 50000);
        cfd_grid_destroy(g);
    }
    return check_done("test_cfd_sample");
}
