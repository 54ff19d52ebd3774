/* aircraft_check.c -- physical consistency of an aircraft file: the unit
 * slips that stay inside every key's range but make an aircraft no real one
 * is (docs/aircraft-format.md, "Consistency checks").
 *
 * Each check compares a derived figure with the band real helicopters lie
 * in; a figure that no helicopter has is an error naming file, line, key,
 * value and why (most likely the unit slip behind it); one that is merely
 * unusual is a warning through core_log (CORE_LOG_WARN). Figures:
 *   tip speed Omega R: 150-250 m/s on every main and tail rotor (tip Mach
 *     0.45-0.75; Leishman, "Principles of Helicopter Aerodynamics", 2nd ed.,
 *     table 1.1 and sec. 6.3);
 *   solidity Nb c / (pi R): main rotors 0.02-0.20 (Robinson R22 0.03, CH-53E
 *     0.115);
 *   Lock number rho a c R^4 / I_beta (Padfield, "Helicopter Flight
 *     Dynamics", 2nd ed., eq. 3.74): 4-12 for real rotors (warning outside),
 *     2-20 at most (error outside), a from the airfoil table at +-4 deg;
 *   flap frequency (Padfield eq. 3.73 with a spring)
 *     nu^2 = 1 + e S_b / I_b + K_b / (I_b Omega^2): articulated rotors
 *     1.02-1.05 /rev, hingeless up to 1.12 (Bo105): a warning above 1.15,
 *     an error above 1.30. A hinge offset and a flap spring are two ways to
 *     give the same hub stiffness; when a file gives both, their joint
 *     frequency is reported (CORE_LOG_INFO) with what each gives alone;
 *   twist: a blade twist below 1 deg in magnitude (but not zero) is a twist
 *     in radians typed into a degree key: an error naming the value in deg;
 *   hover blade loading CT/sigma = W / (rho A (Omega R)^2 sigma): real
 *     helicopters hover at 0.05-0.12; a warning outside 0.04-0.13 (mass in
 *     lb?), an error where the mean lift coefficient 6 CT/sigma exceeds the
 *     airfoil table's maximum (the rotor cannot lift the aircraft);
 *   the collective rig at 0.75 R must reach the hover pitch of blade-element
 *     momentum theory, theta_75 = (6 CT/(sigma a) + 3/2 B^2 lambda)/B^3,
 *     lambda = 1.15 sqrt(CT/2) (Leishman eq. 3.103 with tip loss B and
 *     induced power factor 1.15): the check that catches a rig quoted at a
 *     station other than twist_ref_r_over_R;
 *   geometry signs: the main-rotor hub above the CG (z < 0 in B, z down),
 *     the tail rotor behind it (x < 0);
 *   fuselage drag area at alpha = 0 below 0.05 of the disk area (real
 *     helicopters 0.005-0.02; ft^2 typed into m^2 keys give 0.06-0.2);
 *   the validated error ([model_error]) measured at an airspeed above
 *     45 kt: a warning, since the SHOL's limits are reached at 0-45 kt of
 *     wind over deck and an error from a cruise trim need not be the
 *     hover's (the UH-60A's pedal error is -4.27 % at 1 kt, -1.66 % at
 *     60 kt, docs/validation/hfm.md).
 */
#include "hfm_priv.h"

#include <stdio.h>


/* Bands (see above). */
#define TIP_MIN_MPS 150.0
#define TIP_MAX_MPS 250.0
#define SIGMA_MIN 0.02
#define SIGMA_MAX 0.20
#define LOCK_WARN_LO 4.0
#define LOCK_WARN_HI 12.0
#define LOCK_MIN 2.0
#define LOCK_MAX 20.0
#define FLAP_WARN_PER_REV 1.15
#define FLAP_MAX_PER_REV 1.30
#define TWIST_MIN_DEG 1.0
#define CTS_WARN_LO 0.04
#define CTS_WARN_HI 0.13
#define DRAG_AREA_MAX 0.05
#define KAPPA_HOVER 1.15
#define MODEL_ERROR_MAX_KT 45.0

