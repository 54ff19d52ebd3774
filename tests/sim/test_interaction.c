/* test_interaction.c -- the coupled rotor interaction near the rotor
 * station in the flight loop's air (sim/interaction.c through sim/air.c).
 * A synthetic coupled / isolated / ship-only triple, built in the test on
 * a 2 m grid, each field linear in x and y (which trilinear interpolation
 * and the disk's modal fit reproduce to rounding), so that the difference
 * is known: coupled - isolated = (ship-only - wind) + I. Checks: at the
 * station the loop's air is ship-only + I, on and off the disk; away from
 * the station the fade's weight, back to the ship-only air beyond it; the
 * air's change per step while the rotor moves through the fade is within
 * the fade's bound; the thrust's factor and lag; the status flag; bad
 * pairs refused. With the coupling library: the loop's trimmed hover with
 * the interaction matches the coupling's trim in the same fields
 * (couple/interaction.c's air). Run from the source root. */
#include "cfd.h"
#include "check.h"
#include "hfm.h"
#include "sim.h"
#ifdef DISIM_TEST_COUPLE
#include "couple_priv.h"
#endif
#include "awdb.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define UH60 "scenarios/aircraft/uh60a.ini"
#define SHIP "scenarios/ships/sfs2.ini"

static const double WOD_MPS = 10.0; /* from the bow: wind (-10, 0, 0) in S */
static const double R_M = 8.18;     /* the UH-60A's rotor radius */

/* v(x, y) = c0 + gx x + gy y (each component), + q r^2 with r the
 * distance from the z axis (q = 0 but in the coupling's check: trilinear
 * interpolation and the modes do not reproduce it) */
typedef struct lin {
    double c0[3], gx[3], gy[3], q[3];
} lin;

static void lin_at(const lin *L, const double p[3], double v[3])
{
    for (int k = 0; k < 3; k++)
        v[k] = L->c0[k] + L->gx[k] * p[0] + L->gy[k] * p[1] + L->q[k] * (p[0] * p[0] + p[1] * p[1]);
}

static lin lin_sum(const lin *a, const lin *b, double sb)
{
    lin s;
    for (int k = 0; k < 3; k++) {
        s.c0[k] = a->c0[k] + sb * b->c0[k];
        s.gx[k] = a->gx[k] + sb * b->gx[k];
        s.gy[k] = a->gy[k] + sb * b->gy[k];
        s.q[k] = a->q[k] + sb * b->q[k];
    }
    return s;
}

static int lin_inflow(void *user, const double pos[3], double out[5])
{
    lin_at(user, pos, out);
    out[3] = 0.5;  /* k */
    out[4] = 0.05; /* epsilon */
    return 0;
}

/* Write a field holding L at every cell to path (the solver's initial
 * state from a sampled inflow, written without a run). 0, or -1 with err. */
static double box_m = 40.0; /* the fields' half width: 40 m, a deck zone's 20 m */

static int write_field(lin *L, const cfd_meta *meta, const char *path, core_err *err)
{
    cfd_axis_spec ax[3] = {{-box_m, box_m, 0, 0, 2.0, 2.0, 1.0}, {-box_m, box_m, 0, 0, 2.0, 2.0, 1.0},
                           {-30, 2, 0, 0, 2.0, 2.0, 1.0}};
    cfd_config cfg;
    cfd_config_default(&cfg);
    cfg.u_ref_mps = WOD_MPS;
    cfg.max_iter = 1;
    cfg.bc[CFD_XMAX].type = CFD_BC_INLET;
    cfg.bc[CFD_XMIN].type = CFD_BC_OUTLET;
    cfg.inflow.type = CFD_INFLOW_FIELD;
    cfg.inflow.fn = lin_inflow;
    cfg.inflow.fn_user = L;
    cfd_solver *s = cfd_solver_create(cfd_grid_create_spec(ax, err), &cfg, err);
    if (!s)
        return -1;
    cfd_solver_init_inflow(s);
    int rc = cfd_solver_write(s, meta, path, err);
    cfd_solver_destroy(s);
    return rc;
}

/* A field holding L at every cell, loaded (the file removed). */
static cfd_field *make_field(lin *L, const char *rotor, double thrust_N, const double hub[3], const char *tag)
{
    core_err err = {0};
    cfd_meta meta;
    memset(&meta, 0, sizeof meta);
    meta.wod_speed_mps = WOD_MPS;
    meta.wod_dir_deg = 0.0;
    snprintf(meta.ship, sizeof meta.ship, "test");
    snprintf(meta.rotor, sizeof meta.rotor, "%s", rotor);
    snprintf(meta.grid, sizeof meta.grid, "h2.000 m");
    meta.rotor_thrust_N = thrust_N;
    meta.rotor_radius_m = strcmp(rotor, "off") ? R_M : 0.0;
    if (hub)
        memcpy(meta.rotor_centre_S_m, hub, sizeof meta.rotor_centre_S_m);
    char path[256], xmf[300];
    snprintf(path, sizeof path, "/tmp/disim_test_interaction_%ld_%s.h5", (long)getpid(), tag);
    cfd_field *f = write_field(L, &meta, path, &err) == 0 ? cfd_field_load(path, &err) : NULL;
    if (!f)
        fprintf(stderr, "field %s: %s\n", tag, err.msg);
    unlink(path);
    snprintf(xmf, sizeof xmf, "%s.xmf", path);
    unlink(xmf);
    snprintf(xmf, sizeof xmf, "/tmp/disim_test_interaction_%ld_%s.xmf", (long)getpid(), tag);
    unlink(xmf);
    return f;
}

