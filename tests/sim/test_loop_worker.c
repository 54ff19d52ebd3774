/* test_loop_worker.c -- the flight loop's world changes on its worker
 * thread (sim/loop.c, sim/loop_worker.c), in one process over memq://,
 * with no timing in it: the test holds the worker's build at a gate of
 * its own, so what the loop does while a world is being built is seen
 * step by step.
 * - a reset asked while the build is held: the loop flies the old world
 *   on, step after step, unanswered; no build ran on the loop's thread;
 * - meanwhile a burst of resets, loads and instructor's world controls:
 *   each refused at once, "busy", counted;
 * - the gate opened: the new world swapped in between two steps (its
 *   step 1 next) and the reset answered, accepted;
 * - a broken scenario loaded: refused with the build's reason once the
 *   worker has tried it, the old world flying on (its steps not reset);
 * - the rate limit: past its burst a world change is refused with the
 *   reason and counted, and taken again once the run clock has moved;
 * - the log marks each world change where it was swapped in, and its
 *   replay (as fast as it can) flies the live run step for step, the
 *   swaps at the same steps.
 * Run from the source root. */
#include "check.h"
#include "disim_lcm.h"
#include "sim.h"

#include <lcm/lcm.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define SCEN_A "tests/sim/data/loop_a.ini"
#define SCEN_B "tests/sim/data/loop_b.ini"
#define SCEN_BAD "tests/sim/bad/bad_range.ini"

/* ---- a world (its seaway, its flight) and the gate its builds wait at */
typedef struct gworld {
    sim_scenario sc;
    hfm_aircraft *ac;
    sim_world sw;
} gworld;

typedef struct gate {
    pthread_mutex_t mu;
    pthread_cond_t cv;
    int closed;
    pthread_t main_th;   /* the test's (and the loop's) thread */
    int prepared_on_main; /* builds the loop ran on its own thread: must stay 0 */
    int prepared, built, installed, dropped; /* built: prepares returned */
    gworld w;             /* the running world */
} gate;

static int gworld_build(const char *path, const sim_loop_setup *s, gworld *w, core_err *err)
{
    memset(w, 0, sizeof *w);
    if (sim_scenario_load(path, &w->sc, err) != 0 || !(w->ac = hfm_aircraft_load(w->sc.aircraft_path, NULL, err)))
        return -1;
    sim_world_overrides ov;
    sim_world_overrides_default(&ov);
    if (s && s->sea_state >= 0)
        ov.sea_state = s->sea_state;
    if (sim_world_build(&w->sc, w->ac, &ov, NULL, &w->sw, err) != 0) {
        hfm_aircraft_destroy(w->ac);
        return -1;
    }
    return 0;
}

static void gworld_free(gworld *w)
{
    sim_world_free(&w->sw);
    hfm_aircraft_destroy(w->ac);
}

static void gworld_lw(const gworld *w, sim_loop_world *lw)
{
    memset(lw, 0, sizeof *lw);
    lw->flight = w->sw.flight;
    lw->motion = w->sw.motion;
    lw->info = w->sw.info;
    snprintf(lw->scenario, sizeof lw->scenario, "%s", w->sc.name);
}

static int g_prepare(void *user, const char *path, const sim_loop_setup *s, void **world, sim_loop_world *lw,
                     core_err *err)
{
    gate *g = user;
    pthread_mutex_lock(&g->mu);
    if (pthread_equal(pthread_self(), g->main_th))
        g->prepared_on_main++;
    while (g->closed)
        pthread_cond_wait(&g->cv, &g->mu);
    g->prepared++;
    pthread_mutex_unlock(&g->mu);
    gworld *nw = malloc(sizeof *nw);
    int rc = 0;
    if (!nw || gworld_build(path, s, nw, err) != 0) {
        free(nw);
        rc = -1;
    } else {
        gworld_lw(nw, lw);
        *world = nw;
    }
    pthread_mutex_lock(&g->mu);
    g->built++;
    pthread_cond_broadcast(&g->cv);
    pthread_mutex_unlock(&g->mu);
    return rc;
}

/* Until n prepares have returned (the worker's build done: what is left
 * of its job is the hand-over). */
static void wait_built(gate *g, int n)
{
    pthread_mutex_lock(&g->mu);
    while (g->built < n)
        pthread_cond_wait(&g->cv, &g->mu);
    pthread_mutex_unlock(&g->mu);
}

static void *g_install(void *user, void *world)
{
    gate *g = user;
    gworld *nw = world, old = g->w;
    g->w = *nw;
    *nw = old;
    g->installed++;
    return nw;
}

