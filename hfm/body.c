/* body.c -- the 6-DOF rigid body and the assembly of the component loads.
 *
 * Model: the seed paper's eqs. (6)-(9) (after Padfield, "Helicopter Flight
 * Dynamics", ch. 3): forces and moments of main rotor, tail rotor, fuselage,
 * horizontal and vertical tail plus gravity, summed in body axes at the CG;
 *   [u v w]' = F/m - omega x [u v w],   [p q r]' = I^-1 (M - omega x I omega),
 * I with Ixz; Euler rates from eq. (9) inverted. The reference frame S is
 * taken as inertial (steady ship translation; ship motion is the coupling's
 * business). Velocities are relative to S; the air comes from the hfm_air
 * callback, so the aerodynamic velocity at a point is air - point velocity.
 * Main-rotor wake on the airframe: the wake is a cylinder skewed by the
 * wake angle chi from the shaft, blown along dir_H (the skewed cylindrical
 * vortex wake of Heyson and Katzoff, "Induced velocities near a lifting
 * rotor with nonuniform disk loading", NACA Report 1319, 1957; Padfield,
 * "Helicopter Flight Dynamics", 2nd ed., ch. 3, for the interference on
 * fuselage, empennage and tail rotor). Its cross-section at a depth h
 * below the disk is centred h tan(chi) along dir_H from the hub. There:
 * - the air has travelled s = h / cos(chi) from the disk, and the wake's
 *   velocity has grown from the disk's vi to k(s) vi, with
 *   k(s) = 1 + s / sqrt(s^2 + R^2), the axial velocity of a semi-infinite
 *   cylinder of ring vorticity (an actuator disk) on its axis by Biot-Savart
 *   (1 at the disk, 2 in the far wake, momentum theory's limit; Johnson,
 *   "Helicopter Theory", 1980, ch. 2, for the far-wake value);
 * - the radius has contracted to R sqrt(U0/U(s)), U0 = |V_inplane, V_axial
 *   + vi| and U(s) = |V_inplane, V_axial + k vi|, which carries the disk's
 *   mass flow at the faster speed (continuity in the stream tube): R/sqrt(2)
 *   in the far wake of the hover, almost R in forward flight.
 * A point inside sees k(s) vi along the shaft, with a cosine edge of
 * 0.15 R (hfm_wake_point). Each component takes the mean over its own
 * extent (hfm_wake_speed_patch, hfm_wake_speed_disk) by the midpoint rule
 * on cells no wider than the edge, or (the fuselage, fuselage.c) the loads
 * cell by cell; with a single reference point the edge sweeps past it
 * within 1 kt of airspeed (UH-60A trims jump between 47 and 48 kt).
 * Assumptions: uniform velocity across the wake's section (the
 * disk's first-harmonic inflow is not carried downstream: traced along the
 * wake it put the UH-60A's stabilator at 60 kt in the front of the disk's
 * low inflow and its pitch 2.7 deg below GenHel's); the wake straight
 * (no roll-up, which NACA Report 1319 finds far behind the rotor, and no
 * descent steepening with k(s): with that curvature the tail went into
 * the wake at 80 kt and the UH-60A turned speed-unstable there, M_u < 0 and
 * a real root of +0.24 /s, which its flight-test handling does not show).
 */
#include "hfm_priv.h"

#include <string.h>

int hfm_air_uniform_fn(void *user, const double pos_S_m[3], double t_s, double vel_S_mps[3])
{
    (void)pos_S_m;
    (void)t_s;
    const hfm_air_uniform *u = user;
    vel_S_mps[0] = u->vel_S_mps[0];
    vel_S_mps[1] = u->vel_S_mps[1];
    vel_S_mps[2] = u->vel_S_mps[2];
    return 0;
}

