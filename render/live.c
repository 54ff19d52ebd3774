/* live.c -- live rendering beside a flight loop (render_live_*).
 *
 * Two threads share one mailbox slot. The loop's thread (render_live_offer)
 * decides which states are due: frame k of the run is due at simulation
 * time k / rate_hz, and the first state offered at or after it takes it
 * (the frame clock starts at the first state offered and starts again
 * when the time goes back, a reset). A due state is copied into the slot
 * under a try-lock and the renderer woken; a state not due, one offered
 * while the renderer holds the lock (the next step's state takes the frame
 * then), and a due state still in the slot when a newer one replaces it
 * (the renderer fell behind) are counted as dropped. The loop's side
 * never blocks, allocates or does I/O. render_live_due asks the same
 * frame clock before a state is built, so a loop need not build the
 * states that are not due.
 *
 * The render thread owns everything GL and everything written: it makes
 * the folder, creates its own render_ctx (an OSMesa context is current in
 * one thread), opens one video per camera, draws a frame of each camera
 * that it throws away (llvmpipe compiles its shaders at the first draw,
 * hundreds of milliseconds: render_live_create returns once that is done,
 * so the loop's first states find it ready), and for each state taken draws
 * every camera asked for and writes DIR/CAMERA_NNNNNN.png (NNNNNN: the
 * camera's frames in order from 000000, so ffmpeg's image2 pattern reads
 * them) and/or a frame of DIR/CAMERA.mp4. A video shows simulation time
 * at rate_hz: frames the renderer skipped are filled with the last one
 * drawn. A frame's time in the report is the wall time of a camera's
 * frame from its placing to its PNG or video frame written. The first
 * failure is kept (the thread then draws nothing more and counts what it
 * takes as dropped) and render_live_destroy returns it.
 *
 * The thread runs under SCHED_OTHER at nice +10 whatever its creator runs
 * at (a real-time loop asks for SCHED_FIFO before it starts), and llvmpipe's
 * rasteriser threads, which it creates, inherit that. How many rasteriser
 * threads llvmpipe runs is the environment's LP_NUM_THREADS, read when the
 * process's first GL context is made: the application's to set, not this
 * library's. Every signal is blocked in the thread: the loop's thread
 * takes SIGINT and SIGTERM, and a write to an ffmpeg that died fails with
 * EPIPE instead of killing the process. */
#include "render_priv.h"

#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <sched.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

/* A tolerance on k / rate_hz against the step's t_s (t_s = step / rate of
 * the loop carries rounding). */
#define LIVE_EPS 1e-6
/* The longest run of skipped frames a video is filled over (a longer gap
 * is left as one). */
#define LIVE_FILL_MAX 1000

struct render_live {
    render_scene sc;
    render_live_opts o;
    char dir[4096];
    pthread_t th;
    int started;
    pthread_mutex_t mu;
    pthread_cond_t cv;
    /* under mu */
    render_state slot;
    long slot_k;
    int full, stop, ready;
    /* the loop's side only */
    int clock_set;
    long k_next;
    double last_t_s;
    long offered, dropped;
    /* the thread's side only (read after the join) */
    int rc;
    core_err err;
    long frames, dropped_rt;
    double *times;
    long n_times, cap_times;
};

void render_live_opts_default(render_live_opts *o)
{
    memset(o, 0, sizeof *o);
    o->width = 640;
    o->height = 480;
    o->rate_hz = 10.0;
    o->cameras = 1u << RENDER_CAM_DECK;
    o->png = 1;
    o->video = 0;
}

static void live_fail(render_live *l, const core_err *e, const char *what)
{
    if (l->rc < 0)
        return; /* the first error is kept */
    l->rc = -1;
    core_err_set(&l->err, -1, "live rendering: %s%s%s", what ? what : "", what ? ": " : "", e->msg);
}

static void keep_time(render_live *l, double dt_s)
{
    if (l->n_times == l->cap_times) {
        long cap = l->cap_times ? 2 * l->cap_times : 1024;
        double *t = realloc(l->times, (size_t)cap * sizeof *t);
        if (!t)
            return; /* the percentiles then leave this frame out */
        l->times = t;
        l->cap_times = cap;
    }
    l->times[l->n_times++] = dt_s;
}

