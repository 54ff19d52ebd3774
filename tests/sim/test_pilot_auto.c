/* test_pilot_auto.c -- the automated pilot (sim/pilot_auto.c, issue 26):
 * the station-keeping task of scenarios/tasks/station_keep.ini flown by
 * the UH-60A and the SA365N over the CG-47's spot through the flight API
 * at 200 Hz
 * (sim_flight_create / sim_flight_step, the flight's SAS off, no
 * turbulence, the free stream: no field). From a trimmed hover 3 m to
 * starboard of and 2 m above the target, the pilot must bring the
 * helicopter within the desired tolerances (1 m, 1 m height, 5 deg
 * heading) by 15 s and keep it there for 60 s, in calm air and in a 20 kt
 * head wind, with every control inside its travel. With the pilot's
 * delay raised past what the attitude loops tolerate (1.5 s; the loop's
 * limit is pi / (2 w_c) = 0.63 s at the 2.5 rad/s crossover) the task is
 * not met, and the delays between are flown and printed to show the
 * margin (at least 0.35 s must still meet the desired band).
 * The same run twice gives bit-identical states and controls. The task
 * file's errors name the file, line and key. Run from the source root. */
#include "check.h"
#include "hfm.h"
#include "sim.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define UH60 "scenarios/aircraft/uh60a.ini"
#define SA365 "scenarios/aircraft/sa365n.ini"
#define SHIP "scenarios/ships/cg47.ini"
#define TASK "scenarios/tasks/station_keep.ini"
#define LAND "scenarios/tasks/land_uh60a.ini"
#define RATE_HZ 200.0
#define KT 0.514444

typedef struct run {
    sim_task_result r;
    sim_pilot_gains g; /* the pilot's schedule */
    uint64_t hash;     /* FNV-1a over every step's state and controls */
    int failed;        /* set-up or integrator failure */
    double t_end_s;
} run;

static uint64_t fnv(uint64_t h, const void *p, size_t n)
{
    const unsigned char *b = p;
    for (size_t i = 0; i < n; i++)
        h = (h ^ b[i]) * 1099511628211ull;
    return h;
}

/* Fly the task from the hover at start_S_m in wod_kt head wind with the
 * pilot's delay delay_s; stop early once the helicopter is 30 m or 45 deg
 * of attitude away (the loop has diverged). */
static void fly(const hfm_aircraft *ac, const core_ship *ship, const sim_task *task, const double start_S_m[3],
                double wod_kt, double delay_s, run *out)
{
    memset(out, 0, sizeof *out);
    sim_flight_opts fo;
    sim_flight_opts_default(&fo);
    fo.rate_hz = RATE_HZ;
    fo.turbulence = 0;
    fo.sas = 0;
    fo.wod_speed_mps = wod_kt * KT;
    memcpy(fo.station_S_m, start_S_m, sizeof fo.station_S_m);
    core_err err = {{0}};
    sim_flight *f = sim_flight_create(ac, ship, &fo, NULL, NULL, NULL, NULL, &err);
    if (!f) {
        fprintf(stderr, "flight: %s\n", err.msg);
        out->failed = 1;
        return;
    }
    sim_pilot_auto_opts po;
    sim_pilot_auto_opts_default(&po);
    po.rate_hz = RATE_HZ;
    po.delay_s = delay_s;
    po.wod_speed_mps = wod_kt * KT;
    sim_flight_inputs in;
    sim_flight_trim_inputs(f, &in);
    sim_pilot_auto *p = sim_pilot_auto_create(ac, task, &po, &in, NULL, &err);
    if (!p) {
        fprintf(stderr, "pilot: %s\n", err.msg);
        sim_flight_destroy(f);
        out->failed = 1;
        return;
    }
    sim_pilot_auto_gains(p, &out->g);
    sim_flight_out o;
    sim_flight_state(f, &o);
    uint64_t h = 1469598103934665603ull;
    long n = (long)(sim_task_length_s(task) * RATE_HZ + 0.5);
    for (long s = 0; s < n; s++) {
        sim_pilot_auto_step(p, &o, &in);
        if (sim_flight_step(f, &in, &o, &err) != 0) {
            fprintf(stderr, "step %ld: %s\n", s, err.msg);
            out->failed = 1;
            break;
        }
        h = fnv(h, o.pos_E_m, sizeof o.pos_E_m);
        h = fnv(h, o.euler_E_rad, sizeof o.euler_E_rad);
        h = fnv(h, &in, sizeof in.collective_pct * 4);
        sim_task_result tr;
        sim_pilot_auto_result(p, &tr);
        if (tr.touched) /* a landing ends at touchdown */
            break;
        double d = hypot(o.pos_S_m[0] - task->target_S_m[0], o.pos_S_m[1] - task->target_S_m[1]);
        if (d > 30.0 || fabs(o.euler_E_rad[0]) > 0.785 || fabs(o.euler_E_rad[1]) > 0.785)
            break;
    }
    sim_pilot_auto_step(p, &o, &in); /* grades the last state */
    sim_pilot_auto_result(p, &out->r);
    out->hash = h;
    out->t_end_s = o.t_s;
    sim_pilot_auto_destroy(p);
    sim_flight_destroy(f);
}

