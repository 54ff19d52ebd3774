/* flight.c -- the deterministic flight step of the real-time loop.
 *
 * One step of h = 1 / rate_hz runs its stages in this fixed order, as
 * JSBSim's FGFDMExec::Run runs its models, each a static function fed by
 * an explicit input that the step fills before it runs (as
 * FGFDMExec::LoadInputs):
 *   1. pilot:   the step's controls (sim_flight_inputs; hold keeps the
 *               last), through the stability augmentation (sim/sas.c) from
 *               the body state at the step's start
 *   2. ship:    the ship frame S in E, a pure function of time (the
 *               caller's sim_ship_frame_fn, or the ship steady at its
 *               speed), computed once per step at the step times around
 *               the step (sim/ship_frame.c); every time the later stages
 *               ask within the step is had from these frames
 *   3. air:     the airwake attached to the ship, in E (sim/air.c), sampled
 *               by the flight model at every blade element, the tail rotor,
 *               fuselage and tail surfaces through one hfm_air callback
 *               with the ship stage's frame at the sample's time; its
 *               inputs advanced once per step from the CG in S at the
 *               step's start: the coupled rotor interaction's rotor
 *               (sim/interaction.c) and the frozen turbulence
 *               (sim/turbulence.c) with the field's mean air, k and
 *               epsilon at the CG
 *   4. flight model: the helicopter integrated in the Earth frame E
 *               (inertial) by hfm_tsim, ARKODE explicit Runge-Kutta at the
 *               fixed step (Ralston's 2-stage method, hfm/tsim.c)
 *   5. external loads: the landing gear on the deck (opts.gear,
 *               sim/contact.c) with the ship stage's deck at the time, and
 *               the caller's hfm_ext_fn, summed and added at every
 *               right-hand side; after the step the gear's bookkeeping
 *               (sim_contact_step: the tyres' slides, the strike points,
 *               slide / tip-over / crash), from the state the step ended at
 *   6. outputs: the state in E and relative to the ship, the main rotor's
 *               thrust and power, the gear's loads and flags
 *               (sim_flight_out).
 * A crash on the ship or a roll-over on the deck ends the flight: that
 * step returns 1 with what hit what, and the flight steps no further.
 * No clock, socket, file or print inside: the same inputs give the same
 * trajectory whatever paces the calls (real time or as fast as it can).
 *
 * The start: the hover trim (hfm_trim, HFM_TRIM_HOVER_SHIP) with the CG at
 * the station in S, in the air the flight starts with (the field at the
 * WOD speed, or the free stream), carried into E with the ship's mean
 * (level) frame at t = 0, C_m = the ship's heading alone: position
 * o_E + C_m p_S, velocity the ship's mean velocity, attitude C_EB = C_m C_SB
 * (in a seaway the deck's pitch and roll at t = 0 do not tilt the hover).
 * With the ship steady the flight then starts in equilibrium (the air
 * relative to the helicopter is the trim's).
 *
 * The deck start (SIM_START_DECK): the gear's static loads (the CG over
 * the wheels' support, sim_contact_static_loads) give each leg's static
 * compression; the body's pitch and roll put the plane through the
 * compressed wheels' lowest points on the deck (exact for three legs), its
 * CG over the station's x, y, its heading the option's. It moves with the
 * deck: the velocity of that point of S and the ship's angular velocity
 * (the frame's central differences over 1e-4 s). Collective full down,
 * cyclic and pedals centred; the rotor at its speed with no flapping and
 * no inflow, which the blades' flap and the Pitt-Peters inflow settle in a
 * few tenths of a second while the gear carries the aircraft.
 *
 * Assumptions: the ship's frame is a known function of time (its motion is
 * not affected by the helicopter); the air is the quasi-steady airwake of
 * sim/air.c.
 */
#include "sim.h"
#include "cfd.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

struct sim_flight {
    const hfm_aircraft *ac;
    core_ship ship;
    sim_flight_opts o;
    sim_ship_frame_fn frame;
    void *frame_user;
    sim_ship_frames frames;   /* the ship stage's: S at the step times around the step */
    sim_air *air;
    sim_air_in air_in;        /* the air's inputs: the turbulence, the interaction */
    sim_turb *turb;           /* NULL: no turbulence */
    hfm_air hair;
    /* the frame of the last time the air asked (every point of a stage
     * asks the same one) */
    int have_air_fr;
    double air_t_s;
    sim_ship_frame air_fr;
    hfm_tsim *ts;
    hfm_controls u, u_trim;   /* the pilot's (the rotor's: u with the SAS's) */
    sim_sas *sas;             /* the stability augmentation (sim/sas.c) */
    sim_contact *gear;        /* opts.gear: the landing gear on the deck */
    sim_contact_report rep;   /* its report after the last step */
    hfm_ext_fn ext;           /* the caller's external loads */
    void *ext_user;
    int ended;                /* a crash or a roll-over ended the flight */
    char end_msg[200];
    double h_s;
    long step;
    const core_log *log;
};

