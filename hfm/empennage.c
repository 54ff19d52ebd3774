/* empennage.c -- horizontal stabiliser / stabilator and vertical fin.
 *
 * Each surface: lift CL = a alpha up to CLmax, then a 10 deg blend to the
 * flat plate CL = 1.1 sin(2 alpha); drag cd0 + CL^2/(pi AR 0.8), rising to
 * the flat plate 1.98 sin^2(alpha) after the stall (Hoerner, "Fluid-Dynamic
 * Lift", ch. 4; Padfield ch. 3.2.4). The local air is sampled at the
 * surface (hfm_air callback) plus the main-rotor wake's velocity along
 * the shaft averaged over the surface (body.c: its growth along the
 * skewed wake, its contraction and its boundary),
 * which gives the downwash on the tail as a function of wake skew. The
 * surface is the rectangle of its area and aspect ratio (span sqrt(AR S),
 * chord S/span) centred on pos_B_m: spanwise along y for the stabilator,
 * along z for the fin (sweep and taper neglected). UH-60A stabilator
 * incidence: GenHel's schedule (Howlett, NASA CR-166309, 1981) of airspeed,
 * pitch rate, lateral acceleration and collective, without its 7 deg/s rate
 * limit.
 */
#include "hfm_priv.h"

double hfm_stab_schedule_uh60a(const hfm_wake *w)
{
    double V = w->airspeed_kt, c = w->coll_pct;
    double pr50 = clampd(V - 30.0, 0.0, 50.0);
    double c1 = clampd(70.0 - c, 0.0, 20.0), c2 = clampd(50.0 - c, 0.0, 50.0);
    double i = 42.0 + 0.16 * w->q_degps -
               0.0433 * fmin(V - 30.0, 30.0) * clampd(w->ay_g, -0.13, 0.13) -
               pr50 * (0.67 + 0.003286 * (c1 + c2)) - 0.1119 * clampd(V - 80.0, 0.0, 67.0);
    return clampd(i, -8.0, 39.0) * CORE_DEG_TO_RAD;
}

static void surface_coef(const hfm_surf *s, double alpha, double *cl, double *cd)
{
    double as = s->clmax / s->a, bl = 10.0 * CORE_DEG_TO_RAD;
    double aa = fabs(alpha), sg = alpha < 0 ? -1.0 : 1.0;
    double wfp;
    if (aa <= as) {
        *cl = s->a * alpha;
        wfp = 0.0;
    } else if (aa <= as + bl) {
        double f = (aa - as) / bl, fpb = 1.1 * sin(2.0 * (as + bl)) * sg;
        *cl = (1 - f) * s->clmax * sg + f * fpb;
        wfp = f;
    } else {
        *cl = 1.1 * sin(2.0 * alpha);
        wfp = 1.0;
    }
    double ind = *cl * *cl / (CORE_PI * s->ar * 0.8);
    if (wfp > 0.0) { /* the flat plate's drag only matters past the stall */
        double sa = sin(alpha);
        ind = fmax(ind, wfp * 1.98 * sa * sa);
    }
    *cd = s->cd0 + ind;
}

static int surface(const hfm_aircraft *ac, const hfm_kin *k, const hfm_wake *w,
                   const hfm_surf *s, double inc, hfm_fm *fm)
{
    double v[3];
    if (hfm_air_rel_B(k, s->pos_B, v))
        return -1;
    double span = sqrt(s->ar * s->area), chord = s->area / span;
    const double ha[3] = {0, s->vertical ? 0.0 : 0.5 * span, s->vertical ? 0.5 * span : 0.0};
    const double hb[3] = {0.5 * chord, 0, 0};
    double imm = hfm_wake_speed_patch(ac, w, s->pos_B, ha, hb);
    for (int i = 0; i < 3; i++)
        v[i] += imm * ac->mr.C_BH[i][2];
    const double x[3] = {1, 0, 0};
    const double lh[3] = {0, 0, -1}, lv[3] = {0, -1, 0};
    const double *l = s->vertical ? lv : lh;
    double ax = -v3_dot(v, x), al = v3_dot(v, l);
    double U2 = ax * ax + al * al;
    for (int i = 0; i < 3; i++)
        fm->F_B_N[i] = fm->M_B_Nm[i] = 0.0;
    if (U2 < 1e-8)
        return 0;
    double U = sqrt(U2), alpha = atan2(al, ax) + inc;
    if (alpha > CORE_PI)
        alpha -= 2 * CORE_PI;
    if (alpha < -CORE_PI)
        alpha += 2 * CORE_PI;
    double cl, cd;
    surface_coef(s, alpha, &cl, &cd);
    double qS = 0.5 * ac->mr.rho * U2 * s->area;
    for (int i = 0; i < 3; i++)
        fm->F_B_N[i] = qS * (cl * (al * x[i] + ax * l[i]) + cd * (-ax * x[i] + al * l[i])) / U;
    v3_cross(s->pos_B, fm->F_B_N, fm->M_B_Nm);
    return 0;
}

int hfm_empennage(const hfm_aircraft *ac, const hfm_kin *k, const hfm_wake *w, hfm_fm *stab,
                  hfm_fm *fin, double *incidence)
{
    double inc = ac->stab.schedule == HFM_STAB_UH60A ? hfm_stab_schedule_uh60a(w)
                                                     : ac->stab.incidence;
    *incidence = inc;
    if (surface(ac, k, w, &ac->stab, inc, stab))
        return -1;
    return surface(ac, k, w, &ac->fin, ac->fin.incidence, fin);
}