static void g_drop(void *user, void *world)
{
    gate *g = user;
    gworld_free(world);
    free(world);
    pthread_mutex_lock(&g->mu);
    g->dropped++;
    pthread_mutex_unlock(&g->mu);
}

static int g_build(void *user, const char *path, sim_loop_world *lw, core_err *err)
{
    (void)user, (void)path, (void)lw;
    return core_err_set(err, -1, "the test builds on the worker only");
}

static void gate_set(gate *g, int closed)
{
    pthread_mutex_lock(&g->mu);
    g->closed = closed;
    pthread_cond_broadcast(&g->cv);
    pthread_mutex_unlock(&g->mu);
}

/* ---- LCM: controls sent, the statuses seen */
typedef struct seen {
    disim_sim_status_t last; /* its scalar fields */
    char scenario[64], message[256], control_message[256];
    int answers; /* statuses answering a control other than the one before */
} seen;

static void on_status(const lcm_recv_buf_t *rb, const char *ch, const disim_sim_status_t *m, void *u)
{
    (void)rb, (void)ch;
    seen *s = u;
    if (m->control_seq != s->last.control_seq)
        s->answers++;
    s->last = *m;
    snprintf(s->scenario, sizeof s->scenario, "%s", m->scenario);
    snprintf(s->message, sizeof s->message, "%s", m->message);
    snprintf(s->control_message, sizeof s->control_message, "%s", m->control_message);
}

static long long send_ctl(lcm_t *lc, int cmd, const char *path, int sea)
{
    static long long seq = 5000; /* the test's own count */
    disim_sim_control_t c;
    memset(&c, 0, sizeof c);
    c.seq = ++seq;
    c.command = (int8_t)cmd;
    c.scenario_path = (char *)(path ? path : "");
    c.name = (char *)"";
    c.sea_state = (int8_t)sea;
    disim_sim_control_t_publish(lc, DISIM_CH_SIM_CONTROL, &c);
    return c.seq;
}

typedef struct run {
    sim_flight_out *out;
    int n, cap;
} run;

static int iter(sim_loop *l, lcm_t *lc, run *r, sim_flight_out *out)
{
    core_err err = {0};
    int rc = sim_loop_iterate(l, out, &err);
    if (rc < 0)
        fprintf(stderr, "iterate: %s\n", err.msg);
    while (lcm_handle_timeout(lc, 0) > 0)
        ;
    if (rc == SIM_LOOP_STEPPED) {
        if (r->n == r->cap) {
            int cap = r->cap ? 2 * r->cap : 4096;
            sim_flight_out *p = realloc(r->out, (size_t)cap * sizeof *p);
            if (!p)
                return -1;
            r->out = p;
            r->cap = cap;
        }
        r->out[r->n++] = *out;
    }
    return rc;
}

/* Once the worker has built its nth world: passes until the control seq
 * is answered (the hand-over left; at most max): 1 answered. */
static int until_answered(sim_loop *l, lcm_t *lc, seen *s, gate *g, int n, run *r, long long seq, int max,
                          sim_flight_out *out)
{
    if (iter(l, lc, r, out) != SIM_LOOP_STEPPED)
        return 0;
    if (s->last.control_seq == seq) { /* answered at once: refused before any build */
        fprintf(stderr, "control %lld answered at once: %s\n", seq, s->control_message);
        return 1;
    }
    wait_built(g, n);
    for (int k = 0; k < max; k++) {
        if (s->last.control_seq == seq)
            return 1;
        if (iter(l, lc, r, out) != SIM_LOOP_STEPPED)
            return 0;
    }
    return s->last.control_seq == seq;
}