void sim_flight_opts_default(sim_flight_opts *o)
{
    memset(o, 0, sizeof *o);
    o->rate_hz = 200.0;
    o->station_S_m[2] = -6.0;
    o->blend_s = 3.0;
    o->turbulence = 1;
    o->seed = 1;
    o->sas = -1;
}

/* The ship steady at its speed, heading north, S level: o_E = (U t, 0, 0). */
static int steady_ship(void *user, double t_s, sim_ship_frame *fr)
{
    const sim_flight *f = user;
    memset(fr, 0, sizeof *fr);
    fr->origin_E_m[0] = f->o.ship_speed_mps * t_s;
    fr->C_ES[0] = fr->C_ES[4] = fr->C_ES[8] = 1.0;
    fr->mean_vel_E_mps[0] = f->o.ship_speed_mps;
    return 0;
}

static void m3_mul(const double *A, const double *B, double *C) /* C = A B, row major */
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            C[3 * i + j] = A[3 * i] * B[j] + A[3 * i + 1] * B[3 + j] + A[3 * i + 2] * B[6 + j];
}

static void mat_from_euler(const double e[3], double *C)
{
    core_euler ce = {e[0], e[1], e[2]};
    core_mat3 m = core_mat3_from_euler(ce);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            C[3 * i + j] = m.m[i][j];
}

/* The trim's body state in S carried into E with the ship frame fr. */
static void body_S_to_E(const sim_ship_frame *fr, const hfm_body *bS, hfm_body *bE)
{
    double C_SB[9], C_EB[9];
    mat_from_euler(bS->euler_rad, C_SB);
    m3_mul(fr->C_ES, C_SB, C_EB);
    for (int i = 0; i < 3; i++)
        bE->pos_S_m[i] = fr->origin_E_m[i] + fr->C_ES[3 * i] * bS->pos_S_m[0] + fr->C_ES[3 * i + 1] * bS->pos_S_m[1] +
                         fr->C_ES[3 * i + 2] * bS->pos_S_m[2];
    /* velocity in E: the ship's mean motion plus the body's relative
     * velocity rotated from B (through S) to E; body axes: C_EB^T v_E */
    double vS[3], vE[3];
    for (int i = 0; i < 3; i++)
        vS[i] = C_SB[3 * i] * bS->vel_B_mps[0] + C_SB[3 * i + 1] * bS->vel_B_mps[1] + C_SB[3 * i + 2] * bS->vel_B_mps[2];
    for (int i = 0; i < 3; i++)
        vE[i] = fr->C_ES[3 * i] * vS[0] + fr->C_ES[3 * i + 1] * vS[1] + fr->C_ES[3 * i + 2] * vS[2] +
                fr->mean_vel_E_mps[i];
    for (int i = 0; i < 3; i++)
        bE->vel_B_mps[i] = C_EB[i] * vE[0] + C_EB[3 + i] * vE[1] + C_EB[6 + i] * vE[2];
    memcpy(bE->rate_B_radps, bS->rate_B_radps, sizeof bE->rate_B_radps);
    core_mat3 m;
    memcpy(m.m, C_EB, sizeof m.m);
    core_euler a = core_mat3_to_euler(m);
    bE->euler_rad[0] = a.phi_rad, bE->euler_rad[1] = a.theta_rad, bE->euler_rad[2] = a.psi_rad;
}

/* The air at a right-hand side (the hfm_air callback): the ship stage's
 * frame at t_s and the air's inputs. */
static int flight_air(void *user, const double pos_E_m[3], double t_s, double vel_E_mps[3])
{
    sim_flight *f = user;
    if (!f->have_air_fr || t_s != f->air_t_s) {
        f->have_air_fr = 0;
        if (sim_ship_frames_at(&f->frames, t_s, &f->air_fr) != 0)
            return -1;
        f->have_air_fr = 1;
        f->air_t_s = t_s;
    }
    sim_air_sample_E(f->air, &f->air_in, &f->air_fr, pos_E_m, t_s, vel_E_mps);
    return 0;
}

/* The gear's loads at t_s on the ship stage's deck. */
static int gear_loads(sim_flight *f, double t_s, const hfm_body *b, double F_B_N[3], double M_B_Nm[3])
{
    sim_ship_deck deck;
    if (sim_ship_deck_at(sim_ship_frames_fn, &f->frames, t_s, &deck) != 0)
        return -1;
    return sim_contact_loads(f->gear, &deck, b, F_B_N, M_B_Nm);
}

