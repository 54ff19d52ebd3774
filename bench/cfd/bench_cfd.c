/* bench_cfd.c -- the embedded CFD solver's speed and memory.
 *
 *   bench_cfd sidebyside [--ship sfs2|cg47] [--rotor on|off] [--cells N]
 *       [--np N] [--threads N] [--max-iter N] [--keep-case] [--out DIR]
 *       The embedded solver and OpenFOAM on the same case to the same
 *       criterion (sidebyside.c; docs/openfoam.md, "Side by side").
 *   bench_cfd fieldload [--ship NAME] [--grid coarse|default|fine] [--rounds N]
 *       What reading a sealed field costs, and its two checksums' share,
 *       against the baseline CRC-64 in the same run (fieldload.c).
 *   bench_cfd throughput [--threads N] [--iters N]
 *       SFS2 at 0 deg on the coarse grid, a fixed number of SIMPLEC
 *       iterations with 1 thread and with N threads: cell-updates per
 *       second (fluid cells x iterations / wall time), per core, speed-up.
 *   bench_cfd airwake [--grid coarse|default|fine] [--threads N]
 *       [--max-iter N] [--time-limit-s S] [--dir-deg D] [--ship NAME]
 *       [--speed MPS] [--rotor on|off] [--every N] [--seq N]
 *       --seq N: coarse-to-fine start, at most N iterations on the coarse
 *       grid first (counted in the wall time).
 *       SFS2 (or scenarios/ships/NAME.ini), 15 m/s, UH-60A actuator disk (T = m g, R 8.18 m) hovering
 *       one radius over the spot: wall time to convergence (normalised
 *       residuals < 1e-4 and deck-line monitors changing < 2 %), or to the
 *       limit; solver bytes per cell and the process's peak RSS per cell.
 *   bench_cfd warmstart [--ship NAME] [--grid coarse|default] [--dir-deg D]
 *       [--speed MPS] [--rotor on|off] [--threads N] [--max-iter N]
 *       What the airwake builder does for a finer field, against its
 *       baseline, in one invocation: the field on the grid below (quick
 *       below coarse, coarse below default) solved and written, then the
 *       finer one solved from the inflow and from that file
 *       (cfd_field_load, cfd_solver_init_from_field, as awdb's builder):
 *       iterations and wall time of each, the ratios, and the largest
 *       velocity difference between the two finer fields in % of U.
 *   bench_cfd_compare compare [--ship NAME] [--grid coarse|default|fine]
 *       [--rotor on|off] [--dir-deg D] [--speed MPS] [--iters N]
 *       [--threads N] [--rounds N] [--h-fine-m H --h-max-m H]
 *       The present solver against the baseline (the cfd sources at the
 *       git tag cfd-baseline, the solver before the kernel rewrite; the
 *       target bench_cfd_compare builds it with baseline.sh) on the same
 *       case in this one process, alternating (baseline, present) --rounds times: per run
 *       the iterations, wall time, cell-updates/s and final residuals; the
 *       ratio of the best rates; and the largest difference between the
 *       two final fields (velocities / u_ref, p / (rho u_ref^2), k /
 *       u_ref^2, eps relative).
 */
#include "cfd.h"

#include "bench_case.h"
#include "bench_cfd.h"

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

static double wall_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

typedef struct limit {
    double time_limit_s;
    int every;
    const cfd_solver *s; /* set once created: the progress line prints every residual */
} limit;

static int progress(void *user, int iter, int max_iter, double res, double t)
{
    limit *l = user;
    if (l->every && iter % l->every == 0) {
        int n = 0;
        const double *h = l->s ? cfd_solver_history(l->s, &n) : NULL;
        if (h && n > 0) {
            h += (size_t)(n - 1) * 5;
            fprintf(stderr, "  iteration %d/%d residuals cont %.2e u %.2e v %.2e w %.2e k %.2e %.1f s\n", iter,
                    max_iter, h[0], h[1], h[2], h[3], h[4], t);
        } else {
            fprintf(stderr, "  iteration %d/%d residual %.3e %.1f s\n", iter, max_iter, res, t);
        }
    }
    return l->time_limit_s > 0.0 && t > l->time_limit_s;
}

