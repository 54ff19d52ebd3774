/* test_foam.c -- the OpenFOAM engine against the embedded solver on the
 * same grid: SFS2 in a 15 m/s headwind on the reduced coarse grid (2.4 m
 * focus spacing, the CI size of the sfs2 validation case), solved by the
 * embedded solver and by OpenFOAM through mpirun -np 2; the velocities
 * along the deck lines compared in % of the wind speed (docs/openfoam.md
 * has the figures). A failing OpenFOAM step must stop the run with the
 * step's name and its log's tail and write nothing. The case writer's
 * grading is checked without OpenFOAM; the rest skips (77) where OpenFOAM
 * or mpirun is absent, and under CI that fails. `test_foam blade`: the
 * blade-element rotor through the builder's engine (test_foam_blade.c);
 * `test_foam inflow`: the ABL inflow and a deck zone, their inlets face by
 * face (test_foam_inflow.c). */
#include "cfd.h"
#include "check.h"
#include "core.h"
#include "foam.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

static void log_stderr(void *user, int lv, const char *msg)
{
    (void)user;
    (void)lv;
    fprintf(stderr, "  %s\n", msg);
}

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

static void spec_sfs2(cfd_airwake_spec *sp, const core_ship *ship, int rotor)
{
    memset(sp, 0, sizeof *sp);
    sp->ship = ship;
    sp->wod_speed_mps = 15.0;
    sp->wod_dir_rad = 0.0;
    sp->level = CORE_GRID_COARSE;
    sp->h_fine_m = 2.4;
    sp->monitor_z_m = -6.8;
    sp->max_iter = 800;
    sp->rotor = rotor ? CORE_ROTOR_UNIFORM : CORE_ROTOR_OFF;
    if (rotor) {
        double c[3] = {0.0, 0.0, -8.18};
        core_euler att = {0.0, 0.0, 0.0};
        cfd_disk_from_attitude(&sp->disk, c, att, 8.18, 7438.91 * CORE_G_MPS2);
    }
}

/* A step that fails: a simpleFoam first on PATH that prints and exits 3. */
static void check_failing_step(const cfd_airwake_spec *sp, const foam_opts *o0, const char *tmp)
{
    char bin[1200], prog[1300], out[1300], path[4200];
    snprintf(bin, sizeof bin, "%s/bin", tmp);
    mkdir(bin, 0755);
    snprintf(prog, sizeof prog, "%s/simpleFoam", bin);
    FILE *f = fopen(prog, "w");
    CHECK(f != NULL);
    if (!f)
        return;
    fprintf(f, "#!/bin/sh\necho 'a broken solver: no convergence today'\nexit 3\n");
    fclose(f);
    chmod(prog, 0755);
    const char *old = getenv("PATH");
    char *saved = strdup(old ? old : "");
    snprintf(path, sizeof path, "%s:%s", bin, saved);
    setenv("PATH", path, 1);
    snprintf(out, sizeof out, "%s/failed.h5", tmp);
    foam_opts o = *o0;
    o.keep_case = 0;
    cfd_meta meta;
    memset(&meta, 0, sizeof meta);
    foam_result r;
    core_err err = {0};
    int rc = foam_airwake(sp, &o, &meta, out, &r, &err);
    setenv("PATH", saved, 1);
    free(saved);
    printf("failing step: rc %d: %s\n", rc, err.msg);
    CHECK(rc < 0);
    CHECK(strstr(err.msg, "simpleFoam") != NULL);
    CHECK(strstr(err.msg, "a broken solver") != NULL);
    CHECK(access(out, F_OK) != 0);
    CHECK(access(r.case_dir, F_OK) != 0); /* the case folder is removed */
}

/* A velocity at a point: a solver's or a loaded field's. */
typedef struct sampler {
    const cfd_solver *s;
    const cfd_field *f;
} sampler;

static void sample(const sampler *a, const double p[3], double out[CFD_NVARS])
{
    if (a->s)
        cfd_solver_sample(a->s, p, out);
    else
        cfd_field_sample(a->f, p, out);
}

/* The largest velocity difference between a and b along the deck lines
 * (cfd_airwake_deck_diff: 9 lines along the deck, port quarter, centre line
 * and starboard quarter at 3.8 m, 6.8 m (the hangar's height) and 10 m
 * above the deck), / U, where it is in at, and the RMS difference over
 * every point in *rms; with label, each line's is printed. */
