/* read.c -- OpenFOAM's results back into disim: simpleFoam's log (the
 * iterations, the last initial residuals, whether the residual control
 * ended the run, the version), the probes' monitor velocities, and the
 * latest time's cell fields (ASCII), placed cell by cell on the embedded
 * solver's grid by their cell centres. */
#include "foam_private.h"

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

char *foam_slurp(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    size_t cap = 1 << 16, n = 0;
    char *b = malloc(cap);
    while (b) {
        if (n + 1 >= cap) {
            char *t = realloc(b, cap *= 2);
            if (!t) {
                free(b);
                b = NULL;
                break;
            }
            b = t;
        }
        size_t got = fread(b + n, 1, cap - n - 1, f);
        if (got == 0)
            break;
        n += got;
    }
    fclose(f);
    if (b)
        b[n] = '\0';
    if (len)
        *len = n;
    return b;
}

/* The last occurrence of needle in hay. */
static const char *last_of(const char *hay, const char *needle)
{
    const char *p = NULL, *q = hay;
    while ((q = strstr(q, needle))) {
        p = q;
        q++;
    }
    return p;
}

int foam_log_parse(const char *path, foam_log_info *info)
{
    memset(info, 0, sizeof *info);
    char *b = foam_slurp(path, NULL);
    if (!b)
        return -1;
    /* the banner's build line: "Build  : OPENFOAM=1912 patch=200626" */
    const char *v = strstr(b, "OPENFOAM=");
    if (v) {
        v += 9;
        size_t l = strcspn(v, " \t\n");
        const char *pt = strstr(v, "patch=");
        size_t lp = pt && pt < v + l + 2 ? strcspn(pt + 6, " \t\n") : 0;
        snprintf(info->version, sizeof info->version, "v%.*s%s%.*s", (int)(l < 20 ? l : 20), v, lp ? " patch " : "",
                 (int)(lp < 20 ? lp : 20), lp ? pt + 6 : "");
    }
    /* the last iteration's block: from its "\nTime = " */
    const char *t = last_of(b, "\nTime = ");
    int rc = -1;
    if (t) {
        info->iterations = atoi(t + 8);
        static const char *const eq[5] = {"Solving for p,", "Solving for Ux,", "Solving for Uy,", "Solving for Uz,",
                                          "Solving for k,"};
        for (int q = 0; q < 5; q++) {
            /* the first solve of each in the block (p has one per corrector) */
            const char *s = strstr(t, eq[q]);
            const char *r = s ? strstr(s, "Initial residual = ") : NULL;
            info->residual[q] = r ? strtod(r + 19, NULL) : 0.0;
        }
        rc = 0;
    }
    info->converged = strstr(b, "SIMPLE solution converged in") != NULL;
    free(b);
    return rc;
}

double foam_monitor_change(const char *case_dir, int back, double u_ref)
{
    char p[1200];
    snprintf(p, sizeof p, "%s/postProcessing/monitors/0/U", case_dir);
    char *b = foam_slurp(p, NULL);
    if (!b || !(u_ref > 0.0)) {
        free(b);
        return -1.0;
    }
    /* rows: time (u v w) (u v w) ...; keep the last row and the one `back` before */
    int nrow = 0;
    for (char *l = b; *l; l = strchr(l, '\n') ? strchr(l, '\n') + 1 : l + strlen(l))
        if (*l != '#' && *l != '\n')
            nrow++;
    double change = -1.0;
    if (nrow > back) {
        const char *rows[2] = {NULL, NULL};
        int r = 0;
        for (char *l = b; *l; l = strchr(l, '\n') ? strchr(l, '\n') + 1 : l + strlen(l)) {
            if (*l == '#' || *l == '\n')
                continue;
            if (r == nrow - 1 - back)
                rows[0] = l;
            if (r == nrow - 1)
                rows[1] = l;
            r++;
        }
        change = 0.0;
        const char *a = rows[0], *c = rows[1];
        strtod(a, (char **)&a);
        strtod(c, (char **)&c);
        for (;;) {
            const char *pa = strchr(a, '('), *pc = strchr(c, '(');
            const char *ea = strchr(a, '\n'), *ec = strchr(c, '\n');
            if (!pa || !pc || (ea && pa > ea) || (ec && pc > ec))
                break;
            a = pa + 1;
            c = pc + 1;
            double d2 = 0.0;
            for (int q = 0; q < 3; q++) {
                double x = strtod(a, (char **)&a), y = strtod(c, (char **)&c);
                d2 += (x - y) * (x - y);
            }
            change = fmax(change, sqrt(d2) / u_ref);
        }
    }
    free(b);
    return change;
}

