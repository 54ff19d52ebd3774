/* fuzz_sim_control.c -- libFuzzer harness of the loop's sim_control_t
 * handling: one loop (sim_loop, over memq://, not paced, the instructor's
 * controls on, a flight that ends waiting for the instructor) flying the
 * test scenario tests/sim/data/loop_a.ini (run from the source root) is
 * made once; each input is published whole as one buffer on
 * DISIM_SIM_CONTROL, as any host could send it, and the loop passes once
 * (it takes the buffer: disim_lcm_upgrade, disim_lcm_check_raw, the
 * decoder, disim_lcm_check_sim_control, and carries out what is taken:
 * pause, resume, reset, a scenario load of whatever path came, the
 * instructor's resets, reposition, conditions, snapshots, restores).
 * Then a RESUME, and a RESET when the flight has stopped, are sent and
 * the loop must step again.
 * Checked, beyond no crash, hang, leak or sanitizer report: after any
 * control the loop keeps stepping (never an error, never done), its
 * counts never fall, and the buffer was either answered or refused. */
#include "disim_lcm.h"
#include "hfm.h"
#include "sim.h"

#include <lcm/lcm.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerInitialize(int *argc, char ***argv);

#define SCENARIO "tests/sim/data/loop_a.ini"

/* the world the loop flies, built again by its controls */
typedef struct world {
    sim_scenario sc;
    hfm_aircraft *ac;
    sim_world sw;
} world;

static world W;
static sim_loop *L;
static lcm_t *LC;
static long long own_seq = 1LL << 40; /* the harness's own controls */

static int rebuild(void *user, const char *path, const sim_loop_setup *s, sim_loop_world *lw, core_err *err)
{
    world *w = user, nw;
    memset(&nw, 0, sizeof nw);
    if (sim_scenario_load(path, &nw.sc, err) != 0 || !(nw.ac = hfm_aircraft_load(nw.sc.aircraft_path, NULL, err)))
        return -1;
    sim_world_overrides ov;
    sim_world_overrides_default(&ov);
    if (s) {
        if (s->start >= 0)
            ov.start = s->start;
        ov.start_heading_rad = s->heading_rad;
        if (!isnan(s->wod_speed_mps)) {
            ov.wod_speed_mps = s->wod_speed_mps;
            ov.wod_dir_rad = s->wod_dir_rad;
        }
        if (s->sea_state >= 0)
            ov.sea_state = s->sea_state;
        if (s->turbulence >= 0)
            ov.turbulence = s->turbulence;
        if (s->has_station) {
            ov.has_station = 1;
            memcpy(ov.station_S_m, s->station_S_m, sizeof ov.station_S_m);
        }
    }
    if (sim_world_build(&nw.sc, nw.ac, &ov, NULL, &nw.sw, err) != 0) {
        hfm_aircraft_destroy(nw.ac);
        return -1;
    }
    sim_world_free(&w->sw);
    hfm_aircraft_destroy(w->ac);
    *w = nw;
    memset(lw, 0, sizeof *lw);
    lw->flight = w->sw.flight;
    lw->motion = w->sw.motion;
    lw->info = w->sw.info;
    snprintf(lw->scenario, sizeof lw->scenario, "%s", w->sc.name);
    return 0;
}

static int build(void *user, const char *path, sim_loop_world *lw, core_err *err)
{
    return rebuild(user, path, NULL, lw, err);
}

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc, (void)argv;
    core_err err = {0};
    sim_loop_world lw;
    if (build(&W, SCENARIO, &lw, &err) != 0) {
        fprintf(stderr, "fuzz_sim_control: %s (run from the source root)\n", err.msg);
        exit(1);
    }
    sim_loop_opts o;
    sim_loop_opts_default(&o);
    o.realtime = 0;
    o.duration_s = 1e9;
    o.lcm = 1;
    o.lcm_url = "memq://";
    o.scenario_path = SCENARIO;
    o.rebuild = rebuild;
    o.wait_after_end = 1;
    o.snapshot_max_s = 10.0; /* a restore flies at most 10 s again */
    L = sim_loop_create(&o, &lw, build, &W, NULL, &err);
    if (!L || !(LC = sim_loop_lcm(L))) {
        fprintf(stderr, "fuzz_sim_control: the loop: %s\n", err.msg);
        exit(1);
    }
    return 0;
}

static void send(int command)
{
    disim_sim_control_t c;
    memset(&c, 0, sizeof c);
    c.seq = own_seq++;
    c.command = (int8_t)command;
    c.scenario_path = (char *)"";
    c.name = (char *)"";
    disim_sim_control_t_publish(LC, DISIM_CH_SIM_CONTROL, &c);
}

static int pass(void)
{
    core_err err = {0};
    sim_flight_out out;
    int r = sim_loop_iterate(L, &out, &err);
    if (r < 0 || r == SIM_LOOP_DONE) {
        fprintf(stderr, "fuzz_sim_control: the loop ended (%d): %s\n", r, err.msg);
        abort();
    }
    return r;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size > 65536)
        return 0;
    sim_loop_report before, after;
    sim_loop_report_get(L, &before);
    lcm_publish(LC, DISIM_CH_SIM_CONTROL, data, (unsigned)size);
    pass();
    sim_loop_report_get(L, &after);
    if (after.received != before.received + 1 || after.control_refused < before.control_refused)
        abort(); /* the buffer was not taken in, or a count fell */
    /* back to flying: resumed, and built again when the flight has ended */
    send(DISIM_SIM_CONTROL_T_RESUME);
    if (pass() != SIM_LOOP_STEPPED) {
        send(DISIM_SIM_CONTROL_T_RESET);
        pass();
    }
    if (pass() != SIM_LOOP_STEPPED) {
        fprintf(stderr, "fuzz_sim_control: the loop does not step after a resume and a reset\n");
        abort();
    }
    return 0;
}