/* The external loads at a right-hand side: the gear's and the caller's. */
static int flight_ext(void *user, double t_s, const hfm_body *b, double F_B_N[3], double M_B_Nm[3])
{
    sim_flight *f = user;
    for (int i = 0; i < 3; i++)
        F_B_N[i] = M_B_Nm[i] = 0.0;
    if (f->gear && gear_loads(f, t_s, b, F_B_N, M_B_Nm) != 0)
        return -1;
    if (f->ext) {
        double F[3] = {0, 0, 0}, M[3] = {0, 0, 0};
        if (f->ext(f->ext_user, t_s, b, F, M) != 0)
            return -1;
        for (int i = 0; i < 3; i++) {
            F_B_N[i] += F[i];
            M_B_Nm[i] += M[i];
        }
    }
    return 0;
}

static void set_ext(sim_flight *f)
{
    /* none at all: no callback (the hover's right-hand side unchanged) */
    hfm_tsim_set_external(f->ts, f->gear || f->ext ? flight_ext : NULL, f);
}

/* The deck start's body state in E and its controls (see the head). */
static int deck_start(sim_flight *f, hfm_body *bE, hfm_controls *u, core_err *err)
{
    hfm_gear g;
    hfm_aircraft_gear(f->ac, &g);
    double load[HFM_GEAR_MAX_LEGS];
    if (sim_contact_static_loads(&g, hfm_aircraft_weight_N(f->ac), load, err) != 0)
        return -1;
    /* least squares plane z = a + b x + c y through the lowest points (B)
     * of the wheels at their static compression */
    double M[3][3] = {{0}}, r[3] = {0}, q[HFM_GEAR_MAX_LEGS][3];
    for (int i = 0; i < g.nlegs; i++) {
        q[i][0] = g.leg[i].pos_B_m[0];
        q[i][1] = g.leg[i].pos_B_m[1];
        q[i][2] = g.leg[i].pos_B_m[2] + g.leg[i].tyre_radius_m - sim_contact_leg_compression(&g.leg[i], load[i]);
        double a[3] = {1.0, q[i][0], q[i][1]};
        for (int j = 0; j < 3; j++) {
            r[j] += a[j] * q[i][2];
            for (int k = 0; k < 3; k++)
                M[j][k] += a[j] * a[k];
        }
    }
    double det = M[0][0] * (M[1][1] * M[2][2] - M[1][2] * M[2][1]) - M[0][1] * (M[1][0] * M[2][2] - M[1][2] * M[2][0]) +
                 M[0][2] * (M[1][0] * M[2][1] - M[1][1] * M[2][0]);
    double abc[3];
    for (int j = 0; j < 3; j++) { /* Cramer's rule */
        double Mj[3][3];
        memcpy(Mj, M, sizeof Mj);
        for (int k = 0; k < 3; k++)
            Mj[k][j] = r[k];
        abc[j] = (Mj[0][0] * (Mj[1][1] * Mj[2][2] - Mj[1][2] * Mj[2][1]) -
                  Mj[0][1] * (Mj[1][0] * Mj[2][2] - Mj[1][2] * Mj[2][0]) +
                  Mj[0][2] * (Mj[1][0] * Mj[2][1] - Mj[1][1] * Mj[2][0])) /
                 det;
    }
    hfm_body bS;
    memset(&bS, 0, sizeof bS);
    /* z_S of a body point ~ z_cg - theta x + phi y + z: level on the plane */
    bS.euler_rad[0] = -atan(abc[2]);
    bS.euler_rad[1] = atan(abc[1]);
    bS.euler_rad[2] = f->o.start_heading_rad;
    double C_SB[9];
    mat_from_euler(bS.euler_rad, C_SB);
    double zc = 0.0;
    for (int i = 0; i < g.nlegs; i++)
        zc -= (C_SB[6] * q[i][0] + C_SB[7] * q[i][1] + C_SB[8] * q[i][2]) / g.nlegs;
    bS.pos_S_m[0] = f->o.station_S_m[0];
    bS.pos_S_m[1] = f->o.station_S_m[1];
    bS.pos_S_m[2] = zc;
    sim_ship_frame fr, fa, fb;
    const double dt = 1e-4;
    if (f->frame(f->frame_user, 0.0, &fr) || f->frame(f->frame_user, -dt, &fa) || f->frame(f->frame_user, dt, &fb))
        return core_err_set(err, -1, "flight: no ship frame at t = 0");
    body_S_to_E(&fr, &bS, bE);
    /* moving with the deck: the velocity of the CG's point of S, and the
     * ship's angular velocity (Omega_x = dC/dt C^T), both into B */
    double vE[3], W[3][3], wE[3], C_EB[9];
    for (int i = 0; i < 3; i++) {
        vE[i] = (fb.origin_E_m[i] - fa.origin_E_m[i]) / (2 * dt);
        for (int k = 0; k < 3; k++)
            vE[i] += (fb.C_ES[3 * i + k] - fa.C_ES[3 * i + k]) / (2 * dt) * bS.pos_S_m[k];
    }
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double sum = 0.0;
            for (int k = 0; k < 3; k++)
                sum += (fb.C_ES[3 * i + k] - fa.C_ES[3 * i + k]) / (2 * dt) * fr.C_ES[3 * j + k];
            W[i][j] = sum;
        }
    wE[0] = 0.5 * (W[2][1] - W[1][2]);
    wE[1] = 0.5 * (W[0][2] - W[2][0]);
    wE[2] = 0.5 * (W[1][0] - W[0][1]);
    mat_from_euler(bE->euler_rad, C_EB);
    for (int i = 0; i < 3; i++) {
        bE->vel_B_mps[i] = C_EB[i] * vE[0] + C_EB[3 + i] * vE[1] + C_EB[6 + i] * vE[2];
        bE->rate_B_radps[i] = C_EB[i] * wE[0] + C_EB[3 + i] * wE[1] + C_EB[6 + i] * wE[2];
    }
    u->collective_pct = 0.0;
    u->long_cyclic_pct = u->lat_cyclic_pct = u->pedal_pct = 50.0;
    return 0;
}

