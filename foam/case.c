/* case.c -- the embedded solver's case as OpenFOAM dictionaries.
 *
 * Mesh: one blockMesh hex block over the domain with the grid's cell
 * counts and, per axis, a multi-section grading whose sections are the
 * runs of constant growth of the grid's node spacing (the uniform focus
 * box, the geometric stretching, the capped outer cells), so blockMesh
 * makes the same nodes (to rounding) in the same cell order (x fastest).
 * The blocked ship cells are a cellSet by label (topoSet labelToCell), the
 * rest inverted into fluidCells, and subsetMesh keeps those, turning the
 * exposed faces into the wall patch "ship". The disk's cells are cell
 * zones (below) made by the same topoSet before the subset, which keeps
 * them.
 *
 * Boundaries as the embedded solver's (cfd_config.bc): an inlet fixes U,
 * k and epsilon to the embedded solver's inflow, face by face (below; a
 * uniform inflow as `fixedValue uniform`), p zero gradient; an outlet
 * fixes p = 0 with U, k and epsilon inletOutlet (zero gradient out, the
 * inflow's k and epsilon and no velocity where air comes back in: the
 * values of the first fluid cell's initial state, also with a profile or
 * a sampled inflow, as is the uniform initial internal field); a symmetry face
 * is a symmetryPlane; the sea and the ship are no-slip walls with the
 * standard wall functions (nutkWallFunction, epsilonWallFunction,
 * kqRWallFunction) with the embedded solver's Cmu, kappa and E.
 *
 * Inlets with a profile (the ABL's log law) or a sampled inflow (a deck
 * zone's faces from the outer field): U, k and epsilon are
 * timeVaryingMappedFixedValue with mapMethod nearest on
 * constant/boundaryData/PATCH: `points`, the patch's face centres (the
 * grid's cell centres across the side, its node coordinate along it; the
 * fluid cells' faces only), and 0/{U,k,epsilon}, the embedded solver's
 * inflow at each (cfd_solver_inflow_at), one time that holds for every
 * iteration. Each OpenFOAM face takes the value of the point at its
 * centre (to rounding), whatever the face order: blockMesh numbers a
 * patch's faces in its own order, subsetMesh drops the ship's and
 * decomposePar splits the rest among the ranks, and nearest mapping needs
 * none of that order, where a `fixedValue nonuniform List` would have to
 * reproduce all three.
 *
 * Rotor: the embedded solver's disk force per cell (cfd_solver_disk_force,
 * the Gaussian-smoothed uniform disk) grouped by force density into
 * FOAM_DISK_BANDS bands (cells below FOAM_DISK_TAIL of the peak density
 * left out, their force given to the lowest band); each band is a cell zone with a
 * vectorSemiImplicitSource of the band's total force over rho, spread
 * evenly over the zone's volume (volumeMode absolute), so the total force
 * is the embedded solver's exactly and its spread across the disk to a
 * quarter of the peak density. The loaded rotor with the aircraft's
 * blades: OpenFOAM's rotorDisk on the one cell zone rotorDisk0 (blade.c).
 *
 * Turbulence: RNGkEpsilon with cfd's constants (cfd.h). Schemes: steady,
 * Gauss linear gradients and Laplacians (the grid is orthogonal), bounded
 * Gauss with the grid level's TVD limiter for convection (vanLeer, or
 * Minmod below 1 m spacing), as the embedded solver's deferred correction.
 * SIMPLEC (consistent), GAMG for p, symmetric Gauss-Seidel for the rest;
 * residualControl 1e-4 on every equation (the seed paper's residual, on
 * OpenFOAM's own normalisation), probes at the embedded solver's monitor
 * points. Why these values: docs/openfoam.md.
 */
#include "foam_private.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* The blade-element rotor's cell zone (one: BLADE_ZONE "0"). */
#define BLADE_ZONE "rotorDisk"

const char *const foam_patch_names[CFD_NFACES] = {"xmin", "xmax", "ymin", "ymax", "zmin", "zmax"};

static const char header_fmt[] = "FoamFile\n{\n    version 2.0;\n    format ascii;\n    class %s;\n"
                                 "    object %s;\n}\n\n";

typedef struct writer {
    FILE *f;
    char path[1200];
    core_err *err;
    int failed;
} writer;

static int w_open(writer *w, const char *dir, const char *rel, const char *cls, const char *obj, core_err *err)
{
    w->err = err;
    w->failed = 0;
    if (snprintf(w->path, sizeof w->path, "%s/%s", dir, rel) >= (int)sizeof w->path)
        return core_err_set(err, -1, "foam case: path too long: %s/%s", dir, rel);
    if (!(w->f = fopen(w->path, "w")))
        return core_err_set(err, -1, "foam case: %s: %s", w->path, strerror(errno));
    fprintf(w->f, header_fmt, cls, obj);
    return 0;
}

