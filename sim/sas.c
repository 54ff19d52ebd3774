/* sas.c -- the aircraft's stability augmentation: rate damping and
 * attitude hold per axis, with limited authority, between the pilot's
 * controls and the rotor.
 *
 * Model. Per axis i (roll: lateral cyclic, pitch: longitudinal cyclic,
 * yaw: pedals) the SAS adds to the pilot's control
 *     d_i = clamp(-(K_rate,i w_i + K_att,i e_i), -A_i, +A_i)   (% of travel)
 * with w = (p, q, r) the body rates and e the attitude error: roll phi,
 * pitch theta and heading psi (3-2-1, Earth frame E) less the hold's
 * reference, heading wrapped to (-pi, pi]. The control senses of
 * docs/conventions.md make one sign right for every aircraft: right lateral
 * stick rolls right (p > 0), aft longitudinal stick (a higher percentage)
 * pitches the nose up (q > 0), right pedal yaws right (r > 0); so positive
 * gains oppose the motion. The rotor sees clamp(pilot + d, 0, 100).
 * This is the proportional rate and attitude feedback of a stability and
 * control augmentation system (Padfield, "Helicopter Flight Dynamics", 2nd
 * ed., 2007: ch. 4 for the hover's unstable pitch and roll oscillations,
 * the "hovering cubic", which attitude feedback stabilises, and ch. 6 for
 * limited-authority augmentation). On one axis with the rotor
 * quasi-steady, the attitude theta obeys theta'' = M_q theta' + M_c d
 * (M_q the rate damping, M_c the control derivative per percent), so with
 * d = -(K_q theta' + K_theta theta)
 *     theta'' + (M_c K_q - M_q) theta' + M_c K_theta theta = 0:
 * the rate gain adds M_c K_q to the damping and the attitude gain gives
 * the frequency sqrt(M_c K_theta). The aircraft files choose their gains
 * with it (the [sas] sections of scenarios/aircraft/uh60a.ini
 * and sa365n.ini).
 *
 * The UH-60A's automatic flight control (Howlett, NASA CR-166309, 1981,
 * the GenHel report, which models its SAS and its flight path
 * stabilisation, FPS) has two SAS channels of series actuators, which move
 * the controls without moving the sticks, each with 5 % of travel, 10 %
 * with both engaged (a US Navy avionics training manual on the
 * H-60's automatic flight control, "Stability Augmentation System (SAS)",
 * navyaviation.tpub.com/14009, for its SAS 1 and SAS 2), giving rate damping in pitch,
 * roll and yaw; the FPS holds attitude and heading through the same series
 * actuators and through parallel trim actuators, which move the sticks
 * with full authority at a limited rate.
 *
 * Simplified here: one channel per axis (SAS 1 and SAS 2 as one, their
 * authorities summed); the rate signals unfiltered (no sensor lag or
 * washout), sensors and actuators ideal (the SAS acts within the step);
 * the FPS's attitude and heading hold in the same limited authority (no
 * trim actuators: a long-term trim change is the pilot's); no collective
 * or height channel (the UH-60A's SAS has none); no airspeed hold or turn
 * coordination. The hold's reference is the attitude at engagement or
 * reset, taken anew on an axis while the pilot's control of that axis is
 * more than detent_pct from where it was when the reference was last
 * taken (the stick out of its detent, as the FPS's trim release), so a
 * pilot who moves the stick flies a new attitude and the hold keeps it.
 *
 * Discrete: evaluated once per step from the body state at the step's
 * start, held over the step (a zero-order hold, as a digital SAS); no
 * clock; the same states give the same commands.
 */
#include "sim.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

struct sim_sas {
    hfm_sas_gains g;
    int engaged;
    int sync;                /* take the references at the next step */
    double ref_rad[3];       /* phi, theta, psi the hold keeps */
    double pilot_ref_pct[3]; /* lat, long, pedal when the references were taken */
    sim_sas_out last;
};

