/* hfm_priv.h -- the aircraft data and the component models shared inside hfm.
 * Small vector helpers are inline here because the blade-element loop calls
 * them a few hundred times per evaluation (core's vector functions are out of
 * line); frames, Euler angles and quaternions come from core. */
#ifndef DISIM_HFM_PRIV_H
#define DISIM_HFM_PRIV_H

#include "hfm.h"

#include <math.h>

#define HFM_MAX_SEG 32
#define HFM_MAX_BLADES 8
#define HFM_MAX_AZ 72
#define HFM_TAB_MAX 40

/* An airfoil table resampled on a uniform 1 deg grid over [-180, 180];
 * mach: the compressible drag rise is applied (rotor.c), with the drag
 * divergence Mach number mdd0 at zero lift. */
typedef struct hfm_airfoil {
    double cl[361], cd[361];
    int mach;
    double mdd0;
} hfm_airfoil;

#define HFM_PLAN_MAX 12       /* fuselage planform stations */
#define HFM_WAKE_MAX_CELLS 16 /* wake cells along a side of a part (body.c) */

/* A piecewise-linear table y(x), clamped at its ends. */
typedef struct hfm_table {
    int n;
    double x[HFM_TAB_MAX], y[HFM_TAB_MAX];
} hfm_table;

typedef struct hfm_mr {
    int nb, sense, nseg, naz;
    double R, omega, chord, e, root, B, twist, twist_ref, shaft_tilt;
    double I_beta, S_beta, m_blade, K_beta;
    double hub_B[3];
    double C_BH[3][3]; /* hub -> body */
    double area, rho;
    double r[HFM_MAX_SEG], drl[HFM_MAX_SEG], drd[HFM_MAX_SEG];
    double x[HFM_MAX_SEG], tw[HFM_MAX_SEG]; /* r - e, twist (r/R) */
    double hqc;           /* rho chord / 2 */
    double inv_I_beta, inv_R;
    double az_c[HFM_MAX_AZ], az_s[HFM_MAX_AZ]; /* cos, sin of the trim azimuths */
    hfm_airfoil af;
    double hub_drag_m2;   /* hub and hub-pylon interference flat-plate area, at the hub */
    double hub_dq;        /* 1/2 rho hub_drag_m2 / nb: each blade's share (rotor.c) */
} hfm_mr;

enum { HFM_TR_OPEN = 0, HFM_TR_FENESTRON = 1 };
typedef struct hfm_tr {
    int kind, nb;
    double R, omega, chord, sigma, a, cd0, twist, B, tan_d3, lock, twist_ref;
    double hub_B[3], dir_B[3]; /* thrust direction (anti-torque side, canted) */
    double blockage, blockage_kt; /* thrust factor below that airspeed */
    double fan_fraction;          /* fenestron: fan share of the total thrust */
} hfm_tr;

typedef struct hfm_fus {
    double ref_B[3];
    hfm_table drag, lift, pitch, dbeta; /* m^2, m^2, m^3 vs alpha/beta (rad) */
    double yaw_m3_10deg;                /* N/q at beta = 10 deg, destabilizing */
    double side_m2;                     /* slender-body side force Y/q = -side sin b cos b */
    int plan_n;                         /* wake planform: stations fore to aft (>= 2) */
    double plan_x_B[HFM_PLAN_MAX], plan_w[HFM_PLAN_MAX]; /* body x and width there (m) */
    /* derived (hfm_fuselage_cells): the planform's cells for the wake,
     * cell_na along x by cell_nb across, at cell_x with width cell_w, each
     * of the row carrying cell_cA of the cross-flow drag's 0.5 rho Cc A */
    int cell_na, cell_nb;
    double cell_x[HFM_WAKE_MAX_CELLS], cell_w[HFM_WAKE_MAX_CELLS], cell_cA[HFM_WAKE_MAX_CELLS];
} hfm_fus;

enum { HFM_STAB_FIXED = 0, HFM_STAB_UH60A = 1 };
typedef struct hfm_surf {
    double pos_B[3], area, a, clmax, cd0, ar, incidence;
    int vertical, schedule;
} hfm_surf;

typedef struct hfm_rig {
    double coll_travel, coll_pitch0, coll_gain;
    double long_travel, long_gain;
    double lat_travel, lat_gain;
    double ped_travel, tr_pitch0, tr_gain;
    double mix_cl, mix_pl, mix_ca, mix_cp, mix_cref;
    double swash_phase, swash_c, swash_s; /* and its cos, sin */
} hfm_rig;

struct hfm_aircraft {
    char name[64];
    double mass, I[3][3], Iinv[3][3];
    hfm_mr mr;
    hfm_tr tr;
    hfm_fus fus;
    hfm_surf stab, fin;
    hfm_rig rig;
    int has_sas;       /* the optional [sas] section (aircraft.c) */
    hfm_sas_gains sas;
    int has_gear;      /* the optional [gear] section (aircraft.c) */
    hfm_gear gear;
    int has_eye;       /* the optional [cockpit] section (aircraft.c) */
    double eye_B[3];
    double xmsn_eff;   /* the optional [power] section: transmission efficiency (1 if absent) */
    double acc_W;      /* accessory power (0 if absent) */
    int has_model_error; /* the optional [model_error] section (aircraft.c) */
    hfm_model_error model_error;
};