/* The air of the trim: the flight's air at t = 0 seen in S (the ship's
 * mean frame), for hfm_trim (which works in S). */
typedef struct trim_air {
    const sim_air *air;
    sim_air_in in; /* the interaction; no turbulence */
} trim_air;

static int trim_air_fn(void *user, const double pos_S_m[3], double t_s, double vel_S_mps[3])
{
    (void)t_s;
    const trim_air *ta = user;
    sim_air_sample_S(ta->air, &ta->in, pos_S_m, 0.0, vel_S_mps);
    return 0;
}

/* The hover start: the trim at the station in the starting air, carried
 * into E with the ship's frame at t = 0. */
static int hover_start(sim_flight *f, hfm_body *bE, hfm_rotor_harm *rh, core_err *err)
{
    const hfm_aircraft *ac = f->ac;
    const sim_flight_opts *o = &f->o;
    const core_log *log = f->log;
    hfm_trim *tr = hfm_trim_create(ac, log);
    if (!tr)
        return core_err_set(err, -1, "flight: out of memory");
    trim_air ta = {f->air, {NULL, o->interaction}};
    hfm_air tair = {trim_air_fn, &ta, NULL};
    hfm_trim_cond cond;
    memset(&cond, 0, sizeof cond);
    cond.kind = HFM_TRIM_HOVER_SHIP;
    cond.wod_speed_mps = o->wod_speed_mps;
    cond.wod_dir_rad = o->wod_dir_rad;
    memcpy(cond.pos_S_m, o->station_S_m, sizeof cond.pos_S_m);
    cond.air = &tair;
    hfm_trim_result r;
    int rc = hfm_trim_solve(tr, &cond, NULL, &r);
    hfm_trim_destroy(tr);
    if (rc != 0) {
        core_err_set(err, rc > 0 ? CORE_ERR_NO_TRIM : CORE_ERR_FAIL,
                     "flight: the hover at (%.2f, %.2f, %.2f) m in S in %.2f m/s from %.1f deg %s",
                     o->station_S_m[0], o->station_S_m[1], o->station_S_m[2], o->wod_speed_mps,
                     o->wod_dir_rad * CORE_RAD_TO_DEG, rc > 0 ? "does not trim" : "failed to evaluate");
        return -1;
    }
    f->u = f->u_trim = r.u;
    sim_ship_frame fr0;
    if (f->frame(f->frame_user, 0.0, &fr0) != 0)
        return core_err_set(err, -1, "flight: no ship frame at t = 0");
    /* the hover's equilibrium is relative to gravity: its place and
     * attitude come from the ship's mean (level) frame, its heading alone,
     * not from the deck's pitch and roll at t = 0 (in a seaway these would
     * tilt the start off the trim by the deck's angles) */
    double psi = atan2(fr0.C_ES[3], fr0.C_ES[0]), cp = cos(psi), sp = sin(psi);
    const double C_mean[9] = {cp, -sp, 0.0, sp, cp, 0.0, 0.0, 0.0, 1.0};
    memcpy(fr0.C_ES, C_mean, sizeof C_mean);
    body_S_to_E(&fr0, &r.body, bE);
    *rh = r.rotor;
    return 0;
}