void hfm_kin_setup(hfm_kin *k, const hfm_air *air, double t, const hfm_body *b)
{
    /* core_mat3_from_euler's matrix, keeping the sines and cosines */
    double cf = cos(b->euler_rad[0]), sf = sin(b->euler_rad[0]);
    double ct = cos(b->euler_rad[1]), st = sin(b->euler_rad[1]);
    double cs = cos(b->euler_rad[2]), ss = sin(b->euler_rad[2]);
    k->C_SB[0][0] = ct * cs;
    k->C_SB[0][1] = sf * st * cs - cf * ss;
    k->C_SB[0][2] = cf * st * cs + sf * ss;
    k->C_SB[1][0] = ct * ss;
    k->C_SB[1][1] = sf * st * ss + cf * cs;
    k->C_SB[1][2] = cf * st * ss - sf * cs;
    k->C_SB[2][0] = -st;
    k->C_SB[2][1] = sf * ct;
    k->C_SB[2][2] = cf * ct;
    k->sphi = sf;
    k->cphi = cf;
    k->sth = st;
    k->cth = ct;
    memcpy(k->vel_B, b->vel_B_mps, sizeof k->vel_B);
    memcpy(k->rate_B, b->rate_B_radps, sizeof k->rate_B);
    memcpy(k->pos_S, b->pos_S_m, sizeof k->pos_S);
    k->t = t;
    k->air = air;
    /* the uniform wind is the same at every point: sampled once here */
    k->uniform = air->fn == hfm_air_uniform_fn;
    if (k->uniform)
        m3_tmul(k->C_SB, ((const hfm_air_uniform *)air->user)->vel_S_mps, k->air_B);
}

int hfm_air_rel_B(const hfm_kin *k, const double r_B[3], double out_B[3])
{
    double p[3], aS[3], aB[3], w[3];
    if (k->uniform) {
        memcpy(aB, k->air_B, sizeof aB);
    } else {
        m3_mul(k->C_SB, r_B, p);
        for (int i = 0; i < 3; i++)
            p[i] += k->pos_S[i];
        if (k->air->fn(k->air->user, p, k->t, aS))
            return -1;
        m3_tmul(k->C_SB, aS, aB);
    }
    v3_cross(k->rate_B, r_B, w);
    for (int i = 0; i < 3; i++)
        out_B[i] = aB[i] - (k->vel_B[i] + w[i]);
    return 0;
}

/* The wake at the depth h_m below the disk (hub axes): its velocity
 * growth k and its contracted radius squared there (the model in the
 * file's header; the section's centre is h_m tan(chi) along dir_H). */
static void wake_section(const hfm_aircraft *ac, const hfm_wake *w, double h_m, double *k,
                         double *Rw2_m2)
{
    const double R = ac->mr.R, vi = w->vi_mps, vin = w->vin_mps, vax = w->vax_mps;
    double s = h_m * w->sec_skew;
    double kz = 1.0 + s / sqrt(s * s + R * R);
    double t = vax + kz * vi, uz = sqrt(vin * vin + t * t);
    double c = uz > 1e-9 ? clampd(w->u0_mps / uz, 0.25, 1.0) : 1.0;
    *k = kz;
    *Rw2_m2 = R * R * c;
}

double hfm_wake_point(const hfm_aircraft *ac, const hfm_wake *w, const double r_B[3],
                      double *speed_mps)
{
    const hfm_mr *mr = &ac->mr;
    double d[3] = {r_B[0] - mr->hub_B[0], r_B[1] - mr->hub_B[1], r_B[2] - mr->hub_B[2]}, h[3];
    if (speed_mps)
        *speed_mps = 0.0;
    m3_tmul(mr->C_BH, d, h);
    if (h[2] <= 0.0)
        return 0.0;
    double off = h[2] * w->tan_skew, edge = 0.15 * mr->R;
    double dx = h[0] - off * w->dir_H[0], dy = h[1] - off * w->dir_H[1];
    double d2 = dx * dx + dy * dy, imm;
    if (d2 >= (mr->R + edge) * (mr->R + edge)) /* outside even the uncontracted wake */
        return 0.0;
    double kz, Rw2;
    wake_section(ac, w, h[2], &kz, &Rw2);
    if (d2 <= Rw2) {
        imm = 1.0;
    } else {
        double Rw = sqrt(Rw2), dist = sqrt(d2);
        if (dist >= Rw + edge)
            return 0.0;
        imm = 0.5 * (1.0 + cos(CORE_PI * (dist - Rw) / edge));
    }
    if (speed_mps)
        *speed_mps = imm * kz * w->vi_mps;
    return imm;
}

/* Cells along an extent of length len_m: at most one edge width (0.15 R)
 * wide, at least one, at most nmax. */
int hfm_wake_cells(const hfm_aircraft *ac, double len_m, int nmax)
{
    double n = ceil(len_m / (0.15 * ac->mr.R) - 1e-9);
    return n < 1.0 ? 1 : (n > nmax ? nmax : (int)n);
}

