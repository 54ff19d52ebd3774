/*
 * airwake.c -- a ship airwake case: grid, boundaries, inflow and monitors
 * from a ship, a wind over deck and an optional rotor.
 *
 * Model: the seed paper's section 2.6 set-up, scaled down: a box around the
 * ship with the sea as a no-slip wall (wall functions), a symmetry top, a
 * velocity inlet on each side face the wind enters through and a pressure
 * outlet on each face it leaves through (a face the wind is nearly parallel
 * to, |component| < 5 % of the speed, is a symmetry plane), so the ship stays
 * aligned with the grid for every WOD direction. Domain: 1 L upstream,
 * 1.25 L downstream (L: ship length), +-0.6 L across (on the lee side
 * max(0.6 L, 1.25 L |V_y| / U), so a crosswind wake is as far from its
 * outlet as a headwind one), max(0.5 L, 5 H)
 * high (H: the ship's highest point above the sea), against the seed
 * paper's 4 L / 6 L / +-0.97 L / 1.5 L; the grid study (docs/validation/
 * cfd.md) is the check that the deck region does not feel the difference.
 * The fine-spacing box (the seed paper's mesh density box) covers the
 * flight deck, half a deck length (at most 12 m) aft of the stern, the
 * hangar face and 0.3 deck lengths (at most 8 m) over the hangar roof, and
 * two hangar heights above the deck; cells grow by 12 % per cell outside.
 *
 * Deck zone (spec.zone, a coupled point's fields): the domain shrinks to
 * the rotor's reach (5 R across and along, 4 R above the hub, as the
 * whole domain's open faces are placed) and its open faces take the
 * ship-only field of the same direction, scaled with the wind speed, as a
 * Dirichlet condition where air enters or runs along (a one-way nested,
 * or zonal, boundary; not in the seed paper, which solves the coupled case
 * in its whole domain, section 2.6). Assumptions:
 * the rotor's effect on the air at the zone's inflow faces is small (it is
 * set to zero there), and the ship-only field scales with speed (the one-way
 * coupling's assumption). The isolated rotor of the same key takes the same
 * zone and faces with the inflow profile, so that the boundary's effect
 * largely cancels in the interaction velocity. The trim-level check
 * against the whole domain is in docs/shol.md ("deck zone").
 */
#include "cfd_private.h"

#include <math.h>
#include <string.h>

typedef struct ship_box {
    double x0, x1, y0, y1, ztop, zsea, hangar_top;
} ship_box;

/* The zone's open faces: the ship-only field scaled to the WOD speed. */
static int zone_sample(void *user, const double pos[3], double out[5])
{
    const cfd_airwake_spec *sp = user;
    double v[CFD_NVARS], f = sp->zone_scale;
    cfd_field_sample(sp->zone_field, pos, v);
    for (int d = 0; d < 3; d++)
        out[d] = f * v[CFD_VAR_U + d];
    out[3] = f * f * v[CFD_VAR_K];
    out[4] = f * f * f * v[CFD_VAR_EPS];
    return 0;
}

static void ship_bounds(const core_ship *sh, ship_box *b)
{
    b->x0 = b->y0 = b->ztop = 1e300;
    b->x1 = b->y1 = -1e300;
    b->hangar_top = 0.0;
    for (int i = 0; i < sh->nblocks; i++) {
        const core_ship_block *k = &sh->blocks[i];
        b->x0 = fmin(b->x0, k->x0_m);
        b->x1 = fmax(b->x1, k->x1_m);
        b->y0 = fmin(b->y0, k->y0_m);
        b->y1 = fmax(b->y1, k->y1_m);
        b->ztop = fmin(b->ztop, k->z0_m);
        /* the block standing on the forward end of the flight deck */
        if (k->x0_m <= sh->deck_x1_m + 1.0 && k->x1_m > sh->deck_x1_m + 1.0 && k->z0_m < b->hangar_top)
            b->hangar_top = k->z0_m;
    }
    b->zsea = sh->deck_height_m;
    if (b->hangar_top >= 0.0)
        b->hangar_top = -5.0;
}

