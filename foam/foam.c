/* foam.c -- an airwake case through OpenFOAM, step by step, and OpenFOAM
 * as an airwake builder engine. The steps (each a program of the package,
 * its log in the case folder as log.STEP):
 *   blockMesh; topoSet (the ship's cells, the disk's zones); subsetMesh
 *   fluidCells -patch ship -overwrite (the ship carved out); with np > 1
 *   decomposePar, mpirun -np N simpleFoam -parallel and reconstructPar
 *   -latestTime, else simpleFoam; postProcess -func writeCellCentres;
 * then the latest time read back onto the embedded solver's grid and
 * written through cfd_solver_write (temporary file and rename). */
/* nftw */
#define _XOPEN_SOURCE 700
#include "foam_private.h"

#include <errno.h>
#include <dirent.h>
#include <ftw.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#define FOAM_DEFAULT_ETC "/usr/share/openfoam/etc"

void foam_opts_default(foam_opts *o)
{
    memset(o, 0, sizeof *o);
    o->np = 2;
}

static const char *etc_dir(const foam_opts *o)
{
    const char *e = o && o->foam_etc ? o->foam_etc : getenv("FOAM_ETC");
    return e && *e ? e : FOAM_DEFAULT_ETC;
}

int foam_available(const foam_opts *o, char *why, size_t n)
{
    static const char *const progs[] = {"blockMesh", "topoSet", "subsetMesh", "simpleFoam", "postProcess",
                                        "decomposePar", "reconstructPar"};
    char p[1024];
    for (size_t i = 0; i < sizeof progs / sizeof progs[0]; i++)
        if (!foam_which(progs[i], p, sizeof p)) {
            snprintf(why, n, "OpenFOAM's %s is not on PATH (install the openfoam package: go.sh does)", progs[i]);
            return 0;
        }
    if ((!o || o->np > 1) && !foam_which("mpirun", p, sizeof p)) {
        snprintf(why, n, "mpirun is not on PATH (install openmpi-bin: go.sh does)");
        return 0;
    }
    struct stat st;
    if (o && o->hostfile && (stat(o->hostfile, &st) != 0 || !S_ISREG(st.st_mode) || access(o->hostfile, R_OK) != 0)) {
        snprintf(why, n, "the hostfile %s is not a readable file", o->hostfile);
        return 0;
    }
    snprintf(p, sizeof p, "%s/controlDict", etc_dir(o));
    if (access(p, R_OK) != 0) {
        snprintf(why, n, "OpenFOAM's etc folder %s has no controlDict (set FOAM_ETC)", etc_dir(o));
        return 0;
    }
    return 1;
}

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

static int rm_entry(const char *path, const struct stat *st, int flag, struct FTW *ftw)
{
    (void)st, (void)flag, (void)ftw;
    remove(path);
    return 0;
}

static void rm_tree(const char *dir)
{
    nftw(dir, rm_entry, 16, FTW_DEPTH | FTW_PHYS);
}

/* The refusals: what the engine does not build. NULL when spec is one it
 * does (a deck zone and the ABL inflow among them: their inlets take the
 * embedded solver's inflow face by face, case.c). */
static const char *unsupported(const cfd_airwake_spec *sp, const foam_opts *o)
{
    if (sp->rotor == CORE_ROTOR_LOADED && !o->blades)
        return "the loaded rotor without the aircraft's blades (rotorDisk needs them)";
    return NULL;
}

typedef struct poll_ctx {
    const foam_opts *o;
    const char *dir;
    const char *log_path;
    int max_iter;
    double u_ref, tol_monitor;
    int steady_asked; /* the stop file written */
    int steady_iter;  /* the iteration the monitors were found steady at */
} poll_ctx;

/* The monitor velocities (probes) of the rows at iterations it, it - 50
 * and it - 100 from the tail of the probes' output; the largest change
 * over each of the two windows, / u_ref, into ch[2]. 0, or -1 when the
 * output does not reach back 100 iterations yet. */
