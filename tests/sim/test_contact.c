/* test_contact.c -- the landing gear on the deck (sim/contact.c): the
 * [gear] reader's errors, the static compression under the weight, the
 * UH-60A parked 5 minutes (the SA365N 60 s) on a still deck and in sea
 * state 4 with 30 kt over the deck, a deck tilting nose up that holds at
 * half of atan(mu_static) and slides past it, a deck rolling to 33 deg that
 * rolls it over, a drop from 0.5 m, and the tail driven into the CG-47's
 * hangar face (moved kinematically: the flight cannot face aft). Flown with
 * the flight loop (sim/flight.c) at 200 Hz, the collective lowered to full
 * down. Run from the source root. DISIM_CONTACT_DEBUG=1 prints each parked
 * run's last state. */
#include "check.h"
#include "hfm.h"
#include "sim.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define UH60 "scenarios/aircraft/uh60a.ini"
#define SA365 "scenarios/aircraft/sa365n.ini"
#define CG47 "scenarios/ships/cg47.ini"

/* The CG's height over a level deck at rest: the legs at their static loads. */
static double rest_height_m(const hfm_gear *g, double W)
{
    double load[HFM_GEAR_MAX_LEGS], h = 0;
    core_err err = {0};
    if (sim_contact_static_loads(g, W, load, &err))
        return NAN;
    for (int i = 0; i < g->nlegs; i++)
        h += (g->leg[i].pos_B_m[2] + g->leg[i].tyre_radius_m - sim_contact_leg_compression(&g->leg[i], load[i])) /
             g->nlegs;
    return h;
}

/* Each leg's static compression, from preload/stiffness arithmetic here,
 * is where the gear's forces carry its share of the weight: the aircraft
 * placed level at that height on a still deck gets back each leg's share
 * and the weight in all. */
static void test_static(const hfm_aircraft *ac, const core_ship *ship)
{
    hfm_gear g;
    CHECK(hfm_aircraft_gear(ac, &g) == 0);
    double W = hfm_aircraft_weight_N(ac), load[HFM_GEAR_MAX_LEGS], sum = 0, mx = 0;
    core_err err = {0};
    CHECK(sim_contact_static_loads(&g, W, load, &err) == 0);
    for (int i = 0; i < g.nlegs; i++) {
        sum += load[i];
        mx += load[i] * g.leg[i].pos_B_m[0];
    }
    CHECK_NEAR(sum, W, 1e-6 * W);
    CHECK_NEAR(mx, 0.0, 1e-6 * W);
    sim_contact *c = sim_contact_create(ac, ship, 200.0, &err);
    CHECK(c != NULL);
    if (!c) {
        fprintf(stderr, "contact: %s\n", err.msg);
        return;
    }
    /* all legs at the same height: the level body at the static compression of leg 0 */
    const hfm_gear_leg *l0 = &g.leg[0];
    double x0 = l0->preload_N <= load[0]
                    ? load[0] / l0->tyre_stiffness_Npm + (load[0] - l0->preload_N) / l0->stiffness_Npm
                    : load[0] / l0->tyre_stiffness_Npm;
    CHECK_NEAR(sim_contact_leg_compression(l0, load[0]), x0, 1e-12);
    hfm_body b = {{0, 0, -(l0->pos_B_m[2] + l0->tyre_radius_m - x0)}, {0}, {0}, {0}};
    double F[3], M[3];
    sim_ship_deck still;
    sim_ship_deck_still(&still);
    CHECK(sim_contact_loads(c, &still, &b, F, M) == 0);
    sim_contact_report rep;
    sim_contact_report_get(c, &rep);
    printf("%s: %s static %.0f N, compression %.4f m (strut %.4f), gear load %.0f N\n", hfm_aircraft_name(ac),
           l0->name, load[0], x0, rep.leg[0].strut_m, rep.leg[0].normal_N);
    CHECK_NEAR(rep.leg[0].normal_N, load[0], 1e-6 * load[0]);
    CHECK_NEAR(rep.leg[0].strut_m, (load[0] - l0->preload_N) / l0->stiffness_Npm, 1e-9);
    /* each leg at its own static compression carries its share: the weight
     * in all, no pitching moment */
    double Fz = 0, My = 0;
    for (int i = 0; i < g.nlegs; i++) {
        double h = g.leg[i].pos_B_m[2] + g.leg[i].tyre_radius_m - sim_contact_leg_compression(&g.leg[i], load[i]);
        hfm_body bi = {{0, 0, -h}, {0}, {0}, {0}};
        CHECK(sim_contact_loads(c, &still, &bi, F, M) == 0);
        sim_contact_report_get(c, &rep);
        CHECK_NEAR(rep.leg[i].normal_N, load[i], 1e-6 * load[i]);
        Fz += rep.leg[i].normal_N;
        My += rep.leg[i].normal_N * g.leg[i].pos_B_m[0];
    }
    CHECK_NEAR(Fz, W, 1e-6 * W);
    CHECK_NEAR(My, 0.0, 1e-5 * W);
    sim_contact_destroy(c);
}

