/* pilot_auto.c -- the automated pilot: a multi-loop human pilot model that
 * flies a task file with the four controls a person has.
 *
 * The model. Each inner loop is closed as the crossover model of McRuer
 * and Krendel (1974, AGARDograph AG-188, the crossover model of their
 * chapter on compensatory tracking): near crossover the pilot adapts so
 * that pilot and aircraft together look like
 *     Y_p Y_c = w_c exp(-tau s) / s,
 * an integrator at the crossover frequency w_c behind the pilot's pure
 * delay tau. Around hover each axis of the airframe is, to first order,
 * an attitude (or height) behind a first-order rate response,
 *     Y_c = K / (s (s - a)),
 * (roll: K = L_lat, a = L_p; pitch: M_long, M_q; heading: N_ped, N_r;
 * height, z down: Z_col, Z_w), so the pilot's equalisation is a lead at
 * the aircraft's rate pole:
 *     Y_p = (w_c / K) (s + a_L) exp(-tau s),  a_L = max(-a, 0.3 w_c),
 * i.e. delta = delta_trim + (w_c / K) (a_L e - rate) on the error e (the
 * lead floor keeps a weakly damped axis from asking for a pure rate loop).
 * The loop stays stable while w_c tau < pi / 2 (the phase of the delay
 * eats the integrator's 90 deg margin): 0.63 s at w_c = 2.5 rad/s.
 * The outer loops, as in the multi-loop structure of Lee and Horn (2005,
 * "Simulation of pilot control activity during helicopter shipboard
 * operations", J. Aircraft 42(2), the pilot model's outer guidance
 * loops), run at separated bandwidths, each several times slower than the
 * one inside it: position -> commanded velocity (pos_bw, plus the
 * reference's own velocity fed forward, limited to max_speed), velocity
 * -> commanded acceleration (vel_bw), acceleration -> attitude through
 * the linear model's force derivatives
 *     theta_c = theta_trim + (a_x - X_u u) / X_theta,
 *     phi_c   = phi_trim   + (a_y - Y_v v) / Y_phi,
 * in the helicopter's heading axes, limited to max_att from trim. The
 * gains are scheduled from hfm_linearise's A and B at the task's first
 * hover in the WOD of the options (uniform air); the trims the loops act
 * about are the flight's own, in its air (the airwake): the controls'
 * (sim_flight_trim_inputs) and, with sim_pilot_auto_set_trim_state, the
 * attitudes theta_trim and phi_trim (the trimmed start's body relative
 * to S). Over the CG-47's deck the airwake's trim pitches 1.1 deg more
 * than the uniform WOD's at 40 km/h ahead (7.69 against 6.58 deg); with
 * the uniform trim's references the helicopter drifted until the
 * position loop took up the difference (test_pilot_auto, case 10: 0.68 m
 * in 40 s from a 0.82 deg difference; none with the flight's). The whole command vector goes through one pure delay (a
 * ring buffer of round(delay * rate) steps, filled with the trim at the
 * start): the pilot's perception and neuromuscular lag lumped, as tau in
 * the crossover model. No clock or random number inside: the same flight
 * gives the same controls. The height loop's crossover (2 rad/s, w_c tau
 * = 0.5 rad) is the attitude loops' order: a pilot over a deck holds
 * height tightly, and at 1 rad/s the airwake's downdraft past the deck
 * edge (the CG-47's coarse airwake, 25 kt from red 30) sank the UH-60A
 * onto the deck edge in a manual run (docs/validation.md has the
 * command).
 *
 * The pilot's trim (opts.trim_s, 8 s): a slow integral of the position
 * and height errors added to them, as a pilot trims out a steady force
 * (a mean airwake, a wind the gains were not scheduled for), bounded to
 * 1 m/s of commanded speed and 10 % of collective; its corner 1 / trim_s
 * lies well below the loops' bandwidths (0.3 and 2 rad/s), so it costs
 * them little phase. The height's is held during a descent.
 *
 * The steady trims (opts.moment_s and heave_s; 0 by default, the replay
 * pilot's 4 / att_crossover and 4 / hgt_crossover): a steady roll or
 * pitch moment that the linear model does not have (an airwake's over a
 * deck) leaves each attitude loop, a proportional law, standing off its
 * command by m / (w_c a_L) (m the moment as an angular acceleration),
 * which the velocity loop then meets as a steady force; a steady vertical
 * force (the downdraft past a deck edge) leaves the height loop off by
 * as much. The pilot takes each as the part of the rate's change over a
 * step that the rate damping and the control applied do not explain,
 *     m = dx/dt - a x - K (delta - delta_trim)
 * (x = p, q with L_p, M_q and the cyclic; x = w, the vertical speed, with
 * Z_w and the collective), averages it over its time constant and takes
 * it out with the control, delta -= m / K (at most 10 % of travel; held
 * while a control is at its stop or a wheel on the deck). A manoeuvre's
 * own lag is the controls' doing and does not enter m; an integral of
 * the attitude error would wind up on it (the replay's roll-in in
 * test_pilot_replay, SAS off: 3 deg past the reference's 6 deg with one
 * at 1.6 s).
 *
 * With the SAS (opts.sas = 1, the flight's SAS engaged, sim/sas.c) the
 * pilot flies the augmented aircraft, as a pilot does: the plant of each
 * attitude loop is the linear model with the SAS's rate feedback closed,
 *     a = L_p - L_lat K_rate,roll  (and so on: A - B K_rate on the rate
 * rows), so the lead a_L sits at the augmented rate pole. The SAS's
 * attitude hold is left in the loop unmodelled: the pilot's stick moves
 * by more than its detent (1 % of travel in the aircraft files) in each
 * correction, so the hold keeps re-taking its reference and acts as a
 * weak spring about the pilot's recent attitude.
 *
 * Assumptions: small attitudes (heading axes from the heading alone); the
 * deck's roll and pitch are not followed (the target is in S, the
 * attitude references in E); the pilot sees the ship's frame (the spot's
 * heave) without error.
 *
 * The reference (sim_pilot_ref) is what the outer loops track: a point
 * and velocity in S, a heading, and hold or descend. The task's phases set
 * it each step; sim_pilot_auto_set_reference lets a caller set it instead.
 *
 * Phases (scenarios/README.md, the task files):
 *   hold: the reference at the phase's target; the phase ends once it has
 *     met its desired band (within it no later than the band's time_s and
 *     then for duration_s), else at the adequate band's time plus
 *     duration_s (graded adequate if met, else not met).
 *   move: the reference moves from where it was to the target along a
 *     straight line at speed_mps (the velocity fed forward), speeding up
 *     from rest and slowing to rest at 0.2 m/s^2 (MOVE_ACC_MPS2), as a
 *     pilot starts and stops a translation over a deck: a step in the
 *     commanded speed banked the UH-60A 6 deg from trim to start and stop
 *     the 1 m/s traverse of land_port.ini, past its 5 deg roll limit, and
 *     the roll-yaw coupling took the heading loop's pedal 1.24 % below
 *     the hover's trim, under the 20 % limit (test_pilot_auto, case 11,
 *     calm air: 1.85 deg and 0.53 % with the profile); graded on
 *     the distance from the moving reference throughout and on arriving
 *     (within the band of the target) by time_s; it ends on arrival
 *     within the adequate band, or at adequate.time_s.
 *   descend: wait (quiescent = 1) for a quiescent period of the deck's
 *     heave, and, as a shipboard pilot does, until over the spot and
 *     nearly still: within half the desired position band (GATE_FRAC)
 *     and below the desired drift (0.5 m/s without one) at that moment;
 *     max_wait_s starts it regardless. Then the height reference moves
 *     down at descent_mps to 0.3 m below the wheels' contact height, the
 *     position and velocity loops flying on; while the helicopter is
 *     outside half the desired band and its wheels more than 0.5 m
 *     (COMMIT_M) above the deck the height reference pauses, as a pilot
 *     stops the descent to re-centre over the spot, unless the rest of
 *     the way down (twice clearance / descent_mps, as the phase length
 *     allows for the height loop's lag) would end past the adequate
 *     band's time_s. In the coarse LPD-17
 *     airwake (SA365N, 20 kt from green 30, sea state 3, turbulence) the
 *     hover over the spot wanders about 1.5 m and drifts up to 0.5 m/s:
 *     a descent begun off the spot or drifting, or flown through a drift
 *     in the last metres, landed up to 2 m from it (docs/validation.md,
 *     the manual run). Graded at touchdown on the distance from the
 *     target's x, y, the sink rate, the drift and the heading,
 *     touchdown by time_s (the waits count).
 *   A legacy file (type station_keep or land with target_S_m, [desired],
 *   [adequate]) is one hold phase, and for land a descend phase after it.
 *
 * Grading (ADS-33E-PRF style): the helicopter is within a band when its
 * horizontal distance from the reference, its height error and its
 * heading error are all within the band's tolerances. The task's grade is
 * the lowest of its phases'.
 *
 * The quiescent period. Ferrier's Landing Period Designator (Ferrier and
 * Manning, "Simulation and testing of the Landing Period Designator (LPD)
 * helicopter recovery aid", Naval Engineers Journal, 1998) tells the
 * pilot when the deck's motion energy is low enough to land. Here the
 * energy is that of the spot's heave: with h the spot's heave (up, from
 * its mean) and h' its rate, from the ship's frame in the flight's
 * outputs,
 *     E = (h'^2 / var(h') + (h - mean h)^2 / var(h)) / 2,
 * the variances and mean over the flight so far (after at least 10 s): E
 * averages 1, and for a narrow-band heave it is the squared envelope,
 * which changes slowly, so a low E now predicts a small heave over the
 * next fraction of a period. The deck is quiescent once E has stayed
 * below quiet_energy for quiet_window_s (a still deck, h' rms under
 * 1 mm/s, always is); the descent waits for it up to max_wait_s.
 * The heave phase at touchdown is atan2(-h' / w, h - mean) with w =
 * sqrt(var(h') / var(h)): 0 at a crest, pi in a trough.
 *
 * Touchdown is the first state with a wheel (the aircraft file's [gear],
 * strut extended: its tyre's lowest point) at the deck plane z_S = 0
 * (without [gear]: the CG at touchdown_height_m); its sink rate and drift
 * are relative to the deck (the change of the CG's position in S over
 * the last step), the roll and pitch those of the body relative to S.
 * With the gear (opts.gear = 1, sim/contact.c attached to the flight)
 * the pilot then holds cyclic and pedals where they were and lowers the
 * collective at 20 %/s to 0 % (no delay: the hand goes down), and the run
 * is done once the CG has moved less than 0.05 m/s relative to the deck
 * for 1 s; without the gear the run is done at touchdown and the loops
 * fly on.
 *
 * Control activity (per control, from the start to touchdown): the rms
 * about the mean, the rms of the rate, and the cut-off frequency: the
 * frequency below which cutoff_fraction (0.5) of the rate's variance
 * lies, the pilot-workload measure of Blanken and Pausder (1994,
 * "Investigation of the effects of bandwidth and time delay on helicopter
 * roll-axis handling qualities", J. American Helicopter Society 39(3)) as
 * Lee and Horn (2005) use it for shipboard landings. The controls are
 * averaged over 0.05 s (20 Hz), differenced into rates, and their
 * spectrum taken as a running discrete Fourier transform at 0.05 rad/s
 * spacing up to 30 rad/s (the variance above 30 rad/s left out).
 */