void hfm_aircraft_get_figures(const hfm_aircraft *ac, hfm_aircraft_figures *f)
{
    const hfm_mr *mr = &ac->mr;
    const hfm_tr *tr = &ac->tr;
    const hfm_rig *g = &ac->rig;
    double OR = mr->omega * mr->R, W = ac->mass * CORE_G_MPS2;
    f->tip_speed_mps = OR;
    f->solidity = mr->nb * mr->chord / (CORE_PI * mr->R);
    /* cl at +-4 deg on the 1 deg grid (index 180 is 0 deg) */
    f->lift_slope_per_rad = (mr->af.cl[184] - mr->af.cl[176]) / (8.0 * CORE_DEG_TO_RAD);
    f->lock_number = mr->rho * f->lift_slope_per_rad * mr->chord * pow(mr->R, 4) / mr->I_beta;
    double ke = mr->e * mr->S_beta / mr->I_beta, kk = mr->K_beta / (mr->I_beta * mr->omega * mr->omega);
    f->flap_freq_per_rev = sqrt(1.0 + ke + kk);
    f->flap_freq_offset_per_rev = sqrt(1.0 + ke);
    f->flap_freq_spring_per_rev = sqrt(1.0 + kk);
    f->disk_loading_Pa = W / mr->area;
    double CT = W / (mr->rho * mr->area * OR * OR);
    f->ct_over_sigma_hover = CT / f->solidity;
    double cl_max = 0.0;
    for (int i = 0; i <= 360; i++)
        cl_max = fmax(cl_max, mr->af.cl[i]);
    f->airfoil_cl_max = cl_max;
    double B = mr->B, lam = KAPPA_HOVER * sqrt(0.5 * CT);
    double a = f->lift_slope_per_rad > 0.1 ? f->lift_slope_per_rad : 0.1;
    f->hover_pitch75_deg = (6.0 * CT / (f->solidity * a) + 1.5 * B * B * lam) / (B * B * B) * CORE_RAD_TO_DEG;
    /* the rig's collective gives the pitch at twist_ref R; at 0.75 R add the twist between */
    double d75 = mr->twist * (0.75 - mr->twist_ref) * CORE_RAD_TO_DEG;
    f->coll_pitch75_min_deg = g->coll_pitch0 + d75;
    f->coll_pitch75_max_deg = g->coll_pitch0 + g->coll_gain * g->coll_travel + d75;
    f->tr_tip_speed_mps = tr->omega * tr->R;
    f->tr_solidity = tr->sigma;
    f->drag_area_m2 = hfm_table_eval(&ac->fus.drag, 0.0);
}

/* An error "file:line: [sec] key = value: why", returns -1. */
#define FAIL(sec, key, val, ...)                                                                      \
    do {                                                                                              \
        char why_[700];                                                                               \
        snprintf(why_, sizeof why_, __VA_ARGS__);                                                     \
        return core_err_set(err, -1, "%s:%d: [%s] %s = %g: %s", path,                                \
                            hfm_aircraft_key_line(ini, sec, key), sec, key, (double)(val), why_);    \
    } while (0)
/* The same as a warning. */
#define WARN(sec, key, val, ...)                                                                      \
    do {                                                                                              \
        char why_[700];                                                                               \
        snprintf(why_, sizeof why_, __VA_ARGS__);                                                     \
        core_log_msg(log, CORE_LOG_WARN, "%s:%d: [%s] %s = %g: %s", path,                            \
                     hfm_aircraft_key_line(ini, sec, key), sec, key, (double)(val), why_);           \
    } while (0)

static int check_twist(const core_ini *ini, const char *path, const char *sec, double twist_rad,
                       core_err *err)
{
    double d = twist_rad * CORE_RAD_TO_DEG;
    if (d != 0.0 && fabs(d) < TWIST_MIN_DEG)
        FAIL(sec, "twist_deg", d,
             "a blade twist below %g deg in magnitude is no helicopter blade's (main rotors 5-20 deg): this "
             "looks like radians, which would be %.1f deg; give the twist in degrees (or 0 for an untwisted "
             "blade)",
             TWIST_MIN_DEG, d * CORE_RAD_TO_DEG);
    return 0;
}

