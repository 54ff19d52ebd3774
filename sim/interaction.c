/* interaction.c -- the coupled rotor interaction near the rotor station in
 * the flight loop's air, and the projection of an interaction over a rotor
 * disk on the flight model's inflow modes (shared with couple/).
 *
 * Model:
 *  - The coupling (couple/, seed paper section 2.5) trims the helicopter in
 *    the air  wind + (coupled - isolated): the coupled field (ship and
 *    rotor, the rotor an actuator disk at the trimmed hub) less the
 *    isolated rotor's field (the same disk, wind and grid, no ship), plus
 *    the uniform WOD. The flight model's own Pitt-Peters inflow is the
 *    isolated rotor's wake; the difference holds the ship's airwake and
 *    what the rotor and the ship do to each other (ground effect on the
 *    deck, the airwake pushed and pulled by the rotor's slipstream).
 *  - The loop flies the ship-only airwake S (sim/air.c). The interaction
 *    velocity is what the coupled air adds to it:
 *        v_int(p) = wind + (coupled - isolated)(p) - S(p),
 *    so that at the station, with weight 1, the loop's air S + v_int is
 *    the coupling's air exactly, whatever ship-only field the loop flies.
 *  - Over the rotor disk (within 1.1 R of the shaft and 0.3 R of the disk
 *    plane) the coupled - isolated difference is projected on the inflow
 *    modes of the Pitt-Peters model (uniform and first harmonics, linear in
 *    r; Peters and HaQuang 1988, "Dynamic inflow for practical
 *    applications", JAHS 33(4)) by area-weighted least squares on a polar
 *    grid over 0.2 R to R, as the coupling does (couple/interaction.c says
 *    why: the pointwise difference of two slipstream edges a cell wide is
 *    noise at the blade tips). Elsewhere (fuselage, tail rotor, empennage)
 *    it is pointwise; outside the coupled pair's domain it is zero.
 *  - The loop's air is  S + g v_int,  g = w(d) f(T):
 *    * w, the place: the interaction is a property of the rotor at the
 *      place the coupled field put it (the deck below it, the hangar face
 *      beside it); a rotor elsewhere has another interaction, which the
 *      database does not hold. The weight is 1 while the hub is within
 *      d_in = 0.25 R of where the field's rotor was (the ADS-33E-PRF
 *      precision hover's adequate box, +-6 ft = 1.8 m, is 0.22 R of the
 *      UH-60A: a rotor kept over the spot stays in the field's
 *      interaction), and fades to 0 over one rotor radius beyond, with the
 *      smoothstep w = 1 - s^2 (3 - 2 s), s = (d - d_in) / R in [0, 1]: the
 *      length over which a disk's slipstream and its ground effect change
 *      (Cheeseman and Bennett's T_IGE / T_OGE = 1 / (1 - (R / 4z)^2): 6.7 %
 *      more thrust at z = R, 1.6 % at 2 R), and C1, so the air's rate of
 *      change stays bounded: between two steps g changes by at most
 *      1.5 |v_hub| dt / R. The hub's displacement is the CG's from the
 *      station (the hub offset from the CG is held at the field's: an
 *      attitude change of 5 deg moves the hub 2 m above the CG by 0.17 m,
 *      0.02 R). The blade elements are those within the disk region of
 *      the hub where it is now; the modes they get are the fitted linear
 *      field of the place (x, y in the fit's disk frame from the field's
 *      hub), so that the interaction at a point does not depend on which
 *      side of a region's edge it is sampled from, beyond the projection.
 *    * f, the thrust: the interaction is taken as proportional to the
 *      rotor's induced velocity, the velocity the rotor gives the air that
 *      the deck and the airwake then turn (in ground effect the induced
 *      velocity's change is a fraction of it that depends on the height
 *      alone; Cheeseman and Bennett 1955, ARC R&M 3021). Glauert's
 *      momentum theory with the WOD V as the rotor's free stream, at zero
 *      disk incidence (Leishman, "Principles of Helicopter Aerodynamics",
 *      2nd ed., ch. 2), gives it: v^2 (V^2 + v^2) = (T / (2 rho A))^2, so
 *      f = v(T) / v(T_field): sqrt(T / T_field) in hover, T / T_field in
 *      fast wind. T is the flight model's thrust through a first-order lag
 *      of the wake's transport time over a radius at the field's thrust,
 *      tau = R / sqrt(V^2 + v_field^2) (0.70 s for the UH-60A at 70 kN in
 *      hover, 0.59 s in 10 m/s): the interaction follows the slipstream,
 *      not each blade passage.
 *  - A deck-zone pair (coupled and isolated fields over the deck zone
 *    only, couple.h's settings.zone) holds the zone's version of the ship
 *    airwake; the coupling adds the whole domain's ship-only airwake less
 *    the zone's own, both scaled to the WOD speed, so that the zone adds
 *    only what the rotor changes (couple/couple.c, zone_correction). The
 *    loop does the same: coupled - isolated is then
 *        (coupled - isolated) + (v / v_ref) (S_whole - S_zone)
 *    in every formula above, and outside the zone the interaction is 0.
 *  - The coupling under-relaxes its last iteration against the one before
 *    (half each); the loop takes the pair it is given whole. The
 *    difference is within the coupling's 5 % tolerance on a converged
 *    point. The coupling's flight model skews its rotor wake on the tail
 *    by the undisturbed wind (hfm_air.wake); the loop's by the air at the
 *    hub, as without the interaction (test_interaction: the trims agree
 *    to 0.002 % of collective all the same).
 * Assumptions: the airwake is quasi-steady (sim/air.c); the interaction's
 * change with the rotor's place and thrust is as above (no field holds
 * more).
 */