/* The fields of the test: the ship-only airwake S = wind + A, the
 * isolated rotor's i = wind + Rr (its own slipstream), the coupled c =
 * wind + A + Rr + I; the interaction is I. A deck-zone pair (zone 1): c
 * and i over the zone (20 m round the spot), c with the zone's own
 * version of the airwake, wind + Az + Rr + I, and the zone's ship-only
 * field Sz = wind + Az. */
typedef struct triple {
    lin S, iso, cpl, I, Sz;
    cfd_field *fs, *fi, *fc, *fsz;
    double hub[3], station[3], thrust_N;
} triple;

static int triple_make(triple *t, double thrust_N, const double hub[3], const double station[3], double q_w, int zone)
{
    memset(t, 0, sizeof *t);
    lin wind = {{-WOD_MPS, 0, 0}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    lin A = {{2.0, 0.6, 0.4}, {0.03, -0.01, 0.02}, {0.01, 0.04, -0.015}, {0, 0, 0}}; /* the ship's airwake */
    lin Rr = {{0.2, -0.1, 9.0}, {0.05, 0.0, -0.02}, {0.0, 0.03, 0.01}, {0, 0, 0}};  /* the rotor's own downwash */
    /* upwash off the deck, q_w r^2 less of it toward the tips */
    t->I = (lin){{0.4, -0.3, -1.6}, {0.01, 0.02, -0.03}, {-0.02, 0.01, 0.025}, {0, 0, q_w}};
    t->S = lin_sum(&wind, &A, 1.0);
    t->iso = lin_sum(&wind, &Rr, 1.0);
    lin sr = lin_sum(&t->S, &Rr, 1.0);
    t->cpl = lin_sum(&sr, &t->I, 1.0);
    memcpy(t->hub, hub, sizeof t->hub);
    memcpy(t->station, station, sizeof t->station);
    t->thrust_N = thrust_N;
    t->fs = make_field(&t->S, "off", 0.0, NULL, "ship");
    if (zone) {
        lin Az = {{-1.5, 0.9, -0.7}, {-0.02, 0.03, 0.01}, {0.02, -0.01, 0.03}, {0, 0, 0}}; /* the zone's airwake */
        t->Sz = lin_sum(&wind, &Az, 1.0);
        lin szr = lin_sum(&t->Sz, &Rr, 1.0);
        t->cpl = lin_sum(&szr, &t->I, 1.0);
        box_m = 20.0;
        t->fsz = make_field(&t->Sz, "off", 0.0, NULL, "zone");
    }
    t->fi = make_field(&t->iso, "loaded", thrust_N, hub, "isolated");
    t->fc = make_field(&t->cpl, "loaded", thrust_N, hub, "coupled");
    box_m = 40.0;
    return t->fs && t->fi && t->fc && (!zone || t->fsz) ? 0 : -1;
}

static void triple_free(triple *t)
{
    cfd_field_destroy(t->fs);
    cfd_field_destroy(t->fi);
    cfd_field_destroy(t->fc);
    cfd_field_destroy(t->fsz);
}

static sim_air *make_air(const triple *t, core_err *err)
{
    sim_air_opts ao;
    sim_air_opts_default(&ao);
    ao.wod_speed_mps = WOD_MPS;
    ao.deck_height_m = 10.0;
    sim_air *a = sim_air_create(&ao, err);
    if (a && sim_air_set_field(a, t->fs, -INFINITY, err) != 0) {
        sim_air_destroy(a);
        return NULL;
    }
    return a;
}

static sim_interaction *make_inter(const triple *t, core_err *err)
{
    sim_interaction_opts io;
    sim_interaction_opts_default(&io);
    memcpy(io.station_S_m, t->station, sizeof io.station_S_m);
    if (t->fsz) {
        io.ship_whole = t->fs;
        io.ship_zone = t->fsz;
    }
    return sim_interaction_create(t->fc, t->fi, &io, err);
}

/* The fade's weight as the file header states it (d_in 0.25 R, over R). */
static double weight_of(double d)
{
    double s = (d - 0.25 * R_M) / R_M;
    s = fmin(fmax(s, 0.0), 1.0);
    return 1.0 - s * s * (3.0 - 2.0 * s);
}

/* The largest |air - (S + g I)| over the points, and the smallest |I|. */
static double worst_err(const sim_air *a, const sim_air_in *in, const triple *t, const double (*p)[3], int n, double g, double *min_I)
{
    double worst = 0.0;
    *min_I = INFINITY;
    for (int i = 0; i < n; i++) {
        double v[3], s[3], I[3];
        sim_air_sample_S(a, in, p[i], 0.0, v);
        lin_at(&t->S, p[i], s);
        lin_at(&t->I, p[i], I);
        double e = 0.0, m = 0.0;
        for (int k = 0; k < 3; k++) {
            e = fmax(e, fabs(v[k] - (s[k] + g * I[k])));
            m += I[k] * I[k];
        }
        worst = fmax(worst, e);
        *min_I = fmin(*min_I, sqrt(m));
    }
    return worst;
}

/* At the station: S + I, on the disk (its modes) and off it (pointwise);
 * without the interaction, S. Away: S + w(d) I, S beyond the fade. */
static void test_place(const triple *t)
{
    core_err err = {0};
    sim_air *a = make_air(t, &err);
    sim_interaction *ia = make_inter(t, &err);
    CHECK(a && ia);
    if (!a || !ia) {
        fprintf(stderr, "place: %s\n", err.msg);
        sim_air_destroy(a);
        sim_interaction_destroy(ia);
        return;
    }
    const double *h = t->hub;
    /* on the disk: the hub, mid-span, near the tip; off it: the fuselage
     * 5 m below the hub, the tail rotor behind the disk, above the disk */
    double pd[3][3] = {{h[0], h[1], h[2]}, {h[0] + 3.0, h[1] + 2.0, h[2] + 0.5}, {h[0] + 4.0, h[1] - 7.0, h[2] - 1.0}};
    double po[3][3] = {{h[0], h[1], h[2] + 5.0}, {h[0] - 9.8, h[1] + 0.4, h[2] + 1.0}, {h[0] + 1.0, h[1], h[2] - 4.0}};
    double minI, e_plain = worst_err(a, NULL, t, pd, 3, 0.0, &minI);
    double e0 = fmax(e_plain, worst_err(a, NULL, t, po, 3, 0.0, &minI));
    sim_air_in in = {NULL, ia};
    double ed = worst_err(a, &in, t, pd, 3, 1.0, &minI), eo = worst_err(a, &in, t, po, 3, 1.0, &minI);
    printf("at the station: air - (ship-only + I) %.2e m/s on the disk, %.2e off it (|I| >= %.2f m/s); without the "
           "interaction air - ship-only %.2e\n", ed, eo, minI, e0);
    CHECK(ed < 1e-9 && eo < 1e-9 && e0 < 1e-9 && minI > 1.0);
    CHECK(sim_air_flags(a, ia, 0.0) & SIM_AIR_INTERACTION);
    if (t->fsz) { /* outside the deck zone: the ship-only air alone */
        double px[2][3] = {{30.0, 5.0, -8.0}, {-5.0, -33.0, -3.0}};
        double ex = worst_err(a, &in, t, px, 2, 0.0, &minI);
        printf("deck-zone pair: outside the zone air - ship-only %.2e m/s\n", ex);
        CHECK(ex < 1e-12);
    }
    /* the CG moved from the station across the wind (y): the weight */
    const double ds[] = {0.0, 0.2 * R_M, 0.5 * R_M, 0.9 * R_M, 1.25 * R_M, 1.6 * R_M};
    double worst = 0.0;
    for (int i = 0; i < 6; i++) {
        double cg[3] = {t->station[0], t->station[1] + ds[i], t->station[2]};
        CHECK(sim_interaction_step(ia, cg, NAN, 0.005) == 0);
        double w = weight_of(ds[i]);
        /* a point on the moved disk and one off it, both fixed in S */
        double p[2][3] = {{h[0] + 2.0, h[1] + ds[i] - 3.0, h[2]}, {h[0], h[1] + ds[i], h[2] + 5.0}};
        double e = worst_err(a, &in, t, p, 2, w, &minI);
        sim_interaction_info ii;
        sim_interaction_state(ia, &ii);
        printf("CG %.2f R from the station: weight %.4f (expected %.4f), air - (ship-only + w I) %.2e m/s, flag %u\n",
               ds[i] / R_M, ii.weight, w, e, (sim_air_flags(a, ia, 0.0) & SIM_AIR_INTERACTION) != 0);
        CHECK_NEAR(ii.weight, w, 1e-12);
        CHECK(((sim_air_flags(a, ia, 0.0) & SIM_AIR_INTERACTION) != 0) == (w > 0.0));
        worst = fmax(worst, e);
    }
    CHECK(worst < 1e-9);
    CHECK(weight_of(1.6 * R_M) == 0.0 && weight_of(0.2 * R_M) == 1.0);
    CHECK(sim_interaction_step(ia, (double[3]){NAN, 0, 0}, 1.0, 0.005) < 0);
    sim_interaction_destroy(ia);
    sim_air_destroy(a);
}

/* The rotor flown at 5 m/s out of the station across the fade, 200 Hz:
 * the air at a point changes per step by at most the fade's slope, 1.5 /
 * R, times the distance moved and |I| there; a switch (no fade) would
 * change it by |I| in one step. */
static void test_continuity(const triple *t)
{
    core_err err = {0};
    sim_air *a = make_air(t, &err);
    sim_interaction *ia = make_inter(t, &err);
    CHECK(a && ia);
    if (!a || !ia) {
        sim_air_destroy(a);
        sim_interaction_destroy(ia);
        return;
    }
    sim_air_in in = {NULL, ia};
    const double v = 5.0, h = 0.005;
    double p[3] = {t->hub[0], t->hub[1], t->hub[2] + 5.0}, Ip[3];
    lin_at(&t->I, p, Ip);
    double nI = sqrt(Ip[0] * Ip[0] + Ip[1] * Ip[1] + Ip[2] * Ip[2]);
    double prev[3], jump = 0.0;
    sim_air_sample_S(a, &in, p, 0.0, prev);
    for (int i = 1; i <= 600; i++) {
        double cg[3] = {t->station[0], t->station[1] + v * h * i, t->station[2]};
        sim_interaction_step(ia, cg, NAN, h);
        double now[3], d2 = 0.0;
        sim_air_sample_S(a, &in, p, i * h, now);
        for (int k = 0; k < 3; k++)
            d2 += (now[k] - prev[k]) * (now[k] - prev[k]);
        jump = fmax(jump, sqrt(d2));
        memcpy(prev, now, sizeof prev);
    }
    double bound = 1.5 / R_M * v * h * nI;
    printf("rotor out of the station at %.0f m/s: largest change of the air per 200 Hz step %.5f m/s (the fade's bound "
           "%.5f; a switch: %.3f)\n", v, jump, bound, nI);
    CHECK(jump <= bound * (1.0 + 1e-9));
    CHECK(jump >= 0.9 * bound); /* the fade was crossed: 600 steps, 15 m, to 1.83 R */
    sim_interaction_destroy(ia);
    sim_air_destroy(a);
}

/* Glauert's induced velocity, by bisection (independent of the file's
 * closed form): v^2 (V^2 + v^2) = (T / (2 rho A))^2. */
static double glauert(double T, double V)
{
    double vh2 = T / (2.0 * 1.225 * M_PI * R_M * R_M), lo = 0.0, hi = 100.0;
    for (int i = 0; i < 200; i++) {
        double m = 0.5 * (lo + hi);
        if (m * m * (V * V + m * m) > vh2 * vh2)
            hi = m;
        else
            lo = m;
    }
    return 0.5 * (lo + hi);
}

/* Twice the field's thrust: the factor v(2 T) / v(T) once settled; the
 * lag's step response 1 - exp(-t / tau), tau = R / sqrt(V^2 + v^2). */
static void test_thrust(const triple *t)
{
    core_err err = {0};
    sim_air *a = make_air(t, &err);
    sim_interaction *ia = make_inter(t, &err), *ib = make_inter(t, &err);
    CHECK(a && ia && ib);
    if (!a || !ia || !ib) {
        sim_air_destroy(a);
        sim_interaction_destroy(ia);
        sim_interaction_destroy(ib);
        return;
    }
    sim_air_in in = {NULL, ia};
    double T = 2.0 * t->thrust_N;
    CHECK(sim_interaction_step(ia, t->station, T, 1000.0) == 0); /* settled */
    double f = glauert(T, WOD_MPS) / glauert(t->thrust_N, WOD_MPS), minI;
    double p[2][3] = {{t->hub[0], t->hub[1], t->hub[2]}, {t->hub[0], t->hub[1], t->hub[2] + 5.0}};
    double e = worst_err(a, &in, t, p, 2, f, &minI);
    sim_interaction_info ii;
    sim_interaction_state(ia, &ii);
    printf("twice the field's thrust in %.0f m/s: factor %.5f (Glauert %.5f; sqrt 2 = 1.41421 in hover), air - "
           "(ship-only + f I) %.2e m/s\n", WOD_MPS, ii.factor, f, e);
    CHECK_NEAR(ii.factor, f, 1e-9);
    CHECK(e < 1e-8);
    CHECK(f > 1.2 && f < 2.0);
    /* the lag */
    double vf = glauert(t->thrust_N, WOD_MPS), tau = R_M / sqrt(WOD_MPS * WOD_MPS + vf * vf);
    const double h = 0.005;
    int n = (int)lround(tau / h);
    for (int i = 0; i < n; i++)
        sim_interaction_step(ib, t->station, T, h);
    sim_interaction_step(ib, t->station, NAN, h); /* not known: kept */
    sim_interaction_state(ib, &ii);
    double expect = t->thrust_N + (T - t->thrust_N) * (1.0 - exp(-n * h / tau));
    printf("thrust stepped to twice the field's: after %.3f s (tau %.3f s) the lagged thrust %.1f N (expected %.1f)\n",
           n * h, tau, ii.thrust_N, expect);
    CHECK_NEAR(ii.thrust_N, expect, 1e-6 * T);
    sim_interaction_destroy(ia);
    sim_interaction_destroy(ib);
    sim_air_destroy(a);
}

static void test_bad(const triple *t)
{
    core_err err = {0};
    sim_interaction_opts io;
    sim_interaction_opts_default(&io);
    lin L = t->iso;
    cfd_field *other = make_field(&L, "loaded", t->thrust_N + 50.0, t->hub, "other");
    CHECK(other != NULL);
    CHECK(sim_interaction_create(t->fc, other, &io, &err) == NULL && strstr(err.msg, "isolated") != NULL);
    printf("refused: %s\n", err.msg);
    CHECK(sim_interaction_create(t->fs, t->fi, &io, &err) == NULL && strstr(err.msg, "rotor 'off'") != NULL);
    printf("refused: %s\n", err.msg);
    io.q_SH.w = 2.0;
    CHECK(sim_interaction_create(t->fc, t->fi, &io, &err) == NULL && strstr(err.msg, "quaternion") != NULL);
    cfd_field_destroy(other);
}

#ifdef DISIM_TEST_COUPLE
/* The loop's trimmed hover with the interaction against the coupling's
 * trim in the same fields (couple's air: the wind plus coupled - isolated,
 * its modes fitted over the trimmed disk, tilted with the shaft), a
 * whole-domain pair and a deck-zone one (zone 1). */
static void test_couple_trim(const hfm_aircraft *ac, const core_ship *ship, int zone)
{
    core_err err = {0};
    double station[3] = {0.0, 0.0, -6.0};
    /* the one-way trim in a ship-only field gives the disk the fields are
     * solved for (as the coupling's first iteration) */
    triple t0;
    double hub0[3] = {0, 0, -8};
    if (triple_make(&t0, 70000.0, hub0, station, 0.0, 0) != 0) {
        CHECK(0);
        triple_free(&t0);
        return;
    }
    cfd_field_scaled so = {t0.fs, 1.0};
    hfm_air sair = {cfd_field_air_scaled, &so, NULL};
    hfm_trim *tr = hfm_trim_create(ac, NULL);
    hfm_trim_cond cond;
    memset(&cond, 0, sizeof cond);
    cond.kind = HFM_TRIM_HOVER_SHIP;
    cond.wod_speed_mps = WOD_MPS;
    memcpy(cond.pos_S_m, station, sizeof cond.pos_S_m);
    cond.air = &sair;
    hfm_trim_result r0, rc;
    int ok = tr && hfm_trim_solve(tr, &cond, NULL, &r0) == 0;
    hfm_disk *disk = malloc(sizeof *disk);
    ok = ok && disk && hfm_rotor_disk(ac, &sair, 0.0, &r0.body, &r0.u, &r0.rotor, 8, 12, disk) == 0;
    CHECK(ok);
    triple t;
    memset(&t, 0, sizeof t);
    if (!ok || triple_make(&t, disk->thrust_N, disk->hub_S_m, station, 0.008, zone) != 0) {
        CHECK(0);
        goto out;
    }
    /* the coupling's trim in coupled - isolated */
    air_interaction ai;
    memset(&ai, 0, sizeof ai);
    ai.coupled = t.fc;
    ai.isolated = t.fi;
    ai.w = 1.0;
    ai.wind[0] = -WOD_MPS;
    if (zone) { /* couple.c's zone_correction: both at the coupled fields' speed here */
        ai.ship_whole = t.fs;
        ai.ship_zone = t.fsz;
        ai.corr_scale = 1.0;
    }
    couple_interaction_fit(&ai, disk, R_M);
    hfm_air_uniform uni = {{-WOD_MPS, 0, 0}};
    hfm_air free_air = {hfm_air_uniform_fn, &uni, NULL};
    hfm_air cair = {couple_interaction_air, &ai, &free_air};
    cond.air = &cair;
    CHECK(hfm_trim_solve(tr, &cond, NULL, &rc) == 0);
    /* the loop's: the ship-only field with the interaction */
    sim_interaction *ia = make_inter(&t, &err);
    sim_flight_opts fo;
    sim_flight_opts_default(&fo);
    fo.wod_speed_mps = WOD_MPS;
    fo.turbulence = 0;
    fo.sas = 0;
    memcpy(fo.station_S_m, station, sizeof fo.station_S_m);
    /* the two airs at the disk's points and off the disk */
    if (ia) {
        sim_air *a = make_air(&t, &err);
        sim_air_in in = {NULL, ia};
        const double *h = disk->hub_S_m;
        double p[6][3] = {{h[0], h[1], h[2]},        {h[0] + 3.0, h[1] + 2.0, h[2]}, {h[0] - 2.0, h[1] - 7.5, h[2]},
                          {h[0], h[1], h[2] + 5.0}, {h[0] - 9.8, h[1], h[2] + 1.0}, {h[0] + 2.0, h[1] + 2.0, h[2] - 4.0}};
        double worst_disk = 0.0, worst_off = 0.0, spread = 0.0;
        for (int i = 0; i < 6; i++) {
            double vl[3], vc[3], vp[3];
            sim_air_sample_S(a, &in, p[i], 0.0, vl);
            couple_interaction_air(&ai, p[i], 0.0, vc);
            /* pointwise: wind + c - i (+ S - Sz in a deck zone) */
            double vi[3], vs[3] = {0, 0, 0}, vz[3] = {0, 0, 0};
            lin_at(&t.cpl, p[i], vp);
            lin_at(&t.iso, p[i], vi);
            if (zone) {
                lin_at(&t.S, p[i], vs);
                lin_at(&t.Sz, p[i], vz);
            }
            double e = 0.0, d = 0.0;
            for (int k = 0; k < 3; k++) {
                double pk = vp[k] - vi[k] + vs[k] - vz[k] - WOD_MPS * (k == 0);
                e = fmax(e, fabs(vl[k] - vc[k]));
                d = fmax(d, fabs(vc[k] - pk));
            }
            if (i < 3) {
                worst_disk = fmax(worst_disk, e);
                spread = fmax(spread, d);
            } else
                worst_off = fmax(worst_off, e);
        }
        printf("the loop's air against the coupling's: %.4f m/s on the disk (the modes differ from the pointwise "
               "difference there by up to %.3f m/s), %.2e off it\n", worst_disk, spread, worst_off);
        CHECK(worst_disk < 0.02 && spread > 0.1 && worst_off < 1e-9);
        sim_air_destroy(a);
    }
    sim_flight *f0 = sim_flight_create(ac, ship, &fo, NULL, NULL, t.fs, NULL, &err);
    fo.interaction = ia;
    sim_flight *fl = ia ? sim_flight_create(ac, ship, &fo, NULL, NULL, t.fs, NULL, &err) : NULL;
    CHECK(f0 && fl);
    if (f0 && fl) {
        sim_flight_inputs i0, il;
        sim_flight_trim_inputs(f0, &i0);
        sim_flight_trim_inputs(fl, &il);
        double dc = (il.ctl.collective_pct - rc.u.collective_pct) / rc.u.collective_pct;
        double dw = (rc.u.collective_pct - i0.ctl.collective_pct) / i0.ctl.collective_pct;
        printf("%s: trimmed hover, %.0f m/s, the disk's %.0f N: collective the loop %.3f %%, the coupling %.3f %% "
               "(%+.3f %%), ship-only alone %.3f %% (the interaction moves it %+.2f %%); long %.2f / %.2f, "
               "lat %.2f / %.2f, pedal %.2f / %.2f %%\n",
               zone ? "deck-zone pair" : "whole-domain pair", WOD_MPS, disk->thrust_N, il.ctl.collective_pct,
               rc.u.collective_pct, 100.0 * dc, i0.ctl.collective_pct, 100.0 * dw, il.ctl.long_cyclic_pct,
               rc.u.long_cyclic_pct, il.ctl.lat_cyclic_pct, rc.u.lat_cyclic_pct, il.ctl.pedal_pct, rc.u.pedal_pct);
        /* the airs differ only by the fit's disk plane (level; the
         * coupling's tilted with the trimmed shaft) and the wake's skew
         * (the loop's from the air at the hub, the coupling's from the
         * wind): 0.1 % of collective, where the pointwise difference on
         * the disk instead of its modes gives 0.4 % */
        CHECK(fabs(dc) < 0.001);
        CHECK(fabs(dw) > 0.02); /* the interaction matters: the check can tell */
        /* a second of flight holding the trim: the interaction is flown */
        sim_flight_out out;
        for (int i = 0; i < 200; i++)
            CHECK(sim_flight_step(fl, &il, &out, &err) == 0 || (fprintf(stderr, "%s\n", err.msg), 0));
        sim_interaction_info ii;
        sim_interaction_state(ia, &ii);
        printf("after 1 s holding the trim: CG %.3f m from the station, weight %.3f, thrust factor %.4f (lagged %.0f N, "
               "the field's %.0f N), flags %u\n", ii.dist_m, ii.weight, ii.factor, ii.thrust_N, ii.thrust_field_N,
               out.air_flags);
        CHECK(out.air_flags & SIM_AIR_INTERACTION);
        CHECK(ii.weight == 1.0 && fabs(ii.factor - 1.0) < 0.05);
        /* 2 % more collective for 1 s: the flight model's thrust reaches
         * the interaction through the lag (tau 0.59 s here) */
        sim_flight_inputs up = il;
        up.ctl.collective_pct += 2.0;
        double T_late = 0.0;
        for (int i = 0; i < 200; i++) {
            CHECK(sim_flight_step(fl, &up, &out, &err) == 0);
            if (i >= 100)
                T_late += out.rotor_thrust_N / 100.0;
        }
        sim_interaction_state(ia, &ii);
        double frac = (ii.thrust_N - ii.thrust_field_N) / (T_late - ii.thrust_field_N);
        printf("2 %% more collective for 1 s: the rotor's thrust %.0f N over the last 0.5 s, the interaction's lagged "
               "%.0f N (%.2f of the way from the field's %.0f N), factor %.4f\n", T_late, ii.thrust_N, frac,
               ii.thrust_field_N, ii.factor);
        CHECK(T_late - ii.thrust_field_N > 1000.0 && frac > 0.5 && frac < 1.0 && ii.factor > 1.0);
        /* a start 0.6 R across from the station is trimmed with the
         * interaction's weight there, not the station's */
        sim_interaction *ib = make_inter(&t, &err);
        fo.interaction = ib;
        fo.station_S_m[1] = station[1] + 0.6 * R_M;
        sim_flight *fb = ib ? sim_flight_create(ac, ship, &fo, NULL, NULL, t.fs, NULL, &err) : NULL;
        CHECK(fb != NULL);
        if (fb) {
            sim_interaction_state(ib, &ii);
            printf("a start 0.6 R from the station: trimmed with the weight %.4f (the fade's %.4f)\n", ii.weight,
                   weight_of(0.6 * R_M));
            CHECK_NEAR(ii.weight, weight_of(0.6 * R_M), 1e-12);
        }
        sim_flight_destroy(fb);
        sim_interaction_destroy(ib);
    } else
        fprintf(stderr, "loop: %s\n", err.msg);
    sim_flight_destroy(fl);
    sim_flight_destroy(f0);
    sim_interaction_destroy(ia);
out:
    triple_free(&t);
    triple_free(&t0);
    free(disk);
    hfm_trim_destroy(tr);
}
#endif

/* ------------------------------------- disim fly with a database's fields */
/* The builder's engine for the test's keys: the ship-only field (at the
 * reference speed: S scaled by v_ref / 10 m/s), the isolated rotor's, the
 * coupled one; the rotor's thrust, hub and radius from the key. */
static int db_build(void *user, const awdb_key *k, const char *warm, const char *out, awdb_progress_fn progress,
                    void *pu, core_err *err)
{
    (void)warm;
    (void)progress;
    (void)pu;
    triple *tw = user, *t = k->zone_ref_mps > 0.0 ? tw + 1 : tw; /* whole-domain, deck-zone */
    cfd_meta meta;
    memset(&meta, 0, sizeof meta);
    meta.wod_speed_mps = k->wod_speed_mps;
    meta.wod_dir_deg = k->wod_dir_rad * CORE_RAD_TO_DEG;
    snprintf(meta.ship, sizeof meta.ship, "%.63s", k->ship);
    snprintf(meta.rotor, sizeof meta.rotor, "%s", core_rotor_name(k->rotor));
    snprintf(meta.grid, sizeof meta.grid, "h2.000 m");
    meta.rotor_thrust_N = k->thrust_N;
    meta.rotor_radius_m = k->radius_m;
    memcpy(meta.rotor_centre_S_m, k->station_S_m, sizeof meta.rotor_centre_S_m);
    lin L = k->rotor == CORE_ROTOR_OFF ? t->S : strstr(k->ship, ".isolated") ? t->iso : t->cpl;
    if (k->rotor == CORE_ROTOR_OFF) { /* at the key's speed: the zone's own, or the whole domain's */
        lin zero;
        memset(&zero, 0, sizeof zero);
        L = lin_sum(&zero, k->zone_ref_mps > 0.0 ? &t->Sz : &t->S, k->wod_speed_mps / WOD_MPS);
    }
    box_m = k->zone_ref_mps > 0.0 ? 20.0 : 40.0;
    int rc = write_field(&L, &meta, out, err);
    box_m = 40.0;
    return rc;
}

static volatile sig_atomic_t db_stop = 0;

/* A coupled key of SFS2 + UH-60A at 10 m/s from dir_deg (the rotor
 * uniform), its hub at hub, and its isolated rotor's; zone_ref > 0: a
 * deck-zone pair bounded by the ship-only field at that speed. */
static void pair_keys(double thrust_N, const double hub[3], double dir_deg, double zone_ref, awdb_key *kc, awdb_key *ki)
{
    awdb_key_ship_only(kc, "SFS2", "UH-60A", WOD_MPS, dir_deg * CORE_DEG_TO_RAD, CORE_GRID_DEFAULT);
    kc->zone_ref_mps = zone_ref;
    kc->rotor = CORE_ROTOR_UNIFORM;
    kc->thrust_N = thrust_N;
    memcpy(kc->station_S_m, hub, sizeof kc->station_S_m);
    kc->radius_m = R_M;
    *ki = *kc;
    snprintf(ki->ship, sizeof ki->ship, "SFS2.isolated");
}

static int run_cmd(const char *cmd, char *out, size_t n)
{
    FILE *p = popen(cmd, "r");
    if (!p)
        return -1;
    size_t got = fread(out, 1, n - 1, p);
    out[got] = '\0';
    return pclose(p);
}

/* disim fly over a database holding, for 10 m/s from the bow, the
 * ship-only field, a coupled pair at the station (two coupling iterations,
 * 70000 N then 73000 N), one 20 m forward and a newer one 0.8 m across:
 * it flies the newest pair at the station, says so and raises the flag; from red 30 a deck-zone pair
 * with the zone's ship-only field: it flies that; from green 30 (no
 * coupled fields) it says it flies without. */
static void test_db_fly(const char *disim)
{
    char dir[256], scen[300], csv[300], cmd[2048], out[8192], cwd[1024];
    snprintf(dir, sizeof dir, "/tmp/disim_test_interaction_%ld_db", (long)getpid());
    CHECK(getcwd(cwd, sizeof cwd) != NULL);
    core_err err = {0};
    triple t[2]; /* the whole-domain and the deck-zone lins (the engine writes the fields) */
    double hub[3] = {0.05, 0.0, -7.9}, fwd[3] = {20.0, 0.0, -7.9}, station[3] = {0.0, 0.0, -6.0};
    int ok = triple_make(&t[0], 73000.0, hub, station, 0.0, 0) == 0;
    ok = triple_make(&t[1], 74000.0, hub, station, 0.0, 1) == 0 && ok;
    if (!ok || core_mkdir_p(dir, &err) != 0) {
        CHECK(0);
        triple_free(&t[0]);
        triple_free(&t[1]);
        return;
    }
    awdb *db = awdb_open(dir, NULL, &err);
    CHECK(db != NULL);
    const double ref = AWDB_SHIP_ONLY_REF_MPS;
    awdb_key k[13];
    awdb_key_ship_only(&k[0], "SFS2", "UH-60A", ref, 0.0, CORE_GRID_DEFAULT);
    pair_keys(70000.0, hub, 0.0, 0.0, &k[1], &k[2]);
    pair_keys(73000.0, hub, 0.0, 0.0, &k[3], &k[4]);
    pair_keys(73000.0, fwd, 0.0, 0.0, &k[5], &k[6]);
    /* red 30: the whole domain's ship-only field, the zone's own (at the
     * station, as the coupling keys it) and a deck-zone pair */
    awdb_key_ship_only(&k[7], "SFS2", "UH-60A", ref, -30.0 * CORE_DEG_TO_RAD, CORE_GRID_DEFAULT);
    k[8] = k[7];
    k[8].zone_ref_mps = ref;
    memcpy(k[8].station_S_m, station, sizeof k[8].station_S_m);
    k[8].radius_m = R_M;
    pair_keys(74000.0, hub, -30.0, ref, &k[9], &k[10]);
    /* the newest of all, its hub 0.8 m across from the nearest (0.16 m
     * farther from the station): another place, not flown */
    double side[3] = {hub[0], hub[1] + 0.8, hub[2]};
    pair_keys(75000.0, side, 0.0, 0.0, &k[11], &k[12]);
    ok = db != NULL;
    for (int i = 0; i < 13 && ok; i++)
        ok = awdb_key_canon(&k[i], &err) == 0 && awdb_submit(db, &k[i], NULL, &err) == 0;
    awdb_engine eng = {"test", db_build, t, NULL};
    awdb_builder_opts bo;
    memset(&bo, 0, sizeof bo);
    bo.jobs = 1;
    bo.exit_when_idle = 1;
    bo.poll_s = 0.01;
    ok = ok && awdb_builder_run(db, &eng, &bo, &db_stop, &err) == 0;
    CHECK(ok);
    if (!ok)
        fprintf(stderr, "database: %s\n", err.msg);
    snprintf(scen, sizeof scen, "%s/s.ini", dir);
    snprintf(csv, sizeof csv, "%s/fly.csv", dir);
    FILE *f = fopen(scen, "w");
    CHECK(f != NULL);
    if (f) {
        fprintf(f, "[scenario]\nname = interaction\naircraft = %s/" UH60 "\nship = %s/" SHIP
                   "\n[wod]\nmode = single\nspeed_kt = %.6f\ndir_deg = 0\n[task]\nhover_height_m = 6.0\n"
                   "[cfd]\nengine = embedded\ngrid = default\nrotor = loaded\ncoupling = two-way\n[output]\n"
                   "dir = %s/out\n", cwd, cwd, WOD_MPS / CORE_KT_TO_MPS, dir);
        fclose(f);
    }
    snprintf(cmd, sizeof cmd, "%s fly %s --fast --duration 0.5 --no-turbulence --no-lcm --db %s --csv %s 2>&1", disim,
             scen, dir, csv);
    int rc = run_cmd(cmd, out, sizeof out);
    printf("%s", out);
    CHECK(rc == 0);
    CHECK(strstr(out, "the coupled rotor interaction near the station (the database's coupled field of 73000 N, hub "
                      "(0.05, 0.00, -7.90)") != NULL);
    /* the CSV's air_flags column (found by its header): the interaction
     * flown at every row */
    f = fopen(csv, "r");
    int rows = 0, flagged = 0, col = -1;
    char line[2048];
    while (f && fgets(line, sizeof line, f)) {
        line[strcspn(line, "\n")] = '\0';
        char *tok = line;
        for (int i = 0; tok; i++) { /* the fields, empty ones included */
            char *next = strchr(tok, ',');
            if (next)
                *next++ = '\0';
            if (rows == 0 && !strcmp(tok, "air_flags"))
                col = i;
            if (rows > 0 && i == col)
                flagged += (atoi(tok) & SIM_AIR_INTERACTION) != 0;
            tok = next;
        }
        rows++;
    }
    CHECK(col >= 0);
    if (f)
        fclose(f);
    printf("disim fly: %d of %d rows with the interaction's flag\n", flagged, rows - 1);
    CHECK(rows > 10 && flagged == rows - 1);
    snprintf(cmd, sizeof cmd, "%s fly %s --fast --duration 0.2 --no-turbulence --no-lcm --db %s --wod-dir-deg 30 2>&1",
             disim, scen, dir);
    rc = run_cmd(cmd, out, sizeof out);
    printf("%s", out);
    CHECK(rc == 0 && strstr(out, "no coupled fields for this WOD in the database: the ship-only airwake alone"));
    snprintf(cmd, sizeof cmd, "%s fly %s --fast --duration 0.2 --no-turbulence --no-lcm --db %s --wod-dir-deg -30 2>&1",
             disim, scen, dir);
    rc = run_cmd(cmd, out, sizeof out);
    printf("%s", out);
    CHECK(rc == 0 && strstr(out, "the coupled rotor interaction near the station (the database's coupled field of "
                                 "74000 N, hub (0.05, 0.00, -7.90) m in S, deck zone)"));
    awdb_close(db);
    triple_free(&t[0]);
    triple_free(&t[1]);
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    CHECK(system(cmd) == 0);
}

int main(int argc, char **argv)
{
    setvbuf(stdout, NULL, _IOLBF, 0);
    if (argc > 1) { /* test_interaction_fly: disim fly over a database */
        test_db_fly(argv[1]);
        return check_done("test_interaction_fly");
    }
    triple t;
    double hub[3] = {0.3, -0.2, -8.0}, station[3] = {0.0, 0.0, -6.0};
    int ok = triple_make(&t, 70000.0, hub, station, 0.0, 0) == 0;
    CHECK(ok);
    if (ok) {
        test_place(&t);
        test_continuity(&t);
        test_thrust(&t);
        test_bad(&t);
    }
    triple_free(&t);
    ok = triple_make(&t, 70000.0, hub, station, 0.0, 1) == 0; /* a deck-zone pair */
    CHECK(ok);
    if (ok)
        test_place(&t);
    if (ok) { /* the zone's ship-only field alone is refused */
        core_err err = {0};
        sim_interaction_opts io;
        sim_interaction_opts_default(&io);
        io.ship_zone = t.fsz;
        CHECK(sim_interaction_create(t.fc, t.fi, &io, &err) == NULL && strstr(err.msg, "deck-zone") != NULL);
    }
    triple_free(&t);
#ifdef DISIM_TEST_COUPLE
    core_err err = {0};
    hfm_aircraft *ac = hfm_aircraft_load(UH60, NULL, &err);
    core_ship ship;
    ok = ac && core_ship_load(SHIP, &ship, &err) == 0;
    CHECK(ok);
    if (ok)
        for (int zone = 0; zone < 2; zone++)
            test_couple_trim(ac, &ship, zone);
    else
        fprintf(stderr, "set-up: %s\n", err.msg);
    hfm_aircraft_destroy(ac);
#else
    check_skip("the loop's trim against the coupling's: the coupling library is left out of this build");
#endif
    return check_done("test_interaction");
}