sim_flight *sim_flight_create(const hfm_aircraft *ac, const core_ship *ship, const sim_flight_opts *o,
                              sim_ship_frame_fn frame, void *frame_user, const cfd_field *field,
                              const core_log *log, core_err *err)
{
    if (!ac || !ship || !(o->rate_hz >= 10.0 && o->rate_hz <= 10000.0) || !(o->ship_speed_mps >= 0.0) ||
        !(o->blend_s > 0.0)) {
        core_err_set(err, -1, "flight: expected an aircraft, a ship, a rate of 10 to 10000 Hz, a ship speed >= 0 and "
                              "a blend time > 0");
        return NULL;
    }
    hfm_gear g0;
    int no_gear = hfm_aircraft_gear(ac, &g0) != 0;
    if ((o->gear != 0 && o->gear != 1) || (o->start != SIM_START_HOVER && o->start != SIM_START_DECK) ||
        !isfinite(o->start_heading_rad) || (o->gear && no_gear) || (o->start == SIM_START_DECK && !o->gear)) {
        core_err_set(err, -1, "flight: gear = %d, start = %d: expected gear 0 or 1 (1 needs an aircraft file with a "
                              "[gear] section%s), start hover (0) or deck (1, with the gear), a finite heading",
                     o->gear, o->start, no_gear ? "; this one has none" : "");
        return NULL;
    }
    sim_flight *f = calloc(1, sizeof *f);
    if (!f) {
        core_err_set(err, -1, "flight: out of memory");
        return NULL;
    }
    f->ac = ac;
    f->ship = *ship;
    f->o = *o;
    f->frame = frame ? frame : steady_ship;
    f->frame_user = frame ? frame_user : f;
    f->h_s = 1.0 / o->rate_hz;
    f->log = log;
    sim_air_opts ao;
    sim_air_opts_default(&ao);
    ao.wod_speed_mps = o->wod_speed_mps;
    ao.wod_dir_rad = o->wod_dir_rad;
    ao.deck_height_m = ship->deck_height_m;
    ao.anemometer_height_m = fmax(ship->deck_height_m - ship->anemometer_S_m[2], 2.0);
    ao.blend_s = o->blend_s;
    if (!(f->air = sim_air_create(&ao, err)))
        goto fail;
    if (sim_air_set_field(f->air, field, -INFINITY, err) != 0)
        goto fail;
    f->air_in.inter = o->interaction;
    /* the start's place gives the interaction's weight in the trim */
    if (o->interaction && sim_interaction_step(o->interaction, o->station_S_m, NAN, 0.0) != 0) {
        core_err_set(err, -1, "flight: the station is not finite");
        goto fail;
    }
    if (o->gear && !(f->gear = sim_contact_create(ac, ship, o->rate_hz, err)))
        goto fail;
    hfm_body bE;
    hfm_rotor_harm rh;
    memset(&rh, 0, sizeof rh);
    if (o->start == SIM_START_DECK) {
        if (deck_start(f, &bE, &f->u, err) != 0)
            goto fail;
        f->u_trim = f->u;
    } else if (hover_start(f, &bE, &rh, err) != 0)
        goto fail;
    hfm_sas_gains sg;
    int no_sas = hfm_aircraft_sas(ac, &sg);
    if (o->sas < -1 || o->sas > 1 || (o->sas == 1 && no_sas)) {
        core_err_set(err, -1, "flight: sas = %d: expected -1 (the aircraft file's), 0 (off) or 1 (on, for an aircraft "
                              "file with a [sas] section%s)",
                     o->sas, no_sas ? "; this one has none" : "");
        goto fail;
    }
    if (!(f->sas = sim_sas_create(&sg, err)))
        goto fail;
    if (o->sas >= 0)
        sim_sas_set_engaged(f->sas, o->sas);
    if (o->turbulence) {
        sim_turb_opts to;
        sim_turb_opts_default(&to);
        if (!(f->turb = sim_turb_create(&to, (uint64_t)o->seed, err)))
            goto fail;
        f->air_in.turb = f->turb;
    }
    /* a seaway's frame at the step times by phasor rotation (sim/ship_motion.c) */
    if (f->frame == sim_ship_motion_frame_fn && sim_ship_motion_set_step(f->frame_user, f->h_s, err) != 0)
        goto fail;
    if (sim_ship_frames_advance(&f->frames, f->frame, f->frame_user, f->h_s, 0) != 0) {
        core_err_set(err, -1, "flight: no ship frame at t = 0");
        goto fail;
    }
    f->hair.fn = flight_air;
    f->hair.user = f;
    f->hair.wake = NULL;
    if (!(f->ts = hfm_tsim_create(ac, &f->hair, HFM_TSIM_ARKODE_FIXED, f->h_s, 0.0, log)) ||
        hfm_tsim_init(f->ts, 0.0, &bE, &f->u, &rh) != 0) {
        core_err_set(err, -1, "flight: the time simulation could not start");
        goto fail;
    }
    set_ext(f);
    if (f->gear) { /* the tyres' anchors where they stand at the start, a strike at once */
        hfm_body b;
        sim_ship_deck deck;
        hfm_tsim_body(f->ts, &b);
        if (sim_ship_deck_at(sim_ship_frames_fn, &f->frames, 0.0, &deck) != 0 ||
            sim_contact_step(f->gear, 0.0, &deck, &b, &f->rep) != 0 || (f->rep.flags & SIM_CONTACT_TIP)) {
            core_err_set(err, -1, "flight: at the start: %s", f->rep.what);
            goto fail;
        }
    }
    return f;
fail:
    sim_flight_destroy(f);
    return NULL;
}