#include "sim.h"
#include "cfd.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ------------------------------------------------ the disk's inflow modes */
int sim_disk_modes_in(const sim_disk_modes *dm, const double hub_S_m[3], const double pos_S_m[3], double *rr,
                      double *psi)
{
    core_vec3 d = core_vec3_make(pos_S_m[0] - hub_S_m[0], pos_S_m[1] - hub_S_m[1], pos_S_m[2] - hub_S_m[2]);
    core_vec3 h = core_quat_rotate_inv(dm->q_SH, d);
    double r = sqrt(h.x * h.x + h.y * h.y);
    if (r > 1.1 * dm->R || fabs(h.z) > 0.3 * dm->R)
        return 0;
    *rr = r / dm->R;
    *psi = atan2(h.y, h.x);
    return 1;
}

void sim_disk_modes_fit(sim_disk_modes *dm, const double hub_S_m[3], core_quat q_SH, double R, sim_point_fn fn,
                        void *user)
{
    memcpy(dm->hub_S_m, hub_S_m, sizeof dm->hub_S_m);
    dm->q_SH = q_SH;
    dm->R = R;
    double sm[3] = {0}, sc[3] = {0}, ss[3] = {0}, w0 = 0, wc = 0, ws = 0;
    const int nr = 16, np = 36;
    for (int ir = 0; ir < nr; ir++) {
        double x = 0.2 + 0.8 * (ir + 0.5) / nr; /* r/R */
        for (int ip = 0; ip < np; ip++) {
            double psi = 2.0 * M_PI * (ip + 0.5) / np;
            core_vec3 hp = core_vec3_make(x * R * cos(psi), x * R * sin(psi), 0.0);
            core_vec3 sp = core_quat_rotate(q_SH, hp);
            double pos[3] = {hub_S_m[0] + sp.x, hub_S_m[1] + sp.y, hub_S_m[2] + sp.z}, v[3];
            fn(user, pos, v);
            double wt = x; /* area element r dr dpsi */
            double cc = x * cos(psi), sn = x * sin(psi);
            for (int k = 0; k < 3; k++) {
                sm[k] += wt * v[k];
                sc[k] += wt * v[k] * cc;
                ss[k] += wt * v[k] * sn;
            }
            w0 += wt;
            wc += wt * cc * cc;
            ws += wt * sn * sn;
        }
    }
    for (int k = 0; k < 3; k++) {
        dm->m[k] = sm[k] / w0;
        dm->c[k] = sc[k] / wc;
        dm->s[k] = ss[k] / ws;
    }
}

