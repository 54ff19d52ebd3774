/* air.c -- the air the helicopter meets in the flight loop.
 *
 * Model:
 *  - The ship-only airwake is a steady RANS field in the ship frame S,
 *    solved at a reference WOD speed v_ref. Without the rotor a bluff
 *    body's airwake at these Reynolds numbers scales with the wind speed
 *    (the trims use the same scaling, couple/ and awdb_fields_ship_only_air),
 *    so the field's velocities are multiplied by v_wod / v_ref.
 *  - The field is attached to the ship: a point p_E of the Earth frame is
 *    taken into S by the ship's pose at that instant, p_S = C_ES^T (p_E -
 *    o_E), and the field's velocity, which is relative to the ship's mean
 *    (steadily translating) motion, is rotated back and the ship's mean
 *    velocity added: v_E = C_ES v_S + U_E. The airwake's own response to
 *    the ship's oscillation is neglected (quasi-steady airwake, the usual
 *    assumption of piloted ship-airwake simulation with steady CFD; the
 *    deck's oscillation velocities are small against the WOD, a few
 *    tenths of a m/s at sea state 5).
 *  - Outside the field's domain, or with no field: the free stream, the
 *    WOD at anemometer height with the neutral log law over the sea,
 *    u(h) = u_an ln(h / z0) / ln(h_an / z0), z0 = 2e-4 m (open sea; the
 *    roughness the CFD's ABL inflow uses, cfd.h; Richards and Hoxey 1993,
 *    eq. 1), h above the sea surface, clamped at 0.5 m so that the profile
 *    stays finite at the surface.
 *  - Turbulence (optional, sim/turbulence.c): the gust of the frozen
 *    Dryden field at the point, with the local intensity of the field's
 *    turbulent kinetic energy (k scales with the square of the WOD speed,
 *    epsilon with its cube), added to the mean air in S; none in the free
 *    stream (k = 0 there).
 *  - A field offered while flying is blended in: the air is (1 - w) of the
 *    old one plus w of the new, w rising linearly from 0 to 1 over
 *    blend_s, so the air at a point changes by at most |v_new - v_old|
 *    * dt / blend_s per step.
 *  - With a coupled field pair (sim_air_in.inter), the rotor's
 *    interaction with the ship near the rotor station is added to the mean
 *    air (sim/interaction.c).
 *  - In E (sim_air_sample_E), with the ship's frame at the time that the
 *    caller gives (the flight's ship stage, sim/ship_frame.c).
 * Everything here is a pure function of position, time, the inputs given
 * and the fields offered when: the loop stays deterministic.
 */
#include "sim.h"
#include "cfd.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* one air source: a field scaled to the WOD speed, or the free stream (f NULL) */
typedef struct air_src {
    const cfd_field *f;
    double scale;
    int grid; /* the field's grid level (core_grid_level), -1 none or not a level's */
} air_src;

struct sim_air {
    sim_air_opts o;
    air_src cur, old;
    double t_blend0_s; /* blend from old to cur from this time (-inf: none) */
    double wind_S[3];  /* the WOD free stream at anemometer height, in S */
    double ln_an;      /* ln(h_an / z0) */
};

void sim_air_opts_default(sim_air_opts *o)
{
    memset(o, 0, sizeof *o);
    o->anemometer_height_m = 20.0;
    o->z0_m = 2e-4;
    o->blend_s = 3.0;
}

sim_air *sim_air_create(const sim_air_opts *o, core_err *err)
{
    if (!(o->wod_speed_mps >= 0.0) || !(o->anemometer_height_m > o->z0_m) || !(o->z0_m > 0.0) ||
        !(o->blend_s > 0.0) || !isfinite(o->wod_dir_rad)) {
        core_err_set(err, -1, "flight air: expected a WOD speed >= 0, z0 > 0 below the anemometer "
                              "height and a blend time > 0");
        return NULL;
    }
    sim_air *a = calloc(1, sizeof *a);
    if (!a) {
        core_err_set(err, -1, "flight air: out of memory");
        return NULL;
    }
    a->o = *o;
    a->t_blend0_s = -INFINITY;
    core_vec3 w = core_wod_vel_S_mps(o->wod_speed_mps, o->wod_dir_rad);
    a->wind_S[0] = w.x, a->wind_S[1] = w.y, a->wind_S[2] = w.z;
    a->ln_an = log(o->anemometer_height_m / o->z0_m);
    return a;
}