static double deck_lines(const core_ship *ship, const sampler *a, const sampler *b, double U, double *at,
                         double *rms, const char *label)
{
    cfd_flow fa = {a->s, a->f}, fb = {b->s, b->f};
    cfd_deck_diff d;
    cfd_airwake_deck_diff(ship, &fa, &fb, U, &d);
    for (int l = 0; label && l < CFD_DECK_LINES; l++)
        printf("%s: deck line y %+.1f m, z %.1f m: largest difference %.1f %% of U at x %.1f m\n", label,
               d.line_y_m[l], d.line_z_m[l], 100.0 * d.line_worst[l], d.line_worst_x_m[l]);
    memcpy(at, d.worst_at_m, sizeof d.worst_at_m);
    *rms = d.rms;
    return d.worst;
}

/* Where the flow reattaches behind the hangar along the centre line at z
 * (the first zero crossing of the along-wind velocity aft of the hangar
 * face after reversed flow next to it), m aft of the face; -1 when the
 * flow next to the hangar is not reversed, the reach searched when it
 * does not turn forward again. */
static double reattachment(const core_ship *ship, const sampler *a, double dir_rad, double z)
{
    core_vec3 w = core_wod_vel_S_mps(1.0, dir_rad);
    double prev = 0.0, reach = 3.0 * (ship->deck_x1_m - ship->deck_x0_m);
    int reversed = 0;
    for (double dx = 0.25; dx < reach; dx += 0.05) {
        double p[3] = {ship->deck_x1_m - dx, 0.0, z}, o[CFD_NVARS];
        sample(a, p, o);
        double along = o[0] * w.x + o[1] * w.y;
        if (along < 0.0)
            reversed = 1;
        else if (reversed)
            return dx - 0.05 + 0.05 * prev / (prev - along);
        else if (dx > 2.0)
            return -1.0;
        prev = along;
    }
    return reversed ? reach : -1.0;
}

/* The largest velocity difference, / U, along lines away from the ship:
 * a vertical line 60 m ahead of the bow and one above the deck from 25 m
 * to 60 m up. */
static double far_field(const core_ship *ship, const sampler *a, const sampler *b, double U)
{
    double worst = 0.0;
    double bow = ship->deck_x0_m + ship->length_m;
    for (int i = 0; i <= 20; i++) {
        double pts[2][3] = {{bow + 60.0, 0.0, -60.0 * i / 20.0}, {0.0, 0.0, -25.0 - 35.0 * i / 20.0}};
        for (int q = 0; q < 2; q++) {
            double e[CFD_NVARS], o[CFD_NVARS], d2 = 0.0;
            sample(a, pts[q], e);
            sample(b, pts[q], o);
            for (int d = 0; d < 3; d++)
                d2 += (e[d] - o[d]) * (e[d] - o[d]);
            worst = fmax(worst, sqrt(d2) / U);
        }
    }
    return worst;
}

/* The case writer, without OpenFOAM: the blockMeshDict's grading, laid
 * out as blockMesh lays it out (each section geometric: n cells growing by
 * E^(1/(n-1)) over its length), gives disim's nodes on every axis. */