static void log_fn(void *user, int level, const char *msg)
{
    (void)user;
    (void)level;
    fprintf(stderr, "  %s\n", msg);
}

int bench_cfd_setup_ship(core_ship *ship, cfd_airwake_spec *sp, const char *name, double speed_mps,
                         core_grid_level lv, double dir_deg, int rotor)
{
    core_err err;
    char path[1024];
    snprintf(path, sizeof path, "%s/%s.ini", CFD_SHIPS_DIR, name);
    if (core_ship_load(path, ship, &err)) {
        fprintf(stderr, "%s\n", err.msg);
        return -1;
    }
    memset(sp, 0, sizeof *sp);
    sp->ship = ship;
    sp->wod_speed_mps = speed_mps;
    sp->wod_dir_rad = dir_deg * CORE_DEG_TO_RAD;
    sp->level = lv;
    sp->monitor_z_m = -6.8;
    sp->rotor = rotor;
    if (rotor) {
        double c[3] = {0.0, 0.0, -8.18};
        core_euler att = {0.0, 0.0, 0.0};
        cfd_disk_from_attitude(&sp->disk, c, att, 8.18, 7438.91 * CORE_G_MPS2);
    }
    return 0;
}

static int setup(core_ship *ship, cfd_airwake_spec *sp, core_grid_level lv, double dir_deg, int rotor)
{
    return bench_cfd_setup_ship(ship, sp, "sfs2", 15.0, lv, dir_deg, rotor);
}

static double run_iters(int threads, int iters, double *cells)
{
    omp_set_num_threads(threads);
    core_ship ship;
    cfd_airwake_spec sp;
    if (setup(&ship, &sp, CORE_GRID_COARSE, 0.0, 1))
        return -1;
    sp.max_iter = iters;
    core_err err;
    limit l = {0.0, 0, NULL};
    cfd_solver *s = cfd_airwake_create(&sp, NULL, progress, &l, &err);
    if (!s) {
        fprintf(stderr, "%s\n", err.msg);
        return -1;
    }
    cfd_result res;
    cfd_solver_run(s, &res, &err);
    *cells = (double)cfd_grid_fluid_cells(cfd_solver_grid(s));
    cfd_solver_destroy(s);
    return res.cell_updates / res.wall_s;
}

/* Solve sp (from f when not NULL) to convergence; its solver in *out
 * (the caller destroys it). 0, or -1 with the error printed. */
static int solve_case(const cfd_airwake_spec *sp, const cfd_field *f, cfd_solver **out, cfd_result *res)
{
    core_err err;
    limit l = {0.0, 0, NULL};
    cfd_solver *s = cfd_airwake_create(sp, NULL, progress, &l, &err);
    if (!s || (f && cfd_solver_init_from_field(s, f, &err)) || cfd_solver_run(s, res, &err) < 0) {
        fprintf(stderr, "bench_cfd: %s\n", err.msg);
        cfd_solver_destroy(s);
        return -1;
    }
    *out = s;
    return 0;
}

