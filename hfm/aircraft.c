/* aircraft.c -- the aircraft data file (INI) read into hfm_aircraft.
 *
 * Every parameter is required and range-checked by core's typed getters, so a
 * missing or non-physical value is an error "file:line: [section] key: ...";
 * a few cross-checks (root cut-out inside the blade, table abscissae
 * increasing, the airfoil table spanning -180..180 deg) follow. The
 * [rejection] section belongs to shol and is skipped. Tables are resampled
 * here so that the evaluation never searches: the airfoil on a 1 deg grid.
 */
#include "hfm_priv.h"

#include <stdlib.h>
#include <string.h>

#define D2R CORE_DEG_TO_RAD

double hfm_table_eval(const hfm_table *t, double x)
{
    if (x <= t->x[0])
        return t->y[0];
    if (x >= t->x[t->n - 1])
        return t->y[t->n - 1];
    int i = 1;
    while (t->x[i] < x)
        i++;
    double f = (x - t->x[i - 1]) / (t->x[i] - t->x[i - 1]);
    return t->y[i - 1] + f * (t->y[i] - t->y[i - 1]);
}

/* Getter shorthands: each returns from the loader on failure. */
#define GETD(sec, key, lo, hi, dst)                                                 \
    do {                                                                            \
        if (core_ini_get_double(ini, sec, key, 1, lo, hi, &(dst), err))             \
            goto fail;                                                              \
    } while (0)

static int get_vec3(core_ini *ini, const char *sec, const char *key, double lo, double hi,
                    double out[3], core_err *err)
{
    int cnt = 0;
    int rc = core_ini_get_doubles(ini, sec, key, 1, lo, hi, out, 3, &cnt, err);
    if (rc)
        return -1;
    if (cnt != 3) {
        const core_ini_entry *e = core_ini_find(ini, sec, key);
        return core_err_set(err, -1, "%s:%d: [%s] %s: expected 3 numbers (x, y, z), got %d",
                            core_ini_path(ini), e ? e->line : 0, sec, key, cnt);
    }
    return 0;
}

/* A table from two keys (abscissa in deg, values in [lo, hi]). */
static int get_table(core_ini *ini, const char *sec, const char *kx, const char *ky, double lo,
                     double hi, hfm_table *t, core_err *err)
{
    int nx = 0, ny = 0;
    if (core_ini_get_doubles(ini, sec, kx, 1, -180.0, 180.0, t->x, HFM_TAB_MAX, &nx, err) ||
        core_ini_get_doubles(ini, sec, ky, 1, lo, hi, t->y, HFM_TAB_MAX, &ny, err))
        return -1;
    const core_ini_entry *e = core_ini_find(ini, sec, ky);
    if (nx != ny)
        return core_err_set(err, -1, "%s:%d: [%s] %s: %d values for %d abscissae in %s",
                            core_ini_path(ini), e->line, sec, ky, ny, nx, kx);
    for (int i = 1; i < nx; i++)
        if (!(t->x[i] > t->x[i - 1])) {
            e = core_ini_find(ini, sec, kx);
            return core_err_set(err, -1, "%s:%d: [%s] %s: abscissae must increase (item %d)",
                                core_ini_path(ini), e->line, sec, kx, i + 1);
        }
    for (int i = 0; i < nx; i++)
        t->x[i] *= D2R;
    t->n = nx;
    return 0;
}

static int load_airfoil(core_ini *ini, hfm_airfoil *af, core_err *err)
{
    hfm_table cl, cd;
    const char *S = "main_rotor_airfoil";
    if (get_table(ini, S, "alpha_deg", "cl", -3.0, 3.0, &cl, err))
        return -1;
    if (get_table(ini, S, "alpha_deg", "cd", 0.0, 3.0, &cd, err))
        return -1;
    if (cl.x[0] > -CORE_PI + 1e-9 || cl.x[cl.n - 1] < CORE_PI - 1e-9) {
        const core_ini_entry *e = core_ini_find(ini, S, "alpha_deg");
        return core_err_set(err, -1,
                            "%s:%d: [%s] alpha_deg: the table must span -180 to 180 deg "
                            "(reversed flow)",
                            core_ini_path(ini), e->line, S);
    }
    for (int i = 0; i <= 360; i++) {
        double a = (i - 180) * D2R;
        af->cl[i] = hfm_table_eval(&cl, a);
        af->cd[i] = hfm_table_eval(&cd, a);
    }
    return 0;
}

