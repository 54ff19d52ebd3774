/* fly_task.c -- one task flown headless at one WOD point with one seed:
 * the flown SHOL's fly callback (shol_fly_fn, shol/flown.c), where the
 * simulation (sim/) meets the envelope's criteria (shol/).
 *
 * What is flown. The world of sim_world_build, as `disim fly` builds it:
 * the flight of sim/flight.c (trimmed hover at the task's first point,
 * or the station for a task without one; the ship-only airwake of the
 * direction scaled to the WOD speed; the field's turbulence seeded by
 * seed), the ship in the sea state of the options (sim_world_seaway), the
 * landing gear on the deck and the ship where the aircraft has one
 * (sim/contact.c: a strike or a roll-over is a crash), and the automated
 * pilot (sim/pilot_auto.c) flying the task as `disim fly --pilot auto`
 * flies it (the aircraft's SAS as its file engages it), through the one
 * runner (sim_run, sim/runner.c). The flight ends when the pilot's task
 * is done (touched down and settled on the deck, or its last hold
 * flown), at the task's length, at a crash, or at the
 * first exceedance of a rejection criterion: a flight is rejected at its
 * first exceedance, so the rest would not change the verdict. The
 * criteria judge the flight up to touchdown; on the deck the collective
 * goes down, which is not a control margin.
 *
 * How a flight is judged, in this order (the first that applies is the
 * cause): a start that does not trim ("no trim"); a crash ("crash: WHAT",
 * the gear's report, or "crash: the flight model diverged"); a rejection
 * criterion exceeded, judged on the attitudes in E and the pilot's
 * controls, the stick positions (a SAS acts in series, within its own
 * authority, and moves no stick): the steady limits on the phase's running
 * mean over o.window_s, the transient ones at each step ("roll (3 s mean)
 * in descent", "pitch (transient) in hover", "pedal at stop in hover";
 * shol_flown_track); a
 * touchdown outside the adequate limits ("touchdown sink" first, then
 * "touchdown position"); the task's adequate tolerances not met
 * ("adequate tolerance: position", height, heading, or time when none is
 * exceeded at the end but the helicopter was not within them by the
 * adequate time); a landing with no touchdown ("no touchdown"). The replay pilot's
 * flights carry their tracking error apart from the criteria (below).
 */
#include "couple.h"
#include "cfd.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

struct couple_fly_task {
    const hfm_aircraft *ac;
    sim_scenario *sc;      /* the ship and the options' sea, turbulence and station, as a scenario */
    sim_task task;
    shol_criteria crit;
    couple_fly_task_opts o;
    int has_gear;
    const core_log *log;
    char err[1024];
    couple_fly_task_last last;
    int replay;            /* the replay pilot flies o.replay (task unused) */
};

void couple_fly_task_opts_default(couple_fly_task_opts *o)
{
    memset(o, 0, sizeof *o);
    o->rate_hz = 200.0;
    o->turbulence = 1;
    sim_sea_default(&o->sea);
    o->max_s = 0.0;
    o->replay = NULL;
    o->replay_pos_m = 2.0;
    o->replay_sink_mps = 2.0;
    shol_flown_judge j;
    shol_flown_judge_default(&j);
    o->window_s = j.window_s;
    o->transient_frac = j.transient_frac;
}