static int warmstart(const char *ship_name, double speed, double dir, int lv, int rotor, int threads, int max_iter)
{
    omp_set_num_threads(threads);
    core_ship ship;
    cfd_airwake_spec fine, below;
    if (lv != CORE_GRID_COARSE && lv != CORE_GRID_DEFAULT) {
        fprintf(stderr, "bench_cfd: warmstart: --grid coarse or default (the grid below: quick, coarse)\n");
        return 2;
    }
    if (bench_cfd_setup_ship(&ship, &fine, ship_name, speed, (core_grid_level)lv, dir, rotor))
        return 1;
    fine.max_iter = max_iter;
    below = fine;
    below.level = lv == CORE_GRID_COARSE ? CORE_GRID_QUICK : CORE_GRID_COARSE;
    char path[] = "/tmp/bench_cfd_warm_XXXXXX";
    int fd = mkstemp(path);
    if (fd < 0) {
        perror("bench_cfd: mkstemp");
        return 1;
    }
    close(fd);
    core_err err;
    cfd_solver *sb = NULL, *cold = NULL, *warm = NULL;
    cfd_field *f = NULL;
    cfd_result rb, rc, rw;
    cfd_meta meta;
    memset(&meta, 0, sizeof meta);
    meta.wod_speed_mps = speed;
    meta.wod_dir_deg = dir;
    snprintf(meta.ship, sizeof meta.ship, "%s", ship.name);
    snprintf(meta.rotor, sizeof meta.rotor, "%s", rotor ? "uh60a" : "off");
    int bad = solve_case(&below, NULL, &sb, &rb) || cfd_solver_write(sb, &meta, path, &err) ||
              !(f = cfd_field_load(path, &err));
    if (bad && err.msg[0])
        fprintf(stderr, "bench_cfd: %s\n", err.msg);
    bad = bad || solve_case(&fine, NULL, &cold, &rc) || solve_case(&fine, f, &warm, &rw);
    unlink(path);
    if (!bad) {
        const cfd_grid *g = cfd_solver_grid(cold);
        const unsigned char *solid = cfd_grid_solid(g);
        size_t n = cfd_grid_cells(g);
        double dmax = 0.0;
        for (int d = CFD_VAR_U; d <= CFD_VAR_W; d++) {
            const double *a = cfd_solver_var(cold, d), *b = cfd_solver_var(warm, d);
            for (size_t i = 0; a && b && i < n; i++)
                if (!solid[i])
                    dmax = fmax(dmax, fabs(a[i] - b[i]));
        }
        printf("warmstart: %s %.1f m/s %.0f deg, rotor %s, %s grid (%zu cells) from the %s grid, %d threads\n",
               ship.name, speed, dir, rotor ? "UH-60A" : "off", core_grid_name((core_grid_level)lv), n,
               core_grid_name(below.level), threads);
        printf("  %-28s %5d iterations %s, %7.1f s\n", "below (the start)", rb.iterations,
               rb.converged ? "converged" : "NOT converged", rb.wall_s);
        printf("  %-28s %5d iterations %s, %7.1f s\n", "finer from the inflow", rc.iterations,
               rc.converged ? "converged" : "NOT converged", rc.wall_s);
        printf("  %-28s %5d iterations %s, %7.1f s\n", "finer from the field below", rw.iterations,
               rw.converged ? "converged" : "NOT converged", rw.wall_s);
        printf("  ratio warm / cold: iterations %.3f, wall %.3f (%.3f with the start's solve)\n",
               (double)rw.iterations / rc.iterations, rw.wall_s / rc.wall_s, (rw.wall_s + rb.wall_s) / rc.wall_s);
        printf("  the two finer fields: largest velocity difference %.3f %% of U\n", 100.0 * dmax / speed);
    }
    cfd_field_destroy(f);
    cfd_solver_destroy(sb);
    cfd_solver_destroy(cold);
    cfd_solver_destroy(warm);
    return bad ? 1 : 0;
}

/* Whole-string numbers within [lo, hi]; 0 ok, 1 bad (the caller names the option). */
static int parse_num(const char *s, double lo, double hi, double *out)
{
    char *end;
    double v = strtod(s, &end);
    if (end == s || *end || !isfinite(v) || v < lo || v > hi)
        return 1;
    *out = v;
    return 0;
}

static int parse_int(const char *s, int lo, int hi, int *out)
{
    char *end;
    long v = strtol(s, &end, 10);
    if (end == s || *end || v < lo || v > hi)
        return 1;
    *out = (int)v;
    return 0;
}

#ifdef BENCH_CFD_BASELINE
static void print_run(const char *who, int round, const bench_out *o)
{
    printf("  %-8s round %d: %d iterations, %.2f s, %.3e cell-updates/s; residuals %.2e %.2e %.2e %.2e %.2e\n", who,
           round, o->iterations, o->wall_s, o->cell_updates / o->wall_s, o->residual[0], o->residual[1],
           o->residual[2], o->residual[3], o->residual[4]);
}