#define FOAM_MONITOR_WINDOW 50
static int monitor_windows(const poll_ctx *c, int *it, double ch[2])
{
    char p[1200];
    snprintf(p, sizeof p, "%s/postProcessing/monitors/0/U", c->dir);
    size_t n = 1 << 18;
    char *b = malloc(n);
    if (!b)
        return -1;
    foam_log_tail(p, b, n);
    /* the last row and the rows 50 and 100 before it, by line */
    const char *rows[2 * FOAM_MONITOR_WINDOW + 1];
    int nr = 0;
    for (char *l = b + strlen(b); l > b;) {
        char *st = l;
        while (st > b && st[-1] != '\n')
            st--;
        if (*st != '#' && st < l)
            rows[nr++] = st;
        if (nr == 2 * FOAM_MONITOR_WINDOW + 1)
            break;
        l = st > b ? st - 1 : b;
    }
    int rc = -1;
    if (nr == 2 * FOAM_MONITOR_WINDOW + 1) {
        const char *r3[3] = {rows[0], rows[FOAM_MONITOR_WINDOW], rows[2 * FOAM_MONITOR_WINDOW]};
        double v[3][CFD_MAX_MONITOR][3];
        int nm[3] = {0, 0, 0};
        for (int q = 0; q < 3; q++) {
            const char *a = r3[q];
            char *e;
            double t = strtod(a, &e);
            if (q == 0)
                *it = (int)t;
            a = e;
            while (nm[q] < CFD_MAX_MONITOR) {
                const char *pa = strchr(a, '('), *nl = strchr(a, '\n');
                if (!pa || (nl && pa > nl))
                    break;
                a = pa + 1;
                for (int d = 0; d < 3; d++) {
                    v[q][nm[q]][d] = strtod(a, &e);
                    a = e;
                }
                nm[q]++;
            }
        }
        if (nm[0] > 0 && nm[0] == nm[1] && nm[1] == nm[2]) {
            ch[0] = ch[1] = 0.0;
            for (int m = 0; m < nm[0]; m++)
                for (int w = 0; w < 2; w++) {
                    double d2 = 0.0;
                    for (int d = 0; d < 3; d++)
                        d2 += (v[w][m][d] - v[w + 1][m][d]) * (v[w][m][d] - v[w + 1][m][d]);
                    ch[w] = fmax(ch[w], sqrt(d2) / c->u_ref);
                }
            rc = 0;
        }
    }
    free(b);
    return rc;
}

/* Ask simpleFoam to write and stop: the abort function object of its
 * controlDict sees the stop file at its next iteration. */
static int ask_write_now(const char *dir)
{
    char p[1200];
    snprintf(p, sizeof p, "%s/%s", dir, FOAM_STOP_FILE);
    FILE *f = fopen(p, "w");
    return f && fclose(f) == 0 ? 0 : -1;
}

/* simpleFoam's progress from its log's tail, and the monitors' test: once
 * the monitor velocities change by less than tol_monitor u_ref over each
 * of the last two windows of 50 iterations (the embedded solver's test)
 * after at least 200 iterations, the run is asked to write and stop
 * (OpenFOAM's residuals stall above 1e-4 on these grids; docs/openfoam.md). */
static int on_poll(void *user)
{
    poll_ctx *c = user;
    char tail[4096];
    foam_log_tail(c->log_path, tail, sizeof tail);
    const char *t = NULL, *q = tail;
    while ((q = strstr(q, "\nTime = ")))
        t = q++;
    int it = t ? atoi(t + 8) : 0;
    /* the last p solve in the tail (the last iteration's, or the one before) */
    const char *r = NULL;
    for (q = tail; (q = strstr(q, "Solving for p,")); q++)
        r = q;
    r = r ? strstr(r, "Initial residual = ") : NULL;
    double res = r ? strtod(r + 19, NULL) : 1.0;
    int mit;
    double ch[2];
    if (!c->steady_asked && c->tol_monitor > 0.0 && monitor_windows(c, &mit, ch) == 0 && mit >= 200 &&
        ch[0] < c->tol_monitor && ch[1] < c->tol_monitor && ask_write_now(c->dir) == 0) {
        c->steady_asked = 1;
        c->steady_iter = mit;
        core_log_msg(c->o->log, CORE_LOG_INFO,
                     "openfoam: monitors steady at iteration %d (changes %.4f, %.4f of U over 50 iterations): "
                     "writing and stopping",
                     mit, ch[0], ch[1]);
    }
    if (!c->o->progress)
        return 0;
    return c->o->progress(c->o->progress_user, c->max_iter > 0 ? (double)it / c->max_iter : 0.0, res, it);
}

