/* test_render_live.c -- live rendering beside a loop (render_live_*): states
 * offered at 200 Hz of simulation time for 2 s, paced at half real time
 * (each frame's state offered once the renderer has drawn the last, so the
 * count does not depend on the machine's speed: wait_idle), with
 * rate_hz 10 give 20 frames per camera, numbered from 000000 without
 * a gap; an offer never waits for the renderer (1000 due states offered
 * while the renderer is held mid-frame all return, and it then draws
 * exactly 2 frames, the held one and the newest: counts, not timing); a folder that
 * cannot be made is the error render_live_destroy returns; two identical
 * runs give identical frames and counts, the second offering only the
 * states render_live_due says are due; bad options are refused at create; with an
 * ffmpeg that encodes H.264, one MP4 per camera (without one the case is
 * skipped, exit 77, and fails with CI set: check_skip). The scene: the CG-47, the
 * UH-60A's geometry, a synthetic sea, no overlays. */
#include "check.h"
#include "hfm.h"
#include "render.h"

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

enum { W = 160, H = 120 };
#define LOOP_HZ 200.0

/* A long-crested swell from the north, 1 m amplitude, 60 m long (thread-safe:
 * a pure function). */
static int sea_fn(void *user, double t_s, int n, const double *x, const double *y, double *eta)
{
    (void)user;
    (void)y;
    double k = 2.0 * M_PI / 60.0, w = sqrt(9.80665 * k);
    for (int i = 0; i < n; i++)
        eta[i] = sin(k * x[i] - w * t_s);
    return 0;
}

/* The alarm's end: an offer blocked with the renderer held. */
static void on_alarm(int sig)
{
    (void)sig;
    static const char m[] = "test_render_live: CHECK failed: an offer blocked while the renderer was held "
                            "(20 s without returning)\n";
    ssize_t w = write(2, m, sizeof m - 1);
    (void)w;
    _exit(1);
}

/* A gate in the renderer's sea function: closed, the renderer's thread
 * waits in it mid-frame (outside the mailbox's lock) until it opens. */
typedef struct sea_gate {
    pthread_mutex_t mu;
    pthread_cond_t cv;
    int closed, held;
    long calls;
    double last_t_s;
} sea_gate;

static void gate_init(sea_gate *g)
{
    memset(g, 0, sizeof *g);
    pthread_mutex_init(&g->mu, NULL);
    pthread_cond_init(&g->cv, NULL);
}

static void gate_destroy(sea_gate *g)
{
    pthread_cond_destroy(&g->cv);
    pthread_mutex_destroy(&g->mu);
}

static int gated_sea_fn(void *user, double t_s, int n, const double *x, const double *y, double *eta)
{
    sea_gate *g = user;
    pthread_mutex_lock(&g->mu);
    g->calls++;
    g->last_t_s = t_s;
    while (g->closed) {
        g->held = 1;
        pthread_cond_broadcast(&g->cv);
        pthread_cond_wait(&g->cv, &g->mu);
    }
    g->held = 0;
    pthread_mutex_unlock(&g->mu);
    return sea_fn(NULL, t_s, n, x, y, eta);
}

static void gate_close(sea_gate *g)
{
    pthread_mutex_lock(&g->mu);
    g->closed = 1;
    pthread_mutex_unlock(&g->mu);
}

static void gate_open(sea_gate *g)
{
    pthread_mutex_lock(&g->mu);
    g->closed = 0;
    pthread_cond_broadcast(&g->cv);
    pthread_mutex_unlock(&g->mu);
}

/* 1 once the renderer waits in the gate; 0 after timeout_s (a hang guard) */
static int gate_wait_held(sea_gate *g, double timeout_s)
{
    struct timespec until;
    clock_gettime(CLOCK_REALTIME, &until);
    until.tv_sec += (time_t)timeout_s;
    pthread_mutex_lock(&g->mu);
    int rc = 0;
    while (!g->held && rc == 0)
        rc = pthread_cond_timedwait(&g->cv, &g->mu, &until);
    int held = g->held;
    pthread_mutex_unlock(&g->mu);
    return held;
}