/* A ship whose deck tilts nose up: level until t0_s, then to theta_rad by a
 * smooth ramp over ramp_s; its origin fixed. */
typedef struct tilt {
    double theta_rad, t0_s, ramp_s;
    int roll; /* 1: rolls to starboard instead */
} tilt;
static int tilt_frame(void *user, double t_s, sim_ship_frame *out)
{
    const tilt *tl = user;
    double u = (t_s - tl->t0_s) / tl->ramp_s;
    u = u < 0 ? 0 : u > 1 ? 1 : u;
    double th = tl->theta_rad * u * u * (3 - 2 * u);
    double c = cos(th), s = sin(th);
    memset(out, 0, sizeof *out);
    /* C_ES of a pitch th (x_S = (c, 0, -s) in E), or a roll th (y_S = (0, c, s)) */
    double P[9] = {c, 0, s, 0, 1, 0, -s, 0, c}, R[9] = {1, 0, 0, 0, c, -s, 0, s, c};
    memcpy(out->C_ES, tl->roll ? R : P, sizeof P);
    return 0;
}

typedef struct park {
    double max_dev_m;       /* from the position after the settling */
    double peak_N;          /* the largest leg load */
    double min_N;
    int finite;
    int crashed;
    sim_contact_report rep;
    double settle_S[3];
    double slip_settle_m[HFM_GEAR_MAX_LEGS]; /* each tyre's slip when it had settled */
    double t_parked_slide_s;  /* first time a tyre slid PARKED_SLIDE_M after that; -1 never */
} park;

/* A tyre counts as sliding once it has slid as far as the contact's own
 * report threshold (sim/contact.c, 0.05 m) after the aircraft settled: the
 * touchdown's scrub (the tail tyre's, as the collective goes down with the
 * pedal held, bouncing on its strut) is the landing's, not the parking's. */
#define PARKED_SLIDE_M 0.05

static int park_sas = -1; /* the flight's opts.sas in park_run */

/* The gear as a flight's external loads by hand: the deck at each time
 * from the ship's frame function (NULL: the deck still). */
typedef struct gear_ext {
    sim_contact *c;
    sim_ship_frame_fn frame;
    void *user;
} gear_ext;

static int gear_deck(const gear_ext *g, double t_s, sim_ship_deck *d)
{
    if (!g->frame) {
        sim_ship_deck_still(d);
        return 0;
    }
    return sim_ship_deck_at(g->frame, g->user, t_s, d);
}

static int gear_ext_fn(void *user, double t_s, const hfm_body *b, double F_B_N[3], double M_B_Nm[3])
{
    const gear_ext *g = user;
    sim_ship_deck d;
    return gear_deck(g, t_s, &d) != 0 ? -1 : sim_contact_loads(g->c, &d, b, F_B_N, M_B_Nm);
}

/* Park ac on the deck: the CG over the spot, the lowest tyre touching (or
 * drop_m above), the collective lowered to full down over ramp_s; the
 * position after settle_s, and how far it moves in hold_s more. */