/* The latest time folder's name (the largest number > 0). */
int foam_latest_time(const char *case_dir, char *out, size_t n)
{
    DIR *d = opendir(case_dir);
    if (!d)
        return -1;
    double best = 0.0;
    struct dirent *e;
    while ((e = readdir(d))) {
        char *end;
        double t = strtod(e->d_name, &end);
        if (end != e->d_name && *end == '\0' && t > best) {
            best = t;
            snprintf(out, n, "%s", e->d_name);
        }
    }
    closedir(d);
    return best > 0.0 ? 0 : -1;
}

int foam_read_internal(const char *path, int ncomp, double **vals, size_t *n, core_err *err)
{
    *vals = NULL;
    *n = 0;
    char *b = foam_slurp(path, NULL);
    if (!b)
        return core_err_set(err, -1, "OpenFOAM result: %s: %s", path, strerror(errno));
    const char *p = strstr(b, "internalField");
    int rc = 0;
    if (!p) {
        rc = core_err_set(err, -1, "OpenFOAM result: %s: no internalField", path);
        goto out;
    }
    p += 13;
    while (*p == ' ')
        p++;
    if (!strncmp(p, "nonuniform", 10)) {
        p = strchr(p, '>'); /* List<...> */
        char *end;
        long cnt = p ? strtol(p + 1, &end, 10) : -1;
        if (cnt <= 0 || !(p = strchr(end, '('))) {
            rc = core_err_set(err, -1, "OpenFOAM result: %s: internalField not an ASCII list", path);
            goto out;
        }
        p++;
        double *v = malloc((size_t)cnt * ncomp * sizeof *v);
        if (!v) {
            rc = core_err_set(err, -2, "OpenFOAM result: out of memory");
            goto out;
        }
        for (long i = 0; i < cnt * ncomp; i++) {
            while (*p == ' ' || *p == '\n' || *p == '(' || *p == ')' || *p == '\t')
                p++;
            char *e2;
            v[i] = strtod(p, &e2);
            if (e2 == p) {
                free(v);
                rc = core_err_set(err, -1, "OpenFOAM result: %s: value %ld of %ld unreadable", path, i, cnt * ncomp);
                goto out;
            }
            p = e2;
        }
        *vals = v;
        *n = (size_t)cnt;
    } else {
        rc = core_err_set(err, -1, "OpenFOAM result: %s: internalField is not a list per cell", path);
    }
out:
    free(b);
    return rc;
}

/* Index of the centre nearest x among c[0..n-1] (increasing). */
static int nearest(const double *c, int n, double x)
{
    int lo = 0, hi = n - 1;
    while (hi - lo > 1) {
        int m = (lo + hi) / 2;
        if (c[m] <= x)
            lo = m;
        else
            hi = m;
    }
    return fabs(c[hi] - x) < fabs(c[lo] - x) ? hi : lo;
}

