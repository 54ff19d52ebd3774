/* test_cfd_core.c -- grid stretching, ship blocking, WOD boundary faces,
 * actuator-disk exactness and load shares, HDF5 round trip and trilinear
 * sampling, NaN refusal, damaged field files, divergence detection,
 * iteration averaging and the steady-mean stop, Anderson acceleration,
 * sampled inflow, the deck zone, the mirror image, the monitors-only stop
 * (monitor_stop) and the deck-line comparison. */
#include "cfd.h"
#include "check.h"

#include <dirent.h>
#include <hdf5.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static void test_axis(void)
{
    core_err err;
    cfd_axis_spec a = {-100.0, 50.0, -10.0, 10.0, 0.5, 5.0, 1.1};
    double *x;
    int n;
    CHECK(cfd_axis_build(&a, &x, &n, &err) == 0);
    CHECK_NEAR(x[0], -100.0, 1e-9);
    CHECK_NEAR(x[n], 50.0, 1e-9);
    int mono = 1, fine = 0;
    double hmax = 0.0, ratio = 1.0;
    for (int i = 0; i < n; i++) {
        double h = x[i + 1] - x[i];
        mono &= h > 0.0;
        if (x[i] >= -10.0 - 1e-9 && x[i + 1] <= 10.0 + 1e-9) {
            fine++;
            CHECK_NEAR(h, 0.5, 1e-9);
        }
        if (h > hmax)
            hmax = h;
        if (i > 0)
            ratio = fmax(ratio, fmax(h / (x[i] - x[i - 1]), (x[i] - x[i - 1]) / h));
    }
    CHECK(mono);
    CHECK(fine == 40);
    CHECK(hmax <= 5.0 * 1.2); /* scaled to fit the end */
    CHECK(ratio < 1.25);
    free(x);
    cfd_axis_spec bad = {1.0, 0.0, 0.0, 0.0, 0.1, 1.0, 1.1};
    CHECK(cfd_axis_build(&bad, &x, &n, &err) < 0);
    CHECK(strstr(err.msg, "lo < hi") != NULL);
}

static void test_ship_and_wod(void)
{
    core_ship ship;
    core_err err;
    CHECK(core_ship_load("scenarios/ships/sfs2.ini", &ship, &err) == 0);
    struct {
        double dir_deg;
        int xmin, xmax, ymin, ymax;
    } cases[] = {
        {0.0, CFD_BC_OUTLET, CFD_BC_INLET, CFD_BC_SYMMETRY, CFD_BC_SYMMETRY},
        {-30.0, CFD_BC_OUTLET, CFD_BC_INLET, CFD_BC_INLET, CFD_BC_OUTLET},
        {30.0, CFD_BC_OUTLET, CFD_BC_INLET, CFD_BC_OUTLET, CFD_BC_INLET},
        {90.0, CFD_BC_SYMMETRY, CFD_BC_SYMMETRY, CFD_BC_OUTLET, CFD_BC_INLET},
        {180.0, CFD_BC_INLET, CFD_BC_OUTLET, CFD_BC_SYMMETRY, CFD_BC_SYMMETRY},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        cfd_airwake_spec sp;
        memset(&sp, 0, sizeof sp);
        sp.ship = &ship;
        sp.wod_speed_mps = 10.0;
        sp.wod_dir_rad = cases[i].dir_deg * CORE_DEG_TO_RAD;
        sp.level = CORE_GRID_COARSE;
        sp.h_fine_m = 4.0;
        sp.monitor_z_m = -6.8;
        cfd_solver *s = cfd_airwake_create(&sp, NULL, NULL, NULL, &err);
        CHECK(s != NULL);
        if (!s)
            continue;
        const cfd_config *c = cfd_solver_config(s);
        CHECK(c->bc[CFD_XMIN].type == (cfd_bc_type)cases[i].xmin);
        CHECK(c->bc[CFD_XMAX].type == (cfd_bc_type)cases[i].xmax);
        CHECK(c->bc[CFD_YMIN].type == (cfd_bc_type)cases[i].ymin);
        CHECK(c->bc[CFD_YMAX].type == (cfd_bc_type)cases[i].ymax);
        CHECK(c->bc[CFD_ZMAX].type == CFD_BC_WALL);
        /* the ship is blocked: cells inside the hangar are solid, above are not */
        const cfd_grid *g = cfd_solver_grid(s);
        size_t nsolid = cfd_grid_cells(g) - cfd_grid_fluid_cells(g);
        CHECK(nsolid > 100);
        double in[CFD_NVARS];
        double p_in[3] = {30.0, 0.0, -3.0}, p_out[3] = {0.0, 0.0, -3.0};
        cfd_solver_sample(s, p_out, in);
        CHECK_NEAR(in[0], 10.0 * -cos(sp.wod_dir_rad), 1e-9); /* initial state: the inflow */
        int n[3];
        cfd_grid_dims(g, n);
        const double *xc = cfd_grid_centres(g, 0), *yc = cfd_grid_centres(g, 1), *zc = cfd_grid_centres(g, 2);
        const unsigned char *solid = cfd_grid_solid(g);
        int ok_in = 0, ok_out = 1;
        for (int k = 0; k < n[2]; k++)
            for (int j = 0; j < n[1]; j++)
                for (int ii = 0; ii < n[0]; ii++) {
                    core_vec3 p = core_vec3_make(xc[ii], yc[j], zc[k]);
                    int sol = solid[ii + (size_t)n[0] * (j + (size_t)n[1] * k)];
                    if (sol != core_ship_contains(&ship, p))
                        ok_out = 0;
                    if (fabs(xc[ii] - p_in[0]) < 3 && fabs(yc[j]) < 3 && fabs(zc[k] - p_in[2]) < 3 && sol)
                        ok_in = 1;
                }
        CHECK(ok_in);
        CHECK(ok_out);
        /* The isolated-rotor case: the same grid, nothing blocked. */
        sp.open_ship = 1;
        cfd_solver *so = cfd_airwake_create(&sp, NULL, NULL, NULL, &err);
        CHECK(so != NULL);
        if (so) {
            const cfd_grid *go = cfd_solver_grid(so);
            int no[3];
            cfd_grid_dims(go, no);
            CHECK(no[0] == n[0] && no[1] == n[1] && no[2] == n[2]);
            CHECK(cfd_grid_fluid_cells(go) == cfd_grid_cells(go));
            cfd_solver_destroy(so);
        }
        cfd_solver_destroy(s);
    }
    /* Calm air (WOD 0): refused without a rotor; with one, every face but
     * the sea is open, the reference speed is the hover induced velocity
     * sqrt(T / (2 rho A)) and the domain leaves 4 R above the hub. */
    {
        cfd_airwake_spec sp;
        memset(&sp, 0, sizeof sp);
        sp.ship = &ship;
        sp.level = CORE_GRID_COARSE;
        sp.h_fine_m = 4.0;
        sp.monitor_z_m = -6.8;
        CHECK(cfd_airwake_create(&sp, NULL, NULL, NULL, &err) == NULL);
        CHECK(strstr(err.msg, "WOD speed") != NULL);
        sp.rotor = CORE_ROTOR_UNIFORM;
        double c[3] = {0.0, 0.0, -8.0};
        core_euler att = {0.0, 0.0, 0.0};
        cfd_disk_from_attitude(&sp.disk, c, att, 8.18, 72950.0);
        cfd_solver *s = cfd_airwake_create(&sp, NULL, NULL, NULL, &err);
        CHECK(s != NULL);
        if (s) {
            const cfd_config *cf = cfd_solver_config(s);
            for (int f = 0; f < CFD_NFACES; f++)
                CHECK(cf->bc[f].type == (f == CFD_ZMAX ? CFD_BC_WALL : CFD_BC_OUTLET));
            CHECK_NEAR(cf->u_ref_mps, sqrt(72950.0 / (2.0 * CORE_RHO_SL_KGPM3 * M_PI * 8.18 * 8.18)), 1e-9);
            CHECK(cfd_grid_nodes(cfd_solver_grid(s), 2)[0] <= c[2] - 4.0 * 8.18 + 1e-9);
            cfd_solver_destroy(s);
        }
        sp.disk.thrust_N = 0.0;
        CHECK(cfd_airwake_create(&sp, NULL, NULL, NULL, &err) == NULL);
    }
}

static void disk_totals(const cfd_solver *s, const cfd_disk *d, double F[3], double *torque)
{
    const cfd_grid *g = cfd_solver_grid(s);
    int n[3];
    cfd_grid_dims(g, n);
    const double *f[3] = {cfd_solver_disk_force(s, 0), cfd_solver_disk_force(s, 1), cfd_solver_disk_force(s, 2)};
    const double *xc[3] = {cfd_grid_centres(g, 0), cfd_grid_centres(g, 1), cfd_grid_centres(g, 2)};
    F[0] = F[1] = F[2] = 0.0;
    *torque = 0.0;
    core_vec3 nrm = core_vec3_make(d->normal[0], d->normal[1], d->normal[2]);
    for (int k = 0; k < n[2]; k++)
        for (int j = 0; j < n[1]; j++)
            for (int i = 0; i < n[0]; i++) {
                size_t c = i + (size_t)n[0] * (j + (size_t)n[1] * k);
                core_vec3 fc = core_vec3_make(f[0][c], f[1][c], f[2][c]);
                F[0] += fc.x, F[1] += fc.y, F[2] += fc.z;
                core_vec3 r = core_vec3_make(xc[0][i] - d->centre_m[0], xc[1][j] - d->centre_m[1], xc[2][k] - d->centre_m[2]);
                /* moment about the axis, positive counter-clockwise seen from the thrust side */
                *torque += core_vec3_dot(core_vec3_cross(r, fc), nrm);
            }
}

/* The share of a disk's thrust on the cells whose centres lie within
 * frac R of its axis (in-plane distance). */
static double disk_inner_share(const cfd_solver *s, const cfd_disk *d, double frac)
{
    const cfd_grid *g = cfd_solver_grid(s);
    int n[3];
    cfd_grid_dims(g, n);
    const double *f[3] = {cfd_solver_disk_force(s, 0), cfd_solver_disk_force(s, 1), cfd_solver_disk_force(s, 2)};
    const double *xc[3] = {cfd_grid_centres(g, 0), cfd_grid_centres(g, 1), cfd_grid_centres(g, 2)};
    core_vec3 nrm = core_vec3_make(d->normal[0], d->normal[1], d->normal[2]);
    double in = 0.0, all = 0.0;
    for (int k = 0; k < n[2]; k++)
        for (int j = 0; j < n[1]; j++)
            for (int i = 0; i < n[0]; i++) {
                size_t c = i + (size_t)n[0] * (j + (size_t)n[1] * k);
                double fn = -(f[0][c] * nrm.x + f[1][c] * nrm.y + f[2][c] * nrm.z);
                core_vec3 r = core_vec3_make(xc[0][i] - d->centre_m[0], xc[1][j] - d->centre_m[1], xc[2][k] - d->centre_m[2]);
                double a = core_vec3_dot(r, nrm);
                double rr = sqrt(fmax(0.0, core_vec3_dot(r, r) - a * a));
                all += fn;
                if (rr < frac * d->radius_m)
                    in += fn;
            }
    return in / all;
}

