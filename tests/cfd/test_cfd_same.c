/* test_cfd_same.c -- the solver's field against golden values stored from
 * the baseline solver (the cfd library at the git tag cfd-baseline, the
 * solver before its kernels were rewritten for speed), the same cases
 * through the same driver (bench/cfd/bench_case.c): the rewrite changed the
 * speed, not the answer.
 *
 * The golden file, data/cfd_same_golden.csv, holds per case the cell count,
 * the iterations, the final residuals, every field's scale, its RMS and
 * largest magnitude over all cells, and its values at a fixed set of probe
 * cells (256 spread evenly over the cell indices, plus each field's 5
 * largest and 5 smallest values). Built with CFD_SAME_WRITE (the target
 * cfd_same_golden, where the benchmarks and so the baseline are built),
 * this file is the generator that wrote it; its header says how.
 *
 * On one thread the rewrite changed the order of work and, in the TVD
 * deferred correction, the form of the limited difference (psi delta
 * without r: one division or none where there were two), the same value to
 * round-off: every probed value, RMS and largest magnitude within 1e-12 of
 * its field's scale (velocities / u_ref, p / (rho u_ref^2), k / u_ref^2,
 * eps relative) after the iterations (measured 2e-18 .. 5e-15), the
 * residuals within 1e-9 relative. A change of one model constant in its
 * eighth digit moves them by 1e-10 .. 2e-7. The cases:
 * SFS2 head wind with the rotor, van Leer, 80 iterations (past the 60 from
 * which Anderson acceleration starts where the residuals stall); SFS2 beam
 * wind, no rotor, minmod, 30 iterations, where air comes back in through
 * the outlets. One OpenMP thread, as the golden values were written. */
#include "bench_case.h"
#include "check.h"

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define RHO_KGPM3 1.225
#define TOL 1e-12
#define NPROBE_EVEN 256
#define NPROBE_EXTREME 5 /* per field, each end */
#define NPROBE_MAX (NPROBE_EVEN + 2 * NPROBE_EXTREME * BENCH_NFIELD)

typedef struct same_case {
    const char *key;  /* the golden file's case column */
    const char *name;
    bench_case bc;
} same_case;

/* the coarse level with 4 m cells in the deck box (under 20,000 cells) */
static const same_case cases[] = {
    {"head", "SFS2 head wind 15 m/s, rotor, van Leer, 80 iterations",
     {CFD_SHIPS_DIR, "sfs2", 15.0, 0.0, 0, 1, 80, 4.0, 16.0, 1, 0}},
    {"beam", "SFS2 beam wind 15 m/s from -90 deg, no rotor, minmod, 30 iterations",
     {CFD_SHIPS_DIR, "sfs2", 15.0, -90.0, 0, 0, 30, 4.0, 16.0, 1, 1}},
};
#define NCASE (int)(sizeof cases / sizeof cases[0])

/* What the golden file holds for one case. */
typedef struct golden {
    size_t cells;
    int iterations;
    double residual[5];
    double scale[BENCH_NFIELD]; /* 0: compared relative to the value */
    double l2[BENCH_NFIELD], linf[BENCH_NFIELD];
    size_t nprobe;
    size_t probe[NPROBE_MAX];
    double value[NPROBE_MAX][BENCH_NFIELD];
} golden;

static void scales(const bench_out *o, double scale[BENCH_NFIELD])
{
    double U = o->u_ref_mps;
    double s[BENCH_NFIELD] = {U, U, U, RHO_KGPM3 * U * U, U * U, 0.0};
    memcpy(scale, s, sizeof s);
}

/* RMS and largest magnitude of each field over all cells. */
static void norms(const bench_out *o, double l2[BENCH_NFIELD], double linf[BENCH_NFIELD])
{
    for (int v = 0; v < BENCH_NFIELD; v++) {
        double s = 0.0, m = 0.0;
        for (size_t c = 0; c < o->cells; c++) {
            double x = o->field[v][c];
            s += x * x;
            if (!(fabs(x) <= m))
                m = fabs(x); /* a NaN counts as the largest */
        }
        l2[v] = sqrt(s / (double)o->cells);
        linf[v] = m;
    }
}