typedef struct live_out {
    uint8_t *rgba[RENDER_CAM_COUNT];  /* each camera's image (kept: the last one fills a video's gap) */
    render_video *video[RENDER_CAM_COUNT];
    long n[RENDER_CAM_COUNT];     /* frames written per camera */
    long last_k[RENDER_CAM_COUNT]; /* the frame index of the last one (-1: none) */
} live_out;

/* Draw and write state s (frame k of simulation time) for every camera. */
static void live_draw(render_live *l, render_ctx *rc, live_out *out, const render_state *s, long k)
{
    int w = l->o.width, h = l->o.height;
    for (int c = 0; c < RENDER_CAM_COUNT && l->rc == 0; c++) {
        if (!(l->o.cameras & (1u << c)))
            continue;
        uint8_t *rgba = out->rgba[c];
        core_err e = {0};
        char what[160];
        snprintf(what, sizeof what, "t = %.3f s, camera %s", s->t_s, render_camera_name((render_camera_kind)c));
        double t0 = core_monotonic_s();
        if (out->video[c]) {
            /* the frames skipped since the last one, as it was (a reset's
             * time going back fills nothing), before it is drawn over */
            long gap = out->last_k[c] >= 0 ? k - out->last_k[c] - 1 : 0;
            for (long g = 0; g < gap && gap <= LIVE_FILL_MAX; g++)
                if (render_video_frame(out->video[c], rgba, &e) != 0) {
                    live_fail(l, &e, what);
                    return;
                }
        }
        render_view v;
        if (render_camera_place((render_camera_kind)c, &l->sc, s, &v, &e) != 0 ||
            render_frame(rc, &l->sc, s, &v, rgba, &e) != 0) {
            live_fail(l, &e, what);
            return;
        }
        if (l->o.png) {
            char path[4200 + 64];
            snprintf(path, sizeof path, "%s/%s_%06ld.png", l->dir, render_camera_name((render_camera_kind)c), out->n[c]);
            if (render_write_png(path, w, h, rgba, &e) != 0) {
                live_fail(l, &e, what);
                return;
            }
        }
        if (out->video[c]) {
            if (render_video_frame(out->video[c], rgba, &e) != 0) {
                live_fail(l, &e, what);
                return;
            }
        }
        keep_time(l, core_monotonic_s() - t0);
        out->n[c]++;
        out->last_k[c] = k;
        l->frames++;
    }
}

/* One frame per camera of a still state, not kept: llvmpipe compiles its
 * shaders at the first draw (hundreds of milliseconds), before the loop's
 * first state is due. Its failures are left to the frames that count. */
static void live_warm(render_live *l, render_ctx *rc, uint8_t **rgba)
{
    render_state s;
    memset(&s, 0, sizeof s);
    s.ship.q_EF = core_quat_identity();
    s.have_heli = 1;
    s.heli.q_EF = core_quat_identity();
    s.pos_S_m[2] = -10.0;
    s.heli.pos_E_m = core_vec3_make(0.0, 0.0, -10.0);
    for (int c = 0; c < RENDER_CAM_COUNT; c++) {
        render_view v;
        core_err e = {0};
        if ((l->o.cameras & (1u << c)) && render_camera_place((render_camera_kind)c, &l->sc, &s, &v, &e) == 0)
            render_frame(rc, &l->sc, &s, &v, rgba[c], &e);
    }
}

