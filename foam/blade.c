/* blade.c -- the OpenFOAM engine's blade-element rotor: OpenFOAM's
 * rotorDisk fvOption on a one-cell-thick disk of cells, trimmed by its
 * targetCoeff trim to the helicopter's thrust with no hub pitch or roll
 * moment.
 *
 * Model (OpenFOAM v1912's rotorDiskSource: rotorDiskSourceTemplates.C,
 * calculate(); its use for a helicopter's downwash: Wahono, "Development
 * of Virtual Blade Model for Modelling Helicopter Rotor Downwash in
 * OpenFOAM", DSTO-TR-2931, 2013): in each disk cell at radius r and
 * azimuth psi the local velocity, less its radial part, gives the blade's
 * in-plane speed U_t = Omega r - u_psi and the axial speed u_z; the angle
 * of attack is alpha = theta(r, psi) - atan2(-u_z, U_t) with
 * theta = theta0 + theta1c cos psi + theta1s sin psi + twist(r); cl and cd
 * come from the airfoil table; the cell's share of the N blades'
 * time-averaged load is dF = 1/2 rho |U|^2 c N A_cell / (2 pi r), cl dF
 * along the axis and -cd dF along psi, with no lift beyond tipEffect
 * r_max: blade-element theory (Leishman, "Principles of Helicopter
 * Aerodynamics", 2nd ed., 2006, chapter 3) summed cell by cell over the
 * disk. A_cell is the cell's face area normal to the axis, so the zone
 * must be one cell thick: the cells the disk's plane crosses, one per
 * grid column. The force on the air is minus the blades' load.
 *
 * Trim (targetCoeffTrim.C, correctTrim(), useCoeffs false): every
 * iteration (calcFrequency 1) Newton's method on (theta0, theta1c,
 * theta1s) with a finite-difference Jacobian, to a thrust of the spec's T
 * along the axis and no moment about the two in-plane axes, from the
 * theta0 of the hover collective that hfm_aircraft_figures estimates by
 * blade-element momentum theory.
 *
 * Assumptions: no coning or flapping (the disk is the spec's plane);
 * incompressible (rhoRef the config's density); the rotation: rotorDisk
 * turns the blades right-handed about its axis with the load along +axis,
 * so a counter-clockwise rotor (seen from above) takes the thrust
 * direction as its axis, and a clockwise one the opposite axis, a
 * target of -T and the blade mirrored (twist and theta negated, the
 * airfoil table as cl(-alpha) = -cl, cd(-alpha) = cd), which is the same
 * rotor seen in a mirror.
 */
#include "foam_private.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The radial stations of the blade table (root to tip). */
#define BLADE_STATIONS 11

size_t foam_blade_zone(const cfd_solver *s, const cfd_disk *d, double root_m, int *zone)
{
    const cfd_grid *g = cfd_solver_grid(s);
    const unsigned char *solid = cfd_grid_solid(g);
    int n[3];
    cfd_grid_dims(g, n);
    const double *xc = cfd_grid_centres(g, 0), *yc = cfd_grid_centres(g, 1), *zc = cfd_grid_centres(g, 2);
    const double *zn = cfd_grid_nodes(g, 2);
    size_t nc = cfd_grid_cells(g), used = 0;
    for (size_t c = 0; c < nc; c++)
        zone[c] = -1;
    const double *c0 = d->centre_m, *nv = d->normal;
    if (fabs(nv[2]) < 0.5) /* a disk tilted past 60 deg has no column to sit in */
        return 0;
    for (int j = 0; j < n[1]; j++)
        for (int i = 0; i < n[0]; i++) {
            /* where the disk's plane crosses this column */
            double zp = c0[2] - (nv[0] * (xc[i] - c0[0]) + nv[1] * (yc[j] - c0[1])) / nv[2];
            if (zp < zn[0] || zp >= zn[n[2]])
                continue;
            int k = 0;
            while (k + 1 < n[2] && zn[k + 1] <= zp)
                k++;
            double v[3] = {xc[i] - c0[0], yc[j] - c0[1], zc[k] - c0[2]};
            double ax = v[0] * nv[0] + v[1] * nv[1] + v[2] * nv[2], r2 = 0.0;
            for (int q = 0; q < 3; q++)
                r2 += (v[q] - ax * nv[q]) * (v[q] - ax * nv[q]);
            double r = sqrt(r2);
            size_t cell = (size_t)i + (size_t)n[0] * ((size_t)j + (size_t)n[1] * (size_t)k);
            if (r < root_m || r > d->radius_m || solid[cell])
                continue;
            zone[cell] = 0;
            used++;
        }
    return used;
}