static void live_reset(sim_loop *l, lcm_t *lc, seen *s, gate *g, run *r)
{
    sim_flight_out out;
    sim_loop_report rep;
    for (int k = 0; k < 20; k++)
        CHECK(iter(l, lc, r, &out) == SIM_LOOP_STEPPED);
    gate_set(g, 1);
    long long seq = send_ctl(lc, DISIM_SIM_CONTROL_T_RESET, NULL, 0);
    long step = out.step;
    /* the build held: the old world flies on, step after step, unanswered */
    for (int k = 1; k <= 50; k++) {
        CHECK(iter(l, lc, r, &out) == SIM_LOOP_STEPPED && out.step == step + k);
        CHECK(s->last.control_seq != seq);
    }
    sim_loop_report_get(l, &rep);
    CHECK(rep.change_pending == 1 && rep.builds_in_step == 0 && rep.builds_on_worker == 0);
    /* a burst meanwhile: each refused at once, busy */
    long long last = 0;
    int a0 = s->answers;
    for (int k = 0; k < 30; k++) {
        int cmd = k % 3 == 0 ? DISIM_SIM_CONTROL_T_RESET : k % 3 == 1 ? DISIM_SIM_CONTROL_T_LOAD_SCENARIO
                                                                      : DISIM_SIM_CONTROL_T_SET_SEA;
        last = send_ctl(lc, cmd, SCEN_B, 3);
    }
    CHECK(iter(l, lc, r, &out) == SIM_LOOP_STEPPED && out.step == step + 51);
    sim_loop_report_get(l, &rep);
    CHECK(rep.refused_busy == 30 && rep.control_refused == 30 && rep.refused_rate == 0);
    CHECK(s->last.control_seq == last && s->last.control_result == DISIM_SIM_STATUS_T_CONTROL_REFUSED);
    CHECK(s->answers - a0 == 30); /* each answered */
    CHECK(strstr(s->control_message, "set sea refused: busy: a world change (reset) is being prepared") != NULL);
    printf("test_loop_worker: while a reset is built: '%s'\n", s->control_message);
    /* 30 refused on arrival (an unknown command): answered one by one, 16
     * before the pass's last one (the rest of a flood counted, not echoed) */
    a0 = s->answers;
    for (int k = 0; k < 30; k++)
        last = send_ctl(lc, 99, NULL, 0);
    CHECK(iter(l, lc, r, &out) == SIM_LOOP_STEPPED && out.step == step + 52);
    CHECK(s->answers - a0 == 17 && s->last.control_seq == last);
    printf("test_loop_worker: 30 refused on arrival in one pass, %d answers published\n", s->answers - a0);
    sim_loop_report_get(l, &rep);
    CHECK(rep.control_refused == 60);
    /* the gate opened: swapped in between two steps, answered */
    gate_set(g, 0);
    CHECK(until_answered(l, lc, s, g, 1, r, seq, 1000000, &out));
    CHECK(s->last.control_result == DISIM_SIM_STATUS_T_CONTROL_ACCEPTED && strstr(s->control_message, "reset: loop_a"));
    CHECK(iter(l, lc, r, &out) == SIM_LOOP_STEPPED);
    CHECK(out.step >= 1 && out.step < step); /* the new world's steps */
    sim_loop_report_get(l, &rep);
    CHECK(rep.change_pending == 0 && rep.builds_in_step == 0 && rep.builds_on_worker == 1);
    CHECK(g->prepared == 1 && g->installed == 1 && g->prepared_on_main == 0);
    printf("test_loop_worker: reset answered: '%s'\n", s->control_message);
}

static void live_failure_and_rate(sim_loop *l, lcm_t *lc, seen *s, gate *g, run *r)
{
    sim_flight_out out;
    sim_loop_report rep;
    /* a broken scenario: refused with the build's reason, the old world flying on */
    CHECK(iter(l, lc, r, &out) == SIM_LOOP_STEPPED);
    long step = out.step;
    long long seq = send_ctl(lc, DISIM_SIM_CONTROL_T_LOAD_SCENARIO, SCEN_BAD, 0);
    CHECK(until_answered(l, lc, s, g, 2, r, seq, 1000000, &out));
    CHECK(s->last.control_result == DISIM_SIM_STATUS_T_CONTROL_REFUSED && strstr(s->control_message, "load refused") &&
          strstr(s->control_message, "bad_range.ini") && !strcmp(s->scenario, "loop_a"));
    CHECK(iter(l, lc, r, &out) == SIM_LOOP_STEPPED && out.step > step);
    printf("test_loop_worker: a broken scenario: '%s'\n", s->control_message);
    /* the rate limit (3 at once, one more every 1000 s): the third change taken, the fourth refused */
    seq = send_ctl(lc, DISIM_SIM_CONTROL_T_LOAD_SCENARIO, SCEN_B, 0);
    CHECK(until_answered(l, lc, s, g, 3, r, seq, 1000000, &out));
    CHECK(s->last.control_result == DISIM_SIM_STATUS_T_CONTROL_ACCEPTED);
    CHECK(iter(l, lc, r, &out) == SIM_LOOP_STEPPED && !strcmp(s->scenario, "loop_b"));
    seq = send_ctl(lc, DISIM_SIM_CONTROL_T_RESET, NULL, 0);
    CHECK(iter(l, lc, r, &out) == SIM_LOOP_STEPPED);
    CHECK(s->last.control_seq == seq && s->last.control_result == DISIM_SIM_STATUS_T_CONTROL_REFUSED &&
          strstr(s->control_message, "reset refused: rate limit: at most 3 world changes at once"));
    sim_loop_report_get(l, &rep);
    CHECK(rep.refused_rate == 1 && rep.change_pending == 0);
    printf("test_loop_worker: past the rate limit: '%s'\n", s->control_message);
    for (int k = 0; k < 10; k++)
        CHECK(iter(l, lc, r, &out) == SIM_LOOP_STEPPED);
    sim_loop_report_get(l, &rep);
    CHECK(rep.builds_in_step == 0 && rep.builds_on_worker == 3 && g->prepared_on_main == 0);
}