static const char *grade_name(int g) { return g == 2 ? "desired" : g == 1 ? "adequate" : "not met"; }

static void print_run(const char *what, const run *r)
{
    printf("%s: %s, within desired since %.2f s, adequate since %.2f s (to %.1f s); after 15 s largest error "
           "%.3f m, height %.3f m, heading %.3f deg; controls collective %.1f-%.1f, long %.1f-%.1f, lat %.1f-%.1f, "
           "pedal %.1f-%.1f %%, %ld steps at a stop\n",
           what, grade_name(r->r.grade), r->r.t_desired_s, r->r.t_adequate_s, r->t_end_s, r->r.max_err_pos_m,
           r->r.max_err_height_m, r->r.max_err_heading_rad * CORE_RAD_TO_DEG, r->r.min_pct[0], r->r.max_pct[0],
           r->r.min_pct[1], r->r.max_pct[1], r->r.min_pct[2], r->r.max_pct[2], r->r.min_pct[3], r->r.max_pct[3],
           r->r.stop_steps);
}

/* 1-2. Station keeping in calm air and in a 20 kt head wind. */
static void test_station_keep(const hfm_aircraft *ac, const core_ship *ship, const sim_task *t,
                              const double start[3], uint64_t *hash_calm)
{
    const double wod_kt[2] = {0.0, 20.0};
    for (int k = 0; k < 2; k++) {
        run r;
        fly(ac, ship, t, start, wod_kt[k], 0.25, &r);
        char what[96];
        snprintf(what, sizeof what, "%s, %.0f kt head wind, delay 0.25 s", hfm_aircraft_name(ac), wod_kt[k]);
        print_run(what, &r);
        printf("  scheduled from the linear model (per s, per %% of travel): L_p %.3f L_lat %.4f, M_q %.3f M_long %.4f, "
               "N_r %.3f N_ped %.4f, Z_w %.3f Z_col %.4f, X_u %.3f X_theta %.3f, Y_v %.3f Y_phi %.3f\n",
               r.g.L_p, r.g.L_lat, r.g.M_q, r.g.M_long, r.g.N_r, r.g.N_ped, r.g.Z_w, r.g.Z_col, r.g.X_u, r.g.X_theta,
               r.g.Y_v, r.g.Y_phi);
        CHECK(!r.failed);
        CHECK(r.r.grade == 2);
        /* within desired from no later than 15 s to the end (80 s) */
        CHECK(r.r.t_desired_s >= 0.0 && r.r.t_desired_s <= t->desired.time_s);
        CHECK(r.t_end_s >= sim_task_length_s(t) - 1e-9);
        CHECK(r.r.max_err_pos_m <= t->desired.pos_m && r.r.max_err_height_m <= t->desired.height_m &&
              r.r.max_err_heading_rad <= t->desired.heading_rad);
        /* the controls stay inside their travel */
        CHECK(r.r.stop_steps == 0);
        for (int i = 0; i < 4; i++)
            CHECK(r.r.min_pct[i] > 0.0 && r.r.max_pct[i] < 100.0);
        if (k == 0)
            *hash_calm = r.hash;
    }
}