static void check_grading(const cfd_airwake_spec *sp, const foam_opts *o, const char *tmp, const core_log *log)
{
    char dir[1200], p[1300];
    snprintf(dir, sizeof dir, "%s/case", tmp);
    CHECK(mkdir(dir, 0755) == 0);
    core_err err = {0};
    int rc = foam_case_write(sp, o, dir, &err);
    if (rc)
        fprintf(stderr, "foam_case_write: %s\n", err.msg);
    CHECK(rc == 0);
    cfd_solver *s = cfd_airwake_create(sp, log, NULL, NULL, &err);
    snprintf(p, sizeof p, "%s/system/blockMeshDict", dir);
    FILE *f = fopen(p, "r");
    CHECK(f != NULL && s != NULL);
    if (!f || !s) {
        if (f)
            fclose(f);
        cfd_solver_destroy(s);
        return;
    }
    static char text[1 << 16];
    size_t n = fread(text, 1, sizeof text - 1, f);
    fclose(f);
    text[n] = '\0';
    const char *q = strstr(text, "simpleGrading");
    CHECK(q != NULL);
    double worst = 0.0;
    q = q ? strchr(q, '(') : NULL; /* the three axes' list */
    for (int d = 0; q && d < 3; d++) {
        q = strchr(q + 1, '('); /* the axis's list */
        const double *xn = cfd_grid_nodes(cfd_solver_grid(s), d);
        int dims[3];
        cfd_grid_dims(cfd_solver_grid(s), dims);
        double x = xn[0];
        int cell = 0;
        const char *r = q ? q + 1 : NULL;
        double len, e;
        int cnt, used;
        while (r && sscanf(r, " ( %lf %d %lf )%n", &len, &cnt, &e, &used) == 3) {
            double ratio = cnt > 1 ? pow(e, 1.0 / (cnt - 1)) : 1.0, sum = 0.0;
            for (int i = 0; i < cnt; i++)
                sum += pow(ratio, i);
            for (int i = 0; i < cnt && cell < dims[d]; i++) {
                x += len * pow(ratio, i) / sum;
                cell++;
                worst = fmax(worst, fabs(x - xn[cell]) / (xn[cell] - xn[cell - 1]));
            }
            r += used;
        }
        CHECK(cell == dims[d]);
        q = r;
    }
    printf("blockMesh grading against disim's nodes: largest difference %.2e of a cell\n", worst);
    CHECK(worst < 1e-6);
    cfd_solver_destroy(s);
    static const char *const files[] = {"system/blockMeshDict", "system/topoSetDict", "system/controlDict",
                                        "system/fvSchemes", "system/fvSolution", "system/decomposeParDict",
                                        "constant/transportProperties", "constant/turbulenceProperties",
                                        "0/U", "0/p", "0/k", "0/epsilon", "0/nut"};
    for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) {
        snprintf(p, sizeof p, "%s/%s", dir, files[i]);
        CHECK(access(p, R_OK) == 0);
        remove(p);
    }
    static const char *const sub[] = {"system", "constant", "0", ""};
    for (size_t i = 0; i < sizeof sub / sizeof sub[0]; i++) {
        snprintf(p, sizeof p, "%s/%s", dir, sub[i]);
        rmdir(p);
    }
}

/* test_foam_blade.c */
int test_foam_blade(void);
/* test_foam_inflow.c */
int test_foam_inflow(void);