static int park_run(const hfm_aircraft *ac, const core_ship *ship, sim_ship_frame_fn frame, void *fu, double wod_mps,
                    double drop_m, double ramp_s, double settle_s, double hold_s, park *p)
{
    hfm_gear g;
    hfm_aircraft_gear(ac, &g);
    sim_flight_opts o;
    sim_flight_opts_default(&o);
    o.wod_speed_mps = wod_mps;
    o.sas = park_sas;
    o.station_S_m[0] = 0;
    o.station_S_m[1] = 0;
    double h = rest_height_m(&g, hfm_aircraft_weight_N(ac));
    /* the wheels just touching: the rest height plus the mean static compression */
    double load[HFM_GEAR_MAX_LEGS], xm = 0;
    core_err err = {0};
    sim_contact_static_loads(&g, hfm_aircraft_weight_N(ac), load, &err);
    for (int i = 0; i < g.nlegs; i++)
        xm += sim_contact_leg_compression(&g.leg[i], load[i]) / g.nlegs;
    o.station_S_m[2] = -(h + xm);
    o.turbulence = 0;
    sim_flight *f = sim_flight_create(ac, ship, &o, frame, fu, NULL, NULL, &err);
    if (f) {
        /* in the trim's attitude the lowest tyre just touching, drop_m above */
        sim_flight_out s0;
        sim_flight_state(f, &s0);
        core_euler e = {s0.euler_E_rad[0], s0.euler_E_rad[1], s0.euler_E_rad[2]};
        core_quat q = core_quat_from_euler(e);
        double low = -INFINITY;
        for (int i = 0; i < g.nlegs; i++) {
            core_vec3 r = core_quat_rotate(q, core_vec3_make(g.leg[i].pos_B_m[0], g.leg[i].pos_B_m[1],
                                                             g.leg[i].pos_B_m[2] + g.leg[i].tyre_radius_m));
            double rE[3] = {r.x, r.y, r.z};
            double z = s0.pos_S_m[2];
            for (int k = 0; k < 3; k++)
                z += s0.ship.C_ES[3 * k + 2] * rE[k];
            if (z > low)
                low = z;
        }
        sim_flight_destroy(f);
        o.station_S_m[2] -= low + drop_m;
        f = sim_flight_create(ac, ship, &o, frame, fu, NULL, NULL, &err);
    }
    sim_contact *c = f ? sim_contact_create(ac, ship, o.rate_hz, &err) : NULL;
    if (!f || !c) {
        fprintf(stderr, "park: %s\n", err.msg);
        sim_flight_destroy(f);
        return -1;
    }
    gear_ext ge = {c, frame, fu};
    sim_flight_set_external(f, gear_ext_fn, &ge);
    sim_flight_inputs in;
    sim_flight_trim_inputs(f, &in);
    double coll_trim = in.ctl.collective_pct;
    memset(p, 0, sizeof *p);
    p->finite = 1;
    p->min_N = INFINITY;
    p->t_parked_slide_s = -1.0;
    long n_settle = lround(settle_s * o.rate_hz), n = n_settle + lround(hold_s * o.rate_hz);
    sim_flight_out out;
    for (long i = 0; i < n; i++) {
        /* the collective lowered to full down over ramp_s, as a pilot does */
        double tr = i / o.rate_hz / ramp_s;
        in.ctl.collective_pct = tr < 1 ? coll_trim * (1 - tr) : 0.0;
        if (sim_flight_step(f, &in, &out, &err) != 0) {
            fprintf(stderr, "park: step %ld: %s\n", i, err.msg);
            p->finite = 0;
            break;
        }
        hfm_body b;
        sim_contact_body(&out, &b);
        sim_ship_deck d;
        int rc = gear_deck(&ge, out.t_s, &d) != 0 ? 1 : sim_contact_step(c, out.t_s, &d, &b, &p->rep);
        for (int k = 0; k < 3; k++)
            p->finite &= isfinite(out.pos_S_m[k]) && isfinite(out.vel_S_mps[k]);
        for (int l = 0; l < p->rep.nlegs; l++) {
            p->finite &= isfinite(p->rep.leg[l].normal_N);
            if (p->rep.leg[l].normal_N > p->peak_N)
                p->peak_N = p->rep.leg[l].normal_N;
        }
        if (i == n_settle - 1) {
            memcpy(p->settle_S, out.pos_S_m, sizeof p->settle_S);
            for (int l = 0; l < p->rep.nlegs; l++)
                p->slip_settle_m[l] = p->rep.leg[l].slip_m;
        }
        if (i >= n_settle && p->t_parked_slide_s < 0)
            for (int l = 0; l < p->rep.nlegs; l++)
                if (p->rep.leg[l].slip_m - p->slip_settle_m[l] > PARKED_SLIDE_M)
                    p->t_parked_slide_s = out.t_s;
        if (i >= n_settle) {
            double d = sqrt(pow(out.pos_S_m[0] - p->settle_S[0], 2) + pow(out.pos_S_m[1] - p->settle_S[1], 2) +
                            pow(out.pos_S_m[2] - p->settle_S[2], 2));
            if (d > p->max_dev_m)
                p->max_dev_m = d;
        }
        if (rc) {
            p->crashed = 1;
            break;
        }
        if (!p->finite)
            break;
    }
    if (getenv("DISIM_CONTACT_DEBUG")) {
        printf("  t %.2f pos_S %.3f %.3f %.3f euler %.2f %.2f %.2f deg, pedal %.1f tilt %.1f deg\n", out.t_s,
               out.pos_S_m[0], out.pos_S_m[1], out.pos_S_m[2], out.euler_E_rad[0] * 57.3, out.euler_E_rad[1] * 57.3,
               out.euler_E_rad[2] * 57.3, in.ctl.pedal_pct, p->rep.tilt_rad * 57.3);
        for (int l = 0; l < p->rep.nlegs; l++)
            printf("  leg %d on %d x %.3f N %.0f Ft %.0f %.0f slip %.3f\n", l, p->rep.leg[l].on_deck,
                   p->rep.leg[l].compression_m, p->rep.leg[l].normal_N, p->rep.leg[l].friction_N[0],
                   p->rep.leg[l].friction_N[1], p->rep.leg[l].slip_m);
    }
    sim_contact_destroy(c);
    sim_flight_destroy(f);
    return 0;
}

