/* sidebyside.c -- bench_cfd sidebyside: the embedded solver and OpenFOAM
 * (foam.h) on one cfd_airwake_spec in one invocation on one machine.
 *
 *   bench_cfd sidebyside [--ship sfs2|cg47] [--rotor on|off] [--cells N]
 *       [--np N] [--threads N] [--max-iter N] [--keep-case] [--out DIR]
 *       [--h-fine-m H] [--default on|off]
 *
 * The case: the ship (scenarios/ships/NAME.ini) in a 15 m/s head wind,
 * with the rotor the UH-60A's uniform disk one radius over the spot; the
 * coarse grid level with its focus spacing chosen so that the grid has
 * about --cells fluid cells (default 250,000; --h-fine-m sets it instead).
 * Both engines stop on the same test: from iteration 200 on, once every
 * deck monitor velocity has moved by less than 2 % of U over each of the
 * last two spans of 50 iterations (OpenFOAM's stop in foam.c; the
 * embedded solver's cfd_config.monitor_stop). The embedded solver runs on
 * --threads OpenMP threads (default: as many as --np), OpenFOAM on --np
 * MPI ranks. The embedded solver runs before OpenFOAM and again after it
 * (the ratio takes the mean of its two times, so that a change of the
 * machine's load during the long OpenFOAM run weighs on both), then
 * (--default on) once more to its own default criterion (residuals below
 * 1e-4 and the monitors within 2 %).
 *
 * Printed: the grid; per engine the iterations, the wall time to the
 * criterion (end to end: the case to its HDF5 field file; and the solver
 * alone), CPU time, cell-iterations per second, seconds per iteration
 * and the load while it ran; OpenFOAM's per-step times and the iteration
 * its monitors first passed the test; the ratio OpenFOAM / embedded and
 * whether the embedded solver is 5 times faster or more; the velocity
 * differences along the nine deck lines (cfd_airwake_deck_diff) in % of
 * U. With --out DIR: DIR/sidebyside.json, DIR/sidebyside.csv (one row per
 * run), DIR/sidebyside_deck.csv (one row per deck line) and the fields
 * (embedded.h5, embedded_after.h5, openfoam.h5, embedded_default.h5);
 * OpenFOAM's case folder is made in DIR too. Progress goes to stderr while
 * each engine runs.
 */
/* nftw */
#define _XOPEN_SOURCE 700
#include "bench_cfd.h"
#include "cfd.h"
#include "foam.h"

#include <errno.h>
#include <ftw.h>
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

enum { SBS_WINDOW = 50, SBS_MIN_ITER = 200 };

/* CPU seconds of this process (who RUSAGE_SELF) or of its waited-for
 * children and their descendants (RUSAGE_CHILDREN: OpenFOAM's programs,
 * mpirun's ranks included). */
