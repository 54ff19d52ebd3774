/*
 * test_fly_task.c -- one task flown for the flown SHOL (couple/fly_task.c):
 * the UH-60A's landing on the CG-47's spot in the free stream (no field:
 * small and fast), judged as shol/flown.c judges a point. Each case
 * changes one thing the verdict depends on and checks the cause named:
 * a calm landing passes; a criterion no trim can meet fails at the first
 * step of the hover with window 0, once the hover has lasted the window
 * on its running mean, and at once as a transient limit; a sink limit below the descent rate fails at the
 * touchdown; a start too far from the spot for the adequate time fails
 * the adequate position tolerance; station keeping that runs into the
 * hangar face is a crash naming what hit what; a wind no hover trims in
 * is "no trim"; the seeds of the sea state change the flight and the same
 * seed gives the same one; the replay pilot re-flies a recorded hover and
 * is judged the same way.
 */
#include "check.h"
#include "couple.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define AC "scenarios/aircraft/uh60a.ini"
#define SHIP "scenarios/ships/cg47.ini"
#define LAND "scenarios/tasks/land_uh60a.ini"

static const hfm_aircraft *ac;
static core_ship ship;
static shol_criteria crit;

/* window_s < 0: the default judgement (a 3 s mean) */
static int fly_w(const sim_task *task, const shol_criteria *c, const double station[3], int sea_state, double v_mps,
                 double dir_rad, unsigned long long seed, double window_s, shol_flight *out, couple_fly_task_last *last)
{
    couple_fly_task_opts o;
    couple_fly_task_opts_default(&o);
    o.sea.state = sea_state;
    if (window_s >= 0)
        o.window_s = window_s;
    memcpy(o.station_S_m, station, sizeof o.station_S_m);
    core_err err = {0};
    couple_fly_task *t = couple_fly_task_create(ac, &ship, task, c, &o, NULL, &err);
    if (!t) {
        fprintf(stderr, "fly_task_create: %s\n", err.msg);
        return -9;
    }
    int rc = couple_fly_task_run(t, v_mps, dir_rad, seed, NULL, out);
    if (rc != 0)
        printf("  (run %d: %s)\n", rc, couple_fly_task_last_error(t));
    if (last)
        couple_fly_task_last_get(t, last);
    couple_fly_task_destroy(t);
    return rc;
}

static int fly(const sim_task *task, const shol_criteria *c, const double station[3], int sea_state, double v_mps,
               double dir_rad, unsigned long long seed, shol_flight *out, couple_fly_task_last *last)
{
    return fly_w(task, c, station, sea_state, v_mps, dir_rad, seed, -1.0, out, last);
}

static void show(const char *what, int rc, const shol_flight *f)
{
    printf("%s: rc %d, %s%s%s, %.2f s flown, sink %.3f m/s, %.3f m from the spot, grade %d, %ld steps judged\n", what,
           rc, f->pass ? "pass" : "fail", f->pass ? "" : ": ", f->cause, f->flown_s, f->sink_mps, f->dist_m, f->grade,
           f->track.n_steps);
}

/* A task file written beside the test from the landing task with one
 * section's keys replaced. */
static int write_task(const char *path, const char *type, const char *target, const char *desired,
                      const char *adequate)
{
    FILE *f = fopen(path, "w");
    if (!f)
        return -1;
    fprintf(f, "[task]\ntype = %s\ntarget_S_m = %s\nheading_deg = 0\nduration_s = 10\n", type, target);
    if (!strcmp(type, "land"))
        fprintf(f, "touchdown_height_m = 2.22\ndescent_mps = 0.5\n");
    fprintf(f, "\n[desired]\n%s\n\n[adequate]\n%s\n", desired, adequate);
    return fclose(f);
}

/* A 5 s hover at the spot in calm air, the trim held, recorded by the
 * loop as `disim fly --fast --log` records it: the replay pilot's run. */
static int no_build(void *user, const char *path, sim_loop_world *w, core_err *err)
{
    (void)user, (void)path, (void)w;
    return core_err_set(err, -1, "not in this test");
}