couple_fly_task *couple_fly_task_create(const hfm_aircraft *ac, const core_ship *ship, const sim_task *task,
                                        const shol_criteria *crit, const couple_fly_task_opts *o,
                                        const core_log *log, core_err *err)
{
    if (!ac || !ship || !(task || (o && o->replay)) || !crit || !o) {
        core_err_set(err, -1, "fly_task: expected an aircraft, a ship, a task (or a replayed log), criteria and options");
        return NULL;
    }
    if (o->replay && !(o->replay_pos_m > 0.0 && o->replay_sink_mps > 0.0)) {
        core_err_set(err, -1, "fly_task: replay_pos_m %g, replay_sink_mps %g: expected > 0", o->replay_pos_m,
                     o->replay_sink_mps);
        return NULL;
    }
    if (!(o->rate_hz >= 10.0 && o->rate_hz <= 10000.0) || (o->turbulence != 0 && o->turbulence != 1) ||
        !(o->max_s >= 0.0) || o->sea.state < 0 || o->sea.state > SIM_SEA_MAX_STATE) {
        core_err_set(err, -1, "fly_task: rate %g Hz, turbulence %d, max_s %g s, sea state %d: expected 10 to 10000 "
                              "Hz, 0 or 1, >= 0 and 0 to %d",
                     o->rate_hz, o->turbulence, o->max_s, o->sea.state, SIM_SEA_MAX_STATE);
        return NULL;
    }
    shol_flown_judge j = {o->window_s, o->transient_frac};
    if (shol_flown_judge_check(&j, err) != 0) {
        core_err_set(err, -1, "fly_task: window_s %g s, transient_frac %g: expected 0 to 60 s and 0 to 10",
                     o->window_s, o->transient_frac);
        return NULL;
    }
    for (int i = 0; i < 3; i++)
        if (!isfinite(o->station_S_m[i])) {
            core_err_set(err, -1, "fly_task: station_S_m[%d] is not finite", i);
            return NULL;
        }
    couple_fly_task *t = calloc(1, sizeof *t);
    if (!t || !(t->sc = calloc(1, sizeof *t->sc))) {
        free(t);
        core_err_set(err, -1, "fly_task: out of memory");
        return NULL;
    }
    t->ac = ac;
    t->sc->ship = *ship;
    memcpy(t->sc->station_S_m, o->station_S_m, sizeof t->sc->station_S_m);
    t->sc->turbulence = o->turbulence;
    if (task)
        t->task = *task;
    t->replay = o->replay != NULL;
    t->crit = *crit;
    t->o = *o;
    t->log = log;
    hfm_gear g;
    t->has_gear = hfm_aircraft_gear(ac, &g) == 0 && g.nlegs >= 3;
    return t;
}

int couple_fly_task_air_at_hub(const couple_fly_task *t, const struct cfd_field *field, double *speed_frac,
                               double *ti_frac, core_err *err)
{
    const cfd_meta *m = cfd_field_meta(field);
    if (!(m->wod_speed_mps > 0.0))
        return core_err_set(err, -1, "fly_task: a field with WOD speed %g m/s: expected > 0", m->wod_speed_mps);
    hfm_geometry g;
    hfm_aircraft_geometry(t->ac, &g);
    double pos_S_m[3] = {t->o.station_S_m[0], t->o.station_S_m[1], t->o.station_S_m[2] + g.hub_B_m[2]};
    double v[CFD_NVARS];
    cfd_field_sample(field, pos_S_m, v);
    double k = v[CFD_VAR_K] > 0.0 ? v[CFD_VAR_K] : 0.0;
    *speed_frac = sqrt(v[CFD_VAR_U] * v[CFD_VAR_U] + v[CFD_VAR_V] * v[CFD_VAR_V] + v[CFD_VAR_W] * v[CFD_VAR_W]) /
                  m->wod_speed_mps;
    *ti_frac = sqrt(2.0 * k / 3.0) / m->wod_speed_mps;
    return 0;
}

int couple_fly_task_judge_recording(const couple_fly_task *t, char *cause, size_t n, double *t_s, core_err *err)
{
    if (!t->replay || !t->o.replay)
        return core_err_set(err, -1, "fly_task: no recording to judge");
    sim_log_summary info;
    sim_log_info(t->o.replay, &info);
    shol_flown_track tr;
    shol_flown_judge j = {t->o.window_s, t->o.transient_frac};
    shol_flown_track_init(&tr, &t->crit, &j);
    int exceeded = 0;
    double dt = 1.0 / t->o.rate_hz, tt = info.t0_s;
    cause[0] = '\0';
    *t_s = NAN;
    for (long i = 0; !exceeded && tt <= info.t1_s + 1e-9; i++, tt = info.t0_s + i * dt) {
        sim_log_sample sm;
        if (sim_log_sample_at(t->o.replay, tt, &sm) != 0 || sm.on_deck)
            break;
        shol_trim_point p = {sm.euler_E_rad[0], sm.euler_E_rad[1], sm.controls_pct[1],
                             sm.controls_pct[2], sm.controls_pct[0], sm.controls_pct[3]};
        exceeded = shol_flown_track_step(&tr, tt, sim_replay_phase_name(sm.phase), &p) != 0;
        if (exceeded)
            *t_s = tt;
    }
    if (!exceeded && shol_flown_track_end(&tr)) {
        exceeded = 1;
        *t_s = tt;
    }
    if (exceeded)
        shol_flown_track_cause(&tr, cause, n);
    return exceeded;
}

void couple_fly_task_destroy(couple_fly_task *t)
{
    if (t)
        free(t->sc);
    free(t);
}