__attribute__((format(printf, 2, 3))) static void w_printf(writer *w, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    if (vfprintf(w->f, fmt, ap) < 0)
        w->failed = 1;
    va_end(ap);
}

static int w_close(writer *w)
{
    int bad = w->failed | ferror(w->f);
    if (fclose(w->f) != 0)
        bad = 1;
    w->f = NULL;
    return bad ? core_err_set(w->err, -1, "foam case: %s: write failed", w->path) : 0;
}

/* ------------------------------------------------------------------ mesh */
/* One axis's grading: sections of constant spacing growth, each as
 * (length, cells, last width / first width). */
static void write_grading(writer *w, const double *x, int n)
{
    w_printf(w, "(");
    int s = 0;
    while (s < n) {
        int e = s + 1; /* the section is cells s .. e-1 */
        if (s + 1 < n) {
            double r = (x[s + 2] - x[s + 1]) / (x[s + 1] - x[s]);
            e = s + 2;
            while (e < n) {
                double re = (x[e + 1] - x[e]) / (x[e] - x[e - 1]);
                if (fabs(re - r) > 1e-7 * r)
                    break;
                e++;
            }
        }
        double first = x[s + 1] - x[s], last = x[e] - x[e - 1];
        w_printf(w, " (%.12g %d %.12g)", x[e] - x[s], e - s, last / first);
        s = e;
    }
    w_printf(w, " )");
}

static int write_block_mesh(const cfd_grid *g, const cfd_config *cfg, const char *dir, core_err *err)
{
    int n[3];
    cfd_grid_dims(g, n);
    const double *x[3] = {cfd_grid_nodes(g, 0), cfd_grid_nodes(g, 1), cfd_grid_nodes(g, 2)};
    writer w;
    if (w_open(&w, dir, "system/blockMeshDict", "dictionary", "blockMeshDict", err))
        return -1;
    w_printf(&w, "scale 1;\n\nvertices\n(\n");
    for (int c = 0; c < 8; c++) { /* 0..3 at z lo counter-clockwise from (x lo, y lo); 4..7 at z hi */
        int ix = (c & 3) == 1 || (c & 3) == 2, iy = (c & 3) >= 2, iz = c >= 4;
        w_printf(&w, "    (%.12g %.12g %.12g)\n", x[0][ix ? n[0] : 0], x[1][iy ? n[1] : 0], x[2][iz ? n[2] : 0]);
    }
    w_printf(&w, ");\n\nblocks\n(\n    hex (0 1 2 3 4 5 6 7) (%d %d %d)\n    simpleGrading\n    (\n", n[0], n[1], n[2]);
    for (int d = 0; d < 3; d++) {
        w_printf(&w, "        ");
        write_grading(&w, x[d], n[d]);
        w_printf(&w, "\n");
    }
    w_printf(&w, "    )\n);\n\nedges ();\n\nboundary\n(\n");
    static const char *const faces[CFD_NFACES] = {"(0 4 7 3)", "(1 2 6 5)", "(0 1 5 4)",
                                                  "(3 7 6 2)", "(0 3 2 1)", "(4 5 6 7)"};
    for (int f = 0; f < CFD_NFACES; f++)
        w_printf(&w, "    %s\n    {\n        type %s;\n        faces (%s);\n    }\n", foam_patch_names[f],
                 cfg->bc[f].type == CFD_BC_SYMMETRY ? "symmetryPlane" : cfg->bc[f].type == CFD_BC_WALL ? "wall" : "patch",
                 faces[f]);
    w_printf(&w, "    %s\n    {\n        type wall;\n        faces ();\n    }\n);\n", FOAM_SHIP_PATCH);
    return w_close(&w);
}

/* ------------------------------------------------------------- topoSet */
static void write_labels(writer *w, const size_t *lab, size_t n)
{
    w_printf(w, "(");
    for (size_t i = 0; i < n; i++)
        w_printf(w, "%s%zu", i % 16 ? " " : "\n            ", lab[i]);
    w_printf(w, "\n        )");
}

/* The disk's bands: band[c] in 0..FOAM_DISK_BANDS-1 for a fluid cell with
 * a force density of at least FOAM_DISK_TAIL of the peak, -1 otherwise (the
 * tail's force is added to band 0's, so the total is the disk's); force[b][3] the band's total (N), vol[b] its
 * volume. Returns the cells with a force. */
