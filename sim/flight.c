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
 *   5. external loads: the caller's hfm_ext_fn (the landing gear), added
 *               at every right-hand side
 *   6. outputs: the state in E and relative to the ship (sim_flight_out).
 * No clock, socket, file or print inside: the same inputs give the same
 * trajectory whatever paces the calls (real time or as fast as it can).
 *
 * The start: the hover trim (hfm_trim, HFM_TRIM_HOVER_SHIP) with the CG at
 * the station in S, in the air the flight starts with (the field at the
 * WOD speed, or the free stream), carried into E with the ship's frame at
 * t = 0: position o_E + C_ES p_S, velocity the ship's mean velocity,
 * attitude C_EB = C_ES C_SB. With the ship steady the flight then starts
 * in equilibrium (the air relative to the helicopter is the trim's).
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

/* 3-2-1 Euler angles of a direction cosine matrix C_AB (v_A = C_AB v_B). */
static void euler_from_mat(const double *C, double e[3])
{
    e[1] = asin(fmax(-1.0, fmin(1.0, -C[6])));
    e[0] = atan2(C[7], C[8]);
    e[2] = atan2(C[3], C[0]);
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
    euler_from_mat(C_EB, bE->euler_rad);
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
    /* the start: the hover trim at the station in the starting air */
    hfm_trim *tr = hfm_trim_create(ac, log);
    if (!tr) {
        core_err_set(err, -1, "flight: out of memory");
        goto fail;
    }
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
        core_err_set(err, -1, "flight: the hover at (%.2f, %.2f, %.2f) m in S in %.2f m/s from %.1f deg %s",
                     o->station_S_m[0], o->station_S_m[1], o->station_S_m[2], o->wod_speed_mps,
                     o->wod_dir_rad * CORE_RAD_TO_DEG, rc > 0 ? "does not trim" : "failed to evaluate");
        goto fail;
    }
    f->u = f->u_trim = r.u;
    sim_ship_frame fr0;
    if (f->frame(f->frame_user, 0.0, &fr0) != 0) {
        core_err_set(err, -1, "flight: no ship frame at t = 0");
        goto fail;
    }
    hfm_body bE;
    body_S_to_E(&fr0, &r.body, &bE);
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
        hfm_tsim_init(f->ts, 0.0, &bE, &f->u, &r.rotor) != 0) {
        core_err_set(err, -1, "flight: the time simulation could not start");
        goto fail;
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

void sim_flight_set_external(sim_flight *f, hfm_ext_fn fn, void *user) { hfm_tsim_set_external(f->ts, fn, user); }

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
}

int sim_flight_step(sim_flight *f, const sim_flight_inputs *in, sim_flight_out *out, core_err *err)
{
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
        double p_S[3];
        cg_pos_S(f, &b0, t0, p_S);
        if (sim_interaction_set_rotor(f->o.interaction, p_S, NAN, f->h_s) != 0)
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
    /* 6. outputs */
    if (out)
        sim_flight_state(f, out);
    return 0;
}
