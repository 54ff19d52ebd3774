/* pilot_replay.c -- the replay pilot: re-flies a recorded run, relative to
 * the deck, in another wind over deck and sea state.
 *
 * The reference. A run of `disim fly --log FILE` is an LCM event log;
 * the reader (sim/log.c, sim_log_load) makes of it the helicopter's
 * motion relative to the ship's landing spot as a function of the
 * flight's time (position r_S, velocity v_S relative to the deck,
 * heading from the bow) and the recorded pilot's controls. So a landing
 * flown over a heaving, rolling deck is re-flown relative to the deck: in
 * another sea the replay follows its own deck.
 *
 * The pilot. The automated pilot's loops (sim/pilot_auto.c: crossover
 * model, McRuer and Krendel 1974; outer loops after Lee and Horn 2005)
 * track the reference through sim_pilot_auto_set_reference each step.
 * The loops act on the error from the reference now; what is fed forward
 * is the reference's motion tau ahead (tau = preview_s, default the
 * pilot's delay: a pilot flying a known profile leads it by about his
 * delay, the precognitive mode of McRuer and Krendel's successive
 * organisation of perception), through the pilot's own loop laws:
 *     horizontal:  v_ff = v_S(t + tau) + a_S(t + tau + tau_a) / w_v
 * (the velocity loop's a_c = w_v (v_c - v) then carries a_S, the
 * reference's acceleration, whole; the acceleration is the attitude's,
 * which follows its command about 1 / w_a behind, w_a the attitude loops'
 * crossover: the crossover model closed, Y / (1 + Y) ~ 1 / (1 + s / w_a);
 * tau_a = acc_lead_s, default 1 / w_a),
 * and
 *     vertical:    w_ff = w(t + tau) + (a_z(t + tau) - Z_w w(t + tau)) / w_h
 * (the height loop's rate term then gives the collective the linear model
 * needs for that rate and acceleration, (a_z - Z_w w) / Z_col; w_v and
 * w_h the velocity loop's bandwidth and the height loop's crossover, Z_w
 * the heave damping the gains come from); the heading is the reference's
 * at t + tau. With feed_controls, the recorded pilot's control activity is
 * fed forward as well, about this flight's trim, and the loops act on the
 * deviation from the recorded state:
 *     u = u_trim + (u_rec(t) - u_rec,0) + (P(x) - P(x_rec)),
 * u_rec,0 the controls of the log's first state (the recorded run's trim),
 * P the pilot's delayed command for a state, x the flown state, x_rec the
 * recorded one at the same time (a second copy of the pilot flies the
 * recorded states: their delays match, and the correction is 0 while the
 * flight is on the recorded trajectory). In the recorded conditions that
 * reproduces the run to the samples' precision; in other conditions the
 * loops' correction carries what the recorded controls get wrong.
 *
 * Integral action. A steady force the gains were not scheduled for (the
 * airwake's mean downwash and deficit over the deck, the SAS's attitude
 * hold) leaves a proportional loop a standing error: the velocity loop
 * needs a velocity error a / w_v for an acceleration a, and the position
 * loop a position error a / (w_v w_p) for that. The replay pilot
 * integrates the errors from the reference now (position x, y in S,
 * heading, and the height with feed_controls: without it the heave's
 * trim below takes the vertical force out) and adds each integral over
 * its time constant to the reference the loops are given:
 *     r' = r + (1 / T_i) int (r - x) dt,
 * a PI law about each outer loop (with the shadow of feed_controls flying
 * the reference without it, so that the correction carries it). The rule
 * for T_i: the integral's corner 1 / T_i a quarter of the loop's
 * crossover w_c (T_i = 4 / w_c, INT_CORNER), where it costs the loop
 * atan(1/4) = 14 deg of phase margin: the position loop at pos_bw (0.3
 * rad/s: T_i = 13.3 s), the height loop at hgt_crossover (2 rad/s: 2 s),
 * the heading loop at yaw_crossover (1.5 rad/s: 2.7 s); not fitted to a
 * run. Anti-windup: each integral is clamped so that its share of the
 * reference asks the loops for at most what the automated pilot's trim
 * may (opts.trim_s): 1 m/s of commanded speed (INT_SPEED_MPS, 3.3 m of
 * position at pos_bw 0.3 rad/s), 10 % of collective or pedal travel
 * through the crossover pilot's lead (INT_CTL_PCT: 10 |K| / (w_c a_L) of
 * height or heading); all are frozen while a control is at its stop and
 * while the pilot's hand holds the controls on the deck. The automated
 * pilot's own trim is off in the replay (sim_pilot_replay_opts_default):
 * these integrals replace it. What they cost: a reference's slow swings
 * are followed with the integrals' lag (in the free stream the replay
 * swings about the reference by some 0.3 m over 10 to 12 s); in the
 * CG-47's coarse airwake the steady sidewash and downdraft over the deck
 * no longer push the replay into the hangar (without them it struck it
 * at 19 s).
 *
 * The steady trims. The airwake over the deck rolls and pitches the
 * aircraft as well, and an attitude loop, a proportional law, stands off
 * its command under a steady moment. Over the CG-47's deck (coarse
 * airwake, 25 kt ahead, the port landing) the automated pilot holds
 * 7.6 % more right cyclic than alongside, and its roll stands 3 to 5 deg
 * off its command from the deck edge on; the velocity and position
 * loops take that out as a steady force, slowly. The recorded trajectory
 * holds the recorded pilot's answer to that air; a replay meeting the
 * same air with the same loops answers it again, and so departs from the
 * reference by about what the recorded run departed from its task (its
 * traverse: 1.27 m, height 1.04 m). Measured with the outer integrals
 * alone: rms 0.836 m, worst 1.737 m at 24.23 s, 1.4 m to port over the
 * deck from 20 s; the same with neither run turbulent (0.945 m, 2.40 m),
 * no control at a stop, no better with the acceleration's feed-forward
 * halved or off (0.896 m, 0.887 m), nor with the recorded attitudes fed
 * forward in its place (0.946 m); of the integrals only the height's
 * reached its clamp (at 21 s: the downdraft past the deck edge, which
 * the recorded run sank 0.8 m in and the height's feed-forward asks for
 * again). So the replay pilot flies with the automated pilot's steady
 * trims (opts.pilot.moment_s and heave_s, sim/pilot_auto.c), which
 * estimate the moments and the vertical force the linear model does not
 * explain from the rates' change and take them out with the cyclic and
 * the collective, averaged over T_i = 4 / w_c of each loop (the
 * integrals' rule: roll and pitch at att_crossover 2.5 rad/s, 1.6 s;
 * heave at hgt_crossover 2 rad/s, 2 s), the height's integral left out:
 * rms 0.371 m, worst 0.811 m at 29.54 s, the sideways lag gone (within
 * 0.4 m); what is left is fore and aft (0.6 m ahead at 18 s, 0.7 m
 * behind at 30 s) and the height at the deck edge (0.6 m low at 20 s).
 * The same log in 15 kt from red 30 (its own field): 0.480 m, 1.248 m
 * (with the outer integrals alone 0.992 m, 2.081 m); the free stream
 * above: 0.205 m, 0.443 m (0.316 m, 0.734 m). With feed_controls the
 * recorded controls carry the forces the recorded run met, and both
 * pilots fly without the trims.
 *
 * Assumptions: the log is of one flight from its start at the scenario's
 * station (the replay's flight starts where the reference starts); the
 * flight has the SAS as the recorded run had it (the log's sim_status_t
 * say: sim_log_summary.sas) and the pilot's gains are scheduled for it
 * (opts.pilot.sas, as the automated pilot's); the recorded pilot's inputs go through the loop's
 * stations unchanged (one station, never held long enough to matter).
 *
 * Errors reported: the 3-D distance of the flown CG from the reference at
 * the same time (no preview), rms and largest, over the run and per phase
 * of the reference: descend (sinking faster than 0.2 m/s and faster than
 * it moves across), translate (moving faster than 0.3 m/s, or climbing
 * faster than 0.2 m/s), hover (else), on deck (the recorded state has a
 * wheel on the deck). The heading's largest error too.
 *
 * On the deck. Where the reference and the flight both have a wheel on
 * the deck the pilot lowers the collective at 20 %/s to 0 and holds
 * cyclic and pedals where they were, at once (the automated pilot's hand
 * after touchdown); the loops take over again when the reference leaves
 * the deck.
 */