const char *couple_fly_task_last_error(const couple_fly_task *t) { return t ? t->err : ""; }

void couple_fly_task_last_get(const couple_fly_task *t, couple_fly_task_last *out) { *out = t->last; }

/* The adequate tolerance most exceeded (by its ratio), "time" if none. */
static const char *tol_cause(const sim_task *task, const sim_task_result *r)
{
    const sim_task_tol *a = &task->adequate;
    double q[3] = {fmax(r->err_pos_m, r->max_err_pos_m) / a->pos_m,
                   fmax(fabs(r->err_height_m), r->max_err_height_m) / a->height_m,
                   fmax(fabs(r->err_heading_rad), r->max_err_heading_rad) / a->heading_rad};
    static const char *const name[3] = {"adequate tolerance: position", "adequate tolerance: height",
                                        "adequate tolerance: heading"};
    int k = 0;
    for (int i = 1; i < 3; i++)
        if (q[i] > q[k])
            k = i;
    return q[k] > 1.0 ? name[k] : "adequate tolerance: time";
}

static void track(shol_flown_track *tr, const sim_flight_out *o, const char *phase, int *exceeded)
{
    const hfm_controls *c = &o->ctl;
    shol_trim_point p = {o->euler_E_rad[0], o->euler_E_rad[1], c->long_cyclic_pct,
                         c->lat_cyclic_pct, c->collective_pct, c->pedal_pct};
    if (shol_flown_track_step(tr, o->t_s, phase, &p) != 0)
        *exceeded = 1;
}

/* The phase the pilot flies now, by its name in the task ("hover",
 * "descent", "traverse", ...). */
static const char *phase_name(const couple_fly_task *t, const sim_task_result *r)
{
    if (r->touched)
        return "touchdown";
    if (r->phase_now >= 0 && r->phase_now < t->task.nphases && t->task.phase[r->phase_now].name[0])
        return t->task.phase[r->phase_now].name;
    return t->task.kind == SIM_TASK_LAND ? (r->t_descent_s >= 0.0 ? "descent" : "hover") : "station keeping";
}

/* The world of one run (sim_world_build): the ship's motion in the
 * options' sea and the trimmed hover at station_S_m in field at the WOD,
 * with the options' turbulence and the gear; sas: 1 on, 0 off, -1 as the
 * aircraft file engages it. 0; 1 when the hover does not trim (a
 * rejection); < 0 with err. */
static int world_start(const couple_fly_task *t, double wod_speed_mps, double wod_dir_rad, unsigned long long seed,
                       const struct cfd_field *field, const double station_S_m[3], int sas, sim_world *w,
                       core_err *err)
{
    sim_world_overrides ov;
    sim_world_overrides_default(&ov);
    ov.rate_hz = t->o.rate_hz;
    ov.wod_speed_mps = wod_speed_mps;
    ov.wod_dir_rad = wod_dir_rad;
    ov.seed = seed;
    ov.turbulence = t->o.turbulence;
    ov.sea = &t->o.sea;
    ov.gear = t->has_gear;
    ov.sas = sas;
    ov.has_station = 1;
    memcpy(ov.station_S_m, station_S_m, sizeof ov.station_S_m);
    ov.field = field;
    if (sim_world_build(t->sc, t->ac, &ov, t->log, w, err) != 0)
        return err->code == CORE_ERR_NO_TRIM ? 1 : -1;
    return 0;
}

/* A step that ended the flight (sim_flight_step's st != 0) as the run's
 * cause, in phase: 1 (crashed), or 0 when st is 0. */
static int step_crash(int st, const sim_flight_out *o, const char *phase, char *cause, size_t n)
{
    if (st < 0)
        snprintf(cause, n, "crash: the flight model diverged in %s", phase);
    else if (st > 0 && (o->contact_flags & SIM_CONTACT_CRASH)) /* a strike on the ship */
        snprintf(cause, n, "%s%.80s", strncmp(o->contact_what, "crash", 5) ? "crash: " : "",
                 o->contact_what[0] ? o->contact_what : "a strike on the ship");
    else if (st > 0)
        snprintf(cause, n, "crash: roll-over on the deck");
    return st != 0;
}

/* The cause of a run the criteria stopped. */
static void exceeded_cause(const shol_flown_track *k, char *cause, size_t n)
{
    if (k->first_crit >= 0)
        shol_flown_track_cause(k, cause, n);
    else
        snprintf(cause, n, "crash: the state is not finite");
}