/* The baseline and the present solver side by side (see the file's top). */
static int compare(const bench_case *bc, int threads, int rounds)
{
    omp_set_num_threads(threads);
    double best[2] = {0.0, 0.0}, wall[2] = {1e300, 1e300};
    bench_out last[2];
    memset(last, 0, sizeof last);
    for (int r = 0; r < rounds; r++)
        for (int w = 0; w < 2; w++) {
            bench_out o;
            bench_case c = *bc;
            c.keep_fields = r == rounds - 1;
            int rc = w == 0 ? bench_case_base(&c, &o) : bench_case_new(&c, &o);
            if (rc < 0) {
                fprintf(stderr, "bench_cfd compare: %s: %s\n", w ? "present" : "baseline", o.err);
                bench_out_free(&o);
                bench_out_free(&last[0]);
                return 1;
            }
            if (r == 0 && w == 0)
                printf("compare: %s %.1f m/s %.0f deg, rotor %s, grid level %d, %zu cells (%zu fluid), %d "
                       "iterations at most, %d threads\n",
                       bc->ship, bc->speed_mps, bc->dir_deg, bc->rotor ? "UH-60A" : "off", bc->level, o.cells,
                       o.fluid_cells, bc->iters, threads);
            print_run(w ? "present" : "baseline", r + 1, &o);
            double rate = o.cell_updates / o.wall_s;
            if (rate > best[w])
                best[w] = rate;
            if (o.wall_s < wall[w])
                wall[w] = o.wall_s;
            if (c.keep_fields)
                last[w] = o;
            else
                bench_out_free(&o);
        }
    printf("  best rate: baseline %.3e, present %.3e cell-updates/s: speed-up %.2f\n", best[0], best[1],
           best[1] / best[0]);
    printf("  best wall time: baseline %.2f s (%d iterations), present %.2f s (%d iterations): %.2f x\n", wall[0],
           last[0].iterations, wall[1], last[1].iterations, wall[0] / wall[1]);
    static const char *names[BENCH_NFIELD] = {"u", "v", "w", "p", "k", "eps"};
    double U = last[1].u_ref_mps, rho = CORE_RHO_SL_KGPM3;
    double scale[BENCH_NFIELD] = {U, U, U, rho * U * U, U * U, 0.0};
    printf("  largest field difference, present - baseline:");
    for (int v = 0; v < BENCH_NFIELD; v++) {
        double m = 0.0;
        for (size_t c = 0; c < last[1].cells; c++) {
            double a = last[0].field[v][c], b = last[1].field[v][c];
            double d = scale[v] > 0.0 ? fabs(b - a) / scale[v] : fabs(b - a) / fmax(fabs(a), 1e-30);
            if (!(d <= m))
                m = d;
        }
        printf(" %s %.1e", names[v], m);
    }
    printf(" (velocities / u_ref, p / (rho u_ref^2), k / u_ref^2, eps relative)\n");
    bench_out_free(&last[0]);
    bench_out_free(&last[1]);
    return 0;
}
#else
/* This build has no baseline: bench_cfd_compare has. */
static int compare(const bench_case *bc, int threads, int rounds)
{
    (void)bc;
    (void)threads;
    (void)rounds;
    fprintf(stderr, "bench_cfd compare: this build has no baseline solver: build the target bench_cfd_compare "
                    "(cmake --build BUILD --target bench_cfd_compare: the cfd sources at the git tag "
                    "cfd-baseline) and run bench_cfd_compare compare\n");
    return 2;
}
#endif

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: bench_cfd throughput|airwake|compare|warmstart|sidebyside|fieldload [options]\n");
        return 2;
    }
    if (!strcmp(argv[1], "sidebyside")) {
#ifdef BENCH_CFD_FOAM
        return bench_cfd_sidebyside(argc - 2, argv + 2);
#else
        fprintf(stderr, "bench_cfd sidebyside: this build has no OpenFOAM engine (the foam library)\n");
        return 2;
#endif
    }
    int threads = 2, iters = 50, max_iter = 3000, lv = 1, rotor = 1, every = 100, seq = 0, rounds = 1;
    double tl = 0.0, dir = 0.0, speed = 15.0, h_fine = 0.0, h_max = 0.0;
    const char *ship_name = "sfs2";
    if (strcmp(argv[1], "throughput") && strcmp(argv[1], "airwake") && strcmp(argv[1], "compare") &&
        strcmp(argv[1], "warmstart") && strcmp(argv[1], "fieldload")) {
        fprintf(stderr, "bench_cfd: unknown mode '%s' (expected throughput, airwake, compare, warmstart, sidebyside "
                        "or fieldload)\n",
                argv[1]);
        return 2;
    }
    for (int i = 2; i < argc; i += 2) {
        const char *o = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        int bad = 0;
        if (!v)
            bad = 1;
        else if (!strcmp(o, "--threads"))
            bad = parse_int(v, 1, 256, &threads);
        else if (!strcmp(o, "--iters"))
            bad = parse_int(v, 1, 1000000, &iters);
        else if (!strcmp(o, "--max-iter"))
            bad = parse_int(v, 1, 1000000, &max_iter);
        else if (!strcmp(o, "--time-limit-s"))
            bad = parse_num(v, 0.0, 1e7, &tl);
        else if (!strcmp(o, "--dir-deg"))
            bad = parse_num(v, -180.0, 180.0, &dir);
        else if (!strcmp(o, "--ship"))
            ship_name = v;
        else if (!strcmp(o, "--speed"))
            bad = parse_num(v, 0.1, 100.0, &speed);
        else if (!strcmp(o, "--rotor"))
            bad = !strcmp(v, "on") ? (rotor = 1, 0) : !strcmp(v, "off") ? (rotor = 0, 0) : 1;
        else if (!strcmp(o, "--rounds"))
            bad = parse_int(v, 1, 100, &rounds);
        else if (!strcmp(o, "--h-fine-m"))
            bad = parse_num(v, 0.01, 100.0, &h_fine);
        else if (!strcmp(o, "--h-max-m"))
            bad = parse_num(v, 0.01, 1000.0, &h_max);
        else if (!strcmp(o, "--seq"))
            bad = parse_int(v, 0, 1000000, &seq);
        else if (!strcmp(o, "--every"))
            bad = parse_int(v, 0, 1000000, &every);
        else if (!strcmp(o, "--grid"))
            bad = (lv = core_grid_parse(v)) < 0;
        else {
            fprintf(stderr, "bench_cfd: unknown option '%s'\n", o);
            return 2;
        }
        if (bad) {
            fprintf(stderr, "bench_cfd: %s: expected %s, got '%s'\n", o,
                    !strcmp(o, "--grid")    ? "coarse, default or fine"
                    : !strcmp(o, "--rotor") ? "on or off"
                    : !strcmp(o, "--ship")  ? "a ship name"
                                            : "a number in range",
                    v ? v : "nothing");
            return 2;
        }
    }
    if (!strcmp(argv[1], "fieldload"))
        return bench_cfd_fieldload(ship_name, (core_grid_level)lv, rounds);
    if (!strcmp(argv[1], "warmstart"))
        return warmstart(ship_name, speed, dir, lv, rotor, threads, max_iter);
    if (!strcmp(argv[1], "compare")) {
        bench_case bc = {CFD_SHIPS_DIR, ship_name, speed, dir, lv, rotor, iters, h_fine, h_max, 0, 0};
        return compare(&bc, threads, rounds);
    }
    if (!strcmp(argv[1], "throughput")) {
        double cells = 0.0;
        double r1 = run_iters(1, iters, &cells);
        double rn = run_iters(threads, iters, &cells);
        if (r1 < 0 || rn < 0)
            return 1;
        printf("throughput: SFS2 coarse grid with rotor, %.0f fluid cells, %d iterations\n", cells, iters);
        printf("  1 thread : %.3e cell-updates/s\n", r1);
        printf("  %d threads: %.3e cell-updates/s, %.3e per core, speed-up %.2f\n", threads, rn, rn / threads, rn / r1);
        return 0;
    }
    if (!strcmp(argv[1], "airwake")) {
        omp_set_num_threads(threads);
        core_ship ship;
        cfd_airwake_spec sp;
        if (bench_cfd_setup_ship(&ship, &sp, ship_name, speed, (core_grid_level)lv, dir, rotor))
            return 1;
        sp.max_iter = max_iter;
        core_err err;
        core_log log = {log_fn, NULL, CORE_LOG_INFO};
        double t0 = wall_now();
        cfd_solver *pre = NULL;
        cfd_result pres;
        memset(&pres, 0, sizeof pres);
        if (seq > 0 && lv > 0) {
            /* coarse-to-fine start: the same case on the coarse grid first */
            cfd_airwake_spec sc = sp;
            sc.level = CORE_GRID_COARSE;
            sc.max_iter = seq;
            limit lc = {tl, every, NULL};
            pre = cfd_airwake_create(&sc, &log, progress, &lc, &err);
            if (!pre) {
                fprintf(stderr, "%s\n", err.msg);
                return 1;
            }
            lc.s = pre;
            if (cfd_solver_run(pre, &pres, &err) < 0) {
                fprintf(stderr, "%s\n", err.msg);
                cfd_solver_destroy(pre);
                return 1;
            }
        }
        limit l = {tl, every, NULL};
        cfd_solver *s = cfd_airwake_create(&sp, &log, progress, &l, &err);
        if (!s) {
            fprintf(stderr, "%s\n", err.msg);
            cfd_solver_destroy(pre);
            return 1;
        }
        if (pre) {
            int irc = cfd_solver_init_from_solver(s, pre, &err);
            cfd_solver_destroy(pre);
            if (irc) {
                fprintf(stderr, "%s\n", err.msg);
                cfd_solver_destroy(s);
                return 1;
            }
        }
        l.s = s;
        double t_pre = wall_now() - t0;
        if (tl > 0.0)
            l.time_limit_s = tl - t_pre;
        size_t cells = cfd_grid_cells(cfd_solver_grid(s));
        cfd_result res;
        int rc = cfd_solver_run(s, &res, &err);
        double t_all = wall_now() - t0;
        struct rusage ru;
        getrusage(RUSAGE_SELF, &ru);
        printf("airwake: %s %.1f m/s %.0f deg, rotor %s, grid level %d, %zu cells, %d threads\n", ship.name, speed, dir,
               rotor ? "UH-60A" : "off", lv, cells, threads);
        printf("  %s after %d iterations, wall %.1f s, %.3e cell-updates/s (%.3e per core)\n",
               rc < 0 ? "DIVERGED" : res.converged ? "converged" : "NOT converged", res.iterations, res.wall_s,
               res.cell_updates / res.wall_s, res.cell_updates / res.wall_s / threads);
        if (seq > 0 && lv > 0)
            printf("  coarse-to-fine: %d coarse iterations (%s, %.1f s); total wall time with set-up %.1f s\n",
                   pres.iterations, pres.converged ? "converged" : "not converged", pres.wall_s, t_all);
        else
            printf("  total wall time with set-up %.1f s\n", t_all);
        printf("  final normalised residuals: continuity %.2e u %.2e v %.2e w %.2e k %.2e; monitor change %.2f %% of U\n",
               res.residual[0], res.residual[1], res.residual[2], res.residual[3], res.residual[4],
               100.0 * res.monitor_change);
        if (rc < 0)
            printf("  %s\n", err.msg);
        printf("  memory: solver %.0f bytes/cell, peak RSS %.0f bytes/cell (%.1f MB)\n",
               (double)cfd_solver_bytes(s) / cells, ru.ru_maxrss * 1024.0 / cells, ru.ru_maxrss / 1024.0);
        cfd_solver_destroy(s);
        return 0;
    }
    fprintf(stderr, "bench_cfd: unknown mode '%s'\n", argv[1]);
    return 2;
}