static void test_disk(void)
{
    core_err err;
    cfd_axis_spec ax[3] = {{-6, 6, -1.5, 1.5, 0.2, 0.8, 1.15}, {-6, 6, -1.5, 1.5, 0.25, 0.8, 1.15}, {-5, 7, -0.7, 0.7, 0.15, 0.8, 1.15}};
    cfd_grid *g = cfd_grid_create_spec(ax, &err);
    CHECK(g != NULL);
    cfd_config cfg;
    cfd_config_default(&cfg);
    for (int f = 0; f < CFD_NFACES; f++)
        cfg.bc[f].type = CFD_BC_OUTLET;
    cfd_solver *s = cfd_solver_create(g, &cfg, &err);
    CHECK(s != NULL);
    if (!s)
        return;
    /* uniform disk, tilted 10 deg nose down and 5 deg right */
    cfd_disk d;
    double c[3] = {0.3, -0.2, 0.1};
    core_euler att = {5.0 * CORE_DEG_TO_RAD, -10.0 * CORE_DEG_TO_RAD, 0.0};
    cfd_disk_from_attitude(&d, c, att, 1.2, 1000.0);
    CHECK(cfd_solver_set_disk(s, &d, &err) == 0);
    double F[3], Q;
    disk_totals(s, &d, F, &Q);
    for (int q = 0; q < 3; q++)
        CHECK_NEAR(F[q], -1000.0 * d.normal[q], 1e-9 * 1000.0);
    CHECK_NEAR(Q, 0.0, 1e-6 * 1000.0);
    /* the pressure jump is uniform: the force inside r < R/2 is a quarter
     * (of the area); the cells' centres resolve the circle to 1 % */
    double share_u = disk_inner_share(s, &d, 0.5);
    CHECK_NEAR(share_u, 0.25, 0.01);
    /* loaded disk: thrust growing with radius, swirl torque 300 N m */
    cfd_disk L = d;
    L.nr = 10;
    L.npsi = 4;
    for (int ip = 0; ip < 4; ip++)
        for (int ir = 0; ir < 10; ir++)
            L.load[ip * 10 + ir] = (ir + 0.5) / 10.0 * (1.0 + 0.3 * (ip == 1));
    for (int ir = 0; ir < 10; ir++)
        L.swirl[ir] = 1.0;
    L.torque_Nm = 300.0;
    L.ccw_from_above = 1;
    CHECK(cfd_solver_set_disk(s, &L, &err) == 0);
    disk_totals(s, &L, F, &Q);
    double Fn = F[0] * L.normal[0] + F[1] * L.normal[1] + F[2] * L.normal[2];
    CHECK_NEAR(Fn, -1000.0, 1e-9 * 1000.0);
    /* a jump growing with r puts an eighth inside R/2, not a quarter */
    double share_l = disk_inner_share(s, &L, 0.5);
    CHECK_NEAR(share_l, 0.125, 0.03);
    CHECK_NEAR(Q, 300.0, 0.02 * 300.0); /* torque about the axis, cell-centre lever arms */
    L.ccw_from_above = 0;
    CHECK(cfd_solver_set_disk(s, &L, &err) == 0);
    disk_totals(s, &L, F, &Q);
    CHECK_NEAR(Q, -300.0, 0.02 * 300.0);
    /* a disk outside the grid is an error */
    cfd_disk far = d;
    far.centre_m[0] = 100.0;
    CHECK(cfd_solver_set_disk(s, &far, &err) < 0);
    CHECK(strstr(err.msg, "misses") != NULL);
    cfd_disk badr = d;
    badr.radius_m = -1.0;
    CHECK(cfd_solver_set_disk(s, &badr, &err) < 0);
    cfd_solver_destroy(s);
}

/* The short channel of the averaging tests: 4 m x 1 m x 1 m, 1 m/s in
 * at x = 0, out at x = 4 m, RNG k-epsilon, nu 1e-3. */
static void channel_config(cfd_config *cfg)
{
    cfd_config_default(cfg);
    cfg->turbulence = 1;
    cfg->nu_m2ps = 1e-3;
    cfg->bc[CFD_XMIN].type = CFD_BC_INLET;
    cfg->bc[CFD_XMAX].type = CFD_BC_OUTLET;
    cfg->inflow.vel_mps[0] = 1.0;
}

static cfd_solver *channel_create(const cfd_config *cfg)
{
    core_err err;
    cfd_axis_spec ax[3] = {{0, 4, 0, 4, 0.25, 0.25, 1.0}, {0, 1, 0, 1, 0.1, 0.1, 1.0}, {0, 1, 0, 1, 0.2, 0.2, 1.0}};
    cfd_grid *g = cfd_grid_create_spec(ax, &err);
    return g ? cfd_solver_create(g, cfg, &err) : NULL;
}

/* Create and run; NULL if the solver could not be made or diverged. */
static cfd_solver *channel_solve(const cfd_config *cfg, cfd_result *res)
{
    core_err err;
    cfd_solver *s = channel_create(cfg);
    if (s && cfd_solver_run(s, res, &err) < 0) {
        cfd_solver_destroy(s);
        return NULL;
    }
    return s;
}

/* A short channel run of n iterations, averaging its last w. */
static cfd_solver *channel_run(int n, int w, cfd_result *res)
{
    cfd_config cfg;
    channel_config(&cfg);
    cfg.max_iter = n;
    cfg.avg_window = w;
    return channel_solve(&cfg, res);
}

/* Metadata of a test field: rotor off, grid "test", result res (or none). */
static void test_meta(cfd_meta *meta, const char *ship, double speed_mps, double dir_deg, const cfd_result *res)
{
    memset(meta, 0, sizeof *meta);
    meta->wod_speed_mps = speed_mps;
    meta->wod_dir_deg = dir_deg;
    snprintf(meta->ship, sizeof meta->ship, "%s", ship);
    snprintf(meta->rotor, sizeof meta->rotor, "off");
    snprintf(meta->grid, sizeof meta->grid, "test");
    if (res)
        meta->result = *res;
}

/* A byte of the file at path at offset set to v (SEEK_END when offset < 0). */
static void poke(const char *path, long offset, int v)
{
    FILE *fp = fopen(path, "r+b");
    CHECK(fp != NULL);
    if (!fp)
        return;
    CHECK(fseek(fp, offset, offset < 0 ? SEEK_END : SEEK_SET) == 0);
    CHECK(fputc(v, fp) == v);
    fclose(fp);
}

/* The file's seal (cfd_field_seal): its header, and every kind of damage
 * refused with the file's name before HDF5 reads it. f: a loaded field;
 * path: where to write it. */
static void test_seal(const cfd_field *f, const char *path)
{
    core_err err = {0};
    CHECK(cfd_field_write(f, path, &err) == 0);
    cfd_field *g = cfd_field_load(path, &err);
    CHECK(g && cfd_field_meta(g)->sealed == 1 && cfd_field_meta(g)->checksum == 1);
    cfd_field_destroy(g);
    struct stat st;
    CHECK(stat(path, &st) == 0);
    char head[64] = "";
    FILE *fp = fopen(path, "rb");
    CHECK(fp && fread(head, 1, sizeof head - 1, fp) == sizeof head - 1);
    if (fp)
        fclose(fp);
    char want[64];
    snprintf(want, sizeof want, "disim airwake field\nbytes %lld\ncrc64 ", (long long)st.st_size);
    CHECK(strncmp(head, want, strlen(want)) == 0);
    /* one byte of the data changed (bit rot, a stray write) */
    long mid = (long)st.st_size / 2;
    fp = fopen(path, "rb");
    int was = fp && fseek(fp, mid, SEEK_SET) == 0 ? fgetc(fp) : -1;
    if (fp)
        fclose(fp);
    poke(path, mid, was ^ 0x10);
    CHECK(cfd_field_load(path, &err) == NULL && strstr(err.msg, path) &&
          strstr(err.msg, "the file does not match its checksum (crc64 ") != NULL);
    poke(path, mid, was);
    g = cfd_field_load(path, &err);
    CHECK(g != NULL);
    cfd_field_destroy(g);
    /* cut short, or a byte appended */
    fp = fopen(path, "rb");
    int last = fp && fseek(fp, -1, SEEK_END) == 0 ? fgetc(fp) : -1;
    if (fp)
        fclose(fp);
    CHECK(truncate(path, st.st_size - 1) == 0);
    CHECK(cfd_field_load(path, &err) == NULL && strstr(err.msg, "cut short or written past its end") != NULL);
    CHECK(truncate(path, st.st_size + 1) == 0);
    CHECK(cfd_field_load(path, &err) == NULL && strstr(err.msg, "its header says") != NULL);
    CHECK(truncate(path, st.st_size) == 0);
    poke(path, -1, last); /* the byte cut, back */
    CHECK((g = cfd_field_load(path, &err)) != NULL);
    cfd_field_destroy(g);
    /* the header itself damaged: its size line, its first byte */
    poke(path, 20, 'X');
    CHECK(cfd_field_load(path, &err) == NULL && strstr(err.msg, "a damaged field header") != NULL);
    poke(path, 20, 'b');
    poke(path, 0, 'D');
    CHECK(cfd_field_load(path, &err) == NULL && strstr(err.msg, "not an HDF5 file") != NULL);
    poke(path, 0, 'd');
    CHECK((g = cfd_field_load(path, &err)) != NULL);
    cfd_field_destroy(g);
    /* a file without the user block cannot be sealed */
    fp = fopen(path, "wb");
    CHECK(fp && fputs("\x89HDF\r\n\x1a\n not sealable", fp) >= 0);
    if (fp)
        fclose(fp);
    CHECK(cfd_field_seal(path, &err) < 0 && strstr(err.msg, "no HDF5 superblock after a user block of 512 bytes"));
}