static double cpu_s(int who)
{
    struct rusage ru;
    getrusage(who, &ru);
    return ru.ru_utime.tv_sec + ru.ru_stime.tv_sec + 1e-6 * (ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
}

static double sbs_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* ------------------------------------------------------------ progress */
/* A progress line on stderr: rewritten in place on a terminal (about once
 * a second), else one line a minute. */
typedef struct ticker {
    const char *who;
    int tty, open;
    double every_s, last_s, t0;
    double load_sum, load_next; /* the 1-minute load average, sampled every 5 s */
    int load_n;
} ticker;

static void loadavg(double l[3])
{
    l[0] = l[1] = l[2] = -1.0;
    FILE *f = fopen("/proc/loadavg", "r");
    if (f) {
        if (fscanf(f, "%lf %lf %lf", &l[0], &l[1], &l[2]) != 3)
            l[0] = l[1] = l[2] = -1.0;
        fclose(f);
    }
}

static void ticker_start(ticker *t, const char *who)
{
    t->who = who;
    t->tty = isatty(STDERR_FILENO);
    t->open = 0;
    t->every_s = t->tty ? 1.0 : 60.0;
    t->last_s = 0.0;
    t->t0 = sbs_now();
    t->load_sum = t->load_next = 0.0;
    t->load_n = 0;
}

/* The mean of the load samples (-1: none). */
static double ticker_load(const ticker *t)
{
    return t->load_n ? t->load_sum / t->load_n : -1.0;
}

static void ticker_show(ticker *t, int it, int max_iter, const char *rname, double res)
{
    double el = sbs_now() - t->t0;
    if (el >= t->load_next) {
        double l[3];
        loadavg(l);
        if (l[0] >= 0.0) {
            t->load_sum += l[0];
            t->load_n++;
        }
        t->load_next = el + 5.0;
    }
    if (el - t->last_s < t->every_s)
        return;
    t->last_s = el;
    fprintf(stderr, "%s  %s: iteration %d/%d, %s %.2e, %.0f s%s", t->tty ? "\r" : "", t->who, it, max_iter, rname, res,
            el, t->tty ? "   " : "\n");
    t->open = t->tty;
}

static void ticker_end(ticker *t)
{
    if (t->open)
        fputc('\n', stderr);
    t->open = 0;
}

static int emb_progress(void *user, int iter, int max_iter, double res, double t)
{
    (void)t;
    ticker_show(user, iter, max_iter, "largest residual", res);
    return 0;
}

static int foam_progress(void *user, double frac, double res, int iter)
{
    ticker *t = user;
    int max_iter = frac > 0.0 ? (int)lround(iter / frac) : 0;
    ticker_show(t, iter, max_iter, "p residual", res);
    return 0;
}

static void log_fn(void *user, int level, const char *msg)
{
    ticker *t = user;
    ticker_end(t);
    (void)level;
    fprintf(stderr, "  %s\n", msg);
}

/* ---------------------------------------------------------------- grid */
/* Fluid cells of sp's grid (0 with err on failure). */
static size_t fluid_cells(const cfd_airwake_spec *sp, core_err *err)
{
    cfd_solver *s = cfd_airwake_create(sp, NULL, NULL, NULL, err);
    size_t n = s ? cfd_grid_fluid_cells(cfd_solver_grid(s)) : 0;
    cfd_solver_destroy(s);
    return n;
}

/* sp->h_fine_m such that the grid has about target fluid cells: a secant
 * search on log cells against log spacing from the level's spacing, each
 * step at most a factor 2 (the closest of at most 12 tries). 0, or -1
 * with err. */
static int size_grid(cfd_airwake_spec *sp, double target, core_err *err)
{
    double h = 1.1, hp = 0.0, np_ = 0.0, best_h = h, best = 1e300;
    for (int i = 0; i < 12; i++) {
        sp->h_fine_m = h;
        size_t n = fluid_cells(sp, err);
        if (!n)
            return -1;
        double miss = fabs(log(n / target));
        if (miss < best) {
            best = miss;
            best_h = h;
        }
        if (miss < 0.01)
            break;
        double slope = hp > 0.0 && fabs(log(h / hp)) > 1e-9 ? log(n / np_) / log(h / hp) : -2.5;
        slope = fmin(-1.0, fmax(-4.0, slope));
        double hn = h * exp(log(target / n) / slope);
        hn = fmin(2.0 * h, fmax(0.5 * h, hn));
        hp = h;
        np_ = (double)n;
        h = hn;
    }
    sp->h_fine_m = best_h;
    return 0;
}

/* Each axis's smallest and largest spacing. */
static void spacings(const cfd_grid *g, double lo[3], double hi[3])
{
    int n[3];
    cfd_grid_dims(g, n);
    for (int d = 0; d < 3; d++) {
        const double *x = cfd_grid_nodes(g, d);
        lo[d] = 1e300;
        hi[d] = 0.0;
        for (int i = 0; i < n[d]; i++) {
            lo[d] = fmin(lo[d], x[i + 1] - x[i]);
            hi[d] = fmax(hi[d], x[i + 1] - x[i]);
        }
    }
}

/* ------------------------------------------------------------- engines */
typedef struct emb_run {
    int rc;           /* cfd_solver_run's */
    int monitor_stop; /* 1: run to the common criterion */
    cfd_result res;
    double create_s, write_s, total_s;
    double cpu_s; /* CPU seconds, every thread, end to end */
    double load;  /* the mean 1-minute load average while it ran (-1: not sampled) */
} emb_run;

/* The embedded solver on sp (monitor_stop: the common test), its field
 * written to path. 0, or -1 with the error printed. */
static int run_embedded(const cfd_airwake_spec *sp0, int monitor_stop, const cfd_meta *meta0, const char *path,
                        const char *who, emb_run *r)
{
    cfd_airwake_spec sp = *sp0;
    sp.monitor_stop = monitor_stop;
    ticker tk;
    ticker_start(&tk, who);
    core_log log = {log_fn, &tk, CORE_LOG_WARN};
    core_err err = {0};
    memset(r, 0, sizeof *r);
    r->monitor_stop = monitor_stop;
    double t0 = sbs_now(), c0 = cpu_s(RUSAGE_SELF);
    cfd_solver *s = cfd_airwake_create(&sp, &log, emb_progress, &tk, &err);
    r->create_s = sbs_now() - t0;
    if (s)
        r->rc = cfd_solver_run(s, &r->res, &err);
    ticker_end(&tk);
    r->load = ticker_load(&tk);
    if (!s || r->rc < 0) {
        fprintf(stderr, "bench_cfd sidebyside: %s: %s\n", who, err.msg);
        cfd_solver_destroy(s);
        return -1;
    }
    cfd_meta m = *meta0;
    m.result = r->res;
    double tw = sbs_now();
    int wrc = cfd_solver_write(s, &m, path, &err);
    r->write_s = sbs_now() - tw;
    r->total_s = sbs_now() - t0;
    r->cpu_s = cpu_s(RUSAGE_SELF) - c0;
    cfd_solver_destroy(s);
    if (wrc) {
        fprintf(stderr, "bench_cfd sidebyside: %s: %s\n", who, err.msg);
        return -1;
    }
    return 0;
}

/* The first iteration at which OpenFOAM's monitors passed the common test
 * (foam.c reads the probes' output about once a second while simpleFoam
 * runs, so it stops a few iterations after): from the case's probes'
 * output, every iteration, by the same rule. 0 when it never passed or the
 * output cannot be read. */
static int foam_first_pass(const char *case_dir, double u_ref, double tol)
{
    char p[1200];
    snprintf(p, sizeof p, "%s/postProcessing/monitors/0/U", case_dir);
    FILE *f = fopen(p, "r");
    if (!f)
        return 0;
    size_t cap = 0, n = 0;
    int nm = 0, first = 0;
    double *v = NULL; /* n rows of nm x 3 */
    int *its = NULL;
    static char line[1 << 14];
    while (fgets(line, sizeof line, f)) {
        char *a = line, *e;
        double t = strtod(a, &e);
        if (line[0] == '#' || e == a)
            continue;
        a = e;
        double row[CFD_MAX_MONITOR][3];
        int m = 0;
        for (char *pa; m < CFD_MAX_MONITOR && (pa = strchr(a, '(')); m++) {
            a = pa + 1;
            for (int d = 0; d < 3; d++) {
                row[m][d] = strtod(a, &e);
                a = e;
            }
        }
        if (!nm)
            nm = m;
        if (m != nm || !nm)
            break;
        if (n == cap) {
            cap = cap ? 2 * cap : 1024;
            double *nv = realloc(v, cap * nm * 3 * sizeof *v);
            if (nv)
                v = nv;
            int *ni = nv ? realloc(its, cap * sizeof *its) : NULL;
            if (ni)
                its = ni;
            if (!nv || !ni)
                break;
        }
        memcpy(v + n * nm * 3, row, (size_t)nm * 3 * sizeof *v);
        its[n++] = (int)lround(t);
    }
    fclose(f);
    for (size_t i = 2 * SBS_WINDOW; i < n && !first; i++) {
        if (its[i] < SBS_MIN_ITER)
            continue;
        double ch[2] = {0.0, 0.0};
        for (int w = 0; w < 2; w++)
            for (int m = 0; m < nm; m++) {
                const double *x = v + ((i - w * SBS_WINDOW) * nm + m) * 3;
                const double *y = v + ((i - (w + 1) * SBS_WINDOW) * nm + m) * 3;
                double d2 = (x[0] - y[0]) * (x[0] - y[0]) + (x[1] - y[1]) * (x[1] - y[1]) + (x[2] - y[2]) * (x[2] - y[2]);
                ch[w] = fmax(ch[w], sqrt(d2) / u_ref);
            }
        if (ch[0] < tol && ch[1] < tol)
            first = its[i];
    }
    free(v);
    free(its);
    return first;
}

static int rm_entry(const char *path, const struct stat *st, int flag, struct FTW *ftw)
{
    (void)st, (void)flag, (void)ftw;
    remove(path);
    return 0;
}

/* ------------------------------------------------------------- machine */
static void cpu_model(char *out, size_t n)
{
    snprintf(out, n, "unknown");
    FILE *f = fopen("/proc/cpuinfo", "r");
    char line[512];
    while (f && fgets(line, sizeof line, f)) {
        const char *c = strchr(line, ':');
        if (!strncmp(line, "model name", 10) && c) {
            c++;
            while (*c == ' ')
                c++;
            snprintf(out, n, "%.*s", (int)strcspn(c, "\n"), c);
            break;
        }
    }
    if (f)
        fclose(f);
}

/* ------------------------------------------------------------- options */
typedef struct sbs_opts {
    const char *ship;
    int rotor, np, threads, max_iter, keep_case, run_default;
    double cells, h_fine_m;
    const char *out_dir;
} sbs_opts;

static int parse(int argc, char **argv, sbs_opts *o)
{
    memset(o, 0, sizeof *o);
    o->ship = "sfs2";
    o->rotor = 1;
    o->np = 2;
    o->max_iter = 3000;
    o->run_default = 1;
    o->cells = 250000.0;
    for (int i = 0; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        char *end = NULL;
        int bad = 0;
        if (!strcmp(a, "--keep-case")) {
            o->keep_case = 1;
            continue;
        }
        if (!v) {
            fprintf(stderr, "bench_cfd sidebyside: %s needs a value\n", a);
            return 2;
        }
        i++;
        if (!strcmp(a, "--ship"))
            o->ship = v;
        else if (!strcmp(a, "--rotor") || !strcmp(a, "--default")) {
            int on = !strcmp(v, "on") ? 1 : !strcmp(v, "off") ? 0 : -1;
            bad = on < 0;
            *(!strcmp(a, "--rotor") ? &o->rotor : &o->run_default) = on;
        } else if (!strcmp(a, "--cells"))
            bad = (o->cells = strtod(v, &end)) < 1000.0 || o->cells > 1e8 || *end;
        else if (!strcmp(a, "--h-fine-m"))
            bad = !((o->h_fine_m = strtod(v, &end)) >= 0.05) || o->h_fine_m > 50.0 || *end;
        else if (!strcmp(a, "--np"))
            bad = (o->np = (int)strtol(v, &end, 10)) < 1 || o->np > 256 || *end;
        else if (!strcmp(a, "--threads"))
            bad = (o->threads = (int)strtol(v, &end, 10)) < 1 || o->threads > 256 || *end;
        else if (!strcmp(a, "--max-iter"))
            bad = (o->max_iter = (int)strtol(v, &end, 10)) < 1 || o->max_iter > 1000000 || *end;
        else if (!strcmp(a, "--out"))
            o->out_dir = v;
        else {
            fprintf(stderr, "bench_cfd sidebyside: unknown option '%s' (--ship, --rotor, --cells, --np, --threads, "
                            "--max-iter, --keep-case, --out, --h-fine-m, --default)\n",
                    a);
            return 2;
        }
        if (bad) {
            fprintf(stderr, "bench_cfd sidebyside: %s: bad value '%s'\n", a, v);
            return 2;
        }
    }
    if (!o->threads)
        o->threads = o->np;
    return 0;
}

/* ------------------------------------------------------------- results */
typedef struct sbs {
    sbs_opts o;
    const char *cmd; /* the command line, for the JSON */
    core_ship ship;
    cfd_airwake_spec sp;
    int dims[3];
    size_t cells, fluid;
    double dx_lo[3], dx_hi[3];
    char cpu[128];
    long cores;
    double load0[3], load1[3];
    emb_run emb, emb2, def; /* to the common criterion before and after OpenFOAM; to its own */
    emb_run em;             /* emb and emb2's times averaged: the ratio's embedded figure */
    int have_def;
    foam_result fr;
    int foam_first; /* the first iteration OpenFOAM's monitors passed the test (0: not known) */
    double foam_cpu_s; /* CPU seconds of OpenFOAM's programs and of this process's part, end to end */
    double foam_load;  /* the mean 1-minute load average while it ran */
    cfd_deck_diff deck, crit; /* openfoam - embedded; embedded at the common - at its own criterion */
    double ratio, ratio_solver, ratio_iter;
    double foam_first_s; /* OpenFOAM's end-to-end time less the iterations past the first pass */
    double ratio_first;  /* foam_first_s over the embedded solver's */
} sbs;

static const char *emb_stop(const emb_run *r)
{
    return r->res.converged    ? (r->monitor_stop ? "monitors steady" : "converged")
           : r->res.steady_mean ? "steady mean"
                                : "at the iteration cap";
}

static void json_str(FILE *f, const char *s)
{
    fputc('"', f);
    for (; *s; s++) {
        if (*s == '"' || *s == '\\')
            fputc('\\', f);
        if ((unsigned char)*s >= 0x20)
            fputc(*s, f);
    }
    fputc('"', f);
}

static void json_emb(FILE *f, const char *name, const emb_run *r, int threads)
{
    const cfd_result *q = &r->res;
    fprintf(f,
            "  \"%s\": {\"load\": %.2f, \"threads\": %d, \"iterations\": %d, \"converged\": %d, \"stop\": \"%s\", "
            "\"setup_s\": %.3f, \"solver_s\": %.3f, \"write_s\": %.3f, \"total_s\": %.3f, \"cpu_s\": %.3f, "
            "\"cell_iterations_per_s\": %.6g, \"s_per_iteration\": %.6g, \"monitor_change\": %.6g, "
            "\"residuals\": [%.4g, %.4g, %.4g, %.4g, %.4g]},\n",
            name, r->load, threads, q->iterations, q->converged, emb_stop(r), r->create_s, q->wall_s, r->write_s, r->total_s,
            r->cpu_s,
            q->cell_updates / q->wall_s, q->wall_s / q->iterations, q->monitor_change, q->residual[0], q->residual[1],
            q->residual[2], q->residual[3], q->residual[4]);
}

static void json_deck(FILE *f, const char *name, const cfd_deck_diff *d, int last)
{
    fprintf(f, "  \"%s\": {\"largest_pct_U\": %.4f, \"at_m\": [%.3f, %.3f, %.3f], \"rms_pct_U\": %.4f, \"lines\": [",
            name, 100.0 * d->worst, d->worst_at_m[0], d->worst_at_m[1], d->worst_at_m[2], 100.0 * d->rms);
    for (int l = 0; l < CFD_DECK_LINES; l++)
        fprintf(f, "%s{\"y_m\": %.2f, \"z_m\": %.2f, \"largest_pct_U\": %.4f, \"at_x_m\": %.3f}", l ? ", " : "",
                d->line_y_m[l], d->line_z_m[l], 100.0 * d->line_worst[l], d->line_worst_x_m[l]);
    fprintf(f, "]}%s\n", last ? "" : ",");
}

static int write_json(const sbs *b, const char *dir)
{
    char p[1200];
    snprintf(p, sizeof p, "%s/sidebyside.json", dir);
    FILE *f = fopen(p, "w");
    if (!f) {
        fprintf(stderr, "bench_cfd sidebyside: %s: %s\n", p, strerror(errno));
        return -1;
    }
    const sbs_opts *o = &b->o;
    const foam_result *r = &b->fr;
    fprintf(f, "{\n  \"command\": ");
    json_str(f, b->cmd);
    fprintf(f, ",\n  \"case\": {\"ship\": ");
    json_str(f, b->ship.name);
    fprintf(f,
            ", \"wind_mps\": %.2f, \"wind_dir_deg\": 0, \"rotor\": \"%s\", \"thrust_N\": %.1f, \"radius_m\": %.2f},\n",
            b->sp.wod_speed_mps, o->rotor ? "uniform" : "off", o->rotor ? b->sp.disk.thrust_N : 0.0,
            o->rotor ? b->sp.disk.radius_m : 0.0);
    fprintf(f,
            "  \"grid\": {\"dims\": [%d, %d, %d], \"cells\": %zu, \"fluid_cells\": %zu, \"target_fluid_cells\": %.0f, "
            "\"h_fine_m\": %.4f, \"spacing_min_m\": [%.4f, %.4f, %.4f], \"spacing_max_m\": [%.4f, %.4f, %.4f]},\n",
            b->dims[0], b->dims[1], b->dims[2], b->cells, b->fluid, o->cells, b->sp.h_fine_m, b->dx_lo[0], b->dx_lo[1],
            b->dx_lo[2], b->dx_hi[0], b->dx_hi[1], b->dx_hi[2]);
    fprintf(f, "  \"machine\": {\"cores\": %ld, \"cpu\": ", b->cores);
    json_str(f, b->cpu);
    fprintf(f, ", \"load_start\": [%.2f, %.2f, %.2f], \"load_end\": [%.2f, %.2f, %.2f]},\n", b->load0[0], b->load0[1],
            b->load0[2], b->load1[0], b->load1[1], b->load1[2]);
    fprintf(f,
            "  \"criterion\": {\"tol_monitor_U\": 0.02, \"span_iterations\": %d, \"min_iterations\": %d, "
            "\"max_iter\": %d},\n",
            SBS_WINDOW, SBS_MIN_ITER, o->max_iter);
    json_emb(f, "embedded", &b->emb, o->threads);
    json_emb(f, "embedded_after", &b->emb2, o->threads);
    json_emb(f, "embedded_mean", &b->em, o->threads);
    if (b->have_def)
        json_emb(f, "embedded_default", &b->def, o->threads);
    fprintf(f,
            "  \"openfoam\": {\"load\": %.2f, \"version\": \"%s\", \"ranks\": %d, \"iterations\": %d, \"steady_iter\": %d, "
            "\"first_pass_iter\": %d, \"residual_control_met\": %d, \"total_s\": %.3f, \"cpu_s\": %.3f, \"solver_s\": %.3f, \"cell_iterations_per_s\": %.6g, "
            "\"s_per_iteration\": %.6g, \"monitor_change\": %.6g, "
            "\"residuals_p_Ux_Uy_Uz_k\": [%.4g, %.4g, %.4g, %.4g, %.4g], \"steps_s\": {",
            b->foam_load, r->version, o->np, r->res.iterations, r->steady_iter, b->foam_first, r->res.converged, r->total_wall_s,
            b->foam_cpu_s, r->res.wall_s,
            r->res.cell_updates / r->res.wall_s, r->res.wall_s / r->res.iterations, r->res.monitor_change,
            r->res.residual[0], r->res.residual[1], r->res.residual[2], r->res.residual[3], r->res.residual[4]);
    for (int i = 0; i < FOAM_NSTEPS; i++)
        fprintf(f, "%s\"%s\": %.3f", i ? ", " : "", foam_step_names[i], r->step_s[i]);
    fprintf(f, "}},\n");
    fprintf(f,
            "  \"ratio\": {\"end_to_end\": %.4f, \"end_to_end_at_first_pass\": %.4f, \"solver\": %.4f, "
            "\"per_iteration\": %.4f, \"embedded_5x_faster\": %s},\n",
            b->ratio, b->ratio_first, b->ratio_solver, b->ratio_iter,
            fmin(b->ratio, b->ratio_first) >= 5.0 ? "true" : "false");
    json_deck(f, "deck_openfoam_minus_embedded", &b->deck, !b->have_def);
    if (b->have_def)
        json_deck(f, "deck_embedded_common_minus_default", &b->crit, 1);
    fprintf(f, "}\n");
    return fclose(f) == 0 ? 0 : -1;
}

static int write_csv(const sbs *b, const char *dir)
{
    char p[1200];
    snprintf(p, sizeof p, "%s/sidebyside.csv", dir);
    FILE *f = fopen(p, "w");
    if (!f)
        return -1;
    fprintf(f, "run,workers,criterion,iterations,stop,setup_s,solver_s,total_s,cpu_s,cell_iterations_per_s,"
               "s_per_iteration,fluid_cells,load\n");
    const emb_run *e[3] = {&b->emb, &b->emb2, &b->def};
    static const char *const names[3] = {"embedded", "embedded_after", "embedded_default"};
    for (int i = 0; i < 2 + b->have_def; i++)
        fprintf(f, "%s,%d,%s,%d,%s,%.3f,%.3f,%.3f,%.3f,%.6g,%.6g,%zu,%.2f\n", names[i],
                b->o.threads, i == 2 ? "default" : "common", e[i]->res.iterations, emb_stop(e[i]), e[i]->create_s,
                e[i]->res.wall_s, e[i]->total_s, e[i]->cpu_s, e[i]->res.cell_updates / e[i]->res.wall_s,
                e[i]->res.wall_s / e[i]->res.iterations, b->fluid, e[i]->load);
    const foam_result *r = &b->fr;
    double setup = r->total_wall_s - r->res.wall_s;
    fprintf(f, "openfoam,%d,common,%d,%s,%.3f,%.3f,%.3f,%.3f,%.6g,%.6g,%zu,%.2f\n", b->o.np, r->res.iterations,
            r->steady_iter > 0 ? "monitors steady" : r->res.converged ? "residuals" : "at the iteration cap", setup,
            r->res.wall_s, r->total_wall_s, b->foam_cpu_s, r->res.cell_updates / r->res.wall_s,
            r->res.wall_s / r->res.iterations, r->cells, b->foam_load);
    if (fclose(f) != 0)
        return -1;
    snprintf(p, sizeof p, "%s/sidebyside_deck.csv", dir);
    if (!(f = fopen(p, "w")))
        return -1;
    fprintf(f, "compared,y_m,z_m,largest_pct_U,at_x_m\n");
    const cfd_deck_diff *d[2] = {&b->deck, &b->crit};
    for (int i = 0; i < 1 + b->have_def; i++)
        for (int l = 0; l < CFD_DECK_LINES; l++)
            fprintf(f, "%s,%.2f,%.2f,%.4f,%.3f\n", i ? "embedded_common-embedded_default" : "openfoam-embedded",
                    d[i]->line_y_m[l], d[i]->line_z_m[l], 100.0 * d[i]->line_worst[l], d[i]->line_worst_x_m[l]);
    return fclose(f) == 0 ? 0 : -1;
}

/* ------------------------------------------------------------- printing */
static void print_deck(const char *what, const cfd_deck_diff *d)
{
    printf("  deck lines (%d x %d points), %s: largest %.2f %% of U at (%.1f, %.1f, %.1f) m, RMS %.2f %%\n",
           CFD_DECK_LINES, CFD_DECK_LINE_POINTS, what, 100.0 * d->worst, d->worst_at_m[0], d->worst_at_m[1],
           d->worst_at_m[2], 100.0 * d->rms);
    for (int l = 0; l < CFD_DECK_LINES; l++)
        printf("    y %+.1f m, %.1f m over the deck: %5.2f %% at x %.1f m\n", d->line_y_m[l], -d->line_z_m[l],
               100.0 * d->line_worst[l], d->line_worst_x_m[l]);
}

static void print_emb(const char *what, const emb_run *r, int threads)
{
    const cfd_result *q = &r->res;
    printf("  %s (%d thread%s): %d iterations, %s; set-up %.2f s, solver %.1f s, field written %.2f s: "
           "%.1f s end to end\n",
           what, threads, threads > 1 ? "s" : "", q->iterations, emb_stop(r), r->create_s, q->wall_s, r->write_s,
           r->total_s);
    printf("    CPU time %.1f s (%.2f cores busy on average); load while it ran %.2f\n", r->cpu_s, r->cpu_s / r->total_s,
           r->load);
    printf("    %.3e cell-iterations/s (%.3e per thread), %.4f s per iteration; residuals %.2e %.2e %.2e %.2e %.2e, "
           "monitor change %.2f %% of U\n",
           q->cell_updates / q->wall_s, q->cell_updates / q->wall_s / threads, q->wall_s / q->iterations,
           q->residual[0], q->residual[1], q->residual[2], q->residual[3], q->residual[4], 100.0 * q->monitor_change);
}

static void print_report(const sbs *b)
{
    const sbs_opts *o = &b->o;
    const foam_result *r = &b->fr;
    printf("sidebyside: %s, %.1f m/s head wind, rotor %s\n", b->ship.name, b->sp.wod_speed_mps,
           o->rotor ? "UH-60A uniform disk (thrust = weight, R 8.18 m, hub one radius over the spot)" : "off");
    printf("  grid: %d x %d x %d = %zu cells, %zu fluid (target %.0f); focus spacing %.3f m, growth %.2f, "
           "largest cells x %.2f y %.2f z %.2f m\n",
           b->dims[0], b->dims[1], b->dims[2], b->cells, b->fluid, o->cells, b->sp.h_fine_m, CFD_GRID_GROWTH,
           b->dx_hi[0], b->dx_hi[1], b->dx_hi[2]);
    printf("  machine: %ld cores (%s); load %.2f %.2f %.2f at the start, %.2f %.2f %.2f at the end\n", b->cores,
           b->cpu, b->load0[0], b->load0[1], b->load0[2], b->load1[0], b->load1[1], b->load1[2]);
    printf("  common criterion: from iteration %d on, every deck monitor velocity moved < 2 %% of U over each of "
           "the last two %d-iteration spans (cap %d)\n",
           SBS_MIN_ITER, SBS_WINDOW, o->max_iter);
    print_emb("embedded, before openfoam", &b->emb, o->threads);
    print_emb("embedded, after openfoam", &b->emb2, o->threads);
    double setup = r->step_s[FOAM_STEP_CASE] + r->step_s[FOAM_STEP_BLOCKMESH] + r->step_s[FOAM_STEP_TOPOSET] +
                   r->step_s[FOAM_STEP_SUBSETMESH] + r->step_s[FOAM_STEP_DECOMPOSEPAR];
    printf("  openfoam %s (%d rank%s): %d iterations, %s; %.1f s end to end, simpleFoam %.1f s; CPU time %.1f s "
           "(%.2f cores busy on average)\n",
           r->version, o->np,
           o->np > 1 ? "s" : "", r->res.iterations,
           r->steady_iter > 0   ? "monitors steady"
           : r->res.converged   ? "residuals below 1e-4 (residualControl)"
                                : "at the iteration cap",
           r->total_wall_s, r->res.wall_s, b->foam_cpu_s, b->foam_cpu_s / r->total_wall_s);
    printf("    load while it ran %.2f\n", b->foam_load);
    if (r->steady_iter > 0)
        printf("    (the test first passed at iteration %d by its probes' output, was seen passing at %d and "
               "simpleFoam wrote and stopped at %d: %d iterations, about %.1f s, past the first pass)\n",
               b->foam_first, r->steady_iter, r->res.iterations, r->res.iterations - b->foam_first,
               (r->res.iterations - b->foam_first) * r->res.wall_s / r->res.iterations);
    printf("    %.3e cell-iterations/s (%.3e per rank), %.4f s per iteration; residuals p %.2e Ux %.2e Uy %.2e "
           "Uz %.2e k %.2e, monitor change %.2f %% of U over the last 50 iterations\n",
           r->res.cell_updates / r->res.wall_s, r->res.cell_updates / r->res.wall_s / o->np,
           r->res.wall_s / r->res.iterations, r->res.residual[0], r->res.residual[1], r->res.residual[2],
           r->res.residual[3], r->res.residual[4], 100.0 * r->res.monitor_change);
    printf("    steps:");
    for (int i = 0; i < FOAM_NSTEPS; i++)
        printf(" %s %.1f s%s", foam_step_names[i], r->step_s[i], i + 1 < FOAM_NSTEPS ? "," : "\n");
    printf("    its own criterion (residualControl at 1e-4) %s; disim's OpenFOAM engine stops on the common test\n",
           r->res.converged ? "was met" : "was not reached");
    if (b->have_def) {
        print_emb("embedded to its own criterion (residuals 1e-4, monitors 2 %)", &b->def, o->threads);
    }
    printf("  ratio openfoam / embedded to the common criterion (the embedded solver's two runs averaged): %.2f end "
           "to end (%.1f s / %.1f s), %.2f the solvers alone, %.2f per iteration; %.2f and %.2f end to end "
           "against each run\n",
           b->ratio, r->total_wall_s, b->em.total_s, b->ratio_solver, b->ratio_iter,
           r->total_wall_s / b->emb.total_s, r->total_wall_s / b->emb2.total_s);
    printf("  ... with openfoam's time to its first pass of the test (%.1f s, less its %d iterations after it): "
           "%.2f end to end\n",
           b->foam_first_s, b->foam_first > 0 ? r->res.iterations - b->foam_first : 0, b->ratio_first);
    double q = fmin(b->ratio, b->ratio_first);
    if (q >= 5.0) {
        printf("  the embedded solver is 5x faster or more: yes (%.1fx at the least)\n", q);
    } else {
        double tot = r->total_wall_s;
        printf("  the embedded solver is 5x faster or more: NO (%.2fx at the least; it would need to be %.2f "
               "times faster again)\n",
               q, 5.0 / q);
        printf("    where openfoam's time goes: simpleFoam %.0f %% (%d iterations at %.3f s), meshing and "
               "decomposition %.0f %%, reconstruction, cell centres and read-back %.0f %%\n",
               100.0 * r->res.wall_s / tot, r->res.iterations, r->res.wall_s / r->res.iterations,
               100.0 * setup / tot, 100.0 * (tot - setup - r->res.wall_s) / tot);
        printf("    where the embedded solver's goes: solver %.0f %% (%d iterations at %.3f s), set-up %.0f %%, "
               "field %.0f %%; iterations openfoam / embedded %.2f, time per iteration %.2f\n",
               100.0 * b->em.res.wall_s / b->em.total_s, b->em.res.iterations,
               b->em.res.wall_s / b->em.res.iterations, 100.0 * b->em.create_s / b->em.total_s,
               100.0 * b->em.write_s / b->em.total_s, (double)r->res.iterations / b->em.res.iterations,
               b->ratio_iter);
    }
    print_deck("openfoam - embedded (both at the common criterion)", &b->deck);
    if (b->have_def)
        print_deck("embedded at the common criterion - at its own", &b->crit);
}

/* ------------------------------------------------------------- the mode */
static int make_dir(const char *dir)
{
    if (mkdir(dir, 0755) != 0 && errno != EEXIST) {
        fprintf(stderr, "bench_cfd sidebyside: %s: %s\n", dir, strerror(errno));
        return -1;
    }
    return 0;
}

static int load_pair(const char *pa, const char *pb, cfd_field **fa, cfd_field **fb)
{
    core_err err = {0};
    *fa = cfd_field_load(pa, &err);
    *fb = *fa ? cfd_field_load(pb, &err) : NULL;
    if (!*fb) {
        fprintf(stderr, "bench_cfd sidebyside: %s\n", err.msg);
        cfd_field_destroy(*fa);
        *fa = NULL;
        return -1;
    }
    return 0;
}

/* The runs, in order: the embedded solver to the common criterion,
 * OpenFOAM, the embedded solver to its own. 0 or 1. */
static int run_all(sbs *b, const char *dir)
{
    const sbs_opts *o = &b->o;
    char pe[1200], pe2[1200], pf[1200], pd[1200];
    snprintf(pe, sizeof pe, "%s/embedded.h5", dir);
    snprintf(pe2, sizeof pe2, "%s/embedded_after.h5", dir);
    snprintf(pf, sizeof pf, "%s/openfoam.h5", dir);
    snprintf(pd, sizeof pd, "%s/embedded_default.h5", dir);
    cfd_meta meta;
    memset(&meta, 0, sizeof meta);
    meta.wod_speed_mps = b->sp.wod_speed_mps;
    snprintf(meta.ship, sizeof meta.ship, "%s", b->ship.name);
    snprintf(meta.rotor, sizeof meta.rotor, "%s", core_rotor_name(b->sp.rotor));
    snprintf(meta.grid, sizeof meta.grid, "h%.3f m", b->sp.h_fine_m);
    if (o->rotor) {
        meta.rotor_thrust_N = b->sp.disk.thrust_N;
        meta.rotor_radius_m = b->sp.disk.radius_m;
        memcpy(meta.rotor_centre_S_m, b->sp.disk.centre_m, sizeof meta.rotor_centre_S_m);
    }
    omp_set_num_threads(o->threads);
    fprintf(stderr, "sidebyside: the embedded solver, %d thread%s, to the common criterion\n", o->threads,
            o->threads > 1 ? "s" : "");
    if (run_embedded(&b->sp, 1, &meta, pe, "embedded", &b->emb))
        return 1;

    fprintf(stderr, "sidebyside: openfoam, %d rank%s\n", o->np, o->np > 1 ? "s" : "");
    foam_opts fo;
    foam_opts_default(&fo);
    fo.np = o->np;
    fo.max_iter = o->max_iter;
    fo.keep_case = 1; /* its probes' output is read below */
    fo.work_dir = dir;
    ticker tk;
    ticker_start(&tk, "openfoam");
    core_log log = {log_fn, &tk, CORE_LOG_WARN};
    fo.log = &log;
    fo.progress = foam_progress;
    fo.progress_user = &tk;
    core_err err = {0};
    double c0 = cpu_s(RUSAGE_SELF) + cpu_s(RUSAGE_CHILDREN);
    int rc = foam_airwake(&b->sp, &fo, &meta, pf, &b->fr, &err);
    b->foam_cpu_s = cpu_s(RUSAGE_SELF) + cpu_s(RUSAGE_CHILDREN) - c0;
    ticker_end(&tk);
    b->foam_load = ticker_load(&tk);
    if (b->fr.case_dir[0]) {
        b->foam_first = foam_first_pass(b->fr.case_dir, b->sp.wod_speed_mps, 0.02);
        if (o->keep_case)
            fprintf(stderr, "sidebyside: openfoam's case kept in %s\n", b->fr.case_dir);
        else
            nftw(b->fr.case_dir, rm_entry, 16, FTW_DEPTH | FTW_PHYS);
    }
    if (rc != 0) {
        fprintf(stderr, "bench_cfd sidebyside: openfoam: %s\n", rc < 0 ? err.msg : "stopped");
        return 1;
    }

    /* once more, so that a change of the machine's load during the long
     * OpenFOAM run weighs on both engines' figures */
    fprintf(stderr, "sidebyside: the embedded solver to the common criterion again\n");
    if (run_embedded(&b->sp, 1, &meta, pe2, "embedded (again)", &b->emb2))
        return 1;
    b->em = b->emb;
    b->em.create_s = 0.5 * (b->emb.create_s + b->emb2.create_s);
    b->em.res.wall_s = 0.5 * (b->emb.res.wall_s + b->emb2.res.wall_s);
    b->em.res.cell_updates = 0.5 * (b->emb.res.cell_updates + b->emb2.res.cell_updates);
    b->em.res.iterations = (int)lround(0.5 * (b->emb.res.iterations + b->emb2.res.iterations));
    b->em.write_s = 0.5 * (b->emb.write_s + b->emb2.write_s);
    b->em.total_s = 0.5 * (b->emb.total_s + b->emb2.total_s);
    b->em.cpu_s = 0.5 * (b->emb.cpu_s + b->emb2.cpu_s);
    b->em.load = 0.5 * (b->emb.load + b->emb2.load);

    if (o->run_default) {
        fprintf(stderr, "sidebyside: the embedded solver to its own criterion\n");
        if (run_embedded(&b->sp, 0, &meta, pd, "embedded (its own criterion)", &b->def))
            return 1;
        b->have_def = 1;
    }
    loadavg(b->load1);

    cfd_field *fe = NULL, *ff = NULL;
    if (load_pair(pe, pf, &fe, &ff))
        return 1;
    cfd_flow a = {NULL, ff}, e = {NULL, fe};
    cfd_airwake_deck_diff(&b->ship, &a, &e, b->sp.wod_speed_mps, &b->deck);
    cfd_field_destroy(ff);
    if (b->have_def) {
        cfd_field *fd = cfd_field_load(pd, &err);
        if (!fd) {
            fprintf(stderr, "bench_cfd sidebyside: %s\n", err.msg);
            cfd_field_destroy(fe);
            return 1;
        }
        cfd_flow d = {NULL, fd};
        cfd_airwake_deck_diff(&b->ship, &e, &d, b->sp.wod_speed_mps, &b->crit);
        cfd_field_destroy(fd);
    }
    cfd_field_destroy(fe);

    b->ratio = b->fr.total_wall_s / b->em.total_s;
    b->ratio_solver = b->fr.res.wall_s / b->em.res.wall_s;
    b->ratio_iter = (b->fr.res.wall_s / b->fr.res.iterations) / (b->em.res.wall_s / b->em.res.iterations);
    int past = b->foam_first > 0 ? b->fr.res.iterations - b->foam_first : 0;
    b->foam_first_s = b->fr.total_wall_s - past * b->fr.res.wall_s / b->fr.res.iterations;
    b->ratio_first = b->foam_first_s / b->em.total_s;
    return 0;
}

static void remove_outputs(const char *dir)
{
    static const char *const names[] = {"embedded.h5", "embedded.xmf", "embedded_after.h5", "embedded_after.xmf",
                                        "openfoam.h5", "openfoam.xmf",
                                        "embedded_default.h5", "embedded_default.xmf"};
    char p[1200];
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        snprintf(p, sizeof p, "%s/%s", dir, names[i]);
        remove(p);
    }
}