static int gate_is_held(sea_gate *g)
{
    pthread_mutex_lock(&g->mu);
    int h = g->held;
    pthread_mutex_unlock(&g->mu);
    return h;
}

static long gate_calls(sea_gate *g)
{
    pthread_mutex_lock(&g->mu);
    long c = g->calls;
    pthread_mutex_unlock(&g->mu);
    return c;
}

static double gate_last_t(sea_gate *g)
{
    pthread_mutex_lock(&g->mu);
    double t = g->last_t_s;
    pthread_mutex_unlock(&g->mu);
    return t;
}

/* Step i of a synthetic run: the ship at 5 m/s north pitching, the
 * helicopter hovering 6 m over the spot, bobbing and rolling. */
static void state_at(long i, render_state *s)
{
    memset(s, 0, sizeof *s);
    double t = (double)i / LOOP_HZ;
    s->t_s = t;
    core_euler es = {0.02 * sin(0.7 * t), 0.01 * sin(0.5 * t), 0.0};
    s->ship.pos_E_m = core_vec3_make(5.0 * t, 0.0, 0.3 * sin(0.4 * t));
    s->ship.q_EF = core_quat_from_euler(es);
    s->have_heli = 1;
    s->pos_S_m[0] = -2.0;
    s->pos_S_m[2] = -6.0 + 0.5 * sin(2.0 * t);
    s->heli.pos_E_m = core_pose_point_to_E(&s->ship, core_vec3_make(s->pos_S_m[0], s->pos_S_m[1], s->pos_S_m[2]));
    s->roll_rad = 0.05 * sin(1.5 * t);
    s->pitch_rad = 0.04;
    core_euler eb = {s->roll_rad, s->pitch_rad, 0.0};
    s->heli.q_EF = core_quat_from_euler(eb);
    for (int j = 0; j < 4; j++)
        s->controls_pct[j] = 50.0;
    s->rotor_thrust_N = 7.0e4;
    s->rotor_azimuth_rad = 27.0 * t;
}

static void sleep_until(double t_s)
{
    struct timespec ts;
    ts.tv_sec = (time_t)floor(t_s);
    ts.tv_nsec = (long)((t_s - floor(t_s)) * 1e9);
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL) == EINTR)
        ;
}

/* An offer is slow when it took 1 ms or more: counted and printed, not
 * checked (it depends on the machine's load); that the offer never waits
 * for the renderer is checked by counts, with the renderer held. */
#define SLOW_S 1e-3

/* Offer n steps paced at half LOOP_HZ of wall time (a frame due every
 * 0.2 s: the renderer keeps up on a loaded machine under the sanitizers,
 * and the frames drawn are the due states); the longest offer (s), and
 * the slow ones counted into *slow. ask: offer only the states
 * render_live_due says are due. */
static int count_frames(const char *dir, const char *cam, int *extra);

/* Before the state of frame k (k > 0) is offered, frame k - 1 of the
 * cameras named must be on disk (dir not NULL): the renderer is then idle,
 * so every frame is drawn however slowly this machine renders (under the
 * sanitizers and a loaded CI it missed frames at 10 Hz), and the counts
 * and bytes compared below do not depend on its speed. 30 s at most. */
static void wait_idle(const char *dir, long k)
{
    double until = core_monotonic_s() + 30.0;
    int e;
    while (core_monotonic_s() < until &&
           (count_frames(dir, "deck", &e) < k || count_frames(dir, "overhead", &e) < k))
        usleep(1000);
    usleep(5000); /* the renderer back to its mailbox */
}

static double fly_paced(render_live *l, long n, int ask, int *slow, const char *dir)
{
    double t0 = core_monotonic_s(), worst = 0.0;
    *slow = 0;
    for (long i = 0; i < n; i++) {
        render_state s;
        state_at(i, &s);
        if (dir && i > 0 && i % (long)(LOOP_HZ / 10.0) == 0) {
            wait_idle(dir, i / (long)(LOOP_HZ / 10.0));
            t0 = core_monotonic_s() - 2.0 * (double)i / LOOP_HZ; /* the pace goes on from here */
        }
        double a = core_monotonic_s();
        if (!ask || render_live_due(l, s.t_s))
            render_live_offer(l, &s);
        double d = core_monotonic_s() - a;
        worst = d > worst ? d : worst;
        *slow += d >= SLOW_S;
        sleep_until(t0 + 2.0 * (double)(i + 1) / LOOP_HZ);
    }
    return worst;
}

