/* aircraft.c -- the aircraft data file (INI) read into hfm_aircraft.
 *
 * The file's format, key by key, is docs/aircraft-format.md. One loader per
 * section; every parameter is required (but for the few documented as
 * optional, e.g. hub_drag_m2, drag_divergence_mach, the [power] section)
 * and range-checked by core's typed getters, so a missing or non-physical value is an error
 * "file:line: [section] key: ...". A section the loader does not know is an
 * error naming it before any key is read (a misspelt section would otherwise
 * surface as a missing key of the section meant). Cross-checks inside a
 * section (root cut-out inside the blade, table abscissae increasing, the
 * airfoil table spanning -180..180 deg, mass properties some body has)
 * follow its keys; the checks across sections that catch unit slips
 * (hfm_aircraft_check, aircraft_check.c) run on the whole aircraft. The
 * [rejection] section belongs to shol and is skipped; [model_error] is
 * read here (the validation's numbers belong to the aircraft) and handed
 * to shol by couple. Tables are resampled
 * here so that the evaluation never searches: the airfoil on a 1 deg grid.
 */
#include "hfm_priv.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>


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

/* ------------------------------------------------ read-and-check helpers */
/* The file being read and where its errors go. */
typedef struct rd {
    core_ini *ini;
    const char *path;
    core_err *err;
} rd;

int hfm_aircraft_key_line(const core_ini *ini, const char *sec, const char *key)
{
    const core_ini_entry *e = core_ini_find(ini, sec, key);
    return e ? e->line : 0;
}