int foam_cell_index(const cfd_grid *g, const double xyz[3], size_t c, size_t *k, double *vol, core_err *err)
{
    int n[3], ijk[3];
    cfd_grid_dims(g, n);
    double v = 1.0;
    for (int d = 0; d < 3; d++) {
        const double *xc = cfd_grid_centres(g, d), *xn = cfd_grid_nodes(g, d);
        ijk[d] = nearest(xc, n[d], xyz[d]);
        double h = xn[ijk[d] + 1] - xn[ijk[d]];
        if (fabs(xyz[d] - xc[ijk[d]]) > 1e-4 * h)
            return core_err_set(err, -1,
                                "OpenFOAM result: cell %zu's centre (%g, %g, %g) is not one of disim's grid's "
                                "centres (axis %d off by %g m): the meshes differ",
                                c, xyz[0], xyz[1], xyz[2], d, xyz[d] - xc[ijk[d]]);
        v *= h;
    }
    *k = (size_t)ijk[0] + (size_t)n[0] * ((size_t)ijk[1] + (size_t)n[1] * (size_t)ijk[2]);
    if (vol)
        *vol = v;
    return 0;
}

int foam_read_fields(const char *case_dir, cfd_solver *s, size_t *cells, core_err *err)
{
    char t[256], p[1600];
    if (foam_latest_time(case_dir, t, sizeof t) != 0)
        return core_err_set(err, -1, "OpenFOAM result: %s has no time folder with a solution", case_dir);
    static const char *const names[] = {"C", "U", "p", "k", "epsilon", "nut"};
    static const int ncomp[] = {3, 3, 1, 1, 1, 1};
    double *v[6] = {0};
    size_t nv[6] = {0};
    int rc = 0;
    for (int q = 0; q < 6 && !rc; q++) {
        snprintf(p, sizeof p, "%s/%s/%s", case_dir, t, names[q]);
        rc = foam_read_internal(p, ncomp[q], &v[q], &nv[q], err);
        if (!rc && nv[q] != nv[0])
            rc = core_err_set(err, -1, "OpenFOAM result: %s: %zu cells, C has %zu", p, nv[q], nv[0]);
    }
    const cfd_grid *g = cfd_solver_grid(s);
    size_t nc = cfd_grid_cells(g);
    const unsigned char *solid = cfd_grid_solid(g);
    double *out[CFD_NVARS] = {0};
    unsigned char *hit = rc ? NULL : calloc(nc, 1);
    if (!rc && !hit)
        rc = core_err_set(err, -2, "OpenFOAM result: out of memory");
    for (int q = 0; q < CFD_NVARS && !rc; q++) {
        if (!(out[q] = malloc(nc * sizeof *out[q])))
            rc = core_err_set(err, -2, "OpenFOAM result: out of memory");
        else
            memcpy(out[q], cfd_solver_var(s, q), nc * sizeof *out[q]);
    }
    if (!rc && nv[0] != cfd_grid_fluid_cells(g))
        rc = core_err_set(err, -1, "OpenFOAM result: %zu cells, disim's grid has %zu fluid cells", nv[0],
                          cfd_grid_fluid_cells(g));
    const double rho = cfd_solver_config(s)->rho_kgpm3;
    for (size_t c = 0; c < nv[0] && !rc; c++) {
        size_t k;
        if ((rc = foam_cell_index(g, v[0] + 3 * c, c, &k, NULL, err)))
            break;
        if (solid[k] || hit[k]) {
            rc = core_err_set(err, -1, "OpenFOAM result: cell %zu lands on disim's cell %zu, %s", c, k,
                              solid[k] ? "a ship cell" : "already taken");
            break;
        }
        hit[k] = 1;
        for (int d = 0; d < 3; d++)
            out[CFD_VAR_U + d][k] = v[1][3 * c + d];
        out[CFD_VAR_P][k] = rho * v[2][c];
        out[CFD_VAR_K][k] = v[3][c];
        out[CFD_VAR_EPS][k] = v[4][c];
        out[CFD_VAR_NUT][k] = v[5][c];
    }
    for (int q = 0; q < CFD_NVARS && !rc; q++)
        cfd_solver_set_var(s, q, out[q]);
    if (!rc)
        *cells = nv[0];
    for (int q = 0; q < CFD_NVARS; q++)
        free(out[q]);
    for (int q = 0; q < 6; q++)
        free(v[q]);
    free(hit);
    return rc;
}
