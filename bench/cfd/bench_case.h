/* bench_case.h -- one airwake case run by a fixed number of SIMPLEC
 * iterations, compiled once per solver (bench_case.c): against the live cfd
 * library (bench_case_new; bench_cfd_compare, tests/cfd/test_cfd_same) and
 * against the baseline, the cfd sources at the git tag cfd-baseline
 * (bench_case_base; baseline.sh), so both solvers run the same driver on
 * the same case.
 * Plain types only: the two sides have their own cfd.h. */
#ifndef DISIM_BENCH_CASE_H
#define DISIM_BENCH_CASE_H

#include <stddef.h>

typedef struct bench_case {
    const char *ships_dir; /* scenarios/ships */
    const char *ship;      /* NAME of NAME.ini */
    double speed_mps, dir_deg;
    int level;             /* core_grid_level: 0 coarse, 1 default, 2 fine */
    int rotor;             /* 1: UH-60A actuator disk one radius over the spot */
    int iters;             /* SIMPLEC iterations (the run's max_iter) */
    double h_fine_m, h_max_m; /* > 0: override the level's spacing (small test grids) */
    int keep_fields;       /* 1: copy u, v, w, p, k, eps out (bench_out.field) */
    int minmod;            /* 1: the minmod limiter on every level (else the level's) */
} bench_case;

#define BENCH_NFIELD 6

typedef struct bench_out {
    size_t cells, fluid_cells;
    int iterations;
    double wall_s, cell_updates;
    double residual[5];
    double u_ref_mps;
    double *field[BENCH_NFIELD]; /* keep_fields: ncell values each (free with bench_out_free) */
    char err[1024];
} bench_out;

/* 0 ok (converged or not), < 0 failed (out->err says why). */
int bench_case_new(const bench_case *bc, bench_out *out);
int bench_case_base(const bench_case *bc, bench_out *out);

#include <stdlib.h>
static inline void bench_out_free(bench_out *out)
{
    for (int v = 0; v < BENCH_NFIELD; v++) {
        free(out->field[v]);
        out->field[v] = NULL;
    }
}

#endif