void sim_flight_destroy(sim_flight *f)
{
    if (!f)
        return;
    hfm_tsim_destroy(f->ts);
    sim_contact_destroy(f->gear);
    sim_air_destroy(f->air);
    sim_turb_destroy(f->turb);
    sim_sas_destroy(f->sas);
    free(f);
}

void sim_flight_trim_inputs(const sim_flight *f, sim_flight_inputs *in)
{
    memset(in, 0, sizeof *in);
    in->ctl = f->u_trim;
}

sim_sas *sim_flight_sas(sim_flight *f) { return f->sas; }
const core_ship *sim_flight_ship(const sim_flight *f) { return &f->ship; }

int sim_flight_set_wod(sim_flight *f, double speed_mps, double dir_rad, core_err *err)
{
    if (!(speed_mps >= 0.0) || !isfinite(dir_rad))
        return core_err_set(err, -1, "flight: WOD %g m/s from %g rad: expected a speed >= 0, a finite direction",
                            speed_mps, dir_rad);
    if (f->o.interaction)
        return core_err_set(err, 1, "the coupled rotor interaction is of the WOD it was built for");
    if (fabs(remainder(dir_rad - f->o.wod_dir_rad, 2.0 * CORE_PI)) > 1e-9)
        return core_err_set(err, 1, "a new direction needs the airwake field of that direction");
    if (sim_air_set_wod(f->air, speed_mps, dir_rad, err) != 0)
        return -1;
    f->o.wod_speed_mps = speed_mps;
    f->o.wod_dir_rad = dir_rad;
    return 0;
}

int sim_flight_set_turbulence(sim_flight *f, int on, core_err *err)
{
    if (on && !f->turb) {
        sim_turb_opts to;
        sim_turb_opts_default(&to);
        if (!(f->turb = sim_turb_create(&to, (uint64_t)f->o.seed, err)))
            return -1;
    } else if (!on && f->turb) {
        sim_turb_destroy(f->turb);
        f->turb = NULL;
    }
    f->air_in.turb = f->turb;
    f->o.turbulence = on;
    return 0;
}

void sim_flight_set_external(sim_flight *f, hfm_ext_fn fn, void *user)
{
    f->ext = fn;
    f->ext_user = user;
    set_ext(f);
}

int sim_flight_contact(const sim_flight *f, sim_contact_report *rep)
{
    if (!f->gear) {
        memset(rep, 0, sizeof *rep);
        return 1;
    }
    *rep = f->rep;
    return 0;
}

int sim_flight_set_field(sim_flight *f, const cfd_field *field, core_err *err)
{
    return sim_air_set_field(f->air, field, (double)f->step * f->h_s, err);
}

static double clamp_pct(double v) { return fmin(fmax(v, 0.0), 100.0); }

/* A vector of E in the ship frame: C_ES^T v. */
static void to_S(const sim_ship_frame *fr, const double v_E[3], double v_S[3])
{
    for (int i = 0; i < 3; i++)
        v_S[i] = fr->C_ES[i] * v_E[0] + fr->C_ES[3 + i] * v_E[1] + fr->C_ES[6 + i] * v_E[2];
}

/* The CG's position in S for the body state b (in E) at t_s. 0, or -1
 * outside the ship stage's frames. */
