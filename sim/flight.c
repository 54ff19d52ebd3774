/* flight.c -- the deterministic flight step of the real-time loop.
 *
 * One step of h = 1 / rate_hz runs its stages in this fixed order, as
 * JSBSim's FGFDMExec::Run runs its models, each fed by an explicit input:
 *   1. pilot:   the step's controls (sim_flight_inputs; hold keeps the last)
 *   2. ship:    the ship frame S in E, a pure function of time (the
 *               caller's sim_ship_frame_fn, or the ship steady at its speed)
 *   3. air:     the airwake attached to the ship, in E (sim/air.c), sampled
 *               by the flight model at every blade element, the tail rotor,
 *               fuselage and tail surfaces through one hfm_air callback;
 *               its frozen turbulence (sim/turbulence.c) advanced once per
 *               step with the field's mean air, k and epsilon at the CG
 *   4. flight model: the helicopter integrated in the Earth frame E
 *               (inertial) by hfm_tsim, ARKODE explicit Runge-Kutta at the
 *               fixed step (Ralston's 2-stage method, hfm/tsim.c)
 *   5. external loads: the landing gear on the deck (opts.gear,
 *               sim/contact.c) and the caller's hfm_ext_fn, summed and
 *               added at every right-hand side; after the step the gear's
 *               bookkeeping (sim_contact_step: the tyres' slides, the
 *               strike points, slide / tip-over / crash), from the state
 *               the step ended at
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
    sim_air *air;
    sim_turb *turb;           /* NULL: no turbulence */
    hfm_air hair;
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

/* The gear sees the ship's frame the air has (its cache of the steps'
 * frames): one wave sum per time, the same frames as the air. */
static int gear_frame(void *user, double t_s, sim_ship_frame *fr)
{
    sim_flight *f = user;
    return sim_air_frame(f->air, t_s, fr);
}

/* The external loads at a right-hand side: the gear's and the caller's. */
static int flight_ext(void *user, double t_s, const hfm_body *b, double F_B_N[3], double M_B_Nm[3])
{
    sim_flight *f = user;
    for (int i = 0; i < 3; i++)
        F_B_N[i] = M_B_Nm[i] = 0.0;
    if (f->gear && sim_contact_ext_fn(f->gear, t_s, b, F_B_N, M_B_Nm) != 0)
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
    u->long_pct = u->lat_pct = u->pedal_pct = 50.0;
    return 0;
}

/* The air of the trim: the flight's air at t = 0 seen in S (the ship's
 * mean frame), for hfm_trim (which works in S). */
typedef struct trim_air {
    const sim_air *air;
} trim_air;