static void print_park(const char *what, const park *p)
{
    double scrub = 0.0;
    for (int l = 0; l < p->rep.nlegs; l++)
        scrub = fmax(scrub, p->slip_settle_m[l]);
    printf("%s: moved %.4f m after settling, peak leg load %.0f N, flags %u (%s)%s; touchdown scrub %.3f m, "
           "parked slide %s",
           what, p->max_dev_m, p->peak_N, p->rep.flags, p->rep.what[0] ? p->rep.what : "none",
           p->finite ? "" : ", NOT FINITE", scrub, p->t_parked_slide_s < 0 ? "none\n" : "");
    if (p->t_parked_slide_s >= 0)
        printf("at %.2f s\n", p->t_parked_slide_s);
}

static void test_park(const hfm_aircraft *ac, const core_ship *ship, double hold_s)
{
    park p;
    printf("%s parked for %.0f s:\n", hfm_aircraft_name(ac), hold_s);
    /* still deck, calm */
    CHECK(park_run(ac, ship, NULL, NULL, 0.0, 0.0, 3.0, 8.0, hold_s, &p) == 0);
    print_park("still deck", &p);
    CHECK(p.finite);
    CHECK(!(p.rep.flags & ~(unsigned)SIM_CONTACT_SLIDE));
    CHECK(p.t_parked_slide_s < 0);
    CHECK(p.max_dev_m < 0.1);
    /* the CG at its rest height (the weight on the struts, the rotor's
     * full-down thrust small) */
    CHECK(p.settle_S[2] < 0);

    /* sea state 4, 30 kt over the deck: stays within 0.1 m, neither sliding
     * nor tipping (the gear and the brakes hold it: measured 0.012 m for the
     * UH-60A over 300 s, 0.007 m for the SA365N over 60 s) */
    sim_sea sea;
    sim_sea_default(&sea);
    sea.state = 4;
    sea.wave_dir_rad = 30 * CORE_DEG_TO_RAD;
    core_err err = {0};
    sim_ship_motion *m = sim_ship_motion_create(ship, &sea, 7, &err);
    CHECK(m != NULL);
    if (m) {
        CHECK(park_run(ac, ship, sim_ship_motion_frame_fn, m, 30 * 0.514444, 0.0, 3.0, 8.0, hold_s, &p) == 0);
        print_park("sea state 4, 30 kt", &p);
        CHECK(p.finite);
        CHECK(p.max_dev_m < 0.1);
        CHECK(!(p.rep.flags & (SIM_CONTACT_SLIDE | SIM_CONTACT_TIP | SIM_CONTACT_CRASH)));
        CHECK(p.t_parked_slide_s < 0);
        sim_ship_motion_destroy(m);
    }
}

/* Parked on a level deck that then tilts nose up: tilted to half of
 * atan(mu_static) it holds the aircraft; tilted past atan(mu_static) the
 * tyres slide (no gear can hold there) and it says so. */