/* The runner's observer of one flight: a crash or a criterion exceeded
 * stops it (the rest would not change the verdict). */
typedef struct judge {
    const couple_fly_task *t;
    struct shol_flight *out;
    const sim_pilot_auto *pilot;    /* the automated pilot's flight: its phase */
    const sim_log *ref;      /* the replay pilot's: the reference's phase */
    int exceeded, crashed, touched; /* touched: the replay's first wheel on the deck */
    double prev_z, prev_t;          /* the replay's state before the step */
    double end_S_m[3];              /* the reference's last position */
} judge;

/* The automated pilot's flight: judged in the phase the pilot flew the
 * step in, by the criteria until the wheels touch (on the deck the
 * collective goes down, which is not a control margin). */
static int judge_auto(void *user, const sim_flight_out *o, int st, core_err *err)
{
    judge *b = user;
    (void)err;
    sim_task_result r;
    sim_pilot_auto_result(b->pilot, &r);
    const char *phase = phase_name(b->t, &r);
    if (step_crash(st, o, phase, b->out->cause, sizeof b->out->cause)) /* a strike, a roll-over */
        b->crashed = 1;
    else if (!r.touched)
        track(&b->out->track, o, phase, &b->exceeded);
    return b->crashed || b->exceeded;
}

/* The replay pilot's flight: judged in the reference's phase at the step's
 * start; the first wheel on the deck gives the touchdown's sink (relative
 * to the deck) and distance from the reference's end. */
static int judge_replay(void *user, const sim_flight_out *o, int st, core_err *err)
{
    judge *b = user;
    (void)err;
    sim_log_sample sm;
    sim_log_sample_at(b->ref, b->prev_t, &sm);
    const char *phase = sim_replay_phase_name(sm.phase);
    if (step_crash(st, o, phase, b->out->cause, sizeof b->out->cause))
        b->crashed = 1;
    else if (!b->touched && o->on_deck) {
        b->touched = 1;
        b->out->sink_mps = o->t_s > b->prev_t ? (o->pos_S_m[2] - b->prev_z) / (o->t_s - b->prev_t) : NAN;
        b->out->dist_m = hypot(o->pos_S_m[0] - b->end_S_m[0], o->pos_S_m[1] - b->end_S_m[1]);
    } else if (!b->touched)
        track(&b->out->track, o, phase, &b->exceeded);
    b->prev_z = o->pos_S_m[2];
    b->prev_t = o->t_s;
    return b->crashed || b->exceeded;
}

/* Fly pilot from o (the start) through the runner for T s, judged by b
 * (its start judged first); a phase shorter than the window exceeds at
 * the end. o is the last state. */
static void fly_judged(const couple_fly_task *t, sim_world *w, const sim_pilot *pilot, double T,
                       sim_run_observe_fn observe, judge *b, const char *phase0, sim_flight_out *o)
{
    track(&b->out->track, o, phase0, &b->exceeded);
    sim_run_opts ro;
    sim_run_opts_default(&ro);
    ro.max_steps = b->exceeded ? 0 : (long)llround(T * t->o.rate_hz);
    ro.observe = observe;
    ro.observe_user = b;
    core_err err = {0};
    (void)sim_run(w->flight, pilot, &ro, o, &err); /* the observer takes every end of the flight */
    if (!b->crashed && !b->exceeded && shol_flown_track_end(&b->out->track))
        b->exceeded = 1;
}

/* The replay pilot re-flies a recorded run (sim/pilot_replay.c) as
 * `disim fly --pilot replay` does: from the log's first state, the SAS
 * as the log says it was (off where it does not say), for the log's
 * length. Judged in the same order as a task, with the
 * recorded run as the task: a crash; a criterion exceeded before the
 * wheels touch ("CRITERION in PHASE", the reference's phase: hover,
 * translate, descend); a touchdown sink above replay_sink_mps; the flown
 * CG farther than replay_pos_m from the reference at any step ("could not
 * track": the replay's distance from its recording, not a rejection
 * criterion); no touchdown where the recorded run ended on the deck.
 * The tracking error (the distance's rms and max over the steps flown)
 * and whether it stayed within replay_pos_m are kept whatever the cause,
 * so the criteria's result and the tracking are seen apart. 0 flown, 1
 * no trim, < 0 with err. */