#ifdef CFD_SAME_WRITE

static int cmp_size(const void *a, const void *b)
{
    size_t x = *(const size_t *)a, y = *(const size_t *)b;
    return (x > y) - (x < y);
}

/* The cell of the largest (sign +1) or smallest (-1) value of field f not
 * yet taken; the lowest index on ties. */
static size_t extreme(const double *f, size_t cells, int sign, const unsigned char *taken)
{
    size_t best = cells;
    for (size_t c = 0; c < cells; c++)
        if (!taken[c] && (best == cells || sign * f[c] > sign * f[best]))
            best = c;
    return best;
}

/* The probe cells: NPROBE_EVEN spread evenly over the indices, then each
 * field's NPROBE_EXTREME largest and smallest values not already taken. */
static size_t pick_probes(const bench_out *o, size_t *probe)
{
    unsigned char *taken = calloc(o->cells, 1);
    if (!taken)
        return 0;
    size_t n = 0;
    for (size_t i = 0; i < NPROBE_EVEN; i++) {
        size_t c = i * (o->cells - 1) / (NPROBE_EVEN - 1);
        if (!taken[c]) {
            taken[c] = 1;
            probe[n++] = c;
        }
    }
    for (int v = 0; v < BENCH_NFIELD; v++)
        for (int sign = 1; sign >= -1; sign -= 2)
            for (int j = 0; j < NPROBE_EXTREME; j++) {
                size_t c = extreme(o->field[v], o->cells, sign, taken);
                if (c < o->cells) {
                    taken[c] = 1;
                    probe[n++] = c;
                }
            }
    free(taken);
    qsort(probe, n, sizeof *probe, cmp_size);
    return n;
}

static void write_row(FILE *f, const char *key, const char *what, const char *cell, const double *x, int nx)
{
    fprintf(f, "%s,%s,%s", key, what, cell);
    for (int v = 0; v < BENCH_NFIELD; v++) {
        if (v < nx)
            fprintf(f, ",%.17g", x[v]);
        else
            fprintf(f, ",");
    }
    fprintf(f, "\n");
}

static int write_case(FILE *f, const same_case *sc, const bench_out *o)
{
    static size_t probe[NPROBE_MAX];
    char cell[32];
    double scale[BENCH_NFIELD], l2[BENCH_NFIELD], linf[BENCH_NFIELD];
    scales(o, scale);
    norms(o, l2, linf);
    size_t n = pick_probes(o, probe);
    if (n == 0)
        return -1;
    snprintf(cell, sizeof cell, "%zu", o->cells);
    write_row(f, sc->key, "cells", cell, NULL, 0);
    snprintf(cell, sizeof cell, "%d", o->iterations);
    write_row(f, sc->key, "iterations", cell, NULL, 0);
    write_row(f, sc->key, "residual", "", o->residual, 5);
    write_row(f, sc->key, "scale", "", scale, BENCH_NFIELD);
    write_row(f, sc->key, "l2", "", l2, BENCH_NFIELD);
    write_row(f, sc->key, "linf", "", linf, BENCH_NFIELD);
    for (size_t i = 0; i < n; i++) {
        double x[BENCH_NFIELD];
        for (int v = 0; v < BENCH_NFIELD; v++)
            x[v] = o->field[v][probe[i]];
        snprintf(cell, sizeof cell, "%zu", probe[i]);
        write_row(f, sc->key, "probe", cell, x, BENCH_NFIELD);
    }
    return 0;
}

/* The baseline's commit (the file baseline.sh writes), without the newline. */
static int base_commit(char *commit, size_t n)
{
    FILE *f = fopen(CFD_BASELINE_COMMIT_FILE, "r");
    if (!f)
        return -1;
    int ok = fgets(commit, (int)n, f) != NULL;
    fclose(f);
    commit[strcspn(commit, "\n")] = '\0';
    return ok && commit[0] ? 0 : -1;
}