static void test_tilt(const hfm_aircraft *ac, const core_ship *ship)
{
    hfm_gear g;
    hfm_aircraft_gear(ac, &g);
    double lim = atan(g.mu_static);
    /* above atan(mu_static) no gear can hold; at half of it this one's
     * braked mains carry enough of the weight to */
    tilt lo = {0.5 * lim, 6.0, 5.0, 0}, hi = {lim + 8 * CORE_DEG_TO_RAD, 6.0, 5.0, 0};
    park p;
    CHECK(park_run(ac, ship, tilt_frame, &lo, 0.0, 0.0, 3.0, 6.0, 15.0, &p) == 0);
    print_park("deck tilted atan(mu) / 2", &p);
    CHECK(p.finite);
    CHECK(p.t_parked_slide_s < 0);
    CHECK(p.max_dev_m < 0.1);
    CHECK(park_run(ac, ship, tilt_frame, &hi, 0.0, 0.0, 3.0, 6.0, 15.0, &p) == 0);
    print_park("deck tilted atan(mu) + 8 deg", &p);
    CHECK(p.finite);
    CHECK(p.rep.flags & SIM_CONTACT_SLIDE);
    /* not before the deck passes atan(mu) in its tilt */
    CHECK(p.t_parked_slide_s > 6.0 && p.t_parked_slide_s < 21.0);
}

/* Parked on a deck that rolls to 33 deg, past the gear's lateral tip-over
 * angle (31 deg) and below atan(mu_static) (38.7 deg), so that it tips
 * before it can slide (past 35 deg it slides off the deck's side into the
 * sea first, a crash the contact names), the SAS off
 * (on, its cyclic holds the attitude through the hub moment and the
 * aircraft slides off instead, into the sea: test_flight): it rolls over,
 * and says so, during the deck's roll. */
static void test_rollover(const hfm_aircraft *ac, const core_ship *ship)
{
    tilt rl = {33 * CORE_DEG_TO_RAD, 6.0, 5.0, 1};
    park p;
    park_sas = 0;
    CHECK(park_run(ac, ship, tilt_frame, &rl, 0.0, 0.0, 3.0, 6.0, 10.0, &p) == 0);
    park_sas = -1;
    print_park("deck rolled to 33 deg", &p);
    printf("deck rolled to 33 deg: tipped at %.2f s\n", p.rep.t_tip_s);
    CHECK(p.finite);
    CHECK(p.rep.flags & SIM_CONTACT_TIP);
    CHECK(p.rep.t_tip_s > 6.0 && p.rep.t_tip_s < 16.0);
}

/* A drop from 0.5 m: a bounded peak load, nothing not finite, no crash. */
static void test_drop(const hfm_aircraft *ac, const core_ship *ship)
{
    park p;
    CHECK(park_run(ac, ship, NULL, NULL, 0.0, 0.5, 1.0, 3.0, 2.0, &p) == 0);
    double W = hfm_aircraft_weight_N(ac);
    print_park("drop from 0.5 m", &p);
    printf("drop from 0.5 m: peak leg load %.2f W\n", p.peak_N / W);
    CHECK(p.finite);
    CHECK(!(p.rep.flags & SIM_CONTACT_CRASH));
    /* it hit (more than its static share) and the strut held (a few g at most) */
    CHECK(p.peak_N > 0.5 * W);
    CHECK(p.peak_N < 3.0 * W);
}

/* The tail driven backwards into the hangar face: the aircraft faces aft
 * over the spot, moved toward the bow at 1 m/s; the first strike is the
 * point furthest aft meeting the face, named with the block. */