static sim_loop *loop_new(gate *g, const char *log, const char *replay, double duration_s, core_err *err)
{
    sim_loop_world lw;
    if (gworld_build(SCEN_A, NULL, &g->w, err) != 0)
        return NULL;
    gworld_lw(&g->w, &lw);
    sim_loop_opts o;
    sim_loop_opts_default(&o);
    o.realtime = 0;
    o.duration_s = duration_s;
    o.lcm = 1;
    o.lcm_url = "memq://";
    o.scenario_path = SCEN_A;
    o.log_path = log;
    o.replay_path = replay;
    o.builder.prepare = g_prepare;
    o.builder.install = g_install;
    o.builder.drop = g_drop;
    o.swap = SIM_LOOP_SWAP_READY; /* as in real time: the swap where the build ends */
    o.change_burst = 3;
    o.change_interval_s = 1000.0; /* no change regained in the test's run, however long its builds take */
    return sim_loop_create(&o, &lw, g_build, g, NULL, err);
}

static void gate_init(gate *g)
{
    memset(g, 0, sizeof *g);
    pthread_mutex_init(&g->mu, NULL);
    pthread_cond_init(&g->cv, NULL);
    g->main_th = pthread_self();
}

static void gate_fini(gate *g)
{
    gworld_free(&g->w);
    pthread_cond_destroy(&g->cv);
    pthread_mutex_destroy(&g->mu);
}

static int same_out(const sim_flight_out *a, const sim_flight_out *b)
{
    return a->step == b->step && a->t_s == b->t_s && !memcmp(a->pos_E_m, b->pos_E_m, sizeof a->pos_E_m) &&
           !memcmp(a->vel_E_mps, b->vel_E_mps, sizeof a->vel_E_mps) &&
           !memcmp(a->euler_E_rad, b->euler_E_rad, sizeof a->euler_E_rad) &&
           !memcmp(a->pos_S_m, b->pos_S_m, sizeof a->pos_S_m);
}

static void test_worker(void)
{
    static run live, again;
    char log[64];
    snprintf(log, sizeof log, "/tmp/test_loop_worker_%d.lcm", (int)getpid());
    gate g;
    gate_init(&g);
    core_err err = {0};
    sim_loop *l = loop_new(&g, log, NULL, 1000.0, &err);
    CHECK(l != NULL);
    if (!l) {
        fprintf(stderr, "loop: %s\n", err.msg);
        gate_fini(&g);
        return;
    }
    lcm_t *lc = sim_loop_lcm(l);
    seen s;
    memset(&s, 0, sizeof s);
    disim_sim_status_t_subscription_t *ss = disim_sim_status_t_subscribe(lc, DISIM_CH_SIM_STATUS, on_status, &s);
    live_reset(l, lc, &s, &g, &live);
    live_failure_and_rate(l, lc, &s, &g, &live);
    sim_loop_report rep;
    sim_loop_report_get(l, &rep);
    double run_s = rep.run_s;
    CHECK(sim_loop_finish(l, &err) == 0);
    disim_sim_status_t_unsubscribe(lc, ss);
    sim_loop_destroy(l);
    CHECK(g.dropped == 2); /* the worlds swapped out: the first, the reset's (the broken load built none) */
    gate_fini(&g);
    /* the log: the inputs and a mark at each world change */
    sim_log_frames fr;
    CHECK(sim_log_check_frames(log, &fr, &err) == 0 && fr.n_marks == 3);
    /* its replay, as fast as it can: the same steps, the swaps where they were */
    gate_init(&g);
    l = loop_new(&g, NULL, log, run_s, &err);
    CHECK(l != NULL);
    if (l) {
        sim_flight_out out;
        int rc;
        while ((rc = iter(l, sim_loop_lcm(l), &again, &out)) == SIM_LOOP_STEPPED)
            ;
        CHECK(rc == SIM_LOOP_DONE && again.n == live.n);
        int same = 1;
        for (int k = 0; k < live.n && k < again.n; k++)
            if (!same_out(&live.out[k], &again.out[k])) {
                fprintf(stderr, "replay: step %d differs (step %ld vs %ld)\n", k, live.out[k].step,
                        again.out[k].step);
                same = 0;
                break;
            }
        CHECK(same);
        sim_loop_report_get(l, &rep);
        CHECK(rep.builds_on_worker == 3 && rep.builds_in_step == 0 && rep.refused_busy == 30 &&
              rep.refused_rate == 1);
        printf("test_loop_worker: the replay flew the live run's %d steps step for step, %lld world changes "
               "where the log marks them\n", again.n, rep.builds_on_worker);
        sim_loop_destroy(l);
    }
    gate_fini(&g);
    free(live.out);
    free(again.out);
    unlink(log);
}