#include "sim.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define NX HFM_LIN_NX
#define NU HFM_LIN_NU
#define NBIN 600          /* spectrum bins, 0.05 rad/s apart */
#define BIN_RADPS 0.05
#define DEC_S 0.05        /* the controls' averaging for the spectrum */
#define LEARN_S 10.0      /* the heave statistics' shortest history */
#define DOWN_PCTPS 20.0   /* the collective lowered after touchdown */
#define SETTLE_MPS 0.05
#define SETTLE_S 1.0
#define MOVE_ACC_MPS2 0.2 /* a move's reference speeds up and slows down at this */
#define GATE_FRAC 0.5     /* descend: within this fraction of the desired position and drift */
#define COMMIT_M 0.5      /* descend: the wheels' clearance below which the descent goes on regardless */
#define STEADY_PCT 10.0   /* opts.moment_s, heave_s: the estimates' largest share of their control (% of travel) */

struct sim_pilot_auto {
    sim_task task;
    sim_pilot_auto_opts o;
    sim_pilot_gains g;
    hfm_gear gear;
    int have_gear;
    double a_lead[4];        /* lead corner per axis: roll, pitch, yaw, height */
    int nbuf, head;          /* the delay's ring buffer of commands */
    double *buf;             /* nbuf x 4 */
    sim_task_result r;
    double z_ref_S_m;        /* the height loop's reference (S, z down) */
    double prev_pos_S_m[3], prev_t_s; /* the last state seen (deck-relative rates) */
    int have_prev;
    sim_pilot_ref ref;       /* what the outer loops track */
    int external;            /* 1: a caller sets the reference (the phases do not) */
    double td_height_m;      /* the CG's height above the deck at wheel contact */
    /* the phase machine */
    int ph;                  /* the phase flown (nphases: over) */
    double ph_t0_s;          /* its start */
    double since[2];         /* hold: within the band since (-1: not) */
    int met[2];              /* hold: the band (0 adequate, 1 desired) was met; move: kept */
    double move_from[3], move_len_m; /* move: the line's start and length */
    int descending;          /* descend: the descent is under way */
    double quiet_since_s;    /* descend: E below the threshold since (-1: not) */
    int desc_hold;           /* descend: the height reference paused (off the spot, above COMMIT_M) */
    double clear_m;          /* the wheels' clearance above the deck, this state */
    /* after touchdown */
    double coll_pct, hold_u[4];
    double still_since_s;
    double i_pos_S[2], i_hgt;  /* the trim's integrals of the position and height errors (m s) */
    /* opts.moment_s, heave_s: the steady moments' and vertical force's estimates (roll,
     * pitch: rad/s^2; heave: m/s^2), and the rates and controls (lat, long, collective)
     * of the last step they come from */
    double m_est[3], m_rate[3], m_u[3];
    int m_have;
    int stopped;             /* the last command had a control at its stop */
    /* the heave's running statistics (spot, up) */
    double h_prev_m, hd_last_mps;
    long hn;
    double h_sum, h_sum2, hd_sum2, e_now;
    /* control activity */
    double dec_acc[4];
    int dec_n;
    long ns;                 /* decimated samples */
    double u_prev[4], u_sum[4], u_sum2[4], du_sum[4], du_sum2[4];
    double (*Xre)[NBIN], (*Xim)[NBIN]; /* 4 x NBIN, the rate's running DFT */
};

static int pos_fin(double v) { return isfinite(v) && v > 0.0; }


static double clampd(double v, double lo, double hi) { return fmin(fmax(v, lo), hi); }

/* The body's attitude relative to the ship's frame: C_SB = C_ES^T C_EB. */
static void body_in_S(const sim_flight_out *out, double C_SB[3][3])
{
    core_euler e = {out->euler_E_rad[0], out->euler_E_rad[1], out->euler_E_rad[2]};
    core_mat3 C_EB = core_mat3_from_euler(e);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double s = 0.0;
            for (int k = 0; k < 3; k++)
                s += out->ship.C_ES[3 * k + i] * C_EB.m[k][j];
            C_SB[i][j] = s;
        }
}