static int run_replay(couple_fly_task *t, double wod_speed_mps, double wod_dir_rad, unsigned long long seed,
                      const struct cfd_field *field, struct shol_flight *out, core_err *err)
{
    const sim_log *ref = t->o.replay;
    sim_log_summary info;
    sim_log_info(ref, &info);
    sim_log_sample s0, s1;
    sim_log_sample_at(ref, info.t0_s, &s0);
    sim_log_sample_at(ref, info.t1_s, &s1);
    sim_world w;
    /* the SAS as the recorded run had it (a log that does not say: off) */
    int rc = world_start(t, wod_speed_mps, wod_dir_rad, seed, field, s0.pos_S_m, info.sas > 0, &w, err);
    if (rc != 0)
        return rc;
    sim_pilot_replay_opts po;
    sim_pilot_replay_opts_default(&po);
    po.pilot.rate_hz = t->o.rate_hz;
    po.pilot.wod_speed_mps = wod_speed_mps;
    po.pilot.wod_dir_rad = wod_dir_rad;
    po.pilot.sas = sim_sas_engaged(sim_flight_sas(w.flight)); /* the gains scheduled with it */
    po.feed_controls = t->o.replay_feed_controls;
    sim_flight_inputs in;
    sim_flight_trim_inputs(w.flight, &in);
    sim_pilot_replay *p = sim_pilot_replay_create(t->ac, ref, &po, &in, t->log, err);
    if (!p) {
        sim_world_free(&w);
        return err->code == CORE_ERR_NO_TRIM ? 1 : -1;
    }
    sim_flight_out o;
    sim_flight_state(w.flight, &o);
    /* the attitudes of the flight's own trim, as disim fly --pilot replay
     * (a start the trim state refuses keeps the uniform references) */
    if (!o.on_deck)
        (void)sim_pilot_replay_set_trim_state(p, &o);
    judge b = {t, out, NULL, ref, 0, 0, 0, o.pos_S_m[2], o.t_s, {s1.pos_S_m[0], s1.pos_S_m[1], s1.pos_S_m[2]}};
    sim_log_sample sm;
    sim_log_sample_at(ref, o.t_s, &sm);
    sim_pilot pilot = sim_pilot_replay_pilot(p);
    fly_judged(t, &w, &pilot, t->o.max_s > 0.0 ? t->o.max_s : info.t1_s, judge_replay, &b,
               sim_replay_phase_name(sm.phase), &o);
    if (!b.crashed && !b.exceeded)
        sim_pilot_replay_step(p, &o, &in); /* counts the last state */
    sim_replay_result r;
    sim_pilot_replay_result(p, &r);
    out->flown_s = o.t_s;
    t->last.end = o;
    t->last.replay = r;
    if (r.all.n > 0) {
        out->track_rms_m = r.all.rms_m;
        out->track_max_m = r.all.max_m;
        out->tracked = r.all.max_m <= t->o.replay_pos_m;
    }
    if (b.crashed) {
        /* cause set by the judge */
    } else if (b.exceeded)
        exceeded_cause(&out->track, out->cause, sizeof out->cause);
    else if (b.touched && out->sink_mps > t->o.replay_sink_mps)
        snprintf(out->cause, sizeof out->cause, "touchdown sink");
    else if (r.all.max_m > t->o.replay_pos_m)
        snprintf(out->cause, sizeof out->cause, "could not track");
    else if (s1.on_deck && !b.touched)
        snprintf(out->cause, sizeof out->cause, "no touchdown");
    out->grade = out->cause[0] ? 0 : 1;
    out->pass = out->cause[0] == '\0';
    sim_pilot_replay_destroy(p);
    sim_world_free(&w);
    return 0;
}