/* The rate limit regained over the run clock: one change at once, one
 * more every 0.5 s; swapped at the end of the asking pass (no timing). A
 * frozen flight is not held by it. */
static void test_rate(void)
{
    gate g;
    gate_init(&g);
    core_err err = {0};
    sim_loop_world lw;
    if (gworld_build(SCEN_A, NULL, &g.w, &err) != 0) {
        CHECK(0);
        return;
    }
    gworld_lw(&g.w, &lw);
    sim_loop_opts o;
    sim_loop_opts_default(&o);
    o.realtime = 0;
    o.duration_s = 1000.0;
    o.lcm = 1;
    o.lcm_url = "memq://";
    o.scenario_path = SCEN_A;
    o.builder.prepare = g_prepare;
    o.builder.install = g_install;
    o.builder.drop = g_drop;
    o.change_burst = 1;
    o.change_interval_s = 0.5;
    sim_loop *l = sim_loop_create(&o, &lw, g_build, &g, NULL, &err);
    CHECK(l != NULL);
    if (!l) {
        gate_fini(&g);
        return;
    }
    lcm_t *lc = sim_loop_lcm(l);
    seen s;
    memset(&s, 0, sizeof s);
    disim_sim_status_t_subscription_t *ss = disim_sim_status_t_subscribe(lc, DISIM_CH_SIM_STATUS, on_status, &s);
    run r = {0};
    sim_flight_out out;
    int A = DISIM_SIM_STATUS_T_CONTROL_ACCEPTED, R = DISIM_SIM_STATUS_T_CONTROL_REFUSED;
    long long seq = send_ctl(lc, DISIM_SIM_CONTROL_T_RESET, NULL, 0);
    CHECK(iter(l, lc, &r, &out) == SIM_LOOP_STEPPED && s.last.control_seq == seq && s.last.control_result == A);
    seq = send_ctl(lc, DISIM_SIM_CONTROL_T_RESET, NULL, 0);
    CHECK(iter(l, lc, &r, &out) == SIM_LOOP_STEPPED && s.last.control_seq == seq && s.last.control_result == R);
    CHECK(strstr(s.control_message, "rate limit: at most 1 world changes at once and one more every 0.5 s of run "
                                     "time: the next in 0.49 s") != NULL);
    printf("test_loop_worker: %s\n", s.control_message);
    for (int k = 0; k < 100; k++)
        CHECK(iter(l, lc, &r, &out) == SIM_LOOP_STEPPED);
    seq = send_ctl(lc, DISIM_SIM_CONTROL_T_RESET, NULL, 0);
    CHECK(iter(l, lc, &r, &out) == SIM_LOOP_STEPPED && s.last.control_seq == seq && s.last.control_result == A);
    sim_loop_report rep;
    sim_loop_report_get(l, &rep);
    CHECK(rep.refused_rate == 1 && rep.builds_on_worker == 2 && rep.builds_in_step == 0 && g.prepared_on_main == 0);
    /* the budget spent, the flight frozen: its run clock stands still, so
     * the limit (which guards a flight's steps) does not hold a frozen or
     * ended flight: a reset is taken at once, and again */
    seq = send_ctl(lc, DISIM_SIM_CONTROL_T_PAUSE, NULL, 0);
    iter(l, lc, &r, &out);
    CHECK(s.last.control_seq == seq && s.last.control_result == A);
    for (int k = 0; k < 2; k++) {
        seq = send_ctl(lc, DISIM_SIM_CONTROL_T_RESET, NULL, 0);
        iter(l, lc, &r, &out);
        CHECK(s.last.control_seq == seq && s.last.control_result == A);
    }
    sim_loop_report_get(l, &rep);
    CHECK(rep.refused_rate == 1 && rep.builds_on_worker == 4);
    disim_sim_status_t_unsubscribe(lc, ss);
    sim_loop_destroy(l);
    gate_fini(&g);
    free(r.out);
}

int main(void)
{
    test_worker();
    test_rate();
    printf("test_loop_worker: %d checks, %d failed\n", check_count, check_failures);
    return check_failures != 0;
}