static size_t disk_bands(const cfd_solver *s, int *band, double force[][3], double *vol)
{
    const cfd_grid *g = cfd_solver_grid(s);
    const unsigned char *solid = cfd_grid_solid(g);
    const double *fd[3] = {cfd_solver_disk_force(s, 0), cfd_solver_disk_force(s, 1), cfd_solver_disk_force(s, 2)};
    size_t nc = cfd_grid_cells(g), used = 0;
    int n[3];
    cfd_grid_dims(g, n);
    const double *xn[3] = {cfd_grid_nodes(g, 0), cfd_grid_nodes(g, 1), cfd_grid_nodes(g, 2)};
    double peak = 0.0;
    for (int pass = 0; pass < 2; pass++)
        for (size_t c = 0; c < nc; c++) {
            int i = (int)(c % (size_t)n[0]), j = (int)(c / (size_t)n[0] % (size_t)n[1]),
                k = (int)(c / ((size_t)n[0] * (size_t)n[1]));
            double v = (xn[0][i + 1] - xn[0][i]) * (xn[1][j + 1] - xn[1][j]) * (xn[2][k + 1] - xn[2][k]);
            double fm = fd[0] ? sqrt(fd[0][c] * fd[0][c] + fd[1][c] * fd[1][c] + fd[2][c] * fd[2][c]) : 0.0;
            double dens = fm / v;
            if (pass == 0) {
                band[c] = -1;
                if (!solid[c] && fm > 0.0 && dens > peak)
                    peak = dens;
                continue;
            }
            if (solid[c] || !(fm > 0.0))
                continue;
            if (dens < FOAM_DISK_TAIL * peak) {
                /* the Gaussian's far tail: its force joins the lowest band */
                for (int d = 0; d < 3; d++)
                    force[0][d] += fd[d][c];
                continue;
            }
            int b = (int)(dens / peak * FOAM_DISK_BANDS);
            b = b < 0 ? 0 : b >= FOAM_DISK_BANDS ? FOAM_DISK_BANDS - 1 : b;
            band[c] = b;
            for (int d = 0; d < 3; d++)
                force[b][d] += fd[d][c];
            vol[b] += v;
            used++;
        }
    return used;
}

/* The ship's cells (inverted into fluidCells) and, with band, the cell
 * zones ZONE0.. of the cells whose band[c] is 0.. (ZONE the zone prefix). */
static int write_topo_set(const cfd_solver *s, const int *band, const char *zone, const char *dir, int *has_ship,
                          core_err *err)
{
    const cfd_grid *g = cfd_solver_grid(s);
    const unsigned char *solid = cfd_grid_solid(g);
    size_t nc = cfd_grid_cells(g), ns = 0;
    size_t *lab = malloc((nc ? nc : 1) * sizeof *lab);
    if (!lab)
        return core_err_set(err, -2, "foam case: out of memory");
    writer w;
    if (w_open(&w, dir, "system/topoSetDict", "dictionary", "topoSetDict", err)) {
        free(lab);
        return -1;
    }
    w_printf(&w, "actions\n(\n");
    for (size_t c = 0; c < nc; c++)
        if (solid[c])
            lab[ns++] = c;
    *has_ship = ns > 0;
    if (ns > 0) {
        /* the ship's cells, inverted: the cells subsetMesh keeps */
        w_printf(&w, "    {\n        name fluidCells;\n        type cellSet;\n        action new;\n"
                     "        source labelToCell;\n        value ");
        write_labels(&w, lab, ns);
        w_printf(&w, ";\n    }\n    {\n        name fluidCells;\n        type cellSet;\n        action invert;\n    }\n");
    }
    for (int b = 0; band && b < FOAM_DISK_BANDS; b++) {
        size_t nb = 0;
        for (size_t c = 0; c < nc; c++)
            if (band[c] == b)
                lab[nb++] = c;
        if (nb == 0)
            continue;
        w_printf(&w, "    {\n        name %s%d;\n        type cellSet;\n        action new;\n"
                     "        source labelToCell;\n        value ", zone, b);
        write_labels(&w, lab, nb);
        w_printf(&w, ";\n    }\n    {\n        name %s%d;\n        type cellZoneSet;\n        action new;\n"
                     "        source setToCellZone;\n        set %s%d;\n    }\n", zone, b, zone, b);
    }
    w_printf(&w, ");\n");
    free(lab);
    return w_close(&w);
}

/* --------------------------------------------------------------- fields */
/* The uniform inflow (the solver's state after cfd_solver_init_inflow in
 * its first fluid cell): u v w k epsilon. */