static int load_surface(core_ini *ini, const char *S, hfm_surf *s, int vertical, core_err *err)
{
    s->vertical = vertical;
    if (get_vec3(ini, S, "pos_B_m", -50.0, 50.0, s->pos_B, err))
        return -1;
    if (core_ini_get_double(ini, S, "area_m2", 1, 1e-3, 100.0, &s->area, err) ||
        core_ini_get_double(ini, S, "aspect_ratio", 1, 0.2, 20.0, &s->ar, err) ||
        core_ini_get_double(ini, S, "lift_slope_per_rad", 1, 0.5, 7.0, &s->a, err) ||
        core_ini_get_double(ini, S, "clmax", 1, 0.2, 2.5, &s->clmax, err) ||
        core_ini_get_double(ini, S, "cd0", 1, 0.0, 0.2, &s->cd0, err))
        return -1;
    s->schedule = HFM_STAB_FIXED;
    if (!vertical && core_ini_get_enum(ini, S, "schedule", 1, "fixed|uh60a", &s->schedule, err))
        return -1;
    s->incidence = 0.0;
    if (s->schedule == HFM_STAB_FIXED) {
        if (core_ini_get_double(ini, S, "incidence_deg", 1, -45.0, 45.0, &s->incidence, err))
            return -1;
        s->incidence *= D2R;
    }
    return 0;
}