static void vec(FILE *f, const char *key, const double v[3], double sign)
{
    fprintf(f, "    %s (%.12g %.12g %.12g);\n", key, sign * v[0], sign * v[1], sign * v[2]);
}

void foam_blade_options(FILE *f, const char *zone, const cfd_disk *d, const hfm_blade_data *b, double rho)
{
    /* the mirror for a clockwise rotor (see the top of the file) */
    double m = d->ccw_from_above ? 1.0 : -1.0;
    fprintf(f, "rotor\n{\n    type rotorDisk;\n    active yes;\n    selectionMode cellZone;\n    cellZone %s;\n", zone);
    fprintf(f, "    fields (U);\n    rhoRef %.12g;\n    rpm %.12g;\n    nBlades %d;\n    inletFlowType local;\n", rho,
            b->omega_radps * 60.0 / (2.0 * CORE_PI), b->blades);
    fprintf(f, "    geometryMode specified;\n");
    vec(f, "origin", d->centre_m, 1.0);
    vec(f, "axis", d->normal, m);
    vec(f, "refDirection", d->ref, 1.0);
    fprintf(f, "    tipEffect %.12g;\n    flapCoeffs\n    {\n        beta0 0;\n        beta1c 0;\n        beta2s 0;\n    }\n",
            b->tip_loss);
    fprintf(f,
            "    trimModel targetCoeffTrim;\n    targetCoeffTrimCoeffs\n    {\n        calcFrequency 1;\n"
            "        target\n        {\n            useCoeffs false;\n            thrust %.12g;\n            pitch 0;\n"
            "            roll 0;\n        }\n        pitchAngles\n        {\n            theta0Ini %.12g;\n"
            "            theta1cIni 0;\n            theta1sIni 0;\n        }\n        nIter 50;\n        tol 1e-8;\n"
            "        relax 1;\n        dTheta 0.1;\n        alpha 1;\n    }\n",
            m * d->thrust_N, m * b->hover_pitch0_rad * CORE_RAD_TO_DEG);
    fprintf(f, "    blade\n    {\n        data\n        (\n");
    for (int i = 0; i < BLADE_STATIONS; i++) {
        double r = b->root_cutout_m + (b->radius_m - b->root_cutout_m) * i / (BLADE_STATIONS - 1);
        double tw = b->twist_rad * (r / b->radius_m - b->twist_ref) * CORE_RAD_TO_DEG;
        fprintf(f, "            (airfoil (%.12g %.12g %.12g))\n", r, m * tw, b->chord_m);
    }
    fprintf(f, "        );\n    }\n    profiles\n    {\n        airfoil\n        {\n            type lookup;\n"
               "            data\n            (\n");
    for (int q = 0; q < HFM_BLADE_NALPHA; q++) {
        int i = d->ccw_from_above ? q : HFM_BLADE_NALPHA - 1 - q;
        fprintf(f, "                (%.12g %.12g %.12g)\n", m * b->alpha_deg[i], b->cd[i], m * b->cl[i]);
    }
    fprintf(f, "            );\n        }\n    }\n}\n\n");
}

/* The last value after key in text (NAN when absent). */
static double last_value(const char *text, const char *key)
{
    const char *p = NULL, *q = text;
    while ((q = strstr(q, key)))
        p = q++;
    return p ? strtod(p + strlen(key), NULL) : NAN;
}