/* --------------------------------------------------------------- the pilot */

void sim_pilot_auto_opts_default(sim_pilot_auto_opts *o)
{
    memset(o, 0, sizeof *o);
    o->rate_hz = 200.0;
    o->delay_s = 0.25;
    o->att_crossover_radps = 2.5;
    o->yaw_crossover_radps = 1.5;
    o->hgt_crossover_radps = 2.0;
    o->vel_bw_radps = 0.8;
    o->pos_bw_radps = 0.3;
    o->max_speed_mps = 3.0;
    o->max_att_rad = 10.0 * CORE_DEG_TO_RAD;
    o->cutoff_fraction = 0.5;
    o->trim_s = 8.0;
}

/* The CG's height above a level deck when the lowest wheel, strut
 * extended, touches it (the aircraft file's [gear]; 2 m without one). */
static double gear_height(const hfm_gear *g, int have)
{
    if (!have)
        return 2.0;
    double h = 0.0;
    for (int i = 0; i < g->nlegs; i++)
        h = fmax(h, g->leg[i].pos_B_m[2] + g->leg[i].tyre_radius_m);
    return h;
}

static int ref_ok(const sim_pilot_ref *r)
{
    for (int i = 0; i < 3; i++)
        if (!isfinite(r->pos_S_m[i]) || !isfinite(r->vel_S_mps[i]))
            return 0;
    if (!(fabs(r->heading_rad) <= M_PI) || (r->mode != SIM_PHASE_HOLD && r->mode != SIM_PHASE_DESCEND))
        return 0;
    return r->mode == SIM_PHASE_HOLD || (r->vel_S_mps[2] > 0.0 && r->vel_S_mps[2] <= 5.0);
}

/* The one way the reference changes (the phases and a caller alike): a
 * descent starts from the height reference where it is. */
static void set_ref(sim_pilot_auto *p, const sim_pilot_ref *r)
{
    if (r->mode == SIM_PHASE_HOLD)
        p->z_ref_S_m = r->pos_S_m[2];
    p->ref = *r;
}

int sim_pilot_auto_set_reference(sim_pilot_auto *p, const sim_pilot_ref *r)
{
    if (!p || !r || !ref_ok(r))
        return -1;
    p->external = 1;
    set_ref(p, r);
    return 0;
}

void sim_pilot_auto_reference(const sim_pilot_auto *p, sim_pilot_ref *r) { *r = p->ref; }

static void hold_ref(sim_pilot_auto *p, const double pos[3], const double vel[3], double heading)
{
    sim_pilot_ref r;
    memset(&r, 0, sizeof r);
    memcpy(r.pos_S_m, pos, sizeof r.pos_S_m);
    if (vel)
        memcpy(r.vel_S_mps, vel, sizeof r.vel_S_mps);
    r.heading_rad = core_wrap_pi(heading);
    r.mode = SIM_PHASE_HOLD;
    set_ref(p, &r);
}

/* Start phase i at t_s. */
static void phase_start(sim_pilot_auto *p, int i, double t_s)
{
    p->ph = i;
    p->r.phase_now = i;
    p->ph_t0_s = t_s;
    p->since[0] = p->since[1] = -1.0;
    p->met[0] = p->met[1] = 0;
    p->descending = 0;
    p->desc_hold = 0;
    p->quiet_since_s = -1.0;
    if (i >= p->task.nphases)
        return;
    sim_phase_result *pr = &p->r.phase[i];
    pr->grade = 0;
    pr->t_start_s = t_s;
    pr->t_end_s = -1.0;
    const sim_task_phase *ph = &p->task.phase[i];
    if (ph->kind == SIM_PHASE_MOVE) {
        memcpy(p->move_from, p->ref.pos_S_m, sizeof p->move_from);
        p->met[0] = p->met[1] = 1; /* kept while within the band about the moving reference */
        double d[3] = {ph->target_S_m[0] - p->move_from[0], ph->target_S_m[1] - p->move_from[1],
                       ph->target_S_m[2] - p->move_from[2]};
        p->move_len_m = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    }
    if (!p->external && ph->kind != SIM_PHASE_MOVE)
        hold_ref(p, ph->kind == SIM_PHASE_DESCEND
                        ? (double[3]){ph->target_S_m[0], ph->target_S_m[1], p->ref.pos_S_m[2]}
                        : ph->target_S_m,
                 NULL, ph->heading_rad);
}

/* The task's kind and phases as the pilot flies them. 0, or -1 with err. */
static int task_ok(const sim_task *t, core_err *err)
{
    if ((t->kind != SIM_TASK_STATION_KEEP && t->kind != SIM_TASK_LAND) || t->nphases < 1 ||
        t->nphases > SIM_TASK_MAX_PHASES)
        return core_err_set(err, -1, "pilot_auto: task type %d with %d phases: expected station keeping (%d) or land "
                                     "(%d) with 1 to %d phases (sim_task_load)",
                            t->kind, t->nphases, SIM_TASK_STATION_KEEP, SIM_TASK_LAND, SIM_TASK_MAX_PHASES);
    for (int i = 0; i < t->nphases; i++) {
        const sim_task_phase *ph = &t->phase[i];
        if ((ph->kind == SIM_PHASE_DESCEND && !(ph->descent_mps > 0.0)) ||
            (ph->kind == SIM_PHASE_MOVE && !(ph->speed_mps > 0.0)))
            return core_err_set(err, -1, "pilot_auto: phase %s needs a rate > 0", ph->name);
    }
    return 0;
}

/* The gains' schedule: the hover at the first phase's target in the
 * options' WOD, linearised (with the SAS's rate feedback closed when the
 * pilot flies it), the trim's controls and attitude, the lead's corner on
 * each axis. 0, or < 0 with err. */