static void inflow_values(const cfd_solver *s, double v[5])
{
    const cfd_grid *g = cfd_solver_grid(s);
    const unsigned char *solid = cfd_grid_solid(g);
    size_t c = 0, nc = cfd_grid_cells(g);
    while (c + 1 < nc && solid[c])
        c++;
    static const int vars[5] = {CFD_VAR_U, CFD_VAR_V, CFD_VAR_W, CFD_VAR_K, CFD_VAR_EPS};
    for (int q = 0; q < 5; q++)
        v[q] = cfd_solver_var(s, vars[q])[c];
}

typedef enum { F_U, F_P, F_K, F_EPS, F_NUT } field_id;

/* An inlet mapped from constant/boundaryData (the inflow face by face). */
static void write_mapped(writer *w, const char *value)
{
    w_printf(w, "        type timeVaryingMappedFixedValue;\n        mapMethod nearest;\n        setAverage false;\n"
                "        value uniform %s;\n", value);
}

/* One patch's entry of field id for boundary type t (-1: the ship);
 * mapped: an inlet takes the inflow face by face (boundaryData). */
/* A patch's boundary condition of field id for the face type t (-1: the
 * ship's wall); mapped: inlets take boundaryData face by face; open: calm
 * air, no inlet anywhere, every open face lets air in at total pressure 0
 * (as the embedded solver's openings) and out at static pressure 0. */
static void write_patch(writer *w, field_id id, int t, const double in[5], int mapped, int open)
{
    char val[128];
    if (t == CFD_BC_SYMMETRY) {
        w_printf(w, "        type symmetryPlane;\n");
        return;
    }
    const int wall = t == CFD_BC_WALL || t < 0;
    switch (id) {
    case F_U:
        if (wall)
            w_printf(w, "        type noSlip;\n");
        else if (t == CFD_BC_INLET && mapped) {
            snprintf(val, sizeof val, "(%.12g %.12g %.12g)", in[0], in[1], in[2]);
            write_mapped(w, val);
        } else if (t == CFD_BC_INLET)
            w_printf(w, "        type fixedValue;\n        value uniform (%.12g %.12g %.12g);\n", in[0], in[1], in[2]);
        else if (open)
            w_printf(w, "        type pressureInletOutletVelocity;\n        value uniform (0 0 0);\n");
        else
            w_printf(w, "        type inletOutlet;\n        inletValue uniform (0 0 0);\n"
                        "        value uniform (%.12g %.12g %.12g);\n", in[0], in[1], in[2]);
        break;
    case F_P:
        if (t == CFD_BC_OUTLET && open)
            w_printf(w, "        type totalPressure;\n        p0 uniform 0;\n        value uniform 0;\n");
        else if (t == CFD_BC_OUTLET)
            w_printf(w, "        type fixedValue;\n        value uniform 0;\n");
        else
            w_printf(w, "        type zeroGradient;\n");
        break;
    case F_K:
    case F_EPS: {
        double v = id == F_K ? in[3] : in[4];
        if (wall)
            w_printf(w, "        type %s;\n        value uniform %.12g;\n",
                     id == F_K ? "kqRWallFunction" : "epsilonWallFunction", v);
        else if (t == CFD_BC_INLET && mapped) {
            snprintf(val, sizeof val, "%.12g", v);
            write_mapped(w, val);
        } else if (t == CFD_BC_INLET)
            w_printf(w, "        type fixedValue;\n        value uniform %.12g;\n", v);
        else
            w_printf(w, "        type inletOutlet;\n        inletValue uniform %.12g;\n        value uniform %.12g;\n", v, v);
        break;
    }
    case F_NUT:
        if (wall)
            w_printf(w, "        type nutkWallFunction;\n        Cmu %.12g;\n        kappa %.12g;\n        E %.12g;\n"
                        "        value uniform 0;\n", CFD_RNG_CMU, CFD_WALL_KAPPA, CFD_WALL_E);
        else
            w_printf(w, "        type calculated;\n        value uniform 0;\n");
        break;
    }
}