/* cfd_same_golden OUT.csv: the baseline solver on every case, on one
 * thread, written to OUT.csv. */
int main(int argc, char **argv)
{
    char commit[128];
    if (argc != 2) {
        fprintf(stderr, "usage: cfd_same_golden OUT.csv\n");
        return 2;
    }
    if (base_commit(commit, sizeof commit)) {
        fprintf(stderr, "cfd_same_golden: cannot read %s\n", CFD_BASELINE_COMMIT_FILE);
        return 1;
    }
    omp_set_num_threads(1);
    FILE *f = fopen(argv[1], "w");
    if (!f) {
        fprintf(stderr, "cfd_same_golden: cannot write %s\n", argv[1]);
        return 1;
    }
    fprintf(f, "# cfd_same_golden.csv -- the golden values of tests/cfd/test_cfd_same.c: the\n"
               "# baseline solver, the cfd library at git tag %s\n"
               "# (commit %s),\n"
               "# on one OpenMP thread, through bench/cfd/bench_case.c. Written by\n"
               "#   cmake -S . -B build -DDISIM_BENCH=ON && cmake --build build --target cfd_same_golden\n"
               "#   build/tests/cfd/cfd_same_golden tests/cfd/data/cfd_same_golden.csv\n"
               "# Cases (coarse level, 4 m cells in the deck box, 16 m largest):\n",
            CFD_BASELINE_TAG, commit);
    for (int i = 0; i < NCASE; i++)
        fprintf(f, "#   %s: %s\n", cases[i].key, cases[i].name);
    fprintf(f, "# Rows, by `what`: cells and iterations (the count in `cell`); residual (the final\n"
               "# residuals: continuity, u, v, w, k in the columns u..k); scale (each field's scale:\n"
               "# u_ref, u_ref, u_ref, 1.225 u_ref^2, u_ref^2; eps 0: relative); l2 (RMS over all\n"
               "# cells); linf (largest magnitude over all cells); probe (the fields at cell index `cell`).\n"
               "case,what,cell,u,v,w,p,k,eps\n");
    int rc = 0;
    for (int i = 0; i < NCASE && rc == 0; i++) {
        bench_out o;
        if (bench_case_base(&cases[i].bc, &o) != 0) {
            fprintf(stderr, "cfd_same_golden: %s: %s\n", cases[i].key, o.err);
            rc = 1;
        } else if (write_case(f, &cases[i], &o) != 0) {
            fprintf(stderr, "cfd_same_golden: %s: out of memory\n", cases[i].key);
            rc = 1;
        }
        bench_out_free(&o);
    }
    if (fclose(f) != 0)
        rc = 1;
    return rc;
}

#else

/* The next comma-separated field of *s (empty at a comma or the end). */
static char *next_field(char **s)
{
    char *f = *s;
    char *c = strpbrk(f, ",\n");
    if (c) {
        *s = c + (*c == ',');
        *c = '\0';
    } else {
        *s = f + strlen(f);
    }
    return f;
}

static int parse_doubles(char **s, double *x, int n)
{
    for (int v = 0; v < n; v++) {
        char *f = next_field(s), *end;
        x[v] = strtod(f, &end);
        if (end == f || *end)
            return -1;
    }
    return 0;
}