/* Kinematics shared by the components of one evaluation. */
typedef struct hfm_kin {
    double C_SB[3][3]; /* body -> S */
    double sphi, cphi, sth, cth; /* sin, cos of roll and pitch */
    int uniform;                 /* the air is the uniform wind ... */
    double air_B[3];             /* ... of this velocity in body axes */
    double vel_B[3], rate_B[3], pos_S[3];
    double t;
    const hfm_air *air;
} hfm_kin;

/* Main-rotor wake quantities seen by the other components. */
typedef struct hfm_wake {
    double vi_mps;   /* disk-average induced velocity */
    double vin_mps, vax_mps; /* the wake air through the disk: in-plane speed and
                                the component down the shaft (induced excluded) */
    double u0_mps;   /* |vin, vax + vi|: the air's speed through the disk */
    double sec_skew; /* sqrt(1 + tan_skew^2): path length per depth below the disk */
    double skew_rad; /* wake skew from the shaft (NaN in time simulation,
                        which uses only tan_skew) */
    double tan_skew; /* tan of the skew, held at 89 deg */
    double dir_H[2]; /* in-plane direction the wake is blown to (hub axes) */
    double coll_pct, airspeed_kt, q_degps, ay_g;
    double *tr_inflow; /* NULL, or the tail-rotor inflow of the last evaluation
                          (a first guess, updated; NaN: none yet) */
} hfm_wake;

/* inline vector helpers */
static inline void v3_cross(const double a[3], const double b[3], double o[3])
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}
static inline double v3_dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
static inline void m3_mul(const double m[3][3], const double v[3], double o[3])
{
    o[0] = m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2];
    o[1] = m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2];
    o[2] = m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2];
}
static inline void m3_tmul(const double m[3][3], const double v[3], double o[3])
{
    o[0] = m[0][0] * v[0] + m[1][0] * v[1] + m[2][0] * v[2];
    o[1] = m[0][1] * v[0] + m[1][1] * v[1] + m[2][1] * v[2];
    o[2] = m[0][2] * v[0] + m[1][2] * v[1] + m[2][2] * v[2];
}
static inline double clampd(double x, double lo, double hi)
{
    return x < lo ? lo : (x > hi ? hi : x);
}

/* aircraft.c */
double hfm_table_eval(const hfm_table *t, double x);
/* The line of section/key in ini (0 if absent). */
int hfm_aircraft_key_line(const core_ini *ini, const char *sec, const char *key);
/* aircraft_check.c: the physical-consistency checks of a loaded aircraft
 * (errors name file, line and key of ini; warnings go to log). 0 or -1. */
int hfm_aircraft_check(const hfm_aircraft *ac, const core_ini *ini, const core_log *log, core_err *err);
/* Lift and drag at alpha (rad, any value; NaN reads the -180 deg entry). */
static inline void hfm_airfoil_eval(const hfm_airfoil *af, double alpha_rad, double *cl,
                                    double *cd)
{
    double a = alpha_rad * (180.0 / 3.14159265358979323846) + 180.0;
    if (!(a > 0.0)) /* also NaN: an index must stay in the table */
        a = 0.0;
    if (a > 359.999999)
        a = 359.999999;
    int i = (int)a;
    double f = a - i;
    *cl = af->cl[i] + f * (af->cl[i + 1] - af->cl[i]);
    *cd = af->cd[i] + f * (af->cd[i + 1] - af->cd[i]);
}

/* body.c: kinematics set-up and the air relative velocity at a body point
 * (air minus point velocity, body axes). */
void hfm_kin_setup(hfm_kin *k, const hfm_air *air, double t, const hfm_body *b);
int hfm_air_rel_B(const hfm_kin *k, const double r_B[3], double out_B[3]);
void hfm_body_accel(const hfm_aircraft *ac, const hfm_body *b, hfm_loads *L);
/* The immersion (0..1) of a body point in the main-rotor wake, and where
 * speed_mps is not NULL the wake's velocity there along the shaft (m/s,
 * down the shaft positive): immersion x axial growth x the disk's vi. */
double hfm_wake_point(const hfm_aircraft *ac, const hfm_wake *w, const double r_B[3],
                      double *speed_mps);
/* The mean wake velocity (m/s along the shaft) over the parallelogram
 * c_B + s a_B + t b_B (s, t in [-1, 1]; a_B, b_B its half-sides, m), on
 * cells at most 0.15 R wide (at most HFM_WAKE_MAX_CELLS along a side); a
 * zero half-side is one cell. */
/* Cells along an extent of len_m: at most 0.15 R wide, 1 to nmax of them. */
int hfm_wake_cells(const hfm_aircraft *ac, double len_m, int nmax);
double hfm_wake_speed_patch(const hfm_aircraft *ac, const hfm_wake *w, const double c_B[3],
                            const double a_B[3], const double b_B[3]);