static int trim_air_fn(void *user, const double pos_S_m[3], double t_s, double vel_S_mps[3])
{
    (void)t_s;
    const trim_air *ta = user;
    sim_air_sample_S(ta->air, pos_S_m, 0.0, vel_S_mps);
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
    trim_air ta = {f->air};
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
    if (!(f->air = sim_air_create(&ao, f->frame, f->frame_user, err)))
        goto fail;
    if (sim_air_set_field(f->air, field, -INFINITY, err) != 0)
        goto fail;
    sim_air_set_interaction(f->air, o->interaction);
    /* the start's place gives the interaction's weight in the trim */
    if (o->interaction && sim_interaction_set_rotor(o->interaction, o->station_S_m, NAN, 0.0) != 0) {
        core_err_set(err, -1, "flight: the station is not finite");
        goto fail;
    }
    if (o->gear && !(f->gear = sim_contact_create(ac, ship, gear_frame, f, o->rate_hz, err)))
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
        sim_air_set_turb(f->air, f->turb);
    }
    sim_air_set_step(f->air, f->h_s);
    /* a seaway's frame at the step times by phasor rotation (sim/ship_motion.c) */
    if (f->frame == sim_ship_motion_frame_fn && sim_ship_motion_set_step(f->frame_user, f->h_s, err) != 0)
        goto fail;
    f->hair.fn = sim_air_fn;
    f->hair.user = f->air;
    f->hair.wake = NULL;
    if (!(f->ts = hfm_tsim_create(ac, &f->hair, HFM_TSIM_ARKODE_FIXED, f->h_s, 0.0, log)) ||
        hfm_tsim_init(f->ts, 0.0, &bE, &f->u, &rh) != 0) {
        core_err_set(err, -1, "flight: the time simulation could not start");
        goto fail;
    }
    set_ext(f);
    if (f->gear) { /* the tyres' anchors where they stand at the start, a strike at once */
        hfm_body b;
        hfm_tsim_body(f->ts, &b);
        if (sim_contact_step(f->gear, 0.0, &b, &f->rep) != 0 || (f->rep.flags & SIM_CONTACT_TIP)) {
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
    in->collective_pct = f->u_trim.collective_pct;
    in->long_pct = f->u_trim.long_pct;
    in->lat_pct = f->u_trim.lat_pct;
    in->pedal_pct = f->u_trim.pedal_pct;
}

sim_sas *sim_flight_sas(sim_flight *f) { return f->sas; }

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

sim_contact *sim_flight_gear(sim_flight *f) { return f->gear; }

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

/* The CG's position in S for the body state b (in E) at t_s. */
static void cg_pos_S(const sim_flight *f, const hfm_body *b, double t_s, double p_S[3])
{
    sim_ship_frame fr;
    sim_air_frame(f->air, t_s, &fr);
    double d[3];
    for (int i = 0; i < 3; i++)
        d[i] = b->pos_S_m[i] - fr.origin_E_m[i];
    to_S(&fr, d, p_S);
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
    sim_air_frame(f->air, out->t_s, &out->ship); /* the frame the air has just used, not a second wave sum */
    const sim_ship_frame *fr = &out->ship;
    double d[3], dv[3];
    for (int i = 0; i < 3; i++) {
        d[i] = out->pos_E_m[i] - fr->origin_E_m[i];
        dv[i] = vE[i] - fr->mean_vel_E_mps[i];
    }
    to_S(fr, d, out->pos_S_m);
    to_S(fr, dv, out->vel_S_mps);
    out->collective_pct = f->u.collective_pct;
    out->long_pct = f->u.long_pct;
    out->lat_pct = f->u.lat_pct;
    out->pedal_pct = f->u.pedal_pct;
    double a[3];
    if (sim_air_fn(f->air, out->pos_E_m, out->t_s, a) == 0) {
        double r2 = 0.0;
        for (int i = 0; i < 3; i++)
            r2 += (a[i] - vE[i]) * (a[i] - vE[i]);
        out->airspeed_mps = sqrt(r2);
    }
    out->air_flags = sim_air_flags(f->air, out->t_s);
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

int sim_flight_step(sim_flight *f, const sim_flight_inputs *in, sim_flight_out *out, core_err *err)
{
    if (f->ended) {
        if (out)
            sim_flight_state(f, out);
        return core_err_set(err, 1, "%s", f->end_msg);
    }
    /* 1. pilot, and the stability augmentation between the pilot's
     * controls and the rotor, from the body state at the step's start */
    if (in && !in->hold) {
        f->u.collective_pct = clamp_pct(in->collective_pct);
        f->u.long_pct = clamp_pct(in->long_pct);
        f->u.lat_pct = clamp_pct(in->lat_pct);
        f->u.pedal_pct = clamp_pct(in->pedal_pct);
    }
    hfm_body b0;
    hfm_tsim_body(f->ts, &b0);
    hfm_controls u_rotor;
    sim_sas_step(f->sas, &b0, &f->u, &u_rotor);
    hfm_tsim_set_controls(f->ts, &u_rotor);
    /* 2-3: the ship frame and the air are functions of time, sampled by the
     * flight model's right-hand sides; the turbulence's frozen field moves
     * on by one step, convected by the mean air at the CG */
    double t0 = (double)f->step * f->h_s, t1 = (double)(f->step + 1) * f->h_s;
    if (f->o.interaction) { /* the rotor's place and thrust for the coupled interaction */
        double p_S[3], T_N, P_W;
        cg_pos_S(f, &b0, t0, p_S);
        hfm_tsim_rotor(f->ts, &T_N, &P_W);
        if (sim_interaction_set_rotor(f->o.interaction, p_S, hfm_tsim_rhs_evals(f->ts) > 0 ? T_N : NAN, f->h_s) != 0)
            return core_err_set(err, -1, "flight: the CG is not finite at t = %.3f s", t0);
    }
    if (f->turb) {
        double p_S[3], v[3], k, eps;
        cg_pos_S(f, &b0, t0, p_S);
        sim_air_mean_S(f->air, p_S, t0, v, &k, &eps);
        if (sim_turb_step(f->turb, p_S, v, k, eps, f->h_s, err) != 0)
            return -1;
    }
    /* 4-5: the flight model with the external loads */
    if (hfm_tsim_advance(f->ts, t1) != 0)
        return core_err_set(err, -1, "flight: the integrator failed at t = %.3f s", t1);
    f->step++;
    /* 5. the gear's bookkeeping from the state the step ended at; a crash
     * or a roll-over ends the flight */
    if (f->gear) {
        hfm_body b;
        hfm_tsim_body(f->ts, &b);
        if (sim_contact_step(f->gear, t1, &b, &f->rep) != 0 || (f->rep.flags & SIM_CONTACT_TIP)) {
            f->ended = 1;
            if (f->rep.flags & SIM_CONTACT_CRASH)
                snprintf(f->end_msg, sizeof f->end_msg, "%s at t = %.2f s", f->rep.what, t1);
            else
                snprintf(f->end_msg, sizeof f->end_msg,
                         "roll-over on the deck: tilted %.1f deg from the deck, past the gear's tip-over angle %.1f "
                         "deg, at t = %.2f s",
                         f->rep.tilt_rad * CORE_RAD_TO_DEG, f->rep.tip_angle_rad * CORE_RAD_TO_DEG, t1);
        }
    }
    /* 6. outputs */
    if (out)
        sim_flight_state(f, out);
    if (f->ended)
        return core_err_set(err, 1, "%s", f->end_msg);
    return 0;
}