const char *const foam_step_names[FOAM_NSTEPS] = {"case", "blockMesh", "topoSet", "subsetMesh",
                                                   "decomposePar", "simpleFoam", "reconstructPar",
                                                   "postProcess", "read", "write"};

/* foam_exec, its wall time into *t. */
static int timed_exec(double *t, const char *dir, const char *step, char *const argv[], const char *etc,
                      double tmo, foam_poll_fn poll, void *poll_user, core_err *err)
{
    double t0 = now_s();
    int rc = foam_exec(dir, step, argv, etc, tmo, poll, poll_user, err);
    *t = now_s() - t0;
    return rc;
}

/* The OpenFOAM steps in case_dir, each one's wall time into st. 0, 1
 * stopped, < 0 failed. */
static int run_steps(const char *dir, const foam_opts *o, const cfd_config *cfg, int has_ship, int has_zones,
                     int max_iter, double *solve_s, int *steady_iter, double st[FOAM_NSTEPS], core_err *err)
{
    const char *etc = etc_dir(o);
    double tmo = o->timeout_s > 0.0 ? o->timeout_s : 6 * 3600.0;
    char *mesh[] = {"blockMesh", NULL};
    char *topo[] = {"topoSet", NULL};
    char *subset[] = {"subsetMesh", "fluidCells", "-patch", FOAM_SHIP_PATCH, "-overwrite", NULL};
    char *decomp[] = {"decomposePar", "-force", NULL};
    char *recon[] = {"reconstructPar", "-latestTime", NULL};
    char *centres[] = {"postProcess", "-func", "writeCellCentres", "-latestTime", NULL};
    char *serial[] = {"simpleFoam", NULL};
    char np[16];
    snprintf(np, sizeof np, "%d", o->np);
    char *mpi[14];
    int m = 0;
    mpi[m++] = "mpirun";
    if (geteuid() == 0)
        mpi[m++] = "--allow-run-as-root";
    if (o->hostfile) {
        mpi[m++] = "--hostfile";
        mpi[m++] = (char *)o->hostfile;
    }
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    if (cores > 0 && o->np > cores)
        mpi[m++] = "--oversubscribe";
    mpi[m++] = "-np";
    mpi[m++] = np;
    mpi[m++] = "simpleFoam";
    mpi[m++] = "-parallel";
    mpi[m] = NULL;
    char logp[1200];
    snprintf(logp, sizeof logp, "%s/log.simpleFoam", dir);
    poll_ctx pc = {o, dir, logp, max_iter, cfg->u_ref_mps, cfg->n_monitor > 0 ? cfg->tol_monitor : 0.0, 0, 0};
    int rc = timed_exec(&st[FOAM_STEP_BLOCKMESH], dir, "blockMesh", mesh, etc, tmo, NULL, NULL, err);
    if (!rc && (has_ship || has_zones))
        rc = timed_exec(&st[FOAM_STEP_TOPOSET], dir, "topoSet", topo, etc, tmo, NULL, NULL, err);
    if (!rc && has_ship)
        rc = timed_exec(&st[FOAM_STEP_SUBSETMESH], dir, "subsetMesh", subset, etc, tmo, NULL, NULL, err);
    if (!rc && o->np > 1)
        rc = timed_exec(&st[FOAM_STEP_DECOMPOSEPAR], dir, "decomposePar", decomp, etc, tmo, NULL, NULL, err);
    if (!rc)
        rc = timed_exec(&st[FOAM_STEP_SIMPLEFOAM], dir, "simpleFoam", o->np > 1 ? mpi : serial, etc, tmo, on_poll,
                        &pc, err);
    *solve_s = st[FOAM_STEP_SIMPLEFOAM];
    *steady_iter = pc.steady_iter;
    if (!rc && o->np > 1)
        rc = timed_exec(&st[FOAM_STEP_RECONSTRUCTPAR], dir, "reconstructPar", recon, etc, tmo, NULL, NULL, err);
    if (!rc)
        rc = timed_exec(&st[FOAM_STEP_POSTPROCESS], dir, "postProcess", centres, etc, tmo, NULL, NULL, err);
    return rc;
}