/* The pilot's control of axis i (roll, pitch, yaw) and its slot in hfm_controls. */
static double *axis_ctl(hfm_controls *u, int i)
{
    return i == 0 ? &u->lat_cyclic_pct : i == 1 ? &u->long_cyclic_pct : &u->pedal_pct;
}
static double axis_ctl_c(const hfm_controls *u, int i)
{
    return i == 0 ? u->lat_cyclic_pct : i == 1 ? u->long_cyclic_pct : u->pedal_pct;
}

sim_sas *sim_sas_create(const hfm_sas_gains *g, core_err *err)
{
    static const char *const ax[3] = {"roll", "pitch", "yaw"};
    if (!g) {
        core_err_set(err, -1, "sas: expected gains");
        return NULL;
    }
    for (int i = 0; i < 3; i++)
        if (!isfinite(g->rate_pct_per_radps[i]) || !isfinite(g->att_pct_per_rad[i]) ||
            !(g->authority_pct[i] >= 0.0 && g->authority_pct[i] <= 100.0)) {
            core_err_set(err, -1, "sas: %s axis: expected finite gains and an authority of 0 to 100 %% of travel",
                         ax[i]);
            return NULL;
        }
    if (!(g->detent_pct >= 0.0 && g->detent_pct <= 100.0) || (g->engaged != 0 && g->engaged != 1)) {
        core_err_set(err, -1, "sas: expected a detent of 0 to 100 %% of travel and engaged 0 or 1");
        return NULL;
    }
    sim_sas *s = calloc(1, sizeof *s);
    if (!s) {
        core_err_set(err, -1, "sas: out of memory");
        return NULL;
    }
    s->g = *g;
    s->engaged = g->engaged;
    s->sync = 1;
    return s;
}

void sim_sas_destroy(sim_sas *s) { free(s); }

void sim_sas_set_engaged(sim_sas *s, int on)
{
    on = on != 0;
    if (on && !s->engaged)
        s->sync = 1; /* engaging holds the attitude of that moment */
    s->engaged = on;
}

int sim_sas_engaged(const sim_sas *s) { return s->engaged; }

void sim_sas_gains(const sim_sas *s, hfm_sas_gains *g) { *g = s->g; }

void sim_sas_step(sim_sas *s, const hfm_body *b, const hfm_controls *pilot, hfm_controls *rotor)
{
    *rotor = *pilot;
    memset(&s->last, 0, sizeof s->last);
    s->last.engaged = s->engaged;
    if (s->engaged) {
        for (int i = 0; i < 3; i++) {
            double up = axis_ctl_c(pilot, i);
            if (s->sync || fabs(up - s->pilot_ref_pct[i]) > s->g.detent_pct) {
                s->ref_rad[i] = b->euler_rad[i];
                s->pilot_ref_pct[i] = up;
            }
            double e = b->euler_rad[i] - s->ref_rad[i];
            if (i == 2)
                e = core_wrap_pi(e);
            double d = -(s->g.rate_pct_per_radps[i] * b->rate_B_radps[i] + s->g.att_pct_per_rad[i] * e);
            double A = s->g.authority_pct[i];
            if (d > A || d < -A) {
                d = d > A ? A : -A;
                s->last.saturated[i] = 1;
            }
            if (!isfinite(d)) /* a state that is not finite: no command */
                d = 0.0;
            s->last.delta_pct[i] = d;
            s->last.att_err_rad[i] = e;
            *axis_ctl(rotor, i) = up + d;
        }
        s->sync = 0;
    }
    rotor->collective_pct = fmin(fmax(rotor->collective_pct, 0.0), 100.0);
    for (int i = 0; i < 3; i++) {
        double *c = axis_ctl(rotor, i);
        *c = fmin(fmax(*c, 0.0), 100.0);
    }
}

void sim_sas_last(const sim_sas *s, sim_sas_out *out) { *out = s->last; }