void sim_air_destroy(sim_air *a) { free(a); }

int sim_air_set_field(sim_air *a, const cfd_field *f, double t_s, core_err *err)
{
    double scale = 0.0;
    if (f) {
        const cfd_meta *m = cfd_field_meta(f);
        if (strcmp(m->rotor, core_rotor_name(CORE_ROTOR_OFF)) != 0 || !(m->wod_speed_mps > 0.0))
            return core_err_set(err, -1, "flight air: expected a ship-only field (rotor off) with a WOD speed, got rotor "
                                         "'%s' at %g m/s", m->rotor, m->wod_speed_mps);
        scale = a->o.wod_speed_mps / m->wod_speed_mps;
    }
    a->old = a->cur;
    a->cur.f = f;
    a->cur.scale = scale;
    a->cur.grid = -1;
    if (f) { /* "coarse", "quick-zone": the level's name first */
        char g[sizeof cfd_field_meta(f)->grid];
        snprintf(g, sizeof g, "%s", cfd_field_meta(f)->grid);
        char *dash = strchr(g, '-');
        if (dash)
            *dash = '\0';
        a->cur.grid = core_grid_parse_any(g);
    }
    a->t_blend0_s = t_s;
    return 0;
}

int sim_air_set_wod(sim_air *a, double speed_mps, double dir_rad, core_err *err)
{
    if (!(speed_mps >= 0.0) || !isfinite(dir_rad))
        return core_err_set(err, -1, "flight air: WOD %g m/s from %g rad: expected a speed >= 0, a finite direction",
                            speed_mps, dir_rad);
    a->o.wod_speed_mps = speed_mps;
    a->o.wod_dir_rad = dir_rad;
    core_vec3 w = core_wod_vel_S_mps(speed_mps, dir_rad);
    a->wind_S[0] = w.x, a->wind_S[1] = w.y, a->wind_S[2] = w.z;
    air_src *src[2] = {&a->cur, &a->old};
    for (int i = 0; i < 2; i++)
        if (src[i]->f)
            src[i]->scale = speed_mps / cfd_field_meta(src[i]->f)->wod_speed_mps;
    return 0;
}

int sim_air_grid(const sim_air *a) { return a->cur.f ? a->cur.grid : -1; }

/* The free stream at a point of S: the log law over the sea surface (at
 * z_S = deck height above the waterline). */
static void free_stream_S(const sim_air *a, const double p_S[3], double v_S[3])
{
    double h = fmax(a->o.deck_height_m - p_S[2], 0.5);
    double f = log(h / a->o.z0_m) / a->ln_an;
    for (int i = 0; i < 3; i++)
        v_S[i] = f * a->wind_S[i];
}

/* The field's variables the air needs, in this order: nvar = 3 the
 * velocity, 4 with k, 5 with epsilon too (the rest is not sampled). */
static const int air_vars[5] = {CFD_VAR_U, CFD_VAR_V, CFD_VAR_W, CFD_VAR_K, CFD_VAR_EPS};

/* One source's air in S and (nvar >= 4) its k and (5) epsilon; 1 when it
 * is the free stream (no field, or outside it: k = epsilon = 0). */