static int schedule_gains(sim_pilot_auto *p, const hfm_aircraft *ac, const sim_task *t, const sim_flight_inputs *trim,
                          const core_log *log, core_err *err)
{
    const sim_pilot_auto_opts *o = &p->o;
    hfm_sas_gains sg;
    memset(&sg, 0, sizeof sg);
    if (o->sas && hfm_aircraft_sas(ac, &sg) != 0) {
        core_err_set(err, -1, "pilot_auto: flying with the SAS: %s has no [sas]", hfm_aircraft_name(ac));
        return -1;
    }
    hfm_trim *tr = hfm_trim_create(ac, log);
    if (!tr)
        return core_err_set(err, -1, "pilot_auto: out of memory");
    hfm_trim_cond c;
    memset(&c, 0, sizeof c);
    c.kind = HFM_TRIM_HOVER_SHIP;
    c.wod_speed_mps = o->wod_speed_mps;
    c.wod_dir_rad = o->wod_dir_rad;
    memcpy(c.pos_S_m, t->phase[0].target_S_m, sizeof c.pos_S_m);
    hfm_trim_result res;
    hfm_linear L;
    int rc = hfm_trim_solve(tr, &c, NULL, &res);
    if (rc == 0)
        rc = hfm_linearise(tr, &c, &res, &L);
    hfm_trim_destroy(tr);
    if (rc != 0) {
        core_err_set(err, rc > 0 ? CORE_ERR_NO_TRIM : CORE_ERR_FAIL,
                     "pilot_auto: the hover at the task's first point (%.2f, %.2f, %.2f) m in S in %.2f m/s %s",
                     c.pos_S_m[0], c.pos_S_m[1], c.pos_S_m[2], o->wod_speed_mps,
                     rc > 0 ? "does not trim" : "could not be linearised");
        return -1;
    }
    sim_pilot_gains *g = &p->g;
    g->X_u = L.A[0 * NX + 0];
    g->X_theta = L.A[0 * NX + 7];
    g->Y_v = L.A[1 * NX + 1];
    g->Y_phi = L.A[1 * NX + 6];
    g->Z_w = L.A[2 * NX + 2];
    g->Z_col = L.B[2 * NU + 0];
    g->M_long = L.B[4 * NU + 1];
    g->L_lat = L.B[3 * NU + 2];
    g->N_ped = L.B[5 * NU + 3];
    /* the rate rows with the SAS's rate feedback closed (A - B K_rate):
     * its command -K_rate w on lat (roll), long (pitch), pedal (yaw) */
    g->L_p = L.A[3 * NX + 3] - L.B[3 * NU + 2] * sg.rate_pct_per_radps[0];
    g->M_q = L.A[4 * NX + 4] - L.B[4 * NU + 1] * sg.rate_pct_per_radps[1];
    g->N_r = L.A[5 * NX + 5] - L.B[5 * NU + 3] * sg.rate_pct_per_radps[2];
    g->trim_pct[0] = trim->ctl.collective_pct;
    g->trim_pct[1] = trim->ctl.long_cyclic_pct;
    g->trim_pct[2] = trim->ctl.lat_cyclic_pct;
    g->trim_pct[3] = trim->ctl.pedal_pct;
    g->trim_att_rad[0] = res.body.euler_rad[0];
    g->trim_att_rad[1] = res.body.euler_rad[1];
    const double K[4] = {g->L_lat, g->M_long, g->N_ped, g->Z_col};
    const double ctl[4] = {g->X_theta, g->Y_phi, 0.0, 0.0};
    for (int i = 0; i < 4; i++)
        if (!(fabs(K[i]) > 1e-9) || !isfinite(K[i]) || (i < 2 && !(fabs(ctl[i]) > 1e-6))) {
            core_err_set(err, -1, "pilot_auto: the linear model has no control on axis %d (derivative %g)", i, K[i]);
            return -1;
        }
    const double a[4] = {g->L_p, g->M_q, g->N_r, g->Z_w};
    const double wc[4] = {o->att_crossover_radps, o->att_crossover_radps, o->yaw_crossover_radps,
                          o->hgt_crossover_radps};
    for (int i = 0; i < 4; i++)
        p->a_lead[i] = fmax(-a[i], 0.3 * wc[i]);
    return 0;
}

/* The result's and the reference's start: nothing flown yet, the
 * reference at the first phase's target. */
static void result_start(sim_pilot_auto *p, const sim_task *t)
{
    const sim_pilot_gains *g = &p->g;
    p->r.t_desired_s = p->r.t_adequate_s = p->r.t_descent_s = p->r.t_touchdown_s = p->r.t_settled_s = -1.0;
    p->td_height_m = p->have_gear ? gear_height(&p->gear, 1)
                     : t->touchdown_height_m > 0.0 ? t->touchdown_height_m
                                                   : 2.0;
    p->r.nphases = t->nphases;
    for (int i = 0; i < SIM_TASK_MAX_PHASES; i++) {
        p->r.phase[i].grade = -1;
        p->r.phase[i].t_start_s = p->r.phase[i].t_end_s = -1.0;
    }
    for (int i = 0; i < 4; i++) {
        p->r.min_pct[i] = g->trim_pct[i];
        p->r.max_pct[i] = g->trim_pct[i];
    }
    memcpy(p->ref.pos_S_m, t->phase[0].target_S_m, sizeof p->ref.pos_S_m);
    p->ref.heading_rad = t->phase[0].heading_rad;
    p->z_ref_S_m = p->ref.pos_S_m[2];
    p->still_since_s = -1.0;
}

sim_pilot_auto *sim_pilot_auto_create(const hfm_aircraft *ac, const sim_task *t, const sim_pilot_auto_opts *o,
                                      const sim_flight_inputs *trim, const core_log *log, core_err *err)
{
    if (!ac || !t || !o || !trim || !(o->rate_hz >= 10.0 && o->rate_hz <= 10000.0) ||
        !(o->delay_s >= 0.0 && o->delay_s <= 10.0) || !pos_fin(o->att_crossover_radps) ||
        !pos_fin(o->yaw_crossover_radps) || !pos_fin(o->hgt_crossover_radps) || !pos_fin(o->vel_bw_radps) ||
        !pos_fin(o->pos_bw_radps) || !pos_fin(o->max_speed_mps) || !pos_fin(o->max_att_rad) ||
        !(o->wod_speed_mps >= 0.0) || (o->sas != 0 && o->sas != 1) || (o->gear != 0 && o->gear != 1) ||
        !(o->cutoff_fraction > 0.0 && o->cutoff_fraction < 1.0) || !(o->trim_s >= 0.0 && o->trim_s <= 1000.0) ||
        !(o->moment_s >= 0.0 && o->moment_s <= 1000.0) || !(o->heave_s >= 0.0 && o->heave_s <= 1000.0)) {
        core_err_set(err, -1, "pilot_auto: expected an aircraft, a task, the trim, a rate of 10 to 10000 Hz, a delay "
                              "of 0 to 10 s, positive crossover frequencies, bandwidths and limits, sas and gear 0 "
                              "or 1, a cut-off fraction in (0, 1) and trim, moment and heave times of 0 to 1000 s");
        return NULL;
    }
    sim_task tl;
    if (t && t->nphases == 0) { /* a task built by hand from the legacy fields */
        tl = *t;
        sim_task_legacy_phases(&tl);
        t = &tl;
    }
    if (task_ok(t, err) != 0)
        return NULL;
    sim_pilot_auto *p = calloc(1, sizeof *p);
    if (!p || !(p->Xre = calloc(4, sizeof *p->Xre)) || !(p->Xim = calloc(4, sizeof *p->Xim))) {
        core_err_set(err, -1, "pilot_auto: out of memory");
        goto fail;
    }
    p->task = *t;
    p->o = *o;
    p->have_gear = hfm_aircraft_gear(ac, &p->gear) == 0 && p->gear.nlegs > 0;
    if (schedule_gains(p, ac, t, trim, log, err) != 0)
        goto fail;
    p->nbuf = (int)lround(o->delay_s * o->rate_hz) + 1;
    if (!(p->buf = malloc((size_t)p->nbuf * 4 * sizeof *p->buf))) {
        core_err_set(err, -1, "pilot_auto: out of memory");
        goto fail;
    }
    for (int k = 0; k < p->nbuf; k++)
        memcpy(p->buf + 4 * k, p->g.trim_pct, sizeof p->g.trim_pct);
    result_start(p, t);
    phase_start(p, 0, 0.0);
    return p;
fail:
    sim_pilot_auto_destroy(p);
    return NULL;
}

void sim_pilot_auto_destroy(sim_pilot_auto *p)
{
    if (!p)
        return;
    free(p->buf);
    free(p->Xre);
    free(p->Xim);
    free(p);
}

void sim_pilot_auto_gains(const sim_pilot_auto *p, sim_pilot_gains *g) { *g = p->g; }

int sim_pilot_auto_set_trim_state(sim_pilot_auto *p, const sim_flight_out *s0)
{
    if (!p || !s0)
        return -1;
    for (int k = 0; k < 3; k++)
        if (!isfinite(s0->euler_E_rad[k]))
            return -1;
    for (int k = 0; k < 9; k++)
        if (!isfinite(s0->ship.C_ES[k]))
            return -1;
    /* the start's body relative to S at t = 0: the flight's trim in S
     * (sim_flight_create carried it into E with the ship's attitude then) */
    double C_SB[3][3];
    body_in_S(s0, C_SB);
    double phi = atan2(C_SB[2][1], C_SB[2][2]), theta = asin(clampd(-C_SB[2][0], -1.0, 1.0));
    if (!(fabs(phi) < 0.5 && fabs(theta) < 0.5))
        return -1; /* not a hover's attitude */
    p->g.trim_att_rad[0] = phi;
    p->g.trim_att_rad[1] = theta;
    return 0;
}