static void test_io(void)
{
    core_err err;
    /* a short laminar channel run: a real field to write and read back */
    cfd_result res;
    cfd_solver *s = channel_run(30, 0, &res);
    CHECK(s != NULL);
    if (!s)
        return;
    CHECK(!cfd_solver_has_nan(s));
    char dir[] = "/tmp/disim_cfd_io_XXXXXX";
    CHECK(mkdtemp(dir) != NULL);
    char path[256], xmf[256];
    snprintf(path, sizeof path, "%s/f.h5", dir);
    snprintf(xmf, sizeof xmf, "%s/f.xmf", dir);
    cfd_meta meta;
    test_meta(&meta, "channel", 1.0, -30.0, &res);
    meta.rotor_centre_S_m[0] = 1.5, meta.rotor_centre_S_m[1] = -0.25, meta.rotor_centre_S_m[2] = -7.75;
    CHECK(res.mean_change == -1.0); /* not averaged */
    meta.result.mean_change = 0.0123;
    CHECK(cfd_solver_write(s, &meta, path, &err) == 0);
    CHECK(access(xmf, R_OK) == 0);
    cfd_field *f = cfd_field_load(path, &err);
    CHECK(f != NULL);
    if (f) {
        CHECK_NEAR(cfd_field_meta(f)->wod_dir_deg, -30.0, 1e-12);
        for (int q = 0; q < 3; q++) /* read back (it was written only) */
            CHECK(cfd_field_meta(f)->rotor_centre_S_m[q] == meta.rotor_centre_S_m[q]);
        CHECK(strcmp(cfd_field_meta(f)->ship, "channel") == 0);
        CHECK(cfd_field_meta(f)->result.iterations == res.iterations);
        CHECK(cfd_field_meta(f)->result.mean_change == 0.0123);
        /* a field of an earlier solver, without the attribute: not known */
        hid_t h = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
        CHECK(h >= 0 && H5Adelete(h, "mean_change") >= 0);
        if (h >= 0)
            H5Fclose(h);
        /* changed in place through HDF5: refused until sealed again */
        CHECK(cfd_field_load(path, &err) == NULL && strstr(err.msg, "does not match its checksum") != NULL);
        CHECK(cfd_field_seal(path, &err) == 0);
        cfd_field *old = cfd_field_load(path, &err);
        CHECK(old != NULL && cfd_field_meta(old)->result.mean_change == -1.0);
        cfd_field_destroy(old);
        /* The file carries its data's checksum: /fields/u overwritten with
         * finite garbage is refused naming the file; a field written
         * before files carried one is read, its meta.checksum 0. */
        CHECK(cfd_field_meta(f)->checksum == 1);
        char cpath[300], cxmf[300];
        snprintf(cpath, sizeof cpath, "%s/crc.h5", dir);
        snprintf(cxmf, sizeof cxmf, "%s/crc.xmf", dir);
        CHECK(cfd_field_write(f, cpath, &err) == 0);
        hid_t hc = H5Fopen(cpath, H5F_ACC_RDWR, H5P_DEFAULT);
        hid_t du = hc >= 0 ? H5Dopen2(hc, "/fields/u", H5P_DEFAULT) : -1;
        hid_t sp = du >= 0 ? H5Dget_space(du) : -1;
        hssize_t np = sp >= 0 ? H5Sget_simple_extent_npoints(sp) : 0;
        double *u = np > 0 ? malloc((size_t)np * sizeof *u) : NULL;
        CHECK(u && H5Dread(du, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, u) >= 0);
        if (u) {
            u[np / 2] += 0.5; /* finite, plausible */
            CHECK(H5Dwrite(du, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, u) >= 0);
        }
        free(u);
        if (sp >= 0)
            H5Sclose(sp);
        if (du >= 0)
            H5Dclose(du);
        if (hc >= 0)
            H5Fclose(hc);
        CHECK(cfd_field_seal(cpath, &err) == 0);
        err.msg[0] = '\0';
        CHECK(cfd_field_load(cpath, &err) == NULL);
        CHECK(strstr(err.msg, "crc.h5: the data do not match the file's checksum (data_crc64 ") != NULL);
        hc = H5Fopen(cpath, H5F_ACC_RDWR, H5P_DEFAULT);
        CHECK(hc >= 0 && H5Adelete(hc, "data_crc64") >= 0);
        if (hc >= 0)
            H5Fclose(hc);
        CHECK(cfd_field_seal(cpath, &err) == 0);
        cfd_field *nocrc = cfd_field_load(cpath, &err);
        CHECK(nocrc != NULL && cfd_field_meta(nocrc)->checksum == 0);
        cfd_field_destroy(nocrc);
        test_seal(f, cpath);
        unlink(cpath);
        unlink(cxmf);
        /* what is not a regular file is refused before HDF5 opens it */
        CHECK(cfd_field_load(dir, &err) == NULL && strstr(err.msg, "a folder, expected a regular file"));
        CHECK(cfd_field_load("/dev/zero", &err) == NULL && strstr(err.msg, "a character device"));
        double pts[3][3] = {{0.3, 0.45, 0.5}, {2.1, 0.77, 0.33}, {3.9, 0.05, 0.9}};
        for (int p = 0; p < 3; p++) {
            double a[CFD_NVARS], b[CFD_NVARS], vel[3];
            cfd_solver_sample(s, pts[p], a);
            CHECK(cfd_field_sample(f, pts[p], b) == 0);
            for (int v = 0; v < CFD_NVARS; v++)
                CHECK_NEAR(a[v], b[v], 1e-12 * (1.0 + fabs(a[v])));
            CHECK(cfd_field_air(f, pts[p], 0.0, vel) == 0);
            CHECK_NEAR(vel[0], a[0], 1e-12);
        }
        double outside[3] = {10.0, 0.5, 0.5}, vel[3];
        CHECK(cfd_field_air(f, outside, 0.0, vel) == 1);
        /* warm start on a finer grid (coarse-to-fine): the interpolated
         * state matches the field at the new cell centres */
        cfd_axis_spec ax2[3] = {{0, 4, 0, 4, 0.125, 0.125, 1.0}, {0, 1, 0, 1, 0.05, 0.05, 1.0}, {0, 1, 0, 1, 0.1, 0.1, 1.0}};
        cfd_grid *g2 = cfd_grid_create_spec(ax2, &err);
        cfd_solver *s2 = cfd_solver_create(g2, cfd_solver_config(s), &err);
        CHECK(s2 != NULL);
        if (s2) {
            CHECK(cfd_solver_init_from_field(s2, f, &err) == 0);
            double q[3] = {1.3125, 0.525, 0.45}, a[CFD_NVARS], b[CFD_NVARS];
            cfd_solver_sample(s2, q, a);
            cfd_field_sample(f, q, b);
            for (int v = 0; v < 3; v++)
                CHECK_NEAR(a[v], b[v], 1e-9);
            /* the in-memory coarse-to-fine start gives the same state as
             * the one through the file */
            cfd_grid *g3 = cfd_grid_create_spec(ax2, &err);
            cfd_solver *s3 = cfd_solver_create(g3, cfd_solver_config(s), &err);
            CHECK(s3 != NULL);
            if (s3) {
                CHECK(cfd_solver_init_from_solver(s3, s, &err) == 0);
                double qs[3][3] = {{1.3125, 0.525, 0.45}, {0.0625, 0.025, 0.05}, {3.9, 0.975, 0.95}};
                for (int p = 0; p < 3; p++) {
                    double c2[CFD_NVARS], c3[CFD_NVARS];
                    cfd_solver_sample(s2, qs[p], c2);
                    cfd_solver_sample(s3, qs[p], c3);
                    for (int v = 0; v < CFD_NVARS; v++)
                        CHECK_NEAR(c3[v], c2[v], 1e-9 * (1.0 + fabs(c2[v])));
                }
                cfd_solver_destroy(s3);
            }
            cfd_result r2;
            CHECK(cfd_solver_run(s2, &r2, &err) >= 0);
            CHECK(!cfd_solver_has_nan(s2));
            /* trilinear: exact for a linear function; the grid centres are
             * uniform here, so interpolating between two centres is linear */
            const cfd_grid *gl = cfd_solver_grid(s2);
            int nl[3];
            cfd_grid_dims(gl, nl);
            const double *cx = cfd_grid_centres(gl, 0), *cy = cfd_grid_centres(gl, 1), *cz = cfd_grid_centres(gl, 2);
            double *ul = (double *)cfd_solver_var(s2, CFD_VAR_U);
            for (int k = 0; k < nl[2]; k++)
                for (int j = 0; j < nl[1]; j++)
                    for (int i = 0; i < nl[0]; i++)
                        ul[i + (size_t)nl[0] * (j + (size_t)nl[1] * k)] = 0.7 + 1.3 * cx[i] - 2.1 * cy[j] + 0.4 * cz[k];
            double ql[3][3] = {{1.2917, 0.4133, 0.6211}, {0.0801, 0.9601, 0.0733}, {3.8999, 0.0297, 0.9317}};
            for (int p = 0; p < 3; p++) {
                double o[CFD_NVARS];
                CHECK(cfd_solver_sample(s2, ql[p], o) == 0);
                CHECK_NEAR(o[0], 0.7 + 1.3 * ql[p][0] - 2.1 * ql[p][1] + 0.4 * ql[p][2], 1e-12);
            }
            cfd_solver_destroy(s2);
        }
        cfd_field_destroy(f);
    }
    /* A side file that cannot be replaced (here a folder in its place):
     * the error names it and no field is left without it being reported,
     * nor any temporary file (the field used to take its name first and
     * the error named only the .h5) */
    {
        char blk[256], bxmf[256], inner[300];
        snprintf(blk, sizeof blk, "%s/blocked.h5", dir);
        snprintf(bxmf, sizeof bxmf, "%s/blocked.xmf", dir);
        snprintf(inner, sizeof inner, "%s/keep", bxmf);
        CHECK(mkdir(bxmf, 0700) == 0);
        FILE *k = fopen(inner, "w");
        CHECK(k != NULL);
        if (k)
            fclose(k);
        CHECK(cfd_solver_write(s, &meta, blk, &err) < 0);
        CHECK(strstr(err.msg, "blocked.xmf") != NULL);
        CHECK(access(blk, F_OK) != 0);
        DIR *d = opendir(dir);
        CHECK(d != NULL);
        for (struct dirent *e; d && (e = readdir(d));)
            CHECK(strstr(e->d_name, ".tmp.") == NULL);
        if (d)
            closedir(d);
        unlink(inner);
        rmdir(bxmf);
    }
    /* a field with a NaN is never written */
    double *u = (double *)cfd_solver_var(s, CFD_VAR_U);
    u[5] = NAN;
    char bad[256];
    snprintf(bad, sizeof bad, "%s/bad.h5", dir);
    CHECK(cfd_solver_write(s, &meta, bad, &err) < 0);
    CHECK(access(bad, F_OK) != 0);
    CHECK(strstr(err.msg, "NaN") != NULL);
    /* loading garbage fails cleanly */
    CHECK(cfd_field_load(xmf, &err) == NULL);
    CHECK(cfd_field_load("/nonexistent/x.h5", &err) == NULL);
    unlink(path);
    unlink(xmf);
    rmdir(dir);
    cfd_solver_destroy(s);
}