static int src_S(const sim_air *a, const air_src *s, const double p_S[3], double v_S[3], double ke[2], int nvar)
{
    ke[0] = ke[1] = 0.0;
    if (s->f) {
        double o[5];
        if (cfd_field_sample_vars(s->f, p_S, air_vars, nvar, o) == 0) {
            v_S[0] = s->scale * o[0];
            v_S[1] = s->scale * o[1];
            v_S[2] = s->scale * o[2];
            if (nvar > 3)
                ke[0] = s->scale * s->scale * fmax(o[3], 0.0);
            if (nvar > 4)
                ke[1] = s->scale * s->scale * s->scale * fmax(o[4], 0.0);
            return 0;
        }
    }
    free_stream_S(a, p_S, v_S);
    return 1;
}

double sim_air_blend(const sim_air *a, double t_s)
{
    if (!isfinite(a->t_blend0_s))
        return 1.0;
    return fmin(fmax((t_s - a->t_blend0_s) / a->o.blend_s, 0.0), 1.0);
}

int sim_air_mean_S(const sim_air *a, const double p_S[3], double t_s, double v_S[3], double *k_m2ps2,
                   double *eps_m2ps3)
{
    double ke[2];
    int nvar = eps_m2ps3 ? 5 : k_m2ps2 ? 4 : 3;
    int free_cur = src_S(a, &a->cur, p_S, v_S, ke, nvar);
    double w = sim_air_blend(a, t_s);
    if (w < 1.0) {
        double vo[3], keo[2];
        src_S(a, &a->old, p_S, vo, keo, nvar);
        for (int i = 0; i < 3; i++)
            v_S[i] = w * v_S[i] + (1.0 - w) * vo[i];
        for (int i = 0; i < 2; i++)
            ke[i] = w * ke[i] + (1.0 - w) * keo[i];
    }
    if (k_m2ps2)
        *k_m2ps2 = ke[0];
    if (eps_m2ps3)
        *eps_m2ps3 = ke[1];
    return free_cur;
}

int sim_air_sample_S(const sim_air *a, const sim_air_in *in, const double p_S[3], double t_s, double v_S[3])
{
    const sim_turb *turb = in ? in->turb : NULL;
    double k = 0.0;
    int rc = sim_air_mean_S(a, p_S, t_s, v_S, turb ? &k : NULL, NULL);
    if (in && in->inter) /* the coupled rotor interaction near the station */
        sim_interaction_apply(in->inter, p_S, v_S);
    if (turb && k > 0.0) {
        double g[3];
        if (sim_turb_sample(turb, p_S, k, g) == 0)
            for (int i = 0; i < 3; i++)
                v_S[i] += g[i];
    }
    return rc;
}

void sim_air_sample_E(const sim_air *a, const sim_air_in *in, const sim_ship_frame *fr, const double pos_E_m[3],
                      double t_s, double vel_E_mps[3])
{
    double d[3], p_S[3], v_S[3];
    for (int i = 0; i < 3; i++)
        d[i] = pos_E_m[i] - fr->origin_E_m[i];
    for (int i = 0; i < 3; i++) /* C_ES^T d */
        p_S[i] = fr->C_ES[0 * 3 + i] * d[0] + fr->C_ES[1 * 3 + i] * d[1] + fr->C_ES[2 * 3 + i] * d[2];
    sim_air_sample_S(a, in, p_S, t_s, v_S);
    for (int i = 0; i < 3; i++)
        vel_E_mps[i] = fr->C_ES[i * 3 + 0] * v_S[0] + fr->C_ES[i * 3 + 1] * v_S[1] + fr->C_ES[i * 3 + 2] * v_S[2] +
                       fr->mean_vel_E_mps[i];
}

unsigned sim_air_flags(const sim_air *a, const sim_interaction *inter, double t_s)
{
    unsigned fl = 0;
    if (!a->cur.f)
        fl |= SIM_AIR_FREE_STREAM;
    if (sim_air_blend(a, t_s) < 1.0)
        fl |= SIM_AIR_BLENDING;
    if (inter) {
        sim_interaction_info ii;
        sim_interaction_state(inter, &ii);
        if (ii.weight * ii.factor > 0.0)
            fl |= SIM_AIR_INTERACTION;
    }
    return fl;
}