static int record_hover(const char *log_path)
{
    core_err err = {0};
    sim_flight_opts fo;
    sim_flight_opts_default(&fo);
    fo.turbulence = 0;
    fo.station_S_m[2] = -6.0;
    sim_sea sea;
    sim_sea_default(&sea);
    sim_ship_motion *m = sim_ship_motion_create(&ship, &sea, 2, &err);
    sim_flight *fl = m ? sim_flight_create(ac, &ship, &fo, sim_ship_motion_frame_fn, m, NULL, NULL, &err) : NULL;
    if (!fl) {
        fprintf(stderr, "record: %s\n", err.msg);
        sim_ship_motion_destroy(m);
        return -1;
    }
    sim_loop_opts lo;
    sim_loop_opts_default(&lo);
    lo.realtime = 0;
    lo.lcm = 0;
    lo.duration_s = 5.0;
    lo.log_path = log_path;
    lo.scenario_path = "scenarios/cg47_uh60a.ini";
    sim_loop_world lw;
    memset(&lw, 0, sizeof lw);
    lw.flight = fl;
    lw.motion = m;
    snprintf(lw.scenario, sizeof lw.scenario, "hover");
    sim_loop *l = sim_loop_create(&lo, &lw, no_build, NULL, NULL, &err);
    int rc = l ? 0 : -1;
    sim_flight_out o;
    while (rc == 0) {
        int r = sim_loop_iterate(l, &o, &err);
        if (r == SIM_LOOP_DONE)
            break;
        if (r < 0)
            rc = -1;
    }
    if (rc == 0 && sim_loop_finish(l, &err) != 0)
        rc = -1;
    if (rc)
        fprintf(stderr, "record: %s\n", err.msg);
    sim_loop_destroy(l);
    sim_flight_destroy(fl);
    sim_ship_motion_destroy(m);
    return rc;
}

/* The trimmed hover's pitch in calm air with the CG at station (NAN if it does not trim). */
static double hover_pitch(const double station[3])
{
    core_err err = {0};
    sim_flight_opts fo;
    sim_flight_opts_default(&fo);
    fo.turbulence = 0;
    memcpy(fo.station_S_m, station, sizeof fo.station_S_m);
    sim_sea sea;
    sim_sea_default(&sea);
    sim_ship_motion *m = sim_ship_motion_create(&ship, &sea, 2, &err);
    sim_flight *fl = m ? sim_flight_create(ac, &ship, &fo, sim_ship_motion_frame_fn, m, NULL, NULL, &err) : NULL;
    double th = NAN;
    if (fl) {
        sim_flight_out o;
        sim_flight_state(fl, &o);
        th = o.euler_E_rad[1];
    } else
        fprintf(stderr, "hover_pitch: %s\n", err.msg);
    sim_flight_destroy(fl);
    sim_ship_motion_destroy(m);
    return th;
}

static int replay(const sim_log *ref, const shol_criteria *c, double pos_m, double v_mps, int sea_state,
                  shol_flight *out)
{
    couple_fly_task_opts o;
    couple_fly_task_opts_default(&o); /* the default judgement: a 3 s mean */
    o.sea.state = sea_state;
    o.replay = ref;
    o.replay_pos_m = pos_m;
    core_err err = {0};
    couple_fly_task *t = couple_fly_task_create(ac, &ship, NULL, c, &o, NULL, &err);
    if (!t) {
        fprintf(stderr, "fly_task_create: %s\n", err.msg);
        return -9;
    }
    int rc = couple_fly_task_run(t, v_mps, 0.0, 1, NULL, out);
    couple_fly_task_destroy(t);
    return rc;
}