/* "file:line: [sec] key: why" (the line of the key), returns -1. */
static int rd_fail(const rd *r, const char *sec, const char *key, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
static int rd_fail(const rd *r, const char *sec, const char *key, const char *fmt, ...)
{
    char why[768];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(why, sizeof why, fmt, ap);
    va_end(ap);
    return core_err_set(r->err, -1, "%s:%d: [%s] %s: %s", r->path,
                        hfm_aircraft_key_line(r->ini, sec, key), sec, key, why);
}

/* A required number in [lo, hi]. */
static int rd_num(rd *r, const char *sec, const char *key, double lo, double hi, double *dst)
{
    return core_ini_get_double(r->ini, sec, key, 1, lo, hi, dst, r->err) ? -1 : 0;
}

/* A required angle in degrees in [lo, hi], stored in radians. */
static int rd_deg(rd *r, const char *sec, const char *key, double lo, double hi, double *dst_rad)
{
    double d;
    if (rd_num(r, sec, key, lo, hi, &d))
        return -1;
    *dst_rad = d * CORE_DEG_TO_RAD;
    return 0;
}

/* A required whole number in [lo, hi]. */
static int rd_int(rd *r, const char *sec, const char *key, long lo, long hi, int *dst)
{
    long l;
    if (core_ini_get_int(r->ini, sec, key, 1, lo, hi, &l, r->err))
        return -1;
    *dst = (int)l;
    return 0;
}

/* A required position "x, y, z" with each coordinate in [lo, hi]. */
static int rd_vec3(rd *r, const char *sec, const char *key, double lo, double hi, double out[3])
{
    int cnt = 0;
    if (core_ini_get_doubles(r->ini, sec, key, 1, lo, hi, out, 3, &cnt, r->err))
        return -1;
    if (cnt != 3)
        return rd_fail(r, sec, key, "expected 3 numbers (x, y, z), got %d", cnt);
    return 0;
}

/* A table from two keys (abscissa in deg, increasing; values in [lo, hi]),
 * its abscissa stored in radians. */
static int rd_table(rd *r, const char *sec, const char *kx, const char *ky, double lo, double hi,
                    hfm_table *t)
{
    int nx = 0, ny = 0;
    if (core_ini_get_doubles(r->ini, sec, kx, 1, -180.0, 180.0, t->x, HFM_TAB_MAX, &nx, r->err) ||
        core_ini_get_doubles(r->ini, sec, ky, 1, lo, hi, t->y, HFM_TAB_MAX, &ny, r->err))
        return -1;
    if (nx != ny)
        return rd_fail(r, sec, ky, "%d values for %d abscissae in %s", ny, nx, kx);
    for (int i = 1; i < nx; i++)
        if (!(t->x[i] > t->x[i - 1]))
            return rd_fail(r, sec, kx, "abscissae must increase (item %d)", i + 1);
    for (int i = 0; i < nx; i++)
        t->x[i] *= CORE_DEG_TO_RAD;
    t->n = nx;
    return 0;
}

/* ------------------------------------------------------------- sections */
static const char *const known_sections[] = {"aircraft", "main_rotor", "main_rotor_airfoil",
                                             "tail_rotor", "fuselage",   "stabilator",
                                             "fin",      "controls",   "sas",
                                             "rejection", "gear",      "cockpit",
                                             "power",    "model_error"};

static int check_sections(const rd *r)
{
    for (size_t i = 0; i < core_ini_count(r->ini); i++) {
        const core_ini_entry *e = core_ini_at(r->ini, i);
        int known = 0;
        for (size_t k = 0; k < sizeof known_sections / sizeof known_sections[0]; k++)
            known |= strcmp(e->section, known_sections[k]) == 0;
        if (!known)
            return core_err_set(r->err, -1,
                                "%s:%d: unknown section [%s] (an aircraft file has [aircraft], [main_rotor], "
                                "[main_rotor_airfoil], [tail_rotor], [fuselage], [stabilator], [fin], "
                                "[controls], [sas], [gear], [cockpit], [power], [rejection] and [model_error])",
                                r->path, e->line, e->section);
    }
    return 0;
}

/* [aircraft]: name, mass and inertia about the CG in body axes. */
static int load_mass(rd *r, hfm_aircraft *ac)
{
    const char *A = "aircraft";
    double ixx, iyy, izz, ixz;
    if (core_ini_get_name(r->ini, A, "name", 1, ac->name, sizeof ac->name, r->err) ||
        rd_num(r, A, "mass_kg", 100.0, 1e5, &ac->mass) || rd_num(r, A, "Ixx_kgm2", 1.0, 1e7, &ixx) ||
        rd_num(r, A, "Iyy_kgm2", 1.0, 1e7, &iyy) || rd_num(r, A, "Izz_kgm2", 1.0, 1e7, &izz) ||
        rd_num(r, A, "Ixz_kgm2", -1e6, 1e6, &ixz))
        return -1;
    if (ixz * ixz >= ixx * izz)
        return rd_fail(r, A, "Ixz_kgm2", "inertia matrix not positive definite");
    /* A rigid body's principal moments obey the triangle inequality
     * (I1 + I2 >= I3: each is a sum of two of the three second moments of
     * mass); a data file that breaks it is mistyped, and the 6-DOF
     * equations would still run on it. The x-z block's principal moments,
     * and Iyy. */
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
    if (p[0] > (p[1] + p[2]) * (1.0 + 1e-9))
        return core_err_set(r->err, -1,
                            "%s: [%s] Ixx_kgm2, Iyy_kgm2, Izz_kgm2, Ixz_kgm2: principal moments %.0f, %.0f, %.0f "
                            "kg m^2 break the triangle inequality (%.0f > %.0f + %.0f: each must be at most the sum "
                            "of the other two)",
                            r->path, A, p[0], p[1], p[2], p[0], p[1], p[2]);
    double I[3][3] = {{ixx, 0, -ixz}, {0, iyy, 0}, {-ixz, 0, izz}};
    memcpy(ac->I, I, sizeof I);
    double det = ixx * izz - ixz * ixz;
    double Ii[3][3] = {{izz / det, 0, ixz / det}, {0, 1.0 / iyy, 0}, {ixz / det, 0, ixx / det}};
    memcpy(ac->Iinv, Ii, sizeof Ii);
    return 0;
}

/* [main_rotor]: geometry, blade mass properties, hub, model resolution. */
static int load_main_rotor(rd *r, hfm_mr *mr)
{
    const char *M = "main_rotor";
    int sense;
    if (rd_int(r, M, "blades", 2, HFM_MAX_BLADES, &mr->nb) ||
        core_ini_get_enum(r->ini, M, "sense", 1, "ccw|cw", &sense, r->err))
        return -1;
    mr->sense = sense == 0 ? 1 : -1;
    if (rd_num(r, M, "radius_m", 0.5, 30.0, &mr->R) || rd_num(r, M, "omega_radps", 1.0, 200.0, &mr->omega) ||
        rd_num(r, M, "chord_m", 0.01, 3.0, &mr->chord) ||
        rd_num(r, M, "hinge_offset_m", 0.0, 0.3 * mr->R, &mr->e) ||
        rd_num(r, M, "root_cutout_m", mr->e, 0.5 * mr->R, &mr->root) ||
        rd_num(r, M, "tip_loss", 0.85, 1.0, &mr->B) || rd_deg(r, M, "twist_deg", -40.0, 10.0, &mr->twist) ||
        rd_num(r, M, "twist_ref_r_over_R", 0.0, 1.0, &mr->twist_ref) ||
        rd_num(r, M, "blade_flap_inertia_kgm2", 1.0, 1e5, &mr->I_beta) ||
        rd_num(r, M, "blade_first_moment_kgm", 0.1, 1e4, &mr->S_beta) ||
        rd_num(r, M, "blade_mass_kg", 0.1, 2000.0, &mr->m_blade))
        return -1;
    /* the blade's mass moments about the flap hinge, from one mass
     * distribution over the span R - e: S^2 <= m I (Cauchy-Schwarz),
     * S <= m (R - e) and I <= m (R - e)^2 */
    const double span = mr->R - mr->e, m = mr->m_blade, S = mr->S_beta, Ib = mr->I_beta;
    const char *why = S * S > m * Ib * (1.0 + 1e-9)        ? "first moment^2 > mass x flap inertia"
                      : S > m * span * (1.0 + 1e-9)         ? "first moment > mass x (radius - hinge offset)"
                      : Ib > m * span * span * (1.0 + 1e-9) ? "flap inertia > mass x (radius - hinge offset)^2"
                                                            : NULL;
    if (why)
        return core_err_set(r->err, -1,
                            "%s: [%s] blade_flap_inertia_kgm2 %g, blade_first_moment_kgm %g, blade_mass_kg %g: %s: "
                            "no blade has these",
                            r->path, M, Ib, S, m, why);
    if (rd_num(r, M, "flap_spring_Nmprad", 0.0, 1e7, &mr->K_beta) ||
        rd_deg(r, M, "shaft_tilt_deg", -15.0, 15.0, &mr->shaft_tilt) ||
        rd_vec3(r, M, "hub_B_m", -20.0, 20.0, mr->hub_B) || rd_int(r, M, "segments", 8, HFM_MAX_SEG, &mr->nseg) ||
        rd_int(r, M, "trim_azimuths", 8, HFM_MAX_AZ, &mr->naz))
        return -1;
    /* optional: the hub's (and hub-pylon interference) flat-plate area,
     * 0 when absent (the fuselage table then carries all the airframe drag) */
    mr->hub_drag_m2 = 0.0;
    if (core_ini_get_double(r->ini, M, "hub_drag_m2", 0, 0.0, 20.0, &mr->hub_drag_m2, r->err) < 0)
        return -1;
    /* the wake's velocity at the airframe follows from the wake's path
     * (hfm/body.c); files that still set it by these two factors are
     * refused, naming the key */
    static const char *const gone[2] = {"wake_factor_fuselage", "wake_factor_tail"};
    for (int i = 0; i < 2; i++)
        if (core_ini_find(r->ini, M, gone[i]))
            return rd_fail(r, M, gone[i],
                           "no longer a key: the wake velocity at the airframe grows along the "
                           "wake's path (docs/aircraft-format.md, main-rotor wake); delete the line");
    return 0;
}

/* [main_rotor_airfoil]: cl and cd over the full circle, resampled to 1 deg. */
static int load_airfoil(rd *r, hfm_airfoil *af)
{
    hfm_table cl, cd;
    const char *S = "main_rotor_airfoil";
    if (rd_table(r, S, "alpha_deg", "cl", -3.0, 3.0, &cl) || rd_table(r, S, "alpha_deg", "cd", 0.0, 3.0, &cd))
        return -1;
    if (cl.x[0] > -CORE_PI + 1e-9 || cl.x[cl.n - 1] < CORE_PI - 1e-9)
        return rd_fail(r, S, "alpha_deg", "the table must span -180 to 180 deg (reversed flow)");
    for (int i = 0; i <= 360; i++) {
        double a = (i - 180) * CORE_DEG_TO_RAD;
        af->cl[i] = hfm_table_eval(&cl, a);
        af->cd[i] = hfm_table_eval(&cd, a);
    }
    /* optional: the drag divergence Mach number at zero lift; absent, the
     * table is used at every Mach number (no compressibility) */
    int rc = core_ini_get_double(r->ini, S, "drag_divergence_mach", 0, 0.5, 0.95, &af->mdd0, r->err);
    if (rc < 0)
        return -1;
    af->mach = rc == 0;
    return 0;
}

/* [power] (optional): transmission efficiency and accessory power, between
 * the rotors' shaft power and the engines' output (hfm_loads_power). Absent:
 * efficiency 1, no accessories (engine power = shaft power). Both keys are
 * required once the section is there. */
static int load_power(rd *r, hfm_aircraft *ac)
{
    const char *P = "power";
    ac->xmsn_eff = 1.0;
    ac->acc_W = 0.0;
    if (!core_ini_has_section(r->ini, P))
        return 0;
    double kw;
    if (rd_num(r, P, "transmission_efficiency", 0.5, 1.0, &ac->xmsn_eff) ||
        rd_num(r, P, "accessory_power_kW", 0.0, 1000.0, &kw))
        return -1;
    ac->acc_W = kw * 1e3;
    return 0;
}

/* [model_error] (optional): the model's trim minus a reference's at one
 * airspeed, as the validation measured it (docs/aircraft-format.md).
 * reference and airspeed_kt are required once the section is there, and
 * at least one error; an error key absent is a quantity not validated.
 * The ranges: attitudes within 10 deg, controls within 50 % of travel
 * (an error beyond them is no validated model's). */
static int load_model_error(rd *r, hfm_aircraft *ac)
{
    const char *E = "model_error";
    hfm_model_error *m = &ac->model_error;
    memset(m, 0, sizeof *m);
    m->roll_rad = m->pitch_rad = NAN;
    m->collective_pct = m->long_cyclic_pct = m->lat_cyclic_pct = m->pedal_pct = NAN;
    ac->has_model_error = core_ini_has_section(r->ini, E);
    if (!ac->has_model_error)
        return 0;
    double kt;
    if (core_ini_get_string(r->ini, E, "reference", 1, m->reference, sizeof m->reference, r->err) ||
        rd_num(r, E, "airspeed_kt", 0.0, 250.0, &kt))
        return -1;
    m->airspeed_mps = kt * CORE_KT_TO_MPS;
    static const char *const key[6] = {"roll_deg",        "pitch_deg",      "collective_pct",
                                       "long_cyclic_pct", "lat_cyclic_pct", "pedal_pct"};
    double *dst[6] = {&m->roll_rad,        &m->pitch_rad,      &m->collective_pct,
                      &m->long_cyclic_pct, &m->lat_cyclic_pct, &m->pedal_pct};
    int n = 0;
    for (int k = 0; k < 6; k++) {
        const double lim = k < 2 ? 10.0 : 50.0;
        int rc = core_ini_get_double(r->ini, E, key[k], 0, -lim, lim, dst[k], r->err);
        if (rc < 0)
            return -1;
        if (rc == 0) {
            n++;
            if (k < 2)
                *dst[k] *= CORE_DEG_TO_RAD;
        }
    }
    if (!n)
        return rd_fail(r, E, "reference", "the section states no error: give at least one of roll_deg, pitch_deg, "
                                          "collective_pct, long_cyclic_pct, lat_cyclic_pct, pedal_pct (or leave "
                                          "the section out: not validated)");
    return 0;
}

int hfm_aircraft_model_error(const hfm_aircraft *ac, hfm_model_error *out)
{
    *out = ac->model_error;
    return ac->has_model_error ? 0 : 1;
}

/* What the blade-element loop uses, derived once from the main rotor's data. */
static void derive_main_rotor(hfm_mr *mr)
{
    mr->rho = CORE_RHO_SL_KGPM3;
    mr->area = CORE_PI * mr->R * mr->R;
    mr->hqc = 0.5 * mr->rho * mr->chord;
    mr->inv_I_beta = 1.0 / mr->I_beta;
    mr->inv_R = 1.0 / mr->R;
    mr->hub_dq = 0.5 * mr->rho * mr->hub_drag_m2 / mr->nb;
    for (int j = 0; j < mr->naz; j++) {
        mr->az_c[j] = cos(2.0 * CORE_PI * j / mr->naz);
        mr->az_s[j] = sin(2.0 * CORE_PI * j / mr->naz);
    }
    /* hub axes: z down the shaft, tilted forward by the shaft tilt */
    double s = sin(mr->shaft_tilt), c = cos(mr->shaft_tilt);
    double xh[3] = {c, 0, s}, yh[3] = {0, 1, 0}, zh[3] = {-s, 0, c};
    for (int i = 0; i < 3; i++) {
        mr->C_BH[i][0] = xh[i];
        mr->C_BH[i][1] = yh[i];
        mr->C_BH[i][2] = zh[i];
    }
    /* radial segments of equal width; the lift stops at the tip-loss radius */
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

/* [tail_rotor]: an open tail rotor or a fenestron. */
static int load_tail_rotor(rd *r, hfm_tr *tr)
{
    const char *T = "tail_rotor";
    double d3, cant;
    int side;
    if (core_ini_get_enum(r->ini, T, "type", 1, "open|fenestron", &tr->kind, r->err) ||
        rd_int(r, T, "blades", 2, 20, &tr->nb) || rd_num(r, T, "radius_m", 0.1, 5.0, &tr->R) ||
        rd_num(r, T, "omega_radps", 10.0, 1000.0, &tr->omega) || rd_num(r, T, "chord_m", 0.005, 1.0, &tr->chord) ||
        rd_num(r, T, "lift_slope_per_rad", 2.0, 7.0, &tr->a) || rd_num(r, T, "cd0", 0.0, 0.05, &tr->cd0) ||
        rd_deg(r, T, "twist_deg", -40.0, 10.0, &tr->twist) ||
        rd_num(r, T, "pitch_ref_r_over_R", 0.0, 1.0, &tr->twist_ref) ||
        rd_num(r, T, "tip_loss", 0.85, 1.0, &tr->B) || rd_deg(r, T, "delta3_deg", 0.0, 60.0, &d3) ||
        rd_num(r, T, "lock_number", 0.0, 20.0, &tr->lock) || rd_vec3(r, T, "hub_B_m", -30.0, 30.0, tr->hub_B) ||
        core_ini_get_enum(r->ini, T, "thrust_side", 1, "starboard|port", &side, r->err) ||
        rd_deg(r, T, "cant_deg", -45.0, 45.0, &cant))
        return -1;
    tr->tan_d3 = tan(d3);
    double s = side == 0 ? 1.0 : -1.0;
    tr->dir_B[0] = 0.0;
    tr->dir_B[1] = s * cos(cant);
    tr->dir_B[2] = -sin(cant);
    if (rd_num(r, T, "blockage", 0.5, 1.0, &tr->blockage) ||
        rd_num(r, T, "blockage_below_kt", 0.0, 100.0, &tr->blockage_kt))
        return -1;
    tr->fan_fraction = 1.0;
    if (tr->kind == HFM_TR_FENESTRON && rd_num(r, T, "fan_thrust_fraction", 0.3, 1.0, &tr->fan_fraction))
        return -1;
    tr->sigma = tr->nb * tr->chord / (CORE_PI * tr->R);
    if (tr->sigma > 0.8)
        return rd_fail(r, T, "chord_m", "solidity %.3f is not physical", tr->sigma);
    return 0;
}

/* [fuselage]: force and moment tables per dynamic pressure. */
static int load_fuselage(rd *r, hfm_fus *fu)
{
    const char *F = "fuselage";
    if (rd_vec3(r, F, "ref_B_m", -20.0, 20.0, fu->ref_B) ||
        rd_table(r, F, "drag_alpha_deg", "drag_m2", 0.0, 100.0, &fu->drag) ||
        rd_table(r, F, "lift_alpha_deg", "lift_m2", -50.0, 50.0, &fu->lift) ||
        rd_table(r, F, "pitch_alpha_deg", "pitch_m3", -500.0, 500.0, &fu->pitch) ||
        rd_table(r, F, "sideslip_beta_deg", "sideslip_drag_m2", 0.0, 100.0, &fu->dbeta) ||
        rd_num(r, F, "yaw_m3_at_10deg", 0.0, 500.0, &fu->yaw_m3_10deg) ||
        rd_num(r, F, "side_force_m2", 0.0, 100.0, &fu->side_m2))
        return -1;
    /* optional wake planform (docs/aircraft-format.md): absent, the
     * reference point alone (two stations at ref x, width 0) */
    fu->plan_n = 2;
    fu->plan_x_B[0] = fu->plan_x_B[1] = fu->ref_B[0];
    fu->plan_w[0] = fu->plan_w[1] = 0.0;
    if (core_ini_find(r->ini, F, "planform_x_B_m")) {
        int cnt = 0;
        if (core_ini_get_doubles(r->ini, F, "planform_x_B_m", 1, -50.0, 50.0, fu->plan_x_B,
                                 HFM_PLAN_MAX, &cnt, r->err))
            return -1;
        if (cnt < 2)
            return rd_fail(r, F, "planform_x_B_m",
                           "expected 2 to %d stations (fore end first), got %d", HFM_PLAN_MAX, cnt);
        for (int i = 1; i < cnt; i++)
            if (!(fu->plan_x_B[i - 1] >= fu->plan_x_B[i]))
                return rd_fail(r, F, "planform_x_B_m",
                               "station %d (%g m) is ahead of station %d (%g m): list fore to aft",
                               i + 1, fu->plan_x_B[i], i, fu->plan_x_B[i - 1]);
        fu->plan_n = cnt;
    }
    if (core_ini_find(r->ini, F, "planform_width_m")) {
        int cnt = 0;
        if (core_ini_get_doubles(r->ini, F, "planform_width_m", 1, 0.0, 20.0, fu->plan_w,
                                 HFM_PLAN_MAX, &cnt, r->err))
            return -1;
        if (cnt == 1)
            for (int i = 1; i < fu->plan_n; i++)
                fu->plan_w[i] = fu->plan_w[0];
        else if (cnt != fu->plan_n)
            return rd_fail(r, F, "planform_width_m",
                           "expected 1 width or one per planform_x_B_m station (%d), got %d",
                           fu->plan_n, cnt);
    }
    return 0;
}

/* [stabilator] (vertical = 0) or [fin] (vertical = 1). */
static int load_surface(rd *r, const char *S, hfm_surf *s, int vertical)
{
    s->vertical = vertical;
    if (rd_vec3(r, S, "pos_B_m", -50.0, 50.0, s->pos_B) || rd_num(r, S, "area_m2", 1e-3, 100.0, &s->area) ||
        rd_num(r, S, "aspect_ratio", 0.2, 20.0, &s->ar) || rd_num(r, S, "lift_slope_per_rad", 0.5, 7.0, &s->a) ||
        rd_num(r, S, "clmax", 0.2, 2.5, &s->clmax) || rd_num(r, S, "cd0", 0.0, 0.2, &s->cd0))
        return -1;
    s->schedule = HFM_STAB_FIXED;
    if (!vertical && core_ini_get_enum(r->ini, S, "schedule", 1, "fixed|uh60a", &s->schedule, r->err))
        return -1;
    s->incidence = 0.0;
    if (s->schedule == HFM_STAB_FIXED && rd_deg(r, S, "incidence_deg", -45.0, 45.0, &s->incidence))
        return -1;
    return 0;
}

/* [controls]: the rig from stick inches to blade pitch, and its mixing. */
static int load_controls(rd *r, hfm_rig *rg)
{
    const char *C = "controls";
    if (rd_num(r, C, "collective_travel_in", 1.0, 30.0, &rg->coll_travel) ||
        rd_num(r, C, "collective_pitch0_deg", -10.0, 40.0, &rg->coll_pitch0) ||
        rd_num(r, C, "collective_deg_per_in", 0.1, 10.0, &rg->coll_gain) ||
        rd_num(r, C, "long_travel_in", 1.0, 30.0, &rg->long_travel) ||
        rd_num(r, C, "long_deg_per_in", 0.1, 10.0, &rg->long_gain) ||
        rd_num(r, C, "lat_travel_in", 1.0, 30.0, &rg->lat_travel) ||
        rd_num(r, C, "lat_deg_per_in", 0.1, 10.0, &rg->lat_gain) ||
        rd_num(r, C, "pedal_travel_in", 1.0, 30.0, &rg->ped_travel) ||
        rd_num(r, C, "tr_pitch0_deg", -30.0, 50.0, &rg->tr_pitch0) ||
        rd_num(r, C, "tr_deg_per_in", -20.0, 20.0, &rg->tr_gain) ||
        rd_num(r, C, "mix_coll_to_long", -2.0, 2.0, &rg->mix_cl) ||
        rd_num(r, C, "mix_ped_to_long", -2.0, 2.0, &rg->mix_pl) ||
        rd_num(r, C, "mix_coll_to_lat", -2.0, 2.0, &rg->mix_ca) ||
        rd_num(r, C, "mix_coll_to_ped", -2.0, 2.0, &rg->mix_cp) ||
        rd_num(r, C, "mix_coll_ref_in", 0.0, 30.0, &rg->mix_cref) ||
        rd_deg(r, C, "swash_phase_deg", -45.0, 45.0, &rg->swash_phase))
        return -1;
    rg->swash_c = cos(rg->swash_phase);
    rg->swash_s = sin(rg->swash_phase);
    if (fabs(rg->tr_gain) < 0.1)
        return rd_fail(r, C, "tr_deg_per_in", "pedal gain too small (|gain| >= 0.1)");
    return 0;
}

/* [sas] (optional): the stability augmentation's gains per axis, in the
 * file's degrees, stored per radian. Every key is required once the section
 * is there. */
static int load_sas(rd *r, hfm_aircraft *ac)
{
    const char *S = "sas";
    memset(&ac->sas, 0, sizeof ac->sas);
    ac->has_sas = core_ini_has_section(r->ini, S);
    if (!ac->has_sas)
        return 0;
    static const char *const axis[3] = {"roll", "pitch", "yaw"};
    int off;
    if (core_ini_get_enum(r->ini, S, "engaged", 1, "on|off", &off, r->err) ||
        rd_num(r, S, "detent_pct", 0.0, 10.0, &ac->sas.detent_pct))
        return -1;
    ac->sas.engaged = off == 0;
    for (int i = 0; i < 3; i++) {
        char k[64];
        double rate, att;
        snprintf(k, sizeof k, "%s_rate_pct_per_degps", axis[i]);
        if (rd_num(r, S, k, -20.0, 20.0, &rate))
            return -1;
        snprintf(k, sizeof k, "%s_attitude_pct_per_deg", axis[i]);
        if (rd_num(r, S, k, -20.0, 20.0, &att))
            return -1;
        snprintf(k, sizeof k, "%s_authority_pct", axis[i]);
        if (rd_num(r, S, k, 0.0, 50.0, &ac->sas.authority_pct[i]))
            return -1;
        ac->sas.rate_pct_per_radps[i] = rate / CORE_DEG_TO_RAD;
        ac->sas.att_pct_per_rad[i] = att / CORE_DEG_TO_RAD;
    }
    return 0;
}

int hfm_aircraft_sas(const hfm_aircraft *ac, hfm_sas_gains *g)
{
    *g = ac->sas;
    return ac->has_sas ? 0 : 1;
}

/* ------------------------------------------------------------ [gear] */
/* [gear] (optional): one value per leg in each per-leg list, the legs named
 * by `legs`; the strike points named by `strike_points`. Every key is
 * required once the section is there (docs/aircraft-format.md). */
static int gear_names(rd *r, const char *key, int nmax, char names[][32], int *n)
{
    char buf[512];
    if (core_ini_get_string(r->ini, "gear", key, 1, buf, sizeof buf, r->err))
        return -1;
    *n = 0;
    for (char *tok = strtok(buf, ","); tok; tok = strtok(NULL, ",")) {
        while (*tok == ' ' || *tok == '\t')
            tok++;
        size_t len = strlen(tok);
        while (len && (tok[len - 1] == ' ' || tok[len - 1] == '\t'))
            tok[--len] = 0;
        if (!len || len >= 32)
            return rd_fail(r, "gear", key, "names must be 1 to 31 characters, separated by commas");
        if (*n >= nmax)
            return rd_fail(r, "gear", key, "at most %d names", nmax);
        memcpy(names[(*n)++], tok, len + 1);
    }
    if (!*n)
        return rd_fail(r, "gear", key, "expected at least one name");
    return 0;
}

/* A per-leg (or per-point) list of exactly n numbers in [lo, hi]. */
static int gear_list(rd *r, const char *key, int n, double lo, double hi, double *out)
{
    int cnt = 0;
    if (core_ini_get_doubles(r->ini, "gear", key, 1, lo, hi, out, HFM_GEAR_MAX_POINTS, &cnt, r->err))
        return -1;
    if (cnt != n)
        return rd_fail(r, "gear", key, "expected %d values (one per name), got %d", n, cnt);
    return 0;
}

static int load_gear(rd *r, hfm_aircraft *ac)
{
    const char *G = "gear";
    hfm_gear *g = &ac->gear;
    memset(g, 0, sizeof *g);
    ac->has_gear = core_ini_has_section(r->ini, G);
    if (!ac->has_gear)
        return 0;
    char names[HFM_GEAR_MAX_POINTS][32];
    int n;
    if (gear_names(r, "legs", HFM_GEAR_MAX_LEGS, names, &n))
        return -1;
    g->nlegs = n;
    double v[11][HFM_GEAR_MAX_POINTS];
    static const char *const key[11] = {"pos_x_m", "pos_y_m", "pos_z_m", "tyre_radius_m", "stroke_m",
                                        "stiffness_N_per_m", "damping_compression_Ns_per_m",
                                        "damping_rebound_Ns_per_m", "preload_N", "tyre_stiffness_N_per_m",
                                        "brake"};
    static const double lo[11] = {-30, -10, -1, 0.05, 0.01, 1e3, 0, 0, 0, 1e4, 0};
    static const double hi[11] = {30, 10, 10, 1.0, 2.0, 1e8, 1e7, 1e7, 1e6, 1e8, 1};
    for (int k = 0; k < 11; k++)
        if (gear_list(r, key[k], n, lo[k], hi[k], v[k]))
            return -1;
    double cas[HFM_GEAR_MAX_POINTS];
    if (gear_list(r, "castor", n, 0, 1, cas))
        return -1;
    for (int i = 0; i < n; i++) {
        hfm_gear_leg *l = &g->leg[i];
        memcpy(l->name, names[i], sizeof l->name);
        l->pos_B_m[0] = v[0][i];
        l->pos_B_m[1] = v[1][i];
        l->pos_B_m[2] = v[2][i];
        l->tyre_radius_m = v[3][i];
        l->stroke_m = v[4][i];
        l->stiffness_Npm = v[5][i];
        l->damping_comp_Nspm = v[6][i];
        l->damping_reb_Nspm = v[7][i];
        l->preload_N = v[8][i];
        l->tyre_stiffness_Npm = v[9][i];
        l->brake = v[10][i] > 0.5;
        l->castor = cas[i] > 0.5;
        if (!(l->pos_B_m[2] + l->tyre_radius_m > 0))
            return rd_fail(r, G, "pos_z_m", "leg %s: the tyre's bottom must be below the CG", l->name);
    }
    int off_b, off_l;
    if (rd_num(r, G, "mu_static", 0.05, 2.0, &g->mu_static) ||
        rd_num(r, G, "mu_dynamic", 0.05, 2.0, &g->mu_dynamic) ||
        rd_num(r, G, "mu_rolling", 0.0, 0.2, &g->mu_rolling) ||
        core_ini_get_enum(r->ini, G, "brakes", 1, "on|off", &off_b, r->err) ||
        core_ini_get_enum(r->ini, G, "tail_wheel_lock", 1, "on|off", &off_l, r->err))
        return -1;
    if (g->mu_dynamic > g->mu_static)
        return rd_fail(r, G, "mu_dynamic", "%g exceeds mu_static %g", g->mu_dynamic, g->mu_static);
    g->brakes_on = off_b == 0;
    g->tail_lock_on = off_l == 0;
    if (gear_names(r, "strike_points", HFM_GEAR_MAX_POINTS, g->point_name, &g->npoints))
        return -1;
    double p[3][HFM_GEAR_MAX_POINTS];
    if (gear_list(r, "strike_x_m", g->npoints, -30, 30, p[0]) ||
        gear_list(r, "strike_y_m", g->npoints, -30, 30, p[1]) ||
        gear_list(r, "strike_z_m", g->npoints, -10, 10, p[2]))
        return -1;
    for (int i = 0; i < g->npoints; i++)
        for (int k = 0; k < 3; k++)
            g->point_B_m[i][k] = p[k][i];
    return 0;
}

/* [cockpit] (optional): pilot_eye_B_m, the pilot's design eye point. The
 * eye must lie within 20 m of the CG and not inside the main-rotor hub's
 * height band above it (a swapped sign of z is the usual slip). */
static int load_cockpit(rd *r, hfm_aircraft *ac)
{
    const char *C = "cockpit";
    ac->has_eye = core_ini_has_section(r->ini, C);
    if (!ac->has_eye)
        return 0;
    if (rd_vec3(r, C, "pilot_eye_B_m", -20.0, 20.0, ac->eye_B))
        return -1;
    if (!(ac->eye_B[2] > ac->mr.hub_B[2] + 0.3))
        return core_err_set(r->err, -1,
                            "%s: [cockpit] pilot_eye_B_m z = %g m: expected below the main-rotor hub (hub_B_m z = "
                            "%g m; z is down)",
                            r->path, ac->eye_B[2], ac->mr.hub_B[2]);
    return 0;
}

void hfm_aircraft_geometry(const hfm_aircraft *ac, hfm_geometry *g)
{
    memset(g, 0, sizeof *g);
    snprintf(g->name, sizeof g->name, "%s", ac->name);
    g->blades = ac->mr.nb;
    g->rotor_ccw = ac->mr.sense > 0;
    g->rotor_radius_m = ac->mr.R;
    g->rotor_omega_radps = ac->mr.omega;
    memcpy(g->hub_B_m, ac->mr.hub_B, sizeof g->hub_B_m);
    g->shaft_tilt_rad = ac->mr.shaft_tilt;
    g->tail_fenestron = ac->tr.kind == HFM_TR_FENESTRON;
    g->tail_blades = ac->tr.nb;
    g->tail_radius_m = ac->tr.R;
    g->tail_omega_radps = ac->tr.omega;
    memcpy(g->tail_hub_B_m, ac->tr.hub_B, sizeof g->tail_hub_B_m);
    memcpy(g->tail_dir_B, ac->tr.dir_B, sizeof g->tail_dir_B);
    memcpy(g->stab_B_m, ac->stab.pos_B, sizeof g->stab_B_m);
    memcpy(g->fin_B_m, ac->fin.pos_B, sizeof g->fin_B_m);
    g->has_eye = ac->has_eye;
    memcpy(g->eye_B_m, ac->eye_B, sizeof g->eye_B_m);
    if (ac->has_gear)
        g->gear = ac->gear;
}

int hfm_aircraft_gear(const hfm_aircraft *ac, hfm_gear *g)
{
    if (!ac->has_gear) {
        memset(g, 0, sizeof *g);
        return 1;
    }
    *g = ac->gear;
    return 0;
}

hfm_aircraft *hfm_aircraft_load(const char *path, const core_log *log, core_err *err)
{
    core_ini *ini = core_ini_load(path, err);
    if (!ini)
        return NULL;
    hfm_aircraft *ac = hfm_aircraft_from_ini(ini, log, err);
    core_ini_destroy(ini);
    return ac;
}

hfm_aircraft *hfm_aircraft_from_ini(core_ini *ini, const core_log *log, core_err *err)
{
    const char *path = core_ini_path(ini);
    hfm_aircraft *ac = calloc(1, sizeof *ac);
    if (!ac) {
        core_err_set(err, -1, "%s: out of memory", path);
        return NULL;
    }
    rd r = {ini, path, err};
    if (check_sections(&r) || load_mass(&r, ac) || load_main_rotor(&r, &ac->mr) ||
        load_airfoil(&r, &ac->mr.af))
        goto fail;
    derive_main_rotor(&ac->mr);
    if (load_tail_rotor(&r, &ac->tr) || load_fuselage(&r, &ac->fus) ||
        load_surface(&r, "stabilator", &ac->stab, 0) || load_surface(&r, "fin", &ac->fin, 1) ||
        load_controls(&r, &ac->rig) || load_sas(&r, ac) || load_gear(&r, ac) ||
        load_cockpit(&r, ac) || load_power(&r, ac) || load_model_error(&r, ac))
        goto fail;
    hfm_fuselage_cells(ac);
    core_ini_skip_section(ini, "rejection");
    if (core_ini_check_unused(ini, err) || hfm_aircraft_check(ac, ini, log, err))
        goto fail;
    core_log_msg(log, CORE_LOG_INFO, "hfm: loaded %s (%s), %.0f kg, %d blades, %d segments", ac->name, path,
                 ac->mass, ac->mr.nb, ac->mr.nseg);
    return ac;
fail:
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

void hfm_aircraft_blade_data(const hfm_aircraft *ac, hfm_blade_data *b)
{
    const hfm_mr *mr = &ac->mr;
    memset(b, 0, sizeof *b);
    b->blades = mr->nb;
    b->ccw = mr->sense > 0;
    b->radius_m = mr->R;
    b->omega_radps = mr->omega;
    b->chord_m = mr->chord;
    b->root_cutout_m = mr->root;
    b->tip_loss = mr->B;
    b->twist_rad = mr->twist;
    b->twist_ref = mr->twist_ref;
    for (int i = 0; i < HFM_BLADE_NALPHA; i++) {
        b->alpha_deg[i] = i - 180.0;
        b->cl[i] = mr->af.cl[i];
        b->cd[i] = mr->af.cd[i];
    }
    hfm_aircraft_figures f;
    hfm_aircraft_get_figures(ac, &f);
    b->lift_slope_per_rad = f.lift_slope_per_rad;
    b->hover_pitch0_rad = f.hover_pitch75_deg * CORE_DEG_TO_RAD - mr->twist * (0.75 - mr->twist_ref);
}

/* Controls through the rig (stick inches) and mixing to blade angles. */
void hfm_controls_to_pitch(const hfm_aircraft *ac, const hfm_controls *u, double *theta0_rad,
                           double *A1_rad, double *B1_rad, double *theta_tr_rad)
{
    const hfm_rig *g = &ac->rig;
    double xc = u->collective_pct / 100.0 * g->coll_travel;           /* from bottom */
    double xl = (50.0 - u->long_cyclic_pct) / 100.0 * g->long_travel; /* + forward */
    double xa = (u->lat_cyclic_pct - 50.0) / 100.0 * g->lat_travel;   /* + right */
    double xp = (u->pedal_pct - 50.0) / 100.0 * g->ped_travel;         /* + right */
    double dc = xc - g->mix_cref;
    double xl_e = xl + g->mix_cl * dc + g->mix_pl * xp;
    double xa_e = xa + g->mix_ca * dc;
    double xp_e = xp + g->mix_cp * dc;
    double B1 = g->long_gain * xl_e * CORE_DEG_TO_RAD, A1 = g->lat_gain * xa_e * CORE_DEG_TO_RAD;
    double c = g->swash_c, s = g->swash_s;
    *theta0_rad = (g->coll_pitch0 + g->coll_gain * xc) * CORE_DEG_TO_RAD;
    *A1_rad = c * A1 + s * B1;
    *B1_rad = c * B1 - s * A1;
    *theta_tr_rad = (g->tr_pitch0 + g->tr_gain * xp_e) * CORE_DEG_TO_RAD;
}