static int cg_pos_S(const sim_flight *f, const hfm_body *b, double t_s, double p_S[3])
{
    sim_ship_frame fr;
    if (sim_ship_frames_at(&f->frames, t_s, &fr) != 0)
        return -1;
    double d[3];
    for (int i = 0; i < 3; i++)
        d[i] = b->pos_S_m[i] - fr.origin_E_m[i];
    to_S(&fr, d, p_S);
    return 0;
}

void sim_flight_state(const sim_flight *f, sim_flight_out *out)
{
    memset(out, 0, sizeof *out);
    out->step = f->step;
    out->t_s = (double)f->step * f->h_s;
    hfm_body b;
    hfm_tsim_body(f->ts, &b);
    double C_EB[9], vE[3];
    mat_from_euler(b.euler_rad, C_EB);
    for (int i = 0; i < 3; i++)
        vE[i] = C_EB[3 * i] * b.vel_B_mps[0] + C_EB[3 * i + 1] * b.vel_B_mps[1] + C_EB[3 * i + 2] * b.vel_B_mps[2];
    memcpy(out->pos_E_m, b.pos_S_m, sizeof out->pos_E_m);
    memcpy(out->vel_E_mps, vE, sizeof vE);
    memcpy(out->euler_E_rad, b.euler_rad, sizeof out->euler_E_rad);
    memcpy(out->rate_B_radps, b.rate_B_radps, sizeof out->rate_B_radps);
    /* the ship stage's frame, not a second wave sum */
    int no_frame = sim_ship_frames_at(&f->frames, out->t_s, &out->ship) != 0;
    const sim_ship_frame *fr = &out->ship;
    double d[3], dv[3];
    for (int i = 0; i < 3; i++) {
        d[i] = out->pos_E_m[i] - fr->origin_E_m[i];
        dv[i] = vE[i] - fr->mean_vel_E_mps[i];
    }
    to_S(fr, d, out->pos_S_m);
    to_S(fr, dv, out->vel_S_mps);
    out->ctl = f->u;
    if (!no_frame) {
        double a[3], r2 = 0.0;
        sim_air_sample_E(f->air, &f->air_in, fr, out->pos_E_m, out->t_s, a);
        for (int i = 0; i < 3; i++)
            r2 += (a[i] - vE[i]) * (a[i] - vE[i]);
        out->airspeed_mps = sqrt(r2);
    }
    out->air_flags = sim_air_flags(f->air, f->air_in.inter, out->t_s);
    out->air_grid = sim_air_grid(f->air);
    hfm_tsim_rotor(f->ts, &out->rotor_thrust_N, &out->rotor_power_W);
    if (f->gear) {
        const sim_contact_report *r = &f->rep;
        out->nlegs = r->nlegs;
        for (int i = 0; i < r->nlegs; i++) {
            out->on_deck |= r->leg[i].on_deck;
            out->gear_load_N[i] = r->leg[i].normal_N;
            out->gear_friction_N[i][0] = r->leg[i].friction_N[0];
            out->gear_friction_N[i][1] = r->leg[i].friction_N[1];
        }
        out->contact_flags = r->flags;
        snprintf(out->contact_what, sizeof out->contact_what, "%s", r->what);
    }
}

/* The stages' inputs, filled by the step before each stage runs. */
typedef struct pilot_in {
    const sim_flight_inputs *in; /* NULL or hold: the last controls kept */
    hfm_body body;               /* the state at the step's start, for the SAS */
} pilot_in;
typedef struct ship_in {
    long step; /* the step under way */
} ship_in;
typedef struct air_in {
    double t_s;        /* the step's start */
    double cg_S_m[3];  /* the CG in S there */
    double thrust_N;   /* the main rotor's thrust there (NaN: not known yet) */
} air_in;
typedef struct model_in {
    hfm_controls u_rotor; /* the pilot stage's controls at the rotor */
    double t1_s;          /* the step's end */
} model_in;
typedef struct gear_in {
    double t_s;   /* the step's end */
    hfm_body body; /* the state there */
} gear_in;

/* 1. The pilot's controls, clamped, held when asked, and the controls at
 * the rotor: the SAS's from the state at the step's start. */
static void stage_pilot(sim_flight *f, const pilot_in *in, hfm_controls *u_rotor)
{
    if (in->in && !in->in->hold) {
        const hfm_controls *c = &in->in->ctl;
        f->u.collective_pct = clamp_pct(c->collective_pct);
        f->u.long_cyclic_pct = clamp_pct(c->long_cyclic_pct);
        f->u.lat_cyclic_pct = clamp_pct(c->lat_cyclic_pct);
        f->u.pedal_pct = clamp_pct(c->pedal_pct);
    }
    sim_sas_step(f->sas, &in->body, &f->u, u_rotor);
}