/* 3. The delay: the task flown with longer delays in calm air; 1.5 s must
 * fail, and the largest delay that meets the desired band is printed. */
static void test_delay(const hfm_aircraft *ac, const core_ship *ship, const sim_task *t, const double start[3])
{
    const double delays[8] = {0.3, 0.35, 0.4, 0.45, 0.5, 0.75, 1.0, 1.5};
    double best = 0.25;
    int grade15 = -1, all = 1;
    for (int k = 0; k < 8; k++) {
        run r;
        fly(ac, ship, t, start, 0.0, delays[k], &r);
        char what[96];
        snprintf(what, sizeof what, "%s, calm, delay %.2f s", hfm_aircraft_name(ac), delays[k]);
        print_run(what, &r);
        if (r.r.grade == 2 && all)
            best = delays[k];
        else
            all = 0;
        if (delays[k] == 1.5)
            grade15 = r.failed ? 0 : r.r.grade;
    }
    printf("%s: the largest delay flown that meets the desired band: %.2f s (1.5 s: %s)\n", hfm_aircraft_name(ac), best,
           grade_name(grade15));
    CHECK(grade15 == 0);
    /* the margin: the nominal 0.25 s and at least 0.1 s more are flown */
    CHECK(best >= 0.35);
}

/* 6. The landing (scenarios/tasks/land_uh60a.ini): from the same offset
 * start the hover is met, the descent at 0.5 m/s begins and the wheels
 * meet the deck (no gear yet: the CG at the touchdown height) within the
 * desired touchdown tolerances: 1 m from the spot, sink below 1 m/s
 * (issue 26's acceptance asks below 2 m/s and within 1 m), the sink
 * within 0.2 m/s of the commanded descent. */
static void test_land(const hfm_aircraft *ac, const core_ship *ship, const double start[3])
{
    sim_task t;
    core_err err = {{0}};
    if (sim_task_load(LAND, &t, &err) != 0) {
        fprintf(stderr, "%s\n", err.msg);
        CHECK(0);
        return;
    }
    CHECK(t.kind == SIM_TASK_LAND);
    const double wod_kt[2] = {0.0, 20.0};
    for (int k = 0; k < 2; k++) {
        run r;
        fly(ac, ship, &t, start, wod_kt[k], 0.25, &r);
        printf("%s, landing, %.0f kt head wind: hover %s, descent from %.2f s, touchdown %s at %.2f s: sink %.3f m/s, "
               "drift %.3f m/s, %.3f m from the spot; %ld steps at a stop\n",
               hfm_aircraft_name(ac), wod_kt[k], grade_name(r.r.grade), r.r.t_descent_s,
               r.r.touched ? grade_name(r.r.touchdown_grade) : "none", r.r.t_touchdown_s, r.r.sink_mps, r.r.drift_mps,
               r.r.dist_m, r.r.stop_steps);
        CHECK(!r.failed && r.r.grade == 2);
        CHECK(r.r.t_descent_s > 0.0 && r.r.t_descent_s <= t.desired.time_s + t.duration_s + 1e-9);
        CHECK(r.r.touched && r.r.touchdown_grade == 2);
        CHECK(r.r.dist_m <= t.desired.pos_m && r.r.sink_mps > 0.0 && r.r.sink_mps <= t.desired.sink_mps);
        /* the descent is flown at the commanded rate to the deck */
        CHECK(fabs(r.r.sink_mps - t.descent_mps) <= 0.2);
        CHECK(r.r.stop_steps == 0);
    }
}

