/* runner.c -- the one loop that flies a pilot in a flight (sim_run): every
 * flight of disim flies through it, `disim fly` in every mode, the flown
 * SHOL's flights (couple/fly_task.c) and the real-time loop (sim/loop.c).
 *
 * One pass (sim_run_pass):
 *   1. the wrap's before, where there is one, says whether the flight
 *      steps this pass (the real-time loop takes the messages received,
 *      carries out the controls and stays put while paused) or has flown
 *      its length;
 *   2. the pilot takes the last output (the state after the last step,
 *      the start's before the first) and gives the next step's inputs, or
 *      says it is done: then nothing steps;
 *   3. the flight steps (sim_flight_step, or the wrap's step, which does
 *      it with the publishing and the pacing around it);
 *   4. the observer, where there is one, sees the output and the step's
 *      status (it writes rows, polls for a field, judges the flight) and
 *      may stop the run; a step that ended or failed the flight ends it.
 * sim_run passes until one of those ends, max_steps stepped or the stop
 * flag set (checked before each pass), and says which. What the pilot
 * gets after the end is the caller's (the last state's grading). */
#include "sim.h"

#include <string.h>

int sim_pilot_step(const sim_pilot *p, const sim_flight_out *out, sim_flight_inputs *in)
{
    return p->ops->step(p->self, out, in);
}

void sim_run_opts_default(sim_run_opts *o)
{
    memset(o, 0, sizeof *o);
    o->max_steps = -1;
}

int sim_run_pass(sim_flight *fl, const sim_pilot *p, const sim_run_opts *o, sim_flight_out *out, core_err *err)
{
    if (o->wrap.before) {
        int b = o->wrap.before(o->wrap.user, err);
        if (b != SIM_RUN_STEPPED)
            return b;
    }
    sim_flight_inputs in;
    int pr = sim_pilot_step(p, out, &in);
    if (pr > 0)
        return SIM_RUN_PILOT_DONE;
    if (pr < 0)
        return core_err_set(err, -1, "the %s pilot failed at %.3f s", p->ops->kind, out->t_s);
    int st = o->wrap.step ? o->wrap.step(o->wrap.user, &in, out, err) : sim_flight_step(fl, &in, out, err);
    if (o->observe) {
        int ob = o->observe(o->observe_user, out, st, err);
        if (ob < 0)
            return -1;
        if (ob > 0)
            return SIM_RUN_OBSERVED;
    }
    if (st < 0)
        return -1;
    return st > 0 ? SIM_RUN_ENDED : SIM_RUN_STEPPED;
}

int sim_run(sim_flight *fl, const sim_pilot *p, const sim_run_opts *o, sim_flight_out *out, core_err *err)
{
    long steps = 0;
    while (o->max_steps < 0 || steps < o->max_steps) {
        if (o->stop && *o->stop)
            return SIM_RUN_STOPPED;
        int r = sim_run_pass(fl, p, o, out, err);
        if (r == SIM_RUN_STEPPED)
            steps++;
        else if (r != SIM_RUN_SKIPPED)
            return r;
    }
    return SIM_RUN_LENGTH;
}