static int write_field(const cfd_config *cfg, const double in[5], int mapped, int open, field_id id,
                       const char *dir, core_err *err)
{
    static const char *const names[] = {"U", "p", "k", "epsilon", "nut"};
    static const char *const dims[] = {"[0 1 -1 0 0 0 0]", "[0 2 -2 0 0 0 0]", "[0 2 -2 0 0 0 0]",
                                       "[0 2 -3 0 0 0 0]", "[0 2 -1 0 0 0 0]"};
    char rel[32];
    snprintf(rel, sizeof rel, "0/%s", names[id]);
    writer w;
    if (w_open(&w, dir, rel, id == F_U ? "volVectorField" : "volScalarField", names[id], err))
        return -1;
    w_printf(&w, "dimensions %s;\n\n", dims[id]);
    const double nut0 = CFD_RNG_CMU * in[3] * in[3] / in[4];
    switch (id) {
    case F_U:
        if (open) /* calm air: the air at rest */
            w_printf(&w, "internalField uniform (0 0 0);\n");
        else
            w_printf(&w, "internalField uniform (%.12g %.12g %.12g);\n", in[0], in[1], in[2]);
        break;
    case F_P:
        w_printf(&w, "internalField uniform 0;\n");
        break;
    case F_K:
        w_printf(&w, "internalField uniform %.12g;\n", in[3]);
        break;
    case F_EPS:
        w_printf(&w, "internalField uniform %.12g;\n", in[4]);
        break;
    case F_NUT:
        w_printf(&w, "internalField uniform %.12g;\n", nut0);
        break;
    }
    w_printf(&w, "\nboundaryField\n{\n");
    for (int f = 0; f < CFD_NFACES; f++) {
        w_printf(&w, "    %s\n    {\n", foam_patch_names[f]);
        write_patch(&w, id, (int)cfg->bc[f].type, in, mapped, open);
        w_printf(&w, "    }\n");
    }
    w_printf(&w, "    %s\n    {\n", FOAM_SHIP_PATCH);
    write_patch(&w, id, -1, in, mapped, open);
    w_printf(&w, "    }\n}\n");
    return w_close(&w);
}

/* ---------------------------------------------------------- inlet data */
static int make_dir(const char *dir, const char *rel, core_err *err)
{
    char p[1200];
    if (snprintf(p, sizeof p, "%s/%s", dir, rel) >= (int)sizeof p)
        return core_err_set(err, -1, "foam case: path too long: %s/%s", dir, rel);
    if (mkdir(p, 0755) != 0 && errno != EEXIST)
        return core_err_set(err, -1, "foam case: %s: %s", p, strerror(errno));
    return 0;
}

/* A raw list file of boundaryData (no header: OpenFOAM reads the list). */
static int raw_open(writer *w, const char *dir, const char *rel, core_err *err)
{
    w->err = err;
    w->failed = 0;
    if (snprintf(w->path, sizeof w->path, "%s/%s", dir, rel) >= (int)sizeof w->path)
        return core_err_set(err, -1, "foam case: path too long: %s/%s", dir, rel);
    if (!(w->f = fopen(w->path, "w")))
        return core_err_set(err, -1, "foam case: %s: %s", w->path, strerror(errno));
    return 0;
}

/* constant/boundaryData/PATCH of inlet side f: the fluid cells' face
 * centres (points) and the embedded solver's inflow at each (0/U, 0/k,
 * 0/epsilon). */
static int write_inlet_data(const cfd_solver *s, int f, const char *dir, core_err *err)
{
    const cfd_grid *g = cfd_solver_grid(s);
    const unsigned char *solid = cfd_grid_solid(g);
    int n[3];
    cfd_grid_dims(g, n);
    int d = f >> 1, a = d == 0 ? 1 : 0, b = d == 2 ? 1 : 2;
    const double *xc[3] = {cfd_grid_centres(g, 0), cfd_grid_centres(g, 1), cfd_grid_centres(g, 2)};
    double side = cfd_grid_nodes(g, d)[(f & 1) ? n[d] : 0];
    size_t nf = (size_t)n[a] * (size_t)n[b], m = 0;
    double *pos = malloc((nf ? nf : 1) * 3 * sizeof *pos), *val = malloc((nf ? nf : 1) * 5 * sizeof *val);
    if (!pos || !val) {
        free(pos);
        free(val);
        return core_err_set(err, -2, "foam case: out of memory");
    }
    int rc = 0;
    for (int jb = 0; jb < n[b] && !rc; jb++)
        for (int ja = 0; ja < n[a] && !rc; ja++) {
            int ijk[3];
            ijk[d] = (f & 1) ? n[d] - 1 : 0;
            ijk[a] = ja;
            ijk[b] = jb;
            if (solid[(size_t)ijk[0] + (size_t)n[0] * ((size_t)ijk[1] + (size_t)n[1] * (size_t)ijk[2])])
                continue;
            double *p = pos + 3 * m, *v = val + 5 * m;
            p[a] = xc[a][ja];
            p[b] = xc[b][jb];
            p[d] = side;
            if (cfd_solver_inflow_at(s, f, p, v, v + 3, v + 4) != 0)
                rc = core_err_set(err, -1, "foam case: no inflow on %s at (%g %g %g)", foam_patch_names[f], p[0],
                                  p[1], p[2]);
            m++;
        }
    char rel[2][64];
    snprintf(rel[0], sizeof rel[0], "constant/boundaryData/%s", foam_patch_names[f]);
    snprintf(rel[1], sizeof rel[1], "constant/boundaryData/%s/0", foam_patch_names[f]);
    if (!rc)
        rc = make_dir(dir, "constant/boundaryData", err);
    for (int q = 0; q < 2 && !rc; q++)
        rc = make_dir(dir, rel[q], err);
    static const char *const files[4] = {"points", "0/U", "0/k", "0/epsilon"};
    for (int q = 0; q < 4 && !rc; q++) {
        char path[128];
        snprintf(path, sizeof path, "%s/%s", rel[0], files[q]);
        writer w;
        if ((rc = raw_open(&w, dir, path, err)) != 0)
            break;
        w_printf(&w, "%zu\n(\n", m);
        for (size_t i = 0; i < m; i++) {
            const double *v = q == 0 ? pos + 3 * i : val + 5 * i;
            if (q <= 1)
                w_printf(&w, "(%.15g %.15g %.15g)\n", v[0], v[1], v[2]);
            else
                w_printf(&w, "%.15g\n", v[q == 2 ? 3 : 4]);
        }
        w_printf(&w, ")\n");
        rc = w_close(&w);
    }
    free(pos);
    free(val);
    return rc;
}