int main(int argc, char **argv)
{
    if (argc > 1 && !strcmp(argv[1], "blade"))
        return test_foam_blade();
    if (argc > 1 && !strcmp(argv[1], "inflow"))
        return test_foam_inflow();
    int rotor = argc > 1 && !strcmp(argv[1], "rotor");
    foam_opts o;
    foam_opts_default(&o);
    o.np = 2;
    core_log log = {log_stderr, NULL, CORE_LOG_INFO};
    o.log = &log;
    o.keep_case = getenv("DISIM_FOAM_KEEP") != NULL;
    core_ship ship;
    core_err err = {0};
    if (core_ship_load("scenarios/ships/sfs2.ini", &ship, &err) != 0) {
        fprintf(stderr, "%s\n", err.msg);
        return 1;
    }
    cfd_airwake_spec sp;
    spec_sfs2(&sp, &ship, rotor);
    char tmp[] = "/tmp/test_foam_XXXXXX";
    CHECK(mkdtemp(tmp) != NULL);
    o.work_dir = tmp;
    check_grading(&sp, &o, tmp, &log);
    char why[256];
    if (!foam_available(&o, why, sizeof why)) {
        rmdir(tmp);
        check_skip(why);
        return check_done("test_foam");
    }
    if (!rotor)
        check_failing_step(&sp, &o, tmp);

    /* the embedded solver */
    double t0 = now_s();
    cfd_solver *s = cfd_airwake_create(&sp, &log, NULL, NULL, &err);
    CHECK(s != NULL);
    if (!s)
        return check_done("test_foam");
    cfd_result er;
    int rc = cfd_solver_run(s, &er, &err);
    double emb_s = now_s() - t0;
    CHECK(rc >= 0);

    /* the embedded solver with the other TVD limiter: its own
     * discretisation's reach on this grid */
    cfd_airwake_spec sm = sp;
    sm.limiter_fixed = 1;
    sm.limiter = CFD_LIMITER_MINMOD;
    cfd_solver *alt = cfd_airwake_create(&sm, &log, NULL, NULL, &err);
    cfd_result ar;
    CHECK(alt != NULL && cfd_solver_run(alt, &ar, &err) >= 0);

    /* OpenFOAM, 2 ranks */
    char out[1300];
    snprintf(out, sizeof out, "%s/foam.h5", tmp);
    cfd_meta meta;
    memset(&meta, 0, sizeof meta);
    snprintf(meta.ship, sizeof meta.ship, "%s", ship.name);
    snprintf(meta.rotor, sizeof meta.rotor, "%s", core_rotor_name(sp.rotor));
    snprintf(meta.grid, sizeof meta.grid, "h2.400 m");
    meta.wod_speed_mps = sp.wod_speed_mps;
    foam_result fr;
    rc = foam_airwake(&sp, &o, &meta, out, &fr, &err);
    if (rc != 0)
        fprintf(stderr, "foam_airwake: %s\n", err.msg);
    CHECK(rc == 0);
    cfd_field *f = rc == 0 ? cfd_field_load(out, &err) : NULL;
    CHECK(f != NULL);
    if (f) {
        const cfd_meta *m = cfd_field_meta(f);
        CHECK(!strcmp(m->engine, "openfoam"));
        CHECK(!strncmp(m->engine_version, "OpenFOAM v", 10));
        CHECK(m->result.iterations == fr.res.iterations && fr.res.iterations > 0);
        CHECK(fr.cells == cfd_grid_fluid_cells(cfd_solver_grid(s)));
        double at[3] = {0, 0, 0}, rms = 0.0, at2[3] = {0, 0, 0}, rms2 = 0.0;
        sampler se = {s, NULL}, sf = {NULL, f}, sm = {alt, NULL};
        double worst = deck_lines(&ship, &se, &sf, sp.wod_speed_mps, at, &rms, "openfoam - embedded");
        double self = alt ? deck_lines(&ship, &se, &sm, sp.wod_speed_mps, at2, &rms2, "embedded minmod - van Leer")
                          : NAN;
        printf("cells %zu (%zu fluid); embedded: %d iterations, %.1f s, %s, residual %.2e; "
               "openfoam %s: %d iterations, simpleFoam %.1f s, all steps %.1f s, %s, residuals p %.2e U %.2e k %.2e, "
               "monitor change %.3f\n",
               cfd_grid_cells(cfd_solver_grid(s)), fr.cells, er.iterations, emb_s,
               er.converged ? "converged" : "not converged", er.residual[0], fr.version, fr.res.iterations,
               fr.res.wall_s, fr.total_wall_s, fr.res.converged ? "converged" : "not converged", fr.res.residual[0],
               fr.res.residual[1], fr.res.residual[4], fr.res.monitor_change);
        printf("deck lines, openfoam - embedded: largest %.1f %% of U at (%.1f, %.1f, %.1f), RMS %.1f %%; "
               "the embedded solver's own minmod - van Leer: largest %.1f %% at (%.1f, %.1f, %.1f), RMS %.1f %%\n",
               100.0 * worst, at[0], at[1], at[2], 100.0 * rms, 100.0 * self, at2[0], at2[1], at2[2], 100.0 * rms2);
        double ff = far_field(&ship, &se, &sf, sp.wod_speed_mps);
        double hz = -2.28; /* 0.3 hangar heights above the deck, as the sfs2 validation case */
        double re = reattachment(&ship, &se, sp.wod_dir_rad, hz), ro = reattachment(&ship, &sf, sp.wod_dir_rad, hz);
        printf("away from the ship: largest difference %.2f %% of U; reattachment behind the hangar at %.2f m "
               "above the deck: embedded %.2f m, openfoam %.2f m aft of the hangar face (cells %.1f m)\n",
               100.0 * ff, -hz, re, ro, sp.h_fine_m);
        /* The engines agree where the flow is attached (the far field: the
         * same grid, boundaries, inflow and model); behind the hangar, 3
         * cells high on this grid, they put the reattachment low over the
         * deck at the same place (0.05 m apart) but resolve the separated
         * shear layer above it differently: the deck-line velocities differ
         * by up to 11.5 % of U (RMS 6.7 %), less than either engine's own
         * change from this grid to a 1.6 m one (25 %); the bounds below
         * hold that difference (docs/openfoam.md). */
        CHECK(ff <= 0.01);
        CHECK(re > 0.0 && ro > 0.0 && fabs(re - ro) <= 0.5 * sp.h_fine_m);
        CHECK(worst <= 0.15);
        CHECK(rms <= 0.08);
        cfd_field_destroy(f);
    }
    cfd_solver_destroy(s);
    cfd_solver_destroy(alt);
    if (!o.keep_case) {
        char p[1400];
        snprintf(p, sizeof p, "%s/foam.h5", tmp);
        remove(p);
        snprintf(p, sizeof p, "%s/foam.xmf", tmp);
        remove(p);
        snprintf(p, sizeof p, "%s/bin/simpleFoam", tmp);
        remove(p);
        snprintf(p, sizeof p, "%s/bin", tmp);
        rmdir(p);
        rmdir(tmp);
    }
    return check_done("test_foam");
}