/* ------------------------------------------------- the loop's interaction */
struct sim_interaction {
    const cfd_field *coupled, *isolated;
    const cfd_field *ship_whole, *ship_zone; /* a deck-zone pair's (NULL: a whole-domain pair) */
    double whole_scale, zone_scale;          /* each to the coupled fields' WOD speed */
    sim_interaction_opts o;
    double wind_S[3];
    double thrust_field_N, vi_field_mps;
    double tau_s;         /* the thrust's lag */
    double area_m2;
    sim_disk_modes dm;
    /* the rotor now (sim_interaction_step) */
    double shift_S_m[3];  /* the CG's displacement from the station */
    double shift_H_m[3];  /* the same in the fit's disk frame */
    double dist_m;
    double thrust_N;      /* through the wake's lag */
    double weight, factor;
};

void sim_interaction_opts_default(sim_interaction_opts *o)
{
    memset(o, 0, sizeof *o);
    o->q_SH.w = 1.0;
    o->rho_kgpm3 = CORE_RHO_SL_KGPM3;
}

/* Glauert's induced velocity (m/s) for thrust T in a free stream V at zero
 * disk incidence: v^2 (V^2 + v^2) = vh^4, vh^2 = T / (2 rho A). */
static double induced_mps(const sim_interaction *ia, double T_N)
{
    if (!(T_N > 0.0))
        return 0.0;
    double V2 = ia->o.wod_speed_mps * ia->o.wod_speed_mps;
    double vh2 = T_N / (2.0 * ia->o.rho_kgpm3 * ia->area_m2);
    return sqrt(0.5 * (-V2 + sqrt(V2 * V2 + 4.0 * vh2 * vh2)));
}

/* coupled - isolated at a point (m/s, S), a deck zone's with the whole
 * domain's ship-only airwake in place of the zone's own; 1 where the pair
 * has no value there (outside its domain), then out is 0. */
static int diff_at(const sim_interaction *ia, const double p[3], double out[3])
{
    double c[CFD_NVARS], i[CFD_NVARS];
    if (cfd_field_sample(ia->coupled, p, c) != 0 || cfd_field_sample(ia->isolated, p, i) != 0) {
        out[0] = out[1] = out[2] = 0.0;
        return 1;
    }
    for (int k = 0; k < 3; k++)
        out[k] = c[k] - i[k];
    if (ia->ship_zone) {
        double sw[CFD_NVARS], sz[CFD_NVARS];
        cfd_field_sample(ia->ship_whole, p, sw);
        cfd_field_sample(ia->ship_zone, p, sz);
        for (int k = 0; k < 3; k++)
            out[k] += ia->whole_scale * sw[k] - ia->zone_scale * sz[k];
    }
    return 0;
}

static int diff_fn(void *user, const double p[3], double out[3])
{
    return diff_at(user, p, out);
}

static int same_case(const cfd_meta *c, const cfd_meta *i, double tol_N)
{
    for (int k = 0; k < 3; k++)
        if (fabs(c->rotor_centre_S_m[k] - i->rotor_centre_S_m[k]) > 0.011)
            return 0;
    return fabs(c->rotor_thrust_N - i->rotor_thrust_N) <= tol_N && fabs(c->wod_speed_mps - i->wod_speed_mps) <= 0.011 &&
           fabs(c->wod_dir_deg - i->wod_dir_deg) <= 0.011 && fabs(c->rotor_radius_m - i->rotor_radius_m) <= 0.011 &&
           strcmp(c->rotor, i->rotor) == 0;
}