int foam_blade_result(const char *case_dir, const char *time_dir, const cfd_solver *s, const cfd_disk *d,
                      foam_result *res, core_err *err)
{
    double m = d->ccw_from_above ? 1.0 : -1.0;
    char p[1600];
    snprintf(p, sizeof p, "%s/log.simpleFoam", case_dir);
    char *log = foam_slurp(p, NULL);
    if (!log)
        return core_err_set(err, -1, "OpenFOAM result: %s cannot be read", p);
    /* the trim's last report: "thrust  = CURRENT, TARGET" and the angles */
    const char *blk = NULL, *q = log;
    while ((q = strstr(q, "current and target forces")))
        blk = q++;
    int rc = 0;
    if (!blk) {
        rc = core_err_set(err, -1, "OpenFOAM step simpleFoam: %s has no report of rotorDisk's trim", p);
    } else {
        res->trim_thrust_N = m * last_value(blk, "thrust  = ");
        res->trim_pitch_deg[0] = m * last_value(blk, "theta0  = ");
        res->trim_pitch_deg[1] = m * last_value(blk, "theta1c = ");
        res->trim_pitch_deg[2] = m * last_value(blk, "theta1s = ");
        /* the report before the block says whether Newton's method converged */
        const char *nc = NULL;
        for (q = log; (q = strstr(q, "solution not converged")) && q < blk; q++)
            nc = q;
        const char *ok = NULL;
        for (q = log; (q = strstr(q, "final residual = ")) && q < blk; q++)
            ok = q;
        res->trim_converged = ok && (!nc || nc < ok);
    }
    free(log);
    if (rc)
        return rc;
    /* the force field rotorDisk writes at the last time: the blades' load per
     * unit volume over rho; the thrust is its sum along the thrust direction */
    snprintf(p, sizeof p, "%s/%s/rotor:rotorForce", case_dir, time_dir);
    double *fv = NULL, *cv = NULL;
    size_t nf = 0, ncn = 0;
    rc = foam_read_internal(p, 3, &fv, &nf, err);
    snprintf(p, sizeof p, "%s/%s/C", case_dir, time_dir);
    if (!rc)
        rc = foam_read_internal(p, 3, &cv, &ncn, err);
    if (!rc && nf != ncn)
        rc = core_err_set(err, -1, "OpenFOAM result: rotor:rotorForce has %zu cells, C %zu", nf, ncn);
    const cfd_grid *g = cfd_solver_grid(s);
    const double rho = cfd_solver_config(s)->rho_kgpm3;
    double t = 0.0, torque = 0.0;
    size_t loaded = 0;
    for (size_t c = 0; c < nf && !rc; c++) {
        const double *fc = fv + 3 * c;
        double fn = fc[0] * d->normal[0] + fc[1] * d->normal[1] + fc[2] * d->normal[2];
        if (fc[0] == 0.0 && fc[1] == 0.0 && fc[2] == 0.0)
            continue;
        size_t k;
        double vol;
        if ((rc = foam_cell_index(g, cv + 3 * c, c, &k, &vol, err)))
            break;
        t += rho * fn * vol;
        /* the air's share, -f, about the thrust direction through the hub */
        const double *x = cv + 3 * c, *o = d->centre_m, *nv = d->normal;
        double r[3] = {x[0] - o[0], x[1] - o[1], x[2] - o[2]};
        double mx = r[1] * fc[2] - r[2] * fc[1], my = r[2] * fc[0] - r[0] * fc[2], mz = r[0] * fc[1] - r[1] * fc[0];
        torque -= rho * (mx * nv[0] + my * nv[1] + mz * nv[2]) * vol;
        loaded++;
    }
    free(fv);
    free(cv);
    if (!rc && loaded == 0)
        rc = core_err_set(err, -1, "OpenFOAM result: rotorDisk put no force into any cell");
    if (!rc) {
        res->rotor_force_N = t;
        res->rotor_torque_Nm = d->ccw_from_above ? torque : -torque;
        res->rotor_cells = loaded;
    }
    return rc;
}