cfd_solver *cfd_airwake_create(const cfd_airwake_spec *sp, const core_log *log, cfd_progress_fn progress,
                               void *progress_user, core_err *err)
{
    const core_ship *sh = sp->ship;
    /* zero wind over deck is a case only with the rotor: its wake is the
     * flow (a hover in calm air over the deck) */
    const int calm = sp->rotor && sp->wod_speed_mps == 0.0 && sp->disk.thrust_N > 0.0 && sp->disk.radius_m > 0.0;
    if (sp->zone && (calm || !(sp->disk.radius_m > 0.0) || !(sp->wod_speed_mps > 0.0) ||
                     (sp->zone_field && !(sp->zone_scale > 0.0)))) {
        core_err_set(err, -1,
                     "cfd airwake: a deck zone needs a rotor radius and centre (disk), a wind (got %g m/s) and, "
                     "with an outer field, a scale > 0",
                     sp->wod_speed_mps);
        return NULL;
    }
    if (!sh || sh->nblocks < 1 || !(sp->wod_speed_mps > 0.0 || calm) || core_grid_rank(sp->level) < 0) {
        core_err_set(err, -1,
                     "cfd airwake: expected a ship, a WOD speed > 0 (or 0 with a loaded rotor) and a grid level "
                     "(got %g m/s)",
                     sp->wod_speed_mps);
        return NULL;
    }
    ship_box b;
    ship_bounds(sh, &b);
    double L = b.x1 - b.x0, H = b.zsea - b.ztop;
    double U = sp->wod_speed_mps;
    core_vec3 V = core_wod_vel_S_mps(U, sp->wod_dir_rad);
    /* the ideal hover induced velocity sqrt(T / (2 rho A)) */
    const double vh = sp->rotor ? cfd_disk_hover_vi_mps(&sp->disk, CORE_RHO_SL_KGPM3) : 0.0;
    /* a wind slower than the rotor's induced velocity: the rotor's wake is most of the flow */
    const int rotor_dominated = !calm && U < vh;
    if (calm) /* the reference speed */
        U = vh;
    /* coarse, default, fine, quick (twice the coarse spacing: the first
     * look a flight gets, docs/usage.md) */
    static const double hfine[4] = {1.1, 0.55, 0.43, 2.2};
    static const double hmax[4] = {12.0, 6.0, 5.0, 24.0};
    double hf = sp->h_fine_m > 0.0 ? sp->h_fine_m : hfine[sp->level];
    double deck = sh->deck_x1_m - sh->deck_x0_m;
    double hh = -b.hangar_top; /* hangar height above the deck */
    cfd_axis_spec ax[3];
    /* the wake side gets the longer reach */
    double up = 1.0 * L, down = 1.25 * L;
    ax[0].lo_m = b.x0 - (V.x <= 0.0 ? down : up);
    ax[0].hi_m = b.x1 + (V.x <= 0.0 ? up : down);
    /* half a deck length aft of the stern and 0.3 of it over the hangar,
     * capped at 12 m and 8 m: a 70 m deck (LPD-17) needs the wake behind
     * its stern no further than a 24 m one does (the hangar step and the
     * rotor set the scale, not the deck length), and the cap keeps its
     * coarse grid near a million cells */
    ax[0].f0_m = sh->deck_x0_m - fmin(0.5 * deck, 12.0);
    ax[0].f1_m = sh->deck_x1_m + (sp->focus_fwd_m > 0.0 ? sp->focus_fwd_m : fmin(0.3 * deck, 8.0));
    /* across: +-0.6 L, and on the lee side in a crosswind the along-wind
     * reach scaled by the crosswind component (a crosswind wake must not
     * reach the outlet: backflow there fed the CG-47 red 90 divergence) */
    double lee_y = fmax(0.6 * L, down * fabs(V.y) / U);
    ax[1].lo_m = V.y < 0.0 ? -lee_y : -0.6 * L;
    ax[1].hi_m = V.y > 0.0 ? lee_y : 0.6 * L;
    ax[1].f0_m = b.y0 - 0.5 * (b.y1 - b.y0) * 0.5;
    ax[1].f1_m = b.y1 + 0.5 * (b.y1 - b.y0) * 0.5;
    ax[2].lo_m = b.zsea - fmax(0.5 * L, 5.0 * H);
    ax[2].hi_m = b.zsea;
    ax[2].f0_m = fmin(-2.0 * hh, sp->monitor_z_m - 0.5 * hh);
    ax[2].f1_m = b.zsea;
    if ((sp->rotor || sp->zone) && sp->disk.radius_m > 0.0) {
        /* room for the rotor's wake: open faces at least 5 R from the hub
         * across and 4 R above it (as the hover validation case, whose far
         * wake is within 10 % of momentum theory) */
        const double R = sp->disk.radius_m, *c = sp->disk.centre_m;
        ax[0].lo_m = fmin(ax[0].lo_m, c[0] - 5.0 * R);
        ax[0].hi_m = fmax(ax[0].hi_m, c[0] + 5.0 * R);
        ax[1].lo_m = fmin(ax[1].lo_m, c[1] - 5.0 * R);
        ax[1].hi_m = fmax(ax[1].hi_m, c[1] + 5.0 * R);
        ax[2].lo_m = fmin(ax[2].lo_m, c[2] - 4.0 * R);
        if (sp->zone) {
            /* the deck zone: the same reach from the hub, and no more (the
             * fine box is clipped to it by the axis builder) */
            ax[0].lo_m = c[0] - 5.0 * R;
            ax[0].hi_m = c[0] + 5.0 * R;
            ax[1].lo_m = c[1] - 5.0 * R;
            ax[1].hi_m = c[1] + 5.0 * R;
            ax[2].lo_m = c[2] - 4.0 * R;
        }
    }
    for (int d = 0; d < 3; d++) {
        ax[d].h_fine_m = hf;
        ax[d].h_max_m = sp->h_max_m > 0.0 ? fmax(sp->h_max_m, hf) : fmax(hmax[sp->level], 4.0 * hf);
        ax[d].growth = sp->growth > 1.0 ? sp->growth : CFD_GRID_GROWTH;
    }
    cfd_grid *g = cfd_grid_create_spec(ax, err);
    if (!g)
        return NULL;
    size_t nsolid = sp->open_ship ? 0 : cfd_grid_block_ship(g, sh);
    cfd_config cfg;
    cfd_config_default(&cfg);
    cfg.turbulence = 1;
    cfg.u_ref_mps = U;
    cfg.max_iter = sp->max_iter > 0 ? sp->max_iter : 3000;
    /* a field that does not converge (crosswinds over a tall
     * superstructure, the finest grids) is the mean of its last quarter of
     * iterations, at most 200, not a snapshot of its limit cycle */
    cfg.avg_window = cfg.max_iter / 4 < 200 ? cfg.max_iter / 4 : 200;
    if (sp->avg_window > 0)
        cfg.avg_window = sp->avg_window < cfg.max_iter ? sp->avg_window : cfg.max_iter;
    /* ... and, once the residuals cannot reach the tolerance by the cap,
     * stops at the first window whose mean is steady at the deck monitors,
     * its halves and the window before it agreeing
     * (solver 0.4.0, halves only: CG-47 default grid head after 300 iterations, red 90 after 450;
     * coupled zone fields' means still moved 10-20 % of U at 600, so they
     * run to the cap; docs/validation/cfd.md) */
    cfg.avg_stop = 1;
    /* the OpenFOAM engine's test alone, and its last iterate */
    if (sp->monitor_stop) {
        cfg.monitor_stop = 1;
        cfg.avg_window = 0;
        cfg.avg_stop = 0;
    }
    /* a larger pseudo-time step than the generic 0.7: the transients of a
     * ship airwake (the rotor wake's ground vortex settling behind the
     * stern) die out in fewer iterations (SFS2 coarse with the rotor: 435
     * iterations at 0.85 against 616 at 0.7 and > 1000 at 0.5) */
    cfg.relax_u = 0.85;
    /* On grids finer than about 1 m the hangar-edge shear layers of a 0 deg
     * wind shed in the pseudo-time of the iteration: the largest mass
     * imbalance alternates between the two deck edges just aft of the
     * hangar and the residuals stall at 1e-1 (SFS2, 0.55 m, u 0.85, van
     * Leer). The most diffusive TVD limiter and a smaller pseudo-time step
     * damp it (u 0.5: 1.5e-3 after 700 iterations); with Anderson
     * acceleration (below) the larger step u 0.7 is stable again and
     * converges faster (after 600 iterations: continuity 3.4e-4 at u 0.7
     * with depth 8, 8.1e-4 with depth 5, 2.9e-3 at u 0.85;
     * docs/validation/cfd.md) */
    if (hf < 1.0) {
        cfg.relax_u = 0.7;
        cfg.limiter = CFD_LIMITER_MINMOD;
    }
    if (sp->limiter_fixed)
        cfg.limiter = sp->limiter;
    /* On every ship grid Anderson starts where the residuals stall (the
     * default grid from about iteration 100; SFS2 green 30 on the coarse
     * grid: converged in 351 iterations instead of a 7e-2 stall), and
     * leaves alone a run that converges by itself (on the coarse grid at 0
     * deg Anderson from the start took 4 times the plain 435 iterations).
     * Depth 8: the most within 1 kB per cell. */
    cfg.accel_depth = 8;
    cfg.accel_start = 60;
    cfg.accel_when_stalled = 1;
    /* a hover in calm air diverged at 0.85 and converged at 0.5 (a flat
     * deck, coarse grid); so did the UH-60A over the CG-47 in a 1.4 m/s
     * beam wind (its induced velocity is 10 m/s), which converged on the
     * retry at 0.51. The relaxation changes the path, not the solution. */
    if (calm || rotor_dominated)
        cfg.relax_u = 0.5;
    cfg.log = log;
    cfg.progress = progress;
    cfg.progress_user = progress_user;
    /* a face is an inlet or outlet where the wind's component across it
     * exceeds 5 % of the speed, else a symmetry plane (core_wod_faces; the
     * airwake database chooses warm starts by the same rule) */
    int fsign[2];
    core_wod_faces(sp->wod_speed_mps, sp->wod_dir_rad, fsign);
    for (int d = 0; d < 2; d++) {
        int fmin_ = 2 * d, fmax_ = 2 * d + 1;
        if (fsign[d] < 0) {
            cfg.bc[fmax_].type = CFD_BC_INLET;
            cfg.bc[fmin_].type = CFD_BC_OUTLET;
        } else if (fsign[d] > 0) {
            cfg.bc[fmin_].type = CFD_BC_INLET;
            cfg.bc[fmax_].type = CFD_BC_OUTLET;
        } else {
            cfg.bc[fmin_].type = CFD_BC_SYMMETRY;
            cfg.bc[fmax_].type = CFD_BC_SYMMETRY;
        }
    }
    cfg.bc[CFD_ZMIN].type = CFD_BC_SYMMETRY;
    if (calm) /* no wind: every face but the sea is open (total pressure 0 where air comes in) */
        for (int f = 0; f < CFD_NFACES; f++)
            cfg.bc[f].type = CFD_BC_OUTLET;
    if (sp->zone) {
        /* a zone's faces along the wind and its top are fixed to the outer
         * field: its air crosses them (the superstructure's up- and
         * downwash, a wake's sideways spread) */
        for (int f = 0; f < CFD_NFACES; f++)
            if (cfg.bc[f].type == CFD_BC_SYMMETRY)
                cfg.bc[f].type = CFD_BC_INLET;
    }
    cfg.bc[CFD_ZMAX].type = CFD_BC_WALL; /* the sea */
    cfg.inflow.type = sp->abl ? CFD_INFLOW_ABL : CFD_INFLOW_UNIFORM;
    cfg.inflow.vel_mps[0] = V.x;
    cfg.inflow.vel_mps[1] = V.y;
    cfg.inflow.vel_mps[2] = 0.0;
    cfg.inflow.ground_axis = 2;
    cfg.inflow.ground_sign = 1;
    cfg.inflow.ground_coord_m = b.zsea;
    cfg.inflow.z_ref_m = fmax(b.zsea - sh->anemometer_S_m[2], 1.0);
    cfg.inflow.z0_m = 2e-4;
    cfg.inflow.intensity = 0.02;
    cfg.inflow.length_m = 0.1 * H;
    if (sp->zone && sp->zone_field) {
        cfg.inflow.type = CFD_INFLOW_FIELD;
        cfg.inflow.fn = zone_sample;
        cfg.inflow.fn_user = (void *)sp;
    }
    cfg.n_monitor = 4;
    for (int m = 0; m < 4; m++) {
        cfg.monitor_m[m][0] = sh->deck_x0_m + (m + 0.5) / 4.0 * deck;
        cfg.monitor_m[m][1] = 0.0;
        cfg.monitor_m[m][2] = sp->monitor_z_m;
    }
    int n[3];
    cfd_grid_dims(g, n);
    core_log_msg(log, CORE_LOG_INFO,
                 "cfd airwake: %s, WOD %.1f m/s from %.1f deg, %s %d x %d x %d = %zu cells (%zu in the ship), "
                 "h_fine %.2f m",
                 sh->name, U, sp->wod_dir_rad * CORE_RAD_TO_DEG, sp->zone ? "deck zone" : "grid", n[0], n[1], n[2],
                 cfd_grid_cells(g), nsolid, hf);
    cfd_solver *s = cfd_solver_create(g, &cfg, err);
    if (!s)
        return NULL;
    if (sp->rotor && cfd_solver_set_disk(s, &sp->disk, err)) {
        cfd_solver_destroy(s);
        return NULL;
    }
    return s;
}