static int make_case_dir(const foam_opts *o, char *dir, size_t n, core_err *err)
{
    const char *base = o->work_dir ? o->work_dir : getenv("TMPDIR");
    if (!base || !*base)
        base = "/tmp";
    if (snprintf(dir, n, "%s/disim-foam-XXXXXX", base) >= (int)n)
        return core_err_set(err, -1, "foam: work folder path too long: %s", base);
    if (!mkdtemp(dir))
        return core_err_set(err, -1, "foam: cannot make a case folder in %s: %s", base, strerror(errno));
    return 0;
}

int foam_case_write(const cfd_airwake_spec *spec, const foam_opts *o, const char *dir, core_err *err)
{
    const char *why = unsupported(spec, o);
    if (why)
        return core_err_set(err, -1, "the OpenFOAM engine does not build %s", why);
    cfd_solver *s = cfd_airwake_create(spec, o->log, NULL, NULL, err);
    if (!s)
        return -1;
    cfd_solver_init_inflow(s);
    int has_ship;
    int max_iter = o->max_iter > 0 ? o->max_iter : spec->max_iter > 0 ? spec->max_iter : 3000;
    int rc = foam_case_files(s, spec, o->blades, o->np > 1 ? o->np : 1, max_iter, dir, &has_ship, err);
    cfd_solver_destroy(s);
    return rc;
}

int foam_airwake(const cfd_airwake_spec *spec, const foam_opts *o, const cfd_meta *meta, const char *out_path,
                 foam_result *res, core_err *err)
{
    memset(res, 0, sizeof *res);
    const char *why = unsupported(spec, o);
    if (why)
        return core_err_set(err, -1, "the OpenFOAM engine does not build %s", why);
    char avail[256];
    if (!foam_available(o, avail, sizeof avail))
        return core_err_set(err, -1, "the OpenFOAM engine cannot run: %s", avail);
    if (o->np < 1)
        return core_err_set(err, -1, "the OpenFOAM engine: np %d: expected 1 or more ranks", o->np);
    double t0 = now_s();
    cfd_solver *s = cfd_airwake_create(spec, o->log, NULL, NULL, err);
    if (!s)
        return -1;
    cfd_solver_init_inflow(s);
    int max_iter = o->max_iter > 0 ? o->max_iter : spec->max_iter > 0 ? spec->max_iter : 3000;
    int rc = make_case_dir(o, res->case_dir, sizeof res->case_dir, err);
    if (rc) {
        cfd_solver_destroy(s);
        return rc;
    }
    int has_ship = 0;
    const hfm_blade_data *blades = spec->rotor == CORE_ROTOR_LOADED ? o->blades : NULL;
    rc = foam_case_files(s, spec, blades, o->np, max_iter, res->case_dir, &has_ship, err);
    double solve_s = 0.0;
    int steady_iter = 0;
    if (!rc) {
        core_log_msg(o->log, CORE_LOG_INFO, "openfoam: case %s, %zu fluid cells, %d rank%s", res->case_dir,
                     cfd_grid_fluid_cells(cfd_solver_grid(s)), o->np, o->np > 1 ? "s" : "");
        res->step_s[FOAM_STEP_CASE] = now_s() - t0;
        rc = run_steps(res->case_dir, o, cfd_solver_config(s), has_ship, cfd_solver_disk_force(s, 0) != NULL, max_iter,
                       &solve_s, &steady_iter, res->step_s, err);
    }
    foam_log_info info;
    char logp[1200];
    snprintf(logp, sizeof logp, "%s/log.simpleFoam", res->case_dir);
    if (!rc && foam_log_parse(logp, &info) != 0)
        rc = core_err_set(err, -1, "OpenFOAM step simpleFoam: %s has no iteration", logp);
    double t_read = now_s();
    if (!rc)
        rc = foam_read_fields(res->case_dir, s, &res->cells, err);
    char tdir[256];
    if (!rc && blades && foam_latest_time(res->case_dir, tdir, sizeof tdir) != 0)
        rc = core_err_set(err, -1, "OpenFOAM result: %s has no time folder", res->case_dir);
    if (!rc && blades)
        rc = foam_blade_result(res->case_dir, tdir, s, &spec->disk, res, err);
    res->step_s[FOAM_STEP_READ] = now_s() - t_read;
    if (!rc) {
        res->res.iterations = info.iterations;
        res->res.converged = info.converged;
        memcpy(res->res.residual, info.residual, sizeof res->res.residual);
        res->res.wall_s = solve_s;
        res->res.cell_updates = (double)res->cells * info.iterations;
        res->res.monitor_change = foam_monitor_change(res->case_dir, 50, cfd_solver_config(s)->u_ref_mps);
        res->res.mean_change = -1.0;
        res->steady_iter = steady_iter;
        snprintf(res->version, sizeof res->version, "%s", info.version[0] ? info.version : "unknown");
        cfd_meta m = *meta;
        snprintf(m.engine, sizeof m.engine, "openfoam");
        snprintf(m.engine_version, sizeof m.engine_version, "OpenFOAM %.54s", res->version);
        m.result = res->res;
        if (blades) {
            snprintf(m.rotor_model, sizeof m.rotor_model, "rotorDisk");
            m.rotor_force_N = res->rotor_force_N;
            m.rotor_torque_Nm = res->rotor_torque_Nm;
        }
        double t_write = now_s();
        rc = cfd_solver_write(s, &m, out_path, err);
        res->step_s[FOAM_STEP_WRITE] = now_s() - t_write;
    }
    cfd_solver_destroy(s);
    if (!o->keep_case)
        rm_tree(res->case_dir);
    res->total_wall_s = now_s() - t0;
    return rc;
}