/* ------------------------------------------------- damaged field files */
/* The ways a field file is damaged in test_io_bad. */
enum {
    BAD_NONE,
    BAD_TRANSPOSED,    /* /fields/u stored nx x ny x nz: same count, other order */
    BAD_SOLID_2D,      /* /grid/solid 2-D with the right count */
    BAD_ATTR_ARRAY,    /* wod_speed_mps an array of 4 */
    BAD_ATTR_MISSING,  /* wod_dir_deg absent */
    BAD_ATTR_HUGE,     /* iterations 1e300: no int */
    BAD_ATTR_STRINGS,  /* ship an array of 2 strings */
    BAD_NODE_INF,      /* the last x node infinite */
    BAD_NODES_FLAT,    /* two equal y nodes */
    BAD_NODES_HUGE,    /* 2^22 nodes declared per axis (never written): 2^66 cells */
    BAD_SOLID_FLOAT,   /* the solid mask stored as 8-byte floats: the fuzzer's find had a
                          damaged type of 2 GB a value, converted through a 2 GB buffer */
    BAD_NODES_LARGE,   /* 2^27 x nodes declared (never written), the file a few kB: the
                          fuzzer's find, which had the loader allocate 1 GB and more */
};

/* A small field file written with HDF5 directly, as cfd writes it (4 x 3 x 2
 * cells), damaged as `bad` says. 0 on success. */