static void *live_main(void *arg)
{
    render_live *l = arg;
    /* below the loop: SCHED_OTHER (the attribute) and nice +10 for this
     * thread and the rasteriser threads it starts */
    setpriority(PRIO_PROCESS, (id_t)syscall(SYS_gettid), 10);
    live_out out;
    memset(&out, 0, sizeof out);
    for (int c = 0; c < RENDER_CAM_COUNT; c++)
        out.last_k[c] = -1;
    render_ctx *rc = NULL;
    core_err e = {0};
    for (int c = 0; c < RENDER_CAM_COUNT && l->rc == 0; c++)
        if ((l->o.cameras & (1u << c)) && !(out.rgba[c] = malloc((size_t)4 * l->o.width * l->o.height))) {
            core_err_set(&e, -1, "out of memory");
            live_fail(l, &e, NULL);
        }
    if (l->rc == 0 && core_mkdir_p(l->dir, &e) != 0)
        live_fail(l, &e, NULL);
    if (l->rc == 0 && !(rc = render_create(l->o.width, l->o.height, &e)))
        live_fail(l, &e, NULL);
    for (int c = 0; c < RENDER_CAM_COUNT && l->rc == 0 && l->o.video; c++) {
        if (!(l->o.cameras & (1u << c)))
            continue;
        char path[4200 + 64];
        snprintf(path, sizeof path, "%s/%s.mp4", l->dir, render_camera_name((render_camera_kind)c));
        if (!(out.video[c] = render_video_open(path, l->o.width, l->o.height, l->o.rate_hz, &e)))
            live_fail(l, &e, NULL);
    }
    if (l->rc == 0)
        live_warm(l, rc, out.rgba);
    pthread_mutex_lock(&l->mu);
    l->ready = 1;
    pthread_cond_broadcast(&l->cv);
    for (;;) {
        while (!l->full && !l->stop)
            pthread_cond_wait(&l->cv, &l->mu);
        if (!l->full)
            break; /* stopped, nothing left to draw */
        render_state s = l->slot;
        long k = l->slot_k;
        l->full = 0;
        pthread_mutex_unlock(&l->mu);
        if (l->rc == 0)
            live_draw(l, rc, &out, &s, k);
        else
            l->dropped_rt++;
        pthread_mutex_lock(&l->mu);
    }
    pthread_mutex_unlock(&l->mu);
    for (int c = 0; c < RENDER_CAM_COUNT; c++) {
        if (!out.video[c])
            continue;
        if (l->rc != 0)
            render_video_abort(out.video[c]);
        else if (render_video_close(out.video[c], &e) != 0)
            live_fail(l, &e, NULL);
    }
    render_destroy(rc);
    for (int c = 0; c < RENDER_CAM_COUNT; c++)
        free(out.rgba[c]);
    return NULL;
}

render_live *render_live_create(const render_scene *sc, const render_live_opts *o, core_err *err)
{
    if (!sc || !sc->ship || !o) {
        core_err_set(err, -1, "render_live_create: a scene with a ship and options are required");
        return NULL;
    }
    if (!o->dir || !o->dir[0] || strlen(o->dir) >= 4096) {
        core_err_set(err, -1, "live rendering: expected a folder for the frames");
        return NULL;
    }
    if (o->width < RENDER_SIZE_MIN || o->height < RENDER_SIZE_MIN || o->width > RENDER_SIZE_MAX ||
        o->height > RENDER_SIZE_MAX) {
        core_err_set(err, -1, "live rendering: image size %dx%d: expected %d to %d pixels a side", o->width,
                     o->height, RENDER_SIZE_MIN, RENDER_SIZE_MAX);
        return NULL;
    }
    if (!(o->rate_hz > 0.0) || !isfinite(o->rate_hz) || o->rate_hz > 1000.0) {
        core_err_set(err, -1, "live rendering: rate %g Hz: expected more than 0 and at most 1000 frames a second",
                     o->rate_hz);
        return NULL;
    }
    if (!o->cameras || (o->cameras >> RENDER_CAM_COUNT)) {
        core_err_set(err, -1, "live rendering: cameras 0x%x: expected bits 1 << render_camera_kind (at least one)",
                     o->cameras);
        return NULL;
    }
    if (!o->png && !o->video) {
        core_err_set(err, -1, "live rendering: neither PNG frames nor video asked for");
        return NULL;
    }
    if ((o->cameras & (1u << RENDER_CAM_PILOT)) && (!sc->heli || !sc->heli->has_eye)) {
        core_err_set(err, -1, "live rendering: the pilot camera needs the aircraft's [cockpit] pilot_eye_B_m");
        return NULL;
    }
    if (o->video && !render_video_available()) {
        core_err_set(err, -1, "live rendering: video needs an ffmpeg that encodes H.264 on PATH");
        return NULL;
    }
    render_live *l = calloc(1, sizeof *l);
    if (!l) {
        core_err_set(err, -1, "live rendering: out of memory");
        return NULL;
    }
    l->sc = *sc;
    l->o = *o;
    snprintf(l->dir, sizeof l->dir, "%s", o->dir);
    l->o.dir = l->dir;
    if (pthread_mutex_init(&l->mu, NULL) != 0) {
        free(l);
        core_err_set(err, -1, "live rendering: cannot make a mutex");
        return NULL;
    }
    if (pthread_cond_init(&l->cv, NULL) != 0) {
        pthread_mutex_destroy(&l->mu);
        free(l);
        core_err_set(err, -1, "live rendering: cannot make a condition variable");
        return NULL;
    }
    pthread_attr_t at;
    struct sched_param sp;
    memset(&sp, 0, sizeof sp);
    sigset_t all, old;
    sigfillset(&all);
    int bad = pthread_attr_init(&at);
    if (!bad) {
        bad = pthread_attr_setinheritsched(&at, PTHREAD_EXPLICIT_SCHED) ||
              pthread_attr_setschedpolicy(&at, SCHED_OTHER) || pthread_attr_setschedparam(&at, &sp);
        /* the thread starts with every signal blocked (its mask is inherited) */
        pthread_sigmask(SIG_SETMASK, &all, &old);
        if (!bad)
            bad = pthread_create(&l->th, &at, live_main, l);
        pthread_sigmask(SIG_SETMASK, &old, NULL);
        pthread_attr_destroy(&at);
    }
    if (bad) {
        pthread_cond_destroy(&l->cv);
        pthread_mutex_destroy(&l->mu);
        free(l);
        core_err_set(err, -1, "live rendering: cannot start the thread (%s)", strerror(bad > 0 ? bad : EAGAIN));
        return NULL;
    }
    l->started = 1;
    /* back once the thread is ready to draw (or has failed): the loop's
     * first states are then not lost to the set-up */
    pthread_mutex_lock(&l->mu);
    while (!l->ready)
        pthread_cond_wait(&l->cv, &l->mu);
    pthread_mutex_unlock(&l->mu);
    return l;
}