/* ------------------------------------------------------- builder engine */
struct foam_engine {
    foam_opts o;
    int nships;
    core_ship *ships;
    const char *aircraft_dir;
    awdb *db; /* where deck zones find their ship-only boundary field */
};

void foam_engine_set_db(foam_engine *e, awdb *db)
{
    e->db = db;
}

foam_engine *foam_engine_create(const char *ships_dir, const char *aircraft_dir, const foam_opts *o, core_err *err)
{
    foam_engine *e = calloc(1, sizeof *e);
    if (!e) {
        core_err_set(err, -1, "%s: out of memory", ships_dir);
        return NULL;
    }
    e->o = *o;
    e->aircraft_dir = aircraft_dir;
    if (core_ship_load_dir(ships_dir, &e->ships, &e->nships, err) != 0) {
        foam_engine_destroy(e);
        return NULL;
    }
    return e;
}

void foam_engine_destroy(foam_engine *e)
{
    if (!e)
        return;
    free(e->ships);
    free(e);
}

/* The blades of the aircraft file in dir whose [aircraft] name is name. */
static int find_blades(const char *dir, const char *name, const core_log *log, hfm_blade_data *b, core_err *err)
{
    if (!dir)
        return core_err_set(err, -1, "aircraft '%s': the loaded rotor needs the aircraft files (no folder given)",
                            name);
    DIR *d = opendir(dir);
    if (!d)
        return core_err_set(err, -1, "%s: %s", dir, strerror(errno));
    struct dirent *en;
    int found = 0;
    while (!found && (en = readdir(d))) {
        size_t l = strlen(en->d_name);
        if (l < 5 || strcmp(en->d_name + l - 4, ".ini") != 0)
            continue;
        char p[1200];
        snprintf(p, sizeof p, "%s/%s", dir, en->d_name);
        core_err e2;
        hfm_aircraft *ac = hfm_aircraft_load(p, log, &e2);
        if (ac && !strcmp(hfm_aircraft_name(ac), name)) {
            hfm_aircraft_blade_data(ac, b);
            found = 1;
        }
        hfm_aircraft_destroy(ac);
    }
    closedir(d);
    return found ? 0 : core_err_set(err, -1, "aircraft '%s': no aircraft file of that name in %s", name, dir);
}