#include "sim.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>


#define INT_CORNER 4.0                       /* T_i = INT_CORNER / w_c */
#define INT_SPEED_MPS 1.0                    /* the integrals' largest share: of the commanded speed */
#define INT_CTL_PCT 10.0                     /* of the collective and the pedals */

struct sim_pilot_replay {
    const sim_log *ref;
    sim_pilot_replay_opts o;
    sim_pilot_auto *pilot;  /* flies the flight */
    sim_pilot_auto *shadow; /* feed_controls: flies the recorded states */
    double Z_w;             /* the heave damping the pilot's gains come from (1/s) */
    double trim_pct[4];     /* this flight's trim: the recorded controls are fed forward about it */
    int deck;               /* on the deck with the reference: the collective going down */
    double deck_u[4];       /* the controls then (cyclic and pedals held) */
    double last_u[4];       /* the last controls given */
    double t1_s;            /* the reference's last state's time */
    double ctl0_pct[4];     /* the controls of its first state (the recorded run's trim) */
    double Ti_pos_s, Ti_hgt_s, Ti_psi_s; /* the integral time constants */
    double lim_pos_m, lim_hgt_m, lim_psi_rad; /* the integrals' largest share of the reference */
    double i_pos_S[2], i_hgt, i_psi; /* the integrals of the errors from the reference (m s, rad s) */
    int stop;               /* the last step had a control at its stop */
    double sum2[SIM_REPLAY_NPHASE + 1];
    sim_replay_result r;
};