double hfm_wake_speed_patch(const hfm_aircraft *ac, const hfm_wake *w, const double c_B[3],
                            const double a_B[3], const double b_B[3])
{
    int na = hfm_wake_cells(ac, 2.0 * sqrt(v3_dot(a_B, a_B)), HFM_WAKE_MAX_CELLS);
    int nb = hfm_wake_cells(ac, 2.0 * sqrt(v3_dot(b_B, b_B)), HFM_WAKE_MAX_CELLS);
    double sum = 0.0;
    for (int i = 0; i < na; i++) {
        double s = -1.0 + (2.0 * i + 1.0) / na;
        for (int j = 0; j < nb; j++) {
            double t = -1.0 + (2.0 * j + 1.0) / nb, p[3];
            for (int k = 0; k < 3; k++)
                p[k] = c_B[k] + s * a_B[k] + t * b_B[k];
            double v;
            hfm_wake_point(ac, w, p, &v);
            sum += v;
        }
    }
    return sum / (na * nb);
}

double hfm_wake_speed_disk(const hfm_aircraft *ac, const hfm_wake *w, const double c_B[3],
                           const double n_B[3], double radius_m)
{
    /* two unit vectors in the disk's plane */
    double e[3] = {0, 0, 1}, u[3], v[3];
    if (fabs(n_B[2]) > 0.9) {
        e[0] = 1.0;
        e[2] = 0.0;
    }
    double en = v3_dot(e, n_B);
    for (int k = 0; k < 3; k++)
        u[k] = e[k] - en * n_B[k];
    double un = sqrt(v3_dot(u, u));
    for (int k = 0; k < 3; k++)
        u[k] /= un;
    v3_cross(n_B, u, v);
    /* three annuli of equal area, each at its area-median radius
     * r sqrt((j + 1/2)/3), with 4, 8 and 12 points */
    double sum = 0.0;
    for (int j = 0; j < 3; j++) {
        int np = 4 * (j + 1);
        double rr = radius_m * sqrt((j + 0.5) / 3.0), ring = 0.0;
        for (int i = 0; i < np; i++) {
            double ps = 2.0 * CORE_PI * (i + 0.5 * j) / np, cu = rr * cos(ps), sv = rr * sin(ps), p[3];
            for (int k = 0; k < 3; k++)
                p[k] = c_B[k] + cu * u[k] + sv * v[k];
            double v;
            hfm_wake_point(ac, w, p, &v);
            ring += v;
        }
        sum += ring / np;
    }
    return sum / 3.0;
}

void hfm_body_accel(const hfm_aircraft *ac, const hfm_body *b, hfm_loads *L)
{
    const double *V = b->vel_B_mps, *w = b->rate_B_radps;
    double wxv[3], Iw[3], wxIw[3], r[3];
    v3_cross(w, V, wxv);
    m3_mul(ac->I, w, Iw);
    v3_cross(w, Iw, wxIw);
    for (int i = 0; i < 3; i++) {
        L->acc_B[i] = L->total.F_B_N[i] / ac->mass - wxv[i];
        r[i] = L->total.M_B_Nm[i] - wxIw[i];
    }
    m3_mul(ac->Iinv, r, L->acc_B + 3);
}

int hfm_eval_rest(const hfm_aircraft *ac, const hfm_kin *k, const hfm_body *b,
                  const hfm_controls *u, const hfm_wake *w0, hfm_loads *L)
{
    hfm_wake w = *w0;
    double th0, A1, B1, thtr, spd;
    hfm_controls_to_pitch(ac, u, &th0, &A1, &B1, &thtr);
    if (hfm_fuselage(ac, k, &w, &L->fus, &spd))
        return -1;
    L->airspeed_mps = spd;
    w.airspeed_kt = spd / CORE_KT_TO_MPS;
    if (hfm_tailrotor(ac, k, &w, thtr, &L->tr, &L->tr_thrust_N, &L->tr_power_W))
        return -1;
    w.ay_g = (L->mr.F_B_N[1] + L->tr.F_B_N[1] + L->fus.F_B_N[1]) / (ac->mass * CORE_G_MPS2);
    if (hfm_empennage(ac, k, &w, &L->stab, &L->fin, &L->stab_incidence_rad))
        return -1;
    double g_S[3] = {0, 0, ac->mass * CORE_G_MPS2}, g_B[3];
    m3_tmul(k->C_SB, g_S, g_B);
    const hfm_fm *c[5] = {&L->mr, &L->tr, &L->fus, &L->stab, &L->fin};
    for (int i = 0; i < 3; i++) {
        L->total.F_B_N[i] = g_B[i];
        L->total.M_B_Nm[i] = 0.0;
        for (int j = 0; j < 5; j++) {
            L->total.F_B_N[i] += c[j]->F_B_N[i];
            L->total.M_B_Nm[i] += c[j]->M_B_Nm[i];
        }
    }
    hfm_body_accel(ac, b, L);
    return 0;
}