/* One data row into the golden of its case; -1 when malformed. */
static int golden_row(char *line, golden *g)
{
    char *s = line;
    char *key = next_field(&s), *what = next_field(&s), *cell = next_field(&s);
    int k = -1;
    for (int i = 0; i < NCASE; i++)
        if (strcmp(key, cases[i].key) == 0)
            k = i;
    if (k < 0)
        return -1;
    golden *c = &g[k];
    char *end;
    if (strcmp(what, "cells") == 0) {
        c->cells = strtoul(cell, &end, 10);
        return *end ? -1 : 0;
    }
    if (strcmp(what, "iterations") == 0) {
        c->iterations = (int)strtol(cell, &end, 10);
        return *end ? -1 : 0;
    }
    if (strcmp(what, "residual") == 0)
        return parse_doubles(&s, c->residual, 5);
    if (strcmp(what, "scale") == 0)
        return parse_doubles(&s, c->scale, BENCH_NFIELD);
    if (strcmp(what, "l2") == 0)
        return parse_doubles(&s, c->l2, BENCH_NFIELD);
    if (strcmp(what, "linf") == 0)
        return parse_doubles(&s, c->linf, BENCH_NFIELD);
    if (strcmp(what, "probe") == 0 && c->nprobe < NPROBE_MAX) {
        c->probe[c->nprobe] = strtoul(cell, &end, 10);
        if (end == cell || *end || parse_doubles(&s, c->value[c->nprobe], BENCH_NFIELD))
            return -1;
        c->nprobe++;
        return 0;
    }
    return -1;
}

static int golden_load(const char *path, golden *g)
{
    FILE *f = fopen(path, "r");
    if (!f)
        return -1;
    char line[1024];
    int rc = 0, header = 0;
    while (rc == 0 && fgets(line, sizeof line, f)) {
        if (line[0] == '#')
            continue;
        if (!header) {
            header = 1;
            if (strcmp(line, "case,what,cell,u,v,w,p,k,eps\n") != 0)
                rc = -1;
            continue;
        }
        rc = golden_row(line, g);
    }
    fclose(f);
    return rc;
}

/* |now - gold| in units of the scale (relative to gold where the scale is 0). */
static double diff(double now, double gold, double scale)
{
    double d = scale > 0.0 ? fabs(now - gold) / scale : fabs(now - gold) / fmax(fabs(gold), 1e-30);
    return d == d ? d : INFINITY;
}

static void same(const same_case *sc, const golden *g)
{
    static const char *const vn[BENCH_NFIELD] = {"u", "v", "w", "p", "k", "eps"};
    bench_out now;
    int rn = bench_case_new(&sc->bc, &now);
    CHECK(rn == 0);
    if (rn) {
        fprintf(stderr, "%s: %s\n", sc->name, now.err);
        bench_out_free(&now);
        return;
    }
    CHECK(now.cells == g->cells && g->cells > 1000);
    CHECK(now.iterations == g->iterations);
    CHECK(g->nprobe >= NPROBE_EVEN);
    double scale[BENCH_NFIELD], l2[BENCH_NFIELD], linf[BENCH_NFIELD];
    scales(&now, scale);
    norms(&now, l2, linf);
    printf("%s (%zu cells, %d iterations, %zu probes): largest difference", sc->name, now.cells,
           now.iterations, g->nprobe);
    for (int v = 0; v < BENCH_NFIELD; v++) {
        CHECK(scale[v] == g->scale[v]);
        double d = fmax(diff(l2[v], g->l2[v], g->scale[v]), diff(linf[v], g->linf[v], g->scale[v]));
        for (size_t i = 0; i < g->nprobe; i++) {
            size_t c = g->probe[i];
            CHECK(c < now.cells);
            if (c < now.cells)
                d = fmax(d, diff(now.field[v][c], g->value[i][v], g->scale[v]));
        }
        printf(" %s %.1e", vn[v], d);
        CHECK(d <= TOL);
    }
    printf("\n");
    for (int q = 0; q < 5; q++)
        CHECK(fabs(now.residual[q] - g->residual[q]) <= 1e3 * TOL * fabs(g->residual[q]) + 1e-300);
    bench_out_free(&now);
}

int main(void)
{
    static golden g[NCASE];
    memset(g, 0, sizeof g);
    int rc = golden_load(CFD_GOLDEN_FILE, g);
    CHECK(rc == 0);
    if (rc) {
        fprintf(stderr, "cannot read %s (or a malformed row)\n", CFD_GOLDEN_FILE);
        return check_done("test_cfd_same");
    }
    omp_set_num_threads(1);
    for (int i = 0; i < NCASE; i++)
        same(&cases[i], &g[i]);
    return check_done("test_cfd_same");
}

#endif