sim_interaction *sim_interaction_create(const cfd_field *coupled, const cfd_field *isolated,
                                        const sim_interaction_opts *o, core_err *err)
{
    if (!coupled || !isolated) {
        core_err_set(err, -1, "rotor interaction: expected a coupled and an isolated field");
        return NULL;
    }
    const cfd_meta *mc = cfd_field_meta(coupled), *mi = cfd_field_meta(isolated);
    if (!strcmp(mc->rotor, core_rotor_name(CORE_ROTOR_OFF)) || !(mc->rotor_thrust_N > 0.0) ||
        !(mc->rotor_radius_m > 0.0)) {
        core_err_set(err, -1, "rotor interaction: the coupled field has rotor '%s', thrust %g N, radius %g m: expected "
                              "a rotor with thrust", mc->rotor, mc->rotor_thrust_N, mc->rotor_radius_m);
        return NULL;
    }
    if (!same_case(mc, mi, 0.5)) {
        core_err_set(err, -1, "rotor interaction: the isolated field (rotor '%s', %g N at (%.2f, %.2f, %.2f) m, WOD %.2f "
                              "m/s from %.2f deg) is not the coupled field's case ('%s', %g N at (%.2f, %.2f, %.2f) m, "
                              "%.2f m/s from %.2f deg)", mi->rotor, mi->rotor_thrust_N, mi->rotor_centre_S_m[0],
                     mi->rotor_centre_S_m[1], mi->rotor_centre_S_m[2], mi->wod_speed_mps, mi->wod_dir_deg, mc->rotor,
                     mc->rotor_thrust_N, mc->rotor_centre_S_m[0], mc->rotor_centre_S_m[1], mc->rotor_centre_S_m[2],
                     mc->wod_speed_mps, mc->wod_dir_deg);
        return NULL;
    }
    if (!o->ship_whole != !o->ship_zone) {
        core_err_set(err, -1, "rotor interaction: a deck-zone pair needs both the whole domain's ship-only field and "
                              "the zone's own");
        return NULL;
    }
    if (o->ship_zone) {
        const cfd_meta *mw = cfd_field_meta(o->ship_whole), *mz = cfd_field_meta(o->ship_zone);
        if (strcmp(mw->rotor, core_rotor_name(CORE_ROTOR_OFF)) || strcmp(mz->rotor, core_rotor_name(CORE_ROTOR_OFF)) ||
            !(mw->wod_speed_mps > 0.0) || !(mz->wod_speed_mps > 0.0) ||
            fabs(remainder(mw->wod_dir_deg - mc->wod_dir_deg, 360.0)) > 0.011 ||
            fabs(remainder(mz->wod_dir_deg - mc->wod_dir_deg, 360.0)) > 0.011) {
            core_err_set(err, -1, "rotor interaction: the deck zone's ship-only fields (rotor '%s' and '%s', %.2f and "
                                  "%.2f deg) are not ship-only fields of the coupled field's direction (%.2f deg)",
                         mw->rotor, mz->rotor, mw->wod_dir_deg, mz->wod_dir_deg, mc->wod_dir_deg);
            return NULL;
        }
    }
    double qn = sqrt(o->q_SH.w * o->q_SH.w + o->q_SH.x * o->q_SH.x + o->q_SH.y * o->q_SH.y + o->q_SH.z * o->q_SH.z);
    int st_ok = 1;
    for (int k = 0; k < 3; k++)
        st_ok &= isfinite(o->station_S_m[k]);
    if (!st_ok || !(fabs(qn - 1.0) < 1e-6) || !(o->rho_kgpm3 > 0.0) || !(o->plateau_m >= 0.0) ||
        !(o->fade_m >= 0.0)) {
        core_err_set(err, -1, "rotor interaction: expected a finite station, a unit shaft quaternion, rho > 0 and "
                              "plateau and fade >= 0 (0: the defaults)");
        return NULL;
    }
    sim_interaction *ia = calloc(1, sizeof *ia);
    if (!ia) {
        core_err_set(err, -1, "rotor interaction: out of memory");
        return NULL;
    }
    ia->coupled = coupled;
    ia->isolated = isolated;
    ia->o = *o;
    ia->ship_whole = o->ship_whole;
    ia->ship_zone = o->ship_zone;
    if (ia->ship_zone) {
        ia->whole_scale = mc->wod_speed_mps / cfd_field_meta(o->ship_whole)->wod_speed_mps;
        ia->zone_scale = mc->wod_speed_mps / cfd_field_meta(o->ship_zone)->wod_speed_mps;
    }
    /* the fields' WOD is the coupling's wind */
    ia->o.wod_speed_mps = mc->wod_speed_mps;
    ia->o.wod_dir_rad = mc->wod_dir_deg * CORE_DEG_TO_RAD;
    double R = mc->rotor_radius_m;
    if (!(ia->o.plateau_m > 0.0))
        ia->o.plateau_m = 0.25 * R;
    if (!(ia->o.fade_m > 0.0))
        ia->o.fade_m = R;
    core_vec3 w = core_wod_vel_S_mps(ia->o.wod_speed_mps, ia->o.wod_dir_rad);
    ia->wind_S[0] = w.x, ia->wind_S[1] = w.y, ia->wind_S[2] = w.z;
    ia->area_m2 = CORE_PI * R * R;
    ia->thrust_field_N = mc->rotor_thrust_N;
    ia->vi_field_mps = induced_mps(ia, ia->thrust_field_N);
    ia->tau_s = R / sqrt(ia->o.wod_speed_mps * ia->o.wod_speed_mps + ia->vi_field_mps * ia->vi_field_mps);
    sim_disk_modes_fit(&ia->dm, mc->rotor_centre_S_m, o->q_SH, R, diff_fn, ia);
    ia->thrust_N = ia->thrust_field_N;
    ia->weight = ia->factor = 1.0;
    return ia;
}