/* 2. The ship's frames around the step (one new frame a step). */
static int stage_ship(sim_flight *f, const ship_in *in, core_err *err)
{
    if (sim_ship_frames_advance(&f->frames, f->frame, f->frame_user, f->h_s, in->step) != 0)
        return core_err_set(err, -1, "flight: no ship frame at t = %.3f s", (double)in->step * f->h_s);
    return 0;
}

/* 3. The air's inputs for the step: the interaction's rotor, and the
 * turbulence's frozen field moved on by one step, convected by the mean
 * air at the CG (the interaction's included). */
static int stage_air(sim_flight *f, const air_in *in, core_err *err)
{
    if (f->o.interaction && sim_interaction_step(f->o.interaction, in->cg_S_m, in->thrust_N, f->h_s) != 0)
        return core_err_set(err, -1, "flight: the CG is not finite at t = %.3f s", in->t_s);
    if (f->turb) {
        double v[3], k, eps;
        sim_air_mean_S(f->air, in->cg_S_m, in->t_s, v, &k, &eps);
        if (f->o.interaction)
            sim_interaction_apply(f->o.interaction, in->cg_S_m, v);
        if (sim_turb_step(f->turb, in->cg_S_m, v, k, eps, f->h_s, err) != 0)
            return -1;
    }
    return 0;
}

/* 4-5. The flight model over the step, the external loads at its
 * right-hand sides. */
static int stage_model(sim_flight *f, const model_in *in, core_err *err)
{
    hfm_tsim_set_controls(f->ts, &in->u_rotor);
    if (hfm_tsim_advance(f->ts, in->t1_s) != 0)
        return core_err_set(err, -1, "flight: the integrator failed at t = %.3f s", in->t1_s);
    return 0;
}

/* 5. The gear's bookkeeping from the state the step ended at; a crash or a
 * roll-over ends the flight. */
static int stage_gear(sim_flight *f, const gear_in *in, core_err *err)
{
    sim_ship_deck deck;
    if (sim_ship_deck_at(sim_ship_frames_fn, &f->frames, in->t_s, &deck) != 0)
        return core_err_set(err, -1, "flight: no ship frame at t = %.3f s", in->t_s);
    if (sim_contact_step(f->gear, in->t_s, &deck, &in->body, &f->rep) == 0 && !(f->rep.flags & SIM_CONTACT_TIP))
        return 0;
    f->ended = 1;
    if (f->rep.flags & SIM_CONTACT_CRASH)
        snprintf(f->end_msg, sizeof f->end_msg, "%s at t = %.2f s", f->rep.what, in->t_s);
    else
        snprintf(f->end_msg, sizeof f->end_msg,
                 "roll-over on the deck: tilted %.1f deg from the deck, past the gear's tip-over angle %.1f "
                 "deg, at t = %.2f s",
                 f->rep.tilt_rad * CORE_RAD_TO_DEG, f->rep.tip_angle_rad * CORE_RAD_TO_DEG, in->t_s);
    return 0;
}

int sim_flight_step(sim_flight *f, const sim_flight_inputs *in, sim_flight_out *out, core_err *err)
{
    if (f->ended) {
        if (out)
            sim_flight_state(f, out);
        return core_err_set(err, 1, "%s", f->end_msg);
    }
    double t0 = (double)f->step * f->h_s, t1 = (double)(f->step + 1) * f->h_s;
    pilot_in pi = {.in = in};
    hfm_tsim_body(f->ts, &pi.body);
    model_in mi = {.t1_s = t1};
    stage_pilot(f, &pi, &mi.u_rotor);
    ship_in si = {f->step};
    if (stage_ship(f, &si, err) != 0)
        return -1;
    if (f->o.interaction || f->turb) {
        air_in ai = {.t_s = t0, .thrust_N = NAN};
        if (cg_pos_S(f, &pi.body, t0, ai.cg_S_m) != 0)
            return core_err_set(err, -1, "flight: no ship frame at t = %.3f s", t0);
        double P_W;
        if (hfm_tsim_rhs_evals(f->ts) > 0)
            hfm_tsim_rotor(f->ts, &ai.thrust_N, &P_W);
        if (stage_air(f, &ai, err) != 0)
            return -1;
    }
    if (stage_model(f, &mi, err) != 0)
        return -1;
    f->step++;
    if (f->gear) {
        gear_in gi = {.t_s = t1};
        hfm_tsim_body(f->ts, &gi.body);
        if (stage_gear(f, &gi, err) != 0)
            return -1;
    }
    /* 6. outputs */
    if (out)
        sim_flight_state(f, out);
    if (f->ended)
        return core_err_set(err, 1, "%s", f->end_msg);
    return 0;
}