int cfd_airwake_reattachment(const cfd_solver *s, const core_ship *ship, double wod_dir_rad, double y_m,
                             double z_m, double *len_m)
{
    core_vec3 w = core_wod_vel_S_mps(1.0, wod_dir_rad);
    double xh = ship->deck_x1_m;
    double step = 0.05;
    int reversed = 0;
    *len_m = 0.0;
    double prev = 0.0;
    for (double dx = 0.25; dx < 3.0 * (ship->deck_x1_m - ship->deck_x0_m); dx += step) {
        double pos[3] = {xh - dx, y_m, z_m}, out[CFD_NVARS];
        cfd_solver_sample(s, pos, out);
        double along = out[0] * w.x + out[1] * w.y;
        if (along < 0.0)
            reversed = 1;
        else if (reversed) {
            /* linear interpolation of the zero crossing */
            double f = prev / (prev - along);
            *len_m = dx - step + f * step;
            return 0;
        } else if (dx > 2.0) {
            return 0; /* no reversed flow next to the hangar */
        }
        prev = along;
    }
    *len_m = reversed ? 3.0 * (ship->deck_x1_m - ship->deck_x0_m) : 0.0;
    return reversed ? 1 : 0;
}

static void flow_sample(const cfd_flow *f, const double p[3], double out[CFD_NVARS])
{
    if (f->solver)
        cfd_solver_sample(f->solver, p, out);
    else
        cfd_field_sample(f->field, p, out);
}