static int check_tip_speed(const core_ini *ini, const char *path, const char *sec, double omega,
                           double R, core_err *err)
{
    double v = omega * R;
    if (v < TIP_MIN_MPS || v > TIP_MAX_MPS)
        FAIL(sec, "omega_radps", omega,
             "tip speed omega_radps x radius_m = %g x %g = %.0f m/s, outside the %.0f-%.0f m/s of helicopter "
             "rotors (tip Mach 0.45-0.75): is radius_m in ft (x 0.3048) or omega_radps in rpm (x 0.10472)?",
             omega, R, v, TIP_MIN_MPS, TIP_MAX_MPS);
    return 0;
}

int hfm_aircraft_check(const hfm_aircraft *ac, const core_ini *ini, const core_log *log, core_err *err)
{
    const char *path = core_ini_path(ini), *M = "main_rotor", *T = "tail_rotor";
    const hfm_mr *mr = &ac->mr;
    hfm_aircraft_figures f;
    hfm_aircraft_get_figures(ac, &f);

    /* geometry signs */
    if (!(mr->hub_B[2] < 0.0))
        return core_err_set(err, -1,
                            "%s:%d: [%s] hub_B_m: z = %g m puts the hub at or below the centre of gravity; B has "
                            "z down, so a hub above the CG has z < 0",
                            path, hfm_aircraft_key_line(ini, M, "hub_B_m"), M, mr->hub_B[2]);
    if (!(ac->tr.hub_B[0] < 0.0))
        return core_err_set(err, -1,
                            "%s:%d: [%s] hub_B_m: x = %g m puts the tail rotor at or ahead of the centre of "
                            "gravity; B has x forward, so a tail rotor behind the CG has x < 0",
                            path, hfm_aircraft_key_line(ini, T, "hub_B_m"), T, ac->tr.hub_B[0]);

    /* unit slips of the rotors */
    if (check_twist(ini, path, M, mr->twist, err) || check_twist(ini, path, T, ac->tr.twist, err) ||
        check_tip_speed(ini, path, M, mr->omega, mr->R, err) ||
        check_tip_speed(ini, path, T, ac->tr.omega, ac->tr.R, err))
        return -1;
    if (f.solidity < SIGMA_MIN || f.solidity > SIGMA_MAX)
        FAIL(M, "chord_m", mr->chord,
             "solidity blades x chord_m / (pi radius_m) = %d x %g / (pi x %g) = %.4f, outside the %.2f-%.2f of "
             "helicopter main rotors: are chord_m and radius_m in the same unit (m)?",
             mr->nb, mr->chord, mr->R, f.solidity, SIGMA_MIN, SIGMA_MAX);
    {
        const char *lk = "blade_flap_inertia_kgm2";
        char why[400];
        snprintf(why, sizeof why,
                 "Lock number rho a chord_m radius_m^4 / %s = %.2f (a = %.2f /rad from the airfoil table); real "
                 "rotors lie in %.0f-%.0f: is the flap inertia in lb ft^2 (x 0.04214 kg m^2) or slug ft^2 "
                 "(x 1.3558)?",
                 lk, f.lock_number, f.lift_slope_per_rad, LOCK_WARN_LO, LOCK_WARN_HI);
        if (f.lock_number < LOCK_MIN || f.lock_number > LOCK_MAX)
            FAIL(M, lk, mr->I_beta, "%s", why);
        if (f.lock_number < LOCK_WARN_LO || f.lock_number > LOCK_WARN_HI)
            WARN(M, lk, mr->I_beta, "%s", why);
    }
    {
        /* the key that gives the larger share of the stiffness is named */
        double ke = f.flap_freq_offset_per_rev, kk = f.flap_freq_spring_per_rev, nu = f.flap_freq_per_rev;
        int both = mr->e > 0.0 && mr->K_beta > 0.0;
        const char *key = kk > ke ? "flap_spring_Nmprad" : "hinge_offset_m";
        double val = kk > ke ? mr->K_beta : mr->e;
        char why[600];
        snprintf(why, sizeof why,
                 "the blade flaps at %.3f /rev (hinge_offset_m %g alone gives %.3f /rev, flap_spring_Nmprad %g "
                 "alone %.3f): above the %.2f /rev of the stiffest hingeless rotors (Bo105 1.12)%s",
                 nu, mr->e, ke, mr->K_beta, kk, FLAP_WARN_PER_REV,
                 both ? "; an equivalent-hinge model puts the hub's stiffness in the offset or in the spring, "
                        "not both at full value"
                      : "");
        if (nu > FLAP_MAX_PER_REV)
            FAIL(M, key, val, "%s; no helicopter rotor flaps above %.2f /rev", why, FLAP_MAX_PER_REV);
        if (nu > FLAP_WARN_PER_REV)
            WARN(M, key, val, "%s", why);
        if (both)
            core_log_msg(log, CORE_LOG_INFO,
                         "%s: [%s] hinge_offset_m %g and flap_spring_Nmprad %g together give a flap frequency of "
                         "%.3f /rev (the offset alone %.3f, the spring alone %.3f)",
                         path, M, mr->e, mr->K_beta, nu, ke, kk);
    }

    /* the rotor against the weight */
    if (6.0 * f.ct_over_sigma_hover > f.airfoil_cl_max)
        FAIL("aircraft", "mass_kg", ac->mass,
             "hover blade loading CT/sigma = %.3f needs a mean lift coefficient 6 CT/sigma = %.2f above the "
             "airfoil table's maximum %.2f: the rotor cannot lift this mass (is it in lb? x 0.4536 kg)",
             f.ct_over_sigma_hover, 6.0 * f.ct_over_sigma_hover, f.airfoil_cl_max);
    if (f.ct_over_sigma_hover < CTS_WARN_LO || f.ct_over_sigma_hover > CTS_WARN_HI)
        WARN("aircraft", "mass_kg", ac->mass,
             "hover blade loading CT/sigma = %.3f, outside the %.2f-%.2f that helicopters hover at (the mass in "
             "lb, x 0.4536 kg? the rotor's size or speed?)",
             f.ct_over_sigma_hover, CTS_WARN_LO, CTS_WARN_HI);
    if (f.hover_pitch75_deg < f.coll_pitch75_min_deg || f.hover_pitch75_deg > f.coll_pitch75_max_deg)
        FAIL("controls", "collective_pitch0_deg", ac->rig.coll_pitch0,
             "the collective gives %.1f to %.1f deg at 0.75 R (with twist_deg %g measured from "
             "twist_ref_r_over_R = %g), but the hover needs about %.1f deg there (blade-element momentum "
             "theory): the rig cannot hover the aircraft. Is the rig's pitch quoted at another station than "
             "twist_ref_r_over_R (root 0, three-quarter radius 0.75)?",
             f.coll_pitch75_min_deg, f.coll_pitch75_max_deg, mr->twist * CORE_RAD_TO_DEG, mr->twist_ref,
             f.hover_pitch75_deg);

    /* the fuselage */
    if (f.drag_area_m2 > DRAG_AREA_MAX * mr->area)
        return core_err_set(err, -1,
                            "%s:%d: [fuselage] drag_m2: %g m^2 at alpha = 0 is %.3f of the disk area (%.0f m^2); "
                            "helicopters have 0.005-0.02 and none above %.2f: is the table in ft^2 (x 0.0929 m^2)?",
                            path, hfm_aircraft_key_line(ini, "fuselage", "drag_m2"), f.drag_area_m2,
                            f.drag_area_m2 / mr->area, mr->area, DRAG_AREA_MAX);

    /* the validated error's condition against the speeds the SHOL needs it at */
    if (ac->has_model_error && ac->model_error.airspeed_mps > MODEL_ERROR_MAX_KT * CORE_KT_TO_MPS + 1e-9)
        WARN("model_error", "airspeed_kt", ac->model_error.airspeed_mps / CORE_KT_TO_MPS,
             "the SHOL's limits are reached at 0-%.0f kt of wind over deck; an error measured in a faster trim "
             "need not be the one at the limits (use the validated trim nearest the hover)",
             MODEL_ERROR_MAX_KT);
    return 0;
}