/* The automated pilot flies the task: 0 flown, 1 no trim, < 0 with err. */
static int run_auto(couple_fly_task *t, double wod_speed_mps, double wod_dir_rad, unsigned long long seed,
                    const struct cfd_field *field, struct shol_flight *out, core_err *err)
{
    /* the start: a phase task's first point (alongside, astern), else the station */
    sim_world w;
    int rc = world_start(t, wod_speed_mps, wod_dir_rad, seed, field,
                         t->task.has_start ? t->task.start_S_m : t->o.station_S_m, -1, &w, err);
    if (rc != 0)
        return rc;
    /* the pilot as `disim fly --pilot auto` has it: the aircraft's SAS as
     * its file engages it, the gains scheduled with it; the gear */
    sim_pilot_auto_opts po;
    sim_pilot_auto_opts_default(&po);
    po.rate_hz = t->o.rate_hz;
    po.wod_speed_mps = wod_speed_mps;
    po.wod_dir_rad = wod_dir_rad;
    po.sas = sim_sas_engaged(sim_flight_sas(w.flight));
    po.gear = t->has_gear;
    sim_flight_inputs in;
    sim_flight_trim_inputs(w.flight, &in);
    sim_pilot_auto *p = sim_pilot_auto_create(t->ac, &t->task, &po, &in, t->log, err);
    if (!p) {
        sim_world_free(&w);
        return err->code == CORE_ERR_NO_TRIM ? 1 : -1;
    }
    /* the attitudes it aims at: the flight's trim in the airwake, not the
     * uniform WOD's (a start past 0.5 rad of roll or pitch keeps the
     * uniform ones: the criteria reject it at its first step) */
    sim_flight_out o;
    sim_flight_state(w.flight, &o);
    (void)sim_pilot_auto_set_trim_state(p, &o);
    sim_task_result r;
    sim_pilot_auto_result(p, &r);
    judge b = {t, out, p, NULL, 0, 0, 0, 0.0, 0.0, {0.0, 0.0, 0.0}};
    sim_pilot pilot = sim_pilot_auto_pilot(p);
    /* until the task is done (touched down and settled with the gear, or
     * the last hold flown), its length, a crash or a criterion exceeded */
    fly_judged(t, &w, &pilot, t->o.max_s > 0.0 ? t->o.max_s : sim_task_length_s(&t->task), judge_auto, &b,
               phase_name(t, &r), &o);
    if (!b.crashed && !b.exceeded)
        sim_pilot_auto_step(p, &o, &in); /* grades the last state */
    sim_pilot_auto_result(p, &r);
    out->flown_s = o.t_s;
    out->grade = r.grade;
    if (r.touched) {
        out->sink_mps = r.sink_mps;
        out->dist_m = r.dist_m;
    }
    t->last.result = r;
    t->last.end = o;
    if (b.crashed) {
        /* cause set by the judge */
    } else if (b.exceeded)
        exceeded_cause(&out->track, out->cause, sizeof out->cause);
    else if (t->task.kind == SIM_TASK_LAND && r.touched && r.touchdown_grade == 0)
        snprintf(out->cause, sizeof out->cause, "%s",
                 r.sink_mps > t->task.adequate.sink_mps ? "touchdown sink" : "touchdown position");
    else if (r.grade == 0)
        snprintf(out->cause, sizeof out->cause, "%s", tol_cause(&t->task, &r));
    else if (t->task.kind == SIM_TASK_LAND && !r.touched)
        snprintf(out->cause, sizeof out->cause, "no touchdown");
    out->pass = out->cause[0] == '\0';
    sim_pilot_auto_destroy(p);
    sim_world_free(&w);
    return 0;
}

int couple_fly_task_run(couple_fly_task *t, double wod_speed_mps, double wod_dir_rad, unsigned long long seed,
                        const struct cfd_field *field, struct shol_flight *out)
{
    memset(out, 0, sizeof *out);
    memset(&t->last, 0, sizeof t->last);
    t->err[0] = '\0';
    out->sink_mps = out->dist_m = out->track_rms_m = out->track_max_m = NAN;
    out->tracked = -1;
    shol_flown_judge j = {t->o.window_s, t->o.transient_frac};
    shol_flown_track_init(&out->track, &t->crit, &j);
    core_err err = {0};
    int rc = t->replay ? run_replay(t, wod_speed_mps, wod_dir_rad, seed, field, out, &err)
                       : run_auto(t, wod_speed_mps, wod_dir_rad, seed, field, out, &err);
    if (rc > 0)
        snprintf(out->cause, sizeof out->cause, "no trim");
    if (rc != 0)
        snprintf(t->err, sizeof t->err, "%.1000s", err.msg);
    return rc;
}

int couple_fly_task_shol(void *user, double wod_speed_mps, double wod_dir_rad, unsigned long long seed,
                         struct shol_flight *out)
{
    couple_fly_task_user *u = user;
    const struct cfd_field *f = NULL;
    if (u->field && wod_speed_mps > 0.0) { /* calm air needs no field (it scales to zero) */
        core_err err = {0};
        if (u->field(u->field_user, wod_dir_rad, &f, &err) != 0) {
            snprintf(u->task->err, sizeof u->task->err, "%.1000s", err.msg);
            return -1;
        }
    }
    return couple_fly_task_run(u->task, wod_speed_mps, wod_dir_rad, seed, f, out);
}
