/* bench_case.c -- the driver of bench_case.h, compiled once per solver:
 * BENCH_CASE_FN names it (bench_case_new, or bench_case_base with the
 * baseline's headers and its names renamed by the rename.h that
 * baseline.sh writes). */
#include "cfd.h"

#include "bench_case.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef BENCH_CASE_FN
#error "BENCH_CASE_FN names the driver (bench_case_new or bench_case_base)"
#endif

int BENCH_CASE_FN(const bench_case *bc, bench_out *out)
{
    memset(out, 0, sizeof *out);
    core_err err;
    core_ship ship;
    char path[1024];
    snprintf(path, sizeof path, "%s/%s.ini", bc->ships_dir, bc->ship);
    if (core_ship_load(path, &ship, &err)) {
        snprintf(out->err, sizeof out->err, "%s", err.msg);
        return -1;
    }
    cfd_airwake_spec sp;
    memset(&sp, 0, sizeof sp);
    sp.ship = &ship;
    sp.wod_speed_mps = bc->speed_mps;
    sp.wod_dir_rad = bc->dir_deg * CORE_DEG_TO_RAD;
    sp.level = (core_grid_level)bc->level;
    sp.monitor_z_m = -6.8;
    sp.rotor = bc->rotor;
    sp.max_iter = bc->iters;
    sp.h_fine_m = bc->h_fine_m;
    sp.h_max_m = bc->h_max_m;
    if (bc->minmod) {
        sp.limiter_fixed = 1;
        sp.limiter = CFD_LIMITER_MINMOD;
    }
    if (bc->rotor) {
        double c[3] = {0.0, 0.0, -8.18};
        core_euler att = {0.0, 0.0, 0.0};
        cfd_disk_from_attitude(&sp.disk, c, att, 8.18, 7438.91 * CORE_G_MPS2);
    }
    cfd_solver *s = cfd_airwake_create(&sp, NULL, NULL, NULL, &err);
    if (!s) {
        snprintf(out->err, sizeof out->err, "%s", err.msg);
        return -1;
    }
    cfd_result res;
    int rc = cfd_solver_run(s, &res, &err);
    if (rc < 0) {
        snprintf(out->err, sizeof out->err, "%s", err.msg);
        cfd_solver_destroy(s);
        return -1;
    }
    const cfd_grid *g = cfd_solver_grid(s);
    out->cells = cfd_grid_cells(g);
    out->fluid_cells = cfd_grid_fluid_cells(g);
    out->iterations = res.iterations;
    out->wall_s = res.wall_s;
    out->cell_updates = res.cell_updates;
    memcpy(out->residual, res.residual, sizeof out->residual);
    out->u_ref_mps = cfd_solver_config(s)->u_ref_mps;
    if (bc->keep_fields) {
        for (int v = 0; v < BENCH_NFIELD; v++) {
            out->field[v] = malloc(out->cells * sizeof(double));
            if (!out->field[v]) {
                snprintf(out->err, sizeof out->err, "out of memory");
                cfd_solver_destroy(s);
                return -1;
            }
            memcpy(out->field[v], cfd_solver_var(s, v), out->cells * sizeof(double));
        }
    }
    cfd_solver_destroy(s);
    return 0;
}