/* The frame clock at t_s (finite): 1 when a state at t_s is due. Asking
 * twice for the same t_s gives the same answer. */
static int live_is_due(render_live *l, double t_s)
{
    double rate = l->o.rate_hz;
    if (!l->clock_set || t_s < l->last_t_s - LIVE_EPS / rate) {
        /* the first state, or the time went back (a reset): frames from here */
        l->k_next = (long)ceil(t_s * rate - LIVE_EPS);
        l->clock_set = 1;
    }
    l->last_t_s = t_s;
    return t_s * rate >= (double)l->k_next - LIVE_EPS;
}

int render_live_due(render_live *l, double t_s)
{
    if (!l)
        return 0;
    if (isfinite(t_s) && live_is_due(l, t_s))
        return 1;
    l->offered++; /* counted as render_live_offer would count it */
    l->dropped++;
    return 0;
}

void render_live_offer(render_live *l, const render_state *s)
{
    if (!l || !s)
        return;
    l->offered++;
    if (!isfinite(s->t_s) || !live_is_due(l, s->t_s)) {
        l->dropped++; /* not due */
        return;
    }
    double rate = l->o.rate_hz;
    if (pthread_mutex_trylock(&l->mu) != 0) {
        l->dropped++; /* the renderer is taking the slot: the next state takes this frame */
        return;
    }
    if (l->full)
        l->dropped++; /* the renderer fell behind: the newest state replaces the one waiting */
    l->slot = *s;
    l->slot_k = (long)floor(s->t_s * rate + LIVE_EPS);
    l->full = 1;
    pthread_cond_signal(&l->cv);
    pthread_mutex_unlock(&l->mu);
    l->k_next = l->slot_k + 1;
}

/* The q-th quantile (nearest rank) of v[0..n), sorted in place. */
static int cmpd(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static double quantile(double *v, long n, double q)
{
    if (n <= 0)
        return 0.0;
    long i = (long)ceil(q * (double)n) - 1;
    if (i < 0)
        i = 0;
    if (i >= n)
        i = n - 1;
    return v[i];
}

int render_live_destroy(render_live *l, render_live_report *r, core_err *err)
{
    if (r)
        memset(r, 0, sizeof *r);
    if (!l)
        return 0;
    pthread_mutex_lock(&l->mu);
    l->stop = 1;
    pthread_cond_signal(&l->cv);
    pthread_mutex_unlock(&l->mu);
    if (l->started)
        pthread_join(l->th, NULL);
    if (r) {
        r->frames = l->frames;
        r->offered = l->offered;
        r->dropped = l->dropped + l->dropped_rt;
        if (l->n_times > 0)
            qsort(l->times, (size_t)l->n_times, sizeof *l->times, cmpd);
        r->render_p50_s = quantile(l->times, l->n_times, 0.50);
        r->render_p99_s = quantile(l->times, l->n_times, 0.99);
    }
    int rc = l->rc;
    if (rc < 0)
        core_err_set(err, rc, "%s", l->err.msg);
    pthread_cond_destroy(&l->cv);
    pthread_mutex_destroy(&l->mu);
    free(l->times);
    free(l);
    return rc;
}