int main(void)
{
    setvbuf(stdout, NULL, _IOLBF, 0);
    core_err err = {0};
    hfm_aircraft *a = hfm_aircraft_load(AC, NULL, &err);
    CHECK(a != NULL);
    if (!a) {
        fprintf(stderr, "%s\n", err.msg);
        return check_done("test_fly_task");
    }
    ac = a;
    CHECK(core_ship_load(SHIP, &ship, &err) == 0);
    CHECK(shol_criteria_load(AC, &crit, &err) == 0);
    sim_task land;
    CHECK(sim_task_load(LAND, &land, &err) == 0);
    const double spot[3] = {0, 0, -6};

    /* 1. Calm air, calm sea: the landing passes, touchdown on the spot. */
    shol_flight f;
    couple_fly_task_last last;
    int rc = fly(&land, &crit, spot, 0, 0.0, 0.0, 1, &f, &last);
    show("calm", rc, &f);
    CHECK(rc == 0 && f.pass && f.cause[0] == '\0');
    CHECK(last.result.touched && f.sink_mps > 0 && f.sink_mps <= land.adequate.sink_mps);
    CHECK(f.dist_m <= land.adequate.pos_m);
    CHECK(f.track.first_crit == SHOL_LIMIT_NONE && f.track.n_bad == 0);
    /* every step judged up to the touchdown (then the collective goes down
     * and the gear settles on the deck) */
    CHECK(labs(f.track.n_steps - (lround(last.result.t_touchdown_s * 200.0) + 1)) <= 1);
    CHECK(last.result.t_touchdown_s > 10.0 && f.flown_s >= last.result.t_touchdown_s);
    for (int i = 0; i < SHOL_NCRIT; i++)
        CHECK(f.track.min_frac[i] > 0 && f.track.min_frac[i] <= 1);
    shol_flight f1 = f;
    couple_fly_task_last last1 = last;

    /* 2. A pitch limit below the hover's trimmed pitch: with window 0 the
     * first step; with the default 3 s mean once the hover has lasted
     * 3 s, named so. */
    shol_criteria tight = crit;
    double th0 = hover_pitch(spot);
    tight.pitch_max_rad = 0.8 * fabs(th0); /* the transient limit, 1.2 times the trim, holds it */
    printf("  the hover's trim pitch %.3f deg, the limit %.3f deg\n", th0 / CORE_DEG_TO_RAD,
           tight.pitch_max_rad / CORE_DEG_TO_RAD);
    CHECK(fabs(th0) > 1.0 * CORE_DEG_TO_RAD);
    rc = fly_w(&land, &tight, spot, 0, 0.0, 0.0, 1, 0.0, &f, NULL);
    show("pitch limit below the trim, window 0", rc, &f);
    CHECK(rc == 0 && !f.pass && strcmp(f.cause, "pitch in hover") == 0);
    CHECK(f.track.first_crit == SHOL_CRIT_PITCH && f.track.first_t_s < 0.1);
    CHECK(f.flown_s < 0.1); /* the flight stops at its first exceedance */
    rc = fly(&land, &tight, spot, 0, 0.0, 0.0, 1, &f, NULL);
    show("pitch limit below the trim, 3 s mean", rc, &f);
    CHECK(rc == 0 && !f.pass && strcmp(f.cause, "pitch (3 s mean) in hover") == 0);
    CHECK(f.track.first_kind == SHOL_JUDGE_MEAN && fabs(f.track.first_t_s - 3.0) < 0.01 && f.flown_s < 3.01);
    /* the same limit as a transient one (1 + 0 times it): at once */
    {
        couple_fly_task_opts o;
        couple_fly_task_opts_default(&o);
        o.transient_frac = 0.0;
        memcpy(o.station_S_m, spot, sizeof o.station_S_m);
        couple_fly_task *t = couple_fly_task_create(ac, &ship, &land, &tight, &o, NULL, &err);
        CHECK(t != NULL);
        rc = t ? couple_fly_task_run(t, 0.0, 0.0, 1, NULL, &f) : -9;
        if (t && rc != 0)
            printf("  (run %d: %s)\n", rc, couple_fly_task_last_error(t));
        show("pitch limit below the trim, transient at the limit", rc, &f);
        CHECK(rc == 0 && !f.pass && strcmp(f.cause, "pitch (transient) in hover") == 0 && f.flown_s < 0.1);
        couple_fly_task_destroy(t);
    }

    /* 2b. Mid-flight: the criterion whose worst margin came latest in the
     * calm landing, its limit set just inside that worst value, is
     * exceeded there, not at the start, and named with its phase. */
    int late = -1;
    for (int i = 0; i < SHOL_NCRIT; i++)
        if (f1.track.min_t_s[i] > 1.0 && (late < 0 || f1.track.min_t_s[i] > f1.track.min_t_s[late]))
            late = i;
    CHECK(late >= 0);
    if (late >= 0) {
        shol_criteria mid = crit;
        double *lims[SHOL_NCRIT] = {&mid.roll_max_rad, &mid.pitch_max_rad, &mid.long_cyclic_pct,
                                    &mid.lat_cyclic_pct, &mid.collective_pct, &mid.pedal_pct};
        /* the limit that puts the worst value 1 % of the half-band outside */
        double band = late < 2 ? *lims[late] : *lims[late] - 50.0;
        double worst = band * (1.0 - f1.track.min_frac[late]); /* |angle| or |c - 50| there */
        *lims[late] = (late < 2 ? 0.0 : 50.0) + worst - 0.01 * band;
        rc = fly_w(&land, &mid, spot, 0, 0.0, 0.0, 1, 0.0, &f, NULL); /* the step's values */
        show("a limit just inside the calm landing's worst, window 0", rc, &f);
        char want[64];
        snprintf(want, sizeof want, "%s in %s", shol_limit_name(late),
                 f1.track.min_t_s[late] >= last1.result.t_descent_s ? "descent" : "hover");
        printf("  worst %s at %.2f s (descent from %.2f s): expected '%s'\n", shol_limit_name(late),
               f1.track.min_t_s[late], last1.result.t_descent_s, want);
        CHECK(rc == 0 && !f.pass && strcmp(f.cause, want) == 0);
        CHECK(f.track.first_t_s > 0.5 && f.track.first_t_s <= f1.track.min_t_s[late] + 1e-9);
    }

    /* 3. A sink limit below the descent's 0.5 m/s: the touchdown. */
    char path[] = "/tmp/disim_test_fly_task_XXXXXX";
    int fd = mkstemp(path);
    CHECK(fd >= 0);
    if (fd >= 0)
        close(fd);
    sim_task t3;
    CHECK(write_task(path, "land", "0,0,-6", "pos_m = 1\nheight_m = 1\nheading_deg = 5\ntime_s = 15\nsink_mps = 0.1",
                     "pos_m = 2\nheight_m = 2\nheading_deg = 10\ntime_s = 20\nsink_mps = 0.2") == 0);
    CHECK(sim_task_load(path, &t3, &err) == 0);
    rc = fly(&t3, &crit, spot, 0, 0.0, 0.0, 1, &f, NULL);
    show("sink limit 0.2 m/s", rc, &f);
    CHECK(rc == 0 && !f.pass && strcmp(f.cause, "touchdown sink") == 0 && f.sink_mps > 0.2);

    /* 4. 12 m to starboard of the spot with 1 s to be within 2 m: the
     * adequate position tolerance; the descent never starts. */
    CHECK(write_task(path, "land", "0,0,-6", "pos_m = 1\nheight_m = 1\nheading_deg = 5\ntime_s = 0.5\nsink_mps = 1",
                     "pos_m = 2\nheight_m = 2\nheading_deg = 10\ntime_s = 1\nsink_mps = 2") == 0);
    CHECK(sim_task_load(path, &t3, &err) == 0);
    const double off[3] = {0, 12, -6};
    shol_criteria loose = {90 * CORE_DEG_TO_RAD, 90 * CORE_DEG_TO_RAD, 100, 100, 100, 100}; /* none can be exceeded */
    rc = fly(&t3, &loose, off, 0, 0.0, 0.0, 1, &f, &last);
    show("12 m off, 1 s", rc, &f);
    CHECK(rc == 0 && !f.pass && strcmp(f.cause, "adequate tolerance: position") == 0);
    CHECK(last.result.grade == 0);

    /* 5. Station keeping 4 m ahead of the spot, 5 m above the deck: the
     * rotor's tip (8.7 m ahead of the CG) is then past the hangar face
     * (10 m ahead of the spot, 7 m high), and on the way the aircraft
     * strikes it: a crash in flight, naming what hit what. */
    CHECK(write_task(path, "station_keep", "4,0,-5", "pos_m = 1\nheight_m = 1\nheading_deg = 5\ntime_s = 15",
                     "pos_m = 2\nheight_m = 2\nheading_deg = 10\ntime_s = 20") == 0);
    CHECK(sim_task_load(path, &t3, &err) == 0);
    const double low[3] = {0, 0, -5};
    rc = fly(&t3, &loose, low, 0, 0.0, 0.0, 1, &f, NULL);
    show("4 m ahead, 5 m up", rc, &f);
    CHECK(rc == 0 && !f.pass && !strncmp(f.cause, "crash: ", 7) && strstr(f.cause, " hit hangar") && f.flown_s > 1.0);
    unlink(path);

    /* 6. 100 m/s (194 kt) from green 90: no hover trims in it. */
    rc = fly(&land, &loose, spot, 0, 100.0, 90 * CORE_DEG_TO_RAD, 1, &f, NULL);
    show("100 m/s from green 90", rc, &f);
    CHECK(rc == 1 && !f.pass && strcmp(f.cause, "no trim") == 0);

    /* 7. Sea state 4: the seed moves the deck, the same seed repeats. */
    shol_flight s1, s1b, s2;
    int r1 = fly(&land, &crit, spot, 4, 0.0, 0.0, 1, &s1, NULL), r1b = fly(&land, &crit, spot, 4, 0.0, 0.0, 1, &s1b, NULL),
        r2 = fly(&land, &crit, spot, 4, 0.0, 0.0, 2, &s2, NULL);
    show("sea state 4, seed 1", r1, &s1);
    show("sea state 4, seed 2", r2, &s2);
    CHECK(r1 == 0 && r1b == 0 && r2 == 0);
    CHECK(s1.flown_s == s1b.flown_s && s1.sink_mps == s1b.sink_mps && !strcmp(s1.cause, s1b.cause));
    CHECK(s1.flown_s != s2.flown_s || s1.sink_mps != s2.sink_mps);

    /* 8. The replay pilot re-flies a recorded 5 s hover: in calm air it
     * passes, flying the log's 5 s; with 1 mm allowed from the recorded
     * run, in 5 m/s over a ship in sea state 3 (the reference moves with
     * the deck; the pilot's references are the flight's trim, so the wind
     * alone would leave it on the reference), it could not track (its tracking error, not a criterion); with a pitch limit below the
     * hover's trim it fails at once, in the reference's hover phase. */
    char logp[] = "/tmp/disim_test_fly_task_log_XXXXXX";
    int lfd = mkstemp(logp);
    CHECK(lfd >= 0);
    if (lfd >= 0)
        close(lfd);
    CHECK(record_hover(logp) == 0);
    sim_log *ref = sim_log_load(logp, &err);
    CHECK(ref != NULL);
    if (ref) {
        shol_flight rp;
        rc = replay(ref, &crit, 2.0, 0.0, 0, &rp);
        show("replay, calm", rc, &rp);
        CHECK(rc == 0 && rp.pass && fabs(rp.flown_s - 5.0) < 0.01 && rp.track.n_steps > 900);
        /* the tracking error kept beside the criteria: within the 2 m */
        CHECK(rp.tracked == 1 && isfinite(rp.track_rms_m) && rp.track_rms_m <= rp.track_max_m && rp.track_max_m <= 2.0);
        rc = replay(ref, &crit, 0.001, 5.0, 3, &rp);
        show("replay, 5 m/s, sea state 3, 1 mm allowed", rc, &rp);
        CHECK(rc == 0 && !rp.pass && strcmp(rp.cause, "could not track") == 0);
        CHECK(rp.tracked == 0 && rp.track_max_m > 0.001 && rp.track_rms_m > 0.0 && rp.track_rms_m <= rp.track_max_m);
        rc = replay(ref, &tight, 2.0, 0.0, 0, &rp);
        show("replay, pitch limit below the trim", rc, &rp);
        CHECK(rc == 0 && !rp.pass && strcmp(rp.cause, "pitch (3 s mean) in hover") == 0 &&
              fabs(rp.flown_s - 3.0) < 0.01);
        /* a criterion failed it: its tracking still reported, apart */
        CHECK(rp.tracked == 1 && isfinite(rp.track_max_m));
        sim_log_destroy(ref);
    }
    unlink(logp);

    /* bad options */
    couple_fly_task_opts o;
    couple_fly_task_opts_default(&o);
    o.rate_hz = 1;
    CHECK(couple_fly_task_create(ac, &ship, &land, &crit, &o, NULL, &err) == NULL && strstr(err.msg, "rate"));
    couple_fly_task_opts_default(&o);
    o.window_s = -1;
    CHECK(couple_fly_task_create(ac, &ship, &land, &crit, &o, NULL, &err) == NULL && strstr(err.msg, "window_s"));
    hfm_aircraft_destroy(a);
    return check_done("test_fly_task");
}