void sim_pilot_replay_opts_default(sim_pilot_replay_opts *o)
{
    memset(o, 0, sizeof *o);
    sim_pilot_auto_opts_default(&o->pilot);
    o->pilot.trim_s = 0.0; /* the replay's own integrals instead */
    o->preview_s = -1.0;
    o->acc_lead_s = -1.0;
}

const char *sim_replay_phase_name(int phase)
{
    return phase == SIM_REPLAY_HOVER       ? "hover"
           : phase == SIM_REPLAY_TRANSLATE ? "translate"
           : phase == SIM_REPLAY_DESCEND   ? "descend"
           : phase == SIM_REPLAY_ON_DECK   ? "on deck"
                                           : "all";
}

sim_pilot_replay *sim_pilot_replay_create(const hfm_aircraft *ac, const sim_log *ref,
                                          const sim_pilot_replay_opts *o, const sim_flight_inputs *trim,
                                          const core_log *log, core_err *err)
{
    if (!ac || !ref || !o || !trim) {
        core_err_set(err, -1, "pilot_replay: expected an aircraft, a reference log, options and the trim");
        return NULL;
    }
    double pv = o->preview_s < 0.0 ? o->pilot.delay_s : o->preview_s;
    if (!(pv >= 0.0 && pv <= 10.0) || !(o->acc_lead_s <= 10.0) || !(o->pilot.att_crossover_radps > 0.0)) {
        core_err_set(err, -1, "pilot_replay: preview %g s, acceleration lead %g s: expected up to 10 s each (< 0: the "
                              "defaults) and a positive attitude crossover", o->preview_s, o->acc_lead_s);
        return NULL;
    }
    sim_pilot_replay *p = calloc(1, sizeof *p);
    if (!p) {
        core_err_set(err, -1, "pilot_replay: out of memory");
        return NULL;
    }
    p->ref = ref;
    p->o = *o;
    p->o.preview_s = pv;
    p->o.acc_lead_s = o->acc_lead_s < 0.0 ? 1.0 / o->pilot.att_crossover_radps : o->acc_lead_s;
    /* the automated pilot's gains at the reference's start, as a station
     * keeping there for the log's length; the reference then moves on */
    sim_log_summary info;
    sim_log_info(ref, &info);
    p->t1_s = info.t1_s;
    sim_log_state st0;
    sim_log_state_at(ref, info.t0_s, &st0);
    memcpy(p->ctl0_pct, st0.controls_pct, sizeof p->ctl0_pct);
    sim_log_sample s0;
    sim_log_sample_at(ref, info.t0_s, &s0);
    sim_task t;
    memset(&t, 0, sizeof t);
    t.kind = SIM_TASK_STATION_KEEP;
    memcpy(t.target_S_m, s0.pos_S_m, sizeof t.target_S_m);
    if (!(t.target_S_m[2] < -0.1))
        t.target_S_m[2] = -0.1; /* a log that starts on the deck: the gains of a hover just above it */
    t.heading_rad = s0.heading_rad;
    t.duration_s = fmax(0.1, p->t1_s);
    t.desired.pos_m = t.adequate.pos_m = 1.0;
    t.desired.height_m = t.adequate.height_m = 1.0;
    t.desired.heading_rad = t.adequate.heading_rad = 5.0 * CORE_DEG_TO_RAD;
    sim_task_phase *h = &t.phase[0]; /* one hold phase, as sim_task_load makes a station keeping */
    snprintf(h->name, sizeof h->name, "replay");
    h->kind = SIM_PHASE_HOLD;
    memcpy(h->target_S_m, t.target_S_m, sizeof h->target_S_m);
    h->heading_rad = t.heading_rad;
    h->duration_s = t.duration_s;
    h->desired = t.desired;
    h->adequate = t.adequate;
    t.nphases = 1;
    sim_pilot_auto_opts po = o->pilot; /* the steady trims, unless the recorded controls carry the forces */
    po.moment_s = o->feed_controls ? 0.0 : INT_CORNER / o->pilot.att_crossover_radps;
    po.heave_s = o->feed_controls ? 0.0 : INT_CORNER / o->pilot.hgt_crossover_radps;
    if (!(p->pilot = sim_pilot_auto_create(ac, &t, &po, trim, log, err)))
        goto fail;
    sim_pilot_gains g;
    sim_pilot_auto_gains(p->pilot, &g);
    p->Z_w = g.Z_w;
    memcpy(p->last_u, g.trim_pct, sizeof p->last_u);
    p->trim_pct[0] = trim->ctl.collective_pct, p->trim_pct[1] = trim->ctl.long_cyclic_pct;
    p->trim_pct[2] = trim->ctl.lat_cyclic_pct, p->trim_pct[3] = trim->ctl.pedal_pct;
    if (o->feed_controls && !(p->shadow = sim_pilot_auto_create(ac, &t, &po, trim, log, err)))
        goto fail;
    p->Ti_pos_s = INT_CORNER / o->pilot.pos_bw_radps;
    p->Ti_hgt_s = INT_CORNER / o->pilot.hgt_crossover_radps;
    p->Ti_psi_s = INT_CORNER / o->pilot.yaw_crossover_radps;
    /* the shares: 1 m/s of commanded speed through the position loop; 10 %
     * of travel through the crossover pilot's lead a_L on the height and
     * heading errors (w_c / K) a_L e, a_L = max(-a, 0.3 w_c) */
    double aL_h = fmax(-g.Z_w, 0.3 * o->pilot.hgt_crossover_radps), aL_r = fmax(-g.N_r, 0.3 * o->pilot.yaw_crossover_radps);
    p->lim_pos_m = INT_SPEED_MPS / o->pilot.pos_bw_radps;
    p->lim_hgt_m = INT_CTL_PCT * fabs(g.Z_col) / (o->pilot.hgt_crossover_radps * aL_h);
    p->lim_psi_rad = INT_CTL_PCT * fabs(g.N_ped) / (o->pilot.yaw_crossover_radps * aL_r);
    p->r.t_s = -1.0;
    return p;
fail:
    sim_pilot_replay_destroy(p);
    return NULL;
}