/* ------------------------------------------------------ system, constant */
static int write_control(const cfd_config *cfg, int max_iter, const char *dir, core_err *err)
{
    writer w;
    if (w_open(&w, dir, "system/controlDict", "dictionary", "controlDict", err))
        return -1;
    w_printf(&w, "application simpleFoam;\nstartFrom startTime;\nstartTime 0;\nstopAt endTime;\nendTime %d;\n"
                 "deltaT 1;\nwriteControl timeStep;\nwriteInterval %d;\npurgeWrite 0;\nwriteFormat ascii;\n"
                 "writePrecision 12;\nwriteCompression off;\ntimeFormat general;\ntimePrecision 8;\n"
                 "runTimeModifiable true;\n\nfunctions\n{\n",
             max_iter, max_iter);
    if (cfg->n_monitor > 0) {
        w_printf(&w, "    monitors\n    {\n        type probes;\n        libs (\"libsampling.so\");\n"
                     "        writeControl timeStep;\n        writeInterval 1;\n        fields (U);\n"
                     "        probeLocations\n        (\n");
        for (int m = 0; m < cfg->n_monitor; m++)
            w_printf(&w, "            (%.12g %.12g %.12g)\n", cfg->monitor_m[m][0], cfg->monitor_m[m][1],
                     cfg->monitor_m[m][2]);
        w_printf(&w, "        );\n    }\n");
    }
    /* the engine's stop (foam.c): the function object looks for the file
     * every iteration, where an edited controlDict is noticed only after
     * fileModificationSkew seconds */
    w_printf(&w, "    stop\n    {\n        type abort;\n        libs (\"libutilityFunctionObjects.so\");\n"
                 "        file \"%s/%s\";\n        action writeNow;\n    }\n}\n",
             dir, FOAM_STOP_FILE);
    return w_close(&w);
}

/* stiff: the rotor's flow dominates, first-order upwind convection (see
 * write_solution). */
static int write_schemes(const cfd_config *cfg, int stiff, const char *dir, core_err *err)
{
    const char *lim = cfg->second_order == 0 || stiff ? NULL
                      : cfg->limiter == CFD_LIMITER_MINMOD ? "Minmod"
                                                           : "vanLeer";
    char u[64], t[64];
    /* vectors take the limiter's V form (limited along the direction of
     * steepest change), as the embedded solver limits each component alike */
    snprintf(u, sizeof u, "bounded Gauss %s%s", lim ? lim : "upwind", lim ? "V" : "");
    snprintf(t, sizeof t, "bounded Gauss %s", lim ? lim : "upwind");
    writer w;
    if (w_open(&w, dir, "system/fvSchemes", "dictionary", "fvSchemes", err))
        return -1;
    w_printf(&w, "ddtSchemes\n{\n    default steadyState;\n}\n\ngradSchemes\n{\n    default Gauss linear;\n}\n\n"
                 "divSchemes\n{\n    default none;\n    div(phi,U) %s;\n    div(phi,k) %s;\n"
                 "    div(phi,epsilon) %s;\n    div((nuEff*dev2(T(grad(U))))) Gauss linear;\n}\n\n"
                 "laplacianSchemes\n{\n    default Gauss linear corrected;\n}\n\n"
                 "interpolationSchemes\n{\n    default linear;\n}\n\nsnGradSchemes\n{\n    default corrected;\n}\n\n"
                 "wallDist\n{\n    method meshWave;\n}\n",
             u, t, t);
    return w_close(&w);
}