/* The control activity's cut-off frequencies from the running DFT. */
static void activity(const sim_pilot_auto *p, sim_task_result *r)
{
    long n = p->ns;
    /* sum over the rate samples 1..n-1 of exp(-i w j dt) (a geometric
     * series): the mean's share of each bin */
    double G[2][NBIN];
    for (int k = 0; k < NBIN && n >= 2; k++) {
        double a = (k + 1) * BIN_RADPS * DEC_S, sa = sin(0.5 * a), nd = (double)(n - 1);
        G[0][k] = G[1][k] = 0.0;
        if (fabs(sa) > 1e-12) {
            double mag = sin(0.5 * a * nd) / sa, ph = -0.5 * a * (nd + 1.0);
            G[0][k] = mag * cos(ph);
            G[1][k] = mag * sin(ph);
        }
    }
    for (int i = 0; i < 4; i++) {
        r->ctl_rms_pct[i] = r->ctl_rate_rms_pctps[i] = r->ctl_cutoff_radps[i] = 0.0;
        if (n < 2)
            continue;
        double m = p->u_sum[i] / (double)n, nd = (double)(n - 1);
        r->ctl_rms_pct[i] = sqrt(fmax(p->u_sum2[i] / (double)n - m * m, 0.0));
        double md = p->du_sum[i] / nd;
        r->ctl_rate_rms_pctps[i] = sqrt(fmax(p->du_sum2[i] / nd - md * md, 0.0));
        /* the periodogram of the rate about its mean: X - mean * sum(exp) */
        double P[NBIN], tot = 0.0;
        for (int k = 0; k < NBIN; k++) {
            double re = p->Xre[i][k] - md * G[0][k], im = p->Xim[i][k] - md * G[1][k];
            P[k] = re * re + im * im;
            tot += P[k];
        }
        if (!(tot > 0.0))
            continue;
        double cum = 0.0;
        for (int k = 0; k < NBIN; k++) {
            cum += P[k];
            if (cum >= p->o.cutoff_fraction * tot) {
                r->ctl_cutoff_radps[i] = (k + 1) * BIN_RADPS;
                break;
            }
        }
    }
}

void sim_pilot_auto_result(const sim_pilot_auto *p, sim_task_result *r)
{
    *r = p->r;
    activity(p, r);
}

/* A control sample (the delayed command sent) for the activity. */
static void sample_controls(sim_pilot_auto *p, const double u[4])
{
    for (int i = 0; i < 4; i++)
        p->dec_acc[i] += u[i];
    if (++p->dec_n < (int)lround(DEC_S * p->o.rate_hz))
        return;
    double v[4];
    for (int i = 0; i < 4; i++) {
        v[i] = p->dec_acc[i] / p->dec_n;
        p->dec_acc[i] = 0.0;
    }
    p->dec_n = 0;
    for (int i = 0; i < 4; i++) {
        p->u_sum[i] += v[i];
        p->u_sum2[i] += v[i] * v[i];
    }
    if (p->ns > 0) {
        double ph0 = (double)p->ns * DEC_S;
        for (int i = 0; i < 4; i++) {
            double d = (v[i] - p->u_prev[i]) / DEC_S;
            p->du_sum[i] += d;
            p->du_sum2[i] += d * d;
        }
        for (int k = 0; k < NBIN; k++) {
            double a = (k + 1) * BIN_RADPS * ph0, c = cos(a), s = sin(a);
            for (int i = 0; i < 4; i++) {
                double d = (v[i] - p->u_prev[i]) / DEC_S;
                p->Xre[i][k] += d * c;
                p->Xim[i][k] -= d * s;
            }
        }
    }
    memcpy(p->u_prev, v, sizeof v);
    p->ns++;
}

/* The spot's heave statistics and energy index, from the ship's frame. */
static void heave(sim_pilot_auto *p, const sim_flight_out *out, double h)
{
    double hm = p->hn ? p->h_sum / p->hn : h;
    if (p->hn > 0 && h > 0.0) {
        double hd = (-out->ship.origin_E_m[2] - p->h_prev_m) / h;
        double up = -out->ship.origin_E_m[2];
        p->h_sum += up;
        p->h_sum2 += up * up;
        p->hd_sum2 += hd * hd;
        p->hd_last_mps = hd;
        p->hn++;
        hm = p->h_sum / p->hn;
        double vh = fmax(p->h_sum2 / p->hn - hm * hm, 0.0), vhd = p->hd_sum2 / (p->hn - 1);
        if (sqrt(vhd) < 1e-3)
            p->e_now = 0.0; /* a still deck */
        else if (vh > 0.0 && p->hn * h >= LEARN_S)
            p->e_now = 0.5 * (hd * hd / vhd + (up - hm) * (up - hm) / vh);
        else
            p->e_now = INFINITY; /* too little seen yet */
    } else if (p->hn == 0) {
        p->h_sum = -out->ship.origin_E_m[2];
        p->h_sum2 = p->h_sum * p->h_sum;
        p->hn = 1;
        p->e_now = INFINITY;
    }
    p->h_prev_m = -out->ship.origin_E_m[2];
}

/* The lowest wheel's height above the deck plane (m; < 0: through it),
 * or the CG's height less the touchdown height without a gear. */
static double wheel_clearance(const sim_pilot_auto *p, const sim_flight_out *out, double *roll_deck,
                              double *pitch_deck)
{
    double C_SB[3][3];
    body_in_S(out, C_SB);
    *pitch_deck = asin(clampd(-C_SB[2][0], -1.0, 1.0));
    *roll_deck = atan2(C_SB[2][1], C_SB[2][2]);
    if (!p->have_gear)
        return -out->pos_S_m[2] - p->td_height_m;
    double low = INFINITY;
    for (int l = 0; l < p->gear.nlegs; l++) {
        const hfm_gear_leg *g = &p->gear.leg[l];
        double z = out->pos_S_m[2];
        for (int k = 0; k < 3; k++)
            z += C_SB[2][k] * g->pos_B_m[k];
        low = fmin(low, -(z + g->tyre_radius_m));
    }
    return low;
}

static void end_phase(sim_pilot_auto *p, double t_s, int grade)
{
    sim_phase_result *pr = &p->r.phase[p->ph];
    pr->grade = grade;
    pr->t_end_s = t_s;
    phase_start(p, p->ph + 1, t_s);
}