int sim_pilot_replay_set_trim_state(sim_pilot_replay *p, const sim_flight_out *s0)
{
    if (!p || !s0)
        return -1;
    int rc = sim_pilot_auto_set_trim_state(p->pilot, s0);
    if (rc == 0 && p->shadow)
        rc = sim_pilot_auto_set_trim_state(p->shadow, s0);
    return rc;
}

void sim_pilot_replay_destroy(sim_pilot_replay *p)
{
    if (!p)
        return;
    sim_pilot_auto_destroy(p->pilot);
    sim_pilot_auto_destroy(p->shadow);
    free(p);
}

static void add_err(sim_replay_err *e, double *sum2, double d, double t_s, double h_s)
{
    e->n++;
    *sum2 += d * d;
    e->rms_m = sqrt(*sum2 / (double)e->n);
    if (d > e->max_m || e->n == 1) {
        e->max_m = d;
        e->t_max_s = t_s;
    }
    e->duration_s += h_s;
}

/* The integrals of the errors of out from the reference now, over h:
 * clamped to their share of the reference, frozen while a control was at
 * its stop. */
static void integrate(sim_pilot_replay *p, const sim_flight_out *out, const sim_log_sample *now, double h)
{
    if (p->stop)
        return;
    double psi_ship = atan2(out->ship.C_ES[3], out->ship.C_ES[0]);
    double e_psi = core_wrap_pi(now->heading_rad - (out->euler_E_rad[2] - psi_ship));
    double lp = p->lim_pos_m * p->Ti_pos_s, lh = p->lim_hgt_m * p->Ti_hgt_s, ls = p->lim_psi_rad * p->Ti_psi_s;
    for (int k = 0; k < 2; k++)
        p->i_pos_S[k] = fmin(fmax(p->i_pos_S[k] + (now->pos_S_m[k] - out->pos_S_m[k]) * h, -lp), lp);
    if (!p->o.feed_controls) /* the heave's trim instead (sim_pilot_replay_create) */
        lh = 0.0;
    p->i_hgt = fmin(fmax(p->i_hgt + (now->pos_S_m[2] - out->pos_S_m[2]) * h, -lh), lh);
    p->i_psi = fmin(fmax(p->i_psi + e_psi * h, -ls), ls);
}