static void test_hangar(const hfm_aircraft *ac, const core_ship *ship)
{
    hfm_gear g;
    hfm_aircraft_gear(ac, &g);
    core_err err = {0};
    sim_contact *c = sim_contact_create(ac, ship, 200.0, &err);
    CHECK(c != NULL);
    if (!c)
        return;
    const core_ship_block *hg = NULL;
    for (int k = 0; k < ship->nblocks; k++)
        if (strcmp(ship->blocks[k].name, "hangar") == 0)
            hg = &ship->blocks[k];
    CHECK(hg != NULL);
    double h = rest_height_m(&g, hfm_aircraft_weight_N(ac));
    /* the point furthest aft that is at the hangar's height */
    double reach = -INFINITY;
    int ip = -1;
    for (int i = 0; i < g.npoints; i++) {
        double z = -h + g.point_B_m[i][2];
        if (hg && z > hg->z0_m && z < hg->z1_m && -g.point_B_m[i][0] > reach) {
            reach = -g.point_B_m[i][0];
            ip = i;
        }
    }
    CHECK(ip >= 0);
    double x_hit = NAN;
    sim_contact_report rep;
    for (int i = 0; i < 2000 && hg && ip >= 0; i++) {
        double t = i / 200.0;
        hfm_body b = {{-3.0 + t, 0, -h}, {-1.0, 0, 0}, {0}, {0, 0, M_PI}};
        sim_ship_deck still;
        sim_ship_deck_still(&still);
        if (sim_contact_step(c, t, &still, &b, &rep)) {
            x_hit = b.pos_S_m[0];
            break;
        }
    }
    printf("hangar: %s at CG x_S %.3f m (face %.2f m, %s %.3f m aft)\n", rep.what, x_hit, hg ? hg->x0_m : NAN,
           ip >= 0 ? g.point_name[ip] : "?", reach);
    CHECK(rep.flags & SIM_CONTACT_CRASH);
    int finite = 1;
    for (int l = 0; l < rep.nlegs; l++)
        finite &= isfinite(rep.leg[l].normal_N) && isfinite(rep.leg[l].friction_N[0]) &&
                  isfinite(rep.leg[l].friction_N[1]) && isfinite(rep.leg[l].compression_m);
    CHECK(rep.nlegs == g.nlegs && finite);
    CHECK(ip >= 0 && strstr(rep.what, g.point_name[ip]) != NULL);
    CHECK(strstr(rep.what, "hangar") != NULL);
    CHECK(hg && fabs(x_hit - (hg->x0_m - reach)) < 0.03);
    sim_contact_destroy(c);
}

/* A [gear] list one value short, and mu_dynamic above mu_static, are
 * errors naming the file, the key and what was expected. */
static int bad_gear(const char *from, const char *to, const char *want)
{
    FILE *in = fopen(UH60, "r");
    char path[] = "/tmp/test_contact_XXXXXX";
    int fd = mkstemp(path);
    FILE *out = fd >= 0 ? fdopen(fd, "w") : NULL;
    if (!in || !out) {
        if (in)
            fclose(in);
        if (out)
            fclose(out);
        return 0;
    }
    char line[1024];
    while (fgets(line, sizeof line, in)) {
        if (strncmp(line, from, strlen(from)) == 0)
            fprintf(out, "%s\n", to);
        else
            fputs(line, out);
    }
    fclose(in);
    fclose(out);
    core_err err = {0};
    hfm_aircraft *ac = hfm_aircraft_load(path, NULL, &err);
    int ok = !ac && strstr(err.msg, path) && strstr(err.msg, want);
    printf("bad [gear]: %s\n", err.msg);
    hfm_aircraft_destroy(ac);
    remove(path);
    return ok;
}

int main(void)
{
    setvbuf(stdout, NULL, _IOLBF, 0);
    core_err err = {0};
    hfm_aircraft *uh = hfm_aircraft_load(UH60, NULL, &err);
    if (!uh)
        fprintf(stderr, "set-up: %s\n", err.msg);
    hfm_aircraft *sa = hfm_aircraft_load(SA365, NULL, &err);
    if (!sa)
        fprintf(stderr, "set-up: %s\n", err.msg);
    core_ship ship;
    int ok = uh && sa && core_ship_load(CG47, &ship, &err) == 0;
    CHECK(ok);
    if (!ok) {
        fprintf(stderr, "set-up: %s\n", err.msg);
        hfm_aircraft_destroy(uh);
        hfm_aircraft_destroy(sa);
        return check_done("test_contact");
    }
    const double hold_s = 300.0; /* the acceptance's 5 minutes */
    CHECK(bad_gear("brake = ", "brake = 1, 1", "[gear] brake: expected 3 values"));
    CHECK(bad_gear("mu_dynamic = ", "mu_dynamic = 0.9", "[gear] mu_dynamic: 0.9 exceeds mu_static 0.8"));
    test_static(uh, &ship);
    test_static(sa, &ship);
    test_park(uh, &ship, hold_s);
    test_park(sa, &ship, 60.0);
    test_tilt(uh, &ship);
    test_rollover(uh, &ship);
    test_drop(uh, &ship);
    test_hangar(uh, &ship);
    hfm_aircraft_destroy(uh);
    hfm_aircraft_destroy(sa);
    return check_done("test_contact");
}
