/* test_cfd_same.c -- the solver's field against the frozen baseline's
 * (bench/cfd/baseline/, the solver before its kernels were rewritten for
 * speed), the same case through the same driver (bench/cfd/bench_case.c):
 * the rewrite changed the speed, not the answer.
 *
 * On one thread the rewrite changed the order of work and, in the TVD
 * deferred correction, the form of the limited difference (psi delta
 * without r: one division or none where there were two), the same value to
 * round-off: every field within 1e-12 of its scale (velocities / u_ref, p /
 * (rho u_ref^2), k / u_ref^2, eps relative) after the iterations; measured
 * 1e-18 .. 2e-14. On two threads the sums of the residuals and of the
 * pressure solver's dot products also split differently between the
 * threads: the same tolerance (measured 2e-14 there; bench_cfd compare
 * gives the same order on the CG-47 default grid). The cases: SFS2 head
 * wind with the rotor, van Leer, 80 iterations (past the 60 from which
 * Anderson acceleration starts where the residuals stall); SFS2 beam wind,
 * no rotor, minmod, where air comes back in through the outlets. */
#include "bench_case.h"
#include "check.h"

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <string.h>

#define RHO_KGPM3 1.225

static double max_diff(const bench_out *a, const bench_out *b, int v)
{
    double U = a->u_ref_mps;
    double scale[BENCH_NFIELD] = {U, U, U, RHO_KGPM3 * U * U, U * U, 0.0};
    double m = 0.0;
    for (size_t c = 0; c < a->cells; c++) {
        double x = a->field[v][c], y = b->field[v][c];
        double d = scale[v] > 0.0 ? fabs(y - x) / scale[v] : fabs(y - x) / fmax(fabs(x), 1e-30);
        if (!(d <= m))
            m = d; /* a NaN counts as the largest */
    }
    return m;
}

static void same(const char *name, const bench_case *bc, int threads, double tol)
{
    omp_set_num_threads(threads);
    bench_out base, now;
    int rb = bench_case_base(bc, &base);
    int rn = bench_case_new(bc, &now);
    CHECK(rb == 0);
    CHECK(rn == 0);
    if (rb || rn) {
        fprintf(stderr, "%s: %s %s\n", name, base.err, now.err);
        bench_out_free(&base);
        bench_out_free(&now);
        return;
    }
    CHECK(base.cells == now.cells && base.cells > 1000);
    CHECK(base.iterations == now.iterations);
    static const char *vn[BENCH_NFIELD] = {"u", "v", "w", "p", "k", "eps"};
    printf("%s (%zu cells, %d threads, %d iterations): largest difference", name, now.cells, threads,
           now.iterations);
    for (int v = 0; v < BENCH_NFIELD; v++) {
        double d = max_diff(&base, &now, v);
        printf(" %s %.1e", vn[v], d);
        CHECK(d <= tol);
    }
    printf("\n");
    for (int q = 0; q < 5; q++)
        CHECK(fabs(now.residual[q] - base.residual[q]) <= 1e3 * tol * fabs(base.residual[q]) + 1e-300);
    bench_out_free(&base);
    bench_out_free(&now);
}

int main(void)
{
    /* the coarse level with 4 m cells in the deck box (under 20,000 cells) */
    bench_case head = {CFD_SHIPS_DIR, "sfs2", 15.0, 0.0, 0, 1, 80, 4.0, 16.0, 1, 0};
    same("SFS2 head wind, rotor, van Leer", &head, 1, 1e-12);
    bench_case beam = {CFD_SHIPS_DIR, "sfs2", 15.0, -90.0, 0, 0, 30, 4.0, 16.0, 1, 1};
    same("SFS2 beam wind, minmod", &beam, 1, 1e-12);
    same("SFS2 beam wind, minmod", &beam, 2, 1e-12);
    return check_done("test_cfd_same");
}