int bench_cfd_sidebyside(int argc, char **argv)
{
    static sbs b;
    memset(&b, 0, sizeof b);
    int prc = parse(argc, argv, &b.o);
    if (prc)
        return prc;
    const sbs_opts *o = &b.o;
    static char cmd[2048];
    snprintf(cmd, sizeof cmd, "bench_cfd sidebyside");
    for (int i = 0; i < argc; i++)
        snprintf(cmd + strlen(cmd), sizeof cmd - strlen(cmd), " %s", argv[i]);
    b.cmd = cmd;
    foam_opts fo;
    foam_opts_default(&fo);
    fo.np = o->np;
    char why[256];
    if (!foam_available(&fo, why, sizeof why)) {
        fprintf(stderr, "bench_cfd sidebyside: %s\n", why);
        return 1;
    }
    if (bench_cfd_setup_ship(&b.ship, &b.sp, o->ship, 15.0, CORE_GRID_COARSE, 0.0, o->rotor))
        return 1;
    b.sp.max_iter = o->max_iter;
    b.cores = sysconf(_SC_NPROCESSORS_ONLN);
    cpu_model(b.cpu, sizeof b.cpu);
    loadavg(b.load0);
    core_err err = {0};
    if (o->h_fine_m > 0.0) {
        b.sp.h_fine_m = o->h_fine_m;
    } else {
        fprintf(stderr, "sidebyside: sizing the grid to about %.0f fluid cells\n", o->cells);
        if (size_grid(&b.sp, o->cells, &err)) {
            fprintf(stderr, "bench_cfd sidebyside: %s\n", err.msg);
            return 1;
        }
    }
    cfd_solver *s = cfd_airwake_create(&b.sp, NULL, NULL, NULL, &err);
    if (!s) {
        fprintf(stderr, "bench_cfd sidebyside: %s\n", err.msg);
        return 1;
    }
    const cfd_grid *g = cfd_solver_grid(s);
    cfd_grid_dims(g, b.dims);
    b.cells = cfd_grid_cells(g);
    b.fluid = cfd_grid_fluid_cells(g);
    spacings(g, b.dx_lo, b.dx_hi);
    cfd_solver_destroy(s);
    fprintf(stderr, "sidebyside: grid %d x %d x %d = %zu cells, %zu fluid, focus spacing %.3f m\n", b.dims[0],
            b.dims[1], b.dims[2], b.cells, b.fluid, b.sp.h_fine_m);

    char tmp[] = "/tmp/bench_sidebyside_XXXXXX";
    const char *dir = o->out_dir;
    if (dir ? make_dir(dir) : !mkdtemp(tmp))
        return 1;
    if (!dir)
        dir = tmp;
    int rc = run_all(&b, dir);
    if (!rc) {
        print_report(&b);
        if (o->out_dir && (write_json(&b, dir) || write_csv(&b, dir))) {
            fprintf(stderr, "bench_cfd sidebyside: cannot write the figures into %s\n", dir);
            rc = 1;
        }
    }
    if (!o->out_dir) {
        remove_outputs(dir);
        if (!o->keep_case)
            rmdir(dir);
    }
    return rc;
}