/* The mean wake velocity over a disk (centre c_B, unit normal n_B, radius_m). */
double hfm_wake_speed_disk(const hfm_aircraft *ac, const hfm_wake *w, const double c_B[3],
                           const double n_B[3], double radius_m);

/* rotor.c */
typedef struct hfm_blade_out {
    double F_H[3], M_H[3]; /* loads on the hub (hub axes), moment about the hub centre */
    double M_flap;         /* aerodynamic flap moment about the hinge */
    double T, Lr, Mp;      /* thrust (up) and its first moments r sin psi, r cos psi */
    double P;              /* aerodynamic power absorbed */
    double ddbeta;         /* flap acceleration used (solved when asked) */
    double G;              /* non-aerodynamic flap moment (centrifugal, spring, gyro, weight) */
} hfm_blade_out;
typedef struct hfm_rotor_in {
    double theta0, A1, B1;             /* blade pitch (root), cyclic */
    double vhub_H[3], rate_H[3];       /* hub velocity rel. S and body rate, hub axes */
    double C_SH[3][3];                 /* hub -> S */
    double hub_S[3];
    double lam[3];                     /* lambda0, lambda1s, lambda1c */
    double t;
    const hfm_air *air;
    double g_H[3];                     /* gravity in hub axes */
    double rel_hub_H[3];               /* air relative to the hub centre, hub axes */
    double wake_rel_H[3];              /* the same in the wake's air (hfm_air.wake; else = rel_hub_H) */
    double C_BH_z[3];                  /* shaft axis (down) in body axes */
    double air_H[3];                   /* air at the hub, hub axes */
    int uniform;                       /* the air is the uniform wind (same everywhere) */
} hfm_rotor_in;
int hfm_rotor_setup(const hfm_aircraft *ac, const hfm_kin *k, const hfm_controls *u,
                    const double lam[3], hfm_rotor_in *in);
/* One blade at azimuth psi, given as cos psi and sin psi; ddbeta given, or
 * (solve_dd) from the flap equation with this blade's loads. */
int hfm_rotor_blade(const hfm_aircraft *ac, const hfm_rotor_in *in, double cos_psi,
                    double sin_psi, double beta, double dbeta, double ddbeta, int solve_dd,
                    hfm_blade_out *o, double *dT, double *dS);
/* nbl blades at once (their elements evaluated together, in chunks of
 * HFM_MAX_BLADES): the same as hfm_rotor_blade for each; ddbeta NULL solves
 * each blade's flap acceleration from its flap equation. */
int hfm_rotor_blades(const hfm_aircraft *ac, const hfm_rotor_in *in, int nbl,
                     const double *cos_psi, const double *sin_psi, const double *beta,
                     const double *dbeta, const double *ddbeta, hfm_blade_out *o);
/* Lhat of Pitt-Peters at the rotor's state; the wake skew in *skew (NULL:
 * not computed). */
void hfm_rotor_inflow(const hfm_aircraft *ac, const hfm_rotor_in *in, double CT, double CL,
                      double CM, double Lhat[3][3], double *skew);
void hfm_rotor_wake(const hfm_aircraft *ac, const hfm_rotor_in *in, double skew,
                    const hfm_controls *u, const hfm_body *b, hfm_wake *w);
void hfm_rotor_harm_beta(const hfm_rotor_harm *rh, double Om, double cos_psi, double sin_psi,
                         double *b, double *db, double *ddb);
void hfm_rotor_to_body(const hfm_aircraft *ac, const double F_H[3], const double M_H[3],
                       hfm_fm *fm);

/* tailrotor.c, fuselage.c, empennage.c */
int hfm_tailrotor(const hfm_aircraft *ac, const hfm_kin *k, const hfm_wake *w, double theta,
                  hfm_fm *fm, double *thrust, double *power);
int hfm_fuselage(const hfm_aircraft *ac, const hfm_kin *k, const hfm_wake *w, hfm_fm *fm,
                 double *airspeed);
/* Derive the planform's wake cells (hfm_fus.cell_*) once the main rotor
 * (its radius, the air's density) and the fuselage are loaded. */
void hfm_fuselage_cells(hfm_aircraft *ac);
int hfm_empennage(const hfm_aircraft *ac, const hfm_kin *k, const hfm_wake *w, hfm_fm *stab,
                  hfm_fm *fin, double *incidence);
double hfm_stab_schedule_uh60a(const hfm_wake *w);

const hfm_aircraft *hfm_trim_aircraft(const hfm_trim *tr);

/* evaluate all non-rotor components and sum with the rotor; in body.c */
int hfm_eval_rest(const hfm_aircraft *ac, const hfm_kin *k, const hfm_body *b,
                  const hfm_controls *u, const hfm_wake *w, hfm_loads *L);

/* The air of a trim condition: its own callback, or the uniform wind it
 * implies (still air in forward flight, the WOD in a hover over the ship);
 * wind is the storage the uniform callback points to. */
void hfm_trim_cond_air(const hfm_trim_cond *c, hfm_air_uniform *wind, hfm_air *air);

#endif