/* 7. The reference set by a caller (sim_pilot_auto_set_reference, as a
 * replay pilot does): the station-keeping task's pilot, after 10 s told
 * to hold 5 m forward of and 1 m below the task's target at 10 deg to
 * starboard, is there (within 0.5 m, 0.5 m, 2 deg) 40 s later; the
 * phases do not take the reference back; bad references are refused and
 * change nothing. */
static void test_reference(const hfm_aircraft *ac, const core_ship *ship, const sim_task *t)
{
    sim_flight_opts fo;
    sim_flight_opts_default(&fo);
    fo.rate_hz = RATE_HZ;
    fo.turbulence = 0;
    fo.sas = 0;
    memcpy(fo.station_S_m, t->target_S_m, sizeof fo.station_S_m);
    core_err err = {{0}};
    sim_flight *f = sim_flight_create(ac, ship, &fo, NULL, NULL, NULL, NULL, &err);
    sim_pilot_auto_opts po;
    sim_pilot_auto_opts_default(&po);
    sim_flight_inputs in;
    sim_pilot_auto *p = NULL;
    if (f) {
        sim_flight_trim_inputs(f, &in);
        p = sim_pilot_auto_create(ac, t, &po, &in, NULL, &err);
    }
    CHECK(f && p);
    if (!f || !p) {
        fprintf(stderr, "reference: %s\n", err.msg);
        sim_flight_destroy(f);
        return;
    }
    sim_pilot_ref r0, r, bad;
    sim_pilot_auto_reference(p, &r0);
    CHECK(r0.mode == SIM_PILOT_HOLD && r0.pos_S_m[2] == t->target_S_m[2]);
    r = r0;
    r.pos_S_m[0] += 5.0;
    r.pos_S_m[2] += 1.0;
    r.heading_rad = 10.0 * CORE_DEG_TO_RAD;
    bad = r;
    bad.pos_S_m[1] = NAN;
    CHECK(sim_pilot_auto_set_reference(p, &bad) == -1);
    bad = r;
    bad.heading_rad = 4.0;
    CHECK(sim_pilot_auto_set_reference(p, &bad) == -1);
    bad = r;
    bad.mode = SIM_PILOT_DESCEND;
    bad.vel_S_mps[2] = 0.0;
    CHECK(sim_pilot_auto_set_reference(p, &bad) == -1);
    sim_pilot_ref now;
    sim_pilot_auto_reference(p, &now);
    CHECK(memcmp(&now, &r0, sizeof now) == 0);
    sim_flight_out o;
    sim_flight_state(f, &o);
    for (long s = 0; s < (long)(50.0 * RATE_HZ); s++) {
        if (s == (long)(10.0 * RATE_HZ))
            CHECK(sim_pilot_auto_set_reference(p, &r) == 0);
        sim_pilot_auto_step(p, &o, &in);
        if (sim_flight_step(f, &in, &o, &err) != 0) {
            CHECK(0);
            break;
        }
    }
    sim_pilot_auto_reference(p, &now);
    double psi = o.euler_E_rad[2] - atan2(o.ship.C_ES[3], o.ship.C_ES[0]);
    printf("%s, reference moved at 10 s: at 50 s %.3f m, %.3f m height, %.2f deg heading from it\n",
           hfm_aircraft_name(ac), hypot(o.pos_S_m[0] - r.pos_S_m[0], o.pos_S_m[1] - r.pos_S_m[1]),
           o.pos_S_m[2] - r.pos_S_m[2], (psi - r.heading_rad) * CORE_RAD_TO_DEG);
    CHECK(memcmp(&now, &r, sizeof now) == 0);
    CHECK(hypot(o.pos_S_m[0] - r.pos_S_m[0], o.pos_S_m[1] - r.pos_S_m[1]) <= 0.5);
    CHECK(fabs(o.pos_S_m[2] - r.pos_S_m[2]) <= 0.5);
    CHECK(fabs(psi - r.heading_rad) <= 2.0 * CORE_DEG_TO_RAD);
    sim_pilot_auto_destroy(p);
    sim_flight_destroy(f);
}