/* The touchdown: graded against the descend phase (or the last phase). */
static void touchdown(sim_pilot_auto *p, const sim_flight_out *out, double h, double psi_rel, double roll_d,
                      double pitch_d)
{
    sim_task_result *r = &p->r;
    int i = p->ph < p->task.nphases ? p->ph : p->task.nphases - 1;
    const sim_task_phase *ph = &p->task.phase[i];
    r->touched = 1;
    r->t_touchdown_s = out->t_s;
    r->sink_mps = (out->pos_S_m[2] - p->prev_pos_S_m[2]) / h;
    r->drift_mps = hypot(out->pos_S_m[0] - p->prev_pos_S_m[0], out->pos_S_m[1] - p->prev_pos_S_m[1]) / h;
    r->dist_m = hypot(out->pos_S_m[0] - ph->target_S_m[0], out->pos_S_m[1] - ph->target_S_m[1]);
    r->td_heading_err_rad = core_wrap_pi(psi_rel - ph->heading_rad);
    r->td_roll_deck_rad = roll_d;
    r->td_pitch_deck_rad = pitch_d;
    double hm = p->hn ? p->h_sum / p->hn : 0.0;
    r->td_heave_m = -out->ship.origin_E_m[2] - hm;
    r->td_heave_rate_mps = p->hn > 1 ? p->hd_last_mps : 0.0;
    r->td_energy = p->e_now;
    double vh = p->hn ? fmax(p->h_sum2 / p->hn - hm * hm, 0.0) : 0.0;
    double vhd = p->hn > 1 ? p->hd_sum2 / (p->hn - 1) : 0.0;
    double w = vh > 0.0 ? sqrt(vhd / vh) : 0.0;
    r->td_heave_phase_rad = w > 0.0 ? atan2(-r->td_heave_rate_mps / w, r->td_heave_m) : 0.0;
    double t_in = out->t_s - p->ph_t0_s;
    const sim_task_tol *band[2] = {&ph->adequate, &ph->desired};
    int g = 0;
    for (int b = 0; b < 2; b++)
        if (r->dist_m <= band[b]->pos_m && r->sink_mps <= band[b]->sink_mps &&
            (band[b]->drift_mps <= 0.0 || r->drift_mps <= band[b]->drift_mps) &&
            fabs(r->td_heading_err_rad) <= band[b]->heading_rad && t_in <= band[b]->time_s)
            g = b + 1;
    r->touchdown_grade = g;
    if (p->ph < p->task.nphases) {
        p->r.phase[p->ph].max_err_pos_m = r->dist_m;
        p->r.phase[p->ph].max_err_heading_rad = fabs(r->td_heading_err_rad);
    }
    if (p->ph < p->task.nphases && ph->kind == SIM_PHASE_DESCEND)
        end_phase(p, out->t_s, g);
    else if (p->ph < p->task.nphases) /* a touchdown before the descent: this phase is not met */
        end_phase(p, out->t_s, 0);
    p->ph = p->task.nphases;
    p->r.phase_now = p->ph;
    /* the controls last sent (the delayed command at the head) */
    memcpy(p->hold_u, p->buf + 4 * p->head, sizeof p->hold_u);
    p->coll_pct = p->hold_u[0];
    if (!p->o.gear)
        r->done = 1;
}

/* A move's reference along its line at time t from its start: the
 * distance (returned) and the speed (*v_mps), speeding up from rest and
 * slowing to rest at MOVE_ACC_MPS2 with speed_mps between (a triangle for
 * a line too short to reach it). */
static double move_profile(double t, double len_m, double speed_mps, double *v_mps)
{
    *v_mps = 0.0;
    if (!(len_m > 0.0) || t <= 0.0)
        return 0.0;
    double a = MOVE_ACC_MPS2, v = speed_mps, ta = v / a;
    if (a * ta * ta > len_m) { /* the triangle: up to the middle, down from it */
        ta = sqrt(len_m / a);
        v = a * ta;
    }
    double la = 0.5 * a * ta * ta, tc = (len_m - 2.0 * la) / v;
    if (t < ta) {
        *v_mps = a * t;
        return 0.5 * a * t * t;
    }
    if (t < ta + tc) {
        *v_mps = v;
        return la + v * (t - ta);
    }
    double tl = 2.0 * ta + tc - t; /* the time left */
    if (tl <= 0.0)
        return len_m;
    *v_mps = a * tl;
    return len_m - 0.5 * a * tl * tl;
}

/* The grading and the phase machine for one state (the pilot's view, undelayed). */
static void phases(sim_pilot_auto *p, const sim_flight_out *out, double psi_rel)
{
    sim_task_result *r = &p->r;
    if (p->ph >= p->task.nphases)
        return;
    const sim_task_phase *ph = &p->task.phase[p->ph];
    sim_phase_result *pr = &r->phase[p->ph];
    double t_in = out->t_s - p->ph_t0_s;
    const sim_task_tol *band[2] = {&ph->adequate, &ph->desired};
    /* the errors from the reference (hold, move) */
    double dx = out->pos_S_m[0] - p->ref.pos_S_m[0], dy = out->pos_S_m[1] - p->ref.pos_S_m[1];
    double e_pos = sqrt(dx * dx + dy * dy), e_h = -(out->pos_S_m[2] - p->ref.pos_S_m[2]);
    double e_psi = core_wrap_pi(psi_rel - p->ref.heading_rad);
    if (ph->kind == SIM_PHASE_HOLD) {
        r->err_pos_m = e_pos;
        r->err_height_m = e_h;
        r->err_heading_rad = e_psi;
        r->t_s = out->t_s;
        double *since[2] = {&r->t_adequate_s, &r->t_desired_s};
        for (int b = 0; b < 2; b++) {
            int in = e_pos <= band[b]->pos_m && fabs(e_h) <= band[b]->height_m && fabs(e_psi) <= band[b]->heading_rad;
            if (!in)
                p->since[b] = -1.0;
            else if (p->since[b] < 0.0)
                p->since[b] = t_in;
            *since[b] = p->since[b] < 0.0 ? -1.0 : p->since[b] + p->ph_t0_s;
            if (in && p->since[b] <= band[b]->time_s && t_in - p->since[b] >= ph->duration_s - 1e-9)
                p->met[b] = 1;
        }
        if (t_in >= ph->desired.time_s) {
            pr->max_err_pos_m = fmax(pr->max_err_pos_m, e_pos);
            pr->max_err_height_m = fmax(pr->max_err_height_m, fabs(e_h));
            pr->max_err_heading_rad = fmax(pr->max_err_heading_rad, fabs(e_psi));
            r->max_err_pos_m = fmax(r->max_err_pos_m, e_pos);
            r->max_err_height_m = fmax(r->max_err_height_m, fabs(e_h));
            r->max_err_heading_rad = fmax(r->max_err_heading_rad, fabs(e_psi));
        }
        pr->grade = p->met[1] ? 2 : p->met[0] ? 1 : 0;
        /* the last phase of a station keeping flies its whole length */
        int last = p->ph == p->task.nphases - 1;
        if ((!last && p->met[1]) || t_in >= ph->adequate.time_s + ph->duration_s - 1e-9) {
            end_phase(p, out->t_s, pr->grade);
            if (last)
                r->done = 1;
        }
    } else if (ph->kind == SIM_PHASE_MOVE) {
        double vs, s = move_profile(t_in, p->move_len_m, ph->speed_mps, &vs);
        double f = p->move_len_m > 0.0 ? s / p->move_len_m : 1.0;
        pr->max_err_pos_m = fmax(pr->max_err_pos_m, e_pos);
        pr->max_err_height_m = fmax(pr->max_err_height_m, fabs(e_h));
        pr->max_err_heading_rad = fmax(pr->max_err_heading_rad, fabs(e_psi));
        for (int b = 0; b < 2; b++)
            if (!(e_pos <= band[b]->pos_m && fabs(e_h) <= band[b]->height_m && fabs(e_psi) <= band[b]->heading_rad))
                p->met[b] = 0; /* left the band about the moving reference */
        if (!p->external) {
            double pos[3], vel[3] = {0.0, 0.0, 0.0};
            for (int k = 0; k < 3; k++) {
                pos[k] = p->move_from[k] + f * (ph->target_S_m[k] - p->move_from[k]);
                if (f < 1.0)
                    vel[k] = vs * (ph->target_S_m[k] - p->move_from[k]) / p->move_len_m;
            }
            hold_ref(p, pos, vel, ph->heading_rad);
        }
        if (f >= 1.0) {
            double ex = out->pos_S_m[0] - ph->target_S_m[0], ey = out->pos_S_m[1] - ph->target_S_m[1];
            double ez = out->pos_S_m[2] - ph->target_S_m[2];
            int arrived[2];
            for (int b = 0; b < 2; b++)
                arrived[b] = hypot(ex, ey) <= band[b]->pos_m && fabs(ez) <= band[b]->height_m &&
                             fabs(e_psi) <= band[b]->heading_rad && t_in <= band[b]->time_s;
            if (arrived[0] || t_in >= ph->adequate.time_s) {
                int g = p->met[1] && arrived[1] ? 2 : p->met[0] && arrived[0] ? 1 : 0;
                end_phase(p, out->t_s, g);
            }
        }
    } else { /* descend: wait for a quiescent deck, then down */
        /* over the spot and nearly still: within GATE_FRAC of the desired
         * position band and drift (0.25 m/s without a drift band) */
        double vh = hypot(out->vel_S_mps[0], out->vel_S_mps[1]);
        double v_gate = ph->desired.drift_mps > 0.0 ? ph->desired.drift_mps : 0.5;
        int over = e_pos <= GATE_FRAC * ph->desired.pos_m;
        if (p->descending)
            p->desc_hold = !p->external && !over && p->clear_m > COMMIT_M &&
                           t_in + 2.0 * p->clear_m / ph->descent_mps < ph->adequate.time_s;
        if (!p->descending) {
            int quiet = !ph->quiescent;
            if (ph->quiescent) {
                if (p->e_now <= ph->quiet_energy) {
                    if (p->quiet_since_s < 0.0)
                        p->quiet_since_s = out->t_s;
                    quiet = out->t_s - p->quiet_since_s >= ph->quiet_window_s - 1e-9;
                } else {
                    p->quiet_since_s = -1.0;
                }
            }
            quiet = (quiet && over && vh <= v_gate) || t_in >= ph->max_wait_s;
            if (quiet) {
                p->descending = 1;
                pr->t_wait_s = t_in;
                pr->energy = p->e_now;
                r->t_descent_s = out->t_s;
                if (!p->external) {
                    sim_pilot_ref d = p->ref;
                    d.mode = SIM_PHASE_DESCEND;
                    memset(d.vel_S_mps, 0, sizeof d.vel_S_mps);
                    d.vel_S_mps[2] = ph->descent_mps;
                    set_ref(p, &d);
                }
            }
        }
    }
}