hfm_aircraft *hfm_aircraft_load(const char *path, const core_log *log, core_err *err)
{
    core_ini *ini = core_ini_load(path, err);
    if (!ini)
        return NULL;
    hfm_aircraft *ac = calloc(1, sizeof *ac);
    if (!ac) {
        core_err_set(err, -1, "%s: out of memory", path);
        core_ini_destroy(ini);
        return NULL;
    }
    const char *A = "aircraft", *M = "main_rotor", *T = "tail_rotor", *F = "fuselage",
               *C = "controls";
    double ixx, iyy, izz, ixz, d;
    long l;
    int sense, e;

    if (core_ini_get_string(ini, A, "name", 1, ac->name, sizeof ac->name, err))
        goto fail;
    GETD(A, "mass_kg", 100.0, 1e5, ac->mass);
    GETD(A, "Ixx_kgm2", 1.0, 1e7, ixx);
    GETD(A, "Iyy_kgm2", 1.0, 1e7, iyy);
    GETD(A, "Izz_kgm2", 1.0, 1e7, izz);
    GETD(A, "Ixz_kgm2", -1e6, 1e6, ixz);
    if (ixz * ixz >= ixx * izz) {
        const core_ini_entry *en = core_ini_find(ini, A, "Ixz_kgm2");
        core_err_set(err, -1, "%s:%d: [%s] Ixz_kgm2: inertia matrix not positive definite",
                     path, en->line, A);
        goto fail;
    }
    {
        /* A rigid body's principal moments obey the triangle inequality
         * (I1 + I2 >= I3: each is a sum of two of the three second moments
         * of mass); a data file that breaks it is mistyped, and the 6-DOF
         * equations would still run on it. The x-z block's principal
         * moments, and Iyy. */
        double mean = 0.5 * (ixx + izz), rad = sqrt(0.25 * (ixx - izz) * (ixx - izz) + ixz * ixz);
        double p[3] = {mean + rad, mean - rad, iyy};
        /* largest first: only the largest can exceed the other two's sum */
        for (int a = 0; a < 2; a++)
            for (int b = a + 1; b < 3; b++)
                if (p[b] > p[a]) {
                    double t = p[a];
                    p[a] = p[b];
                    p[b] = t;
                }
        if (p[0] > (p[1] + p[2]) * (1.0 + 1e-9)) {
            core_err_set(err, -1,
                         "%s: [%s] Ixx_kgm2, Iyy_kgm2, Izz_kgm2, Ixz_kgm2: principal moments %.0f, %.0f, %.0f "
                         "kg m^2 break the triangle inequality (%.0f > %.0f + %.0f: each must be at most the sum "
                         "of the other two)",
                         path, A, p[0], p[1], p[2], p[0], p[1], p[2]);
            goto fail;
        }
    }
    double I[3][3] = {{ixx, 0, -ixz}, {0, iyy, 0}, {-ixz, 0, izz}};
    memcpy(ac->I, I, sizeof I);
    double det = ixx * izz - ixz * ixz;
    double Ii[3][3] = {{izz / det, 0, ixz / det}, {0, 1.0 / iyy, 0}, {ixz / det, 0, ixx / det}};
    memcpy(ac->Iinv, Ii, sizeof Ii);

    /* main rotor */
    hfm_mr *mr = &ac->mr;
    if (core_ini_get_int(ini, M, "blades", 1, 2, HFM_MAX_BLADES, &l, err))
        goto fail;
    mr->nb = (int)l;
    if (core_ini_get_enum(ini, M, "sense", 1, "ccw|cw", &sense, err))
        goto fail;
    mr->sense = sense == 0 ? 1 : -1;
    GETD(M, "radius_m", 0.5, 30.0, mr->R);
    GETD(M, "omega_radps", 1.0, 200.0, mr->omega);
    GETD(M, "chord_m", 0.01, 3.0, mr->chord);
    GETD(M, "hinge_offset_m", 0.0, 0.3 * mr->R, mr->e);
    GETD(M, "root_cutout_m", mr->e, 0.5 * mr->R, mr->root);
    GETD(M, "tip_loss", 0.85, 1.0, mr->B);
    GETD(M, "twist_deg", -40.0, 10.0, mr->twist);
    mr->twist *= D2R;
    GETD(M, "twist_ref_r_over_R", 0.0, 1.0, mr->twist_ref);
    GETD(M, "blade_flap_inertia_kgm2", 1.0, 1e5, mr->I_beta);
    GETD(M, "blade_first_moment_kgm", 0.1, 1e4, mr->S_beta);
    GETD(M, "blade_mass_kg", 0.1, 2000.0, mr->m_blade);
    /* the blade's mass moments about the flap hinge, from one mass
     * distribution over the span R - e: S^2 <= m I (Cauchy-Schwarz),
     * S <= m (R - e) and I <= m (R - e)^2 */
    {
        const double span = mr->R - mr->e, m = mr->m_blade, S = mr->S_beta, Ib = mr->I_beta;
        const char *why = S * S > m * Ib * (1.0 + 1e-9)                 ? "first moment^2 > mass x flap inertia"
                          : S > m * span * (1.0 + 1e-9)                  ? "first moment > mass x (radius - hinge offset)"
                          : Ib > m * span * span * (1.0 + 1e-9)          ? "flap inertia > mass x (radius - hinge offset)^2"
                                                                         : NULL;
        if (why) {
            core_err_set(err, -1,
                         "%s: [%s] blade_flap_inertia_kgm2 %g, blade_first_moment_kgm %g, blade_mass_kg %g: %s: "
                         "no blade has these",
                         path, M, Ib, S, m, why);
            goto fail;
        }
    }
    GETD(M, "flap_spring_Nmprad", 0.0, 1e7, mr->K_beta);
    GETD(M, "shaft_tilt_deg", -15.0, 15.0, mr->shaft_tilt);
    mr->shaft_tilt *= D2R;
    if (get_vec3(ini, M, "hub_B_m", -20.0, 20.0, mr->hub_B, err))
        goto fail;
    if (core_ini_get_int(ini, M, "segments", 1, 8, HFM_MAX_SEG, &l, err))
        goto fail;
    mr->nseg = (int)l;
    if (core_ini_get_int(ini, M, "trim_azimuths", 1, 8, HFM_MAX_AZ, &l, err))
        goto fail;
    mr->naz = (int)l;
    GETD(M, "wake_factor_fuselage", 0.0, 2.5, mr->k_fus);
    GETD(M, "wake_factor_tail", 0.0, 2.5, mr->k_tail);
    if (load_airfoil(ini, &mr->af, err))
        goto fail;
    mr->rho = CORE_RHO_SL_KGPM3;
    mr->area = CORE_PI * mr->R * mr->R;
    mr->hqc = 0.5 * mr->rho * mr->chord;
    mr->inv_I_beta = 1.0 / mr->I_beta;
    mr->inv_R = 1.0 / mr->R;
    for (int j = 0; j < mr->naz; j++) {
        mr->az_c[j] = cos(2.0 * CORE_PI * j / mr->naz);
        mr->az_s[j] = sin(2.0 * CORE_PI * j / mr->naz);
    }
    /* hub axes: z down the shaft, tilted forward by the shaft tilt */
    {
        double s = sin(mr->shaft_tilt), c = cos(mr->shaft_tilt);
        double xh[3] = {c, 0, s}, yh[3] = {0, 1, 0}, zh[3] = {-s, 0, c};
        for (int i = 0; i < 3; i++) {
            mr->C_BH[i][0] = xh[i];
            mr->C_BH[i][1] = yh[i];
            mr->C_BH[i][2] = zh[i];
        }
    }
    /* radial segments of equal width; the lift stops at the tip-loss radius */
    {
        double dr = (mr->R - mr->root) / mr->nseg, rB = mr->B * mr->R;
        for (int i = 0; i < mr->nseg; i++) {
            double r0 = mr->root + i * dr, r1 = r0 + dr;
            mr->r[i] = 0.5 * (r0 + r1);
            mr->drd[i] = dr;
            mr->drl[i] = r1 <= rB ? dr : (r0 >= rB ? 0.0 : rB - r0);
            mr->x[i] = mr->r[i] - mr->e;
            mr->tw[i] = mr->twist * mr->r[i] / mr->R;
        }
    }

    /* tail rotor */
    hfm_tr *tr = &ac->tr;
    if (core_ini_get_enum(ini, T, "type", 1, "open|fenestron", &tr->kind, err))
        goto fail;
    if (core_ini_get_int(ini, T, "blades", 1, 2, 20, &l, err))
        goto fail;
    tr->nb = (int)l;
    GETD(T, "radius_m", 0.1, 5.0, tr->R);
    GETD(T, "omega_radps", 10.0, 1000.0, tr->omega);
    GETD(T, "chord_m", 0.005, 1.0, tr->chord);
    GETD(T, "lift_slope_per_rad", 2.0, 7.0, tr->a);
    GETD(T, "cd0", 0.0, 0.05, tr->cd0);
    GETD(T, "twist_deg", -40.0, 10.0, tr->twist);
    tr->twist *= D2R;
    GETD(T, "pitch_ref_r_over_R", 0.0, 1.0, tr->twist_ref);
    GETD(T, "tip_loss", 0.85, 1.0, tr->B);
    GETD(T, "delta3_deg", 0.0, 60.0, d);
    tr->tan_d3 = tan(d * D2R);
    GETD(T, "lock_number", 0.0, 20.0, tr->lock);
    if (get_vec3(ini, T, "hub_B_m", -30.0, 30.0, tr->hub_B, err))
        goto fail;
    if (core_ini_get_enum(ini, T, "thrust_side", 1, "starboard|port", &e, err))
        goto fail;
    GETD(T, "cant_deg", -45.0, 45.0, d);
    {
        double side = e == 0 ? 1.0 : -1.0;
        tr->dir_B[0] = 0.0;
        tr->dir_B[1] = side * cos(d * D2R);
        tr->dir_B[2] = -sin(d * D2R);
    }
    GETD(T, "blockage", 0.5, 1.0, tr->blockage);
    GETD(T, "blockage_below_kt", 0.0, 100.0, tr->blockage_kt);
    tr->fan_fraction = 1.0;
    if (tr->kind == HFM_TR_FENESTRON)
        GETD(T, "fan_thrust_fraction", 0.3, 1.0, tr->fan_fraction);
    tr->sigma = tr->nb * tr->chord / (CORE_PI * tr->R);
    if (tr->sigma > 0.8) {
        const core_ini_entry *en = core_ini_find(ini, T, "chord_m");
        core_err_set(err, -1, "%s:%d: [%s] chord_m: solidity %.3f is not physical", path,
                     en->line, T, tr->sigma);
        goto fail;
    }

    /* fuselage */
    hfm_fus *fu = &ac->fus;
    if (get_vec3(ini, F, "ref_B_m", -20.0, 20.0, fu->ref_B, err) ||
        get_table(ini, F, "drag_alpha_deg", "drag_m2", 0.0, 100.0, &fu->drag, err) ||
        get_table(ini, F, "lift_alpha_deg", "lift_m2", -50.0, 50.0, &fu->lift, err) ||
        get_table(ini, F, "pitch_alpha_deg", "pitch_m3", -500.0, 500.0, &fu->pitch, err) ||
        get_table(ini, F, "sideslip_beta_deg", "sideslip_drag_m2", 0.0, 100.0, &fu->dbeta, err))
        goto fail;
    GETD(F, "yaw_m3_at_10deg", 0.0, 500.0, fu->yaw_m3_10deg);
    GETD(F, "side_force_m2", 0.0, 100.0, fu->side_m2);

    if (load_surface(ini, "stabilator", &ac->stab, 0, err) ||
        load_surface(ini, "fin", &ac->fin, 1, err))
        goto fail;

    /* rigging */
    hfm_rig *rg = &ac->rig;
    GETD(C, "collective_travel_in", 1.0, 30.0, rg->coll_travel);
    GETD(C, "collective_pitch0_deg", -10.0, 40.0, rg->coll_pitch0);
    GETD(C, "collective_deg_per_in", 0.1, 10.0, rg->coll_gain);
    GETD(C, "long_travel_in", 1.0, 30.0, rg->long_travel);
    GETD(C, "long_deg_per_in", 0.1, 10.0, rg->long_gain);
    GETD(C, "lat_travel_in", 1.0, 30.0, rg->lat_travel);
    GETD(C, "lat_deg_per_in", 0.1, 10.0, rg->lat_gain);
    GETD(C, "pedal_travel_in", 1.0, 30.0, rg->ped_travel);
    GETD(C, "tr_pitch0_deg", -30.0, 50.0, rg->tr_pitch0);
    GETD(C, "tr_deg_per_in", -20.0, 20.0, rg->tr_gain);
    GETD(C, "mix_coll_to_long", -2.0, 2.0, rg->mix_cl);
    GETD(C, "mix_ped_to_long", -2.0, 2.0, rg->mix_pl);
    GETD(C, "mix_coll_to_lat", -2.0, 2.0, rg->mix_ca);
    GETD(C, "mix_coll_to_ped", -2.0, 2.0, rg->mix_cp);
    GETD(C, "mix_coll_ref_in", 0.0, 30.0, rg->mix_cref);
    GETD(C, "swash_phase_deg", -45.0, 45.0, rg->swash_phase);
    rg->swash_phase *= D2R;
    rg->swash_c = cos(rg->swash_phase);
    rg->swash_s = sin(rg->swash_phase);
    if (fabs(rg->tr_gain) < 0.1) {
        const core_ini_entry *en = core_ini_find(ini, C, "tr_deg_per_in");
        core_err_set(err, -1, "%s:%d: [%s] tr_deg_per_in: pedal gain too small (|gain| >= 0.1)",
                     path, en->line, C);
        goto fail;
    }

    core_ini_skip_section(ini, "rejection");
    if (core_ini_check_unused(ini, err))
        goto fail;
    core_ini_destroy(ini);
    core_log_msg(log, CORE_LOG_INFO, "hfm: loaded %s (%s), %.0f kg, %d blades, %d segments",
                 ac->name, path, ac->mass, mr->nb, mr->nseg);
    return ac;
fail:
    core_ini_destroy(ini);
    free(ac);
    return NULL;
}