/* 4. The task file: the shipped file's values, and errors that name what. */
static void write_file(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    if (f) {
        fputs(text, f);
        fclose(f);
    }
}

static void test_task_file(const sim_task *t)
{
    CHECK(t->kind == SIM_TASK_STATION_KEEP);
    CHECK_NEAR(t->target_S_m[2], -6.0, 0.0);
    CHECK_NEAR(t->duration_s, 60.0, 0.0);
    CHECK_NEAR(t->desired.pos_m, 1.0, 0.0);
    CHECK_NEAR(t->desired.heading_rad, 5.0 * CORE_DEG_TO_RAD, 1e-15);
    CHECK_NEAR(t->adequate.time_s, 20.0, 0.0);
    char path[64];
    snprintf(path, sizeof path, "/tmp/test_pilot_auto_%d.ini", (int)getpid());
    static const char *const base = "[task]\ntype = station_keep\ntarget_S_m = 0,0,-6\nduration_s = 60\n"
                                    "[desired]\npos_m = 1\nheight_m = 1\nheading_deg = 5\ntime_s = 15\n";
    struct {
        const char *adequate, *want;
    } bad[3] = {
        {"[adequate]\npos_m = 0.5\nheight_m = 2\nheading_deg = 10\ntime_s = 20\n", "no tighter"},
        {"[adequate]\npos_m = 2\nheight_m = 2\ntime_s = 20\n", "heading_deg"},
        {"[adequate]\npos_m = 2\nheight_m = 2\nheading_deg = 10\ntime_s = 20\nspeed = 3\n", ":15:"},
    };
    for (int k = 0; k < 3; k++) {
        char text[512];
        snprintf(text, sizeof text, "%s%s", base, bad[k].adequate);
        write_file(path, text);
        sim_task tt;
        core_err err = {{0}};
        int rc = sim_task_load(path, &tt, &err);
        printf("bad task file %d: %s\n", k, err.msg);
        CHECK(rc < 0 && strstr(err.msg, path) && strstr(err.msg, bad[k].want));
    }
    unlink(path);
}

int main(void)
{
    setvbuf(stdout, NULL, _IOLBF, 0);
    core_err err = {{0}};
    core_ship ship;
    sim_task task;
    if (core_ship_load(SHIP, &ship, &err) != 0 || sim_task_load(TASK, &task, &err) != 0) {
        fprintf(stderr, "set-up: %s\n", err.msg);
        CHECK(0);
        return check_done("test_pilot_auto");
    }
    test_task_file(&task);
    /* 3 m to starboard of and 2 m above the target */
    const double start[3] = {task.target_S_m[0], task.target_S_m[1] + 3.0, task.target_S_m[2] - 2.0};
    const char *files[2] = {UH60, SA365};
    for (int k = 0; k < 2; k++) {
        hfm_aircraft *ac = hfm_aircraft_load(files[k], NULL, &err);
        CHECK(ac != NULL);
        if (!ac) {
            fprintf(stderr, "set-up: %s\n", err.msg);
            continue;
        }
        uint64_t h1 = 0;
        test_station_keep(ac, &ship, &task, start, &h1);
        /* 5. the same run again: bit-identical */
        run again;
        fly(ac, &ship, &task, start, 0.0, 0.25, &again);
        printf("%s, the calm run twice: hash %016llx and %016llx\n", hfm_aircraft_name(ac), (unsigned long long)h1,
               (unsigned long long)again.hash);
        CHECK(!again.failed && again.hash == h1);
        test_delay(ac, &ship, &task, start);
        if (k == 0) {
            test_land(ac, &ship, start);
            test_reference(ac, &ship, &task);
        }
        hfm_aircraft_destroy(ac);
    }
    return check_done("test_pilot_auto");
}