/* stiff: the rotor's flow dominates the wind's (calm air, or a wind
 * slower than the disk's hover induced velocity sqrt(T / (2 rho A))).
 * There the disk drives the flow, and from the inflow SIMPLEC's first
 * iterations meet the disk's force with too little convection to balance
 * it: in calm air k and epsilon went negative in the first iteration and
 * the run diverged within five (SIMPLEC at 0.9 / 0.8, and SIMPLE at 0.5
 * with p at 0.3, with the TVD scheme; van Leer at 0.5 / 0.3 also diverged
 * when started from a converged first-order field), and a deck zone in a
 * 2.78 m/s wind diverged the same way. Plain SIMPLE with U, k and epsilon
 * relaxed to 0.3, p to 0.2 and upwind convection runs, and converges
 * (residuals below 1e-4 at 433 iterations in calm air on the quick grid):
 * such fields are first-order (docs/openfoam.md). */
static int write_solution(int stiff, const char *dir, core_err *err)
{
    writer w;
    if (w_open(&w, dir, "system/fvSolution", "dictionary", "fvSolution", err))
        return -1;
    w_printf(&w, "solvers\n{\n    p\n    {\n        solver GAMG;\n        smoother GaussSeidel;\n"
                 "        tolerance 1e-8;\n        relTol 0.05;\n    }\n"
                 "    \"(U|k|epsilon)\"\n    {\n        solver smoothSolver;\n        smoother symGaussSeidel;\n"
                 "        tolerance 1e-9;\n        relTol 0.1;\n    }\n}\n\n"
                 "SIMPLE\n{\n    nNonOrthogonalCorrectors 0;\n    consistent %s;\n    residualControl\n    {\n"
                 "        p 1e-4;\n        U 1e-4;\n        \"(k|epsilon)\" 1e-4;\n    }\n}\n\n",
             stiff ? "no" : "yes");
    if (stiff)
        w_printf(&w, "relaxationFactors\n{\n    fields\n    {\n        p 0.2;\n    }\n    equations\n    {\n"
                     "        U 0.3;\n        \".*\" 0.3;\n    }\n}\n");
    else
        w_printf(&w, "relaxationFactors\n{\n    equations\n    {\n        U 0.9;\n        \".*\" 0.8;\n    }\n}\n");
    return w_close(&w);
}

static int write_decompose(const cfd_grid *g, int np, const char *dir, core_err *err)
{
    int n[3];
    cfd_grid_dims(g, n);
    int d = n[0] >= n[1] && n[0] >= n[2] ? 0 : n[1] >= n[2] ? 1 : 2; /* split the longest axis */
    int sp[3] = {1, 1, 1};
    sp[d] = np;
    writer w;
    if (w_open(&w, dir, "system/decomposeParDict", "dictionary", "decomposeParDict", err))
        return -1;
    w_printf(&w, "numberOfSubdomains %d;\nmethod simple;\n\nsimpleCoeffs\n{\n    n (%d %d %d);\n    delta 0.001;\n}\n", np,
             sp[0], sp[1], sp[2]);
    return w_close(&w);
}

/* transportProperties, turbulenceProperties and, with a rotor, fvOptions:
 * the uniform disk's bands (band, force, vol) or the blade-element rotor
 * (blades, on the zone BLADE_ZONE0). */
static int write_constant(const cfd_solver *s, const int *band, const double force[][3], const double *vol,
                          const cfd_airwake_spec *sp, const hfm_blade_data *blades, const char *dir, core_err *err)
{
    const cfd_config *cfg = cfd_solver_config(s);
    writer w;
    if (w_open(&w, dir, "constant/transportProperties", "dictionary", "transportProperties", err))
        return -1;
    w_printf(&w, "transportModel Newtonian;\n\nnu [0 2 -1 0 0 0 0] %.12g;\n", cfg->nu_m2ps);
    if (w_close(&w) || w_open(&w, dir, "constant/turbulenceProperties", "dictionary", "turbulenceProperties", err))
        return -1;
    w_printf(&w, "simulationType RAS;\n\nRAS\n{\n    RASModel RNGkEpsilon;\n    turbulence on;\n    printCoeffs on;\n"
                 "    RNGkEpsilonCoeffs\n    {\n        Cmu %.12g;\n        C1 %.12g;\n        C2 %.12g;\n        C3 0;\n"
                 "        sigmak %.12g;\n        sigmaEps %.12g;\n        eta0 %.12g;\n        beta %.12g;\n    }\n}\n",
             CFD_RNG_CMU, CFD_RNG_C1, CFD_RNG_C2, CFD_RNG_SIGMA_K, CFD_RNG_SIGMA_E, CFD_RNG_ETA0, CFD_RNG_BETA);
    if (w_close(&w))
        return -1;
    if (!band)
        return 0;
    if (w_open(&w, dir, "constant/fvOptions", "dictionary", "fvOptions", err))
        return -1;
    if (blades) {
        foam_blade_options(w.f, BLADE_ZONE "0", &sp->disk, blades, cfg->rho_kgpm3);
        return w_close(&w);
    }
    for (int b = 0; b < FOAM_DISK_BANDS; b++) {
        if (!(vol[b] > 0.0))
            continue;
        double r = cfg->rho_kgpm3;
        w_printf(&w, "rotorBand%d\n{\n    type vectorSemiImplicitSource;\n    active yes;\n"
                     "    selectionMode cellZone;\n    cellZone rotorBand%d;\n    volumeMode absolute;\n"
                     "    injectionRateSuSp\n    {\n        U ((%.12g %.12g %.12g) 0);\n    }\n}\n\n",
                 b, b, force[b][0] / r, force[b][1] / r, force[b][2] / r);
    }
    return w_close(&w);
}