void cfd_airwake_deck_diff(const core_ship *ship, const cfd_flow *a, const cfd_flow *b, double u_ref_mps,
                           cfd_deck_diff *out)
{
    static const double ys[3] = {-3.4, 0.0, 3.4}, zs[3] = {-3.8, -6.8, -10.0};
    memset(out, 0, sizeof *out);
    double sum2 = 0.0;
    int np = 0;
    for (int ia = 0; ia < 3; ia++)
        for (int ib = 0; ib < 3; ib++) {
            const int l = 3 * ia + ib;
            out->line_y_m[l] = ys[ia];
            out->line_z_m[l] = zs[ib];
            for (int i = 0; i < CFD_DECK_LINE_POINTS; i++) {
                double p[3] = {ship->deck_x0_m + (ship->deck_x1_m - ship->deck_x0_m) * i / (CFD_DECK_LINE_POINTS - 1.0),
                               ys[ia], zs[ib]};
                double va[CFD_NVARS], vb[CFD_NVARS], d2 = 0.0;
                flow_sample(a, p, va);
                flow_sample(b, p, vb);
                for (int d = 0; d < 3; d++)
                    d2 += (va[d] - vb[d]) * (va[d] - vb[d]);
                double dn = sqrt(d2) / u_ref_mps;
                sum2 += dn * dn;
                np++;
                if (dn > out->line_worst[l]) {
                    out->line_worst[l] = dn;
                    out->line_worst_x_m[l] = p[0];
                }
                if (dn > out->worst) {
                    out->worst = dn;
                    memcpy(out->worst_at_m, p, sizeof p);
                }
            }
        }
    out->rms = sqrt(sum2 / np);
}