void hfm_aircraft_destroy(hfm_aircraft *ac)
{
    free(ac);
}
const char *hfm_aircraft_name(const hfm_aircraft *ac)
{
    return ac->name;
}
double hfm_aircraft_mass_kg(const hfm_aircraft *ac)
{
    return ac->mass;
}
double hfm_aircraft_weight_N(const hfm_aircraft *ac)
{
    return ac->mass * CORE_G_MPS2;
}
int hfm_aircraft_blades(const hfm_aircraft *ac)
{
    return ac->mr.nb;
}
double hfm_aircraft_rotor_radius_m(const hfm_aircraft *ac)
{
    return ac->mr.R;
}
double hfm_aircraft_rotor_omega_radps(const hfm_aircraft *ac)
{
    return ac->mr.omega;
}
int hfm_aircraft_rotor_ccw(const hfm_aircraft *ac)
{
    return ac->mr.sense > 0;
}

/* Controls through the rig (stick inches) and mixing to blade angles. */
void hfm_controls_to_pitch(const hfm_aircraft *ac, const hfm_controls *u, double *theta0_rad,
                           double *A1_rad, double *B1_rad, double *theta_tr_rad)
{
    const hfm_rig *g = &ac->rig;
    double xc = u->collective_pct / 100.0 * g->coll_travel;           /* from bottom */
    double xl = (50.0 - u->long_pct) / 100.0 * g->long_travel;         /* + forward */
    double xa = (u->lat_pct - 50.0) / 100.0 * g->lat_travel;           /* + right */
    double xp = (u->pedal_pct - 50.0) / 100.0 * g->ped_travel;         /* + right */
    double dc = xc - g->mix_cref;
    double xl_e = xl + g->mix_cl * dc + g->mix_pl * xp;
    double xa_e = xa + g->mix_ca * dc;
    double xp_e = xp + g->mix_cp * dc;
    double B1 = g->long_gain * xl_e * D2R, A1 = g->lat_gain * xa_e * D2R;
    double c = g->swash_c, s = g->swash_s;
    *theta0_rad = (g->coll_pitch0 + g->coll_gain * xc) * D2R;
    *A1_rad = c * A1 + s * B1;
    *B1_rad = c * B1 - s * A1;
    *theta_tr_rad = (g->tr_pitch0 + g->tr_gain * xp_e) * D2R;
}