/* The task's grade: the lowest of the phases flown (and the touchdown). */
static int task_grade(const sim_pilot_auto *p)
{
    const sim_task_result *r = &p->r;
    int gr = 2;
    for (int i = 0; i < p->task.nphases && i <= p->ph; i++) {
        if (i == p->ph && p->task.phase[i].kind != SIM_PHASE_HOLD)
            break; /* a move or descent under way is graded at its end */
        gr = r->phase[i].grade < gr ? (r->phase[i].grade < 0 ? 0 : r->phase[i].grade) : gr;
    }
    return gr;
}

/* On the deck with the gear: the collective down, the rest held; settled
 * once still (dpos: the CG's velocity in S over the last step); the
 * controls straight out, no delay: the pilot's hand goes down. */
static void on_deck(sim_pilot_auto *p, const sim_flight_out *out, const double dpos[3], sim_flight_inputs *in)
{
    const sim_pilot_auto_opts *o = &p->o;
    sim_task_result *r = &p->r;
    double cmd[4];
    p->coll_pct = fmax(p->coll_pct - DOWN_PCTPS / o->rate_hz, 0.0);
    memcpy(cmd, p->hold_u, sizeof cmd);
    cmd[0] = p->coll_pct;
    double v = sqrt(dpos[0] * dpos[0] + dpos[1] * dpos[1] + dpos[2] * dpos[2]);
    if (p->coll_pct <= 0.0 && v < SETTLE_MPS) {
        if (p->still_since_s < 0.0)
            p->still_since_s = out->t_s;
        if (!r->settled && out->t_s - p->still_since_s >= SETTLE_S - 1e-9) {
            r->settled = 1;
            r->t_settled_s = out->t_s;
            r->done = 1;
        }
    } else {
        p->still_since_s = -1.0;
    }
    memset(in, 0, sizeof *in);
    in->ctl.collective_pct = cmd[0];
    in->ctl.long_cyclic_pct = cmd[1];
    in->ctl.lat_cyclic_pct = cmd[2];
    in->ctl.pedal_pct = cmd[3];
}

/* The step's height reference (p->z_ref_S_m) and its rate down (m/s). */
static double height_ref(sim_pilot_auto *p)
{
    const sim_pilot_ref *R = &p->ref;
    double w_ref = 0.0;
    if (R->mode == SIM_PHASE_DESCEND) {
        /* the height reference moves down at the descent rate to 0.3 m
         * below the touchdown height (the wheels meet the deck on the way) */
        double z_end = -p->td_height_m + 0.3;
        if (p->z_ref_S_m < z_end && !p->desc_hold) {
            p->z_ref_S_m = fmin(p->z_ref_S_m + R->vel_S_mps[2] / p->o.rate_hz, z_end);
            w_ref = p->z_ref_S_m < z_end ? R->vel_S_mps[2] : 0.0;
        }
    } else {
        w_ref = R->vel_S_mps[2];
        p->z_ref_S_m = R->pos_S_m[2];
    }
    return w_ref;
}

/* The outer loops in the heading axes H (x forward, y right, level): the
 * position and velocity errors to the roll and pitch commands (rad), with
 * the pilot's slow trim of the position and height errors. */
static void outer_loops(sim_pilot_auto *p, const sim_flight_out *out, double psi_rel, double *ph_c, double *th_c)
{
    const sim_pilot_auto_opts *o = &p->o;
    const sim_pilot_gains *g = &p->g;
    const sim_pilot_ref *R = &p->ref;
    double c = cos(psi_rel), s = sin(psi_rel);
    double ex = R->pos_S_m[0] - out->pos_S_m[0], ey = R->pos_S_m[1] - out->pos_S_m[1];
    double eH[2] = {c * ex + s * ey, -s * ex + c * ey};
    double vH[2] = {c * out->vel_S_mps[0] + s * out->vel_S_mps[1], -s * out->vel_S_mps[0] + c * out->vel_S_mps[1]};
    double vr[2] = {c * R->vel_S_mps[0] + s * R->vel_S_mps[1], -s * R->vel_S_mps[0] + c * R->vel_S_mps[1]};
    /* the pilot's trim: slow integral action on the position and height
     * errors (bounded: 1 m/s of commanded speed, 10 % of collective;
     * the height's held during a descent, whose lag it would wind up) */
    double iH[2] = {0.0, 0.0}, dt = 1.0 / o->rate_hz;
    if (o->trim_s > 0.0) {
        double lim = o->trim_s / o->pos_bw_radps;
        for (int k = 0; k < 2; k++)
            p->i_pos_S[k] = clampd(p->i_pos_S[k] + (R->pos_S_m[k] - out->pos_S_m[k]) * dt, -lim, lim);
        iH[0] = (c * p->i_pos_S[0] + s * p->i_pos_S[1]) / o->trim_s;
        iH[1] = (-s * p->i_pos_S[0] + c * p->i_pos_S[1]) / o->trim_s;
        double hl = 10.0 * o->trim_s * fabs(g->Z_col) / (o->hgt_crossover_radps * p->a_lead[3]);
        if (R->mode == SIM_PHASE_HOLD)
            p->i_hgt = clampd(p->i_hgt + (p->z_ref_S_m - out->pos_S_m[2]) * dt, -hl, hl);
    }
    double vc[2] = {vr[0] + o->pos_bw_radps * (eH[0] + iH[0]), vr[1] + o->pos_bw_radps * (eH[1] + iH[1])};
    double vn = hypot(vc[0], vc[1]);
    if (vn > o->max_speed_mps)
        vc[0] *= o->max_speed_mps / vn, vc[1] *= o->max_speed_mps / vn;
    double ac[2] = {o->vel_bw_radps * (vc[0] - vH[0]), o->vel_bw_radps * (vc[1] - vH[1])};
    *th_c = g->trim_att_rad[1] + clampd((ac[0] - g->X_u * vH[0]) / g->X_theta, -o->max_att_rad, o->max_att_rad);
    *ph_c = g->trim_att_rad[0] + clampd((ac[1] - g->Y_v * vH[1]) / g->Y_phi, -o->max_att_rad, o->max_att_rad);
}