static int make_dirs(const char *dir, core_err *err)
{
    static const char *const sub[] = {"system", "constant", "0"};
    for (size_t i = 0; i < sizeof sub / sizeof sub[0]; i++) {
        char p[1200];
        snprintf(p, sizeof p, "%s/%s", dir, sub[i]);
        if (mkdir(p, 0755) != 0 && errno != EEXIST)
            return core_err_set(err, -1, "foam case: %s: %s", p, strerror(errno));
    }
    return 0;
}

int foam_case_files(const cfd_solver *s, const cfd_airwake_spec *sp, const hfm_blade_data *blades, int np,
                    int max_iter, const char *dir, int *has_ship, core_err *err)
{
    const cfd_grid *g = cfd_solver_grid(s);
    const cfd_config *cfg = cfd_solver_config(s);
    double in[5];
    inflow_values(s, in);
    if (!(in[3] > 0.0 && in[4] > 0.0))
        return core_err_set(err, -1, "foam case: the inflow has no turbulence (k %g, epsilon %g)", in[3], in[4]);
    int *band = NULL;
    double force[FOAM_DISK_BANDS][3] = {{0}}, vol[FOAM_DISK_BANDS] = {0};
    if (blades && sp->rotor != CORE_ROTOR_OFF) {
        if (!(band = malloc(cfd_grid_cells(g) * sizeof *band)))
            return core_err_set(err, -2, "foam case: out of memory");
        if (foam_blade_zone(s, &sp->disk, blades->root_cutout_m, band) == 0) {
            free(band);
            return core_err_set(err, -1, "foam case: the rotor disk's plane crosses no fluid cell between the root "
                                         "cut-out and the tip");
        }
    } else if (cfd_solver_disk_force(s, 0)) {
        blades = NULL;
        if (!(band = malloc(cfd_grid_cells(g) * sizeof *band)))
            return core_err_set(err, -2, "foam case: out of memory");
        if (disk_bands(s, band, force, vol) == 0) {
            free(band);
            return core_err_set(err, -1, "foam case: the rotor disk has no fluid cell");
        }
    }
    int open = 1; /* calm air: no inlet anywhere */
    for (int f = 0; f < CFD_NFACES; f++)
        open &= cfg->bc[f].type != CFD_BC_INLET;
    /* the rotor's flow dominates: calm air, or a wind below the disk's
     * hover induced velocity */
    double vi = sp->rotor != CORE_ROTOR_OFF ? cfd_disk_hover_vi_mps(&sp->disk, cfg->rho_kgpm3) : 0.0;
    int stiff = open || sp->wod_speed_mps < vi;
    int rc = make_dirs(dir, err);
    if (!rc)
        rc = write_block_mesh(g, cfg, dir, err);
    if (!rc)
        rc = write_topo_set(s, band, blades ? BLADE_ZONE : "rotorBand", dir, has_ship, err);
    if (!rc)
        rc = write_control(cfg, max_iter, dir, err);
    if (!rc)
        rc = write_schemes(cfg, stiff, dir, err);
    if (!rc)
        rc = write_solution(stiff, dir, err);
    if (!rc)
        rc = write_decompose(g, np, dir, err);
    if (!rc)
        rc = write_constant(s, band, force, vol, sp, band ? blades : NULL, dir, err);
    /* a profile or a sampled inflow: every inlet face by face */
    const int mapped = cfg->inflow.type != CFD_INFLOW_UNIFORM;
    for (int f = 0; mapped && !rc && f < CFD_NFACES; f++)
        if (cfg->bc[f].type == CFD_BC_INLET)
            rc = write_inlet_data(s, f, dir, err);
    for (field_id id = F_U; !rc && id <= F_NUT; id++)
        rc = write_field(cfg, in, mapped, open, id, dir, err);
    free(band);
    return rc;
}