/* How many CAMERA_NNNNNN.png follow on from 000000 in dir; *extra: files
 * of that camera beyond the run (a gap in the numbers). */
static int count_frames(const char *dir, const char *cam, int *extra)
{
    int n = 0;
    char p[1024];
    for (;; n++) {
        snprintf(p, sizeof p, "%s/%s_%06d.png", dir, cam, n);
        if (access(p, F_OK) != 0)
            break;
    }
    *extra = 0;
    DIR *d = opendir(dir);
    struct dirent *e;
    size_t lc = strlen(cam);
    while (d && (e = readdir(d)))
        if (!strncmp(e->d_name, cam, lc) && e->d_name[lc] == '_')
            (*extra)++;
    if (d)
        closedir(d);
    *extra -= n;
    return n;
}

static long file_bytes(const char *path, unsigned char **buf)
{
    *buf = NULL;
    FILE *f = fopen(path, "rb");
    if (!f)
        return -1;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    *buf = malloc(n > 0 ? (size_t)n : 1);
    if (!*buf || fread(*buf, 1, (size_t)n, f) != (size_t)n)
        n = -1;
    fclose(f);
    return n;
}

static int same_file(const char *a, const char *b)
{
    unsigned char *x, *y;
    long na = file_bytes(a, &x), nb = file_bytes(b, &y);
    int same = na > 0 && na == nb && !memcmp(x, y, (size_t)na);
    free(x);
    free(y);
    return same;
}

static void rm_dir(const char *dir)
{
    DIR *d = opendir(dir);
    struct dirent *e;
    char p[1024];
    while (d && (e = readdir(d)))
        if (e->d_name[0] != '.') {
            snprintf(p, sizeof p, "%s/%s", dir, e->d_name);
            remove(p);
        }
    if (d)
        closedir(d);
    rmdir(dir);
}