/* opts.moment_s, heave_s: the roll and pitch moments and the vertical
 * force that the linear model does not explain over the last step,
 *     m = dx/dt - a x - K (delta - delta_trim),
 * x the roll and pitch rates and the vertical speed (down, relative to
 * the ship's mean motion), a the (SAS-augmented) rate damping L_p, M_q
 * or Z_w, delta the control then applied (lat, long, collective),
 * averaged over moment_s (roll, pitch)
 * or heave_s (first order), each at most STEADY_PCT of its control's
 * travel through K and held while the last command had a control at its
 * stop, while a wheel is on the deck (the deck's forces are not the
 * air's) or when steps were missed (h not one step: the replay's hand on
 * the deck); the commands cmd take them out (- m / K). */
static void steady_trim(sim_pilot_auto *p, const sim_flight_out *out, double h, double cmd[4])
{
    const sim_pilot_gains *g = &p->g;
    const double K[3] = {g->L_lat, g->M_long, g->Z_col}, a[3] = {g->L_p, g->M_q, g->Z_w};
    const double T[3] = {p->o.moment_s, p->o.moment_s, p->o.heave_s};
    const double x[3] = {out->rate_B_radps[0], out->rate_B_radps[1], out->vel_S_mps[2]};
    static const int ch[3] = {2, 1, 0}; /* roll: lat, pitch: long, heave: collective */
    int one_step = p->m_have && h > 0.5 / p->o.rate_hz && h < 1.5 / p->o.rate_hz;
    for (int i = 0; i < 3; i++) {
        if (!(T[i] > 0.0))
            continue;
        if (one_step && !p->stopped && !out->on_deck) {
            double m = (x[i] - p->m_rate[i]) / h - a[i] * p->m_rate[i] - K[i] * (p->m_u[i] - g->trim_pct[ch[i]]);
            double lim = STEADY_PCT * fabs(K[i]);
            p->m_est[i] = clampd(p->m_est[i] + h / T[i] * (m - p->m_est[i]), -lim, lim);
        }
        p->m_rate[i] = x[i];
        cmd[ch[i]] -= p->m_est[i] / K[i];
    }
    p->m_have = 1;
}

int sim_pilot_auto_step(sim_pilot_auto *p, const sim_flight_out *out, sim_flight_inputs *in)
{
    const sim_pilot_auto_opts *o = &p->o;
    const sim_pilot_gains *g = &p->g;
    /* the heading relative to the ship: S's x axis in E is C_ES's first column */
    double psi_ship = atan2(out->ship.C_ES[3], out->ship.C_ES[0]);
    double psi_rel = core_wrap_pi(out->euler_E_rad[2] - psi_ship);
    double h = p->have_prev ? out->t_s - p->prev_t_s : 0.0;
    if (!p->have_prev || h > 0.0)
        heave(p, out, h);
    double roll_d, pitch_d, clear = wheel_clearance(p, out, &roll_d, &pitch_d);
    p->clear_m = clear;
    sim_task_result *r = &p->r;
    r->t_s = out->t_s;
    if (!r->touched && p->have_prev && h > 0.0 && clear <= 0.0)
        touchdown(p, out, h, psi_rel, roll_d, pitch_d);
    else if (!r->touched)
        phases(p, out, psi_rel);
    r->grade = task_grade(p);
    double dpos[3] = {0.0, 0.0, 0.0};
    if (h > 0.0)
        for (int k = 0; k < 3; k++)
            dpos[k] = (out->pos_S_m[k] - p->prev_pos_S_m[k]) / h;
    memcpy(p->prev_pos_S_m, out->pos_S_m, sizeof p->prev_pos_S_m);
    p->prev_t_s = out->t_s;
    p->have_prev = 1;
    double cmd[4];
    if (r->touched && o->gear) {
        on_deck(p, out, dpos, in);
        return 0;
    }
    const sim_pilot_ref *R = &p->ref;
    double w_ref = height_ref(p), ph_c, th_c;
    outer_loops(p, out, psi_rel, &ph_c, &th_c);
    /* inner loops: the crossover pilot's lead on each attitude (height) error */
    double e_att[4] = {ph_c - out->euler_E_rad[0], th_c - out->euler_E_rad[1], core_wrap_pi(R->heading_rad - psi_rel),
                       p->z_ref_S_m - out->pos_S_m[2] + (o->trim_s > 0.0 ? p->i_hgt / o->trim_s : 0.0)};
    double rate[4] = {out->rate_B_radps[0], out->rate_B_radps[1], out->rate_B_radps[2], out->vel_S_mps[2] - w_ref};
    const double K[4] = {g->L_lat, g->M_long, g->N_ped, g->Z_col};
    const double wc[4] = {o->att_crossover_radps, o->att_crossover_radps, o->yaw_crossover_radps,
                          o->hgt_crossover_radps};
    static const int ch[4] = {2, 1, 3, 0}; /* axis -> control: lat, long, pedal, collective */
    for (int i = 0; i < 4; i++)
        cmd[ch[i]] = g->trim_pct[ch[i]] + wc[i] / K[i] * (p->a_lead[i] * e_att[i] - rate[i]);
    if (o->moment_s > 0.0 || o->heave_s > 0.0)
        steady_trim(p, out, h, cmd);
    int stop = 0;
    for (int i = 0; i < 4; i++) {
        if (!isfinite(cmd[i]))
            cmd[i] = g->trim_pct[i];
        cmd[i] = clampd(cmd[i], 0.0, 100.0);
    }
    /* the pilot's delay: the command of nbuf - 1 steps ago goes out */
    memcpy(p->buf + 4 * p->head, cmd, sizeof cmd);
    p->head = (p->head + 1) % p->nbuf;
    const double *u = p->buf + 4 * p->head;
    memset(in, 0, sizeof *in);
    in->ctl.collective_pct = u[0];
    in->ctl.long_cyclic_pct = u[1];
    in->ctl.lat_cyclic_pct = u[2];
    in->ctl.pedal_pct = u[3];
    sample_controls(p, u);
    for (int i = 0; i < 4; i++) {
        p->r.min_pct[i] = fmin(p->r.min_pct[i], u[i]);
        p->r.max_pct[i] = fmax(p->r.max_pct[i], u[i]);
        if (u[i] <= 0.0 || u[i] >= 100.0)
            stop = 1;
    }
    if (stop)
        p->r.stop_steps++;
    p->stopped = stop;
    p->m_u[0] = u[2], p->m_u[1] = u[1], p->m_u[2] = u[0];
    return stop;
}

/* ---------------------------------------------- as a sim_pilot (runner) */
static int auto_pilot_step(void *self, const sim_flight_out *out, sim_flight_inputs *in)
{
    sim_pilot_auto *p = self;
    sim_pilot_auto_step(p, out, in);
    return p->r.done ? 1 : 0;
}

sim_pilot sim_pilot_auto_pilot(sim_pilot_auto *p)
{
    static const sim_pilot_ops ops = {"auto", auto_pilot_step};
    sim_pilot pl = {&ops, p};
    return pl;
}