int sim_pilot_replay_step(sim_pilot_replay *p, const sim_flight_out *out, sim_flight_inputs *in)
{
    const sim_log *L = p->ref;
    const double h = 1.0 / p->o.pilot.rate_hz;
    /* the errors of the state the pilot sees, against the reference at its time */
    sim_log_sample now, ahead;
    sim_log_sample_at(L, out->t_s, &now);
    sim_replay_result *r = &p->r;
    if (out->t_s > r->t_s + 1e-9 && out->t_s <= p->t1_s + 1e-9) {
        double d2 = 0.0;
        for (int i = 0; i < 3; i++)
            d2 += (out->pos_S_m[i] - now.pos_S_m[i]) * (out->pos_S_m[i] - now.pos_S_m[i]);
        double d = sqrt(d2);
        double psi_ship = atan2(out->ship.C_ES[3], out->ship.C_ES[0]);
        double dpsi = fabs(core_wrap_pi(out->euler_E_rad[2] - psi_ship - now.heading_rad));
        r->err_m = d;
        r->max_heading_err_rad = fmax(r->max_heading_err_rad, dpsi);
        add_err(&r->all, &p->sum2[SIM_REPLAY_NPHASE], d, out->t_s, h);
        add_err(&r->phase[now.phase], &p->sum2[now.phase], d, out->t_s, h);
        r->t_s = out->t_s;
    }
    r->ended = out->t_s >= p->t1_s - 1e-9;
    /* on the deck, as the reference is: the collective down at 20 %/s,
     * cyclic and pedals held, no delay (the hand goes down, as the
     * automated pilot's after touchdown); off again when the reference
     * leaves the deck */
    if (now.on_deck && out->on_deck) {
        if (!p->deck)
            memcpy(p->deck_u, p->last_u, sizeof p->deck_u);
        p->deck = 1;
        p->deck_u[0] = fmax(p->deck_u[0] - 20.0 * h, 0.0);
        memset(in, 0, sizeof *in);
        in->ctl.collective_pct = p->deck_u[0], in->ctl.long_cyclic_pct = p->deck_u[1];
        in->ctl.lat_cyclic_pct = p->deck_u[2], in->ctl.pedal_pct = p->deck_u[3];
        memcpy(p->last_u, p->deck_u, sizeof p->last_u);
        return 0;
    }
    p->deck = 0;
    integrate(p, out, &now, h);
    /* the loops act on the error from the reference now; what is fed
     * forward is the reference's motion preview_s ahead (the pilot's
     * delay), through the velocity loop (acceleration) and the height
     * loop's rate term (the linear model's collective) */
    sim_log_sample_at(L, out->t_s + p->o.preview_s, &ahead);
    sim_pilot_ref ref;
    memset(&ref, 0, sizeof ref);
    memcpy(ref.pos_S_m, now.pos_S_m, sizeof ref.pos_S_m);
    sim_log_sample acc_ahead; /* the attitude (and so the acceleration) follows its command 1 / w_a late */
    sim_log_sample_at(L, out->t_s + p->o.preview_s + p->o.acc_lead_s, &acc_ahead);
    for (int i = 0; i < 2; i++)
        ref.vel_S_mps[i] = ahead.vel_S_mps[i] + acc_ahead.acc_S_mps2[i] / p->o.pilot.vel_bw_radps;
    ref.vel_S_mps[2] = ahead.vel_S_mps[2] + (ahead.acc_S_mps2[2] - p->Z_w * ahead.vel_S_mps[2]) / p->o.pilot.hgt_crossover_radps;
    ref.heading_rad = core_wrap_pi(ahead.heading_rad);
    ref.mode = SIM_PHASE_HOLD;
    sim_pilot_ref ref_i = ref; /* with the integrals */
    for (int k = 0; k < 2; k++)
        ref_i.pos_S_m[k] += p->i_pos_S[k] / p->Ti_pos_s;
    ref_i.pos_S_m[2] += p->i_hgt / p->Ti_hgt_s;
    ref_i.heading_rad = core_wrap_pi(ref.heading_rad + p->i_psi / p->Ti_psi_s);
    if (sim_pilot_auto_set_reference(p->pilot, &ref_i) != 0)
        return -1; /* not reached: the log's values were checked finite */
    int stop = sim_pilot_auto_step(p->pilot, out, in);
    if (p->shadow) {
        /* the same pilot on the recorded state: its command there, delayed alike */
        sim_flight_out x;
        memset(&x, 0, sizeof x);
        x.t_s = out->t_s;
        x.step = out->step;
        memcpy(x.pos_S_m, now.pos_S_m, sizeof x.pos_S_m);
        memcpy(x.vel_S_mps, now.vel_mean_S_mps, sizeof x.vel_S_mps);
        memcpy(x.euler_E_rad, now.euler_E_rad, sizeof x.euler_E_rad);
        memcpy(x.rate_B_radps, now.rate_B_radps, sizeof x.rate_B_radps);
        memcpy(x.ship.C_ES, now.C_ES, sizeof x.ship.C_ES);
        sim_flight_inputs xs;
        sim_pilot_auto_set_reference(p->shadow, &ref);
        sim_pilot_auto_step(p->shadow, &x, &xs);
        const double c[4] = {in->ctl.collective_pct, in->ctl.long_cyclic_pct, in->ctl.lat_cyclic_pct,
                             in->ctl.pedal_pct};
        const double cs[4] = {xs.ctl.collective_pct, xs.ctl.long_cyclic_pct, xs.ctl.lat_cyclic_pct, xs.ctl.pedal_pct};
        double u[4];
        for (int i = 0; i < 4; i++)
            u[i] = p->trim_pct[i] + (now.controls_pct[i] - p->ctl0_pct[i]) + (c[i] - cs[i]);
        stop = 0;
        for (int i = 0; i < 4; i++) {
            if (u[i] <= 0.0 || u[i] >= 100.0)
                stop = 1;
            u[i] = fmin(fmax(u[i], 0.0), 100.0);
        }
        in->ctl.collective_pct = u[0], in->ctl.long_cyclic_pct = u[1];
        in->ctl.lat_cyclic_pct = u[2], in->ctl.pedal_pct = u[3];
        in->hold = 0;
    }
    if (stop)
        r->stop_steps++;
    p->stop = stop;
    p->last_u[0] = in->ctl.collective_pct, p->last_u[1] = in->ctl.long_cyclic_pct;
    p->last_u[2] = in->ctl.lat_cyclic_pct, p->last_u[3] = in->ctl.pedal_pct;
    return stop;
}

void sim_pilot_replay_result(const sim_pilot_replay *p, sim_replay_result *r) { *r = p->r; }

/* ---------------------------------------------- as a sim_pilot (runner) */
static int replay_pilot_step(void *self, const sim_flight_out *out, sim_flight_inputs *in)
{
    sim_pilot_replay_step(self, out, in);
    return 0;
}

sim_pilot sim_pilot_replay_pilot(sim_pilot_replay *p)
{
    static const sim_pilot_ops ops = {"replay", replay_pilot_step};
    sim_pilot pl = {&ops, p};
    return pl;
}
