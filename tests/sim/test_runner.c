/* test_runner.c -- the one runner (sim/runner.c) on stub pilots, wraps and
 * observers, no flight: each end it says (the length, the pilot done, the
 * flight ended or failed, the observer's stop, the stop flag, the wrap's
 * own length), what the pilot sees (the last output, the start's first),
 * that a pass the wrap skips neither asks the pilot nor counts as a step,
 * and that the observer sees every step with its status. */
#include "check.h"
#include "sim.h"

#include <string.h>

typedef struct stub {
    long done_after;   /* the pilot is done at its call done_after + 1 (< 0: never) */
    long calls;        /* the pilot's calls */
    long seen_step;    /* the step of the output the pilot saw last */
    int seen_ok;       /* every output the pilot saw was the last step's */
    long steps;        /* the wrap's steps */
    long end_at, fail_at; /* the wrap's step that ends (> 0) or fails (< 0) the flight (0: none) */
    long skip_every;   /* the wrap's before skips every so many passes (0: none) */
    long passes;
    long length;       /* the wrap's own length (0: none) */
    long observed, stop_at;
    int last_st;
    volatile sig_atomic_t stop;
    long stop_flag_at; /* the observer sets the stop flag at this step (0: never) */
} stub;

static int pilot_step(void *self, const sim_flight_out *out, sim_flight_inputs *in)
{
    stub *s = self;
    if (out->step != s->steps)
        s->seen_ok = 0;
    s->seen_step = out->step;
    memset(in, 0, sizeof *in);
    in->ctl.collective_pct = 50.0;
    s->calls++;
    return s->done_after >= 0 && s->calls > s->done_after ? 1 : 0;
}

static int wrap_before(void *user, core_err *err)
{
    stub *s = user;
    (void)err;
    if (s->length && s->steps >= s->length)
        return SIM_RUN_LENGTH;
    s->passes++;
    return s->skip_every && s->passes % s->skip_every == 0 ? SIM_RUN_SKIPPED : SIM_RUN_STEPPED;
}

static int wrap_step(void *user, const sim_flight_inputs *in, sim_flight_out *out, core_err *err)
{
    stub *s = user;
    if (in->ctl.collective_pct != 50.0)
        return core_err_set(err, -1, "not the pilot's inputs");
    s->steps++;
    out->step = s->steps;
    out->t_s = (double)s->steps / 100.0;
    if (s->steps == s->fail_at)
        return core_err_set(err, -1, "failed");
    if (s->steps == s->end_at)
        return core_err_set(err, 1, "crash: a strike");
    return 0;
}

static int observe(void *user, const sim_flight_out *out, int st, core_err *err)
{
    stub *s = user;
    (void)err;
    s->observed++;
    s->last_st = st;
    if (out->step == s->stop_flag_at)
        s->stop = 1;
    return s->stop_at && out->step == s->stop_at ? 1 : 0;
}

/* One run on a fresh stub s (its settings given), max_steps, the observer
 * on or off: the end. */
static int run(stub *s, long max_steps, int observed)
{
    s->seen_ok = 1;
    static const sim_pilot_ops ops = {"stub", pilot_step};
    sim_pilot p = {&ops, s};
    sim_run_opts o;
    sim_run_opts_default(&o);
    CHECK(o.max_steps < 0 && !o.stop && !o.observe && !o.wrap.step);
    o.max_steps = max_steps;
    o.stop = &s->stop;
    o.wrap.before = wrap_before;
    o.wrap.step = wrap_step;
    o.wrap.user = s;
    if (observed) {
        o.observe = observe;
        o.observe_user = s;
    }
    sim_flight_out out;
    memset(&out, 0, sizeof out);
    core_err err = {0};
    return sim_run(NULL, &p, &o, &out, &err);
}

int main(void)
{
    stub s;
    /* the length: max_steps steps, the pilot asked before each, the observer after each */
    memset(&s, 0, sizeof s), s.done_after = -1;
    CHECK(run(&s, 10, 1) == SIM_RUN_LENGTH);
    CHECK(s.steps == 10 && s.calls == 10 && s.observed == 10 && s.seen_ok && s.seen_step == 9);
    CHECK(s.last_st == 0);
    /* max_steps 0: nothing flown */
    memset(&s, 0, sizeof s), s.done_after = -1;
    CHECK(run(&s, 0, 1) == SIM_RUN_LENGTH && s.steps == 0 && s.calls == 0);
    /* the pilot done: at its 4th call, before the 4th step */
    memset(&s, 0, sizeof s), s.done_after = 3;
    CHECK(run(&s, 10, 1) == SIM_RUN_PILOT_DONE);
    CHECK(s.steps == 3 && s.calls == 4 && s.observed == 3);
    /* the flight ended at step 5: the observer sees it with st > 0 */
    memset(&s, 0, sizeof s), s.done_after = -1, s.end_at = 5;
    CHECK(run(&s, 10, 1) == SIM_RUN_ENDED);
    CHECK(s.steps == 5 && s.observed == 5 && s.last_st > 0);
    /* the flight failed at step 2: < 0, seen by the observer */
    memset(&s, 0, sizeof s), s.done_after = -1, s.fail_at = 2;
    CHECK(run(&s, 10, 1) < 0 && s.steps == 2 && s.last_st < 0);
    /* without an observer the same ends */
    memset(&s, 0, sizeof s), s.done_after = -1, s.end_at = 4;
    CHECK(run(&s, 10, 0) == SIM_RUN_ENDED && s.steps == 4 && s.observed == 0);
    /* the observer's stop at step 6, before the flight would end at 8 */
    memset(&s, 0, sizeof s), s.done_after = -1, s.stop_at = 6, s.end_at = 8;
    CHECK(run(&s, 10, 1) == SIM_RUN_OBSERVED && s.steps == 6);
    /* the stop flag set at step 3: checked before the next pass */
    memset(&s, 0, sizeof s), s.done_after = -1, s.stop_flag_at = 3;
    CHECK(run(&s, -1, 1) == SIM_RUN_STOPPED && s.steps == 3 && s.calls == 3);
    /* skipped passes (every 3rd): the pilot not asked, the step not counted */
    memset(&s, 0, sizeof s), s.done_after = -1, s.skip_every = 3;
    CHECK(run(&s, 10, 1) == SIM_RUN_LENGTH);
    CHECK(s.steps == 10 && s.calls == 10 && s.observed == 10 && s.passes == 14 && s.seen_ok);
    /* the wrap's own length (no max_steps) */
    memset(&s, 0, sizeof s), s.done_after = -1, s.length = 7;
    CHECK(run(&s, -1, 1) == SIM_RUN_LENGTH && s.steps == 7);
    /* one pass at a time: a step, then the pilot done */
    memset(&s, 0, sizeof s), s.done_after = 1, s.seen_ok = 1;
    static const sim_pilot_ops ops = {"stub", pilot_step};
    sim_pilot p = {&ops, &s};
    sim_run_opts o;
    sim_run_opts_default(&o);
    o.wrap.before = wrap_before;
    o.wrap.step = wrap_step;
    o.wrap.user = &s;
    sim_flight_out out;
    memset(&out, 0, sizeof out);
    core_err err = {0};
    CHECK(sim_run_pass(NULL, &p, &o, &out, &err) == SIM_RUN_STEPPED && out.step == 1);
    CHECK(sim_run_pass(NULL, &p, &o, &out, &err) == SIM_RUN_PILOT_DONE && out.step == 1 && s.steps == 1);
    return check_done("test_runner");
}