static int write_raw_field(const char *path, int bad)
{
    enum { NX = 4, NY = 3, NZ = 2 };
    hid_t f = H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    if (f < 0)
        return -1;
    hid_t gg = H5Gcreate2(f, "grid", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    hid_t gf = H5Gcreate2(f, "fields", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    herr_t rc = 0;
    const char *nn[3] = {"x_nodes", "y_nodes", "z_nodes"};
    int n[3] = {NX, NY, NZ};
    for (int d = 0; d < 3; d++) {
        double x[NX + 1];
        for (int i = 0; i <= n[d]; i++)
            x[i] = i;
        if (bad == BAD_NODE_INF && d == 0)
            x[NX] = INFINITY;
        if (bad == BAD_NODES_FLAT && d == 1)
            x[2] = x[1];
        hsize_t dim = (hsize_t)n[d] + 1;
        hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
        if (bad == BAD_NODES_HUGE || (bad == BAD_NODES_LARGE && d == 0)) {
            /* chunked and never written: the file stays small */
            hsize_t chunk = 1024;
            dim = (hsize_t)1 << (bad == BAD_NODES_HUGE ? 22 : 27);
            H5Pset_chunk(dcpl, 1, &chunk);
        }
        hid_t sp = H5Screate_simple(1, &dim, NULL);
        hid_t ds = H5Dcreate2(gg, nn[d], H5T_NATIVE_DOUBLE, sp, H5P_DEFAULT, dcpl, H5P_DEFAULT);
        if (ds < 0 || (dim == (hsize_t)n[d] + 1 && H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, x) < 0))
            rc = -1;
        H5Dclose(ds);
        H5Sclose(sp);
        H5Pclose(dcpl);
    }
    hsize_t cells[3] = {NZ, NY, NX}, trans[3] = {NX, NY, NZ}, flat[2] = {NX * NY, NZ};
    unsigned char solid[NX * NY * NZ] = {0};
    hid_t sp = bad == BAD_SOLID_2D ? H5Screate_simple(2, flat, NULL) : H5Screate_simple(3, cells, NULL);
    hid_t ds = H5Dcreate2(gg, "solid", bad == BAD_SOLID_FLOAT ? H5T_NATIVE_DOUBLE : H5T_NATIVE_UCHAR, sp,
                          H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    rc |= H5Dwrite(ds, H5T_NATIVE_UCHAR, H5S_ALL, H5S_ALL, H5P_DEFAULT, solid);
    H5Dclose(ds);
    H5Sclose(sp);
    double val[NX * NY * NZ];
    for (int c = 0; c < NX * NY * NZ; c++)
        val[c] = 0.1 * c;
    for (int v = 0; v < CFD_NVARS; v++) {
        sp = H5Screate_simple(3, bad == BAD_TRANSPOSED && v == CFD_VAR_U ? trans : cells, NULL);
        ds = H5Dcreate2(gf, cfd_var_names[v], H5T_NATIVE_DOUBLE, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
        rc |= H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, val);
        H5Dclose(ds);
        H5Sclose(sp);
    }
    const char *strs[3][2] = {{"ship", "box"}, {"rotor", "off"}, {"grid_level", "test"}};
    for (int q = 0; q < 3; q++) {
        hid_t t = H5Tcopy(H5T_C_S1);
        H5Tset_size(t, 8);
        hsize_t two = 2;
        char buf[16] = {0};
        snprintf(buf, 8, "%s", strs[q][1]);
        snprintf(buf + 8, 8, "%s", strs[q][1]);
        sp = bad == BAD_ATTR_STRINGS && q == 0 ? H5Screate_simple(1, &two, NULL) : H5Screate(H5S_SCALAR);
        hid_t a = H5Acreate2(f, strs[q][0], t, sp, H5P_DEFAULT, H5P_DEFAULT);
        rc |= H5Awrite(a, t, buf);
        H5Aclose(a);
        H5Sclose(sp);
        H5Tclose(t);
    }
    const char *nums[] = {"wod_speed_mps", "wod_dir_deg", "rotor_thrust_N", "rotor_radius_m", "iterations",
                          "converged"};
    for (size_t q = 0; q < sizeof nums / sizeof nums[0]; q++) {
        if (bad == BAD_ATTR_MISSING && !strcmp(nums[q], "wod_dir_deg"))
            continue;
        double x[4] = {q == 0 ? 10.0 : 0.0, 0.0, 0.0, 0.0};
        if (bad == BAD_ATTR_HUGE && !strcmp(nums[q], "iterations"))
            x[0] = 1e300;
        hsize_t four = 4;
        sp = bad == BAD_ATTR_ARRAY && q == 0 ? H5Screate_simple(1, &four, NULL) : H5Screate(H5S_SCALAR);
        hid_t a = H5Acreate2(f, nums[q], H5T_NATIVE_DOUBLE, sp, H5P_DEFAULT, H5P_DEFAULT);
        rc |= H5Awrite(a, H5T_NATIVE_DOUBLE, x);
        H5Aclose(a);
        H5Sclose(sp);
    }
    H5Gclose(gg);
    H5Gclose(gf);
    if (H5Fclose(f) < 0)
        rc = -1;
    return rc < 0 ? -1 : 0;
}

/* A damaged field file is refused with an error naming what is wrong, never
 * read out of its bounds or with its arrays in the wrong order. */
static void test_io_bad(void)
{
    core_err err = {0};
    const char *tmp = getenv("TMPDIR");
    char tmpl[256];
    snprintf(tmpl, sizeof tmpl, "%s/disim_cfd_bad_XXXXXX", tmp && *tmp ? tmp : "/tmp");
    char *d = mkdtemp(tmpl);
    CHECK(d != NULL);
    if (!d)
        return;
    char path[512];
    snprintf(path, sizeof path, "%s/f.h5", d);
    /* the writer here makes a field the loader takes: an unsealed one (no
     * user block, HDF5's signature at its start), as fields were written
     * before they were sealed */
    CHECK(write_raw_field(path, BAD_NONE) == 0);
    cfd_field *f = cfd_field_load(path, &err);
    CHECK(f != NULL && cfd_field_meta(f)->sealed == 0);
    if (!f)
        fprintf(stderr, "  %s\n", err.msg);
    if (f) {
        int n[3];
        cfd_field_dims(f, n);
        CHECK(n[0] == 4 && n[1] == 3 && n[2] == 2);
        CHECK(strcmp(cfd_field_meta(f)->ship, "box") == 0);
        CHECK_NEAR(cfd_field_meta(f)->wod_speed_mps, 10.0, 0.0);
        cfd_field_destroy(f);
    }
    struct {
        int bad;
        const char *needle;
    } cases[] = {
        {BAD_TRANSPOSED, "/fields/u has extent 4 x 3 x 2 (rank 3), expected 2 x 3 x 4"},
        {BAD_SOLID_2D, "/grid/solid has extent 12 x 2 (rank 2), expected 2 x 3 x 4"},
        {BAD_ATTR_ARRAY, "attribute wod_speed_mps: expected one number"},
        {BAD_ATTR_MISSING, "attribute wod_dir_deg missing"},
        {BAD_ATTR_HUGE, "attribute iterations out of range"},
        {BAD_ATTR_STRINGS, "attribute ship: expected one fixed-length string"},
        {BAD_NODE_INF, "/grid/x_nodes node 4 is inf: expected a finite coordinate"},
        {BAD_NODES_FLAT, "cfd grid: axis 1 nodes must increase (node 1: 1, 1)"},
        {BAD_NODES_HUGE, "/grid/x_nodes holds 0 bytes, its extent needs 33554432"},
        {BAD_SOLID_FLOAT, "/grid/solid is stored as floats of 8 bytes, expected integers of 1 bytes"},
        {BAD_NODES_LARGE, "/grid/x_nodes holds 0 bytes, its extent needs 1073741824"},
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        CHECK(write_raw_field(path, cases[c].bad) == 0);
        err.msg[0] = 0;
        f = cfd_field_load(path, &err);
        CHECK(f == NULL);
        cfd_field_destroy(f);
        CHECK(strstr(err.msg, path) != NULL && strstr(err.msg, cases[c].needle) != NULL);
        if (!strstr(err.msg, cases[c].needle))
            fprintf(stderr, "  case %zu: expected '%s' in: %s\n", c, cases[c].needle, err.msg);
    }
    /* a file cut short (a copy interrupted, a full disk) says so */
    CHECK(write_raw_field(path, BAD_NONE) == 0);
    FILE *fp = fopen(path, "r+b");
    CHECK(fp != NULL);
    if (fp) {
        fseek(fp, 0, SEEK_END);
        long len = ftell(fp);
        fclose(fp);
        CHECK(truncate(path, len / 2) == 0);
        f = cfd_field_load(path, &err);
        CHECK(f == NULL);
        cfd_field_destroy(f);
        CHECK(strstr(err.msg, "truncated or corrupt") != NULL);
        if (!strstr(err.msg, "truncated or corrupt"))
            fprintf(stderr, "  truncated: %s\n", err.msg);
    }
    unlink(path);
    rmdir(d);
}

/* Divergence: an absurd time scale (no under-relaxation, a huge body force
 * on a coarse grid) must end in a clear error after retries, not a NaN. */
static void test_divergence(void)
{
    core_err err;
    cfd_axis_spec ax[3] = {{-2, 2, 0, 0, 0.25, 0.25, 1.0}, {-2, 2, 0, 0, 0.25, 0.25, 1.0}, {-2, 2, 0, 0, 0.25, 0.25, 1.0}};
    cfd_grid *g = cfd_grid_create_spec(ax, &err);
    cfd_config cfg;
    cfd_config_default(&cfg);
    for (int f = 0; f < CFD_NFACES; f++)
        cfg.bc[f].type = CFD_BC_OUTLET;
    cfg.relax_u = cfg.relax_p = cfg.relax_turb = 1.0;
    cfg.second_order = 1;
    cfg.max_iter = 200;
    cfg.max_retries = 1;
    cfg.nu_m2ps = 1e-9;
    cfd_solver *s = cfd_solver_create(g, &cfg, &err);
    CHECK(s != NULL);
    if (!s)
        return;
    cfd_disk d;
    double c[3] = {0, 0, 0};
    core_euler att = {0, 0, 0};
    cfd_disk_from_attitude(&d, c, att, 1.0, 1e12);
    CHECK(cfd_solver_set_disk(s, &d, &err) == 0);
    cfd_result res;
    int rc = cfd_solver_run(s, &res, &err);
    CHECK(rc < 0);
    CHECK(res.retries == 1);
    CHECK(strstr(err.msg, "diverged") != NULL);
    CHECK(!cfd_solver_has_nan(s));
    cfd_solver_destroy(s);
}

/* A velocity component that is zero in the inflow and forced by a disk
 * (a rotor in a wind exactly from the beam): its scaled residual sum |r| /
 * sum |a_P u_P| is huge in the first iterations (the inflow's u is
 * round-off, so is the scale), on a healthy solution;
 * this is not divergence (CG-47 at WOD 90 deg with the rotor was refused
 * in two iterations while 89 deg ran). */
static void test_zero_component(void)
{
    core_err err;
    cfd_axis_spec ax[3] = {{-3, 3, 0, 0, 0.3, 0.3, 1.0}, {-4, 4, 0, 0, 0.3, 0.3, 1.0}, {-3, 3, 0, 0, 0.3, 0.3, 1.0}};
    cfd_grid *g = cfd_grid_create_spec(ax, &err);
    cfd_config cfg;
    cfd_config_default(&cfg);
    cfg.bc[CFD_XMIN].type = cfg.bc[CFD_XMAX].type = CFD_BC_SYMMETRY;
    cfg.bc[CFD_YMIN].type = CFD_BC_INLET;
    cfg.bc[CFD_YMAX].type = CFD_BC_OUTLET;
    cfg.bc[CFD_ZMIN].type = cfg.bc[CFD_ZMAX].type = CFD_BC_OUTLET;
    /* a wind from 90 deg as core_wod_vel_S_mps gives it: u = 5 cos(pi/2),
     * 3e-16 m/s, so the scale of the u residual is round-off */
    cfg.inflow.vel_mps[0] = 5.0 * cos(0.5 * CORE_PI);
    cfg.inflow.vel_mps[1] = 5.0;
    cfg.u_ref_mps = 5.0;
    cfg.max_iter = 40;
    cfg.max_retries = 0;
    cfd_solver *s = cfd_solver_create(g, &cfg, &err);
    CHECK(s != NULL);
    if (!s)
        return;
    cfd_disk d;
    double c[3] = {0, 0, 0};
    core_euler att = {0, -10.0 * CORE_DEG_TO_RAD, 0}; /* thrust tilted: an x component */
    cfd_disk_from_attitude(&d, c, att, 1.0, 200.0);
    CHECK(cfd_solver_set_disk(s, &d, &err) == 0);
    cfd_result res;
    int rc = cfd_solver_run(s, &res, &err);
    if (rc < 0)
        fprintf(stderr, "zero component: %s\n", err.msg);
    CHECK(rc >= 0 && res.retries == 0);
    CHECK(!cfd_solver_has_nan(s));
    cfd_solver_destroy(s);
}

/* Iteration averaging: a run that stops unconverged at max_iter returns the
 * mean of its last avg_window iterates (here: of iterations 19 and 20). */
static void test_averaging(void)
{
    cfd_result r19, r20, ra;
    cfd_solver *s19 = channel_run(19, 0, &r19), *s20 = channel_run(20, 0, &r20), *sa = channel_run(20, 2, &ra);
    CHECK(s19 && s20 && sa);
    if (s19 && s20 && sa) {
        CHECK(!r20.converged && r20.averaged == 0);
        CHECK(!ra.converged && ra.averaged == 2);
        double worst = 0.0, spread = 0.0;
        for (int v = 0; v < CFD_NVARS; v++) {
            const double *a = cfd_solver_var(s19, v), *b = cfd_solver_var(s20, v), *m = cfd_solver_var(sa, v);
            for (size_t c = 0; c < cfd_grid_cells(cfd_solver_grid(sa)); c++) {
                double ref = 0.5 * (a[c] + b[c]);
                worst = fmax(worst, fabs(m[c] - ref) / fmax(fabs(ref), 1e-12));
                spread = fmax(spread, fabs(a[c] - b[c]) / fmax(fabs(ref), 1e-12));
            }
        }
        printf("averaging: worst relative difference to the mean of iterations 19 and 20 %.2e "
               "(the two differ by %.2e)\n", worst, spread);
        CHECK(spread > 1e-6); /* the two iterates differ: the mean is not trivially either */
        CHECK(worst < 1e-9);
    }
    cfd_solver_destroy(s19);
    cfd_solver_destroy(s20);
    cfd_solver_destroy(sa);
}

/* avg_stop: the channel run below tol_residual 1e-30 never "converges"; its
 * residuals stall at round-off while its flow no longer changes, so the
 * means over the first two averaging windows after the stall agree and the
 * run stops at the second, windows laid back to back so the last ends at
 * max_iter.
 * With tol_monitor 0 no window passes and the run averages its last window
 * at max_iter as without avg_stop; a run that converges is left alone. */
static cfd_solver *channel_stop_run(int max_iter, double tol_res, double tol_mon, int avg, cfd_result *res)
{
    cfd_config cfg;
    channel_config(&cfg);
    cfg.max_iter = max_iter;
    cfg.tol_residual = tol_res;
    cfg.tol_monitor = tol_mon;
    cfg.avg_window = avg;
    cfg.avg_stop = 1;
    cfg.n_monitor = 1;
    cfg.monitor_m[0][0] = 3.0;
    cfg.monitor_m[0][1] = 0.5;
    cfg.monitor_m[0][2] = 0.5;
    return channel_solve(&cfg, res);
}

/* The monitor velocity of every iteration, recorded through the progress
 * callback: the tests below compute the solver's window figures from it. */
typedef struct {
    cfd_solver *s;
    double pos[3];
    double (*vel)[3];
    int n;
} window_probe;

static int window_progress(void *user, int iter, int max_iter, double residual, double elapsed_s)
{
    (void)max_iter;
    (void)residual;
    (void)elapsed_s;
    window_probe *p = user;
    if (iter >= 1 && iter <= p->n) {
        double out[CFD_NVARS];
        cfd_solver_sample(p->s, p->pos, out);
        memcpy(p->vel[iter - 1], out, sizeof p->vel[0]);
    }
    return 0;
}

/* mean_drift against the same quantity computed here from the iterates:
 * the monitor's mean velocity over iterations 41-50 against 51-60 of a
 * cold channel run still settling, averaged over 41-60. */
static void test_mean_drift(void)
{
    core_err err;
    cfd_config cfg;
    channel_config(&cfg);
    cfg.max_iter = 60;
    cfg.tol_residual = 1e-30;
    cfg.avg_window = 20;
    cfg.n_monitor = 1;
    double vel[60][3];
    window_probe p = {NULL, {3.0, 0.5, 0.5}, vel, 60};
    memcpy(cfg.monitor_m[0], p.pos, sizeof p.pos);
    cfg.progress = window_progress;
    cfg.progress_user = &p;
    cfd_solver *s = channel_create(&cfg);
    CHECK(s != NULL);
    if (!s)
        return;
    p.s = s;
    cfd_result r;
    CHECK(cfd_solver_run(s, &r, &err) == 1 && r.averaged == 20);
    double dmax = 0.0;
    for (int d = 0; d < 3; d++) {
        double sum[2] = {0.0, 0.0};
        for (int i = 40; i < 60; i++) /* iterations 41-50, 51-60 */
            sum[i >= 50] += vel[i][d];
        dmax = fmax(dmax, fabs(sum[0] - sum[1]) / 10.0);
    }
    printf("mean drift: %.6e of u_ref (from the iterates here: %.6e)\n", r.mean_drift, dmax);
    CHECK(dmax > 1e-6); /* the flow still moves: the figure is not trivially 0 */
    CHECK(fabs(r.mean_drift - dmax) <= 1e-9 * dmax);
    cfd_solver_destroy(s);
}

/* A steady mean is one whose window agrees with the window before it, not
 * only its two halves with each other: the monitor velocity of every
 * iteration recorded here, the mean of the stopped run's last window (the
 * field itself, sampled at the monitor) against the mean over the avg_window
 * iterations before it, within tol_monitor, and cfd_result.mean_change the
 * same figure. Before solver 0.5.0 the run stopped at the first window whose
 * halves agreed: here after 160 iterations, its mean 2.4 % of u_ref from the
 * window before. */
static void test_steady_mean_windows(void)
{
    core_err err;
    cfd_config cfg;
    channel_config(&cfg);
    cfg.max_iter = 2000;
    cfg.tol_residual = 1e-30;
    /* a slow pseudo-time step: the cold channel's centre-line velocity
     * still rises 1-2.5 % per 40 iterations when the first window opens
     * (after 120), its halves within 1.5 % while two windows are not */
    cfg.relax_u = 0.05;
    cfg.tol_monitor = 0.015;
    const int W = 40;
    cfg.avg_window = W;
    cfg.avg_stop = 1;
    cfg.n_monitor = 1;
    window_probe p = {NULL, {3.0, 0.5, 0.5}, calloc(2000, sizeof *p.vel), 2000};
    memcpy(cfg.monitor_m[0], p.pos, sizeof p.pos);
    cfg.progress = window_progress;
    cfg.progress_user = &p;
    cfd_solver *s = channel_create(&cfg);
    CHECK(s != NULL && p.vel != NULL);
    if (!s || !p.vel) {
        cfd_solver_destroy(s);
        free(p.vel);
        return;
    }
    p.s = s;
    cfd_result r;
    CHECK(cfd_solver_run(s, &r, &err) == 1 && r.steady_mean == 1 && r.averaged == W);
    const int n = r.iterations;
    CHECK(n > 2 * W);
    if (r.steady_mean && n > 2 * W) {
        double last[CFD_NVARS], prev[3] = {0, 0, 0}, d = 0.0;
        cfd_solver_sample(s, p.pos, last); /* the field is the last window's mean */
        for (int i = n - 2 * W; i < n - W; i++) /* iterations n-2W+1 .. n-W */
            for (int k = 0; k < 3; k++)
                prev[k] += p.vel[i][k] / W;
        for (int k = 0; k < 3; k++)
            d = fmax(d, fabs(last[k] - prev[k]));
        d /= cfg.u_ref_mps;
        printf("steady mean after %d iterations: the last window's mean %.3e of u_ref from the window "
               "before (solver: %.3e), halves %.3e\n",
               n, d, r.mean_change, r.mean_drift);
        CHECK(d < cfg.tol_monitor);
        CHECK(r.mean_change >= 0.0 && fabs(r.mean_change - d) <= 1e-9 + 1e-6 * d);
    }
    cfd_solver_destroy(s);
    free(p.vel);
}

static void test_steady_mean(void)
{
    cfd_result rs = {0}, rn = {0}, rc = {0}, rref = {0};
    cfd_solver *ss = channel_stop_run(2000, 1e-30, 0.02, 40, &rs);
    cfd_solver *sn = channel_stop_run(400, 1e-30, 0.0, 40, &rn);
    cfd_solver *sc = channel_stop_run(2000, 1e-4, 0.02, 40, &rc);
    cfd_solver *sref = channel_stop_run(rs.iterations > 0 ? rs.iterations : 1, 1e-30, 0.02, 0, &rref);
    CHECK(ss && sn && sc && sref);
    if (ss && sn && sc && sref) {
        printf("steady mean: stopped after %d of 2000 iterations (mean of %d, monitor halves differ by "
               "%.2e of u_ref); tol_monitor 0: %d iterations, mean of %d; converging run: %d iterations\n",
               rs.iterations, rs.averaged, rs.monitor_change, rn.iterations, rn.averaged, rc.iterations);
        CHECK(rs.steady_mean == 1 && !rs.converged && rs.averaged == 40);
        CHECK(rs.iterations < 2000 && (2000 - rs.iterations) % 40 == 0);
        CHECK(rs.iterations > 120); /* the stall test needs 120 iterations of history */
        CHECK(rn.steady_mean == 0 && rn.iterations == 400 && rn.averaged == 40);
        CHECK(rc.converged && rc.averaged == 0 && rc.steady_mean == 0);
        /* the steady mean is the flow: it matches the last iterate of a run
         * without averaging stopped at the same iteration to round-off */
        double worst = 0.0;
        const double *a = cfd_solver_var(ss, CFD_VAR_U), *b = cfd_solver_var(sref, CFD_VAR_U);
        for (size_t c = 0; c < cfd_grid_cells(cfd_solver_grid(ss)); c++)
            worst = fmax(worst, fabs(a[c] - b[c]));
        printf("steady mean: largest |u| difference to the last iterate of a plain run %.2e m/s\n", worst);
        CHECK(worst < 1e-6);
    }
    cfd_solver_destroy(ss);
    cfd_solver_destroy(sn);
    cfd_solver_destroy(sc);
    cfd_solver_destroy(sref);
}

/* A laminar lid-driven cavity (Re 1000, n x n, second order) run to a
 * residual of 1e-7, with Anderson acceleration of the given depth (0: off). */
static cfd_solver *cavity_run(int n, int depth, int when_stalled, cfd_result *res)
{
    core_err err;
    double xn[65], zn[2] = {0.0, 1.0 / n};
    for (int i = 0; i <= n; i++)
        xn[i] = (double)i / n;
    cfd_grid *g = cfd_grid_create(xn, n, xn, n, zn, 1, &err);
    cfd_config cfg;
    cfd_config_default(&cfg);
    cfg.turbulence = 0;
    cfg.nu_m2ps = 1e-3;
    cfg.rho_kgpm3 = 1.0;
    cfg.bc[CFD_ZMIN].type = cfg.bc[CFD_ZMAX].type = CFD_BC_SYMMETRY;
    cfg.bc[CFD_YMAX].vel_mps[0] = 1.0;
    cfg.max_iter = 5000;
    cfg.tol_residual = 1e-7;
    cfg.relax_u = 0.8;
    cfg.relax_p = 1.0;
    cfg.accel_depth = depth;
    cfg.accel_start = 20;
    cfg.accel_when_stalled = when_stalled;
    cfd_solver *s = cfd_solver_create(g, &cfg, &err);
    if (s && cfd_solver_run(s, res, &err) < 0) {
        cfd_solver_destroy(s);
        return NULL;
    }
    return s;
}

/* Anderson acceleration converges to the same fixed point as the plain
 * iteration (both to 1e-7), in fewer iterations; started only on a stall,
 * it leaves a converging run alone. */
static void test_anderson(void)
{
    cfd_result rp, ra;
    cfd_solver *sp = cavity_run(32, 0, 0, &rp), *sa = cavity_run(32, 5, 0, &ra);
    CHECK(sp && sa);
    if (sp && sa) {
        CHECK(rp.converged && ra.converged);
        double worst = 0.0;
        for (int v = CFD_VAR_U; v <= CFD_VAR_V; v++) {
            const double *a = cfd_solver_var(sp, v), *b = cfd_solver_var(sa, v);
            for (size_t c = 0; c < cfd_grid_cells(cfd_solver_grid(sa)); c++)
                worst = fmax(worst, fabs(a[c] - b[c]));
        }
        printf("anderson: cavity Re 1000 32 x 32 to 1e-7: %d iterations plain, %d with depth 5; "
               "largest velocity difference %.2e of the lid speed\n",
               rp.iterations, ra.iterations, worst);
        CHECK(ra.iterations < 0.8 * rp.iterations);
        CHECK(worst < 1e-4);
    }
    cfd_solver_destroy(sp);
    cfd_solver_destroy(sa);
    /* when_stalled: the cavity's residuals keep falling, so Anderson never
     * starts and the run is the plain one */
    cfd_result rs;
    cfd_solver *ss = cavity_run(32, 5, 1, &rs);
    CHECK(ss && rs.converged && rs.iterations == rp.iterations);
    cfd_solver_destroy(ss);
    /* a depth outside 1..16 is refused */
    core_err err;
    cfd_axis_spec ax[3] = {{0, 1, 0, 1, 0.25, 0.25, 1.0}, {0, 1, 0, 1, 0.25, 0.25, 1.0}, {0, 1, 0, 1, 0.25, 0.25, 1.0}};
    cfd_config cfg;
    cfd_config_default(&cfg);
    cfg.accel_depth = 17;
    CHECK(cfd_solver_create(cfd_grid_create_spec(ax, &err), &cfg, &err) == NULL);
    CHECK(strstr(err.msg, "accel_depth") != NULL);
}

/* A sampled inflow (CFD_INFLOW_FIELD) that returns the uniform inflow's
 * values gives the uniform inflow's solution (the stored face values are
 * the boundary the solver uses), and its initial state is the sampler's. */
static int uniform_sampler(void *user, const double pos[3], double out[5])
{
    (void)pos;
    const double *v = user; /* u, v, w, k, eps */
    memcpy(out, v, 5 * sizeof *out);
    return 0;
}

static int ramp_sampler(void *user, const double pos[3], double out[5])
{
    (void)user;
    out[0] = 0.0;
    out[1] = 5.0 + 0.1 * pos[2];
    out[2] = 0.0;
    out[3] = 0.01;
    out[4] = 0.001;
    return 0;
}

static cfd_solver *sampled_run(int sampled, double *vals, int (*fn)(void *, const double *, double *), int iters)
{
    core_err err;
    cfd_axis_spec ax[3] = {{-3, 3, 0, 0, 0.3, 0.3, 1.0}, {-4, 4, 0, 0, 0.3, 0.3, 1.0}, {-3, 3, 0, 0, 0.3, 0.3, 1.0}};
    cfd_grid *g = cfd_grid_create_spec(ax, &err);
    cfd_config cfg;
    cfd_config_default(&cfg);
    cfg.bc[CFD_XMIN].type = cfg.bc[CFD_XMAX].type = CFD_BC_INLET;
    cfg.bc[CFD_YMIN].type = CFD_BC_INLET;
    cfg.bc[CFD_YMAX].type = CFD_BC_OUTLET;
    cfg.bc[CFD_ZMIN].type = CFD_BC_INLET;
    cfg.bc[CFD_ZMAX].type = CFD_BC_WALL;
    cfg.inflow.vel_mps[1] = 5.0;
    cfg.u_ref_mps = 5.0;
    cfg.max_iter = iters > 0 ? iters : 1;
    cfg.max_retries = 0;
    if (sampled) {
        cfg.inflow.type = CFD_INFLOW_FIELD;
        cfg.inflow.fn = fn;
        cfg.inflow.fn_user = vals;
    }
    cfd_solver *s = cfd_solver_create(g, &cfg, &err);
    CHECK(s != NULL);
    if (!s)
        return NULL;
    cfd_disk d;
    double c[3] = {0, 0, 0};
    core_euler att = {0, -10.0 * CORE_DEG_TO_RAD, 0};
    cfd_disk_from_attitude(&d, c, att, 1.0, 200.0);
    CHECK(cfd_solver_set_disk(s, &d, &err) == 0);
    if (iters > 0) {
        cfd_result res;
        CHECK(cfd_solver_run(s, &res, &err) >= 0);
    }
    return s;
}

static void test_sampled_inflow(void)
{
    /* the uniform inflow's k and epsilon (cfd_config_default: intensity
     * 0.01, length 1 m; Cmu 0.0845) */
    double iu = 0.01 * 5.0, k = 1.5 * iu * iu, eps = pow(0.0845, 0.75) * pow(k, 1.5) / 1.0;
    double vals[5] = {0.0, 5.0, 0.0, k, eps};
    cfd_solver *a = sampled_run(0, NULL, NULL, 30), *b = sampled_run(1, vals, uniform_sampler, 30);
    if (a && b) {
        double maxd = 0.0, maxv = 0.0;
        for (int v = 0; v < CFD_NVARS; v++) {
            const double *x = cfd_solver_var(a, v), *y = cfd_solver_var(b, v);
            for (size_t c = 0; c < cfd_grid_cells(cfd_solver_grid(a)); c++) {
                maxd = fmax(maxd, fabs(x[c] - y[c]));
                maxv = fmax(maxv, fabs(x[c]));
            }
        }
        CHECK(maxv > 1.0);
        CHECK(maxd <= 1e-9 * maxv);
    }
    cfd_solver_destroy(a);
    cfd_solver_destroy(b);
    /* a sheared sampler: the initial state is the sampler at each cell */
    cfd_solver *r = sampled_run(1, NULL, ramp_sampler, 0);
    if (r) {
        double pos[3] = {0.15, -1.05, -2.85}, out[CFD_NVARS];
        cfd_solver_sample(r, pos, out);
        CHECK_NEAR(out[1], 5.0 + 0.1 * pos[2], 1e-12);
        CHECK_NEAR(out[CFD_VAR_K], 0.01, 1e-15);
    }
    cfd_solver_destroy(r);
    /* a sampled inflow without a sampler is refused */
    core_err err;
    cfd_axis_spec ax[3] = {{0, 1, 0, 0, 0.5, 0.5, 1.0}, {0, 1, 0, 0, 0.5, 0.5, 1.0}, {0, 1, 0, 0, 0.5, 0.5, 1.0}};
    cfd_config cfg;
    cfd_config_default(&cfg);
    cfg.u_ref_mps = 1.0;
    cfg.max_iter = 1;
    cfg.inflow.type = CFD_INFLOW_FIELD;
    CHECK(cfd_solver_create(cfd_grid_create_spec(ax, &err), &cfg, &err) == NULL);
    CHECK(strstr(err.msg, "sampler") != NULL);
}

/* The deck zone: a box 5 R round the hub and 4 R above it, the faces along
 * the wind and the top fixed, an initial state and boundary from the outer
 * field scaled to the speed (velocity x f, k x f^2, epsilon x f^3). */
static void test_zone(void)
{
    core_ship ship;
    core_err err;
    CHECK(core_ship_load("scenarios/ships/sfs2.ini", &ship, &err) == 0);
    cfd_airwake_spec sp;
    memset(&sp, 0, sizeof sp);
    sp.ship = &ship;
    sp.wod_speed_mps = 10.0;
    sp.wod_dir_rad = 0.0;
    sp.level = CORE_GRID_COARSE;
    sp.h_fine_m = 4.0;
    sp.monitor_z_m = -6.8;
    sp.max_iter = 20;
    /* the outer field: a short ship-only run on a coarse grid */
    cfd_solver *so = cfd_airwake_create(&sp, NULL, NULL, NULL, &err);
    CHECK(so != NULL);
    if (!so)
        return;
    cfd_result res;
    CHECK(cfd_solver_run(so, &res, &err) >= 0);
    char dir[] = "/tmp/disim_cfd_zone_XXXXXX";
    CHECK(mkdtemp(dir) != NULL);
    char path[256], xmf[256];
    snprintf(path, sizeof path, "%s/outer.h5", dir);
    snprintf(xmf, sizeof xmf, "%s/outer.xmf", dir);
    cfd_meta meta;
    test_meta(&meta, "SFS2", 10.0, 0.0, NULL);
    CHECK(cfd_solver_write(so, &meta, path, &err) == 0);
    cfd_solver_destroy(so);
    cfd_field *outer = cfd_field_load(path, &err);
    CHECK(outer != NULL);
    remove(path);
    remove(xmf);
    rmdir(dir);
    if (!outer)
        return;
    /* refused without a rotor */
    sp.zone = 1;
    sp.zone_field = outer;
    sp.zone_scale = 2.0;
    sp.wod_speed_mps = 20.0;
    CHECK(cfd_airwake_create(&sp, NULL, NULL, NULL, &err) == NULL);
    CHECK(strstr(err.msg, "deck zone") != NULL);
    sp.rotor = CORE_ROTOR_UNIFORM;
    const double R = 5.97, hub[3] = {0.0, 0.0, -8.0};
    core_euler att = {0.0, 0.0, 0.0};
    cfd_disk_from_attitude(&sp.disk, hub, att, R, 40000.0);
    cfd_solver *z = cfd_airwake_create(&sp, NULL, NULL, NULL, &err);
    CHECK(z != NULL);
    if (z) {
        const cfd_grid *g = cfd_solver_grid(z);
        int n[3];
        cfd_grid_dims(g, n);
        CHECK_NEAR(cfd_grid_nodes(g, 0)[0], hub[0] - 5.0 * R, 1e-9);
        CHECK_NEAR(cfd_grid_nodes(g, 0)[n[0]], hub[0] + 5.0 * R, 1e-9);
        CHECK_NEAR(cfd_grid_nodes(g, 1)[0], hub[1] - 5.0 * R, 1e-9);
        CHECK_NEAR(cfd_grid_nodes(g, 2)[0], hub[2] - 4.0 * R, 1e-9);
        CHECK_NEAR(cfd_grid_nodes(g, 2)[n[2]], ship.deck_height_m, 1e-9);
        const cfd_config *c = cfd_solver_config(z);
        /* head wind: enters at x max, leaves at x min; the sides along the
         * wind and the top are fixed to the outer field */
        CHECK(c->bc[CFD_XMAX].type == CFD_BC_INLET && c->bc[CFD_XMIN].type == CFD_BC_OUTLET);
        CHECK(c->bc[CFD_YMIN].type == CFD_BC_INLET && c->bc[CFD_YMAX].type == CFD_BC_INLET);
        CHECK(c->bc[CFD_ZMIN].type == CFD_BC_INLET && c->bc[CFD_ZMAX].type == CFD_BC_WALL);
        CHECK(c->inflow.type == CFD_INFLOW_FIELD);
        /* the initial state at a cell centre over the deck, aft of the hangar */
        const double *xc = cfd_grid_centres(g, 0), *yc = cfd_grid_centres(g, 1), *zc = cfd_grid_centres(g, 2);
        int i = 0, j = 0, k = 0;
        while (i < n[0] - 1 && xc[i] < 6.0)
            i++;
        while (j < n[1] - 1 && yc[j] < 2.0)
            j++;
        while (k < n[2] - 1 && zc[k] < -3.0)
            k++;
        double pos[3] = {xc[i], yc[j], zc[k]}, a[CFD_NVARS], b[CFD_NVARS];
        cfd_solver_sample(z, pos, a);
        cfd_field_sample(outer, pos, b);
        CHECK(fabs(b[0]) > 0.5);
        for (int d = 0; d < 3; d++)
            CHECK_NEAR(a[d], 2.0 * b[d], 1e-9);
        CHECK_NEAR(a[CFD_VAR_K], 4.0 * b[CFD_VAR_K], 1e-9 * (1.0 + b[CFD_VAR_K]));
        CHECK_NEAR(a[CFD_VAR_EPS], 8.0 * b[CFD_VAR_EPS], 1e-9 * (1.0 + b[CFD_VAR_EPS]));
        /* the inflow at a face of the top (an inlet): the outer field at
         * the face centre, scaled; none on the sea or off the side */
        double fp[3] = {xc[i], yc[j], cfd_grid_nodes(g, 2)[0]}, vel[3], ki, ei;
        CHECK(cfd_solver_inflow_at(z, CFD_ZMIN, fp, vel, &ki, &ei) == 0);
        cfd_field_sample(outer, fp, b);
        for (int d = 0; d < 3; d++)
            CHECK_NEAR(vel[d], 2.0 * b[d], 1e-9);
        CHECK_NEAR(ki, 4.0 * b[CFD_VAR_K], 1e-9 * (1.0 + b[CFD_VAR_K]));
        CHECK_NEAR(ei, 8.0 * b[CFD_VAR_EPS], 1e-9 * (1.0 + b[CFD_VAR_EPS]));
        CHECK(cfd_solver_inflow_at(z, CFD_ZMAX, fp, vel, &ki, &ei) == -1);
        fp[0] = 1e6;
        CHECK(cfd_solver_inflow_at(z, CFD_ZMIN, fp, vel, &ki, &ei) == -1);
        cfd_solver_destroy(z);
    }
    /* the isolated rotor's zone: the same grid and faces, the inflow profile */
    sp.open_ship = 1;
    sp.zone_field = NULL;
    cfd_solver *zi = cfd_airwake_create(&sp, NULL, NULL, NULL, &err);
    CHECK(zi != NULL);
    if (zi) {
        CHECK(cfd_solver_config(zi)->inflow.type != CFD_INFLOW_FIELD);
        CHECK(cfd_solver_config(zi)->bc[CFD_ZMIN].type == CFD_BC_INLET);
        CHECK(cfd_grid_fluid_cells(cfd_solver_grid(zi)) == cfd_grid_cells(cfd_solver_grid(zi)));
        cfd_solver_destroy(zi);
    }
    /* the zone's own ship-only field: no rotor, the box from the disk's
     * centre and radius */
    sp.rotor = CORE_ROTOR_OFF;
    cfd_solver *zs = cfd_airwake_create(&sp, NULL, NULL, NULL, &err);
    CHECK(zs != NULL);
    if (zs) {
        const cfd_grid *g = cfd_solver_grid(zs);
        CHECK_NEAR(cfd_grid_nodes(g, 0)[0], hub[0] - 5.0 * R, 1e-9);
        CHECK(cfd_solver_disk_force(zs, 0) == NULL);
        cfd_solver_destroy(zs);
    }
    sp.rotor = CORE_ROTOR_UNIFORM;
    /* no zone in calm air */
    sp.open_ship = 0;
    sp.zone_field = outer;
    sp.wod_speed_mps = 0.0;
    CHECK(cfd_airwake_create(&sp, NULL, NULL, NULL, &err) == NULL);
    cfd_field_destroy(outer);
}


/* The mirror image of a ship-only field (cfd_field_mirror_y) against the
 * field solved for the mirrored wind: SFS2 (symmetric about its centre
 * line) at 10 m/s from red 30 and green 30 on a 4 m grid, each run to the
 * solver's tolerance. The image's grid and blocked cells must be the other
 * run's exactly (the grid builder is mirror-exact), its velocities within
 * 0.1 % of the wind in every fluid cell (measured 1.0e-5: each run stops at
 * the tolerance; stopped unconverged after 40 iterations they differ by
 * 4.3e-3, so the iteration itself is mirror-symmetric only to round-off in
 * its order of operations, and an unconverged field's image is as good as
 * a second unconverged run, not identical to it). */
static cfd_solver *sfs2_run(const core_ship *ship, double dir_deg, cfd_result *res)
{
    core_err err;
    cfd_airwake_spec sp;
    memset(&sp, 0, sizeof sp);
    sp.ship = ship;
    sp.wod_speed_mps = 10.0;
    sp.wod_dir_rad = dir_deg * CORE_DEG_TO_RAD;
    sp.level = CORE_GRID_COARSE;
    sp.h_fine_m = 4.0;
    sp.monitor_z_m = -6.8;
    sp.max_iter = 1500;
    cfd_solver *s = cfd_airwake_create(&sp, NULL, NULL, NULL, &err);
    if (!s)
        return NULL;
    if (cfd_solver_run(s, res, &err) < 0) {
        cfd_solver_destroy(s);
        return NULL;
    }
    return s;
}

static void test_mirror(void)
{
    core_ship ship;
    core_err err;
    CHECK(core_ship_load("scenarios/ships/sfs2.ini", &ship, &err) == 0);
    cfd_result rr, rg;
    cfd_solver *red = sfs2_run(&ship, -30.0, &rr), *green = sfs2_run(&ship, 30.0, &rg);
    CHECK(red && green);
    if (!red || !green) {
        cfd_solver_destroy(red);
        cfd_solver_destroy(green);
        return;
    }
    printf("mirror: red 30 %d iterations (converged %d), green 30 %d (converged %d)\n", rr.iterations, rr.converged,
           rg.iterations, rg.converged);
    CHECK(rr.converged && rg.converged);
    char dir[] = "/tmp/disim_cfd_mirror_XXXXXX";
    CHECK(mkdtemp(dir) != NULL);
    char path[256], mpath[256];
    snprintf(path, sizeof path, "%s/red30.h5", dir);
    snprintf(mpath, sizeof mpath, "%s/green30.h5", dir);
    cfd_meta meta;
    test_meta(&meta, "SFS2", 10.0, -30.0, &rr);
    CHECK(cfd_solver_write(red, &meta, path, &err) == 0);
    cfd_field *f = cfd_field_load(path, &err);
    CHECK(f != NULL);
    cfd_field *m = f ? cfd_field_mirror_y(f, &err) : NULL;
    CHECK(m != NULL);
    /* written and read back: the image says what it is */
    CHECK(m && cfd_field_write(m, mpath, &err) == 0);
    cfd_field_destroy(m);
    m = cfd_field_load(mpath, &err);
    CHECK(m != NULL);
    if (m) {
        const cfd_meta *mm = cfd_field_meta(m);
        CHECK(mm->mirrored == 1 && cfd_field_meta(f)->mirrored == 0);
        CHECK_NEAR(mm->wod_dir_deg, 30.0, 1e-12);
        CHECK(mm->result.iterations == rr.iterations);
        const cfd_grid *g = cfd_solver_grid(green);
        int n[3], nm[3];
        cfd_grid_dims(g, n);
        cfd_field_dims(m, nm);
        CHECK(n[0] == nm[0] && n[1] == nm[1] && n[2] == nm[2]);
        if (n[0] == nm[0] && n[1] == nm[1] && n[2] == nm[2]) {
            /* the nodes, by sampling the image at the green grid's centres:
             * equal grids give the cell values themselves */
            const double *xc = cfd_grid_centres(g, 0), *yc = cfd_grid_centres(g, 1), *zc = cfd_grid_centres(g, 2);
            const unsigned char *solid = cfd_grid_solid(g);
            const double *ug[3] = {cfd_solver_var(green, 0), cfd_solver_var(green, 1), cfd_solver_var(green, 2)};
            double worst = 0.0, node_err = 0.0;
            const double *ygn = cfd_grid_nodes(g, 1);
            /* the image's y nodes are the red grid's, reflected */
            const double *yrn = cfd_grid_nodes(cfd_solver_grid(red), 1);
            for (int j = 0; j <= n[1]; j++)
                node_err = fmax(node_err, fabs(ygn[j] + yrn[n[1] - j]));
            size_t solid_diff = 0;
            const unsigned char *sr = cfd_grid_solid(cfd_solver_grid(red));
            for (int k = 0; k < n[2]; k++)
                for (int j = 0; j < n[1]; j++)
                    for (int i = 0; i < n[0]; i++) {
                        size_t c = (size_t)i + (size_t)n[0] * (j + (size_t)n[1] * k);
                        size_t cr = (size_t)i + (size_t)n[0] * ((n[1] - 1 - j) + (size_t)n[1] * k);
                        solid_diff += solid[c] != sr[cr];
                        if (solid[c])
                            continue;
                        double pos[3] = {xc[i], yc[j], zc[k]}, v[CFD_NVARS];
                        cfd_field_sample(m, pos, v);
                        for (int q = 0; q < 3; q++)
                            worst = fmax(worst, fabs(v[q] - ug[q][c]) / 10.0);
                    }
            printf("mirror: y nodes within %.2e m, %zu blocked cells differ, velocity within %.2e of U\n", node_err,
                   solid_diff, worst);
            CHECK(node_err < 1e-9);
            CHECK(solid_diff == 0);
            CHECK(worst < 1e-3);
        }
        cfd_field_destroy(m);
    }
    /* a field with a rotor does not mirror: the image turns the other way */
    snprintf(meta.rotor, sizeof meta.rotor, "uniform");
    CHECK(cfd_solver_write(red, &meta, path, &err) == 0);
    cfd_field_destroy(f);
    f = cfd_field_load(path, &err);
    CHECK(f && cfd_field_mirror_y(f, &err) == NULL && strstr(err.msg, "rotor") != NULL);
    cfd_field_destroy(f);
    remove(path);
    remove(mpath);
    char xmf[256];
    snprintf(xmf, sizeof xmf, "%s/red30.xmf", dir);
    remove(xmf);
    snprintf(xmf, sizeof xmf, "%s/green30.xmf", dir);
    remove(xmf);
    rmdir(dir);
    cfd_solver_destroy(red);
    cfd_solver_destroy(green);
}

/* The monitor velocities of every iteration, recorded from the progress
 * callback (the state of iteration it). */
typedef struct mon_rec {
    const cfd_solver *s;
    int n;
    double v[1000][CFD_MAX_MONITOR][3];
} mon_rec;

static int record_monitors(void *user, int iter, int max_iter, double res, double t)
{
    (void)max_iter, (void)res, (void)t;
    mon_rec *r = user;
    const cfd_config *c = cfd_solver_config(r->s);
    if (iter < 1 || iter >= 1000)
        return 1;
    for (int m = 0; m < c->n_monitor; m++) {
        double out[CFD_NVARS];
        cfd_solver_sample(r->s, c->monitor_m[m], out);
        memcpy(r->v[iter][m], out, sizeof r->v[iter][m]);
    }
    r->n = iter;
    return 0;
}

/* s run with monitor_stop, its monitors recorded in rec: it stopped at the
 * first iteration from 4 W on (W = monitor_every) whose monitors moved by
 * less than tol_monitor u_ref over each of the two W-iteration spans before
 * it (found here from the record), converged, with the last iterate. The
 * first passing iteration into *first. */
static void check_monitor_stop(const cfd_solver *s, const mon_rec *rec, int rc, const cfd_result *res, int *first)
{
    const cfd_config *c = cfd_solver_config(s);
    const int W = c->monitor_every;
    double worst = -1.0;
    *first = 0;
    for (int it = 4 * W; it <= rec->n && !*first; it++) {
        double ch[2] = {0.0, 0.0};
        for (int w = 0; w < 2; w++)
            for (int m = 0; m < c->n_monitor; m++) {
                double d2 = 0.0;
                for (int d = 0; d < 3; d++) {
                    double a = rec->v[it - W * w][m][d] - rec->v[it - W * (w + 1)][m][d];
                    d2 += a * a;
                }
                ch[w] = fmax(ch[w], sqrt(d2) / c->u_ref_mps);
            }
        if (ch[0] < c->tol_monitor && ch[1] < c->tol_monitor) {
            *first = it;
            worst = fmax(ch[0], ch[1]);
        }
    }
    printf("monitor_stop: stopped at %d (rc %d, converged %d, continuity residual %.2e), the test first passes "
           "at %d (from %d), change %.3e of U\n",
           res->iterations, rc, res->converged, res->residual[0], *first, 4 * W, res->monitor_change);
    CHECK(rc == 0 && res->converged == 1 && res->averaged == 0 && res->steady_mean == 0);
    CHECK(*first >= 4 * W && res->iterations == *first);
    CHECK_NEAR(res->monitor_change, worst, 1e-12);
}

/* monitor_stop (the OpenFOAM engine's test): on a channel whose monitors
 * settle after the test's first iteration and before its residuals reach
 * 1e-4, and on a ship (where the spec turns it on with no averaging); the
 * default run of the ship case keeps its averaging. And the deck lines: a
 * flow against itself differs by nothing, against the inflow by its
 * largest line's figure. */
static void test_monitor_stop(void)
{
    static mon_rec rec;
    cfd_config cfg;
    channel_config(&cfg);
    cfg.max_iter = 900;
    cfg.monitor_stop = 1;
    cfg.monitor_every = 10;
    cfg.tol_monitor = 5e-4;
    cfg.n_monitor = 2;
    double mpos[2][3] = {{1.5, 0.45, 0.5}, {3.0, 0.75, 0.3}};
    memcpy(cfg.monitor_m, mpos, sizeof mpos);
    cfg.progress = record_monitors;
    cfg.progress_user = &rec;
    memset(&rec, 0, sizeof rec);
    core_err err;
    cfd_solver *ch = channel_create(&cfg);
    CHECK(ch != NULL);
    if (ch) {
        rec.s = ch;
        cfd_result res;
        int rc = cfd_solver_run(ch, &res, &err);
        int first;
        check_monitor_stop(ch, &rec, rc, &res, &first);
        /* past the floor, and the residuals not what stopped it */
        CHECK(first > 40);
        double rmax = 0.0;
        for (int q = 0; q < 5; q++)
            rmax = fmax(rmax, res.residual[q]);
        CHECK(rmax > 10.0 * cfg.tol_residual);
        cfd_solver_destroy(ch);
    }

    core_ship ship;
    CHECK(core_ship_load("scenarios/ships/sfs2.ini", &ship, &err) == 0);
    cfd_airwake_spec sp;
    memset(&sp, 0, sizeof sp);
    sp.ship = &ship;
    sp.wod_speed_mps = 10.0;
    sp.level = CORE_GRID_COARSE;
    sp.h_fine_m = 4.0;
    sp.monitor_z_m = -6.8;
    sp.max_iter = 900;
    sp.monitor_stop = 1;
    memset(&rec, 0, sizeof rec);
    cfd_solver *s = cfd_airwake_create(&sp, NULL, record_monitors, &rec, &err);
    CHECK(s != NULL);
    if (!s)
        return;
    rec.s = s;
    const cfd_config *c = cfd_solver_config(s);
    CHECK(c->monitor_stop == 1 && c->avg_window == 0 && c->avg_stop == 0);
    cfd_result res;
    int rc = cfd_solver_run(s, &res, &err), first;
    check_monitor_stop(s, &rec, rc, &res, &first);

    /* the deck lines */
    cfd_flow a = {s, NULL};
    cfd_deck_diff d;
    cfd_airwake_deck_diff(&ship, &a, &a, 10.0, &d);
    CHECK(d.worst == 0.0 && d.rms == 0.0);
    sp.monitor_stop = 0;
    cfd_solver *in = cfd_airwake_create(&sp, NULL, NULL, NULL, &err);
    CHECK(in != NULL);
    if (in) {
        c = cfd_solver_config(in);
        CHECK(c->monitor_stop == 0 && c->avg_stop == 1 && c->avg_window == 200);
        cfd_solver_init_inflow(in);
        cfd_flow b = {in, NULL};
        cfd_airwake_deck_diff(&ship, &a, &b, 10.0, &d);
        double lw = 0.0;
        for (int l = 0; l < CFD_DECK_LINES; l++)
            lw = fmax(lw, d.line_worst[l]);
        printf("deck lines, solved - inflow: largest %.3f of U at (%.1f, %.1f, %.1f), RMS %.3f\n", d.worst,
               d.worst_at_m[0], d.worst_at_m[1], d.worst_at_m[2], d.rms);
        /* the hangar's wake: the flow over the deck is well off the inflow */
        CHECK(d.worst > 0.1 && d.rms > 0.0 && d.rms <= d.worst && lw == d.worst);
        CHECK(d.worst_at_m[0] >= ship.deck_x0_m && d.worst_at_m[0] <= ship.deck_x1_m);
        CHECK(d.line_y_m[0] == -3.4 && d.line_z_m[0] == -3.8 && d.line_y_m[8] == 3.4 && d.line_z_m[8] == -10.0);
        cfd_solver_destroy(in);
    }
    cfd_solver_destroy(s);
}

int main(void)
{
    test_axis();
    test_ship_and_wod();
    test_disk();
    test_io();
    test_io_bad();
    test_averaging();
    test_steady_mean();
    test_steady_mean_windows();
    test_mean_drift();
    test_divergence();
    test_zero_component();
    test_anderson();
    test_sampled_inflow();
    test_zone();
    test_mirror();
    test_monitor_stop();
    return check_done("test_cfd_core");
}