static int engine_build(void *user, const awdb_key *k, const char *warm_path, const char *out_path,
                        awdb_progress_fn progress, void *progress_user, core_err *err)
{
    (void)warm_path; /* OpenFOAM starts from the inflow */
    foam_engine *e = user;
    const char *iso = strstr(k->ship, ".isolated");
    size_t len = iso && iso[9] == '\0' ? (size_t)(iso - k->ship) : strlen(k->ship);
    const core_ship *ship = core_ship_find(e->ships, e->nships, k->ship, len);
    if (!ship)
        return core_err_set(err, -1, "ship '%s': no ship file of that name", k->ship);
    cfd_airwake_spec spec;
    if (awdb_key_spec(k, ship, &spec, err) != 0)
        return -1;
    cfd_field *outer = NULL; /* a deck zone's boundary; outlives the case */
    if (spec.zone && !(iso && iso[9] == '\0')) {
        if (!(outer = awdb_zone_boundary(e->db, k, err)))
            return -1;
        spec.zone_field = outer;
        spec.zone_scale = k->wod_speed_mps / k->zone_ref_mps;
    }
    foam_opts o = e->o;
    hfm_blade_data *blades = NULL;
    if (k->rotor == CORE_ROTOR_LOADED) {
        if (!(blades = malloc(sizeof *blades)))
            return core_err_set(err, -2, "out of memory");
        if (find_blades(e->aircraft_dir, k->aircraft, o.log, blades, err) != 0) {
            free(blades);
            cfd_field_destroy(outer);
            return -1;
        }
        o.blades = blades;
    }
    o.progress = progress;
    o.progress_user = progress_user;
    cfd_meta meta;
    memset(&meta, 0, sizeof meta);
    meta.wod_speed_mps = k->wod_speed_mps;
    meta.wod_dir_deg = k->wod_dir_rad * CORE_RAD_TO_DEG;
    snprintf(meta.ship, sizeof meta.ship, "%.63s", k->ship);
    snprintf(meta.rotor, sizeof meta.rotor, "%s", core_rotor_name(k->rotor));
    snprintf(meta.grid, sizeof meta.grid, "%s", core_grid_name(k->grid));
    meta.rotor_thrust_N = k->thrust_N;
    meta.rotor_radius_m = k->radius_m;
    memcpy(meta.rotor_centre_S_m, k->station_S_m, sizeof meta.rotor_centre_S_m);
    foam_result r;
    int rc = foam_airwake(&spec, &o, &meta, out_path, &r, err);
    free(blades);
    cfd_field_destroy(outer);
    /* the database keeps the HDF5 file only */
    char xmf[1200];
    size_t l = strlen(out_path);
    snprintf(xmf, sizeof xmf, "%s.xmf", out_path);
    remove(xmf);
    if (l > 3 && !strcmp(out_path + l - 3, ".h5")) {
        snprintf(xmf, sizeof xmf, "%.*s.xmf", (int)(l - 3), out_path);
        remove(xmf);
    }
    if (rc == 0)
        core_log_msg(o.log, CORE_LOG_INFO, "openfoam %s: %s v=%.2f dir=%.1f: %d iterations, %.0f s, %s", r.version,
                     k->ship, k->wod_speed_mps, k->wod_dir_rad * CORE_RAD_TO_DEG, r.res.iterations, r.total_wall_s,
                     r.res.converged        ? "converged"
                     : r.steady_iter > 0    ? "monitors steady, residuals above 1e-4"
                                            : "not converged (at the iteration cap)");
    if (rc == 0 && k->rotor == CORE_ROTOR_LOADED)
        core_log_msg(o.log, CORE_LOG_INFO,
                     "openfoam rotorDisk: thrust %.0f N of %.0f N (%+.2f %%), theta0 %.2f deg, theta1c %.2f deg, "
                     "theta1s %.2f deg%s",
                     r.rotor_force_N, k->thrust_N, 100.0 * (r.rotor_force_N / k->thrust_N - 1.0), r.trim_pitch_deg[0],
                     r.trim_pitch_deg[1], r.trim_pitch_deg[2], r.trim_converged ? "" : " (trim not converged)");
    return rc;
}

void foam_engine_get(foam_engine *e, awdb_engine *eng)
{
    memset(eng, 0, sizeof *eng);
    eng->name = "openfoam";
    eng->build = engine_build;
    eng->user = e;
}