int main(void)
{
    core_err err = {0};
    core_ship ship;
    CHECK(core_ship_load("scenarios/ships/cg47.ini", &ship, &err) == 0);
    hfm_aircraft *ac = hfm_aircraft_load("scenarios/aircraft/uh60a.ini", NULL, &err);
    CHECK(ac != NULL);
    if (!ac) {
        fprintf(stderr, "%s\n", err.msg);
        return check_done("test_render_live");
    }
    hfm_geometry geo;
    hfm_aircraft_geometry(ac, &geo);
    render_scene sc;
    memset(&sc, 0, sizeof sc);
    sc.ship = &ship;
    sc.heli = &geo;
    sc.sea = sea_fn;
    sc.title = "test_render_live";
    char tmp[] = "/tmp/test_render_live_XXXXXX";
    CHECK(mkdtemp(tmp) != NULL);
    char dir[2][300];

    /* Two identical paced runs: 2 s at 200 Hz, frames at 10 Hz of the
     * simulation's time, deck and overhead cameras. */
    render_live_opts o;
    render_live_opts_default(&o);
    o.width = W;
    o.height = H;
    o.rate_hz = 10.0;
    o.cameras = (1u << RENDER_CAM_DECK) | (1u << RENDER_CAM_OVERHEAD);
    int n[2][2];
    for (int run = 0; run < 2; run++) {
        snprintf(dir[run], sizeof dir[run], "%s/run%d/frames", tmp, run); /* two levels made */
        o.dir = dir[run];
        render_live *l = render_live_create(&sc, &o, &err);
        CHECK(l != NULL);
        if (!l) {
            fprintf(stderr, "%s\n", err.msg);
            continue;
        }
        int slow;
        double worst = fly_paced(l, (long)(2.0 * LOOP_HZ), run, &slow, dir[run]); /* run 1 asks render_live_due */
        render_live_report r;
        int rc = render_live_destroy(l, &r, &err);
        CHECK(rc == 0);
        if (rc)
            fprintf(stderr, "%s\n", err.msg);
        printf("run %d: %ld frames, %ld offered, %ld dropped, frame p50 %.1f ms p99 %.1f ms, longest offer %.0f us, "
               "%d over 1 ms\n",
               run, r.frames, r.offered, r.dropped, 1e3 * r.render_p50_s, 1e3 * r.render_p99_s, 1e6 * worst, slow);
        CHECK(r.offered == 400);
        int extra[2];
        n[run][0] = count_frames(dir[run], "deck", &extra[0]);
        n[run][1] = count_frames(dir[run], "overhead", &extra[1]);
        for (int c = 0; c < 2; c++) {
            CHECK(n[run][c] == 20);
            CHECK(extra[c] == 0);
        }
        CHECK(r.frames == n[run][0] + n[run][1]);
        CHECK(r.dropped == r.offered - n[run][0]);
        CHECK(r.render_p50_s > 0.0 && r.render_p99_s >= r.render_p50_s);
    }
    /* the same frames, byte for byte; and the run moves (not one image) */
    CHECK(n[0][0] == n[1][0] && n[0][1] == n[1][1]);
    int differ = 0;
    for (int c = 0; c < 2; c++)
        for (int i = 0; i < n[0][c] && i < n[1][c]; i++) {
            char a[400], b[400];
            const char *cam = c ? "overhead" : "deck";
            snprintf(a, sizeof a, "%s/%s_%06d.png", dir[0], cam, i);
            snprintf(b, sizeof b, "%s/%s_%06d.png", dir[1], cam, i);
            differ += !same_file(a, b);
        }
    CHECK(differ == 0);
    {
        char a[400], b[400];
        snprintf(a, sizeof a, "%s/deck_%06d.png", dir[0], 0);
        snprintf(b, sizeof b, "%s/deck_%06d.png", dir[0], 10);
        CHECK(!same_file(a, b));
    }

    /* The offer never waits for the renderer, shown by counts the code
     * controls, not by timing: the renderer is held mid-frame (its sea
     * function waits at a gate the test closed) while 1000 due states are
     * offered; every offer returns with the renderer still held, each
     * replacing the one waiting in the slot; the gate opened, the renderer
     * draws exactly the frame it held and the newest state: 2 frames, the
     * second at the last state's time, 999 dropped. An offer that waited
     * for the renderer would never return (the alarm fails the test). */
    {
        render_live_opts ob = o;
        char bd[300];
        snprintf(bd, sizeof bd, "%s/burst", tmp);
        ob.dir = bd;
        ob.cameras = 1u << RENDER_CAM_DECK;
        sea_gate g;
        gate_init(&g);
        render_scene sg = sc;
        sg.sea = gated_sea_fn;
        sg.sea_user = &g;
        render_live *l = render_live_create(&sg, &ob, &err);
        CHECK(l != NULL);
        if (l) {
            enum { NB = 1000 };
            gate_close(&g);
            render_state s;
            state_at(0, &s);
            s.t_s = 0.0;
            render_live_offer(l, &s);
            int held = gate_wait_held(&g, 30.0);
            CHECK(held);
            long calls0 = gate_calls(&g);
            signal(SIGALRM, on_alarm);
            alarm(20); /* an offer that blocks never returns: fail, do not hang */
            for (long i = 1; held && i <= NB; i++) {
                state_at(i, &s);
                s.t_s = (double)i / ob.rate_hz; /* every one due */
                render_live_offer(l, &s);
            }
            alarm(0);
            /* all offered while the renderer was held in frame 0 */
            int still_held = gate_is_held(&g) && gate_calls(&g) == calls0;
            CHECK(still_held);
            gate_open(&g);
            render_live_report r;
            CHECK(render_live_destroy(l, &r, &err) == 0);
            int extra;
            int nf = count_frames(bd, "deck", &extra);
            printf("held renderer: %d offers returned with the renderer held (%s), then %ld frames (%d files), "
                   "%ld offered, %ld dropped, the last frame at t = %.1f s\n",
                   NB, still_held ? "yes" : "NO", r.frames, nf, r.offered, r.dropped, gate_last_t(&g));
            CHECK(r.frames == 2 && nf == 2 && extra == 0);
            CHECK(r.offered == NB + 1 && r.dropped == NB - 1);
            CHECK(gate_last_t(&g) == (double)NB / ob.rate_hz);
        }
        gate_destroy(&g);
        rm_dir(bd);
    }

    /* A folder that cannot be made (under a plain file): create starts, the
     * thread fails, destroy returns the error naming the folder. */
    {
        char file[300], bad[400];
        snprintf(file, sizeof file, "%s/plain", tmp);
        FILE *f = fopen(file, "w");
        CHECK(f != NULL);
        if (f)
            fclose(f);
        snprintf(bad, sizeof bad, "%s/frames", file);
        render_live_opts oe = o;
        oe.dir = bad;
        render_live *l = render_live_create(&sc, &oe, &err);
        CHECK(l != NULL);
        for (long i = 0; l && i < 100; i++) {
            render_state s;
            state_at(i, &s);
            render_live_offer(l, &s);
        }
        render_live_report r;
        core_err e2 = {0};
        CHECK(render_live_destroy(l, &r, &e2) < 0);
        CHECK(strstr(e2.msg, file) != NULL);
        CHECK(strstr(e2.msg, ".png") == NULL); /* the folder's error, not a frame's after it */
        CHECK(r.frames == 0 && r.offered == 100);
        printf("bad folder: %s\n", e2.msg);
        remove(file);
    }

    /* Bad options, refused at create with a message. */
    {
        render_live_opts ob = o;
        ob.dir = tmp;
        ob.rate_hz = 0.0;
        core_err e2 = {0};
        CHECK(render_live_create(&sc, &ob, &e2) == NULL && strstr(e2.msg, "rate"));
        ob.rate_hz = 10.0;
        ob.cameras = 0;
        CHECK(render_live_create(&sc, &ob, &e2) == NULL && strstr(e2.msg, "cameras"));
        ob.cameras = 1u << RENDER_CAM_PILOT;
        render_scene nh = sc;
        nh.heli = NULL;
        CHECK(render_live_create(&nh, &ob, &e2) == NULL && strstr(e2.msg, "pilot"));
        ob.cameras = 1u << RENDER_CAM_DECK;
        ob.width = 8;
        CHECK(render_live_create(&sc, &ob, &e2) == NULL && strstr(e2.msg, "size"));
    }

    /* With ffmpeg: one MP4 per camera, nothing else left in the folder. */
    if (render_video_available()) {
        render_live_opts ov = o;
        char vd[300];
        snprintf(vd, sizeof vd, "%s/video", tmp);
        ov.dir = vd;
        ov.png = 0;
        ov.video = 1;
        render_live *l = render_live_create(&sc, &ov, &err);
        CHECK(l != NULL);
        if (l) {
            int slow;
            fly_paced(l, (long)LOOP_HZ, 0, &slow, NULL);
            render_live_report r;
            int rc = render_live_destroy(l, &r, &err);
            CHECK(rc == 0);
            if (rc)
                fprintf(stderr, "%s\n", err.msg);
            char p[400];
            struct stat st;
            snprintf(p, sizeof p, "%s/deck.mp4", vd);
            CHECK(stat(p, &st) == 0 && st.st_size > 1000);
            snprintf(p, sizeof p, "%s/overhead.mp4", vd);
            CHECK(stat(p, &st) == 0 && st.st_size > 1000);
            int extra;
            CHECK(count_frames(vd, "deck", &extra) == 0 && extra == 0);
        }
        rm_dir(vd);
    } else
        check_skip("the video case: no ffmpeg with H.264 on PATH (go.sh installs it)");

    for (int run = 0; run < 2; run++) {
        rm_dir(dir[run]);
        char p[320];
        snprintf(p, sizeof p, "%s/run%d", tmp, run);
        rmdir(p);
    }
    rmdir(tmp);
    hfm_aircraft_destroy(ac);
    return check_done("test_render_live");
}