void sim_interaction_destroy(sim_interaction *ia) { free(ia); }

static double fade(const sim_interaction *ia, double d)
{
    double s = (d - ia->o.plateau_m) / ia->o.fade_m;
    if (s <= 0.0)
        return 1.0;
    if (s >= 1.0)
        return 0.0;
    return 1.0 - s * s * (3.0 - 2.0 * s);
}

int sim_interaction_step(sim_interaction *ia, const double cg_S_m[3], double thrust_N, double dt_s)
{
    if (!isfinite(cg_S_m[0]) || !isfinite(cg_S_m[1]) || !isfinite(cg_S_m[2]) || !(dt_s >= 0.0))
        return -1;
    double d2 = 0.0;
    for (int k = 0; k < 3; k++) {
        ia->shift_S_m[k] = cg_S_m[k] - ia->o.station_S_m[k];
        d2 += ia->shift_S_m[k] * ia->shift_S_m[k];
    }
    ia->dist_m = sqrt(d2);
    core_vec3 sh = core_quat_rotate_inv(ia->dm.q_SH, core_vec3_make(ia->shift_S_m[0], ia->shift_S_m[1], ia->shift_S_m[2]));
    ia->shift_H_m[0] = sh.x, ia->shift_H_m[1] = sh.y, ia->shift_H_m[2] = sh.z;
    ia->weight = fade(ia, ia->dist_m);
    if (isfinite(thrust_N) && dt_s > 0.0)
        ia->thrust_N += (1.0 - exp(-dt_s / ia->tau_s)) * (thrust_N - ia->thrust_N);
    ia->factor = ia->vi_field_mps > 0.0 ? induced_mps(ia, ia->thrust_N) / ia->vi_field_mps : 0.0;
    return 0;
}

void sim_interaction_apply(const sim_interaction *ia, const double p_S[3], double v_S[3])
{
    double g = ia->weight * ia->factor;
    if (g == 0.0)
        return;
    double u[3];
    /* the point in the fit's disk frame from the field's hub; the disk
     * region (sim_disk_modes_in's) is the hub's where it is now */
    const double *hf = ia->dm.hub_S_m, R = ia->dm.R;
    core_vec3 h = core_quat_rotate_inv(ia->dm.q_SH, core_vec3_make(p_S[0] - hf[0], p_S[1] - hf[1], p_S[2] - hf[2]));
    double x = h.x - ia->shift_H_m[0], y = h.y - ia->shift_H_m[1], z = h.z - ia->shift_H_m[2];
    if (x * x + y * y <= 1.21 * R * R && fabs(z) <= 0.3 * R) {
        /* the place's fitted field: (r/R) cos psi and (r/R) sin psi */
        for (int k = 0; k < 3; k++)
            u[k] = ia->dm.m[k] + ia->dm.c[k] * (h.x / R) + ia->dm.s[k] * (h.y / R);
    } else if (diff_at(ia, p_S, u) != 0)
        return; /* outside the coupled pair: the ship-only air alone */
    for (int k = 0; k < 3; k++)
        v_S[k] += g * (ia->wind_S[k] + u[k] - v_S[k]);
}

void sim_interaction_state(const sim_interaction *ia, sim_interaction_info *s)
{
    memset(s, 0, sizeof *s);
    s->weight = ia->weight;
    s->factor = ia->factor;
    s->dist_m = ia->dist_m;
    s->thrust_N = ia->thrust_N;
    s->thrust_field_N = ia->thrust_field_N;
    memcpy(s->hub_S_m, ia->dm.hub_S_m, sizeof s->hub_S_m);
    memcpy(s->m_mps, ia->dm.m, sizeof s->m_mps);
    memcpy(s->c_mps, ia->dm.c, sizeof s->c_mps);
    memcpy(s->s_mps, ia->dm.s, sizeof s->s_mps);
}
